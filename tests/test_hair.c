/* tests/test_hair.c - pbrt-v4's "hair" material (hair.c: hair_sample, hair_eval,
   hair_from_params; THEORY §16).

   Checked: the white furnace (sigma_a = 0: the integral of f |cos| over the
   sphere is 1, for several wo, h, beta_m, beta_n, alpha and eta), the pdf
   integrating to 1 and the sampler against it (chi-square), a black fibre's
   albedo (the Fresnel reflectance) and tilted R lobe, the sample's f and
   pdf equal to the evaluation's at its direction, reciprocity where the model has
   it (no tilt, h = 0, theta_i = theta_o), log I0 against its series, the
   reflectance-to-sigma_a conversion and its inverse, the melanin spectra and
   pbrt-v4's precedence and defaults, the refusals at their file:line, and
   pbrt-v4's image of four hair surfaces (sigma_a, melanins, reflectance, the
   default) on spheres and a bilinear patch. */
#include "test.h"
#include "../parser.h"
#include <stdlib.h>
#include <string.h>

/* A hair material of constant sigma_a built by hand (H: the caller's storage). */
static Material hair_material(Hair *H, float sigma_a, float eta, float bm, float bn, float alpha)
{
    Material m;
    memset(&m, 0, sizeof m);
    memset(H, 0, sizeof *H);
    m.type = MAT_HAIR;
    m.hair = H;
    m.eta = test_eta_const(1.0f);
    spec_const(&H->sigma_a, sigma_a);
    H->eta = eta;
    H->beta_m = bm;
    H->beta_n = bn;
    H->alpha = alpha;
    return m;
}

/* A point with n = +z, the fibre along +x and offset h. */
static SurfacePoint hair_point(float h)
{
    SurfacePoint sp = test_flat_point();
    sp.dpdu = v3(1, 0, 0);
    sp.v = (h + 1.0f) / 2.0f;
    return sp;
}

static Vec3 hair_dir(double sin_t, double phi)
{
    double c = sqrt(fmax(0.0, 1.0 - sin_t * sin_t));
    return v3((float)sin_t, (float)(c * cos(phi)), (float)(c * sin(phi)));
}

/* The integrals over the sphere of f |cos| (hero lane) and of the pdf, by the
   midpoint rule on an n x 2n grid in (sin theta, phi) (dw = dsin dphi), jittered
   by r. */
static void sphere_integrals(const Material *m, const SurfacePoint *sp, Vec3 wo, int n, Rng *r,
                             double *fint, double *pint)
{
    static const float lambda[HERO_N] = { 550.0f, 450.0f, 650.0f, 500.0f };
    double du = 2.0 / n, dp = 2.0 * SPECNEE_PI / (2 * n), sf = 0.0, sp_ = 0.0;
    int i, k;
    for (i = 0; i < n; i++)
        for (k = 0; k < 2 * n; k++) {
            float u[2], f[HERO_N], pdf[HERO_N];
            Vec3 wi;
            rng_fill(r, u, 2);
            wi = hair_dir(-1.0 + (i + u[0]) * du, (k + u[1]) * dp);
            bsdf_eval(m, sp, wo, wi, lambda, 1u, f, pdf);
            sf += (double)f[0] * fabs(wi.z);
            sp_ += pdf[0];
        }
    *fint = sf * du * dp;
    *pint = sp_ * du * dp;
}

/* sigma_a = 0: integral f |cos| = sum A_p = 1 and integral pdf = 1 (the paper's
   white furnace, Chiang et al. 2016 section 4.1), for wo at several longitudinal
   angles and azimuths, offsets h and roughnesses. */
static void test_hair_furnace(T *t)
{
    static const float cases[][5] = {    /* beta_m, beta_n, alpha, eta, h */
        { 0.3f, 0.3f, 2.0f, 1.55f, 0.0f }, { 0.1f, 0.2f, 2.0f, 1.55f, 0.5f },
        { 0.6f, 0.8f, 5.0f, 1.3f, -0.9f }, { 1.0f, 1.0f, 0.0f, 1.55f, 0.95f },
        { 0.2f, 0.5f, -3.0f, 2.0f, -0.3f },
    };
    static const double wos[][2] = { { 0.0, 0.4 }, { 0.5, 1.9 }, { -0.8, -2.5 }, { 0.95, 3.0 } };
    Rng r;
    int c, w;
    rng_seed(&r, 36, 1);
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++)
        for (w = 0; w < 4; w++) {
            Hair H;
            Material m = hair_material(&H, 0.0f, cases[c][3], cases[c][0], cases[c][1], cases[c][2]);
            SurfacePoint sp = hair_point(cases[c][4]);
            double fi, pi;
            sphere_integrals(&m, &sp, hair_dir(wos[w][0], wos[w][1]), 400, &r, &fi, &pi);
            if (getenv("DBG")) fprintf(stderr, "furnace %d %d: %.6f %.6f\n", c, w, fi, pi);
            CHECK(t, fabs(fi - 1.0) < 3e-3, "case %d wo %d: integral of f |cos| %.5f, want 1", c, w, fi);
            CHECK(t, fabs(pi - 1.0) < 3e-3, "case %d wo %d: integral of the pdf %.5f, want 1", c, w, pi);
        }
}

