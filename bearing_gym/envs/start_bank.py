"""Start banks: settled starts computed once, so that a reset costs a copy, not a settle.

A reset settles the rotor at the episode's initial operating point (1.46 s of simulated warm-up,
:meth:`bearing_gym.envs.core.PreloadBatch.settle`): 25-90 env steps' worth of simulation, a third
of all the simulated time of training. A **start bank** holds, for a fixed list of scenarios (one
per seed, drawn by a tier's own distribution), the state each settle ends in, and

* :meth:`StartBank.install` makes those states known to every env of the process: a reset whose
  initial operating point is in the bank copies its state instead of simulating - **the same
  bits**, as the states are what the settle computed (``tests/envs/test_start_bank.py``);
* :class:`BankScenarios` is a scenario part that draws the bank's scenarios, each once before any
  repeats (a permutation from the env's generator): an env built with it trains on the bank.

A bank is only valid for the kernel that computed it: it carries the kernel's fingerprint
(:func:`bearing_gym.envs.provenance.kernel_hash`) and the env settings that the settle depends on,
and :func:`load` refuses a bank made by another kernel, naming the command that rebuilds it;
:func:`check_fits` refuses one made for another tier, horizon or env settings.

**From gymnasium.make.** The package ships a bank per tier where one is worth it
(:func:`shipped_path`: ``transient``, training seeds 0-2047); any env takes one::

    env = gymnasium.make("BearingPreload-v0", start_bank="shipped")       # or a path, or a StartBank
    venv = BearingPreloadVectorEnv(num_envs=8, start_bank="shipped")

Its episodes then draw the bank's scenarios (uniformly, from the env's generator, so
``reset(seed=s)`` is reproducible) and every reset is a copy. It is off by default: a bank is a
finite set of *training* scenarios, so an env built with it cannot draw the validation or test
scenarios of a seed, nor pin a scenario through ``reset(options=...)``; train.py uses the
shipped bank by default (``--start-bank``), in its own order (each start once before any repeats).

    python -m bearing_gym.envs.start_bank --tier transient --seeds 0 2048 --out bank.npz
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .core import install_settled
from .scenario import Scenario

__all__ = ["StartBank", "build", "load", "BankScenarios", "shipped_path", "check_fits", "resolve", "env_scenario",
           "install_for", "main", "SHIPPED_DIR"]

_FORMAT = 1
#: where the package's own banks live (``start_bank_<tier>.npz``; ``python -m agents.regenerate``
#: rebuilds them with every change of the kernel)
SHIPPED_DIR = Path(__file__).resolve().parents[1] / "data"


def shipped_path(tier: str) -> Path:
    """The package's start bank of ``tier`` (it may not exist: not every tier ships one)."""
    return SHIPPED_DIR / f"start_bank_{tier}.npz"


