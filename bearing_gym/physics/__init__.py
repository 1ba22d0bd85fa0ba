"""Physics core: numba kernels by equation group, the Simulator and the static equilibrium."""

from .equilibrium import EquilibriumError, StaticEquilibrium, static_equilibrium
from .simulator import SimulationError, SimulationRecord, Simulator, SimulatorState

__all__ = ["Simulator", "SimulatorState", "SimulationRecord", "SimulationError",
           "static_equilibrium", "StaticEquilibrium", "EquilibriumError"]
