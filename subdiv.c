/* subdiv.c - Loop subdivision surfaces (Shape "loopsubdiv"): a control mesh of
   triangles refined at load time into the triangle mesh that geometry.c adds.

   WHAT IT IMPLEMENTS (specnee.h section 9b)
     loop_subdivide  `levels` steps of Loop's scheme, then every vertex moved to its
                     point on the limit surface, with the limit surface's normal
                     there (what pbrt-v4's LoopSubdivide makes of the same mesh)
     subdiv_free     releases a SubdivMesh

   THE SCHEME (C. Loop, "Smooth Subdivision Surfaces Based on Triangles", M.S.
   thesis, University of Utah, 1987; the boundary rules as pbrt-v4 applies them)
   One step splits every triangle in four.  Each edge gets a new "odd" vertex; each
   old "even" vertex moves.  The triangle (v0, v1, v2), with e0 on edge v0v1, e1 on
   v1v2 and e2 on v2v0, becomes (v0, e0, e2), (e0, v1, e1), (e2, e1, v2) and
   (e0, e1, e2): the same winding.  With q_1 .. q_n the n neighbours of v (its
   valence n; a boundary vertex has n - 1 triangles around it, an interior one n):

     even, interior:    v' = (1 - n beta) v + beta (q_1 + ... + q_n),
                        beta(n) = 3/16 when n = 3, else 3 / (8 n)   (1/16 when n = 6)
     even, boundary:    v' = 3/4 v + 1/8 (q_a + q_b), q_a and q_b its two neighbours
                        along the boundary (the rest of the ring is not used)
     odd, interior edge (a, b), between the triangles (a, b, c) and (b, a, d):
                        e = 3/8 (a + b) + 1/8 (c + d)
     odd, boundary edge (a, b):   e = (a + b) / 2

   After the last step every vertex goes to its limit position (the point the
   scheme converges to as the steps go on):

     interior:  v_inf = (1 - n gamma) v + gamma (q_1 + ... + q_n),
                gamma(n) = 1 / (n + 3 / (8 beta(n)))               (1/12 when n = 6)
     boundary:  v_inf = 3/5 v + 1/5 (q_a + q_b)

   and the limit normal is N = S x T, two tangents from the ring of limit
   positions q_0 .. q_{n-1} taken in pbrt-v4's order (below):

     interior:  S = sum_j cos(2 pi j / n) q_j,   T = sum_j sin(2 pi j / n) q_j
     boundary (q_0 and q_{n-1} the boundary neighbours):  S = q_{n-1} - q_0 and
                T = q_0 + q_1 - 2 v                       (n = 2: one triangle)
                T = q_1 - v                               (n = 3)
                T = -q_0 + 2 q_1 + 2 q_2 - q_3 - 2 v      (n = 4, the regular case)
                T = -[sin th (q_0 + q_{n-1}) + sum_{k=1}^{n-2} (2 cos th - 2) sin(k th) q_k],
                    th = pi / (n - 1)                      (n > 4)

   N is left unnormalised, as pbrt-v4 leaves it (geometry.c normalises shading normals).
   The ring order: from the vertex that follows v in one of its triangles, across
   the edge (v, that vertex) into the next triangle, and so on, which turns
   clockwise when the triangles are seen counter-clockwise; so N points to the side
   from which the control triangles are seen clockwise.  (A boundary vertex's ring
   starts at the end of that walk.)  As the shading normal decides a mesh's side
   (bvh.c), that side is the surface's front, as in pbrt-v4.

   THE CONTROL MESH must be a manifold: every edge in one triangle (a boundary) or
   two that run it in opposite directions, the triangles around each vertex one
   fan, every vertex in some triangle, no triangle repeating a vertex.  pbrt-v4
   does not check this (it crashes or loops on such meshes); loop_subdivide refuses
   them by name.  Counts: one step turns V vertices, E edges and F triangles into
   V + E, 2 E + 3 F and 4 F.  Arithmetic in double; the output is float. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

#define NEXT3(k) (((k) + 1) % 3)
#define PREV3(k) (((k) + 2) % 3)

/* One level of the mesh with its connectivity. */
typedef struct {
    int nv, nt, ne;
    double *P;             /* 3 per vertex */
    int32_t *tri;          /* 3 per triangle, counter-clockwise (v0, v1, v2) */
    int32_t *nb;           /* 3 per triangle: the triangle across edge k (v_k, v_k+1), -1: none */
    int32_t *eid;          /* 3 per triangle: the index of edge k */
    int32_t *start;        /* per vertex: a triangle that contains it */
    int32_t *valence;      /* per vertex: its number of neighbours */
    unsigned char *boundary;  /* per vertex: on the boundary */
    int max_valence;
} Level;

