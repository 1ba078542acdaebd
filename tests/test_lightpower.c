/* tests/test_lightpower.c - pbrt-v4's AreaLightSource "diffuse" "float power"
   (lights.c emitter_apply_power, light_Le_at) and Option "integer seed"
   (scene.c option_directive and finish).

   Checked: from the emitter records, each primitive of a lamp of power Phi emits
   pi s A_k Y_k = Phi (s = 2 when two-sided, Y_k its luminance, A_k pbrt-v4's
   area: a disk, a sphere, a cylinder, a bilinear patch, the triangles of a mesh
   of unequal areas, a flat and a twisted patch of one bilinearmesh), so a mesh of
   n triangles emits n Phi; an "rgb L" of power Phi has the luminance of pbrt-v4's
   D65 normalisation times the rgb's, not Phi / (pi A); a sphere under Scale keeps
   the object-space area; an emission image divides by its mean luminance.  The
   irradiance a disk lamp of power Phi gives the floor point below its centre,
   E = Phi / (pi (h^2 + R^2)), in a rendered image.  NEE and BSDF sampling alone
   agree on meshes whose triangles have different radiance.  pbrt-v4's images of
   two scenes frozen.  The refusals at their file:line.  Option "integer seed":
   the Sampler's seed when that gives none, the same image as that seed, another
   than seed 0, the same again on a second render. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* Luminance of emitter e's radiance at primitive prim (-1: the emitter's mean),
   as specnee's film counts it: a lamp of scale 1 seen directly has 1. */
static double lamp_y(const LightSampler *ls, const Scene *s, int e, int prim)
{
    SurfacePoint sp;
    Vec3 n = v3(0, 0, 1);
    Spectrum Le;
    Error err;
    double ratio = 1.0;
    if (!emitter_radiance(s, e, LAMBDA_LO, LAMBDA_HI, &Le, &err)) return -1.0;
    if (prim >= 0) {
        memset(&sp, 0, sizeof sp);
        sp.prim = prim;
        ratio = light_Le_at(ls, e, n, n, &sp, 560.0f) / light_Le(ls, e, n, n, 560.0f);
    }
    return ratio * luminance_sum(&Le, LAMBDA_LO, LAMBDA_HI);
}

static LightSampler *power_sampler(T *t, const Scene *s)
{
    SelOptions o;
    Error err;
    LightSampler *ls;
    memset(&o, 0, sizeof o);
    o.strategy = SEL_POWER;
    o.lo_nm = LAMBDA_LO;
    o.hi_nm = LAMBDA_HI;
    ls = light_sampler_build(s, &o, &err);
    if (!ls) test_failf(t, __FILE__, __LINE__, "light sampler: %s", err.msg);
    return ls;
}

/* Emitters 0-4: a disk (r 0.5), a sphere (r 0.3), a cylinder (r 0.15, height
   0.8), a two-sided bilinear patch (1 x 0.6, scale 0.5), a D65 mesh of power 3
   with triangles of areas 0.4 and 1.2; 5: "rgb L" [ 4 3 2 ] on the same mesh; 6:
   a sphere of radius 0.3 under Scale 2 (pbrt-v4's area 4 pi 0.3^2, in object
   space); 7: a bilinearmesh of a flat patch (area 2) and a twisted one. */
static const char *const RECORDS =
    "WorldBegin\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 6\nShape \"disk\" \"float radius\" 0.5\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000 \"float power\" 15\nTranslate 3 0 0\n"
    "Shape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"stdillum-F4\" \"float power\" 8\nTranslate 6 0 0\n"
    "Shape \"cylinder\" \"float radius\" 0.15 \"float zmin\" -0.4 \"float zmax\" 0.4\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 4 \"bool twosided\" true \"float scale\" 0.5\n"
    "Translate 9 0 0\nShape \"bilinearmesh\" \"point3 P\" [ -0.5 -0.3 0  0.5 -0.3 0  -0.5 0.3 0  0.5 0.3 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 3\nTranslate 0 3 0\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2  1 3 2 ] \"point3 P\" [ 0 0 0  0.8 0 0  0 1 0  3.2 0 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 3 2 ] \"float power\" 3\nTranslate 0 6 0\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2  1 3 2 ] \"point3 P\" [ 0 0 0  0.8 0 0  0 1 0  3.2 0 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 15\nTranslate 3 6 0\nScale 2 2 2\n"
    "Shape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 5\nTranslate 0 9 0\n"
    "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  2 0 0  0 1 0  2 1 0  4 0 1  4 1 0 ] "
    "\"integer indices\" [ 0 1 2 3  1 4 3 5 ]\nAttributeEnd\n";

