/* cmd_converge.c - speed against accuracy: `specnee converge`, the evaluation driver.

   Exported: cmd_converge, eval_parse_variant (specnee.h section 14).  A command
   room: it parses its command line, loads the scene and drives render.c's
   RenderJob; specnee.c dispatches `specnee converge` to it.

   For every variant (an emitter-selection strategy plus modifiers), every spp of
   a ladder and K seeds, render the scene, time it (wall and CPU time; lazily
   built tables are inside the wall time, eager ones reported apart) and measure
   the error against a reference over the whole image and the scene's insets:
       MSE    = mean over pixels and channels of (a - r)^2
       relMSE = mean of (a - r)^2 / (r^2 + 1e-2)           (Rousselle et al. 2011)
   Outputs, with PREFIX from --out:
       PREFIX.csv              one row per (variant, spp, seed, region)
       PREFIX_mse_spp.svg      MSE against spp, log-log, band = min..max over seeds
       PREFIX_mse_time.svg     MSE against time (CPU time unless --time wall), log-log
       PREFIX_efficiency.svg   efficiency 1/(MSE x time) relative to the baseline
       PREFIX.png              the baseline's seed-0 render at the largest spp,
                               insets outlined (png_write_marked)
       PREFIX.md               tables: MSE change against the baseline at the
                               largest spp and at equal time, mean and 95% CI
   Progressive: one render per (variant, seed) climbs the whole ladder (a
   RenderJob), each rung timed as the render so far; its image is bit-identical
   to a separate render with that spp, so the ladder costs the largest spp once
   instead of the sum of all rungs.  A variant whose sampler is not progressive
   (stratified, zsobol: their samples depend on the total spp) renders every rung
   separately, timed alone; converge says so on stderr and never mixes the two.  The variants of a seed take turns rung by
   rung, which pairs their timings (a slow spell of the machine hits all).
   Time: process CPU time by default (all threads; not charged while other
   programs hold the cores, so a busy machine barely moves it), wall time with
   --time wall.  Both are in the CSV.
   Statistics.  For seed k the change of variant v is c_k = MSE_v,k / MSE_b,k - 1
   (b = the baseline, the first variant unless --baseline), reported as the mean
   over seeds with the 95% confidence interval mean +- t_{0.975, K-1} s / sqrt(K).
   Equal time: a variant's cost is its time per rung averaged over the seeds
   (timing noise between renders, e.g. a busy machine, is not sampling noise);
   per seed, the variant's (mean time, MSE) ladder is interpolated in log-log at
   the baseline's mean time for the largest spp, beyond the ladder extended with
   MSE proportional to 1/time (the Monte Carlo rate).  Both the time ratio
   against the baseline (per seed, paired) and the equal-time change are
   averaged in log space (geometric means); the equal-time interval combines the
   sampling noise of the MSE and the timing noise of the time ratio, which are
   independent: half-width sqrt(h_mse^2 + h_time^2) in log space. */
#define _POSIX_C_SOURCE 200809L
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

#define MAX_VARIANTS 40      /* the factorial evaluation (tools/factorial.sh) runs 32 */
#define MAX_SPP 16
#define MAX_SEEDS 64
#define MAX_REGIONS 9

/* "name[:modifier]...": modifiers power, all, tput, importance, visible, mixture,
   mixture=M (weight M of visible), uniform (the wavelength pdf), roughmis, single,
   wide, nonee, nosplit (light trees: a large emissive mesh stays one leaf),
   shapearea shapesa shapeauto (--light-shape-sampling area, solidangle, auto), a
   sampler (independent stratified sobol zsobol), fluorescence (flpower fluniform
   fla flkeep flterminate), media (medterminate medmis: --chromatic-media), and
   terminate, hero, unit that
   pin a setting to the thesis' value whatever the defaults (the factorial
   evaluation names every factor).  Returns 0 on an unknown name or modifier. */