/* With absorption the integral is sum A_p < 1, and the darker the less. */
static void test_hair_absorbs(T *t)
{
    Hair H;
    Rng r;
    double prev = 1.0, fi, pi;
    float sa;
    rng_seed(&r, 36, 2);
    for (sa = 0.25f; sa < 5.0f; sa *= 2.0f) {
        Material m = hair_material(&H, sa, 1.55f, 0.3f, 0.3f, 2.0f);
        SurfacePoint sp = hair_point(0.3f);
        sphere_integrals(&m, &sp, hair_dir(0.2, 0.7), 200, &r, &fi, &pi);
        CHECK(t, fi < prev && fi > 0.02, "sigma_a %g: albedo %.4f after %.4f", sa, fi, prev);
        CHECK(t, fabs(pi - 1.0) < 5e-3, "sigma_a %g: integral of the pdf %.5f", sa, pi);
        prev = fi;
    }
}

/* The unpolarised Fresnel reflectance of a dielectric of index eta at cos c (from
   outside), in double, for the black fibre below. */
static double fresnel_ref(double c, double eta)
{
    double s2 = (1.0 - c * c) / (eta * eta), ct, rs, rp;
    if (s2 >= 1.0) return 1.0;
    ct = sqrt(1.0 - s2);
    rs = (c - eta * ct) / (c + eta * ct);
    rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* A black fibre (sigma_a huge: T = 0) reflects only at its surface, A_0 = F at
   cos theta_o cos gamma_o (33), in the R lobe (30) around the cone theta_i =
   2 alpha - theta_o (34): integral f |cos| = F, and the lobe's mean sin theta_i is
   that of a von Mises-Fisher lobe of concentration 1/v_0 about it,
   (coth(1/v_0) - v_0) sin(2 alpha - theta_o). */
static void test_hair_black_fibre(T *t)
{
    static const float cases[][3] = {   /* h, sin theta_o, alpha */
        { 0.0f, 0.0f, 5.0f }, { 0.5f, 0.4f, 3.0f }, { -0.8f, -0.7f, 6.0f }, { 0.9f, 0.2f, -4.0f },
    };
    static const float lambda[HERO_N] = { 550.0f, 450.0f, 650.0f, 500.0f };
    int c, i, k, n = 400;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
        Hair H;
        Material m = hair_material(&H, 1e4f, 1.55f, 0.3f, 0.3f, cases[c][2]);
        SurfacePoint sp = hair_point(cases[c][0]);
        double so = cases[c][1], to = asin(so), bm = 0.3, v0, a, I = 0.0, S = 0.0, du = 2.0 / n,
               dp = SPECNEE_PI / n, F, mean;
        Vec3 wo = hair_dir(so, 0.8);
        for (i = 0; i < n; i++)
            for (k = 0; k < 2 * n; k++) {
                float f[HERO_N], pdf[HERO_N];
                Vec3 wi = hair_dir(-1.0 + (i + 0.5) * du, (k + 0.5) * dp);
                bsdf_eval(&m, &sp, wo, wi, lambda, 1u, f, pdf);
                I += (double)f[0] * fabs(wi.z);
                S += (double)f[0] * fabs(wi.z) * wi.x;
            }
        I *= du * dp;
        S *= du * dp;
        F = fresnel_ref(cos(to) * sqrt(1.0 - (double)cases[c][0] * cases[c][0]), 1.55);
        v0 = 0.726 * bm + 0.812 * bm * bm + 3.7 * pow(bm, 20.0);
        v0 *= v0;
        a = cases[c][2] * SPECNEE_PI / 180.0;
        mean = (1.0 / tanh(1.0 / v0) - v0) * sin(2.0 * a - to);
        CHECK(t, fabs(I - F) < 2e-3 * F, "case %d: integral of f |cos| %.6f, Fresnel %.6f", c, I, F);
        CHECK(t, fabs(S / I - mean) < 2e-3, "case %d: mean sin theta_i %.5f, want %.5f", c, S / I, mean);
    }
}

/* The sampler follows the pdf (chi-square on a 16 x 32 grid of directions), for
   several wo, h and roughnesses. */
