/* specnee.c - main: the command line, from arguments to a written image.

   The flow a student follows (docs/WALKTHROUGH.md walks through it):
       main -> parse_args -> scene_load (scene.c: parser.c, the builders, PLY, BVH)
            -> render (render.c: wavelengths, the film; path.c: the path, NEE)
            -> img_write (image.c) -> the closing line with the timings.
   Subcommands (merge, diff, spectrum, converge) are dispatched first; each lives in
   a command room of its own (cmd_image.c, cmd_spectrum.c, cmd_converge.c), apart
   from the library rooms it calls.  Exit codes: 0 success, 1 bad input, 2 bad
   usage. */
#define _POSIX_C_SOURCE 200809L
#include "specnee.h"
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char usage_text[] =
"usage: specnee [options] scene.pbrt\n"
"       specnee merge a.pfm b.pfm ... -o out.pfm [--equal-weights]\n"
"                        (sample-count weighted mean of renders)\n"
"       specnee diff test.pfm ref.pfm [--region NAME:x0,y0,x1,y1 ...]\n"
"                        [--error-image err.png] [--max-mse X] [--max-relmse Y] [--csv]\n"
"                        (MSE, relMSE, MAE; --error-image: false-colour error map;\n"
"                        --max-*: exit 1 above a threshold; --csv: one CSV line each)\n"
"       specnee spectrum NAME|FILE | --svg [--range LO HI] NAME... > out.svg | --list\n"
"       specnee spectrum --table [--spd-metric unit|power] [--svg] scene.pbrt\n"
"                        (the emitter x 60-bin table T_e(b) and P(e | bin); --svg: heat map)\n"
"       specnee converge scene.pbrt --ref ref.pfm --lights a,b:mod,... [--spp 16,32,...]\n"
"                        [--seeds K] [--time cpu|wall] [--reuse] [--out PREFIX]\n"
"                        (error against samples and time per strategy: docs/RESULTS.md)\n"
"       Each subcommand explains its options with --help (specnee diff --help, ...).\n"
"\n"
"Renders a pbrt-v4 scene (the subset in docs/conventions.md) with a spectral path\n"
"tracer: 4 hero wavelengths (HWSS) combined by spectral MIS, next event estimation\n"
"with a choice of emitter-selection strategies, Cauchy dispersion.  The estimator\n"
"is derived in docs/THEORY.md; docs/WALKTHROUGH.md follows one sample through it.\n"
"Defaults: the fastest configuration of the evaluation (sobol sampler, mixture\n"
"wavelength pdf, spectral MIS through rough glass, spectral light tree), chosen by\n"
"the best geometric mean of equal-time error over the evaluation scenes, never\n"
"significantly worse than the thesis' baseline (docs/RESULTS.md, What to use);\n"
"--preset thesis renders that baseline.\n"
"\n";

