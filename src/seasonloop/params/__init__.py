"""params.yaml: its typed sections (settings, each key with its check from checks; what a section
is: section), their checks (schema; across sections: across) and the seasons and season pairs
(seasons). Imports nothing else of seasonloop: what names a registry entry is checked above the
registries (seasonloop.registries).
"""
