/* tests/test_filter.c - pbrt-v4's pixel filters (filter.c): the filter
   values against their closed forms, the sampler's distribution against |f|
   (chi-square), the weights' mean against the filter's integral, a flat image
   that stays flat through every filter (the negative lobes must not bias it), the
   ringing of mitchell at a sharp edge where box has none, Option
   "disablepixeljitter" (rays through pixel centres, as pbrt-v4's image), and the
   parser's refusals with their file:line. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static void make_filter(PixelFilter *pf, FilterType type, float radius)
{
    SceneSettings st;
    memset(&st, 0, sizeof st);
    st.filter = type;
    st.filter_radius = radius;
    st.filter_sigma = 0.5f;
    st.filter_b = st.filter_c = 1.0f / 3.0f;
    st.filter_tau = 3.0f;
    filter_init(pf, &st);
}

/* integral of |f1| (absolute = 1) or f1 over [a, b] by Simpson's rule with n
   (even) steps: independent of the filter's tables */
static double integrate_1d(const PixelFilter *pf, double a, double b, int n, int absolute)
{
    double h = (b - a) / n, s = 0.0;
    int i;
    for (i = 0; i <= n; i++) {
        double v = filter_eval_1d(pf, a + i * h);
        if (absolute) v = fabs(v);
        s += v * (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0);
    }
    return s * h / 3.0;
}

/* Values at chosen points against the closed forms, worked by hand:
   Mitchell-Netravali with B = C = 1/3: 6 M(t) = 7|t|^3 - 12|t|^2 + 16/3 on
   |t| <= 1 and -7/3|t|^3 + 12|t|^2 - 20|t| + 32/3 on 1 < |t| <= 2, so
   M(0) = 8/9, M(1) = 1/18, M(1.5) = -5/144, M(2) = 0; the filter is M(2x/r).
   B = 1, C = 0 (the cubic B-spline): M(0) = 2/3, M(1) = 1/6.
   Windowed sinc, tau = 3: f(1/2) = sinc(1/2) sinc(1/6) = (2/pi)(3/pi) = 6/pi^2,
   f(3/2) = sinc(3/2) sinc(1/2) = (-2/(3 pi))(2/pi) = -4/(3 pi^2), f(1) = 0.
   Triangle r = 2: f(0.5, -1) = 1.5 x 1.  Gaussian r = 1.5, sigma = 0.5:
   f1(0) = 1 - exp(-4.5). */
