# The tests use the same numba cache as the library, train.py and the CLI: $NUMBA_CACHE_DIR if
# set, else ~/.cache/bearing_gym/numba (bearing_gym._numba_cache), so the README's two commands
# compile the kernels once. .ci/run sets NUMBA_CACHE_DIR to .numba-cache/ in the checkout.
import pytest


@pytest.fixture(scope="session")
def default_equilibrium():
    import bearing_gym
    from bearing_gym.physics import static_equilibrium
    return static_equilibrium(bearing_gym.default_params())
