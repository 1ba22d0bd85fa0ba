"""The regeneration's manifest and what is fresh.

``agents/data/regeneration.json`` (committed) records, per product, the inputs it was built from
(the kernel's fingerprint, its settings, the digests of the files it reads that no product writes,
and the input hash of each upstream product), their hash, the parts done and, once complete,
the digest of its files. A product is

* **fresh** when its recorded input hash is the hash of today's inputs and its files are the
  ones it wrote;
* **stale** when an input changed (the reasons say which: the kernel, a setting, an upstream
  product, a source), when its files changed since it was built, or when the manifest has no
  record of it (its files were made by hand or by an earlier definition);
* **partial** when it is being built under today's inputs and some parts are done (they are kept);
* **missing** when a file is missing.

An input hash folds in the upstream products' input hashes (not their files' digests), so a
change reaches every product downstream of it, and only those; a product rebuilt under the same
inputs (its files deleted, or changed by hand) leaves its dependants fresh: the builders are
deterministic, so they were made from what it holds again.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from agents.paths import PACKAGE_DIR
from agents.regenerate.product import Layout, Product, as_json, missing_files, tree_digest

__all__ = ["Manifest", "State", "current_inputs", "input_hash", "assess", "FRESH", "STALE", "PARTIAL", "MISSING"]

FRESH, STALE, PARTIAL, MISSING = "fresh", "stale", "partial", "missing"
ABOUT = ("What `python -m agents.regenerate` built, from what: per product the inputs (kernel fingerprint, settings, "
         "sources, upstream products' input hashes), their hash, the parts done and the digest of its files. "
         "`python -m agents.regenerate --status` compares them with today's.")


def input_hash(inputs: dict[str, Any]) -> str:
    return hashlib.sha256(json.dumps(inputs, sort_keys=True).encode()).hexdigest()[:16]


def source_name(path: Path) -> str:
    """A source's name in the manifest: its path in the checkout (``agents/trained/sac/seed_0``)."""
    try:
        return Path(path).resolve().relative_to(PACKAGE_DIR.parent).as_posix()
    except ValueError:
        return Path(path).as_posix()


def current_inputs(products: list[Product], kernel: str, layout: Layout,
                   forced: dict[str, str | None] | None = None) -> dict[str, tuple[dict, str]]:
    """Per product (in the given, upstream-first order): (today's inputs, their hash). ``forced``:
    per product the time of its last ``--force`` (an input of its own, so its dependants follow)."""
    out: dict[str, tuple[dict, str]] = {}
    for p in products:
        missing_up = [u for u in p.upstream if u not in out]
        if missing_up:
            raise ValueError(f"product {p.name}: upstream {missing_up[0]} is not listed before it")
        inputs = {"kernel": kernel if p.kernel else None, "settings": as_json(dict(p.settings)),
                  "sources": {source_name(s): tree_digest((s,), s.parent) for s in p.sources},
                  "upstream": {u: out[u][1] for u in p.upstream}}
        if (forced or {}).get(p.name):
            inputs["forced"] = forced[p.name]
        out[p.name] = (inputs, input_hash(inputs))
    return out


@dataclass
class State:
    """A product's state, why, and which of its parts are done under today's inputs."""

    name: str
    state: str
    reasons: list[str] = field(default_factory=list)
    parts_done: set[str] = field(default_factory=set)


def _flat(d: Any, prefix: str = "") -> dict[str, Any]:
    if not isinstance(d, dict):
        return {prefix: d}
    out: dict[str, Any] = {}
    for k, v in d.items():
        out.update(_flat(v, f"{prefix}.{k}" if prefix else str(k)))
    return out


def _short(v: Any, n: int = 40) -> str:
    s = json.dumps(v)
    return s if len(s) <= n else s[:n - 3] + "..."


