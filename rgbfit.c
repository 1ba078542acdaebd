/* rgbfit.c - RGB to spectrum: Jakob & Hanika's sigmoid polynomials, fitted and tabulated.

   WHAT IT IMPLEMENTS
     Jakob & Hanika 2019, "A Low-Dimensional Function Space for Efficient Spectral
     Upsampling" (Eurographics): s(lambda) = S(c0 x^2 + c1 x + c2), S(p) = 1/2 + p /
     (2 sqrt(1 + p^2)), x = (lambda - 360) / 470, with (c0, c1, c2) found by Newton
     steps so that s(lambda) D65(lambda) maps back to the rgb (the section below has
     the equations), started from rgbtable.c's build-time table or from a coefficient
     table over rgb filled on first use; docs/loading.md measures the load time.  A
     material's rgb reflectance keeps only (c0, c1, c2) (an Albedo): albedo_eval
     computes the two knots of spec_eval's interpolation from them when shaded.
     Each fit is in a colour space (pbrt-v4's ColorSpace: srgb, dci-p3, rec2020,
     aces2065-1; the section below): its matrix and its white weight the forward
     map, and an rgb illuminant is multiplied by that white.  sRGB starts from
     rgbtable.c; the other spaces from the coefficient table filled on first use.

   EXPORTS (specnee.h section 4)
     spec_rgb_coeffs spec_rgb_fit_table spec_rgb_coeffs_from spec_sigmoid_eval
     spec_rgb_table_start spec_rgb_coeffs_fit rgb_table_new rgb_table_free spec_from_rgb
     spec_from_rgb_t spec_ybar_knots spec_to_y_t albedo_eval_rgb albedo_knot
     albedo_from_rgb colorspace_index colorspace_name colorspace_illuminant
     colorspace_from_xyz colorspace_rgb_from_xyz colorspace_luminance colorspace_lookup
     rgb_table_new_cs rgb_table_space

   HOW IT IS USED
     parser.c turns "rgb" parameters into spectra (spec_from_rgb_t) and material
     colours into Albedos (albedo_from_rgb), with the table of the ColorSpace
     current at the directive (parser.h Parser.rgb, one table per space);
     tools/gen_rgbtable.c builds rgbtable.h from this fit; the dense spectra, the CIE tables and the named illuminants it
     reads are spectrum.c's. */
