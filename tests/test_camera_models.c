/* tests/test_camera_models.c - pbrt-v4's orthographic and spherical cameras
   (camera.c: camera_ray; options.c: their Camera statements).

   Checked: the orthographic camera's ray origins span exactly the screen window
   (given, the film's default and "frameaspectratio"'s) in world units along the
   camera's right and up axes, and every direction is its z axis; its thin lens
   sends each ray from the lens disk at the camera's origin through the raster
   point's point on the plane of focus; the spherical camera's axes for both
   mappings, the equal-area map's fold across the film's border, and its equal
   solid angle per pixel (numerically, from each pixel's outline on the sphere,
   and by rendering a sphere light of known solid angle); a spherical camera in a
   uniform environment sees it in every pixel; both cameras move (motion.c); the
   last Camera statement wins; the refusals at their file:line; pbrt-v4's images
   of four small scenes. */
#include "test.h"
#include "../render.h"
#include <string.h>

/* Load `camera` (the statements up to and including Camera) with a w x h film
   and an empty world, and build its Camera. */
static int load_camera(T *t, const char *camera, int w, int h, Scene *s, Camera *c)
{
    char buf[2048];
    snprintf(buf, sizeof buf, "%s\nFilm \"rgb\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ] "
             "\"string filename\" \"c.pfm\"\nWorldBegin\n", camera, w, h);
    if (!test_load_scene(t, s, buf)) return 0;
    camera_init(c, &s->settings);
    return 1;
}

static float dist3(Vec3 a, Vec3 b) { return v3_len(v3_sub(a, b)); }

/* The ray of raster (x, y) at time 0 with lens sample (u0, u1). */
static Ray ray_at(const Camera *c, float x, float y, float u0, float u1)
{
    float w;
    return camera_ray(c, x, y, u0, u1, 0.0f, &w);
}

/* LookAt 1 2 3  1 2 -2  0 1 0: the eye E = (1, 2, 3) looks along D = (0, 0, -1);
   pbrt's left-handed frame has right = up x D = (-1, 0, 0) and up (0, 1, 0). */
#define ORTHO_LOOK "LookAt 1 2 3  1 2 -2  0 1 0\n"

/* Raster (x, y) of a 40 x 20 film starts at E + sx right + sy up, sx = x0 + (x /
   40)(x1 - x0), sy = y1 - (y / 20)(y1 - y0), and goes along D, for a given window,
   the film's default [-2, 2] x [-1, 1] (aspect 2) and the default of
   "frameaspectratio" 0.5, [-1, 1] x [-2, 2]. */
static void test_ortho_window(T *t)
{
    static const char *const cam[3] = {
        ORTHO_LOOK "Camera \"orthographic\" \"float screenwindow\" [ -3 1 -0.5 2 ]",
        ORTHO_LOOK "Camera \"orthographic\"",
        ORTHO_LOOK "Camera \"orthographic\" \"float frameaspectratio\" [ 0.5 ]",
    };
    static const float win[3][4] = { { -3, 1, -0.5f, 2 }, { -2, 2, -1, 1 }, { -1, 1, -2, 2 } };
    const Vec3 E = v3(1, 2, 3), D = v3(0, 0, -1), R = v3(-1, 0, 0), U = v3(0, 1, 0);
    int k, x, y;
    for (k = 0; k < 3; k++) {
        Scene s;
        Camera c;
        if (!load_camera(t, cam[k], 40, 20, &s, &c)) return;
        scene_free(&s);
        CHECK(t, !camera_has_lens(&c), "camera %d: a pinhole reads no lens sample", k);
        for (y = 0; y <= 20; y += 5)
            for (x = 0; x <= 40; x += 5) {
                float sx = win[k][0] + (float)x / 40.0f * (win[k][1] - win[k][0]);
                float sy = win[k][3] - (float)y / 20.0f * (win[k][3] - win[k][2]);
                Vec3 want = v3_add(E, v3_add(v3_mul(R, sx), v3_mul(U, sy)));
                Ray r = ray_at(&c, (float)x, (float)y, 0.5f, 0.5f);
                CHECK(t, dist3(r.o, want) < 1e-5f, "camera %d, raster (%d, %d): origin (%g, %g, %g), want (%g, %g, %g)",
                      k, x, y, r.o.x, r.o.y, r.o.z, want.x, want.y, want.z);
                CHECK(t, dist3(r.d, D) < 1e-6f, "camera %d, raster (%d, %d): direction (%g, %g, %g), want (0, 0, -1)",
                      k, x, y, r.d.x, r.d.y, r.d.z);
            }
    }
}

