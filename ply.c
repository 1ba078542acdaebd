/* ply.c - reads and writes PLY meshes of triangles and quads (Shape "plymesh").

   WHAT IT IMPLEMENTS
     ply_read          ascii, binary_little_endian and binary_big_endian PLY files
     ply_free          releases a PlyMesh
     ply_write_binary  binary little-endian: float x y z, list uchar int vertex_indices

   THE FORMAT (Greg Turk, "The PLY Polygon File Format", 1994; Paul Bourke's copy)
     ply
     format ascii 1.0                  (or binary_little_endian / binary_big_endian)
     comment ...                       (comment and obj_info lines are ignored)
     element vertex 8
     property float x                  (scalar: char uchar short ushort int uint float
     property float y                   double, or int8 uint8 int16 uint16 int32 uint32
     property float z                   float32 float64)
     element face 6
     property list uchar int vertex_indices
     end_header
     <data: elements in header order, properties in declared order>

   WHAT IS READ (the subset pbrt-v4 reads, docs/conventions.md)
     - element vertex: x y z (required), nx ny nz (optional, all three or none), u v
       (or s t, texture_u texture_v, texture_s texture_t: optional, both or none); any
       other property (colours, lists, ...) is read and skipped by its type.
     - element face: list vertex_indices (or vertex_index) with an integer count and
       integer indices; a triangle goes to PlyMesh.idx, a quad to PlyMesh.quads as
       a bilinear patch (pbrt-v4's meaning, patch.c); any other vertex count is an
       error.  A quad face (f0, f1, f2, f3) goes round its boundary, and a patch's
       corners p00 p10 p01 p11 go p00 -> p10 -> p11 -> p01 round it, so the patch
       is (p00, p10, p01, p11) = (f0, f1, f3, f2): the order pbrt-v4's reader
       stores (TriQuadMesh::ReadPLY).  Other face properties (face_indices, ...)
       are skipped.
     - any other element is skipped.

   ERRORS: "path:line: problem", and ply_read returns 0 (never exits, never crashes).
     Header problems give the header line.  Data problems give, for ascii files, the
     line of the offending value, and for binary files the header line of the element
     being read (a binary file has no lines).  Element counts are checked against the
     bytes left in the file before anything is allocated, so a count of 10^12 is an
     error, not a huge malloc: with files of at most READ_MAX_BYTES (1 GiB) the mesh
     then takes at most 3.5 GiB (12 bytes a face for the triangles' array, and 16
     for the quads' array, made at the first quad: 28 bytes a face of at least 8
     bytes), within MEM_BUDGET_MIB.  The file is read whole (read_whole_file_gz): a file that does not
     start with "ply" (/dev/zero) is refused at once; gzip data (.ply.gz) is decompressed first.  Coordinates and normals must be finite; indices must lie
     in [0, vertex count).

   USE
     geometry.c: ply_read(path, &mesh, &err), copy mesh.P / mesh.N / mesh.UV with
     mesh.idx (a triangle mesh) and mesh.quads (a bilinear patch mesh) into the
     Scene (transforming them), ply_free(&mesh).  tools/bench.c writes its mesh with
     ply_write_binary.
*/
#include "specnee.h"
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#define PLY_MAX_ELEMENTS 16      /* limits of this reader, reported as errors */
#define PLY_MAX_PROPS 32
#define PLY_NAME 64

typedef enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } PlyType;

typedef struct {
    char name[PLY_NAME];
    PlyType type;                /* scalar type, or the item type of a list */
    PlyType count_type;          /* list: type of the count; T_NONE for a scalar */
} PlyProp;

typedef struct {
    char name[PLY_NAME];
    long count;
    int line;                    /* header line of "element" */
    int n_props;
    PlyProp props[PLY_MAX_PROPS];
} PlyElement;

typedef enum { FMT_ASCII, FMT_BINARY_LE, FMT_BINARY_BE } PlyFormat;

