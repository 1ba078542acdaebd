/* tests/test_util.c - transforms, frames, the RNG and radical inverses; the
   chi-square helpers of tests/fixtures.c. */
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

/* Deterministic streams; uniformity by a chi-square test on 64 cells (1e5 draws). */
static void test_rng_streams(T *t)
{
    Rng a, b;
    int i;
    double cells[64], ex[64];
    rng_seed(&a, 7, 3);
    rng_seed(&b, 7, 3);
    for (i = 0; i < 100; i++) CHECK(t, rng_u32(&a) == rng_u32(&b), "same key, different numbers");
    rng_seed(&b, 7, 4);
    CHECK(t, rng_u32(&a) != rng_u32(&b), "neighbouring indices give the same number");
    memset(cells, 0, sizeof cells);
    for (i = 0; i < 100000; i++) {
        float u = rng_float(&a);
        CHECK(t, u >= 0.0f && u < 1.0f, "rng_float out of [0,1): %g", u);
        cells[(int)(u * 64)] += 1.0;
    }
    for (i = 0; i < 64; i++) ex[i] = 100000.0 / 64;
    CHECK_CHI2(t, cells, ex, 64, 1, NULL, "rng_float");
}

static void test_radical_inverse(T *t)
{
    CHECK(t, near(radical_inverse(2, 1), 0.5, 1e-15), "base 2, i=1");
    CHECK(t, near(radical_inverse(2, 6), 0.375, 1e-15), "base 2, i=6 (110 -> .011)");
    CHECK(t, near(radical_inverse(3, 5), 7.0 / 9.0, 1e-15), "base 3, i=5 (12 -> .21)");
}

/* cdf_guide / cdf_cell on CDFs with zero cells at both ends, plateaus, a cell
   holding most of the mass and one of tiny mass: the guide is what it says (the
   last cell at or below each step g / m), and the guided search finds the cell
   the full search finds for u at every knot, next to it, at every step of the
   guide, next to it, and at random; with m = cdf_guide_size(n) (the power of two
   >= 4 n, where u m is exact) and with coarser powers of two (m < n: a step then
   spans many cells). */
static int guide_agrees(const float *cdf, int n, const int *guide, int m, double u)
{
    int k = cdf_cell(cdf, n, guide, m, u);
    return k == cdf_cell(cdf, n, NULL, 0, u) && cdf[k] <= u && u < cdf[k + 1];
}

static void test_cdf_guide(T *t)
{
    enum { N = 40, M_MAX = 256 };
    float cdf[N + 1];
    int guide[M_MAX + 1], k, g, bad = 0, tried = 0, m;
    Rng rng;
    double acc = 0.0, sum = 0.0, f[N];
    for (k = 0; k < N; k++) {
        f[k] = (k < 3 || k >= N - 2 || (k >= 10 && k < 20)) ? 0.0 : (k == 25 ? 500.0 : (k == 30 ? 1e-6 : 1.0));
        sum += f[k];
    }
    cdf[0] = 0.0f;
    for (k = 0; k < N; k++) { acc += f[k]; cdf[k + 1] = (float)(acc / sum); }
    cdf[N] = 1.0f;
    CHECK(t, cdf_guide_size(N) == 256 && cdf_guide_size(1) == 4 && cdf_guide_size(64) == 256,
          "cdf_guide_size: %d %d %d", cdf_guide_size(N), cdf_guide_size(1), cdf_guide_size(64));
    for (m = cdf_guide_size(N); m >= 8; m /= 4) {
        cdf_guide(cdf, N, guide, m);
        for (g = 0; g <= m; g++) {
            int c = guide[g];
            double edge = (double)g / m;
            if (!(c >= 0 && c < N && cdf[c] <= edge && (c == N - 1 || cdf[c + 1] > edge))) bad++;
        }
        CHECK(t, bad == 0, "m %d: %d guide entries are not the last cell at or below their step", m, bad);
        for (k = 0; k <= N; k++) {
            double us[6];
            int i;
            us[0] = cdf[k];
            us[1] = nextafter((double)cdf[k], 0.0);
            us[2] = nextafter((double)cdf[k], 1.0);
            us[3] = (double)k / N;
            us[4] = nextafter(us[3], 0.0);
            us[5] = nextafter(us[3], 1.0);
            for (i = 0; i < 6; i++)
                if (us[i] >= 0.0 && us[i] < 1.0) { tried++; if (!guide_agrees(cdf, N, guide, m, us[i])) bad++; }
        }
        for (g = 0; g < m; g++) {
            double us[3];
            int i;
            us[0] = (double)g / m;
            us[1] = nextafter(us[0], 0.0);
            us[2] = nextafter(us[0], 1.0);
            for (i = 0; i < 3; i++)
                if (us[i] >= 0.0 && us[i] < 1.0) { tried++; if (!guide_agrees(cdf, N, guide, m, us[i])) bad++; }
        }
        rng_seed(&rng, 3, (uint64_t)m);
        for (k = 0; k < 20000; k++, tried++)
            if (!guide_agrees(cdf, N, guide, m, rng_float(&rng))) bad++;
    }
    CHECK(t, bad == 0, "the guided search differs from the full one at %d of %d u", bad, tried);
}

