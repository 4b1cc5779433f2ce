"""How the claims (docs/claims.yaml) read on other data, such as real Nordland frames, beside their
verdicts on the synthetic runs: the same comparison, the same paired test, and one word for how
the two agree (READINGS)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from seasonloop.reporting.comparisons import FLIPPED
from seasonloop.reporting.replicates import claim_value_in, record_holds


def claim_direction(value: Mapping[str, Any]) -> str:
    """One pair's claim_values as a verdict: the comparison's own, or a whole table's "better" /
    "worse" (its significant comparisons all that way), "mixed" (both ways) or "no difference"."""
    if "verdict" in value:
        return value["verdict"]
    if value["better"] and value["worse"]:
        return "mixed"
    return "better" if value["better"] else "worse" if value["worse"] else "no difference"


# how a claim's verdict on other data reads beside the synthetic runs' verdicts (reading_beside)
READINGS = {
    "holds": "significant the same way as on a synthetic run, and against none",
    "turns": "significant against a synthetic run's significant verdict",
    "not shown": "significant on a synthetic run, not on this data",
    "new": "significant on this data, on no synthetic run",
    "shown nowhere": "significant on no synthetic run and not on this data",
    "too few queries": "this data has too few queries to test it",
}


# the significant sides of a claim_direction
SIDES = {"better": {"better"}, "worse": {"worse"}, "mixed": {"better", "worse"}}


def reading_beside(synthetic: Sequence[str], other: str) -> str:
    """The READINGS key of a claim's verdict on other data (claim_direction) beside its verdicts
    on the synthetic runs (the default route, the routes pooled, the full preset)."""
    if other == "not enough queries":
        return "too few queries"
    shown = set().union(*(SIDES.get(direction, set()) for direction in synthetic))
    found = SIDES.get(other, set())
    if not found:
        return "not shown" if shown else "shown nowhere"
    if any(FLIPPED[side] in shown for side in found):
        return "turns"
    return "holds" if found & shown else "new"


def claims_beside(
    other: Mapping[str, Any], synthetic: Mapping[str, Mapping[str, Any]], claims: Mapping[str, Mapping[str, str]]
) -> dict[str, dict[str, dict[str, Any]]]:
    """claim -> pair of `other` (a run on other data: its comparisons record) -> {"values": column
    -> the claim's numbers (claim_value_in) in each synthetic record and in `other` (column
    "other"), None in a synthetic run made before the claim's learner or matcher existed,
    "reading": how other's verdict reads beside the synthetic runs that have one (reading_beside)}."""
    beside: dict[str, dict[str, dict[str, Any]]] = {}
    for name, claim in claims.items():
        beside[name] = {}
        held = {column: record for column, record in synthetic.items() if record_holds(record, name, claim)}
        for pair in other["order"]["pairs"]:
            values: dict[str, Any] = {column: None for column in synthetic}
            values.update({column: claim_value_in(record, name, claim, pair) for column, record in held.items()})
            values["other"] = claim_value_in(other, name, claim, pair)
            reading = reading_beside(
                [claim_direction(values[column]) for column in held], claim_direction(values["other"])
            )
            beside[name][pair] = {"values": values, "reading": reading}
    return beside


def claims_read_beside(
    other: Mapping[str, Any], synthetic: Sequence[Mapping[str, Any]], claims: Mapping[str, Mapping[str, str]]
) -> tuple[dict[str, Mapping[str, str]], list[str]]:
    """(the claims `other` and at least one synthetic record have numbers for, the names of the
    others): a claim needs its verdict on this data and on a synthetic run to be read beside it."""
    held = {
        name: claim
        for name, claim in claims.items()
        if record_holds(other, name, claim) and any(record_holds(record, name, claim) for record in synthetic)
    }
    return held, [name for name in claims if name not in held]
