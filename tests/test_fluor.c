/* tests/test_fluor.c - fluorescence (docs/FLUORESCENCE.md): the UV
   extension of the spectra (300-359 nm), UV lamps read as absolute radiance, the
   20 UV bins of emitter selection, and the named UV lamps and fluorophores. */
#include "test.h"
#include <string.h>
#include <stdlib.h>

#define UV_CAMERA "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n" \
    "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"string filename\" \"t.pfm\"\n" \
    "WorldBegin\n"

/* A UV LED sphere at x = -2 and a white LED sphere at x = 2, seen by UV_CAMERA. */
#define UV_AND_LED_SPHERES UV_CAMERA \
    "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-UVLED365\"\n" \
    "Translate -2 0 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n" \
    "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\"\n" \
    "Translate 2 0 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"

/* Emitter e's radiance for a film that integrates [lo, hi] nm (the render's,
   lights.c emitter_radiance); zero if it has none there. */
static Spectrum le_of(const Scene *s, int e, float lo, float hi)
{
    Spectrum Le;
    Error err;
    if (!emitter_radiance(s, e, lo, hi, &Le, &err)) memset(&Le, 0, sizeof Le);
    return Le;
}

/* The inline UV spectrum loads, means absolute radiance x scale, is finite,
   reaches into the UV extension and is zero where L is zero. */
static void test_uv_lamp_absolute(T *t)
{
    Scene s;
    const Emitter *em;
    Spectrum Le;
    int nm, b;
    if (!test_load_scene(t, &s, UV_CAMERA
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" [ 300 0 355 0 360 1 370 1 375 0 830 0 ] \"float scale\" 3\n"
            "Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n")) return;
    CHECK(t, s.n_emitters == 1, "one emitter");
    em = &s.emitters[0];
    CHECK(t, em->absolute == 1, "a lamp with no luminance in 400-700 nm is absolute");
    Le = le_of(&s, 0, LAMBDA_LO, LAMBDA_HI);
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
        CHECK(t, isfinite(spec_get(&Le, nm)), "Le finite at %d nm", nm);
    CHECK(t, spec_eval(&Le, 365.0f) == 3.0f, "Le = scale * L at 365 nm: %g", (double)spec_eval(&Le, 365.0f));
    CHECK(t, fabsf(spec_eval(&Le, 357.5f) - 1.5f) < 1e-6f, "UV extension interpolates: %g",
          (double)spec_eval(&Le, 357.5f));
    CHECK(t, spec_eval(&Le, 340.0f) == 0.0f && spec_eval(&Le, 500.0f) == 0.0f, "zero outside");
    /* UV bins: 355-360 holds the ramp 0 -> 3 (mean 1.5), 360-365 and 365-370 are 3 */
    {
        float b11 = spec_band_average(&Le, SPEC_UV_MIN + 55, 5), b12 = spec_band_average(&Le, SPEC_UV_MIN + 60, 5);
        float b13 = spec_band_average(&Le, SPEC_UV_MIN + 65, 5);
        CHECK(t, fabsf(b11 - 1.5f) < 1e-6f && b12 == 3.0f && b13 == 3.0f, "UV bins: %g %g %g",
              (double)b11, (double)b12, (double)b13);
    }
    for (b = 0; b < SPD_BINS; b++) CHECK(t, spec_bin_average(&Le, b) == 0.0f, "no visible bins");
    /* the same meaning when the film samples 360-830 nm */
    Le = le_of(&s, 0, 360.0f, 830.0f);
    CHECK(t, spec_eval(&Le, 365.0f) == 3.0f, "absolute in wide mode too");
    scene_free(&s);
}

/* A visible lamp keeps pbrt-v4's normalisation (absolute = 0), and an all-zero L
   is an error naming its line. */
static void test_uv_lamp_rules(T *t)
{
    Scene s;
    Spectrum Le;
    Error e;
    if (!test_load_scene(t, &s, UV_CAMERA
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-BLB\"\n"
            "Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n")) return;
    CHECK(t, s.emitters[0].absolute == 0, "BLB has luminance (its Hg lines): pbrt-v4's rule");
    Le = le_of(&s, 0, LAMBDA_LO, LAMBDA_HI);
    CHECK(t, spec_eval(&Le, 365.0f) > 10.0f * spec_eval(&Le, 404.66f),
          "BLB: the UV band dominates the visible leak");
    scene_free(&s);
    memset(&s, 0, sizeof s);
    CHECK(t, !scene_load_string(&s, UV_CAMERA "AttributeBegin\n"
              "AreaLightSource \"diffuse\" \"spectrum L\" [ 300 0 830 0 ]\n"
              "Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n", "z.pbrt", &e) &&
          strstr(e.msg, "z.pbrt:6:") && strstr(e.msg, "zero everywhere"),
          "all-zero L: '%s'", e.msg);
}

/* Spectral selection in a UV bin picks the UV lamp; in a visible bin the visible one. */
static void test_uv_bins_select(T *t)
{
    Scene s;
    SelOptions so;
    LightSampler *ls;
    LightCtx c;
    Error e;
    float P;
    int fb, j;
    if (!test_load_scene(t, &s, UV_AND_LED_SPHERES)) return;
    memset(&so, 0, sizeof so);
    so.strategy = SEL_SPD;
    ls = light_sampler_build(&s, &so, &e);
    CHECK(t, ls != NULL, "build: %s", e.msg);
    memset(&c, 0, sizeof c);
    c.p = v3(0, 0, 0);
    c.voxel = light_voxel(ls, c.p);
    c.alive = 1u;
    c.hero_only = 1;
    for (j = 0; j < HERO_N; j++) c.beta[j] = 1.0f;
    c.lambda[0] = 366.0f;
    CHECK(t, light_select(ls, &c, 0.5f, &P, &fb) == 0 && P > 0.999f && !fb,
          "at 366 nm spd picks the UV LED: P = %g, fell back %d", (double)P, fb);
    CHECK(t, light_select_pmf(ls, &c, 0) == P, "pmf agrees (C1)");
    c.lambda[0] = 550.0f;
    CHECK(t, light_select_pmf(ls, &c, 1) > 0.999f, "at 550 nm spd picks LED1");
    light_sampler_free(ls);
    scene_free(&s);
}

/* The named UV lamps and fluorophores exist, peak where their sources say, reach
   into the UV extension where they should, and the excitation spectra are valid
   absorptances (in [0, 1]). */
static void test_named_fluor_spectra(T *t)
{
    static const struct { const char *name; float peak; } want[] = {
        { "lamp-UVLED365", 365 }, { "lamp-BLB", 365 },
        { "fluor-brightener-ex", 355 }, { "fluor-brightener-em", 440 },
        { "fluor-fluorescein-ex", 490 }, { "fluor-fluorescein-em", 515 },
        { "fluor-pyranine-ex", 455 }, { "fluor-pyranine-em", 511 } };
    Spectrum sp;
    size_t i;
    int nm, arg;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        float m = -1.0f;
        CHECK(t, spec_named(&sp, want[i].name), "%s missing", want[i].name);
        arg = 0;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
            float v = spec_get(&sp, nm);
            CHECK(t, v >= 0.0f && v <= 1.0f, "%s at %d nm: %g outside [0,1]", want[i].name, nm, (double)v);
            if (v > m) { m = v; arg = nm; }
        }
        CHECK(t, abs(arg - (int)want[i].peak) <= 1, "%s peaks at %d nm, want %g", want[i].name, arg,
              (double)want[i].peak);
    }
    {   /* the glasses' indices extend into the UV as real indices (a shifted path may
           cross a prism there) */
        static const char *const glass[] = { "glass-BK7", "glass-BAF10", "glass-FK51A",
            "glass-LASF9", "glass-F5", "glass-F10", "glass-F11", "cauchy-SF11" };
        for (i = 0; i < sizeof glass / sizeof glass[0]; i++) {
            CHECK(t, spec_named(&sp, glass[i]), "%s missing", glass[i]);
            for (nm = SPEC_UV_MIN; nm < SPEC_MIN; nm++)
                CHECK(t, spec_get(&sp, nm) > 1.0f && spec_get(&sp, nm) < 3.0f &&
                      spec_get(&sp, nm) >= spec_get(&sp, nm + 1), "%s at %d nm: %g", glass[i], nm,
                      (double)spec_get(&sp, nm));
        }
    }
    spec_named(&sp, "lamp-UVLED365");   /* FWHM 9 nm: half maximum at 360.5 and 369.5 */
    CHECK(t, fabsf(spec_eval(&sp, 360.5f) - 0.5f) < 0.02f && fabsf(spec_eval(&sp, 369.5f) - 0.5f) < 0.02f,
          "UV LED FWHM 9 nm: %g %g", (double)spec_eval(&sp, 360.5f), (double)spec_eval(&sp, 369.5f));
    spec_named(&sp, "lamp-BLB");
    CHECK(t, spec_eval(&sp, 340.0f) > 0.05f, "BLB band reaches below 360 nm");
    spec_named(&sp, "fluor-brightener-ex");
    CHECK(t, spec_eval(&sp, 340.0f) > 0.5f && spec_eval(&sp, 420.0f) < 0.01f, "brightener absorbs UV only");
}

