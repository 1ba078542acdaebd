/* tests/test_equiangular.c - equiangular distance sampling towards a lamp in a
   homogeneous medium (equiangular.c; path.c's equi_nee and the MIS weights of
   THEORY §12.1).

   - chi2:    equi_sample against equi_pdf (18c)-(18d) on a bounded segment, an
              unbounded one and one that starts past the lamp (chi-square over
              cells of t), the density integrating to 1; a ray through the
              lamp's centre has no density;
   - lamps:   which emitters the technique aims at, and none beyond EQUI_LAMPS_MAX;
   - point:   single scattering from a point light in an infinite fog, against a
              quadrature of the integral along the camera rays, with the
              technique on and off; on, its standard error is well below off's;
   - sphere:  a sphere lamp seen through a forward-scattering chromatic fog: on
              and off agree tile by tile (phase sampling finds the lamp often,
              so emitter_found's weight is in play: without the equiangular
              terms there the image is 7 % too bright);
   - blocked: a blocker between a lamp and the floor in fog without "interface"
              surfaces (the any-hit shadow ray): NEE agrees with phase sampling
              alone. */
#include "test.h"
#include <math.h>
#include <string.h>

/* ---- the sampler against its density */
static void chi2_segment(T *t, Vec3 o, Vec3 d, float tmax, Vec3 c, const char *what)
{
    enum { N = 200000, CELLS = 40, SUB = 400 };
    double obs[CELLS], ex[CELLS], lo, hi, total = 0.0;
    EquiSeg sg;
    Rng rng;
    int i, k;
    CHECK(t, equi_segment(o, d, tmax, c, &sg), "%s: refused", what);
    if (!equi_segment(o, d, tmax, c, &sg)) return;
    /* cells on [0, hi]: tmax, or for an unbounded ray where 99.9 % of the mass lies */
    lo = 0.0;
    hi = isinf(tmax) ? sg.delta + sg.D * tan(sg.theta_a + 0.999 * (sg.theta_b - sg.theta_a)) : tmax;
    for (i = 0; i < CELLS; i++) {
        double a = lo + (hi - lo) * i / CELLS, b = lo + (hi - lo) * (i + 1) / CELLS, s = 0.0;
        for (k = 0; k < SUB; k++) s += equi_pdf(&sg, a + (b - a) * (k + 0.5) / SUB);
        ex[i] = s * (b - a) / SUB * N;
        total += ex[i];
        obs[i] = 0.0;
    }
    rng_seed(&rng, 11, 5);
    for (k = 0; k < N; k++) {
        double pdf, x = equi_sample(&sg, rng_float(&rng), &pdf);
        int cell = (int)((x - lo) / (hi - lo) * CELLS);
        CHECK(t, x >= 0.0 && x <= (double)tmax, "%s: t = %g off the segment", what, x);
        CHECK(t, fabs(pdf - equi_pdf(&sg, x)) <= 1e-12 * pdf, "%s: pdf %g, equi_pdf %g", what, pdf,
              equi_pdf(&sg, x));
        if (cell >= 0 && cell < CELLS) obs[cell] += 1.0;
    }
    CHECK_CHI2(t, obs, ex, CELLS, 3, NULL, "%s", what);
    if (!isinf(tmax))
        CHECK(t, fabs(total / N - 1.0) < 1e-4, "%s: the density integrates to %.6f", what, total / N);
    else {
        /* the mass below hi of the density over [0, inf): the angle's share, with
           theta(inf) = pi / 2 */
        Vec3 oc = v3_sub(c, o);
        double dl = v3_dot(oc, d), dd = sqrt(v3_dot(oc, oc) - dl * dl), a0 = atan(-dl / dd);
        double want = (atan((hi - dl) / dd) - a0) / (0.5 * SPECNEE_PI - a0);
        CHECK(t, fabs(total / N - want) < 2e-4, "%s: the mass below %g is %.6f, expected %.6f", what, hi,
              total / N, want);
    }
}

static void test_chi2(T *t)
{
    EquiSeg sg;
    Vec3 o = v3(0.0f, 0.0f, 0.0f), d = v3_norm(v3(1.0f, 0.2f, -0.3f));
    chi2_segment(t, o, d, 6.0f, v3(2.0f, 1.0f, 0.5f), "bounded, the lamp beside its middle");
    chi2_segment(t, o, d, INFINITY, v3(2.0f, 0.3f, -0.2f), "unbounded, the lamp near the ray");
    chi2_segment(t, o, d, 5.0f, v3(-1.0f, 0.5f, 0.0f), "the lamp behind the start");
    CHECK(t, !equi_segment(o, d, 4.0f, v3_mul(d, 2.0f), &sg), "a ray through the centre has no density");
}

