"""Write the results tables of README.md and docs/*.md from the pipeline's own output files, never by hand.

    python docs/write_tables.py --snapshot   # copy the run's output files into docs/results/, then write
    python docs/write_tables.py              # rewrite the tables from docs/results/

`--snapshot` copies each table's source (an output of `dvc repro` or of a `dvc exp run`) into
docs/results/ together with where it came from (the git commit, whether the workspace had
changes not committed, the CPU), so that the tables can be checked in a clone that has no pipeline
outputs: tests/test_readme_tables.py fails when a README table differs from what this script
writes from docs/results/. A table's block sits between `<!-- table: NAME -->` and `<!-- /table -->`
in one of DOCUMENTS.
"""

from __future__ import annotations

import argparse
import importlib
import json
import pkgutil
import re
import shutil
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "src"), str(ROOT)]  # the library, and the benchmarks' and tools' tables

from seasonloop.ablations.cae_widths import width_table  # noqa: E402
from seasonloop.machine import cpu_model  # noqa: E402
from seasonloop.reporting.comparisons import claim_cell, claims_markdown, legend  # noqa: E402
from seasonloop.reporting.readings import READINGS, claims_beside, claims_read_beside  # noqa: E402
from seasonloop.reporting.summary import percent_cell  # noqa: E402
from tools.run_state import commit_state  # noqa: E402


def measured_modules() -> list[Any]:
    """The modules of benchmarks/ and tools/ whose records have tables: those that declare TABLES
    (a new benchmark's tables need no line here)."""
    import benchmarks
    import tools

    names = [
        info.name
        for package in (benchmarks, tools)
        for info in pkgutil.walk_packages(package.__path__, f"{package.__name__}.")
    ]
    return [module for module in map(importlib.import_module, sorted(names)) if hasattr(module, "TABLES")]


RESULTS = ROOT / "docs" / "results"
README = ROOT / "README.md"
# the documents whose tables this script writes
DOCUMENTS = [README, *sorted((ROOT / "docs").glob("*.md"))]
PROVENANCE = RESULTS / "provenance.json"


# the header cells of records written before the learner column was named "learner" (CHANGELOG.md)
OLD_HEADERS = {"| method |": "| learner |", "| pair method landmark |": "| pair learner landmark |"}


def _fraction_correct(path: Path) -> str:
    """The pipeline's own markdown, without its title line (an old record's header in today's words)."""
    header, _, rows = path.read_text().split("\n", 2)[2].strip().partition("\n")
    for old, new in OLD_HEADERS.items():
        if header.startswith(old):
            header = new + header[len(old) :]
    return f"{header}\n{rows}\n"


