"""Measurements beside the pipeline, run from the repository root as modules, each writing its
record to benchmarks/results/ and printing its headline (docs/benchmarks.md):

- speed/: how fast (and with how much memory) the pipeline and its parts run, at equal quality;
- machines/: whether results stay the same on other CPUs and their kernels;
- studies/: method studies that decide a design (the statistics' real error rates, SeqSLAM's
  window at breaks).
"""

import tools  # noqa: F401  (this checkout's library first, as its records say: see tools/__init__.py)
