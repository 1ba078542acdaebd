/* tests/test_gonio.c - goniometric and projection lights (delta.c section 4).

   Closed forms, with the plane scene of test_delta.c (a white Lambertian plane
   z = 0 seen from straight above by a narrow camera, radiance E / pi):
   - a goniometric light with a constant image of 1 is a point light of the same
     I and scale, whatever its rotation: E = I h / d^3;
   - a projection light of a constant grey image (0.5 0.5 0.5: the RGB illuminant
     spectrum 0.5 D65, luminance 0.5 scale) aiming straight down from height h
     lights the plane like a spot with a sharp rectangular cone: E = I h / d^3
     inside the window |x| <= sx h tan(fov/2), |y| <= sy h tan(fov/2), 0 outside
     (the camera's footprint centred on an edge sees half of each);
   - "power" P: the intensity integrated numerically over the sphere of
     directions (delta_falloff and the texels' luminance) gives P within 1e-3.
   pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 256`, S = 1..8,
   the independent sampler) rendered GONIO_SCENE and PROJ_SCENE, with the images
   tests/data/lights/gonio16.pfm (16 x 16, RGB, non-uniform) and proj16x8.pfm
   (16 x 8, RGB, a coloured checker with a black column): the luminance of the
   image and of its quadrants (top left first), mean over the seeds and its
   standard error, accepted within TEST_K_SIGMA standard errors + 1 % (specnee
   at 1024 spp: gonio image +0.06 %, quadrants within 0.09 %; projection image
   +0.11 %, quadrants within 0.18 %). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* A w x h image of the one colour rgb written as a PFM at a fresh test path. */
static const char *const_image(T *t, const char *name, int w, int h, float v)
{
    const char *p = test_path(t, name);
    Image im;
    int i;
    if (!img_alloc(&im, w, h)) return NULL;
    for (i = 0; i < 3 * w * h; i++) im.rgb[i] = v;
    if (!pfm_write(&im, p)) p = NULL;
    img_free(&im);
    return p;
}

/* The plane scene: a camera at (x0, y0, 5) looking straight down with field of
   view fov (4 x 4 pixels, box filter), the plane and `light`. */
static void plane_scene(char *buf, size_t cap, double x0, double y0, double fov, const char *light)
{
    snprintf(buf, cap,
             "LookAt %g %g 5  %g %g 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ %g ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
             "\"string filename\" \"t.pfm\"\n"
             "PixelFilter \"box\"\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n%s\n"
             "Material \"diffuse\" \"spectrum reflectance\" [ 360 1 830 1 ]\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -40 -40 0  40 -40 0  40 40 0  -40 40 0 ]\n",
             x0, y0, x0, y0, fov, light);
}

/* par: I, h, and for a window the half extents X, Y on the plane (0: none). */
static double window_E(const double *par, double x, double y)
{
    double I = par[0], h = par[1], d2 = h * h + x * x + y * y;
    if (par[2] > 0.0 && (fabs(x) > par[2] || fabs(y) > par[3])) return 0.0;
    return I * h / (d2 * sqrt(d2));
}

/* The mean of window_E over the footprint of a camera at (x0, y0) (64 x 64
   midpoint rule: exact for a window edge through the footprint's centre). */
static double footprint_mean(const double *par, double x0, double y0, double fov)
{
    double a = 5.0 * tan(0.5 * fov * SPECNEE_PI / 180.0), sum = 0.0;
    int i, j, n = 64;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            sum += window_E(par, x0 + a * (2.0 * (i + 0.5) / n - 1.0), y0 + a * (2.0 * (j + 0.5) / n - 1.0));
    return sum / ((double)n * n);
}

/* Render text with strategy st (6 seeds) and hold its luminance to E / pi. */
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

/* ------------------------------------------------------------------ goniometric */
/* A constant image of 1: the point light I h / d^3, under rotations of its frame
   (the y <-> z swap and the inverse CTM must not matter), with an rgb I. */
