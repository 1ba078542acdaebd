/* tests/test_mix.c - pbrt-v4's Material "mix" (material.c mat_choose,
   mix_from_params; the forward names of scene.c finish).

   A mix scatters, at each hit, with one of its two materials: the second with
   probability "amount" (a constant or a float texture), by a hash of the hit
   point and wo.  Checked: the frequencies of the choice (a binomial bound), a
   textured amount and a mix of mixes; the image of a mix of two diffuse
   reflectances against the amount-weighted images of each; bit-identical images
   for any thread count; a "string normalmap" on a mix (and an interface) read
   and ignored, as pbrt-v4; the refusals by message; pbrt-v4's image of a small
   scene, frozen. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static const char *const MIX_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 0 0 0 ]\n";

/* A square (x in [x0, x0 + 2], y in [-2, 2], z = 0) with uv over it. */
#define MIX_SQUARE(x0, x1) "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ " \
    x0 " -2 0  " x1 " -2 0  " x1 " 2 0  " x0 " 2 0 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"

static int load_mix(T *t, Scene *s, const char *body)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", MIX_HEAD, body);
    return test_load_scene(t, s, buf);
}

/* n choices at random points and directions with (u, v): how many took material want. */
static long count_choices(const Scene *s, int mi, float u, float v, int want, long n, Rng *r)
{
    long i, hits = 0;
    SurfacePoint sp;
    memset(&sp, 0, sizeof sp);
    sp.u = u;
    sp.v = v;
    for (i = 0; i < n; i++) {
        float q[5];
        Vec3 wo;
        rng_fill(r, q, 5);
        sp.p = v3(4.0f * q[0] - 2.0f, 4.0f * q[1] - 2.0f, 0.0f);
        wo = v3_norm(v3(q[2] - 0.5f, q[3] - 0.5f, 0.1f + q[4]));
        hits += mat_choose(s->materials, mi, &sp, wo) == want;
    }
    return hits;
}

/* Within 5 binomial standard errors of n p. */
static int binomial_ok(long hits, long n, double p)
{
    return fabs((double)hits - n * p) <= 5.0 * sqrt(n * p * (1.0 - p)) + 1e-9;
}

/* The choice's frequencies: a constant amount 0.3 takes the second material 30 %
   of the time; a checkerboard amount (0 and 0.7, 2 x 2 cells over uv) never takes
   it in a 0 cell and 70 % in a 0.7 cell; a mix of (a, a mix of (b, c) at 0.5) at
   0.4 takes c 20 %, b 20 %, a 60 % (the two hashes independent); amounts 0 and 1
   choose without a hash; the amount is 0.5 by default; a Material "mix" may name a
   material made further down the file.  Also: the same hit always chooses the same material. */
