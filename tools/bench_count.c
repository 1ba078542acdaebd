/* tools/bench_count.c - a fixed, small workload for counting instructions.

   WHAT IT DOES
     Builds tools/bench's mesh (the displaced icosphere, level 6 by default) and its
     incoherent rays, keeps the first n (default 50,000) that enter the mesh's box, and
     casts them once with bvh_intersect (closest hit) and once with bvh_occluded (any
     hit).  It prints the hit counts and the sum of the hit distances, so that two
     versions of bvh.c can be checked to give the same answers.  Run under callgrind,
     it gives instructions per box-entering ray, which do not depend on the load of
     the machine (docs/bvh.md):
       valgrind --tool=callgrind --toggle-collect=bvh_intersect tools/bench_count
       valgrind --tool=callgrind --toggle-collect=bvh_occluded tools/bench_count
     and divide callgrind's "Collected" by n.

   USE
     make tools/bench_count  (LIBOBJ, like tools/bench)
     tools/bench_count [level [n]]
*/
#define BENCH_NO_MAIN
#include "bench.c"

int main(int argc, char **argv)
{
    const int level = argc > 1 ? atoi(argv[1]) : 6, n_want = argc > 2 ? atoi(argv[2]) : 50000;
    int n_verts = 0, n_tris = 0, n_in = 0, i;
    float *P = NULL;
    int32_t *idx = NULL;
    Scene s;
    Ray *rays;
    CastResult c, a;
    (void)stats3;                     /* bench.c's, unused here */
    if (level < 1 || level > 8 || n_want < 1) {
        fprintf(stderr, "usage: %s [level 1..8, default 6] [rays, default 50000]\n", argv[0]);
        return 2;
    }
    rays = (Ray *)malloc((size_t)BENCH_RAYS * sizeof *rays);
    if (!rays || !icosphere(level, &P, &n_verts, &idx, &n_tris) ||
        !mesh_scene(&s, P, n_verts, idx, n_tris) || !bvh_build(&s.bvh, &s)) {
        fprintf(stderr, "bench_count: out of memory\n");
        return 1;
    }
    bench_rays(&s, rays, BENCH_RAYS);
    for (i = 0; i < BENCH_RAYS && n_in < n_want; i++)
        if (ray_hits_box(&rays[i], s.bmin, s.bmax)) rays[n_in++] = rays[i];
    c = cast(&s, rays, n_in, 1, 0);
    a = cast(&s, rays, n_in, 1, 1);
    printf("bench_count: level %d, %d triangles (%d wide nodes), %d box-entering rays: closest hit "
           "%ld hits, sum of t %.6f; any hit %ld hits\n", level, n_tris, s.bvh.n_nodes, n_in,
           c.hits, c.t_sum, a.hits);
    bvh_free(&s.bvh);
    free(rays); free(P); free(idx);
    return 0;
}
