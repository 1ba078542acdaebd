#!/bin/sh
# tools/bench.sh - the benchmarks, run by `make bench` (not part of `make test`).
#   1. tools/bench: BVH build time and ray throughput on a displaced icosphere
#      (81,920 triangles; `tools/bench 7` for 327,680), 1 thread and all threads.
#   2. A render of the Cornell box at 16 spp, when ./specnee and the scene exist:
#      its closing line reports the speed in samples/s.
# Run from the repository root.  Output goes to out/.
set -e
mkdir -p out

echo "== BVH: build and ray throughput (tools/bench)"
./tools/bench "$@"

if [ -x ./specnee ] && [ -f scenes/cornell.pbrt ]; then
    echo "== render: scenes/cornell.pbrt, 16 spp"
    ./specnee scenes/cornell.pbrt --spp 16 -o out/bench_cornell.pfm 2>&1 | tail -n 1
fi