static void test_mix_choice_frequencies(T *t)
{
    Scene s;
    Rng r;
    const long n = test_scaled(20000, 4000);
    int m0, m1, m2, m3, a, b, c, inner;
    long h;
    if (!load_mix(t, &s,
                  "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                  "MakeNamedMaterial \"b\" \"string type\" \"conductor\"\n"
                  "MakeNamedMaterial \"c\" \"string type\" \"dielectric\"\n"
                  "MakeNamedMaterial \"bc\" \"string type\" \"mix\" \"string materials\" [ \"b\" \"c\" ]\n"
                  "Texture \"amt\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 "
                  "\"float tex1\" 0 \"float tex2\" 0.7\n"
                  "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" 0.3\n" MIX_SQUARE("-2", "0")
                  "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"texture amount\" \"amt\"\n" MIX_SQUARE("0", "2")
                  "Material \"mix\" \"string materials\" [ \"a\" \"bc\" ] \"float amount\" 0.4\n" MIX_SQUARE("2", "4")
                  "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" 1\n" MIX_SQUARE("4", "6")
                  "Material \"mix\" \"string materials\" [ \"a\" \"b\" ]\n" MIX_SQUARE("6", "8")
                  "Material \"mix\" \"string materials\" [ \"late\" \"b\" ]\n" MIX_SQUARE("8", "10")
                  "MakeNamedMaterial \"late\" \"string type\" \"coateddiffuse\"\n"))
        return;
    m0 = s.shapes[0].material; m1 = s.shapes[1].material;
    m2 = s.shapes[2].material; m3 = s.shapes[3].material;
    a = s.materials[m0].mix[0]; b = s.materials[m0].mix[1];
    inner = s.materials[m2].mix[1];
    c = s.materials[inner].mix[1];
    CHECK(t, s.materials[m0].type == MAT_MIX && s.materials[a].type == MAT_DIFFUSE &&
          s.materials[b].type == MAT_CONDUCTOR && s.materials[inner].type == MAT_MIX &&
          s.materials[c].type == MAT_DIELECTRIC, "the mixes are not built as written");
    {   /* a name made after the Material "mix" that uses it */
        int late = s.materials[s.shapes[5].material].mix[0];
        CHECK(t, late >= 0 && late < s.n_materials && s.materials[late].type == MAT_COATED_DIFFUSE,
              "a forward name: the mix's first material is %d", late);
    }
    rng_seed(&r, 11, 3);
    h = count_choices(&s, m0, 0.5f, 0.5f, b, n, &r);
    CHECK(t, binomial_ok(h, n, 0.3), "amount 0.3: the second material %ld of %ld times", h, n);
    {
        long ha, hb;
        rng_seed(&r, 12, 0);
        ha = count_choices(&s, m0, 0.5f, 0.5f, a, n, &r);
        rng_seed(&r, 12, 0);
        hb = count_choices(&s, m0, 0.5f, 0.5f, b, n, &r);
        CHECK(t, ha + hb == n, "amount 0.3: %ld of %ld choices are neither material", n - ha - hb, n);
    }
    h = count_choices(&s, m1, 0.25f, 0.25f, b, n, &r);           /* a cell of amount 0 */
    CHECK(t, h == 0, "textured amount 0: the second material %ld times", h);
    h = count_choices(&s, m1, 0.75f, 0.25f, b, n, &r);           /* a cell of amount 0.7 */
    CHECK(t, binomial_ok(h, n, 0.7), "textured amount 0.7: the second material %ld of %ld times", h, n);
    h = count_choices(&s, m2, 0.5f, 0.5f, c, n, &r);
    CHECK(t, binomial_ok(h, n, 0.2), "mix of mixes: c %ld of %ld times (want 20 %%)", h, n);
    h = count_choices(&s, m2, 0.5f, 0.5f, b, n, &r);
    CHECK(t, binomial_ok(h, n, 0.2), "mix of mixes: b %ld of %ld times (want 20 %%)", h, n);
    h = count_choices(&s, m3, 0.5f, 0.5f, b, n, &r);
    CHECK(t, h == n, "amount 1: the second material %ld of %ld times", h, n);
    h = count_choices(&s, s.shapes[4].material, 0.5f, 0.5f, b, n, &r);
    CHECK(t, binomial_ok(h, n, 0.5), "amount by default (0.5): the second material %ld of %ld times", h, n);
    {
        SurfacePoint sp;
        Vec3 wo = v3_norm(v3(0.3f, -0.2f, 1.0f));
        int first, i;
        memset(&sp, 0, sizeof sp);
        sp.p = v3(-1.25f, 0.5f, 0.0f);
        first = mat_choose(s.materials, m0, &sp, wo);
        for (i = 0; i < 8; i++)
            CHECK(t, mat_choose(s.materials, m0, &sp, wo) == first, "the same hit chose two materials");
    }
    scene_free(&s);
}

/* A mix's textured amount on a whole sphere reads pbrt-v4's sphere (u, v): a hit at
   the sphere's +x side (object phi = 0) has u = 0, v = 0.5, and at +y u = 0.25. */
static void test_mix_sphere_uv(T *t)
{
    Scene s;
    Ray r;
    HitRecord h;
    SurfacePoint sp;
    if (!load_mix(t, &s, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                  "Texture \"amt\" \"float\" \"checkerboard\" \"float uscale\" 8\n"
                  "Material \"mix\" \"string materials\" [ \"a\" \"a\" ] \"texture amount\" \"amt\"\n"
                  "Shape \"sphere\"\n"))
        return;
    r.o = v3(0, 5, 0);
    r.d = v3(0, -1, 0);
    r.tmax = INFINITY;
    CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "the ray missed the sphere");
    scene_surface_point(&s, &r, &h, &sp);
    CHECK(t, fabsf(sp.u - 0.25f) < 1e-4f && fabsf(sp.v - 0.5f) < 1e-4f,
          "sphere under a mix: (u, v) = (%g, %g), want (0.25, 0.5)", sp.u, sp.v);
    scene_free(&s);
}

