#!/bin/sh
# tools/realbench.sh - equal error, load time and peak memory against pbrt-v4 on a
# folder of real scene files.
#
#   PBRT=/path/to/pbrt sh tools/realbench.sh [--ref-spp N] [--spp "16 32 64 128 256"]
#        [--seeds K] [--threads T] [--at S] [--time wall|cpu] [--out DIR2]
#        [--refs-only] [--pbrt-at-only] DIR
#
# For every DIR/*.pbrt (each file keeps its own camera, film, sampler, integrator
# and depth; only the sample count and seed are given on the command line):
#   1. a reference image by pbrt-v4 at --ref-spp (default 4096, seed 1000): the
#      yardstick is the other renderer, so a bias of specnee shows as an error
#      that stops falling; a reference already in DIR2/NAME/ from the same file
#      and sample count is kept (DIR2/NAME/ref.key), so --refs-only can make
#      them first, at any priority (their time is not measured), and the timed
#      ladder run later on a quiet machine;
#   2. each renderer at each sample count of the ladder, K seeds (default 2),
#      every image's MSE against the reference (specnee diff) and the process's
#      wall time and peak resident memory (/usr/bin/time);
#   3. load: the wall time of a 1-spp run (parsing, building, one sample; a
#      renderer's start-up as a user meets it), the median of three runs.
# --pbrt-at-only renders pbrt-v4 at 1 spp and at S only (the table reads no
# other pbrt-v4 rung), which halves a run's time.
# It prints one row per scene:
#   pbrt-v4's MSE at S spp (default 64), its time there, the time specnee needs
#   for that MSE (log-log interpolation of specnee's (time, MSE) ladder between
#   the two points that bracket it; '~' marks a value extrapolated from the two
#   nearest points), their ratio (pbrt-v4 time / specnee time: above 1 specnee
#   is faster at equal error), the MSE per sample ratio at S spp, each
#   renderer's 1-spp time and peak memory at S spp.
# Both renderers get the same thread count (default: all cores); the two take
# turns render by render (same spp and seed, pbrt-v4 then specnee), so a slow
# spell of the machine hits both.  Run it on an otherwise idle machine: the times
# are wall-clock; --time cpu charges each run its process CPU time instead (user +
# system, GNU time), steadier on a shared machine. Intermediate images and logs
# go to DIR2/NAME/ (default build/realbench), the table to DIR2/table.md,
# one row as each scene finishes. Without GNU time (/usr/bin/time -f) the wall
# memory column is 0. Times are wall-clock from date, to the nanosecond.
# The scenes used in docs/RESULTS.md are listed, with their repositories and
# edits, in tools/realbench.list.
set -u
refspp=4096
ladder="16 32 64 128 256"
seeds=2
threads=$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
at=64
clock=wall
top=build/realbench
refsonly=0
pbrtat=0
while [ $# -gt 0 ]; do
    case "$1" in
        --ref-spp) refspp=$2; shift 2 ;;
        --spp) ladder=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        --threads) threads=$2; shift 2 ;;
        --at) at=$2; shift 2 ;;
        --time) clock=$2; shift 2 ;;
        --out) top=$2; shift 2 ;;
        --refs-only) refsonly=1; shift ;;
        --pbrt-at-only) pbrtat=1; shift ;;
        -*) echo "realbench: unknown option $1" >&2; exit 2 ;;
        *) break ;;
    esac
done
[ $# -eq 1 ] && [ -d "$1" ] || { echo "usage: PBRT=pbrt sh tools/realbench.sh [options] DIR" >&2; exit 2; }
[ -n "${PBRT:-}" ] && [ -x "$PBRT" ] || { echo "realbench: set PBRT to a pbrt-v4 binary" >&2; exit 2; }
[ -x ./specnee ] || { echo "realbench: run it from the repository root after make" >&2; exit 2; }
case "$clock" in wall|cpu) ;; *) echo "realbench: --time wall or cpu" >&2; exit 2 ;; esac
case " $ladder " in *" $at "*) ;; *) echo "realbench: --at $at is not on the ladder" >&2; exit 2 ;; esac
dir=$1
mkdir -p "$top"
gnutime=0
/usr/bin/time -f '%e %M' true > /dev/null 2>&1 && gnutime=1

[ $clock = cpu ] && [ $gnutime = 0 ] && { echo "realbench: --time cpu needs GNU time" >&2; exit 2; }

# run WHO SPP SEED IMAGE SCENE LOG: one render, timed; prints "seconds maxrss_kb"
# (seconds: wall, or user + system with --time cpu)
run() {
    if [ "$1" = pbrt ]; then
        set -- "$6" "$PBRT" --quiet --nthreads "$threads" --spp "$2" --seed "$3" --outfile "$4" "$5"
    else
        set -- "$6" ./specnee -q --threads "$threads" --spp "$2" --seed "$3" -o "$4" "$5"
    fi
    log=$1; shift
    try=1
    while :; do
        t0=$(date +%s.%N)
        if [ $gnutime = 1 ]; then
            /usr/bin/time -f '%M %U %S' -o "$log.time" "$@" > "$log" 2>&1
        else
            "$@" > "$log" 2>&1 && echo 0 > "$log.time"
        fi && break
        # a run killed by a signal is run again (at most eight times; stderr
        # says so): pbrt-v4 5f7a6068 dies at start in about half its runs of
        # street_light_in_fog on 2 or 3 threads (SIGSEGV; 1, 4 and 16 threads run)
        if [ $try -lt 8 ] && grep -q "terminated by signal" "$log.time" 2>/dev/null; then
            echo "realbench: $1 died by a signal ($(head -n 1 "$log.time")); run again" >&2
            try=$((try + 1))
            continue
        fi
        echo "realbench: failed: $* (see $log)" >&2; return 1
    done
    echo "$t0 $(date +%s.%N) $(tail -n 1 "$log.time") $clock" |
        awk '{ printf "%.4f %d\n", $NF == "cpu" ? $4 + $5 : $2 - $1, $3 }'
}

