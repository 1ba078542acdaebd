/* infinite.c - infinite lights: a constant environment, or an image map in
   pbrt-v4's equal-area octahedral layout, importance-sampled.

   Exported (specnee.h section 11): inf_Le, inf_pdf, inf_sample,
   equal_area_square_to_sphere, equal_area_sphere_to_square, inf_set_image, inf_free.
   The last section builds an InfiniteLight for `LightSource "infinite"` (and reads the
   PFM or EXR image), lights.c treats it as one more emitter for every selection
   strategy, path.c adds its radiance to rays that escape the scene.

   1. THE MAP (Clarberg, "Fast equal-area mapping of the (hemi)sphere using SIMD",
      JGT 2008; pbrt-v4's EqualAreaSquareToSphere).  With (a, b) = 2 (u, v) - 1 in
      [-1, 1]^2, the distance to the diamond |a| + |b| = 1 gives the radius
          r = 1 - |1 - |a| - |b||,  z = +-(1 - r^2)  (+ inside the diamond),
          phi = pi/4 ((|b| - |a|) / r + 1)   in the quadrant of (a, b),
          (x, y) = r sqrt(2 - r^2) (cos phi, sin phi).
      It is equal-area: the unit square's area 1 maps to the sphere's 4 pi, so a
      density p(u, v) on the square is p / (4 pi) per steradian.  The inverse is
      written with atan2 (pbrt-v4 uses a polynomial approximation of it).

   2. RADIANCE.  A constant light has Le(lambda) = scale L(lambda) / sum ybar L
      (lights.c's emitter_radiance, as for area lights: luminance = scale; the sum
      runs over the range the render integrates, so Le comes from the render).  An image texel
      with colour rgb has pbrt-v4's RGB illuminant spectrum
          S(lambda) = m sigmoid(c0 x^2 + c1 x + c2) D65(lambda),   m = 2 max(rgb),
      (spectrum.c section 11; x = (lambda - 360) / 470), divided like pbrt-v4 by
      the luminance of D65 (sum of ybar D65, 1 nm, over the rendered range, as for
      area lights), so a texel (1, 1, 1) has luminance 1, times scale: the factor
      k = scale / sum ybar D65 that inf_Le is given.  The lookup is the nearest texel (pbrt-v4
      ImageLe), so radiance is piecewise constant, like the sampling density.
      Coefficients come from a table over the two smaller components divided by
      2 max (a 33 x 33 grid per largest channel, filled on demand at load time,
      bilinearly interpolated: pbrt-v4 interpolates a precomputed table the same
      way), because a Newton fit per texel would take minutes for a large map.

   3. SAMPLING (pbrt-v4 ImageInfiniteLight: PiecewiseConstant2D over the mean of
      each texel's R, G, B).  A row y is chosen from the marginal CDF of the row
      sums, a column x from that row's CDF, and the point is uniform in the
      texel, so p(u, v) = w(x, y) res^2 / sum w, and the solid-angle pdf is that
      over 4 pi.  A map whose weights are all 0 (and a constant light) is sampled
      uniformly: pdf 1 / (4 pi).  The same numbers serve inf_pdf, so NEE and the
      MIS weight of an escaped ray agree (tested: the pdf integrates to 1 and the
      samples follow it, chi-square).

   The last section builds an infinite light from a scene's LightSource
   parameters for the scene builder (infinite_light_from_params, parser.h). */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ the map */

Vec3 equal_area_square_to_sphere(float u, float v)
{
    double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0, ap = fabs(a), bp = fabs(b);
    double sd = 1.0 - (ap + bp), r = 1.0 - fabs(sd);
    double phi = (r == 0.0 ? 1.0 : (bp - ap) / r + 1.0) * SPECNEE_PI / 4.0;
    double z = sd >= 0.0 ? 1.0 - r * r : -(1.0 - r * r);
    double k = r * sqrt(fmax(0.0, 2.0 - r * r));
    double x = k * cos(phi), y = k * sin(phi);
    return v3((float)(a < 0.0 ? -x : x), (float)(b < 0.0 ? -y : y), (float)z);
}

