/* tests/test_sampler.c - the samplers (sampler.c) and the renderer's use of them.

   - Sobol: every power-of-two prefix of a pixel's 2-D group is a (0,m,2)-net (one
     point in every elementary box of area 2^-m), every 1-D projection stratified;
     zsobol the same over one pixel's 2^L samples; stratified one point per stratum.
   - Scrambles are decorrelated across pixels, seeds and dimension groups
     (Pearson correlation within 5 standard errors of 0).
   - An analytic integrand (irradiance from a triangle light, Lambert's polygon
     formula): unbiased for every sampler, and sobol's MSE falls faster with N
     than independent's (slopes measured by least squares and bounded).
   - The renderer: no dimension is asked for twice by one sample (the table's
     promise); furnace values and a dispersive scene agree with independent over
     seeds; merged seeds are unbiased; images do not depend on the thread count;
     progressive rungs equal separate renders (sobol), non-progressive samplers
     refuse a second pass; the independent sampler's images are pinned by two
     image checksums (see the test). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

#define K_SIGMA TEST_K_SIGMA

/* ---------------------------------------------------------- point-set properties */

/* 1 if the n = 2^m points (x[i], y[i]) have exactly one point in every elementary
   box [a 2^-p, (a+1) 2^-p) x [b 2^-q, (b+1) 2^-q), p + q = m; y == NULL: 1-D. */
static int is_net(const float *x, const float *y, int m, int *bad_p)
{
    int n = 1 << m, p, i;
    unsigned char *cnt = (unsigned char *)calloc((size_t)n, 1);
    if (!cnt) return 0;
    for (p = y ? 0 : m; p <= m; p++) {
        int q = m - p;
        memset(cnt, 0, (size_t)n);
        for (i = 0; i < n; i++) {
            int a = (int)(x[i] * (float)(1 << p)), b = y ? (int)(y[i] * (float)(1 << q)) : 0;
            int box = (a << q) | b;
            if (cnt[box]++) { *bad_p = p; free(cnt); return 0; }
        }
    }
    free(cnt);
    return 1;
}

/* sobol_u32 against the definition (1) of sampler.c: dimension 0 XORs the
   columns 2^(31-b), dimension 1 the columns v[0] = 2^31, v[b] = v[b-1] ^ (v[b-1] >> 1)
   (direction numbers of the polynomial x + 1), for the bits b set in i. */
static void test_sobol_definition(T *t)
{
    uint32_t i;
    int n;
    for (n = 0; n < 5000; n++) {
        uint32_t x0 = 0, x1 = 0, v = 0x80000000u;
        int b;
        i = n < 2048 ? (uint32_t)n : (uint32_t)hash_u64((uint64_t)n, 99);
        for (b = 0; b < 32; b++, v ^= v >> 1)
            if ((i >> b) & 1u) { x0 ^= 0x80000000u >> b; x1 ^= v; }
        CHECK(t, sobol_u32(i, 0) == x0 && sobol_u32(i, 1) == x1, "point %u: sobol_u32 gives %08x %08x, the "
              "generator matrices %08x %08x", i, sobol_u32(i, 0), sobol_u32(i, 1), x0, x1);
    }
}

static void test_sobol_nets(T *t)
{
    static float x[1024], y[1024], z[1024];
    Sampler s;
    int pix, m, k, bad = -1, g;
    sampler_init(&s, SAMPLER_SOBOL, 3, 1024, 0, 0, 1);
    for (pix = 0; pix < 6; pix++)
        for (g = 0; g < 3; g++) {
            int dim2 = g == 0 ? DIM_FILM : dim_bounce(g, BD_DIR), dim1 = g == 0 ? DIM_WAVELENGTH : dim_bounce(g, BD_LOBE);
            for (k = 0; k < 1024; k++) {
                PixelSample ps;
                sampler_start(&s, pix * 7, pix * 3 + 1, k, &ps);
                sampler_2d(&ps, dim2, &x[k], &y[k]);
                z[k] = sampler_1d(&ps, dim1);
                CHECK(t, x[k] >= 0.0f && x[k] < 1.0f && y[k] >= 0.0f && y[k] < 1.0f && z[k] >= 0.0f && z[k] < 1.0f,
                      "value outside [0,1)");
            }
            for (m = 0; m <= 10; m++) {
                CHECK(t, is_net(x, y, m, &bad), "pixel %d dim %d: the first 2^%d points are no (0,%d,2)-net "
                      "(boxes 2^-%d x 2^-%d)", pix, dim2, m, m, bad, m - bad);
                CHECK(t, is_net(x, NULL, m, &bad) && is_net(y, NULL, m, &bad),
                      "pixel %d dim %d: a 1-D projection of 2^%d points is not stratified", pix, dim2, m);
                CHECK(t, is_net(z, NULL, m, &bad), "pixel %d 1-D dim %d: 2^%d points not stratified", pix, dim1, m);
            }
        }
}

/* 1 if the n = 2^m points (x[i], y[i]) hold exactly 2^t points in every box
   [a 2^-p, (a+1) 2^-p) x [b 2^-q, (b+1) 2^-q), p + q = m - t: a (t,m,2)-net. */
static int is_tnet(const float *x, const float *y, int m, int tv)
{
    int n = 1 << m, k = m - tv, p, i;
    int *cnt = (int *)calloc((size_t)1 << (k > 0 ? k : 0), sizeof(int));
    if (!cnt) return 0;
    for (p = 0; p <= k; p++) {
        int q = k - p;
        memset(cnt, 0, sizeof(int) << k);
        for (i = 0; i < n; i++) {
            int box = ((int)(x[i] * (float)(1 << p)) << q) | (int)(y[i] * (float)(1 << q));
            if (++cnt[box] > (1 << tv)) { free(cnt); return 0; }
        }
    }
    free(cnt);
    return 1;
}

/* The smallest t for which the 2^m points are a (t,m,2)-net. */
static int net_t(const float *x, const float *y, int m)
{
    int tv = 0;
    while (tv < m && !is_tnet(x, y, m, tv)) tv++;
    return tv;
}

/* Sobol dimensions 2 and 3: their first generator columns (Joe and Kuo's
   direction numbers; sobol_u32 of 2^b is column b), and as pairs with every
   other of the first four dimensions (t,m,2)-nets with t <= 2 for m <= 10. */
static void test_sobol_dims23(T *t)
{
    static const uint32_t col2[8] = { 0x80000000u, 0xc0000000u, 0x60000000u, 0x90000000u,
                                       0xe8000000u, 0x5c000000u, 0x8e000000u, 0xc5000000u };
    static const uint32_t col3[8] = { 0x80000000u, 0xc0000000u, 0x20000000u, 0x50000000u,
                                       0xf8000000u, 0x74000000u, 0xa2000000u, 0x93000000u };
    static float v[4][1024];
    int b, d, e, m, i;
    for (b = 0; b < 8; b++)
        CHECK(t, sobol_u32(1u << b, 2) == col2[b] && sobol_u32(1u << b, 3) == col3[b],
              "column %d: %08x %08x, expected %08x %08x", b, sobol_u32(1u << b, 2), sobol_u32(1u << b, 3),
              col2[b], col3[b]);
    CHECK(t, sobol_u32(3u, 2) == (col2[0] ^ col2[1]) && sobol_u32(0xffu, 3) == (col3[0] ^ col3[1] ^ col3[2] ^ col3[3]
          ^ col3[4] ^ col3[5] ^ col3[6] ^ col3[7]), "a point is not the XOR of its columns");
    for (d = 0; d < 4; d++)
        for (i = 0; i < 1024; i++) v[d][i] = (float)(sobol_u32((uint32_t)i, d) >> 8) * (1.0f / 16777216.0f);
    for (d = 0; d < 4; d++)
        for (e = d + 1; e < 4; e++)
            for (m = 0; m <= 10; m++)
                CHECK(t, net_t(v[d], v[e], m) <= 2, "Sobol dimensions %d, %d: 2^%d points form a (%d,%d,2)-net",
                      d, e, m, net_t(v[d], v[e], m), m);
}

/* All 32 columns of Sobol dimensions 2 and 3 (sampler.c keeps them in tables):
   against the direction-number recurrences of Bratley and Fox (1988) worked out
   here, column b = m_(b+1) << (31 - b), and points with many bits set against the
   XOR of those columns.  The Owen-scrambled index a render uses has all 32 bits,
   so every column is used. */
