/* subsurface.c - pbrt-v4's "subsurface" material: light that enters a translucent
   body (skin, marble, milk) at one point and leaves it at another, by a tabulated
   BSSRDF (THEORY §18 derives the estimator; its notation is THEORY §0's).

   Exported (specnee.h, section 6): the diffusion profile (bssrdf_single,
   bssrdf_multiple, fresnel_moment1/2), its table (bssrdf_table_build), the
   Catmull-Rom spline tools the table is read with (catmull_rom_*), the profile,
   its density and its sampler per wavelength (bssrdf_sr, bssrdf_pdf_sr,
   bssrdf_sample_sr), SubsurfaceFromDiffuse (bssrdf_from_albedo), the probe
   (sss_probe), the exit lobe Sw (sss_exit_sample, sss_exit_eval), the material's
   coefficients at a point (sss_coeffs) and its builder (subsurface_from_params).
   path.c calls sss_probe and the exit lobe at a subsurface vertex; material.c
   gives the entry its rough or smooth dielectric BSDF.

   THE MODEL (Jensen et al. 2001, "A Practical Model for Subsurface Light
   Transport"; the photon beam diffusion of Habel, Christensen and Jarosz 2013 as
   pbrt-v4 tabulates it).  The BSSRDF is separable,
       S(po, wo, pi, wi) = (1 - Fr(cos o)) Sp(|po - pi|) Sw(wi),
   the entry's Fresnel transmission being the dielectric BSDF's own lobe.  The
   radial profile of a medium with extinction sigma_t and albedo rho is that of a
   unit medium in optical radius r' = sigma_t r:
       Sr(r) = sigma_t^2 Sr'(rho, sigma_t r).                             (39)
   The table holds P(rho_i, r'_k) = 2 pi r' (E_ss + E_ms)(rho_i, r'_k), the
   profile times its circumference, for 100 albedos rho_i = (1 - e^{-8i/99}) /
   (1 - e^{-8}) and 64 radii r'_0 = 0, r'_1 = 0.0025, r'_{k+1} = 1.2 r'_k, and
       rho_eff(rho) = int_0^inf P(rho, r') dr'                            (40)
   the effective albedo, the fraction of the light entering that leaves again
   (by the Catmull-Rom spline through the radii, whose running integral is also
   the radius sampler's CDF).  Between the knots the table is read by tensor
   Catmull-Rom interpolation in (rho, r').
   - Multiple scattering E_ms: the photon beam is a line of point sources at
     depths z_r ~ sigma'_t e^{-sigma'_t z} (100 stratified depths), each with its
     mirror source at z_v = 2 z_e - z_r (the extrapolated boundary z_e = -2 D
     (1 + 3 F2) / (1 - 2 F1)), Grosjean's coefficient D = (2 sigma_a + sigma'_s)
     / (3 sigma'_t^2), sigma_tr = sqrt(sigma_a / D), sigma'_s = (1 - g) sigma_s:
       E_ms = < kappa rho'^2 (c_phi phi(r) + c_E E.n(r)) >,
       phi  = (e^{-sigma_tr d_r} / d_r - e^{-sigma_tr d_v} / d_v) / (4 pi D),
       E.n  = (z_r (1 + sigma_tr d_r) e^{-sigma_tr d_r} / d_r^3
               - z_v (1 + sigma_tr d_v) e^{-sigma_tr d_v} / d_v^3) / (4 pi),
     d = sqrt(r^2 + z^2), c_phi = (1 - 2 F1) / 4, c_E = (1 - 3 F2) / 2, kappa =
     1 - e^{-2 sigma'_t (d_r + z_r)}; F1, F2 the Fresnel moments
     F_i(eta) = int_0^1 Fr(mu, 1/eta) mu^i dmu, by pbrt-v4's polynomial fits.
   - Single scattering E_ss: the refracted beam scatters once at depth t >=
     t_c = r sqrt(eta^2 - 1) and leaves towards the surface point at distance r:
       E_ss = < rho e^{-sigma_t (d + t_c)} / d^2 p_HG(cos o) (1 - Fr(-cos o)) |cos o| >,
     t = t_c + (exponential with sigma_t), 100 stratified samples, d = sqrt(r^2 +
     t^2), cos o = t / d (pbrt-v4's HG sign convention: p_HG(-cos) of hg_phase).
   SubsurfaceFromDiffuse: a "reflectance" R and mean free path mfp give rho =
   rho_eff^-1(R) (the spline through (rho_i, rho_eff_i) inverted), sigma_s = rho /
   mfp, sigma_a = (1 - rho) / mfp.

   SAMPLING THE EXIT (THEORY §18).  With the hero's profile (pbrt-v4's: the
   first wavelength) a radius r is drawn from P(rho_0, .) / rho_eff (the 2-D
   spline sample) and divided by sigma_t,0; the density in the plane is
       p_r,j(r) = Sr_j(r) / rho_eff,j                                      (41)
   for the profile of any wavelength j.  A projection axis a is chosen among
   the shading frame's (s, t, n) with P_a = (1/4, 1/4, 1/2) and the probe is the
   chord of the sphere of radius r_max = (the sampled radius at u = 0.999) along
   a at distance r from po, at angle phi = 2 pi u.  Every surface of the same
   material along it is a candidate; one of the N is chosen uniformly.  The
   exit point pi with normal ni then has the area density
       p_j(pi) = (1/N) sum_a P_a p_r,j(r_a) |ni . a|                      (42)
   (r_a: |pi - po| projected along a), a one-sample MIS over the three axes
   whose weights P_a p_a / sum_b P_b p_b sum to 1 for any N (the 1/N of the
   axis actually taken multiplies every term alike).  The path then carries
       beta_j *= Sp_j(pi) / p_0(pi),   r_j *= p_j(pi) / p_0(pi)           (43)
   (THEORY (5): the ratio r_j is the density the same exit has when lambda_j's
   profile is the hero's), and leaves by the lobe
       Sw(wi) = eta^2 (1 - Fr(cos i, eta)) / (c pi),  c = 1 - 2 F1(1/eta),  (44)
   on the exit's outer side (its shading normal); eta^2 undoes the 1/eta^2 of
   the entry's refraction (radiance mode), so eta2 gets 1/eta^2. */
