/* nanovdb.c - a reader of NanoVDB files (.nvdb) for the float grids of pbrt-v4's
   "nanovdb" medium (medium.c), their trilinear lookup, and the majorant of a grid.

   Exported (specnee.h section 6b): nanovdb_read, nanovdb_read_memory,
   nanovdb_sample, nanovdb_majorant, nanovdb_free.

   THE FILE (NanoVDB 32.3, the version pbrt-v4 5f7a6068 bundles; all numbers
   little-endian, offsets in bytes).  A file is one or more SEGMENTS, each
       segment header  16 B: u64 magic 0x304244566F6E614E ("NanoVDB0" read as
                       bytes), u32 version (major << 21 | minor << 10 | patch; the
                       major must be 32), u16 grid count, u16 codec (0 none,
                       1 ZIP, 2 BLOSC)
       grid metadata   per grid, 176 B: u64 grid size (bytes in memory), u64 file
                       size (bytes on disk), u64 name hash, u64 active voxels,
                       u32 grid type, u32 grid class, 6 f64 world bbox, 6 i32 index
                       bbox, 3 f64 voxel size, u32 name size (with its NUL),
                       4 u32 node counts, 3 u32 tile counts, u16 codec, u16 pad,
                       u32 version; then the name itself (name size bytes)
       grid data       per grid, in the same order, file size bytes: the grid's
                       memory image as it is (codec 0), or a u64 byte count and a
                       zlib stream that inflates to grid size bytes (ZIP)
   A grid's memory image (each block 32-byte aligned; offsets inside it):
       GridData   672 B at 0: u64 magic, u64 checksum, u32 version, u32 flags,
                  u32 grid index, u32 grid count, u64 grid size, char name[256]
                  (at 40), the map (at 296: 9 f32 matrix, 9 f32 inverse, 3 f32
                  translation, f32 taper, then the same 9 + 9 + 3 + 1 in f64), f64
                  world bbox[6] (at 560), f64 voxel size[3], u32 grid class (632),
                  u32 grid type (636: 1 = Float), i64 blind metadata offset, u32
                  blind count
       TreeData   64 B at 672: u64 node offset[4] (from the TreeData to the
                  first leaf, lower, upper node and to the root), u32 node
                  count[3] (leaf, lower, upper), u32 tile count[3], u64 voxels
       RootData   64 B: i32 index bbox[6] (inclusive), u32 tile count, f32
                  background, minimum, maximum, average, deviation; then the
                  tiles, 32 B each: u64 key (x >> 12 in bits 42..62, y >> 12 in
                  21..41, z >> 12 in 0..20, each of the 32-bit two's complement
                  coordinate), i64 child (0: a tile; else the upper node's offset
                  from the RootData), u32 active, f32 value
       upper node 270400 B (32^3 children of 128^3 voxels each): i32 bbox[6],
                  u64 flags, value mask (4096 B at 32), child mask (4096 B at
                  4128), f32 min, max, average, deviation, then at 8256 a table of
                  32768 8-byte entries: an i64 offset of the child from this node
                  where the child mask bit is set, else an f32 tile value
       lower node 33856 B (16^3 children of 8^3 voxels): the same with 512-byte
                  masks at 32 and 544 and the table (4096 entries) at 1088
       leaf       2144 B (8^3 voxels): i32 origin[3], u8 bbox size[3], u8 flags,
                  value mask (64 B at 16), f32 min, max, average, deviation, then
                  at 96 the 512 f32 values, active or not
   Entry n of a node holds the coordinates (x, y, z) with n = (x' << 2L) | (y' << L)
   | z', x' = (x mod dim) >> child's log2 width, L the node's log2 width (5, 4, 3);
   a mask is u64 words, bit n in word n >> 6.  The value at (x, y, z) is the
   leaf's, else the tile's of the first node without a child there, else the
   root's background when no root tile has the key.

   READING (pbrt-v4 NanoVDBMedium::Create, nanovdb::io::readGrid): the first grid
   of the file with the wanted name (none: found = 0, not an error).  Refused with
   "file: message": a wrong magic (a byte-swapped one says so), a major version
   other than 32, BLOSC or an unknown codec, a grid type other than Float, a grid
   class other than fog volume or unknown (pbrt-v4's check), truncated data, and
   any offset that leaves the grid's bytes.  Each child offset is checked once at
   load, and no node may be reached more often than the tree's node counts allow
   (so the check costs no more than the file's size); lookups then read without
   checks.  The name hash and the checksum are not checked (pbrt-v4 compares the
   name, and does not verify the checksum either).

   LOOKUP (nanovdb::SampleFromVoxels, order 1): the value of voxel (i, j, k)
   sits at index point (i, j, k); a point p of the medium's space maps to index
   space by the grid's single-precision inverse map, x = Minv (p - t) (pbrt-v4's
   worldToIndexF), and the density there is the trilinear blend of the eight
   voxels around it, read from the tree (no dense copy: a sparse grid's empty
   space is background, and a dense copy of a real cloud would not fit).

   MAJORANT.  A voxel's value enters lookups within one voxel of it, the open
   box (i - 1, i + 1) in index space; nanovdb_majorant walks every leaf value and
   every tile once and raises each majorant cell that the box's image (through
   the map) overlaps to the value, so a cell's majorant bounds every lookup in
   it (medium.c gives it NANOVDB_MAJORANT_RES^3 cells, pbrt-v4's 64^3).  pbrt-v4
   instead reads, per cell, the voxels between the index images of the cell's two
   corners, one voxel of slop, clipped to the index bbox; both are bounds of the
   same density (a majorant changes the noise, not the mean). */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

