"""One-line error messages naming the key path and its allowed values.

:func:`format_validation_error` turns pydantic's ``ValidationError`` into the one line
that :class:`~pde_rotor.config.errors.ConfigError` carries, before anything is compiled.
"""

from __future__ import annotations

import json
import math
import types
from collections.abc import Mapping
from typing import Annotated, Any, Literal, Union, get_args, get_origin

from pydantic import BaseModel, ValidationError
from pydantic.fields import FieldInfo

from .errors import FieldError
from .schema import RotorConfig

_PROBLEMS = {
    "extra_forbidden": "unknown key",
    "float_parsing": "expected a number",
    "float_type": "expected a number",
    "int_parsing": "expected an integer",
    "int_type": "expected an integer",
    "int_from_float": "expected an integer, got a fraction",
    "bool_parsing": "expected true or false",
    "bool_type": "expected true or false",
    "finite_number": "must be finite",
    "literal_error": "not one of the allowed values",
    "model_type": "expected a section (a mapping of keys)",
    "model_attributes_type": "expected a section (a mapping of keys)",
    "dict_type": "expected a section (a mapping of keys)",
    "greater_than": "out of range",
    "greater_than_equal": "out of range",
    "less_than": "out of range",
    "less_than_equal": "out of range",
}


def _model_at(path: tuple[str, ...]) -> type[BaseModel] | None:
    """The section model that the key path leads into (None if it leaves the schema)."""
    model: type[BaseModel] = RotorConfig
    for part in path:
        field = model.model_fields.get(part)
        if field is None:
            return None
        ann = field.annotation
        if not (isinstance(ann, type) and issubclass(ann, BaseModel)):
            return None
        model = ann
    return model


def _unwrap(ann: Any) -> tuple[Any, list[Any], bool]:
    """Split an annotation into (base type, constraint metadata, whether None is allowed)."""
    optional = False
    if get_origin(ann) in (Union, types.UnionType):
        args = [arg for arg in get_args(ann) if arg is not type(None)]
        optional = len(args) < len(get_args(ann))
        ann = args[0]
    metadata: list[Any] = []
    if get_origin(ann) is Annotated:
        ann, *extras = get_args(ann)
        for extra in extras:
            metadata.extend(extra.metadata if isinstance(extra, FieldInfo) else [extra])
    return ann, metadata, optional


def allowed_values(path: tuple[str, ...]) -> str:
    """Describe the allowed values of the field at `path` (e.g. ``float > 0``)."""
    if not path:
        return "sections " + ", ".join(RotorConfig.model_fields)
    parent = _model_at(path[:-1])
    if parent is None or path[-1] not in parent.model_fields:
        return ""
    field = parent.model_fields[path[-1]]
    sub = _model_at(path)
    if sub is not None:
        return "a section with keys " + ", ".join(sub.model_fields)
    base, metadata, optional = _unwrap(field.annotation)
    metadata = [*field.metadata, *metadata]
    if get_origin(base) is Literal:
        kind = "one of " + ", ".join(str(arg) for arg in get_args(base))
    elif base is bool:
        kind = "true or false"
    elif base is int:
        kind = "integer"
    else:
        kind = "number"
    # annotated_types.Gt(gt=...), Ge, Lt, Le; a field may narrow its type's bound
    # (PositiveFloat's gt=0 and a Field's ge=1e-8): the tightest one is the rule
    lows: list[tuple[float, str]] = []
    highs: list[tuple[float, str]] = []
    for meta in metadata:
        if getattr(meta, "gt", None) is not None:
            lows.append((meta.gt, f"{meta.gt:g} <"))
        elif getattr(meta, "ge", None) is not None:
            lows.append((meta.ge, f"{meta.ge:g} <="))
        elif getattr(meta, "lt", None) is not None:
            highs.append((-meta.lt, f"< {meta.lt:g}"))
        elif getattr(meta, "le", None) is not None:
            highs.append((-meta.le, f"<= {meta.le:g}"))
    lower = max(lows)[1] if lows else ""
    upper = max(highs)[1] if highs else ""
    if lower and not upper:
        value, sym = lower.split(" ")
        kind += f", {path[-1]} {sym.replace('<', '>')} {value}"
    elif lower or upper:
        kind += ", " + " ".join(part for part in (lower, path[-1], upper) if part)
    if optional:
        kind += " or null"
    return kind


def _show(value: Any) -> str:
    if isinstance(value, dict):
        return "{...}"
    text = repr(value) if isinstance(value, str) else json.dumps(value, default=str)
    return text if len(text) <= 40 else text[:37] + "..."


def _format_one(error: Mapping[str, Any]) -> str:
    loc = tuple(str(part) for part in error["loc"])
    kind = error["type"]
    ctx = error.get("ctx") or {}
    cause = ctx.get("error")
    if kind == "value_error" and isinstance(cause, FieldError):
        path = ".".join((*loc, cause.path))
        return f"{path} = {_show(cause.value)}: {cause}"
    path = ".".join(loc) if loc else "<top level>"
    if kind == "extra_forbidden":
        parent = _model_at(loc[:-1])
        keys = ", ".join(parent.model_fields) if parent else ""
        where = ".".join(loc[:-1]) or "top level"
        return f"{path}: unknown key (allowed keys in {where}: {keys})"
    value = error.get("input")
    if kind == "value_error":
        message = str(cause) if cause is not None else error["msg"]
    elif isinstance(value, float) and not math.isfinite(value):
        message = "must be a finite number"
    else:
        message = _PROBLEMS.get(kind, error["msg"].lower())
    allowed = allowed_values(loc)
    suffix = f" (allowed: {allowed})" if allowed else ""
    return f"{path} = {_show(value)}: {message}{suffix}"


def format_validation_error(err: ValidationError, limit: int = 3) -> str:
    """One line describing the first `limit` problems of a validation error."""
    errors = err.errors()
    parts = [_format_one(e) for e in errors[:limit]]
    more = len(errors) - limit
    if more > 0:
        parts.append(f"and {more} more")
    return "; ".join(parts)
