"""Ablations that refit learners and evaluate them again: the training-season effect
(training_seasons, the study's Figure 18) and the CAE at fractions of Table 5's width (cae_widths).
The top of the house: may import every other package.
"""