int eval_parse_variant(const char *spec, RenderOptions *o)
{
    char buf[128], *tok, *save = NULL;
    snprintf(buf, sizeof buf, "%s", spec);
    tok = strtok_r(buf, ":", &save);
    if (!tok) return 0;
    o->sel.strategy = sel_from_name(tok);
    if (o->sel.strategy == SEL_COUNT) return 0;
    while ((tok = strtok_r(NULL, ":", &save)) != NULL) {
        if (!strcmp(tok, "power")) o->sel.power_metric = 1;
        else if (!strcmp(tok, "all")) o->sel.all_wavelengths = 1;
        else if (!strcmp(tok, "tput")) { o->sel.all_wavelengths = 1; o->sel.throughput_weighted = 1; }
        else if (!strcmp(tok, "importance")) o->wl_mode = WL_IMPORTANCE;
        else if (!strcmp(tok, "visible")) o->wl_mode = WL_VISIBLE;
        else if (!strcmp(tok, "mixture")) o->wl_mode = WL_MIXTURE;
        else if (!strncmp(tok, "mixture=", 8)) {        /* mixture=M: with weight M */
            char *end;
            double m = strtod(tok + 8, &end);
            if (*end || !(m > 0.0 && m <= 1.0)) return 0;
            o->wl_mode = WL_MIXTURE;
            o->wl_mix = (float)m;
        }
        else if (!strcmp(tok, "uniform")) o->wl_mode = WL_UNIFORM;
        else if (!strcmp(tok, "roughmis")) o->rough_mis = 1;
        else if (!strcmp(tok, "terminate")) o->rough_mis = 0;      /* pinned, whatever the default */
        else if (!strcmp(tok, "hero")) o->sel.all_wavelengths = o->sel.throughput_weighted = 0;
        else if (!strcmp(tok, "unit")) o->sel.power_metric = 0;
        else if (!strcmp(tok, "single")) o->single_wavelength = 1;
        else if (!strcmp(tok, "wide")) o->wl_wide = 1;
        else if (!strcmp(tok, "nonee")) o->nee = 0;
        else if (!strcmp(tok, "flpower")) o->fluor_li = FLUOR_LI_POWER;     /* --fluor-li power */
        else if (!strcmp(tok, "fluniform")) o->fluor_li = FLUOR_LI_UNIFORM; /* --fluor-li uniform */
        else if (!strcmp(tok, "fla")) o->fluor_li = FLUOR_LI_A;             /* --fluor-li a */
        else if (!strcmp(tok, "flkeep")) o->fluor_keep = 1;                 /* --fluor-lanes keep */
        else if (!strcmp(tok, "flterminate")) o->fluor_keep = 0;
        else if (!strcmp(tok, "nosplit")) o->sel.no_split = 1;
        else if (!strcmp(tok, "shapearea")) o->sel.area_sampling = 1;   /* --light-shape-sampling area */
        else if (!strcmp(tok, "shapesa")) o->sel.area_sampling = 0;     /* ... solidangle */
        else if (!strcmp(tok, "shapeauto")) o->sel.area_sampling = SHAPE_AUTO;   /* ... auto */
        else if (!strcmp(tok, "medterminate")) o->media_terminate = 1;   /* --chromatic-media terminate */
        else if (!strcmp(tok, "medmis")) o->media_terminate = 0;
        else if (sampler_from_name(tok) != SAMPLER_COUNT) o->sampler = sampler_from_name(tok);
        else return 0;
    }
    return 1;
}

/* 97.5% quantile of Student's t for dof 1..30 (standard tables); 1.96 beyond. */
static double t975(int dof)
{
    static const double t[30] = {
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
        2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
        2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042 };
    if (dof < 1) return 0.0;
    return dof <= 30 ? t[dof - 1] : 1.96;
}

static void mean_ci(const double *x, int n, double *mean, double *half)
{
    double s = 0, s2 = 0;
    int i;
    for (i = 0; i < n; i++) s += x[i];
    *mean = s / n;
    for (i = 0; i < n; i++) s2 += (x[i] - *mean) * (x[i] - *mean);
    *half = n > 1 ? t975(n - 1) * sqrt(s2 / (n - 1)) / sqrt((double)n) : 0.0;
}

/* Parse "a,b,c" into up to max items; returns the count (0 on error). */
static int split_list(const char *s, char items[][64], int max)
{
    int n = 0;
    const char *p = s;
    while (*p) {
        const char *c = strchr(p, ',');
        size_t len = c ? (size_t)(c - p) : strlen(p);
        if (n >= max || len == 0 || len >= 64) return 0;
        memcpy(items[n], p, len);
        items[n][len] = 0;
        n++;
        if (!c) break;
        p = c + 1;
    }
    return n;
}

/* MSE at time T from a (time, mse) ladder, interpolated in log-log. */
static double mse_at_time(const double *t, const double *m, int n, double T)
{
    int i;
    if (n <= 0) return NAN;
    if (T <= t[0]) return m[0] * t[0] / T;
    for (i = 0; i + 1 < n; i++) {
        if (T == t[i + 1]) return m[i + 1];
        if (T <= t[i + 1] && t[i + 1] > t[i] && m[i] > 0 && m[i + 1] > 0) {
            double a = (log(T) - log(t[i])) / (log(t[i + 1]) - log(t[i]));
            return exp(log(m[i]) + a * (log(m[i + 1]) - log(m[i])));
        }
    }
    return m[n - 1] * t[n - 1] / T;
}

#define IDX(v, s, k) (((size_t)(v) * MAX_SPP + (s)) * MAX_SEEDS + (k))
#define RIDX(v, s, k, r) (IDX(v, s, k) * MAX_REGIONS + (r))

/* What record_rung needs to file one rung of one (variant, seed) render. */
typedef struct {
    const char *scene_path, *variant;
    int v, k;
    const int *spp;
    const Image *ref;
    int n_reg;
    int (*reg)[4];
    char (*reg_name)[16];
    double *mse, *relmse, *mae, *wall, *cpu, *build;
    FILE *csv;
    const char *png;      /* write this rendering's last rung here, insets outlined (NULL: no) */
    int last;             /* index of the last rung */
    float exposure;
} Rung;

