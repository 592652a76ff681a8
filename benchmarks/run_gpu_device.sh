#!/usr/bin/env bash
# Issue 44's measurements in one run on a lent GPU machine (no package registry there):
#   bash benchmarks/run_gpu_device.sh [first|second]   (writes to $OUT, else /tmp/gpu-out)
# "first" (the default) is the first lent GPU's run; "second" measures what it left: each
# kernel's load from numba-cuda's disk cache in a later process, the implicit kernel's whole
# compilation (the first run killed it at 150 s), JAX in one launch, Ctrl-C and the design study.
# Wheels of the packages the machine lacks travel in .whl/ (pint, pydantic, dask, ...), the
# kernels' inputs of step 0 in .gpu/lanes.npz (bench_gpu.py --write-lanes .gpu/lanes.npz
# --samples 32768: 19 MB); numba, numba-cuda and JAX are the machine's own. Each step is one process with a time limit;
# a step is skipped when less than its limit is left of BUDGET_S (default 450 s). Rows go to
# $OUT/rows.jsonl, the saved lanes to $OUT/*.npz (compare them on the CPU afterwards:
# python benchmarks/bench_gpu.py --compare FILE), everything printed to $OUT/log.txt.
set -u
OUT=${OUT:-/tmp/gpu-out}
mkdir -p "$OUT"
exec > >(tee -a "$OUT/log.txt") 2>&1
export PYTHONUNBUFFERED=1
end=$(( $(date +%s) + ${BUDGET_S:-450} ))
if ls .whl/*.whl >/dev/null 2>&1; then
    python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
        --target /tmp/site .whl/*.whl || exit 1
fi
export PYTHONPATH=$PWD/src:/tmp/site
export NUMBA_CACHE_DIR=/tmp/numba-cache JOINTPLAY_JAX_CACHE=/tmp/jax-cache
rm -rf "$NUMBA_CACHE_DIR" "$JOINTPLAY_JAX_CACHE"  # step 0 and JAX's first run are cold
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv
python3 - <<'EOF'
import importlib.metadata as m, os, platform
print(platform.python_version(), os.cpu_count(), "CPUs", platform.processor())
for name in ("numpy", "scipy", "pandas", "numba", "llvmlite", "numba-cuda", "jax", "jaxlib",
             "cuda-bindings", "pint", "pydantic"):
    try:
        print(name, m.version(name))
    except m.PackageNotFoundError:
        print(name, "missing")
EOF
python3 -c 'from numba import cuda; import importlib.metadata as m
print("numba-cuda", m.version("numba-cuda"), "sees", cuda.get_current_device().name)'
rows="$OUT/rows.jsonl"
mode=${1:-first}
cpu_kernels() {  # cpu_kernels TITLE: what importing eom compiles, in the background (cpu_pid)
    echo "=== $(date -u +%T) $1"
    timeout 240 python3 -c "import time; t = time.perf_counter(); import jointplay._kernels.eom
print(f'CPU kernels (import jointplay._kernels.eom) compiled in {time.perf_counter() - t:.1f} s')" &
    cpu_pid=$!
}
bench() {  # bench LIMIT_S ARGS...: one process of bench_gpu.py, if LIMIT_S is left
    local limit=$1; shift
    local left=$(( end - $(date +%s) ))
    if (( left < limit )); then echo "SKIPPED ($left s left < $limit): $*"; return; fi
    echo "=== $(date -u +%T) bench_gpu.py $*"
    timeout "$limit" python3 benchmarks/bench_gpu.py --json "$rows" "$@"
    echo "=== rc $?"
}
if [[ $mode == first ]]; then
# 0. side by side: the CPU kernels' first compilation (the batch engine's set-up, the same
#    for every backend, once per install) and the numba-cuda kernels on the inputs of
#    .gpu/lanes.npz (bench_gpu.py --write-lanes: they need none of the CPU kernels): each
#    kernel's cold compilation, then one launch per size
cpu_kernels "CPU kernels beside the lanes"
timeout 200 python3 benchmarks/bench_gpu.py --json "$rows" --part lanes --inputs .gpu/lanes.npz \
    --problems conventional --samples 100000 1000000 --budget 60 --save-lanes 4000 \
    --save "$OUT/lanes.npz"
timeout 150 python3 benchmarks/bench_gpu.py --json "$rows" --part lanes --inputs .gpu/lanes.npz \
    --problems physical --samples 10000 100000 --budget 60 --save-lanes 2000 \
    --save "$OUT/lanes.npz"
wait "$cpu_pid"  # (a plain wait would wait for the log's tee too)
# 1. Ctrl-C inside a launch
if (( end - $(date +%s) > 60 )); then
    echo "=== $(date -u +%T) bench_gpu_interrupt.py"
    timeout 60 python3 benchmarks/bench_gpu_interrupt.py --json "$OUT/interrupt.json"
    echo "=== rc $?"
fi
# 2. the design study on cuda (the physical default)
bench 150 --part design --backends cuda --samples 10000
# 3. through simulate_batch: the executor's chunks, then one launch; JAX in one launch
bench 40 --part conventional --backends cuda --samples 100000 100000 --chunks 0 100000
bench 40 --part conventional --backends gpu --samples 100000 --chunks 100000
else
# every process is timed from its start; the log's timestamps say what ran beside what.
# a. the CPU kernels (JAX's simulate_batch needs them), beside the two cuda kernels' cold
#    compilations (CPU-bound NVVM; 16 cores); then each cuda kernel again in a later process
cpu_kernels "CPU kernels, explicit and implicit cuda kernels side by side"
timeout 380 python3 benchmarks/bench_gpu.py --json "$rows" --part lanes --inputs .gpu/lanes.npz \
    --problems physical --samples 10000 100000 --budget 60 --save-lanes 2000 \
    --save "$OUT/lanes.npz" > "$OUT/implicit.txt" 2>&1 &
implicit_pid=$!
timeout 200 python3 benchmarks/bench_gpu.py --json "$rows" --part lanes --inputs .gpu/lanes.npz \
    --problems conventional --samples 100000
echo "=== $(date -u +%T) the explicit kernel again, a later process (numba-cuda's disk cache)"
timeout 60 python3 benchmarks/bench_gpu.py --json "$rows" --part lanes --inputs .gpu/lanes.npz \
    --problems conventional --samples 100000
echo "=== $(date -u +%T) bench_gpu_interrupt.py"
timeout 60 python3 benchmarks/bench_gpu_interrupt.py --json "$OUT/interrupt.json"
echo "=== rc $?"
wait "$cpu_pid"
bench 90 --part conventional --backends gpu --samples 100000 --chunks 100000
bench 40 --part conventional --backends gpu --samples 100000 --chunks 100000
wait "$implicit_pid"
echo "=== $(date -u +%T) implicit kernel (began at the start):"; cat "$OUT/implicit.txt"
bench 40 --part lanes --inputs .gpu/lanes.npz --problems physical --samples 10000
bench 150 --part design --backends cuda --samples 10000
fi
echo "=== done $(date -u +%T)"