#define NVDB_HEADER 16
#define NVDB_META 176
#define NVDB_GRIDDATA 672
#define NVDB_TREEDATA 64
#define NVDB_ROOTDATA 64
#define NVDB_TILE 32
#define NVDB_UPPER 270400
#define NVDB_LOWER 33856
#define NVDB_LEAF 2144
#define NVDB_MAJOR 32

static uint32_t rd32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t rd64(const unsigned char *p) { return (uint64_t)rd32(p) | (uint64_t)rd32(p + 4) << 32; }
static float rdf(const unsigned char *p)
{
    uint32_t u = rd32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}
static double rdd(const unsigned char *p)
{
    uint64_t u = rd64(p);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}
/* A two's complement 32-bit or 64-bit pattern as a signed number. */
static int32_t s32(uint32_t u) { return u < 0x80000000u ? (int32_t)u : -(int32_t)(~u) - 1; }
static int64_t s64(uint64_t u)
{
    return u < ((uint64_t)1 << 63) ? (int64_t)u : -(int64_t)(~u) - 1;
}

/* ---------------------------------------------------------------- lookups */

/* The root key of (x, y, z): the top 20 bits of each coordinate. */
static uint64_t root_key(int32_t x, int32_t y, int32_t z)
{
    return (uint64_t)((uint32_t)z >> 12) | (uint64_t)((uint32_t)y >> 12) << 21 |
           (uint64_t)((uint32_t)x >> 12) << 42;
}

static int mask_on(const unsigned char *mask, uint32_t n) { return (mask[n >> 3] >> (n & 7)) & 1; }

