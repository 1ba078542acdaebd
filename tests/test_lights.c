/* tests/test_lights.c - emitter selection: the consistency contract, positivity,
   lazy = eager tables, and unbiasedness of every strategy where it is weak.

   The image tests compare each strategy against `uniform` (the trivially correct
   choice) per tile, with fixtures.c's statistics: K seeds, tile means,
   |a - b| < 5 standard errors. */
#include "test.h"
#include <stdlib.h>
#include <string.h>


/* ---------------------------------------------------------------- scenes */

/* The open box of fixtures.c seen by a 16x16 camera; emitters are appended. */
static const char *box_camera =
    "LookAt 0 0 -3.2  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
    "Integrator \"path\" \"integer maxdepth\" [ 5 ]\n"
    "WorldBegin\n";

static const char *glass_sphere =
    "AttributeBegin\n Translate 0 -0.6 0\n"
    " Material \"dielectric\" \"float cauchyA\" [ 1.5 ] \"float cauchyB\" [ 0.03 ] \"float roughness\" [ 0.04 ]\n"
    " Shape \"sphere\" \"float radius\" [ 0.38 ]\nAttributeEnd\n";

/* A downward-facing square light of half-size h at (x, 0.99, z). */
static void add_light(char *buf, size_t cap, const char *spectrum, float scale, float x, float z, float h)
{
    size_t n = strlen(buf);
    snprintf(buf + n, cap - n,
             "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" %s \"float scale\" [ %g ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ %g 0.99 %g  %g 0.99 %g  %g 0.99 %g  %g 0.99 %g ]\nAttributeEnd\n",
             spectrum, scale, x - h, z - h, x + h, z - h, x + h, z + h, x - h, z + h);
}

/* A compact fluorescent-like spiky emitter and a blue-heavy LED-like one, as
   inline spectra so the tests do not depend on the lamp models. */
#define SPIKY "[ 400 0 430 0 435 3 440 0 540 0 545 4 550 0 605 0 611 3 617 0 700 0 ]"
#define BLUEISH "[ 400 0.1 450 1.0 480 0.3 560 0.6 700 0.2 ]"
#define LOW_HALF "[ 400 1 550 1 551 0 700 0 ]"
#define HIGH_HALF "[ 400 0 549 0 550 1 700 1 ]"

enum { SC_DISPERSIVE, SC_FACING_AWAY, SC_HALVES, SC_ONE, SC_IDENTICAL, SC_MANY, SC_THROUGH_GLASS,
       SC_LARGE_HALVES, SC_ENV, SC_DELTA, SC_N };
static const char *const scene_names[SC_N] = {
    "two lamps + dispersive glass", "bright emitter facing away", "complementary half spectra",
    "one emitter", "two identical emitters", "64 small emitters", "emitter seen only through glass",
    "large complementary emitters, one wavelength per path",
    "two lamps, glass and a constant environment through the open front",
    "a lamp, glass, a point, a spot and a distant light through the open front"
};

static void build_scene(int which, char *buf, size_t cap)
{
    int i;
    snprintf(buf, cap, "%s%s", box_camera, test_box_walls);
    switch (which) {
    case SC_DISPERSIVE:
        add_light(buf, cap, SPIKY, 4, -0.5f, 0.0f, 0.2f);
        add_light(buf, cap, BLUEISH, 4, 0.5f, 0.0f, 0.25f);
        strcat(buf, glass_sphere);
        break;
    case SC_FACING_AWAY: {
        size_t n;
        add_light(buf, cap, SPIKY, 3, 0.0f, 0.0f, 0.2f);
        strcat(buf, glass_sphere);
        /* a very bright one-sided emitter near the back wall that faces the wall */
        n = strlen(buf);
        snprintf(buf + n, cap - n,
                 "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" " BLUEISH " \"float scale\" [ 60 ]\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "  \"point3 P\" [ -0.3 0.2 0.9  0.3 0.2 0.9  0.3 0.6 0.9  -0.3 0.6 0.9 ]\nAttributeEnd\n");
        break;
    }
    case SC_HALVES:
        add_light(buf, cap, LOW_HALF, 4, -0.5f, 0.0f, 0.2f);
        add_light(buf, cap, HIGH_HALF, 4, 0.5f, 0.0f, 0.2f);
        strcat(buf, glass_sphere);
        break;
    case SC_ONE:
        add_light(buf, cap, SPIKY, 5, 0.0f, 0.0f, 0.25f);
        strcat(buf, glass_sphere);
        break;
    case SC_IDENTICAL:
        add_light(buf, cap, BLUEISH, 4, -0.5f, 0.0f, 0.2f);
        add_light(buf, cap, BLUEISH, 4, 0.5f, 0.0f, 0.2f);
        strcat(buf, glass_sphere);
        break;
    case SC_MANY: {
        const char *spectra[4] = { SPIKY, BLUEISH, LOW_HALF, HIGH_HALF };
        for (i = 0; i < 64; i++)
            add_light(buf, cap, spectra[i % 4], 0.5f + (float)(i % 3), -0.84f + 0.24f * (i % 8),
                      -0.84f + 0.24f * (i / 8), 0.05f);
        strcat(buf, glass_sphere);
        break;
    }
    case SC_LARGE_HALVES:
        /* two large emitters next to the floor and ceiling: BSDF sampling finds them often, so
           the MIS weight of an emitter hit (which needs light_select_pmf) carries
           much of the image; rendered with one wavelength per path, every vertex
           uses the spectral tables */
    {
        size_t n = strlen(buf);
        /* emitters covering the side walls, facing into the box */
        snprintf(buf + n, cap - n,
                 "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" " LOW_HALF " \"float scale\" [ 1 ]\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ]\n"
                 "  \"point3 P\" [ -0.98 -1 -1  -0.98 -1 1  -0.98 1 1  -0.98 1 -1 ]\nAttributeEnd\n"
                 "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" " HIGH_HALF " \"float scale\" [ 1 ]\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "  \"point3 P\" [ 0.98 -1 -1  0.98 -1 1  0.98 1 1  0.98 1 -1 ]\nAttributeEnd\n");
        break;
    }
    case SC_ENV:
        add_light(buf, cap, SPIKY, 4, -0.5f, 0.0f, 0.2f);
        add_light(buf, cap, LOW_HALF, 3, 0.5f, 0.0f, 0.25f);
        strcat(buf, glass_sphere);
        strcat(buf, "LightSource \"infinite\" \"spectrum L\" " BLUEISH " \"float scale\" [ 0.7 ]\n");
        break;
    case SC_DELTA:
        /* delta lights (delta.c) beside an area lamp: a point light of given
           power, a narrow spot with a falloff band aimed at the glass, and a
           distant light through the open front (beside the light trees, as an
           infinite light) */
        add_light(buf, cap, SPIKY, 3, -0.5f, 0.0f, 0.2f);
        strcat(buf, glass_sphere);
        strcat(buf, "LightSource \"point\" \"spectrum I\" " BLUEISH " \"float power\" [ 6 ] "
                    "\"point3 from\" [ 0.5 0.7 0.3 ]\n"
                    "AttributeBegin\n Translate 0 0.8 0\n"
                    " LightSource \"spot\" \"spectrum I\" " HIGH_HALF " \"float scale\" [ 2 ] "
                    "\"point3 from\" [ 0 0 0 ] \"point3 to\" [ 0.1 -1 0 ] \"float coneangle\" [ 25 ] "
                    "\"float conedeltaangle\" [ 10 ]\nAttributeEnd\n"
                    "LightSource \"distant\" \"spectrum L\" " LOW_HALF " \"float scale\" [ 0.6 ] "
                    "\"point3 from\" [ 0.3 0.4 -1 ] \"point3 to\" [ 0 0 0 ]\n");
        break;
    case SC_THROUGH_GLASS: {
        size_t n = strlen(buf);
        /* a small light sphere inside a closed, smooth glass shell: shadow rays from
           outside always hit the glass, so only BSDF-sampled paths bring its light */
        snprintf(buf + n, cap - n,
                 "AttributeBegin\n Translate 0 -0.5 0\n"
                 " AttributeBegin\n  AreaLightSource \"diffuse\" \"spectrum L\" " SPIKY " \"float scale\" [ 3 ]\n"
                 "  Shape \"sphere\" \"float radius\" [ 0.2 ]\n AttributeEnd\n"
                 " Material \"dielectric\" \"float cauchyA\" [ 1.5 ] \"float cauchyB\" [ 0.02 ]\n"
                 " Shape \"sphere\" \"float radius\" [ 0.45 ]\nAttributeEnd\n");
        add_light(buf, cap, BLUEISH, 2, 0.0f, 0.0f, 0.2f);
        break;
    }
    }
}

