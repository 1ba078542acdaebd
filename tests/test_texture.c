/* tests/test_texture.c - textures (texture.c): values at chosen points against
   pbrt-v4's definitions, the (u, v) of meshes, image lookups, a rendered plane
   against E/pi times its texture, and bad input.  Noise, dots and marble against
   numbers frozen from pbrt-v4 (its functions at chosen points, and renders);
   directionmix at chosen normals and against a pbrt-v4 render. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static const char *head =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
    "PixelFilter \"box\"\n"
    "WorldBegin\n";

/* Load head + body; the test fails (0) on a parse error. */
static int load(T *t, Scene *s, const char *body)
{
    static char text[8192];
    snprintf(text, sizeof text, "%s%s", head, body);
    return test_load_scene(t, s, text);
}

static SurfacePoint at_uv(float u, float v)
{
    SurfacePoint sp = test_flat_point();
    sp.u = u;
    sp.v = v;
    return sp;
}

static SurfacePoint at_p(float x, float y, float z)
{
    SurfacePoint sp = test_flat_point();
    sp.p = v3(x, y, z);
    return sp;
}

#define NEAR(a, b, tol) (fabs((double)(a) - (double)(b)) <= (tol))

/* Checkerboard (tex1 where floor(s) + floor(t) is even), scale, mix and the uv
   mapping's scales and offsets. */
static void test_values(T *t)
{
    Scene s;
    SurfacePoint sp;
    if (!load(t, &s,
              "Texture \"c\" \"float\" \"checkerboard\" \"float uscale\" [ 4 ] \"float vscale\" [ 2 ] "
              "\"float udelta\" [ 0.5 ] \"float tex1\" [ 0.9 ] \"float tex2\" [ 0.1 ]\n"
              "Texture \"k\" \"float\" \"constant\" \"float value\" [ 0.25 ]\n"
              "Texture \"s\" \"float\" \"scale\" \"texture tex\" \"c\" \"float scale\" [ 0.5 ]\n"
              "Texture \"m\" \"float\" \"mix\" \"texture tex1\" \"c\" \"float tex2\" [ 0.7 ] "
              "\"texture amount\" \"k\"\n"
              "Texture \"sc\" \"spectrum\" \"checkerboard\" \"spectrum tex1\" [ 400 0.2 700 0.8 ] "
              "\"rgb tex2\" [ 0.5 0.5 0.5 ]\n"))
        return;
    /* s = 4u + 0.5, t = 2v: u = 0.05 -> s = 0.7, v = 0.2 -> t = 0.4: even -> tex1 */
    sp = at_uv(0.05f, 0.2f);
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.9, 1e-6), "checkerboard at (0.7, 0.4): %g",
          tex_eval(s.textures, 0, &sp, 500));
    sp = at_uv(0.15f, 0.2f);                          /* s = 1.1: odd -> tex2 */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.1, 1e-6), "checkerboard at (1.1, 0.4)");
    sp = at_uv(0.15f, 0.6f);                          /* s = 1.1, t = 1.2: even */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.9, 1e-6), "checkerboard at (1.1, 1.2)");
    sp = at_uv(-0.2f, 0.2f);                          /* s = -0.3: floor -1, odd */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.1, 1e-6), "checkerboard at (-0.3, 0.4)");
    sp = at_uv(0.15f, 0.2f);
    CHECK(t, NEAR(tex_eval(s.textures, 2, &sp, 500), 0.05, 1e-6), "scale: %g", tex_eval(s.textures, 2, &sp, 500));
    /* mix: (1 - 0.25) 0.1 + 0.25 0.7 = 0.25 */
    CHECK(t, NEAR(tex_eval(s.textures, 3, &sp, 500), 0.75 * 0.1 + 0.25 * 0.7, 1e-6), "mix: %g",
          tex_eval(s.textures, 3, &sp, 500));
    /* a spectrum checkerboard: tex1's spectrum at 550 nm, tex2 grey */
    sp = at_uv(0.5f, 0.5f);
    CHECK(t, NEAR(tex_eval(s.textures, 4, &sp, 550), 0.5, 1e-5), "spectrum checkerboard tex1 at 550 nm: %g",
          tex_eval(s.textures, 4, &sp, 550));
    sp = at_uv(1.5f, 0.5f);
    CHECK(t, NEAR(tex_eval(s.textures, 4, &sp, 550), 0.5, 1e-5), "spectrum checkerboard tex2: %g",
          tex_eval(s.textures, 4, &sp, 550));
    sp = at_uv(0.5f, 0.5f);
    CHECK(t, NEAR(tex_eval(s.textures, 4, &sp, 450), 0.3, 1e-5), "spectrum checkerboard tex1 at 450 nm: %g",
          tex_eval(s.textures, 4, &sp, 450));
    scene_free(&s);
    /* a diffuse reflectance texture is clamped to [0, 1] (pbrt-v4's DiffuseMaterial) */
    if (!load(t, &s, "Texture \"k\" \"spectrum\" \"constant\" \"spectrum value\" [ 400 1.7 700 1.7 ]\n"
                     "Texture \"z\" \"spectrum\" \"scale\" \"texture tex\" \"k\" \"float scale\" [ -1 ]\n"
                     "Material \"diffuse\" \"texture reflectance\" \"k\"\n"
                     "Shape \"sphere\"\nMaterial \"diffuse\" \"texture reflectance\" \"z\"\nShape \"sphere\"\n"))
        return;
    sp = at_uv(0.5f, 0.5f);
    CHECK(t, mat_albedo_at(&s.materials[s.shapes[0].material], &sp, 500.0f) == 1.0f, "reflectance 1.7 not clamped to 1");
    CHECK(t, mat_albedo_at(&s.materials[s.shapes[1].material], &sp, 500.0f) == 0.0f, "reflectance -1.7 not clamped to 0");
    scene_free(&s);
}

/* The 3-D mappings in the texture's frame (the CTM at the Texture directive). */
static void test_mappings(T *t)
{
    Scene s;
    SurfacePoint sp;
    if (!load(t, &s,
              "AttributeBegin\nTranslate 10 0 0\n"
              "Texture \"pl\" \"float\" \"checkerboard\" \"string mapping\" \"planar\" "
              "\"vector3 v1\" [ 0 1 0 ] \"vector3 v2\" [ 0 0 1 ] \"float udelta\" [ 0.5 ] \"float tex1\" [ 1 ] \"float tex2\" [ 0 ]\n"
              "Texture \"sph\" \"float\" \"checkerboard\" \"string mapping\" \"spherical\" "
              "\"float tex1\" [ 1 ] \"float tex2\" [ 0 ]\n"
              "AttributeEnd\n"
              "Texture \"cyl\" \"float\" \"checkerboard\" \"string mapping\" \"cylindrical\" "
              "\"float tex1\" [ 1 ] \"float tex2\" [ 0 ]\n"))
        return;
    /* planar: q = p - (10, 0, 0); s = 0.5 + q.y, t = q.z */
    sp = at_p(10.0f, 0.2f, 0.3f);                    /* s = 0.7, t = 0.3: even */
    CHECK(t, tex_eval(s.textures, 0, &sp, 500) == 1.0f, "planar at s 0.7 t 0.3");
    sp = at_p(10.0f, 0.6f, 0.3f);                    /* s = 1.1: odd */
    CHECK(t, tex_eval(s.textures, 0, &sp, 500) == 0.0f, "planar at s 1.1 t 0.3");
    sp = at_p(-5.0f, 0.6f, 0.3f);                    /* q.x does not count */
    CHECK(t, tex_eval(s.textures, 0, &sp, 500) == 0.0f, "planar: x moved the point");
    /* spherical: s = theta / pi in [0, 1], t = phi / 2 pi in [0, 1): every point
       has floor(s) = floor(t) = 0 except the pole theta = pi (s = 1) */
    sp = at_p(11.0f, 0.0f, 0.5f);
    CHECK(t, tex_eval(s.textures, 1, &sp, 500) == 1.0f, "spherical inside the cell");
    sp = at_p(10.0f, 0.0f, -1.0f);                   /* the -z pole: s = 1 */
    CHECK(t, tex_eval(s.textures, 1, &sp, 500) == 0.0f, "spherical at the -z pole");
    /* cylindrical (world frame): s in [0, 1], t = z */
    sp = at_p(1.0f, 0.0f, 0.5f);
    CHECK(t, tex_eval(s.textures, 2, &sp, 500) == 1.0f, "cylindrical at z 0.5");
    sp = at_p(1.0f, 0.0f, 1.5f);
    CHECK(t, tex_eval(s.textures, 2, &sp, 500) == 0.0f, "cylindrical at z 1.5");
    scene_free(&s);
}

/* An image texture from a 2 x 2 PFM (values 0.1 0.3 / 0.5 0.9, row 0 at the top):
   texel centres, bilinear between them, t flipped, the wrap modes, scale, invert. */
