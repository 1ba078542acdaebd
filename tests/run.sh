#!/bin/sh
# tests/run.sh - the whole test suite, run by `make test` (and by CI).
#
#  1. the unit/statistical suite (tests/runner) built by make with the default cc
#  2. end-to-end checks of the binary: exit codes, one-line errors, a tiny render
#  3. the same suite built with -Werror by gcc, clang and tcc (C99, pedantic)
#  4. the suite once more under AddressSanitizer + UndefinedBehaviorSanitizer, and
#     the fuzz inputs (fuzz/regress, fuzz/seeds) replayed under it
#  5. the test runner itself: its compiler probe without clang and tcc on PATH
# Steps 3 and 4 run every test with a quarter of the samples (SPECNEE_TEST_SCALE):
# they prove the build and catch memory errors; step 1 carries the statistics.
# Every step counts as tests; the last line is "N passed, N failed, N skipped".
#
# WHAT A FRESH MACHINE NEEDS: a C99 compiler (cc), make and libm; nothing else.
# Steps 3 and 4 use what is present: a compiler that is not installed (gcc, clang,
# tcc) and a sanitizer runtime that does not link are *skipped* with a visible
# "skip" line, not failed.  CI (.ci/run) installs clang and tcc and sets
# SPECNEE_STRICT=1: then a missing compiler or sanitizer is a failure, so every
# landing is proven with all three compilers and the sanitizers.
#
# WHICH STEPS RUN.  A developer's default run is steps 1 and 2 (every unit and
# statistical test, the binary end to end, the goldens, the walkthrough, the docs):
# what a change of the renderer must pass, in about 3 minutes on 2 cores.  Steps
# 3-5 (two more compilers with -Werror, the sanitizers, the runner's own probe)
# prove portability and memory safety; they take as long again and run when asked:
#   SPECNEE_FULL=1    also steps 3-5; a missing compiler or sanitizer is a skip line
#   SPECNEE_STRICT=1  also steps 3-5; a missing compiler or sanitizer fails (CI)
#   SPECNEE_QUICK=1   steps 1-2 only, even with SPECNEE_FULL=1 (not with STRICT)
#   sh tests/run.sh --probe   only say which compilers/sanitizers steps 3-4 would
#                     use (the same decisions, no build); step 5 tests it
set -u
cd "$(dirname "$0")/.." || exit 2
passed=0
failed=0
skipped=0
strict=${SPECNEE_STRICT:-0}
log=tests/tmp/run.log
mkdir -p tests/tmp build
: > "$log"

ok()   { passed=$((passed + 1)); echo "ok   $1"; }
fail() { failed=$((failed + 1)); echo "FAIL $1"; }
# A check that cannot run here: a failure under SPECNEE_STRICT=1, else a skip line.
skip() {
    if [ "$strict" = 1 ]; then fail "$(echo "$1" | sed 's/ (CI proves it)//') (SPECNEE_STRICT=1)"
    else skipped=$((skipped + 1)); echo "skip $1"; fi
}

# ---- the toolchain probe (steps 3 and 4 decide with these; --probe prints them)
SECOND_CC=0          # how many compilers other than the default one were proven
have_cc() { command -v "$1" >/dev/null 2>&1; }
# The first of gcc, clang whose sanitizer runtime compiles, links and runs a tiny
# program with -fsanitize=address,undefined; empty when none does.
asan_cc() {
    printf 'int main(void) { return 0; }\n' > tests/tmp/asan-probe.c
    for c in gcc clang; do
        have_cc $c || continue
        if $c -fsanitize=address,undefined -o tests/tmp/asan-probe tests/tmp/asan-probe.c \
               >/dev/null 2>&1 && tests/tmp/asan-probe >/dev/null 2>&1; then
            echo $c; return
        fi
    done
}
if [ "${1:-}" = --probe ]; then
    for cc in gcc clang tcc; do
        if have_cc $cc; then ok "probe_$cc: found"
        else skip "build_$cc: $cc not installed (CI proves it)"; fi
    done
    a=$(asan_cc)
    if [ -n "$a" ]; then ok "probe_asan: $a"
    else skip "build_asan: no compiler here links -fsanitize=address,undefined (CI proves it)"; fi
    echo "$passed passed, $failed failed, $skipped skipped"
    [ "$failed" -eq 0 ]
    exit
fi

# Run a command that ends with a line "...: N passed, N failed" and add its counts:
# the unit runners, tests/golden.sh, tests/walkthrough.sh.  $1 = label, rest = command.
# A crash (no summary) or a non-zero exit with 0 failures counts as a failure.
counted() {
    label=$1; shift; out=tests/tmp/counted-$label.txt
    "$@" > "$out" 2>&1
    rc=$?
    grep '^FAIL' "$out" | sed "s/^/[$label] /"
    line=$(grep 'passed, .* failed' "$out" | tail -n 1)
    p=$(echo "$line" | sed -n 's/.* \([0-9][0-9]*\) passed.*/\1/p')
    f=$(echo "$line" | sed -n 's/.* \([0-9][0-9]*\) failed.*/\1/p')
    if [ -z "$p" ]; then
        fail "[$label] crashed or printed no summary (rc=$rc)"
        tail -n 20 "$out"
        return
    fi
    echo "[$label] $line"
    passed=$((passed + p)); failed=$((failed + f))
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then fail "[$label] exit code $rc"; fi
}

# Expect exit code $2 from command "$3..." and stderr containing $1 (a grep -E pattern).
expect() {
    name=$1; code=$2; pattern=$3; shift 3
    "$@" > tests/tmp/out.txt 2> tests/tmp/err.txt
    rc=$?
    if [ "$rc" -ne "$code" ]; then
        fail "$name: exit $rc, expected $code"; head -n 3 tests/tmp/err.txt; return
    fi
    if [ -n "$pattern" ] && ! grep -Eq "$pattern" tests/tmp/err.txt; then
        fail "$name: stderr lacks /$pattern/"; head -n 3 tests/tmp/err.txt; return
    fi
    ok "$name"
}

# ---- 1. unit suite with the default build
counted cc tests/runner

