/* tools/bench_lights.c - what emitter selection costs (run by `make bench`).

   usage: tools/bench_lights [scene.pbrt]     per-strategy table for one scene
                                              (default scenes/cornell1.pbrt)
          tools/bench_lights --many [NMAX] [--svg FILE] [--csv FILE] [--only a,b]
                             [--slow-max N]   cost against the number of emitters
                                              (--only: those strategies; spatial
                                              and product only up to N emitters)
          tools/bench_lights --hall N FILE    write the generated scene with N lamps

   ONE SCENE.  Shading points are the first hits of 200,000 rays from the scene's
   centre in uniform directions (surfaces where a path really shades).  For each
   strategy:
     build   light_sampler_build (lazy: only the spectral table and the grid's
             pointers) and the eager build of every voxel (--eager-tables);
     fill    the lazy voxel tables touched by those points (first calls);
     select  ns per vertex for light_select + light_select_pmf (what the
             integrator calls at a vertex and at the next emitter hit), with
             random hero wavelengths, half of the vertices with the hero alone.
   Ratios are against uniform, measured in the same run.

   MANY EMITTERS (--many).  The generated "hall" (write_hall below): a white room
   12 x 3 x 4 m with N small one-sided lamps in a grid under the ceiling, facing
   down, cycling over six spiky built-in spectra; every fifth lamp faces up (it
   lights only the ceiling), a wall in the middle of the hall hides part of them,
   and a dispersive glass sphere stands on the floor.  The lamps' total power
   does not depend on N.  For N = 4, 16, ..., NMAX (default 4096) and the
   strategies uniform, power, spatial, product, tree, spectral-tree:
     build ms   light_sampler_build
     ns/sel     light_select + light_select_pmf at 2,000 first-hit points
                (lazy voxels filled before timing), hero alone half of the time
     us/sample  CPU time of a 64x64, 8 spp render (maxdepth 5, 1 thread) per
                camera sample: the whole per-sample cost, tables included
     table KiB  light_sampler_bytes after the ns/sel loop
   Every time is CPU time of the process (the render: clock(), 1 thread), so a
   busy machine does not inflate it.  --svg writes the log-log chart of us/sample against N
   (docs/lighttree-cost.svg), --csv the table. */
#define _POSIX_C_SOURCE 200809L
#include "specnee.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* CPU time of this process: single-threaded timings that a busy machine does
   not inflate. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* First hits of n rays from the centre of s; returns how many hit. */
static int shading_points(const Scene *s, Vec3 *pts, int n, uint64_t seed)
{
    Rng rng;
    Vec3 c = v3_mul(v3_add(s->bmin, s->bmax), 0.5f);
    int i, m = 0;
    rng_seed(&rng, seed, 1);
    for (i = 0; i < n; i++) {
        Ray r;
        HitRecord h;
        float z = 1 - 2 * rng_float(&rng), rr = sqrtf(fmaxf(0, 1 - z * z)), phi = 2 * PI_F * rng_float(&rng);
        r.o = c; r.d = v3(rr * cosf(phi), rr * sinf(phi), z); r.tmax = INFINITY;
        if (bvh_intersect(&s->bvh, s, &r, &h)) pts[m++] = v3_add(r.o, v3_mul(r.d, h.t * 0.999f));
    }
    return m;
}

