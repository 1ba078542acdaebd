#!/bin/sh
# tools/thesis_table.sh SPP - the thesis' figures beside ours (docs/eval/thesis.md).
#
# Called by tools/eval.sh after the runs.  For each figure the thesis reports, the
# same comparison is computed from our CSVs (docs/eval/<scene>.csv): per seed the
# ratio MSE_variant / MSE_versus - 1 at SPP samples per pixel over the region,
# then the mean and the 95% confidence interval over seeds (Student's t).  The
# last column says whether ours points the same way: "yes" when the interval
# excludes 0 on the thesis' side, "same sign, not significant" when only the mean
# does, "opposite sign, not significant" when the interval holds 0 on the other
# side, "no" when it excludes 0 on the other side.
#
# The thesis' figures (data, not code): Deshmukh, van de Ruit and Eisemann,
# "Efficient Emitter Sampling for Spectral Path Tracing", TU Delft 2022, section 4
# (Evaluation), all at 512 spp against HWSS with the visibility (spatial)
# distribution; its "combined PDF" is our `product`, "unit emission" our default
# metric, "power" our `:power`, "SPD-only PDF" our `spd:power`.
# Fields: scene variant versus region thesis-figure ("worse" = a rise, no number)
set -eu
SPP=${1:-512}
{
    echo "| scene | comparison | region | thesis (sec. 4) | specnee, mean [95% CI] over seeds | same direction? |"
    echo "|---|---|---|---|---|---|"
    while read -r scene variant versus region thesis; do
        case "$scene" in ''|'#'*) continue ;; esac
        csv="docs/eval/$scene.csv"
        [ -f "$csv" ] || continue
        awk -F, -v v="$variant" -v w="$versus" -v reg="$region" -v spp="$SPP" -v th="$thesis" -v sc="$scene" '
        function t975(dof) {   # 97.5% quantile of Student t (standard tables)
            split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228 2.201 2.179 2.160 2.145 2.131 2.120 2.110 2.101 2.093 2.086 2.080 2.074 2.069 2.064 2.060 2.056 2.052 2.048 2.045 2.042", q, " ")
            return dof >= 1 && dof <= 30 ? q[dof] : 1.96
        }
        NR > 1 && $3 == spp && $8 == reg {
            if ($2 == v) a[$4] = $9
            if ($2 == w) b[$4] = $9
        }
        END {
            n = 0; s = 0; s2 = 0
            for (k in a) if (k in b && b[k] > 0) { c[n++] = a[k] / b[k] - 1; s += c[n - 1] }
            if (n < 2) { printf "| %s | `%s` vs `%s` | %s | %s | not in this run | |\n", sc, v, w, reg, th; exit 0 }
            m = s / n
            for (i = 0; i < n; i++) s2 += (c[i] - m) ^ 2
            h = t975(n - 1) * sqrt(s2 / (n - 1)) / sqrt(n)
            lo = m - h; hi = m + h
            sign = (th == "worse") ? 1 : (th + 0 > 0 ? 1 : -1)
            if ((sign > 0 && lo > 0) || (sign < 0 && hi < 0)) same = "yes"
            else if (m * sign > 0) same = "same sign, not significant"
            else if (lo < 0 && hi > 0) same = "opposite sign, not significant"
            else same = "no"
            shown = (th == "worse") ? "worse" : sprintf("%+.1f%%", th)
            printf "| %s | `%s` vs `%s` | %s | %s | %+.1f%% [%+.1f, %+.1f] (%d seeds) | %s |\n",
                   sc, v, w, reg, shown, 100 * m, 100 * lo, 100 * hi, n, same
        }' "$csv"
    done <<'EOF'
# cornell1: "a decrease in error of 4.3% ... inset A: 4.8%, inset B: 6.2% ... inset C (0.3%)" increase
cornell1 product spatial image -4.3
cornell1 product spatial A -4.8
cornell1 product spatial B -6.2
cornell1 product spatial C +0.3
# cornell2: "power as a metric leads to 6.8% more noise than the unit emission metric";
# unit emission: "a decrease of 7.6%, and 8.8% in insets A and B"
cornell2 product:power product image +6.8
cornell2 product spatial A -7.6
cornell2 product spatial B -8.8
# suzanne: "The non-supplemented PDF performs worse than the baseline, while the
# supplemented PDF offers an MSE improvement of 9.9%"
suzanne spd:power spatial image worse
suzanne product spatial image -9.9
EOF
} > docs/eval/thesis.md
