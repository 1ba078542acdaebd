/* rgbtable.c - RGB -> spectrum coefficients by table lookup, without iteration.

   What it implements: pbrt-v4's way of upsampling rgb (Jakob & Hanika 2019): the
   sigmoid coefficients (c0, c1, c2) of rgbfit.c for a colour are
   interpolated from a precomputed grid of fitted coefficients.  The grid is
   rgbtable.h, written at build time by tools/gen_rgbtable.c from rgbfit.c's own
   fit, on the grid of rgbfit.c's rgb_grid_cell (the largest component's value z
   at Jakob & Hanika's smoothstep knots, the two others over z at equal steps,
   RGB_GRID_CELLS cells along each axis), interpolated by rgb_grid_interp
   (tricubic).  Each cell carries a trust bit, set where the interpolation was found
   within RGBT_TOL of the fit's spectrum (at the cell's centre and the centre of its
   lower z face).  The interpolation is poor where the coefficients grow fast (one
   component near 0: the sigmoid must reach 0 over a band), so the table answers
   only in trusted cells; elsewhere its interpolation is the start of rgbfit.c's
   Newton polish (rgbtable_lookup), and for very dark colours, outside the grid,
   rgbfit.c runs its own fit.  Accuracy against the fit over a dense set
   of colours: docs/loading.md and tests/test_spectrum.c (spectrum_rgbtable).

   How it is used: rgbfit.c's spec_from_rgb_t (a scene load) asks rgbtable_lookup
   first.  The table is constant data: no state, the same answer for any thread
   count and any order of colours.  tools/gen_rgbtable.c compiles this file with
   RGBTABLE_GENERATOR defined (the grid's functions, without the table it writes). */
#include "specnee.h"
#include <math.h>

/* The grid (tools/gen_rgbtable.c fills it):
   for the largest component m (ties to the first), the knot coordinate
   x in [0, RGB_GRID_CELLS] of z = rgb[m], z = smoothstep(smoothstep(x / RGB_GRID_CELLS))
   (Jakob & Hanika's knots: dense near 0 and 1; x = RGB_GRID_CELLS / 2 is z = 1/2,
   every rgb illuminant's), and a = rgb[m+1] / z, b = rgb[m+2] / z at equal steps.
   The coefficients are interpolated by Catmull-Rom cubics along the three axes
   (tricubic, 64 knots; error O(h^4) where trilinear's is O(h^2)), the knots
   beyond an edge extrapolated linearly from the two inside it. */
static double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

double rgb_grid_z(double x)
{
    double t = smoothstep(x / RGB_GRID_CELLS);
    return smoothstep(t);
}

static double smoothstep_inv(double y) { return 0.5 - sin(asin(1.0 - 2.0 * y) / 3.0); }

int rgb_grid_cell(const double target[3], int *m, int cell[3], double f[3])
{
    double z, x, a, b;
    *m = 0;
    if (target[1] > target[*m]) *m = 1;
    if (target[2] > target[*m]) *m = 2;
    z = target[*m];
    if (!(z > 0.0) || z > 1.0) return 0;
    x = RGB_GRID_CELLS * smoothstep_inv(smoothstep_inv(z));
    if (!(x >= 1.0)) return 0;                   /* below z_1: no table */
    a = target[(*m + 1) % 3] / z * RGB_GRID_CELLS;
    b = target[(*m + 2) % 3] / z * RGB_GRID_CELLS;
    cell[0] = x >= RGB_GRID_CELLS - 1 ? RGB_GRID_CELLS - 1 : (int)x;
    cell[1] = b >= RGB_GRID_CELLS - 1 ? RGB_GRID_CELLS - 1 : (int)b;
    cell[2] = a >= RGB_GRID_CELLS - 1 ? RGB_GRID_CELLS - 1 : (int)a;
    f[0] = x - cell[0];
    f[1] = b - cell[1];
    f[2] = a - cell[2];
    return 1;
}

/* Knot (zi, bi, ai) of slice m, coefficient k; beyond an edge (z index 0, the black
   slice, or -1 / RGB_GRID_CELLS + 1), the linear extrapolation 2 p_edge - p_inside. */