# ---- 2. the binary end to end
expect "cli_help" 0 "" ./specnee --help
expect "cli_no_scene" 2 "no scene file" ./specnee
expect "cli_bad_option" 2 "unknown option" ./specnee --frobnicate x.pbrt
expect "cli_bad_spp" 2 "positive integer" ./specnee --spp 0 scenes/cornell.pbrt
expect "cli_missing_file" 1 "nonexistent.pbrt" ./specnee tests/tmp/nonexistent.pbrt
printf 'WorldBegin\nShape "sphere" "float radius" [ 1 ]\nFrobnicate 3\n' > tests/tmp/bad.pbrt
expect "cli_bad_directive" 1 "bad.pbrt:3:" ./specnee tests/tmp/bad.pbrt
# gzip: a .pbrt.gz renders (it Includes a .pbrt.gz and reads a .ply.gz); a damaged one is refused
expect "cli_gzip_scene" 0 "samples/s" ./specnee tests/data/gz/room.pbrt.gz -o tests/tmp/gz.pfm
expect "cli_gzip_bad_crc" 1 "bad-crc.pbrt.gz: gzip: CRC-32 mismatch" ./specnee fuzz/seeds/gzip/bad-crc.pbrt.gz -o tests/tmp/gz.pfm
printf 'Film "rgb" "integer xresolution" 4 "integer yresolution" 4\nWorldBegin\nShape "sphere"\n' > tests/tmp/nolight.pbrt
expect "cli_no_lights_warns" 0 "nolight.pbrt: warning: no light sources" ./specnee -q tests/tmp/nolight.pbrt -o tests/tmp/nolight.pfm
./specnee -q scenes/cornell.pbrt --spp 1 --res 4x4 -o tests/tmp/lit.pfm 2> tests/tmp/lit.txt
if grep -q "no light sources" tests/tmp/lit.txt; then fail "cli_lit_scene_no_warning"; else ok "cli_lit_scene_no_warning"; fi
expect "cli_render_tiny" 0 "samples/s" ./specnee scenes/cornell.pbrt --spp 2 -o tests/tmp/tiny.pfm
if [ -f tests/tmp/tiny.pfm ] && [ -f tests/tmp/tiny.pfm.txt ]; then ok "cli_render_writes_pfm_and_sidecar"
else fail "cli_render_writes_pfm_and_sidecar"; fi
expect "cli_render_png" 0 "" ./specnee -q scenes/cornell.pbrt --spp 1 -o tests/tmp/tiny.png
# pbrt-v4's Accelerator is read and ignored with a note; -o overrides Film's
# "string filename" with a note (a placeholder name then loads), and no note about
# the scene's own name (".exr becomes .pfm") appears when -o names the output
printf 'Accelerator "bvh" "integer maxnodeprims" 2\nFilm "rgb" "integer xresolution" 4 "integer yresolution" 4 "string filename" "__OUTPUT_PNG__"\nWorldBegin\nAttributeBegin\nAreaLightSource "diffuse"\nShape "sphere" "float radius" 0.5\nAttributeEnd\n' > tests/tmp/accel.pbrt
expect "cli_output_placeholder_needs_o" 1 "accel.pbrt:2: .*__OUTPUT_PNG__" ./specnee -q tests/tmp/accel.pbrt
expect "cli_accelerator_note" 0 "accel.pbrt:1: note: Accelerator \"bvh\" is read and ignored" ./specnee -q tests/tmp/accel.pbrt -o tests/tmp/accel.png
if grep -q 'accel.pbrt:2: note: the output file "tests/tmp/accel.png" of the command line overrides Film "string filename" "__OUTPUT_PNG__"' tests/tmp/err.txt &&
   [ "$(wc -l < tests/tmp/err.txt)" -eq 2 ] && [ -s tests/tmp/accel.png ]; then ok "cli_output_overrides_film_filename"
else fail "cli_output_overrides_film_filename"; cat tests/tmp/err.txt; fi
sed 's/__OUTPUT_PNG__/scene.exr/' tests/tmp/accel.pbrt > tests/tmp/exr.pbrt
expect "cli_output_no_exr_note" 0 "overrides Film" ./specnee -q tests/tmp/exr.pbrt -o tests/tmp/exr.ppm
if grep -q 'EXR' tests/tmp/err.txt; then fail "cli_output_no_exr_note: an EXR note with -o"; else ok "cli_output_no_exr_note_absent"; fi
# a scene naming an ordinary .pfm/.ppm/.png stays quiet under -o
./specnee -q scenes/cornell.pbrt --spp 1 --res 4x4 -o tests/tmp/quiet.png 2> tests/tmp/quiet.txt
if [ ! -s tests/tmp/quiet.txt ]; then ok "cli_output_ordinary_name_quiet"; else fail "cli_output_ordinary_name_quiet"; cat tests/tmp/quiet.txt; fi
# what changes nothing gets a note and leaves the image as it is: a medium that no
# shape's transition nor the camera leads into, a light's "power" or "illuminance"
# <= 0 (pbrt-v4 ignores it; an area light's too, whose positive "power" specnee
# refuses); a medium that a shape leads into gets no note
printf 'Film "rgb" "integer xresolution" 8 "integer yresolution" 8\nSampler "sobol" "integer pixelsamples" 2\nIntegrator "volpath"\nWorldBegin\nLightSource "point" "point3 from" [ 1 1 1 ]\nAttributeBegin\nAreaLightSource "diffuse"\nTranslate 0 0 3\nShape "sphere" "float radius" 0.5\nAttributeEnd\nShape "bilinearmesh" "point3 P" [ -9 -9 6  9 -9 6  -9 9 6  9 9 6 ]\n' > tests/tmp/used.pbrt
expect "cli_used_quiet" 0 "" ./specnee -q tests/tmp/used.pbrt -o tests/tmp/used.pfm
if [ ! -s tests/tmp/err.txt ]; then ok "cli_used_quiet_no_note"; else fail "cli_used_quiet_no_note"; cat tests/tmp/err.txt; fi
sed -e 's/^WorldBegin$/WorldBegin\nMakeNamedMedium "fog" "string type" "homogeneous"/' \
    -e 's/^LightSource "point"/& "float power" [ -60 ]/' -e 's/^AreaLightSource "diffuse"/& "float power" 0/' \
    tests/tmp/used.pbrt > tests/tmp/unused.pbrt
expect "cli_note_unused_medium" 0 'unused.pbrt:5: note: medium "fog" is defined but never used' ./specnee -q tests/tmp/unused.pbrt -o tests/tmp/unused.pfm
if grep -q 'unused.pbrt:6: note: LightSource "point": "float power" -60 is not positive and is ignored' tests/tmp/err.txt &&
   grep -q 'unused.pbrt:8: note: AreaLightSource "diffuse": "float power" 0 is not positive and is ignored' tests/tmp/err.txt &&
   [ "$(wc -l < tests/tmp/err.txt)" -eq 3 ]; then ok "cli_note_power_ignored"; else fail "cli_note_power_ignored"; cat tests/tmp/err.txt; fi
