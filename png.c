/* png.c - a small PNG reader with its own inflate, for image textures.

   Exported (specnee.h section 10): png_read_memory, png_read, zlib_inflate (the
   inflate below, which exr.c also reads its ZIP blocks with); gzip_inflate
   and read_whole_file_gz (specnee.h section 3: the gzip container around the
   same inflate, which scene.c and ply.c open .pbrt.gz and .ply.gz files with).

   WHAT IT READS (the PNG specification, W3C 2003 / RFC 2083)
     The 8-byte signature, then chunks: length (4 bytes, big-endian, < 2^31),
     type (4 letters), data, CRC-32 of type and data (checked: section 5.5, the
     polynomial of ISO 3309, reflected, 0xEDB88320).  IHDR first (width, height,
     bit depth, colour type, compression 0, filter method 0, interlace 0), PLTE
     (required for palette images, refused for grey ones), IDAT (one or more, their
     data one zlib stream), IEND.  tRNS is checked and dropped (an Image has no
     alpha; neither is the alpha of colour types 4 and 6 kept).  Other ancillary
     chunks (lower-case first letter: tEXt, gAMA, ...) are skipped; an unknown
     critical chunk is an error.  Adam7 interlacing is refused by name.
       colour type  0 grey     bit depths 1 2 4 8 16
                    2 RGB      8 16
                    3 palette  1 2 4 8   (an index into PLTE's RGB triples)
                    4 grey+alpha, 6 RGB+alpha   8 16
     Each row starts with its filter type (section 9.2); with a = the byte bpp
     bytes to the left (bpp = bytes per pixel, at least 1), b = the byte above,
     c = the byte above and left (0 outside the image), the raw byte is
         0 None x   1 Sub x + a   2 Up x + b   3 Average x + floor((a + b) / 2)
         4 Paeth x + the one of a, b, c closest to p = a + b - c (ties: a, b, c)
     all modulo 256.  Samples of fewer than 8 bits fill each byte from its most
     significant bit.

   THE ZLIB STREAM (RFC 1950) AND INFLATE (RFC 1951)
     Two header bytes (CM = 8, a window of at most 32K, CMF*256 + FLG a multiple of
     31, no preset dictionary), the deflate blocks, the Adler-32 of the
     uncompressed bytes (s1 = 1 + sum of bytes, s2 = sum of s1, both mod 65521;
     checked).  A block starts with BFINAL (1 bit) and BTYPE (2 bits, bits read
     from the least significant end of each byte):
       00 stored: skip to the byte boundary, LEN, NLEN = ~LEN, LEN raw bytes;
       01 fixed Huffman codes: literal/length lengths 8 (0-143), 9 (144-255),
          7 (256-279), 8 (280-287), distance codes all 5 bits;
       10 dynamic: HLIT + 257 literal/length and HDIST + 1 distance code lengths,
          themselves coded with HCLEN + 4 code-length-code lengths (3 bits each, in
          the order 16 17 18 0 8 7 9 6 10 5 11 4 12 3 13 2 14 1 15); in that code
          16 repeats the previous length 3-6 times, 17 and 18 give 3-10 and 11-138
          zeros.
     A symbol < 256 is a literal byte, 256 ends the block, 257..285 a length
     (3..258, base plus extra bits) followed by a distance code (1..32768): copy
     that many bytes from that far back (they may overlap what is being written).
     Codes are canonical: from the code lengths alone, shorter codes first and,
     within a length, in symbol order (section 3.2.2).  The decoder below walks
     the lengths one bit at a time (count[len] codes of each length; as in Mark
     Adler's teaching decoder "puff", written here anew).

   THE GZIP FILE (RFC 1952)
     One or more members, back to back, their data concatenated.  A member is
       1F 8B, CM = 8 (deflate), FLG, MTIME (4 bytes), XFL, OS,
       if FLG & 4 (FEXTRA): XLEN (2 bytes) and XLEN bytes of extra fields,
       if FLG & 8 (FNAME): the original name, zero-terminated,
       if FLG & 16 (FCOMMENT): a comment, zero-terminated,
       if FLG & 2 (FHCRC): the low 16 bits of the CRC-32 of the header so far,
       the deflate blocks (as above, without zlib's header and Adler-32),
       CRC-32 of the member's data and ISIZE, its length mod 2^32 (4 bytes each);
     all numbers little-endian.  FLG bits 5-7 are reserved: set, they are an
     error, as are bytes after a member that do not start a member, a wrong CRC-32
     (of the data or of the header) and a wrong ISIZE.  Back-references stay
     inside their member.  The output grows by doubling up to a limit (1 GiB for
     files, READ_MAX_BYTES), which keeps a small "gzip bomb" from taking the
     machine.  pbrt-v4 reads a .pbrt.gz scene, Include or Import, and a .ply.gz
     mesh (chosen by the name); specnee decompresses where the first two bytes
     are 1F 8B, whatever the name, in those two readers only.

   HOSTILE INPUT.  Every read is bounds-checked (running out of bytes is
   "truncated"); the output size is known from IHDR, and a stream that would write
   more (or less) is an error; over-subscribed codes, missing end-of-block codes,
   distances beyond the output, invalid symbols, a wrong CRC or Adler-32 are errors.
   Before anything is allocated, the image must fit IMG_MAX_PIXELS and the memory
   budget MEM_BUDGET_MIB, and the compressed data must be able to hold it (deflate
   expands at most 1032 times: a 258-byte copy coded in 2 bits).  Every loop
   consumes input or output, so nothing hangs.

   THE RESULT.  An Image of linear floats, rows top to bottom, 3 per pixel: each
   sample divided by 2^depth - 1 (grey repeated in R, G, B; a palette index looked
   up), then, unless `linear` is set, decoded from the sRGB transfer curve
   (IEC 61966-2-1: c/12.92 at or below 0.04045, ((c + 0.055)/1.055)^2.4 above),
   the curve an 8-bit picture is stored with.  Data textures (normal or roughness
   maps) ask for linear. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

#define PNG_MAX_BITS 15        /* longest deflate code (RFC 1951 section 3.2.7) */
#define PNG_MAX_EXPANSION 1032 /* most output bytes per input byte of deflate data */

