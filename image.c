/* image.c - images in memory and on disk: PFM, PPM and PNG files, sidecars, merging
   and error metrics.

   WHAT IT IMPLEMENTS
     Image           w x h pixels, 3 floats (linear sRGB) each, TOP row first in memory.
     img_alloc/img_free
     pfm_write/pfm_read   netpbm PFM (pfm(5)):  "PF\n<w> <h>\n<scale>\n" then float32
                     RGB rows from the BOTTOM row to the top.  The sign of <scale> gives
                     the byte order: negative = little-endian, positive = big-endian.
                     We always write -1.0 and emit the bytes one by one, so the file is
                     the same on any host.  The reader also takes "Pf" (grey, replicated
                     to RGB) and big-endian data, and multiplies the samples by |scale|
                     when it is not 1.
     ppm_write       binary P6, 8 bits, TOP row first, after the tone mapping below.
     png_write       our own PNG encoder (PNG spec, W3C 2003): IHDR, one IDAT, IEND; the
                     IDAT holds a zlib stream (RFC 1950) of STORED deflate blocks
                     (RFC 1951 section 3.2.4, at most 65535 bytes each), so no compressor is
                     needed.  CRC-32 (PNG spec annex D) and Adler-32 (RFC 1950 section 9)
                     are computed here.  Every row starts with filter type 0 (None).
     tone mapping    v8 = round(255 * oetf(clamp(2^exposure * v, 0, 1))) with the sRGB
                     transfer curve (IEC 61966-2-1):
                         oetf(c) = 12.92 c                   c <= 0.0031308
                                 = 1.055 c^(1/2.4) - 0.055   otherwise
     img_write       chooses the format by the extension (.pfm .ppm .png, any case).
     sidecar         "<image>.txt" with the lines "spp <n>" and "settings <text>".
     img_merge       sample-count-weighted mean  I = sum_i w_i I_i / sum_i w_i, w_i = spp_i.
     img_error       over a pixel rectangle R with N pixels, a = test, b = reference:
                         MSE    = 1/(3N) sum_{p in R} sum_c (a - b)^2
                         relMSE = 1/(3N) sum sum (a - b)^2 / (b^2 + eps),  eps = 1e-2
                         MAE    = 1/(3N) sum sum |a - b|
                     relMSE in the style of Rousselle, Knaus and Zwicker 2011 ("Adaptive
                     sampling and reconstruction using greedy error minimization"), with
                     the squared reference in the denominator; eps keeps dark pixels from
                     dominating (IMG_RELMSE_EPS in specnee.h).

   HOW IT IS USED
     render() fills an Image; main writes it with img_write and img_write_sidecar.
     `specnee merge a.pfm b.pfm -o ab.pfm` combines independent renders with
     img_merge, and `specnee diff test.pfm ref.pfm --region A:10,10,50,50` measures
     their error with img_error (both commands in cmd_image.c); converge
     (cmd_converge.c) calls img_error too.

   Errors: the readers and img_write fill an Error with one line "path: problem" and
   return 0; the plain writers just return 0 on any I/O error. */
#include "specnee.h"
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* ======================================================================
   Allocation
   ====================================================================== */

int img_alloc(Image *im, int w, int h)
{
    im->w = 0; im->h = 0; im->rgb = NULL;
    if (w <= 0 || h <= 0 || (long long)w * h > IMG_MAX_PIXELS) return 0;
    im->rgb = (float *)calloc((size_t)w * (size_t)h * 3, sizeof(float));
    if (!im->rgb) return 0;
    im->w = w; im->h = h;
    return 1;
}

void img_free(Image *im)
{
    if (!im) return;
    free(im->rgb);
    im->rgb = NULL; im->w = 0; im->h = 0;
}

/* An image the writers can use: positive size within the cap, pixels present. */
static int img_valid(const Image *im)
{
    return im && im->rgb && im->w > 0 && im->h > 0 &&
           (long long)im->w * im->h <= IMG_MAX_PIXELS;
}

/* ======================================================================
   PFM
   ====================================================================== */

/* A float's IEEE-754 bit pattern (C99 does not promise IEEE floats, but every
   platform specnee targets has them; PFM itself assumes them). */
static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

