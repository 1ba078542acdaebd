#!/bin/sh
# tools/survey_run.sh - how far does specnee get through a folder of pbrt-v4 scenes?
#
#   sh tools/survey_run.sh [-s SPECNEE] [-t SECONDS] SCENES OUT
#
# SCENES holds one folder per scene family (as a scene collection lays them out)
# and a file SCENES/scenes.txt naming the top-level scenes, one "family/file.pbrt"
# a line.  docs/pbrt-scenes.md (Method) says how such a folder is rebuilt from a
# public collection and how its missing binary assets are stood in for
# (tools/survey_run.sh --standins SCENES writes the stand-ins: see below).
#
# Each scene is copied to a scratch folder and run from there as
#
#   specnee --res 8x8 --spp 1 --threads 1 -q -o /tmp/survey-out.pfm FILE
#
# with a time limit (default 20 s).  When specnee refuses it, the last
# "file:line: message" line of stderr that is not a note or a warning is the
# blocker; it is worked around on the scratch copy and the scene is run again,
# until it renders (at most 80 rounds):
#   - a refused parameter ("type name" named in the message) is deleted;
#   - a refused material type becomes "diffuse" without parameters;
#   - a refused texture class becomes "constant" without parameters;
#   - any other refused statement is deleted (an Include that cannot be read
#     is how a file the survey could not rebuild shows up: "not surveyed").
# So each scene gets every blocker met, in order.  OUT receives
#   OUT/log.tsv      scene <TAB> round <TAB> blocker label <TAB> raw message
#   OUT/scenes.tsv   scene <TAB> status <TAB> first blocker <TAB> every blocker
#                    <TAB> whether an included file was not surveyed (yes/no)
#   OUT/tally.tsv    blocker <TAB> scenes it stops <TAB> scenes it is first in
# where status is "renders" (as given), "clear" (renders once the included
# files the survey could not rebuild are dropped), "blocked", "stuck" (a
# work-around changed nothing) or "timeout".  Labels drop the file, line and
# object names, so the same feature gets the same label in every scene.
#
#   sh tools/survey_run.sh --standins SCENES
#
# writes, for every file name a scene text quotes that is missing, a stand-in:
# a one-triangle ASCII PLY (.ply), a 2x2 PFM (.pfm), a small PNG (.png), an uncompressed
# 2x2 EXR (.exr), a flat two-point spectrum
# (.spd), an empty file (.bsdf, .nvdb, others), those gzip-compressed for
# .ply.gz and .pbrt.gz.  Included .pbrt files get none ("not surveyed").  It lists what it
# wrote in SCENES/standins.txt.  A run writes them first when that file is
# missing.

set -u
here=$(cd "$(dirname "$0")/.." && pwd)

# a 2x2 RGB half-float OpenEXR image, uncompressed (scanline, compression NONE),
# every value 1: square, as an equal-area environment map must be
exr_standin() {
    printf '\166\057\061\001\002\000\000\000\143\150\141\156\156\145\154\163\000\143\150\154\151\163\164\000\067\000\000\000\102\000\001\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000\107\000\001\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000\122\000\001\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000\000\143\157\155\160\162\145\163\163\151\157\156\000\143\157\155\160\162\145\163\163\151\157\156\000\001\000\000\000\000\144\141\164\141\127\151\156\144\157\167\000\142\157\170\062\151\000\020\000\000\000\000\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000\144\151\163\160\154\141\171\127\151\156\144\157\167\000\142\157\170\062\151\000\020\000\000\000\000\000\000\000\000\000\000\000\001\000\000'
    printf '\000\001\000\000\000\154\151\156\145\117\162\144\145\162\000\154\151\156\145\117\162\144\145\162\000\001\000\000\000\000\160\151\170\145\154\101\163\160\145\143\164\122\141\164\151\157\000\146\154\157\141\164\000\004\000\000\000\000\000\200\077\163\143\162\145\145\156\127\151\156\144\157\167\103\145\156\164\145\162\000\166\062\146\000\010\000\000\000\000\000\000\000\000\000\000\000\163\143\162\145\145\156\127\151\156\144\157\167\127\151\144\164\150\000\146\154\157\141\164\000\004\000\000\000\000\000\200\077\000\111\001\000\000\000\000\000\000\135\001\000\000\000\000\000\000\000\000\000\000\014\000\000\000\000\074\000\074\000\074\000\074\000\074\000\074\001\000\000\000\014\000\000\000\000\074\000\074\000\074\000\074\000\074\000\074'
}