#include "specnee.h"
#include "parser.h"
#include <string.h>

/* ------------------------------------------------------------ the profile (40) */

/* pbrt-v4's polynomial fits (its FresnelMoment1/2) of the Fresnel moments
   F_i(eta) = int_0^1 Fr(mu, 1/eta) mu^i dmu, i = 1, 2 (Fr: fresnel_dielectric);
   the tests compare them with the integrals. */
double fresnel_moment1(double eta)
{
    double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    if (eta < 1.0)
        return 0.45966 - 1.73965 * eta + 3.37668 * e2 - 3.904945 * e3 + 2.49277 * e4 - 0.68441 * e5;
    return -4.61686 + 11.1136 * eta - 10.4646 * e2 + 5.11455 * e3 - 1.27198 * e4 + 0.12746 * e5;
}

double fresnel_moment2(double eta)
{
    double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    double r = 1.0 / eta, r2 = r * r, r3 = r2 * r;
    if (eta < 1.0)
        return 0.27614 - 0.87350 * eta + 1.12077 * e2 - 0.65095 * e3 + 0.07883 * e4 + 0.04860 * e5;
    return -547.033 + 45.3087 * r3 - 218.725 * r2 + 458.843 * r + 404.557 * eta - 189.519 * e2 +
           54.9327 * e3 - 9.00603 * e4 + 0.63942 * e5;
}

/* depth of stratum i of n for an exponential of rate a: -ln(1 - u) / a */
static double exp_depth(int i, int n, double a) { return -log(1.0 - (i + 0.5) / n) / a; }

#define SSS_DEPTHS 100          /* stratified depths of both integrals (pbrt-v4's) */

double bssrdf_multiple(double sigma_s, double sigma_a, double g, double eta, double r)
{
    double sps = sigma_s * (1.0 - g), spt = sigma_a + sps, rhop = sps / spt;
    double D = (2.0 * sigma_a + sps) / (3.0 * spt * spt), str = sqrt(fmax(0.0, sigma_a / D));
    double f1 = fresnel_moment1(eta), f2 = fresnel_moment2(eta);
    double ze = -2.0 * D * (1.0 + 3.0 * f2) / (1.0 - 2.0 * f1);
    double cphi = 0.25 * (1.0 - 2.0 * f1), ce = 0.5 * (1.0 - 3.0 * f2), sum = 0.0;
    int i;
    for (i = 0; i < SSS_DEPTHS; i++) {
        double zr = exp_depth(i, SSS_DEPTHS, spt), zv = 2.0 * ze - zr;
        double dr = sqrt(r * r + zr * zr), dv = sqrt(r * r + zv * zv);
        double er = exp(-str * dr), ev = exp(-str * dv);
        double phi = (er / dr - ev / dv) / (4.0 * SPECNEE_PI * D);
        double en = (zr * (1.0 + str * dr) * er / (dr * dr * dr) -
                     zv * (1.0 + str * dv) * ev / (dv * dv * dv)) / (4.0 * SPECNEE_PI);
        double kappa = 1.0 - exp(-2.0 * spt * (dr + zr));
        sum += kappa * rhop * rhop * (cphi * phi + ce * en);
    }
    return sum / SSS_DEPTHS;
}

