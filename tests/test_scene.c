/* tests/test_scene.c - tests of the pbrt-v4 subset parser (parser.c, scene.c and
   the builders in each concept's room).

   Every parser feature is loaded from a small text and checked for what it
   must mean in pbrt-v4 (transform order and matrix layout, the camera frame,
   orientation, the attribute stack, named materials, Include, insets, emitter
   normalisation), and every rejection is one test that checks the message has
   the form "file:line: ..." with the right line and the key words.  Scratch
   files go to the test tmpdir (test_write_file); fixtures live in tests/scenes/. */
#include "test.h"
#include "../parser.h"
#include <string.h>
#include <stdlib.h>

#define NAME "t.pbrt"

static int load(Scene *s, const char *text, Error *e)
{
    return scene_load_string(s, text, NAME, e);
}

/* Load must fail with "t.pbrt:LINE: ..." containing k1 (and k2 when given). */
static void expect_reject(T *t, const char *text, int line, const char *k1, const char *k2)
{
    Scene s;
    Error e;
    char prefix[64];
    int ok;
    e.msg[0] = '\0';
    ok = load(&s, text, &e);
    if (ok) scene_free(&s);
    CHECK(t, !ok, "accepted bad input, expected an error with \"%s\"", k1);
    snprintf(prefix, sizeof prefix, "%s:%d:", NAME, line);
    CHECK(t, strncmp(e.msg, prefix, strlen(prefix)) == 0, "message \"%s\" does not start "
          "with \"%s\"", e.msg, prefix);
    CHECK(t, strchr(e.msg, '\n') == NULL, "message \"%s\" is not one line", e.msg);
    CHECK(t, strstr(e.msg, k1) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k1);
    CHECK(t, !k2 || strstr(e.msg, k2) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k2);
    /* a failed load leaves an empty scene that scene_free accepts again */
    CHECK(t, s.n_shapes == 0 && s.P == NULL, "failed load left data behind");
    scene_free(&s);
}

/* Luminance as the film sees it: Y = sum_{1 nm} ybar(lambda) S(lambda) over the
   sampled range (so a light with scale s has Y = s). */
static double y_sum(const Spectrum *sp)
{
    double Y = 0.0;
    int lam;
    for (lam = (int)LAMBDA_LO; lam <= (int)LAMBDA_HI; lam++) {
        float xyz[3];
        cie_xyz((float)lam, xyz);
        Y += (double)xyz[1] * spec_eval(sp, (float)lam);
    }
    return Y;
}

/* Y of emitter e's radiance as a render over 400-700 nm sees it (lights.c). */
static double y_emitter(const Scene *s, int e)
{
    Spectrum Le;
    Error err;
    if (!emitter_radiance(s, e, LAMBDA_LO, LAMBDA_HI, &Le, &err)) return -1.0;
    return y_sum(&Le);
}

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }
static int vnear(Vec3 a, Vec3 b, float tol)
{
    return near(a.x, b.x, tol) && near(a.y, b.y, tol) && near(a.z, b.z, tol);
}

/* The oriented geometric normal of triangle i, as bvh.c's scene_surface_point
   computes it (pbrt-v4: cross(p0 - p2, p1 - p2), negated by Shape.flip). */
static Vec3 oriented_normal(const Scene *s, int i)
{
    const Triangle *tr = &s->tris[i];
    Vec3 p0 = s->P[tr->v[0]], p1 = s->P[tr->v[1]], p2 = s->P[tr->v[2]];
    Vec3 n = v3_norm(v3_cross(v3_sub(p0, p2), v3_sub(p1, p2)));
    return s->shapes[tr->shape].flip ? v3_neg(n) : n;
}

/* ------------------------------------------------------------------------
   Features
   ------------------------------------------------------------------------ */
static void test_defaults(T *t)
{
    Scene s;
    Error e;
    const SceneSettings *st = &s.settings;
    CHECK(t, load(&s, "WorldBegin\nShape \"sphere\"\n", &e), "%s", e.msg);
    CHECK(t, st->xres == 1280 && st->yres == 720, "default film %dx%d, pbrt-v4 has 1280x720",
          st->xres, st->yres);
    CHECK(t, st->fov_deg == 90.0f, "default fov %g, pbrt-v4 has 90", st->fov_deg);
    CHECK(t, st->spp == DEFAULT_SPP && !st->spp_set && !st->seed_set && !st->maxdepth_set,
          "defaults must not be marked as given");
    CHECK(t, st->maxdepth == 5, "default maxdepth %d, pbrt-v4 has 5", st->maxdepth);
    CHECK(t, st->filter == FILTER_GAUSSIAN && st->filter_radius == 1.5f &&
          st->filter_sigma == 0.5f, "default filter must be pbrt-v4's gaussian 1.5/0.5");
    CHECK(t, strcmp(st->filename, "pbrt.pfm") == 0, "default file \"%s\"", st->filename);
    CHECK(t, s.n_shapes == 1 && s.n_spheres == 1 && s.n_materials == 1, "one sphere, one material");
    CHECK(t, s.materials[0].type == MAT_DIFFUSE && near(albedo_eval(&s.materials[0].reflectance, 550), 0.5, 1e-6),
          "default material must be diffuse 0.5");
    CHECK(t, s.shapes[0].radius == 1.0f && vnear(s.shapes[0].center, v3(0, 0, 0), 0),
          "default sphere: radius 1 at the origin");
    CHECK(t, near(s.shapes[0].area, 4 * SPECNEE_PI, 1e-4), "sphere area %g", s.shapes[0].area);
    CHECK(t, s.shapes[0].emitter == -1, "no light given, yet an emitter");
    CHECK(t, vnear(s.bmin, v3(-1, -1, -1), 1e-6f) && vnear(s.bmax, v3(1, 1, 1), 1e-6f), "bounds");
    scene_free(&s);
}

static void test_options(T *t)
{
    Scene s;
    Error e;
    const SceneSettings *st = &s.settings;
    const char *text =
        "Camera \"perspective\" \"float fov\" [ 45 ]\n"
        "Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" [ 32 ]\n"
        "     \"string filename\" \"out.png\" \"bool savefp16\" false\n"
        "Sampler \"halton\" \"integer pixelsamples\" 8 \"integer seed\" 7\n"
        "Integrator \"path\" \"integer maxdepth\" 3 \"string lightsampler\" \"power\"\n"
        "PixelFilter \"box\" \"float xradius\" 0.5 \"float yradius\" 0.5\n"
        "WorldBegin\n";
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, st->fov_deg == 45.0f && st->xres == 64 && st->yres == 32, "camera/film values");
    CHECK(t, strcmp(st->filename, "out.png") == 0, "filename \"%s\"", st->filename);
    CHECK(t, st->spp == 8 && st->spp_set && st->seed == 7 && st->seed_set, "sampler values");
    CHECK(t, st->maxdepth == 3 && st->maxdepth_set, "maxdepth");
    CHECK(t, strcmp(st->lightsampler, "power") == 0, "lightsampler \"%s\"", st->lightsampler);
    CHECK(t, st->filter == FILTER_BOX && st->filter_radius == 0.5f, "box filter");
    scene_free(&s);
    /* pbrt-v4 sample-count defaults per sampler type */
    CHECK(t, load(&s, "Sampler \"independent\"\nWorldBegin\n", &e), "%s", e.msg);
    CHECK(t, st->spp == 4 && !st->spp_set, "independent defaults to 4 spp (pbrt-v4), got %d", st->spp);
    scene_free(&s);
    CHECK(t, load(&s, "Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 3\n"
                  "WorldBegin\n", &e), "%s", e.msg);
    CHECK(t, st->spp == 6 && st->spp_set, "stratified spp = xsamples * ysamples, got %d", st->spp);
    scene_free(&s);
    /* pbrt's default film name becomes .pfm */
    CHECK(t, load(&s, "Film \"rgb\" \"string filename\" \"a.exr\"\nWorldBegin\n", &e), "%s", e.msg);
    CHECK(t, strcmp(st->filename, "a.pfm") == 0, "a.exr must map to a.pfm, got %s", st->filename);
    scene_free(&s);
}

/* pbrt's LookAt is left-handed: with up +y looking along +z, world +x is on the
   right of the image (camera x > 0).  `Scale -1 1 1` before LookAt mirrors it:
   the Cornell box's red wall (x = 550) then appears on the left. */
