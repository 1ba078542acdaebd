/* tests/test_bvh.c - tests of bvh.c (BVH, ray/primitive tests, hit points) and ply.c.

   What is checked, and why it can fail:
     bvh_vs_brute        BVH closest hit and any hit equal a loop over every primitive
                         exactly (same primitive, t and barycentrics; ties in t go to
                         the smaller id), on random triangle soups with degenerate
                         triangles and spheres
     bvh_exact_adversarial  the same on scenes made of ties (a subdivided cube and an
                         icosphere with every triangle duplicated, overlapping coplanar
                         triangles) with rays through vertices and edges, along the axes
                         and the normals, and grazing the triangles' planes
     bvh_hit_floor       a hit is never reported nearer than its primitive's box (the
                         floor is met exactly on axis-aligned faces hit along the
                         axes, and never undercut), and the floor moves no hit off
                         its triangle or sphere (t within 1e-5 of the distance solved
                         in double for rays that meet them at more than 10 degrees)
     bvh_simd_matches_scalar  the slab test's SSE2 code, and its AVX2 code where the
                         processor has AVX2, equal the scalar code they mirror bit for
                         bit (entry distances, the mask, the ranks),
                         with d = 0 axes and origins on the boxes' planes; the two bit
                         scans agree on every 8-bit mask
     bvh_avx2_triangle_filter  the AVX2 traversal's 4-lane triangle filter gives the
                         scalar sign test's verdict on every triangle (rays through
                         vertices and edges included) and never drops a hit
     bvh_watertight_*    rays aimed exactly at shared vertices and edges of closed meshes
                         (an icosphere; a subdivided cube hit by axis-aligned rays, whose
                         flat boxes stress the slab test) all hit
     bvh_structure       the 8-wide nodes' child boxes nest and contain their leaves'
                         primitives (records copied exactly), empty slots are inverted
                         boxes, every primitive sits in exactly one leaf of at most
                         BVH_WIDE_LEAF_MAX, the depth stays bounded
     bvh_deterministic   two builds are byte-identical
     bvh_degenerate      coincident centroids and an SAH-hostile exponential spacing
                         give a valid tree of bounded depth, still equal to brute force
     bvh_triangle/sphere the primitive tests against hand-computed answers
     bvh_surface_point   pbrt-v4's normal conventions (winding, flip, shading normals)
     bvh_offset          rays leaving a surface through offset_ray_origin never re-hit it
     ply_*               every PLY feature, every rejection with its message, and a fuzz
                         run (random corruption must give a clean error or a valid mesh)
   The scenes are built by hand; the scene parser is not used. */
#include "test.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* ======================================================================
   Hand-made scenes
   ====================================================================== */
/* A scene with n_verts vertices, n_tris triangles (all in shape 0, a mesh) and
   n_spheres spheres (shapes 1 .., unit spheres at the origin until set). */
static int scene_make(Scene *s, int n_verts, int n_tris, int n_spheres)
{
    int j;
    memset(s, 0, sizeof *s);
    s->P = (Vec3 *)calloc((size_t)n_verts + 1, sizeof *s->P);
    s->tris = (Triangle *)calloc((size_t)n_tris + 1, sizeof *s->tris);
    s->shapes = (Shape *)calloc((size_t)n_spheres + 1, sizeof *s->shapes);
    s->sphere_shape = (int *)calloc((size_t)n_spheres + 1, sizeof *s->sphere_shape);
    if (!s->P || !s->tris || !s->shapes || !s->sphere_shape) return 0;
    s->n_verts = n_verts; s->n_tris = n_tris; s->n_spheres = n_spheres;
    s->n_shapes = 1 + n_spheres;
    s->shapes[0].type = SHAPE_MESH;
    s->shapes[0].emitter = -1;
    s->shapes[0].tri_count = n_tris;
    for (j = 0; j < n_spheres; j++) {
        Shape *sh = &s->shapes[1 + j];
        sh->type = SHAPE_SPHERE;
        sh->emitter = -1;
        sh->radius = 1.0f;
        s->sphere_shape[j] = 1 + j;
    }
    return 1;
}

static void scene_release(Scene *s)
{
    bvh_free(&s->bvh);
    free(s->P); free(s->N); free(s->tris); free(s->shapes); free(s->sphere_shape);
    memset(s, 0, sizeof *s);
}

static float urand(Rng *r, float lo, float hi) { return lo + (hi - lo) * rng_float(r); }

static Vec3 random_dir(Rng *r)
{
    for (;;) {
        Vec3 d = v3(urand(r, -1, 1), urand(r, -1, 1), urand(r, -1, 1));
        float l2 = v3_dot(d, d);
        if (l2 > 1e-4f && l2 <= 1.0f) return v3_mul(d, 1.0f / sqrtf(l2));
    }
}

/* Icosphere: the icosahedron (12 vertices, 20 counter-clockwise faces seen from
   outside) with each triangle split into 4 `level` times, vertices on the unit
   sphere.  Returns the scene (shape 0) or 0 on out of memory. */
