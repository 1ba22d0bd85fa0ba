"""A paused training run carried from one machine to the next through git.

A protocol run of an off-policy algorithm takes longer than a working session on a slow machine
(TQC and CrossQ: 155-175 min of a core on an Intel Xeon), and the next session may start on a
fresh machine where only commits survive. ``train.py --until HH:MM`` pauses a run at its newest
resume point; :func:`pack` puts what ``--resume`` needs into one compressed archive that can be
committed (the carry), and :func:`unpack` restores it into the run's work directory on the next
machine, where the run continues. Once the run is finished and collected the carry is deleted.

What a carry holds (the run's work directory, relative paths): ``config.json`` (the pause: steps
done, training wall time so far), ``start_bank.json`` (the bank whose draws the run continues),
``eval/`` (the validation history, the selected checkpoint so far and the early row's copy) and
the newest checkpoint's model, VecNormalize statistics and replay buffer. The replay buffer is
most of it: SB3 pickles the whole buffer, whose unused part and ``next_observations`` (the
observations one step later) compress to almost nothing with xz, leaving some MB per 100k
transitions.

A resumed run continues the same trajectory of parameters, optimiser state, replay buffer and
start-bank draws from its checkpoint; it is not bit-identical to an uninterrupted run (the random
generators of the environments and of torch are not checkpointed by SB3), as with any
``--resume``.
"""

from __future__ import annotations

import json
import os
import shutil
import tarfile
from pathlib import Path

__all__ = ["pack", "unpack", "carry_steps", "describe", "CarryError", "CarryNotNewer"]

CHECKPOINT_FILES = ("model_{n}_steps.zip", "model_vecnormalize_{n}_steps.pkl", "model_replay_buffer_{n}_steps.pkl")
XZ_PRESET = 9


class CarryError(ValueError):
    """A carry that cannot be made or used: the message says why and what to do."""


class CarryNotNewer(CarryError):
    """The work directory already holds a checkpoint at least as far as the carry's: resume from it."""


def _newest_checkpoint(work: Path) -> int | None:
    """The steps of the newest model checkpoint in ``work/checkpoints`` (None: there is none)."""
    from agents.training.callbacks import checkpoint_steps   # SB3's file names; SB3 only when used
    return max((checkpoint_steps(f) for f in (work / "checkpoints").glob("model_*_steps.zip")), default=None)


def pack(work: Path, dst: Path) -> Path:
    """Archive the paused run in ``work`` into ``dst`` (``.tar.xz``, written atomically): its
    config.json (which must record a pause at the newest checkpoint), start_bank.json, eval/ and
    the newest checkpoint's files. Returns ``dst``."""
    work, dst = Path(work), Path(dst)
    cfg_path = work / "config.json"
    if not cfg_path.exists():
        raise CarryError(f"{cfg_path}: missing; only a run paused by train.py --until can be carried")
    cfg = json.loads(cfg_path.read_text())
    steps = _newest_checkpoint(work)
    if steps is None:
        raise CarryError(f"{work}/checkpoints holds no checkpoint: nothing to carry")
    if not cfg.get("paused") or cfg.get("num_timesteps") != steps:
        raise CarryError(f"{work}: config.json does not record a pause at the newest checkpoint ({steps:,} steps); "
                         "only a run paused by train.py --until can be carried")
    names = ["config.json", "start_bank.json"]
    names += sorted(str(f.relative_to(work)) for f in (work / "eval").rglob("*") if f.is_file())
    names += [f"checkpoints/{pattern.format(n=steps)}" for pattern in CHECKPOINT_FILES
              if (work / "checkpoints" / pattern.format(n=steps)).exists()]
    missing = [n for n in ("start_bank.json", f"checkpoints/model_{steps}_steps.zip",
                           f"checkpoints/model_vecnormalize_{steps}_steps.pkl") if not (work / n).exists()]
    if missing:
        raise CarryError(f"{work}: {', '.join(missing)} missing; the run cannot be resumed from it")
    carried = carry_steps(dst) if dst.exists() else None
    if carried is not None and carried > steps:
        raise CarryError(f"{dst} holds this run paused at {carried:,} steps, further than the {steps:,} of "
                         f"{work}: it is not replaced (continue the run from the carry)")
    dst.parent.mkdir(parents=True, exist_ok=True)
    tmp = dst.with_name(dst.name + ".tmp")
    with tarfile.open(tmp, "w:xz", preset=XZ_PRESET) as tar:
        for name in names:
            tar.add(work / name, arcname=name, recursive=False)
    os.replace(tmp, dst)
    return dst


