"""One-line error messages naming the key path and its allowed values.

:func:`format_validation_error` turns pydantic's ``ValidationError`` into the one line
that :class:`~pde_rotor.config.errors.ConfigError` carries, before anything is compiled.
"""

from __future__ import annotations

import json
import math
import types
from collections.abc import Mapping
from dataclasses import dataclass
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
    "list_type": "expected a list",
    "tuple_type": "expected a list",
    "too_long": "too many values",
    "too_short": "too few values",
    "string_type": "expected a name",
    "string_pattern_mismatch": "a name holds letters, digits, _ and - only",
    "greater_than": "out of range",
    "greater_than_equal": "out of range",
    "less_than": "out of range",
    "less_than_equal": "out of range",
}


Part = str | int
"""One part of a key path as pydantic's error locations give it: a key, a list index, or
the tag of a section chosen by its ``shape`` or ``kind``."""


@dataclass(frozen=True)
class _Place:
    """Where a key path leads in the schema.

    Attributes:
        text: the path as the user writes it (``bodies[1].plate.radius``: list indices in
            brackets, the tags of discriminated sections left out).
        annotation: the type found there.
        field: the field the path ends on (None after a list index).
        name: the last key of the path.
    """

    text: str
    annotation: Any
    field: FieldInfo | None
    name: str


def _kinds(ann: Any) -> list[Any]:
    """The alternatives of an annotation, Annotated and None stripped."""
    if get_origin(ann) is Annotated:
        ann = get_args(ann)[0]
    if get_origin(ann) in (Union, types.UnionType):
        return [_kinds(arg)[0] for arg in get_args(ann) if arg is not type(None)]
    return [ann]


def _models(ann: Any) -> list[type[BaseModel]]:
    """The section models among the alternatives of an annotation."""
    return [k for k in _kinds(ann) if isinstance(k, type) and issubclass(k, BaseModel)]


def _tag_of(model: type[BaseModel]) -> tuple[str, str] | None:
    """(key, value) of the Literal field that tags a member of a discriminated section."""
    for name, field in model.model_fields.items():
        args = get_args(field.annotation) if get_origin(field.annotation) is Literal else ()
        if len(args) == 1:
            return name, args[0]
    return None


def _tags(ann: Any) -> tuple[str, list[str]] | None:
    """The tag key and its values where `ann` is a section chosen by a tag (``plate``)."""
    models = _models(ann)
    tags = [_tag_of(m) for m in models]
    if len(models) < 2 or None in tags:
        return None
    return tags[0][0], [tag[1] for tag in tags if tag is not None]


def _resolve(path: tuple[Part, ...]) -> _Place | None:
    """Follow a key path (an error's location) through the schema; None if it leaves it."""
    place = _Place("", RotorConfig, None, "")
    for part in path:
        ann = place.annotation
        if isinstance(part, int):
            kinds = [k for k in _kinds(ann) if get_origin(k) in (list, tuple)]
            if not kinds:
                return None
            args = get_args(kinds[0])
            item = args[0] if get_origin(kinds[0]) is list else args[min(part, len(args) - 1)]
            place = _Place(f"{place.text}[{part}]", item, None, place.name)
            continue
        models = _models(ann)
        tagged = [m for m in models if len(models) > 1 and (_tag_of(m) or ("", ""))[1] == part]
        if tagged:
            place = _Place(place.text, tagged[0], place.field, place.name)
            continue
        owner = next((m for m in models if part in m.model_fields), None)
        if owner is None:
            return None
        field = owner.model_fields[part]
        text = f"{place.text}.{part}" if place.text else part
        place = _Place(text, field.annotation, field, part)
    return place


def key_text(path: tuple[Part, ...]) -> str:
    """A key path as the user writes it: ``('bodies', 1, 'plate', 'disk', 'radius')`` ->
    ``bodies[1].plate.radius`` (the parts beyond the schema joined as they are)."""
    known = len(path)
    while known and _resolve(path[:known]) is None:
        known -= 1
    place = _resolve(path[:known])
    text = place.text if place is not None else ""
    for part in path[known:]:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text