static void test_filter_values(T *t)
{
    PixelFilter pf;
    const double pi = SPECNEE_PI;
    struct { FilterType type; float r; double x, y, want; } c[] = {
        { FILTER_MITCHELL, 2.0f, 0.0, 0.0, (8.0 / 9.0) * (8.0 / 9.0) },
        { FILTER_MITCHELL, 2.0f, 1.0, 0.0, (1.0 / 18.0) * (8.0 / 9.0) },
        { FILTER_MITCHELL, 2.0f, -1.5, 0.0, (-5.0 / 144.0) * (8.0 / 9.0) },
        { FILTER_MITCHELL, 2.0f, 1.5, 1.5, (5.0 / 144.0) * (5.0 / 144.0) },
        { FILTER_MITCHELL, 2.0f, 2.0, 0.0, 0.0 },
        { FILTER_MITCHELL, 2.0f, 0.0, 2.5, 0.0 },
        { FILTER_MITCHELL, 4.0f, 2.0, 3.0, (1.0 / 18.0) * (-5.0 / 144.0) },  /* M(2x/r) */
        { FILTER_SINC, 4.0f, 0.0, 0.0, 1.0 },
        { FILTER_SINC, 4.0f, 0.5, 0.0, 6.0 / (pi * pi) },
        { FILTER_SINC, 4.0f, -1.5, 0.5, -4.0 / (3.0 * pi * pi) * 6.0 / (pi * pi) },
        { FILTER_SINC, 4.0f, 1.0, 0.0, 0.0 },
        { FILTER_SINC, 4.0f, 4.5, 0.0, 0.0 },
        { FILTER_SINC, 2.0f, 2.5, 0.0, 0.0 },                                /* the window */
        { FILTER_TRIANGLE, 2.0f, 0.5, -1.0, 1.5 },
        { FILTER_TRIANGLE, 2.0f, 2.5, 0.0, 0.0 },
        { FILTER_GAUSSIAN, 1.5f, 0.0, 0.0, (1.0 - exp(-4.5)) * (1.0 - exp(-4.5)) },
        { FILTER_BOX, 0.5f, 0.5, -0.5, 1.0 },
        { FILTER_BOX, 0.5f, 0.6, 0.0, 0.0 },
    };
    int i;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        double got;
        make_filter(&pf, c[i].type, c[i].r);
        got = filter_eval(&pf, c[i].x, c[i].y);
        CHECK(t, fabs(got - c[i].want) <= 1e-6 * fabs(c[i].want) + 1e-9,
              "%s r %g at (%g, %g): %.9g, want %.9g", filter_name(c[i].type), c[i].r,
              c[i].x, c[i].y, got, c[i].want);
    }
    {   /* another B, C: the cubic B-spline */
        SceneSettings st;
        memset(&st, 0, sizeof st);
        st.filter = FILTER_MITCHELL; st.filter_radius = 2.0f; st.filter_b = 1.0f; st.filter_c = 0.0f;
        filter_init(&pf, &st);
        CHECK(t, fabs(filter_eval_1d(&pf, 0.0) - 2.0 / 3.0) < 1e-7 &&
              fabs(filter_eval_1d(&pf, 1.0) - 1.0 / 6.0) < 1e-7, "B-spline: %g %g",
              filter_eval_1d(&pf, 0.0), filter_eval_1d(&pf, 1.0));
        /* B = 3 with a radius below one cell: the table is zero everywhere; the
           samples stay in the filter's square and weigh 0 (no NaN) */
        st.filter_b = 3.0f; st.filter_radius = 0.01f;
        filter_init(&pf, &st);
        {
            float px, py, w = filter_sample(&pf, 0.3f, 0.7f, &px, &py);
            CHECK(t, w == 0.0f && fabsf(px - 0.5f) <= 0.01f && fabsf(py - 0.5f) <= 0.01f,
                  "zero filter: weight %g at (%g, %g)", w, px, py);
        }
    }
}

/* The sampled positions are distributed as |f| (pbrt-v4's filter importance
   sampling): N points in an 8 x 8 grid of cells over [-r, r]^2 against the
   probabilities from Simpson integrals of |f1| (separable: a product), by chi-
   square (CHECK_CHI2). */
static void test_filter_sampler_chi2(T *t)
{
    static const struct { FilterType type; float r; } c[] = {
        { FILTER_MITCHELL, 2.0f }, { FILTER_SINC, 4.0f }, { FILTER_TRIANGLE, 2.0f },
        { FILTER_GAUSSIAN, 1.5f }, { FILTER_BOX, 1.0f }, { FILTER_MITCHELL, 3.0f },
    };
    enum { NB = 8 };
    int n = test_scaled(400000, 40000), i, k;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        PixelFilter pf;
        Rng rng;
        double cnt[NB * NB], ex[NB * NB], p1[NB], tot = 0.0, r = c[i].r;
        int a, b;
        make_filter(&pf, c[i].type, c[i].r);
        memset(cnt, 0, sizeof cnt);
        for (a = 0; a < NB; a++) {
            p1[a] = integrate_1d(&pf, -r + 2.0 * r * a / NB, -r + 2.0 * r * (a + 1) / NB, 2000, 1);
            tot += p1[a];
        }
        rng_seed(&rng, 29, (uint64_t)i);
        for (k = 0; k < n; k++) {
            float u[2], px, py;
            double x, y;
            rng_fill(&rng, u, 2);
            filter_sample(&pf, u[0], u[1], &px, &py);
            x = px - 0.5; y = py - 0.5;
            CHECK(t, fabs(x) <= r && fabs(y) <= r, "%s: offset (%g, %g) beyond radius %g",
                  filter_name(c[i].type), x, y, r);
            a = (int)((x + r) / (2.0 * r) * NB); b = (int)((y + r) / (2.0 * r) * NB);
            if (a == NB) a--;
            if (b == NB) b--;
            cnt[a * NB + b] += 1.0;
        }
        for (a = 0; a < NB; a++)
            for (b = 0; b < NB; b++) ex[a * NB + b] = n * p1[a] * p1[b] / (tot * tot);
        CHECK_CHI2(t, cnt, ex, NB * NB, (int)(sizeof c / sizeof c[0]), NULL, "%s r %g (N = %d)",
                   filter_name(c[i].type), r, n);
    }
}

