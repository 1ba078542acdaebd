/* filter.c - pbrt-v4's pixel filters, and how a camera sample is drawn from them.

   Exported (specnee.h section 8): filter_init, filter_eval_1d, filter_eval,
   filter_sample, filter_gaussian_reject, filter_weighted, filter_name.

   WHAT A PIXEL FILTER MEANS.  A pixel's value is the image L seen through the
   filter f centred on the pixel:

       pixel = integral f(x) L(c + x) dx  /  integral f(x) dx

   pbrt-v4 estimates it by FILTER IMPORTANCE SAMPLING (Ernst et al. 2006): each
   camera sample of the pixel takes its offset x from a density p_f, carries the
   filter weight fw = f(x) / p_f(x), goes to its own pixel only, and the film keeps

       pixel = sum_k fw_k L_k / sum_k fw_k        (RGBFilm::AddSample, GetPixelRGB)

   a ratio of an estimate of the numerator and one of the denominator: consistent,
   and a flat image stays flat whatever the weights.  (Splatting each sample into
   every pixel it reaches would write a pixel from several threads.)
   - box, gaussian, triangle: p_f is proportional to f, so fw is a constant, which
     cancels in the ratio: specnee gives them fw = 1 and the pixel is the mean of
     its samples.
   - mitchell and sinc have negative lobes, so no density is proportional to f.
     pbrt-v4's FilterSampler tabulates f at the centres of int(32 r) cells per
     axis over [-r, r], draws the cell from |f_tab| and the point uniformly in it,
     and weights by fw = f_tab(cell) / p_f = sign(f_tab(cell)) * integral |f_tab|.  The
     sign survives: a sample in a negative lobe counts against the pixel, which is
     what makes these filters sharpen (and ring at edges), and E[fw] = integral f_tab
     (the midpoint rule for integral f).

   THE FILTERS (x, y: offsets in pixels from the pixel centre; every filter is
   separable, f(x, y) = f1(x) f1(y); defaults are pbrt-v4's, filters.cpp)
     box       f1 = 1 for |x| <= r                                   r = 0.5
     gaussian  f1 = max(0, g(x) - g(r)),  g(x) = exp(-x^2 / (2 sigma^2))
                                                                  r = 1.5, sigma = 0.5
     triangle  f1 = max(0, r - |x|)                                  r = 2
     mitchell  f1 = M(2x / r), the Mitchell-Netravali cubic (1988) on |t| <= 2:
                 6 M(t) = (12 - 9B - 6C)|t|^3 + (-18 + 12B + 6C)|t|^2 + (6 - 2B)   |t| <= 1
                 6 M(t) = (-B - 6C)|t|^3 + (6B + 30C)|t|^2 + (-12B - 48C)|t| + (8B + 24C)
                                                                     1 < |t| <= 2
                 (integral of M over [-2, 2] = 1 for every B, C)   r = 2, B = C = 1/3
     sinc      f1 = sinc(x) sinc(x / tau) for |x| <= r, sinc(x) = sin(pi x)/(pi x):
               Lanczos' windowed sinc                              r = 4, tau = 3
   The samplers per axis: box x = (2u - 1) r; triangle the inverse CDF of the tent;
   gaussian a table of FILTER_CELLS cells (or, with the independent sampler,
   rejection from that sampler's own stream: filter_gaussian_reject);
   mitchell and sinc pbrt-v4's table of int(32 r) cells.

   USE.  render.c: filter_init once per render from the SceneSettings, then per
   sample px, py = the sample's position in its pixel ([0, 1)^2 for box r = 1/2)
   and weight fw = filter_sample(pf, u0, u1, &px, &py); the film adds fw L and fw
   when filter_weighted(pf), else L (and divides by the sample count). */
#include "specnee.h"
#include <stdlib.h>

const char *filter_name(FilterType t)
{
    switch (t) {
    case FILTER_BOX: return "box";
    case FILTER_GAUSSIAN: return "gaussian";
    case FILTER_TRIANGLE: return "triangle";
    case FILTER_MITCHELL: return "mitchell";
    case FILTER_SINC: return "sinc";
    }
    return "?";
}

/* ---------------------------------------------------------------- evaluation */

