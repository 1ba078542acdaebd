/* test_coated.c - pbrt-v4's "coateddiffuse" (layered.c): the stochastic f is
   unbiased over its seeds, the sampled walks' weights integrate to the albedo
   that f gives, one pdf function serves NEE and BSDF sampling, NEE-only and
   BSDF-only renders agree, furnaces match numbers frozen from pbrt-v4, and bad
   parameters are refused with file:line. */
#include "test.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

static const float LAM[HERO_N] = { 450.0f, 550.0f, 620.0f, 700.0f };

/* A coated diffuse material; R from r_short (below 550 nm) to r_long. */
static void coated(Material *m, float r_short, float r_long, float alpha, float eta,
                   float thick, float albedo, float g, int nsamples)
{
    memset(m, 0, sizeof *m);
    m->extra = test_material_extra();
    m->type = MAT_COATED_DIFFUSE;
    {
        Spectrum *r = test_material_eta();        /* a table from the ring */
        int nm;
        spec_const(r, r_short);
        for (nm = 550; nm <= SPEC_MAX; nm++) *spec_at(r, nm) = r_long;
        m->reflectance.tab = r;
    }
    m->eta = test_eta_const(eta);
    spec_const(&m->extra->albedo, albedo);
    m->alpha = m->alpha_t = alpha;
    m->thickness = thick;
    m->hg_g = g;
    m->maxdepth = 100;    /* f and the sampled walks truncate differently (pbrt-v4's
                             design: f's next-event estimates see one vertex more);
                             with the medium at 10 the two differ by 1% */
    m->nsamples = nsamples;
}

static Vec3 dir(float theta_deg, float phi_deg)
{
    float t = theta_deg * PI_F / 180.0f, p = phi_deg * PI_F / 180.0f;
    return v3(sinf(t) * cosf(p), sinf(t) * sinf(p), cosf(t));
}

#define N_CASES 3
static void cases(Material *m, int nsamples)
{
    coated(&m[0], 0.8f, 0.3f, 0.0f, 1.5f, 0.01f, 0.0f, 0.0f, nsamples);   /* smooth */
    coated(&m[1], 0.8f, 0.3f, 0.4f, 1.5f, 0.2f, 0.0f, 0.0f, nsamples);    /* rough, absorbing */
    coated(&m[2], 0.6f, 0.9f, 1.0f, 1.33f, 1.0f, 0.9f, 0.0f, nsamples);   /* a medium */
}

/* The mean of single-walk f over many seeds equals one 8192-walk estimate, and a
   seed gives the same value twice. */
static void test_eval_unbiased(T *t)
{
    Material m1[N_CASES], m256[N_CASES];
    Vec3 wo = dir(40, 0), wi = dir(60, 120);
    int c, k, j, n = test_scaled(20000, 2000);
    cases(m1, 1);
    cases(m256, 8192);
    for (c = 0; c < N_CASES; c++) {
        double s[HERO_N] = { 0 }, s2[HERO_N] = { 0 };
        float ref[HERO_N], f[HERO_N], f2[HERO_N], p[HERO_N], p2[HERO_N];
        for (k = 0; k < n; k++) {
            layered_eval(&m1[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, (uint64_t)k + 1), f, p);
            for (j = 0; j < HERO_N; j++) { s[j] += f[j]; s2[j] += (double)f[j] * f[j]; }
        }
        layered_eval(&m256[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, 777), ref, p);   /* 8192 walks */
        for (j = 0; j < HERO_N; j++) {
            double mu = s[j] / n, var = s2[j] / n - mu * mu, se = sqrt(fmax(var, 0.0) / n);
            double se_ref = sqrt(fmax(var, 0.0) / 8192.0);
            if (getenv("DBG")) fprintf(stderr, "case %d j %d: mean %.5f +- %.2g, 8192 walks %.5f\n",
                                       c, j, mu, se, ref[j]);
            CHECK(t, mu > 0.0, "case %d: f = 0", c);
            CHECK(t, fabs(mu - ref[j]) < TEST_K_SIGMA * sqrt(se * se + se_ref * se_ref) + 1e-4,
                  "case %d wavelength %d: mean f %.5f +- %.2g, 8192 walks %.5f", c, j, mu, se, ref[j]);
        }
        layered_eval(&m1[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, 5), f, p);
        layered_eval(&m1[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, 5), f2, p2);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, f[j] == f2[j] && p[j] == p2[j], "case %d: a seed is not deterministic", c);
        /* two-sided: seen from below (both mirrored) the same value */
        layered_eval(&m1[c], NULL, v3_neg(wo), v3_neg(wi), LAM, 15u, layered_seed(wo, wi, 5), f2, p2);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, f[j] == f2[j] && f[j] > 0.0f && p[j] == p2[j], "case %d: from below f %g, "
                  "from above %g", c, f2[j], f[j]);
        /* wi below: the base transmits nothing */
        layered_eval(&m1[c], NULL, wo, v3(wi.x, wi.y, -wi.z), LAM, 15u, 1, f, p);
        CHECK(t, f[0] == 0.0f && p[0] > 0.0f, "case %d: transmission f %g pdf %g", c, f[0], p[0]);
    }
}

