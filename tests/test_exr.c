/* tests/test_exr.c - the OpenEXR reader (exr.c).  Files written by OpenEXR's own
   library (tests/data/exr, every compression read: NONE, RLE, ZIPS with decreasing
   line order, ZIP with a data window off the origin and alpha, a luminance image)
   decode to the values they were made from; two renders of pbrt-v4 (half and
   float, ZIP, a crop window) decode to the PFM pbrt-v4 wrote of the same render;
   files made here (any channel order, HALF specials and subnormals, FLOAT, UINT,
   skipped channels, RLE literal and repeat runs) decode to their samples; what the
   reader does not read (tiled, multi-part, deep, PIZ ... DWAB) is refused by name
   with the conversion command; malformed files (every truncation, bad magic,
   absurd sizes, bad offsets and blocks) are refused with one line naming the
   problem; a sweep of corrupted bytes never crashes (ASan + UBSan in
   tests/run.sh); and a scene reads an .exr image texture and environment map. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

#define DIR "tests/data/exr/"

/* The values of gen_openexr.c (tests/data/exr): channel c of pixel (x, y) of the
   data window, all exact in half. */
static float exr_value(int x, int y, int c)
{
    if (c == 0) return (float)(x / 4) * 0.125f;
    if (c == 1) return (float)y * 0.5f - 2.0f;
    if ((x + y) % 5 == 0) return 1.0f / 1048576.0f;
    if ((x + y) % 7 == 0) return 65504.0f;
    return 1.0f + (float)(x % 3) * 0.25f;
}

static int same(float a, float b)     /* equal, NaN equal to NaN, -0 apart from +0 */
{
    if (a != a || b != b) return a != a && b != b;
    return a == b && (a != 0.0f || (1.0f / a > 0.0f) == (1.0f / b > 0.0f));
}

static void test_exr_openexr_files(T *t)
{
    static const char *const files[] = { "rgb-none.exr", "rgb-rle.exr", "rgb-zips-decreasing.exr",
                                         "rgba-zip-window.exr", "y-zip.exr" };
    int f;
    for (f = 0; f < 5; f++) {
        char path[256];
        Image im;
        Error e;
        int x, y, c, grey = files[f][0] == 'y';
        snprintf(path, sizeof path, DIR "%s", files[f]);
        CHECK(t, exr_read(&im, path, &e), "%s", e.msg);
        if (im.w != 13 || im.h != 18) { img_free(&im); CHECK(t, 0, "%s: %d x %d, want 13 x 18", path, im.w, im.h); }
        for (y = 0; y < im.h; y++)
            for (x = 0; x < im.w; x++)
                for (c = 0; c < 3; c++) {
                    float v = im.rgb[3 * ((size_t)y * 13 + x) + c], want = exr_value(x, y, grey ? 0 : c);
                    if (!same(v, want)) {
                        img_free(&im);
                        CHECK(t, 0, "%s: pixel (%d, %d) channel %d is %.9g, want %.9g", path, x, y, c, v, want);
                    }
                }
        img_free(&im);
    }
}

/* pbrt-v4's EXR of a render against its PFM of the same render (tests/data/exr:
   the half one is stored in half in both, the float one is a crop window). */
static void test_exr_pbrt_renders(T *t)
{
    static const char *const files[][2] = {
        { DIR "pbrt-half-zip.exr", DIR "pbrt-half-zip.pfm" },
        { DIR "pbrt-float-crop.exr", DIR "pbrt-float-crop.pfm" } };
    static const int size[2][2] = { { 16, 12 }, { 12, 17 } };
    int f;
    for (f = 0; f < 2; f++) {
        Image a, b;
        Error e;
        size_t i;
        int nonzero = 0;
        CHECK(t, exr_read(&a, files[f][0], &e), "%s", e.msg);
        if (!pfm_read(&b, files[f][1], &e)) { img_free(&a); CHECK(t, 0, "%s", e.msg); }
        if (a.w != b.w || a.h != b.h || a.w != size[f][0] || a.h != size[f][1]) {
            img_free(&a); img_free(&b);
            CHECK(t, 0, "%s: %d x %d, the PFM %d x %d", files[f][0], a.w, a.h, b.w, b.h);
        }
        for (i = 0; i < 3 * (size_t)a.w * (size_t)a.h; i++) {
            nonzero += a.rgb[i] > 0.0f;
            if (a.rgb[i] != b.rgb[i]) {
                float va = a.rgb[i], vb = b.rgb[i];
                img_free(&a); img_free(&b);
                CHECK(t, 0, "%s: sample %lu is %.9g, the PFM has %.9g", files[f][0], (unsigned long)i, va, vb);
            }
        }
        img_free(&a); img_free(&b);
        CHECK(t, nonzero > 100, "%s: only %d nonzero samples", files[f][0], nonzero);
    }
}

/* ---- files made here ---- */

typedef struct { unsigned char *d; size_t n, cap; } Buf;

