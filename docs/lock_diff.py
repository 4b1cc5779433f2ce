"""Which pipeline outputs changed between a committed dvc.lock and the workspace's, file by file.

    python docs/lock_diff.py HEAD~1      # after `dvc repro`: compare with the lock of that revision

A directory output is compared file by file through the .dir manifests in DVC's cache (both runs
must have been cached here), so a model folder whose only change is learner.json's timings says so.
Used to show that a refactor leaves every output byte-identical except the files that record times.
"""

from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path
from typing import Any

import yaml

CACHE = Path(".dvc/cache/files/md5")


def outputs(lock: dict[str, Any]) -> dict[str, str]:
    """output path -> md5 of every stage's outs in a parsed dvc.lock."""
    return {out["path"]: out["md5"] for stage in lock["stages"].values() for out in stage.get("outs", [])}


def manifest(md5: str) -> dict[str, str]:
    """relpath -> md5 of a cached directory output."""
    return {entry["relpath"]: entry["md5"] for entry in json.loads((CACHE / md5[:2] / md5[2:]).read_text())}


def differences(old: dict[str, str], new: dict[str, str]) -> tuple[list[str], dict[str, list[str]]]:
    """(identical outputs, output -> what differs inside it)."""
    same, differ = [], {}
    for path in sorted(set(old) | set(new)):
        if old.get(path) == new.get(path):
            same.append(path)
        elif path not in old or path not in new:
            differ[path] = ["only in one lock"]
        elif old[path].endswith(".dir") and all(
            (CACHE / md5[:2] / md5[2:]).is_file() for md5 in (old[path], new[path])
        ):
            a, b = manifest(old[path]), manifest(new[path])
            differ[path] = sorted(name for name in set(a) | set(b) if a.get(name) != b.get(name))
        elif old[path].endswith(".dir"):
            differ[path] = ["the folder (its file list is not in this clone's cache: `dvc pull` or run both here)"]
        else:
            differ[path] = ["the file"]
    return same, differ


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("revision", help="git revision whose dvc.lock is the baseline")
    args = parser.parse_args()
    shown = subprocess.run(["git", "show", f"{args.revision}:dvc.lock"], capture_output=True, text=True, check=True)
    same, differ = differences(
        outputs(yaml.safe_load(shown.stdout)), outputs(yaml.safe_load(Path("dvc.lock").read_text()))
    )
    print(f"{len(same)} outputs byte-identical to {args.revision}'s")
    print(f"{len(differ)} differ:")
    for path, files in differ.items():
        print(f"  {path}: {', '.join(files)}")


if __name__ == "__main__":
    main()
