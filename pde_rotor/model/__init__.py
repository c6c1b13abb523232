"""The model in numpy: geometry, domain, protocol, schemes and the readable reference PDE.

This layer says *what* is computed. It imports only :mod:`pde_rotor.config` and the
stop schedule and spline constants of :mod:`pde_rotor.physics`, the compiled physics
it is the independent reference of.

* :mod:`.geometry`: the rotor's plate indicator F and pill indicator G (Eqs. (F), (G));
* :mod:`.bodies`: the same for every body of a ``bodies:`` config (plates of any shape,
  pills anywhere, poses), with the plate velocity and the footprint;
* :mod:`.domain`: the circular domain of radius L on a py-pde CartesianGrid;
* :mod:`.wall`: the no-flux dish wall: cut cells of the circle, their fluxes and step;
* :mod:`.clusters`: the implicit cut cells' clusters, their matrices and sparse factors;
* :mod:`.vessel`: the cut cells of the other vessels (an annular channel, a rectangular
  tank) for the same step;
* :mod:`.protocol`: the stop-and-release schedule (section "Model");
* :mod:`.schemes`, :mod:`.filtering`: the ``paper`` and ``consistent`` discretisations
  of F, G and the torque, and the prefilter tables of the latter;
* :mod:`.body_schemes`: the ``consistent`` scheme for bodies (their filtered F_k and G_k,
  the contour forms of their force and torque);
* :mod:`.pde`: :class:`RotorPDE`, the py-pde PDE whose numpy right-hand side is the
  independent reference of Eqs. (eqc), (eqv) and (eq_motion);
* :mod:`.surface`: :class:`SurfacePDE`, the same model with K bodies on one surface
  (each body's force and torque, Eq. (eq_motion) about its position, a whole step of
  fields and bodies), and its state;
* :mod:`.rates`: the local terms of Eqs. (eqc) and (eqv) (evaporation off the plates, the
  pills' supply, the plates' and the bulk's drag on the flow), written once for both PDEs;
* :mod:`.motion`: the equation of motion of K bodies (accelerations, Euler and Heun
  steps of the poses), the paper's rotor being the ``fixed_axis`` body at the origin;
* :mod:`.analysis`: what needs no time stepping (the stopped plate's steady state);
* :mod:`.setup`: :class:`~pde_rotor.model.setup.Setup`, the one place where a run's
  configuration is made into the objects above (the rotor's shape, the bodies, the stop
  schedules, the schemes); the PDEs, the compiled loops' parameter records, the
  steppers, the trackers and the backends read them from it.

The exact onsets of motion the bodies are checked against are :mod:`pde_rotor.theory`'s.
"""
