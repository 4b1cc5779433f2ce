"""What the learners share: the FeatureLearner interface (learner), principal components
(projection), FastICA (fastica), the torch learners (torch_learner) with the auto-encoders'
(autoencoder_learner, autoencoder_training) and the place-supervised network's training
(place_training), the stopping rule they share (training) and their arithmetic (arithmetic). A
change here reruns every learner's fit; a change to one learner's own module reruns only that
learner.
"""
