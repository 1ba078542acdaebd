/* tests/test_instance.c - object instancing (instance.c, bvh.c's second level) and
   pbrt-v4's Attribute directive (scene.c).

   An instanced scene is checked against the same geometry written out directly
   (hit for hit: t, point, normals, (u, v), shape; and image for image), against
   analytic ray/ellipsoid and ray/triangle answers under translate, rotate and
   non-uniform scale, for the closest-hit tie rule between coincident instances
   (also twenty of them met largest id first, and a farther instance of smaller id
   met last), and against a frozen pbrt-v4 image.  Every refusal is checked by its message and
   line.  Attribute: a directive's own parameter wins over the newest Attribute,
   which wins over older ones, and AttributeEnd drops them (pbrt-v4's
   ParameterDictionary order). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

#define NAME "t.pbrt"

/* Load must fail with "t.pbrt:LINE: ..." containing k1. */
static void expect_reject(T *t, const char *text, int line, const char *k1)
{
    test_rejected_at(t, text, line, k1, NULL);
}

/* ---- the same geometry, instanced and written out ---------------------------- */
#define HEAD \
    "LookAt 0 1.5 6  0 0.5 0  0 1 0\n" \
    "Camera \"perspective\" \"float fov\" 45\n" \
    "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 24\n" \
    "WorldBegin\n" \
    "LightSource \"distant\" \"point3 from\" [ 1 3 2 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 2 2 2 ]\n" \
    "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 4\n" \
    "  \"rgb tex1\" [ 0.9 0.9 0.2 ] \"rgb tex2\" [ 0.1 0.2 0.7 ]\n" \
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ]\n"
/* the object: a textured sphere and quad (uv and vertex normals), a metal disk */
#define THING \
    " Material \"diffuse\" \"texture reflectance\" \"checks\"\n" \
    " Translate 0 0.5 0\n" \
    " Shape \"sphere\" \"float radius\" 0.5\n" \
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n" \
    "  \"point3 P\" [ -0.6 -0.5 0.6  0.6 -0.5 0.6  0.6 0.6 0.6  -0.6 0.6 0.6 ]\n" \
    "  \"normal N\" [ -0.3 0 1  0.3 0 1  0.3 0.2 1  -0.3 0.2 1 ]\n" \
    "  \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n" \
    " Material \"conductor\"\n" \
    " Translate 0 0.6 0\n" \
    " Rotate -90 1 0 0\n" \
    " Shape \"disk\" \"float radius\" 0.4\n"
/* the three placements: plain, rotated with a non-uniform scale, mirrored */
static const char *const placements[3] = {
    "Translate -1.5 0 0\n",
    "Translate 1.4 0 0.3\nRotate 35 0 1 0\nScale 1.3 1.6 0.6\n",
    "Translate 0 0 -1.5\nScale -1 0.8 1\n"
};

static void scene_text(char *buf, size_t cap, int instanced)
{
    size_t n = (size_t)snprintf(buf, cap, "%s", HEAD);
    int k;
    if (instanced) n += (size_t)snprintf(buf + n, cap - n, "ObjectBegin \"thing\"\n%sObjectEnd\n", THING);
    for (k = 0; k < 3; k++)
        n += (size_t)snprintf(buf + n, cap - n, "AttributeBegin\n%s%sAttributeEnd\n", placements[k],
                              instanced ? "ObjectInstance \"thing\"\n" : THING);
}

static float rel(float a, float b)
{
    return fabsf(a - b) / (fabsf(a) + fabsf(b) + 1e-6f);
}

/* The same material (each written-out copy has its own Material record). */
static int same_material(const Scene *a, int sa, const Scene *b, int sb)
{
    const Material *ma = &a->materials[a->shapes[sa].material];
    const Material *mb = &b->materials[b->shapes[sb].material];
    return ma->type == mb->type && (ma->reflectance_tex > 0) == (mb->reflectance_tex > 0) &&
           albedo_eval(&ma->reflectance, 550.0f) == albedo_eval(&mb->reflectance, 550.0f);
}

/* Random rays from the camera's side at the three objects: every hit of the
   instanced scene is the written-out scene's hit, to float rounding. */
