"""Time stepping of one run: the py-pde solver, the simulation and its cost.

* :mod:`.rotor`: :class:`RotorSolver`, the fused explicit py-pde solver;
* :mod:`.bodies`: the compiled step of K bodies bound to one run (the stepper of
  :class:`~pde_rotor.model.surface.SurfacePDE` under :class:`RotorSolver`);
* :mod:`.simulation`: config -> model -> solver -> py-pde Controller, one run, on the
  CPU or as one member of an ensemble backend (the GPU);
* :mod:`.threads`: the threads one run's steps use (``solver.threads``).
"""
