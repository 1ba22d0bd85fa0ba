# The tests use the same numba cache as the library, train.py and the CLI: $NUMBA_CACHE_DIR if
# set, else ~/.cache/bearing_gym/numba (bearing_gym._numba_cache), so the README's two commands
# compile the kernels once. .ci/run sets NUMBA_CACHE_DIR to .numba-cache/ in the checkout.
import os

import pytest

SLOW = bool(os.environ.get("BEARING_GYM_SLOW"))


def pytest_sessionstart(session):
    """One line before the first test about the one-off numba compile, so that a first run's
    silent minutes say why (printed even under -q)."""
    from pathlib import Path

    import bearing_gym
    cache = Path(bearing_gym.NUMBA_CACHE_DIR)
    import sys
    tag = f"*.py{sys.version_info.major}{sys.version_info.minor}.nbi"     # numba's index files of this Python
    cached = sum(1 for _ in cache.rglob(tag)) if cache.is_dir() else 0
    line = (f"bearing_gym: numba kernels cached in {cache} ({cached} index files): they load in seconds"
            if cached else
            f"bearing_gym: no numba cache yet in {cache}: the first tests compile the kernels once "
            "(about 2 min on 2 cores, silent), later runs load them")
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None:
        reporter.write_line(line)


def pytest_collection_modifyitems(config, items):
    """Tests marked ``slow`` (long validation runs) run only with BEARING_GYM_SLOW=1 (as CI
    sets it); the README's test command skips them."""
    if SLOW:
        return
    skip = pytest.mark.skip(reason="slow validation run; set BEARING_GYM_SLOW=1 to run it")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(scope="session")
def default_equilibrium():
    import bearing_gym
    from bearing_gym.physics import static_equilibrium
    return static_equilibrium(bearing_gym.default_params())
