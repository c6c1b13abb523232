"""A key added to the schema at its default changes no dump, config hash or run key.

The schema is extended the way a contributor extends it (a new key in a section, a new
section, a new key of each body); the committed configs and sweep stores must keep their
stored hashes and run keys, and a key set away from its default must change them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

import pytest
import yaml
from pydantic import Field

from pde_rotor.config import BodyConfig, CamphorConfig, RotorConfig, load_config, yaml_io
from pde_rotor.config.fields import FiniteFloat, _Section
from pde_rotor.config.stable import StableModel, leavable_keys
from pde_rotor.sweep.plan import Sweep
from pde_rotor.sweep.spec import RestartEstimator, validate_point
from pde_rotor.sweep.store import read_runs

ROOT = Path(__file__).resolve().parents[2]
STORES = sorted(p.parent for p in (ROOT / "data" / "sweeps").glob("*/sweep.yaml"))
RUN_CONFIGS = sorted((ROOT / "data" / "runs").glob("*/config.yaml"))


class DummySection(_Section):
    """A new section of the schema."""

    level: FiniteFloat = Field(0.0, description="a new key of a new section")


class DummyCamphor(CamphorConfig):
    """The camphor section with one more key, as a saturation law would add."""

    saturation: FiniteFloat | None = Field(None, description="a new key of a section")


class DummyBody(BodyConfig):
    """A body with one more key, as an external force would add."""

    dummy_force: tuple[FiniteFloat, FiniteFloat] = Field((0.0, 0.0), description="new")


class DummyConfig(RotorConfig):
    """The schema with a new key in a section, a new section and a new key of each body."""

    camphor: DummyCamphor = Field(default_factory=DummyCamphor)
    dummy: DummySection = Field(default_factory=DummySection)
    bodies: list[DummyBody] | None = None


@pytest.fixture
def dummy_schema(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every config read or validated (files, sweep points) is a :class:`DummyConfig`."""
    monkeypatch.setattr(yaml_io, "RotorConfig", DummyConfig)


def _disk_bodies() -> list[dict]:
    pill = {"x": 0.0, "y": 0.0, "radius": 0.1}
    motion = {"kind": "free", "mass": 1.0, "friction": 0.15}
    return [
        {"plate": {"shape": "disk", "radius": 0.2}, "pills": [pill], "motion": motion},
        {"plate": {"shape": "disk", "radius": 0.2}, "pills": [pill], "start": {"x": 1.6}},
    ]


def test_new_keys_at_their_defaults_leave_every_dump_unchanged() -> None:
    for data in ({}, {"bodies": _disk_bodies(), "grid": {"wall": "no_flux"}}):
        old, new = RotorConfig.model_validate(data), DummyConfig.model_validate(data)
        assert new.model_dump(mode="json") == old.model_dump(mode="json")
        assert new.model_dump() == old.model_dump()
        assert new.physics() == old.physics()
        assert new.config_hash() == old.config_hash()


def test_a_new_key_set_away_from_its_default_is_dumped_and_hashed() -> None:
    base = DummyConfig.model_validate({"bodies": _disk_bodies()})
    changed = [
        DummyConfig.model_validate({"bodies": _disk_bodies(), "camphor": {"saturation": 2.0}}),
        DummyConfig.model_validate({"bodies": _disk_bodies(), "dummy": {"level": 1.0}}),
    ]
    bodies = _disk_bodies()
    bodies[1]["dummy_force"] = [0.5, 0.0]
    changed.append(DummyConfig.model_validate({"bodies": bodies}))
    hashes = {base.config_hash(), *(c.config_hash() for c in changed)}
    assert len(hashes) == 4
    for config in changed:
        assert DummyConfig.model_validate(config.model_dump(mode="json")) == config
    assert changed[0].model_dump()["camphor"]["saturation"] == 2.0
    assert changed[2].model_dump(mode="json")["bodies"][1]["dummy_force"] == [0.5, 0.0]


def test_the_committed_keys_are_dumped_at_any_value() -> None:
    """The keys of the first stores stay in every dump, defaults included; the later
    grid keys, ``contact`` and ``bodies`` leave it at their defaults."""
    dump = RotorConfig().model_dump(mode="json")
    assert set(dump["camphor"]) == {"diffusion", "evaporation", "supply", "tension_slope"}
    assert set(dump["grid"]) == {"domain_radius", "dx", "dt"}
    assert "bodies" not in dump and "contact" not in dump
    assert [name for name, _ in leavable_keys(RotorConfig)] == ["contact", "bodies"]
    moved = RotorConfig.model_validate({"grid": {"domain_centre": [0.5, 0.0]}})
    assert moved.model_dump(mode="json")["grid"]["domain_centre"] == [0.5, 0.0]


def test_a_variant_keeps_its_tag_and_required_keys() -> None:
    """A new variant's tag and required keys are dumped even where they are new."""

    class Vessel(StableModel):
        shape: str = "annulus"
        inner: float = 1.0
        outer: float

    class AnnulusVessel(StableModel):
        shape: Literal["annulus"] = "annulus"
        inner: float = 1.0

    assert Vessel(outer=2.0).model_dump() == {"outer": 2.0}
    assert AnnulusVessel().model_dump() == {"shape": "annulus"}


def test_an_estimator_key_added_at_its_default_changes_no_run_key() -> None:
    class Estimator(RestartEstimator):
        settle: float = Field(0.0, description="a new estimator key")

    assert Estimator().model_dump(mode="json") == RestartEstimator().model_dump(mode="json")
    assert Estimator(settle=1.0).model_dump(mode="json")["settle"] == 1.0


@pytest.mark.parametrize("path", RUN_CONFIGS, ids=lambda p: p.parent.name)
def test_stored_run_configs_keep_their_hash(dummy_schema: None, path: Path) -> None:
    stored = yaml.safe_load(path.read_text())["provenance"]["config_hash"]
    config = load_config(path)
    assert isinstance(config, DummyConfig)
    assert config.config_hash() == stored


@pytest.mark.parametrize("store", STORES, ids=lambda p: p.name)
def test_every_committed_store_keeps_its_run_keys(dummy_schema: None, store: Path) -> None:
    """Every run stored in the store is a run of its recorded design, planned with the
    extended schema: a resume recomputes nothing."""
    sweep = Sweep.load(store)
    planned = {run.key for run in sweep.runs()}
    # a crowd sweep's base has no bodies (its runs have): check a planned run's config
    assert isinstance(validate_point(sweep.runs()[0].config, "first run"), DummyConfig)
    stored = set(read_runs(store))
    assert stored
    assert stored <= planned