static void test_gonio_point(T *t)
{
    static const char *const fmt[] = {
        "AttributeBegin\nTranslate 0 0 2\nLightSource \"goniometric\" \"float scale\" [ 3 ] "
        "\"string filename\" \"%s\"\nAttributeEnd",
        "AttributeBegin\nTranslate 0 0 1.5\nRotate 70 1 1 0\nLightSource \"goniometric\" "
        "\"rgb I\" [ 1 0.5 0.2 ] \"float scale\" [ 2 ] \"string filename\" \"%s\"\nAttributeEnd",
    };
    const double I[2] = { 3.0, 2.0 * (0.212671 * 1.0 + 0.715160 * 0.5 + 0.072169 * 0.2) };
    const double h[2] = { 2.0, 1.5 };
    SelStrategy strategies[3] = { SEL_SPECTRAL_TREE, SEL_SPATIAL, SEL_POWER };
    const char *img = const_image(t, "gonio_white.pfm", 4, 4, 1.0f);
    int c, k, x;
    CHECK(t, img != NULL, "cannot write a test image");
    for (c = 0; c < 2; c++)
        for (x = 0; x < 2; x++) {
            char light[512], text[4096];
            double par[4] = { 0, 0, 0, 0 }, E, x0 = 1.2 * x;
            par[0] = I[c];
            par[1] = h[c];
            snprintf(light, sizeof light, fmt[c], img);
            plane_scene(text, sizeof text, x0, 0.0, 6.0, light);
            E = footprint_mean(par, x0, 0.0, 6.0);
            for (k = 0; k < 3; k++)
                if (!check_render(t, text, strategies[k], E, c ? "goniometric, rgb I, rotated" :
                                  "goniometric, constant image")) return;
        }
}

/* The first emitter of text (the light under test). */
static int load_light(T *t, Scene *s, const char *light)
{
    char text[4096];
    plane_scene(text, sizeof text, 0.0, 0.0, 6.0, light);
    if (!test_load_scene(t, s, text)) return 0;
    if (s->n_emitters == 1 && s->emitters[0].delta.type != DELTA_NONE) return 1;
    test_failf(t, __FILE__, __LINE__, "no delta light");
    scene_free(s);
    return 0;
}

/* "power" 7 with a non-uniform image: the luminous intensity scale x g(w) (L is
   normalised to luminance 1) integrated over the sphere, a 1024 x 2048 midpoint
   rule in (cos theta, phi), is 7 within 1e-3. */
static void test_gonio_power(T *t)
{
    Scene s;
    const DeltaLight *d;
    double sum = 0.0;
    int i, j, nt = 1024, np = 2048;
    if (!load_light(t, &s, "AttributeBegin\nTranslate 0 0 2\nRotate 30 0 1 0\nLightSource \"goniometric\" "
                    "\"blackbody I\" [ 4000 ] \"float power\" [ 7 ] \"string filename\" "
                    "\"tests/data/lights/gonio16.pfm\"\nAttributeEnd"))
        return;
    d = &s.emitters[0].delta;
    for (i = 0; i < nt; i++) {
        double ct = -1.0 + 2.0 * (i + 0.5) / nt, st = sqrt(1.0 - ct * ct);
        for (j = 0; j < np; j++) {
            double ph = 2.0 * SPECNEE_PI * (j + 0.5) / np;
            sum += delta_falloff(d, v3((float)(st * cos(ph)), (float)(st * sin(ph)), (float)ct));
        }
    }
    sum *= s.emitters[0].scale * 4.0 * SPECNEE_PI / ((double)nt * np);
    CHECK(t, fabs(sum - 7.0) < 7e-3, "goniometric power 7: integrated intensity %.6g", sum);
    CHECK(t, fabs(SPECNEE_PI * s.emitters[0].area * s.emitters[0].scale - 7.0) < 7e-3,
          "goniometric power 7: the selection power pi area scale = %.6g",
          SPECNEE_PI * s.emitters[0].area * s.emitters[0].scale);
    scene_free(&s);
}

