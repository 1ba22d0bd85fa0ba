"""Linear stability of the static equilibrium (eq 35 linearised, no unbalance).

At the static equilibrium U0 of :func:`bearing_gym.physics.static_equilibrium` the bearing force
is F(U0 + u) ≈ F(U0) − K u, with K the stiffness matrix it returns (central differences; slightly
non-symmetric at speed because of the centrifugal and gyroscopic terms). Eq 35 with the
Simulator's viscous damping C and the gyroscopic matrix G (I_z ω coupling θx and θy) becomes

    M u'' + (C + G) u' + K u = 0,       A = [[0, I], [−M⁻¹K, −M⁻¹(C + G)]]

and the equilibrium is asymptotically stable when every eigenvalue of A has a negative real part.
With e → 0 the period-1 unbalance response shrinks onto this equilibrium and its Floquet
multipliers tend to exp(λ T); a loss of stability of the period-1 orbit that the equilibrium does
not share is a property of the finite-amplitude (contact-loss) response, i.e. a secondary
bifurcation in the sense of the paper's section 3.2.
"""

from __future__ import annotations


import numpy as np

from bearing_gym.params import BearingParams
from bearing_gym.units import rpm_to_rad_s

__all__ = ["equilibrium_eigenvalues"]


def equilibrium_eigenvalues(params: BearingParams) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (1/s) of the linearised eq 35 at the static equilibrium of ``params`` (one
    per complex-conjugate pair, non-negative imaginary part, least stable first) and the
    damping coefficients used (those the Simulator would use for ``params``)."""
    from bearing_gym.physics import Simulator

    sim = Simulator(params)
    K = sim.equilibrium.stiffness
    r = params.rotor
    M = np.diag([r.mass_kg] * 3 + [r.inertia_radial_kg_m2] * 2)
    C = np.diag(sim.damping_coefficients)
    G = np.zeros((5, 5))
    # I_z omega, computed as (I_z rpm) pi/30: the rounding of the earlier releases
    g = rpm_to_rad_s(r.inertia_polar_kg_m2 * params.shaft_speed_rpm)
    G[3, 4] = g
    G[4, 3] = -g
    Mi = np.linalg.inv(M)
    A = np.block([[np.zeros((5, 5)), np.eye(5)], [-Mi @ K, -Mi @ (C + G)]])
    lam = np.linalg.eigvals(A)
    lam = lam[lam.imag >= -1e-9 * np.abs(lam)]
    return lam[np.argsort(-lam.real)], sim.damping_coefficients
