#!/usr/bin/env bash
# One-command check of the GPU ensemble backend on a machine with an NVIDIA GPU.
#
#   bash benchmarks/gpu_check.sh [--tiny] [options of benchmarks/gpu_check.py]
#
# Creates .venv-gpu in the checkout and installs the package with the test and gpu extras
# into it (skipped when PYTHON names an interpreter to use instead), then runs
# benchmarks/gpu_check.py: device, CUDA tests on the device, member-steps/s of GPU and CPU
# at the paper grid, a small sweep on both backends compared. Results go to $OUT if set,
# else ./gpu_check (gpu_check_results.json and .txt); the exit status is non-zero if a
# check failed. --tiny (or GPU_CHECK_TINY=1) runs it all in numba's CUDA simulator at a
# tiny size, e.g. without a GPU:  PYTHON=.venv/bin/python bash benchmarks/gpu_check.sh --tiny
set -euo pipefail

cd "$(dirname "$0")/.."
tiny=${GPU_CHECK_TINY:-0}
for arg in "$@"; do
    if [ "$arg" = "--tiny" ]; then tiny=1; fi
done

if [ -z "${PYTHON:-}" ]; then
    start=$SECONDS
    python3 -m venv .venv-gpu
    .venv-gpu/bin/pip install -q --upgrade pip
    .venv-gpu/bin/pip install -q -e ".[test,gpu]"
    PYTHON=.venv-gpu/bin/python
    export GPU_CHECK_INSTALL_S=$((SECONDS - start))
fi

if [ "$tiny" = 1 ]; then
    export NUMBA_ENABLE_CUDASIM=1 GPU_CHECK_TINY=1
else
    export NUMBA_ENABLE_CUDASIM=0
fi
exec "$PYTHON" benchmarks/gpu_check.py "$@"
