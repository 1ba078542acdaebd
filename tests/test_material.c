/* tests/test_material.c - Fresnel, Cauchy, the prism, and the rough dielectric's
   sampler against its pdf (normalisation, chi-square, energy estimates, the pdf
   of one lobe). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static void test_cauchy_bk7(T *t)
{
    float n = cauchy_eta(1.5046f, 0.00420f, 587.6f);
    CHECK(t, fabsf(n - 1.5168f) < 1e-3f, "n_BK7(587.6 nm) = %.5f, catalogue 1.5168", n);
    CHECK(t, cauchy_eta(1.5046f, 0.0042f, 450) > cauchy_eta(1.5046f, 0.0042f, 650),
          "normal dispersion: blue bends more");
}

static void test_fresnel_values(T *t)
{
    float eta = 1.5f, r0 = (eta - 1) / (eta + 1), brewster = atanf(eta);
    float rb = fresnel_dielectric(cosf(brewster), eta);
    /* at Brewster's angle r_par = 0, so F = r_perp^2 / 2 */
    float ct = cosf(asinf(sinf(brewster) / eta));
    float rperp = (cosf(brewster) - eta * ct) / (cosf(brewster) + eta * ct);
    CHECK(t, fabsf(fresnel_dielectric(1.0f, eta) - r0 * r0) < 1e-6f, "normal incidence");
    CHECK(t, fabsf(rb - 0.5f * rperp * rperp) < 1e-5f, "Brewster: %g vs %g", rb, 0.5f * rperp * rperp);
    CHECK(t, fresnel_dielectric(-0.3f, eta) == 1.0f, "TIR from inside at 72.5 deg");
    CHECK(t, fabsf(fresnel_dielectric(-1.0f, eta) - r0 * r0) < 1e-6f, "inside, normal incidence");
}

/* Smooth glass is lossless: the sampled weight f|cos|/p is 1 for reflection and
   1/eta'^2 for transmission; with eta'^2 undone the mean must be exactly 1
   (R + T = 1), and the reflect fraction must be F (4 sigma binomial bound). */
static void test_smooth_energy(T *t)
{
    Material m;
    SurfacePoint sp = test_flat_point();
    float lam[HERO_N] = { 550, 600, 650, 450 };
    Rng r;
    int i, n = 20000, nr = 0;
    double F, sigma;
    Vec3 wo = v3_norm(v3(0.6f, 0.0f, 0.8f));
    test_glass(&m, 1.5f, 0.0f, 0.0f);
    rng_seed(&r, 3, 3);
    F = fresnel_dielectric(wo.z, 1.5f);
    for (i = 0; i < n; i++) {
        BsdfSample bs;
        double w;
        CHECK(t, test_bsdf_sample(&m, &sp, wo, lam, 15u, &r, &bs),
              "smooth glass failed to sample");
        w = bs.f[0] * fabsf(bs.wi.z) / bs.pdf;
        if (bs.wi.z > 0) { nr++; CHECK(t, fabs(w - 1.0) < 1e-5, "reflection weight %g", w); }
        else CHECK(t, fabs(w * 1.5 * 1.5 - 1.0) < 1e-5, "transmission weight %g x eta^2", w);
        CHECK(t, bs.delta && bs.f[3] == bs.f[0], "non-dispersive glass: all wavelengths equal");
    }
    sigma = sqrt(F * (1 - F) / n);
    CHECK(t, fabs((double)nr / n - F) < 4 * sigma, "reflect fraction %g vs F %g", (double)nr / n, F);
}

/* BsdfSample.eta2, what the roulette multiplies beta by (THEORY §8): etap_j^2 for a
   refraction (eta_j^2 entering, 1/eta_j^2 leaving), 1 for a reflection.  Smooth
   glass of index 3, from outside and inside: f|cos|/p x eta2 is exactly 1 (no
   loss), for every lane.  Rough dispersive glass: eta2 per lane with that lane's
   index, and the hero's f|cos|/p x eta2 is the microfacet weight G2/G1, in (0, 1]. */
