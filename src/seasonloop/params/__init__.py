"""params.yaml: its schema (schema, built from the value checks in checks), its typed sections
(settings), and the seasons and season pairs (seasons). Imports nothing else of seasonloop, so
every stage can check the whole file before any work at the cost of a YAML read.
"""
