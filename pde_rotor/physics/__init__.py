"""The compiled physics of the model: every equation once, for the CPU and the GPU.

The scalar functions of Koyano et al. (Chaos 2020) generalised to K bodies
(docs/bodies.md), each module building its functions in a ``make_*`` factory for a
given compiler, so that the CPU loops (:mod:`pde_rotor.kernels`) and the CUDA kernel
call the same source and hold no physics of their own:

* :mod:`.spline`: the cubic spline of c (prefilter, taps, value at a point);
* :mod:`.indicators`: the plate and pill indicators F and G, point values (``paper``)
  and filtered (``consistent``), for the rotor's N-gon and every body's plate;
* :mod:`.rates`: the per-cell right-hand sides of Eqs. (eqc), (eqv), the plate velocity
  and the cut cells' inflow behind a no-flux wall;
* :mod:`.tension`: the tension integral of Eq. (torque), area form and contour form;
* :mod:`.motion`: the equation of motion of a body, Eq. (eq_motion), the stop schedule
  and the noise kick of Eq. (noiseav);
* :mod:`.build`: :func:`~.build.make_physics`, all of the above for one compiler, and
  its CPU build :data:`~.build.CPU`;
* :mod:`.cache`: numba's on-disk caches of the package dropped when a compiled source
  changes (a cached loop keeps what it inlined from other files).

:mod:`pde_rotor.model` keeps an independent numpy version of the same equations as the
test oracle.
"""