typedef struct { int32_t lo, hi, t, k; } EdgeRef;

static void level_free(Level *L)
{
    free(L->P); free(L->tri); free(L->nb); free(L->eid); free(L->start);
    free(L->valence); free(L->boundary);
    memset(L, 0, sizeof *L);
}

static int edge_cmp(const void *a, const void *b)
{
    const EdgeRef *x = (const EdgeRef *)a, *y = (const EdgeRef *)b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    if (x->t != y->t) return x->t < y->t ? -1 : 1;
    return x->k < y->k ? -1 : x->k > y->k;
}

static int vnum(const Level *L, int t, int v)
{
    int k;
    for (k = 0; k < 3; k++)
        if (L->tri[3 * t + k] == v) return k;
    return -1;
}
static int next_tri(const Level *L, int t, int v) { return L->nb[3 * t + vnum(L, t, v)]; }
static int prev_tri(const Level *L, int t, int v) { return L->nb[3 * t + PREV3(vnum(L, t, v))]; }
static int next_vert(const Level *L, int t, int v) { return L->tri[3 * t + NEXT3(vnum(L, t, v))]; }
static int prev_vert(const Level *L, int t, int v) { return L->tri[3 * t + PREV3(vnum(L, t, v))]; }

/* The edges: nb and eid from the triangles, each shared edge checked. */
static int level_edges(Level *L, Error *err)
{
    EdgeRef *e = (EdgeRef *)malloc(sizeof(EdgeRef) * 3 * (size_t)L->nt);
    int i, j, n = 3 * L->nt;
    L->nb = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)L->nt);
    L->eid = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)L->nt);
    if (!e || !L->nb || !L->eid) { free(e); error_set(err, NULL, 0, "out of memory"); return 0; }
    for (i = 0; i < n; i++) {
        int32_t a = L->tri[i], b = L->tri[3 * (i / 3) + NEXT3(i % 3)];
        e[i].lo = a < b ? a : b;
        e[i].hi = a < b ? b : a;
        e[i].t = i / 3;
        e[i].k = i % 3;
    }
    qsort(e, (size_t)n, sizeof *e, edge_cmp);
    L->ne = 0;
    for (i = 0; i < n; i = j) {
        for (j = i + 1; j < n && e[j].lo == e[i].lo && e[j].hi == e[i].hi; j++) {}
        if (j - i > 2) {
            error_set(err, NULL, 0, "the edge (%d, %d) is in %d triangles (at most 2: the mesh must be "
                      "a manifold)", e[i].lo, e[i].hi, j - i);
            free(e);
            return 0;
        }
        if (j - i == 2 && L->tri[3 * e[i].t + e[i].k] == L->tri[3 * e[i + 1].t + e[i + 1].k]) {
            error_set(err, NULL, 0, "the edge (%d, %d) runs the same way in triangles %d and %d (their "
                      "orientations disagree)", L->tri[3 * e[i].t + e[i].k],
                      L->tri[3 * e[i].t + NEXT3(e[i].k)], e[i].t, e[i + 1].t);
            free(e);
            return 0;
        }
        L->nb[3 * e[i].t + e[i].k] = j - i == 2 ? e[i + 1].t : -1;
        L->eid[3 * e[i].t + e[i].k] = L->ne;
        if (j - i == 2) {
            L->nb[3 * e[i + 1].t + e[i + 1].k] = e[i].t;
            L->eid[3 * e[i + 1].t + e[i + 1].k] = L->ne;
        }
        L->ne++;
    }
    free(e);
    return 1;
}

