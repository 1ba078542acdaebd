/* tests/test_curve.c - pbrt-v4's Shape "curve" (curve.c; the hooks in geometry.c,
   bvh.c, bump.c).

   Checked: the bases and degree 2 against their closed forms (cubic and quadratic
   uniform b-splines, the quadratic Bezier) and a piece's blossoms against the
   whole curve; a straight cylinder curve seen by parallel rays covers exactly
   width / extent of them, its (u, v) run along and across it (v - 1/2 = +-y / W),
   its t is the centre line's depth and its normal sweeps a half tube (|n_y| =
   |sin(pi (v - 1/2))|); "float alpha" 0.5 lets half of them through; a flat
   curve faces every ray; the BVH's closest hit equals
   brute force over the pieces bit for bit, shadow rays agree with it, and images
   do not depend on the thread count; refusals at their file:line; pbrt-v4's image
   of flat, cylinder and ribbon curves frozen. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static const char *const CURVE_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] "
    "\"point3 to\" [ 0 0 0 ]\n";

static int load_curve(T *t, Scene *s, const char *body)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", CURVE_HEAD, body);
    return test_load_scene(t, s, buf);
}

static float v3_dist(Vec3 a, Vec3 b) { return v3_len(v3_sub(a, b)); }

/* The bases: b-splines (cubic, quadratic) and the quadratic Bezier turned into
   cubic Beziers are the same polynomials; a piece [u0, u1] is the curve there. */
static void test_curve_bases(T *t)
{
    Rng r;
    int trial, k;
    rng_seed(&r, 41, 0);
    for (trial = 0; trial < 50; trial++) {
        Vec3 p[4], b[4], q[3], c[4], qb[4];
        float u0, u1;
        for (k = 0; k < 4; k++) p[k] = v3_sub(v3_mul(rng_vec3(&r), 4.0f), v3(2, 2, 2));
        curve_bspline_to_bezier(p, b);
        curve_quadratic_bspline_to_bezier(p, q);
        curve_elevate_quadratic(q, c);
        curve_elevate_quadratic(p, qb);            /* the quadratic Bezier p0 p1 p2 */
        u0 = rng_float(&r) * 0.5f;
        u1 = 0.5f + rng_float(&r) * 0.5f;
        for (k = 0; k <= 8; k++) {
            const float x = k / 8.0f, y = 1 - x;
            /* uniform cubic b-spline: ((1-x)^3, 3x^3 - 6x^2 + 4, -3x^3 + 3x^2 + 3x + 1, x^3) / 6 */
            Vec3 want = v3_mul(v3_add(v3_add(v3_mul(p[0], y * y * y), v3_mul(p[1], 3 * x * x * x - 6 * x * x + 4)),
                                      v3_add(v3_mul(p[2], -3 * x * x * x + 3 * x * x + 3 * x + 1), v3_mul(p[3], x * x * x))),
                               1.0f / 6.0f);
            /* uniform quadratic b-spline: ((1-x)^2, -2x^2 + 2x + 1, x^2) / 2 */
            Vec3 want2 = v3_mul(v3_add(v3_add(v3_mul(p[0], y * y), v3_mul(p[1], -2 * x * x + 2 * x + 1)),
                                       v3_mul(p[2], x * x)), 0.5f);
            /* quadratic Bezier: (1-x)^2 p0 + 2x(1-x) p1 + x^2 p2 */
            Vec3 want3 = v3_add(v3_add(v3_mul(p[0], y * y), v3_mul(p[1], 2 * x * y)), v3_mul(p[2], x * x));
            Vec3 got = curve_bezier_eval(b, x, NULL), got2 = curve_bezier_eval(c, x, NULL);
            Vec3 got3 = curve_bezier_eval(qb, x, NULL), sub[4];
            CHECK(t, v3_dist(got, want) < 1e-5f, "cubic b-spline at %g: (%g %g %g), want (%g %g %g)",
                  x, got.x, got.y, got.z, want.x, want.y, want.z);
            CHECK(t, v3_dist(got2, want2) < 1e-5f, "quadratic b-spline at %g: (%g %g %g), want (%g %g %g)",
                  x, got2.x, got2.y, got2.z, want2.x, want2.y, want2.z);
            CHECK(t, v3_dist(got3, want3) < 1e-5f, "quadratic Bezier at %g: (%g %g %g), want (%g %g %g)",
                  x, got3.x, got3.y, got3.z, want3.x, want3.y, want3.z);
            curve_bezier_piece(p, u0, u1, sub);
            got = curve_bezier_eval(sub, x, NULL);
            want = curve_bezier_eval(p, (1 - x) * u0 + x * u1, NULL);
            CHECK(t, v3_dist(got, want) < 1e-5f, "piece [%g, %g] at %g: (%g %g %g), want (%g %g %g)",
                  u0, u1, x, got.x, got.y, got.z, want.x, want.y, want.z);
        }
    }
}

