"""Place recognition from descriptors: distances and best matches (distances), SeqSLAM sequence
matching (sequence), fraction correct, PR curves and recall (metrics), the registry of matchers
(matchers) and evaluating one learner on every pair (learner_evaluation). May import seasonloop.params,
io and plots; never models (it sees descriptors only) or reporting.
"""
