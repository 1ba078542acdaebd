/* tools/gen_rgbtable.c - writes rgbtable.h, the RGB -> spectrum coefficient table
   that rgbtable.c looks up (built and run by the Makefile; rgbtable.h is not kept
   in git).  docs/loading.md, "The coefficient table".

   What it computes, on rgbtable.c's grid (rgb_grid_z, rgb_grid_interp):
   - the knots: for each largest component m, each z knot x = 1..RGB_GRID_CELLS and
     each a, b = 0..RGB_GRID_CELLS, the colour's sigmoid coefficients by rgbfit.c's
     fit (spec_rgb_coeffs: its own start, polished until the fit converges), stored
     as floats (the black slice x = 0 is not used and left 0);
   - the trust bits: a cell (m, x, b, a) is trusted when, at its centre and at the
     centre of its lower z face (where every rgb illuminant lies), the interpolation
     (rgb_grid_interp) gives a spectrum within RGBT_TOL of the fit's at every
     wavelength 360-830 nm.  rgbtable.c answers from the table in trusted cells
     alone and leaves the others to the fit.
   The output is a function of rgbfit.c's fit and these constants.  This program
   links spectrum.c, rgbfit.c, util.c, metals.c and rgbtable.c compiled without its table
   (RGBTABLE_GENERATOR): its rgbtable_coeffs and rgbtable_lookup below answer
   "no table", so
   spec_rgb_coeffs here is the fit alone. */
#include "specnee.h"
#include <stdio.h>
#include <stdlib.h>
#include <math.h>

#define RGBT_TOL 7e-4          /* largest spectrum difference at a check point */
#define N1 (RGB_GRID_CELLS + 1)
#define OK_BYTES ((RGB_GRID_CELLS + 7) / 8)

int rgbtable_coeffs(const double target[3], double c[3])
{
    (void)target; (void)c;
    return 0;
}

int rgbtable_lookup(const double target[3], double c[3])
{
    (void)target; (void)c;
    return 0;
}

static float coef[3 * N1 * N1 * N1 * 3];                          /* [m][x][b][a][k] */
static unsigned char ok[3 * RGB_GRID_CELLS * RGB_GRID_CELLS * OK_BYTES];  /* [m][x][b][a/8] */
static unsigned char pass[3][RGB_GRID_CELLS][RGB_GRID_CELLS][RGB_GRID_CELLS];  /* checks met */

static double sig(const double c[3], double x)
{
    double p = (c[0] * x + c[1]) * x + c[2];
    return 0.5 + 0.5 * p / sqrt(1.0 + p * p);
}

/* The colour at knot coordinate x and a, b in [0, 1] of slice m. */
static void colour(int m, double x, double a, double b, double rgb[3])
{
    double z = rgb_grid_z(x);
    rgb[m] = z;
    rgb[(m + 1) % 3] = z * a;
    rgb[(m + 2) % 3] = z * b;
}

static void fit(RgbTable *T, const double rgb[3], double c[3])
{
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) { c[0] = c[1] = c[2] = 0.0; return; }
    spec_rgb_coeffs(T, rgb, c);
}

/* Largest |s_table - s_fit| over 360..830 nm at (fz, 1/2, 1/2) of cell (m, zi, bi, ai). */
static double cell_error(RgbTable *T, int m, int zi, int bi, int ai, double fz)
{
    double rgb[3], ci[3], cf[3], f[3], worst = 0.0;
    int cell[3], i;
    cell[0] = zi; cell[1] = bi; cell[2] = ai;
    f[0] = fz; f[1] = f[2] = 0.5;
    rgb_grid_interp(coef, m, cell, f, ci);
    colour(m, zi + fz, (ai + 0.5) / RGB_GRID_CELLS, (bi + 0.5) / RGB_GRID_CELLS, rgb);
    fit(T, rgb, cf);
    for (i = 0; i < SPEC_N; i++) {
        double x = (double)i / (SPEC_N - 1), d = fabs(sig(ci, x) - sig(cf, x));
        if (d > worst) worst = d;
    }
    return worst;
}

/* A cell is trusted when it and its 26 neighbours (those that exist) met the
   checks: the error peaks between the check points where a neighbour's is large. */
