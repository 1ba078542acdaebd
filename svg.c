/* svg.c - a small dependency-free SVG line-chart writer (spectra, convergence plots).

   WHAT IT IMPLEMENTS
     svg_line_chart() draws one chart with several series into a standalone SVG 1.1
     file: axes with ticks and labels, an optional title, a legend, one polyline per
     series (solid or dashed) and, per series, an optional shaded band between ylo
     and yhi (e.g. the min..max spread over seeds of a convergence curve).

     Axis mapping (data -> pixels), for the plot rectangle [px0, px1] x [py0, py1]:
         linear:  X = px0 + (x - xmin) / (xmax - xmin) * (px1 - px0)
         log:     X = px0 + (log10 x - log10 xmin) / (log10 xmax - log10 xmin) * (px1 - px0)
     and likewise for y, upwards (SVG's y axis points down).
     Ticks: linear axes at "nice" steps 1, 2 or 5 x 10^k (about 6 ticks); log axes at
     the powers of ten, labelled 10^k (with 2 and 5 x 10^k added when the range spans
     less than two decades).  Automatic ranges cover all finite data (positive data
     on log axes), rounded out to whole ticks (whole decades on log axes).

     Points that cannot be drawn (NaN, inf, <= 0 on a log axis) break the line and
     the band instead of being drawn as zeros.  Series of at most 40 points also get
     a dot at every point (so an isolated point stays visible).  Text is XML-escaped.

   HOW IT IS USED
     cmd_spectrum.c: `specnee spectrum --svg NAME ...` (docs/spectra.svg).  The
     benchmark tools: MSE vs spp and MSE vs time, log-log, one series per strategy.
       SvgSeries s = { "uniform", NULL, n, spp, mse, mse_min, mse_max, 0 };
       SvgChart c = { "Cornell", "samples per pixel", "MSE", 1, 1, 0, 0, 0, 0, 0, 0 };
       svg_line_chart(f, &c, &s, 1);
     Returns 1 on success, 0 on bad arguments or a write error. */
#include "specnee.h"
#include <string.h>

/* Colours for series without one (colour-blind friendly "tab10" order). */
static const char *const svg_palette[] = {
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"
};
#define SVG_PALETTE_N 8
#define SVG_MAX_TICKS 64
#define SVG_MARKER_MAX_POINTS 40  /* series with at most this many points get dot markers */

/* One axis: its data range, scale type and pixel range. */
typedef struct {
    double lo, hi;             /* data range (already log10 for log axes) */
    int log;                   /* 1: values are mapped through log10 */
    double p0, p1;             /* pixel positions of lo and hi */
} Axis;

/* A value as drawn on an axis (log10 for log axes); 0 when it cannot be drawn. */
static int axis_value(const Axis *a, double v, double *out)
{
    if (!isfinite(v)) return 0;
    if (a->log) {
        if (!(v > 0.0)) return 0;
        v = log10(v);
    }
    *out = v;
    return 1;
}

static double axis_pixel(const Axis *a, double t)   /* t already through axis_value */
{
    return a->p0 + (t - a->lo) / (a->hi - a->lo) * (a->p1 - a->p0);
}

/* Write text with &, <, >, " escaped. */
static void put_escaped(FILE *f, const char *s)
{
    for (; s && *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default:
            if ((unsigned char)*s >= 0x20 || *s == '\t') fputc(*s, f);  /* drop control chars */
        }
    }
}

/* Range of the drawable data of all series on one axis (through axis_value). */
static int data_range(const Axis *a, const SvgSeries *s, int n_series, int y_axis,
                      double *lo, double *hi)
{
    int i, k, found = 0;
    double t;
    *lo = HUGE_VAL;
    *hi = -HUGE_VAL;
    for (k = 0; k < n_series; k++) {
        const double *arrays[3];
        int m, n_arrays = 1;
        if (s[k].n <= 0) continue;
        arrays[0] = y_axis ? s[k].y : s[k].x;
        if (y_axis && s[k].ylo && s[k].yhi) { arrays[1] = s[k].ylo; arrays[2] = s[k].yhi; n_arrays = 3; }
        for (m = 0; m < n_arrays; m++) {
            if (!arrays[m]) continue;
            for (i = 0; i < s[k].n; i++)
                if (axis_value(a, arrays[m][i], &t)) {
                    if (t < *lo) *lo = t;
                    if (t > *hi) *hi = t;
                    found = 1;
                }
        }
    }
    return found;
}

