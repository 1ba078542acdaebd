/* tests/test_dielrough.c - a textured and an anisotropic roughness on
   "dielectric" and on the boundary of "subsurface" (parser.c
   microfacet_alphas; material.c dielectric_alphas, mat_point, mat_is_delta,
   mat_needs_tangent).

   Checked: at each hit the BSDF is the one of the numeric roughness the texture
   gives there, remapped (sqrt) unless "remaproughness" is false, bit for bit; a
   hit whose alpha is below 1e-3 is smooth (pbrt-v4's EffectivelySmooth), and so
   is a numeric alpha that small; a constant texture renders the same image as
   its number (bit for bit where it is rough; where it is 0, as the same mean: NEE
   is then tried at a smooth hit, which adds 0 but draws other random numbers);
   the subsurface boundary likewise; the refusals (a roughness out of range, a
   spectrum texture, a missing one) at their file:line; pbrt-v4's images frozen.

   Anisotropic roughness (u and v differ, numbers or textures; pbrt-v4's
   DielectricBxDF over an anisotropic TrowbridgeReitzDistribution): alpha_x
   along the shading frame's s axis (dp/du), alpha_y along t; swapping u and v
   is the same BSDF turned by 90 degrees about n; sampled and evaluated pdfs
   agree, the pdf integrates to the fraction of samples that succeed, the
   sampled weights' mean is the integral of f |cos| (both by uniform sphere
   Monte Carlo), f(a, b)/eta_a^2 = f(b, a)/eta_b^2, and the sampled directions
   pass a chi-square against the pdf; one axis 0 beside a rough one is rough
   (each alpha at least 1e-4, as pbrt-v4); pbrt-v4's images frozen for glass and
   for the subsurface boundary. */
#include "test.h"
#include <string.h>

static const char *const DR_HEAD =
    "LookAt 0 -3 5  0 0 0.8  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 8 ]\nWorldBegin\n";

/* A checkered floor under a disk lamp: the glass's surroundings. */
#define DR_ROOM \
    "Texture \"ch\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 8 ] \"float vscale\" [ 8 ] " \
    "\"rgb tex1\" [ 0.8 0.2 0.1 ] \"rgb tex2\" [ 0.1 0.3 0.8 ]\n" \
    "Material \"diffuse\" \"texture reflectance\" \"ch\"\n" \
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ] " \
    "\"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n" \
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 16 16 16 ]\nTranslate 0 2 4\nReverseOrientation\n" \
    "Shape \"disk\" \"float radius\" [ 1 ]\nAttributeEnd\n"

static int load_dr(T *t, Scene *s, const char *body)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", DR_HEAD, body);
    return test_load_scene(t, s, buf);
}

/* A hit at (u, v) on a surface facing +z. */
static SurfacePoint dr_point(float u, float v)
{
    SurfacePoint sp;
    memset(&sp, 0, sizeof sp);
    sp.ng = sp.ns = v3(0.0f, 0.0f, 1.0f);
    sp.u = u;
    sp.v = v;
    return sp;
}

/* bsdf_eval of materials a and b at sp for one pair of directions (a reflection
   and a refraction): 1 when f and pdf are the same floats. */
static int dr_same_eval(const Material *a, const Material *b, const SurfacePoint *sp, float *fa)
{
    static const float lam[HERO_N] = { 550.0f, 450.0f, 650.0f, 500.0f };
    float f1[HERO_N], p1[HERO_N], f2[HERO_N], p2[HERO_N];
    Vec3 wo = v3_norm(v3(0.3f, 0.1f, 1.0f)), wi[2];
    int k, same = 1;
    wi[0] = v3_norm(v3(-0.2f, -0.15f, 1.0f));
    wi[1] = v3_norm(v3(-0.1f, -0.05f, -1.0f));
    *fa = 0.0f;
    for (k = 0; k < 2; k++) {
        bsdf_eval(a, sp, wo, wi[k], lam, 15u, f1, p1);
        bsdf_eval(b, sp, wo, wi[k], lam, 15u, f2, p2);
        same = same && !memcmp(f1, f2, sizeof f1) && !memcmp(p1, p2, sizeof p1);
        *fa += f1[0];
    }
    return same;
}