static int trusted(int m, int zi, int bi, int ai)
{
    int dz, db, da;
    for (dz = -1; dz <= 1; dz++)
        for (db = -1; db <= 1; db++)
            for (da = -1; da <= 1; da++) {
                int z = zi + dz, b = bi + db, a = ai + da;
                if (z < 1 || z >= RGB_GRID_CELLS || b < 0 || b >= RGB_GRID_CELLS || a < 0 ||
                    a >= RGB_GRID_CELLS) continue;
                if (!pass[m][z][b][a]) return 0;
            }
    return 1;
}

static void write_table(FILE *f, long n_ok)
{
    long i, n = 3L * N1 * N1 * N1 * 3, n_bytes = 3L * RGB_GRID_CELLS * RGB_GRID_CELLS * OK_BYTES;
    fprintf(f, "/* rgbtable.h - written by tools/gen_rgbtable.c (make); do not edit.\n"
               "   3 x %d^3 cells, %ld trusted (spectrum within %g of the fit). */\n",
            RGB_GRID_CELLS, n_ok, RGBT_TOL);
    fprintf(f, "#define RGBT_TOL %g\n", RGBT_TOL);
    /* flat arrays: nested braces make compilers slow on 300,000 numbers */
    fprintf(f, "/* [m][x][b][a][coefficient], RGB_GRID_CELLS + 1 knots along each */\n"
               "static const float rgbt_c[%ld] = {\n", n);
    for (i = 0; i < n; i++) fprintf(f, "%.9g,%s", (double)coef[i], i % 8 == 7 ? "\n" : " ");
    fprintf(f, "};\n/* [m][x][b][a / 8]: bit a %% 8 set where the cell is trusted */\n"
               "static const unsigned char rgbt_ok[%ld] = {\n", n_bytes);
    for (i = 0; i < n_bytes; i++) fprintf(f, "%d,%s", ok[i], i % 16 == 15 ? "\n" : " ");
    fprintf(f, "};\n");
}

int main(int argc, char **argv)
{
    RgbTable *T = rgb_table_new();
    FILE *f;
    long n_ok = 0;
    int m, zi, bi, ai, k;
    if (argc != 2 || !T) { fprintf(stderr, "usage: gen_rgbtable OUT.h\n"); return 2; }
    for (m = 0; m < 3; m++)
        for (zi = 1; zi < N1; zi++)
            for (bi = 0; bi < N1; bi++)
                for (ai = 0; ai < N1; ai++) {
                    double rgb[3], c[3];
                    colour(m, zi, (double)ai / RGB_GRID_CELLS, (double)bi / RGB_GRID_CELLS, rgb);
                    fit(T, rgb, c);
                    for (k = 0; k < 3; k++) coef[3 * (((m * N1 + zi) * N1 + bi) * N1 + ai) + k] = (float)c[k];
                }
    for (m = 0; m < 3; m++)
        for (zi = 1; zi < RGB_GRID_CELLS; zi++)
            for (bi = 0; bi < RGB_GRID_CELLS; bi++)
                for (ai = 0; ai < RGB_GRID_CELLS; ai++)
                    pass[m][zi][bi][ai] = cell_error(T, m, zi, bi, ai, 0.5) <= RGBT_TOL &&
                                          cell_error(T, m, zi, bi, ai, 0.0) <= RGBT_TOL;
    for (m = 0; m < 3; m++)
        for (zi = 1; zi < RGB_GRID_CELLS; zi++)
            for (bi = 0; bi < RGB_GRID_CELLS; bi++)
                for (ai = 0; ai < RGB_GRID_CELLS; ai++)
                    if (trusted(m, zi, bi, ai)) {
                        ok[((m * RGB_GRID_CELLS + zi) * RGB_GRID_CELLS + bi) * OK_BYTES + ai / 8] |=
                            (unsigned char)(1u << (ai % 8));
                        n_ok++;
                    }
    rgb_table_free(T);
    f = fopen(argv[1], "w");
    if (!f) { perror(argv[1]); return 1; }
    write_table(f, n_ok);
    if (fclose(f) != 0) { perror(argv[1]); return 1; }
    fprintf(stderr, "gen_rgbtable: %s: %ld of %d cells trusted\n", argv[1], n_ok,
            3 * (RGB_GRID_CELLS - 1) * RGB_GRID_CELLS * RGB_GRID_CELLS);
    return 0;
}