static void test_lightpower_records(T *t)
{
    /* the power each emitter's primitive emits, pi s A Y: emitters 0-3 whole */
    static const double want[4] = { 6.0, 15.0, 8.0, 4.0 * 0.5 };
    Scene s;
    LightSampler *ls;
    double y, yd[2], yr[2], a, sum = 0.0;
    int e, k, base;
    if (!test_load_scene(t, &s, RECORDS)) return;
    ls = power_sampler(t, &s);
    if (!ls) { scene_free(&s); return; }
    CHECK(t, s.n_emitters == 8, "%d emitters", s.n_emitters);
    for (e = 0; e < 4; e++) {
        const Emitter *em = &s.emitters[e];
        y = lamp_y(ls, &s, e, -1);
        a = SPECNEE_PI * em->area * (em->twosided ? 2.0 : 1.0) * y;
        CHECK(t, fabs(a / want[e] - 1.0) < 1e-5, "emitter %d: pi s A Y = %.7g, want %g", e, a, want[e]);
        CHECK(t, em->prim_scale == NULL, "emitter %d: one radiance, yet a table", e);
    }
    /* the mesh: each triangle emits 3 (radiance 3 / (pi A_k)), the mesh 6 */
    for (k = 0; k < 2; k++) {
        const int tri = s.shapes[s.emitters[4].shape].tri_begin + k;
        yd[k] = lamp_y(ls, &s, 4, tri);
        yr[k] = lamp_y(ls, &s, 5, s.shapes[s.emitters[5].shape].tri_begin + k);
        a = SPECNEE_PI * tri_area(&s, tri) * yd[k];
        sum += a;
        CHECK(t, fabs(a / 3.0 - 1.0) < 1e-5, "triangle %d of area %.3g emits %.7g, want 3", k,
              tri_area(&s, tri), a);
    }
    CHECK(t, fabs(yd[0] / yd[1] - 3.0) < 1e-5, "radiance ratio of the triangles %.7g, want 3", yd[0] / yd[1]);
    CHECK(t, fabs(sum / 6.0 - 1.0) < 1e-5, "the mesh emits %.7g, want 2 x 3", sum);
    /* "rgb L" [ 4 3 2 ]: pbrt-v4 divides by the illuminant's luminance, not by
       L's, so the lamp has Y(L) / Y(D65) times the luminance of the D65 lamp of the
       same power: about the rgb's, 0.2126 4 + 0.7152 3 + 0.0722 2 = 3.1 (within
       the sigmoid fit), not 1 */
    {
        Spectrum d65;
        double ratio;
        spec_named(&d65, "stdillum-D65");
        ratio = spec_to_y(s.emitters[5].L) / spec_to_y(&d65);
        for (k = 0; k < 2; k++)
            CHECK(t, fabs(yr[k] / yd[k] / ratio - 1.0) < 1e-5, "rgb L: luminance %.6g x the D65 "
                  "lamp's, want Y(L) / Y(D65) = %.6g", yr[k] / yd[k], ratio);
        CHECK(t, fabs(ratio / 3.1002 - 1.0) < 0.02, "rgb L: Y(L) / Y(D65) = %.5g, not about 3.1", ratio);
    }
    /* under Scale 2 the sphere's area is pbrt-v4's object-space 4 pi 0.3^2: its
       world area emits 4 x 15 */
    y = lamp_y(ls, &s, 6, -1);
    a = SPECNEE_PI * s.emitters[6].area * y;
    CHECK(t, fabs(a / 60.0 - 1.0) < 1e-5, "scaled sphere: pi A_world Y = %.7g, want 4 x 15", a);
    /* the bilinearmesh: the flat patch (two triangles) and the twisted one each emit 5;
       the twisted one is scaled by pbrt-v4's area, the sum over 3 x 3 sub-quads,
       here 0.35 % below its true area, so that its true power is 0.35 % above 5 */
    {
        const Shape *sh = &s.shapes[s.emitters[7].shape];
        CHECK(t, sh->tri_count == 2 && sh->patch_count == 1, "bilinearmesh: %d triangles, %d patches",
              sh->tri_count, sh->patch_count);
        y = lamp_y(ls, &s, 7, sh->tri_begin);
        CHECK(t, fabs(y / lamp_y(ls, &s, 7, sh->tri_begin + 1) - 1.0) < 1e-6, "the flat patch's halves differ");
        a = SPECNEE_PI * 2.0 * y;
        CHECK(t, fabs(a / 5.0 - 1.0) < 1e-5, "flat patch emits %.7g, want 5", a);
        base = s.n_tris + s.n_spheres + s.n_quadrics + sh->patch_begin;
        y = lamp_y(ls, &s, 7, base);
        {
            Vec3 c[4];
            patch_corners(&s, s.patches[sh->patch_begin].v, c);
            a = SPECNEE_PI * patch_area(c) * y;
        }
        CHECK(t, fabs(a / 5.0 - 1.0035) < 2e-4, "twisted patch emits %.7g, want 5 x 1.0035 (pbrt-v4's "
              "area approximation)", a);
    }
    light_sampler_free(ls);
    scene_free(&s);
}