/* Whether a sample of material m at sp is a delta lobe. */
static int dr_sample_delta(const Material *m, const SurfacePoint *sp)
{
    static const float lam[HERO_N] = { 550.0f, 450.0f, 650.0f, 500.0f };
    BsdfSample bs;
    Vec3 wo = v3_norm(v3(0.3f, 0.1f, 1.0f));
    if (!bsdf_sample(m, sp, wo, lam, 15u, 0.9f, 0.3f, 0.6f, &bs)) return -1;
    return bs.delta;
}

/* Per hit: a bilerp roughness (v00 0, v10 0.3, v01 1e-7, v11 4e-6) is, at each
   corner, the dielectric of that number; a hit of alpha below 1e-3 is smooth. */
static void test_dielrough_per_hit(T *t)
{
    Scene s;
    SurfacePoint sp;
    const Material *tex, *tex_nr, *n03, *n03_nr, *n0, *n1e7, *n4e6;
    float f;
    if (!load_dr(t, &s,
                 "Texture \"r\" \"float\" \"bilerp\" \"float v00\" 0 \"float v10\" 0.3 \"float v01\" 1e-7 "
                 "\"float v11\" 4e-6\n"
                 "Material \"dielectric\" \"texture roughness\" \"r\"\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"texture uroughness\" \"r\" \"texture vroughness\" \"r\" "
                 "\"bool remaproughness\" false\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float roughness\" 0.3\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float roughness\" 0.3 \"bool remaproughness\" false\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float roughness\" 0\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float roughness\" 1e-7\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float roughness\" 4e-6\nShape \"sphere\"\n"))
        return;
    tex = &s.materials[s.shapes[0].material];
    tex_nr = &s.materials[s.shapes[1].material];
    n03 = &s.materials[s.shapes[2].material];
    n03_nr = &s.materials[s.shapes[3].material];
    n0 = &s.materials[s.shapes[4].material];
    n1e7 = &s.materials[s.shapes[5].material];
    n4e6 = &s.materials[s.shapes[6].material];
    CHECK(t, tex->alpha_tex > 0 && tex_nr->alpha_tex == tex->alpha_tex && !tex_nr->remap && tex->remap,
          "the texture and its remap were not kept");
    CHECK(t, !mat_is_delta(tex) && !mat_is_delta(tex_nr), "a textured roughness counted as a delta material");
    CHECK(t, mat_is_delta(n0) && mat_is_delta(n1e7) && !mat_is_delta(n4e6),
          "numeric roughness 0, 1e-7 (alpha 3e-4), 4e-6 (alpha 2e-3): delta %d %d %d, want 1 1 0",
          mat_is_delta(n0), mat_is_delta(n1e7), mat_is_delta(n4e6));
    sp = dr_point(1.0f, 0.0f);                          /* v10: roughness 0.3 */
    CHECK(t, dr_same_eval(tex, n03, &sp, &f) && f > 0.0f, "at (1, 0): not the dielectric of roughness 0.3");
    CHECK(t, dr_same_eval(tex_nr, n03_nr, &sp, &f) && f > 0.0f,
          "at (1, 0), not remapped: not the dielectric of alpha 0.3");
    CHECK(t, dr_sample_delta(tex, &sp) == 0, "roughness 0.3 sampled as a delta lobe");
    sp = dr_point(1.0f, 1.0f);                          /* v11: 4e-6, alpha 2e-3: rough */
    CHECK(t, dr_same_eval(tex, n4e6, &sp, &f) && dr_sample_delta(tex, &sp) == 0,
          "at (1, 1): not the rough dielectric of roughness 4e-6");
    sp = dr_point(0.0f, 0.0f);                          /* v00: 0, smooth */
    CHECK(t, dr_sample_delta(tex, &sp) == 1 && dr_same_eval(tex, n0, &sp, &f) && f == 0.0f,
          "at (0, 0), roughness 0: not a smooth interface");
    sp = dr_point(0.0f, 1.0f);                          /* v01: 1e-7, alpha 3e-4: smooth */
    CHECK(t, dr_sample_delta(tex, &sp) == 1 && dr_same_eval(tex, n0, &sp, &f) && f == 0.0f,
          "at (0, 1), alpha 3e-4: not smooth (pbrt-v4's EffectivelySmooth)");
    sp = dr_point(1.0f, 1.0f);                          /* not remapped: alpha 4e-6, smooth */
    CHECK(t, dr_sample_delta(tex_nr, &sp) == 1, "at (1, 1), alpha 4e-6 (not remapped): not smooth");
    scene_free(&s);
}

