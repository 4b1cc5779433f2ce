"""Write the results tables of README.md and docs/*.md from the pipeline's own output files, never by hand.

    python docs/write_tables.py --snapshot   # copy the run's output files into docs/results/, then write
    python docs/write_tables.py              # rewrite the tables from docs/results/

`--snapshot` copies each table's source (an output of `dvc repro` or of a `dvc exp run`) into
docs/results/ together with where it came from (the git commit, whether the workspace had
uncommitted changes, the CPU), so that the tables can be checked in a clone that has no pipeline
outputs: tests/test_readme_tables.py fails when a README table differs from what this script
writes from docs/results/. A table's block sits between `<!-- table: NAME -->` and `<!-- /table -->`
in one of DOCUMENTS.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from seasonloop.ablations.cae_widths import width_table  # noqa: E402
from seasonloop.machine import cpu_model  # noqa: E402
from seasonloop.reporting.comparisons import claim_cell, claims_markdown, legend  # noqa: E402
from seasonloop.reporting.readings import READINGS, claims_beside  # noqa: E402
from seasonloop.reporting.summary import percent_cell  # noqa: E402

RESULTS = ROOT / "docs" / "results"
README = ROOT / "README.md"
# the documents whose tables this script writes
DOCUMENTS = [README, *sorted((ROOT / "docs").glob("*.md"))]
PROVENANCE = RESULTS / "provenance.json"


def _fraction_correct(path: Path) -> str:
    """The pipeline's own markdown, without its title line."""
    return path.read_text().split("\n", 2)[2].strip() + "\n"


def _headline(path: Path) -> str:
    """The fraction-correct table's rows under the main distance (no @<metric> rows)."""
    rows = _fraction_correct(path).splitlines()
    return "\n".join(row for row in rows if "@" not in row.split("|")[1]) + "\n"


def _autoencoder_training(path: Path) -> str:
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
            f"{row[key]:.5f}"
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


def _bench_autoencoders(path: Path) -> str:
    """benchmarks/bench_autoencoders.py's record: one row per network and variant, then the
    to-the-plateau comparison where the run made it."""
    record = json.loads(path.read_text())
    args = record["args"]
    lines = [
        f"`python benchmarks/bench_autoencoders.py --fae-images {args['fae_images']} --cae-images "
        f"{args['cae_images']} --cae-widths {args['cae_widths']} --quality-images {args['quality_images']} "
        f"--quality-epochs {args['quality_epochs']} --pair-places {args['pair_places']}"
        + (f" --plateau-images {args['plateau_images']}" if args.get("plateau_images") else "")
        + f"` on {record['machine']['cpu']}, {record['machine']['torch_threads']} threads"
        + (f" ({record['load_note']})" if record.get("load_note") else "")
        + ":",
        "",
        "| network | variant | train images/s | describe images/s | train / describe vs float32 | "
        f"validation loss after {args['quality_epochs']} epoch(s) (vs float32) | summer-fall % |",
        "|---|---|---|---|---|---|---|",
    ]
    # the FAE first, and in each network the float32 reference first (the JSON's keys are sorted)
    for network, devices in sorted(record["results"].items(), key=lambda item: (item[0] != "fae", item[0])):
        for device, runs in devices.items():
            if device.endswith("to_plateau"):
                continue
            for variant, run in sorted(runs.items(), key=lambda item: (not item[0].startswith("float32"), item[0])):
                quality = run["quality"]
                checked = (
                    "not checked (emulated)"
                    if quality is None
                    else (f"{quality['final_validation_loss']:.5f} ({quality['validation_loss_change']:+.1%})")
                )
                correct = "" if quality is None else f"{100 * quality['fraction_correct']:.1f}"
                lines.append(
                    f"| {network} ({device}) | {variant} | {run['train_images_per_s']:.1f} | "
                    f"{run['describe_images_per_s']:.1f} | {run['speedup_vs_float32']['train']:.2f}x / "
                    f"{run['speedup_vs_float32']['describe']:.2f}x | {checked} | {correct} |"
                )
    plateau = {
        network: devices["cpu_to_plateau"]
        for network, devices in record["results"].items()
        if "cpu_to_plateau" in devices
    }
    if plateau:
        lines += [
            "",
            f"Each trained to its validation plateau on {args['plateau_images']} images (the pipeline's "
            "stopping rule), channels_last:",
            "",
            "| network | precision | seconds | epochs | converged | best validation loss | summer-fall % |",
            "|---|---|---|---|---|---|---|",
        ]
        for network, runs in plateau.items():
            for precision, run in sorted(runs.items(), key=lambda item: item[0] != "float32"):
                lines.append(
                    f"| {network} | {precision} | {run['training_seconds']:.0f} | {run['epochs_run']} | "
                    f"{str(run['converged']).lower()} | {run['best_validation_loss']:.5f} | "
                    f"{100 * run['fraction_correct']:.1f} |"
                )
    return "\n".join(lines) + "\n"


def _check_cross_isa(path: Path) -> str:
    record = json.loads(path.read_text())
    lines = [
        f"`python benchmarks/check_cross_isa.py --images {record['args']['images']} --epochs "
        f"{record['args']['epochs']}` on {record['machine']['cpu']}:",
        "",
        "| learner and precision | kernels (uncapped / capped) | weights byte-identical | largest weight "
        "difference | final validation loss (uncapped / capped) |",
        "|---|---|---|---|---|",
    ]
    for name, row in record["results"].items():
        loss = row["validation_loss"]
        lines.append(
            f"| {name} | {row['cpu_capability']['native']} / {row['cpu_capability']['capped']} | "
            f"{'yes' if row['identical'] else 'no'} | {row['largest_weight_difference']:.2g} | "
            f"{loss['native'][-1]:.6f} / {loss['capped'][-1]:.6f} |"
        )
    return "\n".join(lines) + "\n"