/* An emission image with "power": pbrt-v4 divides by k_e, the image's mean
   luminance (sRGB's row): the lamp with lamp.pfm emits what the same lamp with the
   white image does, pi A Y_mean = Phi, with Y_mean its mean colour's luminance
   (within the sigmoid fit). */
static void test_lightpower_image(T *t)
{
    static const char *const text =
        "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" "
        "\"tests/data/arealimg/lamp.pfm\" \"float power\" 5\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" "
        "\"tests/data/arealimg/white.pfm\" \"float power\" 5\nTranslate 2 0 0\nShape \"sphere\" "
        "\"float radius\" 0.4\nAttributeEnd\n";
    Scene s;
    LightSampler *ls;
    double a[2];
    int e;
    if (!test_load_scene(t, &s, text)) return;
    ls = power_sampler(t, &s);
    if (!ls) { scene_free(&s); return; }
    for (e = 0; e < 2; e++) a[e] = SPECNEE_PI * s.emitters[e].area * lamp_y(ls, &s, e, -1);
    CHECK(t, fabs(a[1] / 5.0 - 1.0) < 1e-5, "white image lamp emits %.7g, want 5", a[1]);
    CHECK(t, fabs(a[0] / 5.0 - 1.0) < 3e-3, "lamp.pfm lamp emits %.7g, want 5 (within the fit)", a[0]);
    light_sampler_free(ls);
    scene_free(&s);
}

/* A one-sided disk lamp (radius R = 0.5, power Phi = 10, D65) facing down at
   height h = 2 over a floor of flat reflectance rho = 0.5: the irradiance at the
   point below its centre is E = pi L R^2 / (h^2 + R^2) with L = Phi / (pi pi R^2),
   so that point has luminance rho E / pi = rho Phi / (pi^2 (h^2 + R^2)) = 0.11920.
   A camera between them sees a 0.004-wide patch around it (E falls by 2e-6
   there); the lamp is black, so no light comes back from it. */
