"""The prose holds to the paired tests: every sentence of README.md and docs/*.md that ranks one
learner against another either cites a claim of docs/claims.yaml ("[claim: <id>]"), whose
difference and verdict on every pair docs/write_tables.py writes from its run's comparisons (table
`claims` for the default run in docs/results.md, `full_claims` for the full preset's in
docs/full-scale.md), so that no verdict is typed in and none can drift from the numbers; or says
in so many words that it is not tested (a comparison across runs, or a point estimate only).

The default run is one synthetic route; docs/results/replicate_routes.json has every claim on five
routes (tools/replicate_routes.py). A sentence that cites a claim whose verdict is not the
same on every route says which route it speaks of (this one, every one, pooled), and the counts a
sentence gives over the routes ("in 26 of 30 cells", "pooled on five pairs") are the record's.

Real Nordland frames (docs/real-data.md, table `real_claims`): a sentence that speaks of a claim's
verdict there cites it as [real: <id>] and says how it reads beside the synthetic runs ("holds",
"turns", "not shown", ...: seasonloop.reporting.readings.READINGS), as the table computes it."""

from __future__ import annotations

import copy
import importlib.util
import json
import re
from pathlib import Path

import pytest
import yaml

from seasonloop.reporting.comparisons import claim_cells
from seasonloop.reporting.readings import READINGS, claim_direction, claims_beside, claims_read_beside, reading_beside

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
CLAIMS = yaml.safe_load((ROOT / "docs" / "claims.yaml").read_text())
spec = importlib.util.spec_from_file_location("write_tables", ROOT / "docs" / "write_tables.py")
write_tables = importlib.util.module_from_spec(spec)
spec.loader.exec_module(write_tables)

# a claim's run (its `run` key, default "default") -> its comparisons' snapshot and the document
# whose generated claims table shows it
RUNS = {
    "default": (ROOT / "docs" / "results" / "comparisons.json", ROOT / "docs" / "results.md"),
    "full": (ROOT / "docs" / "results" / "full_comparisons.json", ROOT / "docs" / "full-scale.md"),
    # real Nordland frames: no claim is on this run alone; its verdicts are the [real: <id>] citations
    "real": (ROOT / "docs" / "results" / "real_comparisons.json", ROOT / "docs" / "real-data.md"),
}
# the claims' records: the runs', and two runs compared learner by learner (benchmarks/studies/
# compare_runs.py: the real frames' learners trained there against themselves trained on the
# synthetic route), which states no count of its own
RECORDS = {
    **RUNS,
    "transfer": (write_tables.RESULTS / write_tables.TABLES["transfer_claims"][1], ROOT / "docs" / "real-data.md"),
}


REPLICATES = json.loads((ROOT / "docs" / "results" / "replicate_routes.json").read_text())


def run_record(claim: dict) -> dict:
    return json.loads(RECORDS[claim.get("run", "default")][0].read_text())


RANKING = re.compile(r"\b(beats?|beating|better|worse|ahead|behind|outperform\w*|wins?|loses?)\b", re.IGNORECASE)
LEARNER = re.compile(
    r"\b(raw_patchnorm|hog|pca_whiten|pca|ica_bovw|ica|fae|cae|auto-?encoders?|whitened PCA|raw image|learners?)\b",
    re.IGNORECASE,
)
CITATION = re.compile(r"\[claim: ([a-z0-9_]+)\]")
REAL_CITATION = re.compile(r"\[real: ([a-z0-9_]+)\]")
# a ranking the sentence itself says no test stands behind
UNTESTED = re.compile(r"\b(not tested|untested)\b", re.IGNORECASE)
GENERATED = re.compile(r"<!-- table: [a-z0-9_]+ -->.*?<!-- /table -->", re.DOTALL)
CODE = re.compile(r"```.*?```", re.DOTALL)


def sentences(text: str) -> list[str]:
    """The prose of a markdown text, generated tables and code left out, one sentence each."""
    prose = CODE.sub(" ", GENERATED.sub(" ", text))
    # paragraphs and list items
    paragraphs = [" ".join(block.split()) for block in re.split(r"\n\s*\n|\n\s*[-*] ", prose)]
    return [sentence for block in paragraphs for sentence in re.split(r"(?<=[.!?])\s+(?=[A-Z(`*])", block) if sentence]


def test_sentences_split_markdown_prose():
    text = "One: pca beats ica. Two\nlines [claim: x].\n\n<!-- table: t -->\n| pca better |\n<!-- /table -->\nThree.\n- Four"
    assert sentences(text) == ["One: pca beats ica.", "Two lines [claim: x].", "Three.", "Four"]


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: path.name)
def test_every_ranking_sentence_cites_a_claim(document):
    uncited, unknown = [], []
    for sentence in sentences(document.read_text()):
        cited = CITATION.findall(sentence) + REAL_CITATION.findall(sentence)
        unknown += [name for name in cited if name not in CLAIMS]
        if RANKING.search(sentence) and LEARNER.search(sentence) and not cited and not UNTESTED.search(sentence):
            uncited.append(sentence)
    assert not unknown, f"{document.name}: cites claims not in docs/claims.yaml: {unknown}"
    assert not uncited, f"{document.name}: rank learners without citing a claim (docs/claims.yaml):\n" + "\n".join(
        uncited
    )


