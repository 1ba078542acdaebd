/* tests/test_pbrt.c - pbrt-v4 settings that real scene files use: the
   film's imaging ratio (iso, shutter interval) and clamp (maxcomponentvalue), the
   gbuffer film read as rgb, the volpath/bdpt/sppm integrators rendered by path,
   the thin-lens camera; each checked against pbrt-v4's documented formula.
   Also: Accelerator read and ignored, the command line's output file over
   Film's "string filename".

   The scenes are a square emitter facing a camera at the origin that looks down
   +z (no LookAt: camera space is world space), on a black background, so every
   pixel value is the emitter's radiance times the fraction of the pixel (and of
   the lens) that sees it. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* A two-sided square emitter of half-size 0.5 at depth 5, luminance `scale`,
   seen by a 64x64 camera with a 30 degree fov and a box filter; `camera` and
   `film` are extra parameters. */
static void square_scene_film(char *buf, size_t cap, const char *type, const char *camera,
                              const char *film, float scale)
{
    snprintf(buf, cap,
             "Film \"%s\" \"integer xresolution\" 64 \"integer yresolution\" 64 %s\n"
             "PixelFilter \"box\"\n"
             "Camera \"perspective\" \"float fov\" 30 %s\n"
             "WorldBegin\n"
             "AttributeBegin\n"
             " AreaLightSource \"diffuse\" \"bool twosided\" true \"float scale\" %g\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -0.5 -0.5 5  0.5 -0.5 5  0.5 0.5 5  -0.5 0.5 5 ]\n"
             "AttributeEnd\n", type, film, camera, scale);
}

static void square_scene(char *buf, size_t cap, const char *camera, const char *film, float scale)
{
    square_scene_film(buf, cap, "rgb", camera, film, scale);
}

static int render_text(T *t, const char *text, int spp, Image *im)
{
    RenderOptions o;
    render_options_default(&o);
    o.spp = spp;
    o.seed = 5;
    o.threads = 2;
    return test_render_text(t, text, &o, im);
}

/* pbrt-v4 PixelSensor::Create: imaging ratio = exposure time * ISO / 100, the
   exposure time being Camera shutterclose - shutteropen.  The image scales by
   exactly that ratio (same paths, every sample multiplied). */
static void test_iso_exposure(T *t)
{
    static char buf[4096];
    Image a, b, c;
    int i;
    square_scene(buf, sizeof buf, "", "", 1.0f);
    if (!render_text(t, buf, 2, &a)) return;
    square_scene(buf, sizeof buf, "", "\"float iso\" 300", 1.0f);
    if (!render_text(t, buf, 2, &b)) { img_free(&a); return; }
    square_scene(buf, sizeof buf, "\"float shutteropen\" 0.25 \"float shutterclose\" 0.75",
                 "\"float iso\" 400", 1.0f);
    if (!render_text(t, buf, 2, &c)) { img_free(&a); img_free(&b); return; }
    for (i = 0; i < 3 * a.w * a.h; i++) {
        double x = a.rgb[i];
        if (!(fabs(b.rgb[i] - 3.0 * x) <= 1e-6 * fabs(3.0 * x)) ||
            !(fabs(c.rgb[i] - 2.0 * x) <= 1e-6 * fabs(2.0 * x))) {
            test_failf(t, __FILE__, __LINE__, "value %d: %g, with iso 300: %g (want x3), with "
                       "iso 400 and a 0.5 shutter: %g (want x2)", i, x, b.rgb[i], c.rgb[i]);
            break;
        }
    }
    CHECK(t, !t->failed, "(see above)");
    img_free(&a); img_free(&b); img_free(&c);
    {
        Scene s;
        Error e;
        square_scene(buf, sizeof buf, "\"float shutteropen\" 1 \"float shutterclose\" 1", "", 1.0f);
        CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, "t.pbrt:3:") &&
              strstr(e.msg, "never opens"), "a closed shutter is accepted: %s", e.msg);
        scene_free(&s);
    }
}

/* Linear sRGB back to XYZ (the inverse of xyz_to_linear_srgb, by columns). */
static void srgb_to_xyz(const float rgb[3], double xyz[3])
{
    double M[3][3], inv[3][3], det;
    int i, j;
    for (j = 0; j < 3; j++) {
        double e[3] = { 0, 0, 0 }, r[3];
        e[j] = 1.0;
        xyz_to_linear_srgb(e, r);
        for (i = 0; i < 3; i++) M[i][j] = r[i];
    }
    det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0])
        + M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
            inv[i][j] = (M[a][c] * M[b][d] - M[a][d] * M[b][c]) / det;
        }
    for (i = 0; i < 3; i++) xyz[i] = inv[i][0] * rgb[0] + inv[i][1] * rgb[1] + inv[i][2] * rgb[2];
}

/* pbrt-v4 RGBFilm::AddSample: each sample's sensor RGB (XYZ for the default
   cie1931 sensor) is scaled down so that its largest component is at most
   maxcomponentvalue.  So no pixel's XYZ can exceed it; without the clamp the
   bright emitter (Y = 10) does; a clamp above every sample changes nothing. */
static void test_maxcomponentvalue(T *t)
{
    static char buf[4096];
    Image a, b, c;
    double worst = 0.0, worst_free = 0.0;
    int i, k;
    square_scene(buf, sizeof buf, "", "", 10.0f);
    if (!render_text(t, buf, 4, &a)) return;
    square_scene(buf, sizeof buf, "", "\"float maxcomponentvalue\" 2", 10.0f);
    if (!render_text(t, buf, 4, &b)) { img_free(&a); return; }
    square_scene(buf, sizeof buf, "", "\"float maxcomponentvalue\" 1e30", 10.0f);
    if (!render_text(t, buf, 4, &c)) { img_free(&a); img_free(&b); return; }
    for (i = 0; i < a.w * a.h; i++) {
        double xa[3], xb[3];
        srgb_to_xyz(&a.rgb[3 * i], xa);
        srgb_to_xyz(&b.rgb[3 * i], xb);
        for (k = 0; k < 3; k++) {
            if (xb[k] > worst) worst = xb[k];
            if (xa[k] > worst_free) worst_free = xa[k];
        }
    }
    CHECK(t, worst_free > 5.0, "the unclamped image peaks at XYZ %g only: the test has no power", worst_free);
    CHECK(t, worst <= 2.0 * (1.0 + 1e-5), "a clamped pixel has an XYZ component %g > 2", worst);
    CHECK(t, worst > 1.9, "the clamped image peaks at %g, far below the clamp 2", worst);
    CHECK(t, memcmp(a.rgb, c.rgb, sizeof(float) * 3 * (size_t)a.w * a.h) == 0,
          "a clamp of 1e30 changed the image");
    img_free(&a); img_free(&b); img_free(&c);
}

/* The clamp takes the LARGEST component, whichever it is: under a red lamp (600
   to 700 nm, where xbar > ybar and zbar is nearly 0) X is the largest of every
   sample, so the clamped image's X stays at or below maxcomponentvalue, and
   only the clamp keeps it there. */
static void test_maxcomponentvalue_red(T *t)
{
    static char buf[4096];
    static const char *const lamp =
        "WorldBegin\nAttributeBegin\n"
        " AreaLightSource \"diffuse\" \"bool twosided\" true \"spectrum L\" [ 360 0  595 0  600 1  700 1  705 0  830 0 ]"
        " \"float scale\" 10\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -0.5 -0.5 5  0.5 -0.5 5  0.5 0.5 5  -0.5 0.5 5 ]\nAttributeEnd\n";
    Image a, b;
    double xa = 0.0, xb = 0.0;
    int i, k;
    for (k = 0; k < 2; k++) {
        snprintf(buf, sizeof buf, "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32 %s\n"
                 "PixelFilter \"box\"\nCamera \"perspective\" \"float fov\" 30\n%s",
                 k ? "\"float maxcomponentvalue\" 2" : "", lamp);
        if (!render_text(t, buf, 4, k ? &b : &a)) { if (k) img_free(&a); return; }
    }
    for (i = 0; i < a.w * a.h; i++) {
        double x[3];
        srgb_to_xyz(&a.rgb[3 * i], x);
        xa = fmax(xa, x[0]);
        srgb_to_xyz(&b.rgb[3 * i], x);
        xb = fmax(xb, x[0]);
    }
    CHECK(t, xa > 5.0, "the unclamped red image peaks at X %g only: the test has no power", xa);
    CHECK(t, xb <= 2.0 * (1.0 + 1e-5), "a clamped pixel under the red lamp has X %g > 2", xb);
    img_free(&a); img_free(&b);
}

/* Film "gbuffer" is read as "rgb" (same settings, same image), Integrator
   volpath, bdpt, sppm and simplepath render as path with their maxdepth; parameters those
   integrators do not read stay errors, as in pbrt-v4. */
