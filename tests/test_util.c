/* tests/test_util.c - transforms, frames, the RNG and radical inverses. */
#include "test.h"
#include <string.h>

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }

static void test_xform_inverse(T *t)
{
    Xform a = xf_translate(1, 2, 3), b = xf_rotate(33, 1, 2, -1), c = xf_scale(2, -1, 0.5);
    Xform ab = xf_mul(&a, &b), abc = xf_mul(&ab, &c);
    int i, j, k;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) {
            double s = 0;
            for (k = 0; k < 4; k++) s += abc.m[i][k] * abc.inv[k][j];
            CHECK(t, near(s, i == j, 1e-12), "M * M^-1 [%d][%d] = %g", i, j, s);
        }
    CHECK(t, xf_swaps_handedness(&abc), "a mirror scale must swap handedness");
    CHECK(t, !xf_swaps_handedness(&ab), "rotation and translation keep handedness");
}

static void test_xform_rotate_translate(T *t)
{
    Xform r = xf_rotate(90, 0, 0, 1), tr = xf_translate(5, 0, 0), rt = xf_mul(&tr, &r);
    Vec3 p = xf_point(&rt, v3(1, 0, 0));      /* rotate first: (0,1,0), then +5 x */
    Vec3 n;
    Xform s = xf_scale(2, 1, 1);
    CHECK(t, near(p.x, 5, 1e-6) && near(p.y, 1, 1e-6) && near(p.z, 0, 1e-6),
          "Translate * Rotate applies the rotation first: got (%g %g %g)", p.x, p.y, p.z);
    /* normals stay perpendicular: plane x + y = 0 under a non-uniform scale */
    n = xf_normal(&s, v3(1, 1, 0));
    p = xf_vector(&s, v3(1, -1, 0));
    CHECK(t, near(v3_dot(n, p), 0, 1e-6), "transformed normal not perpendicular (%g)", v3_dot(n, p));
}

static void test_lookat_left_handed(T *t)
{
    /* pbrt-v4: camera looks down +z, +x is right = cross(up, dir), +y up */
    Xform cw;
    Vec3 c;
    CHECK(t, xf_lookat(0, 0, -10, 0, 0, 0, 0, 1, 0, &cw), "lookat failed");
    c = xf_point(&cw, v3(1, 2, 0));
    CHECK(t, near(c.x, 1, 1e-6) && near(c.y, 2, 1e-6) && near(c.z, 10, 1e-6),
          "camera coordinates (%g %g %g), expected (1 2 10)", c.x, c.y, c.z);
    CHECK(t, !xf_lookat(0, 0, 0, 0, 1, 0, 0, 1, 0, &cw), "up parallel to dir must fail");
}

static void test_frame_orthonormal(T *t)
{
    Rng r;
    int i;
    rng_seed(&r, 1, 2);
    for (i = 0; i < 1000; i++) {
        Vec3 n = v3_norm(v3_sub(v3_mul(rng_vec3(&r), 2.0f), v3(1.0f, 1.0f, 1.0f)));
        Frame f = frame_from_normal(n);
        Vec3 w = v3(0.3f, -0.2f, 0.9f), back = frame_to_local(&f, frame_to_world(&f, w));
        CHECK(t, near(v3_dot(f.s, f.t), 0, 1e-5) && near(v3_dot(f.s, n), 0, 1e-5) &&
                 near(v3_len(f.s), 1, 1e-5) && near(v3_len(f.t), 1, 1e-5),
              "frame not orthonormal for n=(%g %g %g)", n.x, n.y, n.z);
        CHECK(t, near(back.x, w.x, 1e-5) && near(back.z, w.z, 1e-5), "frame round trip");
    }
}

/* Deterministic streams; uniformity by a chi-square test on 64 cells
   (1e5 draws; the 99.99% point of chi-square with 63 dof is about 112). */
static void test_rng_streams(T *t)
{
    Rng a, b;
    int i, cells[64];
    double chi2 = 0, expect = 100000.0 / 64;
    rng_seed(&a, 7, 3);
    rng_seed(&b, 7, 3);
    for (i = 0; i < 100; i++) CHECK(t, rng_u32(&a) == rng_u32(&b), "same key, different numbers");
    rng_seed(&b, 7, 4);
    CHECK(t, rng_u32(&a) != rng_u32(&b), "neighbouring indices give the same number");
    memset(cells, 0, sizeof cells);
    for (i = 0; i < 100000; i++) {
        float u = rng_float(&a);
        CHECK(t, u >= 0.0f && u < 1.0f, "rng_float out of [0,1): %g", u);
        cells[(int)(u * 64)]++;
    }
    for (i = 0; i < 64; i++) chi2 += (cells[i] - expect) * (cells[i] - expect) / expect;
    CHECK(t, chi2 < 112.0, "chi-square %g over 63 dof (bound 112)", chi2);
}

static void test_radical_inverse(T *t)
{
    CHECK(t, near(radical_inverse(2, 1), 0.5, 1e-15), "base 2, i=1");
    CHECK(t, near(radical_inverse(2, 6), 0.375, 1e-15), "base 2, i=6 (110 -> .011)");
    CHECK(t, near(radical_inverse(3, 5), 7.0 / 9.0, 1e-15), "base 3, i=5 (12 -> .21)");
}

static void test_error_format(T *t)
{
    Error e;
    error_set(&e, "a.pbrt", 12, "unknown directive '%s'", "Foo");
    CHECK(t, strcmp(e.msg, "a.pbrt:12: unknown directive 'Foo'") == 0, "got '%s'", e.msg);
}

const TestCase tests_util[] = {
    { "util_xform_inverse", test_xform_inverse },
    { "util_xform_rotate_translate", test_xform_rotate_translate },
    { "util_lookat_left_handed", test_lookat_left_handed },
    { "util_frame_orthonormal", test_frame_orthonormal },
    { "util_rng_streams", test_rng_streams },
    { "util_radical_inverse", test_radical_inverse },
    { "util_error_format", test_error_format },
    { NULL, NULL }
};
