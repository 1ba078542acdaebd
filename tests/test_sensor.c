/* tests/test_sensor.c - the film's sensor (sensor.c): pbrt-v4's PixelSensor.

   Checked: the four sensors a scene collection uses (cie1931 and three cameras),
   with and without a white balance, against pbrt-v4's images of one scene; the
   imaging ratio scales a camera's image exactly; the camera fit makes a white
   under the balance's illuminant neutral, for every camera; every name pbrt-v4
   knows is read, cie1931's curves are the CIE observer's, and a bad name is
   refused at its file:line with the accepted names. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* The scene: a 32 x 32 camera sees four diffuse quads (a red, a green, a blue and
   a grey 0.6 reflectance, inline spectra: no RGB upsampling) lit by a distant
   blackbody of 3000 K; only the Film's and the Camera's parameters change. */
static const char *const SENSOR_BODY =
    "LightSource \"distant\" \"point3 from\" [ 0.3 0.5 0 ] \"point3 to\" [ 0 0 5 ] \"blackbody L\" [ 3000 ] \"float scale\" [ 3 ]\n"
    "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.05 550 0.1 600 0.7 700 0.85 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -3 -3 5  0 -3 5  0 0 5  -3 0 5 ]\n"
    "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.1 500 0.3 540 0.7 600 0.2 700 0.1 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 -3 5  3 -3 5  3 0 5  0 0 5 ]\n"
    "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.8 460 0.7 520 0.2 700 0.05 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -3 0 5  0 0 5  0 3 5  -3 3 5 ]\n"
    "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.6 700 0.6 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 5  3 0 5  3 3 5  0 3 5 ]\n";

static void sensor_scene(char *buf, size_t cap, const char *film, const char *camera)
{
    snprintf(buf, cap,
             "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] "
             "\"string filename\" \"x.pfm\" %s\n"
             "PixelFilter \"box\"\nSampler \"independent\"\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "Camera \"perspective\" \"float fov\" [ 40 ] %s\nWorldBegin\n%s", film, camera, SENSOR_BODY);
}

/* The Film and Camera parameters of the frozen renders. */
static const char *const SENSOR_CONFIG[7][2] = {
    { "", "" },
    { "\"string sensor\" \"nikon_d850\"", "" },
    { "\"string sensor\" \"canon_eos_100d\"", "" },
    { "\"string sensor\" \"canon_eos_5d_mkiv\"", "" },
    { "\"string sensor\" \"nikon_d850\" \"float whitebalance\" [ 3000 ]", "" },
    { "\"string sensor\" \"canon_eos_5d_mkiv\" \"float whitebalance\" [ 5000 ] \"float iso\" [ 250 ]",
      "\"float shutteropen\" [ 0.25 ] \"float shutterclose\" [ 0.75 ]" },
    { "\"string sensor\" \"cie1931\" \"float whitebalance\" [ 3000 ]", "" },
};

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, CPU build), `pbrt --seed S --spp 1024
   --outfile x.pfm scene.pbrt` for S = 1..4, scene.pbrt = sensor_scene with each
   SENSOR_CONFIG: linear sRGB of the whole image, then of its quadrants (top left,
   top right, bottom left, bottom right), each channel as the mean over the four
   seeds and its standard error.  The cameras move the image from cie1931's by up
   to 9 % (mean blue) and the red quad's blue from -0.014 to +0.017. */
