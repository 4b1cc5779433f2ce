"""Cross-machine checks: the same params give the same bytes on other CPUs' kernels, or how far they
move (docs/pipeline.md: same params, same bytes)."""
