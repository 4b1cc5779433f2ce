"""What can a "no difference" hide? The smallest difference the paired test finds 80% of the time.

    python -m benchmarks.studies.check_power --real REAL_DIR [--workspace DIR] [--replicates R]

A table of the docs compares the default run's learners on one pair (`learners:` of the workspace's
params.yaml), every two of them, Holm-corrected together.
For each n the docs report (the real half's and the default route's queries a pair on the study's
split, about every place of either, five routes of every place pooled) and each dependence fitted
to a run's own outcomes (benchmarks.studies.check_calibration.measure_dependence: the default run's
single images and +seq, the real run's every matcher), one learner is `d` points ahead of the
other, equal learners at fraction p = 0.5 (where a fraction's variance is largest) and 0.8; the power is how
often its comparison with one of them is called, the right way, under Holm over the table
(the verdict a reader sees). The smallest d on the grid found at least 80% of the time is what a
"no difference" there can still hide; a "none on the grid" says a gap of DIFFERENCES[-1] points
can hide. Seeded (--seed); the same arguments give the same record.

Writes benchmarks/results/check_power.json; docs/write_tables.py renders it into docs/statistics.md.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from benchmarks.studies.check_calibration import (
    Dependence,
    matcher_of,
    measure_dependence,
    power_cell,
    read_evaluations,
)
from seasonloop.params.settings import StatisticsConfig

DIFFERENCES = (0.03, 0.05, 0.075, 0.10, 0.15, 0.20, 0.30, 0.40)
FRACTIONS = (0.5, 0.8)
# (queries a route, routes pooled): the study's split on the real half and the default route,
# every place of either, five routes of every place
SIZES = ((147, 1), (158, 1), (1800, 1), (1800, 5))
FOUND = 0.8  # the power a difference needs to count as one the test finds


def comparisons(learners: int) -> int:
    """A learner table's comparisons: every two of its learners."""
    return learners * (learners - 1) // 2


def smallest_found(powers: dict[str, float | None]) -> float | None:
    """The smallest difference (keys: differences as text) whose power is at least FOUND, with every
    larger one found too (None: none on the grid)."""
    ordered = sorted(powers, key=float)
    for k, difference in enumerate(ordered):
        if all((powers[d] or 0.0) >= FOUND for d in ordered[k:]):
            return float(difference)
    return None


def run(
    settings: StatisticsConfig, dependences: dict[str, Any], replicates: int, seed: int, learners: int
) -> list[dict]:
    rows = []
    for k, (name, dependence) in enumerate(dependences.items()):
        for n, routes in SIZES:
            for p in FRACTIONS:
                started = time.perf_counter()
                rng = np.random.default_rng([seed, k, n, routes, int(100 * p)])
                cells = {
                    f"{d:.3f}": power_cell(rng, settings, n, p, d, dependence, replicates, learners, routes)
                    for d in DIFFERENCES
                }
                holm = {d: cell["power_holm"]["rate"] for d, cell in cells.items()}
                row = {
                    "dependence": name,
                    "n": n,
                    "routes": routes,
                    "p": p,
                    "cells": cells,
                    "smallest_found": smallest_found(holm),
                    "seconds": round(time.perf_counter() - started, 1),
                }
                rows.append(row)
                powers = " ".join(f"{float(d):.3f}: {'refused' if v is None else f'{v:.2f}'}" for d, v in holm.items())
                print(
                    f"{name:>14} n={n:>5} x{routes} p={p}: smallest found {row['smallest_found']}  ({powers})",
                    flush=True,
                )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workspace", type=Path, default=Path("."), help="the default run's folder")
    parser.add_argument("--real", type=Path, required=True, help="a run on real frames (after `dvc repro`)")
    parser.add_argument("--replicates", type=int, default=400)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    from benchmarks.common import save_and_report
    from tools.records import machine

    params = yaml.safe_load((args.workspace / "params.yaml").read_text())
    settings = StatisticsConfig.from_params(params)
    learners = len(params["learners"])  # a table of learners x (learners - 1) / 2 comparisons
    default = measure_dependence(read_evaluations(args.workspace))
    real = measure_dependence(read_evaluations(args.real), matcher_of)
    dependences = {
        **{f"default {kind}": Dependence(**fit["dependence"]) for kind, fit in default.items()},
        **{f"real {kind}": Dependence(**fit["dependence"]) for kind, fit in real.items()},
    }
    rows = run(settings, dependences, args.replicates, args.seed, learners)
    record = {
        "replicates": args.replicates,
        "seed": args.seed,
        "statistics": {key: getattr(settings, key) for key in ("level", "degrees_scale", "persistence_scale", "alpha")},
        "differences": DIFFERENCES,
        "table_learners": learners,
        "fitted": {"default": default, "real": real},
        "workspaces": {"default": str(args.workspace), "real": str(args.real)},
        "rows": rows,
        "headline": f"smallest difference found 80% of the time under Holm over {comparisons(learners)}: "
        + ", ".join(
            f"{row['dependence']} n={row['n']}x{row['routes']} p={row['p']}: {row['smallest_found']}" for row in rows
        ),
    }
    save_and_report("check_power", record, machine())


def _power_table(path: Path) -> str:
    """The smallest difference found 80% of the time under Holm, per dependence, n and fraction."""
    record = json.loads(path.read_text())
    rows = record["rows"]
    columns = [(n, routes) for n, routes in SIZES if any(r["n"] == n and r["routes"] == routes for r in rows)]
    header = [f"{n} queries" if routes == 1 else f"{routes} x {n} queries" for n, routes in columns]
    lines = ["| dependence | p | " + " | ".join(header) + " |", "|---|---|" + "---|" * len(columns)]
    for name in dict.fromkeys(row["dependence"] for row in rows):
        for p in record.get("fractions", FRACTIONS):
            cells = []
            for n, routes in columns:
                row = next(
                    (r for r in rows if (r["dependence"], r["n"], r["routes"], r["p"]) == (name, n, routes, p)), None
                )
                found = None if row is None else row["smallest_found"]
                cells.append(f"> {100 * max(record['differences']):.0f}" if found is None else f"{100 * found:g}")
            lines.append(f"| {name} | {p} | " + " | ".join(cells) + " |")
    legend = (
        f"Points of fraction correct; one learner that far ahead of {record['table_learners'] - 1} equal others, "
        f"found the right way under Holm over the table of {comparisons(record['table_learners'])} at alpha "
        f"{record['statistics']['alpha']} in at least 80% of "
        f"{record['replicates']} simulated routes (grid: {', '.join(f'{100 * d:g}' for d in record['differences'])} "
        f"points; '> {100 * max(record['differences']):.0f}': none on the grid). A \"no difference\" in such a cell "
        "can hide a gap up to about this size."
    )
    return "\n".join(lines) + "\n\n" + legend + "\n"


TABLES = {"calibration_power_holm": ("benchmarks/results/check_power.json", "check_power.json", _power_table)}


if __name__ == "__main__":
    main()
