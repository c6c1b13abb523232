"""How the config's keys reach the compiled records, declared next to each key.

The compiled physics reads its parameters from numpy records by field name
(:mod:`pde_rotor.kernels.records`): ``PARAMS`` of a run, ``BODY`` of each body. Their
fields that come from the config are not listed by hand. Every numeric key of a record
section (a section of the run, :data:`pde_rotor.kernels.records.PARAMS_SECTIONS`, or a
body's own keys, :class:`pde_rotor.config.BodyConfig`) is the field of its name with its
value: a float as float64, an int as int64, a bool as bool, a pair [a, b] as the two
fields ``NAME_x`` and ``NAME_y``. A key whose annotation carries a marker goes otherwise:

* :class:`RecordAs` (field, value): the field `field` holds value(key), a quantity
  derived from this key alone and written once, here, next to it (``camphor.saturation``:
  ``inv_saturation`` = 1 / c_sat, 0 for the linear law); without `value`, the key under
  another name (``flow.enabled``: ``flow``);
* :class:`BuiltInto` (field): the records' builder computes `field` from this key and
  others (``camphor.supply`` with ``geometry.pill_radius``: ``source`` = s0 / (pi rho^2));
* :class:`NotRecorded` (why): the kernels do not read it (an initial condition, a seed).

A numeric key that may be null needs a marker (a record holds no null), and
:func:`record_layout` says so in one line. Keys that are not numbers (names, a variant's
tag, nested sections, lists) are the config's structure, not parameters, and are not
walked. So a new numeric key reaches the compiled physics (``p.NAME``, ``b.NAME``) and the
numpy reference (which reads the config's sections) without an edit of the records
(docs/numerics.md, "How to add a term").
"""

from __future__ import annotations

import types
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, Union, get_args, get_origin

from pydantic import BaseModel
from pydantic.fields import FieldInfo


@dataclass(frozen=True)
class RecordAs:
    """The key enters the record as the field `field`, holding value(key) (None: the
    key's value itself) of numpy type `kind` (None: float64 for a value, the key's own
    type for a rename)."""

    field: str
    value: Callable[[Any], Any] | None = None
    kind: str | None = None


@dataclass(frozen=True)
class BuiltInto:
    """The records' builder (:mod:`pde_rotor.kernels.records`) computes the field
    `field` from this key and others."""

    field: str


@dataclass(frozen=True)
class NotRecorded:
    """The kernels do not read the key (`why`: what reads it instead)."""

    why: str


Marker = RecordAs | BuiltInto | NotRecorded

_KINDS = {bool: "b1", int: "i8", float: "f8"}
"""numpy type of the record field of a scalar key, by its Python type."""


def _bare(annotation: Any) -> Any:
    """The annotation without its ``Annotated`` metadata."""
    while get_origin(annotation) is Annotated:
        annotation = get_args(annotation)[0]
    return annotation


def _scalar_kind(annotation: Any) -> str | None:
    """numpy type code of a scalar annotation (bool, int, float), or None."""
    return _KINDS.get(_bare(annotation))


def _kind(annotation: Any) -> str | None:
    """``f8``, ``i8``, ``b1``, ``pair`` (two floats), ``nullable`` (a number or null), or
    None for a key that is not a number."""
    bare = _bare(annotation)
    scalar = _scalar_kind(bare)
    if scalar is not None:
        return scalar
    origin, args = get_origin(bare), get_args(bare)
    if origin is tuple and len(args) == 2 and all(_scalar_kind(a) == "f8" for a in args):
        return "pair"
    numeric = any(_kind(a) is not None for a in args if a is not type(None))
    if origin in (Union, types.UnionType) and type(None) in args and numeric:
        return "nullable"
    return None


def marker(info: FieldInfo) -> Marker | None:
    """The record marker of a field, if its annotation carries one."""
    found = [m for m in info.metadata if isinstance(m, RecordAs | BuiltInto | NotRecorded)]
    return found[0] if found else None


def record_layout(cls: type[BaseModel]) -> list[tuple[str, str]]:
    """(field, numpy type code) of the record fields the keys of `cls` give, in the
    keys' order (module docstring).

    Raises:
        TypeError: a numeric key that may be null carries no marker.
    """
    layout: list[tuple[str, str]] = []
    for key, info in cls.model_fields.items():
        mark, kind = marker(info), _kind(info.annotation)
        if isinstance(mark, RecordAs):
            own = kind if mark.value is None and kind in _KINDS.values() else "f8"
            layout.append((mark.field, mark.kind or own))
        elif mark is not None:
            continue
        elif kind == "pair":
            layout += [(f"{key}_x", "f8"), (f"{key}_y", "f8")]
        elif kind == "nullable":
            msg = (
                f"{cls.__name__}.{key} may be null, which a record cannot hold: mark it "
                "RecordAs, BuiltInto or NotRecorded (pde_rotor/config/recorded.py)"
            )
            raise TypeError(msg)
        elif kind is not None:
            layout.append((key, kind))
    return layout


def record_values(section: BaseModel) -> dict[str, Any]:
    """The record fields of `section` (:func:`record_layout`) with their values."""
    values: dict[str, Any] = {}
    for key, info in type(section).model_fields.items():
        mark, kind, value = marker(info), _kind(info.annotation), getattr(section, key)
        if isinstance(mark, RecordAs):
            values[mark.field] = value if mark.value is None else mark.value(value)
        elif mark is not None or kind is None:
            continue
        elif kind == "pair":
            values[f"{key}_x"], values[f"{key}_y"] = value
        else:
            values[key] = value
    return values


def markers(cls: type[BaseModel]) -> dict[str, Marker]:
    """The marked keys of `cls` and their markers."""
    return {
        key: mark for key, info in cls.model_fields.items() if (mark := marker(info)) is not None
    }