static void test_camera_frame(T *t)
{
    Scene s;
    Error e;
    Vec3 red = v3(550, 274, 280), green = v3(0, 274, 280), look = v3(278, 273, 0), c;
    const char *body = "LookAt 278 273 -800  278 273 0  0 1 0\n"
                       "Camera \"perspective\" \"float fov\" 39.3\nWorldBegin\n";
    char text[512];
    CHECK(t, load(&s, body, &e), "%s", e.msg);
    c = xf_point(&s.settings.camera_from_world, red);
    CHECK(t, c.x > 0, "plain LookAt: world +x must be on the right (camera x %g)", c.x);
    c = xf_point(&s.settings.camera_from_world, look);
    CHECK(t, vnear(c, v3(0, 0, 800), 1e-3f), "look point must be on the axis at z 800: (%g %g %g)",
          c.x, c.y, c.z);
    c = xf_point(&s.settings.camera_from_world, v3(278, 400, 0));
    CHECK(t, c.y > 0, "up must stay up (camera y %g)", c.y);
    scene_free(&s);
    snprintf(text, sizeof text, "Scale -1 1 1\n%s", body);
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    c = xf_point(&s.settings.camera_from_world, red);
    CHECK(t, c.x < 0, "with Scale -1 1 1 the red wall must be on the left (camera x %g)", c.x);
    c = xf_point(&s.settings.camera_from_world, green);
    CHECK(t, c.x > 0, "with Scale -1 1 1 the green wall must be on the right (camera x %g)", c.x);
    CHECK(t, s.settings.fov_deg == 39.3f, "fov");
    scene_free(&s);
}

/* CTM <- CTM * T: the last transform acts first on the object. */
static void test_transform_order(T *t)
{
    Scene s;
    Error e;
    const char *text =
        "WorldBegin\n"
        "AttributeBegin\n Translate 1 0 0\n Scale 2 2 2\n"
        " Shape \"trianglemesh\" \"point3 P\" [ 1 0 0  0 1 0  0 0 1 ]\nAttributeEnd\n"
        "AttributeBegin\n Rotate 90 0 0 1\n"
        " Shape \"trianglemesh\" \"point3 P\" [ 1 0 0  0 1 0  0 0 1 ]\nAttributeEnd\n";
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, s.n_tris == 2 && s.n_verts == 6, "two triangles, six vertices");
    CHECK(t, vnear(s.P[0], v3(3, 0, 0), 1e-6f), "T(1,0,0) S(2): (1,0,0) -> (3,0,0), got (%g %g %g)",
          s.P[0].x, s.P[0].y, s.P[0].z);
    CHECK(t, vnear(s.P[3], v3(0, 1, 0), 1e-6f), "Rotate 90 about z: (1,0,0) -> (0,1,0), got (%g %g %g)",
          s.P[3].x, s.P[3].y, s.P[3].z);
    CHECK(t, vnear(s.P[4], v3(-1, 0, 0), 1e-6f), "Rotate 90 about z: (0,1,0) -> (-1,0,0)");
    scene_free(&s);
}

/* pbrt-v4 reads Transform's 16 numbers column by column: m12 m13 m14 translate. */
static void test_transform_matrix(T *t)
{
    Scene s;
    Error e;
    const char *text =
        "WorldBegin\n"
        "Translate 100 0 0\n"
        "Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]\n"      /* replaces the CTM */
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "ConcatTransform [ 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1 ]\n" /* CTM * S(2) */
        "Shape \"trianglemesh\" \"point3 P\" [ 1 1 1  1 0 0  0 1 0 ]\n"
        "Identity\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 1 1 1  1 0 0  0 1 0 ]\n";
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, vnear(s.P[0], v3(5, 6, 7), 1e-6f), "Transform: origin -> (5,6,7), got (%g %g %g)",
          s.P[0].x, s.P[0].y, s.P[0].z);
    CHECK(t, vnear(s.P[3], v3(7, 8, 9), 1e-6f), "ConcatTransform post-multiplies: (1,1,1) -> (7,8,9), "
          "got (%g %g %g)", s.P[3].x, s.P[3].y, s.P[3].z);
    CHECK(t, vnear(s.P[6], v3(1, 1, 1), 0), "Identity resets the CTM");
    scene_free(&s);
}

static void test_coordsys(T *t)
{
    Scene s;
    Error e;
    Vec3 c;
    const char *text =
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Translate 1 2 3\nCoordinateSystem \"here\"\nTranslate 10 0 0\n"
        "CoordSysTransform \"here\"\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "CoordSysTransform \"camera\"\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n";
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, vnear(s.P[0], v3(1, 2, 3), 1e-6f), "CoordSysTransform restores the named CTM");
    c = s.P[3];
    CHECK(t, vnear(c, v3(0, 0, -5), 1e-5f), "\"camera\" is world_from_camera: origin -> eye, got "
          "(%g %g %g)", c.x, c.y, c.z);
    scene_free(&s);
}

static void test_attribute_stack(T *t)
{
    Scene s;
    Error e;
    const char *text =
        "WorldBegin\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.2 0.2 ]\n"
        "AttributeBegin\n"
        "  Material \"dielectric\"\n  Translate 0 5 0\n  ReverseOrientation\n"
        "  AttributeBegin\n    Translate 0 5 0\n"
        "    Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "  AttributeEnd\n"
        "  Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "AttributeEnd\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "TransformBegin\n  Translate 0 1 0\nTransformEnd\n"   /* deprecated, = Attribute */
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n";
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, s.n_shapes == 4, "four shapes, got %d", s.n_shapes);
    CHECK(t, near(s.P[0].y, 10, 0) && near(s.P[3].y, 5, 0) && near(s.P[6].y, 0, 0) &&
          near(s.P[9].y, 0, 0), "CTM must be pushed and popped");
    CHECK(t, s.materials[s.shapes[0].material].type == MAT_DIELECTRIC &&
          s.materials[s.shapes[1].material].type == MAT_DIELECTRIC &&
          s.materials[s.shapes[2].material].type == MAT_DIFFUSE,
          "material must be pushed and popped");
    CHECK(t, s.shapes[0].flip && s.shapes[1].flip && !s.shapes[2].flip && !s.shapes[3].flip,
          "ReverseOrientation must be pushed and popped");
    scene_free(&s);
}

/* flip = ReverseOrientation XOR swaps_handedness: a mirroring transform changes
   the winding, and flip compensates, so the emitting side follows the normal
   transform; ReverseOrientation really turns the emitter around. */
static void test_orientation(T *t)
{
    static const char *const pre[4] = { "", "Scale -1 1 1\n", "ReverseOrientation\n",
                                        "Scale -1 1 1\nReverseOrientation\n" };
    static const float want_y[4] = { -1, -1, 1, 1 };
    int k;
    for (k = 0; k < 4; k++) {
        Scene s;
        Error e;
        char text[512];
        Vec3 n;
        snprintf(text, sizeof text, "WorldBegin\nAttributeBegin\n%s"
                 "AreaLightSource \"diffuse\"\n"
                 "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2  0 2 3 ]\n"
                 "  \"point3 P\" [ 1 5 -1  1 5 1  -1 5 1  -1 5 -1 ]\nAttributeEnd\n", pre[k]);
        CHECK(t, load(&s, text, &e), "%s", e.msg);
        CHECK(t, s.n_emitters == 1 && s.shapes[0].emitter == 0, "one emitter");
        CHECK(t, s.shapes[0].flip == (k == 1 || k == 2), "case %d: flip %d", k, s.shapes[0].flip);
        n = oriented_normal(&s, 0);
        CHECK(t, near(n.y, want_y[k], 1e-6), "case %d (%s): emitter normal y %g, want %g", k,
              pre[k], n.y, want_y[k]);
        n = oriented_normal(&s, 1);
        CHECK(t, near(n.y, want_y[k], 1e-6), "case %d: second triangle disagrees", k);
        scene_free(&s);
    }
}

static void test_named_materials(T *t)
{
    Scene s;
    Error e;
    const char *text =
        "WorldBegin\n"
        "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"float eta\" 1.33\n"
        "MakeNamedMaterial \"paint\" \"string type\" [ \"diffuse\" ]\n"
        "   \"spectrum reflectance\" [ 300 0.25 900 0.25 ]\n"
        "NamedMaterial \"paint\"\n"
        "Shape \"sphere\"\n"
        "NamedMaterial \"glass\"\n"
        "Shape \"sphere\"\n";
    const Material *m0, *m1;
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    m0 = &s.materials[s.shapes[0].material];
    m1 = &s.materials[s.shapes[1].material];
    CHECK(t, m0->type == MAT_DIFFUSE && near(albedo_eval(&m0->reflectance, 500), 0.25, 1e-6),
          "NamedMaterial \"paint\"");
    CHECK(t, m1->type == MAT_DIELECTRIC && near(spec_eval(m1->eta, 500), 1.33, 1e-6) &&
          !m1->dispersive && m1->alpha == 0, "NamedMaterial \"glass\"");
    scene_free(&s);
}

