/* tests/test_bilerp.c - pbrt-v4's "bilerp" texture, float and spectrum
   (texture.c section 2, TEX_BILERP).

   Checked: the value at the four corners of (s, t) is v00, v10, v01, v11
   (pbrt-v4's order: v10 at s = 1, t = 0), bit for bit, and at the centre their
   mean; any point is (1 - s)(1 - t) v00 + s (1 - t) v10 + (1 - s) t v01 + s t v11,
   also beyond the unit square (not clamped); the defaults (0, 1, 0, 1: the value
   is t); the 2-D mapping's scales and offsets and the planar mapping; a spectrum
   bilerp interpolates its corners' spectra wavelength by wavelength; a diffuse
   reflectance that extrapolates above 1 or below 0 is clamped to [0, 1], as
   pbrt-v4's DiffuseMaterial clamps it; the refusals at their file:line; pbrt-v4's
   image frozen. */
#include "test.h"
#include <string.h>

static const char *const BILERP_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 50 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n";

static int load_bilerp(T *t, Scene *s, const char *body)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", BILERP_HEAD, body);
    return test_load_scene(t, s, buf);
}

/* Texture i of s at (u, v) (and the point p, for the planar mapping). */
static float at(const Scene *s, int i, float u, float v, Vec3 p, float lambda)
{
    SurfacePoint sp;
    memset(&sp, 0, sizeof sp);
    sp.u = u;
    sp.v = v;
    sp.p = p;
    sp.ng = sp.ns = v3(0.0f, 0.0f, 1.0f);
    return tex_eval(s->textures, i, &sp, lambda);
}

/* The bilinear formula in double. */
static double bilerp_ref(double s, double t, double v00, double v01, double v10, double v11)
{
    return (1 - s) * (1 - t) * v00 + s * (1 - t) * v10 + (1 - s) * t * v01 + s * t * v11;
}

static void test_bilerp_float(T *t)
{
    static const float pts[5][2] = { { 0.3f, 0.7f }, { 0.9f, 0.15f }, { 1.5f, 0.5f }, { -0.5f, 2.0f },
                                     { 0.5f, -1.0f } };
    Vec3 o = v3(0.0f, 0.0f, 0.0f);
    Scene s;
    int k;
    if (!load_bilerp(t, &s,
                     "Texture \"f\" \"float\" \"bilerp\" \"float v00\" 0.1 \"float v01\" 0.9 "
                     "\"float v10\" 0.5 \"float v11\" 0.2\n"
                     "Texture \"d\" \"float\" \"bilerp\"\n"
                     "Texture \"m\" \"float\" \"bilerp\" \"float uscale\" 2 \"float udelta\" -0.5 "
                     "\"float vscale\" 0.5 \"float vdelta\" 0.25 \"float v00\" 1 \"float v01\" 2 "
                     "\"float v10\" 3 \"float v11\" 4\n"
                     "Translate 1 0 0\n"
                     "Texture \"p\" \"float\" \"bilerp\" \"string mapping\" \"planar\" "
                     "\"vector3 v1\" [ 0.25 0 0 ] \"vector3 v2\" [ 0 0 0.5 ] \"float udelta\" 0.5 "
                     "\"float v00\" 0 \"float v01\" 1 \"float v10\" 0 \"float v11\" 1\n"))
        return;
    /* corners, exactly: v00 at (0, 0), v10 at (1, 0), v01 at (0, 1), v11 at (1, 1) */
    CHECK(t, at(&s, 0, 0, 0, o, 550) == 0.1f && at(&s, 0, 1, 0, o, 550) == 0.5f &&
          at(&s, 0, 0, 1, o, 550) == 0.9f && at(&s, 0, 1, 1, o, 550) == 0.2f,
          "corners (0,0) (1,0) (0,1) (1,1): %g %g %g %g, want 0.1 0.5 0.9 0.2",
          at(&s, 0, 0, 0, o, 550), at(&s, 0, 1, 0, o, 550), at(&s, 0, 0, 1, o, 550), at(&s, 0, 1, 1, o, 550));
    CHECK(t, fabs(at(&s, 0, 0.5f, 0.5f, o, 550) - 0.425) < 1e-6, "centre %g, want the mean 0.425",
          at(&s, 0, 0.5f, 0.5f, o, 550));
    for (k = 0; k < 5; k++) {
        double want = bilerp_ref(pts[k][0], pts[k][1], 0.1, 0.9, 0.5, 0.2);
        float got = at(&s, 0, pts[k][0], pts[k][1], o, 550);
        CHECK(t, fabs(got - want) < 1e-5, "at (%g, %g): %g, want %g", pts[k][0], pts[k][1], got, want);
    }
    /* pbrt-v4's defaults v00 0, v01 1, v10 0, v11 1: the value is t */
    CHECK(t, at(&s, 1, 0.2f, 0.75f, o, 550) == 0.75f && at(&s, 1, 0.9f, 0.0f, o, 550) == 0.0f,
          "defaults: %g at v 0.75, %g at v 0", at(&s, 1, 0.2f, 0.75f, o, 550), at(&s, 1, 0.9f, 0.0f, o, 550));
    /* uv mapping: s = 2u - 0.5, t = 0.5v + 0.25 */
    for (k = 0; k < 5; k++) {
        double want = bilerp_ref(2.0 * pts[k][0] - 0.5, 0.5 * pts[k][1] + 0.25, 1, 2, 3, 4);
        float got = at(&s, 2, pts[k][0], pts[k][1], o, 550);
        CHECK(t, fabs(got - want) < 1e-5, "mapped at (%g, %g): %g, want %g", pts[k][0], pts[k][1], got, want);
    }
    /* planar in the texture's frame (Translate 1 0 0 at the directive): s = 0.5 +
       0.25 (x - 1), t = 0.5 z, the value t (v01 = v11 = 1) */
    CHECK(t, fabs(at(&s, 3, 0, 0, v3(3.0f, 7.0f, 1.5f), 550) - 0.75) < 1e-6 &&
          fabs(at(&s, 3, 0, 0, v3(-2.0f, 0.0f, 0.25f), 550) - 0.125) < 1e-6,
          "planar: %g %g, want 0.75 0.125", at(&s, 3, 0, 0, v3(3.0f, 7.0f, 1.5f), 550),
          at(&s, 3, 0, 0, v3(-2.0f, 0.0f, 0.25f), 550));
    scene_free(&s);
}