/* ---- the material and its transport (docs/FLUORESCENCE.md §1-§5) ---- */

#define FL_MAT(refl, ex, em, qy) "Material \"fluorescent\" \"spectrum reflectance\" " refl \
    " \"spectrum excitation\" " ex " \"spectrum emission\" " em " \"float quantumyield\" " qy "\n"

/* Bad input: a clear one-line error for each. */
static void test_fluor_parse_errors(T *t)
{
    static const struct { const char *mat, *want; } bad[] = {
        { FL_MAT("[300 1 830 1]", "\"fluor-brightener-ex\"", "\"fluor-brightener-em\"", "1.5"), "quantumyield\": 1.5 is outside [0,1]" },
        { FL_MAT("[300 1 830 1]", "\"fluor-brightener-ex\"", "\"fluor-brightener-em\"", "-0.1"), "outside [0,1]" },
        { FL_MAT("[300 1 830 1]", "[300 0.5 400 1.2 830 0]", "\"fluor-brightener-em\"", "0.9"), "\"spectrum excitation\": value" },
        { FL_MAT("[300 1 830 1]", "[300 -0.1 830 0]", "\"fluor-brightener-em\"", "0.9"), "\"spectrum excitation\": value -" },
        { FL_MAT("[300 1 830 1]", "\"fluor-brightener-ex\"", "[300 0 830 0]", "0.9"), "\"spectrum emission\": zero everywhere" },
        { "Material \"fluorescent\" \"spectrum excitation\" \"fluor-brightener-ex\"\n", "needs \"spectrum excitation\" and \"spectrum emission\"" },
    };
    size_t i;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        Scene s;
        Error e;
        char text[1024];
        snprintf(text, sizeof text, "%s%s", UV_CAMERA, bad[i].mat);
        memset(&s, 0, sizeof s);
        e.msg[0] = 0;
        CHECK(t, !scene_load_string(&s, text, "f.pbrt", &e) && strstr(e.msg, "f.pbrt:5:") &&
              strstr(e.msg, bad[i].want), "case %d: got '%s', want '%s'", (int)i, e.msg, bad[i].want);
    }
}

/* A material from scene text (the first material of the scene). */
static int load_fluor(T *t, Scene *s, const char *mat)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%sShape \"sphere\" \"float radius\" 1\n", UV_CAMERA, mat);
    if (!test_load_scene(t, s, text)) return 0;
    if (s->n_materials < 1 || s->materials[s->n_materials - 1].type != MAT_FLUORESCENT) {
        test_failf(t, __FILE__, __LINE__, "no fluorescent material");
        return 0;
    }
    return 1;
}

/* Integral of A over [a, b] by a fine midpoint rule on spec_eval (independent of
   the material's tables). */
static double quad_A(const Material *m, double a, double b)
{
    double sum = 0.0, h = 0.01, x;
    for (x = a + 0.5 * h; x < b; x += h) sum += spec_eval(&m->fl->excitation, (float)x) * h;
    return sum;
}

/* chi^2 of the lambda_i sampler against the pdf (F3) it claims, with the expected
   counts from an independent quadrature of A; and p(li | lo) integrates to 1 and
   vanishes above lo (the Stokes rule). */
static void test_fluor_li_sampler(T *t)
{
    Scene s;
    const Material *m;
    enum { NB = 34 };
    const double lo = 470.0;
    double cnt[NB], ex[NB], total, pint = 0.0, x;
    int n = test_scaled(40000, 4000), i, b;
    Rng rng;
    Chi2 c;
    if (!load_fluor(t, &s, FL_MAT("[300 1 830 1]", "\"fluor-pyranine-ex\"", "\"fluor-pyranine-em\"", "0.9"))) return;
    m = &s.materials[s.n_materials - 1];
    memset(cnt, 0, sizeof cnt);
    rng_seed(&rng, 17, 0);
    for (i = 0; i < n; i++) {
        float pdf, li = fluor_sample_li(m, (float)lo, rng_float(&rng), &pdf);
        CHECK(t, li >= 300.0f && li <= (float)lo && pdf > 0.0f, "sample %g nm pdf %g", (double)li, (double)pdf);
        CHECK(t, fabsf(pdf - fluor_pdf_li(m, (float)lo, li)) <= 1e-6f * pdf, "sampler and pdf agree");
        b = (int)((li - 300.0f) / 5.0f);
        if (b >= NB) b = NB - 1;
        cnt[b] += 1.0;
    }
    total = quad_A(m, 300.0, lo);
    for (b = 0; b < NB; b++) ex[b] = n * quad_A(m, 300.0 + 5.0 * b, b == NB - 1 ? lo : 300.0 + 5.0 * (b + 1)) / total;
    CHECK_CHI2(t, cnt, ex, NB, 1, &c, "p_A (li | 470 nm)");
    CHECK(t, c.dof >= 20, "only %d degrees of freedom", c.dof);
    for (x = 299.995; x < 600.0; x += 0.01) pint += fluor_pdf_li(m, (float)lo, (float)x) * 0.01;
    CHECK(t, fabs(pint - 1.0) < 2e-3, "p(li | lo) integrates to %g", pint);
    CHECK(t, fluor_pdf_li(m, (float)lo, (float)lo + 1.0f) == 0.0f, "no density above lo");
    scene_free(&s);
}

/* The scene of the render tests: the camera inside a closed, non-reflecting,
   two-sided emitting sphere of radius 10 (the environment), looking at a
   fluorescent unit sphere that fills the view; the fluorescent sphere sees only
   the environment, so one bounce is exact. */
static int load_furnace(T *t, Scene *s, const char *env_L, const char *mat)
{
    char text[4096];
    snprintf(text, sizeof text,
             "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 10\n"
             "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4 \"string filename\" \"t.pfm\"\n"
             "Integrator \"path\" \"integer maxdepth\" 3\n"
             "WorldBegin\n"
             "AttributeBegin\nMaterial \"diffuse\" \"spectrum reflectance\" [300 0 830 0]\n"
             "AreaLightSource \"diffuse\" \"spectrum L\" %s \"bool twosided\" true\n"
             "Shape \"sphere\" \"float radius\" 10\nAttributeEnd\n"
             "%sShape \"sphere\" \"float radius\" 1\n", env_L, mat);
    return test_load_scene(t, s, text);
}

/* The expected radiance of the fluorescent sphere at lo under the environment's
   Le, from (F1)-(F2) by quadrature (1/4 nm), written independently of material.c:
   rho (1 - A) Le(lo) + int Phi A(li) e(lo) (li/lo) / N(li) Le(li) dli, with N by
   its own quadrature. */
static double model_Lo(const Material *m, const Spectrum *Le, double lo, const double *Ntab)
{
    double sum = 0.0, h = 0.25, li;
    double e = spec_eval(&m->fl->emission, (float)lo);
    for (li = 300.0 + 0.5 * h; li < lo; li += h) {
        int k = (int)((li - 300.0) / h);
        if (Ntab[k] > 0.0)
            sum += m->fl->qyield * spec_eval(&m->fl->excitation, (float)li) * e * (li / lo) / Ntab[k]
                   * spec_eval(Le, (float)li) * h;
    }
    return albedo_eval(&m->reflectance, (float)lo) * (1.0 - spec_eval(&m->fl->excitation, (float)lo))
           * spec_eval(Le, (float)lo) + sum;
}

