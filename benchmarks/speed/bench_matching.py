"""Matching one full-scale test pair: distance_matrix + best_matches + evaluate_pair vs a
straightforward per-query Python loop (numpy per query), side by side on the same descriptors.

Descriptors: seeded random database vectors, queries = database + noise (so best matches are
mostly but not always right), 3569 x 3569 places of D = 200 by default (the study's test set, the
pca learner's descriptor length).

    python -m benchmarks.speed.bench_matching [--n-places 3569] [--dim 200] [--metric cosine]

Writes benchmarks/results/bench_matching.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse

import numpy as np

from benchmarks.common import headline_table, load_note, save_and_report, timed
from seasonloop.evaluation.distances import METRICS, best_matches, distance_matrix
from seasonloop.evaluation.metrics import evaluate_pair
from tools.records import machine


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-places", type=int, default=3569)
    parser.add_argument("--dim", type=int, default=200)
    parser.add_argument("--metric", default="cosine", choices=METRICS)
    parser.add_argument(
        "--noise", type=float, default=3.0, help="query noise, in units of the descriptor spread (3: ~85%% correct)"
    )
    parser.add_argument("--repeats", type=int, default=3, help="the fastest of this many runs is reported")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def loop_best_matches(database: np.ndarray, queries: np.ndarray, metric: str) -> np.ndarray:
    """Best database index per query, one query at a time (float64, rounded to float32 like
    distance_matrix's output so ties resolve the same way)."""
    database = database.astype(np.float64)
    if metric == "cosine":
        database = database / np.linalg.norm(database, axis=1, keepdims=True)
    best = np.empty(len(queries), dtype=np.int64)
    for index, query in enumerate(queries.astype(np.float64)):
        if metric == "cosine":
            distances = np.clip(1.0 - database @ (query / np.linalg.norm(query)), 0.0, 2.0)
        else:
            distances = np.sqrt(((database - query) ** 2).sum(axis=1))
        best[index] = np.argmin(distances.astype(np.float32))
    return best


def fastest(function, repeats: int):
    """(result of the last run, fastest wall seconds of `repeats` runs)."""
    runs = [timed(function) for _ in range(repeats)]
    return runs[-1][0], min(seconds for _, seconds in runs)


def main() -> None:
    args = parse_args()
    measured_on = machine()
    rng = np.random.default_rng(args.seed)
    database = rng.normal(size=(args.n_places, args.dim)).astype(np.float32)
    queries = (database + args.noise * rng.normal(size=database.shape)).astype(np.float32)
    places = np.arange(args.n_places)
    print(f"{args.n_places} queries x {args.n_places} database, D = {args.dim}, metric {args.metric}")

    distances, distance_seconds = fastest(lambda: distance_matrix(database, queries, args.metric), args.repeats)
    (best, _), best_seconds = fastest(lambda: best_matches(distances), args.repeats)
    (metrics, _), evaluate_seconds = fastest(
        lambda: evaluate_pair(distances, places, places, tolerance=0), args.repeats
    )
    vectorised_seconds = distance_seconds + best_seconds + evaluate_seconds
    loop_best, loop_seconds = fastest(lambda: loop_best_matches(database, queries, args.metric), args.repeats)
    identical = bool(np.array_equal(best, loop_best))
    loop_total = loop_seconds + evaluate_seconds  # the loop still needs the PR arithmetic
    print(
        f"  distance_matrix {distance_seconds:.3f} s, best_matches {best_seconds:.3f} s, "
        f"evaluate_pair {evaluate_seconds:.3f} s (its own best matches, PR curve, recall@N)"
    )
    print(
        f"  vectorised total {vectorised_seconds:.3f} s; per-query loop best matches {loop_seconds:.3f} s "
        f"(+ evaluate_pair {loop_total:.3f} s); loop / vectorised {loop_total / vectorised_seconds:.1f}x"
    )
    print(f"  best matches identical: {identical}; fraction correct {metrics['fraction_correct']:.4f}")

    note = load_note(measured_on)
    record = {
        "args": vars(args),
        "distance_matrix_seconds": distance_seconds,
        "best_matches_seconds": best_seconds,
        "evaluate_pair_seconds": evaluate_seconds,
        "vectorised_seconds": vectorised_seconds,
        "loop_best_matches_seconds": loop_seconds,
        "loop_total_seconds": loop_total,
        "speedup": loop_total / vectorised_seconds,
        "identical_best_matches": identical,
        "fraction_correct": metrics["fraction_correct"],
        "load_note": note,
    }
    record["headline"] = (
        f"matching a {args.n_places} x {args.n_places} pair (D={args.dim}) takes {vectorised_seconds:.3f} s "
        f"(distances + best matches + evaluation); a per-query loop takes {loop_total / vectorised_seconds:.1f}x "
        f"as long; best matches identical: {identical}"
    )
    save_and_report("bench_matching", record, measured_on)
    if not identical:
        raise SystemExit("best matches differ between the vectorised and the loop implementation")


# docs/write_tables.py's table of this benchmark's record: name -> (record, snapshot, how it is written)
TABLES = {"bench_matching": ("benchmarks/results/bench_matching.json", "bench_matching.json", headline_table)}


if __name__ == "__main__":
    main()
