/* cmd_image.c - `specnee merge` and `specnee diff`: commands on rendered images.

   WHAT IT IMPLEMENTS
     specnee merge a.pfm b.pfm ... -o out.pfm [--equal-weights]
         the sample-count-weighted mean I = sum_i w_i I_i / sum_i w_i, w_i = spp_i
         from each input's sidecar "<input>.txt" (img_merge), written with a
         sidecar holding the summed spp;
     specnee diff test.pfm ref.pfm [--region NAME:x0,y0,x1,y1 ...] ...
         MSE, relMSE and MAE over the whole image and each region (img_error), an
         optional false-colour error image and thresholds for scripts.
   Exit codes: 0 ok, 1 bad input (or a threshold exceeded), 2 bad usage.

   HOW IT IS USED
     specnee.c dispatches the subcommands to cmd_merge and cmd_diff (specnee.h
     section 14); the tests call img_cmd_merge and img_cmd_diff with their own
     streams.  A command room: it parses command lines and prints; the images, the
     sidecars and the metrics are image.c's. */
#include "specnee.h"
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* ======================================================================
   specnee merge
   ====================================================================== */

static const char merge_usage[] =
    "usage: specnee merge a.pfm b.pfm ... -o out.pfm [--equal-weights]\n";

static const char merge_help[] =
    "Averages independent renders of the same scene, weighted by their sample counts:\n"
    "  out = sum_i spp_i * image_i / sum_i spp_i\n"
    "Each input's spp comes from its sidecar \"<input>.txt\" (line \"spp N\").\n"
    "  -o FILE            output image (.pfm, .ppm or .png); its sidecar gets the summed spp\n"
    "  --equal-weights    plain mean, for inputs without sidecars\n"
    "Exit status: 0 ok, 1 bad input, 2 bad usage.\n";

/* The command line of merge. */
typedef struct {
    const char **inputs;       /* argc entries, n used */
    int n;
    const char *out_path;
    int equal;                 /* --equal-weights */
} MergeArgs;

/* The options into m (m->inputs allocated by the caller).  Returns -1 to go on,
   else the exit code (0 after --help). */
static int merge_options(int argc, char **argv, MergeArgs *m, FILE *out, FILE *errf)
{
    int i;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(merge_usage, out); fputs(merge_help, out);
            return 0;
        } else if (strcmp(a, "-o") == 0) {
            if (i + 1 >= argc || m->out_path) {
                fprintf(errf, "merge: %s\n%s", m->out_path ? "-o given twice" : "-o needs a file name",
                        merge_usage);
                return 2;
            }
            m->out_path = argv[++i];
        } else if (strcmp(a, "--equal-weights") == 0) {
            m->equal = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(errf, "merge: unknown option '%s'\n%s", a, merge_usage);
            return 2;
        } else {
            m->inputs[m->n++] = a;
        }
    }
    if (m->n < 1 || !m->out_path) {
        fprintf(errf, "merge: %s\n%s", m->n < 1 ? "no input images" : "no output (-o FILE)",
                merge_usage);
        return 2;
    }
    return -1;
}

/* Every input into ims[]; all must have the first one's size.  0 after a message. */
static int merge_read(const MergeArgs *m, Image *ims, FILE *errf)
{
    Error err;
    int k;
    for (k = 0; k < m->n; k++) {
        if (!pfm_read(&ims[k], m->inputs[k], &err)) { fprintf(errf, "%s\n", err.msg); return 0; }
        if (ims[k].w != ims[0].w || ims[k].h != ims[0].h) {
            fprintf(errf, "%s: size %dx%d differs from %s's %dx%d\n", m->inputs[k],
                    ims[k].w, ims[k].h, m->inputs[0], ims[0].w, ims[0].h);
            return 0;
        }
    }
    return 1;
}

/* The weights: the sample counts from the sidecars (or 1 each), and their sum into
   *total (-1: unknown).  0 after a message. */