static void test_instance_hits_written_out(T *t)
{
    static char ta[8192], tb[8192];
    Scene a, b;
    Rng rng;
    int i, hits = 0, other = 0, n = 4000;
    scene_text(ta, sizeof ta, 1);
    scene_text(tb, sizeof tb, 0);
    if (!test_load_scene(t, &a, ta)) return;
    if (!test_load_scene(t, &b, tb)) { scene_free(&a); return; }
    CHECK(t, a.n_instances == 3 && a.n_objects == 1 && b.n_instances == 0, "%d instances", a.n_instances);
    CHECK(t, a.n_tris == 2 + 2 && b.n_tris == 2 + 3 * 2, "geometry copied: %d triangles", a.n_tris);
    rng_seed(&rng, 36, 0);
    for (i = 0; i < n; i++) {
        Ray r;
        HitRecord ha, hb;
        SurfacePoint pa, pb;
        Vec3 u = rng_vec3(&rng);
        float sign;
        int fa, fb;
        r.o = v3(-3.0f + 6.0f * u.x, 0.2f + 2.5f * u.y, 5.0f);
        u = rng_vec3(&rng);
        r.d = v3_norm(v3_sub(v3(-2.5f + 5.0f * u.x, 1.2f * u.y, -2.0f + 2.5f * u.z), r.o));
        r.tmax = INFINITY;
        fa = bvh_intersect(&a.bvh, &a, &r, &ha);
        fb = bvh_intersect(&b.bvh, &b, &r, &hb);
        CHECK(t, fa == fb, "ray %d: hit %d instanced, %d written out", i, fa, fb);
        CHECK(t, fa == bvh_occluded(&a.bvh, &a, &r), "ray %d: occluded disagrees", i);
        if (!fa) continue;
        scene_surface_point(&a, &r, &ha, &pa);
        scene_surface_point(&b, &r, &hb, &pb);
        /* a grazing hit on an edge may land on the neighbour, rarely */
        if (!same_material(&a, pa.shape, &b, pb.shape) || rel(ha.t, hb.t) > 1e-4f) {
            other++;
            continue;
        }
        hits++;
        CHECK(t, v3_len(v3_sub(pa.p, pb.p)) < 1e-4f, "ray %d: p differs", i);
        /* pbrt-v4 orients a quadric written out under a mirroring CTM by its
           handedness flag, but a TransformedPrimitive carries the object's normal by
           M^-T alone: under the mirroring placement 2 the two are opposite (as in
           pbrt-v4); a triangle's normal comes out the same either way */
        sign = ha.inst == 2 && a.shapes[pa.shape].type != SHAPE_MESH ? -1.0f : 1.0f;
        CHECK(t, sign * v3_dot(pa.ng, pb.ng) > 0.9999f, "ray %d (instance %d, shape type %d): "
              "ng (%g %g %g) vs (%g %g %g)", i, ha.inst, a.shapes[pa.shape].type,
              pa.ng.x, pa.ng.y, pa.ng.z, pb.ng.x, pb.ng.y, pb.ng.z);
        CHECK(t, sign * v3_dot(pa.ns, pb.ns) > 0.9999f, "ray %d: ns differs", i);
        /* (u, v): where a texture reads them (bvh.c skips a whole sphere's when
           nothing does) */
        CHECK(t, a.materials[a.shapes[pa.shape].material].reflectance_tex <= 0 ||
              (fabsf(pa.u - pb.u) < 1e-4f && fabsf(pa.v - pb.v) < 1e-4f),
              "ray %d: uv (%g %g) vs (%g %g)", i, pa.u, pa.v, pb.u, pb.v);
        CHECK(t, a.shapes[pa.shape].medium_inside == b.shapes[pb.shape].medium_inside,
              "ray %d: medium differs", i);
    }
    scene_free(&a);
    scene_free(&b);
    CHECK(t, hits > n / 4 && other <= hits / 200, "%d of %d rays hit the same surface, %d "
          "another", hits, n, other);
}

