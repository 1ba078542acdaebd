/* tests/test_alpha.c - pbrt-v4's shape "alpha" (geometry.c shape_alpha and
   shape_drop; bvh.c ALPHA: alpha_keep; lights.c emitter_alpha).

   A hit on a shape with alpha a counts only when a hash u of the ray is <= a, and a
   ray that passes goes on (beyond it, the same shape again where a line meets it
   twice).  Checked: the frequencies of the test for closest-hit rays (a constant
   0.5 on a triangle, a checkerboard texture, a sphere met twice: 1 - 0.5^2), and
   that shadow rays (any hit) see exactly the same hits; the image behind a
   half-transparent square is half the light; shapes of alpha 0 leave the image bit
   for bit as if absent, except an area light of alpha exactly 0, pbrt-v4's
   invisible light, which lights the scene in full; NEE and BSDF sampling agree on an
   emitter of alpha 0.5 seen through an occluder of alpha 0.5; bit-identical images
   for any thread count; the refusals by message; pbrt-v4's images frozen. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static const char *const ALPHA_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n";

static const char *const ALPHA_SUN =
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 0 0 0 ]\n";

/* A square x in [x0, x1], y in [-2, 2] at height z, with uv over it; then its alpha. */
#define ALPHA_SQUARE(x0, x1, z) "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ " \
    x0 " -2 " z "  " x1 " -2 " z "  " x1 " 2 " z "  " x0 " 2 " z " ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ] "

static int load_alpha(T *t, Scene *s, const char *body)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", ALPHA_HEAD, body);
    return test_load_scene(t, s, buf);
}

/* Within 5 binomial standard errors of n p. */
static int binomial_ok(long hits, long n, double p)
{
    return fabs((double)hits - n * p) <= 5.0 * sqrt(n * p * (1.0 - p)) + 1e-9;
}

/* n rays from random points of the plane z = 3 (x, y in [x0, x0 + w] x [-1, 1])
   straight down (with a small random tilt) to z = -3: how many hit; each ray's
   shadow query must agree with its closest hit (*disagree counts those that do not). */
static long count_hits(const Scene *s, float x0, float w, long n, Rng *rg, long *disagree)
{
    long i, hits = 0;
    for (i = 0; i < n; i++) {
        float q[4];
        Ray r;
        HitRecord h;
        int hit, occ;
        rng_fill(rg, q, 4);
        r.o = v3(x0 + w * q[0], 2.0f * q[1] - 1.0f, 3.0f);
        r.d = v3(0.02f * (q[2] - 0.5f), 0.02f * (q[3] - 0.5f), -1.0f);
        r.tmax = 6.0f;
        hit = bvh_intersect(&s->bvh, s, &r, &h);
        occ = bvh_occluded(&s->bvh, s, &r);
        hits += hit;
        *disagree += hit != occ;
    }
    return hits;
}

/* The test's frequencies: a square of alpha 0.5 stops half the rays; a
   checkerboard alpha (0 and 0.8, 2 x 2 cells over uv) stops none in a 0 cell and
   80 % in a 0.8 cell; a sphere of alpha 0.5, met twice by each ray through its
   middle, stops 1 - 0.5 x 0.5 = 75 % (the far side is tested by the ray spawned
   at the near one, its own hash); alpha 1 stops all; a sphere's checkerboard
   alpha (0 for u < 0.5, 1 beyond) reads pbrt-v4's sphere (u, v).  Shadow rays agree with
   closest-hit rays on every ray.  The same ray always gives the same answer. */
