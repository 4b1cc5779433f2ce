"""The feature learners: one module per learner (its name is its params section), listed by
core/lookup.py (LEARNERS) and imported only when asked for; what several learners share (the FeatureLearner
interface, the PCA projection, FastICA, the torch auto-encoder and its training loop) is in core/.
May import seasonloop.data (patch normalisation), params, io and machine.
"""
