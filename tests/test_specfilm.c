/* tests/test_specfilm.c - pbrt-v4's Film "spectral" (render.c's buckets and
   img_write_spectral) and the OpenEXR writer under it (exr.c).

   The float to half rounding is exact on known values (1, 65504, the overflow
   and underflow edges, subnormals, ties to even) and on every binary16 number;
   written files parse back through exr.c's own reader with their values, sorted
   channel list, windows and strings.  The buckets of a blackbody sky seen
   directly, and of a diffuse sphere with a step reflectance under a constant sky,
   equal the analytic band averages of L CIE_Y_INTEGRAL within 5 standard errors;
   the spectral film's RGB equals the rgb film's (another wavelength pdf: the same
   expectation); a small scene's buckets and RGB equal pbrt-v4's, frozen; and bad
   input is refused with one file:line line. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* ---- the half conversion ---- */

static void test_specfilm_half_values(T *t)
{
    static const struct { float f; unsigned h; } v[] = {
        { 1.0f, 0x3c00 }, { -2.0f, 0xc000 }, { 0.0f, 0x0000 }, { 65504.0f, 0x7bff },
        { 65519.99f, 0x7bff },              /* below the midpoint to 65536: the largest half */
        { 65520.0f, 0x7c00 },               /* the midpoint, odd mantissa: up, to infinity */
        { 1e6f, 0x7c00 }, { -1e6f, 0xfc00 },
        { 6.103515625e-05f, 0x0400 },       /* 2^-14, the smallest normal */
        { 5.9604644775390625e-08f, 0x0001 },/* 2^-24, the smallest subnormal */
        { 2.98023223876953125e-08f, 0x0000 },  /* 2^-25: a tie between 0 and 2^-24, to even 0 */
        { 8.94069671630859375e-08f, 0x0002 },  /* 1.5 2^-24: a tie, to even 2 */
        { 1.4901161193847656e-07f, 0x0002 },   /* 2.5 2^-24: a tie, to even 2 */
        { 6.0975551605224609e-05f, 0x03ff },   /* 1023 2^-24, the largest subnormal */
        { 6.1005353927612305e-05f, 0x0400 },   /* 1023.5 2^-24: a tie, to even 1024 */
        { 1.00048828125f, 0x3c00 },         /* 1 + 2^-11: a tie, to even */
        { 1.00146484375f, 0x3c02 },         /* 1 + 3 2^-11: a tie, to even (up) */
        { 1.0009765625f, 0x3c01 },          /* 1 + 2^-10: exact */
        { 2047.0f, 0x67ff }, { 2049.0f, 0x6800 },  /* ties at 2^11 .. 2^12 */
        { 2051.0f, 0x6802 },
    };
    size_t i;
    unsigned h;
    for (i = 0; i < sizeof v / sizeof v[0]; i++)
        CHECK(t, exr_float_to_half(v[i].f) == v[i].h, "half(%.10g) = 0x%04x, want 0x%04x",
              (double)v[i].f, exr_float_to_half(v[i].f), v[i].h);
    CHECK(t, exr_float_to_half(nextafterf(2.98023223876953125e-08f, 1.0f)) == 0x0001,
          "half(just above 2^-25) = 0x%04x, want 0x0001", exr_float_to_half(nextafterf(2.98023223876953125e-08f, 1.0f)));
    CHECK(t, exr_float_to_half(-0.0f) == 0x8000, "half(-0) = 0x%04x", exr_float_to_half(-0.0f));
    CHECK(t, exr_float_to_half(INFINITY) == 0x7c00 && exr_float_to_half(-INFINITY) == 0xfc00,
          "half(+-inf) = 0x%04x 0x%04x", exr_float_to_half(INFINITY), exr_float_to_half(-INFINITY));
    h = exr_float_to_half(NAN);
    CHECK(t, (h & 0x7c00) == 0x7c00 && (h & 0x3ff) != 0, "half(NaN) = 0x%04x is no NaN", h);
    /* every finite half is its own nearest; halfway up to the next one rounds to
       the even of the two, and just below halfway down */
    for (h = 0; h < 0x7c00; h++) {
        float a = exr_half_to_float(h), b = exr_half_to_float(h + 1), mid = 0.5f * (a + b);
        unsigned even = (h & 1) ? h + 1 : h;
        CHECK(t, exr_float_to_half(a) == h && exr_float_to_half(-a) == (h | 0x8000),
              "half(%.10g) = 0x%04x, want 0x%04x", (double)a, exr_float_to_half(a), h);
        if (h == 0x7bff) break;              /* its midpoint, 65520, is checked above */
        CHECK(t, exr_float_to_half(mid) == even, "half(midpoint %.10g) = 0x%04x, want 0x%04x",
              (double)mid, exr_float_to_half(mid), even);
        CHECK(t, exr_float_to_half(nextafterf(mid, 0.0f)) == h, "half(below %.10g) = 0x%04x, want 0x%04x",
              (double)mid, exr_float_to_half(nextafterf(mid, 0.0f)), h);
    }
}

