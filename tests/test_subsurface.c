/* tests/test_subsurface.c - pbrt-v4's "subsurface" material (subsurface.c;
   THEORY §18).

   Checked: the Fresnel moments' polynomial fits against their integrals; the
   single-scattering term against its integral over depth; the
   Catmull-Rom tools (a line integrated and inverted exactly, the weights summing
   to 1); the profile's integral over the plane equal to the table's effective
   albedo rho_eff for several (rho, sigma_t) (the scaling (39)); the radius
   sampler against its density (chi-square); SubsurfaceFromDiffuse inverting
   rho_eff; the exit lobe Sw passing all the light that reaches it; a furnace (a
   wide flat slab under a uniform sky returns F + (1 - F) rho_eff of it);
   the same image for 1, 2 and 3 threads; pbrt-v4's precedence and the
   refusals; pbrt-v4's images of two subsurface spheres. */
#include "test.h"
#include "../parser.h"
#include <stdlib.h>
#include <string.h>

/* int_0^1 Fr(mu, eta) mu^i dmu by the midpoint rule (microfacet.c's Fresnel). */
static double fresnel_integral(double eta, int i)
{
    const int n = 20000;
    double s = 0.0;
    int k;
    for (k = 0; k < n; k++) {
        double mu = (k + 0.5) / n;
        s += fresnel_dielectric((float)mu, (float)eta) * (i == 1 ? mu : mu * mu);
    }
    return s / n;
}

/* pbrt-v4's fits F_i(eta) are int_0^1 Fr(mu, 1/eta) mu^i dmu (Fr of light going
   from the index-eta side out): within 0.002 over the range scenes use. */
static void test_sss_fresnel_moments(T *t)
{
    static const double etas[] = { 0.5, 0.7, 1.0 / 1.33, 1.2, 1.33, 1.5, 2.0 };
    int k;
    for (k = 0; k < (int)(sizeof etas / sizeof etas[0]); k++) {
        double e = etas[k], f1 = fresnel_integral(1.0 / e, 1), f2 = fresnel_integral(1.0 / e, 2);
        CHECK(t, fabs(fresnel_moment1(e) - f1) < 2e-3, "F1(%g) = %.5f, integral %.5f", e,
              fresnel_moment1(e), f1);
        CHECK(t, fabs(fresnel_moment2(e) - f2) < 2e-3, "F2(%g) = %.5f, integral %.5f", e,
              fresnel_moment2(e), f2);
    }
}

/* A spline through a line is the line: its integral, its inverse and its weights
   are exact; the weights sum to 1 everywhere. */
static void test_sss_catmull_rom(T *t)
{
    float x[7] = { 0.0f, 0.1f, 0.3f, 0.35f, 0.8f, 1.5f, 2.0f }, f[7], cdf[7], w[4];
    int k, off;
    for (k = 0; k < 7; k++) f[k] = 3.0f * x[k] + 1.0f;
    CHECK(t, fabsf(catmull_rom_integrate(x, f, 7, cdf) - 8.0f) < 1e-5f, "integral of 3x + 1 over [0, 2]");
    CHECK(t, fabsf(cdf[4] - (1.5f * 0.64f + 0.8f)) < 1e-5f, "running integral at 0.8: %g", cdf[4]);
    for (k = 0; k < 20; k++) {
        float v = 0.1f * k + 0.03f, y = 3.0f * v + 1.0f, s;
        CHECK(t, fabsf(catmull_rom_invert(x, f, 7, y) - v) < 1e-5f, "inverse at %g", y);
        CHECK(t, catmull_rom_weights(x, 7, v, &off, w), "weights at %g", v);
        s = w[0] + w[1] + w[2] + w[3];
        CHECK(t, fabsf(s - 1.0f) < 1e-5f, "weights at %g sum to %g", v, s);
    }
    CHECK(t, !catmull_rom_weights(x, 7, 2.5f, &off, w), "outside the knots: no weights");
}

