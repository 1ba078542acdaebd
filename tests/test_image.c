/* tests/test_image.c - tests of image.c and cmd_image.c: PFM/PPM/PNG files, sidecars,
   merge and diff.

   The fixture is a 7x5 red 'F' on blue (stb's trick): asymmetric in x and y, so a
   flipped row order or mirrored columns cannot pass, and red/blue differ in every
   channel, so a channel swap cannot either.  The green channel also carries
   g = x/8 + y/64 (exact in float), which makes every pixel unique.

   The PNG test decodes our own file with a small independent decoder below (chunk
   CRCs, zlib header, stored deflate blocks only, Adler-32, filter 0) and compares the
   pixels with the PPM's, so both 8-bit writers are checked against each other and
   against the formats' rules.  Everything here is exact: no statistics. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* ---------- fixtures and helpers ---------- */

static int in_f(int x, int y)   /* the strokes of the 'F': stem, top bar, middle bar */
{
    return x == 1 || (y == 0 && x >= 1 && x <= 5) || (y == 2 && x >= 1 && x <= 3);
}

static void fixture_pixel(int x, int y, float rgb[3])
{
    float g = (float)x / 8 + (float)y / 64;
    rgb[0] = in_f(x, y) ? 1.0f : 0.0f;   /* red F ... */
    rgb[1] = g;
    rgb[2] = in_f(x, y) ? 0.0f : 1.0f;   /* ... on blue */
}

static int make_fixture(Image *im)
{
    int x, y;
    if (!img_alloc(im, 7, 5)) return 0;
    for (y = 0; y < 5; y++)
        for (x = 0; x < 7; x++) fixture_pixel(x, y, im->rgb + 3 * (y * 7 + x));
    return 1;
}

static int fill(Image *im, int w, int h, float v)
{
    size_t i;
    if (!img_alloc(im, w, h)) return 0;
    for (i = 0; i < (size_t)w * h * 3; i++) im->rgb[i] = v;
    return 1;
}

/* The whole file, malloc'ed (plus a NUL), or NULL. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t cap = 0, len = 0, got;
    if (!f) return NULL;
    do {
        if (len + 4096 + 1 > cap) {
            unsigned char *nb;
            cap = 2 * cap + 8192;
            nb = (unsigned char *)realloc(buf, cap);
            if (!nb) { free(buf); fclose(f); return NULL; }
            buf = nb;
        }
        got = fread(buf + len, 1, 4096, f);
        len += got;
    } while (got > 0);
    fclose(f);
    buf[len] = 0;
    *n = len;
    return buf;
}

static int write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    int ok;
    if (!f) return 0;
    ok = fwrite(data, 1, n, f) == n;
    return fclose(f) == 0 && ok;
}

static float le_float(const unsigned char *b)
{
    uint32_t u = (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) |
                 ((uint32_t)b[3] << 24);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void be_bytes(float f, unsigned char *b)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    b[0] = (unsigned char)(u >> 24); b[1] = (unsigned char)(u >> 16);
    b[2] = (unsigned char)(u >> 8);  b[3] = (unsigned char)u;
}

static void le_bytes(float f, unsigned char *b)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    b[0] = (unsigned char)u;         b[1] = (unsigned char)(u >> 8);
    b[2] = (unsigned char)(u >> 16); b[3] = (unsigned char)(u >> 24);
}

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }

/* The expected 8-bit value of one linear channel (the documented tone curve, written
   out again independently of image.c). */
static int expect8(double v)
{
    double c;
    if (!(v > 0)) v = 0;
    if (v > 1) v = 1;
    c = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
    return (int)(c * 255 + 0.5);
}

/* ---------- a tiny PNG decoder for stored-block files ---------- */