/* A "nice" tick step (1, 2 or 5 times a power of ten) giving about 6 ticks. */
static double nice_step(double span)
{
    double raw = span / 6.0, p = pow(10.0, floor(log10(raw))), r = raw / p;
    return (r < 1.5 ? 1.0 : r < 3.5 ? 2.0 : r < 7.5 ? 5.0 : 10.0) * p;
}

/* Choose the axis range: explicit (lo < hi) or automatic from the data. */
static void axis_setup(Axis *a, int log_axis, double want_lo, double want_hi, const SvgSeries *s,
                       int n_series, int y_axis)
{
    double lo, hi;
    a->log = log_axis;
    if (want_hi > want_lo && (!log_axis || want_lo > 0.0)) {
        a->lo = log_axis ? log10(want_lo) : want_lo;
        a->hi = log_axis ? log10(want_hi) : want_hi;
        return;
    }
    if (!data_range(a, s, n_series, y_axis, &lo, &hi)) { lo = 0.0; hi = 1.0; }
    if (log_axis) {                               /* whole decades */
        lo = floor(lo);
        hi = ceil(hi);
        if (hi <= lo) hi = lo + 1.0;
    } else {
        double step;
        if (hi <= lo) {                           /* flat data: open up around it */
            double d = fabs(lo) > 0.0 ? 0.5 * fabs(lo) : 1.0;
            lo -= d; hi += d;
        }
        step = nice_step(hi - lo);
        lo = floor(lo / step) * step;
        hi = ceil(hi / step) * step;
    }
    a->lo = lo;
    a->hi = hi;
}

/* Tick positions (in axis units) and whether each is a power of ten. */
static int axis_ticks(const Axis *a, double *ticks)
{
    int n = 0;
    if (!a->log) {
        double step = nice_step(a->hi - a->lo), t;
        long k, k0 = (long)ceil(a->lo / step - 1e-9), k1 = (long)floor(a->hi / step + 1e-9);
        for (k = k0; k <= k1 && n < SVG_MAX_TICKS; k++) {
            t = k * step;
            if (fabs(t) < 1e-12 * step) t = 0.0;  /* print 0, not -1e-17 */
            ticks[n++] = t;
        }
    } else {
        long d0 = (long)ceil(a->lo - 1e-9), d1 = (long)floor(a->hi + 1e-9), d, every;
        every = (d1 - d0) / 12 + 1;               /* at most ~12 labelled decades */
        for (d = d0; d <= d1 && n < SVG_MAX_TICKS; d += every) ticks[n++] = (double)d;
        if (a->hi - a->lo < 2.0) {                /* few decades: add 2 and 5 x 10^k */
            long dd;
            for (dd = (long)floor(a->lo) ; dd <= (long)ceil(a->hi) && n < SVG_MAX_TICKS - 2; dd++) {
                double t2 = dd + log10(2.0), t5 = dd + log10(5.0);
                if (t2 >= a->lo - 1e-9 && t2 <= a->hi + 1e-9) ticks[n++] = t2;
                if (t5 >= a->lo - 1e-9 && t5 <= a->hi + 1e-9) ticks[n++] = t5;
            }
        }
    }
    return n;
}

/* Tick label: %g for linear axes; 10^k (superscript) or m x 10^k for log axes. */
static void put_tick_label(FILE *f, const Axis *a, double t)
{
    if (!a->log) { fprintf(f, "%g", t); return; }
    {
        double k = floor(t + 1e-9), mant = pow(10.0, t - k);
        if (fabs(mant - 1.0) < 1e-6) {
            if (k == 0.0) fputs("1", f);
            else if (k == 1.0) fputs("10", f);
            else fprintf(f, "10<tspan dy=\"-6\" font-size=\"9\">%ld</tspan>", (long)k);
        } else {
            fprintf(f, "%g", floor(mant + 0.5) * pow(10.0, k));
        }
    }
}

