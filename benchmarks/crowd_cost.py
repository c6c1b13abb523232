"""A collective sweep's cost estimate against the CPU time its stored runs took.

For every stored run of a collective sweep (default: configs/sweeps/crowd_dish.yaml and
its store data/sweeps/crowd_dish), prints the estimate of ``pde-rotor sweep --dry-run``
for that run alone (:func:`pde_rotor.sweep.cost.estimate_sweep`, one idle core) beside
the CPU time its worker spent on it (``cpu_time`` of its record: CPU seconds, which the
load of other work does not inflate), and their ratio. A run that ended early (two
footprints met) is compared with the estimate of its steps scaled to the time it reached
(its last record; one that ended before it is left out) and the run's set-up
(:data:`pde_rotor.sweep.cost.COLLECTIVE_SET_UP_SECONDS`). The totals compare the runs
that reached t_end.

Run:  python benchmarks/crowd_cost.py [SWEEP_FILE [STORE]]
"""

from __future__ import annotations

import sys
from pathlib import Path

from pde_rotor.config import RotorConfig
from pde_rotor.sweep import Sweep, read_runs
from pde_rotor.sweep.cost import COLLECTIVE_SET_UP_SECONDS, estimate_sweep


def main(argv: list[str]) -> None:
    sweep_file = Path(argv[0] if argv else "configs/sweeps/crowd_dish.yaml")
    store = Path(argv[1]) if len(argv) > 1 else Path("data/sweeps") / sweep_file.stem
    sweep = Sweep.load(sweep_file)
    stored = read_runs(store)
    full_estimate = full_measured = 0.0
    print("coords | reached / t_end | estimate s | cpu s | cpu / estimate | wall s")
    for run in sweep.runs():
        record = stored.get(run.key)
        if record is None or "cpu_time" not in record:
            continue
        estimate = estimate_sweep([run], None).core_seconds
        t_end = RotorConfig.model_validate(run.config).protocol.t_end
        reached = record["result"]["t"][-1] if record["result"]["end"] else t_end
        steps = estimate - COLLECTIVE_SET_UP_SECONDS
        scaled = COLLECTIVE_SET_UP_SECONDS + steps * reached / t_end
        if not scaled:
            continue  # ended before its first record
        cpu = record["cpu_time"]
        coords = ", ".join(f"{k.rsplit('.', 1)[-1]} = {v}" for k, v in run.coords.items())
        print(
            f"{coords} | {reached:g} / {t_end:g} | {scaled:.1f} | {cpu:.1f} | "
            f"{cpu / scaled:.2f} | {record['wall_time']:.1f}"
        )
        if not record["result"]["end"]:
            full_estimate += estimate
            full_measured += cpu
    if full_estimate:
        print(
            f"runs that reached t_end: estimate {full_estimate:.1f} s, cpu {full_measured:.1f} s, "
            f"cpu / estimate {full_measured / full_estimate:.2f}"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