static void test_film_and_integrator_aliases(T *t)
{
    static const char *const integ[] = { "volpath", "bdpt", "sppm", "simplepath" };
    static char buf[4096], text[8192];
    Image ref, im;
    Scene s;
    Error e;
    int i;
    square_scene(buf, sizeof buf, "", "", 1.0f);
    snprintf(text, sizeof text, "Integrator \"path\" \"integer maxdepth\" 3\n%s", buf);
    if (!render_text(t, text, 2, &ref)) return;
    for (i = 0; i < 5; i++) {
        int same;
        if (i < 4) snprintf(text, sizeof text, "Integrator \"%s\" \"integer maxdepth\" 3\n%s", integ[i], buf);
        else {
            char g[4096];
            square_scene_film(g, sizeof g, "gbuffer", "", "\"string filename\" \"g.exr\"", 1.0f);
            snprintf(text, sizeof text, "Integrator \"path\" \"integer maxdepth\" 3\n%s", g);
        }
        CHECK(t, test_load_scene(t, &s, text), "(load)");
        CHECK(t, s.settings.maxdepth == 3 && s.settings.maxdepth_set, "%s: maxdepth not read",
              i < 4 ? integ[i] : "gbuffer");
        scene_free(&s);
        if (!render_text(t, text, 2, &im)) { img_free(&ref); return; }
        same = memcmp(im.rgb, ref.rgb, sizeof(float) * 3 * (size_t)im.w * im.h) == 0;
        img_free(&im);
        if (!same) { img_free(&ref); CHECK(t, 0, "%s: not the path image", i < 4 ? integ[i] : "gbuffer"); }
    }
    img_free(&ref);
    CHECK(t, !scene_load_string(&s, "Integrator \"bdpt\" \"string lightsampler\" \"bvh\"\nWorldBegin\n",
                                "t.pbrt", &e) && strstr(e.msg, "t.pbrt:1:") && strstr(e.msg, "lightsampler"),
          "bdpt accepted a lightsampler (pbrt-v4 does not read one): %s", e.msg);
    scene_free(&s);
    CHECK(t, !scene_load_string(&s, "Integrator \"bdpt\" \"bool visualizestrategies\" true\nWorldBegin\n",
                                "t.pbrt", &e) && strstr(e.msg, "visualizestrategies"),
          "bdpt's visualizestrategies accepted: %s", e.msg);
    scene_free(&s);
    /* simplepath reads samplelights and samplebsdf (any value: every variant is
       unbiased), not a lightsampler */
    CHECK(t, scene_load_string(&s, "Integrator \"simplepath\" \"bool samplelights\" false "
                               "\"bool samplebsdf\" true\nWorldBegin\n", "t.pbrt", &e), "%s", e.msg);
    scene_free(&s);
    CHECK(t, !scene_load_string(&s, "Integrator \"simplepath\" \"string lightsampler\" \"bvh\"\nWorldBegin\n",
                                "t.pbrt", &e) && strstr(e.msg, "lightsampler"),
          "simplepath accepted a lightsampler (pbrt-v4 does not read one): %s", e.msg);
    scene_free(&s);
}

/* Second moment about the centroid of the image's luminance (pixel centres),
   and the total. */
static void image_moments(const Image *im, double *total, double *m2)
{
    double sw = 0, sx = 0, sy = 0, sxx = 0;
    int x, y;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++) {
            double w = im->rgb[3 * (y * im->w + x) + 1];
            sw += w; sx += w * (x + 0.5); sy += w * (y + 0.5);
            sxx += w * ((x + 0.5) * (x + 0.5) + (y + 0.5) * (y + 0.5));
        }
    *total = sw;
    *m2 = sw > 0 ? sxx / sw - (sx * sx + sy * sy) / (sw * sw) : 0.0;
}

/* Thin lens (pbrt-v4 PerspectiveCamera): a point at depth z seen through a lens
   of radius r focused at f spreads into a disk of radius r |1/f - 1/z| in tan
   units, i.e. R = r |1/f - 1/z| (h/2) / tan(fov/2) pixels (h = 64, fov = 30).
   Blurring adds the disk's second moment R^2/2 to the image's (moments of
   independent offsets add), keeps the image's total, and a lens focused on the
   square leaves it as sharp as the pinhole.  With r = 1/3, f = 2, z = 5:
   R = 0.1 tan units = 11.9 pixels, R^2/2 = 71.3 pixels^2 against a pinhole
   moment of 95 (the square, 2 a^2/3 with a = 11.9) + 1/6 (the pixels). */
static void test_thin_lens(T *t)
{
    static char buf[4096];
    Image pin, blur, sharp;
    double t0, m0, t1, m1, t2, m2, R, want;
    int spp = test_scaled(32, 16);
    square_scene(buf, sizeof buf, "", "", 1.0f);
    if (!render_text(t, buf, spp, &pin)) return;
    square_scene(buf, sizeof buf, "\"float lensradius\" 0.333333 \"float focaldistance\" 2", "", 1.0f);
    if (!render_text(t, buf, spp, &blur)) { img_free(&pin); return; }
    square_scene(buf, sizeof buf, "\"float lensradius\" 0.333333 \"float focaldistance\" 5", "", 1.0f);
    if (!render_text(t, buf, spp, &sharp)) { img_free(&pin); img_free(&blur); return; }
    image_moments(&pin, &t0, &m0);
    image_moments(&blur, &t1, &m1);
    image_moments(&sharp, &t2, &m2);
    img_free(&pin); img_free(&blur); img_free(&sharp);
    R = 0.333333 * fabs(1.0 / 2.0 - 1.0 / 5.0) * 32.0 / tan(15.0 * SPECNEE_PI / 180.0);
    want = m0 + R * R / 2.0;
    CHECK(t, fabs(m0 - (2.0 / 3.0 * pow(0.1 * 32.0 / tan(15.0 * SPECNEE_PI / 180.0), 2) + 1.0 / 6.0)) < 0.02 * m0,
          "pinhole: second moment %g, want that of the square", m0);
    CHECK(t, fabs(m1 - want) < 0.03 * want, "out of focus: second moment %g, want %g + R^2/2 = %g "
          "(R = %.2f pixels)", m1, m0, want, R);
    CHECK(t, fabs(m2 - m0) < 0.02 * m0, "in focus: second moment %g, the pinhole's %g", m2, m0);
    CHECK(t, fabs(t1 - t0) < 0.02 * t0 && fabs(t2 - t0) < 0.02 * t0,
          "the lens changed the image's total: %g, %g vs %g", t1, t2, t0);
    {
        Scene s;
        Error e;
        square_scene(buf, sizeof buf, "\"float lensradius\" -1", "", 1.0f);
        CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, "lensradius"),
              "a negative lens radius is accepted: %s", e.msg);
        scene_free(&s);
    }
}

/* Camera "screenwindow" and "frameaspectratio" (pbrt-v4 PerspectiveCamera): two
   small square emitters (0.4 wide at depth 10, centres (2, -1) and (4, -3), the
   second twice as bright) on a 40 x 24 film with a 50 degree fov, box filter.
   The luminance centroid and total of each (left of column `split`, right of it)
   are pbrt-v4's, frozen from the oracle at 16384 spp (Sampler "independent"):
     pbrt --outfile sw.pfm sw.pbrt   (screenwindow [-0.3 1.1 -0.9 0.2], split 26)
     pbrt --outfile fa.pfm fa.pbrt   (frameaspectratio 0.8, split 32)
   with each pixel's G channel as the luminance, pixel centres at x + 0.5.
   The centroids agree with the window's map, sx = x0 + (x / w)(x1 - x0), to the
   box filter's discretisation (emitter A: 20.83, 9.04 analytic). */
static void screen_centroids(const Image *im, int split, double tot[2], double cx[2], double cy[2])
{
    int x, y, k;
    for (k = 0; k < 2; k++) tot[k] = cx[k] = cy[k] = 0.0;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++) {
            double v = im->rgb[3 * (y * im->w + x) + 1];
            k = x >= split;                    /* 0: emitter A, 1: B */
            tot[k] += v; cx[k] += v * (x + 0.5); cy[k] += v * (y + 0.5);
        }
    for (k = 0; k < 2; k++)
        if (tot[k] > 0.0) { cx[k] /= tot[k]; cy[k] /= tot[k]; }
}

static void test_screen_window(T *t)
{
    static const struct {
        const char *camera;
        int split;
        double tot[2], cx[2], cy[2];           /* pbrt-v4, 16384 spp */
    } c[] = {
        { "\"float screenwindow\" [ -0.3 1.1 -0.9 0.2 ]", 26,
          { 4.588409, 9.185547 }, { 20.7915, 33.0963 }, { 9.0223, 18.3957 } },
        { "\"float frameaspectratio\" 0.8", 32,
          { 1.404846, 2.840012 }, { 28.5922, 37.1011 }, { 14.0731, 18.2121 } },
    };
    static char buf[4096];
    int i, k, spp = test_scaled(512, 128);
    for (i = 0; i < 2; i++) {
        Image im;
        double tot[2], cx[2], cy[2];
        snprintf(buf, sizeof buf,
                 "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 24\n"
                 "PixelFilter \"box\"\n"
                 "Camera \"perspective\" \"float fov\" 50 %s\n"
                 "WorldBegin\n"
                 "AttributeBegin\n"
                 " AreaLightSource \"diffuse\" \"bool twosided\" true\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "  \"point3 P\" [ 1.8 -1.2 10  2.2 -1.2 10  2.2 -0.8 10  1.8 -0.8 10 ]\n"
                 "AttributeEnd\n"
                 "AttributeBegin\n"
                 " AreaLightSource \"diffuse\" \"bool twosided\" true \"float scale\" 2\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "  \"point3 P\" [ 3.8 -3.2 10  4.2 -3.2 10  4.2 -2.8 10  3.8 -2.8 10 ]\n"
                 "AttributeEnd\n", c[i].camera);
        if (!render_text(t, buf, spp, &im)) return;
        screen_centroids(&im, c[i].split, tot, cx, cy);
        img_free(&im);
        for (k = 0; k < 2; k++) {
            CHECK(t, fabs(cx[k] - c[i].cx[k]) < 0.1 && fabs(cy[k] - c[i].cy[k]) < 0.1,
                  "%s: emitter %c at (%.3f, %.3f) pixels, pbrt-v4 (%.3f, %.3f)", c[i].camera,
                  'A' + k, cx[k], cy[k], c[i].cx[k], c[i].cy[k]);
            CHECK(t, fabs(tot[k] - c[i].tot[k]) < 0.05 * c[i].tot[k],
                  "%s: emitter %c's total %.4f, pbrt-v4 %.4f", c[i].camera, 'A' + k, tot[k],
                  c[i].tot[k]);
        }
    }
    {   /* what pbrt-v4 cannot give a meaning (it reports a wrong count and goes on) */
        static const char *bad[][2] = {
            { "\"float screenwindow\" [ -1 1 -1 ]", "\"float screenwindow\": 3 values, expected 4" },
            { "\"float screenwindow\" [ -1 -1 -1 1 ]", "must be finite with x0 != x1 and y0 != y1" },
            { "\"float frameaspectratio\" 0", "\"float frameaspectratio\" 0 must be finite and > 0" },
        };
        for (i = 0; i < 3; i++) {
            Scene s;
            Error e;
            snprintf(buf, sizeof buf, "Camera \"perspective\" %s\nWorldBegin\n", bad[i][0]);
            CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, bad[i][1]),
                  "%s: want \"%s\", got: %s", bad[i][0], bad[i][1], e.msg);
            scene_free(&s);
        }
    }
}