def _check_cross_blas(path: Path) -> str:
    """benchmarks/check_cross_blas.py's record: per learner, whether model, descriptors and every
    metrics file are the same under this CPU's kernels and an AVX2-only CPU's."""
    record = json.loads(path.read_text())
    lines = [
        f"`python benchmarks/check_cross_blas.py` on {record['machine']['cpu']}, capped run with "
        + " ".join(f"`{key}={value}`" for key, value in record["avx2_only"].items())
        + ":",
        "",
        "| learner | model bytes | descriptors (largest relative difference) | metrics files identical |",
        "|---|---|---|---|",
    ]
    for learner, row in record["learners"].items():
        identical = row["metrics_files"] - len(row["metrics_files_differ"])
        lines.append(
            f"| {learner} | {'identical' if row['model_identical'] else 'differ'} | "
            f"{'identical' if row['features_identical'] else 'differ'} "
            f"({row['largest_relative_descriptor_difference']:.2g}) | {identical} of {row['metrics_files']} |"
        )
    stages = record["stage_outputs"]
    same = sum(row["files"] - len(row["differ"]) for row in stages.values())
    lines += [
        "",
        f"Data stages on the way ({', '.join(stages)}): {same} of {sum(r['files'] for r in stages.values())} files identical.",
    ]
    return "\n".join(lines) + "\n"


def _run_machine(record: dict) -> str:
    """The CPU a benchmark ran on, its threads, and whether its instruction set was capped."""
    machine = record["machine"]
    capped = any((machine.get("isa_cap") or {}).values())
    return f"{machine['cpu']}, {machine['torch_threads']} threads, instruction set " + (
        "capped to AVX2 (an estimate for an AVX2-only CPU)" if capped else "not capped"
    )


def _default_run_time(path: Path) -> str:
    """One sentence: how long the default run took from a fresh copy, where, and its slowest stages."""
    record = json.loads(path.read_text())
    slowest = sorted(record["stages"].items(), key=lambda item: -item[1])[:3]
    load = f" ({record['load_note']})" if record.get("load_note") else ", nothing else running"
    return (
        f"`dvc repro` from a fresh clone took **{record['total_seconds'] / 60:.1f} min** on {_run_machine(record)}{load}; "
        f"largest stage process {record['peak_memory_mb']:.0f} MB; slowest stages "
        + ", ".join(f"{stage} {seconds:.0f} s" for stage, seconds in slowest)
        + ".\n"
    )


def _default_run_stages(path: Path) -> str:
    """Every stage's seconds, slowest first, and its share of the run."""
    record = json.loads(path.read_text())
    total = record["total_seconds"]
    lines = [_default_run_time(path), "| stage | seconds | share |", "|---|---|---|"]
    for stage, seconds in sorted(record["stages"].items(), key=lambda item: -item[1]):
        lines.append(f"| {stage} | {seconds:.1f} | {100 * seconds / total:.0f}% |")
    return "\n".join(lines) + "\n"


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
    return "\n".join(lines) + "\n"


def _cell(value: object) -> str:
    """A value in a table: booleans lower case, floats to 3 significant digits."""
    if isinstance(value, bool):
        return str(value).lower()
    return f"{value:.3g}" if isinstance(value, float) else str(value)


def _full_run_stages(path: Path) -> str:
    """benchmarks/bench_full_run.py's record: the headline, each call, and every stage's seconds and peak memory."""
    record = json.loads(path.read_text())
    calls = "; ".join(
        f"{call['seconds'] / 60:.0f} min on {call['machine']['cpu']}{' (' + call['load_note'] + ')' if call['load_note'] else ''}"
        for call in record["calls"]
    )
    lines = [
        f"{record['headline']}. Calls: {calls}.",
        "",
        "| stage | seconds | share | peak memory MB |",
        "|---|---|---|---|",
    ]
    total = record["total_seconds"]
    for stage, measured in sorted(record["stages"].items(), key=lambda item: -item[1]["seconds"]):
        lines.append(
            f"| {stage} | {measured['seconds']:.0f} | {100 * measured['seconds'] / total:.0f}% | {measured['peak_rss_mb']:.0f} |"
        )
    lines += ["", "| learner | how its fit ended |", "|---|---|"]
    for learner, ended in record["convergence"].items():
        shown = ", ".join(f"{key} {_cell(value)}" for key, value in ended.items()) or "closed form (no iterations)"
        lines.append(f"| {learner} | {shown} |")
    return "\n".join(lines) + "\n"


