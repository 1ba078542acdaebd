/* tests/test_grid.c - heterogeneous media: MakeNamedMedium "uniformgrid"
   (medium.c: the grids, the majorant grid, delta tracking) and the estimator
   that uses it (path.c: grid_flight, grid_event, ratio tracking in
   shadow_transmittance; THEORY §13), against closed forms.

   The scenes put a density that varies along z only into a slab: nx = ny = 2
   samples of the same value make the density flat in x and y over the middle half
   of the bounds (pbrt-v4's lookup interpolates between sample centres and reads 0
   beyond the outermost ones), and the profile along z is the piecewise-linear
   curve through the sample centres (k + 1/2)/nz, falling to half the outermost
   samples at the bounds.  Its integral is then exact by trapezoids (`profile_int`),
   so the closed forms are:
   - transmittance: Le(lambda) exp(-sigma_a(lambda) D) through a chromatic absorbing
     slab of optical thickness D per unit sigma (a ramp and a two-density checker),
     per 10 nm band, with spectral MIS, single wavelengths and termination;
   - NEE: a point light over a white plane seen through a grid slab (ratio tracking
     on the shadow ray): E/pi with both transmittances;
   - furnace: a non-absorbing chromatic grid (albedo 1) inside a constant
     environment: every pixel sees the environment's radiance exactly;
   - emission: a constant-Le and a blackbody (temperature) grid, against the
     integral of sigma_a Le Tr along the ray (a quadrature of the same profile);
   - the sampler: chi-square of delta tracking's collision distances against
     sigma_t(t) exp(-tau(t)); ratio tracking's and delta tracking's transmittance
     against exp(-tau) per wavelength. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* The 1-D profile of samples d[0..n) at u in [0, 1] (the same curve a lookup
   follows along one axis), written independently of medium.c. */
static double profile(const double *d, int n, double u)
{
    double s = u * n - 0.5, f;
    int i;
    if (s < -1.0 || s > n) return 0.0;
    i = (int)floor(s);
    f = s - i;
    return (1.0 - f) * (i >= 0 && i < n ? d[i] : 0.0) + f * (i + 1 >= 0 && i + 1 < n ? d[i + 1] : 0.0);
}

/* Its integral over [0, 1], exact: trapezoids between the breakpoints. */
static double profile_int(const double *d, int n)
{
    double sum = 0.5 / n * 0.75 * (d[0] + d[n - 1]);
    int k;
    for (k = 0; k + 1 < n; k++) sum += (d[k] + d[k + 1]) / (2.0 * n);
    return sum;
}

/* "float density" [...] for nx = ny = 2 and the z profile d[0..n) */
static void grid_values(char *out, size_t cap, const char *name, const double *d, int n)
{
    size_t len;
    int k, q;
    snprintf(out, cap, "\"float %s\" [", name);
    for (k = 0; k < n; k++)
        for (q = 0; q < 4; q++) {
            len = strlen(out);
            snprintf(out + len, cap - len, " %.9g", d[k]);
        }
    len = strlen(out);
    snprintf(out + len, cap - len, " ]");
}

/* ---- transmittance through an absorbing grid slab 0 < z < 1 (camera above, a
   constant emitter below) */
static const char slab_fmt[] =
    "MediumInterface \"\" \"g\"\n"
    "LookAt 0 0 5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 10 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
    "\"string filename\" \"t.pfm\"\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
    "\"spectrum sigma_a\" [ 400 0.2 700 1.4 ] \"spectrum sigma_s\" [ 400 0 700 0 ] "
    "\"integer nx\" 2 \"integer ny\" 2 \"integer nz\" %d %s "
    "\"point3 p0\" [ -100 -100 0 ] \"point3 p1\" [ 100 100 1 ]\n"
    "MediumInterface \"\" \"\"\n"
    "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ] \"float scale\" 2\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -50 -50 -1  50 -50 -1  50 50 -1  -50 50 -1 ]\n";

/* integral over [lo, hi] of ybar Le_eff exp(-sigma_a(lambda) D) (lights.c's
   normalisation: Le_eff = 2 / sum ybar over 400..700 nm) */
static double slab_expect(double lo, double hi, double D)
{
    Spectrum one;
    double norm, sum = 0.0, h = 0.05, l;
    spec_const(&one, 1.0f);
    norm = luminance_sum(&one, LAMBDA_LO, LAMBDA_HI);
    for (l = lo + 0.5 * h; l < hi; l += h) {
        float xyz[3];
        double sa = 0.2 + 1.2 * (l - 400.0) / 300.0;
        cie_xyz((float)l, xyz);
        sum += h * xyz[1] * (2.0 / norm) * exp(-sa * D);
    }
    return sum;
}

static void slab_modes(T *t, const double *d, int n, const char *what)
{
    static char text[16384], vals[8192];
    static const char *const mode[3] = { "spectral MIS", "single wavelength", "terminate" };
    double D = profile_int(d, n);
    Scene s;
    int m, b;
    grid_values(vals, sizeof vals, "density", d, n);
    snprintf(text, sizeof text, slab_fmt, n, vals);
    if (!test_load_scene(t, &s, text)) return;
    for (m = 0; m < 3; m++)
        for (b = 0; b < 4; b++) {      /* three 10 nm bands, then 400-700 nm (the most chromatic) */
            RenderOptions o;
            Tiles tl;
            double lo = b < 3 ? 420.0 + 100.0 * b : 400.0, hi = b < 3 ? lo + 10.0 : 700.0, se, Y,
                   expect = slab_expect(lo, hi, D);
            render_options_default(&o);
            o.spp = test_scaled(128, 16);
            o.band_lo = (float)lo;
            o.band_hi = (float)hi;
            o.single_wavelength = m == 1;
            o.media_terminate = m == 2;
            if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
            Y = test_tile_y(&tl, 0, &se);
            if (!(fabs(Y - expect) < TEST_K_SIGMA * se + 2e-3 * expect)) {
                test_failf(t, __FILE__, __LINE__, "%s, %s, %g-%g nm: Y = %.6g +- %.2g, expected %.6g",
                           what, mode[m], lo, hi, Y, se, expect);
                scene_free(&s);
                return;
            }
        }
    scene_free(&s);
}

static void test_ramp(T *t)
{
    static const double ramp[8] = { 0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75 };
    slab_modes(t, ramp, 8, "a linear ramp");
}

static void test_checker(T *t)
{
    static const double chk[6] = { 0.2, 2.0, 0.2, 2.0, 0.2, 2.0 };
    slab_modes(t, chk, 6, "a checker of two densities");
}

/* ---- NEE through a grid: a point light at z = 4 over a white plane, the grid
   slab 0 < z < 3 with the profile d (the shadow ray and the camera ray cross it
   obliquely: optical depths scale with length / height) */
static double nee_D;   /* integral of sigma_t over the slab's height, 0.3 x 3 x profile_int */

static double slab_point_e(double x, double y)
{
    double r2 = 16.0 + x * x + y * y, r = sqrt(r2), rc = sqrt(25.0 + x * x + y * y);
    return 4.0 * exp(-nee_D * r / 4.0) / (r2 * r) * exp(-nee_D * rc / 5.0) / SPECNEE_PI;
}

static void test_nee(T *t)
{
    static const double d[5] = { 1.0, 3.0, 0.5, 2.0, 1.0 };
    static char text[16384], vals[4096];
    static const char fmt[] =
        "MediumInterface \"\" \"g\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 20 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "PixelFilter \"box\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
        "\"rgb sigma_a\" [ 0.3 0.3 0.3 ] \"rgb sigma_s\" [ 0 0 0 ] "
        "\"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 5 %s "
        "\"point3 p0\" [ -200 -200 0 ] \"point3 p1\" [ 200 200 3 ]\n"
        "MediumInterface \"\" \"\"\n"
        "LightSource \"point\" \"point3 from\" [ 0 0 4 ] \"spectrum I\" [ 400 1 700 1 ]\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 1 830 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -40 -40 0  40 -40 0  40 40 0  -40 40 0 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    double se, Y, expect = 0.0, a = 5.0 * tan(10.0 * SPECNEE_PI / 180.0);
    int i, j, n = 64;
    grid_values(vals, sizeof vals, "density", d, 5);
    snprintf(text, sizeof text, fmt, vals);
    nee_D = 0.3 * 3.0 * profile_int(d, 5);
    if (!test_load_scene(t, &s, text)) return;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            expect += slab_point_e(a * (2.0 * (i + 0.5) / n - 1.0), a * (2.0 * (j + 0.5) / n - 1.0));
    expect /= (double)n * n;
    render_options_default(&o);
    o.spp = test_scaled(16, 4);
    o.maxdepth = 1;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 3e-3 * expect,
          "a point light over a grid slab: Y = %.6g +- %.2g, expected E/pi = %.6g", Y, se, expect);
}