static void test_imagemap(T *t)
{
    Image im;
    Scene s;
    SurfacePoint sp;
    char body[2048];
    const char *path = test_path(t, "tex2x2.pfm");
    static const float v[4] = { 0.1f, 0.3f, 0.5f, 0.9f };  /* (x, y): (0,0) (1,0) (0,1) (1,1) */
    int i, c;
    CHECK(t, img_alloc(&im, 2, 2), "out of memory");
    for (i = 0; i < 4; i++)
        for (c = 0; c < 3; c++) im.rgb[3 * i + c] = v[i];
    CHECK(t, pfm_write(&im, path), "cannot write %s", path);
    img_free(&im);
    snprintf(body, sizeof body,
             "Texture \"r\" \"float\" \"imagemap\" \"string filename\" \"%s\"\n"
             "Texture \"b\" \"float\" \"imagemap\" \"string filename\" \"%s\" \"string wrap\" \"black\"\n"
             "Texture \"c\" \"float\" \"imagemap\" \"string filename\" \"%s\" \"string wrap\" \"clamp\" "
             "\"float scale\" [ 2 ] \"bool invert\" true\n"
             "Texture \"g\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\"\n", path, path, path, path);
    if (!load(t, &s, body)) return;
    /* texel (x, y) has its centre at s = (x + 0.5) / 2, 1 - t = (y + 0.5) / 2 */
    sp = at_uv(0.25f, 0.75f);                         /* texel (0, 0): the top left */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.1, 1e-6), "texel (0,0): %g", tex_eval(s.textures, 0, &sp, 500));
    sp = at_uv(0.75f, 0.25f);                         /* texel (1, 1): bottom right */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.9, 1e-6), "texel (1,1): %g", tex_eval(s.textures, 0, &sp, 500));
    sp = at_uv(0.5f, 0.5f);                           /* the mean of the four */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.45, 1e-6), "centre: %g", tex_eval(s.textures, 0, &sp, 500));
    sp = at_uv(0.375f, 0.75f);                        /* a quarter of the way to texel (1, 0) */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.75 * 0.1 + 0.25 * 0.3, 1e-6), "bilinear in x: %g",
          tex_eval(s.textures, 0, &sp, 500));
    sp = at_uv(0.25f, 0.625f);                        /* a quarter of the way to texel (0, 1) */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.75 * 0.1 + 0.25 * 0.5, 1e-6), "bilinear in y: %g",
          tex_eval(s.textures, 0, &sp, 500));
    /* repeat: s = 0 lies between texel 1 (wrapped from -1) and texel 0 */
    sp = at_uv(0.0f, 0.75f);
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.5 * 0.3 + 0.5 * 0.1, 1e-6), "repeat: %g",
          tex_eval(s.textures, 0, &sp, 500));
    CHECK(t, NEAR(tex_eval(s.textures, 1, &sp, 500), 0.5 * 0.1, 1e-6), "black: %g",
          tex_eval(s.textures, 1, &sp, 500));
    /* clamp, with scale 2 and invert: 1 - 2 v, clamped at 0 */
    CHECK(t, NEAR(tex_eval(s.textures, 2, &sp, 500), 1.0 - 2.0 * 0.1, 1e-6), "clamp, scale, invert: %g",
          tex_eval(s.textures, 2, &sp, 500));
    sp = at_uv(0.75f, 0.25f);
    CHECK(t, tex_eval(s.textures, 2, &sp, 500) == 0.0f, "invert of 1.8 not clamped at 0");
    /* a grey spectrum texel is exactly flat */
    sp = at_uv(0.75f, 0.75f);
    CHECK(t, NEAR(tex_eval(s.textures, 3, &sp, 430), 0.3, 1e-6) && NEAR(tex_eval(s.textures, 3, &sp, 680), 0.3, 1e-6),
          "grey texel: %g, %g", tex_eval(s.textures, 3, &sp, 430), tex_eval(s.textures, 3, &sp, 680));
    scene_free(&s);
}

/* A PNG image texture (png.c): 8-bit values decoded from sRGB by default, read
   as they are with "encoding" "linear" (pbrt-v4). */
static void test_imagemap_png(T *t)
{
    static const unsigned char px[4 * 3] = { 128, 128, 128, 255, 255, 255, 0, 0, 0, 64, 64, 64 };
    Scene s;
    SurfacePoint sp;
    char body[1024];
    const char *path = test_path(t, "tex.png");
    double srgb128 = pow((128.0 / 255.0 + 0.055) / 1.055, 2.4);   /* IEC 61966-2-1 */
    CHECK(t, png_write_rgb8(path, 2, 2, px), "cannot write %s", path);
    snprintf(body, sizeof body,
             "Texture \"a\" \"float\" \"imagemap\" \"string filename\" \"%s\"\n"
             "Texture \"b\" \"float\" \"imagemap\" \"string filename\" \"%s\" \"string encoding\" \"linear\"\n",
             path, path);
    if (!load(t, &s, body)) return;
    sp = at_uv(0.25f, 0.75f);                        /* texel (0, 0): 128 */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), srgb128, 1e-4), "sRGB 128: %g, expected %g",
          tex_eval(s.textures, 0, &sp, 500), srgb128);
    CHECK(t, NEAR(tex_eval(s.textures, 1, &sp, 500), 128.0 / 255.0, 1e-5), "linear 128: %g",
          tex_eval(s.textures, 1, &sp, 500));
    sp = at_uv(0.75f, 0.75f);                        /* texel (1, 0): 255 */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 1.0, 1e-5), "sRGB 255: %g", tex_eval(s.textures, 0, &sp, 500));
    scene_free(&s);
}

/* A coloured texel's spectrum is spec_from_rgb's for its RGB (Newton from the
   previous texel's coefficients finds the same fit as the homotopy). */
static void test_imagemap_colour(T *t)
{
    Image im;
    Scene s;
    SurfacePoint sp;
    char body[1024];
    const char *path = test_path(t, "texcol.pfm");
    static const float rgb[4][3] = { { 0.8f, 0.2f, 0.1f }, { 0.1f, 0.6f, 0.3f },
                                     { 0.2f, 0.3f, 0.9f }, { 0.95f, 0.9f, 0.05f } };
    int i, c, l;
    CHECK(t, img_alloc(&im, 2, 2), "out of memory");
    for (i = 0; i < 4; i++)
        for (c = 0; c < 3; c++) im.rgb[3 * i + c] = rgb[i][c];
    CHECK(t, pfm_write(&im, path), "cannot write %s", path);
    img_free(&im);
    snprintf(body, sizeof body, "Texture \"g\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\"\n", path);
    if (!load(t, &s, body)) return;
    for (i = 0; i < 4; i++) {
        Spectrum ref;
        Error err;
        CHECK(t, spec_from_rgb(&ref, rgb[i], 0, &err, "t", 1), "%s", err.msg);
        sp = at_uv((i % 2 + 0.5f) / 2.0f, 1.0f - (i / 2 + 0.5f) / 2.0f);
        for (l = 400; l <= 700; l += 25) {
            float a = tex_eval(s.textures, 0, &sp, (float)l), b = spec_eval(&ref, (float)l);
            CHECK(t, NEAR(a, b, 2e-3), "texel %d at %d nm: %g, spec_from_rgb %g", i, l, a, b);
        }
    }
    scene_free(&s);
}

/* A mesh's "uv" is interpolated at the hit; without it pbrt-v4's corners
   (0,0), (1,0), (1,1). */
static void test_mesh_uv(T *t)
{
    Scene s;
    Ray r;
    HitRecord h;
    SurfacePoint sp;
    if (!load(t, &s,
              "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ 0 0 0  2 0 0  0 2 0 ] "
              "\"point2 uv\" [ 0.1 0.2  0.5 0.2  0.1 0.9 ]\n"
              "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ 0 0 -3  2 0 -3  2 2 -3 ]\n"))
        return;
    r.o = v3(0.5f, 1.0f, 5.0f); r.d = v3(0, 0, -1); r.tmax = INFINITY;
    CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "no hit");
    scene_surface_point(&s, &r, &h, &sp);
    /* barycentrics (b1, b2) = (0.25, 0.5): uv = 0.25 (0.1,0.2) + 0.25 (0.5,0.2) + 0.5 (0.1,0.9) */
    CHECK(t, NEAR(sp.u, 0.25 * 0.1 + 0.25 * 0.5 + 0.5 * 0.1, 1e-5) && NEAR(sp.v, 0.25 * 0.2 + 0.25 * 0.2 + 0.5 * 0.9, 1e-5),
          "uv (%g, %g)", sp.u, sp.v);
    r.o = v3(1.8f, 0.5f, 5.0f);                      /* past the first triangle's edge */
    CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "no hit on the second mesh");
    scene_surface_point(&s, &r, &h, &sp);
    /* (1.8, 0.5) = b1 (2,0) + b2 (2,2): b2 = 0.25, b1 = 0.65: u = b1 + b2, v = b2 */
    CHECK(t, NEAR(sp.u, 0.9, 1e-5) && NEAR(sp.v, 0.25, 1e-5), "default uv (%g, %g)", sp.u, sp.v);
    scene_free(&s);
}

/* A PLY mesh's "u v" (or "s t", "texture_u texture_v") become the hit's (u, v). */
static void test_ply_uv(T *t)
{
    static const char *const names[3][2] = { { "u", "v" }, { "s", "t" }, { "texture_u", "texture_v" } };
    int k;
    for (k = 0; k < 3; k++) {
        char ply[512], body[1024];
        const char *path;
        Scene s;
        Ray r;
        HitRecord h;
        SurfacePoint sp;
        snprintf(ply, sizeof ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                 "property float y\nproperty float z\nproperty float %s\nproperty float %s\n"
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0 0.1 0.2\n2 0 0 0.5 0.2\n0 2 0 0.1 0.9\n3 0 1 2\n", names[k][0], names[k][1]);
        path = test_write_file(t, "uv.ply", ply);
        snprintf(body, sizeof body, "Shape \"plymesh\" \"string filename\" \"%s\"\n", path);
        if (!load(t, &s, body)) return;
        r.o = v3(0.5f, 1.0f, 5.0f); r.d = v3(0, 0, -1); r.tmax = INFINITY;
        CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "no hit");
        scene_surface_point(&s, &r, &h, &sp);
        CHECK(t, NEAR(sp.u, 0.25 * 0.1 + 0.25 * 0.5 + 0.5 * 0.1, 1e-5) &&
                 NEAR(sp.v, 0.25 * 0.2 + 0.25 * 0.2 + 0.5 * 0.9, 1e-5),
              "PLY %s %s: uv (%g, %g)", names[k][0], names[k][1], sp.u, sp.v);
        scene_free(&s);
    }
}

/* The quadrics' (u, v) (shapes.c), pbrt-v4's: u = phi / phimax; a disk's
   v = (radius - r) / (radius - innerradius), a cylinder's (z - zmin) / (zmax - zmin). */
static void test_quadric_uv(T *t)
{
    Scene s;
    Ray r;
    HitRecord h;
    SurfacePoint sp;
    if (!load(t, &s,
              "Shape \"disk\" \"float radius\" [ 2 ] \"float innerradius\" [ 0.5 ] \"float phimax\" [ 180 ]\n"
              "AttributeBegin\nTranslate 10 0 0\nShape \"cylinder\" \"float radius\" [ 1 ] \"float zmin\" [ -1 ] "
              "\"float zmax\" [ 3 ]\nAttributeEnd\n"))
        return;
    r.o = v3(0.0f, 1.0f, 5.0f); r.d = v3(0, 0, -1); r.tmax = INFINITY;   /* phi = 90 deg, r = 1 */
    CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "no hit on the disk");
    scene_surface_point(&s, &r, &h, &sp);
    CHECK(t, NEAR(sp.u, 0.5, 1e-5) && NEAR(sp.v, (2.0 - 1.0) / 1.5, 1e-5), "disk uv (%g, %g)", sp.u, sp.v);
    r.o = v3(10.0f, -5.0f, 2.0f); r.d = v3(0, 1, 0);                    /* phi = 270 deg, z = 2 */
    CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "no hit on the cylinder");
    scene_surface_point(&s, &r, &h, &sp);
    CHECK(t, NEAR(sp.u, 0.75, 1e-5) && NEAR(sp.v, 0.75, 1e-5), "cylinder uv (%g, %g)", sp.u, sp.v);
    scene_free(&s);
}

