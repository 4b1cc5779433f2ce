"""The schema of params.yaml: every key of every section with its check, and check_params, which runs it.

The checks of one value live in seasonloop.params.checks, seasons and pairs in seasonloop.params.seasons
(both re-exported here); the typed sections built after the check in seasonloop.params.settings.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from seasonloop.params.across import check_across

# re-exported, so that `from seasonloop.params.schema import SEASONS, parse_pair, ...` keeps working
from seasonloop.params.checks import (  # noqa: F401
    Check,
    boolean,
    check_degree_columns,
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
from seasonloop.params.learners import LEARNER_SCHEMA, check_learner
from seasonloop.params.seasons import (  # noqa: F401
    SEASONS,
    STUDY_PAIRS,
    TRAVERSE_KEYS,
    available_pairs,
    check_seasons,
    check_traverses,
    pair_name,
    pair_present,
    parse_pair,
)
from seasonloop.params.section_checks import SECTION_CHECKS

# ---- The schema of params.yaml ---------------------------------------------------------------
# Every key of every section, with its check; adding a param is one line here. The learner
# sections are checked by the learner classes themselves (unknown keys raise there), so they are
# only named here. A stage checks the keys it reads before it starts work (stages/_common.py).

# The names in the library's registries (README: where they are), repeated so that this module
# imports no heavy library; tests/test_config.py keeps each equal to its registry, in order.
DISTANCE_METRICS = ("cosine", "euclidean", "cityblock")
CONFIDENCES = ("distance", "ratio")
MATCHER_NAMES = ("single", "sequence")
CONTRAST_METHODS = ("clahe", "equalize", "none")
SOURCES = ("synthetic", "videos", "frames")
GROUND_TRUTHS = ("aligned", "positions", "matrix", "vpr_bench")
# where positions come from: <positions_dir>/<season>.csv, or each image's name (gmberton's
# '@<utm_east>@<utm_north>@...' layout)
POSITION_SOURCES = ("csv", "image_names")
POSITION_UNITS = ("metres", "degrees")
# the learner sections: their keys and checks are in seasonloop.params.learners
LEARNER_SECTIONS = tuple(LEARNER_SCHEMA)

# SeqSLAM's contrast-enhancement window spans at least 2 database columns
MIN_SEQUENCE_WINDOW = 2
# How SeqSLAM's contrast-enhancement window meets a break in the database's place ids
# (seasonloop.evaluation.sequence.enhancement_windows):
#   ignore: as OpenSeqSLAM, breaks are not looked at; windows are clipped at the database's ends only
#   shift:  a window of fixed size shifted to lie inside the column's segment (the whole segment when shorter)
#   clip:   clipped at the segment's ends (a 2-place segment then always enhances to +-1)
WINDOW_RULES = ("ignore", "shift", "clip")

# synthetic.rides.<season>: seasonloop.data.synthetic.SeasonRide's fields and ranges, each optional
# (tests/test_synthetic_rides.py keeps them in step)
RIDE_SCHEMA: dict[str, Check] = {
    "speed": number(0.2, 5, low_open=True),
    "stop_scale": number(0, 10, low_open=True),
    "start_s": number(0),  # and at most synthetic.seconds - RIDE_ROUTE_LEFT_S (seasonloop.params.section_checks)
    "swing": number(0, 0.9, high_open=True),
}

SCHEMA: dict[str, dict[str, Check]] = {
    "data": {
        "source": one_of(*SOURCES),
        "seasons": seasons,
        "videos_dir": text,
        "video_files": season_map(text),
        "frames_dir": text,
        "frame_step": integer(1),
        "offsets": season_map(integer(0)),
        # what makes a match correct (seasonloop.evaluation.ground_truth)
        "ground_truth": one_of(*GROUND_TRUTHS),
        "positions_dir": text,
        "position_source": one_of(*POSITION_SOURCES),
        "position_columns": list_of(text),
        "position_units": one_of(*POSITION_UNITS),
        "position_key": optional_text,
        "ground_truth_dir": text,
        # a file in frames_dir naming the images to keep (cleanImageNames.txt); "": every image
        "image_list": optional_text,
    },
    "synthetic": {
        "seconds": integer(10),
        "fps": integer(1),
        "width": integer(16),
        "height": integer(16),
        "seed": integer(0),
        # difficulty knobs (seasonloop.data.synthetic.RouteDifficulty); the speed swings by up to
        # 9.5 m/s around the cruise speed, so at 10 m/s and more the train never runs backwards
        "cruise_speed": number(10, 70),
        "brake_time": number(1, 120),
        "tunnel_every_s": number(0, None, low_open=True),
        "tunnel_min_s": integer(1),
        "tunnel_max_s": integer(1),
        "stop_every_s": number(0, None, low_open=True),
        "stop_min_s": integer(1),
        "stop_max_s": integer(1),
        "event_gap_s": integer(0),
        "edge_margin_s": integer(0),
        "winter_contrast": number(0, 2, low_open=True),
        "winter_shading": number(0, 2),
        "rides": season_map(record(RIDE_SCHEMA), allowed=SEASONS),
    },
    "extract": {
        "fps": number(0, None, low_open=True),
        "height": integer(8),
        "width": integer(8),
        "trim_to_shortest": boolean,
        "max_offset": integer(0),
    },
    "preprocess": {
        "height": integer(4),
        "width": integer(4),
        "contrast": one_of(*CONTRAST_METHODS),
        "clahe_clip": number(0, None, low_open=True),
        "clahe_grid": integer(1),
    },
    "split": {
        "section_length": integer(3),
        # more test than training places per section is no longer a training split; 1: the whole
        # route is tested (a protocol's), the learners train on other seasons (check_whole_route)
        "test_fraction": test_fraction,
        "gap": integer(0),
        "dark_threshold": number(0, 255),
        "stop_threshold": number(0),
        "test_every": season_map(integer(1)),
    },
    "augment": {
        "copies": integer(0),
        "horizontal_flip": boolean,
        "width_shift": number(0, 1, high_open=True),
        "height_shift": number(0, 1, high_open=True),
        "seed": integer(0),
    },
    "train": {"seasons": seasons, "augmented": boolean},
    "features": {"batch_size": integer(1)},
    "evaluate": {
        "pairs": list_of(pair),
        "metric": one_of(*DISTANCE_METRICS),
        "extra_metrics": list_of(one_of(*DISTANCE_METRICS), non_empty=False),
        "confidence": one_of(*CONFIDENCES),
        "ratio_exclusion": integer(0),
        "tolerance_frames": integer(0),
        "tolerance_m": number(0),
        "matchers": list_of(one_of(*MATCHER_NAMES)),
    },
    "sequence": {
        "length": integer(1),
        "v_min": number(0, None, low_open=True),
        "v_max": number(0, None, low_open=True),
        "v_steps": integer(1),
        # one source for the range: seasonloop.evaluation.sequence checks the same constant
        "window": integer(MIN_SEQUENCE_WINDOW),
        "window_at_breaks": one_of(*WINDOW_RULES),
    },
    "statistics": {
        "level": number(0, 1, low_open=True, high_open=True),
        "degrees_scale": number(0, None, low_open=True),
        "alpha": number(0, 1, low_open=True, high_open=True),
    },
    "ablation": {"methods": list_of(one_of(*LEARNER_SECTIONS)), "pair": pair, "training_seasons": list_of(seasons)},
    "report": {"example_pair": pair},
    "cae_widths": {
        # fractions of Table 5's channels [96, 256, 384] (seasonloop.ablations.cae_widths); [] skips the sweep
        "widths": list_of(number(0, 1, low_open=True), non_empty=False),
        "pairs": list_of(pair),
    },
}

# Top-level keys that are values, not sections.
TOP_LEVEL: dict[str, Check] = {"seed": integer(0), "learners": list_of(one_of(*LEARNER_SECTIONS))}


def check_params(params: Mapping[str, Any], keys: Sequence[str]) -> None:
    """Check the top-level keys of `params`, then each of `keys` ("split", or one key as "data.seasons").

    Raises a ValueError naming the first unknown, missing or out-of-range key. Learner sections
    are left to the learner classes, which reject unknown keys and bad values.
    """
    for name in params:
        if name not in SCHEMA and name not in TOP_LEVEL and name not in LEARNER_SECTIONS:
            raise ValueError(f"params.yaml: unknown key '{name}'")
    for key in keys:
        section_name, _, sub = key.partition(".")
        if section_name in LEARNER_SECTIONS:
            continue
        if section_name in TOP_LEVEL:
            if section_name not in params:
                raise ValueError(f"params.yaml: missing key '{section_name}'")
            TOP_LEVEL[section_name](section_name, params[section_name])
            continue
        if section_name not in SCHEMA:
            raise ValueError(f"params.yaml: unknown key '{key}'")
        schema = SCHEMA[section_name]
        section = params.get(section_name)
        if not isinstance(section, Mapping):
            raise ValueError(f"params.yaml: missing section '{section_name}'")
        if sub:
            if sub not in schema:
                raise ValueError(f"params.yaml: unknown key '{key}'")
            names = [sub]
        else:
            unknown = [name for name in section if name not in schema]
            if unknown:
                raise ValueError(f"{section_name}.{unknown[0]}: unknown key (known: {', '.join(schema)})")
            names = list(schema)
        for name in names:
            if name not in section:
                raise ValueError(f"params.yaml: missing key '{section_name}.{name}'")
            schema[name](f"{section_name}.{name}", section[name])
            if f"{section_name}.{name}" in TRAVERSE_KEYS:
                check_traverses(f"{section_name}.{name}", section[name], params)
        if not sub and section_name in SECTION_CHECKS:
            SECTION_CHECKS[section_name](section)


def check_whole(params: Mapping[str, Any]) -> None:
    """Check all of params.yaml before any stage works: every section of the schema whole, the
    top-level values and every learner section (a typo anywhere stops the first stage that runs,
    not the stage that reads it), then the checks across sections. Raises a ValueError naming the
    first bad key."""
    check_params(params, [*TOP_LEVEL, *SCHEMA])
    for name in LEARNER_SCHEMA:
        if name in params:
            check_learner(name, params[name])
    check_across(params)
