"""Why does a slowly drifting success rate break the level at 1,800 queries: the rule, or its estimate of the runs?

    python -m benchmarks.studies.check_drift [--replicates R] [--seed S]

check_calibration's out-of-sample drift (a latent AR(1) of correlation length DRIFT_QUERIES
queries, DRIFT_SHARE of its variance; learners sharing the default run's part) breaks the 95%
interval of a fraction at every n the docs report. This study separates the two things the
interval rests on (seasonloop.significance.intervals): the degrees-of-freedom rule, given the
outcomes' true runs, and the runs as the pipeline estimates them from one route's outcomes.
At each n and fraction p it computes
- the outcomes' true persistence ω and inflation (1 + 2 Σ r_k), from the latent's autocorrelation
  through the thresholded normal (check_calibration.binary_correlation), and the ν they give;
- the coverage of the interval with those true runs (`Runs(ω, inflation)`: the rule alone);
- the coverage with the runs estimated from each route (`persistence`, as the evaluate stage does
  for a run with one pair), the share of routes refused, and the 5th, 50th and 95th percentiles of
  the estimated ν;
- the same, the runs pooled over POOLED series of one pair's learners (as the comparisons of a
  table pool theirs).
Seeded; the same arguments give the same record. Writes benchmarks/results/check_drift.json;
docs/write_tables.py renders it into docs/statistics.md.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from benchmarks.common import save_and_report
from benchmarks.studies.check_calibration import (
    DRIFT_QUERIES,
    DRIFT_SHARE,
    Dependence,
    _rate_cell,
    binary_correlation,
    covers,
    drawn,
    rate,
)
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import Runs, cosine_degrees, fraction_interval, persistence
from tools.records import machine
from tools.repository import REPO

SIZES = (158, 1800)
FRACTIONS = (0.05, 0.2, 0.5, 0.95)
POOLED = 8  # a table's learners
LAGS = 20_000  # the true runs' sum: the latent's correlation is 0.3 * 0.99^k, below 1e-88 there


def true_runs(dependence: Dependence, p: float) -> Runs:
    """The outcomes' persistence ω and inflation at fraction p, from the latent's autocorrelation."""
    lags = np.arange(1, LAGS)
    correlation = binary_correlation(dependence.a * dependence.phi**lags, p)
    inflation = 1 + 2 * float(correlation.sum())
    return Runs(2 * float((lags**2 * correlation).sum()) / inflation, inflation)


def cell(settings: StatisticsConfig, dependence: Dependence, n: int, p: float, replicates: int, seed: int) -> dict:
    """The coverage with the true runs, with each route's own and with POOLED series' pooled."""
    truth = true_runs(dependence, p)
    every = np.ones(n, bool)
    known, own, pooled, degrees = [], [], [], []
    rng = np.random.default_rng([seed, n, round(1000 * p)])
    for learners in drawn(rng, replicates, n, [p] * POOLED, dependence):
        for r in range(len(learners[0])):
            series = learners[0][r]
            estimated = persistence([series])
            degrees.append(cosine_degrees(n, settings, estimated.omega))
            known.append(covers(fraction_interval(series, every, settings, runs=truth)["route"], p))
            own.append(covers(fraction_interval(series, every, settings, runs=estimated)["route"], p))
            shared = persistence(learner[r] for learner in learners)
            pooled.append(covers(fraction_interval(series, every, settings, runs=shared)["route"], p))
    return {
        "n": n,
        "p": p,
        "omega": truth.omega,
        "inflation": truth.inflation,
        "degrees": cosine_degrees(n, settings, truth.omega),
        "true_runs": rate(known),
        "own_runs": rate(own),
        "pooled_runs": rate(pooled),
        "estimated_degrees": {f"{q}": float(np.percentile(degrees, q)) for q in (5, 50, 95)},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--replicates", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    import yaml

    settings = StatisticsConfig.from_params(yaml.safe_load((REPO / "params.yaml").read_text()))
    # the default run's learners' shared part, as check_calibration's drift model has it
    record_path = REPO / "benchmarks/results/check_calibration_out_of_sample.json"
    model = json.loads(record_path.read_text())["models"][f"drift over {DRIFT_QUERIES}"]
    dependence = Dependence(model["a"], model["phi"], model["share"])
    assert math.isclose(dependence.a, DRIFT_SHARE), f"{record_path}: another drift than check_calibration's"
    rows = []
    for n in SIZES:
        for p in FRACTIONS:
            rows.append(cell(settings, dependence, n, p, args.replicates, args.seed))
            row = rows[-1]
            print(
                f"n={n} p={p}: nu {row['degrees']} (omega {row['omega']:.0f}); coverage true runs "
                f"{row['true_runs']['rate']}, own {row['own_runs']['rate']} ({row['own_runs']['refused']} refused), "
                f"pooled {row['pooled_runs']['rate']}; estimated nu {row['estimated_degrees']}",
                flush=True,
            )
    answered = [row["true_runs"]["rate"] for row in rows if row["true_runs"]["rate"] is not None]
    record = {
        "replicates": args.replicates,
        "seed": args.seed,
        "dependence": {"a": dependence.a, "phi": dependence.phi, "share": dependence.share},
        "correlation_length": DRIFT_QUERIES,
        "pooled": POOLED,
        "statistics": {key: getattr(settings, key) for key in ("level", "degrees_scale", "persistence_scale")},
        "rows": rows,
        "headline": f"with the true runs the interval covers {min(answered):.3f}-{max(answered):.3f} where it "
        f"answers; with runs estimated from the route, see the table",
    }
    save_and_report("check_drift", record, machine())


def _drift_table(path: Path) -> str:
    """Coverage of a fraction's 95% interval under the drift: with the true runs, and estimated."""
    record = json.loads(path.read_text())
    lines = [
        "| n | p | ν of the true runs | true runs | runs of the route | runs of 8 series pooled "
        "| estimated ν (5th, 50th, 95th percentile) |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in record["rows"]:
        spread = ", ".join(f"{row['estimated_degrees'][q]:.0f}" for q in ("5", "50", "95"))
        lines.append(
            f"| {row['n']} | {row['p']} | {row['degrees']} | {_rate_cell(row['true_runs'])} "
            f"| {_rate_cell(row['own_runs'])} | {_rate_cell(row['pooled_runs'])} | {spread} |"
        )
    error = (0.95 * 0.05 / record["replicates"]) ** 0.5
    legend = (
        f"A latent of correlation length {record['correlation_length']} queries, "
        f"{100 * record['dependence']['a']:.0f}% of its variance; {record['replicates']} simulated routes a cell "
        f"(Monte Carlo standard error {100 * error:.1f} points at 95%); degrees_scale {record['statistics']['degrees_scale']}, "
        f"persistence_scale {record['statistics']['persistence_scale']}; refused: fewer than 2 degrees of "
        'freedom ("runs too long for this many queries"), the rate is the answered routes\'.'
    )
    return "\n".join(lines) + "\n\n" + legend + "\n"


TABLES = {"calibration_drift": ("benchmarks/results/check_drift.json", "check_drift.json", _drift_table)}


if __name__ == "__main__":
    main()