/* ---- NEE and BSDF sampling together through a grid: a white floor beside a
   4 x 4 lamp at height 2 (1 < x < 5, out of the camera's view), a strongly chromatic absorbing checker slab 0.5 < z <
   1.5 between them, the camera above looking down (maxdepth 1: direct light
   only, both techniques weighted by THEORY (24)).  The floor's radiance is
   (1/pi) integral over the lamp of Le cos cos' / r^2 exp(-sigma_a(lambda) D r / 2),
   seen through exp(-sigma_a(lambda) D r_c / 5), D the slab's integral of d. */
static void test_area_light(T *t)
{
    static const double d[6] = { 0.2, 2.0, 0.2, 2.0, 0.2, 2.0 };
    static char text[16384], vals[4096];
    static const char fmt[] =
        "MediumInterface \"\" \"g\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 5 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "PixelFilter \"box\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
        "\"spectrum sigma_a\" [ 400 0.1 700 3.0 ] \"spectrum sigma_s\" [ 400 0 700 0 ] "
        "\"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 6 %s "
        "\"point3 p0\" [ -200 -200 0.5 ] \"point3 p1\" [ 200 200 1.5 ]\n"
        "MediumInterface \"\" \"\"\n"
        "AttributeBegin\n"
        " AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ]\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ]\n"
        "  \"point3 P\" [ 1 -2 2  5 -2 2  5 2 2  1 2 2 ]\n"
        "AttributeEnd\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 1 830 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -40 -40 0  40 -40 0  40 40 0  -40 40 0 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    Spectrum one;
    double se, Y, expect = 0.0, D = profile_int(d, 6), a = 5.0 * tan(2.5 * SPECNEE_PI / 180.0), norm;
    int l, i, j, u, v;
    const int nf = 6, nl = 40;
    grid_values(vals, sizeof vals, "density", d, 6);
    snprintf(text, sizeof text, fmt, vals);
    if (!test_load_scene(t, &s, text)) return;
    spec_const(&one, 1.0f);
    norm = luminance_sum(&one, LAMBDA_LO, LAMBDA_HI);
    for (l = 400; l <= 700; l += 2) {
        float xyz[3];
        double sa = 0.1 + 2.9 * (l - 400.0) / 300.0, L = 0.0;
        cie_xyz((float)l, xyz);
        for (i = 0; i < nf; i++)
            for (j = 0; j < nf; j++) {
                double x = a * (2.0 * (i + 0.5) / nf - 1.0), y = a * (2.0 * (j + 0.5) / nf - 1.0), e = 0.0,
                       rc = sqrt(25.0 + x * x + y * y);
                for (u = 0; u < nl; u++)
                    for (v = 0; v < nl; v++) {
                        double lx = 1.0 + 4.0 * (u + 0.5) / nl - x, ly = 4.0 * (v + 0.5) / nl - 2.0 - y,
                               r2 = lx * lx + ly * ly + 4.0, r = sqrt(r2);
                        e += (16.0 / ((double)nl * nl)) * 4.0 / (r2 * r2) * exp(-sa * D * r / 2.0);
                    }
                L += e / SPECNEE_PI * exp(-sa * D * rc / 5.0) / ((double)nf * nf);
            }
        expect += (l == 400 || l == 700 ? 1.0 : 2.0) * xyz[1] * (1.0 / norm) * L;   /* trapezoids */
    }
    render_options_default(&o);
    o.spp = test_scaled(2048, 256);
    o.maxdepth = 1;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 3e-3 * expect,
          "a lamp over a floor through a chromatic grid: Y = %.6g +- %.2g, expected %.6g", Y, se, expect);
}

/* ---- furnace: albedo 1, chromatic sigma_s, a 24^3 grid of densities 0..4 (finer
   than the 16^3 majorant cells, so most tentative collisions are null) around the
   camera in a constant environment of Y = 1: every path carries exactly 1 (NEE
   and escaped rays through null collisions, both weighted by THEORY (24)) */
static void test_furnace(T *t)
{
    static char text[131072];
    static const char head[] =
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
        "\"spectrum sigma_a\" [ 400 0 700 0 ] \"spectrum sigma_s\" [ 400 4 550 0.3 700 2 ] "
        "\"float g\" 0.4 \"integer nx\" 24 \"integer ny\" 24 \"integer nz\" 24 \"float density\" [";
    static const char tail[] =
        " ] \"point3 p0\" [ -1 -1 -1 ] \"point3 p1\" [ 1 1 1 ]\n"
        "MediumInterface \"\" \"g\"\n"
        "Camera \"perspective\" \"float fov\" [ 60 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1000 ]\n"
        "WorldBegin\n"
        "LightSource \"infinite\" \"spectrum L\" [ 400 1 700 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    double se, Y;
    size_t len;
    int i;
    snprintf(text, sizeof text, "%s", head);
    len = strlen(text);
    for (i = 0; i < 24 * 24 * 24; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, " %d", (int)(hash_u64(37, (uint64_t)i) % 5));
    strncat(text, tail, sizeof text - strlen(text) - 1);
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(1024, 128);
    o.maxdepth = 1000;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - 1.0) < TEST_K_SIGMA * se + 1e-3, "albedo-1 grid furnace: Y = %.6g +- %.2g, expected 1",
          Y, se);
}

/* ---- emission: the camera above an emitting, absorbing slab 0 < z < 1 (nothing
   else lights it): L(lambda) = integral over z of sigma_a(lambda) d(z) Le(z, lambda)
   exp(-sigma_a(lambda) integral_z^1 d), with Le(z) = ls(z) Le (an "Le" spectrum)
   or ls(z) B(T(z)) (a temperature grid, absolute, peak 1) */
static double emission_expect(const double *d, const double *temp, int n, double le_norm)
{
    const int nz = 800;
    double sum = 0.0, one[16];
    int l, k;
    for (k = 0; k < n; k++) one[k] = 1.0;
    for (l = 400; l <= 700; l++) {             /* the film's 1 nm sums */
        float xyz[3];
        double sa = 0.5 + 1.5 * (l - 400.0) / 300.0, tau = 0.0, L = 0.0;
        cie_xyz((float)l, xyz);
        for (k = nz - 1; k >= 0; k--) {        /* from the top down */
            double u = (k + 0.5) / nz, dz = 1.0 / nz, dens = profile(d, n, u), le;
            if (temp) {
                double T = profile(temp, n, u);
                le = T > 100.0 ? profile(one, n, u) * blackbody_eval((float)T, (float)l) : 0.0;
            } else le = profile(one, n, u) * le_norm;
            tau += 0.5 * sa * dens * dz;
            L += sa * dens * le * exp(-tau) * dz;
            tau += 0.5 * sa * dens * dz;
        }
        sum += xyz[1] * L;
    }
    return sum;
}

static void emission_case(T *t, const char *le_param, const double *temp, const char *what)
{
    static const double d[4] = { 0.5, 2.0, 1.0, 3.0 };
    static const double ones[4] = { 1.0, 1.0, 1.0, 1.0 };
    static char text[16384], vals[4096], tv[4096], lv[4096];
    static const char fmt[] =
        "MediumInterface \"\" \"g\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 10 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
        "\"spectrum sigma_a\" [ 400 0.5 700 2.0 ] \"spectrum sigma_s\" [ 400 0 700 0 ] "
        "\"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 4 %s %s %s %s "
        "\"point3 p0\" [ -100 -100 0 ] \"point3 p1\" [ 100 100 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    Spectrum one;
    double se, Y, expect;
    grid_values(vals, sizeof vals, "density", d, 4);
    tv[0] = 0;
    if (temp) grid_values(tv, sizeof tv, "temperature", temp, 4);
    grid_values(lv, sizeof lv, "Lescale", ones, 4);     /* flat in x and y (the default is 1x1x1) */
    snprintf(text, sizeof text, fmt, vals, tv, lv, le_param);
    if (!test_load_scene(t, &s, text)) return;
    spec_const(&one, 1.0f);
    expect = emission_expect(d, temp, 4, 1.0 / luminance_sum(&one, LAMBDA_LO, LAMBDA_HI));
    render_options_default(&o);
    o.spp = test_scaled(16, 4);
    o.maxdepth = 5;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 3e-3 * expect, "%s: Y = %.6g +- %.2g, expected %.6g",
          what, Y, se, expect);
}

