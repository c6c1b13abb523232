"""Paper Fig. 8: inversion probability without the surface flow (v = 0).

P against t_stop for Delta = 0, 2e-5 and 1e-4 with v = 0 in Eqs. (eqc) and (eq_motion)
(sweep ``fig8``: a stored report from data/ if present, else configs/sweeps/fig8.yaml or
fig8_quick.yaml through :mod:`pde_rotor.sweep`; ``--tiny``: a shrunken copy). Markers as
in the paper: red closed circles Delta = 0, green open triangles 2e-5, blue open squares
1e-4. The paper: no systematic inversion for any t_stop; random direction for Delta = 0,
always the favourable direction for 1e-4, the favourable one with probability 0.8 for
2e-5 (P = 2ab/(a+b) = 0.32 of the two-state chain with a = 0.8, b = 0.2); each is
marked in its curve's colour (dash-dotted,
:data:`pde_rotor.gallery.sweeps.PAPER_CLAIMS`). Dashed: the decision model's
prediction without flow, where data/decision/ holds the
report's model.

Run: ``python gallery/fig8_no_flow.py [--quick | --tiny]``.
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
    MODEL_LABEL,
    STOP_LABEL,
    curve,
    draw_model,
    draw_paper_claims,
    draw_paper_points,
    errorbar_p,
    print_points,
    probability_axes,
    probability_footer,
    sweep_data,
)

NAME = "fig8_no_flow"
SWEEP = "fig8"
STYLES = {
    0.0: {"fmt": "o-", "color": "tab:red"},
    2e-5: {"fmt": "^-", "color": "tab:green", "mfc": "white"},
    1e-4: {"fmt": "s-", "color": "tab:blue", "mfc": "white"},
}


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Load or run the sweep, write Fig. 8 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    data = sweep_data(SWEEP, args.fidelity, args.out)
    report = data.report
    deltas = report["asymmetry"].values if "asymmetry" in report.dims else [None]
    fig = new_figure(7.0, 5.0)
    ax = fig.subplots()
    paper = model = ""
    for k, delta in enumerate(deltas):
        ds = curve(report, "t_stop", **({} if delta is None else {"asymmetry": delta}))
        value = float(ds["asymmetry"]) if "asymmetry" in ds.coords else 0.0
        style = STYLES.get(value, {"fmt": "d-", "color": "0.3"})
        x = ds["t_stop"].values
        dodge = 0.03 * (k - (len(deltas) - 1) / 2)  # keep the error bars apart
        errorbar_p(ax, x + dodge, ds, label=f"\u0394 = {value:g}", **style)
        print_points(f"{NAME}: Delta = {value:g}, ", "t_stop", x, ds)
        colour = style["color"]
        # over the whole design: without flow the prediction is flat, measured or not
        span = (float(x.min()), float(x.max()))
        prefix = f"{NAME}: Delta = {value:g}, "
        model = draw_model(ax, prefix, ds, "t_stop", colour, span, label=None) or model
        draw_paper_claims(ax, SWEEP, asymmetry=value, color=colour)
        found = draw_paper_points(
            ax,
            f"{NAME}: Delta = {value:g}, ",
            "t_stop",
            {"fmt": "D", "color": colour, "mfc": colour, "mec": "k", "ms": 8, "label": None},
            asymmetry=value,
            enabled=0.0,
        )
        paper = found or paper
    probability_axes(ax, STOP_LABEL)
    if model:
        ax.plot([], [], "--", color="0.5", label=f"{MODEL_LABEL}, in the curve colours")
    if paper:
        ax.plot([], [], "D", color="0.5", mec="k", label="paper resolution (diamonds)")
    ax.legend(fontsize=8)
    ax.set_title(
        "Fig. 8: no flow (v = 0); paper: no systematic inversion for any t_stop",
        fontsize=10,
    )
    add_footer(
        fig, "\n".join(filter(None, [probability_footer(args.fidelity, data), model, paper]))
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
