#!/bin/sh
# tools/media_bench.sh - the heterogeneous-media measurements of docs/media.md and
# docs/RESULTS.md: equal error against pbrt-v4's volpath, and spectral MIS against
# --chromatic-media terminate, on the coloured-smoke family and a grey cloud.
#
#   PBRT=/path/to/pbrt sh tools/media_bench.sh [--ref-spp N] [--spp "16 32 64 128"]
#        [--seeds K] [--mis-seeds M] [--only realbench|converge|summary] [--out DIR]
#
# 1. Writes the scenes to DIR/smoke.d and DIR/cloud.d (default DIR build/medbench),
#    each 64 x 64 with a sobol sampler: smoke-1x, -2x, -4x, -8x (tools/smoke_scene.sh --spread K:
#    the blue sigma_t is K times the red one; scenes/smoke.pbrt is the 4x one at
#    96 x 96) and cloud-grey (tests/data/grid/cloud.pbrt's procedural cloud with a
#    grey sigma_a 0.6, sigma_s 9).
# 2. tools/realbench.sh on them, one thread each, CPU time, the renderers taking
#    turns (--threads 1 --time cpu): pbrt-v4's reference at N spp (default 1024),
#    the spp ladder (default 16 32 64 128) with K seeds (default 2); its tables,
#    DIR/smoke/table.md and DIR/cloud/table.md, give the time specnee needs for
#    pbrt-v4's MSE at 64 spp.
# 3. specnee converge on each scene against that reference, spectral-tree with
#    --chromatic-media terminate (the baseline) and with spectral MIS, the same
#    ladder, M seeds (default 5), one thread, CPU time: DIR/GROUP/NAME/mis.csv and
#    .md (MSE change at equal spp and at equal time, with 95 % intervals).
# 4. DIR/hetmedia.md: the two realbench tables as one, and one row per scene of
#    the converge tables (spectral MIS against termination), for docs/RESULTS.md.
# --only runs one of 2, 3 and 4 (run 2 and 3 side by side: converge waits for
# each reference realbench writes; then --only summary).
set -u
refspp=1024
ladder="16 32 64 128"
seeds=2
mseeds=5
only=
top=build/medbench
while [ $# -gt 0 ]; do
    case "$1" in
        --ref-spp) refspp=$2; shift 2 ;;
        --spp) ladder=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        --mis-seeds) mseeds=$2; shift 2 ;;
        --only) only=$2; shift 2 ;;
        --out) top=$2; shift 2 ;;
        *) echo "usage: PBRT=pbrt sh tools/media_bench.sh [--ref-spp N] [--spp LADDER] [--seeds K] [--mis-seeds M] [--only realbench|converge|summary] [--out DIR]" >&2; exit 2 ;;
    esac
done
[ -x ./specnee ] || { echo "media_bench: run it from the repository root after make" >&2; exit 2; }
mkdir -p "$top/smoke.d" "$top/cloud.d"
summary() {
    {
        sed -n 1,2p "$top/smoke/table.md"
        grep -h '^| [a-z]' "$top/smoke/table.md" "$top/cloud/table.md" 2> /dev/null | grep -v '^| scene'
        echo
        echo "| scene | blue / red σ_t (rgb) | MSE change at $last spp | time per sample | MSE change at equal time |"
        echo "|---|---|---|---|---|"
        for f in "$top"/smoke/*/mis.md "$top"/cloud/*/mis.md; do
            [ -f "$f" ] || continue
            name=$(basename "$(dirname "$f")")
            case $name in smoke-*) k=${name#smoke-}; k=${k%x} ;; *) k=1 ;; esac
            awk -F'|' -v n="$name" -v k="$k" '$2 ~ /^ spectral-tree $/ { printf "| %s | %s | %s | %s | %s |\n", n, k, $4, $6, $7; exit }' "$f" |
                sed 's/  */ /g'
        done
        echo
        echo "(tools/media_bench.sh: realbench --threads 1 --time cpu --ref-spp $refspp --spp \"$ladder\" --seeds $seeds; converge $mseeds seeds, CPU time, one thread; $(uname -m), $(getconf _NPROCESSORS_ONLN) cores)"
    } > "$top/hetmedia.md"
    echo "wrote $top/hetmedia.md" >&2
}
last=$(echo $ladder | awk '{ print $NF }')
[ "$only" = summary ] && { summary; exit 0; }
if [ "$only" != converge ]; then
for k in 1 2 4 8; do
    sh tools/smoke_scene.sh --spread $k --res 64 --spp 64 > "$top/smoke.d/smoke-${k}x.pbrt"
done
sed -e 's/xresolution" \[ 32 \]/xresolution" [ 64 ]/; s/yresolution" \[ 32 \]/yresolution" [ 64 ]/' \
    -e 's/"independent"/"sobol"/' \
    -e 's/"rgb sigma_a" \[ 0.5 0.6 0.8 \] "rgb sigma_s" \[ 8 9 10 \]/"rgb sigma_a" [ 0.6 0.6 0.6 ] "rgb sigma_s" [ 9 9 9 ]/' \
    tests/data/grid/cloud.pbrt > "$top/cloud.d/cloud-grey.pbrt"
grep -q 'sigma_s" \[ 9 9 9 \]' "$top/cloud.d/cloud-grey.pbrt" || { echo "media_bench: cloud.pbrt changed" >&2; exit 1; }
for group in smoke cloud; do
    sh tools/realbench.sh --threads 1 --time cpu --ref-spp "$refspp" --spp "$ladder" --seeds "$seeds" \
        --out "$top/$group" "$top/$group.d" || exit 1
done
fi
[ "$only" = realbench ] && exit 0
spps=$(echo $ladder | tr ' ' ',')
for scene in "$top"/smoke.d/*.pbrt "$top"/cloud.d/*.pbrt; do
    name=$(basename "$scene" .pbrt)
    group=$(basename "$(dirname "$scene")" .d)
    ref=$top/$group/$name/ref.pfm
    # realbench's reference is complete once its 1-spp render has started
    while [ ! -s "$top/$group/$name/ladder.txt" ]; do sleep 10; done
    echo "== $name: spectral MIS against termination" >&2
    ./specnee converge "$scene" --ref "$ref" --lights spectral-tree:medterminate,spectral-tree \
        --spp "$spps" --seeds "$mseeds" --threads 1 --time cpu --out "$top/$group/$name/mis" \
        > "$top/$group/$name/mis.log" 2>&1 || { echo "media_bench: converge failed on $name" >&2; tail -n 5 "$top/$group/$name/mis.log" >&2; }
done
summary
