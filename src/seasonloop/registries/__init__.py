"""params.yaml checked whole against the library's registries (choices)."""
