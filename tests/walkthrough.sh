#!/bin/sh
# tests/walkthrough.sh - runs docs/WALKTHROUGH.md and docs/EXERCISES.md exactly as a
# student meets them, and checks every output the pages show.
#
# THE STUDENT'S SITUATION
#   A fresh copy of the repository: the files git tracks (plus new files that are
#   not ignored, so that uncommitted edits of the pages are checked too), with NO
#   build products and NO out/ directory.  With --committed the copy is a real
#   `git clone` of HEAD instead.  The copy lives in tests/tmp/walkthrough/clone/
#   (kept afterwards for inspection); the user's own tree and out/ are untouched.
#   Nothing is built for the student: the page's own first block (`make`, and the
#   `mkdir -p out` that every render needs) must do it.
#
# CONVENTION (stated in both documents)
#   Only fenced blocks opened with ```sh are run, in document order, in the root
#   of the copy.  Each non-empty line of such a block is one command (pipes and
#   redirections allowed) unless it starts with '#'.  Blocks that only work after
#   the reader has edited something are fenced ```text and are not run.
#   A command passes when
#     - it exits 0, run by `bash -o pipefail -c` (so `specnee ... | grep ...` fails
#       when specnee fails; plain `sh -c` only where bash is missing), within
#       WALKTHROUGH_TIMEOUT seconds (default 120; `make` gets 900);
#     - if it has "-o FILE", FILE exists and is not empty;
#     (so the pages cut long outputs with `sed -n '1,Np'`, which reads to the end,
#     not with `head`, whose early exit would kill specnee with SIGPIPE, exit 141);
#   and the block's output (stdout and stderr of its commands, in order) is what
#   the page shows:
#     - a ```output block after the ```sh block (with no other fenced block in
#       between) is the expected output.  Lines are compared exactly (trailing
#       blanks ignored); a line that is only "..." stands for any number of lines
#       (also none); "..." inside a line stands for any text (timings);
#     - a ```sh block without a ```output block must print nothing.
#   Then every picture a page links (img/NAME) must exist in docs/img/, must be
#   rendered by one of the page's commands (out/NAME), and must agree with it up
#   to the noise tolerance below (a picture that is not a PNG, such as the SVG
#   heat map of `specnee spectrum --table --svg`, must be the same bytes).
#
# THE PICTURE TOLERANCE
#   Renders are deterministic, so normally out/NAME and docs/img/NAME are the same
#   bytes.  A change of the renderer that only re-draws some samples (a BVH
#   tie-break, another compiler's rounding) moves a picture by part of its noise.
#   For each picture the producing command is run once more with --seed 7: the
#   relMSE between that independent render and docs/img/NAME (8-bit values / 255,
#   relMSE = mean (a - b)^2 / (b^2 + 0.01)) is the picture's noise N.  The
#   picture passes when relMSE(out/NAME, docs/img/NAME) <= WALKTHROUGH_IMG_FRAC x N
#   (default 0.05: about 5% of its samples drawn afresh).  Anything larger (a
#   different picture, a black image, a missing light) fails.
#
# UPDATING THE NUMBERS (one command, after an intended change of the renderer)
#   sh tests/walkthrough.sh --update
#   runs everything as above, then rewrites in docs/ (the working tree):
#     - every ```output block with the output the commands print now ("..." lines
#       and lines with an in-line "..." that still match are kept);
#     - every number in the prose of the same "## " section that is a rounding of
#       a number that changed in an output block (0.057 for 5.739182e-02) to the
#       same rounding of the new number; the page's rule is that a number quoted
#       in the prose is copied from an output block of its section;
#     - docs/img/NAME with out/NAME for every picture the pages link.
#   It prints what it changed; review it with `git diff docs/` and commit.  A
#   second run without --update must then pass.
#
# USAGE
#   sh tests/walkthrough.sh [--update] [--committed]
#   WALKTHROUGH_DOCS="docs/WALKTHROUGH.md" ... checks one page (the default is both).
#   Prints "ok   walkthrough_<n> (file:line)" or "FAIL walkthrough_<n> (file:line): ..."
#   per command and per picture, ends with "walkthrough: N passed, N failed", exits 1
#   on failure.
set -u
cd "$(dirname "$0")/.." || exit 2
# the pages' commands run as a reader types them: not inside a parent make's
# jobserver (`make -j2 test` would make their own `make` print a warning)
unset MAKEFLAGS MFLAGS MAKELEVEL
root=$(pwd)
LIMIT=${WALKTHROUGH_TIMEOUT:-120}
FRAC=${WALKTHROUGH_IMG_FRAC:-0.05}
DOCS=${WALKTHROUGH_DOCS:-docs/WALKTHROUGH.md docs/EXERCISES.md}
scratch=$root/tests/tmp/walkthrough
clone=$scratch/clone
update=0
committed=0
for a in "$@"; do
    case $a in
        --update) update=1 ;;
        --committed) committed=1 ;;
        -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) echo "walkthrough.sh: unknown option '$a' (see --help)" >&2; exit 2 ;;
    esac
