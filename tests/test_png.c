/* tests/test_png.c - the PNG reader (png.c): PNGs made by another
   encoder (Python's zlib: tests/png_fixtures.h, every colour type, bit depths 1 2
   4 8 16, all five row filters, stored, fixed and dynamic Huffman blocks) decode
   to the samples they were made from; specnee's own writer round-trips; malformed
   files (bad CRC, truncation, bad Huffman codes, distances, Adler-32, filters,
   palette indices, interlace, absurd sizes) are refused with a message naming the
   problem; and a sweep of corrupted bytes never crashes (the suite runs under
   ASan + UBSan in tests/run.sh step 4). */
#include "test.h"
#include <stdlib.h>
#include <string.h>
#include "png_fixtures.h"

/* ---- an independent CRC-32 (table driven) and PNG assembly for crafted files */
static uint32_t t_crc(const unsigned char *p, size_t n)
{
    uint32_t table[256], c = 0xffffffffu, k;
    size_t i;
    for (k = 0; k < 256; k++) {                 /* the CRC of each byte value */
        uint32_t v = k;
        int b;
        for (b = 0; b < 8; b++) v = (v >> 1) ^ (0xedb88320u & (0u - (v & 1u)));
        table[k] = v;
    }
    for (i = 0; i < n; i++) c = table[(c ^ p[i]) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

static void t_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24); p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8); p[3] = (unsigned char)v;
}

/* Append a chunk to buf at *n (buf large enough). */
static void t_chunk(unsigned char *buf, size_t *n, const char *type, const unsigned char *d, size_t len)
{
    t_be32(buf + *n, (uint32_t)len);
    memcpy(buf + *n + 4, type, 4);
    if (len) memcpy(buf + *n + 8, d, len);
    t_be32(buf + *n + 8 + len, t_crc(buf + *n + 4, len + 4));
    *n += len + 12;
}

/* A PNG of w x h, depth, colour type, interlace, with z (the zlib stream) as its
   one IDAT and an optional palette; returns its size. */
static size_t t_png(unsigned char *buf, uint32_t w, uint32_t h, int depth, int ctype, int interlace,
                    const unsigned char *pal, size_t n_pal, const unsigned char *z, size_t nz)
{
    static const unsigned char sig[8] = { 137, 80, 78, 71, 13, 10, 26, 10 };
    unsigned char ihdr[13];
    size_t n = 8;
    memcpy(buf, sig, 8);
    t_be32(ihdr, w); t_be32(ihdr + 4, h);
    ihdr[8] = (unsigned char)depth; ihdr[9] = (unsigned char)ctype;
    ihdr[10] = 0; ihdr[11] = 0; ihdr[12] = (unsigned char)interlace;
    t_chunk(buf, &n, "IHDR", ihdr, 13);
    if (pal) t_chunk(buf, &n, "PLTE", pal, n_pal);
    t_chunk(buf, &n, "IDAT", z, nz);
    t_chunk(buf, &n, "IEND", NULL, 0);
    return n;
}

/* A zlib stream of one stored block holding raw[0 .. n) (n < 65536), with its
   Adler-32; returns its size. */
static size_t t_zlib_stored(unsigned char *z, const unsigned char *raw, size_t n)
{
    uint32_t s1 = 1, s2 = 0;
    size_t i;
    z[0] = 0x78; z[1] = 0x01;
    z[2] = 1;                                  /* BFINAL, BTYPE 00 */
    z[3] = (unsigned char)(n & 0xff); z[4] = (unsigned char)(n >> 8);
    z[5] = (unsigned char)(~n & 0xff); z[6] = (unsigned char)((~n >> 8) & 0xff);
    memcpy(z + 7, raw, n);
    for (i = 0; i < n; i++) { s1 = (s1 + raw[i]) % 65521u; s2 = (s2 + s1) % 65521u; }
    t_be32(z + 7 + n, s2 << 16 | s1);
    return n + 11;
}

/* ---- a bit writer for hand-made deflate blocks (RFC 1951 3.1.1: fields from
   the least significant bit; Huffman codes from their most significant bit) */
