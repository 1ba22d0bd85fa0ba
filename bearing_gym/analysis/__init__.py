"""Nonlinear analysis of simulated responses (Bai & Xu 2006, section 3).

Only the signal measures are imported here (NumPy only); import the other modules explicitly,
they load SciPy or matplotlib lazily where needed:

* :mod:`.signals` -- peak-to-peak, RMS, stroboscopic samples, quasi-periodicity index;
* :mod:`.spectra` -- power spectra (Welch, periodogram), spectral peaks, principal frequency,
  ball-pass frequencies N ω_c and N (ω − ω_c);
* :mod:`.poincare` -- Poincare sections on the shaft angle (stroboscopic) and the cage angle;
* :mod:`.floquet` -- monodromy matrix by finite differences, Floquet multipliers, mode naming;
* :mod:`.lyapunov` -- largest Lyapunov exponent (Benettin), for ODEs and the Simulator;
* :mod:`.linear` -- eigenvalues of the linearised equations at the static equilibrium;
* :mod:`.sweeps` -- preload continuation, cold starts, stability maps on a pluggable executor;
"""

from .signals import QPI_THRESHOLD, peak_to_peak, quasi_periodicity_index, rms, stroboscopic_samples

__all__ = ["peak_to_peak", "rms", "stroboscopic_samples", "quasi_periodicity_index", "QPI_THRESHOLD"]
