"""Our torch FastICA vs scikit-learn's, side by side on the same data: fit time and quality.

Quality: Amari distance on a synthetic mixture of known Laplace sources, and the fraction of
correct best matches each model's descriptors give on one test pair.

    python benchmarks/bench_ica.py [--n-samples 8000] [--n-components 256] [--pair summer-fall]

Writes benchmarks/results/bench_ica.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse

import numpy as np
import torch

from _common import load_note, machine, pair_images, timed, training_images, write_result
from seasonloop.evaluation.matching import distance_matrix
from seasonloop.evaluation.metrics import evaluate_pair
from seasonloop.models.core.fastica import TorchFastICA, amari_distance
from seasonloop.models.core.learner import to_float
from seasonloop.models.ica import fit_fastica
from seasonloop.params.schema import parse_pair


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-samples", type=int, default=8000, help="training images (2048 pixels each)")
    parser.add_argument("--n-components", type=int, default=256)
    parser.add_argument("--max-iter", type=int, default=400)
    parser.add_argument("--tol", type=float, default=1e-4)
    parser.add_argument("--whiten-solver", default="eigh", choices=("eigh", "svd"))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--pair", default="summer-fall", help="test pair database-query for the fraction correct")
    parser.add_argument("--metric", default="cosine", choices=("cosine", "euclidean", "cityblock"))
    parser.add_argument("--amari-sources", type=int, default=64, help="known sources in the synthetic mixture")
    return parser.parse_args()


def fit_both(data: np.ndarray, n_components: int, args: argparse.Namespace) -> dict:
    """Fit scikit-learn's and our FastICA (CPU, and CUDA when present) on the same data."""
    settings = dict(n_components=n_components, max_iter=args.max_iter, tol=args.tol, seed=args.seed)
    (sklearn_model, sklearn_record), sklearn_seconds = timed(
        lambda: fit_fastica(data, whiten_solver=args.whiten_solver, **settings)
    )
    ours, ours_seconds = timed(
        lambda: TorchFastICA(whiten_solver=args.whiten_solver, device="cpu", **settings).fit(data)
    )
    fits = {
        "sklearn": {
            "model": sklearn_model,
            "seconds": sklearn_seconds,
            "n_iter": sklearn_record["n_iter"],
            "converged": sklearn_record["converged"],
        },
        "torch_cpu": {"model": ours, "seconds": ours_seconds, "n_iter": ours.n_iter_, "converged": ours.converged_},
    }
    if torch.cuda.is_available():
        TorchFastICA(whiten_solver=args.whiten_solver, device="cuda", **settings).fit(data[:1000])  # warm-up
        torch.cuda.synchronize()
        gpu, gpu_seconds = timed(
            lambda: TorchFastICA(whiten_solver=args.whiten_solver, device="cuda", **settings).fit(data)
        )
        fits["torch_cuda"] = {"model": gpu, "seconds": gpu_seconds, "n_iter": gpu.n_iter_, "converged": gpu.converged_}
    return fits