static int merge_weights(const MergeArgs *m, double *weights, long *total, FILE *errf)
{
    long spp_total = 0;
    int k;
    for (k = 0; k < m->n; k++) {
        long spp = img_read_sidecar_spp(m->inputs[k]);
        if (spp < 0 && !m->equal) {
            fprintf(errf, "%s: no sidecar %s.txt with a valid line 'spp N', N from 0 to %ld "
                    "(needed for the sample-count weights; --equal-weights merges without)\n",
                    m->inputs[k], m->inputs[k], LONG_MAX);
            return 0;
        }
        if (spp == 0 && !m->equal) {
            fprintf(errf, "%s: sidecar says spp 0 (nothing to weight)\n", m->inputs[k]);
            return 0;
        }
        weights[k] = m->equal ? 1.0 : (double)spp;
        if (spp >= 0 && spp_total >= 0 && spp > LONG_MAX - spp_total) {
            fprintf(errf, "%s: sidecar spp %ld: the summed sample count would exceed %ld\n",
                    m->inputs[k], spp, LONG_MAX);
            return 0;
        }
        if (spp_total >= 0) spp_total = spp < 0 ? -1 : spp_total + spp;  /* -1: unknown */
    }
    *total = spp_total;
    return 1;
}

/* The merged image and its sidecar (the summed spp, the inputs as settings), and the
   closing line on out.  0 after a message. */
static int merge_write(const MergeArgs *m, const Image *merged, long spp_total, FILE *out, FILE *errf)
{
    Error err;
    char settings[1024];
    size_t used;
    int k;
    if (!img_write(merged, m->out_path, 0.0f, &err)) { fprintf(errf, "%s\n", err.msg); return 0; }
    used = (size_t)snprintf(settings, sizeof settings, "merge%s of %d images:",
                            m->equal ? " (equal weights)" : "", m->n);
    for (k = 0; k < m->n && used < sizeof settings; k++)
        used += (size_t)snprintf(settings + used, sizeof settings - used, " %s", m->inputs[k]);
    if (!img_write_sidecar(m->out_path, spp_total, settings)) {
        fprintf(errf, "%s.txt: cannot write the sidecar\n", m->out_path);
        return 0;
    }
    if (spp_total >= 0)
        fprintf(out, "merged %d images (%ld spp) into %s\n", m->n, spp_total, m->out_path);
    else
        fprintf(out, "merged %d images (equal weights, spp unknown) into %s\n", m->n, m->out_path);
    return 1;
}

int img_cmd_merge(int argc, char **argv, FILE *out, FILE *errf)
{
    MergeArgs m = { NULL, 0, NULL, 0 };
    Image *ims = NULL, merged = { 0, 0, NULL };
    double *weights = NULL;
    long spp_total = 0;
    int k, status;

    m.inputs = (const char **)malloc(sizeof *m.inputs * (size_t)(argc > 0 ? argc : 1));
    if (!m.inputs) { fprintf(errf, "merge: out of memory\n"); return 1; }
    status = merge_options(argc, argv, &m, out, errf);
    if (status >= 0) { free(m.inputs); return status; }

    status = 1;
    ims = (Image *)calloc((size_t)m.n, sizeof *ims);
    weights = (double *)calloc((size_t)m.n, sizeof *weights);
    if (!ims || !weights) fprintf(errf, "merge: out of memory\n");
    else if (merge_read(&m, ims, errf) && merge_weights(&m, weights, &spp_total, errf)) {
        if (!img_merge(ims, weights, m.n, &merged))
            fprintf(errf, "merge: cannot merge (out of memory)\n");
        else if (merge_write(&m, &merged, spp_total, out, errf))
            status = 0;
    }

    if (ims) for (k = 0; k < m.n; k++) img_free(&ims[k]);
    img_free(&merged);
    free(ims);
    free(weights);
    free(m.inputs);
    return status;
}

