"""The paired comparisons of a run (metrics/comparisons.json): computed from the evaluate stages'
per-query outcomes (run_comparisons; the statistics in seasonloop.significance.tables), and shown
as tables a reader takes in at a glance: per season pair a learner x learner matrix, and per learner what
sequence matching and the extra distance change; the same tables for the report and docs.

A cell reads "+5.1 ▲": the row's fraction correct minus the column's (or the variant's minus the
reference's) in percentage points, ▲ significantly better, ▼ significantly worse, · no difference
shown (the paired test along the route, Holm-corrected across its table, below alpha:
seasonloop.significance.paired).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.html import Section, Table, Text
from seasonloop.reporting.summary import markdown_table
from seasonloop.significance.tables import Variant, comparison_tables, pair_comparisons

SYMBOLS = {"better": "▲", "worse": "▼", "no difference": "·", "not enough queries": "(too few queries)"}
# a comparison too short to test is so either way round
FLIPPED = {
    "better": "worse",
    "worse": "better",
    "no difference": "no difference",
    "not enough queries": "not enough queries",
}


def legend(settings: Mapping[str, Any], cell: str = "the row's fraction correct minus the column's") -> str:
    """What a cell says (`cell`: what its number is), at the record's statistics settings (a record
    written before 36a7aeb, whose settings name a bootstrap block length, says so: its verdicts are
    the old rule's)."""
    if "block_length" in settings:
        test = (
            "by the rule before 36a7aeb (McNemar's exact test Holm-corrected across the table, and a paired "
            f"moving-block bootstrap interval, blocks of {settings['block_length']}, excluding 0), which calls "
            "equal learners different more often than it says (docs/statistics.md)."
        )
    else:
        test = (
            "(a t test of the per-query differences that allows for runs along the route, Holm-corrected across "
            "the table; its real error rates: docs/statistics.md)."
        )
    return (
        f"Cells: {cell}, percentage points, on the same queries; "
        f"▲ significantly better, ▼ significantly worse, · no difference shown at {100 * settings['alpha']:g}% " + test
    )


Reader = Callable[[str, str, str], tuple[np.ndarray, np.ndarray]]  # (learner, pair, suffix) -> (places, correct)


def csv_reader(outcomes_dir: Path) -> Reader:
    """The per-query outcomes an evaluate stage wrote: outcomes_dir/<learner>/<pair><suffix>.csv."""

    def read(learner: str, pair: str, suffix: str) -> tuple[np.ndarray, np.ndarray]:
        outcomes = QueryOutcomes.read_csv(outcomes_dir / learner / f"{pair}{suffix}.csv")
        return outcomes.query_place, outcomes.correct

    return read


def run_comparisons(
    outcomes_dir: Path,
    learners: Sequence[str],
    variants: Sequence[Variant],
    pairs: Sequence[str],
    settings: StatisticsConfig,
) -> dict[str, Any]:
    """Every table of every season pair from outcomes_dir/<learner>/<pair><suffix>.csv, with the
    settings they were computed under and the order of pairs and tables."""
    return comparisons_of(csv_reader(outcomes_dir), learners, variants, pairs, settings)


def comparisons_of(
    read: Reader,
    learners: Sequence[str],
    variants: Sequence[Variant],
    pairs: Sequence[str],
    settings: StatisticsConfig,
    segments_of: Callable[[str], Sequence[int]] | None = None,
) -> dict[str, Any]:
    """run_comparisons' record from any reader of per-query outcomes (one run's, or several runs'
    one after another: seasonloop.reporting.replicates, whose segments_of(pair) gives each run's
    number of queries, independent routes; by default a pair's queries are one route's)."""
    tables = comparison_tables(learners, variants)
    source = {learner + suffix: (learner, suffix) for learner in learners for _, _, suffix in variants}

    def reader(pair: str) -> Callable[[str], tuple[np.ndarray, np.ndarray]]:
        def outcome_of(label: str) -> tuple[np.ndarray, np.ndarray]:
            learner, suffix = source[label]
            return read(learner, pair, suffix)

        return outcome_of

    return {
        "statistics": asdict(settings),
        # JSON objects come back with sorted keys: the run's order of pairs and tables
        "order": {"pairs": list(pairs), "tables": list(tables)},
        "pairs": {
            pair: pair_comparisons(reader(pair), tables, settings, segments_of(pair) if segments_of else None)
            for pair in pairs
        },
    }