if cmp -s tests/tmp/used.pfm tests/tmp/unused.pfm; then ok "cli_ignored_image_unchanged"; else fail "cli_ignored_image_unchanged"; fi
printf 'Film "rgb" "integer xresolution" 4 "integer yresolution" 4\nWorldBegin\nAttributeBegin\nAreaLightSource "diffuse"\nShape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  1 1 0  0 1 0 ] "integer indices" [ 0 1 2  0 2 3  0 3 2 ]\nAttributeEnd\n' > tests/tmp/twins.pbrt
expect "cli_note_coincident_lamp" 0 'twins.pbrt:5: note: area light: triangles 1 and 2 of this mesh lie on each other with opposite windings' ./specnee -q --spp 1 tests/tmp/twins.pbrt -o tests/tmp/twins.pfm
printf 'WorldBegin\nMakeNamedMedium "fog" "string type" "homogeneous"\nAttributeBegin\nMediumInterface "fog" ""\nMaterial "interface"\nShape "sphere"\nAttributeEnd\nLightSource "distant" "float illuminance" -1\n' > tests/tmp/fog.pbrt
./specnee -q tests/tmp/fog.pbrt --res 4x4 --spp 1 -o tests/tmp/fog.pfm 2> tests/tmp/fog.txt
if ! grep -q 'never used' tests/tmp/fog.txt &&
   grep -q 'fog.pbrt:8: note: LightSource "distant": "float illuminance" -1 is not positive' tests/tmp/fog.txt
then ok "cli_note_medium_used_distant"; else fail "cli_note_medium_used_distant"; cat tests/tmp/fog.txt; fi
expect "cli_bad_sampler" 2 "independent, stratified, sobol, zsobol or halton" ./specnee --sampler pmj02bn scenes/cornell.pbrt
expect "cli_render_sampler" 0 "samples/s" ./specnee scenes/cornell.pbrt --res 16x16 --spp 2 --sampler zsobol -o tests/tmp/zs.pfm
if grep -q 'sampler=zsobol' tests/tmp/zs.pfm.txt 2>/dev/null; then ok "cli_sidecar_records_sampler"
else fail "cli_sidecar_records_sampler"; fi
expect "cli_mark_insets_needs_png" 2 "needs a .png" ./specnee scenes/cornell1.pbrt --spp 1 --mark-insets -o tests/tmp/m.pfm
expect "cli_mark_insets" 0 "" ./specnee -q scenes/cornell1.pbrt --spp 1 --mark-insets -o tests/tmp/marked.png
expect "cli_mark_insets_plain" 0 "" ./specnee -q scenes/cornell1.pbrt --spp 1 -o tests/tmp/plain.png
# same size (the outlines replace pixels), different bytes
if [ "$(wc -c < tests/tmp/marked.png)" = "$(wc -c < tests/tmp/plain.png)" ] &&
   ! cmp -s tests/tmp/marked.png tests/tmp/plain.png; then ok "cli_mark_insets_draws"
else fail "cli_mark_insets_draws"; fi
expect "cli_merge" 0 "" ./specnee merge tests/tmp/tiny.pfm tests/tmp/tiny.pfm -o tests/tmp/merged.pfm
expect "cli_diff_identical" 0 "" ./specnee diff tests/tmp/tiny.pfm tests/tmp/merged.pfm --max-mse 0
expect "cli_spectrum" 0 "" ./specnee spectrum lamp-CFL1
expect "cli_spectrum_unknown" 1 "no-such" ./specnee spectrum no-such-spectrum
# --debug-pixel: a pixel outside the film is bad usage; NEE failures are printed
# (with the thesis' spatial selection: its reach mask leaves no emitter at that vertex)
expect "cli_debug_pixel_outside" 2 "outside the 64x64 film" ./specnee scenes/cornell.pbrt --res 64x64 --debug-pixel 200,200 -o tests/tmp/d.pfm
if ./specnee scenes/cornell.pbrt --preset thesis --res 128x128 --spp 1 -q --debug-pixel 40,120 -o tests/tmp/d.pfm 2>&1 |
   grep -q 'NEE: no emitter can be chosen here'; then ok "cli_debug_pixel_nee_failure"
else fail "cli_debug_pixel_nee_failure"; fi
# contract item C4 end to end: through rough dispersive glass with all four
# wavelengths alive, the MIS weights of all (technique, hero) pairs sum to 1
sed 's/^LookAt .*/LookAt 200 20 170   230 548 280   0 0 1/' scenes/cornell1.pbrt > tests/tmp/up.pbrt
./specnee tests/tmp/up.pbrt --res 32x32 --spp 16 -q --lights spd --all-wavelengths --rough-dispersion mis \
    --debug-pixel 16,16 -o tests/tmp/d.pfm > tests/tmp/up.txt 2>&1
if grep -q 'MIS weight' tests/tmp/up.txt && ! grep -q WARNING tests/tmp/up.txt; then ok "cli_debug_pixel_weights_sum_to_one"
else fail "cli_debug_pixel_weights_sum_to_one"; fi
# --debug-pixel's shares multiply to the MIS weight it prints, also for an emitter
# found by a BSDF or phase sample through a chromatic medium, where W's densities
# are q_bsdf(m) Tr_m (THEORY (19))
printf '%s\n' 'MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [0.02 0.05 0.1] "rgb sigma_s" [0.3 0.1 0.05]' \
    'MediumInterface "" "fog"' 'LookAt 0 0 5  0 0 0  0 1 0' 'Camera "perspective" "float fov" [ 50 ]' \
    'Film "rgb" "integer xresolution" 16 "integer yresolution" 16' 'WorldBegin' 'MediumInterface "" ""' \
    'Shape "trianglemesh" "point3 P" [ -5 -5 -1  5 -5 -1  5 5 -1  -5 5 -1 ] "integer indices" [ 0 1 2 0 2 3 ]' \
    'AttributeBegin' 'AreaLightSource "diffuse" "blackbody L" [ 4000 ] "float scale" 4' \
    'Shape "trianglemesh" "point3 P" [ -1 3 -1  1 3 -1  1 3 1  -1 3 1 ] "integer indices" [ 0 1 2 0 2 3 ]' \
    'AttributeEnd' > tests/tmp/fogarea.pbrt
shares=$(./specnee -q tests/tmp/fogarea.pbrt --spp 64 --debug-pixel 8,2 -o tests/tmp/d.pfm 2>&1 |
    awk '/emission from emitter .* MIS weight .* = .* share .* x hero share/ {
             for (i = 1; i <= NF; i++) { if ($i == "weight") w = $(i + 1)
                 if ($i == "share" && $(i - 1) != "hero") a = $(i + 1); if ($i == "share" && $(i - 1) == "hero") b = $(i + 1) }
             n++; if (w > 0 && (a * b / w > 1.002 || a * b / w < 0.998)) bad++ }
         END { print n + 0, bad + 0 }')
if [ "${shares% *}" -gt 0 ] && [ "${shares#* }" -eq 0 ]; then ok "cli_debug_pixel_shares_through_medium ($shares)"
else fail "cli_debug_pixel_shares_through_medium: emission lines, mismatched: $shares"; fi
# --dump-scene shows a Camera's screen window (pbrt-v4's screenwindow / frameaspectratio)
sed 's/^Camera "perspective"/Camera "perspective" "float screenwindow" [ -0.5 1 -1 0.25 ]/' scenes/cornell.pbrt > tests/tmp/sw.pbrt
if ./specnee --dump-scene tests/tmp/sw.pbrt 2>/dev/null | grep -q '^camera: perspective, .*, screen window \[-0.5 1 -1 0.25\]' &&
   ! ./specnee --dump-scene scenes/cornell.pbrt 2>/dev/null | grep -q 'screen window'; then ok "cli_dump_screen_window"
