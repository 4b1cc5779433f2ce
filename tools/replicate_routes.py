"""Replicate routes: the pipeline on several synthetic routes, and which conclusions hold on all.

    python -m tools.replicate_routes run --seeds 1 2 3 4 [--jobs 1]
    python -m tools.replicate_routes collect
    python -m tools.replicate_routes run --preset every_place --seeds 0 1 2 3 4
    python -m tools.replicate_routes keep --preset every_place

With `--preset NAME` every route, the committed run's own seed among them, is an experiment named
route-<NAME>-<seed> with the preset's settings (presets/NAME.yaml, as `-S` settings), so the routes
of a preset need no commit of their own; `collect --preset NAME` reads those back.

`run` queues one DVC experiment per seed, everything else as in params.yaml
(`dvc exp run --queue -n route-<seed> -S synthetic.seed=<seed> <stages>`: the stages that write
what `collect` reads, and what they need; the CAE width sweep, figures and report, which it does not
read, are left as the baseline's), runs the queue
(`dvc queue start -j <jobs>`), waits for it, then collects. `collect` reads the routes back: the
experiments named route-<seed> of `dvc exp show --json` (of the newest commit that has any, and of
older commits with the same pipeline: see routes_of) and the committed run they branched from
(params.yaml's own seed: run `dvc repro` and commit before `run`), each one's metrics/summary.json,
metrics/training_seasons.json and data/outcomes/ through DVC's file system at its revision (from the
cache: no second copy of the pipeline), together with the routes kept in docs/results/routes/
(`keep`, tools.route_snapshots: routes run on another machine or day, whose cache is gone), when
every route ran the same pipeline. It writes benchmarks/results/replicate_routes.json: the
spread of every fraction correct over the routes (and of the training-season ablation's), each claim
of docs/claims.yaml tallied over the routes (each route's own paired tests, from its outcomes as its
compare stage computes them) and pooled (seasonloop.reporting.replicates), and the queue's wall time;
`python docs/write_tables.py --snapshot replicate_spread replicate_claims replicate_training_seasons`
puts it in docs/routes.md.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml
from tqdm import tqdm

from seasonloop.evaluation.matchers import evaluations
from seasonloop.params.seasons import available_pairs, pair_name
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.preset import preset_changes
from seasonloop.reporting.comparisons import comparisons_of, csv_reader
from seasonloop.reporting.replicates import (
    claims_across_routes,
    claims_in,
    first_to_last,
    fraction_spread,
    pooled_comparisons,
)
from tools.records import git_state, machine, write_result
from tools.repository import REPO, start_queue
from tools.route_snapshots import (
    KEPT,
    SUMMARY,
    TRAINING,
    difference,
    fingerprint,
    keep,
    kept_routes,
    npz_reader,
    without_seed,
    yaml_at,
)

PREFIX = "route-"
FETCHED = (SUMMARY, TRAINING, "data/outcomes")  # each route's own paired tests are computed from its outcomes
CLAIMS = REPO / "docs" / "claims.yaml"
SEARCHED = 20  # commits back from HEAD whose experiments `collect` looks at
QUEUE = REPO / "benchmarks" / "results" / "replicate_routes_queue.json"  # the last `run`'s queue


def dvc(*args: str, root: Path = REPO) -> subprocess.CompletedProcess:
    """A dvc command in the repository (or in `root`); a one-line error with its message when it fails."""
    done = subprocess.run(["dvc", *args], cwd=root, capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"dvc {' '.join(args)}: {(done.stderr or done.stdout).strip().splitlines()[-1:]}")
    return done


NO_WORKERS = "Worker status: 0 active, 0 idle"  # `dvc queue status` when no worker runs


def start_workers(jobs: int) -> None:
    """`dvc queue start -j jobs`: workers that run the queue in the background."""
    started = start_queue(REPO, "-j", str(jobs))
    if started.returncode:
        raise SystemExit(f"dvc queue start -j {jobs} failed: {started.stdout.strip()}")


def route_stages(root: Path = REPO) -> list[str]:
    """The stages of the pipeline whose outputs are or lie in FETCHED, as dvc.yaml declares them:
    a route's experiment runs these (and the stages they depend on), not the others."""
    from dvc.repo import Repo

    with Repo(str(root)) as repo:
        return [
            stage.name  # as dvc.yaml names it (addressing is relative to the working directory)
            for stage in repo.index.stages
            if any(
                Path(out.def_path) == Path(path) or Path(path) in Path(out.def_path).parents
                for out in stage.outs
                for path in FETCHED
            )
        ]