static void test_sobol23_columns(T *t)
{
    uint32_t m[2][33], col[2][32];
    int d, b, bad = 0;
    uint64_t h = 12345u;
    for (d = 0; d < 2; d++) {
        int k;
        m[d][1] = 1u;
        m[d][2] = 3u;
        m[d][3] = 1u;                    /* x^3 + x + 1: given; x^2 + x + 1: the loop's */
        for (k = d == 0 ? 3 : 4; k <= 32; k++)
            m[d][k] = d == 0 ? (2u * m[d][k - 1]) ^ (4u * m[d][k - 2]) ^ m[d][k - 2]
                             : (4u * m[d][k - 2]) ^ (8u * m[d][k - 3]) ^ m[d][k - 3];
        for (b = 0; b < 32; b++) col[d][b] = m[d][b + 1] << (31 - b);
    }
    for (d = 0; d < 2; d++)
        for (b = 0; b < 32; b++)
            CHECK(t, sobol_u32(1u << b, d + 2) == col[d][b], "dimension %d, column %d: %08x, the recurrence "
                  "gives %08x", d + 2, b, sobol_u32(1u << b, d + 2), col[d][b]);
    for (b = 0; b < 20000 && !bad; b++) {
        uint32_t i, x[2] = { 0u, 0u };
        int c;
        h = hash_u64(h, (uint64_t)b);
        i = b == 0 ? 0xffffffffu : (uint32_t)h;
        for (c = 0; c < 32; c++)
            if ((i >> c) & 1u) { x[0] ^= col[0][c]; x[1] ^= col[1][c]; }
        if (sobol_u32(i, 2) != x[0] || sobol_u32(i, 3) != x[1]) {
            bad = 1;
            CHECK(t, 0, "point %08x: %08x %08x, the columns' XOR %08x %08x", i, sobol_u32(i, 2),
                  sobol_u32(i, 3), x[0], x[1]);
        }
    }
    CHECK(t, !bad, "20000 random points of dimensions 2 and 3 are the XOR of their columns");
}

/* Coordinate `slot` of halton's scrambled point k of pixel (x, y), straight from
   (2) of sampler.c: the digits of k and of the pixel's uniform Z (hashed from the
   pixel, the seed and the slot), each digit position through the film's tables
   pi_i((a + pi_i^-1(b)) mod p), Z's rest above k's digits; nothing kept between
   calls. */
static float halton_reference(const Sampler *s, int x, int y, uint32_t k, int slot)
{
    uint64_t key = hash_u64(hash_u64((uint64_t)x, (uint64_t)y), (uint64_t)s->seed);
    uint64_t h = hash_u64(key, (uint64_t)slot + 0x4a17u);
    double z = (double)(h >> 11) / 9007199254740992.0, v = 0.0, w = 1.0, t32;
    uint32_t p = 1, rest = k;
    int n = -1, i = 0, nd = s->halton_ndig[slot];
    const unsigned char *pi = s->halton_perm + s->halton_off[slot], *inv = s->halton_inv + s->halton_off[slot];
    while (n < slot) {                 /* p: the (slot + 1)-th prime */
        uint32_t q = 2;
        p++;
        while (q * q <= p && p % q) q++;
        if (q * q > p) n++;
    }
    while (rest > 0) {
        uint32_t a = rest % p, b, d;
        z *= (double)p;
        b = (uint32_t)z;
        z -= (double)b;
        rest /= p;
        w /= (double)p;
        d = i < nd ? pi[i * (int)p + (int)((a + inv[i * (int)p + (int)b]) % p)] : (a + b) % p;
        v += (double)d * w;
        i++;
    }
    v += w * z;
    t32 = v * 4294967296.0;
    return (float)((t32 < 4294967295.0 ? (uint32_t)t32 : 4294967295u) >> 8) * (1.0f / 16777216.0f);
}

/* sampler_restart (the render loop's next sample of the same pixel, keeping what
   depends on the pixel alone: halton's Z and its first digit per coordinate) hands
   out the very numbers sampler_start does, for every sampler, over 300 samples
   (indices of one to nine base-2 digits, two base-163 digits), the Halton point's
   slots and padded dimensions past them, in a camera medium and not; one
   PixelSample goes through three pixels, so a new pixel must forget the last.
   The Halton slots are also compared with (2) computed afresh (halton_reference),
   which neither path shares. */
static void test_restart_same_numbers(T *t)
{
    static const SamplerType types[SAMPLER_COUNT] = { SAMPLER_INDEPENDENT, SAMPLER_STRATIFIED, SAMPLER_SOBOL,
                                                      SAMPLER_ZSOBOL, SAMPLER_HALTON };
    int ty, fog, bad = 0;
    for (ty = 0; ty < SAMPLER_COUNT; ty++)
        for (fog = 0; fog < 2; fog++) {
            Sampler s;
            PixelSample kept;
            int pix, k, d;
            sampler_init(&s, types[ty], 5, 300, 0, 0, 1);
            s.camera_medium = fog;
            for (pix = 0; pix < 3 && !bad; pix++)
                for (k = 0; k < 300 && !bad; k++) {
                    PixelSample fresh;
                    if (k == 0) sampler_start(&s, 7 + pix, 3 * pix, k, &kept);
                    else sampler_restart(&kept, k);
                    sampler_start(&s, 7 + pix, 3 * pix, k, &fresh);
                    for (d = 0; d < HALTON_DIMS + 12 && !bad; d++) {   /* 1-D numbers, 2-D groups */
                        float a0 = sampler_1d(&kept, d), b0 = sampler_1d(&fresh, d), a1, b1, a2, b2;
                        sampler_2d(&kept, dim_bounce(d % 8, BD_DIR), &a1, &a2);
                        sampler_2d(&fresh, dim_bounce(d % 8, BD_DIR), &b1, &b2);
                        if (a0 != b0 || a1 != b1 || a2 != b2) {
                            bad = 1;
                            CHECK(t, 0, "%s%s, pixel %d, sample %d, dimension %d: restart gives %.9g %.9g %.9g, "
                                  "start %.9g %.9g %.9g", sampler_name(types[ty]), fog ? " (camera medium)" : "",
                                  pix, k, d, a0, a1, a2, b0, b1, b2);
                        }
                    }
                    if (!bad) {          /* the camera ray's first free flight: halton's last slot */
                        float a = sampler_1d(&kept, dim_medium(0, 0)), b = sampler_1d(&fresh, dim_medium(0, 0));
                        if (a != b) {
                            bad = 1;
                            CHECK(t, 0, "%s, pixel %d, sample %d: first free flight %.9g, start %.9g",
                                  sampler_name(types[ty]), pix, k, a, b);
                        }
                    }
                    if (!bad && types[ty] == SAMPLER_HALTON && !fog) {   /* the Halton slots, from (2) */
                        for (d = 0; d <= HALTON_DIMS && !bad; d++) {
                            int dim = d < HALTON_DIMS ? d : dim_medium(0, 0);
                            float a = sampler_1d(&kept, dim), r = halton_reference(&s, 7 + pix, 3 * pix, (uint32_t)k, d);
                            if (a != r) {
                                bad = 1;
                                CHECK(t, 0, "halton, pixel %d, sample %d, slot %d: %.9g, (2) gives %.9g", pix, k, d,
                                      a, r);
                            }
                        }
                    }
                }
        }
    CHECK(t, !bad, "sampler_restart and sampler_start give the same numbers");
}

/* Number `c` of a padded Sobol group of pixel (x, y), sample k, straight from
   sampler.c's definitions through the exported sobol_u32, owen_scramble and
   hash_u64 alone: the group g (the camera group's dimensions: g = DIM_FILM,
   coordinates 2 and 3) hashed with the pixel's key (sobol, halton) or with the
   seed alone (zsobol, whose index is the Morton code x 2^L + k, the high half
   scrambled first and its value hashed into the low half's seed); the index
   point i = owen_scramble(k, h); coordinate c of the Sobol point i scrambled with
   the seed h >> 32 (c = 0), that ^ 0x68bc21eb (c = 1), hash_u64(h, c) (2, 3). */
static float sobol_reference(const Sampler *s, int x, int y, uint32_t k, int dim, int c)
{
    uint64_t key = hash_u64(hash_u64((uint64_t)x, (uint64_t)y), (uint64_t)s->seed), h, morton = 0;
    uint32_t i, seed, v;
    int g = dim, b;
    if (s->camera_medium && dim == dim_medium(0, 0)) { g = DIM_FILM; c = 2; }
    if (s->camera_medium && dim == DIM_WAVELENGTH) { g = DIM_FILM; c = 3; }
    if (s->type == SAMPLER_ZSOBOL) {
        uint64_t index, hi;
        for (b = 0; b < 32; b++)
            morton |= ((uint64_t)((uint32_t)x >> b & 1u) << (2 * b)) | ((uint64_t)((uint32_t)y >> b & 1u) << (2 * b + 1));
        index = morton << s->log2_spp | k;
        hi = index >> 32;
        h = hash_u64((uint64_t)s->seed, (uint64_t)g);
        i = owen_scramble((uint32_t)index, (uint32_t)hash_u64(h, hi));
    } else {
        h = hash_u64(key, (uint64_t)g);
        i = owen_scramble(k, (uint32_t)h);
    }
    seed = c == 0 ? (uint32_t)(h >> 32) : c == 1 ? (uint32_t)(h >> 32) ^ 0x68bc21ebu : (uint32_t)hash_u64(h, (uint64_t)c);
    v = owen_scramble(sobol_u32(i, c), seed);
    return (float)(v >> 8) * (1.0f / 16777216.0f);
}