/* ---- the lamps it aims at */
static void test_lamps(T *t)
{
    static const char head[] =
        "Camera \"perspective\"\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "LightSource \"distant\" \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ]\n"
        "LightSource \"point\" \"point3 from\" [ 1 2 3 ]\n"
        "AttributeBegin\n"
        " Translate 0 4 0\n"
        " AreaLightSource \"diffuse\"\n"
        " Shape \"sphere\" \"float radius\" 0.5\n"
        "AttributeEnd\n"
        "AttributeBegin\n"
        " AreaLightSource \"diffuse\"\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "AttributeEnd\n";
    char text[4096];
    Scene s;
    SelOptions so;
    LightSampler *ls;
    const EquiLamps *L;
    Error e;
    int k;
    memset(&so, 0, sizeof so);
    so.strategy = SEL_SPECTRAL_TREE;
    if (!test_load_scene(t, &s, head)) return;
    ls = light_sampler_build(&s, &so, &e);
    CHECK(t, ls != NULL, "light sampler: %s", e.msg);
    if (!ls) { scene_free(&s); return; }
    L = light_equi(ls);
    CHECK(t, L->n == 2, "%d lamps, expected the point light and the sphere", L->n);
    if (L->n == 2) {
        CHECK(t, L->emitter[0] == 1 && L->emitter[1] == 2, "emitters %d %d, expected 1 2",
              L->emitter[0], L->emitter[1]);
        CHECK(t, L->center[1].y == 4.0f && L->center[0].z == 3.0f, "centres (%g %g %g) (%g %g %g)",
              L->center[0].x, L->center[0].y, L->center[0].z, L->center[1].x, L->center[1].y,
              L->center[1].z);
        CHECK(t, equi_lamp_of(L, 2) == 1 && equi_lamp_of(L, 3) == -1 && equi_lamp_of(L, 0) == -1,
              "equi_lamp_of");
    }
    light_sampler_free(ls);
    scene_free(&s);
    /* one lamp more than EQUI_LAMPS_MAX: the technique is off */
    strcpy(text, head);
    for (k = 0; k < EQUI_LAMPS_MAX; k++)
        snprintf(text + strlen(text), sizeof text - strlen(text),
                 "LightSource \"point\" \"point3 from\" [ %d 2 3 ]\n", k);
    if (!test_load_scene(t, &s, text)) return;
    ls = light_sampler_build(&s, &so, &e);
    CHECK(t, ls != NULL && light_equi(ls)->n == 0, "%d lamps: the technique should be off",
          ls ? light_equi(ls)->n : -1);
    light_sampler_free(ls);
    scene_free(&s);
}

/* ---- single scattering from a point light in an infinite fog */
/* sigma_s 0.5, sigma_a 0.1 (flat), g 0.3; the lamp at (0, 1.5, 0), I = 1 (Y); the
   camera at z = 5 looks at the origin with fov 20: its rays pass 0.6 or more from
   the lamp.  Y of a ray through the point (x, y, 0) of the plane z = 0:
   int_0^inf sigma_s exp(-sigma_t t) p_HG(d . w) exp(-sigma_t r) / r^2 dt. */
static double single_scatter_y(double x, double y)
{
    const double ss = 0.5, st = 0.6, g = 0.3, lx = 0.0, ly = 1.5, lz = 0.0, h = 0.004;
    double n = sqrt(x * x + y * y + 25.0), d[3], sum = 0.0, tt;
    d[0] = x / n; d[1] = y / n; d[2] = -5.0 / n;
    for (tt = 0.5 * h; tt < 45.0; tt += h) {
        double p[3], w[3], r2, r, c, ph;
        p[0] = d[0] * tt; p[1] = d[1] * tt; p[2] = 5.0 + d[2] * tt;
        w[0] = lx - p[0]; w[1] = ly - p[1]; w[2] = lz - p[2];
        r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        r = sqrt(r2);
        c = (d[0] * w[0] + d[1] * w[1] + d[2] * w[2]) / r;
        ph = (1.0 - g * g) / (4.0 * SPECNEE_PI * pow(1.0 + g * g - 2.0 * g * c, 1.5));
        sum += h * ss * exp(-st * tt) * ph * exp(-st * r) / r2;
    }
    return sum;
}

