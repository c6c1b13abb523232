"""Paper Fig. 7: inversion probability of asymmetric rotors.

(a) P against t_stop for Delta = 1e-4 (sweep ``fig7a``), (b) for Delta = 2e-5 (``fig7b``),
(c) P against Delta at t_stop = 3 (``fig7c``). Each report is a stored one from data/ if
present, else the sweep configs/sweeps/<name>.yaml (full) or <name>_quick.yaml
(``--quick``) is run through :mod:`pde_rotor.sweep` (``--tiny``: a shrunken copy). P with
its 95 % interval; faintly the conditional probabilities from CCW and from CW rotation
(for Delta > 0 CW is favoured: P(inv | CCW) > P(inv | CW)); in (a) the fall read both ways,
with its 95 % interval (:mod:`pde_rotor.statistics.crossing`): where it starts (P falls
through 0.95; the paper's "started to decay around 1") and the onset (P = 0.5). The paper:
(a) P = 1 for small t_stop, decaying near t_stop = 1 to 0; (b) a plateau near 0.2, as
in the experiment; (c) P falls from 0.5 to 0 as Delta grows (marked in grey,
:data:`pde_rotor.gallery.sweeps.PAPER_CLAIMS`). Panel (c) also draws the t_stop = 3 points of the
curves of Figs. 5, 7(a) and 7(b) (open squares) where their stored reports hold the
model of ``fig7c``: fig7c need not measure Delta = 0, 2e-5 and 1e-4 again. Dashed: the
decision model's prediction, where data/decision/ holds a panel's model.

Run: ``python gallery/fig7_probability.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pde_rotor.gallery.common import (
    add_footer,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.gallery.sweeps import (
    ASYMMETRY_LABEL,
    STOP_LABEL,
    curve,
    draw_conditionals,
    draw_crossing,
    draw_model,
    draw_paper_claims,
    draw_paper_points,
    draw_shared_points,
    errorbar_p,
    print_points,
    probability_axes,
    probability_footer,
    sweep_data,
)
from pde_rotor.statistics.crossing import DECAY_START_LEVEL, ONSET_LEVEL

NAME = "fig7_probability"
PANELS = (
    ("fig7a", "t_stop", "(a) \u0394 = 1e-4; paper: 1 at small t_stop, decays near 1 to 0"),
    ("fig7b", "t_stop", "(b) \u0394 = 2e-5; paper: plateau \u2248 0.2 (as the experiment)"),
    ("fig7c", "asymmetry", "(c) t_stop = 3; paper: P falls from 0.5 to 0 with \u0394"),
)
CURVES = ({"asymmetry": 1e-4}, {"asymmetry": 2e-5}, {"t_stop": 3.0})
"""The fixed setting of each panel, to find its paper-resolution points."""
SHARED = ("fig5", "fig7a", "fig7b")
"""Sweeps whose t_stop = 3 points lie on panel (c): Delta = 0, 1e-4 and 2e-5."""


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Load or run the three sweeps, write Fig. 7 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fig = new_figure(15.0, 5.2)
    axes = fig.subplots(1, 3)
    footers = []
    paper = shared = model = ""
    for ax, (sweep, x_dim, title), fixed in zip(axes, PANELS, CURVES, strict=True):
        data = sweep_data(sweep, args.fidelity, args.out)
        ds = curve(data.report, x_dim)
        x = ds[x_dim].values
        errorbar_p(ax, x, ds, fmt="o-", color="tab:blue", label="P (95 % CI)")
        draw_conditionals(ax, x, ds)
        prefix = f"{NAME} {sweep}: "
        if sweep == "fig7a":
            draw_crossing(ax, prefix, ds, DECAY_START_LEVEL, "fall starts")
            draw_crossing(ax, prefix, ds, ONSET_LEVEL, "onset")
        span = None
        if sweep == "fig7c":
            shared = draw_shared_points(ax, prefix, x_dim, SHARED, sweep, t_stop=3.0)
            span = (0.0, 1e-4)
        model = draw_model(ax, prefix, ds, x_dim, "tab:blue", span) or model
        paper = draw_paper_points(ax, prefix, x_dim, enabled=1.0, **fixed) or paper
        draw_paper_claims(ax, sweep)
        probability_axes(ax, STOP_LABEL if x_dim == "t_stop" else ASYMMETRY_LABEL)
        if x_dim == "asymmetry":
            ax.ticklabel_format(axis="x", style="sci", scilimits=(0, 0))
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=8)
        footers.append(f"({sweep[-1]}) {probability_footer(args.fidelity, data)}")
        print_points(f"{NAME} {sweep}: ", x_dim, x, ds)
    fig.suptitle("Fig. 7: inversion probability of asymmetric rotors", fontsize=11)
    # one footer paragraph per panel: the three sweeps may come at different fidelities
    add_footer(fig, "\n".join(filter(None, [*footers, model, shared, paper])))
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