static void test_alpha_frequencies(T *t)
{
    Scene s;
    Rng r;
    const long n = test_scaled(20000, 4000);
    long h, bad = 0;
    if (!load_alpha(t, &s,
                    "Texture \"cut\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 "
                    "\"float tex1\" 0 \"float tex2\" 0.8\n"
                    ALPHA_SQUARE("-8", "-6", "0") "\"float alpha\" 0.5\n"
                    ALPHA_SQUARE("-4", "-2", "0") "\"texture alpha\" \"cut\"\n"
                    "AttributeBegin\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 1.5 \"float alpha\" 0.5\n"
                    "AttributeEnd\n"
                    ALPHA_SQUARE("4", "6", "0") "\"float alpha\" 1\n"
                    "Texture \"half\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 1 "
                    "\"float tex1\" 0 \"float tex2\" 1\n"
                    "AttributeBegin\nTranslate 10 0 0\nShape \"sphere\" \"float radius\" 1.5 "
                    "\"texture alpha\" \"half\"\nAttributeEnd\n"))
        return;
    CHECK(t, s.n_alpha == 4 && s.shapes[1].alpha_tex > 0, "%d shapes test alpha, want 4", s.n_alpha);
    CHECK(t, !s.shapes[3].alpha_on, "alpha 1 is tested");
    rng_seed(&r, 5, 1);
    h = count_hits(&s, -7.5f, 1.0f, n, &r, &bad);
    CHECK(t, binomial_ok(h, n, 0.5), "alpha 0.5: %ld hits of %ld", h, n);
    /* uv (u, v) = ((x + 4) / 2, (y + 2) / 4): x in [-3.9, -3.1] is u < 0.5 (tex1 0)
       for y in [-1, 0) (v < 0.5) and tex2 0.8 for y in [0, 1]: half the rays each */
    h = count_hits(&s, -3.9f, 0.8f, n, &r, &bad);
    CHECK(t, binomial_ok(h, n, 0.4), "checkerboard 0 / 0.8: %ld hits of %ld, want 40 %%", h, n);
    h = count_hits(&s, 0.6f, 0.8f, n, &r, &bad);
    CHECK(t, binomial_ok(h, n, 0.75), "sphere of alpha 0.5: %ld hits of %ld, want 75 %%", h, n);
    h = count_hits(&s, 4.5f, 1.0f, n, &r, &bad);
    CHECK(t, h == n, "alpha 1: %ld hits of %ld", h, n);
    /* the sphere's u = phi / 2 pi: alpha 0 where y > 0 (u < 0.5), 1 where y < 0 */
    h = count_hits(&s, 9.6f, 0.8f, n, &r, &bad);
    CHECK(t, binomial_ok(h, n, 0.5), "sphere of a textured alpha: %ld hits of %ld, want 50 %%", h, n);
    CHECK(t, bad == 0, "shadow rays and closest-hit rays disagree on %ld rays", bad);
    {
        Ray ray;
        HitRecord h0, h1;
        int i, first;
        ray.o = v3(-7.1f, 0.3f, 3.0f);
        ray.d = v3(0.0f, 0.0f, -1.0f);
        ray.tmax = 4.0f;
        first = bvh_intersect(&s.bvh, &s, &ray, &h0);
        for (i = 0; i < 8; i++)
            CHECK(t, bvh_intersect(&s.bvh, &s, &ray, &h1) == first && (!first || h1.t == h0.t),
                  "the same ray gave two answers");
    }
    scene_free(&s);
}

static int render_img(T *t, const char *body, int spp, int seed, int threads, int nee, Image *im)
{
    static char buf[8192];
    RenderOptions o;
    snprintf(buf, sizeof buf, "%s%s", ALPHA_HEAD, body);
    render_options_default(&o);
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.nee = nee;
    return test_render_text(t, buf, &o, im);
}

/* Mean and standard error of the image Y over K seeds. */
static int mean_Y(T *t, const char *body, int spp, int nee, int K, double *mean, double *se)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", ALPHA_HEAD, body);
    return test_mean_y(t, buf, spp, nee, K, mean, se);
}

/* The camera looks at a lamp (a square emitter facing it) through a black square of
   alpha 0.5 that covers the whole view: the image is half the lamp's. */
static void test_alpha_half_transmission(T *t)
{
    static const char *const lamp =
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
        ALPHA_SQUARE("-6", "6", "-1") "\nAttributeEnd\n";
    char body[2048];
    const int K = 8, spp = test_scaled(4, 1);
    double y0, se0, y1, se1;
    if (!mean_Y(t, lamp, spp, 1, 2, &y0, &se0)) return;
    snprintf(body, sizeof body, "%sMaterial \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
             ALPHA_SQUARE("-6", "6", "1") "\"float alpha\" 0.5\n", lamp);
    if (!mean_Y(t, body, spp, 1, K, &y1, &se1)) return;
    CHECK(t, y0 > 0.5, "the lamp's image is dark: Y %g", y0);
    CHECK(t, fabs(y1 - 0.5 * y0) < TEST_K_SIGMA * sqrt(se1 * se1 + 0.25 * se0 * se0) + 1e-9,
          "through alpha 0.5: Y %.5f +- %.2g, want 0.5 x %.5f", y1, se1, y0);
}

