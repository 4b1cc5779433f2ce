"""Common interface of the feature learners: params, fit, batched describe, save/load."""

from __future__ import annotations

import importlib
import json
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from tqdm.auto import tqdm

from seasonloop.params.checks import Check

LEARNER_FILE = "learner.json"

# Fit-info keys of the run, not the model (its time, its machine): fit() returns them for
# metrics/fit/<learner>.json but keeps them out of fit_info and models/, so the same params and data
# give the same model bytes on every run and DVC reruns nothing after a refit that changed nothing.
RUN_KEYS = ("training_seconds", "device", "torch_threads", "cpu_native_bfloat16")

EpochCallback = Callable[[int, dict[str, float]], None]

# Fit-info keys that say how an iterative fit ended (FeatureLearner.how_fit_ended)
ENDING_KEYS = ("converged", "gradient", "tol", "n_iter", "stop_reason", "epochs_run", "best_validation_loss")


@dataclass(frozen=True)
class PlaceRows:
    """Which frames of a season's source a batch of test images shows: the season, each image's
    row among the source's frames (before data.frame_step and data.offsets) and how many frames the
    source has; for learners whose descriptors exist per frame already (models/precomputed.py)."""

    season: str
    rows: np.ndarray
    n_frames: int


def to_float(images: np.ndarray) -> np.ndarray:
    """uint8 (N, H, W) -> float32 in [0, 1]; float input is passed through as float32."""
    array = np.asarray(images)
    if array.ndim != 3:
        raise ValueError(f"images must have shape (N, H, W), got shape {array.shape}")
    if array.dtype == np.uint8:
        return array.astype(np.float32) / np.float32(255.0)
    if np.issubdtype(array.dtype, np.floating):
        return array.astype(np.float32, copy=False)
    raise ValueError(f"images must be uint8 or float, got dtype {array.dtype}")


def select_training_subset(images: np.ndarray, max_images: int, seed: int) -> tuple[np.ndarray, dict[str, int]]:
    """At most max_images images drawn at random (seeded, kept in order); 0 means all.

    Returns the images and a JSON-ready record of what was used.
    """
    n_available = len(images)
    if max_images == 0 or max_images >= n_available:
        chosen = images
    else:
        rng = np.random.default_rng(seed)
        chosen = images[np.sort(rng.choice(n_available, size=max_images, replace=False))]
    return chosen, {"n_train_images_available": n_available, "n_train_images": len(chosen)}


def with_contiguous_arrays(estimator: Any) -> Any:
    """Give a fitted estimator C-contiguous copies of its non-contiguous array attributes.

    Pickling stores such arrays contiguously, and BLAS rounding depends on memory layout, so
    without this a saved-and-loaded estimator would not reproduce descriptors bit for bit.
    """
    for key, value in vars(estimator).items():
        if isinstance(value, np.ndarray) and not (value.flags.c_contiguous or value.flags.f_contiguous):
            setattr(estimator, key, np.ascontiguousarray(value))
    return estimator