int cmd_merge(int argc, char **argv)
{
    return img_cmd_merge(argc, argv, stdout, stderr);
}

/* ======================================================================
   specnee diff
   ====================================================================== */

static const char diff_usage[] =
    "usage: specnee diff test.pfm ref.pfm [--region NAME:x0,y0,x1,y1 ...] "
    "[--error-image err.png]\n"
    "                    [--max-mse X] [--max-relmse Y] [--csv] [--means]\n";

static const char diff_help[] =
    "Compares a test image with a reference, over the whole image and each region:\n"
    "  MSE    = mean over pixels and the 3 channels of (test - ref)^2\n"
    "  relMSE = mean of (test - ref)^2 / (ref^2 + eps), eps = 1e-2\n"
    "           (Rousselle, Knaus and Zwicker 2011 style)\n"
    "  MAE    = mean of |test - ref|\n"
    "  --region NAME:x0,y0,x1,y1   pixels from the top left, x1 and y1 exclusive,\n"
    "                 clipped to the image (NAME: optional; repeatable)\n"
    "  --error-image FILE.png      false colour of the per-pixel relative squared error\n"
    "                 e = mean_c (test - ref)^2 / (ref^2 + eps) on a log scale with the\n"
    "                 viridis ramp: e <= 1e-5 dark purple, 1e-2 teal, e >= 10 yellow;\n"
    "                 NaN magenta\n"
    "  --max-mse X, --max-relmse Y  exit 1 when the whole image's value exceeds them\n"
    "  --csv          print region,x0,y0,x1,y1,pixels,mse,relmse,mae as CSV\n"
    "  --means        also the luminance means Y_test, Y_ref (sRGB's Y row) and their\n"
    "                 ratio: how bright each image is (tools/pbrt_compare.sh)\n"
    "Exit status: 0 ok, 1 bad input or a threshold exceeded, 2 bad usage.\n";

typedef struct {
    char name[32];
    int x0, y0, x1, y1;
} DiffRegion;

/* "NAME:x0,y0,x1,y1" or "x0,y0,x1,y1" (then named "regionK"). */
static int parse_region(const char *s, int index, DiffRegion *r)
{
    const char *colon = strchr(s, ':'), *p;
    long v[4];
    int k;
    char *endp;
    if (colon) {
        size_t len = (size_t)(colon - s);
        if (len == 0 || len >= sizeof r->name) return 0;
        memcpy(r->name, s, len);
        r->name[len] = '\0';
        p = colon + 1;
    } else {
        snprintf(r->name, sizeof r->name, "region%d", index + 1);
        p = s;
    }
    for (k = 0; k < 4; k++) {
        if (!((*p >= '0' && *p <= '9') || *p == '-' || *p == '+')) return 0;
        v[k] = strtol(p, &endp, 10);
        if (endp == p || v[k] < -IMG_MAX_PIXELS || v[k] > IMG_MAX_PIXELS) return 0;
        p = endp;
        if (k < 3) { if (*p != ',') return 0; p++; }
    }
    if (*p != '\0') return 0;
    r->x0 = (int)v[0]; r->y0 = (int)v[1]; r->x1 = (int)v[2]; r->y1 = (int)v[3];
    return 1;
}

/* A threshold: a finite number >= 0. */
static int parse_threshold(const char *s, double *out)
{
    char *endp;
    double v = strtod(s, &endp);
    if (endp == s || *endp != '\0' || !(v >= 0.0) || v > DBL_MAX) return 0;
    *out = v;
    return 1;
}