/* ---- the writer ---- */

/* The value of attribute name (type type) in the header of d[0 .. n): a pointer and
   its size, NULL if absent. */
static const unsigned char *attr(const unsigned char *d, size_t n, const char *name, const char *type,
                                 long *size)
{
    size_t p = 8;
    while (p < n && d[p]) {
        const char *an = (const char *)d + p, *at = an + strlen(an) + 1;
        const unsigned char *v = (const unsigned char *)at + strlen(at) + 5;
        long s = (long)(v[-4] | v[-3] << 8 | v[-2] << 16 | (unsigned long)v[-1] << 24);
        if (!strcmp(an, name) && !strcmp(at, type)) { *size = s; return v; }
        p = (size_t)(v - d) + (size_t)s;
    }
    return NULL;
}

static long le32_at(const unsigned char *v) { return (long)(int32_t)(v[0] | v[1] << 8 | v[2] << 16 | (uint32_t)v[3] << 24); }

/* 5 x 3 pixels, channels given out of order, HALF and FLOAT: read back (R G B, and
   named), the channel list sorted, the windows and the strings as given. */
static void test_specfilm_exr_roundtrip(T *t)
{
    static const char *const names[5] = { "S0.500,000nm", "R", "B", "S0.400,000nm", "G" };
    static const char *const keys[1] = { "spectralLayoutVersion" }, *const vals[1] = { "1.0" };
    static const char *const want[3] = { "S0.400,000nm", "S0.500,000nm", "S0.400,000nm" };
    float v[5 * 3 * 5];
    int half, i, k;
    for (i = 0; i < 15; i++)
        for (k = 0; k < 5; k++) v[5 * i + k] = (float)(i * 7 + k) * 0.3f - 4.0f + (i == 4 ? 1e-6f : 0.0f);
    for (half = 0; half < 2; half++) {
        ExrWrite x;
        Image im, sp;
        Error err;
        size_t n = 0;
        long size;
        const unsigned char *a;
        unsigned char *d;
        memset(&x, 0, sizeof x);
        x.w = 5; x.h = 3; x.x0 = 2; x.y0 = 1; x.full_w = 9; x.full_h = 6;
        x.n_ch = 5; x.names = names; x.v = v; x.half = half;
        x.n_str = 1; x.str_key = keys; x.str_val = vals;
        d = exr_write_memory(&x, &n);
        CHECK(t, d != NULL, "exr_write_memory failed");
        a = attr(d, n, "channels", "chlist", &size);
        CHECK(t, a && !strcmp((const char *)a, "B") && !strcmp((const char *)a + 18, "G") &&
              !strcmp((const char *)a + 36, "R") && !strcmp((const char *)a + 54, "S0.400,000nm") &&
              le32_at(a + 2) == (half ? 1 : 2), "channel list not B G R S0.400 S0.500 of type %d", half ? 1 : 2);
        a = attr(d, n, "dataWindow", "box2i", &size);
        CHECK(t, a && size == 16 && le32_at(a) == 2 && le32_at(a + 4) == 1 && le32_at(a + 8) == 6 &&
              le32_at(a + 12) == 3, "dataWindow not (2, 1) - (6, 3)");
        a = attr(d, n, "displayWindow", "box2i", &size);
        CHECK(t, a && le32_at(a + 8) == 8 && le32_at(a + 12) == 5, "displayWindow not (0, 0) - (8, 5)");
        a = attr(d, n, "spectralLayoutVersion", "string", &size);
        CHECK(t, a && size == 3 && !memcmp(a, "1.0", 3), "no spectralLayoutVersion \"1.0\"");
        CHECK(t, attr(d, n, "compression", "compression", &size) && attr(d, n, "lineOrder", "lineOrder", &size) &&
              attr(d, n, "pixelAspectRatio", "float", &size) && attr(d, n, "screenWindowCenter", "v2f", &size) &&
              attr(d, n, "screenWindowWidth", "float", &size), "a required attribute is missing");
        err.msg[0] = 0;
        if (!exr_read_memory(d, n, "w.exr", &im, &err) ||
            !exr_read_memory_named(d, n, "w.exr", want, &sp, &err)) {
            free(d);
            CHECK(t, 0, "the written file does not parse: %s", err.msg);
        }
        free(d);
        for (i = 0; i < 15; i++)
            for (k = 0; k < 3; k++) {
                static const int src[3] = { 1, 4, 2 }, nsrc[3] = { 3, 0, 3 };
                float w = v[5 * i + src[k]], ws = v[5 * i + nsrc[k]];
                if (half) { w = exr_half_to_float(exr_float_to_half(w)); ws = exr_half_to_float(exr_float_to_half(ws)); }
                if (im.rgb[3 * i + k] != w || sp.rgb[3 * i + k] != ws) {
                    img_free(&im); img_free(&sp);
                    CHECK(t, 0, "half %d pixel %d channel %d: %g %g, want %g %g", half, i, k,
                          (double)im.rgb[3 * i + k], (double)sp.rgb[3 * i + k], (double)w, (double)ws);
                }
            }
        CHECK(t, im.w == 5 && im.h == 3, "read %d x %d", im.w, im.h);
        img_free(&im);
        img_free(&sp);
    }
    {   /* a missing named channel is one line naming it */
        static const char *const bad[3] = { "R", "S0.1", "B" };
        Image im;
        Error err;
        const char *p = test_path(t, "spec_missing.exr");
        ExrWrite x;
        memset(&x, 0, sizeof x);
        x.w = 5; x.h = 3; x.full_w = 5; x.full_h = 3; x.n_ch = 5; x.names = names; x.v = v;
        CHECK(t, exr_write(p, &x, &err), "exr_write: %s", err.msg);
        CHECK(t, !exr_read_named(&im, p, bad, &err) && strstr(err.msg, "EXR: no channel \"S0.1\""),
              "want no channel \"S0.1\": %s", err.msg);
    }
}

