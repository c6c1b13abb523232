"""Configs in and out: YAML files, ``--set`` overrides, the one dotted-key setter.

:func:`load_config` reads a YAML file, applies ``--set key.path=value`` overrides
(:func:`apply_overrides`) and validates the result; :func:`dump_config` writes a
:class:`~pde_rotor.config.schema.RotorConfig` back so that it loads to an equal one.

In a config with ``bodies:``, ``--set protocol.<key>=<value>`` also sets that key in the protocol of
every body whose protocol is the run's (the shipped configs copy the run's protocol into the
body that is stopped); where no body follows the run's protocol it sets the run's length
only, and where some body has a protocol of its own one warning says so and names them.
"""

from __future__ import annotations

import json
import logging
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError

from .errors import ConfigError
from .messages import format_validation_error
from .protocol import ProtocolConfig
from .schema import RotorConfig

_logger = logging.getLogger(__name__)

PROVENANCE_KEY = "provenance"
"""Top-level key of a run's config.yaml holding versions and hash; ignored when loading."""


class _Loader(yaml.SafeLoader):
    """Safe YAML loader that reads 1e-4 as a float and refuses duplicate keys."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


def _construct_mapping(loader: _Loader, node: yaml.MappingNode, deep: bool = False) -> dict:
    loader.flatten_mapping(node)
    result: dict = {}
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in result:
            mark = key_node.start_mark
            msg = f"line {mark.line + 1}: duplicate key {key!r}"
            raise ConfigError(msg)
        result[key] = loader.construct_object(value_node, deep=deep)
    return result


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def parse_yaml(text: str, source: str = "<string>") -> Any:
    """Parse YAML text (floats like 1e-4 included); errors become one-line ConfigErrors."""
    try:
        return yaml.load(text, Loader=_Loader)
    except ConfigError as err:
        msg = f"{source}: {err}"
        raise ConfigError(msg) from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(err, "problem", None) or str(err).splitlines()[0]
        if "got '['" in problem and "'}'" in problem:
            problem += (
                "; inside {...} a key with a list index must be quoted, "
                '{"bodies[0].start.x": 1}, or written in block style, one key a line'
            )
        msg = f"{source}: invalid YAML{where}: {problem}"
        raise ConfigError(msg) from None


def read_config_data(path: str | Path) -> dict[str, Any]:
    """Read a YAML config file into a plain dict (provenance removed), without validating."""
    path = Path(path)
    if path.is_dir():
        path = path / "config.yaml"
    if not path.exists():
        msg = f"config file {str(path)!r} not found"
        raise ConfigError(msg)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        msg = f"config file {str(path)!r} cannot be read: {err}"
        raise ConfigError(msg) from None
    data = parse_yaml(text, source=str(path))
    if data is None:
        msg = (
            f"{path}: the file is empty or holds only comments; a config names at least one "
            "section (e.g. protocol: {t_stop: 1.0}); write {} to run every default (the "
            "paper's grid and 100 stop-and-release cycles)"
        )
        raise ConfigError(msg)
    if not isinstance(data, dict):
        msg = (
            f"{path}: the top level must be a mapping of sections "
            f"({', '.join(RotorConfig.model_fields)}), got {type(data).__name__}"
        )
        raise ConfigError(msg)
    data.pop(PROVENANCE_KEY, None)
    return data


def load_config(path: str | Path, overrides: Iterable[str] = ()) -> RotorConfig:
    """Load and validate a YAML config file, then apply ``--set`` overrides.

    Args:
        path: YAML file (or a run directory holding config.yaml).
        overrides: strings ``key.path=value``; value is parsed as YAML.

    Raises:
        ConfigError: one line naming the file or key path and the allowed values.
    """
    data = read_config_data(path)
    if {"axes", "samples"} & set(data) and not set(RotorConfig.model_fields) & set(data):
        msg = (
            f"{path} is a sweep file (keys {', '.join(data)}), not a run config: "
            "`pde-rotor sweep FILE --dry-run` checks it"
        )
        raise ConfigError(msg)
    data = apply_overrides(data, overrides)
    return validate_config(data)


def validate_config(data: Mapping[str, Any]) -> RotorConfig:
    """Build a :class:`RotorConfig` from a nested mapping; errors become ConfigErrors."""
    try:
        return RotorConfig.model_validate(dict(data))
    except ValidationError as err:
        raise ConfigError(format_validation_error(err)) from None


_PART = r"[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])?"
_KEY_PATH = re.compile(rf"^{_PART}(\.{_PART})*$")


def parse_override(text: str) -> tuple[list[str], Any]:
    """Split ``key.path=value`` into the key path and the YAML-parsed value.

    A part of the path may index a list: ``bodies[1].start.x=2``.
    """
    key, sep, raw = text.partition("=")
    key = key.strip()
    negative = re.search(r"\[-[0-9]+\]", key)
    if sep and negative:
        msg = (
            f"--set {text!r}: {negative.group()} counts from the end, which a key path does "
            "not (allowed: an index from 0, e.g. bodies[0], or the list's length to add an "
            "entry)"
        )
        raise ConfigError(msg)
    if not sep or not _KEY_PATH.match(key):
        msg = (
            f"--set {text!r}: expected KEY.PATH=VALUE with a dotted key path, "
            "e.g. --set protocol.t_stop=1.5 or --set bodies[0].start.x=1"
        )
        raise ConfigError(msg)
    if raw.strip() == "":
        msg = f"--set {text!r}: missing value after '=' for {key}"
        raise ConfigError(msg)
    value = parse_yaml(raw, source=f"--set {key}")
    return key.split("."), value


def _child(node: Any, part: str, where: str, last: bool, value: Any) -> Any:
    """The entry `part` (``t_stop`` or ``bodies[1]``) of a mapping `node`, created as a
    section where missing; `value` stored there instead where `last`."""
    name, _, index = part.partition("[")
    if not index:
        if last:
            node[name] = value
            return value
        if node.get(name) is None:
            node[name] = {}
        return node[name]
    entries = node.get(name)
    if entries is None:
        entries = node[name] = []
    if not isinstance(entries, list):
        msg = f"{where.rpartition('[')[0]} is not a list"
        raise ConfigError(msg)
    i = int(index.rstrip("]"))
    if i > len(entries):
        msg = (
            f"{where} is not an entry of the {len(entries)} in {name} (allowed: an index "
            f"below {len(entries)}, or {len(entries)} to add one)"
        )
        raise ConfigError(msg)
    if i == len(entries):
        entries.append({})
    if last:
        entries[i] = value
    elif entries[i] is None:
        entries[i] = {}
    return entries[i]


def set_key(data: dict[str, Any], key: str, value: Any) -> None:
    """Set the dotted key `key` (``protocol.t_stop``) of a nested mapping, creating sections.

    A part may index a list (``bodies[1].start.x``): an index one past the end adds an
    entry. The one dotted-key setter of the package: overrides, sweep axes and the
    gallery use it.

    Raises:
        ConfigError: a part of the key path holds a value, not a section, or indexes past
            the end of a list (one line).
    """
    path = key.split(".")
    node: Any = data
    for depth, part in enumerate(path):
        if isinstance(node, list):
            where = ".".join(path[:depth])
            msg = f"{where} is a list, not a section (allowed: an entry, e.g. {where}[0])"
            raise ConfigError(msg)
        if not isinstance(node, dict):
            msg = f"{'.'.join(path[:depth])} is a value, not a section"
            raise ConfigError(msg)
        node = _child(node, part, ".".join(path[: depth + 1]), depth == len(path) - 1, value)


def apply_overrides(data: Mapping[str, Any], overrides: Iterable[str]) -> dict[str, Any]:
    """Return a copy of `data` with every ``key.path=value`` override applied (in order).

    Unknown keys are left for the schema to reject, so overrides and files give the
    same error messages.
    """
    result = json.loads(json.dumps(data, default=str)) if data else {}
    for text in overrides:
        path, value = parse_override(text)
        followers = _protocol_followers(result, path, text)
        try:
            set_key(result, ".".join(path), value)
            for i in followers:
                set_key(result, ".".join([f"bodies[{i}]", *path]), value)
        except ConfigError as err:
            raise ConfigError(f"--set {text!r}: {err}") from None
    return result


def _same_protocol(a: Any, b: Any) -> bool:
    """Whether two protocol sections are the same protocol (defaults filled in)."""
    if not isinstance(a, Mapping) or not isinstance(b, Mapping):
        return False
    try:
        return ProtocolConfig.model_validate(dict(a)) == ProtocolConfig.model_validate(dict(b))
    except ValidationError:
        return dict(a) == dict(b)


def _protocol_followers(data: Mapping[str, Any], path: list[str], text: str) -> list[int]:
    """The bodies a ``protocol.<key>`` override also applies to: those whose protocol is the
    run's; one warning when some body has its own protocol and none follows the run's."""
    bodies = data.get("bodies")
    if path[0] != "protocol" or len(path) < 2 or not isinstance(bodies, list) or not bodies:
        return []
    run = data.get("protocol") or {}
    entries = [b if isinstance(b, Mapping) else {} for b in bodies]
    followers = [i for i, b in enumerate(entries) if _same_protocol(b.get("protocol"), run)]
    own = [
        f"bodies[{i}]" + (f" ({b['name']})" if b.get("name") else "")
        for i, b in enumerate(entries)
        if b.get("protocol") is not None
    ]
    if own and not followers:
        _logger.warning(
            "--set %s changes the run's length (protocol.t_end) only: no body follows the "
            "run's protocol; %s keep their own (set e.g. %s.%s)",
            text,
            ", ".join(own),
            own[0].split()[0],
            ".".join(path),
        )
    return followers


def dump_config(config: RotorConfig, provenance: Mapping[str, Any] | None = None) -> str:
    """The fully resolved config as YAML (every key), optionally with a provenance block.

    :func:`load_config` reads it back to an equal :class:`RotorConfig`.
    """
    data: dict[str, Any] = {}
    if provenance:
        data[PROVENANCE_KEY] = dict(provenance)
    data.update(config.model_dump(mode="json"))
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=False)