PRESETS = REPO / "presets"


def route_name(seed: int, preset: str | None = None) -> str:
    """The experiment of a route: route-<seed>, or route-<preset>-<seed> under a preset."""
    return f"{PREFIX}{preset}-{seed}" if preset else f"{PREFIX}{seed}"


def is_route(name: str, preset: str | None = None) -> bool:
    """Whether an experiment's name is a route's of `preset` (None: the committed params')."""
    return re.fullmatch(re.escape(route_name(0, preset)[:-1]) + r"\d+", name) is not None


def preset_settings(preset: str | None) -> list[str]:
    """The preset's values as `dvc exp run -S` settings (section.key=value, values in YAML's flow
    style, as DVC parses them); none without a preset."""
    if preset is None:
        return []
    settings = []
    for section, values in preset_changes(preset, PRESETS).items():
        pairs = values.items() if isinstance(values, dict) else [(None, values)]
        for key, value in pairs:
            text = yaml.safe_dump(value, default_flow_style=True, width=10**6).strip().removesuffix("\n...")
            settings.append(f"{section}.{key}={text}" if key is not None else f"{section}={text}")
    return settings


def queue_routes(seeds: list[int], jobs: int, stages: list[str], preset: str | None = None) -> tuple[float, list[int]]:
    """Queue and run one experiment per seed (with the preset's settings), up to `stages`
    (route_stages); the queue's wall seconds and the seeds whose experiment succeeded (a route
    removed from the queue by hand, `dvc queue remove`, did not run in that time)."""
    extra = [flag for setting in preset_settings(preset) for flag in ("-S", setting)]
    names = [route_name(seed, preset) for seed in seeds]
    for seed, name in zip(seeds, names):
        dvc("exp", "run", "--queue", "-n", name, "-S", f"synthetic.seed={seed}", *extra, *stages)
    started = workers_started = time.monotonic()
    start_workers(jobs)
    # `dvc queue status` costs ~0.8 s of CPU: asked every 10 s, and at once when a route's
    # experiment ref appears (a git call that costs nothing), so the wait ends with the queue
    asked, finished = -float("inf"), -1
    with tqdm(total=len(seeds), desc="routes", unit="route") as progress:
        while True:
            refs = subprocess.run(
                ["git", "for-each-ref", "--format=%(refname)", "refs/exps"], cwd=REPO, capture_output=True, text=True
            ).stdout.split()
            now_finished = sum(any(ref.endswith(f"/{name}") for ref in refs) for name in names)
            if now_finished != finished or time.monotonic() - asked >= 10:
                status, asked, finished = dvc("queue", "status").stdout, time.monotonic(), now_finished
                done = sum(
                    any(f"{name} " in line for name in names) and "Success" in line for line in status.splitlines()
                )
                progress.update(done - progress.n)
                if not any(word in status for word in ("Queued", "Running")):
                    break
                # DVC's workers can all exit with routes still queued (seen with -j 2 when the first
                # two routes were restored from the run cache in seconds): started again, once the
                # workers of the last start have had time to appear in the status
                if "Running" not in status and NO_WORKERS in status and time.monotonic() - workers_started > 30:
                    start_workers(jobs)
                    workers_started = time.monotonic()
            time.sleep(1)
    if "Failed" in status:
        raise SystemExit(f"a route's experiment failed (`dvc queue logs <name>`):\n{status}")
    ran = [
        seed
        for seed, name in zip(seeds, names)
        if any(f"{name} " in line and "Success" in line for line in status.splitlines())
    ]
    return time.monotonic() - started, ran


QUEUE_TIMED = "by `replicate_routes.py run`, from `dvc queue start` to an empty queue"
RESTORED = " is cached - skipping run"  # DVC's log line of a stage whose outputs came from the run cache


def restored_in(log: str) -> list[str]:
    """The stages an experiment's log (`dvc queue logs`) says DVC restored from its run cache
    instead of running them."""
    return [line.split("'")[1] for line in log.splitlines() if RESTORED in line and line.count("'") >= 2]