/* img_write_spectral of a cropped film: the channels R G B and pbrt-v4's bucket
   names, the values (HALF: clamped to 65504 first), the data window the crop. */
static void test_specfilm_write_film(T *t)
{
    Scene s;
    Image im, back;
    Error err;
    float b[6 * 4 * 2];
    int i;
    const char *p = test_path(t, "spec_film.exr");
    static const char *const want[3] = { "S0.450,000nm", "S0.610,000nm", "R" };
    if (!test_load_scene(t, &s, "Film \"spectral\" \"integer xresolution\" [8] \"integer yresolution\" [4]\n"
                         "  \"integer pixelbounds\" [1 7 2 4] \"integer nbuckets\" [2]\n"
                         "  \"float lambdamin\" [370] \"float lambdamax\" [690] \"string filename\" \"a.exr\"\n"
                         "WorldBegin\n"))
        return;
    CHECK(t, img_alloc(&im, 6, 2), "no memory");
    for (i = 0; i < 12; i++) {
        im.rgb[3 * i] = (float)i; im.rgb[3 * i + 1] = 1e5f; im.rgb[3 * i + 2] = -1.0f;
        b[2 * i] = 0.25f * (float)i; b[2 * i + 1] = i == 3 ? 7e4f : 2.0f;
    }
    err.msg[0] = 0;
    if (!img_write_spectral(&im, b, &s.settings, p, &err) || !exr_read_named(&back, p, want, &err)) {
        img_free(&im); scene_free(&s);
        CHECK(t, 0, "spectral EXR not written or read: %s", err.msg);
    }
    for (i = 0; i < 12 && !t->failed; i++)
        if (back.rgb[3 * i] != 0.25f * (float)i || back.rgb[3 * i + 1] != (i == 3 ? 65504.0f : 2.0f) ||
            back.rgb[3 * i + 2] != (float)i)
            test_failf(t, __FILE__, __LINE__, "pixel %d: %g %g %g", i, (double)back.rgb[3 * i],
                       (double)back.rgb[3 * i + 1], (double)back.rgb[3 * i + 2]);
    img_free(&back);
    {   /* the crop is the data window, the whole film the display window */
        static unsigned char d[4096];
        FILE *f = fopen(p, "rb");
        size_t n = f ? fread(d, 1, sizeof d, f) : 0;
        long size;
        const unsigned char *a = attr(d, n, "dataWindow", "box2i", &size), *dw;
        if (f) fclose(f);
        dw = attr(d, n, "displayWindow", "box2i", &size);
        if (!a || !dw || le32_at(a) != 1 || le32_at(a + 4) != 2 || le32_at(a + 8) != 6 || le32_at(a + 12) != 3 ||
            le32_at(dw) != 0 || le32_at(dw + 4) != 0 || le32_at(dw + 8) != 7 || le32_at(dw + 12) != 3) {
            img_free(&im); scene_free(&s);
            CHECK(t, 0, "data window not (1, 2) - (6, 3) or display window not (0, 0) - (7, 3)");
        }
        a = attr(d, n, "emissiveUnits", "string", &size);
        if (!a || size != 12 || memcmp(a, "W.m^-2.sr^-1", 12) != 0) {
            img_free(&im); scene_free(&s);
            CHECK(t, 0, "no emissiveUnits \"W.m^-2.sr^-1\"");
        }
    }
    s.settings.savefp16 = 0;                 /* FLOAT: no clamp */
    if (!img_write_spectral(&im, b, &s.settings, p, &err) || !exr_read(&back, p, &err)) {
        img_free(&im); scene_free(&s);
        CHECK(t, 0, "float EXR not written or read: %s", err.msg);
    }
    CHECK(t, back.w == 6 && back.h == 2 && back.rgb[1] == 1e5f && back.rgb[3 * 5] == 5.0f,
          "float: %d x %d, G %g", back.w, back.h, (double)back.rgb[1]);
    img_free(&back);
    img_free(&im);
    scene_free(&s);
}

