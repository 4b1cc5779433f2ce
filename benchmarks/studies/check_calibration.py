"""Do the intervals cover what they say, and does "significant" err as often as alpha says?

    python -m benchmarks.studies.check_calibration [--workspace DIR] [--replicates R] [--small]
    python -m benchmarks.studies.check_calibration --means [--workspace DIR] [--replicates R]
    python -m benchmarks.studies.check_calibration --real REAL_DIR [--workspace DIR] [--replicates R]

Simulates per-query outcomes with a known answer and the dependence of a run's own outcomes, and
runs the project's statistics on them (seasonloop.significance, the code every stage uses):
- the dependence: each run's correct/wrong series (WORKSPACE/data/outcomes/<learner>/<pair><suffix>.csv,
  single images and `+seq` apart) is fitted by a thresholded Gaussian process: a query is correct
  when a latent z_t is below the fraction's quantile, z_t = sqrt(a) y_t + sqrt(1 - a) e_t, y an
  AR(1) of coefficient phi, e white noise (a nugget): (a, phi) chosen so that the series'
  autocorrelation at lags 1-10 is the run's mean. Learners of one pair share a part `share` of
  their latent (a place hard for one is hard for the others), fitted to the run's mean correlation
  between two learners' outcomes on the same queries;
- on a grid of n (queries a route), fraction p, dependence and routes (1, or 5 pooled), R routes
  each: the real coverage of the 95% interval of a fraction (the evaluate stage's, the runs'
  persistence pooled over the grid's `pooled_pairs` pairs as the evaluate stage pools a run's
  pairs), with Wilson's (independent queries) beside it; the real false-positive rate of the paired
  test (equal learners, the persistence pooled over the table's comparisons as the compare stage
  pools it) per comparison, and per table (7 equal learners, 21 comparisons, Holm: the family the
  legend names); its power at differences of 3, 5 and 10 points, alone and under Holm over the
  table, and the coverage of the difference's interval there;
- every statistic at the params' statistics settings, and at LLSW's published degrees_scale 0.4
  beside them (the rule the project's scale departs from).
Monte Carlo error: a rate c measured on R routes has standard error sqrt(c (1 - c) / R) (0.49
points at c = 0.95, R = 2000). Seeded (--seed); the same arguments give the same record.

--means checks the interval of a fraction averaged over a run's six season pairs instead: six
series on the same places, each pair's latent sharing a part with the others' (fitted to the run's
mean correlation between two pairs' outcomes of one learner), fractions as different as the
default run's or all equal.

--real checks the same statistics out of sample: on dependence models the degrees rule was not
chosen on (out_of_sample_models: blocks of 20-80 queries all right or all wrong, two-state Markov
chains, a slowly varying success rate, learners that share most failures, and the thresholded AR
fitted to a run on real frames, every matcher apart), at the n the docs report.

Writes benchmarks/results/check_calibration.json (--means: check_calibration_means.json; --real:
check_calibration_out_of_sample.json);
docs/write_tables.py renders them into docs/statistics.md. --small: the grid the tests run (seconds).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import time
from collections.abc import Callable, Sequence
from functools import partial
from itertools import combinations
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from scipy import optimize, signal
from scipy.special import ndtri

from benchmarks.cells import Cells, source_hash
from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import fraction_interval, min_queries, persistence
from seasonloop.significance.means import mean_interval
from seasonloop.significance.tables import table_verdicts

LAGS = tuple(range(1, 11))
FULL_GRID = {
    "n": (20, 50, 100, 158, 400, 1000, 3259, 27592),
    "p": (0.05, 0.2, 0.5, 0.8, 0.95),
    "differences": (0.03, 0.05, 0.10),
    "table_learners": 7,
    "pooled_routes": 5,
    "pooled_n": (158, 1000),
    "pooled_pairs": 6,  # the default run's pairs: an evaluation's persistence is pooled over them
}
SMALL_GRID = {
    "n": (20, 158),
    "p": (0.2, 0.5),
    "differences": (0.10,),
    "table_learners": 4,
    "pooled_routes": 3,
    "pooled_n": (158,),
    "pooled_pairs": 6,
}
LLSW_SCALE = 0.4  # Lazarus, Lewis, Stock and Watson (2018)'s rule: nu = 0.4 n^(2/3)
# LLSW's rule beside the params' on the n where the two differ most (it is there for comparison)
LLSW_N = (100, 158, 400, 1000)


@dataclasses.dataclass(frozen=True)
class Dependence:
    """The latent process of a learner's outcomes along a route (module doc)."""

    a: float  # the AR(1) part's share of the latent variance
    phi: float  # its lag-1 coefficient
    share: float  # the latent part two learners of one pair have in common


INDEPENDENT = Dependence(0.0, 0.0, 0.0)


@dataclasses.dataclass(frozen=True)
class Markov:
    """Each learner's outcomes a two-state Markov chain (runs of geometric length) whose lag-1
    autocorrelation is `correlation` at every fraction; learners independent of each other. Not
    the family the degrees rule was chosen on (a thresholded AR with a nugget): out of sample."""

    correlation: float

    def learners(
        self, rng: np.random.Generator, replicates: int, n: int, fractions: Sequence[float]
    ) -> list[np.ndarray]:
        drawn = []
        for p in fractions:
            # P(right -> right) and P(wrong -> wrong) whose chain has stationary p and lag-1 correlation
            stay_right, stay_wrong = p + (1 - p) * self.correlation, (1 - p) + p * self.correlation
            uniform = rng.random((replicates, n))
            state = np.empty((replicates, n), bool)
            state[:, 0] = uniform[:, 0] < p  # stationary from the start
            for t in range(1, n):
                previous = state[:, t - 1]
                state[:, t] = np.where(previous, uniform[:, t] < stay_right, uniform[:, t] >= stay_wrong)
            drawn.append(state)
        return drawn