/* The single-scattering exitance at radius r (g = 0): a beam refracted straight
   down scatters at depth t >= t_c = r sqrt(eta^2 - 1) (below t_c the way up is
   beyond the critical angle) and the light goes up the segment d = sqrt(r^2 +
   t^2) and out with the Fresnel transmission of the inside, cos o = t / d:
       E_ss = int_{t_c}^inf sigma_s e^{-sigma_t (t - t_c)} e^{-sigma_t (d + t_c)}
              / d^2 (1 / 4 pi) (1 - F(-cos o, eta)) cos o dt
   by 200000 midpoints in t's exponential CDF; bssrdf_single takes 100 (within
   0.3 % from r = 0.2 mean free paths on; the outside's Fresnel is 4-18 % off). */
static void test_sss_single_scattering(T *t)
{
    static const double radii[] = { 0.2, 0.4, 1.0, 2.5 };   /* (at 0.02: 1.3 %) */
    const double ss = 0.8, sa = 0.2, st = ss + sa, eta = 1.33;
    int i, k;
    for (i = 0; i < 4; i++) {
        const int n = 200000;
        double r = radii[i], tc = r * sqrt(eta * eta - 1.0), sum = 0.0, got;
        for (k = 0; k < n; k++) {
            double tt = tc - log(1.0 - (k + 0.5) / n) / st, d = sqrt(r * r + tt * tt), c = tt / d;
            sum += (ss / st) * exp(-st * (d + tc)) / (d * d) / (4.0 * SPECNEE_PI) *
                   (1.0 - fresnel_dielectric((float)-c, (float)eta)) * c;
        }
        sum /= n;
        got = bssrdf_single(ss, sa, 0.0, eta, r);
        CHECK(t, fabs(got - sum) < 0.01 * sum, "r %g: E_ss %.6g, integral %.6g", r, got, sum);
    }
}

/* The table for g = 0, eta = 1.33 (built once per test). */
static BssrdfTable *table_133(void)
{
    BssrdfTable *tb = (BssrdfTable *)malloc(sizeof *tb);
    if (tb) bssrdf_table_build(tb, 0.0f, 1.33f);
    return tb;
}

/* int Sr(r) 2 pi r dr over [0, rmax] by the midpoint rule on a log-spaced grid. */
static double profile_integral(const BssrdfTable *tb, float st, float rho, double rmax)
{
    const int n = 4000;
    double s = 0.0, lo = 1e-6 / st, a = log(rmax / lo);
    int k;
    for (k = 0; k < n; k++) {
        double r0 = lo * exp(a * k / n), r1 = lo * exp(a * (k + 1) / n), r = 0.5 * (r0 + r1);
        s += bssrdf_sr(tb, st, rho, (float)r) * 2.0 * SPECNEE_PI * r * (r1 - r0);
    }
    return s;
}

/* rho_eff interpolated at rho (the table's spline through its albedos). */
static double rho_eff_at(const BssrdfTable *tb, float rho)
{
    float w[4];
    double v = 0.0;
    int off, i;
    if (!catmull_rom_weights(tb->rho, SSS_RHO_N, rho, &off, w)) return -1.0;
    for (i = 0; i < 4; i++)
        if (w[i] != 0.0f) v += w[i] * tb->rho_eff[off + i];
    return v;
}

/* (39), (40): the profile of any sigma_t integrates over the plane to the
   effective albedo; rho_eff grows with rho, from 0, and stays below 1 up to rho
   = 0.9999 (at rho = 1, with no absorption, the diffusion approximation
   overshoots: 1.019). */
