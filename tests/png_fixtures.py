# tests/png_fixtures.py - makes tests/png_fixtures.h, the small PNGs of
# tests/test_png.c, with Python's own zlib (a second, independent encoder):
#     python3 tests/png_fixtures.py > tests/png_fixtures.h [DIR: also write DIR/*.png]
# Each PNG: IHDR, PLTE/tRNS where given, a tEXt chunk (ancillary, skipped), the
# zlib stream split over two IDAT chunks, IEND.  Rows are filtered with the filter
# types listed (all five appear), the deflate blocks are stored (level 0), fixed
# Huffman (Z_FIXED) or dynamic Huffman (default strategy, asserted from BTYPE),
# and 'multi' puts a full flush (an empty stored block) between two blocks.
# want_NAME holds the samples each image was made from (row-major, per pixel
# its channels; palette images: the indices).
import zlib, struct, sys

def chunk(t, d):
    c = struct.pack('>I', len(d)) + t + d
    return c + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)

def filt(rows, bpp, types):
    out = b''; prev = bytes(len(rows[0]))
    for r, ft in zip(rows, types):
        f = bytearray()
        for i in range(len(r)):
            a = r[i - bpp] if i >= bpp else 0
            b = prev[i]; c = prev[i - bpp] if i >= bpp else 0
            if ft == 0: p = 0
            elif ft == 1: p = a
            elif ft == 2: p = b
            elif ft == 3: p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            f.append((r[i] - p) & 0xff)
        out += bytes([ft]) + bytes(f); prev = r
    return out

def deflate(raw, mode):
    if mode == 'fixed':
        co = zlib.compressobj(9, zlib.DEFLATED, 15, 9, zlib.Z_FIXED); return co.compress(raw) + co.flush()
    if mode == 'stored':
        return zlib.compress(raw, 0)
    if mode == 'multi':   # a dynamic/fixed block, a full flush (empty stored block), then more
        co = zlib.compressobj(9)
        h = len(raw) // 2
        return co.compress(raw[:h]) + co.flush(zlib.Z_FULL_FLUSH) + co.compress(raw[h:]) + co.flush()
    co = zlib.compressobj(9, zlib.DEFLATED, 15, 9, zlib.Z_DEFAULT_STRATEGY); return co.compress(raw) + co.flush()

def btype(z):
    return (z[2] >> 1) & 3

def pack_bits(vals, depth):
    out = bytearray(); acc = 0; n = 0
    for v in vals:
        acc = (acc << depth) | v; n += depth
        if n == 8: out.append(acc); acc = 0; n = 0
    if n: out.append(acc << (8 - n))
    return bytes(out)

def png(w, h, depth, ctype, samples, spp, mode, ftypes, plte=None, trns=None):
    # samples: row-major list of ints, spp samples per pixel
    rows = []
    for y in range(h):
        s = samples[y * w * spp:(y + 1) * w * spp]
        if depth < 8: rows.append(pack_bits(s, depth))
        elif depth == 8: rows.append(bytes(s))
        else: rows.append(b''.join(struct.pack('>H', v) for v in s))
    bpp = max(1, depth * spp // 8)
    raw = filt(rows, bpp, ftypes)
    z = deflate(raw, mode)
    d = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, depth, ctype, 0, 0, 0))
    if plte: d += chunk(b'PLTE', bytes(plte))
    if trns: d += chunk(b'tRNS', bytes(trns))
    d += chunk(b'tEXt', b'Comment\x00made by mkpng.py')
    # the IDAT split in two chunks
    k = len(z) // 2
    d += chunk(b'IDAT', z[:k]) + chunk(b'IDAT', z[k:]) + chunk(b'IEND', b'')
    return d, btype(z)

cases = []
W, H = 7, 5
def pat(n, mod, mul=37, add=11):
    return [(i * mul + add + (i * i) % 13) % mod for i in range(n)]