@dataclasses.dataclass(frozen=True)
class Blocks:
    """Blocks of `shortest` to `longest` consecutive queries (uniform), each all right or all wrong:
    a train passing a snowy stretch. The learners of a pair share the blocks (the stretch), and each
    block's outcome is the pair's common draw with probability `share`, else the learner's own."""

    shortest: int
    longest: int
    share: float

    def learners(
        self, rng: np.random.Generator, replicates: int, n: int, fractions: Sequence[float]
    ) -> list[np.ndarray]:
        most = n // self.shortest + 2
        lengths = rng.integers(self.shortest, self.longest + 1, (replicates, most))
        # a random start inside the first block: the route does not begin where a block does
        offset = rng.integers(0, self.longest, replicates)
        ends = np.cumsum(lengths, axis=1)
        index = np.stack([np.searchsorted(ends[r], np.arange(n) + offset[r], side="right") for r in range(replicates)])
        common = rng.random((replicates, most))
        drawn = []
        for p in fractions:
            copied = rng.random((replicates, most)) < self.share
            draw = np.where(copied, common, rng.random((replicates, most)))
            drawn.append(np.take_along_axis(draw < p, index, axis=1))
        return drawn


def autocorrelation(series: np.ndarray, lag: int) -> float | None:
    """Lag-`lag` autocorrelation of a 0/1 series (None when it is constant or too short)."""
    values = series.astype(np.float64) - series.mean()
    variance = float(np.mean(values * values))
    if variance == 0 or lag >= len(values):
        return None
    return float(np.mean(values[:-lag] * values[lag:]) / variance)


def binary_correlation(latent: np.ndarray, p: float) -> np.ndarray:
    """The correlation of two outcomes 1[z < Phi^-1(p)] whose latents z correlate `latent`:
    (P(both) - p^2) / (p (1 - p)), P(both) from the bivariate normal's density integrated over the
    correlation (Gauss-Legendre, exact to ~1e-10 here)."""
    c = float(ndtri(p))
    nodes, weights = np.polynomial.legendre.leggauss(64)
    latent = np.atleast_1d(np.asarray(latent, np.float64))
    t = (nodes[None, :] + 1) / 2 * latent[:, None]  # (k, nodes) in [0, latent]
    density = np.exp(-c * c / (1 + t)) / (2 * np.pi * np.sqrt(1 - t * t))
    return (density * weights).sum(axis=1) * latent / 2 / (p * (1 - p))


def latent_share(correlation: float, p: float) -> float:
    """The latent correlation whose outcomes at fraction p correlate `correlation` (0 for none or less)."""
    if correlation <= 0:
        return 0.0
    return float(optimize.brentq(lambda s: binary_correlation(s, p)[0] - correlation, 0.0, 0.999))


def fit_dependence(series: Sequence[np.ndarray], pairs_of_learners: Sequence[tuple[np.ndarray, np.ndarray]]) -> dict:
    """Dependence (a, phi, share) whose outcomes have the series' mean autocorrelation at LAGS and the
    learner pairs' mean correlation, at the series' mean fraction correct."""
    kept = [s for s in series if 0 < s.mean() < 1]
    measured = np.array([np.mean([autocorrelation(s, lag) for s in kept]) for lag in LAGS])
    p = float(np.clip(np.mean([s.mean() for s in kept]), 0.02, 0.98))

    def misfit(x: np.ndarray) -> float:
        a, phi = x
        return float(np.sum((binary_correlation(a * phi ** np.array(LAGS), p) - measured) ** 2))

    fitted = optimize.minimize(misfit, x0=[0.5, 0.7], bounds=[(0.0, 0.999), (0.0, 0.995)], method="L-BFGS-B")
    a, phi = (float(v) for v in fitted.x)
    between = [
        float(np.corrcoef(first, second)[0, 1])
        for first, second in pairs_of_learners
        if 0 < first.mean() < 1 and 0 < second.mean() < 1
    ]
    cross = float(np.mean(between)) if between else 0.0
    share = latent_share(cross, p)
    return {
        "dependence": dataclasses.asdict(Dependence(a, phi, share)),
        "evaluations": len(kept),
        "mean_fraction_correct": p,
        "autocorrelation_measured": dict(zip(map(str, LAGS), measured.round(4).tolist())),
        "autocorrelation_fitted": dict(
            zip(map(str, LAGS), binary_correlation(a * phi ** np.array(LAGS), p).round(4).tolist())
        ),
        "learner_correlation_measured": cross,
    }


Evaluation = tuple[str, str, QueryOutcomes]  # (learner, result name <pair><suffix>, its outcomes)


def read_evaluations(workspace: Path) -> list[Evaluation]:
    """Every evaluation's per-query outcomes in WORKSPACE/data/outcomes/<learner>/<name>.csv."""
    folder = workspace / "data" / "outcomes"
    read = [(path.parent.name, path.stem, QueryOutcomes.read_csv(path)) for path in sorted(folder.glob("*/*.csv"))]
    if not read:
        raise SystemExit(f"{folder}: no per-query outcomes (run `dvc repro` there first)")
    return read


def kind_of(name: str) -> str:
    """ "+seq" for a sequence matcher's result name, else "single"."""
    return "+seq" if name.endswith("+seq") else "single"


def matcher_of(name: str) -> str:
    """The matcher of a result name: "single", "+seq", "+delta" or "+smoothed" (every kind of
    evaluation apart, for the out-of-sample fit to real frames)."""
    suffix = suffix_of(name)
    return "+" + suffix.rsplit("+", 1)[1] if "+" in suffix else "single"


def suffix_of(name: str) -> str:
    """A result name's suffix ("", "+seq", "@cityblock", ...): a pair's name has neither @ nor +."""
    pair = name.split("@")[0].split("+")[0]
    return name[len(pair) :]


