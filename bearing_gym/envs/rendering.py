"""The frames of ``BearingPreload-v0``, shared by the single and the vector env.

What a frame shows is decided here once: :func:`record_interval` remembers what an env's last
control interval adds to its frame (orbit, Poincare points, preload trace), :func:`draw_frame`
draws the three panels on a matplotlib ``Figure`` and :func:`rgb_frame` renders them to an
RGB array. None of them touches pyplot or the process's matplotlib backend: a ``Figure`` with
an Agg canvas draws off-screen whatever backend the user chose. :class:`HumanWindow` is
``render_mode="human"``: a pyplot window if the user's backend is interactive, else PNG frames.
"""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path
from typing import Any, Callable

import numpy as np

__all__ = ["HISTORY_LENGTH", "POINCARE_LENGTH", "FRAME_SIZE_IN", "FRAME_DPI",
           "record_interval", "draw_frame", "rgb_frame", "HumanWindow", "latest_frame_path", "open_window"]

HISTORY_LENGTH = 500      # control intervals in the preload panel
POINCARE_LENGTH = 2000    # points in the Poincare panel
FRAME_SIZE_IN = (9, 3)    # figure size of an rgb_array frame (inches)
FRAME_DPI = 80


def record_interval(batch, b: int, history: deque, poincare: deque) -> np.ndarray | None:
    """Append env ``b``'s last control interval to its frame memory.

    ``history`` gets ``(t, preload, set-point, qpi)``, ``poincare`` the (x, z) points where the
    unwrapped shaft angle crosses a whole number of turns (a fixed phase, so the points of all
    intervals belong to one section). Returns the interval's x, y, z orbit (rows x 3, metres),
    or None if the interval recorded no rows (the env's previous orbit then stays valid).
    """
    from bearing_gym.analysis.poincare import angle_section
    from .features import F_QPI
    from bearing_gym.physics.rotor import R_SHAFT, R_X

    history.append((float(batch.t_episode[b]), float(batch.preload[b]), float(batch.setpoint[b]),
                    float(batch.feats[b, F_QPI])))
    w = batch.window(b)
    if not len(w):
        return None
    poincare.extend(map(tuple, angle_section(w[:, R_SHAFT], w[:, [R_X, R_X + 2]], 2.0 * math.pi,
                                             phase_rad=0.0)))
    return w[:, R_X:R_X + 3].copy()


def _note(ax, text: str) -> None:
    """A grey note in the middle of an empty panel (so no frame shows bare axes)."""
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, fontsize=7,
            color="0.35")
    ax.set_xticks([])                 # no 0-1 placeholder scale on a panel without data
    ax.set_yticks([])


def draw_frame(fig, orbit: np.ndarray | None, poincare, history) -> None:
    """The three panels of a frame on ``fig``: the x-y orbit of the last interval, the Poincare
    section (x, z once per shaft turn) and the preload and set-point over time. ``orbit`` is
    drawn only once the episode has a history (it would be the previous episode's). A panel
    with nothing to draw yet (the reset frame: the settled start, before the first control
    interval) says so instead of showing empty axes."""
    ax1, ax2, ax3 = fig.subplots(1, 3)
    if orbit is not None and len(history):
        ax1.plot(orbit[:, 0] * 1e6, orbit[:, 1] * 1e6, lw=0.6)
    else:
        _note(ax1, "reset: settled start,\nno control interval yet\n(the orbit of each control\n"
                   "interval is drawn after it)" if not len(history) else
                   "no samples in the last interval")
    ax1.set(title="orbit (last interval)", xlabel="x (um)", ylabel="y (um)")
    if len(poincare):
        p = np.array(poincare)
        ax2.plot(p[:, 0] * 1e6, p[:, 1] * 1e6, ".", ms=2)
    else:
        _note(ax2, "no Poincare points yet\n(one per shaft turn\nonce the episode runs)")
    ax2.set(title="Poincare (once per turn)", xlabel="x (um)", ylabel="z (um)")
    if len(history):
        h = np.array(history)
        mark = "o" if len(h) == 1 else None        # one point: a line would draw nothing
        ax3.plot(h[:, 0], h[:, 1], marker=mark, label="preload")
        ax3.plot(h[:, 0], h[:, 2], "--", marker=mark, mfc="none", label="set-point")
        ax3.legend(fontsize=7)
        lo, hi = float(h[:, 1:3].min()), float(h[:, 1:3].max())
        pad = max(50.0, 0.1 * (hi - lo))      # newtons: no 1e-6 N offset axis for a flat trace
        ax3.set_ylim(lo - pad, hi + pad)
        ax3.ticklabel_format(axis="y", useOffset=False)
    else:
        _note(ax3, "reset: t = 0 s\n(the preload and set-point\ntraces start with the first step)")
    ax3.set(title="preload", xlabel="t (s)", ylabel="preload (N)")
    fig.tight_layout()


