/* tools/bench.c - ray-casting benchmark of the BVH (bvh.c) on a procedural mesh.

   WHAT IT MEASURES
     1. A displaced icosphere: the icosahedron split `level` times (20 * 4^level
        triangles; level 6 = 81,920, level 7 = 327,680), each vertex v on the unit
        sphere moved to radius
            r(v) = 1 + 0.1 sin(5 x) sin(7 y) sin(3 z),
        a smooth bumpy surface.  It is written to out/bench_mesh.ply with
        ply_write_binary and read back with ply_read (both timed).
     2. BVH build time (best of 3).
     3. Incoherent closest-hit throughput: N rays with origins uniform in the mesh's
        bounding box scaled x2 about its centre, directions uniform on the sphere
        (z = 1 - 2u, phi = 2 pi v), fixed seed (PCG32 stream per ray, util.c), tmax = inf.
        Reported in Mrays/s on 1 thread and on all threads (OpenMP, when compiled in);
        best of 3 runs each.
     4. Any-hit (shadow-ray) throughput with the same rays.
     5. Ratios taken in the same run: all-thread / 1-thread speedups, any / closest.
   The hit count and the sum of hit distances are printed as a checksum: they must not
   change with the thread count.

   USE
     make bench             (runs tools/bench.sh, which runs this)
     tools/bench [level]    level 6 (default) or 7, or any of 1..8
*/
#define _POSIX_C_SOURCE 200809L
#include "../specnee.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define BENCH_RAYS (1 << 20)        /* rays per measurement */
#define BENCH_REPEAT 3              /* best of this many runs */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------------------------------------------------------------------
   The mesh: icosphere by repeated 1-to-4 splits, midpoints shared through a hash
   table keyed by the edge's two vertex indices, then displaced radially.
   --------------------------------------------------------------------------- */
