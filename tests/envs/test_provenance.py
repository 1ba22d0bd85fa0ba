"""The kernel's fingerprint: what three fixed episodes compute, so it moves with the numbers and
not with the comments (the same bits on every CPU: tests/portability)."""

import numpy as np

from bearing_gym.envs import core
from bearing_gym.envs.provenance import _code_tokens, fingerprint_episodes, kernel_hash, source_hash


def test_the_fingerprint_is_what_the_episodes_compute_and_repeats():
    assert kernel_hash() == fingerprint_episodes()               # the disk cache holds the same
    assert len(kernel_hash()) == 16 and len(source_hash()) == 16


def test_the_fingerprint_moves_with_the_numbers(monkeypatch):
    before = fingerprint_episodes(steps=3)
    monkeypatch.setattr(core, "SETTLE_TAIL_INTERVALS", core.SETTLE_TAIL_INTERVALS + 1)   # another start
    monkeypatch.setattr(core, "_SETTLED", type(core._SETTLED)())                         # settle afresh
    assert fingerprint_episodes(steps=3) != before


def test_the_source_key_ignores_comments_and_docstrings_but_not_code():
    code = 'def f(x):\n    """doc"""\n    # note\n    return x  # why\n'
    assert _code_tokens(code) == _code_tokens(code.replace("doc", "other").replace("note", "else"))
    assert _code_tokens(code) != _code_tokens(code.replace("return x", "return x + 1"))
    assert np.array_equal(_code_tokens(code), _code_tokens(code))