#include "specnee.h"
#include <ctype.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* ======================================================================
   11. RGB -> spectrum (Jakob & Hanika 2019 sigmoid polynomials)
   ----------------------------------------------------------------------
   Model: s(lambda) = S(p(x)), p(x) = c0 x^2 + c1 x + c2, x = (lambda - 360) / 470,
   S(p) = 1/2 + p / (2 sqrt(1 + p^2)), a smooth spectrum bounded in (0, 1).
   Forward map: rgb(c) = M_XYZ->sRGB * sum_lambda cmf(lambda) s(lambda) w(lambda),
   w = D65 / sum ybar D65 (so s = 1 gives white, rgb = (1, 1, 1)).
   Fit: Newton steps on J(c) dc = target - rgb(c) with the analytic Jacobian
   d rgb / d c_k = M sum cmf w S'(p) x^(2-k), S'(p) = 1 / (2 (1 + p^2)^(3/2)),
   a backtracking line search, and continuation from grey (c = 0, rgb 0.5) to the
   target in 8 steps, which keeps Newton inside its basin for saturated colours (the
   same idea as Jakob & Hanika's table optimisation, done here at load time).
   Grey (r = g = b) gives an exactly constant spectrum, as in pbrt-v4.
   A scene load asks rgbtable.c's build-time table first: its interpolation as it
   is in the cells it trusts, polished by these Newton steps in the others; the
   coefficient table below (its start, polished) and the continuation are the
   fallbacks (and the continuation builds both tables).
   Accuracy (tests/test_spectrum.c): the round trip rgb -> s -> rgb is within 1.3e-6
   (float rounding of the table) over a 5^3 grid of components 0.1..0.9, and within
   1e-4 for the sRGB primaries (steep sigmoids); greys are off by up to 1.5e-4, the
   difference between pbrt-v4's matrix white point and D65 integrated with these
   CMFs (D65 itself maps to (1.00007, 0.99999, 0.99984)).
   ====================================================================== */

typedef RgbFitTable RgbFit;   /* cmf(lambda) * w(lambda) (specnee.h) */
static int solve3(double A[3][3], double b[3], double x[3]);

/* ======================================================================
   Colour spaces (pbrt-v4's RGBColorSpace; docs/spectra.md)
   ----------------------------------------------------------------------
   A linear RGB colour space is three primaries' chromaticities and a white
   illuminant W (a spectrum).  Its matrix follows from them (SMPTE RP 177):
   the primaries' XYZ at Y = 1, R = (x/y, 1, (1-x-y)/y), ... as the columns of
   P; C = P^-1 XYZ(W) (W's XYZ at Y = 1, integrated from its spectrum as pbrt-v4
   does, not its nominal xy); XYZ_from_RGB = P diag(C), so rgb (1, 1, 1) is W;
   RGB_from_XYZ its inverse.  The space sets, for every "rgb" parameter read
   while it is current, the fit's forward map (its matrix, and W as the w of
   the fit: a reflectance of 1 is (1, 1, 1) under W) and the illuminant an
   "rgb L" is multiplied by (W itself); the Film's space sets the image's RGB.
   Primaries (pbrt-v4 src/pbrt/util/colorspace.cpp; the standards):
     srgb        ITU-R BT.709:  R (.64, .33)  G (.30, .60)  B (.15, .06),  D65
     dci-p3      P3-D65 (SMPTE EG 432-1): R (.68, .32) G (.265, .69) B (.15, .06), D65
     rec2020     ITU-R BT.2020: R (.708, .292) G (.170, .797) B (.131, .046), D65
     aces2065-1  SMPTE ST 2065-1 (AP0): R (.7347, .2653) G (0, 1) B (.0001, -.077),
                 ACES's white illum-acesD60 (spectrum.c)
   sRGB keeps xyz_to_linear_srgb's matrix (pbrt-v4's numbers), which this
   construction reproduces to 1e-5; the others are built here. */
static const struct {
    const char *name, *white;
    double xy[3][2];
} color_spaces[COLORSPACE_N] = {
    { "srgb", "stdillum-D65", { { .64, .33 }, { .3, .6 }, { .15, .06 } } },
    { "dci-p3", "stdillum-D65", { { .68, .32 }, { .265, .690 }, { .15, .06 } } },
    { "rec2020", "stdillum-D65", { { .708, .292 }, { .170, .797 }, { .131, .046 } } },
    { "aces2065-1", "illum-acesD60", { { .7347, .2653 }, { 0., 1. }, { .0001, -.077 } } }
};

int colorspace_index(const char *name)
{
    int i, k;
    for (i = 0; i < COLORSPACE_N; i++) {            /* pbrt-v4 lower-cases the name */
        const char *a = color_spaces[i].name;
        for (k = 0; a[k] && tolower((unsigned char)name[k]) == a[k]; k++) {}
        if (!a[k] && !name[k]) return i;
    }
    return -1;
}

const char *colorspace_name(int cs) { return color_spaces[cs].name; }

void colorspace_illuminant(int cs, Spectrum *s)
{
    spec_named(s, color_spaces[cs].white);
}

/* inv = A^-1 by solve3 on each column of the identity; 0 if singular */
static int invert3(double A[3][3], double inv[3][3])
{
    double a[3][3], b[3], x[3];
    int i, j;
    for (j = 0; j < 3; j++) {
        memcpy(a, A, sizeof a);
        for (i = 0; i < 3; i++) b[i] = i == j;
        if (!solve3(a, b, x)) return 0;
        for (i = 0; i < 3; i++) inv[i][j] = x[i];
    }
    return 1;
}

void colorspace_from_xyz(int cs, double m[3][3])
{
    double P[3][3], Pi[3][3], W[3], C[3], xyz_from_rgb[3][3], wx, wy;
    Spectrum w;
    int i, j;
    if (cs == COLORSPACE_SRGB) {                  /* pbrt-v4's constants */
        for (j = 0; j < 3; j++) {
            double e[3] = { 0.0, 0.0, 0.0 }, col[3];
            e[j] = 1.0;
            xyz_to_linear_srgb(e, col);
            for (i = 0; i < 3; i++) m[i][j] = col[i];
        }
        return;
    }
    colorspace_illuminant(cs, &w);
    spec_chromaticity(&w, &wx, &wy);
    W[0] = wx / wy; W[1] = 1.0; W[2] = (1.0 - wx - wy) / wy;
    for (j = 0; j < 3; j++) {                     /* column j: primary j at Y = 1 */
        double x = color_spaces[cs].xy[j][0], y = color_spaces[cs].xy[j][1];
        P[0][j] = x / y; P[1][j] = 1.0; P[2][j] = (1.0 - x - y) / y;
    }
    invert3(P, Pi);                               /* the primaries are independent */
    for (i = 0; i < 3; i++) C[i] = Pi[i][0] * W[0] + Pi[i][1] * W[1] + Pi[i][2] * W[2];
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) xyz_from_rgb[i][j] = P[i][j] * C[j];
    invert3(xyz_from_rgb, m);
}

