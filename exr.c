/* exr.c - a small OpenEXR reader, for image textures and environment maps, and
   a writer, for pbrt-v4's Film "spectral".

   Exported (specnee.h section 10): exr_read_memory, exr_read, exr_read_space, exr_read_named,
   exr_read_memory_named, exr_write, exr_write_memory, exr_float_to_half,
   exr_half_to_float.  texture.c and infinite.c read an imagemap texture's or an
   infinite light's .exr with exr_read (a .pfm of the same name beside it is read
   instead, when there is one); render.c's img_write_spectral writes the spectral
   film with exr_write; the tests read named channels (the film's buckets) back
   with exr_read_named.

   WHAT IT READS (the OpenEXR file layout, openexr.com "OpenEXR File Layout")
     All numbers little-endian.  The magic number 76 2f 31 01, then the version
     field: version 2 in the low byte, and flags: 0x200 tiled, 0x400 long names
     (names up to 255 bytes, read either way), 0x800 deep data, 0x1000 multi-part.
     Tiled, deep and multi-part files are refused by name.  Then the header:
     attributes, each a name (NUL-terminated), a type name (NUL-terminated), a size
     (int32) and that many bytes of value, up to an empty name (one NUL byte).
     Read here:
       channels     chlist: per channel its name, the pixel type (int32: 0 UINT,
                    1 HALF, 2 FLOAT), pLinear (1 byte), 3 reserved bytes, x and y
                    sampling (int32, must be 1), up to an empty name
       compression  1 byte: 0 NONE, 1 RLE, 2 ZIPS, 3 ZIP are read; 4 PIZ, 5 PXR24,
                    6 B44, 7 B44A, 8 DWAA, 9 DWAB and any other are refused by name
       dataWindow   box2i (xMin, yMin, xMax, yMax, int32): the pixels the file holds
       type         (multi-part headers) anything but "scanlineimage" is refused
       chromaticities  8 floats: the primaries' and the white's CIE xy (rx, ry, gx,
                    gy, bx, by, wx, wy): the colour space of the RGB values
                    (exr_read_space; below)
     and every other attribute is skipped (displayWindow, lineOrder, ...).
     After the header, the line offset table: one uint64 file offset per block of
     scan lines (1 line a block for NONE, RLE, ZIPS; 16 for ZIP), then the blocks:
     y of its first line (int32), the size of its data (int32), the data.  A block's
     data holds its lines in turn, and each line the samples of every channel in
     the order of the channel list (which writers sort by name): all of R's, then
     all of G's, ...  A block is read at the offset the table gives, and placed by
     its own y, so the line order (increasing or decreasing y in the file) does not
     matter; every block must come exactly once.

   COMPRESSION.  A block whose data is as long as its raw lines is stored raw,
   whatever the compression (writers do so when compressing does not pay).  Else:
     ZIP, ZIPS  the data is a zlib stream (png.c's zlib_inflate);
     RLE        runs: a byte c < 128 then one byte b gives c + 1 copies of b; a byte
                c >= 128 gives the next 256 - c bytes as they are.
   Both then undo two steps the writer took to make the bytes compress better:
     predictor   t[i] = t[i - 1] + t[i] - 128 (mod 256), for i = 1 .. n - 1
     interleave  the raw bytes are out[2k] = t[k], out[2k + 1] = t[(n + 1) / 2 + k]
                 (the writer put the even-numbered bytes first, then the odd ones).

   PIXELS.  HALF is IEEE 754 binary16: sign s, exponent e (5 bits), mantissa m
   (10 bits); (-1)^s (1024 + m) 2^(e - 25) for e = 1 .. 30, (-1)^s m 2^-24 for e = 0
   (zero and subnormals), infinity (m = 0) or NaN for e = 31: exact in a float.
   FLOAT is IEEE binary32; UINT an unsigned 32-bit integer, converted to the
   nearest float.  Non-finite values are kept, as pfm_read keeps them: the
   infinite light refuses them, an image texture clamps them (texture.c).

   THE RESULT.  An Image of the data window, rows top to bottom (EXR's y grows
   downwards), 3 floats a pixel: R, G, B when the file has all three, else Y
   repeated (a luminance image), else an error.  Other channels (A, layers such as
   "diffuse.R") are skipped.  exr_read_named reads three channels named by the
   caller into the three floats instead (a name may repeat).  The display window
   is not read: pbrt-v4 also makes its image of the data window.

   THE WRITER (exr_write).  The same layout, the simplest way: version 2 with no
   flags, compression NONE, one scan line a block, lines in increasing y.  The
   header holds the attributes every OpenEXR file must have (channels,
   compression, dataWindow, displayWindow, lineOrder, pixelAspectRatio 1,
   screenWindowCenter (0, 0), screenWindowWidth 1) and the caller's strings;
   the channel list is sorted by name (strcmp order, as OpenEXR's ChannelList
   keeps it), and each line holds the channels in that order.  HALF values are
   rounded to the nearest binary16, ties to even (exr_float_to_half): a float
   whose magnitude is 65520 or more becomes infinity, one at most 2^-25 becomes
   zero, and between 2^-25 and 2^-14 a subnormal m 2^-24.

   THE COLOUR SPACE (exr_read_space).  pbrt-v4's ReadEXR gives the image the colour
   space its "chromaticities" name, through RGBColorSpace::Lookup (rgbfit.c's
   colorspace_lookup: ACES2065-1, DCI-P3, Rec2020 or sRGB, each coordinate within
   1e-3 relative), sRGB when the file has none, and sRGB with a warning when they
   match none of the four; the consumers of the image (texture.c, infinite.c)
   then fit its RGB in that space.  exr_read_space reports the space, -1 for "given
   and matching none" (the caller notes it at its file:line and reads sRGB, as
   pbrt-v4 does); exr_read ignores the attribute (normal maps: pbrt-v4 reads
   their values as they are).

   HOSTILE INPUT.  Every read is bounds-checked against the file's length; sizes
   are checked before anything is allocated: the pixel count against
   IMG_MAX_PIXELS, the memory against MEM_BUDGET_MIB, the offset table against the
   file, and the pixel data against what the rest of the file can hold at the
   compression's greatest expansion (RLE 64: 2 bytes give 128; deflate 1032).
   Every loop consumes input or output, so nothing hangs. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

#define EXR_MAX_CHANNELS 64
#define EXR_MAX_NAME 256          /* a name with its NUL (long names: 255 bytes) */
#define EXR_DEFLATE_EXPANSION 1032.0   /* a 258-byte copy coded in 2 bits */
#define EXR_RLE_EXPANSION 64.0         /* a 2-byte run gives 128 bytes */

