"""bearing_gym: the Bai & Xu (2006) high-speed ball-bearing / rotor model as a physics core,
an analysis toolkit and a Gymnasium environment for axial-preload control."""

from . import _numba_cache

NUMBA_CACHE_DIR = _numba_cache.configure()   # before any kernel module is imported

from .params import (  # noqa: E402
    BallWaviness, BearingGeometry, BearingParams, Damping, Integrator, Loads,
                     Material, RaceWaviness, Rotor, Waviness, default_params)

__version__ = "0.1.0"

__all__ = ["default_params", "BearingParams", "BearingGeometry", "Material", "Rotor", "Waviness",
           "RaceWaviness", "BallWaviness", "Loads", "Damping", "Integrator", "__version__"]


def _register() -> None:
    import gymnasium

    from .task import EPISODE_STEPS

    if "BearingPreload-v0" not in gymnasium.registry:
        gymnasium.register(
            id="BearingPreload-v0",
            entry_point="bearing_gym.envs.bearing_preload:BearingPreloadEnv",
            vector_entry_point="bearing_gym.envs.vector:BearingPreloadVectorEnv",
            max_episode_steps=EPISODE_STEPS,
        )


_register()
