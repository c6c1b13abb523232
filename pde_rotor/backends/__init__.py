"""Compute backends that advance many members (realisations) of the rotor at once.

A *member* is one independent simulation of Eqs. (eqc), (eqv), (eq_motion) with its own
configuration: parameters (Delta, t_stop, sigma, ...), noise seed, stop schedule and
initial rotor state. Members of one ensemble share the grid (``grid`` section).

* :mod:`.cpu`: the members one after the other with the fused CPU
  solver (:class:`pde_rotor.solver.rotor.RotorSolver`, driven through its py-pde stepper);
  the reference the GPU backend is checked against.
* :mod:`.gpu`: all members in one batched CUDA computation
  (numba-cuda, fp64), with the same discretisation, stop logic and noise stream; its
  kernel is :mod:`pde_rotor.kernels.cuda`.

Both implement the one ensemble interface, :class:`~pde_rotor.backends.base.EnsembleBackend`
(its runner: :class:`~pde_rotor.backends.base.EnsembleRunner`), and return an
:class:`~pde_rotor.backends.ensemble.EnsembleResult`;
:func:`~pde_rotor.backends.batch.run_batch` runs a sweep's members in batches and
classifies their stops by the inversion rule. Nothing here
imports numba-cuda: :func:`gpu_available` and :func:`run_ensemble` import the GPU
module only when asked, so ``import pde_rotor`` works on machines without a GPU or
without the ``gpu`` extra.

* :mod:`.base`: the interface (runtime-checkable Protocols) both backends implement;
* :mod:`.ensemble`: the plan, state and result of an ensemble shared by the backends;
* :mod:`.batch`: a sweep's members in batches, classified by the inversion rule;
* :mod:`.gpu_bodies`: ``bodies:`` configs on the GPU, a single run's stepper and an
  ensemble of members (kernel: :mod:`pde_rotor.kernels.cuda_bodies`);
* this package: :func:`run_ensemble`, the backend choice and :func:`member_stepper`,
  which runs a single configuration as one member under py-pde's Controller.
"""

from __future__ import annotations

import importlib
import logging
import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from .._lazy import lazy_exports

if TYPE_CHECKING:  # imported on first use: `pde-rotor info` asks for the GPU quickly
    import numpy as np

    from ..config import RotorConfig
    from ..model.pde import RotorPDE, RotorState
    from ..model.setup import Setup
    from ..solver.rotor import MemberStepper, StepperFactory
    from .base import EnsembleBackend, EnsembleRunner
    from .batch import MemberRun, run_batch
    from .ensemble import EnsembleResult, EnsembleState

_logger = logging.getLogger(__name__)

__all__ = [
    "GPU_INSTALL_HINT",
    "BackendError",
    "EnsembleBackend",
    "EnsembleResult",
    "EnsembleRunner",
    "EnsembleState",
    "MemberRun",
    "backend_for",
    "device_name",
    "gpu_available",
    "gpu_unavailable_reason",
    "member_stepper",
    "resolve_backend",
    "run_batch",
    "run_ensemble",
]


GPU_INSTALL_HINT = (
    "GPU support is not installed: it needs the optional package numba-cuda, "
    "pip install 'numba-cuda[cu12]' (the gpu extra; in a clone: pip install -e '.[gpu]'), "
    "and an NVIDIA GPU with its driver"
)
"""What a plain install (without numba-cuda) says instead of a raw import error."""


def gpu_unavailable_reason(allow_simulator: bool = False) -> str | None:
    """Why the GPU backend cannot run here, or None when it can.

    Without numba-cuda, numba's own deprecated ``numba.cuda`` may import, and the check
    then fails on a module it lacks (``numba.cuda.core``): both mean the same, the
    optional package is missing, and say so (:data:`GPU_INSTALL_HINT`).

    Args:
        allow_simulator: count numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) as
            a GPU (tests); by default only real hardware counts.
    """
    try:
        gpu = importlib.import_module("pde_rotor.backends.gpu")
        return gpu.unavailable_reason(allow_simulator=allow_simulator)
    except ImportError:
        return GPU_INSTALL_HINT
    except Exception as err:  # a CUDA error at import
        detail = str(err).splitlines()[0] if str(err) else type(err).__name__
        return f"numba-cuda is installed but not usable ({type(err).__name__}: {detail})"


def gpu_available(allow_simulator: bool = False) -> bool:
    """Whether :func:`run_ensemble` can use the GPU backend on this machine."""
    return gpu_unavailable_reason(allow_simulator=allow_simulator) is None


class BackendError(RuntimeError):
    """The requested compute backend cannot be used here; ``str(err)`` is one line."""


def resolve_backend(requested: str) -> str:
    """Turn ``cpu | gpu | auto`` (``config.solver.backend``) into the backend that will run.

    * ``cpu``: the fused CPU solver.
    * ``gpu``: the GPU backend; it needs a CUDA GPU, or numba's CUDA simulator enabled
      by the user (``NUMBA_ENABLE_CUDASIM=1``: the same kernels, slowly, on the CPU).
    * ``auto``: ``gpu`` on a real GPU, else ``cpu`` (never the simulator).

    Returns:
        "cpu" or "gpu".

    Raises:
        BackendError: "gpu" was requested and cannot be used (one line, with the reason).
        ValueError: unknown backend name.
    """
    if requested == "cpu":
        return "cpu"
    if requested not in ("gpu", "auto"):
        msg = f"unknown backend {requested!r} (allowed: cpu, gpu, auto)"
        raise ValueError(msg)
    reason = gpu_unavailable_reason(allow_simulator=requested == "gpu")
    if reason is None:
        return "gpu"
    if requested == "auto":
        _logger.info("solver.backend = auto: using cpu (%s)", reason)
        return "cpu"
    msg = f"solver.backend = 'gpu': {reason} (allowed here: cpu, auto; use --backend cpu)"
    raise BackendError(msg)