static void test_hair_chi2(T *t)
{
    static const float cases[][6] = {   /* beta_m, beta_n, alpha, sigma_a, h, sin theta_o */
        { 0.3f, 0.3f, 2.0f, 0.0f, 0.0f, 0.3f }, { 0.5f, 0.4f, 4.0f, 0.5f, 0.6f, -0.5f },
        { 0.8f, 0.9f, 0.0f, 2.0f, -0.8f, 0.8f }, { 0.25f, 0.6f, -2.0f, 0.2f, 0.3f, 0.0f },
    };
    int c, n = (int)(sizeof cases / sizeof cases[0]);
    Rng r;
    rng_seed(&r, 36, 3);
    for (c = 0; c < n; c++) {
        Hair H;
        Material m = hair_material(&H, cases[c][3], 1.55f, cases[c][0], cases[c][1], cases[c][2]);
        BsdfDirs b;
        DirTest d;
        b.m = &m;
        b.sp = hair_point(cases[c][4]);
        b.wo = hair_dir(cases[c][5], 1.1);
        b.lambda[0] = 550.0f; b.lambda[1] = 450.0f; b.lambda[2] = 650.0f; b.lambda[3] = 500.0f;
        d = test_bsdf_dirs(&b, test_scaled(400000, 50000));
        CHECK_CHI2_DIRS(t, &d, &r, n, NULL, "hair case %d", c);
    }
}

/* bsdf_sample's f and pdf are bsdf_eval's at the sampled direction, for every
   wavelength (its pdf_l the same for all: the lobe choice averages them). */
static void test_hair_sample_eval(T *t)
{
    static const float lambda[HERO_N] = { 620.0f, 410.0f, 530.0f, 700.0f };
    Hair H;
    Material m = hair_material(&H, 0.0f, 1.55f, 0.4f, 0.3f, 3.0f);
    Rng r;
    int i, j, n_ok = 0;
    rng_seed(&r, 36, 4);
    spec_named(&H.sigma_a, "stdillum-D65");       /* any spectrum that varies */
    for (i = 0; i < 2000; i++) {
        SurfacePoint sp = hair_point(2.0f * rng_float(&r) - 1.0f);
        float u[2], f[HERO_N], pdf[HERO_N];
        Vec3 wo;
        BsdfSample bs;
        rng_fill(&r, u, 2);
        wo = hair_dir(1.98 * u[0] - 0.99, 2.0 * SPECNEE_PI * u[1]);
        if (!test_bsdf_sample(&m, &sp, wo, lambda, 15u, &r, &bs)) continue;
        n_ok++;
        CHECK(t, !bs.delta && bs.pdf > 0.0f, "sample %d: pdf %g", i, bs.pdf);
        bsdf_eval(&m, &sp, wo, bs.wi, lambda, 15u, f, pdf);
        for (j = 0; j < HERO_N; j++) {
            CHECK(t, fabsf(bs.pdf_l[j] - pdf[j]) <= 1e-4f * pdf[j] && bs.pdf_l[j] == bs.pdf,
                  "sample %d lane %d: pdf %g, evaluated %g", i, j, bs.pdf_l[j], pdf[j]);
            CHECK(t, fabsf(bs.f[j] - f[j]) <= 1e-4f * f[j] + 1e-12f,
                  "sample %d lane %d: f %g, evaluated %g", i, j, bs.f[j], f[j]);
        }
    }
    CHECK(t, n_ok > 1990, "only %d of 2000 samples made", n_ok);
}

/* Without tilt and at h = 0, f |cos i| is symmetric in (wo, wi) when theta_i =
   theta_o (A_p depends on theta_o only; N_p is then even in phi); a tilt breaks it. */
static void test_hair_reciprocity(T *t)
{
    static const float lambda[HERO_N] = { 550.0f, 450.0f, 650.0f, 500.0f };
    Hair H;
    SurfacePoint sp = hair_point(0.0f);
    Rng r;
    int i;
    double worst_tilted = 0.0;
    rng_seed(&r, 36, 5);
    for (i = 0; i < 200; i++) {
        float u[3], f1[HERO_N], f2[HERO_N], p[HERO_N];
        Vec3 wo, wi;
        Material m = hair_material(&H, 0.7f, 1.55f, 0.3f, 0.4f, 0.0f);
        double g1, g2;
        rng_fill(&r, u, 3);
        wo = hair_dir(1.8 * u[0] - 0.9, 2.0 * SPECNEE_PI * u[1]);
        wi = hair_dir(wo.x, 2.0 * SPECNEE_PI * u[2]);
        bsdf_eval(&m, &sp, wo, wi, lambda, 15u, f1, p);
        bsdf_eval(&m, &sp, wi, wo, lambda, 15u, f2, p);
        g1 = f1[1] * fabs(wi.z);
        g2 = f2[1] * fabs(wo.z);
        CHECK(t, fabs(g1 - g2) <= 1e-4 * (g1 + g2) + 1e-9, "pair %d: %g against %g", i, g1, g2);
        m = hair_material(&H, 0.7f, 1.55f, 0.3f, 0.4f, 6.0f);
        bsdf_eval(&m, &sp, wo, v3(-wo.x, wo.y, -wo.z), lambda, 15u, f1, p);
        bsdf_eval(&m, &sp, v3(-wo.x, wo.y, -wo.z), wo, lambda, 15u, f2, p);
        g1 = f1[1] * fabs(wo.z);
        g2 = f2[1] * fabs(wo.z);
        if (fabs(g1 - g2) / (g1 + g2) > worst_tilted) worst_tilted = fabs(g1 - g2) / (g1 + g2);
    }
    CHECK(t, worst_tilted > 1e-2, "a tilt of 6 degrees left f symmetric (%g)", worst_tilted);
}