/* E[f cos / p] of bsdf_sample's walks = the directional albedo integral of
   bsdf_eval's f cos (cosine-sampled wi, seeds varied), plus the smooth coat's
   mirror reflection F(cos o), per wavelength; and it is below 1. */
static void sample_weight_albedo(T *t, const Material *m, int n_cases)
{
    SurfacePoint sp = test_flat_point();
    Frame fr = frame_from_normal(sp.ns);
    Vec3 wo = dir(35, 20);
    int c, k, j, n = test_scaled(40000, 4000);
    for (c = 0; c < n_cases; c++) {
        double a[HERO_N] = { 0 }, a2[HERO_N] = { 0 }, b[HERO_N] = { 0 }, b2[HERO_N] = { 0 };
        Rng rng;
        rng_seed(&rng, 91, (uint64_t)c);
        for (k = 0; k < n; k++) {
            BsdfSample bs;
            float f[HERO_N], p[HERO_N], u[2], r, ph;
            Vec3 li, wi;
            if (test_bsdf_sample(&m[c], &sp, frame_to_world(&fr, wo), LAM, 15u, &rng, &bs)) {
                float cw = fabsf(v3_dot(bs.wi, sp.ns));
                for (j = 0; j < HERO_N; j++) {
                    double w = bs.f[j] * cw / bs.pdf;
                    a[j] += w; a2[j] += w * w;
                }
            }
            rng_fill(&rng, u, 2);
            r = sqrtf(u[0]); ph = 2.0f * PI_F * u[1];
            li = v3(r * cosf(ph), r * sinf(ph), sqrtf(fmaxf(0.0f, 1.0f - u[0])));
            if (li.z <= 0.0f) continue;
            wi = li;
            layered_eval(&m[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, (uint64_t)k), f, p);
            for (j = 0; j < HERO_N; j++) {
                double w = f[j] * PI_F;           /* f cos / (cos / pi) */
                b[j] += w; b2[j] += w * w;
            }
        }
        for (j = 0; j < HERO_N; j++) {
            double ma = a[j] / n, mb = b[j] / n;
            double sa = sqrt(fmax(a2[j] / n - ma * ma, 0.0) / n), sb = sqrt(fmax(b2[j] / n - mb * mb, 0.0) / n);
            if (m[c].alpha == 0.0f)                           /* the delta lobe */
                mb += fresnel_dielectric(wo.z, spec_eval(m[c].eta, 550.0f));
            if (getenv("DBG")) fprintf(stderr, "case %d j %d: sampled %.5f +- %.2g, eval %.5f +- %.2g\n",
                                       c, j, ma, sa, mb, sb);
            CHECK(t, fabs(ma - mb) < TEST_K_SIGMA * sqrt(sa * sa + sb * sb) + 1e-3,
                  "case %d wavelength %d: sampled albedo %.5f +- %.2g, from f %.5f +- %.2g",
                  c, j, ma, sa, mb, sb);
            CHECK(t, ma < 1.0 && ma > 0.05, "case %d: albedo %g", c, ma);
        }
    }
}

static void test_sample_weight_albedo(T *t)
{
    Material m[N_CASES];
    cases(m, 1);
    sample_weight_albedo(t, m, N_CASES);
}

/* The pdf estimate integrates to about 1 over the sphere (it is an
   approximation: 0.1 of it uniform, the rest one-bounce paths; MIS needs only a
   positive function used alike by both strategies), bsdf_sample
   reports exactly the pdf bsdf_eval gives the same world pair, and the
   sampled weight uses one pdf function for every wavelength. */
static void pdf_checks(T *t, const Material *m, int n_cases)
{
    SurfacePoint sp = test_flat_point();
    Frame fr = frame_from_normal(sp.ns);
    Vec3 wo = dir(50, 0), wow = frame_to_world(&fr, wo);
    int c, k, j, n = test_scaled(20000, 4000), nd = 0;
    for (c = 0; c < n_cases; c++) {
        double s = 0.0;
        Rng rng;
        rng_seed(&rng, 17, (uint64_t)c);
        for (k = 0; k < n; k++) {
            float u[2], z, r;
            Vec3 wi;
            rng_fill(&rng, u, 2);
            z = 1.0f - 2.0f * u[0]; r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
            wi = v3(r * cosf(2.0f * PI_F * u[1]), r * sinf(2.0f * PI_F * u[1]), z);
            s += layered_pdf(&m[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, 0)) * 4.0 * SPECNEE_PI;
        }
        s /= n;
        if (getenv("DBG")) fprintf(stderr, "case %d: integral of pdf %.4f\n", c, s);
        /* the smooth coat's estimate is a density of the INSIDE direction (cos/pi
           of the refracted pair, pbrt-v4's PDF) read as one of wi: 0.1 + 0.9 x
           compression: 1.59 at wo 50 deg; 1.37 and 1.43 for the rough cases) */
        CHECK(t, s > 0.5 && s < 2.0, "case %d: pdf integrates to %g", c, s);
        for (k = 0; k < 300; k++) {
            BsdfSample bs;
            float f[HERO_N], p[HERO_N];
            if (!test_bsdf_sample(&m[c], &sp, wow, LAM, 15u, &rng, &bs)) continue;
            for (j = 1; j < HERO_N; j++)
                CHECK(t, bs.pdf_l[j] == bs.pdf, "case %d: pdf_l[%d] %g != pdf %g", c, j, bs.pdf_l[j], bs.pdf);
            if (bs.delta) continue;
            nd++;
            bsdf_eval(&m[c], &sp, wow, bs.wi, LAM, 15u, f, p);
            CHECK(t, fabsf(p[0] - bs.pdf) <= 1e-3f * bs.pdf,
                  "case %d: sample's pdf %g, bsdf_eval's %g for the same pair", c, bs.pdf, p[0]);
        }
    }
    CHECK(t, nd > 100 * n_cases, "only %d non-delta samples", nd);
}