def _members(tar: tarfile.TarFile) -> list[tarfile.TarInfo]:
    members = tar.getmembers()
    for m in members:
        parts = Path(m.name).parts
        if not m.isfile() or m.name.startswith("/") or ".." in parts:
            raise CarryError(f"{tar.name}: member {m.name!r} is not a plain relative file: not a carry of this tool")
    return members


def _read_json(tar: tarfile.TarFile, name: str) -> dict:
    try:
        return json.load(tar.extractfile(name))
    except KeyError:
        raise CarryError(f"{tar.name}: no {name} in it: not a carry of this tool") from None


def _open(src: Path) -> tarfile.TarFile:
    try:
        return tarfile.open(src, "r:xz")
    except (OSError, tarfile.TarError, EOFError) as err:   # missing, truncated, not xz
        raise CarryError(f"{src}: cannot be read as a carry ({err})") from None


def carry_steps(src: Path) -> int:
    """The env steps at which the carried run was paused (its config.json)."""
    with _open(src) as tar:
        _members(tar)
        return int(_read_json(tar, "config.json")["num_timesteps"])


def unpack(src: Path, work: Path, bank_path: Path | None = None) -> int:
    """Restore the carry ``src`` into the work directory ``work``, ready for ``train.py --resume``:
    CarryNotNewer if ``work`` already holds a checkpoint at least as far. The carry's files replace
    the run's state in ``work`` (its checkpoints/ and eval/ of another trajectory are removed), all at
    once: they are extracted beside it first. ``start_bank.json`` names the bank by absolute path;
    on another machine or checkout it is pointed at ``bank_path`` (this checkout's bank) when that
    bank has the recorded kernel hash and size (CarryError otherwise: the run would train on other
    starts). Returns the steps of the restored checkpoint."""
    src, work = Path(src), Path(work)
    steps = carry_steps(src)
    here = _newest_checkpoint(work)
    if here is not None and here >= steps:
        raise CarryNotNewer(f"{work} already holds a checkpoint at {here:,} steps, not older than the carry's "
                            f"{steps:,}: resume from it instead")
    staging = work.with_name(work.name + ".unpacking")
    shutil.rmtree(staging, ignore_errors=True)
    try:
        with _open(src) as tar:
            members = _members(tar)
            record = _read_json(tar, "start_bank.json")
            if record.get("path") and bank_path is not None and record["path"] != str(Path(bank_path).resolve()):
                from bearing_gym.envs import start_bank as banks
                bank = banks.load(bank_path)
                if bank.kernel_hash != record["kernel_hash"] or len(bank) != record["starts"]:
                    raise CarryError(f"{src}: the run trained on a start bank of {record['starts']} starts made by "
                                     f"kernel {record['kernel_hash']}; {bank_path} holds {len(bank)} by {bank.kernel_hash}")
                record["path"] = str(Path(bank_path).resolve())
            for m in members:
                target = staging / m.name
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(tar.extractfile(m).read())
        (staging / "start_bank.json").write_text(json.dumps(record, indent=2))
    except (OSError, tarfile.TarError, EOFError) as err:
        shutil.rmtree(staging, ignore_errors=True)
        raise CarryError(f"{src}: cannot be unpacked ({err})") from None
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    work.mkdir(parents=True, exist_ok=True)
    for old in ("checkpoints", "eval"):
        shutil.rmtree(work / old, ignore_errors=True)
    for entry in staging.iterdir():
        target = work / entry.name
        if target.is_dir():
            shutil.rmtree(target)
        os.replace(entry, target)
    staging.rmdir()
    return steps


def describe(src: Path) -> str:
    """One line: the carry's steps, training time so far and size."""
    with _open(src) as tar:
        _members(tar)
        cfg = _read_json(tar, "config.json")
    return (f"{src.name}: paused at {cfg['num_timesteps']:,} of {cfg['timesteps']:,} steps after "
            f"{cfg['train_wall_s'] / 60:.1f} min of training, {src.stat().st_size / 1e6:.1f} MB")
