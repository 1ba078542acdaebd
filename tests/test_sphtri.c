/* tests/test_sphtri.c - sampling a spherical triangle (sphtri.c) and triangle
   lamps sampled by solid angle (lights.c), against closed forms computed here.

     sphtri_uniform_chi2     tri_sample_sa without a normal: counts in the 2 K^2
                             sub-triangles of a barycentric grid against each one's
                             solid angle / the whole (Van Oosterom-Strackee here,
                             not Girard's excess of the code), for a near, a far
                             and a sliver triangle (chi-square)
     sphtri_warp_chi2        the same with the cosine warp: expected counts from
                             tri_pdf_sa integrated over each cell (the density the
                             MIS weight reads agrees with the sampler's)
     sphtri_bilinear_chi2    bilinear_sample against bilinear_pdf integrated in
                             closed form over an 8 x 8 grid
     sphtri_pdf_at_sample    the sample's density equals tri_pdf_sa at its
                             direction (random triangles, points and normals), and
                             solid angle is 0 outside [SPH_TRI_MIN, SPH_TRI_MAX]
     sphtri_warp_corners     the warped density near each vertex direction:
                             4 cos / (2 cos_B + cos_A + cos_C) / Omega
     sphtri_invert           sph_tri_invert(sph_tri_sample(u)) = u
     sphtri_irradiance       a triangle lamp and a quad lamp (two triangles) of
                             L = 1: the mean of cos / pdf_sa of emitter_sample, with
                             and without the warp, against Lambert's polygon formula
                             E = 1/2 sum_k theta_k (n . g_k)
     sphtri_light_pdf        light_sample with a shading normal against light_pdf_sa
                             at the point a ray along its direction finds, and
                             against the density of the mode (solidangle, area)
                             computed here
     sphtri_render_agrees    a quad lamp close over a diffuse sphere, and one
                             standing on a floor: tiles of --light-shape-sampling
                             area and solidangle agree in mean; over the sphere
                             solid angle has less than 0.6 of the variance
     sphtri_auto_rule        tri_sa_pays (--light-shape-sampling auto): plain cases
                             (far, close, on the horizon, behind, in a medium) and
                             the definition recomputed here on random triangles
     sphtri_auto_pdf         sphtri_light_pdf with the rule (auto), from points on
                             both of its sides
     sphtri_auto_chi2        the combined sampler (one triangle of a quad by solid
                             angle, the other by area) against its density
                             (chi-square over directions)
     sphtri_auto_render      sphtri_render_agrees for auto against area */
#include "test.h"
#include <string.h>

/* the solid angle of the triangle a b c seen from the origin (Van Oosterom and
   Strackee 1983): tan(Omega / 2) = |a . (b x c)| / (|a||b||c| + (a.b)|c| + ...) */
static double vos(const double a[3], const double b[3], const double c[3])
{
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double bxc[3], num, den;
    bxc[0] = b[1] * c[2] - b[2] * c[1];
    bxc[1] = b[2] * c[0] - b[0] * c[2];
    bxc[2] = b[0] * c[1] - b[1] * c[0];
    num = fabs(a[0] * bxc[0] + a[1] * bxc[1] + a[2] * bxc[2]);
    den = la * lb * lc + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * lc +
          (a[0] * c[0] + a[1] * c[1] + a[2] * c[2]) * lb + (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) * la;
    return 2.0 * atan2(num, den);
}

/* Girard: the solid angle of v seen from ref as its angle sum minus pi, each
   angle the one between the normals of the planes through the origin and two
   vertices (acos of their dot product) */
static double girard(const Vec3 v[3], Vec3 ref)
{
    double d[3][3], n[3][3], sum = 0.0;
    int i, k;
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) d[i][k] = (double)v3_get(v[i], k) - v3_get(ref, k);
    for (i = 0; i < 3; i++) {          /* n[i]: the normal of the plane (origin, d[i], d[i+1]) */
        const double *a = d[i], *b = d[(i + 1) % 3];
        double l;
        n[i][0] = a[1] * b[2] - a[2] * b[1]; n[i][1] = a[2] * b[0] - a[0] * b[2]; n[i][2] = a[0] * b[1] - a[1] * b[0];
        l = sqrt(n[i][0] * n[i][0] + n[i][1] * n[i][1] + n[i][2] * n[i][2]);
        for (k = 0; k < 3; k++) n[i][k] /= l;
    }
    for (i = 0; i < 3; i++) {          /* the angle at d[i+1]: between -n[i] and n[i+1] */
        const double *p = n[i], *q = n[(i + 1) % 3];
        sum += acos(-(p[0] * q[0] + p[1] * q[1] + p[2] * q[2]));
    }
    return sum - SPECNEE_PI;
}

/* the point of barycentrics (b1, b2) of v, relative to ref */
static void bary_point(const Vec3 v[3], Vec3 ref, double b1, double b2, double out[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        double p0 = v3_get(v[0], k), p1 = v3_get(v[1], k), p2 = v3_get(v[2], k);
        out[k] = p0 + b1 * (p1 - p0) + b2 * (p2 - p0) - v3_get(ref, k);
    }
}

/* The grid: K^2 lower and upper sub-triangles of the barycentric (b1, b2) grid;
   cell c's corners in (b1, b2). */
