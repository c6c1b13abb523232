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
turning body, x, y, U of a free one, and the arc position s and arc speed w of a
``track`` body. Fixed bodies have none. The plate and pill indicators of a pose are
cached, so a linear probe costs one evaluation of the field operators.

**Track bodies.** A track body has one degree of freedom, its angle theta about the
track's centre C (:mod:`pde_rotor.model.motion`): X = C + R e_r(theta), phi = theta + d
pi/2 (its start heading plus theta - theta0), U = w e_theta, omega = w / R. Its coordinate
here is the arc position s = R (theta - theta0) from its start, not theta itself, so that
ds/dt = w is its velocity, as dq/dt = p for every other coordinate (the block [0, 1] of
the linearisation's small matrix holds as it is), its inertia is the mass m of m dw/dt =
(f + f_fr + f_ext + f_contact) . e_theta + d f_t, and its finite-difference step is a
length like a free body's. Moving s moves the plate's position and heading together, and
w drags the flow with the plate's rigid velocity w e_theta and turning w / R.

The accelerations are the reference's own (:func:`pde_rotor.model.motion.accelerations`
with :func:`~pde_rotor.model.motion.contact_forces`): tension, friction, the external
loads and the contact's springs and dashpots (0 where no gap is in range, as between
evenly spaced boats at rest).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from pde import CartesianGrid, ScalarField, VectorField

from ..config import DISH_CENTRE, RotorConfig
from ..model.motion import Inertia, accelerations, contact_forces
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


POSE_VELOCITY = {"x": "u", "y": "v", "phi": "omega", "s": "w"}
"""The velocity of each coordinate of a body's pose (columns of
:data:`pde_rotor.model.surface.POSE_COLUMNS`; a track body's arc position s and arc
speed w, not columns, set its pose by :meth:`DiscreteModel.state`)."""
POSE_INDEX = {"x": 0, "y": 1, "phi": 2, "u": 3, "v": 4, "omega": 5}


@dataclass(frozen=True)
class Dof:
    """One mechanical degree of freedom: a body's coordinate and its velocity.

    Attributes:
        body: the body's index (0 for the paper's rotor).
        name: the body's name.
        coordinate: ``x``, ``y``, ``phi`` or ``s`` (a track body's arc position).
        inertia: m (x, y, s) or I (phi), the coefficient of its equation of motion.
    """

    body: int
    name: str
    coordinate: str
    inertia: float

    @property
    def velocity(self) -> str:
        """``u``, ``v``, ``omega`` or ``w``."""
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
        kinds = {"fixed": (), "fixed_axis": ("phi",), "free": ("x", "y", "phi"), "track": ("s",)}
        for k, body in enumerate(self.pde.bodies):
            for name in kinds[body.motion]:
                inertia = body.inertia if name == "phi" else body.mass
                dofs.append(Dof(k, body.name, name, float(inertia)))
                q0.append(0.0 if name == "s" else body.start[POSE_INDEX[name]])
        return tuple(dofs), np.array(q0, dtype=float)

    @cached_property
    def inertia(self) -> Inertia:
        """The bodies' motion parameters, as the reference's step reads them."""
        return Inertia.of(self.pde.bodies)

    def track_pose(self, k: int, s: float, w: float) -> tuple[float, ...]:
        """(x, y, phi, u, v, omega) of track body `k` at arc position `s` from its start
        and arc speed `w` (module docstring)."""
        body = self.pde.bodies[k]
        (cx, cy), radius = body.track.centre, body.track.radius
        x0, y0, phi0 = body.start
        theta = math.atan2(y0 - cy, x0 - cx) + s / radius
        cos_t, sin_t = math.cos(theta), math.sin(theta)
        return (
            cx + radius * cos_t,
            cy + radius * sin_t,
            phi0 + s / radius,
            -w * sin_t,
            w * cos_t,
            w / radius,
        )

    def arc_coordinates(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(s, w) of every degree of freedom's body at `poses` (K, >= 6), for the track
        ones (the inverse of :meth:`track_pose`; s in (-pi R, pi R]); nan elsewhere."""
        theta, _, speed = self.inertia.tangents(poses)
        s, w = np.full(len(self.dofs), np.nan), np.full(len(self.dofs), np.nan)
        for i, dof in enumerate(self.dofs):
            if dof.coordinate == "s":
                body = self.pde.bodies[dof.body]
                (cx, cy), radius = body.track.centre, body.track.radius
                theta0 = math.atan2(body.start.y - cy, body.start.x - cx)
                s[i] = radius * math.remainder(theta[dof.body] - theta0, 2 * math.pi)
                w[i] = speed[dof.body]
        return s, w

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
            if dof.coordinate == "s":
                poses[dof.body, :6] = self.track_pose(dof.body, float(q[i]), float(p[i]))
                continue
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
        torque of the scheme plus the friction (and the external and contact loads of a
        bodies' config), over m or I; a track body's tangential acceleration dw/dt."""
        state = self.state(c, v, q, p)
        if self.rotor:
            torque, friction = self.pde.rotor_torques(state)
            return np.array([(torque + friction) / self.dofs[0].inertia])
        poses = state.bodies.poses[:, :6]
        contact = contact_forces(poses, self.pde.bodies, self.config)
        accel = accelerations(self.pde.body_forces(state), self.inertia, poses, contact)
        _, tangent, _ = self.inertia.tangents(poses)
        column = {"x": 0, "y": 1, "phi": 2}
        out = np.empty(len(self.dofs))
        for i, dof in enumerate(self.dofs):
            if dof.coordinate == "s":
                out[i] = accel[dof.body, :2] @ tangent[dof.body]
            else:
                out[i] = accel[dof.body, column[dof.coordinate]]
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