/* rgb = m xyz (m row-major), in xyz_to_linear_srgb's order of operations */
static void mat_apply(const double *m, const double xyz[3], double rgb[3])
{
    int r;
    for (r = 0; r < 3; r++)
        rgb[r] = m[3 * r] * xyz[0] + m[3 * r + 1] * xyz[1] + m[3 * r + 2] * xyz[2];
}

void colorspace_rgb_from_xyz(int cs, const double xyz[3], double rgb[3])
{
    double m[3][3];
    colorspace_from_xyz(cs, m);
    mat_apply(&m[0][0], xyz, rgb);
}

/* The luminance row: Y of rgb is y . rgb (pbrt-v4's LuminanceVector, the middle
   row of XYZ_from_RGB).  sRGB's is pbrt-v4's rounded constants, which the lights
   that normalise an sRGB image by it have always used. */
void colorspace_luminance(int cs, double y[3])
{
    double m[3][3], inv[3][3];
    int j;
    if (cs == COLORSPACE_SRGB) { y[0] = 0.2126; y[1] = 0.7152; y[2] = 0.0722; return; }
    colorspace_from_xyz(cs, m);
    invert3(m, inv);                              /* a colour space's matrix is regular */
    for (j = 0; j < 3; j++) y[j] = inv[1][j];
}

/* The space whose primaries and white are the chromaticities xy = (rx, ry, gx, gy,
   bx, by, wx, wy), as an OpenEXR file's "chromaticities" attribute gives them:
   pbrt-v4's RGBColorSpace::Lookup, which tries ACES2065-1, DCI-P3, Rec2020, sRGB in
   that order and takes the first whose four points are each close enough, each
   coordinate a equal to the space's b or |a - b| < 1e-3 |b| (so a zero coordinate,
   ACES's green x, must be exactly zero).  The white of a space is its illuminant's
   chromaticity integrated from the spectrum (as pbrt-v4 computes it), not a
   nominal xy.  The comparison is in float, as pbrt-v4's Point2f.  -1: none. */
int colorspace_lookup(const float xy[8])
{
    static const int order[COLORSPACE_N] = { COLORSPACE_ACES, 2, 1, COLORSPACE_SRGB };
    int o, k;
    for (o = 0; o < COLORSPACE_N; o++) {
        int cs = order[o], ok = 1;
        float want[8];
        double wx, wy;
        Spectrum w;
        colorspace_illuminant(cs, &w);
        spec_chromaticity(&w, &wx, &wy);
        for (k = 0; k < 6; k++) want[k] = (float)color_spaces[cs].xy[k / 2][k % 2];
        want[6] = (float)wx;
        want[7] = (float)wy;
        for (k = 0; k < 8 && ok; k++)
            ok = xy[k] == want[k] || fabsf((xy[k] - want[k]) / want[k]) < 1e-3f;
        if (ok) return cs;
    }
    return -1;
}

/* The fit's tables for colour space cs: cmf x W / sum ybar W, and the matrix. */
static void rgb_fit_init(RgbFit *f, int cs)
{
    Spectrum w;
    double c[3], norm = 0.0;
    int i, k;
    colorspace_illuminant(cs, &w);                /* the fit's weight: the space's white */
    colorspace_from_xyz(cs, f->m);
    for (i = 0; i < SPEC_N; i++) {
        cie_cmf((double)(SPEC_MIN + i), c);
        norm += c[1] * w.v[i];
        for (k = 0; k < 3; k++) f->cmf_w[k][i] = c[k] * w.v[i];
    }
    for (i = 0; i < SPEC_N; i++)
        for (k = 0; k < 3; k++) f->cmf_w[k][i] /= norm;
    for (i = 0; i < SPEC_N; i++) f->x[i] = (double)i / (SPEC_N - 1);
}

/* S(p) = 1/2 + p / (2 sqrt(1 + p^2)); past |p| = 1e100 (where p^2 would overflow)
   it is 0 or 1 to double precision */
static double sigmoid(double p)
{
    if (fabs(p) > 1e100) return p > 0.0 ? 1.0 : 0.0;
    return 0.5 + 0.5 * p / sqrt(1.0 + p * p);
}