enum { K = 6, NCELL = 2 * K * K };
static int cell_corners(int c, double b[3][2])
{
    int i = c / (2 * K), j = (c / 2) % K, up = c % 2;
    if (i + j > K - 1 - up) return 0;                      /* outside the triangle */
    if (!up) {
        b[0][0] = i; b[0][1] = j; b[1][0] = i + 1; b[1][1] = j; b[2][0] = i; b[2][1] = j + 1;
    } else {
        b[0][0] = i + 1; b[0][1] = j; b[1][0] = i + 1; b[1][1] = j + 1; b[2][0] = i; b[2][1] = j + 1;
    }
    for (i = 0; i < 3; i++) { b[i][0] /= K; b[i][1] /= K; }
    return 1;
}

/* the cell of the direction w from ref (Moller-Trumbore here), -1: misses */
static int dir_cell(const Vec3 v[3], Vec3 ref, Vec3 w)
{
    double e1[3], e2[3], s[3], pv[3], qv[3], d[3], det, b1, b2, x, y;
    int k, i, j;
    for (k = 0; k < 3; k++) {
        e1[k] = (double)v3_get(v[1], k) - v3_get(v[0], k);
        e2[k] = (double)v3_get(v[2], k) - v3_get(v[0], k);
        s[k] = (double)v3_get(ref, k) - v3_get(v[0], k);
        d[k] = v3_get(w, k);
    }
    pv[0] = d[1] * e2[2] - d[2] * e2[1]; pv[1] = d[2] * e2[0] - d[0] * e2[2]; pv[2] = d[0] * e2[1] - d[1] * e2[0];
    qv[0] = s[1] * e1[2] - s[2] * e1[1]; qv[1] = s[2] * e1[0] - s[0] * e1[2]; qv[2] = s[0] * e1[1] - s[1] * e1[0];
    det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    b1 = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
    b2 = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    if (b1 < -1e-6 || b2 < -1e-6 || b1 + b2 > 1.0 + 1e-6) return -1;
    x = b1 * K; y = b2 * K;
    i = (int)x; j = (int)y;
    if (i >= K) i = K - 1;
    if (j >= K) j = K - 1;
    if (i < 0) i = 0;
    if (j < 0) j = 0;
    if (i + j > K - 1) { if (i > 0) i--; else j--; }
    return (i * K + j) * 2 + (x - i + y - j > 1.0 && i + j <= K - 2);
}

/* A density per steradian of the direction towards the point p (relative to the
   receiver); 0: refused. */
typedef int (*DirDensity)(void *ctx, const double p[3], double *pdf);

typedef struct { const Vec3 *v; Vec3 ref, n; } TriPdf;

static int tri_pdf_density(void *ctx, const double p[3], double *pdf)
{
    const TriPdf *a = (const TriPdf *)ctx;
    return tri_pdf_sa(a->ref, a->n, a->v, v3_norm(v3((float)p[0], (float)p[1], (float)p[2])), pdf);
}

/* The integral over cell c of the density: by solid angle (n_sub 0: the cell's
   share of omega), or dens at the centroids of its n_sub^2 sub-triangles times
   their solid angles (-1: dens refused a direction). */
static double cell_prob_of(const Vec3 v[3], Vec3 ref, int c, int n_sub, double omega, DirDensity dens, void *ctx)
{
    double b[3][2], acc = 0.0;
    int i, j, up;
    if (!cell_corners(c, b)) return 0.0;
    if (n_sub == 0) {
        double p[3][3];
        for (i = 0; i < 3; i++) bary_point(v, ref, b[i][0], b[i][1], p[i]);
        return vos(p[0], p[1], p[2]) / omega;
    }
    for (i = 0; i < n_sub; i++)
        for (j = 0; j + i < n_sub; j++)
            for (up = 0; up < 2; up++) {
                double q[3][2], p[3][3], cen[3], pdf, om;
                int k;
                if (up && i + j > n_sub - 2) continue;
                q[0][0] = i + up; q[0][1] = j; q[1][0] = i + up; q[1][1] = j + 1;
                q[2][0] = i; q[2][1] = j + 1;
                if (!up) { q[1][0] = i + 1; q[1][1] = j; }
                for (k = 0; k < 3; k++) {   /* sub-cell corner -> the cell's (b1, b2) */
                    double s = q[k][0] / n_sub, r = q[k][1] / n_sub;
                    bary_point(v, ref, b[0][0] + s * (b[1][0] - b[0][0]) + r * (b[2][0] - b[0][0]),
                               b[0][1] + s * (b[1][1] - b[0][1]) + r * (b[2][1] - b[0][1]), p[k]);
                }
                for (k = 0; k < 3; k++) cen[k] = (p[0][k] + p[1][k] + p[2][k]) / 3.0;
                om = vos(p[0], p[1], p[2]);
                if (!dens(ctx, cen, &pdf)) return -1.0;
                acc += pdf * om;
            }
    return acc;
}

/* cell_prob_of with tri_pdf_sa (normal nrm) */
static double cell_prob(const Vec3 v[3], Vec3 ref, Vec3 nrm, int c, int n_sub, double omega)
{
    TriPdf a;
    a.v = v; a.ref = ref; a.n = nrm;
    return cell_prob_of(v, ref, c, n_sub, omega, tri_pdf_density, &a);
}

typedef struct { Vec3 v[3], ref, n; const char *what; } TriCase;