standins() {
    root=$1
    : > "$root/standins.txt"
    for fam in "$root"/*/; do
        fam=${fam%/}
        find "$fam" -name '*.pbrt' -exec grep -ho '"[^"]*\.[A-Za-z0-9]*"' {} + |
        tr -d '"' | sort -u | while IFS= read -r f; do
            case $f in *.pbrt|*.gz|*.exr|*.ply|*.pfm|*.png|*.spd|*.bsdf|*.nvdb|*.tga|*.jpg) ;; *) continue ;; esac
            case $f in /*) continue ;; esac
            [ -e "$fam/$f" ] && continue
            case $f in *.pbrt) continue ;; esac
            grep -rqF "\"$f\"" --include='*.pbrt' "$fam" || continue
            # the image a Film writes is no asset
            grep -rh -A3 '^Film' --include='*.pbrt' "$fam" | grep -qF "\"$f\"" && continue
            mkdir -p "$(dirname "$fam/$f")"
            case $f in
            *.pbrt.gz) printf '# stand-in\n' | gzip -c > "$fam/$f" ;;
            *.gz) printf 'ply\n' | gzip -c > "$fam/$f" ;;
            *.ply) printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' > "$fam/$f" ;;
            *.pfm) printf 'PF\n2 2\n-1.0\n' > "$fam/$f"
                   awk 'BEGIN { for (i = 0; i < 12; i++) printf "%c%c%c%c", 0, 0, 0, 63 }' >> "$fam/$f" ;;
            *.png) cp "$here/fuzz/seeds/png/rgb8_dynamic.png" "$fam/$f" ;;
            *.exr) exr_standin > "$fam/$f" ;;
            *.spd) printf '200 1\n1000 1\n' > "$fam/$f" ;;
            *) : > "$fam/$f" ;;
            esac
            echo "${fam##*/}/$f" >> "$root/standins.txt"
        done
    done
}

# label MESSAGE: the blocker without file, line and object names
label() {
    printf '%s\n' "$1" | sed -E \
        -e 's/^[^ :]+:[0-9]+: //' \
        -e 's/ \(use [^)]*\)$//' \
        -e 's/^MakeNamedMaterial "[^"]*": type ("[^"]*")/Material \1/' \
        -e 's/^(Texture|MakeNamedMedium|NamedMaterial) "[^"]*": /\1: /' \
        -e 's/^(ObjectBegin|ObjectEnd|ObjectInstance)( "[^"]*")? is valid.*/ObjectBegin\/ObjectEnd\/ObjectInstance (instancing)/' \
        -e 's/^Include "[^"]*": .*a gzip-compressed file.*/gzip-compressed Include (.pbrt.gz; its text not surveyed)/' \
        -e 's/^Shape "plymesh": .*a gzip-compressed file.*/gzip-compressed PLY (.ply.gz)/' \
        -e 's/^Include "[^"]*": cannot read .*/included file not surveyed/' \
        -e 's/ is valid pbrt-v4 but not in the specnee subset//' \
        -e 's/^Material "[a-z]+": "string normalmap"$/"string normalmap" (a normal map, any material)/' \
        -e 's/^Film: "string sensor" "[^"]*".*/Film: "string sensor" (a named camera)/' \
        -e 's/^MediumInterface: no MakeNamedMedium defines .*/(follows: a removed medium)/' \
        -e 's/[A-Za-z0-9_./-]+\.(pbrt|ply|exr|png|pfm|spd|bsdf|nvdb)/FILE/g'
}