double bssrdf_single(double sigma_s, double sigma_a, double g, double eta, double r)
{
    double st = sigma_a + sigma_s, rho = sigma_s / st, tc = r * sqrt(fmax(0.0, eta * eta - 1.0));
    double sum = 0.0;
    int i;
    for (i = 0; i < SSS_DEPTHS; i++) {
        double t = tc + exp_depth(i, SSS_DEPTHS, st), d = sqrt(r * r + t * t), c = t / d;
        sum += rho * exp(-st * (d + tc)) / (d * d) * hg_phase((float)g, (float)-c) *
               (1.0 - fresnel_dielectric((float)-c, (float)eta)) * fabs(c);
    }
    return sum / SSS_DEPTHS;
}

/* ------------------------------------------------------------ Catmull-Rom splines */

/* The interval [x_i, x_{i+1}] of the increasing knots x[0..n) holding v (clamped to
   0..n-2); pred(i) = x[i] <= v by bisection. */
static int find_interval(const float *x, int n, float v)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (x[mid] <= v) lo = mid; else hi = mid;
    }
    return lo < n - 2 ? lo : n - 2;
}

int catmull_rom_weights(const float *x, int n, float v, int *offset, float w[4])
{
    int i;
    float x0, x1, t, t2, t3;
    if (!(v >= x[0] && v <= x[n - 1])) return 0;
    i = find_interval(x, n, v);
    *offset = i - 1;
    x0 = x[i];
    x1 = x[i + 1];
    t = (v - x0) / (x1 - x0);
    t2 = t * t;
    t3 = t2 * t;
    w[1] = 2.0f * t3 - 3.0f * t2 + 1.0f;          /* the Hermite basis at the two knots */
    w[2] = -2.0f * t3 + 3.0f * t2;
    if (i > 0) {            /* slope at x0 by the central difference over x_{i-1}, x1 */
        float w0 = (t3 - 2.0f * t2 + t) * (x1 - x0) / (x1 - x[i - 1]);
        w[0] = -w0;
        w[2] += w0;
    } else {                /* first interval: the one-sided difference */
        float w0 = t3 - 2.0f * t2 + t;
        w[0] = 0.0f;
        w[1] -= w0;
        w[2] += w0;
    }
    if (i + 2 < n) {
        float w3 = (t3 - t2) * (x1 - x0) / (x[i + 2] - x0);
        w[1] -= w3;
        w[3] = w3;
    } else {
        float w3 = t3 - t2;
        w[1] -= w3;
        w[2] += w3;
        w[3] = 0.0f;
    }
    return 1;
}

/* The slopes (times the interval's width) at the ends of interval i of f. */
static void spline_slopes(const float *x, const float *f, int n, int i, float *d0, float *d1)
{
    float w = x[i + 1] - x[i];
    *d0 = i > 0 ? w * (f[i + 1] - f[i - 1]) / (x[i + 1] - x[i - 1]) : f[i + 1] - f[i];
    *d1 = i + 2 < n ? w * (f[i + 2] - f[i]) / (x[i + 2] - x[i]) : f[i + 1] - f[i];
}

float catmull_rom_integrate(const float *x, const float *f, int n, float *cdf)
{
    double sum = 0.0;
    int i;
    cdf[0] = 0.0f;
    for (i = 0; i + 1 < n; i++) {
        float d0, d1;
        spline_slopes(x, f, n, i, &d0, &d1);
        sum += (x[i + 1] - x[i]) * ((f[i] + f[i + 1]) * 0.5 + (d0 - d1) / 12.0);
        cdf[i + 1] = (float)sum;
    }
    return (float)sum;
}

/* Newton's method kept inside a bisection bracket: the t in [0, 1] where F(t) =
   target, F increasing with derivative f, both polynomials of degree <= 4. */
typedef struct { double F[5], f[5]; } Poly2;
static double poly(const double *c, double t)
{ return (((c[4] * t + c[3]) * t + c[2]) * t + c[1]) * t + c[0]; }
static double newton_bisection(const Poly2 *q, double target)
{
    double a = 0.0, b = 1.0, t = 0.5;
    int it;
    for (it = 0; it < 64; it++) {
        double F = poly(q->F, t) - target, f = poly(q->f, t);
        if (fabs(F) < 1e-6) break;
        if (F < 0.0) a = t; else b = t;
        t -= F / f;
        if (!(t > a && t < b)) t = 0.5 * (a + b);   /* Newton left the bracket: bisect */
        if (b - a < 1e-6) break;
    }
    return t;
}

