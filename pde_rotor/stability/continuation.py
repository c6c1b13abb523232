"""Eigenvalues along a config key: the branch, its critical value and the kind of onset.

:func:`follow` computes the leading eigenvalues of the linearisation at each value of one
config key (any dotted key, ``rotor.friction``, ``bodies[0].motion.friction``,
``geometry.radius``, ...; the config is rebuilt and validated at each value, so the rest
state and every block follow it). An index ``[*]`` sets the key in every entry of its list
at once (:func:`expand_key`): ``bodies[*].motion.friction`` follows a crowd of identical
bodies in their common friction. Where the largest real part changes sign between two
values, :func:`critical_value` finds the crossing by Brent's method (scipy ``brentq``) to
a stated relative tolerance in the key; the leading eigenvalue there says the kind of
onset: real, a pitchfork (the body starts to move one way or the other: a rotor to turn,
a disk to translate); a complex pair, a Hopf bifurcation with frequency Im lambda.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from ..config import ConfigError, RotorConfig, set_key, validate_config
from .eigen import Spectrum, is_real, leading_modes
from .linear import linearise
from .system import DiscreteModel

CRITICAL_RTOL = 1e-6
"""Default relative tolerance of the critical value (brentq's xtol / |value|)."""


@dataclass(frozen=True)
class Crossing:
    """Where the leading eigenvalue's real part crosses 0.

    Attributes:
        value: the key's critical value.
        tolerance: the bracket's width at the end (brentq's xtol).
        eigenvalue: the leading eigenvalue there (real part ~0).
        kind: ``pitchfork`` (real) or ``hopf`` (complex pair).
        frequency: |Im lambda| (0 for a pitchfork).
        direction: ``stabilising`` (Re lambda falls as the key grows) or ``destabilising``.
    """

    value: float
    tolerance: float
    eigenvalue: complex
    kind: str
    frequency: float
    direction: str


@dataclass
class Branch:
    """The leading eigenvalues along a key.

    Attributes:
        key: the config key.
        values: (N,) its values.
        eigenvalues: (N, k) at each value, by decreasing real part.
        residuals: (N, k) their residuals.
        crossings: every crossing between two neighbouring values.
    """

    key: str
    values: np.ndarray
    eigenvalues: np.ndarray
    residuals: np.ndarray
    crossings: list[Crossing] = field(default_factory=list)

    @property
    def leading(self) -> np.ndarray:
        """(N,) the leading eigenvalue at each value."""
        return self.eigenvalues[:, 0]

    def to_dataset(self, config: RotorConfig | None = None) -> xr.Dataset:
        """The branch as an xarray Dataset (NetCDF-ready): eigenvalues' real and
        imaginary parts and residuals on (value, mode), crossings as attributes."""
        coords = {"value": self.values, "mode": np.arange(self.eigenvalues.shape[1])}
        dims = ("value", "mode")
        attrs: dict[str, Any] = {"key": self.key, "crossings": len(self.crossings)}
        for i, cross in enumerate(self.crossings):
            attrs.update(
                {
                    f"critical_value_{i}": cross.value,
                    f"critical_tolerance_{i}": cross.tolerance,
                    f"critical_kind_{i}": cross.kind,
                    f"critical_frequency_{i}": cross.frequency,
                    f"critical_direction_{i}": cross.direction,
                }
            )
        if config is not None:
            attrs["config"] = json.dumps(config.model_dump(mode="json"))
        return xr.Dataset(
            {
                "growth_rate": (dims, self.eigenvalues.real),
                "frequency": (dims, self.eigenvalues.imag),
                "residual": (dims, self.residuals),
            },
            coords=coords,
            attrs=attrs,
        )


WILDCARD = "[*]"
"""The index of a key that stands for every entry of its list."""


def _entries(data: Mapping[str, Any], path: str, key: str) -> int:
    """The length of the list at the dotted `path` of `data` (`key`: the whole key, for
    the message)."""
    node: Any = data
    for part in path.split("."):
        name, _, index = part.partition("[")
        node = node.get(name) if isinstance(node, Mapping) else None
        if index and isinstance(node, list) and int(index.rstrip("]")) < len(node):
            node = node[int(index.rstrip("]"))]
        elif index:
            node = None
    if not isinstance(node, list) or not node:
        msg = (
            f"--param {key}: {path} is not a list with entries in the config (allowed: "
            f"{WILDCARD} after a list, e.g. bodies[*].motion.friction)"
        )
        raise ConfigError(msg)
    return len(node)


def expand_key(data: Mapping[str, Any], key: str) -> list[str]:
    """The keys a dotted `key` stands for in `data`: itself, or with each ``[*]`` replaced by
    every index of its list (``bodies[*].motion.friction`` -> ``bodies[0].motion.friction``,
    ``bodies[1]...``).

    Raises:
        ConfigError: a ``[*]`` after something that is not a list with entries (one line).
    """
    head, star, tail = key.partition(WILDCARD)
    if not star:
        return [key]
    count = _entries(data, head, key)
    out = []
    for i in range(count):
        out.extend(expand_key(data, f"{head}[{i}]{tail}"))
    return out


def config_at(data: Mapping[str, Any], key: str, value: float) -> RotorConfig:
    """The config `data` with `key` set to `value` (every key it stands for,
    :func:`expand_key`), validated.

    Raises:
        ConfigError: one line naming the key (unknown, not a number, out of range).
    """
    copy = json.loads(json.dumps(dict(data)))
    try:
        for each in expand_key(copy, key):
            set_key(copy, each, value)
    except ConfigError as err:
        msg = f"--param {key} = {value:g}: {err}".replace(f"--param {key}: ", "")
        raise ConfigError(msg) from None
    try:
        config = validate_config(copy)
    except ConfigError as err:
        msg = f"--param {key} = {value:g}: {err}"
        raise ConfigError(msg) from None
    return config


def spectrum_at(
    data: Mapping[str, Any], key: str, value: float, k: int = 4, positions: bool | None = None
) -> Spectrum:
    """The k leading eigenvalues of the config `data` with `key` = `value`, of at least two
    more than the bodies' unknowns computed, so that every root of the bodies is among
    them (the Arnoldi returns those nearest the shift, and with many bodies -- 8 boats on
    a track, 15 unknowns -- the one that crosses first can lie farther from it than k
    others)."""
    lin = linearise(DiscreteModel(config_at(data, key, value)), positions=positions)
    found = leading_modes(lin, k=max(k, lin.small.shape[0] + 2))
    return replace(
        found,
        eigenvalues=found.eigenvalues[:k],
        vectors=found.vectors[:, :k],
        residuals=found.residuals[:k],
    )


def critical_value(
    data: Mapping[str, Any],
    key: str,
    lo: float,
    hi: float,
    rtol: float = CRITICAL_RTOL,
    k: int = 4,
    positions: bool | None = None,
    known: Mapping[float, Spectrum] | None = None,
) -> Crossing:
    """The value of `key` in [lo, hi] where the leading eigenvalue's real part is 0.

    Args:
        data: the config as a mapping.
        key: the dotted key.
        lo: one end of a bracket: Re lambda has opposite signs at its ends.
        hi: the other end.
        rtol: relative tolerance of the value.
        k: eigenvalues kept per evaluation (computed: at least the bodies' unknowns + 2).
        positions: as for :func:`~pde_rotor.stability.linear.linearise`.
        known: spectra already computed, by value (a branch's ends: not computed again).

    Raises:
        ValueError: Re lambda has the same sign at both ends.
    """
    spectra: dict[float, Spectrum] = dict(known or {})

    def growth(value: float) -> float:
        if value not in spectra:
            spectra[value] = spectrum_at(data, key, value, k, positions)
        return spectra[value].leading.real

    xtol = rtol * max(abs(lo), abs(hi))
    g_lo = growth(lo)
    root = brentq(growth, lo, hi, xtol=xtol)
    at_root = spectra[root] if root in spectra else spectrum_at(data, key, root, k, positions)
    lam = at_root.leading
    real = is_real(lam)
    rising = (g_lo < 0) == (lo < hi)
    return Crossing(
        value=float(root),
        tolerance=xtol,
        eigenvalue=complex(lam),
        kind="pitchfork" if real else "hopf",
        frequency=0.0 if real else abs(lam.imag),
        direction="destabilising" if rising else "stabilising",
    )


def follow(
    data: Mapping[str, Any],
    key: str,
    values: Sequence[float],
    k: int = 4,
    positions: bool | None = None,
    rtol: float = CRITICAL_RTOL,
    progress: Callable[[Any], Any] | None = None,
) -> Branch:
    """The leading eigenvalues at each of `values` of `key`, and every crossing of 0.

    Args:
        data: the config as a mapping (a YAML file's contents).
        key: the dotted key.
        values: its values (at least 2, all valid: checked before any compute).
        k: eigenvalues kept per value (computed: at least the bodies' unknowns + 2).
        positions: as for :func:`~pde_rotor.stability.linear.linearise`.
        rtol: relative tolerance of each critical value.
        progress: wraps the iterable of values (e.g. ``tqdm``).

    Raises:
        ConfigError: a value the config refuses (one line), or fewer than 2 values.
    """
    values = np.asarray(values, dtype=float)
    if values.size < 2:
        msg = f"--points {values.size}: a branch needs at least 2 values"
        raise ConfigError(msg)
    for value in values:
        config_at(data, key, value)
    wrap = progress if progress is not None else (lambda it: it)
    spectra = [spectrum_at(data, key, value, k, positions) for value in wrap(values)]
    width = min(s.eigenvalues.size for s in spectra)
    eigenvalues = np.array([s.eigenvalues[:width] for s in spectra])
    residuals = np.array([s.residuals[:width] for s in spectra])
    branch = Branch(key=key, values=values, eigenvalues=eigenvalues, residuals=residuals)
    growth = eigenvalues[:, 0].real
    for i in np.nonzero(np.sign(growth[:-1]) * np.sign(growth[1:]) < 0)[0]:
        ends = {float(values[j]): spectra[j] for j in (i, i + 1)}
        branch.crossings.append(
            critical_value(data, key, values[i], values[i + 1], rtol, k, positions, ends)
        )
    return branch