static void test_sss_profile_integral(T *t)
{
    static const float rhos[] = { 0.1f, 0.5f, 0.8f, 0.95f, 0.99f };
    static const float sts[] = { 0.5f, 4.0f, 60.0f };
    BssrdfTable *tb = table_133();
    int i, k;
    if (!tb) { CHECK(t, 0, "out of memory"); return; }
    CHECK(t, tb->rho_eff[0] == 0.0f, "rho 0 reflects nothing: %g", tb->rho_eff[0]);
    for (i = 1; i < SSS_RHO_N; i++)
        if (!(tb->rho_eff[i] > tb->rho_eff[i - 1])) break;
    CHECK(t, i == SSS_RHO_N && rho_eff_at(tb, 0.9999f) < 1.0 && tb->rho_eff[SSS_RHO_N - 1] < 1.02f,
          "rho_eff increasing, below 1 (%d: %g)", i, tb->rho_eff[SSS_RHO_N - 1]);
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) {
            double want = rho_eff_at(tb, rhos[i]);
            double got = profile_integral(tb, sts[k], rhos[i], tb->radius[SSS_R_N - 1] / sts[k]);
            CHECK(t, fabs(got - want) < 2e-3 * want + 1e-5, "rho %g, sigma_t %g: int Sr dA %.5f, rho_eff %.5f",
                  rhos[i], sts[k], got, want);
        }
    free(tb);
}

/* The radius sampler against its density p_r(r) 2 pi r (41), in 40 cells of
   equal probability under the density itself, for the hero's profile. */
static void test_sss_radius_chi2(T *t)
{
    static const float rhos[] = { 0.3f, 0.9f, 0.995f };
    BssrdfTable *tb = table_133();
    int c;
    if (!tb) { CHECK(t, 0, "out of memory"); return; }
    for (c = 0; c < 3; c++) {
        enum { CELLS = 40 };
        const float st = 3.0f;
        const int n = test_scaled(40000, 10000);
        double obs[CELLS] = { 0 }, ex[CELLS], rmax = tb->radius[SSS_R_N - 1] / st, edge[CELLS + 1];
        double total = profile_integral(tb, st, rhos[c], rmax) / rho_eff_at(tb, rhos[c]);
        Rng r;
        int k;
        /* cell edges: log-spaced over the radii the table covers */
        for (k = 0; k <= CELLS; k++) edge[k] = k == 0 ? 0.0 : 1e-3 / st * pow(rmax * st / 1e-3, (k - 1.0) / (CELLS - 1));
        for (k = 0; k < CELLS; k++)
            ex[k] = n * (profile_integral(tb, st, rhos[c], edge[k + 1]) -
                         (k ? profile_integral(tb, st, rhos[c], edge[k]) : 0.0)) / rho_eff_at(tb, rhos[c]) / total;
        rng_seed(&r, 77, (uint64_t)c);
        for (k = 0; k < n; k++) {
            float rad = bssrdf_sample_sr(tb, st, rhos[c], rng_float(&r));
            int i = 0;
            while (i < CELLS - 1 && rad >= edge[i + 1]) i++;
            obs[i] += 1.0;
        }
        CHECK(t, fabs(total - 1.0) < 2e-3, "rho %g: the density integrates to %.5f", rhos[c], total);
        CHECK_CHI2(t, obs, ex, CELLS, 3, NULL, "radius sampler, rho %g", rhos[c]);
    }
    free(tb);
}

/* SubsurfaceFromDiffuse: the albedo it finds for a reflectance R has rho_eff R,
   and the mean free path is 1 / sigma_t. */
static void test_sss_from_albedo(T *t)
{
    BssrdfTable *tb = table_133();
    int k;
    if (!tb) { CHECK(t, 0, "out of memory"); return; }
    for (k = 1; k < 10; k++) {
        float R = 0.1f * k, sa, ss, mfp = 0.25f;
        bssrdf_from_albedo(tb, R, mfp, &sa, &ss);
        CHECK(t, fabsf(1.0f / (sa + ss) - mfp) < 1e-5f, "R %g: mfp %g", R, 1.0f / (sa + ss));
        CHECK(t, fabs(rho_eff_at(tb, ss / (sa + ss)) - R) < 1e-4, "R %g: rho %g has rho_eff %.5f", R,
              ss / (sa + ss), rho_eff_at(tb, ss / (sa + ss)));
    }
    free(tb);
}

