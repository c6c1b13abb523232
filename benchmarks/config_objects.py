"""How often one run makes each model object from its configuration.

Wraps the ``from_config`` constructors of the model's objects (the rotor's shape, the stop
schedule, the schemes, the bodies and their shapes) with a counter and runs
:func:`pde_rotor.api.run` once on a small rotor config and once on a config with one
``bodies:`` entry that has its own protocol, in memory. Run it under each checkout's
PYTHONPATH to compare::

    PYTHONPATH=. python benchmarks/config_objects.py

Every object made once per run is the aim (:mod:`pde_rotor.model.setup`); the body's own
schedule is the second StopSchedule of the bodies run.
"""

from __future__ import annotations

import collections
from typing import Any

import pde_rotor.model.bodies as bodies
import pde_rotor.model.body_schemes as body_schemes
import pde_rotor.model.geometry as geometry
import pde_rotor.model.protocol as protocol
import pde_rotor.model.schemes as schemes
from pde_rotor.api import run

SMALL: dict[str, Any] = {
    "grid": {"dx": 0.05, "dt": 2e-4, "domain_radius": 2.0},
    "protocol": {"t_ini": 0.01, "t_stop": 0.01, "t_release": 0.01, "cycles": 2},
    "output": {"progress": False, "timeseries_interval": 0.002, "event_interval": 0.002},
}
BOAT = {
    "name": "boat",
    "pills": [{"x": 0.0, "y": 0.0}],
    "motion": {"kind": "free", "mass": 0.5, "inertia": 0.008},
    "protocol": {"t_ini": 0.01, "t_stop": 0.01, "t_release": 0.01, "cycles": 1},
}
CLASSES = (
    (geometry, "RotorShape"),
    (protocol, "StopSchedule"),
    (schemes, "Scheme"),
    (body_schemes, "BodyScheme"),
    (bodies, "Body"),
    (bodies, "BodyShape"),
)


def count_constructors(counts: collections.Counter) -> None:
    """Make every ``from_config`` of :data:`CLASSES` add one to `counts` per call."""
    for module, name in CLASSES:
        klass = getattr(module, name)
        original = klass.__dict__["from_config"].__func__

        def counted(cls: type, *args: Any, _original: Any = original, _name: str = name) -> Any:
            counts[_name] += 1
            return _original(cls, *args)

        klass.from_config = classmethod(counted)


def main() -> None:
    counts: collections.Counter = collections.Counter()
    count_constructors(counts)
    for label, config in (("rotor", SMALL), ("bodies", {**SMALL, "bodies": [BOAT]})):
        counts.clear()
        result = run(config)
        print(f"{label:>6} run ({result.status}): {dict(sorted(counts.items()))}")


if __name__ == "__main__":
    main()