static int make_icosphere(Scene *s, int level)
{
    static const float ico_v[12][3] = {
        {-1, 1.6180340f, 0}, {1, 1.6180340f, 0}, {-1, -1.6180340f, 0}, {1, -1.6180340f, 0},
        {0, -1, 1.6180340f}, {0, 1, 1.6180340f}, {0, -1, -1.6180340f}, {0, 1, -1.6180340f},
        {1.6180340f, 0, -1}, {1.6180340f, 0, 1}, {-1.6180340f, 0, -1}, {-1.6180340f, 0, 1}};
    static const int ico_f[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    int n_tris = 20 << (2 * level), n_verts = 10 * (1 << (2 * level)) + 2;
    int nv = 12, nt = 20, l, i, k;
    int32_t *key_a, *key_b, *key_m, hsize = 8 * n_tris;
    Triangle *tmp;
    if (!scene_make(s, n_verts, n_tris, 0)) return 0;
    for (i = 0; i < 12; i++) s->P[i] = v3_norm(v3(ico_v[i][0], ico_v[i][1], ico_v[i][2]));
    for (i = 0; i < 20; i++)
        for (k = 0; k < 3; k++) s->tris[i].v[k] = ico_f[i][k];
    key_a = (int32_t *)malloc((size_t)hsize * sizeof(int32_t));
    key_b = (int32_t *)malloc((size_t)hsize * sizeof(int32_t));
    key_m = (int32_t *)malloc((size_t)hsize * sizeof(int32_t));
    tmp = (Triangle *)malloc((size_t)n_tris * sizeof *tmp);
    if (!key_a || !key_b || !key_m || !tmp) {
        free(key_a); free(key_b); free(key_m); free(tmp);
        return 0;
    }
    for (l = 0; l < level; l++) {
        int nt2 = 0;
        for (i = 0; i < hsize; i++) key_a[i] = -1;
        for (i = 0; i < nt; i++) {
            int m[3];
            for (k = 0; k < 3; k++) {          /* midpoint of edge (v[k], v[k+1]), shared */
                int a = s->tris[i].v[k], b = s->tris[i].v[(k + 1) % 3], lo = a < b ? a : b,
                    hi = a < b ? b : a;
                uint32_t h = (uint32_t)(hash_u64((uint64_t)lo, (uint64_t)hi) % (uint64_t)hsize);
                while (key_a[h] >= 0 && !(key_a[h] == lo && key_b[h] == hi))
                    h = (h + 1) % (uint32_t)hsize;
                if (key_a[h] < 0) {            /* new vertex, pushed onto the sphere */
                    float x = s->P[a].x + s->P[b].x, y = s->P[a].y + s->P[b].y,
                          z = s->P[a].z + s->P[b].z, inv_len = 1.0f / sqrtf(x * x + y * y + z * z);
                    key_a[h] = lo; key_b[h] = hi; key_m[h] = nv;
                    s->P[nv].x = x * inv_len; s->P[nv].y = y * inv_len; s->P[nv].z = z * inv_len;
                    nv++;
                }
                m[k] = key_m[h];
            }
            {
                int a = s->tris[i].v[0], b = s->tris[i].v[1], c = s->tris[i].v[2];
                int q[4][3];
                q[0][0] = a; q[0][1] = m[0]; q[0][2] = m[2];
                q[1][0] = b; q[1][1] = m[1]; q[1][2] = m[0];
                q[2][0] = c; q[2][1] = m[2]; q[2][2] = m[1];
                q[3][0] = m[0]; q[3][1] = m[1]; q[3][2] = m[2];
                for (k = 0; k < 4; k++) {
                    tmp[nt2].v[0] = q[k][0]; tmp[nt2].v[1] = q[k][1]; tmp[nt2].v[2] = q[k][2];
                    tmp[nt2].shape = 0;
                    nt2++;
                }
            }
        }
        memcpy(s->tris, tmp, (size_t)nt2 * sizeof *tmp);
        nt = nt2;
    }
    free(key_a); free(key_b); free(key_m); free(tmp);
    s->n_verts = nv;
    return nt == n_tris && nv == n_verts;
}

/* Brute force: every primitive in id order, the smallest t; on equal t the first,
   i.e. the smallest id.  This is the definition of the closest hit that the BVH
   must reproduce bit for bit, whatever order its traversal visits the leaves in. */
static int brute_intersect(const Scene *s, const Ray *r, HitRecord *h)
{
    int i, hit = 0;
    float t, b1, b2;
    for (i = 0; i < s->n_tris + s->n_spheres; i++) {
        int ok;
        if (i < s->n_tris)
            ok = intersect_triangle(s->P[s->tris[i].v[0]], s->P[s->tris[i].v[1]],
                                    s->P[s->tris[i].v[2]], r, &t, &b1, &b2);
        else {
            const Shape *sh = &s->shapes[s->sphere_shape[i - s->n_tris]];
            ok = intersect_sphere(sh->center, sh->radius, r, &t);
            b1 = b2 = 0;
        }
        if (ok && (!hit || t < h->t)) { hit = 1; h->t = t; h->prim = i; h->b1 = b1; h->b2 = b2; }
    }
    return hit;
}

/* Compare the BVH with brute force on one ray, exactly: the same answer to "any hit",
   and for the closest hit the same primitive, the same t and the same barycentrics,
   bit for bit.  The ray is also cast with tmax equal to the closest t (which tmax
   excludes: no hit, no occlusion) and to the next float above it (the same hit).
   Returns 0, or 1 with the first disagreement written into msg when msg[0] == 0. */
static int check_ray(const Scene *s, const Ray *r0, int k, char *msg, size_t n_msg)
{
    Ray r = *r0;
    int pass;
    for (pass = 0; pass < 3; pass++) {
        HitRecord hb, hr;
        int got, want, occ;
        memset(&hb, 0, sizeof hb);
        memset(&hr, 0, sizeof hr);
        got = bvh_intersect(&s->bvh, s, &r, &hb);
        want = brute_intersect(s, &r, &hr);
        occ = bvh_occluded(&s->bvh, s, &r);
        if (got != want || occ != want) {
            if (!msg[0]) snprintf(msg, n_msg, "ray %d pass %d (tmax %.9g): bvh hit %d, any hit %d, "
                                  "brute %d (prim %d t %.9g) o %a %a %a d %a %a %a", k, pass, r.tmax, got, occ, want,
                                  want ? hr.prim : -1, want ? hr.t : 0.0f, r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z);
            return 1;
        }
        if (got && (hb.prim != hr.prim || hb.t != hr.t || hb.b1 != hr.b1 || hb.b2 != hr.b2)) {
            if (!msg[0]) snprintf(msg, n_msg, "ray %d pass %d: bvh prim %d t %.9g, brute prim %d "
                                  "t %.9g", k, pass, hb.prim, hb.t, hr.prim, hr.t);
            return 1;
        }
        if (!want) return 0;
        if (pass == 0) r.tmax = hr.t;                     /* excluded: must miss */
        else if (pass == 1) {
            if (got) {
                if (!msg[0]) snprintf(msg, n_msg, "ray %d: tmax = closest t still hits", k);
                return 1;
            }
            r.tmax = nextafterf(r.tmax, INFINITY);        /* included again */
        }
    }
    return 0;
}

/* Compare the BVH with brute force on n_rays random rays; returns the number of
   disagreements and writes the first into msg. */
static int compare_with_brute(const Scene *s, Rng *rng, int n_rays, char *msg, size_t n_msg)
{
    int k, bad = 0;
    msg[0] = 0;
    for (k = 0; k < n_rays; k++) {
        Ray r;
        float u = rng_float(rng);
        r.o = v3(urand(rng, -2, 2), urand(rng, -2, 2), urand(rng, -2, 2));
        r.d = v3_mul(random_dir(rng), urand(rng, 0.5f, 2.0f));       /* not unit length */
        if (u < 0.15f) {                                              /* axis-aligned */
            int a = (int)(rng_float(rng) * 3);
            float sgn = rng_float(rng) < 0.5f ? -1.0f : 1.0f;
            r.d = v3(a == 0 ? sgn : 0.0f, a == 1 ? sgn : 0.0f, a == 2 ? sgn : 0.0f);
        }
        r.tmax = rng_float(rng) < 0.5f ? INFINITY : urand(rng, 0.05f, 3.0f);
        bad += check_ray(s, &r, k, msg, n_msg);
    }
    return bad;
}

/* Adversarial rays against the triangles of s (which must have some): aimed at a
   vertex, an edge point or an interior point of a random triangle, either
   from a random origin, along a coordinate axis (the flat boxes of axis-aligned
   faces, and a dominant axis along the normal where every vertex has the same
   depth), or grazing: almost in the triangle's plane, at angles down to 1e-7. */
static int adversarial_rays(const Scene *s, Rng *rng, int n_rays, char *msg, size_t n_msg)
{
    int k, bad = 0;
    msg[0] = 0;
    for (k = 0; k < n_rays; k++) {
        const Triangle *tri = &s->tris[(int)(rng_float(rng) * (float)s->n_tris) % s->n_tris];
        Vec3 a = s->P[tri->v[0]], b = s->P[tri->v[1]], c = s->P[tri->v[2]], target, d, n;
        int aim = (int)(rng_float(rng) * 3), how = (int)(rng_float(rng) * 4);
        Ray r;
        if (aim == 0) target = rng_float(rng) < 0.5f ? a : b;                 /* vertex */
        else if (aim == 1) target = v3_add(a, v3_mul(v3_sub(b, a), rng_float(rng) < 0.5f
                                                     ? 0.5f : rng_float(rng)));  /* edge */
        else {                                                               /* inside */
            float u = rng_float(rng), v = rng_float(rng);
            if (u + v > 1.0f) { u = 1.0f - u; v = 1.0f - v; }
            target = v3_add(a, v3_add(v3_mul(v3_sub(b, a), u), v3_mul(v3_sub(c, a), v)));
        }
        n = v3_cross(v3_sub(b, a), v3_sub(c, a));
        if (how == 0) {                                  /* from anywhere */
            r.o = v3(urand(rng, -3, 3), urand(rng, -3, 3), urand(rng, -3, 3));
            d = v3_sub(target, r.o);
        } else if (how == 1) {                           /* along an axis */
            int ax = (int)(rng_float(rng) * 3);
            float sgn = rng_float(rng) < 0.5f ? -1.0f : 1.0f, dist = urand(rng, 0.5f, 3.0f);
            d = v3(ax == 0 ? sgn : 0.0f, ax == 1 ? sgn : 0.0f, ax == 2 ? sgn : 0.0f);
            r.o = v3_sub(target, v3_mul(d, dist));
        } else if (how == 2 && v3_dot(n, n) > 0.0f) {   /* along the normal */
            float dist = urand(rng, 0.5f, 3.0f) * (rng_float(rng) < 0.5f ? -1.0f : 1.0f);
            d = v3_norm(n);
            r.o = v3_sub(target, v3_mul(d, dist));
        } else {                                         /* grazing the plane */
            Vec3 in = random_dir(rng);
            float eps = ldexpf(1.0f, -(int)(rng_float(rng) * 24.0f));
            if (v3_dot(n, n) > 0.0f) {
                Vec3 nn = v3_norm(n);
                in = v3_sub(in, v3_mul(nn, v3_dot(in, nn)));       /* in the plane */
                if (v3_dot(in, in) == 0.0f) in = v3_sub(b, a);
                d = v3_add(v3_norm(in), v3_mul(nn, eps * (rng_float(rng) < 0.5f ? -1.0f : 1.0f)));
            } else
                d = in;
            r.o = v3_sub(target, v3_mul(d, urand(rng, 0.2f, 3.0f)));
        }
        r.d = d;
        r.tmax = INFINITY;
        bad += check_ray(s, &r, k, msg, n_msg);
    }
    return bad;
}

/* Random soup: n triangles (about 1 in 8 degenerate) and n_sph spheres in [-1,1]^3. */
static int make_soup(Scene *s, Rng *rng, int n, int n_sph)
{
    int i, k;
    if (!scene_make(s, 3 * n, n, n_sph)) return 0;
    for (i = 0; i < n; i++) {
        Vec3 c = v3(urand(rng, -1, 1), urand(rng, -1, 1), urand(rng, -1, 1));
        float size = urand(rng, 0.01f, 0.5f);
        int kind = (int)(rng_float(rng) * 16);
        for (k = 0; k < 3; k++) {
            s->P[3 * i + k] = v3_add(c, v3_mul(random_dir(rng), size));
            s->tris[i].v[k] = 3 * i + k;
        }
        if (kind == 0) s->P[3 * i + 1] = s->P[3 * i];                   /* repeated vertex */
        if (kind == 1)                                                   /* collinear */
            s->P[3 * i + 2] = v3_add(s->P[3 * i], v3_mul(v3_sub(s->P[3 * i + 1], s->P[3 * i]), 0.5f));
        if (kind == 2) s->P[3 * i + 1] = s->P[3 * i + 2] = s->P[3 * i]; /* a point */
    }
    for (i = 0; i < n_sph; i++) {
        Shape *sh = &s->shapes[1 + i];
        sh->center = v3(urand(rng, -1, 1), urand(rng, -1, 1), urand(rng, -1, 1));
        sh->radius = urand(rng, 0.02f, 0.3f);
    }
    return 1;
}

/* ======================================================================
   BVH tests
   ====================================================================== */
static void test_bvh_vs_brute(T *t)
{
    static const int sizes[][2] = {{1, 0}, {2, 1}, {7, 0}, {33, 3}, {200, 10}, {3000, 40}, {0, 5}};
    Rng rng;
    int i;
    rng_seed(&rng, 11, 0);
    for (i = 0; i < (int)(sizeof sizes / sizeof sizes[0]); i++) {
        Scene s;
        char msg[256] = "";
        int bad;
        CHECK(t, make_soup(&s, &rng, sizes[i][0], sizes[i][1]), "out of memory");
        CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
        bad = compare_with_brute(&s, &rng, 3000, msg, sizeof msg);
        scene_release(&s);
        CHECK(t, bad == 0, "%d tris %d spheres: %d of 3000 rays differ; %s",
              sizes[i][0], sizes[i][1], bad, msg);
    }
}

/* Append `copies - 1` copies of every triangle of s (odd copies with the vertex order
   rotated, which may round t differently): equal or nearly equal t in different
   leaves, the ties that the closest hit must break by primitive id. */
static int duplicate_triangles(Scene *s, int copies)
{
    Triangle *tris = (Triangle *)realloc(s->tris, (size_t)copies * s->n_tris * sizeof *tris);
    int n = s->n_tris, c, i;
    if (!tris) return 0;
    s->tris = tris;
    for (c = 1; c < copies; c++)
        for (i = 0; i < n; i++) {
            Triangle *q = &tris[c * n + i];
            *q = tris[i];
            if (c & 1) { q->v[0] = tris[i].v[1]; q->v[1] = tris[i].v[2]; q->v[2] = tris[i].v[0]; }
        }
    s->n_tris = copies * n;
    s->shapes[0].tri_count = s->n_tris;
    return 1;
}

/* Overlapping triangles in two planes: z = 0.25 (exactly) and a tilted one, plus
   spheres cutting through them. */
static int make_coplanar(Scene *s, Rng *rng, int n)
{
    int i, k;
    if (!scene_make(s, 3 * n, n, 4)) return 0;
    for (i = 0; i < n; i++) {
        for (k = 0; k < 3; k++) {
            float x = urand(rng, -1, 1), y = urand(rng, -1, 1);
            s->P[3 * i + k] = i % 2 ? v3(x, y, 0.25f) : v3(x, y, 0.3f * x - 0.7f * y);
            s->tris[i].v[k] = 3 * i + k;
        }
    }
    for (i = 0; i < 4; i++) {
        s->shapes[1 + i].center = v3(urand(rng, -1, 1), urand(rng, -1, 1), 0.25f);
        s->shapes[1 + i].radius = urand(rng, 0.05f, 0.4f);
    }
    return 1;
}

static int make_grid_cube(Scene *s, int n);

/* The closest hit does not depend on the traversal order: on scenes full of ties
   (shared edges and vertices, coplanar and duplicated triangles) and adversarial
   rays, the BVH returns exactly brute force's answer (see check_ray). */
static void test_bvh_exact_adversarial(T *t)
{
    const int n_rays = test_scaled(6000, 1000);
    Scene s;
    Rng rng;
    char msg[256];
    int bad, scene;
    rng_seed(&rng, 17, 0);
    for (scene = 0; scene < 4; scene++) {
        static const char *names[] = {"grid cube x3", "icosphere x2", "coplanar", "soup x2"};
        int ok;
        if (scene == 0) ok = make_grid_cube(&s, 6) && duplicate_triangles(&s, 3);
        else if (scene == 1) ok = make_icosphere(&s, 3) && duplicate_triangles(&s, 2);
        else if (scene == 2) ok = make_coplanar(&s, &rng, 400);
        else ok = make_soup(&s, &rng, 300, 5) && duplicate_triangles(&s, 2);
        CHECK(t, ok, "out of memory");
        CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
        bad = adversarial_rays(&s, &rng, n_rays, msg, sizeof msg);
        if (!bad) bad = compare_with_brute(&s, &rng, n_rays / 4, msg, sizeof msg);
        scene_release(&s);
        CHECK(t, bad == 0, "%s: %d of %d rays differ from brute force; %s", names[scene], bad,
              n_rays + n_rays / 4, msg);
    }
}

/* THE HIT'S FLOOR (bvh.c, ORDER INDEPENDENCE): a hit is reported at
   max(t_test, entry distance of the primitive's box), which is what lets the
   traversal cull on the full entry distance.  On the axis-aligned faces of a cube
   hit along the axes the box is flat, and the watertight test's t and the box's
   entry distance round differently: the floor must be met exactly by some hits (so
   it is applied) and undercut by none.  On a soup of triangles and spheres, rays
   that meet a primitive at more than 10 degrees: the reported t within 1e-5
   (relative) of the distance solved in double, so the floor moves no hit off its
   primitive (a floor from the far planes, or from a box too large, would). */
static void test_bvh_hit_floor(T *t)
{
    const int n = test_scaled(4000, 1000);
    Scene s;
    Rng rng;
    int k, hits = 0, met = 0, under = 0, far = 0, worst_k = -1;
    double worst = 0.0;
    rng_seed(&rng, 41, 0);
    CHECK(t, make_grid_cube(&s, 6), "out of memory");
    for (k = 0; k < n; k++) {
        const int p = (int)(rng_float(&rng) * (float)s.n_tris) % s.n_tris;
        const Triangle *tri = &s.tris[p];
        const Vec3 a = s.P[tri->v[0]], b = s.P[tri->v[1]], c = s.P[tri->v[2]];
        const int ax = a.x == b.x && b.x == c.x ? 0 : a.y == b.y && b.y == c.y ? 1 : 2;
        float u = rng_float(&rng), v = rng_float(&rng), th, b1, b2, sgn = rng_float(&rng) < 0.5f ? -1.0f : 1.0f;
        Ray r;
        if (u + v > 1.0f) { u = 1.0f - u; v = 1.0f - v; }
        r.d = v3(ax == 0 ? sgn : 0.0f, ax == 1 ? sgn : 0.0f, ax == 2 ? sgn : 0.0f);
        r.o = v3_sub(v3_add(a, v3_add(v3_mul(v3_sub(b, a), u), v3_mul(v3_sub(c, a), v))),
                     v3_mul(r.d, urand(&rng, 0.5f, 3.0f)));
        r.tmax = INFINITY;
        if (!intersect_triangle(a, b, c, &r, &th, &b1, &b2)) continue;
        hits++;
        met += th == bvh_hit_floor(&s, p, &r);
        under += th < bvh_hit_floor(&s, p, &r);
    }
    scene_release(&s);
    CHECK(t, hits > n * 9 / 10 && under == 0 && met > hits / 20,
          "cube faces along the axes: %d of %d rays hit, %d at their floor, %d below it", hits, n, met, under);

    CHECK(t, make_soup(&s, &rng, 300, 40), "out of memory");
    hits = 0;
    for (k = 0; k < n; k++) {
        const int p = (int)(rng_float(&rng) * (float)(s.n_tris + s.n_spheres)) % (s.n_tris + s.n_spheres);
        double te, o[3], d[3], q[3], nn[3], dn = 0, qn = 0, dd = 0;
        Vec3 target, nrm;
        float th, b1, b2;
        int hit, i;
        Ray r;
        if (p < s.n_tris) {
            const Triangle *tri = &s.tris[p];
            const Vec3 a = s.P[tri->v[0]], b = s.P[tri->v[1]], c = s.P[tri->v[2]];
            float u = rng_float(&rng), v = rng_float(&rng);
            if (u + v > 1.0f) { u = 1.0f - u; v = 1.0f - v; }
            nrm = v3_cross(v3_sub(b, a), v3_sub(c, a));
            if (!(v3_dot(nrm, nrm) > 1e-12f)) continue;               /* degenerate */
            nrm = v3_norm(nrm);
            target = v3_add(a, v3_add(v3_mul(v3_sub(b, a), u), v3_mul(v3_sub(c, a), v)));
        } else {
            const Shape *sh = &s.shapes[s.sphere_shape[p - s.n_tris]];
            nrm = random_dir(&rng);
            target = v3_add(sh->center, v3_mul(nrm, sh->radius));
        }
        r.d = random_dir(&rng);
        if (v3_dot(r.d, nrm) > 0.0f) r.d = v3_mul(r.d, -1.0f);          /* towards the face */
        if (!(-v3_dot(r.d, nrm) > 0.17f)) continue;                     /* more than 10 degrees */
        r.o = v3_sub(target, v3_mul(r.d, urand(&rng, 0.3f, 3.0f)));
        r.tmax = INFINITY;
        /* the distance in double to the plane of the triangle, or to the sphere */
        o[0] = r.o.x; o[1] = r.o.y; o[2] = r.o.z;
        d[0] = r.d.x; d[1] = r.d.y; d[2] = r.d.z;
        if (p < s.n_tris) {
            const Triangle *tri = &s.tris[p];
            const Vec3 a = s.P[tri->v[0]], b = s.P[tri->v[1]], c = s.P[tri->v[2]];
            const double e1[3] = { (double)b.x - a.x, (double)b.y - a.y, (double)b.z - a.z };
            const double e2[3] = { (double)c.x - a.x, (double)c.y - a.y, (double)c.z - a.z };
            nn[0] = e1[1] * e2[2] - e1[2] * e2[1];
            nn[1] = e1[2] * e2[0] - e1[0] * e2[2];
            nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
            q[0] = (double)a.x - o[0]; q[1] = (double)a.y - o[1]; q[2] = (double)a.z - o[2];
            for (i = 0; i < 3; i++) { dn += d[i] * nn[i]; qn += q[i] * nn[i]; }
            te = qn / dn;
            hit = intersect_triangle(a, b, c, &r, &th, &b1, &b2);
        } else {
            const Shape *sh = &s.shapes[s.sphere_shape[p - s.n_tris]];
            double bq = 0, cq = -(double)sh->radius * sh->radius;
            q[0] = o[0] - sh->center.x; q[1] = o[1] - sh->center.y; q[2] = o[2] - sh->center.z;
            for (i = 0; i < 3; i++) { dd += d[i] * d[i]; bq += q[i] * d[i]; cq += q[i] * q[i]; }
            te = (-bq - sqrt(bq * bq - dd * cq)) / dd;                   /* the nearer root */
            hit = intersect_sphere(sh->center, sh->radius, &r, &th);
        }
        if (!hit || !(te > 0.0)) continue;
        hits++;
        under += th < bvh_hit_floor(&s, p, &r);
        if (fabs(th - te) > worst * te) { worst = fabs(th - te) / te; worst_k = k; }
        far += fabs(th - te) > 1e-5 * te;
    }
    scene_release(&s);
    CHECK(t, hits > n / 4 && under == 0 && far == 0,
          "soup: %d hits, %d below their floor, %d off by more than 1e-5 (worst %.3g, ray %d)",
          hits, under, far, worst, worst_k);
}

/* The slab test's and the rank's SSE2 code, and their AVX2 code where the processor
   has AVX2 (bvh_avx2), against the scalar code they mirror (bvh_simd_mismatches),
   bit for bit on every node: random rays, rays with zero direction components whose
   origin lies exactly on a box's plane (the NaN of 0 * inf), and culling distances
   from 0 to infinity; on a soup and on the grid cube, whose boxes are flat.  With
   AVX2 the same call compares the AVX2 copy's 4-lane ray preparation with the scalar
   one (verdict and fields), also on rays at its edges: no direction, one shorter
   than FLT_MIN, signed zeros, ties of |d|, non-finite, missing the root box, and
   starting on a plane of the root box with d = 0 across it (the NaN of 0 * inf);
   and rays through the corners of the boxes, the root's included, where only the
   far factor (1 + 2 gamma(3)) decides whether the box is entered. */
static void test_bvh_simd_matches_scalar(T *t)
{
    Scene s;
    Rng rng;
    int scene, k, lanes = 0, bad = 0, expected = 0;
    const int paths = 1 + bvh_avx2();       /* SSE2, and AVX2 where it runs */
    rng_seed(&rng, 29, 0);
    for (scene = 0; scene < 2; scene++) {
        CHECK(t, scene ? make_grid_cube(&s, 8) : make_soup(&s, &rng, 3000, 20), "out of memory");
        CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
        for (k = 0; k < 400; k++) {
            const BvhNode *nd = &s.bvh.nodes[(int)(rng_float(&rng) * (float)s.bvh.n_nodes) % s.bvh.n_nodes];
            const int slot = (int)(rng_float(&rng) * BVH_WIDTH) % BVH_WIDTH, how = k % 4;
            static const float culls[] = {0.0f, 1e-3f, 0.5f, 2.0f, INFINITY};
            Ray r;
            r.o = v3(urand(&rng, -2, 2), urand(&rng, -2, 2), urand(&rng, -2, 2));
            r.d = v3_mul(random_dir(&rng), urand(&rng, 0.5f, 2.0f));
            if (how >= 2) {                 /* d = 0 on an axis, o on a plane of a box */
                const int a = (int)(rng_float(&rng) * 3) % 3;
                float c[3], dd[3];
                c[0] = r.o.x; c[1] = r.o.y; c[2] = r.o.z;
                dd[0] = r.d.x; dd[1] = r.d.y; dd[2] = r.d.z;
                dd[a] = how == 2 ? 0.0f : -0.0f;
                if (isfinite(nd->box[a][slot])) c[a] = nd->box[(how - 2) * 3 + a][slot];
                r.o = v3(c[0], c[1], c[2]);
                r.d = v3(dd[0], dd[1], dd[2]);
            }
            r.tmax = INFINITY;
            bad += bvh_simd_mismatches(&s.bvh, &r, culls[k % 5], &lanes);
            expected += s.bvh.n_nodes * BVH_WIDTH * paths;
        }
        for (k = 0; k < 13; k++) {          /* rays at the edges of the preparation */
            static const float odd[13][6] = {
                {0, 0, 0, 0, 0, 0},                          /* no direction */
                {0, 0, 0, 1e-39f, 0, -1e-39f},               /* shorter than FLT_MIN */
                {0, 0, 0, FLT_MIN, 0, -0.0f},                /* just long enough */
                {0.1f, 0.2f, 0.3f, -0.0f, -0.0f, 1},         /* signed zeros */
                {0.1f, 0.2f, 0.3f, 1, 1, 1},                 /* ties of |d| */
                {0.1f, 0.2f, 0.3f, -1, 1, -1},
                {0.1f, 0.2f, 0.3f, 0, -2, 2},
                {0.1f, 0.2f, 0.3f, -3, 2, 1},                /* each axis dominant */
                {0.1f, 0.2f, 0.3f, 0.5f, -3, 1},
                {INFINITY, 0, 0, 1, 0, 0},                   /* not finite */
                {0, 0, 0, 1, NAN, 0},
                {50, 50, 50, 1, 1, 1},                       /* misses the root box */
                {50, 0, 0, -1, 0, 0}};                       /* enters it along x */
            Ray r;
            r.o = v3(odd[k][0], odd[k][1], odd[k][2]);
            r.d = v3(odd[k][3], odd[k][4], odd[k][5]);
            r.tmax = INFINITY;
            bad += bvh_simd_mismatches(&s.bvh, &r, 1.0f, &lanes);
            expected += k <= 1 || k == 9 || k == 10 ? 0 : s.bvh.n_nodes * BVH_WIDTH * paths;
        }
        for (k = 0; k < 80; k++) {          /* through a corner of a box (k < 20: the root's),
                                               where entry and exit meet but for rounding */
            const BvhNode *nd = &s.bvh.nodes[(int)(rng_float(&rng) * (float)s.bvh.n_nodes) % s.bvh.n_nodes];
            const int slot = (int)(rng_float(&rng) * BVH_WIDTH) % BVH_WIDTH;
            float c[3];
            int a;
            Ray r;
            for (a = 0; a < 3; a++) {
                const int hi = rng_float(&rng) < 0.5f;
                c[a] = k < 20 ? (hi ? s.bvh.bmax[a] : s.bvh.bmin[a]) : nd->box[hi * 3 + a][slot];
            }
            if (!isfinite(c[0])) continue;  /* an empty slot */
            r.o = v3(urand(&rng, -3, 3), urand(&rng, -3, 3), urand(&rng, -3, 3));
            r.d = v3_sub(v3(c[0], c[1], c[2]), r.o);
            r.tmax = INFINITY;
            bad += bvh_simd_mismatches(&s.bvh, &r, INFINITY, &lanes);
            expected += s.bvh.n_nodes * BVH_WIDTH * paths;
        }
        for (k = 0; k < 2; k++) {           /* on a plane of the root box, d = 0 across it */
            Ray r;
            r.o = k ? v3(0.0f, s.bvh.bmax[1], 0.0f) : v3(s.bvh.bmin[0], 0.0f, 0.0f);
            r.d = k ? v3(0.3f, 0.0f, -1.0f) : v3(0.0f, 1.0f, 0.5f);
            r.tmax = INFINITY;
            bad += bvh_simd_mismatches(&s.bvh, &r, 1.0f, &lanes);
            expected += s.bvh.n_nodes * BVH_WIDTH * paths;
        }
        scene_release(&s);
    }
    CHECK(t, lanes > 100000 && lanes == expected, "%d children compared, not %d", lanes, expected);
    CHECK(t, bad == 0, "%d of %d children differ between the SIMD (%s) and the scalar slab test",
          bad, lanes, paths == 2 ? "SSE2 and AVX2" : "SSE2");
}

/* The AVX2 traversal's 4-lane triangle filter (bvh_tri_filter_mismatches) against
   the scalar sign test of the watertight test, on every triangle record, and never
   dropping a triangle the scalar test hits; and its whole triangle test (the filter,
   then tri_hit_rest from the filter's lanes) against tri_hit, verdict, t and
   barycentrics bit for bit, also with tmax at the hit and just below: random rays,
   rays aimed at a triangle's vertex or edge midpoint (where U, V or W is 0 in float
   and the filter must leave the triangle to the double-precision test), and rays
   leaving a triangle's centroid (where t's error bound decides); on a soup, the
   grid cube (axis-aligned rays along its faces: exact zeros) and an icosphere.
   Where the processor has no AVX2 nothing is compared, and the test checks that. */
static void test_bvh_avx2_triangle_filter(T *t)
{
    Scene s;
    Rng rng;
    int scene, k, tested = 0, bad = 0;
    rng_seed(&rng, 31, 0);
    for (scene = 0; scene < 3; scene++) {
        const int ok = scene == 0 ? make_soup(&s, &rng, 2000, 10)
                     : scene == 1 ? make_grid_cube(&s, 6) : make_icosphere(&s, 3);
        CHECK(t, ok, "out of memory");
        CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
        for (k = 0; k < 160; k++) {
            Ray r;
            r.o = v3(urand(&rng, -2, 2), urand(&rng, -2, 2), urand(&rng, -2, 2));
            r.d = random_dir(&rng);
            if (k >= 120) {                 /* from a triangle's centroid */
                const Triangle *tr = &s.tris[(int)(rng_float(&rng) * (float)s.n_tris) % s.n_tris];
                r.o = v3_mul(v3_add(v3_add(s.P[tr->v[0]], s.P[tr->v[1]]), s.P[tr->v[2]]),
                             1.0f / 3.0f);
            } else if (k % 3 != 0) {               /* at a vertex (k % 3 == 1) or an edge's middle */
                const Triangle *tr = &s.tris[(int)(rng_float(&rng) * (float)s.n_tris) % s.n_tris];
                const Vec3 a = s.P[tr->v[0]], b = s.P[tr->v[1]];
                const Vec3 aim = k % 3 == 1 ? a : v3_mul(v3_add(a, b), 0.5f);
                if (scene == 1 && k % 2 == 0) {          /* along an axis */
                    const int ax = (int)(rng_float(&rng) * 3) % 3;
                    float c[3], dd[3] = {0.0f, 0.0f, 0.0f};
                    c[0] = aim.x; c[1] = aim.y; c[2] = aim.z;
                    c[ax] += 3.0f;
                    dd[ax] = -1.0f;
                    r.o = v3(c[0], c[1], c[2]);
                    r.d = v3(dd[0], dd[1], dd[2]);
                } else {
                    r.d = v3_sub(aim, r.o);
                }
            }
            r.tmax = INFINITY;
            bad += bvh_tri_filter_mismatches(&s.bvh, &s, &r, &tested);
        }
        scene_release(&s);
    }
    if (bvh_avx2())
        CHECK(t, tested > 200000, "only %d triangles compared", tested);
    else
        CHECK(t, tested == 0, "%d triangles compared without AVX2", tested);
    CHECK(t, bad == 0, "%d of %d triangles: the AVX2 filter differs from the scalar test",
          bad, tested);
}

static void test_bvh_watertight_icosphere(T *t)
{
    Scene s;
    Rng rng;
    int i, k, misses = 0, rays = 0;
    rng_seed(&rng, 12, 0);
    CHECK(t, make_icosphere(&s, 4), "out of memory");
    CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
    /* from outside, within the region that sees every face around the target */
    for (i = 0; i < s.n_tris; i++) {
        for (k = 0; k < 3; k++) {
            Vec3 a = s.P[s.tris[i].v[k]], b = s.P[s.tris[i].v[(k + 1) % 3]];
            Vec3 target = k == 0 ? a : v3_mul(v3_add(a, b), 0.5f);  /* vertex or edge */
            Vec3 o = v3_add(v3_mul(target, urand(&rng, 1.5f, 4.0f)), v3_mul(random_dir(&rng), 0.2f));
            Ray r;
            HitRecord h;
            r.o = o; r.d = v3_sub(target, o); r.tmax = INFINITY;
            rays++;
            if (!bvh_intersect(&s.bvh, &s, &r, &h) || h.t > 1.0f + 1e-5f) misses++;
            r.tmax = 2.0f;
            if (!bvh_occluded(&s.bvh, &s, &r)) misses++;
        }
    }
    scene_release(&s);
    CHECK(t, misses == 0, "%d of %d rays at shared vertices/edges slipped through", misses, rays);
}

/* The cube [-1,1]^3, each face an n x n grid of quads split into two triangles,
   counter-clockwise from outside.  Grid coordinates are k * 2/n - 1: exact floats. */
static int make_grid_cube(Scene *s, int n)
{
    int f, i, j, nv = 0, nt = 0;
    if (!scene_make(s, 6 * (n + 1) * (n + 1), 12 * n * n, 0)) return 0;
    for (f = 0; f < 6; f++) {
        int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3, base = nv;
        float side = (f & 1) ? 1.0f : -1.0f;
        for (j = 0; j <= n; j++)
            for (i = 0; i <= n; i++) {
                float c[3];
                c[axis] = side;
                c[u] = (float)i * 2.0f / (float)n - 1.0f;
                c[v] = (float)j * 2.0f / (float)n - 1.0f;
                s->P[nv++] = v3(c[0], c[1], c[2]);
            }
        for (j = 0; j < n; j++)
            for (i = 0; i < n; i++) {
                int p00 = base + j * (n + 1) + i, p10 = p00 + 1, p01 = p00 + n + 1, p11 = p01 + 1;
                /* (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis */
                int q[2][3];
                q[0][0] = p00; q[0][1] = p10; q[0][2] = p11;
                q[1][0] = p00; q[1][1] = p11; q[1][2] = p01;
                if (side < 0) { int tmp = q[0][1]; q[0][1] = q[0][2]; q[0][2] = tmp;
                                tmp = q[1][1]; q[1][1] = q[1][2]; q[1][2] = tmp; }
                s->tris[nt].v[0] = q[0][0]; s->tris[nt].v[1] = q[0][1]; s->tris[nt].v[2] = q[0][2]; nt++;
                s->tris[nt].v[0] = q[1][0]; s->tris[nt].v[1] = q[1][1]; s->tris[nt].v[2] = q[1][2]; nt++;
            }
    }
    return nt == s->n_tris && nv == s->n_verts;
}

static void test_bvh_watertight_cube(T *t)
{
    const int n = 16;
    Scene s;
    Rng rng;
    int f, i, j, misses = 0, rays = 0, m;
    rng_seed(&rng, 13, 0);
    CHECK(t, make_grid_cube(&s, n), "out of memory");
    CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
    for (f = 0; f < 6; f++) {
        int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
        float side = (f & 1) ? 1.0f : -1.0f;
        /* targets on a half-step lattice: grid vertices, edge and diagonal midpoints,
           all exact floats, strictly inside the face */
        for (j = 1; j < 2 * n; j++)
            for (i = 1; i < 2 * n; i++)
                for (m = 0; m < 2; m++) {
                    float c[3], o[3];
                    Ray r;
                    HitRecord h;
                    c[axis] = side;
                    c[u] = (float)i / (float)n - 1.0f;
                    c[v] = (float)j / (float)n - 1.0f;
                    if (m == 0) {              /* exactly along -normal: flat boxes */
                        o[0] = c[0]; o[1] = c[1]; o[2] = c[2];
                        o[axis] = side * 3.0f;
                    } else {                   /* oblique, from the face's outside */
                        o[axis] = side * urand(&rng, 1.5f, 4.0f);
                        o[u] = c[u] + urand(&rng, -2, 2);
                        o[v] = c[v] + urand(&rng, -2, 2);
                    }
                    r.o = v3(o[0], o[1], o[2]);
                    r.d = v3_sub(v3(c[0], c[1], c[2]), r.o);
                    r.tmax = INFINITY;
                    rays++;
                    if (!bvh_intersect(&s.bvh, &s, &r, &h) || h.t > 1.0f + 1e-5f) misses++;
                    r.tmax = 1.5f;
                    if (!bvh_occluded(&s.bvh, &s, &r)) misses++;
                }
    }
    scene_release(&s);
    CHECK(t, misses == 0, "%d of %d rays at grid vertices/edges slipped through", misses, rays);
}

/* Recursive check of wide node i, whose box (from its parent's slot, or the root box)
   is lo..hi: every used slot's box lies inside it, empty slots are inverted boxes,
   leaves hold 1..BVH_WIDE_LEAF_MAX primitives whose geometry lies inside the leaf's box,
   whose records copy the scene and are sorted by id (triangles first).  seen[p]
   counts the leaves holding primitive p.  Returns the depth below node i, or -1 (and a message). */
static int check_node(const Bvh *b, const Scene *s, int i, const float *lo, const float *hi,
                      int *seen, char *msg, size_t n_msg)
{
    const BvhNode *nd = &b->nodes[i];
    int k, a, depth = 0, used = 0;
    for (k = 0; k < BVH_WIDTH; k++) {
        float clo[3], chi[3];
        const int32_t ref = nd->child[k];
        for (a = 0; a < 3; a++) { clo[a] = nd->box[a][k]; chi[a] = nd->box[3 + a][k]; }
        if (clo[0] == INFINITY) {                  /* empty slot */
            for (a = 0; a < 3; a++)
                if (clo[a] != INFINITY || chi[a] != -INFINITY || ref != 0) {
                    snprintf(msg, n_msg, "node %d slot %d: empty slot not inverted", i, k);
                    return -1;
                }
            continue;
        }
        used++;
        for (a = 0; a < 3; a++)
            if (!(clo[a] <= chi[a]) || clo[a] < lo[a] || chi[a] > hi[a]) {
                snprintf(msg, n_msg, "node %d slot %d: box empty or sticking out", i, k);
                return -1;
            }
        if (ref < 0) {                             /* leaf */
            const int first = (~ref) >> 3, count = ((~ref) & 7) + 1;
            int q, v;
            if (count > BVH_WIDE_LEAF_MAX || first + count > b->n_prims) {
                snprintf(msg, n_msg, "node %d slot %d: bad leaf %d+%d", i, k, first, count);
                return -1;
            }
            for (q = first; q < first + count; q++) {
                const BvhPrim *r = &b->prims[q];
                const int p = r->prim;
                if (p < 0 || p >= s->n_tris + s->n_spheres) {
                    snprintf(msg, n_msg, "leaf record %d: bad primitive id %d", q, p);
                    return -1;
                }
                if (q > first && !(r[-1].prim < p)) {  /* bvh.c reads the last for the kinds */
                    snprintf(msg, n_msg, "leaf record %d: ids not increasing (%d, %d)", q,
                             r[-1].prim, p);
                    return -1;
                }
                seen[p]++;
                for (v = 0; v < 3; v++)
                    for (a = 0; a < 3; a++) {
                        float x, rec;
                        if (p < s->n_tris) {
                            x = v3_get(s->P[s->tris[p].v[v]], a);
                            rec = r->v[3 * v + a];
                        } else {           /* the sphere's extreme points, exactly */
                            const Shape *sh = &s->shapes[s->sphere_shape[p - s->n_tris]];
                            double c = v3_get(sh->center, a), e = v == 0 ? -sh->radius : sh->radius;
                            x = (float)c;
                            rec = r->v[a];
                            if (c + e < clo[a] || c + e > chi[a]) x = NAN;
                        }
                        if (!(x >= clo[a] && x <= chi[a]) || rec != x) {
                            snprintf(msg, n_msg, "leaf record %d: primitive %d outside its box "
                                     "or not copied", q, p);
                            return -1;
                        }
                    }
            }
        } else {                                   /* inner node: after its parent */
            int d;
            if (ref <= i || ref >= b->n_nodes) {
                snprintf(msg, n_msg, "node %d slot %d: bad child %d", i, k, ref);
                return -1;
            }
            if ((d = check_node(b, s, ref, clo, chi, seen, msg, n_msg)) < 0) return -1;
            if (d + 1 > depth) depth = d + 1;
        }
    }
    if (used == 0) {
        snprintf(msg, n_msg, "node %d has no children", i);
        return -1;
    }
    return depth;
}

static void test_bvh_structure(T *t)
{
    Scene s;
    Rng rng;
    int *seen, depth, i, bad = 0;
    char msg[256] = "";
    rng_seed(&rng, 14, 0);
    CHECK(t, make_soup(&s, &rng, 2000, 20), "out of memory");
    CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
    seen = (int *)calloc((size_t)s.bvh.n_prims, sizeof *seen);
    CHECK(t, seen != NULL, "out of memory");
    depth = check_node(&s.bvh, &s, 0, s.bvh.bmin, s.bvh.bmax, seen, msg, sizeof msg);
    for (i = 0; i < s.bvh.n_prims; i++) bad += seen[i] != 1;
    free(seen);
    i = s.bvh.n_prims;
    scene_release(&s);
    CHECK(t, depth >= 0, "%s", msg);
    CHECK(t, i == 2020 && bad == 0, "%d of %d primitives not in exactly one leaf", bad, i);
    CHECK(t, depth < 64, "depth %d", depth);
}

static void test_bvh_deterministic(T *t)
{
    Scene s;
    Bvh b2;
    Rng rng;
    int same;
    rng_seed(&rng, 15, 0);
    CHECK(t, make_soup(&s, &rng, 1500, 10), "out of memory");
    CHECK(t, bvh_build(&s.bvh, &s) && bvh_build(&b2, &s), "bvh_build failed");
    same = s.bvh.n_nodes == b2.n_nodes &&
           memcmp(s.bvh.nodes, b2.nodes, (size_t)b2.n_nodes * sizeof(BvhNode)) == 0 &&
           memcmp(s.bvh.prims, b2.prims, (size_t)b2.n_prims * sizeof(BvhPrim)) == 0;
    bvh_free(&b2);
    scene_release(&s);
    CHECK(t, same, "two builds of the same scene differ");
}

static void test_bvh_degenerate(T *t)
{
    Scene s;
    Rng rng;
    char msg[256] = "";
    int i, k, bad, depth, *seen;
    rng_seed(&rng, 16, 0);
    /* 1. a thousand copies of one triangle: nothing to bin */
    CHECK(t, scene_make(&s, 3, 1000, 0), "out of memory");
    s.P[0] = v3(0, 0, 0); s.P[1] = v3(1, 0, 0); s.P[2] = v3(0, 1, 0);
    for (i = 0; i < 1000; i++)
        for (k = 0; k < 3; k++) s.tris[i].v[k] = k;
    CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed (copies)");
    seen = (int *)calloc(1000, sizeof *seen);
    depth = seen ? check_node(&s.bvh, &s, 0, s.bvh.bmin, s.bvh.bmax, seen, msg, sizeof msg) : -1;
    free(seen);
    bad = compare_with_brute(&s, &rng, 300, msg, sizeof msg);
    scene_release(&s);
    CHECK(t, depth >= 0 && depth < 64, "copies: depth %d %s", depth, msg);
    CHECK(t, bad == 0, "copies: %s", msg);

    /* 2. triangles at x = 2^-i: every binned split peels off a few, so the build
          must fall back to middle splits to stay within the traversal stack */
    CHECK(t, scene_make(&s, 3 * 3000, 3000, 0), "out of memory");
    for (i = 0; i < 3000; i++) {
        float x = ldexpf(1.0f, -(i % 120)) * (1.0f + (float)(i / 120) * 1e-3f);
        s.P[3 * i] = v3(x, -0.5f, -0.5f);
        s.P[3 * i + 1] = v3(x, 0.5f, -0.5f);
        s.P[3 * i + 2] = v3(x, 0.0f, 0.5f);
        for (k = 0; k < 3; k++) s.tris[i].v[k] = 3 * i + k;
    }
    CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed (exponential)");
    seen = (int *)calloc(3000, sizeof *seen);
    depth = seen ? check_node(&s.bvh, &s, 0, s.bvh.bmin, s.bvh.bmax, seen, msg, sizeof msg) : -1;
    free(seen);
    bad = compare_with_brute(&s, &rng, 300, msg, sizeof msg);
    scene_release(&s);
    CHECK(t, depth >= 0 && depth < 64, "exponential: depth %d %s", depth, msg);
    CHECK(t, bad == 0, "exponential: %s", msg);
}

static void test_bvh_empty_and_invalid(T *t)
{
    Scene s;
    Ray r;
    HitRecord h;
    int ok;
    CHECK(t, scene_make(&s, 0, 0, 0), "out of memory");
    CHECK(t, bvh_build(&s.bvh, &s) && s.bvh.n_nodes == 0, "empty scene must build");
    r.o = v3(0, 0, 0); r.d = v3(0, 0, 1); r.tmax = INFINITY;
    ok = !bvh_intersect(&s.bvh, &s, &r, &h) && !bvh_occluded(&s.bvh, &s, &r);
    scene_release(&s);
    CHECK(t, ok, "empty scene reported a hit");

    CHECK(t, scene_make(&s, 3, 1, 0), "out of memory");
    s.tris[0].v[0] = 0; s.tris[0].v[1] = 1; s.tris[0].v[2] = 3;     /* index 3 of 3 */
    ok = bvh_build(&s.bvh, &s);
    CHECK(t, !ok && s.bvh.nodes == NULL && s.bvh.prims == NULL, "out-of-range vertex index accepted");
    s.tris[0].v[2] = 2;
    s.P[1] = v3(NAN, 0, 0);
    ok = bvh_build(&s.bvh, &s);
    scene_release(&s);
    CHECK(t, !ok, "NaN vertex accepted");
}

static void test_bvh_triangle(T *t)
{
    Vec3 p0 = v3(0, 0, 0), p1 = v3(1, 0, 0), p2 = v3(0, 1, 0);
    Ray r;
    float th, b1, b2;
    r.o = v3(0.25f, 0.5f, 2.0f); r.d = v3(0, 0, -0.5f); r.tmax = INFINITY;
    CHECK(t, intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "front hit missed");
    CHECK(t, th == 4.0f && fabsf(b1 - 0.25f) < 1e-7f && fabsf(b2 - 0.5f) < 1e-7f,
          "t %g b %g %g, want 4, 0.25, 0.5", th, b1, b2);
    r.o.z = -2.0f; r.d.z = 0.5f;
    CHECK(t, intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2) && th == 4.0f, "back face missed");
    r.tmax = 4.0f;
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "t == tmax must not hit");
    r.tmax = 4.0001f;
    CHECK(t, intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "t < tmax missed");
    r.o = v3(0.6f, 0.6f, 1.0f); r.d = v3(0, 0, -1); r.tmax = INFINITY;
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "hit outside the triangle");
    r.o = v3(0.2f, 0.2f, 1.0f); r.d = v3(0, 0, 1);
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "hit behind the origin");
    r.o = v3(-1, 0.2f, 0); r.d = v3(1, 0, 0);
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "ray in the plane hit");
    r.o = v3(0.2f, 0.2f, 0); r.d = v3(0.3f, -0.1f, 1);
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "ray from the surface re-hit it");
    r.o = v3(0.5f, 0.0f, 1.0f); r.d = v3(0, 0, -1);                /* on the edge p0 p1 */
    CHECK(t, intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2) && th == 1.0f, "edge point missed");
    r.o = v3(0.0f, 0.0f, 1.0f);                                     /* on the vertex p0 */
    CHECK(t, intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "vertex missed");
    r.o = v3(0.2f, 0.2f, 1.0f);
    CHECK(t, !intersect_triangle(p0, p1, v3(2, 0, 0), &r, &th, &b1, &b2), "degenerate hit");
    r.d = v3(0, 0, 0);
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "zero direction hit");
    r.d = v3(0, 0, -1); r.o.x = NAN;
    CHECK(t, !intersect_triangle(p0, p1, p2, &r, &th, &b1, &b2), "NaN origin hit");
}

