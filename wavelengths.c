/* wavelengths.c - wavelength sampling for hero wavelength spectral sampling.

   WHAT IT IMPLEMENTS
     The four wavelengths of a path (Wilkie et al. 2014) with the rotation done in
     CDF space (continuous MIS, West et al. 2020; the same as pbrt-v4's
     SampleVisible):
         lambda_j = cdf^-1(frac(u + j / HERO_N)),  pdf_j = p(lambda_j),  j = 0..3,
     so each lambda_j is distributed as p and the four are stratified in cdf
     (THEORY §2, docs/wavelengths.md).  p is one of
       uniform     over the sampled range (plain HWSS, the thesis);
       importance  tabulated per 1 nm cell ~ (xbar + ybar + zbar) x the emitters'
                   spectra, with a floor of 1 % of the mean cell;
       visible     the scene-independent sech^2 pdf of Radziszewski et al. 2009
                   (pbrt-v4's), with an exact inverse CDF;
       mixture     the defensive mixture (1 - mu) importance + mu visible.

   EXPORTS (specnee.h section 4, "Wavelength sampling")
     wl_pdf_uniform wl_pdf_importance wl_pdf_visible wl_pdf_mixture wl_pdf_build
     wl_pdf_free wl_sample wl_pdf_eval wl_cdf wl_mode_from_name wl_mode_name

   HOW IT IS USED
     render.c builds one WavelengthPdf per render with wl_pdf_build (the emitters'
     summed spectrum for importance and mixture) and draws the four wavelengths of
     each sample with wl_sample; wl_pdf_eval evaluates p;
     specnee.c and converge's variants (cmd_converge.c) name the modes with
     wl_mode_from_name.  The colour-matching functions come from spectrum.c
     (cie_cmf).  Tests: tests/test_wavelengths.c and tests/test_spectrum.c. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

/* The scene-independent "visible wavelengths" pdf, a squared hyperbolic secant
   fitted to the CIE luminous efficiency curve:
       p(lambda) ~ sech^2(kappa (lambda - c)),   kappa = 0.0072 / nm,  c = 538 nm.
   Shape and constants: Radziszewski, Boryczko & Alda 2009, "An improved technique
   for full spectral rendering", Journal of WSCG 17, as used by pbrt-v4
   (src/pbrt/util/sampling.h, VisibleWavelengthsPDF / SampleVisibleWavelengths,
   over 360-830 nm).  Since d/dx tanh(x) = sech^2(x), on the sampled range
   [lo, hi] (specnee renormalises to its own range instead of pbrt's 360-830):
       p(lambda)   = kappa sech^2(kappa (lambda - c)) / (th(hi) - th(lo)),
                     th(x) = tanh(kappa (x - c))   (vis_T; kappa is WL_VIS_A)
       cdf(lambda) = (th(lambda) - th(lo)) / (th(hi) - th(lo))
       cdf^-1(u)   = c + atanh(th(lo) + u (th(hi) - th(lo))) / kappa      (exact) */
#define WL_VIS_A 0.0072
#define WL_VIS_C 538.0
static double vis_T(double lambda) { return tanh(WL_VIS_A * (lambda - WL_VIS_C)); }

WlMode wl_mode_from_name(const char *name)
{
    static const char *const names[WL_MODE_COUNT] = { "uniform", "importance", "visible", "mixture" };
    int i;
    for (i = 0; i < WL_MODE_COUNT; i++)
        if (name && !strcmp(name, names[i])) return (WlMode)i;
    return WL_MODE_COUNT;
}

const char *wl_mode_name(WlMode m)
{
    switch (m) {
    case WL_UNIFORM: return "uniform";
    case WL_IMPORTANCE: return "importance";
    case WL_VISIBLE: return "visible";
    case WL_MIXTURE: return "mixture";
    default: return "?";
    }
}