/* After rung s of one (variant, seed) render: the errors of its image against the
   reference, for every region, into the arrays and one CSV row per region. */
static void record_rung(Rung *R, int s, const Image *img, const RenderStats *st)
{
    int r, v = R->v, k = R->k;
    R->wall[IDX(v, s, k)] = st->wall_s;
    R->cpu[IDX(v, s, k)] = st->cpu_s;
    R->build[IDX(v, s, k)] = st->build_s;
    for (r = 0; r < R->n_reg; r++) {
        ImgErr e;
        if (!img_error(img, R->ref, R->reg[r][0], R->reg[r][1], R->reg[r][2], R->reg[r][3], &e))
            e.mse = e.relmse = e.mae = NAN;
        R->mse[RIDX(v, s, k, r)] = e.mse;
        R->relmse[RIDX(v, s, k, r)] = e.relmse;
        R->mae[RIDX(v, s, k, r)] = e.mae;
        fprintf(R->csv, "%s,%s,%d,%d,%.6f,%.6f,%.6f,%s,%.9g,%.9g,%.9g\n", R->scene_path, R->variant,
                R->spp[s], k, st->wall_s, st->cpu_s, st->build_s, R->reg_name[r], e.mse, e.relmse, e.mae);
    }
    fflush(R->csv);
    if (R->png && s == R->last && !png_write_marked(img, R->png, R->exposure, &R->reg[1][0], R->n_reg - 1))
        fprintf(stderr, "%s: cannot write\n", R->png);
    fprintf(stderr, "converge: %s spp %d seed %d: %.3f s wall, %.3f s CPU, MSE %.4g\n", R->variant,
            R->spp[s], k, st->wall_s, st->cpu_s, R->mse[RIDX(v, s, k, 0)]);
}

/* --reuse: fill the arrays from the CSV of an earlier run with the same variants,
   ladder, seeds and regions, instead of rendering.  Every (variant, spp, seed,
   region) must be present exactly once; anything else is an error naming the line. */
static int read_csv(const char *path, char var_names[][64], int n_var, const int *spp, int n_spp, int K,
                    char reg_name[][16], int n_reg, double *mse, double *relmse, double *mae,
                    double *wall, double *cpu, double *build)
{
    FILE *f = fopen(path, "r");
    char line[1024];
    int lineno = 0, want = n_var * n_spp * K * n_reg, got = 0, bad = 0;
    unsigned char *seen = (unsigned char *)calloc((size_t)MAX_VARIANTS * MAX_SPP * MAX_SEEDS * MAX_REGIONS, 1);
    if (!f || !seen) {
        fprintf(stderr, "%s: cannot read (run without --reuse first)\n", path);
        if (f) fclose(f);
        free(seen);
        return 0;
    }
    while (fgets(line, sizeof line, f)) {
        char *field[11], *p = line, *save = NULL;
        int nf = 0, v, s, k, r, sp;
        lineno++;
        if (lineno == 1) continue;   /* the header */
        line[strcspn(line, "\r\n")] = 0;
        for (p = strtok_r(line, ",", &save); p && nf < 11; p = strtok_r(NULL, ",", &save)) field[nf++] = p;
        if (nf != 11) { fprintf(stderr, "%s:%d: expected 11 fields\n", path, lineno); bad = 1; break; }
        for (v = 0; v < n_var && strcmp(var_names[v], field[1]); v++) {}
        sp = atoi(field[2]);
        for (s = 0; s < n_spp && spp[s] != sp; s++) {}
        k = atoi(field[3]);
        for (r = 0; r < n_reg && strcmp(reg_name[r], field[7]); r++) {}
        if (v == n_var || s == n_spp || k < 0 || k >= K || r == n_reg) continue;   /* not asked for */
        if (seen[RIDX(v, s, k, r)]++) { fprintf(stderr, "%s:%d: a second row for this render\n", path, lineno); bad = 1; break; }
        wall[IDX(v, s, k)] = atof(field[4]);
        cpu[IDX(v, s, k)] = atof(field[5]);
        build[IDX(v, s, k)] = atof(field[6]);
        mse[RIDX(v, s, k, r)] = atof(field[8]);
        relmse[RIDX(v, s, k, r)] = atof(field[9]);
        mae[RIDX(v, s, k, r)] = atof(field[10]);
        got++;
    }
    fclose(f);
    free(seen);
    if (bad) return 0;
    if (got != want) {
        fprintf(stderr, "%s: %d of the %d rows these settings need (same --lights, --spp, --seeds?)\n", path, got, want);
        return 0;
    }
    return 1;
}

