#!/bin/sh
# tools/bench_ab.sh - time the work tree's bvh.c (B) against another revision's (A)
# in one process, on the same tree (tools/bench_ab.c says what it measures and
# what it cannot).  Not part of `make test`: a developer's tool for changes of the
# traversal, whose few per cent a separate process per version cannot resolve on a
# shared machine (docs/bvh.md, "How it is measured").
#
#   sh tools/bench_ab.sh REV [rounds]      e.g.  sh tools/bench_ab.sh HEAD
#
# A is `git show REV:bvh.c` (with REV's bvh_avx2.h) and B the work tree's bvh.c
# (with its bvh_avx2.h), both compiled alike with
# the Makefile's compiler and optimisation against the work tree's specnee.h,
# every global name each defines prefixed with A_ or B_ (the names are read from
# bvh.o with nm), so that both link into one program beside the library.  Needs
# git, nm and make.
set -e
rev=${1:?usage: sh tools/bench_ab.sh REV [rounds]}
rounds=${2:-41}
cd "$(dirname "$0")/.."
rm -rf build/bench_ab
mkdir -p build/bench_ab/a build/bench_ab/b
# each version's bvh.c beside its own bvh_avx2.h (where the revision has one): a
# quoted #include looks beside the including file first
git show "$rev:bvh.c" > build/bench_ab/a/bvh.c
git show "$rev:bvh_avx2.h" > build/bench_ab/a/bvh_avx2.h 2>/dev/null || rm -f build/bench_ab/a/bvh_avx2.h
cp bvh.c bvh_avx2.h build/bench_ab/b/
make -s bvh.o
# the Makefile's compiler and optimisation, asked of make once
vars=$(make -s -p -n 2>/dev/null)
cc_=$(printf '%s\n' "$vars" | sed -n 's/^CC = //p' | head -1)
opt=$(printf '%s\n' "$vars" | sed -n 's/^OPT = //p' | head -1)
syms=$(nm -g --defined-only bvh.o | awk '{print $3}')
# both versions compiled alike, into tools/bvh_a.o and tools/bvh_b.o
for V in A B; do
    v=$(echo $V | tr AB ab)
    defs=
    for x in $syms; do defs="$defs -D$x=${V}_$x"; done
    "${cc_:-cc}" $opt -std=c99 $(sh tools/ccflags.sh "${cc_:-cc}") -I. $defs \
        -c build/bench_ab/$v/bvh.c -o tools/bvh_$v.o
done
make -s tools/bench_ab
tools/bench_ab "$rounds"