static uint32_t crc32_bitwise(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        c ^= p[i];
        for (k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return c ^ 0xffffffffu;
}

static uint32_t be32(const unsigned char *b)
{
    return ((uint32_t)b[0] << 24) | ((uint32_t)b[1] << 16) | ((uint32_t)b[2] << 8) | b[3];
}

/* Decodes an 8-bit RGB PNG whose IDAT holds stored deflate blocks.  Returns 1 and a
   malloc'ed top-row-first RGB buffer, or 0 with the reason in why. */
static int png_decode(const unsigned char *d, size_t n, int *w, int *h, int *blocks,
                      unsigned char **pix, const char **why)
{
    static const unsigned char sig[8] = { 137, 80, 78, 71, 13, 10, 26, 10 };
    unsigned char *z = NULL, *raw = NULL;
    size_t zn = 0, pos = 8, rn = 0, rcap, zpos;
    uint32_t s1 = 1, s2 = 0;
    int seen_iend = 0, y;
    *pix = NULL; *w = *h = 0; *blocks = 0;
    if (n < 8 || memcmp(d, sig, 8) != 0) { *why = "bad signature"; return 0; }
    z = (unsigned char *)malloc(n);
    if (!z) { *why = "oom"; return 0; }
    while (!seen_iend) {
        uint32_t len;
        if (pos + 12 > n) { *why = "chunk runs past the end"; goto fail; }
        len = be32(d + pos);
        if (pos + 12 + len > n) { *why = "chunk length past the end"; goto fail; }
        if (crc32_bitwise(d + pos + 4, 4 + (size_t)len) != be32(d + pos + 8 + len)) {
            *why = "chunk CRC mismatch"; goto fail;
        }
        if (memcmp(d + pos + 4, "IHDR", 4) == 0) {
            const unsigned char *c = d + pos + 8;
            if (len != 13 || c[8] != 8 || c[9] != 2 || c[10] || c[11] || c[12]) {
                *why = "IHDR is not 8-bit RGB, deflate, no interlace"; goto fail;
            }
            *w = (int)be32(c); *h = (int)be32(c + 4);
        } else if (memcmp(d + pos + 4, "IDAT", 4) == 0) {
            memcpy(z + zn, d + pos + 8, len);
            zn += len;
        } else if (memcmp(d + pos + 4, "IEND", 4) == 0) {
            seen_iend = 1;
        }
        pos += 12 + len;
    }
    if (pos != n) { *why = "bytes after IEND"; goto fail; }
    if (*w <= 0 || *h <= 0) { *why = "no IHDR"; goto fail; }
    /* zlib header: CM = 8 (deflate), no preset dictionary, (CMF*256 + FLG) % 31 == 0 */
    if (zn < 6 || (z[0] & 15) != 8 || (z[1] & 0x20) || ((z[0] << 8) | z[1]) % 31 != 0) {
        *why = "bad zlib header"; goto fail;
    }
    rcap = (size_t)*h * (1 + 3 * (size_t)*w);
    raw = (unsigned char *)malloc(rcap);
    if (!raw) { *why = "oom"; goto fail; }
    zpos = 2;
    for (;;) {
        unsigned len, nlen;
        int final;
        if (zpos + 5 > zn) { *why = "deflate block header past the end"; goto fail; }
        if (((z[zpos] >> 1) & 3) != 0) { *why = "not a stored block"; goto fail; }
        final = z[zpos] & 1;
        len = z[zpos + 1] | ((unsigned)z[zpos + 2] << 8);
        nlen = z[zpos + 3] | ((unsigned)z[zpos + 4] << 8);
        if ((len ^ 0xffffu) != nlen) { *why = "NLEN is not ~LEN"; goto fail; }
        zpos += 5;
        if (zpos + len > zn || rn + len > rcap) { *why = "stored block too long"; goto fail; }
        memcpy(raw + rn, z + zpos, len);
        rn += len; zpos += len;
        ++*blocks;
        if (final) break;
    }
    if (rn != rcap) { *why = "wrong amount of image data"; goto fail; }
    for (pos = 0; pos < rn; pos++) { s1 = (s1 + raw[pos]) % 65521; s2 = (s2 + s1) % 65521; }
    if (zpos + 4 != zn || be32(z + zpos) != ((s2 << 16) | s1)) {
        *why = "Adler-32 mismatch"; goto fail;
    }
    *pix = (unsigned char *)malloc((size_t)*w * *h * 3);
    if (!*pix) { *why = "oom"; goto fail; }
    for (y = 0; y < *h; y++) {
        const unsigned char *row = raw + (size_t)y * (1 + 3 * (size_t)*w);
        if (row[0] != 0) { *why = "row filter is not 0"; free(*pix); *pix = NULL; goto fail; }
        memcpy(*pix + (size_t)y * *w * 3, row + 1, (size_t)*w * 3);
    }
    free(z); free(raw);
    return 1;
fail:
    free(z); free(raw);
    return 0;
}

/* ---------- running the subcommands with captured output ---------- */

typedef struct { int rc; char out[4096]; char err[4096]; } CmdRun;

static void read_back(FILE *f, char *buf, size_t cap)
{
    size_t n;
    rewind(f);
    n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
}

static int run_cmd(T *t, int (*cmd)(int, char **, FILE *, FILE *), int argc, char **argv,
                   CmdRun *r)
{
    FILE *o = fopen(test_path(t, "image_cmd_stdout.txt"), "w+");
    FILE *e = fopen(test_path(t, "image_cmd_stderr.txt"), "w+");
    if (!o || !e) { if (o) fclose(o); if (e) fclose(e); return 0; }
    r->rc = cmd(argc, argv, o, e);
    read_back(o, r->out, sizeof r->out);
    read_back(e, r->err, sizeof r->err);
    return 1;
}

/* A copy of a test_path() result (its buffers are reused after 8 calls). */
static void tpath(T *t, char *dst, const char *name)
{
    snprintf(dst, 1024, "%s", test_path(t, name));
}

static int write_pfm_with_spp(const char *path, const Image *im, long spp)
{
    return pfm_write(im, path) && (spp < 0 || img_write_sidecar(path, spp, "test"));
}

/* ---------- tests ---------- */

static void test_alloc(T *t)
{
    Image im;
    size_t i;
    CHECK(t, img_alloc(&im, 3, 2), "img_alloc 3x2 failed");
    CHECK(t, im.w == 3 && im.h == 2 && im.rgb, "img_alloc did not fill the image");
    for (i = 0; i < 18; i++) CHECK(t, im.rgb[i] == 0.0f, "pixel value %zu not zero", i);
    img_free(&im);
    CHECK(t, im.rgb == NULL && im.w == 0, "img_free did not reset the image");
    img_free(&im);                                          /* twice is harmless */
    CHECK(t, !img_alloc(&im, 0, 5) && im.rgb == NULL, "0x5 accepted");
    CHECK(t, !img_alloc(&im, -3, 5), "negative width accepted");
    CHECK(t, !img_alloc(&im, 1 << 15, 1 << 14), "2^29 pixels accepted (cap is 2^28)");
}

static void test_pfm_roundtrip(T *t)
{
    Image im, back;
    Error err;
    char path[1024];
    unsigned char *d;
    size_t n, off;
    int x, y, c;
    const char header[] = "PF\n7 5\n-1.0\n";
    tpath(t, path, "image_f.pfm");
    CHECK(t, make_fixture(&im), "fixture");
    CHECK(t, pfm_write(&im, path), "pfm_write failed");

    /* the raw bytes: header, then the BOTTOM row first, little-endian floats */
    d = slurp(path, &n);
    CHECK(t, d != NULL, "cannot read back %s", path);
    off = sizeof header - 1;
    if (n != off + 7 * 5 * 12 || memcmp(d, header, off) != 0) {
        free(d); img_free(&im);
        CHECK(t, 0, "PFM header/size wrong: %zu bytes", n);
    }
    for (y = 0; y < 5; y++)             /* file row r holds image row 4 - r */
        for (x = 0; x < 7; x++)
            for (c = 0; c < 3; c++) {
                float want[3], got = le_float(d + off + 12 * ((size_t)(4 - y) * 7 + x) + 4 * c);
                fixture_pixel(x, y, want);
                if (got != want[c]) {
                    free(d); img_free(&im);
                    CHECK(t, 0, "raw PFM pixel (%d,%d) channel %d is %g, want %g", x, y, c,
                          (double)got, (double)want[c]);
                }
            }
    /* spot checks spelled out: first pixel in the file = bottom-left = blue, g = 4/64,
       and the exact little-endian bytes of 1.0f (00 00 80 3F) in its blue channel */
    c = d[off + 8] == 0x00 && d[off + 9] == 0x00 && d[off + 10] == 0x80 && d[off + 11] == 0x3F &&
        le_float(d + off) == 0.0f && le_float(d + off + 4) == 0.0625f &&
        le_float(d + off + 12) == 1.0f;                    /* (1, bottom) is the F's stem */
    free(d);
    if (!c) { img_free(&im); CHECK(t, 0, "first file pixels are not the bottom row"); }

    /* and the reader inverts it exactly */
    if (!pfm_read(&back, path, &err)) { img_free(&im); CHECK(t, 0, "pfm_read: %s", err.msg); }
    c = back.w == 7 && back.h == 5 && memcmp(back.rgb, im.rgb, sizeof(float) * 105) == 0;
    img_free(&back); img_free(&im);
    CHECK(t, c, "PFM round trip changed the image");
}

static void test_pfm_big_endian_and_grey(T *t)
{
    /* 2x2 big-endian RGB, scale +1: file rows bottom first */
    unsigned char buf[256];
    const char *h1 = "PF\n2 2\n1.0\n", *h2 = "Pf \t 3\r\n\n  2\n-1\n", *h3 = "PF\n1 1\n2.5\n";
    size_t n, i;
    Image im;
    Error err;
    char path[1024];
    int ok;
    tpath(t, path, "image_be.pfm");
    n = strlen(h1);
    memcpy(buf, h1, n);
    for (i = 0; i < 12; i++) be_bytes((float)(i + 1), buf + n + 4 * i);   /* 1 .. 12 */
    CHECK(t, write_bytes(path, buf, n + 48), "write %s", path);
    CHECK(t, pfm_read(&im, path, &err), "big-endian PFM rejected: %s", err.msg);
    /* top row (y = 0) is the file's second row: 7 8 9 | 10 11 12 */
    ok = im.w == 2 && im.h == 2 && im.rgb[0] == 7 && im.rgb[1] == 8 && im.rgb[2] == 9 &&
         im.rgb[3] == 10 && im.rgb[6] == 1 && im.rgb[11] == 6;
    img_free(&im);
    CHECK(t, ok, "big-endian PFM decoded wrongly");

    /* grey 3x2, little-endian, odd whitespace in the header */
    tpath(t, path, "image_grey.pfm");
    n = strlen(h2);
    memcpy(buf, h2, n);
    for (i = 0; i < 6; i++) le_bytes((float)i * 0.5f, buf + n + 4 * i);   /* 0 .. 2.5 */
    CHECK(t, write_bytes(path, buf, n + 24), "write %s", path);
    CHECK(t, pfm_read(&im, path, &err), "grey PFM rejected: %s", err.msg);
    /* top row = second file row: 1.5 2 2.5, each replicated to r = g = b */
    ok = im.w == 3 && im.h == 2 && im.rgb[0] == 1.5f && im.rgb[1] == 1.5f &&
         im.rgb[2] == 1.5f && im.rgb[8] == 2.5f && im.rgb[9] == 0.0f && im.rgb[17] == 1.0f;
    img_free(&im);
    CHECK(t, ok, "grey PFM decoded wrongly (rows or replication)");

    /* |scale| != 1 multiplies the samples */
    tpath(t, path, "image_scale.pfm");
    n = strlen(h3);
    memcpy(buf, h3, n);
    for (i = 0; i < 3; i++) be_bytes(2.0f, buf + n + 4 * i);
    CHECK(t, write_bytes(path, buf, n + 12), "write %s", path);
    CHECK(t, pfm_read(&im, path, &err), "scale 2.5 PFM rejected: %s", err.msg);
    ok = im.rgb[0] == 5.0f && im.rgb[2] == 5.0f;
    img_free(&im);
    CHECK(t, ok, "scale 2.5 not applied");
}

/* pfm_read must fail on text with the message "path: ...want..." on one line. */
static int pfm_fails(T *t, const char *name, const void *data, size_t n, const char *want,
                     char *msg)
{
    char path[1024];
    Image im;
    Error err;
    size_t plen;
    tpath(t, path, name);
    if (data && !write_bytes(path, data, n)) { sprintf(msg, "cannot write %s", path); return 0; }
    err.msg[0] = '\0';
    im.rgb = (float *)&im;                     /* garbage the reader must overwrite */
    if (pfm_read(&im, path, &err)) { img_free(&im); sprintf(msg, "%s accepted", name); return 0; }
    plen = strlen(path);
    if (im.rgb != NULL || strncmp(err.msg, path, plen) != 0 || strncmp(err.msg + plen, ": ", 2) ||
        !strstr(err.msg, want) || strchr(err.msg, '\n')) {
        sprintf(msg, "%s: message '%.300s' lacks '%s'", name, err.msg, want);
        return 0;
    }
    return 1;
}

static void test_pfm_errors(T *t)
{
    char msg[1024];
    unsigned char buf[64];
    size_t n;
    const char *hdr = "PF\n2 2\n-1.0\n";
    memset(buf, 0, sizeof buf);
    n = strlen(hdr);
    memcpy(buf, hdr, n);
    CHECK(t, pfm_fails(t, "image_e1.pfm", "P6\n2 2\n255\n", 11, "bad magic", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e2.pfm", "PX\n2 2\n-1\n", 10, "bad magic", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e3.pfm", "", 0, "bad magic", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e4.pfm", buf, n + 47, "truncated", msg), "%s", msg); /* 1 byte short */
    CHECK(t, pfm_fails(t, "image_e5.pfm", "PF\n2 2", 6, "truncated header", msg), "%s", msg);
    /* a header promising 16000x16000 pixels (3 GB) over 4 bytes of data: refused from
       the file size, before allocating */
    CHECK(t, pfm_fails(t, "image_e5b.pfm", "PF\n16000 16000\n-1\nabcd", 22,
                       "need 3072000000 bytes of data, the file has 4", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e6.pfm", "PF\n100000 100000\n-1\n", 20, "too large", msg),
          "%s", msg);
    CHECK(t, pfm_fails(t, "image_e7.pfm", "PF\n999999999999 1\n-1\n", 21, "bad width", msg),
          "%s", msg);
    CHECK(t, pfm_fails(t, "image_e8.pfm", "PF\n0 2\n-1\n", 10, "bad width", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e9.pfm", "PF\n2 -2\n-1\n", 11, "bad height", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e10.pfm", "PF\n1 1\nnan\n\0\0\0\0\0\0\0\0\0\0\0\0", 23,
                       "scale is NaN", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e11.pfm", "PF\n1 1\n0.0\n\0\0\0\0\0\0\0\0\0\0\0\0", 23,
                       "nonzero", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_e12.pfm", "PF\n# hi\n1 1\n-1\n", 15, "comments", msg),
          "%s", msg);
    CHECK(t, pfm_fails(t, "image_e13.pfm", "PF\n1 1\n-1x\n", 11, "bad scale", msg), "%s", msg);
    CHECK(t, pfm_fails(t, "image_missing_file.pfm", NULL, 0, "cannot open", msg), "%s", msg);
    /* a header of blanks only: stops after 1 KiB */
    {
        char blanks[2100];
        memset(blanks, ' ', sizeof blanks);
        blanks[0] = 'P'; blanks[1] = 'F';
        CHECK(t, pfm_fails(t, "image_e15.pfm", blanks, sizeof blanks, "header longer", msg),
              "%s", msg);
    }
}

static void test_srgb(T *t)
{
    CHECK(t, srgb_oetf(0.0f) == 0.0f, "oetf(0) = %g", (double)srgb_oetf(0.0f));
    /* 12.92 * 0.0031308 = 0.04044994 (the linear piece, including its end point) */
    CHECK(t, near((double)srgb_oetf(0.0031308f), 0.04044994, 1e-6), "oetf(0.0031308) = %.8f",
          (double)srgb_oetf(0.0031308f));
    /* 1.055 * 0.5^(1/2.4) - 0.055 = 0.7353570 */
    CHECK(t, near((double)srgb_oetf(0.5f), 0.7353570, 1e-6), "oetf(0.5) = %.8f",
          (double)srgb_oetf(0.5f));
    CHECK(t, near((double)srgb_oetf(1.0f), 1.0, 1e-6), "oetf(1) = %.8f", (double)srgb_oetf(1.0f));
    /* continuous at the knee: the power piece just above gives nearly the same */
    CHECK(t, near((double)srgb_oetf(0.0031309f), 0.04045, 2e-6), "oetf knee discontinuous");
}

static void test_ppm_bytes(T *t)
{
    Image im;
    char path[1024];
    unsigned char *d;
    size_t n, off;
    const char header[] = "P6\n7 5\n255\n";
    int x, y, c, bad = -1;
    tpath(t, path, "image_f.ppm");
    CHECK(t, make_fixture(&im), "fixture");
    CHECK(t, ppm_write(&im, path, 0.0f), "ppm_write failed");
    d = slurp(path, &n);
    CHECK(t, d != NULL, "cannot read %s", path);
    off = sizeof header - 1;
    if (n != off + 105 || memcmp(d, header, off) != 0) {
        free(d); img_free(&im);
        CHECK(t, 0, "PPM header or size wrong (%zu bytes)", n);
    }
    for (y = 0; y < 5 && bad < 0; y++)           /* TOP row first in a PPM */
        for (x = 0; x < 7; x++)
            for (c = 0; c < 3; c++) {
                float want[3];
                fixture_pixel(x, y, want);
                if (d[off + 3 * (7 * y + x) + c] != expect8((double)want[c])) bad = 3 * (7 * y + x) + c;
            }
    /* explicitly: first pixel top-left blue (0, g=0, 255), second the F's red */
    if (bad < 0 && !(d[off] == 0 && d[off + 1] == 0 && d[off + 2] == 255 && d[off + 3] == 255 &&
                     d[off + 5] == 0)) bad = 0;
    free(d);
    if (bad >= 0) { img_free(&im); CHECK(t, 0, "PPM byte %d wrong", bad); }

    /* exposure +2 multiplies by 4, then clamping to [0, 1] and NaN -> 0 */
    im.rgb[0] = 0.125f; im.rgb[1] = 0.375f; im.rgb[2] = -1.0f;
    {
        volatile float zero = 0.0f;
        im.rgb[3] = zero / zero;                  /* a NaN */
    }
    CHECK(t, ppm_write(&im, path, 2.0f), "ppm_write with exposure failed");
    d = slurp(path, &n);
    img_free(&im);
    CHECK(t, d != NULL, "cannot read %s", path);
    c = d[off] == expect8(0.5) && d[off] == 188 && d[off + 1] == 255 && d[off + 2] == 0 &&
        d[off + 3] == 0;
    free(d);
    CHECK(t, c, "exposure/clamp/NaN handling wrong");
}

static void test_png_decode(T *t)
{
    Image im;
    char path[1024], ppath[1024];
    unsigned char *d, *pix = NULL, *ppm;
    size_t n, pn, i;
    int w, h, blocks, ok;
    const char *why = "";
    tpath(t, path, "image_f.png");
    tpath(t, ppath, "image_f2.ppm");
    CHECK(t, make_fixture(&im), "fixture");
    ok = png_write(&im, path, 0.0f) && ppm_write(&im, ppath, 0.0f);
    img_free(&im);
    CHECK(t, ok, "png_write/ppm_write failed");
    d = slurp(path, &n);
    ppm = slurp(ppath, &pn);
    if (!d || !ppm) { free(d); free(ppm); CHECK(t, 0, "cannot read the files back"); }
    ok = png_decode(d, n, &w, &h, &blocks, &pix, &why);
    free(d);
    if (!ok) { free(ppm); CHECK(t, 0, "our PNG does not decode: %s", why); }
    /* same pixels as the PPM (whose bytes test_ppm_bytes checks), top row first */
    ok = w == 7 && h == 5 && blocks == 1 && pn == 11 + 105 && memcmp(pix, ppm + 11, 105) == 0;
    free(pix); free(ppm);
    CHECK(t, ok, "PNG pixels differ from the PPM's (w %d h %d blocks %d)", w, h, blocks);

    /* 200x120: 120 * 601 = 72120 bytes of rows -> 2 stored blocks (65535 + 6585) */
    CHECK(t, img_alloc(&im, 200, 120), "alloc");
    for (i = 0; i < (size_t)200 * 120 * 3; i++) im.rgb[i] = (float)(i % 251) / 250.0f;
    ok = png_write(&im, path, 0.0f);
    CHECK(t, ok, "png_write 200x120 failed");
    d = slurp(path, &n);
    if (!d) { img_free(&im); CHECK(t, 0, "cannot read back"); }
    ok = png_decode(d, n, &w, &h, &blocks, &pix, &why);
    free(d);
    if (!ok) { img_free(&im); CHECK(t, 0, "200x120 PNG does not decode: %s", why); }
    ok = w == 200 && h == 120 && blocks == 2;
    for (i = 0; ok && i < (size_t)200 * 120 * 3; i++)
        if (pix[i] != expect8((double)im.rgb[i])) ok = 0;
    free(pix); img_free(&im);
    CHECK(t, ok, "200x120 PNG wrong (blocks %d, first bad byte %zu)", blocks, i);

    /* png_write_rgb8 rejects nonsense */
    CHECK(t, !png_write_rgb8(path, 0, 3, (const unsigned char *)"abc"), "0 width accepted");
}

static void test_write_dispatch(T *t)
{
    Image im, back;
    Error err;
    char path[1024], want[1200];
    size_t n;
    unsigned char *d;
    int ok;
    CHECK(t, make_fixture(&im), "fixture");
    /* upper-case extensions are fine */
    tpath(t, path, "image_UPPER.PFM");
    if (!img_write(&im, path, 0.0f, &err)) { img_free(&im); CHECK(t, 0, "%s", err.msg); }
    ok = pfm_read(&back, path, &err) && back.w == 7 && back.h == 5 &&
         memcmp(back.rgb, im.rgb, 105 * sizeof(float)) == 0;
    img_free(&back);
    if (!ok) { img_free(&im); CHECK(t, 0, ".PFM did not round trip"); }
    tpath(t, path, "image_dispatch.Png");
    ok = img_write(&im, path, 0.0f, &err) && (d = slurp(path, &n)) != NULL;
    if (ok) { ok = n > 8 && d[1] == 'P' && d[2] == 'N' && d[3] == 'G'; free(d); }
    if (!ok) { img_free(&im); CHECK(t, 0, ".Png did not write a PNG"); }
    tpath(t, path, "image_dispatch.ppm");
    ok = img_write(&im, path, 0.0f, &err) && (d = slurp(path, &n)) != NULL;
    if (ok) { ok = n > 2 && d[0] == 'P' && d[1] == '6'; free(d); }
    if (!ok) { img_free(&im); CHECK(t, 0, ".ppm did not write a PPM"); }

    /* unsupported format: the exact message */
    tpath(t, path, "image_out.exr");
    ok = !img_write(&im, path, 0.0f, &err);
    snprintf(want, sizeof want, "%s: unsupported output format '.exr' (use .pfm, .ppm or .png)",
             path);
    if (!ok || strcmp(err.msg, want) != 0) {
        img_free(&im);
        CHECK(t, 0, "exr: got '%s'", err.msg);
    }
    /* a dot in a directory name is not an extension */
    tpath(t, path, "image.dir/noext");
    ok = !img_write(&im, path, 0.0f, &err) && strstr(err.msg, "no file extension") != NULL;
    if (!ok) { img_free(&im); CHECK(t, 0, "noext: got '%s'", err.msg); }
    /* I/O failure: a missing directory */
    tpath(t, path, "image_no_such_dir/x.pfm");
    ok = !img_write(&im, path, 0.0f, &err) && strstr(err.msg, "cannot write") != NULL &&
         strncmp(err.msg, path, strlen(path)) == 0;
    CHECK(t, !pfm_write(&im, path) && !ppm_write(&im, path, 0) && !png_write(&im, path, 0),
          "writers claim success on a missing directory");
    img_free(&im);
    CHECK(t, ok, "missing dir: got '%s'", err.msg);
}

static void test_sidecar(T *t)
{
    char path[1024];
    tpath(t, path, "image_side.pfm");
    CHECK(t, img_write_sidecar(path, 64, "spp 5 would be wrong\nsecond line"), "write");
    CHECK(t, img_read_sidecar_spp(path) == 64, "spp read back as %ld",
          img_read_sidecar_spp(path));
    test_write_file(t, "image_side2.pfm.txt", "settings x\nspp  12 \n");
    tpath(t, path, "image_side2.pfm");
    CHECK(t, img_read_sidecar_spp(path) == 12, "spp after settings: %ld",
          img_read_sidecar_spp(path));
    test_write_file(t, "image_side3.pfm.txt", "spp twelve\n");
    tpath(t, path, "image_side3.pfm");
    CHECK(t, img_read_sidecar_spp(path) == -1, "malformed spp accepted");
    test_write_file(t, "image_side4.pfm.txt", "spp -4\n");
    tpath(t, path, "image_side4.pfm");
    CHECK(t, img_read_sidecar_spp(path) == -1, "negative spp accepted");
    tpath(t, path, "image_side_missing.pfm");
    CHECK(t, img_read_sidecar_spp(path) == -1, "missing sidecar gave a count");
    /* unknown spp (-1) writes no spp line */
    tpath(t, path, "image_side5.pfm");
    CHECK(t, img_write_sidecar(path, -1, "merged"), "write");
    CHECK(t, img_read_sidecar_spp(path) == -1, "spp -1 was written");
}

static void test_merge(T *t)
{
    Image a, b, in[2], out, m;
    Error err;
    char pa[1024], pb[1024], po[1024];
    char *argv[5];
    double wts[2] = { 1.0, 3.0 };
    CmdRun r;
    size_t i;
    int ok;
    tpath(t, pa, "image_m1.pfm");
    tpath(t, pb, "image_m3.pfm");
    tpath(t, po, "image_m_out.pfm");
    CHECK(t, fill(&a, 5, 3, 1.0f) && fill(&b, 5, 3, 5.0f), "alloc");
    ok = write_pfm_with_spp(pa, &a, 1) && write_pfm_with_spp(pb, &b, 3);
    /* library: (1*1 + 3*5) / 4 = 4 */
    in[0] = a; in[1] = b;
    ok = ok && img_merge(in, wts, 2, &m);
    for (i = 0; ok && i < 45; i++) ok = m.rgb[i] == 4.0f;
    if (ok) img_free(&m);
    ok = ok && img_merge(in, NULL, 2, &m) && m.rgb[7] == 3.0f;     /* equal weights */
    if (ok) img_free(&m);
    wts[0] = -1.0;
    ok = ok && !img_merge(in, wts, 2, &m);
    img_free(&a); img_free(&b);
    CHECK(t, ok, "img_merge wrong");

    /* the subcommand reads the weights from the sidecars */
    argv[0] = "merge"; argv[1] = pa; argv[2] = pb; argv[3] = "-o"; argv[4] = po;
    CHECK(t, run_cmd(t, img_cmd_merge, 5, argv, &r), "cannot capture output");
    CHECK(t, r.rc == 0, "merge failed (%d): %s", r.rc, r.err);
    CHECK(t, pfm_read(&out, po, &err), "%s", err.msg);
    ok = out.w == 5 && out.h == 3;
    for (i = 0; ok && i < 45; i++) ok = out.rgb[i] == 4.0f;
    img_free(&out);
    CHECK(t, ok, "merged pixel %zu is not 4", i);
    CHECK(t, img_read_sidecar_spp(po) == 4, "merged sidecar spp %ld, want 4",
          img_read_sidecar_spp(po));
    CHECK(t, strstr(r.out, "4 spp") != NULL, "no summary: '%s'", r.out);
}

static void test_merge_errors(T *t)
{
    Image a, c;
    Error err;
    char pa[1024], pn[1024], pc[1024], po[1024], pe[1024], want[1200];
    char *argv[6];
    CmdRun r;
    int ok;
    tpath(t, pa, "image_me_a.pfm");
    tpath(t, pn, "image_me_nosidecar.pfm");
    tpath(t, pc, "image_me_small.pfm");
    tpath(t, po, "image_me_out.pfm");
    tpath(t, pe, "image_me_out.exr");
    CHECK(t, fill(&a, 4, 4, 1.0f) && fill(&c, 3, 4, 1.0f), "alloc");
    a.rgb[0] = 5.0f;
    ok = write_pfm_with_spp(pa, &a, 2) && write_pfm_with_spp(pn, &a, -1) &&
         write_pfm_with_spp(pc, &c, 2);
    img_free(&a); img_free(&c);
    CHECK(t, ok, "writing the inputs failed");
    remove(test_path(t, "image_me_nosidecar.pfm.txt"));

    /* an input without a sidecar: exit 1, "path: ..." */
    argv[0] = "merge"; argv[1] = pa; argv[2] = pn; argv[3] = "-o"; argv[4] = po;
    CHECK(t, run_cmd(t, img_cmd_merge, 5, argv, &r), "capture");
    snprintf(want, sizeof want, "%s: no sidecar", pn);
    CHECK(t, r.rc == 1 && strncmp(r.err, want, strlen(want)) == 0,
          "missing sidecar: rc %d '%s'", r.rc, r.err);
    /* ... unless --equal-weights; the result's spp is then unknown */
    argv[5] = "--equal-weights";
    CHECK(t, run_cmd(t, img_cmd_merge, 6, argv, &r), "capture");
    CHECK(t, r.rc == 0, "--equal-weights failed: %s", r.err);
    CHECK(t, pfm_read(&a, po, &err), "%s", err.msg);
    ok = a.rgb[0] == 5.0f && a.rgb[3] == 1.0f;
    img_free(&a);
    CHECK(t, ok, "equal-weight merge wrong");
    CHECK(t, img_read_sidecar_spp(po) == -1, "unknown spp written as a number");
    /* different sizes */
    argv[2] = pc;
    CHECK(t, run_cmd(t, img_cmd_merge, 5, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "differs") && strncmp(r.err, pc, strlen(pc)) == 0,
          "size mismatch: rc %d '%s'", r.rc, r.err);
    /* a missing input */
    argv[2] = "image_no_such_input.pfm";
    CHECK(t, run_cmd(t, img_cmd_merge, 5, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "image_no_such_input.pfm: cannot open"),
          "missing input: rc %d '%s'", r.rc, r.err);
    /* an unsupported output format */
    argv[2] = pa; argv[4] = pe;
    CHECK(t, run_cmd(t, img_cmd_merge, 5, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "unsupported output format '.exr'"),
          "exr output: rc %d '%s'", r.rc, r.err);
    /* usage errors: no -o, -o without a name, unknown option, no inputs */
    CHECK(t, run_cmd(t, img_cmd_merge, 3, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "usage:"), "no -o: rc %d '%s'", r.rc, r.err);
    argv[3] = "--frobnicate";
    CHECK(t, run_cmd(t, img_cmd_merge, 5, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "unknown option '--frobnicate'"), "unknown: rc %d", r.rc);
    argv[1] = "-o"; argv[2] = po;
    CHECK(t, run_cmd(t, img_cmd_merge, 3, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "no input images"), "no inputs: rc %d '%s'", r.rc, r.err);
    argv[1] = pa; argv[2] = "-o";
    CHECK(t, run_cmd(t, img_cmd_merge, 3, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "-o needs"), "-o at end: rc %d '%s'", r.rc, r.err);
}

/* ref: 4x2 of 0.5; test: the same but pixel (0,0)'s red = 1.5 (d = 1).
   Over 8 pixels x 3 channels: MSE = MAE = 1/24, relMSE = (1/(0.25 + 0.01)) / 24. */
static int write_diff_pair(T *t, char *ptest, char *pref)
{
    Image a, b;
    int ok;
    tpath(t, ptest, "image_d_test.pfm");
    tpath(t, pref, "image_d_ref.pfm");
    if (!fill(&a, 4, 2, 0.5f)) return 0;
    if (!fill(&b, 4, 2, 0.5f)) { img_free(&a); return 0; }
    a.rgb[0] = 1.5f;
    ok = pfm_write(&a, ptest) && pfm_write(&b, pref);
    img_free(&a); img_free(&b);
    return ok;
}

static void test_diff_metrics(T *t)
{
    Image a, b;
    ImgErr e;
    char ptest[1024], pref[1024];
    char *argv[10];
    CmdRun r;
    const char *line;
    int x0, y0, x1, y1;
    long n;
    double mse, rel, mae;
    const double rel1 = 1.0 / 0.26;

    /* library */
    CHECK(t, fill(&a, 4, 2, 0.5f) && fill(&b, 4, 2, 0.5f), "alloc");
    a.rgb[0] = 1.5f;
    CHECK(t, img_error(&a, &b, 0, 0, 4, 2, &e), "img_error failed");
    CHECK(t, e.n == 8 && near(e.mse, 1.0 / 24, 1e-12) && near(e.mae, 1.0 / 24, 1e-12) &&
          near(e.relmse, rel1 / 24, 1e-9), "whole: n %ld mse %g relmse %g mae %g", e.n,
          e.mse, e.relmse, e.mae);
    CHECK(t, img_error(&a, &b, 0, 0, 1, 1, &e) && e.n == 1 && near(e.mse, 1.0 / 3, 1e-12) &&
          near(e.relmse, rel1 / 3, 1e-9), "pixel (0,0): mse %g", e.mse);
    CHECK(t, img_error(&a, &b, 1, 0, 4, 2, &e) && e.n == 6 && e.mse == 0 && e.relmse == 0,
          "error-free region not zero");
    CHECK(t, !img_error(&a, &b, 2, 0, 2, 2, &e) && !img_error(&a, &b, 0, 0, 5, 2, &e),
          "empty/out-of-range rectangle accepted");
    /* the luminance means (--means): pixel (0,0) of a is (1.5, 0.5, 0.5) */
    CHECK(t, img_error(&a, &b, 0, 0, 4, 2, &e) && near(e.y_ref, 0.5, 1e-6) &&
          near(e.y_test, 0.5 + 0.212671 / 8.0, 1e-6), "Y means %g %g", e.y_test, e.y_ref);
    CHECK(t, img_error(&a, &b, 1, 0, 4, 2, &e) && near(e.y_test, 0.5, 1e-6), "Y mean of a region %g", e.y_test);
    img_free(&b);
    CHECK(t, fill(&b, 2, 4, 0.5f), "alloc");
    CHECK(t, !img_error(&a, &b, 0, 0, 1, 1, &e), "size mismatch accepted");
    img_free(&a); img_free(&b);

    /* subcommand, CSV; region C is clipped from (-5,-5,2,100) to (0,0,2,2) */
    CHECK(t, write_diff_pair(t, ptest, pref), "writing the pair");
    argv[0] = "diff"; argv[1] = ptest; argv[2] = pref; argv[3] = "--csv";
    argv[4] = "--region"; argv[5] = "A:0,0,1,1"; argv[6] = "--region"; argv[7] = "C:-5,-5,2,100";
    argv[8] = "--region"; argv[9] = "1,0,4,2";
    CHECK(t, run_cmd(t, img_cmd_diff, 10, argv, &r), "capture");
    CHECK(t, r.rc == 0, "diff failed (%d): %s", r.rc, r.err);
    CHECK(t, strncmp(r.out, "region,x0,y0,x1,y1,pixels,mse,relmse,mae\n", 41) == 0,
          "CSV header: '%.60s'", r.out);
    line = strstr(r.out, "\nimage,");
    CHECK(t, line && sscanf(line + 7, "%d,%d,%d,%d,%ld,%lf,%lf,%lf", &x0, &y0, &x1, &y1, &n,
                            &mse, &rel, &mae) == 8, "no image line: '%s'", r.out);
    CHECK(t, x1 == 4 && y1 == 2 && n == 8 && near(mse, 1.0 / 24, 1e-8) &&
          near(rel, rel1 / 24, 1e-8) && near(mae, 1.0 / 24, 1e-8), "image line wrong");
    line = strstr(r.out, "\nA,");
    CHECK(t, line && sscanf(line + 3, "%d,%d,%d,%d,%ld,%lf,%lf", &x0, &y0, &x1, &y1, &n, &mse,
                            &rel) == 7 && n == 1 && near(mse, 1.0 / 3, 1e-8) &&
          near(rel, rel1 / 3, 1e-8), "region A wrong: '%s'", r.out);
    line = strstr(r.out, "\nC,");
    CHECK(t, line && sscanf(line + 3, "%d,%d,%d,%d,%ld,%lf", &x0, &y0, &x1, &y1, &n, &mse) == 6 &&
          x0 == 0 && y0 == 0 && x1 == 2 && y1 == 2 && n == 4 && near(mse, 1.0 / 12, 1e-8),
          "region C not clipped: '%s'", r.out);
    line = strstr(r.out, "\nregion3,");
    CHECK(t, line && sscanf(line + 9, "%d,%d,%d,%d,%ld,%lf", &x0, &y0, &x1, &y1, &n, &mse) == 6 &&
          n == 6 && mse == 0, "unnamed region wrong: '%s'", r.out);

    /* the text table names each row */
    CHECK(t, run_cmd(t, img_cmd_diff, 3, argv, &r), "capture");
    CHECK(t, r.rc == 0 && strstr(r.out, "relMSE") && strstr(r.out, "\nimage "),
          "text output: '%s'", r.out);
    /* --help states eps */
    argv[1] = "--help";
    CHECK(t, run_cmd(t, img_cmd_diff, 2, argv, &r), "capture");
    CHECK(t, r.rc == 0 && strstr(r.out, "eps = 1e-2") && strstr(r.out, "Rousselle"),
          "--help lacks eps: '%s'", r.out);
}

static void test_diff_thresholds(T *t)
{
    char ptest[1024], pref[1024];
    char *argv[7];
    CmdRun r;
    CHECK(t, write_diff_pair(t, ptest, pref), "writing the pair");
    argv[0] = "diff"; argv[1] = ptest; argv[2] = pref; argv[3] = "--max-mse";
    argv[4] = "0.05";                                     /* MSE = 0.041667 <= 0.05 */
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 0 && r.err[0] == '\0', "under threshold: rc %d '%s'", r.rc, r.err);
    argv[4] = "0.04";                                     /* exceeded */
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "MSE 0.0416667 exceeds --max-mse 0.04") &&
          strchr(r.err, '\n') == r.err + strlen(r.err) - 1, "over: rc %d '%s'", r.rc, r.err);
    argv[3] = "--max-relmse"; argv[4] = "0.2";            /* relMSE = 0.160256 */
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 0, "relmse under: rc %d '%s'", r.rc, r.err);
    argv[4] = "0.1";
    argv[5] = "--max-mse"; argv[6] = "1";
    CHECK(t, run_cmd(t, img_cmd_diff, 7, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "relMSE 0.160256 exceeds --max-relmse 0.1") &&
          !strstr(r.err, "--max-mse"), "relmse over: rc %d '%s'", r.rc, r.err);
    /* identical images pass a zero threshold */
    argv[1] = pref; argv[4] = "0"; argv[6] = "0";
    CHECK(t, run_cmd(t, img_cmd_diff, 7, argv, &r), "capture");
    CHECK(t, r.rc == 0, "identical images fail a 0 threshold: '%s'", r.err);
}

static void test_diff_errors(T *t)
{
    char ptest[1024], pref[1024], psmall[1024];
    char *argv[6];
    CmdRun r;
    Image s;
    CHECK(t, write_diff_pair(t, ptest, pref), "writing the pair");
    tpath(t, psmall, "image_d_small.pfm");
    CHECK(t, fill(&s, 2, 2, 0.5f), "alloc");
    CHECK(t, pfm_write(&s, psmall), "write");
    img_free(&s);
    argv[0] = "diff"; argv[1] = ptest; argv[2] = pref; argv[3] = "--region";
    argv[4] = "Z:10,10,20,20";                          /* outside the 4x2 image */
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "region 'Z'") && strstr(r.err, "outside the 4x2"),
          "outside region: rc %d '%s'", r.rc, r.err);
    argv[4] = "E:2,0,2,2";                              /* empty */
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "empty"), "empty region: rc %d '%s'", r.rc, r.err);
    argv[4] = "A:1,2,3";                                /* malformed: usage */
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "bad --region 'A:1,2,3'") && strstr(r.err, "usage:"),
          "bad region: rc %d '%s'", r.rc, r.err);
    argv[3] = "--max-mse"; argv[4] = "abc";
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "bad --max-mse"), "bad threshold: rc %d '%s'", r.rc, r.err);
    argv[4] = "-1";
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 2, "negative threshold: rc %d", r.rc);
    CHECK(t, run_cmd(t, img_cmd_diff, 4, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "needs a value"), "missing value: rc %d", r.rc);
    CHECK(t, run_cmd(t, img_cmd_diff, 2, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "usage:"), "one image: rc %d", r.rc);
    argv[3] = "--bogus";
    CHECK(t, run_cmd(t, img_cmd_diff, 4, argv, &r), "capture");
    CHECK(t, r.rc == 2 && strstr(r.err, "unknown option"), "unknown option: rc %d", r.rc);
    argv[2] = psmall;                                   /* size mismatch */
    CHECK(t, run_cmd(t, img_cmd_diff, 3, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "differs") && strncmp(r.err, ptest, strlen(ptest)) == 0,
          "size mismatch: rc %d '%s'", r.rc, r.err);
    argv[2] = "image_no_such_ref.pfm";
    CHECK(t, run_cmd(t, img_cmd_diff, 3, argv, &r), "capture");
    CHECK(t, r.rc == 1 && strstr(r.err, "image_no_such_ref.pfm: cannot open"),
          "missing ref: rc %d '%s'", r.rc, r.err);
}