static void test_bvh_sphere(T *t)
{
    Vec3 c = v3(1, 2, 3);
    Ray r;
    float th;
    r.o = v3(1, 2, 10); r.d = v3(0, 0, -1); r.tmax = INFINITY;
    CHECK(t, intersect_sphere(c, 2.0f, &r, &th) && th == 5.0f, "outside: t %g, want 5", th);
    r.o = v3(1, 2, 3.5f);
    CHECK(t, intersect_sphere(c, 2.0f, &r, &th) && th == 2.5f, "inside: t %g, want 2.5", th);
    r.d = v3(0, 0, 1);                     /* inside, the centre behind: b > 0, c < 0 */
    CHECK(t, intersect_sphere(c, 2.0f, &r, &th) && th == 1.5f, "inside, moving away: t %g, want 1.5", th);
    r.d = v3(0, 0, -1);
    r.o = v3(1, 2, 10); r.d = v3(0, 0, 1);
    CHECK(t, !intersect_sphere(c, 2.0f, &r, &th), "sphere behind the ray hit");
    r.d = v3(0, 0, -1); r.tmax = 5.0f;
    CHECK(t, !intersect_sphere(c, 2.0f, &r, &th), "t == tmax must not hit");
    r.o = v3(3.5f, 2, 10); r.tmax = INFINITY;
    CHECK(t, !intersect_sphere(c, 2.0f, &r, &th), "ray passing beside hit");
    /* far away and small: the Ray Tracing Gems form keeps t accurate */
    r.o = v3(0, 0, 0); r.d = v3(0, 0, -1);
    CHECK(t, intersect_sphere(v3(0, 0, -1e4f), 1.0f, &r, &th) && fabsf(th - 9999.0f) <= 2e-3f,
          "far sphere: t %.9g, want 9999", th);
    r.o = v3(0.999f, 0, -1e4f + 5.0f);
    CHECK(t, intersect_sphere(v3(0, 0, -1e4f), 1.0f, &r, &th), "grazing hit missed");
    CHECK(t, !intersect_sphere(c, 0.0f, &r, &th) && !intersect_sphere(c, -1.0f, &r, &th),
          "degenerate radius hit");
}