/* The whole file in memory plus a cursor. */
typedef struct {
    const char *path;
    Error *err;
    unsigned char *data;         /* size + 1 bytes, NUL terminated */
    size_t size, pos;
    PlyFormat format;
    int line;                    /* ascii: current data line */
    int elem_line;               /* binary: header line of the element being read */
} Reader;

/* ---------------------------------------------------------------------------
   Types
   --------------------------------------------------------------------------- */
static PlyType type_from_name(const char *s)
{
    static const struct { const char *name; PlyType t; } names[] = {
        {"char", T_I8}, {"int8", T_I8}, {"uchar", T_U8}, {"uint8", T_U8},
        {"short", T_I16}, {"int16", T_I16}, {"ushort", T_U16}, {"uint16", T_U16},
        {"int", T_I32}, {"int32", T_I32}, {"uint", T_U32}, {"uint32", T_U32},
        {"float", T_F32}, {"float32", T_F32}, {"double", T_F64}, {"float64", T_F64}
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(s, names[i].name) == 0) return names[i].t;
    return T_NONE;
}

static size_t type_size(PlyType t)
{
    switch (t) {
    case T_I8: case T_U8: return 1;
    case T_I16: case T_U16: return 2;
    case T_I32: case T_U32: case T_F32: return 4;
    case T_F64: return 8;
    default: return 0;
    }
}

static int type_is_int(PlyType t) { return t != T_NONE && t != T_F32 && t != T_F64; }

/* ---------------------------------------------------------------------------
   Reading one value (binary or ascii) as a double
   --------------------------------------------------------------------------- */
static int data_line(const Reader *rd)
{
    return rd->format == FMT_ASCII ? rd->line : rd->elem_line;
}

/* Decode an unsigned integer of n bytes in the file's byte order. */
static uint64_t read_uint(const Reader *rd, const unsigned char *p, size_t n)
{
    uint64_t v = 0;
    size_t i;
    if (rd->format == FMT_BINARY_LE)
        for (i = n; i-- > 0;) v = (v << 8) | p[i];
    else
        for (i = 0; i < n; i++) v = (v << 8) | p[i];
    return v;
}

static int read_binary(Reader *rd, PlyType t, const char *what, double *out)
{
    size_t n = type_size(t);
    const unsigned char *p;
    uint64_t u;
    if (rd->size - rd->pos < n) {
        error_set(rd->err, rd->path, data_line(rd), "truncated file: %s ends early", what);
        return 0;
    }
    p = rd->data + rd->pos;
    rd->pos += n;
    u = read_uint(rd, p, n);
    switch (t) {
    case T_I8:  *out = (double)(int8_t)(uint8_t)u; break;
    case T_U8:  *out = (double)u; break;
    case T_I16: *out = u >= 0x8000u ? (double)u - 65536.0 : (double)u; break;
    case T_U16: *out = (double)u; break;
    case T_I32: *out = u >= 0x80000000u ? (double)u - 4294967296.0 : (double)u; break;
    case T_U32: *out = (double)u; break;
    case T_F32: { uint32_t w = (uint32_t)u; float f; memcpy(&f, &w, 4); *out = f; break; }
    case T_F64: { double d; memcpy(&d, &u, 8); *out = d; break; } /* host int and double
                                                                       share a byte order */
    default: *out = 0; break;
    }
    return 1;
}