/* The images agree tile for tile (same seed: the same paths up to rounding). */
static void test_instance_image_written_out(T *t)
{
    static char ta[8192], tb[8192];
    Scene a, b;
    RenderOptions o;
    Tiles x, y;
    int i, c;
    scene_text(ta, sizeof ta, 1);
    scene_text(tb, sizeof tb, 0);
    if (!test_load_scene(t, &a, ta)) return;
    if (!test_load_scene(t, &b, tb)) { scene_free(&a); return; }
    render_options_default(&o);
    o.spp = 8;
    if (!test_render_tiles(t, &a, &o, 4, 4, &x) || !test_render_tiles(t, &b, &o, 4, 4, &y)) {
        scene_free(&a); scene_free(&b);
        return;
    }
    scene_free(&a);
    scene_free(&b);
    /* the same seeds: a path may part from its twin only where rounding moves a hit
       across an edge, so the tiles agree far inside their standard errors; a wrong
       transform, normal, uv or material moves them by many */
    for (i = 0; i < 16; i++)
        for (c = 0; c < 3; c++)
            CHECK(t, fabs(x.mean[i][c] - y.mean[i][c]) <= 0.5 * y.se[i][c] + 1e-6,
                  "tile %d channel %d: %.7g instanced, %.7g +- %.2g written out", i, c,
                  x.mean[i][c], y.mean[i][c], y.se[i][c]);
}