def why_changed(old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    """What differs between recorded inputs ``old`` and today's ``new``, in words."""
    out = []
    if old.get("forced") != new.get("forced"):
        out.append(f"forced (--force, {new.get('forced')})" if new.get("forced") else "forced before")
    if old.get("kernel") != new.get("kernel"):
        out.append(f"kernel {old.get('kernel')} -> {new.get('kernel')}")
    fo, fn = _flat(old.get("settings", {})), _flat(new.get("settings", {}))
    changed = [k for k in sorted(set(fo) | set(fn)) if fo.get(k) != fn.get(k)]
    out += [f"setting {k}: {_short(fo.get(k))} -> {_short(fn.get(k))}" for k in changed[:3]]
    if len(changed) > 3:
        out.append(f"{len(changed) - 3} more settings changed")
    for what in ("sources", "upstream"):
        so, sn = old.get(what, {}), new.get(what, {})
        for k in sorted(set(so) | set(sn)):
            if so.get(k) != sn.get(k):
                out.append(f"{'upstream ' if what == 'upstream' else ''}{k} "
                           + ("added" if k not in so else "removed" if k not in sn else "changed"))
    return out or ["its inputs' hash changed"]


def assess(product: Product, inputs: dict, digest_in: str, entry: dict | None, layout: Layout) -> State:
    """The state of ``product`` given today's inputs and its manifest ``entry`` (module docstring)."""
    gone = [layout.rel(f) for f in missing_files(product.outputs)]
    if product.digest is not None and not gone and product.output_digest(layout.root) is None:
        gone = [f"its entry in {layout.rel(product.outputs[0])}"]
    missing = [f"missing: {', '.join(gone[:3])}" + (f" and {len(gone) - 3} more" if len(gone) > 3 else "")] if gone else []
    if entry is None:
        return State(product.name, MISSING if gone else STALE,
                     ["not in the manifest (made by hand or before this command)"] + missing)
    if entry.get("input_hash") != digest_in:
        return State(product.name, MISSING if gone else STALE, why_changed(entry.get("inputs", {}), inputs) + missing)
    if not entry.get("complete"):
        done = set(entry.get("parts_done", [])) & {p.key for p in product.parts}
        return State(product.name, PARTIAL, [f"{len(done)} of {len(product.parts)} parts built under today's inputs"],
                     done)
    if gone:
        return State(product.name, MISSING, missing)
    if product.output_digest(layout.root) != entry.get("output_digest"):
        return State(product.name, STALE, ["its files changed since it was built (by hand?)"])
    return State(product.name, FRESH)


class Manifest:
    """The manifest file (module docstring): read once, written after every part."""

    def __init__(self, path: Path, profile: str):
        self.path = Path(path)
        self.profile = profile
        data: dict[str, Any] = {}
        if self.path.exists():
            data = json.loads(self.path.read_text())
            if data.get("profile") not in (None, profile):
                raise ValueError(f"{self.path} records the {data.get('profile')!r} profile, this run is {profile!r}: "
                                 "give another --root")
        self.products: dict[str, dict[str, Any]] = data.get("products", {})

    def entry(self, name: str) -> dict[str, Any] | None:
        return self.products.get(name)

    def start(self, name: str, inputs: dict, digest_in: str) -> None:
        """Record that ``name`` is being built under ``digest_in`` with no part done yet (a
        forced product: so that its force outlives a run stopped before any part ends)."""
        e = self.products.get(name)
        if e is None or e.get("input_hash") != digest_in or e.get("complete"):
            self.products[name] = {"input_hash": digest_in, "inputs": inputs, "complete": False, "parts_done": []}
            self.save()

    def part_done(self, name: str, inputs: dict, digest_in: str, key: str) -> None:
        """Record part ``key`` of ``name`` done under ``digest_in`` (starting a new record if the
        product's record was made under other inputs)."""
        e = self.products.get(name)
        if e is None or e.get("input_hash") != digest_in or e.get("complete"):
            e = self.products[name] = {"input_hash": digest_in, "inputs": inputs, "complete": False, "parts_done": []}
        if key not in e["parts_done"]:
            e["parts_done"].append(key)
        self.save()

    def complete(self, name: str, inputs: dict, digest_in: str, output_digest: str | None, built: str,
                 wall_s: float) -> None:
        self.products[name] = {"input_hash": digest_in, "inputs": inputs, "complete": True,
                               "output_digest": output_digest, "built": built, "wall_s": round(wall_s, 1)}
        self.save()

    def save(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(self.path.name + ".tmp")
        tmp.write_text(json.dumps({"about": ABOUT, "profile": self.profile,
                                   "products": dict(sorted(self.products.items()))}, indent=1) + "\n")
        os.replace(tmp, self.path)