static int is_space(int c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

static int read_ascii(Reader *rd, PlyType t, const char *what, double *out)
{
    char tok[80], *end;
    size_t n = 0;
    /* skip white space, counting lines */
    while (rd->pos < rd->size && is_space(rd->data[rd->pos])) {
        if (rd->data[rd->pos] == '\n') rd->line++;
        rd->pos++;
    }
    if (rd->pos >= rd->size) {
        error_set(rd->err, rd->path, rd->line, "truncated file: %s ends early", what);
        return 0;
    }
    while (rd->pos < rd->size && !is_space(rd->data[rd->pos])) {
        if (n + 1 >= sizeof tok) {
            error_set(rd->err, rd->path, rd->line, "bad number in %s (token too long)", what);
            return 0;
        }
        tok[n++] = (char)rd->data[rd->pos++];
    }
    tok[n] = '\0';
    /* strtod for every type: a long may be too narrow for a uint32 */
    *out = strtod(tok, &end);
    if (end == tok || *end != '\0') {
        error_set(rd->err, rd->path, rd->line, "bad number '%s' in %s", tok, what);
        return 0;
    }
    if (type_is_int(t) && *out != floor(*out)) {
        error_set(rd->err, rd->path, rd->line, "bad integer '%s' in %s", tok, what);
        return 0;
    }
    return 1;
}

/* Read one value of type t; integer types are range checked. */
static int read_value(Reader *rd, PlyType t, const char *what, double *out)
{
    static const double lo[] = {0, -128, 0, -32768, 0, -2147483648.0, 0, 0, 0};
    static const double hi[] = {0, 127, 255, 32767, 65535, 2147483647.0, 4294967295.0, 0, 0};
    if (!(rd->format == FMT_ASCII ? read_ascii(rd, t, what, out)
                                  : read_binary(rd, t, what, out)))
        return 0;
    if (type_is_int(t) && (*out < lo[t] || *out > hi[t])) {
        error_set(rd->err, rd->path, data_line(rd), "%s: %.0f is out of range for its type",
                  what, *out);
        return 0;
    }
    return 1;
}

/* Skip one property (scalar or whole list) of an element. */
static int skip_prop(Reader *rd, const PlyProp *pr)
{
    double v;
    long n, i;
    if (pr->count_type == T_NONE) return read_value(rd, pr->type, pr->name, &v);
    if (!read_value(rd, pr->count_type, pr->name, &v)) return 0;
    if (v < 0) {
        error_set(rd->err, rd->path, data_line(rd), "negative list count in %s", pr->name);
        return 0;
    }
    n = (long)v;                               /* v <= 2^32 - 1: the count type is checked */
    if (rd->format != FMT_ASCII) {             /* binary: jump over the items */
        size_t bytes = (size_t)n * type_size(pr->type);
        if ((size_t)n > (rd->size - rd->pos) / type_size(pr->type) ||
            rd->size - rd->pos < bytes) {
            error_set(rd->err, rd->path, data_line(rd), "truncated file: %s ends early",
                      pr->name);
            return 0;
        }
        rd->pos += bytes;
        return 1;
    }
    for (i = 0; i < n; i++)                    /* ascii: each item ends in >= 1 byte */
        if (!read_value(rd, pr->type, pr->name, &v)) return 0;
    return 1;
}

/* ---------------------------------------------------------------------------
   Header
   --------------------------------------------------------------------------- */
/* Split a line into at most max white-space separated words (in place). */
static int split_words(char *s, char **w, int max)
{
    int n = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t') s++;
        if (!*s) return n;
        if (n == max) return max + 1;          /* too many words */
        w[n++] = s;
        while (*s && *s != ' ' && *s != '\t') s++;
        if (*s) *s++ = '\0';
    }
}

