#!/bin/sh
# tools/factorial.sh - the factorial evaluation (`make factorial`): which factor
# of the configuration matters, by how much, at equal time.
#
# Factors and levels (every combination is one `specnee converge` variant, named
# SELECTION:WAVELENGTHS:terminate|roughmis, e.g. product:mixture:roughmis; every
# factor is named, so the variants keep their meaning when the defaults change):
#   WAVELENGTHS  the wavelength pdf          uniform importance visible mixture
#   SELECTIONS   the emitter selection       spatial product spectral-spatial, and
#                                            tree when `specnee --help` lists it
#   ROUGH        rough dispersive glass      terminate mis
# The first level of each list is that factor's reference; the first combination
# (spatial:uniform:terminate: the thesis' baseline, what `--preset thesis` sets) is
# the baseline of the converge tables.
#
# For each scene: converge renders every variant up the spp ladder with SEEDS
# seeds against docs/ref/<scene>.pfm, into docs/eval/factorial/<scene>.csv, .md and
# the charts (<scene>_mse_time.svg: time against MSE for every configuration, the
# Pareto front at a glance).  Then tools/factor_table.sh turns the CSVs into
# docs/eval/factorial/factors.md: the equal-time gain of each factor level over
# its reference, per scene, with 95% confidence intervals.
#
#   SEEDS        seeds per (variant, spp) (default 8)
#   LADDER       spp ladder (default 16,32,64,128,256,512)
#   SCENES       scenes (default: cornell1 cornell2 suzanne cornell-glass; add the
#                many-emitter scene once it has a reference)
#   WAVELENGTHS, SELECTIONS, ROUGH   the levels (defaults above; a pilot may prune)
#   THREADS, TIME, SPECNEE, REUSE    as in tools/eval.sh
# The selection levels take the current defaults of --spd-metric and
# --spd-wavelengths (unit, hero); add ":unit:hero" to each name if those change.
# Cost: SEEDS x variants x the largest spp per scene; 32 variants x 8 seeds x 512
# spp is 32 times one 8-seed baseline run of tools/eval.sh: hours on 2 cores.
# Never run in full by `make test`; tests/run.sh runs it on a tiny setting (factorial_smoke).
set -eu
. "$(dirname "$0")/eval_defaults.sh"
SCENES=${SCENES:-"cornell1 cornell2 suzanne cornell-glass"}
WAVELENGTHS=${WAVELENGTHS:-"uniform importance visible mixture"}
if [ -z "${SELECTIONS:-}" ]; then
    SELECTIONS="spatial product spectral-spatial"
    "$SPECNEE" --help | grep -q '[ ,]tree[ ,]' && SELECTIONS="$SELECTIONS tree"
fi
ROUGH=${ROUGH:-"terminate mis"}
OUT=${OUT:-docs/eval/factorial}
mkdir -p "$OUT"

variants=""
for r in $ROUGH; do
    case $r in terminate) suffix=":terminate" ;; mis) suffix=":roughmis" ;;
        *) echo "factorial: ROUGH levels are terminate and mis, not '$r'" >&2; exit 2 ;; esac
    for w in $WAVELENGTHS; do
        for s in $SELECTIONS; do
            variants="$variants${variants:+,}$s:$w$suffix"
        done
    done
done

start=$(date +%s)
for sc in $SCENES; do
    if [ ! -f "docs/ref/$sc.pfm" ]; then
        echo "factorial: docs/ref/$sc.pfm is missing: run 'sh tools/references.sh $sc' first" >&2
        exit 1
    fi
    if [ "$REUSE" = 1 ]; then
        "$SPECNEE" converge "scenes/$sc.pbrt" --ref "docs/ref/$sc.pfm" --lights "$variants" \
            --spp "$LADDER" --seeds "$SEEDS" --time "$TIME" --out "$OUT/$sc" --reuse
        continue
    fi
    t0=$(date +%s)
    "$SPECNEE" converge "scenes/$sc.pbrt" --ref "docs/ref/$sc.pfm" --lights "$variants" \
        --spp "$LADDER" --seeds "$SEEDS" --threads "$THREADS" --time "$TIME" --out "$OUT/$sc" 2> "$OUT/$sc.log"
    echo "$sc: $(( $(date +%s) - t0 )) s (SEEDS=$SEEDS LADDER=$LADDER TIME=$TIME, $(echo "$variants" | tr ',' '\n' | wc -l) variants, $(getconf _NPROCESSORS_ONLN) cores, $(date -u +%Y-%m-%d))" >> "$OUT/timing.txt"
done
[ "$REUSE" != 1 ] && echo "total: $(( $(date +%s) - start )) s (SCENES=$SCENES)" >> "$OUT/timing.txt"
csvs=""
for sc in $SCENES; do csvs="$csvs $OUT/$sc.csv"; done
# shellcheck disable=SC2086
sh tools/factor_table.sh $csvs > "$OUT/factors.md"
echo "wrote $OUT/factors.md"