static void test_pdf(T *t)
{
    Material m[N_CASES];
    cases(m, 1);
    pdf_checks(t, m, N_CASES);
}

/* ---------------------------------------------------------------- coatedconductor */

/* A coated conductor: the coat (alpha, eta), the base (alpha, pbrt-v4's metal name). */
static void coatcond(Material *m, float alpha, float eta, float base_alpha, const char *metal,
                     float thick, float albedo)
{
    char name[32];
    memset(m, 0, sizeof *m);
    m->extra = test_material_extra();
    m->type = MAT_COATED_CONDUCTOR;
    m->eta = test_eta_const(eta);
    m->alpha = m->alpha_t = alpha;
    m->cond_alpha = m->cond_alpha_t = base_alpha;
    snprintf(name, sizeof name, "metal-%s-eta", metal);
    spec_named(&m->extra->cond_eta, name);
    snprintf(name, sizeof name, "metal-%s-k", metal);
    spec_named(&m->extra->k, name);
    spec_const(&m->extra->albedo, albedo);
    m->thickness = thick;
    m->maxdepth = 100;    /* as cases(): f and the sampled walks truncate alike */
    m->nsamples = 1;
}

#define N_CC 3
static void cc_cases(Material *m)
{
    coatcond(&m[0], 0.0f, 1.5f, 0.3f, "Au", 0.1f, 0.0f);    /* smooth coat, rough base */
    coatcond(&m[1], 0.4f, 1.5f, 0.0f, "Ag", 0.05f, 0.0f);   /* rough coat, smooth base */
    coatcond(&m[2], 0.3f, 1.33f, 0.2f, "Cu", 0.5f, 0.8f);   /* both rough, a medium */
}

/* A coat of index 1 is no interface: with no medium and a vanishing slab the
   coated conductor is the bare conductor, exactly, whatever the seed (every walk
   crosses straight down, meets the base, and cannot return from the coat, whose
   reflectance is 0).  The base's index is relative to the coat's: n / 1 = n. */
static void test_cc_limit_bare(T *t)
{
    Material cc, bare;
    MatPoint mp;
    SurfacePoint sp = test_flat_point();
    Frame fr = frame_from_normal(sp.ns);
    float f[HERO_N], p[HERO_N], fb[HERO_N], pb[HERO_N];
    int k, j;
    coatcond(&cc, 0.0f, 1.0f, 0.3f, "Cu", 1e-6f, 0.0f);
    memset(&bare, 0, sizeof bare);
    bare.extra = test_material_extra();
    bare.type = MAT_CONDUCTOR;
    bare.eta = test_eta_named("metal-Cu-eta");
    spec_named(&bare.extra->k, "metal-Cu-k");
    memset(&mp, 0, sizeof mp);                 /* untextured: no has_r, no has_ek */
    mp.alpha = mp.alpha_t = 0.3f;
    mp.cond_alpha = 0.0f;
    for (k = 0; k < 40; k++) {
        Vec3 wo = dir(5.0f + 2.0f * (float)k, 13.0f * (float)k), wi = dir(80.0f - 1.9f * (float)k, 200.0f);
        layered_eval(&cc, NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, (uint64_t)k), f, p);
        conductor_eval(&bare, &mp, wo, wi, LAM, 15u, fb, pb);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, fb[j] > 0.0f && fabsf(f[j] - fb[j]) <= 1e-4f * fb[j] + 1e-7f,
                  "pair %d wavelength %d: coated (eta 1) f %g, bare conductor %g", k, j, f[j], fb[j]);
    }
    /* a smooth base: the sample is the mirror direction, a delta of weight F */
    cc.cond_alpha = cc.cond_alpha_t = 0.0f;
    for (k = 0; k < 10; k++) {
        Vec3 wo = dir(8.0f * (float)k, 30.0f);
        BsdfSample bs;
        Rng rng;
        rng_seed(&rng, 5, (uint64_t)k);
        CHECK(t, test_bsdf_sample(&cc, &sp, frame_to_world(&fr, wo), LAM, 15u, &rng, &bs) && bs.delta,
              "wo %d: no delta sample", k);
        for (j = 0; j < HERO_N; j++) {
            float w = bs.f[j] * fabsf(v3_dot(bs.wi, sp.ns)) / bs.pdf;
            float F = fresnel_conductor(wo.z, spec_eval(bare.eta, LAM[j]), spec_eval(&bare.extra->k, LAM[j]));
            CHECK(t, fabsf(w - F) <= 1e-4f, "wo %d wavelength %d: weight %g, F %g", k, j, w, F);
        }
    }
}