static int dr_render(T *t, const char *body, int seed, Image *im)
{
    static char buf[8192];
    RenderOptions o;
    snprintf(buf, sizeof buf, "%s%s", DR_HEAD, body);
    render_options_default(&o);
    o.spp = 4;
    o.seed = seed;
    o.threads = 2;
    return test_render_text(t, buf, &o, im);
}

/* Two bodies render the same floats. */
static void dr_same_image(T *t, const char *a, const char *b, const char *what)
{
    Image x, y;
    if (!dr_render(t, a, 5, &x)) return;
    if (!dr_render(t, b, 5, &y)) { img_free(&x); return; }
    CHECK(t, x.w == y.w && x.h == y.h && !memcmp(x.rgb, y.rgb, sizeof(float) * 3 * x.w * x.h),
          "%s: Y %.9g and %.9g", what, test_image_y(&x), test_image_y(&y));
    img_free(&x);
    img_free(&y);
}

#define DR_SPHERE "AttributeBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" [ 0.9 ]\nAttributeEnd\n"
#define DR_CONST(v) "Texture \"c\" \"float\" \"constant\" \"float value\" " v "\n"

/* A constant texture renders as its number: bit for bit where rough (remapped or
   not; glass and the subsurface boundary), and for a numeric alpha below 1e-3 as
   roughness 0; a constant 0 gives the smooth glass's mean. */
static void test_dielrough_constant(T *t)
{
    static const char *const sss =
        "Material \"subsurface\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"rgb mfp\" [ 0.2 0.1 0.05 ] ";
    char a[2048], b[2048];
    double y0, se0, y1, se1;
    snprintf(a, sizeof a, DR_ROOM DR_CONST("0.1") "Material \"dielectric\" \"float roughness\" 0.1\n" DR_SPHERE);
    snprintf(b, sizeof b, DR_ROOM DR_CONST("0.1") "Material \"dielectric\" \"texture roughness\" \"c\"\n" DR_SPHERE);
    dr_same_image(t, a, b, "glass, roughness 0.1 and a constant texture 0.1");
    snprintf(a, sizeof a, DR_ROOM DR_CONST("0.02") "Material \"dielectric\" \"float eta\" 1.33 "
             "\"float roughness\" 0.02 \"bool remaproughness\" false\n" DR_SPHERE);
    snprintf(b, sizeof b, DR_ROOM DR_CONST("0.02") "Material \"dielectric\" \"float eta\" 1.33 "
             "\"texture roughness\" \"c\" \"bool remaproughness\" false\n" DR_SPHERE);
    dr_same_image(t, a, b, "glass, alpha 0.02 and a constant texture 0.02 (not remapped)");
    snprintf(a, sizeof a, DR_ROOM DR_CONST("0.1") "%s\"float roughness\" 0.1\n" DR_SPHERE, sss);
    snprintf(b, sizeof b, DR_ROOM DR_CONST("0.1") "%s\"texture roughness\" \"c\"\n" DR_SPHERE, sss);
    dr_same_image(t, a, b, "subsurface, roughness 0.1 and a constant texture 0.1");
    snprintf(a, sizeof a, DR_ROOM "Material \"dielectric\" \"float roughness\" 0\n" DR_SPHERE);
    snprintf(b, sizeof b, DR_ROOM "Material \"dielectric\" \"float roughness\" 1e-7\n" DR_SPHERE);
    dr_same_image(t, a, b, "glass, roughness 0 and 1e-7 (alpha 3e-4, smooth)");
    snprintf(a, sizeof a, DR_ROOM "%s\"float roughness\" 0\n" DR_SPHERE, sss);
    snprintf(b, sizeof b, DR_ROOM "%s\"float roughness\" 1e-7\n" DR_SPHERE, sss);
    dr_same_image(t, a, b, "subsurface, roughness 0 and 1e-7 (alpha 3e-4, smooth)");
    if (t->failed) return;
    {
        char full[4096];
        snprintf(a, sizeof a, "%s" DR_ROOM "Material \"dielectric\"\n" DR_SPHERE, DR_HEAD);
        snprintf(full, sizeof full, "%s" DR_ROOM DR_CONST("0") "Material \"dielectric\" \"texture roughness\" \"c\"\n"
                 DR_SPHERE, DR_HEAD);
        if (!test_mean_y(t, a, 8, 1, 8, &y0, &se0) || !test_mean_y(t, full, 8, 1, 8, &y1, &se1)) return;
        CHECK(t, y0 > 0.05 && fabs(y1 - y0) < TEST_K_SIGMA * sqrt(se0 * se0 + se1 * se1),
              "smooth glass Y %.5f +- %.2g; with a constant roughness texture 0: %.5f +- %.2g", y0, se0, y1, se1);
    }
}