table=$top/table.md
{
    echo "| scene | pbrt-v4 MSE at $at spp | pbrt-v4 s | specnee s for that MSE | pbrt-v4 time / specnee time | specnee MSE / pbrt-v4 MSE at $at spp | 1 spp s, pbrt-v4 / specnee | peak MB, pbrt-v4 / specnee |"
    echo "|---|---|---|---|---|---|---|---|"
} > "$table"
for scene in "$dir"/*.pbrt; do
    name=$(basename "$scene" .pbrt)
    out=$top/$name
    mkdir -p "$out"
    echo "== $name" >&2
    key="$refspp $(cksum < "$scene")"
    if [ ! -f "$out/ref.pfm" ] || [ "$(cat "$out/ref.key" 2>/dev/null)" != "$key" ]; then
        rm -f "$out/ref.key"
        run pbrt "$refspp" 1000 "$out/ref.pfm" "$scene" "$out/ref.log" > /dev/null || continue
        echo "$key" > "$out/ref.key"
    fi
    [ $refsonly = 1 ] && continue
    : > "$out/ladder.txt"
    for spp in 1 $ladder; do
        k=1
        nk=$seeds
        [ "$spp" = 1 ] && nk=3        # 1 spp (the load): three runs, the median
        while [ $k -le "$nk" ]; do
            for who in pbrt specnee; do
                [ $who = pbrt ] && [ $pbrtat = 1 ] && [ "$spp" != 1 ] && [ "$spp" != "$at" ] && continue
                img=$out/$who-$spp-$k.pfm
                tm=$(run $who "$spp" "$k" "$img" "$scene" "$out/$who-$spp-$k.log") || continue 3
                mse=$(./specnee diff "$img" "$out/ref.pfm" --csv | awk -F, 'NR == 2 { print $7 }')
                echo "$who $spp $k $tm $mse" >> "$out/ladder.txt"
            done
            k=$((k + 1))
        done
    done
    # columns of ladder.txt: who spp seed wall_s rss_kb mse
    awk -v at="$at" -v name="$name" '
        $2 == 1 { t1[$1, ++n1[$1]] = $4 }
        { key = $1 " " $2; t[key] += $4; m[key] += $6; n[key]++
          if ($5 > rss[key]) rss[key] = $5
          if ($1 == "specnee" && $2 != 1 && !($2 in seen)) { seen[$2] = 1; spp[++ns] = $2 } }
        function median1(who,   a, b, c) {   # the median of a renderer 1-spp runs
            if (n1[who] < 3) return t["" who " 1"] / n["" who " 1"]
            a = t1[who, 1]; b = t1[who, 2]; c = t1[who, 3]
            return (a > b) ? ((b > c) ? b : ((a > c) ? c : a)) : ((a > c) ? a : ((b > c) ? c : b))
        }
        END {
            pk = "pbrt " at
            if (!(pk in n) || !(("specnee " at) in n)) { printf "| %s | failed | | | | | | |\n", name; exit }
            pm = m[pk] / n[pk]; pt = t[pk] / n[pk]
            # specnee (log t, log mse) points in ladder order
            for (i = 1; i <= ns; i++) { k = "specnee " spp[i]
                lt[i] = log(t[k] / n[k]); lm[i] = log(m[k] / n[k]) }
            target = log(pm); j = 0
            for (i = 1; i < ns; i++)
                if ((lm[i] - target) * (lm[i + 1] - target) <= 0) { j = i; break }
            mark = ""
            if (j == 0) { mark = "~"; j = (target > lm[1]) ? 1 : ns - 1 }
            if (lm[j + 1] == lm[j]) st = exp(lt[j])
            else st = exp(lt[j] + (target - lm[j]) * (lt[j + 1] - lt[j]) / (lm[j + 1] - lm[j]))
            sk = "specnee " at
            printf "| %s | %.3e | %.2f | %s%.2f | %s%.2f | %.2f | %.3f / %.3f | %.0f / %.0f |\n", name, pm, pt,
                mark, st, mark, pt / st, (m[sk] / n[sk]) / pm, median1("pbrt"),
                median1("specnee"), rss[pk] / 1024, rss[sk] / 1024
        }' "$out/ladder.txt" | tee -a "$table"
done
awk -F'|' 'NR > 2 && $6 ~ /[0-9]/ { v = $6; gsub(/[~ ]/, "", v); if (v > 0) { s += log(v); c++ } }
    END { if (c) printf "geometric mean of pbrt-v4 time / specnee time over %d scenes: %.2f\n", c, exp(s / c) }' \
    "$table" | tee -a "$table"