static const char usage_converge[] =
    "usage: specnee converge SCENE --ref REF.pfm [--lights v1,v2,...] [--spp 16,32,...]\n"
    "         [--seeds K] [--out PREFIX] [--baseline NAME] [--threads N] [--maxdepth N]\n"
    "         [--time cpu|wall] [--base defaults|thesis] [--reuse]\n"
    "  variants: a strategy (uniform power spatial spd product spectral-spatial all\n"
    "  tree spectral-tree)\n"
    "  with modifiers, e.g. spd:power, product:all, product:tput, spatial:importance,\n"
    "  spatial:visible, spatial:mixture, spatial:mixture=0.1, spatial:roughmis,\n"
    "  spatial:single, spatial:nonee, spectral-tree:nosplit, product:flpower\n"
    "  (--fluor-li power), product:fluniform (--fluor-li uniform), product:fla\n"
    "  (--fluor-li a), product:flkeep (--fluor-lanes keep), product:flterminate,\n"
    "  spectral-tree:medterminate (--chromatic-media terminate), spectral-tree:medmis,\n"
    "  spectral-tree:shapearea (--light-shape-sampling area), spectral-tree:shapesa,\n"
    "  and a sampler:\n"
    "  spatial:sobol, spatial:zsobol, spatial:stratified, spatial:independent\n"
    "  (stratified and zsobol are not progressive: their rungs are rendered one by\n"
    "  one).  The first is the baseline.\n"
    "  --time: the time axis and the equal-time comparison use process CPU time\n"
    "  (default: not charged while other programs run) or wall time.\n"
    "  --base: what a variant's unnamed settings are: the defaults (default) or the\n"
    "  thesis' (--preset thesis: uniform wavelengths, terminate, unit, hero,\n"
    "  independent sampler, fluorescence terminate and a), so that a table keeps\n"
    "  its meaning when defaults change.\n"
    "  --reuse: no rendering; the charts and tables are rebuilt from PREFIX.csv of an\n"
    "  earlier run with the same variants, ladder and seeds.\n";

/* The command line of converge. */
typedef struct {
    const char *scene_path, *ref_path, *prefix, *baseline;
    char var_names[MAX_VARIANTS][64];
    char spp_s[MAX_SPP][64];   /* the --spp list as given */
    int n_var, n_spp, spp[MAX_SPP];
    int K, threads, maxdepth;  /* seeds; --threads; --maxdepth (-1: the scene's) */
    int b;                     /* the baseline's index in var_names */
    int use_cpu, reuse, base_thesis;
} ConvergeArgs;

/* The regions the errors are measured over: the whole image, then the scene's insets. */
typedef struct {
    int n;
    int rect[MAX_REGIONS][4];
    char name[MAX_REGIONS][16];
} Regions;

/* The measurements: errors at RIDX(variant, rung, seed, region), times at
   IDX(variant, rung, seed). */
typedef struct { double *mse, *relmse, *mae, *wall, *cpu, *build; } Measures;

/* The options into A.  Returns -1 to go on, else the exit code (0 after --help). */
static int converge_options(int argc, char **argv, ConvergeArgs *A)
{
    int i;
    memset(A, 0, sizeof *A);
    A->prefix = "converge";
    A->n_var = 1;
    A->K = 4;
    A->maxdepth = -1;
    A->use_cpu = 1;
    strcpy(A->var_names[0], "spatial");
    A->n_spp = split_list("16,32,64,128", A->spp_s, MAX_SPP);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) { fputs(usage_converge, stdout); return 0; }
        if (!strcmp(a, "--reuse")) { A->reuse = 1; continue; }
        if (a[0] == '-' && !val) { fprintf(stderr, "converge: %s needs a value\n%s", a, usage_converge); return 2; }
        if (!strcmp(a, "--ref")) A->ref_path = argv[++i];
        else if (!strcmp(a, "--lights")) {
            A->n_var = split_list(argv[++i], A->var_names, MAX_VARIANTS);
            if (!A->n_var) { fprintf(stderr, "converge: bad --lights list\n"); return 2; }
        } else if (!strcmp(a, "--spp")) {
            A->n_spp = split_list(argv[++i], A->spp_s, MAX_SPP);
            if (!A->n_spp) { fprintf(stderr, "converge: bad --spp list\n"); return 2; }
        } else if (!strcmp(a, "--seeds")) {
            A->K = atoi(argv[++i]);
            if (A->K < 2 || A->K > MAX_SEEDS) { fprintf(stderr, "converge: --seeds must be 2..%d\n", MAX_SEEDS); return 2; }
        } else if (!strcmp(a, "--out")) A->prefix = argv[++i];
        else if (!strcmp(a, "--baseline")) A->baseline = argv[++i];
        else if (!strcmp(a, "--base")) {
            const char *bv = argv[++i];
            if (!strcmp(bv, "thesis")) A->base_thesis = 1;
            else if (!strcmp(bv, "defaults")) A->base_thesis = 0;
            else { fprintf(stderr, "converge: --base must be defaults or thesis, not '%s'\n", bv); return 2; }
        }
        else if (!strcmp(a, "--threads")) A->threads = atoi(argv[++i]);
        else if (!strcmp(a, "--maxdepth")) A->maxdepth = atoi(argv[++i]);
        else if (!strcmp(a, "--time")) {
            const char *tv = argv[++i];
            if (!strcmp(tv, "cpu")) A->use_cpu = 1;
            else if (!strcmp(tv, "wall")) A->use_cpu = 0;
            else { fprintf(stderr, "converge: --time must be cpu or wall, not '%s'\n", tv); return 2; }
        }
        else if (a[0] == '-') { fprintf(stderr, "converge: unknown option '%s'\n%s", a, usage_converge); return 2; }
        else if (!A->scene_path) A->scene_path = a;
        else { fprintf(stderr, "converge: more than one scene\n"); return 2; }
    }
    if (!A->scene_path || !A->ref_path) { fputs(usage_converge, stderr); return 2; }
    return -1;
}

