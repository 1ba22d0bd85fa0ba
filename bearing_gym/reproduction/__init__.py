"""Reproduction of Bai & Xu (2006), section 3: ``python -m bearing_gym.reproduction`` (or
``bearing-gym reproduce``); see :mod:`.main` for the options and outputs."""
