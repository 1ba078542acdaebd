/* tests/test_medium.c - homogeneous participating media (medium.c, path.c's
   medium vertex, docs/media.md) against closed forms.

   Every check renders small images over K seeds and accepts a mean within
   TEST_K_SIGMA standard errors plus a small slack for the CIE tables'
   interpolation (the film and the emitters' normalisation integrate the same
   tables, so the luminance is exact up to that).  The closed forms:
   - slab:     radiance Le(lambda) exp(-sigma_a(lambda) d) through an absorbing slab
               of thickness d bounded by Material "interface" quads, per 10 nm band
               (a chromatic sigma: the hero's pass probability differs from the
               others', so spectral MIS is in play at every pass);
   - furnace:  an infinite medium that emits sigma_a Le, albedo a(lambda) = sigma_s /
               sigma_t: with maxdepth D the camera sees Le (1 - a^D) (emission at the
               collisions 0..D-1, pbrt-v4's depth rule);
   - point:    a point light in an absorbing medium over a white plane: E / pi with E
               = I h exp(-sigma r) / r^3, seen through exp(-sigma d_cam) (NEE's
               transmittance);
   - phase:    hg_sample against hg_phase (chi-square over cells of cos theta, phi).
   Unbiasedness where no closed form exists: spectral MIS, termination and single
   wavelengths agree on a chromatic fog (no cross-talk between wavelengths); NEE +
   phase sampling (MIS) agrees with phase sampling alone; every selection strategy
   agrees with uniform selection at medium vertices. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* ---- the slab: camera at z = 5 looking down, a constant emitter at z = -1, an
   absorbing slab 0 < z < 1 (sigma_a 0.2 at 400 nm rising to 1.4 at 700 nm) */
static const char slab_scene[] =
    "LookAt 0 0 5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 10 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
    "\"string filename\" \"t.pfm\"\n"
    "Integrator \"%s\" \"integer maxdepth\" [ 1 ]\n"
    "MakeNamedMedium \"slab\" \"string type\" \"homogeneous\" "
    "\"spectrum sigma_a\" [ 400 0.2 700 1.4 ] \"spectrum sigma_s\" [ 400 0 700 0 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    " AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ] \"float scale\" 2\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -50 -50 -1  50 -50 -1  50 50 -1  -50 50 -1 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    " Material \"interface\"\n"
    " MediumInterface \"slab\" \"\"\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"      /* top, normal +z */
    "  \"point3 P\" [ -50 -50 1  50 -50 1  50 50 1  -50 50 1 ]\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ]\n"      /* bottom, normal -z */
    "  \"point3 P\" [ -50 -50 0  50 -50 0  50 50 0  -50 50 0 ]\n"
    "AttributeEnd\n";

/* integral over [lo, hi] of ybar Le_eff exp(-sigma_a(lambda) d): Le_eff = 2 /
   (sum of ybar over 400..700 nm, 1 nm steps), lights.c's normalisation */
static double slab_expect(double lo, double hi, double d)
{
    Spectrum one;
    double norm, sum = 0.0, h = 0.05, l;
    spec_const(&one, 1.0f);
    norm = luminance_sum(&one, LAMBDA_LO, LAMBDA_HI);
    for (l = lo + 0.5 * h; l < hi; l += h) {
        float xyz[3];
        double sa = 0.2 + 1.2 * (l - 400.0) / 300.0;
        cie_xyz((float)l, xyz);
        sum += h * xyz[1] * (2.0 / norm) * exp(-sa * d);
    }
    return sum;
}

static void test_slab_mode(T *t, const char *integrator, double d, int single, int terminate,
                           const char *what)
{
    char text[4096];
    Scene s;
    RenderOptions o;
    int b;
    snprintf(text, sizeof text, slab_scene, integrator);
    if (!test_load_scene(t, &s, text)) return;
    for (b = 0; b < 3; b++) {
        Tiles tl;
        double lo = 420.0 + 100.0 * b, hi = lo + 10.0, se, Y, expect = slab_expect(lo, hi, d);
        render_options_default(&o);
        o.spp = test_scaled(16, 4);
        o.band_lo = (float)lo;
        o.band_hi = (float)hi;
        o.single_wavelength = single;
        o.media_terminate = terminate;
        if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
        Y = test_tile_y(&tl, 0, &se);
        if (!(fabs(Y - expect) < TEST_K_SIGMA * se + 2e-3 * expect + 1e-9)) {
            test_failf(t, __FILE__, __LINE__, "%s, %g-%g nm: Y = %.6g +- %.2g, expected %.6g",
                       what, lo, hi, Y, se, expect);
            scene_free(&s);
            return;
        }
    }
    scene_free(&s);
}

