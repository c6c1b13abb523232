"""Figures of the stability analysis: an eigenmode and a branch.

:func:`plot_mode` draws a mode the way it acts: the camphor perturbation dc (the real part
of the mode at the phase where the body's velocity is largest), the flow perturbation dv
as arrows on it, the bodies' outlines at rest and the arrow or arc of their motion.
:func:`plot_branch` draws the leading eigenvalues' real and imaginary parts against the
parameter, with each critical value and its kind.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from .continuation import Branch
from .eigen import Spectrum
from .linear import Linearisation


def _phase_aligned(mode: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The real part of a complex mode at the phase where |dp| is largest."""
    dp = mode["dp"]
    j = int(np.argmax(np.abs(dp))) if dp.size else 0
    phase = np.exp(-1j * np.angle(dp[j])) if dp.size and abs(dp[j]) > 0 else 1.0
    return {name: np.real(value * phase) for name, value in mode.items()}


def _draw_motion(ax: plt.Axes, centre: tuple[float, float], motion: dict[str, float]) -> None:
    """A body's velocity in the mode: an arrow for U, the sign of omega as text."""
    u, v = motion.get("u", 0.0), motion.get("v", 0.0)
    if abs(u) + abs(v) > 1e-3:
        end = (centre[0] + 0.4 * u, centre[1] + 0.4 * v)
        ax.annotate("", xy=end, xytext=centre, arrowprops={"color": "darkgreen", "width": 2})
    if abs(motion.get("omega", 0.0)) > 1e-3:
        turn = "ccw" if motion["omega"] > 0 else "cw"
        ax.annotate(turn, centre, ha="center", va="center", fontsize=10, color="darkgreen")


def plot_mode(lin: Linearisation, spectrum: Spectrum, index: int, path: Path) -> Path:
    """One eigenmode: dc (colour), dv (arrows, with flow), the bodies and their motion.

    Args:
        lin: the linearisation.
        spectrum: its eigenvalues and vectors.
        index: which mode.
        path: the PNG to write.
    """
    lam = complex(spectrum.eigenvalues[index])
    mode = _phase_aligned(lin.split(spectrum.vectors[:, index], lam))
    model = lin.model
    x, y = model.coordinates
    dc = np.where(model.c_mask, mode["dc"], np.nan)
    dofs = model.dofs
    largest = np.abs(mode["dp"]).max(initial=0.0) or 1.0
    motions: dict[int, dict[str, float]] = {}
    for dof, value in zip(dofs, mode["dp"] / largest, strict=True):
        motions.setdefault(dof.body, {})[dof.velocity] = float(value)
    centres = [(0.0, 0.0)] if model.rotor else [tuple(b.start[:2]) for b in model.pde.bodies]
    if model.rotor:
        reach = 2.5 * model.config.geometry.radius
    else:
        reach = max(3 * b.shape.reach for b in model.pde.bodies)
    fig, axes = plt.subplots(1, 2, figsize=(11, 5), layout="constrained")
    for ax, zoom in zip(axes, (False, True), strict=True):
        scale = np.nanmax(np.abs(dc)) or 1.0
        mesh = ax.pcolormesh(x, y, dc, cmap="RdBu_r", vmin=-scale, vmax=scale, shading="auto")
        f = model.plate_indicator(model.q0)
        ax.contour(x, y, f, levels=[0.5], colors="k", linewidths=0.8)
        ax.contour(x, y, lin.rest.c, levels=6, colors="0.5", linewidths=0.4)
        if lin.layout.flow:
            step = max(1, x.shape[0] // (40 if not zoom else 120))
            dv = mode["dv"]
            ax.quiver(
                x[::step, ::step], y[::step, ::step], dv[0][::step, ::step], dv[1][::step, ::step],
                color="k", alpha=0.6, scale=25 * (np.abs(dv).max() or 1.0), scale_units="width",
            )  # fmt: skip
        for k, centre in enumerate(centres):
            _draw_motion(ax, centre, motions.get(k, {}))
        if zoom:
            cx, cy = np.mean(centres, axis=0)
            ax.set(xlim=(cx - reach, cx + reach), ylim=(cy - reach, cy + reach))
        ax.set_aspect("equal")
        ax.set(xlabel="x", ylabel="y")
    fig.colorbar(mesh, ax=axes, label="dc (mode, real part)")
    motion = ", ".join(
        f"{dof.label} {value:+.3g}" for dof, value in zip(dofs, mode["dp"] / largest, strict=True)
    )
    fig.suptitle(
        f"mode {index}: lambda = {lam.real:.5g} {lam.imag:+.5g}i "
        f"(residual {spectrum.residuals[index]:.1e}); body motion: {motion}",
        fontsize=10,
    )
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_branch(branch: Branch, path: Path, title: str = "") -> Path:
    """Re lambda and Im lambda of the leading eigenvalues against the parameter."""
    fig, (ax_re, ax_im) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, layout="constrained")
    for j in range(branch.eigenvalues.shape[1]):
        style = {"color": "k", "lw": 1.6} if j == 0 else {"color": "0.6", "lw": 0.8}
        ax_re.plot(branch.values, branch.eigenvalues[:, j].real, "o-", ms=3, **style)
        ax_im.plot(branch.values, branch.eigenvalues[:, j].imag, "o-", ms=3, **style)
    ax_re.axhline(0, color="k", lw=0.5)
    for cross in branch.crossings:
        label = f"{cross.kind} at {cross.value:.6g}"
        if cross.kind == "hopf":
            label += f", omega = {cross.frequency:.4g}"
        for ax in (ax_re, ax_im):
            ax.axvline(cross.value, color="tab:red", ls="--", lw=1)
        ax_re.annotate(label, (cross.value, 0), xytext=(5, 5), textcoords="offset points",
                       color="tab:red", fontsize=9)  # fmt: skip
    ax_re.set(ylabel="Re lambda (growth rate)", title=title)
    ax_im.set(xlabel=branch.key, ylabel="Im lambda (frequency)")
    for ax in (ax_re, ax_im):
        ax.grid(alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
