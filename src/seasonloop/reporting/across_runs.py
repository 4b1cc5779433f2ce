"""Two runs of the same queries, learner against itself: what the change between the runs (where
the learners were fitted, one setting) does to each learner's fraction correct, with the compare
stage's paired test along the route and Holm's correction per table (seasonloop.significance).

A table per evaluation (single images, `+seq`, ..., each distance) holds one comparison a learner:
its fraction correct in the first run minus that in the second, on the same queries (each pair's
query places must be the same in both runs)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.comparisons import Reader, legend, verdict_cell
from seasonloop.reporting.summary import markdown_table
from seasonloop.significance.tables import Variant, pair_comparisons

TABLE = "runs"  # a table's name: TABLE and the evaluation's suffix ("runs", "runs+seq", ...)


def runs_against(
    runs: Mapping[str, Reader],
    learners: Sequence[str],
    variants: Sequence[Variant],
    pairs: Sequence[str],
    settings: StatisticsConfig,
) -> dict[str, Any]:
    """The record of `runs` (two: name -> its per-query outcomes) compared learner by learner:
    per pair, table "runs<suffix>" (the evaluation's suffix: "" single images, "+seq",
    "@cityblock", ...) of each learner in the first run against itself in the second, its rows
    "<learner><suffix> (<run>)" (the shape of the compare stage's record, so claims can cite it)."""
    if len(runs) != 2:
        raise ValueError(f"compare two runs, not {len(runs)}")
    first, second = runs
    suffixes = [suffix for _, _, suffix in variants]
    tables = {
        TABLE + suffix: [(f"{learner}{suffix} ({first})", f"{learner}{suffix} ({second})") for learner in learners]
        for suffix in suffixes
    }
    source = {
        f"{learner}{suffix} ({run})": (run, learner, suffix)
        for run in runs
        for learner in learners
        for suffix in suffixes
    }

    def reader(pair: str):
        def outcome_of(label: str) -> tuple[np.ndarray, np.ndarray]:
            run, learner, suffix = source[label]
            return runs[run](learner, pair, suffix)

        return outcome_of

    return {
        "runs": [first, second],
        "learners": list(learners),
        "statistics": asdict(settings),
        "order": {"pairs": list(pairs), "tables": list(tables)},
        "pairs": {pair: pair_comparisons(reader(pair), tables, settings) for pair in pairs},
    }


def with_difference_interval(row: Mapping[str, Any]) -> str:
    """ "+5.1 ▲ [+2.3, +7.9]": a comparison's difference (points), its verdict (Holm's, over the
    table) and its own interval; the interval left out where the route is too short to give one."""
    cell = verdict_cell(row["difference"], row["verdict"])
    if row["low"] is None:
        return cell
    # a tenth: whole points would round an end just below 0 to "+0"
    return f"{cell} [{100 * row['low'] + 0.0:+.1f}, {100 * row['high'] + 0.0:+.1f}]"


def runs_against_markdown(record: Mapping[str, Any]) -> str:
    """One table a pair: a row per learner, a column per evaluation, each cell the first run's
    fraction correct minus the second's with its verdict and interval (with_difference_interval),
    then the legend."""
    first, second = record["runs"]
    blocks = []
    for pair in record["order"]["pairs"]:
        tables = record["pairs"][pair]
        frame = pd.DataFrame(
            {
                pair + name.removeprefix(TABLE): [with_difference_interval(row) for row in tables[name]]
                for name in record["order"]["tables"]
            },
            index=record["learners"],
        )
        blocks.append(markdown_table(frame, "learner").strip())
    return (
        "\n\n".join(blocks)
        + f"\n\nEach learner {first} against itself {second}; in brackets the difference's "
        + f"{100 * record['statistics']['level']:.0f}% interval (points), each comparison's own, before Holm's "
        + "correction, so an interval can leave out 0 where the table's verdict is no difference. "
        + legend(record["statistics"], f"{first} minus {second}")
        + "\n"
    )
