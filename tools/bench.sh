#!/bin/sh
# tools/bench.sh - the benchmarks, run by `make bench` (not part of `make test`).
#   1. tools/bench: BVH build time and memory, and ray throughput on a displaced
#      icosphere (81,920 triangles; `tools/bench 7` for 327,680, `8` for 1.3 M):
#      closest hit and any hit (shadow rays) on one thread, split into the rays that
#      miss the mesh's bounding box and those that hit it, min/median/max of 5
#      interleaved runs (`tools/bench --runs N`); closest hit on all threads.
#   2. Renders at 16 spp of the Cornell box, of its dispersive-glass variant (rough
#      dispersion terminated and kept alive by spectral MIS) and, per emitter-selection
#      strategy, of cornell1; plus tools/bench_lights (table build, ns per vertex).
#   3. Many emitters (docs/lighttree.md): tools/bench_lights --many, N = 4 .. 4096
#      lamps in a generated hall: build time, ns per selection + pmf, CPU time per
#      sample and table memory per strategy, with the log-log chart
#      out/lighttree-cost.svg (docs/lighttree-cost.svg is a copy of one run) and
#      out/lighttree-cost.csv; then the peak memory of the whole specnee process
#      (/usr/bin/time, where present) rendering the hall with 1024 lamps.
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
    for st in uniform power spatial spd product spectral-spatial all tree spectral-tree; do
        line=$(./specnee $sc --spp 16 --lights $st -o out/bench_lights.pfm 2>&1 | tail -n 1)
        t=$(echo "$line" | sed -n 's/.* in \([0-9.]*\) s wall.*/\1/p')
        [ -z "$base" ] && base=$t
        printf '%-18s %8s s  x%s\n' "$st" "$t" "$(awk -v a="$t" -v b="$base" 'BEGIN { printf "%.2f", a / b }')"
    done
fi

if [ -x ./tools/bench_lights ]; then
    echo "== many emitters: cost against N (tools/bench_lights --many; CPU times, 1 thread)"
    ./tools/bench_lights --many 4096 --runs 5 --svg out/lighttree-cost.svg --csv out/lighttree-cost.csv
    if [ -x /usr/bin/time ] && [ -x ./specnee ]; then
        echo "== peak memory of the process, hall with 1024 lamps, 64x64, 4 spp, 1 thread"
        ./tools/bench_lights --hall 1024 out/hall1024.pbrt
        for st in uniform power spatial product tree spectral-tree; do
            kb=$( { /usr/bin/time -f "%M" ./specnee out/hall1024.pbrt -q --threads 1 --lights $st \
                    -o out/hall1024.pfm 2>&1 >/dev/null; } | tail -n 1)
            printf '%-14s %8s MB\n' "$st" "$(awk -v k="$kb" 'BEGIN { printf "%.1f", k / 1024 }')"
        done
    fi
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