/* A straight cylinder curve along x from -1 to 1 (control points evenly spaced, so u
   = (x + 1) / 2), width W = 0.2, seen by rays straight down from z = 3 at random
   (x, y) in [-1.1, 1.1] x [-0.5, 0.5]: 2 W / 2.2 of them hit, none beyond the
   ends (flat caps: the perpendiculars at the ends bound it); a hit has t = 3 (the
   centre line's depth), u = (x + 1) / 2, |v - 1/2| = |y| / W with v on one side
   above 1/2, and the normal (0, n_y, n_z) with |n_y| = |sin(pi (v - 1/2))|. */
static void test_curve_cylinder_hits(T *t)
{
    Scene s;
    Rng r;
    const long n = test_scaled(20000, 4000);
    long i, hits = 0, bad_uv = 0, bad_n = 0, side = 0, eligible = 0, beyond = 0;
    const float W = 0.2f;
    const double p = W * 2.0 / 2.2;
    if (!load_curve(t, &s, "Shape \"curve\" \"string type\" \"cylinder\" \"float width\" [ 0.2 ] "
                           "\"point3 P\" [ -1 0 0  -0.333333333 0 0  0.333333333 0 0  1 0 0 ]\n"))
        return;
    rng_seed(&r, 43, 0);
    for (i = 0; i < n; i++) {
        float q[2];
        Ray ray;
        HitRecord h;
        SurfacePoint sp;
        rng_fill(&r, q, 2);
        ray.o = v3(-1.1f + 2.2f * q[0], q[1] - 0.5f, 3.0f);
        ray.d = v3(0, 0, -1);
        ray.tmax = 10.0f;
        if (!bvh_intersect(&s.bvh, &s, &ray, &h)) continue;
        hits++;
        if (fabsf(ray.o.x) > 1.0f + 1e-5f) beyond++;
        scene_surface_point(&s, &ray, &h, &sp);
        if (fabsf(h.t - 3.0f) > 1e-5f || fabsf(sp.u - (ray.o.x + 1) / 2) > 1e-4f ||
            fabsf(fabsf(sp.v - 0.5f) - fabsf(ray.o.y) / W) > 1e-4f)
            bad_uv++;
        if (fabsf(ray.o.y) > 1e-4f) {             /* off the centre line: which side */
            eligible++;
            side += (sp.v > 0.5f) != (ray.o.y > 0.0f);
        }
        if (fabsf(fabsf(sp.ng.y) - fabsf(sinf(PI_F * (sp.v - 0.5f)))) > 1e-4f || fabsf(sp.ng.x) > 1e-4f ||
            fabsf(v3_len(sp.ng) - 1) > 1e-5f)
            bad_n++;
    }
    CHECK(t, fabs((double)hits - n * p) <= 5.0 * sqrt(n * p * (1 - p)),
          "%ld of %ld rays hit, want %.0f (width / extent)", hits, n, n * p);
    CHECK(t, beyond == 0, "%ld rays beyond the ends hit", beyond);
    CHECK(t, bad_uv == 0, "%ld hits with t, u or v off the closed form", bad_uv);
    CHECK(t, side == 0 || side == eligible, "v > 1/2 on both sides of the curve (%ld of %ld)", side, eligible);
    CHECK(t, bad_n == 0, "%ld hits whose normal is not the half tube's", bad_n);
    scene_free(&s);
}

/* "float alpha" 0.5 on the straight curve of curve_cylinder_hits: half of the W / 1
   rays that meet it count (bvh.c ALPHA), and a shadow ray agrees with each. */
