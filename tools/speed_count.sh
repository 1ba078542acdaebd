#!/bin/sh
# tools/speed_count.sh - two specnee binaries on a folder of scenes: instructions
# per render and whether the images are the same to the byte
#
#   sh tools/speed_count.sh [--spp S] [--no-valgrind] OLD_BINARY NEW_BINARY SCENE.pbrt...
#
# Answers "is this change faster, and did it change any image?" on a shared,
# noisy machine, where seconds are blurred and instruction counts are not.  Each
# scene is rendered by both binaries at S spp (default 4), seed 1, one thread,
# into .pfm files under build/speed-count/, which `cmp` compares byte for byte
# (a speed change must keep every image: docs/speed.md).  Under callgrind
# (`--dump-instr=no`) each render's instruction count is printed with the ratio
# new / old, and the geometric mean of the ratios at the end.  --no-valgrind
# only renders and compares (seconds instead of minutes).  The scenes are run
# from their own folder (their includes and textures are found there).
# Needs valgrind for the counts; the scenes' outputs are overridden by -o.
set -eu
spp=4; vg=1
while [ $# -gt 0 ]; do
    case "$1" in
        --spp) spp=$2; shift 2 ;;
        --no-valgrind) vg=0; shift ;;
        *) break ;;
    esac
done
[ $# -ge 3 ] || { echo "usage: sh tools/speed_count.sh [--spp S] [--no-valgrind] OLD NEW SCENE.pbrt..." >&2; exit 2; }
old=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
new=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
shift 2
out=$(pwd)/build/speed-count
mkdir -p "$out"
same=0; differ=0; logsum=0; n=0
printf '%-40s %15s %15s %7s  %s\n' scene "Ir old" "Ir new" new/old image
for f in "$@"; do
    name=$(basename "$f" .pbrt)
    dir=$(cd "$(dirname "$f")" && pwd)
    for which in old new; do
        eval bin=\$$which
        if [ $vg = 1 ]; then
            (cd "$dir" && valgrind --tool=callgrind --dump-instr=no --callgrind-out-file=/dev/null \
                "$bin" -q --spp "$spp" --seed 1 --threads 1 -o "$out/$name-$which.pfm" "$(basename "$f")" \
                >/dev/null 2>"$out/$name-$which.log") || true
        else
            (cd "$dir" && "$bin" -q --spp "$spp" --seed 1 --threads 1 -o "$out/$name-$which.pfm" \
                "$(basename "$f")" >/dev/null 2>"$out/$name-$which.log") || true
        fi
    done
    if cmp -s "$out/$name-old.pfm" "$out/$name-new.pfm"; then img=same; same=$((same + 1));
    else img=DIFFERS; differ=$((differ + 1)); fi
    if [ $vg = 1 ]; then
        a=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$out/$name-old.log")
        b=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$out/$name-new.log")
        if [ -n "$a" ] && [ -n "$b" ]; then
            r=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", b / a }')
            logsum=$(awk -v s="$logsum" -v r="$r" 'BEGIN { printf "%.9f", s + log(r) }')
            n=$((n + 1))
            printf '%-40s %15s %15s %7s  %s\n' "$name" "$a" "$b" "$r" "$img"
            continue
        fi
    fi
    printf '%-40s %15s %15s %7s  %s\n' "$name" - - - "$img"
done
[ $n -gt 0 ] && awk -v s="$logsum" -v n="$n" 'BEGIN { printf "geometric mean new/old: %.3f over %d scenes\n", exp(s / n), n }'
echo "images: $same same, $differ differ"
[ $differ = 0 ]