static void test_bvh_surface_point(T *t)
{
    Scene s;
    Ray r;
    HitRecord h;
    SurfacePoint sp;
    int ok;
    CHECK(t, scene_make(&s, 3, 1, 1), "out of memory");
    s.P[0] = v3(0, 0, 0); s.P[1] = v3(1, 0, 0); s.P[2] = v3(0, 1, 0);   /* CCW from +z */
    s.tris[0].v[0] = 0; s.tris[0].v[1] = 1; s.tris[0].v[2] = 2;
    s.shapes[1].center = v3(5, 5, 5); s.shapes[1].radius = 2.0f;
    CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
    r.o = v3(0.25f, 0.5f, 3.0f); r.d = v3(0, 0, -1); r.tmax = INFINITY;
    ok = bvh_intersect(&s.bvh, &s, &r, &h);
    CHECK(t, ok && h.prim == 0, "triangle missed");
    scene_surface_point(&s, &r, &h, &sp);
    CHECK(t, sp.p.x == 0.25f && sp.p.y == 0.5f && sp.p.z == 0.0f, "p (%g %g %g)", sp.p.x, sp.p.y, sp.p.z);
    CHECK(t, sp.ng.x == 0 && sp.ng.y == 0 && sp.ng.z == 1 && sp.ns.z == 1 && sp.shape == 0 && sp.prim == 0,
          "ng (%g %g %g) should be the CCW normal +z", sp.ng.x, sp.ng.y, sp.ng.z);
    s.shapes[0].flip = 1;
    scene_surface_point(&s, &r, &h, &sp);
    CHECK(t, sp.ng.z == -1 && sp.ns.z == -1, "flip must negate ng (got %g)", sp.ng.z);
    /* shading normals: interpolated, normalised, and ng turned to their side */
    s.shapes[0].flip = 0;
    s.shapes[0].has_normals = 1;
    s.N = (Vec3 *)calloc(3, sizeof(Vec3));
    CHECK(t, s.N != NULL, "out of memory");
    s.N[0] = v3(0, 0, -1); s.N[1] = v3(1, 0, -1); s.N[2] = v3(0, 0, -1);
    scene_surface_point(&s, &r, &h, &sp);
    {   /* b = (0.25, 0.25, 0.5): ns = normalize(0.25, 0, -1) */
        float l = sqrtf(0.25f * 0.25f + 1.0f);
        CHECK(t, fabsf(sp.ns.x - 0.25f / l) < 1e-6f && fabsf(sp.ns.z + 1.0f / l) < 1e-6f,
              "ns (%g %g %g)", sp.ns.x, sp.ns.y, sp.ns.z);
        CHECK(t, sp.ng.z == -1, "ng must face the shading normal");
    }
    /* the sphere: outward normal, inward when flipped */
    r.o = v3(5, 5, 10); r.d = v3(0, 0, -2);
    ok = bvh_intersect(&s.bvh, &s, &r, &h);
    CHECK(t, ok && h.prim == 1 && h.t == 1.5f, "sphere: hit %d prim %d t %g", ok, h.prim, h.t);
    scene_surface_point(&s, &r, &h, &sp);
    CHECK(t, sp.shape == 1 && sp.prim == 1 && sp.p.z == 7.0f && sp.ng.z == 1.0f && sp.ns.z == 1.0f,
          "sphere point (%g %g %g) normal z %g", sp.p.x, sp.p.y, sp.p.z, sp.ng.z);
    s.shapes[1].flip = 1;
    scene_surface_point(&s, &r, &h, &sp);
    scene_release(&s);
    CHECK(t, sp.ng.z == -1.0f, "flipped sphere normal must point inwards");
}

