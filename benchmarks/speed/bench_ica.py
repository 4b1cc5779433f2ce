"""Every ICA solver side by side on the same images, to the same stationarity measure.

    python -m benchmarks.speed.bench_ica [--sizes default full] [--full-max-iter 100] [--sweep-components 512 1024]

Sizes: "default" is the default run's scale (12,080 training images of 2,048 pixels, 128
components, ica.max_iter iterations at most); "full" the study's (16,000 images, all 2,048
components, --full-max-iter iterations at most: no solver reaches tol there in a benchmark's time,
so each gets the same iteration budget). Every solver (seasonloop.models.ica.ICA_SOLVERS, through
the pipeline's ICALearner) fits in its own process, so that its peak memory is its own, one after
the other. Each reports the relative gradient it reached (max |skew(diag(s) E[g(y) y^T])|, the
measure `converged` is defined on) and its own stopping test.

Every solver records a gradient trace (seconds since its fit began, whitening included, and the
gradient of each iterate; scikit-learn's through a wrapper of its loop, the measuring time
subtracted). A solver's time to a target gradient is when it gets there and stays below it for
good (a gradient that dips under and rises again does not count); ratios are read at the tightest
target that both solvers of a pair stay below, Picard against scikit-learn's FastICA and against
our torch FastICA, and a solver that never stays below a target is said to, without a ratio. At
the default size each solver also unmixes a synthetic mixture of 64 known Laplace sources: the
Amari distance to the true mixing (0 = recovered).

Writes benchmarks/results/bench_ica.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from benchmarks.common import load_note, save_and_report, timed, training_images, where_measured
from seasonloop.models.core.ica_stationarity import amari_distance, relative_gradient
from seasonloop.models.core.lookup import get_learner
from tools.records import machine
from tools.repository import learner_params

# (name, ica.solver, ica.precision): every solver, the torch ones in both precisions
SOLVERS = (
    ("sklearn", "sklearn", "float32"),
    ("fastica", "fastica", "float32"),
    ("picard", "picard", "float32"),
    ("picard_float64", "picard", "float64"),
    ("python_picard", "python_picard", "float64"),
)
# size -> (training images, components, whiten_solver): the default run's and presets/full.yaml's
SIZES = {"default": (12080, 128, "eigh"), "full": (16000, 2048, "svd")}
MIXTURE_SOURCES = 64


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", default=list(SIZES), choices=list(SIZES))
    parser.add_argument("--solvers", nargs="+", default=[name for name, _, _ in SOLVERS])
    parser.add_argument("--full-max-iter", type=int, default=100, help="every solver's iteration budget at full size")
    parser.add_argument(
        "--sweep-components",
        type=int,
        nargs="*",
        default=[],
        help="Picard alone at the full size with these components",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--child", nargs=2, metavar=("SETTINGS", "RESULT"), help=argparse.SUPPRESS)
    return parser.parse_args()


def traced_sklearn_fit(fit: Callable[[], dict], fun: str) -> tuple[dict, float, list[tuple[float, float]]]:
    """fit() of the sklearn solver with the gradient trace scikit-learn's FastICA does not keep:
    its parallel loop (_ica_par) calls _sym_decorrelation once per iteration on the new W (and
    once on the initial one), so a wrapper there records the gradient of W's sources. The time
    the measurement takes is subtracted from the trace and from the fit's seconds."""
    import sklearn.decomposition._fastica as fastica_module

    original_loop, original_decorrelation = fastica_module._ica_par, fastica_module._sym_decorrelation
    trace: list[tuple[float, float]] = []
    started, paused = time.perf_counter(), 0.0

    def loop(whitened: np.ndarray, *args: Any, **kwargs: Any) -> Any:
        def decorrelation(unmixing: np.ndarray) -> np.ndarray:
            nonlocal paused
            decorrelated = original_decorrelation(unmixing)
            measuring = time.perf_counter()
            trace.append((measuring - started - paused, relative_gradient((decorrelated @ whitened).T, fun)))
            paused += time.perf_counter() - measuring
            return decorrelated

        fastica_module._sym_decorrelation = decorrelation
        try:
            return original_loop(whitened, *args, **kwargs)
        finally:
            fastica_module._sym_decorrelation = original_decorrelation

    fastica_module._ica_par = loop
    try:
        record = fit()
    finally:
        fastica_module._ica_par = original_loop
    return record, time.perf_counter() - started - paused, trace


def fit_in_this_process(settings: dict) -> dict:
    """One solver's fit of settings["data"] (uint8 images or float mixtures, .npy) with the
    pipeline's ICALearner; its fit record, wall time, gradient trace (seconds since the fit began,
    whitening included; the gradient of each iterate) and this process's peak memory."""
    data = np.load(settings["data"])
    learner = get_learner("ica")(learner_params("ica", settings["params"]), seed=settings["seed"])
    images = data if data.ndim == 3 else data.reshape(len(data), 32, 64)
    if settings["params"]["solver"] == "sklearn":
        record, seconds, trace = traced_sklearn_fit(lambda: learner.fit(images), settings["params"]["fun"])
    else:
        (record, seconds), trace = timed(lambda: learner.fit(images)), learner.estimator.trace_
    result = {
        "seconds": seconds,
        "record": record,
        "trace": trace,
        "peak_rss_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
    }
    if settings.get("mixing"):
        result["amari"] = amari_distance(learner.estimator.components_, np.load(settings["mixing"]))
    return result