static void test_dielrough_errors(T *t)
{
    test_rejected_at(t, "WorldBegin\nMaterial \"dielectric\" \"float uroughness\" 0.1 \"float vroughness\" -1\n", 2,
                     "Material \"dielectric\": roughness (0.1, -1) must be within [0, 1e4]", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"subsurface\" \"float uroughness\" 2e4\n", 2,
                     "Material \"subsurface\": roughness (20000, 0) must be within [0, 1e4]", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"k\" \"spectrum\" \"constant\"\n"
                     "Material \"dielectric\" \"texture roughness\" \"k\"\n", 3,
                     "\"texture roughness\": \"k\" is a spectrum texture; a float one is needed here", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"subsurface\"\n  \"texture vroughness\" \"none\"\n", 3,
                     "\"texture vroughness\": no texture named \"none\"", NULL);
}

/* ---------------------------------------------------------------- anisotropic roughness */

/* A glass of index 1.5 with alphas ax along the shading frame's s axis and ay
   along t. */
static void da_glass(Material *m, float ax, float ay)
{
    test_glass(m, 1.5f, 0.0f, ax);
    m->alpha_t = ay;
}

/* A hit facing +z whose dp/du points at angle phi in the plane: the frame's s. */
static SurfacePoint da_point(float phi)
{
    SurfacePoint sp = test_flat_point();
    sp.dpdu = v3(cosf(phi), sinf(phi), 0.0f);
    return sp;
}

static Vec3 da_sphere_dir(Rng *r)
{
    float z = 1.0f - 2.0f * rng_float(r), phi = 2.0f * PI_F * rng_float(r);
    float s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    return v3(s * cosf(phi), s * sinf(phi), z);
}

/* Loading: u and v read per axis (numbers, or a texture beside a number), each
   remapped unless remaproughness is false; an anisotropic interface turns with
   dp/du, an isotropic one keeps the normal's frame; both alphas below 1e-3 are
   smooth, one 0 beside a rough one is not. */
static void test_dielaniso_load(T *t)
{
    Scene s;
    const Material *m[9];
    SurfacePoint sp = dr_point(1.0f, 0.0f);           /* the bilerp's v10: 0.3 */
    float f;
    int i;
    if (!load_dr(t, &s,
                 "Texture \"r\" \"float\" \"bilerp\" \"float v00\" 0 \"float v10\" 0.3 \"float v01\" 0.1 "
                 "\"float v11\" 0.2\n"
                 "Material \"dielectric\" \"float uroughness\" 0.05 \"float vroughness\" 0.4\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float uroughness\" 0 \"float vroughness\" 0.3 "
                 "\"bool remaproughness\" false\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"texture uroughness\" \"r\" \"float vroughness\" 0.1\nShape \"sphere\"\n"
                 "Material \"subsurface\" \"float uroughness\" 0.05 \"float vroughness\" 0.4\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float roughness\" 0.3\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float uroughness\" 1e-7 \"float vroughness\" 2e-7\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float uroughness\" 0 \"texture vroughness\" \"r\"\nShape \"sphere\"\n"
                 "Material \"dielectric\" \"float uroughness\" 0 \"float vroughness\" 0.3\nShape \"sphere\"\n"
                 "Material \"subsurface\" \"texture uroughness\" \"r\" \"float vroughness\" 0\nShape \"sphere\"\n"))
        return;
    for (i = 0; i < 9; i++) m[i] = &s.materials[s.shapes[i].material];
    CHECK(t, m[0]->alpha == sqrtf(0.05f) && m[0]->alpha_t == sqrtf(0.4f) && m[3]->alpha == m[0]->alpha &&
          m[3]->alpha_t == m[0]->alpha_t, "u 0.05, v 0.4: alphas %g %g (subsurface %g %g), want sqrt of each",
          m[0]->alpha, m[0]->alpha_t, m[3]->alpha, m[3]->alpha_t);
    CHECK(t, m[1]->alpha == 0.0f && m[1]->alpha_t == 0.3f && !mat_is_delta(m[1]),
          "u 0, v 0.3 not remapped: alphas %g %g, delta %d", m[1]->alpha, m[1]->alpha_t, mat_is_delta(m[1]));
    CHECK(t, m[2]->alpha_tex > 0 && m[2]->alpha_t_tex == 0 && m[2]->alpha_t == sqrtf(0.1f) && s.shapes[2].reads_uv,
          "a u texture beside a v number: tex %d %d, alpha_t %g", m[2]->alpha_tex, m[2]->alpha_t_tex, m[2]->alpha_t);
    for (i = 0; i < 4; i++)
        CHECK(t, mat_needs_tangent(m[i]) && !mat_is_delta(m[i]), "material %d: tangent %d, delta %d", i,
              mat_needs_tangent(m[i]), mat_is_delta(m[i]));
    CHECK(t, !mat_needs_tangent(m[4]), "an isotropic dielectric turns with dp/du");
    CHECK(t, mat_is_delta(m[5]), "alphas 3e-4 and 4.5e-4: not smooth (pbrt-v4's EffectivelySmooth)");
    CHECK(t, !mat_is_delta(m[6]) && mat_needs_tangent(m[6]) && dr_same_eval(m[6], m[7], &sp, &f) && f > 0.0f,
          "u 0 beside a textured v of 0.3 at (1, 0): delta %d, tangent %d, not the numbers' BSDF (f %g)",
          mat_is_delta(m[6]), mat_needs_tangent(m[6]), f);
    CHECK(t, m[8]->alpha == m[8]->alpha_t && mat_needs_tangent(m[8]) && !mat_is_delta(m[8]),
          "subsurface, a textured u beside v 0: tangent %d, delta %d", mat_needs_tangent(m[8]), mat_is_delta(m[8]));
    scene_free(&s);
}

