/* tests/test_coattex.c - textured slabs and anisotropic layers of pbrt-v4's
   layered materials (coateddiffuse, coatedconductor: "texture thickness",
   "texture g", "texture albedo", u and v roughness), read at each hit by
   material.c's mat_point and used by layered.c.

   Checked: the parser stores the textures and mat_point reads them with pbrt-v4's
   bounds (thickness >= FLT_MIN, g within [-0.99, 0.99], albedo within [0, 1]);
   constant textures render the image of the same numbers bit for bit; two
   limits of one checkerboard thickness at two points of one surface (a slab
   too thick to cross leaves the coat's Fresnel reflectance, one of vanishing
   thickness over a white base is lossless: weight 1); a lossless textured
   medium (albedo 1, any g) keeps every walk's weight 1; bad texture names as
   file:line errors; pbrt-v4's images frozen (a checkerboard on each
   parameter).  Anisotropic coats and bases (u and v roughness): a coat of index
   1 over an anisotropic conductor is the bare conductor in the same dp/du frame;
   NEE and BSDF sampling agree; pbrt-v4's images frozen. */
#include "test.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

static const float LAM[HERO_N] = { 450.0f, 550.0f, 620.0f, 700.0f };

static const char *const CT_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 0 0 0 ]\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.3 0.3 0.3 ]\n";

/* A square x, y in [x0, x1] x [y0, y1] (z = 0) whose uv spans [u0, u1] x [v0, v1]. */
#define CT_QUAD(x0, y0, x1, y1, u0, v0, u1, v1) "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] " \
    "\"point3 P\" [ " x0 " " y0 " 0  " x1 " " y0 " 0  " x1 " " y1 " 0  " x0 " " y1 " 0 ] " \
    "\"point2 uv\" [ " u0 " " v0 "  " u1 " " v0 "  " u1 " " v1 "  " u0 " " v1 " ]\n"

/* The image's four quadrants, each a square whose uv lies inside one cell of a 2 x 2
   checkerboard, 0.05 away from the cell's edges (pbrt-v4 box-filters a checkerboard's
   edges over the ray footprint, specnee point-samples it: inside a cell both read
   the cell's value) */
static const char *const CT_QUADS =
    CT_QUAD("-2", "0", "0", "2", "0.05", "0.55", "0.45", "0.95")
    CT_QUAD("0", "0", "2", "2", "0.55", "0.55", "0.95", "0.95")
    CT_QUAD("-2", "-2", "0", "0", "0.05", "0.05", "0.45", "0.45")
    CT_QUAD("0", "-2", "2", "0", "0.55", "0.05", "0.95", "0.45");

static int load_ct(T *t, Scene *s, const char *body)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s%s%s", CT_HEAD, body, CT_QUADS);
    return test_load_scene(t, s, buf);
}

/* The point of a flat surface at (u, v). */
static SurfacePoint flat_at(float u, float v)
{
    SurfacePoint sp = test_flat_point();
    sp.u = u;
    sp.v = v;
    return sp;
}

/* ---------------------------------------------------------------- parsing */

/* The textures are stored, mat_point reads them at the point with pbrt-v4's
   bounds; a material without them keeps its numbers (a float g beyond 0.99 as
   pbrt-v4's HenyeyGreenstein clamps it). */