/* A spectrum bilerp: grey corners are flat, a "spectrum" corner its own curve;
   each wavelength interpolates the corners' values there. */
static void test_bilerp_spectrum(T *t)
{
    Vec3 o = v3(0.0f, 0.0f, 0.0f);
    Scene s;
    int k;
    if (!load_bilerp(t, &s,
                     "Texture \"s\" \"spectrum\" \"bilerp\" \"rgb v00\" [ 0.4 0.4 0.4 ] "
                     "\"rgb v01\" [ 0.25 0.25 0.25 ] \"spectrum v10\" [ 400 1 700 0 ] "
                     "\"spectrum v11\" [ 400 0.2 700 0.8 ]\n"
                     "Texture \"d\" \"spectrum\" \"bilerp\"\n"))
        return;
    for (k = 0; k < 3; k++) {
        float lam = 400.0f + 150.0f * k;
        double v10 = 1.0 - k * 0.5, v11 = 0.2 + 0.3 * k;
        CHECK(t, fabs(at(&s, 0, 0, 0, o, lam) - 0.4) < 1e-5 && fabs(at(&s, 0, 0, 1, o, lam) - 0.25) < 1e-5,
              "%g nm: grey corners %g %g", lam, at(&s, 0, 0, 0, o, lam), at(&s, 0, 0, 1, o, lam));
        CHECK(t, fabs(at(&s, 0, 1, 0, o, lam) - v10) < 1e-5 && fabs(at(&s, 0, 1, 1, o, lam) - v11) < 1e-5,
              "%g nm: v10 %g (want %g), v11 %g (want %g)", lam, at(&s, 0, 1, 0, o, lam), v10,
              at(&s, 0, 1, 1, o, lam), v11);
        CHECK(t, fabs(at(&s, 0, 0.5f, 0.5f, o, lam) - 0.25 * (0.4 + 0.25 + v10 + v11)) < 1e-5,
              "%g nm: centre %g, want %g", lam, at(&s, 0, 0.5f, 0.5f, o, lam), 0.25 * (0.4 + 0.25 + v10 + v11));
        CHECK(t, fabs(at(&s, 0, 0.2f, 0.6f, o, lam) - bilerp_ref(0.2, 0.6, 0.4, 0.25, v10, v11)) < 1e-5,
              "%g nm: at (0.2, 0.6) %g, want %g", lam, at(&s, 0, 0.2f, 0.6f, o, lam),
              bilerp_ref(0.2, 0.6, 0.4, 0.25, v10, v11));
        CHECK(t, at(&s, 1, 0.3f, 0.6f, o, lam) == 0.6f, "%g nm: the default spectrum bilerp %g at t 0.6",
              lam, at(&s, 1, 0.3f, 0.6f, o, lam));
    }
    scene_free(&s);
}

/* As a diffuse reflectance, extrapolated beyond the corners: clamped to [0, 1]
   (pbrt-v4's DiffuseMaterial: Clamp(reflectance, 0, 1)). */