/* log I0 against the series (double, to x = 40) across the switch at 12. */
static void test_hair_log_i0(T *t)
{
    double x;
    for (x = 0.0; x <= 40.0; x += 0.37) {
        double q = x * x / 4.0, term = 1.0, sum = 1.0;
        int k;
        for (k = 1; k < 400; k++) { term *= q / ((double)k * k); sum += term; }
        CHECK(t, fabs(hair_log_i0(x) - log(sum)) < 2e-6 * (1.0 + log(sum)),
              "log I0(%g) = %.9g, series %.9g", x, hair_log_i0(x), log(sum));
    }
}

/* pbrt-v4's SigmaAFromReflectance: sigma_a = (ln c / d(beta_n))^2, so that
   c = exp(-sqrt(sigma_a) d(beta_n)) comes back (d the paper's quintic, eq. (9)). */
static void test_hair_reflectance_round_trip(T *t)
{
    float bn, c;
    for (bn = 0.05f; bn <= 1.0f; bn += 0.19f)
        for (c = 0.02f; c < 1.0f; c += 0.13f) {
            double d = 5.969 - 0.215 * bn + 2.532 * pow(bn, 2) - 10.73 * pow(bn, 3) +
                       5.574 * pow(bn, 4) + 0.245 * pow(bn, 5);
            float sa = hair_sigma_a_from_reflectance(c, bn);
            double back = exp(-sqrt((double)sa) * d);
            CHECK(t, fabs(back - c) < 1e-5, "beta_n %g c %g: sigma_a %g gives back %g", bn, c, sa, back);
        }
    CHECK(t, hair_sigma_a_from_reflectance(1.0f, 0.3f) == 0.0f, "white hair absorbs");
    CHECK(t, fabsf(hair_sigma_a_from_reflectance(0.5f, 0.3f) - 0.0138565f) < 1e-6f,
          "c 0.5, beta_n 0.3: %.7g", hair_sigma_a_from_reflectance(0.5f, 0.3f));
}

static const char *const HAIR_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n";

/* The Hair a one-material scene built from `material` (a Material statement). */
static int hair_of(T *t, const char *material, Scene *s)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s%s\nShape \"sphere\"\n", HAIR_HEAD, material);
    if (!test_load_scene(t, s, buf)) return 0;
    if (s->n_materials < 1 || s->materials[s->n_materials - 1].type != MAT_HAIR) {
        test_failf(t, __FILE__, __LINE__, "%s: not a hair material", material);
        scene_free(s);
        return 0;
    }
    return 1;
}

/* The colour parameters: pbrt-v4's precedence sigma_a > reflectance (or color) >
   melanins, the default eumelanin 1.3, the melanins' RGB sigma_a, and the other
   defaults (eta 1.55, beta_m = beta_n = 0.3, alpha 2; betas clamped to [0.01, 1]). */