static void test_coattex_params(T *t)
{
    Scene s;
    const Material *m;
    MatPoint mp;
    SurfacePoint sp = flat_at(0.25f, 0.25f);
    int j;
    if (!load_ct(t, &s,
                 "Texture \"th\" \"float\" \"constant\" \"float value\" 0.3\n"
                 "Texture \"neg\" \"float\" \"constant\" \"float value\" -1\n"
                 "Texture \"big\" \"float\" \"constant\" \"float value\" 1e38\n"
                 "Texture \"g\" \"float\" \"constant\" \"float value\" 3\n"
                 "Texture \"gn\" \"float\" \"constant\" \"float value\" -0.995\n"
                 "Texture \"al\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n"
                 "Texture \"al3\" \"spectrum\" \"scale\" \"texture tex\" \"al\" \"float scale\" 3\n"
                 "Material \"coateddiffuse\" \"texture thickness\" \"th\" \"texture g\" \"g\" "
                 "\"texture albedo\" \"al\"\nShape \"sphere\"\n"
                 "Material \"coatedconductor\" \"texture thickness\" \"neg\" \"texture g\" \"gn\" "
                 "\"texture albedo\" \"al3\"\nShape \"sphere\"\n"
                 "Material \"coatedconductor\" \"texture thickness\" \"big\"\nShape \"sphere\"\n"
                 "Material \"coateddiffuse\" \"float thickness\" 0.2 \"float g\" 0.995 "
                 "\"rgb albedo\" [ 0.4 0.4 0.4 ]\nShape \"sphere\"\n"))
        return;
    m = &s.materials[s.n_materials - 4];
    CHECK(t, m->thickness_tex > 0 && m->g_tex > 0 && m->albedo_tex > 0, "textures %d %d %d",
          m->thickness_tex, m->g_tex, m->albedo_tex);
    mat_point(m, &sp, LAM, 15u, &mp);
    CHECK(t, fabsf(mp.thick - 0.3f) < 1e-7f && mp.g == 0.99f && mp.has_a,
          "coateddiffuse: thickness %g g %g (3 clamped to 0.99) has_a %d", mp.thick, mp.g, mp.has_a);
    for (j = 0; j < HERO_N; j++)
        CHECK(t, fabsf(mp.a[j] - 0.5f) < 1e-3f, "albedo %g at %g nm, want 0.5", mp.a[j], LAM[j]);
    m = &s.materials[s.n_materials - 3];
    mat_point(m, &sp, LAM, 5u, &mp);
    CHECK(t, mp.thick == FLT_MIN && mp.g == -0.99f && mp.has_a && mp.a[0] == 1.0f && mp.a[2] == 1.0f &&
          mp.a[1] == 0.0f, "coatedconductor: thickness %g (-1: FLT_MIN) g %g albedo %g %g (1.5: 1; dead: %g)",
          mp.thick, mp.g, mp.a[0], mp.a[2], mp.a[1]);
    m = &s.materials[s.n_materials - 2];
    mat_point(m, &sp, LAM, 15u, &mp);
    CHECK(t, mp.thick == 1e30f && mp.g == 0.0f && !mp.has_a, "thickness %g (1e38: 1e30) g %g has_a %d",
          mp.thick, mp.g, mp.has_a);
    m = &s.materials[s.n_materials - 1];
    mat_point(m, &sp, LAM, 15u, &mp);
    CHECK(t, m->thickness_tex == 0 && m->g_tex == 0 && m->albedo_tex == 0 && mp.thick == 0.2f &&
          mp.g == 0.99f && !mp.has_a, "numbers: thickness %g g %g (0.995: 0.99) has_a %d", mp.thick, mp.g,
          mp.has_a);
    CHECK(t, mat_reads_uv(&s.materials[s.n_materials - 2]) && !mat_reads_uv(m), "mat_reads_uv");
    scene_free(&s);
}

