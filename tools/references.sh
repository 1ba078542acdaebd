#!/bin/sh
# tools/references.sh [scene ...] - high-spp reference renders for the evaluation.
#
# Each reference is split into JOBS independent renders (different seeds, one
# thread each, run as background jobs) and merged by sample count with
# `specnee merge`; the same recipe runs on a cluster (README: GNU parallel,
# Slurm).  The reference's own remaining error is estimated from two of the
# parts: E[MSE(part_a, part_b)] = 2 s^2 for parts of variance s^2, and the merged
# reference of JOBS parts has variance s^2 / JOBS, so
#     MSE(reference) ~= MSE(part_1, part_2) / (2 JOBS),
# written with the reference to docs/ref/<scene>.txt.  It must be far below the
# MSE differences the evaluation reports (docs/RESULTS.md compares them).
#
#   REF_SPP   total samples per pixel (default 16384)
#   JOBS      parallel jobs (default: the number of cores)
# Run from the repository root: `make references` or `sh tools/references.sh cornell1`.
set -eu
REF_SPP=${REF_SPP:-16384}
JOBS=${JOBS:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)}
scenes=${*:-"cornell-glass cornell1 cornell2 suzanne"}
mkdir -p docs/ref out/ref
per=$(( (REF_SPP + JOBS - 1) / JOBS ))
for sc in $scenes; do
    echo "reference $sc: $JOBS jobs x $per spp"
    start=$(date +%s)
    i=1
    while [ $i -le "$JOBS" ]; do
        ./specnee -q "scenes/$sc.pbrt" --threads 1 --spp "$per" --seed $((9000 + i)) \
            -o "out/ref/${sc}_$i.pfm" &
        i=$((i + 1))
    done
    wait
    ./specnee merge out/ref/${sc}_*.pfm -o "docs/ref/$sc.pfm"
    pair=$(./specnee diff "out/ref/${sc}_1.pfm" "out/ref/${sc}_2.pfm" | awk '$1 == "image" { print $7 }')
    end=$(date +%s)
    {
        echo "scene $sc"
        echo "spp $((per * JOBS)) ($JOBS jobs x $per)"
        echo "seconds $((end - start))"
        echo "mse_between_two_parts $pair"
        echo "estimated_reference_mse $(awk -v m="$pair" -v j="$JOBS" 'BEGIN { printf "%.6g", m / (2 * j) }')"
    } > "docs/ref/$sc.txt"
    cat "docs/ref/$sc.txt"
    rm -f out/ref/${sc}_*.pfm out/ref/${sc}_*.pfm.txt
done