static void test_hair_params(T *t)
{
    Scene s;
    Spectrum want;
    float rgb[3];
    Error e;
    int nm;
    const Hair *H;
    if (!hair_of(t, "Material \"hair\"", &s)) return;
    H = s.materials[s.n_materials - 1].hair;
    hair_melanin_rgb(1.3f, 0.0f, rgb);
    CHECK(t, fabsf(rgb[0] - 1.3f * 0.419f) < 1e-6f && fabsf(rgb[2] - 1.3f * 1.37f) < 1e-6f,
          "eumelanin 1.3: rgb %g %g %g", rgb[0], rgb[1], rgb[2]);
    spec_from_rgb(&want, rgb, 2, &e, "t", 1);
    for (nm = SPEC_MIN; nm <= SPEC_MAX; nm += 10)
        CHECK(t, fabsf(spec_get(&H->sigma_a, nm) - spec_get(&want, nm)) < 1e-3f * spec_get(&want, nm),
              "default sigma_a at %d nm: %g, want %g", nm, spec_get(&H->sigma_a, nm), spec_get(&want, nm));
    CHECK(t, !H->from_color && H->eta == 1.55f && H->beta_m == 0.3f && H->beta_n == 0.3f &&
          H->alpha == 2.0f, "defaults: eta %g beta_m %g beta_n %g alpha %g", H->eta, H->beta_m,
          H->beta_n, H->alpha);
    scene_free(&s);

    if (!hair_of(t, "Material \"hair\" \"float pheomelanin\" [ 0.5 ] \"float eumelanin\" [ 0.2 ] "
                 "\"float beta_m\" [ 3 ] \"float beta_n\" [ 0 ]", &s))
        return;
    H = s.materials[s.n_materials - 1].hair;
    hair_melanin_rgb(0.2f, 0.5f, rgb);
    CHECK(t, fabsf(rgb[1] - (0.2f * 0.697f + 0.5f * 0.4f)) < 1e-6f, "melanins: g %g", rgb[1]);
    spec_from_rgb(&want, rgb, 2, &e, "t", 1);
    CHECK(t, fabsf(spec_get(&H->sigma_a, 600) - spec_get(&want, 600)) < 1e-3f * spec_get(&want, 600),
          "melanins at 600 nm: %g, want %g", spec_get(&H->sigma_a, 600), spec_get(&want, 600));
    CHECK(t, H->beta_m == 1.0f && H->beta_n == 0.01f, "betas clamped: %g %g", H->beta_m, H->beta_n);
    scene_free(&s);

    if (!hair_of(t, "Material \"hair\" \"float eumelanin\" [ 8 ] \"rgb color\" [ 0.2 0.4 0.6 ]", &s))
        return;
    H = s.materials[s.n_materials - 1].hair;
    CHECK(t, H->from_color && spec_get(&H->color, 450) > spec_get(&H->color, 650),
          "\"color\" (pbrt-v4's other name for reflectance) wins over the melanins");
    scene_free(&s);

    if (!hair_of(t, "Material \"hair\" \"rgb reflectance\" [ 0.2 0.4 0.6 ] \"spectrum sigma_a\" [ 300 0.25 830 0.25 ]",
                 &s))
        return;
    H = s.materials[s.n_materials - 1].hair;
    CHECK(t, !H->from_color && spec_get(&H->sigma_a, 500) == 0.25f, "sigma_a wins over reflectance");
    scene_free(&s);
}

/* A reflectance is turned into sigma_a at each of the path's wavelengths
   (spectral: pbrt-v4 converts the sampled values), with the hair's beta_n. */
static void test_hair_reflectance_spectral(T *t)
{
    static const float lambda[HERO_N] = { 450.0f, 520.0f, 610.0f, 690.0f };
    Scene s;
    Hair H2;
    int j;
    if (!hair_of(t, "Material \"hair\" \"rgb reflectance\" [ 0.7 0.4 0.1 ] \"float beta_n\" [ 0.45 ]", &s))
        return;
    for (j = 0; j < HERO_N; j++) {
        const Material *m = &s.materials[s.n_materials - 1];
        float c = spec_eval(&m->hair->color, lambda[j]), f1[HERO_N], f2[HERO_N], p[HERO_N];
        float lj[HERO_N];
        SurfacePoint sp = hair_point(0.2f);
        Material m2 = hair_material(&H2, hair_sigma_a_from_reflectance(c, 0.45f), 1.55f, 0.3f, 0.45f, 2.0f);
        int k;
        for (k = 0; k < HERO_N; k++) lj[k] = lambda[j];
        bsdf_eval(m, &sp, hair_dir(0.3, 0.2), hair_dir(-0.2, 2.9), lambda, 15u, f1, p);
        bsdf_eval(&m2, &sp, hair_dir(0.3, 0.2), hair_dir(-0.2, 2.9), lj, 15u, f2, p);
        CHECK(t, fabsf(f1[j] - f2[0]) <= 1e-5f * f2[0], "lane %d (%g nm): f %g, want %g", j, lambda[j],
              f1[j], f2[0]);
    }
    scene_free(&s);
}

/* f of the last material of HAIR_HEAD + text at a fixed hit and pair (the hero's
   wavelength first). */
static int hair_f(T *t, const char *text, float f[HERO_N])
{
    static const float lambda[HERO_N] = { 460.0f, 530.0f, 600.0f, 680.0f };
    char buf[4096];
    Scene s;
    float pdf[HERO_N];
    SurfacePoint sp = hair_point(0.35f);
    snprintf(buf, sizeof buf, "%s%s\nShape \"sphere\"\n", HAIR_HEAD, text);
    if (!test_load_scene(t, &s, buf)) return 0;
    bsdf_eval(&s.materials[s.n_materials - 1], &sp, hair_dir(0.25, 0.3), hair_dir(-0.1, 2.6), lambda, 15u, f, pdf);
    scene_free(&s);
    return 1;
}

/* Every parameter may be a texture (pbrt-v4's GetFloatTexture and
   GetSpectrumTexture): constant textures give what their values give; textured
   melanins (sigma_a made at each hit from the pheomelanin share's table) within
   1e-3 of the constant pair's sigma_a (fitted at load). */