/* ---------------------------------------------------------------- inflate */

typedef struct {
    const unsigned char *in; size_t n_in, pos;   /* the compressed bytes and the next one */
    uint32_t bitbuf; int bitcnt;                  /* bits read but not yet used */
    unsigned char *out; size_t n_out, len;        /* the output buffer, bytes written */
    size_t base;                                  /* where this stream's output starts */
    size_t max_out;                               /* > 0: out is malloc'd and grows to this */
    const char *why;                              /* the error, NULL while fine */
} Inflate;

/* A canonical Huffman code: count[l] codes of length l, and the symbols ordered
   by code (by length, then by symbol). */
typedef struct { short count[PNG_MAX_BITS + 1]; short symbol[288]; } Huffman;

/* `need` bits, least significant first; 0 and z->why set when the input ends. */
static uint32_t get_bits(Inflate *z, int need)
{
    uint32_t v = z->bitbuf;
    while (z->bitcnt < need) {
        if (z->pos >= z->n_in) { z->why = "truncated deflate data"; return 0; }
        v |= (uint32_t)z->in[z->pos++] << z->bitcnt;
        z->bitcnt += 8;
    }
    z->bitbuf = v >> need;
    z->bitcnt -= need;
    return v & ((1u << need) - 1u);
}

/* Build the code from n lengths; 0 if the lengths over-subscribe the code space
   (more codes than a prefix code can have).  An incomplete code is allowed (one
   distance code alone is legal); decode() rejects the codes it lacks. */
static int huff_build(Huffman *h, const unsigned char *length, int n)
{
    short offs[PNG_MAX_BITS + 1];
    int len, sym, left = 1;
    memset(h->count, 0, sizeof h->count);
    for (sym = 0; sym < n; sym++) h->count[length[sym]]++;
    for (len = 1; len <= PNG_MAX_BITS; len++) {
        left <<= 1;                      /* codes of this length still free */
        left -= h->count[len];
        if (left < 0) return 0;
    }
    offs[1] = 0;
    for (len = 1; len < PNG_MAX_BITS; len++) offs[len + 1] = (short)(offs[len] + h->count[len]);
    for (sym = 0; sym < n; sym++)
        if (length[sym] != 0) h->symbol[offs[length[sym]]++] = (short)sym;
    return 1;
}

/* One symbol: read a bit at a time; after len bits, the codes of length len are
   the `count` values first .. first + count - 1 (canonical order). */
static int decode(Inflate *z, const Huffman *h)
{
    int code = 0, first = 0, index = 0, len;
    for (len = 1; len <= PNG_MAX_BITS; len++) {
        int count;
        code |= (int)get_bits(z, 1);
        if (z->why) return -1;
        count = h->count[len];
        if (code - first < count) return h->symbol[index + (code - first)];
        index += count;
        first = (first + count) << 1;
        code <<= 1;
    }
    z->why = "invalid Huffman code";
    return -1;
}

