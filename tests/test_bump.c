/* tests/test_bump.c - bump and normal maps (bump.c: shading_differentials,
   bump_shade, bump_from_params; path.c calls bump_shade at a surface vertex).

   Checked: a displacement linear in (u, v) on a plane tilts the shading normal to
   the analytic (-dd/du |dp/dv|, -dd/dv |dp/du|, |dp/du| |dp/dv|) direction, the
   same on a bilinearmesh and inside an object instance; a constant displacement
   and a normal map of (0.5, 0.5, 1) leave the shading normal of planes and
   spheres (dn/du != 0) as it was, and the image within float rounding; a uniform
   tilted normal map gives the tilt in the frame of dp/du; the sphere's
   derivatives against finite differences of the surface; the refusals at their
   file:line; pbrt-v4's image of a scene with both maps on quads and spheres. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static const char *const BUMP_HEAD =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "Sampler \"independent\"\nPixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n";

/* Write a w x h RGB PFM (rows top first, 3 floats a texel) into the scratch
   directory; its path, or NULL (the test failed). */
static const char *write_pfm(T *t, const char *name, int w, int h, const double *rgb)
{
    Image im;
    const char *path = test_path(t, name);
    int i;
    if (!img_alloc(&im, w, h)) { test_failf(t, __FILE__, __LINE__, "out of memory"); return NULL; }
    for (i = 0; i < 3 * w * h; i++) im.rgb[i] = (float)rgb[i];
    if (!pfm_write(&im, path)) { img_free(&im); test_failf(t, __FILE__, __LINE__, "cannot write %s", path); return NULL; }
    img_free(&im);
    return path;
}

/* A 2 x 2 grey ramp: bilinear over (s, t) in [0.25, 0.75]^2 it is exactly
   0.5 + a (2 s - 0.5) + b (2 t - 0.5) (row 0 is the top: t = 1; kept positive,
   as texture.c reads negative texels as 0). */
static const char *write_ramp(T *t, double a, double b)
{
    double rgb[12];
    int x, y, c;
    for (y = 0; y < 2; y++)
        for (x = 0; x < 2; x++)
            for (c = 0; c < 3; c++) rgb[3 * (2 * y + x) + c] = 0.5 + a * x + b * (1 - y);
    return write_pfm(t, "ramp.pfm", 2, 2, rgb);
}

static int load_bump(T *t, Scene *s, const char *body)
{
    static char buf[16384];
    snprintf(buf, sizeof buf, "%s%s", BUMP_HEAD, body);
    return test_load_scene(t, s, buf);
}

/* The hit of the ray from o along d: its surface point with and without the
   material's Bump (0 when the ray misses). */
static int bumped_hit(const Scene *s, Vec3 o, Vec3 d, SurfacePoint *plain, SurfacePoint *bumped)
{
    Ray r;
    HitRecord h;
    const Material *m;
    r.o = o;
    r.d = d;
    r.tmax = INFINITY;
    if (!bvh_intersect(&s->bvh, s, &r, &h)) return 0;
    scene_surface_point(s, &r, &h, plain);
    m = &s->materials[s->shapes[plain->shape].material];
    *bumped = *plain;
    if (m->bump) bump_shade(s, m, &r, &h, plain, bumped);
    return 1;
}

static float v3_dist(Vec3 a, Vec3 b) { return v3_len(v3_sub(a, b)); }

/* A quad [-1, 1]^2 at z = 0 with uv over [0.25, 0.75]^2: dp/du = (4, 0, 0),
   dp/dv = (0, 4, 0); with d = 0.5 + a (2u - 0.5) + b (2v - 0.5), dp'/du = (4, 0, 2a),
   dp'/dv = (0, 4, 2b) and ns' = normalize(-a, -b, 2).  The same for a flat
   bilinearmesh, and for the quad in an object placed by an instance (rotated 90
   degrees about z: ns' rotated); with u running along -x, dp'/du x dp'/dv points
   down and is turned to the geometric normal's side: normalize(a, -b, 2). */