/* The padded Sobol groups' numbers (sampler_1d, sampler_2d) against their
   definition worked out afresh (sobol_reference), bit for bit: sobol, zsobol and
   halton's padded dimensions, with the camera in a medium (the camera group's
   Sobol coordinates 2 and 3) and not, four pixels (one far out, so that zsobol's
   index has high digits), 64 samples and a few larger indices, 1-D and 2-D
   requests early and late in the dimension table.  sampler.c works them out
   another way (each pixel's share of the group hash kept, the scrambles'
   reversals folded into byte tables, Sobol dimensions 2 and 3 by bytes of the
   index, zsobol's low half alone), which must not move any number. */
static void test_sobol_formula(T *t)
{
    static const SamplerType types[3] = { SAMPLER_SOBOL, SAMPLER_ZSOBOL, SAMPLER_HALTON };
    const int dims[8] = { DIM_FILM, DIM_WAVELENGTH, dim_medium(0, 0), dim_bounce(0, BD_DIR), dim_bounce(9, BD_DIR),
                          dim_bounce(12, BD_ROULETTE), dim_medium(5, 1), DIM_TIME };
    const int two[8] = { 1, 0, 0, 1, 1, 0, 0, 0 };
    int ty, fog, pix, kk, d, bad = 0, n = 0;
    for (ty = 0; ty < 3; ty++)
        for (fog = 0; fog < 2; fog++) {
            Sampler s;
            sampler_init(&s, types[ty], 11, 64, 0, 0, 1);
            s.camera_medium = fog;
            for (pix = 0; pix < 4; pix++)
                for (kk = 0; kk < 68 && !bad; kk++) {
                    uint32_t k = kk < 64 ? (uint32_t)kk : types[ty] == SAMPLER_ZSOBOL ? 63u - (uint32_t)kk % 4u
                                 : (uint32_t)(kk * 1000003);
                    int x = pix < 3 ? 5 + 37 * pix : 70001, y = pix < 3 ? 1000 * pix + 3 : 90003;
                    for (d = 0; d < 8 && !bad; d++) {
                        int dim = dims[d];
                        int camera = dim == DIM_FILM || dim == DIM_WAVELENGTH || dim == dim_medium(0, 0);
                        PixelSample ps;
                        float a0, a1 = 0.0f, r0, r1 = 0.0f;
                        if (types[ty] == SAMPLER_HALTON && !(fog && camera)
                            && (dim < HALTON_DIMS || dim == dim_medium(0, 0)))
                            continue;                       /* the Halton point's own slot */
                        sampler_start(&s, x, y, (int)k, &ps);
                        if (two[d]) sampler_2d(&ps, dim, &a0, &a1);
                        else a0 = sampler_1d(&ps, dim);
                        r0 = sobol_reference(&s, x, y, k, dim, 0);
                        if (two[d]) r1 = sobol_reference(&s, x, y, k, dim, 1);
                        n++;
                        if (a0 != r0 || a1 != r1) {
                            bad = 1;
                            CHECK(t, 0, "%s%s, pixel (%d, %d), sample %u, dimension %d: %.9g %.9g, the definition "
                                  "gives %.9g %.9g", sampler_name(types[ty]), fog ? " (camera medium)" : "", x, y,
                                  k, dim, a0, a1, r0, r1);
                        }
                    }
                }
        }
    CHECK(t, !bad && n > 2000, "%d padded Sobol requests equal their definition", n);
}

/* Decision numbers of one pixel's first 2^m samples: the position (x, y), the
   hero wavelength's u and the camera ray's first free flight, and a free flight
   of a later bounce.  fog: the camera sits in a medium (Sampler.camera_medium). */
static void camera_numbers(SamplerType type, int fog, int pix, int m, float *x, float *y, float *w, float *f,
                           float *late)
{
    Sampler s;
    int k;
    sampler_init(&s, type, 7, 1 << m, 0, 0, 1);
    s.camera_medium = fog;
    for (k = 0; k < (1 << m); k++) {
        PixelSample ps;
        sampler_start(&s, 3 * pix + 1, 5 * pix, k, &ps);
        sampler_2d(&ps, DIM_FILM, &x[k], &y[k]);
        w[k] = sampler_1d(&ps, DIM_WAVELENGTH);
        f[k] = sampler_1d(&ps, dim_medium(0, 0));
        late[k] = sampler_1d(&ps, dim_medium(1 + pix % 20, pix % 3));
    }
}

/* The camera in a medium (sampler.c, THE CAMERA GROUP).  Whether the camera ray
   reaches what it looks at depends on the wavelength, the free flight and the
   position in the pixel together.  With camera_medium, sobol and zsobol give a
   pixel's 2^m samples (m <= 8) a (wavelength, flight) square and (x, flight),
   (y, flight) squares that are (t,m,2)-nets, t <= 2, while the position stays a
   (0,m,2)-net and every 1-D projection, the later free flights (dimensions
   2^21 + 64 d + s) included, stays stratified.  Without it (padding) the
   (wavelength, flight) square is no such net.  The effect: a pass probability
   exp(-sigma(lambda) d) (sigma from 0.01 to 0.06, d = 15, as a coloured fog in
   front of a lamp) estimated per pixel from 64 samples has less than half the
   MSE (over 400 pixels) that padding leaves. */
static void test_camera_group(T *t)
{
    static float x[256], y[256], w[256], f[256], late[256];
    static const SamplerType types[2] = { SAMPLER_SOBOL, SAMPLER_ZSOBOL };
    int ti, pix, m, fog, bad = -1, worst = 0;
    double mse[2] = { 0.0, 0.0 };
    for (ti = 0; ti < 2; ti++)
        for (pix = 0; pix < 8; pix++)
            for (m = 0; m <= 8; m++) {
                camera_numbers(types[ti], 1, pix, m, x, y, w, f, late);
                CHECK(t, is_net(x, y, m, &bad), "%s pixel %d: the position of 2^%d samples is no (0,%d,2)-net",
                      sampler_name(types[ti]), pix, m, m);
                CHECK(t, is_net(w, NULL, m, &bad) && is_net(f, NULL, m, &bad) && is_net(late, NULL, m, &bad),
                      "%s pixel %d, 2^%d samples: the wavelength, the first or a later free flight not stratified",
                      sampler_name(types[ti]), pix, m);
                CHECK(t, net_t(w, f, m) <= 2 && net_t(x, f, m) <= 2 && net_t(y, f, m) <= 2,
                      "%s pixel %d, 2^%d samples: (wavelength, flight) a (%d,%d,2)-net, (x, flight) (%d,..), "
                      "(y, flight) (%d,..); expected t <= 2", sampler_name(types[ti]), pix, m, net_t(w, f, m), m,
                      net_t(x, f, m), net_t(y, f, m));
            }
    for (pix = 0; pix < 8; pix++) {
        camera_numbers(SAMPLER_SOBOL, 0, pix, 8, x, y, w, f, late);
        if (net_t(w, f, 8) > worst) worst = net_t(w, f, 8);
    }
    CHECK(t, worst > 2, "without a camera medium the (wavelength, flight) square is a (%d,8,2)-net: padded "
          "groups should be independent", worst);
    for (fog = 0; fog < 2; fog++)
        for (pix = 0; pix < 400; pix++) {
            double est = 0.0, exact = 0.0;
            int k, j;
            camera_numbers(SAMPLER_SOBOL, fog, pix, 6, x, y, w, f, late);
            for (k = 0; k < 64; k++) est += f[k] < exp(-15.0 * (0.01 + 0.05 * w[k])) ? 1.0 / 64.0 : 0.0;
            for (j = 0; j < 1000; j++) exact += exp(-15.0 * (0.01 + 0.05 * (j + 0.5) / 1000.0)) / 1000.0;
            mse[fog] += (est - exact) * (est - exact) / 400.0;
        }
    CHECK(t, mse[1] < 0.5 * mse[0], "pass probability from 64 samples: MSE %.3g with the camera group, %.3g "
          "padded; expected below half", mse[1], mse[0]);
}

/* The renderer gives the sampler its camera medium.  The camera sits in an
   absorbing fog (sigma_a from 0.02 at 400 nm to 0.12 at 700 nm, no scattering)
   at the centre of a sphere of radius 10 that emits L = 1: every pixel has the
   same value E[Tr(lambda)], estimated from whether the camera ray passes the
   fog, a joint function of the wavelength and the free flight.  Over the 256
   pixels of one render at 64 spp: sobol's spread of Y around the image mean is
   below 0.6 of stratified's (which pairs the two at random, as padding does;
   measured 0.3 with the camera group, 1.0 without), and the image means of
   sobol, stratified and independent agree over 4 seeds (5 standard errors). */