/* The Mitchell-Netravali cubic M(t) of the header, t in [-2, 2] (0 beyond). */
static double mitchell_1d(double t, double B, double C)
{
    t = fabs(t);
    if (t <= 1.0)
        return ((12.0 - 9.0 * B - 6.0 * C) * t * t * t + (-18.0 + 12.0 * B + 6.0 * C) * t * t
                + (6.0 - 2.0 * B)) / 6.0;
    if (t <= 2.0)
        return ((-B - 6.0 * C) * t * t * t + (6.0 * B + 30.0 * C) * t * t
                + (-12.0 * B - 48.0 * C) * t + (8.0 * B + 24.0 * C)) / 6.0;
    return 0.0;
}

/* sin(pi x) / (pi x), 1 at 0 */
static double sinc(double x)
{
    double a = SPECNEE_PI * x;
    return fabs(a) < 1e-5 ? 1.0 - a * a / 6.0 : sin(a) / a;   /* Taylor near 0 */
}

double filter_eval_1d(const PixelFilter *pf, double x)
{
    double r = pf->radius, ax = fabs(x);
    if (ax > r) return 0.0;
    switch (pf->type) {
    case FILTER_BOX: return 1.0;
    case FILTER_GAUSSIAN: {
        double s2 = 2.0 * (double)pf->sigma * pf->sigma, g = exp(-x * x / s2) - exp(-r * r / s2);
        return g > 0.0 ? g : 0.0;
    }
    case FILTER_TRIANGLE: return r - ax;
    case FILTER_MITCHELL: return mitchell_1d(2.0 * x / r, pf->b, pf->c);
    case FILTER_SINC: return sinc(x) * sinc(x / pf->tau);
    }
    return 0.0;
}

double filter_eval(const PixelFilter *pf, double x, double y)
{
    return filter_eval_1d(pf, x) * filter_eval_1d(pf, y);
}

int filter_weighted(const PixelFilter *pf)
{
    return pf->type == FILTER_MITCHELL || pf->type == FILTER_SINC;
}

/* ---------------------------------------------------------------- the tables */

void filter_init(PixelFilter *pf, const SceneSettings *st)
{
    double sum = 0.0, f[FILTER_TABLE_MAX], acc[FILTER_TABLE_MAX + 1];
    int i;
    pf->type = st->filter;
    pf->radius = st->filter_radius;
    pf->sigma = st->filter_sigma;
    pf->b = st->filter_b;
    pf->c = st->filter_c;
    pf->tau = st->filter_tau;
    pf->n = 0;
    pf->m = 0;
    pf->abs_integral = 0.0;
    if (pf->type == FILTER_GAUSSIAN) {
        /* specnee's Gaussian table: FILTER_CELLS cells whatever the radius (mitchell
           and sinc take int(32 r)), g(x) - g(r) at each centre */
        double g_r = exp(-(double)pf->radius * pf->radius / (2.0 * pf->sigma * pf->sigma));
        pf->n = FILTER_CELLS;
        for (i = 0; i < FILTER_CELLS; i++) {
            double x = -pf->radius + 2.0 * pf->radius * (i + 0.5) / FILTER_CELLS;
            double g = exp(-x * x / (2.0 * pf->sigma * pf->sigma)) - g_r;
            f[i] = g > 0.0 ? g : 0.0;
        }
    } else if (filter_weighted(pf)) {
        /* pbrt-v4's FilterSampler: int(32 r) cells over [-r, r], f at the centres */
        pf->n = (int)(32.0f * pf->radius);
        if (pf->n < 1) pf->n = 1;
        if (pf->n > FILTER_TABLE_MAX) pf->n = FILTER_TABLE_MAX;
        for (i = 0; i < pf->n; i++)
            f[i] = filter_eval_1d(pf, -pf->radius + 2.0 * pf->radius * (i + 0.5) / pf->n);
    } else {
        return;                          /* box, triangle: sampled in closed form */
    }
    /* the CDF of |f_tab| (piecewise constant), and integral |f_tab| dx */
    acc[0] = 0.0;
    for (i = 0; i < pf->n; i++) {
        pf->f[i] = (float)f[i];
        sum += fabs(f[i]);
        acc[i + 1] = sum;
    }
    if (!(sum > 0.0 && sum < HUGE_VAL)) {
        /* f_tab is zero everywhere (mitchell with B = 3 and a tiny radius, say) or
           overflows: as pbrt-v4's PiecewiseConstant1D, a uniform table; the
           weights are then 0 (filter_sample), and so is the image */
        for (i = 0; i <= pf->n; i++) pf->cdf[i] = (float)i / (float)pf->n;
        pf->abs_integral = 0.0;
        pf->m = cdf_guide_size(pf->n);
        cdf_guide(pf->cdf, pf->n, pf->guide, pf->m);
        return;
    }
    for (i = 0; i <= pf->n; i++) pf->cdf[i] = (float)(acc[i] / sum);
    pf->cdf[pf->n] = 1.0f;
    pf->abs_integral = sum * 2.0 * pf->radius / pf->n;
    pf->m = cdf_guide_size(pf->n);
    cdf_guide(pf->cdf, pf->n, pf->guide, pf->m);
}

