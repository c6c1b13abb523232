"""Shared fixtures of the physics test suite: configuration builders and random states.

Every configuration is built with ``RotorConfig.model_validate`` from the schema's
defaults (the paper's values) plus the few overrides a test needs; no test repeats a
default number. :data:`COARSE` is the coarse test resolution of the quick configs
(dx = 0.05, dt = 4e-4, delta = 0.05); :data:`SMALL_DOMAIN` shrinks the circular domain
for tests whose property does not depend on L, keeping the support of F and G
(radius R + 20 delta / cos(pi/N)) inside the interior cells.
"""

from __future__ import annotations

import copy
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterator, Mapping
from typing import Any

import numpy as np
import pytest
from numba.core import types as numba_types
from numba.np import numpy_support
from pde import FieldCollection

from pde_rotor.config import RotorConfig
from pde_rotor.model import filtering
from pde_rotor.model.pde import RotorPDE

QUICK = (
    "tests/config/",
    "tests/io/",
    "tests/statistics/",
    "tests/cli/test_common.py",
    "tests/cli/test_user_errors.py",
    "tests/sweep/test_cost.py",
    "tests/test_layers.py",
    "tests/test_docs.py",
)
"""The everyday subset, ``pytest -m quick``: configs and their one-line errors, the files a
run writes, the statistics, the layering and the docs' numbers (README, Tests)."""


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark the tests of :data:`QUICK` (not the slow ones) ``quick``."""
    root = config.rootpath
    for item in items:
        where = item.path.relative_to(root).as_posix()
        if where.startswith(QUICK) and item.get_closest_marker("slow") is None:
            item.add_marker(pytest.mark.quick)


COARSE: dict[str, Any] = {"grid": {"dx": 0.05, "dt": 4e-4}, "geometry": {"smoothing": 0.05}}
"""The coarse test resolution (about 0.26 ms per step with L = 3)."""

DIVERGING: dict[str, Any] = {"rotor": {"omega0": 1e4}, "flow": {"drag": 1e3}}
"""Overrides that make a coarse run diverge within a few steps: the plate's speed omega0 R
= 5000, imposed on the water by a stiff drag, breaks the advection limit dt <= 2 D / |v|^2
(each value is inside the schema's physical bounds)."""

SMALL_DOMAIN: dict[str, Any] = {"grid": {"domain_radius": 1.75}}
"""Domain radius for quick coarse runs: the support of F and G (radius 1.655 with the
coarse delta) stays clear of the border cells of the square grid."""


def merge(base: Mapping[str, Any], *overrides: Mapping[str, Any]) -> dict[str, Any]:
    """Deep-merge nested config dictionaries (later ones win), without mutating inputs."""
    out = copy.deepcopy(dict(base))
    for override in overrides:
        for key, value in override.items():
            if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
                out[key] = merge(out[key], value)
            else:
                out[key] = copy.deepcopy(value)
    return out


def build_coarse_config(*overrides: Mapping[str, Any]) -> RotorConfig:
    """Validated config at the coarse test resolution with the given section overrides."""
    return RotorConfig.model_validate(merge(COARSE, *overrides))


def build_small_config(*overrides: Mapping[str, Any]) -> RotorConfig:
    """Coarse config on the small domain (:data:`SMALL_DOMAIN`) with overrides."""
    return RotorConfig.model_validate(merge(COARSE, SMALL_DOMAIN, *overrides))


@pytest.fixture
def coarse_config() -> Callable[..., RotorConfig]:
    """Builder ``coarse_config({"rotor": {...}}, ...)`` of coarse-resolution configs (L = 3)."""
    return build_coarse_config


@pytest.fixture
def small_config() -> Callable[..., RotorConfig]:
    """Builder of coarse-resolution configs on the small domain."""
    return build_small_config


def smooth_random_state(
    pde: RotorPDE, rng: np.random.Generator, flow: bool = True
) -> FieldCollection:
    """A smooth, random, non-trivial state [c, v] (zero on and outside the circle |r| = L).

    c is positive and of order 1 everywhere inside the circle, including the cells next to
    the boundary (so that boundary fluxes are not negligible); v is a random smooth
    field of order 1 (zero if ``flow`` is False).
    """
    x, y = pde.cell_coordinates()
    mask = pde.domain.interior_mask
    state = pde.initial_state()

    def modes(n_modes: int) -> np.ndarray:
        field = np.zeros_like(x)
        for _ in range(n_modes):
            kx, ky = rng.uniform(-3.0, 3.0, size=2)
            amp, phase = rng.uniform(-1.0, 1.0), rng.uniform(0, 2 * np.pi)
            field += amp * np.cos(kx * x + ky * y + phase)
        return field / n_modes

    state.data[0] = mask * (1.0 + 0.5 * modes(6))
    if flow:
        state.data[1] = mask * modes(6)
        state.data[2] = mask * modes(6)
    return state


@pytest.fixture
def random_state() -> Callable[..., FieldCollection]:
    """``random_state(pde, rng, flow=True)``: see :func:`smooth_random_state`."""
    return smooth_random_state


def _locked_shared_array(simulated: Callable[..., np.ndarray]) -> Callable[..., np.ndarray]:
    """numba's simulated ``cuda.shared.array`` with its allocation under a lock.

    The simulator keys a block's shared arrays by the calling source line and creates
    one on the first call without a lock: two threads of a block that ask at once can
    each create one, and the loser then works on a private, uninitialised array (seen
    here as a rare wrong run under load). Same semantics, allocated once per call site.
    """
    lock = threading.Lock()

    def array(self: Any, shape: Any, dtype: Any, alignment: Any = None) -> np.ndarray:
        if shape == 0 or alignment is not None:
            return simulated(self, shape, dtype, alignment)
        caller = traceback.extract_stack(sys._getframe())[-2][0:2]
        if isinstance(dtype, numba_types.Type):
            dtype = numpy_support.as_dtype(dtype)
        with lock:
            if caller not in self._allocations:
                self._allocations[caller] = np.empty(shape, dtype)
            return self._allocations[caller]

    return array


POLL_NAP = 1e-4
"""Seconds the simulator's block manager sleeps per poll of a thread (:func:`_napping`)."""


def _napping(is_alive: Callable[[Any], bool]) -> Callable[[Any], bool]:
    """The simulated thread's ``is_alive`` after a short sleep.

    The simulator's block manager polls its threads in a busy loop (``is_alive`` per
    thread and round) and so holds the GIL for about a third of the time its simulated
    threads need. A nap per poll hands it to them: the same runs, about a quarter
    faster. The nap only delays the manager's reaction to a ``syncthreads``.
    """

    def napping(self: Any) -> bool:
        time.sleep(POLL_NAP)
        return is_alive(self)

    return napping


@pytest.fixture
def fast_simulator(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Hand the GIL over quickly (the simulator's block manager polls its threads, and
    naps per poll: :func:`_napping`), and allocate the simulator's shared arrays
    race-free (:func:`_locked_shared_array`)."""
    # imported here: the GPU test modules enable the simulator before numba-cuda loads
    from pde_rotor.backends import gpu as gpu_backend

    if not gpu_backend.is_available(allow_simulator=True):
        pytest.fail(f"no GPU and no CUDA simulator: {gpu_backend.unavailable_reason(True)}")
    if gpu_backend.simulator_enabled():
        from numba.cuda.simulator import kernel, kernelapi

        locked = _locked_shared_array(kernelapi.FakeCUDAShared.array)
        monkeypatch.setattr(kernelapi.FakeCUDAShared, "array", locked)
        monkeypatch.setattr(kernel.BlockThread, "is_alive", _napping(kernel.BlockThread.is_alive))
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-5)
    yield
    sys.setswitchinterval(interval)


def compiled_indicators(pde: RotorPDE, phi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """F and G (n, n) of the compiled core on the support cells at angle phi, and the
    rotor table it filled (:func:`pde_rotor.kernels.indicators.update_indicators`)."""
    from pde_rotor.kernels.indicators import update_indicators
    from pde_rotor.kernels.records import make_record

    dom = pde.domain
    F = np.zeros(dom.grid.shape)
    G = np.zeros(dom.grid.shape)
    tab = np.empty((4, pde.shape.n_corners))
    update_indicators(
        F.reshape(-1),
        G.reshape(-1),
        dom.arrays(),
        make_record(pde.setup),
        tab,
        pde.scheme.kernel_tables(),
        phi,
    )
    return F, G, tab


@pytest.fixture
def full_corner_table(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """While active, filter tables are built with the corner table on every cell near a
    bisector (``CORNER_CUTOFF`` 0 puts ``corner_end`` past the table's last node): the
    path without the table's end, to bound what the end changes."""
    monkeypatch.setattr(filtering, "CORNER_CUTOFF", 0.0)
    filtering.make_tables.cache_clear()
    yield
    filtering.make_tables.cache_clear()


@pytest.fixture
def indicators_of() -> Callable[[RotorPDE, float], tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``indicators_of(pde, phi)``: see :func:`compiled_indicators`."""
    return compiled_indicators
