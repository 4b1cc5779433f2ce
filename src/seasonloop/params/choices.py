"""The names and ranges of params.yaml's choices that no library registry holds, for the section
declarations (seasonloop.params.settings) and the library code that reads them. A choice that
selects one of a registry's entries (a distance, a matcher, a learner) is checked against that
registry itself (seasonloop.registries)."""

from __future__ import annotations

from seasonloop.params.checks import Check, number

# where positions come from: <positions_dir>/<season>.csv, or each image's name (gmberton's
# '@<utm_east>@<utm_north>@...' layout)
POSITION_SOURCES = ("csv", "image_names")
POSITION_UNITS = ("metres", "degrees")
# train.fitted: on this dataset, or elsewhere (learners fitted by another run, in train.models_dir)
WHERE_FITTED = ("here", "elsewhere")

# SeqSLAM's contrast-enhancement window spans at least 2 database columns
MIN_SEQUENCE_WINDOW = 2
# How SeqSLAM's contrast-enhancement window meets a break in the database's place ids
# (seasonloop.evaluation.sequence.enhancement_windows):
#   ignore: as OpenSeqSLAM, breaks are not looked at; windows are clipped at the database's ends only
#   shift:  a window of fixed size shifted to lie inside the column's segment (the whole segment when shorter)
#   clip:   clipped at the segment's ends (a 2-place segment then always enhances to +-1)
WINDOW_RULES = ("ignore", "shift", "clip")
# How the sequence descriptors' window (delta, smoothed) meets a break in the place ids
# (seasonloop.evaluation.descriptor_sequences):
#   shift: oravus/seqNet's (datasets.py getSeqInds): L frames, shifted to lie inside the segment
#          (the whole segment when shorter), with seqNet's Delta weights
#   clip:  clipped at the segment's ends, every frame its own window (the smoothing is then
#          DeltaDescriptors' zero-padded one); Delta the difference of the halves' means
DESCRIPTOR_WINDOW_RULES = ("shift", "clip")

# synthetic.rides.<season>: seasonloop.data.synthetic.SeasonRide's fields and their ranges, each
# optional; SeasonRide checks its fields with these
RIDE_SCHEMA: dict[str, Check] = {
    "speed": number(0.2, 5, low_open=True),
    "stop_scale": number(0, 10, low_open=True),
    "start_s": number(0),  # and at most synthetic.seconds - RIDE_ROUTE_LEFT_S (seasonloop.params.section_checks)
    "swing": number(0, 0.9, high_open=True),
}