static void test_dielectric(T *t)
{
    Scene s;
    Error e;
    const char *text =
        "WorldBegin\n"
        "Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"\nShape \"sphere\"\n"
        "Material \"dielectric\" \"float cauchyA\" 1.5 \"float cauchyB\" 0.02 "
        "\"float roughness\" 0.04\nShape \"sphere\"\n"
        "Material \"dielectric\" \"float roughness\" 0.04 \"bool remaproughness\" false\n"
        "Shape \"sphere\"\n"
        "Material \"dielectric\" \"spectrum eta\" [ 300 1.6  900 1.4 ]\nShape \"sphere\"\n";
    const Material *m;
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    m = &s.materials[s.shapes[0].material];
    CHECK(t, m->dispersive && spec_eval(m->eta, 450) > spec_eval(m->eta, 650) &&
          near(spec_eval(m->eta, 587.6f), 1.5168, 2e-3), "glass-BK7: dispersive, n_d 1.5168, "
          "got %g", spec_eval(m->eta, 587.6f));
    m = &s.materials[s.shapes[1].material];
    CHECK(t, m->dispersive && near(spec_eval(m->eta, 500), 1.5 + 0.02 / 0.25, 1e-5) &&
          m->cauchy_a == 1.5f && m->cauchy_b == 0.02f, "Cauchy: n(500) = A + B/0.5^2, got %g",
          spec_eval(m->eta, 500));
    CHECK(t, near(m->alpha, 0.2, 1e-6), "remaproughness: alpha = sqrt(0.04) = 0.2, got %g", m->alpha);
    m = &s.materials[s.shapes[2].material];
    CHECK(t, near(m->alpha, 0.04, 1e-7) && near(spec_eval(m->eta, 500), 1.5, 0) && !m->dispersive,
          "remaproughness false: alpha = roughness; default eta 1.5");
    m = &s.materials[s.shapes[3].material];
    CHECK(t, near(spec_eval(m->eta, 600), 1.5, 1e-5) && m->dispersive, "inline eta table");
    scene_free(&s);
}

static void test_emitters(T *t)
{
    Scene s;
    Error e;
    double Y;
    const char *text =
        "WorldBegin\n"
        "AttributeBegin\n"
        "  AreaLightSource \"diffuse\" \"spectrum L\" [ 400 0  500 8  600 15.6  700 18.4 ]\n"
        "     \"float scale\" 12 \"bool twosided\" true\n"
        "  Shape \"sphere\" \"float radius\" 0.5\n"
        "  Translate 3 0 0\n"
        "  Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "AttributeEnd\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n";
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, s.n_emitters == 2, "two emissive shapes make two emitters, got %d", s.n_emitters);
    CHECK(t, s.shapes[0].emitter == 0 && s.shapes[1].emitter == 1 && s.shapes[2].emitter == -1,
          "the light must end with its attribute block");
    CHECK(t, s.emitters[1].shape == 1 && s.emitters[0].scale == 12.0f && s.emitters[0].twosided,
          "emitter fields");
    CHECK(t, near(spec_eval(s.emitters[0].L, 550), 11.8, 1e-4), "L as given");
    Y = y_emitter(&s, 0);
    CHECK(t, near(Y, 12.0, 12.0 * 1e-3), "pbrt normalisation: a seen light has Y = scale, "
          "got Y %g", Y);
    scene_free(&s);
    /* no L: the colour space's illuminant (D65) */
    CHECK(t, load(&s, "WorldBegin\nAreaLightSource \"diffuse\"\nShape \"sphere\"\n", &e), "%s", e.msg);
    {
        Spectrum d65;
        CHECK(t, spec_named(&d65, "stdillum-D65"), "stdillum-D65 missing");
        CHECK(t, near(spec_eval(s.emitters[0].L, 560), spec_eval(&d65, 560), 1e-6) &&
              s.emitters[0].scale == 1.0f && !s.emitters[0].twosided, "default L = D65, scale 1, one-sided");
    }
    scene_free(&s);
}

/* Lights with the same L share one spectrum record (Scene.spectra): the memory
   for spectra grows with the distinct spectra, not with the lamps.  20 rgb colours
   used twice (the second use after the store has grown past its first table),
   and three spectra that differ only above 700 nm or only in the UV: 43 lamps, 23
   records; each lamp keeps the spectrum it was given and emits exactly what it
   emits alone in a scene. */
static void scene_lamps_text(char *buf, size_t cap, int first, int n)
{
    static const char *const spectra[3] = {
        "\"spectrum L\" [ 300 1  830 1 ]", "\"spectrum L\" [ 300 1  700 1  830 2 ]",
        "\"spectrum L\" [ 300 2  359 1  830 1 ]" };
    size_t len;
    int i;
    snprintf(buf, cap, "WorldBegin\n");
    for (i = first; i < first + n; i++) {
        char L[96];
        int c = i % 20;
        len = strlen(buf);
        if (i < 40) snprintf(L, sizeof L, "\"rgb L\" [ %.2f %.2f %.2f ]", 0.1 + 0.04 * c,
                             0.9 - 0.03 * c, 0.2 + 0.01 * (c % 7));
        else snprintf(L, sizeof L, "%s", spectra[i - 40]);
        snprintf(buf + len, cap - len, "AttributeBegin\n  AreaLightSource \"diffuse\" %s\n"
                 "  Translate %d 0 0\n  Shape \"sphere\" \"float radius\" 0.1\nAttributeEnd\n",
                 L, i);
    }
}

static void test_shared_spectra(T *t)
{
    static char buf[16384];
    Scene s, one;
    Error e;
    int i, j, shared = 1, apart = 1, alone = 1;
    scene_lamps_text(buf, sizeof buf, 0, 43);
    CHECK(t, load(&s, buf, &e), "%s", e.msg);
    if (t->failed) return;
    /* and one record more: the default material's reflectance 0.5 */
    CHECK(t, s.n_emitters == 43 && s.spectra.n == 24, "43 lamps of 23 distinct spectra: "
          "%d emitters, %d spectrum records", s.n_emitters, s.spectra.n);
    for (i = 0; i < 20; i++) {
        shared &= s.emitters[i].L == s.emitters[i + 20].L;
        for (j = 0; j < 43; j++)
            if (j != i && j != i + 20) apart &= s.emitters[i].L != s.emitters[j].L;
    }
    CHECK(t, shared, "lamps with the same rgb L do not share one spectrum");
    CHECK(t, apart, "lamps with different L share a spectrum");
    CHECK(t, spec_eval(s.emitters[40].L, 765.0f) == 1.0f && spec_eval(s.emitters[41].L, 765.0f) == 1.5f &&
          spec_eval(s.emitters[42].L, 765.0f) == 1.0f && spec_eval(s.emitters[42].L, 300.0f) == 2.0f &&
          spec_eval(s.emitters[40].L, 300.0f) == 1.0f,
          "a lamp's L is not the spectrum it was given");
    /* every lamp emits what it emits alone (the same record, byte for byte) */
    for (i = 0; i < 43 && alone; i++) {
        Spectrum a, b;
        scene_lamps_text(buf, sizeof buf, i, 1);
        if (!load(&one, buf, &e)) { alone = 0; break; }
        alone = emitter_radiance(&s, i, LAMBDA_LO, LAMBDA_HI, &a, &e) &&
                emitter_radiance(&one, 0, LAMBDA_LO, LAMBDA_HI, &b, &e) &&
                memcmp(&a, &b, sizeof a) == 0 && memcmp(s.emitters[i].L, one.emitters[0].L, sizeof a) == 0;
        scene_free(&one);
    }
    CHECK(t, alone, "lamp %d emits otherwise than alone", i - 1);
    scene_free(&s);
}

/* Materials of the same index share one eta record (Scene.spectra), those of
   different indices do not, and each material's eta is, byte for byte, the one it
   has when it is the scene's only material; mat_regularized's copy points at the
   same record. */