static int icosphere(int level, float **P_out, int *n_verts, int32_t **idx_out, int *n_tris)
{
    /* icosahedron: (0, +-1, +-g) and its cyclic permutations, g the golden ratio;
       faces counter-clockwise seen from outside */
    static const float g = 1.6180340f;
    const float V0[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                             {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                             {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    static const int F0[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    const int nt_final = 20 << (2 * level), nv_final = 10 * (1 << (2 * level)) + 2;
    const size_t hsize = 4 * (size_t)nt_final;          /* > 2x the number of edges */
    float *P = (float *)malloc(3 * (size_t)nv_final * sizeof *P);
    int32_t *idx = (int32_t *)malloc(3 * (size_t)nt_final * sizeof *idx);
    int32_t *next = (int32_t *)malloc(3 * (size_t)nt_final * sizeof *next);
    int64_t *key = (int64_t *)malloc(hsize * sizeof *key);
    int32_t *mid = (int32_t *)malloc(hsize * sizeof *mid);
    int nv = 12, nt = 20, l, i, k;
    if (!P || !idx || !next || !key || !mid) {
        free(P); free(idx); free(next); free(key); free(mid);
        return 0;
    }
    for (i = 0; i < 12; i++) {
        float len = sqrtf(V0[i][0] * V0[i][0] + V0[i][1] * V0[i][1] + V0[i][2] * V0[i][2]);
        for (k = 0; k < 3; k++) P[3 * i + k] = V0[i][k] / len;
    }
    for (i = 0; i < 20; i++)
        for (k = 0; k < 3; k++) idx[3 * i + k] = F0[i][k];

    for (l = 0; l < level; l++) {
        int32_t *tmp;
        for (i = 0; i < (int)hsize; i++) key[i] = -1;
        for (i = 0; i < nt; i++) {
            int32_t m[3], *v = &idx[3 * i], *o = &next[12 * i];
            for (k = 0; k < 3; k++) {               /* midpoint of edge (v[k], v[k+1]) */
                int32_t a = v[k], b = v[(k + 1) % 3];
                int64_t kk = a < b ? (int64_t)a * nv_final + b : (int64_t)b * nv_final + a;
                size_t h = (size_t)(hash_u64((uint64_t)kk, 0) % hsize);
                while (key[h] >= 0 && key[h] != kk) h = (h + 1) % hsize;
                if (key[h] < 0) {                   /* new vertex, on the unit sphere */
                    float x = P[3 * a] + P[3 * b], y = P[3 * a + 1] + P[3 * b + 1],
                          z = P[3 * a + 2] + P[3 * b + 2];
                    float inv_len = 1.0f / sqrtf(x * x + y * y + z * z);
                    key[h] = kk;
                    mid[h] = nv;
                    P[3 * nv] = x * inv_len; P[3 * nv + 1] = y * inv_len; P[3 * nv + 2] = z * inv_len;
                    nv++;
                }
                m[k] = mid[h];
            }
            /* four children, all counter-clockwise like the parent */
            o[0] = v[0]; o[1] = m[0]; o[2] = m[2];
            o[3] = v[1]; o[4] = m[1]; o[5] = m[0];
            o[6] = v[2]; o[7] = m[2]; o[8] = m[1];
            o[9] = m[0]; o[10] = m[1]; o[11] = m[2];
        }
        nt *= 4;
        tmp = idx; idx = next; next = tmp;
    }
    /* radial displacement r = 1 + 0.1 sin(5x) sin(7y) sin(3z) */
    for (i = 0; i < nv; i++) {
        float *p = &P[3 * i];
        float r = 1.0f + 0.1f * sinf(5.0f * p[0]) * sinf(7.0f * p[1]) * sinf(3.0f * p[2]);
        p[0] *= r; p[1] *= r; p[2] *= r;
    }
    free(next); free(key); free(mid);
    *P_out = P; *n_verts = nv; *idx_out = idx; *n_tris = nt;
    return nv == nv_final && nt == nt_final;
}

/* ---------------------------------------------------------------------------
   Ray casting
   --------------------------------------------------------------------------- */
typedef struct { long hits; double t_sum; double seconds; } CastResult;

/* Cast all rays with `threads` threads (1 = serial loop); any = shadow query. */
static CastResult cast(const Scene *s, const Ray *rays, int n, int threads, int any)
{
    CastResult res;
    long hits = 0;
    double t_sum = 0.0, t0;
    int i;
    (void)threads;
    t0 = now_s();
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 4096) num_threads(threads) reduction(+ : hits, t_sum)
#endif
    for (i = 0; i < n; i++) {
        if (any) {
            hits += bvh_occluded(&s->bvh, s, &rays[i]);
        } else {
            HitRecord h;
            if (bvh_intersect(&s->bvh, s, &rays[i], &h)) { hits++; t_sum += h.t; }
        }
    }
    res.seconds = now_s() - t0;
    res.hits = hits;
    res.t_sum = t_sum;
    return res;
}

static CastResult cast_best(const Scene *s, const Ray *rays, int n, int threads, int any)
{
    CastResult best = cast(s, rays, n, threads, any), r;
    int k;
    for (k = 1; k < BENCH_REPEAT; k++) {
        r = cast(s, rays, n, threads, any);
        if (r.seconds < best.seconds) best = r;
    }
    return best;
}

int main(int argc, char **argv)
{
    const char *ply_path = "out/bench_mesh.ply";
    int level = 6, n_verts = 0, n_tris = 0, i, k, threads = 1, leaves = 0;
    float *P = NULL;
    int32_t *idx = NULL;
    PlyMesh mesh;
    Error err;
    Scene s;
    Ray *rays;
    double t0, t_write, t_read, t_build = 1e30, mrays1, mraysN, any1, anyN;
    Vec3 c, half;
    CastResult r1, rN, a1, aN;

    if (argc > 1) {
        level = atoi(argv[argc - 1]);
        if (level < 1 || level > 8) {
            fprintf(stderr, "usage: %s [level 1..8, default 6]\n", argv[0]);
            return 2;
        }
    }
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif

    /* 1. mesh, written and read back */
    if (!icosphere(level, &P, &n_verts, &idx, &n_tris)) {
        fprintf(stderr, "bench: out of memory for the mesh\n");
        return 1;
    }
    t0 = now_s();
    if (!ply_write_binary(ply_path, P, n_verts, idx, n_tris)) {
        fprintf(stderr, "bench: cannot write %s (does out/ exist?)\n", ply_path);
        return 1;
    }
    t_write = now_s() - t0;
    t0 = now_s();
    if (!ply_read(ply_path, &mesh, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    t_read = now_s() - t0;
    if (mesh.n_verts != n_verts || mesh.n_tris != n_tris ||
        memcmp(mesh.P, P, 3 * (size_t)n_verts * sizeof *P) != 0 ||
        memcmp(mesh.idx, idx, 3 * (size_t)n_tris * sizeof *idx) != 0) {
        fprintf(stderr, "bench: %s did not read back identically\n", ply_path);
        return 1;
    }
    free(P); free(idx);

    /* 2. a Scene holding the one mesh, by hand */
    memset(&s, 0, sizeof s);
    s.n_verts = mesh.n_verts;
    s.n_tris = mesh.n_tris;
    s.n_shapes = 1;
    s.P = (Vec3 *)malloc((size_t)s.n_verts * sizeof *s.P);
    s.tris = (Triangle *)malloc((size_t)s.n_tris * sizeof *s.tris);
    s.shapes = (Shape *)calloc(1, sizeof *s.shapes);
    rays = (Ray *)malloc(BENCH_RAYS * sizeof *rays);
    if (!s.P || !s.tris || !s.shapes || !rays) {
        fprintf(stderr, "bench: out of memory\n");
        return 1;
    }
    s.shapes[0].type = SHAPE_MESH;
    s.shapes[0].emitter = -1;
    s.shapes[0].tri_count = s.n_tris;
    s.bmin = v3(1e30f, 1e30f, 1e30f);
    s.bmax = v3(-1e30f, -1e30f, -1e30f);
    for (i = 0; i < s.n_verts; i++) {
        s.P[i] = v3(mesh.P[3 * i], mesh.P[3 * i + 1], mesh.P[3 * i + 2]);
        s.bmin = v3_min(s.bmin, s.P[i]);
        s.bmax = v3_max(s.bmax, s.P[i]);
    }
    for (i = 0; i < s.n_tris; i++) {
        for (k = 0; k < 3; k++) s.tris[i].v[k] = mesh.idx[3 * i + k];
        s.tris[i].shape = 0;
    }
    ply_free(&mesh);

    /* 3. BVH build, best of 3 */
    for (k = 0; k < BENCH_REPEAT; k++) {
        double dt;
        if (k > 0) bvh_free(&s.bvh);
        t0 = now_s();
        if (!bvh_build(&s.bvh, &s)) {
            fprintf(stderr, "bench: bvh_build failed\n");
            return 1;
        }
        dt = now_s() - t0;
        if (dt < t_build) t_build = dt;
    }
    for (i = 0; i < s.bvh.n_nodes; i++) leaves += s.bvh.nodes[i].count > 0;

    /* 4. rays: origin uniform in the bounds scaled x2 about the centre, direction
          uniform on the sphere */
    c = v3_mul(v3_add(s.bmin, s.bmax), 0.5f);
    half = v3_sub(s.bmax, c);                       /* x2: the box spans c +- 2 half */
    for (i = 0; i < BENCH_RAYS; i++) {
        Rng rng;
        float z, rxy, phi;
        rng_seed(&rng, 20220701u, (uint64_t)i);
        rays[i].o = v3(c.x + half.x * (4.0f * rng_float(&rng) - 2.0f),
                       c.y + half.y * (4.0f * rng_float(&rng) - 2.0f),
                       c.z + half.z * (4.0f * rng_float(&rng) - 2.0f));
        z = 1.0f - 2.0f * rng_float(&rng);
        rxy = sqrtf(1.0f - z * z > 0.0f ? 1.0f - z * z : 0.0f);
        phi = 2.0f * PI_F * rng_float(&rng);
        rays[i].d = v3(rxy * cosf(phi), rxy * sinf(phi), z);
        rays[i].tmax = INFINITY;
    }

    /* 5. throughput */
    r1 = cast_best(&s, rays, BENCH_RAYS, 1, 0);
    rN = cast_best(&s, rays, BENCH_RAYS, threads, 0);
    a1 = cast_best(&s, rays, BENCH_RAYS, 1, 1);
    aN = cast_best(&s, rays, BENCH_RAYS, threads, 1);
    mrays1 = BENCH_RAYS / r1.seconds * 1e-6;
    mraysN = BENCH_RAYS / rN.seconds * 1e-6;
    any1 = BENCH_RAYS / a1.seconds * 1e-6;
    anyN = BENCH_RAYS / aN.seconds * 1e-6;

    printf("bench: displaced icosphere level %d: %d triangles, %d vertices (%s)\n",
           level, s.n_tris, s.n_verts, ply_path);
    printf("  ply write %.3f s, ply read %.3f s\n", t_write, t_read);
    printf("  bvh build %.3f s: %d nodes, %d leaves, %.2f triangles a leaf (best of %d)\n",
           t_build, s.bvh.n_nodes, leaves, (double)s.n_tris / leaves, BENCH_REPEAT);
    printf("  %d incoherent rays, %.1f%% hit (checksum: sum t = %.6g)\n",
           BENCH_RAYS, 100.0 * (double)r1.hits / BENCH_RAYS, r1.t_sum);
    printf("  closest hit, 1 thread:    %7.2f Mrays/s\n", mrays1);
    printf("  closest hit, %d threads:%*s %7.2f Mrays/s  (speedup x%.2f)\n", threads,
           threads < 10 ? 3 : 2, "", mraysN, mraysN / mrays1);
    printf("  any hit,     1 thread:    %7.2f Mrays/s  (x%.2f the closest-hit rate)\n",
           any1, any1 / mrays1);
    printf("  any hit,     %d threads:%*s %7.2f Mrays/s  (speedup x%.2f)\n", threads,
           threads < 10 ? 3 : 2, "", anyN, anyN / any1);
    /* the sum of t is added in another order by each thread count: compare loosely */
    if (rN.hits != r1.hits || fabs(rN.t_sum - r1.t_sum) > 1e-9 * fabs(r1.t_sum) ||
        a1.hits != r1.hits || aN.hits != r1.hits) {
        printf("  ERROR: results differ between runs (hits %ld %ld %ld %ld)\n",
               r1.hits, rN.hits, a1.hits, aN.hits);
        return 1;
    }
    bvh_free(&s.bvh);
    free(s.P); free(s.tris); free(s.shapes); free(rays);
    return 0;
}
