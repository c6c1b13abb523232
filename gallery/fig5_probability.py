"""Paper Fig. 5: inversion probability P against t_stop for the symmetric rotor (Delta = 0).

Reads the report of the sweep ``fig5`` (:func:`pde_rotor.sweep.report`): a stored one
from data/ if present, else it runs configs/sweeps/fig5.yaml (full) or fig5_quick.yaml
(``--quick``) through :mod:`pde_rotor.sweep` (``--tiny``: a shrunken copy). P is drawn
with its 95 % interval, and faintly the conditional probabilities from CCW and CW
rotation, and the decay read both ways with its 95 % interval
(:mod:`pde_rotor.statistics.crossing`): where it starts (P falls through 0.95) and its
halfway point (P = 0.75); and dashed the decision model's prediction where
data/decision/ holds the report's model. The paper: P = 1 for small t_stop, decaying
near t_stop = 1.4 to 0.5 (marked in grey, :data:`pde_rotor.gallery.sweeps.PAPER_CLAIMS`).

Run: ``python gallery/fig5_probability.py [--quick | --tiny]``.
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
    STOP_LABEL,
    curve,
    draw_conditionals,
    draw_crossing,
    draw_model,
    draw_paper_claims,
    draw_paper_points,
    errorbar_p,
    print_points,
    probability_axes,
    probability_footer,
    sweep_data,
)
from pde_rotor.statistics.crossing import DECAY_LEVEL, DECAY_START_LEVEL

NAME = "fig5_probability"
SWEEP = "fig5"


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Load or run the sweep, write Fig. 5 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    data = sweep_data(SWEEP, args.fidelity, args.out)
    ds = curve(data.report, "t_stop")
    x = ds["t_stop"].values
    fig = new_figure(7.0, 5.0)
    ax = fig.subplots()
    errorbar_p(ax, x, ds, fmt="o-", color="tab:red", label="P (95 % CI)")
    draw_conditionals(ax, x, ds)
    decay = [
        draw_crossing(ax, f"{NAME}: ", ds, level, name)
        for level, name in ((DECAY_START_LEVEL, "decay starts"), (DECAY_LEVEL, "decay point"))
    ]
    model = draw_model(ax, f"{NAME}: ", ds, "t_stop", "tab:red")
    paper = draw_paper_points(ax, f"{NAME}: ", "t_stop", asymmetry=0.0, enabled=1.0)
    draw_paper_claims(ax, SWEEP)
    probability_axes(ax, STOP_LABEL)
    ax.legend(fontsize=8)
    ax.set_title(
        "Fig. 5: symmetric rotor (\u0394 = 0); paper: P = 1 for small t_stop, "
        "\u2192 0.5 for long stops",
        fontsize=10,
    )
    add_footer(
        fig,
        "\n".join(
            filter(
                None,
                [
                    probability_footer(args.fidelity, data),
                    *(line.removeprefix(f"{NAME}: ") for line in decay),
                    model,
                    paper,
                ],
            )
        ),
    )
    print_points(f"{NAME}: ", "t_stop", x, ds)
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
