/* tests/test_delta.c - point, spot and distant lights (delta.c) against closed forms.

   A white Lambertian plane z = 0 (albedo 1) is seen from straight above by a
   narrow camera; its radiance is E / pi, with E the irradiance the light gives it
   (delta.c section 1):
       point     E = I h / (h^2 + x^2 + y^2)^(3/2)        (light at height h)
       spot      E = I falloff(theta) cos^3(theta) / h^2   (axis straight down)
       distant   E = L cos(theta)
   where I and L have luminance `scale` (pbrt-v4's normalisation), times
   power / (4 pi) and so on when "power" or "illuminance" is given.  The expected
   pixel luminance is the closed form averaged over the camera's footprint on the
   plane (a 64 x 64 midpoint rule; the box pixel filter keeps every sample inside
   its pixel, so the image covers exactly that footprint).  Renders of K seeds give the mean and its standard error; a
   check passes within TEST_K_SIGMA standard errors plus 0.2% (the film integrates
   400-700 nm, the normalisation too, so the luminance is exact up to the CIE
   table's interpolation).  The light selection strategies and the MIS weight of
   a delta sample (path.c) are in the estimator under test; the unbiasedness of
   every strategy with delta lights mixed among area lights is in test_lights.c
   (lights_unbiased_delta, lights_select_matches_pmf). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* The scene: a camera at (x0, 0, 5) looking straight down with field of view
   fov, the plane, and `light` (directives after WorldBegin). */
static void plane_scene(char *buf, size_t cap, double x0, double fov, const char *light)
{
    snprintf(buf, cap,
             "LookAt %g 0 5  %g 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ %g ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
             "\"string filename\" \"t.pfm\"\n"
             "PixelFilter \"box\"\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n%s\n"
             "Material \"diffuse\" \"spectrum reflectance\" [ 360 1 830 1 ]\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -40 -40 0  40 -40 0  40 40 0  -40 40 0 ]\n",
             x0, x0, fov, light);
}

typedef double (*IrradianceFn)(const double *par, double x, double y);

/* The mean of fn over the footprint [x0 - a, x0 + a] x [-a, a], a = 5 tan(fov/2). */
static double footprint_mean(IrradianceFn fn, const double *par, double x0, double fov)
{
    double a = 5.0 * tan(0.5 * fov * SPECNEE_PI / 180.0), sum = 0.0;
    int i, j, n = 64;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            sum += fn(par, x0 + a * (2.0 * (i + 0.5) / n - 1.0), a * (2.0 * (j + 0.5) / n - 1.0));
    return sum / ((double)n * n);
}

/* Render text with strategy st (K seeds, one tile) and compare the luminance
   with E / pi. */
static int check_render(T *t, const char *text, SelStrategy st, double E, const char *what)
{
    Scene s;
    RenderOptions o;
    Tiles tl;
    double Y, se, expect = E / SPECNEE_PI;
    if (!test_load_scene(t, &s, text)) return 0;
    render_options_default(&o);
    o.sel.grid_res = 4;
    o.sel.strategy = st;
    o.spp = test_scaled(16, 4);
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return 0; }
    scene_free(&s);
    Y = test_luminance(tl.mean[0]);
    se = tl.se[0][1];
    if (!(fabs(Y - expect) < TEST_K_SIGMA * se + 2e-3 * expect + 1e-7)) {
        test_failf(t, __FILE__, __LINE__, "%s (%s): Y = %.6g +- %.2g, expected E/pi = %.6g",
                   what, sel_name(st), Y, se, expect);
        return 0;
    }
    return 1;
}

/* ------------------------------------------------------------------ point */
static double point_E(const double *par, double x, double y)
{
    double I = par[0], h = par[1], d2 = h * h + x * x + y * y;
    return I * h / (d2 * sqrt(d2));
}