/* The Hermite cubic of one interval, F(t) = f0 h00 + f1 h01 + d0 h10 + d1 h11, as
   the polynomial c[0..3] in t. */
static void hermite(float f0, float f1, float d0, float d1, double c[4])
{
    c[0] = f0;
    c[1] = d0;
    c[2] = -3.0 * f0 + 3.0 * f1 - 2.0 * d0 - d1;
    c[3] = 2.0 * f0 - 2.0 * f1 + d0 + d1;
}

float catmull_rom_invert(const float *x, const float *f, int n, float u)
{
    float d0, d1;
    double c[4];
    Poly2 q;
    int i;
    if (!(u > f[0])) return x[0];
    if (!(u < f[n - 1])) return x[n - 1];
    i = find_interval(f, n, u);
    spline_slopes(x, f, n, i, &d0, &d1);
    hermite(f[i], f[i + 1], d0, d1, c);
    memset(&q, 0, sizeof q);
    for (i = 0; i < 4; i++) q.F[i] = c[i];               /* F: the spline, f: its slope */
    for (i = 1; i < 4; i++) q.f[i - 1] = i * c[i];
    i = find_interval(f, n, u);
    return x[i] + (float)newton_bisection(&q, u) * (x[i + 1] - x[i]);
}

/* The table's row interpolated at rho's weights: entry k of sum_i w_i a[(off + i) R + k]. */
static float row_at(const float *a, int off, const float w[4], int k)
{
    float v = 0.0f;
    int i;
    for (i = 0; i < 4; i++)
        if (w[i] != 0.0f) v += a[(off + i) * SSS_R_N + k] * w[i];
    return v;
}

/* The radius r' whose running integral of the interpolated row P(rho, .) is u times
   its whole (rho_eff); *pdf (not NULL) its density P(rho, r') / rho_eff.  0 when rho
   is outside the table. */
static float sample_row(const BssrdfTable *t, float rho, float u, float *pdf)
{
    const float *x = t->radius;
    float w[4], total, f0, f1, d0, d1, width, v;
    double s, c[4];
    Poly2 q;
    int off, lo = 0, hi = SSS_R_N - 1, k, i;
    if (!catmull_rom_weights(t->rho, SSS_RHO_N, rho, &off, w)) return 0.0f;
    total = row_at(t->cdf, off, w, SSS_R_N - 1);
    u *= total;
    while (hi - lo > 1) {                       /* the interval of the interpolated CDF */
        int mid = (lo + hi) / 2;
        if (row_at(t->cdf, off, w, mid) <= u) lo = mid; else hi = mid;
    }
    k = lo;
    f0 = row_at(t->profile, off, w, k);
    f1 = row_at(t->profile, off, w, k + 1);
    width = x[k + 1] - x[k];
    v = (u - row_at(t->cdf, off, w, k)) / width;
    d0 = k > 0 ? width * (f1 - row_at(t->profile, off, w, k - 1)) / (x[k + 1] - x[k - 1]) : f1 - f0;
    d1 = k + 2 < SSS_R_N ? width * (row_at(t->profile, off, w, k + 2) - f0) / (x[k + 2] - x[k])
                         : f1 - f0;
    /* F: the integral of the Hermite cubic from 0 to t; f: the cubic itself */
    hermite(f0, f1, d0, d1, c);
    memset(&q, 0, sizeof q);
    for (i = 0; i < 4; i++) { q.f[i] = c[i]; q.F[i + 1] = c[i] / (i + 1); }
    s = newton_bisection(&q, v);
    if (pdf) *pdf = total > 0.0f ? (float)poly(q.f, s) / total : 0.0f;
    return x[k] + (float)s * width;
}

/* ------------------------------------------------------------ the table */

void bssrdf_table_build(BssrdfTable *t, float g, float eta)
{
    int i, k;
    t->radius[0] = 0.0f;
    t->radius[1] = 2.5e-3f;
    for (k = 2; k < SSS_R_N; k++) t->radius[k] = t->radius[k - 1] * 1.2f;
    for (i = 0; i < SSS_RHO_N; i++)
        t->rho[i] = (float)((1.0 - exp(-8.0 * i / (SSS_RHO_N - 1))) / (1.0 - exp(-8.0)));
    for (i = 0; i < SSS_RHO_N; i++) {
        float *row = t->profile + i * SSS_R_N;
        for (k = 0; k < SSS_R_N; k++) {
            double rho = t->rho[i], r = t->radius[k];
            row[k] = (float)(2.0 * SPECNEE_PI * r * (bssrdf_single(rho, 1.0 - rho, g, eta, r) +
                                                     bssrdf_multiple(rho, 1.0 - rho, g, eta, r)));
        }
        t->rho_eff[i] = catmull_rom_integrate(t->radius, row, SSS_R_N, t->cdf + i * SSS_R_N);
    }
}