/* Draw the runs of consecutive drawable points of one series as path segments. */
static void put_line(FILE *f, const Axis *ax, const Axis *ay, const SvgSeries *s, const char *color)
{
    int i, pen = 0, any = 0;
    double tx, ty;
    for (i = 0; i < s->n; i++) {
        if (!axis_value(ax, s->x[i], &tx) || !axis_value(ay, s->y[i], &ty)) { pen = 0; continue; }
        if (!any) { fputs("<path fill=\"none\" d=\"", f); any = 1; }
        fprintf(f, "%c%.2f %.2f ", pen ? 'L' : 'M', axis_pixel(ax, tx), axis_pixel(ay, ty));
        pen = 1;
    }
    if (any) {
        fprintf(f, "\" stroke=\"%s\" stroke-width=\"1.8\" stroke-linejoin=\"round\"%s/>\n",
                color, s->dashed ? " stroke-dasharray=\"6 4\"" : "");
    }
    if (s->n <= SVG_MARKER_MAX_POINTS)            /* few points (e.g. spp 16..512): mark them */
        for (i = 0; i < s->n; i++)
            if (axis_value(ax, s->x[i], &tx) && axis_value(ay, s->y[i], &ty))
                fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"2.6\" fill=\"%s\"/>\n",
                        axis_pixel(ax, tx), axis_pixel(ay, ty), color);
}

/* Pixel coordinates of point k of a band; 0 when x, ylo or yhi cannot be drawn. */
static int band_point(const Axis *ax, const Axis *ay, const SvgSeries *s, int k,
                      double *X, double *Ylo, double *Yhi)
{
    double tx = 0.0, tl = 0.0, th = 0.0;
    if (!axis_value(ax, s->x[k], &tx) || !axis_value(ay, s->ylo[k], &tl) ||
        !axis_value(ay, s->yhi[k], &th)) return 0;
    *X = axis_pixel(ax, tx);
    *Ylo = axis_pixel(ay, tl);
    *Yhi = axis_pixel(ay, th);
    return 1;
}

/* The band ylo..yhi as one closed polygon per run of drawable points. */
static void put_band(FILE *f, const Axis *ax, const Axis *ay, const SvgSeries *s, const char *color)
{
    int i = 0, j, k;
    double X = 0.0, Ylo = 0.0, Yhi = 0.0;
    while (i < s->n) {
        /* find the next run [i, j) of drawable points */
        while (i < s->n && !band_point(ax, ay, s, i, &X, &Ylo, &Yhi)) i++;
        j = i;
        while (j < s->n && band_point(ax, ay, s, j, &X, &Ylo, &Yhi)) j++;
        if (j - i >= 2) {
            fputs("<path d=\"", f);
            for (k = i; k < j; k++) {             /* lower edge forwards ... */
                band_point(ax, ay, s, k, &X, &Ylo, &Yhi);
                fprintf(f, "%c%.2f %.2f ", k == i ? 'M' : 'L', X, Ylo);
            }
            for (k = j - 1; k >= i; k--) {        /* ... upper edge backwards */
                band_point(ax, ay, s, k, &X, &Ylo, &Yhi);
                fprintf(f, "L%.2f %.2f ", X, Yhi);
            }
            fprintf(f, "Z\" fill=\"%s\" fill-opacity=\"0.18\" stroke=\"none\"/>\n", color);
        }
        i = j;
    }
}

