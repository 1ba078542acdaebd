#!/bin/sh
# tools/mutants.sh - mutation testing: does the unit/statistical suite notice a bug?
# Run by `make mutants` (not part of `make test`: it rebuilds and reruns the suite
# once per mutant).
#
#   sh tools/mutants.sh [--full] [--keep] [--list FILE] [PATTERN ...]
#
# Each block of tests/mutants.txt (format in that file's header) is a one-line
# bug: a text that occurs in exactly one line of a source file and what replaces
# it.  The whole source tree is copied once to build/mutants/tree (the checkout is
# never touched) and tests/runner is built there; the unmutated suite must pass
# there first (else every mutant would look caught).  Then, one mutant at a time:
# the mutated line is written into the copy, tests/runner is rebuilt (make only
# recompiles that file), the suite is run, and the file is put back.  The suite is
# tests/runner: every unit and statistical test, no golden images (a golden image
# detects a change, not an error).  With a `= filter` line only the tests whose
# names contain one of the filter's words run (for speed); --full ignores the
# filters and runs the whole suite for every mutant.  A filter only selects tests
# of the suite a user runs (each test seeds its own random numbers, so a test
# fails alone exactly as it fails in the whole suite): a mutant caught with its
# filter is caught by `make test`; --full shows which other tests catch it.
#
# Each mutant is reported on one line:
#   CAUGHT      some test failed (its names follow), or the runner crashed or hung
#   SURVIVED    every test passed: the suite cannot see this bug
#   BROKEN      the mutant does not apply (its text is not found in exactly one
#               line of the file, the block is malformed) or does not compile
#   EQUIVALENT  marked `! equivalent` (not a bug, say why in a comment) and
#               survived, as it should; a marked mutant that is caught says so
# The last line is "mutants: N caught, N survived, N broken, N equivalent (T s)".
# The exit status is 1 if any mutant survived or is broken, 2 if nothing could be
# judged (no list, the copy does not build, the unmutated suite fails), else 0.
#
# --keep leaves the mutated copy build/mutants/tree in place afterwards;
# PATTERNs run only the mutants whose "FILE | description" contains one of them;
# --list FILE reads another list; MUTANT_TIMEOUT (seconds, default 600) bounds one
# run of the suite when timeout(1) exists, and a mutant's run is also bounded by
# 20 times what its tests took unmutated (at least 60 s): a mutant that makes the
# traversal loop for ever is caught in a minute, not in ten.  POSIX sh + awk +
# make; no python.
set -u
cd "$(dirname "$0")/.." || exit 2
list=tests/mutants.txt
full=0
keep=0
patterns=
while [ $# -gt 0 ]; do
    case $1 in
        --full) full=1 ;;
        --keep) keep=1 ;;
        --list) shift; list=${1:-} ;;
        -h|--help) sed -n '2,40p' "$0"; exit 0 ;;
        -*) echo "usage: sh tools/mutants.sh [--full] [--keep] [--list FILE] [PATTERN ...]" >&2; exit 2 ;;
        *) patterns="$patterns$1
" ;;
    esac
    shift
done
[ -f "$list" ] || { echo "$list: no such file" >&2; exit 2; }
: "${MAKE:=make}"
: "${MUTANT_TIMEOUT:=600}"
work=build/mutants
tree=$work/tree
blocks=$work/blocks
mkdir -p "$work" || exit 2
rm -rf "$blocks"
mkdir -p "$blocks" || exit 2