static void diff_print(FILE *out, int csv, int means, const DiffRegion *r, const ImgErr *e)
{
    double ratio = e->y_ref != 0.0 ? e->y_test / e->y_ref : 0.0;
    if (csv)
        fprintf(out, "%s,%d,%d,%d,%d,%ld,%.9g,%.9g,%.9g", r->name, r->x0, r->y0, r->x1,
                r->y1, e->n, e->mse, e->relmse, e->mae);
    else
        fprintf(out, "%-12s %5d %5d %5d %5d %9ld %13.6e %13.6e %13.6e", r->name, r->x0,
                r->y0, r->x1, r->y1, e->n, e->mse, e->relmse, e->mae);
    if (means) fprintf(out, csv ? ",%.9g,%.9g,%.9g" : " %13.6e %13.6e %9.6f", e->y_test, e->y_ref, ratio);
    fprintf(out, "\n");
}

/* The command line of diff. */
typedef struct {
    const char *paths[2];      /* the test image, the reference */
    const char *err_image;     /* --error-image, or NULL */
    DiffRegion *regions;       /* argc entries, n_regions used */
    int n_regions, csv, means, has_max_mse, has_max_rel;
    double max_mse, max_rel;
} DiffArgs;

/* The options into d (d->regions allocated by the caller).  Returns -1 to go on,
   else the exit code (0 after --help). */
static int diff_options(int argc, char **argv, DiffArgs *d, FILE *out, FILE *errf)
{
    int i, n_paths = 0;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(diff_usage, out); fputs(diff_help, out);
            return 0;
        } else if (strcmp(a, "--csv") == 0) {
            d->csv = 1;
        } else if (strcmp(a, "--means") == 0) {
            d->means = 1;
        } else if (strcmp(a, "--region") == 0 || strcmp(a, "--error-image") == 0 ||
                   strcmp(a, "--max-mse") == 0 || strcmp(a, "--max-relmse") == 0) {
            int ok = val != NULL;
            if (ok && strcmp(a, "--region") == 0) {
                ok = parse_region(val, d->n_regions, &d->regions[d->n_regions]);
                if (ok) d->n_regions++;
            } else if (ok && strcmp(a, "--error-image") == 0) {
                d->err_image = val;
            } else if (ok && strcmp(a, "--max-mse") == 0) {
                ok = parse_threshold(val, &d->max_mse);
                d->has_max_mse = 1;
            } else if (ok) {
                ok = parse_threshold(val, &d->max_rel);
                d->has_max_rel = 1;
            }
            if (!ok) {
                if (!val) fprintf(errf, "diff: %s needs a value\n%s", a, diff_usage);
                else fprintf(errf, "diff: bad %s '%s'%s\n%s", a, val,
                             a[2] == 'r' ? " (expected NAME:x0,y0,x1,y1)"
                                         : " (expected a number >= 0)", diff_usage);
                return 2;
            }
            i++;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(errf, "diff: unknown option '%s'\n%s", a, diff_usage);
            return 2;
        } else if (n_paths < 2) {
            d->paths[n_paths++] = a;
        } else {
            fprintf(errf, "diff: more than two images given ('%s')\n%s", a, diff_usage);
            return 2;
        }
    }
    if (n_paths != 2) {
        fprintf(errf, "diff: need a test image and a reference image\n%s", diff_usage);
        return 2;
    }
    return -1;
}

/* Clips the regions to the w x h image; an empty result is an error (0 after a
   message). */
static int diff_clip_regions(DiffArgs *d, int w, int h, FILE *errf)
{
    int k;
    for (k = 0; k < d->n_regions; k++) {
        DiffRegion *r = &d->regions[k];
        int x0 = r->x0 > 0 ? r->x0 : 0, y0 = r->y0 > 0 ? r->y0 : 0;
        int x1 = r->x1 < w ? r->x1 : w, y1 = r->y1 < h ? r->y1 : h;
        if (x0 >= x1 || y0 >= y1) {
            fprintf(errf, "%s: region '%s' (%d,%d,%d,%d) is empty or outside the %dx%d image\n",
                    d->paths[0], r->name, r->x0, r->y0, r->x1, r->y1, w, h);
            return 0;
        }
        r->x0 = x0; r->y0 = y0; r->x1 = x1; r->y1 = y1;
    }
    return 1;
}

