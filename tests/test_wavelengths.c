/* tests/test_wavelengths.c - the wavelength pdfs beyond uniform and importance: the
   scene-independent "visible" pdf and the defensive mixture (wavelengths.c),
   and the unbiasedness of every pdf on the scenes where importance sampling by the
   emitters' spectra fails (scenes/wl-hidden-lamp.pbrt, scenes/wl-filter.pbrt;
   docs/wavelengths.md).

   What is checked:
   - the visible pdf is pbrt-v4's published one on 360-830 nm (its constant
     0.0039398042 was computed independently of specnee's normalisation) and keeps
     the sech^2 shape when restricted to 400-700 nm;
   - sampler against pdf: chi-square per 1 nm bin (check_wl_sampling, test_spectrum.c)
     and a Kolmogorov-Smirnov test of the hero wavelength against the exact CDF
     wl_cdf; the inverse CDF is exact: cdf(cdf^-1(u)) = u;
   - the mixture is (1 - m) importance + m visible, so it is never below m x visible
     (the worst-case bound of docs/wavelengths.md);
   - renders: furnaces with an analytic answer, and per-tile agreement with
     uniform wavelengths on a dispersive box and on both stress scenes
     (TEST_K_SIGMA standard errors, fixtures.c). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

#define K_SIGMA TEST_K_SIGMA

/* ---------- the pdfs ---------- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Kolmogorov-Smirnov: N heroes from independent u against wl_cdf; the critical
   D at a false-alarm rate of 1e-4 is sqrt(-ln(1e-4 / 2) / (2N)) (the asymptotic
   Kolmogorov distribution). */
static void check_ks(T *t, const WavelengthPdf *w, const char *what)
{
    enum { N = 50000 };
    double *x = (double *)malloc(N * sizeof *x), d = 0.0, crit = sqrt(-log(1e-4 / 2.0) / (2.0 * N));
    Rng rng;
    int i;
    CHECK(t, x != NULL, "out of memory");
    rng_seed(&rng, 11, 0);
    for (i = 0; i < N; i++) {
        Wavelengths wl;
        wl_sample(w, rng_float(&rng), &wl);
        x[i] = wl.lambda[0];
    }
    qsort(x, N, sizeof *x, cmp_double);
    for (i = 0; i < N; i++) {
        double F = wl_cdf(w, (float)x[i]), lo = F - (double)i / N, hi = (double)(i + 1) / N - F;
        if (lo > d) d = lo;
        if (hi > d) d = hi;
    }
    free(x);
    CHECK(t, d < crit, "%s: KS D = %.5f > %.5f (N = %d, p = 1e-4)", what, d, crit, (int)N);
}

/* cdf(cdf^-1(u)) = u, and cdf agrees with the integral of p (midpoint rule, 0.1 nm). */
static void check_cdf(T *t, const WavelengthPdf *w, const char *what)
{
    int i;
    double acc = 0.0, x;
    for (i = 0; i < 1000; i++) {
        Wavelengths wl;
        double u = (i + 0.5) / 1000.0;
        wl_sample(w, (float)u, &wl);
        CHECK(t, fabs(wl_cdf(w, wl.lambda[0]) - u) < 2e-5, "%s: P(P^-1(%g)) = %.7f", what, u,
              wl_cdf(w, wl.lambda[0]));
    }
    for (x = w->lo; x < w->hi - 0.05; x += 0.1) {
        acc += 0.1 * wl_pdf_eval(w, (float)(x + 0.05));
        if (fmod(x - w->lo + 0.1, 50.0) < 0.05)
            CHECK(t, fabs(acc - wl_cdf(w, (float)(x + 0.1))) < 1e-4, "%s: integral of p to %g = %.6f, P = %.6f",
                  what, x + 0.1, acc, wl_cdf(w, (float)(x + 0.1)));
    }
}