else fail "cli_dump_screen_window"; fi
# the emitter x bin table: cornell1's bin 29 (545-550 nm), P(CFL) = 0.1771/(0.1771 + 0.02754)
if ./specnee spectrum --table scenes/cornell1.pbrt | grep -Eq '^ +29 +545-550 +0\.1771 +0\.02754 +0\.8654 +0\.1346$'
then ok "cli_spectrum_table"; else fail "cli_spectrum_table"; fi
./specnee spectrum --table --svg scenes/cornell2.pbrt > tests/tmp/table.svg
if head -c 5 tests/tmp/table.svg | grep -q '<svg' && tail -n 1 tests/tmp/table.svg | grep -q '</svg>' &&
   [ "$(grep -c '<title>emitter' tests/tmp/table.svg)" -eq 360 ]; then ok "cli_spectrum_table_svg"
else fail "cli_spectrum_table_svg"; fi
# a refractive index is plotted as an index, and not mixed with emission spectra
if ./specnee spectrum --svg glass-BK7 | grep -q 'refractive index n' &&
   ! ./specnee spectrum --svg glass-BK7 | grep -q 'relative spectral power'; then ok "cli_spectrum_svg_index"
else fail "cli_spectrum_svg_index"; fi
expect "cli_spectrum_svg_mixed" 2 "refractive indices" ./specnee spectrum --svg glass-BK7 lamp-CFL1
# the closing line counts the lazily built voxel tables
ms=$(./specnee scenes/cornell1.pbrt --res 16x16 --spp 1 --lights product -o tests/tmp/d.pfm 2>&1 |
     sed -n 's/.*tables \([0-9.]*\) ms, built lazily.*/\1/p')
if [ -n "$ms" ] && awk -v m="$ms" 'BEGIN { exit !(m > 0) }'; then ok "cli_tables_time_lazy ($ms ms)"
else fail "cli_tables_time_lazy"; fi
expect "cli_converge_usage" 2 "usage" ./specnee converge
expect "cli_converge_ladder_order" 2 "must increase" ./specnee converge scenes/cornell.pbrt --ref x.pfm --spp 8,4
expect "cli_converge_time_basis" 2 "cpu or wall" ./specnee converge scenes/cornell.pbrt --ref x.pfm --time gpu
# presets (specnee.c): a preset is exactly its flags (bit-identical image and
# sidecar), a later flag overrides it, an earlier one does not survive it (it pins
# every setting whose default may change), an unknown one is a usage error
preset_run() {  # output-name flags...: a tiny cornell1 render (two emitters, rough glass)
    n=$1; shift
    ./specnee -q scenes/cornell1.pbrt --res 24x24 --spp 2 --seed 3 "$@" -o "tests/tmp/preset-$n.pfm" 2> /dev/null
}
same() {  # images bit-identical and the sidecars (spp, settings) equal
    cmp -s "tests/tmp/preset-$1.pfm" "tests/tmp/preset-$2.pfm" &&
        cmp -s "tests/tmp/preset-$1.pfm.txt" "tests/tmp/preset-$2.pfm.txt"
}
preset_run thesis --preset thesis
preset_run thesis-flags --wavelengths uniform --lights spatial --spd-metric unit --spd-wavelengths hero --rough-dispersion terminate --sampler independent --fluor-lanes terminate --fluor-li a --light-shape-sampling area
preset_run spd --preset thesis-spd
preset_run spd-flags --wavelengths uniform --lights product --spd-metric unit --spd-wavelengths hero --rough-dispersion terminate --sampler independent --fluor-lanes terminate --fluor-li a --light-shape-sampling area
preset_run thesis-then-product --preset thesis --lights product
preset_run thesis-then-mis --preset thesis --rough-dispersion mis
preset_run pinned --wavelengths importance --lights product --spd-metric power --all-wavelengths --rough-dispersion mis --sampler sobol --fluor-lanes keep --fluor-li power --preset thesis
preset_run pinned-spd --wavelengths visible --lights spatial --spd-metric power --throughput-weighted --rough-dispersion mis --sampler zsobol --fluor-lanes keep --fluor-li uniform --preset thesis-spd
if same thesis thesis-flags; then ok "cli_preset_thesis_is_its_flags"; else fail "cli_preset_thesis_is_its_flags"; fi
if same spd spd-flags; then ok "cli_preset_thesis_spd_is_its_flags"; else fail "cli_preset_thesis_spd_is_its_flags"; fi
if same thesis-then-product spd && ! same thesis-then-mis thesis && ! same spd thesis; then ok "cli_preset_later_flags_override"
else fail "cli_preset_later_flags_override"; fi
if same pinned thesis && same pinned-spd spd; then ok "cli_preset_pins_every_setting"; else fail "cli_preset_pins_every_setting"; fi
expect "cli_preset_unknown" 2 "unknown --preset" ./specnee --preset pbrt scenes/cornell.pbrt
# --light-shape-sampling (lights.c): auto is the default; solidangle and area force
# one map (cornell1's lamps: the rule picks area for some receivers, so they differ)
preset_run shape-default
preset_run shape-auto --light-shape-sampling auto
preset_run shape-sa --light-shape-sampling solidangle
if cmp -s tests/tmp/preset-shape-default.pfm tests/tmp/preset-shape-auto.pfm &&
   ! cmp -s tests/tmp/preset-shape-auto.pfm tests/tmp/preset-shape-sa.pfm &&
   ! cmp -s tests/tmp/preset-shape-auto.pfm tests/tmp/preset-thesis-flags.pfm; then ok "cli_light_shape_sampling_auto_default"
else fail "cli_light_shape_sampling_auto_default"; fi
expect "cli_light_shape_sampling_unknown" 2 "solidangle" ./specnee --light-shape-sampling sphere scenes/cornell.pbrt
# Option "integer seed" (scene.c): the file's seed when the command line gives none,
# the image of --seed 7 without it; --seed overrides it, as it overrides a Sampler's
{ echo 'Option "integer seed" 7'; cat scenes/cornell1.pbrt; } > tests/tmp/seed7.pbrt
cp scenes/cornell1.pbrt tests/tmp/seed0.pbrt
./specnee -q tests/tmp/seed7.pbrt --res 24x24 --spp 2 -o tests/tmp/preset-opt7.pfm 2> /dev/null
./specnee -q tests/tmp/seed0.pbrt --res 24x24 --spp 2 --seed 7 -o tests/tmp/preset-cli7.pfm 2> /dev/null
./specnee -q tests/tmp/seed7.pbrt --res 24x24 --spp 2 --seed 3 -o tests/tmp/preset-opt7cli3.pfm 2> /dev/null
./specnee -q tests/tmp/seed0.pbrt --res 24x24 --spp 2 --seed 3 -o tests/tmp/preset-cli3.pfm 2> /dev/null
if cmp -s tests/tmp/preset-opt7.pfm tests/tmp/preset-cli7.pfm && cmp -s tests/tmp/preset-opt7cli3.pfm tests/tmp/preset-cli3.pfm &&
   ! cmp -s tests/tmp/preset-opt7.pfm tests/tmp/preset-cli3.pfm; then ok "cli_option_seed"; else fail "cli_option_seed"; fi
