# The tests use the same numba cache as the library, train.py and the CLI: $NUMBA_CACHE_DIR if
# set, else ~/.cache/bearing_gym/numba (bearing_gym._numba_cache), so the README's two commands
# compile the kernels once. .ci/run sets NUMBA_CACHE_DIR to .numba-cache/ in the checkout.
import os

import pytest

SLOW = bool(os.environ.get("BEARING_GYM_SLOW"))


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
