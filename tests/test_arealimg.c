/* tests/test_arealimg.c - pbrt-v4's area light with an emission image
   (AreaLightSource "diffuse" "string filename": lights.c area_light_image and
   light_Le_at, texture.c's illuminant texels) and a bilinearmesh's
   "emissionfilename" (geometry.c emission_file).

   Checked: a 1 x 1 image has the radiance of the "rgb L" of its colour (up to the
   normalisation over the film's range, whose ratio is computed) and its mean
   colour is what selection sees; a lamp whose image is black on one half lights a
   floor symmetric about it with exactly half the light of the all-white lamp; NEE
   and BSDF sampling alone agree on lamps with a non-uniform image (a bilinear
   patch, a sphere, a triangle mesh with uv); pbrt-v4's image of
   tests/data/arealimg/lamp.pbrt frozen; the refusals at their file:line. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

#define IMG_DIR "tests/data/arealimg/"

static const char *const AREALIMG_HEAD =
    "LookAt 0 0 1  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 60 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 24 ]\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 3 ]\n"
    "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
    "\"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ]\n";

/* Mean and standard error over K seeds of the image Y of AREALIMG_HEAD + body. */
static int mean_Y(T *t, const char *body, int spp, int nee, int K, double *mean, double *se)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", AREALIMG_HEAD, body);
    return test_mean_y(t, buf, spp, nee, K, mean, se);
}

/* Emitter 0: a sphere with the 1 x 1 image const.pfm (0.9 0.5 0.2); 1: a D65
   lamp of the same scale (declared next, so that a sampler sharing radiances
   between equal (L, scale) would be tempted); 2: "rgb L" 0.9 0.5 0.2.  The
   image's radiance is k m sigmoid D65 with k = scale / sum ybar D65, the rgb L's
   scale' L / sum ybar L with scale' = scale Y(L) / Y(D65) (rgb_illuminant_scale),
   L = m sigmoid D65: their ratio is Y(D65) sum ybar L / (sum ybar D65 Y(L)) at every
   wavelength (within 1e-5: the fits), 1 within 1e-3.  light_Le (no point) gives
   the image's mean colour, here the same. */
static void test_arealimg_constant(T *t)
{
    static const char *const text =
        "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"" IMG_DIR
        "const.pfm\" \"float scale\" 2\nShape \"sphere\"\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"float scale\" 2\nTranslate 3 0 0\n"
        "Shape \"sphere\"\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 0.9 0.5 0.2 ] \"float scale\" 2\n"
        "Translate 6 0 0\nShape \"sphere\"\nAttributeEnd\n";
    Scene s;
    SelOptions o;
    Error err;
    LightSampler *ls;
    SurfacePoint sp;
    Spectrum d65;
    Vec3 n = v3(0, 0, 1);
    double want, worst = 0.0, worst_mean = 0.0, worst_d65 = 0.0;
    int lam;
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_emitters == 3 && s.emitters[0].image > 0 && !s.emitters[1].image,
          "emitters: %d, image %d %d", s.n_emitters, s.emitters[0].image, s.emitters[1].image);
    memset(&o, 0, sizeof o);
    o.strategy = SEL_POWER;
    o.lo_nm = LAMBDA_LO;
    o.hi_nm = LAMBDA_HI;
    ls = light_sampler_build(&s, &o, &err);
    CHECK(t, ls != NULL, "%s", err.msg);
    if (!ls || t->failed) { scene_free(&s); return; }
    spec_named(&d65, "stdillum-D65");
    want = spec_to_y(&d65) * luminance_sum(s.emitters[2].L, LAMBDA_LO, LAMBDA_HI)
         / (luminance_sum(&d65, LAMBDA_LO, LAMBDA_HI) * spec_to_y(s.emitters[2].L));
    CHECK(t, fabs(want - 1.0) < 1e-3, "normalisation ratio %.6f", want);
    memset(&sp, 0, sizeof sp);
    sp.u = 0.3f;
    sp.v = 0.8f;
    for (lam = (int)LAMBDA_LO; lam <= (int)LAMBDA_HI; lam++) {
        double a = light_Le_at(ls, 0, n, n, &sp, (float)lam), b = light_Le(ls, 2, n, n, (float)lam);
        double m = light_Le(ls, 0, n, n, (float)lam);
        double d = light_Le(ls, 1, n, n, (float)lam) / spec_eval(&d65, (float)lam)
                 / (light_Le(ls, 1, n, n, 560.0f) / spec_eval(&d65, 560.0f));
        if (fabs(a / b / want - 1.0) > worst) worst = fabs(a / b / want - 1.0);
        if (fabs(m / a - 1.0) > worst_mean) worst_mean = fabs(m / a - 1.0);
        if (fabs(d - 1.0) > worst_d65) worst_d65 = fabs(d - 1.0);
    }
    CHECK(t, worst < 1e-5, "image / rgb L differs from %.6f by %.3g (relative)", want, worst);
    CHECK(t, worst_mean < 1e-5, "the mean colour's radiance differs from the image's by %.3g", worst_mean);
    CHECK(t, worst_d65 < 1e-5, "the D65 lamp after the image lamp is not D65 (%.3g)", worst_d65);
    light_sampler_free(ls);
    scene_free(&s);
}

