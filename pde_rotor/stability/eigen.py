"""Leading eigenvalues and eigenmodes of the linearisation, by shift-invert Arnoldi (scipy).

Every eigenvalue of the held problem A (diffusion, sublimation, the flow's relaxation) has
a negative real part; what can grow comes from the bodies' coupling, the roots of the
small determinant det S(lambda) = 0 (:meth:`~.linear.Linearisation.schur`). The shift of
the spectral transformation is put where those roots are: the largest real part of the
eigenvalues of S(0) (the quasi-static estimate: the camphor following the body
instantly, an upper bound for a real growth rate whose response weakens with lambda), or
1e-3 if that is smaller (the onsets, where an eigenvalue crosses the imaginary axis; not 0
itself, where a neutral coordinate would make J - sigma singular).
scipy's ``eigs`` (ARPACK) with ``OPinv`` = (J - sigma)^{-1}
(:meth:`~.linear.Linearisation.shift_invert`) then returns the k eigenvalues nearest
sigma; each comes with its residual |J x - lambda x| / (|lambda| |x|).

An eigenvalue lambda means that a perturbation of the rest state grows as e^{lambda t}:
Re lambda > 0 unstable. Real: the body starts to move in one direction (pitchfork at
its onset); a complex pair: it starts to oscillate at the frequency Im lambda (Hopf).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import eigs

from .linear import Linearisation

SHIFT_FLOOR = 1e-3
"""The smallest automatic shift: not 0, where a neutral mode of the bodies' coordinates
would make J - sigma singular."""
IMAGINARY_TOLERANCE = 1e-8
"""|Im lambda| / max(|lambda|, 1) below which an eigenvalue counts as real."""


@dataclass
class Spectrum:
    """Eigenvalues and modes of a linearisation.

    Attributes:
        eigenvalues: (k,) sorted by decreasing real part.
        vectors: (size, k) the eigenvectors, each of norm 1.
        residuals: (k,) |J x - lambda x| / (max(|lambda|, 1) |x|).
        shift: sigma of the spectral transformation.
    """

    eigenvalues: np.ndarray
    vectors: np.ndarray
    residuals: np.ndarray
    shift: float

    @property
    def leading(self) -> complex:
        """The eigenvalue of largest real part."""
        return complex(self.eigenvalues[0])


def is_real(value: complex) -> bool:
    """Whether an eigenvalue is real within :data:`IMAGINARY_TOLERANCE`."""
    return abs(value.imag) <= IMAGINARY_TOLERANCE * max(abs(value), 1.0)


def auto_shift(lin: Linearisation) -> float:
    """The largest real part of the eigenvalues of S(0) in the co-moving frame, or 0 (see
    the module docstring; the coordinates only add the slow modes of the stiffness)."""
    if lin.n_dofs == 0:
        return 0.0
    values = np.linalg.eigvals(lin.with_positions(False).schur(0.0))
    return float(max(values.real.max(), SHIFT_FLOOR))


def leading_modes(
    lin: Linearisation, k: int = 6, shift: float | None = None, tol: float = 1e-10
) -> Spectrum:
    """The k eigenvalues of J nearest the shift, with modes and residuals.

    Args:
        lin: the linearisation.
        k: how many (fewer if J is smaller).
        shift: sigma (default :func:`auto_shift`).
        tol: ARPACK's relative accuracy of the Ritz values.

    Returns:
        The spectrum, eigenvalues sorted by decreasing real part.
    """
    sigma = auto_shift(lin) if shift is None else float(shift)
    k = min(k, lin.size - 2)
    v0 = np.ones(lin.size)
    values, vectors = eigs(
        lin.operator(), k=k, sigma=sigma, OPinv=lin.shift_invert(sigma), v0=v0, tol=tol
    )
    order = np.lexsort((-values.imag, -values.real))
    values, vectors = values[order], vectors[:, order]
    vectors = vectors / np.linalg.norm(vectors, axis=0)
    residuals = np.array(
        [
            np.linalg.norm(lin.matvec(vectors[:, j]) - values[j] * vectors[:, j])
            / max(abs(values[j]), 1.0)
            for j in range(values.size)
        ]
    )
    return Spectrum(eigenvalues=values, vectors=vectors, residuals=residuals, shift=sigma)