static const char usage_options[] =
"options (a command-line value overrides the scene file's):\n"
"  -o, --out FILE          output image: .pfm (linear float), .ppm or .png (8-bit sRGB);\n"
"                          .exr (only) for Film \"spectral\"; its directory must exist;\n"
"                          it overrides the scene's Film \"string filename\", as\n"
"                          pbrt-v4 --outfile does\n"
"      --spp N             samples per pixel (file: Sampler pixelsamples; default 16)\n"
"      --seed N            random seed (file: Sampler seed; default 0)\n"
"      --sampler NAME      independent, stratified, sobol, zsobol or halton\n"
"                          (file: Sampler; default sobol; docs/sampling.md)\n"
"      --threads N         worker threads (default: all cores; image is identical)\n"
"      --maxdepth N        path vertices that scatter (file: Integrator maxdepth; 5)\n"
"      --res WxH           film resolution (file: Film x/yresolution)\n"
"      --lights NAME       emitter selection for NEE (file: Integrator lightsampler;\n"
"                          pbrt-v4's \"bvh\" maps to tree; default spectral-tree):\n"
"                          spectral-tree  light tree with per-bin spectral power:\n"
"                                         the choice for many emitters (O(log n))\n"
"                          tree           the same tree with total power (pbrt-v4)\n"
"                          spatial product spectral-spatial  the thesis' voxel\n"
"                                         tables: few emitters (each vertex O(n))\n"
"                          uniform power spd all  baselines (docs/lighttree.md)\n"
"      --light-shape-sampling M  a triangle lamp's point for NEE: auto (by solid\n"
"                          angle where the area estimate would vary over the\n"
"                          triangle by more than 3x, else by area; default),\n"
"                          solidangle (by the solid angle it subtends, the cosine\n"
"                          warped in, where that lies in [3e-4, 6.22] sr: pbrt-v4's\n"
"                          rule) or area (uniform on the triangle)\n"
"      --spd-metric M      what the spectral table T_e(b) holds: unit (the bin average\n"
"                          of the emitted radiance Le, default) or power (that x area);\n"
"                          read by spd, product and spectral-spatial only (the trees\n"
"                          weigh power per bin always)\n"
"      --all-wavelengths   spectral strategies weigh every alive wavelength\n"
"      --throughput-weighted  ... each by the path throughput at that wavelength\n"
"      --spd-wavelengths W hero (the thesis, default), all or throughput: the same\n"
"                          as the two flags above, and the way to switch them off;\n"
"                          read by spd, product and spectral-spatial; spectral-tree\n"
"                          always sums the alive wavelengths, so only throughput acts\n"
"      --wavelengths P     the wavelength pdf: mixture (default: importance with a\n"
"                          share of visible that bounds its worst case), uniform\n"
"                          (plain HWSS, the thesis), importance (~ (xbar+ybar+zbar)\n"
"                          x the emitters' spectra) or visible (scene-independent\n"
"                          sech^2 around 538 nm, as pbrt-v4): docs/wavelengths.md\n"
"      --mix-weight M      visible's share in the mixture, 0 < M <= 1 (default 0.5)\n"
"      --wide              sample 360-830 nm (pbrt-v4's range) instead of 400-700\n"
"      --single-wavelength one wavelength per path instead of four\n"
"      --rough-dispersion M  mis (default: keep the secondary wavelengths alive\n"
"                          through rough dispersive glass) or terminate (the thesis)\n"
"      --no-nee            BSDF sampling only (no next event estimation)\n"
"      --chromatic-media M mis (default: spectral MIS keeps the four wavelengths\n"
"                          through media whose sigma_t depends on the wavelength)\n"
"                          or terminate (the secondaries end there): docs/media.md\n"
;
static const char usage_options2[] =
"      --equiangular M     off (default), on (in a homogeneous medium, NEE also from\n"
"                          a distance sampled towards a point, spot or sphere lamp,\n"
"                          MIS-weighted against free flight) or N (on, only on the\n"
"                          first N bounces' segments): docs/media.md\n"
"      --fluor-li M        a fluorescent vertex samples the absorbed wavelength from\n"
"                          A x the emitters' power with a share of A (power,\n"
"                          default), from its excitation A (a), or uniformly on\n"
"                          [300 nm, emitted wavelength] (uniform): docs/FLUORESCENCE.md\n"
"      --fluor-lanes M     at a fluorescent shift, keep all four wavelengths, each\n"
"                          shifted with its own excitation wavelength (keep, default),\n"
"                          or terminate the secondary ones (terminate)\n"
"      --exposure E        multiply by 2^E before writing .ppm/.png\n"
"      --mark-insets       outline the scene's insets (\"# inset\" comments) in the\n"
"                          .png: A yellow, B cyan, C magenta, ...\n"
"      --debug-pixel X,Y   print every path of pixel (X, Y) to stderr: X counts from\n"
"                          the left, Y from the top, both from 0, on the film after\n"
"                          --res (a picture viewer's coordinates)\n"
"      --eager-tables      build every voxel of the spatial tables before rendering\n"
"                          (default: each voxel on first use; the image is the same)\n"
"      --dump-scene        print the scene as understood, then exit\n"
"      --print-defaults    print the render settings, one \"name value\" a line, then\n"
"                          exit: the defaults, or those the other flags give; with\n"
"                          a scene, those its render uses (its Film, Sampler and\n"
"                          Integrator under the flags)\n"
"      --preset NAME       a named list of flags, expanded where it stands (later\n"
"                          flags override it); the presets are listed below\n"
"  -q, --quiet             no progress bar and no closing line\n"
"  -h, --help              this text\n";
/* (split in parts: C99 compilers need to support string literals of 4095 chars only) */
static const char usage_notes[] =
"\n"
"Output: .pfm rows run bottom to top (netpbm), linear sRGB (D65), with a sidecar\n"
"FILE.txt holding the sample count for `specnee merge`.  The closing line gives the\n"
"wall and CPU time and the time spent building emitter tables (\"tables\"), also\n"
"those built lazily during the render.\n"
"Exit status: 0 ok, 1 bad input (a message file:line: problem), 2 bad usage.\n";

/* Presets: a name for a list of flags, nothing more.  `--preset NAME` is parsed as
   if its flags stood at its place on the command line, so a preset renders
   bit-identically to its flags spelled out, and a later flag overrides it.  Each
   preset pins every setting whose default may change (wavelength pdf, emitter
   selection and its variants, rough dispersion, sampler, fluorescence: the thesis
   has none, and a shift terminates the secondaries there as dispersion does), so that it keeps
   meaning the same method when the defaults move.  The sampler is independent
   random numbers, the one specnee reproduced the thesis' figures with (the
   thesis itself rendered with pbrt-v3's default sampler, "halton", which a scene
   file's Sampler maps to specnee's sobol: docs/sampling.md). */