static const char *const ETA_MATS[] = {
    "\"diffuse\"", "\"dielectric\" \"float eta\" 1.5", "\"dielectric\"",
    "\"dielectric\" \"spectrum eta\" \"glass-BK7\"", "\"dielectric\" \"spectrum eta\" \"glass-BK7\"",
    "\"conductor\"", "\"coateddiffuse\"", "\"thindielectric\" \"float eta\" 1.33",
    "\"dielectric\" \"float eta\" 1.33", "\"diffuse\" \"rgb reflectance\" [ 0.2 0.3 0.4 ]"
};
/* A material's reflectance as the loader keeps it.  In a scene that holds
   ALBEDO_TABLES spectrum records (here as many lamps of distinct rgb L), an "rgb"
   colour of diffuse, coateddiffuse and fluorescent is its sigmoid (Albedo.rgb, no
   table), evaluating as spec_from_rgb_t's table of the colour, bit for bit; a grey
   "rgb" and a "spectrum" stay tables (a grey's is the grey in the UV too).  In a
   scene of few spectra the colours are tables too, the same values.  An "rgb" above
   1 is refused with parser.c's message. */
static void test_albedo_kinds(T *t)
{
    static const float col[3][3] = { { 0.2f, 0.5f, 0.9f }, { 0.8f, 0.1f, 0.1f }, { 0.1f, 0.7f, 0.3f } };
    const char *mats =
        "Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.5 0.9 ]\n"
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
        "Material \"fluorescent\" \"rgb reflectance\" [ 0.1 0.7 0.3 ] \"spectrum excitation\" "
        "[ 300 1 400 0 ] \"spectrum emission\" [ 400 1 500 0 ]\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.3 0.3 0.3 ]\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 300 0.2 830 0.6 ]\n";
    size_t cap = 160 * ALBEDO_TABLES + 1024, len;
    char *text = (char *)malloc(cap);
    RgbTable *rt = rgb_table_new();     /* as the load's (parser.h Parser.rgb) */
    Scene s;
    Error e;
    int i, k, many, kept = 1, same = 1;
    CHECK(t, text && rt, "out of memory");
    for (many = 1; many >= 0; many--) {
        int base;
        strcpy(text, "WorldBegin\n");
        for (i = 0; many && i < ALBEDO_TABLES; i++) {
            len = strlen(text);
            snprintf(text + len, cap - len, "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" "
                     "[ %d 1 2 ]\nShape \"sphere\" \"float radius\" 0.01\nAttributeEnd\n", i + 3);
        }
        len = strlen(text);
        snprintf(text + len, cap - len, "%s", mats);
        if (!load(&s, text, &e)) break;
        base = s.n_materials - 5;
        for (k = 0; k < 3; k++) {
            Spectrum tab;
            const Albedo *a = &s.materials[base + k].reflectance;
            kept &= (many ? a->rgb && !a->tab : !a->rgb && a->tab) &&
                    spec_from_rgb_t(rt, &tab, col[k], 0, &e, "t", 1);
            for (i = 0; i <= 5400 && kept; i++)
                same &= albedo_eval(a, 295.0f + 0.1f * (float)i) == spec_eval(&tab, 295.0f + 0.1f * (float)i);
        }
        kept &= !s.materials[base + 3].reflectance.rgb && !s.materials[base + 4].reflectance.rgb;
        same &= albedo_eval(&s.materials[base + 3].reflectance, 330.0f) == 0.3f &&
                albedo_eval(&s.materials[base + 3].reflectance, 600.5f) == 0.3f &&
                fabsf(albedo_eval(&s.materials[base + 4].reflectance, 565.0f) - 0.4f) < 1e-6f;
        scene_free(&s);
    }
    free(text);
    rgb_table_free(rt);
    CHECK(t, many < 0, "%s", e.msg);
    CHECK(t, kept, "colours not kept as sigmoids among many spectra, or not as tables among few; "
          "greys or spectra not as tables");
    CHECK(t, same, "a reflectance differs from its table");
    expect_reject(t, "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 1.2 0.5 0.5 ]\n", 2,
                  "\"rgb reflectance\": a reflectance must be within [0,1]", NULL);
}

static void test_shared_eta(T *t)
{
    /* the records: 1 (0, 9), 1.5 (1, 2, 6), BK7 (3, 4), Cu (5), 1.33 (7, 8) */
    static const int group[10] = { 0, 1, 1, 2, 2, 3, 1, 4, 4, 0 };
    char buf[2048];
    Scene s, one;
    Material r;
    Error e;
    int i, j, same = 1, alone = 1;
    strcpy(buf, "WorldBegin\n");
    for (i = 0; i < 10; i++)
        snprintf(buf + strlen(buf), sizeof buf - strlen(buf), "Material %s\n", ETA_MATS[i]);
    CHECK(t, load(&s, buf, &e), "%s", e.msg);
    if (t->failed) return;
    /* and two records more: the reflectance 0.5 of materials 0 and 6, shared, and
       the colour of material 9 (few spectra: a table, parser.h rgb_albedo_param) */
    CHECK(t, s.n_materials == 10 && s.spectra.n == 7, "10 materials of 5 distinct etas: %d "
          "materials, %d spectrum records", s.n_materials, s.spectra.n);
    CHECK(t, s.materials[0].reflectance.tab && s.materials[0].reflectance.tab == s.materials[6].reflectance.tab &&
          !s.materials[9].reflectance.rgb && s.materials[9].reflectance.tab,
          "the reflectances 0.5 do not share a record, or a colour among few spectra has no table");
    for (i = 0; i < 10; i++)
        for (j = 0; j < 10; j++)
            same &= (s.materials[i].eta == s.materials[j].eta) == (group[i] == group[j]);
    CHECK(t, same, "materials share an eta record if and only if their etas are equal");
    for (i = 0; i < 10 && alone; i++) {
        snprintf(buf, sizeof buf, "WorldBegin\nMaterial %s\n", ETA_MATS[i]);
        if (!load(&one, buf, &e)) { alone = 0; break; }
        alone = memcmp(s.materials[i].eta, one.materials[0].eta, sizeof(Spectrum)) == 0;
        scene_free(&one);
    }
    CHECK(t, alone, "material %d's eta is not the one it has alone", i);
    CHECK(t, spec_eval(s.materials[1].eta, 500.0f) == 1.5f &&
          spec_eval(s.materials[7].eta, 500.0f) == 1.33f && spec_eval(s.materials[0].eta, 500.0f) == 1.0f,
          "eta values");
    CHECK(t, mat_regularized(&s.materials[1], &r) && r.eta == s.materials[1].eta,
          "mat_regularized's copy does not point at the material's eta");
    scene_free(&s);
}

/* pbrt-v4 normalises "rgb L" by D65, not by L: doubling the RGB doubles Le. */
static void test_rgb_light(T *t)
{
    Scene s;
    Error e;
    double y1, y2;
    CHECK(t, load(&s, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"float scale\" 3\n"
                  "Shape \"sphere\"\n", &e), "%s", e.msg);
    y1 = y_emitter(&s, 0);
    scene_free(&s);
    CHECK(t, load(&s, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ] \"float scale\" 3\n"
                  "Shape \"sphere\"\n", &e), "%s", e.msg);
    y2 = y_emitter(&s, 0);
    scene_free(&s);
    CHECK(t, near(y2 / y1, 2.0, 2e-3), "rgb (2,2,2) must emit twice rgb (1,1,1): ratio %g", y2 / y1);
    CHECK(t, near(y1, 3.0, 3.0 * 0.03), "rgb (1,1,1) is D65-white: Y = scale = 3 within 3%%, got %g", y1);
    /* normalised by D65, not by L: a colour's luminance is its rgb's, the Y row of
       sRGB (0.2126, 0.7152, 0.0722), relative to white's (measured 0.94127 against 0.9412) */
    CHECK(t, load(&s, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1.6 0.8 0.4 ] \"float scale\" 3\n"
                  "Shape \"sphere\"\n", &e), "%s", e.msg);
    y2 = y_emitter(&s, 0);
    scene_free(&s);
    CHECK(t, near(y2 / y1, 0.2126 * 1.6 + 0.7152 * 0.8 + 0.0722 * 0.4, 2e-3),
          "rgb (1.6, 0.8, 0.4) emits Y %g of white's, not its rgb's luminance 0.9412", y2 / y1);
}

/* bilinearmesh p00 p10 p01 p11 -> (p00,p10,p11), (p00,p11,p01), same side as
   dp/du x dp/dv = (p10 - p00) x (p01 - p00). */