static void test_bump_linear_tilt(T *t)
{
    static const char *const quad[4] = {
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] ",
        "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 3 2 ] ",
        "ObjectBegin \"q\"\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] ",
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] ",
    };
    static const char *const uv[4] = {
        "0.25 0.25  0.75 0.25  0.75 0.75  0.25 0.75", "0.25 0.25  0.75 0.25  0.75 0.75  0.25 0.75",
        "0.25 0.25  0.75 0.25  0.75 0.75  0.25 0.75", "0.75 0.25  0.25 0.25  0.25 0.75  0.75 0.75",
    };
    const double a = 0.5, b = -0.3;
    const char *ramp = write_ramp(t, a, b);
    int k, i;
    if (!ramp) return;
    for (k = 0; k < 4; k++) {
        Scene s;
        char body[2048];
        Vec3 want = v3_norm(v3((float)-a, (float)-b, 2.0f));
        if (k == 2) want = v3(-want.y, want.x, want.z);          /* Rotate 90 0 0 1 */
        if (k == 3) want = v3(-want.x, want.y, want.z);  /* u along -x: dp'/du x dp'/dv turned to +z */
        snprintf(body, sizeof body,
                 "Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" \"%s\" \"string wrap\" \"clamp\"\n"
                 "Material \"diffuse\" \"texture displacement\" \"ramp\"\n%s"
                 "\"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "
                 "\"point2 uv\" [ %s ]\n%s",
                 ramp, quad[k], uv[k], k == 2 ? "ObjectEnd\nRotate 90 0 0 1\nObjectInstance \"q\"\n" : "");
        if (!load_bump(t, &s, body)) return;
        for (i = 0; i < 25; i++) {
            SurfacePoint sp, bp;
            Vec3 o = v3(-0.8f + 0.4f * (float)(i % 5), -0.8f + 0.4f * (float)(i / 5), 3.0f);
            if (!bumped_hit(&s, o, v3(0.01f, 0.02f, -1.0f), &sp, &bp)) {
                scene_free(&s);
                CHECK(t, 0, "quad %d: ray %d missed", k, i);
            }
            if (v3_dist(bp.ns, want) > 2e-4f) {
                scene_free(&s);
                CHECK(t, 0, "quad %d at (%g, %g): ns (%g, %g, %g), want (%g, %g, %g)", k, sp.p.x, sp.p.y,
                      bp.ns.x, bp.ns.y, bp.ns.z, want.x, want.y, want.z);
            }
            if (v3_dist(sp.ns, v3(0, 0, 1)) > 1e-6f || v3_dist(bp.ng, sp.ng) != 0.0f) {
                scene_free(&s);
                CHECK(t, 0, "quad %d: the geometric normal or the unbumped point changed", k);
            }
        }
        scene_free(&s);
    }
}

/* Render s twice: once as loaded, once with every Bump taken away; the two
   images' luminance means within rel (the paths follow the same samples, so
   only rounding of the shading frame can part them). */
static void same_image(T *t, Scene *s, double rel, const char *what)
{
    RenderOptions o;
    Image a, b;
    RenderStats st;
    Error err;
    double ya = 0, yb = 0;
    Bump *saved[16];
    int i;
    render_options_default(&o);
    o.spp = 4;
    o.seed = 7;
    o.threads = 1;
    if (!render(s, &o, &a, &st, &err)) { test_failf(t, __FILE__, __LINE__, "%s", err.msg); return; }
    for (i = 0; i < s->n_materials && i < 16; i++) { saved[i] = s->materials[i].bump; s->materials[i].bump = NULL; }
    if (!render(s, &o, &b, &st, &err)) { img_free(&a); test_failf(t, __FILE__, __LINE__, "%s", err.msg); return; }
    for (i = 0; i < s->n_materials && i < 16; i++) s->materials[i].bump = saved[i];
    for (i = 0; i < a.w * a.h; i++) {
        ya += 0.2126 * a.rgb[3 * i] + 0.7152 * a.rgb[3 * i + 1] + 0.0722 * a.rgb[3 * i + 2];
        yb += 0.2126 * b.rgb[3 * i] + 0.7152 * b.rgb[3 * i + 1] + 0.0722 * b.rgb[3 * i + 2];
    }
    img_free(&a);
    img_free(&b);
    CHECK(t, fabs(ya - yb) <= rel * yb, "%s: image mean %.8g with the map, %.8g without", what, ya, yb);
}

/* The shading normal of every hit on s along a grid of rays down -z is the
   unbumped one within eps. */
static void same_normals(T *t, const Scene *s, float eps, const char *what)
{
    int i;
    for (i = 0; i < 400; i++) {
        SurfacePoint sp, bp;
        Vec3 o = v3(-1.9f + 0.2f * (float)(i % 20), -1.9f + 0.2f * (float)(i / 20), 4.0f);
        if (!bumped_hit(s, o, v3(0.013f, 0.007f, -1.0f), &sp, &bp)) continue;
        CHECK(t, v3_dist(bp.ns, sp.ns) <= eps, "%s at (%g, %g, %g): ns (%g, %g, %g), unbumped (%g, %g, %g)",
              what, sp.p.x, sp.p.y, sp.p.z, bp.ns.x, bp.ns.y, bp.ns.z, sp.ns.x, sp.ns.y, sp.ns.z);
    }
}

/* Scenes whose map must not change the shading normal: a quad, a sphere (where
   d dn/du is not 0: dp'/du = (1 + d / r) dp/du keeps its direction), a cut sphere,
   a cylinder and a disk (each under a rotation and a uniform scale: a
   non-uniform one bends the normal field, and then a constant displacement does
   turn the shading normal, in pbrt-v4 too), on a backdrop. */