typedef struct {
    const char *name, *what;
    const char *const *flags;  /* NULL-terminated */
} Preset;
static const char *const preset_thesis[] = {
    "--wavelengths", "uniform", "--lights", "spatial", "--spd-metric", "unit",
    "--spd-wavelengths", "hero", "--rough-dispersion", "terminate",
    "--sampler", "independent", "--fluor-lanes", "terminate", "--fluor-li", "a",
    "--light-shape-sampling", "area", NULL };
static const char *const preset_thesis_spd[] = {
    "--wavelengths", "uniform", "--lights", "product", "--spd-metric", "unit",
    "--spd-wavelengths", "hero", "--rough-dispersion", "terminate",
    "--sampler", "independent", "--fluor-lanes", "terminate", "--fluor-li", "a",
    "--light-shape-sampling", "area", NULL };
static const Preset presets[] = {
    { "thesis", "the thesis' baseline: HWSS with uniform wavelengths, pbrt-v3's spatial\n"
                "          selection, termination at dispersive glass", preset_thesis },
    { "thesis-spd", "the thesis' method: spatial x emitted spectrum at the hero wavelength\n"
                    "          (product, unit metric), uniform wavelengths", preset_thesis_spd },
    { NULL, NULL, NULL }
};

static void print_help(void)
{
    int p, k;
    fputs(usage_text, stdout);
    fputs(usage_options, stdout);
    fputs(usage_options2, stdout);
    fputs(usage_notes, stdout);
    fputs("\npresets (--preset NAME is the same as its flags at that place):\n", stdout);
    for (p = 0; presets[p].name; p++) {
        printf("  %-11s", presets[p].name);
        for (k = 0; presets[p].flags[k]; k++) printf(" %s", presets[p].flags[k]);
        printf("\n          = %s\n", presets[p].what);
    }
}

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "specnee: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(see specnee --help)\n");
    return 2;
}

/* Strict integer parsing: the whole string, within [lo, hi]. */
static int parse_int(const char *s, long lo, long hi, int *out)
{
    char *end;
    long v;
    if (!s || !*s) return 0;
    v = strtol(s, &end, 10);
    if (*end || v < lo || v > hi) return 0;
    *out = (int)v;
    return 1;
}

static int parse_float(const char *s, float *out)
{
    char *end;
    double v;
    if (!s || !*s) return 0;
    v = strtod(s, &end);
    if (*end || !isfinite(v)) return 0;
    *out = (float)v;
    return 1;
}

typedef struct {
    RenderOptions ro;
    const char *scene, *out;
    int spp_cli, seed_cli, maxdepth_cli, lights_cli, sampler_cli;
    float exposure;
    int dump, quiet, mark_insets;
    int print_defaults;        /* --print-defaults: print the settings, then exit */
    int res_w, res_h;          /* --res: override the film resolution (0: the file's) */
} Args;

/* The options that name one of a few choices (a method or a mode): sets a from
   "o v" and returns 0, or returns usage_error's code for a missing value or one
   that is not among the choices; -1 when o is not such an option. */