static void test_lightpower_irradiance(T *t)
{
    static const char *const text =
        "LookAt 0 0 1  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 0.25 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
        "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 300 0.5 800 0.5 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -9 -9 0  9 -9 0  9 9 0  -9 9 0 ]\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 10\nTranslate 0 0 2\nReverseOrientation\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\nShape \"disk\" \"float radius\" 0.5\nAttributeEnd\n";
    const double want = 0.5 * 10.0 / (SPECNEE_PI * SPECNEE_PI * (4.0 + 0.25));
    double y, se;
    if (!test_mean_y(t, text, test_scaled(64, 16), 1, 8, &y, &se)) return;
    CHECK(t, fabs(y - want) < TEST_K_SIGMA * se + 1e-4 * want, "floor below the lamp: Y %.6f +- %.2g, "
          "want rho Phi / (pi^2 (h^2 + R^2)) = %.6f", y, se, want);
}

/* NEE (which reads the sampled triangle's radiance) and BSDF sampling alone see
   the same light from a mesh lamp of a small triangle just above the floor and a
   large one far to the side, out of view (radiance ratio 75: the mean radiance
   would light the floor another way), and from a bilinearmesh of a small flat
   patch above the floor and a large twisted one far to the other side. */
static void test_lightpower_nee_agrees(T *t)
{
    static const char *const text =
        "LookAt -0.8 0 4  -0.8 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
        "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 2 ]\nWorldBegin\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ]\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 3\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2  3 4 5 ] \"point3 P\" [ -1.4 -0.4 0.5  -1.2 0.0 0.5  "
        "-1.0 -0.4 0.5  -5 -2 0.5  -5 2 0.5  -5 0 3.5 ]\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 2 \"bool twosided\" true\n"
        "Shape \"bilinearmesh\" \"point3 P\" [ -0.6 0.3 0.6  -0.2 0.3 0.6  -0.6 0.7 0.6  -0.2 0.7 0.6  "
        "5 -2 0.5  5 2 1.0  5.5 -2 3.5  5 2 3 ] \"integer indices\" [ 0 1 2 3  4 5 6 7 ]\nAttributeEnd\n";
    const int K = 8, spp = test_scaled(64, 16);
    double y0, se0, y1, se1;
    if (!test_mean_y(t, text, spp, 1, K, &y0, &se0)) return;
    if (!test_mean_y(t, text, spp, 0, K, &y1, &se1)) return;
    CHECK(t, y0 > 0.01, "the floor is dark: Y %g", y0);
    CHECK(t, fabs(y1 - y0) < TEST_K_SIGMA * sqrt(se0 * se0 + se1 * se1),
          "NEE: Y %.5f +- %.2g; BSDF sampling alone: %.5f +- %.2g", y0, se0, y1, se1);
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, `pbrt --seed S --spp 1024`, S = 1..8, the
   independent sampler) rendered POWER_DIRECT: lamps of "float power" seen directly
   (maxdepth 1, so the image is their radiance): a disk under a non-uniform
   Scale ("rgb L"), a sphere under Scale 0.5 (blackbody), a sphere under a
   non-uniform Scale with an emission image, a mesh of three triangles of unequal
   areas ("rgb L"), a two-sided non-planar bilinear patch seen from behind (scale
   0.5) and a cylinder under Scale (F4).  Luminance of the image and its quadrants
   (top left first), mean over the seeds and its standard error; accepted within 5
   standard errors + 1 % (specnee 2048 spp: image -0.01 %, quadrants within 0.4 %). */