def fit_in_child(settings: dict, folder: Path) -> dict:
    """fit_in_this_process in a fresh Python process (its peak memory measured alone)."""
    settings_path, result_path = folder / "settings.json", folder / "result.json"
    settings_path.write_text(json.dumps(settings))
    subprocess.run(
        [sys.executable, "-m", __spec__.name, "--child", str(settings_path), str(result_path)],
        check=True,
        cwd=Path.cwd(),
    )
    return json.loads(result_path.read_text())


def time_to_stay_below(result: dict, target: float) -> float | None:
    """Seconds into the fit from which the solver's gradient stays at or below `target` for good:
    the time of the first traced iterate after the last one above it (None: its last iterate, or
    the stored model, is above it)."""
    if result["record"]["gradient"] > target or not result["trace"] or result["trace"][-1][1] > target:
        return None
    above = [i for i, (_, gradient) in enumerate(result["trace"]) if gradient > target]
    return result["trace"][above[-1] + 1 if above else 0][0]


def known_mixture(n_samples: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """MIXTURE_SOURCES Laplace sources mixed into 2048 "pixels" by a random matrix, plus 1% noise
    (float data in [0, 1]-like range is not needed: ICA centres and whitens)."""
    rng = np.random.default_rng(seed)
    mixing = rng.normal(size=(32 * 64, MIXTURE_SOURCES))
    data = rng.laplace(size=(n_samples, MIXTURE_SOURCES)) @ mixing.T + 0.01 * rng.normal(size=(n_samples, 32 * 64))
    return data.astype(np.float32), mixing


def run_size(size: str, args: argparse.Namespace, ica_params: dict, folder: Path) -> dict:
    n_samples, n_components, whiten_solver = SIZES[size]
    images, source = training_images(n_samples, args.seed)
    np.save(folder / "images.npy", images)
    max_iter = ica_params["max_iter"] if size == "default" else args.full_max_iter
    print(
        f"\n{size} size: {len(images)} x {images.shape[1] * images.shape[2]} images from {source}; "
        f"{n_components} components, whiten_solver {whiten_solver}, max_iter {max_iter}, tol {ica_params['tol']}"
    )
    mixture = None
    if size == "default":
        data, mixing = known_mixture(n_samples, args.seed)
        np.save(folder / "mixture.npy", data)
        np.save(folder / "mixing.npy", mixing)
        mixture = {"data": str(folder / "mixture.npy"), "mixing": str(folder / "mixing.npy")}
    results = {}
    for name, solver, precision in SOLVERS:
        if name not in args.solvers:
            continue
        params = {
            **ica_params,
            "solver": solver,
            "precision": precision,
            "n_components": n_components,
            "whiten_solver": whiten_solver,
            "max_iter": max_iter,
            "max_train_images": 0,
            "device": "cpu",
        }
        result = fit_in_child({"data": str(folder / "images.npy"), "params": params, "seed": args.seed}, folder)
        if mixture:
            known = fit_in_child(
                {**mixture, "params": {**params, "n_components": MIXTURE_SOURCES}, "seed": args.seed}, folder
            )
            result["amari_known_sources"] = known["amari"]
        record = result["record"]
        results[name] = result
        print(
            f"  {name:15s} {result['seconds']:8.1f} s, {record['n_iter']:5d} iterations, gradient "
            f"{record['gradient']:.2e} (converged {record['converged']}; own test {record['own_criterion']['name']} "
            f"met {record['own_criterion']['met']}), peak memory {result['peak_rss_bytes'] / 2**30:.2f} GiB"
            + (f", Amari on known sources {result['amari_known_sources']:.4f}" if mixture else "")
        )
    return {
        "data": source,
        "n_samples": len(images),
        "n_components": n_components,
        "max_iter": max_iter,
        "fits": results,
    }


# the gradients a solver's time is read at (ica.tol is added): a ratio is the time to reach one and
# stay below it, whitening included on both sides
TARGETS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6)


def targets(ica_params: dict) -> list[float]:
    return sorted({*TARGETS, float(ica_params["tol"])}, reverse=True)


def time_table(measured: dict, ica_params: dict) -> dict[str, dict[str, float | None]]:
    """solver -> target gradient (as text) -> seconds to stay below it (None: never)."""
    return {
        name: {f"{target:.0e}": time_to_stay_below(result, target) for target in targets(ica_params)}
        for name, result in measured["fits"].items()
    }