/* "lensradius" 0.25, "focaldistance" 4: each ray leaves a point of the disk of
   radius 0.25 about E in the plane normal to D (pbrt-v4's lens sits at the
   camera's origin), passes through F = E + sx right + sy up + 4 D, and the lens
   centre's ray runs from E straight to F. */
static void test_ortho_thin_lens(T *t)
{
    const Vec3 E = v3(1, 2, 3), D = v3(0, 0, -1), R = v3(-1, 0, 0), U = v3(0, 1, 0);
    Scene s;
    Camera c;
    Rng rng;
    int i;
    if (!load_camera(t, ORTHO_LOOK "Camera \"orthographic\" \"float screenwindow\" [ -3 1 -0.5 2 ] "
                     "\"float lensradius\" [ 0.25 ] \"float focaldistance\" [ 4 ]", 40, 20, &s, &c)) return;
    scene_free(&s);
    CHECK(t, camera_has_lens(&c), "the thin lens reads its lens sample");
    rng_seed(&rng, 7, 0);
    for (i = 0; i < 200; i++) {
        float u[4], sx, sy;
        Vec3 F, toF;
        Ray r;
        rng_fill(&rng, u, 4);
        if (i == 0) u[2] = u[3] = 0.5f;                       /* the lens centre */
        sx = -3.0f + u[0] * 4.0f;
        sy = 2.0f - u[1] * 2.5f;
        F = v3_add(v3_add(E, v3_mul(D, 4.0f)), v3_add(v3_mul(R, sx), v3_mul(U, sy)));
        r = ray_at(&c, 40.0f * u[0], 20.0f * u[1], u[2], u[3]);
        toF = v3_sub(F, r.o);
        CHECK(t, fabsf(v3_dot(v3_sub(r.o, E), D)) < 1e-5f && dist3(r.o, E) <= 0.25f + 1e-5f,
              "ray %d leaves (%g, %g, %g): not on the lens disk about the eye", i, r.o.x, r.o.y, r.o.z);
        CHECK(t, v3_len(v3_cross(toF, r.d)) < 1e-5f * v3_len(toF) && v3_dot(toF, r.d) > 0.0f,
              "ray %d misses its point of focus (%g, %g, %g)", i, F.x, F.y, F.z);
        CHECK(t, i > 0 || dist3(r.o, E) < 1e-6f, "the lens centre's ray leaves (%g, %g, %g), not the eye",
              r.o.x, r.o.y, r.o.z);
    }
}

/* pbrt-v4 (cameras.cpp, 5f7a6068) reads "focaldistance" only where "lensradius"
   is > 0; exporters write "lensradius" 0 "focaldistance" 0 for a pinhole
   (trianglestrip/pbrt-v4: test_gpu.pbrt).  That camera is a pinhole whose rays
   are those of the camera without the two parameters; a lens focused at 0 stays
   refused. */