typedef struct {
    char name[EXR_MAX_NAME];
    int type;                     /* 0 UINT, 1 HALF, 2 FLOAT */
    size_t offset;                /* of its samples within a line */
} ExrChannel;

typedef struct {
    const unsigned char *d;       /* the file */
    size_t n, pos;                /* its length, the next byte */
    const char *name;             /* for messages */
    Error *err;
    ExrChannel ch[EXR_MAX_CHANNELS];
    int n_ch, compression, have_channels, have_window;
    int space;                    /* "chromaticities": COLORSPACE_*, -1 none of them */
    const char *const *want;      /* three channel names to read; NULL: R G B, or Y */
    int slot[3];                  /* the channel read into each float of a pixel */
    long long x0, y0, x1, y1;     /* the data window */
    /* from plan(): */
    int w, h;                     /* the image */
    int lpb;                      /* scan lines a block */
    size_t line_bytes, block_bytes, n_blocks;
} Exr;

static int exr_fail(Exr *x, const char *what)
{
    error_set(x->err, x->name, 0, "EXR: %s", what);
    return 0;
}

/* A refusal of something this reader does not read, with the commands that
   convert the file to a PFM of the same name beside it (the builders read that one). */
static int exr_refuse(Exr *x, const char *what)
{
    const char *base = strrchr(x->name, '/');
    int stem;
    base = base ? base + 1 : x->name;
    stem = (int)strlen(base);
    if (stem > 4 && base[stem - 4] == '.' && (base[stem - 3] | 32) == 'e' &&
        (base[stem - 2] | 32) == 'x' && (base[stem - 1] | 32) == 'r') stem -= 4;
    if (stem > 64) stem = 64;
    error_set(x->err, x->name, 0, "EXR: %s is not supported (specnee reads scan-line images "
              "compressed NONE, RLE, ZIPS or ZIP); convert it to a .pfm beside it: `imgtool convert "
              "--outfile %.*s.pfm %s` (pbrt-v4) or `oiiotool %s -o %.*s.pfm`", what, stem, base,
              base, base, stem, base);
    return 0;
}

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static long long le32s(const unsigned char *p)   /* a signed int32 */
{
    uint32_t u = le32(p);
    return u >= 0x80000000u ? (long long)u - 4294967296LL : (long long)u;
}

