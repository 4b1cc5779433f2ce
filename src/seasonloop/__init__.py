"""seasonloop: a reproducible study of cross-season loop-closure detection (visual place recognition).

The library knows nothing of DVC; the stage scripts in stages/ bind it to params.yaml and the
pipeline's folders. It is a handful of packages, each importing only those below it
(tests/test_architecture.py checks the direction):

    ablations    studies that refit learners and evaluate them again (training seasons, CAE width)
    reporting    tables, figures, dvc plots files and the HTML report, from evaluation results
    evaluation   matching (distances, SeqSLAM sequences), metrics (fraction correct, PR curves)
    models       the feature learners: one module each, the registry, and their shared core/
    data         route data: the synthetic renderer, real videos and frames, preprocessing,
                 the geographic split and augmentation, and how the split sets are stored
    params       the schema of params.yaml, its typed sections, seasons and pairs

and three foundation modules every package may use, importing nothing of seasonloop: io (atomic
files, arrays, JSON), plots (matplotlib figures from arrays) and machine (the CPU's name).
"""

__version__ = "0.1.0"
