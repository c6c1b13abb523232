"""Fused explicit solver for c, v, phi and omega (py-pde SolverBase subclass).

:class:`FusedStepper` binds the compiled fused step (:func:`pde_rotor.kernels.cpu.advance`:
Eqs. (eqc), (eqv), (eq_motion) and (torque), forward Euler or Heun, the noise of
Eq. (noiseav) by Euler-Maruyama) to one simulation's arrays, parameters and stop
schedule, and reports a state that stops being finite with the time and the field.

:class:`RotorSolver` plugs the loop into py-pde through ``SolverBase._make_inner_stepper``
(py-pde has no built-in coupling of ODEs to fields): py-pde selects
the backend, calls the PDE's post-step hook if it has one, and its Controller and
trackers drive the run unchanged.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from pde import FieldCollection
from pde.solvers.base import SolverBase

from ..kernels.cpu import advance
from ..kernels.records import make_record
from ..model.pde import RotorFields, RotorPDE, RotorState
from ..model.surface import SurfaceFields, SurfacePDE
from .threads import resolve_threads, running_on


class SimulationDivergedError(FloatingPointError):
    """Raised when the state stops being finite (NaN/Inf); says where and when."""


@dataclass
class FusedStepper:
    """The compiled kernel bound to one simulation's arrays and parameters.

    Attributes:
        pde: the model (parameters, domain, rotor state).
        dt: time step.
        rng: numpy Generator for the noise; one standard normal is drawn per step, in
            step order, so a run is reproducible whatever the tracker intervals.
        threads: threads the steps use (``solver.threads`` resolved,
            :func:`~pde_rotor.solver.threads.resolve_threads`); the result does not
            depend on it.
    """

    pde: RotorPDE
    dt: float
    rng: np.random.Generator
    threads: int = field(init=False)
    _spare: np.ndarray = field(init=False, repr=False)
    _stage: np.ndarray = field(init=False, repr=False)
    _record: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.threads = resolve_threads(self.pde.config.solver.threads)
        self._record = make_record(self.pde.setup.at(self.dt))
        self._spare = np.zeros((3, *self.pde.domain.grid.shape))
        heun = self.pde.config.numerics.integrator == "heun"
        self._stage = np.zeros_like(self._spare) if heun else np.empty(0)

    def normals(self, n_steps: int) -> np.ndarray:
        """The standard normals of the noise, one per step (none without noise); the
        kernel scales them to the Euler-Maruyama kicks of Eq. (noiseav)."""
        if self._record["kick"][0] == 0.0:
            return np.empty(0)
        return self.rng.standard_normal(n_steps)

    def __call__(self, data: np.ndarray, rotor_state: RotorState, step0: int, n_steps: int) -> None:
        """Advance `data` and `rotor_state` together by `n_steps` steps from step `step0`.

        Raises:
            SimulationDivergedError: when the state becomes NaN/Inf, naming the time and field.
        """
        pde = self.pde
        dom = pde.domain
        scheme = pde.scheme
        rotor = rotor_state.as_array()
        work = data if data.flags.c_contiguous else np.ascontiguousarray(data)
        with running_on(self.threads):
            failed = advance(
                (work.reshape(-1), self._spare.reshape(-1), self._stage.reshape(-1)),
                (pde.F.reshape(-1), pde.G.reshape(-1)),
                dom.arrays(),
                self._record,
                scheme.kernel_tables(),
                rotor,
                self.normals(n_steps),
                (step0, n_steps),
                self.threads,
            )
        if work is not data:
            data[...] = work
        rotor_state.update_from(rotor)
        if failed >= 0:
            self._diverged((step0 + failed) * self.dt, data, rotor)
        if not np.isfinite(data).all():
            self._diverged((step0 + n_steps) * self.dt, data, rotor)

    def _diverged(self, t: float, data: np.ndarray, rotor: np.ndarray) -> None:
        names = ["c", "v_x", "v_y"]
        bad = [name for name, arr in zip(names, data, strict=True) if not np.isfinite(arr).all()]
        if not np.isfinite(rotor[:2]).all():
            bad.append("phi/omega")
        where = ", ".join(bad) if bad else "torque"
        config = self.pde.config
        unusual = config.far_from_paper()
        cause = (
            f"likely cause: {'; '.join(unusual[:3])}; "
            if unusual
            else "a large flow can violate the advection limit dt <= 2 D / |v|^2; "
        )
        msg = (
            f"simulation diverged at t = {t:.6g}: non-finite {where} ({cause}"
            f"dt = {self.dt:g}, stability limit {config.dt_limit():.4g})"
        )
        raise SimulationDivergedError(msg)


MemberStepper = Callable[[np.ndarray, RotorState, int, int], None]
"""``step(data, rotor, step0, n_steps)``: advance the fields `data` (3, n, n) and the rotor
in place by `n_steps` steps from step `step0`; raise SimulationDivergedError on NaN/Inf."""
StepperFactory = Callable[[RotorPDE, float, np.random.Generator], MemberStepper]
"""``factory(pde, dt, rng)``: the stepper of one run, bound to its model, step and noise."""


def make_fused_stepper(pde: RotorPDE, dt: float, rng: np.random.Generator) -> FusedStepper:
    """Bind the compiled fused CPU kernel to `pde` (see :class:`FusedStepper`)."""
    return FusedStepper(pde=pde, dt=dt, rng=rng)


class RotorSolver(SolverBase):
    """py-pde solver that advances the rotor model with the fused compiled kernel.

    It supplies ``_make_inner_stepper``, the hook through which py-pde's generic backend
    runs a solver: :meth:`SolverBase.make_stepper` records dt, selects the backend and
    asks it for the stepper, which calls the inner stepper from tracker time to tracker
    time. The rotor state travels with the fields (``state.rotor`` of
    :class:`~pde_rotor.model.pde.RotorFields`) and is advanced in the same compiled
    loop as the fields, every step. If the PDE defines a post-step hook
    (``make_post_step_hook``), it is called after every step.
    """

    name = "rotor"

    def __init__(
        self,
        pde: RotorPDE | SurfacePDE,
        *,
        backend: str = "auto",
        rng: np.random.Generator | None = None,
        stepper: StepperFactory = make_fused_stepper,
    ):
        """
        Args:
            pde: the rotor model, or the bodies' (:class:`~pde_rotor.model.surface.SurfacePDE`,
                with `stepper` :func:`pde_rotor.solver.bodies.make_bodies_stepper`).
            backend: py-pde backend; ``auto`` and ``numpy`` both run the fused kernel
                through py-pde's generic stepper (the kernel compiles itself with numba).
            rng: Generator for the torque noise; by default seeded from
                ``pde.config.noise.seed``.
            stepper: what advances the run between the Controller's interrupts: the
                fused CPU kernel (default), or one member of an ensemble backend
                (:func:`pde_rotor.backends.member_stepper`, a run on the GPU). Either way
                py-pde's Controller drives the run and calls the same trackers.

        Raises:
            ValueError: for a py-pde backend that does not go through
                ``_make_inner_stepper`` (numba, jax, torch: they compile py-pde's own
                operators, which this model does not use).
        """
        if backend not in ("auto", "numpy"):
            msg = (
                f"RotorSolver runs its own compiled kernel and takes backend 'auto' or "
                f"'numpy', not {backend!r}"
            )
            raise ValueError(msg)
        # "numpy": py-pde's generic stepper, which calls the kernel; "auto" would first
        # try to compile py-pde's own operators and log a failure for each backend
        super().__init__(pde, backend="numpy")
        self.pde: RotorPDE | SurfacePDE = pde
        seed = pde.config.noise.seed
        self.rng = rng if rng is not None else np.random.default_rng(seed)
        self.make_member = stepper

    def make_stepper(
        self, state: FieldCollection, dt: float | None = None
    ) -> Callable[[FieldCollection, float, float], float]:
        """Return stepper(state, t_start, t_end) -> t advancing by whole steps of dt.

        Args:
            state: the state the stepper will advance (its grid must be the model's).
            dt: time step (default: ``grid.dt`` of the configuration).

        Raises:
            ValueError: if dt exceeds the explicit stability limit (before any step).
        """
        if not isinstance(state, RotorFields | SurfaceFields):
            msg = (
                "RotorSolver advances the rotor with the fields: give it a state of "
                "RotorPDE.initial_state() (RotorFields) or SurfacePDE.initial_state() "
                "(SurfaceFields), not a plain FieldCollection"
            )
            raise TypeError(msg)
        if dt is None:
            dt = self.pde.config.grid.dt
        limit = self.pde.config.dt_limit()
        if dt > limit:
            msg = f"dt = {dt:g} exceeds the explicit stability limit {limit:.4g}"
            raise ValueError(msg)
        stepper = super().make_stepper(state, dt)
        self.info["stochastic"] = self.pde.config.noise.sigma > 0
        kind = "rotor" if isinstance(self.pde, RotorPDE) else f"{len(self.pde.bodies)} bodies"
        self.info["kernel"] = f"numba fused {kind} kernel, scheme {self.pde.scheme.name}"
        return stepper

    def _make_inner_stepper(self, state: FieldCollection) -> Callable[[Any, float, float], float]:
        """The backend-level stepper: state data, t_start, t_end -> t after whole steps."""
        dt = float(self.info["dt"])
        fused = self.make_member(self.pde, dt, self.rng)
        post_step_hook = self._make_post_step_hook(state)
        # the Controller's state: the stepper advances its rotor (or bodies) with the data
        rotor = state.rotor if isinstance(state, RotorFields) else state.bodies
        hooked = self.info["post_step_data"] is not None

        def inner_stepper(state_data: np.ndarray, t_start: float, t_end: float) -> float:
            step0 = round(t_start / dt)
            n_steps = max(1, round((t_end - t_start) / dt))
            if hooked:
                for step in range(step0, step0 + n_steps):
                    fused(state_data, rotor, step, 1)
                    data, self.info["post_step_data"] = post_step_hook(
                        state_data, step * dt, self.info["post_step_data"]
                    )
                    state_data[...] = data
            else:
                fused(state_data, rotor, step0, n_steps)
            self.info["steps"] += n_steps
            return (step0 + n_steps) * dt

        return inner_stepper
