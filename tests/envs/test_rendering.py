"""Rendering leaves the process's matplotlib alone and writes headless frames beside, not
over, the package name."""

import tempfile

import matplotlib
import numpy as np

from bearing_gym.envs import BearingPreloadEnv, BearingPreloadVectorEnv, rendering


def _forbid_backend_changes(monkeypatch):
    import matplotlib.pyplot as plt

    def forbidden(*args, **kwargs):
        raise AssertionError("the env changed the process's matplotlib backend or mode")

    monkeypatch.setattr(matplotlib, "use", forbidden)
    monkeypatch.setattr(matplotlib, "interactive", forbidden)
    monkeypatch.setattr(plt, "ion", forbidden)
    return plt


def test_rgb_array_rendering_changes_no_matplotlib_state(monkeypatch):
    _forbid_backend_changes(monkeypatch)
    env = BearingPreloadEnv(scenario="paper", render_mode="rgb_array")
    env.reset(seed=0)
    env.step(np.array([0.0], dtype=np.float32))
    assert env.render().dtype == np.uint8
    venv = BearingPreloadVectorEnv(num_envs=2, scenario="paper", render_mode="rgb_array")
    venv.reset(seed=0)
    venv.step(np.zeros((2, 1), dtype=np.float32))
    assert all(f.dtype == np.uint8 for f in venv.render())


def test_opening_the_human_window_keeps_the_users_interactive_mode(monkeypatch):
    plt = _forbid_backend_changes(monkeypatch)
    was_interactive = matplotlib.is_interactive()
    monkeypatch.setattr(matplotlib, "get_backend", lambda *a, **k: "tkagg")   # as with a display
    monkeypatch.setattr(plt, "show", lambda *a, **k: None)
    fig = rendering.open_window()
    try:
        assert fig is not None and matplotlib.is_interactive() == was_interactive
    finally:
        plt.close(fig)


def test_headless_human_rendering_writes_to_a_frames_folder_not_a_package_name(monkeypatch, tmp_path):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.setattr(rendering, "open_window", lambda: None)        # headless
    env = BearingPreloadEnv(scenario="paper", render_mode="human")
    env.reset(seed=0)
    env.step(np.array([0.0], dtype=np.float32))
    latest = tmp_path / "bearing_gym_frames" / "latest.png"
    assert latest.read_bytes()[:4] == b"\x89PNG"
    assert not (tmp_path / "bearing_gym").exists()
    env.close()
