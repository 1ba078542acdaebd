/* tests/test.h - the tiny test framework of specnee.

   A test is a function void test_xxx(T *t).  CHECK(t, cond, fmt, ...) records a
   failure with file:line and a message and returns from the test.  Each test file
   exports one NULL-terminated table, e.g. `const TestCase tests_bvh[]`, listed
   once in tests/tables.h.  The runner prints one line per test and ends with
   "unit: N passed, N failed".

   Statistical tests state their confidence bound in the message: a mean is
   accepted when |mean - expected| < k * standard error with k given (usually 4,
   a two-sided false-alarm rate of 6e-5 per check), so a correct renderer passes
   and a biased one fails. */
#ifndef SPECNEE_TEST_H
#define SPECNEE_TEST_H
#include "../specnee.h"
#include <stdarg.h>

typedef struct {
    int failed;               /* set by CHECK */
    char msg[1024];           /* first failure message */
    const char *tmpdir;       /* a scratch directory for files the test writes */
} T;

typedef struct { const char *name; void (*fn)(T *t); } TestCase;

void test_failf(T *t, const char *file, int line, const char *fmt, ...);
/* Write text to tmpdir/name and return the path (static buffer per call slot). */
const char *test_write_file(T *t, const char *name, const char *text);
const char *test_path(T *t, const char *name);

/* Scale factor for sample counts of the statistical tests: SPECNEE_TEST_SCALE in
   the environment (default 1).  The sanitizer and slow-compiler runs use less; the
   confidence bounds are computed from the measured spread, so they stay valid. */
double test_scale(void);
/* n scaled by test_scale(), at least lo. */
int test_scaled(int n, int lo);

#define CHECK(t, cond, ...) do { if (!(cond)) { \
        test_failf((t), __FILE__, __LINE__, __VA_ARGS__); return; } } while (0)

/* ---- fixtures.c: random numbers drawn in a fixed order ----
   C leaves open the order in which a call's arguments are evaluated (gcc goes
   right to left, clang and tcc may go left to right), so f(rng_float(r),
   rng_float(r)) hands the two numbers to f in a compiler-dependent order, and a
   test would draw other samples under each compiler: a failure seen under one
   would not reproduce under another.  Draw them first, one statement each. */
/* u[0 .. n) = the next n numbers of r, in order. */
void rng_fill(Rng *r, float *u, int n);
/* (u0, u1, u2), the next three numbers of r, in order. */
Vec3 rng_vec3(Rng *r);
/* bsdf_sample with its three numbers drawn from r in order. */
int test_bsdf_sample(const Material *m, const SurfacePoint *sp, Vec3 wo, const float *lambda,
                     unsigned alive, Rng *r, BsdfSample *out);

/* ---- fixtures.c: shared by the statistical image tests ---- */
#define TEST_K_SIGMA 5.0     /* a mean is accepted within 5 standard errors */
#define MAX_TILES 16
typedef struct {
    int n;                   /* tiles per axis */
    double mean[MAX_TILES * MAX_TILES][3], se[MAX_TILES * MAX_TILES][3];
} Tiles;
/* Load a scene from text; fails the test (and returns 0) on a parse error. */
int test_load_scene(T *t, Scene *s, const char *text);
/* Load a scene from text and render it with o into *im (the caller frees it);
   fails the test (and returns 0) if it does not load or render. */
int test_render_text(T *t, const char *text, const RenderOptions *o, Image *im);
/* Load head + body as `file`; fails the test unless it is refused with `want` in the message. */
void test_refused(T *t, const char *head, const char *body, const char *file, const char *want);
/* A light statement as line 5 of a small "d.pbrt": fails unless refused in one line
   starting with prefix and holding k1 (and k2 unless NULL). */
void test_light_refused(T *t, const char *light, const char *prefix, const char *k1, const char *k2);
/* Mean image luminance over K renders (seeds 1 + 1000 k, 2 threads) and its standard error. */
int test_mean_y(T *t, const char *text, int spp, int nee, int K, double *mean, double *se);
/* Load text as m.pbrt: 1 if it is refused with k1 (and k2 unless NULL) in the
   message; else the test fails and 0 is returned. */
int test_load_fails(T *t, const char *text, const char *k1, const char *k2);
/* Load text as t.pbrt; the test fails unless it is refused with one line starting
   "t.pbrt:LINE:" that contains k1 (and k2 unless NULL). */