static const char *const NEUTRAL_SHAPES =
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -2 0 0  0 0 0  0 2 0  -2 2 0 ]\n"
    "AttributeBegin\nTranslate 1 1 0\nRotate 30 1 1 0\nShape \"sphere\" \"float radius\" [ 0.8 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -1 -1 0\nScale 1.2 1.2 1.2\nRotate 50 0 1 1\nShape \"sphere\" \"float radius\" [ 0.8 ] \"float zmax\" [ 0.5 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate 1 -1 0\nRotate 70 1 0 0\nShape \"cylinder\" \"float radius\" [ 0.6 ]\n"
    "Translate 0 0 1\nShape \"disk\" \"float radius\" [ 0.6 ]\nAttributeEnd\n";

static void test_bump_constant_neutral(T *t)
{
    Scene s;
    char body[4096];
    snprintf(body, sizeof body,
             "LightSource \"distant\" \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 0 0 0 ]\n"
             "Material \"diffuse\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 -2  4 -4 -2  4 4 -2  -4 4 -2 ]\n"
             "Material \"diffuse\" \"float displacement\" [ 0.3 ]\n%s", NEUTRAL_SHAPES);
    if (!load_bump(t, &s, body)) return;
    same_normals(t, &s, 2e-5f, "constant displacement");
    if (!t->failed) same_image(t, &s, 1e-4, "constant displacement");
    scene_free(&s);
}

static void test_bump_flat_normalmap_neutral(T *t)
{
    static const double flat[3] = { 0.5, 0.5, 1.0 };
    const char *nm = write_pfm(t, "flat.pfm", 1, 1, flat);
    Scene s;
    char body[4096];
    if (!nm) return;
    snprintf(body, sizeof body,
             "LightSource \"distant\" \"point3 from\" [ 1 0.5 4 ] \"point3 to\" [ 0 0 0 ]\n"
             "Material \"diffuse\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 -2  4 -4 -2  4 4 -2  -4 4 -2 ]\n"
             "Material \"conductor\" \"float roughness\" [ 0.2 ] \"string normalmap\" \"%s\"\n%s", nm, NEUTRAL_SHAPES);
    if (!load_bump(t, &s, body)) return;
    same_normals(t, &s, 2e-6f, "normal map (0.5, 0.5, 1)");
    if (!t->failed) same_image(t, &s, 1e-4, "normal map (0.5, 0.5, 1)");
    scene_free(&s);
}

/* An 8-bit PNG normal map is read linearly, as pbrt-v4 reads it: (128, 128, 255)
   is n = (1/255, 1/255, 1) before normalising, 0.3 degrees off (the sRGB curve
   would make it (-0.57, -0.57, 1), 39 degrees). */
static void test_bump_png_linear(T *t)
{
    static const unsigned char px[3] = { 128, 128, 255 };
    const char *path = test_path(t, "flat.png");
    Scene s;
    char body[2048];
    int i;
    CHECK(t, png_write_rgb8(path, 1, 1, px), "cannot write %s", path);
    snprintf(body, sizeof body, "Material \"diffuse\" \"string normalmap\" \"%s\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
             "\"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n", path);
    if (!load_bump(t, &s, body)) return;
    for (i = 0; i < 4; i++) {
        SurfacePoint sp, bp;
        Vec3 want = v3_norm(v3(1.0f / 255.0f, 1.0f / 255.0f, 1.0f));
        Vec3 o = v3(-0.5f + (float)(i % 2), -0.5f + (float)(i / 2), 3.0f);
        int hit = bumped_hit(&s, o, v3(0.0f, 0.0f, -1.0f), &sp, &bp);
        if (!hit || v3_dist(bp.ns, want) > 1e-5f) {
            scene_free(&s);
            CHECK(t, 0, "at (%g, %g): ns (%g, %g, %g), want (%g, %g, %g)", o.x, o.y, bp.ns.x, bp.ns.y,
                  bp.ns.z, want.x, want.y, want.z);
        }
    }
    scene_free(&s);
}

/* A displacement of 0 leaves dp/du x dp/dv along the shading normal the shape
   had: twisted bilinear patches (no "uv"; "uv" reversed in u, so that dp/ds x
   dp/dt is turned; "N", rotated from the patch's normal), a triangle mesh with
   "N" (the frame ss, ts around ns), a flat patch with "N". */
