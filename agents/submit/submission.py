"""The submission file: a scored policy's per-episode results and what it was, as JSON, and adding
it to a board as a row marked submitted.

    python -m agents.submit add my_method.json                 # into docs/results.json (a checkout)
    python -m agents.submit add my_method.json --board runs/leaderboard_pretrained/results.json
    python -m agents.submit check my_method.json               # would it be accepted, and if not why

A file holds (``FORMAT`` ``"bearing-gym-submission"``, ``FORMAT_VERSION``): the benchmark, the
protocol version (:data:`agents.protocol.PROTOCOL_VERSION`), the kernel fingerprint that ran it,
the tier, the variant, the test seeds and horizon; the submitter's algorithm, training budget
(env steps), training seeds, library and version, a link to the code, notes, whether it used
privileged information; and per training
seed (``runs``) every test episode's return, reward terms, time quasi-periodic, mean preload,
termination, vibration amplitude and cost. The row is recomputed from those when the file joins
a board (:func:`agents.submit.api.submitted_row`, the function that made it), with the board's
statistics, so a file cannot carry scores of its own.

A board keeps the submissions added to it in ``submissions/`` beside its results.json
(:func:`stored_path`) and adds them again whenever it is rebuilt (:func:`readd_stored`: the
regeneration's board, ``python -m agents.leaderboard``), so a rebuilt board keeps its submitted
rows - those the new board still takes (a new kernel refuses them all: score them again).

A board refuses (:class:`SubmissionRefused`, saying which) a file made on other test seeds or
another horizon, under another protocol version, by another kernel (or a board made by another
kernel than this one), for another tier than the board has, of the constrained variant (boards
rank the benchmark's reward; a constrained row is reported by itself), that used privileged
information (docs/benchmark.md: main rows read the observation only), or whose name a row of
the board already has (``--replace`` replaces a submitted row).
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.envs.provenance import kernel_hash, package_version
from bearing_gym.envs.reward import REWARD_TERMS

from agents import protocol as P
from agents.evaluation.result import EvalResult
from agents.paths import DATA_DIR
from agents.references.store import result_from_json, result_to_json
from agents.submit.rows import CONTEXTUAL, submitted_row, test_references

__all__ = ["FORMAT", "FORMAT_VERSION", "SubmissionRefused", "make_submission", "write_submission",
           "load_submission", "check_schema", "check_submission", "add_submission", "runs_of", "row_name",
           "store_dir", "stored_path", "readd_stored", "reporting_gaps", "MIN_TRAINING_SEEDS",
           "STEP_BUDGET"]

FORMAT = "bearing-gym-submission"
#: training seeds the rules ask a submission to report (docs/benchmark.md; the protocol's own
#: non-headline algorithms run this many)
MIN_TRAINING_SEEDS = P.OTHER_SEEDS if P.PROTOCOL_VERSION < 2 else P.V2_SEEDS
#: the protocol's env steps per training run (a submission beyond it is noted beside its row)
STEP_BUDGET = P.STEP_BUDGET_PER_RUN if P.PROTOCOL_VERSION < 2 else P.V2_STEP_BUDGET_PER_RUN
FORMAT_VERSION = 1
SUFFIX = " (submitted)"


class SubmissionRefused(ValueError):
    """A submission file that a board does not take; the message says why and what to do."""


def make_submission(scored: Any, algorithm: str, training_steps: int | None = None,
                    training_seeds: list[int] | None = None, library: str = "", library_version: str = "",
                    code: str = "", notes: str = "", privileged: bool = False) -> dict[str, Any]:
    """The submission of a :class:`agents.submit.api.Scored` (module docstring). ``privileged``:
    the policy or its training used information beyond the observation (docs/benchmark.md)."""
    if not isinstance(algorithm, str) or not algorithm.strip():
        raise ValueError("algorithm must name the method (e.g. 'SAC', 'DreamerV3', 'a PI rule')")
    if training_steps is not None and (isinstance(training_steps, bool) or not isinstance(training_steps, int)
                                       or training_steps < 0):
        raise ValueError(f"training_steps must be the env steps of training (an integer >= 0), got {training_steps!r}")
    seeds = None if training_seeds is None else [int(s) for s in training_seeds]
    if seeds is not None and len(seeds) != len(scored.results):
        raise ValueError(f"{len(seeds)} training seeds for {len(scored.results)} scored run(s): one per run")
    runs = []
    for k, r in enumerate(scored.results):
        run = result_to_json(r)
        run["cost"] = None if r.cost is None else [float(c) for c in r.cost]
        run["training_seed"] = None if seeds is None else seeds[k]
        runs.append(run)
    return {"format": FORMAT, "format_version": FORMAT_VERSION, "benchmark": "BearingPreload-v0",
            "protocol_version": scored.protocol_version, "kernel_hash": scored.kernel_hash,
            "package_version": package_version(), "tier": scored.tier, "variant": scored.variant,
            "test_seeds": [scored.seeds[0], scored.seeds[-1]], "episodes": len(scored.seeds),
            "episode_steps": scored.references.episode_steps,
            "name": scored.name, "algorithm": algorithm.strip(), "training_steps": training_steps,
            "training_seeds": seeds, "library": library, "library_version": library_version, "code": code,
            "notes": notes, "privileged": bool(privileged), "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "runs": runs, "row_as_scored": {k: v for k, v in scored.row.items() if k != "episode_returns"}}


def write_submission(submission: dict[str, Any], path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(submission, indent=1) + "\n")
    return path


def load_submission(path: str | Path) -> dict[str, Any]:
    """The submission at ``path``; SubmissionRefused if it is not one."""
    try:
        sub = json.loads(Path(path).read_text())
    except (OSError, ValueError) as err:
        raise SubmissionRefused(f"{path}: not a readable submission file ({type(err).__name__}: {err})") from None
    if not isinstance(sub, dict) or sub.get("format") != FORMAT:
        raise SubmissionRefused(f"{path}: not a submission file (no \"format\": \"{FORMAT}\"); agents.submit.score(...)"
                                ".save(...) writes one")
    if sub.get("format_version") != FORMAT_VERSION:
        raise SubmissionRefused(f"{path}: submission format {sub.get('format_version')}, this code reads "
                                f"{FORMAT_VERSION}")
    check_schema(sub, str(path))
    return sub


#: per run, the per-episode arrays a submission must hold (numbers; ``terminated`` booleans)
RUN_ARRAYS = ("returns", "qp_fraction", "mean_preload")


def check_schema(sub: dict[str, Any], where: str = "the submission") -> None:
    """SubmissionRefused naming the first field of ``sub`` that is missing or malformed: the keys a
    board reads, and per run its per-episode arrays (finite numbers, one per episode) and reward terms."""
    for key, kind in (("name", str), ("tier", str), ("kernel_hash", str), ("test_seeds", list),
                      ("episodes", int), ("episode_steps", int), ("runs", list)):
        if not isinstance(sub.get(key), kind) or isinstance(sub.get(key), bool):
            raise SubmissionRefused(f"{where}: {key!r} must be a {kind.__name__}, got {sub.get(key)!r}")
    if not sub["name"].strip():
        raise SubmissionRefused(f"{where}: 'name' is empty")
    if not sub["runs"]:
        raise SubmissionRefused(f"{where}: no runs")
    n = sub["episodes"]
    for k, run in enumerate(sub["runs"]):
        if not isinstance(run, dict):
            raise SubmissionRefused(f"{where}: run {k} is not an object")
        arrays = {a: run.get(a) for a in RUN_ARRAYS}
        terms = run.get("terms")
        if not isinstance(terms, dict) or set(terms) != set(REWARD_TERMS):
            raise SubmissionRefused(f"{where}: run {k} must give the reward terms {list(REWARD_TERMS)}")
        arrays.update({f"terms.{t}": v for t, v in terms.items()})
        for a in ("vibration_um", "cost"):
            if run.get(a) is not None:
                arrays[a] = run[a]
        for a, v in arrays.items():
            try:
                x = np.asarray(v, dtype=np.float64)
            except (TypeError, ValueError):
                x = None
            if x is None or x.shape != (n,) or not np.all(np.isfinite(x)):
                raise SubmissionRefused(f"{where}: run {k}'s {a!r} must be {n} finite numbers (one per episode)")
        term = run.get("terminated")
        if term is not None and (not isinstance(term, list) or len(term) != n
                                 or not all(isinstance(t, bool) for t in term)):
            raise SubmissionRefused(f"{where}: run {k}'s 'terminated' must be {n} booleans or null")


def runs_of(submission: dict[str, Any]) -> list[EvalResult]:
    """The submission's runs as :class:`EvalResult` (one per training seed)."""
    out = []
    for run in submission["runs"]:
        r = result_from_json(run)
        r.cost = None if run.get("cost") is None else np.asarray(run["cost"], dtype=np.float64)
        out.append(r)
    return out