def synthetic_mixture(n_samples: int, n_sources: int, n_features: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Laplace sources mixed by a random (n_features, n_sources) matrix, plus 1% noise."""
    rng = np.random.default_rng(seed)
    mixing = rng.normal(size=(n_features, n_sources))
    data = rng.laplace(size=(n_samples, n_sources)) @ mixing.T + 0.01 * rng.normal(size=(n_samples, n_features))
    return data.astype(np.float32), mixing


def main() -> None:
    args = parse_args()
    measured_on = machine()
    database, query = parse_pair(args.pair)
    images, source = training_images(args.n_samples, args.seed)
    data = to_float(images).reshape(len(images), -1)
    print(f"training data: {data.shape[0]} x {data.shape[1]} float32 from {source}")
    print(
        f"FastICA: n_components {args.n_components}, max_iter {args.max_iter}, tol {args.tol}, "
        f"whiten_solver {args.whiten_solver}, parallel, logcosh; torch threads {torch.get_num_threads()}"
    )
    if not torch.cuda.is_available():
        print("CUDA not available: torch timed on the CPU only")

    fits = fit_both(data, args.n_components, args)
    sklearn_seconds = fits["sklearn"]["seconds"]
    for name, fit in fits.items():
        print(
            f"  fit {name:9s}: {fit['seconds']:8.2f} s, {fit['n_iter']:4d} iterations, converged {fit['converged']}, "
            f"speed-up vs sklearn {sklearn_seconds / fit['seconds']:.2f}x"
        )

    # The same pair, described by each model.
    database_images, query_images, places, pair_source = pair_images(database, query, args.seed)
    quality = {}
    for name, fit in fits.items():
        describe = lambda batch: fit["model"].transform(to_float(batch).reshape(len(batch), -1))  # noqa: E731, B023 (called at once)
        distances = distance_matrix(describe(database_images), describe(query_images), args.metric)
        metrics, _ = evaluate_pair(distances, places, places, tolerance=0)
        quality[name] = {key: metrics[key] for key in ("fraction_correct", "auc_pr", "recall_at_100_precision")}
        print(
            f"  {args.pair} ({len(places)} places, {pair_source}) {name:9s}: fraction correct "
            f"{metrics['fraction_correct']:.4f}, AUC-PR {metrics['auc_pr']:.4f}"
        )
    # Ours vs scikit-learn's unmixing: 0 when one is a scaled permutation of the other.
    cross_amari = amari_distance(fits["torch_cpu"]["model"].components_, fits["sklearn"]["model"].mixing_)
    print(f"  Amari distance between the torch and sklearn unmixing on these images: {cross_amari:.4f}")

    mixture, mixing = synthetic_mixture(args.n_samples, args.amari_sources, data.shape[1], args.seed)
    mixture_fits = fit_both(mixture, args.amari_sources, args)
    amari = {name: amari_distance(fit["model"].components_, mixing) for name, fit in mixture_fits.items()}
    for name, fit in mixture_fits.items():
        print(
            f"  known sources ({args.n_samples} x {data.shape[1]}, {args.amari_sources} Laplace sources) {name:9s}: "
            f"Amari distance {amari[name]:.4f}, {fit['seconds']:.2f} s, {fit['n_iter']} iterations"
        )

    speedup = sklearn_seconds / fits["torch_cpu"]["seconds"]
    # A speed ratio means something only when both stopped for the same reason: tol reached.
    equal_convergence = fits["sklearn"]["converged"] and fits["torch_cpu"]["converged"]
    convergence = (
        f"both converged to tol {args.tol} (sklearn {fits['sklearn']['n_iter']}, torch "
        f"{fits['torch_cpu']['n_iter']} iterations)"
        if equal_convergence
        else f"NOT at equal convergence: sklearn converged {fits['sklearn']['converged']} in {fits['sklearn']['n_iter']}, "
        f"torch converged {fits['torch_cpu']['converged']} in {fits['torch_cpu']['n_iter']} iterations"
    )
    print(f"  convergence: {convergence}")
    note = load_note(measured_on)
    record = {
        "args": vars(args),
        "data": source,
        "pair_data": pair_source,
        "fit": {name: {key: value for key, value in fit.items() if key != "model"} for name, fit in fits.items()},
        "speedup_cpu": speedup,
        "equal_convergence": equal_convergence,
        "quality": quality,
        "amari_torch_vs_sklearn": cross_amari,
        "amari_known_sources": amari,
        "mixture_fit_seconds": {name: fit["seconds"] for name, fit in mixture_fits.items()},
        "load_note": note,
    }
    record["headline"] = (
        f"torch FastICA fit {speedup:.1f}x faster than scikit-learn on the CPU "
        f"({fits['torch_cpu']['seconds']:.1f} s vs {sklearn_seconds:.1f} s, {data.shape[0]} x {data.shape[1]}, "
        f"{args.n_components} components, {torch.get_num_threads()} threads; {convergence}); fraction correct {args.pair} "
        f"{quality['torch_cpu']['fraction_correct']:.4f} vs {quality['sklearn']['fraction_correct']:.4f}; "
        f"Amari on known sources {amari['torch_cpu']:.4f} vs {amari['sklearn']:.4f}"
    )
    path = write_result("bench_ica", record, measured_on)
    print(f"wrote {path}")
    if note:
        print(note)
    if "torch_cuda" in fits:
        print(f"torch FastICA on CUDA: {sklearn_seconds / fits['torch_cuda']['seconds']:.1f}x faster than sklearn")
    print(f"HEADLINE: {record['headline']}")


if __name__ == "__main__":
    main()