/* The spp ladder (positive, increasing) and the variants (known names; the
   baseline's index).  Returns -1 to go on, else the exit code 2. */
static int converge_ladder(ConvergeArgs *A)
{
    int s, v;
    for (s = 0; s < A->n_spp; s++) {
        A->spp[s] = atoi(A->spp_s[s]);
        if (A->spp[s] <= 0) { fprintf(stderr, "converge: bad spp '%s'\n", A->spp_s[s]); return 2; }
        if (s > 0 && A->spp[s] <= A->spp[s - 1]) {
            fprintf(stderr, "converge: the --spp ladder must increase ('%s' after '%s')\n", A->spp_s[s],
                    A->spp_s[s - 1]);
            return 2;
        }
    }
    for (v = 0; v < A->n_var; v++) {
        RenderOptions o;
        if (A->base_thesis) render_options_thesis(&o); else render_options_default(&o);
        if (!eval_parse_variant(A->var_names[v], &o)) {
            fprintf(stderr, "converge: unknown variant '%s'\n", A->var_names[v]);
            return 2;
        }
        if (A->baseline && !strcmp(A->baseline, A->var_names[v])) A->b = v;
        if (!sampler_progressive(o.sampler) && !A->reuse)
            fprintf(stderr, "converge: %s: the %s sampler is not progressive (its samples depend on "
                    "the total spp): every rung is a separate render, timed alone\n",
                    A->var_names[v], sampler_name(o.sampler));
    }
    return -1;
}

/* The scene, the reference (the size of the image render() makes: the film, or its
   crop, Film cropwindow) and the regions: the whole image, then the scene's insets
   in the rendered part.  0 after a message (nothing left to free). */
static int converge_inputs(const ConvergeArgs *A, Scene *scene, Image *ref, Regions *R)
{
    Error err;
    int fb[4], rect[8][4], n_rect, i;
    const char *names[8];
    memset(scene, 0, sizeof *scene);
    if (!scene_load(scene, A->scene_path, &err)) { fprintf(stderr, "%s\n", err.msg); return 0; }
    if (scene->settings.spectral) {
        /* the spectral film draws its own uniform wavelengths: the strategies
           converge compares would not be the ones rendered */
        fprintf(stderr, "%s: converge compares RGB images under wavelength and light strategies; "
                "Film \"spectral\" fixes the wavelengths (uniform): give Film \"rgb\"\n", A->scene_path);
        scene_free(scene);
        return 0;
    }
    if (!pfm_read(ref, A->ref_path, &err)) { fprintf(stderr, "%s\n", err.msg); scene_free(scene); return 0; }
    film_bounds(&scene->settings, fb);
    if (ref->w != fb[1] - fb[0] || ref->h != fb[3] - fb[2]) {
        fprintf(stderr, "%s: reference is %dx%d, the scene renders %dx%d\n", A->ref_path, ref->w, ref->h,
                fb[1] - fb[0], fb[3] - fb[2]);
        img_free(ref); scene_free(scene);
        return 0;
    }
    R->n = 1;
    strcpy(R->name[0], "image");
    R->rect[0][0] = 0; R->rect[0][1] = 0; R->rect[0][2] = ref->w; R->rect[0][3] = ref->h;
    n_rect = scene_insets_rendered(scene, rect, names);
    for (i = 0; i < n_rect && R->n < MAX_REGIONS; i++, R->n++) {
        snprintf(R->name[R->n], sizeof R->name[R->n], "%s", names[i]);
        memcpy(R->rect[R->n], rect[i], sizeof R->rect[R->n]);
    }
    return 1;
}

/* The exposure of the picture for docs/RESULTS.md: the power of two that brings the
   reference's mean luminance nearest to middle grey (0.18), within -8..8. */
static float converge_exposure(const Image *ref)
{
    double Y = 0.0;
    float exposure;
    size_t p, np = (size_t)ref->w * (size_t)ref->h;
    for (p = 0; p < np; p++)
        Y += 0.212671 * ref->rgb[3 * p] + 0.715160 * ref->rgb[3 * p + 1] + 0.072169 * ref->rgb[3 * p + 2];
    Y /= (double)np;
    exposure = Y > 0.0 ? (float)floor(log2(0.18 / Y) + 0.5) : 0.0f;
    if (exposure < -8.0f) exposure = -8.0f;
    if (exposure > 8.0f) exposure = 8.0f;
    return exposure;
}

