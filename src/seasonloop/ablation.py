"""The training-season ablation (study Figure 18) fitted to the seasons a run actually has.

The study's defaults name all four seasons; a run on a subset (one real pair, say) keeps what it
can: the pair if both its seasons are present, else the first of evaluate.pairs that is; each list
of training seasons cut to the seasons present, repeats dropped. With fewer than two seasons
there is no pair to evaluate and the ablation is skipped, with the reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from seasonloop.config import check_seasons, pair_present, parse_pair


@dataclass(frozen=True)
class AblationPlan:
    pair: tuple[str, str] | None          # None when skipped
    season_sets: list[list[str]]
    notes: list[str] = field(default_factory=list)   # what was adapted, one line each
    skipped: str | None = None            # why nothing is fitted

    @property
    def labels(self) -> list[str]:
        return ["+".join(chosen) for chosen in self.season_sets]


def plan_ablation(seasons: Sequence[str], pair: str, training_seasons: Sequence[Sequence[str]],
                  evaluate_pairs: Sequence[str]) -> AblationPlan:
    """The pair and training-season lists to run with `seasons` present (see the module doc)."""
    parse_pair(pair, "ablation.pair")
    # names are checked against every season, so a typo is an error, not a silently dropped list
    requested = [check_seasons(chosen, "ablation.training_seasons") for chosen in training_seasons]
    if not requested:
        raise ValueError("ablation.training_seasons: expected a non-empty list of season lists")
    if len(seasons) < 2:
        return AblationPlan(None, [], skipped=f"skipped: it needs two seasons and data.seasons has only {list(seasons)}")
    (database, query), note = pair_present(pair, seasons, evaluate_pairs, "ablation.pair")
    notes = [note] if note else []
    season_sets: list[list[str]] = []
    for chosen in requested:
        kept = [season for season in chosen if season in seasons]
        if kept and kept not in season_sets:
            season_sets.append(kept)
    dropped = [chosen for chosen in requested if [s for s in chosen if s in seasons] != chosen]
    if dropped:
        notes.append("ablation.training_seasons: seasons not in data.seasons left out of "
                     + ", ".join("+".join(chosen) for chosen in dropped))
    if not season_sets:
        return AblationPlan(None, [], notes, skipped="skipped: no list of ablation.training_seasons has a season of data.seasons")
    return AblationPlan((database, query), season_sets, notes)