def in_order(record: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """record["pairs"] in the run's order of pairs and of tables (record["order"])."""
    return {
        pair: {name: record["pairs"][pair][name] for name in record["order"]["tables"]}
        for pair in record["order"]["pairs"]
    }


def verdict_cell(difference: float, verdict: str) -> str:
    # + 0.0 turns -0.0 (a tie seen from the other side) into +0.0
    return f"{100 * difference + 0.0:+.1f} {SYMBOLS[verdict]}"


def learner_matrix(rows: Sequence[Mapping[str, Any]], labels: Sequence[str]) -> pd.DataFrame:
    """labels x labels cells (row against column) from one learners table's comparisons."""
    cells = {(row, column): "" for row in labels for column in labels}
    for comparison in rows:
        first, second = comparison["first"], comparison["second"]
        cells[(first, second)] = verdict_cell(comparison["difference"], comparison["verdict"])
        cells[(second, first)] = verdict_cell(-comparison["difference"], FLIPPED[comparison["verdict"]])
    return pd.DataFrame([[cells[(row, column)] for column in labels] for row in labels], index=labels, columns=labels)


def versus_table(pairs: Mapping[str, Mapping[str, Sequence[Mapping[str, Any]]]], table: str) -> pd.DataFrame:
    """One row per comparison of `table` ("matchers", "distances", ...), one column per season
    pair: "ica+seq vs ica" rows, say, across every pair."""
    columns = {}
    for pair, tables in pairs.items():
        columns[pair] = {
            f"{entry['first']} vs {entry['second']}": verdict_cell(entry["difference"], entry["verdict"])
            for entry in tables[table]
        }
    return pd.DataFrame(columns)


def verdict_counts(pairs: Mapping[str, Mapping[str, Sequence[Mapping[str, Any]]]]) -> pd.DataFrame:
    """Per table (rows) and season pair (columns): "significant / compared"."""
    names = list(dict.fromkeys(name for tables in pairs.values() for name in tables))
    return pd.DataFrame(
        {
            pair: {
                name: f"{sum(entry['verdict'] in ('better', 'worse') for entry in tables[name])} / {len(tables[name])}"
                for name in names
            }
            for pair, tables in pairs.items()
        }
    )


def comparison_frames(record: Mapping[str, Any], learners: Sequence[str]) -> list[tuple[str, pd.DataFrame]]:
    """(caption, table) of every table the report and docs show from a comparisons record: the
    learner matrix of each pair under the main evaluation (table "learners"), what each other
    table ("matchers", "distances", ...) finds per learner across pairs, and how many comparisons
    of every table are significant."""
    pairs = in_order(record)
    frames = [
        (
            f"{pair}: learner against learner, evaluate.metric, single images",
            learner_matrix(tables["learners"], learners),
        )
        for pair, tables in pairs.items()
    ]
    names: list[str] = list(next(iter(pairs.values()), {}))
    for name in names:
        if not name.startswith("learners"):
            frames.append(
                (f"{name}: each learner's variant against its reference, per pair", versus_table(pairs, name))
            )
    frames.append(("Significant differences / comparisons, per table and pair", verdict_counts(pairs)))
    return frames


def comparisons_markdown(record: Mapping[str, Any], learners: Sequence[str]) -> str:
    """Every table of comparison_frames as markdown, with the settings and the legend."""
    settings = record["statistics"]
    degrees = f"{settings['degrees_scale']:g} n^(2/3)"
    if "persistence_scale" in settings:  # records before it have the first rule alone
        degrees = f"min({degrees}, {settings['persistence_scale']:g} (n^2 / omega)^(1/3)), omega the runs' persistence"
    lines = [
        f"Paired comparisons, {100 * settings['level']:.0f}% intervals along the route (degrees of freedom "
        f"{degrees}), alpha {settings['alpha']}. " + legend(settings),
        "",
    ]
    for caption, frame in comparison_frames(record, learners):
        lines += [f"**{caption}**", "", markdown_table(frame, "")]
    return "\n".join(lines)


def comparisons_section(record: Mapping[str, Any], learners: Sequence[str]) -> Section:
    """The report's section of paired comparisons: comparison_frames' tables with the legend."""
    settings = record["statistics"]
    intro = (
        f"Is a difference real? Each pair's queries are compared paired, learner against learner on the same "
        f"queries; intervals are {100 * settings['level']:.0f}% and allow for successes coming in runs along "
        "a route (a long-run variance from the per-query differences' low-frequency cosine terms). " + legend(settings)
    )
    return Section(
        "Paired comparisons",
        [Text(intro), *(Table(caption, frame) for caption, frame in comparison_frames(record, learners))],
    )


def find_comparison(rows: Sequence[Mapping[str, Any]], first: str, second: str) -> tuple[float, str]:
    """(first's fraction correct minus second's, first's verdict) from a table's rows, stored in
    either order; a ValueError when the table does not compare the two."""
    for row in rows:
        if (row["first"], row["second"]) == (first, second):
            return row["difference"], row["verdict"]
        if (row["first"], row["second"]) == (second, first):
            return -row["difference"], FLIPPED[row["verdict"]]
    raise ValueError(f"no comparison of {first} with {second} in this table")


def claim_values(record: Mapping[str, Any], claim: Mapping[str, str]) -> dict[str, dict[str, Any]]:
    """pair -> the claim's numbers: {difference, verdict} (first side's) for one comparison,
    {better, worse, of} (its significant comparisons each way, of how many) for a whole table."""
    values: dict[str, dict[str, Any]] = {}
    for pair, tables in in_order(record).items():
        if claim["table"] not in tables:
            raise ValueError(f"claim on table {claim['table']!r}: the run has no such table (it has {sorted(tables)})")
        rows = tables[claim["table"]]
        if "first" in claim:
            difference, verdict = find_comparison(rows, claim["first"], claim["second"])
            values[pair] = {"difference": difference, "verdict": verdict}
        else:
            values[pair] = {
                "better": sum(row["verdict"] == "better" for row in rows),
                "worse": sum(row["verdict"] == "worse" for row in rows),
                "of": len(rows),
            }
    return values


def claim_cell(value: Mapping[str, Any]) -> str:
    """One pair's claim_values as a cell: "+5.1 ▲" for one comparison, "3 ▲ 0 ▼ of 7" for a whole table."""
    if "verdict" in value:
        return verdict_cell(value["difference"], value["verdict"])
    return f"{value['better']} ▲ {value['worse']} ▼ of {value['of']}"


def claim_cells(record: Mapping[str, Any], claim: Mapping[str, str]) -> dict[str, str]:
    """pair -> the claim's cell (claim_cell)."""
    return {pair: claim_cell(value) for pair, value in claim_values(record, claim).items()}


def claims_markdown(record: Mapping[str, Any], claims: Mapping[str, Mapping[str, str]]) -> str:
    """The claims (docs/claims.yaml) as a markdown table: id, what it compares, a cell per pair."""
    pairs = list(record["order"]["pairs"])
    lines = ["| claim | compares | " + " | ".join(pairs) + " |", "|" + "---|" * (len(pairs) + 2)]
    for name, claim in claims.items():
        cells = claim_cells(record, claim)
        lines.append(f"| {name} | {claim['says']} | " + " | ".join(cells[pair] for pair in pairs) + " |")
    return (
        "\n".join(lines) + "\n\n" + legend(record["statistics"]) + " Whole tables: significant differences each way.\n"
    )