def pair_share(evaluations: Sequence[Evaluation], kind: str, p: float) -> dict[str, float]:
    """The latent share of two season pairs' outcomes of one learner and matcher on the same places
    (fitted, at fraction p, to their mean correlation in the evaluations)."""
    series: dict[tuple[str, str], list[QueryOutcomes]] = {}
    for learner, name, outcomes in evaluations:
        if kind_of(name) == kind:
            series.setdefault((learner, suffix_of(name)), []).append(outcomes)
    between = [
        float(np.corrcoef(a.correct, b.correct)[0, 1])
        for outcomes in series.values()
        for a, b in combinations(outcomes, 2)
        if np.array_equal(a.query_place, b.query_place) and 0 < a.correct.mean() < 1 and 0 < b.correct.mean() < 1
    ]
    cross = float(np.mean(between))
    return {"pair_correlation_measured": cross, "pair_share": latent_share(cross, p), "pairs_compared": len(between)}


def means_cell(rng, settings, n, fractions, dependence, share, replicates) -> dict[str, Any]:
    """Coverage of the interval of the mean over len(fractions) pairs on the same n places, each
    pair's latent sharing `share` with the others' (seasonloop.significance.means)."""
    truth, places, covered = float(np.mean(fractions)), np.arange(n), []
    for chunk in chunks(replicates, n * len(fractions)):
        common = latent(rng, chunk, n, dependence)
        pairs = [
            (math.sqrt(share) * common + math.sqrt(1 - share) * latent(rng, chunk, n, dependence)) < ndtri(p)
            for p in fractions
        ]
        for r in range(chunk):
            interval = mean_interval([pair[r] for pair in pairs], [places] * len(pairs), settings)
            covered.append(covers(interval, truth))
    return rate(covered)


MEANS_N = (158, 3259)
# the default run's ica row, single images, roughly; and six pairs alike
MEANS_FRACTIONS = {"like the default run": (0.9, 0.9, 0.85, 0.35, 0.25, 0.1), "all 0.5": (0.5,) * 6}


def calibrate_means(settings, dependences, shares, replicates, seed, cells: Cells | None = None) -> list[dict]:
    rows = []
    for k, (kind, dependence) in enumerate(dependences.items()):
        for n in MEANS_N:
            for name, fractions in MEANS_FRACTIONS.items():
                rng = np.random.default_rng([seed, 11, n, k, len(rows)])
                share = shares[kind]["pair_share"]
                arguments = {
                    "statistics": dataclasses.asdict(settings),
                    "model": describe_model(dependence),
                    "share": share,
                    "seed": [seed, 11, n, k, len(rows)],
                    "fractions": fractions,
                    "replicates": replicates,
                }
                cell = stored(
                    cells, arguments, partial(means_cell, rng, settings, n, fractions, dependence, share, replicates)
                )
                rows.append({"dependence": kind, "n": n, "fractions": name, "coverage": cell})
                print(f"{kind:>6} n={n:>5} {name}: coverage {cell['rate']:.3f}", flush=True)
    return rows


def measure_dependence(evaluations: Sequence[Evaluation], kind: Callable[[str], str] = kind_of) -> dict[str, dict]:
    """fit_dependence of a run's evaluations, single images and +seq apart (`kind`: matcher_of for
    every matcher apart; learners compared on the same result name: the same pair, metric and matcher)."""
    by_kind: dict[str, dict[str, dict[str, np.ndarray]]] = {}
    for learner, name, outcomes in evaluations:
        by_kind.setdefault(kind(name), {}).setdefault(name, {})[learner] = outcomes.correct
    fits = {}
    for kind, evaluations in by_kind.items():
        if not evaluations:
            continue
        series = [correct for learners in evaluations.values() for correct in learners.values()]
        pairs = [pair for learners in evaluations.values() for pair in combinations(learners.values(), 2)]
        fits[kind] = fit_dependence(series, pairs)
    return fits


def latent(rng: np.random.Generator, replicates: int, n: int, dependence: Dependence) -> np.ndarray:
    """(replicates, n) unit-variance latents: sqrt(a) AR(1) + sqrt(1 - a) noise, the AR started stationary."""
    noise = rng.standard_normal((replicates, n))
    if dependence.a == 0:
        return noise
    phi = dependence.phi
    innovations = rng.standard_normal((replicates, n)) * math.sqrt(1 - phi * phi)
    innovations[:, 0] = rng.standard_normal(replicates)  # y_0 ~ N(0, 1): stationary from the start
    ar = signal.lfilter([1.0], [1.0, -phi], innovations, axis=1)
    return math.sqrt(dependence.a) * ar + math.sqrt(1 - dependence.a) * noise


def learners(
    rng: np.random.Generator, replicates: int, n: int, fractions: Sequence[float], dependence: Any
) -> list[np.ndarray]:
    """One (replicates, n) bool outcome array per fraction: learners of one pair, sharing `share` of
    their latent (a Markov or Blocks dependence draws its own way)."""
    if not isinstance(dependence, Dependence):
        return dependence.learners(rng, replicates, n, fractions)
    common = latent(rng, replicates, n, dependence)
    share = dependence.share
    return [
        (math.sqrt(share) * common + math.sqrt(1 - share) * latent(rng, replicates, n, dependence)) < ndtri(p)
        for p in fractions
    ]


def covers(interval: dict[str, Any] | None, value: float) -> bool | None:
    """Whether an interval holds value (None: the interval was refused)."""
    if interval is None or interval.get("low") is None:
        return None
    return bool(interval["low"] <= value <= interval["high"])


def rate(outcomes: Sequence[bool | None]) -> dict[str, Any]:
    """{rate, replicates, refused}: the share of True among the answered replicates."""
    answered = [o for o in outcomes if o is not None]
    return {
        "rate": float(np.mean(answered)) if answered else None,
        "replicates": len(answered),
        "refused": len(outcomes) - len(answered),
    }


def route_lengths(routes: int, n: int) -> list[int] | None:
    return None if routes == 1 else [n] * routes