void test_rejected_at(T *t, const char *text, int line, const char *k1, const char *k2);
/* Render K seeds (base->seed + 1000 k) of s, n x n tiles: per-tile mean over seeds
   of the tile averages and its standard error.  Fails the test on any non-finite
   sample or pixel. */
int test_render_tiles(T *t, Scene *s, const RenderOptions *base, int K, int n, Tiles *out);
/* Luminance Y of linear sRGB (the CIE Y row of the sRGB to XYZ matrix). */
double test_luminance(const double rgb[3]);
/* The mean Y of an image's pixels. */
double test_image_y(const Image *im);
/* Y of tile i of tl; *se = its standard error from the three channels'. */
double test_tile_y(const Tiles *tl, int i, double *se);
/* Render s with the defaults, spp samples, 4 seeds from `seed`, and hold the
   luminance of the image and of its 2 x 2 quadrants (top left first) against
   frozen pbrt-v4 values pbrt[i] = { mean, standard error }: within TEST_K_SIGMA
   combined standard errors (specnee's from the green channel) + rel_slack of the
   value.  Messages start with `what`; DBG=1 prints every value. */
void test_scene_against_pbrt_y(T *t, Scene *s, int spp, int seed, const double pbrt[5][2], double rel_slack,
                               const char *what);
/* The same for `scene` (text) at test_scaled(64, 16) spp. */
void test_against_pbrt_y(T *t, const char *scene, int seed, const double pbrt[5][2], double rel_slack,
                         const char *what);
/* Render s with o, 6 seeds from o->seed, as 2 x 2 tiles, and hold the luminance of
   each quadrant (test_tile_y) and of the image (their mean, its standard error
   from theirs) against frozen pbrt-v4 values pbrt[5] = { image, top left, top
   right, bottom left, bottom right } (means only): within TEST_K_SIGMA standard
   errors + 2 % of a quadrant's value, 1 % of the image's. */
void test_quadrants_against_pbrt(T *t, Scene *s, const RenderOptions *o, const double pbrt[5], const char *what);
/* Two renders of base->spp samples merged by sample count against one render of
   twice the samples, over 10 seed triples: tile means within TEST_K_SIGMA
   standard errors (a w x h image, 4 x 4 tiles). */
void test_merge_agrees(T *t, const Scene *s, const RenderOptions *base, const char *what);
/* 1 if every tile and channel agrees within TEST_K_SIGMA standard errors + slack. */
int test_tiles_agree(T *t, const Tiles *a, const Tiles *b, double slack, const char *what);
/* A (rough, dispersive when B != 0) Cauchy glass A + B/lambda^2 with GGX alpha. */
void test_glass(Material *m, float A, float B, float alpha);
/* The cell of direction w in an nt x np grid over (cos theta in [-1,1], phi in
   [0, 2 pi)), row-major in cos theta: the chi-square tests of sampled directions. */
int test_dir_cell(Vec3 w, int nt, int np);

/* ---- fixtures.c: chi-square tests of samplers (Pearson's statistic, its p-value) ----
   Draw n samples, count them in cells, and compare the counts O_i with the
   expectations E_i = n x (the probability of cell i): X^2 = sum (O_i - E_i)^2 / E_i
   follows a chi-square distribution with (cells - 1) degrees of freedom when the
   sampler follows the density.  Cells expecting fewer than TEST_CHI2_MIN_EXPECTED
   are merged into one cell (it counts when its expectation reaches the minimum).
   The counts are rejected when the p-value P(chi^2_dof >= X^2) falls below the
   significance level: TEST_CHI2_ALPHA for the test as a whole, divided among its
   n_tests checks by the Sidak correction 1 - (1 - alpha)^(1/n_tests), so that a
   correct sampler fails a test with probability TEST_CHI2_ALPHA however many
   checks it makes. */
#define TEST_CHI2_ALPHA 1e-4
#define TEST_CHI2_MIN_EXPECTED 5.0
typedef struct {
    double stat;             /* Pearson's X^2 */
    int dof;                 /* cells counted - 1 (0: nothing to test) */
    double p;                /* P(chi^2_dof >= stat) */
    double total;            /* sum of the expected counts */
} Chi2;
/* P(chi^2_k >= x), the regularised upper incomplete gamma function Q(k/2, x/2). */
double chi2_tail(int k, double x);
/* X^2 of counts obs[0 .. n) against expected counts ex[0 .. n); fails the test
   (the message starts with the caller's file:line and the printf-style what) and
   returns 0 when p < the corrected significance level; *out (if not NULL) gets
   the statistic. */