static void test_wl_visible(T *t)
{
    WavelengthPdf w;
    static const float at[] = { 360, 400, 450, 538, 600, 700, 830 };
    int i;
    /* pbrt-v4 (src/pbrt/util/sampling.h): 0.0039398042 / cosh^2(0.0072 (lambda - 538)) */
    CHECK(t, wl_pdf_build(&w, WL_VISIBLE, (float)SPEC_MIN, (float)SPEC_MAX, NULL, 0.0f), "build failed");
    for (i = 0; i < 7; i++) {
        double c = cosh(0.0072 * (at[i] - 538.0)), pbrt = 0.0039398042 / (c * c);
        CHECK(t, fabs(wl_pdf_eval(&w, at[i]) / pbrt - 1.0) < 1e-5, "360-830: p(%g) = %g, pbrt-v4 %g",
              (double)at[i], (double)wl_pdf_eval(&w, at[i]), pbrt);
    }
    check_wl_sampling(t, &w, "visible 360-830");
    if (t->failed) return;
    check_ks(t, &w, "visible 360-830");
    if (t->failed) return;
    /* restricted to 400-700: the same shape, renormalised */
    CHECK(t, wl_pdf_build(&w, WL_VISIBLE, LAMBDA_LO, LAMBDA_HI, NULL, 0.0f), "build failed");
    CHECK(t, wl_pdf_eval(&w, 399.0f) == 0.0f && wl_pdf_eval(&w, 701.0f) == 0.0f, "p outside the range");
    for (i = 1; i < 6; i++) {
        double c = cosh(0.0072 * (at[i] - 538.0));
        CHECK(t, fabs(wl_pdf_eval(&w, at[i]) / wl_pdf_eval(&w, 538.0f) * (c * c) - 1.0) < 1e-5,
              "400-700: p(%g) / p(538) is not sech^2", (double)at[i]);
    }
    check_wl_sampling(t, &w, "visible 400-700");
    if (t->failed) return;
    check_ks(t, &w, "visible 400-700");
    if (t->failed) return;
    check_cdf(t, &w, "visible 400-700");
    CHECK(t, !wl_pdf_build(&w, WL_VISIBLE, 700.0f, 400.0f, NULL, 0.0f), "an empty range must fail");
}

static void test_wl_mixture(T *t)
{
    WavelengthPdf mix, imp, vis, one;
    Spectrum f11;
    const float m = 0.25f;
    double min_ratio = 1e30;
    int k;
    CHECK(t, spec_named(&f11, "stdillum-F11"), "F11");
    CHECK(t, wl_pdf_build(&mix, WL_MIXTURE, LAMBDA_LO, LAMBDA_HI, &f11, m), "mixture");
    CHECK(t, wl_pdf_build(&imp, WL_IMPORTANCE, LAMBDA_LO, LAMBDA_HI, &f11, 0.0f), "importance");
    CHECK(t, wl_pdf_build(&vis, WL_VISIBLE, LAMBDA_LO, LAMBDA_HI, NULL, 0.0f), "visible");
    CHECK(t, wl_pdf_build(&one, WL_MIXTURE, LAMBDA_LO, LAMBDA_HI, &f11, 1.0f), "mixture 1");
    /* at cell centres the mixture is the blend (the visible part is the cell average,
       which differs from the centre value by < 1e-5 relative on 1 nm) */
    for (k = 0; k < 300; k++) {
        float l = LAMBDA_LO + k + 0.5f;
        double want = (1.0 - m) * wl_pdf_eval(&imp, l) + m * wl_pdf_eval(&vis, l);
        CHECK(t, fabs(wl_pdf_eval(&mix, l) / want - 1.0) < 1e-4, "p_mix(%g) = %g, blend %g", (double)l,
              (double)wl_pdf_eval(&mix, l), want);
        CHECK(t, fabs(wl_pdf_eval(&one, l) / wl_pdf_eval(&vis, l) - 1.0) < 1e-4, "m = 1 is not visible at %g",
              (double)l);
        if (wl_pdf_eval(&mix, l) * 300.0 < min_ratio) min_ratio = wl_pdf_eval(&mix, l) * 300.0;
    }
    /* the bound of docs/wavelengths.md: p_mix >= m min(p_vis) = 0.44 m x uniform */
    CHECK(t, min_ratio > 0.44 * m, "min p_mix / p_uniform = %.4f < 0.44 m", min_ratio);
    check_wl_sampling(t, &mix, "mixture F11 400-700");
    if (!t->failed) check_ks(t, &mix, "mixture F11 400-700");
    if (!t->failed) check_cdf(t, &mix, "mixture F11 400-700");
    wl_pdf_free(&mix);
    wl_pdf_free(&imp);
    wl_pdf_free(&one);
    if (t->failed) return;
    /* the mode names round-trip; unknown names and modes are refused */
    for (k = 0; k < WL_MODE_COUNT; k++)
        CHECK(t, wl_mode_from_name(wl_mode_name((WlMode)k)) == (WlMode)k, "mode %d name", k);
    CHECK(t, wl_mode_from_name("hero") == WL_MODE_COUNT, "unknown name");
    CHECK(t, !wl_pdf_build(&mix, WL_MIXTURE, LAMBDA_LO, LAMBDA_HI, &f11, 1.5f), "mix > 1 must fail");
}

