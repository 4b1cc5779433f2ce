"""Speed and memory: the default and full runs stage by stage, the learners, matching, DVC's own
work, and how they scale (docs/benchmarks.md)."""