/* ---- the buckets ---- */

/* Render s's spectral film (independent sampler, spp, seed): mean and standard
   error over the pixels of each bucket (nb) and of R, G, B (after the buckets). */
static int render_means(T *t, Scene *s, int spp, int seed, double *mean, double *se)
{
    RenderOptions o;
    RenderStats st;
    Image img;
    Error err;
    float *b = NULL;
    int nb = s->settings.nbuckets, k;
    size_t i, n;
    render_options_default(&o);
    o.spp = spp;
    o.seed = seed;
    o.sampler = SAMPLER_INDEPENDENT;
    err.msg[0] = 0;
    if (!render_spectral(s, &o, &img, &b, &st, &err)) {
        test_failf(t, __FILE__, __LINE__, "render_spectral: %s", err.msg);
        return 0;
    }
    n = (size_t)img.w * (size_t)img.h;
    for (k = 0; k < nb + 3; k++) {
        double s1 = 0.0, s2 = 0.0;
        for (i = 0; i < n; i++) {
            double v = k < nb ? b[(size_t)nb * i + (size_t)k] : img.rgb[3 * i + (size_t)(k - nb)];
            s1 += v; s2 += v * v;
        }
        mean[k] = s1 / (double)n;
        se[k] = sqrt(fmax(0.0, s2 / (double)n - mean[k] * mean[k]) / (double)(n - 1));
    }
    free(b);
    img_free(&img);
    return 1;
}

/* The band average of f over bucket k of nb over [lo, hi] (midpoint rule, 0.01 nm). */
static double band_mean(double (*f)(double), double lo, double hi, int nb, int k)
{
    double a = lo + (hi - lo) * k / nb, b = lo + (hi - lo) * (k + 1) / nb, s = 0.0;
    int i, m = (int)((b - a) * 100.0);
    for (i = 0; i < m; i++) s += f(a + (b - a) * (i + 0.5) / m);
    return s / m;
}

static double planck4000(double lambda) { return blackbody_eval(4000.0f, (float)lambda); }

/* The sky seen directly: bucket k = the band mean of B(lambda) CIE_Y / sum ybar B,
   the blackbody normalised as pbrt-v4 normalises a light (sum over 360..830 nm). */