static void put(Buf *b, const void *p, size_t k)
{
    if (b->n + k > b->cap) {
        b->cap = 2 * (b->n + k) + 256;
        b->d = (unsigned char *)realloc(b->d, b->cap);
        if (!b->d) abort();
    }
    memcpy(b->d + b->n, p, k);
    b->n += k;
}
static void put32(Buf *b, uint32_t v)
{
    unsigned char q[4];
    q[0] = (unsigned char)v; q[1] = (unsigned char)(v >> 8); q[2] = (unsigned char)(v >> 16); q[3] = (unsigned char)(v >> 24);
    put(b, q, 4);
}
static void set32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8); p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24);
}
static void attr(Buf *b, const char *name, const char *type, const void *v, size_t size)
{
    put(b, name, strlen(name) + 1);
    put(b, type, strlen(type) + 1);
    put32(b, (uint32_t)size);
    put(b, v, size);
}

/* Half bit patterns and their values, written out by hand. */
static const struct { unsigned bits; float v; } halves[] = {
    { 0x0000, 0.0f }, { 0x8000, -0.0f }, { 0x0001, 5.9604644775390625e-08f },
    { 0x03ff, 6.0975551605224609375e-05f }, { 0x0400, 6.103515625e-05f }, { 0x3c00, 1.0f },
    { 0x3555, 0.333251953125f }, { 0xc000, -2.0f }, { 0x7bff, 65504.0f }, { 0x7c00, 0.0f },
    { 0xfc00, 0.0f }, { 0x7e00, 0.0f } };   /* +inf, -inf, NaN: set in halves_init */
static float half_specials[3];

typedef struct { const char *name; int type; } TChan;   /* 0 UINT, 1 HALF, 2 FLOAT */

/* The sample of channel k at (x, y): its bits as stored (*bits, *bytes) and value. */
static float t_sample(int type, int x, int y, int k, uint32_t *bits)
{
    if (type == 1) {
        int i = (x / 8 + y + k) % 12;
        *bits = halves[i].bits;
        return i >= 9 ? half_specials[i - 9] : halves[i].v;
    }
    if (type == 0) { *bits = (uint32_t)(7 * y + 1000 * k); return (float)*bits; }
    {
        float f = (float)y * 0.5f + (float)k - 3.25f;
        memcpy(bits, &f, 4);
        return f;
    }
}

/* The writer's steps: bytes interleaved (even ones first), then the predictor. */
static void t_forward(const unsigned char *raw, unsigned char *t, size_t n)
{
    size_t i, half = (n + 1) / 2;
    for (i = 0; i < n; i++) t[i % 2 ? half + i / 2 : i / 2] = raw[i];
    for (i = n - 1; i >= 1; i--) t[i] = (unsigned char)(t[i] - t[i - 1] + 128);
}

/* RLE: runs of 3 or more as (count - 1, byte), others as literals (256 - count, bytes). */
static size_t t_rle(const unsigned char *in, size_t n, unsigned char *out)
{
    size_t i = 0, o = 0;
    while (i < n) {
        size_t run = 1, lit = 0;
        while (i + run < n && run < 128 && in[i + run] == in[i]) run++;
        if (run >= 3) { out[o++] = (unsigned char)(run - 1); out[o++] = in[i]; i += run; continue; }
        while (i + lit < n && lit < 128 &&
               !(i + lit + 2 < n && in[i + lit] == in[i + lit + 1] && in[i + lit] == in[i + lit + 2])) lit++;
        out[o++] = (unsigned char)(256 - lit);
        memcpy(out + o, in + i, lit);
        o += lit; i += lit;
    }
    return o;
}

/* An EXR file: channels ch (in this order), compression comp (RLE compresses; the
   ZIPs store each block raw, which the format allows), data window at (x0, y0) of
   w x h, blocks in decreasing y when decreasing.  *packed counts RLE blocks stored
   compressed. */
static Buf t_exr(uint32_t version, const TChan *ch, int n_ch, int comp, int x0, int y0, int w, int h,
                 int decreasing, int *packed)
{
    Buf b = { NULL, 0, 0 }, list = { NULL, 0, 0 };
    int k, lpb = comp == 3 ? 16 : 1, n_blocks = (h + lpb - 1) / lpb, i;
    size_t table, line = 0;
    unsigned char v[16], zero = 0;
    if (packed) *packed = 0;
    put32(&b, 20000630u);
    put32(&b, version);
    for (k = 0; k < n_ch; k++) {
        put(&list, ch[k].name, strlen(ch[k].name) + 1);
        put32(&list, (uint32_t)ch[k].type);
        put32(&list, 0);
        put32(&list, 1); put32(&list, 1);
        line += (size_t)w * (ch[k].type == 1 ? 2 : 4);
    }
    put(&list, &zero, 1);
    attr(&b, "channels", "chlist", list.d, list.n);
    free(list.d);
    v[0] = (unsigned char)comp;
    attr(&b, "compression", "compression", v, 1);
    set32(v, (uint32_t)x0); set32(v + 4, (uint32_t)y0); set32(v + 8, (uint32_t)(x0 + w - 1)); set32(v + 12, (uint32_t)(y0 + h - 1));
    attr(&b, "dataWindow", "box2i", v, 16);
    set32(v, 0); set32(v + 4, 0); set32(v + 8, 99); set32(v + 12, 99);
    attr(&b, "displayWindow", "box2i", v, 16);
    v[0] = (unsigned char)decreasing;
    attr(&b, "lineOrder", "lineOrder", v, 1);
    put(&b, &zero, 1);
    table = b.n;
    for (i = 0; i < n_blocks; i++) { put32(&b, 0); put32(&b, 0); }
    for (i = 0; i < n_blocks; i++) {
        int blk = decreasing ? n_blocks - 1 - i : i, l, lines = h - blk * lpb < lpb ? h - blk * lpb : lpb;
        size_t need = line * (size_t)lines, size = need, x;
        unsigned char *raw = (unsigned char *)malloc(need), *tt = (unsigned char *)malloc(need),
                      *rle = (unsigned char *)malloc(2 * need + 8), *o = raw;
        for (l = 0; l < lines; l++)
            for (k = 0; k < n_ch; k++)
                for (x = 0; x < (size_t)w; x++) {
                    uint32_t bits;
                    int j;
                    t_sample(ch[k].type, (int)x, blk * lpb + l, k, &bits);
                    for (j = 0; j < (ch[k].type == 1 ? 2 : 4); j++) *o++ = (unsigned char)(bits >> (8 * j));
                }
        set32(b.d + table + 8 * (size_t)blk, (uint32_t)b.n);      /* the offset (< 4 GiB) */
        put32(&b, (uint32_t)(y0 + blk * lpb));
        if (comp == 1) {
            t_forward(raw, tt, need);
            size = t_rle(tt, need, rle);
        }
        if (comp == 1 && size < need) {
            put32(&b, (uint32_t)size);
            put(&b, rle, size);
            if (packed) ++*packed;
        } else {
            put32(&b, (uint32_t)need);
            put(&b, raw, need);
        }
        free(raw); free(tt); free(rle);
    }
    return b;
}