/* Pointwise: the glass (ax, ay) over dp/du along x is the glass (ay, ax) over
   dp/du along y (within float rounding, 0.3 %), and differs from (ax, ay) over y; alpha 0 beside a rough axis
   is alpha 1e-4 there (pbrt-v4), with f > 0. */
static void test_dielaniso_axes(T *t)
{
    static const float lam[HERO_N] = { 550.0f, 450.0f, 650.0f, 500.0f };
    Material a, b, z, z4, zt, zt4;
    SurfacePoint px = da_point(0.0f), py = da_point(0.5f * PI_F);
    Rng r;
    int i, j, n = 0;
    double moved = 0.0, total = 0.0, fz = 0.0;
    da_glass(&a, 0.2f, 0.6f);
    da_glass(&b, 0.6f, 0.2f);
    da_glass(&z, 0.0f, 0.4f);
    da_glass(&z4, 1e-4f, 0.4f);
    da_glass(&zt, 0.4f, 0.0f);
    da_glass(&zt4, 0.4f, 1e-4f);
    rng_seed(&r, 71, 1);
    for (i = 0; i < 2000; i++) {
        Vec3 wo = da_sphere_dir(&r), wi = da_sphere_dir(&r);
        float fa[HERO_N], pa[HERO_N], fb[HERO_N], pb[HERO_N], fc[HERO_N], pc[HERO_N];
        if (fabsf(wo.z) < 0.05f || fabsf(wi.z) < 0.05f) continue;
        bsdf_eval(&a, &px, wo, wi, lam, 15u, fa, pa);
        bsdf_eval(&b, &py, wo, wi, lam, 15u, fb, pb);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, fabsf(fa[j] - fb[j]) <= 3e-3f * fa[j] + 1e-7f && fabsf(pa[j] - pb[j]) <= 3e-3f * pa[j] + 1e-7f,
                  "wo (%.3f %.3f %.3f) wi (%.3f %.3f %.3f) lane %d: (0.2, 0.6) over x f %g pdf %g, "
                  "(0.6, 0.2) over y f %g pdf %g", wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, j, fa[j], pa[j], fb[j], pb[j]);
        bsdf_eval(&a, &py, wo, wi, lam, 15u, fc, pc);
        moved += fabs((double)fc[0] - fa[0]);
        total += fa[0];
        bsdf_eval(&z, &px, wo, wi, lam, 1u, fa, pa);
        bsdf_eval(&z4, &px, wo, wi, lam, 1u, fb, pb);
        CHECK(t, fa[0] == fb[0] && pa[0] == pb[0], "alphas (0, 0.4): f %g pdf %g, (1e-4, 0.4): f %g pdf %g",
              fa[0], pa[0], fb[0], pb[0]);
        fz += fa[0];
        bsdf_eval(&zt, &px, wo, wi, lam, 1u, fa, pa);
        bsdf_eval(&zt4, &px, wo, wi, lam, 1u, fb, pb);
        CHECK(t, fa[0] == fb[0] && pa[0] == pb[0], "alphas (0.4, 0): f %g pdf %g, (0.4, 1e-4): f %g pdf %g",
              fa[0], pa[0], fb[0], pb[0]);
        fz += fa[0];
        n++;
    }
    CHECK(t, n > 1000 && moved > 0.2 * total, "turning dp/du by 90 degrees moved f by %g of %g only", moved, total);
    CHECK(t, fz > 0.0, "alphas (0, 0.4) and (0.4, 0): f is 0 everywhere");
}

