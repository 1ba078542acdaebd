#!/bin/sh
# tools/ccflags.sh CC - print the optional flags that compiler CC understands:
#   -ffp-contract=off  (no fused multiply-add, same rounding on every compiler)
#   -fopenmp           (threads; without it specnee is single-threaded, same image)
# Each flag is kept only if a tiny program compiles and links with it.
cc=${1:-cc}
tmp=${TMPDIR:-/tmp}/specnee-ccflags.$$
mkdir -p "$tmp" || exit 0
cat > "$tmp/t.c" <<'C'
#include <stdio.h>
int main(void) { int i, s = 0;
#ifdef _OPENMP
#pragma omp parallel for reduction(+:s)
#endif
  for (i = 0; i < 4; i++) s += i;
  printf("%d\n", s); return 0; }
C
flags=""
for f in -ffp-contract=off -fopenmp; do
  if $cc -std=c99 -Werror $flags $f "$tmp/t.c" -o "$tmp/t" >/dev/null 2>&1 && "$tmp/t" >/dev/null 2>&1; then
    flags="$flags $f"
  fi
done
rm -rf "$tmp"
echo $flags