static void test_bilerp_reflectance_clamped(T *t)
{
    SurfacePoint sp;
    Scene s;
    if (!load_bilerp(t, &s,
                     "Texture \"s\" \"spectrum\" \"bilerp\" \"rgb v00\" [ 0.2 0.2 0.2 ] \"rgb v01\" [ 0.2 0.2 0.2 ] "
                     "\"rgb v10\" [ 0.9 0.9 0.9 ] \"rgb v11\" [ 0.9 0.9 0.9 ]\n"
                     "Material \"diffuse\" \"texture reflectance\" \"s\"\nShape \"sphere\"\n"))
        return;
    memset(&sp, 0, sizeof sp);
    sp.ng = sp.ns = v3(0.0f, 0.0f, 1.0f);
    sp.u = 0.5f;
    CHECK(t, fabsf(mat_albedo_at(&s.materials[0], &sp, 550.0f) - 0.55f) < 1e-5f, "u 0.5: %g, want 0.55",
          mat_albedo_at(&s.materials[0], &sp, 550.0f));
    sp.u = 1.5f;                              /* 0.2 + 1.5 x 0.7 = 1.25 */
    CHECK(t, mat_albedo_at(&s.materials[0], &sp, 550.0f) == 1.0f, "u 1.5: %g, want 1 (clamped)",
          mat_albedo_at(&s.materials[0], &sp, 550.0f));
    sp.u = -0.5f;                             /* 0.2 - 0.35 */
    CHECK(t, mat_albedo_at(&s.materials[0], &sp, 550.0f) == 0.0f, "u -0.5: %g, want 0 (clamped)",
          mat_albedo_at(&s.materials[0], &sp, 550.0f));
    scene_free(&s);
}

static void test_bilerp_errors(T *t)
{
    test_rejected_at(t, "WorldBegin\nTexture \"f\" \"float\" \"constant\"\n"
                     "Texture \"x\" \"float\" \"bilerp\"\n  \"texture v10\" \"f\"\n", 4,
                     "Texture \"bilerp\": \"texture v10\"", "not textures");
    test_rejected_at(t, "WorldBegin\nTexture \"x\" \"float\" \"bilerp\" \"rgb v00\" [ 0.1 0.2 0.3 ]\n", 2,
                     "\"rgb v00\": unused parameter", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"x\" \"spectrum\" \"bilerp\"\n  \"rgb v11\" [ 1.5 0.2 0.3 ]\n", 3,
                     "\"rgb v11\": a reflectance must be within [0,1]", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"x\" \"spectrum\" \"bilerp\" \"string mapping\" \"cubic\"\n", 2,
                     "unknown mapping \"cubic\"", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"x\" \"float\" \"bilerp\" \"float v01\" [ 1 2 ]\n", 2,
                     "v01", NULL);
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 256`, S = 1..8, the
   independent sampler) rendered BILERP_SQUARES: a spectrum bilerp over uv with
   scales and offsets that extrapolate it beyond its corners (a reflectance above
   1 at one corner, clamped), beside a "scale" texture whose scale is a float
   bilerp of the planar mapping; luminance of the image and its quadrants (top
   left first), mean over the seeds and its standard error; accepted within 5
   standard errors + 1 % (specnee 4 x 64 spp: within 0.2 %). */
static const char *const BILERP_SQUARES =
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 0.3 0.2 4 ] \"point3 to\" [ 0 0 0 ]\n"
    "Texture \"b\" \"spectrum\" \"bilerp\" \"float uscale\" [ 1.4 ] \"float udelta\" [ -0.2 ] \"float vscale\" [ 1.2 ] "
    "\"float vdelta\" [ -0.1 ] \"rgb v00\" [ 0.9 0.1 0.1 ] \"rgb v01\" [ 0.1 0.9 0.1 ] \"rgb v10\" [ 0.1 0.1 0.9 ] "
    "\"rgb v11\" [ 0.95 0.9 0.2 ]\n"
    "Texture \"f\" \"float\" \"bilerp\" \"string mapping\" \"planar\" \"vector3 v1\" [ 0.25 0 0 ] \"vector3 v2\" [ 0 0.25 0 ] "
    "\"float udelta\" [ 0.5 ] \"float vdelta\" [ 0.5 ] \"float v00\" [ 0.1 ] \"float v01\" [ 0.9 ] \"float v10\" [ 0.5 ] "
    "\"float v11\" [ 0.2 ]\n"
    "Texture \"fs\" \"spectrum\" \"scale\" \"rgb tex\" [ 0.3 0.8 0.9 ] \"texture scale\" \"f\"\n"
    "Material \"diffuse\" \"texture reflectance\" \"b\"\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -2.2 -2 0  -0.1 -2 0  -0.1 2 0  -2.2 2 0 ] "
    "\"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"
    "Material \"diffuse\" \"texture reflectance\" \"fs\"\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0.1 -2 0  2.2 -2 0  2.2 2 0  0.1 2 0 ]\n";
static const double PBRT_BILERP_Y[5][2] = {
    { 0.291521, 4.1e-05 }, { 0.197199, 4.3e-05 }, { 0.504374, 0.00013 }, { 0.214923, 9.5e-05 }, { 0.249588, 0.00011 },
};

static void test_bilerp_against_pbrt(T *t)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", BILERP_HEAD, BILERP_SQUARES);
    test_against_pbrt_y(t, buf, 3, PBRT_BILERP_Y, 1e-2, "bilerp squares");
}

const TestCase tests_bilerp[] = {
    { "bilerp_float", test_bilerp_float },
    { "bilerp_spectrum", test_bilerp_spectrum },
    { "bilerp_reflectance_clamped", test_bilerp_reflectance_clamped },
    { "bilerp_errors", test_bilerp_errors },
    { "bilerp_against_pbrt", test_bilerp_against_pbrt },
    { NULL, NULL }
};
