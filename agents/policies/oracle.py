"""The oracle rebuilt on the reward map: the best stationary preload of the nearest cell.

``docs/reward_map.csv`` (``python -m bearing_gym.envs.reward_map``) holds the stationary reward of
every preload (300-2000 N, 100 N steps) in 81 cells of speed x radial load x clearance x rotor
unbalance (eccentricity 5, 10, 20 um). For each cell the oracle table keeps the preload of the
highest stationary reward; the policy, told the true operating point (speed, radial load,
clearance, eccentricity) before each ``predict``, sets the preload of the nearest cell (distances
scaled by the grid's spans). It is not interpolated: with isolated period-1 windows, the average
of two good preloads can sit in a quasi-periodic band.

It knows what no policy observes (radial load, clearance and unbalance exactly) but not the
events to come, nor anything between the grid's cells, so it is a reference, not a bound. Before
the eccentricity axis (issue 31) it knew only the 10 um slice, whatever the episode's unbalance.

    python -m agents.policies.oracle      # rebuild agents/data/oracle_table.csv from docs/reward_map.csv
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from bearing_gym.envs.actuator import PreloadActuator

from agents.policies.scripted import Policy
from agents.paths import DATA_DIR, PACKAGE_DIR


__all__ = ["MapOracle", "TABLE_PATH", "build_table"]

TABLE_PATH = DATA_DIR / "oracle_table.csv"
MAP_PATH = PACKAGE_DIR.parent / "docs" / "reward_map.csv"    # in a source checkout (build_table)
COLUMNS = ("speed_rpm", "radial_load_n", "clearance_um", "eccentricity_um", "best_preload_n", "best_reward",
           "period1")


def build_table(map_csv: str | Path = MAP_PATH, out: str | Path = TABLE_PATH) -> list[dict]:
    """Per cell of the reward map, its best preload; written to ``out``."""
    from bearing_gym.envs.reward_map import best_preloads, read_csv
    best = best_preloads(read_csv(map_csv))
    rows = [{"speed_rpm": c[0], "radial_load_n": c[1], "clearance_um": c[2], "eccentricity_um": c[3],
             "best_preload_n": p.preload_n, "best_reward": p.mean_reward, "period1": p.period1}
            for c, p in sorted(best.items())]
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    return rows


class MapOracle(Policy):
    """Best stationary preload of the nearest reward-map cell to the true operating point."""

    def __init__(self, table_path: str | Path = TABLE_PATH, actuator: PreloadActuator | None = None):
        super().__init__(actuator)
        with open(table_path, newline="") as fh:
            rows = list(csv.DictReader(fh))
        self.cells = np.array([[float(r[c]) for c in ("speed_rpm", "radial_load_n", "clearance_um",
                                                      "eccentricity_um")] for r in rows])
        self.best_n = np.array([float(r["best_preload_n"]) for r in rows])
        span = self.cells.max(axis=0) - self.cells.min(axis=0)
        self.scale = np.where(span > 0, span, 1.0)
        self.name = "oracle (reward map, nearest cell)"
        self._conditions: np.ndarray | None = None

    def set_conditions(self, speed_rpm: np.ndarray, radial_load_n: np.ndarray, clearance_m: np.ndarray,
                       eccentricity_m: np.ndarray | None = None) -> None:
        """The true operating point of each env (SI: clearance and rotor eccentricity in m), as
        ``BearingPreloadVectorEnv.operating_points`` gives it."""
        if eccentricity_m is None:
            raise ValueError("MapOracle.set_conditions needs eccentricity_m (the rotor unbalance, m; "
                             "the map's axis spans 5e-6-2e-5 m): the best preload moves with it")
        self._conditions = np.column_stack([speed_rpm, radial_load_n, np.asarray(clearance_m) * 1e6,
                                            np.asarray(eccentricity_m) * 1e6])

    def preload_n(self, conditions: np.ndarray) -> np.ndarray:
        """The best preload of the nearest cell for each row (speed rpm, radial N, clearance um,
        eccentricity um)."""
        d = (conditions[:, None, :] - self.cells[None, :, :]) / self.scale
        return self.best_n[np.argmin(np.sum(d * d, axis=2), axis=1)]

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        if self._conditions is None:
            raise RuntimeError("MapOracle needs set_conditions(speed, radial_load, clearance, eccentricity) "
                               "before predict")
        return self.preload_to_action(self.preload_n(self._conditions)), state


if __name__ == "__main__":
    rows = build_table()
    print(f"wrote {TABLE_PATH}: {len(rows)} cells")