/* E[w] = E[f/q] = integral f: the weights keep their sign.  mitchell's integral
   is r^2/4 (M integrates to 1 over [-2, 2]), sinc's the square of a Simpson
   integral of f1; box, gaussian and triangle sample f exactly and weigh 1.  The
   table's midpoint rule puts E[w] within 2e-3 of the integral (slack). */
static void test_filter_weight_mean(T *t)
{
    static const struct { FilterType type; float r; } c[] = {
        { FILTER_MITCHELL, 2.0f }, { FILTER_MITCHELL, 3.0f }, { FILTER_SINC, 4.0f },
        { FILTER_SINC, 2.5f }, { FILTER_TRIANGLE, 2.0f }, { FILTER_GAUSSIAN, 1.5f },
        { FILTER_BOX, 0.5f },
    };
    int n = test_scaled(1000000, 100000), i, k;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        PixelFilter pf;
        Rng rng;
        double sum = 0.0, sum2 = 0.0, mean, se, want, i1;
        int neg = 0;
        make_filter(&pf, c[i].type, c[i].r);
        i1 = integrate_1d(&pf, -c[i].r, c[i].r, 4000, 0);
        want = c[i].type == FILTER_MITCHELL ? c[i].r * c[i].r / 4.0
             : c[i].type == FILTER_SINC ? i1 * i1 : 1.0;
        if (c[i].type == FILTER_MITCHELL)      /* Simpson agrees with the closed form */
            CHECK(t, fabs(i1 * i1 - want) < 1e-6 * want, "mitchell: %g vs %g", i1 * i1, want);
        rng_seed(&rng, 30, (uint64_t)i);
        for (k = 0; k < n; k++) {
            float u[2], px, py, w;
            rng_fill(&rng, u, 2);
            w = filter_sample(&pf, u[0], u[1], &px, &py);
            sum += w; sum2 += (double)w * w;
            neg += w < 0.0f;
        }
        mean = sum / n;
        se = sqrt((sum2 / n - mean * mean) / n);
        CHECK(t, fabs(mean - want) < 5.0 * se + 2e-3 * fabs(want),
              "%s r %g: E[w] = %.6g +- %.2g, integral %.6g", filter_name(c[i].type), c[i].r,
              mean, se, want);
        CHECK(t, (neg > 0) == filter_weighted(&pf), "%s: %d negative weights",
              filter_name(c[i].type), neg);
    }
}

/* A scene seen through `filter`: an emitter (luminance 1) over x >= x0 at depth 5
   (x0 = -100: the whole view), a camera at the origin looking down +z. */