/* N(li) at li = 300 + (k + 1/2) h, the integral of e over [li, 830], by the
   midpoint rule on the same 1/4 nm grid (half a cell for the cell of li itself). */
static double *model_N(const Material *m)
{
    const double h = 0.25;
    int nk = (int)(530.0 / h), k;
    double *N = (double *)malloc(sizeof(double) * (size_t)nk), above = 0.0;
    if (!N) return NULL;
    for (k = nk - 1; k >= 0; k--) {
        double x = 300.0 + (k + 0.5) * h, e = spec_eval(&m->fl->emission, (float)x);
        N[k] = above + 0.5 * h * e;
        above += h * e;
    }
    return N;
}

/* Expected linear sRGB of the fluorescent sphere over the film range [a, b]:
   int cbar(lo) Lo(lo) dlo by the midpoint rule (1/2 nm), then pbrt-v4's matrix. */
static void model_rgb(const Material *m, const Spectrum *Le, double a, double b, double rgb[3],
                      double *photons_in, double *photons_out, double *energy_in, double *energy_out)
{
    double xyz[3] = { 0, 0, 0 }, lo, h = 0.5;
    double *N = model_N(m);
    *photons_in = *photons_out = *energy_in = *energy_out = 0.0;
    if (!N) return;
    for (lo = a + 0.5 * h; lo < b; lo += h) {
        float c[3];
        double L = model_Lo(m, Le, lo, N);
        cie_xyz((float)lo, c);
        xyz[0] += c[0] * L * h; xyz[1] += c[1] * L * h; xyz[2] += c[2] * L * h;
    }
    for (lo = 300.0 + 0.5 * h; lo < 830.0; lo += h) {   /* photons ~ L lambda, energy ~ L */
        double L = model_Lo(m, Le, lo, N), E = spec_eval(Le, (float)lo);
        *photons_out += L * lo * h; *photons_in += E * lo * h;
        *energy_out += L * h; *energy_in += E * h;
    }
    free(N);
    xyz_to_linear_srgb(xyz, rgb);
}

/* The line tests' scene: the 365 nm LED on a fluorescent furnace (rho 0.8, A on
   345-390 nm, emission 330-520 nm, Phi 0.9) and their options (spp samples, one
   thread, the wide 360-830 nm range, spd selection). */
static int load_line_scene(T *t, Scene *s, RenderOptions *o, int spp)
{
    if (!load_furnace(t, s, "\"lamp-UVLED365\"",
                      FL_MAT("[300 0.8 830 0.8]", "[300 0 345 0 350 1 380 1 390 0 830 0]", "[330 0 360 0.6 400 1 520 0]", "0.9")))
        return 0;
    render_options_default(o);
    o->spp = spp;
    o->threads = 1;
    o->wl_wide = 1;
    o->sel.strategy = SEL_SPD;
    return 1;
}

/* Line test: a narrow UV source (the 365 nm LED, FWHM 9 nm) as the environment;
   the sphere shows only re-radiated light Phi A(365) e(lo) (365/lo) / N(365)
   (spread over the LED's band), and the render must match the quadrature of the
   model in every channel within TEST_K_SIGMA standard errors.  Dropping li/lo,
   allowing anti-Stokes emission or mis-weighting the branch moves the mean. */
static void test_fluor_line(T *t)
{
    Scene s;
    Spectrum Le;
    RenderOptions o;
    Tiles tl;
    double rgb[3], pin, pout, ein, eout;
    int c;
    if (!load_line_scene(t, &s, &o, test_scaled(2048, 256))) return;
    if (!test_render_tiles(t, &s, &o, 8, 1, &tl)) { scene_free(&s); return; }
    Le = le_of(&s, 0, 360.0f, 830.0f);
    model_rgb(&s.materials[s.n_materials - 1], &Le, 360.0, 830.0, rgb, &pin, &pout, &ein, &eout);
    for (c = 0; c < 3; c++)
        CHECK(t, fabs(tl.mean[0][c] - rgb[c]) < TEST_K_SIGMA * tl.se[0][c] + 2e-3 * fabs(rgb[c]),
              "channel %d: render %.6g +- %.2g, model %.6g", c, tl.mean[0][c], tl.se[0][c], rgb[c]);
    if (getenv("FLUOR_VERBOSE"))
        printf("line: render (%g %g %g) +- (%g %g %g), model (%g %g %g)\n", tl.mean[0][0], tl.mean[0][1],
               tl.mean[0][2], tl.se[0][0], tl.se[0][1], tl.se[0][2], rgb[0], rgb[1], rgb[2]);
    CHECK(t, rgb[2] > 0.05, "the sphere glows blue: model rgb (%g %g %g)", rgb[0], rgb[1], rgb[2]);
    scene_free(&s);
}

/* The line scene filled with a medium that is opaque (sigma_a 5 per unit) to the
   exciting UV below 400 nm and clear above: the camera sees the sphere through
   clear medium, but the LED's light must cross 9 units of it to reach the
   sphere, so there is no glow (exp(-45)).  The shadow rays leave the sphere at the
   absorbed wavelength li, not at the camera's: the medium's coefficients must
   follow the path's wavelengths across the fluorescent shift. */
static void test_fluor_in_medium(T *t)
{
    Scene s;
    Spectrum Le;
    RenderOptions o;
    Tiles tl;
    double rgb[3], pin, pout, ein, eout;
    char text[4096];
    int c;
    snprintf(text, sizeof text,
             "MakeNamedMedium \"uvfog\" \"string type\" \"homogeneous\" "
             "\"spectrum sigma_a\" [300 5 395 5 400 0 830 0] \"spectrum sigma_s\" [300 0 830 0]\n"
             "MediumInterface \"\" \"uvfog\"\n"
             "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 10\n"
             "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4 \"string filename\" \"t.pfm\"\n"
             "Integrator \"volpath\" \"integer maxdepth\" 3\n"
             "WorldBegin\n"
             "AttributeBegin\nMaterial \"diffuse\" \"spectrum reflectance\" [300 0 830 0]\n"
             "AreaLightSource \"diffuse\" \"spectrum L\" \"lamp-UVLED365\" \"bool twosided\" true\n"
             "Shape \"sphere\" \"float radius\" 10\nAttributeEnd\n"
             "%sShape \"sphere\" \"float radius\" 1\n",
             FL_MAT("[300 0.8 830 0.8]", "[300 0 345 0 350 1 380 1 390 0 830 0]", "[330 0 360 0.6 400 1 520 0]", "0.9"));
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.settings.camera_medium >= 0, "the camera sits in the medium");
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    o.threads = 1;
    o.wl_wide = 1;
    o.sel.strategy = SEL_SPD;
    if (!t->failed && test_render_tiles(t, &s, &o, 4, 1, &tl)) {
        Le = le_of(&s, 0, 360.0f, 830.0f);
        model_rgb(&s.materials[s.n_materials - 1], &Le, 360.0, 830.0, rgb, &pin, &pout, &ein, &eout);
        CHECK(t, rgb[2] > 0.05, "without the medium the sphere glows blue: model rgb (%g %g %g)", rgb[0], rgb[1], rgb[2]);
        for (c = 0; c < 3; c++)
            CHECK(t, fabs(tl.mean[0][c]) < 1e-3 * rgb[2], "channel %d: %.4g, but the medium absorbs the excitation "
                  "(the glow without it: %.4g)", c, tl.mean[0][c], rgb[2]);
    }
    scene_free(&s);
}

/* Photon furnace: Phi = rho = 1, A = 1 in a UV-A band inside the film's range
   (375-395 nm, so the camera sees the band's own reflectance drop), a flat
   environment.  The model conserves photons and loses energy; the render must
   match the model (so rho (1 - A), not rho; li/lo; and the branch weights are
   checked by the renderer itself). */