def to_json_value(value: Any) -> Any:
    """Convert numpy scalars/arrays (possibly nested) to plain Python for json.dump."""
    if isinstance(value, Mapping):
        return {str(key): to_json_value(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_value(item) for item in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


class FeatureLearner(ABC):
    """A learner: (N, H, W) images -> (N, D) float32 descriptors. Subclasses set `name` and `PARAMS`
    and implement `_fit`, `_describe_batch`, `_save_state` and `_load_state` (`_validate_params`
    checks params across keys). Every stage imports a learner's module to check params.yaml first
    (seasonloop.registries.check_whole), so it imports torch or scikit-learn only inside the
    methods that compute (tests/test_models.py holds every learner module to it).
    """

    name: ClassVar[str]
    # its params section (named `name`): each key's check (seasonloop.params.checks); the values live
    # in params.yaml only (one default a setting), checked against PARAMS before any stage works (every
    # key set, none unknown) and again when the learner is built
    PARAMS: ClassVar[dict[str, Check]]
    # the libraries its methods import when they compute (torch, scikit-learn, ...): the fit stage
    # imports them before its timer starts, so that fit_seconds is the learner's work and not
    # Python's imports (tests/test_models.py: a fit imports nothing heavy that is not listed)
    LIBRARIES: ClassVar[tuple[str, ...]] = ()
    # whether fit() reports epochs to its on_epoch callback (the stage logs them with dvclive)
    trains_in_epochs: ClassVar[bool] = False
    # False: a descriptor that learns nothing from the training images (fit records their size only)
    learns: ClassVar[bool] = True
    # the fewest traverses its training images may come from (2: it learns from places seen twice)
    min_traverses: ClassVar[int] = 1
    # the study's figures its fitted model draws (keys of seasonloop.reporting.figures.FIGURES)
    figures: ClassVar[tuple[str, ...]] = ()
    # its settings in the tests' tiny runs (tools.small_runs: 36 x 64 images, a few hundred places),
    # where params.yaml's would fit for minutes: a fit of seconds that still does real work
    TINY_RUN: ClassVar[dict[str, Any]] = {}

    def __init__(self, params: Mapping[str, Any], seed: int = 0):
        self.check_params(params)
        self.params: dict[str, Any] = {key: params[key] for key in self.PARAMS}  # in PARAMS' order, as saved
        self.seed = int(seed)
        self.fit_info: dict[str, Any] | None = None
        self.input_shape: tuple[int, int] | None = None
        self._validate_params()

    @classmethod
    def how_fit_ended(cls, info: Mapping[str, Any]) -> dict[str, Any]:
        """What of a fit's info says whether the fit reached its definition of done (ICA's
        tolerance, an auto-encoder's validation plateau): its ENDING_KEYS; empty for a closed-form
        fit. A learner whose fit holds other fits adds theirs."""
        return {key: info[key] for key in ENDING_KEYS if key in info}

    @classmethod
    def import_libraries(cls) -> None:
        """Import LIBRARIES now, ahead of a timed fit."""
        for name in cls.LIBRARIES:
            importlib.import_module(name)

    @classmethod
    def check_params(cls, params: Mapping[str, Any]) -> None:
        """Check a learner's whole params section (params.yaml's holds every key: there are no
        defaults elsewhere); a ValueError names the first missing or unknown key or bad value."""
        if not isinstance(params, Mapping):
            raise ValueError(f"{cls.name}: expected a mapping of the learner's params, got {params!r}")
        for key, value in params.items():
            if key not in cls.PARAMS:
                raise ValueError(f"{cls.name}.{key}: unknown key (known: {', '.join(cls.PARAMS)})")
            cls.PARAMS[key](f"{cls.name}.{key}", value)
        missing = [key for key in cls.PARAMS if key not in params]
        if missing:
            raise ValueError(f"{cls.name}.{missing[0]}: missing (params.yaml's {cls.name} section sets every key)")

    # ----- param checks shared by the subclasses -----
    def _key(self, key: str) -> str:
        return f"{self.name}.{key}"

    @property
    def image_shape(self) -> tuple[int, int]:
        """(height, width) of the images the learner was fitted on (set before _fit runs)."""
        if self.input_shape is None:
            raise RuntimeError(f"{self.name}: not fitted yet")
        return self.input_shape

    def _validate_params(self) -> None:  # noqa: B027 (optional hook: most learners need none)
        """Raise ValueError for params that are fine one by one but not together (subclasses override;
        each value's own range and choices are checked by PARAMS)."""

    # ----- public API -----
    def fit(
        self,
        images: np.ndarray,
        progress: bool = True,
        on_epoch: EpochCallback | None = None,
        places: np.ndarray | None = None,
        traverses: np.ndarray | None = None,
    ) -> dict[str, Any]:
        """Learn from uint8 (N, H, W) training images; return JSON-serialisable fit info: the
        model's facts (kept as fit_info and saved with the model) and the run's (RUN_KEYS: time,
        device, threads; returned only).

        places: each image's place id (shared by its augmented copies and by every traverse's
        image of that place), for held-out validation places and place labels; None: each image its
        own place. traverses: each image's traverse; None: all one traverse.
        """
        images = np.asarray(images)
        if images.ndim != 3 or len(images) < 2:
            raise ValueError(f"{self.name}: training images must have shape (N, H, W) with N >= 2, got {images.shape}")
        places = np.arange(len(images)) if places is None else np.asarray(places)
        traverses = np.zeros(len(images), dtype=np.int64) if traverses is None else np.asarray(traverses)
        for key, labels in {"places": places, "traverses": traverses}.items():
            if labels.shape != (len(images),):
                raise ValueError(f"{self.name}: {len(images)} training images but {key} of shape {labels.shape}")
        self.train_places, self.train_traverses = places, traverses
        self.fit_info = None  # a failed re-fit must not leave the old fit looking valid
        self.input_shape = (int(images.shape[1]), int(images.shape[2]))
        info = to_json_value(self._fit(images, progress=progress, on_epoch=on_epoch))
        self.fit_info = {key: value for key, value in info.items() if key not in RUN_KEYS}
        return info

    def describe(self, images: np.ndarray, batch_size: int = 1024, progress: bool = False) -> np.ndarray:
        """(N, H, W) images -> (N, D) float32 descriptors, computed batch by batch (`progress`: a bar
        over the batches, for learners such as the CAE that take minutes per season)."""
        images = self._check_describe_input(images, "describe")
        return self._in_batches(images, batch_size, self._describe_batch, progress, f"{self.name} describe")

    def describe_places(
        self, images: np.ndarray, rows: PlaceRows, batch_size: int = 1024, progress: bool = False
    ) -> np.ndarray:
        """Descriptors of a season's test images, which show the source frames `rows`: the learners
        describe the images; a learner of descriptors computed elsewhere looks the rows up."""
        return self.describe(images, batch_size=batch_size, progress=progress)

    def save(self, directory: Path) -> None:
        """Write directory/learner.json plus the learned state."""
        self._require_fitted("save")
        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        record = {
            "name": self.name,
            "params": to_json_value(self.params),
            "seed": self.seed,
            "input_shape": list(self.image_shape),
            "fit_info": self.fit_info,
        }
        (directory / LEARNER_FILE).write_text(json.dumps(record, indent=2) + "\n")
        self._save_state(directory)

    @classmethod
    def load(cls, directory: Path) -> FeatureLearner:
        """Rebuild a fitted learner written by `save`."""
        record = read_learner_record(directory)
        if record["name"] != cls.name:
            raise ValueError(f"{Path(directory) / LEARNER_FILE} holds a '{record['name']}' learner, not '{cls.name}'")
        learner = cls(record["params"], seed=record["seed"])
        learner.input_shape = (int(record["input_shape"][0]), int(record["input_shape"][1]))
        learner.fit_info = record["fit_info"]
        learner._load_state(Path(directory))
        return learner

    # ----- helpers for subclasses -----
    def _require_fitted(self, action: str) -> None:
        if self.fit_info is None or self.input_shape is None:
            raise RuntimeError(f"{self.name}: call fit() (or load a saved learner) before {action}()")

    def _check_describe_input(self, images: np.ndarray, action: str) -> np.ndarray:
        """Check fitted state and that images are non-empty (N, H, W) of the trained size."""
        self._require_fitted(action)
        images = np.asarray(images)
        if images.ndim != 3 or len(images) == 0 or tuple(images.shape[1:]) != self.image_shape:
            raise ValueError(
                f"{self.name}: expected images of shape (N>=1, {self.image_shape[0]}, "
                f"{self.image_shape[1]}), got {images.shape}"
            )
        return images

    @staticmethod
    def _in_batches(
        images: np.ndarray,
        batch_size: int,
        describe_batch: Callable[[np.ndarray], np.ndarray],
        progress: bool = False,
        description: str = "describe",
    ) -> np.ndarray:
        """Apply describe_batch to consecutive batches and stack the (n, D) results as float32."""
        if batch_size < 1:
            raise ValueError(f"batch_size must be >= 1, got {batch_size}")
        starts = tqdm(
            range(0, len(images), batch_size), desc=description, unit="batch", disable=not progress, leave=False
        )
        return np.concatenate(
            [np.asarray(describe_batch(images[start : start + batch_size]), dtype=np.float32) for start in starts]
        )

    @abstractmethod
    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        """Fit on validated (N, H, W) images; return fit info."""

    @abstractmethod
    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        """Descriptors of one batch of validated images."""

    @abstractmethod
    def _save_state(self, directory: Path) -> None:
        """Write the learned arrays/estimators into directory."""

    @abstractmethod
    def _load_state(self, directory: Path) -> None:
        """Read what `_save_state` wrote."""


def read_learner_record(directory: Path) -> dict[str, Any]:
    """The parsed learner.json of a saved learner directory."""
    path = Path(directory) / LEARNER_FILE
    if not path.is_file():
        raise FileNotFoundError(f"no saved learner: {path} does not exist")
    return json.loads(path.read_text())