/* Header line "element NAME COUNT" (w[0..nw-1]): a new element. */
static int header_element(Reader *rd, PlyElement *el, int *n_el, char **w, int nw, int line)
{
    PlyElement *e;
    char *end;
    long count;
    int i;
    if (nw != 3) {
        error_set(rd->err, rd->path, line, "corrupt header: expected 'element <name> <count>'");
        return 0;
    }
    if (*n_el == PLY_MAX_ELEMENTS) {
        error_set(rd->err, rd->path, line, "too many elements (at most %d)", PLY_MAX_ELEMENTS);
        return 0;
    }
    count = strtol(w[2], &end, 10);
    if (end == w[2] || *end != '\0') {
        error_set(rd->err, rd->path, line, "bad element count '%s'", w[2]);
        return 0;
    }
    if (count < 0) {
        error_set(rd->err, rd->path, line, "negative element count %ld", count);
        return 0;
    }
    if (strlen(w[1]) >= PLY_NAME) {
        error_set(rd->err, rd->path, line, "element name too long");
        return 0;
    }
    for (i = 0; i < *n_el; i++)
        if (strcmp(el[i].name, w[1]) == 0) {
            error_set(rd->err, rd->path, line, "duplicate element '%s'", w[1]);
            return 0;
        }
    e = &el[(*n_el)++];
    memset(e, 0, sizeof *e);
    strcpy(e->name, w[1]);
    e->count = count;
    e->line = line;
    return 1;
}

/* Header line "property TYPE NAME" or "property list CTYPE TYPE NAME": a
   property of the last element. */
static int header_property(Reader *rd, PlyElement *el, int n_el, char **w, int nw, int line)
{
    PlyElement *e;
    PlyProp *pr;
    const char *name;
    int i;
    if (n_el == 0) {
        error_set(rd->err, rd->path, line, "corrupt header: property before any element");
        return 0;
    }
    e = &el[n_el - 1];
    if (e->n_props == PLY_MAX_PROPS) {
        error_set(rd->err, rd->path, line, "too many properties (at most %d)", PLY_MAX_PROPS);
        return 0;
    }
    pr = &e->props[e->n_props];
    if (nw == 3 && strcmp(w[1], "list") != 0) {
        pr->count_type = T_NONE;
        pr->type = type_from_name(w[1]);
        name = w[2];
        if (pr->type == T_NONE) {
            error_set(rd->err, rd->path, line, "unknown property type '%s'", w[1]);
            return 0;
        }
    } else if (nw == 5 && strcmp(w[1], "list") == 0) {
        pr->count_type = type_from_name(w[2]);
        pr->type = type_from_name(w[3]);
        name = w[4];
        if (pr->type == T_NONE || pr->count_type == T_NONE) {
            error_set(rd->err, rd->path, line, "unknown property type in list '%s'", w[4]);
            return 0;
        }
        if (!type_is_int(pr->count_type)) {
            error_set(rd->err, rd->path, line, "list count type of '%s' must be an integer", w[4]);
            return 0;
        }
    } else {
        error_set(rd->err, rd->path, line,
                  "corrupt header: expected 'property <type> <name>' or "
                  "'property list <type> <type> <name>'");
        return 0;
    }
    if (strlen(name) >= PLY_NAME) {
        error_set(rd->err, rd->path, line, "property name too long");
        return 0;
    }
    for (i = 0; i < e->n_props; i++)
        if (strcmp(e->props[i].name, name) == 0) {
            error_set(rd->err, rd->path, line, "duplicate property '%s'", name);
            return 0;
        }
    strcpy(pr->name, name);
    e->n_props++;
    return 1;
}