static void test_bump_zero_neutral(T *t)
{
    Scene s;
    if (!load_bump(t, &s,
                   "Material \"diffuse\" \"float displacement\" [ 0 ]\n"
                   "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] "
                   "\"point3 P\" [ -2 0 0  0 0 0.6  -2 2 0.5  0 2 -0.3 ]\n"
                   "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] "
                   "\"point3 P\" [ 0 0 0  2 0 -0.6  0 2 0.5  2 2 0.3 ] \"point2 uv\" [ 1 0  0 0  1 1  0 1 ]\n"
                   "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] "
                   "\"point3 P\" [ -2 -2 0  0 -2 0.4  -2 0 0.2  0 0 -0.5 ] "
                   "\"normal N\" [ 0.2 0 1  0 0.3 1  -0.2 0.1 1  0.1 -0.2 1 ]\n"
                   "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
                   "\"point3 P\" [ 0 -2 0  1 -2 0  1 0 0  0 0 0 ] \"point2 uv\" [ 0 0  1 0.2  0.9 1  0 1 ] "
                   "\"normal N\" [ 0.3 0 1  0 0.3 1  -0.2 0.1 1  0.1 -0.2 1 ]\n"
                   "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] "
                   "\"point3 P\" [ 1 -2 0  2 -2 0  1 0 0  2 0 0 ] "
                   "\"normal N\" [ 0.3 0 1  0 0.3 1  -0.2 0.1 1  0.1 -0.2 1 ]\n"))
        return;
    same_normals(t, &s, 2e-5f, "displacement 0");
    scene_free(&s);
}

/* A normal map of two texels, n = (sin th, 0, cos th) in its top row and
   (-sin th, 0, cos th) in its bottom one (rgb = (n + 1) / 2), read at v = 0.75
   (the top row's centre: pbrt-v4 looks up (u, 1 - v)) and at v = 0.25: the world
   normal is n_x x + n_z ns with x = dp/du / |dp/du|, along +x for the quad's uv
   running with x, along +y when u runs along y (uv turned), and unchanged by
   vertex normals that are all +z. */
static void test_bump_normalmap_tilt(T *t)
{
    const double th = 0.4;
    double rgb[6];
    const char *nm;
    static const char *const uv[2] = { "0 0  1 0  1 1  0 1", "0 0  0 1  1 1  1 0" };
    int k, i;
    rgb[0] = (sin(th) + 1.0) / 2.0; rgb[1] = 0.5; rgb[2] = (cos(th) + 1.0) / 2.0;
    rgb[3] = (-sin(th) + 1.0) / 2.0; rgb[4] = 0.5; rgb[5] = rgb[2];
    nm = write_pfm(t, "tilt.pfm", 1, 2, rgb);
    if (!nm) return;
    for (k = 0; k < 2; k++) {
        Scene s;
        char body[2048];
        snprintf(body, sizeof body,
                 "Material \"diffuse\" \"string normalmap\" \"%s\"\n"
                 "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
                 "\"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] \"point2 uv\" [ %s ] "
                 "\"normal N\" [ 0 0 1  0 0 1  0 0 1  0 0 1 ]\n", nm, uv[k]);
        if (!load_bump(t, &s, body)) return;
        for (i = 0; i < 6; i++) {
            SurfacePoint sp, bp;
            float across = -0.6f + 0.6f * (float)(i % 3), side = i < 3 ? 0.5f : -0.5f;  /* v = 0.75, 0.25 */
            float tilt = (float)sin(th) * (i < 3 ? 1.0f : -1.0f);
            Vec3 o = k == 0 ? v3(across, side, 3.0f) : v3(side, across, 3.0f);
            Vec3 want = k == 0 ? v3(tilt, 0.0f, (float)cos(th)) : v3(0.0f, tilt, (float)cos(th));
            int hit = bumped_hit(&s, o, v3(0.0f, 0.0f, -1.0f), &sp, &bp);
            if (!hit || v3_dist(bp.ns, want) > 1e-5f) {
                scene_free(&s);
                CHECK(t, 0, "uv %d at (%g, %g): ns (%g, %g, %g), want (%g, %g, %g)", k, o.x, o.y,
                      bp.ns.x, bp.ns.y, bp.ns.z, want.x, want.y, want.z);
            }
        }
        scene_free(&s);
    }
}

/* The sphere's dp/du, dp/dv against central differences of the surface in its
   (u, v), and dn/du = dp/du / r (a sphere's normal is p / r), at random hits on a
   rotated sphere of radius 0.8 (pbrt-v4: u = phi / 2 pi, v = 1 - theta / pi). */
