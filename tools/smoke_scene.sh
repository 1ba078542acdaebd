#!/bin/sh
# tools/smoke_scene.sh - writes the coloured-smoke scene (scenes/smoke.pbrt is its
# default output) and its family for the measurements of docs/media.md.
#
#   sh tools/smoke_scene.sh [--spread K] [--res N] [--spp S] [--grid G] > scene.pbrt
#
# A G^3 "rgbgrid" (default 16^3) over the box [-1, 1]^3: three Gaussian puffs,
# rippled by a product of sines, give the density d(x) in [0, 1] (a sample below
# 0.02 is 0, so the puffs sit in empty space).  Every sample has the same colour:
# sigma_t = 4 d (K^-1/2, 1, K^1/2) in RGB, so the blue sigma_t is K times the red one
# (--spread K, default 4; K = 1 is grey smoke), with the same geometric mean for
# every K, and albedo 0.85 in every band (sigma_s = 0.85 sigma_t, sigma_a = 0.15
# sigma_t).  The smoke scatters blue light more than red: lit from above it looks
# bluish where thin, and the light it lets through onto the grey floor is reddish.
# An area light above, a dim sky, a grey floor; film N x N (default 96), S spp
# (default 64), maxdepth 10.  Both renderers read it (pbrt-v4's rgbgrid).
set -u
spread=4
res=96
spp=64
grid=16
while [ $# -gt 0 ]; do
    case "$1" in
        --spread) spread=$2; shift 2 ;;
        --res) res=$2; shift 2 ;;
        --spp) spp=$2; shift 2 ;;
        --grid) grid=$2; shift 2 ;;
        *) echo "usage: sh tools/smoke_scene.sh [--spread K] [--res N] [--spp S] [--grid G]" >&2; exit 2 ;;
    esac
done
awk -v k="$spread" -v res="$res" -v spp="$spp" -v n="$grid" '
function puff(x, y, z, cx, cy, cz, r) { return exp(-((x-cx)^2 + (y-cy)^2 + (z-cz)^2) / (r * r)) }
function f(v) { return sprintf("%.3g", v) }
BEGIN {
    print "# scenes/smoke.pbrt - coloured smoke: a heterogeneous chromatic medium (pbrt-v4'"'"'s \"rgbgrid\")"
    print "# written by tools/smoke_scene.sh --spread " k " --res " res " --spp " spp " --grid " n "."
    print "# Three puffs of smoke in a " n "^3 grid whose extinction is " k " times larger in blue than in red"
    print "# (albedo 0.85): lit from above it is bluish where thin, and the light it lets through is"
    print "# reddish.  Free flight by delta tracking against the majorant grid, the four hero wavelengths"
    print "# weighted by spectral MIS over null collisions (docs/THEORY.md section 13, docs/media.md);"
    print "# compare --chromatic-media terminate.  docs/media.md measures this scene and its family"
    print "# (--spread 1, 2, 4, 8) against pbrt-v4 and against termination."
    print "# golden: skip a demonstration and measurement scene of docs/media.md; tests/test_grid.c checks rgbgrid against pbrt-v4 and closed forms"
    print "LookAt 0 0.6 4.2  0 -0.1 0  0 1 0"
    print "Camera \"perspective\" \"float fov\" [ 40 ]"
    printf "Film \"rgb\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ] \"string filename\" \"smoke.pfm\"\n", res, res
    printf "Sampler \"sobol\" \"integer pixelsamples\" [ %d ]\n", spp
    print "Integrator \"volpath\" \"integer maxdepth\" [ 10 ]"
    print "WorldBegin"
    print "LightSource \"infinite\" \"rgb L\" [ 0.05 0.06 0.08 ]"
    print "AttributeBegin"
    print "  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"float scale\" 10"
    print "  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]"
    print "    \"point3 P\" [ -1 3 -1  1 3 -1  1 3 1  -1 3 1 ]"
    print "AttributeEnd"
    print "AttributeBegin"
    print "  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]"
    print "  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]"
    print "    \"point3 P\" [ -10 -1 -10  10 -1 -10  10 -1 10  -10 -1 10 ]"
    print "AttributeEnd"
    rs = 4 / sqrt(k); gs = 4; bs = 4 * sqrt(k)
    sa = ""; ss = ""
    for (kz = 0; kz < n; kz++) for (jy = 0; jy < n; jy++) for (ix = 0; ix < n; ix++) {
        x = -1 + 2 * (ix + 0.5) / n; y = -1 + 2 * (jy + 0.5) / n; z = -1 + 2 * (kz + 0.5) / n
        d = puff(x, y, z, 0, -0.35, 0, 0.45) + 0.8 * puff(x, y, z, -0.35, 0.15, -0.1, 0.35) \
            + 0.7 * puff(x, y, z, 0.3, 0.35, 0.15, 0.3)
        d *= 0.8 + 0.2 * sin(9 * x + 1) * sin(7 * y + 2) * sin(8 * z + 3)
        if (d > 1) d = 1
        if (d < 0.02) { sa = sa " 0 0 0"; ss = ss " 0 0 0"; continue }
        sa = sa " " f(0.15 * d * rs) " " f(0.15 * d * gs) " " f(0.15 * d * bs)
        ss = ss " " f(0.85 * d * rs) " " f(0.85 * d * gs) " " f(0.85 * d * bs)
    }
    print "AttributeBegin"
    print "  Rotate 20 0 1 0"
    printf "  MakeNamedMedium \"smoke\" \"string type\" \"rgbgrid\" \"float g\" 0.3\n"
    printf "    \"integer nx\" %d \"integer ny\" %d \"integer nz\" %d\n", n, n, n
    print "    \"rgb sigma_a\" [" sa " ]"
    print "    \"rgb sigma_s\" [" ss " ]"
    print "    \"point3 p0\" [ -1 -1 -1 ] \"point3 p1\" [ 1 1 1 ]"
    print "AttributeEnd"
    print "AttributeBegin"
    print "  Material \"interface\""
    print "  MediumInterface \"smoke\" \"\""
    print "  Shape \"sphere\" \"float radius\" 1.75"
    print "AttributeEnd"
}'
