#!/bin/sh
# tests/coverage.sh - docs/coverage.md, the table of the whole pbrt-v4 format,
# against what specnee does.  Run by tests/run.sh (make test); ends with
# "coverage: N passed, N failed".
#
#   sh tests/coverage.sh            check the table (self-test first)
#   sh tests/coverage.sh --totals   print the totals block the table must hold
#   sh tests/coverage.sh --write-totals   write that block into the table
#   sh tests/coverage.sh --observe  print, per row, what specnee answers
#
# The table is the machine-readable source: every "| type | parameter | ... |"
# row under a "## Category" heading, with its answer `same`, `ignored`,
# `differs`, `refused` (pbrt-v4's format) or `extension` (specnee's own).
# Three checks, each a failure when it does not hold:
#  1. every row is true of the binary.  A tiny scene per row gives the type (a
#     "(type)" row: the type alone) or the parameter, with a value of its type
#     (the row's pbrt-v4 default when that is a literal, else a fixed one):
#     `same`/`ignored`/`differs`/`extension` must load (exit 0) with no refusal
#     on stderr;
#     `refused` must fail with "valid pbrt-v4" or "not in the specnee subset"
#     (refused by name), naming the parameter unless its type is refused.
#  2. specnee reads nothing the table does not list, per type: each accepted
#     type is given an unknown parameter, and every "ptype name" of the list its
#     "unused parameter (... reads: ...)" message prints must be a row of that
#     type (rgb and blackbody count as spectrum; a texture class lists one set
#     for its float and spectrum kinds).
#  3. specnee reads nothing the table does not list, per source file: every
#     parameter name passed as a string literal to the parser's getters in the
#     builders (scene.c, options.c, material.c, ...) is a row of the file's
#     categories.  This catches a getter whose directive forgets to list it.
# And the totals block between the <!-- totals --> markers is what --totals
# computes from the rows.  The self-test first plants a deleted row, a false
# "same", a false "refused" and a getter of an unlisted name: each must fail.
#
# POSIX sh + awk.  SPECNEE_BIN names the binary (./specnee).
set -u
cd "$(dirname "$0")/.." || exit 2
bin=${SPECNEE_BIN:-./specnee}
tmp=${SPECNEE_TEST_TMP:-tests/tmp}/coverage
table=docs/coverage.md
mode=check
case ${1:-} in
    --totals) mode=totals ;;
    --write-totals) mode=write ;;
    --observe) mode=observe ;;
    "") ;;
    *) echo "usage: sh tests/coverage.sh [--totals | --write-totals | --observe]" >&2; exit 2 ;;
esac
rm -rf "$tmp"
mkdir -p "$tmp/run"
root=$(pwd)