static void test_camera_medium_render(T *t)
{
    static const char *text =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"spectrum sigma_a\" [ 400 0.02 700 0.12 ]\n"
        "  \"spectrum sigma_s\" [ 400 0 700 0 ]\nMediumInterface \"\" \"fog\"\n"
        "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
        "Integrator \"volpath\" \"integer maxdepth\" [ 1 ]\nWorldBegin\nMediumInterface \"\" \"\"\n"
        "AttributeBegin\n ReverseOrientation\n AreaLightSource \"diffuse\" \"spectrum L\" [ 360 1 830 1 ]\n"
        " Material \"diffuse\" \"spectrum reflectance\" [ 360 0 830 0 ]\n"
        " Shape \"sphere\" \"float radius\" [ 10 ]\nAttributeEnd\n";
    static const SamplerType types[3] = { SAMPLER_SOBOL, SAMPLER_STRATIFIED, SAMPLER_INDEPENDENT };
    double spread[3] = { 0, 0, 0 }, mean[3] = { 0, 0, 0 }, m2[3] = { 0, 0, 0 };
    Scene s;
    int ti, k, i, a, b;
    if (!test_load_scene(t, &s, text)) return;
    for (ti = 0; ti < 3; ti++)
        for (k = 0; k < 4; k++) {
            RenderOptions o;
            Image img;
            RenderStats st;
            Error err;
            double sum = 0.0, sum2 = 0.0, m;
            render_options_default(&o);
            o.sampler = types[ti];
            o.spp = 64;
            o.seed = 11 + 1000 * k;
            if (!render(&s, &o, &img, &st, &err)) {
                scene_free(&s);
                CHECK(t, 0, "render failed: %s", err.msg);
            }
            for (i = 0; i < img.w * img.h; i++) {
                const float *p = img.rgb + 3 * i;
                double Y = 0.212671 * p[0] + 0.715160 * p[1] + 0.072169 * p[2];
                sum += Y;
                sum2 += Y * Y;
            }
            m = sum / (img.w * img.h);
            spread[ti] += (sum2 / (img.w * img.h) - m * m) / 4.0;
            mean[ti] += m / 4.0;
            m2[ti] += m * m / 4.0;
            img_free(&img);
        }
    scene_free(&s);
    CHECK(t, spread[0] < 0.6 * spread[1], "pixel variance of Y: sobol %.3g, stratified %.3g; the camera group "
          "should give sobol less than 0.6 of it", spread[0], spread[1]);
    for (a = 0; a < 3; a++)
        for (b = a + 1; b < 3; b++) {
            double se2 = (m2[a] - mean[a] * mean[a]) / 3.0 + (m2[b] - mean[b] * mean[b]) / 3.0;
            CHECK(t, fabs(mean[a] - mean[b]) < K_SIGMA * sqrt(se2) + 1e-4, "image mean Y: %s %.5f, %s %.5f "
                  "(standard error %.2g)", sampler_name(types[a]), mean[a], sampler_name(types[b]), mean[b], sqrt(se2));
        }
}

/* zsobol: one pixel's 2^L samples form a net; stratified: one point per stratum. */
static void test_zsobol_stratified_strata(T *t)
{
    static float x[256], y[256], z[256];
    Sampler s;
    int pix, k, bad = -1, L;
    for (L = 0; L <= 8; L += 2)
        for (pix = 0; pix < 5; pix++) {
            sampler_init(&s, SAMPLER_ZSOBOL, 9, 1 << L, 0, 0, 1);
            for (k = 0; k < (1 << L); k++) {
                PixelSample ps;
                sampler_start(&s, 13 * pix, 5 * pix + 2, k, &ps);
                sampler_2d(&ps, dim_bounce(1, BD_POINT), &x[k], &y[k]);
                z[k] = sampler_1d(&ps, dim_bounce(2, BD_ROULETTE));
            }
            CHECK(t, is_net(x, y, L, &bad), "zsobol pixel %d: %d samples are no (0,%d,2)-net", pix, 1 << L, L);
            CHECK(t, is_net(z, NULL, L, &bad), "zsobol pixel %d: %d 1-D samples not stratified", pix, 1 << L);
        }
    /* zsobol's point: the 4 pixels of an aligned 2 x 2 block (4 consecutive Morton
       codes) hold complementary parts of one net, 4 x 2^L points that form a
       (0, L+2, 2)-net together (Ahmed and Wonka 2020) */
    for (L = 0; L <= 6; L += 2)
        for (pix = 0; pix < 4; pix++) {
            static float qx[1024], qy[1024];
            int q, n = 0;
            sampler_init(&s, SAMPLER_ZSOBOL, 5, 1 << L, 0, 0, 1);
            for (q = 0; q < 4; q++)
                for (k = 0; k < (1 << L); k++, n++) {
                    PixelSample ps;
                    sampler_start(&s, 2 * (3 * pix + 1) + (q & 1), 2 * pix + (q >> 1), k, &ps);
                    sampler_2d(&ps, dim_bounce(0, BD_DIR), &qx[n], &qy[n]);
                }
            CHECK(t, is_net(qx, qy, L + 2, &bad), "zsobol, %d spp: the 2 x 2 pixel block %d is no (0,%d,2)-net",
                  1 << L, pix, L + 2);
        }
    {   /* stratified 4 x 3 (12 spp): one sample per 2-D cell and per 1-D twelfth */
        int cell[12], strat[12], j;
        sampler_init(&s, SAMPLER_STRATIFIED, 1, 12, 4, 3, 1);
        CHECK(t, s.xsamples == 4 && s.ysamples == 3, "strata %d x %d, expected 4 x 3", s.xsamples, s.ysamples);
        for (pix = 0; pix < 5; pix++) {
            memset(cell, 0, sizeof cell);
            memset(strat, 0, sizeof strat);
            for (k = 0; k < 12; k++) {
                PixelSample ps;
                float u0, u1, u;
                sampler_start(&s, pix, 2 * pix, k, &ps);
                sampler_2d(&ps, DIM_FILM, &u0, &u1);
                u = sampler_1d(&ps, DIM_WAVELENGTH);
                cell[(int)(u0 * 4) + 4 * (int)(u1 * 3)]++;
                strat[(int)(u * 12)]++;
            }
            for (j = 0; j < 12; j++)
                CHECK(t, cell[j] == 1 && strat[j] == 1, "stratified pixel %d: stratum %d holds %d (2-D) / %d (1-D)",
                      pix, j, cell[j], strat[j]);
        }
        sampler_init(&s, SAMPLER_STRATIFIED, 1, 12, 0, 0, 1);   /* from spp: 4 x 3 */
        CHECK(t, s.xsamples * s.ysamples == 12 && s.ysamples == 3, "12 spp factored as %d x %d", s.xsamples, s.ysamples);
    }
}

/* Pearson correlation of pairs; 1/sqrt(n) is its standard error near 0. */
static double correlation(const double *a, const double *b, int n)
{
    double ma = 0, mb = 0, sab = 0, saa = 0, sbb = 0;
    int i;
    for (i = 0; i < n; i++) { ma += a[i]; mb += b[i]; }
    ma /= n; mb /= n;
    for (i = 0; i < n; i++) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / sqrt(saa * sbb);
}

/* The same (sample, dimension) in neighbouring pixels, in two seeds, and two
   groups of one sample must be decorrelated.  Per pixel and group, the Pearson
   correlation r over the NK samples: for independently ordered point sets its
   permutation distribution has E[r^2] = 1/(NK - 1), so the mean of r^2 over the
   240 (pixel, group) pairs must stay below 2/(NK - 1); shared scrambles or a
   shared order give r^2 near 1 (a pooled correlation would let r = +1 and r = -1
   pixels cancel).  zsobol's pixels share one sequence on purpose, so only its
   seeds and groups are checked. */
static void test_scrambles_decorrelated(T *t)
{
    enum { NPIX = 40, NK = 32, NDIM = 6 };
    static const SamplerType types[4] = { SAMPLER_SOBOL, SAMPLER_ZSOBOL, SAMPLER_STRATIFIED, SAMPLER_HALTON };
    static const char *what[3] = { "neighbouring pixels", "seeds 1 and 2", "two groups of a sample" };
    int ti, rel;
    for (ti = 0; ti < 4; ti++) {
        Sampler s1, s2;
        sampler_init(&s1, types[ti], 1, NK, 0, 0, 1);
        sampler_init(&s2, types[ti], 2, NK, 0, 0, 1);
        for (rel = 0; rel < 3; rel++) {
            double r2 = 0.0;
            int pix, k, di;
            if (rel == 0 && types[ti] == SAMPLER_ZSOBOL) continue;
            for (pix = 0; pix < NPIX; pix++)
                for (di = 0; di < NDIM; di++) {
                    double a[NK], b[NK], r;
                    for (k = 0; k < NK; k++) {
                        PixelSample p, q;
                        int dim = dim_bounce(di, BD_LOBE);
                        sampler_start(&s1, pix, 3, k, &p);
                        a[k] = sampler_1d(&p, dim);
                        if (rel == 0) { sampler_start(&s1, pix + 1, 3, k, &q); b[k] = sampler_1d(&q, dim); }
                        if (rel == 1) { sampler_start(&s2, pix, 3, k, &q); b[k] = sampler_1d(&q, dim); }
                        if (rel == 2) b[k] = sampler_1d(&p, dim_bounce(di, BD_ROULETTE));
                    }
                    r = correlation(a, b, NK);
                    r2 += r * r / (NPIX * NDIM);
                }
            CHECK(t, r2 < 2.0 / (NK - 1), "%s: %s correlate: mean r^2 = %.3f, independent orders give %.3f",
                  sampler_name(types[ti]), what[rel], r2, 1.0 / (NK - 1));
        }
    }
}

/* --------------------------------------------------------------- an analytic integrand */