static void test_emission(T *t)
{
    static const double temp[4] = { 2500.0, 4000.0, 3000.0, 6000.0 };
    emission_case(t, "\"spectrum Le\" [ 400 1 700 1 ]", NULL, "a constant Le grid");
    if (t->failed) return;
    emission_case(t, "", temp, "a blackbody (temperature) grid");
}

/* ---- the sampler itself: medium_track on a ray along z through the z profile */
static const double track_d[6] = { 0.3, 1.5, 0.2, 2.5, 1.0, 0.6 };

static int track_medium(T *t, Scene *s)
{
    static char text[8192], vals[4096];
    grid_values(vals, sizeof vals, "density", track_d, 6);
    snprintf(text, sizeof text,
             "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
             "\"spectrum sigma_a\" [ 400 0.1 700 2.0 ] \"spectrum sigma_s\" [ 400 0.3 700 0.3 ] "
             "\"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 6 %s "
             "\"point3 p0\" [ -1 -1 0 ] \"point3 p1\" [ 1 1 2 ]\n"
             "Rotate 30 1 1 0\n"     /* no effect on the CTM after MakeNamedMedium */
             "WorldBegin\n", vals);
    return test_load_scene(t, s, text);
}

/* optical depth per unit sigma_t from z = 0 to z (world; the bounds are 2 high) */
static double track_tau(double z)
{
    const int n = 4000;
    double sum = 0.0;
    int k;
    for (k = 0; k < n; k++) sum += profile(track_d, 6, (k + 0.5) / n * z / 2.0) * z / n;
    return sum;
}

typedef struct { Rng *rng; double T[HERO_N]; int real; float t; } TrackCtx;

static int delta_fn(void *ctx, const MediumEvent *ev)
{
    TrackCtx *c = (TrackCtx *)ctx;
    if (rng_float(c->rng) * ev->smaj[0] < ev->mp.sa[0] + ev->mp.ss[0]) {
        c->real = 1;
        c->t = ev->t;
        return 0;
    }
    return 1;
}

static int ratio_fn(void *ctx, const MediumEvent *ev)
{
    TrackCtx *c = (TrackCtx *)ctx;
    int j;
    for (j = 0; j < HERO_N; j++)
        c->T[j] *= ev->tm[j] * (ev->smaj[j] - ev->mp.sa[j] - ev->mp.ss[j]) / ev->smaj[0];
    return 1;
}

/* chi-square of the first real collision's distance (20 bins over the 2 units,
   one more for passing) against sigma_t(t) exp(-tau(t)) */
static void test_flight_chi2(T *t)
{
    Scene s;
    Rng rng;
    Ray ray;
    double obs[21] = { 0 }, ex[21], st, tm[HERO_N];
    const float lam[HERO_N] = { 450.0f, 520.0f, 600.0f, 680.0f };
    int i, n = test_scaled(200000, 50000), b;
    if (!track_medium(t, &s)) return;
    st = medium_sigma_t(&s.media[0], lam[0]);
    ray.o = v3(0.1f, -0.2f, -1.0f);      /* from below the bounds, straight up through them */
    ray.d = v3(0.0f, 0.0f, 1.0f);
    rng_seed(&rng, 37, 1);
    for (i = 0; i < n; i++) {
        TrackCtx c;
        float u = rng_float(&rng);
        c.rng = &rng;
        c.real = 0;
        if (medium_track(&s.media[0], ray, 4.0f, lam, 0xFu, u, &rng, delta_fn, &c, tm)) {
            b = (int)((c.t - 1.0f) / 0.1f);
            obs[b < 0 ? 0 : b > 19 ? 19 : b] += 1.0;
        } else obs[20] += 1.0;
    }
    for (b = 0; b < 20; b++) ex[b] = n * (exp(-st * track_tau(0.1 * b)) - exp(-st * track_tau(0.1 * (b + 1))));
    ex[20] = n * exp(-st * track_tau(2.0));
    scene_free(&s);
    CHECK_CHI2(t, obs, ex, 21, 1, NULL, "delta tracking's collision distances");
}

typedef struct { float t[64]; int n; } TrackLog;

static int log_fn(void *ctx, const MediumEvent *ev)
{
    TrackLog *c = (TrackLog *)ctx;
    if (c->n < 64) c->t[c->n] = ev->t;
    c->n++;
    return 1;
}

/* A cloud's majorant is 1 in each of its 16^3 cells: free flight carries the
   optical depth left at a cell's end into the next (THEORY section 13), so the
   tentative collisions along a diagonal through the cells lie where a single
   cell of majorant sigma_t would put them, t_k = (tau_0 + ... + tau_k) / sigma_t
   with tau_0 = -ln(1 - u) and each later tau_i = -ln(1 - rng) drawn at a
   collision; a fresh number in each cell the ray enters puts them elsewhere. */
static void test_track_carries_depth(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "MakeNamedMedium \"c\" \"string type\" \"cloud\" \"rgb sigma_a\" [ 0.5 0.5 0.5 ] "
        "\"rgb sigma_s\" [ 1 1 1 ]\n";
    const float lam[HERO_N] = { 550.0f, 450.0f, 500.0f, 650.0f };
    Scene s;
    Rng rng, copy;
    Ray ray;
    double st, tm[HERO_N], worst = 0.0;
    int i, k, bad = 0, events = 0;
    if (!test_load_scene(t, &s, text)) return;
    st = medium_sigma_t(&s.media[0], lam[0]);
    ray.o = v3(0.02f, 0.03f, 0.01f);
    ray.d = v3_norm(v3(1.0f, 0.9f, 1.1f));
    rng_seed(&rng, 39, 0);
    for (i = 0; i < 3000; i++) {
        TrackLog c;
        float u = rng_float(&rng);
        double tau = -log1p(-(double)u);
        c.n = 0;
        copy = rng;
        medium_track(&s.media[0], ray, 4.0f, lam, 0xFu, u, &rng, log_fn, &c, tm);
        for (k = 0; k < c.n && k < 64; k++) {
            double want = tau / st, err = fabs(c.t[k] - want);
            if (err > worst) worst = err;
            if (err > 1e-5 && bad++ < 3)
                CHECK(t, 0, "track %d: collision %d at %.7g, expected %.7g", i, k, c.t[k], want);
            tau += -log1p(-(double)rng_float(&copy));
        }
        if (c.n < 64 && tau / st < 1.55 && bad++ < 3)   /* the ray leaves the cube at 1.564 */
            CHECK(t, 0, "track %d: no collision at %.7g", i, tau / st);
        events += c.n;
    }
    CHECK(t, bad == 0, "%d collisions off the single-cell stream (worst %.3g)", bad, worst);
    CHECK(t, events > 3000, "only %d collisions", events);
    scene_free(&s);
}

/* ratio tracking's Tr_j (every lane from the hero's collisions) and delta
   tracking's pass fraction (the hero) against exp(-sigma_t(lambda_j) tau) */
static void test_ratio_vs_delta(T *t)
{
    Scene s;
    Rng rng;
    Ray ray;
    const float lam[HERO_N] = { 420.0f, 680.0f, 520.0f, 600.0f };   /* the hero: the thinnest */
    double sum[HERO_N] = { 0 }, sum2[HERO_N] = { 0 }, pass = 0.0, tm[HERO_N], tau = track_tau(2.0);
    int i, j, n = test_scaled(100000, 20000);
    if (!track_medium(t, &s)) return;
    ray.o = v3(0.3f, 0.1f, -1.0f);
    ray.d = v3(0.0f, 0.0f, 2.0f);        /* not unit: distances are still world lengths */
    rng_seed(&rng, 37, 2);
    for (i = 0; i < n; i++) {
        TrackCtx c;
        float u = rng_float(&rng);
        for (j = 0; j < HERO_N; j++) c.T[j] = 1.0;
        c.rng = &rng;
        medium_track(&s.media[0], ray, 2.0f, lam, 0xFu, u, &rng, ratio_fn, &c, tm);
        for (j = 0; j < HERO_N; j++) {
            double v = c.T[j] * tm[j];
            sum[j] += v;
            sum2[j] += v * v;
        }
        u = rng_float(&rng);
        c.real = 0;
        if (!medium_track(&s.media[0], ray, 2.0f, lam, 0xFu, u, &rng, delta_fn, &c, tm)) pass += 1.0;
    }
    for (j = 0; j < HERO_N; j++) {
        double m = sum[j] / n, se = sqrt(fmax(sum2[j] / n - m * m, 0.0) / n),
               expect = exp(-medium_sigma_t(&s.media[0], lam[j]) * tau);
        CHECK(t, fabs(m - expect) < TEST_K_SIGMA * se + 1e-4, "ratio tracking at %g nm: %.6g +- %.2g, "
              "expected %.6g", lam[j], m, se, expect);
    }
    {
        double p = pass / n, expect = exp(-medium_sigma_t(&s.media[0], lam[0]) * tau),
               se = sqrt(expect * (1.0 - expect) / n);
        CHECK(t, fabs(p - expect) < TEST_K_SIGMA * se, "delta tracking passes with %.6g, expected %.6g",
              p, expect);
    }
    scene_free(&s);
}