def _headline(path: Path) -> str:
    """The fraction-correct table under the main distance (no @<metric> rows), a row per learner and
    a column per pair and matcher ("winter-summer", "winter-summer+seq", ...)."""
    header, _, *rows = _fraction_correct(path).splitlines()
    pairs = [cell.strip() for cell in header.split("|")[2:-1]]
    cells: dict[str, dict[str, str]] = {}
    for row in rows:
        label, *values = [cell.strip() for cell in row.split("|")[1:-1]]
        if "@" in label:
            continue
        learner, suffix = label.split("+")[0], label[len(label.split("+")[0]) :]
        cells.setdefault(learner, {}).update({pair + suffix: value for pair, value in zip(pairs, values)})
    columns = list(dict.fromkeys(column for by_column in cells.values() for column in by_column))
    lines = ["| learner | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    lines += [f"| {learner} | " + " | ".join(row.get(c, "") for c in columns) + " |" for learner, row in cells.items()]
    return "\n".join(lines) + "\n"


def _network_training(path: Path) -> str:
    record = json.loads(path.read_text())
    columns = [
        "stop_reason",
        "converged",
        "epochs_run",
        "best_epoch",
        "best_validation_loss",
        "n_train_images",
        "n_validation_images",
        "images_seen",
        "precision",
        "training_seconds",
    ]
    lines = ["| learner | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for learner, row in record.items():
        cells = [
            "n/a"  # a learner fitted elsewhere: its run's facts are that run's
            if row[key] is None
            else f"{row[key]:.5f}"
            if key == "best_validation_loss"
            else f"{row[key]:.0f}"
            if key == "training_seconds"
            else str(row[key]).lower()
            if isinstance(row[key], bool)
            else str(row[key])
            for key in columns
        ]
        lines.append(f"| {learner} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _dataset_seasons(path: Path) -> str:
    """Images per season of metrics/dataset.json, and which ground truth the run used."""
    record = json.loads(path.read_text())
    lines = ["| season | frames | train | train augmented | test |", "|---|---|---|---|---|"]
    for season, row in record["seasons"].items():
        lines.append(f"| {season} | {row['frames']} | {row['train']} | {row['train_augmented']} | {row['test']} |")
    return "\n".join(lines) + f"\n\nGround truth: {record.get('ground_truth', 'aligned')}.\n"


# outputs whose size grows with the number of places (frames, their arrays, descriptors), and the
# places per season of the default run and of presets/full.yaml (the study's 35,768 a season)
# (data/acquired: the rendered videos; real data is read where it lies, not an output)
PLACE_SCALED = ("data/frames", "data/preprocessed", "data/split", "data/augmented", "data/features")
DEFAULT_PLACES, FULL_PLACES = 1800, 35768


def _output_sizes(path: Path) -> str:
    """The outputs of a run by folder, in MB, from its dvc.lock (DVC records each output's size),
    with a full-scale estimate for those that grow with the places."""
    import yaml

    lock = yaml.safe_load(path.read_text())
    sizes: dict[str, int] = {}
    for stage in lock["stages"].values():
        for out in stage.get("outs", []):
            parts = out["path"].split("/")
            group = "/".join(parts[:2]) if parts[0] == "data" else parts[0]
            sizes[group] = sizes.get(group, 0) + int(out.get("size", 0))
    lines = ["| output | this run (MB) | full scale, estimated (GB) |", "|---|---|---|"]
    for group, size in sorted(sizes.items(), key=lambda item: -item[1]):
        estimate = f"{size * FULL_PLACES / DEFAULT_PLACES / 1e9:.1f}" if group in PLACE_SCALED else "-"
        lines.append(f"| `{group}` | {size / 1e6:.1f} | {estimate} |")
    total = sum(sizes.values())
    lines.append(f"| all | {total / 1e6:.1f} | |")
    return "\n".join(lines) + "\n"


def _cae_widths(path: Path) -> str:
    return width_table(json.loads(path.read_text()))


def _ica_fit(path: Path) -> str:
    """metrics/fit/ica.json as one row: how the global ICA was fitted and whether it converged."""
    record = json.loads(path.read_text())
    info = record["info"]
    return (
        "| solver | components | training images | iterations | relative gradient (stored model) | tol "
        "| converged | fit seconds |\n|---|---|---|---|---|---|---|---|\n"
        f"| {info['solver']} ({info.get('precision', 'float64')}) | {info['n_components']} | {record['n_train_images']} "
        f"| {info['n_iter']} | {info['gradient']:.2e} | {info['tol']:.0e} | {str(info['converged']).lower()} "
        f"| {record['fit_seconds']:.1f} |\n"
    )


def _training_seasons(path: Path) -> str:
    """metrics/training_seasons.json: fraction correct (%) of each ablation learner per training-season set."""
    record = json.loads(path.read_text())
    sets = record["season_sets"]
    # a record from before 36a7aeb has block-bootstrap intervals (no degrees of freedom)
    along_route = any(
        "degrees" in interval for by_set in record.get("intervals", {}).values() for interval in by_set.values()
    )
    kind = "interval along the route" if along_route else "block-bootstrap interval (the rule before 36a7aeb)"
    lines = [
        f"Pair {record['pair']}, single image, fraction correct (%) with its 95% {kind}; "
        "columns: the seasons the learner was trained on.",
        "",
        "| learner | " + " | ".join(sets) + " |",
        "|---|" + "---|" * len(sets),
    ]
    intervals = record.get("intervals", {})
    for learner, fractions in record["fraction_correct"].items():
        cells = [percent_cell(fractions[s], intervals.get(learner, {}).get(s)) for s in sets]
        lines.append(f"| {learner} | " + " | ".join(cells) + " |")
    unfitted = [
        f"{learner} on {label}: {why}"
        for learner, by in record.get("not_fitted", {}).items()
        for label, why in by.items()
    ]
    return "\n".join(lines + (["", "n/a: " + "; ".join(unfitted) + "."] if unfitted else [])) + "\n"


def _whole(path: Path) -> str:
    """The pipeline's own markdown as it is."""
    return path.read_text().strip() + "\n"


CLAIMS = ROOT / "docs" / "claims.yaml"


def _claims_of(run: str) -> Callable[[Path], str]:
    """The writer of one run's claims table: docs/claims.yaml's comparisons whose `run` is `run`
    (no `run`: the default run's), each on every pair, from that run's comparisons record."""

    def claims(path: Path) -> str:
        every = yaml.safe_load(CLAIMS.read_text())
        return claims_markdown(
            json.loads(path.read_text()),
            {name: claim for name, claim in every.items() if claim.get("run", "default") == run},
        )

    return claims


# the synthetic runs a run on other data is read beside (table real_claims): column -> its snapshot
SYNTHETIC_RUNS = {
    "default route": "comparisons.json",
    "routes, pooled": "replicate_routes.json",  # as many routes as its record holds
    "full preset": "full_comparisons.json",
}


EVAL_COLUMNS = {
    "recall_at_1": "R@1",
    "recall_at_5": "R@5",
    "recall_at_10": "R@10",
    "recall_at_100_precision": "recall at 100% precision",
    "auc_pr": "AUC-PR",
    "auc_pr_vpr_tutorial": "AUC-PR (VPR_Tutorial)",
    "extended_precision": "EP (VPR-Bench)",
}


def _eval_metrics(path: Path) -> str:
    """A run's metrics/eval/<learner>/<pair><variant>.json as one table (%): the field's recall@N,
    recall at 100% precision and both areas under the PR curve, every evaluation of every pair."""
    learners = yaml.safe_load((ROOT / "params.yaml").read_text())["learners"]
    folders = sorted(
        path.iterdir(),
        key=lambda folder: (learners.index(folder.name) if folder.name in learners else len(learners), folder.name),
    )
    lines = ["| evaluation | " + " | ".join(EVAL_COLUMNS.values()) + " |", "|---|" + "---|" * len(EVAL_COLUMNS)]
    for folder in folders:
        for file in sorted(folder.glob("*.json"), key=lambda file: (len(file.stem), file.stem)):
            record = json.loads(file.read_text())
            # n/a: a metric the run's code did not compute yet (a snapshot older than the metric)
            cells = " | ".join(f"{100 * record[key]:.1f}" if key in record else "n/a" for key in EVAL_COLUMNS)
            lines.append(f"| {folder.name} {file.stem} | {cells} |")
    return "\n".join(lines) + "\n"


def synthetic_records() -> dict[str, dict]:
    """column of SYNTHETIC_RUNS -> its record, from the snapshots in docs/results/."""
    return {column: json.loads((RESULTS / snapshot).read_text()) for column, snapshot in SYNTHETIC_RUNS.items()}


def _claims_beside_runs(path: Path) -> str:
    """The default run's claims (docs/claims.yaml, no `run`) on a run of real frames (`path`: its
    comparisons), beside their verdicts on the same pair in the synthetic runs, and how they read
    (seasonloop.reporting.readings.claims_beside)."""
    record = json.loads(path.read_text())
    synthetic = synthetic_records()
    default_claims = {name: claim for name, claim in yaml.safe_load(CLAIMS.read_text()).items() if "run" not in claim}
    claims, left_out = claims_read_beside(record, list(synthetic.values()), default_claims)
    columns = [*SYNTHETIC_RUNS, "real frames"]
    lines = [
        "| claim | compares | pair | " + " | ".join(columns) + " | on real frames |",
        "|---|---|---|" + "---|" * (len(columns) + 1),
    ]
    beside = claims_beside(record, synthetic, claims)
    for pair in record["order"]["pairs"]:
        for name, claim in claims.items():
            values = beside[name][pair]["values"]
            cells = " | ".join(
                "n/a" if values[column] is None else claim_cell(values[column]) for column in [*SYNTHETIC_RUNS, "other"]
            )
            lines.append(f"| {name} | {claim['says']} | {pair} | {cells} | {beside[name][pair]['reading']} |")
    readings = "; ".join(f"{key}: {meaning}" for key, meaning in READINGS.items())
    return (
        "\n".join(lines)
        + "\n\n"
        + legend(record["statistics"])
        + " Whole tables: significant differences each way. Routes, pooled: every replicate route's queries together "
        + f"(docs/routes.md: {len(synthetic['routes, pooled']['routes'])} routes). n/a: a run made before the claim's learner or matcher existed. On real frames: {readings}."
        + (
            f" Not read here (no verdict on this data or on any synthetic run yet): {', '.join(left_out)}."
            if left_out
            else ""
        )
        + "\n"
    )


# table name -> (the output file it is written from, its snapshot in docs/results/, how): the
# pipeline's own outputs here, each benchmark's and the replicate routes' tables in its own module
TABLES: dict[str, tuple[str, str, Callable[[Path], str]]] = {
    "fraction_correct": ("plots/summary/fraction_correct.md", "fraction_correct.md", _fraction_correct),
    "pr_landmarks": ("plots/summary/pr_landmarks.md", "pr_landmarks.md", _fraction_correct),
    # paired comparisons (docs/comparisons.md), and the claims the prose cites (docs/results.md)
    "comparisons": ("plots/comparisons.md", "comparisons.md", _whole),
    "claims": ("metrics/comparisons.json", "comparisons.json", _claims_of("default")),
    "runtime": ("plots/summary/runtime.md", "runtime.md", _fraction_correct),
    "network_training": ("metrics/network_training.json", "network_training.json", _network_training),
    "cae_widths": ("metrics/cae_widths.json", "cae_widths_sweep.json", _cae_widths),
    # the global ICA's fit and its basis images (docs/ica.md)
    "ica_basis": ("metrics/fit/ica.json", "ica_fit.json", _ica_fit),
    "output_sizes": ("dvc.lock", "dvc_lock_sizes.yaml", _output_sizes),
    # the synthetic route ridden at a different speed in each season, ground truth from positions
    # (docs/other-datasets.md; a run in another clone: --from)
    "rides_dataset": ("metrics/dataset.json", "rides_dataset.json", _dataset_seasons),
    "rides_fraction_correct": ("plots/summary/fraction_correct.md", "rides_fraction_correct.md", _headline),
    # real Nordland frames, summer and winter (docs/real-data.md; a run in another clone: --from)
    "real_dataset": ("metrics/dataset.json", "real_dataset.json", _dataset_seasons),
    "real_headline": ("plots/summary/fraction_correct.md", "real_fraction_correct.md", _headline),
    "real_fraction_correct": ("plots/summary/fraction_correct.md", "real_fraction_correct.md", _fraction_correct),
    "real_precision_recall": ("metrics/eval", "real_eval", _eval_metrics),
    "real_comparisons": ("plots/comparisons.md", "real_comparisons.md", _whole),
    "real_claims": ("metrics/comparisons.json", "real_comparisons.json", _claims_beside_runs),
    "real_training_seasons": ("metrics/training_seasons.json", "real_training_seasons.json", _training_seasons),
    "real_network_training": ("metrics/network_training.json", "real_network_training.json", _network_training),
    "real_ica_basis": ("metrics/fit/ica.json", "real_ica_fit.json", _ica_fit),
    # the same frames described by the learners a default run fitted on the synthetic route
    # (presets/real_elsewhere.yaml; docs/real-data.md)
    "real_elsewhere_headline": ("plots/summary/fraction_correct.md", "real_elsewhere_fraction_correct.md", _headline),
    # presets/full.yaml run in one piece by benchmarks/speed/bench_full_run.py (docs/full-scale.md): its
    # outputs in the run's own folder (--from FOLDER)
    "full_fraction_correct": ("plots/summary/fraction_correct.md", "full_fraction_correct.md", _fraction_correct),
    "full_pr_landmarks": ("plots/summary/pr_landmarks.md", "full_pr_landmarks.md", _fraction_correct),
    # the full run's file before it held place_cnn too (network_training.json since): rerun, rename
    "full_autoencoder_training": (
        "metrics/autoencoder_training.json",
        "full_autoencoder_training.json",
        _network_training,
    ),
    "full_training_seasons": ("metrics/training_seasons.json", "full_training_seasons.json", _training_seasons),
    "full_cae_widths": ("metrics/cae_widths.json", "full_cae_widths_sweep.json", _cae_widths),
    "full_ica_basis": ("metrics/fit/ica.json", "full_ica_fit.json", _ica_fit),
    "full_claims": ("metrics/comparisons.json", "full_comparisons.json", _claims_of("full")),
    **{name: table for module in measured_modules() for name, table in module.TABLES.items()},
}


# tables of runs with other params, made in another clone (--snapshot NAMES --from CLONE), and the
# full run's timing record: left out of a bare --snapshot, which copies this clone's default run
OTHER_RUNS = (
    "full_run_stages",
    "rides_dataset",
    "rides_fraction_correct",
    "real_dataset",
    "real_headline",
    "real_fraction_correct",
    "real_precision_recall",
    "real_comparisons",
    "real_claims",
    "real_training_seasons",
    "real_network_training",
    "real_ica_basis",
    "real_elsewhere_headline",
    "full_fraction_correct",
    "full_pr_landmarks",
    "full_autoencoder_training",
    "full_training_seasons",
    "full_cae_widths",
    "full_ica_basis",
    "full_claims",
)

# figures copied beside a table's snapshot (the README shows the copy): table name -> (figure, copy)
FIGURES = {
    "cae_widths": ("plots/cae_widths.png", "cae_widths_sweep.png"),
    "fraction_correct": ("plots/summary/fraction_correct.png", "fraction_correct.png"),
    "ica_basis": ("plots/figures/fig12b_global_ica_basis.png", "ica_basis.png"),
    "full_fraction_correct": ("plots/summary/fraction_correct.png", "full_fraction_correct.png"),
    "real_fraction_correct": ("plots/summary/fraction_correct.png", "real_fraction_correct.png"),
    "real_ica_basis": ("plots/figures/fig12b_global_ica_basis.png", "real_ica_basis.png"),
    "real_precision_recall": ("plots/summary/pr_winter-summer.png", "real_pr_winter-summer.png"),
    "full_cae_widths": ("plots/cae_widths.png", "full_cae_widths_sweep.png"),
    "full_ica_basis": ("plots/figures/fig12b_global_ica_basis.png", "full_ica_basis.png"),
}


def measured_at(path: Path, run: dict) -> str:
    """The commit a benchmark ran at: its own record's (benchmarks/_bench_common.write_result writes it),
    else the one the snapshot was taken at."""
    record = json.loads(path.read_text()) if path.suffix == ".json" else {}
    commit, dirty = record.get("commit") or run.get("commit", "?"), record.get("dirty", run.get("dirty"))
    return f"{commit}{' + changes not committed' if dirty else ''}"


def provenance_line(name: str, provenance: dict) -> str:
    source, snapshot, _ = TABLES[name]
    run = provenance.get(name, {})
    if source.startswith("benchmarks/"):
        return (
            f"_Written by `docs/write_tables.py` from `{source}` (copy: `docs/results/{snapshot}`), measured at "
            f"commit {measured_at(RESULTS / snapshot, run)}._\n"
        )
    return (
        f"_Written by `docs/write_tables.py` from `{source}` (copy: `docs/results/{snapshot}`), produced at "
        f"commit {run.get('commit', '?')}{' + changes not committed' if run.get('dirty') else ''} "
        f"by `{run.get('command', 'dvc repro')}` on {run.get('cpu', '?')}._\n"
    )


def table_block(name: str, provenance: dict, folder: str = "docs/results") -> str:
    """The table, its figure (linked from a document in `folder`'s parent) and its provenance line."""
    _, snapshot, render = TABLES[name]
    figure = f"\n![{name}]({folder}/{FIGURES[name][1]})\n" if name in FIGURES else ""
    return render(RESULTS / snapshot) + figure + "\n" + provenance_line(name, provenance)


def rewrite(text: str, provenance: dict, folder: str = "docs/results") -> str:
    """A document's text with every table block rewritten; `folder`: docs/results/ seen from the document."""

    def replace(match: re.Match) -> str:
        name = match.group(1)
        if name not in TABLES:
            raise ValueError(f"unknown table '{name}' (known: {', '.join(TABLES)})")
        return f"<!-- table: {name} -->\n{table_block(name, provenance, folder)}<!-- /table -->"

    return re.sub(r"<!-- table: (\w+) -->\n.*?<!-- /table -->", replace, text, flags=re.S)


def run_state(workspace: Path, command: str, preset: str | None = None) -> tuple[str, bool, str]:
    """(commit, changes not committed, command) of the run in `workspace` (tools.run_state.commit_state:
    with `preset`, checked to be its commit with that preset applied), so its tables come from a
    committed state and the command that reproduces them."""
    bench_source = workspace / "bench_source.json"  # a folder of bench_full_run.py: its own commit only sets params
    if bench_source.is_file():
        made_from = json.loads(bench_source.read_text())["made_from"]
        return made_from["commit"], made_from["dirty"], command
    commit, dirty = commit_state(workspace, preset)
    return commit, dirty, command if preset is None else f"python -m seasonloop.preset {preset} && dvc repro"


def refuse_dirty(source: Path, measured: bool, dirty: bool) -> None:
    """A published table comes from a committed state: a benchmark's record measured with
    changes not committed, or a run's outputs in a workspace that has them, are refused (SystemExit)."""
    if measured:
        record = json.loads(source.read_text())
        if record.get("dirty"):
            raise SystemExit(
                f"{source}: measured at {record.get('commit')} + changes not committed; rerun it from a commit"
            )
    elif dirty:
        raise SystemExit(
            f"{source}: its workspace has changes not committed; commit them (or name the preset applied: --preset)"
        )


def snapshot(names: list[str], command: str, workspace: Path = ROOT, preset: str | None = None) -> None:
    """Copy the named tables' output files of `workspace` (this repository, or a clone that ran
    other params or a preset: run_state) into docs/results/ and record where they came from."""
    commit, dirty, command = run_state(workspace, command, preset)
    provenance = json.loads(PROVENANCE.read_text()) if PROVENANCE.is_file() else {}
    RESULTS.mkdir(parents=True, exist_ok=True)
    for name in names:
        source, copy, _ = TABLES[name]
        if not (workspace / source).exists():
            raise FileNotFoundError(f"{workspace / source}: not found (run the pipeline first)")
        refuse_dirty(workspace / source, source.startswith("benchmarks/"), dirty)
        if (workspace / source).is_dir():  # a folder of small files (metrics/eval): copied whole,
            shutil.rmtree(RESULTS / copy, ignore_errors=True)  # but DVC's .gitignore, which would hide them
            shutil.copytree(workspace / source, RESULTS / copy, ignore=shutil.ignore_patterns(".gitignore"))
        else:
            shutil.copyfile(workspace / source, RESULTS / copy)
        if name in FIGURES:
            shutil.copyfile(workspace / FIGURES[name][0], RESULTS / FIGURES[name][1])
        provenance[name] = {"commit": commit, "dirty": dirty, "command": command, "cpu": cpu_model()}
    PROVENANCE.write_text(json.dumps(provenance, indent=2, sort_keys=True) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--snapshot",
        nargs="*",
        metavar="TABLE",
        help=f"copy these tables' output files first (none named: all of {', '.join(TABLES)})",
    )
    parser.add_argument("--command", default="dvc repro", help="the command that produced the outputs (recorded)")
    parser.add_argument(
        "--preset", help="the clone is its commit with this preset applied, then `dvc repro` (checked, recorded)"
    )
    parser.add_argument(
        "--from", dest="workspace", type=Path, default=ROOT, help="the clone whose outputs to copy (default: this one)"
    )
    args = parser.parse_args()
    if args.snapshot is not None:
        # none named: every table of this clone's default run and benchmarks, not the runs of other params
        snapshot(
            args.snapshot or [name for name in TABLES if name not in OTHER_RUNS],
            args.command,
            args.workspace.resolve(),
            args.preset,
        )
    provenance = json.loads(PROVENANCE.read_text()) if PROVENANCE.is_file() else {}
    for document in DOCUMENTS:
        document.write_text(rewrite(document.read_text(), provenance, results_folder(document)))


def results_folder(document: Path) -> str:
    """docs/results/ as a link from `document`."""
    return "docs/results" if document == README else "results"


if __name__ == "__main__":
    main()