static const TriCase *tri_cases(int *n)
{
    static TriCase c[4];
    /* near and big (about 1.6 sr), tilted against the receiver */
    c[0].v[0] = v3(-1.0f, 1.0f, -0.8f); c[0].v[1] = v3(1.5f, 1.2f, -0.5f); c[0].v[2] = v3(0.2f, 1.0f, 1.6f);
    c[0].ref = v3(0.1f, 0.0f, 0.1f); c[0].n = v3_norm(v3(0.3f, 1.0f, -0.2f)); c[0].what = "near";
    /* small (about 0.03 sr) */
    c[1].v[0] = v3(-0.3f, 3.0f, 0.0f); c[1].v[1] = v3(0.3f, 3.1f, 0.1f); c[1].v[2] = v3(0.0f, 2.9f, 0.5f);
    c[1].ref = v3(0.0f, 0.0f, 0.0f); c[1].n = v3_norm(v3(1.0f, 0.2f, 0.0f)); c[1].what = "small";
    /* a sliver, nearly edge-on */
    c[2].v[0] = v3(-2.0f, 1.0f, 0.0f); c[2].v[1] = v3(2.0f, 1.0f, 0.05f); c[2].v[2] = v3(0.5f, 1.3f, 0.6f);
    c[2].ref = v3(0.0f, 0.0f, 0.0f); c[2].n = v3(0.0f, 0.0f, 1.0f); c[2].what = "sliver";
    /* close enough to cover 4 sr */
    c[3].v[0] = v3(-3.0f, 0.4f, -2.0f); c[3].v[1] = v3(3.0f, 0.4f, -2.0f); c[3].v[2] = v3(0.0f, 0.4f, 3.0f);
    c[3].ref = v3(0.0f, 0.0f, 0.0f); c[3].n = v3_norm(v3(0.0f, 1.0f, 0.5f)); c[3].what = "wide";
    *n = 4;
    return c;
}

static void chi2_cases(T *t, int warp)
{
    const int n = test_scaled(200000, 40000);
    int nc, ci, k;
    const TriCase *cs = tri_cases(&nc);
    for (ci = 0; ci < nc; ci++) {
        const TriCase *c = &cs[ci];
        Vec3 nrm = warp ? c->n : v3(0.0f, 0.0f, 0.0f);
        SphTri st;
        double obs[NCELL], ex[NCELL], omega;
        Rng r;
        CHECK(t, sph_tri_setup(c->ref, c->v[0], c->v[1], c->v[2], &st), "%s: degenerate", c->what);
        omega = st.area;
        CHECK(t, omega >= SPH_TRI_MIN && omega <= SPH_TRI_MAX, "%s: solid angle %g out of range", c->what, omega);
        {
            double g = girard(c->v, c->ref);
            CHECK(t, fabs(g - omega) < 1e-6 * omega, "%s: solid angle %.9g, Girard's excess %.9g", c->what, omega, g);
        }
        for (k = 0; k < NCELL; k++) {
            double pr = cell_prob(c->v, c->ref, nrm, k, warp ? 6 : 0, omega);
            CHECK(t, pr >= 0.0, "%s: tri_pdf_sa refused a direction inside", c->what);
            ex[k] = n * pr;
            obs[k] = 0.0;
        }
        rng_seed(&r, 101 + ci, (uint64_t)warp);
        for (k = 0; k < n; k++) {
            float u[2];
            SphTriSample s;
            int cell;
            rng_fill(&r, u, 2);
            CHECK(t, tri_sample_sa(c->ref, nrm, c->v, u[0], u[1], &s), "%s: no sample", c->what);
            cell = dir_cell(c->v, c->ref, s.dir);
            CHECK(t, cell >= 0, "%s: a direction outside the triangle", c->what);
            obs[cell] += 1.0;
        }
        CHECK_CHI2(t, obs, ex, NCELL, nc, NULL, "%s triangle, %s", c->what, warp ? "cosine warp" : "uniform");
    }
}

static void test_uniform_chi2(T *t) { chi2_cases(t, 0); }
static void test_warp_chi2(T *t) { chi2_cases(t, 1); }

static void test_bilinear_chi2(T *t)
{
    enum { G = 8 };
    static const double W[2][4] = { { 0.2, 0.9, 0.05, 1.7 }, { 1.0, 1.0, 0.01, 0.3 } };
    const int n = test_scaled(200000, 40000);
    int c, i, j, k;
    for (c = 0; c < 2; c++) {
        double obs[G * G], ex[G * G], sum = W[c][0] + W[c][1] + W[c][2] + W[c][3];
        Rng r;
        for (i = 0; i < G; i++)
            for (j = 0; j < G; j++) {
                /* the integral of 4 (w0 (1-x)(1-y) + w1 x (1-y) + w2 (1-x) y + w3 x y) / sum */
                double x0 = (double)i / G, x1 = (double)(i + 1) / G, y0 = (double)j / G, y1 = (double)(j + 1) / G;
                double X0 = (x1 - x0) - (x1 * x1 - x0 * x0) / 2, X1 = (x1 * x1 - x0 * x0) / 2;
                double Y0 = (y1 - y0) - (y1 * y1 - y0 * y0) / 2, Y1 = (y1 * y1 - y0 * y0) / 2;
                ex[i * G + j] = n * 4.0 * (W[c][0] * X0 * Y0 + W[c][1] * X1 * Y0 + W[c][2] * X0 * Y1 +
                                           W[c][3] * X1 * Y1) / sum;
                obs[i * G + j] = 0.0;
            }
        rng_seed(&r, 7, (uint64_t)c);
        for (k = 0; k < n; k++) {
            float u[2];
            double x, y;
            rng_fill(&r, u, 2);
            bilinear_sample(W[c], u[0], u[1], &x, &y);
            CHECK(t, x >= 0.0 && x <= 1.0 && y >= 0.0 && y <= 1.0, "sample (%g, %g) off the square", x, y);
            i = (int)(x * G); j = (int)(y * G);
            if (i >= G) i = G - 1;
            if (j >= G) j = G - 1;
            obs[i * G + j] += 1.0;
        }
        CHECK_CHI2(t, obs, ex, G * G, 2, NULL, "bilinear_sample, weights %d", c);
    }
}

