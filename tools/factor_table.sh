#!/bin/sh
# tools/factor_table.sh CSV... - the factor tables of the factorial evaluation
# (tools/factorial.sh) from `specnee converge` CSVs, one per scene, as markdown on
# stdout.  TIME=wall uses wall time instead of CPU time (as converge --time).
#
# Variant names are SELECTION:WAVELENGTHS[:roughmis|:terminate][:...]; the factors
# read from them are the selection (first field), the wavelength pdf (uniform
# importance visible mixture mixture=M; uniform when absent) and rough dispersion
# (mis with the roughmis field, else terminate).  Other fields must match for two
# variants to be compared.  The first variant of a CSV is the baseline;
# its levels are each factor's reference level.  Only the "image" region is used.
#
# Equal time, as converge computes it (cmd_converge.c): the time of a (variant, spp) is its
# mean over seeds; per seed, a variant's MSE at the baseline's time for the largest
# spp, T0, is interpolated in log-log along its ladder of (mean time, MSE), and
# extrapolated as MSE ~ 1/time beyond it.
#
# Table 1, main effects.  For a factor level L against its reference R: pair every
# variant at level L with the variant that differs only in that factor (level R);
# per seed k the log ratio of their equal-time MSEs, averaged over the pairs, is
# d_k.  Gain = exp(-mean d), with the 95% interval mean +- t(0.975, K-1) sd/sqrt(K),
# widened like converge's by the timing noise of the pairs' time ratio at the
# largest spp (half-widths added in quadrature, log space).  Gain > 1: the level
# reaches the reference's MSE in less time (e.g. 2.0 = half the MSE at equal time).
# Column "all scenes": geometric mean of the scene gains; half-width
# sqrt(sum h_s^2) / S (scenes are independent); only for levels run on every scene.
#
# Table 2, every configuration against the baseline at equal time (gain and
# interval as above, one pair per seed), the geometric mean over the scenes, and
# the scenes where it is significantly worse than the baseline (interval entirely
# below 1): the data for a defaults rule such as "best geometric mean, never
# significantly worse than the thesis' baseline".
set -eu
[ $# -ge 1 ] || { echo "usage: sh tools/factor_table.sh SCENE.csv ..." >&2; exit 2; }
for f in "$@"; do
    [ -f "$f" ] || { echo "factor_table: $f: no such file" >&2; exit 1; }
done
awk -v tcol="$([ "${TIME:-cpu}" = wall ] && echo 5 || echo 6)" '
function t975(dof,   t) {
    split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228 2.201 2.179 2.160 2.145 2.131 2.120 2.110 2.101 2.093 2.086 2.080 2.074 2.069 2.064 2.060 2.056 2.052 2.048 2.045 2.042", t, " ")
    if (dof < 1) return 0
    return dof <= 30 ? t[dof] + 0 : 1.96
}
# MSE at time T along n points (tt[i], mm[i]), i = 1..n, log-log (cmd_converge.c mse_at_time)
function mse_at(n, T,   i, a) {
    if (T <= tt[1]) return mm[1] * tt[1] / T
    for (i = 1; i < n; i++) {
        if (T == tt[i + 1]) return mm[i + 1]
        if (T <= tt[i + 1] && tt[i + 1] > tt[i] && mm[i] > 0 && mm[i + 1] > 0) {
            a = (log(T) - log(tt[i])) / (log(tt[i + 1]) - log(tt[i]))
            return exp(log(mm[i]) + a * (log(mm[i + 1]) - log(mm[i])))
        }
    }
    return mm[n] * tt[n] / T
}
function levels(v,   f, n, i, w) {   # sets L_sel, L_wl, L_rough, L_rest
    n = split(v, f, ":")
    L_sel = f[1]; L_wl = "uniform"; L_rough = "terminate"; L_rest = ""
    for (i = 2; i <= n; i++) {
        w = f[i]
        if (w == "uniform" || w == "importance" || w == "visible" || w ~ /^mixture(=.*)?$/) L_wl = w
        else if (w == "roughmis") L_rough = "mis"
        else if (w == "terminate") L_rough = "terminate"
        else L_rest = L_rest ":" w
    }
}
function fmt(g, lo, hi) { return sprintf("%.2f [%.2f, %.2f]", g, lo, hi) }
# The mean M of the n per-seed log MSE ratios dd[1..n] and the half-width H of
# its 95% interval, widened by the timing noise of the log time ratios tq[1..n]
# (half-widths added in quadrature, as converge does).
function mean_ci(n, dd, tq,   q, tm, m2, tm2, h, ht) {
    M = 0; tm = 0; m2 = 0; tm2 = 0
    for (q = 1; q <= n; q++) { M += dd[q]; tm += tq[q] }
    M /= n; tm /= n
    for (q = 1; q <= n; q++) { m2 += (dd[q] - M) ^ 2; tm2 += (tq[q] - tm) ^ 2 }
    h = n > 1 ? t975(n - 1) * sqrt(m2 / (n - 1)) / sqrt(n) : 0
    ht = n > 1 ? t975(n - 1) * sqrt(tm2 / (n - 1)) / sqrt(n) : 0
    H = sqrt(h * h + ht * ht)
}
FNR == 1 { S++; scene[S] = FILENAME; sub(/^.*\//, "", scene[S]); sub(/\.csv$/, "", scene[S]); next }
{
    n = split($0, c, ",")
    if (n < 11 || c[8] != "image") next
    v = c[2]; sp = c[3] + 0; k = c[4] + 0
    if (!((S, v) in isvar)) { isvar[S, v] = 1; nv[S]++; var[S, nv[S]] = v }
    if (!((S, sp) in isspp)) { isspp[S, sp] = 1; ns[S]++; spp[S, ns[S]] = sp }
    if (!((S, k) in isseed)) { isseed[S, k] = 1; nk[S]++; seed[S, nk[S]] = k }
    mse[S, v, sp, k] = c[9] + 0; tim[S, v, sp, k] = c[tcol] + 0
}
END {
    if (S == 0) { print "factor_table: no rows" > "/dev/stderr"; exit 1 }
    for (s = 1; s <= S; s++) {
        # spp ascending (insertion sort)
        for (i = 2; i <= ns[s]; i++) for (j = i; j > 1 && spp[s, j] < spp[s, j - 1]; j--) {
            x = spp[s, j]; spp[s, j] = spp[s, j - 1]; spp[s, j - 1] = x }
        top = spp[s, ns[s]]; K[s] = nk[s]
        for (a = 1; a <= nv[s]; a++) {
            v = var[s, a]
            for (i = 1; i <= ns[s]; i++) {
                sum = 0; for (q = 1; q <= nk[s]; q++) sum += tim[s, v, spp[s, i], seed[s, q]]
                tmean[s, v, i] = sum / nk[s]
            }
        }
        base[s] = var[s, 1]; T0 = tmean[s, base[s], ns[s]]
        for (a = 1; a <= nv[s]; a++) {
            v = var[s, a]
            for (q = 1; q <= nk[s]; q++) {
                for (i = 1; i <= ns[s]; i++) { tt[i] = tmean[s, v, i]; mm[i] = mse[s, v, spp[s, i], seed[s, q]] }
                meq[s, v, q] = mse_at(ns[s], T0)
                ttop[s, v, q] = tim[s, v, top, seed[s, q]]
            }
            levels(v); lv_sel[s, v] = L_sel; lv_wl[s, v] = L_wl; lv_rough[s, v] = L_rough; lv_rest[s, v] = L_rest
            key[s, L_sel, L_wl, L_rough, L_rest] = v
        }
        levels(base[s]); ref["selection"] = L_sel; ref["wavelengths"] = L_wl; ref["rough dispersion"] = L_rough
        # main effects
        for (a = 1; a <= nv[s]; a++) {
            v = var[s, a]
            for (fi = 1; fi <= 3; fi++) {
                F = fi == 1 ? "wavelengths" : fi == 2 ? "selection" : "rough dispersion"
                Lv = fi == 1 ? lv_wl[s, v] : fi == 2 ? lv_sel[s, v] : lv_rough[s, v]
                if (Lv == ref[F]) continue
                p = key[s, fi == 2 ? ref[F] : lv_sel[s, v], fi == 1 ? ref[F] : lv_wl[s, v],
                        fi == 3 ? ref[F] : lv_rough[s, v], lv_rest[s, v]]
                if (p == "") continue
                if (!((F, Lv) in seen)) { seen[F, Lv] = 1; nlev++; lev[nlev] = F SUBSEP Lv }
                npair[s, F, Lv]++
                for (q = 1; q <= nk[s]; q++) {
                    dsum[s, F, Lv, q] += log(meq[s, v, q] / meq[s, p, q])
                    tsum[s, F, Lv, q] += log(ttop[s, v, q] / ttop[s, p, q])
                }
            }
        }
    }
    print "Equal-time gain of each factor level over its reference level (MSE of the reference / MSE of the level at the baseline'"'"'s time for the largest spp; > 1 is better), geometric mean over the configurations of the other factors, mean [95% CI] over seeds."
    print ""
    printf "| factor | level (vs reference) |"
    for (s = 1; s <= S; s++) printf " %s |", scene[s]
    print " all scenes |"
    printf "|---|---|"; for (s = 1; s <= S; s++) printf "---|"; print "---|"
    for (l = 1; l <= nlev; l++) {
        split(lev[l], fl, SUBSEP); F = fl[1]; Lv = fl[2]
        printf "| %s | %s (vs %s) |", F, Lv, ref[F]
        gsum = 0; hsum = 0; gn = 0
        for (s = 1; s <= S; s++) {
            if (!npair[s, F, Lv]) { printf " - |"; continue }
            for (q = 1; q <= K[s]; q++) { dd[q] = dsum[s, F, Lv, q] / npair[s, F, Lv]
                                          tq[q] = tsum[s, F, Lv, q] / npair[s, F, Lv] }
            mean_ci(K[s], dd, tq); m = M; h = H
            printf " %s |", fmt(exp(-m), exp(-m - h), exp(-m + h))
            gsum += m; hsum += h * h; gn++
        }
        if (gn == S) { m = gsum / gn; h = sqrt(hsum) / gn; printf " %s |\n", fmt(exp(-m), exp(-m - h), exp(-m + h)) }
        else print " - (not on every scene) |"
    }
    print ""
    print "Every configuration against the baseline (the first variant: " base[1] ") at equal time, gain [95% CI]; worse: scenes where the whole interval is below 1."
    print ""
    printf "| configuration |"; for (s = 1; s <= S; s++) printf " %s |", scene[s]
    print " geometric mean | worse on |"
    printf "|---|"; for (s = 1; s <= S; s++) printf "---|"; print "---|---|"
    for (a = 1; a <= nv[1]; a++) {
        v = var[1, a]; printf "| %s |", v
        gsum = 0; hsum = 0; gn = 0; worse = ""
        for (s = 1; s <= S; s++) {
            if (!((s, v) in isvar)) { printf " - |"; continue }
            for (q = 1; q <= K[s]; q++) { dd[q] = log(meq[s, v, q] / meq[s, base[s], q])
                                          tq[q] = log(ttop[s, v, q] / ttop[s, base[s], q]) }
            mean_ci(K[s], dd, tq); m = M; h = H
            printf " %s |", fmt(exp(-m), exp(-m - h), exp(-m + h))
            if (exp(-m + h) < 1) worse = worse (worse == "" ? "" : ", ") scene[s]
            gsum += m; hsum += h * h; gn++
        }
        m = gn ? gsum / gn : 0; h = gn ? sqrt(hsum) / gn : 0
        printf " %s | %s |\n", gn == S ? fmt(exp(-m), exp(-m - h), exp(-m + h)) : "- (not on every scene)",
               worse == "" ? "-" : worse
    }
}' "$@"