@dataclass(frozen=True, eq=False)
class StartBank:
    """Settled starts of ``scenarios`` (the scenario of each seed of ``seeds`` on ``tier``):
    ``digests[i]`` is the settle key of scenario i, ``states[digest]`` its settled state (the
    :attr:`~bearing_gym.envs.core.PreloadBatch.STATE` arrays of one env)."""

    tier: str
    seeds: tuple[int, ...]
    scenarios: tuple[Scenario, ...]
    digests: tuple[str, ...]
    states: dict[str, tuple[np.ndarray, ...]] = dataclasses.field(repr=False)
    kernel_hash: str = ""
    env_kwargs: dict[str, Any] = dataclasses.field(default_factory=dict)
    #: the file it was loaded from (None: built in this process)
    path: Path | None = None

    def __len__(self) -> int:
        return len(self.scenarios)

    def install(self) -> "StartBank":
        """Make the bank's settled starts known to every env of this process (returns self)."""
        install_settled(self.states)
        return self

    def save(self, path: str | Path) -> Path:
        """Write the bank as a compressed .npz (one array per state field, stacked)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        first = self.states[self.digests[0]]
        arrays = {f"state_{k}": np.stack([self.states[d][k] for d in self.digests]) for k in range(len(first))}
        meta = {"format": _FORMAT, "tier": self.tier, "seeds": list(self.seeds), "digests": list(self.digests),
                "kernel_hash": self.kernel_hash, "env_kwargs": self.env_kwargs,
                "scenarios": [_scenario_json(sc) for sc in self.scenarios]}
        tmp = path.with_name(path.name + ".tmp.npz")
        np.savez_compressed(tmp, meta=np.array(json.dumps(meta)), **arrays)
        tmp.replace(path)
        return path


def _scenario_json(sc: Scenario) -> dict[str, Any]:
    d = dataclasses.asdict(sc)
    d.pop("entry_point", None)
    return d


def _scenario_from_json(d: Mapping[str, Any]) -> Scenario:
    return Scenario(**{k: (tuple(tuple(r) for r in v) if k.endswith("_profile") else v) for k, v in d.items()})


def rebuild_command(tier: str, seeds: tuple[int, ...], out: str | Path) -> str:
    return (f"python -m bearing_gym.envs.start_bank --tier {tier} --seeds {seeds[0]} {seeds[-1] + 1} "
            f"--out {out}")


def build(tier: str, seeds, batch_envs: int = 32, progress: bool = False, **env_kwargs: Any) -> StartBank:
    """Settle the scenario of every seed of ``seeds`` on ``tier`` (``batch_envs`` at a time: the
    settles of a batch run together on the numba threads) and keep the states."""
    from gymnasium.utils import seeding

    from .composition import DEFAULTS, PreloadTask
    from .provenance import kernel_hash
    seeds = tuple(int(s) for s in seeds)
    if not seeds:
        raise ValueError("seeds must name at least one seed")
    try:
        json.dumps(env_kwargs)
    except TypeError:
        raise TypeError(f"start bank env_kwargs must be JSON values (the bank records them), got {env_kwargs!r}") from None
    n = max(1, min(int(batch_envs), len(seeds)))
    unknown = sorted(set(env_kwargs) - {"scenario", "actuator", "observation", "reward", "params", "control_dt_s",
                                        "episode_steps"})
    if unknown:
        raise TypeError(f"start bank env_kwargs {unknown} are not env arguments that a settle depends on")
    # the envs' own composition; each env's generator seeded as the envs seed it (reset(seed=s))
    task = PreloadTask.build(tier, env_kwargs.get("scenario"), env_kwargs.get("actuator"),
                             env_kwargs.get("observation"), env_kwargs.get("reward"), env_kwargs.get("params"),
                             env_kwargs.get("control_dt_s", DEFAULTS["control_dt_s"]),
                             env_kwargs.get("episode_steps", DEFAULTS["episode_steps"]), num_envs=n)
    scenarios: list[Scenario] = []
    digests: list[str] = []
    states: dict[str, tuple[np.ndarray, ...]] = {}
    t0 = time.time()
    for k in range(0, len(seeds), n):
        chunk = list(seeds[k:k + n])
        idx = np.arange(len(chunk), dtype=np.int64)
        task.reset(idx, [seeding.np_random(s)[0] for s in chunk], None)
        for b in range(len(chunk)):
            digest, state = task.batch.settled_state(b)
            scenarios.append(task.batch.scenarios[b])
            digests.append(digest)
            states[digest] = state
        if progress:
            done = k + len(chunk)
            el = time.time() - t0
            print(f"start bank {tier}: {done}/{len(seeds)} starts settled, {el / 60:.1f} min, about "
                  f"{el / done * (len(seeds) - done) / 60:.1f} min left", flush=True)
    return StartBank(tier, seeds, tuple(scenarios), tuple(digests), states, kernel_hash(), dict(env_kwargs))


def load(path: str | Path, check_kernel: bool = True) -> StartBank:
    """The bank at ``path``; ValueError if it is not a readable bank, or naming the rebuild
    command if another kernel made it (FileNotFoundError if there is none)."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            fields = sorted((k for k in f.files if k.startswith("state_")), key=lambda k: int(k.split("_")[1]))
            arrays = [f[k] for k in fields]
        seeds = tuple(meta["seeds"])
    except FileNotFoundError:
        raise
    except Exception as err:              # not an .npz, truncated, no metadata
        raise ValueError(f"{path} is not a readable start bank ({type(err).__name__}: {err})") from None
    if meta.get("format") != _FORMAT:
        raise ValueError(f"{path}: start bank format {meta.get('format')}, this code reads {_FORMAT}")
    if check_kernel:
        from .provenance import kernel_hash
        here = kernel_hash()
        if meta["kernel_hash"] != here:
            raise ValueError(f"{path}: the start bank was made by kernel {meta['kernel_hash']}, not this one ({here}): "
                             f"its states would not be this kernel's settles; rebuild it with "
                             f"`{rebuild_command(meta['tier'], seeds, path)}`")
    digests = tuple(meta["digests"])
    states = {d: tuple(a[i].copy() for a in arrays) for i, d in enumerate(digests)}
    return StartBank(meta["tier"], seeds, tuple(_scenario_from_json(d) for d in meta["scenarios"]), digests, states,
                     meta["kernel_hash"], dict(meta["env_kwargs"]), path)


