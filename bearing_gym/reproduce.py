"""``python -m bearing_gym.reproduce``: the reproduction of Bai & Xu (2006), kept under its old
name; the code is the package :mod:`bearing_gym.reproduction`."""

from bearing_gym.reproduction.main import main

__all__ = ["main"]

if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