/* Beer-Lambert per band, with spectral MIS, single wavelengths and termination */
static void test_slab_transmittance(T *t)
{
    test_slab_mode(t, "volpath", 1.0, 0, 0, "volpath, spectral MIS");
    if (t->failed) return;
    test_slab_mode(t, "volpath", 1.0, 1, 0, "volpath, single wavelength");
    if (t->failed) return;
    test_slab_mode(t, "volpath", 1.0, 0, 1, "volpath, --chromatic-media terminate");
}

/* ---- two slabs in a row: the same emitter seen through slab A (1 < z < 2, the
   slab's sigma_a) and then slab B (0 < z < 1, sigma_a falling from 1.0 at 400 nm
   to 0.1 at 700 nm), each path entering one medium from the other: Le exp(-(sigma_a,A
   + sigma_a,B) 1) per band, each medium's own coefficients on its own stretch. */
static const char two_slabs_scene[] =
    "LookAt 0 0 5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 10 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
    "\"string filename\" \"t.pfm\"\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
    "MakeNamedMedium \"A\" \"string type\" \"homogeneous\" "
    "\"spectrum sigma_a\" [ 400 0.2 700 1.4 ] \"spectrum sigma_s\" [ 400 0 700 0 ]\n"
    "MakeNamedMedium \"B\" \"string type\" \"homogeneous\" "
    "\"spectrum sigma_a\" [ 400 1.0 700 0.1 ] \"spectrum sigma_s\" [ 400 0 700 0 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    " AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ] \"float scale\" 2\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -50 -50 -1  50 -50 -1  50 50 -1  -50 50 -1 ]\n"
    "AttributeEnd\n"
    "Material \"interface\"\n"
    "AttributeBegin\n MediumInterface \"A\" \"\"\n"                           /* top of A, normal +z */
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -50 -50 2  50 -50 2  50 50 2  -50 50 2 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n MediumInterface \"B\" \"A\"\n"                          /* A above, B below */
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -50 -50 1  50 -50 1  50 50 1  -50 50 1 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n MediumInterface \"B\" \"\"\n"                           /* bottom of B, normal -z */
    " Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ] \"point3 P\" [ -50 -50 0  50 -50 0  50 50 0  -50 50 0 ]\n"
    "AttributeEnd\n";

static void test_two_slabs(T *t)
{
    Scene s;
    RenderOptions o;
    Spectrum one;
    double norm;
    int b;
    if (!test_load_scene(t, &s, two_slabs_scene)) return;
    spec_const(&one, 1.0f);
    norm = luminance_sum(&one, LAMBDA_LO, LAMBDA_HI);
    for (b = 0; b < 3; b++) {
        Tiles tl;
        double lo = 420.0 + 100.0 * b, hi = lo + 10.0, se, Y, expect = 0.0, l, h = 0.05;
        for (l = lo + 0.5 * h; l < hi; l += h) {
            float xyz[3];
            double sa = 0.2 + 1.2 * (l - 400.0) / 300.0, sb = 1.0 - 0.9 * (l - 400.0) / 300.0;
            cie_xyz((float)l, xyz);
            expect += h * xyz[1] * (2.0 / norm) * exp(-(sa + sb));
        }
        render_options_default(&o);
        o.spp = test_scaled(16, 4);
        o.band_lo = (float)lo;
        o.band_hi = (float)hi;
        if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) break;
        Y = test_tile_y(&tl, 0, &se);
        CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 2e-3 * expect + 1e-9,
              "two slabs, %g-%g nm: Y = %.6g +- %.2g, expected %.6g", lo, hi, Y, se, expect);
        if (t->failed) break;
    }
    scene_free(&s);
}

/* Integrator "path" ignores the medium (pbrt-v4): the emitter at full strength */
static void test_path_ignores_media(T *t)
{
    test_slab_mode(t, "path", 0.0, 0, 0, "path ignores media");
}