/* A NUL-terminated name at x->pos, at most EXR_MAX_NAME - 1 bytes, into out. */
static int read_name(Exr *x, char *out)
{
    size_t k;
    for (k = 0; k < EXR_MAX_NAME; k++) {
        if (x->pos + k >= x->n) return exr_fail(x, "truncated header (a name runs past the end)");
        out[k] = (char)x->d[x->pos + k];
        if (!out[k]) { x->pos += k + 1; return 1; }
    }
    return exr_fail(x, "a name in the header longer than 255 bytes");
}

/* The channel list: value bytes v[0 .. size). */
static int read_channels(Exr *x, const unsigned char *v, size_t size)
{
    size_t p = 0;
    x->n_ch = 0;
    for (;;) {
        size_t len;
        ExrChannel *c;
        if (p >= size) return exr_fail(x, "truncated channel list");
        if (v[p] == 0) break;
        for (len = 0; p + len < size && v[p + len]; len++) {}
        if (p + len >= size || len >= EXR_MAX_NAME || size - p - len - 1 < 16)
            return exr_fail(x, "truncated channel list");
        if (x->n_ch == EXR_MAX_CHANNELS) return exr_fail(x, "more than 64 channels");
        c = &x->ch[x->n_ch++];
        memcpy(c->name, v + p, len + 1);
        p += len + 1;
        c->type = (int)le32s(v + p);
        if (c->type < 0 || c->type > 2) return exr_fail(x, "a channel of unknown pixel type (EXR has 0 UINT, 1 HALF, 2 FLOAT)");
        if (le32s(v + p + 8) != 1 || le32s(v + p + 12) != 1) {
            char what[EXR_MAX_NAME + 64];
            snprintf(what, sizeof what, "channel \"%s\" subsampled (x or y sampling not 1)", c->name);
            return exr_refuse(x, what);
        }
        p += 16;
    }
    if (x->n_ch == 0) return exr_fail(x, "no channels");
    x->have_channels = 1;
    return 1;
}

/* Magic, version, and the header's attributes; x->pos ends at the offset table. */
static int read_header(Exr *x)
{
    static const char *const names[] = { "NONE", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44",
                                         "B44A", "DWAA", "DWAB" };
    uint32_t version;
    x->compression = -1;
    if (x->n < 8 || le32(x->d) != 20000630u) return exr_fail(x, "not an OpenEXR file (no magic number 76 2f 31 01)");
    version = le32(x->d + 4);
    if ((version & 0xff) != 2) return exr_fail(x, "unknown version (specnee reads version 2)");
    if (version & 0x1000) return exr_refuse(x, "a multi-part file");
    if (version & 0x800) return exr_refuse(x, "deep data");
    if (version & 0x200) return exr_refuse(x, "a tiled image");
    if (version & ~(uint32_t)0x4ff) return exr_fail(x, "unknown flags in the version field");
    x->pos = 8;
    for (;;) {
        char name[EXR_MAX_NAME], type[EXR_MAX_NAME];
        const unsigned char *v;
        long long size;
        if (x->pos >= x->n) return exr_fail(x, "truncated header (no end of header)");
        if (x->d[x->pos] == 0) { x->pos++; break; }
        if (!read_name(x, name) || !read_name(x, type)) return 0;
        if (x->n - x->pos < 4) return exr_fail(x, "truncated header (an attribute's size)");
        size = le32s(x->d + x->pos);
        x->pos += 4;
        if (size < 0 || (unsigned long long)size > x->n - x->pos)
            return exr_fail(x, "truncated header (an attribute is longer than the file)");
        v = x->d + x->pos;
        x->pos += (size_t)size;
        if (!strcmp(name, "channels")) {
            if (strcmp(type, "chlist") != 0) return exr_fail(x, "\"channels\" is not a chlist");
            if (!read_channels(x, v, (size_t)size)) return 0;
        } else if (!strcmp(name, "compression")) {
            if (strcmp(type, "compression") != 0 || size != 1) return exr_fail(x, "bad \"compression\" attribute");
            x->compression = v[0];
        } else if (!strcmp(name, "dataWindow")) {
            if (strcmp(type, "box2i") != 0 || size != 16) return exr_fail(x, "bad \"dataWindow\" attribute");
            x->x0 = le32s(v); x->y0 = le32s(v + 4); x->x1 = le32s(v + 8); x->y1 = le32s(v + 12);
            x->have_window = 1;
        } else if (!strcmp(name, "chromaticities") && !strcmp(type, "chromaticities")) {
            float xy[8];
            int k;
            if (size != 32) return exr_fail(x, "bad \"chromaticities\" attribute (not 8 floats)");
            for (k = 0; k < 8; k++) {              /* IEEE binary32, little-endian */
                uint32_t u = le32(v + 4 * k);
                memcpy(&xy[k], &u, sizeof u);
            }
            x->space = colorspace_lookup(xy);
        } else if (!strcmp(name, "type")) {
            if (strcmp(type, "string") != 0 || size != 13 || memcmp(v, "scanlineimage", 13) != 0) {
                char what[64];
                snprintf(what, sizeof what, "a part of type \"%.*s\"", size < 20 ? (int)size : 20, (const char *)v);
                return exr_refuse(x, what);
            }
        }
    }
    if (!x->have_channels) return exr_fail(x, "no \"channels\" attribute");
    if (x->compression < 0) return exr_fail(x, "no \"compression\" attribute");
    if (!x->have_window) return exr_fail(x, "no \"dataWindow\" attribute");
    if (x->compression > 3) {
        char what[64];
        if (x->compression < 10) snprintf(what, sizeof what, "%s compression", names[x->compression]);
        else snprintf(what, sizeof what, "compression %d", x->compression);
        return exr_refuse(x, what);
    }
    return 1;
}