static void test_lens_zero_focus_unused(T *t)
{
    static const char *const cam[2] = {
        ORTHO_LOOK "Camera \"perspective\" \"float fov\" [ 50 ] \"float lensradius\" [ 0 ] \"float focaldistance\" [ 0 ]",
        ORTHO_LOOK "Camera \"perspective\" \"float fov\" [ 50 ]",
    };
    Scene s;
    Camera c[2];
    int k, x, y;
    for (k = 0; k < 2; k++) {
        if (!load_camera(t, cam[k], 40, 20, &s, &c[k])) return;
        scene_free(&s);
    }
    CHECK(t, !camera_has_lens(&c[0]), "lensradius 0: a pinhole reads no lens sample");
    for (y = 0; y <= 20; y += 5)
        for (x = 0; x <= 40; x += 5) {
            Ray a = ray_at(&c[0], (float)x, (float)y, 0.3f, 0.8f), b = ray_at(&c[1], (float)x, (float)y, 0.3f, 0.8f);
            CHECK(t, dist3(a.o, b.o) == 0.0f && dist3(a.d, b.d) == 0.0f,
                  "raster (%d, %d): ray (%g, %g, %g) -> (%g, %g, %g), the pinhole's (%g, %g, %g) -> (%g, %g, %g)",
                  x, y, a.o.x, a.o.y, a.o.z, a.d.x, a.d.y, a.d.z, b.o.x, b.o.y, b.o.z, b.d.x, b.d.y, b.d.z);
        }
    test_rejected_at(t, "Camera \"perspective\" \"float lensradius\" [ 0.5 ] \"float focaldistance\" [ 0 ]\nWorldBegin\n",
                     1, "\"float lensradius\" 0.5 must be >= 0 and \"float focaldistance\" 0 > 0", NULL);
}

/* The camera at the origin, its frame the world's (LookAt along +z, up +y; pbrt's
   right = up x dir = +x). */
#define SPH_LOOK "LookAt 0 0 0  0 0 1  0 1 0\n"

/* The directions of named film points: equirectangular, the top row looks up,
   the middle row at u = 0, 1/4, 1/2, 3/4 right, forward, left, back; equal
   area, the centre up, the corners down, the middles of the right, bottom, left
   and top edges right, forward, left and back (the swap of y and z).  A lens
   radius changes nothing (pbrt-v4 reads and ignores it). */
static void test_spherical_axes(T *t)
{
    static const char *const cam[3] = {
        SPH_LOOK "Camera \"spherical\" \"string mapping\" \"equirectangular\"",
        SPH_LOOK "Camera \"spherical\"",
        SPH_LOOK "Camera \"spherical\" \"float lensradius\" [ 0.5 ] \"float focaldistance\" [ 2 ]",
    };
    static const float pts[2][7][5] = {   /* u, v, want direction */
        { { 0.5f, 0, 0, 1, 0 }, { 0.5f, 1, 0, -1, 0 }, { 0, 0.5f, 1, 0, 0 }, { 0.25f, 0.5f, 0, 0, 1 },
          { 0.5f, 0.5f, -1, 0, 0 }, { 0.75f, 0.5f, 0, 0, -1 }, { 0.125f, 0.25f, 0.5f, 0.70710678f, 0.5f } },
        { { 0.5f, 0.5f, 0, 1, 0 }, { 0, 0, 0, -1, 0 }, { 1, 1, 0, -1, 0 }, { 1, 0.5f, 1, 0, 0 },
          { 0.5f, 1, 0, 0, 1 }, { 0, 0.5f, -1, 0, 0 }, { 0.5f, 0, 0, 0, -1 } },
    };
    int k, i;
    for (k = 0; k < 3; k++) {
        Scene s;
        Camera c;
        if (!load_camera(t, cam[k], 40, 20, &s, &c)) return;
        scene_free(&s);
        CHECK(t, !camera_has_lens(&c), "the spherical camera reads no lens sample");
        for (i = 0; i < 7; i++) {
            const float *p = pts[k ? 1 : 0][i];
            Ray r = ray_at(&c, 40.0f * p[0], 20.0f * p[1], 0.5f, 0.5f);
            CHECK(t, v3_len(r.o) == 0.0f, "mapping %d: the rays leave the eye", k);
            CHECK(t, dist3(r.d, v3(p[2], p[3], p[4])) < 1e-5f, "mapping %d, (u, v) = (%g, %g): direction "
                  "(%g, %g, %g), want (%g, %g, %g)", k, p[0], p[1], r.d.x, r.d.y, r.d.z, p[2], p[3], p[4]);
        }
    }
}

/* A filter's sample just outside the film: the equal-area map folds it back
   across the edge it crossed, u < 0 -> (-u, 1 - v), u > 1 -> (2 - u, 1 - v),
   then v the same with u -> 1 - u; its neighbour inside looks almost the same
   way. */