typedef struct { unsigned char b[64]; int nbits; } Bits;
static void put_bits(Bits *w, uint32_t v, int n)          /* a field, LSB first */
{
    int i;
    for (i = 0; i < n; i++, w->nbits++)
        if (v >> i & 1u) w->b[w->nbits / 8] |= (unsigned char)(1u << (w->nbits % 8));
}
static void put_code(Bits *w, uint32_t code, int len)     /* a Huffman code, MSB first */
{
    int i;
    for (i = len - 1; i >= 0; i--) put_bits(w, code >> i & 1u, 1);
}
static size_t t_zlib_bits(unsigned char *z, const Bits *w)
{
    size_t n = (size_t)(w->nbits + 7) / 8;
    z[0] = 0x78; z[1] = 0x01;
    memcpy(z + 2, w->b, n);
    memset(z + 2 + n, 0, 4);                    /* an Adler-32 (never reached) */
    return n + 6;
}

static double srgb_decode(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* Every fixture decodes to its samples: linear, v / (2^depth - 1) (palette: the
   entry / 255), grey in all three channels, alpha dropped; with the sRGB curve
   the same values decoded. */
static void test_png_fixtures(T *t)
{
    int f;
    for (f = 0; f < (int)(sizeof png_fixtures / sizeof png_fixtures[0]); f++) {
        const PngFixture *fx = &png_fixtures[f];
        double max = (double)((1u << fx->depth) - 1u);
        int lin;
        for (lin = 0; lin < 2; lin++) {
            Image im;
            Error e;
            int p, c;
            CHECK(t, png_read_memory(fx->png, fx->n, fx->name, lin, &im, &e), "%s: %s", fx->name, e.msg);
            CHECK(t, im.w == fx->w && im.h == fx->h, "%s: %d x %d", fx->name, im.w, im.h);
            for (p = 0; p < fx->w * fx->h; p++)
                for (c = 0; c < 3; c++) {
                    double want;
                    if (fx->ctype == 3) want = fx->pal[3 * fx->want[p] + c] / 255.0;
                    else if (fx->ctype == 2 || fx->ctype == 6) want = fx->want[p * fx->spp + c] / max;
                    else want = fx->want[p * fx->spp] / max;
                    if (!lin) want = srgb_decode(want);
                    float got = im.rgb[3 * p + c];
                    if (!(fabs(got - want) <= 1e-6)) {
                        img_free(&im);
                        CHECK(t, 0, "%s (%s): pixel (%d, %d) channel %d: %.7g, want %.7g", fx->name,
                              lin ? "linear" : "sRGB", p % fx->w, p / fx->w, c, got, want);
                    }
                }
            img_free(&im);
        }
    }
}

/* specnee's own writer (stored blocks) round-trips: the linear reading times 255
   is the writer's byte round(255 srgb_oetf(v)), at the same place and channel (an
   asymmetric pattern); the default reading is that byte decoded, within 0.5/255
   of v in the encoded space.  A 200 x 120 image spans several stored blocks. */
static void test_png_writer_roundtrip(T *t)
{
    static const int sizes[2][2] = { { 6, 5 }, { 200, 120 } };
    int s;
    for (s = 0; s < 2; s++) {
        Image src, lin, dec;
        Error e;
        const char *path = test_path(t, s ? "rt_big.png" : "rt_small.png");
        int i, n;
        CHECK(t, img_alloc(&src, sizes[s][0], sizes[s][1]), "alloc");
        n = 3 * src.w * src.h;
        for (i = 0; i < n; i++) src.rgb[i] = (float)((i * 7919 + i / 3) % 1000) / 999.0f;
        src.rgb[0] = 1.0f; src.rgb[1] = 0.0f; src.rgb[2] = 0.25f;   /* the top-left corner */
        CHECK(t, png_write(&src, path, 0.0f), "png_write %s", path);
        if (!png_read(&lin, path, 1, &e)) { img_free(&src); CHECK(t, 0, "%s", e.msg); }
        if (!png_read(&dec, path, 0, &e)) { img_free(&src); img_free(&lin); CHECK(t, 0, "%s", e.msg); }
        for (i = 0; i < n; i++) {
            int byte = (int)(srgb_oetf(src.rgb[i]) * 255.0f + 0.5f);
            int got = (int)(lin.rgb[i] * 255.0f + 0.5f);
            double back = srgb_decode(byte / 255.0);
            float v = src.rgb[i], d = dec.rgb[i];
            if (got != byte || fabs(d - back) > 1e-6 ||
                fabs(srgb_oetf(d) - srgb_oetf(v)) > 0.5f / 255.0f + 1e-6f) {
                img_free(&src); img_free(&lin); img_free(&dec);
                CHECK(t, 0, "%dx%d value %d: wrote %g (byte %d), read %d / %g", sizes[s][0],
                      sizes[s][1], i, v, byte, got, d);
            }
        }
        img_free(&src); img_free(&lin); img_free(&dec);
    }
}

/* The message is one printable line naming the file and "PNG:". */
static int message_ok(const Error *e, const char *name)
{
    const unsigned char *c;
    if (strncmp(e->msg, name, strlen(name)) != 0 || !strstr(e->msg, "PNG:")) return 0;
    for (c = (const unsigned char *)e->msg; *c; c++)
        if (*c < 0x20 || *c == 0x7f) return 0;
    return 1;
}

static int refused(T *t, const unsigned char *png, size_t n, const char *want, const char *what)
{
    Image im;
    Error e;
    e.msg[0] = 0;
    if (png_read_memory(png, n, "bad.png", 0, &im, &e)) {
        img_free(&im);
        test_failf(t, __FILE__, __LINE__, "%s: accepted", what);
        return 0;
    }
    if (!message_ok(&e, "bad.png") || !strstr(e.msg, want)) {
        test_failf(t, __FILE__, __LINE__, "%s: message \"%s\" lacks \"%s\"", what, e.msg, want);
        return 0;
    }
    return 1;
}

/* Malformed files, one problem each, refused with a message naming it. */
static void test_png_malformed(T *t)
{
    static unsigned char buf[4096], z[1024];
    unsigned char raw[64], pal[6] = { 1, 2, 3, 4, 5, 6 };
    size_t n, nz;
    Bits w;
    int i;
    /* a 2 x 2 grey 8-bit image: rows "filter 0, 10 20" and "filter 0, 30 40" */
    raw[0] = 0; raw[1] = 10; raw[2] = 20; raw[3] = 0; raw[4] = 30; raw[5] = 40;
    nz = t_zlib_stored(z, raw, 6);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    {   /* the crafted base image itself is fine */
        Image im; Error e;
        CHECK(t, png_read_memory(buf, n, "ok.png", 1, &im, &e), "crafted 2x2: %s", e.msg);
        CHECK(t, fabs(im.rgb[3 * 3] - 40.0 / 255.0) < 1e-6, "crafted 2x2: %g", im.rgb[9]);
        img_free(&im);
    }
    {   /* Paeth's ties (PNG spec 9.4: a before b before c): a 4 x 2 image whose
           second row, Paeth-filtered, has a tie of a and c at x = 1 (a = 4, b = 13,
           c = 10: p = 7, |p - a| = |p - c| = 3, so a) and of b and c at x = 3
           (a = 13, b = 4, c = 10: |p - b| = |p - c| = 3, so b); the filtered
           bytes were worked out by hand from the raw rows 10 13 10 4 / 4 50 13 77 */
        static const unsigned char rows[10] = { 0, 10, 13, 10, 4, 4, 250, 46, 219, 73 };
        static const int want[8] = { 10, 13, 10, 4, 4, 50, 13, 77 };
        Image im; Error e;
        nz = t_zlib_stored(z, rows, 10);
        n = t_png(buf, 4, 2, 8, 0, 0, NULL, 0, z, nz);
        CHECK(t, png_read_memory(buf, n, "paeth.png", 1, &im, &e), "paeth: %s", e.msg);
        for (i = 0; i < 8; i++) {
            int got = (int)(im.rgb[3 * i] * 255.0f + 0.5f);
            if (got != want[i]) { img_free(&im); CHECK(t, 0, "paeth: value %d is %d, want %d", i, got, want[i]); }
        }
        img_free(&im);
    }
    nz = t_zlib_stored(z, raw, 6);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    /* damage: a bit of IHDR's width, a truncation, a missing IEND */
    buf[19] ^= 1;
    if (!refused(t, buf, n, "CRC mismatch in chunk IHDR", "flipped bit")) return;
    buf[19] ^= 1;
    if (!refused(t, buf, n / 2, "truncated", "half a file")) return;
    if (!refused(t, buf, n - 12, "truncated", "no IEND")) return;
    if (!refused(t, buf, 5, "signature", "five bytes")) return;
    /* IHDR's fields */
    n = t_png(buf, 2, 2, 8, 0, 1, NULL, 0, z, nz);
    if (!refused(t, buf, n, "Adam7", "interlaced")) return;
    n = t_png(buf, 0, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "width and height", "zero width")) return;
    n = t_png(buf, 2, 2, 16, 3, 0, pal, 6, z, nz);
    if (!refused(t, buf, n, "bit depth", "16-bit palette")) return;
    n = t_png(buf, 2, 2, 8, 5, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "colour type", "colour type 5")) return;
    n = t_png(buf, 30000, 30000, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "IMG_MAX_PIXELS", "30000 x 30000")) return;
    n = t_png(buf, 16000, 16000, 16, 6, 0, NULL, 0, z, nz);   /* 2.0 + 3.1 GB > 4 GiB */
    if (!refused(t, buf, n, "memory budget", "16000 x 16000 RGBA16")) return;
    n = t_png(buf, 4000, 4000, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "too short", "4000 x 4000 from 17 bytes")) return;
    n = t_png(buf, 2, 2, 8, 3, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "without PLTE", "palette without PLTE")) return;
    n = t_png(buf, 2, 2, 8, 0, 0, pal, 6, z, nz);
    if (!refused(t, buf, n, "palette in a grey image", "PLTE in grey")) return;
    /* the image data */
    n = t_png(buf, 2, 3, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "less data", "2 x 3 from 2 x 2's data")) return;
    n = t_png(buf, 2, 1, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "more data", "2 x 1 from 2 x 2's data")) return;
    raw[3] = 5;                                         /* row filter type 5 */
    nz = t_zlib_stored(z, raw, 6);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "row filter", "filter type 5")) return;
    raw[3] = 0; raw[4] = 2;                             /* index 2 of a 2-entry palette */
    nz = t_zlib_stored(z, raw, 6);
    n = t_png(buf, 2, 2, 8, 3, 0, pal, 6, z, nz);
    if (!refused(t, buf, n, "palette index", "index beyond PLTE")) return;
    nz = t_zlib_stored(z, raw, 6);
    z[nz - 1] ^= 0x40;                                  /* Adler-32 */
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "Adler-32", "Adler-32 flipped")) return;
    nz = t_zlib_stored(z, raw, 6);
    z[5] ^= 1;                                          /* NLEN */
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "LEN and NLEN", "stored NLEN")) return;
    nz = t_zlib_stored(z, raw, 6);
    z[1] = 0x02;                                        /* header check */
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "header check", "zlib FCHECK")) return;
    /* hand-made deflate blocks */
    memset(&w, 0, sizeof w);
    put_bits(&w, 1, 1); put_bits(&w, 3, 2);             /* BTYPE 11 */
    nz = t_zlib_bits(z, &w);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "block type 3", "BTYPE 3")) return;
    memset(&w, 0, sizeof w);                            /* dynamic: 19 code length codes */
    put_bits(&w, 1, 1); put_bits(&w, 2, 2);             /* of length 1: over-subscribed */
    put_bits(&w, 0, 5); put_bits(&w, 0, 5); put_bits(&w, 15, 4);
    for (i = 0; i < 19; i++) put_bits(&w, 1, 3);
    nz = t_zlib_bits(z, &w);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "bad code length code", "over-subscribed")) return;
    memset(&w, 0, sizeof w);                            /* fixed: a copy before any byte */
    put_bits(&w, 1, 1); put_bits(&w, 1, 2);
    put_code(&w, 1, 7);                                 /* length symbol 257: 3 bytes */
    put_code(&w, 0, 5);                                 /* distance code 0: 1 back */
    nz = t_zlib_bits(z, &w);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "distance beyond", "distance 1 at the start")) return;
    memset(&w, 0, sizeof w);                            /* fixed: symbol 286 (invalid) */
    put_bits(&w, 1, 1); put_bits(&w, 1, 2);
    put_code(&w, 0xc6, 8);                              /* 280 + 6 = 286: 11000000 + 6 */
    nz = t_zlib_bits(z, &w);
    n = t_png(buf, 2, 2, 8, 0, 0, NULL, 0, z, nz);
    if (!refused(t, buf, n, "invalid length symbol", "symbol 286")) return;
}