/* A smooth coat over a smooth conductor without a medium is a stack of two
   mirrors: the expected sample weight is the series
       R + T^2 Fc Tr^2 / (1 - R Fc Tr^2),
   R = Fresnel of the coat at wo (T = 1 - R; the same inside, by reciprocity),
   Fc = the conductor's Fresnel at the refracted angle with n / eta and k / eta
   (pbrt-v4 CoatedConductorMaterial::GetBxDF), Tr = exp(-thickness / cos t).
   Every sample is a delta, and bsdf_eval gives 0. */
static void test_cc_smooth_series(T *t)
{
    Material m;
    SurfacePoint sp = test_flat_point();
    Frame fr = frame_from_normal(sp.ns);
    float eta = 1.5f, th = 0.1f;
    int a, k, j, n = test_scaled(40000, 4000);
    coatcond(&m, 0.0f, eta, 0.0f, "Au", th, 0.0f);
    for (a = 0; a < 3; a++) {
        Vec3 wo = dir(10.0f + 30.0f * (float)a, 40.0f), wow = frame_to_world(&fr, wo);
        float ct = sqrtf(1.0f - (1.0f - wo.z * wo.z) / (eta * eta));
        double R = fresnel_dielectric(wo.z, eta), Tr2 = exp(-2.0 * th / ct);
        double s[HERO_N] = { 0 }, s2[HERO_N] = { 0 };
        float f[HERO_N], p[HERO_N];
        Rng rng;
        rng_seed(&rng, 33, (uint64_t)a);
        for (k = 0; k < n; k++) {
            BsdfSample bs;
            if (!test_bsdf_sample(&m, &sp, wow, LAM, 15u, &rng, &bs)) continue;
            CHECK(t, bs.delta, "angle %d: a non-delta sample", a);
            for (j = 0; j < HERO_N; j++) {
                double w = bs.f[j] * fabsf(v3_dot(bs.wi, sp.ns)) / bs.pdf;
                s[j] += w; s2[j] += w * w;
            }
        }
        for (j = 0; j < HERO_N; j++) {
            double Fc = fresnel_conductor(ct, spec_eval(&m.extra->cond_eta, LAM[j]) / eta,
                                          spec_eval(&m.extra->k, LAM[j]) / eta);
            double expect = R + (1.0 - R) * (1.0 - R) * Fc * Tr2 / (1.0 - R * Fc * Tr2);
            double mu = s[j] / n, se = sqrt(fmax(s2[j] / n - mu * mu, 0.0) / n);
            if (getenv("DBG")) fprintf(stderr, "angle %d j %d: %.5f +- %.2g, series %.5f\n", a, j, mu, se, expect);
            CHECK(t, fabs(mu - expect) < TEST_K_SIGMA * se + 1e-4, "angle %d wavelength %d: mean "
                  "weight %.5f +- %.2g, the series %.5f", a, j, mu, se, expect);
        }
        bsdf_eval(&m, &sp, wow, frame_to_world(&fr, dir(30, 200)), LAM, 15u, f, p);
        CHECK(t, f[0] == 0.0f && f[3] == 0.0f, "a specular stack has f %g", f[0]);
    }
}

/* The walks of coateddiffuse's tests with a conductor base: f unbiased over its
   seeds and two-sided, the sampled weights integrate to the albedo f gives (plus
   the smooth coat's mirror), the pdf integrates to about 1 and is the one
   bsdf_eval reports. */
static void test_cc_walks(T *t)
{
    Material m1[N_CC], mref[N_CC];
    Vec3 wo = dir(40, 0), wi = dir(60, 120);
    int c, k, j, n = test_scaled(20000, 2000);
    cc_cases(m1);
    cc_cases(mref);
    for (c = 0; c < N_CC; c++) {
        double s[HERO_N] = { 0 }, s2[HERO_N] = { 0 };
        float ref[HERO_N], f[HERO_N], f2[HERO_N], p[HERO_N], p2[HERO_N];
        mref[c].nsamples = 8192;
        for (k = 0; k < n; k++) {
            layered_eval(&m1[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, (uint64_t)k + 1), f, p);
            for (j = 0; j < HERO_N; j++) { s[j] += f[j]; s2[j] += (double)f[j] * f[j]; }
        }
        layered_eval(&mref[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, 777), ref, p);
        for (j = 0; j < HERO_N; j++) {
            double mu = s[j] / n, var = s2[j] / n - mu * mu, se = sqrt(fmax(var, 0.0) / n);
            double se_ref = sqrt(fmax(var, 0.0) / 8192.0);
            if (getenv("DBG")) fprintf(stderr, "cc case %d j %d: mean %.5f +- %.2g, 8192 walks %.5f\n",
                                       c, j, mu, se, ref[j]);
            CHECK(t, mu > 0.0, "case %d: f = 0", c);
            CHECK(t, fabs(mu - ref[j]) < TEST_K_SIGMA * sqrt(se * se + se_ref * se_ref) + 1e-4,
                  "case %d wavelength %d: mean f %.5f +- %.2g, 8192 walks %.5f", c, j, mu, se, ref[j]);
        }
        layered_eval(&m1[c], NULL, wo, wi, LAM, 15u, layered_seed(wo, wi, 5), f, p);
        layered_eval(&m1[c], NULL, v3_neg(wo), v3_neg(wi), LAM, 15u, layered_seed(wo, wi, 5), f2, p2);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, f[j] == f2[j] && p[j] == p2[j], "case %d: from below f %g, from above %g",
                  c, f2[j], f[j]);
    }
    sample_weight_albedo(t, m1, N_CC);
    pdf_checks(t, m1, N_CC);
}

