"""Adopting files in place: recording a product as built under today's inputs without building it,
when the files' own records prove they hold what a build would write.

A definition change (a product's settings gain a key, an upstream product is redefined) makes a
product stale even where its files could not come out different. Rebuilding the planner's
references costs hours of cores; :func:`adopt` instead runs the product's ``verify`` (a check of
the files against today's inputs: the kernel fingerprint, the settings and the upstream values
each file records) and, when it finds nothing, records the product fresh, its build marked
``adopted``. A product without a ``verify`` cannot be adopted, nor one whose upstream products
are not fresh (adopt or build them first: upstream first).

    python -m agents.regenerate --adopt 'validation:*' 'planner:*'
"""

from __future__ import annotations

from datetime import datetime
from typing import Callable

from agents.regenerate.manifest import FRESH, Manifest, assess
from agents.regenerate.product import Layout
from agents.regenerate.scheduler import Selection

__all__ = ["AdoptError", "adopt"]


class AdoptError(ValueError):
    """A product that cannot be adopted, and why."""


def adopt(sel: Selection, names: list[str], layout: Layout, manifest: Manifest,
          log: Callable[[str], None] = print) -> list[str]:
    """Adopt ``names`` (in the catalogue's upstream-first order); returns those recorded fresh
    (a product already fresh is left as it is). Raises :class:`AdoptError` at the first that
    cannot be, naming what differs; those adopted before it stay recorded."""
    done = []
    for n in [n for n in sel.products if n in set(names)]:
        p = sel.products[n]
        inputs, digest_in = sel.inputs[n]
        state = assess(p, inputs, digest_in, manifest.entry(n), layout)
        if state.state == FRESH:
            log(f"{n}: fresh already")
            continue
        if p.verify is None:
            raise AdoptError(f"{n} has no check of its files against today's inputs: build it "
                             f"(`python -m agents.regenerate --only '{n}'`)")
        not_fresh = [u for u in p.upstream
                     if assess(sel.products[u], *sel.inputs[u], manifest.entry(u), layout).state != FRESH]
        if not_fresh:
            raise AdoptError(f"{n}: its upstream {', '.join(not_fresh)} is not fresh; adopt or build it first")
        problems = p.verify()
        if problems:
            raise AdoptError(f"{n}: its files are not what today's inputs build: " + "; ".join(problems[:3])
                             + (f" (and {len(problems) - 3} more)" if len(problems) > 3 else ""))
        old = manifest.entry(n) or {}
        manifest.complete(n, inputs, digest_in, p.output_digest(layout.root),
                          "adopted " + datetime.now().isoformat(timespec="seconds"), float(old.get("wall_s") or 0.0))
        log(f"{n}: adopted (was {state.state}: {'; '.join(state.reasons)})")
        done.append(n)
    return done