int svg_line_chart(FILE *f, const SvgChart *c, const SvgSeries *s, int n_series)
{
    const double margin_l = 78.0, margin_r = 20.0, margin_t = 38.0, margin_b = 56.0;
    double w, h, ticks[SVG_MAX_TICKS], legend_w = 0.0;
    Axis ax, ay;
    int k, i, n_ticks, n_legend = 0;

    if (!f || !c || n_series < 0 || (n_series > 0 && !s)) return 0;
    for (k = 0; k < n_series; k++)
        if (s[k].n > 0 && (!s[k].x || !s[k].y)) return 0;
    w = c->width > 0 ? c->width : 720;
    h = c->height > 0 ? c->height : 450;
    if (w < margin_l + margin_r + 40.0) w = margin_l + margin_r + 40.0;
    if (h < margin_t + margin_b + 40.0) h = margin_t + margin_b + 40.0;

    axis_setup(&ax, c->logx, c->xmin, c->xmax, s, n_series, 0);
    axis_setup(&ay, c->logy, c->ymin, c->ymax, s, n_series, 1);
    ax.p0 = margin_l;         ax.p1 = w - margin_r;
    ay.p0 = h - margin_b;     ay.p1 = margin_t;   /* up is smaller y in SVG */

    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"%.0f\" "
            "height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" font-family=\"Helvetica, Arial, sans-serif\" "
            "font-size=\"12\">\n", w, h, w, h);
    fprintf(f, "<rect width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", w, h);
    fprintf(f, "<defs><clipPath id=\"plotarea\"><rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" "
            "height=\"%.2f\"/></clipPath></defs>\n", ax.p0, ay.p1, ax.p1 - ax.p0, ay.p0 - ay.p1);
    if (c->title) {
        fprintf(f, "<text x=\"%.2f\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">", 0.5 * w);
        put_escaped(f, c->title);
        fputs("</text>\n", f);
    }

    /* grid, ticks and tick labels */
    n_ticks = axis_ticks(&ax, ticks);
    for (i = 0; i < n_ticks; i++) {
        double X = axis_pixel(&ax, ticks[i]);
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#e4e4e4\"/>\n",
                X, ay.p0, X, ay.p1);
        fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">", X, ay.p0 + 18.0);
        put_tick_label(f, &ax, ticks[i]);
        fputs("</text>\n", f);
    }
    n_ticks = axis_ticks(&ay, ticks);
    for (i = 0; i < n_ticks; i++) {
        double Y = axis_pixel(&ay, ticks[i]);
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#e4e4e4\"/>\n",
                ax.p0, Y, ax.p1, Y);
        fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"end\">", ax.p0 - 6.0, Y + 4.0);
        put_tick_label(f, &ay, ticks[i]);
        fputs("</text>\n", f);
    }
    fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"none\" "
            "stroke=\"black\"/>\n", ax.p0, ay.p1, ax.p1 - ax.p0, ay.p0 - ay.p1);
    if (c->xlabel) {
        fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">", 0.5 * (ax.p0 + ax.p1), h - 14.0);
        put_escaped(f, c->xlabel);
        fputs("</text>\n", f);
    }
    if (c->ylabel) {
        double yc = 0.5 * (ay.p0 + ay.p1);
        fprintf(f, "<text x=\"18\" y=\"%.2f\" text-anchor=\"middle\" transform=\"rotate(-90 18 %.2f)\">",
                yc, yc);
        put_escaped(f, c->ylabel);
        fputs("</text>\n", f);
    }

    /* bands first (under every line), then the lines, clipped to the plot area */
    fputs("<g clip-path=\"url(#plotarea)\">\n", f);
    for (k = 0; k < n_series; k++)
        if (s[k].ylo && s[k].yhi && s[k].n > 0)
            put_band(f, &ax, &ay, &s[k], s[k].color ? s[k].color : svg_palette[k % SVG_PALETTE_N]);
    for (k = 0; k < n_series; k++)
        if (s[k].n > 0) put_line(f, &ax, &ay, &s[k], s[k].color ? s[k].color : svg_palette[k % SVG_PALETTE_N]);
    fputs("</g>\n", f);

    /* legend, top right inside the plot */
    for (k = 0; k < n_series; k++)
        if (s[k].name) {
            double tw = 7.0 * (double)strlen(s[k].name);   /* rough text width */
            if (tw > legend_w) legend_w = tw;
            n_legend++;
        }
    if (n_legend > 0) {
        double lx = ax.p1 - legend_w - 48.0, ly = ay.p1 + 8.0;
        int row = 0;
        fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"white\" "
                "fill-opacity=\"0.85\" stroke=\"#999999\"/>\n", lx, ly, legend_w + 40.0, 18.0 * n_legend + 6.0);
        for (k = 0; k < n_series; k++) {
            double yy;
            const char *color = s[k].color ? s[k].color : svg_palette[k % SVG_PALETTE_N];
            if (!s[k].name) continue;
            yy = ly + 15.0 + 18.0 * row++;
            fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\" "
                    "stroke-width=\"2\"%s/>\n", lx + 6.0, yy - 4.0, lx + 28.0, yy - 4.0, color,
                    s[k].dashed ? " stroke-dasharray=\"6 4\"" : "");
            fprintf(f, "<text x=\"%.2f\" y=\"%.2f\">", lx + 34.0, yy);
            put_escaped(f, s[k].name);
            fputs("</text>\n", f);
        }
    }
    fputs("</svg>\n", f);
    return ferror(f) ? 0 : 1;
}