int test_chi2_at(T *t, const char *file, int line, const double *obs, const double *ex, int n,
                 int n_tests, Chi2 *out, const char *what, ...);
#define CHECK_CHI2(t, obs, ex, n, n_tests, out, ...) do { \
        if (!test_chi2_at((t), __FILE__, __LINE__, (obs), (ex), (n), (n_tests), (out), __VA_ARGS__)) \
            return; } while (0)

/* Directions (pbrt-v4's Chi2Test, Nori's ChiSquareTest): n samples of a direction
   sampler on an nt x np grid over (cos theta in [-1, 1], phi in [0, 2 pi)), against
   its density integrated over each cell (a solid angle of (2 / nt)(2 pi / np)) by
   the two-point Gauss-Legendre rule on sub x sub sub-cells: 2 sub x 2 sub
   evaluations, none on a cell's edge (the horizon, where a BSDF's density jumps,
   is one).  A sampler that returns 0 made no sample (the
   density then integrates to less than 1). */
typedef struct {
    int (*sample)(void *ctx, Rng *r, Vec3 *w);
    double (*pdf)(void *ctx, const double w[3]);    /* per steradian */
    void *ctx;
    int n;                   /* samples */
    int nt, np, sub;         /* the grid and the sub-cells per axis */
} DirTest;
int test_chi2_dirs_at(T *t, const char *file, int line, const DirTest *d, Rng *r, int n_tests,
                      Chi2 *out, const char *what, ...);
#define CHECK_CHI2_DIRS(t, d, r, n_tests, out, ...) do { \
        if (!test_chi2_dirs_at((t), __FILE__, __LINE__, (d), (r), (n_tests), (out), __VA_ARGS__)) \
            return; } while (0)

/* The BSDF as a direction sampler: test_bsdf_sample of the hero lane (alive = 1)
   at the point sp, seen from wo, and bsdf_eval's pdf of the hero lane.  The
   chi-square BSDF test is test_bsdf_dirs(&b, n) under CHECK_CHI2_DIRS: a 16 x 32
   grid, 8 x 8 sub-cells per cell. */
typedef struct {
    const Material *m;
    SurfacePoint sp;
    Vec3 wo;
    float lambda[HERO_N];
} BsdfDirs;
int test_bsdf_dir_sample(void *ctx, Rng *r, Vec3 *w);
double test_bsdf_dir_pdf(void *ctx, const double w[3]);
DirTest test_bsdf_dirs(BsdfDirs *b, int n);
/* A surface point at the origin with normal +z. */
SurfacePoint test_flat_point(void);
/* Material.extra for a material built by hand (a conductor, a coat): zeroed static
   storage, a ring of 64 records reused in turn; never freed (no material_release). */
MaterialSpectra *test_material_extra(void);
/* A Spectrum for a test Material's eta (or reflectance.tab) to point at (a ring of
   64, as above). */
Spectrum *test_material_eta(void);
const Spectrum *test_eta_const(float eta);           /* test_material_eta, constant eta */
const Spectrum *test_eta_named(const char *name);    /* test_material_eta, spec_named */
/* A furnace: a closed cube [-2, 2]^3 whose walls emit L = 1 on both sides (seen
   at every angle down to grazing) and a unit sphere of `material` (a Material
   directive) near one edge, 8 x 8 pixels; the whole scene text into text[n]. */
void test_furnace_text(char *text, size_t n, const char *material);
/* The walls of a small open box [-1,1]^3, as scene text after WorldBegin. */
extern const char test_box_walls[];

/* test_spectrum.c: chi-square of wl_sample against wl_pdf_eval, stratification in wl_cdf. */
void check_wl_sampling(T *t, const WavelengthPdf *w, const char *what);

/* the tables of tests/tables.h: extern const TestCase tests_util[]; ... */
#define TEST_TABLE(x) extern const TestCase tests_##x[];
#include "tables.h"
#undef TEST_TABLE

#endif