/* A textured plane lit straight on by a distant light of illuminance pi: its
   radiance is the reflectance, and a narrow camera on one check sees it. */
static void test_render_checks(T *t)
{
    /* s = 2u = 2x, t = 2y: (0.25, 0.25) is in cell (0, 0), (0.75, 0.25) in cell (1, 0) */
    static const struct { float x; double expect; } at[2] = { { 0.25f, 0.8 }, { 0.75f, 0.2 } };
    int i;
    for (i = 0; i < 2; i++) {
        char text[4096];
        Scene s;
        RenderOptions o;
        Tiles tl;
        double Y;
        snprintf(text, sizeof text,
                 "LookAt %g 0.25 5  %g 0.25 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 2 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
                 "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
                 "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
                 "Texture \"ch\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 2 ] "
                 "\"spectrum tex1\" [ 300 0.8 830 0.8 ] \"spectrum tex2\" [ 300 0.2 830 0.2 ]\n"
                 "Material \"diffuse\" \"texture reflectance\" \"ch\"\n"
                 "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 0  4 0 0  4 4 0  0 4 0 ] "
                 "\"point2 uv\" [ 0 0  4 0  4 4  0 4 ]\n", at[i].x, at[i].x);
        if (!test_load_scene(t, &s, text)) return;
        render_options_default(&o);
        o.spp = test_scaled(8, 2);
        if (!test_render_tiles(t, &s, &o, 4, 1, &tl)) { scene_free(&s); return; }
        scene_free(&s);
        Y = test_luminance(tl.mean[0]);
        CHECK(t, NEAR(Y, at[i].expect, TEST_K_SIGMA * tl.se[0][1] + 2e-3),
              "check at x %g: Y = %.5f +- %.2g, expected %g", at[i].x, Y, tl.se[0][1], at[i].expect);
    }
}

/* pbrt-v4's own Noise and FBm (util/noise.cpp, commit 5f7a606806a4ac7b939131ded9d7a30ebd02416e)
   printed by a small C++ program linked with its libpbrt_lib.a: Noise(x, y, z) and
   FBm(p, dpdx = dpdy = 0, omega, octaves) for (omega, octaves) = (0.5, 8) and (0.7, 3). */
static const float NOISE_AT[8][6] = {
    /* x, y, z, Noise, FBm(0.5, 8), FBm(0.7, 3) */
    { 0.5f, 0.5f, 0.5f, -0.125f, -0.11803776f, -0.137513295f },
    { 1.25f, 2.5f, 0.75f, 0.472781658f, 0.463357776f, 0.456339926f },
    { -3.7f, 0.2f, 5.1f, 0.151658028f, 0.407572746f, 0.560678303f },
    { 10.3f, -7.9f, 2.2f, 0.373561889f, 0.465203583f, 0.480144233f },
    { 0.1f, 0.9f, 0.3f, 0.0940399617f, 0.324288011f, 0.448794901f },
    { 100.77f, 33.3f, -12.6f, 0.340050459f, 0.354269385f, 0.337502658f },
    { 1.5f, 2.8f, 0.5f, 0.56959188f, 0.564189136f, 0.528325379f },
    { -0.3f, -0.7f, -0.5f, 0.0295332149f, -0.036878489f, -0.109459117f },
};

static void test_noise(T *t)
{
    int i;
    for (i = 0; i < 8; i++) {
        const float *q = NOISE_AT[i];
        float n = tex_noise(q[0], q[1], q[2]);
        float f8 = tex_fbm(v3(q[0], q[1], q[2]), 0.5f, 8), f3 = tex_fbm(v3(q[0], q[1], q[2]), 0.7f, 3);
        CHECK(t, NEAR(n, q[3], 2e-6), "noise(%g, %g, %g) = %.9g, pbrt-v4 %.9g", q[0], q[1], q[2], n, q[3]);
        CHECK(t, NEAR(f8, q[4], 1e-5) && NEAR(f3, q[5], 1e-5), "FBm at (%g, %g, %g): %.9g %.9g, "
              "pbrt-v4 %.9g %.9g", q[0], q[1], q[2], f8, f3, q[4], q[5]);
    }
    /* 0 at every lattice point (each corner's offset is 0 there) */
    CHECK(t, tex_noise(3.0f, -7.0f, 12.0f) == 0.0f, "noise at a lattice point: %g", tex_noise(3.0f, -7.0f, 12.0f));
}

/* Section 4's noise written directly (floorf, fmodf, each corner's hash
   perm[perm[perm[x] + y] + z] by its own three lookups mod 256, the gradient by
   branches), with Perlin's reference permutation: texture.c shares lookups among
   corners and selects the gradient by tables; both must give the same float, bit
   for bit, so that the fbm textures and the cloud medium do not move. */
static const unsigned char REF_PERM[256] = {
    151, 160, 137,  91,  90,  15, 131,  13, 201,  95,  96,  53, 194, 233,   7, 225,
    140,  36, 103,  30,  69, 142,   8,  99,  37, 240,  21,  10,  23, 190,   6, 148,
    247, 120, 234,  75,   0,  26, 197,  62,  94, 252, 219, 203, 117,  35,  11,  32,
     57, 177,  33,  88, 237, 149,  56,  87, 174,  20, 125, 136, 171, 168,  68, 175,
     74, 165,  71, 134, 139,  48,  27, 166,  77, 146, 158, 231,  83, 111, 229, 122,
     60, 211, 133, 230, 220, 105,  92,  41,  55,  46, 245,  40, 244, 102, 143,  54,
     65,  25,  63, 161,   1, 216,  80,  73, 209,  76, 132, 187, 208,  89,  18, 169,
    200, 196, 135, 130, 116, 188, 159,  86, 164, 100, 109, 198, 173, 186,   3,  64,
     52, 217, 226, 250, 124, 123,   5, 202,  38, 147, 118, 126, 255,  82,  85, 212,
    207, 206,  59, 227,  47,  16,  58,  17, 182, 189,  28,  42, 223, 183, 170, 213,
    119, 248, 152,   2,  44, 154, 163,  70, 221, 153, 101, 155, 167,  43, 172,   9,
    129,  22,  39, 253,  19,  98, 108, 110,  79, 113, 224, 232, 178, 185, 112, 104,
    218, 246,  97, 228, 251,  34, 242, 193, 238, 210, 144,  12, 191, 179, 162, 241,
     81,  51, 145, 235, 249,  14, 239, 107,  49, 192, 214,  31, 181, 199, 106, 157,
    184,  84, 204, 176, 115, 121,  50,  45, 127,   4, 150, 254, 138, 236, 205,  93,
    222, 114,  67,  29,  24,  72, 243, 141, 128, 195,  78,  66, 215,  61, 156, 180
};

static int ref_perm(int i) { return REF_PERM[((i % 256) + 256) % 256]; }