static void test_hair_textures(T *t)
{
    static const char *const pairs[][2] = {
        { "Texture \"e\" \"float\" \"constant\" \"float value\" [ 1.4 ]\n"
          "Texture \"b\" \"float\" \"constant\" \"float value\" [ 0.45 ]\n"
          "Texture \"n\" \"float\" \"constant\" \"float value\" [ 0.2 ]\n"
          "Texture \"a\" \"float\" \"constant\" \"float value\" [ 4 ]\n"
          "Material \"hair\" \"texture eta\" \"e\" \"texture beta_m\" \"b\" \"texture beta_n\" \"n\" \"texture alpha\" \"a\"",
          "Material \"hair\" \"float eta\" 1.4 \"float beta_m\" 0.45 \"float beta_n\" 0.2 \"float alpha\" 4" },
        { "Texture \"s\" \"spectrum\" \"constant\" \"spectrum value\" [ 400 0.2 700 1.5 ]\n"
          "Material \"hair\" \"texture sigma_a\" \"s\" \"float eumelanin\" 3",
          "Material \"hair\" \"spectrum sigma_a\" [ 400 0.2 700 1.5 ]" },
        { "Texture \"c\" \"spectrum\" \"constant\" \"rgb value\" [ 0.7 0.5 0.2 ]\n"
          "Material \"hair\" \"texture reflectance\" \"c\" \"float beta_n\" 0.5",
          "Material \"hair\" \"rgb reflectance\" [ 0.7 0.5 0.2 ] \"float beta_n\" 0.5" },
        { "Texture \"m\" \"float\" \"constant\" \"float value\" [ 0.7 ]\n"
          "Material \"hair\" \"texture eumelanin\" \"m\" \"float pheomelanin\" 0.3",
          "Material \"hair\" \"float eumelanin\" 0.7 \"float pheomelanin\" 0.3" },
        { "Texture \"m\" \"float\" \"constant\" \"float value\" [ 1.9 ]\n"
          "Material \"hair\" \"texture pheomelanin\" \"m\"",
          "Material \"hair\" \"float pheomelanin\" 1.9" },
    };
    int c, j;
    for (c = 0; c < (int)(sizeof pairs / sizeof pairs[0]); c++) {
        float a[HERO_N], b[HERO_N];
        if (!hair_f(t, pairs[c][0], a) || !hair_f(t, pairs[c][1], b)) return;
        for (j = 0; j < HERO_N; j++)
            CHECK(t, fabsf(a[j] - b[j]) <= 1e-3f * b[j] && b[j] > 0.0f, "pair %d lane %d: textured %g, "
                  "constant %g", c, j, a[j], b[j]);
    }
}

static void test_hair_errors(T *t)
{
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"float eta\" [ 0 ]\n", "hair.pbrt",
                 "hair.pbrt:8: Material \"hair\": \"float eta\" 0 is not an index of refraction");
    test_refused(t, HAIR_HEAD, "Material \"hair\"\n  \"float alpha\" [ 120 ]\n", "hair.pbrt",
                 "hair.pbrt:9: Material \"hair\": \"float alpha\" 120 is not a scale tilt");
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"rgb reflectance\" [ 1.2 0.5 0.5 ]\n", "hair.pbrt",
                 "hair.pbrt:8: \"rgb reflectance\": a reflectance must be within [0,1]");
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"spectrum sigma_a\" [ 300 -1 830 1 ]\n", "hair.pbrt",
                 "hair.pbrt:8: \"spectrum sigma_a\": value -1 at 300 nm is not an absorption coefficient");
    test_refused(t, HAIR_HEAD, "Texture \"b\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n"
                 "MakeNamedMaterial \"h\" \"string type\" \"hair\" \"texture beta_m\" \"b\"\n", "hair.pbrt",
                 "hair.pbrt:9: \"texture beta_m\": \"b\" is a spectrum texture; a float one is needed here");
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"texture sigma_a\" \"nothere\"\n", "hair.pbrt",
                 "hair.pbrt:8: \"texture sigma_a\": no texture named \"nothere\"");
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"float displacement\" [ 0.1 ]\n", "hair.pbrt",
                 "hair.pbrt:8: \"float displacement\": unused parameter");
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"float eta\" [ 1.5 2 ]\n", "hair.pbrt", "hair.pbrt:8:");
}

/* "string normalmap" on hair: pbrt-v4 loads every material's normal map before it
   makes the materials (scene.cpp startLoadingNormalMaps) and stops when the file
   cannot be read, then HairMaterial::GetNormalMap returns none.  So a missing file
   is refused at its file:line, naming it (Material and MakeNamedMaterial alike),
   and a file that exists, or "", loads a hair material with no normal map. */