static void test_specfilm_blackbody_seen(T *t)
{
    Scene s;
    double mean[19], se[19], norm = 0.0;
    int k, lam;
    if (!test_load_scene(t, &s, "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\"\n"
                         "Film \"spectral\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
                         "  \"string filename\" \"sky.exr\"\n"
                         "WorldBegin\nLightSource \"infinite\" \"blackbody L\" [4000]\n"))
        return;
    CHECK(t, s.settings.nbuckets == 16 && s.settings.lambda_min == 360.0f && s.settings.lambda_max == 830.0f &&
          s.settings.savefp16 == 1, "pbrt-v4's defaults: %d buckets over %g..%g, fp16 %d",
          s.settings.nbuckets, (double)s.settings.lambda_min, (double)s.settings.lambda_max, s.settings.savefp16);
    if (!render_means(t, &s, test_scaled(64, 16), 1, mean, se)) { scene_free(&s); return; }
    scene_free(&s);
    for (lam = SPEC_MIN; lam <= SPEC_MAX; lam++) norm += cie_ybar(lam) * blackbody_eval(4000.0f, (float)lam);
    for (k = 0; k < 16; k++) {
        double want = band_mean(planck4000, 360.0, 830.0, 16, k) * CIE_Y_INTEGRAL / norm;
        if (getenv("DBG")) printf("bucket %d: %.6f +- %.6f, want %.6f\n", k, mean[k], se[k], want);
        CHECK(t, fabs(mean[k] - want) < TEST_K_SIGMA * se[k] + 1e-4 * want,
              "bucket %d: %.6f +- %.6f, want %.6f (5 standard errors)", k, mean[k], se[k], want);
    }
}

static double red_edge(double lambda) { return lambda <= 690.0 ? 0.0 : lambda >= 700.0 ? 1.0 : (lambda - 690.0) / 10.0; }

/* A sky that emits only above 690 nm seen directly: the buckets are the band
   means of S CIE_Y / sum ybar S over 360..830 nm, pbrt-v4's normalisation (over
   400..700 nm they would be about 30 times larger). */
static void test_specfilm_red_sky(T *t)
{
    Scene s;
    double mean[11], se[11], norm = 0.0;
    int k, lam;
    if (!test_load_scene(t, &s, "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\"\n"
                         "Film \"spectral\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
                         "  \"integer nbuckets\" [8] \"float lambdamin\" [620] \"string filename\" \"sky.exr\"\n"
                         "WorldBegin\nLightSource \"infinite\" \"spectrum L\" [360 0 690 0 700 1 830 1]\n"))
        return;
    if (!render_means(t, &s, test_scaled(64, 16), 5, mean, se)) { scene_free(&s); return; }
    scene_free(&s);
    for (lam = SPEC_MIN; lam <= SPEC_MAX; lam++) norm += cie_ybar(lam) * red_edge(lam);
    for (k = 0; k < 8; k++) {
        double want = band_mean(red_edge, 620.0, 830.0, 8, k) * CIE_Y_INTEGRAL / norm;
        CHECK(t, fabs(mean[k] - want) <= TEST_K_SIGMA * se[k] + 1e-4 * want,
              "bucket %d: %.6f +- %.6f, want %.6f (5 standard errors)", k, mean[k], se[k], want);
    }
}

/* maxcomponentvalue scales a sample's four radiances together: under a constant
   sky of luminance 1 every lane is 1/sum ybar, above 0.005, so each of the two
   buckets (two lanes a sample each) is 0.005 CIE_Y exactly.  With 61 buckets and one sample a pixel, at most four are
   not empty, and the empty ones are 0. */