def check_fits(bank: StartBank, tier: str, episode_steps: int, batch) -> StartBank:
    """``bank`` if it fits envs of ``tier`` with ``episode_steps``-step episodes whose physics is
    ``batch`` (a :class:`~bearing_gym.envs.core.PreloadBatch`: the bank's first scenario must
    have the settle key it was stored under, i.e. the same physics, actuator and control
    interval); ValueError saying why not. Loads that scenario into ``batch``'s env 0 (a reset
    loads its own)."""
    where = bank.path if bank.path is not None else "the start bank"
    if bank.tier != tier:
        raise ValueError(f"{where} holds tier {bank.tier!r} starts, this env is of tier {tier!r}")
    bank_steps = bank.env_kwargs.get("episode_steps", _default_episode_steps())
    if bank_steps != episode_steps:
        raise ValueError(f"{where} holds scenarios of {bank_steps}-step episodes, this env's have {episode_steps}")
    batch.load(0, bank.scenarios[0])
    if batch.settle_digest(0) != bank.digests[0]:       # the bank must hold this env's settles
        raise ValueError(f"{where} was built for other env settings (physics, actuator or control interval) than "
                         f"this env's: its starts would never be used; rebuild it: "
                         f"{rebuild_command(bank.tier, bank.seeds, where)}")
    return bank


def _default_episode_steps() -> int:
    from bearing_gym.task import EPISODE_STEPS
    return EPISODE_STEPS


def resolve(start_bank: Any, tier: str) -> StartBank:
    """The bank an env's ``start_bank`` argument names: ``"shipped"`` (the package's bank of
    ``tier``: FileNotFoundError naming the tiers that have one if it has none), a path to a
    ``.npz``, or a :class:`StartBank`. Refused (ValueError) if another kernel made it."""
    if isinstance(start_bank, StartBank):
        from .provenance import kernel_hash
        if start_bank.kernel_hash != kernel_hash():
            raise ValueError(f"the start bank was made by kernel {start_bank.kernel_hash}, not this one "
                             f"({kernel_hash()}): its states would not be this kernel's settles; rebuild it with "
                             f"`{rebuild_command(start_bank.tier, start_bank.seeds, start_bank.path or 'bank.npz')}`")
        return start_bank
    if start_bank == "shipped":
        path = shipped_path(tier)
        if not path.exists():
            have = sorted(p.stem.removeprefix("start_bank_") for p in SHIPPED_DIR.glob("start_bank_*.npz"))
            raise FileNotFoundError(f"start_bank='shipped': no bank ships for tier {tier!r} (tiers with one: "
                                    f"{', '.join(have) or 'none'}); build one with `{rebuild_command(tier, (0, 1023), 'bank.npz')}` "
                                    "and pass its path")
        return load(path)
    if isinstance(start_bank, (str, Path)):
        return load(start_bank)
    raise TypeError(f"start_bank must be 'shipped', the path of a bank (.npz) or a StartBank, got {start_bank!r}")