static int render_Y(T *t, const char *body, int spp, int seed, int threads, Image *im)
{
    static char buf[8192];
    RenderOptions o;
    snprintf(buf, sizeof buf, "%s%s", MIX_HEAD, body);
    render_options_default(&o);
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    return test_render_text(t, buf, &o, im);
}

/* A square of "mix" of two grey diffuse reflectances (0.2 and 0.8, amount 0.3)
   under a distant light: its image mean is 0.7 x the image of the 0.2 square +
   0.3 x that of the 0.8 one (each lit the same, the choice's mean being the
   amount), within 5 standard errors over 8 seeds.  The reflectance 0.2 is the
   mix's second material named by a forward name (made after the Material "mix"). */
static void test_mix_image_mean(T *t)
{
    static const char *const grey[2] = {
        "Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.2 0.2 ]\n" MIX_SQUARE("-2", "2"),
        "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n" MIX_SQUARE("-2", "2"),
    };
    static const char *const mix =
        "MakeNamedMaterial \"hi\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n"
        "Material \"mix\" \"string materials\" [ \"lo\" \"hi\" ] \"float amount\" 0.3\n" MIX_SQUARE("-2", "2")
        "MakeNamedMaterial \"lo\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.2 0.2 0.2 ]\n";
    const int K = 8, spp = test_scaled(4, 1);
    double y[2], sum = 0.0, sum2 = 0.0, mean, se, want;
    int k;
    Image im;
    for (k = 0; k < 2; k++) {
        if (!render_Y(t, grey[k], spp, 1, 2, &im)) return;
        y[k] = test_image_y(&im);
        img_free(&im);
    }
    for (k = 0; k < K; k++) {
        double v;
        if (!render_Y(t, mix, spp, 1 + 1000 * k, 2, &im)) return;
        v = test_image_y(&im);
        img_free(&im);
        sum += v;
        sum2 += v * v;
    }
    mean = sum / K;
    se = sqrt(fmax(0.0, (sum2 / K - mean * mean) * K / (K - 1)) / K);
    want = 0.7 * y[0] + 0.3 * y[1];
    CHECK(t, y[1] > 3.9 * y[0] && y[1] < 4.1 * y[0], "the grey squares: Y %g and %g", y[0], y[1]);
    CHECK(t, se > 0.0 && fabs(mean - want) < TEST_K_SIGMA * se,
          "mix image Y %.5f +- %.2g, want 0.7 x %.5f + 0.3 x %.5f = %.5f", mean, se, y[0], y[1], want);
}

/* The choice depends on the hit alone: the images of 1, 2 and 3 threads are the
   same bits (a glass-or-diffuse area light, a textured mix of mixes on a sphere). */
static void test_mix_threads(T *t)
{
    static const char *const body =
        "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
        "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\"\n"
        "MakeNamedMaterial \"metal\" \"string type\" \"conductor\" \"float roughness\" 0.2\n"
        "MakeNamedMaterial \"inner\" \"string type\" \"mix\" \"string materials\" [ \"red\" \"metal\" ] "
        "\"float amount\" 0.6\n"
        "Texture \"amt\" \"float\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 4 "
        "\"float tex1\" 0 \"float tex2\" 0.75\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
        "Material \"mix\" \"string materials\" [ \"glass\" \"red\" ]\nTranslate 0 0 3\nReverseOrientation\n"
        "Shape \"disk\" \"float radius\" 0.7\nAttributeEnd\n"
        "AttributeBegin\nMaterial \"mix\" \"string materials\" [ \"inner\" \"glass\" ] \"texture amount\" \"amt\"\n"
        "Shape \"sphere\" \"float radius\" 1.2\nAttributeEnd\n"
        "NamedMaterial \"inner\"\n" MIX_SQUARE("-2", "2");
    Image a, b, c;
    if (!render_Y(t, body, 4, 7, 1, &a)) return;
    if (!render_Y(t, body, 4, 7, 2, &b)) { img_free(&a); return; }
    if (!render_Y(t, body, 4, 7, 3, &c)) { img_free(&a); img_free(&b); return; }
    CHECK(t, test_image_y(&a) > 0.0, "the scene is black");
    CHECK(t, !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * a.w * a.h) &&
          !memcmp(a.rgb, c.rgb, sizeof(float) * 3 * a.w * a.h),
          "images of 1, 2, 3 threads differ: Y %.9g %.9g %.9g", test_image_y(&a), test_image_y(&b), test_image_y(&c));
    img_free(&a); img_free(&b); img_free(&c);
}