/* RLE runs in[0 .. n_in) into out[0 .. n_out), which they must fill exactly. */
static const char *rle_decode(const unsigned char *in, size_t n_in, unsigned char *out, size_t n_out)
{
    size_t i = 0, o = 0;
    while (i < n_in) {
        unsigned c = in[i++];
        if (c < 128) {                          /* c + 1 copies of the next byte */
            size_t k = (size_t)c + 1;
            if (i >= n_in) return "RLE data: a run without its byte";
            if (k > n_out - o) return "RLE data: more bytes than the lines hold";
            memset(out + o, in[i++], k);
            o += k;
        } else {                                /* 256 - c bytes as they are */
            size_t k = 256 - (size_t)c;
            if (k > n_in - i) return "RLE data: a literal run past the end of the block";
            if (k > n_out - o) return "RLE data: more bytes than the lines hold";
            memcpy(out + o, in + i, k);
            i += k;
            o += k;
        }
    }
    return o == n_out ? NULL : "RLE data: fewer bytes than the lines hold";
}

/* Undo the predictor and the interleave: t[0 .. n) into out[0 .. n). */
static void unpredict(unsigned char *t, unsigned char *out, size_t n)
{
    size_t i, half = (n + 1) / 2;
    for (i = 1; i < n; i++) t[i] = (unsigned char)(t[i - 1] + t[i] - 128);
    for (i = 0; i < half; i++) {
        out[2 * i] = t[i];
        if (2 * i + 1 < n) out[2 * i + 1] = t[half + i];
    }
}

/* A binary16 number as a float (exact). */
float exr_half_to_float(unsigned h)
{
    unsigned e = (h >> 10) & 31u, m = h & 1023u;
    float v;
    if (e == 0) v = ldexpf((float)m, -24);
    else if (e == 31) v = m ? NAN : INFINITY;
    else v = ldexpf((float)(m + 1024u), (int)e - 25);
    return (h & 0x8000u) ? -v : v;
}

/* One sample of channel c, pixel i of a line's bytes. */
static float sample(const unsigned char *line, const ExrChannel *c, size_t i)
{
    float f;
    if (c->type == 1) {
        const unsigned char *p = line + c->offset + 2 * i;
        return exr_half_to_float((unsigned)p[0] | (unsigned)p[1] << 8);
    }
    if (c->type == 0) return (float)le32(line + c->offset + 4 * i);
    {
        uint32_t u = le32(line + c->offset + 4 * i);
        memcpy(&f, &u, sizeof f);
    }
    return f;
}