/* A scene with shapes of alpha 0 or below (a sphere light of alpha -1, a mesh, a
   disk, inside an ObjectBegin too) renders the same bits as the scene without
   them: pbrt-v4 never hits them, and a light of negative alpha sends nothing. */
static void test_alpha_zero_invisible(T *t)
{
    static const char *const base =
        "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.5 0.4 ]\n" ALPHA_SQUARE("-3", "3", "0") "\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\nTranslate 0 0 2\nReverseOrientation\n"
        "Shape \"disk\" \"float radius\" 0.5\nAttributeEnd\n";
    static const char *const extra =
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 9 9 9 ]\nTranslate 1 1 1\n"
        "Shape \"sphere\" \"float radius\" 0.5 \"float alpha\" -1\nAttributeEnd\n"
        ALPHA_SQUARE("-1", "1", "1") "\"float alpha\" 0\n"
        "Shape \"disk\" \"float alpha\" -1\n"
        "ObjectBegin \"o\"\nShape \"sphere\" \"float alpha\" 0\nShape \"sphere\" \"float radius\" 0.2 "
        "\"float alpha\" 1\nObjectEnd\nObjectInstance \"o\"\n";
    char body[4096];
    Image a, b;
    Scene s;
    snprintf(body, sizeof body, "%s%s%s", ALPHA_SUN, base, extra);
    if (!load_alpha(t, &s, body)) return;
    CHECK(t, s.n_shapes == 3 && s.n_emitters == 2 && s.n_spheres == 1 && s.n_alpha == 0,
          "alpha 0 shapes kept: %d shapes, %d emitters, %d spheres", s.n_shapes, s.n_emitters, s.n_spheres);
    scene_free(&s);
    snprintf(body, sizeof body, "%s%s%s", ALPHA_SUN, base,
             "ObjectBegin \"o\"\nShape \"sphere\" \"float radius\" 0.2\nObjectEnd\nObjectInstance \"o\"\n");
    if (!render_img(t, body, 4, 3, 2, 1, &a)) return;
    snprintf(body, sizeof body, "%s%s%s", ALPHA_SUN, base, extra);
    if (!render_img(t, body, 4, 3, 2, 1, &b)) { img_free(&a); return; }
    CHECK(t, test_image_y(&a) > 0.0, "the scene is black");
    CHECK(t, !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * a.w * a.h),
          "alpha 0 shapes change the image: Y %.9g, without them %.9g", test_image_y(&b), test_image_y(&a));
    img_free(&a); img_free(&b);
}

/* pbrt-v4's invisible area light: an area light of the constant alpha 0 ("float
   alpha" 0, or a "constant" float texture of 0) is never hit, yet emits in full.
   (a) Without pbrt-v4: a black sphere lamp behind the camera lights the floor as
   much with alpha 0 as with alpha 1 (it is found by NEE alone then, with the whole
   MIS weight; with alpha 1 by both techniques).  (b) pbrt-v4 (mmp/pbrt-v4 commit
   5f7a6068, `pbrt --seed S --spp 256`, S = 1..8, the independent sampler) rendered
   INVISIBLE_LAMPS: a sphere lamp of "float alpha" 0 and a disk lamp of a constant
   "texture alpha" 0 in view over a floor; luminance of the image and its quadrants
   (top left first), mean over the seeds and its standard error; accepted within 5
   standard errors + 1 % (specnee 8 x 256 spp: image +0.11 %, quadrants within
   0.18 %). */
static const char *const INVISIBLE_LAMPS =
    "LookAt 0 -3 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "Texture \"zero\" \"float\" \"constant\" \"float value\" [ 0 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ]\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 3 2 ]\nTranslate 0.8 0.3 1.2\n"
    "Shape \"sphere\" \"float radius\" [ 0.4 ] \"float alpha\" [ 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 2 4 ]\nTranslate -1.5 -0.5 1.5\nReverseOrientation\n"
    "Shape \"disk\" \"float radius\" [ 0.7 ] \"texture alpha\" \"zero\"\nAttributeEnd\n";
static const double PBRT_INVISIBLE_Y[5][2] = {
    { 0.098799, 2.2e-05 }, { 0.083402, 2.3e-05 }, { 0.075344, 4.5e-05 }, { 0.083439, 3.9e-05 }, { 0.153010, 3.7e-05 },
};