/* rgb(c) and, if J is not NULL, its Jacobian J[r][k] = d rgb_r / d c_k.  With
   w_k = cmf_w[k] and basis (x^2, x, 1):
       xyz_k = sum_i w_k S(p_i),   dxyz_k / dc_r = sum_i w_k S'(p_i) basis_r,
   S(p) = 1/2 + p / (2 sqrt(1 + p^2)), S'(p) = 1 / (2 (1 + p^2)^(3/2)); each sum
   runs in its own scalar in the order of i (the fit is called ~10^5 times per
   big scene: registers, not arrays, and no S' when J is not wanted). */
static void rgb_fit_eval(const RgbFit *f, const double c[3], double rgb[3], double J[3][3])
{
    double xyz[3], d[3][3];
    double X = 0.0, Y = 0.0, Z = 0.0;
    double dX0 = 0.0, dX1 = 0.0, dX2 = 0.0, dY0 = 0.0, dY1 = 0.0, dY2 = 0.0;
    double dZ0 = 0.0, dZ1 = 0.0, dZ2 = 0.0;
    const double *wx = f->cmf_w[0], *wy = f->cmf_w[1], *wz = f->cmf_w[2];
    int i, k, r;
    for (i = 0; i < SPEC_N; i++) {
        double x = f->x[i], p = (c[0] * x + c[1]) * x + c[2];
        double q = sqrt(1.0 + p * p), S = 0.5 + 0.5 * p / q;
        X += wx[i] * S; Y += wy[i] * S; Z += wz[i] * S;
        if (J) {
            double dS = 0.5 / (q * q * q), x2 = x * x;
            double ax = wx[i] * dS, ay = wy[i] * dS, az = wz[i] * dS;   /* times basis 1 */
            dX0 += ax * x2; dX1 += ax * x; dX2 += ax;
            dY0 += ay * x2; dY1 += ay * x; dY2 += ay;
            dZ0 += az * x2; dZ1 += az * x; dZ2 += az;
        }
    }
    xyz[0] = X; xyz[1] = Y; xyz[2] = Z;
    mat_apply(&f->m[0][0], xyz, rgb);
    if (J) {
        double col[3], out[3];
        d[0][0] = dX0; d[0][1] = dX1; d[0][2] = dX2;
        d[1][0] = dY0; d[1][1] = dY1; d[1][2] = dY2;
        d[2][0] = dZ0; d[2][1] = dZ1; d[2][2] = dZ2;
        for (r = 0; r < 3; r++) {                 /* column r of M * dxyz */
            for (k = 0; k < 3; k++) col[k] = d[k][r];
            mat_apply(&f->m[0][0], col, out);
            for (k = 0; k < 3; k++) J[k][r] = out[k];
        }
    }
}

/* Solve the 3x3 system A x = b by Gaussian elimination with partial pivoting. */
static int solve3(double A[3][3], double b[3], double x[3])
{
    int i, j, k;
    for (i = 0; i < 3; i++) {
        int piv = i;
        for (j = i + 1; j < 3; j++) if (fabs(A[j][i]) > fabs(A[piv][i])) piv = j;
        if (!(fabs(A[piv][i]) > 1e-300)) return 0;
        if (piv != i) {
            double t;
            for (k = 0; k < 3; k++) { t = A[i][k]; A[i][k] = A[piv][k]; A[piv][k] = t; }
            t = b[i]; b[i] = b[piv]; b[piv] = t;
        }
        for (j = i + 1; j < 3; j++) {
            double m = A[j][i] / A[i][i];
            for (k = i; k < 3; k++) A[j][k] -= m * A[i][k];
            b[j] -= m * b[i];
        }
    }
    for (i = 2; i >= 0; i--) {
        double s = b[i];
        for (k = i + 1; k < 3; k++) s -= A[i][k] * x[k];
        x[i] = s / A[i][i];
    }
    return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]);
}

static double norm2_diff(const double a[3], const double b[3])
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

/* Newton's method on rgb(c) = target from the c given, at most max_it steps, each
   with the analytic Jacobian, a trust region of length 50 and a backtracking line
   search.  Returns the squared rgb error of the final c.  It stops once that error
   is below 1e-14; after a step, that error is the accepted trial's (the rgb(c) a
   new evaluation would give), so converging costs no evaluation of the Jacobian. */
