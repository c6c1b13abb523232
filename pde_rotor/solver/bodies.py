"""The compiled step of K bodies bound to one simulation (the CPU stepper of SurfacePDE).

:class:`BodiesStepper` binds :func:`pde_rotor.kernels.bodies.advance_bodies` to one
simulation's arrays, parameter records and noise, in the form every stepper of
:class:`pde_rotor.solver.rotor.RotorSolver` has, ``step(data, bodies, step0, n_steps)``;
py-pde's Controller drives it as it drives the rotor's fused step. A run that goes
wrong stops with the time, the body and the reason: a non-finite state, a body at the
dish's edge (the run ends: the dish has no wall force; docs/bodies.md), two bodies
touching.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..kernels.bodies import STATUS_EDGE, STATUS_OVERLAP, advance_bodies
from ..kernels.records import make_body_records, make_body_tables, make_record
from ..kernels.wall import NO_WALL
from ..model.surface import BodiesState, SurfacePDE
from .rotor import SimulationDivergedError


class BodyContactError(RuntimeError):
    """Raised when a body reaches the dish's edge or another body; says which and when."""


@dataclass
class BodiesStepper:
    """The compiled step of the bodies bound to one simulation.

    Attributes:
        pde: the model (parameters, bodies, domain).
        dt: time step.
        rng: numpy Generator for the noise: K standard normals per step, in step order.
    """

    pde: SurfacePDE
    dt: float
    rng: np.random.Generator
    _record: np.ndarray = field(init=False, repr=False)
    _stage: np.ndarray = field(init=False, repr=False)
    _bodies: np.ndarray = field(init=False, repr=False)
    _pills: np.ndarray = field(init=False, repr=False)
    _spare: np.ndarray = field(init=False, repr=False)
    _normals: np.ndarray = field(init=False, repr=False)
    _centres: np.ndarray = field(init=False, repr=False)
    _tables: tuple[np.ndarray, ...] = field(init=False, repr=False)
    _wall: tuple[np.ndarray, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        pde = self.pde
        setup = pde.setup.at(self.dt)
        self._record = make_record(setup)
        self._bodies, self._pills = make_body_records(setup)
        self._spare = np.zeros((3, *pde.domain.grid.shape))
        heun = pde.config.numerics.integrator == "heun"
        self._stage = np.zeros_like(self._spare) if heun else np.empty(0)
        k = len(pde.bodies)
        corners = max(1, *(b.shape.n_corners for b in pde.bodies))
        self._normals = np.zeros((2, corners, k))
        self._centres = np.zeros((2, max(1, len(self._pills))))
        n = pde.domain.coords.size
        self._tables = make_body_tables(pde.bodies, pde.body_scheme, self._bodies, n)
        cells = pde.domain.cut_cells
        coefficient = self.dt * pde.config.camphor.diffusion / pde.domain.dx**2
        self._wall = NO_WALL if cells is None else cells.arrays(coefficient)

    def normals(self, n_steps: int) -> np.ndarray:
        """K standard normals per step (none without noise), in step order."""
        if not np.any(self._bodies["kick"]):
            return np.empty(0)
        return self.rng.standard_normal(n_steps * len(self._bodies))

    def __call__(self, data: np.ndarray, bodies: BodiesState, step0: int, n_steps: int) -> None:
        """Advance `data` and `bodies` together by `n_steps` steps from step `step0`.

        Raises:
            SimulationDivergedError: the state became NaN/Inf (time, body).
            BodyContactError: a body reached the dish's edge or another body (time, bodies).
        """
        pde = self.pde
        dom = pde.domain
        coords, lo, hi, _, _ = dom.arrays()
        work = data if data.flags.c_contiguous else np.ascontiguousarray(data)
        poses = bodies.poses.copy()
        cx, cy = dom.centre
        poses[:, 0] -= cx  # the kernel works in the dish frame of `coords`
        poses[:, 1] -= cy
        status = np.zeros(3, dtype=np.int64)
        failed = advance_bodies(
            (work.reshape(-1), self._spare.reshape(-1), self._stage.reshape(-1)),
            (pde.F.reshape(-1), pde.G.reshape(-1), pde.owner.reshape(-1)),
            (coords, lo, hi),
            self._wall,
            self._record,
            (
                self._bodies,
                self._pills,
                poses,
                pde.drawn,
                pde.box,
                self._normals,
                self._centres,
                self._tables,
            ),
            self.normals(n_steps),
            status,
            (step0, n_steps),
        )
        if work is not data:
            data[...] = work
        poses[:, 0] += cx
        poses[:, 1] += cy
        bodies.poses[...] = poses
        if failed >= 0:
            raise_early_end(self.pde, (step0 + failed) * self.dt, status, bodies, data)
        if not np.isfinite(data).all():
            raise_early_end(self.pde, (step0 + n_steps) * self.dt, status, bodies, data)


def raise_early_end(
    pde: SurfacePDE,
    t: float,
    status: np.ndarray,
    bodies: BodiesState,
    data: np.ndarray,
    where: str = "",
) -> None:
    """Raise the error of a bodies run that ended early, as the compiled step's `status`
    (reason, body, other body) says: a body at the dish's edge or a vessel's wall, or two
    bodies touching
    (:class:`BodyContactError`), else non-finite fields or motion
    (:class:`SimulationDivergedError`). `where` names the backend in the message (empty
    for the CPU), so that the CPU and GPU steppers word an end alike."""
    reason, k, other = (int(s) for s in status)
    names = bodies.names
    vessel = pde.config.grid.vessel
    remedy = (
        "contact.enabled: true repels them"
        if not pde.config.contact.enabled
        else "the contact spring was too weak: raise contact.stiffness"
    )
    if reason == STATUS_EDGE and vessel is not None:
        x, y = bodies.poses[k, :2]
        msg = (
            f"body {names[k]} reached a wall of the {vessel.shape} at t = {t:.6g} (at "
            f"x = {x:.4g}, y = {y:.4g}; its footprint crossed grid.vessel's wall): the run "
            f"ends there ({remedy})"
        )
        raise BodyContactError(msg)
    if reason == STATUS_EDGE:
        x, y = bodies.poses[k, :2]
        msg = (
            f"body {names[k]} reached the dish's edge at t = {t:.6g} (at x = {x:.4g}, "
            f"y = {y:.4g}; grid.domain_radius = {pde.config.grid.domain_radius:g}): "
            "the run ends there (enlarge the dish or start the body further in)"
        )
        raise BodyContactError(msg)
    if reason == STATUS_OVERLAP:
        msg = (
            f"bodies {names[k]} and {names[other]} touched at t = {t:.6g} (their "
            f"footprints met): the run ends there ({remedy})"
        )
        raise BodyContactError(msg)
    fields = ("c", "v_x", "v_y")
    bad = [n for n, arr in zip(fields, data, strict=True) if not np.isfinite(arr).all()]
    what = ", ".join(bad) if bad else f"motion of body {names[max(k, 0)]}"
    msg = (
        f"simulation diverged at t = {t:.6g}{where}: non-finite {what} "
        f"(dt = {pde.config.grid.dt:g}, stability limit {pde.config.dt_limit():.4g})"
    )
    raise SimulationDivergedError(msg)


def make_bodies_stepper(pde: SurfacePDE, dt: float, rng: np.random.Generator) -> BodiesStepper:
    """Bind the compiled step of the bodies to `pde` (see :class:`BodiesStepper`)."""
    return BodiesStepper(pde=pde, dt=dt, rng=rng)