static void test_hair_normalmap(T *t)
{
    char body[1200];
    Scene s;
    test_refused(t, HAIR_HEAD, "Material \"hair\" \"string normalmap\" \"nothere.png\"\n", "hair.pbrt",
                 "hair.pbrt:8: Material \"hair\": \"string normalmap\" \"nothere.png\": cannot open the file "
                 "(pbrt-v4 reads it here too, and stops)");
    test_refused(t, HAIR_HEAD, "MakeNamedMaterial \"h\" \"string type\" \"hair\"\n"
                 "  \"string normalmap\" \"gone.pfm\"\n", "hair.pbrt",
                 "hair.pbrt:9: MakeNamedMaterial \"h\": type \"hair\": \"string normalmap\" \"gone.pfm\": cannot open");
    if (t->failed) return;
    snprintf(body, sizeof body, "Material \"hair\" \"string normalmap\" \"%s\"",
             test_write_file(t, "hair_tilt.pfm", "PF\n1 1\n-1\n"));
    if (!hair_of(t, body, &s)) return;
    CHECK(t, s.materials[s.n_materials - 1].bump == NULL, "the hair material took a normal map");
    scene_free(&s);
    if (!hair_of(t, "Material \"hair\" \"string normalmap\" \"\"", &s)) return;
    scene_free(&s);
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, the independent sampler, 32 x 32,
   `pbrt --seed S --spp 1024 scene.pbrt` for S = 1..4) rendered HAIR_HEAD +
   HAIR_SCENE[j].  Both: a distant light and a dim uniform sky over a grey backdrop.
   (a) (world x > 0 appears on the left) top left a sphere of "eumelanin" 0.3 and
   "pheomelanin" 0.8 with beta_m 0.5 and alpha 5, top right one of "rgb sigma_a"
   (0.1, 0.4, 1.2), bottom left a rotated sphere of the default hair (eumelanin
   1.3), bottom right a twisted bilinear patch of "rgb reflectance" (0.8, 0.5, 0.3)
   with beta_n 0.6 and eta 1.4.  (b) Lit from the side: a sphere of textured
   eumelanin (a directionmix of 0.1 and 1.5) with pheomelanin 0.4 and beta_n 0.5,
   and a bilinear patch of a directionmix "texture reflectance" with beta_m 0.2 and
   alpha -3.  Luminance of the image and of its quadrants (top left first): mean
   over the seeds and its standard error.  specnee is accepted within 5 standard
   errors + 1 %.  (With checkerboards of 8 x 4 cells instead, specnee reads 0.6 %
   brighter: pbrt-v4 box-filters a checkerboard's edges over the ray footprint,
   and sigma_a -> f is not linear, so filtered and point-sampled textures part
   there; a directionmix is not filtered.) */
static const double PBRT_HAIR_Y[2][5][2] = {
    { { 0.242090, 0.00015 },
      { 0.225580, 0.00021 }, { 0.200783, 0.00054 }, { 0.223730, 0.00035 }, { 0.318267, 0.00044 } },
    { { 0.118236, 0.00017 },
      { 0.091333, 5.1e-05 }, { 0.126405, 8.9e-05 }, { 0.083380, 0.00014 }, { 0.171826, 0.0007 } },
};

static const char *const HAIR_SCENE[2] = {
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 2 1 3 ] \"point3 to\" [ 0 0 0 ]\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.2 0.2 0.2 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 -1  4 -4 -1  4 4 -1  -4 4 -1 ]\n"
    "AttributeBegin\nTranslate -0.9 0.9 0\nRotate -90 1 0 0\n"
    "Material \"hair\" \"rgb sigma_a\" [ 0.1 0.4 1.2 ]\n"
    "Shape \"sphere\" \"float radius\" [ 0.75 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate 0.9 0.9 0\nRotate 30 0 1 0\n"
    "Material \"hair\" \"float eumelanin\" [ 0.3 ] \"float pheomelanin\" [ 0.8 ] \"float beta_m\" [ 0.5 ] \"float alpha\" [ 5 ]\n"
    "Shape \"sphere\" \"float radius\" [ 0.75 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -0.9 -0.9 0\n"
    "Material \"hair\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"float beta_n\" [ 0.6 ] \"float eta\" [ 1.4 ]\n"
    "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] \"point3 P\" [ -0.8 -0.8 0.2  0.8 -0.8 -0.2  -0.8 0.8 -0.2  0.8 0.8 0.3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\nTranslate 0.9 -0.9 0\nRotate 60 1 1 0\nMaterial \"hair\"\n"
    "Shape \"sphere\" \"float radius\" [ 0.7 ]\nAttributeEnd\n",
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ -3 1 0.3 ] \"point3 to\" [ 0 0 0 ]\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.2 0.2 0.2 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 -1  4 -4 -1  4 4 -1  -4 4 -1 ]\n"
    "Texture \"mel\" \"float\" \"directionmix\" \"float tex1\" [ 0.1 ] \"float tex2\" [ 1.5 ] \"vector3 dir\" [ 1 1 0 ]\n"
    "Texture \"refl\" \"spectrum\" \"directionmix\" \"rgb tex1\" [ 0.9 0.6 0.3 ] \"rgb tex2\" [ 0.3 0.5 0.8 ] \"vector3 dir\" [ 0 1 1 ]\n"
    "AttributeBegin\nTranslate 0.3 0 0\nRotate -70 1 0 0\n"
    "Material \"hair\" \"texture eumelanin\" \"mel\" \"float pheomelanin\" [ 0.4 ] \"float beta_n\" [ 0.5 ]\n"
    "Shape \"sphere\" \"float radius\" [ 1.1 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -1.3 -0.6 0.8\nRotate 40 0 0 1\n"
    "Material \"hair\" \"texture reflectance\" \"refl\" \"float beta_m\" [ 0.2 ] \"float alpha\" [ -3 ]\n"
    "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] \"point3 P\" [ -0.5 -0.6 0  0.5 -0.6 0.3  -0.5 0.6 0.3  0.5 0.6 0 ]\n"
    "AttributeEnd\n",
};