static float ref_grad(int x, int y, int z, float dx, float dy, float dz)
{
    int h = ref_perm(ref_perm(ref_perm(x) + y) + z) & 15;
    float u = (h < 8 || h == 12 || h == 13) ? dx : dy;
    float v = (h < 4 || h == 12 || h == 13) ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

static float ref_weight(float t) { return t * t * t * (t * (6.0f * t - 15.0f) + 10.0f); }
static float ref_lerp(float t, float a, float b) { return (1.0f - t) * a + t * b; }

static float ref_noise(float x, float y, float z)
{
    float dx, dy, dz, wx, wy, wz, c[8];
    int ix, iy, iz, k;
    if (!(fabsf(x) < 1e30f && fabsf(y) < 1e30f && fabsf(z) < 1e30f)) return 0.0f;
    x = fmodf(x, 1073741824.0f); y = fmodf(y, 1073741824.0f); z = fmodf(z, 1073741824.0f);
    ix = (int)floorf(x); iy = (int)floorf(y); iz = (int)floorf(z);
    dx = x - (float)ix; dy = y - (float)iy; dz = z - (float)iz;
    for (k = 0; k < 8; k++) {
        int cx = k & 1, cy = (k >> 1) & 1, cz = k >> 2;
        c[k] = ref_grad(ix + cx, iy + cy, iz + cz, dx - (float)cx, dy - (float)cy, dz - (float)cz);
    }
    wx = ref_weight(dx); wy = ref_weight(dy); wz = ref_weight(dz);
    return ref_lerp(wz, ref_lerp(wy, ref_lerp(wx, c[0], c[1]), ref_lerp(wx, c[2], c[3])),
                    ref_lerp(wy, ref_lerp(wx, c[4], c[5]), ref_lerp(wx, c[6], c[7])));
}

/* One coordinate of a test point: a uniform one in [-8, 8), a lattice point,
   -0, one near +-2^30 (the reduction), a large one, or one just off a lattice point. */
static float noise_coord(Rng *r)
{
    float u = rng_float(r) * 2.0f - 1.0f;
    switch (rng_u32(r) % 6) {
    case 0: return 8.0f * u;
    case 1: return floorf(300.0f * u);
    case 2: return -0.0f;
    case 3: return ldexpf(1.0f + u * 0.25f, 30) * (u < 0.0f ? -1.0f : 1.0f);
    case 4: return ldexpf(u, (int)(rng_u32(r) % 40));
    default: return nextafterf(floorf(50.0f * u), u < 0.0f ? -1e9f : 1e9f);
    }
}

static void test_noise_direct(T *t)
{
    Rng r;
    int i, bad = 0;
    rng_seed(&r, 37, 0);
    for (i = 0; i < 200000; i++) {
        float x = noise_coord(&r), y = noise_coord(&r), z = noise_coord(&r);
        float a = tex_noise(x, y, z), b = ref_noise(x, y, z);
        if (memcmp(&a, &b, sizeof a) && bad++ < 3)
            CHECK(t, 0, "noise(%.9g, %.9g, %.9g) = %.9g, written directly %.9g", x, y, z, a, b);
    }
    CHECK(t, bad == 0, "%d of 200000 points differ from the direct noise", bad);
}

/* tex_noise_diff (the cloud's wisps) against four tex_noise calls, bit for bit: at
   points whose shifted copies stay in the cell, cross into the next one (a point
   just below a lattice plane), or are huge, infinite or NaN. */
static void test_noise_diff(T *t)
{
    Rng r;
    int i, k, bad = 0, crossed = 0;
    rng_seed(&r, 38, 0);
    for (i = 0; i < 100000; i++) {
        const float hs[4] = { 0.01f, 0.5f, 1.75f, -0.01f };
        float q[3], n[4], want[4], h = hs[rng_u32(&r) % 4];
        for (k = 0; k < 3; k++) {
            q[k] = noise_coord(&r);
            if (rng_u32(&r) % 3 == 0) q[k] = floorf(20.0f * rng_float(&r) - 10.0f) - 0.5f * h * rng_float(&r);
        }
        if (i % 997 == 0) q[i % 3] = i % 2 ? INFINITY : NAN;
        tex_noise_diff(v3(q[0], q[1], q[2]), h, n);
        want[0] = tex_noise(q[0], q[1], q[2]);
        want[1] = tex_noise(q[0] + h, q[1], q[2]);
        want[2] = tex_noise(q[0], q[1] + h, q[2]);
        want[3] = tex_noise(q[0], q[1], q[2] + h);
        for (k = 0; k < 3; k++) crossed += floorf(q[k]) != floorf(q[k] + h);
        if (memcmp(n, want, sizeof n) && bad++ < 3)
            CHECK(t, 0, "noise_diff(%.9g, %.9g, %.9g; %g) = %g %g %g %g, four noise calls %g %g %g %g",
                  q[0], q[1], q[2], h, n[0], n[1], n[2], n[3], want[0], want[1], want[2], want[3]);
    }
    CHECK(t, bad == 0, "%d of 100000 points differ from four noise calls", bad);
    CHECK(t, crossed > 20000, "only %d shifted points left their cell", crossed);
}

/* pbrt-v4's fbm, wrinkled and windy textures (textures.h: FBmTexture, WrinkledTexture,
   WindyTexture over util/noise.cpp's FBm and Turbulence, commit 5f7a6068) for a
   footprint of zero, printed by a small C++ program linked with its libpbrt_lib.a
   (as NOISE_AT; windy built from its FBm as WindyTexture::Evaluate does):
   x, y, z, FBm(0.5, 8), FBm(0.7, 3), Turbulence(0.5, 8), Turbulence(0.7, 3), windy. */
static const float NOISE_TEX_AT[8][8] = {
    { 0.5f, 0.5f, 0.5f, -0.11803776f, -0.137513295f, 0.188431874f, 0.220113203f, -0.0308829248f },
    { 1.25f, 2.5f, 0.75f, 0.463357776f, 0.456339926f, 0.511341631f, 0.565620601f, 0.0490797982f },
    { 0.3f, 0.7f, 0.1f, 0.213505715f, 0.325000674f, 0.42389828f, 0.5879637f, 0.0168855321f },
    { 1.37f, -2.21f, 0.58f, -0.0345556103f, -0.1507743f, 0.304409564f, 0.423674226f, -0.0102710705f },
    { -4.6f, 3.3f, 7.9f, 0.75934124f, 1.00281954f, 0.84801656f, 1.0714196f, 0.0435810015f },
    { 12.25f, 0.125f, -5.5f, 0.0760946274f, 0.127891555f, 0.284320146f, 0.425775677f, 0.00915860757f },
    { 0.01f, 0.02f, 0.03f, 0.17639631f, 0.176211223f, 0.186261669f, 0.244811222f, 0.00208752719f },
    { -0.77f, -0.31f, 2.45f, -0.44443813f, -0.308501154f, 0.764672279f, 0.863881767f, -0.221569315f },
};

static void test_noise_textures(T *t)
{
    Scene s;
    int i, k;
    if (!load(t, &s, "Texture \"f8\" \"float\" \"fbm\"\n"
              "Texture \"f3\" \"float\" \"fbm\" \"float roughness\" [ 0.7 ] \"integer octaves\" [ 3 ]\n"
              "Texture \"w8\" \"float\" \"wrinkled\"\n"
              "Texture \"w3\" \"float\" \"wrinkled\" \"float roughness\" [ 0.7 ] \"integer octaves\" [ 3 ]\n"
              "Texture \"y\" \"float\" \"windy\"\n"
              "AttributeBegin\nTranslate 1 -2 0.5\nTexture \"wt\" \"float\" \"wrinkled\"\nAttributeEnd\n"))
        return;
    for (i = 0; i < 8; i++) {
        const float *q = NOISE_TEX_AT[i];
        SurfacePoint sp = at_p(q[0], q[1], q[2]);
        for (k = 0; k < 5; k++) {
            float got = tex_eval(s.textures, k, &sp, 550);
            CHECK(t, NEAR(got, q[3 + k], 1e-5), "%s at (%g, %g, %g): %.9g, pbrt-v4 %.9g",
                  k < 2 ? "fbm" : k < 4 ? "wrinkled" : "windy", q[0], q[1], q[2], got, q[3 + k]);
        }
        /* the texture's frame: the CTM at the directive */
        sp = at_p(q[0] + 1.0f, q[1] - 2.0f, q[2] + 0.5f);
        CHECK(t, NEAR(tex_eval(s.textures, 5, &sp, 550), q[5], 2e-4), "translated wrinkled at "
              "(%g, %g, %g): %.9g, pbrt-v4 %.9g", q[0], q[1], q[2], tex_eval(s.textures, 5, &sp, 550), q[5]);
    }
    scene_free(&s);
}

/* Dots with the uv mapping (s = u, t = v): pbrt-v4's InsidePolkaDot (textures.cpp,
   same program as NOISE_AT) at 8 points, and the count of points inside a dot on
   the grid s = -3 + 0.173 i, t = -2 + 0.191 j, i, j < 40: 260.  In a dot the texture
   is "outside" (0.25 here), elsewhere "inside" (0.75): pbrt-v4's meaning (texture.c
   section 4). */
static void test_dots(T *t)
{
    static const float at[8][3] = {
        { 0.1f, 0.1f, 0 }, { 1.05f, -0.02f, 0 }, { 2.2f, 3.1f, 1 }, { -1.6f, 0.4f, 0 },
        { 5.5f, 7.25f, 0 }, { 3.0f, 1.0f, 0 }, { 0.9f, 2.1f, 1 }, { -2.3f, -4.4f, 0 },
    };
    Scene s;
    SurfacePoint sp;
    int i, j, n = 0;
    if (!load(t, &s, "Texture \"d\" \"float\" \"dots\" \"float inside\" [ 0.75 ] \"float outside\" [ 0.25 ]\n"
              "Texture \"e\" \"float\" \"dots\" \"float uscale\" [ 2 ] \"float udelta\" [ 0.3 ]\n"))
        return;
    for (i = 0; i < 8; i++) {
        float want = at[i][2] != 0.0f ? 0.25f : 0.75f, got;
        sp = at_uv(at[i][0], at[i][1]);
        got = tex_eval(s.textures, 0, &sp, 550);
        CHECK(t, got == want, "dots at (%g, %g): %g, pbrt-v4 %g", at[i][0], at[i][1], got, want);
        /* the mapping: s = 2u + 0.3; default inside 1, outside 0 */
        sp = at_uv((at[i][0] - 0.3f) / 2.0f, at[i][1]);
        got = tex_eval(s.textures, 1, &sp, 550);
        CHECK(t, NEAR(got, at[i][2] != 0.0f ? 0.0 : 1.0, 0), "dots through uscale/udelta at (%g, %g): %g",
              at[i][0], at[i][1], got);
    }
    for (i = 0; i < 40; i++)
        for (j = 0; j < 40; j++) {
            sp = at_uv(-3.0f + (float)i * 0.173f, -2.0f + (float)j * 0.191f);
            n += tex_eval(s.textures, 0, &sp, 550) == 0.25f;
        }
    CHECK(t, n == 260, "%d grid points in a dot, pbrt-v4 260", n);
    scene_free(&s);
}

/* The linear sRGB colour (under D65, pbrt-v4's RGBAlbedoSpectrum) of texture i at sp. */
static void texture_rgb(const Scene *s, int i, const SurfacePoint *sp, double rgb[3])
{
    static Spectrum S, d65;
    double xyz[3], yd65[3];
    int nm;
    spec_named(&d65, "stdillum-D65");
    spec_to_xyz(&d65, SPEC_MIN, SPEC_MAX, yd65);
    spec_const(&S, 0.0f);
    for (nm = SPEC_MIN; nm <= SPEC_MAX; nm++)
        *spec_at(&S, nm) = tex_eval(s->textures, i, sp, (float)nm) * spec_get(&d65, nm) / (float)yd65[1];
    spec_to_xyz(&S, SPEC_MIN, SPEC_MAX, xyz);
    xyz_to_linear_srgb(xyz, rgb);
}

/* Marble: at points of its frame (Translate 1 2 3, scale 2, variation 0.7,
   roughness 0.6, 5 octaves) its colour is pbrt-v4's spline, 1.5 B(x), within 1e-3
   (the fit's and the knots' error), x from the definition in texture.c section 4
   with tex_fbm (tested above). */
static void test_marble(T *t)
{
    static const float C[9][3] = {
        { .58f, .58f, .6f }, { .58f, .58f, .6f }, { .58f, .58f, .6f }, { .5f, .5f, .5f }, { .6f, .59f, .58f },
        { .58f, .58f, .6f }, { .58f, .58f, .6f }, { .2f, .2f, .33f }, { .58f, .58f, .6f },
    };
    Scene s;
    SurfacePoint sp;
    int i, c;
    if (!load(t, &s, "AttributeBegin\nTranslate 1 2 3\nTexture \"m\" \"spectrum\" \"marble\" \"float scale\" [ 2 ] "
              "\"float variation\" [ 0.7 ] \"float roughness\" [ 0.6 ] \"integer octaves\" [ 5 ]\nAttributeEnd\n"))
        return;
    for (i = 0; i < 24; i++) {
        Vec3 p = v3(0.37f * (float)i - 3.0f, 0.29f * (float)i - 2.5f, 0.11f * (float)i);
        Vec3 q = v3_mul(v3(p.x - 1.0f, p.y - 2.0f, p.z - 3.0f), 2.0f);
        double x = 0.5 + 0.5 * sin(q.y + 0.7 * tex_fbm(q, 0.6f, 5)), rgb[3], want[3], a, b;
        int k = (int)floor(x * 6.0);
        if (k > 5) k = 5;
        x = x * 6.0 - k;
        a = 1.0 - x;
        for (c = 0; c < 3; c++)
            want[c] = 1.5 * (a * a * a * C[k][c] + 3 * a * a * x * C[k + 1][c] + 3 * a * x * x * C[k + 2][c] +
                             x * x * x * C[k + 3][c]);
        sp = at_p(p.x, p.y, p.z);
        texture_rgb(&s, 0, &sp, rgb);
        b = 0.0;
        for (c = 0; c < 3; c++) b = fmax(b, fabs(rgb[c] - want[c]));
        CHECK(t, b < 1e-3, "marble at (%g, %g, %g): rgb (%.4f %.4f %.4f), the spline (%.4f %.4f %.4f)",
              p.x, p.y, p.z, rgb[0], rgb[1], rgb[2], want[0], want[1], want[2]);
    }
    scene_free(&s);
}

/* A 4 x 4 square, uv [0, 1]^2, lit straight on by a distant light of illuminance
   pi (radiance = the reflectance), its texture declared under Translate 0.3 0.1 0,
   Rotate 20 0 0 1 (which moves marble; dots use uv).  pbrt-v4 (commit 5f7a6068)
   rendered this text, with "Sampler \"independent\"" added, 8 times: pbrt --spp 256
   --seed S --outfile x_S.pfm x.pbrt, S = 1..8.  Per 4 x 4 tile (12 x 12 pixels,
   row-major from the top left): the mean over the 8 images of the tile's luminance
   (0.212671 R + 0.715160 G + 0.072169 B) and its standard error. */
static void pbrt_square_text(char *buf, size_t cap, const char *texture)
{
    snprintf(buf, cap,
             "LookAt 2 2 8  2 2 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 28 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ] \"string filename\" \"x.pfm\"\n"
             "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
             "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
             "AttributeBegin\nTranslate 0.3 0.1 0\nRotate 20 0 0 1\n%s\nAttributeEnd\n"
             "Material \"diffuse\" \"texture reflectance\" \"tx\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 0  4 0 0  4 4 0  0 4 0 ] "
             "\"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n", texture);
}

static const char *const PBRT_TEX[2] = {
    "Texture \"tx\" \"spectrum\" \"dots\" \"float uscale\" [ 3 ] \"float vscale\" [ 3 ] "
    "\"rgb inside\" [ 0.9 0.8 0.6 ] \"rgb outside\" [ 0.05 0.1 0.3 ]",
    "Texture \"tx\" \"spectrum\" \"marble\" \"float scale\" [ 1.5 ] \"float variation\" [ 1.5 ] "
    "\"integer octaves\" [ 6 ]",
};
static const double PBRT_TEX_TILES[2][16][2] = {
    { { 0.59739, 0.00022 }, { 0.49551, 0.00017 }, { 0.51690, 0.00015 }, { 0.65243, 0.00022 },
      { 0.52437, 0.00028 }, { 0.44313, 0.00016 }, { 0.37436, 0.00011 }, { 0.56805, 0.00017 },
      { 0.80693, 0.00003 }, { 0.80705, 0.00002 }, { 0.80702, 0.00006 }, { 0.59500, 0.00018 },
      { 0.80694, 0.00004 }, { 0.80685, 0.00007 }, { 0.80701, 0.00003 }, { 0.75811, 0.00019 } },
    { { 0.82932, 0.00014 }, { 0.84224, 0.00006 }, { 0.85117, 0.00010 }, { 0.85468, 0.00004 },
      { 0.73979, 0.00012 }, { 0.76927, 0.00019 }, { 0.81551, 0.00007 }, { 0.82716, 0.00008 },
      { 0.77980, 0.00018 }, { 0.75974, 0.00015 }, { 0.74531, 0.00010 }, { 0.75431, 0.00012 },
      { 0.85458, 0.00008 }, { 0.84610, 0.00008 }, { 0.79948, 0.00013 }, { 0.79847, 0.00011 } },
};

/* specnee's tiles within 5 standard errors + 0.5 % of pbrt-v4's (the colour fits
   of the two renderers differ by about 0.2 %). */
static void test_against_pbrt(T *t)
{
    int c, i;
    for (c = 0; c < 2; c++) {
        char text[4096];
        Scene s;
        RenderOptions o;
        Tiles tl;
        pbrt_square_text(text, sizeof text, PBRT_TEX[c]);
        if (!test_load_scene(t, &s, text)) return;
        render_options_default(&o);
        o.spp = test_scaled(64, 16);
        if (!test_render_tiles(t, &s, &o, 4, 4, &tl)) { scene_free(&s); return; }
        scene_free(&s);
        for (i = 0; i < 16; i++) {
            double Y = test_luminance(tl.mean[i]);
            double Yp = PBRT_TEX_TILES[c][i][0], se = tl.se[i][1], sep = PBRT_TEX_TILES[c][i][1];
            if (getenv("DBG")) fprintf(stderr, "%s tile %d: specnee %.5f +- %.2g, pbrt %.5f\n",
                                       c ? "marble" : "dots", i, Y, se, Yp);
            CHECK(t, fabs(Y - Yp) < TEST_K_SIGMA * sqrt(se * se + sep * sep) + 5e-3 * Yp,
                  "%s: tile %d: specnee Y %.5f +- %.2g, pbrt-v4 %.5f +- %.2g", c ? "marble" : "dots",
                  i, Y, se, Yp, sep);
        }
    }
}

/* Texture-valued parameters of conductor and coateddiffuse (material.c mat_point),
   at points of two checkerboards (uv mapping): "r", a reflectance, is
   [300 0.9 830 0.2] where floor(2u) is even and 0.3 where it is odd; "g", a
   roughness, is 0 where floor(2v) is even and 0.25 where it is odd.
   - conductor "texture reflectance": at normal incidence the smooth mirror's
     weight f |cos| / pdf is exactly r(lambda) (eta = 1, k = 2 sqrt(r)/sqrt(1 - r),
     pbrt-v4's ConductorMaterial), per wavelength;
   - conductor "texture roughness": a delta mirror where g = 0 (eval gives 0, the
     sample is delta), and where g = 0.25 the same f, pdfs and samples as a
     conductor with "float roughness" 0.25; never delta as a material (NEE runs);
   - coateddiffuse "texture reflectance" and "texture roughness": f and the pdfs
     at each point equal a constant coateddiffuse's with that point's values. */
static const char *const MAT_TEXT =
    "Texture \"r\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 2 ] \"spectrum tex1\" [ 300 0.9 830 0.2 ] "
    "\"spectrum tex2\" [ 300 0.3 830 0.3 ]\n"
    "Texture \"g\" \"float\" \"checkerboard\" \"float vscale\" [ 2 ] \"float tex1\" [ 0 ] \"float tex2\" [ 0.25 ]\n"
    "Material \"conductor\" \"texture reflectance\" \"r\"\nShape \"sphere\"\n"
    "Material \"conductor\" \"texture roughness\" \"g\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\nShape \"sphere\"\n"
    "Material \"conductor\" \"float roughness\" [ 0.25 ] \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\nShape \"sphere\"\n"
    "Material \"coateddiffuse\" \"texture reflectance\" \"r\" \"texture roughness\" \"g\"\nShape \"sphere\"\n"
    "Material \"coateddiffuse\" \"spectrum reflectance\" [ 300 0.9 830 0.2 ]\nShape \"sphere\"\n"
    "Material \"coateddiffuse\" \"spectrum reflectance\" [ 300 0.3 830 0.3 ] \"float roughness\" [ 0.25 ]\nShape \"sphere\"\n";

static int same_arrays(const float *a, const float *b)
{
    int j;
    for (j = 0; j < HERO_N; j++) if (!(a[j] == b[j])) return 0;
    return 1;
}

static void test_material_params(T *t)
{
    static const float lam[HERO_N] = { 420.0f, 510.0f, 600.0f, 690.0f };
    const Material *ca, *cb, *cc, *da, *de, *df;
    Scene s;
    SurfacePoint sp;
    BsdfSample bs, bs2;
    Vec3 wo = v3_norm(v3(0.3f, -0.2f, 0.9f)), wi = v3_norm(v3(-0.5f, 0.1f, 0.7f));
    float f[HERO_N], p[HERO_N], f2[HERO_N], p2[HERO_N];
    int j, k, n, base;
    if (!load(t, &s, MAT_TEXT)) return;
    base = s.n_materials - 6;
    ca = &s.materials[base]; cb = &s.materials[base + 1]; cc = &s.materials[base + 2];
    da = &s.materials[base + 3]; de = &s.materials[base + 4]; df = &s.materials[base + 5];
    CHECK(t, ca->type == MAT_CONDUCTOR && cc->type == MAT_CONDUCTOR && da->type == MAT_COATED_DIFFUSE &&
          df->type == MAT_COATED_DIFFUSE, "material order");
    /* conductor, textured reflectance, at normal incidence */
    for (k = 0; k < 2; k++) {
        sp = at_uv(k ? 0.75f : 0.25f, 0.25f);
        CHECK(t, bsdf_sample(ca, &sp, v3(0, 0, 1), lam, 15u, 0.5f, 0.5f, 0.5f, &bs) && bs.delta,
              "textured smooth conductor: no delta sample");
        for (j = 0; j < HERO_N; j++) {
            double r = k ? 0.3 : 0.9 - 0.7 * (lam[j] - 300.0) / 530.0, w = bs.f[j] * fabs(bs.wi.z) / bs.pdf;
            CHECK(t, NEAR(w, r, 2e-5), "conductor texture reflectance at u %g, %g nm: weight %.6f, r %.6f",
                  sp.u, lam[j], w, r);
        }
    }
    /* conductor, textured roughness */
    CHECK(t, !mat_is_delta(cb) && mat_is_delta(ca), "mat_is_delta: textured roughness %d, smooth %d",
          mat_is_delta(cb), mat_is_delta(ca));
    sp = at_uv(0.25f, 0.25f);                          /* g = 0: a mirror here */
    bsdf_eval(cb, &sp, wo, wi, lam, 15u, f, p);
    CHECK(t, f[0] == 0.0f && p[0] == 0.0f, "smooth point: eval f %g pdf %g", f[0], p[0]);
    CHECK(t, bsdf_sample(cb, &sp, wo, lam, 15u, 0.3f, 0.6f, 0.2f, &bs) && bs.delta, "smooth point: no delta sample");
    sp = at_uv(0.25f, 0.75f);                          /* g = 0.25 */
    bsdf_eval(cb, &sp, wo, wi, lam, 15u, f, p);
    bsdf_eval(cc, &sp, wo, wi, lam, 15u, f2, p2);
    CHECK(t, f[0] > 0.0f && same_arrays(f, f2) && same_arrays(p, p2), "rough point: f %g pdf %g, "
          "float roughness 0.25: f %g pdf %g", f[0], p[0], f2[0], p2[0]);
    CHECK(t, bsdf_sample(cb, &sp, wo, lam, 15u, 0.3f, 0.6f, 0.2f, &bs) &&
          bsdf_sample(cc, &sp, wo, lam, 15u, 0.3f, 0.6f, 0.2f, &bs2) && !bs.delta &&
          v3_dot(bs.wi, bs2.wi) == v3_dot(bs2.wi, bs2.wi) && same_arrays(bs.f, bs2.f) && bs.pdf == bs2.pdf,
          "rough point: the sample differs from float roughness 0.25's");
    /* coateddiffuse, both textured */
    for (k = 0; k < 2; k++) {
        const Material *ref = k ? df : de;
        sp = k ? at_uv(0.75f, 0.75f) : at_uv(0.25f, 0.25f);
        bsdf_eval(da, &sp, wo, wi, lam, 15u, f, p);
        bsdf_eval(ref, &sp, wo, wi, lam, 15u, f2, p2);
        CHECK(t, f[1] > 0.0f && same_arrays(f, f2) && same_arrays(p, p2), "coateddiffuse at (%g, %g): "
              "f %g %g, constant material's %g %g", sp.u, sp.v, f[0], f[3], f2[0], f2[3]);
        for (j = 0, n = 0; j < 16; j++) {
            float u0 = (float)j / 16.0f + 0.01f, u1 = 0.3f + 0.04f * (float)j, u2 = 0.9f - 0.05f * (float)j;
            int a1 = bsdf_sample(da, &sp, wo, lam, 15u, u0, u1, u2, &bs);
            int a2 = bsdf_sample(ref, &sp, wo, lam, 15u, u0, u1, u2, &bs2);
            CHECK(t, a1 == a2 && (!a1 || (bs.delta == bs2.delta && same_arrays(bs.f, bs2.f) &&
                                          bs.pdf == bs2.pdf && v3_dot(bs.wi, bs2.wi) > 0.99999f)),
                  "coateddiffuse at (%g, %g), sample %d: differs from the constant material's", sp.u, sp.v, j);
            n += a1;
        }
        CHECK(t, n > 4, "coateddiffuse at (%g, %g): %d of 16 samples", sp.u, sp.v, n);
    }
    scene_free(&s);
}

/* The same square, made a conductor with "texture reflectance" (a checkerboard of
   rgb 0.9 0.6 0.2 and 0.4 0.4 0.4, uscale 2) and "texture roughness" (0.02 and 0.3,
   vscale 2), lit by a distant light from (1, 0.5, 4) towards (2, 2, 0).  pbrt-v4
   (commit 5f7a6068) rendered it as PBRT_TEX_TILES above (8 seeds x 256 spp, the
   independent sampler).  specnee's 4 x 4 tile luminances agree within 5 standard
   errors + 1 % (the RGB fits of the two renderers differ by about 0.2 %; measured
   in a 512 spp render: at most 0.8 %, in the bright highlight).  (A coateddiffuse
   square is not compared: with a delta light only NEE sees it, through f, and
   pbrt-v4's f of a rough coat is biased high (layered.c), 3-8 % here, as much with
   constant parameters as with textured ones; texture_material_params shows that
   textured parameters give exactly the constant material's f.) */
static const double PBRT_COND_TILES[16][2] = {
    { 0.21364, 0.00002 }, { 0.22748, 0.00002 }, { 0.37863, 0.00002 }, { 0.39267, 0.00003 },
    { 0.23328, 0.00001 }, { 0.25065, 0.00003 }, { 0.42026, 0.00003 }, { 0.43699, 0.00003 },
    { 0.30019, 0.00003 }, { 0.53743, 0.00004 }, { 1.42556, 0.00014 }, { 1.89298, 0.00009 },
    { 0.42261, 0.00006 }, { 0.87271, 0.00010 }, { 2.76073, 0.00032 }, { 4.18011, 0.00080 },
};

static void test_conductor_against_pbrt(T *t)
{
    static const char *const text =
        "LookAt 2 2 8  2 2 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 28 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ] \"string filename\" \"x.pfm\"\n"
        "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
        "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 2 2 0 ]\n"
        "Texture \"r\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 2 ] \"rgb tex1\" [ 0.9 0.6 0.2 ] \"rgb tex2\" [ 0.4 0.4 0.4 ]\n"
        "Texture \"g\" \"float\" \"checkerboard\" \"float vscale\" [ 2 ] \"float tex1\" [ 0.02 ] \"float tex2\" [ 0.3 ]\n"
        "Material \"conductor\" \"texture reflectance\" \"r\" \"texture roughness\" \"g\"\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0 0 0  4 0 0  4 4 0  0 4 0 ] "
        "\"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    if (!test_render_tiles(t, &s, &o, 4, 4, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    for (i = 0; i < 16; i++) {
        double Y = test_luminance(tl.mean[i]);
        double Yp = PBRT_COND_TILES[i][0], se = tl.se[i][1], sep = PBRT_COND_TILES[i][1];
        if (getenv("DBG")) fprintf(stderr, "conductor tile %d: specnee %.5f +- %.2g, pbrt %.5f\n", i, Y, se, Yp);
        CHECK(t, fabs(Y - Yp) < TEST_K_SIGMA * sqrt(se * se + sep * sep) + 1e-2 * Yp,
              "textured conductor: tile %d: specnee Y %.5f +- %.2g, pbrt-v4 %.5f +- %.2g", i, Y, se, Yp, sep);
    }
}