static void test_pdf_at_sample(T *t)
{
    Rng r;
    int k, checked = 0, far = 0;
    rng_seed(&r, 5, 5);
    for (k = 0; k < 4000; k++) {
        float u[12];
        Vec3 v[3], ref, n;
        SphTriSample s;
        double pdf;
        int i;
        rng_fill(&r, u, 12);
        for (i = 0; i < 3; i++) v[i] = v3(4.0f * u[3 * i] - 2.0f, 0.5f + 6.0f * u[3 * i + 1], 4.0f * u[3 * i + 2] - 2.0f);
        if (k % 10 == 0)            /* tiny: out of the range, sampled by area */
            for (i = 1; i < 3; i++) v[i] = v3_add(v[0], v3_mul(v3_sub(v[i], v[0]), 0.004f));
        ref = v3(0.0f, 0.0f, 0.0f);
        n = k % 3 == 0 ? v3(0.0f, 0.0f, 0.0f) : v3_norm(v3(u[9] - 0.5f, u[10], u[11] - 0.5f));
        if (!tri_sample_sa(ref, n, v, u[1], u[5], &s)) {
            SphTri st;
            /* refused: degenerate, or the solid angle is out of range (then by area) */
            CHECK(t, !sph_tri_setup(ref, v[0], v[1], v[2], &st) || st.area < SPH_TRI_MIN || st.area > SPH_TRI_MAX,
                  "refused a triangle of %g sr", st.area);
            CHECK(t, !tri_pdf_sa(ref, n, v, v3(0.0f, 1.0f, 0.0f), &pdf), "a density where sampling refused");
            far++;
            continue;
        }
        {
            SphTri st;
            CHECK(t, sph_tri_setup(ref, v[0], v[1], v[2], &st) && st.area >= SPH_TRI_MIN &&
                  st.area <= SPH_TRI_MAX, "sampled by solid angle at %g sr", st.area);
        }
        CHECK(t, tri_pdf_sa(ref, n, v, s.dir, &pdf), "no density at a sampled direction");
        CHECK(t, fabs(pdf - s.pdf) <= 1e-4 * s.pdf, "pdf %.9g at the sample, tri_pdf_sa %.9g (case %d)",
              s.pdf, pdf, k);
        checked++;
    }
    CHECK(t, checked > 3000 && far > 10, "checked %d, out of range %d", checked, far);
}

/* The warp's meaning: near each vertex direction the density times Omega is
   4 cos / (2 cos_B + cos_A + cos_C), cos = max(0.01, |n . direction|) there. */
static void test_warp_corners(T *t)
{
    int nc, ci, k;
    const TriCase *cs = tri_cases(&nc);
    for (ci = 0; ci < nc; ci++) {
        const TriCase *c = &cs[ci];
        double cosv[3], sum, pdf;
        SphTri st;
        CHECK(t, sph_tri_setup(c->ref, c->v[0], c->v[1], c->v[2], &st), "degenerate");
        for (k = 0; k < 3; k++) {
            double x = fabs(v3_dot(c->n, v3_norm(v3_sub(c->v[k], c->ref))));
            cosv[k] = x > 0.01 ? x : 0.01;
        }
        sum = cosv[0] + 2.0 * cosv[1] + cosv[2];
        for (k = 0; k < 3; k++) {
            /* a point 1e-4 of the way from vertex k towards the centroid */
            Vec3 cen = v3_mul(v3_add(v3_add(c->v[0], c->v[1]), c->v[2]), 1.0f / 3.0f);
            Vec3 p = v3_add(c->v[k], v3_mul(v3_sub(cen, c->v[k]), 1e-4f));
            double want = 4.0 * cosv[k] / sum / st.area;
            CHECK(t, tri_pdf_sa(c->ref, c->n, c->v, v3_norm(v3_sub(p, c->ref)), &pdf), "no density");
            CHECK(t, fabs(pdf - want) < 2e-3 * want, "%s: density %.6g at vertex %d, want 4 cos / sum / Omega = %.6g",
                  c->what, pdf, k, want);
        }
    }
}

static void test_invert(T *t)
{
    int nc, ci, i, j;
    const TriCase *cs = tri_cases(&nc);
    for (ci = 0; ci < nc; ci++) {
        SphTri st;
        CHECK(t, sph_tri_setup(cs[ci].ref, cs[ci].v[0], cs[ci].v[1], cs[ci].v[2], &st), "degenerate");
        for (i = 0; i <= 20; i++)
            for (j = 1; j <= 20; j++) {
                double u0 = i / 20.0, u1 = j / 20.0, x, y;
                Vec3 w = sph_tri_sample(&st, u0, u1);
                CHECK(t, sph_tri_invert(&st, w, &x, &y), "%s: no inverse at (%g, %g)", cs[ci].what, u0, u1);
                CHECK(t, fabs(x - u0) < 2e-4 && fabs(y - u1) < 2e-4, "%s: (%g, %g) -> (%.6f, %.6f)",
                      cs[ci].what, u0, u1, x, y);
            }
    }
}