/* The value of voxel (x, y, z) (nanovdb's RootNode::getValue). */
static float value_at(const NanoGrid *g, int32_t x, int32_t y, int32_t z)
{
    uint64_t key = root_key(x, y, z);
    const unsigned char *b = g->buf, *node;
    uint32_t lo = 0, hi = g->n_tiles, n;
    while (lo < hi) {                               /* the sorted keys */
        uint32_t mid = lo + (hi - lo) / 2;
        if (g->keys[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    if (lo == g->n_tiles || g->keys[lo] != key) return g->background;
    node = b + g->tiles[lo];
    if (rd64(node + 8) == 0) return rdf(node + 20);
    node = b + g->root + s64(rd64(node + 8));       /* upper: 32^3 entries */
    n = ((uint32_t)x & 4095) >> 7 << 10 | ((uint32_t)y & 4095) >> 7 << 5 | ((uint32_t)z & 4095) >> 7;
    if (!mask_on(node + 4128, n)) return rdf(node + 8256 + 8 * (size_t)n);
    node += s64(rd64(node + 8256 + 8 * (size_t)n));  /* lower: 16^3 entries */
    n = ((uint32_t)x & 127) >> 3 << 8 | ((uint32_t)y & 127) >> 3 << 4 | ((uint32_t)z & 127) >> 3;
    if (!mask_on(node + 544, n)) return rdf(node + 1088 + 8 * (size_t)n);
    node += s64(rd64(node + 1088 + 8 * (size_t)n));  /* leaf: 8^3 values */
    n = ((uint32_t)x & 7) << 6 | ((uint32_t)y & 7) << 3 | ((uint32_t)z & 7);
    return rdf(node + 96 + 4 * (size_t)n);
}

double nanovdb_sample(const NanoGrid *g, Vec3 p)
{
    float q[3], d[3] = { p.x - g->vecf[0], p.y - g->vecf[1], p.z - g->vecf[2] };
    double f[3], v[8], a, b;
    int32_t i[3];
    int k, c;
    for (k = 0; k < 3; k++) {
        q[k] = g->invf[3 * k] * d[0] + g->invf[3 * k + 1] * d[1] + g->invf[3 * k + 2] * d[2];
        if (!(fabsf(q[k]) < 2e9f)) return 0.0;      /* far outside any grid (or NaN) */
        i[k] = (int32_t)floorf(q[k]);
        f[k] = (double)q[k] - i[k];
    }
    for (c = 0; c < 8; c++) v[c] = value_at(g, i[0] + (c & 1), i[1] + ((c >> 1) & 1), i[2] + (c >> 2));
    a = (1.0 - f[1]) * ((1.0 - f[0]) * v[0] + f[0] * v[1]) + f[1] * ((1.0 - f[0]) * v[2] + f[0] * v[3]);
    b = (1.0 - f[1]) * ((1.0 - f[0]) * v[4] + f[0] * v[5]) + f[1] * ((1.0 - f[0]) * v[6] + f[0] * v[7]);
    return (1.0 - f[2]) * a + f[2] * b;
}

/* ---------------------------------------------------------------- the tree walk */

/* One walk of the tree serves two ends: at load (maj NULL) it checks every child
   offset and value; for the majorant (maj set) it raises the cells each value can
   reach. */
typedef struct {
    const NanoGrid *g;
    Error *e;
    const char *name;
    uint32_t left[3];          /* nodes the walk may still enter: leaf, lower, upper */
    const double *lo, *hi;     /* the majorant's bounds (medium space) */
    int res;
    float *maj;
} Walk;

/* The majorant cells that lookups near voxels a .. a + w - 1 (each axis) can lie in
   take at least v: the index box (a - 1, a + w) through the map, as an AABB. */
static void raise_box(Walk *k, const int32_t a[3], int32_t w, float v)
{
    const NanoGrid *g = k->g;
    double half = 0.5 * (w - 1) + 1.001, c[3], lo[3], hi[3];
    int i, j, r, x, y, z;
    if (!(v > 0.0f)) return;
    for (i = 0; i < 3; i++) c[i] = a[i] + 0.5 * (w - 1);
    for (i = 0; i < 3; i++) {
        double m = g->vec[i], h = 0.0;
        for (j = 0; j < 3; j++) {
            m += g->mat[3 * i + j] * c[j];
            h += fabs(g->mat[3 * i + j]) * half;
        }
        h *= 1.0 + 1e-6;
        r = k->res;
        lo[i] = floor((m - h - k->lo[i]) / (k->hi[i] - k->lo[i]) * r);
        hi[i] = floor((m + h - k->lo[i]) / (k->hi[i] - k->lo[i]) * r);
        if (!(hi[i] >= 0.0) || !(lo[i] < r)) return;     /* beyond the bounds */
        if (lo[i] < 0.0) lo[i] = 0.0;
        if (hi[i] > r - 1) hi[i] = r - 1;
    }
    for (z = (int)lo[2]; z <= (int)hi[2]; z++)
        for (y = (int)lo[1]; y <= (int)hi[1]; y++)
            for (x = (int)lo[0]; x <= (int)hi[0]; x++) {
                float *m = &k->maj[((size_t)z * k->res + y) * k->res + x];
                if (v > *m) *m = v;
            }
}

/* A value of the tree: finite (at load), or raised into the majorant. */
static int walk_value(Walk *k, const int32_t a[3], int32_t w, float v)
{
    if (!k->maj) {
        if (!isfinite(v))
            error_set(k->e, NULL, 0, "grid \"%s\" holds a non-finite value", k->name);
        return isfinite(v);
    }
    raise_box(k, a, w, v);
    return 1;
}

/* The child at offset `rel` from the node at `from`, of `bytes` bytes, at level
   lv (0 leaf, 1 lower, 2 upper): its offset, or 0 (and the error) when it leaves
   the grid or the tree's node count is spent. */
static size_t walk_child(Walk *k, size_t from, uint64_t rel, size_t bytes, int lv)
{
    int64_t off = s64(rel);
    size_t at;
    if (k->maj) return from + (size_t)off;
    if ((off < 0 && (uint64_t)(-(off + 1)) + 1 > from) ||
        (off > 0 && (uint64_t)off > k->g->size - from)) at = 0;
    else at = from + (size_t)off;
    if (at == 0 || bytes > k->g->size - at) {
        error_set(k->e, NULL, 0, "grid \"%s\": a child node's offset leaves the grid", k->name);
        return 0;
    }
    if (k->left[lv] == 0) {
        error_set(k->e, NULL, 0, "grid \"%s\": more child nodes than the tree's node counts",
                  k->name);
        return 0;
    }
    k->left[lv]--;
    return at;
}

/* The entries of an internal node at `at` with origin o: log2 width lg (5 upper,
   4 lower), child log2 width cl (7, 3); its child mask at cm, its table at tb. */
static int walk_node(Walk *k, size_t at, const int32_t o[3], int lg, int cl, size_t cm, size_t tb)
{
    const unsigned char *b = k->g->buf + at;
    uint32_t n, size = 1u << (3 * lg);
    for (n = 0; n < size; n++) {
        int32_t a[3];
        a[0] = o[0] + (int32_t)((n >> (2 * lg)) << cl);
        a[1] = o[1] + (int32_t)(((n >> lg) & ((1u << lg) - 1)) << cl);
        a[2] = o[2] + (int32_t)((n & ((1u << lg) - 1)) << cl);
        if (!mask_on(b + cm, n)) {
            if (!walk_value(k, a, (int32_t)1 << cl, rdf(b + tb + 8 * (size_t)n))) return 0;
        } else if (lg == 5) {
            size_t c = walk_child(k, at, rd64(b + tb + 8 * (size_t)n), NVDB_LOWER, 1);
            if (!c || !walk_node(k, c, a, 4, 3, 544, 1088)) return 0;
        } else {
            size_t c = walk_child(k, at, rd64(b + tb + 8 * (size_t)n), NVDB_LEAF, 0);
            uint32_t v;
            if (!c) return 0;
            for (v = 0; v < 512; v++) {
                int32_t p[3];
                p[0] = a[0] + (int32_t)(v >> 6);
                p[1] = a[1] + (int32_t)((v >> 3) & 7);
                p[2] = a[2] + (int32_t)(v & 7);
                if (!walk_value(k, p, 1, rdf(k->g->buf + c + 96 + 4 * (size_t)v))) return 0;
            }
        }
    }
    return 1;
}

/* The 32-bit coordinate whose top 20 bits a root key's 21-bit field holds. */
static int32_t key_coord(uint64_t key, int shift)
{
    return s32((uint32_t)(((key >> shift) & 0x1FFFFF) << 12));
}

static int walk_tree(Walk *k)
{
    const NanoGrid *g = k->g;
    uint32_t t;
    for (t = 0; t < g->n_tiles; t++) {
        const unsigned char *tile = g->buf + g->tiles[t];
        int32_t o[3];
        o[0] = key_coord(g->keys[t], 42);
        o[1] = key_coord(g->keys[t], 21);
        o[2] = key_coord(g->keys[t], 0);
        if (rd64(tile + 8) == 0) {
            if (!walk_value(k, o, 4096, rdf(tile + 20))) return 0;
        } else {
            size_t c = walk_child(k, g->root, rd64(tile + 8), NVDB_UPPER, 2);
            if (!c || !walk_node(k, c, o, 5, 7, 4128, 8256)) return 0;
        }
    }
    return 1;
}

void nanovdb_majorant(const NanoGrid *g, const double lo[3], const double hi[3], int res, float *maj)
{
    Walk k;
    size_t i, n = (size_t)res * res * res;
    memset(&k, 0, sizeof k);
    k.g = g;
    k.lo = lo;
    k.hi = hi;
    k.res = res;
    k.maj = maj;
    for (i = 0; i < n; i++) maj[i] = g->background > 0.0f ? g->background : 0.0f;
    walk_tree(&k);
}

/* ---------------------------------------------------------------- loading */

static int key_cmp(const void *a, const void *b)
{
    const uint64_t *x = (const uint64_t *)a, *y = (const uint64_t *)b;
    return x[0] < y[0] ? -1 : x[0] > y[0];
}

/* The root tiles sorted by key (pairs key, offset), for value_at's binary search. */
static int sort_tiles(NanoGrid *g, const char *name, Error *e)
{
    uint64_t *pairs = (uint64_t *)malloc(2 * sizeof(uint64_t) * (g->n_tiles ? g->n_tiles : 1));
    uint32_t t;
    g->keys = (uint64_t *)malloc(sizeof(uint64_t) * (g->n_tiles ? g->n_tiles : 1));
    g->tiles = (size_t *)malloc(sizeof(size_t) * (g->n_tiles ? g->n_tiles : 1));
    if (!pairs || !g->keys || !g->tiles) {
        free(pairs);
        error_set(e, NULL, 0, "out of memory");
        return 0;
    }
    for (t = 0; t < g->n_tiles; t++) {
        pairs[2 * t] = rd64(g->buf + g->root + NVDB_ROOTDATA + (size_t)NVDB_TILE * t);
        pairs[2 * t + 1] = g->root + NVDB_ROOTDATA + (size_t)NVDB_TILE * t;
    }
    qsort(pairs, g->n_tiles, 2 * sizeof(uint64_t), key_cmp);
    for (t = 0; t < g->n_tiles; t++) {
        if (t > 0 && pairs[2 * t] == pairs[2 * t - 2]) {
            free(pairs);
            error_set(e, NULL, 0, "grid \"%s\": two root tiles with the same key", name);
            return 0;
        }
        g->keys[t] = pairs[2 * t];
        g->tiles[t] = (size_t)pairs[2 * t + 1];
    }
    free(pairs);
    return 1;
}

static const char *grid_type_name(uint32_t t)
{
    static const char *const names[] = { "Unknown", "Float", "Double", "Int16", "Int32", "Int64",
        "Vec3f", "Vec3d", "Mask", "Half", "UInt32", "Boolean", "RGBA8", "Fp4", "Fp8", "Fp16",
        "FpN", "Vec4f", "Vec4d" };
    return t < sizeof names / sizeof names[0] ? names[t] : "unknown-type";
}

/* The grid's header blocks (GridData, TreeData, RootData) checked and read. */
static int parse_grid(NanoGrid *g, const char *name, Error *e)
{
    const unsigned char *b = g->buf;
    uint64_t root;
    uint32_t type = rd32(b + 636), cls = rd32(b + 632), lv;
    static const size_t node_bytes[3] = { NVDB_LEAF, NVDB_LOWER, NVDB_UPPER };
    int i;
    Walk k;
    if (rd64(b) != 0x304244566F6E614EULL)
        return error_set(e, NULL, 0, "grid \"%s\": its data does not start with NanoVDB's magic number",
                         name), 0;
    if (type != 1)
        return error_set(e, NULL, 0, "grid \"%s\" holds %s values; only Float grids are read", name,
                         grid_type_name(type)), 0;
    if (cls != 0 && cls != 2)
        return error_set(e, NULL, 0, "grid \"%s\" isn't a FogVolume grid (class %u)", name,
                         (unsigned)cls), 0;
    root = rd64(b + NVDB_GRIDDATA + 24);
    if (root > g->size - NVDB_GRIDDATA || NVDB_ROOTDATA > g->size - NVDB_GRIDDATA - root)
        return error_set(e, NULL, 0, "grid \"%s\": its root node lies outside the grid", name), 0;
    g->root = NVDB_GRIDDATA + (size_t)root;
    g->n_tiles = rd32(b + g->root + 24);
    if (g->n_tiles > (g->size - g->root - NVDB_ROOTDATA) / NVDB_TILE)
        return error_set(e, NULL, 0, "grid \"%s\": %u root tiles do not fit in the grid", name,
                         (unsigned)g->n_tiles), 0;
    g->background = rdf(b + g->root + 28);
    for (i = 0; i < 9; i++) {
        g->invf[i] = rdf(b + 296 + 36 + 4 * i);
        g->mat[i] = rdd(b + 296 + 88 + 8 * i);
    }
    for (i = 0; i < 3; i++) {
        g->vecf[i] = rdf(b + 296 + 72 + 4 * i);
        g->vec[i] = rdd(b + 296 + 232 + 8 * i);
        g->wmin[i] = rdd(b + 560 + 8 * i);
        g->wmax[i] = rdd(b + 560 + 24 + 8 * i);
    }
    for (i = 0; i < 9; i++)
        if (!isfinite(g->invf[i]) || !isfinite(g->mat[i]) || (i < 3 && (!isfinite(g->vecf[i]) ||
            !isfinite(g->vec[i]))))
            return error_set(e, NULL, 0, "grid \"%s\": its index-to-world map is not finite", name), 0;
    if (!isfinite(g->background))
        return error_set(e, NULL, 0, "grid \"%s\" holds a non-finite value", name), 0;
    memset(&k, 0, sizeof k);
    k.g = g;
    k.e = e;
    k.name = name;
    for (lv = 0; lv < 3; lv++) {
        k.left[lv] = rd32(b + NVDB_GRIDDATA + 32 + 4 * lv);
        if (k.left[lv] > g->size / node_bytes[lv]) k.left[lv] = (uint32_t)(g->size / node_bytes[lv]);
    }
    return sort_tiles(g, name, e) && walk_tree(&k);
}

/* Grid `gi` of a segment whose data starts at d[0 .. n): into g (codec 0 or 1). */
static int grid_bytes(const unsigned char *d, size_t n, uint64_t size, unsigned codec,
                      const char *name, NanoGrid *g, Error *e)
{
    const char *why;
    uint64_t cs;
    if (size < NVDB_GRIDDATA + NVDB_TREEDATA + NVDB_ROOTDATA || size > READ_MAX_BYTES)
        return error_set(e, NULL, 0, "grid \"%s\": grid size %.0f bytes is out of range", name,
                         (double)size), 0;
    if (codec == 0 && size > n)
        return error_set(e, NULL, 0, "truncated: grid \"%s\" needs %.0f bytes, the file has %.0f", name,
                         (double)size, (double)n), 0;
    if (codec == 1) {
        if (n < 8 || (cs = rd64(d)) > n - 8)
            return error_set(e, NULL, 0, "truncated: grid \"%s\"'s ZIP block", name), 0;
        if (size / 1100 > cs)                     /* deflate expands at most 1032:1 */
            return error_set(e, NULL, 0, "grid \"%s\": %.0f ZIP bytes cannot hold %.0f bytes", name,
                             (double)cs, (double)size), 0;
    }
    g->buf = (unsigned char *)malloc((size_t)size);
    if (!g->buf) return error_set(e, NULL, 0, "out of memory"), 0;
    g->size = (size_t)size;
    if (codec == 0) memcpy(g->buf, d, (size_t)size);
    else if ((why = zlib_inflate(d + 8, (size_t)cs, g->buf, (size_t)size)) != NULL)
        return error_set(e, NULL, 0, "grid \"%s\": ZIP: %s", name, why), 0;
    return parse_grid(g, name, e);
}

/* Segment header at d[0 .. n): the codec, the grid count; 0 and the error when it
   is no NanoVDB 32 header. */
static int segment_header(const unsigned char *d, size_t n, unsigned *codec, unsigned *count, Error *e)
{
    uint32_t v;
    if (n < NVDB_HEADER) return error_set(e, NULL, 0, "truncated: a segment header needs 16 bytes"), 0;
    if (rd64(d) == 0x4E616E6F56444230ULL)
        return error_set(e, NULL, 0, "a NanoVDB file with reversed endianness"), 0;
    if (n >= 8 && memcmp(d, "NanoVDB", 7) == 0 && d[7] != '0')
        return error_set(e, NULL, 0, "a NanoVDB file of a later format (magic \"NanoVDB%c\"); only "
                         "\"NanoVDB0\" files (NanoVDB 32.3, pbrt-v4's) are read", d[7] >= 0x20 &&
                         d[7] < 0x7F ? d[7] : '?'), 0;
    if (rd64(d) != 0x304244566F6E614EULL)
        return error_set(e, NULL, 0, "not a NanoVDB file (no \"NanoVDB0\" magic number)"), 0;
    v = rd32(d + 8);
    if (v >> 21 != NVDB_MAJOR)
        return error_set(e, NULL, 0, "NanoVDB version %u.%u.%u; only major version 32 is read "
                         "(the NanoVDB of pbrt-v4)", (unsigned)(v >> 21), (unsigned)((v >> 10) & 2047),
                         (unsigned)(v & 1023)), 0;
    *count = d[12] | (unsigned)d[13] << 8;
    *codec = d[14] | (unsigned)d[15] << 8;
    return 1;
}

/* The metadata of the segment at d[0 .. n) scanned for gridname: *gi its index
   (-1: not there), *data where the grids' data starts. */
static int segment_find(const unsigned char *d, size_t n, unsigned count, const char *gridname,
                        long *gi, size_t *data, uint64_t *size, Error *e)
{
    size_t at = NVDB_HEADER, len = strlen(gridname);
    unsigned i;
    *gi = -1;
    for (i = 0; i < count; i++) {
        uint32_t ns;
        if (n - at < NVDB_META || (ns = rd32(d + at + 136)) > n - at - NVDB_META)
            return error_set(e, NULL, 0, "truncated: grid metadata"), 0;
        if (*gi < 0 && ns > len && memcmp(d + at + NVDB_META, gridname, len + 1) == 0) {
            *gi = (long)i;
            *size = rd64(d + at);
        }
        at += NVDB_META + ns;
    }
    *data = at;
    return 1;
}

static int read_memory(const unsigned char *d, size_t n, const char *gridname, NanoGrid *g, Error *e)
{
    size_t pos = 0;
    if (n == 0) return error_set(e, NULL, 0, "empty file (not a NanoVDB file)"), 0;
    while (pos < n) {
        unsigned codec, count, i;
        long gi;
        size_t data, meta = NVDB_HEADER;
        uint64_t size = 0;
        if (!segment_header(d + pos, n - pos, &codec, &count, e) ||
            !segment_find(d + pos, n - pos, count, gridname, &gi, &data, &size, e))
            return 0;
        for (i = 0; i < count; i++) {
            uint64_t fs = rd64(d + pos + meta + 8);   /* the grid's bytes on disk */
            meta += NVDB_META + rd32(d + pos + meta + 136);
            if (gi == (long)i) {
                if (codec == 2)
                    return error_set(e, NULL, 0, "grid \"%s\" is BLOSC-compressed; only uncompressed "
                                     "and ZIP grids are read", gridname), 0;
                if (codec > 2)
                    return error_set(e, NULL, 0, "grid \"%s\": unknown codec %u", gridname, codec), 0;
                return grid_bytes(d + pos + data, n - pos - data, size, codec, gridname, g, e);
            }
            if (fs > n - pos - data) return error_set(e, NULL, 0, "truncated: grid data"), 0;
            data += (size_t)fs;
        }
        pos += data;
    }
    return 1;                                     /* not in the file */
}

int nanovdb_read_memory(const unsigned char *d, size_t n, const char *name, const char *gridname,
                        NanoGrid *g, Error *e)
{
    Error inner;
    memset(g, 0, sizeof *g);
    if (read_memory(d, n, gridname, g, &inner)) return 1;
    nanovdb_free(g);
    error_set(e, name, 0, "%s", inner.msg);
    return 0;
}

int nanovdb_read(const char *path, const char *gridname, NanoGrid *g, Error *e)
{
    ReadStatus rs;
    size_t n;
    unsigned char *d = (unsigned char *)read_whole_file(path, 0, NULL, &n, &rs);
    int ok;
    memset(g, 0, sizeof *g);
    if (!d) {
        error_set(e, path, 0, "%s", rs == READ_OPEN ? "cannot read file" : read_status_text(rs));
        return 0;
    }
    ok = nanovdb_read_memory(d, n, path, gridname, g, e);
    free(d);
    return ok;
}

void nanovdb_free(NanoGrid *g)
{
    free(g->buf);
    free(g->keys);
    free(g->tiles);
    memset(g, 0, sizeof *g);
}
