"""The CUDA compiler of the GPU kernels, imported in this one place.

Every CUDA kernel and device function of the package (:mod:`pde_rotor.kernels.cuda`,
:mod:`pde_rotor.kernels.cuda_bodies` and its parts) and the GPU backend's host code
(:mod:`pde_rotor.backends.gpu`, :mod:`pde_rotor.backends.gpu_bodies`) take the compiler
from here: ``cuda`` (device arrays, ``shared.array``, ``syncthreads``,
``blockIdx``, ``threadIdx``, ``blockDim``, ``to_device``, ``device_array``,
``is_available``, ``get_current_device``), the decorators :func:`device_function` and
:func:`kernel`, and the element types of shared arrays (``float64``, ``int64``). Moving
to another numba CUDA target is a change of the import below (docs/gpu.md, "What the
GPU path depends on").

The compiler is numba-cuda (the ``gpu`` extra). With ``NUMBA_ENABLE_CUDASIM=1`` set
before this module is first imported, numba-cuda runs the same kernels in its CUDA
simulator on the CPU, one Python thread per CUDA thread (:func:`simulator_enabled`):
how the tests run the GPU path without a GPU.
"""

from __future__ import annotations

from collections.abc import Callable

from numba import cuda, float64, int64

__all__ = ["cuda", "device_function", "float64", "int64", "kernel", "simulator_enabled"]


def simulator_enabled() -> bool:
    """Whether numba runs CUDA kernels in its CPU simulator (``NUMBA_ENABLE_CUDASIM=1``)."""
    from numba.cuda.core import config as cuda_config

    return bool(cuda_config.ENABLE_CUDASIM)


def device_function(func: Callable) -> Callable:
    """A CUDA device function, inlined into the kernels that call it (the physics'
    ``jit`` argument, :func:`pde_rotor.physics.build.make_physics`)."""
    return cuda.jit(device=True, inline=True)(func)


def kernel(func: Callable, launch_bounds: tuple[int, ...] | None = None) -> Callable:
    """A CUDA kernel, compiled on its first launch; `launch_bounds` (threads per block,
    and optionally the least blocks per multiprocessor) is passed on a GPU only (the
    simulator has none)."""
    if launch_bounds is None or simulator_enabled():
        return cuda.jit(func)
    return cuda.jit(launch_bounds=launch_bounds)(func)
