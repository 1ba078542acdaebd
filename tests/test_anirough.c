/* tests/test_anirough.c - anisotropic textured roughness: "texture uroughness"
   and "texture vroughness" of different textures (or a texture and a number) on
   conductor, coateddiffuse and coatedconductor (its interface.* and conductor.*)
   (parser.c microfacet_roughness; material.c mat_point, mat_needs_tangent,
   mat_is_delta).

   Checked: two constant textures render the image of the two numbers they hold,
   bit for bit, on each material and for each mix of a texture and a number, and
   swapping them changes the image (the axes are not merged); a number out of
   range beside a texture is refused at its file:line (test_dielrough.c checks
   the anisotropic dielectric); pbrt-v4's image of a conductor with a bilerp u
   roughness and a constant v roughness, frozen. */
#include "test.h"
#include <string.h>

static const char *const AR_HEAD =
    "LookAt 2 2 8  2 2 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 28 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
    "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 4 ]\nWorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] "
    "\"point3 to\" [ 2 2 0 ]\nLightSource \"infinite\" \"rgb L\" [ 0.2 0.3 0.4 ]\n"
    "Texture \"a\" \"float\" \"constant\" \"float value\" [ 0.02 ]\n"
    "Texture \"b\" \"float\" \"constant\" \"float value\" [ 0.3 ]\n";
/* u runs along y here: dp/du, the anisotropic frame's s axis, is not the x axis
   that a frame built from the normal alone would take */
static const char *const AR_SQUARE =
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 0  4 0 0  4 4 0  0 4 0 ] "
    "\"point2 uv\" [ 0 0  0 1  1 1  1 0 ]\n";

/* The image of AR_HEAD, the material line mat and AR_SQUARE at 4 spp. */
static int ar_render(T *t, const char *mat, Image *im)
{
    char buf[2048];
    RenderOptions o;
    render_options_default(&o);
    o.spp = 4;
    snprintf(buf, sizeof buf, "%s%s\n%s", AR_HEAD, mat, AR_SQUARE);
    return test_render_text(t, buf, &o, im);
}

static int ar_same(const Image *a, const Image *b)
{
    return a->w == b->w && a->h == b->h &&
           memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * (size_t)a->h) == 0;
}

