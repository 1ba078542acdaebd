/* tools/bench_lights.c - what emitter selection costs (run by `make bench`).

   usage: tools/bench_lights [scene.pbrt]     per-strategy table for one scene
                                              (default scenes/cornell1.pbrt)
          tools/bench_lights --many [NMAX] [--svg FILE] [--csv FILE] [--only a,b]
                             [--slow-max N] [--runs R] [--geometry G]
                                              cost against the number of emitters
                                              (--only: those strategies; spatial
                                              and product only up to N emitters;
                                              --runs: renders per entry, default 5;
                                              --geometry: G lamp quads in every
                                              scene, N of them emitting)
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
                camera sample: the whole per-sample cost, render_begin (tables,
                radiance, wavelength pdf) included; the median and the minimum
                of R renders interleaved over N and strategy (round r renders
                every entry once; spatial and product, 100 x slower, once), and
                render_begin's share
     ratios     per strategy the cost at 1024 over that at 4 emitters (the
                issue-11 target), and every strategy against uniform per N
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

/* The generated scene (see the top of this file) as pbrt-v4 text; malloc'd.
   The lamps are laid out as for g lamps (g >= n); n of them, spread evenly over
   the grid, emit and the others are dark quads of the walls' material, so that
   g > n holds the geometry fixed while n varies (--geometry). */
static char *write_hall(int n, int g)
{
    static const char *spectra[6] = { "stdillum-F2", "stdillum-F7", "stdillum-F11",
                                      "lamp-CFL1", "lamp-LED1", "lamp-LED2" };
    size_t cap, len = 0;
    char *b;
    int nx = 1, nz, i, next = 0, k = 0;
    float sx, sz, h, scale;
    if (g < n) g = n;
    cap = (size_t)g * 400 + 8192;
    b = (char *)malloc(cap);
    if (!b) return NULL;
    while ((nx * nx) / 3 < g) nx++;                  /* about 3 x as many along the hall */
    nz = (g + nx - 1) / nx;
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
    for (i = 0; i < g; i++) {
        float x = -6.0f + sx * (0.5f + (float)(i % nx)), z = -2.0f + sz * (0.5f + (float)(i / nx)), y = 2.9f;
        int up = k % 5 == 4, lit = i == next && k < n;   /* every fifth lamp faces the ceiling */
        if (lit) {
            len += (size_t)snprintf(b + len, cap - len,
                "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" \"%s\" \"float scale\" [ %g ]\n",
                spectra[k % 6], scale);
            k++;
            next = (int)((long)k * g / n);
        } else {
            len += (size_t)snprintf(b + len, cap - len, "AttributeBegin\n");
            up = 0;
        }
        len += (size_t)snprintf(b + len, cap - len,
            " Shape \"trianglemesh\" \"integer indices\" [ %s ]\n"
            "  \"point3 P\" [ %g %g %g  %g %g %g  %g %g %g  %g %g %g ]\nAttributeEnd\n",
            up ? "0 2 1 0 3 2" : "0 1 2 0 2 3",
            x - h, y, z - h, x + h, y, z - h, x + h, y, z + h, x - h, y, z + h);
    }
    return b;
}

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : a > b;
}

/* The cost of one render at the bench's settings, CPU seconds: *setup for
   render_begin (emitter radiance, selection tables, wavelength pdf), *pass for
   the samples; returns the number of camera samples (0: failed). */
