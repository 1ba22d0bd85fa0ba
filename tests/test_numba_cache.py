"""Where the numba kernels are cached: one place for the library, train.py, the CLI and the tests."""

from pathlib import Path


def test_cache_dir_is_numba_cache_dir_else_the_user_cache(monkeypatch, tmp_path):
    import numba

    from bearing_gym import _numba_cache
    before = numba.config.CACHE_DIR
    try:
        monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "env"))
        explicit = Path(_numba_cache.configure())
        monkeypatch.delenv("NUMBA_CACHE_DIR")
        monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
        xdg = Path(_numba_cache.configure())
        monkeypatch.delenv("XDG_CACHE_HOME")
        monkeypatch.setenv("HOME", str(tmp_path / "home"))
        home = Path(_numba_cache.configure())
    finally:
        numba.config.CACHE_DIR = before
    assert explicit.parent == tmp_path / "env"
    assert xdg.parent == tmp_path / "xdg" / "bearing_gym" / "numba"
    assert home.parent == tmp_path / "home" / ".cache" / "bearing_gym" / "numba"
    # the last part is the hash of the kernel sources, the same whatever the base directory
    assert explicit.name == xdg.name == home.name and len(explicit.name) == 16