/* (44): int Sw(wi) cos dwi / eta^2 = 1, the exit passes what reaches it (the
   Fresnel moment's fit: within 0.5 %); the sampler's f cos / pdf is Sw cos /
   (cos / pi) and the evaluation agrees with the sample. */
static void test_sss_exit_lobe(T *t)
{
    static const float etas[] = { 1.33f, 1.5f, 1.2f };
    Subsurface ss;
    Material m;
    SurfacePoint sp;
    int e;
    memset(&m, 0, sizeof m);
    memset(&sp, 0, sizeof sp);
    m.type = MAT_SUBSURFACE_EXIT;
    m.sss = &ss;
    sp.ng = sp.ns = v3_norm(v3(0.3f, -0.2f, 0.9f));
    for (e = 0; e < 3; e++) {
        const int n = 20000;
        double s = 0.0;
        int k;
        Rng r;
        ss.eta = etas[e];
        rng_seed(&r, 5, (uint64_t)e);
        for (k = 0; k < n; k++) {
            BsdfSample bs;
            float f[HERO_N], pdf[HERO_N], u1 = rng_float(&r), u2 = rng_float(&r);
            if (!bsdf_sample(&m, &sp, sp.ns, NULL, 1u, 0.0f, u1, u2, &bs)) continue;
            s += bs.f[0] * v3_dot(bs.wi, sp.ns) / bs.pdf;
            bsdf_eval(&m, &sp, sp.ns, bs.wi, NULL, 1u, f, pdf);
            if (fabsf(f[0] - bs.f[0]) > 1e-6f * f[0] || fabsf(pdf[0] - bs.pdf) > 1e-5f * pdf[0]) break;
            if (fabsf(bs.eta2[0] * etas[e] * etas[e] - 1.0f) > 1e-6f) break;
        }
        CHECK(t, k == n, "eta %g: sample %d disagrees with the evaluation", etas[e], k);
        s /= n * etas[e] * etas[e];
        CHECK(t, fabs(s - 1.0) < 5e-3, "eta %g: int Sw cos / eta^2 = %.5f", etas[e], s);
    }
}

/* Luminance of an image. */
static double image_Y(const Image *im)
{
    double acc = 0.0;
    int i;
    for (i = 0; i < im->w * im->h; i++)
        acc += 0.212671 * im->rgb[3 * i] + 0.715160 * im->rgb[3 * i + 1] + 0.072169 * im->rgb[3 * i + 2];
    return acc / (im->w * im->h);
}

static int render_Y(T *t, const char *text, int spp, int seed, int threads, Image *im)
{
    Scene s;
    RenderOptions o;
    RenderStats st;
    Error err;
    int ok;
    if (!test_load_scene(t, &s, text)) return 0;
    render_options_default(&o);
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    ok = render(&s, &o, im, &st, &err);
    if (!ok) test_failf(t, __FILE__, __LINE__, "render: %s", err.msg);
    scene_free(&s);
    return ok;
}

/* A furnace: a flat slab (a square 4000 mean free paths wide, seen from above
   at normal incidence) under a sky of radiance L returns F(0) L by its
   surface and (1 - F(0)) rho_eff L by its inside (the probe of the normal axis
   always finds the plane; the tangent axes never do, and (42) weighs them 0),
   less the 0.1 % beyond r_max.  sigma_s 1, sigma_a 0.1 per unit, eta 1.33. */