/* A square lamp facing down over the floor, the camera between them looking down
   (world x along the image's rows): with half.pfm (u < 1/2 black, u > 1/2 white,
   bilinear: the mean over u is exactly 1/2) the floor, symmetric under x -> -x
   (which swaps the halves), gets exactly half of what white.pfm gives it. */
static void test_arealimg_half(T *t)
{
    static const char *const fmt =
        "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"" IMG_DIR "%s\" "
        "\"float scale\" 3\nTranslate 0 0 2\nReverseOrientation\n"
        "Shape \"bilinearmesh\" \"point3 P\" [ -1 -1 0  1 -1 0  -1 1 0  1 1 0 ]\nAttributeEnd\n";
    char body[1024];
    const int K = 8, spp = test_scaled(16, 4);
    double y0, se0, y1, se1;
    snprintf(body, sizeof body, fmt, "white.pfm");
    if (!mean_Y(t, body, spp, 1, K, &y1, &se1)) return;
    snprintf(body, sizeof body, fmt, "half.pfm");
    if (!mean_Y(t, body, spp, 1, K, &y0, &se0)) return;
    CHECK(t, y1 > 0.05, "the floor is dark: Y %g", y1);
    CHECK(t, fabs(y0 - 0.5 * y1) < TEST_K_SIGMA * sqrt(se0 * se0 + 0.25 * se1 * se1),
          "half-black lamp: Y %.5f +- %.2g, want 0.5 x %.5f +- %.2g", y0, se0, y1, se1);
}

/* NEE (with MIS) and BSDF sampling alone see the same radiance at each point of
   lamps with non-uniform images, lighting the floor: a tilted two-sided bilinear
   patch out of view with half.pfm (its halves at different heights, so that NEE
   reading the mean colour instead of the sampled point's is 11 % off), and a
   sphere and a triangle mesh with its own uv with lamp.pfm. */