/* Every byte of every fixture (and of a writer's PNG) changed, three ways, with
   the chunk's CRC left alone (then every change must be refused: CRC-32 sees
   every one-byte error, and a changed length or type fails another check) and
   with the CRC recomputed (so that the damage reaches inflate and the filters:
   any outcome but a crash, a hang or a value outside [0, 1]); and every
   truncation.  Counts are in the failure message. */
static void test_png_corruption_sweep(T *t)
{
    static const unsigned char xors[3] = { 0x01, 0x80, 0xff };
    static unsigned char buf[8192];
    Image src;
    unsigned char *own = NULL;
    size_t own_n = 0;
    int f, nf = (int)(sizeof png_fixtures / sizeof png_fixtures[0]);
    long decoded = 0, refused_n = 0;
    {   /* a PNG from specnee's writer */
        const char *path = test_path(t, "sweep.png");
        ReadStatus rs;
        int i;
        CHECK(t, img_alloc(&src, 9, 4), "alloc");
        for (i = 0; i < 3 * 9 * 4; i++) src.rgb[i] = (float)(i % 11) / 10.0f;
        CHECK(t, png_write(&src, path, 0.0f), "png_write");
        img_free(&src);
        own = (unsigned char *)read_whole_file(path, 0, NULL, &own_n, &rs);
        CHECK(t, own != NULL && own_n < sizeof buf, "read back %s", path);
    }
    for (f = 0; f <= nf; f++) {
        const unsigned char *png = f < nf ? png_fixtures[f].png : own;
        size_t n = f < nf ? png_fixtures[f].n : own_n, i, cut;
        int x, fix;
        for (cut = 0; cut < n; cut++) {                 /* truncations */
            Image im; Error e;
            if (png_read_memory(png, cut, "cut.png", 0, &im, &e)) {
                img_free(&im); free(own);
                CHECK(t, 0, "file %d cut to %lu bytes of %lu: accepted", f, (unsigned long)cut,
                      (unsigned long)n);
            }
        }
        for (fix = 0; fix < 2; fix++)
            for (i = 8; i < n; i++)
                for (x = 0; x < 3; x++) {
                    Image im; Error e;
                    memcpy(buf, png, n);
                    buf[i] ^= xors[x];
                    if (fix) {                          /* recompute the CRC of i's chunk */
                        size_t pos = 8;
                        while (pos + 12 <= n) {
                            size_t len = (size_t)png[pos] << 24 | (size_t)png[pos + 1] << 16 |
                                         (size_t)png[pos + 2] << 8 | png[pos + 3];
                            if (i >= pos + 8 && i < pos + 8 + len) {
                                t_be32(buf + pos + 8 + len, t_crc(buf + pos + 4, len + 4));
                                break;
                            }
                            pos += len + 12;
                        }
                    }
                    e.msg[0] = 0;
                    if (png_read_memory(buf, n, "sweep.png", 0, &im, &e)) {
                        int k, bad = 0;
                        for (k = 0; k < 3 * im.w * im.h; k++)
                            bad |= !(im.rgb[k] >= 0.0f && im.rgb[k] <= 1.0f);
                        img_free(&im);
                        if (bad || !fix) {
                            free(own);
                            CHECK(t, 0, "file %d byte %lu ^ 0x%02x%s: %s", f, (unsigned long)i,
                                  xors[x], fix ? " (CRC fixed)" : "",
                                  bad ? "a value outside [0, 1]" : "accepted with a wrong CRC");
                        }
                        decoded++;
                    } else {
                        if (!message_ok(&e, "sweep.png")) {
                            free(own);
                            CHECK(t, 0, "file %d byte %lu: message \"%s\"", f, (unsigned long)i, e.msg);
                        }
                        refused_n++;
                    }
                }
    }
    free(own);
    CHECK(t, refused_n > 0 && decoded > 0, "sweep: %ld refused, %ld decoded", refused_n, decoded);
}

