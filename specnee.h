/* specnee.h - the one header of specnee, a teaching spectral path tracer in C99.

   ABOUT
     specnee renders scenes written in a subset of the pbrt-v4 scene format with a
     spectral path tracer: hero wavelength spectral sampling (HWSS, 4 wavelengths,
     Wilkie et al. 2014) combined by continuous/spectral MIS (West et al. 2020),
     next event estimation (NEE) with a choice of emitter-selection strategies, and
     dispersive glass whose index follows Cauchy's law.  It reproduces the thesis
     "Efficient Emitter Sampling for Spectral Path Tracing" (Deshmukh, van de Ruit,
     Eisemann, TU Delft 2022): the emitter for NEE is chosen in proportion to a
     table of the emitters' spectra at the hero wavelength (by default their
     emitted radiance, the thesis' "unit emission"; optionally times the area, the
     thesis' "power"), times a spatial estimate (`--preset thesis` sets exactly
     the thesis' configuration).  The defaults go further, each chosen by measured
     error at equal time (docs/RESULTS.md, "What to use"): a spectral light tree
     that keeps the thesis' spectral preference at O(log N) per vertex
     (docs/lighttree.md), wavelengths sampled from the emitters' spectra mixed with
     a visible-range pdf (docs/wavelengths.md), Owen-scrambled Sobol' samples
     (docs/sampling.md), and spectral MIS at rough dispersive glass.  Fluorescent
     surfaces and ultraviolet lamps, the thesis' future work, are in
     docs/FLUORESCENCE.md.  docs/THEORY.md derives the estimator;
     docs/WALKTHROUGH.md follows one sample through the code.

     Read this header top to bottom: it walks from the tunables through the math
     types, spectra, geometry, materials, emitters, the integrator and the images,
     in the order the renderer uses them.  Each .c file opens with the equations it
     implements.

   BUILDING
     make                     # gcc or clang, OpenMP when the compiler has it
     make CC=tcc              # any C99 compiler works
     cc -std=c99 -O2 *.c -lm -o specnee     # the one-line fallback (no OpenMP)

   USAGE
     specnee [options] scene.pbrt          render (see `specnee --help`)
     specnee merge a.pfm b.pfm ... -o out.pfm
     specnee diff test.pfm ref.pfm [--region NAME:x0,y0,x1,y1] [--error-image e.png]
                  [--max-mse X] [--max-relmse Y] [--csv]
     specnee spectrum NAME|FILE            (--svg NAME... > plot.svg, --list)
     specnee converge scene.pbrt --ref ref.pfm --lights a,b:mod --spp 16,32 --seeds K
                  [--time cpu|wall] [--reuse]   (error against time: docs/RESULTS.md)

   OUTPUT
     .pfm: linear sRGB (D65) float32, rows bottom to top (netpbm PFM), negative
     values kept; a sidecar "<file>.txt" records spp, seed and the settings.
     .ppm/.png: 8-bit with the sRGB transfer curve, after an optional exposure.

   CONVENTIONS (docs/conventions.md has the details)
     - pbrt-v4 meaning: left-handed camera frame (LookAt's right = up x dir), fov on
       the shorter image axis, area-light spectra normalised so that Y = scale.
     - Wavelengths in nanometres; Cauchy's B in square micrometres.
     - No hidden globals: every function gets what it needs as arguments.
*/
#ifndef SPECNEE_H
#define SPECNEE_H

#include <stddef.h>
#include <stdlib.h>
#include <stdint.h>
#include <stdio.h>
#include <math.h>

/* ======================================================================
   1. CONFIG: every tunable in one place (@@ marks what it trades off)
   ====================================================================== */
#define HERO_N 4            /* @@ wavelengths carried per path (HWSS cluster size) */
#define SPEC_MIN 360        /* @@ first nm of the dense spectrum table (pbrt-v4's range) */
#define SPEC_MAX 830        /* @@ last nm of the dense spectrum table */
#define SPEC_N (SPEC_MAX - SPEC_MIN + 1) /* 471 samples, 1 nm apart */
#define SPEC_UV_MIN 300     /* @@ first nm of the UV extension of every spectrum: emitters and
                               fluorescent excitation reach down to here (docs/FLUORESCENCE.md
                               section 6); the camera's colour matching stays >= SPEC_MIN */
#define SPEC_UV_N (SPEC_MIN - SPEC_UV_MIN)  /* 60 more samples, 300..359 nm */
#define CIE_Y_INTEGRAL 106.856895  /* pbrt-v4's integral of ybar over 360..830 nm (nm) */
#define LAMBDA_LO 400.0f    /* @@ default sampled range: the thesis' 400-700 nm */
#define LAMBDA_HI 700.0f
#define SPD_BINS 60         /* thesis: 60 bins over 400-700 nm ... */
#define SPD_BIN_NM 5.0f     /* ... i.e. 5 nm each */
#define SPD_UV_BINS 20      /* beyond the thesis: 20 more 5 nm bins over 300-400 nm, for the
                               excitation wavelengths of fluorescence (thesis' future work) */
#define BVH_LEAF_MAX 4      /* @@ primitives per BVH leaf: deeper trees vs. more tests */
#define BVH_BINS 16         /* @@ SAH bins per axis: build time vs. tree quality */
#define SAH_DEPTH_MAX 32    /* below this depth the BVH build splits at the middle, which
                               bounds the traversal stack (bvh.c BVH_STACK) */
#define SPATIAL_RES 64      /* @@ voxels on the longest axis of the spatial grid (pbrt-v3) */
#define SPATIAL_SAMPLES 128 /* @@ receiver points per voxel (pbrt-v3) */
#define LIGHT_TREE_BINS 12  /* @@ split candidates per axis in the light tree build */
#define LIGHT_CLUSTER_TRIS 4 /* @@ triangles per light-tree leaf of a split emissive mesh */
#define REACH_MAX_TRIS 64   /* @@ emitter meshes up to this size get the exact per-triangle
                               "which side does it light" test (lights.c section 4) */
#define RR_START_DEPTH 1    /* @@ Russian roulette from this depth on (pbrt-v4: after depth 1) */
#define LOBE_REUSE_MIN 0.00390625 /* @@ 2^-8: a smooth dielectric's rescaled lobe number is
                               reused while the chosen lobes' probabilities multiply to at
                               least this; its 2^-24 steps then stay below 2^-16 (THEORY §8.1) */
#define DEFAULT_SPP 16
#define DEFAULT_MAXDEPTH 5  /* pbrt-v4's default for Integrator "path" */
#define MEM_BUDGET_MIB 4096  /* @@ memory budget of one input-sized allocation (film,
                                mesh, image): a bigger claim is an error naming the need */
#define FILM_BYTES_PER_PIXEL 48  /* render buffers a film pixel costs: 3 doubles of sums,
                                1 double of filter weights (mitchell, sinc), 3 floats of
                                image, 4 bytes of writer output */
#define FILTER_CELLS 256    /* @@ cells of the Gaussian pixel filter's sampling table
                               (1/85 pixel for radius 1.5): accuracy vs. table size */
#define FILTER_TABLE_MAX 512 /* cells of a filter table: pbrt-v4's 32 per unit of radius
                               (mitchell, sinc) at the largest radius, 16 */
#define FILTER_GAUSS_CELLS 64 /* @@ cells of [0, radius] for the exact Gaussian from the
                                independent sampler's stream (filter.c): more cells
                                accept more often, at a larger table */
#define FILTER_GUIDE_MAX 2048 /* steps of a filter table's guide: cdf_guide_size of
                                FILTER_TABLE_MAX cells (the smallest power of two >= 4 n) */
#define SPECNEE_PI 3.14159265358979323846
#define PI_F 3.14159265358979323846f

/* ======================================================================
   2. Small math: vectors, rays, 4x4 transforms, a counter-based RNG (util.c),
      samplers (sampler.c)
   ====================================================================== */
typedef struct {
    float x, y, z;
#ifdef __TINYC__
    float tcc_pad;   /* tcc 0.9.27 on x86-64 writes 16 bytes when a function returns
                        a 12-byte struct, clobbering the next local: pad it to 16 */
#endif
} Vec3;

static inline Vec3 v3(float x, float y, float z)
{ Vec3 r; r.x = x; r.y = y; r.z = z;
#ifdef __TINYC__
  r.tcc_pad = 0.0f;
#endif
  return r; }
