/* util.c - the small mathematics every other file leans on.

   Implements (declared in specnee.h section 2 and 3):
   - Xform: 4x4 affine transforms with their inverses, built the way pbrt-v4's
     scene directives build them (Translate, Scale, Rotate about an axis, LookAt).
     Points transform as p' = M p, vectors by the upper 3x3 part, normals by the
     inverse transpose (so they stay perpendicular to transformed surfaces).
   - LookAt (pbrt-v4, left-handed): dir = normalize(look - eye),
     right = normalize(cross(normalize(up), dir)), newUp = cross(dir, right);
     the camera-to-world matrix has columns (right, newUp, dir, eye) and LookAt
     returns its inverse, world-to-camera.
   - Rotate(theta, axis): Rodrigues' rotation formula.
   - PCG32 random numbers (O'Neill 2014, "PCG: A Family of Simple Fast
     Space-Efficient Statistically Good Algorithms for Random Number Generation"):
     state' = state * 6364136223846793005 + inc, output = rotate(xorshift(state)).
     Streams are keyed by work item (pixel, sample), never by thread.
   - hash_u64 (defined inline in specnee.h): a 64-bit finaliser (the "splitmix64"
     mixing constants of Steele, Lea, Flood 2014) to turn keys into well-spread seeds.
   - radical_inverse: Halton points (van der Corput in base b) for tables built
     from deterministic sample points (the spatial light distribution).
   - cdf_guide_size, cdf_guide (cdf_cell in specnee.h): the inverse of a tabulated CDF through a guide table
     (the wavelength pdf, the pixel filter's table).
   - frame_from_normal: an orthonormal basis around n (Duff et al. 2017,
     "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
   - error_set: formats the one-line "file:line: problem" messages (bytes that
     are not printable text are escaped as \xNN).
   - read_whole_file: a whole file into memory, at most READ_MAX_BYTES, refusing
     (for text) NUL bytes and gzip data as soon as they are read (gzip data is
     returned compressed when asked for: png.c's read_whole_file_gz decompresses
     it); read_status_text says why it refused. */
#include "specnee.h"
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---------- transforms ---------- */

static void mat_identity(double m[4][4])
{
    int i, j;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) m[i][j] = (i == j) ? 1.0 : 0.0;
}

static void mat_mul(double a[4][4], double b[4][4], double r[4][4])
{
    int i, j, k;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) {
            double s = 0.0;
            for (k = 0; k < 4; k++) s += a[i][k] * b[k][j];
            r[i][j] = s;
        }
}

/* Gauss-Jordan inversion with partial pivoting; returns 0 if singular. */
static int mat_inverse(double m[4][4], double inv[4][4])
{
    double a[4][8];
    int i, j, k;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) { a[i][j] = m[i][j]; a[i][j + 4] = (i == j) ? 1.0 : 0.0; }
    for (i = 0; i < 4; i++) {
        int piv = i;
        double big = fabs(a[i][i]);
        for (k = i + 1; k < 4; k++)
            if (fabs(a[k][i]) > big) { big = fabs(a[k][i]); piv = k; }
        if (!(big > 1e-300)) return 0;
        if (piv != i)
            for (j = 0; j < 8; j++) { double t = a[i][j]; a[i][j] = a[piv][j]; a[piv][j] = t; }
        {
            double d = 1.0 / a[i][i];
            for (j = 0; j < 8; j++) a[i][j] *= d;
        }
        for (k = 0; k < 4; k++) {
            double f;
            if (k == i) continue;
            f = a[k][i];
            if (f != 0.0)
                for (j = 0; j < 8; j++) a[k][j] -= f * a[i][j];
        }
    }
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) inv[i][j] = a[i][j + 4];
    return 1;
}

Xform xf_identity(void)
{
    Xform t;
    mat_identity(t.m);
    mat_identity(t.inv);
    return t;
}

Xform xf_mul(const Xform *a, const Xform *b)
{
    Xform r, ca = *a, cb = *b;        /* copies: C99 cannot pass const 2-D arrays */
    mat_mul(ca.m, cb.m, r.m);
    mat_mul(cb.inv, ca.inv, r.inv);   /* (AB)^-1 = B^-1 A^-1 */
    return r;
}

Xform xf_translate(double x, double y, double z)
{
    Xform t = xf_identity();
    t.m[0][3] = x;  t.m[1][3] = y;  t.m[2][3] = z;
    t.inv[0][3] = -x; t.inv[1][3] = -y; t.inv[2][3] = -z;
    return t;
}

