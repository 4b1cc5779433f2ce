"""The study's four seasons, in the Nordland dataset's order: the one list every module uses."""

SEASONS: tuple[str, ...] = ("summer", "spring", "fall", "winter")
