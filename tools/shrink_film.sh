#!/bin/sh
# tools/shrink_film.sh - a smaller copy of a pbrt-v4 scene for comparisons.
#
#   sh tools/shrink_film.sh FILE.pbrt MAX
#
# writes FILE-small.pbrt beside FILE.pbrt (so that its relative paths still
# resolve), with the Film's "integer xresolution"/"yresolution" scaled so that the
# longer axis is MAX pixels (the aspect kept, rounded); nothing else changes.
# pbrt-v4 has no command-line flag for the resolution, so the comparisons of
# docs/real-scenes.md render such copies of big real scenes with both renderers.
set -u
f="$1"; max="$2"; out="${f%.pbrt}-small.pbrt"
flat=$(tr '\n' ' ' < "$f")
x=$(printf '%s' "$flat" | grep -o 'xresolution"* *\[* *[0-9]*' | grep -o '[0-9]*$' | head -n 1)
y=$(printf '%s' "$flat" | grep -o 'yresolution"* *\[* *[0-9]*' | grep -o '[0-9]*$' | head -n 1)
[ -n "$x" ] && [ -n "$y" ] || { echo "shrink_film: no xresolution/yresolution in $f" >&2; exit 1; }
if [ "$x" -ge "$y" ]; then nx=$max; ny=$(( (y * max + x / 2) / x )); else ny=$max; nx=$(( (x * max + y / 2) / y )); fi
[ "$nx" -ge 1 ] || nx=1; [ "$ny" -ge 1 ] || ny=1
sed -e "s/\(xresolution\"*[[:space:]]*\[*[[:space:]]*\)$x\([^0-9]\)/\1$nx\2/" \
    -e "s/\(yresolution\"*[[:space:]]*\[*[[:space:]]*\)$y\([^0-9]\)/\1$ny\2/" \
    -e "s/\(xresolution\"*[[:space:]]*\[*[[:space:]]*\)$x\$/\1$nx/" \
    -e "s/\(yresolution\"*[[:space:]]*\[*[[:space:]]*\)$y\$/\1$ny/" "$f" > "$out"
echo "$out ${nx}x${ny}"