/* The guide table only narrows wl_sample's search: with it and without it (guide
   NULL: the whole table is searched) the wavelengths and pdfs are the same, for
   u at every cdf knot and around it, at the guide's steps g / m and around them,
   and at random; and the pdfs are wl_pdf_eval's of the wavelengths.  CFL1 on 360-830 nm has long floor plateaus and narrow lines,
   where one guide step spans many cells and many guide steps share one cell. */
static int same_sample(const WavelengthPdf *w, float u)
{
    WavelengthPdf bare = *w;
    Wavelengths a, b;
    int j, ok = 1;
    bare.guide = NULL;
    wl_sample(w, u, &a);
    wl_sample(&bare, u, &b);
    for (j = 0; j < HERO_N; j++) ok = ok && a.pdf[j] == wl_pdf_eval(w, a.lambda[j]);
    return ok && memcmp(&a, &b, sizeof a) == 0;
}

static void test_wl_guide(T *t)
{
    WavelengthPdf w;
    Spectrum cfl;
    Rng rng;
    int k, bad = 0, tried = 0;
    CHECK(t, spec_named(&cfl, "lamp-CFL1"), "CFL1");
    CHECK(t, wl_pdf_build(&w, WL_MIXTURE, (float)SPEC_MIN, (float)SPEC_MAX, &cfl, 0.1f), "mixture");
    CHECK(t, w.guide != NULL, "a table pdf has a guide");
    if (t->failed) return;
    CHECK(t, w.m == cdf_guide_size(w.n), "a guide of %d steps for %d cells", w.m, w.n);
    for (k = 0; k < w.m; k++) {
        float knot = w.cdf[k < w.n ? k : w.n], step = (float)((double)k / w.m);
        float us[6];
        int i;
        us[0] = knot;
        us[1] = nextafterf(knot, 0.0f);
        us[2] = nextafterf(knot, 1.0f);
        us[3] = step;
        us[4] = nextafterf(step, 0.0f);
        us[5] = nextafterf(step, 1.0f);
        for (i = 0; i < 6; i++, tried++)
            if (us[i] < 1.0f && !same_sample(&w, us[i])) bad++;
    }
    rng_seed(&rng, 7, 1);
    for (k = 0; k < 100000; k++, tried++)
        if (!same_sample(&w, rng_float(&rng))) bad++;
    CHECK(t, bad == 0, "the guided search differs from the full one at %d of %d u", bad, tried);
    wl_pdf_free(&w);
    CHECK(t, w.guide == NULL, "wl_pdf_free resets the guide");
}

/* ---------- renders ---------- */

static const char *camera_8 =
    "LookAt 0 0 -3  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 10 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ] \"string filename\" \"t.pfm\"\n";

/* White furnaces: a convex object inside a closed sphere whose inner surface emits
   L = 1.  A diffuse sphere of albedo 0.5 has Y = 0.5 everywhere; a lossless
   dispersive glass sphere has Y = 1 although only the hero survives it; both
   have the colour of the equal-energy emitter (spec_to_xyz over 400-700 nm). */