static int render_half(T *t, const char *filter, float x0, int res, int spp, Image *im)
{
    char buf[2048];
    Scene s;
    RenderOptions o;
    RenderStats st;
    Error err;
    int ok;
    snprintf(buf, sizeof buf,
             "Film \"rgb\" \"integer xresolution\" %d \"integer yresolution\" %d\n"
             "PixelFilter %s\n"
             "Camera \"perspective\" \"float fov\" 30\n"
             "WorldBegin\n"
             "AttributeBegin\n"
             " AreaLightSource \"diffuse\" \"bool twosided\" true\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ %g -100 5  100 -100 5  100 100 5  %g 100 5 ]\n"
             "AttributeEnd\n", res, res, filter, x0, x0);
    if (!test_load_scene(t, &s, buf)) return 0;
    render_options_default(&o);
    o.spp = spp;
    o.seed = 7;
    o.threads = 2;
    o.maxdepth = 1;
    ok = render(&s, &o, im, &st, &err);
    if (!ok) test_failf(t, __FILE__, __LINE__, "render: %s", err.msg);
    else if (st.nonfinite) { test_failf(t, __FILE__, __LINE__, "non-finite samples"); ok = 0; img_free(im); }
    scene_free(&s);
    return ok;
}

/* A flat image stays flat: an emitter filling the view renders the same mean
   through every filter (the weights' signs and their normalisation sum w L /
   sum w must not bias it), within 5 standard errors of the pixels' spread. */
static void test_filter_flat_image(T *t)
{
    static const char *const filters[] = {
        "\"box\"", "\"gaussian\"", "\"triangle\"", "\"mitchell\"", "\"sinc\"",
        "\"mitchell\" \"float B\" 0 \"float C\" 1", "\"sinc\" \"float xradius\" 2 \"float yradius\" 2",
    };
    double m0 = 0.0, se0 = 0.0;
    int i, spp = test_scaled(256, 64);
    for (i = 0; i < (int)(sizeof filters / sizeof filters[0]); i++) {
        Image im;
        double s = 0.0, s2 = 0.0, m, se;
        int p, n;
        if (!render_half(t, filters[i], -100.0f, 8, spp, &im)) return;
        n = im.w * im.h;
        for (p = 0; p < n; p++) {
            double v = im.rgb[3 * p + 1];          /* green ~ luminance */
            s += v; s2 += v * v;
        }
        img_free(&im);
        m = s / n;
        se = sqrt((s2 / n - m * m) / (n - 1));
        if (i == 0) { m0 = m; se0 = se; continue; }
        CHECK(t, fabs(m - m0) < 5.0 * sqrt(se * se + se0 * se0) + 1e-6,
              "PixelFilter %s: flat image mean %.5f +- %.5f, box %.5f +- %.5f", filters[i],
              m, se, m0, se0);
    }
    CHECK(t, fabs(m0 - 1.0) < 0.03, "box: flat image mean %g, want ~1 (a D65 emitter of Y = 1)", m0);
}

/* An edge: the emitter covers x >= 0, which falls on the boundary between the
   columns 7 and 8 of a 16 x 16 film.  Through box each pixel sees only itself: the
   dark columns are exactly 0, the bright ones flat.  Through mitchell (r = 2) a
   pixel sees 2 pixels around it: the dark column next to the edge picks up light
   (blur) by L x integral_{0.5}^{2} M = L (1/2 - 2.276042/6) = 0.120660 L, the one
   after it goes negative (the negative lobe: ringing) by L x integral_{1.5}^{2} M
   = -L/128, and the bright side overshoots next to it (M from the header of
   filter_values; the integrals worked by hand from its antiderivative). */