/* Room for k more output bytes.  A fixed buffer (PNG, EXR: the size is known)
   has it or the data is too long; a growing one (gzip) doubles, up to max_out. */
static int room(Inflate *z, size_t k)
{
    size_t cap = z->n_out < 65536 ? 65536 : z->n_out;
    unsigned char *nb;
    if (k <= z->n_out - z->len) return 1;
    if (z->max_out == 0) { z->why = "more data than the image needs"; return 0; }
    if (k > z->max_out - z->len) { z->why = "uncompressed data larger than the limit"; return 0; }
    while (cap - z->len < k) cap = cap > z->max_out / 2 ? z->max_out : 2 * cap;
    nb = (unsigned char *)realloc(z->out, cap + 1);     /* + 1: room for a closing NUL */
    if (!nb) { z->why = "out of memory"; return 0; }
    z->out = nb;
    z->n_out = cap;
    return 1;
}

static int put_byte(Inflate *z, unsigned char b)
{
    if (z->len >= z->n_out && !room(z, 1)) return 0;
    z->out[z->len++] = b;
    return 1;
}

/* The symbols of one Huffman-coded block, up to its end-of-block code 256. */
static int inflate_codes(Inflate *z, const Huffman *lit, const Huffman *dist)
{
    static const short len_base[29] = { 3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27,
        31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258 };
    static const short len_extra[29] = { 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3,
        3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0 };
    static const unsigned short dist_base[30] = { 1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65,
        97, 129, 193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289,
        16385, 24577 };
    static const short dist_extra[30] = { 0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7,
        8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13 };
    for (;;) {
        int sym = decode(z, lit);
        size_t length, distance;
        if (sym < 0) return 0;
        if (sym < 256) { if (!put_byte(z, (unsigned char)sym)) return 0; continue; }
        if (sym == 256) return 1;                              /* end of block */
        sym -= 257;
        if (sym >= 29) { z->why = "invalid length symbol"; return 0; }
        length = (size_t)len_base[sym] + get_bits(z, len_extra[sym]);
        sym = decode(z, dist);
        if (sym < 0) return 0;
        if (sym >= 30) { z->why = "invalid distance symbol"; return 0; }
        distance = (size_t)dist_base[sym] + get_bits(z, dist_extra[sym]);
        if (z->why) return 0;
        if (distance > z->len - z->base) { z->why = "distance beyond the start of the data"; return 0; }
        if (!room(z, length)) return 0;
        while (length-- > 0) {           /* byte by byte: the copy may overlap itself */
            z->out[z->len] = z->out[z->len - distance];
            z->len++;
        }
    }
}

static int inflate_stored(Inflate *z)
{
    size_t len, nlen;
    z->bitbuf = 0; z->bitcnt = 0;        /* skip to the byte boundary */
    if (z->n_in - z->pos < 4) { z->why = "truncated deflate data"; return 0; }
    len = z->in[z->pos] | (size_t)z->in[z->pos + 1] << 8;
    nlen = z->in[z->pos + 2] | (size_t)z->in[z->pos + 3] << 8;
    z->pos += 4;
    if (len != (~nlen & 0xffffu)) { z->why = "stored block: LEN and NLEN disagree"; return 0; }
    if (z->n_in - z->pos < len) { z->why = "truncated deflate data"; return 0; }
    if (!room(z, len)) return 0;
    if (len > 0) memcpy(z->out + z->len, z->in + z->pos, len);   /* out may still be NULL */
    z->pos += len;
    z->len += len;
    return 1;
}

static int inflate_fixed(Inflate *z)
{
    unsigned char l[288];
    Huffman lit, dist;
    int i;
    for (i = 0; i < 144; i++) l[i] = 8;
    for (; i < 256; i++) l[i] = 9;
    for (; i < 280; i++) l[i] = 7;
    for (; i < 288; i++) l[i] = 8;
    huff_build(&lit, l, 288);
    for (i = 0; i < 30; i++) l[i] = 5;
    huff_build(&dist, l, 30);
    return inflate_codes(z, &lit, &dist);
}

