"""Write the README's results tables from the pipeline's own output files, never by hand.

    python docs/write_tables.py --snapshot   # copy the run's output files into docs/results/, then write
    python docs/write_tables.py              # rewrite the README's tables from docs/results/

`--snapshot` copies each table's source (an output of `dvc repro` or of a `dvc exp run`) into
docs/results/ together with where it came from (the git commit, whether the workspace had
uncommitted changes, the CPU), so that the tables can be checked in a clone that has no pipeline
outputs: tests/test_readme_tables.py fails when a README table differs from what this script
writes from docs/results/. A table's block in README.md sits between
`<!-- table: NAME -->` and `<!-- /table -->`.
"""

from __future__ import annotations

import argparse
import json
import platform
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from seasonloop.cae_widths import width_table  # noqa: E402

RESULTS = ROOT / "docs" / "results"
README = ROOT / "README.md"
PROVENANCE = RESULTS / "provenance.json"


def _fraction_correct(path: Path) -> str:
    """The pipeline's own markdown, without its title line."""
    return path.read_text().split("\n", 2)[2].strip() + "\n"


def _autoencoder_training(path: Path) -> str:
    record = json.loads(path.read_text())
    columns = ["stop_reason", "converged", "epochs_run", "best_epoch", "best_validation_loss", "n_train_images",
               "n_validation_images", "images_seen", "precision", "training_seconds"]
    lines = ["| learner | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for learner, row in record.items():
        cells = [f"{row[key]:.5f}" if key == "best_validation_loss" else f"{row[key]:.0f}" if key == "training_seconds"
                 else str(row[key]).lower() if isinstance(row[key], bool) else str(row[key]) for key in columns]
        lines.append(f"| {learner} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _cae_widths(path: Path) -> str:
    return width_table(json.loads(path.read_text()))


# table name -> (the output file it is written from, its snapshot in docs/results/, how)
TABLES: dict[str, tuple[str, str, Callable[[Path], str]]] = {
    "fraction_correct": ("plots/summary/fraction_correct.md", "fraction_correct.md", _fraction_correct),
    "autoencoder_training": ("metrics/autoencoder_training.json", "autoencoder_training.json", _autoencoder_training),
    "cae_widths": ("metrics/cae_widths.json", "cae_widths_sweep.json", _cae_widths),
}


def provenance_line(name: str, provenance: dict) -> str:
    source, snapshot, _ = TABLES[name]
    run = provenance.get(name, {})
    return (f"_Written by `docs/write_tables.py` from `{source}` (copy: `docs/results/{snapshot}`), produced at "
            f"commit {run.get('commit', '?')}{' + uncommitted changes' if run.get('dirty') else ''} "
            f"by `{run.get('command', 'dvc repro')}` on {run.get('cpu', '?')}._\n")


def table_block(name: str, provenance: dict) -> str:
    _, snapshot, render = TABLES[name]
    return render(RESULTS / snapshot) + "\n" + provenance_line(name, provenance)


def rewrite(text: str, provenance: dict) -> str:
    """README text with every table block rewritten."""
    def replace(match: re.Match) -> str:
        name = match.group(1)
        if name not in TABLES:
            raise ValueError(f"README.md: unknown table '{name}' (known: {', '.join(TABLES)})")
        return f"<!-- table: {name} -->\n{table_block(name, provenance)}<!-- /table -->"

    return re.sub(r"<!-- table: (\w+) -->\n.*?<!-- /table -->", replace, text, flags=re.S)


def cpu_model() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown CPU"


def snapshot(names: list[str], command: str) -> None:
    """Copy the named tables' output files into docs/results/ and record where they came from."""
    git = ["git", "-C", str(ROOT)]
    commit = subprocess.run([*git, "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True).stdout.strip()
    dirty = bool(subprocess.run([*git, "status", "--porcelain", "--untracked-files=no"], capture_output=True, text=True,
                                check=True).stdout.strip())
    provenance = json.loads(PROVENANCE.read_text()) if PROVENANCE.is_file() else {}
    RESULTS.mkdir(parents=True, exist_ok=True)
    for name in names:
        source, copy, _ = TABLES[name]
        if not (ROOT / source).is_file():
            raise FileNotFoundError(f"{source}: not found (run the pipeline first)")
        shutil.copyfile(ROOT / source, RESULTS / copy)
        provenance[name] = {"commit": commit, "dirty": dirty, "command": command, "cpu": cpu_model()}
    PROVENANCE.write_text(json.dumps(provenance, indent=2, sort_keys=True) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--snapshot", nargs="*", metavar="TABLE",
                        help=f"copy these tables' output files first (none named: all of {', '.join(TABLES)})")
    parser.add_argument("--command", default="dvc repro", help="the command that produced the outputs (recorded)")
    args = parser.parse_args()
    if args.snapshot is not None:
        snapshot(args.snapshot or list(TABLES), args.command)
    provenance = json.loads(PROVENANCE.read_text()) if PROVENANCE.is_file() else {}
    README.write_text(rewrite(README.read_text(), provenance))


if __name__ == "__main__":
    main()