/* ---------------------------------------------------------------- unit tests */

typedef struct { SelStrategy st; int power_metric, all_wl, tput; const char *name; } Variant;
static const Variant variants[] = {
    { SEL_UNIFORM, 0, 0, 0, "uniform" },
    { SEL_POWER, 0, 0, 0, "power" },
    { SEL_SPATIAL, 0, 0, 0, "spatial" },
    { SEL_SPD, 0, 0, 0, "spd" },
    { SEL_SPD, 1, 0, 0, "spd power-metric" },
    { SEL_PRODUCT, 0, 0, 0, "product" },
    { SEL_PRODUCT, 1, 0, 0, "product power-metric" },
    { SEL_SPECTRAL_SPATIAL, 0, 0, 0, "spectral-spatial" },
    { SEL_SPD, 0, 1, 0, "spd all-wavelengths" },
    { SEL_PRODUCT, 0, 1, 1, "product throughput-weighted" },
    { SEL_SPECTRAL_SPATIAL, 0, 1, 0, "spectral-spatial all-wavelengths" },
    { SEL_TREE, 0, 0, 0, "tree" },
    { SEL_SPECTRAL_TREE, 0, 0, 0, "spectral-tree" },
};
#define N_VARIANTS ((int)(sizeof variants / sizeof variants[0]))

/* The light sampler of variants[v] on s (8^3 voxels), or NULL after a failed check. */
static LightSampler *variant_sampler(T *t, const Scene *s, int v)
{
    SelOptions o;
    LightSampler *ls;
    Error err;
    memset(&o, 0, sizeof o);
    o.grid_res = 8;
    o.strategy = variants[v].st;
    o.power_metric = variants[v].power_metric;
    o.all_wavelengths = variants[v].all_wl;
    o.throughput_weighted = variants[v].tput;
    ls = light_sampler_build(s, &o, &err);
    if (!ls) test_failf(t, __FILE__, __LINE__, "%s: %s", variants[v].name, err.msg);
    return ls;
}

static LightCtx random_ctx(const Scene *s, const LightSampler *ls, Rng *r)
{
    LightCtx c;
    int j;
    Vec3 ext = v3_sub(s->bmax, s->bmin);
    memset(&c, 0, sizeof c);
    {
        const Vec3 u = rng_vec3(r);
        c.p = v3_add(s->bmin, v3(ext.x * u.x, ext.y * u.y, ext.z * u.z));
    }
    c.voxel = light_voxel(ls, c.p);
    /* half the contexts carry the hero alone (after a wavelength-dependent event) */
    c.alive = rng_float(r) < 0.5f ? 1u : (1u | ((rng_u32(r) & 7u) << 1));
    c.hero_only = c.alive == 1u;
    /* a receiver normal for the light trees (zero: none) */
    if (rng_float(r) < 0.75f)
        c.n = v3_norm(v3_sub(v3_mul(rng_vec3(r), 2.0f), v3(1.0f, 1.0f, 1.0f)));
    for (j = 0; j < HERO_N; j++) {
        c.lambda[j] = 400.0f + 300.0f * rng_float(r);
        c.beta[j] = (c.alive & (1u << j)) ? 0.1f + rng_float(r) : 0.0f;
    }
    return c;
}

