"""What the learners share: the FeatureLearner interface (learner), principal components
(projection), FastICA (fastica), the torch auto-encoder learner (torch_learner), its training
loop (training) and arithmetic (arithmetic). A change here reruns every learner's fit; a change to one learner's own module
reruns only that learner.
"""