UNTIMED = {"queue_seconds": None, "jobs": None, "queue_timed": None, "queue_cpu": None}


def saved_queue(saved: Path) -> tuple[dict[str, Any], dict[str, Any]]:
    """The last `run`'s queue file (saved; {} when there is none) and its cost {queue_seconds, jobs,
    queue_timed (how), queue_cpu (the machine that ran it; None in a file from before it was kept)}."""
    queued = json.loads(saved.read_text()) if saved.is_file() else {}
    if not queued or queued["seconds"] is None:
        return queued, dict(UNTIMED)
    return queued, {
        "queue_seconds": queued["seconds"],
        "jobs": queued["jobs"],
        "queue_timed": queued.get("timed", QUEUE_TIMED),
        "queue_cpu": queued.get("cpu"),
    }


def queue_cost(seeds: list[int], preset: str | None = None, saved: Path = QUEUE) -> dict[str, Any]:
    """{queue_seconds, jobs, queue_timed, queue_cpu} (saved_queue) of the last `run` when it queued
    exactly the routes of `seeds` that are experiments (every seed but the first, the baseline's;
    under a preset every seed) with that preset, else None for each."""
    queued, cost = saved_queue(saved)
    queued_routes = seeds if preset else seeds[1:]
    if sorted(queued.get("seeds", [])) != sorted(queued_routes) or queued.get("preset") != preset:
        return dict(UNTIMED)
    return cost


def routes_of(
    shown: list[dict[str, Any]], same_pipeline: Callable[[str, str], bool], preset: str | None = None
) -> dict[str, dict[str, Any]]:
    """name -> {rev, seed} of the routes in `dvc exp show --json`: the newest commit that has
    experiments named as routes (route_name), those experiments, and those of older commits whose
    pipeline is the same (same_pipeline(newer, older): a commit that changed only docs leaves the
    routes comparable); the newest route of a seed. Without a preset the commit's own run is the
    baseline route (its params.yaml's seed), first; under a preset every route is an experiment."""
    routes: dict[str, dict[str, Any]] = {}
    newest = None
    for baseline in shown:
        if baseline["rev"] == "workspace" or (newest is not None and not same_pipeline(newest, baseline["rev"])):
            continue
        for experiment in baseline.get("experiments") or []:
            # a queued, running or failed experiment has params but no outputs of its own
            if (experiment.get("executor") or {}).get("state") not in (None, "success"):
                continue
            for rev in experiment["revs"]:
                name = rev.get("name") or ""
                if is_route(name, preset) and rev["data"].get("params"):
                    seed = int(rev["data"]["params"]["params.yaml"]["data"]["synthetic"]["seed"])
                    if newest is None:
                        newest = baseline["rev"]
                        if preset is None:
                            own = int(baseline["data"]["params"]["params.yaml"]["data"]["synthetic"]["seed"])
                            routes[f"{PREFIX}{own} (baseline)"] = {"rev": newest, "seed": own}
                    if seed not in {route["seed"] for route in routes.values()}:
                        routes[name] = {"rev": rev["rev"], "seed": seed}
    first = list(routes.items())[:1] if preset is None else []
    return dict(first + sorted(list(routes.items())[len(first) :], key=lambda item: item[1]["seed"]))


def commit_of(shown: list[dict[str, Any]], rev: str) -> str:
    """The commit of `dvc exp show --json` that is `rev` or has it as an experiment."""
    for baseline in shown:
        experiments = baseline.get("experiments") or []
        if baseline["rev"] == rev or any(r["rev"] == rev for experiment in experiments for r in experiment["revs"]):
            return baseline["rev"]
    raise ValueError(f"replicate_routes: {rev} is not in `dvc exp show`")


def same_pipeline(newer: str, older: str, root: Path = REPO) -> bool:
    """Whether two commits run the same pipeline: no change to dvc.yaml, params.yaml, stages/ or
    src/ between them (git)."""
    paths = ["dvc.yaml", "params.yaml", "stages", "src"]
    return subprocess.run(["git", "diff", "--quiet", older, newer, "--", *paths], cwd=root).returncode == 0


def fetch(rev: str, folder: Path, root: Path = REPO) -> None:
    """The route's outputs FETCHED at revision `rev` of the repository at `root`, from DVC's cache, into `folder`."""
    from dvc.api import DVCFileSystem

    fs = DVCFileSystem(str(root), rev=rev)
    for path in FETCHED:
        target = folder / path
        target.parent.mkdir(parents=True, exist_ok=True)
        fs.get(path, str(target), recursive=path.startswith("data/"))