/* ---- lookups: pbrt-v4's convention, and the majorants bound every lookup */
static void test_lookup(T *t)
{
    static float v[2] = { 1.0f, 3.0f };
    static const struct { float u; double want; } c[] = {
        { 0.25f, 1.0 }, { 0.75f, 3.0 }, { 0.5f, 2.0 }, { 0.0f, 0.5 }, { 1.0f, 1.5 }, { -3.0f, 0.0 },
        { 1.25f, 0.0 }
    };
    MediumGrid g;
    Scene s;
    Rng rng;
    size_t i;
    int k;
    g.nx = 2; g.ny = 1; g.nz = 1; g.v = v;
    for (i = 0; i < sizeof c / sizeof c[0]; i++) {
        double got = medium_grid_lookup(&g, v3(c[i].u, 0.5f, 0.5f));
        CHECK(t, fabs(got - c[i].want) < 1e-6, "lookup at x = %g: %g, expected %g", c[i].u, got, c[i].want);
    }
    if (!track_medium(t, &s)) return;
    rng_seed(&rng, 37, 3);
    for (k = 0; k < 100000; k++) {
        Vec3 u = rng_vec3(&rng);
        int cx = (int)(u.x * MAJORANT_RES), cy = (int)(u.y * MAJORANT_RES), cz = (int)(u.z * MAJORANT_RES);
        double d = medium_grid_lookup(&s.media[0].density, u),
               mx = s.media[0].majorant[(cz * MAJORANT_RES + cy) * MAJORANT_RES + cx];
        if (!(d <= mx * (1.0 + 1e-6))) {
            test_failf(t, __FILE__, __LINE__, "density %g above its cell's majorant %g", d, mx);
            break;
        }
    }
    scene_free(&s);
}

/* ---- 1 and 2 threads give the same bits (the tracking's streams are keyed by
   the camera sample) */
static void test_threads(T *t)
{
    static char text[16384];
    static const char fmt[] =
        "LookAt 0 0 4  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 40 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] "
        "\"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
        "\"spectrum sigma_a\" [ 400 0.3 700 0.1 ] \"spectrum sigma_s\" [ 400 2 700 0.5 ] "
        "\"spectrum Le\" [ 400 0 550 1 700 0 ] \"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 2 "
        "\"float density\" [ 0 1 2 3 4 3 2 1 ] \"point3 p0\" [ -1 -1 -1 ] \"point3 p1\" [ 1 1 1 ]\n"
        "LightSource \"point\" \"point3 from\" [ 0 3 0 ] \"spectrum I\" [ 400 1 700 1 ] \"float scale\" 5\n"
        "AttributeBegin\n Material \"interface\"\n MediumInterface \"g\" \"\"\n"
        " Shape \"sphere\" \"float radius\" 1.2\nAttributeEnd\n";
    Scene s;
    RenderOptions o;
    Image a, b;
    RenderStats st;
    Error e;
    snprintf(text, sizeof text, "%s", fmt);
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = 8;
    o.threads = 1;
    CHECK(t, render(&s, &o, &a, &st, &e), "%s", e.msg);
    o.threads = 2;
    CHECK(t, render(&s, &o, &b, &st, &e), "%s", e.msg);
    scene_free(&s);
    CHECK(t, memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * a.h) == 0, "1 and 2 threads differ");
    CHECK(t, st.dims_reused == 0, "%ld sampler dimensions reused", st.dims_reused);
    img_free(&a);
    img_free(&b);
}

/* ---- the format's errors, each at its file:line */
static void test_bad_input(T *t)
{
#define G "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"uniformgrid\" "
    if (!test_load_fails(t, G "\n", "m.pbrt:2:", "\"float density\" is required")) return;
    if (!test_load_fails(t, G "\"integer nx\" 2\n \"float density\" [ 1 2 3 ]\n", "m.pbrt:3:",
                         "3 \"density\" values; expected nx*ny*nz = 2*1*1 = 2")) return;
    if (!test_load_fails(t, G "\"float density\" [ -1 ]\n", "m.pbrt:2:", "\"density\" value 0 is -1; need a finite value >= 0")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1e35 ]\n", "m.pbrt:2:", "need a finite value")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1 ] \"integer nz\" 0\n", "m.pbrt:2:", "\"integer nz\" 0 must lie in 1..4096")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1 ]\n \"point3 p1\" [ 1 0 1 ]\n", "m.pbrt:3:",
                         "need finite p0 < p1 on every axis")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1 ] \"point3 p0\" [ 0 0 ]\n", "m.pbrt:2:", "needs 3 values")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1 ] \"float temperature\" [ 1000 ] \"rgb Le\" [ 1 1 1 ]\n",
                         "m.pbrt:2:", "both \"Le\" and \"temperature\"")) return;
    if (!test_load_fails(t, G "\"integer nx\" 2 \"float density\" [ 1 1 ] \"float temperature\" [ 1 ]\n", "m.pbrt:2:",
                         "1 \"temperature\" values; expected nx*ny*nz")) return;
    if (!test_load_fails(t, G "\"integer nx\" 2 \"float density\" [ 1 1 ] \"float Lescale\" [ 1 ]\n", "m.pbrt:2:",
                         "1 \"Lescale\" values; expected nx*ny*nz")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1 ] \"float g\" 1\n", "m.pbrt:2:", "(-1, 1)")) return;
    if (!test_load_fails(t, G "\"float density\" [ 1 ] \"string preset\" \"Skin1\"\n", "m.pbrt:2:", "preset")) return;
    if (!test_load_fails(t, "WorldBegin\nMakeNamedMedium \"s\" \"string type\" \"nanovdb\"\n", "m.pbrt:2:",
                         "\"string filename\" is required")) return;
#undef G
}

/* A medium made before the Camera directive.  pbrt-v4 places it by its render
   space (the world moved so that the camera sits at the origin), so a box made
   there around the origin lies around the camera (scene.c media_before_camera).
   A unit box of density 1 (one cell; pbrt-v4's cell-centred lookup fades it to 0.5
   at the faces) and sigma_a 1, the camera at (0, 0, 4) looking at the origin under
   a white sky.  Frozen pbrt-v4 5f7a6068 means (Sampler "independent", seed 0):
   made before LookAt, 0.6887282 (8192 spp: the camera at the box's centre, tau
   about 0.375); made after LookAt, 0.9974972 (64 spp: the box lands behind the
   camera, the sky unoccluded).  Placed in the world, the first would be 0.498. */