void wl_pdf_uniform(WavelengthPdf *w, float lo, float hi)
{
    w->lo = lo;
    w->hi = hi;
    w->n = 0;
    w->pdf = NULL;
    w->cdf = NULL;
    w->guide = NULL;
    w->m = 0;
    w->h = 0.0;
    w->visible = 0;
    w->vis_t_lo = w->vis_t_span = 0.0;
}

int wl_pdf_visible(WavelengthPdf *w, float lo, float hi)
{
    wl_pdf_uniform(w, lo, hi);
    if (!isfinite(lo) || !isfinite(hi) || !(hi > lo)) return 0;
    w->visible = 1;
    w->vis_t_lo = vis_T(lo);                      /* computed once: wl_sample and */
    w->vis_t_span = vis_T(hi) - w->vis_t_lo;      /* wl_pdf_eval run per sample */
    return 1;
}

/* The importance weights of n cells of width h from lo:
       f_k = mean over cell k of (xbar + ybar + zbar)(lambda) * emission(lambda)
   (Simpson's rule, exact here: on 1 nm cells both factors are linear, so their
   product is a quadratic), then f_k = max(f_k, 0.01 * mean f).  The floor keeps the
   pdf positive wherever the CMFs are (everywhere in 360..830 nm), so the estimator
   stays unbiased for any scene, at the price of at most 1 % of the samples.
   emission == NULL means 1.  An all-zero product gives equal cells. */
static void importance_cells(double lo, double h, int n, const Spectrum *emission, double *f)
{
    double sum = 0.0, mean, floor_f;
    int k;
    for (k = 0; k < n; k++) {
        double a = lo + k * h, b = a + h, m = 0.5 * (a + b), fa, fm, fb, c[3];
        cie_cmf(a, c); fa = c[0] + c[1] + c[2];
        cie_cmf(m, c); fm = c[0] + c[1] + c[2];
        cie_cmf(b, c); fb = c[0] + c[1] + c[2];
        if (emission) {
            fa *= spec_eval(emission, (float)a);
            fm *= spec_eval(emission, (float)m);
            fb *= spec_eval(emission, (float)b);
        }
        f[k] = (fa + 4.0 * fm + fb) / 6.0;
        if (!(f[k] > 0.0)) f[k] = 0.0;           /* negative or NaN emission */
        sum += f[k];
    }
    mean = sum / n;
    floor_f = (mean > 0.0 && isfinite(mean)) ? 0.01 * mean : 1.0;
    for (k = 0; k < n; k++) {
        if (!(mean > 0.0) || !isfinite(mean)) f[k] = 1.0;
        else if (f[k] < floor_f) f[k] = floor_f;
    }
}

/* A piecewise-constant pdf on cells of (about) 1 nm over [lo, hi] with cell
   weights from importance_cells, optionally mixed with the visible pdf:
       prob_k = (1 - mu) f_k / sum f + mu (th(b_k) - th(a_k)) / (th(hi) - th(lo)),  mu = mix
   (the visible pdf's exact mass on the cell [a_k, b_k], so the visible part enters
   cell-averaged: its inverse CDF within a cell becomes linear, the table's).
   The density per nm is prob_k / h; cdf[] accumulates prob_k. */