/* Irradiance / L at p (normal n) from a uniform Lambertian polygon (Lambert 1760):
   E / L = 1/2 |sum_i acos(v_i . v_i+1) n . normalize(v_i x v_i+1)|, v_i the unit
   vectors from p to the vertices. */
static double polygon_irradiance(Vec3 p, Vec3 n, const Vec3 *v, int nv)
{
    double sum = 0.0;
    int i;
    for (i = 0; i < nv; i++) {
        Vec3 a = v3_norm(v3_sub(v[i], p)), b = v3_norm(v3_sub(v[(i + 1) % nv], p));
        double ab = v3_dot(a, b);
        Vec3 cr = v3_norm(v3_cross(a, b));
        if (ab > 1.0) ab = 1.0;
        sum += acos(ab) * v3_dot(n, cr);
    }
    return 0.5 * fabs(sum);
}

/* Direct light from a triangle emitter onto a point of a diffuse plane, estimated
   as (1/N) sum cos_p / pdf_sa with emitter_sample's point from the sampler (NEE's
   dimensions at bounce 0).  Over 256 pixels (independent scrambles) the MSE
   against Lambert's formula at N = 4 .. 256 gives a log-log slope: about -1 for
   independent (Monte Carlo), about -3 for Owen-scrambled Sobol on a smooth 2-D
   integrand (Owen 1997); measured -1.05, -2.6 (sobol and zsobol), -1.95
   (stratified).  Bounds: independent -1 +- 0.3, sobol and zsobol below -2.2 and 10x
   less error at 256; every sampler's mean within K_SIGMA standard errors. */
static void test_analytic_slope(T *t)
{
    static const SamplerType types[4] = { SAMPLER_INDEPENDENT, SAMPLER_SOBOL, SAMPLER_ZSOBOL, SAMPLER_STRATIFIED };
    static const int Ns[5] = { 4, 16, 64, 256, 1024 };
    const Vec3 tri[3] = { { -0.3f, 1.0f, -0.2f }, { 0.4f, 1.0f, -0.3f }, { 0.1f, 1.0f, 0.4f } };
    const Vec3 p = v3(0.5f, 0.0f, 0.2f), n = v3(0.0f, 1.0f, 0.0f);
    const int NPIX = test_scaled(256, 64);
    double exact = polygon_irradiance(p, n, tri, 3), slope[4], mse_last[4];
    Scene s;
    int ti;
    if (!test_load_scene(t, &s,
        "WorldBegin\nAreaLightSource \"diffuse\" \"spectrum L\" [ 360 1 830 1 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ]\n"
        "  \"point3 P\" [ -0.3 1 -0.2  0.4 1 -0.3  0.1 1 0.4 ]\n")) return;
    for (ti = 0; ti < 4; ti++) {
        double lx[5], ly[5], sx = 0, sy = 0, sxx = 0, sxy = 0;
        int ni;
        for (ni = 0; ni < 5; ni++) {
            Sampler smp;
            double se2 = 0.0, sum_err = 0.0, sum_err2 = 0.0;
            int pix, k;
            sampler_init(&smp, types[ti], 17, Ns[ni], 0, 0, 1);
            for (pix = 0; pix < NPIX; pix++) {
                double est = 0.0, err;
                for (k = 0; k < Ns[ni]; k++) {
                    PixelSample ps;
                    EmitterSample es;
                    float u0, u1, u2;
                    sampler_start(&smp, pix % 16, pix / 16, k, &ps);
                    u0 = sampler_1d(&ps, dim_bounce(0, BD_TRIANGLE));
                    sampler_2d(&ps, dim_bounce(0, BD_POINT), &u1, &u2);
                    if (emitter_sample(&s, 0, p, v3(0.0f, 0.0f, 0.0f), (const float[3]){ u0, u1, u2 }, &es) && es.pdf_sa > 0.0f)
                        est += v3_dot(es.wi, n) / es.pdf_sa;
                }
                err = est / Ns[ni] - exact;
                sum_err += err;
                sum_err2 += err * err;
            }
            se2 = sum_err2 / NPIX;                      /* the MSE */
            {   /* unbiased: mean error within K_SIGMA standard errors */
                double mean = sum_err / NPIX, sd = sqrt((sum_err2 / NPIX - mean * mean) / (NPIX - 1));
                CHECK(t, fabs(mean) < K_SIGMA * sd + 1e-6 * exact, "%s N=%d: mean %.6g, exact %.6g (se %.2g)",
                      sampler_name(types[ti]), Ns[ni], mean + exact, exact, sd);
            }
            lx[ni] = log((double)Ns[ni]);
            ly[ni] = log(se2);
            if (ni == 3) mse_last[ti] = se2;
        }
        for (ni = 0; ni < 5; ni++) { sx += lx[ni]; sy += ly[ni]; sxx += lx[ni] * lx[ni]; sxy += lx[ni] * ly[ni]; }
        slope[ti] = (5 * sxy - sx * sy) / (5 * sxx - sx * sx);
    }
    CHECK(t, slope[0] > -1.3 && slope[0] < -0.7, "independent: MSE slope %.2f, expected -1 +- 0.3", slope[0]);
    CHECK(t, slope[1] < -2.2, "sobol: MSE slope %.2f, expected below -2.2 (independent %.2f)", slope[1], slope[0]);
    CHECK(t, slope[2] < -2.2, "zsobol: MSE slope %.2f, expected below -2.2", slope[2]);
    CHECK(t, mse_last[1] < 0.1 * mse_last[0], "sobol at 256: MSE %.3g, independent %.3g: not 10x less",
          mse_last[1], mse_last[0]);
    CHECK(t, mse_last[3] < mse_last[0], "stratified at 256: MSE %.3g above independent's %.3g",
          mse_last[3], mse_last[0]);
    scene_free(&s);
}

/* --------------------------------------------------------------- the renderer */

static const char *box_scene =
    "LookAt 0 0 -3.2  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
    "Integrator \"path\" \"integer maxdepth\" [ 6 ]\n"
    "WorldBegin\n"
    "%s"
    "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" \"stdillum-F11\" \"float scale\" [ 6 ]\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -0.4 0.99 -0.4  0.4 0.99 -0.4  0.4 0.99 0.4  -0.4 0.99 0.4 ]\nAttributeEnd\n"
    "AttributeBegin\n Translate 0 -0.55 0\n"
    " Material \"dielectric\" \"float cauchyA\" [ 1.5 ] \"float cauchyB\" [ 0.04 ] \"float roughness\" [ 0.09 ]\n"
    " Shape \"sphere\" \"float radius\" [ 0.42 ]\nAttributeEnd\n";

static int load_box(T *t, Scene *s, int box_filter)
{
    char text[8192];
    snprintf(text, sizeof text, box_scene, test_box_walls);
    if (!test_load_scene(t, s, text)) return 0;
    if (box_filter) { s->settings.filter = FILTER_BOX; s->settings.filter_radius = 0.5f; }
    return 1;
}

/* FNV-1a over the image's float bytes. */
static uint64_t image_hash(const Image *im)
{
    const unsigned char *b = (const unsigned char *)im->rgb;
    size_t i, n = sizeof(float) * 3 * (size_t)im->w * (size_t)im->h;
    uint64_t h = 1469598103934665603ull;
    for (i = 0; i < n; i++) { h ^= b[i]; h *= 1099511628211ull; }
    return h;
}

/* The independent sampler's images, pinned: two small renders (a box with a rough
   dispersive glass sphere, the gaussian and the box filter) under the thesis'
   settings must give these image checksums bit for bit (gcc, clang and tcc agree
   under -ffp-contract=off, tests/golden/README.md).  Any change of the numbers the
   independent sampler hands out, of their order, or of the rounding of anything
   these renders go through (the rough glass's GGX in microfacet.c, say) changes
   them: then re-take them and say why in the commit. */
static void test_independent_unchanged(T *t)
{
    static const uint64_t expected[2] = { 0xb4ab0789a5b7f1cbull, 0xdac29ae3cf7ed1e0ull };  /* gaussian, box */
    int f;
    for (f = 0; f < 2; f++) {
        Scene s;
        RenderOptions o;
        Image img;
        RenderStats st;
        Error err;
        uint64_t h;
        if (!load_box(t, &s, f)) return;
        render_options_thesis(&o);        /* the settings of that commit's defaults */
        o.sel.grid_res = 8;
        o.sampler = SAMPLER_INDEPENDENT;
        o.spp = 4;
        o.seed = 7;
        o.threads = 2;
        CHECK(t, render(&s, &o, &img, &st, &err), "render: %s", err.msg);
        h = image_hash(&img);
        img_free(&img);
        scene_free(&s);
        CHECK(t, h == expected[f], "%s filter: image checksum %016llx, pinned %016llx",
              f ? "box" : "gaussian", (unsigned long long)h, (unsigned long long)expected[f]);
    }
}

/* No sample asks for a dimension twice (the table's promise, counted by the
   sampler in RenderStats.dims_reused), with NEE on and off and every strategy
   family, for every sampler; the table itself is injective over 31 bounces. */
