"""``python -m bearing_gym.cli``: the ``bearing-gym`` command line."""

from bearing_gym.cli.main import main

raise SystemExit(main())