/* "rgb eta" on a dielectric: pbrt-v4 reads it as an RGBUnboundedSpectrum.  A
   glass sphere (radius 1.2 at depth 5) before an emitter that fills the left
   half of the background (x < 0.3 at depth 10), 32 x 32, 30 degree fov, box
   filter.  Grey (1.5, 1.5, 1.5) is the constant 1.5 (pbrt-v4's sigmoid of 0
   times 2 max = 3): the image of "float eta" 1.5, bit for bit (a dielectric's
   and a thindielectric's).  The coloured
   index (1.2, 1.5, 1.9): the mean R, G, B of the left and right halves are
   pbrt-v4's at 16384 spp, frozen from the oracle (Sampler "independent"):
     pbrt --outfile eta_c.pfm eta_c.pbrt
   (its "float eta" 1.5 render gives 0.5154 and 0.5653 in every channel). */
static void test_rgb_eta(T *t)
{
    static const double want[2][3] = { { 0.816935, 0.512795, 0.429795 },
                                       { 0.610085, 0.567645, 0.478295 } };
    static const char *eta[5] = { "\"float eta\" 1.5", "\"rgb eta\" [ 1.5 1.5 1.5 ]",
                                  "\"rgb eta\" [ 1.2 1.5 1.9 ]", "\"float eta\" 1.5",
                                  "\"rgb eta\" [ 1.5 1.5 1.5 ]" };
    static char buf[4096];
    Image im[5];
    int i, h, c, x, y, spp = test_scaled(512, 128);
    for (i = 0; i < 5; i++) {
        snprintf(buf, sizeof buf,
                 "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n"
                 "PixelFilter \"box\"\n"
                 "Camera \"perspective\" \"float fov\" 30\n"
                 "WorldBegin\n"
                 "AttributeBegin\n"
                 " AreaLightSource \"diffuse\" \"bool twosided\" true\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "  \"point3 P\" [ -10 -10 10  0.3 -10 10  0.3 10 10  -10 10 10 ]\n"
                 "AttributeEnd\n"
                 "AttributeBegin\n"
                 " Material \"%s\" %s\n"
                 " Translate 0 0 5\n"
                 " Shape \"sphere\" \"float radius\" 1.2\n"
                 "AttributeEnd\n", i < 3 ? "dielectric" : "thindielectric", eta[i]);
        if (!render_text(t, buf, i == 2 ? spp : 4, &im[i])) {
            while (i-- > 0) img_free(&im[i]);
            return;
        }
    }
    CHECK(t, memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * 32 * 32) == 0,
          "\"rgb eta\" [1.5 1.5 1.5] renders unlike \"float eta\" 1.5");
    CHECK(t, memcmp(im[3].rgb, im[4].rgb, sizeof(float) * 3 * 32 * 32) == 0,
          "thindielectric: \"rgb eta\" [1.5 1.5 1.5] renders unlike \"float eta\" 1.5");
    for (h = 0; h < 2; h++)
        for (c = 0; c < 3; c++) {
            double m = 0.0;
            for (y = 0; y < 32; y++)
                for (x = 16 * h; x < 16 * h + 16; x++) m += im[2].rgb[3 * (y * 32 + x) + c];
            m /= 16.0 * 32.0;
            CHECK(t, fabs(m - want[h][c]) < 0.02 * want[h][c],
                  "\"rgb eta\" [1.2 1.5 1.9]: %s half, %c = %.4f, pbrt-v4 %.4f",
                  h ? "right" : "left", "RGB"[c], m, want[h][c]);
        }
    for (i = 0; i < 5; i++) img_free(&im[i]);
}

/* A diffuse "spectrum reflectance" outside [0, 1]: pbrt-v4 reads it and clamps
   each value to [0, 1] where it uses it (DiffuseMaterial::GetBxDF); an "rgb"
   above 1 it refuses, and so does specnee.  An 8 x 8 view (fov 10) filled by a
   diffuse sphere (radius 1 at depth 5) under LightSource "infinite" "rgb L"
   [1 1 1]: a convex surface in a uniform sky shows its reflectance times the
   sky.  1.5 everywhere is 1 everywhere, bit for bit; two ramps crossing 1 and 0
   between 550 and 560 nm give pbrt-v4's mean R, G, B at 65536 spp, frozen from
   the oracle (Sampler "independent"):  pbrt --outfile refl_mix.pfm refl_mix.pbrt
   (the sphere at 1.5: 1.00003 0.99999 0.99970). */
static void test_reflectance_clamp(T *t)
{
    static const struct { const char *refl; double rgb[3]; } c[] = {
        { "[ 300 1.5 800 1.5 ]", { 0, 0, 0 } },
        { "[ 300 1 800 1 ]", { 0, 0, 0 } },
        { "[ 300 0.2 550 0.2 560 1.6 800 1.6 ]", { 1.32860, 0.45687, 0.14568 } },
        { "[ 300 -0.5 550 -0.5 560 0.7 800 0.7 ]", { 0.98412, 0.18538, -0.04265 } },
    };
    static char buf[2048];
    Image im[4];
    int i, k, n = 0, spp = test_scaled(1024, 256);
    for (i = 0; i < 4; i++, n++) {
        snprintf(buf, sizeof buf,
                 "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n"
                 "PixelFilter \"box\"\n"
                 "Camera \"perspective\" \"float fov\" 10\n"
                 "WorldBegin\n"
                 "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
                 "Material \"diffuse\" \"spectrum reflectance\" %s\n"
                 "Translate 0 0 5\n"
                 "Shape \"sphere\" \"float radius\" 1\n", c[i].refl);
        if (!render_text(t, buf, i < 2 ? 16 : spp, &im[i])) break;
    }
    if (n == 4) {
        CHECK(t, memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * 64) == 0,
              "a reflectance of 1.5 renders unlike 1: not clamped");
        for (i = 2; i < 4; i++)
            for (k = 0; k < 3; k++) {
                double m = 0.0;
                int j;
                for (j = 0; j < 64; j++) m += im[i].rgb[3 * j + k];
                m /= 64.0;
                CHECK(t, fabs(m - c[i].rgb[k]) < 0.01, "%s: mean %c %.4f, pbrt-v4 %.4f",
                      c[i].refl, "RGB"[k], m, c[i].rgb[k]);
            }
    }
    while (n-- > 0) img_free(&im[n]);
    {
        Scene s;
        Error e;
        snprintf(buf, sizeof buf, "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 1.5 1 1 ]\n");
        CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, "t.pbrt:2:") &&
              strstr(e.msg, "a reflectance must be within [0,1]"),
              "an rgb reflectance above 1 (pbrt-v4 refuses it) is accepted: %s", e.msg);
        scene_free(&s);
    }
}

/* ---------------------------------------------------------------- infinite lights */

/* pbrt-v4's equal-area octahedral map: the inverse undoes it, +z is the centre,
   and it is equal-area: uniform points of the square give z uniform in [-1, 1]
   (Archimedes), checked by chi-square over 20 bins of z. */
static void test_equal_area_map(T *t)
{
    Rng r;
    int i, n = test_scaled(40000, 10000);
    double bins[20] = { 0 }, ex[20];
    Vec3 c = equal_area_square_to_sphere(0.5f, 0.5f);
    CHECK(t, fabsf(c.z - 1.0f) < 1e-6f, "the centre maps to (%g %g %g), not +z", c.x, c.y, c.z);
    c = equal_area_square_to_sphere(0.0f, 0.0f);
    CHECK(t, fabsf(c.z + 1.0f) < 1e-6f, "a corner maps to (%g %g %g), not -z", c.x, c.y, c.z);
    rng_seed(&r, 11, 0);
    for (i = 0; i < n; i++) {
        float u = rng_float(&r), v = rng_float(&r), u2, v2;
        Vec3 d = equal_area_square_to_sphere(u, v);
        int b = (int)((d.z + 1.0f) * 10.0f);
        CHECK(t, fabsf(v3_len(d) - 1.0f) < 1e-5f, "not a unit vector at (%g, %g)", u, v);
        equal_area_sphere_to_square(d, &u2, &v2);
        CHECK(t, fabsf(u2 - u) < 2e-4f && fabsf(v2 - v) < 2e-4f,
              "(%g, %g) -> (%g %g %g) -> (%g, %g)", u, v, d.x, d.y, d.z, u2, v2);
        bins[b < 0 ? 0 : b > 19 ? 19 : b] += 1.0;
    }
    for (i = 0; i < 20; i++) ex[i] = n / 20.0;
    CHECK_CHI2(t, bins, ex, 20, 1, NULL, "z of uniform square points is not uniform");
}