static void test_before_camera(T *t)
{
    static const char fmt[] =
        "%s"
        "MakeNamedMedium \"box\" \"string type\" \"uniformgrid\" \"rgb sigma_a\" [ 1 1 1 ]\n"
        "  \"rgb sigma_s\" [ 0 0 0 ] \"integer nx\" 1 \"integer ny\" 1 \"integer nz\" 1\n"
        "  \"float density\" [ 1 ] \"point3 p0\" [ -0.5 -0.5 -0.5 ] \"point3 p1\" [ 0.5 0.5 0.5 ]\n"
        "MediumInterface \"\" \"box\"\n"
        "%s"
        "Camera \"perspective\" \"float fov\" 2\n"
        "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4\n"
        "Integrator \"volpath\" \"integer maxdepth\" 5\n"
        "WorldBegin\nLightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n";
    static const char look[] = "LookAt 0 0 4  0 0 0  0 1 0\n";
    static const double pbrt[2] = { 0.6887282, 0.9974972 };
    int k;
    for (k = 0; k < 2; k++) {
        char text[2048];
        Scene s;
        RenderOptions o;
        Tiles tl;
        double se, Y;
        Vec3 c;
        snprintf(text, sizeof text, fmt, k == 0 ? "" : look, k == 0 ? look : "");
        if (!test_load_scene(t, &s, text)) return;
        /* k = 0: the camera's position (0, 0, 4) is the box's centre */
        c = xf_point(&s.media[0].medium_from_world, v3(0.0f, 0.0f, 4.0f));
        if (k == 0 && !(fabsf(c.x) < 1e-6f && fabsf(c.y) < 1e-6f && fabsf(c.z) < 1e-6f)) {
            test_failf(t, __FILE__, __LINE__, "the camera lies at (%g, %g, %g) in the medium's "
                       "frame, expected its origin", c.x, c.y, c.z);
            scene_free(&s);
            return;
        }
        render_options_default(&o);
        o.spp = test_scaled(64, 16);
        if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
        Y = test_tile_y(&tl, 0, &se);
        scene_free(&s);
        CHECK(t, fabs(Y - pbrt[k]) < TEST_K_SIGMA * se + 0.01 * pbrt[k],
              "medium made %s LookAt: Y = %.6g +- %.2g, pbrt-v4 %.7g", k == 0 ? "before" : "after",
              Y, se, pbrt[k]);
    }
}

/* ---- what loads: the parameters' values and the medium's frame */
static void test_format(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "Translate 1 2 3\n"
        "MakeNamedMedium \"fire\" \"string type\" \"uniformgrid\" \"integer nx\" 2 "
        "\"float density\" [ 1 3 ] \"float temperature\" [ 500 1500 ] \"float temperaturecutoff\" 100 "
        "\"float temperaturescale\" 2 \"float scale\" 2 \"rgb sigma_a\" [ 1 1 1 ] \"rgb sigma_s\" [ 0 0 0 ] "
        "\"point3 p0\" [ 0 0 0 ] \"point3 p1\" [ 2 1 1 ]\n";
    Scene s;
    MediumPoint mp;
    const float lam[HERO_N] = { 550.0f, 550.0f, 550.0f, 550.0f };
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_media == 1 && s.media[0].type == MEDIUM_UNIFORMGRID, "not a uniformgrid");
    /* world (2.5, 2.5, 3.5) = medium (1.5, 0.5, 0.5): x = 0.75 of the bounds, sample 1 */
    medium_point(&s.media[0], v3(2.5f, 2.5f, 3.5f), lam, 1u, &mp);
    CHECK(t, fabs(mp.sa[0] / medium_sigma_a(&s.media[0], 550.0f) - 3.0) < 1e-5, "density %g, expected 3",
          mp.sa[0] / medium_sigma_a(&s.media[0], 550.0f));
    CHECK(t, fabs(medium_sigma_a(&s.media[0], 550.0f) - 2.0) < 0.05, "sigma_a %g, expected scale 2 x 1",
          medium_sigma_a(&s.media[0], 550.0f));
    /* T = (1500 - 100) x 2 = 2800 K; Lescale pbrt-v4's default, a 1x1x1 grid of 1:
       its one sample sits at the centre, so at x = 0.75 it reads 0.75 */
    CHECK(t, fabs(mp.le[0] - 0.75 * blackbody_eval(2800.0f, 550.0f)) < 1e-5,
          "Le %g, expected 0.75 B(2800 K) = %g", mp.le[0], 0.75 * blackbody_eval(2800.0f, 550.0f));
    scene_free(&s);
}

/* ---- against pbrt-v4: the luminance of the whole image and of its quadrants
   (top-left, top-right, bottom-left, bottom-right) for tests/data/grid/ramp.pbrt
   (a rotated 8^3 density ramp of chromatic smoke under an area light, over a
   floor) and flame.pbrt (an 8^3 temperature grid, the only light, with
   temperaturecutoff and temperaturescale).  Frozen from pbrt-v4 (mmp/pbrt-v4
   5f7a6068, `pbrt --spp 4096 --seed S` for S = 1, 2 on these files, the mean of
   the two; they differ by at most 0.05 % (ramp) and 0.6 % (flame) per value).
   specnee at 1024 and 4096 spp: ramp within 0.2 % everywhere, flame within 0.7 %
   (tools/pbrt_compare.sh on 96 x 96 versions: ratios 0.9995 and 0.9931).
   rgbsmoke.pbrt: a 4^3 rgbgrid, chromatic in space (sigma_a from red- to
   blue-absorbing along x, random sigma_s, an emissive rgb Le checker), frozen the
   same way (seeds 1, 2: within 0.4 % per value); specnee at 2048 spp within
   0.25 % of it everywhere (image 0.99989).  cloud.pbrt: pbrt-v4's procedural
   cloud (density 1.2, wispiness 1.5, frequency 4, chromatic sigma_a and sigma_s,
   g 0.6) under an area light and a dim sky, frozen the same way (seeds 1, 2:
   within 0.3 %); specnee at 1024 spp: image 1.0018, quadrants within 0.6 %. */
static void test_against_pbrt(T *t)
{
    static const char *const files[4] = { "tests/data/grid/ramp.pbrt", "tests/data/grid/flame.pbrt",
                                           "tests/data/grid/rgbsmoke.pbrt", "tests/data/grid/cloud.pbrt" };
    static const double pbrt_y[4][5] = {
        { 0.0721728, 0.0901002, 0.0680942, 0.0463952, 0.0841016 },
        { 0.0748587, 0.0135396, 0.0136273, 0.136353, 0.135915 },
        { 4.11874, 3.8083, 3.19728, 5.30156, 4.16782 },
        { 0.307388, 0.225366, 0.23421, 0.387634, 0.382343 }
    };
    int f;
    for (f = 0; f < 4; f++) {
        Scene s;
        RenderOptions o;
        Error e;
        CHECK(t, scene_load(&s, files[f], &e), "%s", e.msg);
        render_options_default(&o);
        o.spp = test_scaled(64, 16);
        o.maxdepth = 20;
        test_quadrants_against_pbrt(t, &s, &o, pbrt_y[f], files[f]);
        scene_free(&s);
        if (t->failed) return;
    }
}

/* ---- scenes/smoke.pbrt against pbrt-v4: the shipped coloured smoke (a 16^3
   rgbgrid, sigma_t 4 x larger in blue than in red, albedo 0.85, an area light and
   a dim sky over a floor; tools/smoke_scene.sh) rendered at 32 x 32 (the film
   override keeps the field of view, as `sh tools/smoke_scene.sh --res 32` does).
   Frozen from pbrt-v4 (mmp/pbrt-v4 5f7a6068, `pbrt --spp 4096 --seed S` on the
   file that command writes, S = 1, 2, the mean of the two; they differ by at most
   0.2 % per value); specnee at 4096 spp (seed 5) is within 0.06 % of them everywhere
   (image 0.99995).  The luminance of the image and of its quadrants (top-left,
   top-right, bottom-left, bottom-right). */
static void test_smoke_scene(T *t)
{
    static const double pbrt_y[5] = { 0.179166, 0.100301, 0.104896, 0.258380, 0.253087 };
    Scene s;
    RenderOptions o;
    Error e;
    CHECK(t, scene_load(&s, "scenes/smoke.pbrt", &e), "%s", e.msg);
    s.settings.xres = s.settings.yres = 32;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    o.maxdepth = s.settings.maxdepth;
    test_quadrants_against_pbrt(t, &s, &o, pbrt_y, "smoke.pbrt");
    scene_free(&s);
}


/* ==== rgbgrid: sigma_a, sigma_s and Le as grids of rgb triples ====
   Each sample's spectrum is computed here with spec_from_rgb (the full fit, no
   coefficient table: independent of medium.c's per-sample coefficients) and the
   closed forms interpolate those spectra's values. */

/* "rgb NAME" [ ... ] of nx = ny = 2 and the z profile of triples rgb[0..n) */
static void rgb_values(char *out, size_t cap, const char *name, const double (*rgb)[3], int n)
{
    size_t len;
    int k, q;
    snprintf(out, cap, "\"rgb %s\" [", name);
    for (k = 0; k < n; k++)
        for (q = 0; q < 4; q++) {
            len = strlen(out);
            snprintf(out + len, cap - len, " %.9g %.9g %.9g", rgb[k][0], rgb[k][1], rgb[k][2]);
        }
    len = strlen(out);
    snprintf(out + len, cap - len, " ]");
}