expect "cli_preset_help" 0 "" ./specnee --help
if grep -q 'thesis-spd *--wavelengths uniform --lights product' tests/tmp/out.txt; then ok "cli_preset_help_lists_flags"
else fail "cli_preset_help_lists_flags"; fi
expect "cli_wavelengths_unknown" 2 "uniform, importance, visible or mixture" ./specnee --wavelengths hero scenes/cornell.pbrt
expect "cli_mix_weight_range" 2 "in \(0, 1\]" ./specnee --mix-weight 0 scenes/cornell.pbrt
# the evaluation pipeline in miniature (make eval's smoke test): the committed
# cornell-glass reference, two variants, spp 1 and 2, two seeds; the CSV must have
# its header and 2x2x2 rows for each of the 4 regions (image, insets A-C), no NaN,
# and the three SVG charts and the table must be complete
expect "eval_smoke_converge" 0 "" ./specnee converge scenes/cornell-glass.pbrt --ref docs/ref/cornell-glass.pfm \
    --lights spatial,spatial:importance --spp 1,2 --seeds 2 --out tests/tmp/smoke
rows=$(grep -c '^scenes/cornell-glass.pbrt,spatial' tests/tmp/smoke.csv 2>/dev/null || echo 0)
if head -n 1 tests/tmp/smoke.csv 2>/dev/null | grep -q '^scene,variant,spp,seed,wall_s,cpu_s,build_s,region,mse,relmse,mae$' &&
   [ "$rows" -eq 32 ] && ! grep -qi 'nan' tests/tmp/smoke.csv; then ok "eval_smoke_csv"
else fail "eval_smoke_csv (rows $rows)"; fi
svg_ok=1
for c in mse_spp mse_time efficiency; do
    f=tests/tmp/smoke_$c.svg
    head -c 200 "$f" 2>/dev/null | grep -q '<svg' && tail -c 20 "$f" | grep -q '</svg>' &&
        grep -q 'spatial:importance' "$f" || svg_ok=0
done
if [ $svg_ok = 1 ] && grep -q '| spatial:importance |' tests/tmp/smoke.md &&
   grep -q 'CPU time (s)' tests/tmp/smoke_mse_time.svg; then ok "eval_smoke_svg_and_table"
else fail "eval_smoke_svg_and_table"; fi
# --reuse rebuilds the tables from the CSV without rendering: the same MSE columns;
# with settings the CSV does not hold it refuses
cp tests/tmp/smoke.md tests/tmp/smoke-first.md
expect "eval_smoke_reuse" 0 "" ./specnee converge scenes/cornell-glass.pbrt --ref docs/ref/cornell-glass.pfm \
    --lights spatial,spatial:importance --spp 1,2 --seeds 2 --out tests/tmp/smoke --reuse
if [ "$(cut -d'|' -f2-4 tests/tmp/smoke.md)" = "$(cut -d'|' -f2-4 tests/tmp/smoke-first.md)" ] &&
   grep -q '| spatial:importance |' tests/tmp/smoke.md; then ok "eval_smoke_reuse_same_tables"
else fail "eval_smoke_reuse_same_tables"; fi
expect "eval_smoke_reuse_mismatch" 1 "rows these settings need" ./specnee converge scenes/cornell-glass.pbrt \
    --ref docs/ref/cornell-glass.pfm --lights spatial,spatial:importance --spp 1,2 --seeds 3 --out tests/tmp/smoke --reuse
# a CSV with a duplicated row is refused, naming the line
cp tests/tmp/smoke.csv tests/tmp/dup.csv && tail -n 1 tests/tmp/smoke.csv >> tests/tmp/dup.csv
expect "eval_smoke_reuse_duplicate" 1 "dup.csv:[0-9]+: a second row" ./specnee converge scenes/cornell-glass.pbrt \
    --ref docs/ref/cornell-glass.pfm --lights spatial,spatial:importance --spp 1,2 --seeds 2 --out tests/tmp/dup --reuse
# a cropped film (Film cropwindow): the reference is the crop's size, the insets are
# clipped to the crop and moved to its origin (A and B stay, C lies outside)
sed 's/^Film "rgb"/Film "rgb" "float cropwindow" [ 0.25 0.75 0.25 0.75 ]/' scenes/cornell-glass.pbrt > tests/tmp/crop.pbrt
expect "eval_crop_reference" 0 "" ./specnee -q tests/tmp/crop.pbrt --spp 4 -o tests/tmp/crop-ref.pfm
expect "eval_crop_converge" 0 "" ./specnee converge tests/tmp/crop.pbrt --ref tests/tmp/crop-ref.pfm \
    --lights spatial --spp 1,2 --seeds 2 --out tests/tmp/crop
if [ "$(grep -c ',image,' tests/tmp/crop.csv 2>/dev/null)" = 4 ] && [ "$(grep -c ',A,' tests/tmp/crop.csv)" = 4 ] &&
   [ "$(grep -c ',B,' tests/tmp/crop.csv)" = 4 ] && ! grep -q ',C,' tests/tmp/crop.csv; then ok "eval_crop_regions"
else fail "eval_crop_regions"; fi
expect "eval_crop_full_reference_refused" 1 "reference is 160x160, the scene renders 80x80" ./specnee converge \
    tests/tmp/crop.pbrt --ref docs/ref/cornell-glass.pfm --lights spatial --spp 1 --seeds 2 --out tests/tmp/crop2
expect "cli_mark_insets_crop" 0 "" ./specnee -q tests/tmp/crop.pbrt --spp 1 --mark-insets -o tests/tmp/crop-marked.png
# the picture: a PNG (signature, IHDR 160x160) and its caption with the inset colours
if [ "$(head -c 8 tests/tmp/smoke.png 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] &&
   [ "$(od -An -tx1 -j16 -N8 tests/tmp/smoke.png | tr -d ' \n')" = 000000a0000000a0 ] &&
   grep -q 'insets outlined: A yellow, B cyan, C magenta' tests/tmp/smoke.md; then ok "eval_smoke_picture"
else fail "eval_smoke_picture"; fi

# no tracked file is a compiled program (an ELF, Mach-O or PE executable, or an
# executable file that is not a #! script): build products belong in .gitignore
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    bad=""
    for f in $(git ls-files); do
        [ -f "$f" ] || continue
        magic=$(head -c 4 "$f" | od -An -tx1 | tr -d ' \n')
        case "$magic" in
            7f454c46|cffaedfe|cefaedfe|feedfacf|feedface|4d5a*) bad="$bad $f"; continue ;;
        esac
        if [ -x "$f" ] && [ "$(head -c 2 "$f")" != '#!' ]; then bad="$bad $f"; fi
    done
    if [ -z "$bad" ]; then ok "repo_no_tracked_binaries"
    else fail "repo_no_tracked_binaries: tracked executables:$bad (build products belong in .gitignore)"; fi
