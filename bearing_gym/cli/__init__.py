"""``bearing-gym``: the command line of bearing_gym (see :mod:`.main` for the commands)."""

from .errors import CLIError, RunError
from .main import main

__all__ = ["main", "CLIError", "RunError"]
