"""The repository's own commands and helpers, beside the library (src/seasonloop knows nothing of
git or DVC; these drive both): copies of the repository and its small configurations for runs that
start from nothing (repository.py, small_runs.py), what a measured record says about where it was
measured (records.py), and the command that runs the pipeline on more synthetic routes:

    python -m tools.replicate_routes run --seeds 1 2 3 4
"""

import sys
from pathlib import Path

# The commands run the library of their own checkout, whose commit their records name: not whichever
# checkout pip installed in editable mode (stages/_common.py does the same for the stages).
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
