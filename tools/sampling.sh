#!/bin/sh
# tools/sampling.sh - how much less noise each sampler leaves than independent, at
# equal spp, without a reference: the variance of one render from pairs of seeds.
#
#   sh tools/sampling.sh [scene.pbrt ...]        (default: every scenes/*.pbrt)
#   env: RES=96x96 (film, --res; "" for the file's), SPP="16 64", PAIRS=4,
#        SAMPLERS="sobol zsobol stratified", THREADS=2, SPECNEE=./specnee
#
# For every scene, spp and sampler (and independent), 2 x PAIRS renders with seeds
# 1 .. 2 PAIRS; two renders of one pair are independent and unbiased, so
# E[MSE(a, b)] = 2 Var, and MSE(a, b) / MSE_independent(a', b') estimates the
# variance ratio sampler / independent at equal spp (docs/sampling.md).  The table
# gives the geometric mean of that ratio over the pairs, with a 95% interval
# (Student's t on the log ratios), and the CPU time ratio at equal spp (sum over
# the renders).  Renders run one by one, the samplers in turn within each pair.
set -u
BIN=${SPECNEE:-./specnee}
RES=${RES-96x96}
SPP=${SPP:-16 64}
PAIRS=${PAIRS:-4}
SAMPLERS=${SAMPLERS:-sobol zsobol stratified}
THREADS=${THREADS:-2}
tmp=${TMPDIR:-/tmp}/specnee-sampling.$$
mkdir -p "$tmp" || exit 1
[ $# -gt 0 ] || set -- scenes/*.pbrt
resopt=""
[ -n "$RES" ] && resopt="--res $RES"
echo "| scene | spp | sampler | variance ratio to independent [95% CI] | CPU time ratio |"
echo "|---|---|---|---|---|"
for sc in "$@"; do
    name=$(basename "$sc" .pbrt)
    for spp in $SPP; do
        : > "$tmp/rows"
        p=1
        while [ $p -le "$PAIRS" ]; do
            for smp in independent $SAMPLERS; do
                for half in a b; do
                    seed=$((2 * p - 1)); [ $half = b ] && seed=$((2 * p))
                    line=$($BIN "$sc" $resopt --spp "$spp" --seed $seed --threads "$THREADS" --sampler $smp \
                           -o "$tmp/$half.pfm" 2>&1 | tail -n 1)
                    cpu=$(echo "$line" | sed -n 's/.*(\([0-9.]*\) s CPU.*/\1/p')
                    echo "cpu $smp ${cpu:-0}" >> "$tmp/rows"
                done
                mse=$($BIN diff "$tmp/a.pfm" "$tmp/b.pfm" --csv | awk -F, '$1 == "image" { print $7 }')
                echo "mse $smp $p $mse" >> "$tmp/rows"
            done
            p=$((p + 1))
        done
        for smp in $SAMPLERS; do
            awk -v s="$smp" -v name="$name" -v spp="$spp" '
                $1 == "mse" && $2 == "independent" { base[$3] = $4 }
                $1 == "mse" && $2 == s { mine[$3] = $4 }
                $1 == "cpu" && $2 == "independent" { cb += $3 }
                $1 == "cpu" && $2 == s { cs += $3 }
                END {
                    split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228", tq, " ")
                    n = 0; sum = 0; sum2 = 0
                    for (p in mine) if (base[p] > 0 && mine[p] > 0) {
                        l = log(mine[p] / base[p]); n++; sum += l; sum2 += l * l }
                    m = sum / n; sd = n > 1 ? sqrt((sum2 - n * m * m) / (n - 1)) : 0
                    h = n > 1 ? (n - 1 <= 10 ? tq[n - 1] : 2.0) * sd / sqrt(n) : 0
                    printf "| %s | %d | %s | %.3f [%.3f, %.3f] | %.3f |\n", name, spp, s, exp(m), exp(m - h), exp(m + h),
                           (cb > 0 ? cs / cb : 0) }' "$tmp/rows"
        done
    done
done
[ -n "${KEEP:-}" ] || rm -rf "$tmp"