/* Lambert: the irradiance at the origin (normal n) from a polygon p[0..m) of
   L = 1 wholly above the horizon, E = 1/2 |sum_k theta_k (n . g_k)|, theta_k the
   angle p_k p_k+1 subtends and g_k the unit normal of their plane. */
static double lambert(const double p[][3], int m, Vec3 nrm)
{
    double acc = 0.0;
    int k;
    for (k = 0; k < m; k++) {
        const double *a = p[k], *b = p[(k + 1) % m];
        double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        double g[3], lg, th;
        g[0] = a[1] * b[2] - a[2] * b[1]; g[1] = a[2] * b[0] - a[0] * b[2]; g[2] = a[0] * b[1] - a[1] * b[0];
        lg = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        th = atan2(lg, (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]));
        (void)la; (void)lb;
        acc += th * (g[0] * nrm.x + g[1] * nrm.y + g[2] * nrm.z) / lg;
    }
    return 0.5 * fabs(acc);
}

/* A two-sided lamp at height h (a plane y = h) over the receiver at ref, normal
   nrm: a triangle or a quad of two triangles. */
static void irradiance_case(T *t, int quad, float h, Vec3 ref, Vec3 nrm, int warp, const char *what)
{
    static const double tri_p[3][2] = { { -1.5, -1 }, { 1.0, -1.2 }, { 0.3, 1.4 } };   /* (x, z) */
    static const double quad_p[4][2] = { { -2, -1 }, { 2, -1 }, { 2, 1 }, { -2, 1 } };
    char text[1024], *w = text;
    double p[4][3], sum = 0.0, sum2 = 0.0, mean, se, E;
    const int n = test_scaled(100000, 20000), m = quad ? 4 : 3;
    Scene s;
    Rng r;
    int k;
    w += sprintf(w, "Camera \"perspective\"\nWorldBegin\nAttributeBegin\n"
                 "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n"
                 "Shape \"trianglemesh\" \"integer indices\" [%s] \"point3 P\" [",
                 quad ? "0 1 2 0 2 3" : "0 1 2");
    for (k = 0; k < m; k++) {
        const double *q = quad ? quad_p[k] : tri_p[k];
        w += sprintf(w, " %g %g %g", q[0], (double)h, q[1]);
        p[k][0] = q[0] - ref.x; p[k][1] = h - ref.y; p[k][2] = q[1] - ref.z;
    }
    sprintf(w, "]\nAttributeEnd\n");
    if (!test_load_scene(t, &s, text)) return;
    rng_seed(&r, 31, (uint64_t)(quad * 2 + warp));
    for (k = 0; k < n; k++) {
        float u[3];
        EmitterSample es;
        double x = 0.0;
        rng_fill(&r, u, 3);
        if (emitter_sample(&s, 0, ref, warp ? nrm : v3(0.0f, 0.0f, 0.0f), u, &es)) {
            double c = v3_dot(es.wi, nrm);
            x = c > 0.0 ? c / es.pdf_sa : 0.0;
        }
        sum += x;
        sum2 += x * x;
    }
    scene_free(&s);
    mean = sum / n;
    se = sqrt((sum2 / n - mean * mean) / n);
    E = lambert((const double (*)[3])p, m, nrm);
    CHECK(t, fabs(mean - E) < TEST_K_SIGMA * se + 1e-5 * E, "%s: E %.6g +- %.2g, Lambert %.6g", what, mean, se, E);
}

static void test_irradiance(T *t)
{
    const Vec3 up = v3(0.0f, 1.0f, 0.0f), tilt = v3_norm(v3(0.15f, 1.0f, 0.1f));
    irradiance_case(t, 0, 0.7f, v3(0.1f, 0.0f, 0.0f), up, 1, "triangle at 0.7, warp");
    if (t->failed) return;
    irradiance_case(t, 0, 0.7f, v3(0.1f, 0.0f, 0.0f), tilt, 0, "triangle at 0.7, tilted, uniform");
    if (t->failed) return;
    irradiance_case(t, 0, 0.7f, v3(0.1f, 0.0f, 0.0f), tilt, 1, "triangle at 0.7, tilted, warp");
    if (t->failed) return;
    irradiance_case(t, 1, 1.5f, v3(0.5f, 0.0f, 0.2f), tilt, 1, "quad at 1.5, tilted, warp");
    if (t->failed) return;
    irradiance_case(t, 1, 1.5f, v3(0.5f, 0.0f, 0.2f), up, 0, "quad at 1.5, uniform");
    if (t->failed) return;
    irradiance_case(t, 1, 300.0f, v3(0.5f, 0.0f, 0.2f), up, 1, "quad at 300 (by area)");
}

/* the lamp of the render test: a 4 x 2 quad facing -z, close to a sphere */
#define QUAD_ROOM \
    "LookAt 0 1 6  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n" \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n" \
    "Integrator \"volpath\" \"integer maxdepth\" [3]\nWorldBegin\n" \
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [2 2 2]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n" \
    "  \"point3 P\" [-2 3 2.2  2 3 2.2  2 1 2.2  -2 1 2.2]\nAttributeEnd\n" \
    "AttributeBegin\nTranslate 0 1 0\nMaterial \"diffuse\" \"rgb reflectance\" [0.7 0.55 0.2]\n" \
    "Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n" \
    "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.3 0.3 0.3]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n" \
    "  \"point3 P\" [-5 0 -5  5 0 -5  5 0 5  -5 0 5]\nAttributeEnd\n"