static void test_point_irradiance(T *t)
{
    static const struct { const char *light; double I, h; const char *what; } cases[] = {
        { "LightSource \"point\" \"float scale\" [ 3 ] \"point3 from\" [ 0 0 2 ]", 3.0, 2.0,
          "scale 3, default spectrum" },
        /* the CTM moves "from": (-1, 0, 1.5) + (1, 0, 0) */
        { "AttributeBegin\nTranslate 1 0 0\nLightSource \"point\" \"spectrum I\" [ 400 0.2 550 2 700 0.7 ] "
          "\"point3 from\" [ -1 0 1.5 ]\nAttributeEnd", 1.0, 1.5, "a tabulated I, moved by the CTM" },
        /* "power" 10: luminous intensity 10 / (4 pi), whatever the spectrum */
        { "LightSource \"point\" \"blackbody I\" [ 3000 ] \"float power\" [ 10 ] \"point3 from\" [ 0 0 2.5 ]",
          10.0 / (4.0 * SPECNEE_PI), 2.5, "power 10, blackbody" },
        /* an rgb I is normalised by D65 (pbrt-v4): luminance = scale x Y(rgb) */
        { "LightSource \"point\" \"rgb I\" [ 1 0.5 0.2 ] \"float scale\" [ 2 ] \"point3 from\" [ 0 0 2 ]",
          2.0 * (0.212671 * 1.0 + 0.715160 * 0.5 + 0.072169 * 0.2), 2.0, "rgb I" },
    };
    SelStrategy strategies[3] = { SEL_SPECTRAL_TREE, SEL_SPATIAL, SEL_POWER };
    int c, k;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
        char text[4096];
        double par[2], E;
        par[0] = cases[c].I;
        par[1] = cases[c].h;
        plane_scene(text, sizeof text, 0.0, 6.0, cases[c].light);
        E = footprint_mean(point_E, par, 0.0, 6.0);
        for (k = 0; k < 3; k++)
            if (!check_render(t, text, strategies[k], E, cases[c].what)) return;
    }
}

/* ------------------------------------------------------------------ spot */
/* par: I, h, cos_end, cos_start (axis straight down from (0, 0, h)) */
static double spot_E(const double *par, double x, double y)
{
    double I = par[0], h = par[1], d2 = h * h + x * x + y * y, c = h / sqrt(d2), f;
    double a = par[2], b = par[3], u;
    if (a == b) f = c < a ? 0.0 : 1.0;
    else {
        u = (c - a) / (b - a);
        u = u < 0 ? 0 : u > 1 ? 1 : u;
        f = u * u * (3.0 - 2.0 * u);
    }
    return I * f * c / d2;                 /* I f cos(theta) / d^2 = I f cos^3 / h^2 */
}

/* Points inside the full cone, across the falloff band and outside, for a spot
   of coneangle 30 and conedeltaangle 10 at height 2 aiming straight down; the
   trees' cone bounds and the reach mask of the spatial tables must keep every
   point of the band possible. */
static void test_spot_falloff(T *t)
{
    static const double theta_deg[] = { 0.0, 12.0, 21.0, 24.0, 27.0, 29.5, 33.0 };
    SelStrategy strategies[4] = { SEL_SPECTRAL_TREE, SEL_TREE, SEL_SPATIAL, SEL_PRODUCT };
    double par[4];
    int i, k;
    par[0] = 2.0;
    par[1] = 2.0;
    par[2] = cos(30.0 * SPECNEE_PI / 180.0);
    par[3] = cos(20.0 * SPECNEE_PI / 180.0);
    for (i = 0; i < (int)(sizeof theta_deg / sizeof theta_deg[0]); i++) {
        char text[4096];
        double x0 = 2.0 * tan(theta_deg[i] * SPECNEE_PI / 180.0), E;
        char what[64];
        /* the spot's frame turned by the CTM: from (0, 0, 0) towards +x, rotated
           -90 degrees about y so that it aims down, then lifted to height 2 */
        plane_scene(text, sizeof text, x0, 0.5,
                    "AttributeBegin\nTranslate 0 0 2\nRotate 90 0 1 0\n"
                    "LightSource \"spot\" \"float scale\" [ 2 ] \"point3 from\" [ 0 0 0 ] "
                    "\"point3 to\" [ 1 0 0 ] \"float coneangle\" [ 30 ] \"float conedeltaangle\" [ 10 ]\n"
                    "AttributeEnd");
        E = footprint_mean(spot_E, par, x0, 0.5);
        snprintf(what, sizeof what, "spot at %g degrees", theta_deg[i]);
        for (k = 0; k < 4; k++)
            if (!check_render(t, text, strategies[k], E, what)) return;
    }
    {
        /* "power" P: luminous intensity P / (2 pi ((1 - cs) + (cs - ce) / 2)) */
        char text[4096];
        double cs = par[3], ce = par[2], E;
        par[0] = 5.0 / (2.0 * SPECNEE_PI * ((1.0 - cs) + (cs - ce) / 2.0));
        plane_scene(text, sizeof text, 0.0, 0.5,
                    "LightSource \"spot\" \"float power\" [ 5 ] \"point3 from\" [ 0 0 2 ] "
                    "\"point3 to\" [ 0 0 0 ] \"float coneangle\" [ 30 ] \"float conedeltaangle\" [ 10 ]");
        E = footprint_mean(spot_E, par, 0.0, 0.5);
        check_render(t, text, SEL_SPECTRAL_TREE, E, "spot with power 5");
    }
}