/* The lines of raw (lines x line_bytes) into rows row0 .. of im. */
static void put_lines(const Exr *x, const unsigned char *raw, int lines, int row0, Image *im)
{
    int l, k;
    size_t i;
    for (l = 0; l < lines; l++) {
        const unsigned char *line = raw + (size_t)l * x->line_bytes;
        float *out = im->rgb + 3 * (size_t)(row0 + l) * (size_t)im->w;
        for (k = 0; k < 3; k++)
            for (i = 0; i < (size_t)im->w; i++) out[3 * i + (size_t)k] = sample(line, &x->ch[x->slot[k]], i);
    }
}

/* The index of the channel called name, -1 if none. */
static int channel_index(const Exr *x, const char *name)
{
    int k;
    for (k = 0; k < x->n_ch; k++)
        if (!strcmp(x->ch[k].name, name)) return k;
    return -1;
}

/* The channel read into each of a pixel's three floats: the caller's names, else
   R, G, B, else Y three times. */
static int choose_slots(Exr *x)
{
    static const char *const rgb[3] = { "R", "G", "B" };
    const char *const *names = x->want ? x->want : rgb;
    int k;
    for (k = 0; k < 3; k++) x->slot[k] = channel_index(x, names[k]);
    if (x->want) {
        for (k = 0; k < 3; k++)
            if (x->slot[k] < 0) {
                char msg[EXR_MAX_NAME + 32];
                snprintf(msg, sizeof msg, "no channel \"%s\"", x->want[k]);
                return exr_fail(x, msg);
            }
    } else if (x->slot[0] < 0 || x->slot[1] < 0 || x->slot[2] < 0) {
        x->slot[0] = x->slot[1] = x->slot[2] = channel_index(x, "Y");
        if (x->slot[0] < 0)
            return exr_fail(x, "no R, G, B channels and no Y channel (specnee reads RGB or luminance images)");
    }
    return 1;
}

/* After the header: the channels to read, the image's size, the block layout, and
   every check that must pass before anything is allocated.  x->pos stays at the
   offset table. */
static int plan(Exr *x)
{
    int k;
    long long w, h;
    double raw_total, expansion, line_bytes_d = 0.0, memory;
    if (!choose_slots(x)) return 0;
    w = x->x1 - x->x0 + 1;
    h = x->y1 - x->y0 + 1;
    if (w < 1 || h < 1) return exr_fail(x, "an empty data window (xMax < xMin or yMax < yMin)");
    if ((double)w * (double)h > (double)IMG_MAX_PIXELS) return exr_fail(x, "more pixels than IMG_MAX_PIXELS");
    x->w = (int)w;
    x->h = (int)h;
    x->lpb = x->compression == 3 ? 16 : 1;
    for (k = 0; k < x->n_ch; k++) line_bytes_d += (double)w * (x->ch[k].type == 1 ? 2.0 : 4.0);
    memory = 2.0 * line_bytes_d * (double)(h < x->lpb ? h : x->lpb) + 12.0 * (double)w * (double)h;
    if (memory > (double)MEM_BUDGET_MIB * 1048576.0) {
        char msg[160];
        snprintf(msg, sizeof msg, "%lld x %lld pixels need %.1f GiB, more than specnee's memory "
                 "budget (MEM_BUDGET_MIB in specnee.h)", w, h, memory / 1073741824.0);
        return exr_fail(x, msg);
    }
    x->line_bytes = 0;
    for (k = 0; k < x->n_ch; k++) {
        x->ch[k].offset = x->line_bytes;
        x->line_bytes += (size_t)w * (x->ch[k].type == 1 ? 2u : 4u);
    }
    x->block_bytes = x->line_bytes * (size_t)(h < x->lpb ? h : x->lpb);
    x->n_blocks = (size_t)((h + x->lpb - 1) / x->lpb);
    if (x->n_blocks > (x->n - x->pos) / 8) return exr_fail(x, "truncated (the line offset table is longer than the file)");
    raw_total = (double)x->line_bytes * (double)h;
    expansion = x->compression == 0 ? 1.0 : x->compression == 1 ? EXR_RLE_EXPANSION : EXR_DEFLATE_EXPANSION;
    if ((double)(x->n - x->pos - 8 * x->n_blocks) * expansion < raw_total)
        return exr_fail(x, "truncated (the pixel data is too short for the data window)");
    return 1;
}

