#!/bin/sh
# tools/bench.sh - the benchmarks, run by `make bench` (not part of `make test`).
#   1. tools/bench: BVH build time and ray throughput on a displaced icosphere
#      (81,920 triangles; `tools/bench 7` for 327,680), 1 thread and all threads.
#   2. Renders at 16 spp of the Cornell box, of its dispersive-glass variant (rough
#      dispersion terminated and kept alive by spectral MIS) and, per emitter-selection
#      strategy, of cornell1; plus tools/bench_lights (table build, ns per vertex).
#      The Cornell render, when ./specnee and the scene exist:
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

if [ -x ./specnee ] && [ -f scenes/cornell-glass.pbrt ]; then
    echo "== render: scenes/cornell-glass.pbrt (smooth + rough dispersive glass), 16 spp"
    for mode in terminate mis; do
        printf 'rough-dispersion %-9s ' "$mode"
        ./specnee scenes/cornell-glass.pbrt --spp 16 --rough-dispersion $mode -o out/bench_glass.pfm 2>&1 | tail -n 1
    done
fi

if [ -x ./tools/bench_lights ]; then
    sc=scenes/cornell1.pbrt
    [ -f $sc ] || sc=scenes/cornell-glass.pbrt
    echo "== emitter selection: table build and per-vertex cost (tools/bench_lights $sc)"
    ./tools/bench_lights $sc
    echo "== render time per strategy, $sc at 16 spp (ratio to uniform in the same run)"
    base=""
    for st in uniform power spatial spd product spectral-spatial all; do
        line=$(./specnee $sc --spp 16 --lights $st -o out/bench_lights.pfm 2>&1 | tail -n 1)
        t=$(echo "$line" | sed -n 's/.* in \([0-9.]*\) s wall.*/\1/p')
        [ -z "$base" ] && base=$t
        printf '%-18s %8s s  x%s\n' "$st" "$t" "$(awk -v a="$t" -v b="$base" 'BEGIN { printf "%.2f", a / b }')"
    done
fi
if [ -x ./specnee ] && [ -f scenes/cornell1.pbrt ]; then
    # samplers (docs/sampling.md): the same render with each, interleaved over rounds
    # so that a busy spell of the machine slows them alike; CPU time of 1 thread
    sc=scenes/cornell1.pbrt
    rounds=${SAMPLER_ROUNDS:-3}
    echo "== CPU time per sampler, $sc at 16 spp, 1 thread, $rounds rounds (ratio to independent)"
    : > out/bench_sampler.txt
    r=0
    while [ $r -lt "$rounds" ]; do
        for smp in independent stratified sobol zsobol; do
            line=$(./specnee $sc --spp 16 --threads 1 --sampler $smp -o out/bench_sampler.pfm 2>&1 | tail -n 1)
            echo "$smp $(echo "$line" | sed -n 's/.*(\([0-9.]*\) s CPU.*/\1/p')" >> out/bench_sampler.txt
        done
        r=$((r + 1))
    done
    awk '{ t[$1] += $2; n[$1]++ } END {
        split("independent stratified sobol zsobol", order, " ")
        for (i = 1; i <= 4; i++) { s = order[i]
            printf "%-12s %8.3f s CPU (mean of %d)  x%.3f\n", s, t[s] / n[s], n[s], t[s] / t["independent"] } }' \
        out/bench_sampler.txt
fi