/* par: I, h, cos_end, cos_start, k: a spot at (0, 0, h) aiming down under Scale k 1 1,
   so that in its frame the direction (x, y, -h) is (x / k, y, -h) (pbrt-v4 measures
   the cone there: an elliptic cone in the world) */
static double spot_stretched_E(const double *par, double x, double y)
{
    double h = par[1], k = par[4], d2 = h * h + x * x + y * y;
    double co = h / sqrt(x * x / (k * k) + y * y + h * h), a = par[2], b = par[3], u, f;
    u = (co - a) / (b - a);
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    f = u * u * (3.0 - 2.0 * u);
    return par[0] * f * (h / sqrt(d2)) / d2;
}

/* A spot under a CTM that stretches x by 2: the cone is twice as wide along x
   as along y.  Points across the stretched band along x (at x = 2, 45 degrees off
   the axis in the world, still inside the band in the light's frame), and one
   along y, where the stretch does not act. */
static void test_spot_stretched(T *t)
{
    static const double xy[][2] = { { 1.0, 0.0 }, { 1.6, 0.0 }, { 2.0, 0.0 }, { 2.4, 0.0 }, { 0.0, 0.95 } };
    SelStrategy strategies[3] = { SEL_SPECTRAL_TREE, SEL_SPATIAL, SEL_UNIFORM };
    double par[5];
    int i, k;
    par[0] = 2.0;
    par[1] = 2.0;
    par[2] = cos(30.0 * SPECNEE_PI / 180.0);
    par[3] = cos(20.0 * SPECNEE_PI / 180.0);
    par[4] = 2.0;
    for (i = 0; i < (int)(sizeof xy / sizeof xy[0]); i++) {
        char text[4096], light[512], what[64];
        double E;
        /* the camera looks down at (x, y): plane_scene puts it over (x0, 0), so
           move the whole scene by -y instead (a Translate before everything) */
        snprintf(light, sizeof light,
                 "AttributeBegin\nTranslate 0 %g 0\nScale 2 1 1\n"
                 "LightSource \"spot\" \"float scale\" [ 2 ] \"point3 from\" [ 0 0 2 ] \"point3 to\" [ 0 0 0 ] "
                 "\"float coneangle\" [ 30 ] \"float conedeltaangle\" [ 10 ]\nAttributeEnd", -xy[i][1]);
        plane_scene(text, sizeof text, xy[i][0], 0.5, light);
        {
            /* footprint around (x, y) relative to the light: shift the closed form */
            double q[5];
            int j;
            for (j = 0; j < 5; j++) q[j] = par[j];
            E = 0.0;
            {
                double a = 5.0 * tan(0.25 * SPECNEE_PI / 180.0), sum = 0.0;
                int u, v, n = 64;
                for (u = 0; u < n; u++)
                    for (v = 0; v < n; v++)
                        sum += spot_stretched_E(q, xy[i][0] + a * (2.0 * (u + 0.5) / n - 1.0),
                                                xy[i][1] + a * (2.0 * (v + 0.5) / n - 1.0));
                E = sum / ((double)n * n);
            }
        }
        snprintf(what, sizeof what, "stretched spot at (%g, %g)", xy[i][0], xy[i][1]);
        for (k = 0; k < 3; k++)
            if (!check_render(t, text, strategies[k], E, what)) return;
    }
}

/* ------------------------------------------------------------------ distant */
static double distant_E(const double *par, double x, double y)
{
    (void)x; (void)y;
    return par[0] * par[1];                /* L cos(theta) */
}

/* The cosine law, and "illuminance": a distant light from angle theta to the
   plane's normal.  The plane passes through the origin, where a light without a
   position must not be put into the tree (its importance would vanish there). */
