#!/bin/sh
# fuzz/run.sh - `make fuzz`: builds the libFuzzer targets of fuzz/targets.c with
# clang (AddressSanitizer + UndefinedBehaviorSanitizer) and runs each one.
#
#   sh fuzz/run.sh [SECONDS] [TARGET...]    default: 60 s each for scene ply pfm spectrum png exr nvdb gzip measured
#
# Not part of `make test`.  Runs at low priority on one core (nice, one job).
# Corpora grow in build/fuzz/corpus-TARGET, seeded from fuzz/seeds/TARGET,
# fuzz/regress/TARGET and the scenes/ directory; an input that crashes, hangs (60 s: the machine may be busy),
# leaks or allocates more than 2 GiB is written to build/fuzz/crash-TARGET-* (or
# timeout-/leak-/oom-).  Keep each one, after the fix, in fuzz/regress/TARGET/:
# `make test` replays that directory through the same target (fuzz/replay.c).
# The last lines give, per target, the executions run and what was found.
set -u
cd "$(dirname "$0")/.." || exit 2
secs=${1:-60}
[ $# -gt 0 ] && shift
targets=${*:-scene ply pfm spectrum png exr nvdb gzip measured}
CC=${FUZZ_CC:-clang}
mkdir -p build/fuzz
echo 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { (void)d; (void)n; return 0; }' \
    > build/fuzz/probe.c
if ! "$CC" -fsanitize=fuzzer build/fuzz/probe.c -o build/fuzz/probe >/dev/null 2>&1; then
    echo "make fuzz: needs clang with libFuzzer (-fsanitize=fuzzer); set FUZZ_CC" >&2
    exit 2
fi
${MAKE:-make} rgbtable.h || exit 1      # rgbtable.c's build-time table
LIBSRC="util.c sampler.c bvh.c bvhbuild.c hitpoint.c instance.c motion.c shapes.c patch.c curve.c spectrum.c wavelengths.c metals.c lights.c arealight.c sphtri.c lighttree.c infinite.c delta.c texture.c filter.c parser.c options.c scene.c geometry.c dump.c ply.c displace.c subdiv.c medium.c equiangular.c nanovdb.c material.c microfacet.c conductor.c layered.c hair.c measured.c subsurface.c bump.c camera.c lens.c path.c sensor.c render.c image.c png.c exr.c svg.c cmd_converge.c cmd_image.c cmd_spectrum.c rgbfit.c rgbtable.c"
FLAGS="-std=c99 -g -O1 -ffp-contract=off -fno-omit-frame-pointer \
       -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all"
summary=""
for t in $targets; do
    echo "== building fuzz-$t"
    $CC $FLAGS -I. -DFUZZ_TARGET="\"$t\"" -o build/fuzz/fuzz-$t fuzz/libfuzzer.c fuzz/targets.c \
        $LIBSRC -lm || exit 1
done
for t in $targets; do
    corpus=build/fuzz/corpus-$t
    mkdir -p "$corpus" fuzz/regress/$t
    extra="fuzz/seeds/$t fuzz/regress/$t"
    if [ "$t" = scene ]; then      # the example scenes, but not the 100 KB mesh one (slow)
        mkdir -p build/fuzz/seeds-scene
        for f in scenes/*.pbrt; do
            grep -q plymesh "$f" || cp "$f" build/fuzz/seeds-scene/
        done
        extra="$extra build/fuzz/seeds-scene"
    fi
    log=build/fuzz/log-$t.txt
    echo "== fuzz-$t for $secs s (log $log)"
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    nice -n 19 build/fuzz/fuzz-$t -max_total_time="$secs" -timeout=60 -rss_limit_mb=2048 \
        -max_len=16384 -print_final_stats=1 -artifact_prefix=build/fuzz/ \
        "$corpus" $extra > "$log" 2>&1
    rc=$?
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    found=$(grep -E '^(==[0-9]+==ERROR|SUMMARY|ERROR: libFuzzer)' "$log" | head -n 1)
    [ -z "$found" ] && [ "$rc" -ne 0 ] && found="exit $rc (see $log)"
    line="fuzz-$t: ${execs:-0} executions, ${found:-no crash, hang, leak or OOM}"
    echo "$line"
    summary="$summary$line
"
done
echo "== summary ($secs s per target)"
printf '%s' "$summary"