/* ==== gzip (RFC 1952): members crafted here, around a stored block or hand-made
   fixed-Huffman bits; and the .pbrt.gz / .ply.gz twins of tests/data/gz ==== */

static void t_le32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24);
}

/* The header of a member with the optional fields flg names (FHCRC 2, FEXTRA 4,
   FNAME 8, FCOMMENT 16) at out; its length. */
static size_t t_gz_header(unsigned char *out, unsigned flg)
{
    static const unsigned char fixed[10] = { 0x1F, 0x8B, 8, 0, 1, 2, 3, 4, 2, 3 };
    size_t n = 10;
    memcpy(out, fixed, 10);
    out[3] = (unsigned char)flg;
    if (flg & 4u) { memcpy(out + n, "\x06\x00" "ab\x02\x00xy", 8); n += 8; }
    if (flg & 8u) { memcpy(out + n, "name.pbrt", 10); n += 10; }
    if (flg & 16u) { memcpy(out + n, "a comment", 10); n += 10; }
    if (flg & 2u) {
        uint32_t c = t_crc(out, n);
        out[n] = (unsigned char)c; out[n + 1] = (unsigned char)(c >> 8);
        n += 2;
    }
    return n;
}

/* A whole member of d[0 .. nd) in one stored block; its length. */
static size_t t_gz_member(unsigned char *out, const char *d, size_t nd, unsigned flg)
{
    size_t n = t_gz_header(out, flg);
    out[n] = 1;                                    /* BFINAL 1, BTYPE 00: stored */
    out[n + 1] = (unsigned char)nd; out[n + 2] = (unsigned char)(nd >> 8);
    out[n + 3] = (unsigned char)~nd; out[n + 4] = (unsigned char)(~nd >> 8);
    memcpy(out + n + 5, d, nd);
    n += 5 + nd;
    t_le32(out + n, t_crc((const unsigned char *)d, nd));
    t_le32(out + n + 4, (uint32_t)nd);
    return n + 8;
}

