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
   exactly, from that sampler's own stream: filter_gaussian_reject, by cells and
   rejection);
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

static void gauss_cells(PixelFilter *pf);   /* the exact Gaussian's cells (below) */

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
    pf->gauss_ok = 0;
    if (pf->type == FILTER_GAUSSIAN) {
        gauss_cells(pf);                 /* the exact sampler of the independent stream */
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

/* ------------------------------------- the Gaussian from the independent stream

   With the independent sampler each camera sample has its own stream of random
   numbers (sampler.c), so the Gaussian f1(x) = g(x) - g(r) on [-r, r] can be drawn
   EXACTLY, by rejection, instead of from the table's midpoint rule.  Plain
   rejection from the box [-r, r] x [0, 1 - g(r)] accepts 41 % of its tries (sigma
   1/2, r 3/2) and pays an exp and two numbers for each.  Here the box is cut into
   cells fitted to the curve (the layered rejection behind Marsaglia and Tsang's
   ziggurat, 2000, with cells of equal width instead of equal area):

     1. f1 is even: draw |x| and a sign.  [0, r] is cut into K = FILTER_GAUSS_CELLS
        cells of width w = r / K; on cell c, [c w, (c + 1) w], f1 decreases, so
        lo_c <= f1(x) <= hi_c with hi_c its value at the inner edge and lo_c at the
        outer one (gauss_hi, gauss_lo: raised and lowered a little, so that they
        bound f1 as it is computed, in float).
     2. The cell c with probability hi_c / sum hi, in O(1) by Walker's alias method
        (Walker 1977, "An efficient method for generating discrete random variables
        with general distributions", ACM TOMS 3(3); Vose's construction, 1991,
        IEEE TSE 17(9)): a uniform cell i, kept if a uniform coin is below
        gauss_keep[i], else gauss_alias[i].
     3. x uniform in the cell, v uniform in [0, hi_c): accept if v < f1(x).  The
        squeeze v < lo_c accepts without the exp (most tries); else f1(x) is
        computed.  A rejected try starts again at 1.

   The accepted x has the density sum_c (hi_c / sum hi) (1 / w) (f1(x) / hi_c) on
   its cell = f1(x) / (w sum hi): f1 itself, normalised, whatever the cells; the
   cells only set the acceptance rate, integral f1 / (w sum hi), 0.98 for 64 cells.
   One try takes one 32-bit number (bit 31 the sign, bits 25..30 the cell i, bits
   0..24 the alias coin) and two 24-bit floats (the position and v).  After 64
   rejected tries (probability below 10^-100) the offset is 0. */

/* The alias table of FILTER_GAUSS_CELLS cells with weights q (Vose): cell i keeps
   the probability keep_i / 2^25 of its 1 / K slot and gives the rest to alias_i. */
static void gauss_alias(PixelFilter *pf, const double *q, double sum)
{
    enum { K = FILTER_GAUSS_CELLS };
    double p[K];
    int small[K], large[K], ns = 0, nl = 0, c;
    for (c = 0; c < K; c++) {
        p[c] = K * q[c] / sum;                   /* 1 on average */
        if (p[c] < 1.0) small[ns++] = c; else large[nl++] = c;
    }
    while (ns > 0 && nl > 0) {                   /* a small cell's slot, topped up by a large one */
        int sm = small[--ns], lg = large[--nl];
        pf->gauss_keep[sm] = (uint32_t)(p[sm] * 33554432.0 + 0.5);
        pf->gauss_alias[sm] = (unsigned char)lg;
        p[lg] = (p[lg] + p[sm]) - 1.0;
        if (p[lg] < 1.0) small[ns++] = lg; else large[nl++] = lg;
    }
    while (nl > 0) { c = large[--nl]; pf->gauss_keep[c] = 33554432u; pf->gauss_alias[c] = (unsigned char)c; }
    while (ns > 0) { c = small[--ns]; pf->gauss_keep[c] = 33554432u; pf->gauss_alias[c] = (unsigned char)c; }
}

/* The cells' bounds and alias table of a Gaussian filter (filter_init). */
static void gauss_cells(PixelFilter *pf)
{
    double r = pf->radius, k = 1.0 / (2.0 * (double)pf->sigma * pf->sigma), g_r, q[FILTER_GAUSS_CELLS], sum = 0.0;
    int c;
    pf->gauss_ok = 0;
    if (!(r > 0.0 && k > 0.0 && r < HUGE_VAL && k < HUGE_VAL)) return;
    pf->gauss_k = (float)k;
    pf->gauss_gr = expf(-pf->radius * pf->radius * pf->gauss_k);
    pf->gauss_w = pf->radius / (float)FILTER_GAUSS_CELLS;
    g_r = pf->gauss_gr;
    for (c = 0; c < FILTER_GAUSS_CELLS; c++) {
        double a = (double)c * pf->gauss_w, b = (double)(c + 1) * pf->gauss_w;
        double hi = exp(-a * a * k) - g_r, lo = exp(-b * b * k) - g_r;
        /* margins of 10^-4 relative and 10^-6 absolute: far above the float
           evaluation's error (a few 10^-7 of g, tested by filter_gauss_table) */
        pf->gauss_hi[c] = (float)(hi * (1.0 + 1e-4) + 1e-6);
        lo = lo * (1.0 - 1e-4) - 1e-6;
        pf->gauss_lo[c] = lo > 0.0 ? (float)lo : 0.0f;
        q[c] = pf->gauss_hi[c];
        sum += q[c];
    }
    if (!(sum > 0.0 && sum < HUGE_VAL)) return;
    gauss_alias(pf, q, sum);
    pf->gauss_ok = 1;
}

float filter_gaussian_reject(const PixelFilter *pf, Rng *rng)
{
    int tries;
    if (!pf->gauss_ok) return 0.0f;
    for (tries = 0; tries < 64; tries++) {
        const uint32_t b = rng_u32(rng);
        int c = (int)((b >> 25) & (FILTER_GAUSS_CELLS - 1));
        float x, v;
        if ((b & 0x1FFFFFFu) >= pf->gauss_keep[c]) c = pf->gauss_alias[c];
        x = ((float)c + rng_float(rng)) * pf->gauss_w;
        v = rng_float(rng) * pf->gauss_hi[c];
        if (v < pf->gauss_lo[c] || v < expf(-x * x * pf->gauss_k) - pf->gauss_gr)
            return (b >> 31) ? -x : x;
    }
    return 0.0f;
}
