#!/bin/sh
# tests/docs_history.sh - the code and the docs describe the program as it is.
# Run by tests/run.sh (make test); ends with "docs_history: N passed, N failed".
#
#   sh tests/docs_history.sh [FILE ...]     (default: every file listed below)
#
# History lives in git log.  A comment or a page that says which issue asked for
# something, which session measured it, or that an image is the same "as before"
# describes a change, not the code; a reader cannot check it against the files in
# front of them.  This script reports every line of the files it reads that holds
# one of these words (case-insensitive):
#
#   session    "issue" followed by a number ("issue 18", "issue #17")
#   "as before"    "identical to before"    "last round"
#
# Files read: README.md, Makefile, docs/*.md, tests/golden/README.md, *.c, *.h,
# tests/*.c, tests/*.h, tests/*.sh, tests/*.py, tests/mutants.txt, tools/*.c,
# tools/*.sh, fuzz/*.c, fuzz/*.sh - but not this script, which names the words.
# A design note that is worth keeping after a change goes to docs/ in the present
# tense: what the code does, what was measured, what was tried and why it was not
# kept (docs/bvh.md is an example).  Cite docs as "THEORY §N" or "docs/FILE.md".
#
# tests/history-allow.txt lists the files that still hold such words and are not
# cleaned yet, one path a line ('#' starts a comment).  Their lines are not
# reported, but a listed file that holds none of the words any more, or that does
# not exist, fails: delete its line, so the list only shrinks.
#
# Self-test first: a planted file with each word must be reported, a clean one and
# an allowed one must pass, and a clean file left on the allow-list must fail.
set -u
cd "$(dirname "$0")/.." || exit 2
tmp=${SPECNEE_TEST_TMP:-tests/tmp}/docs-history
mkdir -p "$tmp"
passed=0
failed=0
ok()   { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL $1"; }

WORDS='session|issue *#?[0-9]|as before|identical to before|last round'

# check ALLOWFILE FILE...: one FAIL line per file that holds a word (its first
# three hits) and is not allowed, and per allowed file that is clean or missing;
# one ok per file that passes.
check() {
    allow=$1; shift
    for f in "$@"; do
        listed=0
        if grep -v '^[[:space:]]*#' "$allow" | grep -qxF "$f"; then listed=1; fi
        if grep -n -i -E "$WORDS" "$f" > "$tmp/hits.txt" 2>/dev/null; then
            if [ $listed = 1 ]; then ok
            else fail "docs_history: $f: $(head -n 3 "$tmp/hits.txt" | tr '\n' ' ')"; fi
        elif [ $listed = 1 ]; then
            fail "docs_history: $f is on $allow but holds none of the words: delete its line"
        else ok; fi
    done
    grep -v '^[[:space:]]*#' "$allow" | grep -v '^[[:space:]]*$' | while IFS= read -r f; do
        [ -f "$f" ] || echo "FAIL docs_history: $allow lists $f, which does not exist: delete its line"
    done > "$tmp/missing.txt"
    if [ -s "$tmp/missing.txt" ]; then
        cat "$tmp/missing.txt"
        failed=$((failed + $(wc -l < "$tmp/missing.txt")))
    fi
}

# ---- self-test
mkdir -p "$tmp/plant"
: > "$tmp/plant/allow.txt"
n=0
for w in "measured in session 7" "added for Issue 18" "asked by issue #17" \
         "the image is bit-identical to before" "renders as before" "since the last round"; do
    n=$((n + 1))
    printf 'int x;  /* clean line */\n/* %s */\n' "$w" > "$tmp/plant/stale$n.c"
done
printf '/* the issue of a number is not history; before, the loop ran once */\n' > "$tmp/plant/clean.c"
printf '/* measured in session 7 */\n' > "$tmp/plant/allowed.c"
printf '/* nothing to report */\n' > "$tmp/plant/cleaned.c"
printf '# not cleaned yet\n%s\n%s\n%s\n' "$tmp/plant/allowed.c" "$tmp/plant/cleaned.c" \
    "$tmp/plant/gone.c" > "$tmp/plant/allow.txt"
p0=$passed; f0=$failed
check "$tmp/plant/allow.txt" "$tmp"/plant/stale*.c "$tmp/plant/clean.c" "$tmp/plant/allowed.c" \
    "$tmp/plant/cleaned.c" > "$tmp/self.out"
passed=$p0; failed=$f0
n_stale=$(grep -c '^FAIL docs_history: .*/stale[0-9]\.c:' "$tmp/self.out")
n_list=$(grep -c '^FAIL docs_history: .*\(cleaned\.c is on\|gone\.c, which does not exist\)' "$tmp/self.out")
n_fail=$(grep -c '^FAIL' "$tmp/self.out")
if [ "$n_stale" -eq "$n" ] && [ "$n_list" -eq 2 ] && [ "$n_fail" -eq $((n + 2)) ]; then ok
else
    fail "docs_history_selftest: $n_stale of the $n planted words, $n_list of the 2 stale allow-list lines reported ($n_fail FAIL lines)"
    cat "$tmp/self.out"
fi

# ---- the repository
if [ $# -eq 0 ]; then
    set -- README.md Makefile docs/*.md tests/golden/README.md *.c *.h tests/*.c tests/*.h \
        tests/*.sh tests/*.py tests/mutants.txt tools/*.c tools/*.sh fuzz/*.c fuzz/*.sh
fi
files=""
for f in "$@"; do
    [ "$f" = tests/docs_history.sh ] || [ ! -f "$f" ] || files="$files $f"
done
# shellcheck disable=SC2086
check tests/history-allow.txt $files
echo "docs_history: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
