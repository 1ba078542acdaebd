#!/bin/sh
# tools/callgraph.sh - the include/call graph among the rooms (.c files) of specnee,
# and the check that the library rooms call each other without a cycle.
#
#   sh tools/callgraph.sh [--allow A.c:B.c ...] [FILE.c ...]
#
# WHAT IT DOES
#   1. Every function defined at file scope and not static in one of the files
#      (default: every *.c of the repository's root) is mapped to its file.
#   2. Each file's code (comments, string and character literals removed) is scanned
#      for calls NAME( of a function defined in another file; a file's own
#      functions, static ones included, are never counted as calls elsewhere.
#   3. It prints one line per edge, "FROM -> TO: the functions FROM calls", and one
#      per local include, "FROM includes HEADER".
#   4. The library rooms are every file except the command rooms (specnee.c, main's
#      command line, and cmd_*.c, the subcommands).  A library room that calls a
#      command room is reported, and so is every cycle among the library rooms: a
#      strongly connected component of two or more rooms (the rooms of one
#      component reach each other through calls).
#   --allow A.c:B.c  tolerates the cycle whose component is exactly {A.c, B.c}
#                    (reported as "allowed"); an allowed pair that is not a cycle
#                    gets a note.  Repeatable.
#   The last line is "callgraph: N rooms, N edges, N cycles among library rooms
#   (N allowed), N calls from library to command rooms"; exit 1 when a cycle that
#   is not allowed or a call into a command room exists, 2 on bad usage.
#
# LIMITS (a teaching tool, POSIX sh and awk only): calls through function pointers
# and through macros or static inline functions of the headers are not seen; a
# member call p->f( or s.f( is skipped.  tests/run.sh runs it
# (repo_no_library_cycle).
set -u
cd "$(dirname "$0")/.." || exit 2
allow=""
while [ $# -gt 0 ]; do
    case "$1" in
        --allow)
            [ $# -ge 2 ] || { echo "callgraph: --allow needs A.c:B.c" >&2; exit 2; }
            case "$2" in
                *.c:*.c) allow="$allow $2" ;;
                *) echo "callgraph: --allow needs A.c:B.c, not '$2'" >&2; exit 2 ;;
            esac
            shift 2 ;;
        -h|--help) sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "callgraph: unknown option '$1'" >&2; exit 2 ;;
        *) break ;;
    esac
