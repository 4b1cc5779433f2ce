"""Presets: a params.yaml for another scale or protocol, declared as only what it changes.

presets/<name>.yaml holds the values that differ from params.yaml, section by section, and may name
another preset it builds on (`base: full`). Applying one writes params.yaml with those values set
and everything else, comments included, as it was:

    python -m seasonloop.preset NAME [--params params.yaml] [--presets presets]

run from the repository root; `dvc repro` then runs the preset, `git checkout params.yaml` goes
back. A section's keys are set one by one; a value (a number, a list, a season map) is replaced
whole. A key that params.yaml does not have is an error naming the preset and the key, so a preset
cannot drift from the schema unnoticed.
"""

from __future__ import annotations

import argparse
import io
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

BASE = "base"  # a preset's key naming the preset it builds on


def preset_changes(name: str, folder: Path) -> dict[str, Any]:
    """The values preset `name` (folder/<name>.yaml) sets, its base's first."""
    path = folder / f"{name}.yaml"
    if not path.is_file():
        known = ", ".join(sorted(p.stem for p in folder.glob("*.yaml"))) or "none"
        raise FileNotFoundError(f"{path}: no such preset (known: {known})")
    own = yaml.safe_load(path.read_text()) or {}
    if not isinstance(own, Mapping):
        raise ValueError(f"{path}: expected a mapping of sections")
    own = dict(own)
    base = own.pop(BASE, None)
    changes = preset_changes(str(base), folder) if base is not None else {}
    for section, values in own.items():
        if isinstance(values, Mapping) and isinstance(changes.get(section), Mapping):
            changes[section] = {**changes[section], **values}
        else:
            changes[section] = values
    return changes


def overlay(params: Mapping[str, Any], changes: Mapping[str, Any], source: str = "preset") -> dict[str, Any]:
    """params with `changes` set: a section's keys one by one, any other value whole."""
    result = {key: dict(value) if isinstance(value, Mapping) else value for key, value in params.items()}
    for section, values in changes.items():
        if section not in result:
            raise ValueError(f"{source}: '{section}' is not a key of params.yaml")
        if isinstance(result[section], dict):
            if not isinstance(values, Mapping):
                raise ValueError(f"{source}: '{section}' is a section of params.yaml, not a value")
            for key, value in values.items():
                if key not in result[section]:
                    raise ValueError(f"{source}: '{section}.{key}' is not a key of params.yaml")
                result[section][key] = value
        else:
            result[section] = values
    return result


def composed_params(name: str, params: Path, folder: Path) -> dict[str, Any]:
    """The params preset `name` makes of the params file, as a dict (what apply_preset writes)."""
    return overlay(yaml.safe_load(params.read_text()), preset_changes(name, folder), f"{folder / name}.yaml")


def applied_text(params_text: str, changes: Mapping[str, Any], header: str, source: str = "preset") -> str:
    """params.yaml's text with `changes` set (overlay), its comments and layout kept (ruamel.yaml's
    round trip, as DVC's own `-S` edits it), under a `header` comment."""
    from ruamel.yaml import YAML
    from ruamel.yaml.comments import CommentedMap, CommentedSeq

    document = YAML()
    document.width, document.preserve_quotes = 4096, True
    document.indent(mapping=2, sequence=4, offset=2)
    tree = document.load(params_text)
    overlay(tree, changes, source)  # the checks, before anything is written

    def like(old: Any, new: Any) -> Any:
        """new as a ruamel container in old's style (flow or block), old's trailing comment kept."""
        if isinstance(new, list):
            converted: Any = CommentedSeq([like(None, item) for item in new])
        elif isinstance(new, Mapping):
            converted = CommentedMap({key: like(None, item) for key, item in new.items()})
        else:
            return new
        block = isinstance(old, (CommentedSeq, CommentedMap)) and old.fa.flow_style() is False
        if block:
            converted.ca.end = old.ca.end  # the blank line or comment after a block's last item
        else:
            converted.fa.set_flow_style()
        return converted

    for section, values in changes.items():
        if isinstance(tree[section], CommentedMap):
            for key, value in values.items():
                tree[section][key] = like(tree[section][key], value)
        else:
            tree[section] = like(tree[section], values)
    text = io.StringIO()
    document.dump(tree, text)
    return "".join(f"# {line}\n" for line in header.splitlines()) + text.getvalue()


def preset_text(name: str, params_text: str, folder: Path, params_name: str = "params.yaml") -> str:
    """The text apply_preset writes: params_text with preset `name` (folder/<name>.yaml) applied."""
    header = (
        f"{folder.name}/{name}.yaml applied over this file by `python -m seasonloop.preset {name}` "
        f"(`git checkout {params_name}` goes back)"
    )
    return applied_text(params_text, preset_changes(name, folder), header, f"{folder / name}.yaml")


def apply_preset(name: str, params: Path, folder: Path) -> dict[str, Any]:
    """Write preset `name` over the params file (see the module doc); the values it set."""
    changes = preset_changes(name, folder)
    params.write_text(preset_text(name, params.read_text(), folder, params.name))
    return changes


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Apply a preset: params.yaml with the values of presets/<NAME>.yaml set."
    )
    parser.add_argument("name", help="the preset: presets/<NAME>.yaml")
    parser.add_argument("--params", type=Path, default=Path("params.yaml"))
    parser.add_argument("--presets", type=Path, default=Path("presets"))
    args = parser.parse_args(argv)
    try:
        changes = apply_preset(args.name, args.params, args.presets)
    except (OSError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    keys = sum(len(values) if isinstance(values, dict) else 1 for values in changes.values())
    print(f"{args.params}: {keys} values of {args.presets / args.name}.yaml set")
    return 0


if __name__ == "__main__":
    sys.exit(main())