else
    skip "repo_no_tracked_binaries: not a git checkout"
fi
# the scripts that compile the library themselves (the compiler matrix below,
# make fuzz) list the same sources as the Makefile's LIBOBJ
mk_src=$(sed -n '/^LIBOBJ *=/,/[^\\]$/p' Makefile | sed 's/LIBOBJ *=//; s/\\//g' | tr ' ' '\n' |
         sed -n 's/\.o$/.c/p' | sort | tr '\n' ' ')
for f in tests/run.sh fuzz/run.sh; do
    f_src=$(sed -n 's/^ *LIBSRC="\([^"]*\)".*/\1/p' "$f" | head -n 1 | tr ' ' '\n' | grep . | sort | tr '\n' ' ')
    if [ -n "$mk_src" ] && [ "$f_src" = "$mk_src" ]; then ok "repo_libsrc_$(echo "$f" | tr '/.' '__')"
    else fail "repo_libsrc_$(echo "$f" | tr '/.' '__'): LIBSRC is '$f_src', the Makefile's LIBOBJ '$mk_src'"; fi
done
# the call graph of the rooms (tools/callgraph.sh): no library room calls a command
# room (specnee.c, cmd_*.c) and the library rooms call each other without a cycle.
if sh tools/callgraph.sh > tests/tmp/callgraph.txt 2>&1; then
    ok "repo_no_library_cycle$(sed -n 's/^note: \(.*\)/ (\1)/p' tests/tmp/callgraph.txt | tr -d '\n')"