static void test_fluor_photon_furnace(T *t)
{
    Scene s;
    Spectrum Le;
    RenderOptions o;
    Tiles tl;
    double rgb[3], pin, pout, ein, eout;
    int c;
    if (!load_furnace(t, &s, "[300 1 830 1]",
                      FL_MAT("[300 1 830 1]", "[300 0 370 0 375 1 395 1 400 0 830 0]", "[420 0 470 1 520 0]", "1")))
        return;
    render_options_default(&o);
    o.spp = test_scaled(256, 32);
    o.threads = 1;
    o.wl_wide = 1;
    if (!test_render_tiles(t, &s, &o, 8, 1, &tl)) { scene_free(&s); return; }
    Le = le_of(&s, 0, 360.0f, 830.0f);
    model_rgb(&s.materials[s.n_materials - 1], &Le, 360.0, 830.0, rgb, &pin, &pout, &ein, &eout);
    if (getenv("FLUOR_VERBOSE"))
        printf("furnace: render (%g %g %g) +- (%g %g %g), model (%g %g %g)\n", tl.mean[0][0], tl.mean[0][1],
               tl.mean[0][2], tl.se[0][0], tl.se[0][1], tl.se[0][2], rgb[0], rgb[1], rgb[2]);
    /* the model as written: photon radiance equal over 300-830 nm (to the quadrature's
       accuracy), energy strictly less */
    CHECK(t, fabs(pout - pin) < 2e-3 * pin, "photon radiance: out %.8g, in %.8g", pout, pin);
    CHECK(t, eout < ein * (1.0 - 1e-3), "energy: out %.8g must be below in %.8g", eout, ein);
    for (c = 0; c < 3; c++)
        CHECK(t, fabs(tl.mean[0][c] - rgb[c]) < TEST_K_SIGMA * tl.se[0][c] + 2e-3 * fabs(rgb[c]),
              "channel %d: render %.6g +- %.2g, model %.6g", c, tl.mean[0][c], tl.se[0][c], rgb[c]);
    scene_free(&s);
    /* The Stokes rule: excitation and emission bands that overlap (as fluorescein's
       do), so anti-Stokes emission would add light at the short side. */
    if (!load_furnace(t, &s, "[300 1 830 1]",
                      FL_MAT("[300 1 830 1]", "[300 0 440 0 470 1 500 1 510 0 830 0]", "[440 0 490 1 560 0]", "1")))
        return;
    if (!test_render_tiles(t, &s, &o, 8, 1, &tl)) { scene_free(&s); return; }
    Le = le_of(&s, 0, 360.0f, 830.0f);
    model_rgb(&s.materials[s.n_materials - 1], &Le, 360.0, 830.0, rgb, &pin, &pout, &ein, &eout);
    CHECK(t, fabs(pout - pin) < 2e-3 * pin && eout < ein * (1.0 - 1e-4), "overlap: photons %.8g / %.8g, energy %.8g / %.8g",
          pout, pin, eout, ein);
    for (c = 0; c < 3; c++)
        CHECK(t, fabs(tl.mean[0][c] - rgb[c]) < TEST_K_SIGMA * tl.se[0][c] + 2e-3 * fabs(rgb[c]),
              "overlap, channel %d: render %.6g +- %.2g, model %.6g", c, tl.mean[0][c], tl.se[0][c], rgb[c]);
    scene_free(&s);
}

/* ---- spectral checks, one band of the film at a time (RenderOptions.band_lo/hi:
   the camera samples only the band, the emitters keep the film's normalisation) ---- */

/* Render the band [a, b] of s with o (K seeds, one tile) and compare every channel
   with the model's rgb of that band within TEST_K_SIGMA standard errors plus a
   relative slack rel (quadrature error) and an absolute floor abs_floor. */
static int band_matches(T *t, Scene *s, const RenderOptions *o, double a, double b, int K,
                        const double want[3], double rel, double abs_floor, const char *what)
{
    RenderOptions ob = *o;
    Tiles tl;
    int c, ok = 1;
    ob.band_lo = (float)a;
    ob.band_hi = (float)b;
    if (!test_render_tiles(t, s, &ob, K, 1, &tl)) return 0;
    for (c = 0; c < 3; c++) {
        double d = fabs(tl.mean[0][c] - want[c]);
        if (!(d < TEST_K_SIGMA * tl.se[0][c] + rel * fabs(want[c]) + abs_floor)) {
            test_failf(t, __FILE__, __LINE__, "%s, %g-%g nm, channel %d: render %.6g +- %.2g, model %.6g",
                       what, a, b, c, tl.mean[0][c], tl.se[0][c], want[c]);
            ok = 0;
        }
    }
    if (getenv("FLUOR_VERBOSE"))
        printf("%s %g-%g: render (%.5g %.5g %.5g) +- (%.2g %.2g %.2g), model (%.5g %.5g %.5g)\n", what, a, b,
               tl.mean[0][0], tl.mean[0][1], tl.mean[0][2], tl.se[0][0], tl.se[0][1], tl.se[0][2],
               want[0], want[1], want[2]);
    return ok;
}

/* Line test per 10 nm bin: the 365 nm LED scene of fluor_line, each
   10 nm bin of 360-530 nm rendered alone and compared with the quadrature of the
   model over that bin, Phi A e(lo) (li/lo) / N(li) integrated over the LED's band:
   the output spectrum, not only its colour. */
static void test_fluor_line_bins(T *t)
{
    Scene s;
    Spectrum Le;
    RenderOptions o;
    double a;
    if (!load_line_scene(t, &s, &o, test_scaled(96, 32))) return;
    Le = le_of(&s, 0, 360.0f, 830.0f);
    for (a = 360.0; a < 530.0; a += 10.0) {
        double rgb[3], pin, pout, ein, eout;
        model_rgb(&s.materials[s.n_materials - 1], &Le, a, a + 10.0, rgb, &pin, &pout, &ein, &eout);
        if (!band_matches(t, &s, &o, a, a + 10.0, 16, rgb, 2e-3, 1e-7, "line")) break;
    }
    scene_free(&s);
}

/* The closed sphere (docs/FLUORESCENCE.md §7b).  Inside a closed sphere
   whose wall is the fluorescent material and emits Le uniformly, the radiance is
   the same everywhere and in every direction, and (F1)-(F2) with the wall's own
   1/pi cos integrating to 1 give the wavelength equation L = Le + P L:
       L(lo) = Le(lo) + a_r(lo) L(lo) + int_300^lo K(li, lo) L(li) dli,
       a_r = rho (1 - A),  K(li, lo) = Phi A(li) e(lo) (li/lo) / N(li).
   P is triangular (the Stokes rule), so on a grid x_0 < x_1 < ... the trapezoid
   rule gives L at x_k from the L at x_i, i < k, by forward substitution:
       L_k (1 - a_r(x_k) - w_k K(x_k, x_k)) = Le(x_k) + sum_{i<k} w_i K(x_i, x_k) L_i.
   Everything here (N, the grid, the colour integral) is computed from spec_eval
   alone, independently of material.c. */
typedef struct {
    double h;                 /* grid step, nm */
    int n;                    /* knots 300 + k h, k < n */
    double *L;                /* the solution at the knots */
} SphereModel;

static int closed_sphere_solve(const Material *m, const Spectrum *Le, SphereModel *sm)
{
    const double h = 0.25;
    int n = (int)(530.0 / h) + 1, k, i;
    double *N = (double *)malloc(sizeof(double) * (size_t)n), *A = (double *)malloc(sizeof(double) * (size_t)n);
    sm->h = h;
    sm->n = n;
    sm->L = (double *)malloc(sizeof(double) * (size_t)n);
    if (!N || !A || !sm->L) { free(N); free(A); free(sm->L); sm->L = NULL; return 0; }
    N[n - 1] = 0.0;
    for (k = n - 2; k >= 0; k--)      /* N(x_k) = int_{x_k}^{830} e, trapezoid */
        N[k] = N[k + 1] + 0.5 * h * (spec_eval(&m->fl->emission, (float)(300.0 + k * h)) +
                                     spec_eval(&m->fl->emission, (float)(300.0 + (k + 1) * h)));
    for (k = 0; k < n; k++) A[k] = spec_eval(&m->fl->excitation, (float)(300.0 + k * h));
    for (k = 0; k < n; k++) {
        double lo = 300.0 + k * h, e = spec_eval(&m->fl->emission, (float)lo);
        double ar = albedo_eval(&m->reflectance, (float)lo) * (1.0 - A[k]);
        double rhs = spec_eval(Le, (float)lo), diag = 1.0 - ar;
        for (i = 0; i <= k; i++) {
            double li = 300.0 + i * h, w = (i == 0 || i == k) ? 0.5 * h : h, K;
            if (!(N[i] > 0.0) || k == 0) continue;
            K = m->fl->qyield * A[i] * e * (li / lo) / N[i];
            if (i < k) rhs += w * K * sm->L[i];
            else diag -= w * K;
        }
        sm->L[k] = rhs / diag;
    }
    free(N);
    free(A);
    return 1;
}