/* ns per light_select + light_select_pmf over the points, at least min_s seconds. */
static double select_ns(LightSampler *ls, const Vec3 *pts, int n, double min_s)
{
    Rng rng;
    volatile float sink = 0.0f;
    long calls = 0;
    double t0 = now(), t;
    rng_seed(&rng, 2, 2);
    do {
        int i;
        for (i = 0; i < 1000; i++, calls++) {
            LightCtx ctx;
            float p;
            int j, e;
            memset(&ctx, 0, sizeof ctx);
            ctx.p = pts[calls % n];
            ctx.voxel = light_voxel(ls, ctx.p);
            ctx.alive = (calls & 1) ? 1u : 15u;       /* half with the hero alone */
            ctx.hero_only = ctx.alive == 1u;
            ctx.lambda[0] = 400.0f + 300.0f * rng_float(&rng);
            for (j = 1; j < HERO_N; j++) ctx.lambda[j] = ctx.lambda[0] + 75.0f * j > 700.0f ? ctx.lambda[0] + 75.0f * j - 300.0f : ctx.lambda[0] + 75.0f * j;
            for (j = 0; j < HERO_N; j++) ctx.beta[j] = 1.0f;
            e = light_select(ls, &ctx, rng_float(&rng), &p, NULL);
            sink += p + (e >= 0 ? light_select_pmf(ls, &ctx, e) : 0.0f);
        }
        t = now() - t0;
    } while (t < min_s);
    (void)sink;
    return 1e9 * t / (double)calls;
}