static void test_hair_against_pbrt(T *t)
{
    char body[8192];
    int j;
    for (j = 0; j < 2; j++) {
        Scene s;
        char what[8];
        snprintf(body, sizeof body, "%s%s", HAIR_HEAD, HAIR_SCENE[j]);
        if (!test_load_scene(t, &s, body)) return;
        snprintf(what, sizeof what, "scene %c", 'a' + j);
        test_scene_against_pbrt_y(t, &s, test_scaled(64, 16), 7, PBRT_HAIR_Y[j], 1e-2, what);
        scene_free(&s);
        if (t->failed) return;
    }
}

/* Hair on curves, the shape it is made for: the fibre's axis is the curve's dp/du
   and h = -1 + 2v across it.  pbrt-v4 (5f7a6068, `pbrt --seed S --spp 1024`,
   S = 1..4, 32 x 32) rendered HAIR_CURVES: two cylinder curves and a flat one
   under a distant light and a dim sky, nothing behind them.  Luminance of the
   image and its quadrants (top left first): mean over the seeds and its standard
   error; specnee (2 x 1024 spp) read 0.190145 for the image. */
static const char *const HAIR_CURVES =
    "LookAt 0 -4 0.5  0 0 0.5  0 0 1\n"
    "Camera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 10 ]\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 -2 3 ] \"point3 to\" [ 0 0 0 ]\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.2 0.2 0.25 ]\n"
    "Material \"hair\" \"float eumelanin\" [ 0.8 ]\n"
    "Shape \"curve\" \"string type\" \"cylinder\" \"point3 P\" [ -0.8 0 0  -0.3 0 0.6  0.3 0 0.4  0.8 0 1 ] "
    "\"float width0\" [ 0.12 ] \"float width1\" [ 0.04 ]\n"
    "Shape \"curve\" \"string type\" \"flat\" \"point3 P\" [ -0.8 0.2 0.9  -0.3 0.2 0.3  0.3 0.2 0.9  0.8 0.2 0.2 ] "
    "\"float width\" [ 0.1 ]\n"
    "Material \"hair\" \"rgb sigma_a\" [ 0.2 0.8 1.6 ]\n"
    "Shape \"curve\" \"string type\" \"cylinder\" \"point3 P\" [ -0.8 0 -0.2  -0.3 0 0.2  0.3 0 -0.1  0.8 0 0.3 ] "
    "\"float width\" [ 0.15 ]\n";
static const double PBRT_HAIR_CURVES_Y[5][2] = {
    { 0.190125, 2.1e-05 }, { 0.195772, 3.2e-05 }, { 0.197428, 1.7e-05 }, { 0.187590, 4.8e-05 }, { 0.179718, 2.3e-05 },
};

static void test_hair_on_curves_against_pbrt(T *t)
{
    test_against_pbrt_y(t, HAIR_CURVES, 7, PBRT_HAIR_CURVES_Y, 5e-3, "hair curves");
}

const TestCase tests_hair[] = {
    { "hair_furnace", test_hair_furnace },
    { "hair_absorbs", test_hair_absorbs },
    { "hair_black_fibre", test_hair_black_fibre },
    { "hair_chi2", test_hair_chi2 },
    { "hair_sample_eval", test_hair_sample_eval },
    { "hair_reciprocity", test_hair_reciprocity },
    { "hair_log_i0", test_hair_log_i0 },
    { "hair_reflectance_round_trip", test_hair_reflectance_round_trip },
    { "hair_params", test_hair_params },
    { "hair_reflectance_spectral", test_hair_reflectance_spectral },
    { "hair_textures", test_hair_textures },
    { "hair_errors", test_hair_errors },
    { "hair_normalmap", test_hair_normalmap },
    { "hair_against_pbrt", test_hair_against_pbrt },
    { "hair_on_curves_against_pbrt", test_hair_on_curves_against_pbrt },
    { NULL, NULL }
};