/* ---- the furnace: an infinite emissive medium around the camera */
static void test_furnace(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"glow\" \"string type\" \"homogeneous\" "
        "\"spectrum sigma_a\" [ 400 0.2 700 1.0 ] \"spectrum sigma_s\" [ 400 1.0 700 0.4 ] "
        "\"spectrum Le\" [ 400 1 700 1 ] \"float Lescale\" 3 \"float g\" 0.6\n"
        "MediumInterface \"\" \"glow\"\n"
        "Camera \"perspective\" \"float fov\" [ 60 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ %d ]\n"
        "WorldBegin\n";
    int D;
    for (D = 1; D <= 3; D += 2) {
        char buf[2048];
        Scene s;
        RenderOptions o;
        Tiles tl;
        Spectrum one;
        double se, Y, expect = 0.0, norm, h = 0.05, l;
        snprintf(buf, sizeof buf, text, D);
        if (!test_load_scene(t, &s, buf)) return;
        spec_const(&one, 1.0f);
        norm = luminance_sum(&one, LAMBDA_LO, LAMBDA_HI);
        for (l = 400.0 + 0.5 * h; l < 700.0; l += h) {
            float xyz[3];
            double x = (l - 400.0) / 300.0, sa = 0.2 + 0.8 * x, ss = 1.0 - 0.6 * x;
            cie_xyz((float)l, xyz);
            expect += h * xyz[1] * (3.0 / norm) * (1.0 - pow(ss / (sa + ss), D));
        }
        render_options_default(&o);
        o.spp = test_scaled(32, 8);
        o.maxdepth = D;             /* (the file's maxdepth is the command line's to apply) */
        if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
        scene_free(&s);
        Y = test_tile_y(&tl, 0, &se);
        CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 3e-3 * expect,
              "maxdepth %d: Y = %.6g +- %.2g, expected Le (1 - a^D) = %.6g", D, Y, se, expect);
    }
}

/* ---- a point light in an absorbing medium over a white plane */
/* Render text (a camera 5 above a white plane, 20 degrees) over 6 seeds and compare
   the luminance with E/pi averaged over the camera's footprint (a 64 x 64 midpoint
   rule), within TEST_K_SIGMA standard errors + 0.3 %. */
static void check_plane(T *t, const char *text, double (*e_over_pi)(double x, double y),
                        const char *what)
{
    Scene s;
    RenderOptions o;
    Tiles tl;
    double se, Y, expect = 0.0, a = 5.0 * tan(10.0 * SPECNEE_PI / 180.0);
    int i, j, n = 64;
    if (!test_load_scene(t, &s, text)) return;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            expect += e_over_pi(a * (2.0 * (i + 0.5) / n - 1.0), a * (2.0 * (j + 0.5) / n - 1.0));
    expect /= (double)n * n;
    render_options_default(&o);
    o.spp = test_scaled(16, 4);
    o.maxdepth = 1;
    if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    Y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(Y - expect) < TEST_K_SIGMA * se + 3e-3 * expect,
          "%s: Y = %.6g +- %.2g, expected E/pi = %.6g", what, Y, se, expect);
}

static double point_e(double h, double sigma, double x, double y)
{
    double r2 = h * h + x * x + y * y, r = sqrt(r2), rc = sqrt(25.0 + x * x + y * y);
    return h * exp(-sigma * r) / (r2 * r) * exp(-sigma * rc) / SPECNEE_PI;
}

/* sigma_a 0.3, the light at height 2 */
static double point_e_smoke(double x, double y) { return point_e(2.0, 0.3, x, y); }

static void test_point_light_through_medium(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"smoke\" \"string type\" \"homogeneous\" "
        "\"rgb sigma_a\" [ 0.3 0.3 0.3 ] \"rgb sigma_s\" [ 0 0 0 ]\n"
        "MediumInterface \"\" \"smoke\"\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 20 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "PixelFilter \"box\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
        "WorldBegin\n"
        "LightSource \"point\" \"point3 from\" [ 0 0 2 ] \"spectrum I\" [ 400 1 700 1 ]\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 1 830 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -40 -40 0  40 -40 0  40 40 0  -40 40 0 ]\n";
    check_plane(t, text, point_e_smoke, "a point light in the smoke");
}

/* The same with the medium only in the slab 0 < z < 3 (Material "interface"
   quads) and the light above it at z = 4: the shadow ray crosses the slab's top
   (3/4 of its length lies in the slab), the camera ray 3/5 of its own. */
static double slab_point_e(double x, double y)
{
    const double sigma = 0.3;
    double r2 = 16.0 + x * x + y * y, r = sqrt(r2), rc = sqrt(25.0 + x * x + y * y);
    return 4.0 * exp(-sigma * 0.75 * r) / (r2 * r) * exp(-sigma * 0.6 * rc) / SPECNEE_PI;
}