/* ---- analytic hits under translate, rotate, non-uniform scale ----------------- */
static void test_instance_analytic(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "ObjectBegin \"ball\"\n Shape \"sphere\" \"float radius\" 1\nObjectEnd\n"
        "ObjectBegin \"tri\"\n Translate 0 0 0.5\n"
        " Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\nObjectEnd\n"
        "AttributeBegin\n Translate 3 0 0\n Rotate 90 0 0 1\n Scale 2 1 0.5\n"
        " ObjectInstance \"ball\"\nAttributeEnd\n"
        "AttributeBegin\n Translate -3 1 0\n Rotate 30 1 1 0\n Scale 1 2 -3\n"
        " ObjectInstance \"tri\"\nAttributeEnd\n";
    Scene s;
    Xform mb, mt, a, b2;
    Rng rng;
    int i, n_ball = 0, n_tri = 0;
    if (!test_load_scene(t, &s, text)) return;
    a = xf_translate(3, 0, 0); b2 = xf_rotate(90, 0, 0, 1); mb = xf_mul(&a, &b2);
    b2 = xf_scale(2, 1, 0.5); mb = xf_mul(&mb, &b2);
    a = xf_translate(-3, 1, 0); b2 = xf_rotate(30, 1, 1, 0); mt = xf_mul(&a, &b2);
    b2 = xf_scale(1, 2, -3); mt = xf_mul(&mt, &b2);
    b2 = xf_translate(0, 0, 0.5); mt = xf_mul(&mt, &b2);
    rng_seed(&rng, 36, 1);
    for (i = 0; i < 2000; i++) {
        Vec3 u = rng_vec3(&rng), aim;
        Ray r;
        HitRecord h;
        SurfacePoint sp;
        double o[3], d[3], A = 0, B = 0, C = 0, tt;
        int k;
        /* the ellipsoid: aim at a point inside it, from 10 units away */
        aim = xf_point(&mb, v3(0.9f * (u.x - 0.5f), 0.9f * (u.y - 0.5f), 0.9f * (u.z - 0.5f)));
        u = rng_vec3(&rng);
        r.o = v3_add(aim, v3_mul(v3_norm(v3(u.x - 0.5f, u.y - 0.5f, u.z - 0.5f + 1e-3f)), 10.0f));
        r.d = v3_sub(aim, r.o);
        r.tmax = INFINITY;
        CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h) && h.inst >= 0, "ray %d missed the ellipsoid", i);
        for (k = 0; k < 3; k++) {   /* object space: |o' + t d'| = 1 */
            o[k] = mb.inv[k][0] * r.o.x + mb.inv[k][1] * r.o.y + mb.inv[k][2] * r.o.z + mb.inv[k][3];
            d[k] = mb.inv[k][0] * r.d.x + mb.inv[k][1] * r.d.y + mb.inv[k][2] * r.d.z;
            A += d[k] * d[k]; B += o[k] * d[k]; C += o[k] * o[k];
        }
        tt = (-B - sqrt(B * B - A * (C - 1.0))) / A;
        /* instance 0 is the ellipsoid; the triangle may stand in front of it */
        CHECK(t, h.inst == 0 || h.t < tt, "ray %d: instance %d hit behind the ellipsoid", i, h.inst);
        if (h.inst == 0) {
            n_ball++;
            CHECK(t, fabs(h.t - tt) < 1e-5 * tt, "ray %d: t %.8g, analytic %.8g", i, h.t, tt);
            scene_surface_point(&s, &r, &h, &sp);
        }
        if (h.inst == 0) {
            Vec3 po = v3((float)(o[0] + tt * d[0]), (float)(o[1] + tt * d[1]), (float)(o[2] + tt * d[2]));
            Vec3 n = v3_norm(xf_normal(&mb, po)), p = xf_point(&mb, po);
            CHECK(t, v3_len(v3_sub(sp.p, p)) < 1e-4f, "ray %d: p off by %g", i, v3_len(v3_sub(sp.p, p)));
            CHECK(t, v3_dot(sp.ng, n) > 0.99999f, "ray %d: normal (%g %g %g), analytic (%g %g %g)",
                  i, sp.ng.x, sp.ng.y, sp.ng.z, n.x, n.y, n.z);
        }
        /* the triangle: aim at barycentrics (b1, b2), each at least 0.05 from an edge */
        u = rng_vec3(&rng);
        {
            const float b1 = 0.05f + 0.45f * u.x, bb2 = 0.05f + 0.45f * u.y * (1.0f - u.x);
            Vec3 P0 = xf_point(&mt, v3(0, 0, 0)), P1 = xf_point(&mt, v3(1, 0, 0)),
                 P2 = xf_point(&mt, v3(0, 1, 0));
            float tref, r1, r2;
            Vec3 n;
            aim = v3_add(v3_add(v3_mul(P0, 1.0f - b1 - bb2), v3_mul(P1, b1)), v3_mul(P2, bb2));
            n = v3_neg(v3_norm(v3_cross(v3_sub(P0, P2), v3_sub(P1, P2))));
            u = rng_vec3(&rng);
            r.o = v3_add(aim, v3_mul(v3_norm(v3(u.x - 0.5f, u.y - 0.5f, u.z - 0.5f + 1e-3f)), 5.0f));
            r.d = v3_sub(aim, r.o);
            r.tmax = INFINITY;
            /* a grazing ray's t is ill-conditioned in the vertices' rounding: skip */
            if (fabsf(v3_dot(v3_norm(r.d), n)) < 0.2f) continue;
            CHECK(t, intersect_triangle(P0, P1, P2, &r, &tref, &r1, &r2), "ray %d: reference missed", i);
            CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h) && h.inst >= 0, "ray %d missed the triangle", i);
            CHECK(t, h.inst == 1 || h.t < tref, "ray %d: instance %d hit behind the triangle", i, h.inst);
            if (h.inst != 1) continue;             /* the ellipsoid stood in front */
            n_tri++;
            CHECK(t, fabsf(h.t - tref) < 1e-5f * tref, "ray %d: t %.8g, reference %.8g", i, h.t, tref);
            scene_surface_point(&s, &r, &h, &sp);
            /* default uv: u = b1 + b2, v = b2, barycentrics kept by an affine map */
            CHECK(t, fabsf(sp.u - (b1 + bb2)) < 1e-4f && fabsf(sp.v - bb2) < 1e-4f,
                  "ray %d: uv (%g %g), barycentrics give (%g %g)", i, sp.u, sp.v, b1 + bb2, bb2);
            /* n: pbrt-v4's normal of the written-out triangle, (p0 - p2) x (p1 - p2)
               negated for a mirroring CTM (det < 0 here: Scale 1 2 -3) */
            CHECK(t, v3_dot(sp.ng, n) > 0.9999f, "ray %d: triangle normal flipped or off", i);
        }
    }
    scene_free(&s);
    CHECK(t, n_ball > 1500 && n_tri > 1000, "only %d ellipsoid and %d triangle hits checked", n_ball, n_tri);
}

/* ---- ties: coincident instances ------------------------------------------------
   Instance 1 (object p, a quad at z = 0) and instance 2 (object q: the same quad
   and a triangle far to the side at z = 1.2, so its box reaches nearer the camera)
   coincide: every ray hits both at the same t, and the smaller id, 1, must win
   however the tree orders them; instance 0 (q moved back to z = -1, its box still
   reaching z = 0.2) lies behind both and must never win.  A row of world triangles
   far above makes the tree deep enough to put the instances in different leaves. */