/* a lamp standing on a floor, seen from above: the cosines at the floor's points
   run from 0 (the lamp's foot) to 1, where the warp and its MIS density matter most */
#define WALL_ROOM \
    "LookAt 0 3 2.5  0 0 0.6  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n" \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n" \
    "Integrator \"volpath\" \"integer maxdepth\" [1]\nWorldBegin\n" \
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [2 2 2]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n" \
    "  \"point3 P\" [-1 0 0  1 0 0  1 1.5 0  -1 1.5 0]\nAttributeEnd\n" \
    "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n" \
    "  \"point3 P\" [-5 0 0.01  5 0 0.01  5 0 5  -5 0 5]\nAttributeEnd\n"

/* light_sample (shape mode `shape`) against light_pdf_sa at the point a ray along
   its direction finds, from points around the quad lamp of QUAD_ROOM (one in four
   in a medium); *n_sa, *n_area: how many of the checked samples the rule
   (tri_sa_pays) sent to each map. */
static void light_pdf_case(T *t, int shape, int *n_sa, int *n_area)
{
    Scene s;
    LightSampler *ls;
    SelOptions so;
    Error err;
    Rng r;
    int k, checked = 0;
    *n_sa = *n_area = 0;
    if (!test_load_scene(t, &s, QUAD_ROOM)) return;
    memset(&so, 0, sizeof so);
    so.strategy = SEL_SPECTRAL_TREE;
    so.area_sampling = shape;
    ls = light_sampler_build(&s, &so, &err);
    CHECK(t, ls != NULL, "light_sampler_build: %s", err.msg);
    rng_seed(&r, 9, 9);
    for (k = 0; k < 2000; k++) {
        float u[9];
        Vec3 ref, n, v[3];
        EmitterSample es;
        Ray ray;
        HitRecord h;
        SurfacePoint sp;
        float pdf;
        double want;
        int by_sa;
        rng_fill(&r, u, 9);
        ref = v3(3.0f * u[0] - 1.5f, 0.3f + 2.0f * u[1], 1.8f * u[2] - 1.0f);
        if (shape == SHAPE_AUTO) ref.z = 2.1f - 12.0f * u[2] * u[2];   /* near and far */
        n = k % 4 == 0 ? v3(0.0f, 0.0f, 0.0f) : v3_norm(v3(u[3] - 0.5f, u[4] - 0.5f, u[5]));
        if (!light_sample(ls, 0, ref, n, u + 6, &es)) continue;
        ray.o = ref; ray.d = es.wi; ray.tmax = es.dist * 1.001f; ray.time = 0.0f;
        if (!bvh_intersect(&s.bvh, &s, &ray, &h)) continue;
        scene_surface_point(&s, &ray, &h, &sp);
        if (s.shapes[sp.shape].emitter != 0 || fabsf(h.t - es.dist) > 1e-3f) continue;
        pdf = light_pdf_sa(ls, 0, ref, n, sp.p, sp.ng, sp.prim);
        CHECK(t, fabsf(pdf - es.pdf_sa) <= 1e-3f * es.pdf_sa, "pdf at the hit %g, sampled %g", pdf, es.pdf_sa);
        /* the density the mode asks for, computed here: half (the triangle's
           share of the 4 x 2 quad) of tri_pdf_sa's, or d^2 / (8 |cos_y|) */
        v[0] = s.P[s.tris[sp.prim].v[0]]; v[1] = s.P[s.tris[sp.prim].v[1]]; v[2] = s.P[s.tris[sp.prim].v[2]];
        by_sa = shape == SHAPE_SA || (shape == SHAPE_AUTO && tri_sa_pays(ref, n, v));
        if (!by_sa || !tri_pdf_sa(ref, n, v, es.wi, &want))
            want = (double)es.dist * es.dist / (8.0 * fabs(es.wi.z));
        else
            want *= 0.5;
        CHECK(t, fabs(want - es.pdf_sa) <= 1e-3 * want, "mode %d: the sample's density %g, the mode's %g",
              shape, es.pdf_sa, want);
        if (tri_sa_pays(ref, n, v)) (*n_sa)++; else (*n_area)++;
        checked++;
    }
    light_sampler_free(ls);
    scene_free(&s);
    CHECK(t, checked > 500, "only %d samples found again", checked);
}

static void test_light_pdf(T *t)
{
    int n_sa, n_area;
    light_pdf_case(t, SHAPE_SA, &n_sa, &n_area);
    light_pdf_case(t, SHAPE_AREA, &n_sa, &n_area);
}

/* --light-shape-sampling auto: the same agreement, with points on both sides of
   the rule (each side at least 200 checked samples) */
static void test_auto_pdf(T *t)
{
    int n_sa, n_area;
    light_pdf_case(t, SHAPE_AUTO, &n_sa, &n_area);
    CHECK(t, n_sa >= 200 && n_area >= 200, "the rule's sides: %d by solid angle, %d by area", n_sa, n_area);
}

/* tri_sa_pays, by cases whose answer is plain: a lamp far overhead (the area
   estimate's factor |n . D| / |D|^4 nearly constant: 0), the same lamp close (1),
   a lamp with a vertex on the receiver's tangent plane (1), a receiver in the
   lamp's plane (every factor 0: 0), a far lamp across the receiver's horizon
   (|n . D|, as the warp reads it: 0), a far lamp behind
   the receiver (the |.|: 0), and in a medium (1 / d^3) far (0) and close (1);
   then against the definition, computed here, on random triangles (both answers
   occurring). */