static void test_alpha_zero_light(T *t)
{
    static const char *const fmt =
        "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.5 0.4 ]\n" ALPHA_SQUARE("-3", "3", "0") "\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\nTranslate 0.5 0.5 6.5\n"
        "Shape \"sphere\" \"float radius\" 1 \"float alpha\" %s\nAttributeEnd\n";
    char body[2048];
    const int K = 8, spp = test_scaled(16, 4);
    double y0, se0, y1, se1;
    snprintf(body, sizeof body, fmt, "1");
    if (!mean_Y(t, body, spp, 1, K, &y1, &se1)) return;
    snprintf(body, sizeof body, fmt, "0");
    if (!mean_Y(t, body, spp, 1, K, &y0, &se0)) return;
    CHECK(t, y1 > 0.01, "the floor is dark: Y %g", y1);
    CHECK(t, fabs(y1 - y0) < TEST_K_SIGMA * sqrt(se0 * se0 + se1 * se1),
          "lamp of alpha 0: Y %.5f +- %.2g; of alpha 1: %.5f +- %.2g", y0, se0, y1, se1);
    if (t->failed) return;
    test_against_pbrt_y(t, INVISIBLE_LAMPS, 3, PBRT_INVISIBLE_Y, 1e-2, "invisible lamps");
}

/* A floor lit by a lamp of alpha 0.5 through an occluder of alpha 0.5 (with a
   checkerboard cut-out beside it): NEE (shadow rays, the lamp's radiance x alpha)
   and BSDF sampling alone (closest-hit rays) give the same image mean. */
static void test_alpha_nee_agrees(T *t)
{
    static const char *const body =
        "Texture \"cut\" \"float\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 4 "
        "\"float tex1\" 0 \"float tex2\" 1\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n" ALPHA_SQUARE("-3", "3", "0") "\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\nTranslate 0 0 2.5\nReverseOrientation\n"
        "Shape \"disk\" \"float radius\" 1.5 \"float alpha\" 0.5\nAttributeEnd\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.2 0.2 ]\n"
        "AttributeBegin\nTranslate -1 0 1\nShape \"sphere\" \"float radius\" 0.6 \"float alpha\" 0.5\nAttributeEnd\n"
        ALPHA_SQUARE("0", "2", "1.2") "\"texture alpha\" \"cut\"\n";
    const int K = 8, spp = test_scaled(16, 4);
    double y0, se0, y1, se1;
    if (!mean_Y(t, body, spp, 1, K, &y0, &se0)) return;
    if (!mean_Y(t, body, spp, 0, K, &y1, &se1)) return;
    CHECK(t, y0 > 0.01, "the floor is dark: Y %g", y0);
    CHECK(t, fabs(y1 - y0) < TEST_K_SIGMA * sqrt(se0 * se0 + se1 * se1),
          "NEE: Y %.5f +- %.2g; BSDF sampling alone: %.5f +- %.2g", y0, se0, y1, se1);
}

/* The test depends on the ray alone: the images of 1, 2 and 3 threads are the
   same bits (constant and textured alpha on a mesh, a sphere and a lamp). */
static void test_alpha_threads(T *t)
{
    static const char *const body =
        "Texture \"cut\" \"float\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 4 "
        "\"float tex1\" 0.2 \"float tex2\" 1\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.6 0.5 ]\n" ALPHA_SQUARE("-3", "3", "0") "\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\nTranslate 0 0 2.5\nReverseOrientation\n"
        "Shape \"disk\" \"float radius\" 1 \"float alpha\" 0.7\nAttributeEnd\n"
        "AttributeBegin\nTranslate -1 0 1\nShape \"sphere\" \"float radius\" 0.6 \"texture alpha\" \"cut\"\n"
        "AttributeEnd\n" ALPHA_SQUARE("0", "2", "1.2") "\"float alpha\" 0.4\n";
    Image a, b, c;
    if (!render_img(t, body, 4, 7, 1, 1, &a)) return;
    if (!render_img(t, body, 4, 7, 2, 1, &b)) { img_free(&a); return; }
    if (!render_img(t, body, 4, 7, 3, 1, &c)) { img_free(&a); img_free(&b); return; }
    CHECK(t, test_image_y(&a) > 0.0, "the scene is black");
    CHECK(t, !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * a.w * a.h) &&
          !memcmp(a.rgb, c.rgb, sizeof(float) * 3 * a.w * a.h),
          "images of 1, 2, 3 threads differ: Y %.9g %.9g %.9g", test_image_y(&a), test_image_y(&b), test_image_y(&c));
    img_free(&a); img_free(&b); img_free(&c);
}