/* The decoded image against t_sample: R, G, B from the channels named so, else Y. */
static int t_check(T *t, const Buf *b, const TChan *ch, int n_ch, int w, int h, const char *what)
{
    Image im;
    Error e;
    int x, y, c, k, role[3] = { -1, -1, -1 };
    if (!exr_read_memory(b->d, b->n, "made.exr", &im, &e)) {
        test_failf(t, __FILE__, __LINE__, "%s: %s", what, e.msg);
        return 0;
    }
    for (k = 0; k < n_ch; k++) {
        if (!strcmp(ch[k].name, "R")) role[0] = k;
        if (!strcmp(ch[k].name, "G")) role[1] = k;
        if (!strcmp(ch[k].name, "B")) role[2] = k;
    }
    if (role[0] < 0)
        for (k = 0; k < n_ch; k++) if (!strcmp(ch[k].name, "Y")) role[0] = role[1] = role[2] = k;
    if (im.w != w || im.h != h) {
        test_failf(t, __FILE__, __LINE__, "%s: %d x %d, want %d x %d", what, im.w, im.h, w, h);
        img_free(&im);
        return 0;
    }
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            for (c = 0; c < 3; c++) {
                uint32_t bits;
                float want = t_sample(ch[role[c]].type, x, y, role[c], &bits), v = im.rgb[3 * ((size_t)y * w + x) + c];
                if (!same(v, want)) {
                    test_failf(t, __FILE__, __LINE__, "%s: pixel (%d, %d) channel %d is %.9g, want %.9g",
                               what, x, y, c, v, want);
                    img_free(&im);
                    return 0;
                }
            }
    img_free(&im);
    return 1;
}

static void test_exr_made_files(T *t)
{
    static const TChan sorted[] = { { "B", 1 }, { "G", 1 }, { "R", 1 } };
    static const TChan mixed[] = { { "A", 1 }, { "R", 2 }, { "diffuse.R", 1 }, { "B", 0 }, { "G", 1 }, { "Y", 2 } };
    static const TChan grey[] = { { "A", 2 }, { "Y", 1 }, { "Z", 0 } };
    int comp, packed, total_packed = 0;
    half_specials[0] = (float)HUGE_VAL; half_specials[1] = -(float)HUGE_VAL;
    half_specials[2] = (float)(HUGE_VAL - HUGE_VAL);
    for (comp = 0; comp < 4; comp++) {
        Buf b;
        char what[64];
        int ok, dec;
        for (dec = 0; dec < 2; dec++) {
            snprintf(what, sizeof what, "B G R half, compression %d, decreasing %d", comp, dec);
            b = t_exr(2, sorted, 3, comp, -5, 7, 40, 21, dec, &packed);
            total_packed += packed;
            ok = t_check(t, &b, sorted, 3, 40, 21, what);
            free(b.d);
            if (!ok) return;
        }
        snprintf(what, sizeof what, "A R diffuse.R B G Y, compression %d", comp);
        b = t_exr(2, mixed, 6, comp, 0, 0, 17, 35, 0, &packed);
        total_packed += packed;
        ok = t_check(t, &b, mixed, 6, 17, 35, what);
        free(b.d);
        if (!ok) return;
        snprintf(what, sizeof what, "A Y Z (grey), compression %d, long names flag", comp);
        b = t_exr(0x402, grey, 3, comp, 3, -9, 9, 1, 0, &packed);
        ok = t_check(t, &b, grey, 3, 9, 1, what);
        free(b.d);
        if (!ok) return;
    }
    CHECK(t, total_packed > 40, "only %d RLE blocks were stored compressed", total_packed);
}