def backend_for(config: RotorConfig) -> str:
    """The backend that will run `config`: ``solver.backend`` resolved for its numerics.

    Every run goes on either backend with Euler or Heun: bodies (``bodies:``) on the
    GPU's :mod:`pde_rotor.backends.gpu_bodies` or the CPU's loop, the rotor on its own
    kernels, or with Heun on the GPU as its ``fixed_axis`` body
    (:func:`pde_rotor.backends.gpu_bodies.run_rotor_ensemble`).
    The CLI and :func:`pde_rotor.run` ask here before they write anything.

    Raises:
        BackendError: "gpu" requested and no usable GPU (one line, with the reason).
    """
    return resolve_backend(config.solver.backend)


def device_name(backend: str) -> str:
    """What runs a resolved backend: "cpu", the GPU's name, or numba's CUDA simulator."""
    if backend != "gpu":
        return "cpu"
    gpu = importlib.import_module("pde_rotor.backends.gpu")
    return gpu.device_name()


def member_stepper(backend: str) -> StepperFactory:
    """A run of one configuration as an ensemble of one member on `backend`.

    The factory that :class:`~pde_rotor.solver.rotor.RotorSolver` takes: py-pde's
    Controller drives the run and calls the same trackers as on the CPU, and between two
    interrupts the member advances on the ensemble backend from the state the Controller
    holds (fields and rotor), with the run's noise stream drawn in step order, as the CPU
    solver draws it. This is how ``solver.backend: gpu`` runs a single configuration
    (with ``numerics.integrator: heun`` as the rotor's ``fixed_axis`` body on the bodies'
    kernel, :func:`pde_rotor.backends.gpu_bodies.run_rotor_ensemble`).

    Args:
        backend: ``gpu``, or ``cpu`` (the CPU ensemble backend: the same path, checked
            against the fused CPU solver by the tests).
    """

    from ..solver.rotor import SimulationDivergedError
    from .ensemble import EnsembleState

    def factory(pde: RotorPDE, dt: float, rng: np.random.Generator) -> MemberStepper:
        config = pde.config

        def step(data: np.ndarray, rotor: RotorState, step0: int, n_steps: int) -> None:
            initial = EnsembleState(
                data=data[None].copy(), rotor=rotor.as_array()[None], step=step0
            )
            result = run_ensemble(
                [config],
                (step0 + n_steps) * dt,
                backend=backend,
                record_interval=n_steps * dt,
                initial=initial,
                rngs=[rng],
            )
            failed = float(result.diverged_at[0])
            data[...] = result.state.data[0]
            rotor.update_from(result.state.rotor[0])
            if not math.isnan(failed):
                msg = (
                    f"simulation diverged at t = {failed:.6g} on the {result.backend} backend: "
                    f"non-finite state (dt = {dt:g}, stability limit {config.dt_limit():.4g})"
                )
                raise SimulationDivergedError(msg)

        return step

    return factory


def run_ensemble(
    configs: Sequence[Setup | RotorConfig],
    t_end: float | None = None,
    *,
    backend: str = "auto",
    record_interval: float | None = None,
    initial: EnsembleState | None = None,
    rngs: Sequence[np.random.Generator] | None = None,
    progress: Callable[[int, int], None] | None = None,
    **options: Any,
) -> EnsembleResult:
    """Advance every member of an ensemble to `t_end`; the entry point of sweeps and the CLI.

    Args:
        configs: one validated configuration per member, or its setup
            (:class:`~pde_rotor.model.setup.Setup`, made once by the caller); all with the
            same ``grid``.
        t_end: final time (default: the latest ``protocol.t_end`` of the members);
            a multiple of ``grid.dt``.
        backend: ``cpu``, ``gpu`` or ``auto`` (see :func:`resolve_backend`).
        record_interval: time between rows of phi(t), omega(t), ... (default:
            ``output.timeseries_interval`` of the first member); a multiple of dt.
        initial: state to continue from (default: c = v = 0, phi0, omega0 at t = 0).
        rngs: one numpy Generator per member for the noise (default:
            ``np.random.default_rng(config.noise.seed)``, as the CPU solver).
        progress: called as ``progress(steps_done, steps_total)`` between chunks.
        **options: backend-specific options (GPU: ``threads_per_block``,
            ``chunk_steps``; see :func:`pde_rotor.backends.gpu.run_ensemble`).

    Returns:
        The per-member time series, divergence times and final state.
    """
    name = resolve_backend(backend)
    module = importlib.import_module(f"pde_rotor.backends.{name}")
    return module.run_ensemble(
        configs,
        t_end,
        record_interval=record_interval,
        initial=initial,
        rngs=rngs,
        progress=progress,
        **options,
    )


__getattr__, __dir__ = lazy_exports(__name__)