static void test_distant_cosine(T *t)
{
    static const double theta_deg[] = { 0.0, 40.0, 70.0 };
    SelStrategy strategies[3] = { SEL_SPECTRAL_TREE, SEL_SPATIAL, SEL_UNIFORM };
    int i, k;
    for (i = 0; i < 3; i++) {
        char text[4096], light[512], what[64];
        double th = theta_deg[i] * SPECNEE_PI / 180.0, par[2], E;
        snprintf(light, sizeof light, "LightSource \"distant\" \"float illuminance\" [ 2 ] "
                 "\"float scale\" [ 1.5 ] \"point3 from\" [ %.9g 0 %.9g ] \"point3 to\" [ 0 0 0 ]",
                 sin(th), cos(th));
        par[0] = 3.0;
        par[1] = cos(th);
        plane_scene(text, sizeof text, 0.0, 4.0, light);
        E = footprint_mean(distant_E, par, 0.0, 4.0);
        snprintf(what, sizeof what, "distant at %g degrees", theta_deg[i]);
        for (k = 0; k < 3; k++)
            if (!check_render(t, text, strategies[k], E, what)) return;
    }
}

/* ------------------------------------------------------------------ power */
/* The power strategy picks by pbrt-v4's Phi: a point light of power 4 pi (Phi
   = 4 pi over the luminance-normalised spectrum, i.e. int Le = 1 per nm-weighted
   unit) against a distant light of L = 1 over a scene of bounding radius R
   (Phi = pi R^2) and a point light of scale 1 (Phi = 4 pi): same spectrum, so
   P_i = Phi_i / sum Phi. */
static void test_power_pmf(T *t)
{
    const char *text =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "LightSource \"point\" \"float power\" [ 12.566370614359172 ] \"point3 from\" [ 0 0 1 ]\n"
        "LightSource \"point\" \"float scale\" [ 2 ] \"point3 from\" [ 0 0 2 ]\n"
        "LightSource \"distant\" \"float scale\" [ 1 ] \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
        "LightSource \"spot\" \"float scale\" [ 1 ] \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ] "
        "\"float coneangle\" [ 60 ] \"float conedeltaangle\" [ 20 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -3 -4 0  3 -4 0  3 4 0  -3 4 0 ]\n";
    Scene s;
    SelOptions o;
    LightSampler *ls;
    Error err;
    LightCtx c;
    double phi[4], sum = 0.0, R = 5.0, cs = cos(40.0 * SPECNEE_PI / 180.0), ce = 0.5;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    phi[0] = 4.0 * SPECNEE_PI;                       /* power 4 pi */
    phi[1] = 4.0 * SPECNEE_PI * 2.0;                 /* 4 pi x scale 2 */
    phi[2] = SPECNEE_PI * R * R;                     /* pi R^2 L, R = half the box diagonal */
    phi[3] = 2.0 * SPECNEE_PI * ((1.0 - cs) + (cs - ce) / 2.0);
    for (i = 0; i < 4; i++) sum += phi[i];
    memset(&o, 0, sizeof o);
    o.strategy = SEL_POWER;
    ls = light_sampler_build(&s, &o, &err);
    CHECK(t, ls != NULL, "%s", err.msg);
    memset(&c, 0, sizeof c);
    for (i = 0; i < 4; i++) {
        double p = light_select_pmf(ls, &c, i);
        if (!(fabs(p - phi[i] / sum) < 1e-3 * phi[i] / sum)) {
            test_failf(t, __FILE__, __LINE__, "light %d: P = %.6g, expected Phi/sum = %.6g", i, p,
                       phi[i] / sum);
            break;
        }
    }
    light_sampler_free(ls);
    scene_free(&s);
}

/* A distant light has no position: as in pbrt-v4's BVHLightSampler it stands
   beside the light tree with an infinite light, each getting 1 / (2 + 1) of
   the choices wherever the tree can light the point (the tree the rest). */
