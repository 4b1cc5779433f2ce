"""params.yaml's sections, each key declared once: its type and, beside it, its check.

A section is a frozen dataclass whose fields are the section's keys (seasonloop.params.section);
`setting(check)` gives a field the check its value must pass (seasonloop.params.checks), and the
schema params.yaml is checked with is read from these fields. A key whose value names an entry of
one of the library's registries (a distance, a matcher, a learner) is declared here as text and
checked against that registry by the whole-file check (seasonloop.registries), which sits above
the registries. A new key is one field here and its value in params.yaml. The dataclass is what
the library receives instead of a raw dict, so a typo in a key is caught once, at the edge, and
the library's signatures say what they read; lists become tuples so that a config is immutable.
"""

from __future__ import annotations

from dataclasses import dataclass

from seasonloop.params.checks import (
    Check,
    boolean,
    integer,
    list_of,
    number,
    one_of,
    optional_text,
    pair,
    record,
    season_map,
    seasons,
    test_fraction,
    text,
)
from seasonloop.params.choices import (
    DESCRIPTOR_WINDOW_RULES,
    MIN_SEQUENCE_WINDOW,
    POSITION_SOURCES,
    POSITION_UNITS,
    RIDE_SCHEMA,
    WHERE_FITTED,
    WINDOW_RULES,
)
from seasonloop.params.seasons import SEASONS
from seasonloop.params.section import Section, setting


@dataclass(frozen=True)
class DataConfig(Section):
    NAME = "data"
    source: str = setting(text)
    seasons: tuple[str, ...] = setting(seasons)
    videos_dir: str = setting(text)
    video_files: dict[str, str] = setting(season_map(text))
    frames_dir: str = setting(text)
    frame_step: int = setting(integer(1))
    offsets: dict[str, int] = setting(season_map(integer(0)))
    # what makes a match correct (seasonloop.data.ground_truth)
    ground_truth: str = setting(text)
    positions_dir: str = setting(text)
    position_source: str = setting(one_of(*POSITION_SOURCES))
    position_columns: tuple[str, ...] = setting(list_of(text))
    position_units: str = setting(one_of(*POSITION_UNITS))
    position_key: str = setting(optional_text)
    ground_truth_dir: str = setting(text)
    # a file in frames_dir naming the images to keep (cleanImageNames.txt); "": every image
    image_list: str = setting(optional_text)


@dataclass(frozen=True)
class SyntheticConfig(Section):
    NAME = "synthetic"
    seconds: int = setting(integer(10))
    fps: int = setting(integer(1))
    width: int = setting(integer(16))
    height: int = setting(integer(16))
    seed: int = setting(integer(0))
    # the route's difficulty knobs: seasonloop.data.synthetic.RouteDifficulty has the same fields
    # difficulty knobs (seasonloop.data.synthetic.RouteDifficulty); the speed swings by up to
    # 9.5 m/s around the cruise speed, so at 10 m/s and more the train never runs backwards
    cruise_speed: float = setting(number(10, 70))
    brake_time: float = setting(number(1, 120))
    tunnel_every_s: float = setting(number(0, None, low_open=True))
    tunnel_min_s: int = setting(integer(1))
    tunnel_max_s: int = setting(integer(1))
    stop_every_s: float = setting(number(0, None, low_open=True))
    stop_min_s: int = setting(integer(1))
    stop_max_s: int = setting(integer(1))
    event_gap_s: int = setting(integer(0))
    edge_margin_s: int = setting(integer(0))
    winter_contrast: float = setting(number(0, 2, low_open=True))
    winter_shading: float = setting(number(0, 2))
    # season -> some of SeasonRide's fields: that season's own ride (absent: the reference ride)
    rides: dict[str, dict[str, float]] = setting(season_map(record(RIDE_SCHEMA), allowed=SEASONS))


@dataclass(frozen=True)
class ExtractConfig(Section):
    NAME = "extract"
    fps: float = setting(number(0, None, low_open=True))
    height: int = setting(integer(8))
    width: int = setting(integer(8))
    trim_to_shortest: bool = setting(boolean)
    max_offset: int = setting(integer(0))


@dataclass(frozen=True)
class PreprocessConfig(Section):
    NAME = "preprocess"
    height: int = setting(integer(4))
    width: int = setting(integer(4))
    contrast: str = setting(text)
    clahe_clip: float = setting(number(0, None, low_open=True))
    clahe_grid: int = setting(integer(1))