static void test_curve_alpha(T *t)
{
    Scene s;
    Rng r;
    const long n = test_scaled(20000, 4000);
    long i, hits = 0, disagree = 0;
    const double p = 0.2 * 0.5;
    if (!load_curve(t, &s, "Shape \"curve\" \"string type\" \"cylinder\" \"float width\" [ 0.2 ] \"float alpha\" 0.5 "
                           "\"point3 P\" [ -1 0 0  -0.333333333 0 0  0.333333333 0 0  1 0 0 ]\n"))
        return;
    rng_seed(&r, 46, 0);
    for (i = 0; i < n; i++) {
        float q[2];
        Ray ray;
        HitRecord h;
        int hit;
        rng_fill(&r, q, 2);
        ray.o = v3(-0.8f + 1.6f * q[0], q[1] - 0.5f, 3.0f);
        ray.d = v3(0, 0, -1);
        ray.tmax = 10.0f;
        hit = bvh_intersect(&s.bvh, &s, &ray, &h);
        hits += hit;
        disagree += hit != bvh_occluded(&s.bvh, &s, &ray);
    }
    CHECK(t, fabs((double)hits - n * p) <= 5.0 * sqrt(n * p * (1 - p)),
          "%ld of %ld rays hit, want %.0f (width / extent x alpha)", hits, n, n * p);
    CHECK(t, disagree == 0, "%ld shadow rays disagree with their closest hit", disagree);
    scene_free(&s);
}

/* A flat curve faces the ray: random rays through random points of a curved flat
   band; at each hit the normal is the ray's direction made perpendicular to dp/du
   (unit, up to sign), and dp/dv lies across the band, of length the width. */
static void test_curve_flat_faces_ray(T *t)
{
    Scene s;
    Rng r;
    const int n = test_scaled(2000, 400);
    int i, hits = 0, bad = 0;
    if (!load_curve(t, &s, "Shape \"curve\" \"float width\" [ 0.3 ] "
                           "\"point3 P\" [ -1 0 0  -0.3 1 0.5  0.3 -1 0.2  1 0 0 ]\n"))
        return;
    rng_seed(&r, 44, 0);
    for (i = 0; i < n; i++) {
        Vec3 u3 = rng_vec3(&r), target, dpdu, dpdv, want;
        float uu = rng_float(&r);
        Ray ray;
        HitRecord h;
        SurfacePoint sp;
        ShadingDiff d;
        Vec3 cp[4];
        cp[0] = v3(-1, 0, 0); cp[1] = v3(-0.3f, 1, 0.5f); cp[2] = v3(0.3f, -1, 0.2f); cp[3] = v3(1, 0, 0);
        target = curve_bezier_eval(cp, uu, NULL);
        ray.o = v3_add(target, v3_mul(v3_norm(v3_sub(u3, v3(0.5f, 0.5f, 0.2f))), 4.0f));
        ray.d = v3_sub(target, ray.o);
        ray.tmax = 2.0f;
        if (!bvh_intersect(&s.bvh, &s, &ray, &h)) continue;
        hits++;
        scene_surface_point(&s, &ray, &h, &sp);
        shading_differentials(&s, &ray, &h, &sp, &d);
        dpdu = d.dpdu;
        dpdv = d.dpdv;
        want = v3_norm(v3_sub(ray.d, v3_mul(dpdu, v3_dot(ray.d, dpdu) / v3_dot(dpdu, dpdu))));
        if (fabsf(fabsf(v3_dot(sp.ng, want)) - 1) > 1e-4f || fabsf(v3_dot(dpdv, dpdu)) > 1e-4f * v3_len(dpdu) ||
            fabsf(v3_dot(dpdv, ray.d)) > 1e-4f * v3_len(ray.d) || fabsf(v3_len(dpdv) - 0.3f) > 1e-4f)
            bad++;
    }
    CHECK(t, hits > n / 2, "only %d of %d rays aimed at the centre line hit", hits, n);
    CHECK(t, bad == 0, "%d hits whose normal does not face the ray or dp/dv is not across", bad);
    scene_free(&s);
}