static int one_scene(const char *path)
{
    static const char *variants[] = { "uniform", "power", "spatial", "spd", "product",
                                      "spectral-spatial", "product:all", "spectral-spatial:all",
                                      "tree", "spectral-tree" };
    enum { NV = sizeof variants / sizeof variants[0], NP = 200000 };
    Scene s;
    Error err;
    Vec3 *pts;
    int n, i, v;
    double base_ns = 0.0;
    memset(&s, 0, sizeof s);
    if (!scene_load(&s, path, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    pts = (Vec3 *)malloc(sizeof(Vec3) * NP);
    if (!pts) return 1;
    n = shading_points(&s, pts, NP, 1);
    printf("scene %s: %d emitters, %d shading points\n", path, s.n_emitters, n);
    printf("%-22s %10s %10s %10s %12s %8s %10s\n", "strategy", "build ms", "eager ms", "fill ms",
           "ns/vertex", "x unif", "table KiB");
    for (v = 0; v < NV; v++) {
        RenderOptions o;
        LightSampler *ls, *eager;
        double t0, t_build, t_eager, t_fill, ns;
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
        ns = select_ns(ls, pts, n, 0.5);
        if (v == 0) base_ns = ns;
        printf("%-22s %10.3f %10.1f %10.1f %12.1f %8.2f %10.1f\n", variants[v], 1e3 * t_build, 1e3 * t_eager,
               1e3 * t_fill, ns, ns / base_ns, light_sampler_bytes(ls) / 1024.0);
        light_sampler_free(ls);
    }
    free(pts);
    scene_free(&s);
    return 0;
}

/* ------------------------------------------------------------------ the hall */

/* The generated scene (see the top of this file) as pbrt-v4 text; malloc'd. */
static char *write_hall(int n)
{
    static const char *spectra[6] = { "stdillum-F2", "stdillum-F7", "stdillum-F11",
                                      "lamp-CFL1", "lamp-LED1", "lamp-LED2" };
    size_t cap = (size_t)n * 400 + 8192, len = 0;
    char *b = (char *)malloc(cap);
    int nx = 1, nz, i;
    float sx, sz, h, scale;
    if (!b) return NULL;
    while ((nx * nx) / 3 < n) nx++;                  /* about 3 x as many along the hall */
    nz = (n + nx - 1) / nx;
    if (nz < 1) nz = 1;
    sx = 12.0f / nx;                                 /* the hall runs along x: -6..6 */
    sz = 4.0f / nz;                                  /* and is 4 m wide: -2..2 */
    h = 0.15f * fminf(sx, sz);                       /* half-size of a lamp */
    scale = 8.0f / (n * h * h);                      /* total power independent of n */
    len += (size_t)snprintf(b + len, cap - len,
        "# bench hall: %d lamps (tools/bench_lights --hall; see its header)\n"
        "LookAt -5.5 1.4 -1.6  4 0.8 1.0  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 60 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ] \"string filename\" \"hall.pfm\"\n"
        "Sampler \"independent\" \"integer pixelsamples\" [ 4 ]\n"
        "Integrator \"path\" \"integer maxdepth\" [ 5 ]\n"
        "WorldBegin\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.7 700 0.7 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3  4 6 5 4 7 6  8 9 10 8 10 11  12 14 13 12 15 14  16 18 17 16 19 18  20 21 22 20 22 23 ]\n"
        "  \"point3 P\" [ -6 0 -2  -6 0 2  6 0 2  6 0 -2   -6 3 -2  -6 3 2  6 3 2  6 3 -2\n"
        "               -6 0 -2  6 0 -2  6 3 -2  -6 3 -2   -6 0 2  6 0 2  6 3 2  -6 3 2\n"
        "               -6 0 -2  -6 3 -2  -6 3 2  -6 0 2   6 0 -2  6 0 2  6 3 2  6 3 -2 ]\n"
        "# a partition in the middle of the hall hides the far lamps from the near half\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ 1 0 -2  1 0 1  1 2.9 1  1 2.9 -2 ]\n"
        "AttributeBegin\n Translate 0 0.5 0.6\n"
        " Material \"dielectric\" \"spectrum eta\" \"glass-F5\"\n"
        " Shape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n", n);
    for (i = 0; i < n; i++) {
        float x = -6.0f + sx * (0.5f + (float)(i % nx)), z = -2.0f + sz * (0.5f + (float)(i / nx)), y = 2.9f;
        int up = i % 5 == 4;                         /* faces the ceiling */
        len += (size_t)snprintf(b + len, cap - len,
            "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" \"%s\" \"float scale\" [ %g ]\n"
            " Shape \"trianglemesh\" \"integer indices\" [ %s ]\n"
            "  \"point3 P\" [ %g %g %g  %g %g %g  %g %g %g  %g %g %g ]\nAttributeEnd\n",
            spectra[i % 6], scale, up ? "0 2 1 0 3 2" : "0 1 2 0 2 3",
            x - h, y, z - h, x + h, y, z - h, x + h, y, z + h, x - h, y, z + h);
    }
    return b;
}

static int many(int nmax, int slow_max, const char *svg, const char *csv, const char *only)
{
    static const char *strat[] = { "uniform", "power", "spatial", "product", "tree", "spectral-tree" };
    enum { NS = sizeof strat / sizeof strat[0], NMAXPTS = 8, NPTS = 2000 };
    double xs[NMAXPTS], us[NS][NMAXPTS];
    int counts[NMAXPTS], nn = 0, k, v;
    FILE *fc = csv ? fopen(csv, "w") : NULL;
    for (k = 4; k <= nmax && nn < NMAXPTS; k *= 4) counts[nn++] = k;
    if (fc) fprintf(fc, "emitters,strategy,build_ms,ns_per_select_pmf,us_per_sample,table_kib\n");
    printf("%-8s %-14s %10s %10s %11s %10s\n", "emitters", "strategy", "build ms", "ns/sel", "us/sample",
           "table KiB");
    for (k = 0; k < nn; k++) {
        char *text = write_hall(counts[k]);
        Scene s;
        Error err;
        Vec3 pts[NPTS];
        int np;
        if (!text || !scene_load_string(&s, text, "hall", &err)) {
            fprintf(stderr, "%s\n", text ? err.msg : "out of memory");
            return 1;
        }
        free(text);
        np = shading_points(&s, pts, NPTS, 7);
        xs[k] = counts[k];
        for (v = 0; v < NS; v++) {
            RenderOptions o;
            LightSampler *ls;
            Image img;
            RenderStats st;
            double t0, t_build, ns;
            int i;
            us[v][k] = NAN;
            if (only && !strstr(only, strat[v])) continue;
            if ((!strcmp(strat[v], "spatial") || !strcmp(strat[v], "product")) && counts[k] > slow_max) continue;
            render_options_default(&o);
            eval_parse_variant(strat[v], &o);
            t0 = now();
            ls = light_sampler_build(&s, &o.sel, &err);
            t_build = now() - t0;
            if (!ls) { fprintf(stderr, "%s\n", err.msg); return 1; }
            for (i = 0; i < np; i++) {               /* fill the lazy voxels first */
                LightCtx ctx;
                float p;
                memset(&ctx, 0, sizeof ctx);
                ctx.p = pts[i];
                ctx.voxel = light_voxel(ls, pts[i]);
                ctx.alive = 15u;
                ctx.lambda[0] = 550.0f;
                light_select(ls, &ctx, 0.5f, &p, NULL);
            }
            ns = select_ns(ls, pts, np, 0.3);
            o.spp = 8;
            o.threads = 1;
            o.maxdepth = 5;
            if (!render(&s, &o, &img, &st, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
            us[v][k] = 1e6 * st.cpu_s / (double)st.samples;
            printf("%-8d %-14s %10.2f %10.1f %11.2f %10.1f\n", counts[k], strat[v], 1e3 * t_build, ns,
                   us[v][k], light_sampler_bytes(ls) / 1024.0);
            fflush(stdout);
            if (fc) fprintf(fc, "%d,%s,%.4f,%.2f,%.4f,%.1f\n", counts[k], strat[v], 1e3 * t_build, ns,
                            us[v][k], light_sampler_bytes(ls) / 1024.0);
            img_free(&img);
            light_sampler_free(ls);
        }
        scene_free(&s);
    }
    if (fc) fclose(fc);
    if (svg) {
        SvgSeries ser[NS];
        SvgChart ch;
        FILE *f = fopen(svg, "w");
        memset(&ch, 0, sizeof ch);
        ch.title = "Per-sample cost against the number of emitters (generated hall, 64x64, 8 spp, 1 thread)";
        ch.xlabel = "emitters";
        ch.ylabel = "CPU microseconds per camera sample";
        ch.logx = ch.logy = 1;
        for (v = 0; v < NS; v++) {
            memset(&ser[v], 0, sizeof ser[v]);
            ser[v].name = strat[v];
            ser[v].n = nn;
            ser[v].x = xs;
            ser[v].y = us[v];
            ser[v].dashed = v < 2;
        }
        if (!f || !svg_line_chart(f, &ch, ser, NS)) { fprintf(stderr, "%s: cannot write\n", svg); return 1; }
        fclose(f);
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "--hall")) {
        char *text;
        FILE *f;
        if (argc != 4 || atoi(argv[2]) < 1) { fprintf(stderr, "usage: tools/bench_lights --hall N FILE\n"); return 2; }
        text = write_hall(atoi(argv[2]));
        f = fopen(argv[3], "w");
        if (!text || !f || fputs(text, f) < 0) { fprintf(stderr, "%s: cannot write\n", argv[3]); return 1; }
        fclose(f);
        free(text);
        return 0;
    }
    if (argc > 1 && !strcmp(argv[1], "--many")) {
        int i, nmax = 4096, slow_max = 1 << 30;
        const char *svg = NULL, *csv = NULL, *only = NULL;
        for (i = 2; i < argc; i++) {
            if (!strcmp(argv[i], "--svg") && i + 1 < argc) svg = argv[++i];
            else if (!strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
            else if (!strcmp(argv[i], "--slow-max") && i + 1 < argc) slow_max = atoi(argv[++i]);
            else if (!strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
            else if (atoi(argv[i]) >= 4) nmax = atoi(argv[i]);
            else { fprintf(stderr, "usage: tools/bench_lights --many [NMAX] [--svg FILE] [--csv FILE] [--only a,b] [--slow-max N]\n"); return 2; }
        }
        return many(nmax, slow_max, svg, csv, only);
    }
    return one_scene(argc > 1 ? argv[1] : "scenes/cornell1.pbrt");
}