/* Rays spawned with offset_ray_origin never re-hit their own surface: leaving a
   convex mesh misses everything; entering it hits another triangle. */
static void test_bvh_offset(T *t)
{
    static const float shift[2][3] = {{0, 0, 0}, {1000, -500, 200}};
    Rng rng;
    int pass, k, i, bad = 0, rays = 0;
    rng_seed(&rng, 17, 0);
    for (pass = 0; pass < 2; pass++) {
        Scene s;
        CHECK(t, make_icosphere(&s, 3), "out of memory");
        for (i = 0; i < s.n_verts; i++)
            s.P[i] = v3_add(s.P[i], v3(shift[pass][0], shift[pass][1], shift[pass][2]));
        CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
        for (k = 0; k < 4000; k++) {
            Vec3 c = v3(shift[pass][0], shift[pass][1], shift[pass][2]);
            Vec3 dir = random_dir(&rng), w;
            Ray r;
            HitRecord h, h2;
            SurfacePoint sp;
            float cos_w;
            r.o = v3_add(c, v3_mul(dir, 3.0f));
            r.d = v3_sub(v3_add(c, v3_mul(random_dir(&rng), 0.5f)), r.o);
            r.tmax = INFINITY;
            if (!bvh_intersect(&s.bvh, &s, &r, &h)) { bad++; continue; }
            scene_surface_point(&s, &r, &h, &sp);
            if (v3_dot(sp.ng, v3_sub(sp.p, c)) <= 0) { bad++; continue; }   /* outward? */
            /* leave: directions down to grazing */
            w = random_dir(&rng);
            cos_w = v3_dot(w, sp.ng);
            if (cos_w < 0) w = v3_sub(w, v3_mul(sp.ng, 2 * cos_w));
            if (k % 4 == 0) w = v3_norm(v3_add(v3_sub(w, v3_mul(sp.ng, v3_dot(w, sp.ng))),
                                               v3_mul(sp.ng, 1e-3f)));
            r.o = offset_ray_origin(sp.p, sp.ng, w); r.d = w; r.tmax = INFINITY;
            rays++;
            if (bvh_intersect(&s.bvh, &s, &r, &h2) || bvh_occluded(&s.bvh, &s, &r)) bad++;
            /* enter */
            w = v3_neg(w);
            r.o = offset_ray_origin(sp.p, sp.ng, w); r.d = w;
            rays++;
            if (!bvh_intersect(&s.bvh, &s, &r, &h2) || h2.prim == h.prim) bad++;
        }
        scene_release(&s);
    }
    /* a huge ground triangle hit near the origin */
    {
        Scene s;
        CHECK(t, scene_make(&s, 3, 1, 0), "out of memory");
        s.P[0] = v3(-1e5f, 0, -1e5f); s.P[1] = v3(0, 0, 1e5f); s.P[2] = v3(1e5f, 0, -1e5f);
        s.tris[0].v[0] = 0; s.tris[0].v[1] = 1; s.tris[0].v[2] = 2;
        CHECK(t, bvh_build(&s.bvh, &s), "bvh_build failed");
        for (k = 0; k < 2000; k++) {
            Ray r;
            HitRecord h, h2;
            SurfacePoint sp;
            Vec3 w = random_dir(&rng);
            r.o = v3(urand(&rng, -3, 3), 2.0f, urand(&rng, -3, 3));
            r.d = v3(urand(&rng, -1, 1), -1.0f, urand(&rng, -1, 1));
            r.tmax = INFINITY;
            if (!bvh_intersect(&s.bvh, &s, &r, &h)) { bad++; continue; }
            scene_surface_point(&s, &r, &h, &sp);
            if (v3_dot(w, sp.ng) < 0) w = v3_neg(w);
            r.o = offset_ray_origin(sp.p, sp.ng, w); r.d = w;
            rays++;
            if (bvh_intersect(&s.bvh, &s, &r, &h2)) bad++;
            /* from p itself, exactly on the plane y = 0, at a grazing angle: the true
               t is 0, so only the error bound on t keeps rounding from a hit */
            r.o = sp.p;
            r.d = v3(urand(&rng, -1, 1), urand(&rng, -0.01f, 0.01f), urand(&rng, -1, 1));
            rays++;
            if (sp.p.y != 0.0f || bvh_intersect(&s.bvh, &s, &r, &h2)) bad++;
        }
        scene_release(&s);
    }
    CHECK(t, bad == 0, "%d of %d spawned rays re-hit their surface or missed", bad, rays);
}