/* A 16 x 16 map with one texel 200 times brighter: its pdf integrates to 1 over
   the sphere (exactly, texel by texel: the map is equal-area) also when the light
   is rotated, and directions from inf_sample fall in each texel as often as its
   weight says (chi-square over the 256 texels) with the pdf inf_pdf gives them. */
static void test_env_map_pdf_and_sampling(T *t)
{
    static char text[2048];
    Image im;
    Scene s;
    Rng r;
    const Emitter *em;
    const char *path = test_path(t, "env_one_bright.pfm");
    static double count[256], ex[256];
    double integral = 0.0, wsum = 0.0, w[256];
    int x, y, i, k, n = test_scaled(100000, 20000), rot;
    CHECK(t, img_alloc(&im, 16, 16), "out of memory");
    for (i = 0; i < 256; i++) { im.rgb[3 * i] = 0.2f; im.rgb[3 * i + 1] = 0.3f; im.rgb[3 * i + 2] = 0.4f; }
    im.rgb[3 * (3 * 16 + 12)] = 60.0f; im.rgb[3 * (3 * 16 + 12) + 1] = 60.0f; im.rgb[3 * (3 * 16 + 12) + 2] = 60.0f;
    for (i = 0; i < 256; i++) { w[i] = (im.rgb[3 * i] + im.rgb[3 * i + 1] + im.rgb[3 * i + 2]) / 3.0; wsum += w[i]; }
    CHECK(t, pfm_write(&im, path), "cannot write %s", path);
    img_free(&im);
    for (rot = 0; rot < 2; rot++) {
        snprintf(text, sizeof text, "WorldBegin\n%s\nLightSource \"infinite\" \"string filename\" \"%s\"\n",
                 rot ? "Rotate 37 1 2 3" : "", path);
        if (!test_load_scene(t, &s, text)) return;
        em = &s.emitters[0];
        CHECK(t, em->inf && em->inf->res == 16, "not a 16 x 16 image map");
        /* integral over the sphere: 16 points per texel, each texel 4 pi / 256 sr */
        integral = 0.0;
        for (y = 0; y < 16; y++)
            for (x = 0; x < 16; x++)
                for (k = 0; k < 16; k++) {
                    Vec3 d = equal_area_square_to_sphere((x + (k % 4 + 0.5f) / 4) / 16, (y + (k / 4 + 0.5f) / 4) / 16);
                    d = v3_norm(xf_vector(&em->inf->world_from_light, d));
                    integral += inf_pdf(em, v3(0, 0, 0), d) * (4.0 * SPECNEE_PI / 256.0) / 16.0;
                }
        CHECK(t, fabs(integral - 1.0) < 1e-3, "rotation %d: the pdf integrates to %.6f", rot, integral);
        if (rot == 0) {
            rng_seed(&r, 3, 3);
            for (i = 0; i < 256; i++) count[i] = 0;
            for (i = 0; i < n; i++) {
                Vec3 d;
                float pdf, u, v;
                int tx, ty;
                const float u1 = rng_float(&r), u2 = rng_float(&r);   /* in this order */
                CHECK(t, inf_sample(em, v3(0, 0, 0), u1, u2, &d, &pdf), "no sample");
                CHECK(t, pdf == inf_pdf(em, v3(0, 0, 0), d), "inf_sample's pdf %g != inf_pdf %g", pdf, inf_pdf(em, v3(0, 0, 0), d));
                equal_area_sphere_to_square(d, &u, &v);
                tx = (int)(u * 16); ty = (int)(v * 16);
                if (tx > 15) tx = 15;
                if (ty > 15) ty = 15;
                count[ty * 16 + tx] += 1;
            }
            for (i = 0; i < 256; i++) ex[i] = n * w[i] / wsum;
            CHECK_CHI2(t, count, ex, 256, 1, NULL, "sampled texels do not follow the weights");
            CHECK(t, count[3 * 16 + 12] > 0.4 * n, "the bright texel got %g of %d samples", count[3 * 16 + 12], n);
        }
        scene_free(&s);
    }
}

/* Mean and standard error of Y over the pixels [x0, x1) x [y0, y1). */
static void region_Y(const Image *im, int x0, int y0, int x1, int y1, double *mean, double *se)
{
    double s1 = 0, s2 = 0;
    int x, y, n = 0;
    for (y = y0; y < y1; y++)
        for (x = x0; x < x1; x++) {
            const float *p = im->rgb + 3 * (y * im->w + x);
            double Y = 0.2126390 * p[0] + 0.7151687 * p[1] + 0.0721923 * p[2];
            s1 += Y; s2 += Y * Y; n++;
        }
    *mean = s1 / n;
    *se = sqrt(fmax(0.0, s2 / n - *mean * *mean) / (n - 1));
}

/* The furnace: a diffuse sphere of albedo 0.5 under an environment of luminance
   1 reflects luminance 0.5 everywhere (convex: one bounce), and the environment
   seen directly has luminance 1.  For a constant light with L flat, an rgb L, a
   white 8 x 8 image map (a texel (1, 1, 1) has luminance 1, pbrt-v4), and a
   constant light given by its illuminance: E_v = 2 pi lux on an upward-facing
   point means L = 2 (pbrt-v4: E = pi L), so the sphere shows 1. */
static void test_env_furnace(T *t)
{
    static char text[2048];
    static const char *const lights[] = {
        "LightSource \"infinite\" \"spectrum L\" [ 400 1 700 1 ]",
        "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]",
        "LightSource \"infinite\" \"string filename\" \"%s\"",
        "LightSource \"infinite\" \"spectrum L\" [ 400 3 700 3 ] \"float illuminance\" 6.283185307"
    };
    const char *path = test_path(t, "env_white.pfm");
    Image im;
    int i, k;
    CHECK(t, img_alloc(&im, 8, 8), "out of memory");
    for (k = 0; k < 3 * 64; k++) im.rgb[k] = 1.0f;
    CHECK(t, pfm_write(&im, path), "cannot write %s", path);
    img_free(&im);
    for (i = 0; i < 4; i++) {
        char light[512];
        double m, se, want = i == 3 ? 1.0 : 0.5;
        snprintf(light, sizeof light, lights[i], path);
        snprintf(text, sizeof text,
                 "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n"
                 "LookAt 0 0 -5 0 0 0 0 1 0\nCamera \"perspective\" \"float fov\" 30\nPixelFilter \"box\"\n"
                 "WorldBegin\n%s\nMaterial \"diffuse\" \"spectrum reflectance\" [ 400 0.5 700 0.5 ]\n"
                 "Shape \"sphere\" \"float radius\" 1\n", light);
        if (!render_text(t, text, test_scaled(32, 8), &im)) return;
        region_Y(&im, 12, 12, 20, 20, &m, &se);
        if (!(fabs(m - want) < TEST_K_SIGMA * se + 2e-3)) {
            img_free(&im);
            CHECK(t, 0, "light %d: the sphere has Y %.5f +- %.5f, want %g", i, m, se, want);
        }
        region_Y(&im, 0, 0, 4, 4, &m, &se);
        img_free(&im);
        CHECK(t, fabs(m - 2.0 * want) < TEST_K_SIGMA * se + 2e-3,
              "light %d: the environment seen directly has Y %.5f +- %.5f, want %g", i, m, se, 2.0 * want);
    }
}

/* What the subset does not read is said so (a missing EXR by its name),
   portals, a non-square map, a goniometric light without its image. */
static void test_env_rejections(T *t)
{
    static const char *const bad[][2] = {
        { "LightSource \"infinite\" \"string filename\" \"sky.exr\"", "sky.exr: cannot read the EXR file" },
        { "LightSource \"infinite\" \"point3 portal\" [ 0 0 0 1 0 0 1 1 0 0 1 0 ]", "portal" },
        { "LightSource \"goniometric\"", "\"string filename\" is required" },
        { "LightSource \"infinite\" \"string filename\" \"NONSQUARE\"", "not square" },
        { "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ] \"string filename\" \"x.pfm\"", "both" },
    };
    static char text[1024], line[512];
    const char *path = test_path(t, "env_nonsquare.pfm");
    Image im;
    Scene s;
    Error e;
    int i;
    CHECK(t, img_alloc(&im, 8, 4), "out of memory");
    CHECK(t, pfm_write(&im, path), "cannot write");
    img_free(&im);
    for (i = 0; i < 5; i++) {
        const char *nonsq = strstr(bad[i][0], "NONSQUARE");
        if (nonsq) snprintf(line, sizeof line, "LightSource \"infinite\" \"string filename\" \"%s\"", path);
        else snprintf(line, sizeof line, "%s", bad[i][0]);
        snprintf(text, sizeof text, "WorldBegin\n%s\n", line);
        e.msg[0] = 0;
        CHECK(t, !scene_load_string(&s, text, "t.pbrt", &e), "accepted: %s", line);
        CHECK(t, strncmp(e.msg, "t.pbrt:2:", 9) == 0 && strstr(e.msg, bad[i][1]) && !strchr(e.msg, '\n'),
              "message \"%s\" lacks \"t.pbrt:2:\" or \"%s\"", e.msg, bad[i][1]);
        scene_free(&s);
    }
}