/* ---------------------------------------------------------------- renders */

static const char *const MAT_A = "Material \"coateddiffuse\"";
static const char *const MAT_B = "Material \"coateddiffuse\" \"float roughness\" 0.3 "
    "\"spectrum reflectance\" [ 360 0.1 600 0.1 620 0.8 830 0.8 ]";
static const char *const MAT_C = "Material \"coateddiffuse\" \"float roughness\" 0.1 "
    "\"spectrum reflectance\" [ 360 0.7 830 0.7 ] \"float thickness\" 0.2 "
    "\"spectrum albedo\" [ 360 0.5 830 0.5 ] \"float g\" 0.3 \"float eta\" 1.33";

/* NEE + MIS and BSDF sampling alone give the same image: the MIS weights of
   both strategies use layered_pdf (a wrong pdf in bsdf_sample's f or a
   mismatched seed would bias one of them). */
static void test_nee_vs_bsdf(T *t)
{
    const char *mats[3];
    int c;
    mats[0] = MAT_A; mats[1] = MAT_B; mats[2] = MAT_C;
    for (c = 0; c < 3; c++) {
        char text[2048];
        Scene s;
        RenderOptions o;
        Tiles a, b;
        test_furnace_text(text, sizeof text, mats[c]);
        if (!test_load_scene(t, &s, text)) return;
        render_options_default(&o);
        o.maxdepth = 40;
        o.spp = test_scaled(64, 16);
        if (!test_render_tiles(t, &s, &o, 8, 2, &a)) { scene_free(&s); return; }
        o.nee = 0;
        if (!test_render_tiles(t, &s, &o, 8, 2, &b)) { scene_free(&s); return; }
        scene_free(&s);
        if (!test_tiles_agree(t, &a, &b, 2e-3, mats[c])) return;
    }
}

/* pbrt-v4 (commit 5f7a606806a4ac7b939131ded9d7a30ebd02416e) rendered
   test_furnace_text's scene with "Integrator "path" "integer maxdepth" [ 40 ]" added,
   8 times: pbrt --seed S --spp 1024 --outfile x_S.pfm x.pbrt, S = 1..8.  Per 2 x 2
   tile (row-major from the top left): the mean over the 8 images of the tile's
   luminance (0.212671 R + 0.715160 G + 0.072169 B) and its standard error. */
static const double PBRT_TILES[3][4][2] = {
    { { 0.30467, 0.00057 }, { 0.30515, 0.00049 }, { 0.30505, 0.00061 }, { 0.30503, 0.00049 } },
    { { 0.10225, 0.00016 }, { 0.10212, 0.00019 }, { 0.10224, 0.00030 }, { 0.10156, 0.00034 } },
    { { 0.33506, 0.00074 }, { 0.33350, 0.00083 }, { 0.33403, 0.00091 }, { 0.33493, 0.00076 } },
};

/* Render text (K = 8 seeds, spp) and compare its 2 x 2 tiles' luminance with
   pbrt-v4's frozen tab (mean, standard error). */
