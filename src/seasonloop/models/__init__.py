"""Feature learners; see registry.py."""
