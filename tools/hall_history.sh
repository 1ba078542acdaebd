#!/bin/sh
# tools/hall_history.sh - the many-lamp hall's cost and error across commits
#
#   sh tools/hall_history.sh [--spp S] [--seeds K] [--ref-spp R] COMMIT...
#
# Answers "did specnee get slower or noisier on many lamps between two commits?"
# with measures that a busy machine does not blur.  The scenes are the halls of
# tools/bench_lights --hall N (N = 4 and 1024 small lamps of six spiky spectra,
# docs/lighttree.md), written once by this checkout's bench_lights, so every
# commit renders the same files.  Each COMMIT is built in a detached worktree
# under build/hall-history/ (`make specnee`, the commit's own flags), then:
#   Ir        callgrind's instruction count of a 64x64, 8 spp, 1-thread render
#             (load, setup and render: deterministic, unlike seconds);
#   MSE       the mean over seeds 1..K of the MSE at S spp (default 32) against
#             a reference rendered by this checkout's specnee at R spp
#             (default 4096, seed 99);
#   Ir x MSE  their product: proportional to the time needed for a given error
#             when MSE falls as 1/spp, so the ratio between two commits is the
#             ratio of their times to equal error (up to the cost per
#             instruction).
# Each hall is rendered twice: with its own Sampler ("independent") and with
# the Sampler line removed (specnee's default for a file without one).
# Needs git, make, valgrind; run from the repository root after `make`.
set -eu
spp=32; seeds=6; refspp=4096
while [ $# -gt 0 ]; do
    case "$1" in
        --spp) spp=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        --ref-spp) refspp=$2; shift 2 ;;
        -*) echo "hall_history: unknown option $1" >&2; exit 2 ;;
        *) break ;;
    esac
done
[ $# -ge 1 ] || { echo "usage: sh tools/hall_history.sh [--spp S] [--seeds K] [--ref-spp R] COMMIT..." >&2; exit 2; }
command -v valgrind >/dev/null || { echo "hall_history: needs valgrind" >&2; exit 2; }
[ -x ./specnee ] && [ -x tools/bench_lights ] || make -s specnee tools/bench_lights
out=build/hall-history
mkdir -p "$out"
for n in 4 1024; do
    tools/bench_lights --hall $n "$out/hall$n.pbrt" > /dev/null
    grep -v '^Sampler' "$out/hall$n.pbrt" > "$out/hall$n-default.pbrt"
    [ -f "$out/ref$n.pfm" ] || ./specnee -q --spp "$refspp" --seed 99 -o "$out/ref$n.pfm" "$out/hall$n.pbrt"
done
printf '%-10s %-14s %12s %12s %12s\n' commit scene Ir "MSE@$spp" "Ir x MSE"
for c in "$@"; do
    w=$out/wt-$c
    [ -d "$w" ] || git worktree add -q --detach "$w" "$c"
    (cd "$w" && make -s specnee > /dev/null 2>&1) || { echo "hall_history: $c does not build" >&2; exit 1; }
    for n in 4 1024; do
        for v in "" -default; do
            f=$out/hall$n$v.pbrt
            ir=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$w/specnee" -q --spp 8 \
                   --seed 1 --threads 1 -o "$out/ir.pfm" "$f" 2>&1 | sed -n 's/.*Collected : \([0-9]*\).*/\1/p')
            s=1; : > "$out/mse.txt"
            while [ $s -le "$seeds" ]; do
                "$w/specnee" -q --spp "$spp" --seed $s --threads 1 -o "$out/t.pfm" "$f"
                ./specnee diff "$out/t.pfm" "$out/ref$n.pfm" | awk '$1 == "image" { print $7 }' >> "$out/mse.txt"
                s=$((s + 1))
            done
            awk -v c="$c" -v sc="hall$n${v:-}" -v ir="$ir" '{ s += $1 } END {
                m = s / NR; printf "%-10s %-14s %12.4e %12.4e %12.4e\n", c, sc, ir, m, ir * m }' "$out/mse.txt"
        done
    done
done