void equal_area_sphere_to_square(Vec3 d, float *u, float *v)
{
    double x = fabs(d.x), y = fabs(d.y), z = fabs(d.z);
    double r = sqrt(fmax(0.0, 1.0 - z));
    double phi = (x == 0.0 && y == 0.0) ? 0.0 : atan2(y, x) * 2.0 / SPECNEE_PI;  /* in [0, 1] */
    double vv = phi * r, uu = r - vv;
    if (d.z < 0.0f) {                    /* southern hemisphere: mirror across the diamond */
        double t = uu;
        uu = 1.0 - vv;
        vv = 1.0 - t;
    }
    if (d.x < 0.0f) uu = -uu;
    if (d.y < 0.0f) vv = -vv;
    *u = (float)(0.5 * (uu + 1.0));
    *v = (float)(0.5 * (vv + 1.0));
}

/* ------------------------------------------------------------------ texels */

#define COEF_GRID 32                     /* cells per axis of the coefficient table */

typedef struct {
    float c[3][COEF_GRID + 1][COEF_GRID + 1][3];
    unsigned char done[3][COEF_GRID + 1][COEF_GRID + 1];
    RgbTable *rgb;                       /* the fit's start (spec_rgb_coeffs) */
} CoefTable;

/* Coefficients at node (i, j) of the table for largest channel k. */
static const float *coef_node(CoefTable *t, int k, int i, int j)
{
    if (!t->done[k][i][j]) {
        double target[3], c[3];
        int m;
        target[k] = 0.5;
        target[(k + 1) % 3] = 0.5 * i / COEF_GRID;
        target[(k + 2) % 3] = 0.5 * j / COEF_GRID;
        spec_rgb_coeffs(t->rgb, target, c);
        for (m = 0; m < 3; m++) t->c[k][i][j][m] = (float)c[m];
        t->done[k][i][j] = 1;
    }
    return t->c[k][i][j];
}

/* out = (m, c0, c1, c2) for a non-negative rgb. */
static void texel_coeffs(CoefTable *t, const float rgb[3], float out[4])
{
    int k = 0, m, i0, j0;
    float mx, a, b, fa, fb;
    const float *c00, *c10, *c01, *c11;
    if (rgb[1] > rgb[k]) k = 1;
    if (rgb[2] > rgb[k]) k = 2;
    mx = rgb[k];
    out[0] = 2.0f * mx;
    out[1] = out[2] = out[3] = 0.0f;
    if (!(mx > 0.0f)) return;
    a = rgb[(k + 1) % 3] / mx * COEF_GRID;         /* in [0, COEF_GRID] */
    b = rgb[(k + 2) % 3] / mx * COEF_GRID;
    i0 = (int)a; if (i0 >= COEF_GRID) i0 = COEF_GRID - 1;
    j0 = (int)b; if (j0 >= COEF_GRID) j0 = COEF_GRID - 1;
    fa = a - (float)i0;
    fb = b - (float)j0;
    c00 = coef_node(t, k, i0, j0); c10 = coef_node(t, k, i0 + 1, j0);
    c01 = coef_node(t, k, i0, j0 + 1); c11 = coef_node(t, k, i0 + 1, j0 + 1);
    for (m = 0; m < 3; m++)
        out[1 + m] = (1 - fa) * (1 - fb) * c00[m] + fa * (1 - fb) * c10[m]
                   + (1 - fa) * fb * c01[m] + fa * fb * c11[m];
}

void inf_free(InfiniteLight *inf)
{
    if (!inf) return;
    free(inf->texel);
    free(inf->cdf_rows);
    free(inf->cdf_cols);
    free(inf->row_sum);
    free(inf);
}

