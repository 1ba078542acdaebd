/* infinite.c - infinite lights: a constant environment, or an image map in
   pbrt-v4's equal-area octahedral layout, importance-sampled; either of them seen
   only through a portal (pbrt-v4's PortalImageInfiniteLight).

   Exported (specnee.h section 11): inf_Le, inf_pdf, inf_sample, inf_sees,
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
      (rgbfit.c; x = (lambda - 360) / 470), divided like pbrt-v4 by
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

   4. PORTALS (pbrt-v4 PortalImageInfiniteLight, lights.h/.cpp).  `"point3 portal"
      [p0 p1 p2 p3]` is a rectangle in world space (the CTM does not move it) with
      the frame s = (p3 - p0)/|.|, t = (p1 - p0)/|.|, n = s x t; n points to the
      sky.  A direction w with local coordinates (x, y, z), z > 0, gets the
      rectified coordinates
          u = atan2(x, z)/pi + 1/2,  v = atan2(y, z)/pi + 1/2,
      and back: with a = tan(pi (u - 1/2)), b = tan(pi (v - 1/2)), w = (a, b, 1)/r,
      r^2 = 1 + a^2 + b^2.  Since a = x/z, dw = da db / r^3 and da = pi (1 + a^2) du:
          dw/d(u, v) = pi^2 (1 + a^2)(1 + b^2) / r^3 = pi^2 (1 - x^2)(1 - y^2) / z.
      The lines u = const are lines of the portal's plane parallel to t, so a
      point o on the room side (z of every corner - o > 0) sees the portal as the
      rectangle W(o) of (u, v) between the coordinates of p0 and p2: light arrives
      at o along w only if (u, v) of w lies in W(o) (inf_sees; path.c asks it for
      an escaped ray from its origin).  pbrt-v4 resamples the map once onto a
      res x res grid of (u, v) (res: the map's), each texel the map's bilinear
      value (pixel centres at half-integers, its octahedral wrap) in the
      direction of the texel's centre taken to the light's frame; a constant L
      becomes a 1 x 1 map of its sRGB colour (XYZ through the sRGB matrix).  Le is
      the nearest rectified texel as an RGB illuminant spectrum (section 2, with
      D65's normalisation, not L's).
      Sampling (pbrt-v4's WindowedPiecewiseConstant2D): weights f = the texel's
      mean R, G, B times dw/d(u, v) at its centre, in a summed-area table whose
      bilinear interpolation is the exact integral F(u, v) of the piecewise-
      constant f.  From o: v by inverting the window's marginal F-differences
      (bisection over texel rows, then the straight line inside a row), u likewise
      inside the chosen row; p(u, v) = f / (integral of f over W(o)), and per
      steradian p(u, v) / (dw/d(u, v)).  inf_pdf gives the same for a direction in
      W(o), 0 outside, so NEE and the MIS weight of an escaped ray agree (tested:
      the pdf integrates to 1 over the portal's area, chi-square of the samples
      in cells of the portal).

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
    free(inf->sat);
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

/* ------------------------------------------------------------------ portals */

static Vec3 to_light(const InfiniteLight *inf, Vec3 d);

/* The rectified (u, v) of a world direction: alpha = atan2(x, z) and beta =
   atan2(y, z) in the portal's frame, u = alpha / pi + 1/2, v = beta / pi + 1/2;
   0 for a direction that does not point to the sky side (z <= 0). */
static int portal_uv(const InfiniteLight *inf, Vec3 dir, double *u, double *v)
{
    Vec3 w = frame_to_local(&inf->portal_frame, dir);
    if (!(w.z > 0.0f)) return 0;
    *u = fmin(1.0, fmax(0.0, atan2(w.x, w.z) / SPECNEE_PI + 0.5));
    *v = fmin(1.0, fmax(0.0, atan2(w.y, w.z) / SPECNEE_PI + 0.5));
    return 1;
}

/* The unit world direction of (u, v), and dw/d(u, v) there (section 4). */
static Vec3 portal_dir(const InfiniteLight *inf, double u, double v, double *jac)
{
    double a = tan((u - 0.5) * SPECNEE_PI), b = tan((v - 0.5) * SPECNEE_PI);
    double r = sqrt(1.0 + a * a + b * b);
    *jac = SPECNEE_PI * SPECNEE_PI * (1.0 + a * a) * (1.0 + b * b) / (r * r * r);
    return v3_norm(frame_to_world(&inf->portal_frame,
                                  v3((float)(a / r), (float)(b / r), (float)(1.0 / r))));
}

