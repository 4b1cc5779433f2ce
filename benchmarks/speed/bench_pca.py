"""The pca learner as configured (params.yaml pca section, svd_solver covariance_eigh by default) vs
scikit-learn's PCA with other solvers, side by side on one full-scale-shaped training matrix.

Agreement: principal angles between the kept subspaces (components n_discard .. n_discard+n_keep)
of each solver and of the exact reference ("full" LAPACK SVD when it is timed, else the first
exact solver listed).

    python -m benchmarks.speed.bench_pca [--n-samples 128000] [--solvers full covariance_eigh auto]

Writes benchmarks/results/bench_pca.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse

import numpy as np
import yaml
from scipy.linalg import subspace_angles
from sklearn.decomposition import PCA

from benchmarks.common import headline_table, load_note, save_and_report, timed, training_images
from seasonloop.models.core.learner import to_float
from seasonloop.models.core.projection import SVD_SOLVERS
from seasonloop.models.pca import PCALearner
from tools.records import machine

EXACT_SOLVERS = ("full", "covariance_eigh")


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-samples", type=int, default=128000, help="training images (2048 pixels each)")
    parser.add_argument(
        "--solvers",
        nargs="+",
        default=["full", "covariance_eigh", "auto"],
        choices=[solver for solver in SVD_SOLVERS if solver != "arpack"],
        help="scikit-learn svd_solver values to time beside the learner",
    )
    parser.add_argument("--params", default="params.yaml", help="where the pca learner's section is read")
    parser.add_argument("--repeats", type=int, default=2, help="fits per solver; the fastest counts")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def kept_components(components: np.ndarray, n_discard: int) -> np.ndarray:
    """(n_keep, D) float64 rows of the kept components."""
    return np.asarray(components[n_discard:], dtype=np.float64)


def agreement(ours: np.ndarray, reference: np.ndarray) -> dict[str, float]:
    """Largest principal angle (degrees) between the row spaces, and the per-component |cosine|."""
    angles = np.degrees(subspace_angles(ours.T, reference.T))
    cosines = np.abs(np.einsum("ij,ij->i", ours, reference)) / (
        np.linalg.norm(ours, axis=1) * np.linalg.norm(reference, axis=1)
    )
    return {
        "max_principal_angle_deg": float(angles.max()),
        "median_principal_angle_deg": float(np.median(angles)),
        "min_component_abs_cosine": float(cosines.min()),
        "median_component_abs_cosine": float(np.median(cosines)),
    }


def main() -> None:
    args = parse_args()
    measured_on = machine()
    with open(args.params) as handle:
        pca_params = yaml.safe_load(handle)["pca"]
    learner = PCALearner(pca_params, seed=args.seed)
    n_discard, n_keep = learner.params["n_discard"], learner.params["n_keep"]
    images, source = training_images(args.n_samples, args.seed)
    print(f"training data: {images.shape[0]} x {images.shape[1] * images.shape[2]} (float32 in the fit) from {source}")
    print(f"pca learner from {args.params}: {learner.params}; components kept {n_discard}..{n_discard + n_keep}")

    def fit(name: str) -> tuple[np.ndarray, dict | None]:
        """Fit `name` ("ours" or a scikit-learn svd_solver) on the images: (components, learner fit info).
        The uint8 -> float32 conversion the learner does is part of every fit."""
        if name == "ours":
            learner = PCALearner(pca_params, seed=args.seed)
            info = learner.fit(images, progress=False)
            return learner.estimator.components_, info
        model = PCA(n_components=n_discard + n_keep, svd_solver=name, random_state=args.seed)
        model.fit(to_float(images).reshape(len(images), -1))
        resolved[name] = model._fit_svd_solver
        return model.components_, None

    # Rounds in alternating order, fastest run of each counts: the first touch of fresh memory
    # (slow on a VM especially) would otherwise penalise whichever fit comes first.
    names = ["ours", *args.solvers]
    seconds: dict[str, list[float]] = {name: [] for name in names}
    components, resolved, info = {}, {}, None
    for round_index in range(args.repeats):
        for name in names if round_index % 2 == 0 else reversed(names):
            (components[name], fit_info), elapsed = timed(lambda: fit(name))  # noqa: B023 (called at once)
            seconds[name].append(elapsed)
            info = fit_info or info
    fastest = {name: min(values) for name, values in seconds.items()}
    ours_seconds = fastest["ours"]
    ours = kept_components(components["ours"], n_discard)
    print(
        f"  ours (learner, svd_solver {learner.params['svd_solver']}): {ours_seconds:8.2f} s "
        f"(runs: {', '.join(f'{value:.2f}' for value in seconds['ours'])})"
    )
    results = {}
    for solver in args.solvers:
        results[solver] = {
            "seconds": fastest[solver],
            "runs_seconds": seconds[solver],
            "resolved_solver": resolved[solver],
            "components": kept_components(components[solver], n_discard),
        }
        print(
            f"  sklearn svd_solver {solver:15s} (runs {resolved[solver]}): {fastest[solver]:8.2f} s "
            f"(runs: {', '.join(f'{value:.2f}' for value in seconds[solver])}), "
            f"ours is {fastest[solver] / ours_seconds:.2f}x faster"
        )

    exact = [solver for solver in EXACT_SOLVERS if solver in results]
    reference_name = exact[0] if exact else None
    agreements = {}
    if reference_name is None:
        print("no exact solver (full, covariance_eigh) timed: agreement not measured")
    else:
        reference = results[reference_name]["components"]
        candidates = {
            "ours": ours,
            **{name: result["components"] for name, result in results.items() if name != reference_name},
        }
        for name, components in candidates.items():
            agreements[name] = agreement(components, reference)
            figures = agreements[name]
            print(
                f"  kept subspace, {name} vs {reference_name}: max principal angle "
                f"{figures['max_principal_angle_deg']:.3f} deg (median {figures['median_principal_angle_deg']:.3f}), "
                f"component |cos| min {figures['min_component_abs_cosine']:.4f} "
                f"median {figures['median_component_abs_cosine']:.4f}"
            )

    note = load_note(measured_on)
    record = {
        "args": vars(args),
        "data": source,
        "learner_params": learner.params,
        "ours_seconds": ours_seconds,
        "ours_runs_seconds": seconds["ours"],
        "explained_variance_ratio_kept": info["explained_variance_ratio_kept"],
        "sklearn": {
            name: {key: value for key, value in result.items() if key != "components"}
            for name, result in results.items()
        },
        "speedup": {name: result["seconds"] / ours_seconds for name, result in results.items()},
        "agreement_reference": reference_name,
        "agreement": agreements,
        "load_note": note,
    }
    baseline = "full" if "full" in results else args.solvers[0]
    headline = (
        f"pca learner (svd_solver {learner.params['svd_solver']}) {ours_seconds:.1f} s vs sklearn "
        f"svd_solver {baseline} {results[baseline]['seconds']:.1f} s ({results[baseline]['seconds'] / ours_seconds:.1f}x) "
        f"on {images.shape[0]} x {images.shape[1] * images.shape[2]}"
    )
    if "ours" in agreements:
        headline += (
            f"; kept components {n_discard}-{n_discard + n_keep} vs {reference_name}: max principal angle "
            f"{agreements['ours']['max_principal_angle_deg']:.2f} deg"
        )
    record["headline"] = headline
    save_and_report("bench_pca", record, measured_on)


# docs/write_tables.py's table of this benchmark's record: name -> (record, snapshot, how it is written)
TABLES = {"bench_pca": ("benchmarks/results/bench_pca.json", "bench_pca.json", headline_table)}


if __name__ == "__main__":
    main()