/* ---- refusals and malformed input ---- */

static int message_ok(const Error *e, const char *name)
{
    const unsigned char *c;
    if (strncmp(e->msg, name, strlen(name)) != 0 || strncmp(e->msg + strlen(name), ": ", 2) != 0) return 0;
    for (c = (const unsigned char *)e->msg; *c; c++)
        if (*c < 0x20 || *c == 0x7f) return 0;
    return 1;
}

static int refused(T *t, const Buf *b, const char *want, const char *what)
{
    Image im;
    Error e;
    e.msg[0] = 0;
    if (exr_read_memory(b->d, b->n, "bad.exr", &im, &e)) {
        img_free(&im);
        test_failf(t, __FILE__, __LINE__, "%s: accepted", what);
        return 0;
    }
    if (!message_ok(&e, "bad.exr") || !strstr(e.msg, "EXR: ") || !strstr(e.msg, want)) {
        test_failf(t, __FILE__, __LINE__, "%s: message \"%s\" lacks \"%s\"", what, e.msg, want);
        return 0;
    }
    return 1;
}

#define CONVERT "convert it to a .pfm beside it: `imgtool convert --outfile bad.pfm bad.exr` (pbrt-v4) or `oiiotool bad.exr -o bad.pfm`"

static void test_exr_refused(T *t)
{
    static const TChan rgb[] = { { "B", 1 }, { "G", 1 }, { "R", 1 } };
    static const char *const names[] = { "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB" };
    static const struct { uint32_t version; const char *want; } flags[] = {
        { 0x202, "a tiled image is not supported" }, { 0x802, "deep data is not supported" },
        { 0x1002, "a multi-part file is not supported" }, { 0x1a02, "a multi-part file" } };
    Image im;
    Error e;
    Buf b;
    int i, ok;
    /* files OpenEXR wrote */
    CHECK(t, !exr_read(&im, DIR "rgb-piz.exr", &e), "PIZ accepted");
    CHECK(t, strstr(e.msg, "rgb-piz.exr: EXR: PIZ compression is not supported (specnee reads scan-line "
                    "images compressed NONE, RLE, ZIPS or ZIP); convert it to a .pfm beside it: `imgtool "
                    "convert --outfile rgb-piz.pfm rgb-piz.exr` (pbrt-v4) or `oiiotool rgb-piz.exr -o rgb-piz.pfm`"),
          "message \"%s\"", e.msg);
    CHECK(t, !exr_read(&im, DIR "rgb-tiled.exr", &e), "tiled accepted");
    CHECK(t, strstr(e.msg, "rgb-tiled.exr: EXR: a tiled image is not supported") &&
          strstr(e.msg, "imgtool convert --outfile rgb-tiled.pfm rgb-tiled.exr"), "message \"%s\"", e.msg);
    /* made here */
    for (i = 0; i < 6; i++) {
        char want[64];
        b = t_exr(2, rgb, 3, 4 + i, 0, 0, 4, 4, 0, NULL);
        snprintf(want, sizeof want, "EXR: %s compression is not supported", names[i]);
        ok = refused(t, &b, want, names[i]) && refused(t, &b, CONVERT, names[i]);
        free(b.d);
        if (!ok) return;
    }
    b = t_exr(2, rgb, 3, 12, 0, 0, 4, 4, 0, NULL);
    ok = refused(t, &b, "compression 12 is not supported", "compression 12");
    free(b.d);
    if (!ok) return;
    for (i = 0; i < 4; i++) {
        b = t_exr(flags[i].version, rgb, 3, 0, 0, 0, 4, 4, 0, NULL);
        ok = refused(t, &b, flags[i].want, flags[i].want) && refused(t, &b, CONVERT, flags[i].want);
        free(b.d);
        if (!ok) return;
    }
    b = t_exr(3, rgb, 3, 0, 0, 0, 4, 4, 0, NULL);
    ok = refused(t, &b, "unknown version (specnee reads version 2)", "version 3");
    free(b.d);
    if (!ok) return;
    b = t_exr(0x10002, rgb, 3, 0, 0, 0, 4, 4, 0, NULL);
    ok = refused(t, &b, "unknown flags in the version field", "flag 0x10000");
    free(b.d);
    if (!ok) return;
    /* a subsampled channel: G's y sampling 2 (bytes 4 + 4 + 4 + 4 after "G\0") */
    b = t_exr(2, rgb, 3, 0, 0, 0, 4, 4, 0, NULL);
    {
        unsigned char *g = b.d + 8 + strlen("channels") + 1 + strlen("chlist") + 1 + 4 + 18;
        if (g[0] != 'G') { free(b.d); CHECK(t, 0, "the test's channel list moved"); }
        g[2 + 12] = 2;
        ok = refused(t, &b, "channel \"G\" subsampled (x or y sampling not 1) is not supported", "subsampled");
    }
    free(b.d);
    if (!ok) return;
    /* a multi-part header's type */
    {
        Buf h = { NULL, 0, 0 };
        unsigned char zero = 0;
        put32(&h, 20000630u); put32(&h, 2);
        attr(&h, "type", "string", "deeptile", 8);
        put(&h, &zero, 1);
        ok = refused(t, &h, "a part of type \"deeptile\" is not supported", "type deeptile");
        free(h.d);
        if (!ok) return;
    }
}

