"""The presets are full copies of params.yaml: they must keep exactly its keys."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]


def key_paths(tree: dict, prefix: str = "") -> set[str]:
    paths = set()
    for key, value in tree.items():
        paths.add(prefix + key)
        if isinstance(value, dict):
            paths |= key_paths(value, f"{prefix}{key}.")
    return paths


@pytest.mark.parametrize("preset", sorted((REPO / "presets").glob("*.yaml")), ids=lambda p: p.stem)
def test_preset_has_the_keys_of_params_yaml(preset):
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    assert key_paths(yaml.safe_load(preset.read_text())) == key_paths(params)