static void tiles_vs_pbrt(T *t, const char *text, int maxdepth, int spp, const double tab[4][2],
                          const char *what)
{
    Scene s;
    RenderOptions o;
    Tiles tl;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.maxdepth = maxdepth;
    o.spp = spp;
    if (!test_render_tiles(t, &s, &o, 8, 2, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    for (i = 0; i < 4; i++) {
        double Y = test_luminance(tl.mean[i]), se = tl.se[i][1], Yp = tab[i][0], sep = tab[i][1];
        double bound = TEST_K_SIGMA * sqrt(se * se + sep * sep);
        if (getenv("DBG")) fprintf(stderr, "%s tile %d: specnee %.5f +- %.2g, pbrt %.5f +- %.2g\n",
                                   what, i, Y, se, Yp, sep);
        CHECK(t, fabs(Y - Yp) < bound + 1e-3 * Yp, "%s: tile %d: specnee Y %.5f +- %.2g, "
              "pbrt-v4 %.5f +- %.2g", what, i, Y, se, Yp, sep);
    }
}

static void test_against_pbrt(T *t)
{
    const char *mats[3];
    int c;
    mats[0] = MAT_A; mats[1] = MAT_B; mats[2] = MAT_C;
    for (c = 0; c < 3; c++) {
        char text[2048];
        test_furnace_text(text, sizeof text, mats[c]);
        tiles_vs_pbrt(t, text, 40, test_scaled(256, 32), PBRT_TILES[c], mats[c]);
        if (t->failed) return;
    }
}

/* ---- coatedconductor renders ---- */

static const char *const CC_A = "Material \"coatedconductor\"";
static const char *const CC_B = "Material \"coatedconductor\" \"float conductor.roughness\" 0.2 "
    "\"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" "
    "\"float thickness\" 0.1";
static const char *const CC_C = "Material \"coatedconductor\" \"float interface.roughness\" 0.3 "
    "\"float conductor.roughness\" 0.1 \"rgb reflectance\" [ 0.9 0.6 0.3 ] "
    "\"spectrum albedo\" [ 360 0.5 830 0.5 ] \"float thickness\" 0.2 \"float interface.eta\" 1.33";

static void test_cc_nee_vs_bsdf(T *t)
{
    const char *mats[2];
    int c;
    mats[0] = CC_B; mats[1] = CC_C;
    for (c = 0; c < 2; c++) {
        char text[2048];
        Scene s;
        RenderOptions o;
        Tiles a, b;
        test_furnace_text(text, sizeof text, mats[c]);
        if (!test_load_scene(t, &s, text)) return;
        render_options_default(&o);
        o.maxdepth = 40;
        o.spp = test_scaled(64, 16);
        if (!test_render_tiles(t, &s, &o, 8, 2, &a)) { scene_free(&s); return; }
        o.nee = 0;
        if (!test_render_tiles(t, &s, &o, 8, 2, &b)) { scene_free(&s); return; }
        scene_free(&s);
        if (!test_tiles_agree(t, &a, &b, 2e-3, mats[c])) return;
    }
}

/* pbrt-v4 (commit 5f7a6068) on test_furnace_text's scene with CC_A, CC_B, CC_C and
   "Integrator "path" "integer maxdepth" [ 40 ]" added: pbrt --seed S --spp 1024
   --outfile x_S.pfm x.pbrt, S = 1..8, per 2 x 2 tile the mean luminance over the 8
   images and its standard error (as PBRT_TILES).  CC_C has a rough coat, whose f
   pbrt-v4 biases (layered.c section 2), so its row is pbrt-v4's BSDF sampling
   alone (unbiased): "Integrator "simplepath" "integer maxdepth" [ 40 ] "bool
   samplelights" false"; its path integrator gives 0.24107 +- 0.00042 for the
   image, 0.25% above its own BSDF sampling (0.24048 +- 0.00039; specnee 0.23992 +-
   0.00029 at 12 x 1024 spp). */
static const double PBRT_CC_TILES[3][4][2] = {
    { { 0.62833, 0.00015 }, { 0.62840, 0.00017 }, { 0.62826, 0.00016 }, { 0.62822, 0.00009 } },
    { { 0.30319, 0.00045 }, { 0.30181, 0.00078 }, { 0.30272, 0.00097 }, { 0.30367, 0.00068 } },
    { { 0.23997, 0.00075 }, { 0.24035, 0.00077 }, { 0.24064, 0.00026 }, { 0.24097, 0.00080 } },
};

static void test_cc_against_pbrt(T *t)
{
    const char *mats[3];
    int c;
    mats[0] = CC_A; mats[1] = CC_B; mats[2] = CC_C;
    for (c = 0; c < 3; c++) {
        char text[2048];
        test_furnace_text(text, sizeof text, mats[c]);
        tiles_vs_pbrt(t, text, 40, test_scaled(256, 32), PBRT_CC_TILES[c], mats[c]);
        if (t->failed) return;
    }
}

/* A small scene after pbrt-v4-scenes' killeroos/killeroo-coated-gold.pbrt (its
   camera, disk light, distant light from the camera and walls; a gold sphere for
   the killeroo, a grey floor for the textured one, 32 x 24 pixels), with that
   scene's material: interface.roughness 0.02 and conductor.roughness 0.002 over
   metal-Au.  smooth = 1: the coat made smooth (interface.roughness 0). */
static void gold_text(char *text, size_t n, int smooth, int distant)
{
    snprintf(text, n,
             "LookAt 200 250 70  0 33 -50  0 0 1\n"
             "Camera \"perspective\" \"float fov\" [ 38 ]\n"
             "Film \"rgb\" \"string filename\" \"t.pfm\" \"integer xresolution\" [ 32 ] "
             "\"integer yresolution\" [ 24 ]\n"
             "WorldBegin\n"
             "AttributeBegin\n Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
             " AreaLightSource \"diffuse\" \"rgb L\" [ 50 50 50 ]\n Translate 0 0 800\n"
             " ReverseOrientation\n Shape \"disk\" \"float radius\" [ 150 ]\nAttributeEnd\n"
             "%s"
             "AttributeBegin\n Material \"diffuse\" \"rgb reflectance\" [ 0.25 0.25 0.25 ]\n"
             " Translate 0 0 -140\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 2 3 0 ] \"point3 P\" "
             "[ -400 -400 0 400 -400 0 400 400 0 -400 400 0 ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 2 3 0 ] \"point3 P\" "
             "[ -400 -400 0 400 -400 0 400 -400 1000 -400 -400 1000 ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 2 3 0 ] \"point3 P\" "
             "[ -400 -400 0 -400 400 0 -400 400 1000 -400 -400 1000 ]\nAttributeEnd\n"
             "AttributeBegin\n Material \"coatedconductor\" \"spectrum conductor.k\" \"metal-Au-k\" "
             "\"spectrum conductor.eta\" \"metal-Au-eta\" %s\"float conductor.roughness\" 0.002\n"
             " Translate 0 33 -80\n Shape \"sphere\" \"float radius\" [ 60 ]\nAttributeEnd\n",
             distant ? "AttributeBegin\n CoordSysTransform \"camera\"\n"
                       " LightSource \"distant\" \"rgb L\" [ 0.2 0.2 0.2 ]\nAttributeEnd\n" : "",
             smooth ? "" : "\"float interface.roughness\" 0.02 ");
}

/* pbrt-v4 (commit 5f7a6068) on gold_text with "Integrator "path" "integer maxdepth"
   [ 5 ]" added, pbrt --seed S --spp 1024 --outfile x_S.pfm x.pbrt, S = 1..8, tiles
   as above.  Row 0: the smooth coat with the distant light.  Row 1: the scene's
   rough coat without the distant light, rendered by pbrt-v4's BSDF sampling alone
   ("Integrator "simplepath" "integer maxdepth" [ 5 ] "bool samplelights" false",
   which cannot reach a delta light), which uses pbrt-v4's unbiased Sample_f only:
   image mean 0.24671 +- 0.00063, specnee 0.24670 +- 0.00019 (8 x 1024 spp), while
   pbrt-v4's path integrator, whose NEE uses its biased rough-coat f, gives
   0.25195 +- 0.00030, 2.1% brighter.  With the distant light and the rough coat:
   pbrt-v4 0.26176 +- 0.00044, specnee 0.25754 +- 0.00031 (1.6%; the top right
   tile, the highlight, 0.27792 against 0.27149: 2.4%). */
static const double PBRT_GOLD_TILES[2][4][2] = {
    { { 0.26209, 0.00069 }, { 0.28729, 0.00080 }, { 0.24814, 0.00032 }, { 0.25878, 0.00026 } },
    { { 0.24337, 0.00186 }, { 0.25760, 0.00069 }, { 0.23911, 0.00074 }, { 0.24676, 0.00060 } },
};

static void test_cc_gold_scene(T *t)
{
    char text[4096];
    gold_text(text, sizeof text, 1, 1);
    tiles_vs_pbrt(t, text, 5, test_scaled(256, 32), PBRT_GOLD_TILES[0], "gold, smooth coat");
    if (t->failed) return;
    gold_text(text, sizeof text, 0, 0);
    tiles_vs_pbrt(t, text, 5, test_scaled(256, 32), PBRT_GOLD_TILES[1], "gold, rough coat");
}

/* ---------------------------------------------------------------- parsing */

static void test_parse(T *t)
{
    Scene s;
    const Material *m;
    if (!test_load_scene(t, &s, "WorldBegin\nMaterial \"coateddiffuse\"\n"
                         "Shape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, m->type == MAT_COATED_DIFFUSE, "type %d", (int)m->type);
    CHECK(t, albedo_eval(&m->reflectance, 500) == 0.5f && spec_eval(m->eta, 500) == 1.5f &&
          spec_eval(&m->extra->albedo, 500) == 0.0f && m->thickness == 0.01f && m->hg_g == 0.0f &&
          m->maxdepth == 10 && m->nsamples == 1 && m->alpha == 0.0f,
          "defaults: R %g eta %g albedo %g thickness %g g %g maxdepth %d nsamples %d alpha %g",
          albedo_eval(&m->reflectance, 500), spec_eval(m->eta, 500), spec_eval(&m->extra->albedo, 500),
          m->thickness, m->hg_g, m->maxdepth, m->nsamples, m->alpha);
    scene_free(&s);
    if (!test_load_scene(t, &s, "WorldBegin\nMaterial \"coateddiffuse\" \"float roughness\" 0.25 "
                         "\"float eta\" 1.2 \"float thickness\" 0.5 \"float g\" -0.5 "
                         "\"integer maxdepth\" 3 \"integer nsamples\" 4\nShape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, m->alpha == 0.5f && spec_eval(m->eta, 700) == 1.2f && m->thickness == 0.5f &&
          m->hg_g == -0.5f && m->maxdepth == 3 && m->nsamples == 4, "parameters not read");
    scene_free(&s);
    {   /* pbrt-v4's LayeredBxDF takes max(thickness, FLT_MIN): 0 and -1 (exporters write 0) are
           the thinnest slab, as a textured thickness is (material.c); only huge ones are refused */
        static const char *const thin[2] = { "0", "-1" };
        int k;
        for (k = 0; k < 2; k++) {
            char text[160];
            snprintf(text, sizeof text, "WorldBegin\nMaterial \"coateddiffuse\" \"float thickness\" %s\n"
                     "Shape \"sphere\"\n", thin[k]);
            if (!test_load_scene(t, &s, text)) return;
            m = &s.materials[s.n_materials - 1];
            CHECK(t, m->thickness == FLT_MIN, "thickness %s read as %g, want FLT_MIN", thin[k], m->thickness);
            scene_free(&s);
        }
    }
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"float thickness\" 1e39\n", 2, "thickness", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\"\n \"integer maxdepth\" 0\n", 3, "maxdepth", ">= 1");
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"integer nsamples\" 0\n", 2, "nsamples", ">= 1");
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"float g\" 1\n", 2, "\"float g\"", "(-1, 1)");
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"float g\" -1\n", 2, "\"float g\"", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\"\n \"spectrum albedo\" [ 400 0.5 700 1.5 ]\n", 3,
                     "albedo", "[0,1]");
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\"\n \"spectrum eta\" [ 400 1.5 700 -1 ]\n", 3,
                     "the coat's \"eta\"", ">= 0");
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"float eta\" 0\n", 2, "eta", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"texture albedo\" \"t\"\n", 2,
                     "no texture named", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"coateddiffuse\" \"texture reflectance\" \"t\"\n", 2,
                     "no texture named", NULL);
}