static void test_wl_furnaces(T *t)
{
    static const char *inner[2] = {
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 0.5 830 0.5 ]",
        "Material \"dielectric\" \"float cauchyA\" [ 1.5 ] \"float cauchyB\" [ 0.04 ]" };
    static const double Yref[2] = { 0.5, 1.0 };
    static const WlMode modes[3] = { WL_VISIBLE, WL_MIXTURE, WL_IMPORTANCE };
    int obj, md, i;
    Spectrum e;
    double xyz_e[3], rgb_e[3];
    spec_const(&e, 1.0f);
    spec_to_xyz(&e, LAMBDA_LO, LAMBDA_HI, xyz_e);
    xyz_to_linear_srgb(xyz_e, rgb_e);
    for (obj = 0; obj < 2; obj++)
        for (md = 0; md < 3; md++) {
            char text[2048];
            Scene s;
            RenderOptions o;
            Tiles tl;
            snprintf(text, sizeof text,
                     "%sWorldBegin\n"
                     "AttributeBegin\n ReverseOrientation\n AreaLightSource \"diffuse\" \"spectrum L\" [ 360 1 830 1 ]\n"
                     " Material \"diffuse\" \"spectrum reflectance\" [ 360 0 830 0 ]\n"
                     " Shape \"sphere\" \"float radius\" [ 20 ]\nAttributeEnd\n"
                     "AttributeBegin\n %s\n Shape \"sphere\" \"float radius\" [ 1 ]\nAttributeEnd\n",
                     camera_8, inner[obj]);
            if (!test_load_scene(t, &s, text)) return;
            render_options_default(&o);
            o.sel.grid_res = 8;
            o.spp = test_scaled(32, 4);
            o.maxdepth = obj ? 24 : 5;
            o.wl_mode = modes[md];
            if (!test_render_tiles(t, &s, &o, 8, 2, &tl)) { scene_free(&s); return; }
            scene_free(&s);
            for (i = 0; i < 4; i++) {
                double Y = test_luminance(tl.mean[i]);
                int c;
                CHECK(t, fabs(Y - Yref[obj]) < K_SIGMA * tl.se[i][1] + 3e-3,
                      "%s furnace, %s wavelengths, tile %d: Y = %.5f +- %.2g, expected %g",
                      obj ? "glass" : "diffuse", wl_mode_name(modes[md]), i, Y, tl.se[i][1], Yref[obj]);
                /* and the colour: Yref x the equal-energy white's linear sRGB */
                for (c = 0; c < 3; c++)
                    CHECK(t, fabs(tl.mean[i][c] - Yref[obj] * rgb_e[c]) < K_SIGMA * tl.se[i][c] + 3e-3,
                          "%s furnace, %s wavelengths, tile %d: rgb[%d] = %.5f +- %.2g, expected %.5f",
                          obj ? "glass" : "diffuse", wl_mode_name(modes[md]), i, c, tl.mean[i][c],
                          tl.se[i][c], Yref[obj] * rgb_e[c]);
            }
        }
}

/* A pdf agrees with uniform wavelengths on scene s, tile by tile. */
static int agrees_with_uniform(T *t, Scene *s, const RenderOptions *base, int K, const WlMode *modes,
                               int n_modes, const char *scene)
{
    RenderOptions o = *base;
    Tiles ref, other;
    int md;
    char what[128];
    o.wl_mode = WL_UNIFORM;
    if (!test_render_tiles(t, s, &o, K, 2, &ref)) return 0;
    for (md = 0; md < n_modes; md++) {
        o.wl_mode = modes[md];
        if (!test_render_tiles(t, s, &o, K, 2, &other)) return 0;
        snprintf(what, sizeof what, "%s: %s vs uniform wavelengths", scene, wl_mode_name(modes[md]));
        if (!test_tiles_agree(t, &ref, &other, 1e-4, what)) return 0;
    }
    return 1;
}

/* The dispersive box: F11 ceiling light, rough dispersive glass sphere; with
   termination and with rough spectral MIS. */