/* ======================================================================
   PLY tests
   ====================================================================== */
typedef struct { unsigned char b[4096]; size_t n; int big; } Bytes;

static void put(Bytes *o, const void *p, size_t n)
{
    size_t i;
    for (i = 0; i < n && o->n < sizeof o->b; i++) {     /* host is little-endian or not: */
        size_t k = o->big ? n - 1 - i : i;               /* we write from an integer */
        o->b[o->n++] = ((const unsigned char *)p)[k];
    }
}
static void put_text(Bytes *o, const char *s)
{
    size_t n = strlen(s);
    if (o->n + n <= sizeof o->b) { memcpy(o->b + o->n, s, n); o->n += n; }
}
/* Values are put byte by byte from their little-endian image. */
static void put_u32(Bytes *o, uint32_t v)
{ unsigned char c[4]; c[0] = v & 255; c[1] = (v >> 8) & 255; c[2] = (v >> 16) & 255;
  c[3] = (unsigned char)(v >> 24); put(o, c, 4); }
static void put_u16(Bytes *o, unsigned v)
{ unsigned char c[2]; c[0] = v & 255; c[1] = (v >> 8) & 255; put(o, c, 2); }
static void put_u8(Bytes *o, unsigned v) { unsigned char c = (unsigned char)v; put(o, &c, 1); }
static void put_f32(Bytes *o, float f) { uint32_t w; memcpy(&w, &f, 4); put_u32(o, w); }
static void put_f64(Bytes *o, double d)
{
    uint64_t w;
    unsigned char c[8];
    int i;
    memcpy(&w, &d, 8);
    for (i = 0; i < 8; i++) c[i] = (unsigned char)(w >> (8 * i));
    put(o, c, 8);
}

