#!/bin/sh
# tools/gen_spheres.sh - write a pbrt-v4 scene of N small emissive spheres, each
# with its own "rgb L", in a closed 10 m room filled with a thin homogeneous fog:
# the load-time and memory benchmark of docs/loading.md (many distinct RGB
# emitters, the case where RGB -> spectrum upsampling dominates loading).
#
# Usage: sh tools/gen_spheres.sh N [SEED [material|plain]] > spheres.pbrt
# With "material" every sphere also gets its own Material "diffuse" with its own
# "rgb reflectance" (a Material directive per object, as exporters write them).
# With "plain" the N spheres do not emit (the room's diffuse material) and one
# sphere lamp at the centre lights them: the curve over primitives.
# Deterministic: the same arguments (SEED default 1) give the same file (a linear
# congruential generator in awk, no rand()), so specnee and pbrt-v4 read the
# same bytes.  Both renderers read the output.
set -eu
n=${1:?usage: sh tools/gen_spheres.sh N [SEED [material]]}
seed=${2:-1}
mat=0
case ${3:-} in material) mat=1;; plain) mat=2;; '') ;; *) echo "gen_spheres.sh: the third argument can only be 'material' or 'plain'" >&2; exit 2;; esac
case $n in *[!0-9]*|'') echo "gen_spheres.sh: N must be a non-negative integer" >&2; exit 2;; esac
case $seed in *[!0-9]*|'') echo "gen_spheres.sh: SEED must be a non-negative integer" >&2; exit 2;; esac
awk -v n="$n" -v seed="$seed" -v mat="$mat" '
function rnd() {                      # LCG mod 2^31 (exact in doubles), in [0, 1)
    state = (state * 1103515245 + 12345) % 2147483648
    return state / 2147483648
}
BEGIN {
    state = seed % 2147483648
    printf "# %d %sspheres in a fog room (tools/gen_spheres.sh %d %d%s)\n", n, mat == 2 ? "" : "emissive ", n, seed, mat == 1 ? " material" : mat == 2 ? " plain" : ""
    print "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\""
    print "    \"rgb sigma_a\" [ 0.01 0.01 0.01 ] \"rgb sigma_s\" [ 0.05 0.06 0.08 ]"
    print "    \"float g\" [ 0.2 ]"
    print "MediumInterface \"\" \"fog\""
    print "LookAt 0 0 9  0 0 0  0 1 0"
    print "Camera \"perspective\" \"float fov\" [ 60 ]"
    print "Film \"rgb\" \"string filename\" [ \"spheres.exr\" ]"
    print "     \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ]"
    print "Sampler \"independent\" \"integer pixelsamples\" [ 1 ]"
    print "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]"
    print "WorldBegin"
    print "MediumInterface \"\" \"\""
    print "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]"
    # the room: six inward-facing quads of a 20 m cube centred at the origin
    print "Shape \"trianglemesh\" \"integer indices\" ["
    print "    0 1 2  0 2 3   4 6 5  4 7 6   0 4 5  0 5 1   3 2 6  3 6 7   0 3 7  0 7 4   1 5 6  1 6 2 ]"
    print "  \"point3 P\" [ -10 -10 -10  10 -10 -10  10 10 -10  -10 10 -10"
    print "              -10 -10 10  10 -10 10  10 10 10  -10 10 10 ]"
    if (mat == 2) {
        print "AttributeBegin"
        print "  AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]"
        print "  Shape \"sphere\" \"float radius\" [ 0.5 ]"
        print "AttributeEnd"
    }
    for (i = 0; i < n; i++) {
        x = -8 + 16 * rnd(); y = -8 + 16 * rnd(); z = -8 + 16 * rnd()
        r = 0.02 + 0.08 * rnd()
        printf "AttributeBegin\n"
        if (mat == 1)
            printf "  Material \"diffuse\" \"rgb reflectance\" [ %.4f %.4f %.4f ]\n", rnd(), rnd(), rnd()
        if (mat != 2)
            printf "  AreaLightSource \"diffuse\" \"rgb L\" [ %.4f %.4f %.4f ]\n", 4 * rnd(), 4 * rnd(), 4 * rnd()
        printf "  Translate %.4f %.4f %.4f\n", x, y, z
        printf "  Shape \"sphere\" \"float radius\" [ %.4f ]\n", r
        printf "AttributeEnd\n"
    }
}'