/* ------------------------------------------------------------------ projection */
/* A grey 8 x 4 image (aspect 2: window [-2, 2] x [-1, 1] in units of t =
   tan(fov/2)) of fov 60 from height h = 2 straight down (Rotate 180 about x:
   light z -> world -z), scale 3: I = 1.5 inside |x| <= X = 2 h t, |y| <= Y = h t;
   footprints inside, centred on each edge and on a corner, and outside. */
static void test_projection_frustum(T *t)
{
    const double h = 2.0, tt = tan(30.0 * SPECNEE_PI / 180.0);
    const double X = 2.0 * h * tt, Y = h * tt;
    const double at[][2] = { { 0.0, 0.0 }, { 0.3 * X, -0.5 * Y }, { X, 0.0 }, { 0.0, -Y }, { -X, Y },
                             { 1.3 * X, 0.0 }, { 0.0, 1.4 * Y } };
    SelStrategy strategies[3] = { SEL_SPECTRAL_TREE, SEL_SPATIAL, SEL_UNIFORM };
    const char *img = const_image(t, "proj_grey.pfm", 8, 4, 0.5f);
    char light[512];
    int i, k;
    CHECK(t, img != NULL, "cannot write a test image");
    snprintf(light, sizeof light, "AttributeBegin\nTranslate 0 0 2\nRotate 180 1 0 0\n"
             "LightSource \"projection\" \"float fov\" [ 60 ] \"float scale\" [ 3 ] "
             "\"string filename\" \"%s\"\nAttributeEnd", img);
    for (i = 0; i < (int)(sizeof at / sizeof at[0]); i++) {
        char text[4096], what[96];
        double par[4], E;
        par[0] = 1.5;
        par[1] = h;
        par[2] = X;
        par[3] = Y;
        plane_scene(text, sizeof text, at[i][0], at[i][1], 4.0, light);
        E = footprint_mean(par, at[i][0], at[i][1], 4.0);
        snprintf(what, sizeof what, "projection at (%.3g, %.3g), E %.4g", at[i][0], at[i][1], E);
        for (k = 0; k < 3; k++)
            if (!check_render(t, text, strategies[k], E, what)) return;
    }
}

/* "power" 20 with a grey 64 x 32 image (fov 50, tilted): its intensity, 0.5 x
   scale inside the window (the texel's spectrum 0.5 D65 at every wavelength,
   checked at three), integrated over the plane z = 1 of the light's frame
   (dw = cos^3 dA, a 1600 x 800 midpoint rule over a rectangle 1.25 times the
   window, whose edges fall on cell boundaries, delta_falloff telling inside from
   outside) is 20 within 1e-3 (pbrt-v4 takes cos^3 at the texels' centres: 1e-4
   off here). */