def row_name(submission: dict[str, Any]) -> str:
    return f"{submission['name']}{SUFFIX}"


def check_submission(sub: dict[str, Any], board: dict[str, Any]) -> dict[str, Any]:
    """The board's tier object that ``sub`` would join; SubmissionRefused saying why it cannot."""
    here = kernel_hash()
    if sub.get("benchmark") != board.get("benchmark"):
        raise SubmissionRefused(f"the submission is for {sub.get('benchmark')}, the board for {board.get('benchmark')}")
    board_version = (board.get("protocol") or {}).get("version")
    if board_version != P.PROTOCOL_VERSION:
        raise SubmissionRefused(f"the board was made under protocol version {board_version}, this code's is "
                                f"{P.PROTOCOL_VERSION}: rebuild the board first (python -m agents.regenerate)")
    if sub.get("protocol_version") != board_version:
        raise SubmissionRefused(f"the submission was made under protocol version {sub.get('protocol_version')}, this "
                                f"board's is {board_version}: score the policy again with this version "
                                "(agents.submit.score)")
    if board.get("kernel_hash") != here:
        raise SubmissionRefused(f"the board was made by kernel {board.get('kernel_hash')}, this code's kernel is {here}: "
                                "regenerate the board first (python -m agents.regenerate)")
    if sub.get("kernel_hash") != here:
        raise SubmissionRefused(f"the submission was made by kernel {sub.get('kernel_hash')} (bearing_gym "
                                f"{sub.get('package_version')}), not by this one ({here}, bearing_gym "
                                f"{package_version()}): its returns are another simulator's; score the policy "
                                "again with this version")
    if sub.get("privileged", False):
        raise SubmissionRefused("the submission used privileged information (the hidden scenario, info keys beyond the "
                                "reward terms and cost): a board's main rows read the observation only "
                                "(docs/benchmark.md); report it apart")
    if sub.get("variant", "standard") != "standard":
        raise SubmissionRefused(f"a {sub.get('variant')!r} submission: boards rank the benchmark's reward; report the "
                                "constrained variant's row by itself (Scored.markdown())")
    tier = sub.get("tier")
    if tier not in board.get("tiers", {}):
        raise SubmissionRefused(f"the submission is for tier {tier!r}, the board has {', '.join(board.get('tiers', {}))}")
    t = board["tiers"][tier]
    if (list(sub.get("test_seeds", [])) != list(t["seeds"]) or sub.get("episodes") != t["episodes"]
            or sub.get("episode_steps") != t["episode_steps"]):
        raise SubmissionRefused(f"the submission ran test seeds {sub.get('test_seeds')} ({sub.get('episodes')} episodes "
                                f"of {sub.get('episode_steps')} steps), the board's tier {tier} seeds {t['seeds']} "
                                f"({t['episodes']} of {t['episode_steps']}): score it on the board's episodes "
                                "(agents.submit.score without episodes=)")
    runs = sub.get("runs") or []
    if not runs or any(len(r.get("returns") or []) != t["episodes"] for r in runs):
        raise SubmissionRefused(f"every run of the submission must hold {t['episodes']} episode returns")
    return t


