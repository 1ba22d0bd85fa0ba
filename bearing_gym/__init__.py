"""bearing_gym: the Bai & Xu (2006) high-speed ball-bearing / rotor model as a physics core,
an analysis toolkit and a Gymnasium environment for axial-preload control."""

from .params import (BallWaviness, BearingGeometry, BearingParams, Damping, Integrator, Loads,
                     Material, RaceWaviness, Rotor, Waviness, default_params)

__version__ = "0.1.0"

__all__ = ["default_params", "BearingParams", "BearingGeometry", "Material", "Rotor", "Waviness",
           "RaceWaviness", "BallWaviness", "Loads", "Damping", "Integrator", "__version__"]