static void test_sss_furnace(T *t)
{
    static const char *const sky =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 4 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
        "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n";
    static const char *const slab =
        "Material \"subsurface\" \"spectrum sigma_a\" [ 300 0.1 830 0.1 ] \"spectrum sigma_s\" [ 300 1 830 1 ] "
        "\"float eta\" 1.33\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
        "\"point3 P\" [ -2000 -2000 0  2000 -2000 0  2000 2000 0  -2000 2000 0 ]\n";
    char buf[2048];
    Image a, b;
    BssrdfTable *tb = table_133();
    double F0 = (0.33 / 2.33) * (0.33 / 2.33), want, got, env;
    if (!tb) { CHECK(t, 0, "out of memory"); return; }
    want = F0 + (1.0 - F0) * rho_eff_at(tb, 1.0f / 1.1f) * 0.999;
    free(tb);
    snprintf(buf, sizeof buf, "%s%s", sky, slab);
    if (!render_Y(t, sky, 4, 1, 2, &a)) return;
    if (!render_Y(t, buf, test_scaled(256, 64), 1, 2, &b)) { img_free(&a); return; }
    env = image_Y(&a);
    got = image_Y(&b) / env;
    CHECK(t, fabs(got - want) < 0.01 * want, "slab returns %.5f of the sky, want F + (1 - F) rho_eff = %.5f",
          got, want);
    img_free(&a);
    img_free(&b);
}

/* Two subsurface spheres on a grey floor: Skin1 by name (scale 10, eta 1.5,
   smooth) under a distant light; a reflectance and mfp with roughness 0.1 (not
   remapped) under a spherical lamp (NEE at the rough entry and at the exit). */
#define SSS_HEAD \
    "LookAt 0 -4 2.5  0 0 0.6  0 0 1\nCamera \"perspective\" \"float fov\" [ 35 ]\n" \
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n" \
    "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
#define SSS_FLOOR_SPHERE \
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ]\n"
static const char *const SSS_SKIN =
    SSS_HEAD
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ -1 1 3 ] \"point3 to\" [ 0 0 0 ]\n"
    SSS_FLOOR_SPHERE
    "Material \"subsurface\" \"string name\" \"Skin1\" \"float scale\" 10 \"float eta\" 1.5\n"
    "AttributeBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n";
static const char *const SSS_ROUGH =
    SSS_HEAD
    "AttributeBegin\nTranslate 1.5 -1 3\nAreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
    "Shape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
    SSS_FLOOR_SPHERE
    "Material \"subsurface\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"rgb mfp\" [ 0.2 0.1 0.05 ] "
    "\"float uroughness\" 0.1 \"float vroughness\" 0.1 \"bool remaproughness\" false \"float eta\" 1.33\n"
    "AttributeBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n";

/* The head of pbrt-v4's collection in small: a textured reflectance and an rgb mfp
   (Jensen's Skin1 in scene units), roughness 0.1 not remapped, under a sky and a
   distant light.  (maxdepth 5 in every scene here: test_against_pbrt_y renders at
   specnee's default depth.) */
static const char *const SSS_TEXTURED =
    "LookAt 0 -4 2.5  0 0 0.6  0 0 1\nCamera \"perspective\" \"float fov\" [ 35 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.3 0.35 0.4 ]\n"
    "LightSource \"distant\" \"float scale\" [ 2 ] \"point3 from\" [ 1 -1 2 ] \"point3 to\" [ 0 0 0 ]\n"
    SSS_FLOOR_SPHERE
    "Texture \"albedo\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 8 ] \"float vscale\" [ 4 ] "
    "\"rgb tex1\" [ 0.9 0.6 0.4 ] \"rgb tex2\" [ 0.3 0.5 0.8 ]\n"
    "Material \"subsurface\" \"bool remaproughness\" false \"float uroughness\" 0.1 \"float vroughness\" 0.1 "
    "\"float eta\" 1.33 \"texture reflectance\" \"albedo\" \"rgb mfp\" [ 0.13 0.095 0.067 ]\n"
    "AttributeBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n";

