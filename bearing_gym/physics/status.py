"""Status codes of the integrator (:func:`.rotor.integrate`) and their messages, in one table.

The ball solver's codes (:mod:`.ball`: ``BALL_OK``, ``BALL_NOT_CONVERGED``, ``BALL_SINGULAR``)
pass through unchanged as 0, 1 and 2; the integrator adds 3 and 4.
"""

from __future__ import annotations

__all__ = ["ST_OK", "ST_BALL_NOT_CONVERGED", "ST_BALL_SINGULAR", "ST_NEWMARK_NOT_CONVERGED",
           "ST_DIVERGED", "STATUS_TEXT", "status_text"]

ST_OK = 0
ST_BALL_NOT_CONVERGED = 1
ST_BALL_SINGULAR = 2
ST_NEWMARK_NOT_CONVERGED = 3
ST_DIVERGED = 4

STATUS_TEXT: dict[int, str] = {
    ST_OK: "ok",
    ST_BALL_NOT_CONVERGED: "ball equilibrium (eq 31) did not converge",
    ST_BALL_SINGULAR: "ball equilibrium Jacobian singular",
    ST_NEWMARK_NOT_CONVERGED: "Newmark equilibrium iterations did not converge",
    ST_DIVERGED: "diverged: displacement beyond integrator.divergence_limit_m or not finite",
}


def status_text(code: int) -> str:
    """The message of an integrator status code (ValueError for an unknown code)."""
    try:
        return STATUS_TEXT[int(code)]
    except KeyError:
        raise ValueError(f"unknown integrator status code {code!r}; known: "
                         f"{sorted(STATUS_TEXT)}") from None