/* "string normalmap" on a mix and on an interface: read and ignored, as pbrt-v4
   (MixMaterial has no normal map of its own, an interface no surface; pbrt-v4's
   image of a mix over a floor with a normal map tilting n by 37 degrees keeps
   its mean, 0.1578 against 0.1580 and 0.1584 in two renders without, while the
   diffuse floor's own map moves it from 0.2409 to 0.1908; its interface sphere's
   image is the same bits): each loads without a bump record and renders the
   image without it, bit for bit. */
static void test_mix_normalmap_ignored(T *t)
{
    static const char *const mix =
        "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.8 0.2 0.2 ]\n"
        "MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.2 0.2 0.8 ]\n"
        "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" 0.3 %s\n" MIX_SQUARE("-2", "2")
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ 1 1 1 ] "
        "\"rgb sigma_s\" [ 1 1 1 ]\nMediumInterface \"fog\" \"\"\nMaterial \"interface\" %s\n"
        "AttributeBegin\nTranslate 0 0 0.5\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n";
    char a[4096], b[4096], nm[1100];
    Image x, y;
    Scene s;
    int i, bumped = 0;
    snprintf(nm, sizeof nm, "\"string normalmap\" \"%s\"", test_write_file(t, "tilt.pfm", "PF\n1 1\n-1\n"));
    snprintf(a, sizeof a, mix, "", "");
    snprintf(b, sizeof b, mix, nm, nm);
    if (!load_mix(t, &s, b)) return;
    for (i = 0; i < s.n_materials; i++) bumped += s.materials[i].bump != NULL;
    CHECK(t, bumped == 0, "%d materials given a normal map", bumped);
    scene_free(&s);
    if (!render_Y(t, a, 4, 3, 2, &x)) return;
    if (!render_Y(t, b, 4, 3, 2, &y)) { img_free(&x); return; }
    CHECK(t, test_image_y(&x) > 0.0 && !memcmp(x.rgb, y.rgb, sizeof(float) * 3 * x.w * x.h),
          "with the normal maps Y %.9g, without %.9g", test_image_y(&y), test_image_y(&x));
    img_free(&x);
    img_free(&y);
}

static void expect_error(T *t, const char *body, const char *want)
{
    test_refused(t, MIX_HEAD, body, "mix.pbrt", want);
}

/* pbrt-v4's refusals, each at its file:line: not two names; a name not made (a named
   mix sees only the materials made before it, a Material "mix" all of them); an
   interface as an element; an amount naming a spectrum texture; a parameter a mix
   does not read. */