done

passed=0
failed=0
ok()   { passed=$((passed + 1)); echo "ok   walkthrough_$1"; }
fail() { failed=$((failed + 1)); echo "FAIL walkthrough_$1"; }
finish() { echo "walkthrough: $passed passed, $failed failed"; [ "$failed" -eq 0 ]; exit $?; }

if command -v bash > /dev/null 2>&1; then run_sh="bash -o pipefail -c"
else run_sh="sh -c"; echo "note: no bash: pipelines are checked by their last command only"; fi
if command -v timeout > /dev/null 2>&1; then have_timeout=1; else have_timeout=0; fi

# ---- 1. the fresh copy
rm -rf "$scratch"
mkdir -p "$scratch"
if [ "$committed" = 1 ]; then
    if ! git clone -q "$root" "$clone" > "$scratch/copy.log" 2>&1; then
        fail "copy: git clone failed"; cat "$scratch/copy.log"; finish
    fi
else
    mkdir -p "$clone"
    if ! git -C "$root" ls-files --cached --others --exclude-standard > "$scratch/files.all" 2> "$scratch/copy.log"; then
        # outside git (a source archive, or no git installed): every file
        # but what .gitignore names - build products, out/, tests/tmp/, build/
        (cd "$root" && find . -type f ! -name '*.o' ! -name 'a.out' ! -name '*.exe' \
            ! -path './specnee' ! -path './tests/runner' ! -path './fuzz/replay' \
            ! -path './tools/bench' ! -path './tools/bench_lights' ! -path './tools/bench_embree' \
            ! -path './tools/bench_count' ! -path './tools/bench_ab' \
            ! -path './tests/tmp/*' ! -path './out/*' ! -path './build/*' ! -path '*.dSYM/*' \
            ! -path './.git/*' | sed 's|^\./||' | LC_ALL=C sort) > "$scratch/files.all"
        echo "note: no git checkout here: copying the files .gitignore does not name"
    fi
    while IFS= read -r f; do [ -f "$f" ] && printf '%s\n' "$f"; done < "$scratch/files.all" > "$scratch/files"
    if ! tar -cf - -T "$scratch/files" | tar -xf - -C "$clone"; then fail "copy: tar failed"; finish; fi
fi
if [ -e "$clone/out" ] || [ -e "$clone/specnee" ]; then
    fail "copy: the fresh copy already has out/ or specnee (are they tracked?)"
fi