static void test_bump_sphere_derivatives(T *t)
{
    Scene s;
    Rng rg;
    int i;
    if (!load_bump(t, &s, "Material \"diffuse\" \"float displacement\" [ 0 ]\n"
                          "Translate 0.2 0.1 0\nRotate 40 1 2 0\nShape \"sphere\" \"float radius\" [ 0.8 ]\n"))
        return;
    rng_seed(&rg, 11, 0);
    for (i = 0; i < 200; i++) {
        float q[2];
        Ray r;
        HitRecord h;
        SurfacePoint sp;
        ShadingDiff d;
        Vec3 c = v3(0.2f, 0.1f, 0.0f), e, f;
        const float R = 0.8f, pi = PI_F;
        float phi, th, eps = 1e-3f;
        rng_fill(&rg, q, 2);
        r.o = v3(1.4f * q[0] - 0.5f, 1.4f * q[1] - 0.6f, 3.0f);
        r.d = v3(0, 0, -1);
        r.tmax = INFINITY;
        if (!bvh_intersect(&s.bvh, &s, &r, &h)) continue;
        scene_surface_point(&s, &r, &h, &sp);
        shading_differentials(&s, &r, &h, &sp, &d);
        phi = 2.0f * pi * sp.u;
        th = pi * (1.0f - sp.v);
        if (th < 0.2f || th > pi - 0.2f) continue;               /* near the poles */
        {   /* the world point at object (phi, theta): the hit's point rotated back */
            Xform m = s.shapes[sp.shape].q.world_from_obj;
            Vec3 pu0 = xf_point(&m, v3(R * sinf(th) * cosf(phi - 2.0f * pi * eps), R * sinf(th) * sinf(phi - 2.0f * pi * eps), R * cosf(th)));
            Vec3 pu1 = xf_point(&m, v3(R * sinf(th) * cosf(phi + 2.0f * pi * eps), R * sinf(th) * sinf(phi + 2.0f * pi * eps), R * cosf(th)));
            Vec3 pv0 = xf_point(&m, v3(R * sinf(th + pi * eps) * cosf(phi), R * sinf(th + pi * eps) * sinf(phi), R * cosf(th + pi * eps)));
            Vec3 pv1 = xf_point(&m, v3(R * sinf(th - pi * eps) * cosf(phi), R * sinf(th - pi * eps) * sinf(phi), R * cosf(th - pi * eps)));
            e = v3_mul(v3_sub(pu1, pu0), 1.0f / (2.0f * eps));
            f = v3_mul(v3_sub(pv1, pv0), 1.0f / (2.0f * eps));
        }
        if (v3_dist(d.dpdu, e) > 2e-3f * v3_len(e) + 1e-4f || v3_dist(d.dpdv, f) > 2e-3f * v3_len(f) + 1e-4f ||
            v3_dist(d.dndu, v3_mul(d.dpdu, 1.0f / R)) > 1e-4f || v3_dist(d.dndv, v3_mul(d.dpdv, 1.0f / R)) > 1e-4f ||
            v3_dist(sp.p, v3_add(c, v3_mul(sp.ng, R))) > 1e-5f) {
            scene_free(&s);
            CHECK(t, 0, "hit %d (u %g, v %g): dp/du (%g, %g, %g) vs (%g, %g, %g), dp/dv (%g, %g, %g) vs "
                  "(%g, %g, %g)", i, sp.u, sp.v, d.dpdu.x, d.dpdu.y, d.dpdu.z, e.x, e.y, e.z,
                  d.dpdv.x, d.dpdv.y, d.dpdv.z, f.x, f.y, f.z);
        }
    }
    scene_free(&s);
}

static void expect_error(T *t, const char *body, const char *want)
{
    test_refused(t, BUMP_HEAD, body, "bump.pbrt", want);
}

/* Refusals at their file:line: a missing normal map, one in a format specnee does
   not read, a displacement naming a spectrum texture or no texture; mix and
   interface refuse a displacement, which pbrt-v4 does not read there (their
   "string normalmap" is read and ignored: test_mix.c). */
static void test_bump_errors(T *t)
{
    expect_error(t, "Material \"diffuse\" \"string normalmap\" \"nothere.png\"\n",
                 "bump.pbrt:8: Material \"diffuse\": \"string normalmap\" \"nothere.png\": ");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"m\" \"string type\" \"conductor\" \"string normalmap\" \"n.tga\"\n",
                 "bump.pbrt:8: MakeNamedMaterial \"m\": type \"conductor\": \"string normalmap\" \"n.tga\": specnee reads "
                 "normal maps as PNG, PFM or EXR");
    if (t->failed) return;
    expect_error(t, "Texture \"k\" \"spectrum\" \"constant\"\n"
                 "Material \"coateddiffuse\" \"texture displacement\" \"k\"\n",
                 "bump.pbrt:9: \"texture displacement\": \"k\" is a spectrum texture; a float one is needed here");
    if (t->failed) return;
    expect_error(t, "Material \"dielectric\" \"texture displacement\" \"nothere\"\n",
                 "bump.pbrt:8: \"texture displacement\": no texture named \"nothere\"");
    if (t->failed) return;
    expect_error(t, "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                 "Material \"mix\" \"string materials\" [ \"a\" \"a\" ] \"float displacement\" [ 1 ]\n",
                 "bump.pbrt:9: \"float displacement\": unused parameter");
    if (t->failed) return;
    expect_error(t, "Material \"interface\" \"float displacement\" [ 1 ]\n",
                 "bump.pbrt:8: \"float displacement\": unused parameter");
}