else fail "repo_no_library_cycle: $(grep -v ' -> \| includes ' tests/tmp/callgraph.txt | tr '\n' ' ')"; fi
# ... and the script finds a ring of three rooms and a call into a command room
rm -rf tests/tmp/cg && mkdir -p tests/tmp/cg
printf 'int a_f(void) { return b_f(); }\n' > tests/tmp/cg/a.c
printf 'int b_f(void) { return c_f(); }\n' > tests/tmp/cg/b.c
printf 'int c_f(void)\n{\n    return a_f() + cmd_x(0);\n}\n' > tests/tmp/cg/c.c
printf 'int cmd_x(int n) { return n; }\n' > tests/tmp/cg/cmd_x.c
if ! sh tools/callgraph.sh tests/tmp/cg/*.c > tests/tmp/cg/out.txt 2>&1 &&
   grep -q '^cycle among library rooms: tests/tmp/cg/a.c tests/tmp/cg/b.c tests/tmp/cg/c.c$' tests/tmp/cg/out.txt &&
   grep -q '^library room tests/tmp/cg/c.c calls the command room tests/tmp/cg/cmd_x.c: cmd_x$' tests/tmp/cg/out.txt
then ok "repo_callgraph_selftest"
else fail "repo_callgraph_selftest: $(tr '\n' ' ' < tests/tmp/cg/out.txt)"; fi
# every tests/test_X.c is registered in tests/tables.h: the runner runs its table X
reg=$(tests/runner --tables 2>/dev/null | sort)
unreg=$(for f in tests/test_*.c; do x=${f#tests/test_}; x=${x%.c}
            echo "$reg" | grep -qx "$x" || printf ' %s' "$f"; done)
if [ -n "$reg" ] && [ -z "$unreg" ]; then ok "repo_test_tables"
else fail "repo_test_tables: not in tests/tables.h (their tests never run):${unreg:- (tests/runner --tables printed nothing)}"; fi
# hostile input end to end (tests/test_robust.c has the unit cases)
# a PFM read from a pipe: the header claims 16384 x 16384 (3 GiB); 18 bytes arrive.
# Within 1 GiB of address space the reader must report the truncation, not try to
# allocate what the header claims first
rm -f tests/tmp/pipe.pfm
if mkfifo tests/tmp/pipe.pfm 2>/dev/null; then
    (printf 'PF\n16384 16384\n-1\n' > tests/tmp/pipe.pfm &)
    expect "robust_pfm_pipe" 1 "truncated: 16384x16384 pixels need 3221225472 bytes of data, the stream has 0" \
        sh -c 'ulimit -v 1048576; exec ./specnee merge --equal-weights tests/tmp/pipe.pfm -o tests/tmp/pipe-out.pfm'
    rm -f tests/tmp/pipe.pfm
else
    skip "robust_pfm_pipe: no mkfifo"
fi
expect "robust_res_budget" 2 "memory budget" ./specnee --res 16384x16384 scenes/cornell.pbrt
# every input that ever crashed a fuzz target (fuzz/regress) and the fuzz seeds
for t in scene ply pfm spectrum png exr nvdb gzip measured; do
    mkdir -p tests/tmp/replay-$t
    counted replay-$t fuzz/replay $t tests/tmp/replay-$t fuzz/seeds/$t/* $(ls fuzz/regress/$t/* 2>/dev/null)
done

# the factorial evaluation in miniature (tools/factorial.sh, tools/factor_table.sh):
# one small scene, 2 x 2 x 2 levels, 2 seeds, spp 1 and 2; the factor table must
# name every non-reference level with a finite gain and list all 8 configurations
rm -rf tests/tmp/factorial
if SCENES=wl-filter SEEDS=2 LADDER=1,2 WAVELENGTHS="uniform visible" SELECTIONS="spatial product" \
       OUT=tests/tmp/factorial sh tools/factorial.sh > tests/tmp/factorial.txt 2>&1 &&
   grep -q '^| wavelengths | visible (vs uniform) | [0-9.]* \[[0-9.]*, [0-9.]*\] |' tests/tmp/factorial/factors.md &&
   grep -q '^| selection | product (vs spatial) |' tests/tmp/factorial/factors.md &&
   grep -q '^| rough dispersion | mis (vs terminate) |' tests/tmp/factorial/factors.md &&
   [ "$(grep -c '^| spatial:\|^| product:' tests/tmp/factorial/factors.md)" -eq 8 ] &&
   ! grep -qi 'nan\|inf' tests/tmp/factorial/factors.md; then ok "factorial_smoke"
else fail "factorial_smoke"; tail -n 5 tests/tmp/factorial.txt; fi

# a sampler that is not progressive (zsobol): converge renders its rungs one by one and says so
expect "eval_converge_not_progressive" 0 "zsobol sampler is not progressive" ./specnee converge scenes/cornell-glass.pbrt \
    --ref docs/ref/cornell-glass.pfm --lights spatial,spatial:zsobol --spp 1,2 --seeds 2 --out tests/tmp/smoke-z
# the docs call nothing the default that the binary does not do by default
# (--print-defaults; the script plants stale claims first and must report them)
expect "cli_print_defaults" 0 "" ./specnee --print-defaults
if grep -qx "lights spectral-tree" tests/tmp/out.txt && grep -qx "wavelengths mixture" tests/tmp/out.txt &&
   ./specnee --preset thesis --print-defaults | grep -qx "rough-dispersion terminate"; then ok "cli_print_defaults_lines"
else fail "cli_print_defaults_lines"; fi
counted docs-defaults sh tests/docs_defaults.sh
# docs/coverage.md, the table of pbrt-v4's whole format, says what the binary and the
# builders do: each row tried on a tiny scene, each type's reads and each getter listed
counted coverage sh tests/coverage.sh
# with a scene, --print-defaults prints what that scene renders with: its Film,
# Sampler and Integrator (cornell.pbrt: 256x256, 64 spp, maxdepth 8) under the flags
expect "cli_print_defaults_scene" 0 "" ./specnee scenes/cornell.pbrt --maxdepth 3 --print-defaults
if grep -qx "spp 64" tests/tmp/out.txt && grep -qx "maxdepth 3" tests/tmp/out.txt &&
   grep -qx "res 256x256" tests/tmp/out.txt && ! grep -q "^spp 16$" tests/tmp/out.txt; then ok "cli_print_defaults_scene_lines"
else fail "cli_print_defaults_scene_lines: $(tr '\n' ' ' < tests/tmp/out.txt)"; fi
# --spd-metric and --spd-wavelengths hero/all act on the thesis' spectral tables
# only: --print-defaults says so for the strategy in use, and under the default
# spectral-tree a render with them changed is the same image
./specnee --print-defaults > tests/tmp/pd-tree.txt
./specnee --lights product --print-defaults > tests/tmp/pd-product.txt
./specnee -q scenes/cornell1.pbrt --spp 2 --res 16x16 -o tests/tmp/spd-a.pfm
./specnee -q scenes/cornell1.pbrt --spp 2 --res 16x16 --spd-metric power --spd-wavelengths all -o tests/tmp/spd-b.pfm
if grep -q "^spd-metric unit .*ignored by spectral-tree" tests/tmp/pd-tree.txt &&
   grep -q "^spd-metric unit  # read by --lights spd, product, spectral-spatial$" tests/tmp/pd-product.txt &&
   cmp -s tests/tmp/spd-a.pfm tests/tmp/spd-b.pfm; then ok "cli_spd_flags_marked_where_ignored"
else fail "cli_spd_flags_marked_where_ignored"; fi
# the output path is checked before any sample is traced: 10^6 spp would take
# hours, the error comes at once (exit 1, one line naming the path); `timeout`
# (where installed) ends a binary that renders first after 60 s
rm -rf tests/tmp/no-such-dir
tmo=""; command -v timeout > /dev/null 2>&1 && tmo="timeout 60"
t0=$(date +%s)
expect "cli_output_dir_missing" 1 "^tests/tmp/no-such-dir/out.png: cannot write: the directory tests/tmp/no-such-dir does not exist" \
    $tmo ./specnee -q scenes/cornell.pbrt --spp 1000000 -o tests/tmp/no-such-dir/out.png
if [ $(($(date +%s) - t0)) -le 5 ] && [ "$(wc -l < tests/tmp/err.txt)" -eq 1 ]; then ok "cli_output_dir_missing_at_once"
else fail "cli_output_dir_missing_at_once: $(($(date +%s) - t0)) s, $(wc -l < tests/tmp/err.txt) lines"; fi
expect "cli_output_bad_format_at_once" 1 "tests/tmp/out.jpg: unsupported output format '.jpg'" \
    $tmo ./specnee -q scenes/cornell.pbrt --spp 1000000 -o tests/tmp/out.jpg
printf 'Film "rgb" "integer xresolution" 4 "integer yresolution" 4 "string filename" "tests/tmp/no-such-dir/film.pfm"\nSampler "independent" "integer pixelsamples" 1000000\nWorldBegin\nShape "sphere"\n' > tests/tmp/filmdir.pbrt
expect "cli_output_film_dir_missing" 1 "^tests/tmp/no-such-dir/film.pfm: cannot write: the directory" $tmo ./specnee -q tests/tmp/filmdir.pbrt
mkdir -p tests/tmp/a-dir.png
expect "cli_output_is_directory" 1 "^tests/tmp/a-dir.png: cannot write: it is a directory" $tmo ./specnee -q scenes/cornell.pbrt --spp 1000000 -o tests/tmp/a-dir.png
# Film "spectral" writes an OpenEXR file (its magic number); any other output is refused at once
printf 'Film "spectral" "integer xresolution" 4 "integer yresolution" 4 "integer nbuckets" 2 "string filename" "tests/tmp/spec.exr"\nSampler "independent" "integer pixelsamples" 4\nWorldBegin\nLightSource "infinite"\n' > tests/tmp/spec.pbrt
rm -f tests/tmp/spec.exr
expect "cli_spectral_film" 0 "" ./specnee -q tests/tmp/spec.pbrt
if [ "$(od -An -tx1 -N4 tests/tmp/spec.exr 2>/dev/null | tr -d ' \n')" = "762f3101" ]; then ok "cli_spectral_film_exr_written"
else fail "cli_spectral_film_exr_written: tests/tmp/spec.exr is no OpenEXR file"; fi
expect "cli_spectral_film_not_exr" 1 '^tests/tmp/spec.pbrt:1: Film "spectral": "tests/tmp/x.pfm": pbrt-v4 writes the spectral film as .exr only' \
    $tmo ./specnee -q tests/tmp/spec.pbrt --spp 1000000 -o tests/tmp/x.pfm
# converge compares wavelength strategies, which the spectral film does not use
expect "cli_spectral_film_converge_refused" 1 'Film "spectral" fixes the wavelengths' \
    ./specnee converge tests/tmp/spec.pbrt --ref tests/tmp/spec.exr --spp 1,2
# the code, the tests and the docs describe the program as it is; history lives
# in git log (tests/history-allow.txt: the files not cleaned yet)
counted docs-history sh tests/docs_history.sh
# every block of tests/mutants.txt still applies to its file: a moved or rewritten
# line fails here, not as BROKEN in the next `make mutants`
if sh tools/mutants_check.sh > tests/tmp/mutants-check.txt 2>&1; then ok "mutants_apply"
else fail "mutants_apply: $(grep -v '^mutants_check' tests/tmp/mutants-check.txt | head -n 3 | tr '\n' ' ')"; fi
# golden images (bit-exact with this binary) and every command of the walkthrough
counted golden sh tests/golden.sh
counted walkthrough sh tests/walkthrough.sh

full=0
[ "$strict" = 1 ] && full=1
[ "${SPECNEE_FULL:-0}" = 1 ] && full=1
[ "${SPECNEE_QUICK:-0}" = 1 ] && [ "$strict" != 1 ] && full=0
if [ "$full" != 1 ]; then
    echo "note: steps 3-5 (gcc, clang and tcc with -Werror, ASan + UBSan) not run: SPECNEE_FULL=1 make test runs them, CI runs them strict"
fi
if [ "$full" = 1 ]; then
    # ---- 3. three compilers, warnings are errors (each one that is installed)
    LIBSRC="util.c sampler.c bvh.c bvhbuild.c hitpoint.c instance.c motion.c shapes.c patch.c curve.c spectrum.c wavelengths.c metals.c lights.c arealight.c sphtri.c lighttree.c infinite.c delta.c texture.c filter.c parser.c options.c scene.c geometry.c dump.c ply.c displace.c subdiv.c medium.c equiangular.c nanovdb.c material.c microfacet.c conductor.c layered.c hair.c measured.c subsurface.c bump.c camera.c lens.c path.c sensor.c render.c image.c png.c exr.c svg.c cmd_converge.c cmd_image.c cmd_spectrum.c rgbfit.c rgbtable.c"
    proven=""
    for cc in gcc clang tcc; do
        if ! have_cc $cc; then skip "build_$cc: $cc not installed (CI proves it)"; continue; fi
        flags="-std=c99 -pedantic -Wall -Wextra -Werror -O2 $(sh tools/ccflags.sh $cc)"
        [ $cc = tcc ] && flags="-std=c99 -Wall -Werror -O2"
        # the binary and the runner compile at once, one on each of two cores
        $cc $flags -I. -o build/specnee-$cc specnee.c $LIBSRC -lm > "$log.$cc-bin" 2>&1 &
        bin_pid=$!
        $cc $flags -I. -o build/runner-$cc tests/*.c $LIBSRC -lm > "$log.$cc-runner" 2>&1
        runner_rc=$?
        wait $bin_pid
        bin_rc=$?
        cat "$log.$cc-bin" "$log.$cc-runner" >> "$log"
        if [ $bin_rc -eq 0 ] && [ $runner_rc -eq 0 ]; then
            ok "build_$cc (no warnings)"
            proven="$proven $cc"
            [ $cc = gcc ] || counted $cc env SPECNEE_TEST_SCALE=0.25 build/runner-$cc
            # the goldens rendered by this compiler, within the noise-derived tolerance
            [ $cc = gcc ] || counted golden-$cc env SPECNEE_BIN=build/specnee-$cc sh tests/golden.sh --tolerant --no-selftest
        else
            fail "build_$cc"; tail -n 15 "$log"
        fi
    done
    # which compiler built step 1 (the Makefile's choice: cc, else gcc, clang, tcc)?
    # Another one proven above is "a second compiler"
    for defcc in cc gcc clang tcc; do have_cc $defcc && break; done
    if echo __clang__ __TINYC__ | $defcc -E - 2>/dev/null | grep -q '^1 __TINYC__'; then cckind=clang
    elif echo __clang__ __TINYC__ | $defcc -E - 2>/dev/null | grep -q '__clang__ 1'; then cckind=tcc
    else cckind=gcc; fi
    second=0
    for c in $proven; do [ $c = $cckind ] || second=1; done
    [ $second = 1 ] || echo "note: no second compiler was available: only cc ($cckind) was proven (CI installs clang and tcc)"
    # ---- 4. sanitizers (gcc or clang, whichever links them)
    acc=$(asan_cc)
    replay_rc=1
    if [ -n "$acc" ]; then
        # the fuzz replayer compiles on the second core while the runner compiles
        $acc -std=c99 -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all \
            -fno-omit-frame-pointer -I. -o build/replay-asan fuzz/replay.c fuzz/targets.c \
            $LIBSRC -lm > "$log.replay-asan" 2>&1 &
        replay_pid=$!
    fi
    if [ -z "$acc" ]; then
        skip "build_asan: no compiler here links -fsanitize=address,undefined (CI proves it)"
    elif $acc -std=c99 -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer \
           -I. -o build/runner-asan tests/*.c $LIBSRC -lm >> "$log" 2>&1; then
        ok "build_asan ($acc)"
        counted asan env SPECNEE_TEST_SCALE=0.25 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
            UBSAN_OPTIONS=print_stacktrace=1 build/runner-asan
    else
        fail "build_asan ($acc)"; tail -n 15 "$log"
    fi
    # the fuzz inputs (fuzz/regress, fuzz/seeds) under the same sanitizers
    if [ -n "$acc" ]; then
        wait $replay_pid
        replay_rc=$?
        cat "$log.replay-asan" >> "$log"
        if [ $replay_rc -eq 0 ]; then
            for t in scene ply pfm spectrum png exr nvdb gzip measured; do
                counted replay-asan-$t env ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
                    UBSAN_OPTIONS=print_stacktrace=1 build/replay-asan $t tests/tmp/replay-$t \
                    fuzz/seeds/$t/* $(ls fuzz/regress/$t/* 2>/dev/null)
            done
        else
            fail "build_replay_asan ($acc)"; tail -n 15 "$log"
        fi
    fi
    # ---- 5. the runner itself: with clang and tcc hidden from PATH the probe
    # skips them and exits 0; under SPECNEE_STRICT=1 the same probe fails
    nopath=tests/tmp/nopath
    rm -rf "$nopath"; mkdir -p "$nopath"
    IFS_save=$IFS; IFS=:
    for d in $PATH; do
        [ -d "$d" ] || continue
        for f in "$d"/*; do
            b=${f##*/}
            case "$b" in clang*|tcc*) continue ;; esac
            [ -x "$f" ] && [ ! -e "$nopath/$b" ] && ln -s "$f" "$nopath/$b"
        done
    done
    IFS=$IFS_save
    PATH="$PWD/$nopath" SPECNEE_STRICT=0 sh tests/run.sh --probe > tests/tmp/probe.txt 2>&1
    rc=$?
    if [ $rc -eq 0 ] && grep -q '^skip build_tcc: tcc not installed (CI proves it)' tests/tmp/probe.txt &&
       grep -q '^skip build_clang: clang not installed' tests/tmp/probe.txt &&
       grep -q 'passed, 0 failed, [1-9][0-9]* skipped$' tests/tmp/probe.txt; then
        ok "runner_skips_missing_compilers"
    else fail "runner_skips_missing_compilers (rc $rc)"; cat tests/tmp/probe.txt; fi
    PATH="$PWD/$nopath" SPECNEE_STRICT=1 sh tests/run.sh --probe > tests/tmp/probe-strict.txt 2>&1
    rc=$?
    if [ $rc -ne 0 ] && grep -q '^FAIL build_tcc: tcc not installed .*SPECNEE_STRICT=1' tests/tmp/probe-strict.txt; then
        ok "runner_strict_fails_missing_compilers"
    else fail "runner_strict_fails_missing_compilers (rc $rc)"; cat tests/tmp/probe-strict.txt; fi
fi

echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ]