/* A copy of b with bytes [at, at + k) replaced by v. */
static Buf patched(const Buf *b, size_t at, const void *v, size_t k)
{
    Buf c = { NULL, 0, 0 };
    put(&c, b->d, b->n);
    if (c.d && at + k <= c.n) memcpy(c.d + at, v, k);
    return c;
}

static size_t find(const Buf *b, const char *s)
{
    size_t i, k = strlen(s) + 1;
    for (i = 0; i + k <= b->n; i++) if (!memcmp(b->d + i, s, k)) return i;
    return 0;
}

static void test_exr_malformed(T *t)
{
    static const TChan rgb[] = { { "B", 1 }, { "G", 1 }, { "R", 1 } };
    static const TChan other[] = { { "A", 1 }, { "Z", 1 } };
    static const TChan odd[] = { { "B", 1 }, { "G", 7 }, { "R", 1 } };
    Buf b = t_exr(2, rgb, 3, 1, 0, 0, 24, 5, 0, NULL), c;
    unsigned char big[16], four[4];
    size_t dw = find(&b, "dataWindow") + 11 + 6 + 4, table = b.n, k, first;
    int ok = 1;
    Image im;
    Error e;
    /* the offset table: after the header's last attribute (lineOrder, 1 byte) and the NUL */
    table = find(&b, "lineOrder") + 10 + 10 + 4 + 1 + 1;
    first = (size_t)b.d[table] | (size_t)b.d[table + 1] << 8;
    CHECK(t, exr_read_memory(b.d, b.n, "ok.exr", &im, &e), "%s", e.msg);
    img_free(&im);
    c = patched(&b, 0, "v/1\x02", 4);
    ok = ok && refused(t, &c, "not an OpenEXR file (no magic number 76 2f 31 01)", "magic");
    free(c.d);
    set32(big, 0); set32(big + 4, 0); set32(big + 8, 0x7ffffffe); set32(big + 12, 0x7ffffffe);
    c = patched(&b, dw, big, 16);
    ok = ok && refused(t, &c, "more pixels than IMG_MAX_PIXELS", "huge window");
    free(c.d);
    set32(big + 8, 0x7ffffff); set32(big + 12, 0);        /* 2^27 x 1 pixels: fits the count */
    c = patched(&b, dw, big, 16);
    ok = ok && refused(t, &c, "truncated (the pixel data is too short for the data window)", "wide window");
    free(c.d);
    set32(big + 8, 0x7fff); set32(big + 12, 0x7fff);       /* 2^30 pixels */
    c = patched(&b, dw, big, 16);
    ok = ok && refused(t, &c, "more pixels than IMG_MAX_PIXELS", "huge square");
    free(c.d);
    set32(big, 5); set32(big + 8, 4); set32(big + 12, 4);
    c = patched(&b, dw, big, 16);
    ok = ok && refused(t, &c, "an empty data window (xMax < xMin or yMax < yMin)", "empty window");
    free(c.d);
    set32(big, 0); set32(big + 4, 0); set32(big + 8, 23); set32(big + 12, 999999);
    c = patched(&b, dw, big, 16);
    ok = ok && refused(t, &c, "truncated (the line offset table is longer than the file)", "tall window");
    free(c.d);
    set32(four, 0x7ffffff0);
    c = patched(&b, table, four, 4);
    ok = ok && refused(t, &c, "truncated (block 0's offset is past the end of the file)", "offset");
    free(c.d);
    set32(four, 3);                                          /* block 0 claims line 3 */
    c = patched(&b, first, four, 4);
    ok = ok && refused(t, &c, "two blocks for line y = 3", "duplicate");
    free(c.d);
    set32(four, 2 + 16);
    c = patched(&b, first, four, 4);
    ok = ok && refused(t, &c, "block 0 starts at line y = 18, not a block of the data window", "y");
    free(c.d);
    set32(four, 0x7ffffff0);
    c = patched(&b, first + 4, four, 4);
    ok = ok && refused(t, &c, "truncated (block 0 is longer than the file)", "block size");
    free(c.d);
    c = patched(&b, first + 8, "\x05\x00", 2);               /* a run of 6 where RLE data began */
    {
        Image im2;
        Error e2;
        if (exr_read_memory(c.d, c.n, "bad.exr", &im2, &e2)) img_free(&im2);
        else ok = ok && message_ok(&e2, "bad.exr") && strstr(e2.msg, "block at line y = 0: RLE data") != NULL;
        if (!ok) test_failf(t, __FILE__, __LINE__, "RLE damage: \"%s\"", e2.msg);
    }
    free(c.d);
    c = patched(&b, find(&b, "compression") + 12 + 12 + 4, "\x00", 1);   /* RLE blocks read as NONE */
    ok = ok && refused(t, &c, "truncated (the pixel data is too short for the data window)", "RLE as NONE");
    free(c.d);
    {
        Buf n = t_exr(2, rgb, 3, 0, 0, 0, 24, 5, 0, NULL);
        set32(four, 24 * 3 * 2 - 1);                         /* block 0 a byte short */
        c = patched(&n, first + 4, four, 4);
        free(n.d);
        ok = ok && refused(t, &c, "block at line y = 0: a block's size does not match its lines", "NONE size");
        free(c.d);
    }
    c = patched(&b, find(&b, "channels"), "xhannels", 8);
    ok = ok && refused(t, &c, "no \"channels\" attribute", "no channels");
    free(c.d);
    c = patched(&b, find(&b, "compression"), "Compression", 11);
    ok = ok && refused(t, &c, "no \"compression\" attribute", "no compression");
    free(c.d);
    c = patched(&b, find(&b, "dataWindow"), "datawindow", 10);
    ok = ok && refused(t, &c, "no \"dataWindow\" attribute", "no dataWindow");
    free(c.d);
    c = patched(&b, find(&b, "box2i"), "box2f", 5);
    ok = ok && refused(t, &c, "bad \"dataWindow\" attribute", "box2f");
    free(c.d);
    free(b.d);
    if (!ok) return;
    b = t_exr(2, other, 2, 0, 0, 0, 4, 4, 0, NULL);
    ok = refused(t, &b, "no R, G, B channels and no Y channel (specnee reads RGB or luminance images)", "A Z");
    free(b.d);
    b = t_exr(2, odd, 3, 0, 0, 0, 4, 4, 0, NULL);
    ok = ok && refused(t, &b, "a channel of unknown pixel type (EXR has 0 UINT, 1 HALF, 2 FLOAT)", "type 7");
    free(b.d);
    if (!ok) return;
    /* every truncation of two real files: an error naming the file, never a crash */
    for (k = 0; k < 2; k++) {
        size_t len, n;
        ReadStatus rs;
        char *buf = read_whole_file(k ? DIR "rgb-rle.exr" : DIR "rgba-zip-window.exr", 0, NULL, &len, &rs);
        CHECK(t, buf, "cannot read the fixture");
        for (n = 0; n < len; n++) {
            e.msg[0] = 0;
            if (exr_read_memory((const unsigned char *)buf, n, "cut.exr", &im, &e) ||
                !message_ok(&e, "cut.exr") || !strstr(e.msg, "EXR: ")) {
                if (e.msg[0] == 0) img_free(&im);
                free(buf);
                CHECK(t, 0, "cut at %lu of %lu: \"%s\"", (unsigned long)n, (unsigned long)len, e.msg);
            }
        }
        free(buf);
    }
    CHECK(t, !exr_read(&im, DIR "nonexistent.exr", &e) && strstr(e.msg, "nonexistent.exr: cannot read the EXR file"),
          "message \"%s\"", e.msg);
    CHECK(t, !exr_read(&im, DIR "pbrt-half-zip.pfm", &e) &&
          strstr(e.msg, "pbrt-half-zip.pfm: EXR: not an OpenEXR file (no magic number 76 2f 31 01)"),
          "message \"%s\"", e.msg);
}