/* Constant textures give the image of the same numbers, bit for bit. */
static void test_coattex_constant(T *t)
{
    static const char *const mats[2][2] = {
        { "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.6 0.5 0.3 ] \"float thickness\" 0.3 "
          "\"float g\" 0.4 \"rgb albedo\" [ 0.7 0.7 0.7 ]\n",
          "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.6 0.5 0.3 ] \"texture thickness\" \"th\" "
          "\"texture g\" \"g\" \"texture albedo\" \"al\"\n" },
        { "Material \"coatedconductor\" \"float conductor.roughness\" 0.2 \"float thickness\" 0.3 "
          "\"float g\" 0.4 \"rgb albedo\" [ 0.7 0.7 0.7 ]\n",
          "Material \"coatedconductor\" \"float conductor.roughness\" 0.2 \"texture thickness\" \"th\" "
          "\"texture g\" \"g\" \"texture albedo\" \"al\"\n" },
    };
    int c, k;
    for (c = 0; c < 2; c++) {
        Image im[2];
        for (k = 0; k < 2; k++) {
            char text[8192];
            RenderOptions o;
            render_options_default(&o);
            o.spp = 8;
            o.seed = 3;
            snprintf(text, sizeof text, "%s"
                     "Texture \"th\" \"float\" \"constant\" \"float value\" 0.3\n"
                     "Texture \"g\" \"float\" \"constant\" \"float value\" 0.4\n"
                     "Texture \"al\" \"spectrum\" \"constant\" \"rgb value\" [ 0.7 0.7 0.7 ]\n%s%s",
                     CT_HEAD, mats[c][k], CT_QUADS);
            if (!test_render_text(t, text, &o, &im[k])) {
                if (k) img_free(&im[0]);
                return;
            }
        }
        CHECK(t, test_image_y(&im[0]) > 0.05, "the image is dark: Y %g", test_image_y(&im[0]));
        CHECK(t, !memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * im[0].w * im[0].h),
              "%s: numbers Y %.9g, constant textures Y %.9g", c ? "coatedconductor" : "coateddiffuse",
              test_image_y(&im[0]), test_image_y(&im[1]));
        img_free(&im[0]);
        img_free(&im[1]);
    }
}

/* The mean of bsdf_sample's weights f cos / pdf at the hero wavelength from wo
   (n samples) at sp, and its standard error. */
static double mean_weight(const Material *m, const SurfacePoint *sp, Vec3 wo, int n, uint64_t seed,
                          double *se)
{
    Rng r;
    double s = 0.0, s2 = 0.0;
    int i;
    rng_seed(&r, seed, 3);
    for (i = 0; i < n; i++) {
        BsdfSample b;
        double w = 0.0;
        if (test_bsdf_sample(m, sp, wo, LAM, 15u, &r, &b) && b.pdf > 0.0f)
            w = (double)b.f[0] * fabs(v3_dot(b.wi, sp->ns)) / b.pdf;
        s += w;
        s2 += w * w;
    }
    s /= n;
    *se = sqrt(fmax(0.0, s2 / n - s * s) / (n - 1));
    return s;
}

/* Limits, per hit of one checkerboard thickness (u < 0.5: 1e38, clamped to 1e30;
   u >= 0.5: -1, pbrt-v4's FLT_MIN), over a white base under a smooth coat of
   index 1.5, albedo 0: where the slab is too thick to cross only the coat's
   Fresnel reflection is left (the directional albedo is F(cos theta)); where it
   is vanishingly thin nothing is absorbed (every walk's weight is 1, maxdepth
   1000 so that no walk is cut).  And a lossless medium (textured albedo 1, a
   textured g of 0.7, thickness 0.5) over the white base keeps weight 1 too. */