/* dw/d(u, v) of a unit world direction: pi^2 (1 - x^2)(1 - y^2) / z in the frame. */
static double portal_jacobian(const InfiniteLight *inf, Vec3 dir)
{
    Vec3 w = frame_to_local(&inf->portal_frame, dir);
    double x = w.x, y = w.y, z = w.z;
    if (!(z > 0.0)) return 0.0;
    return SPECNEE_PI * SPECNEE_PI * (1.0 - x * x) * (1.0 - y * y) / z;
}

/* The window [w0, w1] x [w2, w3] of (u, v) through which o sees the portal: the
   rectangle between the (u, v) of its corners 0 and 2 (pbrt-v4 ImageBounds); 0
   when o is on the sky side or in the portal's plane. */
static int portal_window(const InfiniteLight *inf, Vec3 o, double w[4])
{
    double ua, va, ub, vb;
    if (!portal_uv(inf, v3_norm(v3_sub(inf->portal_p[0], o)), &ua, &va)
        || !portal_uv(inf, v3_norm(v3_sub(inf->portal_p[2], o)), &ub, &vb)) return 0;
    w[0] = fmin(ua, ub); w[1] = fmax(ua, ub);
    w[2] = fmin(va, vb); w[3] = fmax(va, vb);
    return 1;
}

/* Texel x (or row) of the coordinate u, clamped to [0, n). */
static int cell_of(double u, int n)
{
    int x = (int)(u * n);
    return x < 0 ? 0 : x >= n ? n - 1 : x;
}

/* The rectified texel of dir (nearest, as pbrt-v4's lookup); -1 away from the sky. */
static int portal_texel(const InfiniteLight *inf, Vec3 dir)
{
    double u, v;
    if (!portal_uv(inf, dir, &u, &v)) return -1;
    return cell_of(v, inf->res) * inf->res + cell_of(u, inf->res);
}

/* F(u, v), the integral of the weights over [0, u] x [0, v]: the summed-area table
   interpolated bilinearly, which is exact for piecewise-constant weights. */
static double sat_at(const InfiniteLight *inf, double u, double v)
{
    int n = inf->res, i = cell_of(u, n), j = cell_of(v, n);
    double fx = u * n - i, fy = v * n - j;
    const double *S = inf->sat + (size_t)j * (n + 1) + i;
    return (1 - fy) * ((1 - fx) * S[0] + fx * S[1]) + fy * ((1 - fx) * S[n + 1] + fx * S[n + 2]);
}

/* The integral of the weights over [u0, u1] x [v0, v1]. */
static double sat_box(const InfiniteLight *inf, double u0, double u1, double v0, double v1)
{
    return sat_at(inf, u1, v1) - sat_at(inf, u0, v1) - sat_at(inf, u1, v0) + sat_at(inf, u0, v0);
}

/* The weight of texel t (the mean of its R, G, B times dw/d(u, v) at its centre),
   read back from the table. */
static double texel_weight(const InfiniteLight *inf, int x, int y)
{
    return sat_box(inf, (double)x / inf->res, (x + 1.0) / inf->res, (double)y / inf->res,
                   (y + 1.0) / inf->res) * inf->res * inf->res;
}

static float portal_pdf(const InfiniteLight *inf, Vec3 ref, Vec3 dir)
{
    double w[4], u, v, total, jac = portal_jacobian(inf, dir);
    int n = inf->res;
    if (!(jac > 0.0) || !portal_window(inf, ref, w) || !portal_uv(inf, dir, &u, &v)) return 0.0f;
    if (u < w[0] || u > w[1] || v < w[2] || v > w[3]) return 0.0f;
    total = sat_box(inf, w[0], w[1], w[2], w[3]);
    if (!(total > 0.0)) return 0.0f;
    return (float)(texel_weight(inf, cell_of(u, n), cell_of(v, n)) / total / jac);
}

/* The t in [lo, hi] where the increasing, piecewise-linear (breaks at the texel
   edges k / n) function c reaches target: bisection over the texels, then the
   straight line inside one.  c(t) = G(a, t) below: the integral over the window's
   other coordinate (fixed to [b0, b1]) from its start a up to t; along u (row j
   fixed) when along_u. */