static const char *write_bytes(T *t, const char *name, const Bytes *o)
{
    const char *p = test_path(t, name);
    FILE *f = fopen(p, "wb");
    if (f) { fwrite(o->b, 1, o->n, f); fclose(f); }
    return p;
}

static void test_ply_ascii(T *t)
{
    const char *p = test_write_file(t, "ply_ascii.ply",
        "ply\nformat ascii 1.0\ncomment a pyramid, with a colour to skip\nobj_info x\n"
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 0\n0.5 0.5 1e0 7\n"
        "3 0 1 4\r\n4 0 1 2 3\n");
    PlyMesh m;
    Error err;
    static const int32_t want[3] = {0, 1, 4}, want_q[4] = {0, 1, 3, 2};
    int ok = ply_read(p, &m, &err), same;
    CHECK(t, ok, "ply_read failed: %s", err.msg);
    same = m.n_verts == 5 && m.n_tris == 1 && m.n_quads == 1 && m.N == NULL &&
           memcmp(m.idx, want, sizeof want) == 0 && memcmp(m.quads, want_q, sizeof want_q) == 0 &&
           m.P[12] == 0.5f && m.P[13] == 0.5f && m.P[14] == 1.0f && m.P[3] == 1.0f;
    ply_free(&m);
    CHECK(t, same, "wrong mesh (the quad 0 1 2 3 must become the patch 0 1 3 2)");
}

/* Binary file with normals, skipped properties of every kind and an extra element;
   big = 1 writes it big-endian with doubles and the vertex_index spelling. */