static void test_spherical_fold(T *t)
{
    static const float out[6][4] = {   /* raster outside, raster of the fold (32 x 32) */
        { -0.3f, 5.0f, 0.3f, 27.0f }, { 32.4f, 9.0f, 31.6f, 23.0f }, { 7.0f, -0.5f, 25.0f, 0.5f },
        { 11.0f, 32.2f, 21.0f, 31.8f }, { -0.2f, -0.4f, 31.8f, 31.6f }, { 32.3f, 32.1f, 0.3f, 0.1f },
    };
    Scene s;
    Camera c;
    int i;
    if (!load_camera(t, SPH_LOOK "Camera \"spherical\" \"string mapping\" \"equalarea\"", 32, 32, &s, &c)) return;
    scene_free(&s);
    for (i = 0; i < 6; i++) {
        Ray a = ray_at(&c, out[i][0], out[i][1], 0.5f, 0.5f), b = ray_at(&c, out[i][2], out[i][3], 0.5f, 0.5f);
        Ray in = ray_at(&c, fminf(fmaxf(out[i][0], 0.0f), 32.0f), fminf(fmaxf(out[i][1], 0.0f), 32.0f), 0.5f, 0.5f);
        CHECK(t, dist3(a.d, b.d) < 1e-5f, "raster (%g, %g) looks along (%g, %g, %g), its fold (%g, %g) along "
              "(%g, %g, %g)", out[i][0], out[i][1], a.d.x, a.d.y, a.d.z, out[i][2], out[i][3], b.d.x, b.d.y, b.d.z);
        CHECK(t, dist3(a.d, in.d) < 0.1f, "raster (%g, %g): not continuous across the film's border", out[i][0],
              out[i][1]);
    }
}

/* The solid angle of the spherical triangle a b c (Van Oosterom and Strackee),
   signed by its orientation. */
static double tri_solid_angle(Vec3 a, Vec3 b, Vec3 c)
{
    double det = a.x * ((double)b.y * c.z - (double)b.z * c.y) - a.y * ((double)b.x * c.z - (double)b.z * c.x)
               + a.z * ((double)b.x * c.y - (double)b.y * c.x);
    double den = 1.0 + v3_dot(a, b) + v3_dot(b, c) + v3_dot(c, a);
    return 2.0 * atan2(det, den);
}

/* The solid angle of pixel (px, py)'s image on the sphere: a fan from its
   centre's direction over its outline, each edge cut into m pieces. */
static double pixel_solid_angle(const Camera *c, int px, int py, int m)
{
    static const float corner[5][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 }, { 0, 0 } };
    Vec3 ctr = ray_at(c, (float)px + 0.5f, (float)py + 0.5f, 0.5f, 0.5f).d, prev = ctr;
    double sum = 0.0;
    int e, j;
    for (e = 0; e < 4; e++)
        for (j = 0; j <= m; j++) {
            float f = (float)j / (float)m;
            float x = (float)px + corner[e][0] + f * (corner[e + 1][0] - corner[e][0]);
            float y = (float)py + corner[e][1] + f * (corner[e + 1][1] - corner[e][1]);
            Vec3 d = ray_at(c, x, y, 0.5f, 0.5f).d;
            if (e > 0 || j > 0) sum += tri_solid_angle(ctr, prev, d);
            prev = d;
        }
    return fabs(sum);
}

/* Equal area: every pixel of a 16 x 16 film subtends 4 pi / 256 sr (within 0.5 %,
   the outline's polygon error), and the pixels together the whole sphere;
   equirectangular: the pixels of the top row subtend less than half of that. */
static void test_spherical_equal_area(T *t)
{
    const double want = 4.0 * SPECNEE_PI / 256.0;
    Scene s;
    Camera c;
    double total = 0.0, top;
    int px, py;
    if (!load_camera(t, SPH_LOOK "Camera \"spherical\"", 16, 16, &s, &c)) return;
    scene_free(&s);
    for (py = 0; py < 16; py++)
        for (px = 0; px < 16; px++) {
            double a = pixel_solid_angle(&c, px, py, 32);
            total += a;
            CHECK(t, fabs(a / want - 1.0) < 5e-3, "pixel (%d, %d) subtends %.6g sr, want 4 pi / 256 = %.6g",
                  px, py, a, want);
        }
    CHECK(t, fabs(total / (4.0 * SPECNEE_PI) - 1.0) < 1e-3, "the pixels subtend %.6g sr, want 4 pi", total);
    if (!load_camera(t, SPH_LOOK "Camera \"spherical\" \"string mapping\" \"equirectangular\"", 16, 16, &s, &c))
        return;
    scene_free(&s);
    top = pixel_solid_angle(&c, 3, 0, 32);
    CHECK(t, top < 0.5 * want, "equirectangular: a top pixel subtends %.6g sr, want < %.6g", top, 0.5 * want);
}