/* Block b of the offset table, decoded (through raw and tmp, block_bytes each) into
   its rows of im; seen[] marks the blocks read. */
static int read_block(Exr *x, size_t b, unsigned char *raw, unsigned char *tmp, unsigned char *seen,
                      Image *im)
{
    const unsigned char *e = x->d + x->pos + 8 * b, *body;
    uint32_t lo = le32(e), hi = le32(e + 4);
    long long y, size, first;
    size_t off, need;
    int lines;
    const char *why = NULL;
    char msg[96];
    if (hi != 0 || lo > x->n || x->n - lo < 8) {
        snprintf(msg, sizeof msg, "truncated (block %lu's offset is past the end of the file)", (unsigned long)b);
        return exr_fail(x, msg);
    }
    off = lo;
    y = le32s(x->d + off);
    size = le32s(x->d + off + 4);
    body = x->d + off + 8;
    first = y - x->y0;
    if (first < 0 || first >= x->h || first % x->lpb != 0) {
        snprintf(msg, sizeof msg, "block %lu starts at line y = %lld, not a block of the data window",
                 (unsigned long)b, y);
        return exr_fail(x, msg);
    }
    if (seen[first / x->lpb]++) {
        snprintf(msg, sizeof msg, "two blocks for line y = %lld", y);
        return exr_fail(x, msg);
    }
    lines = (int)(x->h - first < x->lpb ? x->h - first : x->lpb);
    need = x->line_bytes * (size_t)lines;
    if (size < 0 || (unsigned long long)size > x->n - off - 8) {
        snprintf(msg, sizeof msg, "truncated (block %lu is longer than the file)", (unsigned long)b);
        return exr_fail(x, msg);
    }
    if ((size_t)size == need) memcpy(raw, body, need);          /* stored raw */
    else if (x->compression == 0 || (size_t)size > need) why = "a block's size does not match its lines";
    else {
        why = x->compression == 1 ? rle_decode(body, (size_t)size, tmp, need)
                                  : zlib_inflate(body, (size_t)size, tmp, need);
        if (!why) unpredict(tmp, raw, need);
    }
    if (why) {
        snprintf(msg, sizeof msg, "block at line y = %lld: %s", y, why);
        return exr_fail(x, msg);
    }
    put_lines(x, raw, lines, (int)first, im);
    return 1;
}

/* The reader: the image, and (space not NULL) the colour space of its
   chromaticities (COLORSPACE_SRGB when it has none). */
static int exr_decode(const unsigned char *data, size_t n, const char *name,
                      const char *const want[3], Image *im, int *space, Error *err)
{
    Exr *x;
    int ok = 0;
    size_t b;
    unsigned char *raw = NULL, *tmp = NULL, *seen = NULL;
    memset(im, 0, sizeof *im);
    x = (Exr *)calloc(1, sizeof *x);
    if (!x) { error_set(err, name ? name : "<exr>", 0, "EXR: out of memory"); return 0; }
    x->d = data; x->n = n; x->name = name ? name : "<exr>"; x->err = err; x->want = want;
    if (read_header(x) && plan(x)) {
        raw = (unsigned char *)malloc(x->block_bytes);
        tmp = (unsigned char *)malloc(x->block_bytes);
        seen = (unsigned char *)calloc(x->n_blocks, 1);
        if (!raw || !tmp || !seen || !img_alloc(im, x->w, x->h)) exr_fail(x, "out of memory");
        else
            /* the blocks, in the order of the offset table, each placed by its own y */
            for (ok = 1, b = 0; ok && b < x->n_blocks; b++) ok = read_block(x, b, raw, tmp, seen, im);
    }
    if (!ok) img_free(im);
    if (space) *space = x->space;
    free(raw);
    free(tmp);
    free(seen);
    free(x);
    return ok;
}

int exr_read_memory_named(const unsigned char *data, size_t n, const char *name,
                          const char *const want[3], Image *im, Error *err)
{
    return exr_decode(data, n, name, want, im, NULL, err);
}

int exr_read_memory(const unsigned char *data, size_t n, const char *name, Image *im, Error *err)
{
    return exr_read_memory_named(data, n, name, NULL, im, err);
}