static void test_eta2_of_refractions(T *t)
{
    static const float alphas[2] = { 0.0f, 0.3f };
    float lam[HERO_N] = { 550, 600, 650, 450 };
    SurfacePoint sp = test_flat_point();
    Rng r;
    int ia, side, i, j, nt = 0;
    rng_seed(&r, 5, 3);
    for (ia = 0; ia < 2; ia++)
        for (side = 0; side < 2; side++) {
            Material m;
            Vec3 wo = v3_norm(v3(0.3f, 0.1f, side ? -0.9f : 0.9f));
            test_glass(&m, 3.0f, ia ? 0.05f : 0.0f, alphas[ia]);
            for (i = 0; i < 4000; i++) {
                BsdfSample bs;
                int refr;
                if (!test_bsdf_sample(&m, &sp, wo, lam, 15u, &r, &bs)) continue;
                refr = bs.wi.z * wo.z < 0.0f;
                nt += refr;
                for (j = 0; j < HERO_N; j++) {
                    float eta = mat_eta(&m, lam[j]);
                    float want = !refr ? 1.0f : side ? 1.0f / (eta * eta) : eta * eta;
                    double w = bs.f[j] * fabsf(bs.wi.z) / bs.pdf * bs.eta2[j];
                    CHECK(t, fabsf(bs.eta2[j] - want) <= 1e-5f * want,
                          "alpha %g side %d lane %d: eta2 %g, expected %g", alphas[ia], side, j,
                          bs.eta2[j], want);
                    if (!ia) CHECK(t, fabs(w - 1.0) < 1e-5, "smooth side %d lane %d: f|cos|/p x eta2 = %g",
                                   side, j, w);
                    else if (j == 0) CHECK(t, w > 0.0 && w <= 1.0 + 1e-4, "rough side %d: f|cos|/p x eta2 = %g",
                                           side, w);
                }
            }
        }
    CHECK(t, nt > 4000, "only %d refractions", nt);
}

/* A 60-degree prism in air: the deviation for a ray at incidence theta1 follows
   Snell twice.  Trace it with refract_dir and compare with the closed form. */
static double prism_deviation(float eta, float theta1)
{
    /* face 1 normal (outward) and face 2 normal, apex angle 60 deg, in the xy plane */
    double A = SPECNEE_PI / 3.0;
    double t2 = asin(sin(theta1) / eta), t3 = A - t2, t4 = asin(eta * sin(t3));
    return theta1 + t4 - A;
}

static void test_prism_deviation(T *t)
{
    float lambdas[2] = { 450.0f, 650.0f }, theta1 = 50.0f * PI_F / 180.0f;
    int k;
    for (k = 0; k < 2; k++) {
        float eta = cauchy_eta(1.5046f, 0.0042f, lambdas[k]), etap;
        /* face 1 has outward normal (-1, 0, 0); face 2's outward normal points at
           -60 degrees, so the faces meet at the 60 degree apex */
        Vec3 n1 = v3(-1, 0, 0), n2 = v3(cosf(PI_F / 3), -sinf(PI_F / 3), 0), d, w_in, w_out;
        double dev, expect = prism_deviation(eta, theta1);
        /* incoming direction hits face 1 at theta1 from the normal, going +x */
        d = v3(cosf(theta1), -sinf(theta1), 0);
        CHECK(t, refract_dir(v3_neg(d), n1, eta, &etap, &w_in), "refraction at face 1");
        CHECK(t, fabsf(etap - eta) < 1e-6f, "entering glass: eta' = eta");
        /* leaving the glass: w is on the inside, so refract_dir flips n2 and eta */
        CHECK(t, refract_dir(v3_neg(w_in), n2, eta, &etap, &w_out), "refraction at face 2");
        CHECK(t, fabsf(etap - 1.0f / eta) < 1e-6f, "leaving glass: eta' = 1/eta");
        dev = acos(v3_dot(v3_norm(d), v3_norm(w_out)));
        CHECK(t, fabs(dev - expect) < 1e-4, "deviation at %g nm: %g rad, Snell %g", lambdas[k], dev, expect);
    }
    CHECK(t, prism_deviation(cauchy_eta(1.5046f, 0.0042f, 450), theta1) >
             prism_deviation(cauchy_eta(1.5046f, 0.0042f, 650), theta1), "blue deviates more");
}

/* Uniform sphere direction from two numbers. */
static Vec3 sphere_dir(float u1, float u2)
{
    float z = 1 - 2 * u1, r = sqrtf(fmaxf(0, 1 - z * z)), phi = 2 * PI_F * u2;
    return v3(r * cosf(phi), r * sinf(phi), z);
}

/* For alpha in {0.05, 0.3} and wo outside and inside:
   (a) int p dw (uniform-sphere MC) = the fraction of successful samples;
   (b) E[f|cos|/p] over samples = int f|cos| dw (uniform-sphere MC);
   (c) pdf returned by the sampler = pdf evaluated by bsdf_eval (a consistency
       check only: both come from rough_eval; the pdf and the sampling density are
       checked against independent formulas in tests/test_physics.c).
   The bounds are 4 standard errors of the MC estimates plus 1%. */