/* The model's linear sRGB over the band [a, b]: int cbar L by the trapezoid rule on
   the model's grid, then pbrt-v4's matrix. */
static void closed_sphere_rgb(const SphereModel *sm, double a, double b, double rgb[3])
{
    double xyz[3] = { 0, 0, 0 };
    int k;
    for (k = 0; k + 1 < sm->n; k++) {
        double x0 = 300.0 + k * sm->h, x1 = x0 + sm->h, y, c, j;
        if (x1 <= a || x0 >= b) continue;
        for (j = 0; j < 2; j++) {     /* the cell's overlap with the band, 2-point Gauss */
            double lo = x0 > a ? x0 : a, hi = x1 < b ? x1 : b, g = (j == 0 ? -1.0 : 1.0) / sqrt(3.0);
            float cm[3];
            y = 0.5 * (lo + hi) + 0.5 * (hi - lo) * g;
            c = sm->L[k] + (sm->L[k + 1] - sm->L[k]) * (y - x0) / sm->h;
            cie_xyz((float)y, cm);
            xyz[0] += 0.5 * (hi - lo) * cm[0] * c;
            xyz[1] += 0.5 * (hi - lo) * cm[1] * c;
            xyz[2] += 0.5 * (hi - lo) * cm[2] * c;
        }
    }
    xyz_to_linear_srgb(xyz, rgb);
}

#define CLOSED_SPHERE_MAT FL_MAT("[300 0.6 830 0.6]", "[300 0 340 0 350 0.9 470 0.9 490 0 830 0]", \
                                 "[300 0 420 0 470 1 540 0 830 0]", "0.8")

static int load_closed_sphere(T *t, Scene *s)
{
    return test_load_scene(t, s,
        "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 60\n"
        "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4 \"string filename\" \"t.pfm\"\n"
        "Integrator \"path\" \"integer maxdepth\" 200\n"
        "WorldBegin\n"
        CLOSED_SPHERE_MAT
        "AreaLightSource \"diffuse\" \"spectrum L\" [300 1 830 1] \"bool twosided\" true\n"
        "Shape \"sphere\" \"float radius\" 1\n");
}

/* Per 10 nm bin over 400-700 nm with the default settings, then the whole film
   range for every way of sampling lambda_i and both hero-wavelength modes. */
static void test_fluor_closed_sphere(T *t)
{
    Scene s;
    Spectrum Le;
    RenderOptions o;
    SphereModel sm;
    double a, rgb[3];
    int v;
    if (!load_closed_sphere(t, &s)) return;
    Le = le_of(&s, 0, LAMBDA_LO, LAMBDA_HI);
    if (!closed_sphere_solve(&s.materials[s.n_materials - 1], &Le, &sm)) {
        test_failf(t, __FILE__, __LINE__, "out of memory");
        scene_free(&s);
        return;
    }
    {   /* the fluorescence is real: the sphere is brighter at 520 nm than a plain
           reflector of albedo 0.6 (Le / 0.4) and darker in the absorption band */
        double L520 = sm.L[(int)((520.0 - 300.0) / sm.h)], L400 = sm.L[(int)((400.0 - 300.0) / sm.h)];
        double Le0 = spec_eval(&Le, 520.0f);
        CHECK(t, L520 > 1.2 * Le0 / 0.4 && L400 < Le0 / 0.4, "model: L(520) %g, L(400) %g, Le %g",
              L520, L400, Le0);
    }
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    o.threads = 1;
    o.maxdepth = 200;          /* the options', not the file's: 0.8^200 of truncation */
    for (a = 400.0; a < 700.0; a += 10.0) {
        closed_sphere_rgb(&sm, a, a + 10.0, rgb);
        if (!band_matches(t, &s, &o, a, a + 10.0, 16, rgb, 1e-3, 1e-6, "closed sphere")) break;
    }
    closed_sphere_rgb(&sm, LAMBDA_LO, LAMBDA_HI, rgb);
    for (v = 0; v < 6; v++) {
        static const char *const name[] = { "li ~ A", "li ~ A x power", "li uniform",
                                            "li ~ A, lanes kept", "li ~ A x power, lanes kept",
                                            "li uniform, lanes kept" };
        RenderOptions ov = o;
        ov.fluor_li = v % 3 == 0 ? FLUOR_LI_A : v % 3 == 1 ? FLUOR_LI_POWER : FLUOR_LI_UNIFORM;
        ov.fluor_keep = v >= 3;
        ov.spp = test_scaled(256, 32);
        ov.seed = 100 + v;
        if (!band_matches(t, &s, &ov, LAMBDA_LO, LAMBDA_HI, 16, rgb, 1e-3, 1e-6, name[v])) break;
    }
    free(sm.L);
    scene_free(&s);
}

/* Unbiasedness: a UV LED, a visible LED and a fluorescent sphere on a diffuse floor.
   NEE+MIS with every emitter strategy and BSDF sampling only must agree tile by
   tile.  NEE at lo after a shift, or a selection pmf at lo in the MIS weight,
   would break the agreement. */
static void test_fluor_estimators_agree(T *t)
{
    static const SelStrategy strat[] = { SEL_SPD, SEL_UNIFORM, SEL_POWER, SEL_SPATIAL,
                                         SEL_PRODUCT, SEL_SPECTRAL_SPATIAL };
    Scene s;
    RenderOptions o;
    static Tiles ref, other;
    size_t i;
    int K = 16;
    if (!test_load_scene(t, &s,
            "LookAt 0 1 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n"
            "Film \"rgb\" \"integer xresolution\" 12 \"integer yresolution\" 12 \"string filename\" \"t.pfm\"\n"
            "Integrator \"path\" \"integer maxdepth\" 4\n"
            "WorldBegin\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-BLB\" \"float scale\" 0.02\n"
            "Translate -1.5 2.8 1\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\" \"float scale\" 1\n"
            "Translate 1.5 2.5 1\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
            "Material \"diffuse\" \"spectrum reflectance\" [300 0.5 830 0.5]\n"
            "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [-4 -1 -4  4 -1 -4  4 -1 4  -4 -1 4]\n"
            FL_MAT("[300 0.7 830 0.7]", "\"fluor-brightener-ex\"", "\"fluor-brightener-em\"", "0.9")
            "Shape \"sphere\" \"float radius\" 1\n")) return;
    render_options_default(&o);
    o.spp = test_scaled(96, 16);
    o.threads = 1;
    o.sel.strategy = SEL_SPD;
    o.fluor_keep = 0;          /* the baseline: secondaries terminated, lambda_i ~ A */
    o.fluor_li = FLUOR_LI_A;
    o.sel.grid_res = 4;
    if (!test_render_tiles(t, &s, &o, K, 3, &ref)) { scene_free(&s); return; }
    for (i = 0; i <= sizeof strat / sizeof strat[0]; i++) {
        RenderOptions oi = o;
        char what[64];
        if (i < sizeof strat / sizeof strat[0]) { oi.sel.strategy = strat[i]; oi.seed = 7 + (int)i; }
        else { oi.nee = 0; oi.spp *= 4; oi.seed = 99; }           /* BSDF sampling only */
        oi.fluor_keep = i % 2;     /* both hero-wavelength modes against the baseline */
        if (i == 0) continue;
        if (!test_render_tiles(t, &s, &oi, K, 3, &other)) { scene_free(&s); return; }
        snprintf(what, sizeof what, "%s%s vs spd", i < sizeof strat / sizeof strat[0] ? sel_name(strat[i]) : "BSDF only",
                 oi.fluor_keep ? ", lanes kept" : "");
        if (!test_tiles_agree(t, &ref, &other, 1e-3, what)) { scene_free(&s); return; }
    }
    scene_free(&s);
}