/* A zero scale factor makes the transform singular; the parser rejects it first. */
Xform xf_scale(double x, double y, double z)
{
    Xform t = xf_identity();
    t.m[0][0] = x; t.m[1][1] = y; t.m[2][2] = z;
    t.inv[0][0] = 1.0 / x; t.inv[1][1] = 1.0 / y; t.inv[2][2] = 1.0 / z;
    return t;
}

/* Rotation by deg degrees about axis (x,y,z) (Rodrigues); the inverse of a
   rotation is its transpose.  A zero axis gives the identity. */
Xform xf_rotate(double deg, double x, double y, double z)
{
    Xform t = xf_identity();
    double len = sqrt(x * x + y * y + z * z), th, s, c;
    int i, j;
    if (!(len > 0.0)) return t;
    x /= len; y /= len; z /= len;
    th = deg * (SPECNEE_PI / 180.0);
    s = sin(th); c = cos(th);
    t.m[0][0] = x * x + (1 - x * x) * c;
    t.m[0][1] = x * y * (1 - c) - z * s;
    t.m[0][2] = x * z * (1 - c) + y * s;
    t.m[1][0] = x * y * (1 - c) + z * s;
    t.m[1][1] = y * y + (1 - y * y) * c;
    t.m[1][2] = y * z * (1 - c) - x * s;
    t.m[2][0] = x * z * (1 - c) - y * s;
    t.m[2][1] = y * z * (1 - c) + x * s;
    t.m[2][2] = z * z + (1 - z * z) * c;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) t.inv[i][j] = t.m[j][i];
    return t;
}

int xf_lookat(double ex, double ey, double ez, double lx, double ly, double lz,
              double ux, double uy, double uz, Xform *out)
{
    double d[3], up[3], r[3], nu[3], len;
    double cam_to_world[4][4];
    d[0] = lx - ex; d[1] = ly - ey; d[2] = lz - ez;
    len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 0.0)) return 0;
    d[0] /= len; d[1] /= len; d[2] /= len;
    len = sqrt(ux * ux + uy * uy + uz * uz);
    if (!(len > 0.0)) return 0;
    up[0] = ux / len; up[1] = uy / len; up[2] = uz / len;
    /* right = cross(up, dir): pbrt's left-handed camera frame */
    r[0] = up[1] * d[2] - up[2] * d[1];
    r[1] = up[2] * d[0] - up[0] * d[2];
    r[2] = up[0] * d[1] - up[1] * d[0];
    len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(len > 1e-12)) return 0;             /* up parallel to the view direction */
    r[0] /= len; r[1] /= len; r[2] /= len;
    nu[0] = d[1] * r[2] - d[2] * r[1];          /* newUp = cross(dir, right) */
    nu[1] = d[2] * r[0] - d[0] * r[2];
    nu[2] = d[0] * r[1] - d[1] * r[0];
    mat_identity(cam_to_world);
    cam_to_world[0][0] = r[0]; cam_to_world[1][0] = r[1]; cam_to_world[2][0] = r[2];
    cam_to_world[0][1] = nu[0]; cam_to_world[1][1] = nu[1]; cam_to_world[2][1] = nu[2];
    cam_to_world[0][2] = d[0]; cam_to_world[1][2] = d[1]; cam_to_world[2][2] = d[2];
    cam_to_world[0][3] = ex; cam_to_world[1][3] = ey; cam_to_world[2][3] = ez;
    memcpy(out->inv, cam_to_world, sizeof cam_to_world);
    return mat_inverse(cam_to_world, out->m);
}

int xf_from_matrix(double m[4][4], Xform *out)
{
    memcpy(out->m, m, sizeof out->m);
    return mat_inverse(m, out->inv);
}

Vec3 xf_point(const Xform *t, Vec3 p)
{
    double x = t->m[0][0] * p.x + t->m[0][1] * p.y + t->m[0][2] * p.z + t->m[0][3];
    double y = t->m[1][0] * p.x + t->m[1][1] * p.y + t->m[1][2] * p.z + t->m[1][3];
    double z = t->m[2][0] * p.x + t->m[2][1] * p.y + t->m[2][2] * p.z + t->m[2][3];
    double w = t->m[3][0] * p.x + t->m[3][1] * p.y + t->m[3][2] * p.z + t->m[3][3];
    if (w != 1.0 && w != 0.0) { x /= w; y /= w; z /= w; }
    return v3((float)x, (float)y, (float)z);
}