static int parse_choice(const char *o, const char *v, Args *a)
{
    static const char *const names[] = { "--light-shape-sampling", "--spd-metric", "--spd-wavelengths",
                                         "--fluor-li", "--fluor-lanes", "--chromatic-media",
                                         "--equiangular", "--rough-dispersion", NULL };
    int k, n;
    for (k = 0; names[k] && strcmp(o, names[k]); k++) {}
    if (!names[k]) return -1;
    if (!v) return usage_error("option %s needs a value", o);
    switch (k) {
    case 0:
        if (!strcmp(v, "solidangle")) a->ro.sel.area_sampling = SHAPE_SA;
        else if (!strcmp(v, "area")) a->ro.sel.area_sampling = SHAPE_AREA;
        else if (!strcmp(v, "auto")) a->ro.sel.area_sampling = SHAPE_AUTO;
        else return usage_error("--light-shape-sampling is auto, solidangle or area, not '%s'", v);
        break;
    case 1:
        if (!strcmp(v, "unit")) a->ro.sel.power_metric = 0;
        else if (!strcmp(v, "power")) a->ro.sel.power_metric = 1;
        else return usage_error("--spd-metric is unit or power, not '%s'", v);
        break;
    case 2:
        if (!strcmp(v, "hero")) a->ro.sel.all_wavelengths = a->ro.sel.throughput_weighted = 0;
        else if (!strcmp(v, "all")) { a->ro.sel.all_wavelengths = 1; a->ro.sel.throughput_weighted = 0; }
        else if (!strcmp(v, "throughput")) a->ro.sel.all_wavelengths = a->ro.sel.throughput_weighted = 1;
        else return usage_error("--spd-wavelengths is hero, all or throughput, not '%s'", v);
        break;
    case 3:
        if (!strcmp(v, "a")) a->ro.fluor_li = FLUOR_LI_A;
        else if (!strcmp(v, "power")) a->ro.fluor_li = FLUOR_LI_POWER;
        else if (!strcmp(v, "uniform")) a->ro.fluor_li = FLUOR_LI_UNIFORM;
        else return usage_error("--fluor-li is a, power or uniform, not '%s'", v);
        break;
    case 4:
        if (!strcmp(v, "terminate")) a->ro.fluor_keep = 0;
        else if (!strcmp(v, "keep")) a->ro.fluor_keep = 1;
        else return usage_error("--fluor-lanes is terminate or keep, not '%s'", v);
        break;
    case 5:
        if (!strcmp(v, "mis")) a->ro.media_terminate = 0;
        else if (!strcmp(v, "terminate")) a->ro.media_terminate = 1;
        else return usage_error("--chromatic-media is mis or terminate, not '%s'", v);
        break;
    case 6:   /* on, off, or N > 0: only the first N bounces' segments */
        if (!strcmp(v, "on")) { a->ro.equiangular = 1; a->ro.equi_depth = 0; }
        else if (!strcmp(v, "off")) a->ro.equiangular = 0;
        else if (parse_int(v, 1, 1000, &n)) { a->ro.equiangular = 1; a->ro.equi_depth = n; }
        else return usage_error("--equiangular is on, off or a number of bounces 1..1000, not '%s'", v);
        break;
    default:
        if (!strcmp(v, "mis")) a->ro.rough_mis = 1;
        else if (!strcmp(v, "terminate")) a->ro.rough_mis = 0;
        else return usage_error("--rough-dispersion is mis or terminate, not '%s'", v);
        break;
    }
    return 0;
}

/* Parse argv[0 .. argc) into a; in_preset: the flags of a preset (no scene file,
   no nested preset there).  Returns 0 on success, else the exit code. */