/* Render `text` at 64 spp (seed 3); 0 when the test failed. */
static int render64(T *t, const char *text, Image *im)
{
    RenderOptions o;
    render_options_default(&o);
    o.spp = test_scaled(64, 32);
    o.seed = 3;
    return test_render_text(t, text, &o, im);
}

static double mean_y(const Image *im) { return test_image_y(im); }

/* Inside a uniform environment of L = 0.5 every pixel of both mappings sees
   L (each within 3 %: the spectral noise of 64 samples), as the perspective
   camera's image does, on films of other shapes too. */
static void test_spherical_uniform_environment(T *t)
{
    static const char *const cam[3] = {
        "Camera \"perspective\"", "Camera \"spherical\"", "Camera \"spherical\" \"string mapping\" \"equirectangular\"",
    };
    char buf[1024];
    double ref = 0.0;
    int k, i;
    for (k = 0; k < 3; k++) {
        Image im;
        snprintf(buf, sizeof buf, SPH_LOOK "%s\nFilm \"rgb\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ 12 ] "
                 "\"string filename\" \"u.pfm\"\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [ 0.5 0.5 0.5 ]\n",
                 cam[k], k == 2 ? 24 : 16);
        if (!render64(t, buf, &im)) return;
        if (k == 0) ref = mean_y(&im);
        for (i = 0; i < im.w * im.h; i++) {
            const float *p = im.rgb + 3 * i;
            double y = 0.212671 * p[0] + 0.715160 * p[1] + 0.072169 * p[2];
            if (fabs(y / ref - 1.0) > 0.03) {
                img_free(&im);
                CHECK(t, 0, "%s: pixel %d reads Y %.5g, the environment %.5g", cam[k], i, y, ref);
            }
        }
        img_free(&im);
    }
    CHECK(t, fabs(ref - 0.5) < 0.01, "the environment of L = 0.5 reads Y %.5g", ref);
}

/* A sphere light of radius 1 at distance 3 subtends Omega = 2 pi (1 - sqrt(8/9))
   sr; on the equal-area film it covers Omega / 4 pi of the area, whichever way
   it lies (forward, up at the film's centre, down at its corners, askew), so the
   image's mean is that fraction of the mean of the camera inside an emitting
   sphere (black, so the inside sees L alone; box filter: each pixel is the
   mean over its area; 3 %).  On the
   equirectangular film the sphere overhead covers the whole top band: more than
   1.5 times that fraction. */
static void test_spherical_sphere_light(T *t)
{
    static const char *const where[4] = { "0 0 3", "0 3 0", "0 -3 0", "1.7320508 -1.7320508 1.7320508" };
    const double frac = 0.5 * (1.0 - sqrt(8.0 / 9.0));
    char buf[1024];
    double inside = 0.0;
    int k;
    for (k = -1; k < 5; k++) {
        Image im;
        double m;
        snprintf(buf, sizeof buf, SPH_LOOK "Camera \"spherical\"%s\nFilm \"rgb\" \"integer xresolution\" [ 32 ] "
                 "\"integer yresolution\" [ 32 ] \"string filename\" \"s.pfm\"\nPixelFilter \"box\"\nWorldBegin\n"
                 "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
                 "AttributeBegin\nTranslate %s\nAreaLightSource \"diffuse\" \"bool twosided\" true \"rgb L\" [ 1 1 1 ]\n"
                 "Shape \"sphere\" \"float radius\" [ %s ]\nAttributeEnd\n",
                 k == 4 ? " \"string mapping\" \"equirectangular\"" : "", k < 0 ? "0 0 0" : k == 4 ? "0 3 0" : where[k],
                 k < 0 ? "5" : "1");
        if (!render64(t, buf, &im)) return;
        m = mean_y(&im);
        img_free(&im);
        if (k < 0) { inside = m; continue; }
        if (k == 4)
            CHECK(t, m / inside > 1.5 * frac, "equirectangular, the sphere overhead covers %.5g, want > %.5g",
                  m / inside, 1.5 * frac);
        else
            CHECK(t, fabs(m / inside / frac - 1.0) < 0.03, "equal area, the sphere at (%s) covers %.5g of the "
                  "film, want Omega / 4 pi = %.5g", where[k], m / inside, frac);
    }
}