# ---- 2. the plan: commands and expected outputs, in document order
# plan.txt: "C<TAB>block<TAB>file<TAB>line<TAB>command" and "O<TAB>block<TAB>file<TAB>line"
# (line of the ```output fence); the expected lines of block B go to expect-B.txt.
awk -v dir="$scratch" '
    FNR == 1 { fence = ""; last_sh = 0 }
    /^```/ {
        if (fence != "") {                       # closing fence
            if (fence == "output") close(efile)
            fence = ""; next
        }
        tag = substr($0, 4); sub(/[ \t]+$/, "", tag)
        fence = (tag == "") ? "plain" : tag
        if (fence == "sh") { nb++; last_sh = nb }
        else if (fence == "output") {
            if (last_sh == 0) { printf "X\t0\t%s\t%d\tan output block that follows no sh block\n", FILENAME, FNR; fence = "ignored" ; next }
            efile = dir "/expect-" last_sh ".txt"; printf "" > efile
            printf "O\t%d\t%s\t%d\n", last_sh, FILENAME, FNR
            last_sh = 0
        } else last_sh = 0
        next
    }
    fence == "sh" && $0 !~ /^[ \t]*(#|$)/ { printf "C\t%d\t%s\t%d\t%s\n", nb, FILENAME, FNR, $0 }
    fence == "output" { print > efile }
' $DOCS > "$scratch/plan.txt"

# ---- 3. the output matcher (awk; also used by --update)
# match_output EXPECT ACTUAL [NEW]: exit 0 if ACTUAL matches EXPECT; with NEW,
# writes the updated expected block there and, to stdout, "old<TAB>new" for each
# line pair that changed.
cat > "$scratch/match.awk" << 'EOF'
function rtrim(s) { sub(/[ \t\r]+$/, "", s); return s }
function skipline(s) { return s ~ /^[ \t]*\.\.\.[ \t]*$/ }
function linematch(p, a,    n, parts, i, pos, k) {
    if (index(p, "...") == 0) return p == a
    n = split(p, parts, /\.\.\./)
    if (substr(a, 1, length(parts[1])) != parts[1]) return 0
    pos = length(parts[1]) + 1
    for (i = 2; i < n; i++) {
        k = index(substr(a, pos), parts[i]); if (k == 0) return 0
        pos += k - 1 + length(parts[i])
    }
    if (length(a) - pos + 1 < length(parts[n])) return 0
    return substr(a, length(a) - length(parts[n]) + 1) == parts[n]
}
BEGIN { n = 0; m = 0 }
# For --update: a line with an in-line "..." whose literal pieces no longer match
# because numbers changed.  Each piece becomes a regular expression in which every
# number matches any number; if the pieces still match in order, the new pattern
# keeps the "..." and takes the pieces' new text, and the changed numbers are
# printed as "old<TAB>new" lines.  Returns "" when even that fails.
function piece_re(s,    out, c, i, ch) {
    out = ""
    while (match(s, /[-+]?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?/)) {
        out = out esc(substr(s, 1, RSTART - 1)) "[-+]?[0-9]+(\\.[0-9]+)?([eE][-+]?[0-9]+)?"
        s = substr(s, RSTART + RLENGTH)
    }
    return out esc(s)
}
function esc(s,    out, i, ch) {
    out = ""
    for (i = 1; i <= length(s); i++) {
        ch = substr(s, i, 1)
        out = out (index("\\^$.[]|()*+?{}/", ch) ? "\\" ch : ch)
    }
    return out
}
function skel_update(p, a,    n, parts, i, rest, newp, got, re) {
    n = split(p, parts, /\.\.\./)
    rest = a; newp = ""
    for (i = 1; i <= n; i++) {
        re = piece_re(parts[i])
        if (i == 1) re = "^" re
        if (i == n) re = re "$"
        if (!match(rest, re)) return ""
        if (i == 1 && RSTART != 1) return ""
        got[i] = substr(rest, RSTART, RLENGTH)
        rest = substr(rest, RSTART + RLENGTH)
        newp = newp (i > 1 ? "..." : "") got[i]
    }
    for (i = 1; i <= n; i++) if (got[i] != parts[i]) printf "%s\t%s\n", parts[i], got[i]
    return newp
}
FILENAME == EXPECT { e[++n] = rtrim($0); next }
{ a[++m] = rtrim($0) }
END {
    BIG = 1000
    for (i = 0; i <= n; i++) for (j = 0; j <= m; j++) {
        if (i == 0 && j == 0) { c[0, 0] = 0; continue }
        best = 1e9
        if (i > 0 && skipline(e[i])) {
            if (c[i - 1, j] < best) { best = c[i - 1, j]; how[i, j] = "u" }
            if (j > 0 && c[i, j - 1] < best) { best = c[i, j - 1]; how[i, j] = "l" }
        } else {
            if (i > 0 && j > 0) { v = c[i - 1, j - 1] + (linematch(e[i], a[j]) ? 0 : 1); if (v < best) { best = v; how[i, j] = "d" } }
            if (i > 0 && c[i - 1, j] + BIG < best) { best = c[i - 1, j] + BIG; how[i, j] = "u" }   # expected line missing
            if (j > 0 && c[i, j - 1] + BIG < best) { best = c[i, j - 1] + BIG; how[i, j] = "l" }   # extra line printed
        }
        c[i, j] = best
    }
    if (NEW != "") {
        i = n; j = m; k = 0
        while (i > 0 || j > 0) {
            h = how[i, j]
            if (h == "d") {
                if (linematch(e[i], a[j])) out[++k] = e[i]
                else if (index(e[i], "...") && (sk = skel_update(e[i], a[j])) != "") out[++k] = sk
                else { out[++k] = a[j]; printf "%s\t%s\n", e[i], a[j] }
                i--; j-- }
            else if (h == "u") { if (skipline(e[i])) out[++k] = e[i]; i-- }
            else { if (!(i > 0 && skipline(e[i]))) out[++k] = a[j]; j-- }
        }
        for (; k > 0; k--) print out[k] > NEW
        close(NEW)
    }
    if (c[n, m] != 0) {
        # show the first difference for the log
        i = n; j = m
        while (i > 0 || j > 0) {
            h = how[i, j]
            if (h == "d") { if (!linematch(e[i], a[j])) { fe = e[i]; fa = a[j] } i--; j-- }
            else if (h == "u") { if (!skipline(e[i])) { fe = e[i]; fa = "(nothing)" } i-- }
            else { if (!(i > 0 && skipline(e[i]))) { fe = "(nothing)"; fa = a[j] } j-- }
        }
        printf "    expected: %s\n    printed:  %s\n", fe, fa > "/dev/stderr"
        exit 1
    }
}
EOF
match_output() {   # $1 expected file, $2 actual file, $3 optional new file
    awk -v EXPECT="$1" -v NEW="${3:-}" -f "$scratch/match.awk" "$1" "$2"
}

# ---- 4. run the commands, block by block
tab=$(printf '\t')
n=0
cur=0
check_block() {   # $1 block id, $2 where (file:line of its first command)
    [ "$1" -gt 0 ] || return 0
    act=$scratch/actual-$1.txt
    [ -f "$act" ] || : > "$act"
    if [ -f "$scratch/expect-$1.txt" ]; then
        if match_output "$scratch/expect-$1.txt" "$act" 2> "$scratch/why-$1.txt"; then
            ok "output_$1 ($2)"
        else
            fail "output_$1 ($2): the output differs from the page's \`\`\`output block"
            cat "$scratch/why-$1.txt"
        fi
    elif [ -s "$act" ]; then
        fail "output_$1 ($2): prints output the page does not show (add a \`\`\`output block)"
        head -n 3 "$act" | sed 's/^/    /'
    else
        ok "output_$1 ($2)"
    fi
}
grep "^X$tab" "$scratch/plan.txt" | while IFS="$tab" read -r _ _ file line why; do
    echo "FAIL walkthrough_plan ($file:$line): $why"
done
if grep -q "^X$tab" "$scratch/plan.txt"; then failed=$((failed + 1)); fi
grep "^C$tab" "$scratch/plan.txt" > "$scratch/commands.txt"
first_where=
while IFS="$tab" read -r _ block file line cmd; do
    if [ "$block" != "$cur" ]; then check_block "$cur" "$first_where"; cur=$block; first_where=$file:$line; fi
    n=$((n + 1))
    log=$scratch/cmd-$n.log
    lim=$LIMIT
    case $cmd in make|make\ *) lim=900 ;; esac
    if [ "$have_timeout" = 1 ]; then
        (cd "$clone" && timeout "$lim" $run_sh "$cmd") > "$log" 2>&1 < /dev/null
    else
        (cd "$clone" && $run_sh "$cmd") > "$log" 2>&1 < /dev/null
    fi
    rc=$?
    cat "$log" >> "$scratch/actual-$block.txt"
    printf '%s\n' "$cmd" >> "$scratch/commands-$block.txt"
    if [ "$rc" -ne 0 ]; then
        why="exit $rc"
        [ "$rc" -eq 124 ] && why="timed out after $lim s"
        fail "$n ($file:$line): $why: $cmd"
        tail -n 3 "$log" | sed 's/^/    /'
        continue
    fi
    out=$(printf '%s\n' "$cmd" | sed -n 's/.* -o \([^ ]*\).*/\1/p')
    if [ -n "$out" ] && [ ! -s "$clone/$out" ]; then
        fail "$n ($file:$line): wrote no $out: $cmd"
        continue
    fi
    ok "$n ($file:$line)"
done < "$scratch/commands.txt"
# the loop ran in this shell (redirection, not a pipe): counters are kept
check_block "$cur" "$first_where"
if [ "$n" -eq 0 ]; then fail "commands: no \`\`\`sh commands found in $DOCS"; fi
for f in "$scratch"/expect-*.txt; do
    [ -f "$f" ] || continue
    b=$(basename "$f" .txt); b=${b#expect-}
    grep -q "^C$tab$b$tab" "$scratch/plan.txt" || fail "output_$b: an output block whose sh block has no command"
done

# ---- 5. pictures
# png_relmse A B: relMSE of two 8-bit RGB PNGs as specnee writes them (stored
# deflate blocks, filter 0), or "size" / "format" when they cannot be compared.
png_relmse() {
    { od -An -v -tu1 "$1"; echo X; od -An -v -tu1 "$2"; } | awk '
        function decode(b, nb, pix,    p, len, type, i, w, h, z, nz, q, bl, L, fin, r, x, k) {
            p = 9; nz = 0; w = -1
            while (p + 8 <= nb) {
                len = b[p] * 16777216 + b[p + 1] * 65536 + b[p + 2] * 256 + b[p + 3]
                type = sprintf("%c%c%c%c", b[p + 4], b[p + 5], b[p + 6], b[p + 7])
                if (type == "IHDR") { w = b[p + 10] * 256 + b[p + 11]; h = b[p + 14] * 256 + b[p + 15]
                                      if (b[p + 16] != 8 || b[p + 17] != 2) return -1 }
                if (type == "IDAT") for (i = 0; i < len; i++) z[++nz] = b[p + 8 + i]
                p += 12 + len
            }
            if (w < 0) return -1
            q = 3; k = 0                                 # skip the zlib header
            do {
                fin = z[q] % 2; if (int(z[q] / 2) % 4 != 0) return -1
                L = z[q + 1] + 256 * z[q + 2]; q += 5
                for (i = 0; i < L; i++) raw[++k] = z[q + i]
                q += L
            } while (!fin && q <= nz)
            k = 0; r = 0
            for (i = 1; i <= h * (1 + 3 * w); i++) {
                if ((i - 1) % (1 + 3 * w) == 0) { if (raw[i] != 0) return -1; continue }
                pix[++k] = raw[i] / 255
            }
            W = w; H = h
            return k
        }
        $1 == "X" { second = 1; next }
        { for (i = 1; i <= NF; i++) if (second) B[++nB] = $i; else A[++nA] = $i }
        END {
            na = decode(A, nA, pa); wa = W; ha = H
            nb = decode(B, nB, pb)
            if (na < 0 || nb < 0) { print "format"; exit }
            if (na != nb || wa != W || ha != H) { print "size"; exit }
            for (i = 1; i <= na; i++) s += (pa[i] - pb[i]) ^ 2 / (pb[i] ^ 2 + 0.01)
            printf "%.6g\n", s / na
        }'
}
for doc in $DOCS; do
    for img in $(grep -o '](img/[^)]*)' "$doc" | sed 's/^](img\///; s/)$//' | sort -u); do
        id=img_$img
        if [ ! -f "docs/img/$img" ] && [ "$update" = 0 ]; then
            fail "$id: linked from $doc but docs/img/$img is missing"; continue
        fi
        if [ ! -f "$clone/out/$img" ]; then
            fail "$id: linked from $doc but no command of the pages renders out/$img"; continue
        fi
        if [ "$update" = 1 ]; then
            cmp -s "$clone/out/$img" "docs/img/$img" 2> /dev/null || { cp "$clone/out/$img" "docs/img/$img"; echo "updated docs/img/$img"; }
            ok "$id (updated)"; continue
        fi
        if cmp -s "$clone/out/$img" "docs/img/$img"; then ok "$id (identical)"; continue; fi
        case $img in
            *.png) ;;
            *) fail "$id: differs from docs/img/$img (not a render: it must be the same bytes; intended? sh tests/walkthrough.sh --update)"
               continue ;;
        esac
        # the noise: the same command with another seed
        cmd=$(grep -h -- "-o out/$img\( \|\$\)" "$scratch"/commands-*.txt | head -n 1)
        (cd "$clone" && $run_sh "$cmd --seed 7 -q -o out/noise-$img") > /dev/null 2>&1
        d=$(png_relmse "$clone/out/$img" "docs/img/$img")
        N=$(png_relmse "$clone/out/noise-$img" "docs/img/$img")
        case $d$N in *format*|*size*|"") fail "$id: cannot compare with docs/img/$img ($d $N)"; continue ;; esac
        if awk -v d="$d" -v N="$N" -v f="$FRAC" 'BEGIN { exit !(d <= f * N) }'; then
            ok "$id (relMSE $d <= $FRAC x noise $N)"
        else
            fail "$id: differs from docs/img/$img: relMSE $d > $FRAC x noise $N (intended? sh tests/walkthrough.sh --update)"
        fi
    done
done

# ---- 6. --update: rewrite the output blocks and the numbers quoted in the prose
if [ "$update" = 1 ]; then
    grep "^O$tab" "$scratch/plan.txt" | while IFS="$tab" read -r _ block file line; do
        act=$scratch/actual-$block.txt; [ -f "$act" ] || : > "$act"
        match_output "$scratch/expect-$block.txt" "$act" "$scratch/new-$block.txt" 2> /dev/null > "$scratch/pairs-$block.txt"
        printf '%s\t%s\t%s\n' "$file" "$line" "$block"
    done > "$scratch/blocks.txt"
    for doc in $DOCS; do
        awk -F '\t' -v doc="$doc" -v dir="$scratch" '
            # pass 1: which blocks belong to this doc, and the number changes per section
            FILENAME == dir "/blocks.txt" { if ($1 == doc) { blk[$2] = $3 } next }
            function nums(s, arr,    k) {
                k = 0
                while (match(s, /[-+]?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?/)) {
                    arr[++k] = substr(s, RSTART, RLENGTH); s = substr(s, RSTART + RLENGTH)
                }
                return k
            }
            FNR == 1 { pass++ }
            pass == 1 {                          # the doc, first reading: sections
                if ($0 ~ /^## /) sec++
                if ($0 ~ /^```output/ && (FNR in blk)) {
                    f = dir "/pairs-" blk[FNR] ".txt"
                    while ((getline pl < f) > 0) {
                        split(pl, two, "\t")
                        no = nums(two[1], on); nn = nums(two[2], nw)
                        if (no == nn) for (k = 1; k <= no; k++) if (on[k] != nw[k]) { np++; psec[np] = sec; pold[np] = on[k]; pnew[np] = nw[k] }
                    }
                    close(f)
                }
                next
            }
            # second reading: rewrite
            function sig(x,    t) { t = x; sub(/[eE].*/, "", t); gsub(/[^0-9]/, "", t); sub(/^0+/, "", t); return length(t) }
            function fmt_like(x, v,    d, t) {
                if (x ~ /[eE]/) { t = x; sub(/[eE].*/, "", t); d = (index(t, ".") ? length(t) - index(t, ".") : 0); return sprintf("%." d "e", v) }
                d = (index(x, ".") ? length(x) - index(x, ".") : 0); return sprintf("%." d "f", v)
            }
            {
                line = $0
                if (line ~ /^## /) sec2++
                if (skip) { if (line ~ /^```/) { skip = 0; while ((getline nl < nf) > 0) print nl; close(nf); print line } next }
                if (line ~ /^```/) { infence = !infence
                    if (infence && line ~ /^```output/ && (FNR in blk)) { nf = dir "/new-" blk[FNR] ".txt"; skip = 1; infence = 0 }
                    print line; next }
                if (!infence && np > 0) {
                    out = ""; rest = line
                    while (match(rest, /[0-9]+\.[0-9]+([eE][-+]?[0-9]+)?/)) {
                        tok = substr(rest, RSTART, RLENGTH); rep = tok
                        if (sig(tok) >= 2) for (k = 1; k <= np; k++)
                            if (psec[k] == sec2 && fmt_like(tok, pold[k] + 0) == tok) { rep = fmt_like(tok, pnew[k] + 0); break }
                        if (rep != tok) printf "%s: prose %s -> %s\n", doc, tok, rep > "/dev/stderr"
                        out = out substr(rest, 1, RSTART - 1) rep; rest = substr(rest, RSTART + RLENGTH)
                    }
                    line = out rest
                }
                print line
            }
        ' "$scratch/blocks.txt" "$doc" "$doc" > "$scratch/doc.new" 2> "$scratch/prose.log"
        cat "$scratch/prose.log"
        if ! cmp -s "$scratch/doc.new" "$doc"; then cp "$scratch/doc.new" "$doc"; echo "updated $doc"; fi
    done
    echo "walkthrough: review with git diff docs/, then run sh tests/walkthrough.sh again"
fi

finish