static void measures_free(Measures *M)
{
    free(M->mse); free(M->relmse); free(M->mae); free(M->wall); free(M->cpu); free(M->build);
}

/* Every array zeroed; 0 when one is out of memory (free them with measures_free). */
static int measures_alloc(Measures *M)
{
    size_t n_err = (size_t)MAX_VARIANTS * MAX_SPP * MAX_SEEDS * MAX_REGIONS;
    size_t n_time = (size_t)MAX_VARIANTS * MAX_SPP * MAX_SEEDS;
    M->mse = (double *)calloc(n_err, sizeof(double));
    M->relmse = (double *)calloc(n_err, sizeof(double));
    M->mae = (double *)calloc(n_err, sizeof(double));
    M->wall = (double *)calloc(n_time, sizeof(double));
    M->cpu = (double *)calloc(n_time, sizeof(double));
    M->build = (double *)calloc(n_time, sizeof(double));
    return M->mse && M->relmse && M->mae && M->wall && M->cpu && M->build;
}

/* The renders: seeds outermost so an interrupted run has every variant.  For
   each seed every variant is one progressive render (a RenderJob) up the whole
   ladder, and the variants take turns rung by rung: variant 1 to 16 spp,
   variant 2 to 16 spp, ..., variant 1 to 32 spp, ...  Each rung's image is
   bit-identical to a separate render with that spp; taking turns puts the
   variants' passes seconds apart, so a slow spell of the machine slows them
   alike and their time ratios stay paired.  Returns 0 after a message when a
   render fails. */
static int converge_render(const ConvergeArgs *A, const Scene *scene, const Image *ref, Regions *R,
                           Measures *M, FILE *csv, const char *png_path, float exposure)
{
    int k, v, s;
    Error err;
    for (k = 0; k < A->K; k++) {
        RenderOptions o[MAX_VARIANTS];
        RenderJob *job[MAX_VARIANTS];
        Rung rung[MAX_VARIANTS];
        int failed = 0;
        for (v = 0; v < A->n_var; v++) job[v] = NULL;
        for (v = 0; v < A->n_var && !failed; v++) {
            Rung *g = &rung[v];
            if (A->base_thesis) render_options_thesis(&o[v]); else render_options_default(&o[v]);
            eval_parse_variant(A->var_names[v], &o[v]);
            o[v].seed = 1000003 * (k + 1);
            o[v].threads = A->threads;
            o[v].maxdepth = A->maxdepth >= 0 ? A->maxdepth
                            : scene->settings.maxdepth_set ? scene->settings.maxdepth : DEFAULT_MAXDEPTH;
            g->scene_path = A->scene_path; g->variant = A->var_names[v]; g->v = v; g->k = k;
            g->spp = A->spp; g->ref = ref; g->n_reg = R->n; g->reg = R->rect; g->reg_name = R->name;
            g->mse = M->mse; g->relmse = M->relmse; g->mae = M->mae;
            g->wall = M->wall; g->cpu = M->cpu; g->build = M->build;
            g->csv = csv;
            g->png = v == A->b && k == 0 ? png_path : NULL;
            g->last = A->n_spp - 1;
            g->exposure = exposure;
            job[v] = render_begin(scene, &o[v], &err);
            if (!job[v]) failed = 1;
        }
        for (s = 0; s < A->n_spp && !failed; s++)
            for (v = 0; v < A->n_var && !failed; v++) {
                if (s > 0 && !sampler_progressive(o[v].sampler)) {
                    /* a fresh render for this rung: its samples depend on the spp */
                    render_end(job[v]);
                    job[v] = render_begin(scene, &o[v], &err);
                    if (!job[v]) { failed = 1; break; }
                }
                if (!render_advance(job[v], A->spp[s], A->spp[A->n_spp - 1], &err)) failed = 1;
                else record_rung(&rung[v], s, render_image(job[v]), render_stats(job[v]));
            }
        for (v = 0; v < A->n_var; v++) render_end(job[v]);
        if (failed) { fprintf(stderr, "%s\n", err.msg); return 0; }
    }
    return 1;
}

/* The charts of the whole image: MSE against spp and against time (CPU or wall time,
   --time), band = min..max over seeds, and the efficiency 1/(MSE x time) relative to
   the baseline. */