/* Both pmfs against what the sampler does (neither against the other: both go
   through context_weights, so comparing them could not fail): the frequencies
   match light_select_pmf (chi-square, CHECK_CHI2) and the pmf that
   light_select reports (binomial bound per emitter); the pmfs sum to 1; uniform
   selection has the closed form 1/n. */
static void select_matches_pmf_on(T *t, int sc)
{
    char buf[65536];
    Scene s;
    int v, trial;
    build_scene(sc, buf, sizeof buf);
    if (!test_load_scene(t, &s, buf)) return;
    for (v = 0; v < N_VARIANTS; v++) {
        LightSampler *ls = variant_sampler(t, &s, v);
        Rng r;
        if (!ls) continue;
        rng_seed(&r, 77, (uint64_t)v);
        for (trial = 0; trial < 6; trial++) {
            LightCtx c = random_ctx(&s, ls, &r);
            static double count[64], pmf[64], rep[64], ex[64];
            double sum = 0;
            int i, n = 20000;
            for (i = 0; i < s.n_emitters; i++) {
                count[i] = 0; rep[i] = -1; pmf[i] = light_select_pmf(ls, &c, i); sum += pmf[i];
                if (variants[v].st == SEL_UNIFORM)          /* closed form */
                    CHECK(t, fabs(pmf[i] - 1.0 / s.n_emitters) < 1e-6, "uniform: pmf %g, not 1/%d", pmf[i], s.n_emitters);
            }
            if (sum == 0.0) {
                /* allowed only where no emitter can light p (the reach mask of
                   lights.c section 4: p above the ceiling lamps); then none is chosen */
                float p;
                for (i = 0; i < s.n_emitters; i++)
                    CHECK(t, !emitter_can_reach(&s, i, c.p), "%s: pmfs sum to 0 but emitter %d reaches p",
                          variants[v].name, i);
                CHECK(t, light_select(ls, &c, 0.5f, &p, NULL) < 0, "%s: chose an emitter with pmf 0",
                      variants[v].name);
                continue;
            }
            CHECK(t, fabs(sum - 1.0) < 1e-4, "%s: pmfs sum to %g", variants[v].name, sum);
            for (i = 0; i < n; i++) {
                float p;
                int e = light_select(ls, &c, rng_float(&r), &p, NULL);
                CHECK(t, e >= 0 && e < s.n_emitters, "%s: no emitter chosen", variants[v].name);
                /* in one context an emitter's reported pmf is one number */
                CHECK(t, rep[e] < 0 || rep[e] == p, "%s: emitter %d reported %g and %g", variants[v].name, e, rep[e], p);
                rep[e] = p;
                count[e] += 1;
            }
            /* light_select_pmf (used for the MIS weight of hits) against the frequencies */
            for (i = 0; i < s.n_emitters; i++) ex[i] = pmf[i] * n;
            CHECK_CHI2(t, count, ex, s.n_emitters, 3 * N_VARIANTS * 6, NULL, "%s", variants[v].name);
            /* the pmf light_select reports (used by NEE) against the frequencies, on
               its own: each chosen emitter's count within 5 binomial standard
               deviations of n times its reported pmf */
            for (i = 0; i < s.n_emitters; i++) {
                double ex = rep[i] * n;
                if (rep[i] < 0) continue;
                CHECK(t, fabs(count[i] - ex) < 5 * sqrt(ex * (1 - rep[i])) + 2,
                      "%s: emitter %d chosen %g times in %d, but light_select reports pmf %g",
                      variants[v].name, i, count[i], n, rep[i]);
            }
        }
        light_sampler_free(ls);
    }
    scene_free(&s);
}

/* 64 lamps; and two lamps with an infinite light, which the light trees choose
   beside the tree (lighttree.c) */
static void test_select_matches_pmf(T *t)
{
    select_matches_pmf_on(t, SC_MANY);
    select_matches_pmf_on(t, SC_ENV);
    select_matches_pmf_on(t, SC_DELTA);
}

/* Positivity (item C3 of the consistency contract, THEORY §5): an
   emitter that emits at the hero wavelength always has P > 0 in hero-only mode,
   for spectra with a 1 nm line at a bin edge too. */
static void test_positive_where_emitting(T *t)
{
    char buf[65536];
    Scene s;
    int v;
    snprintf(buf, sizeof buf, "%s%s", box_camera, test_box_walls);
    add_light(buf, sizeof buf, "[ 400 0 439 0 440 5 441 0 700 0 ]", 1, -0.5f, 0, 0.2f);  /* line at a bin edge */
    add_light(buf, sizeof buf, "[ 400 0 599.5 0 600 2 600.5 0 700 0 ]", 1, 0.5f, 0, 0.2f);
    add_light(buf, sizeof buf, LOW_HALF, 1, 0.0f, 0.5f, 0.2f);
    if (!test_load_scene(t, &s, buf)) return;
    for (v = 0; v < N_VARIANTS; v++) {
        SelOptions o;
        LightSampler *ls;
        Error err;
        int e, k;
        memset(&o, 0, sizeof o);
        o.grid_res = 8;
        o.strategy = variants[v].st;
        o.power_metric = variants[v].power_metric;
        ls = light_sampler_build(&s, &o, &err);
        CHECK(t, ls != NULL, "%s", err.msg);
        for (k = 0; k <= 600; k++) {
            LightCtx c;
            memset(&c, 0, sizeof c);
            c.p = v3(0.1f, -0.5f, 0.2f);
            c.voxel = light_voxel(ls, c.p);
            c.alive = 1u;
            c.hero_only = 1;
            c.lambda[0] = 400.0f + 0.5f * k;
            c.beta[0] = 1;
            for (e = 0; e < s.n_emitters; e++) {
                Spectrum Le;
                light_spectrum(ls, e, &Le);
                if (spec_eval(&Le, c.lambda[0]) > 0.0f)
                    CHECK(t, light_select_pmf(ls, &c, e) > 0.0f, "%s: emitter %d emits at %.1f nm but P = 0",
                          variants[v].name, e, c.lambda[0]);
            }
        }
        light_sampler_free(ls);
    }
    scene_free(&s);
}