static void test_anirough_constant(T *t)
{
    /* { with textures, with the numbers they hold, u and v swapped } */
    static const char *const c[][3] = {
        { "Material \"conductor\" \"texture uroughness\" \"a\" \"texture vroughness\" \"b\"",
          "Material \"conductor\" \"float uroughness\" 0.02 \"float vroughness\" 0.3",
          "Material \"conductor\" \"texture uroughness\" \"b\" \"texture vroughness\" \"a\"" },
        { "Material \"conductor\" \"texture uroughness\" \"a\" \"float vroughness\" 0.3",
          "Material \"conductor\" \"float uroughness\" 0.02 \"float vroughness\" 0.3",
          "Material \"conductor\" \"float uroughness\" 0.3 \"texture vroughness\" \"a\"" },
        { "Material \"conductor\" \"texture roughness\" \"b\" \"texture uroughness\" \"a\"",
          "Material \"conductor\" \"float uroughness\" 0.02 \"float vroughness\" 0.3",
          "Material \"conductor\" \"texture roughness\" \"b\" \"texture vroughness\" \"a\"" },
        /* u: "roughness" 0, a smooth axis beside a rough one (not a delta material;
           its f vanishes where wm leaves the (y, z) plane, so no swap is compared) */
        { "Material \"conductor\" \"texture vroughness\" \"b\"",
          "Material \"conductor\" \"float vroughness\" 0.3", NULL },
        { "Material \"coateddiffuse\" \"texture uroughness\" \"a\" \"texture vroughness\" \"b\"",
          "Material \"coateddiffuse\" \"float uroughness\" 0.02 \"float vroughness\" 0.3",
          "Material \"coateddiffuse\" \"texture uroughness\" \"b\" \"texture vroughness\" \"a\"" },
        { "Material \"coatedconductor\" \"texture interface.uroughness\" \"a\" "
          "\"texture interface.vroughness\" \"b\" \"float conductor.roughness\" 0.1",
          "Material \"coatedconductor\" \"float interface.uroughness\" 0.02 "
          "\"float interface.vroughness\" 0.3 \"float conductor.roughness\" 0.1",
          "Material \"coatedconductor\" \"texture interface.uroughness\" \"b\" "
          "\"texture interface.vroughness\" \"a\" \"float conductor.roughness\" 0.1" },
        { "Material \"coatedconductor\" \"texture conductor.uroughness\" \"a\" "
          "\"texture conductor.vroughness\" \"b\" \"float interface.eta\" 1.2",
          "Material \"coatedconductor\" \"float conductor.uroughness\" 0.02 "
          "\"float conductor.vroughness\" 0.3 \"float interface.eta\" 1.2",
          "Material \"coatedconductor\" \"texture conductor.uroughness\" \"b\" "
          "\"texture conductor.vroughness\" \"a\" \"float interface.eta\" 1.2" },
        { "Material \"conductor\" \"texture uroughness\" \"a\" \"texture vroughness\" \"b\" "
          "\"bool remaproughness\" false",
          "Material \"conductor\" \"float uroughness\" 0.02 \"float vroughness\" 0.3 "
          "\"bool remaproughness\" false",
          "Material \"conductor\" \"texture uroughness\" \"b\" \"texture vroughness\" \"a\" "
          "\"bool remaproughness\" false" },
    };
    int i;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        Image a, b, sw;
        if (!ar_render(t, c[i][0], &a)) return;
        if (!ar_render(t, c[i][1], &b)) { img_free(&a); return; }
        CHECK(t, ar_same(&a, &b), "case %d: the textures' image differs from the numbers' (Y %.6f, %.6f)",
              i, test_image_y(&a), test_image_y(&b));
        img_free(&b);
        if (c[i][2] && ar_render(t, c[i][2], &sw)) {
            CHECK(t, !ar_same(&a, &sw), "case %d: u and v swapped renders the same image (Y %.6f)", i,
                  test_image_y(&a));
            img_free(&sw);
        }
        img_free(&a);
    }
}

/* A sphere computes (u, v) at its hits for a material whose only texture is
   one axis's roughness (scene.c reads_uv, material.c mat_reads_uv); two textured
   axes build the dp/du frame (mat_needs_tangent); a number below 1e-3 beside a
   textured axis is no delta material (pbrt-v4 decides EffectivelySmooth per hit,
   from both alphas). */
static void test_anirough_flags(T *t)
{
    static const char *const mat[3] = {
        "Material \"conductor\" \"texture vroughness\" \"b\"",
        "Material \"coatedconductor\" \"texture conductor.vroughness\" \"b\"",
        "Material \"coateddiffuse\" \"texture vroughness\" \"b\"",
    };
    char buf[2048];
    Scene s;
    int i;
    for (i = 0; i < 3; i++) {
        const Material *m;
        snprintf(buf, sizeof buf, "%s%s\nShape \"sphere\"\n", AR_HEAD, mat[i]);
        if (!test_load_scene(t, &s, buf)) return;
        m = &s.materials[s.shapes[0].material];
        CHECK(t, s.n_shapes == 1 && s.shapes[0].reads_uv, "%s: the sphere reads no (u, v)", mat[i]);
        CHECK(t, mat_needs_tangent(m) && !mat_is_delta(m), "%s: needs a tangent %d, delta %d", mat[i],
              mat_needs_tangent(m), mat_is_delta(m));
        scene_free(&s);
    }
}