static void test_filter_edge_ringing(T *t)
{
    Image box, mit;
    double col_box[16], col_m[16], se_m[16], L;
    int spp = test_scaled(1024, 256), x, y, dark1, dark2, bright1, bright2, dir;
    if (!render_half(t, "\"box\"", 0.0f, 16, 64, &box)) return;
    if (!render_half(t, "\"mitchell\"", 0.0f, 16, spp, &mit)) { img_free(&box); return; }
    for (x = 0; x < 16; x++) {
        double s = 0.0, sm = 0.0, sm2 = 0.0;
        for (y = 0; y < 16; y++) {
            double v = mit.rgb[3 * (y * 16 + x) + 1];
            s += box.rgb[3 * (y * 16 + x) + 1];
            sm += v; sm2 += v * v;
        }
        col_box[x] = s / 16.0;
        col_m[x] = sm / 16.0;
        se_m[x] = sqrt((sm2 / 16.0 - col_m[x] * col_m[x]) / 15.0);
    }
    img_free(&box); img_free(&mit);
    /* which side is bright (the camera's handedness is not what is tested here) */
    dir = col_box[8] > col_box[7] ? 1 : -1;
    bright1 = dir > 0 ? 8 : 7; bright2 = bright1 + dir;
    dark1 = dir > 0 ? 7 : 8; dark2 = dark1 - dir;
    L = col_box[bright1];
    CHECK(t, L > 0.5 && col_box[dark1] == 0.0 && col_box[dark2] == 0.0 &&
          fabs(col_box[bright2] - L) < 0.05 * L, "box: columns %g %g | %g %g", col_box[dark2],
          col_box[dark1], L, col_box[bright2]);
    CHECK(t, fabs(col_m[dark1] - 0.120660 * L) < 5.0 * se_m[dark1] + 1e-3 * L,
          "mitchell: first dark column %g +- %g, want L x 0.120660 (blur)", col_m[dark1], se_m[dark1]);
    CHECK(t, fabs(col_m[dark2] + L / 128.0) < 5.0 * se_m[dark2] + 1e-3 * L && col_m[dark2] < 0.0,
          "mitchell: second dark column %g +- %g, want -L/128 = %g (ringing)", col_m[dark2],
          se_m[dark2], -L / 128.0);
    CHECK(t, col_m[bright2] > L + 3.0 * se_m[bright2] && col_m[bright1] < L,
          "mitchell: bright columns %g %g, box %g (overshoot next to the edge)", col_m[bright1],
          col_m[bright2], L);
}

/* Option "disablepixeljitter" (pbrt-v4's GetCameraSample: the filter's sample
   drawn, then the film position the pixel's centre and the weight 1): a 16 x 16
   image of two triangles, reflectance 0.9 and 0.1, meeting along a slanted edge
   under a distant light.  pbrt-v4 (commit 5f7a6068, `pbrt --spp 64 --seed 1`,
   its default gaussian filter) renders it with the option as 106 dark pixels
   (Y < 0.5) and no pixel between 0.15 and 0.75, and without it 25 such blended
   pixels along the edge.  specnee with the option, in pbrt-v4's spelling and the
   typed one: 106 dark, none blended; without: some blended. */
static void test_filter_no_pixel_jitter(T *t)
{
    static const char *const opt[3] = { "", "Option \"disablepixeljitter\" true\n",
                                        "Option \"bool disablepixeljitter\" true\n" };
    int k;
    for (k = 0; k < 3; k++) {
        char text[2048];
        RenderOptions o;
        Image im;
        int i, dark = 0, mid = 0;
        snprintf(text, sizeof text, "%sLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 20 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
                 "Integrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
                 "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 0 0 5 ] "
                 "\"point3 to\" [ 0 0 0 ]\n"
                 "Material \"diffuse\" \"rgb reflectance\" [ 0.9 0.9 0.9 ]\n"
                 "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ -3 -3 0  3 -3 0  -3 3.3 0 ]\n"
                 "Material \"diffuse\" \"rgb reflectance\" [ 0.1 0.1 0.1 ]\n"
                 "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ 3 -3 0  3 3 0  -3 3.3 0 ]\n",
                 opt[k]);
        render_options_default(&o);
        o.spp = 16;
        o.seed = 1;
        o.threads = 2;
        if (!test_render_text(t, text, &o, &im)) return;
        for (i = 0; i < im.w * im.h; i++) {
            const float *c = im.rgb + 3 * i;
            double y = 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2];
            dark += y < 0.5;
            mid += y > 0.15 && y < 0.75;
        }
        img_free(&im);
        if (k) CHECK(t, dark == 106 && mid == 0, "%s: %d dark pixels, %d blended (pbrt-v4: 106, 0)", opt[k], dark, mid);
        else CHECK(t, mid > 10, "jittered: only %d blended pixels along the edge", mid);
    }
    test_rejected_at(t, "Option \"disablepixeljitter\" 1\nWorldBegin\n", 1,
                     "Option \"disablepixeljitter\": expected true or false", NULL);
}

