"""Typed views of params.yaml: one frozen dataclass per section, built once, after checking.

`seasonloop.params.schema` owns the schema (which keys a section has and what each may hold) and names a
bad key in its error; a dataclass here is what the library receives instead of a raw dict, so a
typo in a key is caught once, at the edge, and the library's signatures say what they read.
Field names are the section's keys (tests/test_settings.py keeps both in step); lists become
tuples so that a config is immutable.

    split = SplitConfig.from_params(params)      # checks params["split"], then builds
    make_split(n_places, split, ...)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any, ClassVar, TypeVar

from seasonloop.params.schema import check_params

SectionT = TypeVar("SectionT", bound="Section")


def _frozen(value: Any) -> Any:
    """Lists (and lists of lists) as tuples; mappings as plain dicts of frozen values."""
    if isinstance(value, Mapping):
        return {key: _frozen(entry) for key, entry in value.items()}
    if isinstance(value, (list, tuple)):
        return tuple(_frozen(entry) for entry in value)
    return value


@dataclass(frozen=True)
class Section:
    """Base of the typed sections; `NAME` is the params.yaml section a subclass reads."""

    NAME: ClassVar[str]

    @classmethod
    def from_params(cls: type[SectionT], params: Mapping[str, Any]) -> SectionT:
        """Check section `NAME` of `params` against the schema (a bad key raises a ValueError that
        names it), then build the dataclass from it."""
        check_params(params, [cls.NAME])
        section = params[cls.NAME]
        return cls(**{field.name: _frozen(section[field.name]) for field in fields(cls)})

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(field.name for field in fields(cls))


@dataclass(frozen=True)
class DataConfig(Section):
    NAME = "data"
    source: str
    seasons: tuple[str, ...]
    videos_dir: str
    video_files: dict[str, str]
    frames_dir: str
    frame_step: int
    offsets: dict[str, int]
    ground_truth: str
    positions_dir: str
    position_source: str
    position_columns: tuple[str, ...]
    position_units: str
    position_key: str
    ground_truth_dir: str
    image_list: str


@dataclass(frozen=True)
class SyntheticConfig(Section):
    NAME = "synthetic"
    seconds: int
    fps: int
    width: int
    height: int
    seed: int
    # the route's difficulty knobs: seasonloop.data.synthetic.RouteDifficulty has the same fields
    cruise_speed: float
    brake_time: float
    tunnel_every_s: float
    tunnel_min_s: int
    tunnel_max_s: int
    stop_every_s: float
    stop_min_s: int
    stop_max_s: int
    event_gap_s: int
    edge_margin_s: int
    winter_contrast: float
    winter_shading: float
    # season -> some of SeasonRide's fields: that season's own ride (absent: the reference ride)
    rides: dict[str, dict[str, float]]


@dataclass(frozen=True)
class ExtractConfig(Section):
    NAME = "extract"
    fps: float
    height: int
    width: int
    trim_to_shortest: bool
    max_offset: int


@dataclass(frozen=True)
class PreprocessConfig(Section):
    NAME = "preprocess"
    height: int
    width: int
    contrast: str
    clahe_clip: float
    clahe_grid: int


@dataclass(frozen=True)
class SplitConfig(Section):
    NAME = "split"
    section_length: int
    test_fraction: float
    gap: int
    dark_threshold: float
    stop_threshold: float
    test_every: dict[str, int]


@dataclass(frozen=True)
class AugmentConfig(Section):
    NAME = "augment"
    copies: int
    horizontal_flip: bool
    width_shift: float
    height_shift: float
    seed: int


@dataclass(frozen=True)
class TrainConfig(Section):
    NAME = "train"
    seasons: tuple[str, ...]
    augmented: bool


@dataclass(frozen=True)
class FeaturesConfig(Section):
    NAME = "features"
    batch_size: int


@dataclass(frozen=True)
class EvaluateConfig(Section):
    NAME = "evaluate"
    pairs: tuple[str, ...]
    metric: str
    extra_metrics: tuple[str, ...]
    confidence: str
    ratio_exclusion: int
    tolerance_frames: int
    tolerance_m: float
    matchers: tuple[str, ...]


@dataclass(frozen=True)
class StatisticsConfig(Section):
    NAME = "statistics"
    level: float  # of every interval
    degrees_scale: float  # a route of n queries has floor(degrees_scale * n^(2/3)) degrees of freedom
    alpha: float  # of the paired tests, after Holm's correction


@dataclass(frozen=True)
class SequenceConfig(Section):
    NAME = "sequence"
    length: int
    v_min: float
    v_max: float
    v_steps: int
    window: int
    window_at_breaks: str


@dataclass(frozen=True)
class AblationConfig(Section):
    NAME = "ablation"
    methods: tuple[str, ...]
    pair: str
    training_seasons: tuple[tuple[str, ...], ...]


@dataclass(frozen=True)
class CaeWidthsConfig(Section):
    NAME = "cae_widths"
    widths: tuple[float, ...]
    pairs: tuple[str, ...]


@dataclass(frozen=True)
class ReportConfig(Section):
    NAME = "report"
    example_pair: str


SECTIONS: tuple[type[Section], ...] = (
    DataConfig,
    SyntheticConfig,
    ExtractConfig,
    PreprocessConfig,
    SplitConfig,
    AugmentConfig,
    TrainConfig,
    FeaturesConfig,
    EvaluateConfig,
    SequenceConfig,
    StatisticsConfig,
    AblationConfig,
    CaeWidthsConfig,
    ReportConfig,
)