static void test_instance_ties(T *t)
{
    static char text[8192];
    Scene s;
    Rng rng;
    size_t n;
    int i, k;
    n = (size_t)snprintf(text, sizeof text,
        "WorldBegin\n"
        "AttributeBegin\n Translate 0 0 -1\n ObjectInstance \"q\"\nAttributeEnd\n"  /* before its ObjectBegin */
        "ObjectBegin \"p\"\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
        "ObjectEnd\n"
        "ObjectBegin \"q\"\n"
        " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
        " Shape \"trianglemesh\" \"point3 P\" [ 5 0 1.2  6 0 1.2  5 1 1.2 ]\n"
        "ObjectEnd\n"
        "ObjectBegin \"empty\"\nObjectEnd\n"
        "ObjectInstance \"empty\"\n"
        "ObjectInstance \"p\"\n"
        "ObjectInstance \"q\"\n"
        "Shape \"trianglemesh\" \"point3 P\" [");
    for (k = 0; k < 64; k++)
        n += (size_t)snprintf(text + n, sizeof text - n, " %d 10 %d  %d.5 10 %d  %d 11 %d",
                              k - 32, k % 5, k - 32, k % 5, k - 32, k % 5);
    n += (size_t)snprintf(text + n, sizeof text - n, " ] \"integer indices\" [");
    for (k = 0; k < 3 * 64; k++) n += (size_t)snprintf(text + n, sizeof text - n, " %d", k);
    snprintf(text + n, sizeof text - n, " ]\n");
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_instances == 3, "%d instances (the empty one must be dropped)", s.n_instances);
    rng_seed(&rng, 36, 2);
    for (i = 0; i < 4000; i++) {
        Vec3 u = rng_vec3(&rng), aim;
        Ray r;
        HitRecord h;
        aim = v3(-0.95f + 1.9f * u.x, -0.95f + 1.9f * u.y, 0.0f);   /* on the quad */
        u = rng_vec3(&rng);
        r.o = v3(-2.0f + 4.0f * u.x, -2.0f + 4.0f * u.y, 2.0f + u.z);
        r.d = v3_sub(aim, r.o);
        r.tmax = INFINITY;
        CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "ray %d missed", i);
        CHECK(t, h.inst == 1, "ray %d: instance %d won, not instance 1", i, h.inst);
    }
    scene_free(&s);
}

/* ---- ties and order between many instances ------------------------------------
   Twenty objects, each the quad at z = 0 and a small triangle off to the side at
   z = 0.1 (k + 1), so that instance k's box reaches nearer a camera above as k
   grows: the traversal meets the instances in the order of their boxes, the
   largest id first, and their centroids spread so that they sit in different
   leaves.  Every ray aimed at the quad hits all twenty at one t; the tie goes to
   the smallest id, instance 0, which a trace of instance 0's object must accept at
   t equal to the best so far.  Then a twenty-first instance, declared first (id
   0): the quad moved back to z = -1, its side triangle to z = 0.05, so that its
   box still reaches above the quad but less than any other: the traversal meets
   it last, after the hit at the quad, and its object's trace must stop at that
   hit, since its own smaller id must not win with a farther t. */
static void test_instance_ties_many(T *t)
{
    static char text[16384];
    int pass;
    for (pass = 0; pass < 2; pass++) {
        Scene s;
        Rng rng;
        size_t n = 0;
        int i, k;
        n += (size_t)snprintf(text + n, sizeof text - n, "WorldBegin\n");
        if (pass == 1)
            n += (size_t)snprintf(text + n, sizeof text - n, "ObjectBegin \"back\"\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
                 " Shape \"trianglemesh\" \"point3 P\" [ 5 0 1.05  6 0 1.05  5 1 1.05 ]\n"
                 "ObjectEnd\nAttributeBegin\n Translate 0 0 -1\n ObjectInstance \"back\"\nAttributeEnd\n");
        for (k = 0; k < 20; k++)
            n += (size_t)snprintf(text + n, sizeof text - n, "ObjectBegin \"q%d\"\n"
                 " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
                 " Shape \"trianglemesh\" \"point3 P\" [ 5 0 %g  6 0 %g  5 1 %g ]\n"
                 "ObjectEnd\nObjectInstance \"q%d\"\n", k, 0.1 * (k + 1), 0.1 * (k + 1), 0.1 * (k + 1), k);
        if (!test_load_scene(t, &s, text)) return;
        CHECK(t, s.n_instances == 20 + pass, "%d instances", s.n_instances);
        rng_seed(&rng, 37, (uint64_t)pass);
        for (i = 0; i < 2000; i++) {
            Vec3 u = rng_vec3(&rng), aim;
            Ray r;
            HitRecord h;
            aim = v3(-0.95f + 1.9f * u.x, -0.95f + 1.9f * u.y, 0.0f);
            u = rng_vec3(&rng);
            r.o = v3(-2.0f + 4.0f * u.x, -2.0f + 4.0f * u.y, 3.0f + u.z);
            r.d = v3_sub(aim, r.o);
            r.tmax = INFINITY;
            CHECK(t, bvh_intersect(&s.bvh, &s, &r, &h), "pass %d, ray %d missed", pass, i);
            CHECK(t, h.inst == pass && h.t > 0.999f && h.t < 1.001f,
                  "pass %d, ray %d: instance %d won at t %g, not instance %d at t 1", pass, i, h.inst, h.t, pass);
        }
        scene_free(&s);
    }
}

