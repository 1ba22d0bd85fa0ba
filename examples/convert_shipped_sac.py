"""Write examples/cleanrl_sac_actor.pt: the shipped SAC's actor (agents/pretrained/sac) as the
state dict of examples/cleanrl_actor.py's CleanRL-style Actor, the VecNormalize scaling folded into
fc1 (W1' = W1 / std, b1' = b1 - W1' mean, std = sqrt(var + eps)); the clip of scaled observations
at +-10 is dropped (a CleanRL actor has none). Run again when the shipped SAC changes:

    python examples/convert_shipped_sac.py
"""
from pathlib import Path

import numpy as np
import torch

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "examples" / "cleanrl_sac_actor.pt"


def converted(portable: Path = ROOT / "agents" / "pretrained" / "sac" / "portable_policy.npz") -> dict:
    p = np.load(portable)
    if str(p["kind"]) != "sac" or p["hidden_0_w"].shape != (64, 15) or "hidden_2_w" in p.files:
        raise ValueError(f"{portable}: not a 64x64 SAC actor; the example's Actor needs another shape")
    std = np.sqrt(p["obs_var"] + float(p["epsilon"]))
    w1 = p["hidden_0_w"] / std
    b1 = p["hidden_0_b"] - w1 @ p["obs_mean"]
    arrays = {"fc1.weight": w1, "fc1.bias": b1, "fc2.weight": p["hidden_1_w"], "fc2.bias": p["hidden_1_b"],
              "fc_mean.weight": p["out_w"], "fc_mean.bias": p["out_b"]}
    return {k: torch.as_tensor(v, dtype=torch.float32) for k, v in arrays.items()}


if __name__ == "__main__":
    torch.save(converted(), OUT)
    print(f"wrote {OUT}")
