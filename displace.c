/* displace.c - pbrt-v4's displaced "plymesh" ("texture displacement",
   "float edgelength"), built once at load time.

   A PLY mesh with a float displacement texture d is, as pbrt-v4's
   TriQuadMesh::Displace:
     1. made of triangles only: a quad (ply.c's p00 p10 p01 p11 = the face's
        0 1 3 2) becomes the face's (0, 1, 2) and (0, 2, 3);
     2. given vertex normals when the file has none: each vertex the normalised
        sum of the unit normals (p1 - p0) x (p2 - p1) of its triangles;
     3. refined: a triangle with an edge at least `edgelength` long (measured
        between the world-space points, pbrt-v4's render space: the same
        lengths) is split at the midpoint of its longest edge into two, and each
        half again, until every edge is shorter; a midpoint is shared by the two
        triangles of its edge (a hash of the edge's two indices), its normal the
        normalised sum of the edge's two normals, its uv their mean;
     4. displaced: each vertex moves along its normal (in object space, the
        normal as the file gives it or as step 2 made it, not renormalised) by
        d evaluated at its uv and at its object-space position (pbrt-v4 hands
        the texture the object-space point);
     5. given new normals by step 2's rule; they are the mesh's shading normals.
   The mesh is then an ordinary triangle mesh (geometry.c add_mesh).  Used by
   geometry.c's plymesh builder: ply_displace(&mesh, ...) between ply_read and
   add_mesh. */
#include "specnee.h"
#include "parser.h"   /* MAX_ELEMENTS */
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The growing mesh and the table of split edges (open addressing on the pair). */
typedef struct {
    float *P, *N, *UV;
    int nv, cap_v;
    int32_t *idx;
    int nt, cap_t;
    uint64_t *key; int32_t *mid; size_t cap_h;   /* edge (lo << 32 | hi) -> midpoint */
    size_t n_h;
    const Xform *ctm;
    double edge;
    long max_tris;
} Refiner;

static int grow_to(void **a, int *cap, int need, size_t sz)
{
    void *q;
    int c = *cap ? *cap : 64;
    if (need <= *cap) return 1;
    while (c < need) c = c > (1 << 29) ? need : 2 * c;
    q = realloc(*a, (size_t)c * sz);
    if (!q) return 0;
    *a = q;
    *cap = c;
    return 1;
}

static Vec3 vert(const float *a, int i) { return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }

/* Step 2 and 5: the normalised sum of the unit triangle normals at each vertex
   (a vertex no triangle of non-zero area touches keeps (0, 0, 1)). */
static void compute_normals(const float *P, int nv, const int32_t *idx, int nt, float *N)
{
    int i, k;
    memset(N, 0, sizeof(float) * 3 * (size_t)nv);
    for (i = 0; i < nt; i++) {
        const int32_t *t = idx + 3 * i;
        Vec3 p0 = vert(P, t[0]), p1 = vert(P, t[1]), p2 = vert(P, t[2]);
        Vec3 c = v3_cross(v3_sub(p1, p0), v3_sub(p2, p1));
        if (!(v3_dot(c, c) > 0.0f)) continue;
        c = v3_norm(c);
        for (k = 0; k < 3; k++) {
            N[3 * t[k]] += c.x;
            N[3 * t[k] + 1] += c.y;
            N[3 * t[k] + 2] += c.z;
        }
    }
    for (i = 0; i < nv; i++) {
        Vec3 n = vert(N, i);
        n = v3_dot(n, n) > 0.0f ? v3_norm(n) : v3(0, 0, 1);
        N[3 * i] = n.x; N[3 * i + 1] = n.y; N[3 * i + 2] = n.z;
    }
}

static double world_dist(const Refiner *r, int a, int b)
{
    Vec3 pa = xf_point(r->ctm, vert(r->P, a)), pb = xf_point(r->ctm, vert(r->P, b));
    return v3_len(v3_sub(pa, pb));
}