static void test_wl_dispersive_box(T *t)
{
    static const WlMode modes[2] = { WL_VISIBLE, WL_MIXTURE };
    char text[8192];
    Scene s;
    RenderOptions o;
    snprintf(text, sizeof text,
             "LookAt 0 0 -3.2  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 45 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
             "WorldBegin\n%s"
             "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" \"stdillum-F11\" \"float scale\" [ 6 ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -0.4 0.99 -0.4  0.4 0.99 -0.4  0.4 0.99 0.4  -0.4 0.99 0.4 ]\nAttributeEnd\n"
             "AttributeBegin\n Translate 0 -0.55 0\n"
             " Material \"dielectric\" \"float cauchyA\" [ 1.5 ] \"float cauchyB\" [ 0.04 ] \"float roughness\" [ 0.09 ]\n"
             " Shape \"sphere\" \"float radius\" [ 0.42 ]\nAttributeEnd\n",
             test_box_walls);
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.sel.grid_res = 8;
    o.spp = test_scaled(32, 4);
    o.maxdepth = 6;
    if (agrees_with_uniform(t, &s, &o, 10, modes, 2, "dispersive box, terminate")) {
        o.rough_mis = 1;
        agrees_with_uniform(t, &s, &o, 10, modes, 2, "dispersive box, rough MIS");
    }
    scene_free(&s);
}

/* The two scenes where importance by the emitters' spectra fails: every pdf is
   still unbiased there (16 x 16 pixels of the 48 x 48 film, the same view). */
static void test_wl_stress_scenes(T *t)
{
    static const char *files[2] = { "scenes/wl-hidden-lamp.pbrt", "scenes/wl-filter.pbrt" };
    static const WlMode modes[3] = { WL_IMPORTANCE, WL_VISIBLE, WL_MIXTURE };
    int f;
    for (f = 0; f < 2; f++) {
        Scene s;
        RenderOptions o;
        Error err;
        int ok;
        memset(&s, 0, sizeof s);
        CHECK(t, scene_load(&s, files[f], &err), "%s", err.msg);
        s.settings.xres = s.settings.yres = 16;
        render_options_default(&o);
        o.sel.grid_res = 8;
        /* at least 16 spp a seed: importance by the lamps' spectra fails here by
           design, so a pixel's samples are heavy-tailed, and 12 seeds of 8 spp
           (the quarter scale of the compiler and sanitizer steps) estimate the
           standard error too low (wl-filter: 5.4 "standard errors" apart at 8 spp
           with --light-shape-sampling auto, whose full-scale renders agree) */
        o.spp = test_scaled(32, 16);
        o.maxdepth = s.settings.maxdepth;
        ok = agrees_with_uniform(t, &s, &o, 12, modes, 3, files[f]);
        scene_free(&s);
        if (!ok) return;
    }
}

/* converge's variant names carry the wavelength pdf and pin settings (the
   factorial evaluation relies on it, tools/factorial.sh). */
static void test_wl_variant_names(T *t)
{
    RenderOptions o;
    render_options_default(&o);
    CHECK(t, eval_parse_variant("product:mixture=0.3:roughmis", &o), "mixture=0.3 refused");
    CHECK(t, o.sel.strategy == SEL_PRODUCT && o.wl_mode == WL_MIXTURE && o.wl_mix == 0.3f && o.rough_mis,
          "product:mixture=0.3:roughmis parsed wrong");
    o.sel.all_wavelengths = o.sel.throughput_weighted = o.sel.power_metric = 1;
    CHECK(t, eval_parse_variant("spatial:visible:terminate:hero:unit", &o), "pins refused");
    CHECK(t, o.wl_mode == WL_VISIBLE && !o.rough_mis && !o.sel.all_wavelengths && !o.sel.throughput_weighted
          && !o.sel.power_metric, "terminate, hero, unit must pin their settings");
    CHECK(t, eval_parse_variant("spatial:importance:uniform", &o) && o.wl_mode == WL_UNIFORM, "uniform");
    CHECK(t, !eval_parse_variant("spatial:mixture=0", &o) && !eval_parse_variant("spatial:mixture=1.5", &o)
          && !eval_parse_variant("spatial:mixture=x", &o) && !eval_parse_variant("spatial:hot", &o),
          "bad modifiers must be refused");
}

/* The thesis' settings (render_options_thesis, converge --base thesis) are the
   defaults with every factor pinned to the thesis' level by name: whatever the
   defaults are, the two agree field by field. */