static int wl_pdf_table(WavelengthPdf *w, float lo, float hi, const Spectrum *emission, double mix)
{
    double h, sum = 0.0, acc = 0.0, *f, t_lo, t_span;
    int n, k;
    wl_pdf_uniform(w, lo, hi);
    if (!isfinite(lo) || !isfinite(hi) || !(hi > lo) || !(mix >= 0.0 && mix <= 1.0)) return 0;
    n = (int)ceil((double)hi - lo - 1e-4);
    if (n < 1) n = 1;
    if (n > 100000) return 0;
    h = ((double)hi - lo) / n;
    f = (double *)malloc((size_t)n * sizeof *f);
    w->pdf = (float *)malloc((size_t)n * sizeof *w->pdf);
    w->cdf = (float *)malloc((size_t)(n + 1) * sizeof *w->cdf);
    if (!f || !w->pdf || !w->cdf) { free(f); wl_pdf_free(w); wl_pdf_uniform(w, lo, hi); return 0; }
    importance_cells(lo, h, n, emission, f);
    for (k = 0; k < n; k++) sum += f[k];
    if (mix > 0.0) {                              /* f_k becomes prob_k, summing to 1 */
        t_lo = vis_T(lo);
        t_span = vis_T(hi) - t_lo;
        for (k = 0; k < n; k++) {
            double a = lo + k * h, b = (k == n - 1) ? (double)hi : a + h;
            f[k] = (1.0 - mix) * f[k] / sum + mix * (vis_T(b) - vis_T(a)) / t_span;
        }
        sum = 1.0;
    }
    w->n = n;
    w->cdf[0] = 0.0f;
    for (k = 0; k < n; k++) {
        w->pdf[k] = (float)(f[k] / (sum * h));    /* density per nm */
        acc += f[k];
        w->cdf[k + 1] = (float)(acc / sum);
    }
    w->cdf[n] = 1.0f;
    free(f);
    w->h = h;                                     /* the same double wl_sample and wl_pdf_eval computed */
    w->m = cdf_guide_size(n);
    w->guide = (int *)malloc((size_t)(w->m + 1) * sizeof *w->guide);
    if (w->guide) cdf_guide(w->cdf, n, w->guide, w->m);   /* without it wl_sample searches all cells */
    return 1;
}

int wl_pdf_importance(WavelengthPdf *w, float lo, float hi, const Spectrum *emission)
{
    return wl_pdf_table(w, lo, hi, emission, 0.0);
}

/* The defensive mixture (Hesterberg 1995, "Weighted average importance sampling
   and defensive mixture distributions", Technometrics 37): wherever the emitters'
   spectra mislead the importance pdf, p >= mix x p_visible still holds, which
   bounds the second moment of every estimate by 1 / mix times that of the visible
   pdf (docs/wavelengths.md). */
int wl_pdf_mixture(WavelengthPdf *w, float lo, float hi, const Spectrum *emission, float mix)
{
    return wl_pdf_table(w, lo, hi, emission, (double)mix);
}

int wl_pdf_build(WavelengthPdf *w, WlMode mode, float lo, float hi, const Spectrum *emission,
                 float mix)
{
    switch (mode) {
    case WL_UNIFORM:
        wl_pdf_uniform(w, lo, hi);
        return isfinite(lo) && isfinite(hi) && hi > lo;
    case WL_IMPORTANCE: return wl_pdf_importance(w, lo, hi, emission);
    case WL_VISIBLE: return wl_pdf_visible(w, lo, hi);
    case WL_MIXTURE: return wl_pdf_mixture(w, lo, hi, emission, mix > 0.0f ? mix : WL_MIX_DEFAULT);
    default: wl_pdf_uniform(w, lo, hi); return 0;
    }
}

void wl_pdf_free(WavelengthPdf *w)
{
    free(w->pdf);
    free(w->cdf);
    free(w->guide);
    w->pdf = NULL;
    w->cdf = NULL;
    w->guide = NULL;
    w->n = 0;
}

/* The table's density at lambda in [lo, hi]: the cell (int)((lambda - lo) / h),
   the last one closed.  wl_pdf_eval and wl_sample share it. */
static float table_pdf(const WavelengthPdf *w, float lambda_nm)
{
    int k = (int)(((double)lambda_nm - w->lo) / w->h);
    if (k >= w->n) k = w->n - 1;
    if (k < 0) k = 0;
    return w->pdf[k];
}

/* p(lambda): 0 outside [lo, hi]; inside the uniform density, the visible formula or
   the cell's density (the last cell is closed). */
