"""Descriptors computed elsewhere (NetVLAD, DINOv2, ...), evaluated beside the study's learners.

Nothing is learned: `precomputed.dir` holds one array per season, <season>.npy of shape (frames, D),
one row per frame of that season's source in its order (a folder's images in natural order, a
video's samples at extract.fps), before data.frame_step and data.offsets pick the places. The
features stage asks for the rows of the season's test places (describe_places), so the external
descriptors go through exactly the evaluation, plots and report of the learners.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.models.core.learner import EpochCallback, FeatureLearner, PlaceRows
from seasonloop.params.checks import text


class PrecomputedDescriptors(FeatureLearner):
    """Rows of <dir>/<season>.npy, looked up by place."""

    name = "precomputed"
    learns = False
    PARAMS = {"dir": text}

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        folder = Path(self.params["dir"])
        if not folder.is_dir():
            raise FileNotFoundError(f"{folder}: precomputed.dir not found (one <season>.npy of descriptors per season)")
        return {"external": True, "dir": str(folder), "files": sorted(path.name for path in folder.glob("*.npy"))}

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        raise ValueError(
            "precomputed: descriptors computed elsewhere describe a season's places, not new images "
            "(it cannot be refitted, e.g. in ablation.learners)"
        )

    def describe_places(
        self, images: np.ndarray, rows: PlaceRows, batch_size: int = 1024, progress: bool = False
    ) -> np.ndarray:
        """The descriptors of rows.season's places: rows rows.rows of <dir>/<season>.npy, which must
        hold rows.n_frames rows, one per source frame, all finite."""
        self._require_fitted("describe_places")
        path = Path(self.params["dir"]) / f"{rows.season}.npy"
        if not path.is_file():
            raise FileNotFoundError(f"{path}: no precomputed descriptors for season '{rows.season}'")
        try:
            descriptors = np.load(path, mmap_mode="r", allow_pickle=False)
        except (ValueError, OSError, EOFError) as error:
            raise ValueError(f"{path}: cannot read descriptors ({error})") from None
        if not isinstance(descriptors, np.ndarray):
            descriptors.close()
            raise ValueError(f"{path}: cannot read descriptors (an .npz archive, not one array saved with np.save)")
        # complex or boolean descriptors would lose their meaning in the float32 cast below
        if descriptors.ndim != 2 or descriptors.dtype.kind not in "iuf":
            raise ValueError(
                f"{path}: expected a 2-D real-valued (frames, D) array, got {descriptors.shape} {descriptors.dtype}"
            )
        if len(descriptors) != rows.n_frames:
            raise ValueError(
                f"{path}: {len(descriptors)} rows of descriptors for the {rows.n_frames} frames of season "
                f"'{rows.season}' (one row per frame of its source, in order)"
            )
        chosen = np.asarray(descriptors[rows.rows], dtype=np.float32)
        if not np.isfinite(chosen).all():
            raise ValueError(
                f"{path}: NaN or infinite descriptors at {int((~np.isfinite(chosen)).any(1).sum())} test places"
            )
        return chosen

    def _save_state(self, directory: Path) -> None:
        """Nothing is learned; learner.json names the folder."""

    def _load_state(self, directory: Path) -> None:
        """Nothing is learned; learner.json names the folder."""