/* Every byte of three files xor 0x01, 0x80, 0xff: decoded or refused in one line. */
static void test_exr_corruption_sweep(T *t)
{
    static const char *const files[] = { DIR "rgb-rle.exr", DIR "rgba-zip-window.exr", DIR "pbrt-float-crop.exr" };
    static const unsigned char xors[] = { 0x01, 0x80, 0xff };
    long decoded = 0, refused_n = 0;
    int f;
    for (f = 0; f < 3; f++) {
        size_t len, i;
        ReadStatus rs;
        unsigned char *buf = (unsigned char *)read_whole_file(files[f], 0, NULL, &len, &rs);
        int x;
        CHECK(t, buf, "cannot read %s", files[f]);
        for (i = 0; i < len; i++)
            for (x = 0; x < 3; x++) {
                Image im;
                Error e;
                buf[i] ^= xors[x];
                e.msg[0] = 0;
                if (exr_read_memory(buf, len, "sweep.exr", &im, &e)) {
                    img_free(&im);
                    decoded++;
                } else if (!message_ok(&e, "sweep.exr")) {
                    free(buf);
                    CHECK(t, 0, "%s byte %lu ^ 0x%02x: message \"%s\"", files[f], (unsigned long)i, xors[x], e.msg);
                } else {
                    refused_n++;
                }
                buf[i] ^= xors[x];
            }
        free(buf);
    }
    CHECK(t, refused_n > 0 && decoded > 0, "sweep: %ld refused, %ld decoded", refused_n, decoded);
}

/* A scene reads an .exr texture (without a .pfm beside it) and an .exr environment;
   a .pfm beside an .exr texture wins. */