static void test_dimensions_not_shared(T *t)
{
    Scene s;
    int ti, d, slot, variant;
    static const int slots[6] = { BD_LIGHT, BD_TRIANGLE, BD_POINT, BD_LOBE, BD_DIR, BD_ROULETTE };
    static const int width[6] = { 1, 1, 2, 1, 2, 1 };
    unsigned char seen[SAMPLER_CHECKED_DIMS];
    memset(seen, 0, sizeof seen);
    seen[DIM_FILM] = seen[DIM_FILM + 1] = seen[DIM_LENS] = seen[DIM_LENS + 1] = seen[DIM_WAVELENGTH] = 1;
    CHECK(t, DIM_BOUNCE0 == DIM_WAVELENGTH + 1, "camera dimensions and bounce 0 overlap or leave a gap");
    for (d = 0; d < 31; d++)
        for (slot = 0; slot < 6; slot++) {
            int w;
            for (w = 0; w < width[slot]; w++) {
                int dim = dim_bounce(d, slots[slot]) + w;
                CHECK(t, dim < SAMPLER_CHECKED_DIMS && !seen[dim], "bounce %d slot %d: dimension %d used twice",
                      d, slots[slot], dim);
                seen[dim] = 1;
            }
        }
    if (!load_box(t, &s, 0)) return;
    for (ti = 0; ti < SAMPLER_COUNT; ti++)
        for (variant = 0; variant < 3; variant++) {
            RenderOptions o;
            Image img;
            RenderStats st;
            Error err;
            render_options_default(&o);
            o.sel.grid_res = 8;
            o.sampler = (SamplerType)ti;
            o.spp = 4;
            o.threads = 2;
            o.maxdepth = 12;
            if (variant == 1) o.nee = 0;
            if (variant == 2) o.sel.strategy = SEL_ALL;
            CHECK(t, render(&s, &o, &img, &st, &err), "render: %s", err.msg);
            img_free(&img);
            CHECK(t, st.dims_reused == 0, "%s (variant %d): %ld dimensions asked for twice in one sample",
                  sampler_name(o.sampler), variant, st.dims_reused);
        }
    scene_free(&s);
}

/* Unbiased over seeds: the furnace (Y = 0.5 on a diffuse sphere, Y = 1 through
   dispersive glass) and the dispersive box against independent, tile by tile. */
static void test_unbiased_over_seeds(T *t)
{
    static const char *furnace =
        "LookAt 0 0 -3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 10 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ] \"string filename\" \"t.pfm\"\n"
        "WorldBegin\n"
        "AttributeBegin\n ReverseOrientation\n AreaLightSource \"diffuse\" \"spectrum L\" [ 360 1 830 1 ]\n"
        " Material \"diffuse\" \"spectrum reflectance\" [ 360 0 830 0 ]\n"
        " Shape \"sphere\" \"float radius\" [ 20 ]\nAttributeEnd\n"
        "AttributeBegin\n %s\n Shape \"sphere\" \"float radius\" [ 1 ]\nAttributeEnd\n";
    static const char *mats[2] = {
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 0.5 830 0.5 ]",
        "Material \"dielectric\" \"spectrum eta\" [ 400 1.625 450 1.599 500 1.58 550 1.566 600 1.556 650 1.547 700 1.541 ]" };
    static const double expect[2] = { 0.5, 1.0 };
    static const SamplerType types[4] = { SAMPLER_SOBOL, SAMPLER_ZSOBOL, SAMPLER_STRATIFIED, SAMPLER_HALTON };
    int ti, m, i;
    for (m = 0; m < 2; m++) {
        char text[2048];
        Scene s;
        snprintf(text, sizeof text, furnace, mats[m]);
        if (!test_load_scene(t, &s, text)) return;
        for (ti = 0; ti < 4; ti++) {
            RenderOptions o;
            Tiles tl;
            render_options_default(&o);
            o.sel.grid_res = 8;
            o.sampler = types[ti];
            o.spp = test_scaled(16, 4);
            o.maxdepth = 24;
            if (!test_render_tiles(t, &s, &o, 8, 2, &tl)) { scene_free(&s); return; }
            for (i = 0; i < 4; i++) {
                double Y = test_luminance(tl.mean[i]);
                CHECK(t, fabs(Y - expect[m]) < K_SIGMA * tl.se[i][1] + 3e-3,
                      "%s, furnace %d, tile %d: Y = %.5f +- %.2g, expected %g", sampler_name(types[ti]), m, i, Y,
                      tl.se[i][1], expect[m]);
            }
        }
        scene_free(&s);
    }
    {
        Scene s;
        RenderOptions o;
        Tiles ref, other;
        if (!load_box(t, &s, 0)) return;
        render_options_default(&o);
        o.sel.grid_res = 8;
        o.spp = test_scaled(32, 4);
        o.sampler = SAMPLER_INDEPENDENT;
        if (!test_render_tiles(t, &s, &o, 12, 4, &ref)) { scene_free(&s); return; }
        for (ti = 0; ti < 4; ti++) {
            o.sampler = types[ti];
            if (!test_render_tiles(t, &s, &o, 12, 4, &other)) break;
            if (!test_tiles_agree(t, &ref, &other, 1e-4, sampler_name(types[ti]))) break;
        }
        scene_free(&s);
    }
}

/* specnee merge of differently seeded sobol renders: two halves (seeds a, b)
   merged by sample count agree over seeds with full renders (seed c). */
static void test_merge_seeds_unbiased(T *t)
{
    Scene s;
    RenderOptions o;
    if (!load_box(t, &s, 0)) return;
    render_options_default(&o);
    o.sel.grid_res = 8;
    o.sampler = SAMPLER_SOBOL;
    o.spp = test_scaled(16, 4);
    test_merge_agrees(t, &s, &o, "sobol box");
    scene_free(&s);
}

/* Bit-identical for 1 and 2 threads, for every sampler; seeds differ. */
static void test_sampler_threads(T *t)
{
    Scene s;
    int ti;
    if (!load_box(t, &s, 0)) return;
    for (ti = 0; ti < SAMPLER_COUNT; ti++) {
        RenderOptions o;
        Image a, b, c;
        RenderStats st;
        Error err;
        size_t bytes;
        render_options_default(&o);
        o.sel.grid_res = 8;
        o.sampler = (SamplerType)ti;
        o.spp = 4;
        o.threads = 1;
        CHECK(t, render(&s, &o, &a, &st, &err), "render: %s", err.msg);
        o.threads = 2;
        CHECK(t, render(&s, &o, &b, &st, &err), "render: %s", err.msg);
        o.seed = 1;
        CHECK(t, render(&s, &o, &c, &st, &err), "render: %s", err.msg);
        bytes = sizeof(float) * 3 * (size_t)a.w * (size_t)a.h;
        CHECK(t, memcmp(a.rgb, b.rgb, bytes) == 0, "%s: 1 and 2 threads differ", sampler_name(o.sampler));
        CHECK(t, memcmp(a.rgb, c.rgb, bytes) != 0, "%s: seeds 0 and 1 give the same image", sampler_name(o.sampler));
        img_free(&a); img_free(&b); img_free(&c);
    }
    scene_free(&s);
}

/* Ladders: sobol's rungs of one progressive render equal separate renders; a
   non-progressive sampler (stratified, zsobol) refuses a second pass of a job
   and render_ladder renders its rungs separately (again equal to separate
   renders); a 2^k-spp sobol render is the prefix of a larger one (its merge with
   the rest is the larger render: checked through the ladder's equality). */
typedef struct { Image rung[3]; int calls; } Keep;
static int keep_rung(void *user, int rung, const Image *img, const RenderStats *st)
{
    Keep *K = (Keep *)user;
    (void)st;
    if (img_alloc(&K->rung[rung], img->w, img->h))
        memcpy(K->rung[rung].rgb, img->rgb, sizeof(float) * 3 * (size_t)img->w * (size_t)img->h);
    K->calls++;
    return 1;
}

static void test_sampler_ladders(T *t)
{
    static const int ladder[3] = { 4, 8, 16 };
    static const SamplerType types[4] = { SAMPLER_SOBOL, SAMPLER_ZSOBOL, SAMPLER_STRATIFIED, SAMPLER_HALTON };
    Scene s;
    int ti, i;
    if (!load_box(t, &s, 0)) return;
    for (ti = 0; ti < 4; ti++) {
        RenderOptions o;
        RenderStats st;
        Error err;
        Image last;
        Keep K;
        RenderJob *j;
        render_options_default(&o);
        o.sel.grid_res = 8;
        o.sampler = types[ti];
        o.seed = 4;
        o.threads = 2;
        memset(&K, 0, sizeof K);
        CHECK(t, render_ladder(&s, &o, ladder, 3, keep_rung, &K, &last, &st, &err), "ladder: %s", err.msg);
        CHECK(t, K.calls == 3, "%d rungs", K.calls);
        for (i = 0; i < 3; i++) {
            Image one;
            RenderStats st1;
            o.spp = ladder[i];
            CHECK(t, render(&s, &o, &one, &st1, &err), "render: %s", err.msg);
            CHECK(t, memcmp(K.rung[i].rgb, one.rgb, sizeof(float) * 3 * (size_t)one.w * (size_t)one.h) == 0,
                  "%s: rung %d (%d spp) differs from a separate render", sampler_name(o.sampler), i, ladder[i]);
            if (i == 2) CHECK(t, memcmp(last.rgb, one.rgb, sizeof(float) * 3 * (size_t)one.w * (size_t)one.h) == 0,
                              "%s: the ladder's last image is not its last rung", sampler_name(o.sampler));
            img_free(&one);
            img_free(&K.rung[i]);
        }
        img_free(&last);
        j = render_begin(&s, &o, &err);
        CHECK(t, j != NULL, "render_begin: %s", err.msg);
        CHECK(t, render_advance(j, 4, 8, &err), "advance: %s", err.msg);
        i = render_advance(j, 8, 8, &err);
        render_end(j);
        if (sampler_progressive(o.sampler))
            CHECK(t, i, "%s: a second pass was refused: %s", sampler_name(o.sampler), err.msg);
        else
            CHECK(t, !i && strstr(err.msg, "not progressive"), "%s: a second pass was accepted or gave '%s'",
                  sampler_name(o.sampler), i ? "" : err.msg);
    }
    scene_free(&s);
}