/* The interpolated profile P(rho, r') at the optical radius ro and (rho_eff not
   NULL) the interpolated rho_eff; 0 when (rho, ro) is outside the table. */
static float profile_at(const BssrdfTable *t, float rho, float ro, float *rho_eff)
{
    float wr[4], wk[4], sr = 0.0f, re = 0.0f;
    int or_, ok, j, k;
    if (!catmull_rom_weights(t->rho, SSS_RHO_N, rho, &or_, wr) ||
        !catmull_rom_weights(t->radius, SSS_R_N, ro, &ok, wk)) return 0.0f;
    for (j = 0; j < 4; j++) {
        if (wr[j] == 0.0f) continue;
        re += t->rho_eff[or_ + j] * wr[j];
        for (k = 0; k < 4; k++)
            if (wk[k] != 0.0f) sr += t->profile[(or_ + j) * SSS_R_N + ok + k] * wr[j] * wk[k];
    }
    if (rho_eff) *rho_eff = re;
    return sr;
}

float bssrdf_sr(const BssrdfTable *t, float sigma_t, float rho, float r)
{
    float ro = r * sigma_t, sr = profile_at(t, rho, ro, NULL);
    if (ro != 0.0f) sr /= 2.0f * PI_F * ro;                 /* P is 2 pi r' times Sr' */
    sr *= sigma_t * sigma_t;                                 /* (39) */
    return sr > 0.0f ? sr : 0.0f;
}

float bssrdf_pdf_sr(const BssrdfTable *t, float sigma_t, float rho, float r)
{
    float ro = r * sigma_t, re = 0.0f, sr = profile_at(t, rho, ro, &re), p;
    if (!(re > 0.0f)) return 0.0f;
    if (ro != 0.0f) sr /= 2.0f * PI_F * ro;
    p = sr * sigma_t * sigma_t / re;                        /* (41) */
    return p > 0.0f ? p : 0.0f;
}

float bssrdf_sample_sr(const BssrdfTable *t, float sigma_t, float rho, float u)
{
    if (!(sigma_t > 0.0f)) return -1.0f;
    return sample_row(t, rho, u, NULL) / sigma_t;
}

void bssrdf_from_albedo(const BssrdfTable *t, float R, float mfp, float *sigma_a, float *sigma_s)
{
    float rho = catmull_rom_invert(t->rho, t->rho_eff, SSS_RHO_N, R);
    *sigma_s = rho / mfp;
    *sigma_a = (1.0f - rho) / mfp;
}

/* ------------------------------------------------------------ the material at a point */

/* A spectrum parameter of the material: texture tex (1 + index) at sp, else s. */
static float sss_value(const Material *m, int tex, const Spectrum *s, const SurfacePoint *sp, float lam)
{
    if (tex > 0 && m->textures) return tex_eval(m->textures, tex - 1, sp, lam);
    return spec_eval(s, lam);
}

void sss_coeffs(const Material *m, const SurfacePoint *sp, const float *lam, unsigned alive,
                float sigma_t[HERO_N], float rho[HERO_N])
{
    const Subsurface *ss = m->sss;
    int j;
    for (j = 0; j < HERO_N; j++) {
        float sa, sc;
        sigma_t[j] = rho[j] = 0.0f;
        if (!(alive & (1u << j))) continue;
        if (ss->from_albedo) {
            float R = m->reflectance_tex > 0 && m->textures
                      ? tex_eval(m->textures, m->reflectance_tex - 1, sp, lam[j])   /* texture.c */
                      : albedo_eval(&m->reflectance, lam[j]);
            float mfp = ss->scale * sss_value(m, ss->tex[SSS_TEX_MFP], &ss->mfp, sp, lam[j]);
            R = R > 0.0f ? (R < 1.0f ? R : 1.0f) : 0.0f;     /* pbrt-v4: clamped to [0, 1] */
            if (!(mfp > 0.0f)) continue;                      /* (pbrt-v4: ClampZero, then 1/0) */
            bssrdf_from_albedo(&ss->table, R, mfp, &sa, &sc);
        } else {
            sa = ss->scale * sss_value(m, ss->tex[SSS_TEX_SIGMA_A], &ss->sigma_a, sp, lam[j]);
            sc = ss->scale * sss_value(m, ss->tex[SSS_TEX_SIGMA_S], &ss->sigma_s, sp, lam[j]);
            sa = sa > 0.0f ? sa : 0.0f;
            sc = sc > 0.0f ? sc : 0.0f;
        }
        sigma_t[j] = sa + sc;
        rho[j] = sigma_t[j] > 0.0f ? sc / sigma_t[j] : 0.0f;
    }
}

