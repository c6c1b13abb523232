"""Linear stability of any camphor layout: rest state, Jacobian, eigenvalues, continuation.

Every paper on camphor objects finds the onset of motion by a linear stability analysis
done by hand for one geometry; this package does it for any config, on the discrete
model the solver steps (Eqs. (eqc), (eqv), (eq_motion); docs/stability.md):

* :mod:`.system`: the discrete model's rates as functions of the fields and the bodies'
  coordinates and velocities (the numpy reference of :mod:`pde_rotor.model`);
* :mod:`.fields`: the field unknowns and the sparse matrices of the field operators;
* :mod:`.rest`: the rest state, the bodies held, by one sparse solve;
* :mod:`.linear`: the Jacobian about it, in blocks (sparse fields, dense bodies);
* :mod:`.eigen`: leading eigenvalues and modes by shift-invert Arnoldi, with residuals;
* :mod:`.continuation`: eigenvalues along a config key, the critical value and the kind
  of onset (pitchfork or Hopf), the branch as an xarray Dataset;
* :mod:`.plots`: a mode (dc, dv, the body motion) and a branch, as figures.

Everything uses scipy (``scipy.sparse``, ``scipy.sparse.linalg``, ``scipy.optimize``);
the command line is ``pde-rotor stability CONFIG`` (:mod:`pde_rotor.cli.stability`).
"""

from .continuation import Branch, Crossing, critical_value, follow
from .eigen import Spectrum, is_real, leading_modes
from .linear import Linearisation, linearise
from .rest import RestState, rest_state
from .system import DiscreteModel, Dof

__all__ = [
    "Branch",
    "Crossing",
    "DiscreteModel",
    "Dof",
    "Linearisation",
    "RestState",
    "Spectrum",
    "critical_value",
    "follow",
    "is_real",
    "leading_modes",
    "linearise",
    "rest_state",
]