def rgb_frame(orbit: np.ndarray | None, poincare, history) -> np.ndarray:
    """The frame as an (H, W, 3) uint8 array, drawn off-screen (Figure + Agg canvas, no pyplot)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=FRAME_SIZE_IN, dpi=FRAME_DPI)
    canvas = FigureCanvasAgg(fig)
    draw_frame(fig, orbit, poincare, history)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()


def latest_frame_path() -> Path:
    """Where headless human rendering without ``render_dir`` keeps the latest frame."""
    import tempfile
    # not <tmp>/bearing_gym: a folder of the package's name would shadow the package for any
    # script run from the temp dir
    return Path(tempfile.gettempdir()) / "bearing_gym_frames" / "latest.png"


def open_window():
    """A pyplot figure in the user's matplotlib backend if that backend is interactive, else
    None (headless). Neither picks a backend nor switches interactive mode on: the window is
    shown with ``show(block=False)`` and updated by ``pause``, whatever the user's settings."""
    try:
        import matplotlib
        import matplotlib.pyplot as plt
        backend = matplotlib.get_backend().lower()
        try:
            from matplotlib.backends import BackendFilter, backend_registry
            interactive = backend_registry.list_builtin(BackendFilter.INTERACTIVE)
        except ImportError:                      # matplotlib < 3.9
            from matplotlib import rcsetup
            interactive = rcsetup.interactive_bk
        if backend not in {b.lower() for b in interactive}:
            return None
        fig = plt.figure("BearingPreload-v0", figsize=(FRAME_SIZE_IN[0], FRAME_SIZE_IN[1] + 0.3))
        plt.show(block=False)
        return fig
    except Exception:  # noqa: BLE001 - e.g. a GUI backend named in MPLBACKEND without a display
        return None


class HumanWindow:
    """``render_mode="human"``: the frame in a window (:func:`open_window`) while the user keeps
    it open, and/or as PNG files: every frame into ``render_dir`` if given, else - headless
    only - the latest one at :func:`latest_frame_path`. ``state`` is "unopened", then "open",
    "closed" (by the user) or "none" (no interactive backend)."""

    def __init__(self, render_dir: Path | None, fps: float, opener: Callable[[], Any] | None = None,
                 warn: Callable[[str], None] | None = None):
        self.render_dir = render_dir
        self.fps = fps
        self.figure: Any = None
        self.state = "unopened"
        self.frames = 0
        self._opener = opener
        self._warn = warn

    def show(self, draw: Callable[[Any], None], title: str) -> None:
        """Draw a frame (``draw(fig)`` puts the panels on a figure) with ``title``."""
        if self.state == "unopened":
            self.figure = (self._opener or open_window)()      # looked up now: tests replace it
            self.state = "open" if self.figure is not None else "none"
            if self.figure is None and self.render_dir is None and self._warn is not None:
                self._warn(f"render_mode='human': no interactive matplotlib backend (no display?); writing the "
                           f"latest frame to {latest_frame_path()} (pass render_dir=... to keep every frame)")
        if self.state == "open":
            import matplotlib.pyplot as plt
            if not plt.fignum_exists(self.figure.number):       # closed by the user
                self.figure, self.state = None, "closed"
            else:
                self.figure.clf()
                draw(self.figure)
                self.figure.suptitle(title, fontsize=8)
                self.figure.tight_layout()
                self.figure.canvas.draw_idle()
                plt.pause(1.0 / self.fps)
        if self.render_dir is None and self.state != "none":
            return
        from matplotlib.figure import Figure

        fig = Figure(figsize=(FRAME_SIZE_IN[0], FRAME_SIZE_IN[1] + 0.3), dpi=FRAME_DPI)   # + title
        draw(fig)
        fig.suptitle(title, fontsize=8)
        fig.tight_layout()
        if self.render_dir is not None:
            self.render_dir.mkdir(parents=True, exist_ok=True)
            path = self.render_dir / f"frame_{self.frames:05d}.png"
        else:
            path = latest_frame_path()
            path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path)
        self.frames += 1

    @property
    def target(self) -> str | None:
        """Where frames go once the first is out: "window", the frames folder, the latest-frame
        PNG, or None (nothing drawn yet, or the window was closed)."""
        if self.state in ("unopened", "closed"):
            return None
        if self.state == "open":
            return "window"
        return str(self.render_dir) if self.render_dir is not None else str(latest_frame_path())

    def close(self) -> None:
        if self.figure is not None:
            import matplotlib.pyplot as plt
            plt.close(self.figure)
            self.figure = None
