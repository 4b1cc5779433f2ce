"""seasonloop: cross-season loop-closure detection study."""

__version__ = "0.1.0"