float wl_pdf_eval(const WavelengthPdf *w, float lambda_nm)
{
    if (!(lambda_nm >= w->lo) || !(lambda_nm <= w->hi) || !(w->hi > w->lo)) return 0.0f;
    if (w->n == 0 && w->visible) {
        double ch = cosh(WL_VIS_A * ((double)lambda_nm - WL_VIS_C));
        return (float)(WL_VIS_A / (ch * ch) / w->vis_t_span);
    }
    if (w->n == 0) return (float)(1.0 / ((double)w->hi - w->lo));
    return table_pdf(w, lambda_nm);
}

/* cdf(lambda) = the probability of a wavelength below lambda. */
double wl_cdf(const WavelengthPdf *w, float lambda_nm)
{
    double x = lambda_nm, range = (double)w->hi - w->lo, h, cell;
    int k;
    if (!(x > w->lo)) return 0.0;
    if (!(x < w->hi)) return 1.0;
    if (w->n == 0 && w->visible) return (vis_T(x) - w->vis_t_lo) / w->vis_t_span;
    if (w->n == 0) return (x - w->lo) / range;
    h = range / w->n;
    cell = (x - w->lo) / h;
    k = (int)cell;
    if (k >= w->n) k = w->n - 1;
    return w->cdf[k] + (cell - k) * ((double)w->cdf[k + 1] - w->cdf[k]);
}

/* lambda_j = cdf^-1(frac(u + j / HERO_N)): the hero j = 0 and HERO_N - 1 companions
   rotated in CDF space, so each is distributed as p and the set is stratified.
   The inverse of the piecewise-linear CDF: the cell k through the guide table
   (cdf_cell, specnee.h: O(1), a table read and a compare or two), then linear in
   it,  lambda = lo + h (k + (u_j - cdf[k]) / (cdf[k + 1] - cdf[k]));
   the visible pdf's is the closed form above.  pdf[j] is wl_pdf_eval(lambda_j),
   the function the integrator evaluates: on the table, lambda_j lies in [lo, hi]
   by its clamp, so the density is table_pdf's without wl_pdf_eval's range tests.
   This runs once per camera sample (docs/speed.md). */
void wl_sample(const WavelengthPdf *w, float u, Wavelengths *out)
{
    double u0 = (double)u, range = (double)w->hi - w->lo;
    int j;
    if (!(u0 >= 0.0 && u0 < 1.0)) {               /* into [0, 1) (u is there nearly always) */
        if (!isfinite(u0)) u0 = 0.0;
        u0 -= floor(u0);
    }
    if (w->n > 0) {                               /* the table: importance, mixture */
        for (j = 0; j < HERO_N; j++) {
            double uj = u0 + (double)j / HERO_N, lambda, c0, c1;
            int k;
            if (uj >= 1.0) uj -= 1.0;
            k = cdf_cell(w->cdf, w->n, w->guide, w->m, uj);
            c0 = w->cdf[k];
            c1 = w->cdf[k + 1];
            lambda = w->lo + w->h * (k + (c1 > c0 ? (uj - c0) / (c1 - c0) : 0.5));
            if (lambda < w->lo) lambda = w->lo;
            if (lambda > w->hi) lambda = w->hi;
            out->lambda[j] = (float)lambda;
            out->pdf[j] = table_pdf(w, out->lambda[j]);
        }
        return;
    }
    for (j = 0; j < HERO_N; j++) {
        double uj = u0 + (double)j / HERO_N, lambda;
        if (uj >= 1.0) uj -= 1.0;
        if (w->visible) lambda = WL_VIS_C + atanh(w->vis_t_lo + uj * w->vis_t_span) / WL_VIS_A;
        else lambda = w->lo + uj * range;
        if (lambda < w->lo) lambda = w->lo;
        if (lambda > w->hi) lambda = w->hi;
        out->lambda[j] = (float)lambda;
        out->pdf[j] = wl_pdf_eval(w, out->lambda[j]);
    }
}