/* ==== infinite lights with a portal (pbrt-v4's PortalImageInfiniteLight) ====
   The portal of these tests is the unit square at height 2 over the origin,
   corners in the order that makes its frame's n = (p3 - p0) x (p1 - p0) point up
   (+y): the sky is above it. */
#define PORTAL_P "\"point3 portal\" [ -0.5 2 -0.5   0.5 2 -0.5   0.5 2 0.5   -0.5 2 0.5 ]"

/* The point where the ray from o along d crosses the portal's plane y = 2, as
   (s, t) in [0, 1]^2 over the square; 0 if it misses the square. */
static int portal_hit(Vec3 o, Vec3 d, double *s, double *t)
{
    double k;
    if (!(d.y > 0.0f)) return 0;
    k = (2.0 - o.y) / d.y;
    *s = o.x + k * d.x + 0.5;
    *t = o.z + k * d.z + 0.5;
    return *s >= 0.0 && *s <= 1.0 && *t >= 0.0 && *t <= 1.0;
}

/* The breakpoints in [a0, a1] of one axis of the portal plane seen from o: the
   cell's ends and the lines c + h tan(-pi/2 + k pi / res) where the light's
   rectified texels change (h: the height of the plane over o), sorted; their count. */
static int portal_breaks(double c, double h, int res, double a0, double a1, double *out)
{
    int k, n = 0, i, j;
    out[n++] = a0;
    for (k = 1; k < res; k++) {
        double x = c + h * tan(-0.5 * SPECNEE_PI + k * SPECNEE_PI / res);
        if (x > a0 && x < a1) out[n++] = x;
    }
    out[n++] = a1;
    for (i = 1; i < n; i++)                          /* insertion sort */
        for (j = i; j > 0 && out[j] < out[j - 1]; j--) { double tmp = out[j]; out[j] = out[j - 1]; out[j - 1] = tmp; }
    return n;
}

/* The probability of the directions through the portal cell [s0, s1] x [t0, t1]
   (s along world x, t along world z, the square's corner at s = t = 0) seen from
   o: the pdf integrated over the cell's area, dw = cos / r^2 dA, by the 3 x 3
   Gauss-Legendre rule on each piece between the lines where the pdf jumps (the
   area parameterisation, not the light's own: its pieces are smooth). */
static double portal_cell_prob(const Emitter *em, Vec3 o, double s0, double s1, double t0,
                               double t1)
{
    static const double gx[3] = { -0.774596669241483, 0.0, 0.774596669241483 };
    static const double gw[3] = { 5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0 };
    double bs[40], bt[40], sum = 0.0, h = 2.0 - o.y;
    int ns = portal_breaks(o.x + 0.5, h, em->inf->res, s0, s1, bs);
    int nt = portal_breaks(o.z + 0.5, h, em->inf->res, t0, t1, bt), i, j, a, b;
    for (j = 0; j + 1 < nt; j++)
        for (i = 0; i + 1 < ns; i++)
            for (b = 0; b < 3; b++)
                for (a = 0; a < 3; a++) {
                    double sx = 0.5 * (bs[i] + bs[i + 1]) + 0.5 * (bs[i + 1] - bs[i]) * gx[a];
                    double tz = 0.5 * (bt[j] + bt[j + 1]) + 0.5 * (bt[j + 1] - bt[j]) * gx[b];
                    Vec3 d = v3_sub(v3((float)(sx - 0.5), 2.0f, (float)(tz - 0.5)), o);
                    double r2 = v3_dot(d, d), cosx = d.y / sqrt(r2);
                    sum += gw[a] * gw[b] * 0.25 * (bs[i + 1] - bs[i]) * (bt[j + 1] - bt[j]) *
                           inf_pdf(em, o, v3_norm(d)) * cosx / r2;
                }
    return sum;
}

/* A portal light with an image map (16 x 16, one texel 300 times brighter, the
   light turned): seen from three points inside, its pdf integrates to 1 over the
   portal's area, each sample passes through the portal with the pdf inf_pdf gives
   it, and the samples fall in 8 x 8 cells of the portal as often as the pdf says
   (chi-square); from the sky side nothing is sampled and the pdf is 0. */
static void test_portal_pdf_and_sampling(T *t)
{
    static char text[1024];
    static double count[64], ex[64];
    Image im;
    Scene sc;
    Rng r;
    const Emitter *em;
    const char *path = test_path(t, "portal_sky.pfm");
    const Vec3 refs[3] = { { 0.0f, 1.0f, 0.0f }, { 0.7f, 0.3f, -0.6f }, { -0.2f, 1.8f, 0.4f } };
    int i, k, c, n = test_scaled(100000, 20000);
    float pdf;
    Vec3 d;
    CHECK(t, img_alloc(&im, 16, 16), "out of memory");
    for (i = 0; i < 256; i++)
        for (c = 0; c < 3; c++) im.rgb[3 * i + c] = 0.1f + 0.05f * (float)((i * 7 + c) % 11);
    for (c = 0; c < 3; c++) im.rgb[3 * (6 * 16 + 8) + c] = 60.0f;
    CHECK(t, pfm_write(&im, path), "cannot write %s", path);
    img_free(&im);
    snprintf(text, sizeof text, "WorldBegin\nRotate -80 1 0.2 0\nLightSource \"infinite\" "
             "\"string filename\" \"%s\" " PORTAL_P "\n", path);
    if (!test_load_scene(t, &sc, text)) return;
    em = &sc.emitters[0];
    CHECK(t, em->inf && em->inf->portal && em->inf->res == 16, "not a 16 x 16 portal light");
    for (k = 0; k < 3; k++) {
        double total = 0.0, sp, tp;
        for (i = 0; i < 64; i++) {
            ex[i] = portal_cell_prob(em, refs[k], (i % 8) / 8.0, (i % 8 + 1) / 8.0, (i / 8) / 8.0,
                                     (i / 8 + 1) / 8.0);
            total += ex[i];
            ex[i] *= n;
            count[i] = 0.0;
        }
        CHECK(t, fabs(total - 1.0) < 1e-4, "from point %d the pdf integrates to %.6f", k, total);
        rng_seed(&r, 17, (uint64_t)k);
        for (i = 0; i < n; i++) {
            const float u1 = rng_float(&r), u2 = rng_float(&r);     /* in this order */
            int cs, ct;
            CHECK(t, inf_sample(em, refs[k], u1, u2, &d, &pdf), "point %d: no sample", k);
            CHECK(t, pdf == inf_pdf(em, refs[k], d) && inf_sees(em, refs[k], d),
                  "point %d: pdf %g, inf_pdf %g, sees %d", k, pdf, inf_pdf(em, refs[k], d),
                  inf_sees(em, refs[k], d));
            CHECK(t, portal_hit(refs[k], d, &sp, &tp), "point %d: a sample misses the portal", k);
            cs = (int)(sp * 8); ct = (int)(tp * 8);
            count[(ct > 7 ? 7 : ct) * 8 + (cs > 7 ? 7 : cs)] += 1.0;
        }
        CHECK_CHI2(t, count, ex, 64, 3, NULL, "point %d: portal samples against their pdf", k);
    }
    rng_seed(&r, 18, 0);
    CHECK(t, !inf_sample(em, v3(0.1f, 2.5f, 0.0f), 0.3f, 0.6f, &d, &pdf) &&
          inf_pdf(em, v3(0.1f, 2.5f, 0.0f), v3(0, 1, 0)) == 0.0f &&
          !inf_sees(em, v3(0.1f, 2.5f, 0.0f), v3(0, 1, 0)), "the sky side sees the light");
    CHECK(t, !inf_sees(em, v3(0, 1, 0), v3_norm(v3(1, 1, 0))) &&
          inf_pdf(em, v3(0, 1, 0), v3_norm(v3(1, 1, 0))) == 0.0f, "a direction past the portal sees it");
    scene_free(&sc);
}

/* The projected solid angle of the portal seen from p with normal +y (Lambert's
   polygon formula: 1/2 sum over edges of the edge's angle times the cosine of its
   plane's normal with +y). */
static double portal_psa(Vec3 p)
{
    static const float cx[4] = { -0.5f, 0.5f, 0.5f, -0.5f }, cz[4] = { -0.5f, -0.5f, 0.5f, 0.5f };
    double sum = 0.0;
    int i;
    for (i = 0; i < 4; i++) {
        Vec3 a = v3_norm(v3_sub(v3(cx[i], 2.0f, cz[i]), p));
        Vec3 b = v3_norm(v3_sub(v3(cx[(i + 1) % 4], 2.0f, cz[(i + 1) % 4]), p));
        Vec3 g = v3_cross(a, b);
        double len = v3_len(g);
        sum += acos(fmax(-1.0, fmin(1.0, (double)v3_dot(a, b)))) * g.y / len;
    }
    return 0.5 * fabs(sum);
}