int pfm_write(const Image *im, const char *path)
{
    FILE *f;
    unsigned char *row;
    int x, y, c, ok;
    if (!img_valid(im) || !path) return 0;
    row = (unsigned char *)malloc((size_t)im->w * 12);
    if (!row) return 0;
    f = fopen(path, "wb");
    if (!f) { free(row); return 0; }
    /* -1.0: little-endian samples, scale 1 */
    ok = fprintf(f, "PF\n%d %d\n-1.0\n", im->w, im->h) > 0;
    /* PFM stores the bottom row first; memory holds the top row first. */
    for (y = im->h - 1; ok && y >= 0; y--) {
        const float *src = im->rgb + (size_t)y * (size_t)im->w * 3;
        for (x = 0; x < im->w; x++)
            for (c = 0; c < 3; c++) {
                uint32_t u = float_bits(src[3 * x + c]);
                unsigned char *b = row + 12 * x + 4 * c;
                b[0] = (unsigned char)(u & 0xff);            /* least significant first */
                b[1] = (unsigned char)((u >> 8) & 0xff);
                b[2] = (unsigned char)((u >> 16) & 0xff);
                b[3] = (unsigned char)((u >> 24) & 0xff);
            }
        ok = fwrite(row, 12, (size_t)im->w, f) == (size_t)im->w;
    }
    free(row);
    if (fclose(f) != 0) ok = 0;
    return ok;
}

