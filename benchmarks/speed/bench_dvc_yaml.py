"""DVC's own work per stage with ruamel.yaml's C parser (ruamel.yaml.clib) against its pure-Python
parser, side by side on the same tiny pipeline.

DVC reads params.yaml, dvc.yaml, dvc.lock and its run cache with ruamel.yaml, several times a
stage; from ruamel.yaml 0.19 its C parser is used only when ruamel.yaml.clib is installed (a
dependency of this project for that reason). The pure parser is forced in a process of its own by
clearing ruamel.yaml's C classes before DVC starts; everything else is the same installation.

A workspace with the end-to-end tests' one-learner params (tools/small_runs.py DATA_PATH, 16
stages) is run once, then, for each parser in turn, `repeats` times:
- `dvc status`: DVC's start-up and its reading of every stage;
- `dvc repro` with every stage up to date;
- `dvc repro` after dvc.lock is removed: every stage restored from DVC's run cache, no stage's
  command run, so all of it is DVC's own work per stage;
- `dvc repro --force`: every stage's command run again (what a test or a user pays).
The dvc.lock each parser restores must be byte-identical.

    python -m benchmarks.speed.bench_dvc_yaml [--repeats 3]

Writes benchmarks/results/bench_dvc_yaml.json; the headline line is printed last. Nothing else
should run meanwhile (the load before and after is recorded).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

from benchmarks.common import copy_repository, headline_table, load_note, save_and_report
from tools.records import machine

# DVC's command line with ruamel.yaml's C classes cleared first: YAML(typ="safe") then picks the
# pure-Python parser and emitter, as when ruamel.yaml.clib is not installed
PURE = "import sys, ruamel.yaml.main as m; m.CParser = m.CEmitter = None; from dvc.cli import main; sys.exit(main())"
C_PARSER = "import sys; from dvc.cli import main; sys.exit(main())"
PARSERS = {"pure": PURE, "c": C_PARSER}
COMMANDS = {
    "status": ["status"],
    "repro_up_to_date": ["repro"],
    "repro_restored": ["repro"],  # after removing dvc.lock
    "repro_forced": ["repro", "--force"],
}


def check_c_parser() -> None:
    from ruamel.yaml import YAML
    from ruamel.yaml.main import CParser

    if CParser is None or YAML(typ="safe").Parser is not CParser:
        raise SystemExit(
            "ruamel.yaml's C parser is not installed (ruamel.yaml.clib): pip install -c requirements.lock -e ."
        )


def dvc(root: Path, parser: str, *args: str) -> float:
    """Wall seconds of one DVC command in root run with `parser`; stops on a failure. The stages it
    runs find this Python first on PATH (tools/repository.py tool_env), venv activated or not."""
    from tools.repository import tool_env

    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", PARSERS[parser], *args], cwd=root, env=tool_env(), capture_output=True, text=True
    )
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"dvc {' '.join(args)} ({parser} parser) failed in {root}:\n{done.stderr[-2000:]}")
    return seconds


def make_workspace(root: Path) -> int:
    """The repository at root with the tests' one-learner params, run once; its number of stages."""
    from tools.repository import commit_all, write_params
    from tools.small_runs import DATA_PATH

    copy_repository(root)
    write_params(root, DATA_PATH)
    commit_all(root)
    dvc(root, "c", "repro")
    return len(yaml.safe_load((root / "dvc.lock").read_text())["stages"])


def measure(root: Path, repeats: int) -> tuple[dict[str, dict[str, float]], bool]:
    """command -> parser -> fastest seconds of `repeats` (the parsers alternate, so that a slow
    spell of the machine falls on both), and whether the two parsers restored the same dvc.lock in
    every repeat (compared within a repeat: a forced run adds run-cache entries whose timing files
    differ, and a later restore may take those)."""
    fastest: dict[str, dict[str, float]] = {command: {} for command in COMMANDS}
    identical = True

    def timed(command: str, parser: str) -> None:
        seconds = dvc(root, parser, *COMMANDS[command])
        fastest[command][parser] = min(seconds, fastest[command].get(parser, float("inf")))
        print(f"  {command:18s} {parser:4s} {seconds:6.2f} s", flush=True)

    for _ in range(repeats):
        locks = set()
        for parser in PARSERS:
            timed("status", parser)
            timed("repro_up_to_date", parser)
            (root / "dvc.lock").unlink()
            timed("repro_restored", parser)
            locks.add((root / "dvc.lock").read_bytes())
        identical &= len(locks) == 1
        for parser in PARSERS:
            timed("repro_forced", parser)
    return fastest, identical


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="the fastest of this many runs is reported")
    args = parser.parse_args()
    check_c_parser()
    measured_on = machine()
    with tempfile.TemporaryDirectory(prefix="dvc-yaml-") as folder:
        stages = make_workspace(Path(folder))
        print(f"{stages} stages (tools/small_runs.py DATA_PATH)")
        seconds, identical = measure(Path(folder), args.repeats)
    ratios = {command: by_parser["pure"] / by_parser["c"] for command, by_parser in seconds.items()}
    restored = seconds["repro_restored"]
    per_stage = {parser: restored[parser] / stages for parser in PARSERS}
    note = load_note(measured_on)
    headline = (
        f"with ruamel.yaml's C parser DVC restores {stages} stages from its run cache in {restored['c']:.2f} s "
        f"instead of {restored['pure']:.2f} s ({per_stage['c']:.2f} vs {per_stage['pure']:.2f} s a stage, "
        f"{ratios['repro_restored']:.2f}x); dvc status {ratios['status']:.2f}x, an up-to-date repro "
        f"{ratios['repro_up_to_date']:.2f}x, a forced repro of every stage {seconds['repro_forced']['c']:.1f} vs "
        f"{seconds['repro_forced']['pure']:.1f} s ({ratios['repro_forced']:.2f}x); restored dvc.lock identical: {identical}"
    )
    record = {
        "args": vars(args),
        "stages": stages,
        "seconds": seconds,
        "ratios": ratios,
        "restored_seconds_per_stage": per_stage,
        "identical_lock": identical,
        "load_note": note,
        "headline": headline,
    }
    save_and_report("bench_dvc_yaml", record, measured_on)
    if not identical:
        raise SystemExit("the restored dvc.lock differs between the two parsers")


# docs/write_tables.py's table of this benchmark's record: name -> (record, snapshot, how it is written)
TABLES = {"bench_dvc_yaml": ("benchmarks/results/bench_dvc_yaml.json", "bench_dvc_yaml.json", headline_table)}


if __name__ == "__main__":
    main()