/* Furnace-like: a constant "rgb L" [1 1 1] portal light (luminance 1) lights a
   small white-ish patch (rgb 0.5) off the portal's axis; the camera sees only the
   patch, so each pixel has luminance 0.5 E / pi with E = L x the portal's
   projected solid angle (closed form).  The unit check first: cos / pdf of the
   light's samples, and pi x the share of cosine-distributed directions that
   inf_sees lets through, both estimate that angle. */
static void test_portal_furnace(T *t)
{
    static char text[2048];
    const Vec3 p = v3(0.3f, 0.0f, -0.4f);
    double psa = portal_psa(p), sum = 0.0, sum2 = 0.0, hits = 0.0, m, se, y;
    Scene sc;
    RenderOptions o;
    Tiles tl;
    Rng r;
    int i, n = test_scaled(100000, 20000);
    snprintf(text, sizeof text,
             "LookAt 0.3 0.5 -0.4  0.3 0 -0.4  0 0 1\nCamera \"perspective\" \"float fov\" 2\n"
             "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4\nPixelFilter \"box\"\n"
             "WorldBegin\nLightSource \"infinite\" \"rgb L\" [ 1 1 1 ] " PORTAL_P "\n"
             "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" "
             "[ 0.28 0 -0.42  0.28 0 -0.38  0.32 0 -0.38  0.32 0 -0.42 ]\n");
    if (!test_load_scene(t, &sc, text)) return;
    rng_seed(&r, 21, 0);
    for (i = 0; i < n; i++) {
        const float u1 = rng_float(&r), u2 = rng_float(&r), u3 = rng_float(&r), u4 = rng_float(&r);
        float pdf, rad = sqrtf(u3), phi = 2.0f * (float)SPECNEE_PI * u4;
        Vec3 d, c = v3(rad * cosf(phi), sqrtf(fmaxf(0.0f, 1.0f - u3)), rad * sinf(phi));
        double v = 0.0;
        if (inf_sample(&sc.emitters[0], p, u1, u2, &d, &pdf)) v = d.y / pdf;
        sum += v; sum2 += v * v;
        hits += inf_sees(&sc.emitters[0], p, c);
    }
    m = sum / n;
    se = sqrt(fmax(0.0, sum2 / n - m * m) / n);
    CHECK(t, fabs(m - psa) < TEST_K_SIGMA * se + 1e-4 * psa, "NEE: projected solid angle %.6f +- %.2g, "
          "closed form %.6f", m, se, psa);
    m = SPECNEE_PI * hits / n;
    se = SPECNEE_PI * sqrt(hits / n * (1.0 - hits / n) / n);
    CHECK(t, fabs(m - psa) < TEST_K_SIGMA * se, "cosine directions through the portal: %.6f +- %.2g, "
          "closed form %.6f", m, se, psa);
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    if (!test_render_tiles(t, &sc, &o, 6, 1, &tl)) { scene_free(&sc); return; }
    scene_free(&sc);
    y = test_tile_y(&tl, 0, &se);
    CHECK(t, fabs(y - 0.5 * psa / SPECNEE_PI) < TEST_K_SIGMA * se + 0.005 * y,
          "the patch: Y %.6f +- %.2g, 0.5 E / pi = %.6f", y, se, 0.5 * psa / SPECNEE_PI);
}

/* Against pbrt-v4: the luminance of the whole image and of its quadrants (top
   left, top right, bottom left, bottom right) of tests/data/portal/room-rgb.pbrt
   (a room lit through a window in its ceiling by a portal light of constant "rgb
   L", the window seen directly) and room-map.pbrt (the same with the equal-area
   map sky.pfm, turned, whose "sun" lights the far wall).  Frozen from pbrt-v4
   (mmp/pbrt-v4 5f7a6068, `pbrt --spp 4096 --seed S` for S = 1, 2 on these files,
   the mean of the two; they differ by at most 0.06 % (rgb) and 0.13 % (map) per
   value).  specnee at 1024 spp (tools/pbrt_compare.sh's regions): rgb image
   1.0011, quadrants within 0.3 %; map image 1.0014, quadrants within 0.2 %. */
static void test_portal_against_pbrt(T *t)
{
    static const char *const files[2] = { "tests/data/portal/room-rgb.pbrt",
                                          "tests/data/portal/room-map.pbrt" };
    static const double pbrt_y[2][5] = {
        { 0.318797, 0.553688, 0.559965, 0.0763397, 0.0851945 },
        { 0.162853, 0.196928, 0.205339, 0.120729, 0.128418 }
    };
    int f;
    for (f = 0; f < 2; f++) {
        Scene sc;
        RenderOptions o;
        Error e;
        CHECK(t, scene_load(&sc, files[f], &e), "%s", e.msg);
        render_options_default(&o);
        o.spp = test_scaled(32, 8);
        test_quadrants_against_pbrt(t, &sc, &o, pbrt_y[f], files[f]);
        scene_free(&sc);
        if (t->failed) return;
    }
}

/* What a portal light cannot be is refused by name, at the portal's line. */
static void test_portal_rejections(T *t)
{
    static const char *const bad[][2] = {
        { "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n \"point3 portal\" [ 0 2 0  1 2 0  1 2 1 ]", "needs 4 points" },
        { "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n \"point3 portal\" [ 0 2 0  1 2 0  1.2 2 1  0 2 1 ]", "not a rectangle" },
        { "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n \"point3 portal\" [ 0 2 0  1 2 0  1 2.5 1  0 2 1 ]", "not a rectangle" },
        { "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n \"point3 portal\" [ 0 2 0  0 2 0  1 2 1  0 2 1 ]", "equal corners" },
        { "LightSource \"infinite\"\n \"point3 portal\" [ 0 2 0  1 2 0  1 2 1  0 2 1 ]", "needs \"L\" or \"filename\"" },
    };
    static char text[512];
    Scene sc;
    Error e;
    int i;
    for (i = 0; i < 5; i++) {
        snprintf(text, sizeof text, "WorldBegin\n%s\n", bad[i][0]);
        e.msg[0] = 0;
        CHECK(t, !scene_load_string(&sc, text, "t.pbrt", &e), "accepted: %s", bad[i][0]);
        CHECK(t, strncmp(e.msg, "t.pbrt:3:", 9) == 0 && strstr(e.msg, bad[i][1]),
              "message \"%s\" lacks \"t.pbrt:3:\" or \"%s\"", e.msg, bad[i][1]);
        scene_free(&sc);
    }
}

/* ---- the remaining film and integrator settings ---- */

/* Render a scene and a variant; 1 if both rendered. */
static int render_pair(T *t, const char *ta, const char *tb, int spp, Image *a, Image *b)
{
    if (!render_text(t, ta, spp, a)) return 0;
    if (!render_text(t, tb, spp, b)) { img_free(a); return 0; }
    return 1;
}

/* Film "float scale" is pbrt-v3's; pbrt-v4's --upgrade writes it as "float iso"
   100 * scale, so the image scales by it (times iso's own ratio).  Integrator
   "float rrthreshold" is pbrt-v3's too and no longer read by pbrt-v4: accepted
   and ignored, the image bit for bit the same. */
static void test_film_scale_rrthreshold(T *t)
{
    static char a_txt[4096], b_txt[4096], c_txt[8192];
    Image a, b, c;
    int i;
    square_scene(a_txt, sizeof a_txt, "", "", 1.0f);
    square_scene(b_txt, sizeof b_txt, "", "\"float scale\" 3 \"float iso\" 200", 1.0f);
    if (!render_pair(t, a_txt, b_txt, 2, &a, &b)) return;
    for (i = 0; i < 3 * a.w * a.h; i++)
        if (!(fabs(b.rgb[i] - 6.0 * a.rgb[i]) <= 1e-6 * fabs(6.0 * a.rgb[i]))) {
            test_failf(t, __FILE__, __LINE__, "value %d: %g, with scale 3 and iso 200: %g "
                       "(want x6)", i, a.rgb[i], b.rgb[i]);
            break;
        }
    snprintf(c_txt, sizeof c_txt, "Integrator \"volpath\" \"float rrthreshold\" [ 0 ]\n%s", a_txt);
    if (render_text(t, c_txt, 2, &c)) {
        CHECK(t, memcmp(a.rgb, c.rgb, sizeof(float) * 3 * (size_t)a.w * a.h) == 0,
              "rrthreshold changed the image");
        img_free(&c);
    }
    img_free(&a); img_free(&b);
    {
        Scene s;
        Error e;
        square_scene(b_txt, sizeof b_txt, "", "\"float scale\" 0", 1.0f);
        CHECK(t, !scene_load_string(&s, b_txt, "t.pbrt", &e) && strstr(e.msg, "t.pbrt:1:")
              && strstr(e.msg, "scale"), "Film scale 0 accepted: %s", e.msg);
        scene_free(&s);
    }
}

/* pbrt-v4 FilmBaseParameters: a cropwindow (x0 x1 y0 y1, fractions, each pair
   sorted) renders and writes pixels ceil(res * fraction) .. ceil(res * fraction)
   (end exclusive), pixelbounds the given pixels clipped to the film; the crop
   window wins over pixelbounds; the camera keeps the whole film.  So each crop is
   bit for bit its rectangle of the whole image. */