static void test_rough_pdf_and_energy(T *t)
{
    float alphas[2] = { 0.05f, 0.3f }, lam[HERO_N] = { 550, 550, 550, 550 };
    Vec3 wos[2];
    int ia, io, i;
    wos[0] = v3_norm(v3(0.5f, 0.1f, 0.8f));
    wos[1] = v3_norm(v3(-0.3f, 0.2f, -0.9f));
    for (ia = 0; ia < 2; ia++)
        for (io = 0; io < 2; io++) {
            Material m;
            SurfacePoint sp = test_flat_point();
            Rng r;
            int n_s = 200000, n_u = 400000, ok = 0;
            double sum_w = 0, sum_w2 = 0, ip = 0, ip2 = 0, fi = 0, fi2 = 0, mean, se, frac;
            Vec3 wo = wos[io];
            test_glass(&m, 1.5f, 0.0f, alphas[ia]);
            rng_seed(&r, 11, (uint64_t)(ia * 2 + io));
            for (i = 0; i < n_s; i++) {
                BsdfSample bs;
                float f[HERO_N], p[HERO_N];
                if (!test_bsdf_sample(&m, &sp, wo, lam, 1u, &r, &bs))
                    continue;
                ok++;
                {
                    double w = bs.f[0] * fabsf(bs.wi.z) / bs.pdf;
                    sum_w += w; sum_w2 += w * w;
                }
                if (i < 2000) {
                    bsdf_eval(&m, &sp, wo, bs.wi, lam, 1u, f, p);
                    CHECK(t, fabsf(p[0] - bs.pdf) <= 1e-3f * bs.pdf + 1e-6f,
                          "sampled pdf %g != evaluated pdf %g", bs.pdf, p[0]);
                }
            }
            for (i = 0; i < n_u; i++) {
                const float u1 = rng_float(&r), u2 = rng_float(&r);   /* in this order */
                Vec3 wi = sphere_dir(u1, u2);
                float f[HERO_N], p[HERO_N];
                double a, b;
                bsdf_eval(&m, &sp, wo, wi, lam, 1u, f, p);
                a = p[0] * 4 * SPECNEE_PI;
                b = f[0] * fabsf(wi.z) * 4 * SPECNEE_PI;
                ip += a; ip2 += a * a; fi += b; fi2 += b * b;
            }
            frac = (double)ok / n_s;
            mean = ip / n_u;
            se = sqrt((ip2 / n_u - mean * mean) / n_u);
            CHECK(t, fabs(mean - frac) < 4 * se + 0.01,
                  "alpha %g wo %d: int p = %g +- %g, but %g of the samples succeed", alphas[ia], io, mean, se, frac);
            {
                double est = sum_w / n_s, est_se = sqrt((sum_w2 / n_s - (sum_w / n_s) * (sum_w / n_s)) / n_s);
                double q = fi / n_u, q_se = sqrt((fi2 / n_u - q * q) / n_u);
                CHECK(t, fabs(est - q) < 4 * sqrt(est_se * est_se + q_se * q_se) + 0.01 * q,
                      "alpha %g wo %d: E[f cos/p] = %g +- %g, quadrature %g +- %g",
                      alphas[ia], io, est, est_se, q, q_se);
            }
        }
}

/* Chi-square test of the sampled directions against the pdf on a 16 x 32
   (cos theta, phi) grid over the sphere (test_bsdf_dirs: expected counts integrate
   the pdf over each cell, cells expecting < 5 merged).
   (Narrower lobes, alpha = 0.05, are checked by the energy test above: on this grid
   their expected counts cannot be integrated accurately enough for a chi-square.) */
static void test_rough_chi2(T *t)
{
    float alphas[2] = { 0.3f, 0.6f };
    int ia;
    for (ia = 0; ia < 2; ia++) {
        Material m;
        BsdfDirs b = { 0 };
        DirTest d;
        Rng r;
        Chi2 c;
        b.m = &m;
        b.sp = test_flat_point();
        b.wo = v3_norm(v3(0.4f, 0.0f, 0.7f));
        b.lambda[0] = b.lambda[1] = b.lambda[2] = b.lambda[3] = 550;
        test_glass(&m, 1.5f, 0.0f, alphas[ia]);
        rng_seed(&r, 5, (uint64_t)ia);
        d = test_bsdf_dirs(&b, 200000);
        CHECK_CHI2_DIRS(t, &d, &r, 2, &c, "alpha %g", alphas[ia]);
    }
}

