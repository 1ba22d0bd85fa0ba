"""``python -m bearing_gym``: the ``bearing-gym`` command line (:mod:`bearing_gym.cli`), e.g.
``python -m bearing_gym simulate`` (the paper's spindle at 20,000 rpm and 800 N, a summary and
figures)."""

from bearing_gym.cli import main

if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
