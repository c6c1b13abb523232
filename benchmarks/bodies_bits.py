"""Save and compare a bodies run's numbers, to check that two checkouts agree bit for bit.

``save`` runs a config with ``bodies:`` (with ``--set`` overrides, as the CLI takes them)
and writes every sampled column of the bodies' time series (poses, velocities, tension
forces and torques, drags, friction, stops: Eq. (eq_motion)'s inputs and outputs) and the
final concentration field (Eq. (eqc)) to one ``.npz``. ``compare`` prints, per quantity,
the largest absolute and relative difference between two such files and exits 1 where
one exceeds ``--tol`` (relative to the largest magnitude of the quantity's family of
columns with one unit, :data:`FAMILIES`, or of the quantity itself).
Run ``save`` once under each checkout's PYTHONPATH with the same overrides::

    PYTHONPATH=/path/a python benchmarks/bodies_bits.py save configs/bodies/free_disk.yaml \
        a.npz --set protocol.t_ini=0.02
    PYTHONPATH=/path/b python benchmarks/bodies_bits.py save configs/bodies/free_disk.yaml \
        b.npz --set protocol.t_ini=0.02
    python benchmarks/bodies_bits.py compare a.npz b.npz
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def save(config: str, out: str, overrides: list[str]) -> None:
    """Run `config` with `overrides` and write its time series and final field to `out`."""
    from pde_rotor.config.yaml_io import load_config
    from pde_rotor.solver.simulation import Simulation
    from pde_rotor.trackers.bodies import BodiesTracker

    cfg = load_config(config, overrides)
    sim = Simulation(cfg)
    tracker = BodiesTracker(cfg, cfg.output.timeseries_interval, None)
    sim.run(trackers=[tracker])
    data = tracker.to_dataset()
    arrays = {
        f"ts_{name}": np.asarray(data[name].values, dtype=float)
        for name in data.data_vars
        if np.issubdtype(data[name].dtype, np.number)
    }
    arrays["time"] = np.asarray(data["time"].values, dtype=float)
    arrays["field_c"] = np.asarray(sim.state.data, dtype=float)
    arrays["final_poses"] = np.asarray(sim.bodies.poses, dtype=float)
    np.savez(out, **arrays)
    print(f"{config}: {len(arrays['time'])} samples to t = {sim.t:g}, wrote {out}")


FAMILIES = (
    ("ts_x", "ts_y"),
    ("ts_u", "ts_v"),
    ("ts_force_x", "ts_force_y", "ts_drag_x", "ts_drag_y"),
    ("ts_torque", "ts_friction"),
)
"""Columns that share a unit: each is measured against the largest of its family (a
component that vanishes by symmetry is measured against the one that does not)."""


def _scale(data: np.lib.npyio.NpzFile, key: str) -> float:
    """The largest magnitude of `key`'s family in `data` (:data:`FAMILIES`)."""
    family = next((f for f in FAMILIES if key in f), (key,))
    values = [np.abs(np.nan_to_num(data[k])).max() for k in family if k in data.files]
    return float(max(values, default=0.0))


def compare(a: str, b: str, tol: float) -> int:
    """Print the max abs/rel difference of every quantity in `a` and `b`; 1 if over `tol`."""
    left, right = np.load(a), np.load(b)
    keys = sorted(set(left.files) | set(right.files))
    worst_rel, bad = 0.0, []
    for key in keys:
        if key not in left.files or key not in right.files:
            print(f"{key:>18}: only in {a if key in left.files else b}")
            bad.append(key)
            continue
        x, y = left[key], right[key]
        if x.shape != y.shape:
            print(f"{key:>18}: shapes differ {x.shape} vs {y.shape}")
            bad.append(key)
            continue
        both_nan = np.isnan(x) & np.isnan(y)
        diff = np.where(both_nan, 0.0, np.abs(x - y))
        abs_max = float(np.nanmax(diff)) if diff.size else 0.0
        scale = _scale(left, key) if x.size else 0.0
        rel = abs_max / max(scale, 1e-300)
        worst_rel = max(worst_rel, rel)
        flag = "" if rel <= tol and not np.isnan(diff).any() else "  <-- over tol"
        if flag:
            bad.append(key)
        print(f"{key:>18}: max |a-b| = {abs_max:.3e}, rel (to its family) = {rel:.3e}{flag}")
    print(f"worst relative difference {worst_rel:.3e} (tol {tol:g}); {len(bad)} over: {bad}")
    return 1 if bad else 0


def main() -> int:
    """Command line: ``save CONFIG OUT [--set K=V ...]`` or ``compare A B [--tol T]``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p_save = sub.add_parser("save", help="run a bodies config and save its numbers")
    p_save.add_argument("config")
    p_save.add_argument("out")
    p_save.add_argument("--set", dest="overrides", action="append", default=[])
    p_cmp = sub.add_parser("compare", help="compare two saved files")
    p_cmp.add_argument("a")
    p_cmp.add_argument("b")
    p_cmp.add_argument("--tol", type=float, default=1e-12)
    args = parser.parse_args()
    if args.command == "save":
        save(args.config, args.out, args.overrides)
        return 0
    return compare(args.a, args.b, args.tol)


if __name__ == "__main__":
    sys.exit(main())