/* sample spectra of rgb triples (2: unbounded, 1: an illuminant, with D65) */
static int rgb_spectra(T *t, const double (*rgb)[3], int n, int kind, Spectrum *out)
{
    Error e;
    int k;
    for (k = 0; k < n; k++) {
        const float c[3] = { (float)rgb[k][0], (float)rgb[k][1], (float)rgb[k][2] };
        if (!spec_from_rgb(&out[k], c, kind, &e, "t", 1)) { test_failf(t, __FILE__, __LINE__, "%s", e.msg); return 0; }
    }
    return 1;
}

/* A constant rgbgrid is the homogeneous medium of the same rgb; a two-sample
   checker interpolates the samples' spectra (not their rgb); the majorant grid
   bounds sigma_t at every wavelength, and a constant grid's majorant is pbrt-v4's
   scale x (max_lambda sigma_a + max_lambda sigma_s). */
static void test_rgb_lookup(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "MakeNamedMedium \"h\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ 0.2 0.5 0.9 ] "
        "\"rgb sigma_s\" [ 0.1 1.5 0.2 ] \"float scale\" 2\n"
        "MakeNamedMedium \"c\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"float scale\" 2 "
        "\"rgb sigma_a\" [ 0.2 0.5 0.9  0.2 0.5 0.9 ] \"rgb sigma_s\" [ 0.1 1.5 0.2  0.1 1.5 0.2 ]\n"
        "MakeNamedMedium \"k\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 2 "
        "\"rgb sigma_a\" [ 0.9 0.1 0.1  0.1 0.2 3  0.9 0.1 0.1  0.1 0.2 3  0.9 0.1 0.1  0.1 0.2 3  "
        "0.9 0.1 0.1  0.1 0.2 3 ] \"point3 p0\" [ 0 0 0 ] \"point3 p1\" [ 2 2 2 ]\n";
    static const double chk[2][3] = { { 0.9, 0.1, 0.1 }, { 0.1, 0.2, 3.0 } };
    Scene s;
    Spectrum sp[2];
    MediumPoint mp;
    Rng rng;
    int i, j, l;
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_media == 3 && s.media[1].type == MEDIUM_RGBGRID && s.media[1].chromatic, "not a chromatic rgbgrid");
    for (l = 360; l <= 820; l += 10) {
        const float lam[HERO_N] = { (float)l, (float)l + 3.5f, 500.0f, 700.0f };
        medium_point(&s.media[1], v3(0.5f, 0.5f, 0.5f), lam, 15u, &mp);
        for (j = 0; j < 2; j++) {
            double ha = medium_sigma_a(&s.media[0], lam[j]), hs = medium_sigma_s(&s.media[0], lam[j]);
            CHECK(t, fabs(mp.sa[j] - ha) < 1e-3 * ha + 1e-6 && fabs(mp.ss[j] - hs) < 1e-3 * hs + 1e-6,
                  "%g nm: rgbgrid sigma_a %g sigma_s %g, homogeneous %g %g", lam[j], mp.sa[j], mp.ss[j], ha, hs);
        }
    }
    rng_seed(&rng, 37, 0);
    for (i = 0; i < 2000; i++) {          /* the majorant bounds sigma_t everywhere */
        const Medium *m = &s.media[1 + (i & 1)];
        Vec3 p = v3(2.0f * rng_float(&rng), 2.0f * rng_float(&rng), 2.0f * rng_float(&rng)), u;
        const float lam[HERO_N] = { 360.0f + 470.0f * rng_float(&rng), 400.0f, 600.0f, 830.0f };
        int c[3];
        if (m == &s.media[1]) p = v3_mul(p, 0.5f);
        u = v3((p.x - m->p0.x) / (m->p1.x - m->p0.x), (p.y - m->p0.y) / (m->p1.y - m->p0.y),
               (p.z - m->p0.z) / (m->p1.z - m->p0.z));
        c[0] = (int)(u.x * MAJORANT_RES); c[1] = (int)(u.y * MAJORANT_RES); c[2] = (int)(u.z * MAJORANT_RES);
        for (j = 0; j < 3; j++) if (c[j] > MAJORANT_RES - 1) c[j] = MAJORANT_RES - 1;
        medium_point(m, p, lam, 15u, &mp);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, mp.sa[j] + mp.ss[j] <= m->majorant[(c[2] * MAJORANT_RES + c[1]) * MAJORANT_RES + c[0]] * 1.0001,
                  "sigma_t %g above the majorant %g", mp.sa[j] + mp.ss[j],
                  m->majorant[(c[2] * MAJORANT_RES + c[1]) * MAJORANT_RES + c[0]]);
    }
    {   /* a constant grid's majorant: pbrt-v4's, from the homogeneous spectra's maxima
           (sigma_s green: its maximum lies inside the range) */
        double ma = 0.0, ms = 0.0;
        for (l = SPEC_MIN; l <= SPEC_MAX; l++) {
            ma = fmax(ma, medium_sigma_a(&s.media[0], (float)l));
            ms = fmax(ms, medium_sigma_s(&s.media[0], (float)l));
        }
        CHECK(t, fabs(s.media[1].majorant[0] - (ma + ms)) < 1e-3 * (ma + ms), "majorant %g, expected %g",
              s.media[1].majorant[0], ma + ms);
    }
    if (!rgb_spectra(t, chk, 2, 2, sp)) { scene_free(&s); return; }
    for (l = 380; l <= 780; l += 25) {    /* the checker: halfway, the mean of the two spectra */
        const float lam[HERO_N] = { (float)l, (float)l, (float)l, (float)l };
        double want[3] = { spec_eval(&sp[0], (float)l), 0.5 * (spec_eval(&sp[0], (float)l) + spec_eval(&sp[1], (float)l)),
                           spec_eval(&sp[1], (float)l) };
        for (i = 0; i < 3; i++) {
            medium_point(&s.media[2], v3(0.5f + 0.5f * i, 1.0f, 1.0f), lam, 1u, &mp);
            CHECK(t, fabs(mp.sa[0] - want[i]) < 2e-3 * want[i] + 1e-5, "checker at x = %g, %d nm: %g, expected %g",
                  0.5 + 0.5 * i, l, mp.sa[0], want[i]);
            CHECK(t, fabs(mp.ss[0] - 1.0) < 1e-6, "absent sigma_s reads %g, expected 1", mp.ss[0]);
        }
    }
    scene_free(&s);
}

/* ---- per-band transmittance through an absorbing rgbgrid slab 0 < z < 1 whose
   z profile alternates two rgb triples (a chromatic checker), spectral MIS and
   termination: Y = integral of ybar Le_eff exp(-D(lambda)), D the profile
   integral of the samples' spectra at lambda */
static void test_rgb_transmittance(T *t)
{
    static const double chk[4][3] = { { 0.9, 0.1, 0.1 }, { 0.1, 0.3, 1.6 }, { 0.9, 0.1, 0.1 }, { 0.1, 0.3, 1.6 } };
    static const double zero[4][3] = { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } };
    static char text[16384], va[4096], vs[4096];
    static const char fmt[] =
        "MediumInterface \"\" \"g\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 10 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 4 "
        "%s %s \"point3 p0\" [ -100 -100 0 ] \"point3 p1\" [ 100 100 1 ]\n"
        "MediumInterface \"\" \"\"\n"
        "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ] \"float scale\" 2\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -50 -50 -1  50 -50 -1  50 50 -1  -50 50 -1 ]\n";
    Spectrum sp[4], one;
    Scene s;
    int m, b;
    double norm;
    rgb_values(va, sizeof va, "sigma_a", chk, 4);
    rgb_values(vs, sizeof vs, "sigma_s", zero, 4);
    snprintf(text, sizeof text, fmt, va, vs);
    if (!rgb_spectra(t, chk, 4, 2, sp) || !test_load_scene(t, &s, text)) return;
    spec_const(&one, 1.0f);
    norm = luminance_sum(&one, LAMBDA_LO, LAMBDA_HI);
    for (m = 0; m < 2; m++)
        for (b = 0; b < 4; b++) {
            RenderOptions o;
            Tiles tl;
            double lo = b < 3 ? 420.0 + 100.0 * b : 400.0, hi = b < 3 ? lo + 10.0 : 700.0, se, Y, expect = 0.0, l;
            for (l = lo + 0.025; l < hi; l += 0.05) {
                float xyz[3];
                double d[4];
                int k;
                for (k = 0; k < 4; k++) d[k] = spec_eval(&sp[k], (float)l);
                cie_xyz((float)l, xyz);
                expect += 0.05 * xyz[1] * (2.0 / norm) * exp(-profile_int(d, 4));
            }
            render_options_default(&o);
            o.spp = test_scaled(128, 16);
            o.band_lo = (float)lo;
            o.band_hi = (float)hi;
            o.media_terminate = m == 1;
            if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
            Y = test_tile_y(&tl, 0, &se);
            if (!(fabs(Y - expect) < TEST_K_SIGMA * se + 2e-3 * expect)) {
                test_failf(t, __FILE__, __LINE__, "rgb checker, %s, %g-%g nm: Y = %.6g +- %.2g, expected %.6g",
                           m ? "terminate" : "spectral MIS", lo, hi, Y, se, expect);
                scene_free(&s);
                return;
            }
        }
    scene_free(&s);
}

