"""The compiled core: each per-cell rate, indicator and rotor integral, and the loops.

* :mod:`.core`: the scalar functions of the model, written once and compiled with
  numba; the CPU and CUDA loops call them;
* :mod:`.records`: the kernels' scalar parameters as one numpy record per run, built
  from the config in one place;
* :mod:`.indicators`: F and G on the support cells, row by row, on the CPU;
* :mod:`.spline`: the cubic spline of c for the contour torque, many lines at once, on
  the CPU;
* :mod:`.cpu`: the fused explicit step of c, v, phi and omega on the CPU, one pass over
  the rows shared among threads;
* :mod:`.body_core`: the physics of bodies, written once: plate shapes, plate velocity,
  force and torque of a body (Eq. (eq_motion) about its position);
* :mod:`.bodies`: the step of K bodies and the fields on the CPU (``paper`` scheme);
* :mod:`.wall`: the step of the fields behind a no-flux dish wall (cut cells of the circle);
* :mod:`.cuda_target`: the CUDA compiler (numba-cuda), imported in this one place;
* :mod:`.cuda`: the batched CUDA kernel of an ensemble (:mod:`pde_rotor.backends.gpu`);
* :mod:`.cuda_bodies`: the batched CUDA kernel of K bodies, Euler or Heun
  (:mod:`pde_rotor.backends.gpu_bodies`), with :mod:`.cuda_body_draw` (a body's F, G and
  owner drawn by a block) and :mod:`.cuda_body_sums` (a body's integrals, area and
  contour form).
"""