static double rgb_newton(const RgbFit *f, const double target[3], double c[3], int max_it)
{
    double rgb[3], J[3][3], rhs[3], dc[3], trial[3], trial_rgb[3], err0 = 1.0;
    int it, k, h;
    for (it = 0; it < max_it; it++) {
        double len;
        if (it > 0 && err0 < 1e-14) break;        /* rgb(c) known from the last trial */
        rgb_fit_eval(f, c, rgb, J);
        err0 = norm2_diff(rgb, target);
        if (err0 < 1e-14) break;
        for (k = 0; k < 3; k++) rhs[k] = target[k] - rgb[k];
        if (!solve3(J, rhs, dc)) break;
        len = sqrt(dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2]);
        if (len > 50.0) for (k = 0; k < 3; k++) dc[k] *= 50.0 / len;  /* trust region */
        for (h = 0; h < 12; h++) {                /* backtracking: halve until better */
            for (k = 0; k < 3; k++) trial[k] = c[k] + dc[k];
            rgb_fit_eval(f, trial, trial_rgb, NULL);
            if (norm2_diff(trial_rgb, target) < err0) break;
            for (k = 0; k < 3; k++) dc[k] *= 0.5;
        }
        if (h == 12) break;                       /* no progress: best we can do */
        for (k = 0; k < 3; k++) c[k] = trial[k];
        err0 = norm2_diff(trial_rgb, target);
    }
    return err0;
}

/* Fit c so that rgb(c) ~ target (each component in [0, 1]): continuation from grey
   (c = 0) to the target in 8 steps of up to 25 Newton steps each. */
static void rgb_fit(const RgbFit *f, const double target[3], double c[3])
{
    const int n_steps = 8;
    double grey[3], t[3];
    int s, k;
    c[0] = c[1] = c[2] = 0.0;
    rgb_fit_eval(f, c, grey, NULL);
    for (s = 1; s <= n_steps; s++) {
        for (k = 0; k < 3; k++) t[k] = grey[k] + (target[k] - grey[k]) * s / n_steps;
        rgb_newton(f, t, c, 25);
    }
}

void spec_rgb_fit_table(RgbFitTable *t, int cs) { rgb_fit_init(t, cs); }

/* Newton's method from start straight at target (no homotopy from grey): a few
   steps when start fits a nearby colour.  1 when the fit's error is below 1e-10
   (squared, in rgb), else 0 (c holds the last iterate). */
int spec_rgb_coeffs_from(const RgbFitTable *f, const double target[3], const double start[3], double c[3])
{
    int k;
    for (k = 0; k < 3; k++) c[k] = start[k];
    return rgb_newton(f, target, c, 12) < 1e-10;
}

/* The coefficient table: the fit at the corners of a grid over rgb, built once in a
   fixed order (so its content never depends on who asks first), and looked up by
   trilinear interpolation of the coefficients, then polished by Newton steps.
   Grid (Jakob & Hanika's parametrisation): the largest component m (which of the
   three, ties to the first), z = rgb[m] in [0, 1] at RGB_TAB_N knots
   z_k = smoothstep(smoothstep(k / (RGB_TAB_N - 1))) (dense near 0 and 1, where the
   coefficients grow fastest; the middle knot is z = 1/2, every rgb illuminant's),
   and the two other components divided by z, a = rgb[m+1] / z, b = rgb[m+2] / z in
   [0, 1] at equal steps.  A corner is fitted by Newton from its fitted neighbour
   (a sweep from the grey corner a = b = 1, where c = 0 exactly), by the continuation
   from grey where that fails.  Each slice (m, z_k) is built by its own sweep, on
   the first lookup that needs it, so a scene builds only the slices its colours
   use (every rgb illuminant lies on the z = 1/2 slices), and a slice's content does
   not depend on which lookup asked first.  Below z_1 the z_1 slice is used alone.
   Accuracy: the polish stops where the full fit does (squared rgb error 1e-14), so
   a spectrum matches the full fit's to the fit's own precision; a colour whose
   polish does not converge within RGB_POLISH steps (saturated colours that the
   sigmoid cannot reach, near the gamut boundary) takes the full continuation:
   tests/test_spectrum.c (spectrum_rgb_table) measures both. */
