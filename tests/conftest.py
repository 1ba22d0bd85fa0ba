import os

import pytest

os.environ.setdefault("NUMBA_CACHE_DIR", os.path.join(os.path.dirname(__file__), "..", ".numba-cache"))


@pytest.fixture(scope="session")
def default_equilibrium():
    import bearing_gym
    from bearing_gym.physics import static_equilibrium
    return static_equilibrium(bearing_gym.default_params())
