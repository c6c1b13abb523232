"""Assemble and run one simulation: config -> model -> solver -> py-pde Controller.

This is the single entry point that the CLI, sweeps and gallery use to run the model.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pde
from pde import Controller
from pde.trackers.base import TrackerBase

from ..config import RotorConfig
from ..model.pde import RotorFields, RotorPDE, RotorState
from ..model.setup import Setup, as_setup
from ..model.surface import BodiesState, SurfaceFields, SurfacePDE
from .bodies import make_bodies_stepper
from .rotor import RotorSolver, StepperFactory, make_fused_stepper

pde.config["backend.numba.multithreading"] = "never"
"""py-pde's own threading is 50x slower on 2 shared cores above 256^2 cells; the fused
kernel runs its own threads (``solver.threads``), so py-pde must never switch threads on
by itself."""


class Simulation:
    """One run of the model: the PDE, its state, the fused solver and the time reached.

    Attributes:
        setup: the run's objects (:class:`~pde_rotor.model.setup.Setup`), which the PDE,
            the stepper and the trackers read.
        config: the run configuration.
        pde: the model (parameters, domain, scheme).
        state: the fields c and v with the rotor's phi and omega
            (:class:`~pde_rotor.model.pde.RotorFields`).
        solver: the fused :class:`RotorSolver`.
        t: simulated time reached.
    """

    def __init__(
        self,
        run: Setup | RotorConfig,
        rng: np.random.Generator | None = None,
        stepper: StepperFactory | None = None,
    ):
        """
        Args:
            run: the run's setup, or its configuration (validated; made into a setup
                here).
            rng: Generator for the noise; default: seeded from ``config.noise.seed``.
            stepper: what advances the run (:class:`RotorSolver`): the fused CPU kernel
                by default (the rotor's, or with ``bodies:`` the bodies'
                :func:`~pde_rotor.solver.bodies.make_bodies_stepper`);
                :func:`pde_rotor.backends.member_stepper` for a GPU run (with bodies
                :func:`pde_rotor.backends.gpu_bodies.gpu_bodies_stepper`).
        """
        self.setup = setup = as_setup(run)
        self.config = config = setup.config
        self.pde: RotorPDE | SurfacePDE
        if config.bodies is None:
            self.pde = RotorPDE(setup)
            default: StepperFactory = make_fused_stepper
        else:
            self.pde = SurfacePDE(setup)
            default = make_bodies_stepper
        self.state: RotorFields | SurfaceFields = self.pde.initial_state()
        self.solver = RotorSolver(self.pde, rng=rng, stepper=stepper or default)
        self.t = 0.0

    def branch(
        self, run: Setup | RotorConfig | None = None, rng: np.random.Generator | None = None
    ) -> Simulation:
        """A new simulation that starts from this one's fields, rotor state and time.

        Args:
            run: setup or configuration of the branch (default: this one's setup); it
                must describe the same grid.
            rng: Generator for the branch's noise (default: from ``config.noise.seed``).

        Raises:
            ValueError: if the grids differ.
        """
        other = Simulation(run or self.setup, rng=rng, stepper=self.solver.make_member)
        if other.pde.domain.grid != self.pde.domain.grid:
            msg = "branch: the configuration describes a different grid (grid.*)"
            raise ValueError(msg)
        other.state = self.state.copy()  # the rotor travels with the fields
        other.t = self.t
        return other

    @property
    def rotor(self) -> RotorState:
        """The rotor state (phi, omega, torque, friction, stopped) of :attr:`state`."""
        return self.state.rotor

    @property
    def bodies(self) -> BodiesState:
        """The bodies' state (poses, velocities, forces) of a run with ``bodies:``."""
        return self.state.bodies

    def run(self, t_end: float | None = None, trackers: Sequence[TrackerBase] = ()) -> None:
        """Advance from the current time to `t_end` (default: end of the protocol).

        py-pde's Controller drives the fused stepper and calls the trackers.
        """
        if t_end is None:
            t_end = self.config.protocol.t_end
        if t_end <= self.t:
            return
        controller = Controller(self.solver, t_range=(self.t, t_end), tracker=list(trackers))
        # the Controller evolves a copy of the state: keep its result, also when a step
        # raises (SimulationDivergedError names the time of the failing state it leaves)
        try:
            self.state = controller.run(self.state, dt=self.config.grid.dt)
        except Exception:
            self.state = controller.diagnostics.get("last_state", self.state)
            raise
        self.t = float(controller.info["t_final"])
