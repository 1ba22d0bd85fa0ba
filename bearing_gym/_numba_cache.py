"""Point numba's on-disk cache at a directory keyed by a hash of this package's source.

numba's ``cache=True`` invalidates a cached function when *its own* file changes, but not when a
function it inlines from another module changes (``ball_residual`` is inlined into
``bearing_force`` and ``integrate``). After an upgrade or an edit that touches only
``physics/ball.py`` the cached ``integrate`` would silently run the old physics. Keying the cache
directory on the hash of every source file of the package makes any change to a module holding kernels (any file with ``@njit``, and all of ``physics/``)
start a fresh cache; other edits keep it.
The base directory is ``$NUMBA_CACHE_DIR`` if set, else ``~/.cache/bearing_gym/numba``.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path


def configure() -> str:
    import numba

    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if b"@njit" not in text and path.parent.name != "physics":
            continue                      # only the modules that hold (or feed) kernels
        digest.update(str(path.relative_to(root)).encode())
        digest.update(text)
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
        "bearing_gym", "numba")
    cache_dir = os.path.join(base, digest.hexdigest()[:16])
    numba.config.CACHE_DIR = cache_dir
    return cache_dir