static void test_film_crop(T *t)
{
    static const struct { const char *film; int x0, y0, w, h; } c[] = {
        { "\"float cropwindow\" [ 0.25 0.75 0.1 0.6 ]", 16, 7, 32, 32 },      /* 6.4 -> 7 */
        { "\"float cropwindow\" [ 0.75 0.25 0.6 0.1 ]", 16, 7, 32, 32 },      /* sorted */
        { "\"integer pixelbounds\" [ 3 40 5 70 ]", 3, 5, 37, 59 },           /* clipped */
        { "\"integer pixelbounds\" [ 0 8 0 8 ] \"float cropwindow\" [ 0.5 1 0.5 1 ]", 32, 32, 32, 32 },
    };
    static char buf[4096];
    Image full, im;
    Scene s;
    Error e;
    int i;
    square_scene(buf, sizeof buf, "", "", 1.0f);
    if (!render_text(t, buf, 2, &full)) return;
    for (i = 0; i < 4; i++) {
        int x, y, same = 1;
        square_scene(buf, sizeof buf, "", c[i].film, 1.0f);
        if (!render_text(t, buf, 2, &im)) break;
        CHECK(t, im.w == c[i].w && im.h == c[i].h, "%s: image %d x %d, want %d x %d",
              c[i].film, im.w, im.h, c[i].w, c[i].h);
        if (im.w == c[i].w && im.h == c[i].h)
            for (y = 0; y < im.h; y++)
                for (x = 0; x < im.w; x++)
                    if (memcmp(&im.rgb[3 * (y * im.w + x)],
                               &full.rgb[3 * ((y + c[i].y0) * full.w + x + c[i].x0)], 3 * sizeof(float)))
                        same = 0;
        CHECK(t, same, "%s: not the whole image's rectangle at (%d, %d)", c[i].film, c[i].x0, c[i].y0);
        img_free(&im);
    }
    img_free(&full);
    square_scene(buf, sizeof buf, "", "\"float cropwindow\" [ 0 1 0.5 ]", 1.0f);
    CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, "t.pbrt:1:")
          && strstr(e.msg, "3 values, expected 4"), "3-value cropwindow: %s", e.msg);
    scene_free(&s);
    square_scene(buf, sizeof buf, "", "\"float cropwindow\" [ 0.5 0.5 0 1 ]", 1.0f);
    CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, "t.pbrt:1:")
          && strstr(e.msg, "selects no pixel"), "empty cropwindow: %s", e.msg);
    scene_free(&s);
}

/* The insets ("# inset" comments, in pixels of the whole film) in the cropped
   image: clipped to the crop and moved to its origin; one outside the crop is left
   out (--mark-insets and converge's regions use them). */
static void test_film_crop_insets(T *t)
{
    static char buf[4096], b2[4200];
    static const int want[2][4] = { { 4, 0, 14, 5 }, { 24, 23, 32, 32 } };
    int rect[8][4], n, i;
    const char *names[8];
    Scene s;
    square_scene(buf, sizeof buf, "", "\"float cropwindow\" [ 0.25 0.75 0.1 0.6 ]", 1.0f);  /* x 16..48, y 7..39 */
    snprintf(b2, sizeof b2, "# inset A 0 0 8 8\n# inset B 20 4 30 12\n# inset C 40 30 60 60\n%s", buf);
    if (!test_load_scene(t, &s, b2)) return;
    n = scene_insets_rendered(&s, rect, names);
    CHECK(t, n == 2, "%d insets in the crop, want 2 (A lies outside it)", n);
    for (i = 0; i < n && i < 2; i++)
        CHECK(t, !strcmp(names[i], i ? "C" : "B") && !memcmp(rect[i], want[i], sizeof want[i]),
              "inset %s: (%d %d %d %d) in the crop, want %s (%d %d %d %d)", names[i], rect[i][0], rect[i][1],
              rect[i][2], rect[i][3], i ? "C" : "B", want[i][0], want[i][1], want[i][2], want[i][3]);
    scene_free(&s);
    /* without a crop they are the insets as written */
    square_scene(buf, sizeof buf, "", "", 1.0f);
    snprintf(b2, sizeof b2, "# inset A 0 0 8 8\n%s", buf);
    if (!test_load_scene(t, &s, b2)) return;
    n = scene_insets_rendered(&s, rect, names);
    CHECK(t, n == 1 && rect[0][0] == 0 && rect[0][1] == 0 && rect[0][2] == 8 && rect[0][3] == 8,
          "uncropped inset A: %d insets, (%d %d %d %d)", n, rect[0][0], rect[0][1], rect[0][2], rect[0][3]);
    scene_free(&s);
}

/* Film "string sensor": "cie1931" (pbrt-v4's default) is specnee's XYZ, a named
   pbrt-v4 camera is read (tests/test_sensor.c holds its images), an unknown name
   is called unknown; the gbuffer film reads it too. */
static void test_film_sensor(T *t)
{
    static const char *const ok[] = {
        "\"string sensor\" \"cie1931\"", "\"string sensor\" \"nikon_d850\"",
        "\"string sensor\" \"canon_eos_5d_mkiv\" \"float whitebalance\" 5000",
    };
    static char buf[4096];
    Scene s;
    Error e;
    int i;
    for (i = 0; i < 3; i++) {
        square_scene_film(buf, sizeof buf, i == 2 ? "gbuffer" : "rgb", "", ok[i], 1.0f);
        CHECK(t, test_load_scene(t, &s, buf), "%s refused", ok[i]);
        scene_free(&s);
    }
    square_scene(buf, sizeof buf, "", "\"string sensor\" \"kodak\"", 1.0f);
    e.msg[0] = 0;
    CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strncmp(e.msg, "t.pbrt:1:", 9) == 0
          && strstr(e.msg, "\"kodak\": unknown sensor type"), "kodak: \"%s\"", e.msg);
    scene_free(&s);
}

/* Film "whitebalance" T (pbrt-v4 PixelSensor): a Bradford von Kries map from the
   white of CIE daylight at T * 1.4388 / 1.4380 K (so the nominal 5000 and 7500
   are D50 and D75) to sRGB's white.  Its property: the white it adapts from
   becomes neutral.  The whites are CIE 015:2004's tabulated chromaticities, not
   the locus formula the code uses: D50 (0.34567, 0.35850), D75 (0.29902,
   0.31485), D65 (0.31271, 0.32902).  Then a render: each white-balanced pixel's
   XYZ is that matrix times the plain pixel's. */
static void test_film_whitebalance(T *t)
{
    static const struct { float T; double x, y; } w[] = {
        { 5000.0f, 0.34567, 0.35850 }, { 7500.0f, 0.29902, 0.31485 }, { 6500.0f, 0.31271, 0.32902 },
    };
    static char buf[4096], b2[4096];
    char film[64];
    Scene s;
    Error e;
    Image a, b;
    int i, k;
    for (i = 0; i < 3; i++) {
        double xyz[3], out[3], rgb[3];
        const double *m;
        snprintf(film, sizeof film, "\"float whitebalance\" %g", w[i].T);
        square_scene(buf, sizeof buf, "", film, 1.0f);
        if (!test_load_scene(t, &s, buf)) return;
        m = s.settings.white_balance_m;
        xyz[0] = w[i].x / w[i].y; xyz[1] = 1.0; xyz[2] = (1.0 - w[i].x - w[i].y) / w[i].y;
        for (k = 0; k < 3; k++) out[k] = m[3 * k] * xyz[0] + m[3 * k + 1] * xyz[1] + m[3 * k + 2] * xyz[2];
        xyz_to_linear_srgb(out, rgb);
        CHECK(t, fabs(rgb[0] / rgb[1] - 1.0) < 2e-3 && fabs(rgb[2] / rgb[1] - 1.0) < 2e-3,
              "whitebalance %g: its white becomes rgb (%g, %g, %g), not neutral", w[i].T,
              rgb[0], rgb[1], rgb[2]);
        if (i == 0) {   /* D50 is yellower than D65: the map must change it */
            xyz_to_linear_srgb(xyz, rgb);
            CHECK(t, rgb[2] / rgb[1] < 0.8, "D50's white unbalanced is (%g, %g, %g): no power",
                  rgb[0], rgb[1], rgb[2]);
        }
        scene_free(&s);
    }
    square_scene(buf, sizeof buf, "", "", 1.0f);
    square_scene(b2, sizeof b2, "", "\"float whitebalance\" 3000", 1.0f);
    if (!test_load_scene(t, &s, b2)) return;
    if (render_pair(t, buf, b2, 2, &a, &b)) {
        const double *m = s.settings.white_balance_m;
        double worst = 0.0;
        for (i = 0; i < a.w * a.h; i++) {
            double xa[3], xb[3];
            srgb_to_xyz(&a.rgb[3 * i], xa);
            srgb_to_xyz(&b.rgb[3 * i], xb);
            for (k = 0; k < 3; k++) {
                double want = m[3 * k] * xa[0] + m[3 * k + 1] * xa[1] + m[3 * k + 2] * xa[2];
                double d = fabs(xb[k] - want) / (fabs(want) + 1e-3);
                if (d > worst) worst = d;
            }
        }
        CHECK(t, worst < 1e-4, "whitebalanced pixels differ from M x plain by %g (relative)", worst);
        CHECK(t, fabs(m[0] - 1.0) > 0.05 || fabs(m[8] - 1.0) > 0.05, "3000 K: M is near identity");
        img_free(&a); img_free(&b);
    }
    scene_free(&s);
    square_scene(buf, sizeof buf, "", "\"float whitebalance\" 500", 1.0f);
    CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && strstr(e.msg, "t.pbrt:1:")
          && strstr(e.msg, "whitebalance"), "whitebalance 500 K accepted: %s", e.msg);
    scene_free(&s);
}