/* gzip_inflate of in[0 .. n) must give status want and, when READ_OK, the bytes
   expect (and a NUL after them). */
static int gz_is(T *t, const unsigned char *in, size_t n, ReadStatus want, const char *expect,
                 const char *what)
{
    unsigned char *out = NULL;
    size_t n_out = 0;
    ReadStatus st = gzip_inflate(in, n, 1u << 20, &out, &n_out);
    int ok = st == want;
    if (ok && st == READ_OK)
        ok = n_out == strlen(expect) && !memcmp(out, expect, n_out) && out[n_out] == '\0';
    if (!ok)
        test_failf(t, __FILE__, __LINE__, "%s: status %d (%s), %lu bytes; expected %d (%s)", what,
                   (int)st, read_status_text(st), (unsigned long)n_out, (int)want,
                   read_status_text(want));
    free(out);
    return ok;
}

/* Every combination of the optional header fields is skipped (FHCRC checked);
   members concatenate; an empty member is empty. */
static void test_gzip_members(T *t)
{
    static unsigned char buf[512];
    unsigned flg;
    size_t n;
    char what[64];
    for (flg = 0; flg < 32; flg += 2) {            /* FTEXT (1) is a hint, left out */
        n = t_gz_member(buf, "hello gzip", 10, flg);
        snprintf(what, sizeof what, "FLG 0x%02x", flg);
        if (!gz_is(t, buf, n, READ_OK, "hello gzip", what)) return;
    }
    n = t_gz_member(buf, "hello ", 6, 8u);
    n += t_gz_member(buf + n, "", 0, 0u);
    n += t_gz_member(buf + n, "gzip", 4, 30u);
    if (!gz_is(t, buf, n, READ_OK, "hello gzip", "three members")) return;
    n = t_gz_member(buf, "", 0, 0u);
    if (!gz_is(t, buf, n, READ_OK, "", "one empty member")) return;
}