/* The vertices: a triangle of each, the boundary flag and the valence; each
   vertex's triangles must form one fan. */
static int level_vertices(Level *L, Error *err)
{
    int32_t *count = (int32_t *)calloc((size_t)L->nv, sizeof(int32_t));
    int i, v;
    L->start = (int32_t *)malloc(sizeof(int32_t) * (size_t)L->nv);
    L->valence = (int32_t *)malloc(sizeof(int32_t) * (size_t)L->nv);
    L->boundary = (unsigned char *)malloc((size_t)L->nv);
    if (!count || !L->start || !L->valence || !L->boundary) {
        free(count);
        error_set(err, NULL, 0, "out of memory");
        return 0;
    }
    for (v = 0; v < L->nv; v++) L->start[v] = -1;
    for (i = 0; i < 3 * L->nt; i++) {
        count[L->tri[i]]++;
        if (L->start[L->tri[i]] < 0) L->start[L->tri[i]] = i / 3;
    }
    L->max_valence = 0;
    for (v = 0; v < L->nv; v++) {
        int t = L->start[v], fan = 0;
        if (t < 0) {
            error_set(err, NULL, 0, "vertex %d is in no triangle", v);
            free(count);
            return 0;
        }
        do {                                     /* forward, until back or the boundary */
            fan++;
            t = next_tri(L, t, v);
        } while (t >= 0 && t != L->start[v] && fan <= count[v]);
        L->boundary[v] = t < 0;
        if (t < 0)                               /* then backward from the start */
            for (t = prev_tri(L, L->start[v], v); t >= 0 && fan <= count[v]; t = prev_tri(L, t, v)) fan++;
        if (fan != count[v]) {
            error_set(err, NULL, 0, "the %d triangles at vertex %d are not one fan (a non-manifold "
                      "vertex)", count[v], v);
            free(count);
            return 0;
        }
        L->valence[v] = fan + L->boundary[v];
        if (L->valence[v] > L->max_valence) L->max_valence = L->valence[v];
    }
    free(count);
    return 1;
}

/* v's neighbours in pbrt-v4's order (see the top); returns their number. */
static int one_ring(const Level *L, int v, int32_t *ring)
{
    int t = L->start[v], g, n = 0;
    if (!L->boundary[v]) {
        do {
            ring[n++] = next_vert(L, t, v);
            t = next_tri(L, t, v);
        } while (t != L->start[v]);
        return n;
    }
    while ((g = next_tri(L, t, v)) >= 0) t = g;
    ring[n++] = next_vert(L, t, v);
    do {
        ring[n++] = prev_vert(L, t, v);
        t = prev_tri(L, t, v);
    } while (t >= 0);
    return n;
}

static double loop_beta(int n) { return n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n); }
static double loop_gamma(int n) { return 1.0 / (n + 3.0 / (8.0 * loop_beta(n))); }

/* out = (1 - n w) v + w (sum of the ring) for an interior vertex, (1 - 2 wb) v +
   wb (q_0 + q_{n-1}) for a boundary one. */
static void ring_weighted(const Level *L, int v, const int32_t *ring, int n, double w, double wb,
                          double *out)
{
    int a, j;
    for (a = 0; a < 3; a++) {
        const double *P = L->P;
        double s;
        if (L->boundary[v]) {
            s = (1.0 - 2.0 * wb) * P[3 * v + a] + wb * (P[3 * ring[0] + a] + P[3 * ring[n - 1] + a]);
        } else {
            s = (1.0 - n * w) * P[3 * v + a];
            for (j = 0; j < n; j++) s += w * P[3 * ring[j] + a];
        }
        out[a] = s;
    }
}

