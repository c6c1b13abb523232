"""The compiled loops: the grid walked row by row (CPU) or thread by thread (CUDA).

The physics they call is :mod:`pde_rotor.physics` (every equation once); the loops hold
none of their own.

* :mod:`.records`: the kernels' scalar parameters as one numpy record per run, and one
  per body, built from the config in one place;
* :mod:`.indicators`: F and G on the support cells, row by row, on the CPU;
* :mod:`.spline`: the cubic spline of c for the contour form, many lines at once, on
  the CPU;
* :mod:`.cpu`: the fused step of c, v and the paper's rotor on the CPU (Euler or Heun),
  one pass over the rows shared among threads;
* :mod:`.bodies`: the step of K bodies and the fields on the CPU (Euler or Heun, both
  schemes), with :mod:`.body_draw` (a body's F, G and owner on its footprint's chords),
  :mod:`.body_sums` (a body's integrals, area and contour form; the contour form's
  circles in :mod:`.body_arcs`) and :mod:`.body_fields` (the fields' update over the
  bodies' runs of cells);
* :mod:`.wall`: the step of the fields behind a no-flux dish wall (cut cells of the circle);
* :mod:`.cuda_target`: the CUDA compiler (numba-cuda), imported in this one place;
* :mod:`.cuda`: the batched CUDA kernel of an ensemble (:mod:`pde_rotor.backends.gpu`);
* :mod:`.cuda_bodies`: the batched CUDA kernel of K bodies, Euler or Heun
  (:mod:`pde_rotor.backends.gpu_bodies`), with :mod:`.cuda_body_draw` (a body's F, G and
  owner drawn by a block) and :mod:`.cuda_body_sums` (a body's integrals, area and
  contour form).
"""