static void expect_error(T *t, const char *body, const char *want)
{
    test_refused(t, ALPHA_HEAD, body, "alpha.pbrt", want);
}

/* Lamps with a "texture alpha" (a mesh: 0.3 and 1 in a checkerboard; a sphere: 0
   and 1; a disk: a checkerboard over its (u, v)): NEE, which weighs the radiance by
   the texture at the sampled point (emitter_alpha_at), and BSDF sampling alone,
   whose rays find the lamp with that probability, give the same image mean. */
static void test_alpha_texture_light_nee_agrees(T *t)
{
    static const char *const body =
        "Texture \"frac\" \"float\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 4 "
        "\"float tex1\" 0.3 \"float tex2\" 1\n"
        "Texture \"cut\" \"float\" \"checkerboard\" \"float uscale\" 6 \"float vscale\" 2 "
        "\"float tex1\" 0 \"float tex2\" 1\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n" ALPHA_SQUARE("-3", "3", "0") "\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\nReverseOrientation\n"
        ALPHA_SQUARE("-2.5", "0", "2") "\"texture alpha\" \"frac\"\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\nTranslate 1.5 0 1\n"
        "Shape \"sphere\" \"float radius\" 0.6 \"texture alpha\" \"cut\"\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\nTranslate 1.5 -1 2.5\nReverseOrientation\n"
        "Shape \"disk\" \"float radius\" 1 \"texture alpha\" \"cut\"\nAttributeEnd\n";
    const int K = 8, spp = test_scaled(16, 4);
    double y0, se0, y1, se1;
    if (!mean_Y(t, body, spp, 1, K, &y0, &se0)) return;
    if (!mean_Y(t, body, spp, 0, K, &y1, &se1)) return;
    if (getenv("DBG")) fprintf(stderr, "NEE %.6f +- %.2g, BSDF %.6f +- %.2g\n", y0, se0, y1, se1);
    CHECK(t, y0 > 0.01, "the floor is dark: Y %g", y0);
    CHECK(t, fabs(y1 - y0) < TEST_K_SIGMA * sqrt(se0 * se0 + se1 * se1),
          "NEE: Y %.5f +- %.2g; BSDF sampling alone: %.5f +- %.2g", y0, se0, y1, se1);
}

/* pbrt-v4 (mmp/pbrt-v4 5f7a6068, `pbrt --seed S --spp 1024`, S = 1..4, the
   independent sampler, 32 x 32) rendered ALPHA_LAMPS: a floor under a square lamp
   with a checkerboard "texture alpha" of 0 and 1 and a sphere lamp with another
   (its (u, v)); DiffuseAreaLight's L is 0 where alpha is 0 and the shape is cut out
   there.  Luminance of the image and its quadrants (top left first), mean over the
   seeds and its standard error; accepted within 5 standard errors + 1 % (specnee
   2048 spp: image +0.2 %, quadrants within 0.4 %). */
static const char *const ALPHA_LAMPS =
    "LookAt 0 -3 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "Texture \"cut\" \"float\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 4 \"float tex1\" 0 \"float tex2\" 1\n"
    "Texture \"ring\" \"float\" \"checkerboard\" \"float uscale\" 6 \"float vscale\" 2 \"float tex1\" 1 \"float tex2\" 0\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ]\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\nReverseOrientation\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -2.5 -1 2  0.5 -1 2  0.5 2 2  -2.5 2 2 ] "
    "\"point2 uv\" [ 0 0 1 0 1 1 0 1 ] \"texture alpha\" \"cut\"\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 2 1 ]\nTranslate 1.5 0 1\n"
    "Shape \"sphere\" \"float radius\" 0.6 \"texture alpha\" \"ring\"\nAttributeEnd\n";
static const double PBRT_ALPHA_LAMPS_Y[5][2] = {
    { 0.315580, 0.00021 }, { 0.422095, 0.00038 }, { 0.233152, 0.00035 }, { 0.265592, 0.00011 }, { 0.341480, 0.00038 },
};

static void test_alpha_texture_light_against_pbrt(T *t)
{
    test_against_pbrt_y(t, ALPHA_LAMPS, 3, PBRT_ALPHA_LAMPS_Y, 1e-2, "alpha lamps");
}