static void test_point_light_through_interface(T *t)
{
    static const char text[] =
        "MakeNamedMedium \"smoke\" \"string type\" \"homogeneous\" "
        "\"rgb sigma_a\" [ 0.3 0.3 0.3 ] \"rgb sigma_s\" [ 0 0 0 ]\n"
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 20 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
        "\"string filename\" \"t.pfm\"\n"
        "PixelFilter \"box\"\n"
        "WorldBegin\n"
        "LightSource \"point\" \"point3 from\" [ 0 0 4 ] \"spectrum I\" [ 400 1 700 1 ]\n"
        "AttributeBegin\n"
        " Material \"interface\"\n"
        " MediumInterface \"smoke\" \"\"\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -60 -60 3  60 -60 3  60 60 3  -60 60 3 ]\n"
        "AttributeEnd\n"
        "MediumInterface \"smoke\" \"smoke\"\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 1 830 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -40 -40 0  40 -40 0  40 40 0  -40 40 0 ]\n";
    check_plane(t, text, slab_point_e, "a point light above the smoke slab");
}

/* Integrator "path" (pbrt-v4's): an "interface" surface stops shadow rays but
   not the path, which finds the light behind it as after a specular bounce
   (weight 1).  So a lamp behind an interface lights a floor exactly as BSDF
   sampling alone would without the interface. */
static void test_path_interface(T *t)
{
    static const char text[] =
        "LookAt 0 3 3  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 50 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ] "
        "\"string filename\" \"t.pfm\"\n"
        "Integrator \"path\"\n"
        "WorldBegin\n"
        "AttributeBegin\n"
        " AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ]\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -1 2 -1  1 2 -1  1 2 1  -1 2 1 ]\n"
        "AttributeEnd\n"
        "%s"
        "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.5 700 0.5 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\n";
    static const char iface[] =
        "AttributeBegin\n Material \"interface\"\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -3 1 -3  3 1 -3  3 1 3  -3 1 3 ]\nAttributeEnd\n";
    char buf[4096];
    Scene s;
    RenderOptions o;
    Tiles a, b;
    snprintf(buf, sizeof buf, text, iface);
    if (!test_load_scene(t, &s, buf)) return;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    o.maxdepth = 2;
    if (!test_render_tiles(t, &s, &o, 6, 2, &a)) { scene_free(&s); return; }
    scene_free(&s);
    snprintf(buf, sizeof buf, text, "");
    if (!test_load_scene(t, &s, buf)) return;
    o.nee = 0;
    if (!test_render_tiles(t, &s, &o, 6, 2, &b)) { scene_free(&s); return; }
    scene_free(&s);
    test_tiles_agree(t, &a, &b, 1e-4, "path: a lamp behind an interface vs BSDF sampling alone");
}

/* ---- a scattering slab under a distant light, against pbrt-v4: the means of
   the reflected (camera above) and transmitted (camera below) light, per RGB
   channel.  Frozen from pbrt-v4 (mmp/pbrt-v4 5f7a6068, `pbrt --spp 16384 --seed S`
   for S = 1, 2, the mean of the two; they differ by at most 0.25 %) on this text
   with the camera line of each side; specnee's own renders agreed within 0.3 %. */
static const char slab_pbrt_scene[] =
    "%s\n"
    "Camera \"perspective\" \"float fov\" [ 10 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ] "
    "\"string filename\" \"t.pfm\"\n"
    "PixelFilter \"box\"\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 100 ]\n"
    "MakeNamedMedium \"slab\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ 0.1 0.2 0.4 ] "
    "\"rgb sigma_s\" [ 1.5 1.0 0.5 ] \"float g\" [ 0.5 ]\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"point3 from\" [ 1 0.5 3 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 1 1 1 ]\n"
    "AttributeBegin\n"
    " Material \"interface\"\n"
    " MediumInterface \"slab\" \"\"\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" "
    "[ -100 -100 1  100 -100 1  100 100 1  -100 100 1 ]\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ] \"point3 P\" "
    "[ -100 -100 0  100 -100 0  100 100 0  -100 100 0 ]\n"
    "AttributeEnd\n";