/* Item C4 of the consistency contract (THEORY §6): while several
   wavelengths are alive, P(e | c) must not depend on which of them is the hero,
   because path.c uses one q_nee for every hero m in the MIS denominator.  The
   context is rotated so that each alive wavelength in turn sits in slot 0 (with
   its alive bit, and its throughput divided by an arbitrary common factor, as the
   throughput relative to another hero's pdf would be); every emitter's P must stay
   the same, up to the rounding of a sum taken in another order. */
static void test_pmf_same_for_every_hero(T *t)
{
    char buf[65536];
    Scene s;
    int v, trial;
    build_scene(SC_MANY, buf, sizeof buf);
    if (!test_load_scene(t, &s, buf)) return;
    for (v = 0; v < N_VARIANTS; v++) {
        LightSampler *ls = variant_sampler(t, &s, v);
        Rng r;
        if (!ls) continue;
        rng_seed(&r, 91, (uint64_t)v);
        for (trial = 0; trial < 40; trial++) {
            LightCtx c = random_ctx(&s, ls, &r);
            int h, k, e;
            c.hero_only = 0;
            c.alive = 1u | 2u | ((rng_u32(&r) & 3u) << 2);   /* at least two alive */
            for (k = 0; k < HERO_N; k++) c.beta[k] = (c.alive & (1u << k)) ? 0.1f + rng_float(&r) : 0.0f;
            for (h = 1; h < HERO_N; h++) {
                LightCtx ch = c;
                float scale = 0.3f + rng_float(&r);
                if (!(c.alive & (1u << h))) continue;
                ch.alive = 0u;
                for (k = 0; k < HERO_N; k++) {
                    int from = (h + k) % HERO_N;
                    ch.lambda[k] = c.lambda[from];
                    ch.beta[k] = c.beta[from] / scale;
                    if (c.alive & (1u << from)) ch.alive |= 1u << k;
                }
                for (e = 0; e < s.n_emitters; e++) {
                    float p0 = light_select_pmf(ls, &c, e), ph = light_select_pmf(ls, &ch, e);
                    CHECK(t, fabsf(ph - p0) <= 1e-5f * p0 + 1e-7f,
                          "%s: emitter %d has P = %g with lambda_0 = %.1f nm as the hero but %g with %.1f nm",
                          variants[v].name, e, p0, c.lambda[0], ph, ch.lambda[0]);
                }
            }
        }
        light_sampler_free(ls);
    }
    scene_free(&s);
}

/* Lazy and eager spatial tables are bit-identical. */
static void test_lazy_equals_eager(T *t)
{
    char buf[65536];
    Scene s;
    SelOptions o;
    LightSampler *lazy, *eager;
    Error err;
    Rng r;
    int i, e;
    build_scene(SC_DISPERSIVE, buf, sizeof buf);
    if (!test_load_scene(t, &s, buf)) return;
    memset(&o, 0, sizeof o);
        o.grid_res = 8;
    o.strategy = SEL_SPECTRAL_SPATIAL;
    lazy = light_sampler_build(&s, &o, &err);
    o.eager = 1;
    eager = light_sampler_build(&s, &o, &err);
    CHECK(t, lazy && eager, "%s", err.msg);
    rng_seed(&r, 1, 1);
    for (i = 0; i < 2000; i++) {
        LightCtx c = random_ctx(&s, lazy, &r);
        for (e = 0; e < s.n_emitters; e++)
            CHECK(t, light_select_pmf(lazy, &c, e) == light_select_pmf(eager, &c, e), "lazy != eager");
    }
    light_sampler_free(lazy);
    light_sampler_free(eager);
    scene_free(&s);
}

/* The spatial distribution sees an emitter that faces away as nearly
   impossible (the floor), and a flat scene gets a grid of one cell in depth. */
static void test_spatial_facing_and_flat(T *t)
{
    char buf[65536];
    Scene s;
    SelOptions o;
    LightSampler *ls;
    Error err;
    LightCtx c;
    memset(&o, 0, sizeof o);
        o.grid_res = 8;
    o.strategy = SEL_SPATIAL;
    build_scene(SC_FACING_AWAY, buf, sizeof buf);
    if (!test_load_scene(t, &s, buf)) return;
    ls = light_sampler_build(&s, &o, &err);
    CHECK(t, ls != NULL, "%s", err.msg);
    memset(&c, 0, sizeof c);
    c.p = v3(0.0f, -0.9f, -0.5f);                 /* on the floor, in front of the emitter's back */
    c.voxel = light_voxel(ls, c.p);
    c.alive = 15u;
    CHECK(t, light_select_pmf(ls, &c, 1) == 0.0f,
          "facing-away emitter has P = %g at a point behind it (lights.c section 4: 0)",
          light_select_pmf(ls, &c, 1));
    c.p = v3(0.0f, -0.9f, 0.95f);                 /* in front of it (z > 0.9): the floor keeps P > 0 */
    c.voxel = light_voxel(ls, c.p);
    CHECK(t, light_select_pmf(ls, &c, 1) > 0.0f, "facing-away emitter has P = 0 in front of it");
    light_sampler_free(ls);
    scene_free(&s);
    /* flat: everything in the plane z = 0 */
    if (!test_load_scene(t, &s,
              "LookAt 0 0 -3 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n"
              "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ]\n"
              "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n"
              "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ 2 0 0 3 0 0 2 1 0 ]\n")) return;
    ls = light_sampler_build(&s, &o, &err);
    CHECK(t, ls != NULL, "%s", err.msg);
    c.p = v3(0.5f, 0.5f, 0.1f);                  /* in front of both (in their plane: P = 0) */
    c.voxel = light_voxel(ls, c.p);
    CHECK(t, c.voxel >= 0, "flat scene: no voxel");
    CHECK(t, fabsf(light_select_pmf(ls, &c, 0) + light_select_pmf(ls, &c, 1) - 1.0f) < 1e-5f, "flat scene pmf");
    light_sampler_free(ls);
    scene_free(&s);
}