def compare(size: str, measured: dict, ica_params: dict) -> str:
    """Picard (float32) against each FastICA at the tightest gradient both stay below, as one line;
    a baseline that never stays below a gradient Picard reaches is said so, not given a ratio."""
    fits, table = measured["fits"], time_table(measured, ica_params)
    if "picard" not in fits:
        return f"{size}: picard not run"
    parts = []
    for baseline, label in (("sklearn", "scikit-learn's FastICA"), ("fastica", "our torch FastICA")):
        if baseline not in fits:
            continue
        ours, theirs = table["picard"], table[baseline]
        reached = [(key, seconds) for key, seconds in ours.items() if seconds is not None]
        only_picard = [key for key, _ in reached if theirs[key] is None]
        both = [(key, seconds, other) for key, seconds in reached if (other := theirs[key]) is not None]
        if both:
            key, seconds, other = both[-1]  # targets run from loose to tight
            parts.append(
                f"to stay below gradient {key}: Picard {seconds:.1f} s, {label} {other:.1f} s ({other / seconds:.1f}x)"
            )
        else:
            parts.append(f"{label} stays below none of the gradients Picard reaches")
        if only_picard:
            parts.append(
                f"{label} never stays below {only_picard[0]} in {fits[baseline]['record']['n_iter']} iterations "
                f"(Picard: {ours[only_picard[0]]:.1f} s)"
            )
    picard = fits["picard"]["record"]
    status = (
        f"Picard converged (gradient {picard['gradient']:.1e} < tol) in {fits['picard']['seconds']:.1f} s"
        if picard["converged"]
        else f"Picard not converged in {picard['n_iter']} iterations (gradient {picard['gradient']:.1e})"
    )
    return (
        f"{size} ({measured['n_samples']} x 2048, {measured['n_components']} components, whitening included): "
        f"{status}; " + "; ".join(parts)
    )


def sweep_components(args: argparse.Namespace, ica_params: dict, folder: Path) -> dict:
    """Picard (float32) at the full size's 16,000 images with fewer components, each to ica.tol
    within ica.max_iter: how far the full preset can keep a converged ICA (presets/full.yaml)."""
    n_samples, _, whiten_solver = SIZES["full"]
    images, source = training_images(n_samples, args.seed)
    np.save(folder / "images.npy", images)
    print(
        f"\ncomponents sweep: Picard float32 on {len(images)} images from {source}, max_iter {ica_params['max_iter']}"
    )
    results = {}
    for n_components in args.sweep_components:
        params = {
            **ica_params,
            "solver": "picard",
            "precision": "float32",
            "n_components": n_components,
            "whiten_solver": whiten_solver,
            "max_train_images": 0,
            "device": "cpu",
        }
        result = fit_in_child({"data": str(folder / "images.npy"), "params": params, "seed": args.seed}, folder)
        record = result["record"]
        print(
            f"  {n_components:5d} components: {result['seconds']:8.1f} s, {record['n_iter']:5d} iterations, "
            f"gradient {record['gradient']:.2e}, converged {record['converged']}, "
            f"peak memory {result['peak_rss_bytes'] / 2**30:.2f} GiB"
        )
        results[str(n_components)] = {key: value for key, value in result.items() if key != "trace"}
    return {"data": source, "n_samples": len(images), "fits": results}


def main() -> None:
    args = parse_args()
    if args.child:
        settings = json.loads(Path(args.child[0]).read_text())
        Path(args.child[1]).write_text(json.dumps(fit_in_this_process(settings)))
        return
    measured_on = machine()
    ica_params = yaml.safe_load(Path("params.yaml").read_text())["ica"]
    print(f"machine: {measured_on['cpu']}, {measured_on['torch_threads']} torch threads; ica params of params.yaml")
    started = time.perf_counter()
    sizes = {}
    with tempfile.TemporaryDirectory() as folder:
        for size in args.sizes:
            sizes[size] = run_size(size, args, ica_params, Path(folder))
        sweep = sweep_components(args, ica_params, Path(folder)) if args.sweep_components else None
    lines = [compare(size, measured, ica_params) for size, measured in sizes.items()]
    for measured in sizes.values():
        measured["seconds_to_stay_below"] = time_table(measured, ica_params)
    for line in lines:
        print(line)
    note = load_note(measured_on)
    record = {
        "args": {key: value for key, value in vars(args).items() if key != "child"},
        "ica_params": ica_params,
        "sizes": sizes,
        "components_sweep": sweep,
        "seconds": time.perf_counter() - started,
        "load_note": note,
        "headline": " | ".join(lines),
    }
    save_and_report("bench_ica", record, measured_on)


def _bench_ica(path: Path) -> str:
    """benchmarks/speed/bench_ica.py's record: one row per size and solver (and per components of the
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
    return "\n".join(lines) + "\n\n" + _bench_ica_times(record) + ratios + "\n\n" + where_measured(record) + "\n"


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


# docs/write_tables.py's table of this benchmark's record: name -> (record, snapshot, how it is written)
TABLES = {"bench_ica": ("benchmarks/results/bench_ica.json", "bench_ica.json", _bench_ica)}


if __name__ == "__main__":
    main()
