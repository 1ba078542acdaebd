#!/bin/sh
# tests/walkthrough.sh - runs every command of docs/WALKTHROUGH.md and
# docs/EXERCISES.md, so that the documentation cannot rot.
#
# CONVENTION (stated in both documents)
#   Only fenced blocks opened with ```sh are run.  Each non-empty line in such a
#   block is one command (pipes and redirections allowed), except lines that
#   start with '#'.  Blocks that only work after the reader has edited something
#   are fenced ```text and are not run.
#
# HOW
#   Commands run one by one, in order (later ones may read what earlier ones wrote
#   to out/), with `sh -c`, under a time limit of WALKTHROUGH_TIMEOUT seconds
#   (default 60), in a scratch directory tests/tmp/walkthrough/ that holds a fresh,
#   empty out/ and links to the repository's scenes/, tests/ and docs/ and to the
#   binary (./specnee, or SPECNEE_BIN), so a user's own out/ is never touched.
#   `make ...` lines run in the repository root (make builds there).
#   A command passes when it exits 0 and, if it has "-o FILE", wrote a non-empty
#   FILE.
#   Afterwards, every image a document links (img/...) must exist, and every
#   out/walkthrough-*.png the commands rendered is compared byte for byte with
#   docs/img/: a difference is reported as a "note" (the pictures are
#   illustrations; an intended change of the renderer moves them), and
#   --update-images copies the new renders into docs/img/.
#
# USAGE
#   sh tests/walkthrough.sh [--update-images]
# Prints "ok   walkthrough_<n> (file:line)" or "FAIL walkthrough_<n> (file:line): ..."
# per command and ends with "walkthrough: N passed, N failed"; exits 1 on failure.
set -u
cd "$(dirname "$0")/.." || exit 2
root=$(pwd)
BIN=${SPECNEE_BIN:-./specnee}
LIMIT=${WALKTHROUGH_TIMEOUT:-60}
DOCS=${WALKTHROUGH_DOCS:-docs/WALKTHROUGH.md docs/EXERCISES.md}   # (override: to test this script)
scratch=tests/tmp/walkthrough
update=0
for a in "$@"; do
    case $a in
        --update-images) update=1 ;;
        -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) echo "walkthrough.sh: unknown option '$a' (see --help)" >&2; exit 2 ;;
    esac
done

passed=0
failed=0
ok()   { passed=$((passed + 1)); echo "ok   walkthrough_$1"; }
fail() { failed=$((failed + 1)); echo "FAIL walkthrough_$1"; }

case $BIN in /*) bin_abs=$BIN ;; *) bin_abs=$root/$BIN ;; esac
if [ ! -x "$bin_abs" ]; then
    echo "FAIL walkthrough_binary: no executable $BIN (run make)"
    echo "walkthrough: 0 passed, 1 failed"
    exit 1
fi

# The scratch directory: links to the repository, an empty out/.
rm -rf "$scratch"
mkdir -p "$scratch/out"
ln -s "$bin_abs" "$scratch/specnee"
for d in scenes tests docs; do ln -s "$root/$d" "$scratch/$d"; done

# "file<TAB>line<TAB>command" for every runnable line, in document order.
awk '
    FNR == 1 { in_sh = 0 }
    /^```/ { if (in_sh) { in_sh = 0; next } if ($0 ~ /^```sh[ \t]*$/) { in_sh = 1; next } }
    in_sh && $0 !~ /^[ \t]*(#|$)/ { printf "%s\t%d\t%s\n", FILENAME, FNR, $0 }
' $DOCS > "$scratch/commands.txt"

if command -v timeout > /dev/null 2>&1; then limit="timeout $LIMIT"; else limit=""; fi

n=0
while IFS="$(printf '\t')" read -r file line cmd; do
    n=$((n + 1))
    where="$file:$line"
    log=$root/$scratch/cmd-$n.log
    case $cmd in
        make|make\ *) dir=$root ;;
        *) dir=$root/$scratch ;;
    esac
    (cd "$dir" && $limit sh -c "$cmd") > "$log" 2>&1 < /dev/null
    rc=$?
    if [ "$rc" -ne 0 ]; then
        why="exit $rc"
        [ "$rc" -eq 124 ] && why="timed out after ${LIMIT} s"
        fail "$n ($where): $why: $cmd"
        tail -n 3 "$log" | sed 's/^/    /'
        continue
    fi
    out=$(echo "$cmd" | sed -n 's/.* -o \([^ ]*\).*/\1/p')
    if [ -n "$out" ] && [ ! -s "$dir/$out" ]; then
        fail "$n ($where): wrote no $out: $cmd"
        continue
    fi
    ok "$n ($where)"
done < "$scratch/commands.txt"

if [ "$n" -eq 0 ]; then fail "commands: no \`\`\`sh commands found in $DOCS"; fi

# Pictures: what the commands render now against what the documents show.
for png in "$scratch"/out/walkthrough-*.png; do
    [ -f "$png" ] || continue
    name=$(basename "$png")
    if [ "$update" = 1 ]; then
        cp "$png" "docs/img/$name" && echo "updated docs/img/$name"
    elif [ -f "docs/img/$name" ] && ! cmp -s "$png" "docs/img/$name"; then
        echo "note: docs/img/$name differs from what its command renders now (sh tests/walkthrough.sh --update-images)"
    fi
done

# Every linked image must exist.
for doc in $DOCS; do
    for img in $(grep -o '](img/[^)]*)' "$doc" | sed 's/^](//; s/)$//' | sort -u); do
        if [ -f "docs/$img" ]; then ok "img_$(basename "$img")"
        else fail "img_$(basename "$img"): linked from $doc but missing (sh tests/walkthrough.sh --update-images)"
        fi
    done
done

echo "walkthrough: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