#define RGB_TAB_N 9
#define RGB_POLISH 8
struct RgbTable {                              /* specnee.h: owned by a scene load */
    int ready;                                 /* fit and z filled */
    int cs;                                    /* its colour space (COLORSPACE_*) */
    int built[3][RGB_TAB_N];                   /* slice (m, z_k) filled */
    RgbFit fit;
    Spectrum illum;                            /* the space's white (Y = 1), for illuminants */
    double ybar[SPEC_N], ybar_sum;             /* cie_ybar at each knot, and their sum */
    double z[RGB_TAB_N];
    double c[3][RGB_TAB_N][RGB_TAB_N][RGB_TAB_N][3];  /* [m][z][b][a][coefficient] */
};

static double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

/* The rgb of corner (m, zi, bi, ai). */
static void rgb_table_corner(const RgbTable *T, int m, int zi, int bi, int ai, double rgb[3])
{
    double z = T->z[zi];
    rgb[m] = z;
    rgb[(m + 1) % 3] = z * ai / (RGB_TAB_N - 1);
    rgb[(m + 2) % 3] = z * bi / (RGB_TAB_N - 1);
}

static void rgb_table_fit_corner(RgbTable *T, int m, int zi, int bi, int ai, const double start[3])
{
    double rgb[3], *c = T->c[m][zi][bi][ai];
    int k;
    rgb_table_corner(T, m, zi, bi, ai, rgb);
    for (k = 0; k < 3; k++) c[k] = start[k];
    if (rgb_newton(&T->fit, rgb, c, 25) >= 1e-10) rgb_fit(&T->fit, rgb, c);
}

/* Fill slice (m, zi >= 1) by a sweep from its grey corner. */
static void rgb_table_build_slice(RgbTable *T, int m, int zi)
{
    static const double zero[3] = { 0.0, 0.0, 0.0 };
    const int top = RGB_TAB_N - 1;
    int ai, bi;
    rgb_table_fit_corner(T, m, zi, top, top, zero);                       /* grey */
    for (bi = top - 1; bi >= 0; bi--)                                      /* a = 1 */
        rgb_table_fit_corner(T, m, zi, bi, top, T->c[m][zi][bi + 1][top]);
    for (bi = top; bi >= 0; bi--)                                          /* rows */
        for (ai = top - 1; ai >= 0; ai--)
            rgb_table_fit_corner(T, m, zi, bi, ai, T->c[m][zi][bi][ai + 1]);
    T->built[m][zi] = 1;
}

/* A cache of a pure function of the grid, owned by whoever loads (scene.c's
   Parser): empty when made, its fit and knots set on the first lookup, its
   slices filled as lookups need them.  Not for concurrent use. */
RgbTable *rgb_table_new(void)
{
    return rgb_table_new_cs(COLORSPACE_SRGB);
}

RgbTable *rgb_table_new_cs(int cs)
{
    RgbTable *T = (RgbTable *)calloc(1, sizeof(RgbTable));
    if (T) T->cs = cs;
    return T;
}

int rgb_table_space(const RgbTable *T) { return T ? T->cs : COLORSPACE_SRGB; }

void rgb_table_free(RgbTable *T)
{
    free(T);
}

static RgbTable *rgb_table_get(RgbTable *T)
{
    int zi;
    if (!T->ready) {
        rgb_fit_init(&T->fit, T->cs);
        colorspace_illuminant(T->cs, &T->illum);
        T->ybar_sum = 0.0;
        for (zi = 0; zi < SPEC_N; zi++) {           /* spec_to_y's terms, in its order */
            T->ybar[zi] = cie_ybar((double)(SPEC_MIN + zi));
            T->ybar_sum += T->ybar[zi];
        }
        for (zi = 0; zi < RGB_TAB_N; zi++)
            T->z[zi] = smoothstep(smoothstep((double)zi / (RGB_TAB_N - 1)));
        T->ready = 1;
    }
    return T;
}

/* Trilinear interpolation of the table's coefficients at target (not all zero),
   filling the slices it needs. */