static void test_bilinear(T *t)
{
    Scene s;
    Error e;
    Vec3 n0, n1;
    CHECK(t, load(&s, "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" "
                  "[ 0 0 0  1 0 0  0 1 0  1 1 0 ]\n", &e), "%s", e.msg);
    CHECK(t, s.n_tris == 2 && s.shapes[0].tri_count == 2, "a patch is two triangles");
    CHECK(t, near(s.shapes[0].area, 1.0, 1e-6), "unit patch area %g", s.shapes[0].area);
    CHECK(t, s.tris[0].v[0] == 0 && s.tris[0].v[1] == 1 && s.tris[0].v[2] == 3 &&
          s.tris[1].v[0] == 0 && s.tris[1].v[1] == 3 && s.tris[1].v[2] == 2, "triangle order");
    n0 = oriented_normal(&s, 0);
    n1 = oriented_normal(&s, 1);
    CHECK(t, near(n0.z, 1, 1e-6) && near(n1.z, 1, 1e-6), "both triangles face +z like du x dv");
    scene_free(&s);
}

static void test_normals(T *t)
{
    Scene s;
    Error e;
    const char *text =
        "WorldBegin\nScale 1 2 1\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "  \"normal N\" [ 1 1 0  1 1 0  1 1 0 ] \"point2 uv\" [ 0 0 1 0 0 1 ]\n"
        "ReverseOrientation\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"
        "  \"normal N\" [ 0 0 1  0 0 1  0 0 1 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n";
    float r = 1.0f / sqrtf(1.25f);
    CHECK(t, load(&s, text, &e), "%s", e.msg);
    CHECK(t, s.N != NULL && s.shapes[0].has_normals && s.shapes[1].has_normals &&
          !s.shapes[2].has_normals, "normals flags");
    CHECK(t, vnear(s.N[0], v3(r, 0.5f * r, 0), 1e-6f), "N by the inverse transpose, normalised: "
          "(%g %g %g)", s.N[0].x, s.N[0].y, s.N[0].z);
    CHECK(t, vnear(s.N[3], v3(0, 0, -1), 1e-6f), "ReverseOrientation negates N (pbrt-v4)");
    scene_free(&s);
}

static void test_sphere_transform(T *t)
{
    Scene s;
    Error e;
    CHECK(t, load(&s, "WorldBegin\nTranslate 1 2 3\nRotate 30 1 1 0\nScale -2 -2 -2\n"
                  "Shape \"sphere\" \"float radius\" 0.5\n", &e), "%s", e.msg);
    CHECK(t, vnear(s.shapes[0].center, v3(1, 2, 3), 1e-6f), "sphere centre = CTM(origin)");
    CHECK(t, near(s.shapes[0].radius, 1.0, 1e-6), "radius scaled by |s|: %g", s.shapes[0].radius);
    CHECK(t, near(s.shapes[0].area, 4 * SPECNEE_PI, 1e-4), "area of the world sphere");
    CHECK(t, s.sphere_shape[0] == 0 && s.shapes[0].flip, "a mirroring scale sets flip");
    CHECK(t, vnear(s.bmin, v3(0, 1, 2), 1e-5f) && vnear(s.bmax, v3(2, 3, 4), 1e-5f), "bounds");
    scene_free(&s);
}

static void test_include(T *t)
{
    Scene s;
    Error e;
    char text[256];
    const char *part = test_write_file(t, "scene_inc_part.pbrt",
        "# an included file\nNamedMaterial \"m\"\nShape \"sphere\" \"float radius\" 2\n");
    const char *main_path;
    (void)part;
    snprintf(text, sizeof text, "WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"dielectric\"\n"
             "Include \"scene_inc_part.pbrt\"\nShape \"sphere\"\n");
    main_path = test_write_file(t, "scene_inc_main.pbrt", text);
    CHECK(t, scene_load(&s, main_path, &e), "%s", e.msg);
    CHECK(t, s.n_shapes == 2 && s.shapes[0].radius == 2.0f, "the included sphere comes first");
    CHECK(t, strstr(s.shapes[0].file, "scene_inc_part.pbrt") && s.shapes[0].line == 3,
          "shape location %s:%d", s.shapes[0].file, s.shapes[0].line);
    CHECK(t, s.materials[s.shapes[1].material].type == MAT_DIELECTRIC,
          "Include shares the graphics state (pbrt-v4)");
    scene_free(&s);
    /* an error inside the included file names that file and its line */
    test_write_file(t, "scene_inc_bad.pbrt", "# line 1\n\nShape \"sphere\" \"float radius\" -1\n");
    main_path = test_write_file(t, "scene_inc_main2.pbrt",
                                "WorldBegin\nInclude \"scene_inc_bad.pbrt\"\n");
    CHECK(t, !scene_load(&s, main_path, &e), "negative radius accepted");
    CHECK(t, strstr(e.msg, "scene_inc_bad.pbrt:3:") && strstr(e.msg, "radius"),
          "error must name the included file and line: %s", e.msg);
    scene_free(&s);
}

static void test_include_missing(T *t)
{
    Scene s;
    Error e;
    const char *p = test_write_file(t, "scene_inc_missing.pbrt",
                                    "WorldBegin\n\nInclude \"no-such-file.pbrt\"\n");
    CHECK(t, !scene_load(&s, p, &e), "missing include accepted");
    CHECK(t, strstr(e.msg, "scene_inc_missing.pbrt:3:") && strstr(e.msg, "no-such-file.pbrt"),
          "message must name the including file, its line and the missing file: %s", e.msg);
}

static void test_include_cycle(T *t)
{
    Scene s;
    Error e;
    const char *p = test_write_file(t, "scene_inc_cycle.pbrt",
                                    "WorldBegin\nInclude \"scene_inc_cycle.pbrt\"\n");
    CHECK(t, !scene_load(&s, p, &e), "include cycle accepted");
    CHECK(t, strstr(e.msg, "scene_inc_cycle.pbrt:") && strstr(e.msg, "cycle"), "%s", e.msg);
}

static void test_plymesh(T *t)
{
    static const float P[12] = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
    static const int32_t idx[6] = { 0, 1, 2, 0, 2, 3 };
    Scene s;
    Error e;
    const char *main_path;
    CHECK(t, ply_write_binary(test_path(t, "scene_quad.ply"), P, 4, idx, 2), "cannot write ply");
    main_path = test_write_file(t, "scene_ply.pbrt", "WorldBegin\nTranslate 0 0 2\n"
                                "Shape \"plymesh\" \"string filename\" \"scene_quad.ply\"\n");
    CHECK(t, scene_load(&s, main_path, &e), "%s", e.msg);
    CHECK(t, s.n_tris == 2 && s.n_verts == 4 && near(s.shapes[0].area, 1.0, 1e-6), "ply quad");
    CHECK(t, near(s.P[2].z, 2, 0), "ply vertices are transformed");
    scene_free(&s);
    main_path = test_write_file(t, "scene_ply2.pbrt", "WorldBegin\n"
                                "Shape \"plymesh\" \"string filename\" \"scene_nope.ply\"\n");
    CHECK(t, !scene_load(&s, main_path, &e), "missing ply accepted");
    CHECK(t, strstr(e.msg, "scene_ply2.pbrt:2:") && strstr(e.msg, "plymesh"), "%s", e.msg);
}

static void test_spectrum_file(T *t)
{
    Scene s;
    Error e;
    const char *main_path;
    test_write_file(t, "scene_refl.spd", "# a flat reflectance\n300 0.3\n900 0.3\n");
    main_path = test_write_file(t, "scene_spd.pbrt", "WorldBegin\n"
        "Material \"diffuse\" \"spectrum reflectance\" \"scene_refl.spd\"\nShape \"sphere\"\n");
    CHECK(t, scene_load(&s, main_path, &e), "%s", e.msg);
    CHECK(t, near(albedo_eval(&s.materials[0].reflectance, 555), 0.3, 1e-6),
          "spectrum file next to the scene");
    scene_free(&s);
}

static void test_insets(T *t)
{
    Scene s;
    Error e;
    CHECK(t, load(&s, "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 50\n"
                  "# inset glass 10 20 30 40\n#inset-not-structured\n# inset B 0 0 100 50\n"
                  "WorldBegin\n", &e), "%s", e.msg);
    CHECK(t, s.n_insets == 2 && strcmp(s.inset_name[0], "glass") == 0 &&
          s.inset[0][0] == 10 && s.inset[0][1] == 20 && s.inset[0][2] == 30 && s.inset[0][3] == 40 &&
          strcmp(s.inset_name[1], "B") == 0, "insets parsed");
    scene_free(&s);
}

