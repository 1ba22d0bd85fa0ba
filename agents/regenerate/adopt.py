"""Adopting files in place: recording a product as built under today's inputs without building it,
when the files' own records prove they hold what a build would write.

A definition change (a product's settings gain a key, an upstream product is redefined) makes a
product stale even where its files could not come out different. Rebuilding the planner's
references costs hours of cores; :func:`adopt` instead runs the product's ``verify`` (a check of
the files against today's inputs: the kernel fingerprint, the settings and the upstream values
each file records) and, when it finds nothing, records the product fresh, its build marked
``adopted``. A product without a ``verify`` cannot be adopted, nor one whose upstream products
are not fresh (adopt or build them first: upstream first), nor one that is stale for what a
check of records cannot see: files changed since they were built (by hand), or a ``--force``.
The check trusts what the files record about how they were made; their content is checked where
they are used (the references' merge replays every plan against its stored return).

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
        entry = manifest.entry(n)
        if inputs.get("forced") and not (entry and entry.get("complete")
                                         and entry.get("inputs", {}).get("forced") == inputs["forced"]):
            raise AdoptError(f"{n} is forced (--force: a change the hashes do not see): build it")
        if entry is not None and entry.get("input_hash") == digest_in:
            raise AdoptError(f"{n}: its inputs are today's; it is not fresh because its files changed since it was "
                             f"built (by hand?) or its build is partial: build it (`python -m agents.regenerate --only '{n}'`)")
        if entry is not None and entry.get("complete") and entry.get("output_digest") not in (
                None, p.output_digest(layout.root)):
            raise AdoptError(f"{n}: its files changed since its last build (by hand?): build it")
        if p.verify is None:
            raise AdoptError(f"{n} has no check of its files against today's inputs: build it "
                             f"(`python -m agents.regenerate --only '{n}'`)")
        not_fresh = [u for u in p.upstream
                     if assess(sel.products[u], *sel.inputs[u], manifest.entry(u), layout).state != FRESH]
        if not_fresh:
            raise AdoptError(f"{n}: its upstream {', '.join(not_fresh)} is not fresh; adopt or build it first")
        try:
            problems = p.verify()
        except Exception as err:  # noqa: BLE001 - a check that cannot run finds its files unproven
            problems = [f"its check failed: {type(err).__name__}: {err}"]
        if problems:
            raise AdoptError(f"{n}: its files are not what today's inputs build: " + "; ".join(problems[:3])
                             + (f" (and {len(problems) - 3} more)" if len(problems) > 3 else ""))
        manifest.complete(n, inputs, digest_in, p.output_digest(layout.root),
                          "adopted " + datetime.now().isoformat(timespec="seconds"), float((entry or {}).get("wall_s") or 0.0))
        log(f"{n}: adopted (was {state.state}: {'; '.join(state.reasons)})")
        done.append(n)
    return done