static const double PBRT_SENSOR[7][5][6] = {
    { { 0.687012, 8.9e-05, 0.298728, 2.9e-05, 0.098631, 3.1e-05 },
      { 0.172358, 4.5e-05, 0.153220, 2.2e-05, 0.224084, 0.00011 },
      { 1.003329, 0.00022, 0.481004, 3.5e-05, 0.154362, 3.6e-05 },
      { 1.273019, 0.00021, 0.127294, 6.1e-05, -0.013936, 7.7e-06 },
      { 0.299343, 3.6e-05, 0.433393, 4.5e-05, 0.030015, 3.9e-05 } },
    { { 0.690941, 6.1e-05, 0.300448, 3e-05, 0.107497, 3.3e-05 },
      { 0.164657, 8.3e-05, 0.151365, 7.3e-05, 0.225768, 0.00012 },
      { 1.012506, 0.00019, 0.487595, 9.6e-05, 0.171283, 6.4e-05 },
      { 1.297668, 0.00012, 0.142563, 4.5e-05, 0.016766, 1.7e-05 },
      { 0.288934, 0.00011, 0.420271, 1.1e-05, 0.016173, 2.8e-05 } },
    { { 0.691931, 4.6e-05, 0.302603, 2.4e-05, 0.102331, 1.4e-05 },
      { 0.163539, 2.7e-05, 0.152565, 4.5e-05, 0.224375, 5.6e-05 },
      { 1.013919, 4.2e-05, 0.490516, 5.9e-05, 0.162938, 1.6e-05 },
      { 1.284465, 0.00016, 0.149115, 4.7e-05, 0.002350, 1.3e-05 },
      { 0.305802, 1.8e-05, 0.418217, 1.8e-05, 0.019661, 1.4e-05 } },
    { { 0.691529, 4.4e-05, 0.303514, 3e-05, 0.106611, 3e-05 },
      { 0.166333, 6e-05, 0.152570, 6.9e-05, 0.225599, 0.00011 },
      { 1.011238, 5.1e-05, 0.492756, 7.8e-05, 0.169075, 4.6e-05 },
      { 1.282126, 0.00011, 0.153487, 4.5e-05, 0.012223, 1.4e-05 },
      { 0.306417, 2.8e-05, 0.415242, 7.9e-06, 0.019546, 2.6e-05 } },
    { { 0.381000, 3.4e-05, 0.349971, 3.8e-05, 0.335754, 7.3e-05 },
      { 0.025792, 2.3e-05, 0.175108, 9.2e-05, 0.607707, 0.00028 },
      { 0.550606, 0.00011, 0.569675, 0.00012, 0.540278, 0.00013 },
      { 0.802672, 7.8e-05, 0.152217, 5.7e-05, 0.042786, 2.7e-05 },
      { 0.144931, 6.5e-05, 0.502882, 1.5e-05, 0.152247, 6.7e-05 } },
    { { 0.748232, 5.3e-05, 0.385344, 3.9e-05, 0.186689, 4.8e-05 },
      { 0.168427, 6.4e-05, 0.190003, 9.7e-05, 0.371979, 0.00018 },
      { 1.091943, 6.9e-05, 0.626925, 9.9e-05, 0.296548, 6.9e-05 },
      { 1.409023, 0.00013, 0.186342, 5.9e-05, 0.027451, 2.2e-05 },
      { 0.323536, 2.8e-05, 0.538104, 7.5e-06, 0.050777, 4.2e-05 } },
    { { 0.401008, 8.1e-05, 0.354851, 3.3e-05, 0.362768, 8.6e-05 },
      { 0.049618, 3.5e-05, 0.172107, 2.9e-05, 0.677658, 0.00031 },
      { 0.565993, 0.00019, 0.569526, 3.3e-05, 0.566782, 0.00011 },
      { 0.939332, 0.00018, 0.172447, 6.6e-05, 0.036531, 2.6e-05 },
      { 0.049091, 4e-05, 0.505326, 5.1e-05, 0.170100, 0.00011 } }
};

static void test_sensor_against_pbrt(T *t)
{
    static char buf[8192];
    int c, i, k;
    for (c = 0; c < 7; c++) {
        Scene s;
        RenderOptions o;
        Tiles q, whole;
        sensor_scene(buf, sizeof buf, SENSOR_CONFIG[c][0], SENSOR_CONFIG[c][1]);
        if (!test_load_scene(t, &s, buf)) return;
        render_options_default(&o);
        o.spp = test_scaled(64, 16);
        o.seed = 5;
        if (!test_render_tiles(t, &s, &o, 4, 2, &q) || !test_render_tiles(t, &s, &o, 4, 1, &whole)) {
            scene_free(&s);
            return;
        }
        scene_free(&s);
        for (i = 0; i < 5; i++)
            for (k = 0; k < 3; k++) {
                const Tiles *tl = i == 0 ? &whole : &q;
                int j = i == 0 ? 0 : i - 1;
                double v = tl->mean[j][k], se = tl->se[j][k];
                double p = PBRT_SENSOR[c][i][2 * k], sep = PBRT_SENSOR[c][i][2 * k + 1];
                double tol = TEST_K_SIGMA * sqrt(se * se + sep * sep) + 0.01 * fmax(fabs(p), 0.05);
                if (getenv("DBG"))
                    fprintf(stderr, "sensor %d tile %d ch %d: specnee %.6f +- %.2g, pbrt %.6f (%.2f tol)\n",
                            c, i, k, v, se, p, fabs(v - p) / tol);
                CHECK(t, fabs(v - p) <= tol, "Film %s: %s %d channel %d: specnee %.5f +- %.2g, "
                      "pbrt-v4 %.5f +- %.2g", SENSOR_CONFIG[c][0], i ? "quadrant" : "image", j, k,
                      v, se, p, sep);
            }
    }
}