static double rgb_grid_at(const float *coef, int m, int zi, int bi, int ai, int k)
{
    const int n = RGB_GRID_CELLS + 1;
    if (zi < 1) return 2.0 * rgb_grid_at(coef, m, 1, bi, ai, k) - rgb_grid_at(coef, m, 2, bi, ai, k);
    if (zi > n - 1) return 2.0 * rgb_grid_at(coef, m, n - 1, bi, ai, k) - rgb_grid_at(coef, m, n - 2, bi, ai, k);
    if (bi < 0) return 2.0 * rgb_grid_at(coef, m, zi, 0, ai, k) - rgb_grid_at(coef, m, zi, 1, ai, k);
    if (bi > n - 1) return 2.0 * rgb_grid_at(coef, m, zi, n - 1, ai, k) - rgb_grid_at(coef, m, zi, n - 2, ai, k);
    if (ai < 0) return 2.0 * rgb_grid_at(coef, m, zi, bi, 0, k) - rgb_grid_at(coef, m, zi, bi, 1, k);
    if (ai > n - 1) return 2.0 * rgb_grid_at(coef, m, zi, bi, n - 1, k) - rgb_grid_at(coef, m, zi, bi, n - 2, k);
    return coef[3 * (((m * n + zi) * n + bi) * n + ai) + k];
}

/* Catmull-Rom weights of the knots -1, 0, 1, 2 at t in [0, 1]. */
static void catmull_rom(double t, double w[4])
{
    w[0] = ((-0.5 * t + 1.0) * t - 0.5) * t;
    w[1] = (1.5 * t - 2.5) * t * t + 1.0;
    w[2] = ((-1.5 * t + 2.0) * t + 0.5) * t;
    w[3] = (0.5 * t - 0.5) * t * t;
}

/* The 4 x 4 x 4 knots around a cell, weighted in the order dz, db, da; where all
   of them lie inside the grid (most cells), read in place, else through
   rgb_grid_at's extrapolation: the same sums either way. */
void rgb_grid_interp(const float *coef, int m, const int cell[3], const double f[3], double c[3])
{
    const int n = RGB_GRID_CELLS + 1;
    double wz[4], wb[4], wa[4];
    int dz, db, da, k, inside = 1;
    catmull_rom(f[0], wz);
    catmull_rom(f[1], wb);
    catmull_rom(f[2], wa);
    c[0] = c[1] = c[2] = 0.0;
    for (k = 0; k < 3; k++)
        if (cell[k] - 1 < (k == 0 ? 1 : 0) || cell[k] + 2 > n - 1) inside = 0;
    for (dz = 0; dz < 4; dz++)
        for (db = 0; db < 4; db++) {
            const float *row = inside ? coef + 3 * (((m * n + cell[0] + dz - 1) * n + cell[1] + db - 1) * n
                                                    + cell[2] - 1) : NULL;
            for (da = 0; da < 4; da++) {
                double w = wz[dz] * wb[db] * wa[da];
                for (k = 0; k < 3; k++)
                    c[k] += w * (row ? (double)row[3 * da + k]
                                     : rgb_grid_at(coef, m, cell[0] + dz - 1, cell[1] + db - 1,
                                                   cell[2] + da - 1, k));
            }
        }
}

#ifndef RGBTABLE_GENERATOR
#include "rgbtable.h"

/* The interpolation at target in any cell: 2 in a trusted cell, 1 in another
   (c is then a start for rgbfit.c's polish), 0 outside the grid (c untouched). */
int rgbtable_lookup(const double target[3], double c[3])
{
    double f[3];
    int m, cell[3], byte;
    if (!rgb_grid_cell(target, &m, cell, f)) return 0;
    byte = ((m * RGB_GRID_CELLS + cell[0]) * RGB_GRID_CELLS + cell[1]) * ((RGB_GRID_CELLS + 7) / 8)
           + cell[2] / 8;
    rgb_grid_interp(rgbt_c, m, cell, f, c);
    return (rgbt_ok[byte] >> (cell[2] % 8)) & 1 ? 2 : 1;
}

int rgbtable_coeffs(const double target[3], double c[3])
{
    double ci[3];
    if (rgbtable_lookup(target, ci) != 2) return 0;
    c[0] = ci[0]; c[1] = ci[1]; c[2] = ci[2];
    return 1;
}
#endif
