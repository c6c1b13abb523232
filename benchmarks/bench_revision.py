"""ms/step of this checkout against an earlier revision, timed in turn in one run.

The speed goals compare with the code before the physics core was rewritten
(the default revision, a973f43^): the ``paper`` scheme must be >= 1.5x faster than it
was, and the default ``consistent`` scheme no dearer than the ``paper`` scheme was. The
earlier revision is checked out into a temporary git worktree; each timing is a fresh
process (compilation and a warm-up excluded) that steps the paper's rotor at the
paper's resolution (dx = delta = 0.025, dt = 1e-4, no noise) from its spin-up state.
The processes alternate (old, new paper, new consistent, ...) so that a shared,
loaded machine slows all of them alike; the ratios are taken pair by pair and their
median printed.

    python benchmarks/bench_revision.py [--rev a973f43^] [--steps 3000] [--rounds 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

TIMER = """
import sys, time
from pde_rotor import RotorConfig, Simulation
scheme, steps = sys.argv[1], int(sys.argv[2])
data = {"grid": {"dx": 0.025, "dt": 1e-4}, "geometry": {"smoothing": 0.025},
        "noise": {"sigma": 0.0}}
if scheme != "-":
    data["numerics"] = {"scheme": scheme}
sim = Simulation(RotorConfig.model_validate(data))
dt = sim.config.grid.dt
sim.run(0.2)
start = time.perf_counter()
sim.run(sim.t + steps * dt)
print((time.perf_counter() - start) / steps * 1e3)
"""


def time_step(tree: Path, cache: Path, scheme: str, steps: int) -> float:
    """ms/step of `tree`'s package, numba caching into `cache` (scheme "-": the
    revision has no numerics.scheme)."""
    env = {**os.environ, "PYTHONPATH": str(tree), "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run(
        [sys.executable, "-c", TIMER, scheme, str(steps)],
        cwd=tree,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    return float(out.stdout.split()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rev", default="a973f43^", help="earlier revision (paper scheme only)")
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp) / "old"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(old), args.rev],
            check=True,
        )
        try:
            rows = []
            for k in range(args.rounds):
                row = (
                    time_step(old, Path(tmp) / "old_cache", "-", args.steps),
                    time_step(ROOT, Path(tmp) / "new_cache", "paper", args.steps),
                    time_step(ROOT, Path(tmp) / "new_cache", "consistent", args.steps),
                )
                rows.append(row)
                print(
                    f"round {k + 1}: {args.rev} {row[0]:.3f}, paper {row[1]:.3f}, "
                    f"consistent {row[2]:.3f} ms/step",
                    flush=True,
                )
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(old)], check=True
            )
    speedup = statistics.median(r[0] / r[1] for r in rows)
    cost = statistics.median(r[2] / r[0] for r in rows)
    print(f"paper scheme: {speedup:.2f}x faster than {args.rev} (goal >= 1.5)")
    print(f"consistent scheme: {cost:.2f} x the step of {args.rev} (goal <= 1)")


if __name__ == "__main__":
    main()
