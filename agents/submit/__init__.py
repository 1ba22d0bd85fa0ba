"""The open board: score any policy as the board does, write a submission, add it to a board.

    from agents.submit import score
    result = score(lambda obs: np.zeros((len(obs), 1)), tier="transient", name="mid-range constant")
    print(result.markdown())                   # the row beside the references
    result.save("mine.json", algorithm="constant", library="numpy")
    # python -m agents.submit add mine.json   -> a row marked submitted on docs/results.json

Needs the env and the ``score`` extra (``pip install "bearing-gym[score]"``: rliable), not torch.
:func:`score` (:mod:`.api`), the adapters for callables, SB3 models, train.py directories and
RLlib modules (:mod:`.adapters`, :mod:`.rllib`), the submission file and the board's checks
(:mod:`.submission`), the constrained variant (:mod:`.constrained`). The rules - what a policy may
read, the seeds, the budgets, what a submission reports - are docs/benchmark.md.
"""

from agents.submit.adapters import CallablePolicy, as_policies, as_policy
from agents.submit.api import VARIANTS, Scored, score
from agents.submit.submission import SubmissionRefused, add_submission, check_submission, load_submission

__all__ = ["score", "Scored", "VARIANTS", "as_policy", "as_policies", "CallablePolicy", "SubmissionRefused",
           "add_submission", "check_submission", "load_submission"]