# name, w, h, depth, ctype, spp, mode, filters, plte, trns
specs = [
    ('rgb8_dynamic', 24, 10, 8, 2, 3, 'dynamic', [0, 1, 2, 3, 4] * 2, None, [0, 1, 0, 2, 0, 3]),
    ('rgba8_fixed', W, H, 8, 6, 4, 'fixed', [4, 3, 2, 1, 0], None, None),
    ('grey8_stored', W, H, 8, 0, 1, 'stored', [1, 4, 4, 3, 2], None, None),
    ('greya8_multi', 40, 12, 8, 4, 2, 'multi', [4, 1, 2, 3, 0, 4, 4, 1, 2, 3, 0, 4], None, None),
    ('grey16_dynamic', 20, 8, 16, 0, 1, 'dynamic', [2, 4, 1, 3, 0, 0, 2, 4], None, [0, 5]),
    ('rgb16_fixed', W, H, 16, 2, 3, 'fixed', [3, 4, 0, 2, 1], None, None),
    ('grey1_fixed', 13, 3, 1, 0, 1, 'fixed', [0, 2, 4], None, None),
    ('grey4_fixed', 40, 8, 4, 0, 1, 'fixed', [1, 1, 2, 4, 3, 0, 0, 2], None, None),
    ('pal2_fixed', W, H, 2, 3, 1, 'fixed', [4, 0, 1, 2, 3], [255, 0, 0, 0, 128, 255, 10, 20, 30, 200, 201, 202], [128]),
    ('pal8_dynamic', W, H, 8, 3, 1, 'dynamic', [0, 4, 3, 2, 1], [i % 256 for i in range(3 * 20)], None),
]
out = []
for (name, w, h, depth, ctype, spp, mode, ft, plte, trns) in specs:
    mod = (1 << depth) if ctype != 3 else (len(plte) // 3)
    s = pat(w * h * spp, mod, mul=(37 if depth <= 8 else 9973), add=(11 if depth <= 8 else 4099))
    if depth == 16: s = [(v * 7919) % 65536 for v in s]
    if mode == 'dynamic' and depth != 16 and ctype != 3:   # compressible: a skewed alphabet
        s = [(v % 5) * (mod // 8) + ((i // 9) % 3) for i, v in enumerate(s)]
    if name == 'grey16_dynamic':
        s = [(i // 3) * 256 + (i % 4) for i in range(len(s))]
    if name == 'greya8_multi':
        s = [((i // 80) * 3 + (i % 7)) % 256 for i in range(w * h * spp)]   # runs: long matches
    d, bt = png(w, h, depth, ctype, s, spp, mode, ft[:h], plte, trns)
    out.append((name, w, h, depth, ctype, spp, d, s, bt, mode, plte))
for (name, w, h, depth, ctype, spp, d, s, bt, mode, plte) in out:
    assert bt == {'dynamic': 2, 'fixed': 1, 'stored': 0, 'multi': bt}[mode], name
    sys.stderr.write('%s: %d bytes, first block type %d (%s)\n' % (name, len(d), bt, mode))
    if len(sys.argv) > 1: open('%s/%s.png' % (sys.argv[1], name), 'wb').write(d)
# C arrays
print('/* tests/png_fixtures.h - made by `python3 tests/png_fixtures.py > tests/png_fixtures.h`')
print('   (see that script: PNGs encoded by Python\'s zlib; do not edit by hand). */')
print('typedef struct { const char *name; int w, h, depth, ctype, spp; const unsigned char *png; size_t n; const unsigned short *want; const unsigned char *pal; } PngFixture;')
for (name, w, h, depth, ctype, spp, d, s, bt, mode, plte) in out:
    print('static const unsigned char png_%s[%d] = {' % (name, len(d)))
    for i in range(0, len(d), 16):
        print('    ' + ', '.join('0x%02x' % b for b in d[i:i + 16]) + ',')
    print('};')
    print('static const unsigned short want_%s[%d] = {' % (name, len(s)))
    for i in range(0, len(s), 16):
        print('    ' + ', '.join('%d' % v for v in s[i:i + 16]) + ',')
    print('};')
    if plte:
        print('static const unsigned char pal_%s[%d] = { %s };' % (name, len(plte), ', '.join(str(v) for v in plte)))
print('static const PngFixture png_fixtures[] = {')
for (name, w, h, depth, ctype, spp, d, s, bt, mode, plte) in out:
    print('    { "%s", %d, %d, %d, %d, %d, png_%s, sizeof png_%s, want_%s, %s },' % (name, w, h, depth, ctype, spp, name, name, name, ('pal_' + name) if plte else 'NULL'))
print('};')