# fix FILE LINE MESSAGE: work the blocker around in FILE (scratch copy)
fix() {
    f=$1 l=$2 m=$3
    p=$(printf '%s\n' "$m" | grep -oE '"(bool|float|integer|string|rgb|spectrum|texture|point2|point3|point|normal|normal3|vector|vector2|vector3|blackbody|color) [A-Za-z0-9_.]+"' | head -n 1)
    mt=$(printf '%s\n' "$m" | sed -nE 's/^[^:]*:[0-9]+: (Material "|MakeNamedMaterial "[^"]*": type ")([a-z]+)" is valid pbrt-v4.*/\2/p')
    tc=$(printf '%s\n' "$m" | sed -nE 's/^[^:]*:[0-9]+: Texture "[^"]*": class "[a-z]+" is valid.*/x/p')
    awk -v L="$l" -v P="$p" -v MT="$mt" -v TC="$tc" '
    function cont(s) { return s ~ /^[ \t]*("|\[|\]|[-+.0-9])/ }
    NR < L { print; next }
    NR == L && P != "" && index($0, P) {
        i = index($0, P); pre = substr($0, 1, i - 1); rest = substr($0, i + length(P))
        if (match(rest, /^[ \t]*\[[^]]*\]/)) rest = substr(rest, RLENGTH + 1)
        else if (match(rest, /^[ \t]*("[^"]*"|[^ \t]+)/)) rest = substr(rest, RLENGTH + 1)
        s = pre rest; if (s !~ /^[ \t]*$/) print s; done = 1; next }
    NR == L && MT != "" {
        sub("\"" MT "\"", "\"diffuse\""); print; drop = 1; keep = 0; next }
    NR == L && TC != "" {
        sub(/"[a-z]+"[ \t]*$/, "\"constant\""); n = split($0, w, "\""); print w[1] "\"" w[2] "\" \"" w[4] "\" \"constant\""; drop = 1; next }
    NR == L { skip = 1; next }
    drop && cont($0) { if ($0 ~ /"string type"/) { print "  \"string type\" \"diffuse\"" } ; next }
    skip && cont($0) { next }
    { drop = 0; skip = 0; print }' "$f" > "$f.tmp" && mv "$f.tmp" "$f"
}

if [ "${1:-}" = --standins ]; then standins "$2"; exit 0; fi
S=$here/specnee T=20
while [ $# -gt 2 ]; do
    case $1 in -s) S=$2; shift 2 ;; -t) T=$2; shift 2 ;; *) break ;; esac
done
[ $# -eq 2 ] || { echo "usage: sh tools/survey_run.sh [-s SPECNEE] [-t SECONDS] SCENES OUT" >&2; exit 2; }
root=$(cd "$1" && pwd) out=$2
[ -e "$root/standins.txt" ] || standins "$root"
mkdir -p "$out"; out=$(cd "$out" && pwd)
: > "$out/log.tsv"; : > "$out/raw.tsv"
scratch=$(mktemp -d)
while read -r scene; do
    [ -n "$scene" ] || continue
    fam=${scene%%/*} file=${scene#*/}
    # the whole folder: a scene may name files of another family (../x/...)
    rm -rf "$scratch/w"; mkdir "$scratch/w"; cp -r "$root/." "$scratch/w"
    round=0 status=blocked first="" all="" prev=""
    while :; do
        round=$((round + 1))
        ( cd "$scratch/w/$fam" && timeout "$T" "$S" --res 8x8 --spp 1 --threads 1 -q \
            -o /tmp/survey-out.pfm "$file" ) > /dev/null 2> "$scratch/err"
        rc=$?
        [ $rc -eq 0 ] && { [ -z "$first" ] && status=renders; break; }
        [ $rc -eq 124 ] && { status=timeout; break; }
        msg=$(grep -E '^[^ :]+:[0-9]+: ' "$scratch/err" | grep -vE '^[^ :]+:[0-9]+: (note|warning):' | tail -n 1)
        [ -n "$msg" ] || msg=$(tail -n 1 "$scratch/err")
        lab=$(label "$msg")
        printf '%s\t%s\t%s\t%s\n' "$scene" "$round" "$lab" "$msg" >> "$out/log.tsv"
        [ -z "$first" ] && first=$lab
        case "|$all|" in *"|$lab|"*) ;; *) all=${all:+$all|}$lab ;; esac
        if [ "$msg" = "$prev" ] || [ $round -ge 80 ]; then status=stuck; break; fi
        prev=$msg
        ef=${msg%%:*} el=${msg#*:}; el=${el%%:*}
        case $el in *[!0-9]*|"") status=stuck; break ;; esac
        fix "$scratch/w/$fam/$ef" "$el" "$msg"
    done
    printf '%s\t%s\t%s\n' "$scene" "$status" "${all:--}" >> "$out/raw.tsv"
done < "$root/scenes.txt"
rm -rf "$scratch"
# blockers are the labels but "(follows: ...)" (a consequence of an earlier
# work-around) and "included file not surveyed" (no feature of specnee)
awk -F'\t' -v OFS='\t' '{
        n = split($3, b, "|"); first = ""; list = ""; ns = "no"
        for (i = 1; i <= n; i++) {
            if (b[i] ~ /not surveyed/) ns = "yes"
            if (b[i] == "included file not surveyed") continue
            if (b[i] == "-" || b[i] ~ /^\(/) continue
            if (first == "") first = b[i]
            list = list (list == "" ? "" : "|") b[i]
        }
        st = $2 == "blocked" ? (first == "" ? "clear" : "blocked") : $2
        print $1, st, (first == "" ? "-" : first), (list == "" ? "-" : list), ns
     }' "$out/raw.tsv" > "$out/scenes.tsv"
awk -F'\t' '{ n = split($4, b, "|"); for (i = 1; i <= n; i++) if (b[i] != "-") stops[b[i]]++
              if ($3 != "-") first[$3]++; st[$2 " (part not surveyed: " $5 ")"]++ }
     END { for (k in stops) printf "%s\t%d\t%d\n", k, stops[k], first[k] + 0
           for (k in st) printf "STATUS %s\t%d\t-\n", k, st[k] }' "$out/scenes.tsv" |
    sort -t '	' -k2,2nr -k1,1 > "$out/tally.tsv"
cat "$out/tally.tsv"
