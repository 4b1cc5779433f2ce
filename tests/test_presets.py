"""Presets are overlays: presets/<name>.yaml holds what differs from params.yaml (or from the
preset it builds on), and `python -m seasonloop.preset NAME` writes params.yaml with it applied."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from seasonloop.preset import composed_params, overlay, preset_changes

REPO = Path(__file__).resolve().parents[1]
PRESETS = sorted(path.stem for path in (REPO / "presets").glob("*.yaml"))
# the commit whose presets were full copies of params.yaml (the last before they became overlays),
# and those presets
FULL_COPIES = "d0eeca7"
REPLACED = ("full", "gpu", "patchnetvlad_nordland", "vpr_bench_nordland")


def apply_in_a_process(name: str, params: Path, presets: Path) -> subprocess.CompletedProcess:
    """`python -m seasonloop.preset NAME` on the params file, as a user runs it."""
    command = [sys.executable, "-m", "seasonloop.preset", name, "--params", str(params), "--presets", str(presets)]
    return subprocess.run(command, capture_output=True, text=True)


# keys renamed since the full copies (section, old name) -> today's name (CHANGELOG.md)
RENAMED = {("ablation", "methods"): "learners"}


def at_full_copies(path: str) -> dict | None:
    """A YAML file as it was when presets were full copies, in today's key names, or None without
    that history."""
    shown = subprocess.run(["git", "-C", str(REPO), "show", f"{FULL_COPIES}:{path}"], capture_output=True, text=True)
    if shown.returncode:
        return None
    old = yaml.safe_load(shown.stdout)
    for (section, key), name in RENAMED.items():
        if key in old.get(section, {}):
            old[section] = {name if entry == key else entry: value for entry, value in old[section].items()}
    return old


@pytest.mark.parametrize("name", REPLACED)
def test_each_preset_composes_to_the_full_copy_it_replaced(name):
    before, defaults_before = at_full_copies(f"presets/{name}.yaml"), at_full_copies("params.yaml")
    if before is None or defaults_before is None:
        pytest.skip(f"no git history of {FULL_COPIES} in this clone")
    defaults = yaml.safe_load((REPO / "params.yaml").read_text())
    composed = composed_params(name, REPO / "params.yaml", REPO / "presets")
    for section, values in before.items():
        # a key added since takes params.yaml's value; every key the full copy had is the same, but
        # for a default changed since that the preset did not set (it follows params.yaml)
        now = {key: composed[section][key] for key in values} if isinstance(values, dict) else composed[section]
        expected = (
            {
                key: defaults[section][key]
                if value == defaults_before[section].get(key) != defaults[section].get(key)
                else value
                for key, value in values.items()
            }
            if isinstance(values, dict)
            else defaults[section]
            if values == defaults_before[section] != defaults[section]
            else values
        )
        assert now == expected, section
    # sections added to params.yaml since (a new learner's) are in every preset
    assert composed.keys() - before.keys() == defaults.keys() - defaults_before.keys()
    assert before.keys() <= composed.keys()


@pytest.mark.parametrize("name", PRESETS)
def test_a_preset_holds_only_what_differs(name):
    changes = yaml.safe_load((REPO / "presets" / f"{name}.yaml").read_text())
    base_name = changes.pop("base", None)
    base = (
        composed_params(base_name, REPO / "params.yaml", REPO / "presets")
        if base_name
        else yaml.safe_load((REPO / "params.yaml").read_text())
    )
    same = [
        f"{section}.{key}"
        for section, values in changes.items()
        for key, value in (values.items() if isinstance(values, dict) else [("", values)])
        if (base[section][key] if key else base[section]) == value
    ]
    assert not same, f"presets/{name}.yaml repeats what it builds on: {same}"


def test_applying_writes_params_yaml_with_its_comments_and_the_preset_values(tmp_path):
    params = tmp_path / "params.yaml"
    params.write_text((REPO / "params.yaml").read_text())
    result = apply_in_a_process("full", params, REPO / "presets")
    assert result.returncode == 0, result.stderr
    text = params.read_text()
    assert text.startswith("# presets/full.yaml applied over this file by `python -m seasonloop.preset full`")
    assert "  seconds: 35768       # route length; second t of every season is the same place" in text
    assert yaml.safe_load(text) == composed_params("full", REPO / "params.yaml", REPO / "presets")


def test_a_base_is_applied_first_and_a_key_params_yaml_lacks_is_one_line(tmp_path):
    (tmp_path / "big.yaml").write_text("split:\n  section_length: 3000\n  gap: 20\n")
    (tmp_path / "bigger.yaml").write_text("base: big\nsplit:\n  gap: 30\nlearners: [pca]\n")
    assert preset_changes("bigger", tmp_path) == {"split": {"section_length": 3000, "gap": 30}, "learners": ["pca"]}
    params = {"split": {"section_length": 300, "gap": 10, "test_every": {}}, "learners": ["pca", "ica"]}
    # a season map is a value: replaced whole
    assert overlay(params, {"split": {"test_every": {"summer": 10}}})["split"]["test_every"] == {"summer": 10}
    (tmp_path / "typo.yaml").write_text("split:\n  gapp: 3\n")
    with pytest.raises(ValueError, match=r"typo.yaml: 'split.gapp' is not a key of params.yaml"):
        overlay(params, preset_changes("typo", tmp_path), str(tmp_path / "typo.yaml"))
    with pytest.raises(FileNotFoundError, match="no such preset"):
        preset_changes("none", tmp_path)


def test_a_bad_preset_leaves_params_yaml_as_it_was(tmp_path):
    params = tmp_path / "params.yaml"
    params.write_text("split:\n  gap: 10\n")
    (tmp_path / "presets").mkdir()
    (tmp_path / "presets" / "bad.yaml").write_text("split:\n  gapp: 3\n")
    result = apply_in_a_process("bad", params, tmp_path / "presets")
    assert result.returncode == 1 and result.stderr.count("\n") == 1 and "split.gapp" in result.stderr
    assert params.read_text() == "split:\n  gap: 10\n"
