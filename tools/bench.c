/* tools/bench.c - ray-casting benchmark of the BVH (bvh.c) on a procedural mesh.

   WHAT IT MEASURES
     1. A displaced icosphere: the icosahedron split `level` times (20 * 4^level
        triangles; level 6 = 81,920, level 7 = 327,680, level 8 = 1,310,720), each
        vertex v on the unit sphere moved to radius
            r(v) = 1 + 0.1 sin(5 x) sin(7 y) sin(3 z),
        a smooth bumpy surface.  It is written to out/bench_mesh.ply with
        ply_write_binary and read back with ply_read (both timed).
     2. BVH build time (min/median/max of the runs), the BVH's memory per triangle and
        the process's peak resident memory (getrusage).
     3. Incoherent rays: N rays with origins uniform in the mesh's bounding box scaled
        x2 about its centre, directions uniform on the sphere (z = 1 - 2u,
        phi = 2 pi v), fixed seed (PCG32 stream per ray, util.c), tmax = inf.  They
        are split into the rays that miss the mesh's bounding box (the BVH rejects
        them with one box test) and those that hit it (the real work).
     4. Single-thread throughput in Mrays/s of closest hit (bvh_intersect) and of any
        hit (bvh_occluded, the shadow-ray query), on all rays and on each part.  Every
        measurement is repeated `runs` times (default 5), interleaved (each run times
        every measurement once, in the same order), and min/median/max are printed:
        the machine is shared, so the median is the figure to quote and the spread
        says how noisy it was.  Single-thread work (build, casts) is timed in CPU time
        (CLOCK_PROCESS_CPUTIME_ID), which leaves out the time spent waiting for a core.
        Closest hit is also timed on all threads (OpenMP, wall-clock time).
   The hit count and the sum of hit distances are printed as a checksum: they must not
   change with the thread count or between closest and any hit (hits only).

   USE
     make bench             (runs tools/bench.sh, which runs this)
     tools/bench [--runs N] [level]    level 6 (default), any of 1..8
*/
#define _POSIX_C_SOURCE 200809L
#include "../specnee.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/resource.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define BENCH_RAYS (1 << 20)        /* rays per measurement */
#define BENCH_RUNS 5                /* default number of interleaved runs */
#define MAX_RUNS 99

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of this process: single-thread work is timed with it, so that time the
   process spends waiting for a core on a busy machine does not count. */
static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
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
    t0 = threads == 1 ? cpu_s() : now_s();
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
    res.seconds = (threads == 1 ? cpu_s() : now_s()) - t0;
    res.hits = hits;
    res.t_sum = t_sum;
    return res;
}

/* min, median and max of x[0..n) (sorts x) */
static void stats3(double *x, int n, double *mn, double *med, double *mx)
{
    int i, j;
    for (i = 1; i < n; i++)
        for (j = i; j > 0 && x[j - 1] > x[j]; j--) { double t = x[j]; x[j] = x[j - 1]; x[j - 1] = t; }
    *mn = x[0];
    *med = n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
    *mx = x[n - 1];
}

/* Does the ray meet the box [lo, hi] at some t >= 0?  (Only to split the rays, in
   double, independent of bvh.c.) */
static int ray_hits_box(const Ray *r, Vec3 lo, Vec3 hi)
{
    double t0 = 0.0, t1 = INFINITY;
    int a;
    for (a = 0; a < 3; a++) {
        double o = v3_get(r->o, a), d = v3_get(r->d, a), l = v3_get(lo, a), h = v3_get(hi, a);
        if (d == 0.0) {
            if (o < l || o > h) return 0;
            continue;
        }
        {
            double ta = (l - o) / d, tb = (h - o) / d;
            if (ta > tb) { double t = ta; ta = tb; tb = t; }
            if (ta > t0) t0 = ta;
            if (tb < t1) t1 = tb;
        }
    }
    return t0 <= t1;
}

/* The Scene of one triangle mesh (vertices P[3 * n_verts], indices idx[3 * n_tris]),
   filled by hand: bounds, one Shape, the triangles.  0 when out of memory. */
static int mesh_scene(Scene *s, const float *P, int n_verts, const int32_t *idx, int n_tris)
{
    int i, k;
    memset(s, 0, sizeof *s);
    s->n_verts = n_verts;
    s->n_tris = n_tris;
    s->n_shapes = 1;
    s->P = (Vec3 *)malloc((size_t)n_verts * sizeof *s->P);
    s->tris = (Triangle *)malloc((size_t)n_tris * sizeof *s->tris);
    s->shapes = (Shape *)calloc(1, sizeof *s->shapes);
    if (!s->P || !s->tris || !s->shapes) return 0;
    s->shapes[0].type = SHAPE_MESH;
    s->shapes[0].emitter = -1;
    s->shapes[0].tri_count = n_tris;
    s->bmin = v3(1e30f, 1e30f, 1e30f);
    s->bmax = v3(-1e30f, -1e30f, -1e30f);
    for (i = 0; i < n_verts; i++) {
        s->P[i] = v3(P[3 * i], P[3 * i + 1], P[3 * i + 2]);
        s->bmin = v3_min(s->bmin, s->P[i]);
        s->bmax = v3_max(s->bmax, s->P[i]);
    }
    for (i = 0; i < n_tris; i++) {
        for (k = 0; k < 3; k++) s->tris[i].v[k] = idx[3 * i + k];
        s->tris[i].shape = 0;
    }
    return 1;
}