/* ---- a frozen pbrt-v4 image ----------------------------------------------------
   A floor, a disk lamp, a distant light and three instances of a sphere and a
   triangle (plain; rotated with a non-uniform scale; mirrored).  pbrt-v4 (mmp/pbrt-v4
   5f7a6068, `pbrt --spp 16384 --seed S` for S = 1, 2, the mean of the two, which
   differ by at most 0.4 % per quadrant channel) on this text: the RGB means of the
   four quadrants (top left, top right, bottom left, bottom right).  specnee at
   16384 spp agreed within 0.4 %. */
static const char pbrt_instanced_scene[] =
    "LookAt 0 2 7  0 0.6 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" 40\n"
    "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 12 \"string filename\" \"t.pfm\"\n"
    "PixelFilter \"box\"\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"point3 from\" [ 1 3 2 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 2 2 2 ]\n"
    "AttributeBegin\n"
    " AreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\n"
    " Translate 0 4 0\n"
    " Rotate 90 1 0 0\n"
    " Shape \"disk\" \"float radius\" 1\n"
    "AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ]\n"
    "ObjectBegin \"thing\"\n"
    " Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.25 0.2 ]\n"
    " Translate 0 0.5 0\n"
    " Shape \"sphere\" \"float radius\" 0.5\n"
    " Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.7 0.3 ]\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ -0.6 -0.5 0.6  0.6 -0.5 0.6  0 0.7 0.6 ]\n"
    "ObjectEnd\n"
    "AttributeBegin\n Translate -1.5 0 0\n ObjectInstance \"thing\"\nAttributeEnd\n"
    "AttributeBegin\n Translate 1.4 0 0.3\n Rotate 35 0 1 0\n Scale 1.3 1.6 0.6\n ObjectInstance \"thing\"\nAttributeEnd\n"
    "AttributeBegin\n Translate 0 0 -1.5\n Scale -1 0.8 1\n ObjectInstance \"thing\"\nAttributeEnd\n";