static void test_exr_scene(T *t)
{
    static const TChan rgb[] = { { "B", 2 }, { "G", 2 }, { "R", 2 } };
    Buf b = t_exr(2, rgb, 3, 0, 0, 0, 8, 8, 0, NULL);
    const char *path = test_path(t, "exr_scene_tex.exr");
    char text[1024];
    FILE *f = fopen(path, "wb");
    Scene s;
    Error e;
    int wrote;
    CHECK(t, f, "cannot write %s", path);
    wrote = fwrite(b.d, 1, b.n, f) == b.n;
    wrote &= fclose(f) == 0;
    free(b.d);
    CHECK(t, wrote, "cannot write %s", path);
    snprintf(text, sizeof text, "Camera \"perspective\"\nWorldBegin\nTexture \"i\" \"spectrum\" \"imagemap\" "
             "\"string filename\" \"%s\"\nMaterial \"diffuse\" \"texture reflectance\" \"i\"\n"
             "LightSource \"infinite\" \"string filename\" \"%s\"\nShape \"sphere\"\n", path, path);
    CHECK(t, scene_load_string(&s, text, "exr.pbrt", &e), "%s", e.msg);
    scene_free(&s);
    /* a .pfm beside the .exr is read instead (the .exr here is not even an EXR) */
    {
        const char *bogus = test_write_file(t, "exr_scene_beside.exr", "not an EXR file\n");
        const char *pfm = test_path(t, "exr_scene_beside.pfm");
        Image im;
        CHECK(t, img_alloc(&im, 2, 2), "out of memory");
        wrote = pfm_write(&im, pfm);
        img_free(&im);
        CHECK(t, wrote, "cannot write %s", pfm);
        snprintf(text, sizeof text, "WorldBegin\nTexture \"i\" \"spectrum\" \"imagemap\" \"string filename\" "
                 "\"%s\"\n", bogus);
        CHECK(t, scene_load_string(&s, text, "exr.pbrt", &e), "the .pfm beside it was not read: %s", e.msg);
        scene_free(&s);
    }
    snprintf(text, sizeof text, "WorldBegin\nTexture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\"\n",
             DIR "rgb-piz.exr");
    CHECK(t, !scene_load_string(&s, text, "exr.pbrt", &e) &&
          strstr(e.msg, "exr.pbrt:2: Texture \"imagemap\" \"i\": " DIR "rgb-piz.exr: EXR: PIZ compression is not supported"),
          "message \"%s\"", e.msg);
}

/* ---- the "chromaticities" attribute: the image's colour space ---- */

/* A 1 x 1 FLOAT file of rgb, compression NONE, with "chromaticities" xy (rx ry gx
   gy bx by wx wy) when xy is not NULL, written to the test's folder as name. */
static const char *chroma_exr(T *t, const char *name, const float rgb[3], const float *xy)
{
    static const char *const ch[3] = { "B", "G", "R" };
    Buf b = { NULL, 0, 0 }, list = { NULL, 0, 0 };
    unsigned char v[32], zero = 0;
    const char *path = test_path(t, name);
    FILE *f;
    int k, ok;
    put32(&b, 20000630u);
    put32(&b, 2);
    for (k = 0; k < 3; k++) {
        put(&list, ch[k], 2);
        put32(&list, 2); put32(&list, 0); put32(&list, 1); put32(&list, 1);
    }
    put(&list, &zero, 1);
    attr(&b, "channels", "chlist", list.d, list.n);
    free(list.d);
    v[0] = 0;
    attr(&b, "compression", "compression", v, 1);
    memset(v, 0, 16);
    attr(&b, "dataWindow", "box2i", v, 16);
    attr(&b, "displayWindow", "box2i", v, 16);
    attr(&b, "lineOrder", "lineOrder", v, 1);
    if (xy) {
        for (k = 0; k < 8; k++) {
            uint32_t u;
            memcpy(&u, &xy[k], 4);
            set32(v + 4 * k, u);
        }
        attr(&b, "chromaticities", "chromaticities", v, 32);
    }
    put(&b, &zero, 1);
    put32(&b, (uint32_t)(b.n + 8)); put32(&b, 0);        /* the one block's offset */
    put32(&b, 0); put32(&b, 12);                         /* y 0, 12 bytes */
    for (k = 2; k >= 0; k--) {                           /* B, G, R */
        uint32_t u;
        memcpy(&u, &rgb[k], 4);
        put32(&b, u);
    }
    f = fopen(path, "wb");
    ok = f && fwrite(b.d, 1, b.n, f) == b.n;
    if (f) ok &= fclose(f) == 0;
    free(b.d);
    return ok ? path : NULL;
}

/* The XYZ of an imagemap texture made of file under the illuminant named white
   (1-nm sums over 360..830 nm, normalised so that a reflectance of 1 has Y = 1). */
static int texture_xyz(T *t, const char *file, const char *white, double xyz[3])
{
    char text[1024];
    Scene s;
    Error e;
    Spectrum W;
    SurfacePoint sp = test_flat_point();
    double norm = 0.0;
    int nm, k;
    snprintf(text, sizeof text, "WorldBegin\nTexture \"i\" \"spectrum\" \"imagemap\" \"string filename\" "
             "\"%s\"\n", file);
    if (!scene_load_string(&s, text, "chroma.pbrt", &e)) { test_failf(t, __FILE__, __LINE__, "%s", e.msg); return 0; }
    if (!spec_named(&W, white)) { scene_free(&s); test_failf(t, __FILE__, __LINE__, "no spectrum %s", white); return 0; }
    sp.u = sp.v = 0.5f;
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    for (nm = 360; nm <= 830; nm++) {
        double c[3], r = tex_eval(s.textures, 0, &sp, (float)nm), w = spec_eval(&W, (float)nm);
        cie_cmf((double)nm, c);
        for (k = 0; k < 3; k++) xyz[k] += c[k] * r * w;
        norm += c[1] * w;
    }
    for (k = 0; k < 3; k++) xyz[k] /= norm;
    scene_free(&s);
    return 1;
}