static int parse_flags(int argc, const char *const *argv, Args *a, int in_preset)
{
    int i, rc;
    for (i = 0; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEEDS_VALUE() do { if (!v) return usage_error("option %s needs a value", o); i++; } while (0)
        if (!strcmp(o, "-h") || !strcmp(o, "--help")) {
            print_help();
            exit(0);
        } else if (!strcmp(o, "--preset") && !in_preset) {
            int p, n;
            NEEDS_VALUE();
            for (p = 0; presets[p].name && strcmp(presets[p].name, v); p++) {}
            if (!presets[p].name) return usage_error("unknown --preset '%s' (see specnee --help)", v);
            for (n = 0; presets[p].flags[n]; n++) {}
            if ((rc = parse_flags(n, presets[p].flags, a, 1)) != 0) return rc;
        } else if (!strcmp(o, "-o") || !strcmp(o, "--out")) {
            NEEDS_VALUE(); a->out = v;
        } else if (!strcmp(o, "--spp")) {
            NEEDS_VALUE();
            if (!parse_int(v, 1, 1L << 30, &a->ro.spp)) return usage_error("--spp needs a positive integer, not '%s'", v);
            a->spp_cli = 1;
        } else if (!strcmp(o, "--seed")) {
            NEEDS_VALUE();
            if (!parse_int(v, -2147483647L, 2147483647L, &a->ro.seed)) return usage_error("--seed needs an integer, not '%s'", v);
            a->seed_cli = 1;
        } else if (!strcmp(o, "--sampler")) {
            NEEDS_VALUE();
            a->ro.sampler = sampler_from_name(v);
            if (a->ro.sampler == SAMPLER_COUNT)
                return usage_error("--sampler is independent, stratified, sobol, zsobol or halton, not '%s'", v);
            a->sampler_cli = 1;
        } else if (!strcmp(o, "--threads")) {
            NEEDS_VALUE();
            if (!parse_int(v, 1, 4096, &a->ro.threads)) return usage_error("--threads needs a positive integer, not '%s'", v);
        } else if (!strcmp(o, "--maxdepth")) {
            NEEDS_VALUE();
            if (!parse_int(v, 0, 1000, &a->ro.maxdepth)) return usage_error("--maxdepth needs an integer 0..1000, not '%s'", v);
            a->maxdepth_cli = 1;
        } else if (!strcmp(o, "--lights")) {
            NEEDS_VALUE();
            a->ro.sel.strategy = sel_from_name(v);
            if (a->ro.sel.strategy == SEL_COUNT) return usage_error("unknown --lights strategy '%s'", v);
            a->lights_cli = 1;
        } else if ((rc = parse_choice(o, v, a)) >= 0) {   /* a method or a mode */
            if (rc) return rc;
            i++;
        } else if (!strcmp(o, "--all-wavelengths")) {
            a->ro.sel.all_wavelengths = 1;
        } else if (!strcmp(o, "--throughput-weighted")) {
            a->ro.sel.all_wavelengths = 1;
            a->ro.sel.throughput_weighted = 1;
        } else if (!strcmp(o, "--wavelengths")) {
            NEEDS_VALUE();
            a->ro.wl_mode = wl_mode_from_name(v);
            if (a->ro.wl_mode == WL_MODE_COUNT)
                return usage_error("--wavelengths is uniform, importance, visible or mixture, not '%s'", v);
        } else if (!strcmp(o, "--mix-weight")) {
            NEEDS_VALUE();
            if (!parse_float(v, &a->ro.wl_mix) || !(a->ro.wl_mix > 0.0f && a->ro.wl_mix <= 1.0f))
                return usage_error("--mix-weight needs a number in (0, 1], not '%s'", v);
        } else if (!strcmp(o, "--wide")) {
            a->ro.wl_wide = 1;
        } else if (!strcmp(o, "--single-wavelength")) {
            a->ro.single_wavelength = 1;
        } else if (!strcmp(o, "--no-nee")) {
            a->ro.nee = 0;
        } else if (!strcmp(o, "--mark-insets")) {
            a->mark_insets = 1;
        } else if (!strcmp(o, "--exposure")) {
            NEEDS_VALUE();
            if (!parse_float(v, &a->exposure)) return usage_error("--exposure needs a number, not '%s'", v);
        } else if (!strcmp(o, "--debug-pixel")) {
            char *end;
            NEEDS_VALUE();
            a->ro.debug_x = (int)strtol(v, &end, 10);
            if (*end != ',' || a->ro.debug_x < 0) return usage_error("--debug-pixel needs X,Y, not '%s'", v);
            a->ro.debug_y = (int)strtol(end + 1, &end, 10);
            if (*end || a->ro.debug_y < 0) return usage_error("--debug-pixel needs X,Y, not '%s'", v);
        } else if (!strcmp(o, "--res")) {
            char *end;
            long w, h;
            NEEDS_VALUE();
            w = strtol(v, &end, 10);
            if (*end != 'x' || w < 1 || w > 16384) return usage_error("--res needs WxH (1..16384), not '%s'", v);
            h = strtol(end + 1, &end, 10);
            if (*end || h < 1 || h > 16384) return usage_error("--res needs WxH (1..16384), not '%s'", v);
            if ((double)w * h * FILM_BYTES_PER_PIXEL > (double)MEM_BUDGET_MIB * 1048576.0)
                return usage_error("--res %s: the render's buffers would exceed the memory "
                                   "budget (MEM_BUDGET_MIB in specnee.h)", v);
            a->res_w = (int)w;
            a->res_h = (int)h;
        } else if (!strcmp(o, "--eager-tables")) {
            a->ro.sel.eager = 1;
        } else if (!strcmp(o, "--dump-scene")) {
            a->dump = 1;
        } else if (!strcmp(o, "--print-defaults")) {
            a->print_defaults = 1;
        } else if (!strcmp(o, "-q") || !strcmp(o, "--quiet")) {
            a->quiet = 1;
        } else if (o[0] == '-' && o[1]) {
            return usage_error("unknown option '%s'", o);
        } else if (!a->scene && !in_preset) {
            a->scene = o;
        } else {
            return usage_error("more than one scene file given ('%s')", o);
        }
#undef NEEDS_VALUE
    }
    return 0;
}

/* --print-defaults: the render settings, one "name value" line each, from the
   RenderOptions the command line gave (render_options_default when no flag
   precedes it, so the binary itself says what it does by default: the docs' test
   tests/docs_defaults.sh compares every "(default)" in docs/ with these lines).
   Each name is an option; an option that takes a value prints that value (so
   "--NAME VALUE" sets it), a switch prints on or off.  With a scene (s not NULL)
   the settings are those the render of that scene uses: its Film, Sampler and
   Integrator as apply_scene_settings applies them, under the command line's
   flags, and the film's resolution.
   spd-metric and spd-wavelengths say after a '#' which --lights strategies read
   them (sel_reads_metric, sel_reads_wavelengths): the thesis' spectral tables
   (spd, product, spectral-spatial) read both; the light trees use power per bin
   and sum over the alive wavelengths always (THEORY §5.4), so the metric
   and "hero"/"all" leave them as they are, and spectral-tree reads "throughput"
   only. */
static int sel_reads_metric(SelStrategy st)
{
    return st == SEL_SPD || st == SEL_PRODUCT || st == SEL_SPECTRAL_SPATIAL;
}