static void test_auto_rule(T *t)
{
    Vec3 far[3], near[3], edge[3], v[3], o = v3(0.0f, 0.0f, 0.0f), up = v3(0.0f, 0.0f, 1.0f);
    Rng r;
    int k, yes = 0, no = 0;
    far[0] = v3(-1.0f, -1.0f, 20.0f); far[1] = v3(1.0f, -1.0f, 20.0f); far[2] = v3(0.0f, 1.0f, 20.0f);
    near[0] = v3(-1.0f, -1.0f, 0.7f); near[1] = v3(1.0f, -1.0f, 0.7f); near[2] = v3(0.0f, 1.0f, 0.7f);
    edge[0] = v3(-1.0f, 5.0f, 0.0f); edge[1] = v3(1.0f, 5.0f, 3.0f); edge[2] = v3(0.0f, 6.0f, 3.0f);
    CHECK(t, !tri_sa_pays(o, up, far), "a small lamp far overhead is sampled by solid angle");
    CHECK(t, tri_sa_pays(o, up, near), "a large lamp close overhead is sampled by area");
    CHECK(t, tri_sa_pays(o, up, edge), "a lamp rising from the horizon is sampled by area");
    CHECK(t, !tri_sa_pays(v3(0.0f, 0.0f, 20.0f), up, far), "from the lamp's own plane it is sampled by solid angle");
    CHECK(t, !tri_sa_pays(o, v3(0.0f, 0.0f, -1.0f), far), "a far lamp behind the receiver is sampled by solid angle");
    /* across the horizon, |n . D| at the vertices 1, 1, 1 and at the centroid 1/3
       (closer): a spread under 3, by area; the signed cosine would flip it */
    v[0] = v3(10.0f, -1.0f, 1.0f); v[1] = v3(10.0f, 1.0f, 1.0f); v[2] = v3(10.0f, 0.0f, -1.0f);
    CHECK(t, !tri_sa_pays(o, up, v), "a far lamp across the horizon is sampled by solid angle");
    CHECK(t, !tri_sa_pays(o, o, far), "in a medium, a far lamp is sampled by solid angle");
    CHECK(t, tri_sa_pays(o, o, near), "in a medium, a close lamp is sampled by area");
    rng_seed(&r, 38, 1);
    for (k = 0; k < 4000; k++) {
        float u[12];
        double g[4], gmin, gmax, spread;
        Vec3 ref, n;
        int i, want;
        rng_fill(&r, u, 12);
        for (i = 0; i < 3; i++) v[i] = v3(4.0f * u[3 * i] - 2.0f, 4.0f * u[3 * i + 1] - 2.0f, 2.0f + 3.0f * u[3 * i + 2]);
        ref = v3(2.0f * u[9] - 1.0f, 2.0f * u[10] - 1.0f, -3.0f * u[11]);
        n = k % 5 == 0 ? o : v3_norm(v3(u[9] - 0.5f, u[10] - 0.5f, 1.0f));
        for (i = 0; i < 4; i++) {
            double p[3], d2 = 0.0, c = 0.0;
            int a;
            for (a = 0; a < 3; a++) {
                p[a] = i < 3 ? v3_get(v[i], a) : ((double)v3_get(v[0], a) + v3_get(v[1], a) + v3_get(v[2], a)) / 3.0;
                p[a] -= v3_get(ref, a);
                d2 += p[a] * p[a];
                c += p[a] * v3_get(n, a);
            }
            g[i] = k % 5 == 0 ? 1.0 / (d2 * sqrt(d2)) : fabs(c) / (d2 * d2);
        }
        gmin = gmax = g[0];
        for (i = 1; i < 4; i++) { gmin = g[i] < gmin ? g[i] : gmin; gmax = g[i] > gmax ? g[i] : gmax; }
        spread = gmax / gmin;
        if (fabs(spread / SPH_TRI_SPREAD - 1.0) < 1e-6) continue;       /* on the edge: rounding */
        want = spread > SPH_TRI_SPREAD;
        CHECK(t, tri_sa_pays(ref, n, v) == want, "case %d: spread %g, the rule says %d", k, spread, !want);
        if (want) yes++; else no++;
    }
    CHECK(t, yes > 400 && no > 400, "random triangles: %d by solid angle, %d by area", yes, no);
}

/* The combined sampler of --light-shape-sampling auto (a triangle by area, then
   its map by the rule) from a point where the rule splits a quad lamp: one
   triangle by solid angle, the other by area.  Counts in the barycentric cells of
   both triangles against light_pdf_sa integrated over each (chi-square). */
typedef struct { LightSampler *ls; Vec3 ref, n, p0, ng; int prim; } AutoPdf;

static int auto_pdf_density(void *ctx, const double p[3], double *pdf)
{
    const AutoPdf *a = (const AutoPdf *)ctx;
    Vec3 q = v3_add(a->ref, v3((float)p[0], (float)p[1], (float)p[2]));
    *pdf = light_pdf_sa(a->ls, 0, a->ref, a->n, q, a->ng, a->prim);
    return *pdf > 0.0;
}