static void test_distant_beside_tree(T *t)
{
    const char *text =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "LightSource \"point\" \"point3 from\" [ 0.5 0.5 1 ]\n"
        "LightSource \"distant\" \"point3 from\" [ 1 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
        "LightSource \"spot\" \"point3 from\" [ -0.5 0 1 ] \"point3 to\" [ -0.5 0 0 ]\n"
        "LightSource \"infinite\" \"float scale\" [ 0.1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -3 -4 0  3 -4 0  3 4 0  -3 4 0 ]\n";
    Scene s;
    int st;
    if (!test_load_scene(t, &s, text)) return;
    for (st = 0; st < 2; st++) {
        SelOptions o;
        LightSampler *ls;
        Error err;
        Rng r;
        int k;
        memset(&o, 0, sizeof o);
        o.strategy = st ? SEL_SPECTRAL_TREE : SEL_TREE;
        ls = light_sampler_build(&s, &o, &err);
        CHECK(t, ls != NULL, "%s", err.msg);
        rng_seed(&r, 5, (uint64_t)st);
        for (k = 0; k < 50; k++) {
            LightCtx c;
            float u[3], pd, pi, sum;
            int j;
            memset(&c, 0, sizeof c);
            rng_fill(&r, u, 3);
            c.p = v3(-2.0f + 4.0f * u[0], -2.0f + 4.0f * u[1], 0.3f * u[2]);   /* under the lights */
            c.n = v3(0, 0, 1);
            c.alive = 15u;
            for (j = 0; j < HERO_N; j++) { c.lambda[j] = 420.0f + 70.0f * j; c.beta[j] = 1.0f; }
            pd = light_select_pmf(ls, &c, 1);
            pi = light_select_pmf(ls, &c, 3);
            sum = pd + pi + light_select_pmf(ls, &c, 0) + light_select_pmf(ls, &c, 2);
            if (!(fabsf(pd - 1.0f / 3.0f) < 1e-6f && fabsf(pi - 1.0f / 3.0f) < 1e-6f &&
                  fabsf(sum - 1.0f) < 1e-5f)) {
                test_failf(t, __FILE__, __LINE__, "%s at (%g, %g, %g): P(distant) = %g, "
                           "P(infinite) = %g, sum %g; expected 1/3, 1/3, 1", sel_name(o.strategy),
                           c.p.x, c.p.y, c.p.z, pd, pi, sum);
                break;
            }
        }
        light_sampler_free(ls);
        if (t->failed) break;
    }
    scene_free(&s);
}

/* ------------------------------------------------------------------ bad input */
static void expect_error(T *t, const char *light, const char *k1, const char *k2)
{
    test_light_refused(t, light, "d.pbrt:", k1, k2);
}

static void test_bad_input(T *t)
{
    expect_error(t, "LightSource \"spot\" \"float coneangle\" [ 0 ]", "coneangle", "(0, 180]");
    expect_error(t, "LightSource \"spot\" \"float coneangle\" [ 200 ]", "coneangle", "(0, 180]");
    expect_error(t, "LightSource \"spot\" \"float conedeltaangle\" [ -1 ]", "conedeltaangle", ">= 0");
    expect_error(t, "LightSource \"spot\" \"point3 from\" [ 1 1 1 ] \"point3 to\" [ 1 1 1 ]",
                 "spot", "same point");
    expect_error(t, "LightSource \"distant\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ 0 0 0 ]",
                 "distant", "same point");
    expect_error(t, "LightSource \"point\" \"float scale\" [ -1 ]", "point", ">= 0");
    expect_error(t, "LightSource \"point\" \"spectrum I\" [ 400 1 500 -1 700 1 ]", "I is negative", NULL);
    expect_error(t, "LightSource \"point\" \"point3 from\" [ 1 2 ]", "from", "3 values");
    expect_error(t, "LightSource \"point\" \"float coneangle\" [ 20 ]", "coneangle", "unused");
    expect_error(t, "LightSource \"distant\" \"float power\" [ 20 ]", "power", "unused");
    expect_error(t, "LightSource \"goniometric\"", "goniometric", "filename");
    expect_error(t, "LightSource \"point\" \"float scale\" [ 1e39 ]", "scale", "finite");
}

const TestCase tests_delta[] = {
    { "delta_point_irradiance", test_point_irradiance },
    { "delta_spot_falloff", test_spot_falloff },
    { "delta_spot_stretched", test_spot_stretched },
    { "delta_distant_cosine", test_distant_cosine },
    { "delta_power_pmf", test_power_pmf },
    { "delta_distant_beside_tree", test_distant_beside_tree },
    { "delta_bad_input", test_bad_input },
    { NULL, NULL }
};
