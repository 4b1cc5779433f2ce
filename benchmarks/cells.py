"""Cells of a long benchmark kept as they finish, so that a run cut short resumes where it stopped.

A simulation grid of hours (check_calibration) is many independent cells, each seeded on its own:
a finished cell is appended to benchmarks/results/<name>.cells.jsonl under a key that holds
everything its numbers depend on (the cell's arguments, and a hash of the code that computes it),
and a later run with the same key reads it back instead of computing it again. A change to the
code or to any argument is a new key: a stale cell is never reused.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from tools.records import RESULTS_DIR


def source_hash(paths: Iterable[Path]) -> str:
    """sha256 of the files' text, in sorted path order (the code a cell's numbers come from)."""
    digest = hashlib.sha256()
    for path in sorted(Path(p) for p in paths):
        digest.update(str(path).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


class Cells:
    """get(key, compute): the stored row of `key`, or compute() stored then returned."""

    def __init__(self, name: str, code: str, directory: Path = RESULTS_DIR):
        self.path = directory / f"{name}.cells.jsonl"
        self.code = code
        self.resumed = 0
        self.stored: dict[str, Any] = {}
        if self.path.is_file():
            for line in self.path.read_text().splitlines():
                try:
                    entry = json.loads(line)
                except json.JSONDecodeError:  # a line cut short by the interruption itself
                    continue
                self.stored[entry["key"]] = entry["row"]

    def key(self, arguments: dict[str, Any]) -> str:
        return json.dumps({"code": self.code, **arguments}, sort_keys=True, default=str)

    def get(self, arguments: dict[str, Any], compute: Callable[[], Any]) -> Any:
        key = self.key(arguments)
        if key in self.stored:
            self.resumed += 1
            return self.stored[key]
        row = compute()
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with self.path.open("a") as file:
            file.write(json.dumps({"key": key, "row": row}) + "\n")
        self.stored[key] = row
        return row