static void test_slab_against_pbrt(T *t)
{
    static const char *const cams[2] = { "LookAt 0 0 5  0 0 0  0 1 0", "LookAt 0 0 -4  0 0 0  0 1 0" };
    static const double pbrt_rgb[2][3] = {
        { 0.0477398, 0.0254740, 0.00780404 },    /* reflected */
        { 0.181116, 0.142445, 0.0801802 }        /* transmitted */
    };
    int side, c;
    for (side = 0; side < 2; side++) {
        char text[4096];
        Scene s;
        RenderOptions o;
        Tiles tl;
        snprintf(text, sizeof text, slab_pbrt_scene, cams[side]);
        if (!test_load_scene(t, &s, text)) return;
        render_options_default(&o);
        o.spp = test_scaled(256, 64);
        o.maxdepth = 100;
        if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
        scene_free(&s);
        for (c = 0; c < 3; c++)
            CHECK(t, fabs(tl.mean[0][c] - pbrt_rgb[side][c]) < TEST_K_SIGMA * tl.se[0][c] + 0.01 * pbrt_rgb[side][c],
                  "%s, channel %d: %.6g +- %.2g, pbrt-v4 %.6g", side ? "transmitted" : "reflected", c,
                  tl.mean[0][c], tl.se[0][c], pbrt_rgb[side][c]);
    }
}

/* ---- Henyey-Greenstein sampling against its density */
typedef struct {
    float g;
    Vec3 d;                  /* the incident direction: the pole of the grid */
    Frame fr;
    float bad_pdf, want;     /* the first pdf that is not the phase function's */
} PhaseDirs;

/* hg_sample about d, in the frame of d (cos theta = the cosine to d) */
static int phase_dir_sample(void *ctx, Rng *r, Vec3 *w)
{
    PhaseDirs *c = (PhaseDirs *)ctx;
    float u[2], pdf;
    Vec3 wi;
    rng_fill(r, u, 2);
    wi = hg_sample(c->g, c->d, u[0], u[1], &pdf);
    if (!(fabsf(pdf - hg_phase(c->g, v3_dot(c->d, wi))) <= 1e-4f * pdf) && c->bad_pdf == 0.0f) {
        c->bad_pdf = pdf;
        c->want = hg_phase(c->g, v3_dot(c->d, wi));
    }
    *w = frame_to_local(&c->fr, wi);
    return 1;
}

static double phase_dir_pdf(void *ctx, const double w[3])
{
    return hg_phase(((const PhaseDirs *)ctx)->g, (float)w[2]);
}

/* 200000 samples on a 16 x 8 grid about d (32 x 32 sub-cells per cell, for the
   peak of g = 0.9): the counts follow the phase function, which integrates to 1
   over the grid, and hg_sample's pdf is the phase function. */
static void test_phase_chi2(T *t)
{
    static const float gs[] = { -0.7f, 0.0f, 0.3f, 0.9f };
    int gi;
    for (gi = 0; gi < 4; gi++) {
        PhaseDirs c;
        DirTest dt;
        Rng rng;
        Chi2 x;
        c.g = gs[gi];
        c.d = v3_norm(v3(0.3f, -0.5f, 0.8f));
        c.fr = frame_from_normal(c.d);
        c.bad_pdf = c.want = 0.0f;
        dt.sample = phase_dir_sample;
        dt.pdf = phase_dir_pdf;
        dt.ctx = &c;
        dt.n = 200000;
        dt.nt = 16;
        dt.np = 8;
        dt.sub = 32;
        rng_seed(&rng, 7 + gi, 3);
        CHECK_CHI2_DIRS(t, &dt, &rng, 4, &x, "g %g", c.g);
        CHECK(t, c.bad_pdf == 0.0f, "g %g: pdf %g is not the phase function's %g", c.g, c.bad_pdf, c.want);
        CHECK(t, fabs(x.total / dt.n - 1.0) < 2e-3, "g %g: the phase function integrates to %.5f", c.g,
              x.total / dt.n);
    }
}

/* ---- a chromatic fog lit by an area light and a spot, a glass sphere in it */
static const char fog_scene[] =
    "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" "
    "\"spectrum sigma_a\" [ 400 0.05 700 0.15 ] \"spectrum sigma_s\" [ 400 0.9 550 0.4 700 0.1 ] "
    "\"float g\" 0.4\n"
    "MediumInterface \"\" \"fog\"\n"
    "LookAt 0 0 3.5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] "
    "\"string filename\" \"t.pfm\"\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 4 ]\n"
    "WorldBegin\n"
    "%s"
    "AttributeBegin\n"
    " AreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\" \"float scale\" 3\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -0.3 0.99 -0.3  0.3 0.99 -0.3  0.3 0.99 0.3  -0.3 0.99 0.3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    " AreaLightSource \"diffuse\" \"spectrum L\" \"lamp-CFL1\" \"float scale\" 2\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "  \"point3 P\" [ -0.99 -0.3 -0.3  -0.99 0.3 -0.3  -0.99 0.3 0.3  -0.99 -0.3 0.3 ]\n"
    "AttributeEnd\n"
    "%s";

