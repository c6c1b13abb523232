"""The configuration made into the model's objects, once, in one place.

A validated :class:`~pde_rotor.config.RotorConfig` describes a run; the code below the
configuration works with the objects it describes: the paper's rotor shape (Eqs. (F),
(G), :class:`~pde_rotor.model.geometry.RotorShape`), the bodies (the shorthand's rotor
being its ``fixed_axis`` body at the origin, :class:`~pde_rotor.model.bodies.Body`),
the stop schedule of section "Model" in steps of the run's dt and each body's own
(:class:`~pde_rotor.model.protocol.StopSchedule`), and the discretisation of F, G and
the torque for the rotor and for the bodies (:class:`~pde_rotor.model.schemes.Scheme`,
:class:`~pde_rotor.model.body_schemes.BodyScheme`). :class:`Setup` holds them; it is
made where a run enters the package (:func:`pde_rotor.api.run`, the backends, the
sweep runner, the stability tool, the gallery) and travels down with the run: the
PDEs, the steppers, the trackers and the parameter records
(:func:`pde_rotor.kernels.records.make_record`) read their objects from it and
build none from the configuration themselves.

Each object is made on first use and kept (the ``consistent`` scheme's filter tables
take seconds; a cost estimate needs only the shape), so a setup makes each at most
once. A stepper whose dt differs from ``grid.dt`` asks :meth:`Setup.at`, which shares
every object that does not depend on dt.

A function that takes either a config or a setup (the public API's) turns it into a
setup once at its top with :func:`as_setup`.
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

from ..config import RotorConfig
from .geometry import RotorShape

if TYPE_CHECKING:
    from .bodies import Body
    from .body_schemes import BodyScheme
    from .protocol import StopSchedule
    from .schemes import Scheme

_SHARED = ("shape", "bodies", "scheme", "body_scheme")
"""The objects of a setup that do not depend on its dt (shared by :meth:`Setup.at`)."""
_TIMED = ("schedule", "body_schedules")
"""The objects of a setup counted in steps of its dt."""


class Setup:
    """The model's objects of one run, each made from its configuration once.

    Attributes:
        config: the validated run configuration.
        dt: the time step the schedules count in (``grid.dt`` unless given).
    """

    def __init__(self, config: RotorConfig, dt: float | None = None):
        """
        Args:
            config: the run configuration (validated).
            dt: the step of the run (default: ``grid.dt``).
        """
        self.config = config
        self.dt = float(config.grid.dt if dt is None else dt)
        self._parent: Setup | None = None

    def __repr__(self) -> str:
        return f"Setup(dt = {self.dt:g}, made: {', '.join(self.made()) or 'nothing'})"

    def made(self) -> tuple[str, ...]:
        """The names of the objects this setup has made so far."""
        return tuple(name for name in (*_SHARED, *_TIMED) if name in self.__dict__)

    @cached_property
    def shape(self) -> RotorShape:
        """The paper's rotor: its plate and pills (``geometry``, Eqs. (F), (G))."""
        if self._parent is not None:
            return self._parent.shape
        return RotorShape.from_config(self.config.geometry)

    @cached_property
    def bodies(self) -> tuple[Body, ...]:
        """The bodies of the run (``bodies``, or the ``geometry`` shorthand's rotor as its
        ``fixed_axis`` body at the origin)."""
        from .bodies import Body, BodyShape  # py-pde: made only where bodies are asked for

        if self._parent is not None:
            return self._parent.bodies
        smoothing = self.config.geometry.smoothing
        widths = self.config.numerics.footprint_widths
        return tuple(
            Body.from_config(body, BodyShape.from_config(body, smoothing, widths))
            for body in self.config.body_list()
        )

    @cached_property
    def schedule(self) -> StopSchedule:
        """The run's stop schedule (``protocol``) in steps of :attr:`dt`."""
        from .protocol import StopSchedule  # numba: made only where a schedule is asked for

        return StopSchedule.from_config(self.config.protocol, self.dt)

    @cached_property
    def body_schedules(self) -> tuple[StopSchedule | None, ...]:
        """Each body's own stop schedule in steps of :attr:`dt` (None: it has none)."""
        from .protocol import StopSchedule

        return tuple(
            None if body.protocol is None else StopSchedule.from_config(body.protocol, self.dt)
            for body in self.bodies
        )

    @cached_property
    def scheme(self) -> Scheme:
        """The discretisation of the rotor's F, G and torque (``numerics``)."""
        from .schemes import Scheme

        if self._parent is not None:
            return self._parent.scheme
        return Scheme.from_config(self.config, self.shape)

    @cached_property
    def body_scheme(self) -> BodyScheme:
        """The discretisation of the bodies' F_k, G_k, forces and torques (``numerics``)."""
        from .body_schemes import BodyScheme

        if self._parent is not None:
            return self._parent.body_scheme
        return BodyScheme.from_config(self.config, self.bodies)

    def at(self, dt: float) -> Setup:
        """This run with step `dt`: the schedules in steps of `dt`; every other object
        (shape, bodies, schemes) is this setup's, made by it at most once."""
        if float(dt) == self.dt:
            return self
        other = Setup(self.config, dt)
        other._parent = self._parent or self
        return other


def as_setup(run: Setup | RotorConfig) -> Setup:
    """`run` if it is a setup, else the setup of the configuration `run`."""
    return run if isinstance(run, Setup) else Setup(run)