/* Damaged members: each refused with the status that names the damage; every
   truncation is "truncated". */
static void test_gzip_malformed(T *t)
{
    static unsigned char buf[512];
    unsigned char *out;
    size_t n, cut, n_out;
    Bits w;
    n = t_gz_member(buf, "hello gzip", 10, 30u);
    buf[n - 8] ^= 1;                               /* the data's CRC-32 */
    if (!gz_is(t, buf, n, READ_GZ_CRC, "", "CRC-32 of the data")) return;
    n = t_gz_member(buf, "hello gzip", 10, 30u);
    buf[n - 4] ^= 1;                               /* ISIZE */
    if (!gz_is(t, buf, n, READ_GZ_SIZE, "", "ISIZE")) return;
    n = t_gz_member(buf, "hello gzip", 10, 2u);
    buf[10] ^= 1;                                  /* the header's CRC-16 */
    if (!gz_is(t, buf, n, READ_GZ_CRC, "", "header CRC")) return;
    n = t_gz_member(buf, "hello gzip", 10, 0u);
    buf[2] = 7;                                    /* CM 7: not deflate */
    if (!gz_is(t, buf, n, READ_GZ_HEADER, "", "CM 7")) return;
    n = t_gz_member(buf, "hello gzip", 10, 0u);
    buf[3] = 0x20;                                 /* a reserved flag bit */
    if (!gz_is(t, buf, n, READ_GZ_HEADER, "", "reserved FLG bit")) return;
    n = t_gz_member(buf, "hello gzip", 10, 0u);
    buf[n++] = '\n';                               /* a byte after the member */
    if (!gz_is(t, buf, n, READ_GZ_HEADER, "", "trailing byte")) return;
    n = t_gz_member(buf, "hello gzip", 10, 0u);
    buf[n - 8 - 15] = 3;                           /* BTYPE 11 */
    if (!gz_is(t, buf, n, READ_GZ_DATA, "", "block type 3")) return;
    n = t_gz_member(buf, "hello gzip", 10, 30u);
    for (cut = 0; cut < n; cut++) {
        char what[96];
        snprintf(what, sizeof what, "cut to %lu of %lu bytes", (unsigned long)cut, (unsigned long)n);
        if (!gz_is(t, buf, cut, READ_GZ_TRUNC, "", what)) return;
    }
    CHECK(t, gzip_inflate(buf, n, 9, &out, &n_out) == READ_GZ_BIG && !out,
          "10 bytes with a limit of 9 not refused as too big");
    /* a back-reference into the member before: "x", then a fixed block whose
       first symbol copies 3 bytes from 1 back */
    n = t_gz_member(buf, "x", 1, 0u);
    n += t_gz_header(buf + n, 0u);
    memset(&w, 0, sizeof w);
    put_bits(&w, 1, 1); put_bits(&w, 1, 2);        /* BFINAL, fixed Huffman */
    put_code(&w, 1, 7); put_code(&w, 0, 5);        /* length 3, distance 1 */
    put_code(&w, 0, 7);                            /* end of block */
    memcpy(buf + n, w.b, 3);
    t_le32(buf + n + 3, t_crc((const unsigned char *)"xxx", 3));
    t_le32(buf + n + 7, 3u);
    if (!gz_is(t, buf, n + 11, READ_GZ_DATA, "", "back-reference across members")) return;
}

