#!/bin/sh
# tools/factorial_pilot.sh - the pilot of the factorial evaluation that chose
# specnee's defaults (docs/RESULTS.md, "What to use").  Two stages, each a
# `specnee converge` run per scene against docs/ref/<scene>.pfm, every variant
# against the thesis' baseline (spatial:uniform:terminate:independent, what
# `--preset thesis` renders):
#   stage 1  wavelength pdf {uniform importance visible mixture} x rough dispersion
#            {terminate mis}, spatial selection, the default sampler (sobol): which
#            wavelength pdf and which treatment of rough glass;
#   stage 2  emitter selection {spatial product spectral-spatial tree spectral-tree}
#            with the winner of stage 1 (mixture, mis); on many-lamps without
#            product and spectral-spatial (see below).
# The full grid (tools/factorial.sh: 4 x 4 x 2 = 32 variants x 6 rungs up to 512 spp
# x 8 seeds) costs hours per scene on 2 cores; the pilot prunes it to a fractional
# design (one factor at a time around the best level, 9 + 6 variants), LADDER
# 16,64 (64 spp: the budget the defaults were chosen for) and 4 seeds.  What that cannot show:
# interactions between selection and the wavelength pdf away from the chosen levels.
#   SCENES  (default: the evaluation scenes and the two stress scenes of
#           docs/wavelengths.md)   SEEDS (4)   LADDER (16,64)   THREADS (1)
#   SPECNEE (./specnee)   REUSE=1: rebuild the tables from the CSVs only
# Output: docs/eval/factorial/pilot_s{1,2}_<scene>.{csv,md,svg} and pilot.md (the
# equal-time change of every configuration on every scene, whole image).
set -eu
SEEDS=${SEEDS:-4}
LADDER=${LADDER:-16,64}
THREADS=${THREADS:-1}
SPECNEE=${SPECNEE:-./specnee}
REUSE=${REUSE:-0}
SCENES=${SCENES:-"cornell1 cornell2 suzanne cornell-glass many-lamps wl-hidden-lamp wl-filter"}
OUT=docs/eval/factorial
mkdir -p "$OUT"
BASE=spatial:uniform:terminate:independent
S1="$BASE"
for r in terminate roughmis; do
    for w in uniform importance visible mixture; do S1="$S1,spatial:$w:$r"; done
done
S2="$BASE"
for s in spatial product spectral-spatial tree spectral-tree; do S2="$S2,$s:mixture:roughmis"; done
for sc in $SCENES; do
    for st in s1 s2; do
        if [ $st = s1 ]; then V=$S1; else V=$S2; fi
        # many-lamps (257 emitters): product and spectral-spatial build O(n) voxel
        # tables like spatial (about 19 s CPU per 16 spp here, against 1 s for a
        # tree); docs/lighttree.md measures them, the pilot leaves them out there
        if [ $st = s2 ] && [ "$sc" = many-lamps ]; then
            V="$BASE,spatial:mixture:roughmis,tree:mixture:roughmis,spectral-tree:mixture:roughmis"
        fi
        if [ "$REUSE" = 1 ]; then
            "$SPECNEE" converge "scenes/$sc.pbrt" --ref "docs/ref/$sc.pfm" --lights "$V" --spp "$LADDER" \
                --seeds "$SEEDS" --time cpu --out "$OUT/pilot_${st}_$sc" --reuse
        else
            t0=$(date +%s)
            "$SPECNEE" converge "scenes/$sc.pbrt" --ref "docs/ref/$sc.pfm" --lights "$V" --spp "$LADDER" \
                --seeds "$SEEDS" --threads "$THREADS" --time cpu --out "$OUT/pilot_${st}_$sc" 2> "$OUT/pilot_${st}_$sc.log"
            echo "pilot $st $sc: $(( $(date +%s) - t0 )) s (SEEDS=$SEEDS LADDER=$LADDER THREADS=$THREADS, $(date -u +%Y-%m-%d))" >> "$OUT/timing.txt"
        fi
    done
done
# the summary: equal-time change against the thesis' baseline, whole image
{
    printf '| configuration |'; for sc in $SCENES; do printf ' %s |' "$sc"; done; echo
    printf '|---|'; for sc in $SCENES; do printf -- '---|'; done; echo
    first=$(echo $SCENES | awk '{ print $1 }')
    for st in s1 s2; do
        awk -F'|' '/^\*\*image\*\*/ { on = 1; next } /^\*\*/ { on = 0 }
            on && NF > 5 && $2 !~ /variant|---|baseline/ { v = $2; gsub(/^ +| +$/, "", v); print v }' \
            "$OUT/pilot_${st}_$first.md"
    done | awk '!seen[$0]++' | while read -r v; do
        printf '| `%s` |' "$v"
        for sc in $SCENES; do
            val=""
            for st in s1 s2; do
                f=$OUT/pilot_${st}_$sc.md
                [ -f "$f" ] || continue
                x=$(awk -F'|' -v v="$v" '/^\*\*image\*\*/ { on = 1; next } /^\*\*/ { on = 0 }
                    on && NF > 5 { a = $2; gsub(/^ +| +$/, "", a)
                                   if (a == v) { b = $7; gsub(/^ +| +$/, "", b); print b; exit } }' "$f")
                if [ -n "$x" ]; then val=$x; break; fi
            done
            printf ' %s |' "${val:--}"
        done
        echo
    done
} > "$OUT/pilot.md"
# the rule: geometric mean over the scenes of the equal-time MSE ratio (1 + change)
awk -F'|' 'NR > 2 { n = 0; s = 0; worse = 0
    for (i = 3; i < NF; i++) { x = $i; if (x ~ /^ *-? *$/) continue
        split(x, p, "%"); r = 1 + p[1] / 100; s += log(r); n++
        if (match(x, /\[[-+0-9.]+/)) { lo = substr(x, RSTART + 1, RLENGTH - 1) + 0; if (lo > 0) worse++ } }
    if (n) printf "%s geo-mean ratio %.3f over %d scenes, significantly worse than the thesis on %d\n", $2, exp(s / n), n, worse }' \
    "$OUT/pilot.md" > "$OUT/pilot_rule.txt"
echo "wrote $OUT/pilot.md and $OUT/pilot_rule.txt"