static void make_binary(Bytes *o, int big)
{
    int i;
    static const float P[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    memset(o, 0, sizeof *o);
    put_text(o, big ? "ply\nformat binary_big_endian 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
    put_text(o, "element vertex 4\n");
    put_text(o, big ? "property double x\nproperty double y\nproperty double z\n"
                    : "property float32 x\nproperty float32 y\nproperty float32 z\n");
    put_text(o, "property short junk\nproperty float nx\nproperty float ny\nproperty float nz\n"
                "property list uchar double extra\n"
                "element edge 1\nproperty int vertex1\nproperty int vertex2\n");
    put_text(o, big ? "element face 2\nproperty list ushort uint16 vertex_index\n"
                    : "element face 2\nproperty list uint8 uint32 vertex_indices\n");
    put_text(o, "property int flags\nend_header\n");
    o->big = big;
    for (i = 0; i < 4; i++) {
        if (big) { put_f64(o, P[i][0]); put_f64(o, P[i][1]); put_f64(o, P[i][2]); }
        else { put_f32(o, P[i][0]); put_f32(o, P[i][1]); put_f32(o, P[i][2]); }
        put_u16(o, 0xBEEF);
        put_f32(o, 0); put_f32(o, 0); put_f32(o, (float)(i + 1));
        put_u8(o, 2); put_f64(o, 1.5); put_f64(o, -2.5);
    }
    put_u32(o, 0); put_u32(o, 1);                       /* the edge */
    if (big) { put_u16(o, 3); put_u16(o, 0); put_u16(o, 1); put_u16(o, 2); }
    else { put_u8(o, 3); put_u32(o, 0); put_u32(o, 1); put_u32(o, 2); }
    put_u32(o, 77);
    if (big) { put_u16(o, 4); put_u16(o, 3); put_u16(o, 2); put_u16(o, 1); put_u16(o, 0); }
    else { put_u8(o, 4); put_u32(o, 3); put_u32(o, 2); put_u32(o, 1); put_u32(o, 0); }
    put_u32(o, 78);
}

static void test_ply_binary(T *t)
{
    static const int32_t want[3] = {0, 1, 2}, want_q[4] = {3, 2, 0, 1};   /* face 3 2 1 0 */
    int big;
    for (big = 0; big < 2; big++) {
        Bytes o;
        PlyMesh m;
        Error err;
        const char *p;
        int ok, same;
        make_binary(&o, big);
        p = write_bytes(t, big ? "ply_be.ply" : "ply_le.ply", &o);
        ok = ply_read(p, &m, &err);
        CHECK(t, ok, "%s: ply_read failed: %s", big ? "big" : "little", err.msg);
        same = m.n_verts == 4 && m.n_tris == 1 && m.n_quads == 1 && m.N != NULL &&
               memcmp(m.idx, want, sizeof want) == 0 && memcmp(m.quads, want_q, sizeof want_q) == 0 &&
               m.P[6] == 1.0f && m.P[7] == 1.0f && m.P[8] == 0.0f && m.N[11] == 4.0f && m.N[9] == 0.0f;
        ply_free(&m);
        CHECK(t, same, "%s-endian: wrong mesh", big ? "big" : "little");
    }
}

static void test_ply_roundtrip(T *t)
{
    static const float P[5 * 3] = {0, 0, 0, 1.5f, -2, 3, 1e-8f, 4e6f, -0.125f, 7, 8, 9, -1, -2, -3};
    static const int32_t idx[2 * 3] = {0, 1, 2, 4, 3, 0};
    const char *p = test_path(t, "ply_roundtrip.ply");
    PlyMesh m;
    Error err;
    int ok, same;
    CHECK(t, ply_write_binary(p, P, 5, idx, 2), "ply_write_binary failed");
    ok = ply_read(p, &m, &err);
    CHECK(t, ok, "re-read failed: %s", err.msg);
    same = m.n_verts == 5 && m.n_tris == 2 && memcmp(m.P, P, sizeof P) == 0 &&
           memcmp(m.idx, idx, sizeof idx) == 0;
    ply_free(&m);
    CHECK(t, same, "round trip changed the mesh");
    CHECK(t, !ply_write_binary(test_path(t, "no/such/dir/x.ply"), P, 5, idx, 2),
          "writing into a missing directory must fail");
}

#define HDR_V "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
#define HDR_F "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
#define VERTS "0 0 0\n1 0 0\n0 1 0\n"

static void test_ply_errors(T *t)
{
    static const struct { const char *name, *text, *line, *words; } cases[] = {
        {"e_magic.ply", "plx\nformat ascii 1.0\n", ":1:", "not a PLY"},
        {"e_empty.ply", "", ":1:", "empty"},
        {"e_format.ply", "ply\nformat foo 1.0\n" HDR_F, ":2:", "unknown format"},
        {"e_version.ply", "ply\nformat ascii 2.0\n" HDR_F, ":2:", "format"},
        {"e_noformat.ply", "ply\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
         ":4:", "no format"},
        {"e_noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", ":3:", "no end_header"},
        {"e_keyword.ply", "ply\nformat ascii 1.0\nelemnt vertex 3\n", ":3:", "unknown keyword"},
        {"e_negative.ply", "ply\nformat ascii 1.0\nelement vertex -3\n", ":3:", "negative element count"},
        {"e_badcount.ply", "ply\nformat ascii 1.0\nelement vertex 3x\n", ":3:", "bad element count"},
        {"e_type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty flot x\n", ":4:",
         "unknown property type"},
        {"e_floatcount.ply", "ply\nformat ascii 1.0\nelement face 3\nproperty list float int vertex_indices\n",
         ":4:", "must be an integer"},
        {"e_early.ply", "ply\nformat ascii 1.0\nproperty float x\n", ":3:", "property before any element"},
        {"e_dup.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\n",
         ":5:", "duplicate property"},
        {"e_absurd.ply", "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\n"
         "property float y\nproperty float z\n" HDR_F VERTS "3 0 1 2\n", ":3:", "does not fit"},
        {"e_noface.ply", HDR_V "end_header\n" VERTS, ":7:", "no element face"},
        {"e_novert.ply", "ply\nformat ascii 1.0\n" HDR_F "3 0 1 2\n", ":5:", "no element vertex"},
        {"e_missing_x.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float y\n"
         "property float z\n" HDR_F "0 0\n1 0\n0 1\n3 0 1 2\n", ":3:", "lacks property x"},
        {"e_someN.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nproperty float nx\n" HDR_F "0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n", ":3:",
         "nx ny nz"},
        {"e_noindices.ply", HDR_V "element face 1\nproperty list uchar int corners\nend_header\n"
         VERTS "3 0 1 2\n", ":7:", "no vertex_indices"},
        {"e_trunc.ply", HDR_V HDR_F "0      0      0\n1      0      0\n", ":12:", "truncated"},
        {"e_short.ply", HDR_V HDR_F "0 0 0\n1 0 0\n", ":3:", "3 rows need at least 18 bytes"},
        {"e_faces.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1\n", ":7:", "3 rows need at least 24 bytes"},
        {"e_range.ply", HDR_V HDR_F VERTS "3 0 1 3\n", ":13:", "out of range"},
        {"e_negindex.ply", HDR_V HDR_F VERTS "3 0 -1 2\n", ":13:", "out of range"},
        {"e_pentagon.ply", HDR_V HDR_F VERTS "5 0 1 2 0 1\n", ":13:", "5 vertices"},
        {"e_count300.ply", HDR_V HDR_F VERTS "300 0 1 2\n", ":13:", "out of range for its type"},
        {"e_nan.ply", HDR_V HDR_F "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", ":11:", "not a finite"},
        {"e_inf.ply", HDR_V HDR_F "0 0 0\n1 0 0\n0 1e39 0\n3 0 1 2\n", ":12:", "not a finite"},
        {"e_number.ply", HDR_V HDR_F "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", ":11:", "bad number"},
        {"e_fraction.ply", HDR_V HDR_F VERTS "3 0 1.5 2\n", ":13:", "bad integer"},
    };
    int i;
    for (i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
        const char *p = test_write_file(t, cases[i].name, cases[i].text);
        PlyMesh m;
        Error err;
        int ok;
        memset(&err, 0, sizeof err);
        ok = ply_read(p, &m, &err);
        if (ok) ply_free(&m);
        CHECK(t, !ok, "%s: accepted", cases[i].name);
        CHECK(t, m.P == NULL && m.idx == NULL, "%s: mesh not cleared", cases[i].name);
        CHECK(t, strstr(err.msg, p) == err.msg && strstr(err.msg, cases[i].line) &&
                 strstr(err.msg, cases[i].words) && !strchr(err.msg, '\n'),
              "%s: message '%s' lacks '%s' or '%s'", cases[i].name, err.msg, cases[i].line,
              cases[i].words);
    }
    {   /* binary: a truncated file and an absurd count (element line) */
        Bytes o;
        PlyMesh m;
        Error err;
        const char *p;
        make_binary(&o, 0);
        o.n -= 3;
        p = write_bytes(t, "e_trunc_bin.ply", &o);
        CHECK(t, !ply_read(p, &m, &err) && strstr(err.msg, "truncated") && strstr(err.msg, ":15:"),
              "truncated binary: '%s'", err.msg);
        memset(&o, 0, sizeof o);
        put_text(&o, "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                     "property float x\nproperty float y\nproperty float z\n"
                     "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
        put_f32(&o, 1); put_f32(&o, 2); put_f32(&o, 3);
        p = write_bytes(t, "e_absurd_bin.ply", &o);
        CHECK(t, !ply_read(p, &m, &err) && strstr(err.msg, "does not fit") && strstr(err.msg, ":3:"),
              "absurd binary count: '%s'", err.msg);
        p = test_path(t, "e_does_not_exist.ply");
        CHECK(t, !ply_read(p, &m, &err) && strstr(err.msg, p) && strstr(err.msg, "cannot read"),
              "missing file: '%s'", err.msg);
    }
}

/* Random corruption of valid files: ply_read must return a valid mesh or a
   one-line error naming the file, and never crash (the suite runs under ASan). */
static void test_ply_fuzz(T *t)
{
    Bytes base[2], o;
    Rng rng;
    int k, accepted = 0, rejected = 0;
    const char *text = HDR_V HDR_F VERTS "3 0 1 2\n";
    make_binary(&base[0], 0);
    memset(&base[1], 0, sizeof base[1]);
    put_text(&base[1], text);
    rng_seed(&rng, 18, 0);
    for (k = 0; k < 600; k++) {
        PlyMesh m;
        Error err;
        const char *p;
        int n_mut = 1 + (int)(rng_float(&rng) * 4), j, i;
        o = base[k & 1];
        for (j = 0; j < n_mut; j++) {
            size_t at = (size_t)(rng_float(&rng) * (float)o.n);
            float u = rng_float(&rng);
            if (u < 0.5f) o.b[at] = (unsigned char)rng_u32(&rng);           /* random byte */
            else if (u < 0.7f) o.b[at] = (unsigned char)"0123456789 -\n9"[rng_u32(&rng) % 14];
            else if (u < 0.85f) o.n = at;                                     /* truncate */
            else o.b[at] ^= (unsigned char)(1u << (rng_u32(&rng) % 8));      /* bit flip */
        }
        p = write_bytes(t, "fuzz.ply", &o);
        memset(&err, 0, sizeof err);
        if (ply_read(p, &m, &err)) {
            accepted++;
            for (i = 0; i < 3 * m.n_tris; i++)
                CHECK(t, m.idx[i] >= 0 && m.idx[i] < m.n_verts, "case %d: index out of range", k);
            for (i = 0; i < 4 * m.n_quads; i++)
                CHECK(t, m.quads[i] >= 0 && m.quads[i] < m.n_verts, "case %d: quad index out of range", k);
            for (i = 0; i < 3 * m.n_verts; i++)
                CHECK(t, isfinite(m.P[i]), "case %d: non-finite vertex accepted", k);
            ply_free(&m);
        } else {
            rejected++;
            CHECK(t, strstr(err.msg, p) == err.msg && !strchr(err.msg, '\n'),
                  "case %d: bad message '%s'", k, err.msg);
        }
    }
    CHECK(t, accepted > 0 && rejected > 0, "fuzz: %d accepted, %d rejected", accepted, rejected);
}

const TestCase tests_bvh[] = {
    {"bvh_vs_brute", test_bvh_vs_brute},
    {"bvh_exact_adversarial", test_bvh_exact_adversarial},
    {"bvh_hit_floor", test_bvh_hit_floor},
    {"bvh_simd_matches_scalar", test_bvh_simd_matches_scalar},
    {"bvh_avx2_triangle_filter", test_bvh_avx2_triangle_filter},
    {"bvh_watertight_icosphere", test_bvh_watertight_icosphere},
    {"bvh_watertight_cube", test_bvh_watertight_cube},
    {"bvh_structure", test_bvh_structure},
    {"bvh_deterministic", test_bvh_deterministic},
    {"bvh_degenerate", test_bvh_degenerate},
    {"bvh_empty_and_invalid", test_bvh_empty_and_invalid},
    {"bvh_triangle", test_bvh_triangle},
    {"bvh_sphere", test_bvh_sphere},
    {"bvh_surface_point", test_bvh_surface_point},
    {"bvh_offset", test_bvh_offset},
    {"ply_ascii", test_ply_ascii},
    {"ply_binary", test_ply_binary},
    {"ply_roundtrip", test_ply_roundtrip},
    {"ply_errors", test_ply_errors},
    {"ply_fuzz", test_ply_fuzz},
    {NULL, NULL}
};