/* Refusals at their file:line: a spectrum texture, a missing one. */
static void test_alpha_errors(T *t)
{
    expect_error(t, "Texture \"k\" \"spectrum\" \"constant\"\nShape \"disk\" \"texture alpha\" \"k\"\n",
                 "alpha.pbrt:9: \"texture alpha\": \"k\" is a spectrum texture; a float one is needed here");
    if (t->failed) return;
    expect_error(t, "Shape \"cylinder\" \"texture alpha\" \"nothere\"\n",
                 "alpha.pbrt:8: \"texture alpha\": no texture named \"nothere\"");
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 256` for S = 1..8, the
   independent sampler) rendered ALPHA_HEAD + ALPHA_SUN with a white square behind
   (z = 0) and, in front: (a) a red square of "float alpha" 0.5 beside one of a
   checkerboard "texture alpha" (0 and 1, 4 x 4 cells over uv); (b) a red sphere of
   alpha 0.5 (each ray meets it twice) beside a cylinder of the checkerboard alpha.
   Luminance of the image and of its 2 x 2 quadrants (top left first), mean over
   the seeds and its standard error.  pbrt-v4 hashes the ray with its own hash, so
   only the means can agree: within 5 standard errors + 1 % (the RGB fits). */
static const double PBRT_ALPHA_Y[2][5][2] = {
    { { 0.296584, 0.00016 },
      { 0.287676, 0.00016 }, { 0.326874, 0.00044 }, { 0.247926, 0.00022 }, { 0.323858, 0.00028 } },
    { { 0.344438, 0.00011 },
      { 0.209097, 0.00018 }, { 0.495859, 0.00025 }, { 0.199892, 0.00018 }, { 0.472903, 0.00021 } },
};

static void test_alpha_against_pbrt(T *t)
{
    static const char *const scene[2] = {
        "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
        ALPHA_SQUARE("-2", "0", "1") "\"float alpha\" [ 0.5 ]\n"
        ALPHA_SQUARE("0", "2", "1") "\"texture alpha\" \"cut\"\n",
        "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
        "AttributeBegin\nTranslate -1 0 1\nShape \"sphere\" \"float radius\" [ 0.9 ] \"float alpha\" [ 0.5 ]\n"
        "AttributeEnd\nAttributeBegin\nTranslate 1 0 1\nRotate 90 1 0 0\n"
        "Shape \"cylinder\" \"float radius\" [ 0.8 ] \"float zmin\" [ -1.5 ] \"float zmax\" [ 1.5 ] "
        "\"texture alpha\" \"cut\"\nAttributeEnd\n",
    };
    int j;
    for (j = 0; j < 2; j++) {
        Scene s;
        char body[4096], what[8];
        snprintf(body, sizeof body, "%s"
                 "Texture \"cut\" \"float\" \"checkerboard\" \"float uscale\" [ 4 ] \"float vscale\" [ 4 ] "
                 "\"float tex1\" [ 0 ] \"float tex2\" [ 1 ]\n"
                 "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n"
                 "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
                 "\"point3 P\" [ -3 -3 0  3 -3 0  3 3 0  -3 3 0 ]\n%s", ALPHA_SUN, scene[j]);
        if (!load_alpha(t, &s, body)) return;
        snprintf(what, sizeof what, "scene %c", 'a' + j);
        test_scene_against_pbrt_y(t, &s, test_scaled(32, 8), 3, PBRT_ALPHA_Y[j], 1e-2, what);
        scene_free(&s);
        if (t->failed) return;
    }
}

const TestCase tests_alpha[] = {
    { "alpha_frequencies", test_alpha_frequencies },
    { "alpha_half_transmission", test_alpha_half_transmission },
    { "alpha_zero_invisible", test_alpha_zero_invisible },
    { "alpha_zero_light", test_alpha_zero_light },
    { "alpha_nee_agrees", test_alpha_nee_agrees },
    { "alpha_texture_light_nee_agrees", test_alpha_texture_light_nee_agrees },
    { "alpha_texture_light_against_pbrt", test_alpha_texture_light_against_pbrt },
    { "alpha_threads", test_alpha_threads },
    { "alpha_errors", test_alpha_errors },
    { "alpha_against_pbrt", test_alpha_against_pbrt },
    { NULL, NULL }
};