static void converge_charts(const ConvergeArgs *A, const Measures *M)
{
    double x[MAX_VARIANTS][MAX_SPP], y[MAX_VARIANTS][MAX_SPP], lo[MAX_VARIANTS][MAX_SPP],
        hi[MAX_VARIANTS][MAX_SPP], tx[MAX_VARIANTS][MAX_SPP], eff[MAX_VARIANTS][MAX_SPP];
    const double *tb = A->use_cpu ? M->cpu : M->wall;
    SvgSeries ser[MAX_VARIANTS];
    SvgChart ch;
    char path[1024];
    int chart, v, s, k, b = A->b;
    for (v = 0; v < A->n_var; v++)
        for (s = 0; s < A->n_spp; s++) {
            double sm = 0, st = 0, mn = INFINITY, mx = 0;
            for (k = 0; k < A->K; k++) {
                double m = M->mse[RIDX(v, s, k, 0)];
                sm += m; st += tb[IDX(v, s, k)];
                if (m < mn) mn = m;
                if (m > mx) mx = m;
            }
            x[v][s] = A->spp[s];
            y[v][s] = sm / A->K;
            lo[v][s] = mn;
            hi[v][s] = mx;
            tx[v][s] = st / A->K;
        }
    for (v = 0; v < A->n_var; v++)
        for (s = 0; s < A->n_spp; s++)
            eff[v][s] = (y[b][s] * tx[b][s]) / (y[v][s] * tx[v][s]);
    for (chart = 0; chart < 3; chart++) {
        FILE *f;
        const char *suffix[3] = { "mse_spp", "mse_time", "efficiency" };
        memset(&ch, 0, sizeof ch);
        for (v = 0; v < A->n_var; v++) {
            memset(&ser[v], 0, sizeof ser[v]);
            ser[v].name = A->var_names[v];
            ser[v].n = A->n_spp;
            ser[v].x = chart == 1 ? tx[v] : x[v];
            ser[v].y = chart == 2 ? eff[v] : y[v];
            ser[v].ylo = chart == 2 ? NULL : lo[v];
            ser[v].yhi = chart == 2 ? NULL : hi[v];
            ser[v].dashed = v == b;
        }
        ch.title = chart == 0 ? "MSE against samples per pixel (band: min..max over seeds)"
                 : chart == 1 ? "MSE against render time (equal time: read across)"
                              : "efficiency 1/(MSE x time) relative to the baseline";
        ch.xlabel = chart == 1 ? (A->use_cpu ? "CPU time (s)" : "wall time (s)") : "samples per pixel";
        ch.ylabel = chart == 2 ? "relative efficiency" : "MSE (whole image)";
        ch.logx = 1;
        ch.logy = chart != 2;
        snprintf(path, sizeof path, "%s_%s.svg", A->prefix, suffix[chart]);
        f = fopen(path, "w");
        if (!f || !svg_line_chart(f, &ch, ser, A->n_var)) fprintf(stderr, "%s: cannot write\n", path);
        if (f) fclose(f);
    }
}

/* One row of region r's table: variant v's MSE and change against the baseline at
   the largest spp, its time and time ratio, and its change at equal time (the
   statistics of the head comment).  tmean: time per (variant, rung), mean over seeds. */
static void converge_table_row(FILE *md, const ConvergeArgs *A, const Measures *M,
                               double tmean[][MAX_SPP], int v, int r)
{
    const double *tb = A->use_cpu ? M->cpu : M->wall;
    double c_spp[MAX_SEEDS], c_time[MAX_SEEDS], mm[MAX_SEEDS], tt[MAX_SEEDS], tr[MAX_SEEDS];
    double tv[MAX_SPP], m1, h1, m2, h2, m0, h0, tm, th, rm, rh;
    int s, k, b = A->b, last = A->n_spp - 1;
    for (s = 0; s < A->n_spp; s++) tv[s] = tmean[v][s];
    for (k = 0; k < A->K; k++) {
        double mv[MAX_SPP];
        mm[k] = M->mse[RIDX(v, last, k, r)];
        tt[k] = tb[IDX(v, last, k)];
        tr[k] = log(tb[IDX(v, last, k)] / tb[IDX(b, last, k)]);
        c_spp[k] = M->mse[RIDX(v, last, k, r)] / M->mse[RIDX(b, last, k, r)] - 1.0;
        for (s = 0; s < A->n_spp; s++) mv[s] = M->mse[RIDX(v, s, k, r)];
        c_time[k] = log(mse_at_time(tv, mv, A->n_spp, tmean[b][last]) / M->mse[RIDX(b, last, k, r)]);
    }
    mean_ci(mm, A->K, &m0, &h0);
    mean_ci(c_spp, A->K, &m1, &h1);
    mean_ci(c_time, A->K, &m2, &h2);
    mean_ci(tt, A->K, &tm, &th);
    mean_ci(tr, A->K, &rm, &rh);
    h2 = sqrt(h2 * h2 + rh * rh);   /* sampling and timing noise, independent */
    fprintf(md, "| %s%s | %.4g | %+.1f%% [%+.1f, %+.1f] | %.2f | %+.1f%% [%+.1f, %+.1f] | %+.1f%% [%+.1f, %+.1f] |\n",
            A->var_names[v], v == b ? " (baseline)" : "", m0, 100 * m1, 100 * (m1 - h1),
            100 * (m1 + h1), tm, 100 * (exp(rm) - 1), 100 * (exp(rm - rh) - 1), 100 * (exp(rm + rh) - 1),
            100 * (exp(m2) - 1), 100 * (exp(m2 - h2) - 1), 100 * (exp(m2 + h2) - 1));
}

