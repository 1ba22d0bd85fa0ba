"""``python -m bearing_gym.reproduction``: see :mod:`bearing_gym.reproduction.main`."""

from bearing_gym.reproduction.main import main

raise SystemExit(main())