/* The benchmark's n rays: origin uniform in the scene's bounds scaled x2 about the
   centre, direction uniform on the sphere, fixed seed (a PCG32 stream per ray).  The
   random numbers are drawn into variables one statement at a time: C leaves the
   order in which a call's arguments are evaluated open (gcc goes right to left, clang
   left to right), and three rng_float calls inside v3(...) gave each compiler other
   rays, hence other checksums. */
static void bench_rays(const Scene *s, Ray *rays, int n)
{
    const Vec3 c = v3_mul(v3_add(s->bmin, s->bmax), 0.5f);
    const Vec3 half = v3_sub(s->bmax, c);           /* x2: the box spans c +- 2 half */
    int i;
    for (i = 0; i < n; i++) {
        Rng rng;
        float ux, uy, uz, z, rxy, phi;
        rng_seed(&rng, 20220701u, (uint64_t)i);
        ux = rng_float(&rng);
        uy = rng_float(&rng);
        uz = rng_float(&rng);
        rays[i].o = v3(c.x + half.x * (4.0f * ux - 2.0f), c.y + half.y * (4.0f * uy - 2.0f),
                       c.z + half.z * (4.0f * uz - 2.0f));
        z = 1.0f - 2.0f * rng_float(&rng);
        rxy = sqrtf(1.0f - z * z > 0.0f ? 1.0f - z * z : 0.0f);
        phi = 2.0f * PI_F * rng_float(&rng);
        rays[i].d = v3(rxy * cosf(phi), rxy * sinf(phi), z);
        rays[i].tmax = INFINITY;
    }
}

#ifndef BENCH_NO_MAIN   /* tools/bench_embree.c includes this file for its mesh and rays */
/* The BVH's leaves, used child slots and bytes. */
static double bvh_stats(const Bvh *b, int *leaves, int *slots)
{
    int i, k;
    for (i = 0; i < b->n_nodes; i++)
        for (k = 0; k < BVH_WIDTH; k++) {
            *leaves += b->nodes[i].child[k] < 0;
            *slots += b->nodes[i].box[0][k] != INFINITY;
        }
    return (double)b->n_nodes * sizeof(BvhNode) + (double)b->n_prims * sizeof(BvhPrim);
}

/* One line "name: min / median / max Mrays/s" from the run times of n rays. */
static double print_rate(const char *name, const double *seconds, int runs, long n)
{
    double rate[MAX_RUNS], mn, med, mx;
    int k;
    for (k = 0; k < runs; k++) rate[k] = (double)n / seconds[k] * 1e-6;
    stats3(rate, runs, &mn, &med, &mx);
    printf("  %-34s %7.2f  %7.2f  %7.2f Mrays/s  (%.0f ns a ray, median)\n", name, mn, med, mx,
           1e3 / med);
    return med;
}