/* The path is a function of the ray and the sample alone: 1, 2, 3 threads give
   the same bits. */
static void test_sss_threads(T *t)
{
    Image a, b, c;
    if (!render_Y(t, SSS_ROUGH, 2, 7, 1, &a)) return;
    if (!render_Y(t, SSS_ROUGH, 2, 7, 2, &b)) { img_free(&a); return; }
    if (!render_Y(t, SSS_ROUGH, 2, 7, 3, &c)) { img_free(&a); img_free(&b); return; }
    CHECK(t, image_Y(&a) > 0.0, "the scene is black");
    CHECK(t, !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * a.w * a.h) &&
          !memcmp(a.rgb, c.rgb, sizeof(float) * 3 * a.w * a.h),
          "images of 1, 2, 3 threads differ: Y %.9g %.9g %.9g", image_Y(&a), image_Y(&b), image_Y(&c));
    img_free(&a); img_free(&b); img_free(&c);
}

/* pbrt-v4's precedence: a name wins (g forced to 0); sigma_a with sigma_s; else a
   reflectance (mfp 1 by default); else whole milk's coefficients.  Scale, eta,
   roughness (remapped unless told) as read. */
static void test_sss_params(T *t)
{
    Scene s;
    const Material *m;
    if (!test_load_scene(t, &s, "WorldBegin\nMaterial \"subsurface\" \"string name\" \"Ketchup\" "
                         "\"float g\" 0.5 \"float scale\" 2\nShape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, m->type == MAT_SUBSURFACE && m->sss->g == 0.0f && m->sss->scale == 2.0f &&
          !m->sss->from_albedo && fabsf(m->sss->eta - 1.33f) < 1e-6f && m->alpha == 0.0f,
          "named: g %g scale %g eta %g", m->sss->g, m->sss->scale, m->sss->eta);
    /* Jensen et al. 2001: sigma'_s (0.18, 0.07, 0.03), sigma_a (0.061, 0.97, 1.45) per mm */
    CHECK(t, fabsf(spec_eval(&m->sss->sigma_s, 650.0f) - 0.18f) < 0.05f &&
          fabsf(spec_eval(&m->sss->sigma_a, 450.0f) - 1.45f) < 0.3f,
          "Ketchup: sigma_s(650) %g, sigma_a(450) %g", spec_eval(&m->sss->sigma_s, 650.0f),
          spec_eval(&m->sss->sigma_a, 450.0f));
    scene_free(&s);
    if (!test_load_scene(t, &s, "WorldBegin\nMaterial \"subsurface\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] "
                         "\"float roughness\" 0.25\nShape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, m->sss->from_albedo && spec_eval(&m->sss->mfp, 500.0f) == 1.0f && fabsf(m->alpha - 0.5f) < 1e-6f,
          "reflectance: mfp %g, alpha %g", spec_eval(&m->sss->mfp, 500.0f), m->alpha);
    scene_free(&s);
    if (!test_load_scene(t, &s, "WorldBegin\nMaterial \"subsurface\"\nShape \"sphere\"\n")) return;
    m = &s.materials[s.n_materials - 1];
    CHECK(t, !m->sss->from_albedo && fabsf(spec_eval(&m->sss->sigma_s, 550.0f) - 3.2f) < 0.3f,
          "default: whole milk's sigma_s(550) %g", spec_eval(&m->sss->sigma_s, 550.0f));
    CHECK(t, !s.settings.sss_ignored, "no Integrator: volpath's subsurface scattering");
    scene_free(&s);
    /* pbrt-v4's other integrators render the boundary alone (with a warning) */
    if (!test_load_scene(t, &s, "Integrator \"path\"\nWorldBegin\nMaterial \"subsurface\"\nShape \"sphere\"\n"))
        return;
    CHECK(t, s.settings.sss_ignored, "Integrator \"path\": the dielectric boundary alone");
    scene_free(&s);
}

static void test_sss_errors(T *t)
{
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"string name\" \"Blood\"\n", "t.pbrt",
                 "t.pbrt:2: Material \"subsurface\": \"string name\" \"Blood\": no such named medium");
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"rgb sigma_a\" [ 1 1 1 ]\n", "t.pbrt",
                 "t.pbrt:2: Material \"subsurface\": \"sigma_a\" given without \"sigma_s\"");
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                 "  \"spectrum mfp\" [ 400 1 700 -1 ]\n", "t.pbrt", "t.pbrt:3: \"spectrum mfp\": value");
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] "
                 "\"spectrum mfp\" [ 400 0 700 0 ]\n", "t.pbrt", "a mean free path must be > 0");
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"float g\" 1\n", "t.pbrt",
                 "\"float g\" 1 must be in (-1, 1)");
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"float eta\" -1\n", "t.pbrt",
                 "\"float eta\" -1 must be > 0");
    test_refused(t, "WorldBegin\n", "Material \"subsurface\" \"float scale\" -1\n", "t.pbrt",
                 "\"float scale\" -1 must be >= 0");
    test_refused(t, "WorldBegin\nTexture \"r\" \"float\" \"checkerboard\"\n",
                 "Material \"subsurface\" \"texture uroughness\" \"r\" \"float vroughness\" -0.5\n", "t.pbrt",
                 "t.pbrt:3: Material \"subsurface\": roughness (0, -0.5) must be within [0, 1e4]");
}