def found_routes(preset: str | None = None, root: Path = REPO) -> dict[str, dict[str, Any]]:
    """name -> {rev, seed, commit, fingerprint, params} of the routes among the experiments of the
    repository at `root` (routes_of), each with the pipeline it ran (route_snapshots.fingerprint of
    its dvc.lock)."""
    shown = json.loads(dvc("exp", "show", "--json", "-n", str(SEARCHED), root=root).stdout)
    routes = routes_of(shown, lambda newer, older: same_pipeline(newer, older, root), preset)
    stages = route_stages(root)
    for route in routes.values():
        route["commit"] = commit_of(shown, route["rev"])
        route["fingerprint"] = fingerprint(yaml_at(route["rev"], "dvc.lock", root), stages)
        route["params"] = yaml_at(route["rev"], "params.yaml", root)  # with an experiment's -S settings
    return routes


def keep_routes(preset: str | None = None, root: Path = REPO) -> list[Path]:
    """Write every route among the experiments of the repository at `root` (this one, or a checkout
    of an older commit that ran them) into this repository's docs/results/routes/
    (tools.route_snapshots), each with the cost of that repository's last `run` queue where that
    queue ran it (queue_of)."""
    routes = found_routes(preset, root)
    if not routes:
        raise SystemExit(
            f"replicate_routes: no route experiment in {root} to keep: run `replicate_routes.py run` first"
        )
    params = next(iter(routes.values()))["params"]
    evaluate = EvaluateConfig.from_params(params)
    outcomes = {
        "learners": params["learners"],
        "suffixes": [suffix for _, _, suffix in evaluations(evaluate)],
        "pairs": [pair_name(a, b) for a, b in available_pairs(params["data"]["seasons"], evaluate.pairs)],
    }
    queued = root / QUEUE.relative_to(REPO)
    kept = []
    with tempfile.TemporaryDirectory() as tmp:
        for index, (name, route) in enumerate(routes.items()):
            folder = Path(tmp) / f"route{index}"
            fetch(route["rev"], folder, root)
            queue = queue_of(route["seed"], preset, queued)
            kept.append(keep(name, folder, {**route, "preset": preset, "queue": queue}, outcomes))
    return kept


def queue_of(seed: int, preset: str | None, saved: Path) -> dict[str, Any]:
    """{seeds, queue_seconds, jobs, queue_timed, queue_cpu} of the last `run`'s queue (saved) when it ran the
    route of `seed` under `preset`, else None for each: a kept route names the queue it ran in,
    whatever other experiments the repository holds."""
    queued, cost = saved_queue(saved)
    if seed not in queued.get("seeds", []) or queued.get("preset") != preset:
        return {"seeds": None, **UNTIMED}
    return {"seeds": sorted(queued["seeds"]), **cost}


def all_routes(preset: str | None) -> dict[str, dict[str, Any]]:
    """The routes among the experiments and those kept in docs/results/routes/ (a seed the
    experiments have is read from them), by seed (the baseline first); one line naming a route whose
    pipeline differs from the first's."""
    routes = found_routes(preset)
    seeds = {route["seed"] for route in routes.values()}
    routes |= {name: route for name, route in kept_routes(preset).items() if route["seed"] not in seeds}
    if not routes:
        flag = f" --preset {preset}" if preset else ""
        raise SystemExit(
            f"replicate_routes: no experiment named {route_name(0, preset)[:-1]}<seed> on the last {SEARCHED} "
            f"commits and none kept in {KEPT}: run `replicate_routes.py run{flag}` first"
        )
    routes = dict(sorted(routes.items(), key=lambda item: (not item[0].endswith("(baseline)"), item[1]["seed"])))
    (first_name, first), *others = routes.items()
    seeds = [route["seed"] for route in routes.values()]
    if len(set(seeds)) < len(seeds):
        raise SystemExit(f"replicate_routes: two routes of one seed among {', '.join(routes)}: keep one")
    for name, route in others:
        differs = difference(first["fingerprint"], route["fingerprint"])
        if differs is None and without_seed(first["params"]) != without_seed(route["params"]):
            differs = "params.yaml"
        if differs:
            raise SystemExit(f"replicate_routes: {name} ran another pipeline than {first_name} ({differs}): not pooled")
    return routes