/* The parser: pbrt-v4's names and defaults; radii outside (0, 16], tau <= 0,
   unequal radii, a parameter of another filter, a non-finite number are
   errors at their line. */
static void test_filter_parse(T *t)
{
    static const char *const bad[] = {
        "PixelFilter \"mitchell\" \"float xradius\" 0 \"float yradius\" 0\n",
        "PixelFilter \"sinc\" \"float xradius\" 17 \"float yradius\" 17\n",
        "PixelFilter \"triangle\" \"float xradius\" -1 \"float yradius\" -1\n",
        "PixelFilter \"sinc\" \"float tau\" 0\n",
        "PixelFilter \"sinc\" \"float tau\" -2\n",
        "PixelFilter \"mitchell\" \"float xradius\" 1\n",
        "PixelFilter \"sinc\" \"float B\" 0.5\n",
        "PixelFilter \"triangle\" \"float sigma\" 0.5\n",
        "PixelFilter \"mitchell\" \"float C\" nan\n",
        "PixelFilter \"lanczos\"\n",
    };
    static const struct { const char *text; FilterType t; float r, b, c, tau; } good[] = {
        { "PixelFilter \"mitchell\"\n", FILTER_MITCHELL, 2.0f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f },
        { "PixelFilter \"sinc\"\n", FILTER_SINC, 4.0f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f },
        { "PixelFilter \"triangle\"\n", FILTER_TRIANGLE, 2.0f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f },
        { "PixelFilter \"mitchell\" \"float B\" 0.5 \"float C\" 0.25 \"float xradius\" 3 "
          "\"float yradius\" 3\n", FILTER_MITCHELL, 3.0f, 0.5f, 0.25f, 3.0f },
        { "PixelFilter \"sinc\" \"float tau\" 2\n", FILTER_SINC, 4.0f, 1.0f / 3.0f, 1.0f / 3.0f, 2.0f },
    };
    char buf[512];
    Scene s;
    Error e;
    int i;
    for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
        snprintf(buf, sizeof buf, "Film \"rgb\"\n%sWorldBegin\n", bad[i]);
        CHECK(t, !scene_load_string(&s, buf, "f.pbrt", &e) && strstr(e.msg, "f.pbrt:2:"),
              "accepted or not at f.pbrt:2: %s -> %s", bad[i], e.msg);
    }
    for (i = 0; i < (int)(sizeof good / sizeof good[0]); i++) {
        const SceneSettings *st = &s.settings;
        snprintf(buf, sizeof buf, "%sWorldBegin\n", good[i].text);
        CHECK(t, scene_load_string(&s, buf, "f.pbrt", &e), "%s: %s", good[i].text, e.msg);
        CHECK(t, st->filter == good[i].t && st->filter_radius == good[i].r &&
              st->filter_b == good[i].b && st->filter_c == good[i].c && st->filter_tau == good[i].tau,
              "%s: read as %s r %g B %g C %g tau %g", good[i].text, filter_name(st->filter),
              st->filter_radius, st->filter_b, st->filter_c, st->filter_tau);
        scene_free(&s);
    }
}

/* filter_sample through the table's guide (cdf_cell) gives the positions and
   weights it gives without it (m = 0), when cdf_cell searches the whole table: at
   every knot of the CDF, next to it, at every step of the guide, and at random. */