int main(int argc, char **argv)
{
    const char *ply_path = "out/bench_mesh.ply";
    int level = 6, runs = BENCH_RUNS, n_verts = 0, n_tris = 0, i, k, q, threads = 1;
    int leaves = 0, slots = 0, n_in = 0, n_out = 0;
    float *P = NULL;
    int32_t *idx = NULL;
    PlyMesh mesh;
    Error err;
    Scene s;
    Ray *rays, *rays_in, *rays_out;
    double t0, t_write, t_read, t_build[MAX_RUNS], bmn, bmed, bmx, mem;
    double sec[7][MAX_RUNS], med_c_in, med_a_in;
    CastResult res[7];
    struct rusage ru;

    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = atoi(argv[++i]);
            if (runs < 1 || runs > MAX_RUNS) break;
        } else {
            level = atoi(argv[i]);
            if (level < 1 || level > 8) break;
        }
    }
    if (i < argc) {
        fprintf(stderr, "usage: %s [--runs 1..%d, default %d] [level 1..8, default 6]\n",
                argv[0], MAX_RUNS, BENCH_RUNS);
        return 2;
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
    rays = (Ray *)malloc(3 * (size_t)BENCH_RAYS * sizeof *rays);
    if (!rays || !mesh_scene(&s, mesh.P, mesh.n_verts, mesh.idx, mesh.n_tris)) {
        fprintf(stderr, "bench: out of memory\n");
        return 1;
    }
    rays_in = rays + BENCH_RAYS;
    rays_out = rays + 2 * BENCH_RAYS;
    ply_free(&mesh);

    /* 3. BVH build, timed `runs` times */
    for (k = 0; k < runs; k++) {
        if (k > 0) bvh_free(&s.bvh);
        t0 = cpu_s();
        if (!bvh_build(&s.bvh, &s)) {
            fprintf(stderr, "bench: bvh_build failed\n");
            return 1;
        }
        t_build[k] = cpu_s() - t0;
    }
    stats3(t_build, runs, &bmn, &bmed, &bmx);
    mem = bvh_stats(&s.bvh, &leaves, &slots);

    /* 4. rays: origin uniform in the bounds scaled x2 about the centre, direction
          uniform on the sphere; then split by the mesh's bounding box */
    bench_rays(&s, rays, BENCH_RAYS);
    for (i = 0; i < BENCH_RAYS; i++) {
        if (ray_hits_box(&rays[i], s.bmin, s.bmax)) rays_in[n_in++] = rays[i];
        else rays_out[n_out++] = rays[i];
    }

    printf("bench: displaced icosphere level %d: %d triangles, %d vertices (%s)\n",
           level, s.n_tris, s.n_verts, ply_path);
    printf("  bounds (%.3g %.3g %.3g) .. (%.3g %.3g %.3g)\n", s.bmin.x, s.bmin.y, s.bmin.z,
           s.bmax.x, s.bmax.y, s.bmax.z);
    printf("  ply write %.3f s, ply read %.3f s\n", t_write, t_read);
    printf("  bvh build %.3f / %.3f / %.3f s CPU time (min / median / max of %d)\n", bmn, bmed,
           bmx, runs);
    printf("  bvh: %d nodes of %d children, %d leaves, %.2f children a node, "
           "%.2f triangles a leaf\n", s.bvh.n_nodes, BVH_WIDTH, leaves,
           (double)slots / s.bvh.n_nodes, (double)s.n_tris / leaves);
    printf("  bvh memory %.1f MB, %.1f bytes a triangle\n", mem * 1e-6, mem / s.n_tris);
    printf("  rays: %d, origins uniform in the bounds scaled x2 about the centre,\n"
           "        directions uniform on the sphere, tmax = inf\n", BENCH_RAYS);
    printf("        %d (%.1f%%) miss the mesh's bounding box, %d (%.1f%%) hit it\n",
           n_out, 100.0 * n_out / BENCH_RAYS, n_in, 100.0 * n_in / BENCH_RAYS);

    /* 5. throughput: every run times each measurement once, in this order */
    for (k = 0; k < runs; k++) {
        for (q = 0; q < 7; q++) {
            const Ray *set = q % 3 == 0 ? rays : q % 3 == 1 ? rays_in : rays_out;
            const int n = q % 3 == 0 ? BENCH_RAYS : q % 3 == 1 ? n_in : n_out;
            CastResult r = cast(&s, set, n, q == 6 ? threads : 1, q >= 3 && q < 6);
            sec[q][k] = r.seconds;
            if (k > 0 && (r.hits != res[q].hits || r.t_sum != res[q].t_sum) && q != 6) {
                printf("  ERROR: run %d of measurement %d gave another result\n", k, q);
                return 1;
            }
            res[q] = r;
        }
    }
    printf("  %d hit the mesh (%.1f%% of all, %.1f%% of those that hit the box); "
           "checksum: sum t = %.9g\n", (int)res[0].hits, 100.0 * res[0].hits / BENCH_RAYS,
           100.0 * res[1].hits / (n_in > 0 ? n_in : 1), res[0].t_sum);
    printf("  single thread (CPU time), %d interleaved runs: min   median      max\n", runs);
    print_rate("closest hit, all rays", sec[0], runs, BENCH_RAYS);
    med_c_in = print_rate("closest hit, rays hitting the box", sec[1], runs, n_in);
    print_rate("closest hit, rays missing the box", sec[2], runs, n_out);
    print_rate("any hit,     all rays", sec[3], runs, BENCH_RAYS);
    med_a_in = print_rate("any hit,     rays hitting the box", sec[4], runs, n_in);
    print_rate("any hit,     rays missing the box", sec[5], runs, n_out);
    printf("  any hit / closest hit on the box-hitting rays: x%.2f (medians)\n",
           med_a_in / med_c_in);
    printf("  %d threads (wall-clock time):\n", threads);
    print_rate("closest hit, all rays", sec[6], runs, BENCH_RAYS);
    getrusage(RUSAGE_SELF, &ru);
    printf("  peak resident memory %.1f MB (whole process)\n", (double)ru.ru_maxrss / 1024.0);
    /* the same hits on every path; the sum of t is added in another order by each
       thread count: compare loosely */
    if (res[3].hits != res[0].hits || res[1].hits + res[2].hits != res[0].hits ||
        res[4].hits != res[1].hits || res[2].hits != 0 || res[5].hits != 0 ||
        res[6].hits != res[0].hits || fabs(res[6].t_sum - res[0].t_sum) > 1e-9 * fabs(res[0].t_sum)) {
        printf("  ERROR: results differ between queries or thread counts\n");
        return 1;
    }
    bvh_free(&s.bvh);
    free(s.P); free(s.tris); free(s.shapes); free(rays);
    return 0;
}
#endif /* BENCH_NO_MAIN */