static double invert_linear(const InfiniteLight *inf, int along_u, double a, double b0, double b1,
                            double lo, double hi, double target)
{
    int n = inf->res, k0 = cell_of(lo, n), k1 = cell_of(hi, n);
    double t0, t1, c0, c1;
    while (k0 < k1) {                  /* the first texel whose end passes target */
        int mid = (k0 + k1) / 2;
        double end = fmin(hi, (mid + 1.0) / n);
        double c = along_u ? sat_box(inf, a, end, b0, b1) : sat_box(inf, b0, b1, a, end);
        if (c > target) k1 = mid; else k0 = mid + 1;
    }
    t0 = fmax(lo, (double)k0 / n);
    t1 = fmin(hi, (k0 + 1.0) / n);
    c0 = along_u ? sat_box(inf, a, t0, b0, b1) : sat_box(inf, b0, b1, a, t0);
    c1 = along_u ? sat_box(inf, a, t1, b0, b1) : sat_box(inf, b0, b1, a, t1);
    if (!(c1 > c0)) return 0.5 * (t0 + t1);
    return fmin(t1, fmax(t0, t0 + (target - c0) / (c1 - c0) * (t1 - t0)));
}

/* pbrt-v4's windowed piecewise-constant sampling: v from the window's marginal
   over rows, then u from the chosen row inside the window; the density in (u, v)
   is weight / (the window's integral), divided by dw/d(u, v) per steradian. */
static int portal_sample(const InfiniteLight *inf, Vec3 ref, float u1, float u2, Vec3 *dir,
                         float *pdf)
{
    double w[4], total, u, v, jac;
    int n = inf->res, j;
    if (!portal_window(inf, ref, w)) return 0;
    total = sat_box(inf, w[0], w[1], w[2], w[3]);
    if (!(total > 0.0)) return 0;
    v = invert_linear(inf, 0, w[2], w[0], w[1], w[2], w[3], u2 * total);
    j = cell_of(v, n);
    {   /* the row's share of the window: u inside texel row j */
        double r0 = fmax(w[2], (double)j / n), r1 = fmin(w[3], (j + 1.0) / n);
        double row = sat_box(inf, w[0], w[1], r0, r1);
        if (!(row > 0.0) || !(r1 > r0)) return 0;
        u = invert_linear(inf, 1, w[0], r0, r1, w[0], w[1], u1 * row);
    }
    *dir = portal_dir(inf, u, v, &jac);
    *pdf = portal_pdf(inf, ref, *dir);
    return *pdf > 0.0f && isfinite(*pdf);
}

/* Image value of channel c at pixel (x, y) after pbrt-v4's octahedral wrap
   (a pixel beyond an edge is mirrored across it and across the other axis's
   middle: the equal-area square folds that way onto the sphere). */
static float octa_pixel(const Image *im, int x, int y, int c)
{
    int n = im->w;
    if (x < 0) { x = -x; y = n - 1 - y; }
    else if (x >= n) { x = 2 * n - 1 - x; y = n - 1 - y; }
    if (y < 0) { x = n - 1 - x; y = -y; }
    else if (y >= n) { x = n - 1 - x; y = 2 * n - 1 - y; }
    if (n == 1) x = y = 0;
    return im->rgb[3 * ((size_t)y * n + x) + c];
}

/* pbrt-v4's bilinear lookup (pixel centres at half-integers) with that wrap. */
static float octa_bilerp(const Image *im, float u, float v, int c)
{
    float x = u * im->w - 0.5f, y = v * im->h - 0.5f;
    int xi = (int)floorf(x), yi = (int)floorf(y);
    float dx = x - (float)xi, dy = y - (float)yi;
    return (1 - dx) * (1 - dy) * octa_pixel(im, xi, yi, c) + dx * (1 - dy) * octa_pixel(im, xi + 1, yi, c)
         + (1 - dx) * dy * octa_pixel(im, xi, yi + 1, c) + dx * dy * octa_pixel(im, xi + 1, yi + 1, c);
}

/* The portal's texels: the equal-area map im resampled at the centre of each
   rectified texel (its direction taken into the light's frame), as pbrt-v4 does
   when it makes the light; then the summed-area table of the weights. */
