"""What the reproduction computes: the paper's reference numbers, the grids and durations of the
full and the quick run, and the settings of every sweep point."""

from __future__ import annotations

from dataclasses import dataclass

from bearing_gym.analysis.sweeps import SweepSettings

__all__ = ["PAPER", "QPI_THRESHOLD", "Plan", "FULL", "QUICK", "sweep_settings", "DAMPING_MODEL"]

PAPER = dict(
    floquet_800n=complex(-0.77911, 0.25389),      # corrected (docs/model.md, errata), modulus 0.8194
    floquet_600n=complex(-1.2041, 1.4228),        # modulus 1.8639
    critical_preload_n=650.0,                     # section 3.4 (section 3.2: "below 800 N")
    critical_preload_n_radial_200=1150.0,
    critical_preload_n_radial_500=1350.0,
)


from bearing_gym.analysis.signals import QPI_THRESHOLD  # noqa: E402  (re-exported for the reproduction)


@dataclass(frozen=True)
class Plan:
    """Grids and durations (s) of one reproduction run."""

    name: str
    cage_rpms: tuple = (2500.0, 5000.0, 10000.0, 20000.0)
    cage_settle_s: float = 0.4
    cage_measure_s: float = 0.2
    cage_static_rpms: tuple = tuple(sorted({float(r) for r in range(1000, 25001, 1000)} | {2500.0}))
    models_settle_s: float = 0.5
    models_measure_s: float = 0.09
    detail_first_settle_s: float = 0.6
    detail_path_settle_s: float = 0.3
    detail_measure_s: float = 0.4
    lyapunov_s: float = 0.3
    sweep_settle_s: float = 0.3
    sweep_measure_s: float = 0.1
    sweep_cold_settle_s: float = 0.5
    default_down: tuple = tuple(float(p) for p in range(1600, 399, -25))
    default_refine_n: float | None = 5.0
    default_up: tuple = tuple(float(p) for p in range(400, 1601, 25))
    default_cold: tuple = tuple(float(p) for p in range(1600, 399, -25))
    clearances_um: tuple = (4.0, 10.0, 20.0, 30.0)
    clearance_down: tuple = tuple(float(p) for p in range(1600, 299, -50))
    clearance_refine_n: float | None = 10.0
    clearance_cold: bool = True
    radial_loads_n: tuple = (200.0, 500.0)
    radial_down: tuple = tuple(float(p) for p in range(2000, 399, -50))
    radial_refine_n: float | None = 10.0
    radial_cold: bool = True
    radial_spectra: bool = True
    waviness_settle_s: float = 0.3
    waviness_measure_s: float = 0.2
    speed_map_rpms: tuple = (10000.0, 15000.0, 20000.0, 25000.0)
    speed_map_preloads: tuple = tuple(float(p) for p in range(1200, 199, -100))
    damping_ratios: tuple = (0.01, 0.04)
    damping_down: tuple = tuple(float(p) for p in range(1000, 399, -25))
    damping_cold: tuple = tuple(float(p) for p in range(1000, 399, -50))
    linear_preloads: tuple = tuple(float(p) for p in range(100, 1601, 100))


FULL = Plan(name="full")


QUICK = Plan(
    name="quick", cage_settle_s=0.1, cage_measure_s=0.1, cage_static_rpms=(2500.0, 5000.0, 10000.0, 15000.0, 20000.0),
    models_settle_s=0.2, detail_first_settle_s=0.25, detail_path_settle_s=0.1, detail_measure_s=0.15,
    lyapunov_s=0.05, sweep_settle_s=0.15, sweep_measure_s=0.05, sweep_cold_settle_s=0.3,
    default_down=tuple(float(p) for p in range(1000, 499, -50)), default_refine_n=10.0,
    default_up=(), default_cold=(800.0, 700.0, 650.0, 600.0),
    clearance_down=tuple(float(p) for p in range(1200, 399, -100)), clearance_refine_n=None,
    clearance_cold=False, radial_down=tuple(float(p) for p in range(2000, 999, -100)),
    radial_refine_n=None, radial_cold=False, radial_spectra=False, waviness_settle_s=0.1,
    waviness_measure_s=0.1, speed_map_rpms=(), damping_ratios=(),
    linear_preloads=(400.0, 800.0, 1200.0, 1600.0))


def sweep_settings(plan: Plan, refine: float | None = None):
    return SweepSettings(settle_s=plan.sweep_settle_s, measure_s=plan.sweep_measure_s,
                         cold_settle_s=plan.sweep_cold_settle_s, qpi_threshold=QPI_THRESHOLD,
                         floquet=True, refine_step_n=refine)


DAMPING_MODEL = ("viscous damping on each rotor DOF (x, y, z, theta_x, theta_y), ratio zeta on the "
                 "DOF's uncoupled non-rotating mode at the static equilibrium of each point: "
                 "c_k = 2 zeta sqrt(K_kk M_kk) (docs/model.md)")