/* Parse the header; fills elements and leaves rd->pos at the first data byte. */
static int parse_header(Reader *rd, PlyElement *el, int *n_el, int *end_line)
{
    int line = 0, have_format = 0;
    *n_el = 0;
    for (;;) {
        char buf[256], *w[8];
        size_t start = rd->pos, len;
        int nw;
        const unsigned char *nl;
        if (rd->pos >= rd->size) {
            error_set(rd->err, rd->path, line > 0 ? line : 1,
                      line > 0 ? "corrupt header: no end_header" : "not a PLY file (empty)");
            return 0;
        }
        line++;
        nl = (const unsigned char *)memchr(rd->data + start, '\n', rd->size - start);
        len = nl ? (size_t)(nl - (rd->data + start)) : rd->size - start;
        rd->pos = start + len + (nl ? 1 : 0);
        if (len > 0 && rd->data[start + len - 1] == '\r') len--;
        if (memchr(rd->data + start, '\0', len)) {
            error_set(rd->err, rd->path, line, "corrupt header: NUL byte");
            return 0;
        }
        if (line == 1) {
            if (len != 3 || memcmp(rd->data + start, "ply", 3) != 0) {
                error_set(rd->err, rd->path, line, "not a PLY file (no 'ply' magic line)");
                return 0;
            }
            continue;
        }
        if ((len >= 7 && memcmp(rd->data + start, "comment", 7) == 0) ||
            (len >= 8 && memcmp(rd->data + start, "obj_info", 8) == 0))
            continue;                          /* any length, not parsed */
        if (len >= sizeof buf) {
            error_set(rd->err, rd->path, line, "corrupt header: line too long");
            return 0;
        }
        memcpy(buf, rd->data + start, len);
        buf[len] = '\0';
        nw = split_words(buf, w, 6);
        if (nw == 0) continue;                 /* blank line */
        if (strcmp(w[0], "format") == 0) {
            if (nw != 3 || strcmp(w[2], "1.0") != 0) {
                error_set(rd->err, rd->path, line, "corrupt header: expected 'format <type> 1.0'");
                return 0;
            }
            if (strcmp(w[1], "ascii") == 0) rd->format = FMT_ASCII;
            else if (strcmp(w[1], "binary_little_endian") == 0) rd->format = FMT_BINARY_LE;
            else if (strcmp(w[1], "binary_big_endian") == 0) rd->format = FMT_BINARY_BE;
            else {
                error_set(rd->err, rd->path, line, "unknown format '%s'", w[1]);
                return 0;
            }
            have_format = 1;
        } else if (strcmp(w[0], "element") == 0) {
            if (!header_element(rd, el, n_el, w, nw, line)) return 0;
        } else if (strcmp(w[0], "property") == 0) {
            if (!header_property(rd, el, *n_el, w, nw, line)) return 0;
        } else if (strcmp(w[0], "end_header") == 0 && nw == 1) {
            if (!have_format) {
                error_set(rd->err, rd->path, line, "corrupt header: no format line");
                return 0;
            }
            *end_line = line;
            return 1;
        } else {
            error_set(rd->err, rd->path, line, "corrupt header: unknown keyword '%s'", w[0]);
            return 0;
        }
    }
}

static int find_prop(const PlyElement *e, const char *name)
{
    int i;
    for (i = 0; i < e->n_props; i++)
        if (strcmp(e->props[i].name, name) == 0) return i;
    return -1;
}

/* Fewest bytes one row of e can take: binary from the types (a list at least its
   count, and the face's vertex list at least 3 indices), ascii two bytes per value
   (a digit and a separator; the file's very last value may lack the separator,
   which the caller allows for). */
static size_t min_row_bytes(const Reader *rd, const PlyElement *e)
{
    size_t n = 0;
    int i, face = strcmp(e->name, "face") == 0;
    for (i = 0; i < e->n_props; i++) {
        const PlyProp *pr = &e->props[i];
        int items = face && pr->count_type != T_NONE && (!strcmp(pr->name, "vertex_indices")
                    || !strcmp(pr->name, "vertex_index")) ? 3 : 0;
        if (rd->format == FMT_ASCII) n += 2 * (size_t)(1 + items);
        else n += type_size(pr->count_type != T_NONE ? pr->count_type : pr->type)
                + (size_t)items * type_size(pr->type);
    }
    return n;
}

/* ---------------------------------------------------------------------------
   Elements
   --------------------------------------------------------------------------- */