/* The connectivity of L (its P and tri set). */
static int level_topology(Level *L, Error *err)
{
    return level_edges(L, err) && level_vertices(L, err);
}

/* One step of the scheme: L becomes the refined mesh. */
static int level_refine(Level *L, Error *err)
{
    Level N;
    int32_t *ring = (int32_t *)malloc(sizeof(int32_t) * ((size_t)L->max_valence + 1));
    unsigned char *done;
    int v, t, k;
    memset(&N, 0, sizeof N);
    N.nv = L->nv + L->ne;
    N.nt = 4 * L->nt;
    N.P = (double *)malloc(sizeof(double) * 3 * (size_t)N.nv);
    N.tri = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)N.nt);
    done = (unsigned char *)calloc((size_t)L->ne, 1);
    if (!ring || !N.P || !N.tri || !done) {
        free(ring); free(done); level_free(&N);
        error_set(err, NULL, 0, "out of memory");
        return 0;
    }
    for (v = 0; v < L->nv; v++) {                /* the even vertices */
        int n = one_ring(L, v, ring);
        ring_weighted(L, v, ring, n, loop_beta(n), 1.0 / 8.0, N.P + 3 * v);
    }
    for (t = 0; t < L->nt; t++)
        for (k = 0; k < 3; k++) {                /* the odd vertices, one per edge */
            int e = L->eid[3 * t + k], a = L->tri[3 * t + k], b = L->tri[3 * t + NEXT3(k)];
            int c = L->tri[3 * t + PREV3(k)], u = L->nb[3 * t + k], i;
            double *q = N.P + 3 * (L->nv + e);
            if (done[e]) continue;
            done[e] = 1;
            for (i = 0; i < 3; i++) {
                if (u < 0) {
                    q[i] = 0.5 * (L->P[3 * a + i] + L->P[3 * b + i]);
                } else {
                    int d = L->tri[3 * u + PREV3(vnum(L, u, b))];   /* u runs (b, a, d) */
                    q[i] = 3.0 / 8.0 * (L->P[3 * a + i] + L->P[3 * b + i]) +
                           1.0 / 8.0 * (L->P[3 * c + i] + L->P[3 * d + i]);
                }
            }
        }
    for (t = 0; t < L->nt; t++) {                /* four triangles in place of each */
        int32_t *c = N.tri + 12 * t;
        for (k = 0; k < 3; k++) {
            int32_t odd = L->nv + L->eid[3 * t + k], odd_prev = L->nv + L->eid[3 * t + PREV3(k)];
            c[3 * k + k] = L->tri[3 * t + k];    /* corner k keeps vertex k's place */
            c[3 * k + NEXT3(k)] = odd;
            c[3 * k + PREV3(k)] = odd_prev;
            c[9 + k] = odd;
        }
    }
    free(ring);
    free(done);
    level_free(L);
    *L = N;
    return level_topology(L, err);
}

