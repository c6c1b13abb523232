"""A sweep's crowd: the ``bodies:`` list of N copies of one body, placed by a rule.

A sweep over the number of bodies cannot name a config key (the list itself changes), so
a sweep file may carry a ``crowd`` section instead of listing the bodies in its base::

    crowd:
      count: 30                       # N: an axis may vary it (axes: {crowd.count: [...]})
      body:                           # one body of a bodies: list, without its start
        plate: {shape: none}
        pills: [{radius: 0.1}]
        motion: {kind: free, friction: 0.15}
      placement: {kind: scatter, radius: 3.4, min_distance: 1.3, speed: 0.1}
      seed: 1                         # placements differ by sample: seeded (seed, sample)

``placement``:

* ``ring``: centres evenly spaced on the circle of ``radius`` about the vessel's centre,
  each moved along the circle by ``jitter`` times the even spacing times a uniform draw in
  [-1/2, 1/2] (0: exactly even), heading along the circle counter-clockwise (a boat in a
  ring channel), with ``speed`` along its heading;
* ``scatter``: centres uniform in the disk of ``radius`` about the vessel's centre, at
  least ``min_distance`` apart (drawn one by one, a draw too near an earlier centre is
  redrawn), headings uniform, with ``speed`` along the heading.

Any key of the crowd is an axis (``crowd.count``, ``crowd.body.motion.friction``); the
bodies are part of each run's resolved config, hence of its run key.
"""

from __future__ import annotations

import copy
import math
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import ConfigDict, Field

from ..config.stable import StableModel

PLACEMENT_ATTEMPTS = 10_000
"""Draws per body before a scatter placement gives up (the disk is too crowded)."""


class _Strict(StableModel):
    model_config = ConfigDict(extra="forbid")


class RingPlacement(_Strict):
    """N centres evenly spaced on a circle, heading along it counter-clockwise."""

    kind: Literal["ring"] = "ring"
    radius: float = Field(gt=0, description="radius of the circle about the vessel's centre")
    jitter: float = Field(0.0, ge=0, le=1, description="random shift, in even spacings")
    speed: float = Field(0.0, description="initial speed along the heading")


class ScatterPlacement(_Strict):
    """N centres uniform in a disk, at least min_distance apart, random headings."""

    kind: Literal["scatter"] = "scatter"
    radius: float = Field(gt=0, description="radius of the disk about the vessel's centre")
    min_distance: float = Field(0.0, ge=0, description="least distance between two centres")
    speed: float = Field(0.0, description="initial speed along the heading")


Placement = Annotated[RingPlacement | ScatterPlacement, Field(discriminator="kind")]


class CrowdSpec(_Strict):
    """N copies of one body, placed by a rule (module docstring)."""

    count: int = Field(ge=1, description="N: the number of bodies")
    body: dict[str, Any] = Field(description="one entry of a bodies: list, without start")
    placement: Placement
    seed: int = Field(0, ge=0, description="seed of the placements (with the sample index)")


class CrowdError(ValueError):
    """A crowd that cannot be placed; ``str(err)`` is one line."""


def place(crowd: CrowdSpec, centre: tuple[float, float], sample: int) -> list[dict[str, Any]]:
    """The ``bodies:`` list of `crowd` about `centre` for `sample`.

    Raises:
        CrowdError: a scatter placement that finds no room for a body (one line).
    """
    rng = np.random.default_rng([crowd.seed, sample])
    p = crowd.placement
    n = crowd.count
    if isinstance(p, RingPlacement):
        spacing = 2 * math.pi / n
        angles = spacing * (np.arange(n) + p.jitter * rng.uniform(-0.5, 0.5, n))
        xy = p.radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        headings = angles + math.pi / 2
    else:
        xy = _scatter(rng, n, p)
        headings = rng.uniform(0, 2 * math.pi, n)
    bodies = []
    for k in range(n):
        body = copy.deepcopy(crowd.body)
        body["name"] = f"{crowd.body.get('name', 'body')}{k}"
        h = float(headings[k])
        body["start"] = {
            "x": float(centre[0] + xy[k, 0]),
            "y": float(centre[1] + xy[k, 1]),
            "angle": float(math.remainder(h, 2 * math.pi)),
        }
        if p.speed:
            body["start"]["velocity"] = [p.speed * math.cos(h), p.speed * math.sin(h)]
        bodies.append(body)
    return bodies


def _scatter(rng: np.random.Generator, n: int, p: ScatterPlacement) -> np.ndarray:
    """N centres uniform in the disk of p.radius, at least p.min_distance apart."""
    xy = np.zeros((n, 2))
    for k in range(n):
        for _ in range(PLACEMENT_ATTEMPTS):
            r = p.radius * math.sqrt(rng.uniform())
            a = rng.uniform(0, 2 * math.pi)
            xy[k] = r * math.cos(a), r * math.sin(a)
            if k == 0 or np.hypot(*(xy[:k] - xy[k]).T).min() >= p.min_distance:
                break
        else:
            msg = (
                f"crowd.placement: no room for body {k} of {n} in a disk of radius "
                f"{p.radius:g} at least {p.min_distance:g} apart (enlarge radius or lower "
                "min_distance or count)"
            )
            raise CrowdError(msg)
    return xy
