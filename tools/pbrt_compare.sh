#!/bin/sh
# tools/pbrt_compare.sh - does a scene mean the same to specnee as to pbrt-v4?
#
#   PBRT=/path/to/pbrt sh tools/pbrt_compare.sh [--spp N] scene.pbrt ...
#
# Renders each scene with pbrt-v4 (the oracle: docs/real-scenes.md says how to
# build one; specnee never depends on it) and with specnee, both at N samples per
# pixel (default 256) and the scene's own resolution (pbrt-v4 has no flag that
# changes it: edit a copy of the file to render a big scene smaller), into PFM files under
# build/compare/, and prints one line per scene:
#
#   scene  Y(pbrt)  Y(specnee)  ratio  worst quadrant ratio  status
#
# Y is the luminance mean of the image (specnee diff --means), "ratio" specnee /
# pbrt-v4 over the whole image, "worst quadrant" the quadrant ratio farthest from
# 1.  status is "ok" when the image is within 2 % and every quadrant within 5 %
# (the bar of docs/real-scenes.md), "differs" otherwise, and "refused: <message>" or
# "pbrt failed" when a renderer does not render it.  Both renderers use their
# default samplers, so the figures carry Monte Carlo noise: raise --spp until a
# repeat with another seed moves the ratio by much less than the bar.
# A scene that writes EXR names gets PFM names: pbrt-v4 writes any format its
# --outfile names.  Run from the repository root after `make`.
set -u
spp=256
while [ $# -gt 0 ]; do
    case "$1" in
        --spp) spp=$2; shift 2 ;;
        --) shift; break ;;
        -*) echo "pbrt_compare: unknown option $1" >&2; exit 2 ;;
        *) break ;;
    esac
done
[ -n "${PBRT:-}" ] && [ -x "$PBRT" ] || { echo "pbrt_compare: set PBRT to a pbrt-v4 binary" >&2; exit 2; }
[ -x ./specnee ] || { echo "pbrt_compare: build specnee first (make)" >&2; exit 2; }
out=build/compare
mkdir -p "$out"
printf '%-40s %12s %12s %8s %8s  %s\n' scene "Y(pbrt)" "Y(specnee)" ratio quadrant status
for scene in "$@"; do
    name=$(basename "$scene" .pbrt)
    a="$out/$name-pbrt.pfm"; b="$out/$name-specnee.pfm"
    if ! ./specnee -q --spp "$spp" -o "$b" "$scene" > "$out/$name-specnee.log" 2>&1; then
        printf '%-40s %12s %12s %8s %8s  refused: %s\n' "$name" - - - - \
            "$(grep -v ': note:' "$out/$name-specnee.log" | head -n 1)"
        continue
    fi
    w=$(sed -n 2p "$b" | awk '{print $1}'); h=$(sed -n 2p "$b" | awk '{print $2}')
    if ! "$PBRT" --spp "$spp" --outfile "$a" "$scene" > "$out/$name-pbrt.log" 2>&1 || [ ! -f "$a" ]; then
        printf '%-40s %12s %12s %8s %8s  pbrt failed\n' "$name" - - - -
        continue
    fi
    hw=$((w / 2)); hh=$((h / 2))
    ./specnee diff "$b" "$a" --csv --means --region "q00:0,0,$hw,$hh" --region "q10:$hw,0,$w,$hh" \
        --region "q01:0,$hh,$hw,$h" --region "q11:$hw,$hh,$w,$h" > "$out/$name-diff.csv" 2>&1 ||
        { printf '%-40s  diff failed: %s\n' "$name" "$(head -n 1 "$out/$name-diff.csv")"; continue; }
    awk -F, -v name="$name" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { yt = $col["y_test"]; yr = $col["y_ref"]; r = yr > 0 ? yt / yr : 0
          if ($1 == "image") { Yt = yt; Yr = yr; R = r }
          else { d = r - 1; if (d < 0) d = -d; if (d >= worstd) { worstd = d; worst = r } } }
        END { st = (R > 0.98 && R < 1.02 && worstd < 0.05) ? "ok" : "differs"
              if (Yr == 0 && Yt == 0) st = "ok (both black)"
              printf "%-40s %12.6g %12.6g %8.4f %8.4f  %s\n", name, Yr, Yt, R, worst, st }' "$out/$name-diff.csv"
done