def add_submission(sub: dict[str, Any], board: dict[str, Any], references_dir: Path = DATA_DIR,
                   replace: bool = False) -> tuple[str, dict[str, Any]]:
    """Add ``sub`` to ``board`` (a results.json, changed in place) as a submitted row; returns the
    row's name and the row. The row is computed from the submission's returns against the stored
    references of the board's episodes, with the board's statistics (the board's validation and
    hindsight rows must hold the stored returns bit for bit, as the re-scoring demands)."""
    from agents.leaderboard.rescore import check_same_returns, row_named
    t = check_submission(sub, board)
    tier = sub["tier"]
    name = row_name(sub)
    if name in t["policies"]:
        if t["policies"][name].get("kind") != "submitted":
            raise SubmissionRefused(f"tier {tier} has a row {name!r} of its own: submit under another name")
        if not replace:
            raise SubmissionRefused(f"tier {tier} already has a submitted row {name!r}; pass --replace to replace it, "
                                    "or submit under another name")
    refs = test_references(tier, t["episodes"], Path(references_dir))
    check_same_returns(tier, *row_named(t["policies"], "validation constant", tier), refs.validation_constant.returns)
    check_same_returns(tier, *row_named(t["policies"], "hindsight constant", tier), refs.hindsight.returns)
    stats = board["statistics"]
    meta = {k: sub.get(k) for k in ("algorithm", "training_steps", "training_seeds", "library", "library_version",
                                    "code", "notes", "created")}
    industry = t.get("best_industry_row")      # the board's best industry row: P(> best industry) as for its own rows
    row = submitted_row(runs_of(sub), np.asarray(t["policies"][CONTEXTUAL]["episode_returns"][0], dtype=np.float64),
                        refs, stats["bootstrap_reps"], stats["poi_reps"],
                        versus={industry: t["policies"][industry]["episode_returns"]} if industry else None,
                        n_runs=len(sub["runs"]), **meta, submission_notes=reporting_gaps(sub))
    t["policies"][name] = row
    return name, row