static void test_specfilm_clamp_and_empty(T *t)
{
    Scene s;
    RenderOptions o;
    RenderStats st;
    Image img;
    Error err;
    float *b = NULL;
    int pass;
    for (pass = 0; pass < 2; pass++) {
        size_t i, k;
        if (!test_load_scene(t, &s, pass == 0
                ? "Camera \"perspective\"\nFilm \"spectral\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
                  "  \"integer nbuckets\" [2] \"float maxcomponentvalue\" [0.005]\nWorldBegin\nLightSource \"infinite\" \"spectrum L\" [360 1 830 1]\n"
                : "Camera \"perspective\"\nFilm \"spectral\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
                  "  \"integer nbuckets\" [61]\nWorldBegin\nLightSource \"infinite\" \"spectrum L\" [360 1 830 1]\n"))
            return;
        render_options_default(&o);
        o.spp = pass == 0 ? 8 : 1;
        err.msg[0] = 0;
        if (!render_spectral(&s, &o, &img, &b, &st, &err)) { scene_free(&s); CHECK(t, 0, "render_spectral: %s", err.msg); }
        for (i = 0; i < 16 && !t->failed; i++) {
            int full = 0;
            for (k = 0; k < (size_t)s.settings.nbuckets; k++) {
                float v = b[(size_t)s.settings.nbuckets * i + k];
                if (pass == 0 && fabs(v - 0.005 * CIE_Y_INTEGRAL) > 1e-5)
                    test_failf(t, __FILE__, __LINE__, "pixel %d bucket %d: %g, want %g (clamped)", (int)i, (int)k,
                               (double)v, 0.005 * CIE_Y_INTEGRAL);
                full += v != 0.0f;
                if (!isfinite(v)) test_failf(t, __FILE__, __LINE__, "pixel %d bucket %d: %g", (int)i, (int)k, (double)v);
            }
            if (pass == 1 && (full < 1 || full > 4))
                test_failf(t, __FILE__, __LINE__, "pixel %d: %d buckets not empty of 61, want 1..4", (int)i, full);
        }
        free(b);
        img_free(&img);
        scene_free(&s);
    }
}

static double step_reflectance(double lambda)
{
    return lambda <= 500.0 ? 0.2 : lambda >= 520.0 ? 0.8 : 0.2 + 0.6 * (lambda - 500.0) / 20.0;
}

static const char *SPHERE_WORLD =
    "WorldBegin\nLightSource \"infinite\" \"spectrum L\" [360 1 830 1]\n"
    "Material \"diffuse\" \"spectrum reflectance\" [360 0.2 500 0.2 520 0.8 830 0.8]\n"
    "Shape \"sphere\" \"float radius\" [1]\n";

/* A convex diffuse sphere under a constant sky, one bounce: L = rho Le, through
   NEE and BSDF sampling with spectral MIS; bucket k = the band mean of rho times
   CIE_Y / sum ybar (the sky normalised to luminance 1), over 400..700 nm. */
static void test_specfilm_sphere_buckets(T *t)
{
    Scene s;
    double mean[13], se[13];
    char text[1024];
    int k;
    snprintf(text, sizeof text, "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [10]\n"
             "Integrator \"path\" \"integer maxdepth\" [1]\n"
             "Film \"spectral\" \"integer xresolution\" [12] \"integer yresolution\" [12]\n"
             "  \"string filename\" \"ball.exr\" \"integer nbuckets\" [10] \"float lambdamin\" [400]\n"
             "  \"float lambdamax\" [700]\n%s", SPHERE_WORLD);
    if (!test_load_scene(t, &s, text)) return;
    if (!render_means(t, &s, test_scaled(64, 16), 2, mean, se)) { scene_free(&s); return; }
    scene_free(&s);
    for (k = 0; k < 10; k++) {
        double want = band_mean(step_reflectance, 400.0, 700.0, 10, k) * CIE_Y_INTEGRAL /
                      cie_y_integral((float)SPEC_MIN, (float)SPEC_MAX);
        if (getenv("DBG")) printf("bucket %d: %.6f +- %.6f, want %.6f\n", k, mean[k], se[k], want);
        CHECK(t, fabs(mean[k] - want) < TEST_K_SIGMA * se[k] + 1e-4 * want,
              "bucket %d: %.6f +- %.6f, want %.6f (5 standard errors)", k, mean[k], se[k], want);
    }
}

/* The spectral film's R, G, B against the rgb film's (its mixture pdf over the same
   360..830 nm): the same expectation, within 5 combined standard errors. */