static void test_coattex_limits(T *t)
{
    Scene s;
    const int n = test_scaled(20000, 4000);
    int k;
    if (!load_ct(t, &s,
                 "Texture \"th\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 1 "
                 "\"float tex1\" 1e38 \"float tex2\" -1\n"
                 "Texture \"one\" \"spectrum\" \"constant\" \"rgb value\" [ 1 1 1 ]\n"
                 "Texture \"g\" \"float\" \"constant\" \"float value\" 0.7\n"
                 "Material \"coateddiffuse\" \"rgb reflectance\" [ 1 1 1 ] \"texture thickness\" \"th\" "
                 "\"integer maxdepth\" 1000\nShape \"sphere\"\n"
                 "Material \"coateddiffuse\" \"rgb reflectance\" [ 1 1 1 ] \"float thickness\" 0.5 "
                 "\"texture albedo\" \"one\" \"texture g\" \"g\" \"integer maxdepth\" 1000\n"
                 "Shape \"sphere\"\n"))
        return;
    for (k = 0; k < 3; k++) {
        const Material *m = &s.materials[s.n_materials - (k < 2 ? 2 : 1)];
        SurfacePoint sp = flat_at(k == 0 ? 0.25f : 0.75f, 0.5f);
        float ct = k == 1 ? 0.3f : 0.8f;
        Vec3 wo = v3(sqrtf(1.0f - ct * ct), 0.0f, ct);
        double se, w = mean_weight(m, &sp, wo, n, 11 + k, &se);
        double want = k == 0 ? fresnel_dielectric(ct, 1.5f) : 1.0;
        if (getenv("DBG")) fprintf(stderr, "limit %d: %.6f +- %.2g, want %.6f\n", k, w, se, want);
        CHECK(t, fabs(w - want) < TEST_K_SIGMA * se + 1e-4, "%s: mean weight %.5f +- %.2g, want %.5f",
              k == 0 ? "thick slab" : k == 1 ? "thin slab" : "lossless medium", w, se, want);
    }
    scene_free(&s);
}

/* Bad texture names: file:line, the parameter and what is wrong. */
static void test_coattex_errors(T *t)
{
    static const char *const tex =
        "Texture \"f\" \"float\" \"constant\" \"float value\" 0.5\n"
        "Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n";
    char body[1024];
    snprintf(body, sizeof body, "%sMaterial \"coateddiffuse\" \"texture thickness\" \"k\"\n", tex);
    test_refused(t, CT_HEAD, body, "ct.pbrt",
                 "ct.pbrt:12: \"texture thickness\": \"k\" is a spectrum texture; a float one is needed here");
    snprintf(body, sizeof body, "%sMaterial \"coatedconductor\"\n \"texture albedo\" \"f\"\n", tex);
    test_refused(t, CT_HEAD, body, "ct.pbrt",
                 "ct.pbrt:13: \"texture albedo\": \"f\" is a float texture; a spectrum one is needed here");
    snprintf(body, sizeof body, "%sMaterial \"coatedconductor\" \"texture g\" \"nothere\"\n", tex);
    test_refused(t, CT_HEAD, body, "ct.pbrt", "ct.pbrt:12: \"texture g\": no texture named \"nothere\"");
    snprintf(body, sizeof body, "%sMaterial \"coateddiffuse\" \"texture g\" \"f\" \"float g\" 0.2\n", tex);
    test_refused(t, CT_HEAD, body, "ct.pbrt", "ct.pbrt:12: \"texture g\": \"g\" is given as a number too");
    snprintf(body, sizeof body, "%sMaterial \"coatedconductor\" \"rgb albedo\" [ 0.5 0.5 0.5 ]\n"
             " \"texture albedo\" \"k\"\n", tex);
    test_refused(t, CT_HEAD, body, "ct.pbrt", "ct.pbrt:13: \"texture albedo\": \"albedo\" is given as a number too");
}