static void print_settings(const RenderOptions *o, const Scene *s)
{
    SelStrategy st = o->sel.strategy;
    printf("spp %d\nseed %d\nmaxdepth %d\nsampler %s\n", o->spp, o->seed, o->maxdepth,
           sampler_name(o->sampler));
    if (s) printf("res %dx%d\n", s->settings.xres, s->settings.yres);
    printf("wavelengths %s\nmix-weight %g\nwide %s\nsingle-wavelength %s\n", wl_mode_name(o->wl_mode),
           (double)(o->wl_mix > 0.0f ? o->wl_mix : WL_MIX_DEFAULT), o->wl_wide ? "on" : "off",
           o->single_wavelength ? "on" : "off");
    printf("lights %s\n", sel_name(st));
    printf("light-shape-sampling %s\n", o->sel.area_sampling == SHAPE_AREA ? "area" :
           o->sel.area_sampling == SHAPE_AUTO ? "auto" : "solidangle");
    printf("spd-metric %s  # read by --lights spd, product, spectral-spatial%s%s\n",
           o->sel.power_metric ? "power" : "unit", sel_reads_metric(st) ? "" : "; ignored by ",
           sel_reads_metric(st) ? "" : sel_name(st));
    printf("spd-wavelengths %s  # read by --lights spd, product, spectral-spatial; spectral-tree "
           "reads throughput only (it always sums over the alive wavelengths)%s%s\n",
           o->sel.throughput_weighted ? "throughput" : o->sel.all_wavelengths ? "all" : "hero",
           sel_reads_metric(st) || st == SEL_SPECTRAL_TREE ? "" : "; ignored by ",
           sel_reads_metric(st) || st == SEL_SPECTRAL_TREE ? "" : sel_name(st));
    printf("rough-dispersion %s\nno-nee %s\n", o->rough_mis ? "mis" : "terminate", o->nee ? "off" : "on");
    printf("chromatic-media %s\n", o->media_terminate ? "terminate" : "mis");
    if (o->equiangular && o->equi_depth > 0) printf("equiangular %d\n", o->equi_depth);
    else printf("equiangular %s\n", o->equiangular ? "on" : "off");
    printf("fluor-li %s\nfluor-lanes %s\n",
           o->fluor_li == FLUOR_LI_A ? "a" : o->fluor_li == FLUOR_LI_POWER ? "power" : "uniform",
           o->fluor_keep ? "keep" : "terminate");
}

/* The output is checked before any sample is traced, so that a render cannot run
   for minutes and then fail to write: a known extension (img_format_check, the
   same message img_write would give), an existing directory (specnee does not
   create directories), and a file there that can be opened for writing.
   exr: an .exr is allowed (the spectral film's; its scene's Film checks the name).
   Returns 0, or 1 after a one-line message naming the path. */