@dataclass(frozen=True)
class SplitConfig(Section):
    NAME = "split"
    section_length: int = setting(integer(3))
    # more test than training places per section is no longer a training split; 1: the whole
    # route is tested (a protocol's), the learners train on other seasons or on a database
    # traverse, never on a query one (check_whole_route)
    test_fraction: float = setting(test_fraction)
    gap: int = setting(integer(0))
    # 1: the study's split; round(1 / test_fraction): blocked cross-validation, every place tested
    # once (seasonloop.data.split.fold_blocks; section_checks says which values a split allows)
    folds: int = setting(integer(1))
    dark_threshold: float = setting(number(0, 255))
    stop_threshold: float = setting(number(0))
    test_every: dict[str, int] = setting(season_map(integer(1)))


@dataclass(frozen=True)
class AugmentConfig(Section):
    NAME = "augment"
    copies: int = setting(integer(0))
    horizontal_flip: bool = setting(boolean)
    width_shift: float = setting(number(0, 1, high_open=True))
    height_shift: float = setting(number(0, 1, high_open=True))
    seed: int = setting(integer(0))


@dataclass(frozen=True)
class TrainConfig(Section):
    NAME = "train"
    seasons: tuple[str, ...] = setting(seasons)
    augmented: bool = setting(boolean)
    fitted: str = setting(one_of(*WHERE_FITTED))
    models_dir: str = setting(text)
    jobs: int = setting(integer(1))  # fits at once (a learner's folds: seasonloop.models.core.parallel)
    threads: int = setting(integer(0))  # threads each fit uses (0: the libraries' defaults)


@dataclass(frozen=True)
class FeaturesConfig(Section):
    NAME = "features"
    batch_size: int = setting(integer(1))


@dataclass(frozen=True)
class EvaluateConfig(Section):
    NAME = "evaluate"
    pairs: tuple[str, ...] = setting(list_of(pair))
    metric: str = setting(text)
    extra_metrics: tuple[str, ...] = setting(list_of(text, non_empty=False))
    confidence: str = setting(text)
    ratio_exclusion: int = setting(integer(0))
    tolerance_frames: int = setting(integer(0))
    tolerance_m: float = setting(number(0))
    matchers: tuple[str, ...] = setting(list_of(text))


@dataclass(frozen=True)
class StatisticsConfig(Section):
    NAME = "statistics"
    level: float = setting(number(0, 1, low_open=True, high_open=True))  # of every interval
    degrees_scale: float = setting(
        number(0, None, low_open=True)
    )  # a route of n queries has at most floor(degrees_scale * n^(2/3)) degrees of freedom
    persistence_scale: float = setting(
        number(0, None, low_open=True)
    )  # and at most floor(persistence_scale * (n^2 / omega)^(1/3)) where its runs have persistence omega
    alpha: float = setting(number(0, 1, low_open=True, high_open=True))  # of the paired tests, after Holm's correction


@dataclass(frozen=True)
class SequenceConfig(Section):
    NAME = "sequence"
    length: int = setting(integer(1))
    v_min: float = setting(number(0, None, low_open=True))
    v_max: float = setting(number(0, None, low_open=True))
    v_steps: int = setting(integer(1))
    # one source for the range: seasonloop.evaluation.sequence checks the same constant
    window: int = setting(integer(MIN_SEQUENCE_WINDOW))
    window_at_breaks: str = setting(one_of(*WINDOW_RULES))
    descriptor_window_at_breaks: str = setting(one_of(*DESCRIPTOR_WINDOW_RULES))


@dataclass(frozen=True)
class AblationConfig(Section):
    NAME = "ablation"
    learners: tuple[str, ...] = setting(list_of(text))
    pair: str = setting(pair)
    training_seasons: tuple[tuple[str, ...], ...] = setting(list_of(seasons))


@dataclass(frozen=True)
class CaeWidthsConfig(Section):
    NAME = "cae_widths"
    # fractions of Table 5's channels [96, 256, 384] (seasonloop.ablations.cae_widths); [] skips the sweep
    widths: tuple[float, ...] = setting(list_of(number(0, 1, low_open=True), non_empty=False))
    pairs: tuple[str, ...] = setting(list_of(pair))


@dataclass(frozen=True)
class ReportConfig(Section):
    NAME = "report"
    example_pair: str = setting(pair)


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


# every section's keys and checks, read from the dataclasses above
SCHEMA: dict[str, dict[str, Check]] = {section.NAME: section.checks() for section in SECTIONS}