/* A file, read whole, decoded (space: as exr_decode). */
static int exr_read_file(Image *im, const char *path, const char *const want[3], int *space,
                         Error *err)
{
    size_t len;
    ReadStatus rs;
    char *buf = read_whole_file(path, 0, "\x76\x2f\x31\x01", &len, &rs);
    int ok;
    memset(im, 0, sizeof *im);
    if (!buf) {
        error_set(err, path, 0, "%s", rs == READ_OPEN ? "cannot read the EXR file"
                  : rs == READ_MAGIC ? "EXR: not an OpenEXR file (no magic number 76 2f 31 01)"
                  : read_status_text(rs));
        return 0;
    }
    ok = exr_decode((const unsigned char *)buf, len, path, want, im, space, err);
    free(buf);
    return ok;
}

int exr_read_named(Image *im, const char *path, const char *const want[3], Error *err)
{
    return exr_read_file(im, path, want, NULL, err);
}

int exr_read(Image *im, const char *path, Error *err)
{
    return exr_read_file(im, path, NULL, NULL, err);
}

int exr_read_space(Image *im, const char *path, int *space, Error *err)
{
    return exr_read_file(im, path, NULL, space, err);
}

/* ------------------------------------------------------------------ the writer */

/* f rounded to the nearest binary16, ties to even (the bits; NaN stays a NaN). */
unsigned exr_float_to_half(float f)
{
    uint32_t u, a, h;
    unsigned sign;
    memcpy(&u, &f, sizeof u);
    sign = (unsigned)(u >> 16) & 0x8000u;
    a = u & 0x7fffffffu;
    if (a > 0x7f800000u) return sign | 0x7e00u;            /* NaN */
    /* >= 65520 (and inf): infinity.  From 65520 up the normal case below would
       round up into the infinity's bits by itself; from 65536 it would not */
    if (a >= 0x477ff000u) return sign | 0x7c00u;           /* >= 65520 (and inf): infinity */
    if (a >= 0x38800000u) {                                /* >= 2^-14: normal */
        uint32_t rem = a & 0x1fffu;
        h = (a - 0x38000000u) >> 13;                       /* exponent 127 -> 15 bias */
        if (rem > 0x1000u || (rem == 0x1000u && (h & 1u))) h++;
        return sign | (unsigned)h;
    }
    if (a <= 0x33000000u) return sign;                     /* <= 2^-25: zero (and no shift of 32 or more below) */
    {   /* subnormal: m 2^-24 with m = the 24-bit significand >> (126 - exponent) */
        int shift = 126 - (int)(a >> 23);
        uint32_t mant = (a & 0x7fffffu) | 0x800000u, half = 1u << (shift - 1);
        uint32_t rem = mant & ((1u << shift) - 1u);
        h = mant >> shift;
        if (rem > half || (rem == half && (h & 1u))) h++;
        return sign | (unsigned)h;
    }
}

/* A growing byte buffer; ok drops to 0 when memory runs out. */
typedef struct { unsigned char *d; size_t n, cap; int ok; } Bytes;

static void put(Bytes *b, const void *p, size_t n)
{
    if (!b->ok) return;
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        unsigned char *d;
        while (cap < b->n + n) cap *= 2;
        if (!(d = (unsigned char *)realloc(b->d, cap))) { b->ok = 0; return; }
        b->d = d;
        b->cap = cap;
    }
    memcpy(b->d + b->n, p, n);
    b->n += n;
}

static void put32(Bytes *b, uint32_t v)
{
    unsigned char p[4];
    p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24);
    put(b, p, 4);
}

/* An attribute's name, type and size; its value follows. */
static void put_attr(Bytes *b, const char *name, const char *type, size_t size)
{
    put(b, name, strlen(name) + 1);
    put(b, type, strlen(type) + 1);
    put32(b, (uint32_t)size);
}

static void put_box(Bytes *b, const char *name, int x0, int y0, int x1, int y1)
{
    put_attr(b, name, "box2i", 16);
    put32(b, (uint32_t)x0); put32(b, (uint32_t)y0); put32(b, (uint32_t)x1); put32(b, (uint32_t)y1);
}

static void put_float(Bytes *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put32(b, u);
}

/* order[0 .. n): the channels' indices sorted by name (insertion sort, strcmp). */
static void sort_channels(const ExrWrite *im, int *order)
{
    int i, j;
    for (i = 0; i < im->n_ch; i++) {
        int c = order[i] = i;
        for (j = i; j > 0 && strcmp(im->names[order[j - 1]], im->names[c]) > 0; j--)
            order[j] = order[j - 1];
        order[j] = c;
    }
}