/* An EXR texture's texel is the colour its file means: fitted in the colour space
   its chromaticities name, so that its XYZ under that space's white is the space's
   published RGB -> XYZ matrix times the texel (SMPTE ST 2065-1 for ACES2065-1's
   AP0 with white (0.32168, 0.33767); ITU-R BT.2020's matrix; IEC 61966-2-1 sRGB's
   for a file without chromaticities, with sRGB's, and with chromaticities of no
   space pbrt-v4 knows (Adobe RGB 1998's), which pbrt-v4 reads as sRGB).  Within
   5e-4: the published matrices use the whites' nominal xy, the fit the whites
   integrated from their spectra.  A texel read in the wrong space is off by 0.1 or
   more.  Also: the environment map of an ACES file shines ACES's white, and an
   emission image in a space other than sRGB is refused by name. */
static void test_exr_chromaticities(T *t)
{
    static const float aces[8] = { 0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f };
    static const float rec2020[8] = { 0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f };
    static const float srgb[8] = { 0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f };
    static const float adobe[8] = { 0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, 0.3127f, 0.3290f };
    static const double m_aces[3][3] = { { 0.9525523959, 0.0, 0.0000936786 },
                                         { 0.3439664498, 0.7281660966, -0.0721325464 },
                                         { 0.0, 0.0, 1.0088251844 } };
    static const double m_2020[3][3] = { { 0.636958, 0.144617, 0.168881 },
                                         { 0.262700, 0.677998, 0.059302 },
                                         { 0.0, 0.028073, 1.060985 } };
    static const double m_srgb[3][3] = { { 0.4124564, 0.3575761, 0.1804375 },
                                         { 0.2126729, 0.7151522, 0.0721750 },
                                         { 0.0193339, 0.1191920, 0.9503041 } };
    static const struct { const char *file; const float *xy; const double (*m)[3]; const char *white; }
        cases[] = { { "chroma_aces.exr", aces, m_aces, "illum-acesD60" },
                    { "chroma_2020.exr", rec2020, m_2020, "stdillum-D65" },
                    { "chroma_srgb.exr", srgb, m_srgb, "stdillum-D65" },
                    { "chroma_none.exr", NULL, m_srgb, "stdillum-D65" },
                    { "chroma_adobe.exr", adobe, m_srgb, "stdillum-D65" } };
    static const float rgb[3] = { 0.2f, 0.5f, 0.3f };
    char text[1024];
    Scene s;
    Error e;
    int c, k, j;
    for (c = 0; c < 5; c++) {
        const char *path = chroma_exr(t, cases[c].file, rgb, cases[c].xy);
        double xyz[3], want[3];
        CHECK(t, path, "cannot write %s", cases[c].file);
        if (!texture_xyz(t, path, cases[c].white, xyz)) return;
        for (k = 0; k < 3; k++) {
            for (want[k] = 0.0, j = 0; j < 3; j++) want[k] += cases[c].m[k][j] * rgb[j];
            CHECK(t, fabs(xyz[k] - want[k]) < 5e-4, "%s: XYZ[%d] = %.5f under %s, the space's matrix "
                  "gives %.5f", cases[c].file, k, xyz[k], cases[c].white, want[k]);
        }
    }
    /* an ACES environment map: its texels' illuminant is ACES's white */
    {
        const char *path = chroma_exr(t, "chroma_env.exr", rgb, aces);
        Spectrum d60;
        int nm;
        CHECK(t, path && spec_named(&d60, "illum-acesD60"), "cannot write chroma_env.exr");
        snprintf(text, sizeof text, "WorldBegin\nLightSource \"infinite\" \"string filename\" \"%s\"\n", path);
        CHECK(t, scene_load_string(&s, text, "chroma.pbrt", &e), "%s", e.msg);
        for (nm = 360; nm <= 830; nm += 10)
            if (spec_eval(s.emitters[0].L, (float)nm) != spec_eval(&d60, (float)nm)) {
                float got = spec_eval(s.emitters[0].L, (float)nm);
                scene_free(&s);
                CHECK(t, 0, "the ACES map's illuminant at %d nm is %g, illum-acesD60's %g", nm, got,
                      spec_eval(&d60, (float)nm));
            }
        scene_free(&s);
        /* an emission image in ACES: refused by name */
        snprintf(text, sizeof text, "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" "
                 "\"string filename\" \"%s\"\nShape \"sphere\"\nAttributeEnd\n", path);
        CHECK(t, !scene_load_string(&s, text, "chroma.pbrt", &e) &&
              strstr(e.msg, "chroma.pbrt:3: AreaLightSource \"diffuse\": ") &&
              strstr(e.msg, "colour space \"aces2065-1\""), "message \"%s\"", e.msg);
    }
}

const TestCase tests_exr[] = {
    { "exr_openexr_files", test_exr_openexr_files },
    { "exr_pbrt_renders", test_exr_pbrt_renders },
    { "exr_made_files", test_exr_made_files },
    { "exr_refused", test_exr_refused },
    { "exr_malformed", test_exr_malformed },
    { "exr_corruption_sweep", test_exr_corruption_sweep },
    { "exr_scene", test_exr_scene },
    { "exr_chromaticities", test_exr_chromaticities },
    { NULL, NULL }
};
