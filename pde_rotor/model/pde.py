"""The rotor model as a py-pde PDE: readable numpy reference of Eqs. (eqc), (eqv), (eq_motion).

State: :class:`RotorFields`, a FieldCollection [ScalarField c, VectorField v] on the
Cartesian grid of :mod:`pde_rotor.model.domain` that also carries the rotor, phi and
omega of Eq. (eq_motion) (:class:`RotorState`): py-pde has no built-in coupling of ODEs to
fields, so the rotor travels with the fields. ``state.copy()`` copies it, py-pde's
Controller and trackers see it, and a branch of a run starts from both.

:meth:`RotorPDE.evolution_rate` and :meth:`RotorPDE.rotor_torques` are the executable
specification used by the tests; :mod:`pde_rotor.kernels.cpu` computes the same right-hand
side in one fused compiled loop from :mod:`pde_rotor.physics`.

Torque, Eq. (torque). The force that the surface exerts on the plate is the surface
tension pulling on its contour, gamma n dl (n the outward normal). Its torque is

    T = oint r x (gamma n) dl = int_Omega (x d_y gamma - y d_x gamma) dA
      = int_Omega r x grad gamma dA = -k int F r x grad c dA,

by the divergence theorem applied to the field (x gamma, ... ) and gamma = gamma0 - k c,
Eq. (surfacetension). The paper prints T = int r x (-grad gamma) dA, the opposite sign:
that torque opposes the rotation and leaves the rotor at rest
(tests/model/test_pde.py::test_torque_sign_physical_spins_up_printed_decays).
``rotor.torque = "physical"`` (default) uses the derived sign, ``"printed"`` the printed.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from pde import FieldCollection, ScalarField, VectorField
from pde.pdes.base import PDEBase

from ..config import DISH_CENTRE, ConfigError, RotorConfig
from .domain import Domain, make_domain
from .filtering import filtered_indicators
from .geometry import edge_normal_angles, pill_indicator, plate_indicator
from .rates import camphor_local_rate, flow_local_rate
from .schemes import contour_cross_grad, surface_pressure
from .setup import Setup, as_setup

BOUNDARY = {"value": 0}
"""py-pde boundary condition on the square; it never reaches an interior cell."""

TORQUE_SIGN = {"physical": -1.0, "printed": 1.0}
"""T = sign * k * int F r x grad c dA for the two torque conventions."""


@dataclass
class RotorState:
    """Rotor degrees of freedom and the rotor diagnostics of the last step.

    Attributes:
        phi: rotor angle phi [rad].
        omega: angular velocity dphi/dt.
        torque: surface tension torque T, Eq. (torque), of the last step.
        friction: friction torque -mu int F (|r|^2 omega - r x v) dA of the last step.
        stopped: whether the last step was in a stop phase.
    """

    phi: float
    omega: float
    torque: float = 0.0
    friction: float = 0.0
    stopped: bool = False

    def as_array(self) -> np.ndarray:
        """Pack for the kernel: [phi, omega, torque, friction, stopped]."""
        return np.array([self.phi, self.omega, self.torque, self.friction, float(self.stopped)])

    def update_from(self, values: np.ndarray) -> None:
        """Unpack the kernel's array (inverse of :meth:`as_array`)."""
        self.phi, self.omega, self.torque, self.friction = (float(v) for v in values[:4])
        self.stopped = bool(values[4])


class RotorFields(FieldCollection):
    """The model's state: the fields c and v, and the rotor (phi, omega, diagnostics).

    Attributes:
        rotor: the rotor's state at the fields' time.
    """

    def __init__(self, fields: Any, *args: Any, rotor: RotorState | None = None, **kwargs: Any):
        """
        Args:
            fields: the fields [c, v], as for :class:`~pde.FieldCollection`.
            *args: passed to :class:`~pde.FieldCollection`.
            rotor: the rotor state (default: at rest at phi = 0).
            **kwargs: passed to :class:`~pde.FieldCollection`.
        """
        super().__init__(fields, *args, **kwargs)
        self.rotor = rotor if rotor is not None else RotorState(phi=0.0, omega=0.0)

    def copy(self, *, label: str | None = None, dtype: Any = None) -> RotorFields:
        """A copy of the fields' data and of the rotor (not of the grid)."""
        new = super().copy(label=label, dtype=dtype)
        new.rotor = copy.copy(self.rotor)
        return new


