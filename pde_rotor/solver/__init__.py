"""Time stepping of one run: the py-pde solver, the simulation and its cost.

* :mod:`.rotor`: :class:`RotorSolver`, the fused explicit py-pde solver;
* :mod:`.simulation`: config -> model -> solver -> py-pde Controller, one run;
* :mod:`.single_run`: one run with its trackers on an ensemble backend (one member).
"""