/* A camera moving 2 along +z over the shutter (ActiveTransform EndTime): at time
   1/2 the orthographic ray of every raster point starts 1 further along z than
   at time 0, the spherical camera's rays start at (0, 0, 1); the directions stay. */
static void test_camera_models_move(T *t)
{
    static const char *const cam[2] = {
        "ActiveTransform EndTime\nTranslate 0 0 -2\nActiveTransform All\nCamera \"orthographic\"",
        "ActiveTransform EndTime\nTranslate 0 0 -2\nActiveTransform All\nCamera \"spherical\"",
    };
    int k, i;
    for (k = 0; k < 2; k++) {
        Scene s;
        Camera c;
        if (!load_camera(t, cam[k], 20, 10, &s, &c)) return;
        scene_free(&s);
        CHECK(t, c.moving, "camera %d does not move", k);
        for (i = 0; i < 5; i++) {
            float w, x = 4.0f * (float)i + 1.5f, y = 2.0f * (float)i + 0.5f;
            Ray r0 = camera_ray(&c, x, y, 0.5f, 0.5f, 0.0f, &w), r1 = camera_ray(&c, x, y, 0.5f, 0.5f, 0.5f, &w);
            CHECK(t, dist3(v3_sub(r1.o, r0.o), v3(0, 0, 1)) < 1e-5f && dist3(r0.d, r1.d) < 1e-6f,
                  "camera %d, raster (%g, %g): time 1/2 moves the ray by (%g, %g, %g)", k, x, y,
                  r1.o.x - r0.o.x, r1.o.y - r0.o.y, r1.o.z - r0.o.z);
            CHECK(t, k == 0 || v3_len(v3_sub(r1.o, v3(0, 0, 1))) < 1e-6f, "the spherical camera's eye at time 1/2");
        }
    }
}

/* A pinhole's rays all start at its eye, which camera_init works out once
   (Camera.eye): bit for bit xf_point(world_from_camera, 0), at the LookAt's
   eye, for the perspective and the spherical camera; a thin lens's rays start
   on the lens, not at the eye (the lens samples 0.1 and 0.9 along x map to -0.8
   and 0.8 of the radius 0.5, 0.8 apart). */
static void test_camera_eye(T *t)
{
    static const char *const cam[3] = {
        "LookAt 1 2 3  1 2 -2  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]",
        "LookAt 1 2 3  1 2 -2  0 1 0\nCamera \"spherical\"",
        "LookAt 1 2 3  1 2 -2  0 1 0\nCamera \"perspective\" \"float lensradius\" [ 0.5 ] \"float focaldistance\" [ 4 ]",
    };
    int k, i, bad = 0;
    for (k = 0; k < 3; k++) {
        Scene s;
        Camera c;
        Vec3 eye;
        if (!load_camera(t, cam[k], 20, 10, &s, &c)) return;
        scene_free(&s);
        eye = xf_point(&c.world_from_camera, v3(0.0f, 0.0f, 0.0f));
        for (i = 0; i < 7; i++) {
            float x = 3.0f * (float)i + 0.25f, y = 1.5f * (float)i + 0.75f;
            Ray r0 = ray_at(&c, x, y, 0.1f, 0.5f), r1 = ray_at(&c, x, y, 0.9f, 0.5f);
            if (k < 2 && (memcmp(&r0.o, &eye, sizeof eye) || memcmp(&r1.o, &eye, sizeof eye))) bad++;
            if (k == 2 && !(fabsf(dist3(r0.o, r1.o) - 0.8f) < 1e-4f)) bad++;
        }
        CHECK(t, dist3(eye, v3(1, 2, 3)) < 1e-6f, "camera %d: the eye at (%g, %g, %g), want (1, 2, 3)",
              k, eye.x, eye.y, eye.z);
        CHECK(t, bad == 0, "camera %d: %d rays start off %s", k, bad, k < 2 ? "the eye" : "the lens");
    }
}