static void test_anirough_errors(T *t)
{
    test_rejected_at(t, "WorldBegin\nTexture \"a\" \"float\" \"constant\"\n"
                     "Material \"conductor\" \"texture uroughness\" \"a\"\n  \"float vroughness\" -1\n", 3,
                     "Material \"conductor\": roughness (0, -1) must be within [0, 1e4]", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"a\" \"float\" \"constant\"\n"
                     "Material \"coatedconductor\" \"texture conductor.vroughness\" \"a\" "
                     "\"float conductor.uroughness\" 2e4\n", 3,
                     "conductor.roughness (20000, 0) must be within [0, 1e4]", NULL);
}

/* A 4 x 4 square, its uv the unit square, of the default conductor (copper) with
   "texture uroughness" a bilerp of 0.01, 0.3, 0.1, 0.02 (v00, v10, v01, v11) and
   "texture vroughness" a constant 0.05, lit by a distant light from (1, 0.5, 4)
   towards (2, 2, 0), path maxdepth 1, box filter, 48 x 48.  pbrt-v4 (commit
   5f7a6068, `pbrt --seed S --spp 256`, S = 1..8, the independent sampler): the
   4 x 4 tiles' luminance, top row first, mean and standard error over the seeds.
   specnee at 4 x 256 spp: within 0.05 % of every tile.  (A checkerboard u
   roughness agrees as well away from the checks' edges; on the pixels along an
   edge pbrt-v4 box-filters the checkerboard over the pixel's footprint, which
   specnee has no ray differentials for: up to 30 % there, 1-3 % of a tile.) */
static const double PBRT_ANI_TILES[16][2] = {
    { 0.37151, 0.00003 }, { 0.44526, 0.00002 }, { 0.48736, 0.00005 }, { 0.49855, 0.00004 },
    { 0.52167, 0.00004 }, { 0.62226, 0.00005 }, { 0.74788, 0.00005 }, { 0.88467, 0.00008 },
    { 0.74315, 0.00003 }, { 0.90465, 0.00005 }, { 1.16302, 0.00010 }, { 1.61119, 0.00007 },
    { 1.01180, 0.00008 }, { 1.24444, 0.00013 }, { 1.67664, 0.00008 }, { 2.83074, 0.00032 },
};

static void test_anirough_against_pbrt(T *t)
{
    static const char *const text =
        "LookAt 2 2 8  2 2 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 28 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ]\n"
        "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
        "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 2 2 0 ]\n"
        "Texture \"g\" \"float\" \"bilerp\" \"float v00\" [ 0.01 ] \"float v10\" [ 0.3 ] "
        "\"float v01\" [ 0.1 ] \"float v11\" [ 0.02 ]\n"
        "Texture \"c\" \"float\" \"constant\" \"float value\" [ 0.05 ]\n"
        "Material \"conductor\" \"texture uroughness\" \"g\" \"texture vroughness\" \"c\"\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 0  4 0 0  4 4 0  0 4 0 ] "
        "\"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    if (!test_render_tiles(t, &s, &o, 4, 4, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    for (i = 0; i < 16; i++) {
        double Y = test_luminance(tl.mean[i]);
        double Yp = PBRT_ANI_TILES[i][0], se = tl.se[i][1], sep = PBRT_ANI_TILES[i][1];
        if (getenv("DBG")) fprintf(stderr, "anisotropic tile %d: specnee %.5f +- %.2g, pbrt %.5f\n", i, Y, se, Yp);
        CHECK(t, fabs(Y - Yp) < TEST_K_SIGMA * sqrt(se * se + sep * sep) + 1e-2 * Yp,
              "anisotropic textured conductor: tile %d: specnee Y %.5f +- %.2g, pbrt-v4 %.5f +- %.2g",
              i, Y, se, Yp, sep);
    }
}

const TestCase tests_anirough[] = {
    { "anirough_constant", test_anirough_constant },
    { "anirough_flags", test_anirough_flags },
    { "anirough_errors", test_anirough_errors },
    { "anirough_against_pbrt", test_anirough_against_pbrt },
    { NULL, NULL }
};