/* ---------------------------------------------------------------- pbrt-v4 */

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 1024`, S = 1..8, the
   independent sampler) rendered CT_HEAD + each body + CT_QUADS: a checkerboard on
   (a) coateddiffuse's thickness (0.01 and 2), (b) its albedo (a spectrum: rgb 0.9
   0.6 0.2 and 0.1), (c) its g (-0.8 and 0.8, albedo 0.95, thickness 1), (d)
   coatedconductor's thickness, g and albedo at once (three checkerboards of other
   cells: each quadrant its own three); and spectral coat indices, which terminate
   the secondary wavelengths: (e) coateddiffuse's "spectrum eta" from 2.2 (360 nm)
   to 1.3 (830 nm), (f) coatedconductor's "rgb interface.eta" over silver.
   Luminance of the image and its quadrants (top left first), mean over the seeds
   and its standard error; accepted within 5 standard errors + 1 % (specnee at 8 x
   1024 spp: all within 0.25 %). */
static const char *const CT_BODY[6] = {
    "Texture \"ck\" \"float\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 2 ] "
    "\"float tex1\" [ 0.01 ] \"float tex2\" [ 2 ]\n"
    "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.7 0.5 0.3 ] \"texture thickness\" \"ck\"\n",
    "Texture \"ck\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 2 ] "
    "\"rgb tex1\" [ 0.9 0.6 0.2 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
    "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.4 0.4 0.4 ] \"texture albedo\" \"ck\" "
    "\"float thickness\" [ 0.5 ] \"float g\" [ 0.3 ]\n",
    "Texture \"ck\" \"float\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 2 ] "
    "\"float tex1\" [ -0.8 ] \"float tex2\" [ 0.8 ]\n"
    "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.2 0.2 0.2 ] \"texture g\" \"ck\" "
    "\"float thickness\" [ 1 ] \"rgb albedo\" [ 0.95 0.95 0.95 ]\n",
    "Texture \"th\" \"float\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 2 ] "
    "\"float tex1\" [ 0.02 ] \"float tex2\" [ 0.8 ]\n"
    "Texture \"gg\" \"float\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 1 ] "
    "\"float tex1\" [ -0.5 ] \"float tex2\" [ 0.6 ]\n"
    "Texture \"al\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 1 ] \"float vscale\" [ 2 ] "
    "\"rgb tex1\" [ 0.8 0.8 0.3 ] \"rgb tex2\" [ 0.2 0.5 0.9 ]\n"
    "Material \"coatedconductor\" \"float conductor.roughness\" [ 0.2 ] \"spectrum conductor.eta\" "
    "\"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" \"texture thickness\" \"th\" "
    "\"texture g\" \"gg\" \"texture albedo\" \"al\"\n",
    "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"spectrum eta\" [ 360 2.2 500 2.0 560 1.4 830 1.3 ]\n",
    ("Material \"coatedconductor\" \"rgb interface.eta\" [ 1.3 1.6 2.0 ] \"float conductor.roughness\" [ 0.1 ] "
     "\"spectrum conductor.eta\" \"metal-Ag-eta\" \"spectrum conductor.k\" \"metal-Ag-k\"\n"),
};
static const double PBRT_CT_Y[6][5][2] = {
    { { 0.205052, 0.00011 }, { 0.393801, 0.00024 }, { 0.016418, 4.4e-05 }, { 0.016479, 4.2e-05 }, { 0.393510, 0.00028 } },
    { { 0.133904, 4.4e-05 }, { 0.172775, 8.5e-05 }, { 0.095255, 8.4e-05 }, { 0.095359, 7.9e-05 }, { 0.172228, 0.00015 } },
    { { 0.591665, 0.00028 }, { 0.525384, 0.00032 }, { 0.115922, 0.00023 }, { 0.116349, 0.00022 }, { 1.609007, 0.001 } },
    { { 0.393612, 0.00012 }, { 0.560552, 0.00019 }, { 0.242530, 0.00016 }, { 0.265574, 0.00024 }, { 0.505793, 0.00041 } },
    { { 0.348317, 0.00016 }, { 0.348871, 0.00053 }, { 0.348247, 0.00030 }, { 0.348266, 0.00048 }, { 0.347885, 0.00046 } },
    { { 0.989908, 0.00043 }, { 1.149198, 0.0018 }, { 0.931198, 0.00052 }, { 1.026941, 0.0010 }, { 0.852295, 0.00075 } },
};

static void test_coattex_against_pbrt(T *t)
{
    int j;
    for (j = 0; j < 6; j++) {
        Scene s;
        char what[8];
        if (!load_ct(t, &s, CT_BODY[j])) return;
        snprintf(what, sizeof what, "scene %c", 'a' + j);
        test_scene_against_pbrt_y(t, &s, test_scaled(64, 16), 3, PBRT_CT_Y[j], 1e-2, what);
        scene_free(&s);
        if (t->failed) return;
    }
}

/* ---------------------------------------------------------------- anisotropic coats */

/* A square lamp above and beside the squares (seen by BSDF sampling too). */
static const char *const CT_LAMP =
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\nReverseOrientation\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 1 -3 3  4 -3 3  4 -2 3  1 -2 3 ]\n"
    "AttributeEnd\n";

/* CT_HEAD without its lights (the first 7 lines), then CT_LAMP. */
static int load_lamp(T *t, Scene *s, const char *material)
{
    static char buf[8192];
    const char *p = CT_HEAD;
    int n;
    for (n = 0; n < 7; n++) p = strchr(p, '\n') + 1;
    snprintf(buf, sizeof buf, "%.*s%s%s%s", (int)(p - CT_HEAD), CT_HEAD, CT_LAMP, material, CT_QUADS);
    return test_load_scene(t, s, buf);
}

/* A coat of index 1 over a vanishing slab without albedo is no coat: the coated
   conductor with an anisotropic base is the bare anisotropic conductor, pair for
   pair, in the shading frame both take from dp/du (here turned 53 degrees from x). */
static void test_coattex_aniso_bare(T *t)
{
    Scene s;
    SurfacePoint sp = test_flat_point();
    int k, j;
    if (!test_load_scene(t, &s, "WorldBegin\n"
                         "Material \"coatedconductor\" \"float interface.eta\" 1 \"float thickness\" 1e-6 "
                         "\"float conductor.uroughness\" 0.3 \"float conductor.vroughness\" 0.08 "
                         "\"bool remaproughness\" false\nShape \"sphere\"\n"
                         "Material \"conductor\" \"float uroughness\" 0.3 \"float vroughness\" 0.08 "
                         "\"bool remaproughness\" false\nShape \"sphere\"\n"
                         "Material \"coateddiffuse\" \"float uroughness\" 0.2 \"float vroughness\" 0.2\n"
                         "Shape \"sphere\"\n"))
        return;
    sp.dpdu = v3(0.6f, 0.8f, 0.0f);
    CHECK(t, mat_needs_tangent(&s.materials[0]) && !mat_needs_tangent(&s.materials[2]),
          "the shading frame: anisotropic base %d, isotropic coat %d", mat_needs_tangent(&s.materials[0]),
          mat_needs_tangent(&s.materials[2]));
    {   /* pbrt-v4's Regularize widens both of the base's alphas */
        Material r;
        CHECK(t, mat_regularized(&s.materials[0], &r) && r.cond_alpha == 0.3f && r.cond_alpha_t == 0.16f,
              "regularized base alphas %g %g, want 0.3 0.16", r.cond_alpha, r.cond_alpha_t);
    }
    for (k = 0; k < 40; k++) {
        float tk = 0.03f * (float)k, po = 0.7f * (float)k, pi = 2.5f + 0.3f * (float)k;
        Vec3 wo = v3(sinf(0.2f + tk) * cosf(po), sinf(0.2f + tk) * sinf(po), cosf(0.2f + tk));
        Vec3 wi = v3(sinf(1.4f - tk) * cosf(pi), sinf(1.4f - tk) * sinf(pi), cosf(1.4f - tk));
        float fc[HERO_N], fb[HERO_N], pc[HERO_N], pb[HERO_N];
        bsdf_eval(&s.materials[0], &sp, wo, wi, LAM, 15u, fc, pc);
        bsdf_eval(&s.materials[1], &sp, wo, wi, LAM, 15u, fb, pb);
        for (j = 0; j < HERO_N; j++)
            CHECK(t, fb[j] > 0.0f && fabsf(fc[j] - fb[j]) <= 1e-4f * fb[j] + 1e-7f,
                  "pair %d wavelength %d: coated (eta 1) f %g, bare conductor %g", k, j, fc[j], fb[j]);
    }
    scene_free(&s);
}

/* Anisotropic coats and bases: NEE + MIS and BSDF sampling alone give the same
   image (the walks' sampling and the f and pdf estimates see the same alphas,
   along the same axes). */
static void test_coattex_aniso_nee_vs_bsdf(T *t)
{
    static const char *const mats[2] = {
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.3 0.4 0.5 ] \"float uroughness\" 0.05 "
        "\"float vroughness\" 0.4 \"bool remaproughness\" false\n",
        "Material \"coatedconductor\" \"float interface.uroughness\" 0.3 \"float interface.vroughness\" 0.1 "
        "\"float conductor.uroughness\" 0.02 \"float conductor.vroughness\" 0.3 \"bool remaproughness\" false "
        "\"rgb albedo\" [ 0.5 0.5 0.5 ] \"float thickness\" 0.1\n",
    };
    int c;
    for (c = 0; c < 2; c++) {
        Scene s;
        RenderOptions o;
        Tiles a, b;
        if (!load_lamp(t, &s, mats[c])) return;
        render_options_default(&o);
        o.spp = test_scaled(32, 8);
        if (!test_render_tiles(t, &s, &o, 8, 2, &a)) { scene_free(&s); return; }
        o.nee = 0;
        if (!test_render_tiles(t, &s, &o, 8, 2, &b)) { scene_free(&s); return; }
        scene_free(&s);
        if (!test_tiles_agree(t, &a, &b, 2e-3, mats[c])) return;
    }
}

/* pbrt-v4 (commit 5f7a6068, `pbrt --seed S --spp N`, the independent sampler):
   (a) CT_HEAD + a smooth coat over an anisotropic gold base (conductor.uroughness
   0.05, vroughness 0.4, not remapped) + CT_QUADS, N = 1024, S = 1..8; (b) an
   anisotropic rough coat (uroughness 0.02, vroughness 0.3) over a Lambertian,
   under CT_LAMP, rendered by pbrt-v4's BSDF sampling alone ("Integrator
   "simplepath" "bool samplelights" false": its Sample_f is unbiased, its f under a
   rough coat is not, layered.c section 2), N = 2048, S = 1..16.  Luminance of the
   image and its quadrants, mean over the seeds and its standard error; accepted
   within 5 standard errors + 1 %.  Swapping u and v changes the quadrants by
   10-700 %.  specnee at 8 x 1024 spp: (a) within 0.2 %, (b) image -0.1 %,
   quadrants within 0.9 % (2.5 standard errors); pbrt-v4's path integrator, whose
   NEE uses its f, renders (b) 1.0 % brighter (image 0.021022 +- 0.000035). */
static const char *const CT_ANISO[2] = {
    "Material \"coatedconductor\" \"float conductor.uroughness\" [ 0.05 ] \"float conductor.vroughness\" [ 0.4 ] "
    "\"bool remaproughness\" false \"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\"\n",
    "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.3 0.4 0.5 ] \"float uroughness\" [ 0.02 ] "
    "\"float vroughness\" [ 0.3 ] \"bool remaproughness\" false\n",
};
static const double PBRT_CT_ANISO_Y[2][5][2] = {
    { { 1.350351, 0.00075 }, { 2.491896, 0.0014 }, { 0.290511, 0.00021 }, { 2.328800, 0.0026 }, { 0.290195, 0.00019 } },
    { { 0.020811, 3.0e-05 }, { 0.014464, 6.0e-05 }, { 0.006457, 2.4e-05 }, { 0.048596, 9.8e-05 }, { 0.013729, 4.3e-05 } },
};

static void test_coattex_aniso_against_pbrt(T *t)
{
    int j;
    for (j = 0; j < 2; j++) {
        Scene s;
        if (!(j ? load_lamp(t, &s, CT_ANISO[j]) : load_ct(t, &s, CT_ANISO[j]))) return;
        test_scene_against_pbrt_y(t, &s, test_scaled(64, 16), 3, PBRT_CT_ANISO_Y[j], 1e-2,
                                  j ? "rough anisotropic coat" : "anisotropic base");
        scene_free(&s);
        if (t->failed) return;
    }
}

/* ---------------------------------------------------------------- spectral coat index */

/* A spectral eta: a constant one is the float (the same image, bit for bit; 0
   means 1, as in pbrt-v4) and does not terminate; a varying one (spectrum or rgb) marks the material
   dispersive, and the path then carries the hero's wavelength alone from the
   coat on (pbrt-v4's TerminateSecondary): the image of four wavelengths per path
   equals, per tile and channel, that of one wavelength per path, which the coat's
   single index cannot bias (without the termination the secondaries would see the
   hero's index: their colours wash out). */
static void test_coattex_spectral_eta(T *t)
{
    static const char *const mats[5] = {
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"float eta\" 1.7\n",
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"spectrum eta\" [ 360 1.7 830 1.7 ]\n",
        "Material \"coatedconductor\" \"rgb interface.eta\" [ 1.3 1.6 2.0 ] \"float conductor.roughness\" 0.1\n",
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"float eta\" 1\n",
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"spectrum eta\" [ 360 0 830 0 ]\n",
    };
    Scene s;
    RenderOptions o;
    Tiles a, b;
    int k, c;
    for (c = 0; c < 2; c++) {        /* 1.7 as a float and a spectrum; 1 and pbrt-v4's 0 */
        Image im[2];
        for (k = 0; k < 2; k++) {
            char text[8192];
            render_options_default(&o);
            o.spp = 8;
            snprintf(text, sizeof text, "%s%s%s", CT_HEAD, mats[c ? 3 + k : k], CT_QUADS);
            if (!test_render_text(t, text, &o, &im[k])) {
                if (k) img_free(&im[0]);
                return;
            }
        }
        CHECK(t, !memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * im[0].w * im[0].h),
              "%s as a float: Y %.9g, as a spectrum: Y %.9g", c ? "eta 1 (spectrum 0)" : "eta 1.7",
              test_image_y(&im[0]), test_image_y(&im[1]));
        img_free(&im[0]);
        img_free(&im[1]);
    }
    if (!load_ct(t, &s, mats[1])) return;
    CHECK(t, !s.materials[s.n_materials - 1].dispersive, "a constant spectral eta is dispersive");
    scene_free(&s);
    if (!load_ct(t, &s, mats[2])) return;
    CHECK(t, s.materials[s.n_materials - 1].dispersive, "rgb interface.eta [ 1.3 1.6 2.0 ] not dispersive");
    scene_free(&s);
    if (!load_ct(t, &s, "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] "
                 "\"spectrum eta\" [ 360 2.2 500 2.0 560 1.4 830 1.3 ]\n"))
        return;
    render_options_default(&o);
    o.spp = test_scaled(32, 8);
    if (!test_render_tiles(t, &s, &o, 8, 2, &a)) { scene_free(&s); return; }
    o.single_wavelength = 1;
    o.spp *= 2;
    if (!test_render_tiles(t, &s, &o, 8, 2, &b)) { scene_free(&s); return; }
    scene_free(&s);
    test_tiles_agree(t, &a, &b, 2e-3, "dispersive coat: four wavelengths against one");
}

const TestCase tests_coattex[] = {
    { "coattex_params", test_coattex_params },
    { "coattex_constant", test_coattex_constant },
    { "coattex_limits", test_coattex_limits },
    { "coattex_errors", test_coattex_errors },
    { "coattex_against_pbrt", test_coattex_against_pbrt },
    { "coattex_aniso_bare", test_coattex_aniso_bare },
    { "coattex_aniso_nee_vs_bsdf", test_coattex_aniso_nee_vs_bsdf },
    { "coattex_aniso_against_pbrt", test_coattex_aniso_against_pbrt },
    { "coattex_spectral_eta", test_coattex_spectral_eta },
    { NULL, NULL },
};