/* The last Camera statement wins, whatever the types before it. */
static void test_camera_models_last_wins(T *t)
{
    static const char *const text[3] = {
        "Camera \"spherical\"\nCamera \"perspective\"\nWorldBegin\n",
        "Camera \"perspective\"\nCamera \"orthographic\"\nWorldBegin\n",
        "Camera \"orthographic\"\nCamera \"realistic\" \"string lensfile\" \"tests/data/lenses/dgauss.50mm.dat\"\nWorldBegin\n",
    };
    static const CameraType want[3] = { CAMERA_PERSPECTIVE, CAMERA_ORTHOGRAPHIC, CAMERA_PERSPECTIVE };
    int k;
    for (k = 0; k < 3; k++) {
        Scene s;
        CameraType got;
        int lens;
        if (!test_load_scene(t, &s, text[k])) return;
        got = s.settings.camera_type;
        lens = s.settings.lens.n;
        scene_free(&s);
        CHECK(t, got == want[k] && (k == 2) == (lens > 0), "scene %d: camera type %d (lens %d), want %d", k,
              (int)got, lens, (int)want[k]);
    }
}

static void test_camera_models_errors(T *t)
{
    test_rejected_at(t, SPH_LOOK "Camera \"spherical\"\n  \"string mapping\" \"cubemap\"\nWorldBegin\n", 3,
                     "Camera \"spherical\": \"string mapping\" \"cubemap\": unknown mapping", "equirectangular");
    if (t->failed) return;
    test_rejected_at(t, "Camera \"orthographic\"\n \"float fov\" [ 30 ]\nWorldBegin\n", 2,
                     "\"float fov\": unused parameter", "Camera \"orthographic\"");
    if (t->failed) return;
    test_rejected_at(t, "Camera \"orthographic\" \"float screenwindow\" [ -1 1 2 ]\nWorldBegin\n", 1,
                     "\"float screenwindow\": 3 values", NULL);
    if (t->failed) return;
    test_rejected_at(t, "Camera \"orthographic\" \"float lensradius\" [ -1 ]\nWorldBegin\n", 1,
                     "\"float lensradius\" -1 must be >= 0", NULL);
    if (t->failed) return;
    test_rejected_at(t, "Camera \"spherical\" \"float shutteropen\" 1 \"float shutterclose\" 1\nWorldBegin\n", 1,
                     "the shutter never opens", NULL);
    if (t->failed) return;
    test_rejected_at(t, "Camera \"fisheye\"\nWorldBegin\n", 1, "Camera \"fisheye\": unknown camera type", NULL);
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 2048` for S = 1..8)
   rendered the scenes below: (a) an orthographic camera with an off-centre
   window over a floor with a red and a blue sphere and a yellow quad, under a
   grey sky and a sun; (b) the same through its thin lens (pbrt-v4's: the lens at
   the camera's origin, focused at 5); (c) and (d) a spherical camera 1 above a
   floor among four coloured spheres (ahead, right, overhead, behind left), the
   equal-area and equirectangular mappings.  Luminance of the image and of its
   2 x 2 quadrants (top left first): mean over the seeds and its standard error.
   specnee is accepted within 5 standard errors + 1 %. */
static const double PBRT_CAMERA_Y[4][5][2] = {
    { { 0.379392, 4.7e-05 }, { 0.372002, 0.00015 }, { 0.402211, 0.00017 }, { 0.358185, 0.00011 }, { 0.385172, 0.00014 } },
    { { 0.356604, 4.3e-05 }, { 0.323988, 9.3e-05 }, { 0.341887, 0.00014 }, { 0.369501, 0.00011 }, { 0.391040, 0.00014 } },
    { { 0.303684, 2.9e-05 }, { 0.290198, 0.00011 }, { 0.326471, 0.00013 }, { 0.299096, 7.9e-05 }, { 0.298973, 5.9e-05 } },
    { { 0.294419, 4.6e-05 }, { 0.245864, 5.4e-05 }, { 0.214309, 2.6e-05 }, { 0.348583, 0.00015 }, { 0.368920, 0.00023 } },
};

static const char *const ORTHO_WORLD =
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 24 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.3 0.3 0.3 ]\n"
    "LightSource \"distant\" \"point3 from\" [ 1 3 2 ] \"point3 to\" [ 0 0 0 ] \"float scale\" [ 2 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ]\n"
    "AttributeBegin\nTranslate 1 0.5 0\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
    "Shape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -1 0.3 0.8\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.1 0.2 0.8 ]\n"
    "Shape \"sphere\" \"float radius\" [ 0.3 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -0.5 0.4 -1.2\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.9 0.8 0.1 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -0.4 -0.4 0  0.4 -0.4 0  0.4 0.4 0  -0.4 0.4 0 ]\n"
    "AttributeEnd\n";

static const char *const SPHERICAL_WORLD =
    "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.3 0.3 0.3 ]\n"
    "LightSource \"distant\" \"point3 from\" [ 1 3 2 ] \"point3 to\" [ 0 0 0 ] \"float scale\" [ 2 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ]\n"
    "AttributeBegin\nTranslate 0 1 4\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
    "Shape \"sphere\" \"float radius\" [ 1.5 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate 4 1.5 1\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.1 0.8 0.1 ]\n"
    "Shape \"sphere\" \"float radius\" [ 1.2 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -1 5 -1\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.1 0.2 0.8 ]\n"
    "Shape \"sphere\" \"float radius\" [ 2 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -3 1 -3\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.9 0.8 0.1 ]\n"
    "Shape \"sphere\" \"float radius\" [ 1 ]\nAttributeEnd\n";

static const char *const CAMERA_SCENE_HEAD[4] = {
    "LookAt 3 4 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [ -2.4 2 -1.5 1.8 ]\n",
    "LookAt 3 4 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [ -2.4 2 -1.5 1.8 ] "
    "\"float lensradius\" [ 0.15 ] \"float focaldistance\" [ 5 ]\n",
    "LookAt 0 1 0  0 1 1  0 1 0\nCamera \"spherical\"\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n",
    "LookAt 0 1 0  0 1 1  0 1 0\nCamera \"spherical\" \"string mapping\" \"equirectangular\"\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 16 ] \"string filename\" \"x.pfm\"\n",
};

static void test_camera_models_against_pbrt(T *t)
{
    static const char *const what[4] = { "orthographic", "orthographic thin lens", "spherical equalarea",
                                         "spherical equirectangular" };
    static char buf[8192];
    int k;
    for (k = 0; k < 4; k++) {
        snprintf(buf, sizeof buf, "%s%s", CAMERA_SCENE_HEAD[k], k < 2 ? ORTHO_WORLD : SPHERICAL_WORLD);
        test_against_pbrt_y(t, buf, 3, PBRT_CAMERA_Y[k], 1e-2, what[k]);
        if (t->failed) return;
    }
}

const TestCase tests_camera_models[] = {
    { "camera_ortho_window", test_ortho_window },
    { "camera_ortho_thin_lens", test_ortho_thin_lens },
    { "camera_lens_zero_focus_unused", test_lens_zero_focus_unused },
    { "camera_spherical_axes", test_spherical_axes },
    { "camera_spherical_fold", test_spherical_fold },
    { "camera_spherical_equal_area", test_spherical_equal_area },
    { "camera_spherical_uniform_environment", test_spherical_uniform_environment },
    { "camera_spherical_sphere_light", test_spherical_sphere_light },
    { "camera_models_move", test_camera_models_move },
    { "camera_eye", test_camera_eye },
    { "camera_models_last_wins", test_camera_models_last_wins },
    { "camera_models_errors", test_camera_models_errors },
    { "camera_models_against_pbrt", test_camera_models_against_pbrt },
    { NULL, NULL }
};