/* pbrt-v4 (mmp/pbrt-v4 commit 5f7a6068, the independent sampler, 32 x 32, `pbrt
   --seed S --spp 1024` (scene a) or `--nthreads 1 --seed S --spp 512` (scene b)
   for S = 1..8) rendered BUMP_HEAD + BUMP_SUN + a grey backdrop + the shapes of
   BUMP_SCENE below.  ramp.pfm is 2 x 1 (0, 1), nmap.pfm 4 x 4 normals 20 degrees
   off +z (nmap_texels).  (a) In the four corners (world x > 0 appears on the
   left) a quad with a linear displacement (0.6 x the ramp, uv [0.25, 0.75]^2), a
   quad with vertex normals and the normal map, a sphere with a displacement linear
   in u (d = u) and a sphere with the normal map.  (b) A twisted bilinear patch
   with "uv" and "N" and the quad's displacement, a rough conductor cylinder with
   d = u / 2, a disk with the normal map, and the displaced quad in an object
   placed by a rotated instance beside a cut sphere (zmin, phimax) with d = u / 2.
   Luminance of the image and of its 2 x 2 quadrants (top left first): mean over
   the seeds and its standard error.  Without the maps pbrt-v4's quadrants read
   (a) 0.5720, 0.5503, 0.2870, 0.2946 and (b) 0.2936, 0.5758, 0.3390, 0.3626 (512
   spp): the maps move them by (a) 0.7, 27, 1 and 5 % and (b) 3, 0.2, 13 and 1 %.
   specnee is accepted within 5 standard errors + 1 %.  Strong tilts are held by
   shading_tilt_against_pbrt below. */
static const double PBRT_BUMP_Y[2][5][2] = {
    { { 0.383177, 2.1e-05 },
      { 0.567983, 7.1e-05 }, { 0.401824, 3.4e-05 }, { 0.284171, 4.5e-05 }, { 0.278730, 4.3e-05 } },
    { { 0.378836, 5.6e-05 },
      { 0.284834, 6.8e-05 }, { 0.576990, 0.0001 }, { 0.294958, 8.3e-05 }, { 0.358565, 8e-05 } },
};

static const char *const BUMP_SUN =
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 2 1 3 ] \"point3 to\" [ 0 0 0 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -4 -4 -1  4 -4 -1  4 4 -1  -4 4 -1 ]\n";

/* The shapes of the two scenes: printf formats of the ramp's path (twice) and the
   normal map's. */
static const char *const BUMP_SCENE[2] = {
    "Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" \"%1$s\" \"string wrap\" \"clamp\" \"float scale\" [ 0.6 ]\n"
    "Texture \"ramps\" \"float\" \"imagemap\" \"string filename\" \"%1$s\" \"string wrap\" \"clamp\" \"float scale\" [ 1 ] "
    "\"float uscale\" [ 0.5 ] \"float udelta\" [ 0.25 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ] \"texture displacement\" \"ramp\"\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1.7 0.1 0  -0.1 0.1 0  -0.1 1.7 0  -1.7 1.7 0 ] "
    "\"point2 uv\" [ 0.25 0.25  0.75 0.25  0.75 0.75  0.25 0.75 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ] \"string normalmap\" \"%2$s\"\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ 0.1 0.1 0  1.7 0.1 0  1.7 1.7 0  0.1 1.7 0 ] "
    "\"point2 uv\" [ 0 0  1 0  1 1  0 1 ] \"normal N\" [ -0.2 -0.2 1  0.2 -0.2 1  0.2 0.2 1  -0.2 0.2 1 ]\n"
    "AttributeBegin\nTranslate -0.9 -0.9 0\nRotate -90 1 0 0\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"texture displacement\" \"ramps\"\n"
    "Shape \"sphere\" \"float radius\" [ 0.75 ]\nAttributeEnd\n"
    "AttributeBegin\nTranslate 0.9 -0.9 0\nRotate -90 1 0 0\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.3 0.5 0.8 ] \"string normalmap\" \"%2$s\"\n"
    "Shape \"sphere\" \"float radius\" [ 0.75 ]\nAttributeEnd\n",
    "Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" \"%1$s\" \"string wrap\" \"clamp\" \"float scale\" [ 0.6 ]\n"
    "Texture \"ramps\" \"float\" \"imagemap\" \"string filename\" \"%1$s\" \"string wrap\" \"clamp\" \"float scale\" [ 0.5 ] "
    "\"float uscale\" [ 0.5 ] \"float udelta\" [ 0.25 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ] \"texture displacement\" \"ramp\"\n"
    "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] \"point3 P\" [ -1.7 0.1 0.3  -0.1 0.1 -0.3  -1.7 1.7 -0.2  -0.1 1.7 0.4 ] "
    "\"point2 uv\" [ 0.25 0.25  0.75 0.3  0.3 0.75  0.7 0.7 ] \"normal N\" [ 0.2 0 1  0 0.2 1  -0.1 0.1 1  0.1 -0.2 1 ]\n"
    "AttributeBegin\nTranslate 0.9 0.9 0\nRotate -90 1 0 0\n"
    "Material \"conductor\" \"float roughness\" [ 0.3 ] \"texture displacement\" \"ramps\"\n"
    "Shape \"cylinder\" \"float radius\" [ 0.7 ] \"float zmin\" [ -0.8 ] \"float zmax\" [ 0.8 ] \"float phimax\" [ 360 ]\n"
    "AttributeEnd\nAttributeBegin\nTranslate -0.9 -0.9 0\nRotate 20 0 1 0\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.5 0.3 ] \"string normalmap\" \"%2$s\"\n"
    "Shape \"disk\" \"float radius\" [ 0.8 ] \"float innerradius\" [ 0.1 ]\nAttributeEnd\n"
    "ObjectBegin \"q\"\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.3 0.5 0.8 ] \"texture displacement\" \"ramp\"\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -0.8 -0.8 0  0.8 -0.8 0  0.8 0.8 0  -0.8 0.8 0 ] "
    "\"point2 uv\" [ 0.25 0.25  0.75 0.25  0.75 0.75  0.25 0.75 ]\nObjectEnd\n"
    "AttributeBegin\nTranslate 0.9 -0.9 0\nRotate 60 0 0 1\nRotate 20 1 0 0\nObjectInstance \"q\"\nAttributeEnd\n"
    "AttributeBegin\nTranslate 0.9 -0.9 0.4\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.3 ] \"texture displacement\" \"ramps\"\n"
    "Shape \"sphere\" \"float radius\" [ 0.4 ] \"float zmin\" [ -0.1 ] \"float phimax\" [ 300 ]\nAttributeEnd\n",
};

