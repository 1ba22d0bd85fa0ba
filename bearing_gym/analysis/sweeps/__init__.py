"""Parameter sweeps: preload continuation, cold starts and stability maps (paper sections
3.2-3.4, Figs 7, 15-17).

* :mod:`.points` -- one point (:func:`measure_point`, :func:`cold_start_point`) or one
  continuation chain (:func:`continuation_chain`), the row columns and :class:`SweepSettings`;
* :mod:`.runner` -- many points on a pluggable executor (:func:`run_tasks`,
  :func:`stability_map`, :class:`SerialExecutor`);
* :mod:`.store` -- a sweep CSV that a rerun resumes (:class:`.store.ResumingExecutor`);
* :mod:`.io` -- CSV and NPZ files of rows; :mod:`.results` -- critical preload and period-1
  windows; :mod:`.plots` -- figures.

Every public name of these modules but the store's is importable from here.
"""

from .io import load_csv, save_csv, save_npz
from .plots import column_label, plot_stability_map, plot_sweep, point_classes
from .points import (AXIAL_SHARE, COLUMNS, SweepSettings, axial_index, axial_pair,
                     cold_start_point, continuation_chain, measure_point, operating_point)
from .results import critical_preload, stable_windows
from .runner import SerialExecutor, local_process_pool, run_tasks, stability_map

__all__ = ["COLUMNS", "SweepSettings", "SerialExecutor", "local_process_pool", "AXIAL_SHARE", "measure_point",
           "axial_index", "axial_pair", "operating_point", "continuation_chain",
           "cold_start_point", "run_tasks", "stability_map", "critical_preload",
           "stable_windows", "save_csv", "load_csv", "save_npz", "plot_sweep",
           "plot_stability_map", "column_label", "point_classes"]