static void fog_text(char *buf, size_t cap, int with_spot)
{
    snprintf(buf, cap, fog_scene,
             with_spot ? "LightSource \"spot\" \"point3 from\" [ 0.5 0.9 0 ] \"point3 to\" "
                         "[ 0.5 -1 0 ] \"float coneangle\" 25 \"spectrum I\" \"lamp-LED2\"\n" : "",
             test_box_walls);
}

static int fog_tiles(T *t, const char *text, const RenderOptions *o, Tiles *tl)
{
    Scene s;
    int ok;
    if (!test_load_scene(t, &s, text)) return 0;
    ok = test_render_tiles(t, &s, o, 8, 2, tl);
    scene_free(&s);
    return ok;
}

/* spectral MIS = single wavelengths = termination (no cross-talk), with NEE */
static void test_no_crosstalk(T *t)
{
    static char text[16384];
    RenderOptions o;
    Tiles a, b, c;
    fog_text(text, sizeof text, 1);
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    if (!fog_tiles(t, text, &o, &a)) return;
    o.single_wavelength = 1;
    o.spp = test_scaled(64, 16);
    if (!fog_tiles(t, text, &o, &b)) return;
    if (!test_tiles_agree(t, &a, &b, 1e-4, "chromatic fog: spectral MIS vs single wavelength")) return;
    o.single_wavelength = 0;
    o.media_terminate = 1;
    o.spp = test_scaled(32, 8);
    if (!fog_tiles(t, text, &o, &c)) return;
    test_tiles_agree(t, &a, &c, 1e-4, "chromatic fog: spectral MIS vs termination");
}

/* NEE + phase/BSDF sampling (MIS) = phase/BSDF sampling alone: a thick chromatic
   fog under a ceiling that is one big lamp, so that both techniques find it
   often and a wrong weight on either side shows */
static void test_mis_vs_phase_only(T *t)
{
    static const char head[] =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" "
        "\"spectrum sigma_a\" [ 400 0.05 700 0.3 ] \"spectrum sigma_s\" [ 400 2.0 700 0.5 ] "
        "\"float g\" 0.3\n"
        "MediumInterface \"\" \"fog\"\n"
        "LookAt 0 0 0.9  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 70 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] "
        "\"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "AttributeBegin\n"
        " AreaLightSource \"diffuse\" \"spectrum L\" \"lamp-LED1\"\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -1 0.99 -1  1 0.99 -1  1 0.99 1  -1 0.99 1 ]\n"
        "AttributeEnd\n";
    static char text[16384];
    RenderOptions o;
    Tiles a, b;
    snprintf(text, sizeof text, "%s%s", head, test_box_walls);
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    o.maxdepth = 3;
    if (!fog_tiles(t, text, &o, &a)) return;
    o.nee = 0;
    o.spp = test_scaled(64, 16);
    if (!fog_tiles(t, text, &o, &b)) return;
    test_tiles_agree(t, &a, &b, 1e-4, "thick fog: NEE + phase sampling vs phase sampling alone");
}

/* every selection strategy agrees with uniform selection at medium vertices */
static void test_strategies_in_medium(T *t)
{
    static char text[16384];
    static const SelStrategy st[] = { SEL_POWER, SEL_SPATIAL, SEL_SPD, SEL_PRODUCT,
                                      SEL_SPECTRAL_SPATIAL, SEL_TREE, SEL_SPECTRAL_TREE };
    RenderOptions o;
    Tiles ref, x;
    int i;
    fog_text(text, sizeof text, 1);
    render_options_default(&o);
    o.sel.grid_res = 4;
    o.sel.strategy = SEL_UNIFORM;
    o.spp = test_scaled(32, 8);
    if (!fog_tiles(t, text, &o, &ref)) return;
    for (i = 0; i < (int)(sizeof st / sizeof st[0]); i++) {
        char what[96];
        o.sel.strategy = st[i];
        o.single_wavelength = i == 3;     /* spd/product act on hero-only paths */
        if (!fog_tiles(t, text, &o, &x)) return;
        snprintf(what, sizeof what, "chromatic fog: %s vs uniform", sel_name(st[i]));
        if (!test_tiles_agree(t, &ref, &x, 1e-4, what)) return;
    }
}

