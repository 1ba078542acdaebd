/* tools/bench_ab.c - two versions of the traversal (bvh.c) timed in one process.

   WHAT IT MEASURES
     The time of version B's bvh_intersect and bvh_occluded over version A's, on
     tools/bench's box-hitting rays (level 6), both versions answering from the
     same tree in the same memory.  A separate process per version (as
     tools/bench_embree and two builds of it) lands the tree at other physical
     addresses each time, and on the shared 2-core machine one build's ratio to
     Embree then spreads from 1.2 to 1.4 between processes (docs/bvh.md, "How it
     is measured"); here that spread is common to A and B and cancels.  Each
     round casts all rays with A and with B (the order alternating between rounds,
     so neither always runs on the caches the other left), and B's time over A's
     is taken per round; the median, quartiles and the ratio of the summed times
     are printed.  The hit counts and the sums of t of A and B must agree; the
     program stops with an error where they do not.
   WHAT IT CANNOT MEASURE
     A change of the tree's layout or build (bvhbuild.c, the BvhNode and BvhPrim
     types): both versions read the tree built by the current bvhbuild.c, and A
     is compiled against the current specnee.h.  Those are compared with
     tools/bench_count (instructions) and tools/bench_embree (time).

   USE (tools/bench_ab.sh builds A from a git revision and B from the work tree)
     sh tools/bench_ab.sh REV [rounds, default 41]
   The control: sh tools/bench_ab.sh HEAD with bvh.c unchanged gave medians of
   0.975 to 1.005 (closest hit) and 0.969 to 1.016 (any hit) in five runs on that
   machine (B a little ahead: where each copy's code lands), so a change is read
   against the control, not against 1.
*/
#define BENCH_NO_MAIN
#include "bench.c"

/* the two versions of bvh.c, their global names prefixed (bench_ab.sh): A another
   revision's, B the work tree's, compiled alike (the library's own bvh.o serves
   the build and the rest) */
int A_bvh_intersect(const Bvh *b, const Scene *s, const Ray *r, HitRecord *h);
int A_bvh_occluded(const Bvh *b, const Scene *s, const Ray *r);
int B_bvh_intersect(const Bvh *b, const Scene *s, const Ray *r, HitRecord *h);
int B_bvh_occluded(const Bvh *b, const Scene *s, const Ray *r);

/* Cast rays[0..n) with version B (b = 1) or A; CPU seconds. */
static double cast_ab(int b, int any, const Scene *s, const Ray *rays, int n, long *hits,
                      double *t_sum)
{
    const double t0 = cpu_s();
    long h = 0;
    double ts = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        HitRecord hr;
        if (any)
            h += b ? B_bvh_occluded(&s->bvh, s, &rays[i]) : A_bvh_occluded(&s->bvh, s, &rays[i]);
        else if (b ? B_bvh_intersect(&s->bvh, s, &rays[i], &hr)
                   : A_bvh_intersect(&s->bvh, s, &rays[i], &hr)) {
            h++;
            ts += hr.t;
        }
    }
    *hits = h;
    *t_sum = ts;
    return cpu_s() - t0;
}

int main(int argc, char **argv)
{
    const int rounds = argc > 1 ? atoi(argv[1]) : 41;
    int n_verts = 0, n_tris = 0, n_in = 0, i, k, any;
    float *P = NULL;
    int32_t *idx = NULL;
    Scene s;
    Ray *rays;
    double ratio[MAX_RUNS];
    (void)cast;                       /* bench.c's, unused here */
    if (rounds < 3 || rounds > MAX_RUNS) {
        fprintf(stderr, "usage: %s [rounds 3..%d, default 41]\n", argv[0], MAX_RUNS);
        return 2;
    }
    rays = (Ray *)malloc((size_t)BENCH_RAYS * sizeof *rays);
    if (!rays || !icosphere(6, &P, &n_verts, &idx, &n_tris) ||
        !mesh_scene(&s, P, n_verts, idx, n_tris) || !bvh_build(&s.bvh, &s)) {
        fprintf(stderr, "bench_ab: out of memory\n");
        return 1;
    }
    bench_rays(&s, rays, BENCH_RAYS);
    for (i = 0; i < BENCH_RAYS; i++)
        if (ray_hits_box(&rays[i], s.bmin, s.bmax)) rays[n_in++] = rays[i];
    printf("bench_ab: level 6, %d triangles, %d box-hitting rays, one thread, CPU time, "
           "%d rounds, A and B in turn\n", n_tris, n_in, rounds);
    for (any = 0; any < 2; any++) {
        double sum_a = 0.0, sum_b = 0.0, q1, med, q3, lo, hi;
        for (k = 0; k < rounds; k++) {
            long ha, hb;
            double ta, tb, sa, sb;
            if (k % 2) {
                tb = cast_ab(1, any, &s, rays, n_in, &hb, &sb);
                ta = cast_ab(0, any, &s, rays, n_in, &ha, &sa);
            } else {
                ta = cast_ab(0, any, &s, rays, n_in, &ha, &sa);
                tb = cast_ab(1, any, &s, rays, n_in, &hb, &sb);
            }
            if (ha != hb || sa != sb) {
                fprintf(stderr, "bench_ab: A and B differ (%s: %ld against %ld hits, sum of t "
                        "%.9g against %.9g)\n", any ? "any hit" : "closest hit", ha, hb, sa, sb);
                return 1;
            }
            ratio[k] = tb / ta;
            sum_a += ta;
            sum_b += tb;
        }
        stats3(ratio, rounds, &lo, &med, &hi);   /* sorts ratio */
        q1 = ratio[rounds / 4];
        q3 = ratio[(3 * rounds) / 4];
        printf("  %-12s time B / A: median %.3f (quartiles %.3f-%.3f, range %.3f-%.3f); "
               "summed %.3f\n", any ? "any hit" : "closest hit", med, q1, q3, lo, hi,
               sum_b / sum_a);
    }
    bvh_free(&s.bvh);
    free(rays); free(P); free(idx);
    return 0;
}