/* A whole sphere's (u, v) are pbrt-v4's, in object space: u = phi / 2 pi, v = 1 -
   theta / pi of the hit point mapped by the inverse CTM.  Under Rotate 90 1 0 0
   (object (x, y, z) -> world (x, -z, y)) the world's +z pole is the object's +y
   axis: (u, v) = (0.25, 0.5); world +x is object +x: (0, 0.5); world -y is object
   +z: v = 1.  Under Scale -2 2 2 (a mirror and a scale) world +y is object +y:
   (0.25, 0.5), world -x is object +x: u = 0.  A textured roughness reads them too. */
static void test_sphere_object_uv(T *t)
{
    static const struct { int scene; float ox, oy, oz, dx, dy, dz, u, v; } c[] = {
        { 0, 0, 0, 5, 0, 0, -1, 0.25f, 0.5f },
        { 0, 5, 0, 0, -1, 0, 0, 0.0f, 0.5f },
        { 0, 0, -5, 0, 0, 1, 0, -1.0f, 1.0f },      /* u undefined at the pole (not checked) */
        { 0, 0, 0.6f, 5, 0, 0, -1, 0.25f, (float)(0.9272952180016122 / SPECNEE_PI) },  /* object (0, .8, -.6) */
        { 1, 0, 5, 0, 0, -1, 0, 0.25f, 0.5f },
        { 1, -5, 0, 0, 1, 0, 0, 0.0f, 0.5f },
        { 2, 0, 0, 5, 0, 0, -1, 0.25f, 0.5f },
    };
    static const char *const body[3] = {
        "Texture \"k\" \"spectrum\" \"constant\"\nMaterial \"diffuse\" \"texture reflectance\" \"k\"\n"
        "Rotate 90 1 0 0\nShape \"sphere\"\n",
        "Texture \"k\" \"spectrum\" \"constant\"\nMaterial \"diffuse\" \"texture reflectance\" \"k\"\n"
        "Scale -2 2 2\nShape \"sphere\"\n",
        "Texture \"g\" \"float\" \"constant\"\nMaterial \"conductor\" \"texture roughness\" \"g\"\n"
        "Rotate 90 1 0 0\nShape \"sphere\"\n",
    };
    int i;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        Scene s;
        Ray r;
        HitRecord h;
        SurfacePoint sp;
        if (!load(t, &s, body[c[i].scene])) return;
        CHECK(t, s.n_spheres == 1, "not a whole sphere");
        r.o = v3(c[i].ox, c[i].oy, c[i].oz);
        r.d = v3(c[i].dx, c[i].dy, c[i].dz);
        r.tmax = INFINITY;
        CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "case %d: no hit", i);
        scene_surface_point(&s, &r, &h, &sp);
        CHECK(t, (c[i].u < 0.0f || NEAR(sp.u, c[i].u, 1e-5)) && NEAR(sp.v, c[i].v, 1e-5),
              "case %d: (u, v) = (%g, %g), object space gives (%g, %g)", i, sp.u, sp.v, c[i].u, c[i].v);
        scene_free(&s);
    }
}

