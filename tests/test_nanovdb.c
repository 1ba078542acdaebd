/* tests/test_nanovdb.c - MakeNamedMedium "nanovdb": the NanoVDB reader
   (nanovdb.c) and the medium built on it (medium.c).

   Two sources of files:
   - tests/data/nanovdb/cloud.nvdb, written by the NanoVDB library itself
     (NanoVDB 32.3.3, the version pbrt-v4 5f7a6068 bundles: GridBuilder<float>,
     FogVolume, voxel size 0.08, origin (-0.1, 0.2, 0.05), io::writeGrids with the
     ZIP codec): a "density" grid d(i, j, k) = 0.5 + 0.5 sin(0.7 i) cos(0.5 j)
     (k + 5) / 15 where above 0.05, and a "temperature" grid 300 + 100 (i + j + k
     + 14) kelvin, both over i in -6..9, j in -3..12, k in -5..9 (eight root
     tiles: the grid crosses 0 on every axis).  The library's own sampler
     (SampleFromVoxels order 1 at worldToIndexF) gave the frozen values below;
   - files written here by nvdb_write, which lays the bytes out as nanovdb.c's
     block comment documents (one root tile, one upper and one lower node, leaves
     or 8^3 tiles; uncompressed, or ZIP with stored deflate blocks), so a test can
     choose the map, the values and the damage. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- the writer */

typedef struct {
    const char *name;
    uint32_t type, cls;        /* grid type (1 Float), class (2 fog volume) */
    int32_t origin[3];         /* the 128^3 lower node's origin (multiples of 128) */
    int n[3];                  /* voxels origin .. origin + n - 1 hold values */
    double (*fn)(const int32_t ijk[3]);
    int tiles;                 /* 1: each 8^3 block a tile of fn at its first voxel */
    double mat[9], vec[3];     /* index -> world */
    float background;
} WGrid;

typedef struct { unsigned char *b; size_t n, cap; } Buf;

