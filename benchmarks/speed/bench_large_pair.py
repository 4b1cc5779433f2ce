"""One pair at the field's protocols' size, evaluated as the evaluate stage does (a block of query
rows at a time), and the whole-matrix path beside it at a size it can hold: peak memory and time.

Patch-NetVLAD's Nordland split is 27,592 queries x 27,592 database places (3 GB of float32
distances a copy); VPR-Bench's is 2,760 x 27,592. Each run is its own process, so its peak resident
memory (ru_maxrss) is its own: the blocked path (blocks.pair_distances + evaluate_in_blocks)
at --n-queries x --n-database, and both paths (matchers.match_distances on the whole matrix vs the
blocked one) at --side-by-side places, whose metrics must be identical.

Descriptors: seeded random scenes, database = scene + noise, queries = scene + more noise (D =
--dim, the full preset's ICA / whitened PCA length 512); truth: aligned within 7 places (the
Patch-NetVLAD protocol's).

    python -m benchmarks.speed.bench_large_pair [--n-queries 27592] [--n-database 27592] [--side-by-side 6000]

Writes benchmarks/results/bench_large_pair.json.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from benchmarks.common import load_note, where_measured
from tools.records import machine, write_result
from tools.repository import REPO

MATCHERS = ("single", "sequence")
TOLERANCE = 7  # Patch-NetVLAD's radius of 10 on (i, i) coordinates


def child(n_queries: int, n_database: int, dim: int, matcher: str, path: str, metric: str) -> dict:
    """One evaluation in this process: its wall seconds, peak resident memory and metrics."""
    from seasonloop.data.ground_truth import aligned_truth
    from seasonloop.evaluation.blocks import evaluate_in_blocks, pair_distances
    from seasonloop.evaluation.distances import distance_matrix
    from seasonloop.evaluation.matchers import match_distances
    from seasonloop.params.settings import EvaluateConfig, SequenceConfig

    rng = np.random.default_rng(0)
    scene = rng.normal(size=(max(n_queries, n_database), dim)).astype(np.float32)
    database = scene[:n_database] + 0.5 * rng.normal(size=(n_database, dim)).astype(np.float32)
    queries = scene[:n_queries] + 1.5 * rng.normal(size=(n_queries, dim)).astype(np.float32)
    del scene
    evaluate = EvaluateConfig(("a-b",), metric, (), "distance", 10, TOLERANCE, 10.0, (matcher,))
    sequence = SequenceConfig(
        length=10,
        v_min=0.8,
        v_max=1.2,
        v_steps=5,
        window=10,
        window_at_breaks="ignore",
        descriptor_window_at_breaks="shift",
    )
    baseline = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.perf_counter()
    truth = aligned_truth(np.arange(n_database), np.arange(n_queries), TOLERANCE)
    if path == "whole":
        metrics, _, _ = match_distances(
            distance_matrix(database, queries, metric=metric), truth, matcher, evaluate, sequence
        )
    else:
        metrics = evaluate_in_blocks(
            # never whole, as every pair over blocks.WHOLE_DISTANCES_MAX_BYTES is evaluated
            pair_distances(database, queries, metric, whole_max_bytes=0),
            n_database,
            truth,
            matcher,
            evaluate,
            sequence,
        ).metrics
    seconds = time.perf_counter() - start
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: kB
    return {"seconds": seconds, "peak_rss_mb": peak_mb, "before_mb": baseline / 1024, "metrics": metrics}


def run_child(n_queries: int, n_database: int, dim: int, matcher: str, path: str, metric: str) -> dict:
    spec = json.dumps([n_queries, n_database, dim, matcher, path, metric])
    result = subprocess.run(
        [sys.executable, "-m", __spec__.name, "--child", spec], cwd=REPO, capture_output=True, text=True, check=False
    )
    if result.returncode != 0:
        raise SystemExit(f"{path} {matcher} {n_queries} x {n_database} failed:\n{result.stderr[-2000:]}")
    record = json.loads(result.stdout.strip().splitlines()[-1])
    print(
        f"{path:>7} {matcher:>8} {n_queries:>6} x {n_database:<6}: {record['seconds']:7.1f} s, "
        f"peak {record['peak_rss_mb']:7.0f} MB (descriptors {record['before_mb']:.0f} MB before), "
        f"R@1 {record['metrics']['recall_at_1']:.4f}",
        flush=True,
    )
    return record


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-queries", type=int, default=27592)
    parser.add_argument("--n-database", type=int, default=27592)
    parser.add_argument("--side-by-side", type=int, default=6000, help="places of the whole-vs-blocked comparison")
    parser.add_argument("--dim", type=int, default=512)
    parser.add_argument("--metric", default="cosine")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(*json.loads(args.child))))
        return
    measured_on = machine()
    print(f"CPU: {measured_on['cpu']}")
    large = {
        matcher: run_child(args.n_queries, args.n_database, args.dim, matcher, "blocks", args.metric)
        for matcher in MATCHERS
    }
    side_by_side = {
        matcher: {
            path: run_child(args.side_by_side, args.side_by_side, args.dim, matcher, path, args.metric)
            for path in ("whole", "blocks")
        }
        for matcher in MATCHERS
    }
    for matcher, paths in side_by_side.items():
        same = paths["whole"]["metrics"] == paths["blocks"]["metrics"]
        print(
            f"{matcher} at {args.side_by_side} x {args.side_by_side}: blocks / whole peak memory "
            f"{paths['blocks']['peak_rss_mb'] / paths['whole']['peak_rss_mb']:.2f}, time "
            f"{paths['blocks']['seconds'] / paths['whole']['seconds']:.2f}, metrics identical: {same}"
        )
        if not same:
            raise SystemExit(f"{matcher}: the blocked metrics differ from the whole matrix's")
    note = load_note(measured_on)
    if note:
        print(note)
    record = {
        "size": [args.n_queries, args.n_database],
        "dim": args.dim,
        "metric": args.metric,
        "tolerance": TOLERANCE,
        "large": large,
        "side_by_side_places": args.side_by_side,
        "side_by_side": side_by_side,
        "load_note": note,
    }
    print(f"wrote {write_result('bench_large_pair', record, measured_on)}")


def _bench_large_pair(path: Path) -> str:
    """benchmarks/speed/bench_large_pair.py's record: each run's seconds and peak memory, the blocked
    path at the protocols' size and both paths side by side at a size the whole matrix fits."""
    record = json.loads(path.read_text())
    lines = [
        "| path | matcher | queries x database | seconds | peak memory MB (before it: descriptors, imports) | R@1 |",
        "|---|---|---|---|---|---|",
    ]
    side = record["side_by_side_places"]
    runs = [(record["size"], "blocks", matcher, run) for matcher, run in record["large"].items()]
    runs += [
        ([side, side], path_name, matcher, run)
        for matcher, paths in record["side_by_side"].items()
        for path_name, run in paths.items()
    ]
    for (n_queries, n_database), path_name, matcher, run in runs:
        lines.append(
            f"| {path_name} | {matcher} | {n_queries:,} x {n_database:,} | {run['seconds']:.1f} "
            f"| {run['peak_rss_mb']:,.0f} ({run['before_mb']:,.0f}) | {run['metrics']['recall_at_1']:.4f} |"
        )
    same = all(paths["whole"]["metrics"] == paths["blocks"]["metrics"] for paths in record["side_by_side"].values())
    return (
        "\n".join(lines)
        + f"\n\nD = {record['dim']}, {record['metric']} distance, correct within {record['tolerance']} places; "
        + f"metrics of the two paths identical at {side:,} x {side:,}: {same}. {where_measured(record)}\n"
    )


# docs/write_tables.py's table of this benchmark's record: name -> (record, snapshot, how it is written)
TABLES = {"bench_large_pair": ("benchmarks/results/bench_large_pair.json", "bench_large_pair.json", _bench_large_pair)}


if __name__ == "__main__":
    main()
