/* tools/bench_embree.c - specnee's BVH against Embree 3 on tools/bench's mesh and rays.

   WHAT IT MEASURES
     The closest-hit throughput (Mrays/s, one thread, CPU time) of bvh_intersect and
     of Embree 3's rtcIntersect1, and the any-hit throughput of bvh_occluded and
     rtcOccluded1 (shadow rays), on the same triangles and the same rays: the
     displaced icosphere and the 2^20 incoherent rays of tools/bench.c (that file is
     included, so both programs build the very same mesh and rays), on all rays and
     on the rays that hit the mesh's bounding box.  Each of `runs` rounds (default 5)
     times the eight casts once, in the same order, so a busy spell of the shared
     machine slows them alike; the best and the median of the rounds are printed,
     with Embree's speed over specnee's (docs/bvh.md has the figures).  The hit
     counts of the two must agree; they are printed.
     Embree is built with its defaults (rtcNewDevice "threads=1", a scene of one
     triangle geometry, RTC_BUILD_QUALITY_MEDIUM), and it picks its own SIMD width at
     run time: its AVX-512 kernels where the processor has them.  Those are not
     always its fastest (on an AMD Zen 4 its AVX2 kernels take 11 % less time a
     closest hit, docs/bvh.md), so a second scene is built on a device held to
     AVX2 ("threads=1,isa=avx2"), cast in the same rounds, and the ratios are
     printed against each and against the faster of the two, query by query.  On a
     processor without AVX-512 the two are the same kernels.  specnee is C99 at -O2
     with its AVX2 copy of the traversal where the processor has AVX2 (SSE2 else).

   NOT PART OF THE RENDERER
     specnee depends on nothing; this program is the only file that uses Embree, and
     only `make bench-embree` builds it, when the Embree 3 headers and library are
     installed (Debian: apt-get install libembree-dev); otherwise it says so and
     stops.  Neither `make`, `make test` nor `make bench` needs it.

   USE
     make bench-embree                  (level 6, 5 rounds)
     tools/bench_embree [level [runs]]  level 1..8 as in tools/bench
     tools/bench_embree count           Embree on tools/bench_count's rays (the first
                                        50,000 box-hitting rays of level 6), once with
                                        rtcIntersect1 and once with rtcOccluded1, for
                                        callgrind (docs/bvh.md, "How it is measured"):
       valgrind --tool=callgrind --toggle-collect=rtcIntersect1 tools/bench_embree count
*/
#define BENCH_NO_MAIN
#include "bench.c"
#include <embree3/rtcore.h>

/* Cast rays[0..n) with Embree (any = 1: rtcOccluded1, the shadow-ray query);
   returns the CPU time, sets the hit count. */