/* Energy and pdf, as material.c's isotropic test: for wo outside and inside,
   (a) int p dw (uniform sphere MC) = the fraction of samples that succeed,
   (b) E[f |cos| / p] over samples = int f |cos| dw, (c) the sampled pdf is
   the evaluated one; and f(a, b)/eta_a^2 = f(b, a)/eta_b^2 (radiance mode). */
static void test_dielaniso_energy(T *t)
{
    static const float lam[HERO_N] = { 550, 550, 550, 550 };
    Material m;
    SurfacePoint sp = da_point(0.5f);
    Vec3 wos[2];
    int io, i, nrec = 0;
    Rng r;
    wos[0] = v3_norm(v3(0.5f, 0.1f, 0.8f));
    wos[1] = v3_norm(v3(-0.3f, 0.4f, -0.9f));
    da_glass(&m, sqrtf(0.05f), sqrtf(0.4f));
    for (io = 0; io < 2; io++) {
        int n_s = test_scaled(100000, 40000), n_u = test_scaled(200000, 80000), ok = 0;
        double sw = 0, sw2 = 0, ip = 0, ip2 = 0, fi = 0, fi2 = 0, mean, se, est, est_se, q, q_se;
        Vec3 wo = wos[io];
        rng_seed(&r, 73, (uint64_t)io);
        for (i = 0; i < n_s; i++) {
            BsdfSample bs;
            float f[HERO_N], p[HERO_N];
            double w;
            if (!test_bsdf_sample(&m, &sp, wo, lam, 1u, &r, &bs)) continue;
            ok++;
            w = bs.f[0] * fabsf(v3_dot(bs.wi, sp.ns)) / bs.pdf;
            sw += w; sw2 += w * w;
            if (i < 2000) {
                bsdf_eval(&m, &sp, wo, bs.wi, lam, 1u, f, p);
                CHECK(t, fabsf(p[0] - bs.pdf) <= 1e-3f * bs.pdf + 1e-6f, "wo %d: sampled pdf %g, evaluated %g",
                      io, bs.pdf, p[0]);
            }
        }
        for (i = 0; i < n_u; i++) {
            Vec3 wi = da_sphere_dir(&r);
            float f[HERO_N], p[HERO_N];
            double a, b;
            bsdf_eval(&m, &sp, wo, wi, lam, 1u, f, p);
            a = p[0] * 4 * SPECNEE_PI;
            b = f[0] * fabsf(wi.z) * 4 * SPECNEE_PI;
            ip += a; ip2 += a * a; fi += b; fi2 += b * b;
        }
        mean = ip / n_u;
        se = sqrt((ip2 / n_u - mean * mean) / n_u);
        CHECK(t, fabs(mean - (double)ok / n_s) < 4 * se + 0.01, "wo %d: int p = %g +- %g, %g of the samples succeed",
              io, mean, se, (double)ok / n_s);
        est = sw / n_s;
        est_se = sqrt((sw2 / n_s - est * est) / n_s);
        q = fi / n_u;
        q_se = sqrt((fi2 / n_u - q * q) / n_u);
        CHECK(t, fabs(est - q) < 4 * sqrt(est_se * est_se + q_se * q_se) + 0.01 * q,
              "wo %d: E[f cos/p] = %g +- %g, quadrature %g +- %g", io, est, est_se, q, q_se);
    }
    rng_seed(&r, 73, 7);
    for (i = 0; i < 20000; i++) {
        Vec3 a = da_sphere_dir(&r), b = da_sphere_dir(&r);
        float fab[HERO_N], fba[HERO_N], p[HERO_N];
        double ea = a.z > 0 ? 1.0 : 1.5, eb = b.z > 0 ? 1.0 : 1.5, x, y;
        if (fabsf(a.z) < 0.02f || fabsf(b.z) < 0.02f) continue;
        bsdf_eval(&m, &sp, a, b, lam, 1u, fab, p);
        bsdf_eval(&m, &sp, b, a, lam, 1u, fba, p);
        x = fab[0] / (ea * ea);
        y = fba[0] / (eb * eb);
        CHECK(t, fabs(x - y) <= 2e-3 * fmax(x, y) + 1e-5, "f(a,b)/eta_a^2 = %g but f(b,a)/eta_b^2 = %g", x, y);
        nrec += x > 1e-3;
    }
    CHECK(t, nrec > 2000, "only %d pairs compared", nrec);
}

