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

int img_cmd_merge(int argc, char **argv, FILE *out, FILE *errf)
{
    const char *out_path = NULL;
    int equal = 0, n = 0, i, k, status = 1;
    const char **inputs;
    Image *ims = NULL, merged = { 0, 0, NULL };
    double *weights = NULL;
    long spp_total = 0;
    Error err;
    char settings[1024];
    size_t used;

    inputs = (const char **)malloc(sizeof *inputs * (size_t)(argc > 0 ? argc : 1));
    if (!inputs) { fprintf(errf, "merge: out of memory\n"); return 1; }
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(merge_usage, out); fputs(merge_help, out);
            free(inputs);
            return 0;
        } else if (strcmp(a, "-o") == 0) {
            if (i + 1 >= argc || out_path) {
                fprintf(errf, "merge: %s\n%s", out_path ? "-o given twice" : "-o needs a file name",
                        merge_usage);
                free(inputs);
                return 2;
            }
            out_path = argv[++i];
        } else if (strcmp(a, "--equal-weights") == 0) {
            equal = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(errf, "merge: unknown option '%s'\n%s", a, merge_usage);
            free(inputs);
            return 2;
        } else {
            inputs[n++] = a;
        }
    }
    if (n < 1 || !out_path) {
        fprintf(errf, "merge: %s\n%s", n < 1 ? "no input images" : "no output (-o FILE)",
                merge_usage);
        free(inputs);
        return 2;
    }

    ims = (Image *)calloc((size_t)n, sizeof *ims);
    weights = (double *)calloc((size_t)n, sizeof *weights);
    if (!ims || !weights) { fprintf(errf, "merge: out of memory\n"); goto done; }

    /* 1. Read every input; all must have the first one's size. */
    for (k = 0; k < n; k++) {
        if (!pfm_read(&ims[k], inputs[k], &err)) { fprintf(errf, "%s\n", err.msg); goto done; }
        if (ims[k].w != ims[0].w || ims[k].h != ims[0].h) {
            fprintf(errf, "%s: size %dx%d differs from %s's %dx%d\n", inputs[k],
                    ims[k].w, ims[k].h, inputs[0], ims[0].w, ims[0].h);
            goto done;
        }
    }

    /* 2. Weights: the sample counts from the sidecars (or 1 each). */
    for (k = 0; k < n; k++) {
        long spp = img_read_sidecar_spp(inputs[k]);
        if (spp < 0 && !equal) {
            fprintf(errf, "%s: no sidecar %s.txt with a valid line 'spp N', N from 0 to %ld "
                    "(needed for the sample-count weights; --equal-weights merges without)\n",
                    inputs[k], inputs[k], LONG_MAX);
            goto done;
        }
        if (spp == 0 && !equal) {
            fprintf(errf, "%s: sidecar says spp 0 (nothing to weight)\n", inputs[k]);
            goto done;
        }
        weights[k] = equal ? 1.0 : (double)spp;
        if (spp >= 0 && spp_total >= 0 && spp > LONG_MAX - spp_total) {
            fprintf(errf, "%s: sidecar spp %ld: the summed sample count would exceed %ld\n",
                    inputs[k], spp, LONG_MAX);
            goto done;
        }
        if (spp_total >= 0) spp_total = spp < 0 ? -1 : spp_total + spp;  /* -1: unknown */
    }

    /* 3. Merge and write the result with its sidecar. */
    if (!img_merge(ims, weights, n, &merged)) {
        fprintf(errf, "merge: cannot merge (out of memory)\n");
        goto done;
    }
    if (!img_write(&merged, out_path, 0.0f, &err)) { fprintf(errf, "%s\n", err.msg); goto done; }
    used = (size_t)snprintf(settings, sizeof settings, "merge%s of %d images:",
                            equal ? " (equal weights)" : "", n);
    for (k = 0; k < n && used < sizeof settings; k++)
        used += (size_t)snprintf(settings + used, sizeof settings - used, " %s", inputs[k]);
    if (!img_write_sidecar(out_path, spp_total, settings)) {
        fprintf(errf, "%s.txt: cannot write the sidecar\n", out_path);
        goto done;
    }
    if (spp_total >= 0)
        fprintf(out, "merged %d images (%ld spp) into %s\n", n, spp_total, out_path);
    else
        fprintf(out, "merged %d images (equal weights, spp unknown) into %s\n", n, out_path);
    status = 0;

done:
    if (ims) for (k = 0; k < n; k++) img_free(&ims[k]);
    img_free(&merged);
    free(ims);
    free(weights);
    free(inputs);
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

