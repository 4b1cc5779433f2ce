"""The tests' own sequence settings: a test states only what it changes (`sequence_config(length=10)`), so a
new key of the section is one edit here."""

from seasonloop.params.settings import SequenceConfig

SEQUENCE = {
    "length": 3,
    "v_min": 1.0,
    "v_max": 1.0,
    "v_steps": 1,
    "window": 4,
    "window_at_breaks": "clip",
    "descriptor_window_at_breaks": "shift",
}


def sequence_config(**changes: object) -> SequenceConfig:
    """SequenceConfig of SEQUENCE with `changes` set (an unknown key is a TypeError)."""
    return SequenceConfig(**{**SEQUENCE, **changes})  # type: ignore[arg-type]