static void test_params_pbrt_rules(T *t)
{
    Scene s;
    Error e;
    /* the last of two equal parameters wins (pbrt-v4); bare booleans; hex floats */
    CHECK(t, load(&s, "Camera \"perspective\" \"float fov\" 30 \"float fov\" [ 60 ]\n"
                  "Film \"rgb\" \"bool savefp16\" true \"string filename\" \"x.pfm\"\n"
                  "WorldBegin\n", &e), "%s", e.msg);
    CHECK(t, s.settings.fov_deg == 60.0f, "the last fov must win, got %g", s.settings.fov_deg);
    scene_free(&s);
    /* escapes in strings and comments after values */
    CHECK(t, load(&s, "Film \"rgb\" \"string filename\" \"a\\\\b.pfm\" # comment\nWorldBegin\n",
                  &e), "%s", e.msg);
    CHECK(t, strcmp(s.settings.filename, "a\\b.pfm") == 0, "escaped backslash: %s", s.settings.filename);
    scene_free(&s);
}

static void test_dump(T *t)
{
    Scene s;
    Error e;
    FILE *f;
    char buf[8192];
    size_t n;
    CHECK(t, load(&s, "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 16\n"
                  "WorldBegin\nAreaLightSource \"diffuse\" \"float scale\" 5\n"
                  "Shape \"sphere\"\n", &e), "%s", e.msg);
    f = fopen(test_path(t, "scene_dump.txt"), "w+");
    CHECK(t, f != NULL, "cannot open scratch file");
    scene_dump(&s, f);
    rewind(f);
    n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    scene_free(&s);
    CHECK(t, strstr(buf, "film: 32 x 16") && strstr(buf, "emitters: 1") &&
          strstr(buf, "sphere") && strstr(buf, "bounds:"), "dump lacks sections:\n%s", buf);
    CHECK(t, strstr(buf, "Y(Le) 5"), "dump must show the emitter's Y = scale 5:\n%s", buf);
}

/* The default scene parses and means what its comments say. */
static void test_cornell(T *t)
{
    Scene s;
    Error e;
    double Y;
    int i, red = -1;
    Vec3 c;
    CHECK(t, scene_load(&s, "scenes/cornell.pbrt", &e), "%s", e.msg);
    CHECK(t, s.settings.xres == 256 && s.settings.yres == 256 && s.settings.spp == 64 &&
          s.settings.maxdepth == 8 && strcmp(s.settings.filename, "cornell.pfm") == 0 &&
          s.settings.fov_deg == 39.3f, "cornell settings");
    CHECK(t, s.n_emitters == 1 && s.n_shapes == 8, "one light and 7 other shapes, got %d/%d",
          s.n_emitters, s.n_shapes);
    Y = y_emitter(&s, 0);
    CHECK(t, Y >= 10 && Y <= 20, "light Y %g should be 10-20", Y);
    CHECK(t, oriented_normal(&s, s.shapes[s.emitters[0].shape].tri_begin).y < -0.99f,
          "the light must face down");
    for (i = 0; i < s.n_shapes; i++) {
        const Material *m = &s.materials[s.shapes[i].material];
        if (m->type == MAT_DIFFUSE && albedo_eval(&m->reflectance, 650) > 0.5f &&
            albedo_eval(&m->reflectance, 450) < 0.1f) red = i;
    }
    CHECK(t, red >= 0, "no red wall found");
    c = xf_point(&s.settings.camera_from_world, s.P[s.tris[s.shapes[red].tri_begin].v[0]]);
    CHECK(t, c.x < 0, "the red wall must be on the left of the image (camera x %g)", c.x);
    CHECK(t, near(s.bmax.y, 548.8, 1e-3) && near(s.bmin.y, 0, 0), "bounds y %g..%g", s.bmin.y, s.bmax.y);
    scene_free(&s);
}

/* ------------------------------------------------------------------------
   Rejections: one test each, checking "t.pbrt:LINE:" and the key words
   ------------------------------------------------------------------------ */
#define REJECT(fn, text, line, k1, k2) static void fn(T *t) { expect_reject(t, text, line, k1, k2); }

REJECT(rej_unterminated_string, "WorldBegin\n\nShape \"sphere\n", 3, "unterminated string", NULL)
REJECT(rej_unterminated_bracket, "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0\n 1 0 0\n",
       2, "unterminated", "[")
REJECT(rej_nested_bracket, "WorldBegin\nShape \"sphere\" \"float radius\" [ 1 [ 2 ] ]\n", 2, "'['", NULL)
REJECT(rej_stray_bracket, "WorldBegin\n]\n", 2, "expected a directive", "']'")
REJECT(rej_non_numeric, "Translate 1 x 3\nWorldBegin\n", 1, "Translate", "not a finite number")
REJECT(rej_nan, "Camera \"perspective\" \"float fov\" nan\nWorldBegin\n", 1, "nan", "not a finite number")
REJECT(rej_inf, "WorldBegin\nTranslate 1e999 0 0\n", 2, "1e999", "not a finite number")
REJECT(rej_unknown_directive, "WorldBegin\nFrobnicate 3\n", 2, "Unknown directive", "Frobnicate")
REJECT(rej_world_end, "WorldBegin\nWorldEnd\n", 2, "WorldEnd is pbrt-v3 syntax", NULL)
REJECT(rej_unknown_param_type, "Camera \"perspective\" \"real fov\" 30\nWorldBegin\n", 1,
       "unknown parameter type", "real")
REJECT(rej_v3_param_type, "WorldBegin\nShape \"trianglemesh\" \"point P\" [ 0 0 0 1 0 0 0 1 0 ]\n",
       2, "pbrt-v3", "point")
REJECT(rej_unused_param, "WorldBegin\nShape \"sphere\" \"float foo\" 3\n", 2, "\"float foo\"",
       "unused parameter")
REJECT(rej_wrong_type, "Film \"rgb\" \"float xresolution\" 100\nWorldBegin\n", 1,
       "\"float xresolution\"", "wrong type")
REJECT(rej_int_not_integer, "Film \"rgb\" \"integer xresolution\" 1.5\nWorldBegin\n", 1,
       "not an integer", NULL)
REJECT(rej_quoted_bool, "WorldBegin\nAreaLightSource \"diffuse\" \"bool twosided\" \"true\"\n", 2,
       "twosided", "without quotes")
REJECT(rej_resolution_zero, "Film \"rgb\" \"integer xresolution\" 0\nWorldBegin\n", 1, "resolution", NULL)
REJECT(rej_resolution_negative, "Film \"rgb\" \"integer yresolution\" -4\nWorldBegin\n", 1, "resolution", NULL)
REJECT(rej_resolution_huge, "Film \"rgb\" \"integer xresolution\" 100000\nWorldBegin\n", 1, "resolution", NULL)
REJECT(rej_film_extension, "Film \"rgb\" \"string filename\" \"x.jpg\"\nWorldBegin\n", 1, "x.jpg", ".pfm")
/* pbrt-v4's stratified sampler reads xsamples/ysamples, never pixelsamples (its
   samplers.cpp; --spp only): a leftover there too, not "valid pbrt-v4" */
REJECT(rej_stratified_pixelsamples, "Sampler \"stratified\"\n  \"integer pixelsamples\" 8\nWorldBegin\n", 2,
       "\"integer pixelsamples\": unused parameter (Sampler \"stratified\" reads: integer xsamples", NULL)
REJECT(rej_pmj02bn_randomization, "Sampler \"pmj02bn\" \"string randomization\" \"owen\"\nWorldBegin\n", 1,
       "\"string randomization\": unused parameter (Sampler \"pmj02bn\"", NULL)
/* two problems in one statement: the first in the file is named, at its own line */
REJECT(rej_first_problem_refused, "Integrator \"bdpt\"\n \"bool regularize\" true\n \"bool foo\" true\nWorldBegin\n", 2,
       "\"bool regularize\" true is valid pbrt-v4", NULL)
REJECT(rej_first_problem_unused, "Integrator \"bdpt\"\n \"bool foo\" true\n \"bool regularize\" true\nWorldBegin\n", 2,
       "\"bool foo\": unused parameter", NULL)
REJECT(rej_spp_zero, "Sampler \"independent\" \"integer pixelsamples\" 0\nWorldBegin\n", 1,
       "samples per pixel", NULL)
REJECT(rej_spp_negative, "Sampler \"sobol\" \"integer pixelsamples\" -16\nWorldBegin\n", 1,
       "samples per pixel", NULL)