/* The header: magic, version, attributes, the end of the header. */
static void put_header(Bytes *b, const ExrWrite *im, const int *order)
{
    static const unsigned char zero4[4] = { 0, 0, 0, 0 }, none = 0;
    size_t chlist = 1;
    int k;
    put32(b, 20000630u);
    put32(b, 2u);
    for (k = 0; k < im->n_ch; k++) chlist += strlen(im->names[k]) + 1 + 16;
    put_attr(b, "channels", "chlist", chlist);
    for (k = 0; k < im->n_ch; k++) {
        const char *name = im->names[order[k]];
        put(b, name, strlen(name) + 1);
        put32(b, im->half ? 1u : 2u);           /* HALF or FLOAT */
        put(b, zero4, 4);                       /* pLinear 0, 3 reserved bytes */
        put32(b, 1u);                           /* x and y sampling */
        put32(b, 1u);
    }
    put(b, &none, 1);
    put_attr(b, "compression", "compression", 1);
    put(b, &none, 1);                           /* NONE */
    put_box(b, "dataWindow", im->x0, im->y0, im->x0 + im->w - 1, im->y0 + im->h - 1);
    put_box(b, "displayWindow", 0, 0, im->full_w - 1, im->full_h - 1);
    put_attr(b, "lineOrder", "lineOrder", 1);
    put(b, &none, 1);                           /* INCREASING_Y */
    put_attr(b, "pixelAspectRatio", "float", 4);
    put_float(b, 1.0f);
    put_attr(b, "screenWindowCenter", "v2f", 8);
    put_float(b, 0.0f);
    put_float(b, 0.0f);
    put_attr(b, "screenWindowWidth", "float", 4);
    put_float(b, 1.0f);
    for (k = 0; k < im->n_str; k++) {
        put_attr(b, im->str_key[k], "string", strlen(im->str_val[k]));
        put(b, im->str_val[k], strlen(im->str_val[k]));
    }
    put(b, &none, 1);
}

unsigned char *exr_write_memory(const ExrWrite *im, size_t *n)
{
    Bytes b = { NULL, 0, 0, 1 };
    int order[EXR_MAX_CHANNELS], y, k, i;
    size_t table, line = (size_t)im->w * (size_t)im->n_ch * (im->half ? 2u : 4u);
    if (im->n_ch < 1 || im->n_ch > EXR_MAX_CHANNELS || im->w < 1 || im->h < 1) return NULL;
    sort_channels(im, order);
    put_header(&b, im, order);
    table = b.n;
    for (y = 0; y < im->h; y++) {               /* the offset table: one line a block */
        uint64_t off = table + 8u * (uint64_t)im->h + (uint64_t)y * (8u + line);
        put32(&b, (uint32_t)off);
        put32(&b, (uint32_t)(off >> 32));
    }
    for (y = 0; y < im->h; y++) {
        put32(&b, (uint32_t)(im->y0 + y));
        put32(&b, (uint32_t)line);
        for (k = 0; k < im->n_ch; k++)
            for (i = 0; i < im->w; i++) {
                float v = im->v[((size_t)y * (size_t)im->w + (size_t)i) * (size_t)im->n_ch + (size_t)order[k]];
                if (im->half) {
                    unsigned h = exr_float_to_half(v);
                    unsigned char p[2];
                    p[0] = (unsigned char)h; p[1] = (unsigned char)(h >> 8);
                    put(&b, p, 2);
                } else {
                    put_float(&b, v);
                }
            }
    }
    if (!b.ok) { free(b.d); return NULL; }
    *n = b.n;
    return b.d;
}

int exr_write(const char *path, const ExrWrite *im, Error *err)
{
    size_t n = 0;
    unsigned char *d = exr_write_memory(im, &n);
    FILE *f;
    int ok;
    if (!d) { error_set(err, path, 0, "EXR: out of memory"); return 0; }
    f = fopen(path, "wb");
    ok = f && fwrite(d, 1, n, f) == n;
    if (f && fclose(f) != 0) ok = 0;
    free(d);
    if (!ok) error_set(err, path, 0, "cannot write");
    return ok;
}