static void expect_error(T *t, const char *body, const char *k1, const char *k2)
{
    char text[4096];
    Scene s;
    Error e;
    int ok;
    snprintf(text, sizeof text, "%s%s\n", head, body);
    e.msg[0] = '\0';
    ok = scene_load_string(&s, text, "x.pbrt", &e);
    if (ok) scene_free(&s);
    CHECK(t, !ok, "accepted \"%s\"", body);
    CHECK(t, strncmp(e.msg, "x.pbrt:", 7) == 0, "message \"%s\" names no file:line", e.msg);
    CHECK(t, strstr(e.msg, k1) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k1);
    CHECK(t, !k2 || strstr(e.msg, k2) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k2);
}

/* pbrt-v4's DirectionMixTexture: a tex1 + (1 - a) tex2 with a = |ng . dir|, ng
   the geometric normal (not the shading one), dir carried by the CTM at the
   directive as a vector and normalised.  Values at chosen points, then a render
   against pbrt-v4: two diffuse spheres (radius 0.8 at x = -0.9 and 0.9, depth 5,
   fov 30, 32 x 16) under LightSource "infinite" "rgb L" [1 1 1], one with a
   float directionmix (dir 1 0 0 under Rotate 30 0 0 1) as the scale of a white
   spectrum, one with a spectrum directionmix (dir 0 2 1, tex2 a texture).
   pbrt-v4's mean R, G, B per tile (4 x 4 tiles of 8 x 4 pixels, row-major from
   the top left; a PFM file stores the bottom row first) at 16384 spp, frozen from the oracle (Sampler "independent"):
     pbrt --quiet --spp 16384 dm.pbrt */
