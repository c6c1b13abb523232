"""How the model is discretised (the ``numerics:`` section) and where it runs (the
``solver:`` section)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from .fields import (
    X_SATURATION,
    Int,
    _Section,
)

FOOTPRINT_WIDTHS_MIN = 3.0
"""The shortest footprint ``numerics.footprint_widths`` allows: 3 smoothing widths beyond
plate and pills, where a point-value indicator's tail is 1 / (1 + e^6) = 2.5e-3."""


class NumericsConfig(_Section):
    """How F, G and the torque are discretised on the grid (docs/model.md, "Schemes")."""

    scheme: Literal["paper", "consistent"] = Field(
        "consistent",
        description=(
            "consistent: F and G through an isotropic prefilter and the torque in contour "
            "form, almost free of the grid's lattice torque; paper: point values of F and "
            "G and the area-form torque with central differences, as in the paper "
            "(docs/model.md, Schemes)"
        ),
    )
    integrator: Literal["euler", "heun"] = Field(
        "euler",
        description=(
            "euler: forward Euler, the paper's method (first order in dt); heun: Heun's "
            "second-order method at twice the cost per step (CPU backend only)"
        ),
    )
    plate_filter_kernel: Literal["gaussian", "sharpened"] = Field(
        "gaussian",
        description=(
            "consistent scheme: prefilter of the plate's F, the Gaussian N_eps (changes "
            "the model at order eps^2) or sharpened 2 N_eps - N_(sqrt2 eps) (zero second "
            "moment; docs/model.md, Schemes)"
        ),
    )
    plate_filter_width: float = Field(
        0.7,
        ge=0.25,
        le=2.0,
        description="consistent scheme: width eps of the plate's prefilter, in units of dx",
    )
    pill_filter_kernel: Literal["gaussian", "sharpened"] = Field(
        "sharpened",
        description=(
            "consistent scheme: prefilter of the pills' G (gaussian or sharpened, as "
            "plate_filter_kernel); the sharpened kernel keeps the pills' second moment, "
            "which the asymmetry torque feels (docs/model.md, Schemes)"
        ),
    )
    pill_filter_width: float = Field(
        0.95,
        ge=0.25,
        le=2.0,
        description="consistent scheme: width eps of the pills' prefilter, in units of dx",
    )
    table_refinement: Int = Field(
        8, ge=4, le=32, description="consistent scheme: nodes per dx of the plate's F table"
    )
    contour_nodes: Int = Field(
        32, ge=4, le=256, description="consistent scheme: Gauss-Legendre nodes per plate edge"
    )
    band_nodes: Int = Field(
        6,
        ge=1,
        le=24,
        description="consistent scheme: Gauss nodes across the smoothed plate edge",
    )

    footprint_widths: float = Field(
        X_SATURATION,
        ge=FOOTPRINT_WIDTHS_MIN,
        le=X_SATURATION,
        description=(
            "bodies: w, the radius of a body's footprint beyond its plate and pills in "
            "smoothing widths delta; F_k and G_k are 0 outside it. A point-value indicator "
            "is cut where its tail is 1 / (1 + e^(2w)) < e^(-2w) (20: 4.2e-18, where the "
            "tanh is saturated in float64; 10: 2.1e-9; 8: 1.1e-7; 6: 6.1e-6); the "
            "consistent scheme's circles end their contour rule there too. Contact and the "
            "walls keep the 20-width footprint (docs/bodies.md, The footprint's precision)"
        ),
    )

    def acting(self) -> dict[str, Any]:
        """The settings that change a result of this scheme (JSON values): every one for
        ``consistent``, only ``scheme``, ``integrator`` and (where set) the bodies'
        ``footprint_widths`` for ``paper``, whose point values ignore the prefilter and
        contour settings."""
        data = self.model_dump(mode="json")
        if self.scheme == "paper":
            kept = ("scheme", "integrator", "footprint_widths")
            return {key: data[key] for key in kept if key in data}
        return data


class SolverConfig(_Section):
    """Where the time steps run."""

    backend: Literal["cpu", "gpu", "auto"] = Field(
        "cpu",
        description=(
            "compute backend: cpu (fused numba kernel), gpu (needs the optional gpu extra "
            "and a GPU), auto (gpu when available, else cpu)"
        ),
    )
    threads: Int | None = Field(
        None,
        ge=1,
        description=(
            "threads one run's time steps use on the CPU (results are identical for any "
            "number); null: every core this process may use (os.sched_getaffinity) that no "
            "other process keeps busy when the run starts, at most numba's thread count "
            "(NUMBA_NUM_THREADS; 1 in the worker processes of a sweep, pde-rotor sweep "
            "--threads); bodies runs step on one thread"
        ),
    )