done
if [ $# -eq 0 ]; then set -- *.c; fi
for f in "$@"; do [ -f "$f" ] || { echo "callgraph: $f: no such file" >&2; exit 2; }; done

# Pass 1 maps the definitions, pass 2 finds the calls.  Output records:
#   E FROM TO NAME       FROM calls TO's function NAME
#   I FROM HEADER        FROM includes "HEADER"
#   N FILE               a room
edges=$(awk '
# The code of a line: comments (also across lines), string and character literals
# blanked.  incomment carries a /* ... */ over line ends.
function strip(line,    out, i, n, c, c2, q, j) {
    out = ""; n = length(line); i = 1
    while (i <= n) {
        if (incomment) {
            j = index(substr(line, i), "*/")
            if (j == 0) return out
            i += j + 1; incomment = 0; out = out " "; continue
        }
        c = substr(line, i, 1); c2 = substr(line, i, 2)
        if (c2 == "/*") { incomment = 1; i += 2; continue }
        if (c2 == "//") return out
        if (c == "\"" || c == "\047") {
            q = c; i++
            while (i <= n) {
                c = substr(line, i, 1)
                if (c == "\\") { i += 2; continue }
                if (c == q) break
                i++
            }
            i++; out = out " "; continue
        }
        out = out c; i++
    }
    return out
}
# The first NAME( of s ("" if none).
function first_call(s) {
    if (!match(s, /[A-Za-z_][A-Za-z0-9_]*[ \t]*\(/)) return ""
    s = substr(s, RSTART, RLENGTH); sub(/[ \t]*\($/, "", s)
    return s
}
FNR == 1 { incomment = 0; depth = 0; pend = ""; inmacro = 0; if (pass == 1) print "N", FILENAME }
{
    raw = $0
    s = strip(raw)
    if (inmacro || s ~ /^[ \t]*#/) {              # preprocessor lines (and their continuations)
        inmacro = (raw ~ /\\$/)
        if (pass == 1 && match(s, /^[ \t]*#[ \t]*include[ \t]*/) && match(raw, /"[^"]*"/))
            print "I", FILENAME, substr(raw, RSTART + 1, RLENGTH - 2)
        if (pass == 1) next
    } else if (pass == 1) {
        # a definition: a line at file scope that starts with a type and names a
        # function, whose next "{" comes before any ";"
        if (depth == 0 && pend == "" && s ~ /^[A-Za-z_]/ && s !~ /^(typedef|struct|union|enum|extern)[ \t]/) {
            pend = first_call(s)
            pend_static = (s ~ /^static[ \t]/ || s ~ /^inline[ \t]/)
        }
        if (pend != "") {
            b = index(s, "{"); e = index(s, ";")
            if (b > 0 && (e == 0 || b < e)) {
                own[FILENAME, pend] = 1
                if (!pend_static) def[pend] = FILENAME
                pend = ""
            } else if (e > 0) pend = ""
        }
        t = s; depth += gsub(/\{/, "", t); t = s; depth -= gsub(/\}/, "", t)
        next
    }
    # pass 2: the calls
    while (match(s, /[A-Za-z_][A-Za-z0-9_]*[ \t]*\(/)) {
        name = substr(s, RSTART, RLENGTH); sub(/[ \t]*\($/, "", name)
        before = RSTART > 1 ? substr(s, RSTART - 1, 1) : ""
        s = substr(s, RSTART + RLENGTH)
        if (before == "." || before == ">") continue
        if ((name in def) && def[name] != FILENAME && !((FILENAME, name) in own))
            print "E", FILENAME, def[name], name
    }
}
' pass=1 "$@" pass=2 "$@" | sort -u)

printf '%s\n' "$edges" | awk -v allow="$allow" '
function is_command(f) { sub(/.*\//, "", f); return f == "specnee.c" || f ~ /^cmd_.*\.c$/ }
$1 == "N" { node[++n] = $2; next }
$1 == "I" { inc[++ni] = $2 " includes " $3; next }
$1 == "E" {
    key = $2 " -> " $3
    if (!(key in fns)) { order[++ne] = key; from[ne] = $2; to[ne] = $3; fns[key] = $4 }
    else fns[key] = fns[key] " " $4
    next
}
END {
    for (i = 1; i <= ne; i++) print order[i] ": " fns[order[i]]
    for (i = 1; i <= ni; i++) print inc[i]
    # reach[a, b]: a reaches b through calls among library rooms (Floyd-Warshall)
    bad = 0; into_cmd = 0
    for (i = 1; i <= ne; i++) {
        if (!is_command(from[i]) && is_command(to[i])) {
            print "library room " from[i] " calls the command room " to[i] ": " fns[order[i]]
            into_cmd++
        }
        if (!is_command(from[i]) && !is_command(to[i])) reach[from[i], to[i]] = 1
    }
    for (k = 1; k <= n; k++) for (i = 1; i <= n; i++) if ((node[i], node[k]) in reach)
        for (j = 1; j <= n; j++) if ((node[k], node[j]) in reach) reach[node[i], node[j]] = 1
    na = split(allow, al, " ")
    for (a = 1; a <= na; a++) { split(al[a], p, ":"); allowed[p[1], p[2]] = 1; allowed[p[2], p[1]] = 1 }
    cycles = 0; nallowed = 0
    for (i = 1; i <= n; i++) {
        if (is_command(node[i]) || (node[i] in done)) continue
        comp = node[i]; size = 1
        for (j = i + 1; j <= n; j++)
            if (!is_command(node[j]) && ((node[i], node[j]) in reach) && ((node[j], node[i]) in reach)) {
                comp = comp " " node[j]; size++; done[node[j]] = 1; second = node[j]
            }
        if (size < 2) continue
        cycles++
        if (size == 2 && ((node[i], second) in allowed)) {
            nallowed++; seen[node[i], second] = 1; seen[second, node[i]] = 1
            print "cycle among library rooms: " comp " (allowed)"
        } else { bad++; print "cycle among library rooms: " comp }
    }
    for (a = 1; a <= na; a++) {
        split(al[a], p, ":")
        if (!((p[1], p[2]) in seen)) print "note: --allow " al[a] " is not a cycle (drop it)"
    }
    printf "callgraph: %d rooms, %d edges, %d cycles among library rooms (%d allowed), %d calls from library to command rooms\n", n, ne, cycles, nallowed, into_cmd
    exit (bad > 0 || into_cmd > 0) ? 1 : 0
}'