NUMBERS = {"no": 0, "none": 0, "one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "all": 6}
# "significant on two of the six pairs [claim: x]": a count the prose states, checked against the claim
COUNTED = re.compile(r"significant\w* (?:\w+ )?on (\w+) of the six pairs[^\[]*\[claim: ([a-z0-9_]+)\]")


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: path.name)
def test_counts_of_significant_pairs_are_the_claims(document):
    for sentence in sentences(document.read_text()):
        for number, name in COUNTED.findall(sentence):
            cells = claim_cells(run_record(CLAIMS[name]), CLAIMS[name])
            significant = sum(cell.endswith(("▲", "▼")) for cell in cells.values())
            assert NUMBERS.get(number, number) == significant, f"{document.name}: {sentence}"


def test_every_claim_is_in_its_run_and_in_its_documents_table():
    for name, claim in CLAIMS.items():
        assert set(claim) <= {"says", "table", "first", "second", "run"}, name
        record, document = run_record(claim), RECORDS[claim.get("run", "default")][1]
        cells = claim_cells(record, claim)  # a claim on a comparison the run lacks raises
        assert list(cells) == record["order"]["pairs"]
        assert f"| {name} | {claim['says']} |" in document.read_text(), f"{name}: not in {document.name}'s claims table"


def test_a_sentence_that_says_it_is_untested_needs_no_claim():
    ranking = "On the wider sweep the code is the better descriptor than the CAE's output"
    assert RANKING.search(ranking) and LEARNER.search(ranking) and not UNTESTED.search(ranking)
    assert UNTESTED.search(ranking + " (by point estimate, not tested).")


def same_on_every_route(name: str) -> bool:
    """Whether every replicate route gives the claim the same verdict on every pair (not known, so
    False, for a claim the replicate record does not hold yet)."""
    if name not in REPLICATES["claims"]:
        return False
    routes = len(REPLICATES["routes"])
    for counts in REPLICATES["claims"][name].values():
        if "better" in counts and not (counts["better"] in (0, routes) and counts["worse"] in (0, routes)):
            return False
        if "least_better" in counts and (
            counts["least_better"] != counts["most_better"] or counts["least_worse"] != counts["most_worse"]
        ):
            return False
    return True


# a sentence that says which route(s) its verdict is of
ROUTE = re.compile(r"\b(routes?|pooled)\b", re.IGNORECASE)


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: path.name)
def test_a_verdict_that_turns_with_the_route_says_which_route(document):
    general = []
    for sentence in sentences(document.read_text()):
        cited = [name for name in CITATION.findall(sentence) if CLAIMS[name].get("run", "default") == "default"]
        if any(not same_on_every_route(name) for name in cited) and not ROUTE.search(sentence):
            general.append(sentence)
    assert not general, (
        f"{document.name}: cite a claim whose verdict differs between the replicate routes "
        "(docs/results/replicate_routes.json) without saying which route:\n" + "\n".join(general)
    )


def replicate_totals(name: str) -> dict[str, int]:
    """Over every route and pair: cells ahead, significantly better and worse; pairs pooled significant."""
    cells = REPLICATES["claims"][name].values()
    totals = {key: sum(counts.get(key, 0) for counts in cells) for key in ("ahead", "better", "worse")}
    totals["pooled"] = sum(counts["pooled"].endswith(("▲", "▼")) for counts in cells)
    return totals


# "pooled on five pairs", "pooled ... significant on every pair but summer-fall", "pooled on all six"
PAIRS_POOLED = re.compile(
    r"pooled\b[^\[;]*?\bon (all six|every|one|two|three|four|five|six|no)\b(?! (?:or|to|routes?)\b)(?: pairs?)?( but [\w-]+)?[^\[]*"
    r"\[claim: ([a-z0-9_]+)\]"
)
# route x pair cells of the record: the prose's "30" (five routes, six pairs)
CELLS_IN_ALL = len(REPLICATES["routes"]) * len(REPLICATES["pairs"])
CELLS = re.compile(r"in (all|\d+ of) (?:the )?30\b(?: route-pair)?(?: cells)?[^\[]*\[claim: ([a-z0-9_]+)\]")
CELLS_SIGNIFICANT = re.compile(r"significant(?:ly)? in (all|\d+)\b[^\[]*\[claim: ([a-z0-9_]+)\]")


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: path.name)
def test_counts_over_the_routes_are_the_replicate_records(document):
    for sentence in sentences(document.read_text()):
        for said, but, name in PAIRS_POOLED.findall(sentence):
            pairs = {"all six": 6, "every": 6}.get(said, NUMBERS.get(said, -1)) - (1 if but else 0)
            assert replicate_totals(name)["pooled"] == pairs, f"{document.name}: {sentence}"
        for said, name in CELLS.findall(sentence):
            ahead = CELLS_IN_ALL if said == "all" else int(said.split()[0])
            assert replicate_totals(name)["ahead"] == ahead, f"{document.name}: {sentence}"
        for said, name in CELLS_SIGNIFICANT.findall(sentence):
            totals = replicate_totals(name)
            assert max(totals["better"], totals["worse"]) == (CELLS_IN_ALL if said == "all" else int(said)), (
                f"{document.name}: {sentence}"
            )


