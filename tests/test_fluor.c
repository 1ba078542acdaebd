/* tests/test_fluor.c - fluorescence (issue #17, docs/FLUORESCENCE.md): the UV
   extension of the spectra (300-359 nm), UV lamps read as absolute radiance, the
   20 UV bins of emitter selection, and the named UV lamps and fluorophores. */
#include "test.h"
#include <string.h>
#include <stdlib.h>

#define UV_CAMERA "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n" \
    "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"string filename\" \"t.pfm\"\n" \
    "WorldBegin\n"

/* The inline UV spectrum loads, means absolute radiance x scale, is finite,
   reaches into the UV extension and is zero where L is zero. */
static void test_uv_lamp_absolute(T *t)
{
    Scene s;
    const Emitter *em;
    int nm, b;
    if (!test_load_scene(t, &s, UV_CAMERA
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" [ 300 0 355 0 360 1 370 1 375 0 830 0 ] \"float scale\" 3\n"
            "Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n")) return;
    CHECK(t, s.n_emitters == 1, "one emitter");
    em = &s.emitters[0];
    CHECK(t, em->absolute == 1, "a lamp with no luminance in 400-700 nm is absolute");
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
        CHECK(t, isfinite(spec_get(&em->Le, nm)), "Le finite at %d nm", nm);
    CHECK(t, spec_eval(&em->Le, 365.0f) == 3.0f, "Le = scale * L at 365 nm: %g", (double)spec_eval(&em->Le, 365.0f));
    CHECK(t, fabsf(spec_eval(&em->Le, 357.5f) - 1.5f) < 1e-6f, "UV extension interpolates: %g",
          (double)spec_eval(&em->Le, 357.5f));
    CHECK(t, spec_eval(&em->Le, 340.0f) == 0.0f && spec_eval(&em->Le, 500.0f) == 0.0f, "zero outside");
    /* UV bins: 355-360 holds the ramp 0 -> 3 (mean 1.5), 360-365 and 365-370 are 3 */
    CHECK(t, fabsf(em->bin_uv[11] - 1.5f) < 1e-6f && em->bin_uv[12] == 3.0f && em->bin_uv[13] == 3.0f,
          "UV bins: %g %g %g", (double)em->bin_uv[11], (double)em->bin_uv[12], (double)em->bin_uv[13]);
    for (b = 0; b < SPD_BINS; b++) CHECK(t, em->bin[b] == 0.0f, "no visible bins");
    /* the same meaning when the film samples 360-830 nm */
    {
        Error e;
        CHECK(t, emitters_prepare(&s, 360.0f, 830.0f, &e), "prepare wide: %s", e.msg);
        CHECK(t, spec_eval(&s.emitters[0].Le, 365.0f) == 3.0f, "absolute in wide mode too");
    }
    scene_free(&s);
}

/* A visible lamp keeps pbrt-v4's normalisation (absolute = 0), and an all-zero L
   is an error naming its line. */
static void test_uv_lamp_rules(T *t)
{
    Scene s;
    Error e;
    if (!test_load_scene(t, &s, UV_CAMERA
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-BLB\"\n"
            "Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n")) return;
    CHECK(t, s.emitters[0].absolute == 0, "BLB has luminance (its Hg lines): pbrt-v4's rule");
    CHECK(t, spec_eval(&s.emitters[0].Le, 365.0f) > 10.0f * spec_eval(&s.emitters[0].Le, 404.66f),
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
    if (!test_load_scene(t, &s, UV_CAMERA
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-UVLED365\"\n"
            "Translate -2 0 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\"\n"
            "Translate 2 0 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n")) return;
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

const TestCase tests_fluor[] = {
    { "fluor_uv_lamp_absolute", test_uv_lamp_absolute },
    { "fluor_uv_lamp_rules", test_uv_lamp_rules },
    { "fluor_uv_bins_select", test_uv_bins_select },
    { "fluor_named_spectra", test_named_fluor_spectra },
    { NULL, NULL }
};