/* Chi-square of the sampled directions against bsdf_eval's pdf (alphas 0.3
   and 0.7, dp/du at 30 degrees; narrower lobes as in material.c's test). */
static void test_dielaniso_chi2(T *t)
{
    Material m;
    BsdfDirs b = { 0 };
    DirTest d;
    Rng r;
    Chi2 c;
    int io;
    da_glass(&m, 0.3f, 0.7f);
    b.m = &m;
    b.sp = da_point(PI_F / 6.0f);
    b.lambda[0] = b.lambda[1] = b.lambda[2] = b.lambda[3] = 550;
    for (io = 0; io < 2; io++) {
        b.wo = io ? v3_norm(v3(-0.2f, 0.5f, -0.6f)) : v3_norm(v3(0.4f, 0.3f, 0.7f));
        rng_seed(&r, 79, (uint64_t)io);
        d = test_bsdf_dirs(&b, 200000);
        CHECK_CHI2_DIRS(t, &d, &r, 2, &c, "anisotropic glass, wo %d", io);
    }
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 1024`, S = 1..8)
   rendered (a) DR_GLASS: over DR_ROOM, a glass sphere of a bilerp roughness over
   its (u, v) (0 at one corner: smooth there) and one of a constant texture not
   remapped (the independent sampler); (b) DR_SSS: test_subsurface.c's rough
   subsurface sphere with a bilerp roughness, not remapped (pbrt-v4's default
   sampler).  Luminance of the image and its quadrants (top left first), mean over
   the seeds and its standard error; accepted within 5 standard errors + 1 %. */
static const char *const DR_GLASS =
    DR_ROOM
    "Texture \"r\" \"float\" \"bilerp\" \"float v00\" [ 0 ] \"float v01\" [ 0.02 ] \"float v10\" [ 0.3 ] "
    "\"float v11\" [ 0.08 ]\n"
    "Texture \"c\" \"float\" \"constant\" \"float value\" [ 0.05 ]\n"
    "Material \"dielectric\" \"float eta\" [ 1.5 ] \"texture roughness\" \"r\"\n"
    "AttributeBegin\nTranslate -1 0 1\nShape \"sphere\" \"float radius\" [ 0.9 ]\nAttributeEnd\n"
    "Material \"dielectric\" \"float eta\" [ 1.33 ] \"texture uroughness\" \"c\" \"texture vroughness\" \"c\" "
    "\"bool remaproughness\" false\n"
    "AttributeBegin\nTranslate 1.1 0 0.9\nShape \"sphere\" \"float radius\" [ 0.8 ]\nAttributeEnd\n";
static const double PBRT_DR_GLASS_Y[5][2] = {
    { 0.131893, 0.0002 }, { 0.161275, 0.00012 }, { 0.141150, 0.00012 }, { 0.129134, 0.00038 }, { 0.096014, 0.00033 },
};
static const char *const DR_SSS =
    "LookAt 0 -4 2.5  0 0 0.6  0 0 1\nCamera \"perspective\" \"float fov\" [ 35 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "AttributeBegin\nTranslate 1.5 -1 3\nAreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
    "Shape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ]\n"
    "Texture \"r\" \"float\" \"bilerp\" \"float v00\" [ 0.3 ] \"float v01\" [ 0.01 ] \"float v10\" [ 0 ] "
    "\"float v11\" [ 0.15 ]\n"
    "Material \"subsurface\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"rgb mfp\" [ 0.2 0.1 0.05 ] "
    "\"texture roughness\" \"r\" \"bool remaproughness\" false \"float eta\" 1.33\n"
    "AttributeBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n";
static const double PBRT_DR_SSS_Y[5][2] = {
    { 0.038133, 1.7e-05 }, { 0.074239, 9e-05 }, { 0.018021, 4.8e-05 }, { 0.048383, 3.4e-05 }, { 0.011891, 2.5e-05 },
};

static void test_dielrough_against_pbrt(T *t)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", DR_HEAD, DR_GLASS);
    test_against_pbrt_y(t, buf, 3, PBRT_DR_GLASS_Y, 1e-2, "glass");
    if (t->failed) return;
    test_against_pbrt_y(t, DR_SSS, 5, PBRT_DR_SSS_Y, 1e-2, "subsurface");
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 1024 --nthreads 2`,
   S = 1..8) rendered (a) DA_GLASS: over DR_ROOM (DR_HEAD's camera, the
   independent sampler), a glass sphere of uroughness 0.05 and vroughness 0.4
   (remapped: alphas 0.224 and 0.632 along dp/du and across it) and one whose u
   roughness is a bilerp texture (0 at one corner: smooth there) beside a
   vroughness of 0, not remapped (alpha 1e-4 across dp/du where u is rough);
   (b) DA_SSS: DR_SSS's scene with the subsurface sphere's boundary of
   uroughness 0.05 and vroughness 0.4 (pbrt-v4's default sampler).  Luminance
   of the image and its quadrants (top left first), mean over the seeds and its
   standard error; accepted within 5 standard errors + 1 %.  (Swapping u and v
   on the first sphere moves pbrt-v4's image by 9 %.) */
static const char *const DA_GLASS =
    DR_ROOM
    "Material \"dielectric\" \"float eta\" [ 1.5 ] \"float uroughness\" [ 0.05 ] \"float vroughness\" [ 0.4 ]\n"
    "AttributeBegin\nTranslate -1 0 1\nShape \"sphere\" \"float radius\" [ 0.9 ]\nAttributeEnd\n"
    "Texture \"r\" \"float\" \"bilerp\" \"float v00\" [ 0 ] \"float v01\" [ 0.02 ] \"float v10\" [ 0.3 ] "
    "\"float v11\" [ 0.08 ]\n"
    "Material \"dielectric\" \"float eta\" [ 1.33 ] \"texture uroughness\" \"r\" \"float vroughness\" [ 0 ] "
    "\"bool remaproughness\" false\n"
    "AttributeBegin\nTranslate 1.1 0 0.9\nShape \"sphere\" \"float radius\" [ 0.8 ]\nAttributeEnd\n";
static const double PBRT_DA_GLASS_Y[5][2] = {
    { 0.127205, 0.00019 }, { 0.161067, 0.00015 }, { 0.137018, 9.1e-05 }, { 0.127021, 0.00048 },
    { 0.083712, 0.00038 },
};

static const char *const DA_SSS =
    "LookAt 0 -4 2.5  0 0 0.6  0 0 1\nCamera \"perspective\" \"float fov\" [ 35 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "AttributeBegin\nTranslate 1.5 -1 3\nAreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
    "Shape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ]\n"
    "Material \"subsurface\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"rgb mfp\" [ 0.2 0.1 0.05 ] "
    "\"float uroughness\" 0.05 \"float vroughness\" 0.4 \"float eta\" 1.33\n"
    "AttributeBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n";
static const double PBRT_DA_SSS_Y[5][2] = {
    { 0.036689, 1.4e-05 }, { 0.071047, 7.2e-05 }, { 0.017336, 4.6e-05 }, { 0.046851, 1.1e-05 },
    { 0.011522, 1.5e-05 },
};

static void test_dielaniso_against_pbrt(T *t)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s", DR_HEAD, DA_GLASS);
    test_against_pbrt_y(t, buf, 3, PBRT_DA_GLASS_Y, 1e-2, "anisotropic glass");
    if (t->failed) return;
    test_against_pbrt_y(t, DA_SSS, 5, PBRT_DA_SSS_Y, 1e-2, "anisotropic subsurface boundary");
}

const TestCase tests_dielrough[] = {
    { "dielrough_per_hit", test_dielrough_per_hit },
    { "dielrough_constant", test_dielrough_constant },
    { "dielrough_errors", test_dielrough_errors },
    { "dielrough_against_pbrt", test_dielrough_against_pbrt },
    { "dielaniso_load", test_dielaniso_load },
    { "dielaniso_axes", test_dielaniso_axes },
    { "dielaniso_energy", test_dielaniso_energy },
    { "dielaniso_chi2", test_dielaniso_chi2 },
    { "dielaniso_against_pbrt", test_dielaniso_against_pbrt },
    { NULL, NULL }
};
