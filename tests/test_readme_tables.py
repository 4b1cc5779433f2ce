"""The README's results tables are what docs/write_tables.py writes from the pipeline's outputs
(their copies in docs/results/), never typed in by hand."""

import importlib.util
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("write_tables", ROOT / "docs" / "write_tables.py")
write_tables = importlib.util.module_from_spec(spec)
spec.loader.exec_module(write_tables)


def provenance() -> dict:
    return json.loads(write_tables.PROVENANCE.read_text())


def test_every_table_is_what_the_script_writes():
    names = []
    for document in write_tables.DOCUMENTS:
        text = document.read_text()
        names += [line.split()[2] for line in text.splitlines() if line.startswith("<!-- table: ")]
        folder = write_tables.results_folder(document)
        assert write_tables.rewrite(text, provenance(), folder) == text, (
            f"{document.name}: run `python docs/write_tables.py`"
        )
    assert sorted(names) == sorted(write_tables.TABLES), (
        "each table of docs/write_tables.py appears once in README or docs"
    )


def test_no_results_table_is_typed_in():
    # a markdown table with a number in it, outside a generated block, is a typed-in result
    for document in write_tables.DOCUMENTS:
        outside = re.sub(r"<!-- table: \w+ -->.*?<!-- /table -->", "", document.read_text(), flags=re.S)
        numeric_cell = r"\|\s*[-+]?[\d,]+(\.\d+)?\s*(%|s|ms|x|GB|MB)?\s*(?=\|)"
        typed = [line for line in outside.splitlines() if line.startswith("|") and re.search(numeric_cell, line)]
        assert not typed, f"{document.name}: a results table typed in by hand: {typed[0][:80]}"


def test_the_snapshots_say_where_they_came_from():
    record = provenance()
    for name, (_, copy, _) in write_tables.TABLES.items():
        assert (write_tables.RESULTS / copy).exists()
        assert {"commit", "dirty", "command", "cpu"} <= set(record[name])


@pytest.mark.parametrize("name", ["fraction_correct", "network_training", "pr_landmarks", "runtime"])
def test_snapshots_of_the_default_run_match_its_outputs_when_present(name):
    """Where this clone holds the run a snapshot names (the default `dvc repro` with the committed
    lock, or a preset applied and run), the copies in docs/results/ must be its outputs (otherwise
    the docs show another run)."""
    source, copy, _ = write_tables.TABLES[name]
    if not (ROOT / source).is_file():
        pytest.skip(f"{source} not present (the pipeline has not run in this clone)")
    import subprocess

    command = provenance()[name]["command"]
    preset = re.fullmatch(r"python -m seasonloop.preset (\w+) && dvc repro", command)
    if preset:
        try:
            write_tables.run_state(ROOT, command, preset.group(1))
        except ValueError:
            pytest.skip(f"this clone does not hold the run of `{command}`")
    else:
        lock_changed = subprocess.run(
            ["git", "-C", str(ROOT), "diff", "--quiet", "HEAD", "--", "dvc.lock", "params.yaml"]
        )
        if lock_changed.returncode:
            pytest.skip("dvc.lock or params.yaml differ from HEAD: the workspace holds another run")
        # a later commit's lock (a rerun whose outputs differ from the snapshot's run in timings, say)
        # holds another run than the one the snapshot names
        snapshot_commit = provenance()[name]["commit"]
        relocked = subprocess.run(
            ["git", "-C", str(ROOT), "diff", "--quiet", snapshot_commit, "HEAD", "--", "dvc.lock"]
        )
        if relocked.returncode:
            pytest.skip(f"dvc.lock changed since {snapshot_commit}, whose run the snapshot is")
    assert (ROOT / source).read_text() == (write_tables.RESULTS / copy).read_text(), (
        f"run `python docs/write_tables.py --snapshot {name}` after `{command}`"
    )


def test_an_unknown_table_name_is_an_error():
    with pytest.raises(ValueError, match="unknown table 'nope'"):
        write_tables.rewrite("<!-- table: nope -->\nx\n<!-- /table -->", {})


def test_an_old_record_is_read_in_todays_words(tmp_path):
    # records written before the learner column was named "learner" say "method": the tables show
    # them with today's header, their rows as they are
    old = tmp_path / "fraction_correct.md"
    old.write_text("title\n\n| method | summer-fall |\n|---|---|\n| pca | 90.1 [80, 95] |\n")
    assert write_tables._fraction_correct(old) == "| learner | summer-fall |\n|---|---|\n| pca | 90.1 [80, 95] |\n"
    landmarks = tmp_path / "pr_landmarks.md"
    landmarks.write_text("title\n\n| pair method landmark | ours |\n|---|---|\n")
    assert write_tables._fraction_correct(landmarks).startswith("| pair learner landmark | ours |")
    old.write_text("title\n\n| learner | summer-fall |\n|---|---|\n")
    assert write_tables._fraction_correct(old).startswith("| learner | summer-fall |")


def test_no_published_number_comes_from_uncommitted_changes():
    # every table of README and docs names the commit that produced it, and that commit alone
    # reproduces it (docs/write_tables.py refuses a dirty record; this keeps the pages so)
    for document in write_tables.DOCUMENTS:
        text = document.read_text().lower()
        assert "changes not committed" not in text and "uncommitted" not in text, f"{document.name}: a dirty run"


def test_every_docs_page_opens_with_the_question_it_answers():
    # a reader lands on a page with a question: the first sentence after its title is that question
    for page in sorted((write_tables.ROOT / "docs").glob("*.md")):
        prose = " ".join(
            line for line in page.read_text().splitlines()[1:] if line.strip() and not line.startswith("#")
        )
        question, statement = prose.find("?"), prose.find(". ")
        assert question >= 0 and (statement < 0 or question < statement), f"{page.name}: {prose[:120]}"