# ---- 1. split the list into one directory per mutant: file, desc, old, new, filter,
#         equiv, and err (why the block is malformed, if it is)
awk -v dir="$blocks" '
function flush() {
    if (n == 0) return
    d = dir "/" n
    printf "%s\n", file > (d "/file"); close(d "/file")
    printf "%s\n", desc > (d "/desc"); close(d "/desc")
    printf "%s\n", line0 > (d "/line"); close(d "/line")
    if (nold == 1) { printf "%s\n", old > (d "/old"); close(d "/old") }
    if (nnew == 1) { printf "%s\n", new > (d "/new"); close(d "/new") }
    printf "%s\n", filter > (d "/filter"); close(d "/filter")
    if (equiv) { printf "1\n" > (d "/equiv"); close(d "/equiv") }
    e = err
    if (e == "" && nold != 1) e = "needs exactly one - line (has " nold ")"
    if (e == "" && nnew != 1) e = "needs exactly one + line (has " nnew ")"
    if (e == "" && old == "") e = "empty - text"
    if (e != "") { printf "%s\n", e > (d "/err"); close(d "/err") }
    open = 0
}
function start() {
    flush(); n++; open = 1
    file = ""; desc = ""; old = ""; new = ""; filter = ""; err = ""
    nold = 0; nnew = 0; equiv = 0; line0 = NR
    system("mkdir -p \"" dir "/" n "\"")
}
/^#/ { next }
/^[ \t]*$/ { flush(); next }
/^@@ / {
    start()
    s = substr($0, 4)
    i = index(s, "|")
    if (i == 0) { file = s; err = "the @@ line needs FILE | description" }
    else { file = substr(s, 1, i - 1); desc = substr(s, i + 1) }
    gsub(/^[ \t]+|[ \t]+$/, "", file); gsub(/^[ \t]+|[ \t]+$/, "", desc)
    next
}
{
    if (!open) { start(); err = "line " NR ": a block must start with @@ FILE | description" }
    c = substr($0, 1, 1); t = substr($0, 2)
    if (substr(t, 1, 1) == " ") t = substr(t, 2)      # "- text": one space is the separator
    if (c == "-") { old = t; nold++ }
    else if (c == "+") { new = t; nnew++ }
    else if (c == "=") { filter = t }
    else if (c == "!") { if (t ~ /^equivalent/) equiv = 1; else err = "line " NR ": unknown ! marker" }
    else if (err == "") err = "line " NR ": unknown line"
}
END { flush(); print n + 0 > (dir "/count") }
' "$list" || exit 2
count=$(cat "$blocks/count")

# ---- 2. a copy of the source tree, with tests/runner built from the unmutated code
echo "mutants: copying the tree to $tree"
rm -rf "$tree"
mkdir -p "$tree" || exit 2
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git ls-files -co --exclude-standard | grep -v '^build/' > "$work/files"
else
    find . -type f ! -path './build/*' ! -path './.git/*' ! -name '*.o' ! -path './tests/runner' \
        ! -path './specnee' | sed 's|^\./||' > "$work/files"
fi
# cp -p keeps the modification times (make must see the copy as up to date)
while IFS= read -r f; do
    [ -f "$f" ] || continue
    if ! { mkdir -p "$tree/$(dirname "$f")" && cp -p "$f" "$tree/$f"; }; then
        echo "mutants: cannot copy $f" >&2; exit 2
    fi
done < "$work/files"
mkdir -p "$tree/tests/tmp"
if ! (cd "$tree" && $MAKE tests/runner) > "$work/build.log" 2>&1; then
    echo "mutants: the unmutated tree does not build (see $work/build.log)" >&2
    exit 2
fi
tmo=
command -v timeout >/dev/null 2>&1 && tmo="timeout $MUTANT_TIMEOUT"

# Is the mutant "FILE | description" $1 among those the PATTERNs select?
selected() {
    [ -z "$patterns" ] && return 0
    sel=1
    while IFS= read -r pat; do
        [ -n "$pat" ] || continue
        case $1 in *"$pat"*) sel=0 ;; esac
    done <<EOF
$patterns
EOF
    return $sel
}

# ---- 3. the unmutated suite must pass, or every mutant would look caught: the
#         union of the selected mutants' filters (the whole suite if one has none)
base_filter=
base_all=$full
i=0
while [ "$i" -lt "$count" ]; do
    i=$((i + 1))
    selected "$(cat "$blocks/$i/file") | $(cat "$blocks/$i/desc")" || continue
    [ -f "$blocks/$i/err" ] && continue
    f=$(cat "$blocks/$i/filter")
    if [ -z "$f" ]; then base_all=1; else base_filter="$base_filter $f"; fi
done
[ "$base_all" = 1 ] && base_filter=
# shellcheck disable=SC2086
if ! (cd "$tree" && SPECNEE_TEST_TMP=tests/tmp/mutant $tmo tests/runner $base_filter) > "$work/run-base.log" 2>&1; then
    echo "mutants: the UNMUTATED suite fails, so no mutant can be judged:" >&2
    grep '^FAIL' "$work/run-base.log" >&2
    exit 2
fi
echo "mutants: the unmutated suite passes ($(grep -c '^ok   ' "$work/run-base.log") tests)"

# The time limit of a mutant's run: 20 times the seconds its tests took in the
# unmutated run (the runner's "ok   NAME (T s)" lines whose NAME contains a word of
# the filter; every test without one), at least 60 s, at most MUTANT_TIMEOUT.
limit_of() {
    awk -v filter="$1" -v cap="$MUTANT_TIMEOUT" '
        BEGIN { n = split(filter, w, " ") }
        /^ok   / {
            name = $2; t = $3; gsub(/[()s]/, "", t)
            hit = n == 0
            for (k = 1; k <= n && !hit; k++) hit = index(name, w[k]) > 0
            if (hit) sum += t
        }
        END { lim = int(20 * sum) + 1; if (lim < 60) lim = 60; if (lim > cap) lim = cap; print lim }' \
        "$work/run-base.log"
}