/* ------------------------------------------------------------ the probe (42) */

/* p_j(pi) of (42) without the 1/N: the three axes' densities at the exit pi, ni
   seen from the entry po with shading frame fr. */
static float pdf_sp(const BssrdfTable *t, float sigma_t, float rho, const Frame *fr, Vec3 po,
                    Vec3 pi, Vec3 ni)
{
    Vec3 d = frame_to_local(fr, v3_sub(pi, po)), n = frame_to_local(fr, ni);
    float rs = sqrtf(d.y * d.y + d.z * d.z), rt = sqrtf(d.z * d.z + d.x * d.x);
    float rn = sqrtf(d.x * d.x + d.y * d.y);
    return 0.25f * bssrdf_pdf_sr(t, sigma_t, rho, rs) * fabsf(n.x) +
           0.25f * bssrdf_pdf_sr(t, sigma_t, rho, rt) * fabsf(n.y) +
           0.5f * bssrdf_pdf_sr(t, sigma_t, rho, rn) * fabsf(n.z);
}

int sss_probe(const struct Scene *s, const Material *m, int mi, const SurfacePoint *entry,
              const float *lam, unsigned alive, const float u[4], SssExit *out)
{
    const BssrdfTable *t = &m->sss->table;
    float st[HERO_N], rho[HERO_N], r, rmax, phi, l;
    Frame fr = frame_from_normal(entry->ns);
    Vec3 axis, a1, a2, p0, p1;
    Ray ray;
    Rng rng;
    int j, any = 0;
    memset(out, 0, sizeof *out);
    sss_coeffs(m, entry, lam, alive, st, rho);
    if (u[0] < 0.25f) { axis = fr.s; a1 = fr.t; a2 = fr.n; }    /* P_a = 1/4, 1/4, 1/2 */
    else if (u[0] < 0.5f) { axis = fr.t; a1 = fr.n; a2 = fr.s; }
    else { axis = fr.n; a1 = fr.s; a2 = fr.t; }
    r = bssrdf_sample_sr(t, st[0], rho[0], u[1]);
    rmax = bssrdf_sample_sr(t, st[0], rho[0], 0.999f);
    if (!(r >= 0.0f) || !(r < rmax)) return 0;
    phi = 2.0f * PI_F * u[2];
    l = 2.0f * sqrtf(rmax * rmax - r * r);
    p0 = v3_add(entry->p, v3_add(v3_mul(v3_add(v3_mul(a1, cosf(phi)), v3_mul(a2, sinf(phi))), r),
                                 v3_mul(axis, -0.5f * l)));
    p1 = v3_add(p0, v3_mul(axis, l));
    /* every surface of material mi along p0 -> p1; one kept uniformly (reservoir) */
    rng_seed(&rng, hash_u64((uint64_t)(u[3] * 4294967296.0), 0x535353u), 0);
    ray.o = p0;
    ray.d = v3_sub(p1, p0);
    ray.tmax = 1.0f;
    while (out->rays < SSS_PROBE_HITS) {
        HitRecord h;
        SurfacePoint sp;
        out->rays++;
        if (!bvh_intersect(&s->bvh, s, &ray, &h)) break;
        scene_surface_point(s, &ray, &h, &sp);
        if (s->shapes[sp.shape].material == mi) {
            out->n++;
            if (rng_float(&rng) * (float)out->n < 1.0f) { out->sp = sp; out->hit = h; }
        }
        ray.o = spawn_origin(&sp, ray.d);
        ray.d = v3_sub(p1, ray.o);
        if (v3_dot(ray.d, axis) <= 0.0f) break;              /* past p1 */
    }
    if (out->n == 0) return 0;
    for (j = 0; j < HERO_N; j++) {
        if (!(alive & (1u << j))) continue;
        out->Sp[j] = bssrdf_sr(t, st[j], rho[j], v3_len(v3_sub(out->sp.p, entry->p)));
        out->pdf[j] = pdf_sp(t, st[j], rho[j], &fr, entry->p, out->sp.p, out->sp.ng) / (float)out->n;
        if (out->Sp[j] > 0.0f) any = 1;
    }
    return any && out->pdf[0] > 0.0f;
}

/* ------------------------------------------------------------ the exit lobe Sw (44) */