def reporting_gaps(sub: dict[str, Any]) -> list[str]:
    """What a submission leaves out of what the rules ask it to report (docs/benchmark.md), or
    where it departs from the protocol's budget: shown beside its row, not refused."""
    gaps = []
    runs = len(sub.get("runs") or [])
    if runs < MIN_TRAINING_SEEDS:
        gaps.append(f"{runs} training seed(s) (the rules ask for at least {MIN_TRAINING_SEEDS})")
    steps = sub.get("training_steps")
    if steps is None:
        gaps.append("no training budget stated")
    elif steps > STEP_BUDGET:
        gaps.append(f"{steps:,} env steps of training (the protocol's budget: {STEP_BUDGET:,})")
    if not sub.get("code"):
        gaps.append("no link to its code")
    if not sub.get("library"):
        gaps.append("no library named")
    return gaps


def store_dir(board_path: Path) -> Path:
    """Where a board keeps the submissions added to it: ``submissions/`` beside its results.json."""
    return Path(board_path).parent / "submissions"


def stored_path(board_path: Path, sub: dict[str, Any]) -> Path:
    """The file a submission is kept in beside ``board_path`` (its tier and name, made a file name)."""
    slug = "".join(c if c.isalnum() or c in "-_" else "_" for c in sub["name"].strip().lower()).strip("_") or "policy"
    return store_dir(board_path) / f"{sub['tier']}_{slug}.json"


def readd_stored(board: dict[str, Any], board_path: Path, tiers: list[str] | None = None,
                 references_dir: Path = DATA_DIR) -> list[str]:
    """Add the submissions kept beside ``board_path`` to ``board`` (its tiers ``tiers``, default
    all): what a rebuilt board does, so that its submitted rows survive the rebuild. One that the
    rebuilt board refuses (another kernel, protocol version, test seeds) is left out with its
    reason; the lines returned say what happened to each."""
    out = []
    for f in sorted(store_dir(board_path).glob("*.json")):
        try:
            sub = load_submission(f)
            if tiers is not None and sub["tier"] not in tiers:
                continue
            name, _ = add_submission(sub, board, references_dir, replace=True)
            out.append(f"{f.name}: row {name!r} on {sub['tier']}")
        except (SubmissionRefused, ValueError, RuntimeError) as err:
            out.append(f"{f.name}: left out ({err})")
    return out