REJECT(rej_fov_zero, "Camera \"perspective\" \"float fov\" 0\nWorldBegin\n", 1, "fov", NULL)
REJECT(rej_fov_180, "Camera \"perspective\" \"float fov\" 180\nWorldBegin\n", 1, "fov", NULL)
/* pbrt-v4's options that leave the image as it is load, with a note. */
static void option_ignored(T *t)
{
    static const char *const opt[] = {
        "\"string msereferenceimage\" \"ref.exr\"", "\"string msereferenceout\" \"mse.txt\"",
        "\"string rendercoordsys\" \"world\"", "\"bool pixelstats\" true", "\"bool wavefront\" true"
    };
    int i;
    for (i = 0; i < 5 && !t->failed; i++) {
        char text[256];
        Scene s;
        snprintf(text, sizeof text, "Option %s\nWorldBegin\nLightSource \"infinite\"\n", opt[i]);
        if (test_load_scene(t, &s, text)) scene_free(&s);
    }
}

REJECT(rej_option_refused, "Option \"bool forcediffuse\" true\nWorldBegin\n", 1,
       "Option \"forcediffuse\" is valid pbrt-v4 but not in the specnee subset", NULL)
REJECT(rej_option_unknown, "WorldBegin\nOption \"bool bogus\" true\n", 2, "Option \"bogus\": unknown option", NULL)
REJECT(rej_option_two, "Option \"bool pixelstats\" true \"bool wavefront\" true\nWorldBegin\n", 1,
       "Option: expected one \"type name\" value pair, found 2", NULL)
REJECT(rej_camera_type, "Camera \"fisheye\"\nWorldBegin\n", 1, "unknown camera type", "fisheye")
REJECT(rej_integrator_type, "Integrator \"mlt\"\nWorldBegin\n", 1,
       "valid pbrt-v4 but not in the specnee subset", "mlt")
REJECT(rej_regularize, "Integrator \"bdpt\" \"bool regularize\" true\nWorldBegin\n", 1, "regularize", NULL)
REJECT(rej_negative_radius, "WorldBegin\nShape \"sphere\" \"float radius\" -2\n", 2, "radius", NULL)
REJECT(rej_sphere_zmin, "WorldBegin\nShape \"sphere\" \"float zmin\" 0.5 \"float zmax\" 0.5\n", 2,
       "zmin = zmax = 0.5", "no height")
REJECT(rej_shape_curve, "WorldBegin\nShape \"curve\"\n", 2,
       "Shape \"curve\": \"point3 P\" is required", NULL)
REJECT(rej_shape_unknown, "WorldBegin\nShape \"blob\"\n", 2, "unknown shape type", NULL)
REJECT(rej_material_conductor, "WorldBegin\nMaterial \"subsurface\" \"string name\" \"Blood\"\n", 2,
       "subsurface", "no such named medium")
REJECT(rej_unknown_named_spectrum, "WorldBegin\nMaterial \"dielectric\" \"spectrum eta\" \"glass-XYZ\"\n",
       2, "unknown named spectrum", "glass-XYZ")
REJECT(rej_odd_spectrum, "WorldBegin\nAreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 500 ]\n", 2,
       "odd number", NULL)
REJECT(rej_rgb_reflectance_above_one, "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.5 2 0.5 ]\n",
       2, "reflectance", "[0,1]")
REJECT(rej_texture_param, "WorldBegin\nMaterial \"dielectric\" \"texture roughness\" \"checks\"\n", 2,
       "\"texture roughness\"", "no texture named \"checks\"")
REJECT(rej_cauchy_half, "WorldBegin\nMaterial \"dielectric\" \"float cauchyA\" 1.5\n", 2, "cauchyB", NULL)
/* pbrt-v4 resolves names when the scene is built: an unknown name is an error only for a shape that uses it, at its NamedMaterial */
REJECT(rej_named_material_unknown, "WorldBegin\nNamedMaterial \"nope\"\nShape \"sphere\"\n", 2, "no MakeNamedMaterial defines it", "nope")
REJECT(rej_named_material_twice, "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
       "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n", 3, "redefined", NULL)
REJECT(rej_attribute_end_unmatched, "WorldBegin\nAttributeBegin\nAttributeEnd\nAttributeEnd\n", 4,
       "unmatched AttributeEnd", NULL)
REJECT(rej_attribute_begin_open, "WorldBegin\nAttributeBegin\nShape \"sphere\"\n", 2,
       "AttributeBegin without a matching AttributeEnd", NULL)
REJECT(rej_shape_before_world, "Shape \"sphere\"\nWorldBegin\n", 1, "Shape", "before WorldBegin")
REJECT(rej_camera_in_world, "WorldBegin\nCamera \"perspective\"\n", 2, "Camera", "after WorldBegin")
REJECT(rej_truncated_lookat, "LookAt 0 0 0  0 0 1\n", 1, "LookAt", "end of file")
REJECT(rej_degenerate_lookat, "LookAt 0 0 0  0 1 0  0 1 0\nWorldBegin\n", 1, "LookAt", "degenerate")
REJECT(rej_scale_zero, "WorldBegin\nScale 1 0 1\n", 2, "Scale", "singular")
REJECT(rej_transform_count, "WorldBegin\nTransform [ 1 0 0 0 1 0 0 0 1 ]\n", 2, "Transform", "16")
REJECT(rej_indices_range, "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 3 ]\n"
       "  \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n", 2, "out of range", NULL)
REJECT(rej_indices_multiple, "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 ]\n"
       "  \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n", 2, "multiple of 3", NULL)
REJECT(rej_indices_missing, "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 0 ]\n",
       2, "indices", "required")
REJECT(rej_attribute_directive, "WorldBegin\nAttribute \"shapes\" \"float radius\" 2\n", 2,
       "Unknown attribute target \"shapes\"", NULL)
REJECT(rej_import_before_world, "Import \"x.pbrt\"\nWorldBegin\n", 1, "Import", "WorldBegin")
REJECT(rej_no_world, "Film \"rgb\"\n", 1, "WorldBegin", NULL)
REJECT(rej_inset_outside, "Film \"rgb\" \"integer xresolution\" 10 \"integer yresolution\" 10\n"
       "# inset A 0 0 20 5\nWorldBegin\n", 2, "inset A", "outside")
REJECT(rej_inset_malformed, "# inset A 1 2 3\nWorldBegin\n", 1, "inset", NULL)

/* Names as long as a file writes them (exporters write ~90-character texture
   names): textures, named materials (one used before its definition), a medium,
   an object and a coordinate system of 300 characters, in pairs that differ only
   in the last one, each found by its whole name; and an Include whose path is
   longer than 1024 characters. */