/* ORDER INDEPENDENCE: the BVH's closest hit equals the brute-force minimum over
   every piece (smallest t, ties to the smallest id) bit for bit, and a shadow ray
   finds a hit exactly when the closest-hit ray does. */
static void test_curve_bvh_exact(T *t)
{
    Scene s;
    Rng r;
    const int n = test_scaled(3000, 600);
    int i, k, bad = 0, disagree = 0, hits = 0;
    if (!load_curve(t, &s, "Shape \"curve\" \"string type\" \"cylinder\" \"float width0\" [ 0.3 ] "
                           "\"float width1\" [ 0.05 ] \"string basis\" \"bspline\" "
                           "\"point3 P\" [ -1 -1 0  -0.5 1 0.5  0 -1 -0.5  0.5 1 0  1 -1 0.3  1.2 0 0 ]\n"
                           "Shape \"curve\" \"string type\" \"ribbon\" \"float width\" [ 0.4 ] \"integer degree\" [ 2 ] "
                           "\"point3 P\" [ -1 0 0.2  0 1 0  1 0 0.2 ] \"normal N\" [ 0 0 1  1 0 1 ]\n"
                           "Shape \"curve\" \"float width\" [ 0.2 ] \"point3 P\" [ 0 -1 0  0 0 1  0 0 -1  0 1 0 ]\n"))
        return;
    rng_seed(&r, 45, 0);
    for (i = 0; i < n; i++) {
        Vec3 a = rng_vec3(&r), b = rng_vec3(&r);
        Ray ray;
        HitRecord h;
        int hit, occ, best = -1;
        float tb = 0;
        const int base = s.n_tris + s.n_spheres + s.n_quadrics + s.n_patches;
        ray.o = v3_add(v3_mul(v3_sub(a, v3(0.5f, 0.5f, 0.5f)), 6.0f), v3(0, 0, 3));
        ray.d = v3_sub(v3_mul(v3_sub(b, v3(0.5f, 0.5f, 0.5f)), 2.0f), ray.o);
        ray.tmax = 1.5f;
        hit = bvh_intersect(&s.bvh, &s, &ray, &h);
        occ = bvh_occluded(&s.bvh, &s, &ray);
        for (k = 0; k < s.n_curve_pieces; k++) {
            HitRecord c;
            if (curve_intersect(&s, &s.curve_pieces[k], &ray, ray.tmax, 0, &c) && c.t < ray.tmax &&
                (best < 0 || c.t < tb)) { best = k; tb = c.t; }
        }
        hits += hit;
        disagree += hit != occ;
        if (hit != (best >= 0) || (hit && (h.t != tb || h.prim != base + best))) bad++;
    }
    CHECK(t, hits > n / 10, "only %d of %d rays hit the curves", hits, n);
    CHECK(t, bad == 0, "%d rays where the BVH and brute force differ", bad);
    CHECK(t, disagree == 0, "%d rays where the shadow query and the closest hit differ", disagree);
    scene_free(&s);
}

#define CURVE_FLOOR \
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -3 -3 -1  3 -3 -1  3 3 -1  -3 3 -1 ]\n"
static const char *const CURVE_SCENE = CURVE_FLOOR
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.3 0.1 ]\n"
    "Shape \"curve\" \"string type\" \"flat\" \"integer degree\" [ 2 ] \"point3 P\" [ -1.6 0.3 0  -1.2 2 0.5  "
    "-0.2 1.2 0  0.6 0.4 -0.5  -0.1 0.2 0 ] \"float width\" [ 0.25 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.1 0.6 0.2 ]\n"
    "Shape \"curve\" \"string type\" \"cylinder\" \"point3 P\" [ 0.2 0.3 0  0.6 1.9 0.8  1.2 -0.2 -0.5  1.7 1.5 0 ] "
    "\"float width0\" [ 0.35 ] \"float width1\" [ 0.15 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.3 0.8 ]\n"
    "Shape \"curve\" \"string type\" \"ribbon\" \"string basis\" \"bspline\" \"point3 P\" [ -1.8 -0.4 0  -1.2 -1.6 0.5  "
    "-0.6 -0.3 0  -0.1 -1.5 -0.3  0.1 -0.5 0 ] \"normal N\" [ 0 0 1  0 1 1  1 0 1 ] \"float width\" [ 0.3 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.2 ]\n"
    "Shape \"curve\" \"string type\" \"cylinder\" \"string basis\" \"bspline\" \"integer degree\" [ 2 ] \"point3 P\" "
    "[ 0.3 -0.3 0.3  0.8 -1.8 0  1.3 -0.4 0.2  1.8 -1.6 0 ] \"float width0\" [ 0.4 ] \"float width1\" [ 0.1 ] "
    "\"integer splitdepth\" [ 1 ]\n";