static void test_specfilm_rgb_as_rgb_film(T *t)
{
    static const char *head = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [10]\n"
                              "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [1]\n";
    Scene s;
    char text[1024];
    double mean[19], se[19], m[3] = { 0, 0, 0 }, m2[3] = { 0, 0, 0 };
    RenderOptions o;
    RenderStats st;
    Image img;
    Error err;
    int c, n;
    size_t i;
    snprintf(text, sizeof text, "%sFilm \"spectral\" \"integer xresolution\" [12] \"integer yresolution\" [12]\n"
             "  \"string filename\" \"ball.exr\"\n%s", head, SPHERE_WORLD);
    if (!test_load_scene(t, &s, text)) return;
    if (!render_means(t, &s, test_scaled(64, 16), 3, mean, se)) { scene_free(&s); return; }
    scene_free(&s);
    snprintf(text, sizeof text, "%sFilm \"rgb\" \"integer xresolution\" [12] \"integer yresolution\" [12]\n"
             "  \"string filename\" \"ball.pfm\"\n%s", head, SPHERE_WORLD);
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    o.seed = 4;
    o.sampler = SAMPLER_INDEPENDENT;
    o.wl_wide = 1;
    err.msg[0] = 0;
    if (!render(&s, &o, &img, &st, &err)) { scene_free(&s); CHECK(t, 0, "render: %s", err.msg); }
    scene_free(&s);
    n = img.w * img.h;
    for (i = 0; i < (size_t)n; i++)
        for (c = 0; c < 3; c++) { m[c] += img.rgb[3 * i + c]; m2[c] += (double)img.rgb[3 * i + c] * img.rgb[3 * i + c]; }
    img_free(&img);
    for (c = 0; c < 3; c++) {
        double mu = m[c] / n, s2 = sqrt(fmax(0.0, m2[c] / n - mu * mu) / (n - 1));
        double tol = TEST_K_SIGMA * sqrt(s2 * s2 + se[16 + c] * se[16 + c]);
        if (getenv("DBG")) printf("channel %d: spectral %.5f +- %.5f, rgb %.5f +- %.5f\n", c, mean[16 + c], se[16 + c], mu, s2);
        CHECK(t, fabs(mean[16 + c] - mu) < tol && mu > 0.05,
              "channel %d: spectral film %.5f +- %.5f, rgb film %.5f +- %.5f", c, mean[16 + c], se[16 + c], mu, s2);
    }
}

/* pbrt-v4 5f7a6068 (built as docs/real-scenes.md says; pbrt --seed 1..4 --spp 1024, each EXR read
   by exr_read_named; mean over the 16 x 16 pixels, then mean and standard error
   over the four seeds) of this scene: the 8 buckets over 400..720 nm, then R G B. */
static const char *FROZEN_SCENE =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [30]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [16]\n"
    "Integrator \"volpath\" \"integer maxdepth\" [1]\nPixelFilter \"box\"\n"
    "Film \"spectral\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
    "    \"string filename\" \"frozen.exr\" \"integer nbuckets\" [8] \"bool savefp16\" false\n"
    "    \"float lambdamin\" [400] \"float lambdamax\" [720]\n"
    "WorldBegin\nLightSource \"infinite\" \"blackbody L\" [4000]\n"
    "Material \"diffuse\" \"spectrum reflectance\" [360 0.2 500 0.2 520 0.8 830 0.8]\n"
    "Shape \"sphere\" \"float radius\" [1]\n";
static const double PBRT_FROZEN[11][2] = {
    { 0.319172, 0.000096 }, { 0.426138, 0.000120 }, { 0.584807, 0.000173 }, { 0.871118, 0.000053 },
    { 0.965511, 0.000062 }, { 1.033295, 0.000053 }, { 1.075847, 0.000051 }, { 1.096574, 0.000059 },
    { 1.313116, 0.000126 }, { 0.816164, 0.000079 }, { 0.306641, 0.000144 },
};