static float sw_value(float eta, float cos_i)
{
    float c = 1.0f - 2.0f * (float)fresnel_moment1(1.0 / eta);
    return eta * eta * (1.0f - fresnel_dielectric(cos_i, eta)) / (c * PI_F);
}

void sss_exit_eval(const Material *m, const SurfacePoint *sp, Vec3 wi, unsigned alive,
                   float f[HERO_N], float pdf_l[HERO_N])
{
    float c = v3_dot(wi, sp->ns), v;
    int j;
    for (j = 0; j < HERO_N; j++) f[j] = pdf_l[j] = 0.0f;
    if (!(c > 0.0f)) return;                                /* only the outer side */
    v = sw_value(m->sss->eta, c);
    for (j = 0; j < HERO_N; j++) {
        pdf_l[j] = c / PI_F;
        if (alive & (1u << j)) f[j] = v;
    }
}

int sss_exit_sample(const Material *m, const SurfacePoint *sp, unsigned alive, float u1, float u2,
                    BsdfSample *out)
{
    Frame fr = frame_from_normal(sp->ns);
    float r = sqrtf(u1), phi = 2.0f * PI_F * u2, e2 = m->sss->eta * m->sss->eta;
    int j;
    memset(out, 0, sizeof *out);
    out->wi = frame_to_world(&fr, v3(r * cosf(phi), r * sinf(phi), sqrtf(fmaxf(0.0f, 1.0f - u1))));
    sss_exit_eval(m, sp, out->wi, alive, out->f, out->pdf_l);
    out->pdf = out->pdf_l[0];
    for (j = 0; j < HERO_N; j++) out->eta2[j] = 1.0f / e2;   /* beta regains eta^2 */
    return out->pdf > 0.0f;
}

/* ------------------------------------------------------------ from scene parameters */

/* A spectrum or texture parameter `name`: *tex = 1 + the texture's index, or the
   spectrum in *s (use: its pbrt-v4 type), or def when absent.  *given: present. */
static int sss_param(Parser *P, ParamList *pl, const char *name, SpecUse use, Spectrum *s,
                     int *tex, int *given)
{
    Param *pt = param_find(pl, PT_TEXTURE, name), *ps = find_spectrum_param(pl, name);
    *given = pt || ps;
    if (pt) {
        int ti = texture_lookup(P, pt, 0);
        if (ti < 0) return 0;
        *tex = ti + 1;
        return 1;
    }
    if (ps) {
        int nm;
        if (!param_spectrum(P, ps, use, s, NULL)) return 0;
        for (nm = SPEC_MIN; nm <= SPEC_MAX; nm++)
            if (!(spec_get(s, nm) >= 0.0f && spec_get(s, nm) < 1e30f))
                return fail(P, ps->file, ps->line, "\"%s %s\": value %g at %d nm must be >= 0",
                            param_type_names[ps->type], name, spec_get(s, nm), nm);
        if (!strcmp(name, "mfp"))
            for (nm = SPEC_MIN; nm <= SPEC_MAX; nm++)
                if (!(spec_get(s, nm) > 0.0f))
                    return fail(P, ps->file, ps->line, "\"%s mfp\": value 0 at %d nm: a mean free "
                                "path must be > 0", param_type_names[ps->type], nm);
    }
    return 1;
}

/* The coefficients: by name, sigma_a and sigma_s, reflectance and mfp, or pbrt-v4's
   defaults (whole milk's, per mm), in that order of precedence. */