static int render_scene(T *t, const char *text, Image *im)
{
    RenderOptions o;
    render_options_default(&o);
    o.spp = 4;
    o.seed = 3;
    o.threads = 2;
    return test_render_text(t, text, &o, im);
}

/* The imaging ratio (shutterclose - shutteropen) iso / 100 multiplies every
   sample's sensor RGB before the sensor's matrix: with a camera, iso 200, or iso
   400 over half the shutter time, is the iso 100 image times 2 exactly (a
   multiplication by 2 is exact in floating point, so bit for bit). */
static void test_sensor_imaging_ratio(T *t)
{
    static char buf[8192];
    Image a, b, c;
    int i, bad = 0;
    sensor_scene(buf, sizeof buf, "\"string sensor\" \"canon_eos_100d\"", "");
    if (!render_scene(t, buf, &a)) return;
    sensor_scene(buf, sizeof buf, "\"string sensor\" \"canon_eos_100d\" \"float iso\" [ 200 ]", "");
    if (!render_scene(t, buf, &b)) { img_free(&a); return; }
    sensor_scene(buf, sizeof buf, "\"string sensor\" \"canon_eos_100d\" \"float iso\" [ 400 ]",
                 "\"float shutteropen\" [ 0.5 ] \"float shutterclose\" [ 1 ]");
    if (!render_scene(t, buf, &c)) { img_free(&a); img_free(&b); return; }
    for (i = 0; i < 3 * a.w * a.h && !bad; i++)
        if (b.rgb[i] != 2.0f * a.rgb[i] || c.rgb[i] != 2.0f * a.rgb[i]) {
            test_failf(t, __FILE__, __LINE__, "value %d: %.9g, iso 200: %.9g, iso 400 and a 0.5 "
                       "shutter: %.9g (want exactly x2)", i, a.rgb[i], b.rgb[i], c.rgb[i]);
            bad = 1;
        }
    CHECK(t, a.rgb[0] > 0.0f, "the image is black");
    img_free(&a); img_free(&b); img_free(&c);
}

/* The camera fit maps the ColorChecker under the balance's illuminant to its XYZ
   under D65 at the camera's white brightness: a white (reflectance 1) under the
   illuminant comes out close to D65's chromaticity (0.3127, 0.3290), at Y close to
   sum ybar E / sum g E times the camera's green response to it (1 here).  For
   every camera, at 6500 K (the default) and 3000 K (a blackbody): a least-squares
   fit over 24 patches is not exact, so within 0.01 in x and y and 3 % in Y; and
   without the balance (the sensor RGB read as XYZ) the 3000 K white is far off. */
static void test_sensor_fit_white(T *t)
{
    static const float temps[2] = { 6500.0f, 3000.0f };
    int s, k, nm, c;
    for (s = 1; s <= SENSOR_CAMERAS; s++)
        for (k = 0; k < 2; k++) {
            double m[9], rgb[3] = { 0, 0, 0 }, xyz[3], yE = 0.0, sum, x, y;
            Spectrum E;
            CHECK(t, sensor_xyz_matrix(s, temps[k], m), "%s: no fit", sensor_name(s));
            if (temps[k] == 6500.0f) spec_named(&E, "stdillum-D65");
            else spec_blackbody(&E, temps[k] * 1.4388f / 1.4380f);
            for (nm = SPEC_MIN; nm <= SPEC_MAX; nm++) {
                float r[3];
                double cmf[3];
                sensor_response(s, (float)nm, r);
                cie_cmf(nm, cmf);
                for (c = 0; c < 3; c++) rgb[c] += r[c] * spec_get(&E, nm);
                yE += cmf[1] * spec_get(&E, nm);
            }
            yE /= rgb[1];
            rgb[0] /= rgb[1]; rgb[2] /= rgb[1]; rgb[1] = 1.0;
            for (c = 0; c < 3; c++) xyz[c] = m[3 * c] * rgb[0] + m[3 * c + 1] * rgb[1] + m[3 * c + 2] * rgb[2];
            sum = xyz[0] + xyz[1] + xyz[2];
            x = xyz[0] / sum;
            y = xyz[1] / sum;
            CHECK(t, fabs(x - 0.3127) < 0.01 && fabs(y - 0.3290) < 0.01 && fabs(xyz[1] / yE - 1.0) < 0.03,
                  "%s at %g K: the white comes out at xy (%.4f, %.4f), Y %.4f of %.4f",
                  sensor_name(s), temps[k], x, y, xyz[1], yE);
            if (k == 1) {
                sum = rgb[0] + rgb[1] + rgb[2];
                CHECK(t, fabs(rgb[0] / sum - 0.3127) > 0.03 || fabs(rgb[1] / sum - 0.3290) > 0.03,
                      "%s: its raw RGB of a 3000 K white is already neutral: the test has no power",
                      sensor_name(s));
            }
        }
}

