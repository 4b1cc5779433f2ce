"""Route data, from videos to the training and test sets: the synthetic renderer (synthetic/), real
videos and frame folders (sources, frames, extract), preprocessing (preprocess, alignment,
patchnorm), the geographic split (split) and augmentation (augment), and how the split and
augmented sets are stored (datasets). May import seasonloop.params, io and machine only.
"""