static void test_diff_error_image(T *t)
{
    Image a, b;
    char ptest[1024], pref[1024], ppng[1024];
    char *argv[5];
    CmdRun r;
    unsigned char *d, *pix = NULL;
    size_t n;
    int w, h, blocks, ok;
    const char *why = "";
    tpath(t, ptest, "image_ei_test.pfm");
    tpath(t, pref, "image_ei_ref.pfm");
    tpath(t, ppng, "image_ei_err.png");
    CHECK(t, fill(&a, 3, 1, 0.5f) && fill(&b, 3, 1, 0.5f), "alloc");
    /* pixel 0: no error (e = 0 -> the ramp's dark end); pixel 1: e = 1e-2 * ... mid;
       pixel 2: d = 10 in every channel, e = 100 / 0.26 = 385 > 10 -> bright end */
    a.rgb[3] = 0.5f + 0.051f; a.rgb[4] = 0.5f + 0.051f; a.rgb[5] = 0.5f + 0.051f;  /* e = 0.01 */
    a.rgb[6] = a.rgb[7] = a.rgb[8] = 10.5f;
    ok = pfm_write(&a, ptest) && pfm_write(&b, pref);
    img_free(&a); img_free(&b);
    CHECK(t, ok, "write inputs");
    argv[0] = "diff"; argv[1] = ptest; argv[2] = pref; argv[3] = "--error-image"; argv[4] = ppng;
    CHECK(t, run_cmd(t, img_cmd_diff, 5, argv, &r), "capture");
    CHECK(t, r.rc == 0, "diff --error-image failed: %s", r.err);
    d = slurp(ppng, &n);
    CHECK(t, d != NULL, "no error image");
    ok = png_decode(d, n, &w, &h, &blocks, &pix, &why);
    free(d);
    CHECK(t, ok, "error image does not decode: %s", why);
    /* viridis ends: (68, 1, 84) and (253, 231, 37); e = 1e-2 sits in the middle of
       the 1e-5 .. 10 log range, where viridis is teal (green and blue > red) */
    ok = w == 3 && h == 1 && pix[0] == 68 && pix[1] == 1 && pix[2] == 84 &&
         pix[6] == 253 && pix[7] == 231 && pix[8] == 37 &&
         pix[4] > pix[3] + 60 && pix[5] > pix[3] + 60;
    CHECK(t, ok, "error image colours: (%d %d %d) (%d %d %d) (%d %d %d)", pix[0], pix[1],
          pix[2], pix[3], pix[4], pix[5], pix[6], pix[7], pix[8]);
    free(pix);
}

const TestCase tests_image[] = {
    { "image_alloc", test_alloc },
    { "image_pfm_roundtrip", test_pfm_roundtrip },
    { "image_pfm_big_endian_grey", test_pfm_big_endian_and_grey },
    { "image_pfm_errors", test_pfm_errors },
    { "image_srgb", test_srgb },
    { "image_ppm_bytes", test_ppm_bytes },
    { "image_png_decode", test_png_decode },
    { "image_write_dispatch", test_write_dispatch },
    { "image_sidecar", test_sidecar },
    { "image_merge", test_merge },
    { "image_merge_errors", test_merge_errors },
    { "image_diff_metrics", test_diff_metrics },
    { "image_diff_thresholds", test_diff_thresholds },
    { "image_diff_errors", test_diff_errors },
    { "image_diff_error_image", test_diff_error_image },
    { NULL, NULL }
};