static void rgb_table_lookup(RgbTable *T, const double target[3], double c[3])
{
    double z, a, b, fz, fa, fb;
    int m = 0, zi, ai, bi, k, dz, da, db;
    if (target[1] > target[m]) m = 1;
    if (target[2] > target[m]) m = 2;
    z = target[m];
    a = target[(m + 1) % 3] / z * (RGB_TAB_N - 1);
    b = target[(m + 2) % 3] / z * (RGB_TAB_N - 1);
    for (zi = 1; zi < RGB_TAB_N - 2 && T->z[zi + 1] < z; zi++) {}
    fz = z <= T->z[zi] ? 0.0 : (z - T->z[zi]) / (T->z[zi + 1] - T->z[zi]);
    ai = a >= RGB_TAB_N - 1 ? RGB_TAB_N - 2 : (int)a;
    bi = b >= RGB_TAB_N - 1 ? RGB_TAB_N - 2 : (int)b;
    fa = a - ai; fb = b - bi;
    for (k = 0; k < 3; k++) c[k] = 0.0;
    for (dz = 0; dz < 2; dz++) {
        if (dz == 1 && fz == 0.0) break;          /* on a knot: one slice */
        if (!T->built[m][zi + dz]) rgb_table_build_slice(T, m, zi + dz);
        for (db = 0; db < 2; db++)
            for (da = 0; da < 2; da++) {
                double w = (dz ? fz : 1.0 - fz) * (db ? fb : 1.0 - fb) * (da ? fa : 1.0 - fa);
                for (k = 0; k < 3; k++) c[k] += w * T->c[m][zi + dz][bi + db][ai + da][k];
            }
    }
}

/* c for target (components in [0, 1], not grey): rgbtable.c's interpolation in
   its trusted cells; elsewhere that interpolation polished by Newton, else this
   coarse table's start polished, else (or where there is no table, T NULL) the
   full continuation. */
static void rgb_coeffs(RgbTable *T, const double target[3], double c[3])
{
    int in_table;
    if (!T) {
        RgbFit fit;
        rgb_fit_init(&fit, COLORSPACE_SRGB);
        rgb_fit(&fit, target, c);
        return;
    }
    /* rgbtable.c: sRGB's build-time table; the other spaces start from the
       coarse table below, filled on first use (docs/spectra.md measures it) */
    in_table = T->cs == COLORSPACE_SRGB ? rgbtable_lookup(target, c) : 0;
    if (in_table == 2) return;                  /* a trusted cell: no iteration */
    rgb_table_get(T);
    /* another cell: its interpolation, polished (about 3 evaluations of rgb(c)) */
    if (in_table == 1 && rgb_newton(&T->fit, target, c, RGB_POLISH) < 1e-14) return;
    rgb_table_lookup(T, target, c);
    if (rgb_newton(&T->fit, target, c, RGB_POLISH) >= 1e-14) rgb_fit(&T->fit, target, c);
}

int spec_from_rgb(Spectrum *s, const float rgb[3], int illuminant, Error *err,
                  const char *file, int line)
{
    return spec_from_rgb_t(NULL, s, rgb, illuminant, err, file, line);
}

int spec_from_rgb_t(RgbTable *T, Spectrum *s, const float rgb[3], int illuminant, Error *err,
                    const char *file, int line)
{
    double target[3], c[3], m = 0.0;
    int i, k;
    for (i = 0; i < SPEC_UV_N; i++) s->uv[i] = 0.0f;   /* rgb spectra have no UV */
    for (k = 0; k < 3; k++) {
        if (!isfinite(rgb[k]) || rgb[k] > 1e30f) {   /* 1e30: D65 times it stays finite */
            error_set(err, file, line, "rgb value (%g, %g, %g) is not finite or too large",
                      (double)rgb[0], (double)rgb[1], (double)rgb[2]);
            return 0;
        }
        target[k] = rgb[k] < 0.0f ? 0.0 : rgb[k];            /* negative -> 0 */
        if (!illuminant && target[k] > 1.0) target[k] = 1.0;  /* reflectance in [0, 1] */
        if (target[k] > m) m = target[k];
    }
    if (illuminant) {
        /* pbrt-v4 RGBIlluminantSpectrum: m = 2 max(rgb), fit rgb / m (max 1/2),
           multiply by m and by the colour space's illuminant (T's: D65 or ACES D60, Y = 1; T NULL: D65).
           illuminant == 2: pbrt-v4's RGBUnboundedSpectrum, the same without the illuminant
           (the coefficients of a medium). */
        Spectrum one;
        const Spectrum *white = &one;
        const double *xs = NULL;      /* T's table of the knots' x (the same doubles) */
        if (m == 0.0) { spec_const(s, 0.0f); return 1; }
        if (illuminant == 2) spec_const(&one, 1.0f);
        else if (T) { white = &rgb_table_get(T)->illum; xs = T->fit.x; }
        else spec_named(&one, "stdillum-D65");
        m *= 2.0;
        for (k = 0; k < 3; k++) target[k] /= m;
        if (target[0] == target[1] && target[1] == target[2]) c[0] = c[1] = c[2] = 0.0;  /* s = 1/2 */
        else rgb_coeffs(T, target, c);
        for (i = 0; i < SPEC_N; i++) {
            double x = xs ? xs[i] : (double)i / (SPEC_N - 1);
            s->v[i] = (float)(m * sigmoid((c[0] * x + c[1]) * x + c[2]) * white->v[i]);
        }
        return 1;
    }
    if (target[0] == target[1] && target[1] == target[2]) {  /* grey: exactly constant */
        spec_const(s, (float)target[0]);
        return 1;
    }
    rgb_coeffs(T, target, c);
    for (i = 0; i < SPEC_N; i++) s->v[i] = albedo_knot(c, i);
    return 1;
}

