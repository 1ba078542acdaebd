#!/bin/sh
# tools/pbrt_equal_error.sh - how long does each renderer need for the same error?
#
#   PBRT=/path/to/pbrt sh tools/pbrt_equal_error.sh [--ref-spp N] [--spp "4 16 64"] [--seeds K] scene.pbrt
#
# Renders a reference with specnee at --ref-spp (default 4096; tools/pbrt_compare.sh
# shows first that the two renderers' means agree), then each renderer at each spp
# of the ladder and K seeds (default 3), timing every run (wall clock of the whole
# process, as a user sees it), and prints per renderer and spp: the mean wall time
# and the mean MSE against the reference (specnee diff), and their product, the
# inverse efficiency.  The last line is the ratio of the two efficiencies at the
# largest spp: how many times less time specnee needs for pbrt-v4's error there
# (MSE falls as 1/time for both, so equal error at a time ratio of the products).
# Both renderers use every core; run it on an otherwise idle machine.
set -u
refspp=4096
ladder="4 16 64"
seeds=3
while [ $# -gt 0 ]; do
    case "$1" in
        --ref-spp) refspp=$2; shift 2 ;;
        --spp) ladder=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        -*) echo "pbrt_equal_error: unknown option $1" >&2; exit 2 ;;
        *) break ;;
    esac
done
[ $# -eq 1 ] || { echo "usage: PBRT=pbrt sh tools/pbrt_equal_error.sh [options] scene.pbrt" >&2; exit 2; }
[ -n "${PBRT:-}" ] && [ -x "$PBRT" ] || { echo "pbrt_equal_error: set PBRT to a pbrt-v4 binary" >&2; exit 2; }
scene=$1
name=$(basename "$scene" .pbrt)
out=build/equal-error/$name
mkdir -p "$out"
now() { date +%s.%N; }
./specnee -q --spp "$refspp" -o "$out/ref.pfm" "$scene" 2> "$out/ref.log" || { cat "$out/ref.log"; exit 1; }
printf '%-8s %6s %10s %14s %14s\n' renderer spp "time (s)" MSE "MSE x time"
for who in pbrt specnee; do
    for spp in $ladder; do
        k=0; tsum=0; msum=0
        while [ $k -lt "$seeds" ]; do
            img="$out/$who-$spp-$k.pfm"
            t0=$(now)
            if [ $who = pbrt ]; then
                "$PBRT" --quiet --spp "$spp" --seed $((k + 1)) --outfile "$img" "$scene" > "$out/$who.log" 2>&1
            else
                ./specnee -q --spp "$spp" --seed $((k + 1)) -o "$img" "$scene" > "$out/$who.log" 2>&1
            fi
            t1=$(now)
            mse=$(./specnee diff "$img" "$out/ref.pfm" --csv | awk -F, 'NR == 2 { print $7 }')
            tsum=$(echo "$tsum $t0 $t1" | awk '{ printf "%.6f", $1 + $3 - $2 }')
            msum=$(echo "$msum $mse" | awk '{ printf "%.9g", $1 + $2 }')
            k=$((k + 1))
        done
        echo "$who $spp $tsum $msum $seeds" | awk '{ t = $3 / $5; m = $4 / $5; printf "%-8s %6d %10.3f %14.6e %14.6e\n", $1, $2, t, m, t * m }'
    done
done | tee "$out/table.txt"
awk -v last="$(echo $ladder | awk '{ print $NF }')" '$2 == last { p[$1] = $5 }
    END { if (p["specnee"] > 0) printf "equal error at %s spp: specnee needs %.2fx less time than pbrt-v4\n", last, p["pbrt"] / p["specnee"] }' "$out/table.txt"