static int check_output(const char *out, int exr)
{
    Error err;
    struct stat sb;
    FILE *f;
    int existed;
    char dir[1024];
    const char *slash = strrchr(out, '/');
    size_t n = slash ? (size_t)(slash - out) : 0, len = strlen(out);
    err.msg[0] = '\0';
    if (!(exr && len > 4 && out[len - 4] == '.' && (out[len - 3] | 32) == 'e' &&
          (out[len - 2] | 32) == 'x' && (out[len - 1] | 32) == 'r') && !img_format_check(out, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    if (!slash) strcpy(dir, ".");
    else if (n >= sizeof dir) {
        fprintf(stderr, "%s: cannot write: the path is too long\n", out);
        return 1;
    } else {
        if (n == 0) n = 1;                         /* "/x.png": the root */
        memcpy(dir, out, n);
        dir[n] = '\0';
    }
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
        fprintf(stderr, "%s: cannot write: the directory %s does not exist "
                        "(specnee does not create directories)\n", out, dir);
        return 1;
    }
    if (stat(out, &sb) == 0 && S_ISDIR(sb.st_mode)) {
        fprintf(stderr, "%s: cannot write: it is a directory\n", out);
        return 1;
    }
    /* the one test that also holds for root and read-only file systems: open the
       file to append (which changes nothing), and remove it again if it is new */
    existed = stat(out, &sb) == 0;
    errno = 0;
    if (!(f = fopen(out, "ab"))) {
        fprintf(stderr, "%s: cannot write: %s\n", out, errno ? strerror(errno) : "I/O error");
        return 1;
    }
    fclose(f);
    if (!existed) remove(out);
    return 0;
}

/* Returns 0 on success, else the exit code. */
static int parse_args(int argc, char **argv, Args *a)
{
    int rc;
    memset(a, 0, sizeof *a);
    render_options_default(&a->ro);
    if ((rc = parse_flags(argc - 1, (const char *const *)(argv + 1), a, 0)) != 0) return rc;
    if (a->print_defaults && !a->scene) {
        print_settings(&a->ro, NULL);
        exit(0);
    }
    if (!a->scene) return usage_error("%s", "no scene file given");
    return 0;
}

/* The scene's own settings, unless the command line overrides them. */
static int apply_scene_settings(Args *a, Scene *s)
{
    const SceneSettings *st = &s->settings;
    if (!a->spp_cli && st->spp_set) a->ro.spp = st->spp;
    if (!a->seed_cli && st->seed_set) a->ro.seed = st->seed;
    if (!a->maxdepth_cli && st->maxdepth_set) a->ro.maxdepth = st->maxdepth;
    if (!a->sampler_cli && st->sampler[0]) {
        a->ro.sampler = sampler_from_name(st->sampler);   /* scene.c wrote a known name */
        a->ro.xsamples = st->xsamples;
        a->ro.ysamples = st->ysamples;
        a->ro.jitter = st->jitter;
    }
    if (a->res_w > 0) {
        /* a smaller film keeps the field of view (pbrt: fov spans the shorter axis) */
        s->settings.xres = a->res_w;
        s->settings.yres = a->res_h;
    }
    if (!a->lights_cli && st->lightsampler[0]) {
        if (!strcmp(st->lightsampler, "bvh")) {
            a->ro.sel.strategy = SEL_TREE;     /* pbrt-v4's BVHLightSampler */
        } else {
            a->ro.sel.strategy = sel_from_name(st->lightsampler);
            if (a->ro.sel.strategy == SEL_COUNT) {
                fprintf(stderr, "%s: Integrator \"string lightsampler\" \"%s\" is unknown\n",
                        a->scene, st->lightsampler);
                return 1;
            }
        }
    }
    return 0;
}

/* pbrt-v4's Film "spectral": the render with its buckets, written as OpenEXR
   (image.c); frees the scene.  Returns the exit code. */
static int render_spectral_main(const Args *a, Scene *scene, const char *out)
{
    Image img;
    RenderStats st;
    Error err;
    RenderOptions d;
    float *buckets = NULL;
    int ok;
    err.msg[0] = '\0';
    render_options_default(&d);
    if (a->ro.wl_mode != d.wl_mode || a->ro.wl_mix != d.wl_mix || a->ro.wl_wide)
        fprintf(stderr, "%s: note: Film \"spectral\" samples its wavelengths uniformly in "
                "%g-%g nm (pbrt-v4): --wavelengths, --mix-weight and --wide do not apply\n",
                a->scene, scene->settings.lambda_min, scene->settings.lambda_max);
    ok = render_spectral(scene, &a->ro, &img, &buckets, &st, &err) &&
         img_write_spectral(&img, buckets, &scene->settings, out, &err);
    if (!ok) fprintf(stderr, "%s\n", err.msg);
    else if (!a->quiet)
        fprintf(stderr, "specnee: %s: %dx%d, %d spp, %d buckets over %g-%g nm (wavelengths "
                "uniform), in %.3f s wall%s\n", out, img.w, img.h, a->ro.spp, scene->settings.nbuckets,
                scene->settings.lambda_min, scene->settings.lambda_max, st.wall_s,
                st.nonfinite ? " (WARNING: non-finite samples dropped)" : "");
    free(buckets);
    img_free(&img);
    scene_free(scene);
    return ok ? 0 : 1;
}

static int render_main(int argc, char **argv)
{
    Args a;
    Scene scene;
    Image img;
    RenderStats st;
    Error err;
    const char *out;
    int rc = parse_args(argc, argv, &a), i, glow = 0;
    char settings[512], wl_text[32];
    if (rc) return rc;
    if (a.out && !a.dump && !a.print_defaults && check_output(a.out, 1)) return 1;
    memset(&scene, 0, sizeof scene);
    err.msg[0] = '\0';
    if (!scene_load_as(&scene, a.scene, a.out, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    if (a.dump) {
        scene_dump(&scene, stdout);
        scene_free(&scene);
        return 0;
    }
    if (apply_scene_settings(&a, &scene)) { scene_free(&scene); return 1; }
    if (a.print_defaults) {
        print_settings(&a.ro, &scene);
        scene_free(&scene);
        return 0;
    }
    if (a.ro.debug_x >= 0 && (a.ro.debug_x >= scene.settings.xres || a.ro.debug_y >= scene.settings.yres)) {
        fprintf(stderr, "specnee: --debug-pixel %d,%d is outside the %dx%d film (X 0..%d from the left, "
                        "Y 0..%d from the top)\n(see specnee --help)\n", a.ro.debug_x, a.ro.debug_y,
                scene.settings.xres, scene.settings.yres, scene.settings.xres - 1, scene.settings.yres - 1);
        scene_free(&scene);
        return 2;
    }
    for (i = 0; i < scene.n_media && !glow; i++) glow = scene.media[i].Le_scale > 0.0f;
    if (scene.n_emitters == 0 && !glow)
        /* pbrt-v4 warns and renders; so does specnee (exit 0, docs/conventions.md 1);
           an emissive medium is a light of its own */
        fprintf(stderr, "%s: warning: no light sources (AreaLightSource or LightSource) in the "
                        "scene: the image is black\n", a.scene);
    a.ro.progress = !a.quiet && isatty(fileno(stderr));
    out = a.out ? a.out : scene.settings.filename;
    if (a.mark_insets && (strlen(out) < 4 || strcmp(out + strlen(out) - 4, ".png") || a.res_w > 0)) {
        fprintf(stderr, "specnee: --mark-insets needs a .png output at the file's own resolution (no --res)\n");
        scene_free(&scene);
        return 2;
    }
    if (check_output(out, scene.settings.spectral)) {
        scene_free(&scene);
        return 1;
    }
    if (scene.settings.spectral) return render_spectral_main(&a, &scene, out);
    if (!render(&scene, &a.ro, &img, &st, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        scene_free(&scene);
        return 1;
    }
    if (a.mark_insets) {
        int rect[8][4], n_rect;
        const char *names[8];
        n_rect = scene_insets_rendered(&scene, rect, names);
        if (!png_write_marked(&img, out, a.exposure, &rect[0][0], n_rect)) {
            fprintf(stderr, "%s: cannot write\n", out);
            img_free(&img);
            scene_free(&scene);
            return 1;
        }
    } else if (!img_write(&img, out, a.exposure, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        img_free(&img);
        scene_free(&scene);
        return 1;
    }
    if (a.ro.wl_mode == WL_MIXTURE)
        snprintf(wl_text, sizeof wl_text, "mixture:%g", (double)(a.ro.wl_mix > 0.0f ? a.ro.wl_mix : WL_MIX_DEFAULT));
    else
        snprintf(wl_text, sizeof wl_text, "%s", wl_mode_name(a.ro.wl_mode));
    snprintf(settings, sizeof settings,
             "scene=%s seed=%d sampler=%s maxdepth=%d lights=%s spd-metric=%s all-wavelengths=%d "
             "wavelengths=%s range=%s single=%d rough-dispersion=%s nee=%d fluor-lanes=%s fluor-li=%s "
             "chromatic-media=%s",
             a.scene, a.ro.seed, sampler_name(a.ro.sampler), a.ro.maxdepth, sel_name(a.ro.sel.strategy),
             a.ro.sel.power_metric ? "power" : "unit", a.ro.sel.all_wavelengths,
             wl_text, a.ro.wl_wide ? "360-830" : "400-700",
             a.ro.single_wavelength, a.ro.rough_mis ? "mis" : "terminate", a.ro.nee,
             a.ro.fluor_keep ? "keep" : "terminate",
             a.ro.fluor_li == FLUOR_LI_A ? "a" : a.ro.fluor_li == FLUOR_LI_POWER ? "power" : "uniform",
             a.ro.media_terminate ? "terminate" : "mis");
    {
        /* the sample count travels with float images, for `specnee merge` */
        size_t len = strlen(out);
        if (len > 4 && (!strcmp(out + len - 4, ".pfm") || !strcmp(out + len - 4, ".PFM")))
            img_write_sidecar(out, a.ro.spp, settings);
    }
    if (!a.quiet)
        fprintf(stderr, "specnee: %s: %dx%d, %d spp, %s, in %.3f s wall (%.3f s CPU, tables %.1f ms%s): "
                        "%.0f samples/s, %.2f Mrays/s%s%s%s\n",
                out, img.w, img.h, a.ro.spp, sel_name(a.ro.sel.strategy), st.wall_s, st.cpu_s,
                1e3 * (st.build_s + st.lazy_s), st.lazy_s > 0.0 ? ", built lazily during the render" : "", (double)st.samples / st.wall_s, (double)st.rays / st.wall_s * 1e-6,
                st.nonfinite ? " (WARNING: non-finite samples dropped)" : "",
                st.dims_reused ? " (WARNING: a sampler dimension was used twice)" : "",
                st.fallbacks ? " (some vertices fell back to spatial: no emitter in the hero's bin)" : "");
    img_free(&img);
    scene_free(&scene);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        if (!strcmp(argv[1], "merge")) return cmd_merge(argc - 1, argv + 1);
        if (!strcmp(argv[1], "diff")) return cmd_diff(argc - 1, argv + 1);
        if (!strcmp(argv[1], "spectrum")) return cmd_spectrum(argc - 1, argv + 1);
        if (!strcmp(argv[1], "converge")) return cmd_converge(argc - 1, argv + 1);
    }
    return render_main(argc, argv);
}
