# Makefile - builds specnee, its tests and its benchmarks.
# Plain POSIX make (GNU make and bmake both work): suffix rules and `!=` only.
#
#   make            build ./specnee (OpenMP when the compiler has it)
#   make run        build and render the default scene into out/
#   make test       the whole test suite (unit tests, three compilers, sanitizers)
#   make bench      benchmarks (not part of make test)
#   make bench-embree  the BVH against Embree 3, where it is installed
#   make fuzz       libFuzzer targets with clang, ASan + UBSan (not part of make test;
#                   FUZZ_SECONDS per target, default 60; fuzz/run.sh)
#   make references high-spp reference renders (docs/ref/; long: see tools/references.sh)
#   make eval       the strategy comparison behind docs/RESULTS.md (long: tools/eval.sh)
#   make factorial  wavelength pdf x selection x rough dispersion (longer: tools/factorial.sh)
#   make golden     regenerate the golden images of tests/golden/ (read its README first)
#   make mutants    mutation testing: each bug of tests/mutants.txt must fail the suite
#                   (not part of make test; tools/mutants.sh)
#   make CC=tcc     any C99 compiler
#
# No fast-math optimisation flags: results must be exact and independent of the
# thread count.
# -ffp-contract=off (when the compiler knows it) forbids fused multiply-adds, so
# gcc and clang round the same way.  tools/ccflags.sh probes the compiler.

# cc, or the first C compiler found when a machine has no `cc` (only clang, say)
CC != for c in cc gcc clang tcc; do command -v $$c >/dev/null 2>&1 && { echo $$c; exit 0; }; done; echo cc
OPT = -O2
WARN = -std=c99 -pedantic -Wall -Wextra
DETECTED != sh tools/ccflags.sh "$(CC)"
CFLAGS = $(OPT) $(WARN) $(DETECTED)
LDLIBS = -lm

LIBOBJ = util.o sampler.o bvh.o bvhbuild.o hitpoint.o instance.o motion.o shapes.o patch.o curve.o spectrum.o rgbfit.o wavelengths.o metals.o lights.o arealight.o sphtri.o lighttree.o infinite.o \
         delta.o texture.o filter.o parser.o options.o scene.o geometry.o dump.o ply.o displace.o subdiv.o medium.o equiangular.o nanovdb.o material.o microfacet.o \
         conductor.o layered.o hair.o measured.o subsurface.o bump.o camera.o lens.o path.o sensor.o render.o image.o png.o exr.o svg.o cmd_converge.o cmd_image.o \
         cmd_spectrum.o rgbtable.o