/* --------------------------------------------------------------- halton */

/* The dimensions the Halton point serves (sampler.c, THE HALTON POINT), then two
   it leaves to padded groups (a later bounce's lamp point, the motion time). */
static int halton_dim(int j)
{
    if (j < HALTON_DIMS) return j;
    return j == HALTON_DIMS ? dim_medium(0, 0) : j == HALTON_DIMS + 1 ? dim_bounce(6, BD_POINT) : DIM_TIME;
}

/* Pearson's chi-square of counts in nb equal bins, expected e each. */
static double chi_square(const int *cnt, int nb, double e)
{
    double x2 = 0.0;
    int b;
    for (b = 0; b < nb; b++) x2 += (cnt[b] - e) * (cnt[b] - e) / e;
    return x2;
}

/* Every number halton serves is uniform on [0, 1): sample k of 4096 pixels
   (independent scrambles) for k = 0, 7 and 300, in 16 bins, and the same for the
   position within the finest digit box, frac(u 2^16) (the jitter below the last
   digit), and for two dimensions served by padded groups.  Chi-square, 15 degrees
   of freedom: mean 15, the bound 60 is passed by uniform numbers with probability
   1 - 1e-7 (120 checks).  Sample k does not depend on spp (progressive). */
static void test_halton_uniform(T *t)
{
    static const int ks[3] = { 0, 7, 300 };
    Sampler s;
    int j, ki;
    double worst = 0.0, worst_fine = 0.0;
    Sampler big;
    sampler_init(&s, SAMPLER_HALTON, 3, 64, 0, 0, 1);
    sampler_init(&big, SAMPLER_HALTON, 3, 4096, 0, 0, 1);
    CHECK(t, sampler_progressive(SAMPLER_HALTON), "halton is not progressive");
    for (j = 0; j <= HALTON_DIMS + 2; j++) {
        PixelSample a, b;
        sampler_start(&s, 3, 4, 37, &a);
        sampler_start(&big, 3, 4, 37, &b);
        CHECK(t, sampler_1d(&a, halton_dim(j)) == sampler_1d(&b, halton_dim(j)), "dimension %d: sample 37 "
              "depends on spp", halton_dim(j));
    }
    for (j = 0; j <= HALTON_DIMS + 2; j++)
        for (ki = 0; ki < 3; ki++) {
            int cnt[16] = { 0 }, fine[16] = { 0 }, pix;
            double x2, x2f;
            for (pix = 0; pix < 4096; pix++) {
                PixelSample ps;
                float u;
                double f;
                sampler_start(&s, pix & 63, pix >> 6, ks[ki], &ps);
                u = sampler_1d(&ps, halton_dim(j));
                CHECK(t, u >= 0.0f && u < 1.0f, "slot %d: u = %g outside [0, 1)", j, u);
                f = (double)u * 65536.0;
                cnt[(int)(u * 16.0f) & 15]++;
                fine[(int)((f - floor(f)) * 16.0) & 15]++;
            }
            x2 = chi_square(cnt, 16, 256.0);
            x2f = chi_square(fine, 16, 256.0);
            if (x2 > worst) worst = x2;
            if (x2f > worst_fine) worst_fine = x2f;
            CHECK(t, x2 < 60.0 && x2f < 60.0, "slot %d, sample %d: chi-square %.1f, in the finest box %.1f (15 dof)",
                  j, ks[ki], x2, x2f);
        }
    printf("    halton uniform: worst chi-square %.1f, in the finest box %.1f (15 dof)\n", worst, worst_fine);
}

/* The joint strata padding lacks.  N = prod_j b_j^e_j consecutive Halton points
   hold one point in each cell of the grid of prod_j b_j^e_j boxes (bases b_j:
   sampler.c, (2)), and a digit scramble keeps it.  Three grids of a pixel's first N
   samples: (position x, point on the lamp u): 16 x 19 = 304 cells; (lens u, lamp
   u): 25 x 19; (position y, lens u, lamp u): 9 x 5 x 19 = 855 cells in 3-D;
   (hero wavelength, the camera ray's first free flight): 11 x 163.
   Halton leaves no cell empty, in 8 pixels; padded points pair at random and
   leave about N/e empty (measured in the test's output). */
static int empty_cells(SamplerType type, const int *dims, const int *cells, int nd)
{
    Sampler s;
    int pix, k, c, n = 1, empty = 0;
    unsigned char *cnt;
    for (c = 0; c < nd; c++) n *= cells[c];
    cnt = (unsigned char *)malloc((size_t)n);
    if (!cnt) return -1;
    sampler_init(&s, type, 4, n, 0, 0, 1);
    for (pix = 0; pix < 8; pix++) {
        memset(cnt, 0, (size_t)n);
        for (k = 0; k < n; k++) {
            PixelSample ps;
            int cell = 0;
            sampler_start(&s, pix, 2, k, &ps);
            for (c = 0; c < nd; c++) cell = cell * cells[c] + (int)(sampler_1d(&ps, dims[c]) * (float)cells[c]);
            cnt[cell] = 1;
        }
        for (c = 0; c < n; c++) empty += !cnt[c];
    }
    free(cnt);
    return empty;
}

static void test_halton_joint_strata(T *t)
{
    static const int dims[4][3] = { { DIM_FILM, DIM_BOUNCE0 + BD_POINT, 0 },
                                    { DIM_LENS, DIM_BOUNCE0 + BD_POINT, 0 },
                                    { DIM_FILM + 1, DIM_LENS, DIM_BOUNCE0 + BD_POINT },
                                    { DIM_WAVELENGTH, DIM_MEDIUM0, 0 } };
    static const int cells[4][3] = { { 16, 19, 1 }, { 25, 19, 1 }, { 9, 5, 19 }, { 11, 163, 1 } };
    int g;
    CHECK(t, DIM_MEDIUM0 == dim_medium(0, 0), "the camera ray's first free flight moved");
    for (g = 0; g < 4; g++) {
        int nd = cells[g][2] > 1 ? 3 : 2;
        int n = cells[g][0] * cells[g][1] * cells[g][2];
        int h = empty_cells(SAMPLER_HALTON, dims[g], cells[g], nd);
        int p = empty_cells(SAMPLER_SOBOL, dims[g], cells[g], nd);
        printf("    grid %d (%d cells, 8 pixels): %d empty (halton), %d (padded sobol)\n", g, n, h, p);
        CHECK(t, h == 0, "halton: grid %d: %d of %d cells empty over 8 pixels", g, h, 8 * n);
        CHECK(t, p > 8 * n / 5, "padded sobol: grid %d: only %d of %d cells empty", g, p, 8 * n);
    }
}

/* A smooth 4-D integrand over (position in the pixel, point on the lamp):
   f = exp(x + y + u + v), integral (e - 1)^4.  Over 256 pixels the RMS error at 16
   and 256 samples: Monte Carlo (and padding, in the interactions) falls 4x
   (sqrt 16); the Halton point faster, nearly as 1/N (16x).  Measured ratios:
   halton 10.2, sobol 4.0; bounds: halton > 7, sobol < 6; halton's mean over the 256 pixels at 16 samples
   within K_SIGMA standard errors of the integral. */
static void halton_rms(SamplerType type, int n, double *rms, double *mean, double *se)
{
    const double exact = pow(exp(1.0) - 1.0, 4.0);
    Sampler s;
    int pix, k;
    double s1 = 0.0, s2 = 0.0;
    sampler_init(&s, type, 2, n, 0, 0, 1);
    for (pix = 0; pix < 256; pix++) {
        double est = 0.0;
        for (k = 0; k < n; k++) {
            PixelSample ps;
            float x, y, u, v;
            sampler_start(&s, pix & 15, pix >> 4, k, &ps);
            sampler_2d(&ps, DIM_FILM, &x, &y);
            sampler_2d(&ps, dim_bounce(0, BD_POINT), &u, &v);
            est += exp((double)x + y + u + v) / n;
        }
        s1 += (est - exact) / 256.0;
        s2 += (est - exact) * (est - exact) / 256.0;
    }
    *rms = sqrt(s2);
    *mean = exact + s1;
    *se = sqrt((s2 - s1 * s1) / 255.0);
}

