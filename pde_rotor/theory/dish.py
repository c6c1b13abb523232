"""A camphor disk at the centre of a dish: the Hopf onset of its orbit, or its drift.

The disk of :mod:`.disk` inside a circular wall (no flow, sharp indicators). Its
displacement X exp(lambda t) obeys m lambda^2 + mu A lambda - Phi(lambda) = 0 with the
force per unit displacement Phi of :func:`~pde_rotor.theory.disk.free_disk_displacement_force`.
A no-flux wall holds the disk at the centre, which loses stability through a Hopf pair
(:func:`dish_hopf_onset`, :func:`dish_hopf_rate`; Koyano, Suematsu & Kitahata, PRE 99,
022211 (2019)); an absorbing wall pulls it away at every friction (:func:`dish_drift_rate`).
docs/bodies.md, section 2, derives each result.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.optimize import brentq

from .disk import CamphorDisk, Wall, free_disk_displacement_force


def dish_hopf_onset(disk: CamphorDisk, wall: Wall, mass: float = 0.0) -> tuple[float, float]:
    """Critical friction and frequency of the Hopf onset of a disk at the centre of a dish.

    The displacement X exp(lambda t) obeys m lambda^2 + mu A lambda - Phi(lambda) = 0
    (:func:`free_disk_displacement_force`). A no-flux wall pushes the disk back to the
    centre (Phi(0) < 0), so the rest state loses stability through lambda = +-i omega:
    Re Phi(i omega) = -m omega^2 fixes omega, mu_c = Im Phi(i omega) / (omega A). The m = 1
    mode is twofold (x and y), hence the double Hopf of Koyano, Suematsu & Kitahata.

    Args:
        disk: the disk.
        wall: the dish; its wall must hold the disk (no-flux).
        mass: m of the disk.

    Returns:
        (mu_c, omega_c).

    Raises:
        ValueError: if the wall does not restore (an absorbing wall: the centre is a
            saddle at every friction, its real root is :func:`dish_drift_rate`).
    """
    if free_disk_displacement_force(disk, 0.0, wall) >= 0:
        msg = f"a {wall.condition} wall does not hold the disk at the centre: no Hopf onset"
        raise ValueError(msg)

    def real_part(omega: float) -> float:
        return (
            float(np.real(free_disk_displacement_force(disk, 1j * omega, wall))) + mass * omega**2
        )

    omegas = np.geomspace(1e-8, 1e4, 241) * disk.evaporation
    signs = np.sign([real_part(w) for w in omegas])
    first = int(np.argmax(signs > 0))
    if signs[first] <= 0:
        msg = "no frequency found where the wall's restoring force is balanced"
        raise ValueError(msg)
    omega = brentq(real_part, omegas[first - 1], omegas[first], xtol=1e-15, rtol=1e-13)
    force = free_disk_displacement_force(disk, 1j * omega, wall)
    return float(np.imag(force)) / (omega * disk.area), float(omega)


def dish_hopf_rate(disk: CamphorDisk, wall: Wall, friction: float, mass: float = 0.0) -> complex:
    """The complex growth rate lambda = sigma + i omega of the Hopf pair at friction mu.

    The root of m lambda^2 + mu A lambda - Phi(lambda) = 0 that passes through i omega_c
    at mu_c (:func:`dish_hopf_onset`), followed from there in steps of mu_c / 400 by
    Newton's method (Phi is analytic; its derivative by a central difference): sigma > 0
    below mu_c, < 0 above, and omega the frequency of the linear orbit about the centre.
    Away from mu_c the pair can meet on the real axis and split into two real rates;
    the root followed is then one of them (omega = 0).

    Args:
        disk: the disk.
        wall: the dish (no-flux).
        friction: mu.
        mass: m of the disk.

    Returns:
        lambda.

    Raises:
        ValueError: as :func:`dish_hopf_onset`, or if Newton's method does not converge.
    """
    mu_c, omega_c = dish_hopf_onset(disk, wall, mass)

    def phi(lam: complex) -> complex:
        return complex(free_disk_displacement_force(disk, lam, wall))

    lam = 1j * omega_c
    steps = max(1, math.ceil(abs(friction - mu_c) / mu_c * 400))
    for mu in np.linspace(mu_c, friction, steps + 1)[1:]:
        lam = _newton(lambda z, mu=mu: mass * z**2 + mu * disk.area * z - phi(z), lam)
        if lam is None:
            msg = f"no Hopf root found at friction {mu:g} (mu_c = {mu_c:g})"
            raise ValueError(msg)
    return complex(lam)


def _newton(func: Callable[[complex], complex], start: complex) -> complex | None:
    """A root of the analytic `func` by Newton's method from `start` (None: no convergence)."""
    lam = start
    for _ in range(60):
        step = 1e-6 * max(abs(lam), 1.0)
        slope = (func(lam + step) - func(lam - step)) / (2 * step)
        delta = func(lam) / slope
        lam -= delta
        if abs(delta) < 1e-13 * max(abs(lam), 1.0):
            return lam
    return None


def dish_drift_rate(disk: CamphorDisk, wall: Wall, friction: float, mass: float = 0.0) -> float:
    """Largest real root of m lambda^2 + mu A lambda - Phi(lambda) = 0 (docs/bodies.md, section 2).

    With an absorbing wall (the simulator's Dirichlet circle) Phi(0) > 0: the wall pulls
    the disk off the centre at every friction, slowly when the wall is far. This is the
    rate at which a disk released at the centre drifts away.

    Args:
        disk: the disk.
        wall: the dish.
        friction: mu.
        mass: m of the disk.

    Returns:
        The largest real lambda in (0, infinity), or nan if there is none.
    """

    def chi(lam: float) -> float:
        force = float(free_disk_displacement_force(disk, lam, wall))
        return mass * lam**2 + friction * disk.area * lam - force

    lams = np.geomspace(1e-12, 1e8, 401) * disk.evaporation
    values = np.array([chi(lam) for lam in lams])
    crossings = np.nonzero(np.diff(np.sign(values)) != 0)[0]
    if crossings.size == 0:
        return math.nan
    i = int(crossings[-1])
    return float(brentq(chi, lams[i], lams[i + 1], xtol=1e-16, rtol=1e-12))