/* pbrt-v4 looks named materials up when the scene is built: a NamedMaterial may
   come before its MakeNamedMaterial; a name never made is an error at the
   NamedMaterial.  And an unsupported type in MakeNamedMaterial names it. */
static void test_named_material_forward(T *t)
{
    static const char *const fwd =
        "WorldBegin\n"
        "AttributeBegin\n"
        "NamedMaterial \"m\"\n"
        "Shape \"sphere\"\n"
        "AttributeEnd\n"
        "Shape \"sphere\" \"float radius\" 2\n"
        "MakeNamedMaterial \"m\" \"string type\" \"dielectric\"\n";
    Scene s;
    Error e;
    if (test_load_scene(t, &s, fwd)) {
        CHECK(t, s.n_shapes == 2 && s.materials[s.shapes[0].material].type == MAT_DIELECTRIC
              && s.materials[s.shapes[1].material].type == MAT_DIFFUSE,
              "the forward NamedMaterial is not the dielectric it names");
        scene_free(&s);
    }
    CHECK(t, !scene_load_string(&s, "WorldBegin\nNamedMaterial \"m\"\nShape \"sphere\"\n"
                                "MakeNamedMaterial \"n\" \"string type\" \"diffuse\"\n", "t.pbrt", &e)
          && strstr(e.msg, "t.pbrt:2:") && strstr(e.msg, "\"m\"") && strstr(e.msg, "no MakeNamedMaterial"),
          "a never-made name: %s", e.msg);
    scene_free(&s);
    CHECK(t, !scene_load_string(&s, "WorldBegin\nNamedMaterial \"m\"\nShape \"sphere\"\n"
                                "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
                                "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n", "t.pbrt", &e)
          && strstr(e.msg, "t.pbrt:5:") && strstr(e.msg, "redefined"), "a redefinition: %s", e.msg);
    scene_free(&s);
    CHECK(t, !scene_load_string(&s, "WorldBegin\nMakeNamedMaterial \"CarPaint\" \"string type\" "
                                "\"subsurface\" \"string name\" \"Paint\"\n", "t.pbrt", &e)
          && strstr(e.msg, "t.pbrt:2: MakeNamedMaterial \"CarPaint\": type \"subsurface\": \"string name\" \"Paint\": no such named medium"),
          "MakeNamedMaterial message: %s", e.msg);
    scene_free(&s);
}

/* --dump-scene shows every setting that changes the image. */
static void test_dump_settings(T *t)
{
    static const char *const want[] = {
        "lensradius 0.25 focaldistance 7", "imaging ratio 6", "maxcomponentvalue 4",
        "whitebalance 5000 K", "cropwindow: renders and writes pixels x 16..47, y 7..38 (32 x 32)",
    };
    static char buf[4096], text[65536];
    FILE *f;
    Scene s;
    size_t n;
    int i;
    square_scene(buf, sizeof buf, "\"float lensradius\" 0.25 \"float focaldistance\" 7",
                 "\"float iso\" 300 \"float scale\" 2 \"float maxcomponentvalue\" 4 "
                 "\"float whitebalance\" 5000 \"float cropwindow\" [ 0.25 0.75 0.1 0.6 ]", 1.0f);
    if (!test_load_scene(t, &s, buf)) return;
    f = tmpfile();
    CHECK(t, f != NULL, "no tmpfile");
    if (!f) { scene_free(&s); return; }
    scene_dump(&s, f);
    rewind(f);
    n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
    for (i = 0; i < 5; i++) CHECK(t, strstr(text, want[i]) != NULL, "dump lacks \"%s\":\n%s", want[i], text);
    scene_free(&s);
}

/* Accelerator: pbrt-v4 reads it before WorldBegin and checks its
   parameters; the image cannot depend on it.  specnee reads the parameters pbrt-v4
   reads for "bvh" and "kdtree" and renders bit for bit the image without it;
   unknown types and parameters, and the directive after WorldBegin, are errors
   at their line. */
static void test_accelerator(T *t)
{
    static char a_txt[4096], b_txt[8192];
    static const char *const bad[][2] = {      /* text, what the message names */
        { "Accelerator \"octree\"\nWorldBegin\n", "unknown accelerator type" },
        { "Accelerator \"bvh\" \"integer maxprims\" 3\nWorldBegin\n", "maxprims" },
        { "Accelerator \"bvh\" \"float maxnodeprims\" 3\nWorldBegin\n", "wrong type" },
        { "Accelerator \"kdtree\" \"integer emptybonus\" 1\nWorldBegin\n", "wrong type" },
        { "WorldBegin\nAccelerator \"bvh\"\n", "Options cannot be set inside world block" },
    };
    Image a, b;
    Scene s;
    Error e;
    int i;
    square_scene(a_txt, sizeof a_txt, "", "", 1.0f);
    snprintf(b_txt, sizeof b_txt, "Accelerator \"bvh\" \"string splitmethod\" \"middle\" "
             "\"integer maxnodeprims\" 1\n%s", a_txt);
    if (!render_pair(t, a_txt, b_txt, 2, &a, &b)) return;
    i = memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * a.h);
    img_free(&a); img_free(&b);
    CHECK(t, i == 0, "Accelerator \"bvh\" changed the image");
    snprintf(b_txt, sizeof b_txt, "Accelerator \"kdtree\" \"integer intersectcost\" 80 "
             "\"integer traversalcost\" 1 \"float emptybonus\" 0.2 \"integer maxprims\" 2 "
             "\"integer maxdepth\" 9\n%s", a_txt);
    CHECK(t, scene_load_string(&s, b_txt, "t.pbrt", &e), "kdtree refused: %s", e.msg);
    scene_free(&s);
    for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
        char where[16];
        snprintf(b_txt, sizeof b_txt, "%s", bad[i][0]);
        snprintf(where, sizeof where, "t.pbrt:%d:", i == 4 ? 2 : 1);
        CHECK(t, !scene_load_string(&s, b_txt, "t.pbrt", &e) && strstr(e.msg, where)
              && strstr(e.msg, bad[i][1]), "accepted, or not at %s naming \"%s\": %s -> %s",
              where, bad[i][1], bad[i][0], e.msg);
    }
}

/* The command line's output file (-o) overrides Film's "string filename", as
   pbrt-v4 --outfile does: the scene's name is then not checked, so a placeholder
   such as "__OUTPUT_PNG__" (or an .exr name) loads; without -o the same file is
   refused, naming the line. */
static void test_film_output_override(T *t)
{
    static char buf[4096];
    const char *path;
    Scene s;
    Error e;
    square_scene(buf, sizeof buf, "", "\"string filename\" \"__OUTPUT_PNG__\"", 1.0f);
    path = test_write_file(t, "placeholder.pbrt", buf);
    CHECK(t, !scene_load(&s, path, &e) && strstr(e.msg, "placeholder.pbrt:1:")
          && strstr(e.msg, "__OUTPUT_PNG__"), "placeholder accepted without -o: %s", e.msg);
    CHECK(t, scene_load_as(&s, path, "out/x.png", &e), "placeholder refused with -o: %s", e.msg);
    CHECK(t, !strcmp(s.settings.filename, "out/x.png"), "filename %s", s.settings.filename);
    scene_free(&s);
    square_scene(buf, sizeof buf, "", "\"string filename\" \"a.exr\"", 1.0f);
    path = test_write_file(t, "exr.pbrt", buf);
    CHECK(t, scene_load(&s, path, &e) && !strcmp(s.settings.filename, "a.pfm"), "%s", e.msg);
    scene_free(&s);
    CHECK(t, scene_load_as(&s, path, "b.ppm", &e) && !strcmp(s.settings.filename, "b.ppm"),
          "%s", e.msg);
    scene_free(&s);
}

const TestCase tests_pbrt[] = {
    { "pbrt_iso_exposure", test_iso_exposure },
    { "pbrt_maxcomponentvalue", test_maxcomponentvalue },
    { "pbrt_maxcomponentvalue_red", test_maxcomponentvalue_red },
    { "pbrt_film_and_integrator_aliases", test_film_and_integrator_aliases },
    { "pbrt_thin_lens", test_thin_lens },
    { "pbrt_screen_window", test_screen_window },
    { "pbrt_rgb_eta", test_rgb_eta },
    { "pbrt_reflectance_clamp", test_reflectance_clamp },
    { "pbrt_equal_area_map", test_equal_area_map },
    { "pbrt_env_map_pdf_and_sampling", test_env_map_pdf_and_sampling },
    { "pbrt_env_furnace", test_env_furnace },
    { "pbrt_env_rejections", test_env_rejections },
    { "pbrt_portal_pdf_and_sampling", test_portal_pdf_and_sampling },
    { "pbrt_portal_furnace", test_portal_furnace },
    { "pbrt_portal_against_pbrt", test_portal_against_pbrt },
    { "pbrt_portal_rejections", test_portal_rejections },
    { "pbrt_film_scale_rrthreshold", test_film_scale_rrthreshold },
    { "pbrt_film_crop", test_film_crop },
    { "pbrt_film_crop_insets", test_film_crop_insets },
    { "pbrt_film_sensor", test_film_sensor },
    { "pbrt_film_whitebalance", test_film_whitebalance },
    { "pbrt_named_material_forward", test_named_material_forward },
    { "pbrt_dump_settings", test_dump_settings },
    { "pbrt_accelerator", test_accelerator },
    { "pbrt_film_output_override", test_film_output_override },
    { NULL, NULL }
};