static void test_halton_integral(T *t)
{
    const double exact = pow(exp(1.0) - 1.0, 4.0);
    double h16, h256, p16, p256, m, se, dummy;
    halton_rms(SAMPLER_HALTON, 16, &h16, &m, &se);
    halton_rms(SAMPLER_HALTON, 256, &h256, &dummy, &dummy);
    halton_rms(SAMPLER_SOBOL, 16, &p16, &dummy, &dummy);
    halton_rms(SAMPLER_SOBOL, 256, &p256, &dummy, &dummy);
    printf("    exp(x+y+u+v): RMS error 16 -> 256 samples falls %.1fx (halton), %.1fx (padded sobol)\n",
           h16 / h256, p16 / p256);
    CHECK(t, h16 / h256 > 7.0, "halton: error falls only %.1fx from 16 to 256 samples", h16 / h256);
    CHECK(t, p16 / p256 < 6.0, "padded sobol: error falls %.1fx: the interaction is stratified?", p16 / p256);
    CHECK(t, fabs(m - exact) < K_SIGMA * se, "halton: mean %.5f, exact %.5f, standard error %.5f", m, exact, se);
}

/* Two coordinates of large bases (151 and 157: the last bounce's last slots of
   the Halton point) over a pixel's first 64 samples, where k < p: the first digit
   carries the number, so a digit map that is linear in the digit (a shift, or an
   affine a m + b) puts the 64 pairs on a few lines, with a large correlation in
   many pixels.  The film's random digit permutations pair them at random: the
   Pearson correlation of 64 independent pairs has standard deviation 1/8, so
   |r| > 0.5 (4 standard deviations) happens in about 6e-5 of the pixels.
   Measured over 2,000 pixels: 0 (permutations), 1415 (a shift alone: the mutant);
   bound: at most 3. */
static void test_halton_large_bases_pair_at_random(T *t)
{
    Sampler s;
    int pix, k, bad = 0;
    const int da = HALTON_DIMS - 2, db = HALTON_DIMS - 1;
    sampler_init(&s, SAMPLER_HALTON, 5, 64, 0, 0, 1);
    for (pix = 0; pix < 2000; pix++) {
        double sa = 0.0, sb = 0.0, saa = 0.0, sbb = 0.0, sab = 0.0, r;
        for (k = 0; k < 64; k++) {
            PixelSample ps;
            double a, b;
            sampler_start(&s, pix % 50, pix / 50, k, &ps);
            a = sampler_1d(&ps, da);
            b = sampler_1d(&ps, db);
            sa += a; sb += b; saa += a * a; sbb += b * b; sab += a * b;
        }
        r = (sab - sa * sb / 64.0) / sqrt((saa - sa * sa / 64.0) * (sbb - sb * sb / 64.0));
        bad += fabs(r) > 0.5;
    }
    printf("    dimensions %d, %d (bases 151, 157): |r| > 0.5 in %d of 2000 pixels\n", da, db, bad);
    CHECK(t, bad <= 3, "halton: large bases correlated (|r| > 0.5) in %d of 2000 pixels", bad);
}

/* With the camera in a rendered medium, halton leaves the pixel position, the hero
   wavelength and the camera ray's first free flight to the camera group (sampler.c):
   those four numbers are sobol's, bit for bit, and the other Halton coordinates
   (the lens, the first bounce) stay Halton's.  Without the medium the four are
   Halton coordinates again. */
static void test_halton_camera_group(T *t)
{
    static const int group[4] = { DIM_FILM, DIM_FILM + 1, DIM_WAVELENGTH, DIM_MEDIUM0 };
    Sampler h, sb, hn;
    int pix, k, c, same = 0, differ = 0, halton_own = 0;
    sampler_init(&h, SAMPLER_HALTON, 9, 64, 0, 0, 1);
    sampler_init(&sb, SAMPLER_SOBOL, 9, 64, 0, 0, 1);
    sampler_init(&hn, SAMPLER_HALTON, 9, 64, 0, 0, 1);
    h.camera_medium = sb.camera_medium = 1;
    for (pix = 0; pix < 16; pix++)
        for (k = 0; k < 64; k++) {
            PixelSample a, b, n;
            for (c = 0; c < 4; c++) {
                float ua, ub, un;
                sampler_start(&h, pix, 1, k, &a);
                sampler_start(&sb, pix, 1, k, &b);
                sampler_start(&hn, pix, 1, k, &n);
                ua = sampler_1d(&a, group[c]);
                ub = sampler_1d(&b, group[c]);
                un = sampler_1d(&n, group[c]);
                same += ua == ub;
                halton_own += un != ub;
            }
            sampler_start(&h, pix, 1, k, &a);
            sampler_start(&hn, pix, 1, k, &n);
            differ += sampler_1d(&a, DIM_LENS) != sampler_1d(&n, DIM_LENS);
        }
    CHECK(t, same == 16 * 64 * 4, "halton in a camera medium: %d of %d camera-group numbers are sobol's",
          same, 16 * 64 * 4);
    CHECK(t, differ == 0, "halton: the lens moved with the camera medium (%d samples)", differ);
    CHECK(t, halton_own > 16 * 64 * 4 - 40, "halton without a camera medium: only %d of %d numbers its own",
          halton_own, 16 * 64 * 4);
}

/* Sampler directives mean what they mean in pbrt-v4: the type picks the sampler
   (halton its own; pmj02bn, paddedsobol: the nearest, sobol), stratified keeps its strata
   and jitter; no directive leaves the choice to the options. */
static void test_scene_directives(T *t)
{
    static const struct { const char *text, *want; int xs, ys, jitter; } cases[] = {
        { "Sampler \"zsobol\" \"integer pixelsamples\" 32\nWorldBegin\n", "zsobol", 0, 0, 1 },
        { "Sampler \"sobol\"\nWorldBegin\n", "sobol", 0, 0, 1 },
        { "Sampler \"halton\"\nWorldBegin\n", "halton", 0, 0, 1 },
        { "Sampler \"pmj02bn\"\nWorldBegin\n", "sobol", 0, 0, 1 },
        { "Sampler \"paddedsobol\" \"string randomization\" \"owen\"\nWorldBegin\n", "sobol", 0, 0, 1 },
        { "Sampler \"independent\"\nWorldBegin\n", "independent", 0, 0, 1 },
        { "Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 3 \"bool jitter\" false\nWorldBegin\n",
          "stratified", 2, 3, 0 },
        { "WorldBegin\n", "", 0, 0, 0 } };
    int i;
    for (i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
        Scene s;
        const SceneSettings *st = &s.settings;
        if (!test_load_scene(t, &s, cases[i].text)) return;
        CHECK(t, !strcmp(st->sampler, cases[i].want), "case %d: sampler '%s', expected '%s'", i, st->sampler,
              cases[i].want);
        if (!strcmp(cases[i].want, "stratified"))
            CHECK(t, st->xsamples == cases[i].xs && st->ysamples == cases[i].ys && st->jitter == cases[i].jitter
                  && st->spp == 6, "stratified: %d x %d jitter %d spp %d", st->xsamples, st->ysamples, st->jitter, st->spp);
        CHECK(t, cases[i].want[0] == 0 || sampler_from_name(st->sampler) != SAMPLER_COUNT,
              "case %d: '%s' is no sampler", i, st->sampler);
        scene_free(&s);
    }
}

const TestCase tests_sampler[] = {
    { "sampler_halton_uniform", test_halton_uniform },
    { "sampler_halton_joint_strata", test_halton_joint_strata },
    { "sampler_halton_integral", test_halton_integral },
    { "sampler_halton_large_bases_pair_at_random", test_halton_large_bases_pair_at_random },
    { "sampler_halton_camera_group", test_halton_camera_group },
    { "sampler_scene_directives", test_scene_directives },
    { "sampler_sobol_definition", test_sobol_definition },
    { "sampler_sobol_nets", test_sobol_nets },
    { "sampler_sobol_dims23", test_sobol_dims23 },
    { "sampler_sobol23_columns", test_sobol23_columns },
    { "sampler_restart_same_numbers", test_restart_same_numbers },
    { "sampler_sobol_formula", test_sobol_formula },
    { "sampler_camera_group", test_camera_group },
    { "sampler_camera_medium_render", test_camera_medium_render },
    { "sampler_zsobol_stratified_strata", test_zsobol_stratified_strata },
    { "sampler_scrambles_decorrelated", test_scrambles_decorrelated },
    { "sampler_analytic_slope", test_analytic_slope },
    { "sampler_independent_unchanged", test_independent_unchanged },
    { "sampler_dimensions_not_shared", test_dimensions_not_shared },
    { "sampler_unbiased_over_seeds", test_unbiased_over_seeds },
    { "sampler_merge_seeds_unbiased", test_merge_seeds_unbiased },
    { "sampler_threads", test_sampler_threads },
    { "sampler_ladders", test_sampler_ladders },
    { NULL, NULL }
};