/* emitter_can_reach: which side a one-sided or two-sided mesh and a sphere light,
   a point on the emitter itself, and a folded quad (two triangles 4.6 mm out of
   plane, the far lamp of the issue-20 scene below). */
static void test_emitter_can_reach(T *t)
{
    Scene s;
    if (!test_load_scene(t, &s,
              "WorldBegin\n"
              "AttributeBegin AreaLightSource \"diffuse\"\n"            /* 0: faces +z */
              " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 0 1 0 0 1 1 0 0 1 0 ]\n"
              "AttributeEnd\n"
              "AttributeBegin AreaLightSource \"diffuse\" \"bool twosided\" true\n"   /* 1 */
              " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 5 1 0 5 1 1 5 0 1 5 ]\n"
              "AttributeEnd\n"
              "AttributeBegin AreaLightSource \"diffuse\" Translate 10 0 0\n"        /* 2: sphere */
              " Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n"
              "AttributeBegin AreaLightSource \"diffuse\" Translate 20 0 0 ReverseOrientation\n"  /* 3 */
              " Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n"
              "AttributeBegin AreaLightSource \"diffuse\"\n"            /* 4: the folded quad */
              " Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [5.7 -13.5 -76.2 "
              "-14.9 -13.8 -75.3 -14.9 13 -66.6 5.8 13.3 -67.5]\nAttributeEnd\n"))
        return;
    CHECK(t, emitter_can_reach(&s, 0, v3(0.5f, 0.5f, 0.3f)), "in front of a one-sided quad: not reached");
    CHECK(t, !emitter_can_reach(&s, 0, v3(0.5f, 0.5f, -0.3f)), "behind a one-sided quad: reached");
    CHECK(t, !emitter_can_reach(&s, 0, v3(0.3f, 0.6f, 0.0f)), "on the quad itself: reached");
    CHECK(t, !emitter_can_reach(&s, 0, v3(7.0f, -3.0f, 0.0f)), "in the quad's plane: reached");
    CHECK(t, emitter_can_reach(&s, 1, v3(0.5f, 0.5f, 4.0f)) && emitter_can_reach(&s, 1, v3(0.5f, 0.5f, 6.0f)),
          "two-sided quad: a side not reached");
    CHECK(t, !emitter_can_reach(&s, 1, v3(0.2f, 0.2f, 5.0f)), "on the two-sided quad: reached");
    CHECK(t, emitter_can_reach(&s, 2, v3(12.0f, 0.0f, 0.0f)), "outside a sphere: not reached");
    CHECK(t, !emitter_can_reach(&s, 2, v3(10.2f, 0.1f, 0.0f)), "inside an outward sphere: reached");
    CHECK(t, !emitter_can_reach(&s, 2, v3(11.0f, 0.0f, 0.0f)), "on an outward sphere: reached");
    CHECK(t, emitter_can_reach(&s, 3, v3(20.2f, 0.1f, 0.0f)) && emitter_can_reach(&s, 3, v3(21.0f, 0.0f, 0.0f)),
          "inside / on a flipped sphere: not reached");
    CHECK(t, !emitter_can_reach(&s, 3, v3(23.0f, 0.0f, 0.0f)), "outside a flipped sphere: reached");
    {   /* the folded quad: points on either triangle, and 1 m behind / in front */
        Vec3 a = v3(5.7f, -13.5f, -76.2f), b = v3(-14.9f, -13.8f, -75.3f), c = v3(-14.9f, 13.0f, -66.6f);
        Vec3 d = v3(5.8f, 13.3f, -67.5f);
        Vec3 on1 = v3_mul(v3_add(v3_add(a, b), c), 1.0f / 3.0f), on2 = v3_mul(v3_add(v3_add(a, c), d), 1.0f / 3.0f);
        Vec3 n = v3_norm(v3_cross(v3_sub(a, c), v3_sub(b, c)));
        CHECK(t, !emitter_can_reach(&s, 4, on1) && !emitter_can_reach(&s, 4, on2), "folded quad lights itself");
        CHECK(t, !emitter_can_reach(&s, 4, v3_sub(on1, n)), "behind the folded quad: reached");
        CHECK(t, emitter_can_reach(&s, 4, v3_add(on1, n)), "in front of the folded quad: not reached");
    }
    scene_free(&s);
}

/* The back of a one-sided lamp, lit by a second lamp.  The voxels cut by the far
   lamp hold receivers in front of it, so a spatial table without the reach mask
   gives it most of the probability also at points on its own back, where it sends
   nothing: banded noise, the mean difference of horizontally neighbouring pixels
   3.5 times uniform's (spatial, spd, product and spectral-spatial alike; 100x140,
   64 spp).
   With the reach mask (lights.c section 4) the spatial strategies choose the near
   lamp there: their noise must not exceed uniform's, which spends half its
   samples on the far lamp (measured 0.42 x uniform).  A test on noise, not on the
   mean; the means are checked by the unbiasedness tests. */
static const char back_of_lamp_scene[] =
    "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 56\n"
    "LookAt 0 5.5 24  0 11 -10  0 1 0\n"
    "Camera \"perspective\" \"float fov\" 47\n"
    "WorldBegin\n"
    "AttributeBegin AreaLightSource \"diffuse\"\n"
    "  Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [5.7 -13.5 -76.2 -14.9 -13.8 -75.3 -14.9 13 -66.6 5.8 13.3 -67.5]\n"
    "AttributeEnd\n"
    "AttributeBegin AreaLightSource \"diffuse\"\n"
    "  Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [9.3 19.2 24.6 -9.1 19.2 25.3 -9.7 32.2 11 8.7 32.2 10.4]\n"
    "AttributeEnd\n";