static int rel_near(double a, double b, double tol) { return fabs(a - b) <= tol * fabs(b); }

/* The chi-square helpers of tests/fixtures.c.  The tail against closed forms:
   k = 2: e^(-x/2); k = 4: e^(-x/2) (1 + x/2); k = 1: erfc(sqrt(x/2)); k = 3:
   erfc(sqrt(x/2)) + sqrt(2x/pi) e^(-x/2); and Q(63 dof, 112), Q(400 dof, 300)
   and Q(400 dof, 500) (both branches of chi2_tail; the regularised gamma function of
   mpmath, 15 digits).  The verdict: exact counts
   pass; a deviation in the cells expecting < 5 (merged into one) fails; with one
   dof, X^2 = 16.56 (p = 4.7e-5) fails one check (level 1e-4) and passes one of
   four (level 2.5e-5). */
static void test_chi2_helpers(T *t)
{
    static const double xs[] = { 0.1, 1.0, 3.0, 10.0, 40.0 };
    double obs[12], ex[12];
    Chi2 c;
    T scratch;
    int i;
    for (i = 0; i < 5; i++) {
        double x = xs[i], e = exp(-x / 2), q3 = erfc(sqrt(x / 2)) + sqrt(2 * x / SPECNEE_PI) * e;
        CHECK(t, rel_near(chi2_tail(2, x), e, 1e-9), "Q(2 dof, %g) = %.12g, want %.12g", x, chi2_tail(2, x), e);
        CHECK(t, rel_near(chi2_tail(4, x), e * (1 + x / 2), 1e-9), "Q(4 dof, %g) = %.12g, want %.12g", x,
              chi2_tail(4, x), e * (1 + x / 2));
        CHECK(t, rel_near(chi2_tail(1, x), erfc(sqrt(x / 2)), 1e-9), "Q(1 dof, %g) = %.12g, want %.12g", x,
              chi2_tail(1, x), erfc(sqrt(x / 2)));
        CHECK(t, rel_near(chi2_tail(3, x), q3, 1e-9), "Q(3 dof, %g) = %.12g, want %.12g", x, chi2_tail(3, x), q3);
    }
    CHECK(t, rel_near(chi2_tail(63, 112.0), 1.43202822868971e-4, 1e-9), "Q(63 dof, 112) = %.12g",
          chi2_tail(63, 112.0));
    CHECK(t, rel_near(chi2_tail(400, 300.0), 0.999942903114258, 1e-9), "Q(400 dof, 300) = %.12g",
          chi2_tail(400, 300.0));
    CHECK(t, rel_near(chi2_tail(400, 500.0), 4.82212759593434e-4, 1e-9), "Q(400 dof, 500) = %.12g",
          chi2_tail(400, 500.0));
    for (i = 0; i < 12; i++) obs[i] = ex[i] = i < 10 ? 1000.0 : 3.0;
    memset(&scratch, 0, sizeof scratch);
    CHECK(t, test_chi2_at(&scratch, __FILE__, __LINE__, obs, ex, 12, 1, &c, "exact") && c.stat == 0.0 &&
          c.dof == 10 && c.p == 1.0 && c.total == 10006.0,
          "exact counts: X^2 %g, %d dof, p %g, total %g (%s)", c.stat, c.dof, c.p, c.total, scratch.msg);
    obs[10] = obs[11] = 30.0;
    CHECK(t, !test_chi2_at(&scratch, __FILE__, __LINE__, obs, ex, 12, 1, &c, "merged") &&
          fabs(c.stat - 54.0 * 54.0 / 6.0) < 1e-9, "60 samples where 6 are expected pass: X^2 %g", c.stat);
    obs[0] = 1091.0;
    obs[1] = 909.0;
    memset(&scratch, 0, sizeof scratch);
    CHECK(t, !test_chi2_at(&scratch, __FILE__, __LINE__, obs, ex, 2, 1, &c, "one check") && c.dof == 1 &&
          strstr(scratch.msg, "one check: chi-square 16.6 with 1 dof") != NULL,
          "X^2 %g with %d dof (p %g) passes one check (%s)", c.stat, c.dof, c.p, scratch.msg);
    CHECK(t, test_chi2_at(&scratch, __FILE__, __LINE__, obs, ex, 2, 4, &c, "one of four"),
          "X^2 %g with %d dof (p %g) fails one of four checks", c.stat, c.dof, c.p);
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
    { "util_cdf_guide", test_cdf_guide },
    { "util_error_format", test_error_format },
    { "util_chi2_helpers", test_chi2_helpers },
    { NULL, NULL }
};