static double embree_cast(RTCScene scene, const Ray *rays, int n, int any, long *hits)
{
    struct RTCIntersectContext ctx;
    const double t0 = cpu_s();
    long h = 0;
    int i;
    rtcInitIntersectContext(&ctx);
    for (i = 0; i < n; i++) {
        if (any) {
            struct RTCRay ray;
            ray.org_x = rays[i].o.x; ray.org_y = rays[i].o.y; ray.org_z = rays[i].o.z;
            ray.dir_x = rays[i].d.x; ray.dir_y = rays[i].d.y; ray.dir_z = rays[i].d.z;
            ray.tnear = 0.0f;
            ray.tfar = rays[i].tmax;
            ray.time = 0.0f;
            ray.mask = 0xFFFFFFFFu;
            ray.id = 0;
            ray.flags = 0;
            rtcOccluded1(scene, &ctx, &ray);
            h += ray.tfar < 0.0f;                  /* Embree sets tfar = -inf on a hit */
            continue;
        }
        {
        struct RTCRayHit rh;
        rh.ray.org_x = rays[i].o.x; rh.ray.org_y = rays[i].o.y; rh.ray.org_z = rays[i].o.z;
        rh.ray.dir_x = rays[i].d.x; rh.ray.dir_y = rays[i].d.y; rh.ray.dir_z = rays[i].d.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = rays[i].tmax;
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    *hits = h;
    return cpu_s() - t0;
}

/* Embree's scene of the mesh P, idx on device dev (NULL if it cannot be set up) */
static RTCScene embree_scene(RTCDevice dev, const float *P, int n_verts, const int32_t *idx,
                             int n_tris)
{
    RTCScene scene;
    RTCGeometry geom;
    float *vb;
    unsigned *ib;
    int i;
    if (!dev) return NULL;
    scene = rtcNewScene(dev);
    geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    vb = (float *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                          3 * sizeof(float), (size_t)n_verts);
    ib = (unsigned *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                             3 * sizeof(unsigned), (size_t)n_tris);
    if (!scene || !vb || !ib) return NULL;
    memcpy(vb, P, 3 * (size_t)n_verts * sizeof *vb);
    for (i = 0; i < 3 * n_tris; i++) ib[i] = (unsigned)idx[i];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    return scene;
}

/* the casts of one round, per query (closest hit, then any hit): */
enum { SP_ALL, SP_BOX, EM_ALL, EM_BOX, E2_ALL, E2_BOX, PER_QUERY };

int main(int argc, char **argv)
{
    static const char *name[PER_QUERY] = {
        "specnee, all rays", "specnee, rays hitting the box",
        "Embree 3 (default), all rays", "Embree 3 (default), box rays",
        "Embree 3 (isa=avx2), all rays", "Embree 3 (isa=avx2), box rays"};
    const int count = argc > 1 && strcmp(argv[1], "count") == 0;   /* tools/bench_count's rays */
    const int level = argc > 1 && !count ? atoi(argv[1]) : 6, runs = argc > 2 ? atoi(argv[2]) : 5;
    int n_verts = 0, n_tris = 0, n_in = 0, i, k, q, ok = 1;
    float *P = NULL;
    int32_t *idx = NULL;
    Scene s;
    Ray *rays, *rays_in;
    double sec[2 * PER_QUERY][MAX_RUNS], best[2 * PER_QUERY], med[2 * PER_QUERY], worst;
    long hits[2 * PER_QUERY];
    RTCDevice dev[2];
    RTCScene scene[2];

    if (level < 1 || level > 8 || runs < 1 || runs > MAX_RUNS) {
        fprintf(stderr, "usage: %s [level 1..8, default 6] [runs 1..%d, default 5] | count\n",
                argv[0], MAX_RUNS);
        return 2;
    }
    rays = (Ray *)malloc(2 * (size_t)BENCH_RAYS * sizeof *rays);
    if (!rays || !icosphere(level, &P, &n_verts, &idx, &n_tris) ||
        !mesh_scene(&s, P, n_verts, idx, n_tris) || !bvh_build(&s.bvh, &s)) {
        fprintf(stderr, "bench_embree: out of memory\n");
        return 1;
    }
    rays_in = rays + BENCH_RAYS;
    bench_rays(&s, rays, BENCH_RAYS);
    for (i = 0; i < BENCH_RAYS; i++)
        if (ray_hits_box(&rays[i], s.bmin, s.bmax)) rays_in[n_in++] = rays[i];

    dev[0] = rtcNewDevice("threads=1");
    dev[1] = rtcNewDevice("threads=1,isa=avx2");
    for (k = 0; k < 2; k++)
        if (!(scene[k] = embree_scene(dev[k], P, n_verts, idx, n_tris))) {
            fprintf(stderr, "bench_embree: Embree could not be set up\n");
            return 1;
        }

    if (count) {      /* the first 50,000 box-hitting rays once each way, for callgrind */
        const int n = n_in < 50000 ? n_in : 50000;
        embree_cast(scene[0], rays_in, n, 0, &hits[0]);
        embree_cast(scene[0], rays_in, n, 1, &hits[1]);
        printf("bench_embree count: %d box-entering rays: closest hit %ld hits; any hit %ld hits\n",
               n, hits[0], hits[1]);
        return 0;
    }
    printf("bench_embree: displaced icosphere level %d, %d triangles; %d rays (%d hit the "
           "mesh's box), one thread, CPU time, %d interleaved rounds\n",
           level, n_tris, BENCH_RAYS, n_in, runs);
    /* q = 0..5 closest hit, 6..11 any hit; in each the casts of the enum above */
    for (k = 0; k < runs; k++)
        for (q = 0; q < 2 * PER_QUERY; q++) {
            const int c = q % PER_QUERY, any = q >= PER_QUERY, box = c % 2;
            const Ray *set = box ? rays_in : rays;
            const int n = box ? n_in : BENCH_RAYS;
            if (c < EM_ALL) {
                CastResult r = cast(&s, set, n, 1, any);
                sec[q][k] = r.seconds;
                hits[q] = r.hits;
            } else
                sec[q][k] = embree_cast(scene[c >= E2_ALL], set, n, any, &hits[q]);
        }
    for (q = 0; q < 2 * PER_QUERY; q++)
        ok &= hits[q] == hits[q < PER_QUERY ? SP_ALL : PER_QUERY + SP_ALL];   /* one count a query */
    printf("  hits: specnee %ld, Embree %ld and %ld%s\n", hits[SP_ALL], hits[EM_ALL],
           hits[E2_ALL], ok ? "" : "  (DIFFER)");
    for (q = 0; q < 2 * PER_QUERY; q++) {
        const double n = q % 2 ? n_in : BENCH_RAYS;
        if (q % PER_QUERY == 0)
            printf("  %-32s %10s %10s\n", q ? "any hit (shadow rays)" : "closest hit", "best", "median");
        stats3(sec[q], runs, &best[q], &med[q], &worst);
        printf("  %-32s %7.2f Mrays/s %7.2f Mrays/s\n", name[q % PER_QUERY], n / best[q] * 1e-6,
               n / med[q] * 1e-6);
    }
    for (q = 0; q < 2 * PER_QUERY; q += PER_QUERY) {
        const char *what = q ? "any hit" : "closest hit";
        for (k = 0; k < 2; k++) {
            const int e = q + (k ? E2_ALL : EM_ALL);
            printf("  Embree (%s) / specnee, %s: all rays x%.2f (best) x%.2f (median); "
                   "box-hitting rays x%.2f x%.2f\n", k ? "isa=avx2" : "default", what,
                   best[q] / best[e], med[q] / med[e], best[q + 1] / best[e + 1],
                   med[q + 1] / med[e + 1]);
        }
        /* the faster Embree by its median time, on each set of rays */
        printf("  Embree (faster) / specnee, %s: all rays x%.2f (median); box-hitting rays "
               "x%.2f (median)\n", what,
               med[q] / (med[q + EM_ALL] < med[q + E2_ALL] ? med[q + EM_ALL] : med[q + E2_ALL]),
               med[q + 1] / (med[q + EM_BOX] < med[q + E2_BOX] ? med[q + EM_BOX] : med[q + E2_BOX]));
    }
    for (k = 0; k < 2; k++) {
        rtcReleaseScene(scene[k]);
        rtcReleaseDevice(dev[k]);
    }
    bvh_free(&s.bvh);
    free(rays); free(P); free(idx);
    return ok ? 0 : 1;
}