static double neighbour_noise(const Image *im)
{
    double sum = 0.0;
    int x, y;
    for (y = 0; y < im->h; y++)
        for (x = 0; x + 1 < im->w; x++)
            sum += fabs(im->rgb[3 * (y * im->w + x) + 1] - im->rgb[3 * (y * im->w + x + 1) + 1]);
    return sum / ((double)im->h * (im->w - 1));
}

static void test_back_of_lamp_noise(T *t)
{
    static const SelStrategy st[] = { SEL_SPATIAL, SEL_SPD, SEL_PRODUCT, SEL_SPECTRAL_SPATIAL };
    Scene s;
    RenderOptions o;
    Image im;
    RenderStats rs;
    Error err;
    double ref;
    int i;
    if (!test_load_scene(t, &s, back_of_lamp_scene)) return;
    render_options_default(&o);
    o.spp = test_scaled(16, 8);
    o.seed = 3;
    o.sel.strategy = SEL_UNIFORM;
    CHECK(t, render(&s, &o, &im, &rs, &err), "%s", err.msg);
    ref = neighbour_noise(&im);
    img_free(&im);
    CHECK(t, ref > 0.0, "uniform: a black image");
    for (i = 0; i < 4; i++) {
        double noise;
        o.sel.strategy = st[i];
        CHECK(t, render(&s, &o, &im, &rs, &err), "%s", err.msg);
        noise = neighbour_noise(&im);
        img_free(&im);
        CHECK(t, noise < ref, "%s: neighbour-pixel noise %.3g is %.2f x uniform's (back of a lamp)",
              sel_name(st[i]), noise, noise / ref);
    }
    scene_free(&s);
}

/* ---------------------------------------------------------------- images */

/* Every strategy converges to uniform's image, scene by scene. */
static void strategies_on_scene_opt(T *t, int which, int single);
static void strategies_on_scene(T *t, int which) { strategies_on_scene_opt(t, which, 0); }

static void strategies_on_text(T *t, const char *buf, const char *name, int single);
static void strategies_on_scene_opt(T *t, int which, int single)
{
    static char buf[65536];
    build_scene(which, buf, sizeof buf);
    strategies_on_text(t, buf, scene_names[which], single);
}

static void strategies_on_text(T *t, const char *buf, const char *name, int single)
{
    static Tiles ref, m;
    Scene s;
    RenderOptions o;
    int v;
    const int K = 8;
    if (!test_load_scene(t, &s, buf)) return;
    render_options_default(&o);
    o.sel.grid_res = 8;
    /* the single-wavelength scene is the one that must expose an inconsistent
       light_select_pmf: more samples give it the power to (a pmf evaluated in the
       wrong mode shows up at about 8 standard errors) */
    o.spp = test_scaled(single ? 64 : 24, 4);
    o.seed = 1;
    o.single_wavelength = single;
    o.sel.strategy = SEL_UNIFORM;
    if (!test_render_tiles(t, &s, &o, K, 2, &ref)) goto done;
    for (v = 1; v <= N_VARIANTS; v++) {
        char what[160];
        memset(&o.sel, 0, sizeof o.sel);
        o.sel.grid_res = 8;
        if (v < N_VARIANTS) {
            o.sel.strategy = variants[v].st;
            o.sel.power_metric = variants[v].power_metric;
            o.sel.all_wavelengths = variants[v].all_wl;
            o.sel.throughput_weighted = variants[v].tput;
        } else {
            o.sel.strategy = SEL_ALL;
        }
        snprintf(what, sizeof what, "%s, %s vs uniform", name,
                 v < N_VARIANTS ? variants[v].name : "all");
        if (!test_render_tiles(t, &s, &o, K, 2, &m)) goto done;
        if (!test_tiles_agree(t, &m, &ref, 1e-4, what)) goto done;
    }
    if (s.emitters[s.n_emitters - 1].inf) {
        /* with an infinite light, also BSDF sampling alone (no NEE, no pdf of the
           map used): catches an emitter pdf that differs from the sampling density,
           which would bias every strategy, uniform included, the same way */
        char what[160];
        memset(&o.sel, 0, sizeof o.sel);
        o.nee = 0;
        o.spp *= 4;
        snprintf(what, sizeof what, "%s, BSDF sampling only vs uniform NEE", name);
        if (!test_render_tiles(t, &s, &o, K, 2, &m)) goto done;
        if (!test_tiles_agree(t, &m, &ref, 1e-4, what)) goto done;
    }
done:
    scene_free(&s);
}

static void test_unbiased_dispersive(T *t) { strategies_on_scene(t, SC_DISPERSIVE); }
static void test_unbiased_facing_away(T *t) { strategies_on_scene(t, SC_FACING_AWAY); }
static void test_unbiased_half_spectra(T *t) { strategies_on_scene(t, SC_HALVES); }
static void test_unbiased_one_emitter(T *t) { strategies_on_scene(t, SC_ONE); }
static void test_unbiased_identical(T *t) { strategies_on_scene(t, SC_IDENTICAL); }
static void test_unbiased_many(T *t) { strategies_on_scene(t, SC_MANY); }
static void test_unbiased_through_glass(T *t) { strategies_on_scene(t, SC_THROUGH_GLASS); }
static void test_unbiased_environment(T *t) { strategies_on_scene(t, SC_ENV); }
/* point, spot and distant lights with a lamp: HWSS (the trees' and spatial
   tables' case) and one wavelength per path (the spectral tables' case) */
static void test_unbiased_delta(T *t)
{
    strategies_on_scene(t, SC_DELTA);
    if (!t->failed) strategies_on_scene_opt(t, SC_DELTA, 1);
}