/* ---- furnace: a non-absorbing rgbgrid of hashed chromatic sigma_s (albedo 1)
   inside a constant environment: every pixel sees the environment exactly */
static void test_rgb_furnace(T *t)
{
    static char text[65536];
    static const char head[] =
        "MakeNamedMedium \"g\" \"string type\" \"rgbgrid\" \"float g\" -0.3 "
        "\"integer nx\" 8 \"integer ny\" 8 \"integer nz\" 8 \"rgb sigma_a\" [";
    static const char tail[] =
        " ] \"point3 p0\" [ -1 -1 -1 ] \"point3 p1\" [ 1 1 1 ]\n"
        "MediumInterface \"\" \"g\"\n"
        "Camera \"perspective\" \"float fov\" [ 60 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1000 ]\n"
        "WorldBegin\n"
        "LightSource \"infinite\" \"spectrum L\" [ 400 1 700 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    double se, Y;
    size_t len;
    int i;
    snprintf(text, sizeof text, "%s", head);
    len = strlen(text);
    for (i = 0; i < 512; i++) len += (size_t)snprintf(text + len, sizeof text - len, " 0 0 0");
    len += (size_t)snprintf(text + len, sizeof text - len, " ] \"rgb sigma_s\" [");
    for (i = 0; i < 3 * 512; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, " %g", 0.5 * (double)(hash_u64(41, (uint64_t)i) % 9));
    strncat(text, tail, sizeof text - strlen(text) - 1);
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(1024, 128);
    o.maxdepth = 1000;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - 1.0) < TEST_K_SIGMA * se + 1e-3, "albedo-1 rgbgrid furnace: Y = %.6g +- %.2g, expected 1", Y, se);
}

/* ---- emission: an emitting, absorbing rgbgrid slab 0 < z < 1 seen from above:
   L(lambda) = integral over z of sigma_a(z, lambda) Le(z, lambda) exp(-tau), Le the
   rgb illuminant spectrum (with D65) of the Le samples times Lescale, in
   pbrt-v4's units: D65 scaled to a luminance of 1, that is by CIE_Y_integral
   (106.856895, pbrt-v4's) over the sum of ybar D65 over 400..700 nm, the film's
   sum; not divided by Le's own luminance as lights are */
static void test_rgb_emission(T *t)
{
    static const double sa[4][3] = { { 0.5, 1.0, 2.0 }, { 2.0, 0.8, 0.3 }, { 1.0, 1.0, 1.0 }, { 3.0, 0.5, 0.2 } };
    static const double le[4][3] = { { 1.0, 0.5, 0.2 }, { 1.0, 0.5, 0.2 }, { 1.0, 0.5, 0.2 }, { 1.0, 0.5, 0.2 } };
    static const double zero[4][3] = { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } };
    static char text[16384], va[4096], vs[4096], vl[4096];
    static const char fmt[] =
        "MediumInterface \"\" \"g\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 10 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"integer ny\" 2 \"integer nz\" 4 "
        "%s %s %s \"float Lescale\" 3 \"point3 p0\" [ -100 -100 0 ] \"point3 p1\" [ 100 100 1 ]\n";
    Spectrum sp[4], lsp[1], d65;
    Scene s;
    RenderOptions o;
    Tiles tl;
    double se, Y, expect = 0.0, norm;
    int l, k;
    rgb_values(va, sizeof va, "sigma_a", sa, 4);
    rgb_values(vs, sizeof vs, "sigma_s", zero, 4);
    rgb_values(vl, sizeof vl, "Le", le, 4);
    snprintf(text, sizeof text, fmt, va, vs, vl);
    if (!rgb_spectra(t, sa, 4, 2, sp) || !rgb_spectra(t, le, 1, 1, lsp) || !test_load_scene(t, &s, text)) return;
    spec_named(&d65, "stdillum-D65");
    norm = luminance_sum(&d65, LAMBDA_LO, LAMBDA_HI);
    for (l = 400; l <= 700; l++) {              /* the film's 1 nm sums */
        const double ones[4] = { 1, 1, 1, 1 };
        double d[4], tau = 0.0, L = 0.0;
        float xyz[3];
        for (k = 0; k < 4; k++) d[k] = spec_eval(&sp[k], (float)l);
        cie_xyz((float)l, xyz);
        for (k = 799; k >= 0; k--) {            /* from the top down */
            double u = (k + 0.5) / 800, dz = 1.0 / 800, a = profile(d, 4, u);
            tau += 0.5 * a * dz;
            L += a * profile(ones, 4, u) * 3.0 * spec_eval(&lsp[0], (float)l) * 106.856895 / norm * exp(-tau) * dz;
            tau += 0.5 * a * dz;
        }
        expect += xyz[1] * L;
    }
    render_options_default(&o);
    o.spp = test_scaled(256, 32);
    o.maxdepth = 5;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 3e-3 * expect, "rgbgrid Le: Y = %.6g +- %.2g, expected %.6g",
          Y, se, expect);
}

/* ---- 1 and 2 threads give the same image through an emissive rgbgrid */
static void test_rgb_threads(T *t)
{
    static const char text[] =
        "LookAt 0 0 4  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 40 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "MakeNamedMedium \"g\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"integer ny\" 1 \"integer nz\" 2 "
        "\"rgb sigma_a\" [ 0.3 0.1 0.1  0.1 0.3 0.1  0.1 0.1 0.3  0.2 0.2 0.2 ] "
        "\"rgb sigma_s\" [ 2 0.5 0.5  0.5 2 0.5  0.5 0.5 2  1 1 1 ] "
        "\"rgb Le\" [ 1 0 0  0 0 0  0 0 1  0 0 0 ] \"point3 p0\" [ -1 -1 -1 ] \"point3 p1\" [ 1 1 1 ]\n"
        "LightSource \"point\" \"point3 from\" [ 0 3 0 ] \"spectrum I\" [ 400 1 700 1 ] \"float scale\" 5\n"
        "AttributeBegin\n Material \"interface\"\n MediumInterface \"g\" \"\"\n"
        " Shape \"sphere\" \"float radius\" 1.2\nAttributeEnd\n";
    Scene s;
    RenderOptions o;
    Image a, b;
    RenderStats st;
    Error e;
    double sum = 0.0;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = 8;
    o.threads = 1;
    CHECK(t, render(&s, &o, &a, &st, &e), "%s", e.msg);
    o.threads = 2;
    CHECK(t, render(&s, &o, &b, &st, &e), "%s", e.msg);
    scene_free(&s);
    for (i = 0; i < 3 * a.w * a.h; i++) sum += a.rgb[i];
    CHECK(t, sum > 0.0, "a black image");
    CHECK(t, memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * a.h) == 0, "1 and 2 threads differ");
    img_free(&a);
    img_free(&b);
}