static int is_space(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Read one whitespace-terminated header token into tok.  Leading whitespace is
   skipped; the single whitespace character that ends the token is consumed (after
   the scale that is exactly the one separator before the pixel data).  *budget
   bounds the header's length so that a file of blanks cannot keep us reading.
   Returns 1, or 0 at end of file / too long (why says which). */
static int pfm_token(FILE *f, char *tok, size_t cap, long *budget, const char **why)
{
    size_t n = 0;
    int c;
    do {
        c = getc(f);
        if (--*budget < 0) { *why = "header longer than 1024 bytes"; return 0; }
    } while (c != EOF && is_space(c));
    while (c != EOF && !is_space(c)) {
        if (n + 1 >= cap) { *why = "header field too long"; return 0; }
        tok[n++] = (char)c;
        c = getc(f);
        if (--*budget < 0) { *why = "header longer than 1024 bytes"; return 0; }
    }
    tok[n] = '\0';
    if (c == EOF) { *why = "truncated header"; return 0; }
    return 1;
}

/* A width or height: decimal digits only, 1 .. IMG_MAX_PIXELS. */
static int parse_dim(const char *s, int *out)
{
    long v = 0;
    if (!*s) return 0;
    for (; *s; s++) {
        if (*s < '0' || *s > '9') return 0;
        v = v * 10 + (*s - '0');
        if (v > IMG_MAX_PIXELS) return 0;
    }
    if (v < 1) return 0;
    *out = (int)v;
    return 1;
}

/* The pixel bytes of a PFM file that cannot seek (a pipe): its size is unknown
   until the data ends, so the bytes are read first, up to need, into *data, a
   buffer that grows only as data arrives (an 18-byte input claiming 3 GiB
   allocates 64 KiB, not 3 GiB); *have = the bytes read (< need: truncated).
   Returns 0 when out of memory (*data is then the caller's to free). */
static int pfm_read_stream(FILE *f, size_t need, unsigned char **data, size_t *have)
{
    size_t cap = 0, got;
    for (;;) {
        if (*have == cap) {
            unsigned char *nb;
            if (cap == need) break;
            cap = cap ? (cap > need / 2 ? need : 2 * cap) : (need < 65536 ? need : 65536);
            nb = (unsigned char *)realloc(*data, cap);
            if (!nb) return 0;
            *data = nb;
        }
        got = fread(*data + *have, 1, cap - *have, f);
        *have += got;
        if (got == 0) break;
    }
    return 1;
}

int pfm_read(Image *im, const char *path, Error *err)
{
    FILE *f;
    char tok[64];
    const char *why = "";
    long budget = 1024;                  /* header bytes we are willing to read */
    int m0, m1, channels, w, h, x, y, c, big_endian;
    long pos, end;
    double scale;
    char *endp;
    unsigned char *row = NULL, *data = NULL;   /* data: all pixel bytes (pipes only) */
    size_t row_bytes, have = 0;
    int seekable = 0;

    im->w = 0; im->h = 0; im->rgb = NULL;
    f = fopen(path, "rb");
    if (!f) { error_set(err, path, 0, "cannot open: %s", strerror(errno)); return 0; }

    /* 1. Magic: "PF" (RGB) or "Pf" (grey). */
    m0 = getc(f); m1 = getc(f);
    if (m0 != 'P' || (m1 != 'F' && m1 != 'f')) {
        error_set(err, path, 0, "not a PFM file (bad magic: expected 'PF' or 'Pf')");
        goto fail;
    }
    channels = (m1 == 'F') ? 3 : 1;
    budget -= 2;
    c = getc(f);
    if (c == EOF || !is_space(c)) {
        error_set(err, path, 0, "not a PFM file (bad magic: expected 'PF' or 'Pf')");
        goto fail;
    }

    /* 2. Width, height, scale: any whitespace between them; no comments (the format
          has none, and a '#' could be the first byte of the data). */
    if (!pfm_token(f, tok, sizeof tok, &budget, &why)) goto bad_header;
    if (tok[0] == '#') { why = "comments are not allowed in a PFM header"; goto bad_header; }
    if (!parse_dim(tok, &w)) {
        error_set(err, path, 0, "bad width '%s' (expected 1 to %ld)", tok, (long)IMG_MAX_PIXELS);
        goto fail;
    }
    if (!pfm_token(f, tok, sizeof tok, &budget, &why)) goto bad_header;
    if (tok[0] == '#') { why = "comments are not allowed in a PFM header"; goto bad_header; }
    if (!parse_dim(tok, &h)) {
        error_set(err, path, 0, "bad height '%s' (expected 1 to %ld)", tok, (long)IMG_MAX_PIXELS);
        goto fail;
    }
    if (!pfm_token(f, tok, sizeof tok, &budget, &why)) goto bad_header;
    scale = strtod(tok, &endp);
    if (endp == tok || *endp != '\0') {
        error_set(err, path, 0, "bad scale '%s' (expected a number such as -1.0)", tok);
        goto fail;
    }
    if (scale != scale) { error_set(err, path, 0, "scale is NaN"); goto fail; }
    if (scale == 0.0 || scale > DBL_MAX || scale < -DBL_MAX) {
        error_set(err, path, 0, "bad scale '%s' (must be finite and nonzero: its sign "
                  "gives the byte order)", tok);
        goto fail;
    }
    big_endian = scale > 0.0;
    if (scale < 0.0) scale = -scale;

    /* 3. Sizes: cap the pixel count, then compare with what the file holds before
          allocating anything, so a lying header cannot make us allocate gigabytes. */
    if ((long long)w * h > IMG_MAX_PIXELS) {
        error_set(err, path, 0, "image size %dx%d is too large (limit %ld pixels)",
                  w, h, (long)IMG_MAX_PIXELS);
        goto fail;
    }
    row_bytes = (size_t)w * (size_t)channels * 4;
    pos = ftell(f);
    seekable = pos >= 0 && fseek(f, 0, SEEK_END) == 0 && (end = ftell(f)) >= 0;
    if (seekable) {
        double need = (double)row_bytes * h;
        if ((double)(end - pos) < need) {
            error_set(err, path, 0, "truncated: %dx%d pixels need %.0f bytes of data, "
                      "the file has %ld", w, h, need, end - pos);
            goto fail;
        }
        if (fseek(f, pos, SEEK_SET) != 0) {
            error_set(err, path, 0, "cannot seek: %s", strerror(errno));
            goto fail;
        }
    } else {
        const size_t need = row_bytes * (size_t)h;
        if (!pfm_read_stream(f, need, &data, &have)) {
            error_set(err, path, 0, "out of memory for a %dx%d image", w, h);
            goto fail;
        }
        if (have < need) {
            error_set(err, path, 0, "truncated: %dx%d pixels need %.0f bytes of data, "
                      "the stream has %.0f", w, h, (double)need, (double)have);
            goto fail;
        }
    }

    /* 4. Pixels, bottom row first in the file. */
    row = seekable ? (unsigned char *)malloc(row_bytes) : NULL;
    if ((seekable && !row) || !img_alloc(im, w, h)) {
        error_set(err, path, 0, "out of memory for a %dx%d image", w, h);
        goto fail;
    }
    for (y = h - 1; y >= 0; y--) {
        float *dst = im->rgb + (size_t)y * (size_t)w * 3;
        if (!seekable) {
            row = data + (size_t)(h - 1 - y) * row_bytes;
        } else if (fread(row, 1, row_bytes, f) != row_bytes) {
            error_set(err, path, 0, "truncated pixel data (row %d of %d from the bottom)",
                      h - y, h);
            goto fail;
        }
        for (x = 0; x < w; x++)
            for (c = 0; c < channels; c++) {
                const unsigned char *b = row + 4 * (x * channels + c);
                uint32_t u = big_endian
                    ? ((uint32_t)b[0] << 24) | ((uint32_t)b[1] << 16) | ((uint32_t)b[2] << 8) | b[3]
                    : ((uint32_t)b[3] << 24) | ((uint32_t)b[2] << 16) | ((uint32_t)b[1] << 8) | b[0];
                float v = bits_float(u);
                if (scale != 1.0) v = (float)((double)v * scale);   /* |scale| is a unit factor */
                if (channels == 3) dst[3 * x + c] = v;
                else dst[3 * x] = dst[3 * x + 1] = dst[3 * x + 2] = v;   /* grey -> RGB */
            }
    }
    if (seekable) free(row);
    free(data);
    fclose(f);
    return 1;

bad_header:
    error_set(err, path, 0, "bad PFM header: %s", why);
fail:
    if (seekable) free(row);
    free(data);
    img_free(im);
    fclose(f);
    return 0;
}

/* ======================================================================
   Tone mapping to 8 bits
   ====================================================================== */

float srgb_oetf(float linear)
{
    /* IEC 61966-2-1: a linear toe below 0.0031308, a 1/2.4 power above; the two
       pieces meet (to 7 digits) at 0.0031308 -> 0.0404500. */
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
}

/* One channel: scale by gain = 2^exposure, clamp to [0, 1] (negatives and NaN go
   to 0), apply the sRGB curve and round to 0..255. */
static unsigned char tonemap8(float linear, float gain)
{
    float v = linear * gain;
    if (!(v > 0.0f)) v = 0.0f;
    if (v > 1.0f) v = 1.0f;
    return (unsigned char)(srgb_oetf(v) * 255.0f + 0.5f);
}

/* The whole image as 8-bit RGB, top row first; NULL when out of memory. */
static unsigned char *img_to_rgb8(const Image *im, float exposure)
{
    size_t i, n = (size_t)im->w * (size_t)im->h * 3;
    float gain = powf(2.0f, exposure);
    unsigned char *out = (unsigned char *)malloc(n);
    if (!out) return NULL;
    for (i = 0; i < n; i++) out[i] = tonemap8(im->rgb[i], gain);
    return out;
}

int ppm_write(const Image *im, const char *path, float exposure)
{
    FILE *f;
    unsigned char *rgb;
    size_t n;
    int ok;
    if (!img_valid(im) || !path) return 0;
    rgb = img_to_rgb8(im, exposure);
    if (!rgb) return 0;
    f = fopen(path, "wb");
    if (!f) { free(rgb); return 0; }
    n = (size_t)im->w * (size_t)im->h * 3;
    /* P6 rows run top to bottom, unlike PFM. */
    ok = fprintf(f, "P6\n%d %d\n255\n", im->w, im->h) > 0 && fwrite(rgb, 1, n, f) == n;
    if (fclose(f) != 0) ok = 0;
    free(rgb);
    return ok;
}

/* ======================================================================
   PNG: chunks with CRC-32, a zlib stream of stored deflate blocks
   ====================================================================== */

typedef struct {
    FILE *f;
    int ok;                    /* 0 after any failed write */
    uint32_t crc;              /* running CRC-32 register of the current chunk */
    uint32_t crc_table[256];   /* CRC of each byte value (PNG spec annex D) */
} PngFile;

/* CRC-32 with the reflected polynomial 0xEDB88320 (ISO 3309 / ITU-T V.42). */
static void crc_table_init(uint32_t table[256])
{
    uint32_t n, k, c;
    for (n = 0; n < 256; n++) {
        c = n;
        for (k = 0; k < 8; k++) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        table[n] = c;
    }
}

/* Write bytes, folding them into the chunk's CRC. */
static void png_put(PngFile *pf, const unsigned char *p, size_t n)
{
    size_t i;
    uint32_t c = pf->crc;
    for (i = 0; i < n; i++) c = pf->crc_table[(c ^ p[i]) & 0xff] ^ (c >> 8);
    pf->crc = c;
    if (pf->ok && fwrite(p, 1, n, pf->f) != n) pf->ok = 0;
}

static void put_be32(unsigned char *b, uint32_t v)
{
    b[0] = (unsigned char)(v >> 24); b[1] = (unsigned char)(v >> 16);
    b[2] = (unsigned char)(v >> 8);  b[3] = (unsigned char)v;
}

/* A chunk is: length (4 bytes, big-endian, data only), type, data, CRC of type+data. */
static void png_chunk_begin(PngFile *pf, const char *type, uint32_t length)
{
    unsigned char b[4];
    put_be32(b, length);
    if (pf->ok && fwrite(b, 1, 4, pf->f) != 4) pf->ok = 0;
    pf->crc = 0xffffffffu;
    png_put(pf, (const unsigned char *)type, 4);
}

static void png_chunk_end(PngFile *pf)
{
    unsigned char b[4];
    put_be32(b, pf->crc ^ 0xffffffffu);
    if (pf->ok && fwrite(b, 1, 4, pf->f) != 4) pf->ok = 0;
}

/* The deflate stream as stored blocks: each block is a 5-byte header
   [BFINAL | BTYPE=00 << 1] [LEN lo] [LEN hi] [~LEN lo] [~LEN hi] and LEN raw bytes.
   The whole raw length is known up front, so the block sizes are too. */
typedef struct {
    PngFile *pf;
    uint64_t left;             /* raw bytes still to come in the whole stream */
    uint32_t in_block;         /* raw bytes still to come in the current block */
    uint32_t s1, s2;           /* Adler-32 sums: s1 = 1 + sum of bytes, s2 = sum of s1 */
} StoredStream;

#define STORED_MAX 65535u      /* LEN is 16 bits (RFC 1951 section 3.2.4) */
#define ADLER_MOD 65521u       /* largest prime below 2^16 (RFC 1950 section 9) */

static void stored_put(StoredStream *z, const unsigned char *p, size_t n)
{
    while (n > 0) {
        size_t k, i;
        if (z->in_block == 0) {              /* start the next block */
            unsigned char hdr[5];
            uint32_t len = z->left > STORED_MAX ? STORED_MAX : (uint32_t)z->left;
            hdr[0] = (unsigned char)(len == z->left ? 1 : 0);   /* BFINAL on the last */
            hdr[1] = (unsigned char)(len & 0xff);
            hdr[2] = (unsigned char)(len >> 8);
            hdr[3] = (unsigned char)(~len & 0xff);
            hdr[4] = (unsigned char)((~len >> 8) & 0xff);
            png_put(z->pf, hdr, 5);
            z->in_block = len;
        }
        k = n < z->in_block ? n : z->in_block;
        png_put(z->pf, p, k);
        for (i = 0; i < k; i++) {
            z->s1 = (z->s1 + p[i]) % ADLER_MOD;
            z->s2 = (z->s2 + z->s1) % ADLER_MOD;
        }
        z->in_block -= (uint32_t)k;
        z->left -= k;
        p += k; n -= k;
    }
}

int png_write_rgb8(const char *path, int w, int h, const unsigned char *rgb)
{
    static const unsigned char signature[8] = { 137, 80, 78, 71, 13, 10, 26, 10 };
    PngFile pf;
    StoredStream z;
    unsigned char ihdr[13], b[4];
    unsigned char filter_none = 0;
    uint64_t raw, blocks, idat_len;
    int y;

    if (!path || !rgb || w <= 0 || h <= 0 || (long long)w * h > IMG_MAX_PIXELS) return 0;
    raw = (uint64_t)h * (1 + 3 * (uint64_t)w);           /* filter byte + pixels per row */
    blocks = (raw + STORED_MAX - 1) / STORED_MAX;
    idat_len = 2 + 5 * blocks + raw + 4;                 /* zlib header, blocks, Adler */
    if (idat_len > 0x7fffffffu) return 0;                /* PNG's chunk length limit */

    pf.f = fopen(path, "wb");
    if (!pf.f) return 0;
    pf.ok = 1;
    crc_table_init(pf.crc_table);
    if (fwrite(signature, 1, 8, pf.f) != 8) pf.ok = 0;

    /* IHDR: width, height, bit depth 8, colour type 2 (RGB), deflate, filter method 0,
       no interlace. */
    put_be32(ihdr, (uint32_t)w);
    put_be32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8; ihdr[9] = 2; ihdr[10] = 0; ihdr[11] = 0; ihdr[12] = 0;
    png_chunk_begin(&pf, "IHDR", 13);
    png_put(&pf, ihdr, 13);
    png_chunk_end(&pf);

    /* IDAT: zlib header 0x78 0x01 (deflate, 32K window, no dictionary; 0x7801 is a
       multiple of 31 as RFC 1950 requires), the stored blocks, then Adler-32. */
    png_chunk_begin(&pf, "IDAT", (uint32_t)idat_len);
    b[0] = 0x78; b[1] = 0x01;
    png_put(&pf, b, 2);
    z.pf = &pf; z.left = raw; z.in_block = 0; z.s1 = 1; z.s2 = 0;
    for (y = 0; y < h; y++) {
        stored_put(&z, &filter_none, 1);
        stored_put(&z, rgb + (size_t)y * (size_t)w * 3, (size_t)w * 3);
    }
    put_be32(b, (z.s2 << 16) | z.s1);
    png_put(&pf, b, 4);
    png_chunk_end(&pf);

    png_chunk_begin(&pf, "IEND", 0);
    png_chunk_end(&pf);

    if (fclose(pf.f) != 0) pf.ok = 0;
    return pf.ok;
}

int png_write(const Image *im, const char *path, float exposure)
{
    unsigned char *rgb;
    int ok;
    if (!img_valid(im) || !path) return 0;
    rgb = img_to_rgb8(im, exposure);
    if (!rgb) return 0;
    ok = png_write_rgb8(path, im->w, im->h, rgb);
    free(rgb);
    return ok;
}

/* png_write plus the rectangles' outlines, one pixel wide, inside each rectangle,
   rectangle i in colour i mod 8 of the table below. */
int png_write_marked(const Image *im, const char *path, float exposure, const int *rect, int n)
{
    static const unsigned char colour[8][3] = {   /* yellow cyan magenta orange white green blue red */
        { 255, 230, 0 }, { 0, 230, 255 }, { 255, 60, 200 }, { 255, 140, 0 },
        { 255, 255, 255 }, { 60, 230, 60 }, { 60, 90, 255 }, { 255, 40, 40 } };
    unsigned char *rgb;
    int ok, i, x, y;
    if (!img_valid(im) || !path || n < 0) return 0;
    rgb = img_to_rgb8(im, exposure);
    if (!rgb) return 0;
    for (i = 0; i < n; i++) {
        const int *q = rect + 4 * i;
        int x0 = q[0] < 0 ? 0 : q[0], y0 = q[1] < 0 ? 0 : q[1];
        int x1 = q[2] > im->w ? im->w : q[2], y1 = q[3] > im->h ? im->h : q[3];
        for (y = y0; y < y1; y++)
            for (x = x0; x < x1; x++)
                if (x == x0 || x == x1 - 1 || y == y0 || y == y1 - 1)
                    memcpy(rgb + 3 * ((size_t)y * im->w + x), colour[i % 8], 3);
    }
    ok = png_write_rgb8(path, im->w, im->h, rgb);
    free(rgb);
    return ok;
}

/* ======================================================================
   Writing by extension, sidecars
   ====================================================================== */

/* The extension of path (from the last '.' after the last separator), or "". */
static const char *path_ext(const char *path)
{
    const char *dot = NULL, *p;
    for (p = path; *p; p++) {
        if (*p == '/' || *p == '\\') dot = NULL;
        else if (*p == '.') dot = p;
    }
    return dot ? dot : "";
}

/* Case-insensitive equality for ASCII extensions (strcasecmp is POSIX, not C99). */
static int ext_is(const char *ext, const char *want)
{
    for (; *ext && *want; ext++, want++) {
        int a = (*ext >= 'A' && *ext <= 'Z') ? *ext - 'A' + 'a' : *ext;
        if (a != *want) return 0;
    }
    return *ext == '\0' && *want == '\0';
}

int img_format_check(const char *path, Error *err)
{
    const char *ext = path_ext(path);
    if (ext_is(ext, ".pfm") || ext_is(ext, ".ppm") || ext_is(ext, ".png")) return 1;
    if (!*ext) error_set(err, path, 0, "no file extension (use .pfm, .ppm or .png)");
    else error_set(err, path, 0, "unsupported output format '%s' (use .pfm, .ppm or .png)", ext);
    return 0;
}

int img_write(const Image *im, const char *path, float exposure, Error *err)
{
    const char *ext = path_ext(path);
    int ok;
    if (!img_valid(im)) { error_set(err, path, 0, "no image to write"); return 0; }
    if (!img_format_check(path, err)) return 0;
    errno = 0;                        /* so a failure below reports its own cause */
    if (ext_is(ext, ".pfm")) ok = pfm_write(im, path);
    else if (ext_is(ext, ".ppm")) ok = ppm_write(im, path, exposure);
    else ok = png_write(im, path, exposure);
    if (!ok) {
        error_set(err, path, 0, "cannot write: %s", errno ? strerror(errno) : "I/O error");
        return 0;
    }
    return 1;
}

/* "<path>.txt", malloc'ed. */
static char *sidecar_path(const char *path)
{
    size_t n = strlen(path);
    char *s = (char *)malloc(n + 5);
    if (!s) return NULL;
    memcpy(s, path, n);
    memcpy(s + n, ".txt", 5);
    return s;
}

/* Writes "spp <n>" (left out when spp < 0: unknown) and "settings <text>" with any
   line breaks in the text turned into spaces, so each record stays one line. */
int img_write_sidecar(const char *path, long spp, const char *settings)
{
    char *sp = sidecar_path(path);
    FILE *f;
    int ok = 1;
    const char *s;
    if (!sp) return 0;
    f = fopen(sp, "w");
    free(sp);
    if (!f) return 0;
    if (spp >= 0 && fprintf(f, "spp %ld\n", spp) < 0) ok = 0;
    if (fputs("settings ", f) == EOF) ok = 0;
    for (s = settings ? settings : ""; *s; s++)
        if (fputc(*s == '\n' || *s == '\r' ? ' ' : *s, f) == EOF) ok = 0;
    if (fputc('\n', f) == EOF) ok = 0;
    if (fclose(f) != 0) ok = 0;
    return ok;
}

/* The n of the first line "spp <n>" (n >= 0) of "<path>.txt"; -1 when the file is
   missing or has no such line.  Reads at most 1 MiB. */
long img_read_sidecar_spp(const char *path)
{
    char *sp = sidecar_path(path);
    char line[256];
    FILE *f;
    long result = -1, total = 0;
    int at_line_start = 1;
    if (!sp) return -1;
    f = fopen(sp, "r");
    free(sp);
    if (!f) return -1;
    while (result < 0 && total < (1L << 20) && fgets(line, sizeof line, f)) {
        size_t n = strlen(line);
        int starts = at_line_start;     /* a long line arrives in pieces: skip the rest */
        total += (long)n;
        at_line_start = n > 0 && line[n - 1] == '\n';
        if (starts && strncmp(line, "spp", 3) == 0 && is_space((unsigned char)line[3])) {
            char *endp;
            long v;
            errno = 0;
            v = strtol(line + 3, &endp, 10);
            if (endp == line + 3 || errno == ERANGE) break;   /* no number, or too big */
            while (is_space((unsigned char)*endp)) endp++;
            if (*endp == '\0' && v >= 0) result = v;
            break;
        }
    }
    fclose(f);
    return result;
}

/* ======================================================================
   Merging and error metrics (library)
   ====================================================================== */

int img_merge(const Image *in, const double *weights, int n, Image *out)
{
    double wsum = 0.0;
    size_t i, count;
    int k;
    if (!in || n < 1 || !out) return 0;
    for (k = 0; k < n; k++) {
        double wk = weights ? weights[k] : 1.0;
        if (!img_valid(&in[k]) || in[k].w != in[0].w || in[k].h != in[0].h) return 0;
        if (!(wk >= 0.0) || wk > DBL_MAX) return 0;   /* negative, NaN or infinite */
        wsum += wk;
    }
    if (!(wsum > 0.0)) return 0;
    if (!img_alloc(out, in[0].w, in[0].h)) return 0;
    count = (size_t)out->w * (size_t)out->h * 3;
    for (i = 0; i < count; i++) {
        double acc = 0.0;                             /* sum_k w_k I_k in double */
        for (k = 0; k < n; k++) acc += (weights ? weights[k] : 1.0) * (double)in[k].rgb[i];
        out->rgb[i] = (float)(acc / wsum);
    }
    return 1;
}

int img_error(const Image *a, const Image *ref, int x0, int y0, int x1, int y1, ImgErr *out)
{
    double se = 0.0, rel = 0.0, ae = 0.0, m, ya = 0.0, yr = 0.0;
    static const double yrow[3] = { 0.212671, 0.715160, 0.072169 };   /* sRGB's Y row */
    int x, y, c;
    if (!img_valid(a) || !img_valid(ref) || !out) return 0;
    if (a->w != ref->w || a->h != ref->h) return 0;
    if (x0 < 0 || y0 < 0 || x1 > a->w || y1 > a->h || x0 >= x1 || y0 >= y1) return 0;
    for (y = y0; y < y1; y++)
        for (x = x0; x < x1; x++)
            for (c = 0; c < 3; c++) {
                size_t i = ((size_t)y * (size_t)a->w + (size_t)x) * 3 + (size_t)c;
                double b = (double)ref->rgb[i], d = (double)a->rgb[i] - b;
                se += d * d;
                rel += d * d / (b * b + IMG_RELMSE_EPS);
                ae += fabs(d);
                ya += yrow[c] * a->rgb[i];
                yr += yrow[c] * b;
            }
    out->n = (long)(x1 - x0) * (long)(y1 - y0);
    m = 3.0 * (double)out->n;
    out->mse = se / m;
    out->relmse = rel / m;
    out->mae = ae / m;
    out->y_test = ya / (double)out->n;
    out->y_ref = yr / (double)out->n;
    return 1;
}

/* The false-colour ramp of the error image: matplotlib's "viridis" (van der Walt and
   Smith 2015, CC0), perceptually uniform and readable in grey and by colour-blind
   viewers, sampled at its table entries 0, 32, ..., 224, 255 and interpolated
   linearly in between. */
static const double viridis_stops[9][3] = {
    { 0.267004, 0.004874, 0.329415 }, { 0.278826, 0.175490, 0.483397 },
    { 0.229739, 0.322361, 0.545706 }, { 0.172719, 0.448791, 0.557885 },
    { 0.127568, 0.566949, 0.550556 }, { 0.157851, 0.683765, 0.501686 },
    { 0.369214, 0.788888, 0.382914 }, { 0.678489, 0.863742, 0.189503 },
    { 0.993248, 0.906157, 0.143936 }
};
static const double viridis_pos[9] = {
    0.0, 32.0 / 255, 64.0 / 255, 96.0 / 255, 128.0 / 255, 160.0 / 255,
    192.0 / 255, 224.0 / 255, 1.0
};

/* The log scale of the error image: e = 10^ERRIMG_LOG_LO (or less) is the ramp's dark
   end, e = 10^ERRIMG_LOG_HI (or more) its bright end, one colour step per decade. */
#define ERRIMG_LOG_LO (-5.0)
#define ERRIMG_LOG_HI 1.0

static void error_colour(double e, unsigned char rgb[3])
{
    double t;
    int k, c;
    if (e != e) { rgb[0] = 255; rgb[1] = 0; rgb[2] = 255; return; }   /* NaN: magenta */
    t = e > 0.0 ? (log10(e) - ERRIMG_LOG_LO) / (ERRIMG_LOG_HI - ERRIMG_LOG_LO) : 0.0;
    if (t < 0.0) t = 0.0;
    if (t > 1.0) t = 1.0;
    for (k = 0; k < 7 && t > viridis_pos[k + 1]; k++) {}
    for (c = 0; c < 3; c++) {
        double f = (t - viridis_pos[k]) / (viridis_pos[k + 1] - viridis_pos[k]);
        double v = viridis_stops[k][c] + f * (viridis_stops[k + 1][c] - viridis_stops[k][c]);
        rgb[c] = (unsigned char)(v * 255.0 + 0.5);
    }
}

/* Per pixel e = 1/3 sum_c (a - b)^2 / (b^2 + eps), coloured by error_colour. */
int img_write_error_png(const Image *a, const Image *ref, const char *path)
{
    unsigned char *rgb;
    size_t i, n;
    int ok;
    if (!img_valid(a) || !img_valid(ref) || a->w != ref->w || a->h != ref->h) return 0;
    n = (size_t)a->w * (size_t)a->h;
    rgb = (unsigned char *)malloc(n * 3);
    if (!rgb) return 0;
    for (i = 0; i < n; i++) {
        double e = 0.0;
        int c;
        for (c = 0; c < 3; c++) {
            double b = (double)ref->rgb[3 * i + c], d = (double)a->rgb[3 * i + c] - b;
            e += d * d / (b * b + IMG_RELMSE_EPS);
        }
        error_colour(e / 3.0, rgb + 3 * i);
    }
    ok = png_write_rgb8(path, a->w, a->h, rgb);
    free(rgb);
    return ok;
}
