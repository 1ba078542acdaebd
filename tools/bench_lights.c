/* tools/bench_lights.c - what emitter selection costs: table build time and the
   per-vertex cost of every strategy, against `uniform` (run by `make bench`).

   usage: tools/bench_lights [scene.pbrt]     (default scenes/cornell1.pbrt)

   Shading points are the first hits of 200,000 rays from the scene's centre in
   uniform directions (surfaces where a path really shades).  For each strategy:
     build   light_sampler_build (lazy: only the spectral table and the grid's
             pointers) and the eager build of every voxel (--eager-tables);
     fill    the lazy voxel tables touched by those points (first calls);
     select  ns per vertex for light_select + light_select_pmf (what the
             integrator calls at a vertex and at the next emitter hit), with
             random hero wavelengths, half of the vertices in hero-only mode.
   Ratios are against uniform, measured in the same run. */
#define _POSIX_C_SOURCE 200809L
#include "specnee.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "scenes/cornell1.pbrt";
    static const char *variants[] = { "uniform", "power", "spatial", "spd", "product",
                                      "spectral-spatial", "product:all", "spectral-spatial:all" };
    enum { NV = sizeof variants / sizeof variants[0], NP = 200000, CALLS = 2000000 };
    Scene s;
    Error err;
    Vec3 *pts;
    int n = 0, i, v;
    Rng rng;
    double base_ns = 0.0;
    Vec3 c;
    memset(&s, 0, sizeof s);
    if (!scene_load(&s, path, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    pts = (Vec3 *)malloc(sizeof(Vec3) * NP);
    if (!pts) return 1;
    c = v3_mul(v3_add(s.bmin, s.bmax), 0.5f);
    rng_seed(&rng, 1, 1);
    for (i = 0; i < NP; i++) {
        Ray r;
        HitRecord h;
        float z = 1 - 2 * rng_float(&rng), rr = sqrtf(fmaxf(0, 1 - z * z)), phi = 2 * PI_F * rng_float(&rng);
        r.o = c; r.d = v3(rr * cosf(phi), rr * sinf(phi), z); r.tmax = INFINITY;
        if (bvh_intersect(&s.bvh, &s, &r, &h)) pts[n++] = v3_add(r.o, v3_mul(r.d, h.t * 0.999f));
    }
    printf("scene %s: %d emitters, %d shading points\n", path, s.n_emitters, n);
    printf("%-22s %10s %10s %10s %12s %8s %10s\n", "strategy", "build ms", "eager ms", "fill ms",
           "ns/vertex", "x unif", "table KiB");
    for (v = 0; v < NV; v++) {
        RenderOptions o;
        LightSampler *ls, *eager;
        double t0, t_build, t_eager, t_fill, t_sel;
        volatile float sink = 0.0f;
        render_options_default(&o);
        eval_parse_variant(variants[v], &o);
        t0 = now();
        ls = light_sampler_build(&s, &o.sel, &err);
        t_build = now() - t0;
        o.sel.eager = 1;
        t0 = now();
        eager = light_sampler_build(&s, &o.sel, &err);
        t_eager = now() - t0;
        if (!ls || !eager) { fprintf(stderr, "%s\n", err.msg); return 1; }
        light_sampler_free(eager);
        t0 = now();
        for (i = 0; i < n; i++) {
            LightCtx ctx;
            float p;
            memset(&ctx, 0, sizeof ctx);
            ctx.p = pts[i];
            ctx.voxel = light_voxel(ls, pts[i]);
            ctx.alive = 15u;
            ctx.lambda[0] = 550.0f;
            light_select(ls, &ctx, 0.5f, &p, NULL);
        }
        t_fill = now() - t0;
        rng_seed(&rng, 2, 2);
        t0 = now();
        for (i = 0; i < CALLS; i++) {
            LightCtx ctx;
            float p;
            int j, e;
            memset(&ctx, 0, sizeof ctx);
            ctx.p = pts[i % n];
            ctx.voxel = light_voxel(ls, ctx.p);
            ctx.alive = (i & 1) ? 1u : 15u;       /* half with the hero alone */
            ctx.lambda[0] = 400.0f + 300.0f * rng_float(&rng);
            for (j = 1; j < HERO_N; j++) ctx.lambda[j] = ctx.lambda[0] + 75.0f * j > 700.0f ? ctx.lambda[0] + 75.0f * j - 300.0f : ctx.lambda[0] + 75.0f * j;
            for (j = 0; j < HERO_N; j++) ctx.beta[j] = 1.0f;
            e = light_select(ls, &ctx, rng_float(&rng), &p, NULL);
            sink += p + (e >= 0 ? light_select_pmf(ls, &ctx, e) : 0.0f);
        }
        t_sel = now() - t0;
        if (v == 0) base_ns = 1e9 * t_sel / CALLS;
        printf("%-22s %10.3f %10.1f %10.1f %12.1f %8.2f %10.1f\n", variants[v], 1e3 * t_build, 1e3 * t_eager,
               1e3 * t_fill, 1e9 * t_sel / CALLS, (1e9 * t_sel / CALLS) / base_ns,
               light_sampler_bytes(ls) / 1024.0);
        (void)sink;
        light_sampler_free(ls);
    }
    free(pts);
    scene_free(&s);
    return 0;
}