static void test_auto_chi2(T *t)
{
    const int n = test_scaled(200000, 40000);
    Scene s;
    SelOptions so;
    Error err;
    AutoPdf a;
    Rng r;
    Vec3 v[2][3];
    static double obs[2 * NCELL], ex[2 * NCELL];
    int i, j, k, found = 0;
    if (!test_load_scene(t, &s, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
                         "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
                         "  \"point3 P\" [-2 3 2.2  2 3 2.2  2 1 2.2  -2 1 2.2]\n")) return;
    for (k = 0; k < 2; k++)
        for (j = 0; j < 3; j++) v[k][j] = s.P[s.tris[k].v[j]];
    a.n = v3(0.0f, 0.0f, 1.0f);
    for (i = 0; i < 41 && !found; i++)            /* a point where the rule splits the lamp */
        for (j = 0; j < 9 && !found; j++) {
            a.ref = v3(-4.0f + 0.2f * (float)i, 2.0f, 1.9f - 0.5f * (float)j);
            found = tri_sa_pays(a.ref, a.n, v[0]) != tri_sa_pays(a.ref, a.n, v[1]);
        }
    CHECK(t, found, "no point where one triangle goes by solid angle and the other by area");
    memset(&so, 0, sizeof so);
    so.strategy = SEL_UNIFORM;
    so.area_sampling = SHAPE_AUTO;
    a.ls = light_sampler_build(&s, &so, &err);
    CHECK(t, a.ls != NULL, "light_sampler_build: %s", err.msg);
    a.ng = v3(0.0f, 0.0f, 1.0f);
    for (k = 0; k < 2; k++) {
        a.prim = k;
        for (j = 0; j < NCELL; j++) {
            double pr = cell_prob_of(v[k], a.ref, j, 6, 1.0, auto_pdf_density, &a);
            ex[k * NCELL + j] = n * (pr > 0.0 ? pr : 0.0);
            obs[k * NCELL + j] = 0.0;
        }
    }
    rng_seed(&r, 38, 2);
    for (k = 0; k < n; k++) {
        float u[3];
        EmitterSample es;
        int cell;
        rng_fill(&r, u, 3);
        if (!light_sample(a.ls, 0, a.ref, a.n, u, &es) || es.prim < 0 || es.prim > 1) continue;
        cell = dir_cell(v[es.prim], a.ref, es.wi);
        if (cell >= 0) obs[es.prim * NCELL + cell] += 1.0;
    }
    light_sampler_free(a.ls);
    scene_free(&s);
    CHECK_CHI2(t, obs, ex, 2 * NCELL, 1, NULL, "auto from (%g, %g, %g)", a.ref.x, a.ref.y, a.ref.z);
}

/* Tiles of --light-shape-sampling `first` and area over K seeds: their means
   agree; *va, *vb: the sums of their squared standard errors. */
static int render_pair(T *t, const char *text, int first, int K, int spp, double *va, double *vb,
                       const char *what)
{
    static Tiles a, b;
    Scene s;
    RenderOptions o, oa;
    int i, c, ok;
    if (!test_load_scene(t, &s, text)) return 0;
    render_options_default(&o);
    o.spp = test_scaled(spp, 4);
    o.seed = 1;
    o.sel.area_sampling = first;
    oa = o;
    oa.sel.area_sampling = SHAPE_AREA;
    ok = test_render_tiles(t, &s, &o, K, 4, &a) && test_render_tiles(t, &s, &oa, K, 4, &b);
    scene_free(&s);
    if (!ok || !test_tiles_agree(t, &a, &b, 1e-4, what)) return 0;
    *va = *vb = 0.0;
    for (i = 0; i < 16; i++)
        for (c = 0; c < 3; c++) { *va += a.se[i][c] * a.se[i][c]; *vb += b.se[i][c] * b.se[i][c]; }
    return 1;
}

/* --light-shape-sampling `first` (solidangle, auto) against area, rendered in
   both rooms: the same means; over the sphere, where the close lamp sends most
   points to the solid-angle map, less than 0.6 of area's variance. */
static void render_vs_area(T *t, int first, const char *name)
{
    char what[96];
    double va, vb;
    snprintf(what, sizeof what, "quad lamp over a sphere, %s vs area", name);
    if (!render_pair(t, QUAD_ROOM, first, 8, 16, &va, &vb, what)) return;
    CHECK(t, va < 0.6 * vb, "%s's variance %.3g is not below 0.6 x area's %.3g", name, va, vb);
    snprintf(what, sizeof what, "lamp standing on a floor, %s vs area", name);
    render_pair(t, WALL_ROOM, first, 16, 128, &va, &vb, what);
}

static void test_render_agrees(T *t) { render_vs_area(t, SHAPE_SA, "solidangle"); }
static void test_auto_render(T *t) { render_vs_area(t, SHAPE_AUTO, "auto"); }

const TestCase tests_sphtri[] = {
    { "sphtri_uniform_chi2", test_uniform_chi2 },
    { "sphtri_warp_chi2", test_warp_chi2 },
    { "sphtri_bilinear_chi2", test_bilinear_chi2 },
    { "sphtri_pdf_at_sample", test_pdf_at_sample },
    { "sphtri_warp_corners", test_warp_corners },
    { "sphtri_invert", test_invert },
    { "sphtri_irradiance", test_irradiance },
    { "sphtri_light_pdf", test_light_pdf },
    { "sphtri_render_agrees", test_render_agrees },
    { "sphtri_auto_rule", test_auto_rule },
    { "sphtri_auto_pdf", test_auto_pdf },
    { "sphtri_auto_chi2", test_auto_chi2 },
    { "sphtri_auto_render", test_auto_render },
    { NULL, NULL }
};