/* 1 if the two renders of scene files a and b are the same bytes. */
static int same_render(T *t, const char *a, const char *b)
{
    Image im[2];
    int k, same;
    for (k = 0; k < 2; k++) {
        Scene s;
        RenderOptions o;
        RenderStats st;
        Error e;
        memset(&im[k], 0, sizeof im[k]);
        if (!scene_load(&s, k ? b : a, &e)) {
            if (k) img_free(&im[0]);
            test_failf(t, __FILE__, __LINE__, "%s", e.msg);
            return 0;
        }
        render_options_default(&o);
        o.progress = 0;
        if (!render(&s, &o, &im[k], &st, &e)) {
            scene_free(&s);
            if (k) img_free(&im[0]);
            test_failf(t, __FILE__, __LINE__, "%s", e.msg);
            return 0;
        }
        scene_free(&s);
    }
    same = im[0].w == im[1].w && im[0].h == im[1].h && im[0].w == 24 &&
           !memcmp(im[0].rgb, im[1].rgb, sizeof(float) * 3 * (size_t)im[0].w * (size_t)im[0].h);
    img_free(&im[0]);
    img_free(&im[1]);
    return same;
}

/* tests/data/gz: room.pbrt.gz (one member with FNAME, as gzip writes it) Includes
   light.pbrt.gz (two members) and reads box.ply.gz (FEXTRA, FNAME, FCOMMENT,
   FHCRC): the image is the one of their uncompressed twins, byte for byte, and the
   mesh the same arrays.  A damaged copy is refused with "file: gzip: ...". */