/* the same image for 1 and 2 threads, bit for bit */
static void test_threads(T *t)
{
    static char text[16384];
    Scene s;
    RenderOptions o;
    Image a, b;
    RenderStats st;
    Error e;
    fog_text(text, sizeof text, 1);
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

/* ---- what spectral MIS gains: the variance of one sample over the pixels of
   a uniform image (every pixel sees the same radiance), spectral MIS against
   termination of the secondaries at the first chromatic event.  A strongly
   chromatic medium (sigma_t from 0.1 to 3 across the range) makes the hero a
   poor sampler of the other wavelengths: termination keeps one wavelength of
   four, and weights that ignore the pdf ratios r_m (equal weights, also
   unbiased) let a lane whose light the hero rarely samples blow up. */
static double pixel_variance(T *t, const char *text, int terminate, double *mean)
{
    Scene s;
    RenderOptions o;
    Image img;
    RenderStats st;
    Error e;
    double sum = 0.0, sum2 = 0.0;
    int i, n;
    if (!test_load_scene(t, &s, text)) return -1.0;
    s.settings.xres = s.settings.yres = 64;
    render_options_default(&o);
    o.spp = 1;
    o.maxdepth = 3;
    o.media_terminate = terminate;
    if (!render(&s, &o, &img, &st, &e)) {
        test_failf(t, __FILE__, __LINE__, "%s", e.msg);
        scene_free(&s);
        return -1.0;
    }
    scene_free(&s);
    n = img.w * img.h;
    for (i = 0; i < n; i++) {
        double rgb[3], y;
        rgb[0] = img.rgb[3 * i]; rgb[1] = img.rgb[3 * i + 1]; rgb[2] = img.rgb[3 * i + 2];
        y = test_luminance(rgb);
        sum += y;
        sum2 += y * y;
    }
    img_free(&img);
    *mean = sum / n;
    return sum2 / n - *mean * *mean;
}

static void test_mis_gain(T *t)
{
    static const char slab[] =
        "LookAt 0 0 5  0 0 0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 5 ]\n"
        "Film \"rgb\" \"string filename\" \"t.pfm\"\n"
        "MakeNamedMedium \"slab\" \"string type\" \"homogeneous\" "
        "\"spectrum sigma_a\" [ 400 0.1 700 3 ] \"spectrum sigma_s\" [ 400 0 700 0 ]\n"
        "WorldBegin\n"
        "LightSource \"distant\" \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ] "
        "\"spectrum L\" [ 400 1 700 1 ]\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 400 1 700 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -50 -50 -1  50 -50 -1  50 50 -1  -50 50 -1 ]\n"
        "Material \"interface\"\n"
        "MediumInterface \"slab\" \"\"\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -50 -50 1  50 -50 1  50 50 1  -50 50 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 2 1 0 3 2 ]\n"
        "  \"point3 P\" [ -50 -50 0  50 -50 0  50 50 0  -50 50 0 ]\n";
    static const char glow[] =
        "MakeNamedMedium \"glow\" \"string type\" \"homogeneous\" "
        "\"spectrum sigma_a\" [ 400 0.1 700 1.5 ] \"spectrum sigma_s\" [ 400 0 700 1.5 ] "
        "\"spectrum Le\" [ 400 1 700 1 ]\n"
        "MediumInterface \"\" \"glow\"\n"
        "Camera \"perspective\" \"float fov\" [ 5 ]\n"
        "Film \"rgb\" \"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 400 0 700 0 ]\n"
        "Shape \"sphere\" \"float radius\" 100\n";
    /* measured: 0.57 and 0.23 (equal weights: 0.74 and 0.87) */
    static const double bound[2] = { 0.66, 0.5 };
    const char *texts[2] = { slab, glow }, *names[2] = { "a floor under an absorbing slab", "emissive medium" };
    int k;
    for (k = 0; k < 2; k++) {
        double m1, m2, v1 = pixel_variance(t, texts[k], 0, &m1), v2;
        if (t->failed) return;
        v2 = pixel_variance(t, texts[k], 1, &m2);
        if (t->failed) return;
        CHECK(t, v1 < bound[k] * v2, "%s: one sample's variance with spectral MIS %.4g (mean %.4g) "
              "is not below %g x termination's %.4g (mean %.4g)", names[k], v1, m1, bound[k], v2, m2);
    }
}

/* ---- the format */
static void test_bad_input(T *t)
{
#define MED "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" "
    if (!test_load_fails(t, "WorldBegin\n" MED "\"rgb sigma_a\" [ -1 0 0 ]\n", "m.pbrt:2:", "negative")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\"spectrum sigma_s\" [ 400 1 700 -0.5 ]\n", "m.pbrt:2:", "need a finite value >= 0")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\n \"float scale\" [ inf ]\n", "m.pbrt:3:", "scale")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\n \"float g\" [ 1 ]\n", "m.pbrt:3:", "(-1, 1)")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\n \"float g\" [ -1.5 ]\n", "m.pbrt:3:", "(-1, 1)")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\n \"string preset\" \"Fog\"\n", "m.pbrt:3:", "unknown preset \"Fog\"")) return;
    if (!test_load_fails(t, "WorldBegin\nMakeNamedMedium \"s\" \"string type\" \"nanovdb\"\n", "m.pbrt:2:",
                         "\"string filename\" is required")) return;
    if (!test_load_fails(t, "WorldBegin\nMakeNamedMedium \"s\" \"string type\" \"fluffy\"\n", "m.pbrt:2:",
                         "unknown medium type")) return;
    if (!test_load_fails(t, "WorldBegin\nMakeNamedMedium \"s\"\n", "m.pbrt:2:", "\"string type\" is required")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\n" MED "\n", "m.pbrt:3:", "redefined")) return;
    if (!test_load_fails(t, "MediumInterface \"\" \"fgo\"\nWorldBegin\n" MED "\n", "m.pbrt:1:",
                         "no MakeNamedMedium defines the medium \"fgo\"")) return;
    if (!test_load_fails(t, "WorldBegin\n" MED "\"float sigma_a\" 1\n", "m.pbrt:2:", "wrong type")) return;
    if (!test_load_fails(t, "WorldBegin\nMaterial \"interface\"\nAreaLightSource \"diffuse\"\n"
                         "Shape \"sphere\"\n", "m.pbrt:4:", "\"interface\"")) return;
#undef MED
}

