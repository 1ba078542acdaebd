#!/bin/sh
# tools/eval.sh - the evaluation behind docs/RESULTS.md (`make eval`).
#
# For each scene: `specnee converge` renders every variant at every spp of the
# ladder with SEEDS seeds against the reference in docs/ref/ (make references),
# writing docs/eval/<scene>.csv, .md and three SVG charts.  Then docs/RESULTS.md
# is rebuilt from docs/RESULTS.in.md, whose lines "@@include docs/eval/X.md@@"
# are replaced by the generated tables: no number in RESULTS.md is typed by hand.
#
#   SEEDS   seeds per (variant, spp) (default 8)
#   LADDER  spp ladder (default 16,32,64,128,256,512, the thesis' ladder)
#   SCENES  which runs (default all: cornell1 cornell2 suzanne cornell-glass); a
#           subset keeps each call short, e.g. on a lent machine with a per-command
#           limit; the tables of the other runs stay as they are
#   THREADS render threads (default: all cores)
#   TIME    cpu (default) or wall: the time basis of the charts and of equal time
#   SPECNEE the binary (default ./specnee; a copy lets you rebuild during a run)
#   REUSE   1: render nothing, rebuild the charts and tables from the CSVs already
#           in docs/eval/ (same SEEDS and LADDER as the run that wrote them)
# Each (variant, seed) is one progressive render up the ladder (render_ladder), so
# a run costs SEEDS x variants x 512 spp.  Run time: docs/eval/timing.txt.
set -eu
. "$(dirname "$0")/eval_defaults.sh"
mkdir -p docs/eval
start=$(date +%s)
run_as() {  # output-name scene variants
    out=$1; sc=$2; shift 2
    if [ ! -f "docs/ref/$sc.pfm" ]; then
        echo "eval: docs/ref/$sc.pfm is missing: run 'make references' first" >&2
        exit 1
    fi
    t0=$(date +%s)
    if [ "$REUSE" = 1 ]; then
        "$SPECNEE" converge "scenes/$sc.pbrt" --ref "docs/ref/$sc.pfm" --lights "$1" \
            --spp "$LADDER" --seeds "$SEEDS" --time "$TIME" --base thesis --out "docs/eval/$out" --reuse
        return
    fi
    "$SPECNEE" converge "scenes/$sc.pbrt" --ref "docs/ref/$sc.pfm" --lights "$1" \
        --spp "$LADDER" --seeds "$SEEDS" --threads "$THREADS" --time "$TIME" --base thesis --out "docs/eval/$out" 2> "docs/eval/$out.log"
    echo "$out: $(( $(date +%s) - t0 )) s (SEEDS=$SEEDS LADDER=$LADDER TIME=$TIME, $(getconf _NPROCESSORS_ONLN) cores, $(date -u +%Y-%m-%d))" >> docs/eval/timing.txt
}
run() { run_as "$1" "$@"; }  # scene variants: tables named after the scene
SCENES=${SCENES:-"cornell1 cornell2 suzanne cornell-glass"}
want() { case " $SCENES " in *" $1 "*) return 0 ;; esac; return 1; }
[ -f docs/eval/timing.txt ] || : > docs/eval/timing.txt
# emitter selection on the thesis' scenes; on cornell1 also the selection by all
# alive wavelengths (:all, :tput) and NEE to every emitter (all)
want cornell1 && run cornell1 "spatial,spd,product,spectral-spatial,all,product:all,spectral-spatial:all,product:tput"
want cornell2 && run cornell2 "spatial,product,product:power,spectral-spatial"
want suzanne && run suzanne "spatial,spd:power,product,spectral-spatial"
# wavelength strategies on the F11-lit glass box
want cornell-glass && run cornell-glass "spatial,spatial:single,spatial:importance,spatial:roughmis"
[ "$REUSE" != 1 ] && [ "$(date +%s)" -gt "$start" ] &&
    echo "total: $(( $(date +%s) - start )) s (SCENES=$SCENES SEEDS=$SEEDS LADDER=$LADDER TIME=$TIME on $(getconf _NPROCESSORS_ONLN) cores)" >> docs/eval/timing.txt
# the references' own error beside the baseline's MSE at the largest spp
# (docs/eval/references.md; the argument for "enough spp" in RESULTS.md)
{
    echo "| scene | reference spp | estimated MSE of the reference | baseline MSE at the largest spp (mean over seeds) | ratio |"
    echo "|---|---|---|---|---|"
    for sc in cornell1 cornell2 suzanne cornell-glass; do
        [ -f "docs/ref/$sc.txt" ] && [ -f "docs/eval/$sc.csv" ] || continue
        awk -v sc="$sc" '
        FNR == NR { if ($1 == "estimated_reference_mse") refmse = $2; if ($1 == "spp") refspp = $2; next }
        FNR == 1 { next }
        {
            split($0, f, ",")
            if (base == "") base = f[2]
            if (f[2] == base && f[8] == "image") {
                spp = f[3] + 0
                if (spp > top) { top = spp; sum = 0; n = 0 }
                if (spp == top) { sum += f[9]; n++ }
            }
        }
        END {
            if (n == 0 || refmse == "") exit 1
            printf "| %s | %s | %.2g | %.3g (`%s`, %d spp) | %.2g%% |\n", sc, refspp, refmse, sum / n, base, top, 100 * refmse / (sum / n)
        }' "docs/ref/$sc.txt" "docs/eval/$sc.csv"
    done
} > docs/eval/references.md
# the thesis' figures beside ours (docs/eval/thesis.md)
sh tools/thesis_table.sh "${LADDER##*,}"
# assemble docs/RESULTS.md
awk '
/^@@include .*@@$/ {
    f = $2; sub(/@@$/, "", f)
    while ((getline line < f) > 0) print line
    close(f)
    next
}
{ print }' docs/RESULTS.in.md > docs/RESULTS.md
echo "wrote docs/RESULTS.md"