def significant_counts(record: dict) -> tuple[int, int]:
    """(significant, compared) over every table and pair of a comparisons record."""
    rows = [row for tables in record["pairs"].values() for table in tables.values() for row in table]
    return sum(row["verdict"] in ("better", "worse") for row in rows), len(rows)


# "On this run 368 of the 672 comparisons are significant", "584 of this run's 672 comparisons are significant"
COMPARISONS_COUNTED = re.compile(r"(\d[\d,]*) of (?:the|this run's) (\d[\d,]*) comparisons are significant")


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: path.name)
def test_counts_of_significant_comparisons_are_the_runs(document):
    # full-scale.md speaks of the full preset's run, every other document of the default run's
    run = next((name for name, (_, shown_in) in RUNS.items() if shown_in == document and name != "default"), "default")
    said = [
        (int(significant.replace(",", "")), int(compared.replace(",", "")))
        for sentence in sentences(document.read_text())
        for significant, compared in COMPARISONS_COUNTED.findall(sentence)
    ]
    expected = significant_counts(json.loads(RUNS[run][0].read_text()))
    assert all(pair == expected for pair in said), (
        f"{document.name}: says {said}, the {run} run's record has {expected}"
    )


def test_the_runs_count_of_significant_comparisons_is_said():
    for _, document in RUNS.values():
        assert any(COMPARISONS_COUNTED.search(sentence) for sentence in sentences(document.read_text())), document.name


def real_readings() -> dict[str, set[str]]:
    """claim -> how its verdict on real frames reads beside the synthetic runs, over the real run's
    pairs (the table real_claims, from the same snapshots)."""
    record = json.loads(RUNS["real"][0].read_text())
    synthetic = write_tables.synthetic_records()
    claims, _ = claims_read_beside(
        record, list(synthetic.values()), {name: claim for name, claim in CLAIMS.items() if "run" not in claim}
    )
    return {
        name: {value["reading"] for value in by_pair.values()}
        for name, by_pair in claims_beside(record, synthetic, claims).items()
    }


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: path.name)
def test_a_sentence_on_real_frames_says_how_its_claim_reads_there(document):
    readings = real_readings()
    wrong = []
    for sentence in sentences(document.read_text()):
        for name in REAL_CITATION.findall(sentence):
            assert name in readings, f"{document.name}: [real: {name}] is not a claim of the default run"
            said = {reading for reading in READINGS if re.search(rf"\b{reading}\b", sentence, re.IGNORECASE)}
            if not said & readings[name] or "real" not in sentence.lower():
                wrong.append(f"{sentence} (on real frames {name} {' / '.join(sorted(readings[name]))})")
    assert not wrong, f"{document.name}: real-frame verdicts not as table real_claims reads them:\n" + "\n".join(wrong)


def test_readings_beside_the_synthetic_runs():
    assert reading_beside(["better", "no difference", "better"], "better") == "holds"
    assert reading_beside(["better", "no difference", "no difference"], "worse") == "turns"
    assert reading_beside(["no difference", "worse", "no difference"], "no difference") == "not shown"
    assert reading_beside(["no difference"] * 3, "better") == "new"
    assert reading_beside(["no difference"] * 3, "no difference") == "shown nowhere"
    assert reading_beside(["better", "better", "better"], "mixed") == "turns"
    assert reading_beside(["better"] * 3, "not enough queries") == "too few queries"


def test_a_run_older_than_a_claims_learner_reads_n_a_and_the_others_decide():
    record = json.loads(RUNS["real"][0].read_text())
    newer = json.loads(RUNS["default"][0].read_text())
    # the same run as a run older than place_cnn would be: no comparison of it
    older = copy.deepcopy(newer)
    for tables in older["pairs"].values():
        for name, rows in tables.items():
            tables[name] = [row for row in rows if "place_cnn" not in row["first"] + row["second"]]
    synthetic = {"newer": newer, "older": older}
    claims = {"place_over_ica": CLAIMS["place_over_ica"]}
    held, left_out = claims_read_beside(record, list(synthetic.values()), claims)
    assert set(held) == {"place_over_ica"} and not left_out
    for value in claims_beside(record, synthetic, held)["place_over_ica"].values():
        assert value["values"]["older"] is None and value["values"]["newer"] is not None
        assert value["reading"] == reading_beside(
            [claim_direction(value["values"]["newer"])], claim_direction(value["values"]["other"])
        )
    _, left_out = claims_read_beside(record, [older], claims)
    assert left_out == ["place_over_ica"]
