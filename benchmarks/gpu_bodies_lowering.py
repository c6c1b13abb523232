"""Type and lower the bodies' CUDA kernel for a GPU (sm_90) without a GPU.

numba-cuda's front end and lowering run on the CPU; only the last stage (NVVM to PTX)
needs the CUDA toolkit's libraries. This compiles
:func:`pde_rotor.kernels.cuda_bodies._advance_bodies` for the real CUDA target (not the
simulator) up to its LLVM IR, with the argument types the host passes
(:class:`pde_rotor.backends.gpu_bodies.BodiesBatch`): a typing or lowering error the
simulator cannot see (it runs the kernel as Python) shows here.

Run:  PYTHONPATH=. python benchmarks/gpu_bodies_lowering.py [paper|consistent]
      [absorbing|no_flux]   (about 2 minutes)
"""

from __future__ import annotations

import os
import sys
import time

os.environ["NUMBA_ENABLE_CUDASIM"] = "0"  # the real target, before numba-cuda is imported

import numpy as np
from numba import typeof
from numba.cuda.compiler import _compile_pyfunc_with_fixup

from pde_rotor import RotorConfig
from pde_rotor.kernels import cuda_bodies
from pde_rotor.kernels.records import make_body_records, make_body_tables, make_record
from pde_rotor.kernels.wall import NO_WALL
from pde_rotor.model.surface import POSE_COLUMNS, SurfacePDE


def main(scheme: str = "paper", wall: str = "absorbing") -> None:
    """Print the size of the kernel's LLVM IR and the time taken."""
    cfg = RotorConfig.model_validate(
        {
            "grid": {"dx": 0.1, "dt": 1e-3, "domain_radius": 1.6, "wall": wall},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": [
                {
                    "plate": {"shape": "disk", "radius": 0.2},
                    "pills": [{"x": 0.1, "radius": 0.06}],
                    "motion": {"kind": "free", "mass": 1e-3},
                }
            ],
        }
    )
    pde = SurfacePDE(cfg)
    n = pde.domain.coords.size
    nn, e = n * n, 2
    rec, pills = make_body_records(pde.setup.at(1e-3))
    tables = make_body_tables(pde.bodies, pde.body_scheme, rec, n)[:7]
    coords, lo, hi, _, _ = pde.domain.arrays()
    cells = pde.domain.cut_cells
    args = (
        (np.zeros(9 * e * nn), np.zeros((e, nn)), np.zeros((e, nn)), np.zeros((e, nn), np.int64)),
        (coords, np.stack([lo, hi]).astype(np.int64)),
        np.stack([rec] * e),
        (
            np.stack([pills] * e),
            np.zeros((e, 1, len(POSE_COLUMNS))),
            np.zeros((e, 1, 3)),
            np.zeros((e, 1, 4), np.int64),
        ),
        (
            np.zeros((e, 1, 2, 1)),
            np.zeros((e, 2, 1)),
            np.zeros((e, 1, 2, 9)),
            np.zeros((e, 1, 6)),
            np.zeros((e, nn)),
        ),
        tuple(np.ascontiguousarray(t) for t in tables),
        (NO_WALL if cells is None else cells.arrays(0.1), np.zeros((e, nn))),
        np.stack([make_record(pde.setup.at(1e-3))[0]] * e),
        (np.zeros((e, 4)), np.zeros((e, 4), np.int64)),
        (np.int64(0),) * 4,
    )
    start = time.perf_counter()
    library, _ = _compile_pyfunc_with_fixup(
        cuda_bodies._advance_bodies,
        tuple(typeof(a) for a in args),
        device=False,
        cc=(9, 0),
        launch_bounds=(128,),
        abi="numba",
    )
    size = len(library.get_llvm_str())
    print(
        f"{scheme}, {wall}: typed and lowered for sm_90, LLVM IR {size} characters, "
        f"{time.perf_counter() - start:.0f} s"
    )


if __name__ == "__main__":
    main(*sys.argv[1:3])