/* Dispersion: the hero picks the direction; other wavelengths get their own f and
   pdf for it, and they differ when B > 0. */
static void test_rough_dispersion_per_wavelength(T *t)
{
    Material m;
    SurfacePoint sp = test_flat_point();
    float lam[HERO_N] = { 450, 525, 600, 675 };
    Rng r;
    int i, differ = 0;
    Vec3 wo = v3_norm(v3(0.3f, 0.0f, 0.9f));
    test_glass(&m, 1.5f, 0.02f, 0.3f);
    rng_seed(&r, 9, 9);
    for (i = 0; i < 100; i++) {
        BsdfSample bs;
        float f[HERO_N], p[HERO_N];
        int j;
        if (!test_bsdf_sample(&m, &sp, wo, lam, 15u, &r, &bs)) continue;
        if (bs.wi.z > 0) continue;
        bsdf_eval(&m, &sp, wo, bs.wi, lam, 15u, f, p);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, fabsf(p[j] - bs.pdf_l[j]) <= 1e-3f * p[j] + 1e-6f && fabsf(f[j] - bs.f[j]) <= 1e-3f * f[j] + 1e-6f,
                  "wavelength %d: sample and eval disagree", j);
        if (fabsf(bs.pdf_l[3] - bs.pdf_l[0]) > 1e-3f * bs.pdf_l[0]) differ++;
    }
    CHECK(t, differ > 10, "dispersive rough glass: per-wavelength pdfs should differ (%d)", differ);
}

/* microfacet.c's tr_dielectric_pair restricted to one lobe (layered.c asks for the
   transmission alone when it weights a walk's exit): f does not depend on the
   lobes, and the pdf is the two-lobe pdf divided by that lobe's probability, F for
   a reflection pair and 1 - F for a transmission pair (0 for the other lobe). */
static void test_dielectric_lobes(T *t)
{
    Rng rng;
    int k, n = 0;
    rng_seed(&rng, 11, 3);
    for (k = 0; k < 2000; k++) {
        float a = 0.05f + 0.6f * rng_float(&rng), eta = 1.2f + rng_float(&rng), etap, F;
        float fb, pb, fr, pr, ft, pt;
        Vec3 wo = equal_area_square_to_sphere(rng_float(&rng), rng_float(&rng));
        Vec3 wi = equal_area_square_to_sphere(rng_float(&rng), rng_float(&rng)), wm;
        int reflect = wo.z * wi.z > 0.0f;
        tr_dielectric_pair(a, eta, wo, wi, LOBE_R | LOBE_T, &fb, &pb);
        tr_dielectric_pair(a, eta, wo, wi, LOBE_R, &fr, &pr);
        tr_dielectric_pair(a, eta, wo, wi, LOBE_T, &ft, &pt);
        CHECK(t, fr == fb && ft == fb, "f depends on the lobes: %g %g %g", fb, fr, ft);
        if (!(pb > 0.0f)) continue;
        etap = reflect ? 1.0f : wo.z > 0.0f ? eta : 1.0f / eta;
        wm = v3_norm(v3_add(v3_mul(wi, etap), wo));
        if (wm.z < 0.0f) wm = v3_neg(wm);                 /* as the pair turns it */
        F = fresnel_dielectric(v3_dot(wo, wm), eta);
        if (reflect)
            CHECK(t, fabsf(pr * F - pb) <= 1e-4f * pb && pt == 0.0f,
                  "reflection pair: p_R %g F %g p %g p_T %g", pr, F, pb, pt);
        else
            CHECK(t, fabsf(pt * (1.0f - F) - pb) <= 1e-4f * pb && pr == 0.0f,
                  "transmission pair: p_T %g 1-F %g p %g p_R %g", pt, 1.0f - F, pb, pr);
        n++;
    }
    CHECK(t, n > 500, "only %d pairs with a pdf", n);
}

const TestCase tests_material[] = {
    { "material_cauchy_bk7", test_cauchy_bk7 },
    { "material_fresnel_values", test_fresnel_values },
    { "material_smooth_energy", test_smooth_energy },
    { "material_eta2_of_refractions", test_eta2_of_refractions },
    { "material_prism_deviation", test_prism_deviation },
    { "material_rough_pdf_and_energy", test_rough_pdf_and_energy },
    { "material_rough_chi2", test_rough_chi2 },
    { "material_rough_dispersion_per_wavelength", test_rough_dispersion_per_wavelength },
    { "material_dielectric_lobes", test_dielectric_lobes },
    { NULL, NULL }
};