/* An image map (16 x 16, one texel 200 times brighter and coloured, the rest a
   dim gradient) rotated so the bright texel shines into the box, with two lamps:
   every strategy converges to uniform's image. */
static void test_unbiased_environment_map(T *t)
{
    static char buf[65536];
    Image im;
    int x, y;
    const char *path = test_path(t, "env_bright.pfm");
    CHECK(t, img_alloc(&im, 16, 16), "out of memory");
    for (y = 0; y < 16; y++)
        for (x = 0; x < 16; x++) {
            float *px = im.rgb + 3 * (y * 16 + x);
            px[0] = 0.05f + 0.01f * x; px[1] = 0.05f + 0.01f * y; px[2] = 0.1f;
        }
    im.rgb[3 * (7 * 16 + 8) + 0] = 30.0f;   /* texel (8, 7): near +z, the map's centre */
    im.rgb[3 * (7 * 16 + 8) + 1] = 12.0f;
    im.rgb[3 * (7 * 16 + 8) + 2] = 2.0f;
    CHECK(t, pfm_write(&im, path), "cannot write %s", path);
    img_free(&im);
    snprintf(buf, sizeof buf, "%s%s", box_camera, test_box_walls);
    add_light(buf, sizeof buf, SPIKY, 4, -0.5f, 0.0f, 0.2f);
    add_light(buf, sizeof buf, HIGH_HALF, 3, 0.5f, 0.0f, 0.25f);
    strcat(buf, glass_sphere);
    /* the map's +z turned to -z: the bright texel lights the box through its open front */
    snprintf(buf + strlen(buf), sizeof buf - strlen(buf),
             "AttributeBegin\n Rotate 180 0 1 0\n LightSource \"infinite\" \"string filename\" \"%s\"\n"
             "AttributeEnd\n", path);
    strategies_on_text(t, buf, "two lamps, glass and an image map", 0);
}
/* The test that catches a light_select_pmf inconsistent with light_select (e.g. a
   different bin or mode): checked by breaking lights.c on purpose. */
static void test_unbiased_large_single(T *t) { strategies_on_scene_opt(t, SC_LARGE_HALVES, 1); }

/* A sphere lamp seen from outside is sampled in the cone it subtends (lights.c,
   sphere_cone).  For a receiver facing the centre at distance d the irradiance per
   unit radiance is pi sin^2 theta_max = pi r^2 / d^2: the estimate
   mean(cos theta / p_sigma) must match it, every sample must lie on the sphere on
   the cap facing the receiver, and emitter_pdf_sa must give the sampler's density
   there; inside a flipped sphere the area sampler is kept (its density too). */
static void test_sphere_cone_sampling(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ]\n"
        " Translate 1 2 3\n Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
        "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ]\n"
        " ReverseOrientation\n Shape \"sphere\" \"float radius\" 20\nAttributeEnd\n";
    static const double dists[] = { 0.52, 0.8, 2.0, 30.0 };
    Scene s;
    Vec3 c = v3(1, 2, 3);
    int di;
    if (!test_load_scene(t, &s, text)) return;
    for (di = 0; di < 4; di++) {
        double d = dists[di], sum = 0.0, sum2 = 0.0, mean, se, expect = SPECNEE_PI * 0.25 / (d * d);
        Vec3 axis = v3_norm(v3(0.3f, -0.8f, 0.5f)), ref = v3_add(c, v3_mul(axis, (float)d));
        Rng rng;
        int k, n = 200000;
        rng_seed(&rng, 11 + di, 5);
        for (k = 0; k < n; k++) {
            float u[3], pdf2, cos_r;
            EmitterSample es;
            double v = 0.0;
            rng_fill(&rng, u, 3);
            if (emitter_sample(&s, 0, ref, v3(0.0f, 0.0f, 0.0f), u, &es)) {
                float off = fabsf(v3_len(v3_sub(es.p, c)) - 0.5f);
                CHECK(t, off < 1e-4f, "d %g: a sample %g off the sphere", d, off);
                CHECK(t, v3_dot(es.n, es.wi) < 0.0f, "d %g: a sample on the far side", d);
                pdf2 = emitter_pdf_sa(&s, 0, ref, v3(0.0f, 0.0f, 0.0f), es.p, es.n, es.prim);
                CHECK(t, fabsf(pdf2 - es.pdf_sa) <= 1e-4f * es.pdf_sa, "d %g: pdf %g at the sample, "
                      "emitter_pdf_sa %g", d, es.pdf_sa, pdf2);
                cos_r = v3_dot(es.wi, v3_neg(axis));     /* receiver normal towards the centre */
                v = cos_r > 0.0f ? cos_r / es.pdf_sa : 0.0;
            }
            sum += v;
            sum2 += v * v;
        }
        mean = sum / n;
        se = sqrt((sum2 / n - mean * mean) / n);
        CHECK(t, fabs(mean - expect) < 5.0 * se + 1e-4 * expect, "d %g: irradiance %.6g +- %.2g, "
              "expected pi r^2/d^2 = %.6g", d, mean, se, expect);
    }
    {   /* inside the flipped sphere: the area density */
        EmitterSample es;
        Vec3 ref = v3(0.5f, -1.0f, 2.0f);
        CHECK(t, emitter_sample(&s, 1, ref, v3(0.0f, 0.0f, 0.0f), (const float[3]){ 0.3f, 0.6f, 0.2f }, &es), "no sample inside the big sphere");
        CHECK(t, fabsf(es.pdf_sa - emitter_pdf_sa(&s, 1, ref, v3(0.0f, 0.0f, 0.0f), es.p, es.n, es.prim)) <= 1e-4f * es.pdf_sa &&
              fabsf(es.pdf_sa - (float)(es.dist * es.dist / (4.0 * SPECNEE_PI * 400.0 *
                    fabs(v3_dot(es.n, es.wi))))) <= 1e-3f * es.pdf_sa,
              "inside: pdf %g is not the area density", es.pdf_sa);
    }
    scene_free(&s);
}

