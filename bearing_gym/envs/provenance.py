"""Which kernel made a number: its fingerprint.

Since the kernel is portable (:mod:`bearing_gym.physics.portable_math`), a stored episode return
is a function of the code (and NumPy's random streams) alone, not of the CPU. :func:`kernel_hash`
fingerprints what the kernel *computes*: the SHA-256 of the final physics states, observations
and rewards of three fixed 40-step episodes (a quasi-periodic one with race waviness, where any
change of a last bit shows; a ``transient`` one with events under varying actions; a ``field`` one
with the sensor's noise). A refactoring that keeps the bits keeps the fingerprint; any change
of the numbers changes it; it is the same on every CPU. Stored results (the test references, the
board's per-episode returns) carry it with :func:`package_version`, and a reader refuses a store
made by another kernel.

Computing it takes a few seconds, so it is cached on disk beside the numba cache, keyed by
:func:`source_hash` (the tokens of the code that feeds the state, an observation or the reward:
``physics/``, ``envs/`` without rendering and the reward-map tool, ``params.py``, ``units.py``,
``task.py``, ``analysis/signals.py``; comments and docstrings left out) and the NumPy,
numba and Python versions.
"""

from __future__ import annotations

import functools
import hashlib
import io
import tokenize
from pathlib import Path

__all__ = ["kernel_hash", "source_hash", "package_version", "KERNEL_SOURCES", "FINGERPRINT_STEPS"]

_ROOT = Path(__file__).resolve().parents[1]
FINGERPRINT_STEPS = 40
KERNEL_SOURCES = ("physics", "envs", "params.py", "units.py", "task.py", "analysis/signals.py")
_NOT_KERNEL = {"envs/rendering.py", "envs/reward_map.py"}


def _code_tokens(text: str) -> list[str]:
    """The source's tokens without comments, blank lines and docstrings (a string that is a
    statement of its own)."""
    out: list[str] = []
    toks = list(tokenize.generate_tokens(io.StringIO(text).readline))
    skip = {tokenize.COMMENT, tokenize.NL, tokenize.ENCODING}
    statement_start = True
    for i, tok in enumerate(toks):
        if tok.type in skip:
            continue
        if tok.type == tokenize.STRING and statement_start:
            nxt = next((t for t in toks[i + 1:] if t.type not in skip), None)
            if nxt is not None and nxt.type in (tokenize.NEWLINE, tokenize.ENDMARKER):
                continue                       # a docstring
        statement_start = tok.type in (tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT)
        out.append(f"{tok.type}:{tok.string}")
    return out


def _files() -> list[Path]:
    files: list[Path] = []
    for name in KERNEL_SOURCES:
        path = _ROOT / name
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    return [f for f in files if f.relative_to(_ROOT).as_posix() not in _NOT_KERNEL]


@functools.lru_cache(maxsize=1)
def source_hash() -> str:
    """16 hex digits of SHA-256 over the kernel's code tokens (the fingerprint's cache key)."""
    digest = hashlib.sha256()
    for path in _files():
        digest.update(path.relative_to(_ROOT).as_posix().encode())
        digest.update("\n".join(_code_tokens(path.read_text())).encode())
    return digest.hexdigest()[:16]


def fingerprint_episodes(steps: int = FINGERPRINT_STEPS) -> str:
    """SHA-256 (16 hex digits) of what three fixed episodes compute (module docstring)."""
    import gymnasium as gym
    import numpy as np

    import bearing_gym  # noqa: F401 - registers BearingPreload-v0
    digest = hashlib.sha256()
    actions = np.random.default_rng(1).uniform(-1.0, 1.0, size=(steps, 1)).astype(np.float32)
    quasi_periodic = {"shaft_speed_rpm": 17500.0, "radial_load_n": 250.0, "clearance_m": 17e-6,
                      "initial_preload_n": 300.0, "waviness_amplitude_m": 0.5e-6}
    for tier, seed, options, acts in (("stationary", 7, quasi_periodic, np.full((steps, 1), -1.0, np.float32)),
                                      ("transient", 300123, None, actions), ("field", 300007, None, actions)):
        # the env through its registration, unwrapped: the env modules import this one (a start
        # bank's kernel check), so this one does not import them
        env = gym.make("BearingPreload-v0", tier=tier, disable_env_checker=True).unwrapped
        obs, _ = env.reset(seed=seed, options=options)
        digest.update(np.asarray(obs, dtype=np.float64).tobytes())
        for a in acts:
            obs, r, term, trunc, _ = env.step(a)
            digest.update(np.asarray(obs, dtype=np.float64).tobytes())
            digest.update(np.float64(r).tobytes())
        b = env.batch
        for arr in (b.X[0], b.V[0], b.A[0], b.scal[0], b.psi_b[0], b.ball_v[0], b.ball_out[0]):
            digest.update(np.ascontiguousarray(arr, dtype=np.float64).tobytes())
    return digest.hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def kernel_hash() -> str:
    """The kernel's fingerprint (module docstring), from the disk cache when this code, NumPy,
    numba and Python computed it before."""
    import platform

    import numba
    import numpy as np

    import bearing_gym
    key = f"{source_hash()}-np{np.__version__}-nb{numba.__version__}-py{platform.python_version()}"
    cache = Path(bearing_gym.NUMBA_CACHE_DIR) / f"kernel_fingerprint_{key}.txt"
    try:
        value = cache.read_text().strip()
        if len(value) == 16:
            return value
    except OSError:
        pass
    value = fingerprint_episodes()
    try:
        cache.parent.mkdir(parents=True, exist_ok=True)
        cache.write_text(value + "\n")
    except OSError:
        pass                                # a read-only cache: compute it again next time
    return value


def package_version() -> str:
    from bearing_gym import __version__
    return __version__
