"""Checks across the keys of one params.yaml section, run when the whole section is checked
(seasonloop.params.section.Section.check)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from seasonloop.params.checks import check_degree_columns

RIDE_ROUTE_LEFT_S = 10  # seconds of route a season's ride must have left after its start


def _check_split(section: Mapping[str, Any]) -> None:
    length, fraction, gap, folds = (section[key] for key in ("section_length", "test_fraction", "gap", "folds"))
    if fraction == 1:
        if folds != 1:
            raise ValueError(
                f"split.folds: {folds}, but split.test_fraction 1 already tests every place; set folds to 1"
            )
        return
    tiling = round(1 / fraction)
    if folds not in (1, tiling):
        raise ValueError(
            f"split.folds: {folds}; test blocks of split.test_fraction {fraction} tile a section in {tiling} folds: "
            f"set {tiling} (every place tested once) or 1 (the study's split)"
        )
    test = max(1, round(length * fraction))
    # the largest of a fold's blocks: the study's, or one of the K - 1 that share the rest
    block = test if folds == 1 else max(test, -(-(length - test) // (folds - 1)))
    if length - block - 2 * gap < 1:
        raise ValueError(
            f"split: a section of {length} places with a test block of {block} and gaps of {gap} "
            "on either side leaves no training place (split.section_length, test_fraction, gap, folds)"
        )


def _check_synthetic(section: Mapping[str, Any]) -> None:
    for kind in ("tunnel", "stop"):
        low, high = section[f"{kind}_min_s"], section[f"{kind}_max_s"]
        if high < low:
            raise ValueError(f"synthetic.{kind}_max_s: {high} is below synthetic.{kind}_min_s {low}")
    for season, ride in section["rides"].items():
        start = ride.get("start_s", 0)
        if start > section["seconds"] - RIDE_ROUTE_LEFT_S:
            raise ValueError(
                f"synthetic.rides.{season}.start_s: {start} leaves less than {RIDE_ROUTE_LEFT_S} s "
                f"of the {section['seconds']} s route (synthetic.seconds)"
            )


def _check_sequence(section: Mapping[str, Any]) -> None:
    if section["v_max"] < section["v_min"]:
        raise ValueError(f"sequence.v_max: {section['v_max']} is below sequence.v_min {section['v_min']}")


def _check_data(section: Mapping[str, Any]) -> None:
    degrees = section["ground_truth"] == "positions" and section["position_units"] == "degrees"
    if degrees and section["position_source"] == "image_names":
        raise ValueError("data.position_units: image names hold UTM metres (position_source image_names); set metres")
    if degrees:
        check_degree_columns(section["position_columns"])
    if section["ground_truth"] == "vpr_bench" and len(section["seasons"]) != 2:
        raise ValueError(
            f"data.seasons: VPR-Bench's ground truth holds two traverses, [reference, query]; got {list(section['seasons'])}"
        )


def _check_evaluate(section: Mapping[str, Any]) -> None:
    if section["metric"] in section["extra_metrics"]:
        raise ValueError(f"evaluate.extra_metrics: {section['metric']!r} is already evaluate.metric")


SECTION_CHECKS: dict[str, Callable[[Mapping[str, Any]], None]] = {
    "data": _check_data,
    "synthetic": _check_synthetic,
    "split": _check_split,
    "evaluate": _check_evaluate,
    "sequence": _check_sequence,
}