int img_cmd_diff(int argc, char **argv, FILE *out, FILE *errf)
{
    const char *paths[2] = { NULL, NULL }, *err_image = NULL;
    int n_paths = 0, n_regions = 0, csv = 0, means = 0, has_max_mse = 0, has_max_rel = 0;
    int i, k, status = 1;
    double max_mse = 0.0, max_rel = 0.0;
    DiffRegion *regions, whole;
    Image test = { 0, 0, NULL }, ref = { 0, 0, NULL };
    ImgErr e;
    Error err;

    regions = (DiffRegion *)malloc(sizeof *regions * (size_t)(argc > 0 ? argc : 1));
    if (!regions) { fprintf(errf, "diff: out of memory\n"); return 1; }

    /* 1. Arguments. */
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(diff_usage, out); fputs(diff_help, out);
            free(regions);
            return 0;
        } else if (strcmp(a, "--csv") == 0) {
            csv = 1;
        } else if (strcmp(a, "--means") == 0) {
            means = 1;
        } else if (strcmp(a, "--region") == 0 || strcmp(a, "--error-image") == 0 ||
                   strcmp(a, "--max-mse") == 0 || strcmp(a, "--max-relmse") == 0) {
            int ok = val != NULL;
            if (ok && strcmp(a, "--region") == 0) {
                ok = parse_region(val, n_regions, &regions[n_regions]);
                if (ok) n_regions++;
            } else if (ok && strcmp(a, "--error-image") == 0) {
                err_image = val;
            } else if (ok && strcmp(a, "--max-mse") == 0) {
                ok = parse_threshold(val, &max_mse);
                has_max_mse = 1;
            } else if (ok) {
                ok = parse_threshold(val, &max_rel);
                has_max_rel = 1;
            }
            if (!ok) {
                if (!val) fprintf(errf, "diff: %s needs a value\n%s", a, diff_usage);
                else fprintf(errf, "diff: bad %s '%s'%s\n%s", a, val,
                             a[2] == 'r' ? " (expected NAME:x0,y0,x1,y1)"
                                         : " (expected a number >= 0)", diff_usage);
                free(regions);
                return 2;
            }
            i++;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(errf, "diff: unknown option '%s'\n%s", a, diff_usage);
            free(regions);
            return 2;
        } else if (n_paths < 2) {
            paths[n_paths++] = a;
        } else {
            fprintf(errf, "diff: more than two images given ('%s')\n%s", a, diff_usage);
            free(regions);
            return 2;
        }
    }
    if (n_paths != 2) {
        fprintf(errf, "diff: need a test image and a reference image\n%s", diff_usage);
        free(regions);
        return 2;
    }

    /* 2. Images of the same size. */
    if (!pfm_read(&test, paths[0], &err) || !pfm_read(&ref, paths[1], &err)) {
        fprintf(errf, "%s\n", err.msg);
        goto done;
    }
    if (test.w != ref.w || test.h != ref.h) {
        fprintf(errf, "%s: size %dx%d differs from the reference %s's %dx%d\n", paths[0],
                test.w, test.h, paths[1], ref.w, ref.h);
        goto done;
    }

    /* 3. Clip the regions to the image; an empty result is an error. */
    for (k = 0; k < n_regions; k++) {
        DiffRegion *r = &regions[k];
        int x0 = r->x0 > 0 ? r->x0 : 0, y0 = r->y0 > 0 ? r->y0 : 0;
        int x1 = r->x1 < test.w ? r->x1 : test.w, y1 = r->y1 < test.h ? r->y1 : test.h;
        if (x0 >= x1 || y0 >= y1) {
            fprintf(errf, "%s: region '%s' (%d,%d,%d,%d) is empty or outside the %dx%d image\n",
                    paths[0], r->name, r->x0, r->y0, r->x1, r->y1, test.w, test.h);
            goto done;
        }
        r->x0 = x0; r->y0 = y0; r->x1 = x1; r->y1 = y1;
    }

    /* 4. Metrics: the whole image, then each region. */
    strcpy(whole.name, "image");
    whole.x0 = 0; whole.y0 = 0; whole.x1 = test.w; whole.y1 = test.h;
    if (csv) fprintf(out, "region,x0,y0,x1,y1,pixels,mse,relmse,mae%s\n", means ? ",y_test,y_ref,ratio" : "");
    else fprintf(out, "%-12s %5s %5s %5s %5s %9s %13s %13s %13s%s\n", "region", "x0", "y0",
                 "x1", "y1", "pixels", "MSE", "relMSE", "MAE",
                 means ? "        Y_test         Y_ref     ratio" : "");
    img_error(&test, &ref, 0, 0, test.w, test.h, &e);
    diff_print(out, csv, means, &whole, &e);
    for (k = 0; k < n_regions; k++) {
        ImgErr er;
        img_error(&test, &ref, regions[k].x0, regions[k].y0, regions[k].x1, regions[k].y1, &er);
        diff_print(out, csv, means, &regions[k], &er);
    }

    errno = 0;
    if (err_image && !img_write_error_png(&test, &ref, err_image)) {
        fprintf(errf, "%s: cannot write the error image: %s\n", err_image,
                errno ? strerror(errno) : "I/O error");
        goto done;
    }

    /* 5. Thresholds on the whole image; NaN counts as exceeded. */
    status = 0;
    {
        int over_mse = has_max_mse && !(e.mse <= max_mse);
        int over_rel = has_max_rel && !(e.relmse <= max_rel);
        if (over_mse || over_rel) {
            fprintf(errf, "diff:");
            if (over_mse) fprintf(errf, " MSE %.6g exceeds --max-mse %g", e.mse, max_mse);
            if (over_mse && over_rel) fprintf(errf, ";");
            if (over_rel) fprintf(errf, " relMSE %.6g exceeds --max-relmse %g", e.relmse, max_rel);
            fprintf(errf, "\n");
            status = 1;
        }
    }

done:
    img_free(&test);
    img_free(&ref);
    free(regions);
    return status;
}

int cmd_diff(int argc, char **argv)
{
    return img_cmd_diff(argc, argv, stdout, stderr);
}
