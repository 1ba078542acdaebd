#!/bin/sh
# tests/docs_defaults.sh - the docs cannot call something else the default.
# Run by tests/run.sh (make test); ends with "docs_defaults: N passed, N failed".
#
#   sh tests/docs_defaults.sh [FILE ...]     (default: README.md docs/*.md)
#
# The binary says what it does by default: `specnee --print-defaults` prints one
# "name value" line per render setting, read from render_options_default (and
# `specnee FLAGS --print-defaults` prints what FLAGS set instead).  This script
# finds every place where a doc calls a setting "the default" and asks the binary:
#
#   `--wavelengths uniform` (default)     a command-line fragment followed by
#   (`--spd-metric unit`, the default:     "(default", ", the default", "is the
#   `--fluor-lanes keep` (the defaults)    default", ": the default" ...: those
#                                          flags must leave --print-defaults as it is
#   | `spatial` (default) |                a bare value: some option that takes it
#   `sobol` is the default                 (--lights spatial, ...) must have it as
#   the sampler is the default `sobol`     its default; a word no option takes is
#                                          not a setting of specnee (ignored)
#   (`--mix-weight m`, default 0.5)        the value after "default" replaces the
#                                          placeholder: --mix-weight 0.5
#   | factor | default | ...               a table column headed "default": the
#   | sampler | `sobol`: ... |             first `...` of each row's cell, as above
#
# "pbrt-v4's default", "the thesis' default" are someone else's and not read; so
# are fenced code blocks.  Prose without a `...` ("by default p is uniform") is not
# read either: write a default as one of the forms above and this test guards it.
#
# Self-test first: planted stale claims, one per form, must each be reported, and
# true ones must pass; then the docs.  SPECNEE_BIN names the binary (./specnee).
set -u
cd "$(dirname "$0")/.." || exit 2
bin=${SPECNEE_BIN:-./specnee}
tmp=${SPECNEE_TEST_TMP:-tests/tmp}/docs-defaults
mkdir -p "$tmp"
passed=0
failed=0
ok()   { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL $1"; }

if ! "$bin" --print-defaults > "$tmp/defaults.txt" 2> "$tmp/err.txt" || [ ! -s "$tmp/defaults.txt" ]; then
    echo "FAIL docs_defaults: $bin --print-defaults failed"; cat "$tmp/err.txt"
    echo "docs_defaults: 0 passed, 1 failed"; exit 1
fi
# the options that take a word as their value (not on/off switches, not numbers)
word_options=$(awk '$2 !~ /^(on|off|[-0-9.]+)$/ { print $1 }' "$tmp/defaults.txt")

# Every claim of FILEs as "file:line<TAB>fragment": a command-line fragment
# ("--flag value ...") or "=value" for a bare value.
claims() {
    awk '
    function trim(s) { gsub(/^[ \t]+|[ \t]+$/, "", s); return s }
    function emit(span) { printf "%s:%d\t%s\n", FILENAME, FNR, span }
    # the span `s` seen in the text: a fragment of flags, or a bare value
    function claim(s, value,   n, t) {
        if (s ~ /^--/) {
            if (value != "") {      # `--flag placeholder`, default VALUE
                n = split(s, t, " ")
                if (n != 2) return
                s = t[1] " " value
            }
            emit(s)
        } else if (value == "" && s ~ /^[a-z][a-z0-9-]*$/) emit("=" s)
    }
    FNR == 1 { fence = 0; col = 0 }
    /^[ \t]*```/ { fence = !fence; col = 0; next }
    fence { next }
    # a table whose header has a cell "default": remember the column
    /^[ \t]*\|/ {
        n = split($0, cell, "|")
        if (col == 0) {
            for (i = 2; i < n; i++) if (tolower(trim(cell[i])) == "default") col = i
        } else if ($0 !~ /^[ \t]*\|[- :|]*$/ && match(cell[col], /`[^`]+`/)) {
            claim(substr(cell[col], RSTART + 1, RLENGTH - 2), "")
        }
    }
    !/^[ \t]*\|/ { col = 0 }
    {
        rest = $0; before = ""
        while (match(rest, /`[^`]+`/)) {
            span = substr(rest, RSTART + 1, RLENGTH - 2)
            before = before substr(rest, 1, RSTART - 1)
            rest = substr(rest, RSTART + RLENGTH)
            after = tolower(rest)
            # "default `value`", not "pbrt-v4'"'"'s default `value`"
            if (tolower(before) ~ /(^|[^a-z])default $/ && before !~ /'"'"'s? default $/) claim(span, "")
            # `span` (default ..., `span`, the default, `span` is the default
            if (match(after, /^[ ]*(\(|,|:)?[ ]*((is|are)[ ]+)?(the[ ]+)?defaults?([^a-z]|$)/)) {
                tail = substr(rest, RLENGTH + 1)
                if (substr(after, RLENGTH, 1) ~ /[^a-z]/) tail = substr(rest, RLENGTH)
                if (match(tail, /^[ ]*:?[ ]*[0-9][0-9.]*/)) {
                    v = substr(tail, RSTART, RLENGTH); gsub(/[ :]/, "", v); claim(span, v)
                } else claim(span, "")
            }
            before = before "`" span "`"
        }
    }' "$@"
}

# Check the claims of FILEs; report each stale one.  Prints nothing else.
check() {
    claims "$@" > "$tmp/claims.txt"
    while IFS='	' read -r where frag; do
        case $frag in
        =*)
            v=${frag#=}; takers=""; agrees=0
            for o in $word_options; do
                if "$bin" "--$o" "$v" --print-defaults > "$tmp/got.txt" 2> /dev/null; then
                    takers="$takers --$o $v (default $(sed -n "s/^$o //p" "$tmp/defaults.txt"));"
                    cmp -s "$tmp/got.txt" "$tmp/defaults.txt" && agrees=1
                fi
            done
            if [ -z "$takers" ] || [ $agrees = 1 ]; then ok
            else fail "$where: calls \`$v\` the default, but it is not:$takers specnee --print-defaults"; fi ;;
        *)
            set -f; "$bin" $frag --print-defaults > "$tmp/got.txt" 2> /dev/null; rc=$?; set +f
            if [ $rc -ne 0 ]; then
                fail "$where: \`$frag\` (called the default) is not a valid specnee command line"
            elif cmp -s "$tmp/got.txt" "$tmp/defaults.txt"; then ok
            else
                d=$(awk 'NR == FNR { def[$1] = $2; next } def[$1] != $2 { printf " %s is %s,", $1, def[$1] }' \
                        "$tmp/defaults.txt" "$tmp/got.txt")
                fail "$where: calls \`$frag\` the default, but by default$d says specnee --print-defaults"
            fi ;;
        esac
    done < "$tmp/claims.txt"
}

# ---- self-test: every form of a stale claim is reported, true ones are not
cat > "$tmp/stale.md" <<'EOF'
- `--wavelengths uniform` (default): plain HWSS
| `spatial` (default) | s_e(v) |
`terminate` is the default here.
(`--mix-weight m`, default 0.3)
the sampler is the default `independent`.
(`--spd-metric power`, the default: radiant power)
| factor | default | thesis |
|---|---|---|
| wavelength pdf | `uniform` HWSS | `uniform` |
| fluorescence | `--fluor-lanes terminate --fluor-li a`: ... | |
EOF
cat > "$tmp/true.md" <<'EOF'
- `--wavelengths mixture` (default): importance with a share of visible
| `spectral-tree` (default) | the light tree |
`sobol` is the default; `zsobol` (pbrt-v4's default) is not.
(`--mix-weight m`, default 0.5), (`--spd-metric unit`, the default: radiance)
the thesis' default `spatial`; the default `mis` of rough glass
`gaussian` (default) is a filter of the scene file, no option of specnee.
```
./specnee --lights spatial   # (default) in a code block is not read
```
| factor | default | thesis |
|---|---|---|
| wavelength pdf | `mixture`: ... | `uniform` |
| fluorescence | `--fluor-lanes keep --fluor-li power`: ... | `terminate` |
EOF
p0=$passed; f0=$failed
check "$tmp/stale.md" > "$tmp/stale.out"
n_stale=$(grep -c '^FAIL' "$tmp/stale.out")
passed=$p0; failed=$f0
if [ "$n_stale" -eq 8 ]; then ok
else fail "docs_defaults_selftest: $n_stale of the 8 planted stale claims reported"; cat "$tmp/stale.out"; fi
check "$tmp/true.md" > "$tmp/true.out"
n_true=$(grep -c '^FAIL' "$tmp/true.out")
passed=$p0; failed=$f0
n_read=$(wc -l < "$tmp/claims.txt")
if [ "$n_true" -eq 0 ] && [ "$n_read" -eq 9 ]; then ok
else fail "docs_defaults_selftest: true claims: $n_true reported, $n_read read (9 expected)"; cat "$tmp/true.out"; fi

# ---- the docs
if [ $# -eq 0 ]; then set -- README.md docs/*.md; fi
check "$@"
echo "docs_defaults: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