static int portal_set_image(InfiniteLight *inf, const Image *im, RgbTable *rgb, const char *file,
                            int line, Error *err)
{
    int n = im->w, x, y, c;
    Image rect;
    if (im->w != im->h) return inf_set_image(inf, im, rgb, file, line, err);  /* its message */
    if (!img_alloc(&rect, n, n) ||
        !(inf->sat = (double *)calloc(((size_t)n + 1) * ((size_t)n + 1), sizeof(double)))) {
        if (rect.rgb) img_free(&rect);
        error_set(err, file, line, "out of memory for a %d x %d image map", n, n);
        return 0;
    }
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            double jac;
            float eu, ev;
            Vec3 d = to_light(inf, portal_dir(inf, (x + 0.5) / n, (y + 0.5) / n, &jac));
            equal_area_sphere_to_square(d, &eu, &ev);
            for (c = 0; c < 3; c++) rect.rgb[3 * ((size_t)y * n + x) + c] = octa_bilerp(im, eu, ev, c);
        }
    if (!inf_set_image(inf, &rect, rgb, file, line, err)) { img_free(&rect); return 0; }
    free(inf->cdf_rows); free(inf->cdf_cols); free(inf->row_sum);   /* section 3's, unused here */
    inf->cdf_rows = inf->cdf_cols = inf->row_sum = NULL;
    for (y = 0; y < n; y++) {
        double *S = inf->sat + (size_t)(y + 1) * (n + 1), row = 0.0;
        for (x = 0; x < n; x++) {
            const float *px = rect.rgb + 3 * ((size_t)y * n + x);
            double jac, mean = 0.0;
            (void)portal_dir(inf, (x + 0.5) / n, (y + 0.5) / n, &jac);
            for (c = 0; c < 3; c++) mean += px[c] > 0.0f ? px[c] / 3.0 : 0.0;
            row += mean * jac / ((double)n * n);
            S[x + 1] = S[x + 1 - (n + 1)] + row;
        }
    }
    img_free(&rect);
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
    t = inf->portal ? portal_texel(inf, dir) : texel_of(em, dir, &u, &v);
    if (t < 0) return 0.0f;
    tx = inf->texel + 4 * (size_t)t;
    if (tx[0] == 0.0f) return 0.0f;
    d65 = spec_eval(em->L, lambda_nm);                 /* L holds D65 for a map */
    return (float)(k * tx[0] * spec_sigmoid_eval(tx + 1, lambda_nm) * d65);
}