static void test_projection_power(T *t)
{
    Scene s;
    const Emitter *em;
    const char *img = const_image(t, "proj_grey64.pfm", 64, 32, 0.5f);
    char light[512];
    double tt = tan(25.0 * SPECNEE_PI / 180.0), bx = 2.5 * tt, by = 1.25 * tt, sum = 0.0, k;
    int i, j, nx = 1600, ny = 800;
    CHECK(t, img != NULL, "cannot write a test image");
    snprintf(light, sizeof light, "AttributeBegin\nTranslate 0 0 2\nRotate 160 1 0 0\n"
             "LightSource \"projection\" \"float fov\" [ 50 ] \"float power\" [ 20 ] "
             "\"string filename\" \"%s\"\nAttributeEnd", img);
    if (!load_light(t, &s, light)) return;
    em = &s.emitters[0];
    k = em->scale / luminance_sum(em->L, 360.0f, 830.0f);
    for (i = 0; i < 3; i++) {
        float lam = 450.0f + 100.0f * i, want = (float)(0.5 * em->scale * spec_eval(em->L, lam) /
                                                        luminance_sum(em->L, 360.0f, 830.0f));
        Vec3 w = v3(0.0f, -(float)sin(20.0 * SPECNEE_PI / 180.0), -(float)cos(20.0 * SPECNEE_PI / 180.0));
        float got = delta_projection_Le(em, k, w, lam);
        CHECK(t, fabsf(got - want) < 1e-4f * want, "projection Le at %g nm: %g, want %g", lam, got, want);
    }
    for (i = 0; i < nx; i++)
        for (j = 0; j < ny; j++) {
            /* (x, y, 1) in the light's frame (y flipped: symmetric) to the world:
               Rotate 160 about x */
            double x = bx * (2.0 * (i + 0.5) / nx - 1.0), y = by * (2.0 * (j + 0.5) / ny - 1.0);
            double c = cos(160.0 * SPECNEE_PI / 180.0), sn = sin(160.0 * SPECNEE_PI / 180.0);
            double r2 = 1.0 + x * x + y * y, r = sqrt(r2);
            Vec3 w = v3((float)(x / r), (float)((c * y - sn) / r), (float)((sn * y + c) / r));
            sum += delta_falloff(&em->delta, w) / (r2 * r);
        }
    sum *= 0.5 * em->scale * (2.0 * bx) * (2.0 * by) / ((double)nx * ny);
    CHECK(t, fabs(sum - 20.0) < 2e-2, "projection power 20: integrated intensity %.6g", sum);
    {
        /* nothing behind the light: the mirror image of the axis (pbrt-v4's v_z >= 1e-3) */
        double c = cos(160.0 * SPECNEE_PI / 180.0), sn = sin(160.0 * SPECNEE_PI / 180.0);
        CHECK(t, delta_falloff(&em->delta, v3(0.0f, (float)sn, (float)-c)) == 0.0f &&
              delta_falloff(&em->delta, v3(0.0f, (float)-sn, (float)c)) == 1.0f,
              "projection: the axis lit, the opposite direction dark");
    }
    scene_free(&s);
    /* selection by power: beside a point light of power 20 the power strategy
       picks either with probability 1/2 (the projection's power area and stand-in
       spectrum make pi area int Le its power) */
    {
        char two[1024];
        SelOptions o;
        LightSampler *ls;
        LightCtx c;
        Error err;
        double p0, p1;
        snprintf(two, sizeof two, "%s\nLightSource \"point\" \"float power\" [ 20 ] \"point3 from\" [ 0 0 3 ]",
                 light);
        {
            char text[4096];
            plane_scene(text, sizeof text, 0.0, 0.0, 6.0, two);
            if (!test_load_scene(t, &s, text)) return;
        }
        memset(&o, 0, sizeof o);
        o.strategy = SEL_POWER;
        ls = light_sampler_build(&s, &o, &err);
        CHECK(t, ls != NULL, "%s", err.msg);
        memset(&c, 0, sizeof c);
        p0 = light_select_pmf(ls, &c, 0);
        p1 = light_select_pmf(ls, &c, 1);
        CHECK(t, fabs(p0 - 0.5) < 1e-3 && fabs(p1 - 0.5) < 1e-3,
              "projection and point light of power 20: P = %.6g, %.6g; want 1/2 each", p0, p1);
        light_sampler_free(ls);
        scene_free(&s);
    }
}

/* ------------------------------------------------------------------ pbrt-v4 */
static const char *const GONIO_SCENE =
    "LookAt 0 -3 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 50 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ]\n"
    "AttributeBegin\nTranslate 0.3 0.2 1.5\nRotate 30 1 0 0\nRotate 20 0 0 1\n"
    "LightSource \"goniometric\" \"rgb I\" [ 1 0.8 0.6 ] \"float scale\" [ 3 ] "
    "\"string filename\" \"tests/data/lights/gonio16.pfm\"\nAttributeEnd\n";
static const double PBRT_GONIO_Y[5][2] = {
    { 0.037888, 6.8e-06 }, { 0.055971, 1.4e-05 }, { 0.026999, 4.3e-06 }, { 0.049282, 1.1e-05 }, { 0.019301, 4.1e-06 },
};

