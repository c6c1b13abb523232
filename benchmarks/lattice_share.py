"""How much of a long-stop plateau is the lattice torque?

Reads the stored runs of a bank-estimator sweep (``pde-rotor sweep``, estimator
``kind: bank``): every run records the torque on the stopped plate at the end of its stop
(``torque_end``) and where the released rotor went. Without noise (sigma = 0) the outcome
is a deterministic function of the stop angle. In the continuum model a long stop
(memory lost) leaves only the asymmetry torque, the same at every angle: every stop of a
Delta > 0 rotor would end CW, and the plateau would be 0. On the Cartesian grid the
spurious lattice torque (docs/model.md) adds an angle-dependent part; where it outweighs
the asymmetry torque the rotor ends in the unfavourable direction. For each point this
prints, at sigma = 0: the mean and spread over stop angles of the end-of-stop torque (per
direction before the stop: at short stops the flow's memory torque dominates it),
the share of stops ending against the sign of Delta, whether sign(torque_end) predicts the
outcome, and P itself — the plateau that the lattice alone produces.

    python benchmarks/lattice_share.py SWEEP_DIR [SWEEP_DIR ...]
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path

import numpy as np

from pde_rotor.statistics.proportions import restart_counts, two_state_chain
from pde_rotor.sweep import Sweep, read_runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep_dirs", type=Path, nargs="+")
    args = parser.parse_args()
    for sweep_dir in args.sweep_dirs:
        points: dict[str, list[dict]] = defaultdict(list)
        sweep = Sweep.load(sweep_dir)
        if sweep.spec.estimator.kind != "bank":
            print(f"{sweep_dir}: not a bank sweep")
            continue
        stored = read_runs(sweep_dir)
        for run in sweep.runs():
            content = stored.get(run.key)
            config = run.config
            if content is None or config["noise"]["sigma"] != 0:
                continue
            key = json.dumps(
                {
                    "dx": config["grid"]["dx"],
                    "Delta": config["geometry"]["asymmetry"],
                    "t_stop": config["protocol"]["t_stop"],
                    "flow": config["flow"]["enabled"],
                },
                sort_keys=True,
            )
            points[key].append(content["result"])
        print(f"{sweep_dir}: noise-free runs of the bank estimator")
        for key, results in sorted(points.items()):
            where = json.loads(key)
            torque = np.array([r["torque_end"] for r in results])
            after = np.array([r["direction_after"] for r in results])
            before = np.array([r["direction_before"] for r in results])
            spread = ", ".join(
                f"from {name}: mean {torque[before == d].mean():.3e}, "
                f"std {torque[before == d].std():.3e}"
                for d, name in ((1, "CCW"), (-1, "CW"))
                if (before == d).any()
            )
            sign = -np.sign(where["Delta"])  # Delta > 0 favours CW (-1)
            against = float(np.mean(after != sign)) if sign != 0 else float("nan")
            predicts = float(np.mean(np.sign(torque) == after))
            chain = two_state_chain(restart_counts(before.tolist(), after.tolist()))
            label = ", ".join(f"{k} = {v}" for k, v in where.items())
            print(
                f"  {label}: {len(results)} stops; torque_end over stop angles {spread}; "
                f"ends against Delta: {against:.3f}; "
                f"sign(torque_end) = outcome: {predicts:.3f}; "
                f"P = {chain.p:.3f} [{chain.low:.3f}, {chain.high:.3f}]"
            )


if __name__ == "__main__":
    main()