# ---- 4. one mutant at a time
caught=0; survived=0; broken=0; equiv=0
t_start=$(date +%s)
i=0
while [ "$i" -lt "$count" ]; do
    i=$((i + 1))
    d=$blocks/$i
    file=$(cat "$d/file")
    desc=$(cat "$d/desc")
    name="$file | $desc"
    selected "$name" || continue
    is_equiv=0; [ -f "$d/equiv" ] && is_equiv=1
    filter=$(cat "$d/filter")
    [ "$full" = 1 ] && filter=
    if [ -f "$d/err" ]; then
        broken=$((broken + 1))
        printf 'BROKEN      %s  [%s:%s: %s]\n' "$name" "$list" "$(cat "$d/line")" "$(cat "$d/err")"
        continue
    fi
    case $file in /*|*..*) 
        broken=$((broken + 1))
        printf 'BROKEN      %s  [the file must be a path inside the tree]\n' "$name"; continue ;;
    esac
    if [ ! -f "$tree/$file" ]; then
        broken=$((broken + 1))
        printf 'BROKEN      %s  [no file %s]\n' "$name" "$file"
        continue
    fi
    # apply: the - text must occur in exactly one line; its first occurrence in
    # that line is replaced by the + text (index/substr: no regular expressions)
    cp -p "$tree/$file" "$work/orig"
    awk -v oldf="$d/old" -v newf="$d/new" -v out="$work/mutated" '
        BEGIN { getline old < oldf; getline new < newf; hits = 0 }
        {
            k = index($0, old)
            if (k > 0) { hits++; $0 = substr($0, 1, k - 1) new substr($0, k + length(old)) }
            print > out
        }
        END { print hits; }' "$work/orig" > "$work/hits"
    hits=$(cat "$work/hits")
    if [ "$hits" != 1 ]; then
        broken=$((broken + 1))
        printf 'BROKEN      %s  [the - text is in %s lines of %s, not 1]\n' "$name" "$hits" "$file"
        continue
    fi
    cat "$work/mutated" > "$tree/$file"
    t0=$(date +%s)
    if ! (cd "$tree" && $MAKE tests/runner) > "$work/build-$i.log" 2>&1; then
        cat "$work/orig" > "$tree/$file"
        broken=$((broken + 1))
        printf 'BROKEN      %s  [does not compile: %s]\n' "$name" \
            "$(grep -m1 -i 'error' "$work/build-$i.log" | cut -c1-100)"
        continue
    fi
    # the filter is a list of words on purpose: $filter is not quoted
    # shellcheck disable=SC2086
    [ -n "$tmo" ] && tmo="timeout $(limit_of "$filter")"
    (cd "$tree" && SPECNEE_TEST_TMP=tests/tmp/mutant $tmo tests/runner $filter) > "$work/run-$i.log" 2>&1
    rc=$?
    cat "$work/orig" > "$tree/$file"          # newer mtime: the next build recompiles it
    t1=$(date +%s)
    fails=$(sed -n 's/^FAIL \([^:]*\):.*/\1/p' "$work/run-$i.log" | tr '\n' ' ' | sed 's/ $//')
    summary=$(grep -c '^ok   ' "$work/run-$i.log")
    if [ "$rc" -ne 0 ]; then
        why=$fails
        [ -z "$why" ] && why="runner exit $rc (crash or timeout)"
        caught=$((caught + 1))
        tag=CAUGHT
        [ "$is_equiv" = 1 ] && why="$why; marked equivalent but caught"
        printf '%-11s %s  [%s] (%ss)\n' "$tag" "$name" "$why" $((t1 - t0))
    elif [ "$summary" -eq 0 ]; then
        broken=$((broken + 1))
        printf 'BROKEN      %s  [the filter "%s" runs no test]\n' "$name" "$filter"
    elif [ "$is_equiv" = 1 ]; then
        equiv=$((equiv + 1))
        printf 'EQUIVALENT  %s  [survived %s tests, as documented] (%ss)\n' "$name" "$summary" $((t1 - t0))
    else
        survived=$((survived + 1))
        printf 'SURVIVED    %s  [%s tests passed%s] (%ss)\n' "$name" "$summary" \
            "${filter:+, filter: $filter}" $((t1 - t0))
    fi
done
t_end=$(date +%s)
[ "$keep" = 1 ] || rm -rf "$tree"
echo "mutants: $caught caught, $survived survived, $broken broken, $equiv equivalent ($((t_end - t_start)) s)"
[ "$survived" -eq 0 ] && [ "$broken" -eq 0 ]