static int buf_room(Buf *o, size_t k)
{
    if (o->n + k <= o->cap) return 1;
    while (o->cap < o->n + k) o->cap = o->cap ? 2 * o->cap : 4096;
    o->b = (unsigned char *)realloc(o->b, o->cap);
    return o->b != NULL;
}
static void put_le(unsigned char *p, uint64_t v, int bytes)
{
    int i;
    for (i = 0; i < bytes; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static void put_f32(unsigned char *p, float f) { uint32_t u; memcpy(&u, &f, 4); put_le(p, u, 4); }
static void put_f64(unsigned char *p, double d) { uint64_t u; memcpy(&u, &d, 8); put_le(p, u, 8); }
static void put_i32(unsigned char *p, int32_t v) { put_le(p, (uint64_t)(uint32_t)v, 4); }
static void append(Buf *o, const void *d, size_t k)
{
    if (!buf_room(o, k)) return;
    memcpy(o->b + o->n, d, k);
    o->n += k;
}

static void inverse3(const double m[9], double r[9])
{
    double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                 m[2] * (m[3] * m[7] - m[4] * m[6]);
    r[0] = (m[4] * m[8] - m[5] * m[7]) / det; r[1] = (m[2] * m[7] - m[1] * m[8]) / det;
    r[2] = (m[1] * m[5] - m[2] * m[4]) / det; r[3] = (m[5] * m[6] - m[3] * m[8]) / det;
    r[4] = (m[0] * m[8] - m[2] * m[6]) / det; r[5] = (m[2] * m[3] - m[0] * m[5]) / det;
    r[6] = (m[3] * m[7] - m[4] * m[6]) / det; r[7] = (m[1] * m[6] - m[0] * m[7]) / det;
    r[8] = (m[0] * m[4] - m[1] * m[3]) / det;
}

/* The world bbox of index voxels lo .. hi (NanoVDB: corners lo and hi + 1 mapped). */
static void world_bbox(const WGrid *g, const int32_t lo[3], const int32_t hi[3], double out[6])
{
    int c, k;
    for (c = 0; c < 8; c++) {
        double x[3];
        x[0] = c & 1 ? hi[0] + 1 : lo[0];
        x[1] = c & 2 ? hi[1] + 1 : lo[1];
        x[2] = c & 4 ? hi[2] + 1 : lo[2];
        for (k = 0; k < 3; k++) {
            double w = g->vec[k] + g->mat[3 * k] * x[0] + g->mat[3 * k + 1] * x[1] + g->mat[3 * k + 2] * x[2];
            if (c == 0 || w < out[k]) out[k] = w;
            if (c == 0 || w > out[3 + k]) out[3 + k] = w;
        }
    }
}

/* Grid g's memory image: GridData, TreeData, RootData + 1 tile, upper, lower,
   leaves (breadth first, as NanoVDB lays them out). */
static int grid_image(const WGrid *g, Buf *o)
{
    const size_t tree = 672, root = 736, upper = 832, lower = upper + 270400, leaves = lower + 33856;
    int32_t lo[3], hi[3], b[3];
    double inv[9], wb[6];
    uint32_t nleaf = 0, n;
    int k;
    unsigned char *p;
    for (k = 0; k < 3; k++) { lo[k] = g->origin[k]; hi[k] = g->origin[k] + g->n[k] - 1; }
    for (b[0] = 0; b[0] < 16; b[0]++) for (b[1] = 0; b[1] < 16; b[1]++) for (b[2] = 0; b[2] < 16; b[2]++)
        if (!g->tiles && 8 * b[0] < g->n[0] && 8 * b[1] < g->n[1] && 8 * b[2] < g->n[2]) nleaf++;
    o->n = 0;
    if (!buf_room(o, leaves + 2144 * (size_t)nleaf)) return 0;
    o->n = leaves + 2144 * (size_t)nleaf;
    p = o->b;
    memset(p, 0, o->n);
    inverse3(g->mat, inv);
    world_bbox(g, lo, hi, wb);
    put_le(p, 0x304244566F6E614EULL, 8);                         /* GridData */
    put_le(p + 16, 32u << 21 | 3u << 10 | 3u, 4);
    put_le(p + 28, 1, 4);
    put_le(p + 32, o->n, 8);
    memcpy(p + 40, g->name, strlen(g->name));
    for (k = 0; k < 9; k++) {
        put_f32(p + 296 + 4 * k, (float)g->mat[k]);
        put_f32(p + 296 + 36 + 4 * k, (float)inv[k]);
        put_f64(p + 296 + 88 + 8 * k, g->mat[k]);
        put_f64(p + 296 + 160 + 8 * k, inv[k]);
    }
    for (k = 0; k < 3; k++) {
        put_f32(p + 296 + 72 + 4 * k, (float)g->vec[k]);
        put_f64(p + 296 + 232 + 8 * k, g->vec[k]);
        put_f64(p + 560 + 8 * k, wb[k]);
        put_f64(p + 584 + 8 * k, wb[3 + k]);
        put_f64(p + 608 + 8 * k, sqrt(g->mat[k] * g->mat[k] + g->mat[3 + k] * g->mat[3 + k] +
                                      g->mat[6 + k] * g->mat[6 + k]));
    }
    put_f32(p + 296 + 84, 1.0f);
    put_f64(p + 296 + 256, 1.0);
    put_le(p + 632, g->cls, 4);
    put_le(p + 636, g->type, 4);
    put_le(p + tree, nleaf ? leaves - tree : 0, 8);                /* TreeData */
    put_le(p + tree + 8, lower - tree, 8);
    put_le(p + tree + 16, upper - tree, 8);
    put_le(p + tree + 24, root - tree, 8);
    put_le(p + tree + 32, nleaf, 4);
    put_le(p + tree + 36, 1, 4);
    put_le(p + tree + 40, 1, 4);
    for (k = 0; k < 3; k++) { put_i32(p + root + 4 * k, lo[k]); put_i32(p + root + 12 + 4 * k, hi[k]); }
    put_le(p + root + 24, 1, 4);                                  /* RootData + its tile */
    put_f32(p + root + 28, g->background);
    put_le(p + root + 64, (uint64_t)((uint32_t)g->origin[2] >> 12) | (uint64_t)((uint32_t)g->origin[1] >> 12) << 21 |
                          (uint64_t)((uint32_t)g->origin[0] >> 12) << 42, 8);
    put_le(p + root + 72, upper - root, 8);
    n = ((uint32_t)g->origin[0] & 4095) >> 7 << 10 | ((uint32_t)g->origin[1] & 4095) >> 7 << 5 |
        ((uint32_t)g->origin[2] & 4095) >> 7;                     /* upper: one child */
    p[upper + 4128 + n / 8] |= (unsigned char)(1u << (n % 8));
    put_le(p + upper + 8256 + 8 * (size_t)n, lower - upper, 8);
    nleaf = 0;
    for (n = 0; n < 4096; n++) {                                  /* lower: leaves or tiles */
        int32_t a[3], v;
        a[0] = g->origin[0] + (int32_t)(n >> 8) * 8;
        a[1] = g->origin[1] + (int32_t)((n >> 4) & 15) * 8;
        a[2] = g->origin[2] + (int32_t)(n & 15) * 8;
        if (a[0] > hi[0] || a[1] > hi[1] || a[2] > hi[2]) continue;
        if (g->tiles) { put_f32(p + lower + 1088 + 8 * (size_t)n, (float)g->fn(a)); continue; }
        p[lower + 544 + n / 8] |= (unsigned char)(1u << (n % 8));
        put_le(p + lower + 1088 + 8 * (size_t)n, leaves + 2144 * (size_t)nleaf - lower, 8);
        for (k = 0; k < 3; k++) put_i32(p + leaves + 2144 * (size_t)nleaf + 4 * k, a[k]);
        for (v = 0; v < 512; v++) {
            int32_t q[3];
            q[0] = a[0] + (v >> 6); q[1] = a[1] + ((v >> 3) & 7); q[2] = a[2] + (v & 7);
            put_f32(p + leaves + 2144 * (size_t)nleaf + 96 + 4 * (size_t)v,
                    q[0] <= hi[0] && q[1] <= hi[1] && q[2] <= hi[2] ? (float)g->fn(q) : g->background);
        }
        nleaf++;
    }
    return 1;
}

static uint32_t adler32(const unsigned char *d, size_t n)
{
    uint32_t a = 1, b = 0;
    size_t i;
    for (i = 0; i < n; i++) { a = (a + d[i]) % 65521u; b = (b + a) % 65521u; }
    return b << 16 | a;
}

/* A zlib stream of stored deflate blocks (RFC 1950/1951), after its u64 size. */
static void zip_stored(Buf *o, const unsigned char *d, size_t n)
{
    unsigned char h[8] = { 0 }, z[5];
    size_t start = o->n, at = 0;
    uint32_t ad = adler32(d, n);
    append(o, h, 8);
    z[0] = 0x78; z[1] = 0x01;
    append(o, z, 2);
    do {
        size_t k = n - at < 65535 ? n - at : 65535;
        z[0] = at + k == n;
        put_le(z + 1, k, 2);
        put_le(z + 3, ~k & 0xFFFF, 2);
        append(o, z, 5);
        append(o, d + at, k);
        at += k;
    } while (at < n);
    z[0] = (unsigned char)(ad >> 24); z[1] = (unsigned char)(ad >> 16);
    z[2] = (unsigned char)(ad >> 8); z[3] = (unsigned char)ad;
    append(o, z, 4);
    put_le(o->b + start, o->n - start - 8, 8);
}

/* A file of one segment: header, the grids' metadata, their data (codec 0 or 1). */
static int nvdb_file(const WGrid *g, int n, unsigned codec, Buf *out)
{
    Buf img[4];
    size_t at[4];
    unsigned char m[176];
    int i;
    memset(img, 0, sizeof img);
    out->n = 0;
    memset(m, 0, 16);
    put_le(m, 0x304244566F6E614EULL, 8);
    put_le(m + 8, 32u << 21 | 3u << 10 | 3u, 4);
    put_le(m + 12, (unsigned)n, 2);
    put_le(m + 14, codec, 2);
    append(out, m, 16);
    for (i = 0; i < n; i++) {
        if (!grid_image(&g[i], &img[i])) return 0;
        memset(m, 0, sizeof m);
        put_le(m, img[i].n, 8);
        put_le(m + 32, g[i].type, 4);
        put_le(m + 36, g[i].cls, 4);
        memcpy(m + 40, img[i].b + 560, 48);
        put_le(m + 136, strlen(g[i].name) + 1, 4);
        put_le(m + 168, codec, 2);
        put_le(m + 172, 32u << 21 | 3u << 10 | 3u, 4);
        at[i] = out->n;
        append(out, m, 176);
        append(out, g[i].name, strlen(g[i].name) + 1);
    }
    for (i = 0; i < n; i++) {
        size_t start = out->n;
        if (codec == 1) zip_stored(out, img[i].b, img[i].n);
        else append(out, img[i].b, img[i].n);
        put_le(out->b + at[i] + 8, out->n - start, 8);
        free(img[i].b);
    }
    return out->b != NULL;
}

static const char *write_buf(T *t, const char *name, const Buf *b)
{
    const char *path = test_path(t, name);
    FILE *f = fopen(path, "wb");
    if (!f) return NULL;
    if (fwrite(b->b, 1, b->n, f) != b->n) { fclose(f); return NULL; }
    return fclose(f) == 0 ? path : NULL;
}

/* ---------------------------------------------------------------- lookups */

/* cloud.nvdb against NanoVDB's own trilinear sampler (the generator printed
   SampleFromVoxels<FloatTree, 1, false>(worldToIndexF(p)) for these points). */
static void test_library_values(T *t)
{
    static const double pts[7][5] = {
        { 0, 0.5, 0.3, 0.441827357, 2512.5 },
        { -0.55, 0, -0.3, 0.504304469, 449.999939 },
        { 0.3, 1.1, 0.7, 0.38159281, 4137.5 },
        { 0.61, 0.93, 0.84, 0.0630579367, 550 },
        { -0.2, 0.33, 0.1, 0.408793479, 1800 },
        { 2, 2, 2, 0, 0 },
        { 0.123, 0.456, 0.0789, 0.495766878, 2334.875 }
    };
    static const double wb[6] = { -0.58, -0.04, -0.35, 0.7, 1.24, 0.85 };
    NanoGrid g[2];
    Error e;
    int i, k;
    CHECK(t, nanovdb_read("tests/data/nanovdb/cloud.nvdb", "density", &g[0], &e), "%s", e.msg);
    if (!nanovdb_read("tests/data/nanovdb/cloud.nvdb", "temperature", &g[1], &e)) {
        nanovdb_free(&g[0]);
        CHECK(t, 0, "%s", e.msg);
    }
    for (i = 0; i < 7; i++)
        for (k = 0; k < 2; k++) {
            double v = nanovdb_sample(&g[k], v3((float)pts[i][0], (float)pts[i][1], (float)pts[i][2]));
            if (!(fabs(v - pts[i][3 + k]) <= 2e-6 * fabs(pts[i][3 + k]) + 1e-7)) {
                test_failf(t, __FILE__, __LINE__, "point %d, grid %d: %.9g, NanoVDB %.9g", i, k, v, pts[i][3 + k]);
                break;
            }
        }
    for (k = 0; k < 6; k++)
        if (!(fabs((k < 3 ? g[0].wmin[k] : g[0].wmax[k - 3]) - wb[k]) < 1e-12))
            test_failf(t, __FILE__, __LINE__, "world bbox %d: %.17g, NanoVDB %.17g", k,
                       k < 3 ? g[0].wmin[k] : g[0].wmax[k - 3], wb[k]);
    CHECK(t, g[0].n_tiles == 8 && g[0].background == 0.0f, "%u root tiles, background %g", g[0].n_tiles,
          g[0].background);
    nanovdb_free(&g[0]);
    nanovdb_free(&g[1]);
}

/* A linear function of the index: trilinear filtering reproduces it exactly
   between voxels. */
static double lin(const int32_t q[3]) { return 2.0 + 0.25 * q[0] - 0.125 * q[1] + 0.0625 * q[2]; }

/* A rotated, non-uniformly scaled, translated map; voxels -128..-109 x 0..11 x
   128..136 (root keys of negative coordinates), leaves, both codecs: lookups at
   random index points between the voxels, mapped to the world here, give the
   linear function there; beyond the voxels, the background. */
static void test_linear_map(T *t)
{
    WGrid w;
    Buf b;
    NanoGrid g;
    Error e;
    Rng r;
    int codec, i, k;
    memset(&w, 0, sizeof w);
    memset(&b, 0, sizeof b);
    w.name = "density"; w.type = 1; w.cls = 2; w.fn = lin; w.background = 0.0f;
    w.origin[0] = -128; w.origin[1] = 0; w.origin[2] = 128;
    w.n[0] = 20; w.n[1] = 12; w.n[2] = 9;
    w.mat[0] = 0.08; w.mat[1] = -0.03; w.mat[2] = 0.0;
    w.mat[3] = 0.05; w.mat[4] = 0.06; w.mat[5] = 0.01;
    w.mat[6] = 0.0; w.mat[7] = 0.02; w.mat[8] = 0.1;
    w.vec[0] = 3.0; w.vec[1] = -1.0; w.vec[2] = -12.0;
    rng_seed(&r, 7, 1);
    for (codec = 0; codec < 2; codec++) {
        const char *path;
        CHECK(t, nvdb_file(&w, 1, (unsigned)codec, &b), "out of memory");
        path = write_buf(t, codec ? "lin-zip.nvdb" : "lin.nvdb", &b);
        CHECK(t, path != NULL, "cannot write the file");
        if (!nanovdb_read(path, "density", &g, &e)) { free(b.b); CHECK(t, 0, "%s", e.msg); }
        for (i = 0; i < 200; i++) {
            double x[3], p[3], v, want;
            float u[3];
            rng_fill(&r, u, 3);
            x[0] = -128 + 19.0 * u[0]; x[1] = 11.0 * u[1]; x[2] = 128 + 8.0 * u[2];
            if (i >= 150) x[0] -= 40.0;                   /* beyond the voxels: background */
            for (k = 0; k < 3; k++) p[k] = w.vec[k] + w.mat[3 * k] * x[0] + w.mat[3 * k + 1] * x[1] + w.mat[3 * k + 2] * x[2];
            v = nanovdb_sample(&g, v3((float)p[0], (float)p[1], (float)p[2]));
            want = 2.0 + 0.25 * x[0] - 0.125 * x[1] + 0.0625 * x[2];
            if (i >= 150) want = 0.0;
            if (!(fabs(v - want) < 2e-4 * (1.0 + fabs(want)))) {
                test_failf(t, __FILE__, __LINE__, "codec %d, index (%g %g %g): %.7g, expected %.7g", codec,
                           x[0], x[1], x[2], v, want);
                break;
            }
        }
        nanovdb_free(&g);
    }
    free(b.b);
}

/* ---------------------------------------------------------------- closed forms */

static double one(const int32_t q[3]) { (void)q; return 1.0; }
static double kelvin(const int32_t q[3]) { (void)q; return 2400.0; }

/* A box of 8^3 tiles of density 1 over voxels 0..31 (tiles: no leaves), mapped
   to x, y in [-128, 128] (8 per voxel) and z in [0, 1] (1/32 per voxel); with
   temp, a temperature grid of 2400 K over voxels 0..39 in the same frame. */
static const char *box_file(T *t, int temp, const char *name)
{
    WGrid w[2];
    Buf b;
    const char *path;
    int k;
    memset(w, 0, sizeof w);
    memset(&b, 0, sizeof b);
    for (k = 0; k < 2; k++) {
        w[k].name = k ? "temperature" : "density"; w[k].type = 1; w[k].cls = 2;
        w[k].fn = k ? kelvin : one; w[k].tiles = 1;
        w[k].n[0] = w[k].n[1] = w[k].n[2] = k ? 40 : 32;
        w[k].mat[0] = w[k].mat[4] = 8.0; w[k].mat[8] = 1.0 / 32.0;
        w[k].vec[0] = w[k].vec[1] = -128.0;
    }
    if (!nvdb_file(w, temp ? 2 : 1, 0, &b)) return NULL;
    path = write_buf(t, name, &b);
    free(b.b);
    return path;
}

static const char box_fmt[] =
    "MediumInterface \"\" \"g\"\n"
    "LookAt 0 0 5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 4 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
    "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "MakeNamedMedium \"g\" \"string type\" \"nanovdb\" \"string filename\" \"%s\" "
    "\"spectrum sigma_a\" [ 400 0.2 700 1.4 ] \"spectrum sigma_s\" [ 400 0 700 0 ] \"float scale\" 1.5 %s\n"
    "MediumInterface \"\" \"\"\n"
    "%s";
static const char box_light[] =
    "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1 ] \"float scale\" 2\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -50 -50 -1  50 -50 -1  50 50 -1  -50 50 -1 ]\n";

/* Y over [lo, hi] nm of what leaves the top of the box: the emitter below
   through it (lights.c's normalisation of L), or (temp) the blackbody the box
   emits, Lescale B((T - cutoff) scale) (1 - exp(-sigma_a D)). */
static double box_expect(double lo, double hi, double D, int temp)
{
    Spectrum c;
    double norm, sum = 0.0, h = 0.05, l;
    spec_const(&c, 1.0f);
    norm = luminance_sum(&c, LAMBDA_LO, LAMBDA_HI);
    for (l = lo + 0.5 * h; l < hi; l += h) {
        float xyz[3];
        double sa = 0.2 + 1.2 * (l - 400.0) / 300.0;
        cie_xyz((float)l, xyz);
        if (temp) sum += h * xyz[1] * 0.7 * blackbody_eval((2400.0f - 400.0f) * 1.25f, (float)l) * (1.0 - exp(-sa * D));
        else sum += h * xyz[1] * (2.0 / norm) * exp(-sa * D);
    }
    return sum;
}

/* Through the box along z: D = 1.5 x (31 + 1/2) / 32 (density 1 over voxels
   0..31, the last half voxel a ramp to the background), per band, with spectral
   MIS and with termination; and its blackbody emission alone. */
static void test_box(T *t)
{
    static char text[4096];
    static const char *const mode[3] = { "spectral MIS", "terminate", "emission" };
    const double D = 1.5 * 31.5 / 32.0;
    int m, b;
    for (m = 0; m < 3; m++) {
        const char *path = box_file(t, m == 2, m == 2 ? "box-t.nvdb" : "box.nvdb");
        Scene s;
        CHECK(t, path != NULL, "cannot write the file");
        snprintf(text, sizeof text, box_fmt, path, m == 2 ? "\"float Lescale\" 0.7 \"float temperaturecutoff\" 400 "
                 "\"float temperaturescale\" 1.25" : "", m == 2 ? "" : box_light);
        if (!test_load_scene(t, &s, text)) return;
        for (b = 0; b < 4; b++) {
            RenderOptions o;
            Tiles tl;
            double lo = b < 3 ? 420.0 + 100.0 * b : 400.0, hi = b < 3 ? lo + 10.0 : 700.0, se, Y,
                   expect = box_expect(lo, hi, D, m == 2);
            render_options_default(&o);
            o.spp = test_scaled(64, 16);
            o.band_lo = (float)lo;
            o.band_hi = (float)hi;
            o.media_terminate = m == 1;
            if (!test_render_tiles(t, &s, &o, 6, 1, &tl)) { scene_free(&s); return; }
            Y = test_tile_y(&tl, 0, &se);
            if (!(fabs(Y - expect) < TEST_K_SIGMA * se + 2e-3 * expect)) {
                test_failf(t, __FILE__, __LINE__, "%s, %g-%g nm: Y = %.6g +- %.2g, expected %.6g", mode[m],
                           lo, hi, Y, se, expect);
                scene_free(&s);
                return;
            }
        }
        scene_free(&s);
    }
}

/* ---------------------------------------------------------------- the medium */

/* Every lookup inside the bounds lies under its majorant cell (cloud.nvdb under
   a rotating CTM, with scale 3). */
static void test_majorant(T *t)
{
    static const char text[] =
        "WorldBegin\nRotate 30 1 1 0\nTranslate 0.2 0 -0.1\n"
        "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" "
        "\"tests/data/nanovdb/cloud.nvdb\" \"float scale\" 3\n"
        "Material \"interface\"\nMediumInterface \"m\" \"\"\nShape \"sphere\" \"float radius\" 3\n";
    static const float lam[HERO_N] = { 450.0f, 520.0f, 600.0f, 680.0f };
    Scene s;
    Rng r;
    int i, c[3], k, inside = 0;
    const Medium *m;
    Xform world;
    if (!test_load_scene(t, &s, text)) return;
    m = &s.media[0];
    memcpy(world.m, m->medium_from_world.inv, sizeof world.m);
    memcpy(world.inv, m->medium_from_world.m, sizeof world.inv);
    rng_seed(&r, 11, 2);
    for (i = 0; i < 20000; i++) {
        float u[3];
        Vec3 q, p;
        MediumPoint mp;
        rng_fill(&r, u, 3);
        q = v3(m->p0.x + u[0] * (m->p1.x - m->p0.x), m->p0.y + u[1] * (m->p1.y - m->p0.y),
               m->p0.z + u[2] * (m->p1.z - m->p0.z));
        p = xf_point(&world, q);                  /* the medium's space to the world */
        medium_point(m, p, lam, 15u, &mp);
        for (k = 0; k < 3; k++) {
            c[k] = (int)(u[k] * m->maj_res);
            if (c[k] > m->maj_res - 1) c[k] = m->maj_res - 1;
        }
        if (mp.sa[0] > 0.0) inside++;
        for (k = 0; k < HERO_N; k++)
            if (!(mp.sa[k] + mp.ss[k] <= medium_sigma_t(m, lam[k]) *
                  m->majorant[(c[2] * m->maj_res + c[1]) * m->maj_res + c[0]] * 1.0001)) {
                scene_free(&s);
                CHECK(t, 0, "point %d: sigma_t %g above its majorant", i, mp.sa[k] + mp.ss[k]);
            }
    }
    k = m->maj_res;
    scene_free(&s);
    CHECK(t, inside > 2000, "only %d of 20000 points in the density", inside);
    CHECK(t, k == 64, "a %d^3 majorant grid; pbrt-v4's is 64^3", k);
}

/* ---- against pbrt-v4: the luminance of the whole image and of its quadrants
   (top-left, top-right, bottom-left, bottom-right) of tests/data/nanovdb/smoke.pbrt
   (cloud.nvdb's density as chromatic smoke, turned by the CTM, scale 2, g 0.3,
   under an area light over a floor) and fire.pbrt (its temperature grid as a
   blackbody, Lescale 0.5, temperaturecutoff 400, temperaturescale 0.8, absorbing
   and scattering by its density, the only light).  Frozen from pbrt-v4
   (mmp/pbrt-v4 5f7a6068, `pbrt --spp 4096 --seed S` for S = 1, 2, the mean of
   the two; they differ by at most 0.63 % (smoke) and 0.69 % (fire) per value). */
static void test_against_pbrt(T *t)
{
    static const char *const files[2] = { "tests/data/nanovdb/smoke.pbrt", "tests/data/nanovdb/fire.pbrt" };
    static const double pbrt_y[2][5] = {
        { 5.59719, 11.9119, 2.32162, 7.13575, 1.0195 },
        { 0.67532, 1.89262, 0.535862, 0.232733, 0.0400619 }
    };
    int f;
    for (f = 0; f < 2; f++) {
        Scene s;
        RenderOptions o;
        Error e;
        CHECK(t, scene_load(&s, files[f], &e), "%s", e.msg);
        render_options_default(&o);
        o.spp = test_scaled(64, 16);
        o.maxdepth = 20;
        test_quadrants_against_pbrt(t, &s, &o, pbrt_y[f], files[f]);
        scene_free(&s);
        if (t->failed) return;
    }
}

/* ---------------------------------------------------------------- bad files */

/* path read for "density" must fail with a message holding `want` (and the path). */
static int read_fails(T *t, const char *path, const char *want, int line)
{
    NanoGrid g;
    Error e;
    e.msg[0] = 0;
    if (nanovdb_read(path, "density", &g, &e)) {
        nanovdb_free(&g);
        test_failf(t, __FILE__, line, "%s read; expected \"%s\"", path, want);
        return 0;
    }
    if (!strstr(e.msg, want) || strncmp(e.msg, path, strlen(path)) != 0 || strchr(e.msg, '\n')) {
        test_failf(t, __FILE__, line, "message \"%s\" lacks \"%s\" or the file", e.msg, want);
        return 0;
    }
    return 1;
}

/* A small valid grid (one leaf) as an uncompressed file in b. */
static int small_file(Buf *b, uint32_t type, uint32_t cls, unsigned codec)
{
    WGrid w;
    memset(&w, 0, sizeof w);
    w.name = "density"; w.type = type; w.cls = cls; w.fn = one;
    w.n[0] = w.n[1] = w.n[2] = 4;
    w.mat[0] = w.mat[4] = w.mat[8] = 0.25;
    return nvdb_file(&w, 1, codec, b);
}

#define FAILS(path, want) do { if (!read_fails(t, (path), (want), __LINE__)) { free(b.b); return; } } while (0)

/* Each damage gives its one-line "file: message"; every truncation of a valid
   file fails cleanly too. */
static void test_bad_files(T *t)
{
    Buf b;
    const char *p;
    size_t n, cut;
    NanoGrid g;
    Error e;
    memset(&b, 0, sizeof b);
    CHECK(t, small_file(&b, 1, 2, 0), "out of memory");
    p = write_buf(t, "ok.nvdb", &b);
    CHECK(t, p && nanovdb_read(p, "density", &g, &e) && g.buf, "the valid file: %s", e.msg);
    nanovdb_free(&g);
    CHECK(t, nanovdb_read(p, "smoke", &g, &e) && !g.buf, "a missing name is no error");
    n = b.n;
    for (cut = 0; cut < n; cut += cut < 1000 ? 7 : 4093) {     /* truncated anywhere */
        Buf c = b;
        c.n = cut;
        p = write_buf(t, "cut.nvdb", &c);
        FAILS(p, cut == 0 ? "empty file" : "truncated");
    }
    b.b[0] ^= 1;                                                  /* the magic number */
    FAILS(write_buf(t, "magic.nvdb", &b), "not a NanoVDB file");
    b.b[0] ^= 1;
    b.b[7] = '1';                                                 /* a later file format */
    FAILS(write_buf(t, "later.nvdb", &b), "a NanoVDB file of a later format (magic \"NanoVDB1\")");
    b.b[7] = '0';
    {
        unsigned char m[8];
        int k;
        memcpy(m, b.b, 8);
        for (k = 0; k < 8; k++) b.b[k] = m[7 - k];                /* byte-swapped */
        FAILS(write_buf(t, "swapped.nvdb", &b), "reversed endianness");
        memcpy(b.b, m, 8);
    }
    put_le(b.b + 8, 31u << 21 | 3u << 10 | 3u, 4);               /* version 31.3.3 */
    FAILS(write_buf(t, "v31.nvdb", &b), "NanoVDB version 31.3.3");
    put_le(b.b + 8, 32u << 21 | 3u << 10 | 3u, 4);
    b.b[14] = 2;                                                  /* BLOSC */
    FAILS(write_buf(t, "blosc.nvdb", &b), "BLOSC-compressed");
    b.b[14] = 9;
    FAILS(write_buf(t, "codec.nvdb", &b), "unknown codec 9");
    b.b[14] = 0;
    b.b[16 + 176 + 8 + 672 + 27] ^= 0x40;                         /* the root offset */
    FAILS(write_buf(t, "root.nvdb", &b), "root node lies outside");
    b.b[16 + 176 + 8 + 672 + 27] ^= 0x40;
    b.b[16 + 176 + 8 + 832 + 8256 + 7] ^= 0x10;                   /* an upper child offset */
    FAILS(write_buf(t, "child.nvdb", &b), "offset leaves the grid");
    put_le(b.b + 200 + 832 + 8256, (b.n - 200) - 100 - 832, 8);     /* a lower node past the end */
    FAILS(write_buf(t, "child-end.nvdb", &b), "offset leaves the grid");
    free(b.b);
    memset(&b, 0, sizeof b);
    CHECK(t, small_file(&b, 2, 2, 0), "out of memory");
    FAILS(write_buf(t, "double.nvdb", &b), "holds Double values; only Float grids are read");
    free(b.b);
    memset(&b, 0, sizeof b);
    CHECK(t, small_file(&b, 1, 1, 0), "out of memory");
    FAILS(write_buf(t, "sdf.nvdb", &b), "isn't a FogVolume grid");
    free(b.b);
    memset(&b, 0, sizeof b);
    CHECK(t, small_file(&b, 1, 2, 1), "out of memory");
    b.b[b.n - 1] ^= 0xFF;                                         /* the ZIP stream's checksum */
    FAILS(write_buf(t, "zip.nvdb", &b), "ZIP:");
    free(b.b);
    b.b = NULL;
    FAILS("tests/data/nanovdb/no-such-file.nvdb", "cannot read file");
}

/* fire.pbrt (emission, scattering, a rotated frame) with 1 and 2 threads. */
static void test_threads(T *t)
{
    Scene s;
    RenderOptions o;
    Image a, b;
    RenderStats st;
    Error e;
    CHECK(t, scene_load(&s, "tests/data/nanovdb/fire.pbrt", &e), "%s", e.msg);
    render_options_default(&o);
    o.spp = 4;
    o.threads = 1;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    if (!render(&s, &o, &a, &st, &e)) { scene_free(&s); CHECK(t, 0, "%s", e.msg); }
    o.threads = 2;
    if (!render(&s, &o, &b, &st, &e)) { img_free(&a); scene_free(&s); CHECK(t, 0, "%s", e.msg); }
    scene_free(&s);
    if (memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * a.h) != 0)
        test_failf(t, __FILE__, __LINE__, "1 and 2 threads differ");
    img_free(&a);
    img_free(&b);
}

const TestCase tests_nanovdb[] = {
    { "nanovdb_library_values", test_library_values },
    { "nanovdb_linear_map", test_linear_map },
    { "nanovdb_box_transmittance", test_box },
    { "nanovdb_majorant", test_majorant },
    { "nanovdb_bad_files", test_bad_files },
    { "nanovdb_threads", test_threads },
    { "nanovdb_against_pbrt", test_against_pbrt },
    { NULL, NULL }
};
