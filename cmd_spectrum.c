/* cmd_spectrum.c - `specnee spectrum`: print, plot and tabulate spectra.

   WHAT IT IMPLEMENTS
     specnee spectrum NAME|FILE   the spectrum as a pbrt .spd table at 1 nm steps,
                                  then its chromaticity xy, CCT and Duv, luminance,
                                  thesis eq. 6 bin sum and the pbrt "float scale"
                                  that normalises it to thesis eq. 6 with c = 1;
     --svg NAME|FILE ...          a line chart of emission spectra (each divided by
                                  its maximum) or of refractive indices (svg.c);
     --table scene.pbrt           the scene's emitter x 60-bin table T_e(b) and
                                  P(e | b) = T_e(b) / sum_k T_k(b) of the spectral
                                  strategies (THEORY §5), as text or a heat map;
     --list                       the built-in names.
   Exit codes: 0 ok, 1 bad input, 2 bad usage.

   HOW IT IS USED
     specnee.c dispatches `specnee spectrum ...` to cmd_spectrum (specnee.h section
     14).  A command room: it loads scenes (--table) and parses its own command
     line; the spectra themselves come from spectrum.c and the emitters' radiance
     from lights.c. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

static const char spectrum_usage[] =
    "usage: specnee spectrum NAME|FILE\n"
    "       specnee spectrum --svg [--range LO HI] NAME|FILE ... > plot.svg\n"
    "       specnee spectrum --table [--spd-metric unit|power] [--svg] scene.pbrt\n"
    "       specnee spectrum --list\n"
    "Prints the spectrum as a pbrt .spd table at 1 nm steps (360-830 nm) followed by\n"
    "'#' lines with its chromaticity xy, CCT, Duv, luminance, thesis eq. 6 bin sum and\n"
    "the pbrt \"float scale\" that normalises it to thesis eq. 6 with c = 1.  --svg plots one\n"
    "or more emission spectra, each divided by its maximum, or refractive indices\n"
    "(glass-*) as they are; --list prints the built-in names.\n"
    "--table prints the scene's emitter x 60-bin table of the spectral strategies\n"
    "(thesis Sec. 2; docs/THEORY.md): T_e(b), the bin average of emitter e's radiance\n"
    "Le over bin b (x area x sides with --spd-metric power), and P(e | b) =\n"
    "T_e(b) / sum_k T_k(b), the probability that `--lights spd` chooses e for a hero in\n"
    "bin b; with --svg, the same as a heat map.\n";

/* A built-in name, else a file.  Prints a one-line message and returns 0 on failure. */
static int spectrum_arg(const char *arg, Spectrum *s)
{
    Error err;
    FILE *probe;
    if (spec_named(s, arg)) return 1;
    probe = fopen(arg, "rb");
    if (!probe) {
        fprintf(stderr, "specnee spectrum: '%s' is neither a built-in spectrum (see --list) "
                "nor a readable file\n", arg);
        return 0;
    }
    fclose(probe);
    err.msg[0] = '\0';
    if (!spec_from_file(s, arg, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 0;
    }
    return 1;
}

static int spectrum_print(const char *arg, const Spectrum *s)
{
    double x, y, cct = 0.0, duv = 0.0, lum, binsum, ysum_specnee, ysum_pbrt, xyz[3];
    int i;
    printf("# specnee spectrum %s\n", arg);
    printf("# pbrt .spd: wavelength (nm) and value, 1 nm steps over %d-%d nm\n", SPEC_MIN, SPEC_MAX);
    for (i = 0; i < SPEC_N; i++) printf("%d %.9g\n", SPEC_MIN + i, (double)s->v[i]);

    spec_to_xyz(s, (float)SPEC_MIN, (float)SPEC_MAX, xyz);
    lum = xyz[1] * cie_y_integral((float)SPEC_MIN, (float)SPEC_MAX);   /* sum ybar S */
    spec_to_xyz(s, LAMBDA_LO, LAMBDA_HI, xyz);
    ysum_specnee = xyz[1] * cie_y_integral(LAMBDA_LO, LAMBDA_HI);
    ysum_pbrt = lum;
    binsum = spec_bin_sum(s);
    spec_chromaticity(s, &x, &y);
    if (x > 0.0 && y > 0.0) cct = cct_from_xy(x, y, &duv);

    printf("# colorimetry: CIE 1931 2-degree observer, 1 nm sums over %d-%d nm\n", SPEC_MIN, SPEC_MAX);
    printf("# xy = %.5f %.5f\n", x, y);
    if (cct > 0.0) printf("# CCT = %.1f K, Duv = %+.5f (exact, nearest point of the Planckian locus in CIE 1960 uv)\n", cct, duv);
    else printf("# CCT = (undefined)\n");
    printf("# luminance sum_{360-830, 1 nm} ybar S = %.9g (pbrt-v4 named illuminants: 106.856895)\n", lum);
    printf("# thesis eq. 6 bin sum (60 bins of 5 nm over 400-700 nm) = %.9g\n", binsum);
    if (binsum > 0.0 && ysum_specnee > 0.0) {
        printf("# AreaLightSource \"diffuse\" \"spectrum L\" with this spectrum emits the thesis eq. 6\n"
               "# normalised spectrum (bin sum c = 1) with:\n");
        printf("#   \"float scale\" [ %.9g ]   specnee (Le = scale L / sum_{400-700 nm} ybar L)\n",
               ysum_specnee / binsum);
        printf("#   \"float scale\" [ %.9g ]   pbrt-v4 (Le = scale L / sum_{360-830 nm} ybar L)\n",
               ysum_pbrt / binsum);
        printf("# (multiply by c for another thesis eq. 6 constant, e.g. c = 2)\n");
    }
    return ferror(stdout) ? 1 : 0;
}

static int spectrum_svg(char **names, int n, double lo, double hi)
{
    SvgChart chart;
    SvgSeries *series;
    double *x, *y;
    Spectrum s;
    int i, k, n_pts, i0, ok, index;
    i0 = (int)ceil(lo) - SPEC_MIN;
    n_pts = (int)floor(hi) - (int)ceil(lo) + 1;
    series = (SvgSeries *)calloc((size_t)n, sizeof *series);
    x = (double *)malloc((size_t)n_pts * sizeof *x);
    y = (double *)malloc((size_t)n * (size_t)n_pts * sizeof *y);
    if (!series || !x || !y) {
        free(series); free(x); free(y);
        fprintf(stderr, "specnee spectrum: out of memory\n");
        return 1;
    }
    for (i = 0; i < n_pts; i++) x[i] = SPEC_MIN + i0 + i;
    /* Refractive indices (the built-in glass-* names) are plotted as they are, on
       their own axis: divided by the maximum, n = 1.51..1.53 would look flat. */
    for (k = 0; k < n; k++)
        if ((strncmp(names[k], "glass-", 6) == 0) != (strncmp(names[0], "glass-", 6) == 0)) {
            fprintf(stderr, "specnee spectrum: cannot plot refractive indices (glass-*) and "
                            "emission spectra in one chart\n");
            free(series); free(x); free(y);
            return 2;
        }
    index = strncmp(names[0], "glass-", 6) == 0;
    for (k = 0; k < n; k++) {
        double peak = 0.0;
        if (!spectrum_arg(names[k], &s)) { free(series); free(x); free(y); return 1; }
        for (i = 0; i < n_pts; i++) if (s.v[i0 + i] > peak) peak = s.v[i0 + i];
        if (index) peak = 1.0;
        for (i = 0; i < n_pts; i++) y[k * n_pts + i] = peak > 0.0 ? s.v[i0 + i] / peak : s.v[i0 + i];
        series[k].name = names[k];
        series[k].color = NULL;                   /* svg.c's palette */
        series[k].n = n_pts;
        series[k].x = x;
        series[k].y = y + k * n_pts;
    }
    memset(&chart, 0, sizeof chart);
    chart.xlabel = "wavelength (nm)";
    chart.xmin = lo; chart.xmax = hi;
    if (index) {
        chart.title = "Refractive index";
        chart.ylabel = "refractive index n";
        chart.ymin = chart.ymax = 0.0;            /* from the data */
    } else {
        chart.title = "Emission spectra (each divided by its maximum)";
        chart.ylabel = "relative spectral power";
        chart.ymin = 0.0; chart.ymax = 1.05;
    }
    ok = svg_line_chart(stdout, &chart, series, n);
    free(series); free(x); free(y);
    if (!ok) { fprintf(stderr, "specnee spectrum: cannot write the SVG\n"); return 1; }
    return 0;
}

/* `specnee spectrum --table scene.pbrt`: the emitter x bin table of the spectral
   strategies (lights.c, section 2; THEORY §5), as text or as an SVG
   heat map with two panels: T_e(b) divided by its largest entry, and P(e | b). */
static void heat_colour(double t, char out[8])
{
    /* white (0) to dark blue (1), linear in sRGB: readable in grey and by
       colour-blind viewers; NaN (no emitter in the bin) grey */
    int r, g, b;
    if (t != t) { strcpy(out, "#bbbbbb"); return; }
    if (t < 0.0) t = 0.0;
    if (t > 1.0) t = 1.0;
    r = (int)(255.0 + t * (8.0 - 255.0) + 0.5);
    g = (int)(255.0 + t * (48.0 - 255.0) + 0.5);
    b = (int)(255.0 + t * (107.0 - 255.0) + 0.5);
    sprintf(out, "#%02x%02x%02x", r, g, b);
}

static int spectrum_table(const char *path, int power_metric, int svg)
{
    Scene scene;
    Error err;
    int e, b, n, panel;
    double tmax = 0.0;
    float *bins;
    memset(&scene, 0, sizeof scene);
    err.msg[0] = '\0';
    if (!scene_load(&scene, path, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    n = scene.n_emitters;
    if (n == 0) {
        fprintf(stderr, "%s: the scene has no emitters (AreaLightSource)\n", path);
        scene_free(&scene);
        return 1;
    }
    /* T_e(b): as light_sampler_build fills its table (the emitters normalised over
       400-700 nm, the range of the bins) */
    bins = (float *)malloc(sizeof(float) * (size_t)n * SPD_BINS);
    if (!bins) { fprintf(stderr, "out of memory\n"); scene_free(&scene); return 1; }
    for (e = 0; e < n; e++) {
        Spectrum Le;
        if (!emitter_radiance(&scene, e, LAMBDA_LO, LAMBDA_HI, &Le, &err)) spec_const(&Le, 0.0f);
        for (b = 0; b < SPD_BINS; b++) bins[(size_t)e * SPD_BINS + b] = spec_bin_average(&Le, b);
    }
#define TABLE_T(e, b) ((double)bins[(size_t)(e) * SPD_BINS + (b)] * (power_metric ? \
        scene.emitters[e].area * (scene.emitters[e].twosided ? 2.0 : 1.0) : 1.0))
    for (e = 0; e < n; e++)
        for (b = 0; b < SPD_BINS; b++)
            if (TABLE_T(e, b) > tmax) tmax = TABLE_T(e, b);
    if (!svg) {
        printf("# specnee spectrum --table %s (--spd-metric %s)\n", path, power_metric ? "power" : "unit");
        printf("# T_e(b) = bin average of emitter e's Le over bin b%s; P(e|b) = T_e(b) / sum_k T_k(b)\n",
               power_metric ? " x area x sides" : "");
        printf("# (P is '-' where no emitter emits: there the spectral strategies fall back to spatial)\n");
        for (e = 0; e < n; e++) {
            const Emitter *em = &scene.emitters[e];
            if (em->inf)
                printf("# emitter %d: %s:%d, infinite light, area 4 pi R^2 = %.6g\n", e,
                       em->inf->file, em->inf->line, em->area);
            else if (em->delta.type != DELTA_NONE)
                printf("# emitter %d: %s:%d, delta light, power area %.6g\n", e,
                       em->delta.file, em->delta.line, em->area);
            else
                printf("# emitter %d: %s:%d, area %.6g\n", e, scene.shapes[em->shape].file,
                       scene.shapes[em->shape].line, em->area);
        }
        printf("# bin       nm");
        for (e = 0; e < n; e++) printf("     T_%-4d", e);
        for (e = 0; e < n; e++) printf("  P_%-4d", e);
        printf("\n");
        for (b = 0; b < SPD_BINS; b++) {
            double sum = 0.0;
            float lo = LAMBDA_LO + b * SPD_BIN_NM;
            for (e = 0; e < n; e++) sum += TABLE_T(e, b);
            printf("%5d  %3.0f-%3.0f", b, lo, lo + SPD_BIN_NM);
            for (e = 0; e < n; e++) printf(" %10.4g", TABLE_T(e, b));
            for (e = 0; e < n; e++)
                if (sum > 0.0) printf("  %6.4f", TABLE_T(e, b) / sum);
                else printf("  %6s", "-");
            printf("\n");
        }
    } else {
        const int cw = 11, ch = 22, x0 = 110, top = 50, gap = 60;
        int W = x0 + SPD_BINS * cw + 30, H = top + 2 * (n * ch + gap) + 40;
        printf("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
               "font-family=\"sans-serif\" font-size=\"12\">\n", W, H);
        printf("<rect width=\"%d\" height=\"%d\" fill=\"white\"/>\n", W, H);
        printf("<text x=\"%d\" y=\"22\" font-size=\"14\">Emitter x bin table (--spd-metric %s)</text>\n",
               x0, power_metric ? "power" : "unit");
        for (panel = 0; panel < 2; panel++) {
            int y0 = top + panel * (n * ch + gap);
            printf("<text x=\"%d\" y=\"%d\">%s</text>\n", x0, y0 - 8,
                   panel == 0 ? "T_e(b) / max T (bin average of Le; white 0, dark 1)"
                              : "P(e | b) = T_e(b) / sum_k T_k(b) (white 0, dark 1; grey: no emitter)");
            for (e = 0; e < n; e++) {
                printf("<text x=\"%d\" y=\"%d\" text-anchor=\"end\">emitter %d</text>\n",
                       x0 - 6, y0 + e * ch + ch / 2 + 4, e);
                for (b = 0; b < SPD_BINS; b++) {
                    double sum = 0.0, t;
                    char col[8];
                    int k;
                    for (k = 0; k < n; k++) sum += TABLE_T(k, b);
                    if (panel == 0) t = tmax > 0.0 ? TABLE_T(e, b) / tmax : 0.0;
                    else t = sum > 0.0 ? TABLE_T(e, b) / sum : (double)NAN;
                    heat_colour(t, col);
                    printf("<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\">"
                           "<title>emitter %d, %.0f-%.0f nm: %.4g</title></rect>\n",
                           x0 + b * cw, y0 + e * ch, cw, ch, col, e,
                           LAMBDA_LO + b * SPD_BIN_NM, LAMBDA_LO + (b + 1) * SPD_BIN_NM, t);
                }
            }
            printf("<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"black\"/>\n",
                   x0, y0, SPD_BINS * cw, n * ch);
            for (b = 0; b <= SPD_BINS; b += 10)
                printf("<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%.0f</text>\n",
                       x0 + b * cw, y0 + n * ch + 15, LAMBDA_LO + b * SPD_BIN_NM);
        }
        printf("<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">wavelength (nm), 60 bins of 5 nm</text>\n",
               x0 + SPD_BINS * cw / 2, H - 8);
        printf("</svg>\n");
    }
#undef TABLE_T
    free(bins);
    scene_free(&scene);
    return ferror(stdout) ? 1 : 0;
}

int cmd_spectrum(int argc, char **argv)
{
    int i = 1, svg = 0, table = 0, power_metric = 0;
    double lo = SPEC_MIN, hi = SPEC_MAX;
    Spectrum s;
    while (i < argc && argv[i][0] == '-' && argv[i][1] == '-') {
        if (strcmp(argv[i], "--svg") == 0) { svg = 1; i++; }
        else if (strcmp(argv[i], "--table") == 0) { table = 1; i++; }
        else if (strcmp(argv[i], "--spd-metric") == 0 && i + 1 < argc) {
            if (strcmp(argv[i + 1], "unit") == 0) power_metric = 0;
            else if (strcmp(argv[i + 1], "power") == 0) power_metric = 1;
            else {
                fprintf(stderr, "specnee spectrum: --spd-metric is unit or power, not '%s'\n", argv[i + 1]);
                return 2;
            }
            i += 2;
        }
        else if (strcmp(argv[i], "--list") == 0) {
            const char *const *names = spec_named_list();
            if (i + 1 != argc) { fputs(spectrum_usage, stderr); return 2; }
            for (; *names; names++) printf("%s\n", *names);
            return 0;
        } else if (strcmp(argv[i], "--help") == 0) { fputs(spectrum_usage, stdout); return 0; }
        else if (strcmp(argv[i], "--range") == 0 && i + 2 < argc) {
            char *e1, *e2;
            lo = strtod(argv[i + 1], &e1);
            hi = strtod(argv[i + 2], &e2);
            if (*e1 || *e2 || !(lo >= SPEC_MIN) || !(hi <= SPEC_MAX) || !(hi - lo >= 1.0)) {
                fprintf(stderr, "specnee spectrum: --range needs %d <= LO < HI <= %d\n", SPEC_MIN, SPEC_MAX);
                return 2;
            }
            i += 3;
        } else {
            fprintf(stderr, "specnee spectrum: unknown option '%s'\n", argv[i]);
            fputs(spectrum_usage, stderr);
            return 2;
        }
    }
    if (table) {
        if (argc - i != 1) { fputs(spectrum_usage, stderr); return 2; }
        return spectrum_table(argv[i], power_metric, svg);
    }
    if (svg) {
        if (i >= argc) { fputs(spectrum_usage, stderr); return 2; }
        return spectrum_svg(argv + i, argc - i, lo, hi);
    }
    if (argc - i != 1) { fputs(spectrum_usage, stderr); return 2; }
    if (!spectrum_arg(argv[i], &s)) return 1;
    return spectrum_print(argv[i], &s);
}
