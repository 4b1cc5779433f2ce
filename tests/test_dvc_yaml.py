"""DVC reads the project's YAML (params.yaml, dvc.yaml, dvc.lock, the presets) with ruamel.yaml's C
parser, and reads it the same as with the pure-Python one.

DVC parses these files several times a stage, and ruamel.yaml (0.19 on) uses its C parser only
when ruamel.yaml.clib is installed (pyproject.toml). Without it, restoring a one-learner tiny
pipeline from the run cache took 1.3x as long and every `dvc status` 1.4x
(benchmarks/speed/bench_dvc_yaml.py, docs/benchmarks.md), which the end-to-end tests pay hundreds of times.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from dvc.utils.serialize import parse_yaml
from ruamel.yaml import YAML
from ruamel.yaml.main import CParser

ROOT = Path(__file__).resolve().parents[1]
FILES = [
    "params.yaml",
    "dvc.yaml",
    "dvc.lock",
    *sorted(str(path.relative_to(ROOT)) for path in ROOT.glob("presets/*.yaml")),
]


def test_dvc_parses_yaml_with_the_c_parser() -> None:
    # DVC's parse_yaml builds YAML(typ="safe"): the C parser when ruamel.yaml.clib is importable
    assert CParser is not None, "ruamel.yaml.clib is not installed: pip install -c requirements.lock -e ."
    assert YAML(typ="safe").Parser is CParser


@pytest.mark.parametrize("name", FILES)
def test_the_c_parser_reads_the_projects_yaml_as_the_pure_one(name: str) -> None:
    text = (ROOT / name).read_text()  # dvc.lock is committed: every clone has it
    assert parse_yaml(text, name) == YAML(typ="safe", pure=True).load(text)
