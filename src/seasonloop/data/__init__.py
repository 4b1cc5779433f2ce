"""Route data: the built-in synthetic route and readers for real videos or frame folders."""
