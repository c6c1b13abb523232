"""Figure primitives: a run's movie frames and summary, and the helpers every figure shares.

The figures that belong to one concept live with it: the Fig. 9 map in
:mod:`pde_rotor.decision.map`, the figure of a sweep report in :mod:`pde_rotor.sweep.plot`,
the paper's figures in :mod:`pde_rotor.gallery`.

* :mod:`.run`: movie frames and the summary figure of ``pde-rotor show``;
* :mod:`.bodies`: the outline, pills and path of every body, the summary of a bodies run;
* :mod:`.figures`: pyplot-free figures, footers, probability axes and interval bars.
"""