static void test_thesis_options(T *t)
{
    RenderOptions a, b;
    render_options_thesis(&a);
    render_options_default(&b);
    CHECK(t, eval_parse_variant("spatial:uniform:terminate:unit:hero:independent:flterminate:fla:shapearea", &b),
          "pins refused");
    CHECK(t, a.wl_mode == WL_UNIFORM && a.sel.strategy == SEL_SPATIAL && !a.rough_mis &&
          a.sampler == SAMPLER_INDEPENDENT && !a.sel.power_metric && !a.sel.all_wavelengths &&
          !a.fluor_keep && a.fluor_li == FLUOR_LI_A,
          "render_options_thesis is not the thesis' baseline");
    CHECK(t, memcmp(&a, &b, sizeof a) == 0, "render_options_thesis differs from the defaults "
          "with the thesis' levels named");
}

/* Option "disablewavelengthjitter" (pbrt-v4's lu = 0.5: every sample at the four
   wavelengths SampleVisible(1/2) gives, 360-830 nm, divided by its visible pdf):
   the camera looks into a constant sky, so each pixel is the four-point quadrature
   of the sky's colour, the same in every sample and every pixel, and off the
   jittered colour by its quadrature error (R +22 %, B -42 % for D65).  pbrt-v4
   (commit 5f7a6068, `pbrt --spp 4 --seed 1 --nthreads 1`, a 4 x 4 film, all
   pixels equal) gives (1.2187500, 1.0146484, 0.6025391) for the default sky (D65)
   and (2.4511719, 0.7133789, 0.1408691) for "blackbody L" 2700; specnee's every
   pixel is within 1.2 % of these (measured: 0.3-0.8 %, the difference between
   specnee's 5-nm CIE table, linearly interpolated, and pbrt-v4's 1-nm one at four
   points; the jittered quadrature averages it away).  The typed spelling reads the
   same; "false" is the default. */
static void test_wl_no_jitter(T *t)
{
    static const struct { const char *opt, *L; double want[3]; } cases[] = {
        { "Option \"disablewavelengthjitter\" true\n", "", { 1.2187500, 1.0146484, 0.6025391 } },
        { "Option \"bool disablewavelengthjitter\" true\n", "\"blackbody L\" [ 2700 ]",
          { 2.4511719, 0.7133789, 0.1408691 } } };
    int c, i, k;
    for (c = 0; c < 2; c++) {
        char text[1024];
        RenderOptions o;
        Image im;
        snprintf(text, sizeof text, "%sLookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
                 "WorldBegin\nLightSource \"infinite\" %s\n", cases[c].opt, cases[c].L);
        render_options_default(&o);            /* the mixture pdf over 400-700 nm */
        o.spp = 4;
        o.seed = 1;
        o.threads = 2;
        if (!test_render_text(t, text, &o, &im)) return;
        for (i = 0; i < im.w * im.h; i++)
            for (k = 0; k < 3; k++) {
                double v = im.rgb[3 * i + k];
                if (!(fabs(v - cases[c].want[k]) < 0.012 * cases[c].want[k])) {
                    img_free(&im);
                    CHECK(t, 0, "case %d pixel %d channel %d: %.7f, pbrt-v4 %.7f", c, i, k, v,
                          cases[c].want[k]);
                }
            }
        img_free(&im);
    }
    {
        Scene s;
        Error e;
        CHECK(t, scene_load_string(&s, "Option \"disablewavelengthjitter\" false\nWorldBegin\n", "o.pbrt", &e),
              "%s", e.msg);
        CHECK(t, !s.settings.no_wavelength_jitter, "\"false\" set the option");
        scene_free(&s);
    }
}

const TestCase tests_wavelengths[] = {
    { "wavelengths_thesis_options", test_thesis_options },
    { "wavelengths_variant_names", test_wl_variant_names },
    { "wavelengths_visible_pdf", test_wl_visible },
    { "wavelengths_mixture_pdf", test_wl_mixture },
    { "wavelengths_guided_search", test_wl_guide },
    { "wavelengths_furnaces", test_wl_furnaces },
    { "wavelengths_dispersive_box", test_wl_dispersive_box },
    { "wavelengths_stress_scenes", test_wl_stress_scenes },
    { "wavelengths_no_jitter", test_wl_no_jitter },
    { NULL, NULL }
};