static void test_long_names(T *t)
{
    static char L[301], text[8192], dir[2048], path[2400], cmd[2600];
    static const char *const fmt =
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
        "Camera \"perspective\"\nWorldBegin\n"
        "AttributeBegin\nTranslate 0 0 7\nCoordinateSystem \"%sc\"\nAttributeEnd\n"
        "CoordinateSystem \"%sd\"\n"
        "Texture \"%sa\" \"spectrum\" \"constant\" \"rgb value\" [ 0.2 0.2 0.2 ]\n"
        "Texture \"%sb\" \"spectrum\" \"constant\" \"rgb value\" [ 0.7 0.7 0.7 ]\n"
        "AttributeBegin\nNamedMaterial \"%sm2\"\nMediumInterface \"%sf\" \"\"\n"
        "CoordSysTransform \"%sc\"\nShape \"sphere\"\nAttributeEnd\n"
        "MakeNamedMaterial \"%sm1\" \"string type\" \"diffuse\" \"texture reflectance\" \"%sb\"\n"
        "MakeNamedMaterial \"%sm2\" \"string type\" \"diffuse\" \"texture reflectance\" \"%sa\"\n"
        "MakeNamedMedium \"%sf\" \"string type\" \"homogeneous\"\n"
        "ObjectBegin \"%so\"\nNamedMaterial \"%sm1\"\nShape \"sphere\"\nObjectEnd\n"
        "ObjectInstance \"%so\"\n";
    Scene s;
    Error e;
    FILE *f;
    int k;
    memset(L, 'n', 297);
    L[297] = '\0';
    snprintf(text, sizeof text, fmt, L, L, L, L, L, L, L, L, L, L, L, L, L, L, L);
    if (!load(&s, text, &e)) CHECK(t, 0, "%s", e.msg);
    CHECK(t, s.n_textures == 2 && s.n_media == 1 && s.n_objects == 1 && s.n_shapes == 2,
          "%d textures, %d media, %d objects, %d shapes", s.n_textures, s.n_media, s.n_objects,
          s.n_shapes);
    CHECK(t, strlen(s.media[0].name) == 298 && strlen(s.objects[0].name) == 298,
          "names kept as %d and %d characters", (int)strlen(s.media[0].name),
          (int)strlen(s.objects[0].name));
    for (k = 0; k < 2; k++) {      /* world sphere: m2 -> "...a"; the object's: m1 -> "...b" */
        const Shape *sh = &s.shapes[k];
        int want = sh->in_object ? 2 : 1;
        CHECK(t, s.materials[sh->material].reflectance_tex == want, "shape %d: texture %d, "
              "expected %d", k, s.materials[sh->material].reflectance_tex, want);
        if (!sh->in_object)
            CHECK(t, sh->medium_inside == 0 && fabs(sh->q.world_from_obj.m[2][3] - 7.0) < 1e-9,
                  "the sphere's medium %d, z %g", sh->medium_inside, sh->q.world_from_obj.m[2][3]);
    }
    scene_free(&s);
    /* an Include 5 directories of 230 characters deep */
    snprintf(dir, sizeof dir, "%s/longpath", t->tmpdir);
    for (k = 0; k < 5; k++) {
        size_t n = strlen(dir);
        dir[n] = '/';
        memset(dir + n + 1, 'd', 230);
        dir[n + 231] = '\0';
    }
    snprintf(cmd, sizeof cmd, "mkdir -p %s", dir);
    CHECK(t, system(cmd) == 0, "mkdir");
    snprintf(path, sizeof path, "%s/inc.pbrt", dir);
    CHECK(t, (f = fopen(path, "w")) != NULL, "cannot write %s", path);
    fputs("Shape \"sphere\"\n", f);
    fclose(f);
    snprintf(text, sizeof text, "WorldBegin\nInclude \"%s/inc.pbrt\"\n",
             dir + strlen(t->tmpdir) + strlen("/longpath/"));
    snprintf(path, sizeof path, "%s/longpath/main.pbrt", t->tmpdir);
    CHECK(t, (f = fopen(path, "w")) != NULL, "cannot write %s", path);
    fputs(text, f);
    fclose(f);
    CHECK(t, strlen(dir) > 1024, "path of %d characters", (int)strlen(dir));
    if (!scene_load(&s, path, &e)) CHECK(t, 0, "%.200s", e.msg);
    CHECK(t, s.n_shapes == 1, "%d shapes", s.n_shapes);
    scene_free(&s);
    {   /* beyond NAME_CAP: one line naming the length */
        static char big[5200];
        snprintf(big, sizeof big, "WorldBegin\nMakeNamedMaterial \"%0*d\" \"string type\" \"diffuse\"\n",
                 5000, 7);
        expect_reject(t, big, 2, "a name of 5000 characters (at most 4095)", NULL);
    }
}

const TestCase tests_scene[] = {
    {"scene_shared_spectra", test_shared_spectra},
    {"scene_shared_eta", test_shared_eta},
    {"scene_albedo_kinds", test_albedo_kinds},
    {"scene_defaults", test_defaults},
    {"scene_options", test_options},
    {"scene_camera_frame", test_camera_frame},
    {"scene_transform_order", test_transform_order},
    {"scene_transform_matrix", test_transform_matrix},
    {"scene_coordsys", test_coordsys},
    {"scene_attribute_stack", test_attribute_stack},
    {"scene_orientation", test_orientation},
    {"scene_named_materials", test_named_materials},
    {"scene_dielectric", test_dielectric},
    {"scene_emitters", test_emitters},
    {"scene_rgb_light", test_rgb_light},
    {"scene_bilinear", test_bilinear},
    {"scene_normals", test_normals},
    {"scene_sphere_transform", test_sphere_transform},
    {"scene_include", test_include},
    {"scene_long_names", test_long_names},
    {"scene_include_missing", test_include_missing},
    {"scene_include_cycle", test_include_cycle},
    {"scene_plymesh", test_plymesh},
    {"scene_spectrum_file", test_spectrum_file},
    {"scene_insets", test_insets},
    {"scene_params_pbrt_rules", test_params_pbrt_rules},
    {"scene_dump", test_dump},
    {"scene_cornell", test_cornell},
    {"scene_reject_unterminated_string", rej_unterminated_string},
    {"scene_reject_unterminated_bracket", rej_unterminated_bracket},
    {"scene_reject_nested_bracket", rej_nested_bracket},
    {"scene_reject_stray_bracket", rej_stray_bracket},
    {"scene_reject_non_numeric", rej_non_numeric},
    {"scene_reject_nan", rej_nan},
    {"scene_reject_inf", rej_inf},
    {"scene_reject_unknown_directive", rej_unknown_directive},
    {"scene_reject_world_end", rej_world_end},
    {"scene_reject_unknown_param_type", rej_unknown_param_type},
    {"scene_reject_v3_param_type", rej_v3_param_type},
    {"scene_reject_unused_param", rej_unused_param},
    {"scene_reject_wrong_type", rej_wrong_type},
    {"scene_reject_int_not_integer", rej_int_not_integer},
    {"scene_reject_quoted_bool", rej_quoted_bool},
    {"scene_reject_resolution_zero", rej_resolution_zero},
    {"scene_reject_resolution_negative", rej_resolution_negative},
    {"scene_reject_resolution_huge", rej_resolution_huge},
    {"scene_reject_film_extension", rej_film_extension},
    {"scene_reject_spp_zero", rej_spp_zero},
    {"scene_reject_stratified_pixelsamples", rej_stratified_pixelsamples},
    {"scene_reject_pmj02bn_randomization", rej_pmj02bn_randomization},
    {"scene_reject_first_problem_refused", rej_first_problem_refused},
    {"scene_reject_first_problem_unused", rej_first_problem_unused},
    {"scene_reject_spp_negative", rej_spp_negative},
    {"scene_reject_fov_zero", rej_fov_zero},
    {"scene_reject_fov_180", rej_fov_180},
    {"scene_option_ignored", option_ignored},
    {"scene_reject_option_refused", rej_option_refused},
    {"scene_reject_option_unknown", rej_option_unknown},
    {"scene_reject_option_two", rej_option_two},
    {"scene_reject_camera_type", rej_camera_type},
    {"scene_reject_integrator_type", rej_integrator_type},
    {"scene_reject_regularize", rej_regularize},
    {"scene_reject_negative_radius", rej_negative_radius},
    {"scene_reject_sphere_zmin", rej_sphere_zmin},
    {"scene_reject_shape_curve", rej_shape_curve},
    {"scene_reject_shape_unknown", rej_shape_unknown},
    {"scene_reject_material_conductor", rej_material_conductor},
    {"scene_reject_unknown_named_spectrum", rej_unknown_named_spectrum},
    {"scene_reject_odd_spectrum", rej_odd_spectrum},
    {"scene_reject_rgb_reflectance_above_one", rej_rgb_reflectance_above_one},
    {"scene_reject_texture_param", rej_texture_param},
    {"scene_reject_cauchy_half", rej_cauchy_half},
    {"scene_reject_named_material_unknown", rej_named_material_unknown},
    {"scene_reject_named_material_twice", rej_named_material_twice},
    {"scene_reject_attribute_end_unmatched", rej_attribute_end_unmatched},
    {"scene_reject_attribute_begin_open", rej_attribute_begin_open},
    {"scene_reject_shape_before_world", rej_shape_before_world},
    {"scene_reject_camera_in_world", rej_camera_in_world},
    {"scene_reject_truncated_lookat", rej_truncated_lookat},
    {"scene_reject_degenerate_lookat", rej_degenerate_lookat},
    {"scene_reject_scale_zero", rej_scale_zero},
    {"scene_reject_transform_count", rej_transform_count},
    {"scene_reject_indices_range", rej_indices_range},
    {"scene_reject_indices_multiple", rej_indices_multiple},
    {"scene_reject_indices_missing", rej_indices_missing},
    {"scene_reject_attribute_directive", rej_attribute_directive},
    {"scene_reject_import_before_world", rej_import_before_world},
    {"scene_reject_no_world", rej_no_world},
    {"scene_reject_inset_outside", rej_inset_outside},
    {"scene_reject_inset_malformed", rej_inset_malformed},
    {NULL, NULL}
};
