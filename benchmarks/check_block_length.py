"""How long the bootstrap's blocks must be: how far along the route a query's success tells about its
neighbours', and how wide the fraction-correct intervals come out at each block length.

    python benchmarks/check_block_length.py [WORKSPACE]   (default: this clone, after `dvc repro`)

Reads every evaluation's per-query outcomes (WORKSPACE/data/outcomes/<learner>/<pair><suffix>.csv,
route order) and prints, for single images and `+seq` apart: the mean autocorrelation of the
correct/wrong series at lags 1, 2, 5, 10, 20 and 40 queries (0: neighbours tell nothing), and the
mean width (points) of the 95% percentile interval at block lengths 1 (every query independent:
the binomial's case) to 40, beside the Wilson interval's. Writes
benchmarks/results/check_block_length.json. The seed, level and resamples are WORKSPACE's
params.yaml `statistics`; only the block length varies.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np
import yaml

from _bench_common import machine, write_result
from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import block_resampling, fraction_interval

LAGS = (1, 2, 5, 10, 20, 40)
BLOCK_LENGTHS = (1, 5, 10, 20, 40)


def autocorrelation(correct: np.ndarray, lag: int) -> float | None:
    """Lag-`lag` autocorrelation of a 0/1 series (None when it is constant or too short)."""
    values = correct.astype(np.float64) - correct.mean()
    variance = float(np.mean(values * values))
    if variance == 0 or lag >= len(values):
        return None
    return float(np.mean(values[:-lag] * values[lag:]) / variance)


def interval_width(correct: np.ndarray, settings: StatisticsConfig, kind: str) -> float:
    every = np.ones_like(correct)
    interval = fraction_interval(correct, every, block_resampling(len(correct), settings), settings)[kind]
    return 100 * (interval["high"] - interval["low"])


def measure(workspace: Path) -> dict:
    """Per matcher ("single", "+seq"): mean autocorrelation per lag, mean interval width per block length."""
    params = yaml.safe_load((workspace / "params.yaml").read_text())
    settings = StatisticsConfig.from_params(params)
    series: dict[str, list[np.ndarray]] = {"single": [], "+seq": []}
    for path in sorted((workspace / "data" / "outcomes").glob("*/*.csv")):
        series["+seq" if path.stem.endswith("+seq") else "single"].append(QueryOutcomes.read_csv(path).correct)
    if not series["single"]:
        raise SystemExit(f"{workspace / 'data/outcomes'}: no outcomes (run `dvc repro` there first)")
    record = {}
    for matcher, runs in series.items():
        correlations = {lag: [autocorrelation(run, lag) for run in runs] for lag in LAGS}
        widths = {
            length: float(
                np.mean(
                    [
                        interval_width(run, dataclasses.replace(settings, block_length=length), "block_bootstrap")
                        for run in runs
                    ]
                )
            )
            for length in BLOCK_LENGTHS
        }
        record[matcher] = {
            "evaluations": len(runs),
            "autocorrelation": {
                str(lag): float(np.mean([value for value in values if value is not None]))
                for lag, values in correlations.items()
            },
            "interval_width_points": {str(length): width for length, width in widths.items()},
            "wilson_width_points": float(np.mean([interval_width(run, settings, "wilson") for run in runs])),
        }
    return {"workspace_params": dataclasses.asdict(settings), "by_matcher": record}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("workspace", type=Path, nargs="?", default=Path("."))
    args = parser.parse_args()
    measured_on = machine()
    record = measure(args.workspace)
    for matcher, row in record["by_matcher"].items():
        print(f"{matcher} ({row['evaluations']} evaluations)")
        print(
            "  autocorrelation at lag "
            + ", ".join(f"{lag}: {value:.2f}" for lag, value in row["autocorrelation"].items())
        )
        print(
            "  95% interval width (points) at block length "
            + ", ".join(f"{length}: {width:.1f}" for length, width in row["interval_width_points"].items())
            + f"; Wilson {row['wilson_width_points']:.1f}"
        )
    print(f"wrote {write_result('check_block_length', record, measured_on)}")


if __name__ == "__main__":
    main()