Vec3 xf_vector(const Xform *t, Vec3 v)
{
    return v3((float)(t->m[0][0] * v.x + t->m[0][1] * v.y + t->m[0][2] * v.z),
              (float)(t->m[1][0] * v.x + t->m[1][1] * v.y + t->m[1][2] * v.z),
              (float)(t->m[2][0] * v.x + t->m[2][1] * v.y + t->m[2][2] * v.z));
}

/* n' = (M^-1)^T n */
Vec3 xf_normal(const Xform *t, Vec3 n)
{
    return v3((float)(t->inv[0][0] * n.x + t->inv[1][0] * n.y + t->inv[2][0] * n.z),
              (float)(t->inv[0][1] * n.x + t->inv[1][1] * n.y + t->inv[2][1] * n.z),
              (float)(t->inv[0][2] * n.x + t->inv[1][2] * n.y + t->inv[2][2] * n.z));
}

int xf_swaps_handedness(const Xform *t)
{
    const double (*m)[4] = t->m;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
               - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
               + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return det < 0.0;
}

/* ---------- frames ---------- */

Frame frame_from_normal(Vec3 n)
{
    Frame f;
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    f.s = v3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = v3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

/* ---------- random numbers ---------- */


void rng_seed(Rng *r, uint64_t stream, uint64_t index)
{
    r->state = 0u;
    r->inc = (stream << 1u) | 1u;           /* the stream selects the increment */
    rng_u32(r);
    r->state += hash_u64(index, stream);    /* the index selects the start */
    rng_u32(r);
}

uint32_t rng_u32(Rng *r)
{
    uint64_t old = r->state;
    uint32_t xorshifted, rot;
    r->state = old * 6364136223846793005ull + r->inc;
    xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

/* 24 random bits scaled by 2^-24: exactly representable, strictly below 1. */
float rng_float(Rng *r)
{
    return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f);
}

double radical_inverse(int base, uint64_t i)
{
    double inv_base = 1.0 / base, f = inv_base, r = 0.0;
    while (i > 0) {
        r += (double)(i % (uint64_t)base) * f;
        i /= (uint64_t)base;
        f *= inv_base;
    }
    return r;
}

/* ---------- guide tables ---------- */

/* Inverse-CDF sampling of a table of n cells finds the cell k with
   cdf[k] <= u < cdf[k + 1]; it is unique, as cdf[] never decreases (cdf[0] = 0,
   cdf[n] = 1).  A binary search over all n cells takes log2 n steps that the
   processor cannot predict.  A GUIDE TABLE (Chen and Asau 1974, "On generating
   random variates from an empirical distribution", AIIE Transactions 6(2)) keeps,
   for each of the m + 1 steps g / m of u, the last cell whose cdf[k] <= g / m:
   the cell of u in [g / m, (g + 1) / m) lies between guide[g] and guide[g + 1].
   With m a power of two, u * m and g / m are exact in double, so g = (int)(u m)
   obeys g / m <= u < (g + 1) / m to the last bit and the bracket needs no
   widening; with m >= 4 n (cdf_guide_size) it holds one or two cells nearly
   always, so the search (cdf_cell, specnee.h) costs a table read and a compare
   or two: O(1).  The guide only narrows the search, so the cell, and every
   number drawn from it, is the one the full search finds. */
int cdf_guide_size(int n)
{
    int m = 1;
    while (m < 4 * n && m < (1 << 24)) m *= 2;
    return m;
}

void cdf_guide(const float *cdf, int n, int *guide, int m)
{
    int g, k = 0;
    for (g = 0; g <= m; g++) {
        double edge = (double)g / m;
        while (k + 1 < n && (double)cdf[k + 1] <= edge) k++;
        guide[g] = k;
    }
}

/* ---------- errors ---------- */

/* Length of the valid UTF-8 sequence at p (at most n bytes), 0 if there is none.
   Used to print non-ASCII file names as they are and anything else escaped. */
static size_t utf8_len(const unsigned char *p, size_t n)
{
    size_t len, i;
    if (p[0] < 0x80) return 1;
    if (p[0] >= 0xC2 && p[0] <= 0xDF) len = 2;
    else if (p[0] >= 0xE0 && p[0] <= 0xEF) len = 3;
    else if (p[0] >= 0xF0 && p[0] <= 0xF4) len = 4;
    else return 0;
    if (len > n) return 0;
    for (i = 1; i < len; i++)
        if ((p[i] & 0xC0) != 0x80) return 0;
    return len;
}

void error_set(Error *e, const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    char raw[sizeof e->msg];
    size_t i, o = 0, n;
    int k = 0;
    if (!e) return;
    if (file && line > 0) k = snprintf(raw, sizeof raw, "%s:%d: ", file, line);
    else if (file) k = snprintf(raw, sizeof raw, "%s: ", file);
    if (k < 0 || k >= (int)sizeof raw) k = 0;
    va_start(ap, fmt);
    vsnprintf(raw + k, sizeof raw - (size_t)k, fmt, ap);
    va_end(ap);
    /* One printable line whatever the input held: control bytes (line breaks
       included) and bytes that are not UTF-8 are written as \xNN, so a binary
       file named as a scene never sends raw bytes to the terminal. */
    n = strlen(raw);
    for (i = 0; i < n;) {
        const unsigned char *c = (const unsigned char *)raw + i;
        size_t len = (*c < 0x20 || *c == 0x7F) ? 0 : utf8_len(c, n - i);
        if (len == 0) {
            if (o + 4 >= sizeof e->msg) break;
            snprintf(e->msg + o, 5, "\\x%02X", *c);
            o += 4;
            i++;
        } else {
            if (o + len >= sizeof e->msg) break;
            memcpy(e->msg + o, c, len);
            o += len;
            i += len;
        }
    }
    e->msg[o] = '\0';
}

/* ---------- reading whole files ---------- */

const char *read_status_text(ReadStatus st)
{
    switch (st) {
    case READ_OK: return "ok";
    case READ_OPEN: return "cannot open the file";
    case READ_IO: return "read error";
    case READ_NOMEM: return "out of memory";
    case READ_TOO_BIG: return "file larger than 1 GiB (READ_MAX_BYTES)";
    case READ_GZIP: return "a gzip-compressed file: compressed files are not in the specnee "
                           "subset (decompress it first, e.g. gunzip -k FILE.gz, and name "
                           "the result)";
    case READ_NUL: return "not a text file (it contains NUL bytes)";
    case READ_MAGIC: return "not the expected file format (wrong first bytes)";
    case READ_GZ_TRUNC: return "gzip: truncated compressed data";
    case READ_GZ_HEADER: return "gzip: bad member header (not deflate, reserved flag bits set, "
                                "or bytes after a member that are not a gzip member)";
    case READ_GZ_DATA: return "gzip: corrupt deflate data";
    case READ_GZ_CRC: return "gzip: CRC-32 mismatch (corrupt data)";
    case READ_GZ_SIZE: return "gzip: ISIZE mismatch (corrupt data)";
    case READ_GZ_BIG: return "gzip: uncompressed data larger than 1 GiB (READ_MAX_BYTES)";
    }
    return "?";
}

char *read_whole_file(const char *path, int flags, const char *magic, size_t *len,
                      ReadStatus *st)
{
    size_t nm = magic ? strlen(magic) : 0;
    int text = flags & READ_TEXT, gz = 0;
    FILE *f;
    char *buf = NULL;
    size_t n = 0, cap = 0;
    *len = 0;
    *st = READ_OK;
    f = fopen(path, "rb");
    if (!f) { *st = READ_OPEN; return NULL; }
    for (;;) {
        size_t got;
        if (cap - n < 4096) {
            char *nb;
            size_t ncap = cap ? 2 * cap : 65536;
            if (cap >= READ_MAX_BYTES) { *st = READ_TOO_BIG; break; }
            if (ncap > READ_MAX_BYTES) ncap = READ_MAX_BYTES;
            nb = (char *)realloc(buf, ncap + 1);
            if (!nb) { *st = READ_NOMEM; break; }
            buf = nb;
            cap = ncap;
        }
        got = fread(buf + n, 1, cap - n, f);
        /* what the first bytes say is checked as soon as they arrive, so that
           /dev/zero or a compressed file is refused without reading it whole */
        if (n < 2 && n + got >= 2 && (unsigned char)buf[0] == 0x1F
            && (unsigned char)buf[1] == 0x8B) {
            if (!(flags & READ_GUNZIP)) { *st = READ_GZIP; break; }
            gz = 1;                    /* returned as it is: png.c decompresses and checks it */
        }
        if (!gz && n < nm && n + got >= nm && memcmp(buf, magic, nm) != 0) { *st = READ_MAGIC; break; }
        if (!gz && text && memchr(buf + n, '\0', got)) { *st = READ_NUL; break; }
        n += got;
        if (got == 0) {
            if (ferror(f)) *st = READ_IO;
            else if (n < nm && !gz) *st = READ_MAGIC;
            break;
        }
    }
    fclose(f);
    if (*st != READ_OK) { free(buf); return NULL; }
    if (!buf && !(buf = (char *)malloc(1))) { *st = READ_NOMEM; return NULL; }
    buf[n] = '\0';
    *len = n;
    return buf;
}
