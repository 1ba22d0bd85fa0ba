"""Critical preload over (shaft speed, radial load, clearance): the table behind the
speed-scheduled policy and the critical-preload oracle of the first definition
(``OraclePreload``; the evaluation now uses the reward-map oracle, :mod:`agents.policies.oracle`).

Built with :func:`bearing_gym.analysis.sweeps.stability_map` (continuation: the preload steps
down from the previous end state, so the number is the loss of stability of the periodic orbit)
and saved to ``agents/data/stability_table.npz``:

    python -m agents.policies.stability_table            # about 5 minutes on 2 cores

The radial load here is the magnitude |F_r| of the env's radial load (the sweep applies
P_x = P_y = |F_r| / sqrt(2)). Lookups interpolate linearly and clamp to the grid.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agents.paths import DATA_DIR


DEFAULT_PATH = DATA_DIR / "stability_table.npz"
SPEEDS_RPM = (10000.0, 15000.0, 20000.0, 25000.0)
RADIAL_LOADS_N = (0.0, 250.0, 500.0)
CLEARANCES_M = (4e-6, 15e-6, 30e-6)
PRELOADS_N = tuple(float(p) for p in np.arange(2000.0, 299.0, -100.0))


@dataclass(frozen=True)
class StabilityTable:
    speeds_rpm: np.ndarray
    radial_loads_n: np.ndarray
    clearances_m: np.ndarray
    critical_n: np.ndarray          # (speeds, radial loads, clearances)

    @classmethod
    def load(cls, path: str | Path = DEFAULT_PATH) -> "StabilityTable":
        path = Path(path)
        if not path.exists():
            raise FileNotFoundError(f"{path} not found: build it with `python -m agents.policies.stability_table`")
        d = np.load(path)
        return cls(d["speeds_rpm"], d["radial_loads_n"], d["clearances_m"], d["critical_n"])

    def save(self, path: str | Path = DEFAULT_PATH) -> None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        np.savez(path, speeds_rpm=self.speeds_rpm, radial_loads_n=self.radial_loads_n,
                 clearances_m=self.clearances_m, critical_n=self.critical_n)

    def critical(self, speed_rpm, radial_load_n, clearance_m) -> np.ndarray:
        """Critical preload (N) at the given conditions (arrays of equal length)."""
        from scipy.interpolate import RegularGridInterpolator
        grid = (self.speeds_rpm, self.radial_loads_n, self.clearances_m)
        f = RegularGridInterpolator(grid, self.critical_n)
        pts = np.column_stack([np.clip(np.asarray(v, dtype=float), g[0], g[-1])
                               for v, g in zip((speed_rpm, radial_load_n, clearance_m), grid)])
        return f(pts)

    def worst_case(self, speed_rpm) -> np.ndarray:
        """Highest critical preload over radial loads and clearances at each speed."""
        worst = self.critical_n.max(axis=(1, 2))
        return np.interp(np.asarray(speed_rpm, dtype=float), self.speeds_rpm, worst)


def build(speeds=SPEEDS_RPM, radial_loads=RADIAL_LOADS_N, clearances=CLEARANCES_M,
          preloads=PRELOADS_N, progress: bool = True) -> StabilityTable:
    import bearing_gym
    from bearing_gym.analysis.sweeps import SweepSettings, critical_preload, stability_map

    settings = SweepSettings(settle_s=0.2, measure_s=0.06, floquet=False)
    rows = stability_map(bearing_gym.default_params(), list(preloads), settings=settings,
                         shaft_speeds_rpm=list(speeds),
                         radial_loads_n=[r / math.sqrt(2.0) for r in radial_loads],
                         clearances_m=list(clearances), mode="continuation", progress=progress)
    crit = np.full((len(speeds), len(radial_loads), len(clearances)), np.nan)
    by_label: dict = {}
    for r in rows:
        by_label.setdefault(r["label"], []).append(r)
    for group in by_label.values():
        r0 = group[0]
        i = int(np.argmin(np.abs(np.asarray(speeds) - float(r0["shaft_speed_rpm"]))))
        j = int(np.argmin(np.abs(np.asarray(radial_loads) - math.hypot(float(r0["radial_load_x_n"]), float(r0["radial_load_y_n"])))))
        k = int(np.argmin(np.abs(np.asarray(clearances) - float(r0["clearance_m"]))))
        c = critical_preload(group)
        value = float(c["critical_n"])
        if not np.isfinite(value):   # periodic everywhere -> lowest preload; never -> highest
            value = min(preloads) if "below the range" in c["note"] else max(preloads)
        crit[i, j, k] = value
    return StabilityTable(np.asarray(speeds, float), np.asarray(radial_loads, float),
                          np.asarray(clearances, float), crit)


def main() -> None:
    ap = argparse.ArgumentParser(description="Build the critical-preload table of the scripted policies.")
    ap.add_argument("--out", default=str(DEFAULT_PATH))
    args = ap.parse_args()
    table = build()
    table.save(args.out)
    print(f"wrote {args.out}")
    for i, s in enumerate(table.speeds_rpm):
        print(f"{s:8.0f} rpm:", np.array2string(table.critical_n[i], precision=0))


if __name__ == "__main__":
    main()