static void test_filter_guided_search(T *t)
{
    static const struct { FilterType type; float r; } c[] = {
        { FILTER_MITCHELL, 2.0f }, { FILTER_SINC, 4.0f }, { FILTER_GAUSSIAN, 1.5f }, { FILTER_MITCHELL, 0.7f },
    };
    static PixelFilter pf, bare;
    int i, k, bad = 0, tried = 0;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        Rng rng;
        make_filter(&pf, c[i].type, c[i].r);
        bare = pf;
        bare.m = 0;
        CHECK(t, pf.m == cdf_guide_size(pf.n), "%s: a guide of %d steps", filter_name(c[i].type), pf.m);
        rng_seed(&rng, 31, (uint64_t)i);
        for (k = 0; k < 3 * (pf.n + 1) + 3 * pf.m + 20000; k++, tried++) {
            float u = k < 3 * (pf.n + 1) ? pf.cdf[k / 3]
                    : k < 3 * (pf.n + 1) + 3 * pf.m ? (float)((k - 3 * (pf.n + 1)) / 3) / (float)pf.m
                    : rng_float(&rng), p[4], w[2];
            if (k < 3 * (pf.n + 1) + 3 * pf.m && k % 3) u = nextafterf(u, k % 3 == 1 ? 0.0f : 1.0f);
            if (!(u < 1.0f)) continue;
            w[0] = filter_sample(&pf, u, 0.5f, &p[0], &p[1]);
            w[1] = filter_sample(&bare, u, 0.5f, &p[2], &p[3]);
            if (memcmp(&w[0], &w[1], sizeof w[0]) || memcmp(&p[0], &p[2], 2 * sizeof p[0])) bad++;
        }
    }
    CHECK(t, bad == 0, "guided filter sampling differs at %d of %d u", bad, tried);
}

/* The independent sampler's Gaussian (filter_gaussian_reject) against the
   truncated Gaussian f1 = g(x) - g(r) itself, for three (radius, sigma): a
   chi-square over 40 bins of [-r, r] (each bin's mass by Simpson's rule in
   double) and the second moment E[x^2] within 4 standard errors of
   integral x^2 f1 / integral f1; and the work: at most 1.05 tries on average
   (3 numbers of the stream per try), where plain rejection took 2.4. */
static void test_filter_gauss_exact(T *t)
{
    static const float rs[3][2] = { { 1.5f, 0.5f }, { 2.0f, 1.0f }, { 1.0f, 0.3f } };
    enum { NB = 40 };
    int n = test_scaled(400000, 40000), i, k;
    for (i = 0; i < 3; i++) {
        PixelFilter pf;
        SceneSettings st;
        Rng rng, probe;
        double cnt[NB], ex[NB], tot = 0.0, m2 = 0.0, s1 = 0.0, s2 = 0.0, r = rs[i][0], se, want;
        long steps = 0;
        int a, probed = 0;
        memset(&st, 0, sizeof st);
        st.filter = FILTER_GAUSSIAN;
        st.filter_radius = rs[i][0];
        st.filter_sigma = rs[i][1];
        filter_init(&pf, &st);
        CHECK(t, pf.gauss_ok, "r %g sigma %g: no exact table", r, rs[i][1]);
        if (t->failed) return;
        for (a = 0; a < NB; a++) {
            double lo = -r + 2.0 * r * a / NB, hi = -r + 2.0 * r * (a + 1) / NB, h = (hi - lo) / 400.0;
            int j;
            ex[a] = 0.0;
            for (j = 0; j <= 400; j++) {
                double x = lo + j * h, f = filter_eval_1d(&pf, x), wgt = j == 0 || j == 400 ? 1.0 : j % 2 ? 4.0 : 2.0;
                ex[a] += wgt * f * h / 3.0;
                m2 += wgt * x * x * f * h / 3.0;
            }
            tot += ex[a];
        }
        want = m2 / tot;
        memset(cnt, 0, sizeof cnt);
        rng_seed(&rng, 41, (uint64_t)i);
        for (k = 0; k < n; k++) {
            double x;
            if (k < 20000) {                     /* count the stream's numbers a draw takes */
                probe = rng;
                x = filter_gaussian_reject(&pf, &rng);
                while (memcmp(&probe, &rng, sizeof rng) && steps < 100L * n) { rng_u32(&probe); steps++; }
                probed++;
            } else {
                x = filter_gaussian_reject(&pf, &rng);
            }
            CHECK(t, fabs(x) <= r, "offset %g beyond radius %g", x, r);
            if (t->failed) return;
            a = (int)((x + r) / (2.0 * r) * NB);
            if (a == NB) a--;
            cnt[a] += 1.0;
            s1 += x * x;
            s2 += x * x * x * x;
        }
        for (a = 0; a < NB; a++) ex[a] *= n / tot;
        CHECK_CHI2(t, cnt, ex, NB, 3, NULL, "gaussian r %g sigma %g (N = %d)", r, rs[i][1], n);
        s1 /= n;
        se = sqrt((s2 / n - s1 * s1) / n);
        CHECK(t, fabs(s1 - want) < 4.0 * se, "r %g sigma %g: E[x^2] = %.6g +- %.2g, want %.6g", r, rs[i][1],
              s1, se, want);
        CHECK(t, steps <= 3.15 * probed, "r %g sigma %g: %.3f tries a draw (3 numbers each)", r, rs[i][1],
              steps / (3.0 * probed));
    }
}