static void test_instance_against_pbrt(T *t)
{
    static const double pbrt_rgb[4][3] = {
        { 0.0513410, 0.0476709, 0.0337045 },
        { 0.0362025, 0.0320645, 0.0266009 },
        { 0.2754115, 0.2999655, 0.2761250 },
        { 0.2808790, 0.3024600, 0.2811275 }
    };
    Scene s;
    RenderOptions o;
    Tiles tl;
    int q, c;
    if (!test_load_scene(t, &s, pbrt_instanced_scene)) return;
    render_options_default(&o);
    o.spp = test_scaled(256, 64);
    if (!test_render_tiles(t, &s, &o, 6, 2, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    for (q = 0; q < 4; q++)
        for (c = 0; c < 3; c++)
            CHECK(t, fabs(tl.mean[q][c] - pbrt_rgb[q][c]) < TEST_K_SIGMA * tl.se[q][c] + 0.01 * pbrt_rgb[q][c],
                  "quadrant %d, channel %d: %.6g +- %.2g, pbrt-v4 %.6g", q, c, tl.mean[q][c],
                  tl.se[q][c], pbrt_rgb[q][c]);
}

/* ---- refusals ------------------------------------------------------------------ */
static void test_instance_errors(T *t)
{
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\"\n", 3,
                  "ObjectBegin \"b\" called inside of instance definition \"a\"");
    expect_reject(t, "WorldBegin\nObjectEnd\n", 2, "ObjectEnd called outside of instance definition");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nObjectEnd\nObjectBegin \"a\"\n", 4,
                  "ObjectBegin \"a\": trying to redefine an object instance (first at t.pbrt:2)");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nObjectEnd\n\nObjectInstance \"b\"\n", 5,
                  "ObjectInstance \"b\": object instance not defined");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nObjectInstance \"a\"\n", 3,
                  "ObjectInstance \"a\" can't be called inside instance definition \"a\"");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nAttributeEnd\n", 3,
                  "Mismatched nesting: open ObjectBegin from t.pbrt:2 at AttributeEnd");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nAttributeBegin\nObjectEnd\n", 4,
                  "Mismatched nesting: open AttributeBegin from t.pbrt:3 at ObjectEnd");
    expect_reject(t, "WorldBegin\nAttributeBegin\nObjectBegin \"a\"\n", 3,
                  "ObjectBegin without a matching ObjectEnd");
    expect_reject(t, "ObjectBegin \"a\"\n", 1, "\"ObjectBegin\" not allowed before WorldBegin");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nAreaLightSource \"diffuse\"\n"
                  "Shape \"sphere\"\n", 4, "area lights are not supported with object instancing");
    expect_reject(t, "WorldBegin\nObjectBegin \"a\"\nShape \"sphere\"\nObjectEnd\n"
                  "ConcatTransform [ 1 0 0 0  0 1 0 0  0 0 1 0.5  0 0 0 1 ]\nObjectInstance \"a\"\n", 6,
                  "ObjectInstance \"a\": projective transform not supported");
    expect_reject(t, "WorldBegin\nAttribute \"camera\" \"float fov\" 3\n", 2,
                  "Unknown attribute target \"camera\"");
    /* an Attribute that pbrt-v4 would read and specnee cannot: refused by name */
    expect_reject(t, "WorldBegin\nAttribute \"shape\" \"string emissionfilename\" \"e.exr\"\n"
                  "Shape \"sphere\"\n", 2, "\"string emissionfilename\" is valid pbrt-v4 but not in the specnee subset");
}

