"""What train.py and the protocol's runs share: the training callbacks (:mod:`.callbacks`), the
board after training (:mod:`.after_training`) and running the protocol's runs
(:mod:`.protocol_runs`)."""

from agents.extras import require_extra as _require_extra

_require_extra("agents.training (train.py and the protocol's runs)")