def chunks(replicates: int, queries: int) -> list[int]:
    """Replicates drawn at a time, so that a draw holds at most ~2 million queries a learner."""
    size = max(1, min(replicates, 2_000_000 // queries))
    return [min(size, replicates - start) for start in range(0, replicates, size)]


def drawn(rng, replicates: int, n: int, fractions: Sequence[float], dependence: Dependence, routes: int = 1):
    """learners() of `routes` independent routes joined, chunk by chunk: yields one list of
    (chunk, routes * n) outcome arrays per chunk."""
    for chunk in chunks(replicates, routes * n):
        per_route = [learners(rng, chunk, n, fractions, dependence) for _ in range(routes)]
        yield [np.concatenate([route[k] for route in per_route], axis=1) for k in range(len(fractions))]


def coverage_cell(rng, settings, n, p, dependence, replicates, pairs_pooled=1) -> dict[str, Any]:
    """Coverage of the fraction's interval along the route and of Wilson's, one route of n queries;
    the runs' persistence pooled over `pairs_pooled` pairs' outcomes of one learner (as the evaluate
    stage pools a run's pairs), drawn as learners of one pair (sharing the dependence's `share`)."""
    every = np.ones(n, bool)
    route, wilson = [], []
    for pairs in drawn(rng, replicates, n, [p] * pairs_pooled, dependence):
        for r in range(len(pairs[0])):
            pooled = persistence(pair[r] for pair in pairs)
            interval = fraction_interval(pairs[0][r], every, settings, runs=pooled)
            route.append(covers(interval["route"], p))
            wilson.append(covers(interval["wilson"], p))
    return {"route": rate(route), "wilson": rate(wilson)}


def judged_table(outcomes: Sequence[np.ndarray], settings, segments) -> list[dict[str, Any]]:
    """Every comparison of a table of learners (outcomes: one bool array each) in combinations
    order, as the compare stage judges a table (seasonloop.significance.tables.table_verdicts)."""
    return table_verdicts(
        [(outcomes[i], outcomes[j]) for i, j in combinations(range(len(outcomes)), 2)], settings, segments
    )


def table_cell(rng, settings, n, p, dependence, replicates, size, routes=1) -> dict[str, Any]:
    """Two-or-more learners of equal laws: the share of comparisons called significant (first
    comparison of each table), and of tables with any significant comparison (Holm over the table)."""
    first, any_in_table = [], []
    segments = route_lengths(routes, n)
    # routes pooled: each route's learners drawn independently of the other routes'
    for outcomes in drawn(rng, replicates, n, [p] * size, dependence, routes):
        for r in range(len(outcomes[0])):
            judged = judged_table([learner[r] for learner in outcomes], settings, segments)
            if judged[0]["p_value"] is None:
                first.append(None)
                any_in_table.append(None)
                continue
            first.append(judged[0]["p_value"] < settings.alpha)
            any_in_table.append(any(row["verdict"] in ("better", "worse") for row in judged))
    return {
        "per_comparison": rate(first),
        "per_table": rate(any_in_table),
        "comparisons_per_table": size * (size - 1) // 2,
    }


def power_cell(rng, settings, n, p, difference, dependence, replicates, size, routes=1) -> dict[str, Any]:
    """A table of `size` learners, one of them `difference` ahead of the others (behind where
    p + d > 1), the others equal: how often its comparison with one of them is found at alpha alone
    ("power") and under Holm over the table ("power_holm", what a table's verdict needs), and its
    interval's coverage."""
    second = p + difference if p + difference <= 0.99 else p - difference
    true = second - p
    segments = route_lengths(routes, n)
    found, found_holm, covered = [], [], []
    for outcomes in drawn(rng, replicates, n, [second] + [p] * (size - 1), dependence, routes):
        for r in range(len(outcomes[0])):
            row = judged_table([learner[r] for learner in outcomes], settings, segments)[0]
            if row["p_value"] is None:
                found.append(None)
                found_holm.append(None)
                covered.append(None)
                continue
            right_way = np.sign(row["difference"]) == np.sign(true)
            found.append(bool(row["p_value"] < settings.alpha and right_way))
            found_holm.append(bool(row["p_holm"] < settings.alpha and right_way))
            covered.append(bool(row["low"] <= true <= row["high"]))
    return {
        "second_fraction": second,
        "power": rate(found),
        "power_holm": rate(found_holm),
        "interval_coverage": rate(covered),
    }


def run_grid(
    settings: StatisticsConfig,
    dependences: dict[str, Dependence],
    grid: dict,
    replicates: int,
    seed: int,
    cells: Cells | None = None,
) -> list[dict]:
    """Every cell of the grid, one row each (module doc); `cells`: finished cells kept and reused."""
    rows = []
    for index, (kind, dependence) in enumerate(dependences.items()):
        arguments = {
            "statistics": dataclasses.asdict(settings),
            "model": describe_model(dependence),
            "index": index,
            "grid": grid,
            "replicates": replicates,
            "seed": seed,
        }
        for n in grid["n"]:
            for p in grid["p"]:
                row = stored(
                    cells,
                    {**arguments, "n": n, "p": p, "routes": 1},
                    partial(grid_cell, settings, kind, index, dependence, grid, n, p, replicates, seed),
                )
                rows.append(row)
                print(summary_line(row), flush=True)
        for n in grid["pooled_n"]:
            routes = grid["pooled_routes"]
            row = stored(
                cells,
                {**arguments, "n": n, "p": 0.5, "routes": routes},
                partial(pooled_cell, settings, kind, index, dependence, grid, n, replicates, seed),
            )
            rows.append(row)
            print(summary_line(row), flush=True)
    return rows


def stored(cells: Cells | None, arguments: dict, compute: Callable[[], dict]) -> dict:
    return compute() if cells is None else cells.get(arguments, compute)


def grid_cell(settings, kind, index, dependence, grid, n, p, replicates, seed) -> dict[str, Any]:
    """One route of n queries at fraction p: coverage, false positives, power (module doc)."""
    # a seed per cell: a cell's numbers do not depend on which other cells run
    rng = np.random.default_rng([seed, int(1000 * p), n, index])
    started = time.perf_counter()
    row: dict[str, Any] = {"dependence": kind, "n": n, "p": p, "routes": 1}
    row["coverage"] = coverage_cell(rng, settings, n, p, dependence, replicates, grid["pooled_pairs"])
    row.update(tests_cell(rng, settings, n, p, dependence, replicates, grid))
    row["seconds"] = round(time.perf_counter() - started, 1)
    return row


def pooled_cell(settings, kind, index, dependence, grid, n, replicates, seed) -> dict[str, Any]:
    """grid["pooled_routes"] routes of n queries pooled, at p 0.5: false positives and power."""
    p, routes = 0.5, grid["pooled_routes"]
    rng = np.random.default_rng([seed, 7, n, index])
    return {
        "dependence": kind,
        "n": n,
        "p": p,
        "routes": routes,
        **tests_cell(rng, settings, n, p, dependence, replicates, grid, routes),
    }


def tests_cell(rng, settings, n, p, dependence, replicates, grid, routes=1) -> dict[str, Any]:
    """The paired tests on `routes` routes of n queries at fraction p: false positives of a table of
    equal learners, then power at each of the grid's differences (half the replicates each)."""
    size = grid["table_learners"]
    return {
        "false_positive": table_cell(rng, settings, n, p, dependence, replicates, size, routes),
        "power": {
            f"{difference:.2f}": power_cell(rng, settings, n, p, difference, dependence, replicates // 2, size, routes)
            for difference in grid["differences"]
        },
    }


# the n the docs report: the real half's and the default route's queries a pair on the study's
# split, about every place of either, five routes pooled (5 x 1,800: about 9,000), and 5 x 158
OUT_OF_SAMPLE_GRID = {
    "n": (147, 158, 1800),
    "p": (0.05, 0.2, 0.5, 0.8, 0.95),
    "differences": (0.05, 0.10, 0.20),
    "pooled_routes": 5,
    "pooled_n": (158, 1800),
    "pooled_pairs": 1,  # the real half's one pair: an evaluation's persistence from its own outcomes
}
BLOCK_LENGTHS = (20, 80)  # all right or all wrong for 20 to 80 queries: a snowy stretch
BLOCK_SHARE = 0.5  # a pair's learners take the stretch's common outcome half the time
DRIFT_QUERIES = 100  # the correlation length of a slowly varying success rate, in queries
DRIFT_SHARE = 0.3  # of the latent's variance
SHARED_FAILURES = 0.9  # of their latent two learners share: most failures in common


def out_of_sample_models(default: dict[str, dict], real: dict[str, dict]) -> dict[str, Any]:
    """Dependence models the degrees rule was not chosen on (the thresholded AR fitted to the default
    run's single and +seq outcomes): runs of fixed-length blocks, two-state Markov chains (0.8, and
    fitted to the real run's mean lag-1 autocorrelation), a slowly varying success rate, learners
    that share most failures, and the thresholded AR fitted to the real run's outcomes, every
    matcher apart (`default`, `real`: measure_dependence of the two runs, real by matcher_of)."""
    single = Dependence(**default["single"]["dependence"])
    lag_one = float(np.mean([fit["autocorrelation_measured"]["1"] for fit in real.values()]))
    return {
        f"blocks {BLOCK_LENGTHS[0]}-{BLOCK_LENGTHS[1]}": Blocks(*BLOCK_LENGTHS, BLOCK_SHARE),
        "Markov 0.8": Markov(0.8),
        f"Markov {lag_one:.2f} (real)": Markov(round(lag_one, 2)),
        f"drift over {DRIFT_QUERIES}": Dependence(DRIFT_SHARE, math.exp(-1 / DRIFT_QUERIES), single.share),
        "shared failures": dataclasses.replace(single, share=SHARED_FAILURES),
        **{f"real {kind}": Dependence(**fit["dependence"]) for kind, fit in real.items()},
    }


def describe_model(dependence: Any) -> dict[str, Any]:
    return {"model": type(dependence).__name__, **dataclasses.asdict(dependence)}


def calibrate_out_of_sample(
    settings: StatisticsConfig, models: dict[str, Any], grid: dict, replicates: int, seed: int, cells=None
) -> dict:
    """run_grid of the out-of-sample models at the settings, with the settings they ran under."""
    print(f"statistics: {dataclasses.asdict(settings)} (min queries a route: {min_queries(settings)})")
    return {
        "replicates": replicates,
        "seed": seed,
        "grid": grid,
        "models": {name: describe_model(model) for name, model in models.items()},
        "runs": {
            "params": {
                "statistics": dataclasses.asdict(settings),
                "min_queries": min_queries(settings),
                "rows": run_grid(settings, models, grid, replicates, seed, cells),
            }
        },
    }


def summary_line(row: dict) -> str:
    def fmt(cell: dict) -> str:
        return "refused" if cell["rate"] is None else f"{cell['rate']:.3f}"

    parts = [f"{row['dependence']:>6} n={row['n']:>5} p={row['p']:.2f} routes={row['routes']}"]
    if "coverage" in row:
        parts.append(f"coverage {fmt(row['coverage']['route'])} (Wilson {fmt(row['coverage']['wilson'])})")
    fp = row["false_positive"]
    parts.append(f"false positives {fmt(fp['per_comparison'])} per comparison, {fmt(fp['per_table'])} per table")
    parts.append("power " + " ".join(f"{d}: {fmt(c['power'])}" for d, c in row["power"].items()))
    return "  ".join(parts)


def calibrate(
    settings: StatisticsConfig,
    dependences: dict[str, Dependence],
    grid: dict,
    replicates: int,
    seed: int,
    cells: Cells | None = None,
) -> dict:
    """The grid at the settings' degrees_scale and at LLSW's, with the settings they ran under."""
    record: dict[str, Any] = {"replicates": replicates, "seed": seed, "grid": grid, "runs": {}}
    llsw_grid = {**grid, "n": tuple(n for n in grid["n"] if n in LLSW_N) or grid["n"], "pooled_n": ()}
    for name, scale, grid_cells in (("params", settings.degrees_scale, grid), ("llsw", LLSW_SCALE, llsw_grid)):
        scaled = dataclasses.replace(settings, degrees_scale=scale)
        print(f"statistics: {dataclasses.asdict(scaled)} (min queries a route: {min_queries(scaled)})")
        record["runs"][name] = {
            "statistics": dataclasses.asdict(scaled),
            "min_queries": min_queries(scaled),
            "rows": run_grid(scaled, dependences, grid_cells, replicates, seed, cells),
        }
    return record


def kept(name: str) -> Cells:
    """The finished cells of record `name`, kept so that a run cut short resumes (benchmarks.cells),
    keyed by this file's code and the significance package's."""
    here = Path(__file__)
    significance = here.parents[2] / "src" / "seasonloop" / "significance"
    return Cells(name, source_hash([here, *significance.glob("*.py")]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workspace", type=Path, default=Path("."), help="a run's folder (after `dvc repro`)")
    parser.add_argument("--replicates", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--small", action="store_true", help="the tests' small grid")
    parser.add_argument("--means", action="store_true", help="the interval of the mean over six pairs")
    parser.add_argument(
        "--real", type=Path, help="a run on real frames (after `dvc repro`): the out-of-sample models (module doc)"
    )
    args = parser.parse_args()
    from benchmarks.common import save_and_report
    from tools.records import machine

    params = yaml.safe_load((args.workspace / "params.yaml").read_text())
    settings = StatisticsConfig.from_params(params)
    evaluations = read_evaluations(args.workspace)
    fits = measure_dependence(evaluations)
    for kind, fit in fits.items():
        print(f"{kind}: {fit}")
    if args.real is not None:
        real = measure_dependence(read_evaluations(args.real), matcher_of)
        models = out_of_sample_models(fits, real)
        # a table of the workspace's learners: learners x (learners - 1) / 2 comparisons under Holm
        grid = {**OUT_OF_SAMPLE_GRID, "table_learners": len(params["learners"])}
        record = calibrate_out_of_sample(
            settings, models, grid, args.replicates, args.seed, kept("check_calibration_out_of_sample")
        )
        record["fitted"] = {"default": fits, "real": real}
        record["workspaces"] = {"default": str(args.workspace), "real": str(args.real)}
        record["headline"] = headline(record)
        save_and_report("check_calibration_out_of_sample", record, machine())
        return
    if args.means:
        dependences = {kind: Dependence(**fit["dependence"]) for kind, fit in fits.items()}
        shares = {kind: pair_share(evaluations, kind, fit["mean_fraction_correct"]) for kind, fit in fits.items()}
        rows = calibrate_means(
            settings, dependences, shares, args.replicates, args.seed, kept("check_calibration_means")
        )
        low, high = min(row["coverage"]["rate"] for row in rows), max(row["coverage"]["rate"] for row in rows)
        record = {
            "replicates": args.replicates,
            "seed": args.seed,
            "statistics": dataclasses.asdict(settings),
            "fractions": MEANS_FRACTIONS,
            "fitted": {kind: {**fits[kind], **shares[kind]} for kind in fits},
            "rows": rows,
            "headline": f"the 95% interval of the mean over six pairs covers {low:.3f}-{high:.3f} "
            f"({args.replicates} simulated runs a cell)",
        }
        save_and_report("check_calibration_means", record, machine())
        return
    dependences = {"independent": INDEPENDENT, **{kind: Dependence(**fit["dependence"]) for kind, fit in fits.items()}}
    grid = SMALL_GRID if args.small else FULL_GRID
    record = calibrate(settings, dependences, grid, args.replicates, args.seed, kept("check_calibration"))
    record["fitted"] = fits
    record["workspace"] = str(args.workspace)
    record["headline"] = headline(record)
    save_and_report("check_calibration", record, machine())


def worst(rows: list[dict], key: str, subkey: str, low: bool) -> float | None:
    values = [row[key][subkey]["rate"] for row in rows if key in row and row[key][subkey]["rate"] is not None]
    return (min(values) if low else max(values)) if values else None


def headline(record: dict) -> str:
    rows = record["runs"]["params"]["rows"]
    return (
        f"95% intervals cover {worst(rows, 'coverage', 'route', True):.3f}-{worst(rows, 'coverage', 'route', False):.3f} "
        f"over the grid; paired test's false positives at most {worst(rows, 'false_positive', 'per_comparison', False):.3f} "
        f"per comparison and {worst(rows, 'false_positive', 'per_table', False):.3f} per table "
        f"({record['replicates']} routes a cell)"
    )


# the calibration targets of docs/statistics.md: a 95% interval covers 94-96.5%, a test at 5% errs
# at most 5.5% of the time; a cell outside them is marked
COVERAGE_TARGET, FALSE_POSITIVE_TARGET = (0.94, 0.965), 0.055


def _monte_carlo_error(cell: dict, nominal: float) -> float:
    return (nominal * (1 - nominal) / cell["replicates"]) ** 0.5


def _coverage_off(cell: dict) -> bool:
    """Outside COVERAGE_TARGET by more than two Monte Carlo standard errors."""
    margin = 2 * _monte_carlo_error(cell, 0.95)
    return not COVERAGE_TARGET[0] - margin <= cell["rate"] <= COVERAGE_TARGET[1] + margin


def _false_positives_off(cell: dict) -> bool:
    """Above FALSE_POSITIVE_TARGET by more than two Monte Carlo standard errors."""
    return cell["rate"] > FALSE_POSITIVE_TARGET + 2 * _monte_carlo_error(cell, 0.05)


def _rate_cell(cell: dict, off: Callable[[dict], bool] = lambda cell: False) -> str:
    if cell["rate"] is None:
        return "refused"
    refused = cell.get("refused", 0) / (cell["replicates"] + cell.get("refused", 0))
    return f"{cell['rate']:.3f}" + (" †" if off(cell) else "") + (f" ({100 * refused:.0f}% refused)" if refused else "")


def _calibration_rows(path: Path, run: str = "params") -> tuple[dict, list[dict]]:
    record = json.loads(path.read_text())
    return record, record["runs"][run]["rows"]


def _calibration_legend(record: dict, run: str = "params", replicates: int | None = None) -> str:
    """replicates: the simulated routes a cell of the table has (default: the record's)."""
    statistics, replicates = record["runs"][run]["statistics"], replicates or record["replicates"]
    error = (0.95 * 0.05 / replicates) ** 0.5
    return (
        f"{replicates} simulated routes a cell (Monte Carlo standard error {100 * error:.1f} points at 95% "
        f"or 5%); degrees_scale {statistics['degrees_scale']}"
        + (f", persistence_scale {statistics['persistence_scale']}" if "persistence_scale" in statistics else "")
        + f"; refused: fewer than {record['runs'][run]['min_queries']} queries a route, or runs too long for "
        'the queries (the pipeline writes "not enough queries" or "runs too long for this many queries"; '
        "a share in brackets: the routes of the cell refused so, the rate is the others'); † outside the "
        "target by more than two Monte Carlo standard errors."
    )


def _by_fraction(rows: list[dict], ps: list[float], keys: tuple[str, ...], cell: Callable[[dict], str | None]) -> str:
    """A table of the grid: a line per value of `keys` (e.g. dependence and n), a column per fraction p,
    cell(row) the text of a row of the record (None: the row is not in this table)."""
    cells: dict[tuple, dict[float, str]] = {}
    for row in rows:
        text = cell(row)
        if text is not None:
            cells.setdefault(tuple(row[key] for key in keys), {})[row["p"]] = text
    lines = ["| " + " | ".join(keys) + " | " + " | ".join(f"p = {p}" for p in ps) + " |"]
    lines.append("|" + "---|" * (len(keys) + len(ps)))
    for key, by_p in cells.items():
        lines.append("| " + " | ".join(map(str, key)) + " | " + " | ".join(by_p.get(p, "") for p in ps) + " |")
    return "\n".join(lines)


def _calibration_coverage(path: Path) -> str:
    """Coverage of the 95% interval along the route (Wilson's in brackets) per dependence, n and p."""
    record, rows = _calibration_rows(path)

    def cell(row: dict) -> str | None:
        if "coverage" not in row:
            return None
        return f"{_rate_cell(row['coverage']['route'], _coverage_off)} ({row['coverage']['wilson']['rate']:.3f})"

    table = _by_fraction(rows, record["grid"]["p"], ("dependence", "n"), cell)
    return table + "\n\n" + _calibration_legend(record) + " In brackets: Wilson's interval.\n"


def _calibration_false_positives(path: Path) -> str:
    """Equal learners called different: per comparison / per table (Holm), per dependence, n, routes and p."""
    record, rows = _calibration_rows(path)

    def cell(row: dict) -> str:
        rates = row["false_positive"]
        return " / ".join(_rate_cell(rates[kind], _false_positives_off) for kind in ("per_comparison", "per_table"))

    size = record["grid"]["table_learners"]
    return (
        _by_fraction(rows, record["grid"]["p"], ("dependence", "n", "routes"), cell)
        + f"\n\nCells: per comparison / per table ({size} learners of equal laws, {size * (size - 1) // 2} "
        "comparisons, Holm). routes > 1: that many independent routes pooled (p = 0.5 only). "
        + _calibration_legend(record)
        + "\n"
    )


def _calibration_power(path: Path) -> str:
    """How often the paired test finds a difference of 3, 5 and 10 points (and the difference's interval coverage)."""
    record, rows = _calibration_rows(path)
    differences = sorted(next(iter(rows))["power"], key=float)
    header = [f"power at {100 * float(d):.0f} points" for d in differences]
    header += [f"interval coverage at {100 * float(d):.0f}" for d in differences]
    lines = ["| dependence | n | routes | p | " + " | ".join(header) + " |", "|---|---|---|---|" + "---|" * len(header)]
    for row in rows:
        if row["p"] != 0.5:
            continue
        power = [_rate_cell(row["power"][d]["power"]) for d in differences]
        coverage = [_rate_cell(row["power"][d]["interval_coverage"], _coverage_off) for d in differences]
        lines.append(
            f"| {row['dependence']} | {row['n']} | {row['routes']} | {row['p']} | "
            + " | ".join(power + coverage)
            + " |"
        )
    return (
        "\n".join(lines)
        + "\n\nPower: the share of routes on which the paired test (one comparison, at alpha) finds the difference, in its direction. "
        + _calibration_legend(record, replicates=_power_replicates(rows))
        + "\n"
    )


def _power_replicates(rows: list[dict]) -> int:
    """The simulated routes of a power cell (check_calibration draws half as many as for the others)."""
    cell = next(iter(rows[-1]["power"].values()))["power"]
    return cell["replicates"] + cell["refused"]


def _calibration_difference_coverage(path: Path) -> str:
    """The 95% interval of a difference where the difference is real: its lowest coverage over the
    differences of the grid, per dependence, n and the first learner's fraction (one route)."""
    record, rows = _calibration_rows(path)

    def cell(row: dict) -> str | None:
        if row["routes"] != 1:
            return None
        answered = [
            cell["interval_coverage"] for cell in row["power"].values() if cell["interval_coverage"]["rate"] is not None
        ]
        return _rate_cell(min(answered, key=lambda cell: cell["rate"]) if answered else {"rate": None}, _coverage_off)

    table = _by_fraction(rows, record["grid"]["p"], ("dependence", "n"), cell)
    differences = ", ".join(f"{100 * float(d):.0f}" for d in sorted(next(iter(rows))["power"], key=float))
    return (
        table
        + f"\n\nCells: the lowest coverage over differences of {differences} points (the second learner's fraction p "
        "plus the difference, minus where that passes 0.99). "
        + _calibration_legend(record, replicates=_power_replicates(rows))
        + "\n"
    )


def _calibration_llsw(path: Path) -> str:
    """The params' degrees_scale beside LLSW's 0.4: worst coverage and worst false-positive rate per dependence and n."""
    record = json.loads(path.read_text())
    runs = {name: record["runs"][name] for name in ("params", "llsw")}  # JSON keys come back sorted
    scales = {name: run["statistics"]["degrees_scale"] for name, run in runs.items()}
    lines = [
        "| dependence | n | "
        + " | ".join(f"scale {scales[name]}: coverage, lowest / highest" for name in runs)
        + " | "
        + " | ".join(f"scale {scales[name]}: false positives, highest" for name in runs)
        + " |",
        "|---|---|" + "---|" * (2 * len(runs)),
    ]
    keys = sorted(
        {(row["dependence"], row["n"]) for row in runs["llsw"]["rows"]},
        key=lambda key: (list(record["grid"]["n"]).index(key[1]), key[0]),
    )
    for dependence, n in keys:
        coverage, false_positive = [], []
        for run in runs.values():
            rows = [row for row in run["rows"] if (row["dependence"], row["n"], row["routes"]) == (dependence, n, 1)]
            rates = [row["coverage"]["route"]["rate"] for row in rows if row["coverage"]["route"]["rate"] is not None]
            fps = [
                row["false_positive"]["per_comparison"]["rate"]
                for row in rows
                if row["false_positive"]["per_comparison"]["rate"] is not None
            ]
            coverage.append(f"{min(rates):.3f} / {max(rates):.3f}" if rates else "refused")
            false_positive.append(f"{max(fps):.3f}" if fps else "refused")
        lines.append(f"| {dependence} | {n} | " + " | ".join(coverage + false_positive) + " |")
    return (
        "\n".join(lines)
        + f"\n\nOver p in {list(record['grid']['p'])}, one route; {record['replicates']} simulated routes a cell.\n"
    )


def _calibration_means(path: Path) -> str:
    """Coverage of the 95% interval of the mean over six pairs, per dependence, n and fractions."""
    record = json.loads(path.read_text())
    names = list(record["fractions"])
    lines = [
        "| dependence | n | " + " | ".join(f"pairs {name}" for name in names) + " |",
        "|---|---|" + "---|" * len(names),
    ]
    cells: dict[tuple[str, int], dict[str, str]] = {}
    for row in record["rows"]:
        cells.setdefault((row["dependence"], row["n"]), {})[row["fractions"]] = _rate_cell(
            row["coverage"], _coverage_off
        )
    for (dependence, n), by_name in cells.items():
        lines.append(f"| {dependence} | {n} | " + " | ".join(by_name[name] for name in names) + " |")
    shares = ", ".join(
        f"{kind} {fit['pair_share']:.2f} (outcomes' correlation {fit['pair_correlation_measured']:.2f})"
        for kind, fit in record["fitted"].items()
    )
    fractions = "; ".join(f"{name}: {list(values)}" for name, values in record["fractions"].items())
    error = (0.95 * 0.05 / record["replicates"]) ** 0.5
    return (
        "\n".join(lines)
        + f"\n\nFractions of the six pairs: {fractions}. Latent share between two pairs, fitted: {shares}. "
        f"{record['replicates']} simulated runs a cell (Monte Carlo standard error {100 * error:.1f} points); "
        "† outside 94-96.5% by more than two standard errors.\n"
    )


def _calibration_fit(path: Path) -> str:
    """The dependence the simulation was given: fitted to the run's per-query outcomes."""
    record = json.loads(path.read_text())
    lags = ("1", "2", "5", "10")
    lines = [
        "| outcomes | evaluations | a | phi | share | "
        + " | ".join(f"autocorr. lag {lag}: run / fitted" for lag in lags)
        + " | learners' correlation |",
        "|---|---|---|---|---|" + "---|" * (len(lags) + 1),
    ]
    for kind, fit in record["fitted"].items():
        d = fit["dependence"]
        cells = [
            f"{fit['autocorrelation_measured'][lag]:.2f} / {fit['autocorrelation_fitted'][lag]:.2f}" for lag in lags
        ]
        lines.append(
            f"| {kind} | {fit['evaluations']} | {d['a']:.2f} | {d['phi']:.2f} | {d['share']:.2f} | "
            + " | ".join(cells)
            + f" | {fit['learner_correlation_measured']:.2f} |"
        )
    return "\n".join(lines) + "\n"


# docs/write_tables.py's tables of this study's records, the statistics' real coverage and error
# rates on simulated routes (docs/statistics.md): name -> (record, snapshot, how it is written)
def _out_of_sample_models(path: Path) -> str:
    """The out-of-sample dependence models, each with its parameters and its outcomes' lag-1
    autocorrelation, and the real run's fits they include."""
    from benchmarks.common import cell_text  # as main imports it: the module's tests need none of it

    record = json.loads(path.read_text())
    lines = ["| dependence | model | parameters |", "|---|---|---|"]
    for name, model in record["models"].items():
        shown = ", ".join(f"{key} {cell_text(value)}" for key, value in model.items() if key != "model")
        lines.append(f"| {name} | {model['model']} | {shown} |")
    real = "; ".join(
        f"{kind}: {fit['evaluations']} evaluations, lag-1 autocorrelation {fit['autocorrelation_measured']['1']:.2f}, "
        f"learners' correlation {fit['learner_correlation_measured']:.2f}"
        for kind, fit in record["fitted"]["real"].items()
    )
    return "\n".join(lines) + f"\n\nFitted to the run on real frames, each matcher apart: {real}.\n"


TABLES = {
    **{
        name: ("benchmarks/results/check_calibration.json", "check_calibration.json", writer)
        for name, writer in (
            ("calibration_fit", _calibration_fit),
            ("calibration_coverage", _calibration_coverage),
            ("calibration_false_positives", _calibration_false_positives),
            ("calibration_power", _calibration_power),
            ("calibration_difference_coverage", _calibration_difference_coverage),
            ("calibration_llsw", _calibration_llsw),
        )
    },
    "calibration_means": (
        "benchmarks/results/check_calibration_means.json",
        "check_calibration_means.json",
        _calibration_means,
    ),
    **{
        name: (
            "benchmarks/results/check_calibration_out_of_sample.json",
            "check_calibration_out_of_sample.json",
            writer,
        )
        for name, writer in (
            ("calibration_out_of_sample_models", _out_of_sample_models),
            ("calibration_out_of_sample_coverage", _calibration_coverage),
            ("calibration_out_of_sample_false_positives", _calibration_false_positives),
            ("calibration_out_of_sample_power", _calibration_power),
        )
    },
}


if __name__ == "__main__":
    main()
