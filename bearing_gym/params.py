"""Frozen, validated parameter dataclasses for the Bai & Xu (2006) bearing/rotor model.

Every quantity is in SI units. The defaults are the paper's Table 1 bearing and the rotor of
its section 3.1 (m = 12.17 kg, I_r = 0.0330 kg m^2, I_z = 0.0609 kg m^2), steel as in
``docs/model.md`` (E = 208 GPa, nu = 0.3, rho = 7850 kg/m^3).

Each dataclass validates itself in ``__post_init__`` and raises :class:`ValueError` naming the
field and the allowed range. :func:`default_params` builds the Table 1 configuration with flat
keyword overrides. This module imports no physics: the conversion to the flat float64 arrays of
the numba kernels is :func:`bearing_gym.physics.layout.pack_params`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bearing_gym.units import rpm_to_rad_s
from bearing_gym.validation import check_bool, check_int, check_real, check_real_tuple

__all__ = [
    "BearingGeometry",
    "Material",
    "Rotor",
    "RaceWaviness",
    "BallWaviness",
    "Waviness",
    "Loads",
    "Damping",
    "Integrator",
    "BearingParams",
    "default_params",
    "RACE_CONTROLS",
]

RACE_CONTROLS = ("outer", "inner", "auto")


# ---------------------------------------------------------------------------------------------
# validation helpers (bearing_gym.validation)
# ---------------------------------------------------------------------------------------------
_as_float_tuple = check_real_tuple


def _set(obj: Any, name: str, value: Any) -> None:
    object.__setattr__(obj, name, value)


# ---------------------------------------------------------------------------------------------
# dataclasses
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BearingGeometry:
    """Angular-contact ball bearing geometry (paper Table 1).

    ``inner_groove_radius_m`` and ``outer_groove_radius_m`` are the race (groove) curvature
    radii r_i and r_o; the clearances c_i and c_o are the radial gaps of eqs 16-17 and 22-23
    (a gap of c at each contact when the rotor is at U = 0).
    """

    n_balls: int = 18
    ball_diameter_m: float = 19.05e-3
    pitch_diameter_m: float = 140.0e-3
    inner_groove_radius_m: float = 10.2870e-3
    outer_groove_radius_m: float = 9.906e-3
    contact_angle_rad: float = math.radians(25.0)
    clearance_inner_m: float = 4.0e-6
    clearance_outer_m: float = 4.0e-6

    def __post_init__(self) -> None:
        n = check_int("n_balls", self.n_balls, 3, 200)
        db = check_real("ball_diameter_m", self.ball_diameter_m, 0.0, 0.5, low_open=True)
        dp = check_real("pitch_diameter_m", self.pitch_diameter_m, db, 5.0, low_open=True)
        if n * db >= math.pi * dp:
            raise ValueError(
                f"n_balls * ball_diameter_m must be < pi * pitch_diameter_m (balls overlap): "
                f"n_balls must be in [3, {int(math.pi * dp / db - 1e-12)}] for these diameters, got {n}")
        ci = check_real("clearance_inner_m", self.clearance_inner_m, 0.0, 1e-3)
        co = check_real("clearance_outer_m", self.clearance_outer_m, 0.0, 1e-3)
        ri = check_real("inner_groove_radius_m", self.inner_groove_radius_m, db / 2 + ci, db,
                         low_open=True)
        ro = check_real("outer_groove_radius_m", self.outer_groove_radius_m, db / 2 + co, db,
                         low_open=True)
        a0 = check_real("contact_angle_rad", self.contact_angle_rad, 0.0, math.radians(80.0),
                         high_open=True)
        for k, v in (("n_balls", n), ("ball_diameter_m", db), ("pitch_diameter_m", dp),
                     ("clearance_inner_m", ci), ("clearance_outer_m", co),
                     ("inner_groove_radius_m", ri), ("outer_groove_radius_m", ro),
                     ("contact_angle_rad", a0)):
            _set(self, k, v)

    @property
    def diameter_ratio(self) -> float:
        """gamma = D_b / D_p (nomenclature)."""
        return self.ball_diameter_m / self.pitch_diameter_m


@dataclass(frozen=True)
class Material:
    """Elastic and mass properties of balls and races (steel; the paper does not say)."""

    youngs_modulus_pa: float = 208.0e9
    poisson_ratio: float = 0.3
    density_kg_m3: float = 7850.0

    def __post_init__(self) -> None:
        _set(self, "youngs_modulus_pa",
             check_real("youngs_modulus_pa", self.youngs_modulus_pa, 1e6, 1e13))
        _set(self, "poisson_ratio",
             check_real("poisson_ratio", self.poisson_ratio, -0.99, 0.5, high_open=True))
        _set(self, "density_kg_m3", check_real("density_kg_m3", self.density_kg_m3, 1.0, 1e5))


@dataclass(frozen=True)
class Rotor:
    """Rigid rotor of eq 35: mass, radial and polar moments of inertia, mass eccentricity e."""

    mass_kg: float = 12.17
    inertia_radial_kg_m2: float = 0.0330
    inertia_polar_kg_m2: float = 0.0609
    eccentricity_m: float = 1.0e-5

    def __post_init__(self) -> None:
        _set(self, "mass_kg", check_real("mass_kg", self.mass_kg, 0.0, 1e6, low_open=True))
        _set(self, "inertia_radial_kg_m2", check_real(
            "inertia_radial_kg_m2", self.inertia_radial_kg_m2, 0.0, 1e6, low_open=True))
        _set(self, "inertia_polar_kg_m2", check_real(
            "inertia_polar_kg_m2", self.inertia_polar_kg_m2, 0.0, 1e6, low_open=True))
        _set(self, "eccentricity_m",
             check_real("eccentricity_m", self.eccentricity_m, 0.0, 1e-2))


@dataclass(frozen=True)
class RaceWaviness:
    """Waviness of one race (corrected eqs 9-12): sum over orders n of
    ``A_n cos(n * ring_angle + xi_n)`` (radial, p) and ``B_n cos(n * ring_angle + eta_n)``
    (axial, q), where ring_angle is the angle of the ball measured on the ring."""

    orders: tuple[int, ...] = ()
    radial_amplitudes_m: tuple[float, ...] = ()
    radial_phases_rad: tuple[float, ...] = ()
    axial_amplitudes_m: tuple[float, ...] = ()
    axial_phases_rad: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        orders = tuple(check_int(f"waviness orders[{k}]", o, 1, 10000)
                       for k, o in enumerate(tuple(self.orders)))
        n = len(orders)
        _set(self, "orders", orders)
        for name, lo, hi in (("radial_amplitudes_m", 0.0, 1e-4), ("radial_phases_rad", None, None),
                             ("axial_amplitudes_m", 0.0, 1e-4), ("axial_phases_rad", None, None)):
            vals = check_real_tuple(name, getattr(self, name), lo, hi)
            if len(vals) == 0:
                vals = (0.0,) * n
            if len(vals) != n:
                raise ValueError(f"{name} must have one entry per waviness order ({n}), got {len(vals)}")
            _set(self, name, vals)

    @property
    def is_zero(self) -> bool:
        return not any(self.radial_amplitudes_m) and not any(self.axial_amplitudes_m)


@dataclass(frozen=True)
class BallWaviness:
    """Ball waviness (eqs 13-14): ``C_n cos(n psi_b + zeta_nj)`` at the inner contact and
    ``C_n cos(n (psi_b + pi) + zeta_nj)`` at the outer contact; ``oversize_m`` is h_j of
    eqs 16-17 (one value per ball, or empty for none). ``phases_rad`` holds one phase per order
    (same for all balls) or one row of phases per ball."""

    orders: tuple[int, ...] = ()
    amplitudes_m: tuple[float, ...] = ()
    phases_rad: tuple = ()
    oversize_m: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        orders = tuple(check_int(f"ball waviness orders[{k}]", o, 1, 10000)
                       for k, o in enumerate(tuple(self.orders)))
        n = len(orders)
        _set(self, "orders", orders)
        amps = check_real_tuple("ball amplitudes_m", self.amplitudes_m, 0.0, 1e-4)
        if len(amps) == 0:
            amps = (0.0,) * n
        if len(amps) != n:
            raise ValueError(f"ball amplitudes_m must have one entry per order ({n}), got {len(amps)}")
        _set(self, "amplitudes_m", amps)
        ph = tuple(self.phases_rad)
        if len(ph) and isinstance(ph[0], (tuple, list, np.ndarray)):
            rows = tuple(check_real_tuple(f"ball phases_rad[{j}]", r) for j, r in enumerate(ph))
            for j, r in enumerate(rows):
                if len(r) != n:
                    raise ValueError(f"ball phases_rad[{j}] must have one entry per order ({n})")
            _set(self, "phases_rad", rows)
        else:
            ph = check_real_tuple("ball phases_rad", ph)
            if len(ph) == 0:
                ph = (0.0,) * n
            if len(ph) != n:
                raise ValueError(f"ball phases_rad must have one entry per order ({n}), got {len(ph)}")
            _set(self, "phases_rad", ph)
        _set(self, "oversize_m", check_real_tuple("oversize_m", self.oversize_m, -1e-4, 1e-4))

    @property
    def is_zero(self) -> bool:
        return not any(self.amplitudes_m) and not any(self.oversize_m)


@dataclass(frozen=True)
class Waviness:
    """Waviness of the inner race, the outer race and the balls (eqs 9-14)."""

    inner: RaceWaviness = field(default_factory=RaceWaviness)
    outer: RaceWaviness = field(default_factory=RaceWaviness)
    balls: BallWaviness = field(default_factory=BallWaviness)

    def __post_init__(self) -> None:
        for name, cls in (("inner", RaceWaviness), ("outer", RaceWaviness), ("balls", BallWaviness)):
            if not isinstance(getattr(self, name), cls):
                raise ValueError(f"waviness.{name} must be a {cls.__name__}")


@dataclass(frozen=True)
class Loads:
    """External loads of eq 35: radial loads P_x, P_y and the axial preload P (= P_z)."""

    radial_load_x_n: float = 0.0
    radial_load_y_n: float = 0.0
    axial_preload_n: float = 800.0

    def __post_init__(self) -> None:
        _set(self, "radial_load_x_n",
             check_real("radial_load_x_n", self.radial_load_x_n, -1e6, 1e6))
        _set(self, "radial_load_y_n",
             check_real("radial_load_y_n", self.radial_load_y_n, -1e6, 1e6))
        _set(self, "axial_preload_n",
             check_real("axial_preload_n", self.axial_preload_n, 0.0, 1e6))


@dataclass(frozen=True)
class Damping:
    """Viscous damping added to eq 35 (the paper has none; see docs/model.md).

    Model: a diagonal damping matrix, one coefficient per rotor DOF,
    ``c_k = 2 * damping_ratio * sqrt(K_kk * M_kk)``, where K_kk is the diagonal of the bearing
    stiffness matrix at the static equilibrium of the configuration the Simulator is built (or
    re-damped) with and M_kk the rotor mass or radial inertia. This is a damping ratio of
    ``damping_ratio`` on each DOF's uncoupled, non-rotating mode. ``coefficients`` (5 values,
    N s/m for x, y, z and N m s/rad for theta_x, theta_y) overrides the ratio when given.
    """

    damping_ratio: float = 0.02
    coefficients: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        _set(self, "damping_ratio", check_real("damping_ratio", self.damping_ratio, 0.0, 1.0))
        if self.coefficients is not None:
            c = check_real_tuple("damping coefficients", self.coefficients, 0.0, 1e9)
            if len(c) != 5:
                raise ValueError(f"damping coefficients must have 5 entries (x, y, z, theta_x, theta_y), got {len(c)}")
            _set(self, "coefficients", c)


@dataclass(frozen=True)
class Integrator:
    """Newmark-beta time integration with equilibrium iterations at every step, and the
    per-ball Newton-Raphson solver (eq 31).

    ``newmark_tol_m`` bounds the estimated error (m; rotations at the groove radius) of the
    rotor's equilibrium iteration, and of each ball's once its Newton iteration converges
    quadratically; ``newton_tol_m`` bounds a ball's last Newton step where it does not yet (the
    stopping rules are in :mod:`bearing_gym.physics.rotor` and
    :func:`bearing_gym.physics.ball.solve_ball`)."""

    dt_s: float = 1.0e-5
    newmark_beta: float = 0.25
    newmark_gamma: float = 0.5
    newmark_tol_m: float = 1.0e-13
    newmark_max_iter: int = 30
    newton_tol_m: float = 1.0e-9
    newton_max_iter: int = 50
    divergence_limit_m: float = 1.0e-3

    def __post_init__(self) -> None:
        _set(self, "dt_s", check_real("dt_s", self.dt_s, 0.0, 1e-3, low_open=True))
        _set(self, "newmark_beta",
             check_real("newmark_beta", self.newmark_beta, 0.0, 0.5, low_open=True))
        _set(self, "newmark_gamma", check_real("newmark_gamma", self.newmark_gamma, 0.5, 1.0))
        _set(self, "newmark_tol_m",
             check_real("newmark_tol_m", self.newmark_tol_m, 0.0, 1e-6, low_open=True))
        _set(self, "newmark_max_iter", check_int("newmark_max_iter", self.newmark_max_iter, 1, 10000))
        _set(self, "newton_tol_m",
             check_real("newton_tol_m", self.newton_tol_m, 0.0, 1e-6, low_open=True))
        _set(self, "newton_max_iter", check_int("newton_max_iter", self.newton_max_iter, 1, 10000))
        _set(self, "divergence_limit_m", check_real(
            "divergence_limit_m", self.divergence_limit_m, 0.0, 1.0, low_open=True))


@dataclass(frozen=True)
class BearingParams:
    """Complete configuration of the rotor / ball-bearing system.

    ``race_control`` selects the race-control hypothesis of App. B: ``"outer"`` (default; the
    classic high-speed assumption), ``"inner"``, or ``"auto"`` (Jones/Harris criterion per
    ball: outer-race control when Q_o a_o E(k_o) cos(alpha_i - alpha_o) > Q_i a_i E(k_i)).

    ``include_centrifugal`` and ``include_gyroscopic`` switch the high-speed terms of the ball
    model off (both True by default, the paper's full model): without the centrifugal force
    F_e = m_b (D_p/2 + v_r) omega_m^2 (eq 29) the ball mass is taken as zero, and without the
    gyroscopic moment M_g (eq 30, with the race-control friction it causes, eqs 28 and 32) the
    ball inertia I_b is taken as zero; m_b and I_b enter the ball model only through these
    terms. Used for the paper's three-model comparison at 2,000 rpm (section 3.1, Fig. 6).
    """

    geometry: BearingGeometry = field(default_factory=BearingGeometry)
    material: Material = field(default_factory=Material)
    rotor: Rotor = field(default_factory=Rotor)
    waviness: Waviness = field(default_factory=Waviness)
    loads: Loads = field(default_factory=Loads)
    damping: Damping = field(default_factory=Damping)
    integrator: Integrator = field(default_factory=Integrator)
    shaft_speed_rpm: float = 20000.0
    race_control: str = "outer"
    initial_cage_angle_rad: float = 0.0
    include_centrifugal: bool = True
    include_gyroscopic: bool = True

    def __post_init__(self) -> None:
        for name, cls in (("geometry", BearingGeometry), ("material", Material), ("rotor", Rotor),
                          ("waviness", Waviness), ("loads", Loads), ("damping", Damping),
                          ("integrator", Integrator)):
            if not isinstance(getattr(self, name), cls):
                raise ValueError(f"{name} must be a {cls.__name__}, got {type(getattr(self, name)).__name__}")
        _set(self, "shaft_speed_rpm",
             check_real("shaft_speed_rpm", self.shaft_speed_rpm, 0.0, 200000.0))
        if self.race_control not in RACE_CONTROLS:
            raise ValueError(f"race_control must be one of {RACE_CONTROLS}, got {self.race_control!r}")
        _set(self, "initial_cage_angle_rad",
             check_real("initial_cage_angle_rad", self.initial_cage_angle_rad))
        _set(self, "include_centrifugal", check_bool("include_centrifugal", self.include_centrifugal))
        _set(self, "include_gyroscopic", check_bool("include_gyroscopic", self.include_gyroscopic))
        n = self.geometry.n_balls
        bw = self.waviness.balls
        if len(bw.oversize_m) not in (0, n):
            raise ValueError(f"waviness.balls.oversize_m must have n_balls = {n} entries or none, got {len(bw.oversize_m)}")
        if len(bw.phases_rad) and isinstance(bw.phases_rad[0], tuple) and len(bw.phases_rad) != n:
            raise ValueError(f"waviness.balls.phases_rad must have n_balls = {n} rows, got {len(bw.phases_rad)}")
        g = self.geometry
        for j, h in enumerate(bw.oversize_m):
            if h / 2 + sum(bw.amplitudes_m) >= min(g.inner_groove_radius_m, g.outer_groove_radius_m) - g.ball_diameter_m / 2:
                raise ValueError(f"waviness.balls.oversize_m[{j}] = {h:g} makes ball {j} larger than its groove")

    # --- derived quantities -------------------------------------------------------------------
    @property
    def shaft_speed_rad_s(self) -> float:
        return rpm_to_rad_s(self.shaft_speed_rpm)

    @property
    def ball_mass_kg(self) -> float:
        """m_b = rho pi D_b^3 / 6."""
        d = self.geometry.ball_diameter_m
        return self.material.density_kg_m3 * math.pi * (d * d * d) / 6.0

    @property
    def ball_inertia_kg_m2(self) -> float:
        """I_b = m_b D_b^2 / 10 (solid sphere)."""
        d = self.geometry.ball_diameter_m
        return self.ball_mass_kg * (d * d) / 10.0

    def replace(self, **overrides: Any) -> "BearingParams":
        """Return a copy with flat overrides applied (same keywords as :func:`default_params`)."""
        return _apply_overrides(self, overrides)



# flat keyword -> (section, field); section None means a BearingParams field
_FLAT_KEYS: dict[str, tuple[str | None, str]] = {
    "shaft_speed_rpm": (None, "shaft_speed_rpm"),
    "race_control": (None, "race_control"),
    "initial_cage_angle_rad": (None, "initial_cage_angle_rad"),
    "include_centrifugal": (None, "include_centrifugal"),
    "include_gyroscopic": (None, "include_gyroscopic"),
    "damping_ratio": ("damping", "damping_ratio"),
    "damping_coefficients": ("damping", "coefficients"),
}
for _sec, _cls in (("geometry", BearingGeometry), ("material", Material), ("rotor", Rotor),
                   ("loads", Loads), ("integrator", Integrator)):
    for _f in dataclasses.fields(_cls):
        _FLAT_KEYS[_f.name] = (_sec, _f.name)
_SECTIONS = ("geometry", "material", "rotor", "waviness", "loads", "damping", "integrator")


def _apply_overrides(base: BearingParams, overrides: dict[str, Any]) -> BearingParams:
    top: dict[str, Any] = {}
    per_section: dict[str, dict[str, Any]] = {}
    for key, value in overrides.items():
        if key in _SECTIONS:
            top[key] = value
        elif key in _FLAT_KEYS:
            sec, name = _FLAT_KEYS[key]
            if sec is None:
                top[name] = value
            else:
                per_section.setdefault(sec, {})[name] = value
        else:
            raise TypeError(
                f"unknown parameter {key!r}; valid keywords: {', '.join(sorted(list(_FLAT_KEYS) + list(_SECTIONS)))}")
    for sec, vals in per_section.items():
        current = top.get(sec, getattr(base, sec))
        top[sec] = dataclasses.replace(current, **vals)
    return dataclasses.replace(base, **top)


def default_params(**overrides: Any) -> BearingParams:
    """The paper's Table 1 configuration (20,000 rpm, 800 N preload, c = 4 um, e = 1e-5 m).

    Flat keyword overrides name any field of any section, e.g. ``shaft_speed_rpm``,
    ``axial_preload_n``, ``radial_load_x_n``, ``radial_load_y_n``, ``clearance_inner_m``,
    ``clearance_outer_m``, ``eccentricity_m``, ``damping_ratio``, ``race_control``, ``dt_s``;
    whole sections can be passed too (``waviness=Waviness(...)``). An unknown keyword raises
    :class:`TypeError` naming it; an invalid value raises :class:`ValueError` naming the field.
    """
    return _apply_overrides(BearingParams(), overrides)