int inf_set_image(InfiniteLight *inf, const Image *im, RgbTable *rgb, const char *file, int line,
                  Error *err)
{
    int n = im->w, x, y, c;
    CoefTable *tab;
    double acc;
    if (im->w != im->h) {
        error_set(err, file, line, "LightSource \"infinite\": image map %d x %d is not square: "
                  "pbrt-v4 needs its equal-area octahedral layout", im->w, im->h);
        return 0;
    }
    for (x = 0; x < 3 * n * n; x++)
        if (!isfinite(im->rgb[x])) {
            error_set(err, file, line, "LightSource \"infinite\": image map has a non-finite "
                      "value (pixel %d, %d)", (x / 3) % n, (x / 3) / n);
            return 0;
        }
    inf->res = n;
    inf->texel = (float *)malloc(sizeof(float) * 4 * (size_t)n * n);
    inf->cdf_rows = (float *)malloc(sizeof(float) * ((size_t)n + 1));
    inf->cdf_cols = (float *)malloc(sizeof(float) * (size_t)n * ((size_t)n + 1));
    inf->row_sum = (float *)malloc(sizeof(float) * (size_t)n);
    tab = (CoefTable *)calloc(1, sizeof *tab);
    if (!inf->texel || !inf->cdf_rows || !inf->cdf_cols || !inf->row_sum || !tab) {
        free(tab);
        error_set(err, file, line, "out of memory for a %d x %d image map", n, n);
        return 0;
    }
    tab->rgb = rgb;
    inf->weight_sum = 0.0;
    for (y = 0; y < n; y++) {
        float *cdf = inf->cdf_cols + (size_t)y * (n + 1);
        acc = 0.0;
        cdf[0] = 0.0f;
        for (x = 0; x < n; x++) {
            float rgb[3];
            for (c = 0; c < 3; c++) {
                rgb[c] = im->rgb[3 * ((size_t)y * n + x) + c];
                if (rgb[c] < 0.0f) rgb[c] = 0.0f;          /* pbrt-v4 ClampZero */
            }
            texel_coeffs(tab, rgb, inf->texel + 4 * ((size_t)y * n + x));
            acc += (rgb[0] + rgb[1] + rgb[2]) / 3.0;       /* the texel's weight */
            cdf[x + 1] = (float)acc;
        }
        for (x = 1; x <= n; x++) cdf[x] = acc > 0.0 ? (float)(cdf[x] / acc) : (float)x / n;
        cdf[n] = 1.0f;
        inf->row_sum[y] = (float)acc;
        inf->weight_sum += acc;
    }
    acc = 0.0;
    inf->cdf_rows[0] = 0.0f;
    for (y = 0; y < n; y++) {
        acc += inf->row_sum[y];
        inf->cdf_rows[y + 1] = inf->weight_sum > 0.0 ? (float)(acc / inf->weight_sum) : (float)(y + 1) / n;
    }
    inf->cdf_rows[n] = 1.0f;
    free(tab);
    return 1;
}

/* ------------------------------------------------------------------ radiance and pdf */

/* A world direction in the light's frame (the inverse CTM, normalised: pbrt-v4
   assumes a rotation). */
static Vec3 to_light(const InfiniteLight *inf, Vec3 d)
{
    const double (*m)[4] = inf->world_from_light.inv;
    return v3_norm(v3((float)(m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z),
                      (float)(m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z),
                      (float)(m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z)));
}

/* The direction in the light's frame, and the texel it falls in. */
static int texel_of(const Emitter *em, Vec3 dir, float *u, float *v)
{
    const InfiniteLight *inf = em->inf;
    Vec3 d = to_light(inf, dir);
    int x, y, n = inf->res;
    equal_area_sphere_to_square(d, u, v);
    if (n == 0) return -1;
    x = (int)(*u * n); if (x >= n) x = n - 1; if (x < 0) x = 0;
    y = (int)(*v * n); if (y >= n) y = n - 1; if (y < 0) y = 0;
    return y * n + x;
}

float inf_Le(const Emitter *em, const Spectrum *Le, double k, Vec3 dir, float lambda_nm)
{
    const InfiniteLight *inf = em->inf;
    float u, v, d65;
    const float *tx;
    int t;
    if (inf->res == 0) return spec_eval(Le, lambda_nm);
    t = texel_of(em, dir, &u, &v);
    tx = inf->texel + 4 * (size_t)t;
    if (tx[0] == 0.0f) return 0.0f;
    d65 = spec_eval(&em->L, lambda_nm);                 /* L holds D65 for a map */
    return (float)(k * tx[0] * spec_sigmoid_eval(tx + 1, lambda_nm) * d65);
}

