"""seasonloop: a reproducible study of cross-season loop-closure detection (visual place recognition).

The library knows nothing of DVC; the stage scripts in stages/ bind it to params.yaml and the
pipeline's folders. PACKAGES are its packages, highest first: each imports only those after it
(tests/test_architecture.py checks the direction); FOUNDATION its top-level modules, which import
nothing of seasonloop and which every package may use.
"""

__version__ = "0.1.0"

# package -> what it owns, highest first
PACKAGES = {
    "registries": "params.yaml checked whole against the library's registries: which keys choose among which names",
    "ablations": "studies that refit learners: the training-season effect, the CAE's width",
    "reporting": "summary tables beside the study's numbers, dvc plots files, the study's figures, the HTML report",
    "evaluation": "distances and best matches, SeqSLAM sequences, sequence descriptors, fraction correct, PR curves",
    "significance": "intervals along the route, paired tests and Holm's correction over a table",
    "models": "the learners, one module each (core/lookup.py finds one by its name), and their shared core/",
    "data": "the synthetic renderer, real videos and frames, preprocessing, ground truth, the split, augmentation",
    "params": "params.yaml's sections, each key declared once with its check, seasons and pairs",
}
# top-level module -> what it holds
FOUNDATION = {
    "io": "atomic files, arrays, JSON",
    "plots": "matplotlib figures from arrays",
    "machine": "the CPU's name",
    "preset": "a params.yaml with a preset's values (python -m seasonloop.preset NAME)",
}