/* nmap.pfm's normals as rgb = (n + 1) / 2, rows top first: texel (x, y) is tilted
   0.35 rad from +z towards azimuth (4 x + y) 0.37 2 pi. */
static void nmap_texels(double *rgb)
{
    int x, y;
    for (y = 0; y < 4; y++)
        for (x = 0; x < 4; x++) {
            double ph = (x * 4 + y) * 2.0 * SPECNEE_PI * 0.37, *c = rgb + 3 * (4 * y + x);
            c[0] = (sin(0.35) * cos(ph) + 1.0) / 2.0;
            c[1] = (sin(0.35) * sin(ph) + 1.0) / 2.0;
            c[2] = (cos(0.35) + 1.0) / 2.0;
        }
}

/* Scene j's shapes with the paths filled in (BUMP_SCENE's %1$s and %2$s). */
static void bump_scene_text(int j, const char *ramp, const char *nmap, char *out, size_t n)
{
    const char *f = BUMP_SCENE[j];
    size_t k = 0;
    while (*f && k + 1 < n) {
        if (f[0] == '%' && (f[1] == '1' || f[1] == '2') && f[2] == '$' && f[3] == 's') {
            const char *v = f[1] == '1' ? ramp : nmap;
            while (*v && k + 1 < n) out[k++] = *v++;
            f += 4;
        } else {
            out[k++] = *f++;
        }
    }
    out[k] = '\0';
}

static void test_bump_against_pbrt(T *t)
{
    static const double ramp[6] = { 0, 0, 0, 1, 1, 1 };
    double nrgb[48];
    const char *rp, *np;
    char rpath[1024], shapes[8192], body[12288];
    int j;
    nmap_texels(nrgb);
    rp = write_pfm(t, "ramp1.pfm", 2, 1, ramp);
    if (!rp) return;
    snprintf(rpath, sizeof rpath, "%s", rp);
    np = write_pfm(t, "nmap.pfm", 4, 4, nrgb);
    if (!np) return;
    for (j = 0; j < 2; j++) {
        Scene s;
        char what[8];
        bump_scene_text(j, rpath, np, shapes, sizeof shapes);
        snprintf(body, sizeof body, "%s%s", BUMP_SUN, shapes);
        if (!load_bump(t, &s, body)) return;
        snprintf(what, sizeof what, "scene %c", 'a' + j);
        test_scene_against_pbrt_y(t, &s, test_scaled(64, 16), 5, PBRT_BUMP_Y[j], 1e-2, what);
        scene_free(&s);
        if (t->failed) return;
    }
}