/* x = cdf^-1(u) in the table's CDF: the cell through the guide table (cdf_cell:
   cdf[lo] <= u < cdf[lo + 1], so cells of zero |f| are never chosen), uniform
   within it.  The offset in [-r, r]; *cell: the cell. */
static float table_sample(const PixelFilter *pf, float u, int *cell)
{
    int lo = cdf_cell(pf->cdf, pf->n, pf->guide, pf->m, (double)u);
    float t;
    t = pf->cdf[lo + 1] > pf->cdf[lo] ? (u - pf->cdf[lo]) / (pf->cdf[lo + 1] - pf->cdf[lo]) : 0.5f;
    *cell = lo;
    return pf->radius * (-1.0f + 2.0f * ((float)lo + t) / (float)pf->n);
}

/* The tent max(0, r - |x|) by its inverse CDF: the left or the right half with
   probability 1/2 each (u rescaled to [0, 1) again), then in the right half
   P(x) = 1 - (1 - x/r)^2, so x = r (1 - sqrt(1 - u)); the left half mirrors it. */
static float tent_sample(float u, float r)
{
    if (u < 0.5f) {
        u = 2.0f * u;
        return -r * (1.0f - sqrtf(u));       /* -r at u = 0, 0 at u -> 1 */
    }
    u = 2.0f * u - 1.0f;
    return r * (1.0f - sqrtf(1.0f - u));
}

float filter_sample(const PixelFilter *pf, float u0, float u1, float *px, float *py)
{
    int cx, cy;
    double qx, qy;
    switch (pf->type) {
    case FILTER_BOX:
        if (pf->radius == 0.5f) { *px = u0; *py = u1; }    /* the pixel itself, u unchanged
                                                              (no rounding of 0.5 + (2u - 1) r) */
        else { *px = 0.5f + (2.0f * u0 - 1.0f) * pf->radius; *py = 0.5f + (2.0f * u1 - 1.0f) * pf->radius; }
        return 1.0f;
    case FILTER_GAUSSIAN:
        *px = 0.5f + table_sample(pf, u0, &cx);
        *py = 0.5f + table_sample(pf, u1, &cy);
        return 1.0f;                     /* p_f ~ f_tab: a constant weight, cancelled */
    case FILTER_TRIANGLE:
        *px = 0.5f + tent_sample(u0, pf->radius);
        *py = 0.5f + tent_sample(u1, pf->radius);
        return 1.0f;
    case FILTER_MITCHELL:
    case FILTER_SINC:
        *px = 0.5f + table_sample(pf, u0, &cx);
        *py = 0.5f + table_sample(pf, u1, &cy);
        /* fw = f_tab / p_f with p_f = |f_tab| / integral |f_tab| per axis (qx, qy):
           the sign of the lobe times the integral (the fallback 0 cannot happen: a
           chosen cell has |f_tab| > 0) */
        if (!(pf->abs_integral > 0.0)) return 0.0f;  /* a filter that is zero everywhere */
        qx = fabs((double)pf->f[cx]) / pf->abs_integral;
        qy = fabs((double)pf->f[cy]) / pf->abs_integral;
        if (!(qx > 0.0 && qy > 0.0)) return 0.0f;
        return (float)((pf->f[cx] / qx) * (pf->f[cy] / qy));
    }
    *px = *py = 0.5f;
    return 0.0f;
}

/* One axis of the Gaussian, g(x) - g(radius), by rejection: the independent
   sampler's way (a variable count of numbers from its stream; at most 64 tries,
   then 0).  An offset in [-r, r]. */
float filter_gaussian_reject(Rng *rng, float radius, float sigma)
{
    float g_r = expf(-radius * radius / (2.0f * sigma * sigma));
    int tries;
    for (tries = 0; tries < 64; tries++) {
        float x = (2.0f * rng_float(rng) - 1.0f) * radius;
        float g = expf(-x * x / (2.0f * sigma * sigma)) - g_r;
        if (rng_float(rng) * (1.0f - g_r) < g) return x;
    }
    return 0.0f;
}