/* The midpoint vertex of edge (a, b): found in the table or made; -1: no memory. */
static int midpoint(Refiner *r, int a, int b)
{
    uint64_t key = a < b ? ((uint64_t)a << 32 | (uint32_t)b) : ((uint64_t)b << 32 | (uint32_t)a);
    size_t h, i;
    int m, k;
    Vec3 n;
    if (2 * (r->n_h + 1) > r->cap_h) {                 /* rehash at half full */
        size_t nc = r->cap_h ? 2 * r->cap_h : 1024, j;
        uint64_t *nk = (uint64_t *)malloc(nc * sizeof(uint64_t));
        int32_t *nm = (int32_t *)malloc(nc * sizeof(int32_t));
        if (!nk || !nm) { free(nk); free(nm); return -1; }
        for (j = 0; j < nc; j++) nk[j] = UINT64_MAX;
        for (j = 0; j < r->cap_h; j++)
            if (r->key[j] != UINT64_MAX) {
                for (h = hash_u64(r->key[j], 0) & (nc - 1); nk[h] != UINT64_MAX; h = (h + 1) & (nc - 1)) {}
                nk[h] = r->key[j];
                nm[h] = r->mid[j];
            }
        free(r->key); free(r->mid);
        r->key = nk; r->mid = nm; r->cap_h = nc;
    }
    for (i = hash_u64(key, 0) & (r->cap_h - 1); r->key[i] != UINT64_MAX; i = (i + 1) & (r->cap_h - 1))
        if (r->key[i] == key) return r->mid[i];
    if (r->nv >= MAX_ELEMENTS) return -1;
    if (r->nv + 1 > r->cap_v) {                        /* P, N, UV share one capacity */
        int c1 = r->cap_v, c2 = r->cap_v, c3 = r->cap_v;
        if (!grow_to((void **)&r->P, &c1, r->nv + 1, 3 * sizeof(float)) ||
            !grow_to((void **)&r->N, &c2, r->nv + 1, 3 * sizeof(float)) ||
            !grow_to((void **)&r->UV, &c3, r->nv + 1, 2 * sizeof(float)))
            return -1;
        r->cap_v = c1;
    }
    m = r->nv++;
    for (k = 0; k < 3; k++) r->P[3 * m + k] = 0.5f * (r->P[3 * a + k] + r->P[3 * b + k]);
    for (k = 0; k < 2; k++) r->UV[2 * m + k] = 0.5f * (r->UV[2 * a + k] + r->UV[2 * b + k]);
    n = v3_add(vert(r->N, a), vert(r->N, b));
    if (v3_dot(n, n) > 0.0f) n = v3_norm(n);
    r->N[3 * m] = n.x; r->N[3 * m + 1] = n.y; r->N[3 * m + 2] = n.z;
    r->key[i] = key;
    r->mid[i] = m;
    r->n_h++;
    return m;
}

/* Step 3 for one triangle: 0 when out of memory or past max_tris. */
static int refine(Refiner *r, int v0, int v1, int v2)
{
    double d01 = world_dist(r, v0, v1), d12 = world_dist(r, v1, v2), d20 = world_dist(r, v2, v0);
    int a, b, c, m;
    if (d01 < r->edge && d12 < r->edge && d20 < r->edge) {
        if (r->nt >= r->max_tris || !grow_to((void **)&r->idx, &r->cap_t, r->nt + 1, 3 * sizeof(int32_t)))
            return 0;
        r->idx[3 * r->nt] = v0; r->idx[3 * r->nt + 1] = v1; r->idx[3 * r->nt + 2] = v2;
        r->nt++;
        return 1;
    }
    /* the longest edge first (a, b), as pbrt-v4 orders the three */
    if (d01 > d12) { if (d01 > d20) { a = v0; b = v1; c = v2; } else { a = v2; b = v0; c = v1; } }
    else if (d12 > d20) { a = v1; b = v2; c = v0; }
    else { a = v2; b = v0; c = v1; }
    m = midpoint(r, a, b);
    return m >= 0 && refine(r, a, m, c) && refine(r, m, b, c);
}