/* what loads: a preset (pbrt-v4's numbers, RGB upsampled unbounded), forward
   references, the camera's medium, "" and "none" as "interface" */
static void test_format(T *t)
{
    static const char text[] =
        "MediumInterface \"milk\"\n"
        "Camera \"perspective\"\n"
        "WorldBegin\n"
        "MakeNamedMedium \"milk\" \"string type\" \"homogeneous\" \"string preset\" \"Wholemilk\" "
        "\"float scale\" 2\n"
        "Material \"\"\n"
        "MediumInterface \"milk\" \"\"\n"
        "Shape \"sphere\"\n"
        "Material \"none\"\n"
        "Shape \"sphere\"\n";
    Scene s;
    float sa, ss;
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_media == 1 && s.settings.camera_medium == 0, "%d media, camera in %d",
          s.n_media, s.settings.camera_medium);
    CHECK(t, s.shapes[0].medium_inside == 0 && s.shapes[0].medium_outside == -1,
          "shape 0: inside %d outside %d", s.shapes[0].medium_inside, s.shapes[0].medium_outside);
    CHECK(t, s.materials[s.shapes[0].material].type == MAT_INTERFACE &&
          s.materials[s.shapes[1].material].type == MAT_INTERFACE, "\"\" / \"none\" are not interfaces");
    /* Wholemilk: sigma_s' (2.55, 3.21, 3.77), sigma_a (0.0011, 0.0024, 0.014) mm^-1, x2:
       the red end near 2 x 2.55, the blue end near 2 x 3.77 */
    ss = medium_sigma_s(&s.media[0], 650.0f);
    sa = medium_sigma_a(&s.media[0], 450.0f);
    CHECK(t, ss > 4.0f && ss < 6.0f, "sigma_s(650 nm) = %g, expected near 5.1", ss);
    CHECK(t, sa > 0.015f && sa < 0.04f, "sigma_a(450 nm) = %g, expected near 0.028", sa);
    scene_free(&s);
}

const TestCase tests_medium[] = {
    { "medium_slab_transmittance", test_slab_transmittance },
    { "medium_path_ignores_media", test_path_ignores_media },
    { "medium_two_slabs", test_two_slabs },
    { "medium_furnace", test_furnace },
    { "medium_point_light", test_point_light_through_medium },
    { "medium_point_light_interface", test_point_light_through_interface },
    { "medium_path_interface", test_path_interface },
    { "medium_slab_against_pbrt", test_slab_against_pbrt },
    { "medium_phase_chi2", test_phase_chi2 },
    { "medium_no_crosstalk", test_no_crosstalk },
    { "medium_mis_vs_phase_only", test_mis_vs_phase_only },
    { "medium_strategies", test_strategies_in_medium },
    { "medium_threads", test_threads },
    { "medium_mis_gain", test_mis_gain },
    { "medium_bad_input", test_bad_input },
    { "medium_format", test_format },
    { NULL, NULL }
};
