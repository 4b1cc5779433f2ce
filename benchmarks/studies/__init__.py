"""Method studies: the statistics' real coverage and error rates on simulated routes
(docs/statistics.md), SeqSLAM's contrast window at breaks (docs/pipeline.md)."""