static void test_rgb_bad_input(T *t)
{
#define G "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"rgbgrid\" "
    if (!test_load_fails(t, G "\n", "m.pbrt:2:", "needs \"rgb sigma_a\" and/or \"rgb sigma_s\"")) return;
    if (!test_load_fails(t, G "\"integer nx\" 2\n \"rgb sigma_a\" [ 1 2 3 ]\n", "m.pbrt:3:",
                         "3 \"rgb sigma_a\" values; expected 3*nx*ny*nz = 3*2*1*1 = 6")) return;
    if (!test_load_fails(t, G "\"rgb sigma_s\" [ 1 1 1 ] \"rgb Le\" [ 1 1 1 ]\n", "m.pbrt:2:",
                         "with \"rgb Le\" needs \"rgb sigma_a\"")) return;
    if (!test_load_fails(t, G "\n \"rgb sigma_s\" [ 1 -1 1 ]\n", "m.pbrt:3:",
                         "\"rgb sigma_s\" value 1 is -1; need a finite value >= 0")) return;
    if (!test_load_fails(t, G "\"rgb sigma_s\" [ 1 1 1 ] \"float g\" 1\n", "m.pbrt:2:", "(-1, 1)")) return;
    if (!test_load_fails(t, G "\"rgb sigma_s\" [ 1 1 1 ]\n \"float scale\" -1\n", "m.pbrt:3:", "\"float scale\" -1")) return;
    if (!test_load_fails(t, G "\"rgb sigma_s\" [ 1 1 1 ] \"float density\" [ 1 ]\n", "m.pbrt:2:", "density")) return;
    if (!test_load_fails(t, G "\"rgb sigma_s\" [ 1 1 1 ] \"integer ny\" 0\n", "m.pbrt:2:", "\"integer ny\" 0 must lie in 1..4096")) return;
#undef G
}


/* ==== cloud: pbrt-v4's procedural density ==== */

/* The density's shape: 1 at and below y = 0 (2 (1/2 - y) >= 1), always in
   [0, 1] (above y = 1 the factor 1 - y turns negative noise into density, as in
   pbrt-v4); without wisps it is
   clamp((1 - y) 4.5 density sum_i 2^-(i+1) noise(1.99^i frequency q)) plus the fill
   below y = 1/2, written here from tex_noise alone; with wisps it differs. */
static void test_cloud_density(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "MakeNamedMedium \"a\" \"string type\" \"cloud\" \"float density\" 1.5 \"float wispiness\" 0 "
        "\"float frequency\" 3\n"
        "MakeNamedMedium \"b\" \"string type\" \"cloud\" \"float density\" 1.5 \"float frequency\" 3\n"
        "Translate 0 2 0\n"
        "MakeNamedMedium \"c\" \"string type\" \"cloud\" \"float density\" 1.5 \"float frequency\" 3 "
        "\"rgb sigma_a\" [ 1 1 1 ] \"rgb sigma_s\" [ 0 0 0 ]\n";
    Scene s;
    Rng rng;
    int i, k, differ = 0;
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_media == 3 && s.media[0].type == MEDIUM_CLOUD, "not a cloud");
    {   /* the density in the medium's frame: world (0.3, 2.45, 0.4) is medium (0.3, 0.45, 0.4) */
        const float lam[HERO_N] = { 550.0f, 550.0f, 550.0f, 550.0f };
        MediumPoint mp;
        float want = medium_cloud_density(&s.media[2], v3(0.3f, 0.45f, 0.4f));
        medium_point(&s.media[2], v3(0.3f, 2.45f, 0.4f), lam, 1u, &mp);
        CHECK(t, fabs(mp.sa[0] - want * medium_sigma_a(&s.media[2], 550.0f)) < 1e-5 && want > 0.1f && want < 0.99f,
              "sigma_a %g at the translated point, expected %g x sigma_a", mp.sa[0], want);
    }
    CHECK(t, s.media[1].wispiness == 1.0f && s.media[1].frequency == 3.0f && s.media[1].cloud_density == 1.5f &&
          medium_sigma_t(&s.media[1], 550.0f) == 2.0f, "parameters or defaults not pbrt-v4's");
    rng_seed(&rng, 38, 0);
    for (i = 0; i < 3000; i++) {
        Vec3 q = v3(rng_float(&rng) * 2.0f - 0.5f, rng_float(&rng) * 2.0f - 0.5f, rng_float(&rng) * 2.0f - 0.5f);
        float da = medium_cloud_density(&s.media[0], q), db = medium_cloud_density(&s.media[1], q), sum = 0.0f,
              w = 0.5f, f = 1.0f, want;
        for (k = 0; k < 5; k++) {
            sum += w * tex_noise(3.0f * q.x * f, 3.0f * q.y * f, 3.0f * q.z * f);
            w *= 0.5f;
            f *= 1.99f;
        }
        want = (1.0f - q.y) * 4.5f * 1.5f * sum;
        want = want < 0.0f ? 0.0f : want > 1.0f ? 1.0f : want;
        want += 2.0f * (q.y < 0.5f ? 0.5f - q.y : 0.0f);
        want = want > 1.0f ? 1.0f : want;
        CHECK(t, fabsf(da - want) < 1e-4f, "(%g %g %g): density %g, expected %g", q.x, q.y, q.z, da, want);
        CHECK(t, db >= 0.0f && db <= 1.0f, "wispy density %g outside [0, 1]", db);
        if (q.y <= 0.0f) CHECK(t, da == 1.0f && db == 1.0f, "y = %g <= 0: density %g %g, expected 1", q.y, da, db);
        if (fabsf(da - db) > 1e-3f) differ++;
    }
    CHECK(t, differ > 300, "the wisps moved only %d of 3000 densities", differ);
    for (i = 0; i < MAJORANT_RES * MAJORANT_RES * MAJORANT_RES; i++)
        CHECK(t, s.media[1].majorant[i] == 1.0f, "majorant cell %d is %g, expected 1", i, s.media[1].majorant[i]);
    scene_free(&s);
}

/* ---- furnace: a non-absorbing cloud (albedo 1) around the camera in a constant
   environment: Y = 1 */
static void test_cloud_furnace(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"c\" \"string type\" \"cloud\" \"spectrum sigma_a\" [ 400 0 700 0 ] "
        "\"spectrum sigma_s\" [ 400 30 550 5 700 15 ] \"float g\" 0.5 \"point3 p0\" [ -1 -1 -1 ] "
        "\"point3 p1\" [ 1 1 1 ]\n"
        "MediumInterface \"\" \"c\"\n"
        "Camera \"perspective\" \"float fov\" [ 60 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1000 ]\n"
        "WorldBegin\n"
        "LightSource \"infinite\" \"spectrum L\" [ 400 1 700 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    double se, Y;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(256, 32);
    o.maxdepth = 1000;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - 1.0) < TEST_K_SIGMA * se + 1e-3, "albedo-1 cloud furnace: Y = %.6g +- %.2g, expected 1", Y, se);
}

static void test_cloud_bad_input(T *t)
{
#define G "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"cloud\" "
    if (!test_load_fails(t, G "\"float scale\" 2\n", "m.pbrt:2:", "scale")) return;
    if (!test_load_fails(t, G "\"float g\" -1\n", "m.pbrt:2:", "(-1, 1)")) return;
    if (!test_load_fails(t, G "\n \"point3 p1\" [ 0 1 1 ]\n", "m.pbrt:3:", "need finite p0 < p1 on every axis")) return;
    if (!test_load_fails(t, G "\"rgb sigma_s\" [ -1 1 1 ]\n", "m.pbrt:2:", "sigma_s")) return;
#undef G
}

const TestCase tests_grid[] = {
    { "grid_lookup", test_lookup },
    { "grid_format", test_format },
    { "grid_bad_input", test_bad_input },
    { "grid_flight_chi2", test_flight_chi2 },
    { "grid_track_carries_depth", test_track_carries_depth },
    { "grid_ratio_vs_delta", test_ratio_vs_delta },
    { "grid_ramp_transmittance", test_ramp },
    { "grid_checker_transmittance", test_checker },
    { "grid_nee", test_nee },
    { "grid_area_light", test_area_light },
    { "grid_furnace", test_furnace },
    { "grid_emission", test_emission },
    { "grid_threads", test_threads },
    { "grid_against_pbrt", test_against_pbrt },
    { "grid_smoke_scene_against_pbrt", test_smoke_scene },
    { "grid_medium_before_camera", test_before_camera },
    { "rgbgrid_lookup", test_rgb_lookup },
    { "rgbgrid_transmittance", test_rgb_transmittance },
    { "rgbgrid_furnace", test_rgb_furnace },
    { "rgbgrid_emission", test_rgb_emission },
    { "rgbgrid_threads", test_rgb_threads },
    { "rgbgrid_bad_input", test_rgb_bad_input },
    { "cloud_density", test_cloud_density },
    { "cloud_furnace", test_cloud_furnace },
    { "cloud_bad_input", test_cloud_bad_input },
    { NULL, NULL }
};