static const char *const PROJ_SCENE =
    "LookAt 0 0 6  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ]\n"
    "AttributeBegin\nTranslate 0.2 -0.3 2.5\nRotate 180 1 0 0\nRotate 10 0 1 0\nRotate 15 0 0 1\n"
    "LightSource \"projection\" \"float fov\" [ 90 ] \"float power\" [ 20 ] "
    "\"string filename\" \"tests/data/lights/proj16x8.pfm\"\nAttributeEnd\n";
static const double PBRT_PROJ_Y[5][2] = {
    { 0.137634, 1.8e-05 }, { 0.176967, 3.6e-05 }, { 0.137889, 4.3e-05 }, { 0.168050, 2.8e-05 }, { 0.067631, 4.2e-05 },
};

static void test_gonio_pbrt(T *t)
{
    test_against_pbrt_y(t, GONIO_SCENE, 3, PBRT_GONIO_Y, 1e-2, "goniometric");
}

static void test_projection_pbrt(T *t)
{
    test_against_pbrt_y(t, PROJ_SCENE, 3, PBRT_PROJ_Y, 1e-2, "projection");
}

/* ------------------------------------------------------------------ bad input */
static void expect_error(T *t, const char *light, const char *k1, const char *k2)
{
    test_light_refused(t, light, "d.pbrt:5:", k1, k2);
}

static void test_gonio_bad_input(T *t)
{
    char buf[512];
    const char *wide = const_image(t, "gonio_wide.pfm", 8, 4, 1.0f);
    const char *black = const_image(t, "gonio_black.pfm", 4, 4, 0.0f);
    CHECK(t, wide && black, "cannot write a test image");
    expect_error(t, "LightSource \"goniometric\"", "goniometric", "\"string filename\" is required");
    expect_error(t, "LightSource \"projection\" \"float fov\" [ 30 ]", "projection", "\"string filename\" is required");
    expect_error(t, "LightSource \"goniometric\" \"string filename\" \"no/such.pfm\"", "goniometric", "no/such.pfm");
    expect_error(t, "LightSource \"projection\" \"string filename\" \"no/such.exr\"", "projection", "no/such.exr");
    expect_error(t, "LightSource \"projection\" \"string filename\" \"a.tga\"", "projection", "PFM, EXR or PNG");
    snprintf(buf, sizeof buf, "LightSource \"goniometric\" \"string filename\" \"%s\"", wide);
    expect_error(t, buf, "goniometric", "8 x 4 is not square");
    snprintf(buf, sizeof buf, "LightSource \"goniometric\" \"string filename\" \"%s\"", black);
    expect_error(t, buf, "goniometric", "black");
    snprintf(buf, sizeof buf, "LightSource \"projection\" \"float fov\" [ 180 ] \"string filename\" \"%s\"", wide);
    expect_error(t, buf, "fov", "(0, 180)");
    snprintf(buf, sizeof buf, "LightSource \"projection\" \"float fov\" [ 0 ] \"string filename\" \"%s\"", wide);
    expect_error(t, buf, "fov", "(0, 180)");
    snprintf(buf, sizeof buf, "LightSource \"projection\" \"rgb I\" [ 1 1 1 ] \"string filename\" \"%s\"", wide);
    expect_error(t, buf, "I", "unused");
    snprintf(buf, sizeof buf, "LightSource \"goniometric\" \"float scale\" [ -1 ] \"string filename\" \"%s\"", wide);
    expect_error(t, buf, "goniometric", ">= 0");
}

const TestCase tests_gonio[] = {
    { "gonio_point", test_gonio_point },
    { "gonio_power", test_gonio_power },
    { "gonio_pbrt", test_gonio_pbrt },
    { "gonio_bad_input", test_gonio_bad_input },
    { "projection_frustum", test_projection_frustum },
    { "projection_power", test_projection_power },
    { "projection_pbrt", test_projection_pbrt },
    { NULL, NULL }
};