static void test_gzip_twins(T *t)
{
    PlyMesh m[2];
    Error e;
    unsigned char *raw;
    size_t n;
    ReadStatus rs;
    Scene s;
    const char *bad;
    FILE *f;
    int k;
    CHECK(t, same_render(t, "tests/data/gz/room.pbrt", "tests/data/gz/room.pbrt.gz"),
          "room.pbrt.gz renders otherwise than room.pbrt");
    for (k = 0; k < 2; k++)
        CHECK(t, ply_read(k ? "tests/data/gz/box.ply.gz" : "tests/data/gz/box.ply", &m[k], &e), "%s", e.msg);
    k = m[0].n_verts == 8 && m[1].n_verts == 8 && m[0].n_tris == 12 && m[1].n_tris == 12 &&
        !memcmp(m[0].P, m[1].P, 24 * sizeof(float)) && !memcmp(m[0].idx, m[1].idx, 36 * sizeof(int32_t));
    ply_free(&m[0]);
    ply_free(&m[1]);
    CHECK(t, k, "box.ply.gz differs from box.ply");
    raw = (unsigned char *)read_whole_file("tests/data/gz/room.pbrt.gz", 0, NULL, &n, &rs);
    CHECK(t, rs == READ_GZIP && !raw, "gzip data read without READ_GUNZIP: status %d", (int)rs);
    raw = (unsigned char *)read_whole_file_gz("tests/data/gz/box.ply.gz", READ_TEXT, NULL, &n, &rs);
    CHECK(t, rs == READ_NUL && !raw, "binary PLY data read as text: status %d", (int)rs);
    {
        static unsigned char gz[4096];
        f = fopen("tests/data/gz/room.pbrt.gz", "rb");
        CHECK(t, f != NULL, "open room.pbrt.gz");
        n = fread(gz, 1, sizeof gz, f);
        fclose(f);
        gz[n - 6] ^= 0x10;                         /* a byte of the CRC-32 */
        bad = test_path(t, "bad-crc.pbrt.gz");
        f = fopen(bad, "wb");
        CHECK(t, f != NULL, "write %s", bad);
        fwrite(gz, 1, n, f);
        fclose(f);
    }
    CHECK(t, !scene_load(&s, bad, &e) && strstr(e.msg, "bad-crc.pbrt.gz: gzip: CRC-32 mismatch"),
          "a damaged CRC-32: \"%s\"", e.msg);
    bad = test_write_file(t, "inc-bad.pbrt", "WorldBegin\nInclude \"bad-crc.pbrt.gz\"\n");
    CHECK(t, !scene_load(&s, bad, &e) && strstr(e.msg, "inc-bad.pbrt:2: Include")
          && strstr(e.msg, "gzip: CRC-32 mismatch"), "an Included damaged file: \"%s\"", e.msg);
}

const TestCase tests_png[] = {
    { "png_fixtures", test_png_fixtures },
    { "png_writer_roundtrip", test_png_writer_roundtrip },
    { "png_malformed", test_png_malformed },
    { "png_corruption_sweep", test_png_corruption_sweep },
    { "png_gzip_members", test_gzip_members },
    { "png_gzip_malformed", test_gzip_malformed },
    { "png_gzip_twins", test_gzip_twins },
    { NULL, NULL }
};
