"""The one version of the package (read by pyproject.toml, the CLI and the run records)."""

__version__ = "0.1.0"