static int read_vertices(Reader *rd, const PlyElement *e, PlyMesh *m)
{
    int ix = find_prop(e, "x"), iy = find_prop(e, "y"), iz = find_prop(e, "z");
    int inx = find_prop(e, "nx"), iny = find_prop(e, "ny"), inz = find_prop(e, "nz");
    int iu = -1, iv = -1, has_uv, names;
    int has_n, slot[PLY_MAX_PROPS], i, k;
    /* texture coordinates under any of the names pbrt-v4's reader accepts */
    static const char *const uv_names[4][2] = {
        { "u", "v" }, { "s", "t" }, { "texture_u", "texture_v" }, { "texture_s", "texture_t" }
    };
    for (names = 0; names < 4 && (iu < 0 || iv < 0); names++) {
        iu = find_prop(e, uv_names[names][0]);
        iv = find_prop(e, uv_names[names][1]);
    }
    has_uv = iu >= 0 && iv >= 0;
    long v;
    if (ix < 0 || iy < 0 || iz < 0) {
        error_set(rd->err, rd->path, e->line, "element vertex lacks property %s",
                  ix < 0 ? "x" : iy < 0 ? "y" : "z");
        return 0;
    }
    has_n = inx >= 0 || iny >= 0 || inz >= 0;
    if (has_n && (inx < 0 || iny < 0 || inz < 0)) {
        error_set(rd->err, rd->path, e->line, "element vertex has only some of nx ny nz");
        return 0;
    }
    /* slot: 0..2 position, 3..5 normal, -1 skipped */
    for (i = 0; i < e->n_props; i++) slot[i] = -1;
    slot[ix] = 0; slot[iy] = 1; slot[iz] = 2;
    if (has_n) { slot[inx] = 3; slot[iny] = 4; slot[inz] = 5; }
    if (has_uv) { slot[iu] = 6; slot[iv] = 7; }
    for (i = 0; i < e->n_props; i++)
        if (slot[i] >= 0 && e->props[i].count_type != T_NONE) {
            error_set(rd->err, rd->path, e->line, "vertex property %s must not be a list",
                      e->props[i].name);
            return 0;
        }
    if (e->count > INT_MAX / 3) {
        error_set(rd->err, rd->path, e->line, "too many vertices (%ld)", e->count);
        return 0;
    }
    m->n_verts = (int)e->count;
    m->P = (float *)malloc(3 * (size_t)e->count * sizeof(float) + 1);
    m->N = has_n ? (float *)malloc(3 * (size_t)e->count * sizeof(float) + 1) : NULL;
    m->UV = has_uv ? (float *)malloc(2 * (size_t)e->count * sizeof(float) + 1) : NULL;
    if (!m->P || (has_n && !m->N) || (has_uv && !m->UV)) {
        error_set(rd->err, rd->path, e->line, "out of memory for %ld vertices", e->count);
        return 0;
    }
    rd->elem_line = e->line;
    for (v = 0; v < e->count; v++) {
        for (i = 0; i < e->n_props; i++) {
            double val;
            if (slot[i] < 0) {
                if (!skip_prop(rd, &e->props[i])) return 0;
                continue;
            }
            if (!read_value(rd, e->props[i].type, e->props[i].name, &val)) return 0;
            if (!isfinite(val) || !isfinite((float)val)) {
                error_set(rd->err, rd->path, data_line(rd),
                          "vertex %ld: %s is not a finite float", v, e->props[i].name);
                return 0;
            }
            k = slot[i];
            if (k < 3) m->P[3 * v + k] = (float)val;
            else if (k < 6) m->N[3 * v + k - 3] = (float)val;
            else m->UV[2 * v + k - 6] = (float)val;
        }
    }
    return 1;
}

/* Face f's n = 3 or 4 indices q (in file order) into m: a triangle as it is, a quad
   as the patch (q0, q1, q3, q2) (the header comment); quads has room for count quads. */
