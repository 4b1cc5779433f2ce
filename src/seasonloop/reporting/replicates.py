"""Conclusions across replicate routes: the same pipeline and params on several synthetic routes
(synthetic.seed), each run as a DVC experiment (tools/replicate_routes.py queues and collects
them), read back as each route's outputs: metrics/summary.json, metrics/comparisons.json and the
per-query outcomes data/outcomes/.

Three answers per route set:
- the spread of every fraction correct (label x pair): mean, standard deviation, lowest, highest;
  the same for the training-season ablation (label x training set), and in how many routes its
  largest training set is above its smallest;
- for each claim of docs/claims.yaml (one comparison, or a whole table), on each pair: in how many
  routes it points each way and is significant each way (each route's own paired tests);
- the pooled verdict: every route's queries of a pair taken together, with the same paired test
  and Holm correction as a single run (seasonloop.significance.tables), each route's long-run
  variance its own (the routes are independent; no route's runs join another's) and the pooled
  difference's variance their weighted sum (seasonloop.significance.intervals.mean_variance). It
  does not depend on the order the routes are read in. What it generalises over: the queries of
  these routes, not routes in general: a route-to-route spread of the true difference is not in
  its variance (with five routes a test over routes would have 4 degrees of freedom; the spread
  and the per-route tallies above show how much the routes differ).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.comparisons import Reader, claim_cell, claim_cells, claim_values, comparisons_of
from seasonloop.significance.tables import Variant


def fraction_spread(summaries: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, dict[str, float] | None]]:
    """label -> pair -> {mean, std, min, max} of fraction correct over the routes (summaries[route]:
    that route's metrics/summary.json; std with one degree of freedom, 0 for a single route); None
    where no route has a value (a learner not fitted on a training set it cannot learn from)."""
    first = next(iter(summaries.values()))["fraction_correct"]
    spread: dict[str, dict[str, dict[str, float] | None]] = {}
    for label, by_pair in first.items():
        spread[label] = {}
        for pair in by_pair:
            found = [summary["fraction_correct"][label][pair] for summary in summaries.values()]
            values = np.array([value for value in found if value is not None], dtype=np.float64)
            if not len(values):
                spread[label][pair] = None
                continue
            spread[label][pair] = {
                "mean": float(values.mean()),
                "std": float(values.std(ddof=1)) if len(values) > 1 else 0.0,
                "min": float(values.min()),
                "max": float(values.max()),
            }
    return spread


def first_to_last(records: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, int]]:
    """label -> in how many routes the last training set's fraction correct is above ("up"), below
    ("down") or equal to ("same") the first's (records[route]: its metrics/training_seasons.json,
    whose training sets are named by their seasons joined with "+": first and last by that count,
    among the sets the learner was fitted on)."""
    counts: dict[str, dict[str, int]] = {}
    for record in records.values():
        for label, by_set in record["fraction_correct"].items():
            sets = sorted((name for name in by_set if by_set[name] is not None), key=lambda name: name.count("+"))
            if not sets:
                continue
            first, last = by_set[sets[0]], by_set[sets[-1]]
            change = "up" if last > first else "down" if last < first else "same"
            counts.setdefault(label, {"up": 0, "down": 0, "same": 0})[change] += 1
    return counts


def pooled_comparisons(
    routes: Mapping[int, Reader],
    learners: Sequence[str],
    variants: Sequence[Variant],
    pairs: Sequence[str],
    settings: StatisticsConfig,
) -> dict[str, Any]:
    """The comparisons record (as metrics/comparisons.json) of every route's queries together:
    routes[key] reads the per-query outcomes of the route keyed by its synthetic.seed (csv_reader
    of its data/outcomes folder, or a kept route's reader)."""
    # in key order: the pooled sums then do not depend on the order the routes are given in
    readers = dict(sorted(routes.items()))

    # read once: segments_of reads the first evaluation of a pair, which pooled reads again
    @functools.cache
    def routes_of(learner: str, pair: str, suffix: str) -> list[tuple[np.ndarray, np.ndarray]]:
        return [reader(learner, pair, suffix) for reader in readers.values()]

    def pooled(learner: str, pair: str, suffix: str) -> tuple[np.ndarray, np.ndarray]:
        read = routes_of(learner, pair, suffix)
        # places numbered per route: route i's place p is i * (1 + the largest place) + p
        span = 1 + max(int(places.max()) for places, _ in read)
        places = np.concatenate([route * span + places for route, (places, _) in enumerate(read)])
        return places, np.concatenate([correct for _, correct in read])

    def segments_of(pair: str) -> list[int]:
        # a pair's evaluations share their queries (pair_comparisons checks): the first one's count
        return [len(places) for places, _ in routes_of(learners[0], pair, variants[0][2])]

    return comparisons_of(pooled, learners, variants, pairs, settings, segments_of)


def claims_in(
    record: Mapping[str, Any], claims: Mapping[str, Mapping[str, str]]
) -> tuple[dict[str, Mapping[str, str]], list[str]]:
    """(the claims a comparisons record can answer, the names of those it cannot: a learner or
    table the run does not have, e.g. a run on fewer learners)."""
    kept, left_out = {}, []
    for name, claim in claims.items():
        try:
            claim_cells(record, claim)
        except ValueError:
            left_out.append(name)
        else:
            kept[name] = claim
    return kept, left_out


def claim_tally(
    records: Mapping[str, Mapping[str, Any]], claims: Mapping[str, Mapping[str, str]]
) -> dict[str, dict[str, dict[str, int]]]:
    """claim -> pair -> counts over the routes (records[route]: its comparisons record). A claim on
    one comparison: "ahead" / "behind" (first's point estimate above / below second's), "better" /
    "worse" (significant). A claim on a whole table: "least_better" / "most_better" and "least_worse" /
    "most_worse", the range over the routes of its significant comparisons each way."""
    tally: dict[str, dict[str, dict[str, int]]] = {}
    for name, claim in claims.items():
        tally[name] = {}
        for record in records.values():
            for pair, value in claim_values(record, claim).items():
                counts = tally[name].setdefault(pair, {})
                if "verdict" in value:
                    for key, holds in (
                        ("ahead", value["difference"] > 0),
                        ("behind", value["difference"] < 0),
                        ("better", value["verdict"] == "better"),
                        ("worse", value["verdict"] == "worse"),
                    ):
                        counts[key] = counts.get(key, 0) + int(holds)
                else:
                    for side in ("better", "worse"):
                        counts[f"least_{side}"] = min(counts.get(f"least_{side}", value[side]), value[side])
                        counts[f"most_{side}"] = max(counts.get(f"most_{side}", value[side]), value[side])
    return tally


def claims_across_routes(
    records: Mapping[str, Mapping[str, Any]], pooled: Mapping[str, Any], claims: Mapping[str, Mapping[str, str]]
) -> dict[str, dict[str, dict[str, Any]]]:
    """claim -> pair -> the routes' tally (claim_tally), the pooled cell ("+5.1 ▲", "3 ▲ 0 ▼ of 7")
    and its numbers (claim_values) as pooled_<key>."""
    tally = claim_tally(records, claims)
    across: dict[str, dict[str, dict[str, Any]]] = {}
    for name, claim in claims.items():
        across[name] = {
            pair: {**tally[name][pair], "pooled": claim_cell(value), **{f"pooled_{key}": v for key, v in value.items()}}
            for pair, value in claim_values(pooled, claim).items()
        }
    return across


def record_holds(record: Mapping[str, Any], name: str, claim: Mapping[str, str]) -> bool:
    """Whether a record (claim_value_in's) has the claim's numbers: a run made before the claim's
    learner or matcher existed has not."""
    if "routes" in record:
        return name in record["claims"]
    try:
        claim_values(record, claim)
    except ValueError:
        return False
    return True


def claim_value_in(record: Mapping[str, Any], name: str, claim: Mapping[str, str], pair: str) -> dict[str, Any]:
    """A claim's numbers on one pair as claim_values gives them ({difference, verdict} or {better,
    worse, of}): of one run's comparisons record, or pooled, of a replicate routes' record."""
    if "routes" in record:
        return {
            key.removeprefix("pooled_"): value
            for key, value in record["claims"][name][pair].items()
            if key.startswith("pooled_")
        }
    return claim_values(record, claim)[pair]
