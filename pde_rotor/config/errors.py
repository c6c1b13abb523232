"""The two errors of configuration input, both one readable line."""

from __future__ import annotations

from typing import Any


class FieldError(ValueError):
    """A cross-field check failed; carries the key path it is about.

    Attributes:
        path: dotted key path relative to the model that raised it (e.g. ``pill_radius``
            inside ``geometry``, or ``grid.dx`` at the top level).
        value: the offending value.
    """

    def __init__(self, path: str, value: Any, message: str):
        super().__init__(message)
        self.path = path
        self.value = value

    def __reduce__(self) -> tuple[type[FieldError], tuple[str, Any, str]]:
        """Pickle with all three arguments (a worker process sends its errors back)."""
        return type(self), (self.path, self.value, str(self))


class ConfigError(ValueError):
    """Invalid configuration input; ``str(err)`` is one readable line."""