/* PREFIX.md: what was compared, the picture's caption, and one table per region. */
static void converge_tables(const ConvergeArgs *A, const Measures *M, const Regions *R,
                            const char *png_path, float exposure)
{
    static const char *cname[8] = { "yellow", "cyan", "magenta", "orange", "white", "green", "blue", "red" };
    const double *tb = A->use_cpu ? M->cpu : M->wall;
    double tmean[MAX_VARIANTS][MAX_SPP];   /* time per (variant, rung), mean over seeds */
    char path[1024];
    FILE *md;
    int last = A->n_spp - 1, v, s, k, r;
    snprintf(path, sizeof path, "%s.md", A->prefix);
    md = fopen(path, "w");
    for (v = 0; v < A->n_var; v++)
        for (s = 0; s < A->n_spp; s++) {
            tmean[v][s] = 0.0;
            for (k = 0; k < A->K; k++) tmean[v][s] += tb[IDX(v, s, k)] / A->K;
        }
    if (!md) { fprintf(stderr, "%s: cannot write\n", path); return; }
    fprintf(md, "Scene `%s`, reference `%s`, %d seeds, spp ladder", A->scene_path, A->ref_path, A->K);
    for (s = 0; s < A->n_spp; s++) fprintf(md, " %d", A->spp[s]);
    if (A->base_thesis) fprintf(md, "; every variant on the thesis' settings (`--base thesis`)");
    fprintf(md, "; baseline `%s`. Changes are MSE ratios minus 1 (negative = better), "
                "mean [95%% CI] over seeds. Time: %s time at %d spp, mean over seeds, and its "
                "ratio to the baseline's (per seed, geometric mean [95%% CI]). Equal time: each "
                "variant's MSE at the baseline's mean time for %d spp, along its own ladder of "
                "mean times (geometric mean over seeds; the interval adds the timing noise of the "
                "time ratio to the sampling noise).\n\n", A->var_names[A->b], A->use_cpu ? "CPU" : "wall",
            A->spp[last], A->spp[last]);
    fprintf(md, "Picture `%s`: `%s`, seed 0, %d spp, exposure %+g; insets outlined:", png_path,
            A->var_names[A->b], A->spp[last], exposure);
    for (r = 1; r < R->n; r++)
        fprintf(md, "%s %s %s", r > 1 ? "," : "", R->name[r], cname[(r - 1) % 8]);
    fprintf(md, ".\n\n");
    for (r = 0; r < R->n; r++) {
        fprintf(md, "**%s** (%d,%d)-(%d,%d)\n\n", R->name[r], R->rect[r][0], R->rect[r][1], R->rect[r][2],
                R->rect[r][3]);
        fprintf(md, "| variant | MSE at %d spp | change at %d spp | %s time (s) | time vs baseline | change at equal time |\n",
                A->spp[last], A->spp[last], A->use_cpu ? "CPU" : "wall");
        fprintf(md, "|---|---|---|---|---|---|\n");
        for (v = 0; v < A->n_var; v++) converge_table_row(md, A, M, tmean, v, r);
        fprintf(md, "\n");
    }
    fclose(md);
}

/* specnee converge: the options, the inputs, the renders (or --reuse's CSV), then
   the charts and the tables. */
int cmd_converge(int argc, char **argv)
{
    ConvergeArgs A;
    Scene scene;
    Image ref;
    Regions R;
    Measures M;
    char path[1024], png_path[1024];
    float exposure;
    FILE *csv = NULL;
    int status = converge_options(argc, argv, &A);
    if (status < 0) status = converge_ladder(&A);
    if (status >= 0) return status;
    if (!converge_inputs(&A, &scene, &ref, &R)) return 1;
    /* the picture for docs/RESULTS.md: the baseline's seed-0 render at the largest
       spp, insets outlined */
    exposure = converge_exposure(&ref);
    snprintf(png_path, sizeof png_path, "%s.png", A.prefix);
    snprintf(path, sizeof path, "%s.csv", A.prefix);
    if (!measures_alloc(&M) ||
        (A.reuse ? !read_csv(path, A.var_names, A.n_var, A.spp, A.n_spp, A.K, R.name, R.n, M.mse, M.relmse,
                             M.mae, M.wall, M.cpu, M.build)
                 : (csv = fopen(path, "w")) == NULL)) {
        if (!A.reuse) fprintf(stderr, "%s: cannot write (or out of memory)\n", path);
        measures_free(&M);
        img_free(&ref); scene_free(&scene);
        return 1;
    }
    if (csv) {
        fprintf(csv, "scene,variant,spp,seed,wall_s,cpu_s,build_s,region,mse,relmse,mae\n");
        status = converge_render(&A, &scene, &ref, &R, &M, csv, png_path, exposure);
        fclose(csv);
        if (!status) {
            measures_free(&M);
            img_free(&ref); scene_free(&scene);
            return 1;
        }
    }
    converge_charts(&A, &M);
    converge_tables(&A, &M, &R, png_path, exposure);
    measures_free(&M);
    img_free(&ref);
    scene_free(&scene);
    return 0;
}
