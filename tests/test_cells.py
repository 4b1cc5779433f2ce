"""benchmarks.cells: a finished cell is read back under its own key, never under another's."""

from __future__ import annotations

from benchmarks.cells import Cells, source_hash


def test_a_finished_cell_is_read_back_and_a_changed_key_computes_again(tmp_path):
    calls = []

    def compute():
        calls.append(1)
        return {"rate": 0.95, "replicates": len(calls)}

    first = Cells("grid", "code-a", tmp_path)
    row = first.get({"n": 158, "p": 0.5}, compute)
    resumed = Cells("grid", "code-a", tmp_path)
    assert resumed.get({"n": 158, "p": 0.5}, compute) == row and resumed.resumed == 1 and len(calls) == 1
    assert resumed.get({"n": 158, "p": 0.2}, compute)["replicates"] == 2  # another argument: computed
    assert Cells("grid", "code-b", tmp_path).get({"n": 158, "p": 0.5}, compute)["replicates"] == 3  # new code


def test_a_line_cut_short_is_skipped(tmp_path):
    Cells("grid", "code", tmp_path).get({"n": 1}, lambda: {"rate": 1.0})
    with (tmp_path / "grid.cells.jsonl").open("a") as file:
        file.write('{"key": "cut')
    assert Cells("grid", "code", tmp_path).get({"n": 1}, lambda: {"rate": 0.0}) == {"rate": 1.0}


def test_the_source_hash_follows_the_text(tmp_path):
    path = tmp_path / "a.py"
    path.write_text("x = 1\n")
    before = source_hash([path])
    path.write_text("x = 2\n")
    assert source_hash([path]) != before