def collect(measured_on: dict[str, Any], preset: str | None = None) -> Path:
    routes = all_routes(preset)
    params = next(iter(routes.values()))["params"]  # every route's, but the seed (all_routes)
    evaluate = EvaluateConfig.from_params(params)
    settings = StatisticsConfig.from_params(params)
    seasons = params["data"]["seasons"]
    pairs = [pair_name(a, b) for a, b in available_pairs(seasons, evaluate.pairs)]
    learners, variants = params["learners"], evaluations(evaluate)
    claims = {name: claim for name, claim in yaml.safe_load(CLAIMS.read_text()).items() if "run" not in claim}
    summaries, training, readers = {}, {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for index, (name, route) in enumerate(routes.items()):
            print(f"reading {name} ({route['rev'][:7]}{', kept' if 'folder' in route else ''})", file=sys.stderr)
            if "folder" in route:  # kept: tools.route_snapshots
                folder = route["folder"]
                summaries[name] = json.loads((folder / Path(SUMMARY).name).read_text())
                training[name] = json.loads((folder / Path(TRAINING).name).read_text())
                readers[name] = npz_reader(folder / "outcomes.npz")
            else:
                folder = Path(tmp) / f"route{index}"
                fetch(route["rev"], folder)
                summaries[name] = json.loads((folder / SUMMARY).read_text())
                training[name] = json.loads((folder / TRAINING).read_text())
                readers[name] = csv_reader(folder / "data" / "outcomes")
        # each route's own paired tests (what its compare stage writes), and every route's together
        comparisons = {name: comparisons_of(readers[name], learners, variants, pairs, settings) for name in routes}
        pooled = pooled_comparisons(
            {route["seed"]: readers[name] for name, route in routes.items()}, learners, variants, pairs, settings
        )
    claims, left_out = claims_in(next(iter(comparisons.values())), claims)
    experiments = [route["seed"] for route in routes.values() if "folder" not in route]
    record = {
        "routes": {
            name: {
                "rev": route["rev"],
                "seed": route["seed"],
                "commit": route["commit"],
                "kept": "folder" in route,
                "queue": route.get("queue"),
            }
            for name, route in routes.items()
        },
        "preset": preset,
        "pairs": pairs,
        # the last `run`'s queue, when it queued the experiments read here
        **queue_cost(experiments, preset),
        "fraction_correct": fraction_spread(summaries),
        # the training-season ablation: label -> training set -> spread; the largest set against the smallest
        "training_seasons": {"fraction_correct": fraction_spread(training), "first_to_last": first_to_last(training)},
        "claims": claims_across_routes(comparisons, pooled, claims),
        "claims_says": {name: claim["says"] for name, claim in claims.items()},
        # JSON objects come back with sorted keys: the tables' order of rows
        "order": {
            "labels": [learner + suffix for _, _, suffix in variants for learner in learners],
            "claims": list(claims),
        },
        "claims_left_out": left_out,  # on a learner or table this run does not have
    }
    return write_result("replicate_routes", record, measured_on)


def save_queue(seeds: list[int], jobs: int, seconds: float | None, cpu: str, preset: str | None = None) -> None:
    """The queue's cost (None: not a cost of its routes) and the CPU that ran it, kept apart so
    that a later `collect` or `keep` (on another machine, too) reports them (QUEUE)."""
    QUEUE.parent.mkdir(parents=True, exist_ok=True)
    queue = {"seeds": seeds, "jobs": jobs, "seconds": seconds, "preset": preset, "cpu": cpu}
    QUEUE.write_text(json.dumps(queue) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("action", choices=["run", "keep", "collect"])
    parser.add_argument(
        "--seeds",
        type=int,
        nargs="+",
        default=[1, 2, 3, 4],
        help="synthetic.seed of each route run as an experiment (the committed run's own seed is a route "
        "without a preset; under one, name it too)",
    )
    parser.add_argument("--jobs", type=int, default=1, help="experiments run at a time (dvc queue start -j)")
    parser.add_argument("--preset", help="run every route with presets/PRESET.yaml's settings (e.g. every_place)")
    parser.add_argument(
        "--repo", type=Path, default=REPO, help="keep: the repository whose experiments are kept (default: this one)"
    )
    args = parser.parse_args()
    if args.preset:
        preset_settings(args.preset)  # an unknown preset: one line naming it, before anything is queued
    if args.action == "keep":
        for folder in keep_routes(args.preset, args.repo.resolve()):
            print(f"kept {folder.relative_to(REPO)}")
        return
    measured_on = {**machine(), "source": git_state()}
    if args.action == "run":
        seconds, ran = queue_routes(args.seeds, args.jobs, route_stages(), args.preset)
        # a stage restored from the run cache ran earlier, elsewhere: the queue's time is no route's cost
        names = [route_name(seed, args.preset) for seed in ran]
        restored = [f"{name}: {stage}" for name in names for stage in restored_in(dvc("queue", "logs", name).stdout)]
        if restored:
            print(
                f"replicate_routes: {len(restored)} stages came from DVC's run cache ({restored[0]}, ...): "
                "the queue's time is not recorded",
                file=sys.stderr,
            )
        save_queue(ran, args.jobs, None if restored else seconds, measured_on["cpu"], args.preset)
    print(collect(measured_on, args.preset))


def _queue_phrase(what: str, seconds: float | None, jobs: int | None, cpu: str) -> str:
    """What a queue of routes cost ("" when not timed)."""
    return f"the queue of {what} took {seconds / 60:.0f} min, {jobs} at a time, on {cpu}" if seconds else ""


def _routes_line(record: dict) -> str:
    """Which routes a replicate record stands on, the commit each ran at, and what their queues cost."""
    routes = list(record["routes"].values())
    seeds = ", ".join(str(route["seed"]) for route in routes)
    preset = record.get("preset")
    under = f", each with preset {preset} (`--preset {preset}`)" if preset else ""
    # (commit, kept, the seeds of a kept route's queue) -> its routes; older records name no commit
    runs: dict[tuple[str, bool, tuple], list[dict]] = {}
    for route in routes:
        if route.get("commit"):
            queued = tuple((route.get("queue") or {}).get("seeds") or ()) if route["kept"] else ()
            runs.setdefault((route["commit"][:7], route["kept"], queued), []).append(route)
    parts = []
    for (commit, kept, queued), ran in runs.items():
        queue = (ran[0]["queue"] or {}) if kept else record
        count = len(queued) if kept else len(ran)  # a kept route's queue may have run routes not read here
        # the CPU that ran the queue (a record from before queue_cpu names the collecting machine, as it did)
        cpu = queue.get("queue_cpu") or ("a CPU not recorded" if kept else record["machine"]["cpu"])
        cost = _queue_phrase(
            f"{count} route{'s' if count > 1 else ''}", queue.get("queue_seconds"), queue.get("jobs"), cpu
        )
        where = " (kept in docs/results/routes/)" if kept else ""
        parts.append(
            f"seed {', '.join(str(route['seed']) for route in ran)} run at {commit}{where}"
            + (f": {cost}" if cost else "")
        )
    if not runs:
        extra = len(routes) - (0 if preset else 1)
        what = f"the {extra} {'' if preset else 'extra '}routes"
        cpu = record.get("queue_cpu") or record["machine"]["cpu"]
        cost = _queue_phrase(what, record.get("queue_seconds"), record.get("jobs"), cpu)
        parts = [cost] if cost else []
    return f"{len(routes)} routes (synthetic.seed {seeds}){under}" + "".join(f"; {part}" for part in parts) + "."


def _spread_cell(spread: dict) -> str:
    """A fraction correct's spread over the routes (replicates.fraction_spread), in %: "mean ± std [lowest, highest]"."""
    return (
        f"{100 * spread['mean']:.1f} ± {100 * spread['std']:.1f} [{100 * spread['min']:.0f}, {100 * spread['max']:.0f}]"
    )


def _replicate_spread(path: Path) -> str:
    """Fraction correct over the replicate routes, under the main distance: mean ± standard
    deviation [lowest, highest], in %."""
    record = json.loads(path.read_text())
    pairs = record["pairs"]
    lines = [_routes_line(record), "", "| learner | " + " | ".join(pairs) + " |", "|---|" + "---|" * len(pairs)]
    for label in record["order"]["labels"]:
        by_pair = record["fraction_correct"][label]
        if "@" in label:
            continue
        cells = [_spread_cell(by_pair[pair]) for pair in pairs]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _replicate_training_seasons(path: Path) -> str:
    """The training-season ablation over the replicate routes: per label and training set, fraction
    correct mean ± standard deviation [lowest, highest] (%); in how many routes the largest training
    set is above, below or equal to the smallest."""
    record = json.loads(path.read_text())
    spread, changes = record["training_seasons"]["fraction_correct"], record["training_seasons"]["first_to_last"]
    sets = sorted(next(iter(spread.values())), key=lambda name: name.count("+"))
    lines = [
        _routes_line(record),
        "",
        "| learner | " + " | ".join(sets) + " | largest set against smallest |",
        "|---|" + "---|" * (len(sets) + 1),
    ]
    for label, by_set in spread.items():
        cells = ["n/a" if by_set[name] is None else _spread_cell(by_set[name]) for name in sets]
        change = changes.get(label, {"up": 0, "down": 0, "same": 0})
        cells.append(f"above in {change['up']}, below in {change['down']}, equal in {change['same']}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _replicate_totals(cells: list[dict], routes: int) -> str:
    """A claim over every route-pair cell: ahead / significant counts of all, and on how many pairs
    its pooled verdict is significant each way."""
    if "ahead" not in cells[0]:  # a whole table
        better, worse, of = (sum(cell[f"pooled_{key}"] for cell in cells) for key in ("better", "worse", "of"))
        return f"pooled ▲ {better} ▼ {worse} of {of} comparisons"
    pooled_better = sum(cell["pooled_verdict"] == "better" for cell in cells)
    pooled_worse = sum(cell["pooled_verdict"] == "worse" for cell in cells)
    pooled = f"pooled ▲ on {pooled_better}, ▼ on {pooled_worse} of {len(cells)} pairs"
    total = routes * len(cells)
    ahead, better, worse = (sum(cell[key] for cell in cells) for key in ("ahead", "better", "worse"))
    return f"ahead in {ahead}/{total}, ▲ {better} ▼ {worse}; {pooled}"


def _replicate_claims(path: Path) -> str:
    """Each claim of docs/claims.yaml over the replicate routes: per pair, in how many routes it
    points each way and is significant, and its pooled verdict."""
    record = json.loads(path.read_text())
    pairs, routes = record["pairs"], len(record["routes"])
    lines = [
        _routes_line(record),
        "",
        "| claim | compares | " + " | ".join(pairs) + " | all pairs |",
        "|---|---|" + "---|" * (len(pairs) + 1),
    ]
    for name in record["order"]["claims"]:
        by_pair = record["claims"][name]
        cells = []
        for pair in pairs:
            counts = by_pair[pair]
            if "ahead" in counts:
                routes_cell = f"ahead in {counts['ahead']}/{routes}, ▲ {counts['better']} ▼ {counts['worse']}"
            else:
                better = f"{counts['least_better']}-{counts['most_better']}"
                worse = f"{counts['least_worse']}-{counts['most_worse']}"
                routes_cell = f"▲ {better} ▼ {worse} per route"
            cells.append(f"{routes_cell}; pooled {counts['pooled']}")
        cells.append(_replicate_totals([by_pair[pair] for pair in pairs], routes))
        lines.append(f"| {name} | {record['claims_says'][name]} | " + " | ".join(cells) + " |")
    legend = (
        "Cells: in how many routes the first side's point estimate is ahead, and in how many it is "
        "significantly better (▲) or worse (▼) by that route's own paired test (for a whole table: the "
        "range over the routes of its significant comparisons each way); all pairs: the same counted over "
        "every route and pair; pooled: every route's queries of the pair together, the same paired test "
        "and Holm correction as in one run, each route's variance along it its own "
        "(seasonloop.reporting.replicates; a statement about these routes' queries)."
    )
    return "\n".join(lines) + "\n\n" + legend + "\n"


# docs/write_tables.py's tables of the replicate routes' record: name -> (record, snapshot, how it is written)
TABLES = {
    name: ("benchmarks/results/replicate_routes.json", "replicate_routes.json", writer)
    for name, writer in (
        ("replicate_spread", _replicate_spread),
        ("replicate_claims", _replicate_claims),
        ("replicate_training_seasons", _replicate_training_seasons),
    )
}


if __name__ == "__main__":
    main()