/* Every name pbrt-v4 knows is read (and named back); cie1931's curves are the CIE
   1931 observer's, bit for bit, and it has no matrix without a white balance; a
   camera's curves are held constant beyond 380..720 nm and are 0 outside
   360..830 nm. */
static void test_sensor_names(T *t)
{
    static const char *const want[] = {
        "canon_eos_100d", "canon_eos_1dx_mkii", "canon_eos_200d", "canon_eos_200d_mkii",
        "canon_eos_5d", "canon_eos_5d_mkii", "canon_eos_5d_mkiii", "canon_eos_5d_mkiv",
        "canon_eos_5ds", "canon_eos_m", "hasselblad_l1d_20c", "nikon_d810", "nikon_d850",
        "sony_ilce_6400", "sony_ilce_7m3", "sony_ilce_7rm3", "sony_ilce_9"
    };
    float a[3], b[3], lo[3], hi[3];
    double m[9];
    int i, lam;
    CHECK(t, sensor_index("cie1931") == 0 && !strcmp(sensor_name(0), "cie1931"), "cie1931 is not sensor 0");
    CHECK(t, sensor_index("kodak") == -1 && sensor_index("") == -1, "an unknown name is a sensor");
    for (i = 0; i < SENSOR_CAMERAS; i++)
        CHECK(t, sensor_index(want[i]) == i + 1 && !strcmp(sensor_name(i + 1), want[i]),
              "%s: index %d", want[i], sensor_index(want[i]));
    for (lam = 360; lam <= 830; lam += 7) {
        sensor_response(0, lam + 0.3f, a);
        cie_xyz(lam + 0.3f, b);
        CHECK(t, !memcmp(a, b, sizeof a), "cie1931 at %g nm: (%g %g %g), not the CMFs", lam + 0.3, a[0], a[1], a[2]);
    }
    CHECK(t, sensor_xyz_matrix(0, 0.0f, m) && m[0] == 1.0 && m[4] == 1.0 && m[8] == 1.0 && m[1] == 0.0,
          "cie1931 without a balance is not the identity");
    for (i = 1; i <= SENSOR_CAMERAS; i++) {
        sensor_response(i, 380.0f, a);
        sensor_response(i, 365.0f, lo);
        sensor_response(i, 720.0f, b);
        sensor_response(i, 825.0f, hi);
        CHECK(t, !memcmp(a, lo, sizeof a) && !memcmp(b, hi, sizeof b) && a[1] > 0.0f,
              "%s: not held constant outside 380..720 nm", sensor_name(i));
        sensor_response(i, 355.0f, lo);
        sensor_response(i, 835.0f, hi);
        CHECK(t, lo[0] == 0.0f && lo[2] == 0.0f && hi[1] == 0.0f, "%s: not 0 outside 360..830 nm",
              sensor_name(i));
    }
    sensor_response(13, 525.0f, a);      /* nikon_d850's g halfway between its 520 and 530 nm knots */
    sensor_response(13, 520.0f, lo);
    sensor_response(13, 530.0f, hi);
    CHECK(t, fabsf(a[1] - 0.5f * (lo[1] + hi[1])) < 1e-6f, "not linear between knots: %g vs %g %g",
          a[1], lo[1], hi[1]);
}

/* A bad sensor name: one line at its file:line naming the accepted ones. */
static void test_sensor_refused(T *t)
{
    static char buf[8192];
    Scene s;
    Error e;
    sensor_scene(buf, sizeof buf, "\"string sensor\" \"kodak\"", "");
    e.msg[0] = 0;
    CHECK(t, !scene_load_string(&s, buf, "t.pbrt", &e) && !strncmp(e.msg, "t.pbrt:1: Film: \"string "
          "sensor\" \"kodak\": unknown sensor type (pbrt-v4 knows \"cie1931\" and 17 named cameras: "
          "canon_eos_100d, canon_eos_1dx_mkii, ", 122) && strstr(e.msg, ", sony_ilce_9)")
          && !strchr(e.msg, '\n'), "message: %s", e.msg);
    scene_free(&s);
}

const TestCase tests_sensor[] = {
    { "sensor_against_pbrt", test_sensor_against_pbrt },
    { "sensor_imaging_ratio", test_sensor_imaging_ratio },
    { "sensor_fit_white", test_sensor_fit_white },
    { "sensor_names", test_sensor_names },
    { "sensor_refused", test_sensor_refused },
    { NULL, NULL }
};
