"""Which physics settings two configs differ in: the one comparison of stored results
with the config that asks for them (gallery runs, the points that sweeps share)."""

from __future__ import annotations

from collections.abc import Collection, Iterator, Mapping
from typing import Any

from .schema import RotorConfig


def _leaves(data: Mapping[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    """(dotted key, value) of every leaf of a nested mapping."""
    for key, value in data.items():
        if isinstance(value, Mapping):
            yield from _leaves(value, f"{prefix}{key}.")
        else:
            yield f"{prefix}{key}", value


def physics_differences(
    config: RotorConfig, other: RotorConfig, ignore: Collection[str] = ()
) -> dict[str, tuple[Any, Any]]:
    """The settings of :meth:`RotorConfig.physics` in which `config` and `other` differ.

    Args:
        config: one config.
        other: the config it is compared with.
        ignore: dotted keys (``protocol.t_stop``) left out of the comparison.

    Returns:
        Dotted key -> (value in `config`, value in `other`), sorted by key; empty where
        the two give the same result.
    """
    mine, theirs = (dict(_leaves(c.physics())) for c in (config, other))
    keys = sorted((mine.keys() | theirs.keys()) - set(ignore))
    return {k: (mine.get(k), theirs.get(k)) for k in keys if mine.get(k) != theirs.get(k)}
