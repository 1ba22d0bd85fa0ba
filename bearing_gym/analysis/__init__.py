"""Nonlinear analysis of simulated responses: signal measures, Poincare sections, Floquet
multipliers, Lyapunov exponents, spectra and parameter sweeps."""

from .signals import peak_to_peak, quasi_periodicity_index, rms, stroboscopic_samples

__all__ = ["peak_to_peak", "rms", "stroboscopic_samples", "quasi_periodicity_index"]