# ---- the rows of a table file: category TAB type TAB parameter TAB default TAB answer
rows() {
    awk '
    function trim(s) { gsub(/^[ \t]+|[ \t]+$/, "", s); gsub(/`/, "", s); return s }
    /^## / { cat = tolower(substr($0, 4)); intable = 0; next }
    /^[ \t]*\|/ {
        n = split($0, c, "|")
        if (trim(c[2]) == "type" && trim(c[3]) == "parameter") { intable = 1; next }
        if (!intable || $0 ~ /^[ \t]*\|[- :|]*$/) next
        printf "%s\t%s\t%s\t%s\t%s\n", cat, trim(c[2]), trim(c[3]), trim(c[4]), trim(c[5])
        next
    }
    { intable = 0 }' "$1"
}

# ---- the totals block computed from rows on stdin
totals() {
    awk -F'\t' '
    $5 == "extension" { next }
    { c = $1; if (!(c in seen)) { seen[c] = 1; order[++n] = c }
      if ($3 == "(type)") { types[c]++; tt++; if ($5 != "refused") tok[c]++; next }
      if (c == "directives") {          # a directive is a type of its own, its forms the rows
          if (!((c, $2) in dir)) { dir[c, $2] = 1; types[c]++; tt++ }
          if ($5 != "refused" && !((c, $2) in dok)) { dok[c, $2] = 1; tok[c]++ } }
      par[c]++; a[c, $5]++; pt++; at[$5]++ }
    END {
        print "| category | types (accepted) | parameters | same | ignored | differs | refused |"
        print "|---|---|---|---|---|---|---|"
        for (i = 1; i <= n; i++) { c = order[i]; tk += tok[c]
            printf "| %s | %d (%d) | %d | %d | %d | %d | %d |\n", c, types[c], tok[c], par[c],
                a[c, "same"], a[c, "ignored"], a[c, "differs"], a[c, "refused"] }
        printf "| all | %d (%d) | %d | %d | %d | %d | %d |\n", tt, tk, pt, at["same"], at["ignored"],
            at["differs"], at["refused"]
    }'
}

# ---- one scene per row (and one probe per type) under $tmp/run; the list of
# runs as: id TAB category TAB type TAB parameter (id "p..." : the probes)
scenes() {
    awk -F'\t' -v dir="$tmp/run" -v root="$root" '
    BEGIN {
        texdefs = "Texture \"tex\" \"float\" \"constant\" \"float value\" 0.5\n" \
                  "Texture \"tex\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n"
        mixdefs = "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n" \
                  "MakeNamedMaterial \"b\" \"string type\" \"conductor\"\n"
        tri = "[ 0 0 0  1 0 0  0 1 0 ]"; quad = "[ 0 0 0  1 0 0  0 1 0  1 1 0 ]"
        # values a parameter needs where one number or the default will not do
        ov["trianglemesh|point3 P"] = tri;  ov["trianglemesh|normal N"] = "[ 0 0 1  0 0 1  0 0 1 ]"
        ov["trianglemesh|point2 uv"] = "[ 0 0  1 0  0 1 ]"; ov["trianglemesh|integer indices"] = "[ 0 1 2 ]"
        ov["trianglemesh|vector3 S"] = "[ 1 0 0  1 0 0  1 0 0 ]"
        ov["bilinearmesh|point3 P"] = quad; ov["bilinearmesh|normal N"] = "[ 0 0 1  0 0 1  0 0 1  0 0 1 ]"
        ov["bilinearmesh|point2 uv"] = "[ 0 0  1 0  0 1  1 1 ]"; ov["bilinearmesh|integer indices"] = "[ 0 1 2 3 ]"
        ov["plymesh|string filename"] = "\"" root "/tests/data/uvsquare.ply\""   # uv: displacement
        ov["float imagemap|string filename"] = "\"" root "/fuzz/seeds/pfm/rgb.pfm\""
        ov["spectrum imagemap|string filename"] = ov["float imagemap|string filename"]
        ov["infinite|string filename"] = ov["float imagemap|string filename"]
        ov["diffuse|string filename"] = ov["float imagemap|string filename"]
        ov["bilinearmesh|string emissionfilename"] = ov["float imagemap|string filename"]
        ov["infinite|point3 portal"] = "[ -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5 ] \"rgb L\" [ 1 1 1 ]"
        ov["perspective|float screenwindow"] = "[ -1 1 -1 1 ]"
        ov["orthographic|float screenwindow"] = ov["perspective|float screenwindow"]
        ov["spherical|float screenwindow"] = ov["perspective|float screenwindow"]
        ov["realistic|string lensfile"] = "\"" root "/tests/data/lenses/wide.22mm.dat\""
        ex["realistic"] = "\"string lensfile\" " ov["realistic|string lensfile"]
        ov["realistic|string aperture"] = "\"pentagon\""
        ov["rgb|float cropwindow"] = "[ 0 1 0 1 ]"; ov["rgb|integer pixelbounds"] = "[ 0 4 0 4 ]"
        ov["gbuffer|float cropwindow"] = "[ 0 1 0 1 ]"; ov["gbuffer|integer pixelbounds"] = "[ 0 4 0 4 ]"
        ov["rgb|float whitebalance"] = 6500; ov["gbuffer|float whitebalance"] = 6500
        ov["rgb|string filename"] = "\"out.pfm\""; ov["gbuffer|string filename"] = "\"out.pfm\""
        ov["spectral|float cropwindow"] = "[ 0 1 0 1 ]"; ov["spectral|integer pixelbounds"] = "[ 0 4 0 4 ]"
        ov["spectral|float whitebalance"] = 6500; ov["spectral|string filename"] = "\"out.exr\""
        ov["diffuse|float power"] = 10
        nmap = "\"" root "/fuzz/seeds/pfm/rgb.pfm\""      # the "string normalmap" of every material
        ov["homogeneous|string preset"] = "\"Wholemilk\""
        ov["dielectric|spectrum eta"] = "\"glass-BK7\""; ov["thindielectric|spectrum eta"] = "\"glass-BK7\""
        # what a type needs besides the parameter
        ex["trianglemesh"] = "\"point3 P\" " tri; ex["bilinearmesh"] = "\"point3 P\" " quad
        ex["plymesh"] = "\"string filename\" " ov["plymesh|string filename"]
        ex["float imagemap"] = "\"string filename\" " ov["float imagemap|string filename"]
        ex["spectrum imagemap"] = ex["float imagemap"]
        ex["uniformgrid"] = "\"float density\" [ 0.5 ]"
        ex["curve"] = "\"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]"; ov["curve|point3 P"] = "[ 0 0 0  1 0 0  2 0 0  3 0 0 ]"
        ex["loopsubdiv"] = "\"integer indices\" [ 0 1 2 ];\"point3 P\" " tri
        ov["loopsubdiv|integer indices"] = "[ 0 1 2 ]"; ov["loopsubdiv|point3 P"] = tri
        ex["mix"] = "\"string materials\" [ \"a\" \"b\" ]"
        ov["mix|string materials"] = "[ \"a\" \"b\" ]"
        ov["uniformgrid|point3 p1"] = "[ 1 1 1 ]"
        ex["rgbgrid"] = "\"rgb sigma_s\" [ 0.5 0.5 0.5 ]"; ov["rgbgrid|point3 p1"] = "[ 1 1 1 ]"
        ov["nanovdb|string filename"] = "\"" root "/tests/data/nanovdb/cloud.nvdb\""
        ex["nanovdb"] = "\"string filename\" " ov["nanovdb|string filename"]
        ov["measured|string filename"] = "\"" root "/tests/data/measured/ggx.bsdf\""
        ex["measured"] = "\"string filename\" " ov["measured|string filename"]
        ov["goniometric|string filename"] = "\"" root "/tests/data/lights/gonio16.pfm\""
        ex["goniometric"] = "\"string filename\" " ov["goniometric|string filename"]
        ov["projection|string filename"] = "\"" root "/tests/data/lights/proj16x8.pfm\""
        ex["projection"] = "\"string filename\" " ov["projection|string filename"]
        ov["rgbgrid|rgb Le"] = "[ 0.5 0.5 0.5 ] \"rgb sigma_a\" [ 0.5 0.5 0.5 ]"
        ex["fluorescent"] = "\"spectrum excitation\" [ 300 1 400 0 ];\"spectrum emission\" [ 400 0 500 1 ]"
        ov["subsurface|string name"] = "\"Skin1\""      # sigma_a with sigma_s, mfp with a reflectance:
        ov["subsurface|spectrum sigma_a"] = "[ 300 0.5 830 0.5 ] \"rgb sigma_s\" [ 1 1 1 ]"
        ov["subsurface|texture sigma_a"] = "\"tex\" \"rgb sigma_s\" [ 1 1 1 ]"
        ov["subsurface|spectrum sigma_s"] = "[ 300 0.5 830 0.5 ] \"rgb sigma_a\" [ 1 1 1 ]"
        ov["subsurface|texture sigma_s"] = "\"tex\" \"rgb sigma_a\" [ 1 1 1 ]"
        ov["subsurface|spectrum mfp"] = "[ 300 0.5 830 0.5 ] \"rgb reflectance\" [ 0.5 0.5 0.5 ]"
        ov["subsurface|texture mfp"] = "\"tex\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]"
        ov["dielectric|float cauchyA"] = "1.5 \"float cauchyB\" 0.004"
        ov["dielectric|float cauchyB"] = "0.004 \"float cauchyA\" 1.5"
        gen["float"] = "0.5"; gen["integer"] = "1"; gen["bool"] = "false"; gen["string"] = "\"x\""
        gen["point2"] = "[ 0 0 ]"; gen["vector2"] = "[ 0 1 ]"; gen["point3"] = "[ 0 0 0 ]"
        gen["vector3"] = "[ 0 0 1 ]"; gen["normal"] = "[ 0 0 1 ]"; gen["rgb"] = "[ 0.5 0.5 0.5 ]"
        gen["spectrum"] = "[ 300 0.5 830 0.5 ]"; gen["texture"] = "\"tex\""
    }
    function value(c, type, param, def,   pt, q) {
        if (c == "media" && param == "string type") return "\"" type "\""
        if ((type "|" param) in ov) return ov[type "|" param]
        if (c == "materials" && param == "string normalmap") return nmap
        # u and v roughness given alone are anisotropic: give the pair, equal
        if (param ~ /[ .][uv]roughness$/) {
            pt = param; sub(/ .*/, "", pt)
            q = param; sub(/^[a-z]+ /, "", q)
            q = (q ~ /uroughness$/) ? substr(q, 1, length(q) - 10) "vroughness" : substr(q, 1, length(q) - 10) "uroughness"
            return gen[pt] " \"" pt " " q "\" " gen[pt]
        }
        pt = param; sub(/ .*/, "", pt)
        if ((pt == "float" || pt == "integer") && def ~ /^-?[0-9]+(\.[0-9]+)?$/) return def
        if (pt == "bool" && (def == "true" || def == "false")) return def
        if (pt == "string" && def ~ /^"[^"]+"$/) return def
        if (pt ~ /^(point|vector|normal)/ && def ~ /^-?[0-9.]+( -?[0-9.]+)+$/) return "[ " def " ]"
        return gen[pt]
    }
    # the scene of one row: category c, type t, the parameter as written (p)
    function scene(c, t, p,   k, cls, e, m, j, it) {
        e = ""
        if (t in ex) {                  # the extras, less the parameter of the row
            k = p; sub(/^"[a-z0-9]+ /, "", k); sub(/".*/, "", k)
            m = split(ex[t], it, ";")
            for (j = 1; j <= m; j++) if (p == "" || index(it[j], " " k "\"") == 0) e = e " " it[j]
        }
        if (c == "shapes") return "WorldBegin\n" texdefs "Shape \"" t "\" " p e "\n"
        if (c == "materials") return "WorldBegin\n" texdefs (t == "mix" ? mixdefs : "") "Material \"" t "\" " p e "\nShape \"sphere\"\n"
        if (c == "textures") { cls = t; sub(/^[a-z]+ /, "", cls)
            return "WorldBegin\n" texdefs "Texture \"t\" \"" substr(t, 1, index(t, " ") - 1) "\" \"" cls "\" " p e "\n" }
        if (c == "lights") return "WorldBegin\nLightSource \"" t "\" " p e "\n"
        if (c == "area lights") return "WorldBegin\nAttributeBegin\nAreaLightSource \"" t "\" " p "\nShape \"sphere\"\nAttributeEnd\n"
        if (c == "cameras") return "Camera \"" t "\" " p e "\nWorldBegin\n"
        if (c == "samplers") return "Sampler \"" t "\" " p "\nWorldBegin\n"
        if (c == "filters") return "PixelFilter \"" t "\" " p "\nWorldBegin\n"
        if (c == "films") return "Film \"" t "\" " p "\nWorldBegin\n"
        if (c == "media") return "MakeNamedMedium \"m\" \"string type\" \"" t "\" " p e "\nWorldBegin\n"
        if (c == "integrators") return "Integrator \"" t "\" " p "\nWorldBegin\n"
        if (c == "accelerators") return "Accelerator \"" t "\" " p "\nWorldBegin\n"
        if (c == "directives") return (index(p, "WorldBegin") ? "" : "WorldBegin\n") p "\n"
        return ""
    }
    function emit(id, c, t, par, text) {
        if (text == "") { print "coverage: no scene for category " c > "/dev/stderr"; return }
        printf "%s", text > (dir "/" id ".pbrt"); close(dir "/" id ".pbrt")
        printf "%s\t%s\t%s\t%s\n", id, c, t, par
    }
    {
        n++
        if ($3 == "(type)") {
            emit("r" n, $1, $2, $3, scene($1, $2, ""))
            if ($1 != "directives" && $5 != "refused")
                emit("p" n, $1, $2, "probe", scene($1, $2, "\"float zzcoverage\" 1"))
        } else if ($1 == "directives") emit("r" n, $1, $2, $3, scene($1, $2, $3))
        else emit("r" n, $1, $2, $3, scene($1, $2, "\"" $3 "\" " value($1, $2, $3, $4)))
    }'
}

# ---- run every scene: $tmp/run/ID.rc and ID.err
run_all() {
    printf '' > "$tmp/run/inc.pbrt"
    while IFS='	' read -r id rest; do
        (cd "$tmp/run" && "$root/$bin" --dump-scene "$id.pbrt" > /dev/null 2> "$id.err"
         echo $? > "$id.rc")
    done < "$tmp/runs.tsv"
}

# ---- judge rows (file $1) against the runs: one "FAIL ..." line per problem,
# then "judged N"
judge() {
    awk -F'\t' -v dir="$tmp/run" '
    function slurp(f,   s, l) { s = ""; while ((getline l < f) > 0) s = s l "\n"; close(f); return s }
    FILENAME == ARGV[1] { id[$2 "|" $3 "|" $4] = $1; next }      # runs.tsv
    {   key = $1 "|" $2 "|" $3
        if ($3 == "(type)") { typeans[$1 "|" $2] = $5 }
        listed[$1 "|" $2 "|" $3] = 1
        row[++n] = $0
    }
    END {
        for (i = 1; i <= n; i++) {
            split(row[i], f, "\t"); c = f[1]; t = f[2]; p = f[3]; ans = f[5]
            if (ans !~ /^(same|ignored|differs|refused|extension)$/) {
                printf "FAIL %s %s %s: answer \"%s\" is not same, ignored, differs, refused or extension\n", c, t, p, ans; bad++; continue }
            k = c "|" t "|" p
            if (!(k in id)) { printf "FAIL %s %s %s: no run (table changed under the test)\n", c, t, p; bad++; continue }
            rc = slurp(dir "/" id[k] ".rc") + 0; err = slurp(dir "/" id[k] ".err")
            refusal = err ~ /valid pbrt-v4|not in the specnee subset/
            unknown = err ~ /unused parameter|wrong type|Unknown directive|unknown [a-z ]*(type|class)/
            if (ans == "refused") {
                nm = p; sub(/^[a-z0-9]+ /, "", nm)
                if (rc == 0) why = "loads (exit 0)"
                else if (!refusal) why = "is not refused by name: " err
                else if (c != "directives" && p != "(type)" && typeans[c "|" t] != "refused" && index(err, nm) == 0)
                    why = "is refused without its name: " err
                else why = ""
            } else {
                if (rc != 0) why = "does not load: " err
                else if (refusal || unknown) why = "is refused: " err
                else why = ""
            }
            if (why != "") { sub(/\n$/, "", why); printf "FAIL %s %s %s (%s): %s\n", c, t, p, ans, why; bad++ }
            judged++
        }
        # check 2: what each accepted type says it reads is listed
        for (k in id) {
            split(k, f, "|"); if (f[3] != "probe") continue
            c = f[1]; t = f[2]
            if (!((c "|" t "|(type)") in listed) || typeans[c "|" t] == "refused") continue
            err = slurp(dir "/" id[k] ".err")
            if (match(err, /reads: [^\n]*\)\n/)) list = substr(err, RSTART + 7, RLENGTH - 9)
            else if (match(err, /reads: [^\n]*, /))
                list = substr(err, RSTART + 7, RLENGTH - 9)   # a message cut at its 511 bytes: the whole items
            else { printf "FAIL %s %s: the probe got no \"reads:\" list: %s\n", c, t, err; bad++; continue }
            if (list == "nothing") continue
            m = split(list, it, ", ")
            for (j = 1; j <= m; j++) {
                q = it[j]; sub(/^(rgb|blackbody) /, "spectrum ", q)
                # a texture class lists what it reads for both kinds (float, spectrum)
                o = t; if (c == "textures") { if (sub(/^float /, "spectrum ", o) == 0) sub(/^spectrum /, "float ", o) }
                if (!((c "|" t "|" q) in listed) && !((c "|" o "|" q) in listed) && !((c "|" t "|" it[j]) in listed)) { printf "FAIL %s %s: specnee reads \"%s\", the table does not list it\n", c, t, it[j]; bad++ }
            }
            judged++
        }
        printf "judged %d\n", judged
    }' "$tmp/runs.tsv" "$1"
}

# ---- check 3: parameter names in the getters of the builders (files: $2...),
# each a row of its file's categories in the rows file $1
sources() {
    r=$1; shift
    awk -F'\t' '
    BEGIN {
        cats["scene.c"] = "shapes,directives"; cats["geometry.c"] = "shapes"
        cats["options.c"] = "cameras,films,filters,samplers,integrators,accelerators"
        cats["material.c"] = "materials"; cats["conductor.c"] = "materials"; cats["layered.c"] = "materials"; cats["bump.c"] = "materials"
        cats["parser.c"] = "materials"; cats["texture.c"] = "textures"; cats["medium.c"] = "media,directives"
        cats["lights.c"] = "area lights"; cats["delta.c"] = "lights"; cats["infinite.c"] = "lights"
        # pbrt-v3 names that a builder looks up only to refuse them with the pbrt-v4 name
        # (pbrt-v4 has no such parameter, so no row lists them)
        v3only["nlevels"] = 1
    }
    FILENAME == ARGV[1] { nm = $3; sub(/^[a-z0-9]+ /, "", nm); if ($1 == "directives") nm = $3
                          has[$1 "|" nm] = 1; next }
    FNR == 1 { incomment = 0 }
    {
        f = FILENAME; sub(/.*\//, "", f)
        if (!(f in cats)) { if (FNR == 1) printf "FAIL %s: no categories for this file\n", f; next }
        # the code of the line: comments and strcmp() arguments left out
        line = $0
        if (incomment) { if (!sub(/^.*\*\//, "", line)) next; incomment = 0 }
        gsub(/\/\*([^*]|\*[^\/])*\*\//, "", line)
        if (sub(/\/\*.*$/, "", line)) incomment = 1
        gsub(/strcmp\([^)]*\)/, "", line)
        while (match(line, /(get_float|get_int|get_bool|get_string|get_finite|get_points|param_find|find_spectrum_param|note_not_positive|accept_not_positive|fail_param|texture_arg|rough_param)\(/)) {
            line = substr(line, RSTART + RLENGTH); rest = line
            while (match(rest, /"([^"\\]|\\.)*"/)) {
                s = substr(rest, RSTART + 1, RLENGTH - 2); rest = substr(rest, RSTART + RLENGTH)
                if (s !~ /^[A-Za-z][A-Za-z0-9_.]*$/) continue
                if (s in v3only) continue
                found++; ok = 0; m = split(cats[f], cl, ",")
                for (j = 1; j <= m; j++) {
                    if ((cl[j] "|" s) in has) ok = 1
                    if (cl[j] == "directives") for (k in has) if (index(k, "directives|") == 1 && index(k, "\"string " s "\"")) ok = 1
                }
                if (!ok) { printf "FAIL %s:%d: reads \"%s\", which no row of %s lists\n", f, FNR, s, cats[f]; bad++ }
            }
        }
    }
    END { printf "names %d\n", found }' "$r" "$@"
}
builders="scene.c geometry.c options.c material.c conductor.c layered.c bump.c parser.c texture.c medium.c lights.c delta.c infinite.c"

rows "$table" > "$tmp/rows.tsv"
if [ "$mode" = totals ]; then totals < "$tmp/rows.tsv"; exit 0; fi
if [ "$mode" = write ]; then
    totals < "$tmp/rows.tsv" > "$tmp/totals.md"
    awk -v f="$tmp/totals.md" '/<!-- \/totals -->/ { on = 0 } !on { print }
        /<!-- totals -->/ { on = 1; while ((getline l < f) > 0) print l }' "$table" > "$tmp/table.md" &&
        cp "$tmp/table.md" "$table"
    exit
fi
scenes < "$tmp/rows.tsv" > "$tmp/runs.tsv"
run_all
if [ "$mode" = observe ]; then
    while IFS='	' read -r id c t p; do
        printf '%s\t%s\t%s\t%s\t%s\n' "$c" "$t" "$p" "$(cat "$tmp/run/$id.rc")" "$(tr '\n' ' ' < "$tmp/run/$id.err")"
    done < "$tmp/runs.tsv"
    exit 0
fi

passed=0
failed=0
ok()   { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL $1"; }

# ---- self-test: each way the table can be wrong is reported
n_rows=$(wc -l < "$tmp/rows.tsv")
# a row of a type specnee accepts deleted (the probe still prints its name)
awk -F'\t' 'done || !($1 == "shapes" && $2 == "sphere" && $3 == "float radius")' "$tmp/rows.tsv" > "$tmp/del.tsv"
if [ "$(wc -l < "$tmp/del.tsv")" -eq $((n_rows - 1)) ] && judge "$tmp/del.tsv" | grep -q 'specnee reads "float radius"'
then ok; else fail "coverage_selftest: deleting the row sphere \"float radius\" is not reported"; fi
# a refused row claimed the same (the first refused row: a directive's, since
# every parameter row of an accepted type has pbrt-v4's meaning or is ignored),
# and a row claimed refused that specnee reads (the first among the parameters
# of the types specnee accepts)
awk -F'\t' -v claimed="$tmp/claimed.tsv" 'BEGIN { OFS = "\t" }
     $3 == "(type)" { acc = $5 != "refused"; print; next }
     $5 == "refused" && !r { $5 = "same"; r = 1; print > claimed }
     acc && $1 != "directives" && $5 == "same" && !s { $5 = "refused"; s = 1; print > claimed }
     { print }' "$tmp/rows.tsv" > "$tmp/claim.tsv"
judge "$tmp/claim.tsv" > "$tmp/claim.txt"
n_claim=0
while IFS='	' read -r c t p d a; do
    grep -qF "FAIL $c $t $p ($a)" "$tmp/claim.txt" && n_claim=$((n_claim + 1))
done < "$tmp/claimed.tsv"
if [ "$n_claim" -eq 2 ]; then ok
else fail "coverage_selftest: $n_claim of 2 false claims (a refused row called same, a same one refused) reported"; fi
# a getter of a name no row lists, in a builder
printf 'static int f(Parser *P, ParamList *pl)\n{\n    float v;\n    /* "zzcomment" */\n    if (!get_float(P, pl, "zzcoverage", 0, &v)) return 0;\n    return 1;\n}\n' > "$tmp/scene.c"
sources "$tmp/rows.tsv" "$tmp/scene.c" > "$tmp/getter.txt"
if grep -q 'reads "zzcoverage"' "$tmp/getter.txt" && ! grep -q zzcomment "$tmp/getter.txt"
then ok; else fail "coverage_selftest: a getter of an unlisted name in scene.c is not reported"; fi

# ---- the table
judge "$tmp/rows.tsv" > "$tmp/judge.txt"
grep '^FAIL' "$tmp/judge.txt"
j=$(grep -c '^FAIL' "$tmp/judge.txt")
failed=$((failed + j))
passed=$((passed + $(sed -n 's/^judged //p' "$tmp/judge.txt") - j))
sources "$tmp/rows.tsv" $builders > "$tmp/sources.txt"
grep '^FAIL' "$tmp/sources.txt"
s=$(grep -c '^FAIL' "$tmp/sources.txt")
if [ "$s" -eq 0 ]; then ok; else failed=$((failed + s)); fi
# the totals block
totals < "$tmp/rows.tsv" > "$tmp/totals.md"
awk '/<!-- \/totals -->/ { on = 0 } on { print } /<!-- totals -->/ { on = 1 }' "$table" > "$tmp/totals-doc.md"
if cmp -s "$tmp/totals.md" "$tmp/totals-doc.md"; then ok
else fail "coverage_totals: the totals block of $table is not what sh tests/coverage.sh --totals prints"
     diff "$tmp/totals-doc.md" "$tmp/totals.md" | head -n 10; fi
echo "coverage: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