/* ---- Attribute: precedence and scope ------------------------------------------- */
static void test_attribute_precedence(T *t)
{
    static const char text[] =
        "WorldBegin\n"
        "Attribute \"shape\" \"float radius\" 0.25\n"
        "AttributeBegin\n"
        " Attribute \"shape\" \"float radius\" 0.5\n"
        " Shape \"sphere\"\n"                       /* 0: the newest Attribute, 0.5 */
        " Shape \"sphere\" \"float radius\" 0.75\n" /* 1: its own parameter wins */
        " Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"  /* 2: radius unread: fine */
        " Attribute \"light\" \"float scale\" 3\n"
        " Attribute \"light\" \"bool twosided\" true\n"   /* keeps the scale */
        " AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
        " Translate 5 0 0\n"
        " Shape \"sphere\"\n"                       /* 3: emitter with scale 3 */
        "AttributeEnd\n"
        "Shape \"sphere\"\n"                        /* 4: back to 0.25 */
        "Attribute \"material\" \"rgb reflectance\" [ 0.1 0.2 0.3 ]\n"
        "Material \"diffuse\"\n"
        "Translate 0 5 0\n"
        "Shape \"sphere\"\n"                        /* 5: reflectance from the Attribute */
        "Material \"diffuse\" \"rgb reflectance\" [ 0.1 0.2 0.3 ]\n"
        "Translate 0 5 0\n"
        "Shape \"sphere\"\n";                       /* 6: the same, given directly */
    Scene s;
    int l;
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_shapes == 7, "%d shapes", s.n_shapes);
    CHECK(t, fabsf(s.shapes[0].radius - 0.5f) < 1e-6f, "newest Attribute: radius %g", s.shapes[0].radius);
    CHECK(t, fabsf(s.shapes[1].radius - 0.75f) < 1e-6f, "own parameter: radius %g", s.shapes[1].radius);
    CHECK(t, fabsf(s.shapes[4].radius - 0.25f) < 1e-6f, "after AttributeEnd: radius %g", s.shapes[4].radius);
    {   /* the lamp's scale, against the same lamp with "float scale" 3 given directly */
        Scene d;
        if (!test_load_scene(t, &d, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] "
                             "\"float scale\" 3 \"bool twosided\" true\nShape \"sphere\"\n")) { scene_free(&s); return; }
        l = s.shapes[3].emitter >= 0 && s.emitters[s.shapes[3].emitter].scale == d.emitters[0].scale &&
            s.emitters[s.shapes[3].emitter].twosided == 1 && d.emitters[0].twosided == 1;
        scene_free(&d);
        CHECK(t, l, "Attribute \"light\" \"float scale\" and \"bool twosided\" not both applied");
    }
    scene_free(&s);
    {   /* "texture" and "medium" defaults reach Texture and MakeNamedMedium */
        static const char tm[] =
            "Attribute \"medium\" \"float g\" 0.5 \"rgb sigma_a\" [ 0.1 0.2 0.3 ]\n"
            "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ 1 1 1 ]\n"
            "WorldBegin\n"
            "Attribute \"texture\" \"float uscale\" 4\n"
            "Texture \"c\" \"spectrum\" \"checkerboard\"\n"
            "Texture \"d\" \"spectrum\" \"checkerboard\" \"float uscale\" 2\n"
            "MediumInterface \"fog\" \"\"\nMaterial \"interface\"\nShape \"sphere\"\n";
        if (!test_load_scene(t, &s, tm)) return;
        CHECK(t, s.n_textures == 2 && s.textures[0].su == 4.0f && s.textures[1].su == 2.0f,
              "Attribute \"texture\": uscale %g and %g", s.textures[0].su, s.textures[1].su);
        CHECK(t, s.n_media == 1 && s.media[0].g == 0.5f, "Attribute \"medium\": g %g", s.media[0].g);
        CHECK(t, medium_sigma_a(&s.media[0], 550.0f) > 0.9f,
              "the medium's own sigma_a lost to the Attribute: %g", medium_sigma_a(&s.media[0], 550.0f));
        scene_free(&s);
    }
    if (!test_load_scene(t, &s, text)) return;
    for (l = 400; l <= 700; l += 50) {
        const float a = albedo_eval(&s.materials[s.shapes[5].material].reflectance, (float)l);
        const float b = albedo_eval(&s.materials[s.shapes[6].material].reflectance, (float)l);
        CHECK(t, a == b, "reflectance at %d nm: %g from the Attribute, %g given directly", l, a, b);
    }
    scene_free(&s);
}

/* Each ObjectInstance names its object, looked up where it is read (the last object
   named first) or, for one defined further down, at the end of the file: instances
   of two objects that alternate, and one before its ObjectBegin, each place their own
   object, in the order of the file. */
static void test_instance_names(T *t)
{
    static const char *const want[6] = { "a", "b", "b", "a", "c", "a" };
    Scene s;
    int i;
    const char *text =
        "WorldBegin\n"
        "ObjectBegin \"a\"\nShape \"sphere\" \"float radius\" 1\nObjectEnd\n"
        "ObjectBegin \"b\"\nShape \"sphere\" \"float radius\" 2\nObjectEnd\n"
        "Translate 5 0 0\nObjectInstance \"a\"\nObjectInstance \"b\"\nObjectInstance \"b\"\n"
        "ObjectInstance \"a\"\nObjectInstance \"c\"\nObjectInstance \"a\"\n"
        "ObjectBegin \"c\"\nShape \"sphere\" \"float radius\" 3\nObjectEnd\n";
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_instances == 6, "%d instances", s.n_instances);
    for (i = 0; i < 6 && i < s.n_instances; i++)
        CHECK(t, !strcmp(s.objects[s.instances[i].object].name, want[i]),
              "instance %d places \"%s\", not \"%s\"", i, s.objects[s.instances[i].object].name,
              want[i]);
    scene_free(&s);
}

const TestCase tests_instance[] = {
    { "instance_names", test_instance_names },
    { "instance_hits_written_out", test_instance_hits_written_out },
    { "instance_image_written_out", test_instance_image_written_out },
    { "instance_analytic", test_instance_analytic },
    { "instance_ties", test_instance_ties },
    { "instance_ties_many", test_instance_ties_many },
    { "instance_against_pbrt", test_instance_against_pbrt },
    { "instance_errors", test_instance_errors },
    { "attribute_precedence", test_attribute_precedence },
    { NULL, NULL }
};