static void test_mix_errors(T *t)
{
    expect_error(t, "Material \"interface\" \"string normalmap\" \"nothere.pfm\"\n",
                 "mix.pbrt:9: Material \"interface\": \"string normalmap\" \"nothere.pfm\": cannot open "
                 "the file (pbrt-v4 reads it here too, and stops)");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "Material \"mix\" \"string materials\" [ \"a\" ]\n",
                 "mix.pbrt:10: Material \"mix\": \"string materials\" must name two materials (1 given)");
    if (t->failed) return;
    expect_error(t, "Material \"mix\" \"float amount\" 0.5\n",
                 "mix.pbrt:9: Material \"mix\": \"string materials\" must name two materials (0 given)");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [ \"a\" \"b\" ]\n"
                 "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n",
                 "mix.pbrt:9: MakeNamedMaterial \"m\": type \"mix\": named material \"a\" not found "
                 "(a named \"mix\" can only use materials made before it)");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "Material \"mix\" \"string materials\" [ \"a\" \"nothere\" ]\nShape \"sphere\"\n",
                 "mix.pbrt:10: Material \"mix\": named material \"nothere\" not found");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "MakeNamedMaterial \"b\" \"string type\" \"interface\"\n"
                 "Material \"mix\" \"string materials\" [ \"a\" \"b\" ]\n",
                 "mix.pbrt:11: Material \"mix\": \"b\": an \"interface\" material cannot be used as an "
                 "element of the \"mix\" material");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "Material \"mix\" \"string materials\" [ \"b\" \"a\" ]\n"
                 "MakeNamedMaterial \"b\" \"string type\" \"interface\"\n",
                 "mix.pbrt:10: Material \"mix\": \"b\": an \"interface\" material cannot be used as an "
                 "element of the \"mix\" material");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "Texture \"k\" \"spectrum\" \"constant\"\n"
                 "Material \"mix\" \"string materials\" [ \"a\" \"a\" ] \"texture amount\" \"k\"\n",
                 "mix.pbrt:11: \"texture amount\": \"k\" is a spectrum texture; a float one is needed here");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "Material \"mix\" \"string materials\" [ \"a\" \"a\" ] \"rgb reflectance\" [ 1 1 1 ]\n",
                 "mix.pbrt:10: \"rgb reflectance\": unused parameter (Material \"mix\" reads: "
                 "string materials, float amount, texture amount, string normalmap)");
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 256` for S = 1..8, the
   independent sampler) rendered MIX_HEAD with two squares side by side: a mix of
   rgb 0.2 and rgb (0.8 0.7 0.6) at amount 0.3, and the same two under a checkerboard
   amount (0.1 and 0.9, 4 x 4 cells over uv).  Luminance of the image and of its
   2 x 2 quadrants (top left first; pbrt-v4's camera shows world +x on the left),
   mean over the seeds and its standard error.  pbrt-v4 hashes other bytes (its
   material pointers) than specnee, so only the means can agree: within 5 standard
   errors + 1 % (the RGB fits of the two renderers). */
static const double PBRT_MIX_Y[5][2] = {
    { 0.390721, 0.00017 },
    { 0.438746, 0.00019 }, { 0.341012, 0.00020 }, { 0.442319, 0.00021 }, { 0.340806, 0.00044 },
};

static void test_mix_against_pbrt(T *t)
{
    Scene s;
    if (!load_mix(t, &s,
                  "MakeNamedMaterial \"dark\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.2 0.2 0.2 ]\n"
                  "MakeNamedMaterial \"bright\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.8 0.7 0.6 ]\n"
                  "Texture \"amt\" \"float\" \"checkerboard\" \"float uscale\" [ 4 ] \"float vscale\" [ 4 ] "
                  "\"float tex1\" [ 0.1 ] \"float tex2\" [ 0.9 ]\n"
                  "MakeNamedMaterial \"m1\" \"string type\" \"mix\" \"string materials\" [ \"dark\" \"bright\" ] "
                  "\"float amount\" [ 0.3 ]\n"
                  "MakeNamedMaterial \"m2\" \"string type\" \"mix\" \"string materials\" [ \"dark\" \"bright\" ] "
                  "\"texture amount\" \"amt\"\n"
                  "NamedMaterial \"m1\"\n" MIX_SQUARE("-2", "0") "NamedMaterial \"m2\"\n" MIX_SQUARE("0", "2")))
        return;
    test_scene_against_pbrt_y(t, &s, test_scaled(32, 8), 3, PBRT_MIX_Y, 1e-2, "mix");
    scene_free(&s);
}

const TestCase tests_mix[] = {
    { "mix_normalmap_ignored", test_mix_normalmap_ignored },
    { "mix_choice_frequencies", test_mix_choice_frequencies },
    { "mix_sphere_uv", test_mix_sphere_uv },
    { "mix_image_mean", test_mix_image_mean },
    { "mix_threads", test_mix_threads },
    { "mix_errors", test_mix_errors },
    { "mix_against_pbrt", test_mix_against_pbrt },
    { NULL, NULL }
};
