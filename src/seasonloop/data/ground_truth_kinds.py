"""What makes a match correct: the kinds of ground truth (data.ground_truth), one class each.

A kind says what extraction keeps (seasons paired frame by frame, or each its own frames; positions
read or not), how the split maps every season onto the first season's places, how one pair's
truth on the test places is built (seasonloop.data.ground_truth), and how the dataset table words
it. A new kind is one class here and one line of TRUTH_KINDS (data.ground_truth is checked against
its names, seasonloop.registries). Checks of data.* that depend on the kind (degrees only with positions,
VPR-Bench's two traverses) run with the params (seasonloop.params.section_checks).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import ClassVar

import numpy as np

from seasonloop.data.ground_truth import PairTruth, aligned_truth, matrix_truth, position_truth
from seasonloop.data.ground_truth_files import matrix_between, pair_matrix
from seasonloop.data.season_split import by_matrix, by_position
from seasonloop.io import load_array
from seasonloop.params.settings import EvaluateConfig

# (database, query) -> that pair's truth on the test places
PairBuilder = Callable[[str, str], PairTruth]


class TruthKind:
    """A kind of ground truth. `test`: season -> its test place ids; `counts`: season -> its
    places; `frames_dir`: where extraction wrote <season>_positions.npy; `truth_dir`:
    data.ground_truth_dir."""

    name: ClassVar[str]
    aligned: ClassVar[bool] = False  # frame i of every season is the same place (one route, one split)
    reads_positions: ClassVar[bool] = False  # extraction writes each place's position
    # a ground-truth file that sits in the dataset's folder beside its traverses' folders (in
    # data.frames_dir): extraction copies it beside the frames, where this kind reads it
    file_in_dataset: ClassVar[str | None] = None

    def reference_places(
        self, seasons: Sequence[str], counts: Mapping[str, int], frames_dir: Path, truth_dir: Path, tolerance_m: float
    ) -> dict[str, np.ndarray]:
        """season -> the first season's place for each of its frames (-1: none): how the split
        lays every season on the first one's route (kinds that are not aligned)."""
        raise NotImplementedError(f"data.ground_truth {self.name}: the seasons are one route (aligned)")

    def pair_builder(
        self,
        seasons: Sequence[str],
        test: Mapping[str, np.ndarray],
        counts: Mapping[str, int],
        evaluate: EvaluateConfig,
        frames_dir: Path,
        truth_dir: Path,
    ) -> PairBuilder:
        raise NotImplementedError

    def describe(self, evaluate: EvaluateConfig) -> str:
        """What makes a match correct, in words, for the dataset table."""
        raise NotImplementedError


class Aligned(TruthKind):
    name = "aligned"
    aligned = True

    def pair_builder(self, seasons, test, counts, evaluate, frames_dir, truth_dir) -> PairBuilder:
        return lambda database, query: aligned_truth(test[database], test[query], int(evaluate.tolerance_frames))

    def describe(self, evaluate: EvaluateConfig) -> str:
        return f"the query's own frame index +- {evaluate.tolerance_frames} places"


class Positions(TruthKind):
    name = "positions"
    reads_positions = True

    @staticmethod
    def _positions(seasons: Sequence[str], frames_dir: Path) -> dict[str, np.ndarray]:
        return {season: load_array(frames_dir / f"{season}_positions.npy") for season in seasons}

    def reference_places(self, seasons, counts, frames_dir, truth_dir, tolerance_m) -> dict[str, np.ndarray]:
        return by_position(self._positions(seasons, frames_dir), seasons[0], tolerance_m)

    def pair_builder(self, seasons, test, counts, evaluate, frames_dir, truth_dir) -> PairBuilder:
        positions = self._positions(seasons, frames_dir)
        tolerance = float(evaluate.tolerance_m)

        def build(database: str, query: str) -> PairTruth:
            at = positions[database][test[database]], positions[query][test[query]]
            return position_truth(*at, test[database], test[query], tolerance)

        return build

    def describe(self, evaluate: EvaluateConfig) -> str:
        return f"a database place within {float(evaluate.tolerance_m):g} m of the query's position"


class Matrix(TruthKind):
    """A boolean matrix per pair given with the data (seasonloop.data.ground_truth_files)."""

    name = "matrix"

    def traverses(self, seasons: Sequence[str]) -> tuple[str, str] | None:
        """VPR-Bench's (reference, query) traverses of its one file; None: a file per pair."""
        return None

    def reference_places(self, seasons, counts, frames_dir, truth_dir, tolerance_m) -> dict[str, np.ndarray]:
        first = seasons[0]
        mapped = {first: np.arange(counts[first])}
        for season in seasons[1:]:
            matrix = matrix_between(truth_dir, first, season, counts[first], counts[season], self.traverses(seasons))
            mapped[season] = by_matrix(matrix, f"{first}-{season}")
        return mapped

    def pair_builder(self, seasons, test, counts, evaluate, frames_dir, truth_dir) -> PairBuilder:
        traverses = self.traverses(seasons)

        def build(database: str, query: str) -> PairTruth:
            needed_for = f"the evaluation of {query} queries against the {database} database needs it"
            hard, soft, path = pair_matrix(
                truth_dir, database, query, counts[database], counts[query], needed_for, traverses
            )
            return matrix_truth(hard, soft, test[database], test[query], str(path))

        return build

    def describe(self, evaluate: EvaluateConfig) -> str:
        return "the ground-truth matrix given with the data ('hard'; 'soft' cells neither right nor wrong)"


class VprBench(Matrix):
    """VPR-Bench's ground_truth_new.npy: one file for its two traverses, data.seasons [reference,
    query], in the dataset's folder beside ref/ and query/ (data.frames_dir; data.ground_truth_dir
    is not read)."""

    name = "vpr_bench"
    file_in_dataset = "ground_truth_new.npy"

    def traverses(self, seasons: Sequence[str]) -> tuple[str, str] | None:
        return seasons[0], seasons[1]

    def reference_places(self, seasons, counts, frames_dir, truth_dir, tolerance_m) -> dict[str, np.ndarray]:
        return super().reference_places(seasons, counts, frames_dir, frames_dir, tolerance_m)

    def pair_builder(self, seasons, test, counts, evaluate, frames_dir, truth_dir) -> PairBuilder:
        return super().pair_builder(seasons, test, counts, evaluate, frames_dir, frames_dir)

    def describe(self, evaluate: EvaluateConfig) -> str:
        return "the reference places VPR-Bench's ground_truth_new.npy lists for the query"


TRUTH_KINDS: dict[str, TruthKind] = {kind.name: kind for kind in (Aligned(), Positions(), Matrix(), VprBench())}


def truth_kind(name: str) -> TruthKind:
    """The kind data.ground_truth names, or a ValueError naming the known ones."""
    if name not in TRUTH_KINDS:
        raise ValueError(f"data.ground_truth: unknown kind '{name}' (known: {', '.join(TRUTH_KINDS)})")
    return TRUTH_KINDS[name]
