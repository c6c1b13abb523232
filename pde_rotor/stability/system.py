"""The discrete model as functions of its unknowns: the rates the stability analysis linearises.

The solver steps Eqs. (eqc), (eqv) and (eq_motion) on the grid; their numpy reference is
:class:`pde_rotor.model.pde.RotorPDE` (the paper's rotor, a config without ``bodies``) or
:class:`pde_rotor.model.surface.SurfacePDE` (a ``bodies:`` list). :class:`DiscreteModel`
wraps the reference of a config and evaluates, at any camphor field c, flow v, body
coordinates q and body velocities p:

* :meth:`DiscreteModel.field_rates`: dc/dt and dv/dt on the grid, Eqs. (eqc) and (eqv);
* :meth:`DiscreteModel.accelerations`: dp/dt of every moving body's velocity, Eq.
  (eq_motion): (tension + friction force) / m and (torque + friction torque) / I.

The unknowns of the linearisation are c on the cells that hold camphor, the two
components of v on the dish's interior (with flow only), and the moving bodies'
coordinates and velocities (:class:`Dof`): the angle phi and angular velocity omega of a
turning body, and x, y, U of a free one. Fixed bodies have none. The plate and pill
indicators of a pose are cached, so a linear probe costs one evaluation of the field
operators.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from pde import CartesianGrid, ScalarField, VectorField

from ..config import DISH_CENTRE, ConfigError, RotorConfig
from ..model.pde import RotorFields, RotorPDE, RotorState
from ..model.setup import Setup, as_setup
from ..model.surface import POSE_COLUMNS, BodiesState, SurfaceFields, SurfacePDE

_GRIDS: dict[tuple, CartesianGrid] = {}
"""One py-pde grid per grid geometry: py-pde compiles its operators per grid object, and a
continuation builds a model per value."""


def _share_grid(pde: RotorPDE | SurfacePDE) -> None:
    """Give `pde` the grid object of an earlier model on the same grid (its compiled
    Laplacian, divergence and gradient with it)."""
    grid = pde.domain.grid
    key = (type(grid).__name__, np.asarray(grid.axes_bounds).tobytes(), grid.shape)
    pde.domain = replace(pde.domain, grid=_GRIDS.setdefault(key, grid))


POSE_VELOCITY = {"x": "u", "y": "v", "phi": "omega"}
"""The velocity of each coordinate of a body's pose (columns of
:data:`pde_rotor.model.surface.POSE_COLUMNS`)."""
POSE_INDEX = {"x": 0, "y": 1, "phi": 2, "u": 3, "v": 4, "omega": 5}


@dataclass(frozen=True)
class Dof:
    """One mechanical degree of freedom: a body's coordinate and its velocity.

    Attributes:
        body: the body's index (0 for the paper's rotor).
        name: the body's name.
        coordinate: ``x``, ``y`` or ``phi``.
        inertia: m (x, y) or I (phi), the coefficient of its equation of motion.
    """

    body: int
    name: str
    coordinate: str
    inertia: float

    @property
    def velocity(self) -> str:
        """``u``, ``v`` or ``omega``."""
        return POSE_VELOCITY[self.coordinate]

    @property
    def label(self) -> str:
        """e.g. ``body0.omega``."""
        return f"{self.name}.{self.velocity}"


class DiscreteModel:
    """The right-hand side of the discrete model of a config (see the module docstring).

    Attributes:
        config: the configuration.
        pde: its numpy reference (RotorPDE or SurfacePDE).
        rotor: whether it is the paper's rotor (RotorPDE).
        flow: whether Eq. (eqv) is solved (``flow.enabled``).
        dofs: the moving bodies' degrees of freedom.
        q0: (m,) the coordinates of the rest pose (the bodies' start).
        c_mask, v_mask: (n, n) cells that hold c and v.
    """

    def __init__(self, run: Setup | RotorConfig):
        """
        Args:
            run: any valid config (the shorthand rotor or ``bodies:``), or its setup
                (:class:`~pde_rotor.model.setup.Setup`; made here once from a config).
        """
        setup = as_setup(run)
        self.config = config = setup.config
        self.rotor = config.bodies is None and config.grid.domain_centre == DISH_CENTRE
        self.pde: RotorPDE | SurfacePDE = RotorPDE(setup) if self.rotor else SurfacePDE(setup)
        _share_grid(self.pde)
        self.flow = bool(config.flow.enabled)
        domain = self.pde.domain
        self.c_mask = np.asarray(getattr(domain, "camphor_mask", domain.interior_mask))
        self.v_mask = np.asarray(domain.interior_mask)
        self.dofs, self.q0 = self._dofs()
        self._cache: dict[bytes, object] = {}
        self._install_cache()

    def _dofs(self) -> tuple[tuple[Dof, ...], np.ndarray]:
        if self.rotor:
            inertia = self.config.rotor.inertia
            return (Dof(0, "body0", "phi", inertia),), np.array([self.config.rotor.phi0])
        dofs, q0 = [], []
        for k, body in enumerate(self.pde.bodies):
            if body.motion == "track":
                msg = (
                    f"bodies[{k}].motion.kind = track: the linear analysis takes fixed, "
                    "fixed_axis and free bodies (allowed: one of those)"
                )
                raise ConfigError(msg)
            names = {"fixed": (), "fixed_axis": ("phi",), "free": ("x", "y", "phi")}[body.motion]
            for name in names:
                inertia = body.inertia if name == "phi" else body.mass
                dofs.append(Dof(k, body.name, name, float(inertia)))
                q0.append(body.start[POSE_INDEX[name]])
        return tuple(dofs), np.array(q0, dtype=float)

    def _install_cache(self) -> None:
        """Cache the indicators per pose: the probes of a linearisation share one pose."""
        pde = self.pde
        if self.rotor:
            compute = pde.indicators

            def indicators(phi: float) -> tuple[np.ndarray, np.ndarray]:
                key = np.float64(phi).tobytes()
                if key not in self._cache:
                    self._cache.clear()
                    self._cache[key] = compute(phi)
                return self._cache[key]

            pde.indicators = indicators
            return
        compute_fields = pde.body_fields

        def body_fields(state: BodiesState) -> list[tuple[np.ndarray, np.ndarray]]:
            key = np.ascontiguousarray(state.poses[:, :3]).tobytes()
            if key not in self._cache:
                self._cache.clear()
                self._cache[key] = compute_fields(state)
            return self._cache[key]

        pde.body_fields = body_fields

    @property
    def shape(self) -> tuple[int, int]:
        """The grid's (n, n)."""
        return self.pde.domain.grid.shape

    @property
    def cell_area(self) -> float:
        """dx^2."""
        return self.pde.domain.cell_area

    @cached_property
    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) of every cell centre, (n, n) each, in the frame of the bodies' poses."""
        return self.pde.cell_coordinates()

    def state(self, c: np.ndarray, v: np.ndarray, q: np.ndarray, p: np.ndarray):
        """The reference's state (fields and bodies) for grid arrays c (n, n), v (2, n, n)
        and the degrees of freedom's coordinates q and velocities p."""
        grid = self.pde.domain.grid
        fields = [ScalarField(grid, c, label="c"), VectorField(grid, v, label="v")]
        if self.rotor:
            rotor = RotorState(phi=float(q[0]), omega=float(p[0]))
            return RotorFields(fields, rotor=rotor)
        bodies = self.pde.bodies
        poses = np.zeros((len(bodies), len(POSE_COLUMNS)))
        for k, body in enumerate(bodies):
            poses[k, :3] = body.start
        for i, dof in enumerate(self.dofs):
            poses[dof.body, POSE_INDEX[dof.coordinate]] = q[i]
            poses[dof.body, POSE_INDEX[dof.velocity]] = p[i]
        names = tuple(b.name for b in bodies)
        return SurfaceFields(fields, bodies=BodiesState(names, poses))

    def field_rates(
        self, c: np.ndarray, v: np.ndarray, q: np.ndarray, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """dc/dt (n, n) and dv/dt (2, n, n), Eqs. (eqc) and (eqv), of the reference."""
        rate = self.pde.evolution_rate(self.state(c, v, q, p))
        return rate[0].data, rate[1].data

    def accelerations(
        self, c: np.ndarray, v: np.ndarray, q: np.ndarray, p: np.ndarray
    ) -> np.ndarray:
        """(m,) dp/dt of every degree of freedom, Eq. (eq_motion): the tension force or
        torque of the scheme plus the friction, over m or I."""
        state = self.state(c, v, q, p)
        if self.rotor:
            torque, friction = self.pde.rotor_torques(state)
            return np.array([(torque + friction) / self.dofs[0].inertia])
        forces = self.pde.body_forces(state)
        column = {"x": 0, "y": 1, "phi": 2}
        out = np.empty(len(self.dofs))
        for i, dof in enumerate(self.dofs):
            j = column[dof.coordinate]
            out[i] = (forces[dof.body, j] + forces[dof.body, j + 3]) / dof.inertia
        return out

    def source_total(self) -> float:
        """sum over the pills of s_j (1 + pi^2 delta^2 / (12 rho_j^2)): the integral of the
        pill sources of Eq. (eqc) for tanh edges of width delta (docs/numerics.md)."""
        delta = self.config.geometry.smoothing
        if self.rotor:
            geo = self.config.geometry
            per_pill = 1 + math.pi**2 * delta**2 / (12 * geo.pill_radius**2)
            return geo.n_corners * self.config.camphor.supply * per_pill
        total = 0.0
        for body in self.pde.bodies:
            for _, _, rho, supply in body.shape.pills:
                total += supply * (1 + math.pi**2 * delta**2 / (12 * rho**2))
        return total

    def camphor_total(self, c: np.ndarray) -> float:
        """The camphor in the dish (volume fractions behind a no-flux wall)."""
        return self.pde.domain.camphor_total(c)

    def plate_indicator(self, q: np.ndarray) -> np.ndarray:
        """sum_k F_k of the bodies at coordinates q, on the grid (the scheme's F)."""
        if self.rotor:
            return self.pde.indicators(float(q[0]))[0]
        state = self.state(np.zeros(self.shape), np.zeros((2, *self.shape)), q, 0 * q)
        return sum(f for f, _ in self.pde.body_fields(state.bodies))
