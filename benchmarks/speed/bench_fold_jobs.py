"""What do a learner's folds gain from being fitted at once (train.jobs), at equal bytes?

    python -m benchmarks.speed.bench_fold_jobs WORKSPACE [--learners pca ica ica_bovw]

WORKSPACE is a clone that ran the every-place preset (`python -m seasonloop.preset every_place &&
dvc repro`, at least to data/split). For each learner its K folds are fitted, by this checkout's
fit stage code (stages/fit.py's fit_fold, into a temporary folder: the workspace is not touched),
three ways, each in a fresh process:
- jobs 1, threads 0: one fold after another, each with every core (the default);
- jobs 1, threads 1: one after another, one thread each;
- jobs J, threads 1: J at once (J = the machine's cores), one thread each.
The last two must give the same bytes (checked); the ratios are the default's and one-thread's
wall time over the jobs' (above 1: fitting at once is faster). The fits' convergence is recorded
beside (an ICA fit at other threads sums in another order: the same tolerance, other bytes).
Writes benchmarks/results/bench_fold_jobs.json.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time
from functools import partial
from pathlib import Path

import yaml

from benchmarks.common import load_note, save_and_report
from tools.records import machine
from tools.repository import REPO


def fit_all(workspace: Path, name: str, jobs: int, threads: int, out: Path) -> dict:
    """The learner's K folds on the workspace's data fitted into `out`; each fold's fit info, and
    the seconds of them all."""
    os.chdir(workspace)  # the stages read data/ and params.yaml from the current folder
    sys.path.insert(0, str(REPO / "stages"))
    from fit import fit_fold

    from _common import train_seasons
    from _datasets import SPLIT
    from seasonloop.data.datasets import count_folds
    from seasonloop.models.core.parallel import run_each

    params = yaml.safe_load(Path("params.yaml").read_text())
    params["train"] = {**params["train"], "jobs": jobs, "threads": threads}
    folds = count_folds(SPLIT)
    start = time.perf_counter()
    fitted = run_each(partial(fit_fold, name, params, train_seasons(params), folds, out), [*range(folds)], jobs)
    return {"seconds": time.perf_counter() - start, "folds": folds, "infos": [info for info, _ in fitted]}


def model_hash(folder: Path) -> str:
    """sha256 of the saved models' files (not their JSON reports, which hold times)."""
    digest = hashlib.sha256()
    for path in sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix != ".json"):
        digest.update(str(path.relative_to(folder)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def converged(infos: list[dict]) -> str:
    """The fits' own stop report, summarised (a learner without one: 'closed form')."""
    # ica: its own flag; ica_bovw: its patch ICA's; the auto-encoders: their plateau flag
    stops = [info.get("converged", (info.get("ica") or {}).get("converged")) for info in infos]
    if all(stop is None for stop in stops):
        return "closed form"
    if all(isinstance(stop, bool) for stop in stops):
        return f"{sum(stops)} of {len(stops)} converged"
    return ", ".join(sorted({str(stop) for stop in stops}))


def one_way(workspace: Path, name: str, jobs: int, threads: int) -> dict:
    """fit_all in a fresh process (thread pools are set once a process), its models hashed."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "models"
        command = [sys.executable, "-m", "benchmarks.speed.bench_fold_jobs", str(workspace), "--one", name]
        command += [str(jobs), str(threads), str(out)]
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), str(REPO / "src")])}
        # from this checkout (python -m puts the current folder first: not the workspace's own copy)
        done = subprocess.run(command, cwd=REPO, env=env, capture_output=True, text=True)
        if done.returncode:
            raise SystemExit(f"{name} jobs {jobs} threads {threads} failed:\n{done.stderr[-3000:]}")
        result = json.loads(done.stdout.strip().splitlines()[-1])
        return {
            "jobs": jobs,
            "threads": threads,
            "seconds": result["seconds"],
            "folds": result["folds"],
            "fits": converged(result["infos"]),
            "model_sha256": model_hash(out),
        }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("workspace", type=Path)
    parser.add_argument("--learners", nargs="+", default=["pca", "ica", "ica_bovw"])
    parser.add_argument("--one", nargs=4, metavar=("LEARNER", "JOBS", "THREADS", "OUT"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        name, jobs, threads, out = args.one
        print(json.dumps(fit_all(args.workspace.resolve(), name, int(jobs), int(threads), Path(out)), default=str))
        return
    measured_on = machine()
    cores = os.cpu_count() or 1
    rows = {}
    for name in args.learners:
        ways = [
            one_way(args.workspace.resolve(), name, jobs, threads) for jobs, threads in ((1, 0), (1, 1), (cores, 1))
        ]
        default, single, together = ways
        rows[name] = {
            "ways": ways,
            "same_bytes": single["model_sha256"] == together["model_sha256"],
            "default_over_jobs": default["seconds"] / together["seconds"],
            "one_thread_over_jobs": single["seconds"] / together["seconds"],
        }
        print(
            f"{name}: {together['folds']} folds  default {default['seconds']:.0f} s ({default['fits']})  "
            f"one thread {single['seconds']:.0f} s  {cores} at once {together['seconds']:.0f} s ({together['fits']})  "
            f"same bytes: {rows[name]['same_bytes']}",
            flush=True,
        )
    headline = "; ".join(
        f"{name} {row['default_over_jobs']:.2f}x the default's speed, {row['one_thread_over_jobs']:.2f}x "
        f"one-thread fits', {'same' if row['same_bytes'] else 'OTHER'} bytes"
        for name, row in rows.items()
    )
    record = {
        "cores": cores,
        "learners": rows,
        "headline": f"{cores} folds at once: {headline}",
        "load_note": load_note(measured_on),
    }
    save_and_report("bench_fold_jobs", record, measured_on)


def fold_jobs_table(path: Path) -> str:
    """bench_fold_jobs' record: each learner's K folds fitted three ways, the ratios, the bytes."""
    from benchmarks.common import where_measured

    record = json.loads(path.read_text())
    cores = record["cores"]
    lines = [
        f"| learner | folds | one after another, every core (s) | one after another, 1 thread (s) | {cores} at once, "
        "1 thread each (s) | speed-up over every core | over 1 thread | same bytes as 1 thread | fits: every core / 1 thread |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, row in record["learners"].items():
        default, single, together = row["ways"]
        lines.append(
            f"| {name} | {together['folds']} | {default['seconds']:.0f} | {single['seconds']:.0f} | "
            f"{together['seconds']:.0f} | {row['default_over_jobs']:.2f} | {row['one_thread_over_jobs']:.2f} | "
            f"{'yes' if row['same_bytes'] else 'no'} | {default['fits']} / {together['fits']} |"
        )
    return "\n".join(lines) + f"\n\n{where_measured(record)}\n"


TABLES = {"bench_fold_jobs": ("benchmarks/results/bench_fold_jobs.json", "bench_fold_jobs.json", fold_jobs_table)}


if __name__ == "__main__":
    main()
