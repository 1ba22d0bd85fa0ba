"""The operating-point options and the BearingParams fields behind them: defaults, conversion
from the options' units to SI, and errors of bearing_gym.params translated to the option."""

from __future__ import annotations

import math
import re
from typing import Any, Sequence

from bearing_gym import default_params
from bearing_gym.params import BearingParams

from .errors import CLIError

__all__ = ["PARAM_OPTIONS", "LIST_OPTIONS", "option_defaults", "make_params", "params_from_args",
           "clearance_limit_m"]

PARAM_OPTIONS: dict[str, tuple[tuple[str, ...], float | None, str]] = {
    "rpm": (("shaft_speed_rpm",), 1.0, "rpm"),
    "preload": (("axial_preload_n",), 1.0, "N"),
    "clearance_um": (("clearance_inner_m", "clearance_outer_m"), 1e6, "um"),
    "radial_load": (("radial_load_x_n", "radial_load_y_n"), 1.0, "N"),
    "eccentricity_um": (("eccentricity_m",), 1e6, "um"),
    "damping_ratio": (("damping_ratio",), 1.0, ""),
    "dt_us": (("dt_s",), 1e6, "us"),
    "race_control": (("race_control",), None, ""),
}


LIST_OPTIONS = {"preloads": "preload", "rpms": "rpm", "radial_loads": "radial_load",
                 "clearances_um": "clearance_um", "damping_ratios": "damping_ratio"}


def clearance_limit_m(params: BearingParams | None = None) -> float:
    """The largest clearance the geometry allows (exclusive): the smaller groove radius minus
    the ball radius."""
    g = (params or default_params()).geometry
    return min(g.inner_groove_radius_m, g.outer_groove_radius_m) - g.ball_diameter_m / 2


def option_defaults() -> dict:
    p = default_params()
    return dict(clearance_max_um=clearance_limit_m(p) * 1e6, rpm=p.shaft_speed_rpm, preload=p.loads.axial_preload_n,
                clearance_um=p.geometry.clearance_inner_m * 1e6,
                radial_load=p.loads.radial_load_x_n, eccentricity_um=p.rotor.eccentricity_m * 1e6,
                damping_ratio=p.damping.damping_ratio, dt_us=p.integrator.dt_s * 1e6,
                race_control=p.race_control)


_RANGE = re.compile(r"in ([\[(])([^,\]()]+), ([^,\]()]+)([\])])")


def _scaled_range(msg: str, divisor: float) -> str | None:
    """The first interval of a params error message, converted from SI to the option's unit."""
    m = _RANGE.search(msg)
    if not m:
        return None

    def conv(txt: str) -> str:
        try:
            v = float(txt)
        except ValueError:
            return txt
        return txt if math.isinf(v) else f"{v * divisor:g}"

    return f"{m.group(1)}{conv(m.group(2))}, {conv(m.group(3))}{m.group(4)}"


def _explain_params_error(err: Exception, owner: dict[str, tuple[str, str, Any]]) -> str:
    """One line naming the option behind a ValueError of bearing_gym.params."""
    msg = " ".join(str(err).split())
    field = msg.split(" ", 1)[0]
    if (field in ("inner_groove_radius_m", "outer_groove_radius_m", "clearance_inner_m",
                  "clearance_outer_m") and "clearance_inner_m" in owner):
        limit = clearance_limit_m()
        opt, _, value = owner["clearance_inner_m"]
        if limit < 1e-3:
            return (f"{opt}: the clearance must be in [0, {limit * 1e6:g}) um (below the groove "
                    f"radius minus the ball radius), got {value:g}")
    if field not in owner:
        return f"invalid operating point: {msg}"
    opt, dest, value = owner[field]
    divisor = PARAM_OPTIONS[dest][1]
    unit = PARAM_OPTIONS[dest][2]
    text = f"{opt}: {msg}"
    if divisor not in (None, 1.0):
        rng = _scaled_range(msg, divisor)
        if rng:
            text += f" (i.e. {opt} must be in {rng} {unit}, got {value:g})"
    return text


def make_params(items: Sequence[tuple[str, str, Any]], base=None):
    """BearingParams from (option string, option dest, value) triples; a bad value raises
    CLIError naming the option."""
    over: dict[str, Any] = {}
    owner: dict[str, tuple[str, str, Any]] = {}
    for opt, dest, value in items:
        fields, divisor, _ = PARAM_OPTIONS[dest]
        for f in fields:
            over[f] = value if divisor is None else value / divisor
            owner[f] = (opt, dest, value)
    try:
        return base.replace(**over) if base is not None else default_params(**over)
    except (ValueError, TypeError) as err:
        raise CLIError(_explain_params_error(err, owner)) from None


def params_from_args(args, exclude: Sequence[str] = ()):
    items = [(f"--{d.replace('_', '-')}", d, getattr(args, d)) for d in PARAM_OPTIONS
             if d not in exclude and hasattr(args, d)]
    return make_params(items)
