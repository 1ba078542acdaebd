#!/bin/sh
# tools/load_curve.sh - load time and peak memory against the number of emitters
# (docs/loading.md): for each N, tools/gen_spheres.sh writes N emissive spheres
# (and, with "material", a Material per sphere; with "plain", N spheres lit by one lamp), and each renderer given loads and
# renders it at 1 spp on one thread; the render of a 64x64 film at 1 spp takes
# milliseconds, so the time is the load.  Prints one line per (file, renderer):
# the median over RUNS runs of user + system CPU seconds and of the peak resident
# set (GNU time's %M), and the run count.
#
# Usage: sh tools/load_curve.sh "N1 N2 ..." LABEL=SPECNEE_BINARY ... [pbrt=PBRT_BINARY]
#   e.g. sh tools/load_curve.sh "100 1000 10000" new=./specnee old=/tmp/specnee.old \
#        pbrt=/path/to/pbrt    (a pbrt-v4 binary: docs/real-scenes.md says how to build one)
# The renderers run interleaved (run 1 of each, then run 2 of each, ...), so that a
# change of the machine's load falls on all of them alike.
# Environment: RUNS (default 3; files of 100,000 spheres or more run BIG_RUNS
# times, default 1; of 1,000,000 or more once),
# MODES (default "spheres material"; "plain": N spheres that do not emit and one
# lamp, the curve over primitives), TMPDIR.  Needs /usr/bin/time (GNU).
set -eu
ns=${1:?usage: sh tools/load_curve.sh "N ..." LABEL=BINARY ...}
shift
here=$(cd "$(dirname "$0")" && pwd)
tmp=${TMPDIR:-/tmp}/load_curve.$$
mkdir -p "$tmp"
trap 'rm -rf "$tmp"' EXIT
median() { sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
printf '%-9s %-9s %-8s %10s %10s %5s\n' mode N renderer "cpu_s" "peak_MB" runs
for mode in ${MODES:-spheres material}; do
    for n in $ns; do
        f=$tmp/$mode$n.pbrt
        case $mode in
            material|plain) sh "$here/gen_spheres.sh" "$n" 1 "$mode" > "$f";;
            *) sh "$here/gen_spheres.sh" "$n" > "$f";;
        esac
        runs=${RUNS:-3}
        [ "$n" -ge 100000 ] && runs=${BIG_RUNS:-1}
        [ "$n" -ge 1000000 ] && runs=1
        j=0
        for spec in "$@"; do : > "$tmp/t$j"; : > "$tmp/m$j"; j=$((j + 1)); done
        i=0
        while [ $i -lt $runs ]; do          # the renderers interleaved, run by run
            j=0
            for spec in "$@"; do
                label=${spec%%=*}; bin=${spec#*=}
                if [ "$label" = pbrt ]; then
                    /usr/bin/time -f "%U %S %M" -o "$tmp/one" "$bin" --nthreads 1 --spp 1 --quiet \
                        --outfile "$tmp/out.exr" "$f" > /dev/null 2>&1
                else
                    /usr/bin/time -f "%U %S %M" -o "$tmp/one" "$bin" "$f" --spp 1 --threads 1 -q \
                        -o "$tmp/out.pfm" > /dev/null 2>&1
                fi
                awk '{ printf "%.2f\n", $1 + $2 }' "$tmp/one" >> "$tmp/t$j"
                awk '{ printf "%.1f\n", $3 / 1024 }' "$tmp/one" >> "$tmp/m$j"
                j=$((j + 1))
            done
            i=$((i + 1))
        done
        j=0
        for spec in "$@"; do
            printf '%-9s %-9s %-8s %10s %10s %5s\n' "$mode" "$n" "${spec%%=*}" "$(median < "$tmp/t$j")" \
                "$(median < "$tmp/m$j")" "$runs"
            j=$((j + 1))
        done
    done
done