/* pbrt-v4 (mmp/pbrt-v4 5f7a6068, `pbrt --seed S --spp 1024` for S = 1..4, 32 x
   32) rendered SSS_SKIN, SSS_ROUGH and SSS_TEXTURED; luminance of the image and its quadrants
   (top left first), mean over the seeds and its standard error. */
static const double PBRT_SSS_SKIN_Y[5][2] = {
    { 0.136566, 1.2e-05 }, { 0.094407, 4.1e-05 }, { 0.111958, 8.2e-05 }, { 0.076788, 5.7e-05 }, { 0.263111, 4.2e-05 },
};
static const double PBRT_SSS_ROUGH_Y[5][2] = {
    { 0.038082, 1.2e-05 }, { 0.074211, 9.8e-05 }, { 0.017945, 5.1e-05 }, { 0.048269, 2.1e-05 }, { 0.011901, 1.5e-05 },
};
static const double PBRT_SSS_TEXTURED_Y[5][2] = {
    { 0.373989, 0.00013 }, { 0.456521, 0.0004 }, { 0.361582, 0.00026 }, { 0.376012, 0.00019 }, { 0.301841, 0.00038 },
};

static void test_sss_against_pbrt(T *t)
{
    test_against_pbrt_y(t, SSS_SKIN, 3, PBRT_SSS_SKIN_Y, 5e-3, "skin");
    test_against_pbrt_y(t, SSS_ROUGH, 5, PBRT_SSS_ROUGH_Y, 5e-3, "rough");
    test_against_pbrt_y(t, SSS_TEXTURED, 9, PBRT_SSS_TEXTURED_Y, 5e-3, "textured");
}

const TestCase tests_subsurface[] = {
    { "sss_fresnel_moments", test_sss_fresnel_moments },
    { "sss_catmull_rom", test_sss_catmull_rom },
    { "sss_single_scattering", test_sss_single_scattering },
    { "sss_profile_integral", test_sss_profile_integral },
    { "sss_radius_chi2", test_sss_radius_chi2 },
    { "sss_from_albedo", test_sss_from_albedo },
    { "sss_exit_lobe", test_sss_exit_lobe },
    { "sss_furnace", test_sss_furnace },
    { "sss_threads", test_sss_threads },
    { "sss_params", test_sss_params },
    { "sss_errors", test_sss_errors },
    { "sss_against_pbrt", test_sss_against_pbrt },
    { NULL, NULL }
};