static void test_cc_parse(T *t)
{
    Scene s;
    const Material *m;
    Spectrum cu;
    if (!test_load_scene(t, &s, "WorldBegin\nMaterial \"coatedconductor\"\nShape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    spec_named(&cu, "metal-Cu-k");
    CHECK(t, m->type == MAT_COATED_CONDUCTOR, "type %d", (int)m->type);
    CHECK(t, spec_eval(m->eta, 500) == 1.5f && spec_eval(&m->extra->albedo, 500) == 0.0f &&
          m->thickness == 0.01f && m->hg_g == 0.0f && m->maxdepth == 10 && m->nsamples == 1 &&
          m->alpha == 0.0f && m->cond_alpha == 0.0f && spec_eval(&m->extra->k, 600) == spec_eval(&cu, 600),
          "defaults: eta %g albedo %g thickness %g g %g maxdepth %d nsamples %d alphas %g %g k %g",
          spec_eval(m->eta, 500), spec_eval(&m->extra->albedo, 500), m->thickness, m->hg_g, m->maxdepth,
          m->nsamples, m->alpha, m->cond_alpha, spec_eval(&m->extra->k, 600));
    scene_free(&s);
    if (!test_load_scene(t, &s, "WorldBegin\nTexture \"r\" \"float\" \"constant\" \"float value\" 0.09\n"
                         "Material \"coatedconductor\" \"float interface.roughness\" 0.25 "
                         "\"texture conductor.roughness\" \"r\" \"float interface.eta\" 1.2 "
                         "\"float thickness\" 0.5 \"float g\" -0.5 \"rgb albedo\" [ 0.5 0.5 0.5 ] "
                         "\"integer maxdepth\" 3 \"integer nsamples\" 4 \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                         "Shape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, m->alpha == 0.5f && m->cond_alpha_tex == 1 && spec_eval(m->eta, 700) == 1.2f &&
          m->thickness == 0.5f && m->hg_g == -0.5f && m->maxdepth == 3 && m->nsamples == 4 &&
          spec_eval(&m->extra->cond_eta, 600) == 1.0f && fabsf(spec_eval(&m->extra->k, 600) - 2.0f) < 0.05f,
          "parameters not read: alpha %g tex %d k %g", m->alpha, m->cond_alpha_tex, spec_eval(&m->extra->k, 600));
    {   /* the roughness texture at a point: alpha = sqrt(0.09) */
        MatPoint mp;
        SurfacePoint sp = test_flat_point();
        mat_point(m, &sp, LAM, 15u, &mp);
        CHECK(t, fabsf(mp.cond_alpha - 0.3f) < 1e-6f && mp.alpha == 0.5f, "mat_point: base alpha %g",
              mp.cond_alpha);
    }
    scene_free(&s);
    test_rejected_at(t, "WorldBegin\nMaterial \"coatedconductor\" \"rgb reflectance\" [ 1 1 1 ]\n"
                     " \"spectrum conductor.eta\" \"metal-Au-eta\"\n", 2, "reflectance", "not both");
    test_rejected_at(t, "WorldBegin\nMaterial \"coatedconductor\"\n \"spectrum interface.eta\" [ 400 1.5 700 -1 ]\n",
                     3, "the coat's \"eta\"", ">= 0");
    test_rejected_at(t, "WorldBegin\nMaterial \"coatedconductor\"\n \"float thickness\" 1e35\n", 3, "thickness", "> 0");
    test_rejected_at(t, "WorldBegin\nMaterial \"coatedconductor\" \"float roughness\" 0.1\n", 2, "roughness", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"coatedconductor\"\n \"spectrum conductor.k\" [ 400 -1 700 1 ]\n",
                     3, "conductor.k", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"coatedconductor\" \"float interface.eta\" 0\n", 2,
                     "interface.eta", NULL);
}

const TestCase tests_coated[] = {
    { "coated_eval_unbiased", test_eval_unbiased },
    { "coated_sample_weight_albedo", test_sample_weight_albedo },
    { "coated_pdf", test_pdf },
    { "coated_parse", test_parse },
    { "coated_nee_vs_bsdf", test_nee_vs_bsdf },
    { "coated_against_pbrt", test_against_pbrt },
    { "coatedconductor_limit_bare", test_cc_limit_bare },
    { "coatedconductor_smooth_series", test_cc_smooth_series },
    { "coatedconductor_walks", test_cc_walks },
    { "coatedconductor_nee_vs_bsdf", test_cc_nee_vs_bsdf },
    { "coatedconductor_against_pbrt", test_cc_against_pbrt },
    { "coatedconductor_gold_scene", test_cc_gold_scene },
    { "coatedconductor_parse", test_cc_parse },
    { NULL, NULL }
};