/* The metrics table: the whole image (its errors into *whole_err), then each region. */
static void diff_table(const DiffArgs *d, const Image *test, const Image *ref, ImgErr *whole_err,
                       FILE *out)
{
    DiffRegion whole;
    int k;
    strcpy(whole.name, "image");
    whole.x0 = 0; whole.y0 = 0; whole.x1 = test->w; whole.y1 = test->h;
    if (d->csv) fprintf(out, "region,x0,y0,x1,y1,pixels,mse,relmse,mae%s\n", d->means ? ",y_test,y_ref,ratio" : "");
    else fprintf(out, "%-12s %5s %5s %5s %5s %9s %13s %13s %13s%s\n", "region", "x0", "y0",
                 "x1", "y1", "pixels", "MSE", "relMSE", "MAE",
                 d->means ? "        Y_test         Y_ref     ratio" : "");
    img_error(test, ref, 0, 0, test->w, test->h, whole_err);
    diff_print(out, d->csv, d->means, &whole, whole_err);
    for (k = 0; k < d->n_regions; k++) {
        const DiffRegion *r = &d->regions[k];
        ImgErr er;
        img_error(test, ref, r->x0, r->y0, r->x1, r->y1, &er);
        diff_print(out, d->csv, d->means, r, &er);
    }
}

/* The thresholds on the whole image; NaN counts as exceeded.  1 (after a line on
   errf) when one is exceeded, else 0. */
static int diff_thresholds(const DiffArgs *d, const ImgErr *e, FILE *errf)
{
    int over_mse = d->has_max_mse && !(e->mse <= d->max_mse);
    int over_rel = d->has_max_rel && !(e->relmse <= d->max_rel);
    if (!over_mse && !over_rel) return 0;
    fprintf(errf, "diff:");
    if (over_mse) fprintf(errf, " MSE %.6g exceeds --max-mse %g", e->mse, d->max_mse);
    if (over_mse && over_rel) fprintf(errf, ";");
    if (over_rel) fprintf(errf, " relMSE %.6g exceeds --max-relmse %g", e->relmse, d->max_rel);
    fprintf(errf, "\n");
    return 1;
}

int img_cmd_diff(int argc, char **argv, FILE *out, FILE *errf)
{
    DiffArgs d;
    Image test = { 0, 0, NULL }, ref = { 0, 0, NULL };
    ImgErr e;
    Error err;
    int status;

    memset(&d, 0, sizeof d);
    d.regions = (DiffRegion *)malloc(sizeof *d.regions * (size_t)(argc > 0 ? argc : 1));
    if (!d.regions) { fprintf(errf, "diff: out of memory\n"); return 1; }
    status = diff_options(argc, argv, &d, out, errf);
    if (status >= 0) { free(d.regions); return status; }

    /* images of the same size, the regions clipped to them, the table, the error
       image, the thresholds */
    status = 1;
    if (!pfm_read(&test, d.paths[0], &err) || !pfm_read(&ref, d.paths[1], &err)) {
        fprintf(errf, "%s\n", err.msg);
    } else if (test.w != ref.w || test.h != ref.h) {
        fprintf(errf, "%s: size %dx%d differs from the reference %s's %dx%d\n", d.paths[0],
                test.w, test.h, d.paths[1], ref.w, ref.h);
    } else if (diff_clip_regions(&d, test.w, test.h, errf)) {
        diff_table(&d, &test, &ref, &e, out);
        errno = 0;
        if (d.err_image && !img_write_error_png(&test, &ref, d.err_image))
            fprintf(errf, "%s: cannot write the error image: %s\n", d.err_image,
                    errno ? strerror(errno) : "I/O error");
        else
            status = diff_thresholds(&d, &e, errf);
    }

    img_free(&test);
    img_free(&ref);
    free(d.regions);
    return status;
}

int cmd_diff(int argc, char **argv)
{
    return img_cmd_diff(argc, argv, stdout, stderr);
}