static int sss_coefficients(Parser *P, ParamList *pl, const char *file, int line, const char *dir,
                            Material *m, float *g)
{
    Subsurface *ss = m->sss;
    const char *name = NULL;
    int ga, gs, gr, gm;
    float sa[3] = { 0.0011f, 0.0024f, 0.014f }, sc[3] = { 2.55f, 3.21f, 3.77f };
    Spectrum r;                     /* "reflectance", shared (albedo_set_table) */
    if (!get_string(P, pl, "name", &name)) return 0;
    if (name && *name) {
        Param *pg = param_find(pl, PT_FLOAT, "g");
        if (!medium_preset(name, sa, sc))
            return fail(P, file, line, "%s \"subsurface\": \"string name\" \"%s\": no such named "
                        "medium (pbrt-v4's names, e.g. \"Skin1\", \"Ketchup\", \"Wholemilk\")",
                        dir, name);
        if (pg && *g != 0.0f)
            fprintf(stderr, "%s:%d: note: \"float g\" %g ignored with named scattering "
                    "coefficients (reduced ones, g = 0), as pbrt-v4 does\n", pg->file, pg->line, *g);
        *g = 0.0f;
        return spec_from_rgb_t(rgb_srgb_table(P), &ss->sigma_a, sa, 2, P->err, file, line) &&
               spec_from_rgb_t(rgb_srgb_table(P), &ss->sigma_s, sc, 2, P->err, file, line);
    }
    if (!sss_param(P, pl, "sigma_a", SPEC_COEFF, &ss->sigma_a, &ss->tex[SSS_TEX_SIGMA_A], &ga) ||
        !sss_param(P, pl, "sigma_s", SPEC_COEFF, &ss->sigma_s, &ss->tex[SSS_TEX_SIGMA_S], &gs))
        return 0;
    if (ga != gs)
        return fail(P, file, line, "%s \"subsurface\": \"sigma_%s\" given without \"sigma_%s\"",
                    dir, ga ? "a" : "s", ga ? "s" : "a");
    if (ga) return 1;
    if (!sss_param(P, pl, "reflectance", SPEC_ALBEDO, &r, &m->reflectance_tex, &gr))
        return 0;
    if (gr) {
        if (!m->reflectance_tex && !albedo_set_table(P, &m->reflectance, &r, file, line)) return 0;
        spec_const(&ss->mfp, 1.0f);
        ss->from_albedo = 1;
        return sss_param(P, pl, "mfp", SPEC_COEFF, &ss->mfp, &ss->tex[SSS_TEX_MFP], &gm);
    }
    return spec_from_rgb_t(rgb_srgb_table(P), &ss->sigma_a, sa, 2, P->err, file, line) &&
           spec_from_rgb_t(rgb_srgb_table(P), &ss->sigma_s, sc, 2, P->err, file, line);
}

/* The table for ss's (g, eta): a copy of an earlier subsurface material's with the
   same pair (a build takes about 50 ms), else built. */
static void sss_table(Parser *P, Subsurface *ss)
{
    int k;
    for (k = 0; k < P->s->n_materials; k++) {
        const Material *o = &P->s->materials[k];
        if (o->type == MAT_SUBSURFACE && o->sss->g == ss->g && o->sss->eta == ss->eta) {
            ss->table = o->sss->table;
            return;
        }
    }
    bssrdf_table_build(&ss->table, ss->g, ss->eta);
}

int subsurface_from_params(Parser *P, ParamList *pl, const char *file, int line, const char *dir,
                           const char *what, Material *m)
{
    Subsurface *ss = (Subsurface *)calloc(1, sizeof *ss);
    float g;
    Spectrum ior;
    m->type = MAT_SUBSURFACE;
    m->sss = ss;
    if (!ss) return oom(P, file, line);
    if (!get_float(P, pl, "g", 0.0f, &g) || !sss_coefficients(P, pl, file, line, dir, m, &g) ||
        !get_float(P, pl, "scale", 1.0f, &ss->scale) || !get_float(P, pl, "eta", 1.33f, &ss->eta))
        return 0;
    /* the boundary's roughness per axis (u along the shading frame's s, v along
       t): numbers, or textures read at each hit (parser.c microfacet_alphas) */
    if (!microfacet_alphas(P, pl, file, line, what, m)) return 0;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "string name, float g, spectrum sigma_a, rgb sigma_a, "
                             "texture sigma_a, spectrum sigma_s, rgb sigma_s, texture sigma_s, "
                             "spectrum reflectance, rgb reflectance, texture reflectance, "
                             "spectrum mfp, rgb mfp, texture mfp, float scale, float eta, "
                             "float roughness, float uroughness, float vroughness, "
                             "texture roughness, texture uroughness, texture vroughness, "
                             "bool remaproughness", NULL))
        return 0;
    if (!(ss->scale >= 0.0f && ss->scale < 1e30f))
        return fail(P, file, line, "%s \"subsurface\": \"float scale\" %g must be >= 0", dir, ss->scale);
    if (!(ss->eta > 0.0f && ss->eta < 100.0f))
        return fail(P, file, line, "%s \"subsurface\": \"float eta\" %g must be > 0", dir, ss->eta);
    if (!(g > -1.0f && g < 1.0f))
        return fail(P, file, line, "%s \"subsurface\": \"float g\" %g must be in (-1, 1)", dir, g);
    ss->g = g;
    if (m->alpha_tex <= 0 && m->alpha_t_tex <= 0 && tr_smooth(m->alpha, m->alpha_t))
        m->alpha = m->alpha_t = 0.0f;                  /* pbrt-v4's EffectivelySmooth */
    sss_table(P, ss);
    spec_const(&ior, ss->eta);
    return material_set_eta(P, m, &ior, file, line);
}
