/* tests/test.h - the tiny test framework of specnee.

   A test is a function void test_xxx(T *t).  CHECK(t, cond, fmt, ...) records a
   failure with file:line and a message and returns from the test.  Each test file
   exports one NULL-terminated table, e.g. `const TestCase tests_bvh[]`, listed in
   tests/runner.c.  The runner prints one line per test and ends with
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
/* Render K seeds (base->seed + 1000 k) of s, n x n tiles: per-tile mean over seeds
   of the tile averages and its standard error.  Fails the test on any non-finite
   sample or pixel. */
int test_render_tiles(T *t, Scene *s, const RenderOptions *base, int K, int n, Tiles *out);
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
/* A surface point at the origin with normal +z. */
SurfacePoint test_flat_point(void);
/* The walls of a small open box [-1,1]^3, as scene text after WorldBegin. */
extern const char test_box_walls[];

/* test_spectrum.c: chi-square of wl_sample against wl_pdf_eval, stratification in wl_cdf. */
void check_wl_sampling(T *t, const WavelengthPdf *w, const char *what);

extern const TestCase tests_util[], tests_bvh[], tests_spectrum[], tests_scene[],
    tests_image[], tests_material[], tests_render[], tests_lights[], tests_scenes[],
    tests_physics[], tests_robust[], tests_lighttree[], tests_pbrt[], tests_wavelengths[],
    tests_sampler[], tests_fluor[], tests_delta[], tests_texture[], tests_shapes[], tests_filter[],
    tests_png[], tests_exr[], tests_conductor[], tests_coated[], tests_medium[];

#endif