/* A quad whose vertex normals lean 43 degrees from its geometric normal, over a lit
   grey floor.  As in pbrt-v4, no BSDF looks at the geometric normal (docs/
   conventions.md §6): a diffuse sample on the shading normal's side that points
   below the quad's plane goes on and may find the lit floor.  A BSDF that drops such
   samples renders this 2 % darker (3 % in the bottom-left quadrant).  pbrt-v4 (mmp/
   pbrt-v4 5f7a6068, `pbrt --seed S --spp 1024` for S = 1..4, 32 x 32) rendered
   SHADING_TILT; luminance of the image and its quadrants (top left first), mean over
   the seeds and its standard error. */
static const char *const SHADING_TILT =
    "LookAt 0 -2.5 4  0 0 0  0 0 1\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 -1 3 ] \"point3 to\" [ 0 0 0 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -5 -5 -1  5 -5 -1  5 5 -1  -5 5 -1 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "
    "\"normal N\" [ 0.682 0 0.731  0.682 0 0.731  0.682 0 0.731  0.682 0 0.731 ]\n";
static const double PBRT_TILT_Y[5][2] = {
    { 0.533802, 2.4e-05 }, { 0.522207, 6e-05 }, { 0.515813, 5.9e-05 }, { 0.558195, 9.8e-05 }, { 0.538995, 0.00015 },
};

static void test_shading_tilt_against_pbrt(T *t)
{
    test_against_pbrt_y(t, SHADING_TILT, 3, PBRT_TILT_Y, 5e-3, "tilt");
}

/* An anisotropic rough conductor (u 0.03, v 0.4) with a bump map: its frame's s
   axis is the bumped dp/du, as pbrt-v4's BumpMap hands it to the BSDF.  The quad
   (3 x 3, rotated 30 degrees about z, "uv" [0.25, 0.75]^2) is displaced by 1.5 x
   the ramp (0.5 + (2s - 0.5) + (2t - 0.5)): slopes of 0.5 along both dp/du and
   dp/dv, and a point light where the bumped normal mirrors the camera.  The
   unbumped dp/du made tangent to the bumped normal would turn the frame by about
   10 degrees: quadrants 0.0096, 0.0644, 0.1069, 0.0099 instead.  pbrt-v4 (mmp/
   pbrt-v4 5f7a6068, `pbrt --seed S --spp 1024`, S = 1..4, 32 x 32, volpath)
   rendered it; luminance of the image and its quadrants (top left first), mean over
   the seeds and its standard error. */
static const double PBRT_BUMP_ANISO_Y[5][2] = {
    { 0.047595, 3.2e-06 }, { 0.007482, 3.3e-06 }, { 0.069964, 8.3e-06 }, { 0.105423, 7.4e-06 }, { 0.007509, 2.1e-06 },
};

static void test_bump_anisotropic_frame_against_pbrt(T *t)
{
    static char text[4096];
    const char *ramp = write_ramp(t, 1.0, 1.0);
    if (!ramp) return;
    snprintf(text, sizeof text,
             "LookAt 0 -3 3  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
             "Integrator \"volpath\" \"integer maxdepth\" [ 5 ]\nWorldBegin\n"
             "LightSource \"point\" \"point3 from\" [ -0.58 -0.75 1.76 ] \"float scale\" [ 2 ]\n"
             "Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" \"%s\" \"string wrap\" \"clamp\" "
             "\"float scale\" [ 1.5 ]\n"
             "Material \"conductor\" \"float uroughness\" [ 0.03 ] \"float vroughness\" [ 0.4 ] "
             "\"bool remaproughness\" false \"texture displacement\" \"ramp\"\n"
             "AttributeBegin\nRotate 30 0 0 1\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1.5 -1.5 0  1.5 -1.5 0  "
             "1.5 1.5 0  -1.5 1.5 0 ] \"point2 uv\" [ 0.25 0.25  0.75 0.25  0.75 0.75  0.25 0.75 ]\n"
             "AttributeEnd\n", ramp);
    test_against_pbrt_y(t, text, 3, PBRT_BUMP_ANISO_Y, 1e-2, "bumped anisotropic conductor");
}

const TestCase tests_bump[] = {
    { "bump_anisotropic_frame_against_pbrt", test_bump_anisotropic_frame_against_pbrt },
    { "bump_linear_tilt", test_bump_linear_tilt },
    { "bump_constant_neutral", test_bump_constant_neutral },
    { "bump_flat_normalmap_neutral", test_bump_flat_normalmap_neutral },
    { "bump_png_linear", test_bump_png_linear },
    { "bump_zero_neutral", test_bump_zero_neutral },
    { "bump_normalmap_tilt", test_bump_normalmap_tilt },
    { "bump_sphere_derivatives", test_bump_sphere_derivatives },
    { "bump_errors", test_bump_errors },
    { "bump_against_pbrt", test_bump_against_pbrt },
    { "shading_tilt_against_pbrt", test_shading_tilt_against_pbrt },
    { NULL, NULL }
};