/* The exact Gaussian's table: each cell's bounds hold f1 as the sampler computes
   it (float, expf(-x^2 k) - g_r) at 2001 points of the cell, its edges included
   (a bound below f1 would clip the density there: the sampler would no longer be
   exact); and the alias table gives cell c the probability hi_c / sum hi (to
   2^-25, its coin's resolution). */
static void test_filter_gauss_table(T *t)
{
    PixelFilter pf;
    SceneSettings st;
    double p[FILTER_GAUSS_CELLS], sum = 0.0, worst = 0.0;
    int c, j, bad = 0;
    memset(&st, 0, sizeof st);
    st.filter = FILTER_GAUSSIAN;
    st.filter_radius = 1.5f;
    st.filter_sigma = 0.5f;
    filter_init(&pf, &st);
    CHECK(t, pf.gauss_ok, "no exact table");
    if (t->failed) return;
    for (c = 0; c < FILTER_GAUSS_CELLS; c++) {
        for (j = 0; j <= 2000; j++) {
            float x = ((float)c + (float)j / 2000.0f) * pf.gauss_w;
            float f = expf(-x * x * pf.gauss_k) - pf.gauss_gr;
            if (!(pf.gauss_lo[c] <= f && f <= pf.gauss_hi[c])) bad++;
        }
        sum += pf.gauss_hi[c];
        p[c] = 0.0;
    }
    CHECK(t, bad == 0, "%d points of the cells outside their bounds", bad);
    for (c = 0; c < FILTER_GAUSS_CELLS; c++) {   /* the alias table's probabilities */
        p[c] += pf.gauss_keep[c] / 33554432.0 / FILTER_GAUSS_CELLS;
        p[pf.gauss_alias[c]] += (1.0 - pf.gauss_keep[c] / 33554432.0) / FILTER_GAUSS_CELLS;
        CHECK(t, pf.gauss_keep[c] <= 33554432u, "cell %d keeps %u / 2^25", c, pf.gauss_keep[c]);
    }
    for (c = 0; c < FILTER_GAUSS_CELLS; c++) worst = fmax(worst, fabs(p[c] - pf.gauss_hi[c] / sum));
    CHECK(t, worst < 1e-6, "the alias table's probabilities are off by up to %.3g", worst);
}

const TestCase tests_filter[] = {
    { "filter_gauss_exact", test_filter_gauss_exact },
    { "filter_gauss_table", test_filter_gauss_table },
    { "filter_no_pixel_jitter", test_filter_no_pixel_jitter },
    { "filter_values", test_filter_values },
    { "filter_sampler_chi2", test_filter_sampler_chi2 },
    { "filter_guided_search", test_filter_guided_search },
    { "filter_weight_mean", test_filter_weight_mean },
    { "filter_flat_image", test_filter_flat_image },
    { "filter_edge_ringing", test_filter_edge_ringing },
    { "filter_parse", test_filter_parse },
    { NULL, NULL }
};
