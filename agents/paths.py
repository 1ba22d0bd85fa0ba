"""Where agents reads and writes: one module for every path.

Read-only data ship with the package (``DATA_DIR``: stored references, the contextual fits, the
oracle and stability tables; ``PRETRAINED_DIR``: the shipped policies; ``HYPERPARAMS_DIR``: the
RL Zoo yml files). Everything a command writes goes under the current directory's ``runs/``
(:func:`runs_dir`) or where ``--out`` says - never inside the installed package. The committed
results (``docs/results.json``, the stores in ``agents/data/``, the protocol's trained runs in
``agents/trained/``) are written only by the commands that exist to rebuild them, and only in a
source checkout (:func:`checkout_root`; an editable install): in an installed package they say
which option names the file instead.
"""

from __future__ import annotations

import hashlib
from pathlib import Path


__all__ = ["file_digest", "PACKAGE_DIR", "DATA_DIR", "PRETRAINED_DIR", "HYPERPARAMS_DIR", "checkout_root", "require_checkout",
           "runs_dir", "docs_dir", "TRAINED_DIR", "start_bank_path"]

PACKAGE_DIR = Path(__file__).resolve().parent
DATA_DIR = PACKAGE_DIR / "data"
PRETRAINED_DIR = PACKAGE_DIR / "pretrained"
HYPERPARAMS_DIR = PACKAGE_DIR / "hyperparams"
TRAINED_DIR = PACKAGE_DIR / "trained"      # the protocol's trained runs (committed in a checkout)
TRAINED_V2_DIR = PACKAGE_DIR / "trained_v2"   # protocol v2's runs (agents.training.protocol_runs --protocol 2)


def checkout_root() -> Path | None:
    """The source checkout this package is part of (the directory holding ``pyproject.toml``,
    ``train.py`` and ``docs/`` beside ``agents/``), or None for an installed package."""
    root = PACKAGE_DIR.parent
    if (root / "pyproject.toml").is_file() and (root / "train.py").is_file() and (root / "docs").is_dir():
        return root
    return None


def require_checkout(what: str, option: str) -> Path:
    """The checkout's root, or a ValueError saying that ``what`` is a committed file of a source
    checkout and that ``option`` names another place to write."""
    root = checkout_root()
    if root is None:
        raise ValueError(f"{what} is a committed file of the bearing_gym source checkout, and this agents package "
                         f"is installed ({PACKAGE_DIR}), not part of one: pass {option} to say where to write")
    return root


def runs_dir(*parts: str) -> Path:
    """``runs/<parts...>`` under the current directory: the default home of every output."""
    return Path.cwd().joinpath("runs", *parts)


def docs_dir() -> Path:
    """The checkout's ``docs/`` (committed reports and results)."""
    return require_checkout("docs/", "--out") / "docs"


def start_bank_path(tier: str) -> Path:
    """The start bank shipped for ``tier`` (``train.py``'s default and the envs'
    ``start_bank="shipped"``; it may not exist): in the env's package, bearing_gym/data/."""
    from bearing_gym.envs.start_bank import shipped_path
    return shipped_path(tier)


def file_digest(path: Path) -> str:
    """The SHA-256 (hex) of a file's bytes, read in 1 MiB blocks: how a record names the exact
    file it was made from (the regeneration's inputs, an offline dataset's policy weights)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