static const char *const DM_TEXT =
    "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 16\n"
    "PixelFilter \"box\"\nCamera \"perspective\" \"float fov\" 30\nWorldBegin\n"
    "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
    "AttributeBegin\nRotate 30 0 0 1\n"
    "Texture \"fdm\" \"float\" \"directionmix\" \"vector3 dir\" [ 1 0 0 ] \"float tex1\" 0.9 \"float tex2\" 0.2\n"
    "AttributeEnd\n"
    "Texture \"blue\" \"spectrum\" \"constant\" \"rgb value\" [ 0.1 0.2 0.9 ]\n"
    "Texture \"sdm\" \"spectrum\" \"directionmix\" \"vector3 dir\" [ 0 2 1 ] \"rgb tex1\" [ 0.8 0.1 0.1 ] "
    "\"texture tex2\" \"blue\"\n"
    "AttributeBegin\nTranslate -0.9 0 5\n"
    "Texture \"sc\" \"spectrum\" \"scale\" \"rgb tex\" [ 1 1 1 ] \"texture scale\" \"fdm\"\n"
    "Material \"diffuse\" \"texture reflectance\" \"sc\"\nShape \"sphere\" \"float radius\" 0.8\n"
    "AttributeEnd\n"
    "AttributeBegin\nTranslate 0.9 0 5\nMaterial \"diffuse\" \"texture reflectance\" \"sdm\"\n"
    "Shape \"sphere\" \"float radius\" 0.8\nAttributeEnd\n";
static const double DM_TILES[16][3] = {
    { 0.99936, 0.99934, 0.99916 }, { 0.95409, 0.95367, 0.95505 }, { 0.94930, 0.91646, 0.94637 }, { 0.99937, 0.99918, 1.00040 },
    { 0.87025, 0.87038, 0.86967 }, { 0.55894, 0.55544, 0.57288 }, { 0.35679, 0.30199, 0.76447 }, { 0.82824, 0.81643, 0.94325 },
    { 0.91809, 0.91788, 0.91871 }, { 0.47361, 0.46889, 0.47893 }, { 0.61637, 0.26368, 0.46065 }, { 0.89227, 0.80683, 0.86991 },
    { 0.99988, 0.99973, 0.99950 }, { 0.94727, 0.94661, 0.94685 }, { 0.97755, 0.91254, 0.91537 }, { 0.99927, 0.99928, 0.99965 },
};

