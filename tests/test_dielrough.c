/* tests/test_dielrough.c - a textured roughness on "dielectric" and on the
   boundary of "subsurface" (parser.c microfacet_alpha_texture; material.c
   dielectric_alpha, mat_point, mat_is_delta).

   Checked: at each hit the BSDF is the one of the numeric roughness the texture
   gives there, remapped (sqrt) unless "remaproughness" is false, bit for bit; a
   hit whose alpha is below 1e-3 is smooth (pbrt-v4's EffectivelySmooth), and so
   is a numeric alpha that small; a constant texture renders the same image as
   its number (bit for bit where it is rough; where it is 0, as the same mean: NEE
   is then tried at a smooth hit, which adds 0 but draws other random numbers);
   the subsurface boundary likewise; the refusals (u and v from different
   sources, a spectrum texture, a missing one) at their file:line; pbrt-v4's
   images frozen. */
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
    test_rejected_at(t, "WorldBegin\nTexture \"r\" \"float\" \"checkerboard\"\nTexture \"q\" \"float\" \"constant\"\n"
                     "Material \"dielectric\" \"texture uroughness\" \"r\" \"texture vroughness\" \"q\"\n", 4,
                     "Material \"dielectric\": u and v roughness from different sources", "anisotropic");
    test_rejected_at(t, "WorldBegin\nTexture \"r\" \"float\" \"constant\"\n"
                     "Material \"dielectric\" \"texture roughness\" \"r\" \"float vroughness\" 0.1\n", 3,
                     "u and v roughness from different sources", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"r\" \"float\" \"constant\"\n"
                     "MakeNamedMaterial \"g\" \"string type\" \"dielectric\" \"texture uroughness\" \"r\"\n", 3,
                     "u and v roughness from different sources", NULL);
    test_rejected_at(t, "WorldBegin\nTexture \"k\" \"spectrum\" \"constant\"\n"
                     "Material \"dielectric\" \"texture roughness\" \"k\"\n", 3,
                     "\"texture roughness\": \"k\" is a spectrum texture; a float one is needed here", NULL);
    test_rejected_at(t, "WorldBegin\nMaterial \"subsurface\"\n  \"texture vroughness\" \"none\"\n", 3,
                     "\"texture vroughness\": no texture named \"none\"", NULL);
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

const TestCase tests_dielrough[] = {
    { "dielrough_per_hit", test_dielrough_per_hit },
    { "dielrough_constant", test_dielrough_constant },
    { "dielrough_errors", test_dielrough_errors },
    { "dielrough_against_pbrt", test_dielrough_against_pbrt },
    { NULL, NULL }
};