static void test_arealimg_nee_agrees(T *t)
{
    static const char *const body =
        "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"" IMG_DIR "half.pfm\" "
        "\"bool twosided\" true \"float scale\" 3\nTranslate -1.0 0.3 0.8\nRotate 40 0 1 0\n"
        "Shape \"bilinearmesh\" \"point3 P\" [ -0.6 -0.6 0  0.6 -0.6 0  -0.6 0.6 0  0.6 0.6 0 ]\n"
        "AttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"" IMG_DIR "lamp.pfm\"\n"
        "Translate 0.9 -0.6 1.6\nRotate 50 1 0 0\nShape \"sphere\" \"float radius\" 0.35\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"" IMG_DIR "lamp.pfm\" "
        "\"float scale\" 2\nTranslate 0.5 0.9 1.3\nReverseOrientation\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -0.5 -0.3 0  "
        "0.5 -0.3 0  0.5 0.3 0.2  -0.5 0.3 0.2 ] \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\nAttributeEnd\n";
    const int K = 8, spp = test_scaled(16, 4);
    double y0, se0, y1, se1;
    if (!mean_Y(t, body, spp, 1, K, &y0, &se0)) return;
    if (!mean_Y(t, body, spp, 0, K, &y1, &se1)) return;
    CHECK(t, y0 > 0.01, "the floor is dark: Y %g", y0);
    CHECK(t, fabs(y1 - y0) < TEST_K_SIGMA * sqrt(se0 * se0 + se1 * se1),
          "NEE: Y %.5f +- %.2g; BSDF sampling alone: %.5f +- %.2g", y0, se0, y1, se1);
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 4096`, S = 1, 2, the
   mean; the two differ by at most 0.17 % per value) rendered
   tests/data/arealimg/lamp.pbrt: a tilted two-sided bilinear patch lamp seen from
   its front and a one-sided sphere lamp, both with the 8 x 8 lamp.pfm, over a grey
   floor.  Luminance of the image and its quadrants (top left first).  specnee at
   1024 spp (tools/pbrt_compare.sh): image 0.9988, quadrants within 0.4 %. */
static void test_arealimg_against_pbrt(T *t)
{
    static const double pbrt_y[5] = { 0.314656, 0.460927, 0.369872, 0.299961, 0.127864 };
    Scene sc;
    RenderOptions o;
    Error e;
    CHECK(t, scene_load(&sc, IMG_DIR "lamp.pbrt", &e), "%s", e.msg);
    if (t->failed) return;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    test_quadrants_against_pbrt(t, &sc, &o, pbrt_y, "lamp.pbrt");
    scene_free(&sc);
}

/* Refusals, one line at the directive's file:line; a bilinearmesh's
   "emissionfilename" is read (a missing file is an error, as in pbrt-v4) and
   otherwise changes nothing. */
static void test_arealimg_errors(T *t)
{
    static char text[1024];
    Scene s;
    test_rejected_at(t, "WorldBegin\n\nAreaLightSource \"diffuse\" \"string filename\" \"nothere.pfm\"\n",
                     3, "AreaLightSource \"diffuse\"", "nothere.pfm");
    test_rejected_at(t, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"string filename\" \""
                     IMG_DIR "const.pfm\"\n", 2, "both \"L\" and \"filename\"", NULL);
    test_rejected_at(t, "WorldBegin\nAreaLightSource \"diffuse\" \"string filename\" \"a.tga\"\n", 2,
                     "\"a.tga\": specnee reads emission images as PNG, PFM or EXR", NULL);
    test_rejected_at(t, "WorldBegin\n\nShape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 0 ] "
                     "\"string emissionfilename\" \"nothere.exr\"\n", 3, "Shape \"bilinearmesh\"",
                     "nothere.exr");
    if (t->failed) return;
    snprintf(text, sizeof text, "WorldBegin\nAreaLightSource \"diffuse\"\n"
             "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 0 ] "
             "\"string emissionfilename\" \"" IMG_DIR "lamp.pfm\"\n");
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_emitters == 1 && !s.emitters[0].image, "emissionfilename made an image light");
    scene_free(&s);
}

const TestCase tests_arealimg[] = {
    { "arealimg_constant", test_arealimg_constant },
    { "arealimg_half", test_arealimg_half },
    { "arealimg_nee_agrees", test_arealimg_nee_agrees },
    { "arealimg_against_pbrt", test_arealimg_against_pbrt },
    { "arealimg_errors", test_arealimg_errors },
    { NULL, NULL }
};