static int store_face(Reader *rd, const PlyElement *e, const int32_t q[4], int n, PlyMesh *m)
{
    int32_t *d;
    if (n == 3) {
        d = m->idx + 3 * (size_t)m->n_tris++;
        d[0] = q[0]; d[1] = q[1]; d[2] = q[2];
        return 1;
    }
    if (!m->quads) {
        m->quads = (int32_t *)malloc(4 * (size_t)e->count * sizeof(int32_t) + 1);
        if (!m->quads) {
            error_set(rd->err, rd->path, e->line, "out of memory for %ld faces", e->count);
            return 0;
        }
    }
    d = m->quads + 4 * (size_t)m->n_quads++;
    d[0] = q[0]; d[1] = q[1]; d[2] = q[3]; d[3] = q[2];    /* p00 p10 p01 p11 */
    return 1;
}

static int read_faces(Reader *rd, const PlyElement *e, long n_verts, PlyMesh *m)
{
    int ilist = find_prop(e, "vertex_indices"), i, k;
    long f;
    if (ilist < 0) ilist = find_prop(e, "vertex_index");
    if (ilist < 0) {
        error_set(rd->err, rd->path, e->line, "element face has no vertex_indices list");
        return 0;
    }
    if (e->props[ilist].count_type == T_NONE || !type_is_int(e->props[ilist].type)) {
        error_set(rd->err, rd->path, e->line, "vertex_indices must be a list of integers");
        return 0;
    }
    if (e->count > INT_MAX / 6) {
        error_set(rd->err, rd->path, e->line, "too many faces (%ld)", e->count);
        return 0;
    }
    m->idx = (int32_t *)malloc(3 * (size_t)e->count * sizeof(int32_t) + 1);
    if (!m->idx) {
        error_set(rd->err, rd->path, e->line, "out of memory for %ld faces", e->count);
        return 0;
    }
    m->n_tris = 0;
    m->n_quads = 0;
    rd->elem_line = e->line;
    for (f = 0; f < e->count; f++) {
        for (i = 0; i < e->n_props; i++) {
            const PlyProp *pr = &e->props[i];
            double val;
            int32_t q[4];
            int n;
            if (i != ilist) {
                if (!skip_prop(rd, pr)) return 0;
                continue;
            }
            if (!read_value(rd, pr->count_type, pr->name, &val)) return 0;
            if (val != 3 && val != 4) {
                error_set(rd->err, rd->path, data_line(rd),
                          "face %ld has %.0f vertices (only triangles and quads)", f, val);
                return 0;
            }
            n = (int)val;
            for (k = 0; k < n; k++) {
                if (!read_value(rd, pr->type, pr->name, &val)) return 0;
                if (val < 0 || val >= (double)n_verts) {
                    error_set(rd->err, rd->path, data_line(rd),
                              "face %ld: vertex index %.0f out of range [0, %ld)", f, val, n_verts);
                    return 0;
                }
                q[k] = (int32_t)val;
            }
            if (!store_face(rd, e, q, n, m)) return 0;
        }
    }
    return 1;
}

void ply_free(PlyMesh *m)
{
    free(m->P);
    free(m->N);
    free(m->UV);
    free(m->idx);
    free(m->quads);
    memset(m, 0, sizeof *m);
}