static void test_directionmix(T *t)
{
    Scene s;
    SurfacePoint sp = test_flat_point();
    RenderOptions o;
    Tiles tl;
    double a3 = 3.0 / sqrt(10.0);
    int i, c;
    if (!load(t, &s,
              "Texture \"d\" \"float\" \"directionmix\" \"vector3 dir\" [ 0 0 1 ] \"float tex1\" [ 0.9 ] "
              "\"float tex2\" [ 0.2 ]\n"
              "Texture \"e\" \"float\" \"directionmix\"\n"
              "Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n"
              "Texture \"s\" \"spectrum\" \"directionmix\" \"spectrum tex1\" [ 400 0.2 700 0.8 ] "
              "\"texture tex2\" \"k\"\n"
              "AttributeBegin\nScale 1 3 1\n"
              "Texture \"f\" \"float\" \"directionmix\" \"vector3 dir\" [ 1 1 0 ] \"float tex1\" [ 1 ] "
              "\"float tex2\" [ 0 ]\nAttributeEnd\n"))
        return;
    sp.ns = v3(1, 0, 0);                               /* the shading normal is not read */
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.9, 1e-6), "ng = dir: tex1, got %g",
          tex_eval(s.textures, 0, &sp, 500));
    sp.ng = v3(0.6f, 0, 0.8f);
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.8 * 0.9 + 0.2 * 0.2, 1e-6), "a = 0.8: %g",
          tex_eval(s.textures, 0, &sp, 500));
    sp.ng = v3(0, 0, -1);
    CHECK(t, NEAR(tex_eval(s.textures, 0, &sp, 500), 0.9, 1e-6), "|ng . dir|: a back face, got %g",
          tex_eval(s.textures, 0, &sp, 500));
    sp.ng = v3(0, 1, 0);                               /* defaults: dir 0 1 0, tex1 0, tex2 1 */
    CHECK(t, tex_eval(s.textures, 1, &sp, 500) == 0.0f, "defaults at ng = +y: %g", tex_eval(s.textures, 1, &sp, 500));
    sp.ng = v3(1, 0, 0);
    CHECK(t, tex_eval(s.textures, 1, &sp, 500) == 1.0f, "defaults at ng = +x: %g", tex_eval(s.textures, 1, &sp, 500));
    sp.ng = v3(0, 0.6f, 0.8f);                         /* spectrum: a = 0.6 */
    CHECK(t, NEAR(tex_eval(s.textures, 3, &sp, 550), 0.5, 1e-5), "spectrum at 550 nm: %g",
          tex_eval(s.textures, 3, &sp, 550));
    CHECK(t, NEAR(tex_eval(s.textures, 3, &sp, 450), 0.6 * 0.3 + 0.4 * 0.5, 1e-5), "spectrum at 450 nm: %g",
          tex_eval(s.textures, 3, &sp, 450));
    /* Scale 1 3 1 carries dir (1 1 0) to (1 3 0) (a vector, not a normal) */
    sp.ng = v3(0, 1, 0);
    CHECK(t, NEAR(tex_eval(s.textures, 4, &sp, 500), a3, 1e-6), "dir under Scale 1 3 1: a %g, want %g",
          tex_eval(s.textures, 4, &sp, 500), a3);
    scene_free(&s);
    expect_error(t, "Texture \"m\" \"float\" \"directionmix\" \"vector3 dir\" [ 0 0 0 ]", "dir",
                 "not a direction");
    if (!test_load_scene(t, &s, DM_TEXT)) return;
    render_options_default(&o);
    o.spp = test_scaled(128, 32);
    if (!test_render_tiles(t, &s, &o, 2, 4, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    for (i = 0; i < 16; i++)
        for (c = 0; c < 3; c++)
            CHECK(t, fabs(tl.mean[i][c] - DM_TILES[i][c]) < TEST_K_SIGMA * tl.se[i][c] + 0.01 * DM_TILES[i][c],
                  "directionmix: tile %d %c: specnee %.5f +- %.2g, pbrt-v4 %.5f", i, "RGB"[c],
                  tl.mean[i][c], tl.se[i][c], DM_TILES[i][c]);
}

static void test_bad_input(T *t)
{
    expect_error(t, "Material \"diffuse\" \"texture reflectance\" \"nope\"", "no texture named", "nope");
    expect_error(t, "Texture \"f\" \"float\" \"constant\"\nMaterial \"diffuse\" \"texture reflectance\" \"f\"",
                 "is a float texture", NULL);
    expect_error(t, "Texture \"m\" \"spectrum\" \"wrinkled\"", "wrinkled", "is a float texture");
    expect_error(t, "Texture \"m\" \"spectrum\" \"fbm\"", "fbm", "is a float texture");
    expect_error(t, "Texture \"m\" \"float\" \"ptex\"", "ptex", "not in the specnee subset");
    expect_error(t, "Texture \"m\" \"float\" \"fbm\" \"integer octaves\" [ -1 ]", "octaves", NULL);
    expect_error(t, "Texture \"m\" \"float\" \"wrinkled\" \"float roughness\" [ 1e39 ]", "finite", NULL);
    expect_error(t, "Texture \"m\" \"float\" \"windy\" \"integer octaves\" [ 3 ]", "octaves", "unused");
    expect_error(t, "Texture \"m\" \"float\" \"marble\"", "marble", "spectrum texture");
    expect_error(t, "Texture \"m\" \"spectrum\" \"marble\" \"integer octaves\" [ 100 ]", "octaves", NULL);
    expect_error(t, "Texture \"m\" \"spectrum\" \"marble\" \"float variation\" [ 1e39 ]", "finite", NULL);
    expect_error(t, "Texture \"m\" \"spectrum\" \"marble\" \"string mapping\" \"uv\"", "mapping", "unused");
    expect_error(t, "Texture \"d\" \"float\" \"dots\" \"texture inside\" \"zz\"", "no texture named", NULL);
    expect_error(t, "Texture \"g\" \"float\" \"constant\"\nMaterial \"dielectric\" \"texture uroughness\" \"g\" "
                 "\"float vroughness\" [ -0.1 ]", "roughness (0, -0.1) must be within [0, 1e4]", NULL);
    expect_error(t, "Texture \"g\" \"float\" \"constant\"\n"
                 "Material \"subsurface\" \"texture uroughness\" \"g\" \"texture vroughness\" \"h\"", "no texture named", NULL);
    expect_error(t, "Texture \"c\" \"spectrum\" \"constant\"\nMaterial \"conductor\" \"texture roughness\" \"c\"",
                 "is a spectrum texture", NULL);
    expect_error(t, "Texture \"c\" \"spectrum\" \"constant\"\nMaterial \"conductor\" \"texture reflectance\" \"c\" "
                 "\"spectrum k\" \"metal-Au-k\"", "either", NULL);
    expect_error(t, "Texture \"m\" \"spectrum\" \"bogus\"", "unknown class", NULL);
    expect_error(t, "Texture \"m\" \"color\" \"constant\"", "must be \"spectrum\" or \"float\"", NULL);
    expect_error(t, "Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" [ 4 ]", "3-D", NULL);
    expect_error(t, "Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" [ 3 ] \"float uscale\" [ 2 ]",
                 "uscale", "unused");
    expect_error(t, "Texture \"c\" \"float\" \"checkerboard\" \"string mapping\" \"cubic\"", "unknown mapping", NULL);
    expect_error(t, "Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"none.pfm\"", "imagemap", NULL);
    expect_error(t, "Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"sky.exr\"", "sky.exr", "cannot read the EXR file");
    expect_error(t, "Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"w.jpg\"", "PNG or PFM", NULL);
    expect_error(t, "Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"w.png\" "
                 "\"string encoding\" \"gamma 2.2\"", "gamma 2.2", "not in the specnee subset");
    expect_error(t, "Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"", "missing.png", NULL);
    expect_error(t, "Texture \"i\" \"spectrum\" \"imagemap\"", "filename", "required");
    expect_error(t, "Texture \"c\" \"float\" \"checkerboard\" \"float uscale\" [ 1e39 ]", "finite", NULL);
    expect_error(t, "Texture \"c\" \"float\" \"checkerboard\" \"float radius\" [ 1 ]", "radius", "unused");
    expect_error(t, "Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 2 0 0 ]", "within", NULL);
}

/* Planck's law, unnormalised (lambda in nm, T in K; c2 = hc/k = 1.438777e-2 m K). */
static double planck(double nm, double kelvin)
{
    double l = nm * 1e-9;
    return 1.0 / (l * l * l * l * l * (exp(1.438777e-2 / (l * kelvin)) - 1.0));
}

/* "blackbody" where a reflectance is read (a diffuse "reflectance", a spectrum
   texture's "value"): pbrt-v4's BlackbodySpectrum, Planck's law divided by its value
   at Wien's peak lambda_max = 2.897771955e-3 m K / T, the same for every use.  Its
   values lie in (0, 1], so it is a valid reflectance as it is. */
static void test_blackbody_reflectance(T *t)
{
    static const double nms[4] = { 400.0, 500.0, 580.0, 700.0 };
    Scene s;
    SurfacePoint sp = at_uv(0.5f, 0.5f);
    int k;
    if (!load(t, &s, "Material \"diffuse\" \"blackbody reflectance\" [ 5000 ]\nShape \"sphere\"\n"
                     "Texture \"b\" \"spectrum\" \"constant\" \"blackbody value\" [ 3000 ]\n"
                     "Material \"diffuse\" \"texture reflectance\" \"b\"\nShape \"sphere\"\n"))
        return;
    for (k = 0; k < 4; k++) {
        double w5 = planck(nms[k], 5000.0) / planck(2.897771955e6 / 5000.0, 5000.0);
        double w3 = planck(nms[k], 3000.0) / planck(2.897771955e6 / 3000.0, 3000.0);
        float r5 = mat_albedo_at(&s.materials[s.shapes[0].material], &sp, (float)nms[k]);
        float r3 = mat_albedo_at(&s.materials[s.shapes[1].material], &sp, (float)nms[k]);
        CHECK(t, fabs(r5 - w5) < 1e-5 * w5 + 1e-7, "5000 K reflectance at %g nm: %.7f, Planck %.7f",
              nms[k], r5, w5);
        CHECK(t, fabs(r3 - w3) < 1e-5 * w3 + 1e-7, "3000 K texture at %g nm: %.7f, Planck %.7f",
              nms[k], r3, w3);
    }
    scene_free(&s);
}

/* pbrt-v4's 3-D checkerboard ("integer dimension" 3): tex1 where floor(q_x) +
   floor(q_y) + floor(q_z) is even, q the point in the frame of the CTM at the
   Texture directive (TextureMapping3D); the point's (u, v) play no part. */
static void test_checkerboard_3d(T *t)
{
    /* CTM = Translate(0.5, 0, 0) Scale(2, 1, 1): q = ((x - 0.5) / 2, y, z) */
    static const float pts[6][4] = {
        { 0.6f, 0.2f, 0.3f, 1 },     /* q (0.05, 0.2, 0.3): 0 + 0 + 0, even */
        { 2.6f, 0.2f, 0.3f, 0 },     /* q_x 1.05: odd */
        { 2.6f, 1.2f, 0.3f, 1 },     /* 1 + 1 + 0 */
        { 2.6f, 1.2f, 1.3f, 0 },     /* 1 + 1 + 1 */
        { 0.4f, 0.2f, 0.3f, 0 },     /* q_x -0.05: floor -1, odd */
        { 1.4f, 0.2f, -0.3f, 0 },    /* q (0.45, 0.2, -0.3): 0 + 0 - 1, odd */
    };
    Scene s;
    int k;
    if (!load(t, &s, "AttributeBegin\nTranslate 0.5 0 0\nScale 2 1 1\n"
                     "Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" [ 3 ] "
                     "\"float tex1\" [ 0.9 ] \"float tex2\" [ 0.1 ]\n"
                     "Texture \"sc\" \"spectrum\" \"checkerboard\" \"integer dimension\" [ 3 ] "
                     "\"spectrum tex1\" [ 400 0.2 700 0.8 ]\n"
                     "AttributeEnd\n"))
        return;
    for (k = 0; k < 6; k++) {
        SurfacePoint sp = at_p(pts[k][0], pts[k][1], pts[k][2]);
        int even = (int)pts[k][3];
        float f, g;
        sp.u = 0.3f + 0.4f * (float)k;               /* any (u, v) */
        sp.v = 0.7f * (float)k;
        f = tex_eval(s.textures, 0, &sp, 500);
        g = tex_eval(s.textures, 1, &sp, 550);
        CHECK(t, f == (even ? 0.9f : 0.1f), "float 3-D checkerboard at (%g, %g, %g): %g", pts[k][0],
              pts[k][1], pts[k][2], f);
        CHECK(t, NEAR(g, even ? 0.5 : 0.0, 1e-5), "spectrum 3-D checkerboard at (%g, %g, %g), 550 nm: %g",
              pts[k][0], pts[k][1], pts[k][2], g);
    }
    scene_free(&s);
}

/* "string filter" "point" and Option "disabletexturefiltering": a 2 x 2 grey image
   (top row 0.1 0.7, bottom 0.4 0.9) on a square that fills an orthographic 16 x
   16 view, box pixel filter, under a white sky ("rgb L" 1 1 1) with one bounce:
   a pixel is its texel's reflectance.  With "point" (pbrt-v4's Point filter, read
   at full resolution: the option zeroes the footprint) each quadrant is one
   texel; bilinear blends them.  pbrt-v4 (commit 5f7a6068, `pbrt --spp 256 --seed
   1`, the same scene; its view mirrors x as specnee's does) gives the quadrant
   means of Y top-left, top-right, bottom-left, bottom-right 0.70013 0.10001
   0.90049 0.40000 with the option and "point" (the same without the option), and
   0.60652 0.31869 0.71886 0.45609 with "bilinear".  specnee at 64 spp: within 2 %
   of each (measured 0.4 %). */
static void test_point_filter(T *t)
{
    static const double want[2][4] = { { 0.70013, 0.10001, 0.90049, 0.40000 },
                                       { 0.60652, 0.31869, 0.71886, 0.45609 } };
    static const float grey[4] = { 0.1f, 0.7f, 0.4f, 0.9f };
    const char *pfm = test_path(t, "point_filter.pfm");
    Image q;
    int f, i, ok;
    CHECK(t, img_alloc(&q, 2, 2), "out of memory");
    for (i = 0; i < 12; i++) q.rgb[i] = grey[i / 3];
    ok = pfm_write(&q, pfm);
    img_free(&q);
    CHECK(t, ok, "cannot write %s", pfm);
    for (f = 0; f < 2; f++) {
        char text[2048];
        RenderOptions o;
        Image im;
        double m[4] = { 0, 0, 0, 0 };
        int x, y;
        snprintf(text, sizeof text, "Option \"disabletexturefiltering\" true\n"
                 "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [ -1 1 -1 1 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
                 "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
                 "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
                 "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"%s\"\n"
                 "Material \"diffuse\" \"texture reflectance\" \"t\"\n"
                 "Shape \"bilinearmesh\" \"point3 P\" [ -1 -1 0  1 -1 0  -1 1 0  1 1 0 ] "
                 "\"point2 uv\" [ 0 0  1 0  0 1  1 1 ]\n", pfm, f ? "bilinear" : "point");
        render_options_default(&o);
        o.spp = 64;
        o.seed = 1;
        o.threads = 2;
        if (!test_render_text(t, text, &o, &im)) return;
        CHECK(t, im.w == 16 && im.h == 16, "%d x %d", im.w, im.h);
        for (y = 0; y < 16; y++)
            for (x = 0; x < 16; x++) {
                const float *c = im.rgb + 3 * (y * 16 + x);
                m[(y / 8) * 2 + x / 8] += (0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]) / 64.0;
            }
        img_free(&im);
        for (i = 0; i < 4; i++)
            CHECK(t, fabs(m[i] - want[f][i]) < 0.02 * want[f][i], "%s: quadrant %d Y %.5f, pbrt-v4 %.5f",
                  f ? "bilinear" : "point", i, m[i], want[f][i]);
    }
}

const TestCase tests_texture[] = {
    { "texture_values", test_values },
    { "texture_mappings", test_mappings },
    { "texture_checkerboard_3d", test_checkerboard_3d },
    { "texture_imagemap", test_imagemap },
    { "texture_imagemap_colour", test_imagemap_colour },
    { "texture_imagemap_png", test_imagemap_png },
    { "texture_mesh_uv", test_mesh_uv },
    { "texture_ply_uv", test_ply_uv },
    { "texture_quadric_uv", test_quadric_uv },
    { "texture_sphere_object_uv", test_sphere_object_uv },
    { "texture_render_checks", test_render_checks },
    { "texture_bad_input", test_bad_input },
    { "texture_noise", test_noise },
    { "texture_noise_direct", test_noise_direct },
    { "texture_noise_diff", test_noise_diff },
    { "texture_noise_textures", test_noise_textures },
    { "texture_material_params", test_material_params },
    { "texture_conductor_against_pbrt", test_conductor_against_pbrt },
    { "texture_dots", test_dots },
    { "texture_marble", test_marble },
    { "texture_against_pbrt", test_against_pbrt },
    { "texture_directionmix", test_directionmix },
    { "texture_blackbody_reflectance", test_blackbody_reflectance },
    { "texture_point_filter", test_point_filter },
    { NULL, NULL }
};
