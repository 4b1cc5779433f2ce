"""The presets are full copies of params.yaml: they must keep exactly its keys."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]


# season -> value maps: their keys are data, not schema (a preset may name a season params.yaml does not)
SEASON_MAPS = {"data.video_files", "data.offsets", "synthetic.rides", "split.test_every"}


def key_paths(tree: dict, prefix: str = "") -> set[str]:
    paths = set()
    for key, value in tree.items():
        paths.add(prefix + key)
        if isinstance(value, dict) and prefix + key not in SEASON_MAPS:
            paths |= key_paths(value, f"{prefix}{key}.")
    return paths


@pytest.mark.parametrize("preset", sorted((REPO / "presets").glob("*.yaml")), ids=lambda p: p.stem)
def test_preset_has_the_keys_of_params_yaml(preset):
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    assert key_paths(yaml.safe_load(preset.read_text())) == key_paths(params)