int ply_read(const char *path, PlyMesh *m, Error *err)
{
    Reader rd;
    PlyElement *el;
    int n_el = 0, end_line = 0, i, ivert = -1, iface = -1, ok = 1;
    ReadStatus rs;

    memset(m, 0, sizeof *m);
    memset(&rd, 0, sizeof rd);
    rd.path = path;
    rd.err = err;
    rd.data = (unsigned char *)read_whole_file_gz(path, 0, "ply", &rd.size, &rs);
    if (!rd.data) {
        if (rs == READ_MAGIC && rd.size == 0)
            error_set(err, path, 1, "not a PLY file (no 'ply' magic line)");
        else
            error_set(err, path, 0, "%s", rs == READ_OPEN ? "cannot read file"
                      : rs == READ_MAGIC ? "not a PLY file (no 'ply' magic line)"
                      : read_status_text(rs));
        return 0;
    }
    el = (PlyElement *)malloc(PLY_MAX_ELEMENTS * sizeof *el);
    if (!el) {
        free(rd.data);
        error_set(err, path, 0, "out of memory");
        return 0;
    }
    if (!parse_header(&rd, el, &n_el, &end_line)) ok = 0;
    rd.line = end_line + 1;

    if (ok) {                                  /* what the header must declare */
        for (i = 0; i < n_el; i++) {
            if (strcmp(el[i].name, "vertex") == 0) ivert = i;
            if (strcmp(el[i].name, "face") == 0) iface = i;
        }
        if (ivert < 0 || iface < 0) {
            error_set(err, path, end_line, "no element %s in the header",
                      ivert < 0 ? "vertex" : "face");
            ok = 0;
        }
    }
    /* element counts must fit the bytes left (no giant allocations, no endless loops) */
    {   /* the elements in order: each needs its rows after the rows before it */
        double before = 0.0, left = (double)(rd.size - rd.pos) + 1.0;  /* +1: see above */
        for (i = 0; ok && i < n_el; i++) {
            double need = (double)el[i].count * (double)min_row_bytes(&rd, &el[i]);
            if (before + need > left) {
                error_set(err, path, el[i].line,
                          "element %s: count %ld does not fit in the file (truncated or "
                          "corrupt: %ld rows need at least %.0f bytes, %.0f are left)",
                          el[i].name, el[i].count, el[i].count, need,
                          before < left - 1.0 ? left - 1.0 - before : 0.0);
                ok = 0;
            }
            before += need;
        }
    }
    for (i = 0; ok && i < n_el; i++) {
        const PlyElement *e = &el[i];
        long r;
        int j;
        if (i == ivert) ok = read_vertices(&rd, e, m);
        else if (i == iface) ok = read_faces(&rd, e, el[ivert].count, m);
        else if (e->n_props > 0) {             /* some other element: skip it */
            rd.elem_line = e->line;
            for (r = 0; ok && r < e->count; r++)
                for (j = 0; ok && j < e->n_props; j++) ok = skip_prop(&rd, &e->props[j]);
        }
    }
    free(el);
    free(rd.data);
    if (!ok) {
        ply_free(m);
        return 0;
    }
    return 1;
}

/* ---------------------------------------------------------------------------
   Writing
   --------------------------------------------------------------------------- */
static void put_u32_le(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v & 0xff);
    p[1] = (unsigned char)((v >> 8) & 0xff);
    p[2] = (unsigned char)((v >> 16) & 0xff);
    p[3] = (unsigned char)((v >> 24) & 0xff);
}

int ply_write_binary(const char *path, const float *P, int n_verts, const int32_t *idx, int n_tris)
{
    FILE *f;
    unsigned char row[13];
    int i, k, ok;
    if (n_verts < 0 || n_tris < 0 || (n_verts > 0 && !P) || (n_tris > 0 && !idx)) return 0;
    f = fopen(path, "wb");
    if (!f) return 0;
    ok = fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by specnee\n"
                    "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face %d\nproperty list uchar int vertex_indices\nend_header\n",
                 n_verts, n_tris) > 0;
    for (i = 0; ok && i < n_verts; i++) {
        for (k = 0; k < 3; k++) {              /* little-endian whatever the host is */
            uint32_t w;
            memcpy(&w, &P[3 * (size_t)i + k], 4);
            put_u32_le(row + 4 * k, w);
        }
        ok = fwrite(row, 1, 12, f) == 12;
    }
    for (i = 0; ok && i < n_tris; i++) {
        row[0] = 3;
        for (k = 0; k < 3; k++) put_u32_le(row + 1 + 4 * k, (uint32_t)idx[3 * (size_t)i + k]);
        ok = fwrite(row, 1, 13, f) == 13;
    }
    if (fclose(f) != 0) ok = 0;
    return ok;
}