static void test_specfilm_pbrt_frozen(T *t)
{
    Scene s;
    double mean[11], se[11], sum[11], sum2[11];
    int seed, k, K = 4;
    if (!test_load_scene(t, &s, FROZEN_SCENE)) return;
    memset(sum, 0, sizeof sum);
    memset(sum2, 0, sizeof sum2);
    for (seed = 0; seed < K; seed++) {
        if (!render_means(t, &s, test_scaled(64, 16), 10 + seed, mean, se)) { scene_free(&s); return; }
        for (k = 0; k < 11; k++) { sum[k] += mean[k]; sum2[k] += mean[k] * mean[k]; }
    }
    scene_free(&s);
    for (k = 0; k < 11; k++) {
        double mu = sum[k] / K, sek = sqrt(fmax(0.0, sum2[k] / K - mu * mu) / (K - 1));
        double tol = TEST_K_SIGMA * sqrt(sek * sek + PBRT_FROZEN[k][1] * PBRT_FROZEN[k][1]) + 0.003 * PBRT_FROZEN[k][0];
        if (getenv("DBG")) printf("%d: specnee %.6f +- %.6f, pbrt-v4 %.6f +- %.6f, tol %.6f\n", k, mu, sek,
                                  PBRT_FROZEN[k][0], PBRT_FROZEN[k][1], tol);
        CHECK(t, fabs(mu - PBRT_FROZEN[k][0]) < tol, "%s %d: specnee %.6f +- %.6f, pbrt-v4 %.6f +- %.6f",
              k < 8 ? "bucket" : "RGB channel", k < 8 ? k : k - 8, mu, sek, PBRT_FROZEN[k][0], PBRT_FROZEN[k][1]);
    }
}

/* ---- bad input ---- */

static void test_specfilm_refused(T *t)
{
    static const char *head = "Camera \"perspective\"\n";
    Scene s;
    Error err;
    const char *p;
    test_refused(t, head, "Film \"spectral\" \"string filename\" \"out.png\"\nWorldBegin\n", "f.pbrt",
                 "f.pbrt:2: Film \"spectral\": \"out.png\": pbrt-v4 writes the spectral film as .exr only");
    test_refused(t, head, "Film \"spectral\"\n  \"float lambdamin\" [300]\nWorldBegin\n", "f.pbrt",
                 "f.pbrt:3: Film \"spectral\": wavelengths 300..830 nm: \"float lambdamin\" < \"float "
                 "lambdamax\" within pbrt-v4's range 360..830 nm");
    test_refused(t, head, "Film \"spectral\" \"float lambdamax\" [900]\nWorldBegin\n", "f.pbrt",
                 "f.pbrt:2: Film \"spectral\": wavelengths 360..900 nm");
    test_refused(t, head, "Film \"spectral\" \"float lambdamin\" [600]\n \"float lambdamax\" [500]\nWorldBegin\n",
                 "f.pbrt", "f.pbrt:3: Film \"spectral\": wavelengths 600..500 nm");
    test_refused(t, head, "Film \"spectral\" \"integer nbuckets\" [0]\nWorldBegin\n", "f.pbrt",
                 "f.pbrt:2: Film \"spectral\": \"integer nbuckets\" 0 outside 1..61");
    test_refused(t, head, "Film \"spectral\" \"integer nbuckets\" [62]\nWorldBegin\n", "f.pbrt",
                 "f.pbrt:2: Film \"spectral\": \"integer nbuckets\" 62 outside 1..61");
    /* the command line's file must be an .exr too (pbrt-v4 --outfile) */
    p = test_write_file(t, "spec_o.pbrt", "Camera \"perspective\"\nFilm \"spectral\"\nWorldBegin\n");
    err.msg[0] = 0;
    if (scene_load_as(&s, p, "x.pfm", &err)) { scene_free(&s); CHECK(t, 0, "-o x.pfm accepted"); }
    CHECK(t, strstr(err.msg, "spec_o.pbrt:2: Film \"spectral\": \"x.pfm\": pbrt-v4 writes the spectral film "
                    "as .exr only"), "error \"%s\"", err.msg);
    CHECK(t, scene_load_as(&s, p, "x.EXR", &err) && !strcmp(s.settings.filename, "x.EXR"), "-o x.EXR: %s", err.msg);
    scene_free(&s);
}

const TestCase tests_specfilm[] = {
    { "specfilm_half_values", test_specfilm_half_values },
    { "specfilm_exr_roundtrip", test_specfilm_exr_roundtrip },
    { "specfilm_write_film", test_specfilm_write_film },
    { "specfilm_blackbody_seen", test_specfilm_blackbody_seen },
    { "specfilm_red_sky", test_specfilm_red_sky },
    { "specfilm_clamp_and_empty", test_specfilm_clamp_and_empty },
    { "specfilm_sphere_buckets", test_specfilm_sphere_buckets },
    { "specfilm_rgb_as_rgb_film", test_specfilm_rgb_as_rgb_film },
    { "specfilm_pbrt_frozen", test_specfilm_pbrt_frozen },
    { "specfilm_refused", test_specfilm_refused },
    { NULL, NULL }
};