static int inflate_dynamic(Inflate *z)
{
    static const unsigned char order[19] = { 16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3,
                                             13, 2, 14, 1, 15 };
    unsigned char lengths[320];
    Huffman lencode, lit, dist;
    int nlen, ndist, ncode, i;
    nlen = (int)get_bits(z, 5) + 257;
    ndist = (int)get_bits(z, 5) + 1;
    ncode = (int)get_bits(z, 4) + 4;
    if (z->why) return 0;
    if (nlen > 286 || ndist > 30) { z->why = "dynamic block: too many codes"; return 0; }
    memset(lengths, 0, sizeof lengths);
    for (i = 0; i < ncode; i++) lengths[order[i]] = (unsigned char)get_bits(z, 3);
    if (z->why) return 0;
    if (!huff_build(&lencode, lengths, 19)) { z->why = "dynamic block: bad code length code"; return 0; }
    /* the literal/length and distance code lengths, one sequence */
    i = 0;
    while (i < nlen + ndist) {
        int sym = decode(z, &lencode), rep;
        unsigned char v = 0;
        if (sym < 0) return 0;
        if (sym < 16) { lengths[i++] = (unsigned char)sym; continue; }
        if (sym == 16) {
            if (i == 0) { z->why = "dynamic block: repeat with no previous length"; return 0; }
            v = lengths[i - 1];
            rep = 3 + (int)get_bits(z, 2);
        } else if (sym == 17) {
            rep = 3 + (int)get_bits(z, 3);
        } else {
            rep = 11 + (int)get_bits(z, 7);
        }
        if (z->why) return 0;
        if (i + rep > nlen + ndist) { z->why = "dynamic block: too many code lengths"; return 0; }
        while (rep-- > 0) lengths[i++] = v;
    }
    if (lengths[256] == 0) { z->why = "dynamic block: no end-of-block code"; return 0; }
    if (!huff_build(&lit, lengths, nlen) || !huff_build(&dist, lengths + nlen, ndist)) {
        z->why = "dynamic block: over-subscribed Huffman code";
        return 0;
    }
    return inflate_codes(z, &lit, &dist);
}

/* The deflate blocks from z->pos up to the one marked last; nonzero on error (z->why). */
static int inflate_blocks(Inflate *z)
{
    int last;
    do {
        int type;
        last = (int)get_bits(z, 1);
        type = (int)get_bits(z, 2);
        if (z->why) return 1;
        if (type == 0) inflate_stored(z);
        else if (type == 1) inflate_fixed(z);
        else if (type == 2) inflate_dynamic(z);
        else z->why = "invalid deflate block type 3";
        if (z->why) return 1;
    } while (!last);
    return 0;
}

/* The zlib stream in[0 .. n_in) into out[0 .. n_out), which it must fill exactly.
   NULL on success, else what is wrong.  Also exr.c's, for ZIP blocks. */
const char *zlib_inflate(const unsigned char *in, size_t n_in, unsigned char *out, size_t n_out)
{
    Inflate z;
    uint32_t s1 = 1, s2 = 0, adler;
    size_t i;
    memset(&z, 0, sizeof z);
    z.in = in; z.n_in = n_in; z.out = out; z.n_out = n_out;
    if (n_in < 2) return "truncated zlib stream";
    if ((in[0] & 0x0f) != 8 || (in[0] >> 4) > 7) return "zlib stream: not deflate with a window of at most 32K";
    if (((unsigned)in[0] << 8 | in[1]) % 31 != 0) return "zlib stream: bad header check";
    if (in[1] & 0x20) return "zlib stream: a preset dictionary (not allowed in PNG)";
    z.pos = 2;
    if (inflate_blocks(&z)) return z.why;
    if (z.len != n_out) return "less data than the image needs";
    if (z.n_in - z.pos < 4) return "truncated zlib stream (no Adler-32)";
    for (i = 0; i < n_out; i++) {
        s1 = (s1 + out[i]) % 65521u;
        s2 = (s2 + s1) % 65521u;
    }
    adler = (uint32_t)in[z.pos] << 24 | (uint32_t)in[z.pos + 1] << 16 |
            (uint32_t)in[z.pos + 2] << 8 | in[z.pos + 3];
    if (adler != (s2 << 16 | s1)) return "Adler-32 checksum mismatch";
    return NULL;
}

/* ---------------------------------------------------------------- PNG */

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* CRC-32 of ISO 3309 (PNG annex D, RFC 1952 section 8), PNG's and gzip's: the
   256-entry table of the reflected polynomial 0xEDB88320 is made on each call (2K
   steps), then one lookup per byte. */