float inf_pdf(const Emitter *em, Vec3 ref, Vec3 dir)
{
    const InfiniteLight *inf = em->inf;
    float u, v, w;
    int t, n = inf->res;
    if (inf->portal) return portal_pdf(inf, ref, dir);
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

int inf_sample(const Emitter *em, Vec3 ref, float u1, float u2, Vec3 *dir, float *pdf)
{
    const InfiniteLight *inf = em->inf;
    int n = inf->res;
    float u = u1, v = u2;
    if (inf->portal) return portal_sample(inf, ref, u1, u2, dir, pdf);
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
    *pdf = inf_pdf(em, ref, *dir);
    return *pdf > 0.0f && isfinite(*pdf);
}

int inf_sees(const Emitter *em, Vec3 o, Vec3 dir)
{
    double w[4], u, v;
    if (!em->inf->portal) return 1;
    return portal_window(em->inf, o, w) && portal_uv(em->inf, dir, &u, &v)
        && u >= w[0] && u <= w[1] && v >= w[2] && v <= w[3];
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   infinite_light_from_params: the scene builder's (scene.c) LightSource
   "infinite", read from its parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* "point3 portal": four corners in world space (pbrt-v4 applies no CTM to them),
   which must make a rectangle (pbrt-v4's own test: opposite edges parallel and
   adjacent ones perpendicular, within 0.001 in their cosines; pbrt-v4 only
   complains about another quad and renders it with a frame that is no longer
   orthonormal, so it is refused here).  The frame: s = p3 - p0, t = p1 - p0,
   n = s x t (pbrt-v4 Frame::FromXY). */
static int portal_params(Parser *P, const Param *pp, InfiniteLight *inf)
{
    Vec3 e01, e12, e32, e03;
    int i;
    if (pp->n_num != 12)
        return fail(P, pp->file, pp->line, "LightSource \"infinite\": \"point3 portal\" needs 4 "
                    "points (12 numbers), not %d numbers", pp->n_num);
    for (i = 0; i < 4; i++)
        inf->portal_p[i] = v3((float)pp->num[3 * i], (float)pp->num[3 * i + 1], (float)pp->num[3 * i + 2]);
    e01 = v3_sub(inf->portal_p[1], inf->portal_p[0]);
    e12 = v3_sub(inf->portal_p[2], inf->portal_p[1]);
    e32 = v3_sub(inf->portal_p[2], inf->portal_p[3]);
    e03 = v3_sub(inf->portal_p[3], inf->portal_p[0]);
    if (!(v3_len(e01) > 0.0f && v3_len(e12) > 0.0f && v3_len(e32) > 0.0f && v3_len(e03) > 0.0f))
        return fail(P, pp->file, pp->line, "LightSource \"infinite\": \"point3 portal\" has two "
                    "equal corners");
    e01 = v3_norm(e01); e12 = v3_norm(e12); e32 = v3_norm(e32); e03 = v3_norm(e03);
    if (fabsf(v3_dot(e01, e32) - 1.0f) > 0.001f || fabsf(v3_dot(e12, e03) - 1.0f) > 0.001f
        || fabsf(v3_dot(e01, e12)) > 0.001f || fabsf(v3_dot(e12, e32)) > 0.001f
        || fabsf(v3_dot(e32, e03)) > 0.001f || fabsf(v3_dot(e03, e01)) > 0.001f)
        return fail(P, pp->file, pp->line, "LightSource \"infinite\": \"point3 portal\" is not a "
                    "rectangle (corners in order around it); pbrt-v4 renders other quads with a "
                    "distorted frame, which is not in the specnee subset");
    inf->portal = 1;
    inf->portal_frame.s = e03;
    inf->portal_frame.t = e01;
    inf->portal_frame.n = v3_cross(e03, e01);
    return 1;
}

/* A portal light with a constant L: pbrt-v4 converts L to sRGB (its XYZ, 1-nm
   sums over 360-830 nm / sum ybar, through the sRGB matrix) and makes a 1 x 1
   image of it; the light then is an image light (texels with D65). */
static int portal_constant_image(const Spectrum *L, int rgb_illum, const char *file, int line,
                                 Image *im)
{
    double xyz[3], rgb[3];
    int c;
    if (!img_alloc(im, 1, 1)) return 0;
    spec_to_xyz(L, (float)SPEC_MIN, (float)SPEC_MAX, xyz);
    xyz_to_linear_srgb(xyz, rgb);
    for (c = 0; c < 3; c++) im->rgb[c] = (float)rgb[c];
    if (!rgb_illum)
        fprintf(stderr, "%s:%d: note: LightSource \"infinite\": a portal light's L is converted to "
                "RGB (%.4g %.4g %.4g), as pbrt-v4 does\n", file, line, rgb[0], rgb[1], rgb[2]);
    return 1;
}

/* LightSource "infinite": constant (L, scale, illuminance) or an
   image map (filename: a PFM in pbrt-v4's equal-area octahedral layout).  The
   CTM is the light's frame.  pbrt-v4's normalisation: L is divided by its
   luminance (an rgb L by D65's), a map's texels by their colour space's white's
   (sRGB's D65 for a PFM; an EXR's space is its chromaticities', exr.c, each
   texel then fitted in that space and lit by that white), so a constant light or
   a white texel has luminance scale; "illuminance" E_v (lux) then multiplies
   scale by E_v / k_e, k_e the illuminance the light would give an upward-facing
   point (+z of the light's frame) without it: pi for a constant light, and for a
   map pbrt-v4's sum over the upper hemisphere's texels of Y(rgb) cos(theta) 2 pi
   / res^2 (pbrt-v4 lights.cpp, reproduced as it is).  With a "portal", L makes a
   1 x 1 map (portal_constant_image), and the map (that one or the file's) is
   resampled for the portal; both L and filename: the file, as in pbrt-v4. */
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
    if (p && fn && !portal)
        return fail(P, file, line, "LightSource \"infinite\": cannot have both \"L\" and "
                    "\"filename\" (pbrt-v4)");
    if (portal && !p && !fn)
        return fail(P, portal->file, portal->line, "LightSource \"infinite\": a \"portal\" needs "
                    "\"L\" or \"filename\" (pbrt-v4 has no default for it)");
    if (portal && p && P->gs.colorspace != COLORSPACE_SRGB)
        return fail(P, file, line, "LightSource \"infinite\": a \"portal\" with \"L\" in ColorSpace "
                    "\"%s\" is not in the specnee subset (only in \"srgb\")",
                    colorspace_name(P->gs.colorspace));
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &L, &rgb_illum)) return 0;
    } else {
        space_white(P, &L);                    /* the colour space's illuminant */
    }
    if (!params_check_unused(P, pl, "LightSource \"infinite\"",
                             "spectrum L, rgb L, blackbody L, float scale, float illuminance, "
                             "string filename, point3 portal", NULL))
        return 0;
    if (!(scale >= 0.0f))
        return fail(P, file, line, "LightSource \"infinite\": \"float scale\" must be >= 0");
    note_not_positive(pl, "LightSource \"infinite\"", "illuminance", ev);
    for (i = 0; i < SPEC_N; i++)
        if (!(L.v[i] >= 0.0f))
            return fail(P, p ? p->file : file, p ? p->line : line,
                        "LightSource \"infinite\": L is negative at %d nm", SPEC_MIN + i);
    if (rgb_illum && !portal) scale = rgb_illuminant_scale(P, &L, scale);
    inf = (InfiniteLight *)calloc(1, sizeof *inf);
    if (!inf) return oom(P, file, line);
    inf->world_from_light = P->gs.ctm;
    inf->file = file;
    inf->line = line;
    if (portal && !portal_params(P, portal, inf)) { free(inf); return 0; }
    if (fn || portal) {
        char path[PATH_CAP];
        Image im;
        Error ierr;
        double mean[3] = { 0, 0, 0 }, k_e = 0.0, lum[3];
        float mrgb[3];
        int x, y, c, space = COLORSPACE_SRGB;   /* the map's colour space */
        RgbTable *table;
        if (!fn) {
            if (!portal_constant_image(&L, rgb_illum, file, line, &im)) { free(inf); return oom(P, file, line); }
            if (!spec_named(&L, "stdillum-D65")) {
                img_free(&im);
                free(inf);
                return fail(P, file, line, "LightSource: the built-in spectrum stdillum-D65 is missing");
            }
        } else if (!ends_with_ci(fn, ".pfm") && !ends_with_ci(fn, ".exr")) {
            free(inf);
            return fail(P, file, line, "LightSource \"infinite\": \"%s\": specnee reads image "
                        "maps only as PFM or EXR (convert with pbrt-v4's `imgtool convert`)", fn);
        } else {
            resolve_path(P, file, fn, path, sizeof path);
            if (ends_with_ci(fn, ".exr") ? !read_exr_image(path, "LightSource \"infinite\"", file, line,
                                                            &im, &space, &ierr)
                                         : !pfm_read(&im, path, &ierr)) {
                free(inf);
                return fail(P, file, line, "LightSource \"infinite\": %s", ierr.msg);
            }
            /* the texels' illuminant is the map's space's white (pbrt-v4's
               RGBIlluminantSpectrum(*imageColorSpace, rgb)), whatever L was */
            colorspace_illuminant(space, &L);
        }
        table = rgb_space_table(P, space);
        if (!table) { img_free(&im); free(inf); return oom(P, file, line); }
        if (!(portal ? portal_set_image(inf, &im, table, file, line, P->err)
                     : inf_set_image(inf, &im, table, file, line, P->err))) {
            img_free(&im);
            inf_free(inf);
            return 0;
        }
        colorspace_luminance(space, lum);
        for (y = 0; y < im.h; y++)
            for (x = 0; x < im.w; x++) {
                const float *px = im.rgb + 3 * ((size_t)y * im.w + x);
                for (c = 0; c < 3; c++) mean[c] += px[c] > 0.0f ? px[c] : 0.0f;
                if (ev > 0.0f) {
                    Vec3 w = equal_area_square_to_sphere((x + 0.5f) / im.w, (y + 0.5f) / im.h);
                    if (w.z > 0.0f)                      /* the space's luminance row */
                        k_e += (lum[0] * px[0] + lum[1] * px[1] + lum[2] * px[2]) * w.z;
                }
            }
        for (c = 0; c < 3; c++) mrgb[c] = (float)(mean[c] / ((double)im.w * im.h));
        k_e *= 2.0 * SPECNEE_PI / ((double)im.w * im.h);
        img_free(&im);
        if (!spec_from_rgb_t(table, &inf->mean, mrgb, 1, P->err, file, line)) {
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
    em->L = spec_store_add(&P->s->spectra, &L);   /* an image map: its space's white, the texels' illuminant */
    if (!em->L) { inf_free(inf); em->inf = NULL; return fail(P, file, line, "out of memory"); }
    em->scale = scale;
    return 1;
}