static inline Vec3 v3_add(Vec3 a, Vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline Vec3 v3_sub(Vec3 a, Vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline Vec3 v3_mul(Vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline Vec3 v3_neg(Vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline float v3_dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline Vec3 v3_cross(Vec3 a, Vec3 b)
{ return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static inline float v3_len(Vec3 a) { return sqrtf(v3_dot(a, a)); }
static inline Vec3 v3_norm(Vec3 a) { float l = v3_len(a); return l > 0 ? v3_mul(a, 1.0f / l) : a; }
static inline Vec3 v3_min(Vec3 a, Vec3 b)
{ return v3(a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z); }
static inline Vec3 v3_max(Vec3 a, Vec3 b)
{ return v3(a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z); }
static inline float v3_get(Vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }

/* An orthonormal frame (s, t, n) around a unit normal n (Duff et al. 2017). */
typedef struct { Vec3 s, t, n; } Frame;
Frame frame_from_normal(Vec3 n);
static inline Vec3 frame_to_local(const Frame *f, Vec3 v)
{ return v3(v3_dot(v, f->s), v3_dot(v, f->t), v3_dot(v, f->n)); }
static inline Vec3 frame_to_world(const Frame *f, Vec3 v)
{ return v3_add(v3_add(v3_mul(f->s, v.x), v3_mul(f->t, v.y)), v3_mul(f->n, v.z)); }

typedef struct {
    Vec3 o, d;      /* origin and direction (not necessarily unit length) */
    float tmax;     /* the ray is the segment o + t d, 0 < t < tmax */
    float time;     /* the camera ray's time in the shutter, kept by every ray of its
                       path (motion.c); read only where something moves */
} Ray;

/* Row-major 4x4 matrix with its inverse: points p' = M p (p as a column vector). */
typedef struct { double m[4][4], inv[4][4]; } Xform;
Xform xf_identity(void);
Xform xf_mul(const Xform *a, const Xform *b);          /* a * b: apply b first */
Xform xf_translate(double x, double y, double z);
Xform xf_scale(double x, double y, double z);
Xform xf_rotate(double deg, double x, double y, double z);
int   xf_lookat(double ex, double ey, double ez, double lx, double ly, double lz,
                double ux, double uy, double uz, Xform *out);  /* 0 if degenerate */
int   xf_from_matrix(double m[4][4], Xform *out);                /* 0 if singular */
Vec3  xf_point(const Xform *t, Vec3 p);
Vec3  xf_vector(const Xform *t, Vec3 v);
Vec3  xf_normal(const Xform *t, Vec3 n);              /* by the inverse transpose */
int   xf_swaps_handedness(const Xform *t);            /* det of the 3x3 part < 0 */

/* PCG32 (O'Neill 2014), keyed by work item: every (pixel, sample) owns its stream,
   so the image does not depend on the thread count or schedule. */
typedef struct { uint64_t state, inc; } Rng;
/* 64-bit mix of two keys (util.c's comment: splitmix64's finaliser); inline, as the
   samplers call it for nearly every number they hand out.  In three parts, so that
   a caller hashing many b with one a (sampler.c: a pixel's groups) can keep a's
   share of the first step, hash_a_mul(a) and hash_a_add(a), and finish each hash as
   hash_mix(mul ^ (b + add)): the same number to the bit (unsigned sums wrap
   mod 2^64, so their order does not matter). */
static inline uint64_t hash_a_mul(uint64_t a) { return a * 0x9E3779B97F4A7C15ull; }
static inline uint64_t hash_a_add(uint64_t a) { return 0x632BE59BD9B4E019ull + (a << 6) + (a >> 2); }
static inline uint64_t hash_mix(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static inline uint64_t hash_u64(uint64_t a, uint64_t b)
{
    return hash_mix(hash_a_mul(a) ^ (b + hash_a_add(a)));
}
void     rng_seed(Rng *r, uint64_t stream, uint64_t index);
uint32_t rng_u32(Rng *r);
float    rng_float(Rng *r);                          /* uniform in [0, 1) */

/* Radical inverse of i in a prime base (Halton points, for deterministic tables). */
double radical_inverse(int base, uint64_t i);

/* Inverse-CDF sampling of a table of n cells (cdf[]: n + 1 entries, 0 to 1, never
   decreasing, cdf[n] = 1) through a guide table of m + 1 entries, m a power of two
   (util.c; cdf_guide_size(n) is the smallest one >= 4 n): cdf_cell returns the
   cell k with cdf[k] <= u < cdf[k + 1], the same with or without (NULL, or m = 0)
   the guide.
   Inline: it runs four times per camera sample for the wavelengths and twice for
   the pixel filter (docs/speed.md). */
int  cdf_guide_size(int n);
void cdf_guide(const float *cdf, int n, int *guide, int m);
static inline int cdf_cell(const float *cdf, int n, const int *guide, int m, double u)
{
    int lo = 0, hi = n;                          /* invariant: cdf[lo] <= u < cdf[hi] */
    if (guide && m > 0 && u >= 0.0 && u < 1.0) {
        const int g = (int)(u * m);              /* exact: g / m <= u < (g + 1) / m */
        lo = guide[g];                           /* cdf[lo] <= g / m <= u */
        hi = guide[g + 1] + 1;                   /* hi = n, or cdf[hi] > (g + 1) / m > u */
    }
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if ((double)cdf[mid] <= u) lo = mid; else hi = mid;
    }
    return lo;
}

/* ---- Samplers (sampler.c): the number for a (pixel, sample, dimension) ----
   Every random decision of the renderer asks the sampler for its number by its
   DIMENSION.  The table (docs/sampling.md explains it):

     dim            numbers  decision                              group
     0, 1           2-D      position in the pixel (pixel filter)  camera
     2, 3           2-D      a point on a thin lens (lensradius>0) lens
     4              1-D      hero wavelength u (HWSS rotates the   wavelength
                             other three by j/4)
     then for bounce d = 0, 1, ... at DIM_BOUNCE0 + d * DIMS_PER_BOUNCE + slot:
     +0 BD_LIGHT    1-D      which emitter NEE picks (light_select)
     +1 BD_TRIANGLE 1-D      which triangle of that emitter (by area)
     +2 BD_POINT    2-D      the point on the triangle / sphere
     +4 BD_LOBE     1-D      reflect or refract (dielectrics; path.c lobe_number may
                             reuse the previous smooth choice's number instead)
     +5 BD_DIR      2-D      the BSDF direction
     +7 BD_ROULETTE 1-D      Russian roulette after the bounce
     and at a fluorescent vertex of bounce d (docs/FLUORESCENCE.md), beyond every
     bounce's dimensions (maxdepth <= 10000):
     DIM_FLUOR0 + 2d  2-D    re-radiate or reflect, and the absorbed wavelength (with
                             --fluor-li power the second number also picks the
                             mixture's component, rescaled: no extra dimension)
     and in a participating medium (docs/media.md), for segment s of bounce d:
     DIM_MEDIUM0 + 64d + s  1-D  the free-flight distance (a scatter vertex then
                             uses the bounce's BD_LIGHT..BD_POINT for NEE and
                             BD_DIR for the phase function's direction)
     and where the path of bounce d refracts into a subsurface material
     (subsurface.c), at dim_sss(d) + slot: BD_LIGHT..BD_POINT for NEE at the exit
     and BD_DIR for the exit lobe's direction, as a bounce's, and SSS_AXIS,
     SSS_RADIUS (2-D: radius, angle) and SSS_PICK for the probe,
     so a scene without media asks for no number beyond the bounces' and the
     fluorescent vertices'.  When the camera sits in a medium, sobol and zsobol
     serve 0, 1, DIM_WAVELENGTH and dim_medium(0, 0) as ONE 4-D group (sampler.c,
     THE CAMERA GROUP).  A scene where something moves (motion.c) also asks, after
     the lens, for
     DIM_TIME       1-D    the camera sample's time in the shutter
     which a static scene never does (its numbers stay those without motion).

   A GROUP is one request: the two numbers of a 2-D group map together onto a 2-D
   domain (pixel, triangle, hemisphere), so they must be spread as a 2-D point
   set; every group gets its own scramble and sample order (padding), so groups
   are decorrelated and any number of bounces can be served by 2-D sequences.
   No two decisions share a dimension: two decisions driven by one number would
   be correlated (and biased).  Each sample counts a dimension asked for twice
   (RenderStats.dims_reused, which must stay 0). */
#define DIM_FILM 0
#define DIM_LENS 2
#define DIM_WAVELENGTH 4
#define DIM_BOUNCE0 5
#define DIMS_PER_BOUNCE 8
enum { BD_LIGHT = 0, BD_TRIANGLE = 1, BD_POINT = 2, BD_LOBE = 4, BD_DIR = 5, BD_ROULETTE = 7 };
static inline int dim_bounce(int depth, int slot) { return DIM_BOUNCE0 + depth * DIMS_PER_BOUNCE + slot; }
#define DIM_FLUOR0 (1 << 20)
static inline int dim_fluor(int depth) { return DIM_FLUOR0 + 2 * depth; }
#define DIM_MEDIUM0 (1 << 21)
#define MEDIUM_SEGMENTS 64  /* @@ ray segments one bounce may cross (Material "interface"
                               boundaries of media); a path that needs more ends there */
static inline int dim_medium(int depth, int seg) { return DIM_MEDIUM0 + MEDIUM_SEGMENTS * depth + seg; }
/* equiangular sampling on segment s of bounce d (THEORY §12.1): EQ_T the distance,
   EQ_LAMP which lamp, EQ_POINT (2-D) the point on it */
#define DIM_EQUI0 (1 << 24)
enum { EQ_T = 0, EQ_LAMP = 1, EQ_POINT = 2, DIMS_PER_EQUI = 4 };
static inline int dim_equi(int depth, int seg, int slot)
{
    return DIM_EQUI0 + DIMS_PER_EQUI * (MEDIUM_SEGMENTS * depth + seg) + slot;
}
#define DIM_SSS0 (1 << 22)
enum { SSS_AXIS = 8, SSS_RADIUS = 9, SSS_PICK = 11, DIMS_PER_SSS = 16 };
static inline int dim_sss(int depth) { return DIM_SSS0 + DIMS_PER_SSS * depth; }
#define DIM_TIME (1 << 23)
#define HALTON_BOUNCES 4      /* halton: the bounces whose dimensions join the Halton point */
#define HALTON_DIMS (DIM_BOUNCE0 + HALTON_BOUNCES * DIMS_PER_BOUNCE)
#define HALTON_PERM_N 11725   /* sum over the HALTON_DIMS + 1 bases p of p x (digits for 2^24) */
#define SAMPLER_CHECKED_DIMS 256   /* dimensions whose reuse is counted (31 bounces) */

typedef enum {
    SAMPLER_INDEPENDENT,       /* PCG32 per (pixel, sample), dimensions drawn in request order */
    SAMPLER_STRATIFIED,        /* jittered strata (pbrt-v4 xsamples, ysamples, jitter) */
    SAMPLER_SOBOL,             /* padded Owen-scrambled Sobol per pixel (Burley 2020) */
    SAMPLER_ZSOBOL,            /* one Sobol sequence over the film in Morton order (pbrt-v4) */
    SAMPLER_HALTON,            /* one scrambled Halton point per sample over the first
                                  HALTON_DIMS dimensions (pbrt-v4's "halton"), then padded */
    SAMPLER_COUNT
} SamplerType;

typedef struct {
    SamplerType type;
    uint32_t seed;             /* --seed: different seeds give independent scrambles */
    int spp;                   /* samples per pixel of the render (stratified, zsobol use it) */
    int xsamples, ysamples;    /* stratified: the 2-D strata, xsamples * ysamples = spp */
    int jitter;                /* stratified: 1 = random point in the stratum, 0 = centre */
    int log2_spp;              /* zsobol: 2^log2_spp >= spp indices per pixel */
    uint64_t seed_mul, seed_add;   /* zsobol: hash_a_mul(seed), hash_a_add(seed): each group's
                                  hash_u64(seed, g) finishes from them (sampler.c, sobol_index) */
    int camera_medium;         /* sobol, zsobol: 1 = the camera sits in a rendered medium; its
                                  first free flight and the wavelength join the pixel's group */
    /* halton: one random permutation of the base-p digits per coordinate and digit
       position, drawn from the seed by sampler_init (the same over the film; each
       pixel adds its own digit shifts; sampler.c, "Halton") */
    unsigned short halton_off[HALTON_DIMS + 1];   /* coordinate j's first table */
    unsigned char halton_ndig[HALTON_DIMS + 1];   /* its digit positions with a table */
    unsigned char halton_perm[HALTON_PERM_N];     /* the tables, p entries each */
    unsigned char halton_inv[HALTON_PERM_N];      /* their inverses */
    /* Sobol dimensions 2 and 3 (the camera group): for each byte b of the index
       and its value v, the XOR of the columns of v's bits, digits reversed
       (sampler.c, sobol23_tables) */
    uint32_t sobol23_rev[2][4][256];
} Sampler;

typedef struct {               /* one sample of one pixel, on the stack of the tracer */
    const Sampler *s;
    uint64_t key;              /* hash of (x, y, seed) */
    uint64_t key_mul, key_add; /* hash_a_mul(key), hash_a_add(key): hash_u64(key, g) of
                                  each group finishes from them (sampler.c, key_hash) */
    uint64_t index;            /* zsobol: Morton code of the pixel x 2^log2_spp + k */
    uint32_t k;                /* sample index in the pixel */
    uint32_t k_reversed;       /* its bits reversed (sobol's index scramble starts there) */
    uint32_t low_reversed;     /* zsobol: index's low 32 bits reversed (its scramble's start) */
    Rng rng;                   /* independent: the sample's PCG32 stream */
    uint32_t used[SAMPLER_CHECKED_DIMS / 32];  /* dimensions asked for so far */
    int reused;                /* dimensions asked for a second time */
    /* halton: what coordinate j's digit scramble takes from the pixel alone, kept
       over the pixel's samples (sampler_restart): bit j of halton_have says slot j
       is filled; Z's value z0, its rest z1 after the first base-p digit b_0, and
       pi_0^-1(b_0) (sampler.c, halton_coord) */
    uint64_t halton_have;
    double halton_z0[HALTON_DIMS + 1], halton_z1[HALTON_DIMS + 1];
    unsigned char halton_c0[HALTON_DIMS + 1];
} PixelSample;

/* xsamples/ysamples: the file's strata (0: factor spp into two near-equal factors,
   as pbrt-v4 does when --spp overrides them). */
void  sampler_init(Sampler *s, SamplerType type, int seed, int spp, int xsamples, int ysamples,
                   int jitter);
void  sampler_start(const Sampler *s, int x, int y, int k, PixelSample *ps);
/* Sample k of the pixel ps was started on: the same numbers as sampler_start with
   that pixel and k, keeping what depends on the pixel only (the render loop takes
   a pixel's samples in a row). */
void  sampler_restart(PixelSample *ps, int k);
float sampler_1d(PixelSample *ps, int dim);                     /* in [0, 1) */
void  sampler_2d(PixelSample *ps, int dim, float *u0, float *u1);  /* dims dim, dim + 1 */
/* The independent sampler's raw stream, for the one consumer that needs a
   variable count of numbers (the Gaussian filter's rejection loop, the independent
   sampler's way of drawing the Gaussian: filter.c); NULL for the other samplers. */
Rng  *sampler_stream(PixelSample *ps);
/* 1 if sample k does not depend on spp (a progressive render equals separate ones). */
int   sampler_progressive(SamplerType t);
SamplerType sampler_from_name(const char *name);   /* SAMPLER_COUNT if unknown */
const char *sampler_name(SamplerType t);
uint32_t sobol_u32(uint32_t i, int dim);            /* Sobol dimension 0..3, 32 bits */
uint32_t owen_scramble(uint32_t x, uint32_t seed);  /* nested uniform scramble of x's digits */

/* ======================================================================
   3. Errors: libraries return, only main exits (util.c)
   ====================================================================== */
/* Every loader writes one line "file:line: problem" into an Error and returns 0. */
typedef struct { char msg[512]; } Error;
/* Control bytes and bytes that are not UTF-8 are written as \xNN: one printable line. */
void error_set(Error *e, const char *file, int line, const char *fmt, ...);

/* A whole file in memory, NUL-terminated (scene text, PLY, spectrum files).  flags:
   READ_TEXT refuses a NUL byte; gzip data (first bytes 1F 8B) is refused at once,
   unless READ_GUNZIP asks for it as it is (compressed; png.c's read_whole_file_gz
   then inflates it: pbrt-v4's .pbrt.gz and .ply.gz).  Reading stops early where
   magic is not NULL and the first bytes are not magic; never more than
   READ_MAX_BYTES.  NULL and *st on failure. */
#define READ_MAX_BYTES ((size_t)1 << 30)   /* @@ 1 GiB: largest input file read */
#define READ_TEXT 1
#define READ_GUNZIP 2
typedef enum { READ_OK, READ_OPEN, READ_IO, READ_NOMEM, READ_TOO_BIG, READ_GZIP,
               READ_NUL, READ_MAGIC, READ_GZ_TRUNC, READ_GZ_HEADER, READ_GZ_DATA,
               READ_GZ_CRC, READ_GZ_SIZE, READ_GZ_BIG } ReadStatus;
char *read_whole_file(const char *path, int flags, const char *magic, size_t *len,
                      ReadStatus *st);
const char *read_status_text(ReadStatus st);   /* "not a text file (...)", ... */
/* A gzip file in[0 .. n) (RFC 1952: members with their CRC-32 and ISIZE checked)
   inflated into a new buffer *out of *n_out bytes and a NUL, at most max_out bytes
   (png.c, next to its inflate): READ_OK, or a READ_GZ_ status (or READ_NOMEM). */
ReadStatus gzip_inflate(const unsigned char *in, size_t n, size_t max_out, unsigned char **out,
                        size_t *n_out);
/* read_whole_file for the files pbrt-v4 reads compressed (scene text, PLY): gzip
   data is inflated (at most READ_MAX_BYTES), then checked against text and magic
   as a plain file is (png.c). */
char *read_whole_file_gz(const char *path, int flags, const char *magic, size_t *len,
                         ReadStatus *st);

/* ======================================================================
   4. Spectra (spectrum.c; the metals' data in metals.c, wavelength sampling in
      wavelengths.c)
   A spectrum is a dense table at 1 nm over SPEC_MIN..SPEC_MAX (pbrt-v4's range),
   evaluated by linear interpolation; zero outside.  A UV extension uv[] holds
   SPEC_UV_MIN..SPEC_MIN-1 (300-359 nm): zero unless the spectrum's source defines it
   there (constants, blackbody, Cauchy/Sellmeier indices, wavelength pairs or files
   that list UV wavelengths, the named UV lamps and fluorophores); spectra from rgb
   have none.  Only fluorescence ever evaluates a spectrum below SPEC_MIN, so the UV
   extension changes no render of a scene without it (docs/FLUORESCENCE.md §6).  Every
   source of a spectrum
   (inline pairs, named spectra, files, rgb) is resampled into this table once at
   load time, so rendering never searches a list.
   ====================================================================== */
typedef struct { float v[SPEC_N]; float uv[SPEC_UV_N]; } Spectrum;
/* The sample at integer nm in SPEC_UV_MIN..SPEC_MAX (the caller keeps nm in range). */
static inline float *spec_at(Spectrum *s, int nm)
{ return nm < SPEC_MIN ? &s->uv[nm - SPEC_UV_MIN] : &s->v[nm - SPEC_MIN]; }
static inline float spec_get(const Spectrum *s, int nm)
{ return nm < SPEC_MIN ? s->uv[nm - SPEC_UV_MIN] : s->v[nm - SPEC_MIN]; }

float spec_eval(const Spectrum *s, float lambda_nm);
/* Spectra shared by reference: a scene keeps one record per distinct table
   (Scene.spectra), and what holds a spectrum that is often repeated (an
   Emitter's L) points at it.  spec_store_add returns the record equal to s
   byte for byte, adding a copy of s when there is none (NULL: out of memory);
   a record never moves or changes until spec_store_free. */
typedef struct {
    Spectrum **rec; int n, cap;     /* the records, each its own allocation */
    unsigned *hash;                 /* hash of each record's bytes */
    int *slot; int n_slots;         /* hash of the bytes -> 1 + record index (0: empty) */
} SpectrumStore;
const Spectrum *spec_store_add(SpectrumStore *st, const Spectrum *s);
void  spec_store_free(SpectrumStore *st);
/* spec_eval of the table (float)(num * s / den) (num * s a float product) at every
   knot, bit for bit, without storing it (lights.c: an emitter's Le = scale L / norm). */
float spec_eval_scaled(const Spectrum *s, float num, double den, float lambda_nm);
void  spec_const(Spectrum *s, float value);
int   spec_is_constant(const Spectrum *s);
/* From (lambda, value) pairs, piecewise linear, zero outside the listed range
   (pbrt-v4).  Lambdas must increase strictly; returns 0 and fills err otherwise. */
int   spec_from_pairs(Spectrum *s, const float *lambda, const float *value, int n, Error *err,
                      const char *file, int line);
/* Built-in named spectra: stdillum-D65, stdillum-F1..F12, the thesis' lamps
   (lamp-CFL1, lamp-LED1, lamp-LED2), glass-* indices, ...  Returns 0 if unknown. */
int   spec_named(Spectrum *s, const char *name);
const char *const *spec_named_list(void);   /* NULL-terminated list of the names */
/* The metals' optical constants by pbrt-v4's names, metal-Ag-eta, metal-Ag-k, ...
   (metals.c: the data and their sources); spec_named asks it.  0 if unknown. */
int   metal_named(Spectrum *s, const char *name);
/* A file of wavelength/value pairs: pbrt .spd text or CSV (optional header). */
int   spec_from_file(Spectrum *s, const char *path, Error *err);
/* RGB upsampled to a smooth spectrum, pbrt-v4's way: illuminant 0, a reflectance
   (0..1); 1, an illuminant (times the colour space's white: D65 for srgb, dci-p3,
   rec2020 and T NULL, ACES's D60 for aces2065-1); 2, unbounded (a medium's
   coefficients); fitted in T's colour space (rgb_table_new_cs).
   spec_from_rgb_t starts each fit from the coefficient table T, which its owner
   (a scene load: parser.h's Parser) makes with rgb_table_new and frees with
   rgb_table_free; slices are filled on first use, each by a fixed sweep, so the
   spectra do not depend on the order of the colours.  T NULL, and spec_from_rgb:
   the full fit from grey, without a table. */
typedef struct RgbTable RgbTable;
RgbTable *rgb_table_new(void);      /* NULL: out of memory */
/* pbrt-v4's colour spaces (rgbfit.c; docs/spectra.md): the ColorSpace directive's
   names (case-insensitive; -1 unknown), each space's white illuminant (stdillum-D65,
   or illum-acesD60 for aces2065-1; Y = 1), its XYZ -> RGB matrix, and a coefficient
   table whose fits are in that space (rgb_table_new: srgb). */
#define COLORSPACE_SRGB 0
#define COLORSPACE_ACES 3      /* aces2065-1 */
#define COLORSPACE_N 4
int   colorspace_index(const char *name);
const char *colorspace_name(int cs);
void  colorspace_illuminant(int cs, Spectrum *s);
void  colorspace_from_xyz(int cs, double m[3][3]);
void  colorspace_rgb_from_xyz(int cs, const double xyz[3], double rgb[3]);
/* Y = y . rgb in space cs (pbrt-v4's LuminanceVector; sRGB's rounded constants). */
void  colorspace_luminance(int cs, double y[3]);
/* The space whose primaries and white are xy = (rx, ry, gx, gy, bx, by, wx, wy)
   within pbrt-v4's tolerance (RGBColorSpace::Lookup; an EXR's chromaticities), -1 none. */
int   colorspace_lookup(const float xy[8]);
RgbTable *rgb_table_new_cs(int cs);
int   rgb_table_space(const RgbTable *T);  /* T's colour space (NULL: srgb) */
void  rgb_table_free(RgbTable *T);
int   spec_from_rgb(Spectrum *s, const float rgb[3], int illuminant, Error *err,
                    const char *file, int line);
int   spec_from_rgb_t(RgbTable *T, Spectrum *s, const float rgb[3], int illuminant,
                      Error *err, const char *file, int line);
void  spec_blackbody(Spectrum *s, float kelvin);  /* normalised to a peak of 1 (pbrt-v4) */
float blackbody_eval(float kelvin, float lambda_nm); /* spec_blackbody's value at one wavelength */

/* The sigmoid fit behind spec_from_rgb(_t), for infinite.c's image maps: coefficients for a
   colour whose largest component is 1/2 (from the table T, or the full fit when T is
   NULL), and the shape sigmoid(poly(lambda)). */
void  spec_rgb_coeffs(RgbTable *T, const double target[3], double c[3]);
/* Fitting many colours (image textures, texture.c): the table the fit integrates
   against, built once, and Newton's method from a nearby colour's coefficients
   (0 when it does not converge: then use spec_rgb_coeffs). */
typedef struct {
    double cmf_w[3][SPEC_N];
    double x[SPEC_N];          /* (lambda - SPEC_MIN) / (SPEC_MAX - SPEC_MIN) at each knot */
    double m[3][3];            /* the colour space's XYZ -> RGB */
} RgbFitTable;
void  spec_rgb_fit_table(RgbFitTable *t, int cs);   /* in colour space cs */
int   spec_rgb_coeffs_from(const RgbFitTable *t, const double target[3], const double start[3],
                           double c[3]);
float spec_sigmoid_eval(const float c[3], float lambda_nm);
/* A reflectance as a Material holds it (pbrt-v4's RGBAlbedoSpectrum): an "rgb" colour
   that is not grey is the three coefficients c of its sigmoid (40 B where a Spectrum
   takes 2.1 KB: docs/loading.md) in a scene of many spectra (parser.h
   rgb_albedo_param), any other spectrum a table shared through Scene.spectra
   (parser.h albedo_set_table).  albedo_eval(a, lambda) of a colour is
   spec_eval of the table spec_from_rgb_t makes from it, bit for bit: the knots
   albedo_knot(c, i) = (float) clamp(S((c0 x + c1) x + c2), 0, 1) at x = i / 470,
   interpolated as spec_eval does, two knots per call; zero in the UV but for the ramp
   from 359 nm to the knot at 360 nm.  A zeroed Albedo is zero everywhere.
   albedo_from_rgb: rgb (components in [0, 1]) as the coefficients of spec_from_rgb_t's
   fit (from the table T); 0 (a untouched) for a grey or a value outside [0, 1]: the
   caller then tabulates it. */
typedef struct {
    double c[3];           /* rgb: the sigmoid's coefficients */
    const Spectrum *tab;   /* not rgb: the table (NULL: zero) */
    int rgb;               /* 1: the sigmoid of c; 0: tab */
} Albedo;
float albedo_eval_rgb(const Albedo *a, float lambda_nm);   /* no table: the sigmoid, or 0 */
static inline float albedo_eval(const Albedo *a, float lambda_nm)
{ return a->tab ? spec_eval(a->tab, lambda_nm) : albedo_eval_rgb(a, lambda_nm); }
float albedo_knot(const double c[3], int i);
int   albedo_from_rgb(RgbTable *T, const float rgb[3], Albedo *a);
/* For tests: the coefficient table's interpolated start for target (before the
   Newton polish), and the full continuation fit from grey (no table). */
void  spec_rgb_table_start(RgbTable *T, const double target[3], double c[3]);
/* spec_to_y (below) with T's table of ybar at the knots (the same value; T NULL:
   spec_to_y): a load's rgb lights take their Y from it (parser.c). */
double spec_to_y_t(RgbTable *T, const Spectrum *s);
/* T's table of cie_ybar at the knots SPEC_MIN..SPEC_MAX (SPEC_N doubles) */
const double *spec_ybar_knots(RgbTable *T);
void  spec_rgb_coeffs_fit(const double target[3], double c[3]);
/* rgbtable.c: the coefficients of target (components in [0, 1], not all 0) by
   interpolation of the build-time table rgbtable.h, without iteration; 0 where the
   table is not trusted (then spec_rgb_coeffs fits). */
int   rgbtable_coeffs(const double target[3], double c[3]);
/* ... and the interpolation in any cell: 2 trusted (c as rgbtable_coeffs), 1 not
   (c: the start that rgbfit.c polishes by Newton), 0 outside the grid. */
int   rgbtable_lookup(const double target[3], double c[3]);
/* The table's grid (rgbtable.c; docs/loading.md): knots x = 0..RGB_GRID_CELLS of
   z = rgb[m], the largest component, at z = rgb_grid_z(x); rgb_grid_cell gives m,
   the cell (x, b, a) and the fractions in it (0 where z is below the knot x = 1);
   rgb_grid_interp interpolates a table coef[m][x][b][a][3] (floats) there. */
#define RGB_GRID_CELLS 32
double rgb_grid_z(double x);
int   rgb_grid_cell(const double target[3], int *m, int cell[3], double f[3]);
void  rgb_grid_interp(const float *coef, int m, const int cell[3], const double f[3], double c[3]);
/* CIE 1931 2-degree colour matching functions at lambda (nm), linear in the 5 nm CIE table. */
void  cie_xyz(float lambda_nm, float xyz[3]);
void  cie_cmf(double lambda_nm, double xyz[3]);  /* the same in double precision */
double cie_ybar(double lambda_nm);               /* cie_cmf's y alone */
double cie_y_integral(float lo_nm, float hi_nm); /* sum of ybar at 1 nm steps over [lo, hi] */
void  spec_to_xyz(const Spectrum *s, float lo_nm, float hi_nm, double xyz[3]); /* 1-nm sums / sum ybar:
                                               an equal-energy spectrum has Y = 1 */
double spec_to_y(const Spectrum *s);          /* spec_to_xyz's Y over SPEC_MIN..SPEC_MAX alone */
void  xyz_to_linear_srgb(const double xyz[3], double rgb[3]);  /* pbrt-v4's matrix */
/* CIE colorimetry of a spectrum: chromaticity, CCT (exact, Planckian locus), Duv. */
void  spec_chromaticity(const Spectrum *s, double *x, double *y);
double cct_from_xy(double x, double y, double *duv);
/* thesis eq. 6: sum of the 60 bin averages over 400-700 nm. */
double spec_bin_sum(const Spectrum *s);
float spec_bin_average(const Spectrum *s, int bin);  /* mean over [400+5b, 405+5b] nm */
/* Exact mean of the piecewise-linear spectrum over [lo, lo + width] nm (integers,
   inside SPEC_UV_MIN..SPEC_MAX, else 0), in double and rounded to float;
   spec_bin_average is this over a thesis bin. */
double spec_band_mean(const Spectrum *s, int lo_nm, int width_nm);
float spec_band_average(const Spectrum *s, int lo_nm, int width_nm);

/* Cauchy's law n(lambda) = A + B / lambda^2, lambda in micrometres. */
static inline float cauchy_eta(float A, float B, float lambda_nm)
{ float um = lambda_nm * 1e-3f; return A + B / (um * um); }
/* Named Cauchy glasses with cited coefficients: BK7, fused-silica, SF10, SF11, diamond,
   teaching, teaching-strong (case-insensitive, optional "cauchy-" prefix). */
int   cauchy_named(const char *name, float *A, float *B);

/* ---- Wavelength sampling (wavelengths.c): lambda_j = cdf^-1(frac(u + j/4)) (HWSS
   rotated in the CDF of p as in West et al. 2020; THEORY §2).  p is
   uniform, an importance pdf, the visible pdf or a mixture (docs/wavelengths.md);
   the four are combined by spectral MIS (THEORY §3). ---- */
/* Which pdf the wavelengths are drawn from (--wavelengths). */
typedef enum {
    WL_UNIFORM,                /* uniform over the range: plain HWSS, the thesis */
    WL_IMPORTANCE,             /* ~ (xbar + ybar + zbar) x the sum of the emitters' spectra */
    WL_VISIBLE,                /* scene-independent: sech^2 around 538 nm (pbrt-v4's
                                  "visible wavelengths" pdf, Radziszewski et al. 2009) */
    WL_MIXTURE,                /* (1 - mu) importance + mu visible: a defensive mixture */
    WL_MODE_COUNT
} WlMode;
#define WL_MIX_DEFAULT 0.5f    /* @@ mu of WL_MIXTURE: robustness vs. the gain of importance
                                  (chosen by the sweep in docs/wavelengths.md) */
typedef struct {
    float lo, hi;              /* sampled range in nm (400-700 default, 360-830 wide) */
    int   n;                   /* number of table cells (1 nm each), 0 = analytic */
    float *pdf;                /* per-nm pdf (n cells) for importance sampling */
    float *cdf;                /* n + 1 entries, cdf[0] = 0, cdf[n] = 1 */
    int   *guide;              /* m + 1 entries, cdf's guide table (cdf_guide; NULL:
                                  wl_sample searches all cells) */
    int   m;                   /* the guide's steps, a power of two >= 4 n (cdf_guide_size) */
    double h;                  /* the cells' width, (hi - lo) / n nm */
    int   visible;             /* n == 0: 1 = the visible sech^2 pdf, 0 = uniform */
    double vis_t_lo, vis_t_span; /* visible: th(lo) = tanh(kappa (lo - c)) and th(hi) - th(lo)
                                    (wavelengths.c) */
} WavelengthPdf;
typedef struct {
    float lambda[HERO_N];      /* nm; lambda[0] is the hero */
    float pdf[HERO_N];         /* marginal pdf p(lambda_j) of each (1/nm) */
} Wavelengths;
void  wl_pdf_uniform(WavelengthPdf *w, float lo, float hi);
/* pdf proportional to (xbar + ybar + zbar) times the given emission spectrum. */
int   wl_pdf_importance(WavelengthPdf *w, float lo, float hi, const Spectrum *emission);
/* pbrt-v4's visible pdf restricted to [lo, hi] and renormalised (exact inverse CDF). */
int   wl_pdf_visible(WavelengthPdf *w, float lo, float hi);
/* (1 - mix) x the importance pdf + mix x the visible pdf, tabulated per 1 nm cell. */
int   wl_pdf_mixture(WavelengthPdf *w, float lo, float hi, const Spectrum *emission, float mix);
/* One of the above by mode (emission: the emitters' summed spectrum, may be NULL). */
int   wl_pdf_build(WavelengthPdf *w, WlMode mode, float lo, float hi, const Spectrum *emission,
                   float mix);
void  wl_pdf_free(WavelengthPdf *w);
void  wl_sample(const WavelengthPdf *w, float u, Wavelengths *out);
float wl_pdf_eval(const WavelengthPdf *w, float lambda_nm);
double wl_cdf(const WavelengthPdf *w, float lambda_nm);   /* cdf(lambda), exact (tests) */
WlMode wl_mode_from_name(const char *name);               /* WL_MODE_COUNT if unknown */
const char *wl_mode_name(WlMode m);

/* ======================================================================
   5. Geometry (scene.c builds it, bvhbuild.c its BVH, bvh.c intersects it, hitpoint.c reads a hit, shapes.c holds the quadrics)
   ====================================================================== */
typedef enum {
    SHAPE_MESH,                /* triangles (trianglemesh, bilinearmesh, plymesh) */
    SHAPE_SPHERE,              /* a whole sphere under a rigid + uniform-scale CTM, in world space */
    SHAPE_DISK,                /* the quadrics of shapes.c, intersected in object space: */
    SHAPE_CYLINDER,            /*   a disk (annulus sector), an open cylinder, and a sphere */
    SHAPE_SPHERE_PART,         /*   cut by zmin/zmax/phimax or under a non-uniform CTM */
    SHAPE_CURVE                /* pbrt-v4 "curve": Bezier segments in Scene.curves (curve.c) */
} ShapeType;
static inline int shape_is_quadric(ShapeType t) { return t >= SHAPE_DISK && t <= SHAPE_SPHERE_PART; }

/* A quadric's object-space description (shapes.c): pbrt-v4's parameters, and the
   CTM that puts it in the world. */
typedef struct {
    Xform world_from_obj;      /* m: world from object; inv: object from world */
    double radius;             /* disk: outer radius; cylinder, sphere: radius */
    double inner;              /* disk: innerradius (0) */
    double height;             /* disk: the plane z = height (0) */
    double zmin, zmax;         /* cylinder, sphere: the z range kept (sphere: clamped to
                                  [-radius, radius], as pbrt-v4 does) */
    double phimax;             /* radians in (0, 2 pi]: the sector 0 <= phi <= phimax kept */
    int similarity;            /* the CTM's 3x3 part is a rotation (or mirror) times a
                                  uniform scale: object areas scale by sim_scale^2 */
    double sim_scale;
} Quadric;

/* One Shape directive: a triangle mesh, a sphere or another quadric, with its
   material and, when it sits inside an AreaLightSource, the emitter it belongs to. */
typedef struct {
    ShapeType type;
    int material;              /* index into Scene.materials */
    int emitter;               /* index into Scene.emitters, -1 if not emissive */
    int flip;                  /* ReverseOrientation XOR a handedness-swapping transform */
    int has_normals;           /* mesh carries per-vertex shading normals */
    int has_uv;                /* mesh carries per-vertex (u, v) in Scene.UV */
    int has_tangents;          /* trianglemesh "vector3 S": per-vertex tangents in Scene.S,
                                  the shading frame's dp/du (bump.c) */
    int tri_begin, tri_count;  /* triangles [tri_begin, tri_begin + tri_count) */
    int bilinear;              /* bilinearmesh or a PLY file's quads: its triangles come in
                                  pairs, each a flat patch whose (u, v), "uv" and "N" are
                                  the patch's (patch.c) */
    int patch_begin, patch_count;  /* its other patches: Scene.patches[patch_begin ..) */
    Vec3 center; float radius; /* sphere, in world space */
    Quadric q;                 /* disk, cylinder, partial sphere: in object space;
                                  curve: only q.world_from_obj (its CTM) */
    double area;               /* world-space surface area */
    int medium_inside;         /* MediumInterface at the Shape: indices into Scene.media,
                                  -1 for none (vacuum).  Where they differ the shape is a */
    int medium_outside;        /* transition: a ray leaving it along w is in the outside
                                  medium if w . ng > 0, else in the inside one (pbrt-v4) */
    int in_object;             /* 0: in the world; k > 0: part of object definition
                                  k - 1 (Scene.objects), its coordinates in the
                                  object's space (instance.c) */
    float alpha;               /* pbrt-v4 "float alpha" (1: opaque): a hit is kept only when
                                  a hash of the ray is <= alpha (bvh.c: ALPHA) */
    int alpha_tex;             /* "texture alpha": 1 + its index in Scene.textures, read at
                                  the hit's (u, v); 0: none */
    int alpha_on;              /* alpha < 1 or a texture: the BVH tests the hits */
    int reads_uv;              /* a hit needs its (u, v): an alpha texture, a material
                                  that reads them (mat_reads_uv) or an emission image;
                                  set when loading ends */
    const char *file; int line;/* where it was declared, for messages */
} Shape;

typedef struct { int32_t v[3]; int32_t shape; } Triangle;   /* indices into Scene.P / N */
/* A bilinear patch that is not flat (patch.c): corners p00 p10 p01 p11, pbrt-v4's order. */
typedef struct { int32_t v[4]; int32_t shape; } Patch;
/* A curve's cubic Bezier segment (curve.c), in its Shape's object space, with u in
   [0, 1]; the BVH holds its pieces [u0, u1] (pbrt-v4's "splitdepth"). */
typedef enum { CURVE_FLAT, CURVE_CYLINDER, CURVE_RIBBON } CurveType;
typedef struct {
    Vec3 cp[4];                /* control points */
    float width[2];            /* width at u = 0 and u = 1 (object space) */
    Vec3 n[2];                 /* ribbon: unit normals at u = 0 and u = 1 */
    float normal_angle;        /* ribbon: the angle between n[0] and n[1] ... */
    float inv_sin_angle;       /* ... and 1 / its sine (0 when the angle is 0) */
    int type;                  /* CurveType */
    int shape;                 /* index into Scene.shapes */
} Curve;
typedef struct { int32_t curve; float u0, u1; } CurvePiece;   /* a BVH primitive */

typedef struct {
    float t;                   /* ray parameter of the hit */
    int prim;                  /* triangle index, n_tris + sphere index,
                               n_tris + n_spheres + quadric index,
                               n_tris + n_spheres + n_quadrics + patch index, or
                               that + n_patches + curve piece index */
    float b1, b2;              /* barycentrics of v[1], v[2] (triangles); a patch's or a
                                  curve's (u, v) */
    int inst;                  /* -1: prim is in the world; else the index of the
                                  instance (Scene.instances) whose object holds prim */
} HitRecord;

/* The BVH (bvh.c; the node layout is drawn at the top of that file): 8-wide nodes
   holding their children's boxes, and the primitives in leaf order. */
#define BVH_WIDTH 8
#define BVH_WIDE_LEAF_MAX 8    /* a leaf of the wide tree: at most this many primitives */
typedef struct {
    float box[6][BVH_WIDTH];   /* children's boxes by plane: lo x, lo y, lo z, hi x,
                                  hi y, hi z; an empty slot has lo = +inf, hi = -inf */
    int32_t child[BVH_WIDTH];  /* >= 0: inner node index; < 0: a leaf,
                                  ~(first primitive << 3 | (count - 1)) */
    int32_t pad[BVH_WIDTH];    /* to 256 bytes: four whole cache lines */
} BvhNode;

typedef struct {
    float v[9];                /* triangle: p0, p1, p2; sphere: centre, radius; quadric:
                                  unused (its Shape holds transform and parameters) */
    int32_t prim;              /* primitive id: triangle i, n_tris + sphere j, or
                                  n_tris + n_spheres + quadric k */
} BvhPrim;

typedef struct {
    BvhNode *nodes; int n_nodes;     /* nodes[0] is the root (64-byte aligned) */
    BvhPrim *prims; int n_prims;     /* in leaf order */
    float bmin[3], bmax[3];          /* the root's box */
    void *node_mem;                  /* what malloc returned for nodes */
} Bvh;

struct Scene;
int  bvh_build(Bvh *b, const struct Scene *s);          /* bvhbuild.c; 0 on out of memory */
/* The Shape of primitive id below the instances (a triangle, sphere, quadric or
   patch; bvh.c's numbering), -1 for an index out of range (also instance.c's). */
int  bvh_prim_shape(const struct Scene *s, int id);
void bvh_free(Bvh *b);
/* The box the build gives primitive id (bvhbuild.c; the tree's boxes are unions of
   these), and a sphere's (rounded outwards); 0 for an invalid primitive.  A hit on
   a primitive is never reported nearer than its box's entry distance (bvh.c, THE
   HIT'S FLOOR); bvh_hit_floor is that distance along r, for tests. */
int  bvh_prim_box(const struct Scene *s, int id, float lo[3], float hi[3]);
void bvh_sphere_box(const float c[3], float radius, float lo[3], float hi[3]);
float bvh_hit_floor(const struct Scene *s, int id, const Ray *r);
/* Closest hit along r (0 < t < r->tmax); returns 1 and fills h on a hit. */
int  bvh_intersect(const Bvh *b, const struct Scene *s, const Ray *r, HitRecord *h);
/* Any hit along r: the shadow-ray query. */
int  bvh_occluded(const Bvh *b, const struct Scene *s, const Ray *r);
/* The slab test runs on four children at a time in SSE2 where the compiler has it,
   and on all eight in AVX2 where the processor has it too (bvh_avx2() = 1), beside
   the scalar code they mirror (bvh.c).  For ray r and closest hit so far t_best:
   how many children of b's nodes get an entry distance, an
   entered/not or a rank that differs in any bit between the scalar code and each
   SIMD path, plus how many masks 1..255 get different lowest bits from the two bit
   scans; *lanes += children compared (each node's 8 once per SIMD path).  With AVX2
   it also counts 1 when the AVX2 copy's ray preparation (its verdict, or a field the
   traversal reads) differs from the scalar one.  For tests. */
int  bvh_simd_mismatches(const Bvh *b, const Ray *r, float t_best, int *lanes);
int  bvh_avx2(void);
/* Where the AVX2 copy runs, a triangle is first tested by a 4-lane filter (bvh.c:
   tri_miss4) and finished from its lanes (tri_hit_rest): how many of b's triangle
   records r gets a filter verdict for that differs from the scalar sign test of the
   watertight test, that the filter drops though the scalar test hits, or whose
   whole AVX2 test differs from tri_hit (verdict, t, b1, b2 in any bit; tmax infinite,
   at the hit and just below it); *tested += triangles compared (none without AVX2).
   For tests. */
int  bvh_tri_filter_mismatches(const Bvh *b, const struct Scene *s, const Ray *r, int *tested);
/* The BVH over the given primitives only (an object definition's: instance.c). */
int  bvh_build_object(Bvh *b, const struct Scene *s, const int32_t *ids, int n);
/* The two primitive tests, exposed for tests and the brute-force reference; each
   reports a hit no nearer than its primitive's box (bvh.c, THE HIT'S FLOOR). */
int  intersect_triangle(Vec3 p0, Vec3 p1, Vec3 p2, const Ray *r, float *t, float *b1, float *b2);
int  intersect_sphere(Vec3 c, float radius, const Ray *r, float *t);

/* Object instancing (instance.c; pbrt-v4's ObjectBegin / ObjectEnd / ObjectInstance).
   The shapes between ObjectBegin and ObjectEnd are stored once, in the object's own
   space (the CTM at each Shape directive), with a BVH of their own; ObjectInstance
   places the object in the world by the CTM at that directive.  The scene's BVH
   holds the world's primitives and one primitive per instance, with the id
   n_tris + n_spheres + n_quadrics + its index; a ray that enters an instance's box
   is carried into object space and traced through the object's BVH. */
typedef struct {
    const char *name;          /* in Scene.strings; "" for an unnamed one */
    Bvh bvh;                   /* over the object's primitives, in its space */
    const char *file; int line;/* its ObjectBegin */
    int unnamed;               /* made for one moving shape (motion.c): no name */
} Object;
/* Motion blur (motion.c; pbrt-v4's ActiveTransform, TransformTimes and
   AnimatedTransform).  Two transforms, at the start and end times, each taken apart
   as M = T R S (translation, rotation as a unit quaternion, the rest); between
   the times T and S are interpolated linearly and R by slerp, outside them the
   nearer end is used. */
typedef struct {
    double t0, t1;             /* TransformTimes: start, end */
    Xform start, end;          /* the transforms at t0 and t1 */
    double T[2][3], q[2][4], S[2][3][3];   /* their parts; q = (w, x, y, z) */
    double theta;              /* the angle between q[0] and q[1] (half the rotation) */
} Motion;
/* The motion from start (at t0) to end (at t1); 0 when an end mirrors (negative
   determinant) or is projective: neither has a rotation to interpolate. */
int  motion_init(Motion *m, const Xform *start, double t0, const Xform *end, double t1);
/* The transform at time (and its inverse). */
void motion_at(const Motion *m, double time, Xform *out);
/* A box that holds the box [lo, hi] moved by m at every time (conservative: the
   corners' paths sampled, widened by a bound of their curvature). */
void motion_bounds(const Motion *m, const double lo[3], const double hi[3], double wlo[3], double whi[3]);
/* Whether two transforms differ in any entry (pbrt-v4's "actually animated"). */
int  xf_differ(const Xform *a, const Xform *b);

typedef struct {
    int object;                /* index into Scene.objects */
    int motion;                /* 1 + its index into Scene.motions; 0: it stays */
    Xform world_from_obj;      /* the CTM at ObjectInstance (inv: object from world);
                                  a moving instance's start one (a ray takes
                                  motion_at of its time) */
    float lo[3], hi[3];        /* world box of the placed object, rounded outwards */
    const char *file; int line;/* its ObjectInstance */
} Instance;
/* Build every object's BVH and every instance's world box, dropping the instances
   of empty objects (scene_load); 0 and a "file:line: problem" on failure. */
int  instances_prepare(struct Scene *s, Error *err);

/* Everything the integrator needs at a hit point. */
typedef struct {
    Vec3 p;                    /* position */
    Vec3 ng;                   /* geometric normal, oriented by the shape's orientation */
    Vec3 ns;                   /* shading normal (= ng without vertex normals) */
    int shape;                 /* index into Scene.shapes */
    int prim;
    float u, v;                /* the shape's (u, v) parameters (pbrt-v4): a mesh's "uv"
                                  interpolated, else (0,0), (1,0), (1,1) at its corners;
                                  quadrics: pbrt-v4's (phi / phimax, ...) (shapes.c)
                                  (texture.c's "uv" mapping reads them) */
    Vec3 err;                  /* a curve hit's error box (pbrt-v4's), which a ray
                                  leaving it clears (spawn_origin); 0 for the others */
    Vec3 dpdu;                 /* the shape's dp/du, set only where it is read: by hair_shade
                                  (hair.c: the fibre's axis) and tangent_shade (bump.c: an
                                  anisotropic BSDF's s axis, pbrt-v4's dp/du) */
} SurfacePoint;
/* The surface point at hit h of ray r (hitpoint.c). */
void scene_surface_point(const struct Scene *s, const Ray *r, const HitRecord *h, SurfacePoint *sp);
/* An instance's transforms (motion.c; instance.c: RAYS AND HITS): its M for ray r (a moving
   one's at the ray's time, written into *tmp), the world ray r in its object
   space, and a hit point computed there put back into the world. */
const Xform *instance_xf(const struct Scene *s, const Instance *in, const Ray *r, Xform *tmp);
Ray  instance_ray(const Xform *x, const Ray *r);
void instance_point(const Xform *x, SurfacePoint *sp);
/* Origin for a ray leaving p towards w: p moved along ng to w's side by
   1e-5 (1 + max|p_i|) (the self-intersection policy at the top of hitpoint.c). */
Vec3 offset_ray_origin(Vec3 p, Vec3 ng, Vec3 w);
/* The origin of a ray leaving the hit sp towards w: offset_ray_origin moved further
   along ng by |ng| . sp->err (pbrt-v4's offset past a curve hit's error box). */
Vec3 spawn_origin(const SurfacePoint *sp, Vec3 w);
/* That policy's distance for coordinates up to m in magnitude: 1e-5 (1 + m)
   (also the light tree's round-off margin for "behind the box"). */
float offset_eps(float m);

/* The quadrics (shapes.c): disk, cylinder and partial sphere, each intersected
   analytically in its object space (docs/conventions.md §3 for their
   orientation).  sh->type must be one of them. */
/* Set q's CTM (and whether it is a similarity); 0 for a projective CTM. */
int    quadric_set_transform(Quadric *q, const Xform *ctm);
/* Closest hit of the world-space ray r with 0 < t <= tmax; 1 and *t on a hit. */
int    quadric_intersect(const Shape *sh, const Ray *r, float tmax, float *t);
/* Position, oriented normals and pbrt-v4's (u, v) of the hit of r at t (sp->shape,
   prim left alone). */
void   quadric_surface_point(const Shape *sh, const Ray *r, float t, SurfacePoint *sp);
/* World-space box holding the shape, rounded outwards. */
void   quadric_bounds(const Shape *sh, float lo[3], float hi[3]);
/* World-space area: closed form under a similarity CTM (and for a disk under any
   affine CTM, whose area scale is constant), a quadrature otherwise. */
double quadric_area(const Shape *sh);
/* 1 when a point uniform by object-space area is uniform by world-space area
   (a disk always; a cylinder or sphere under a similarity CTM), so that
   quadric_sample's density is 1 / area. */
int    quadric_uniform_sampling(const Shape *sh);
/* A point uniform by object area for (u1, u2) in [0,1)^2 (uniform by world area
   given quadric_uniform_sampling), with the oriented geometric normal a hit there
   would get. */
void   quadric_sample(const Shape *sh, float u1, float u2, Vec3 *p, Vec3 *n);
/* 1 / (quadric_sample's density per world area) at world point p on the shape:
   Shape.area when quadric_uniform_sampling, else a_obj |det L| |L^-T n(p)|. */
double quadric_area_at(const Shape *sh, Vec3 p);

/* Bilinear patches (patch.c): p(u, v) = lerp(u, lerp(v, p00, p01), lerp(v, p10, p11))
   with corners c = (p00, p10, p01, p11); pbrt-v4's (u, v), normal dp/du x dp/dv. */
void   patch_corners(const struct Scene *s, const int32_t v[4], Vec3 c[4]);
/* A flat patch kept as the two triangles (p00,p10,p11), (p00,p11,p01) of shape sh:
   from triangle prim, the patch's vertex ids q (p00 p10 p01 p11) and the (u, v) of
   its point p. */
void   flat_patch_uv(const struct Scene *s, const Shape *sh, int prim, Vec3 p, int32_t q[4], float *u, float *v);
/* 1 when the patch is planar and not folded: then it is exactly the triangles
   (p00, p10, p11) and (p00, p11, p01), and scene.c stores it so. */
int    patch_is_flat(const Vec3 c[4]);
/* Closest hit with 0 < t <= tmax; 1 and *t, the patch's (*u, *v) on a hit. */
int    patch_intersect(const Vec3 c[4], const Ray *r, float tmax, float *t, float *u, float *v);
/* (u, v) of a point p of a flat patch (the bilinear map inverted, clamped). */
void   patch_uv_of_point(const Vec3 c[4], Vec3 p, float *u, float *v);
/* Position, oriented normals, texture (s, t) at (u, v) of the patch v of shape sh
   (r: its direction is the normal of a degenerate patch). */
void   patch_surface_point(const struct Scene *s, const Shape *sh, const int32_t v[4], double u,
                           double w, const Ray *r, SurfacePoint *sp);
/* Only the shading normal (from "N", reorienting sp->ng) and the texture (s, t)
   ("uv" bilinear, else (u, v)), given sp->ng. */
void   patch_shading(const struct Scene *s, const Shape *sh, const int32_t v[4], double u, double w,
                     SurfacePoint *sp);
/* World area, integral of |dp/du x dp/dv| (exact for flat patches). */
double patch_area(const Vec3 c[4]);
/* (u, v) whose point is uniform by area (density 1 / patch_area), from (u1, u2). */
void   patch_sample(const Vec3 c[4], float u1, float u2, float *u, float *v);

/* Curves (curve.c; pbrt-v4's Shape "curve": flat, cylinder, ribbon).  Cubic Bezier
   arithmetic: the point at u and B'(u); the control points of the part [u0, u1];
   the other bases and degree 2 as cubic Beziers (the same polynomials). */
Vec3   curve_bezier_eval(const Vec3 cp[4], float u, Vec3 *deriv);
void   curve_bezier_piece(const Vec3 cp[4], float u0, float u1, Vec3 out[4]);
void   curve_bspline_to_bezier(const Vec3 p[4], Vec3 out[4]);
void   curve_quadratic_bspline_to_bezier(const Vec3 p[3], Vec3 out[3]);
void   curve_elevate_quadratic(const Vec3 a[3], Vec3 out[4]);
/* A piece's world box (widened by half its width, rounded outwards). */
void   curve_piece_bounds(const struct Scene *s, const CurvePiece *pc, float lo[3], float hi[3]);
/* The closest (any_hit: any) hit of world ray r with 0 < t <= tmax: 1 and h's t,
   b1 = the segment's u, b2 = v (0..1 across the width) on a hit (Nakamaru and Ohno
   2002); h's prim and inst are left alone. */
int    curve_intersect(const struct Scene *s, const CurvePiece *pc, const Ray *r, float tmax,
                       int any_hit, HitRecord *h);
/* The hit h (t, u = b1, v = b2) of r: position, normals, (u, v), err; dp/du and
   dp/dv in the world when not NULL (pbrt-v4's, which the hair material's frame uses). */
void   curve_surface_point(const struct Scene *s, const CurvePiece *pc, const Ray *r,
                           const HitRecord *h, SurfacePoint *sp, Vec3 *dpdu, Vec3 *dpdv);

/* ======================================================================
   6. Materials: only what the scenes need (material.c; microfacet.c, conductor.c,
      layered.c; textures in texture.c; media in medium.c, 6b)
   ====================================================================== */
typedef enum {
    MAT_DIFFUSE, MAT_DIELECTRIC, MAT_FLUORESCENT,
    MAT_CONDUCTOR,             /* pbrt-v4 "conductor": complex Fresnel, smooth or GGX (conductor.c) */
    MAT_THIN_DIELECTRIC,       /* pbrt-v4 "thindielectric": reflect or pass straight through */
    MAT_DIFFUSE_TRANSMISSION,  /* pbrt-v4 "diffusetransmission": Lambert both sides */
    MAT_COATED_DIFFUSE,        /* pbrt-v4 "coateddiffuse": dielectric coat over Lambert (layered.c) */
    MAT_COATED_CONDUCTOR,      /* pbrt-v4 "coatedconductor": dielectric coat over a conductor
                                  (layered.c) */
    MAT_INTERFACE,             /* pbrt-v4 "interface": no surface, only the boundary of a medium
                                  (rays pass it; medium.c, docs/media.md) */
    MAT_MIX,                   /* pbrt-v4 "mix": at each hit one of two materials, chosen by
                                  a hash of the point and wo (mat_choose) */
    MAT_HAIR,                  /* pbrt-v4 "hair": Chiang et al. 2016's fibre model (hair.c) */
    MAT_MEASURED,              /* pbrt-v4 "measured": a tabulated BRDF file (measured.c) */
    MAT_SUBSURFACE,            /* pbrt-v4 "subsurface": a dielectric boundary over a tabulated
                                  BSSRDF (subsurface.c) */
    MAT_SUBSURFACE_EXIT        /* the lobe Sw a subsurface path leaves its exit point by;
                                  path.c makes it from the material (never in a scene) */
} MaterialType;
#define FL_N (SPEC_MAX - SPEC_UV_MIN + 1)   /* 1 nm knots of the fluorescence tables */
/* A fluorescent layer (docs/FLUORESCENCE.md, F2): f = (1/pi) [rho (1 - A) delta(li - lo)
   + Phi A(li) e(lo) (li/lo) H(lo - li) / N(li)], rho being the Material's reflectance.
   Its own record, held by pointer, so that the other materials do not carry its
   12.7 KB (docs/loading.md, memory per emitter). */
typedef struct {
    Spectrum excitation;       /* A, the absorptance, in [0, 1] */
    Spectrum emission;         /* e, the emission shape in photon units */
    float qyield;              /* Phi, the photon quantum yield, in [0, 1] */
    double cdf[FL_N];          /* C at each knot: integral of A from 300 nm (F3) */
    double tail[FL_N];         /* N at each knot: integral of e from the knot to 830 nm */
} Fluorescence;
/* The spectra that only some material types read, in a record of their own held by
   pointer (like Fluorescence), so that a diffuse or dielectric material does not
   carry their 8.5 KB (docs/loading.md, memory per emitter). */
typedef struct {
    Spectrum k;                /* conductor: extinction coefficient (Material.eta holds n);
                                  coatedconductor: the base's k (cond_eta holds its n) */
    Spectrum transmittance;    /* diffusetransmission: T (reflectance holds R), scaled */
    Spectrum albedo;           /* coateddiffuse, coatedconductor: the slab's albedo */
    Spectrum cond_eta;         /* coatedconductor: the base conductor's n */
    int transmittance_tex;     /* diffusetransmission: "texture transmittance", 1 + its
                                  index (0: the spectrum above) */
    float dt_scale;            /* diffusetransmission: "scale", applied to textured R, T
                                  at the point (the spectra above hold it already) */
    int eta_tex, k_tex;        /* conductor: "texture eta", "texture k"; coatedconductor:
                                  "texture conductor.eta", "texture conductor.k": 1 + a
                                  spectrum texture's index, read through mat_point (0: the
                                  spectrum, Material.eta or cond_eta, and k) */
} MaterialSpectra;
typedef struct {
    MaterialType type;
    Albedo reflectance;        /* diffuse albedo; fluorescent: rho, of the light not absorbed
                                  (a colour's sigmoid, or a table of Scene.spectra) */
    Fluorescence *fl;          /* fluorescent: A, e, Phi and their tables (owned, freed by
                                  material_release); NULL for every other type */
    const Spectrum *eta;       /* dielectric index of refraction n(lambda); a Cauchy glass
                                  (A + B/lambda^2) is tabulated at load time.  Shared, not
                                  owned: a record of Scene.spectra (parser.h material_set_eta), so
                                  the many materials of one index hold one table */
    float cauchy_a, cauchy_b;  /* the Cauchy coefficients when given (for --dump-scene) */
    int dispersive;            /* eta varies with lambda: terminates the secondaries */
    float alpha;               /* GGX roughness alpha (0 = smooth), after remaproughness;
                                  conductor, a layered material's coat: alpha along the
                                  shading frame's s axis */
    float alpha_t;             /* conductor, coat: alpha along the t axis (anisotropic GGX) */
    MaterialSpectra *extra;    /* conductor, coateddiffuse, coatedconductor,
                                  diffusetransmission: k, transmittance, albedo, cond_eta
                                  (owned, freed by material_release); NULL for the others */
    float p_reflect;           /* diffusetransmission: probability of sampling the
                                  reflect lobe, max R / (max R + max T) over 300-830 nm */
    int reflectance_tex;       /* diffuse, conductor, coateddiffuse, diffusetransmission:
                                  "texture reflectance",
                                  1 + its index into Scene.textures (0, as a zeroed
                                  Material has it: the spectrum above) */
    int alpha_tex;             /* conductor, coateddiffuse, dielectric, subsurface:
                                  "texture roughness" or "texture uroughness", 1 + its
                                  index (0: alpha above); read through mat_point */
    int alpha_t_tex;           /* conductor, coat: the t axis's ("texture vroughness"),
                                  1 + its index (0: alpha_t); dielectric, subsurface:
                                  unused (their roughness is isotropic) */
    int remap;                 /* with alpha_tex: remaproughness (alpha = sqrt(value)) */
    const struct Texture *textures;  /* the scene's textures (set when loading ends) */
    /* coateddiffuse, coatedconductor (layered.c): eta (a constant) and alpha (alpha_tex)
       are the coat's; coateddiffuse: reflectance is the base's R */
    /* extra->albedo: single-scattering albedo of the medium between the layers */
    float thickness, hg_g;     /* the slab's height (sigma_t = 1) and HG asymmetry */
    int thickness_tex, g_tex;  /* "texture thickness", "texture g": 1 + a float texture's
                                  index, read through mat_point (0: the numbers above) */
    int albedo_tex;            /* "texture albedo": 1 + a spectrum texture's index, read
                                  through mat_point (0: extra->albedo) */
    int maxdepth, nsamples;    /* the random walks' vertex limit and count */
    /* coatedconductor: the base conductor's n (extra->cond_eta, extra->k) in vacuum, or
       its "reflectance" (then reflectance_tex or reflectance, cond_eta = 1 and k from it
       as for the conductor); its GGX alphas (cond_alpha_tex, cond_alpha_t_tex: 1 + a
       roughness texture's index) */
    float cond_alpha, cond_alpha_t;   /* along the shading frame's s and t (anisotropic GGX) */
    int cond_alpha_tex, cond_alpha_t_tex;   /* textures of the s and t axes (0: the numbers) */
    /* mix: the two materials (indices into Scene.materials, neither an interface) and
       the probability "amount" of the second, a constant or (amount_tex: 1 + its
       index) a float texture */
    int mix[2];
    float amount;
    int amount_tex;
    struct Hair *hair;         /* hair: its parameters (hair.c), owned, freed by
                                  material_release; NULL for the other types */
    struct Bump *bump;         /* "displacement" or "normalmap" (bump.c), owned, freed by
                                  material_release; NULL: the shape's shading normal */
    struct MeasuredBrdf *measured;  /* measured: the file's tables (measured.c), owned,
                                  freed by material_release */
    struct Subsurface *sss;    /* subsurface: its coefficients and table (subsurface.c),
                                  owned, freed by material_release (a MAT_SUBSURFACE_EXIT
                                  copy points at its material's) */

    int regularized;           /* a copy made by mat_regularized: mat_point regularizes
                                  the alphas it reads from textures too */
} Material;

/* Free what a Material owns (its Fluorescence, its MaterialSpectra); the record
   itself is the caller's. */
void  material_release(Material *m);
/* m->extra, allocated zeroed on first use (a builder of a type that reads it); NULL:
   out of memory.  Inline: the builders of conductor.c and layered.c call it, and
   material.c calls them. */
static inline MaterialSpectra *material_extra(Material *m)
{
    if (!m->extra) m->extra = (MaterialSpectra *)calloc(1, sizeof *m->extra);
    return m->extra;
}
/* Fluorescence (docs/FLUORESCENCE.md §1-§3).  fluor_prepare fills the tables
   of a MAT_FLUORESCENT material (m->fl set); returns 0 if the emission is zero everywhere. */
int   fluor_prepare(Material *m);
float fluor_branch_pf(const Material *m, float lo);      /* P_f(lo): re-radiate */
/* Phi A(li) e(lo) (li/lo) H(lo - li) / N(li): (F2)'s second term without 1/pi. */
float fluor_weight(const Material *m, float li, float lo);
/* Sample li on [300, lo] from A (F3); *pdf = p(li | lo), 0 when A is 0 there. */
float fluor_sample_li(const Material *m, float lo, float u, float *pdf);
float fluor_pdf_li(const Material *m, float lo, float li);
/* Beyond sampling from A (docs/FLUORESCENCE.md §3): li on [300, lo] with the density
   a p_A + (1 - a) p_AE, p_AE proportional to A(li) E(li), E the scene's emitter power
   per nm; fluor_power_cdf fills pcdf[FL_N] (its running integral, 1 nm cells) for a
   render; where A E has no mass below lo the density is p_A alone. */
void  fluor_power_cdf(const Material *m, const Spectrum *E, double *pcdf);
float fluor_sample_li_mix(const Material *m, const double *pcdf, float a, float lo, float u, float *pdf);
float fluor_pdf_li_mix(const Material *m, const double *pcdf, float a, float lo, float li);
#define FLUOR_LI_DEFENSIVE 0.25f   /* a: the share of A alone in --fluor-li power */
/* Uniformly on [300, lo] (--fluor-li uniform): p(li | lo) = 1 / (lo - 300). */
float fluor_sample_li_uniform(float lo, float u, float *pdf);
float fluor_pdf_li_uniform(float lo, float li);
/* --fluor-li: lambda_i from A, from A x the emitters' power mixed with A, uniformly. */
typedef enum { FLUOR_LI_A, FLUOR_LI_POWER, FLUOR_LI_UNIFORM } FluorLi;
/* The material a hit on a surface of material mi (an index into materials) scatters
   with: mi itself, or for a mix (pbrt-v4's MixMaterial::ChooseMaterial) the first
   of its two when the amount a at sp is <= 0, the second when a >= 1, else the
   second when u <= a, u in [0, 1) a hash of (sp->p, wo, the two indices): the
   same hit always chooses the same, whatever the thread count.  A mix of mixes
   is resolved down to a material that is not one. */
int   mat_choose(const Material *materials, int mi, const SurfacePoint *sp, Vec3 wo);
/* Whether the material reads the hit's (u, v): a texture, a mix (its amount may be
   one), a bump or normal map. */
int   mat_reads_uv(const Material *m);
/* The diffuse albedo of the reflect lobe: rho (diffuse) or rho (1 - A) (fluorescent). */
float mat_albedo(const Material *m, float lambda_nm);
/* The same at a surface point: a textured reflectance evaluated there, clamped to
   [0, 1] (pbrt-v4's DiffuseMaterial), else mat_albedo. */
float mat_albedo_at(const Material *m, const SurfacePoint *sp, float lambda_nm);

/* ---- Textures (texture.c): pbrt-v4's Texture directive ----
   A texture is a function of the surface point evaluated at one wavelength (a
   "spectrum" texture) or a number (a "float" texture).  2-D textures first map
   the point to (s, t): "uv" (s = uscale u + udelta, t = vscale v + vdelta),
   "spherical", "cylindrical" or "planar" (in the texture's frame, the CTM at the
   Texture directive).  3-D textures (marble, fbm, wrinkled, windy) use the point
   in that frame.  An
   argument (tex1, tex2, amount, tex, scale, inside, outside) is a constant or
   another texture. */
typedef enum { TEX_CONSTANT, TEX_CHECKERBOARD, TEX_SCALE, TEX_MIX, TEX_IMAGEMAP,
               TEX_DOTS, TEX_MARBLE, TEX_FBM, TEX_WRINKLED, TEX_WINDY, TEX_DIRECTIONMIX,
               TEX_BILERP } TexType;
/* TEXMAP_POINT3D: the 3-D checkerboard's point in the texture's frame (pbrt-v4's
   TextureMapping3D, "integer dimension" 3) */
typedef enum { TEXMAP_UV, TEXMAP_SPHERICAL, TEXMAP_CYLINDRICAL, TEXMAP_PLANAR,
               TEXMAP_POINT3D } TexMapType;
typedef enum { TEXWRAP_REPEAT, TEXWRAP_BLACK, TEXWRAP_CLAMP } TexWrap;
#define TEX_ARGS 4             /* bilerp's four corners; the others use 2 */
typedef struct Texture {
    TexType type;
    int is_float;              /* a "float" texture, else a "spectrum" one */
    TexMapType map;
    float su, sv, du, dv;      /* uv: scales and offsets; planar: du, dv the offsets */
    Vec3 vs, vt;               /* planar: the s and t axes ("v1", "v2") */
    Vec3 dir;                  /* directionmix: "dir" in world space, a unit vector */
    Xform tex_from_world;      /* spherical, cylindrical, planar and the 3-D textures: the
                                  inverse CTM */
    /* arguments: checkerboard tex1, tex2; mix and directionmix tex1, tex2 (and mix's
       amount); scale tex, scale;
       dots "inside" (shown outside the dots, as in pbrt-v4), "outside" (in them);
       bilerp v00, v01, v10, v11 (constants only) */
    int arg_tex[TEX_ARGS];     /* a texture index, or -1: the constant below */
    Spectrum arg_s[TEX_ARGS];  /* spectrum constants */
    float arg_f[TEX_ARGS];     /* float constants (also scale's "scale") */
    int amount_tex; float amount;  /* mix: a float texture or constant (0.5) */
    int scale_tex;             /* scale: "scale" as a float texture (-1: arg_f[1]) */
    int octaves;               /* marble, fbm, wrinkled: octaves of noise (8) */
    float omega, mscale, variation;  /* marble: "roughness" (0.5), "scale" (1), "variation" (0.2);
                                        fbm, wrinkled: omega = "roughness" (0.5) */
    /* imagemap: w x h texels, row 0 at the top of the image; a spectrum texture
       keeps 4 floats per texel (m and the sigmoid's 3 coefficients: the texel's
       reflectance is m sigmoid(c, lambda), rgbfit.c), a float one 1 (the mean of
       R, G, B); bilinear lookup (pbrt-v4's default filter).  marble: its colour spline
       tabulated the same way, w knots in one row (texture.c section 4) */
    int w, h;
    float *texel;
    TexWrap wrap;
    int nearest;               /* "string filter" "point": the nearest texel (pbrt-v4's
                                  Point filter at full resolution), else bilinear */
    int illuminant;            /* an area light's emission image (lights.c): texels are RGB
                                  illuminant spectra, m = 2 max(rgb) times the sigmoid of
                                  rgb / m, not clamped to 1 (the light multiplies by D65) */
    int rgb_arg;               /* a spectrum argument was an "rgb" that is not grey: held
                                  as a reflectance (RGBAlbedoSpectrum), which an unbounded
                                  use (a conductor's eta, k) would read otherwise */
    const char *file; int line;
} Texture;
/* Texture t of the table tex at the surface point (lambda ignored by float textures). */
float tex_eval(const Texture *tex, int t, const SurfacePoint *sp, float lambda_nm);
void  tex_free(Texture *t);   /* (tex_set_image, which reads an Image, is in section 10) */
/* pbrt-v4's Perlin noise at (x, y, z) (Perlin 2002's gradients and permutation), in
   about [-1, 1], 0 at integer points; dots call it with z = 0.5. */
float tex_noise(float x, float y, float z);
/* n[0] = tex_noise at p, n[1..3] at p + h along x, y and z, the same floats as four
   tex_noise calls; the calls in one lattice cell share its corner hashes (the
   finite-difference gradient of the cloud's wisps, medium.c). */
void  tex_noise_diff(Vec3 p, float h, float n[4]);
/* Fractional Brownian motion: sum over i < octaves of omega^i noise(1.99^i p), pbrt-v4's
   FBm for a footprint of zero (texture.c section 4). */
float tex_fbm(Vec3 p, float omega, int octaves);
/* pbrt-v4's Turbulence for a footprint of zero: sum over i < octaves of omega^i
   |noise(1.99^i p)|, plus 0.2 omega^octaves (texture.c section 4). */
float tex_turbulence(Vec3 p, float omega, int octaves);
/* A marble texture's colour table (texture.c section 4): 0 and a message when out of memory. */
int   tex_marble_init(Texture *t, RgbTable *rgb, Error *err);
/* ---- Shading-normal perturbation (bump.c): pbrt-v4's bump and normal maps ----
   A material's "displacement" d moves the surface to p + d ns, its "normalmap"
   gives ns in the frame (dp/du, ns x dp/du, ns); either way the shading normal of
   the hit becomes normalize(dp'/du x dp'/dv), on the geometric normal's side
   (THEORY §14).  The derivatives are pbrt-v4's per shape (ShadingDiff). */
typedef struct Bump {
    int disp_tex;              /* "texture displacement": 1 + a float texture's index;
                                  0: the constant disp */
    float disp;                /* "float displacement" */
    int nw, nh;                /* "normalmap": nw x nh texels (nw = 0: none) ... */
    float *nrgb;               /* ... linear RGB, 3 floats each, top row first */
} Bump;
void bump_free(Bump *b);
/* The shading frame's derivatives at a hit: dp/du, dp/dv (triangles with "N":
   made tangent to ns) and dn/du, dn/dv, in world space. */
typedef struct { Vec3 dpdu, dpdv, dndu, dndv; } ShadingDiff;
/* At the hit h of ray r whose point is *sp (scene_surface_point); sets sp->u, sp->v
   of a full sphere, which bvh.c leaves 0 unless a texture reads them. */
void shading_differentials(const struct Scene *s, const Ray *r, const HitRecord *h,
                           SurfacePoint *sp, ShadingDiff *d);
/* *sp with the shading normal of m's Bump (m->bump not NULL), written to *out;
   returns out. */
const SurfacePoint *bump_shade(const struct Scene *s, const Material *m, const Ray *r,
                               const HitRecord *h, const SurfacePoint *sp, SurfacePoint *out);
/* *sp with out->dpdu set to the shading frame's dp/du (shading_differentials: a
   triangle's "S" when it has them), written to *out; returns out. */
const SurfacePoint *tangent_shade(const struct Scene *s, const Ray *r, const HitRecord *h,
                                  const SurfacePoint *sp, SurfacePoint *out);
/* Smooth dielectrics scatter into discrete (delta) directions: no NEE there.  A
   conductor with a roughness texture is not: it may be smooth at some points, where
   bsdf_eval gives 0 and bsdf_sample a delta lobe. */
int   mat_is_delta(const Material *m);
/* pbrt-v4's BSDF::Regularize (Integrator "bool regularize", path.c; THEORY §14):
   *out = m with its microfacet alphas widened by tr_regularize (dielectric, conductor,
   coateddiffuse's coat, coatedconductor's coat and base), 1; 0 and no copy for the
   other types, which pbrt-v4 leaves as they are. */
int   mat_regularized(const Material *m, Material *out);
/* A conductor's, coateddiffuse's or coatedconductor's texture-valued parameters at one surface point
   (pbrt-v4 evaluates them in GetBxDF): the alphas, when has_r the reflectance at
   the path's wavelengths, clamped to [0, 1], when has_ek a conductor's eta and k
   there (unbounded: k >= 0, eta >= 1e-3), a layered material's slab (thickness, g,
   when has_a its albedo); without textures the Material's own. */
typedef struct {
    float alpha, alpha_t;
    int has_r;
    float r[HERO_N];
    float cond_alpha, cond_alpha_t;   /* coatedconductor: the base's alphas */
    int has_ek;                /* a textured eta or k: the conductor's (coatedconductor:
                                  the base's, in vacuum) n and k at the path's wavelengths */
    float eta[HERO_N], k[HERO_N];
    float thick, g;            /* coateddiffuse, coatedconductor: the slab's thickness and
                                  HG g (textured: thickness >= FLT_MIN, g in [-0.99, 0.99]) */
    int has_a;                 /* a textured albedo: the slab's albedo a at the path's
                                  wavelengths, clamped to [0, 1] */
    float a[HERO_N];
} MatPoint;
void  mat_point(const Material *m, const SurfacePoint *sp, const float *lambda, unsigned alive,
                MatPoint *mp);

/* A direction sampled from the BSDF with the hero wavelength lambda[0]. */
typedef struct {
    Vec3 wi;                   /* unit direction towards the next vertex */
    float f[HERO_N];           /* BSDF value per wavelength (without the cosine) */
    float pdf;                 /* solid-angle pdf of wi with the hero's index (delta:
                                  the probability of the chosen lobe) */
    float pdf_l[HERO_N];       /* the pdf the same wi has with each wavelength's own
                                  index (rough spectral MIS); pdf_l[0] == pdf */
    int delta;                 /* 1 for a specular (Dirac) sample */
    float eta2[HERO_N];        /* etap_j^2 when wi refracts through a dielectric (f holds
                                  its 1/etap_j^2: radiance is squeezed into the denser
                                  side), else 1; the roulette undoes it (THEORY §8) */
    float u_lobe;              /* a smooth dielectric's lobe number u0 rescaled into the
                                  chosen lobe: u0 / F after a reflection, (u0 - F) / (1 - F)
                                  after a refraction.  Given the lobe it is uniform on
                                  [0, 1) and independent of it, so path.c may spend it on
                                  the next such choice (THEORY §8.1); -1 elsewhere */
} BsdfSample;

/* Sample wi given wo (unit, pointing away from the surface).  Wavelengths whose
   bit is not in `alive` get f = 0.  Returns 0 when no direction was produced. */
int  bsdf_sample(const Material *m, const SurfacePoint *sp, Vec3 wo, const float *lambda,
                 unsigned alive, float u0, float u1, float u2, BsdfSample *out);
/* Evaluate f and the pdfs for a given pair (for NEE); delta materials give 0. */
void bsdf_eval(const Material *m, const SurfacePoint *sp, Vec3 wo, Vec3 wi,
               const float *lambda, unsigned alive, float f[HERO_N], float pdf_l[HERO_N]);
/* The conductor's sampler, value and pdf, called by bsdf_sample and bsdf_eval in
   the shading frame (local directions, n = +z).  pdf_l[j] = pdf for every j: the
   direction does not depend on the wavelength. */
int   conductor_sample(const Material *m, const MatPoint *mp, Vec3 wo, const float *lambda,
                       unsigned alive, float u1, float u2, BsdfSample *out, Vec3 *wi_local);
void  conductor_eval(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                     unsigned alive, float f[HERO_N], float pdf_l[HERO_N]);
/* ---- Measured BRDFs (measured.c): pbrt-v4's "measured" material, an RGL tensor
   file in Dupuy and Jakob's adaptive parameterization (docs/measured.md) ----
   A Warp2D is a bilinear density on an nx x ny grid over [0,1]^2, interpolated
   linearly between up to 3 parameters' grid values; `sampled` ones are normalized
   per parameter slice and carry the CDFs that warp2d_sample and warp2d_invert use. */
typedef struct {
    int nx, ny, nparam, sampled;
    int psize[3];              /* knots per parameter */
    unsigned stride[3];        /* slices per step of each parameter (0 for one knot) */
    float *pval[3];            /* the parameters' knots, increasing (owned) */
    float *data, *marg, *cond; /* density; marginal CDF over rows; running sums in rows */
} Warp2D;
/* A copy of data (psize[0] x .. x ny x nx floats, the last index contiguous); 0 when
   out of memory or a sampled slice integrates to 0. */
int   warp2d_init(Warp2D *w, const float *data, int nx, int ny, int nparam, const int *psize,
                  const float *const *pval, int sampled);
void  warp2d_free(Warp2D *w);
/* The interpolated value at (ux, uy) (a sampled warp: the normalized density). */
float warp2d_eval(const Warp2D *w, const float *param, float ux, float uy);
/* u uniform in [0,1)^2 -> a point of the density, *pdf its density; invert: back. */
void  warp2d_sample(const Warp2D *w, const float *param, float u[2], float *pdf);
void  warp2d_invert(const Warp2D *w, const float *param, float u[2], float *pdf);
typedef struct MeasuredBrdf {
    Warp2D ndf, sigma;         /* D over u(wm), projected area over u(wo) */
    Warp2D vndf, lum;          /* the visible-NDF warp and the luminance warp (phi_i, theta_i) */
    Warp2D spectra;            /* R over the warped square (phi_i, theta_i, lambda) */
    float *theta_i, *phi_i, *wavelengths;
    int n_wavelengths, isotropic;
    int refs;                  /* materials sharing it (material.c: one read per file) */
    char path[1024];           /* the file it was read from ("" : not shared) */
} MeasuredBrdf;
/* Read a tensor file (from memory: name is for messages); 0 and "file: problem". */
int   measured_read(const char *path, MeasuredBrdf *b, Error *e);
int   measured_read_memory(const unsigned char *d, size_t n, const char *name, MeasuredBrdf *b,
                           Error *e);
void  measured_free(MeasuredBrdf *b);
/* f and pdf (pdf_l[j] = pdf: the direction does not depend on lambda) in the shading
   frame, and the sampler (wi_local in that frame; 0 when no direction). */
void  measured_eval(const MeasuredBrdf *b, Vec3 wo, Vec3 wi, const float *lambda, unsigned alive,
                    float f[HERO_N], float pdf_l[HERO_N]);
int   measured_sample(const MeasuredBrdf *b, Vec3 wo, const float *lambda, unsigned alive, float u1,
                      float u2, BsdfSample *out, Vec3 *wi_local);
/* Whether m's BSDF turns with the surface's dp/du (pbrt-v4's shading frame): an
   anisotropic measured file (its phi) or an anisotropic rough conductor, coat or
   coated conductor's base (alpha_x along dp/du); path.c then sets sp->dpdu by
   tangent_shade (bump.c). */
int   mat_needs_tangent(const Material *m);
/* The shading frame of material m at sp: (dp/du made tangent, ns x that, ns) where
   mat_needs_tangent, else frame_from_normal(ns). */
Frame mat_frame(const Material *m, const SurfacePoint *sp);
/* coateddiffuse and coatedconductor (layered.c), in the shading frame: f and the pdf are stochastic
   estimates by random walks, deterministic for a given seed; bsdf_eval seeds them
   with layered_seed(world wo, world wi, 0), and layered_sample (which takes the
   frame and the world wo, and sets out->wi in world space) reports that same pdf
   with f scaled so that f cos / pdf is the walk's weight.  key (0 in renders)
   varies the random streams (the tests average over it).  mp: the textured
   parameters at the point (mat_point), or NULL for the Material's own. */
uint64_t layered_seed(Vec3 wo_world, Vec3 wi_world, uint64_t key);
float layered_pdf(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                  unsigned alive, uint64_t seed);
void  layered_eval(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                   unsigned alive, uint64_t seed, float f[HERO_N], float pdf_l[HERO_N]);
int   layered_sample(const Material *m, const MatPoint *mp, const Frame *fr, Vec3 wo_world,
                     const float *lambda, unsigned alive, float u0, float u1, float u2, uint64_t key,
                     BsdfSample *out);
/* ---- pbrt-v4's "hair" (hair.c; THEORY §16): Chiang et al. 2016's fibre, spectral ----
   sigma_a per unit radius is given, or made from a reflectance c (at each
   wavelength, hair_sigma_a_from_reflectance) or from melanin concentrations
   (hair_melanin_rgb, an unbounded RGB spectrum); eta, beta_m, beta_n are the index
   and the longitudinal and azimuthal roughnesses, alpha the scales' tilt (degrees). */
enum { HAIR_SIGMA_A, HAIR_COLOR, HAIR_EU, HAIR_PH, HAIR_ETA, HAIR_BETA_M, HAIR_BETA_N,
       HAIR_ALPHA, HAIR_NTEX };    /* the parameters that may be textures */
#define HAIR_MEL_N 129             /* knots of the melanin ratio table */
typedef struct Hair {
    Spectrum sigma_a;          /* the absorption when from_color is 0 (constant melanins:
                                  made from them) */
    Spectrum color;            /* from_color: the reflectance c, clamped to [0, 1] at use */
    int from_color;
    int from_melanin;          /* textured melanins: sigma_a made at each hit */
    float eumelanin, pheomelanin;
    float eta, beta_m, beta_n, alpha;
    int tex[HAIR_NTEX];        /* 1 + a texture's index (Scene.textures), 0: the value above */
    float mel_c[HAIR_MEL_N][3];/* from_melanin: the sigmoid coefficients of the melanins'
                                  RGB at pheomelanin share k / (HAIR_MEL_N - 1) */
} Hair;
/* The hit point sp with the shape's dp/du (the fibre's axis) and (u, v) filled in,
   written to *out; returns out (path.c, at a hair vertex). */
const SurfacePoint *hair_shade(const struct Scene *s, const Ray *r, const HitRecord *h,
                               const SurfacePoint *sp, SurfacePoint *out);
/* The BSDF of a MAT_HAIR material at sp (sp->dpdu set), as bsdf_sample and
   bsdf_eval: f without the cosine, pdf_l[j] = pdf for every j (the lobe is chosen
   by the mean attenuation over the alive wavelengths). */
int   hair_sample(const Material *m, const SurfacePoint *sp, Vec3 wo, const float *lambda,
                  unsigned alive, float u0, float u1, float u2, BsdfSample *out);
void  hair_eval(const Material *m, const SurfacePoint *sp, Vec3 wo, Vec3 wi, const float *lambda,
                unsigned alive, float f[HERO_N], float pdf_l[HERO_N]);
/* pbrt-v4's SigmaAFromReflectance (Chiang et al. (9)) at one wavelength; the linear
   sRGB sigma_a of the two melanins (pbrt-v4's SigmaAFromConcentration); log I0. */
float hair_sigma_a_from_reflectance(float c, float beta_n);
void  hair_melanin_rgb(float eumelanin, float pheomelanin, float rgb[3]);
double hair_log_i0(double x);
/* ---- pbrt-v4's "subsurface" (subsurface.c; THEORY §18): a tabulated BSSRDF ----
   The surface is a dielectric of index eta (smooth or GGX, Material.eta, alpha);
   a path that refracts in leaves at another point of the same material, found by
   a probe segment, with weight Sp / pdf, and goes on from there by the lobe Sw.
   The radial profile of a medium of albedo rho and extinction 1 is tabulated at
   SSS_RHO_N albedos and SSS_R_N optical radii (profile: 2 pi r' Sr'; rho_eff its
   integral; cdf its running integral), read by Catmull-Rom splines. */
#define SSS_RHO_N 100              /* albedo knots of the table (pbrt-v4's) */
#define SSS_R_N 64                 /* radius knots (pbrt-v4's) */
#define SSS_PROBE_HITS 256         /* @@ surfaces one probe segment may cross; beyond, the
                                      rest of the segment is not searched */
typedef struct {
    float rho[SSS_RHO_N], radius[SSS_R_N];
    float profile[SSS_RHO_N * SSS_R_N], cdf[SSS_RHO_N * SSS_R_N];
    float rho_eff[SSS_RHO_N];
} BssrdfTable;
enum { SSS_TEX_SIGMA_A, SSS_TEX_SIGMA_S, SSS_TEX_MFP, SSS_NTEX };
typedef struct Subsurface {
    BssrdfTable table;         /* for this material's g and eta */
    int from_albedo;           /* 1: "reflectance" (Material.reflectance or reflectance_tex)
                                  and mfp give the coefficients at each point */
    Spectrum sigma_a, sigma_s; /* per scene unit before "scale" (named: per mm, pbrt-v4) */
    Spectrum mfp;              /* from_albedo: the mean free path before "scale" */
    int tex[SSS_NTEX];         /* 1 + a spectrum texture's index; 0: the spectrum above */
    float scale, eta, g;
} Subsurface;
/* The diffusion profile's two parts for a medium (sigma_s, sigma_a, g) under a
   boundary of index eta at radius r (photon beam diffusion, subsurface.c), and
   pbrt-v4's polynomial Fresnel moments. */
double bssrdf_single(double sigma_s, double sigma_a, double g, double eta, double r);
double bssrdf_multiple(double sigma_s, double sigma_a, double g, double eta, double r);
double fresnel_moment1(double eta);
double fresnel_moment2(double eta);
void  bssrdf_table_build(BssrdfTable *t, float g, float eta);
/* Catmull-Rom splines through (x[k], f[k]), x increasing: the four weights of
   f[offset .. offset+3] at v (0 outside [x0, x_n-1]); the integral (cdf[k]: up
   to x[k]); the x where the increasing f reaches u. */
int   catmull_rom_weights(const float *x, int n, float v, int *offset, float w[4]);
float catmull_rom_integrate(const float *x, const float *f, int n, float *cdf);
float catmull_rom_invert(const float *x, const float *f, int n, float u);
/* Per wavelength, for extinction sigma_t and albedo rho: the profile Sr(r), the
   density of the radius sampler in the plane, Sr / rho_eff, and the sampler
   (-1: none); rho and mfp from an effective albedo R (pbrt-v4's
   SubsurfaceFromDiffuse). */
float bssrdf_sr(const BssrdfTable *t, float sigma_t, float rho, float r);
float bssrdf_pdf_sr(const BssrdfTable *t, float sigma_t, float rho, float r);
float bssrdf_sample_sr(const BssrdfTable *t, float sigma_t, float rho, float u);
void  bssrdf_from_albedo(const BssrdfTable *t, float R, float mfp, float *sigma_a, float *sigma_s);
/* sigma_t and rho of a subsurface material at sp for the alive wavelengths. */
void  sss_coeffs(const Material *m, const SurfacePoint *sp, const float *lam, unsigned alive,
                 float sigma_t[HERO_N], float rho[HERO_N]);
/* The exit of a path that entered material m (index mi into Scene.materials, as
   its shapes name it) at `entry`: u[0] the probe's axis, u[1], u[2] its radius
   and angle, u[3] the choice among the hits.  1 and *out (the exit point, Sp and
   the area density per wavelength) when there is one. */
typedef struct {
    SurfacePoint sp;
    HitRecord hit;
    float Sp[HERO_N], pdf[HERO_N];
    int n;                     /* hits of the material along the probe */
    int rays;                  /* BVH queries made */
} SssExit;
int   sss_probe(const struct Scene *s, const Material *m, int mi, const SurfacePoint *entry,
                const float *lam, unsigned alive, const float u[4], SssExit *out);
/* The exit lobe Sw (cosine-weighted on the side of sp->ns); bsdf_sample and
   bsdf_eval call these for a MAT_SUBSURFACE_EXIT material. */
int   sss_exit_sample(const Material *m, const SurfacePoint *sp, unsigned alive, float u1, float u2,
                      BsdfSample *out);
void  sss_exit_eval(const Material *m, const SurfacePoint *sp, Vec3 wi, unsigned alive,
                    float f[HERO_N], float pdf_l[HERO_N]);
/* ---- The scattering room (microfacet.c): what the BSDFs above are built from ----
   Local shading frame (n = +z), directions pointing away from the surface.
   material.c, conductor.c and layered.c call it; it calls none of them. */
/* Mirror w about n: 2 (w.n) n - w. */
Vec3  reflect_dir(Vec3 w, Vec3 n);
/* Refract w about n (unit, any side) with relative index eta; 0 on total internal
   reflection.  *etap receives the index ratio along the path. */
int   refract_dir(Vec3 w, Vec3 n, float eta, float *etap, Vec3 *wt);
/* A material's real index of refraction at one wavelength (a sampled 0 means 1). */
float mat_eta(const Material *m, float lambda_nm);
/* Fresnel reflectance of a dielectric interface, unpolarised (cos_i may be < 0:
   then the ray is inside and eta is inverted). */
float fresnel_dielectric(float cos_i, float eta);
/* Fresnel reflectance of a conductor (complex index eta + i k) seen from a medium
   of index 1, unpolarised; cos_i in [0, 1]. */
float fresnel_conductor(float cos_i, float eta, float k);
/* pbrt-v4's conductor "reflectance" r as an absorption index over eta = 1:
   k = 2 sqrt(r) / sqrt(1 - r), whose normal-incidence Fresnel is exactly r
   (the caller clamps r below 1) */
float conductor_k_of_reflectance(double r);
/* Anisotropic Trowbridge-Reitz (GGX) with alpha_x, alpha_y (isotropic: equal): the
   normal distribution D(wm), the height-correlated masking-shadowing G(wo, wi),
   and the visible-normal sampler with its density
   D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / |cos wo|. */
float tr_D(float ax, float ay, Vec3 wm);
float tr_G(float ax, float ay, Vec3 wo, Vec3 wi);
Vec3  tr_sample_wm(float ax, float ay, Vec3 wo, float u1, float u2);
float tr_pdf_wm(float ax, float ay, Vec3 wo, Vec3 wm);
/* Reflection: the half vector normalize(wo + wi) turned to +z (0: none), and the
   density D_wo(wm) / (4 |wo.wm|) of wi = reflect_dir(wo, wm). */
int   tr_half_vector(Vec3 wo, Vec3 wi, Vec3 *wm);
float tr_pdf_reflect(float ax, float ay, Vec3 wo, Vec3 wm);
/* Both alphas below 1e-3: a smooth (delta) surface.  remaproughness: alpha = sqrt(r).
   tr_regularize: pbrt-v4's Regularize, alpha < 0.3 -> clamp(2 alpha, 0.1, 0.3). */
int   tr_smooth(float ax, float ay);
void  tr_rough_floor(float *ax, float *ay);   /* rough: each alpha >= 1e-4 (pbrt-v4) */
float tr_alpha_of_roughness(float roughness);
float tr_regularize(float alpha);
/* The rough dielectric interface (GGX alpha, index eta) for a local pair: f in
   radiance mode (with 1/eta'^2 on transmission) and the pdf of sampling wi from wo
   by a visible normal and the lobe choice F : 1 - F, restricted to `lobes`
   (LOBE_R | LOBE_T: both); 0 for a pair no microfacet connects.  _xy: anisotropic,
   alpha_x along the local x axis, alpha_y along y (a layered material's coat). */
#define LOBE_R 1
#define LOBE_T 2
void  tr_dielectric_pair(float alpha, float eta, Vec3 wo, Vec3 wi, int lobes, float *f, float *pdf);
void  tr_dielectric_pair_xy(float ax, float ay, float eta, Vec3 wo, Vec3 wi, int lobes, float *f,
                            float *pdf);

/* ======================================================================
   6b. Participating media (medium.c; THEORY §12 derives the estimator)
   ====================================================================== */
/* pbrt-v4's MakeNamedMedium "homogeneous": a medium that fills the space between
   the surfaces whose MediumInterface names it, with the same coefficients
   everywhere.  Light travelling a distance t in it keeps the fraction
   Tr(t) = exp(-sigma_t t) (THEORY (15)), sigma_t = sigma_a + sigma_s (per scene unit, per
   wavelength: a chromatic medium when sigma_t depends on lambda); a collision
   scatters with probability sigma_s / sigma_t into the Henyey-Greenstein lobe of
   asymmetry g (THEORY (18a)); the medium emits radiance sigma_a Le per unit length. */
/* pbrt-v4's MakeNamedMedium "uniformgrid" (docs/media.md, THEORY §14): the same
   spectra scaled at each point by a density d(x) >= 0, sigma_t(x, lambda) =
   d(x) sigma_t(lambda), and an emission scaled by a grid too.  A MediumGrid holds
   nx ny nz samples over the unit cube of the medium's bounds p0..p1, x fastest;
   sample (i, j, k) sits at the centre of its cell ((i + 1/2)/nx, ...), a lookup
   interpolates trilinearly between the eight nearest and reads 0 beyond the
   outermost samples (pbrt-v4's SampledGrid).  The majorant grid holds, for each
   of MAJORANT_RES^3 cells of the unit cube, the largest sample any lookup in the
   cell can interpolate: d(x) <= dmax(cell) there, so sigma_bar(lambda) =
   dmax sigma_t(lambda) bounds sigma_t(x, lambda) (delta tracking, medium.c). */
/* pbrt-v4's "rgbgrid" (RGBGridMedium): sigma_a, sigma_s and Le themselves are
   grids of rgb triples, so the medium is chromatic in space: each sample becomes a
   spectrum at load (2 max(rgb) x sigmoid, RgbTable's fit; D65 for Le), a lookup
   interpolates the eight samples' values at each wavelength (pbrt-v4 converts,
   then interpolates), and the majorant grid holds scale x (the largest sigma_a
   over wavelengths + the largest sigma_s) of the cell's samples: the same for
   every wavelength. */
/* pbrt-v4's "cloud" (CloudMedium): sigma_a(lambda) and sigma_s(lambda) scaled by a
   procedural density in [0, 1] (medium_cloud_density: Perlin noise, tex_noise);
   its majorant grid holds 1 everywhere (pbrt-v4's one homogeneous majorant). */
/* pbrt-v4's "nanovdb" (NanoVDBMedium): the uniformgrid's model with d(x) read
   from a float grid of a NanoVDB file (nanovdb.c documents the layout): a sparse
   tree of 8^3-voxel leaves under 16^3 and 32^3 nodes, voxel (i, j, k) at index
   point (i, j, k), an affine map from index space to the medium's space.  A
   NanoGrid is one grid's bytes as the file holds them; nanovdb_sample blends
   the eight voxels around a point of the medium's space trilinearly (background
   where the tree has none).  Its majorant grid has NANOVDB_MAJORANT_RES^3 cells
   over the file's world bbox (pbrt-v4's 64^3). */
typedef enum { MEDIUM_HOMOGENEOUS, MEDIUM_UNIFORMGRID, MEDIUM_RGBGRID, MEDIUM_CLOUD,
               MEDIUM_NANOVDB } MediumType;
typedef struct { int nx, ny, nz; float *v; } MediumGrid;
typedef struct {
    unsigned char *buf; size_t size;   /* the grid's memory image (NULL: none) */
    size_t root;                       /* where its root node starts in buf */
    uint32_t n_tiles;                  /* root tiles, */
    uint64_t *keys; size_t *tiles;     /* sorted by key, with their offsets in buf */
    float background;                  /* the value where no tile is */
    float invf[9], vecf[3];            /* index = invf (p - vecf) (pbrt-v4's worldToIndexF) */
    double mat[9], vec[3];             /* p = mat index + vec */
    double wmin[3], wmax[3];           /* the file's world bbox of its active voxels */
} NanoGrid;
/* The first grid named gridname of the file (g->buf NULL when there is none: not
   an error); 0 and "file: problem" for a file it refuses (nanovdb.c says which). */
int    nanovdb_read(const char *path, const char *gridname, NanoGrid *g, Error *e);
int    nanovdb_read_memory(const unsigned char *d, size_t n, const char *name,
                           const char *gridname, NanoGrid *g, Error *e);
double nanovdb_sample(const NanoGrid *g, Vec3 p);    /* p in the medium's space */
/* maj[res^3] (x fastest) over lo..hi: each cell's bound of nanovdb_sample there */
void   nanovdb_majorant(const NanoGrid *g, const double lo[3], const double hi[3], int res,
                        float *maj);
void   nanovdb_free(NanoGrid *g);
#define MAJORANT_RES 16            /* @@ majorant cells per axis (pbrt-v4: 16) */
#define NANOVDB_MAJORANT_RES 64    /* @@ a nanovdb medium's (pbrt-v4: 64) */
#define MEDIUM_MAX_EVENTS 1000000L /* @@ tentative collisions one tracking may meet; a ray
                                      that needs more (an optical depth of about 10^6)
                                      is taken as blocked */

typedef struct {
    const char *name;          /* the MakeNamedMedium name (in Scene.strings) */
    MediumType type;
    Spectrum sigma_a, sigma_s; /* absorption, scattering (1/scene unit), "scale" applied */
    Spectrum Le;               /* emission as given (its shape; radiance per Lescale) */
    float Le_scale;            /* "Lescale" (an rgb Le: with the D65 normalisation of rgb
                                  illuminants); 0: the medium does not emit */
    float g;                   /* HG asymmetry in (-1, 1) */
    /* uniformgrid only (all zero for homogeneous): */
    Xform medium_from_world;   /* the inverse of the CTM at MakeNamedMedium */
    Vec3 p0, p1;               /* the grids' bounds in the medium's space */
    MediumGrid density;        /* d(x) */
    MediumGrid lescale;        /* the emission's scale grid ("Lescale"; default 1x1x1 of 1) */
    MediumGrid temperature;    /* kelvin (v NULL: none): blackbody emission instead of Le */
    float temp_offset, temp_scale;  /* T = (T_grid - offset) scale; no emission below 100 K */
    float *majorant;           /* maj_res^3 maxima of d, x fastest (rgbgrid: of
                                  sigma_t itself, per scene unit) */
    int maj_res;               /* MAJORANT_RES; a nanovdb medium NANOVDB_MAJORANT_RES */
    /* rgbgrid only: 4 floats per sample, 2 max(rgb) and the sigmoid coefficients
       (spec_sigmoid_eval); v NULL: absent (sigma_a, sigma_s: 1 everywhere) */
    MediumGrid rgb_sa, rgb_ss, rgb_le;
    float rgb_scale;           /* "scale" of the rgb grids */
    int chromatic;             /* rgbgrid: some sigma sample is not grey */
    float cloud_density, wispiness, frequency;  /* cloud: "density", "wispiness", "frequency" */
    NanoGrid vdb[2];           /* nanovdb: density and temperature (buf NULL: none) */
    const char *file; int line;/* the MakeNamedMedium directive */
} Medium;

/* What a uniformgrid holds at world point p for wavelengths lam[j] (lanes not in
   `alive` get 0): sigma_a, sigma_s and the emitted radiance before the render's
   normalisation (render.c: R.med_le; a temperature grid's blackbody is absolute,
   peak 1). */
typedef struct { double sa[HERO_N], ss[HERO_N], le[HERO_N]; } MediumPoint;
void  medium_point(const Medium *m, Vec3 p, const float *lam, unsigned alive, MediumPoint *out);
double medium_grid_lookup(const MediumGrid *g, Vec3 u);   /* u in the unit cube */
float medium_cloud_density(const Medium *m, Vec3 q);       /* a cloud's d at q, medium space */
void  medium_free(Medium *m);                              /* its grids */

/* Delta tracking (medium.c, THEORY §14).  medium_track walks the ray o + t d
   (d unit) from t = 0 to tmax through the majorant cells of medium m and draws
   tentative collisions at the hero's majorant sigma_bar_0 (the first distance
   from u, the one after each collision from rng; the optical depth left at a
   cell's end carries into the next).  At each it calls fn(ctx, ev): fn returns 0 to
   stop there (a real collision), 1 to go on (a null one).  Returns 1 when fn
   stopped it, 0 when the ray reached tmax with tm_end[j] = Tbar_j / Tbar_0 of the
   stretch after the last tentative collision. */
typedef struct {
    float t;                   /* distance along the ray */
    Vec3 p;                    /* the point */
    double smaj[HERO_N];       /* the majorant sigma_bar(lambda_j) of its cell */
    double tm[HERO_N];         /* Tbar_j / Tbar_0 since the previous tentative collision */
    MediumPoint mp;            /* the medium there */
} MediumEvent;
typedef int (*MediumEventFn)(void *ctx, const MediumEvent *ev);
int   medium_track(const Medium *m, Ray ray, float tmax, const float *lam, unsigned alive,
                   float u, Rng *rng, MediumEventFn fn, void *ctx, double tm_end[HERO_N]);

float medium_sigma_t(const Medium *m, float lambda_nm);
float medium_sigma_s(const Medium *m, float lambda_nm);
float medium_sigma_a(const Medium *m, float lambda_nm);
/* The Henyey-Greenstein phase function for the cosine between the direction the
   light travelled (d) and the one it leaves in (wi): forward scattering for g > 0;
   it integrates to 1 over the sphere (THEORY (18a)). */
float hg_phase(float g, float cos_d_wi);
/* Sample wi from it around the unit travel direction d (THEORY (18b));
   *pdf = hg_phase(...). */
Vec3  hg_sample(float g, Vec3 d, float u1, float u2, float *pdf);
/* pbrt-v4's named scattering coefficients (MakeNamedMedium "string preset"):
   sigma_a and sigma_s' as RGB in mm^-1; 0 if the name is unknown. */
int   medium_preset(const char *name, float sigma_a[3], float sigma_s[3]);
/* The medium a ray leaving shape sh along w is in, for a ray that was in `cur`:
   the shape's inside or outside medium if it is a transition, else cur. */
int   medium_after(const struct Scene *s, int shape, int cur, Vec3 w, Vec3 ng);

/* Equiangular distance sampling (equiangular.c, THEORY §12.1): along the segment
   o + t d, 0 <= t <= tmax (d unit; tmax may be INFINITY), towards the point c,
   the density (18c) D / ((theta_b - theta_a) (D^2 + (t - Delta)^2)).
   equi_segment returns 0 when the ray passes through c (no density). */
typedef struct {
    double delta, D;           /* distance along the ray to the point nearest c; the
                                  ray's distance from c */
    double theta_a, theta_b;   /* the angles, seen from c, of t = 0 and t = tmax */
    float tmax;
} EquiSeg;
int    equi_segment(Vec3 o, Vec3 d, float tmax, Vec3 c, EquiSeg *seg);
double equi_sample(const EquiSeg *seg, double u, double *pdf);   /* (18d) */
double equi_pdf(const EquiSeg *seg, double t);                   /* (18c); 0 off the segment */
/* The lamps the technique aims at (point and spot lights, whole spheres NEE samples
   as one piece): n = 0 (off) without any or with more than EQUI_LAMPS_MAX; each
   is chosen with probability 1 / n. */
#define EQUI_LAMPS_MAX 8
typedef struct {
    int n;
    int emitter[EQUI_LAMPS_MAX];
    Vec3 center[EQUI_LAMPS_MAX];
} EquiLamps;
void   equi_lamps_build(const struct Scene *s, const int *emitter_piece, EquiLamps *out);
int    equi_lamp_of(const EquiLamps *L, int e);       /* its index in L; -1: not one */

/* ======================================================================
   7. Emitters and emitter selection: the types (lights.c; infinite.c, delta.c,
      lighttree.c)
   ====================================================================== */
/* An infinite light (LightSource "infinite", infinite.c): light arriving from every
   direction, from infinitely far away.  Constant (one spectrum) or an image map in
   pbrt-v4's equal-area octahedral layout, a square RGB image whose texel (x, y)
   (row 0 at the top) covers the directions equal_area_square_to_sphere maps its
   cell to, in the light's frame (the CTM at the LightSource).  RGB texels become
   spectra as pbrt-v4's RGBIlluminantSpectrum does: 2 max(rgb) x sigmoid(quadratic
   in lambda) x D65. */
typedef struct {
    Xform world_from_light;    /* CTM at the LightSource (rotation expected) */
    int res;                   /* image map: res x res texels; 0: constant */
    float *texel;              /* 4 floats per texel: m = 2 max(rgb) and the sigmoid
                                  polynomial's 3 coefficients (spectrum.c) */
    float *cdf_rows;           /* res + 1: marginal CDF over rows (pbrt-v4: texel weight =
                                  the mean of its R, G, B) */
    float *cdf_cols;           /* res x (res + 1): each row's conditional CDF */
    float *row_sum;            /* res: each row's weight sum */
    double weight_sum;         /* sum of all texel weights (0: sampled uniformly) */
    Vec3 center; double radius;/* the scene's bounding sphere (power, NEE points) */
    Spectrum mean;             /* image map: the RGB illuminant spectrum of its mean colour
                                  (selection weights only) */
    /* A portal (pbrt-v4's PortalImageInfiniteLight, infinite.c section 4): light
       arrives only through the rectangle portal_p[0..3] (world space), and texel[]
       holds the map resampled onto the portal's rectified directions (u, v). */
    int portal;                /* 1: a portal light */
    Vec3 portal_p[4];          /* its corners, as given */
    Frame portal_frame;        /* s = p3 - p0, t = p1 - p0 (unit), n = s x t: towards the sky */
    double *sat;               /* (res + 1)^2 summed-area table of the rectified sampling
                                  weights (each texel's mean R, G, B times dw/d(u,v)) */
    const char *file; int line;/* the LightSource directive, for messages */
} InfiniteLight;

/* A delta light (delta.c): pbrt-v4's LightSource "point", "spot", "distant",
   "goniometric" and "projection".  A point or spot light sits at one point and
   radiates intensity I(lambda) (W/sr/nm), a spot only into a cone with a smooth
   falloff; a goniometric light is a point light whose intensity an image of
   directions scales; a projection light projects an RGB image through a
   frustum; a distant light sends radiance from one direction, as from infinitely
   far away.  No ray can hit one: NEE alone finds them (THEORY §11). */
typedef enum { DELTA_NONE = 0, DELTA_POINT, DELTA_SPOT, DELTA_DISTANT, DELTA_GONIO,
               DELTA_PROJECTION } DeltaType;
typedef struct {
    DeltaType type;            /* DELTA_NONE: not a delta light */
    Vec3 p;                    /* point, spot, goniometric, projection: the position, in
                                  world space */
    Vec3 w;                    /* spot: unit axis of the cone (from -> to); projection:
                                  CTM(0, 0, 1), unit; distant: unit direction TOWARDS
                                  the light (from - to) */
    float cos_start, cos_end;  /* spot: cos(coneangle - conedeltaangle), cos(coneangle):
                                  full intensity inside the first, none outside the second;
                                  projection: 1 and the cosine of the frustum's corner */
    float obj_from_world[9];   /* spot, goniometric, projection: the inverse CTM's 3x3 part
                                  (row-major): the light's own frame, as in pbrt-v4 ... */
    Vec3 axis_obj;             /* ... and a spot's (projection's) unit axis in that frame */
    int stretched;             /* spot, projection: the CTM stretches or shears, so the
                                  cone is not round in the world (the light trees then
                                  bound it by the whole sphere of directions) */
    int img_w, img_h;          /* goniometric, projection: the image's texels */
    float *img;                /* goniometric: one factor a texel (the mean of its R, G,
                                  B); projection: 4 floats a texel, m = 2 max(rgb) and
                                  the sigmoid's coefficients (as InfiniteLight.texel) */
    float sx, sy, tan_half;    /* projection: the screen window [-sx, sx] x [-sy, sy]
                                  and tan(fov / 2) */
    double parea;              /* goniometric, projection: the "power area"
                                  (delta_power_area), from the image */
    const Spectrum *mean;      /* projection: the selection tables' stand-in spectrum,
                                  of the cos^3-weighted mean colour (L holds D65) */
    Vec3 center; double radius;/* distant: the scene's bounding sphere (its power
                                  pi R^2 L, and how far a shadow ray must go) */
    const char *file; int line;/* the LightSource directive, for messages */
} DeltaLight;

typedef struct {
    int shape;                 /* the Shape that emits; -1 for an infinite or delta light */
    InfiniteLight *inf;        /* NULL for an area light */
    DeltaLight delta;          /* delta.type != DELTA_NONE: a point, spot, distant,
                                  goniometric or projection light (shape -1, inf NULL);
                                  L is then its intensity (point, spot, goniometric),
                                  radiance (distant) or D65 (projection) spectrum */
    const Spectrum *L;         /* the spectrum as given in the file (its shape matters),
                                  in Scene.spectra: lights with the same L share it */
    float scale;               /* "float scale" */
    int twosided;
    /* geometry, filled by emitters_prepare at load time (the radiance Le depends on
       the wavelength range a render samples, so it lives with the render: see
       light_sampler_build and light_Le) */
    double area;               /* total area (sampling picks a triangle by area); infinite:
                                  4 pi radius^2, so that its power pi area int Le is
                                  pbrt-v4's Phi = 4 pi^2 R^2 int Le; a delta light: the
                                  same "power area" (delta_power_area), so that
                                  pi area int Le is its power too */
    float *tri_cdf;            /* tri_count + 1 entries for meshes */
    /* which side it lights (emitter_can_reach): a point p can receive light from
       a one-sided triangle only if it lies in front of the triangle's plane (off
       the plane, either side, when two-sided).  Meshes of up to REACH_MAX_TRIS
       triangles keep each triangle's plane; a sphere lights its outside (its
       inside when flipped); bigger meshes are never ruled out. */
    int n_planes;              /* 0: no plane test */
    double *planes;            /* 4 per triangle: oriented unit normal n, offset d = n . v0 */
    double reach_eps;          /* distance below which a point counts as in the plane */
    int absolute;              /* L has no luminance in 400-700 nm (a UV lamp): Le = scale * L,
                                  absolute spectral radiance (docs/conventions.md §4) */
    double y_vis;              /* luminance_sum(L, LAMBDA_LO, LAMBDA_HI), computed once: by
                                  area_light_from_params (AreaLightDesc) or emitters_prepare */
    int image;                 /* AreaLightSource "filename": 1 + the index in Scene.textures
                                  of its emission image (L then holds D65), 0: none */
    const Spectrum *image_mean;/* ... and the RGB illuminant spectrum of the image's mean
                                  colour (selection weights and power only) */
    float power;               /* AreaLightSource "float power" over the image's mean
                                  luminance (1 without one); <= 0: none.  pbrt-v4 gives each
                                  primitive that power: emitters_prepare folds it into
                                  scale and, for a mesh of unequal primitives, ... */
    float *prim_scale;         /* ... a factor per triangle and twisted patch (Abar / A_k),
                                  which light_Le_at applies at a point; else NULL */
} Emitter;

/* A point sampled on an emitter, as seen from a reference point. */
typedef struct {
    Vec3 p, n;                 /* point on the emitter, its (oriented) normal */
    Vec3 wi;                   /* unit direction from the reference point to p */
    float dist;                /* distance to p */
    float pdf_sa;              /* solid-angle pdf (given this emitter); for a delta
                                  light, which has no density, 1 / G with G the factor
                                  its incident radiance gets (falloff / dist^2 for a
                                  point or spot, 1 for a distant light), so that Le /
                                  pdf_sa is the estimate of the incident light for
                                  every kind of emitter */
    int delta;                 /* 1: a delta light's sample (no BSDF direction can
                                  find it: its MIS weight against BSDF sampling is 1) */
    int prim;                  /* a mesh's or bilinear patch's sample: its primitive
                                  (bvh.c's numbering) and parameters there (triangle:
                                  barycentrics b1, b2; patch: u, v), which an alpha
                                  texture reads (emitter_alpha_at) */
    float b1, b2;
} EmitterSample;

typedef enum {
    SEL_UNIFORM, SEL_POWER, SEL_SPATIAL, SEL_SPD, SEL_PRODUCT, SEL_SPECTRAL_SPATIAL,
    SEL_ALL, SEL_TREE, SEL_SPECTRAL_TREE, SEL_COUNT
} SelStrategy;

/* Context of one selection: the same context must be passed to light_select and
   later to light_select_pmf for an emitter found by BSDF sampling (the
   consistency contract, item C1 of THEORY §5).  The thesis'
   spectral strategies (spd, product, spectral-spatial) use their spectral table
   only where hero_only or shifted; the light trees and --all-wavelengths use every
   alive wavelength. */
typedef struct {
    Vec3 p;                    /* shading point (the light tree's distance and angles) */
    Vec3 n;                    /* its shading normal (the tree's receiver-cosine bound);
                                  the zero vector: no bound */
    int voxel;                 /* spatial cell of p, computed once at the vertex */
    float lambda[HERO_N];
    unsigned alive;            /* bit j set: wavelength j still carried */
    int hero_only;             /* 1 when only the hero is alive (alive == 1): after
                                  termination at dispersive glass, or from the start
                                  with --single-wavelength; 0 after rough glass with
                                  --rough-dispersion mis (THEORY §7) */
    int shifted;               /* 1 after a fluorescent shift that kept several
                                  wavelengths (--fluor-lanes keep): they are absorbed
                                  ones now, no longer spread over the film's range, so
                                  the spatial table (weighted by visible light) says
                                  nothing about them; the spectral strategies then sum
                                  their table over the alive wavelengths' bins
                                  (docs/FLUORESCENCE.md §4b) */
    float beta[HERO_N];        /* path throughput per wavelength (optional weighting) */
} LightCtx;

struct LightSampler;           /* opaque: tables built by light_sampler_build */
typedef struct LightSampler LightSampler;

/* ======================================================================
   8. The scene (scene.c builds it from the pbrt-v4 subset that parser.c reads;
      the options block in options.c, --dump-scene in dump.c, the pixel filters
      in filter.c, the film's sensor in sensor.c)
   ====================================================================== */
/* The film's sensor (sensor.c): 0 is pbrt-v4's "cie1931" (the CIE 1931 observer:
   the sensor RGB is XYZ), 1..SENSOR_CAMERAS its measured digital cameras. */
#define SENSOR_CAMERAS 17
int   sensor_index(const char *name);      /* -1: not a pbrt-v4 sensor name */
const char *sensor_name(int sensor);
/* The sensor's r, g, b sensitivities at lambda (xbar, ybar, zbar for cie1931). */
void  sensor_response(int sensor, float lambda_nm, float rgb[3]);
/* The 3x3 map (row-major) from the sensor's RGB to XYZ, white-balanced for
   daylight of `kelvin` (0: none; a camera is fitted for 6500 K then): the
   Bradford map for cie1931, pbrt-v4's least-squares fit over the ColorChecker
   for a camera.  0 if the fit is singular. */
int   sensor_xyz_matrix(int sensor, float kelvin, double m[9]);
/* CIE daylight (CIE 015:2004 eq. 3.3-3.7): the locus chromaticity at a correlated
   colour temperature (4000..25000 K), and S0 + M1 S1 + M2 S2 at SPEC_MIN..SPEC_MAX
   (1 nm) for a locus chromaticity, M1 and M2 rounded to 3 decimals when round3. */
void  cie_daylight_xy(double cct, double *x, double *y);
void  cie_daylight(double x, double y, int round3, double E[SPEC_N]);

/* pbrt-v4's RealisticCamera (lens.c; docs/THEORY.md §17): spherical lens
   interfaces from the front (scene side) to the rear (film side), in metres. */
#define LENS_MAX 64              /* interfaces in a lens file */
#define LENS_PUPIL_RINGS 64      /* exit pupil boxes, per film radius ring */
#define LENS_PUPIL_SAMPLES 65536 /* rays per ring that bound its box (pbrt-v4: 2^20) */
typedef struct {
    double radius;               /* of curvature; > 0: centre towards the film; 0: the stop */
    double thickness;            /* to the next interface along the axis (the last: to the film) */
    double eta;                  /* index of refraction after the interface (0: air) */
    double aperture;             /* radius of the clear aperture */
} LensElement;
/* the stop's shape ("string aperture"): a circle or pbrt-v4's built-in images */
enum { LENS_APERTURE_CIRCLE, LENS_APERTURE_GAUSSIAN, LENS_APERTURE_SQUARE, LENS_APERTURE_PENTAGON,
       LENS_APERTURE_STAR };
typedef struct {
    int n;                       /* interfaces; 0: the camera is the perspective one */
    LensElement e[LENS_MAX];
    int aperture;                /* LENS_APERTURE_* */
    double aperture_scale;       /* a shape's weight: its raster scaled to a mean of pi/4 */
    double diagonal;             /* the film's diagonal (Film "diagonal", m) */
    double pz[2], fz[2];         /* the cardinal points lens_focus found, lens coordinates
                                    (-z of camera space) before the film moved: principal
                                    planes and focal points, [0] of the film's side */
    double pupil[LENS_PUPIL_RINGS][4];  /* per ring: x0 y0 x1 y1 of the exit pupil's box
                                           on the rear interface's plane (x0 > x1: none) */
} Lens;
/* A ray in camera space: the film is z = 0, the lens towards +z. */
typedef struct { double o[3], d[3]; } LensRay;
/* Read a lens file (mm, four numbers per interface) into metres; "path:line:
   problem" in err. */
int    lens_read(Lens *L, const char *path, Error *err);
/* Narrow every stop to `diameter` (m); 0 when a stop is narrower (it is kept). */
int    lens_set_stop(Lens *L, double diameter);
/* The stop's shape: "" (a circle), "gaussian", "square", "pentagon" or "star";
   0 for another name. */
int    lens_set_aperture(Lens *L, const char *name);
/* Move the film so that the plane at `distance` is sharp (thick-lens model), then
   bound the exit pupil with `samples` rays per ring; 0 with a message in err. */
int    lens_focus(Lens *L, double distance, double diagonal, int samples, Error *err);
/* Trace r through the interfaces from the film (from_film 1) or from the scene:
   r becomes the ray that leaves and the weight is returned (1; a shaped stop's
   weight from the film), or 0 when blocked. */
double lens_trace(const Lens *L, LensRay *r, int from_film);
/* The camera ray from film point (fx, fy) through exit pupil sample (u0, u1):
   its weight cos^4 / (pdf t_rear^2), 0 when blocked. */
double lens_ray(const Lens *L, double fx, double fy, float u0, float u1, LensRay *r);

/* pbrt-v4's camera projections (camera.c has their equations): perspective (a
   realistic camera is the perspective one with a Lens of n > 0), orthographic,
   and spherical, whose "string mapping" is "equalarea" or "equirectangular" */
typedef enum { CAMERA_PERSPECTIVE, CAMERA_ORTHOGRAPHIC, CAMERA_EQUAL_AREA, CAMERA_EQUIRECT } CameraType;

/* pbrt-v4's pixel filters (filter.c has their formulas and defaults) */
typedef enum { FILTER_BOX, FILTER_GAUSSIAN, FILTER_TRIANGLE, FILTER_MITCHELL, FILTER_SINC } FilterType;

typedef struct {
    Xform camera_from_world;   /* CTM at the Camera directive */
    Xform camera_from_world_end;   /* its end transform (ActiveTransform EndTime) */
    double camera_t0, camera_t1;   /* TransformTimes at the Camera directive */
    float shutter_open, shutter_close; /* Camera "shutteropen", "shutterclose" */
    CameraType camera_type;    /* Camera "perspective" (and "realistic"), "orthographic", "spherical" */
    float fov_deg;             /* pbrt: field of view of the shorter image axis */
    int xres, yres;
    char filename[256];
    FilterType filter;
    float filter_radius, filter_sigma;   /* gaussian: radius 1.5, sigma 0.5 */
    float filter_b, filter_c;            /* mitchell: B = C = 1/3 */
    float filter_tau;                    /* sinc: tau = 3 */
    int no_pixel_jitter;       /* Option "disablepixeljitter": every camera ray through its
                                  pixel's centre, filter weight 1 (pbrt-v4's GetCameraSample) */
    int no_wavelength_jitter;  /* Option "disablewavelengthjitter": every sample at the four
                                  wavelengths of u = 1/2 (pbrt-v4's lu = 0.5; render.c) */
    int spp, seed, maxdepth;
    int spp_set, seed_set, maxdepth_set; /* given in the file */
    char lightsampler[32];     /* Integrator "string lightsampler", "" if unset */
    /* thin lens (pbrt-v4 PerspectiveCamera, OrthographicCamera): 0 = pinhole */
    float lens_radius, focal_distance;   /* "lensradius" = 0, "focaldistance" = 1e6 */
    /* Camera "realistic" (lens.c): lens.n > 0; focused by scene_load at
       focus_distance for the film's "diagonal" (mm, default 35) */
    Lens lens;
    float focus_distance, film_diagonal;
    /* pbrt-v4 Perspective/OrthographicCamera "screenwindow" x0 x1 y0 y1 (screen_set 0: the
       default, from "frameaspectratio"; frame_aspect 0: the film's xres / yres) */
    int screen_set;
    float screen[4], frame_aspect;
    /* pbrt-v4's sensor: every sample's XYZ is multiplied by the imaging ratio
       (shutterclose - shutteropen) * iso / 100, then scaled down so that its largest
       component is at most max_component (Film "maxcomponentvalue", default inf) */
    float imaging_ratio, max_component;
    /* pbrt-v4 Film "whitebalance" (kelvin, 0 = none): a Bradford adaptation from the
       white of the daylight illuminant of that temperature to sRGB's white, applied
       to the pixel's XYZ (row-major 3x3, xyz' = white_balance_m xyz).  With a
       camera sensor (Film "sensor", sensor.c: 0 = cie1931) the samples hold its
       RGB and white_balance_m is its XYZ-from-RGB matrix, fitted for
       white_balance (6500 K unless given) */
    int sensor;
    float white_balance;
    double white_balance_m[9];
    /* pbrt-v4 Film "cropwindow" (fractions x0 x1 y0 y1 of the film) or "pixelbounds"
       (pixels x0 x1 y0 y1, end exclusive): only that part is rendered and written;
       the camera keeps the whole film's projection.  film_bounds() turns them into
       pixels for the current resolution. */
    int crop_set, pixel_bounds_set;
    float crop[4];
    int pixel_bounds[4];
    /* pbrt-v4 Film "spectral" (spectral 1; else "rgb"): the camera samples its four
       wavelengths uniformly in [lambda_min, lambda_max] (360..830 nm by default),
       emitters keep pbrt-v4's 360..830 nm normalisation, and besides the RGB image
       the film keeps nbuckets channels: per band of equal width, the radiance of
       the samples whose wavelength fell in it times CIE_Y_INTEGRAL, averaged
       (render.c); written as OpenEXR (render.c, exr.c), HALF when savefp16, else FLOAT */
    int spectral, nbuckets, savefp16;
    float lambda_min, lambda_max;
    char sampler[16];          /* Sampler: the specnee sampler it maps to, "" if none */
    int camera_medium;         /* the outside medium at the Camera directive (-1: none) */
    int media_ignored;         /* Integrator "path" (or simplepath, sppm): as in pbrt-v4
                                  the media are not rendered; "volpath" (pbrt-v4's
                                  default), "bdpt" render them (medium.c) */
    int sss_ignored;           /* an Integrator other than "volpath": as in pbrt-v4 a
                                  "subsurface" material is its dielectric boundary alone */
    int xsamples, ysamples, jitter;      /* Sampler "stratified" */
    int regularize;            /* Integrator "bool regularize" (path, volpath): pbrt-v4's
                                  biased roughening of near-specular BSDFs after a
                                  non-specular bounce (path.c, THEORY §14) */
} SceneSettings;

typedef struct Scene {
    SceneSettings settings;
    Vec3 *P; Vec3 *N; int n_verts;       /* N may be NULL; per-vertex normals */
    Triangle *tris; int n_tris;
    Shape *shapes; int n_shapes;
    Material *materials; int n_materials;
    Emitter *emitters; int n_emitters;
    SpectrumStore spectra;               /* the emitters' L, one record per distinct one */
    Texture *textures; int n_textures;   /* texture.c; materials refer to them by index */
    Medium *media; int n_media;          /* medium.c; shapes and the camera refer to them */
    float *UV;                           /* per vertex (u, v), NULL when no mesh has "uv" */
    Vec3 *S;                             /* per vertex tangent ("vector3 S", world space),
                                            NULL when no mesh has one; valid for the
                                            vertices of the shapes with has_tangents */
    int n_spheres; int *sphere_shape;    /* sphere j is shapes[sphere_shape[j]] */
    int n_quadrics; int *quadric_shape;  /* quadric k (disk, cylinder, partial sphere)
                                            is shapes[quadric_shape[k]] */
    Patch *patches; int n_patches;       /* bilinear patches that are not flat (patch.c) */
    Curve *curves; int n_curves;         /* curve segments (curve.c) ... */
    CurvePiece *curve_pieces; int n_curve_pieces;   /* ... and their pieces, the BVH's */
    Object *objects; int n_objects;      /* ObjectBegin definitions (instance.c) */
    Instance *instances; int n_instances;/* ObjectInstance placements */
    Motion *motions; int n_motions;      /* the moving instances' transforms (motion.c) */
    int n_alpha;                         /* shapes with alpha_on (0: no alpha test at all) */
    int n_interface;                     /* shapes of Material "interface" (0: a shadow ray
                                            crosses no medium boundary, path.c) */
    Vec3 bmin, bmax;                     /* world bounds of all geometry */
    Bvh bvh;
    char **strings; int n_strings;       /* owned file names referenced by shapes */
    /* insets from structured comments "# inset A x0 y0 x1 y1" */
    int n_insets; char inset_name[8][16]; int inset[8][4];
} Scene;

/* Parse a pbrt-v4 subset file (with Include/Import) and build the BVH.
   Returns 0 and a "file:line: problem" message on any error. */
int  scene_load(Scene *s, const char *path, Error *err);
/* The same for a render whose output file the command line names (-o; NULL: none):
   it overrides Film's "string filename", as pbrt-v4's --outfile does, and the
   file's name is then not checked (a note on stderr when that name is not a
   .pfm/.ppm/.png: a placeholder, .exr). */
int  scene_load_as(Scene *s, const char *path, const char *output, Error *err);
/* Same from a string in memory (tests); name is used in messages. */
int  scene_load_string(Scene *s, const char *text, const char *name, Error *err);
void scene_free(Scene *s);
void scene_dump(const Scene *s, FILE *f);      /* --dump-scene (dump.c) */
/* The film's part to render, in pixels [b[0], b[1]) x [b[2], b[3]) of the
   xres x yres film (pbrt-v4 FilmBaseParameters: cropwindow scaled with ceil,
   pixelbounds clipped to the film); the whole film when neither is given.
   Returns 0 when the part is empty.  (options.c, with scene_insets_rendered) */
int  film_bounds(const SceneSettings *st, int b[4]);
/* The camera's screen window x0 x1 y0 y1 for the xres x yres film (pbrt-v4
   PerspectiveCamera): "screenwindow" when given, else the shorter axis of the
   frame spans [-1, 1].  (options.c; camera.c maps the raster onto it) */
void camera_screen_window(const SceneSettings *st, float sw[4]);
/* The scene's insets in the pixels of the image render() makes: each clipped to
   film_bounds() and moved to its origin (x0 y0 x1 y1, end exclusive), with its
   name; an inset outside a crop is left out.  Returns how many. */
int  scene_insets_rendered(const Scene *s, int rect[8][4], const char *names[8]);

/* Pixel filters (filter.c): pbrt-v4's filter importance sampling.  A camera
   sample's position in its pixel is drawn from the filter f (mitchell, sinc: from
   a table of |f|) with the density p_f and the weight fw = f/p_f, and the pixel is
   sum fw L / sum fw. */
typedef struct {
    FilterType type;
    float radius, sigma, b, c, tau;      /* as in SceneSettings (one radius: x = y) */
    int n;                               /* cells of the table over [-radius, radius]
                                            (gaussian, mitchell, sinc; else 0) */
    float f[FILTER_TABLE_MAX];           /* f1 at the cells' centres */
    float cdf[FILTER_TABLE_MAX + 1];     /* CDF of |f1| over the cells */
    int guide[FILTER_GUIDE_MAX + 1];     /* cdf's guide table (cdf_guide), m + 1 entries */
    int m;                               /* its steps, cdf_guide_size(n) (0: no guide) */
    double abs_integral;                 /* integral of |f1_tab| over [-radius, radius] */
    /* gaussian: the exact sampler of filter_gaussian_reject (filter.c): a cell of
       [0, radius] by Walker's alias method, then rejection against the cell's
       bound.  f1 here is g(x) - g(r) in float, expf(-x^2 k) - g_r */
    int gauss_ok;                        /* 0: no Gaussian table (the offset is 0) */
    float gauss_k, gauss_gr, gauss_w;    /* 1 / (2 sigma^2), g(radius), the cells' width */
    float gauss_hi[FILTER_GAUSS_CELLS];  /* above f1 on the cell (its inner edge's value, raised) */
    float gauss_lo[FILTER_GAUSS_CELLS];  /* below f1 on the cell (its outer edge's, lowered) */
    uint32_t gauss_keep[FILTER_GAUSS_CELLS];   /* alias: keep the cell if 25 bits < this */
    unsigned char gauss_alias[FILTER_GAUSS_CELLS];   /* else take this one */
} PixelFilter;
void  filter_init(PixelFilter *pf, const SceneSettings *st);
/* f1(x), and f(x, y) = f1(x) f1(y); x, y in pixels from the pixel's centre. */
double filter_eval_1d(const PixelFilter *pf, double x);
double filter_eval(const PixelFilter *pf, double x, double y);
/* The sample's position in its pixel (0.5, 0.5 is the centre) from two uniform
   numbers, and its weight fw = f/p_f (1 for box, gaussian, triangle). */
float filter_sample(const PixelFilter *pf, float u0, float u1, float *px, float *py);
/* 1 if the weights are not constant (mitchell, sinc): the film must keep sum fw. */
int   filter_weighted(const PixelFilter *pf);
/* One offset of the Gaussian (gaussian filters) from the independent sampler's
   stream, exactly (a variable count of numbers): a cell, then rejection. */
float filter_gaussian_reject(const PixelFilter *pf, Rng *rng);
const char *filter_name(FilterType t);

/* ======================================================================
   9. PLY meshes (ply.c)
   ====================================================================== */
typedef struct {
    float *P; float *N; int n_verts;     /* xyz per vertex, optional normals */
    float *UV;                           /* optional (u, v) per vertex (u v, s t,
                                            texture_u texture_v, texture_s texture_t) */
    int32_t *idx; int n_tris;            /* the triangles: 3 indices each */
    int32_t *quads; int n_quads;         /* the quads: 4 indices each, a bilinear patch's
                                            p00 p10 p01 p11 = the face's 0 1 3 2 (pbrt-v4) */
} PlyMesh;
int  ply_read(const char *path, PlyMesh *m, Error *err);
void ply_free(PlyMesh *m);
int  ply_write_binary(const char *path, const float *P, int n_verts, const int32_t *idx, int n_tris);
/* pbrt-v4's displaced plymesh (displace.c): quads split into triangles, every
   triangle split at its longest edge until each world-space edge (world_from_obj
   applied) is shorter than edgelength, each vertex moved along its normal by
   float texture tex at its uv, then smooth normals recomputed; the mesh replaced
   in place (0 and a message in err when too large or out of memory). */
int  ply_displace(PlyMesh *mesh, const Xform *world_from_obj, float edgelength,
                  const Texture *textures, int tex, Error *err);

/* ======================================================================
   9b. Loop subdivision surfaces (subdiv.c)
   ====================================================================== */
/* Shape "loopsubdiv": `levels` steps of Loop's scheme on the control mesh (P: 3
   doubles a vertex, idx: 3 indices a triangle), every vertex then moved to the
   limit surface, with pbrt-v4's limit normal (unnormalised).  The control mesh must
   be a manifold with consistently oriented triangles (subdiv.c says what is
   refused); 0 and a message in err (no file:line) otherwise. */
typedef struct {
    float *P; float *N; int n_verts;     /* limit positions and normals, 3 floats each */
    int32_t *idx; int n_tris;
} SubdivMesh;
int  loop_subdivide(const double *P, int nv, const int32_t *idx, int nt, int levels,
                    SubdivMesh *out, Error *err);
#define SUBDIV_BYTES_PER_TRI 128.0   /* loop_subdivide's peak memory per triangle it makes
                                        (about 117 bytes), checked against MEM_BUDGET_MIB */
void subdiv_free(SubdivMesh *m);

/* ======================================================================
   10. Images (image.c; the readers png.c and exr.c; merge and diff in cmd_image.c)
   ====================================================================== */
typedef struct { int w, h; float *rgb; } Image;   /* top row first, 3 floats a pixel */
/* An image texture's texels from an RGB image (rows top to bottom), after pbrt-v4's
   scale and invert (texture.c): 0 and a message when out of memory. */
int   tex_set_image(Texture *t, const Image *im, float scale, int invert, RgbTable *rgb,
                    Error *err);
#define IMG_MAX_PIXELS (1L << 28)  /* @@ largest w*h accepted (guards against absurd headers) */
#define IMG_RELMSE_EPS 1e-2        /* relMSE = mean (a-b)^2/(b^2 + eps) (Rousselle et al. 2011) */
int  img_alloc(Image *im, int w, int h);  /* zero-filled; 0 on bad size or no memory */
void img_free(Image *im);
int  img_write(const Image *im, const char *path, float exposure, Error *err); /* by extension */
int  img_format_check(const char *path, Error *err);  /* .pfm .ppm .png, else 0 and a message */
int  pfm_write(const Image *im, const char *path);
int  pfm_read(Image *im, const char *path, Error *err);
int  ppm_write(const Image *im, const char *path, float exposure);
int  png_write(const Image *im, const char *path, float exposure);
int  png_write_rgb8(const char *path, int w, int h, const unsigned char *rgb);
/* PNG reader (png.c, its own inflate): colour types 0 2 3 4 6, bit depths 1 2 4 8 16,
   no interlace; alpha and tRNS are dropped.  Samples / (2^depth - 1), then decoded
   from the sRGB curve unless linear (data textures).  0 and "name: PNG: problem"
   on any malformed input; the image must fit IMG_MAX_PIXELS and MEM_BUDGET_MIB. */
int  png_read_memory(const unsigned char *data, size_t n, const char *name, int linear, Image *im,
                Error *err);
int  png_read(Image *im, const char *path, int linear, Error *err);
/* The zlib stream (RFC 1950, 1951) in[0 .. n_in) inflated into out[0 .. n_out), which
   it must fill exactly (png.c): NULL, or what is wrong. */
const char *zlib_inflate(const unsigned char *in, size_t n_in, unsigned char *out, size_t n_out);
/* OpenEXR reader (exr.c): single-part scanline images, compression NONE, RLE, ZIPS,
   ZIP; channels HALF, FLOAT or UINT; R, G, B (or Y: grey) of the data window, rows
   top to bottom, linear values as stored.  0 and "name: EXR: problem" on malformed
   input, and on what it does not read (tiled, multi-part, deep, PIZ, PXR24, B44,
   DWA...), with the command that converts the file to a PFM. */
int  exr_read_memory(const unsigned char *data, size_t n, const char *name, Image *im, Error *err);
int  exr_read(Image *im, const char *path, Error *err);
/* exr_read, and the colour space the file's "chromaticities" name (pbrt-v4's
   RGBColorSpace::Lookup: COLORSPACE_*; sRGB when the file has none; -1 when they
   match none of the four, which pbrt-v4 reads as sRGB with a warning). */
int  exr_read_space(Image *im, const char *path, int *space, Error *err);
/* The same with the three channels named in want read into a pixel's three floats
   (a name may repeat; a missing one is an error): the spectral film's buckets. */
int  exr_read_named(Image *im, const char *path, const char *const want[3], Error *err);
int  exr_read_memory_named(const unsigned char *data, size_t n, const char *name,
                           const char *const want[3], Image *im, Error *err);
/* OpenEXR writer (exr.c): a single-part scan-line image, compression NONE, the
   channels sorted by name (as OpenEXR requires), HALF or FLOAT, the attributes
   OpenEXR requires plus n_str string attributes. */
typedef struct {
    int w, h;                  /* the data window's size */
    int x0, y0;                /* its first pixel in the display window */
    int full_w, full_h;        /* the display window: (0, 0) .. (full_w - 1, full_h - 1) */
    int n_ch;                  /* channels, 1..64 */
    const char *const *names;  /* their names, in the order of the values */
    const float *v;            /* n_ch values a pixel, rows top to bottom */
    int half;                  /* 1: HALF (exr_float_to_half), 0: FLOAT */
    int n_str;                 /* string attributes str_key[i] = str_val[i] */
    const char *const *str_key, *const *str_val;
} ExrWrite;
int  exr_write(const char *path, const ExrWrite *im, Error *err);  /* 0: "path: problem" */
unsigned char *exr_write_memory(const ExrWrite *im, size_t *n);    /* malloc'd; NULL: bad size or no memory */
unsigned exr_float_to_half(float f);     /* nearest binary16 (ties to even), its bits */
float exr_half_to_float(unsigned h);     /* exact */
/* png_write with the outlines of n pixel rectangles, rect[4i..4i+3] = x0, y0, x1,
   y1 (x1, y1 exclusive), drawn in, rectangle i in colour i mod 8 of: yellow, cyan, magenta,
   orange, white, green, blue, red (the insets of docs/RESULTS.md). */
int  png_write_marked(const Image *im, const char *path, float exposure, const int *rect, int n);
float srgb_oetf(float linear);           /* IEC 61966-2-1 transfer curve */
/* Sidecar "<path>.txt": lines "spp <n>" (left out when spp < 0: unknown) and
   "settings <text>", for merge. */
int  img_write_sidecar(const char *path, long spp, const char *settings);
long img_read_sidecar_spp(const char *path);   /* -1 if missing or no valid spp line */
/* Error of a against ref over the pixels [x0, x1) x [y0, y1) (top-left origin), means
   over pixels and the 3 channels; 0 on a size mismatch or an empty/out-of-range rect. */
typedef struct {
    double mse, relmse, mae; long n;   /* n: pixels */
    double y_test, y_ref;              /* luminance means (sRGB's Y row) of a and ref */
} ImgErr;
int  img_error(const Image *a, const Image *ref, int x0, int y0, int x1, int y1, ImgErr *out);
/* out = sum_i w_i in_i / sum_i w_i (weights NULL: equal); allocates out; 0 on a size
   mismatch, a negative/NaN weight, a zero weight sum or no memory. */
int  img_merge(const Image *in, const double *weights, int n, Image *out);
/* False-colour PNG of the per-pixel relative squared error (log scale, viridis). */
int  img_write_error_png(const Image *a, const Image *ref, const char *path);
/* cmd_merge/cmd_diff writing to the given streams (cmd_image.c; for tests). */
int  img_cmd_merge(int argc, char **argv, FILE *out, FILE *err);
int  img_cmd_diff(int argc, char **argv, FILE *out, FILE *err);

/* ======================================================================
   11. Emitters and their selection: the API (lights.c, lighttree.c, infinite.c,
       delta.c)
   ====================================================================== */
/* Check each emitter (its spectrum emits in 400-700 nm, its area is positive) and
   fill its area and triangle CDF.  scene_load calls it; nothing here depends on
   the wavelength range a render samples. */
int   emitters_prepare(Scene *s, Error *err);
/* arealight.c: fold emitter em's "float power" (em->power, Phi / k_e) into em->scale
   and, for a mesh whose primitives differ in area, em->prim_scale (pbrt-v4: one
   light per primitive, each emitting Phi).  emitters_prepare calls it; 0: out of
   memory. */
int   emitter_apply_power(const Scene *s, Emitter *em, const Shape *sh);
/* Emitter e's radiance for a film that integrates [lo, hi] nm (pbrt-v4: Le = scale
   * L / sum_{1 nm} ybar L over the range); 0 and a message if it emits nothing there.
   For an image map (L holds D65) Le is the spectrum of the map's mean colour, a
   stand-in used only by the selection tables. */
int   emitter_radiance(const Scene *s, int e, float lo_nm, float hi_nm, Spectrum *Le, Error *err);
/* Spherical triangles (sphtri.c, THEORY §5.6): a triangle seen from a point as the
   unit directions a, b, c towards its vertices, e the unit tangent at a of the arc
   from a to c, the cosine and sine of its angle alpha at a, and its solid angle
   (area, sr).  sph_tri_setup: 0 when degenerate (area <= 0).  sph_tri_sample:
   Arvo's map of [0, 1]^2 onto it (density 1 / area); sph_tri_invert: its inverse
   for a direction inside (0 when w lies along b). */
typedef struct { double a[3], b[3], c[3], e[3], cos_alpha, sin_alpha, area; } SphTri;
int   sph_tri_setup(Vec3 ref, Vec3 v0, Vec3 v1, Vec3 v2, SphTri *t);
Vec3  sph_tri_sample(const SphTri *t, double u0, double u1);
int   sph_tri_invert(const SphTri *t, Vec3 w, double *u0, double *u1);
/* The bilinear density on [0, 1]^2 with corner weights w (at (0,0), (1,0), (0,1),
   (1,1)), and its sampling (y by its marginal, then x given y). */
double bilinear_pdf(const double w[4], double x, double y);
void  bilinear_sample(const double w[4], double u0, double u1, double *x, double *y);
/* A triangle lamp v[0..2] sampled by solid angle from ref (pbrt-v4's rule: where
   SPH_TRI_MIN <= its solid angle <= SPH_TRI_MAX), the cosine at the shading
   normal n warped in (n the zero vector, in a medium: uniform).  tri_sample_sa: a
   direction, its density and the barycentrics (of v[1], v[2]) where it meets the
   triangle; tri_pdf_sa: the density of dir (a direction that meets the triangle).
   Both 0 when the solid angle is out of range: the caller samples by area. */
#define SPH_TRI_MIN 3e-4       /* sr */
#define SPH_TRI_MAX 6.22       /* sr */
typedef struct { Vec3 dir; float b1, b2; double pdf; } SphTriSample;
int   tri_sample_sa(Vec3 ref, Vec3 n, const Vec3 v[3], float u1, float u2, SphTriSample *out);
int   tri_pdf_sa(Vec3 ref, Vec3 n, const Vec3 v[3], Vec3 dir, double *pdf);
/* --light-shape-sampling auto: 1 where the solid-angle map pays for triangle v
   seen from ref (normal n, zero in a medium): where the area estimate's factor
   |n . D| / |D|^4 (D = p - ref) spreads over the triangle's vertices and centroid
   by more than SPH_TRI_SPREAD (sphtri.c).  The same answer at the sample and at
   the pdf of a BSDF hit keeps the estimator unbiased. */
#define SPH_TRI_SPREAD 3.0
int   tri_sa_pays(Vec3 ref, Vec3 n, const Vec3 v[3]);

/* Sample a point on the whole of emitter e, seen from ref (shading normal ns; the
   zero vector in a medium), with the numbers u[0..2]: a mesh's triangle by area,
   then on it by solid angle (tri_sample_sa) or, out of its range, uniform by area;
   a sphere in its cone; other shapes by area.  Geometry only: the radiance comes
   from light_Le. */
int   emitter_sample(const Scene *s, int e, Vec3 ref, Vec3 ns, const float u[3], EmitterSample *out);
/* Solid-angle pdf of emitter_sample producing point p (normal n, on primitive prim
   in bvh.c's numbering, -1: not known) from ref.  For an infinite light the
   direction p - ref counts. */
float emitter_pdf_sa(const Scene *s, int e, Vec3 ref, Vec3 ns, Vec3 p, Vec3 n, int prim);
/* The factor NEE gives emitter e's radiance at its sampled points: its shape's
   "float alpha" clamped to [0, 1] (a hit found by a ray counts with that
   probability, bvh.c ALPHA), 1 for every other emitter. */
float emitter_alpha(const Scene *s, int e);
/* The same at the point es that emitter e's sampler drew from ref (light_sample,
   emitter_sample): a "texture alpha" evaluated there, clamped to [0, 1], so that NEE
   weighs the radiance by the probability alpha(x) with which a ray finds x (bvh.c
   ALPHA); emitter_alpha without a texture. */
float emitter_alpha_at(const Scene *s, int e, Vec3 ref, const EmitterSample *es);
/* The surface point of es on emitter e (hitpoint.c's scene_surface_point, as a ray
   from ref would find it), for what depends on its (u, v): an alpha texture, an
   emission image.  Returns sp, or NULL for an infinite or delta light or a
   sample without its primitive. */
const SurfacePoint *emitter_point_at(const Scene *s, int e, Vec3 ref, const EmitterSample *es,
                                     SurfacePoint *sp);
/* pbrt-v4's invisible area light (constant alpha 0): no ray hits it, it emits in
   full, and NEE alone finds it (1), else 0 */
int   emitter_invisible(const Scene *s, int e);

/* Infinite lights (infinite.c).  dir: unit world direction towards the light (the
   direction of a ray that escapes).  Radiance and solid-angle pdf of inf_sample.
   Le and k come from the render (light_sampler_build): Le = the emitter's
   normalised radiance (constant light), k = scale / sum_{lo..hi} ybar L, the
   factor that turns an image map's texel spectrum into radiance. */
float inf_Le(const Emitter *em, const Spectrum *Le, double k, Vec3 dir, float lambda_nm);
/* ref: the point that looks (a portal light's pdf depends on where the portal is seen
   from; other infinite lights ignore it). */
float inf_pdf(const Emitter *em, Vec3 ref, Vec3 dir);
/* A direction with density inf_pdf (piecewise constant over texels; uniform for a
   constant light; a portal light's inside the portal as seen from ref); 0 if none. */
int   inf_sample(const Emitter *em, Vec3 ref, float u1, float u2, Vec3 *dir, float *pdf);
/* 1 if a ray from o along dir can receive the light: always, except for a portal
   light, whose radiance arrives only through its portal (inf_Le does not check). */
int   inf_sees(const Emitter *em, Vec3 o, Vec3 dir);
/* pbrt-v4's equal-area octahedral map (Clarberg 2008): the unit square <-> the
   unit sphere, +z at the centre, -z at the corners. */
Vec3  equal_area_square_to_sphere(float u, float v);
void  equal_area_sphere_to_square(Vec3 d, float *u, float *v);
/* Build an image map's texels and distribution from an RGB image (rows top to
   bottom); 0 and a message on a non-square or non-finite image. */
int   inf_set_image(InfiniteLight *inf, const Image *im, RgbTable *rgb, const char *file,
                    int line, Error *err);
void  inf_free(InfiniteLight *inf);
/* 0 when emitter e certainly sends no light to the point p (p behind every
   triangle of a one-sided emitter, or in their planes - e.g. on the emitter
   itself -, or on the dark side of a sphere); 1 when it may.  Conservative: never
   0 where light could arrive from farther than reach_eps off a triangle's plane. */
int   emitter_can_reach(const Scene *s, int e, Vec3 p);

/* Delta lights (delta.c).  delta_falloff: a spot light's smoothstep falloff for
   the unit direction w leaving it, a goniometric light's image factor, a
   projection light's 1 inside its frustum (0 outside, or on a black texel), 1
   for point and distant lights.
   delta_sample: the one point (or direction) that lights ref, with pdf_sa = 1/G
   (EmitterSample); 0 when it sends nothing to ref (outside a spot's cone, or ref
   at the light).  delta_power_area: the "area" A with pi A int Le = the light's
   power (pbrt-v4's Phi): 4 for a point light, 2 ((1 - cos_start) + (cos_start -
   cos_end) / 2) for a spot, R^2 for a distant light, 4 x the image's mean for a
   goniometric light, a projection's from its image (delta.c section 4).
   delta_can_reach: 0 only where the light sends nothing (outside a spot's or a
   projection's cone). */
float  delta_falloff(const DeltaLight *d, Vec3 w);
int    delta_sample(const DeltaLight *d, Vec3 ref, EmitterSample *out);
double delta_power_area(const DeltaLight *d);
int    delta_can_reach(const DeltaLight *d, Vec3 p);
/* A projection light's radiance factor towards w (world, leaving the light):
   k m sigmoid(lambda) D65(lambda) of the texel w projects to, 0 outside its
   frustum (k = scale / sum ybar D65, lights.c).  delta_free: its image. */
float  delta_projection_Le(const Emitter *em, double k, Vec3 w, float lambda_nm);
void   delta_free(DeltaLight *d);

/* How a triangle lamp's point is drawn (SelOptions.area_sampling). */
enum { SHAPE_SA = 0, SHAPE_AREA = 1, SHAPE_AUTO = 2 };

typedef struct {
    SelStrategy strategy;
    int power_metric;          /* spd tables: 1 = radiance x area, 0 = unit radiance */
    int all_wavelengths;       /* beyond the thesis: select by all alive wavelengths */
    int throughput_weighted;   /* ... weighted by the path throughput per wavelength */
    int eager;                 /* build every spatial voxel up front (else lazily) */
    int grid_res;              /* voxels on the longest axis; 0 = SPATIAL_RES (tests use
                                  small grids: a tiny render touches few points per voxel) */
    float lo_nm, hi_nm;        /* the range the film integrates, for the emitters'
                                  normalisation and the tree's bins (0, 0: 400-700) */
    int no_split;              /* light tree: keep every emissive mesh one leaf */
    int area_sampling;         /* a triangle lamp's point: SHAPE_SA (0, by solid
                                  angle where its range allows, sphtri.c),
                                  SHAPE_AREA (1, uniform by area) or SHAPE_AUTO
                                  (by solid angle where tri_sa_pays says so);
                                  --light-shape-sampling solidangle|area|auto */
} SelOptions;

/* The per-render state of the emitters: their radiance normalised for the range
   o->lo_nm..hi_nm and the selection tables of o->strategy (for the light trees:
   the tree, built here in O(N log N)).  The Scene is only read. */
LightSampler *light_sampler_build(const Scene *s, const SelOptions *o, Error *err);
void  light_sampler_free(LightSampler *ls);
/* The lamps equiangular sampling aims at (equiangular.c; n = 0: none). */
const EquiLamps *light_equi(const LightSampler *ls);
/* Radiance leaving emitter e at a point with oriented normal n towards w (unit):
   zero from the back of a one-sided emitter.  An area light with an emission
   image ("filename") depends on the point's (u, v): light_Le_at reads it from at
   (the hit's SurfacePoint, or emitter_point_at's for an NEE sample); light_Le,
   and at NULL, give the image's mean colour instead. */
float light_Le(const LightSampler *ls, int e, Vec3 n, Vec3 w, float lambda_nm);
float light_Le_at(const LightSampler *ls, int e, Vec3 n, Vec3 w, const SurfacePoint *at,
                  float lambda_nm);
/* arealight.c: sum over 1 nm steps in [lo, hi] of ybar L: the luminance that normalises an
   emitter's spectrum L (and an emissive medium's Le, render.c). */
double luminance_sum(const Spectrum *L, float lo_nm, float hi_nm);
/* the same sum with ybar from a load's RgbTable (spec_ybar_knots; T NULL: luminance_sum) */
double luminance_sum_t(RgbTable *T, const Spectrum *L, float lo_nm, float hi_nm);
void  light_spectrum(const LightSampler *ls, int e, Spectrum *Le);   /* e's Le, tabulated */
/* the sum of every emitter's Le at the 360-830 nm knots (UV 0), the emitters added in
   order (the wavelength pdf's importance); a zero spectrum without emitters */
const Spectrum *light_spectrum_sum(const LightSampler *ls);
/* What NEE chooses is a PIECE: a whole emitter, or (light trees only) a cluster of
   at most LIGHT_CLUSTER_TRIS triangles of a large emissive mesh.  Without
   splitting, piece i is emitter i. */
int   light_n_pieces(const LightSampler *ls);
int   light_piece_emitter(const LightSampler *ls, int piece);
/* The piece holding primitive prim (SurfacePoint.prim) of emitter e. */
int   light_piece_of(const LightSampler *ls, int e, int prim);
/* Sample a point on the piece as emitter_sample does (by area only with
   SelOptions.area_sampling); its pdf in solid angle at ref (shading normal ns), and
   light_pdf_sa, the same pdf for the point p (normal n) on primitive prim. */
int   light_sample(const LightSampler *ls, int piece, Vec3 ref, Vec3 ns, const float u[3],
                   EmitterSample *out);
float light_pdf_sa(const LightSampler *ls, int piece, Vec3 ref, Vec3 ns, Vec3 p, Vec3 n, int prim);
int   light_voxel(const LightSampler *ls, Vec3 p);       /* -1 when not spatial */
/* Choose one piece for NEE with the uniform number u; returns -1 for "none" and
   sets *pmf.  *fell_back (may be NULL) is set to 1 when a spectral table had no
   emitter for the bin and the spatial distribution was used instead. */
int   light_select(LightSampler *ls, const LightCtx *c, float u, float *pmf, int *fell_back);
/* The probability light_select gives piece i in context c (for MIS weights). */
float light_select_pmf(LightSampler *ls, const LightCtx *c, int piece);
/* What next event estimation asks (path.c), so that no strategy is special-cased
   there.  One NEE estimate at a vertex takes light_nee_count pieces: one, chosen
   with one uniform number (*needs_u = 1), or for the strategy "all" every piece
   with probability 1 and no number (a sum, not a choice).  light_nee_piece: the
   k-th of them and its *P (-1: none can be chosen), u read only when needed;
   light_nee_pmf: the P it gives piece in context c (for the MIS weight of an
   emitter that BSDF sampling finds); light_nee_source: where P came from, in
   words (--debug-pixel). */
int   light_nee_count(const LightSampler *ls, int *needs_u);
int   light_nee_piece(LightSampler *ls, const LightCtx *c, int k, float u, float *P, int *fell_back);
float light_nee_pmf(LightSampler *ls, const LightCtx *c, int piece);
const char *light_nee_source(const LightSampler *ls, const LightCtx *c, int fell_back);
/* The light tree computes the importances of a node's four children side by
   side (SSE2, where the compiler has it) and keeps the scalar code that this
   mirrors (lighttree.c).  At context c: how many children, over the
   whole tree, get a power or an importance that differs in any bit between
   the two (0 without SSE2 or without a tree); *lanes: how many were compared.
   For tests. */
int   light_tree_simd_mismatches(const LightSampler *ls, const LightCtx *c, int *lanes);
/* (test lighttree_bins_sum) the tree's lanes whose power per bin, or the root's,
   is not the sum of the leaves' below it (relative 1e-5); *lanes: lanes checked */
int   light_tree_bins_mismatches(const LightSampler *ls, int *lanes);
/* (test lighttree_root_bins_are_band_means) the tree's root power per 5 nm bin
   from 300 nm up into bins[0..max); returns how many bins it has (0: no tree) */
int   light_tree_root_bins(const LightSampler *ls, float *bins, int max);
size_t light_sampler_bytes(const LightSampler *ls);      /* memory held by its tables */
/* Seconds spent so far building voxel tables on first use (eager builds excluded). */
double light_sampler_lazy_seconds(const LightSampler *ls);
SelStrategy sel_from_name(const char *name);             /* SEL_COUNT if unknown */
const char *sel_name(SelStrategy s);

/* The light tree (lighttree.c): what lights.c asks of it for the strategies tree
   and spectral-tree.  Not for callers of the API above: light_sampler_build
   builds the tree over its pieces (a LightSampler owns its LightTree), and
   light_select / light_select_pmf hand the tree strategies' contexts to it.
   A piece as lights.c makes it and the tree reads it: */
typedef struct {
    int emitter;
    int first, count;          /* a cluster: triangles piece_tri[first .. first + count)
                                  (LightTreeInput.piece_tri); 0: a whole emitter */
    double area;               /* m^2 (a delta light's: 0) */
    /* a whole mesh emitter (count == 0): what light_sample reads, copied here so
       that NEE does not read the scene's Emitter (2 KB, mostly its spectrum) and
       Shape for every sample (a cache miss each with many emitters); NULL:
       spheres, quadrics, infinite and delta lights, sampled by emitter_sample */
    const float *tri_cdf;
    int tri_begin, tri_count;
} LightPiece;
/* What the tree is built from; read during light_tree_build only. */
typedef struct {
    const Scene *scene;
    const SelOptions *opt;     /* strategy (spectral-tree: bin powers), throughput
                                  weighting, lo_nm..hi_nm (resolved: hi > lo) */
    const LightPiece *pieces;  /* every piece, those beside the tree included */
    int n_pieces;
    const int *piece_tri;      /* the clusters' scene triangles */
    /* the distinct radiances for the sampled range (lights.c keeps them untabulated):
       le_knots(le_ctx, i, nm0, n, out) gives out[k] = radiance i's table at nm0 + k nm
       (SPEC_UV_MIN <= nm0 <= nm0 + n - 1 <= SPEC_MAX), the values emitter_radiance
       tabulates */
    void (*le_knots)(const void *le_ctx, int i, int nm0, int n, float *out);
    const void *le_ctx;
    int n_le;
    const int *le_of;          /* per emitter: its radiance, an index into Le */
    const double *piece_power; /* per piece: pi A (2 if two-sided) times the sum of its
                                  emitter's SPD_BINS bin averages of Le, 400-700 nm */
} LightTreeInput;
typedef struct LightTree LightTree;
LightTree *light_tree_build(const LightTreeInput *in);   /* NULL: out of memory */
void   light_tree_free(LightTree *t);
/* Choose a piece (-1: none) and its probability in context c; the probability of
   a given piece.  Select and pmf walk the same nodes with the same importance. */
int    light_tree_select(const LightTree *t, const LightCtx *c, float u, float *pmf);
float  light_tree_pmf(const LightTree *t, const LightCtx *c, int piece);
int    light_tree_simd_check(const LightTree *t, const LightCtx *c, int *lanes);  /* as above */
int    light_tree_bins_check(const LightTree *t, int *lanes);   /* as light_tree_bins_mismatches */
int    light_tree_root_bins_copy(const LightTree *t, float *bins, int max);   /* as light_tree_root_bins */
size_t light_tree_bytes(const LightTree *t);
/* Shared by lights.c (its mesh clusters) and the tree's build (lighttree.c): the
   area of scene triangle t; items[0..n) sorted by coordinate `axis` of their
   points pts[item] (ties by item, so the order is deterministic; tmp holds n);
   the axis (0, 1, 2) along which the extent d is longest. */
typedef struct { float key; int idx; } KeyIdx;
double tri_area(const Scene *s, int t);
void   sort_by_axis(int *items, int n, const Vec3 *pts, int axis, KeyIdx *tmp);
int    longest_axis(Vec3 d);

/* ======================================================================
   12. The integrator (render.c; its camera in camera.c, its path estimator in
       path.c) and its options
   ====================================================================== */
typedef struct {
    int spp, seed, threads, maxdepth;
    SelOptions sel;
    WlMode wl_mode;            /* --wavelengths: uniform importance visible mixture */
    float wl_mix;              /* --mix-weight: mu of WL_MIXTURE (0: WL_MIX_DEFAULT) */
    int wl_wide;               /* sample 360-830 nm instead of 400-700 */
    int single_wavelength;     /* 1 wavelength per path instead of HWSS */
    int rough_mis;             /* --rough-dispersion mis: secondaries survive rough glass */
    int nee;                   /* 1: NEE + BSDF sampling by MIS; 0: BSDF sampling only */
    FluorLi fluor_li;          /* --fluor-li: how a fluorescent vertex samples lambda_i
                                  (docs/FLUORESCENCE.md §3): from A, A x emitter power mixed
                                  with A (default), or uniformly on [300, lambda_o] */
    int fluor_keep;            /* --fluor-lanes keep (default): all four wavelengths go
                                  through a shift, each with its own lambda_i
                                  (docs/FLUORESCENCE.md §4b); 0: the secondaries are terminated
                                  (the thesis' way with wavelength-dependent events) */
    float band_lo, band_hi;    /* band_hi > band_lo: the camera samples its wavelengths
                                  uniformly in [band_lo, band_hi] only, the emitters keep
                                  the film range's normalisation, so the image is the
                                  integral of cbar L over the band: a spectral film one
                                  band at a time, for the tests (no command-line flag) */
    SamplerType sampler;       /* --sampler (file: Sampler); sobol by default */
    int xsamples, ysamples;    /* stratified strata (0: from spp) */
    int jitter;                /* stratified: jitter in the strata (default 1) */
    int media_terminate;       /* --chromatic-media terminate: the secondaries end at the
                                  first event in a medium whose sigma_t depends on the
                                  wavelength; 0 (default): spectral MIS carries all four
                                  through it (docs/media.md) */
    int equiangular;           /* --equiangular on|N: equiangular sampling towards the
                                  lamps in homogeneous media (THEORY §12.1); 0 (default): off */
    int equi_depth;            /* --equiangular N: only on the segments of the first N
                                  bounces (0: every bounce) */
    int progress;              /* progress bar on stderr */
    int debug_x, debug_y;      /* --debug-pixel: print that pixel's paths (-1: off) */
} RenderOptions;

typedef struct {
    double wall_s, cpu_s, build_s;   /* render time, CPU time, table build time before
                                        the first pass (eager tables) */
    double lazy_s;                   /* tables built on first use during the passes
                                        (part of wall_s) */
    uint64_t rays, samples;
    long nonfinite;                  /* samples rejected as NaN/inf (must stay 0) */
    long dims_reused;                /* sampler dimensions asked for twice by one
                                        sample (the dimension table; must stay 0) */
    long fallbacks;
} RenderStats;

void render_options_default(RenderOptions *o);
/* The thesis' settings, whatever the defaults (what `--preset thesis` sets): HWSS
   with uniform wavelengths, spatial selection (unit metric, hero wavelength),
   termination at rough dispersive glass, independent random numbers. */
void render_options_thesis(RenderOptions *o);
/* Render s into img (linear sRGB, w x h of the scene's film).  The scene is only
   read: the emitters' radiance for the sampled wavelength range, the wavelength
   pdf and the selection tables belong to the render (its RenderJob). */
int  render(const Scene *s, const RenderOptions *o, Image *img, RenderStats *st, Error *err);
/* render() for pbrt-v4's Film "spectral" (SceneSettings.spectral), with its
   buckets: *buckets (malloc'd; the caller frees it) holds nbuckets floats a pixel
   of img, bucket k the mean of L CIE_Y_INTEGRAL over the band
   [lambda_min + k d, lambda_min + (k + 1) d), d = (lambda_max - lambda_min) /
   nbuckets (render.c says how the four wavelengths of a sample go to them). */
int  render_spectral(const Scene *s, const RenderOptions *o, Image *img, float **buckets,
                     RenderStats *st, Error *err);
/* The spectral film as OpenEXR (render.c, with exr.c's writer): img's R, G, B and
   the buckets of render_spectral, named and clamped as pbrt-v4 writes them. */
int  img_write_spectral(const Image *im, const float *buckets, const SceneSettings *st,
                        const char *path, Error *err);
/* Progressive render up an increasing ladder of spp (o->spp is ignored): after
   the pass that reaches ladder[i], on_rung(user, i, img, st) sees the image with
   ladder[i] samples per pixel (bit-identical to render() with that spp) and the
   cumulative statistics of the render so far (time spent in on_rung excluded);
   returning 0 stops the render.  img holds the last image on return.  With a
   sampler that is not progressive (stratified, zsobol: sampler_progressive) every
   rung is a render of its own and st covers that render alone. */
typedef int (*RenderRungFn)(void *user, int rung, const Image *img, const RenderStats *st);
int  render_ladder(const Scene *s, const RenderOptions *o, const int *ladder, int n_rungs,
                   RenderRungFn on_rung, void *user, Image *img, RenderStats *st, Error *err);
/* The same, one step at a time, so that several renders can take turns (converge
   interleaves its variants rung by rung, pairing their timings):
     j = render_begin(s, o, err)       emitters, wavelength pdf, emitter tables
     render_advance(j, spp, final, err) add samples up to spp (increasing; final,
                                       the last spp planned, only for the progress bar)
     render_image(j), render_stats(j)  the image at spp and the cumulative statistics
                                       (build + passes; time between calls not counted)
     render_end(j)
   o and s must outlive j; s is only read, so jobs with different wavelength ranges
   may alternate.  A job whose sampler is not progressive takes one advance only (a
   second one fails: "not progressive"). */
typedef struct RenderJob RenderJob;
RenderJob *render_begin(const Scene *s, const RenderOptions *o, Error *err);
int  render_advance(RenderJob *j, int spp, int spp_final, Error *err);
const Image *render_image(const RenderJob *j);
const RenderStats *render_stats(const RenderJob *j);
void render_end(RenderJob *j);

/* ======================================================================
   13. SVG charts (svg.c): line plots for spectra and convergence charts
   ====================================================================== */
/* One series of a line chart: points (x[i], y[i]), i < n, drawn as a line (NaN, inf
   and, on log axes, values <= 0 break it), with an optional shaded band ylo..yhi
   (e.g. the min..max over seeds; both NULL for none). */
typedef struct {
    const char *name;          /* legend text; NULL: not in the legend */
    const char *color;         /* SVG colour ("#1f77b4"); NULL: the built-in palette */
    int n;                     /* number of points */
    const double *x, *y;       /* the points */
    const double *ylo, *yhi;   /* band edges, or NULL */
    int dashed;                /* 1: dashed line */
} SvgSeries;
typedef struct {
    const char *title, *xlabel, *ylabel;   /* any may be NULL */
    int logx, logy;            /* 1: log10 axis with ticks at powers of ten */
    int width, height;         /* pixels; 0: 720 x 450 */
    double xmin, xmax, ymin, ymax;         /* axis ranges; min >= max: from the data */
} SvgChart;
/* Write a standalone SVG chart to f; 1 on success, 0 on bad arguments or write error. */
int svg_line_chart(FILE *f, const SvgChart *c, const SvgSeries *s, int n_series);

/* ======================================================================
   14. Subcommands (each returns the process exit code: 0 ok, 1 bad input,
       2 bad usage); argv[0] is the subcommand's name
   ====================================================================== */
int cmd_spectrum(int argc, char **argv);   /* cmd_spectrum.c */
int cmd_merge(int argc, char **argv);      /* cmd_image.c */
int cmd_diff(int argc, char **argv);       /* cmd_image.c */
int cmd_converge(int argc, char **argv);   /* cmd_converge.c: error against time, charts, tables */
/* "strategy[:modifier]..." (modifiers: power all tput importance visible mixture
   mixture=M uniform roughmis terminate hero unit single wide nonee nosplit flpower
   fluniform flkeep flterminate) into
   render options; 0 if unknown.  Used by converge and its tests. */
int eval_parse_variant(const char *spec, RenderOptions *o);

#endif /* SPECNEE_H */