def _bench_training_schedule(path: Path) -> str:
    """Every run of the auto-encoders' training settings, then the script's verdicts."""
    record = json.loads(path.read_text())
    lines = [
        f"`python benchmarks/bench_training_schedule.py --learners {record['args']['learners']} "
        f"--seeds {record['args']['seeds']}"
        + "".join(f' --settings "{setting}"' for setting in record["args"]["settings"])
        + "`:",
        "",
        "| learner | setting | seed | seconds | epochs | s / epoch | stop | best validation loss | fraction correct % |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, measured in record["learners"].items():
        for run in measured["runs"]:
            lines.append(
                f"| {name} | {run['setting']} | {run['seed']} | {run['seconds']:.0f} | {run['epochs_run']} "
                f"| {run['seconds_per_epoch']:.2f} | {run['stop_reason']} | {run['best_validation_loss']:.5f} "
                f"| {run['mean_fraction_correct']:.1f} |"
            )
    verdicts = "\n".join(f"- {line}" for line in record["headline"])
    return "\n".join(lines) + "\n\n" + verdicts + "\n\n" + _where(record) + "\n"


def _bench_headline(path: Path) -> str:
    """A CPU benchmark's own headline (ratio, convergence and quality, as the script states them) and
    where it ran."""
    record = json.loads(path.read_text())
    machine = record["machine"]
    capped = any((machine.get("isa_cap") or {}).values())
    where = f"{machine['cpu']}, {machine['torch_threads']} threads, instruction set " + (
        "capped to AVX2 (an estimate for an AVX2-only CPU)" if capped else "not capped"
    )
    load = record.get("load_note") or "nothing else running"
    return f"| result | measured on | load |\n|---|---|---|\n| {record['headline']} | {where} | {load} |\n"


def _bench_ica(path: Path) -> str:
    """benchmarks/bench_ica.py's record: one row per size and solver (and per components of the
    sweep), the equal-gradient ratios it states, and where it ran."""
    record = json.loads(path.read_text())
    lines = [
        "| size | solver | components | seconds | iterations | relative gradient | converged (< tol) "
        "| own stopping test met | peak memory GiB | Amari, known sources |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    rows = [
        (size, name, measured["n_components"], fit)
        for size, measured in record["sizes"].items()
        for name, fit in measured["fits"].items()
    ]
    sweep = record.get("components_sweep") or {"fits": {}}
    rows += [("full, sweep", "picard", int(k), fit) for k, fit in sweep["fits"].items()]
    for size, name, components, fit in rows:
        info = fit["record"]
        amari = fit.get("amari_known_sources")
        lines.append(
            f"| {size} | {name} | {components} | {fit['seconds']:.1f} | {info['n_iter']} | {info['gradient']:.1e} "
            f"| {str(info['converged']).lower()} | {str(info['own_criterion']['met']).lower()} "
            f"| {fit['peak_rss_bytes'] / 2**30:.2f} | {'' if amari is None else f'{amari:.4f}'} |"
        )
    ratios = "\n\n".join(record["headline"].split(" | "))
    return "\n".join(lines) + "\n\n" + _bench_ica_times(record) + ratios + "\n\n" + _where(record) + "\n"


def _bench_ica_times(record: dict) -> str:
    """Seconds (whitening included) until each solver's gradient stays below each target, per size;
    '-' where it never does (records of before the traces were kept: nothing)."""
    lines: list[str] = []
    for size, measured in record["sizes"].items():
        table = measured.get("seconds_to_stay_below")
        if not table:
            continue
        targets = list(next(iter(table.values())))
        lines += [
            f"{size}: seconds until the gradient stays below each target ('-': never)",
            "",
            "| solver | " + " | ".join(targets) + " |",
            "|---|" + "---|" * len(targets),
        ]
        for name, times in table.items():
            lines.append(
                f"| {name} | " + " | ".join("-" if times[t] is None else f"{times[t]:.1f}" for t in targets) + " |"
            )
        lines.append("")
    return "\n".join(lines) + ("\n" if lines else "")


def _compare_window_rules(path: Path) -> str:
    """benchmarks/compare_window_rules.py's record: per run, each rule's +seq fraction correct against 'clip'."""
    record = json.loads(path.read_text())
    lines = [
        "| run | cells | `ignore`: mean points, up / down | `shift`: mean points, up / down |",
        "|---|---|---|---|",
    ]
    for workspace, run in record["runs"].items():
        folder = Path(workspace)
        name = folder.parent.name if folder.name == "repo" else folder.name  # a test's workspace: its test
        cells = [
            f"{row['mean_points']:+.2f}, {row['up']} / {row['down']}"
            for row in (run["against_clip"][rule] for rule in ("ignore", "shift"))
        ]
        lines.append(f"| {name} | {run['against_clip']['clip']['cells']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + f"\n\nComputed on {record['machine']['cpu']} (fractions correct; no timing).\n"


def _bench_large_pair(path: Path) -> str:
    """benchmarks/bench_large_pair.py's record: each run's seconds and peak memory, the blocked
    path at the protocols' size and both paths side by side at a size the whole matrix fits."""
    record = json.loads(path.read_text())
    lines = [
        "| path | matcher | queries x database | seconds | peak memory MB (before it: descriptors, imports) | R@1 |",
        "|---|---|---|---|---|---|",
    ]
    side = record["side_by_side_places"]
    runs = [(record["size"], "blocks", matcher, run) for matcher, run in record["large"].items()]
    runs += [
        ([side, side], path_name, matcher, run)
        for matcher, paths in record["side_by_side"].items()
        for path_name, run in paths.items()
    ]
    for (n_queries, n_database), path_name, matcher, run in runs:
        lines.append(
            f"| {path_name} | {matcher} | {n_queries:,} x {n_database:,} | {run['seconds']:.1f} "
            f"| {run['peak_rss_mb']:,.0f} ({run['before_mb']:,.0f}) | {run['metrics']['recall_at_1']:.4f} |"
        )
    same = all(paths["whole"]["metrics"] == paths["blocks"]["metrics"] for paths in record["side_by_side"].values())
    return (
        "\n".join(lines)
        + f"\n\nD = {record['dim']}, {record['metric']} distance, correct within {record['tolerance']} places; "
        + f"metrics of the two paths identical at {side:,} x {side:,}: {same}. {_where(record)}\n"
    )


def _bench_scaling(path: Path) -> str:
    """benchmarks/bench_scaling.py's record: every stage's seconds and peak memory against places,
    its growth exponents and share of the full run, the commit each size ran from, and where."""
    record = json.loads(path.read_text())
    places = record["places"]
    lines = [
        "| stage | "
        + " | ".join(f"s at {size:,}" for size in places)
        + " | time exponent | peak MB at "
        + f"{places[0]:,} / {places[-1]:,} | memory exponent | share of the full run |",
        "|---|" + "---|" * (len(places) + 4),
    ]
    for stage, row in sorted(record["stages"].items(), key=lambda item: -item[1]["seconds"][-1]):

        def exponent(value: float | None) -> str:
            return "-" if value is None else f"{value:.2f}"

        lines.append(
            f"| {stage} | "
            + " | ".join(f"{value:.0f}" for value in row["seconds"])
            + f" | {exponent(row['time_exponent'])} | {row['peak_rss_mb'][0]:,.0f} / {row['peak_rss_mb'][-1]:,.0f} "
            + f"| {exponent(row['memory_exponent'])} | {100 * row['share_of_full_run']:.1f}% |"
        )
    runs = [(size, record["runs"][str(size)]) for size in places]
    made_from = ", ".join(f"{size:,}: {run.get('made_from', {}).get('commit', '?')}" for size, run in runs)
    notes = [f"{size:,}: {call['load_note']}" for size, run in runs for call in run["calls"] if call.get("load_note")]
    where = _where({**record["runs"][str(places[-1])]["calls"][-1], "load_note": "; ".join(notes)})
    return (
        "\n".join(lines)
        + f"\n\n{record['headline']}. Places a season per run and the commit its folder was made from: "
        + f"{made_from}. {where}\n"
    )


def _where(record: dict) -> str:
    machine = record["machine"]
    capped = any((machine.get("isa_cap") or {}).values())
    cap = "capped to AVX2 (an estimate for an AVX2-only CPU)" if capped else "not capped"
    load = record.get("load_note") or "nothing else running"
    return f"Measured on {machine['cpu']}, {machine['torch_threads']} threads, instruction set {cap}; {load}."


def _whole(path: Path) -> str:
    """The pipeline's own markdown as it is."""
    return path.read_text().strip() + "\n"


CLAIMS = ROOT / "docs" / "claims.yaml"


# the calibration targets of docs/statistics.md: a 95% interval covers 94-96.5%, a test at 5% errs
# at most 5.5% of the time; a cell outside them is marked
COVERAGE_TARGET, FALSE_POSITIVE_TARGET = (0.94, 0.965), 0.055


def _monte_carlo_error(cell: dict, nominal: float) -> float:
    return (nominal * (1 - nominal) / cell["replicates"]) ** 0.5


def _coverage_off(cell: dict) -> bool:
    """Outside COVERAGE_TARGET by more than two Monte Carlo standard errors."""
    margin = 2 * _monte_carlo_error(cell, 0.95)
    return not COVERAGE_TARGET[0] - margin <= cell["rate"] <= COVERAGE_TARGET[1] + margin


def _false_positives_off(cell: dict) -> bool:
    """Above FALSE_POSITIVE_TARGET by more than two Monte Carlo standard errors."""
    return cell["rate"] > FALSE_POSITIVE_TARGET + 2 * _monte_carlo_error(cell, 0.05)


def _rate_cell(cell: dict, off: Callable[[dict], bool] = lambda cell: False) -> str:
    if cell["rate"] is None:
        return "refused"
    return f"{cell['rate']:.3f}" + (" †" if off(cell) else "")


def _calibration_rows(path: Path, run: str = "params") -> tuple[dict, list[dict]]:
    record = json.loads(path.read_text())
    return record, record["runs"][run]["rows"]


def _calibration_legend(record: dict, run: str = "params", replicates: int | None = None) -> str:
    """replicates: the simulated routes a cell of the table has (default: the record's)."""
    statistics, replicates = record["runs"][run]["statistics"], replicates or record["replicates"]
    error = (0.95 * 0.05 / replicates) ** 0.5
    return (
        f"{replicates} simulated routes a cell (Monte Carlo standard error {100 * error:.1f} points at 95% "
        f"or 5%); degrees_scale {statistics['degrees_scale']}; "
        f"refused: fewer than {record['runs'][run]['min_queries']} queries a route (the pipeline writes "
        '"not enough queries"); † outside the target by more than two Monte Carlo standard errors.'
    )


def _by_fraction(rows: list[dict], ps: list[float], keys: tuple[str, ...], cell: Callable[[dict], str | None]) -> str:
    """A table of the grid: a line per value of `keys` (e.g. dependence and n), a column per fraction p,
    cell(row) the text of a row of the record (None: the row is not in this table)."""
    cells: dict[tuple, dict[float, str]] = {}
    for row in rows:
        text = cell(row)
        if text is not None:
            cells.setdefault(tuple(row[key] for key in keys), {})[row["p"]] = text
    lines = ["| " + " | ".join(keys) + " | " + " | ".join(f"p = {p}" for p in ps) + " |"]
    lines.append("|" + "---|" * (len(keys) + len(ps)))
    for key, by_p in cells.items():
        lines.append("| " + " | ".join(map(str, key)) + " | " + " | ".join(by_p.get(p, "") for p in ps) + " |")
    return "\n".join(lines)


def _calibration_coverage(path: Path) -> str:
    """Coverage of the 95% interval along the route (Wilson's in brackets) per dependence, n and p."""
    record, rows = _calibration_rows(path)

    def cell(row: dict) -> str | None:
        if "coverage" not in row:
            return None
        return f"{_rate_cell(row['coverage']['route'], _coverage_off)} ({row['coverage']['wilson']['rate']:.3f})"

    table = _by_fraction(rows, record["grid"]["p"], ("dependence", "n"), cell)
    return table + "\n\n" + _calibration_legend(record) + " In brackets: Wilson's interval.\n"


def _calibration_false_positives(path: Path) -> str:
    """Equal learners called different: per comparison / per table (Holm), per dependence, n, routes and p."""
    record, rows = _calibration_rows(path)

    def cell(row: dict) -> str:
        rates = row["false_positive"]
        return " / ".join(_rate_cell(rates[kind], _false_positives_off) for kind in ("per_comparison", "per_table"))

    size = record["grid"]["table_learners"]
    return (
        _by_fraction(rows, record["grid"]["p"], ("dependence", "n", "routes"), cell)
        + f"\n\nCells: per comparison / per table ({size} learners of equal laws, {size * (size - 1) // 2} "
        "comparisons, Holm). routes > 1: that many independent routes pooled (p = 0.5 only). "
        + _calibration_legend(record)
        + "\n"
    )


def _calibration_power(path: Path) -> str:
    """How often the paired test finds a difference of 3, 5 and 10 points (and the difference's interval coverage)."""
    record, rows = _calibration_rows(path)
    differences = sorted(next(iter(rows))["power"], key=float)
    header = [f"power at {100 * float(d):.0f} points" for d in differences]
    header += [f"interval coverage at {100 * float(d):.0f}" for d in differences]
    lines = ["| dependence | n | routes | p | " + " | ".join(header) + " |", "|---|---|---|---|" + "---|" * len(header)]
    for row in rows:
        if row["p"] != 0.5:
            continue
        power = [_rate_cell(row["power"][d]["power"]) for d in differences]
        coverage = [_rate_cell(row["power"][d]["interval_coverage"], _coverage_off) for d in differences]
        lines.append(
            f"| {row['dependence']} | {row['n']} | {row['routes']} | {row['p']} | "
            + " | ".join(power + coverage)
            + " |"
        )
    return (
        "\n".join(lines)
        + "\n\nPower: the share of routes on which the paired test (one comparison, at alpha) finds the difference, in its direction. "
        + _calibration_legend(record, replicates=_power_replicates(rows))
        + "\n"
    )


def _power_replicates(rows: list[dict]) -> int:
    """The simulated routes of a power cell (check_calibration draws half as many as for the others)."""
    cell = next(iter(rows[-1]["power"].values()))["power"]
    return cell["replicates"] + cell["refused"]


def _calibration_difference_coverage(path: Path) -> str:
    """The 95% interval of a difference where the difference is real: its lowest coverage over the
    differences of the grid, per dependence, n and the first learner's fraction (one route)."""
    record, rows = _calibration_rows(path)

    def cell(row: dict) -> str | None:
        if row["routes"] != 1:
            return None
        answered = [
            cell["interval_coverage"] for cell in row["power"].values() if cell["interval_coverage"]["rate"] is not None
        ]
        return _rate_cell(min(answered, key=lambda cell: cell["rate"]) if answered else {"rate": None}, _coverage_off)

    table = _by_fraction(rows, record["grid"]["p"], ("dependence", "n"), cell)
    differences = ", ".join(f"{100 * float(d):.0f}" for d in sorted(next(iter(rows))["power"], key=float))
    return (
        table
        + f"\n\nCells: the lowest coverage over differences of {differences} points (the second learner's fraction p "
        "plus the difference, minus where that passes 0.99). "
        + _calibration_legend(record, replicates=_power_replicates(rows))
        + "\n"
    )


def _calibration_llsw(path: Path) -> str:
    """The params' degrees_scale beside LLSW's 0.4: worst coverage and worst false-positive rate per dependence and n."""
    record = json.loads(path.read_text())
    runs = {name: record["runs"][name] for name in ("params", "llsw")}  # JSON keys come back sorted
    scales = {name: run["statistics"]["degrees_scale"] for name, run in runs.items()}
    lines = [
        "| dependence | n | "
        + " | ".join(f"scale {scales[name]}: coverage, lowest / highest" for name in runs)
        + " | "
        + " | ".join(f"scale {scales[name]}: false positives, highest" for name in runs)
        + " |",
        "|---|---|" + "---|" * (2 * len(runs)),
    ]
    keys = sorted(
        {(row["dependence"], row["n"]) for row in runs["llsw"]["rows"]},
        key=lambda key: (list(record["grid"]["n"]).index(key[1]), key[0]),
    )
    for dependence, n in keys:
        coverage, false_positive = [], []
        for run in runs.values():
            rows = [row for row in run["rows"] if (row["dependence"], row["n"], row["routes"]) == (dependence, n, 1)]
            rates = [row["coverage"]["route"]["rate"] for row in rows if row["coverage"]["route"]["rate"] is not None]
            fps = [
                row["false_positive"]["per_comparison"]["rate"]
                for row in rows
                if row["false_positive"]["per_comparison"]["rate"] is not None
            ]
            coverage.append(f"{min(rates):.3f} / {max(rates):.3f}" if rates else "refused")
            false_positive.append(f"{max(fps):.3f}" if fps else "refused")
        lines.append(f"| {dependence} | {n} | " + " | ".join(coverage + false_positive) + " |")
    return (
        "\n".join(lines)
        + f"\n\nOver p in {list(record['grid']['p'])}, one route; {record['replicates']} simulated routes a cell.\n"
    )


def _calibration_means(path: Path) -> str:
    """Coverage of the 95% interval of the mean over six pairs, per dependence, n and fractions."""
    record = json.loads(path.read_text())
    names = list(record["fractions"])
    lines = [
        "| dependence | n | " + " | ".join(f"pairs {name}" for name in names) + " |",
        "|---|---|" + "---|" * len(names),
    ]
    cells: dict[tuple[str, int], dict[str, str]] = {}
    for row in record["rows"]:
        cells.setdefault((row["dependence"], row["n"]), {})[row["fractions"]] = _rate_cell(
            row["coverage"], _coverage_off
        )
    for (dependence, n), by_name in cells.items():
        lines.append(f"| {dependence} | {n} | " + " | ".join(by_name[name] for name in names) + " |")
    shares = ", ".join(
        f"{kind} {fit['pair_share']:.2f} (outcomes' correlation {fit['pair_correlation_measured']:.2f})"
        for kind, fit in record["fitted"].items()
    )
    fractions = "; ".join(f"{name}: {list(values)}" for name, values in record["fractions"].items())
    error = (0.95 * 0.05 / record["replicates"]) ** 0.5
    return (
        "\n".join(lines)
        + f"\n\nFractions of the six pairs: {fractions}. Latent share between two pairs, fitted: {shares}. "
        f"{record['replicates']} simulated runs a cell (Monte Carlo standard error {100 * error:.1f} points); "
        "† outside 94-96.5% by more than two standard errors.\n"
    )


def _calibration_fit(path: Path) -> str:
    """The dependence the simulation was given: fitted to the run's per-query outcomes."""
    record = json.loads(path.read_text())
    lags = ("1", "2", "5", "10")
    lines = [
        "| outcomes | evaluations | a | phi | share | "
        + " | ".join(f"autocorr. lag {lag}: run / fitted" for lag in lags)
        + " | learners' correlation |",
        "|---|---|---|---|---|" + "---|" * (len(lags) + 1),
    ]
    for kind, fit in record["fitted"].items():
        d = fit["dependence"]
        cells = [
            f"{fit['autocorrelation_measured'][lag]:.2f} / {fit['autocorrelation_fitted'][lag]:.2f}" for lag in lags
        ]
        lines.append(
            f"| {kind} | {fit['evaluations']} | {d['a']:.2f} | {d['phi']:.2f} | {d['share']:.2f} | "
            + " | ".join(cells)
            + f" | {fit['learner_correlation_measured']:.2f} |"
        )
    return "\n".join(lines) + "\n"


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


def _routes_line(record: dict) -> str:
    """Which routes a replicate record stands on, and what their queue cost."""
    seeds = ", ".join(str(route["seed"]) for route in record["routes"].values())
    cost = (
        f"; the queue of the {len(record['routes']) - 1} extra routes took {record['queue_seconds'] / 60:.0f} min, "
        f"{record['jobs']} at a time, on {record['machine']['cpu']}"
        if record.get("queue_seconds")
        else ""
    )
    return f"{len(record['routes'])} routes (synthetic.seed {seeds}){cost}."


def _spread_cell(spread: dict) -> str:
    """A fraction correct's spread over the routes (replicates.fraction_spread), in %: "mean ± std [lowest, highest]"."""
    return (
        f"{100 * spread['mean']:.1f} ± {100 * spread['std']:.1f} [{100 * spread['min']:.0f}, {100 * spread['max']:.0f}]"
    )


def _replicate_spread(path: Path) -> str:
    """Fraction correct over the replicate routes, under the main distance: mean ± standard
    deviation [lowest, highest], in %."""
    record = json.loads(path.read_text())
    pairs = record["pairs"]
    lines = [_routes_line(record), "", "| method | " + " | ".join(pairs) + " |", "|---|" + "---|" * len(pairs)]
    for label in record["order"]["labels"]:
        by_pair = record["fraction_correct"][label]
        if "@" in label:
            continue
        cells = [_spread_cell(by_pair[pair]) for pair in pairs]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _replicate_training_seasons(path: Path) -> str:
    """The training-season ablation over the replicate routes: per label and training set, fraction
    correct mean ± standard deviation [lowest, highest] (%); in how many routes the largest training
    set is above, below or equal to the smallest."""
    record = json.loads(path.read_text())
    spread, changes = record["training_seasons"]["fraction_correct"], record["training_seasons"]["first_to_last"]
    sets = sorted(next(iter(spread.values())), key=lambda name: name.count("+"))
    lines = [
        _routes_line(record),
        "",
        "| method | " + " | ".join(sets) + " | largest set against smallest |",
        "|---|" + "---|" * (len(sets) + 1),
    ]
    for label, by_set in spread.items():
        cells = [_spread_cell(by_set[name]) for name in sets]
        change = changes[label]
        cells.append(f"above in {change['up']}, below in {change['down']}, equal in {change['same']}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _replicate_totals(cells: list[dict], routes: int) -> str:
    """A claim over every route-pair cell: ahead / significant counts of all, and on how many pairs
    its pooled verdict is significant each way."""
    if "ahead" not in cells[0]:  # a whole table
        better, worse, of = (sum(cell[f"pooled_{key}"] for cell in cells) for key in ("better", "worse", "of"))
        return f"pooled ▲ {better} ▼ {worse} of {of} comparisons"
    pooled_better = sum(cell["pooled_verdict"] == "better" for cell in cells)
    pooled_worse = sum(cell["pooled_verdict"] == "worse" for cell in cells)
    pooled = f"pooled ▲ on {pooled_better}, ▼ on {pooled_worse} of {len(cells)} pairs"
    total = routes * len(cells)
    ahead, better, worse = (sum(cell[key] for cell in cells) for key in ("ahead", "better", "worse"))
    return f"ahead in {ahead}/{total}, ▲ {better} ▼ {worse}; {pooled}"


def _replicate_claims(path: Path) -> str:
    """Each claim of docs/claims.yaml over the replicate routes: per pair, in how many routes it
    points each way and is significant, and its pooled verdict."""
    record = json.loads(path.read_text())
    pairs, routes = record["pairs"], len(record["routes"])
    lines = [
        _routes_line(record),
        "",
        "| claim | compares | " + " | ".join(pairs) + " | all pairs |",
        "|---|---|" + "---|" * (len(pairs) + 1),
    ]
    for name in record["order"]["claims"]:
        by_pair = record["claims"][name]
        cells = []
        for pair in pairs:
            counts = by_pair[pair]
            if "ahead" in counts:
                routes_cell = f"ahead in {counts['ahead']}/{routes}, ▲ {counts['better']} ▼ {counts['worse']}"
            else:
                better = f"{counts['least_better']}-{counts['most_better']}"
                worse = f"{counts['least_worse']}-{counts['most_worse']}"
                routes_cell = f"▲ {better} ▼ {worse} per route"
            cells.append(f"{routes_cell}; pooled {counts['pooled']}")
        cells.append(_replicate_totals([by_pair[pair] for pair in pairs], routes))
        lines.append(f"| {name} | {record['claims_says'][name]} | " + " | ".join(cells) + " |")
    legend = (
        "Cells: in how many routes the first side's point estimate is ahead, and in how many it is "
        "significantly better (▲) or worse (▼) by that route's own paired test (for a whole table: the "
        "range over the routes of its significant comparisons each way); all pairs: the same counted over "
        "every route and pair; pooled: every route's queries of the pair together, the same paired test "
        "and Holm correction as in one run, each route's variance along it its own "
        "(seasonloop.reporting.replicates; a statement about these routes' queries)."
    )
    return "\n".join(lines) + "\n\n" + legend + "\n"


# the synthetic runs a run on other data is read beside (table real_claims): column -> its snapshot
SYNTHETIC_RUNS = {
    "default route": "comparisons.json",
    "five routes, pooled": "replicate_routes.json",
    "full preset": "full_comparisons.json",
}


EVAL_COLUMNS = {
    "recall_at_1": "R@1",
    "recall_at_5": "R@5",
    "recall_at_10": "R@10",
    "recall_at_100_precision": "recall at 100% precision",
    "auc_pr": "AUC-PR",
    "auc_pr_vpr_tutorial": "AUC-PR (VPR_Tutorial)",
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
            cells = " | ".join(f"{100 * record[key]:.1f}" for key in EVAL_COLUMNS)
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
    claims = {name: claim for name, claim in yaml.safe_load(CLAIMS.read_text()).items() if "run" not in claim}
    synthetic = synthetic_records()
    columns = [*SYNTHETIC_RUNS, "real frames"]
    lines = [
        "| claim | compares | pair | " + " | ".join(columns) + " | on real frames |",
        "|---|---|---|" + "---|" * (len(columns) + 1),
    ]
    beside = claims_beside(record, synthetic, claims)
    for pair in record["order"]["pairs"]:
        for name, claim in claims.items():
            values = beside[name][pair]["values"]
            cells = " | ".join(claim_cell(values[column]) for column in [*SYNTHETIC_RUNS, "other"])
            lines.append(f"| {name} | {claim['says']} | {pair} | {cells} | {beside[name][pair]['reading']} |")
    readings = "; ".join(f"{key}: {meaning}" for key, meaning in READINGS.items())
    return (
        "\n".join(lines)
        + "\n\n"
        + legend(record["statistics"])
        + " Whole tables: significant differences each way. Five routes, pooled: every route's queries together "
        + f"(docs/results.md). On real frames: {readings}.\n"
    )


# table name -> (the output file it is written from, its snapshot in docs/results/, how)
TABLES: dict[str, tuple[str, str, Callable[[Path], str]]] = {
    "fraction_correct": ("plots/summary/fraction_correct.md", "fraction_correct.md", _fraction_correct),
    "pr_landmarks": ("plots/summary/pr_landmarks.md", "pr_landmarks.md", _fraction_correct),
    # paired comparisons (docs/results.md: how sure): every table, and the claims the prose cites
    "comparisons": ("plots/comparisons.md", "comparisons.md", _whole),
    "claims": ("metrics/comparisons.json", "comparisons.json", _claims_of("default")),
    # the statistics' real coverage and error rates on simulated routes (docs/statistics.md)
    **{
        name: ("benchmarks/results/check_calibration.json", "check_calibration.json", writer)
        for name, writer in (
            ("calibration_fit", _calibration_fit),
            ("calibration_coverage", _calibration_coverage),
            ("calibration_false_positives", _calibration_false_positives),
            ("calibration_power", _calibration_power),
            ("calibration_difference_coverage", _calibration_difference_coverage),
            ("calibration_llsw", _calibration_llsw),
        )
    },
    "calibration_means": (
        "benchmarks/results/check_calibration_means.json",
        "check_calibration_means.json",
        _calibration_means,
    ),
    "runtime": ("plots/summary/runtime.md", "runtime.md", _fraction_correct),
    "autoencoder_training": ("metrics/autoencoder_training.json", "autoencoder_training.json", _autoencoder_training),
    "cae_widths": ("metrics/cae_widths.json", "cae_widths_sweep.json", _cae_widths),
    # the global ICA's fit and its basis images (docs/results.md)
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
    "real_ica_basis": ("metrics/fit/ica.json", "real_ica_fit.json", _ica_fit),
    # three runs of the benchmark (its file is rewritten by each): Table 5's width, the default
    # width, and the default width trained to its plateau in float32 and bfloat16
    "bench_autoencoders_table5": (
        "benchmarks/results/bench_autoencoders.json",
        "bench_autoencoders_table5.json",
        _bench_autoencoders,
    ),
    "bench_autoencoders_width16": (
        "benchmarks/results/bench_autoencoders.json",
        "bench_autoencoders_width16.json",
        _bench_autoencoders,
    ),
    "bench_autoencoders_plateau": (
        "benchmarks/results/bench_autoencoders.json",
        "bench_autoencoders_plateau.json",
        _bench_autoencoders,
    ),
    "check_cross_isa": ("benchmarks/results/check_cross_isa.json", "check_cross_isa.json", _check_cross_isa),
    "bench_ica": ("benchmarks/results/bench_ica.json", "bench_ica.json", _bench_ica),
    "check_cross_blas": ("benchmarks/results/check_cross_blas.json", "check_cross_blas.json", _check_cross_blas),
    # the default run timed from a fresh copy, uncapped and capped to AVX2 (docs/results.md)
    "default_run_stages": ("benchmarks/results/bench_default_run.json", "bench_default_run.json", _default_run_stages),
    "default_run_stages_capped": (
        "benchmarks/results/bench_default_run_capped.json",
        "bench_default_run_capped.json",
        _default_run_stages,
    ),
    "bench_pca": ("benchmarks/results/bench_pca.json", "bench_pca.json", _bench_headline),
    # five runs of the benchmark (its file is rewritten by each): halved training sets, the
    # settings between those and params.yaml's, then the training's kernels (fused Adam, denormals
    # flushed, the CAE's sub-pixel up-sampling) against the ones before, and three more seeds of the CAE
    "bench_training_schedule": (
        "benchmarks/results/bench_training_schedule.json",
        "bench_training_schedule.json",
        _bench_training_schedule,
    ),
    "bench_training_schedule_subsets": (
        "benchmarks/results/bench_training_schedule.json",
        "bench_training_schedule_subsets.json",
        _bench_training_schedule,
    ),
    "bench_training_kernels": (
        "benchmarks/results/bench_training_schedule.json",
        "bench_training_kernels.json",
        _bench_training_schedule,
    ),
    "bench_training_kernels_cae_seeds": (
        "benchmarks/results/bench_training_schedule.json",
        "bench_training_kernels_cae_seeds.json",
        _bench_training_schedule,
    ),
    "bench_matching": ("benchmarks/results/bench_matching.json", "bench_matching.json", _bench_headline),
    # DVC's per-stage work with ruamel.yaml's C parser and without (the suite's and every run's overhead)
    "bench_dvc_yaml": ("benchmarks/results/bench_dvc_yaml.json", "bench_dvc_yaml.json", _bench_headline),
    "bench_scaling": ("benchmarks/results/bench_scaling.json", "bench_scaling.json", _bench_scaling),
    "bench_large_pair": ("benchmarks/results/bench_large_pair.json", "bench_large_pair.json", _bench_large_pair),
    # two runs of benchmarks/compare_window_rules.py (its file is rewritten by each): the full preset
    # run's outputs, then the default run's and the tests' non-aligned workspaces
    "compare_window_rules_full": (
        "benchmarks/results/compare_window_rules.json",
        "compare_window_rules_full.json",
        _compare_window_rules,
    ),
    "compare_window_rules": (
        "benchmarks/results/compare_window_rules.json",
        "compare_window_rules.json",
        _compare_window_rules,
    ),
    # presets/full.yaml run in one piece by benchmarks/bench_full_run.py (docs/full-scale.md): its
    # timing record here, its outputs in the run's own folder (--from FOLDER)
    "full_run_stages": ("benchmarks/results/bench_full_run.json", "bench_full_run.json", _full_run_stages),
    "full_fraction_correct": ("plots/summary/fraction_correct.md", "full_fraction_correct.md", _fraction_correct),
    "full_pr_landmarks": ("plots/summary/pr_landmarks.md", "full_pr_landmarks.md", _fraction_correct),
    "full_autoencoder_training": (
        "metrics/autoencoder_training.json",
        "full_autoencoder_training.json",
        _autoencoder_training,
    ),
    "full_training_seasons": ("metrics/training_seasons.json", "full_training_seasons.json", _training_seasons),
    "full_cae_widths": ("metrics/cae_widths.json", "full_cae_widths_sweep.json", _cae_widths),
    "full_ica_basis": ("metrics/fit/ica.json", "full_ica_fit.json", _ica_fit),
    "full_claims": ("metrics/comparisons.json", "full_comparisons.json", _claims_of("full")),
    # the default params on several synthetic routes (benchmarks/replicate_routes.py)
    "replicate_spread": ("benchmarks/results/replicate_routes.json", "replicate_routes.json", _replicate_spread),
    "replicate_claims": ("benchmarks/results/replicate_routes.json", "replicate_routes.json", _replicate_claims),
    "replicate_training_seasons": (
        "benchmarks/results/replicate_routes.json",
        "replicate_routes.json",
        _replicate_training_seasons,
    ),
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
    "real_ica_basis",
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
    return f"{commit}{' + uncommitted changes' if dirty else ''}"


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
        f"commit {run.get('commit', '?')}{' + uncommitted changes' if run.get('dirty') else ''} "
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


def snapshot(names: list[str], command: str, workspace: Path = ROOT) -> None:
    """Copy the named tables' output files of `workspace` (this repository, or a clone that ran
    other params) into docs/results/ and record where they came from."""
    git = ["git", "-C", str(workspace)]
    commit = subprocess.run(
        [*git, "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
    ).stdout.strip()
    dirty = bool(
        subprocess.run(
            [*git, "status", "--porcelain", "--untracked-files=no"], capture_output=True, text=True, check=True
        ).stdout.strip()
    )
    bench_source = workspace / "bench_source.json"  # a folder of bench_full_run.py: its own commit only sets params
    if bench_source.is_file():
        made_from = json.loads(bench_source.read_text())["made_from"]
        commit, dirty = made_from["commit"], made_from["dirty"]
    provenance = json.loads(PROVENANCE.read_text()) if PROVENANCE.is_file() else {}
    RESULTS.mkdir(parents=True, exist_ok=True)
    for name in names:
        source, copy, _ = TABLES[name]
        if not (workspace / source).exists():
            raise FileNotFoundError(f"{workspace / source}: not found (run the pipeline first)")
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
        "--from", dest="workspace", type=Path, default=ROOT, help="the clone whose outputs to copy (default: this one)"
    )
    args = parser.parse_args()
    if args.snapshot is not None:
        # none named: every table of this clone's default run and benchmarks, not the runs of other params
        snapshot(
            args.snapshot or [name for name in TABLES if name not in OTHER_RUNS], args.command, args.workspace.resolve()
        )
    provenance = json.loads(PROVENANCE.read_text()) if PROVENANCE.is_file() else {}
    for document in DOCUMENTS:
        document.write_text(rewrite(document.read_text(), provenance, results_folder(document)))


def results_folder(document: Path) -> str:
    """docs/results/ as a link from `document`."""
    return "docs/results" if document == README else "results"


if __name__ == "__main__":
    main()