/* The limit positions, then the limit normals from them. */
static int level_limit(Level *L, SubdivMesh *out, Error *err)
{
    int32_t *ring = (int32_t *)malloc(sizeof(int32_t) * ((size_t)L->max_valence + 1));
    double *lim = (double *)malloc(sizeof(double) * 3 * (size_t)L->nv);
    int v, j, a;
    out->P = (float *)malloc(sizeof(float) * 3 * (size_t)L->nv);
    out->N = (float *)malloc(sizeof(float) * 3 * (size_t)L->nv);
    if (!ring || !lim || !out->P || !out->N) {
        free(ring); free(lim);
        error_set(err, NULL, 0, "out of memory");
        return 0;
    }
    for (v = 0; v < L->nv; v++) {
        int n = one_ring(L, v, ring);
        ring_weighted(L, v, ring, n, loop_gamma(n), 1.0 / 5.0, lim + 3 * v);
    }
    free(L->P);
    L->P = lim;
    for (v = 0; v < L->nv; v++) {
        int n = one_ring(L, v, ring);
        const double *P = L->P, *p = P + 3 * v;
        double S[3], T[3];
        for (a = 0; a < 3; a++) {
            const double *q0 = P + 3 * ring[0] + a, *qn = P + 3 * ring[n - 1] + a;
            S[a] = T[a] = 0.0;
            if (!L->boundary[v]) {
                for (j = 0; j < n; j++) {
                    S[a] += cos(2.0 * SPECNEE_PI * j / n) * P[3 * ring[j] + a];
                    T[a] += sin(2.0 * SPECNEE_PI * j / n) * P[3 * ring[j] + a];
                }
                continue;
            }
            S[a] = *qn - *q0;
            if (n == 2) {
                T[a] = *q0 + P[3 * ring[1] + a] - 2.0 * p[a];
            } else if (n == 3) {
                T[a] = P[3 * ring[1] + a] - p[a];
            } else if (n == 4) {
                T[a] = -*q0 + 2.0 * P[3 * ring[1] + a] + 2.0 * P[3 * ring[2] + a] - *qn - 2.0 * p[a];
            } else {
                double th = SPECNEE_PI / (n - 1);
                T[a] = sin(th) * (*q0 + *qn);
                for (j = 1; j < n - 1; j++) T[a] += (2.0 * cos(th) - 2.0) * sin(j * th) * P[3 * ring[j] + a];
                T[a] = -T[a];
            }
        }
        out->N[3 * v + 0] = (float)(S[1] * T[2] - S[2] * T[1]);
        out->N[3 * v + 1] = (float)(S[2] * T[0] - S[0] * T[2]);
        out->N[3 * v + 2] = (float)(S[0] * T[1] - S[1] * T[0]);
        for (a = 0; a < 3; a++) out->P[3 * v + a] = (float)p[a];
    }
    free(ring);
    return 1;
}

int loop_subdivide(const double *P, int nv, const int32_t *idx, int nt, int levels,
                   SubdivMesh *out, Error *err)
{
    Level L;
    int i, k;
    memset(out, 0, sizeof *out);
    memset(&L, 0, sizeof L);
    for (i = 0; i < nt; i++)
        for (k = 0; k < 3; k++) {
            if (idx[3 * i + k] < 0 || idx[3 * i + k] >= nv) {
                error_set(err, NULL, 0, "vertex index %d out of range [0, %d)", idx[3 * i + k], nv);
                return 0;
            }
            if (idx[3 * i + k] == idx[3 * i + NEXT3(k)]) {
                error_set(err, NULL, 0, "triangle %d names vertex %d twice", i, idx[3 * i + k]);
                return 0;
            }
        }
    L.nv = nv;
    L.nt = nt;
    L.P = (double *)malloc(sizeof(double) * 3 * (size_t)nv);
    L.tri = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)nt);
    if (!L.P || !L.tri) { level_free(&L); error_set(err, NULL, 0, "out of memory"); return 0; }
    memcpy(L.P, P, sizeof(double) * 3 * (size_t)nv);
    memcpy(L.tri, idx, sizeof(int32_t) * 3 * (size_t)nt);
    if (!level_topology(&L, err)) { level_free(&L); return 0; }
    for (i = 0; i < levels; i++)
        if (!level_refine(&L, err)) { level_free(&L); return 0; }
    if (!level_limit(&L, out, err)) { level_free(&L); subdiv_free(out); return 0; }
    out->n_verts = L.nv;
    out->n_tris = L.nt;
    out->idx = L.tri;
    L.tri = NULL;
    level_free(&L);
    return 1;
}

void subdiv_free(SubdivMesh *m)
{
    free(m->P); free(m->N); free(m->idx);
    memset(m, 0, sizeof *m);
}