/* An area light's L: the first knot from 300 nm up that is negative is refused
   (in the UV and in the visible), and an L that is zero at every knot; the sum
   light_spectrum_sum keeps equals the emitters' Le added in order, bit for bit,
   two emitters sharing one L included. */
#define AL_HEAD "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n"
static void test_area_L_checked_and_summed(T *t)
{
    static const char *const bad[][2] = {
        { "[ 300 1 309 1 310 -1 311 1 830 1 ]", "n.pbrt:4: AreaLightSource: L is negative at 310 nm" },
        { "[ 300 1 400 1 401 -2 402 1 499 1 500 -1 501 1 830 1 ]",
          "n.pbrt:4: AreaLightSource: L is negative at 401 nm" },
        { "[ 300 0 830 0 ]", "n.pbrt:4: AreaLightSource: spectrum L is zero everywhere in 300-830 nm" }
    };
    char body[256];
    Scene s;
    SelOptions o;
    LightSampler *ls;
    Error err;
    Spectrum sum, Le;
    int i, e, k, same = 1;
    for (i = 0; i < 3; i++) {
        snprintf(body, sizeof body, "AreaLightSource \"diffuse\" \"spectrum L\" %s\n"
                 "Shape \"sphere\" \"float radius\" 1\n", bad[i][0]);
        test_refused(t, AL_HEAD, body, "n.pbrt", bad[i][1]);
    }
    if (!test_load_scene(t, &s, AL_HEAD
            "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 0.5 0.9 ]\n"
            "Shape \"sphere\" \"float radius\" 0.2\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000\nTranslate 1 0 0\n"
            "Shape \"sphere\" \"float radius\" 0.2\nAttributeEnd\n"
            "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 0.5 0.9 ]\nTranslate 0 1 0\n"
            "Shape \"sphere\" \"float radius\" 0.2\nAttributeEnd\n")) return;
    memset(&o, 0, sizeof o);
    o.strategy = SEL_SPECTRAL_TREE;
    ls = light_sampler_build(&s, &o, &err);
    CHECK(t, ls != NULL, "%s", err.msg);
    if (!ls) { scene_free(&s); return; }
    spec_const(&sum, 0.0f);
    for (e = 0; e < s.n_emitters; e++) {
        light_spectrum(ls, e, &Le);
        for (k = 0; k < SPEC_N; k++) sum.v[k] += Le.v[k];
    }
    for (k = 0; k < SPEC_N; k++) same &= sum.v[k] == light_spectrum_sum(ls)->v[k];
    for (k = 0; k < SPEC_UV_N; k++) same &= light_spectrum_sum(ls)->uv[k] == 0.0f;
    CHECK(t, s.n_emitters == 3 && same, "light_spectrum_sum is not the emitters' Le summed in order");
    light_sampler_free(ls);
    scene_free(&s);
}

/* luminance_sum (arealight.c) is the definition sum_{whole nm in [lo, hi]}
   ybar(lambda) L(lambda) with ybar rounded to float: on a ramp L (every knot
   differs from its neighbour) it equals that sum written out here, exactly, over
   the visible range and a range inside it; a knot read one nm off changes it. */
static void test_luminance_sum_definition(T *t)
{
    static const float ranges[2][2] = { { 360.0f, 830.0f }, { 400.5f, 700.0f } };
    Spectrum L;
    int nm, r;
    for (nm = SPEC_MIN; nm <= SPEC_MAX; nm++) *spec_at(&L, nm) = 0.001f * (float)(nm - SPEC_MIN) + 0.1f;
    for (nm = 0; nm < SPEC_UV_N; nm++) L.uv[nm] = 0.0f;
    for (r = 0; r < 2; r++) {
        double want = 0.0, got = luminance_sum(&L, ranges[r][0], ranges[r][1]);
        for (nm = (int)ceilf(ranges[r][0]); nm <= (int)floorf(ranges[r][1]); nm++)
            want += (double)(float)cie_ybar((double)nm) * spec_get(&L, nm);
        CHECK(t, got == want, "luminance_sum over [%g, %g]: %.17g, the definition %.17g",
              ranges[r][0], ranges[r][1], got, want);
    }
}

const TestCase tests_lights[] = {
    { "lights_luminance_sum_definition", test_luminance_sum_definition },
    { "lights_area_L_checked_and_summed", test_area_L_checked_and_summed },
    { "lights_sphere_cone_sampling", test_sphere_cone_sampling },
    { "lights_select_matches_pmf", test_select_matches_pmf },
    { "lights_positive_where_emitting", test_positive_where_emitting },
    { "lights_pmf_same_for_every_hero", test_pmf_same_for_every_hero },
    { "lights_lazy_equals_eager", test_lazy_equals_eager },
    { "lights_spatial_facing_and_flat", test_spatial_facing_and_flat },
    { "lights_emitter_can_reach", test_emitter_can_reach },
    { "lights_back_of_lamp_noise", test_back_of_lamp_noise },
    { "lights_unbiased_dispersive", test_unbiased_dispersive },
    { "lights_unbiased_facing_away", test_unbiased_facing_away },
    { "lights_unbiased_half_spectra", test_unbiased_half_spectra },
    { "lights_unbiased_one_emitter", test_unbiased_one_emitter },
    { "lights_unbiased_identical", test_unbiased_identical },
    { "lights_unbiased_many", test_unbiased_many },
    { "lights_unbiased_through_glass", test_unbiased_through_glass },
    { "lights_unbiased_large_single", test_unbiased_large_single },
    { "lights_unbiased_environment", test_unbiased_environment },
    { "lights_unbiased_environment_map", test_unbiased_environment_map },
    { "lights_unbiased_delta", test_unbiased_delta },
    { NULL, NULL }
};
