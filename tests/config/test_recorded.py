"""The record layout read off a schema's fields (pde_rotor.config.recorded)."""

from __future__ import annotations

from typing import Annotated, Literal

import pytest
from pydantic import Field

from pde_rotor.config.fields import FiniteFloat, Int, PositiveFloat, _Section
from pde_rotor.config.recorded import (
    BuiltInto,
    NotRecorded,
    RecordAs,
    markers,
    record_layout,
    record_values,
)


def _half(value: float) -> float:
    return value / 2


class Toy(_Section):
    """A section with one key of every kind the layout reads."""

    rate: FiniteFloat = Field(0.5, description="a float")
    count: Int = Field(3, description="an int")
    on: bool = Field(True, description="a bool")
    force: tuple[FiniteFloat, FiniteFloat] = Field((1.0, -2.0), description="a pair")
    law: Annotated[PositiveFloat | None, RecordAs("inv_law", lambda v: 0.0 if v is None else 1 / v)]
    halved: Annotated[FiniteFloat, RecordAs("half", _half)] = Field(3.0, description="derived")
    enabled: Annotated[bool, RecordAs("switch")] = Field(False, description="renamed")
    total: Annotated[FiniteFloat, BuiltInto("built")] = Field(1.0, description="built")
    start: Annotated[FiniteFloat, NotRecorded("initial")] = Field(0.0, description="unused")
    name: str = Field("toy", description="structure")
    kind: Literal["a", "b"] = Field("a", description="structure")
    pills: list[float] = Field(default_factory=list, description="structure")


def test_every_numeric_key_is_a_field_and_the_markers_rename_or_leave_it() -> None:
    assert record_layout(Toy) == [
        ("rate", "f8"),
        ("count", "i8"),
        ("on", "b1"),
        ("force_x", "f8"),
        ("force_y", "f8"),
        ("inv_law", "f8"),
        ("half", "f8"),
        ("switch", "b1"),
    ]
    values = record_values(Toy(law=4.0))
    assert values == {
        "rate": 0.5,
        "count": 3,
        "on": True,
        "force_x": 1.0,
        "force_y": -2.0,
        "inv_law": 0.25,
        "half": 1.5,
        "switch": False,
    }
    assert record_values(Toy(law=None))["inv_law"] == 0.0
    assert [name for name, _ in record_layout(Toy)] == list(values)
    assert set(markers(Toy)) == {"law", "halved", "enabled", "total", "start"}


def test_a_nullable_number_without_a_marker_is_refused_in_one_line() -> None:
    class Loose(_Section):
        limit: PositiveFloat | None = Field(None, description="may be null")

    with pytest.raises(TypeError, match=r"^Loose\.limit may be null") as err:
        record_layout(Loose)
    assert "\n" not in str(err.value)
