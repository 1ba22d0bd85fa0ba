"""A CleanRL-style PyTorch actor on the board: CleanRL's SAC Actor, deterministic (tanh of the mean).
Run: python examples/cleanrl_actor.py [EPISODES]  (torch; weights beside it: convert_shipped_sac.py)."""
import sys
import torch
from torch import nn
from agents.submit import score

class Actor(nn.Module):  # observations scaled as in its training: the scaling is folded into fc1
    def __init__(self):
        super().__init__()
        self.fc1, self.fc2, self.fc_mean = nn.Linear(15, 64), nn.Linear(64, 64), nn.Linear(64, 1)
    def forward(self, x):
        return torch.tanh(self.fc_mean(torch.relu(self.fc2(torch.relu(self.fc1(x))))))
actor = Actor()
actor.load_state_dict(torch.load(__file__.replace("cleanrl_actor.py", "cleanrl_sac_actor.pt"), weights_only=True))
result = score(lambda o: actor(torch.as_tensor(o)).detach().numpy(), tier="transient", name="CleanRL actor",
               episodes=int(sys.argv[1]) if sys.argv[1:] else None)
result.save("runs/submissions/cleanrl_actor.json", algorithm="SAC", library="cleanrl-style torch")
print(result.markdown())