def env_scenario(start_bank: Any, scenario: Any, tier: str) -> tuple[Any, "StartBank | None"]:
    """What an env's ``start_bank`` argument makes of its ``scenario`` argument: (the scenario part,
    the bank) - the bank's scenarios drawn uniformly, or ``scenario`` unchanged and None without a
    bank. Both given: ValueError. The env then calls :func:`install_for` with its task."""
    if start_bank is None:
        return scenario, None
    if scenario is not None:
        raise ValueError("start_bank draws the bank's scenarios: pass scenario= or start_bank=, not both")
    bank = resolve(start_bank, tier)
    return BankScenarios(bank, draw="uniform"), bank


def install_for(bank: "StartBank | None", task: Any) -> None:
    """Check that ``bank`` fits the env's ``task`` (:class:`~bearing_gym.envs.composition.PreloadTask`:
    tier, horizon, physics; :func:`check_fits`) and install it; nothing without a bank."""
    if bank is not None:
        check_fits(bank, task.tier, task.episode_steps, task.batch).install()


@dataclass
class BankScenarios:
    """A scenario part that draws the scenarios of a start bank: each once, in an order drawn from
    the env's generator at the first draw, before any repeats (then a new order). With the bank
    installed, every reset is a copy. Pinning options are refused (the bank's scenarios are fixed).

    The order is the part's, shared by the envs of a vector env in the order they reset; seeding
    an env again does not restart it (a finite training set, each start once per pass - not one
    episode per seed). The first order depends only on the generator's seed, so a training run
    resumed in a new process with the same seed passes ``skip`` = the draws its earlier sessions
    made and continues where they stopped (``train.py --resume``); orders after the first are drawn
    from the generator as it stands then."""

    bank: StartBank = dataclasses.field(repr=False, compare=False)
    #: draws of the first order to pass over (made by an earlier session of the same run)
    skip: int = 0
    #: ``"permutation"`` (above; train.py) or ``"uniform"``: each draw an independent uniform
    #: pick by the env's generator, so ``reset(seed=s)`` gives the same scenario every time
    #: (what Gymnasium's env checks ask; an env's ``start_bank`` argument uses it)
    draw: str = "permutation"

    def __post_init__(self) -> None:
        if not len(self.bank):
            raise ValueError("BankScenarios needs a start bank with at least one scenario")
        if self.draw not in ("permutation", "uniform"):
            raise ValueError(f"BankScenarios draw must be 'permutation' or 'uniform', got {self.draw!r}")
        if int(self.skip) != self.skip or self.skip < 0:
            raise ValueError(f"BankScenarios skip must be a whole number >= 0 of draws, got {self.skip!r}")
        self._order: np.ndarray | None = None
        self._next = 0

    def sample(self, rng: np.random.Generator, episode_s: float, pinned: Mapping[str, Any] | None = None) -> Scenario:
        if pinned:
            raise ValueError(f"a start bank's scenarios are fixed: reset options {sorted(pinned)} cannot pin them "
                             "(pass options={'scenario': Scenario(...)} for one of your own)")
        if self.draw == "uniform":
            return self.bank.scenarios[int(rng.integers(len(self.bank)))]
        if self._order is None:
            self._order, self._next = rng.permutation(len(self.bank)), int(self.skip)
        while self._next >= len(self._order):
            self._order, self._next = rng.permutation(len(self.bank)), self._next - len(self._order)
        i = int(self._order[self._next])
        self._next += 1
        return self.bank.scenarios[i]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m bearing_gym.envs.start_bank", description=__doc__.split("\n\n")[0])
    ap.add_argument("--tier", required=True)
    ap.add_argument("--seeds", nargs=2, type=int, metavar=("FIRST", "STOP"), required=True,
                    help="the seeds FIRST..STOP-1, one scenario each")
    ap.add_argument("--out", required=True, help="the .npz to write")
    ap.add_argument("--batch-envs", type=int, default=32)
    a = ap.parse_args(argv)
    if not a.seeds[1] > a.seeds[0]:
        ap.error(f"--seeds FIRST STOP needs STOP > FIRST, got {a.seeds}")
    bank = build(a.tier, range(*a.seeds), a.batch_envs, progress=True)
    print(f"wrote {bank.save(a.out)} ({len(bank)} settled starts, kernel {bank.kernel_hash})")


if __name__ == "__main__":
    main()