def refuse_bodies(config: RotorConfig) -> None:
    """Refuse, in one line, a config the rotor's kernel cannot run: a ``bodies:`` list or a
    dish off the rotor's axis (``grid.domain_centre``); such configs run as
    :class:`~pde_rotor.model.surface.SurfacePDE`. Asked by :class:`RotorPDE`.

    Raises:
        ConfigError: the config has bodies or a dish centre other than the origin.
    """
    if config.bodies is not None:
        msg = (
            f"bodies: {len(config.bodies)} bodies run as SurfacePDE, not as the rotor of "
            "geometry: (Simulation chooses it)"
        )
        raise ConfigError(msg)
    if config.grid.domain_centre != DISH_CENTRE:
        msg = (
            f"grid.domain_centre = {list(config.grid.domain_centre)}: the rotor of geometry: "
            "turns at the dish centre (allowed: [0, 0]; a dish elsewhere holds bodies:)"
        )
        raise ConfigError(msg)


class RotorPDE(PDEBase):
    """Camphor rotor of Koyano et al. (Chaos 2020): Eqs. (eqc), (eqv), (eq_motion).

    Attributes:
        setup: the run's objects (:class:`~pde_rotor.model.setup.Setup`).
        config: the run configuration (all parameters).
        shape: derived rotor geometry (the setup's).
        domain: grid and loop ranges.
        scheme: discretisation of F, G and the torque (``numerics``, the setup's).
        F, G: plate and pill indicators on the grid, maintained by the solver.
    """

    check_implementation = False

    def __init__(self, run: Setup | RotorConfig):
        """
        Args:
            run: the run's setup, or its configuration (made into a setup here).

        Raises:
            ConfigError: the config has bodies (:func:`refuse_bodies`).
        """
        super().__init__()
        setup = as_setup(run)
        refuse_bodies(setup.config)
        self.setup = setup
        self.config = setup.config
        self.shape = setup.shape
        self.domain: Domain = make_domain(self.config.grid, self.shape)
        self.scheme = setup.scheme
        self.F = np.zeros(self.domain.grid.shape)
        self.G = np.zeros(self.domain.grid.shape)

    def initial_state(self) -> RotorFields:
        """c = 0, v = 0, phi(0) and dphi/dt(0) of the config: the paper's initial condition."""
        grid = self.domain.grid
        rotor = RotorState(phi=self.config.rotor.phi0, omega=self.config.rotor.omega0)
        return RotorFields(
            [ScalarField(grid, label="c"), VectorField(grid, label="v")],
            label="rotor state",
            rotor=rotor,
        )

    def cell_coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) of every cell centre, each of shape (n, n)."""
        coords = self.domain.coords
        return np.meshgrid(coords, coords, indexing="ij")

    def indicators(self, phi: float) -> tuple[np.ndarray, np.ndarray]:
        """F and G of every cell with numpy (reference for the compiled update).

        Point values at the cell centres (scheme ``paper``) or the Gaussian-filtered
        fields of scheme ``consistent`` (:mod:`pde_rotor.model.filtering`), the latter from
        the filter tables with scipy's spline and numpy's linear interpolation.
        """
        x, y = self.cell_coordinates()
        tables = self.scheme.tables
        if tables is None:
            return plate_indicator(x, y, self.shape, phi), pill_indicator(x, y, self.shape, phi)
        return filtered_indicators(tables, self.shape, x, y, phi)

    def evolution_rate(self, state: RotorFields, t: float = 0) -> FieldCollection:
        """Right-hand sides of Eqs. (eqc) and (eqv) at the state's rotor (numpy).

        The flow term uses omega = ``state.rotor.omega`` (0 during a stop). Cells on and
        outside the circle of radius L keep c = v = 0.
        """
        cfg = self.config
        c, v = state
        rotor = state.rotor
        F, G = self.indicators(rotor.phi)
        mask = self.domain.interior_mask
        source = cfg.camphor.supply / (math.pi * cfg.geometry.pill_radius**2) * G
        c_rate = cfg.camphor.diffusion * c.laplace(BOUNDARY).data + camphor_local_rate(
            cfg.camphor, c.data, F, source
        )
        v_rate = np.zeros_like(v.data)
        if cfg.flow.enabled:
            c_rate -= (c * v).divergence(BOUNDARY).data
            x, y = self.cell_coordinates()
            plate_flow = F * rotor.omega * np.stack([-y, x])
            v_rate = flow_local_rate(cfg.flow, v.data, F, plate_flow)
            v_rate += cfg.flow.viscosity * v.laplace(BOUNDARY).data
        grid = self.domain.grid
        return FieldCollection([ScalarField(grid, c_rate * mask), VectorField(grid, v_rate * mask)])

    def rotor_torques(self, state: RotorFields) -> tuple[float, float]:
        """Torque T, Eq. (torque), and friction torque of Eq. (eq_motion) (numpy).

        The torque's integral int F r x grad c dA is taken in the scheme's form: area
        form with central differences (``paper``) or contour form (``consistent``).

        Returns:
            (T, -mu int F (|r|^2 omega - r x v) dA) at the state's rotor.
        """
        cfg = self.config
        c, v = state
        rotor = state.rotor
        F, _ = self.indicators(rotor.phi)
        x, y = self.cell_coordinates()
        area = self.domain.cell_area
        if self.scheme.contour:
            normals = edge_normal_angles(self.shape.n_corners, rotor.phi)
            cross_grad = contour_cross_grad(
                c.data,
                float(self.domain.coords[0]),
                self.domain.dx,
                self.scheme,
                normals,
                self.shape.apothem,
                self.shape.smoothing,
                cfg.camphor,
            )
        else:
            pressure = ScalarField(c.grid, surface_pressure(c.data, cfg.camphor))
            grad = pressure.gradient(BOUNDARY).data
            cross_grad = np.sum(F * (x * grad[1] - y * grad[0])) * area
        torque = TORQUE_SIGN[cfg.rotor.torque] * cfg.camphor.tension_slope * cross_grad
        cross_v = np.sum(F * (x * v.data[1] - y * v.data[0])) * area if cfg.flow.enabled else 0.0
        moment = np.sum(F * (x**2 + y**2)) * area
        friction = -cfg.rotor.friction * (moment * rotor.omega - cross_v)
        return float(torque), float(friction)

    def solve(
        self,
        state: RotorFields,
        t_range: float | tuple[float, float],
        dt: float | None = None,
        tracker: Any = "auto",
        *,
        solver: Any = "rotor",
        **kwargs: Any,
    ) -> Any:
        """Solve with py-pde's solver ``rotor`` (:class:`~pde_rotor.solver.rotor.RotorSolver`).

        Arguments as for py-pde's ``PDEBase.solve``; `dt` defaults to ``grid.dt``. The
        solver is found in py-pde's registry by name (``SolverBase.from_name``), where
        importing :mod:`pde_rotor.solver` registers it; it advances phi and omega with
        the fields.

        Raises:
            ValueError: for any other solver: py-pde's generic solvers advance only the
                fields and would leave the rotor frozen at its current angle.
        """
        if solver != "rotor" and getattr(solver, "name", None) != "rotor":
            msg = (
                f"solver {solver!r} would leave the rotor frozen; RotorPDE is solved by "
                "RotorSolver (solver='rotor'), which advances phi and omega with the fields"
            )
            raise ValueError(msg)
        if dt is None:
            dt = self.config.grid.dt
        return super().solve(state, t_range, dt, tracker, solver="rotor", **kwargs)