static double render_once(const Scene *s, const RenderOptions *o, double *setup, double *pass)
{
    Error err;
    RenderJob *j;
    double t0 = now(), t1, samples;
    j = render_begin(s, o, &err);
    t1 = now();
    if (!j || !render_advance(j, o->spp, o->spp, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        if (j) render_end(j);
        return 0.0;
    }
    *setup = t1 - t0;
    *pass = now() - t1;
    samples = (double)render_stats(j)->samples;
    render_end(j);
    return samples;
}

enum { NSTRAT = 6, NMAXPTS = 8, MAXRUNS = 64 };

static int many(int nmax, int slow_max, int runs, int geometry, const char *svg, const char *csv,
                const char *only)
{
    static const char *strat[NSTRAT] = { "uniform", "power", "spatial", "product", "tree", "spectral-tree" };
    enum { NPTS = 2000 };
    static double us_run[NMAXPTS][NSTRAT][MAXRUNS], setup_run[NMAXPTS][NSTRAT][MAXRUNS];
    double xs[NMAXPTS], med[NSTRAT][NMAXPTS], mins[NSTRAT][NMAXPTS], setup_med[NSTRAT][NMAXPTS];
    double build_ms[NMAXPTS][NSTRAT], ns_sel[NMAXPTS][NSTRAT], kib[NMAXPTS][NSTRAT];
    int nrun[NMAXPTS][NSTRAT], want[NMAXPTS][NSTRAT];
    int counts[NMAXPTS], nn = 0, k, v, r, i4 = -1, i1024 = -1;
    Scene scenes[NMAXPTS];
    FILE *fc = csv ? fopen(csv, "w") : NULL;
    for (k = 4; k <= nmax && nn < NMAXPTS; k *= 4) counts[nn++] = k;
    if (runs < 1) runs = 1;
    if (runs > MAXRUNS) runs = MAXRUNS;
    if (geometry > 0)
        printf("lamp geometry held fixed: %d lamp quads in every scene, N of them emit\n", geometry);
    /* pass 1: per N and strategy the selection microbenchmarks and one render */
    for (k = 0; k < nn; k++) {
        char *text = write_hall(counts[k], geometry);
        Error err;
        Vec3 pts[NPTS];
        int np;
        if (!text || !scene_load_string(&scenes[k], text, "hall", &err)) {
            fprintf(stderr, "%s\n", text ? err.msg : "out of memory");
            return 1;
        }
        free(text);
        np = shading_points(&scenes[k], pts, NPTS, 7);
        xs[k] = counts[k];
        if (counts[k] == 4) i4 = k;
        if (counts[k] == 1024) i1024 = k;
        for (v = 0; v < NSTRAT; v++) {
            RenderOptions o;
            LightSampler *ls;
            double t0;
            int i;
            nrun[k][v] = 0;
            med[v][k] = mins[v][k] = setup_med[v][k] = NAN;
            want[k][v] = !(only && !strstr(only, strat[v])) &&
                         !((!strcmp(strat[v], "spatial") || !strcmp(strat[v], "product")) && counts[k] > slow_max);
            if (!want[k][v]) continue;
            render_options_default(&o);
            eval_parse_variant(strat[v], &o);
            t0 = now();
            ls = light_sampler_build(&scenes[k], &o.sel, &err);
            build_ms[k][v] = 1e3 * (now() - t0);
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
            ns_sel[k][v] = select_ns(ls, pts, np, 0.3);
            kib[k][v] = light_sampler_bytes(ls) / 1024.0;
            light_sampler_free(ls);
        }
    }
    /* pass 2: the renders, interleaved: round r renders every N and strategy once,
       so that a busy spell of the machine slows them alike; spatial and product
       (100 x slower) render in the first round only */
    for (r = 0; r < runs; r++)
        for (k = 0; k < nn; k++)
            for (v = 0; v < NSTRAT; v++) {
                RenderOptions o;
                double setup, pass, samples;
                if (!want[k][v]) continue;
                if (r > 0 && (!strcmp(strat[v], "spatial") || !strcmp(strat[v], "product"))) continue;
                render_options_default(&o);
                eval_parse_variant(strat[v], &o);
                o.spp = 8;
                o.threads = 1;
                o.maxdepth = 5;
                samples = render_once(&scenes[k], &o, &setup, &pass);
                if (!(samples > 0.0)) return 1;
                us_run[k][v][nrun[k][v]] = 1e6 * (setup + pass) / samples;
                setup_run[k][v][nrun[k][v]] = 1e6 * setup / samples;
                nrun[k][v]++;
            }
    printf("%-8s %-14s %9s %9s %10s %10s %10s %10s\n", "emitters", "strategy", "build ms", "ns/sel",
           "us/sample", "(min)", "(setup)", "table KiB");
    if (fc) fprintf(fc, "emitters,strategy,build_ms,ns_per_select_pmf,us_per_sample,us_per_sample_min,"
                        "us_setup_per_sample,table_kib,runs\n");
    for (k = 0; k < nn; k++)
        for (v = 0; v < NSTRAT; v++) {
            int m = nrun[k][v];
            if (!want[k][v] || m == 0) continue;
            qsort(us_run[k][v], (size_t)m, sizeof(double), cmp_double);
            qsort(setup_run[k][v], (size_t)m, sizeof(double), cmp_double);
            med[v][k] = m % 2 ? us_run[k][v][m / 2] : 0.5 * (us_run[k][v][m / 2 - 1] + us_run[k][v][m / 2]);
            mins[v][k] = us_run[k][v][0];
            setup_med[v][k] = m % 2 ? setup_run[k][v][m / 2]
                                    : 0.5 * (setup_run[k][v][m / 2 - 1] + setup_run[k][v][m / 2]);
            printf("%-8d %-14s %9.2f %9.1f %10.2f %10.2f %10.2f %10.1f\n", counts[k], strat[v], build_ms[k][v],
                   ns_sel[k][v], med[v][k], mins[v][k], setup_med[v][k], kib[k][v]);
            if (fc) fprintf(fc, "%d,%s,%.4f,%.2f,%.4f,%.4f,%.4f,%.1f,%d\n", counts[k], strat[v], build_ms[k][v],
                            ns_sel[k][v], med[v][k], mins[v][k], setup_med[v][k], kib[k][v], m);
        }
    printf("us/sample: median of %d interleaved renders (spatial, product: 1), (min) their minimum, "
           "(setup) the median of render_begin's share\n", runs);
    if (i4 >= 0 && i1024 >= 0) {
        printf("per-sample cost, 1024 vs 4 emitters (median; min):\n");
        for (v = 0; v < NSTRAT; v++)
            if (nrun[i4][v] > 0 && nrun[i1024][v] > 0)
                printf("  %-14s %5.2fx  %5.2fx\n", strat[v], med[v][i1024] / med[v][i4],
                       mins[v][i1024] / mins[v][i4]);
    }
    if (nrun[0][0] > 0) {
        printf("per-sample cost against uniform at the same N (median):\n");
        for (k = 0; k < nn; k++) {
            printf("  %-6d", counts[k]);
            for (v = 1; v < NSTRAT; v++)
                if (nrun[k][v] > 0) printf("  %s %.2fx", strat[v], med[v][k] / med[0][k]);
            printf("\n");
        }
    }
    for (k = 0; k < nn; k++) scene_free(&scenes[k]);
    if (fc) fclose(fc);
    if (svg) {
        SvgSeries ser[NSTRAT];
        SvgChart ch;
        FILE *f = fopen(svg, "w");
        memset(&ch, 0, sizeof ch);
        ch.title = geometry > 0 ? "Per-sample cost against the number of emitters (hall, lamp geometry fixed, "
                                  "64x64, 8 spp, 1 thread, median)"
                                : "Per-sample cost against the number of emitters (generated hall, 64x64, 8 spp, "
                                  "1 thread, median)";
        ch.xlabel = "emitters";
        ch.ylabel = "CPU microseconds per camera sample";
        ch.logx = ch.logy = 1;
        for (v = 0; v < NSTRAT; v++) {
            memset(&ser[v], 0, sizeof ser[v]);
            ser[v].name = strat[v];
            ser[v].n = nn;
            ser[v].x = xs;
            ser[v].y = med[v];
            ser[v].dashed = v < 2;
        }
        if (!f || !svg_line_chart(f, &ch, ser, NSTRAT)) { fprintf(stderr, "%s: cannot write\n", svg); return 1; }
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
        text = write_hall(atoi(argv[2]), 0);
        f = fopen(argv[3], "w");
        if (!text || !f || fputs(text, f) < 0) { fprintf(stderr, "%s: cannot write\n", argv[3]); return 1; }
        fclose(f);
        free(text);
        return 0;
    }
    if (argc > 1 && !strcmp(argv[1], "--many")) {
        int i, nmax = 4096, slow_max = 1 << 30, runs = 5, geometry = 0;
        const char *svg = NULL, *csv = NULL, *only = NULL;
        for (i = 2; i < argc; i++) {
            if (!strcmp(argv[i], "--svg") && i + 1 < argc) svg = argv[++i];
            else if (!strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
            else if (!strcmp(argv[i], "--slow-max") && i + 1 < argc) slow_max = atoi(argv[++i]);
            else if (!strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
            else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
            else if (!strcmp(argv[i], "--geometry") && i + 1 < argc) geometry = atoi(argv[++i]);
            else if (atoi(argv[i]) >= 4) nmax = atoi(argv[i]);
            else { fprintf(stderr, "usage: tools/bench_lights --many [NMAX] [--svg FILE] [--csv FILE] [--only a,b] [--slow-max N] [--runs R] [--geometry G]\n"); return 2; }
        }
        return many(nmax, slow_max, runs, geometry, svg, csv, only);
    }
    return one_scene(argc > 1 ? argv[1] : "scenes/cornell1.pbrt");
}