static const char *const POWER_DIRECT =
    "LookAt 0 0 6  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 3 2 ] \"float power\" 6\n"
    "Translate -1.3 1.2 0\nScale 1.5 0.8 1\nShape \"disk\" \"float radius\" 0.5\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000 \"float power\" 15\n"
    "Translate 1.2 1.3 0\nScale 0.5 0.5 0.5\nShape \"sphere\" \"float radius\" 1.2\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"tests/data/arealimg/lamp.pfm\" "
    "\"float power\" 5\nTranslate 0.3 1.0 -1\nScale 0.6 1 0.6\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 2 3 ] \"float power\" 3\nTranslate -1.4 -1.2 0\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2  0 2 3  1 4 2 ] \"point3 P\" [ -0.6 -0.4 0  0.2 -0.4 0  "
    "0.2 0.4 0.1  -0.6 0.4 0.1  1.0 -0.4 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 4 \"bool twosided\" true \"float scale\" 0.5\n"
    "Translate 1.3 -0.8 0\nRotate 160 0 1 0\nShape \"bilinearmesh\" \"point3 P\" [ -0.5 -0.3 0  0.5 -0.3 0  "
    "-0.5 0.3 0.2  0.5 0.3 0 ] \"integer indices\" [ 0 1 2 3 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"spectrum L\" \"stdillum-F4\" \"float power\" 8\n"
    "Translate 0.8 -1.7 0\nScale 1.5 1 1\nRotate 90 0 1 0\n"
    "Shape \"cylinder\" \"float radius\" 0.15 \"float zmin\" -0.4 \"float zmax\" 0.4\nAttributeEnd\n";
static const double PBRT_POWER_DIRECT_Y[5][2] = {
    { 0.594365, 0.0002 }, { 0.102726, 8e-05 }, { 1.166774, 0.00064 }, { 0.262942, 0.00025 }, { 0.845017, 0.0004 },
};

/* pbrt-v4 (as above, `--spp 1024`, S = 1..8) rendered POWER_LIT: lamps of "float
   power" under rigid transforms lighting a grey floor (volpath, maxdepth 5): a
   disk ("rgb L"), a sphere (blackbody), a two-sided bilinear patch (scale 0.5), a
   mesh of three triangles of unequal areas ("rgb L") and a sphere with an
   emission image.  Accepted as POWER_DIRECT (specnee 4096 spp: image +0.1 %,
   quadrants within 0.4 %). */
static const char *const POWER_LIT =
    "LookAt 0 -3 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"independent\"\nIntegrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ]\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 3 2 ] \"float power\" 6\n"
    "Translate -1.4 1.0 1.5\nReverseOrientation\nShape \"disk\" \"float radius\" 0.5\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000 \"float power\" 15\n"
    "Translate 1.3 0.8 0.8\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 4 \"bool twosided\" true \"float scale\" 0.5\n"
    "Translate 0.4 -1.4 1.0\nRotate 60 1 0 0\n"
    "Shape \"bilinearmesh\" \"point3 P\" [ -0.5 -0.3 0  0.5 -0.3 0  -0.5 0.3 0  0.5 0.3 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 2 3 ] \"float power\" 3\n"
    "Translate -0.8 -0.6 1.6\nReverseOrientation\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2  0 2 3  1 4 2 ] \"point3 P\" [ -0.6 -0.4 0  0.2 -0.4 0  "
    "0.2 0.4 0.1  -0.6 0.4 0.1  1.4 -0.4 0 ]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"tests/data/arealimg/lamp.pfm\" "
    "\"float power\" 5\nTranslate 0.2 1.6 1.2\nRotate 30 0 1 0\nShape \"sphere\" \"float radius\" 0.35\nAttributeEnd\n";
static const double PBRT_POWER_LIT_Y[5][2] = {
    { 0.310041, 0.00011 }, { 0.560987, 0.00041 }, { 0.168365, 0.00014 }, { 0.201318, 0.00016 }, { 0.309495, 0.00018 },
};

static void test_lightpower_against_pbrt(T *t)
{
    test_against_pbrt_y(t, POWER_DIRECT, 3, PBRT_POWER_DIRECT_Y, 1e-2, "power, seen directly");
    if (t->failed) return;
    test_against_pbrt_y(t, POWER_LIT, 3, PBRT_POWER_LIT_Y, 1e-2, "power, lighting a floor");
}