/* Knot i of a reflectance's table: its sigmoid at x = i / (SPEC_N - 1), clamped
   to [0, 1] and rounded to float. */
float albedo_knot(const double c[3], int i)
{
    double x = (double)i / (SPEC_N - 1), v = sigmoid((c[0] * x + c[1]) * x + c[2]);
    return (float)(v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v);
}

/* spec_eval's interpolation over the knots albedo_knot computes (two per call);
   albedo_eval (specnee.h) calls it for an Albedo without a table. */
float albedo_eval_rgb(const Albedo *a, float lambda_nm)
{
    float t = lambda_nm - (float)SPEC_MIN, k0, k1;
    int i;
    if (!a->rgb) return 0.0f;                      /* a zeroed Albedo */
    if (!(t >= 0.0f) || t > (float)(SPEC_N - 1))
        /* the UV knots are 0: only [359, 360) nm ramps up to the knot at 360 nm */
        return t < 0.0f && t >= -1.0f ? (t + 1.0f) * albedo_knot(a->c, 0) : 0.0f;
    i = (int)t;
    if (i >= SPEC_N - 1) return albedo_knot(a->c, SPEC_N - 1);
    t -= (float)i;
    k0 = albedo_knot(a->c, i);
    k1 = albedo_knot(a->c, i + 1);
    return k0 + t * (k1 - k0);
}

int albedo_from_rgb(RgbTable *T, const float rgb[3], Albedo *a)
{
    double target[3];
    int k;
    for (k = 0; k < 3; k++) {
        if (!(rgb[k] >= 0.0f && rgb[k] <= 1.0f)) return 0;   /* NaN too */
        target[k] = rgb[k];
    }
    if (target[0] == target[1] && target[1] == target[2]) return 0;
    rgb_coeffs(T, target, a->c);
    a->tab = NULL;
    a->rgb = 1;
    return 1;
}

/* The sigmoid-polynomial fit of spec_from_rgb for one colour whose largest
   component is 1/2 (an RGB illuminant divided by twice its maximum): used by
   infinite.c, which tabulates it for image maps.  A grey target gives c = 0. */
void spec_rgb_coeffs(RgbTable *T, const double target[3], double c[3])
{
    if (target[0] == target[1] && target[1] == target[2]) { c[0] = c[1] = c[2] = 0.0; return; }
    rgb_coeffs(T, target, c);
}

/* ybar at the knots SPEC_MIN..SPEC_MAX (cie_ybar's values), from T's table. */
const double *spec_ybar_knots(RgbTable *T)
{
    return rgb_table_get(T)->ybar;
}

/* spec_to_y(s) with ybar read from T's knots instead of interpolated per knot:
   the same products and sums in the same order, so the same value. */
double spec_to_y_t(RgbTable *T, const Spectrum *s)
{
    double y = 0.0;
    int i;
    if (!T) return spec_to_y(s);
    rgb_table_get(T);
    for (i = 0; i < SPEC_N; i++) y += T->ybar[i] * s->v[i];
    return T->ybar_sum > 0.0 ? y / T->ybar_sum : 0.0;
}

void spec_rgb_table_start(RgbTable *T, const double target[3], double c[3])
{
    rgb_table_lookup(rgb_table_get(T), target, c);
}

void spec_rgb_coeffs_fit(const double target[3], double c[3])
{
    RgbFit fit;
    rgb_fit_init(&fit, COLORSPACE_SRGB);
    rgb_fit(&fit, target, c);
}

/* sigmoid((c0 x + c1) x + c2) with x = (lambda - SPEC_MIN) / (SPEC_MAX - SPEC_MIN),
   the spectral shape spec_from_rgb tabulates. */
float spec_sigmoid_eval(const float c[3], float lambda_nm)
{
    double x = ((double)lambda_nm - SPEC_MIN) / (double)(SPEC_N - 1);
    return (float)sigmoid(((double)c[0] * x + c[1]) * x + c[2]);
}