def _model_at(path: tuple[Part, ...]) -> type[BaseModel] | None:
    """The section model that the key path leads into (None if it leaves the schema)."""
    place = _resolve(path)
    models = _models(place.annotation) if place is not None else []
    return models[0] if len(models) == 1 else None


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


def _sections(ann: Any) -> str:
    """What a section (or a list of sections, or a section chosen by a tag) allows."""
    tags = _tags(ann)
    if tags is not None:
        return f"a section with {tags[0]}: one of " + ", ".join(tags[1])
    models = _models(ann)
    if len(models) == 1:
        return "a section with keys " + ", ".join(models[0].model_fields)
    lists = [k for k in _kinds(ann) if get_origin(k) is list]
    if lists:
        inner = _sections(get_args(lists[0])[0])
        return f"a list of {inner.removeprefix('a ').replace('section', 'sections', 1)}"
    return ""


def allowed_values(path: tuple[Part, ...]) -> str:
    """Describe the allowed values of the field at `path` (e.g. ``float > 0``)."""
    if not path:
        return "sections " + ", ".join(RotorConfig.model_fields)
    place = _resolve(path)
    if place is None or (place.field is None and not isinstance(path[-1], int)):
        return ""
    sections = _sections(place.annotation)
    if sections:
        return sections
    base, metadata, optional = _unwrap(place.annotation)
    if place.field is not None:
        metadata = [*place.field.metadata, *metadata]
    if get_origin(base) is Literal:
        kind = "one of " + ", ".join(str(arg) for arg in get_args(base))
    elif get_origin(base) is tuple:
        return f"[{', '.join('number' for _ in get_args(base))}]"
    elif base is bool:
        kind = "true or false"
    elif base is int:
        kind = "integer"
    elif base is str:
        kind = "text"
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
    name = place.name
    if lower and not upper:
        value, sym = lower.split(" ")
        kind += f", {name} {sym.replace('<', '>')} {value}"
    elif lower or upper:
        kind += ", " + " ".join(part for part in (lower, name, upper) if part)
    if optional:
        kind += " or null"
    return kind


def _show(value: Any) -> str:
    if isinstance(value, dict):
        return "{...}"
    text = repr(value) if isinstance(value, str) else json.dumps(value, default=str)
    return text if len(text) <= 40 else text[:37] + "..."


def _format_one(error: Mapping[str, Any]) -> str:
    loc = tuple(error["loc"])
    kind = error["type"]
    ctx = error.get("ctx") or {}
    cause = ctx.get("error")
    where = key_text(loc)
    if kind == "value_error" and isinstance(cause, FieldError):
        path = f"{where}.{cause.path}" if where else cause.path
        return f"{path} = {_show(cause.value)}: {cause}"
    path = where or "<top level>"
    if kind == "extra_forbidden":
        parent = _model_at(loc[:-1])
        keys = ", ".join(parent.model_fields) if parent else ""
        return f"{path}: unknown key (allowed keys in {key_text(loc[:-1]) or 'top level'}: {keys})"
    tags = _tags(_resolve(loc).annotation) if _resolve(loc) is not None else None
    if kind in ("union_tag_invalid", "union_tag_not_found") and tags is not None:
        key, values = tags
        allowed = f"(allowed: one of {', '.join(values)})"
        if kind == "union_tag_not_found":
            return f"{path}.{key}: missing key {allowed}"
        return f"{path}.{key} = {_show(ctx.get('tag'))}: not one of the allowed values {allowed}"
    if kind == "missing" and loc and isinstance(loc[-1], int):
        # a position of a fixed-length list ([u_x, u_y]) that the value left out
        values = error.get("input")
        place = _resolve(loc[:-1])
        size = len(get_args(_unwrap(place.annotation)[0])) if place is not None else 0
        got = len(values) if isinstance(values, list | tuple) else 1
        allowed = allowed_values(loc[:-1])
        path = key_text(loc[:-1])
        return f"{path} = {_show(values)}: expected {size} values, got {got} (allowed: {allowed})"
    if kind == "missing":
        allowed = allowed_values(loc)
        return f"{path}: missing key" + (f" (allowed: {allowed})" if allowed else "")
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