/* The same bits for 1, 2 and 3 threads (the test scene, 4 spp). */
static void test_curve_threads(T *t)
{
    Image im[3];
    int k;
    for (k = 0; k < 3; k++) {
        Scene s;
        RenderOptions o;
        RenderStats st;
        Error err;
        if (!load_curve(t, &s, CURVE_SCENE)) return;
        render_options_default(&o);
        o.spp = 4;
        o.seed = 5;
        o.threads = k + 1;
        if (!render(&s, &o, &im[k], &st, &err)) {
            test_failf(t, __FILE__, __LINE__, "render: %s", err.msg);
            scene_free(&s);
            while (k-- > 0) img_free(&im[k]);
            return;
        }
        scene_free(&s);
    }
    CHECK(t, !memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * im[0].w * im[0].h) &&
          !memcmp(im[0].rgb, im[2].rgb, sizeof(float) * 3 * im[0].w * im[0].h),
          "images of 1, 2, 3 threads differ");
    for (k = 0; k < 3; k++) img_free(&im[k]);
}

static void expect_error(T *t, const char *body, const char *want)
{
    test_refused(t, CURVE_HEAD, body, "curve.pbrt", want);
}

/* Refusals at their file:line (the head is 8 lines). */
static void test_curve_errors(T *t)
{
    expect_error(t, "Shape \"curve\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0  4 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": 5 control points: a degree 3 Bezier curve needs 4 + n * 3 (n >= 0)");
    expect_error(t, "Shape \"curve\" \"integer degree\" 2 \"point3 P\" [ 0 0 0  1 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": 2 control points: a degree 2 Bezier curve needs 3 + n * 2 (n >= 0)");
    expect_error(t, "Shape \"curve\" \"string basis\" \"bspline\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": 3 control points: a degree 3 b-spline needs at least 4");
    expect_error(t, "Shape \"curve\" \"string basis\" \"hermite\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": unknown \"string basis\" \"hermite\" (bezier or bspline)");
    expect_error(t, "Shape \"curve\" \"string type\" \"tube\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": unknown \"string type\" \"tube\" (flat, cylinder or ribbon)");
    expect_error(t, "Shape \"curve\" \"integer degree\" 4 \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0  4 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": \"integer degree\" 4: only 2 and 3 (as in pbrt-v4)");
    expect_error(t, "Shape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": a ribbon needs \"normal N\" at its 2 segment ends (6 values), not 0");
    expect_error(t, "Shape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ] "
                 "\"normal N\" [ 0 0 1  0 0 -1 ]\n",
                 "curve.pbrt:9: Shape \"curve\": \"normal N\" 0 and 1 are opposite");
    expect_error(t, "Shape \"curve\" \"float width\" -1 \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": widths -1, -1 must be finite and >= 0");
    expect_error(t, "Shape \"curve\" \"integer splitdepth\" -1 \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]\n",
                 "curve.pbrt:9: Shape \"curve\": \"integer splitdepth\" -1 must lie in [0, 12]");
    expect_error(t, "Shape \"curve\" \"float width\" 1\n",
                 "curve.pbrt:9: Shape \"curve\": \"point3 P\" is required");
    expect_error(t, "AttributeBegin\nAreaLightSource \"diffuse\"\n"
                 "Shape \"curve\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]\nAttributeEnd\n",
                 "curve.pbrt:11: Shape \"curve\" under an AreaLightSource is valid pbrt-v4 but not in the specnee subset");
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 256` for S = 1..8, the
   independent sampler) rendered CURVE_HEAD + CURVE_SCENE, (a) as it is: a grey floor
   behind four curves under a distant light, a flat degree-2 Bezier with two
   segments, a tapered cylinder, a ribbon b-spline with turning normals, a degree-2
   b-spline cylinder of splitdepth 1; (b) without the floor (the curves alone, on
   black).  Luminance of the image and of its 2 x 2 quadrants (top left first), mean
   over the seeds and its standard error; specnee within 5 standard errors + 1 %
   (the RGB fits).  A distant light: the point lights are sampled from is tested by
   test_curve_point_light_against_pbrt. */
static const double PBRT_CURVE_Y[2][5][2] = {
    { { 0.654264, 9.5e-05 },
      { 0.642830, 0.0002 }, { 0.583835, 0.00019 }, { 0.685565, 0.00012 }, { 0.704826, 0.00011 } },
    { { 0.056533, 2.1e-05 },
      { 0.057737, 6.5e-05 }, { 0.077064, 6.9e-05 }, { 0.055711, 6.1e-05 }, { 0.035621, 5.9e-05 } },
};

static void test_curve_against_pbrt(T *t)
{
    int j;
    for (j = 0; j < 2; j++) {
        Scene s;
        char what[8];
        if (!load_curve(t, &s, j == 0 ? CURVE_SCENE : CURVE_SCENE + strlen(CURVE_FLOOR))) return;
        snprintf(what, sizeof what, "scene %c", 'a' + j);
        test_scene_against_pbrt_y(t, &s, test_scaled(32, 8), 3, PBRT_CURVE_Y[j], 1e-2, what);
        scene_free(&s);
        if (t->failed) return;
    }
}

/* pbrt-v4 (mmp/pbrt-v4 5f7a6068, `pbrt --seed S --spp 1024`, S = 1..4, the
   independent sampler, 32 x 32) rendered CURVE_POINT_LIT: a flat and a cylinder
   curve (widths 0.25 and 0.2) under a point light about 18 widths away, on black.
   pbrt-v4 samples lights from the hit moved past its error bound (a width in each
   axis) to the viewer's side (SampleLd's LightSampleContext nudge; path.c
   light_origin does the same): from the hit itself specnee was 6.8 % darker
   (image 0.017985 at 4096 spp), with the nudge 0.0 % (quadrants within 0.8 %).
   Luminance of the image and its quadrants (top left first), mean over the seeds
   and its standard error; accepted within 5 standard errors + 1.5 %. */
static const char *const CURVE_POINT_LIT =
    "LookAt 0 -0.5 5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 3 ]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"float scale\" [ 20 ] \"point3 from\" [ 1 2 4 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"curve\" \"point3 P\" [ -1.5 -0.6 0  -0.5 0.6 0  0.5 -0.6 0  1.5 0.6 0 ] \"float width\" [ 0.25 ] "
    "\"string type\" \"flat\"\n"
    "Shape \"curve\" \"point3 P\" [ -1.5 -1 0  -0.5 -0.8 0.3  0.5 -1.2 0  1.5 -1 0 ] \"float width\" [ 0.2 ] "
    "\"string type\" \"cylinder\"\n";
static const double PBRT_CURVE_POINT_Y[5][2] = {
    { 0.019298, 2.1e-05 }, { 0.024404, 3.6e-05 }, { 0.006045, 8.1e-06 }, { 0.019139, 6.1e-05 }, { 0.027602, 1.2e-05 },
};

static void test_curve_point_light_against_pbrt(T *t)
{
    test_against_pbrt_y(t, CURVE_POINT_LIT, 3, PBRT_CURVE_POINT_Y, 1.5e-2, "curve point light");
}

const TestCase tests_curve[] = {
    { "curve_bases", test_curve_bases },
    { "curve_cylinder_hits", test_curve_cylinder_hits },
    { "curve_alpha", test_curve_alpha },
    { "curve_flat_faces_ray", test_curve_flat_faces_ray },
    { "curve_bvh_exact", test_curve_bvh_exact },
    { "curve_threads", test_curve_threads },
    { "curve_errors", test_curve_errors },
    { "curve_against_pbrt", test_curve_against_pbrt },
    { "curve_point_light_against_pbrt", test_curve_point_light_against_pbrt },
    { NULL, NULL }
};