/* Refusals, one line at file:line. */
static void test_lightpower_errors(T *t)
{
    test_rejected_at(t, "WorldBegin\n\nAreaLightSource \"diffuse\" \"float power\" 1e39\n", 3,
                     "\"float power\"", "is not a finite number");
    test_rejected_at(t, "WorldBegin\nAreaLightSource \"diffuse\" \"string filename\" "
                     "\"tests/data/arealimg/black.pfm\" \"float power\" 2\n", 2,
                     "\"float power\" with the image", "black.pfm");
    test_rejected_at(t, "WorldBegin\nAreaLightSource \"diffuse\" \"spectrum L\" [ 300 1 380 1 390 0 800 0 ] "
                     "\"float power\" 2\n", 2, "\"float power\" with an L that has no luminance", NULL);
    test_rejected_at(t, "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 1e30\n"
                     "Shape \"disk\" \"float radius\" 1e-6\nAttributeEnd\n", 4,
                     "scale x power / area is not a finite number", NULL);
    test_rejected_at(t, "Option \"float seed\" 7\nWorldBegin\n", 1,
                     "Option \"seed\": expected one \"integer seed\" value", NULL);
}

/* Option "integer seed": the scene's seed when its Sampler gives none (pbrt-v4:
   the Sampler's "integer seed" wins, wherever the Option stands); rendering
   with it is rendering the same scene without it at that seed, deterministic, and
   not the image of seed 0. */
static void test_option_seed(T *t)
{
    static const char *const body =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n%s"
        "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 3\n"
        "Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 -1  4 -4 -1  4 4 -1  -4 4 -1 ]\n";
    static const char *const head[4] = {
        "Option \"integer seed\" 7\nSampler \"independent\"\n",
        "Sampler \"independent\" \"integer seed\" 3\nOption \"integer seed\" 7\n",
        "Option \"integer seed\" 7\nSampler \"independent\" \"integer seed\" 3\n",
        "Sampler \"independent\"\n",
    };
    static const int want[4][2] = { { 7, 1 }, { 3, 1 }, { 3, 1 }, { 0, 0 } };
    char text[2048];
    Image im[4];
    int i, seeds[4] = { 7, 7, 7, 0 };
    for (i = 0; i < 4; i++) {
        Scene s;
        snprintf(text, sizeof text, body, head[i]);
        if (!test_load_scene(t, &s, text)) return;
        CHECK(t, s.settings.seed == want[i][0] && s.settings.seed_set == want[i][1],
              "case %d: seed %d (set %d), want %d (%d)", i, s.settings.seed, s.settings.seed_set,
              want[i][0], want[i][1]);
        scene_free(&s);
    }
    /* im 0: the Option's seed, as specnee.c applies it; 1: again; 2: no Option, at
       7; 3: no Option, at 0 */
    for (i = 0; i < 4; i++) {
        RenderOptions o;
        Scene s;
        RenderStats st;
        Error err;
        int ok;
        snprintf(text, sizeof text, body, i < 2 ? head[0] : head[3]);
        if (!test_load_scene(t, &s, text)) return;
        render_options_default(&o);
        o.spp = 4;
        o.threads = 2;
        o.seed = i < 2 ? s.settings.seed : seeds[i];
        ok = render(&s, &o, &im[i], &st, &err);
        scene_free(&s);
        CHECK(t, ok, "render: %s", err.msg);
    }
    CHECK(t, !memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * 64), "two renders at Option seed 7 differ");
    CHECK(t, !memcmp(im[0].rgb, im[2].rgb, sizeof(float) * 3 * 64), "Option seed 7 is not seed 7");
    CHECK(t, memcmp(im[0].rgb, im[3].rgb, sizeof(float) * 3 * 64) != 0, "Option seed 7 renders seed 0");
    for (i = 0; i < 4; i++) img_free(&im[i]);
}

const TestCase tests_lightpower[] = {
    { "lightpower_records", test_lightpower_records },
    { "lightpower_image", test_lightpower_image },
    { "lightpower_irradiance", test_lightpower_irradiance },
    { "lightpower_nee_agrees", test_lightpower_nee_agrees },
    { "lightpower_against_pbrt", test_lightpower_against_pbrt },
    { "lightpower_errors", test_lightpower_errors },
    { "option_seed", test_option_seed },
    { NULL, NULL }
};