/* A card that only re-radiates (rho = 0, A = 1 over 350-380 nm, emission 380-520 nm)
   facing the camera, maxdepth 1, lit by a UV LED sphere (its scale and radius given)
   to the right and a white LED1 sphere of radius 0.7 (its scale given) to the left:
   the scene of fluor_mis_pmf_at_li and fluor_shift_selects_spectrally. */
static int load_uv_card(T *t, Scene *s, const char *uv_scale, const char *uv_radius,
                        const char *led_scale)
{
    char text[2048];
    snprintf(text, sizeof text,
            "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 25\n"
            "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"string filename\" \"t.pfm\"\n"
            "Integrator \"path\" \"integer maxdepth\" 1\n"
            "WorldBegin\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-UVLED365\" \"float scale\" %s\n"
            "Translate 1.5 0 0.9\nShape \"sphere\" \"float radius\" %s\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\" \"float scale\" %s\n"
            "Translate -1.5 0 0.9\nShape \"sphere\" \"float radius\" 0.7\nAttributeEnd\n"
            FL_MAT("[300 0 830 0]", "[300 0 345 0 350 1 380 1 385 0 830 0]", "[380 0 440 1 520 0]", "1")
            "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [-3 -3 0  3 -3 0  3 3 0  -3 3 0]\n", uv_scale, uv_radius, led_scale);
    return test_load_scene(t, s, text);
}

/* The MIS weights after a shift use the selection pmf at lambda_i (docs/FLUORESCENCE.md §5,
   contract C1).  A card that only re-radiates (rho = 0, A = 1 over 350-380 nm) lit
   by a UV LED (nothing in 400-700 nm) beside a white LED1 (nothing below 380 nm):
   at lambda_i the spectral strategies choose the UV LED with P = 1, at lambda_o they
   would give it P = 0.  A pmf taken at lambda_o sets q_nee = 0 in the weight of the
   UV light found by BSDF sampling, so that weight becomes 1 while NEE keeps its
   own: the weights sum to 1 + w_nee and the card comes out up to twice too bright.
   The lamps are spheres that subtend about 0.5 sr, so BSDF sampling finds them
   often and w_nee is large: the bias is tens of percent against a standard error
   of about 1 % on the image mean.  BSDF sampling alone (no selection pmf at all)
   and uniform selection (a pmf that does not depend on lambda) are the
   independent references; every spectral strategy must agree with both. */
static void test_fluor_mis_pmf_at_li(T *t)
{
    static const SelStrategy strat[] = { SEL_SPD, SEL_PRODUCT, SEL_SPECTRAL_SPATIAL,
                                         SEL_SPECTRAL_TREE, SEL_TREE, SEL_POWER };
    Scene s;
    RenderOptions o;
    static Tiles ref, other;
    size_t i;
    int K = 8;
    if (!load_uv_card(t, &s, "0.05", "0.7", "1")) return;
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    o.threads = 1;
    o.sel.strategy = SEL_UNIFORM;
    o.fluor_keep = 0;          /* the baseline: secondaries terminated, lambda_i ~ A */
    o.fluor_li = FLUOR_LI_A;
    if (!test_render_tiles(t, &s, &o, K, 1, &ref)) { scene_free(&s); return; }
    CHECK(t, ref.mean[0][2] > 0.01 && ref.se[0][2] < 0.06 * ref.mean[0][2],
          "the card glows blue with a small standard error: %g +- %g", ref.mean[0][2], ref.se[0][2]);
    for (i = 0; i <= sizeof strat / sizeof strat[0] + 6; i++) {
        RenderOptions oi = o;
        char what[64];
        size_t ns = sizeof strat / sizeof strat[0];
        if (i < ns) { oi.sel.strategy = strat[i]; oi.seed = 11 + (int)i; }
        else if (i == ns) { oi.nee = 0; oi.spp *= 4; oi.seed = 77; }   /* BSDF sampling only */
        else if (i <= ns + 2) { oi.sel.strategy = i == ns + 1 ? SEL_PRODUCT : SEL_UNIFORM; oi.fluor_li = FLUOR_LI_POWER; oi.seed = 55 + (int)i; }
        else if (i == ns + 3) { oi.sel.strategy = SEL_PRODUCT; oi.fluor_li = FLUOR_LI_UNIFORM; oi.spp *= 2; oi.seed = 61; }
        else {
            oi.sel.strategy = i == ns + 4 ? SEL_SPECTRAL_TREE : i == ns + 5 ? SEL_UNIFORM : SEL_PRODUCT;
            oi.fluor_keep = 1;
            oi.seed = 63 + (int)i;
        }
        if (!test_render_tiles(t, &s, &oi, K, 1, &other)) { scene_free(&s); return; }
        snprintf(what, sizeof what, "%s vs uniform", i < ns ? sel_name(strat[i]) : i == ns ? "BSDF only"
                 : i == ns + 1 ? "product, li ~ A x power" : i == ns + 2 ? "uniform, li ~ A x power"
                 : i == ns + 3 ? "product, li uniform" : i == ns + 4 ? "spectral-tree, lanes kept"
                 : i == ns + 5 ? "uniform, lanes kept" : "product, lanes kept");
        if (getenv("FLUOR_VERBOSE"))
            printf("%s: %g +- %g (uniform %g +- %g)\n", what, other.mean[0][2], other.se[0][2],
                   ref.mean[0][2], ref.se[0][2]);
        if (!test_tiles_agree(t, &ref, &other, 1e-4, what)) { scene_free(&s); return; }
    }
    scene_free(&s);
}

/* After a fluorescent shift with the lanes kept (--fluor-lanes keep) every alive
   wavelength is an absorbed one; the thesis' spectral strategies (spd, product,
   spectral-spatial) must then weigh the emitters by the alive wavelengths' bins
   (LightCtx.shifted), not fall back to the spatial table, which is built from
   visible light and gives a UV lamp next to nothing.
   (1) Unit: four UV wavelengths alive after a shift: P(UV LED) > 0.99 for each of
       the three, the same whichever lane is the hero (C4), select agrees with pmf
       (C1); the same context without `shifted` takes the spatial table, where the
       UV LED's share is small (the failure the flag removes).
   (2) Render: a card that only re-radiates (rho = 0, maxdepth 1: only the
       vertex after a shift can light it), lit by a small UV LED beside a large
       bright white LED, with the lanes kept: each strategy renders exactly the
       image it renders with --all-wavelengths, seed for seed (the same choices
       after a shift).  With the spatial table instead NEE picks the white LED,
       which cannot excite the card, and the image differs (its standard error
       is about 6x larger). */