/* A lower bound on the triangles refinement makes: each ends with edges below
   e, so with an area below (sqrt 3 / 4) e^2; the world area over that. */
static double min_triangles(const float *P, const int32_t *idx, int nt, const Xform *ctm, double e)
{
    double area = 0.0;
    int i;
    for (i = 0; i < nt; i++) {
        Vec3 p0 = xf_point(ctm, vert(P, idx[3 * i])), p1 = xf_point(ctm, vert(P, idx[3 * i + 1]));
        Vec3 p2 = xf_point(ctm, vert(P, idx[3 * i + 2]));
        area += 0.5 * v3_len(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
    }
    return area / (0.4330127 * e * e);
}

int ply_displace(PlyMesh *mesh, const Xform *world_from_obj, float edgelength,
                 const Texture *textures, int tex, Error *err)
{
    Refiner r;
    int i, nt0 = mesh->n_tris + 2 * mesh->n_quads, ok = 1;
    int32_t *tris = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)(nt0 + 1));
    memset(&r, 0, sizeof r);
    if (!tris) { error_set(err, NULL, 0, "out of memory displacing the mesh"); return 0; }
    memcpy(tris, mesh->idx, sizeof(int32_t) * 3 * (size_t)mesh->n_tris);
    for (i = 0; i < mesh->n_quads; i++) {              /* step 1 */
        const int32_t *q = mesh->quads + 4 * i;
        int32_t *t = tris + 3 * (mesh->n_tris + 2 * i);
        t[0] = q[0]; t[1] = q[1]; t[2] = q[3];
        t[3] = q[0]; t[4] = q[3]; t[5] = q[2];
    }
    {
        double least = min_triangles(mesh->P, tris, nt0, world_from_obj, edgelength);
        if (!(least <= MAX_ELEMENTS)) {
            free(tris);
            error_set(err, NULL, 0, "edgelength %g makes at least %.3g triangles (at most %d)",
                      (double)edgelength, least, MAX_ELEMENTS);
            return 0;
        }
    }
    r.nv = r.cap_v = mesh->n_verts;
    r.P = mesh->P; r.UV = mesh->UV; r.N = mesh->N;
    mesh->P = mesh->UV = mesh->N = NULL;
    if (!r.N) {                                        /* step 2 */
        r.N = (float *)malloc(sizeof(float) * 3 * (size_t)(r.nv + 1));
        if (r.N) compute_normals(r.P, r.nv, tris, nt0, r.N);
    }
    r.ctm = world_from_obj;
    r.edge = edgelength;
    r.max_tris = MAX_ELEMENTS;
    for (i = 0; ok && r.N && i < nt0; i++) ok = refine(&r, tris[3 * i], tris[3 * i + 1], tris[3 * i + 2]);
    free(tris);
    free(r.key); free(r.mid);
    if (ok && r.N) {
        for (i = 0; i < r.nv; i++) {                   /* step 4 */
            SurfacePoint sp;
            float d;
            memset(&sp, 0, sizeof sp);
            sp.p = vert(r.P, i);
            sp.u = r.UV[2 * i];
            sp.v = r.UV[2 * i + 1];
            d = tex_eval(textures, tex, &sp, 550.0f);
            r.P[3 * i] += d * r.N[3 * i];
            r.P[3 * i + 1] += d * r.N[3 * i + 1];
            r.P[3 * i + 2] += d * r.N[3 * i + 2];
        }
        compute_normals(r.P, r.nv, r.idx, r.nt, r.N);  /* step 5 */
    }
    free(mesh->idx); free(mesh->quads);
    mesh->P = r.P; mesh->N = r.N; mesh->UV = r.UV; mesh->n_verts = r.nv;
    mesh->idx = r.idx; mesh->n_tris = r.nt;
    mesh->quads = NULL; mesh->n_quads = 0;
    if (!ok || !mesh->N) {
        error_set(err, NULL, 0, "edgelength %g makes more than %d triangles or vertices (or out of memory)",
                  (double)edgelength, MAX_ELEMENTS);
        return 0;
    }
    return 1;
}