static void test_point_single(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" "
        "\"spectrum sigma_a\" [ 400 0.1 700 0.1 ] \"spectrum sigma_s\" [ 400 0.5 700 0.5 ] \"float g\" 0.3\n"
        "MediumInterface \"\" \"fog\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 20 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "PixelFilter \"box\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
        "WorldBegin\n"
        "LightSource \"point\" \"point3 from\" [ 0 1.5 0 ] \"spectrum I\" [ 400 1 700 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    double a = 5.0 * tan(10.0 * SPECNEE_PI / 180.0), expect = 0.0, Y[2], se[2];
    int i, j, n = 24, off;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            expect += single_scatter_y(a * (2.0 * (i + 0.5) / n - 1.0), a * (2.0 * (j + 0.5) / n - 1.0));
    expect /= (double)n * n;
    if (!test_load_scene(t, &s, text)) return;
    for (off = 0; off < 2; off++) {
        render_options_default(&o);
        o.spp = test_scaled(16, 4);
        o.maxdepth = 1;
        o.equiangular = !off;
        if (!test_render_tiles(t, &s, &o, 8, 1, &tl)) { scene_free(&s); return; }
        Y[off] = test_tile_y(&tl, 0, &se[off]);
        CHECK(t, fabs(Y[off] - expect) < TEST_K_SIGMA * se[off] + 3e-3 * expect,
              "equiangular %s: Y = %.6g +- %.2g, expected %.6g (quadrature)", off ? "off" : "on", Y[off],
              se[off], expect);
    }
    scene_free(&s);
    CHECK(t, se[0] < 0.5 * se[1], "the standard error with equiangular sampling, %.3g, is not well "
          "below free flight's alone, %.3g", se[0], se[1]);
}

/* ---- a sphere lamp in a chromatic fog: on and off agree */
static void test_sphere_agree(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" "
        "\"spectrum sigma_a\" [ 400 0.02 700 0.08 ] \"spectrum sigma_s\" [ 400 0.6 550 0.3 700 0.1 ] "
        "\"float g\" 0.8\n"
        "MediumInterface \"\" \"fog\"\n"
        "LookAt 0 0 3  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 60 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 2 ]\n"
        "WorldBegin\n"
        "AttributeBegin\n"
        " AreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\" \"float scale\" 4\n"
        " Shape \"sphere\" \"float radius\" 1\n"
        "AttributeEnd\n";
    Scene s;
    RenderOptions o;
    Tiles on, off;
    int ok;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    o.equiangular = 1;
    ok = test_render_tiles(t, &s, &o, 8, 2, &on);
    o.equiangular = 0;
    o.spp = test_scaled(64, 16);
    ok = ok && test_render_tiles(t, &s, &o, 8, 2, &off);
    scene_free(&s);
    if (ok) test_tiles_agree(t, &on, &off, 1e-4, "sphere lamp in chromatic fog: equiangular on vs off");
}

/* ---- the any-hit shadow ray in a medium without "interface" surfaces: a black
   blocker between a sphere lamp and the floor must block NEE as it blocks phase
   sampling (NEE + phase sampling against phase sampling alone) */
static void test_blocked_in_fog(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" "
        "\"rgb sigma_a\" [ 0.05 0.05 0.05 ] \"rgb sigma_s\" [ 0.3 0.3 0.3 ]\n"
        "MediumInterface \"\" \"fog\"\n"
        "LookAt 0 0.5 4  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 40 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 2 ]\n"
        "WorldBegin\n"
        "AttributeBegin\n"
        " Translate 0 2 0\n"
        " AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
        " Shape \"sphere\" \"float radius\" 0.5\n"
        "AttributeEnd\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -3 1 -3  -3 1 3  3 1 3  3 1 -3 ]\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -10 0 -10  10 0 -10  10 0 10  -10 0 10 ]\n";
    Scene s;
    RenderOptions o;
    Tiles a, b;
    int ok;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    ok = test_render_tiles(t, &s, &o, 8, 2, &a);
    o.nee = 0;
    o.spp = test_scaled(64, 16);
    ok = ok && test_render_tiles(t, &s, &o, 8, 2, &b);
    scene_free(&s);
    if (ok) test_tiles_agree(t, &a, &b, 1e-4, "a blocker in fog: NEE + phase sampling vs phase sampling alone");
}

const TestCase tests_equiangular[] = {
    { "equiangular_chi2", test_chi2 },
    { "equiangular_lamps", test_lamps },
    { "equiangular_point_single", test_point_single },
    { "equiangular_sphere_agree", test_sphere_agree },
    { "equiangular_blocked_in_fog", test_blocked_in_fog },
    { NULL, NULL }
};