static void test_fluor_shift_selects_spectrally(T *t)
{
    static const SelStrategy strat[] = { SEL_SPD, SEL_PRODUCT, SEL_SPECTRAL_SPATIAL };
    Scene s;
    RenderOptions o;
    static Tiles a, b;
    size_t i;
    int j, k;
    if (!test_load_scene(t, &s, UV_AND_LED_SPHERES)) return;
    for (i = 0; i < sizeof strat / sizeof strat[0]; i++) {
        SelOptions so;
        LightSampler *ls;
        LightCtx c;
        Error e;
        float P, p0, prot;
        int fb;
        memset(&so, 0, sizeof so);
        so.strategy = strat[i];
        so.grid_res = 4;
        ls = light_sampler_build(&s, &so, &e);
        CHECK(t, ls != NULL, "build: %s", e.msg);
        if (!ls) break;
        memset(&c, 0, sizeof c);
        c.p = v3(0, 0.5f, 0);
        c.voxel = light_voxel(ls, c.p);
        c.alive = 15u;
        c.shifted = 1;
        for (j = 0; j < HERO_N; j++) { c.lambda[j] = 352.0f + 7.0f * j; c.beta[j] = 1.0f; }
        p0 = light_select_pmf(ls, &c, 0);
        CHECK(t, light_select(ls, &c, 0.5f, &P, &fb) == 0 && P == p0 && p0 > 0.99f && !fb,
              "%s after a shift: UV LED P = %g (pmf %g), fell back %d", sel_name(strat[i]),
              (double)P, (double)p0, fb);
        for (k = 1; k < HERO_N; k++) {               /* another lane as the hero (C4) */
            float tmp = c.lambda[0];
            c.lambda[0] = c.lambda[k];
            c.lambda[k] = tmp;
            prot = light_select_pmf(ls, &c, 0);
            CHECK(t, fabsf(prot - p0) <= 1e-6f * p0, "%s: hero %d gives P = %.9g, hero 0 %.9g",
                  sel_name(strat[i]), k, (double)prot, (double)p0);
            c.lambda[k] = c.lambda[0];
            c.lambda[0] = tmp;
        }
        c.shifted = 0;
        CHECK(t, light_select_pmf(ls, &c, 0) < 0.5f,
              "%s without the shift flag: the spatial table should give the UV LED little, "
              "not %g", sel_name(strat[i]), (double)light_select_pmf(ls, &c, 0));
        light_sampler_free(ls);
    }
    scene_free(&s);

    if (!load_uv_card(t, &s, "1", "0.15", "5")) return;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    o.threads = 1;
    o.fluor_keep = 1;
    o.fluor_li = FLUOR_LI_A;
    for (i = 0; i < sizeof strat / sizeof strat[0]; i++) {
        o.sel.strategy = strat[i];
        o.sel.all_wavelengths = 0;
        if (!test_render_tiles(t, &s, &o, 4, 2, &a)) break;
        o.sel.all_wavelengths = 1;
        if (!test_render_tiles(t, &s, &o, 4, 2, &b)) break;
        for (k = 0; k < 4; k++)
            CHECK(t, a.mean[k][2] == b.mean[k][2] && a.mean[k][2] > 0.0,
                  "%s, lanes kept, tile %d: %.9g, with --all-wavelengths %.9g (after a shift "
                  "both sum the spectral table over the alive bins: the same choices)",
                  sel_name(strat[i]), k, a.mean[k][2], b.mean[k][2]);
    }
    scene_free(&s);
}

/* The spectral light tree's UV bins (lighttree.c): each node stores its power
   per 5 nm bin from 300 nm, so after a fluorescent shift to lambda_i < 400 nm
   `spectral-tree` picks the UV lamp; select and pmf agree bit for bit and in
   frequency (chi^2) at UV wavelengths; `tree` keeps the power of the sampled range
   alone, so a UV LED (no power in 400-700 nm) gets nothing from it.  Both film
   ranges: 400-700 nm (20 UV bins) and --wide 360-830 nm (12). */
static void test_fluor_tree_uv_bins(T *t)
{
    Scene s;
    Rng r;
    int wide, k;
    if (!test_load_scene(t, &s, UV_CAMERA
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-UVLED365\" \"float scale\" 0.2\n"
            "Translate -1 0 0\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\"\n"
            "Translate 1 0 0\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-BLB\" \"float scale\" 0.05\n"
            "Translate 0 1.5 0\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" [ 300 1 330 1 331 0 830 0 ]\n"
            "Translate 0 -1.5 0\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n")) return;
    rng_seed(&r, 23, 0);
    for (wide = 0; wide < 2; wide++) {
        SelOptions so;
        LightSampler *spec, *tree;
        LightCtx c;
        Error e;
        int j;
        memset(&so, 0, sizeof so);
        so.strategy = SEL_SPECTRAL_TREE;
        if (wide) { so.lo_nm = 360.0f; so.hi_nm = 830.0f; }
        spec = light_sampler_build(&s, &so, &e);
        so.strategy = SEL_TREE;
        tree = light_sampler_build(&s, &so, &e);
        CHECK(t, spec && tree, "build: %s", e.msg);
        memset(&c, 0, sizeof c);
        c.p = v3(0, 0, 0);
        c.voxel = -1;
        c.alive = 1u;
        c.hero_only = 1;
        for (j = 0; j < HERO_N; j++) { c.lambda[j] = 550.0f; c.beta[j] = 1.0f; }
        c.lambda[0] = 366.0f;      /* the UV LED's band: it, and the BLB tube */
        {
            float pu = light_select_pmf(spec, &c, light_piece_of(spec, 0, -1));
            float pl = light_select_pmf(spec, &c, light_piece_of(spec, 1, -1));
            float pb = light_select_pmf(spec, &c, light_piece_of(spec, 2, -1));
            CHECK(t, pu > 100.0f * pl && pu + pb > 0.999f,
                  "wide %d: spectral tree at 366 nm: UV LED %g, BLB %g, LED1 %g", wide,
                  (double)pu, (double)pb, (double)pl);
        }
        c.lambda[0] = 315.0f;      /* only the 300-330 nm lamp emits here */
        CHECK(t, light_select_pmf(spec, &c, light_piece_of(spec, 3, -1)) > 0.99f,
              "wide %d: at 315 nm the 300-330 nm lamp has P = %g", wide,
              (double)light_select_pmf(spec, &c, light_piece_of(spec, 3, -1)));
        c.lambda[0] = 550.0f;
        CHECK(t, light_select_pmf(spec, &c, light_piece_of(spec, 1, -1)) > 0.9f, "at 550 nm LED1");
        /* tree: the power of the sampled range, where the 300-330 nm lamp has none
           (nor has the UV LED when the range starts at 400 nm) */
        CHECK(t, light_select_pmf(tree, &c, light_piece_of(tree, 3, -1)) == 0.0f &&
              (wide || light_select_pmf(tree, &c, light_piece_of(tree, 0, -1)) == 0.0f) &&
              light_select_pmf(tree, &c, light_piece_of(tree, 1, -1)) > 0.0f,
              "wide %d: tree: 300-330 nm lamp %g, UV LED %g, LED1 %g", wide,
              (double)light_select_pmf(tree, &c, light_piece_of(tree, 3, -1)),
              (double)light_select_pmf(tree, &c, light_piece_of(tree, 0, -1)),
              (double)light_select_pmf(tree, &c, light_piece_of(tree, 1, -1)));
        /* select == pmf bit for bit, and in frequency, at random UV wavelengths and
           points (the hero alone, as after a shift) */
        for (k = 0; k < 30; k++) {
            enum { NP = 4, DRAWS = 4000 };
            double cnt[NP + 1], ex[NP + 1], sum = 0.0;
            float pm[NP];
            int i;
            c.p = v3_sub(v3_mul(rng_vec3(&r), 4.0f), v3(2.0f, 2.0f, 2.0f));
            c.n = v3_norm(v3_sub(v3_mul(rng_vec3(&r), 2.0f), v3(1.0f, 1.0f, 1.0f)));
            c.lambda[0] = 300.0f + 100.0f * rng_float(&r);
            for (i = 0; i < NP; i++) { pm[i] = light_select_pmf(spec, &c, i); sum += pm[i]; cnt[i] = 0.0; }
            cnt[NP] = 0.0;
            CHECK(t, sum < 1.0 + 1e-4, "pmfs sum to %g", sum);
            for (i = 0; i < DRAWS; i++) {
                float p;
                int fb, got = light_select(spec, &c, rng_float(&r), &p, &fb);
                if (got < 0) { cnt[NP] += 1.0; continue; }
                CHECK(t, got < NP && p == pm[got] && p > 0.0f, "%.1f nm: chose %d with %g, pmf %g",
                      (double)c.lambda[0], got, (double)p, got < NP ? (double)pm[got] : -1.0);
                cnt[got] += 1.0;
            }
            for (i = 0; i <= NP; i++) {
                ex[i] = (i < NP ? pm[i] : 1.0 - sum) * DRAWS;
                CHECK(t, ex[i] > 0.0 || cnt[i] == 0.0, "chosen with pmf 0");
            }
            CHECK_CHI2(t, cnt, ex, NP + 1, 2 * 30, NULL, "%.1f nm", (double)c.lambda[0]);
        }
        light_sampler_free(spec);
        light_sampler_free(tree);
    }
    scene_free(&s);
}