# every tests/*.c (a new test file is registered in tests/tables.h alone)
TESTOBJ != ls tests/*.c | sed 's/\.c$$/.o/'

all: specnee

specnee: specnee.o $(LIBOBJ)
	$(CC) $(CFLAGS) -o specnee specnee.o $(LIBOBJ) $(LDLIBS)

tests/runner: $(TESTOBJ) $(LIBOBJ)
	$(CC) $(CFLAGS) -o tests/runner $(TESTOBJ) $(LIBOBJ) $(LDLIBS)

fuzz/replay: fuzz/replay.o fuzz/targets.o $(LIBOBJ)
	$(CC) $(CFLAGS) -o fuzz/replay fuzz/replay.o fuzz/targets.o $(LIBOBJ) $(LDLIBS)

tools/bench: tools/bench.o $(LIBOBJ)
	$(CC) $(CFLAGS) -o tools/bench tools/bench.o $(LIBOBJ) $(LDLIBS)

tools/bench_count: tools/bench_count.c tools/bench.c $(LIBOBJ)
	$(CC) $(CFLAGS) -Itools -o tools/bench_count tools/bench_count.c $(LIBOBJ) $(LDLIBS)

# tools/gen_measured: writes the measured-BRDF test file (tests/data/measured/)
tools/gen_measured: tools/gen_measured.o $(LIBOBJ)
	$(CC) $(CFLAGS) -o tools/gen_measured tools/gen_measured.o $(LIBOBJ) $(LDLIBS)

tools/bench_lights: tools/bench_lights.o $(LIBOBJ)
	$(CC) $(CFLAGS) -o tools/bench_lights tools/bench_lights.o $(LIBOBJ) $(LDLIBS)

# rgbtable.h: the RGB -> spectrum coefficient table, computed from rgbfit.c's fit
# by tools/gen_rgbtable.c (about 15 s of one core; not kept in git)
rgbtable.o: rgbtable.h
rgbtable.h: tools/gen_rgbtable.c rgbtable.c spectrum.o rgbfit.o util.o metals.o
	$(CC) $(CFLAGS) -DRGBTABLE_GENERATOR -I. -o tools/gen_rgbtable tools/gen_rgbtable.c rgbtable.c \
	    spectrum.o rgbfit.o util.o metals.o $(LDLIBS)
	./tools/gen_rgbtable rgbtable.h.tmp && mv rgbtable.h.tmp rgbtable.h

.SUFFIXES: .c .o
.c.o:
	$(CC) $(CFLAGS) -I. -c -o $@ $<

$(LIBOBJ) specnee.o $(TESTOBJ) tools/gen_measured.o tools/bench.o tools/bench_lights.o fuzz/replay.o fuzz/targets.o: specnee.h
parser.o options.o scene.o geometry.o instance.o material.o conductor.o layered.o texture.o lights.o arealight.o delta.o infinite.o medium.o bump.o curve.o hair.o subsurface.o tests/test_hair.o tests/test_subsurface.o: parser.h
$(TESTOBJ): tests/test.h tests/tables.h
tests/test_png.o: tests/png_fixtures.h
camera.o path.o render.o: render.h
bvh.o: bvh_avx2.h

run: specnee
	mkdir -p out
	./specnee scenes/cornell.pbrt -o out/cornell.png

test: specnee tests/runner fuzz/replay
	sh tests/run.sh

FUZZ_SECONDS = 60
fuzz:
	sh fuzz/run.sh $(FUZZ_SECONDS)

bench: specnee tools/bench tools/bench_lights
	sh tools/bench.sh

# specnee's BVH against Embree 3 (docs/bvh.md): only where Embree is installed; the
# renderer and its tests never need it (tools/bench_embree.c)
bench-embree: $(LIBOBJ)
	@if printf '#include <embree3/rtcore.h>\nint main(void){return 0;}\n' | \
	    $(CC) -x c - -o /dev/null -lembree3 2>/dev/null; then \
	    $(CC) $(OPT) -std=c99 -Wall -Wextra $(DETECTED) -Itools -o tools/bench_embree \
	        tools/bench_embree.c $(LIBOBJ) -lembree3 $(LDLIBS) && ./tools/bench_embree; \
	else echo "bench-embree: Embree 3 is not installed (Debian: apt-get install libembree-dev)"; fi

# two versions of the traversal timed in one process (docs/bvh.md): tools/bench_ab.sh
# REV compiles REV's bvh.c and the work tree's into tools/bvh_a.o and tools/bvh_b.o,
# then builds and runs this
tools/bench_ab: tools/bench_ab.c tools/bench.c tools/bvh_a.o tools/bvh_b.o $(LIBOBJ)
	$(CC) $(CFLAGS) -Itools -o tools/bench_ab tools/bench_ab.c tools/bvh_a.o tools/bvh_b.o \
	    $(LIBOBJ) $(LDLIBS)

references: specnee
	sh tools/references.sh

eval: specnee
	sh tools/eval.sh

mutants:
	sh tools/mutants.sh

factorial: specnee
	sh tools/factorial.sh

golden: specnee
	sh tests/golden.sh --update

clean:
	rm -f specnee *.o tests/*.o tests/runner tools/*.o tools/bench tools/bench_lights tools/bench_embree tools/bench_count tools/bench_ab
	rm -f rgbtable.h tools/gen_rgbtable
	rm -f fuzz/*.o fuzz/replay
	rm -rf build

.PHONY: all run test bench bench-embree references eval factorial golden mutants clean fuzz
