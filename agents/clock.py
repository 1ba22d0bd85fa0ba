"""The ``--until HH:MM`` of the long commands: a wall-clock deadline that work is split against."""

from __future__ import annotations

from datetime import datetime, timedelta

__all__ = ["deadline"]


def deadline(text: str) -> datetime:
    """The next time ``HH:MM`` (local): today's, or tomorrow's if it has passed. SystemExit naming
    the option on anything else."""
    try:
        hh, mm = (int(x) for x in text.split(":"))
        at = datetime.now().replace(hour=hh, minute=mm, second=0, microsecond=0)
    except ValueError:
        raise SystemExit(f"--until takes a time as HH:MM (00:00-23:59), got {text!r}") from None
    return at if at > datetime.now() else at + timedelta(days=1)
