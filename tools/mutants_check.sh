#!/bin/sh
# tools/mutants_check.sh - does every block of tests/mutants.txt still apply?
# A block applies when its "- text" occurs in exactly one line of its FILE (the
# format is in tests/mutants.txt's header).  This is the cheap half of `make
# mutants` (no build, no run): tests/run.sh calls it so that a block whose line
# moved to another file, or was rewritten, fails `make test` at once instead of
# turning up BROKEN in the next full mutation run.
#   sh tools/mutants_check.sh [LIST]   prints one line per block that does not
#   apply and ends with "mutants_check: N apply, N do not"; exit 1 if any does not.
set -u
cd "$(dirname "$0")/.." || exit 2
list=${1:-tests/mutants.txt}
[ -f "$list" ] || { echo "$list: no such file" >&2; exit 2; }
awk '
function check() {
    if (file == "") return
    if (old == "") { bad++; printf "%s:%d: %s | %s: no - line\n", FILENAME, line0, file, desc; file = ""; return }
    n = 0
    while ((getline l < file) > 0) if (index(l, old) > 0) n++
    close(file)
    if (n == 1) good++
    else { bad++; printf "%s:%d: %s | %s: the - text occurs in %d lines of %s\n", FILENAME, line0, file, desc, n, file }
    file = ""
}
/^#/ { next }
/^[ \t]*$/ { check(); next }
/^@@ / {
    check()
    s = substr($0, 4); i = index(s, "|")
    file = substr(s, 1, i - 1); desc = substr(s, i + 1)
    gsub(/^[ \t]+|[ \t]+$/, "", file); gsub(/^[ \t]+|[ \t]+$/, "", desc)
    old = ""; line0 = FNR
    next
}
/^- / { old = substr($0, 3); next }
/^-$/ { old = ""; next }
END { check(); printf "mutants_check: %d apply, %d do not\n", good, bad; exit bad > 0 }
' "$list"
