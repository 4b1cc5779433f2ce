"""Which committed state a finished run in another folder is: its commit, and the preset applied
over the commit's params.yaml (`python -m seasonloop.preset NAME`), checked exactly, so a table made
from it names a state that reproduces it (docs/write_tables.py, benchmarks/studies/)."""

from __future__ import annotations

import subprocess
from pathlib import Path

from seasonloop.preset import preset_text


def git(workspace: Path, *args: str) -> str:
    return subprocess.run(["git", "-C", str(workspace), *args], capture_output=True, text=True, check=True).stdout


def dvc_entries_only(workspace: Path, path: str) -> bool:
    """Whether `path` is a .gitignore whose only changes are lines added for DVC's outputs ("/name",
    as `dvc repro` writes for an output new to the commit): the run's bookkeeping, as dvc.lock."""
    if Path(path).name != ".gitignore":
        return False
    before = subprocess.run(
        ["git", "-C", str(workspace), "show", f"HEAD:{path}"], capture_output=True, text=True
    ).stdout.splitlines()
    after = (workspace / path).read_text().splitlines() if (workspace / path).is_file() else []
    added = [line for line in after if line not in before]
    return set(before) <= set(after) and all(line.startswith("/") for line in added)


def commit_state(workspace: Path, preset: str | None = None) -> tuple[str, bool]:
    """(commit, changes not committed) of the run in `workspace`. `preset`: the workspace is its
    commit with that preset applied and `dvc repro` run (checked: params.yaml is exactly the
    preset's text over the commit's, no other tracked file changed but dvc.lock and DVC's .gitignore
    entries; a ValueError names what differs)."""
    commit = git(workspace, "rev-parse", "--short", "HEAD").strip()
    changed = git(workspace, "status", "--porcelain", "--untracked-files=no").splitlines()
    if preset is None:
        return commit, bool(changed)
    committed = git(workspace, "show", "HEAD:params.yaml")
    others = [
        line[3:]
        for line in changed
        if line[3:] not in ("params.yaml", "dvc.lock") and not dvc_entries_only(workspace, line[3:])
    ]
    if others or (workspace / "params.yaml").read_text() != preset_text(preset, committed, workspace / "presets"):
        reason = f"changed: {', '.join(others)}" if others else f"params.yaml is not preset {preset} applied"
        raise ValueError(f"{workspace}: not commit {commit} with preset {preset} applied ({reason})")
    return commit, False


def applied_preset(workspace: Path) -> str | None:
    """The preset whose text over the commit's params.yaml the workspace's params.yaml is; None
    where it is the commit's own (a ValueError where it is neither)."""
    committed = git(workspace, "show", "HEAD:params.yaml")
    current = (workspace / "params.yaml").read_text()
    if current == committed:
        return None
    folder = workspace / "presets"
    for name in sorted(path.stem for path in folder.glob("*.yaml")):
        if preset_text(name, committed, folder) == current:
            return name
    raise ValueError(f"{workspace}/params.yaml: neither the commit's nor any preset of {folder} applied over it")


def finished_run(workspace: Path) -> dict[str, str | None]:
    """A finished run's state, what a table made from it names: its folder, commit and preset
    (applied_preset). A ValueError where it is not that commit with that preset and its `dvc repro`
    (commit_state; without a preset, dvc.lock committed too) or `dvc status` is not clean."""
    status = subprocess.run(["dvc", "status", "--quiet"], cwd=workspace, capture_output=True, text=True)
    if status.returncode != 0:
        raise ValueError(f"{workspace}: `dvc status` is not clean (run `dvc repro` there first)")
    preset = applied_preset(workspace)
    commit, dirty = commit_state(workspace, preset)
    if dirty:
        raise ValueError(f"{workspace}: changes not committed on {commit} (commit them, dvc.lock included)")
    return {"folder": str(workspace), "commit": commit, "preset": preset}