static uint32_t crc32_png(const unsigned char *p, size_t n)
{
    uint32_t table[256], c;
    size_t i;
    int k;
    for (i = 0; i < 256; i++) {
        c = (uint32_t)i;
        for (k = 0; k < 8; k++) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
        table[i] = c;
    }
    c = 0xffffffffu;
    for (i = 0; i < n; i++) c = table[(c ^ p[i]) & 0xffu] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

/* The sRGB transfer curve undone: an encoded value c in [0, 1] to linear. */
static float srgb_to_linear(double c)
{
    return (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
}

static int png_fail(Error *err, const char *name, const char *what)
{
    error_set(err, name, 0, "PNG: %s", what);
    return 0;
}

/* The IHDR chunk's body (len bytes): the size, bit depth, colour type and
   channel count, checked; NULL, or why the header is refused. */
static const char *png_ihdr(const unsigned char *body, uint32_t len, uint32_t *w, uint32_t *h,
                            int *depth, int *ctype, int *channels)
{
    if (len != 13) return "IHDR is not 13 bytes";
    *w = be32(body); *h = be32(body + 4);
    *depth = body[8]; *ctype = body[9];
    if (*w == 0 || *h == 0 || *w > 0x7fffffffu || *h > 0x7fffffffu)
        return "width and height must be 1 .. 2^31 - 1";
    *channels = *ctype == 0 ? 1 : *ctype == 2 ? 3 : *ctype == 3 ? 1 : *ctype == 4 ? 2 : *ctype == 6 ? 4 : 0;
    if (!*channels) return "unknown colour type (PNG has 0, 2, 3, 4, 6)";
    if (!((*depth == 8) || (*depth == 16 && *ctype != 3) ||
          ((*depth == 1 || *depth == 2 || *depth == 4) && (*ctype == 0 || *ctype == 3))))
        return "a bit depth this colour type does not allow";
    if (body[10] != 0 || body[11] != 0) return "unknown compression or filter method";
    if (body[12] == 1) return "Adam7 interlaced images are not supported (save the PNG without interlacing)";
    if (body[12] != 0) return "unknown interlace method";
    return NULL;
}

/* Undo the row filters in place: raw holds h rows of 1 + rowbytes bytes. */
static const char *unfilter(unsigned char *raw, int h, size_t rowbytes, size_t bpp)
{
    int y;
    for (y = 0; y < h; y++) {
        unsigned char *row = raw + (size_t)y * (rowbytes + 1), *x = row + 1;
        const unsigned char *up = y > 0 ? x - (rowbytes + 1) : NULL;  /* the row above */
        size_t i;
        switch (row[0]) {
        case 0: break;
        case 1: for (i = bpp; i < rowbytes; i++) x[i] = (unsigned char)(x[i] + x[i - bpp]); break;
        case 2: if (up) for (i = 0; i < rowbytes; i++) x[i] = (unsigned char)(x[i] + up[i]); break;
        case 3:
            for (i = 0; i < rowbytes; i++) {
                int a = i >= bpp ? x[i - bpp] : 0, b = up ? up[i] : 0;
                x[i] = (unsigned char)(x[i] + (a + b) / 2);
            }
            break;
        case 4:
            for (i = 0; i < rowbytes; i++) {
                int a = i >= bpp ? x[i - bpp] : 0, b = up ? up[i] : 0;
                int c = i >= bpp && up ? up[i - bpp] : 0;
                int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
                int pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
                x[i] = (unsigned char)(x[i] + pred);
            }
            break;
        default: return "unknown row filter type";
        }
    }
    return NULL;
}

int png_read_memory(const unsigned char *data, size_t n, const char *name, int linear, Image *im,
               Error *err)
{
    static const unsigned char signature[8] = { 137, 80, 78, 71, 13, 10, 26, 10 };
    uint32_t w = 0, h = 0;
    int depth = 0, ctype = -1, channels = 0, n_pal = 0, seen_idat = 0, seen_iend = 0;
    unsigned char pal[256 * 3];
    size_t pos, idat_total = 0, rowbytes = 0, raw_size = 0, k;
    unsigned char *z = NULL, *raw = NULL;
    const char *why;
    float lut[256];
    int pass;
    memset(im, 0, sizeof *im);
    if (!name) name = "<png>";
    if (n < 8 || memcmp(data, signature, 8) != 0) return png_fail(err, name, "not a PNG file (no PNG signature)");
    /* two passes over the chunks: the first checks them and sums IDAT's length,
       the second copies IDAT's data into one buffer */
    for (pass = 0; pass < 2; pass++) {
        size_t zpos = 0;
        for (pos = 8; !seen_iend || pass == 1;) {
            uint32_t len;
            const unsigned char *type, *body;
            if (pass == 1 && pos >= n) break;
            if (n - pos < 12) { free(z); return png_fail(err, name, "truncated (a chunk is cut short; no IEND)"); }
            len = be32(data + pos);
            type = data + pos + 4;
            body = data + pos + 8;
            if (len > 0x7fffffffu || n - pos - 12 < len) { free(z); return png_fail(err, name, "truncated (a chunk is longer than the file)"); }
            if (pass == 0) {
                int ok = 1;
                for (k = 0; k < 4; k++)
                    ok &= (type[k] >= 'A' && type[k] <= 'Z') || (type[k] >= 'a' && type[k] <= 'z');
                if (!ok) return png_fail(err, name, "a chunk type that is not 4 letters");
                if (crc32_png(type, (size_t)len + 4) != be32(body + len)) {
                    char msg[80];
                    snprintf(msg, sizeof msg, "CRC mismatch in chunk %c%c%c%c (the file is damaged)",
                             type[0], type[1], type[2], type[3]);
                    return png_fail(err, name, msg);
                }
                if (pos == 8 && memcmp(type, "IHDR", 4) != 0) return png_fail(err, name, "the first chunk is not IHDR");
                if (!memcmp(type, "IHDR", 4)) {
                    if (pos != 8) return png_fail(err, name, "a second IHDR");
                    why = png_ihdr(body, len, &w, &h, &depth, &ctype, &channels);
                    if (why) return png_fail(err, name, why);
                } else if (!memcmp(type, "PLTE", 4)) {
                    if (ctype == 0 || ctype == 4) return png_fail(err, name, "a palette in a grey image");
                    if (len % 3 != 0 || len == 0 || len > 768 || seen_idat || n_pal > 0)
                        return png_fail(err, name, "bad PLTE (1 .. 256 RGB entries, once, before IDAT)");
                    n_pal = (int)(len / 3);
                    memcpy(pal, body, len);
                } else if (!memcmp(type, "tRNS", 4)) {
                    /* checked, then dropped: the Image has no alpha channel */
                    if ((ctype == 0 && len != 2) || (ctype == 2 && len != 6) ||
                        (ctype == 3 && (n_pal == 0 || (int)len > n_pal)) || ctype == 4 || ctype == 6)
                        return png_fail(err, name, "bad tRNS for this colour type");
                } else if (!memcmp(type, "IDAT", 4)) {
                    seen_idat = 1;
                    idat_total += len;
                } else if (!memcmp(type, "IEND", 4)) {
                    seen_iend = 1;
                } else if (type[0] >= 'A' && type[0] <= 'Z') {
                    char msg[80];
                    snprintf(msg, sizeof msg, "unknown critical chunk %c%c%c%c", type[0], type[1],
                             type[2], type[3]);
                    return png_fail(err, name, msg);
                }
            } else if (!memcmp(type, "IDAT", 4)) {
                memcpy(z + zpos, body, len);
                zpos += len;
            } else if (!memcmp(type, "IEND", 4)) {
                break;
            }
            pos += (size_t)len + 12;
        }
        if (pass == 1) break;
        if (!seen_idat) return png_fail(err, name, "no IDAT chunk (no image data)");
        if (ctype == 3 && n_pal == 0) return png_fail(err, name, "a palette image without PLTE");
        /* the sizes, before any allocation: the pixel count, the memory budget
           (the raw rows and the float image), and what the compressed data can
           hold at most */
        rowbytes = ((size_t)w * (size_t)channels * (size_t)depth + 7) / 8;
        if ((double)w * (double)h > (double)IMG_MAX_PIXELS)
            return png_fail(err, name, "more pixels than IMG_MAX_PIXELS");
        raw_size = (size_t)h * (rowbytes + 1);
        if ((double)raw_size + 12.0 * (double)w * (double)h > (double)MEM_BUDGET_MIB * 1048576.0) {
            char msg[160];
            snprintf(msg, sizeof msg, "%lu x %lu pixels need %.1f GiB, more than specnee's memory "
                     "budget (MEM_BUDGET_MIB in specnee.h)", (unsigned long)w, (unsigned long)h,
                     ((double)raw_size + 12.0 * (double)w * (double)h) / 1073741824.0);
            return png_fail(err, name, msg);
        }
        if ((double)raw_size > (double)PNG_MAX_EXPANSION * (double)idat_total + 258.0)
            return png_fail(err, name, "truncated (the image data is too short for the image's size)");
        z = (unsigned char *)malloc(idat_total > 0 ? idat_total : 1);
        if (!z) return png_fail(err, name, "out of memory");
    }
    raw = (unsigned char *)malloc(raw_size);
    if (!raw) { free(z); return png_fail(err, name, "out of memory"); }
    why = zlib_inflate(z, idat_total, raw, raw_size);
    free(z);
    if (!why) why = unfilter(raw, (int)h, rowbytes, (size_t)(channels * depth + 7) / 8);
    if (why) { free(raw); return png_fail(err, name, why); }
    if (!img_alloc(im, (int)w, (int)h)) { free(raw); return png_fail(err, name, "out of memory"); }
    /* samples to floats */
    for (k = 0; k < 256; k++) lut[k] = linear ? (float)(k / 255.0) : srgb_to_linear(k / 255.0);
    {
        uint32_t x, y;
        double max = (double)((1u << depth) - 1u);
        for (y = 0; y < h; y++) {
            const unsigned char *row = raw + (size_t)y * (rowbytes + 1) + 1;
            float *out = im->rgb + 3 * (size_t)y * w;
            for (x = 0; x < w; x++) {
                unsigned v[4] = { 0, 0, 0, 0 };
                int c;
                for (c = 0; c < channels && c < 3; c++) {   /* alpha (the last) is dropped */
                    size_t bit = ((size_t)x * channels + (size_t)c) * (size_t)depth;
                    if (depth == 16) v[c] = (unsigned)row[bit / 8] << 8 | row[bit / 8 + 1];
                    else if (depth == 8) v[c] = row[bit / 8];
                    else v[c] = (row[bit / 8] >> (8 - depth - (int)(bit % 8))) & ((1u << depth) - 1u);
                }
                if (ctype == 3) {
                    if ((int)v[0] >= n_pal) {
                        img_free(im); free(raw);
                        return png_fail(err, name, "a palette index beyond PLTE's entries");
                    }
                    for (c = 0; c < 3; c++) out[3 * x + c] = lut[pal[3 * v[0] + c]];
                } else if (channels >= 3) {
                    for (c = 0; c < 3; c++)
                        out[3 * x + c] = depth == 8 ? lut[v[c]] : linear ? (float)(v[c] / max)
                                                                 : srgb_to_linear(v[c] / max);
                } else {
                    float g = depth == 8 ? lut[v[0]] : linear ? (float)(v[0] / max)
                                                              : srgb_to_linear(v[0] / max);
                    out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = g;
                }
            }
        }
    }
    free(raw);
    return 1;
}

int png_read(Image *im, const char *path, int linear, Error *err)
{
    size_t len;
    ReadStatus rs;
    char *buf = read_whole_file(path, 0, "\x89PNG\r\n\x1a\n", &len, &rs);
    int ok;
    memset(im, 0, sizeof *im);
    if (!buf) {
        error_set(err, path, 0, "%s", rs == READ_OPEN ? "cannot read the PNG file"
                  : rs == READ_MAGIC ? "not a PNG file (no PNG signature)" : read_status_text(rs));
        return 0;
    }
    ok = png_read_memory((const unsigned char *)buf, len, path, linear, im, err);
    free(buf);
    return ok;
}

/* ---------------------------------------------------------------- gzip */

/* The header of the member at in[*pos] (RFC 1952 section 2.3); *pos moves to its
   deflate data.  FLG bits: 1 FTEXT (a hint, ignored), 2 FHCRC, 4 FEXTRA, 8 FNAME,
   16 FCOMMENT; bits 5-7 are reserved and must be zero. */
static ReadStatus gzip_header(const unsigned char *in, size_t n, size_t *pos)
{
    size_t p = *pos, start = *pos;
    unsigned flg;
    int field;
    if (n - p == 0) return READ_GZ_TRUNC;
    if (in[p] != 0x1F || (n - p >= 2 && in[p + 1] != 0x8B)) return READ_GZ_HEADER;
    if (n - p < 10) return READ_GZ_TRUNC;
    if (in[p + 2] != 8) return READ_GZ_HEADER;
    flg = in[p + 3];
    if (flg & 0xE0u) return READ_GZ_HEADER;
    p += 10;                           /* ID1 ID2 CM FLG, MTIME (4), XFL, OS */
    if (flg & 4u) {                    /* FEXTRA: XLEN (2 bytes, little-endian), then XLEN bytes */
        size_t xlen;
        if (n - p < 2) return READ_GZ_TRUNC;
        xlen = in[p] | (size_t)in[p + 1] << 8;
        if (n - p - 2 < xlen) return READ_GZ_TRUNC;
        p += 2 + xlen;
    }
    for (field = 8; field <= 16; field *= 2)   /* FNAME, FCOMMENT: zero-terminated */
        if (flg & (unsigned)field) {
            const unsigned char *end = (const unsigned char *)memchr(in + p, 0, n - p);
            if (!end) return READ_GZ_TRUNC;
            p = (size_t)(end - in) + 1;
        }
    if (flg & 2u) {                    /* FHCRC: the low 16 bits of the header's CRC-32 */
        if (n - p < 2) return READ_GZ_TRUNC;
        if ((crc32_png(in + start, p - start) & 0xFFFFu) != (in[p] | (uint32_t)in[p + 1] << 8))
            return READ_GZ_CRC;
        p += 2;
    }
    *pos = p;
    return READ_OK;
}

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* One member: its header, deflate data appended to z's output, and its trailer
   CRC-32 and ISIZE (the member's length mod 2^32), both checked. */
static ReadStatus gzip_member(Inflate *z)
{
    ReadStatus st = gzip_header(z->in, z->n_in, &z->pos);
    size_t size;
    if (st != READ_OK) return st;
    z->base = z->len;                  /* back-references stay inside the member */
    z->bitbuf = 0; z->bitcnt = 0;
    if (inflate_blocks(z)) {
        if (!strcmp(z->why, "truncated deflate data")) return READ_GZ_TRUNC;
        if (!strcmp(z->why, "out of memory")) return READ_NOMEM;
        if (!strcmp(z->why, "uncompressed data larger than the limit")) return READ_GZ_BIG;
        return READ_GZ_DATA;
    }
    if (z->n_in - z->pos < 8) return READ_GZ_TRUNC;
    size = z->len - z->base;
    if ((size ? crc32_png(z->out + z->base, size) : 0u) != le32(z->in + z->pos)) return READ_GZ_CRC;
    if ((uint32_t)size != le32(z->in + z->pos + 4)) return READ_GZ_SIZE;
    z->pos += 8;
    return READ_OK;
}

/* A gzip file: one or more members, their data concatenated (RFC 1952 section 2.2). */
ReadStatus gzip_inflate(const unsigned char *in, size_t n, size_t max_out, unsigned char **out,
                        size_t *n_out)
{
    Inflate z;
    ReadStatus st = READ_OK;
    memset(&z, 0, sizeof z);
    z.in = in; z.n_in = n; z.max_out = max_out;
    *out = NULL;
    *n_out = 0;
    do st = gzip_member(&z);
    while (st == READ_OK && z.pos < n);
    if (st == READ_OK && !z.out && !(z.out = (unsigned char *)malloc(1))) st = READ_NOMEM;
    if (st != READ_OK) { free(z.out); return st; }
    z.out[z.len] = '\0';
    *out = z.out;
    *n_out = z.len;
    return READ_OK;
}

/* The gzip data buf[0 .. *n) replaced by what it holds, then checked as a file
   read plainly would be: its first bytes against magic, and (text) for NUL bytes. */
static ReadStatus gunzip_checked(char **buf, size_t *n, int text, const char *magic)
{
    unsigned char *out;
    size_t n_out, nm = magic ? strlen(magic) : 0;
    ReadStatus st = gzip_inflate((const unsigned char *)*buf, *n, READ_MAX_BYTES, &out, &n_out);
    free(*buf);
    *buf = (char *)out;
    *n = n_out;
    if (st != READ_OK) return st;
    if (magic && (n_out < nm || memcmp(out, magic, nm) != 0)) return READ_MAGIC;
    if (text && memchr(out, '\0', n_out)) return READ_NUL;
    return READ_OK;
}

char *read_whole_file_gz(const char *path, int flags, const char *magic, size_t *len,
                         ReadStatus *st)
{
    char *buf = read_whole_file(path, flags | READ_GUNZIP, magic, len, st);
    if (!buf || *len < 2 || (unsigned char)buf[0] != 0x1F || (unsigned char)buf[1] != 0x8B)
        return buf;
    *st = gunzip_checked(&buf, len, flags & READ_TEXT, magic);
    if (*st == READ_OK) return buf;
    free(buf);
    *len = 0;
    return NULL;
}