float inf_pdf(const Emitter *em, Vec3 dir)
{
    const InfiniteLight *inf = em->inf;
    float u, v, w;
    int t, n = inf->res;
    if (n == 0 || !(inf->weight_sum > 0.0)) return (float)(1.0 / (4.0 * SPECNEE_PI));
    t = texel_of(em, dir, &u, &v);
    {
        int y = t / n, x = t % n;
        float *cdf = inf->cdf_cols + (size_t)y * (n + 1);
        w = (cdf[x + 1] - cdf[x]) * inf->row_sum[y];    /* the texel's weight, as sampled */
    }
    return (float)(w * (double)n * n / inf->weight_sum / (4.0 * SPECNEE_PI));
}

/* First index i in [0, n) with cdf[i + 1] > u (cdf has n + 1 entries). */
static int cdf_find(const float *cdf, int n, float u)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (cdf[mid + 1] <= u) lo = mid + 1; else hi = mid;
    }
    return lo;
}

int inf_sample(const Emitter *em, float u1, float u2, Vec3 *dir, float *pdf)
{
    const InfiniteLight *inf = em->inf;
    int n = inf->res;
    float u = u1, v = u2;
    if (n > 0 && inf->weight_sum > 0.0) {
        int y = cdf_find(inf->cdf_rows, n, u2), x;
        const float *cdf = inf->cdf_cols + (size_t)y * (n + 1);
        float dv = inf->cdf_rows[y + 1] - inf->cdf_rows[y], du;
        x = cdf_find(cdf, n, u1);
        du = cdf[x + 1] - cdf[x];
        /* remap the random numbers inside the chosen texel: uniform there */
        v = ((float)y + (dv > 0.0f ? (u2 - inf->cdf_rows[y]) / dv : 0.5f)) / (float)n;
        u = ((float)x + (du > 0.0f ? (u1 - cdf[x]) / du : 0.5f)) / (float)n;
        if (!(v < 1.0f)) v = ((float)y + 0.5f) / (float)n;
        if (!(u < 1.0f)) u = ((float)x + 0.5f) / (float)n;
    }
    *dir = v3_norm(xf_vector(&inf->world_from_light, equal_area_square_to_sphere(u, v)));
    *pdf = inf_pdf(em, *dir);
    return *pdf > 0.0f && isfinite(*pdf);
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   infinite_light_from_params: the scene builder's (scene.c) LightSource
   "infinite", read from its parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* LightSource "infinite": constant (L, scale, illuminance) or an
   image map (filename: a PFM in pbrt-v4's equal-area octahedral layout).  The
   CTM is the light's frame.  pbrt-v4's normalisation: L is divided by its
   luminance (an rgb L by D65's), a map's texels by D65's, so a constant light or
   a white texel has luminance scale; "illuminance" E_v (lux) then multiplies
   scale by E_v / k_e, k_e the illuminance the light would give an upward-facing
   point (+z of the light's frame) without it: pi for a constant light, and for a
   map pbrt-v4's sum over the upper hemisphere's texels of Y(rgb) cos(theta) 2 pi
   / res^2 (pbrt-v4 lights.cpp, reproduced as it is). */
int infinite_light_from_params(Parser *P, ParamList *pl, const char *file, int line,
                               Emitter *em)
{
    InfiniteLight *inf;
    Param *p, *portal;
    const char *fn = NULL;
    float scale, ev;
    int rgb_illum = 0, i;
    Spectrum L;
    p = find_spectrum_param(pl, "L");
    if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
    if (!get_float(P, pl, "illuminance", -1.0f, &ev)) return 0;
    if (!get_string(P, pl, "filename", &fn)) return 0;
    portal = param_find(pl, PT_POINT3, "portal");
    if (portal)
        return fail(P, portal->file, portal->line, "LightSource \"infinite\": \"point3 portal\" "
                    "is valid pbrt-v4 but not in the specnee subset");
    if (p && fn)
        return fail(P, file, line, "LightSource \"infinite\": cannot have both \"L\" and "
                    "\"filename\" (pbrt-v4)");
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &L, &rgb_illum)) return 0;
    } else if (!spec_named(&L, "stdillum-D65")) {
        return fail(P, file, line, "LightSource: the built-in spectrum stdillum-D65 is missing");
    }
    if (!params_check_unused(P, pl, "LightSource \"infinite\"",
                             "spectrum L, rgb L, blackbody L, float scale, float illuminance, "
                             "string filename", "portal"))
        return 0;
    if (!(scale >= 0.0f))
        return fail(P, file, line, "LightSource \"infinite\": \"float scale\" must be >= 0");
    note_not_positive(pl, "LightSource \"infinite\"", "illuminance", ev);
    for (i = 0; i < SPEC_N; i++)
        if (!(L.v[i] >= 0.0f))
            return fail(P, p ? p->file : file, p ? p->line : line,
                        "LightSource \"infinite\": L is negative at %d nm", SPEC_MIN + i);
    if (rgb_illum) scale = rgb_illuminant_scale(&L, scale);
    inf = (InfiniteLight *)calloc(1, sizeof *inf);
    if (!inf) return oom(P, file, line);
    inf->world_from_light = P->gs.ctm;
    inf->file = file;
    inf->line = line;
    if (fn) {
        char path[1024];
        Image im;
        Error ierr;
        double mean[3] = { 0, 0, 0 }, k_e = 0.0;
        float mrgb[3];
        int x, y, c;
        if (!ends_with_ci(fn, ".pfm") && !ends_with_ci(fn, ".exr")) {
            free(inf);
            return fail(P, file, line, "LightSource \"infinite\": \"%s\": specnee reads image "
                        "maps only as PFM or EXR (convert with pbrt-v4's `imgtool convert`)", fn);
        }
        resolve_path(P, file, fn, path, sizeof path);
        if (ends_with_ci(fn, ".exr") ? !exr_read(&im, path, &ierr) : !pfm_read(&im, path, &ierr)) {
            free(inf);
            return fail(P, file, line, "LightSource \"infinite\": %s", ierr.msg);
        }
        if (!inf_set_image(inf, &im, P->rgb, file, line, P->err)) {
            img_free(&im);
            inf_free(inf);
            return 0;
        }
        for (y = 0; y < im.h; y++)
            for (x = 0; x < im.w; x++) {
                const float *px = im.rgb + 3 * ((size_t)y * im.w + x);
                for (c = 0; c < 3; c++) mean[c] += px[c] > 0.0f ? px[c] : 0.0f;
                if (ev > 0.0f) {
                    Vec3 w = equal_area_square_to_sphere((x + 0.5f) / im.w, (y + 0.5f) / im.h);
                    if (w.z > 0.0f)                      /* sRGB's luminance row */
                        k_e += (0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]) * w.z;
                }
            }
        for (c = 0; c < 3; c++) mrgb[c] = (float)(mean[c] / ((double)im.w * im.h));
        k_e *= 2.0 * SPECNEE_PI / ((double)im.w * im.h);
        img_free(&im);
        if (!spec_from_rgb_t(P->rgb, &inf->mean, mrgb, 1, P->err, file, line)) {
            inf_free(inf);
            return 0;
        }
        if (ev > 0.0f) {
            if (!(k_e > 0.0)) {
                inf_free(inf);
                return fail(P, file, line, "LightSource \"infinite\": \"illuminance\" given, but "
                            "the map sends no light to the upper hemisphere");
            }
            scale = (float)(scale * ev / k_e);
        }
    } else if (ev > 0.0f) {
        scale = (float)(scale * ev / SPECNEE_PI);
    }
    memset(em, 0, sizeof *em);
    em->shape = -1;
    em->inf = inf;
    em->L = L;                   /* an image map: D65, the texels' illuminant */
    em->scale = scale;
    return 1;
}