/* --fluor-li power (docs/FLUORESCENCE.md §3): the mixture a p_A + (1 - a) p_AE.  The sampler
   returns the density fluor_pdf_li_mix gives, its samples follow that density
   (chi^2 against expected counts from the pdf integrated on a fine grid), the
   density integrates to 1 over [300, lo], vanishes above lo, and is p_A alone
   where the emitters have no power below lo. */
static void test_fluor_li_mix_sampler(T *t)
{
    Scene s;
    const Material *m;
    Spectrum E;
    static double pcdf[FL_N];
    enum { NB = 34 };
    const float lo = 470.0f;
    double cnt[NB], ex[NB], pint = 0.0, x;
    int n = test_scaled(40000, 4000), i, b, k;
    Rng rng;
    Chi2 c;
    if (!load_fluor(t, &s, FL_MAT("[300 1 830 1]", "\"fluor-pyranine-ex\"", "\"fluor-pyranine-em\"", "0.9"))) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, spec_named(&E, "lamp-UVLED365"), "lamp-UVLED365");
    for (k = 0; k < SPEC_N; k++) E.v[k] = 5.0f * E.v[k] + 0.1f;
    for (k = 0; k < SPEC_UV_N; k++) E.uv[k] = 5.0f * E.uv[k] + 0.1f;
    fluor_power_cdf(m, &E, pcdf);
    memset(cnt, 0, sizeof cnt);
    memset(ex, 0, sizeof ex);
    rng_seed(&rng, 29, 0);
    for (i = 0; i < n; i++) {
        float pdf, li = fluor_sample_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, rng_float(&rng), &pdf);
        CHECK(t, li >= 300.0f && li <= lo && pdf > 0.0f, "sample %g nm pdf %g", (double)li, (double)pdf);
        CHECK(t, fabsf(pdf - fluor_pdf_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, li)) <= 1e-6f * pdf,
              "sampler %g and pdf %g disagree at %g nm", (double)pdf,
              (double)fluor_pdf_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, li), (double)li);
        b = (int)((li - 300.0f) / 5.0f);
        if (b >= NB) b = NB - 1;
        cnt[b] += 1.0;
    }
    for (x = 300.0005; x < lo; x += 0.001) {     /* expected counts: the pdf on a fine grid */
        double p = fluor_pdf_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, (float)x) * 0.001;
        b = (int)((x - 300.0) / 5.0);
        if (b >= NB) b = NB - 1;
        ex[b] += n * p;
        pint += p;
    }
    CHECK(t, fabs(pint - 1.0) < 2e-3, "the mixture density integrates to %g", pint);
    CHECK_CHI2(t, cnt, ex, NB, 1, &c, "the mixture (li | 470 nm)");
    CHECK(t, c.dof >= 19, "only %d degrees of freedom", c.dof);
    CHECK(t, fluor_pdf_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, lo + 1.0f) == 0.0f, "no density above lo");
    /* the UV band carries (1 - a) of the mass and more: 360-370 nm holds far more
       than under p_A alone */
    {
        double pa = 0.0, pm = 0.0;
        for (x = 360.0005; x < 370.0; x += 0.001) {
            pa += fluor_pdf_li(m, lo, (float)x) * 0.001;
            pm += fluor_pdf_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, (float)x) * 0.001;
        }
        CHECK(t, pm > 3.0 * pa, "360-370 nm: mixture %g, A alone %g", pm, pa);
    }
    /* no emitter power: the mixture is p_A */
    spec_const(&E, 0.0f);
    fluor_power_cdf(m, &E, pcdf);
    CHECK(t, fluor_pdf_li_mix(m, pcdf, FLUOR_LI_DEFENSIVE, lo, 400.0f) == fluor_pdf_li(m, lo, 400.0f),
          "without power the mixture is A alone");
    scene_free(&s);
}

/* --fluor-li uniform (docs/FLUORESCENCE.md §3): samples uniform on [300, lo] by chi^2 over 5 nm
   bins, the density 1 / (lo - 300) where it claims, nothing above lo. */
static void test_fluor_li_uniform_sampler(T *t)
{
    enum { NB = 34 };
    const float lo = 470.0f;
    double cnt[NB], ex[NB];
    int n = test_scaled(40000, 4000), i, b;
    Rng rng;
    memset(cnt, 0, sizeof cnt);
    rng_seed(&rng, 31, 0);
    for (i = 0; i < n; i++) {
        float pdf, li = fluor_sample_li_uniform(lo, rng_float(&rng), &pdf);
        CHECK(t, li >= 300.0f && li <= lo && pdf == fluor_pdf_li_uniform(lo, li) &&
              fabsf(pdf - 1.0f / 170.0f) < 1e-9f, "sample %g nm pdf %g", (double)li, (double)pdf);
        b = (int)((li - 300.0f) / 5.0f);
        if (b >= NB) b = NB - 1;
        cnt[b] += 1.0;
    }
    for (b = 0; b < NB; b++) ex[b] = n / (double)NB;
    CHECK_CHI2(t, cnt, ex, NB, 1, NULL, "uniform li");
    CHECK(t, fluor_pdf_li_uniform(lo, lo + 0.5f) == 0.0f && fluor_pdf_li_uniform(lo, 299.0f) == 0.0f,
          "no density outside [300, lo]");
    {
        float pdf;
        fluor_sample_li_uniform(300.0f, 0.5f, &pdf);
        CHECK(t, pdf == 0.0f, "nothing below 300 nm to absorb: pdf %g", (double)pdf);
    }
}

/* The fluorescence tables (12.7 KB) live in their own record, held only by
   fluorescent materials: a scene of many plain materials does not carry them
   (docs/loading.md, memory per emitter). */
static void test_fluor_record_owned(T *t)
{
    Scene s;
    memset(&s, 0, sizeof s);
    /* six spectra (reflectance, eta, k, transmittance, albedo, cond_eta) and scalars;
       with A, e and the two tables inside it would be 25 KB */
    CHECK(t, sizeof(Material) < 7 * sizeof(Spectrum), "Material %d B holds more than its spectra",
          (int)sizeof(Material));
    if (!load_fluor(t, &s, "Material \"diffuse\"\n" FL_MAT("[300 1 830 1]", "\"fluor-brightener-ex\"",
                                                     "\"fluor-brightener-em\"", "0.9"))) return;
    CHECK(t, s.n_materials == 2 && s.materials[0].type == MAT_DIFFUSE && !s.materials[0].fl &&
          s.materials[1].fl && s.materials[1].fl->qyield == 0.9f,
          "diffuse owns no tables, fluorescent owns its own (n %d)", s.n_materials);
    scene_free(&s);
}

const TestCase tests_fluor[] = {
    { "fluor_uv_lamp_absolute", test_uv_lamp_absolute },
    { "fluor_uv_lamp_rules", test_uv_lamp_rules },
    { "fluor_uv_bins_select", test_uv_bins_select },
    { "fluor_named_spectra", test_named_fluor_spectra },
    { "fluor_parse_errors", test_fluor_parse_errors },
    { "fluor_record_owned", test_fluor_record_owned },
    { "fluor_li_sampler_chi2", test_fluor_li_sampler },
    { "fluor_li_mix_sampler_chi2", test_fluor_li_mix_sampler },
    { "fluor_li_uniform_sampler_chi2", test_fluor_li_uniform_sampler },
    { "fluor_line", test_fluor_line },
    { "fluor_photon_furnace", test_fluor_photon_furnace },
    { "fluor_in_medium", test_fluor_in_medium },
    { "fluor_line_bins", test_fluor_line_bins },
    { "fluor_closed_sphere", test_fluor_closed_sphere },
    { "fluor_estimators_agree", test_fluor_estimators_agree },
    { "fluor_mis_pmf_at_li", test_fluor_mis_pmf_at_li },
    { "fluor_tree_uv_bins", test_fluor_tree_uv_bins },
    { "fluor_shift_selects_spectrally", test_fluor_shift_selects_spectrally },
    { NULL, NULL }
};
