/* sampler.c - the numbers a path uses: one u in [0, 1) per (pixel, sample, dimension).

   Exported (specnee.h section 2, "Samplers"): sampler_init, sampler_start,
   sampler_restart (the next sample of the same pixel), sampler_1d, sampler_2d, sampler_stream, sampler_progressive, sampler_from_name,
   sampler_name, sobol_u32, owen_scramble.

   A path tracer is a Monte Carlo integrator over a space of many dimensions: the
   position in the pixel, the hero wavelength, then per bounce the emitter, the
   point on it, the BSDF lobe, the direction, the roulette.  path.c asks for the
   number of each decision by its DIMENSION (the table in specnee.h, DIM_*): a
   sampler decides how the numbers of one dimension are spread over the samples
   of a pixel.  Every sampler hands out numbers that are uniform on [0, 1) one at
   a time, so every estimator stays unbiased; they differ in how evenly the N
   samples of a pixel cover each dimension (docs/sampling.md).

   independent  PCG32 (util.c), one stream per (pixel, seed, sample).  It ignores
                the dimension and hands out the stream's numbers in the order they
                are asked for.
   stratified   pbrt-v4's jittered strata: a 2-D request falls into one of
                xsamples x ysamples cells, a 1-D request into one of spp cells; a
                hashed permutation per (pixel, dimension) decides which sample takes
                which cell, a hashed jitter where in the cell.  Not progressive: the
                cells depend on spp.
   sobol        The Sobol (0,2)-sequence in its first two dimensions, PADDED: every
                dimension group (one 1-D or 2-D request, specnee.h's table) takes the
                2-D (or 1-D) Sobol points of its own shuffled order, with its own
                Owen scramble (Burley 2020, "Practical Hash-based Owen Scrambling",
                JCGT 9(4)).  Seeds are hashed from (pixel, seed, group), so groups,
                pixels and seeds are decorrelated.  Progressive: sample k does not
                depend on spp, and any 2^m first samples of a pixel form a (0,m,2)-net
                in every 2-D group.
   zsobol       pbrt-v4's default (Ahmed and Wonka 2020, "Screen-Space Blue-Noise
                Diffusion of Monte Carlo Sampling Error via Hierarchical Ordering of
                Pixels"): ONE Sobol sequence for the whole film, pixel p taking the
                2^L indices morton(p) * 2^L ... (2^L >= spp), shuffled per group by a
                nested scramble of the index; neighbouring pixels then hold
                neighbouring, complementary parts of one net, which spreads the error
                like blue noise.  Not progressive: the index depends on L.
   halton       NOT padded, as pbrt-v4's "halton": the first dimensions of a sample
                are the coordinates of ONE point of the Halton sequence, sample k
                of a pixel its k-th point, each coordinate randomised by a digit
                scramble of its own (THE HALTON POINT below); the rest padded as
                sobol.  Progressive.

   THE SOBOL POINTS.  Dimension d of point i is the 32-bit fraction
       x_d(i) = XOR over the bits b set in i of v_d[b]                      (1)
   with the generator matrix's columns v_d.  Dimension 0 is van der Corput's
   sequence, v_0[b] = 2^(31-b) (x_0 = the bits of i reversed).  Dimension 1 is
   the one with primitive polynomial x + 1 (Bratley and Fox 1988): v_1[0] = 2^31,
   v_1[b] = v_1[b-1] XOR (v_1[b-1] >> 1) (Pascal's triangle mod 2).  Together they
   are a (0,2)-sequence in base 2: every aligned block of 2^m points is a
   (0,m,2)-net, one point in every elementary box of area 2^-m.

   OWEN SCRAMBLING (Owen 1995) flips digit j of x by a random bit chosen by the
   digits above j: it keeps nets nets and makes every point uniform on [0,1).
   Burley's hash does it in one pass: reverse the bits (the first digit becomes the
   lowest), apply operations in which each output bit depends only on the input
   bits below it (adding a seed, multiplying by an odd number, x ^= x * even),
   and reverse back.  The same scramble of the INDEX i shuffles the order of the
   samples: the first 2^m indices map onto an aligned block of 2^m, so every
   power-of-two prefix is still a net, and two groups with different shuffles are
   decorrelated (padding).  The multipliers are data: the improved
   Laine-Karras hash of N. Vegdahl (2021, "Building a Better LK Hash",
   psychopath.io), which Burley's method admits in place of the paper's own
   constants and pbrt-v4 uses too.

   THE CAMERA GROUP.  Padding pairs the groups at random, so a decision that
   depends on the numbers of two groups jointly converges like independent
   sampling in their interaction, at 1/N.  The camera ray in a medium is such a
   case: whether it reaches the surface it looks at depends on the free-flight
   number AND on the hero wavelength (sigma_t(lambda) of a coloured fog) AND, at
   an object's silhouette, on the position in the pixel.  So when the camera sits
   in a rendered medium (Sampler.camera_medium), these three decisions are ONE
   4-D group: the pixel position (dimensions 0, 1), the camera ray's first free
   flight (dim_medium(0, 0)) and the hero wavelength (DIM_WAVELENGTH) are Sobol
   dimensions 0, 1, 2 and 3 of one shuffled index, each with a value scramble of
   its own.  Sobol dimensions 2 and 3 (Joe and Kuo's primitive polynomials
   x^2 + x + 1 and x^3 + x + 1, initial direction numbers 1, 3 and 1, 3, 1)
   pair with each other and with 0 and 1 as (t,m,2)-nets with t <= 2, so the
   pixel's samples cover the (wavelength, flight) square and the (position,
   flight) cube evenly.  Without a camera medium nothing changes: the wavelength
   keeps its own group (docs/sampling.md, "The camera in a medium").

   THE HALTON POINT.  Padding pairs the groups at random, so an integrand that
   depends jointly on numbers of two groups (the position in the pixel, the point
   on the lens and the point on the lamp together decide whether and how brightly
   a blurred edge is lit) converges only at the Monte Carlo rate in their
   interaction.  The halton sampler serves dimension j < HALTON_DIMS (the camera's
   five and the first HALTON_BOUNCES bounces', specnee.h's table: consecutive
   numbers, so one slot each) and the camera ray's first free flight (slot
   HALTON_DIMS) as coordinate j of the Halton point k (Halton 1960):
       x_j(k) = sum_i pi_ji(a_i) p_j^-(i+1),    k = sum_i a_i p_j^i,           (2)
   p_j the (j+1)-th prime, pi_ji a random bijection of the digits {0..p_j-1} per
   (pixel, seed, coordinate, digit position i), below.  Unscrambled, any N = prod_j p_j^e_j
   consecutive points put one point in every box prod_j [c_j p_j^-e_j, (c_j + 1)
   p_j^-e_j) (the box of x(k) is fixed by k mod p_j^e_j for each j, and by the
   Chinese remainder theorem each combination occurs once), so (pixel, lens, lamp
   point) are stratified JOINTLY.  A digit bijection keeps that (it relabels the
   boxes) and, being random, makes every digit uniform and independent of the other
   positions' digits: the number is uniform on [0, 1) (random digit permutation,
   pbrt-v4's default "permutedigits" for halton).  specnee's bijection is
   pi_i(a) = sigma_i((a + sigma_i^-1(b_i)) mod p): sigma_i a uniformly random
   permutation of the digits per coordinate and digit position, drawn once per film
   from the seed (Sampler.halton_perm, halton_tables), and b_i the i-th digit of a
   uniform number per (pixel, seed, coordinate).  Over the pixels every digit is
   uniform whatever a is; pi_i(0) = b_i, so the digits above k's own cost nothing:
   they are the rest of a uniform number.  A digit map linear in a (a shift, or
   m a + b) would be cheaper, but where k < p the first digit is then linear in k,
   and two coordinates of large bases pair on a few lines (in 1,415 of 2,000
   pixels their 64 samples correlate with |r| > 0.5; the test
   sampler_halton_large_bases_pair_at_random).  Each number is uniform on [0, 1)
   (to 2^-53), and the point sets stay stratified at every scale.  When the camera
   sits in a rendered medium the camera group (above) serves the pixel position,
   the wavelength and the first free flight, as for sobol: its 4-D Sobol net
   stratifies the three jointly where Halton bases 2, 3, 11 and 163 cannot at a
   few dozen samples (docs/sampling.md).  A scene's further dimensions (later bounces,
   media, time, subsurface) are padded sobol groups: they are unbiased and
   converge as sobol's do.

   KEPT PER PIXEL.  The render loop takes a pixel's samples in a row
   (sampler_start for the first, sampler_restart for the next): halton's Z, its
   first digit b_0 and pi_0^-1(b_0) depend on (pixel, seed, coordinate) only, so
   PixelSample keeps them per coordinate from the pixel's first sample that asks
   (halton_coord); every later sample skips the hash and the first digit's
   extraction.  The numbers are the same to the bit (the test
   sampler_restart_same_numbers).

   THE COST OF A SOBOL NUMBER.  Most numbers of a deep path come from Sobol
   groups (sobol, zsobol, halton past its point), so sampler_1d and sampler_2d
   ask for those first and work them out inline; the rest are the same
   definitions in fewer instructions, every number the same to the bit (the test
   sampler_sobol_formula works each one out afresh from sobol_u32, owen_scramble
   and hash_u64):
   - the group's hash hash_u64(key, g) starts with a * C ^ (g + C' + (a << 6)
     + (a >> 2)); the key's two shares are worked out once per pixel
     (PixelSample.key_mul, key_add; zsobol's seed's once per film), and each group
     pays the finaliser alone (key_hash);
   - the index's scramble starts from k reversed (zsobol: the index's low 32 bits
     reversed), kept per sample (sampler_restart); zsobol's 64-digit nested
     scramble gives the Sobol point its low 32 digits only, so the high half's
     scramble, whose value is never used, is not worked out (its digits still seed
     the low half's);
   - a scrambled value's float keeps the top 24 bits of a reversal, i.e. the low
     24 bits reversed: three lookups in a table of reversed bytes (reversed_float);
   - the camera group's Sobol dimensions 2 and 3 XOR four entries of byte tables
     of their reversed columns (Sampler.sobol23_rev, sampler_init), not one column
     per set bit of the index.

   A FLOAT from 32 bits keeps the top 24 (as rng_float does): exactly representable
   and strictly below 1. */
#include "specnee.h"
#include <string.h>

/* ------------------------------------------------------------------ names */

static const char *const sampler_names[SAMPLER_COUNT] = { "independent", "stratified", "sobol", "zsobol", "halton" };

const char *sampler_name(SamplerType t)
{
    return (int)t >= 0 && (int)t < SAMPLER_COUNT ? sampler_names[t] : "unknown";
}

SamplerType sampler_from_name(const char *name)
{
    int i;
    for (i = 0; i < SAMPLER_COUNT; i++)
        if (!strcmp(name, sampler_names[i])) return (SamplerType)i;
    return SAMPLER_COUNT;
}

int sampler_progressive(SamplerType t)
{
    return t == SAMPLER_INDEPENDENT || t == SAMPLER_SOBOL || t == SAMPLER_HALTON;
}

/* ------------------------------------------------------------------ bits */

static inline uint32_t reverse_bits32(uint32_t v)
{
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
    v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
    return (v >> 16) | (v << 16);
}

/* Morton code: the bits of x and y interleaved, x in the even bits. */
static uint64_t spread_bits(uint32_t v)
{
    uint64_t x = v;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x << 2)) & 0x3333333333333333ull;
    x = (x | (x << 1)) & 0x5555555555555555ull;
    return x;
}

static float u32_to_float(uint32_t v) { return (float)(v >> 8) * (1.0f / 16777216.0f); }

/* The 256 bytes with their 8 bits reversed, built as a tree of the bits: entry
   b7..b0 is b0..b7.  R2(n) lists the four values of the two lowest bits (which
   land in the top two bits, 128 and 64) on top of n, R4 and R6 the next two pairs
   (32, 16 and 8, 4), and the outer list the two highest bits (land in 2 and 1). */
#define R2(n) (n), (n) + 128, (n) + 64, (n) + 192
#define R4(n) R2(n), R2((n) + 32), R2((n) + 16), R2((n) + 48)
#define R6(n) R4(n), R4((n) + 8), R4((n) + 4), R4((n) + 12)
static const unsigned char reversed_byte[256] = { R6(0), R6(2), R6(1), R6(3) };
#undef R2
#undef R4
#undef R6

/* u32_to_float(reverse_bits32(y)), the float of a number whose digits are kept
   reversed (an Owen scramble's output, first digit in bit 0).  The float keeps
   the top 24 bits of the reversal, which are y's low 24 bits reversed: three
   byte lookups, not a whole reversal of 32 bits. */
static inline float reversed_float(uint32_t y)
{
    uint32_t top24 = (uint32_t)reversed_byte[y & 0xffu] << 16 | (uint32_t)reversed_byte[(y >> 8) & 0xffu] << 8
                     | reversed_byte[(y >> 16) & 0xffu];
    return (float)top24 * (1.0f / 16777216.0f);
}

/* hash_u64(ps->key, b): the key's share of the hash's first step was worked out
   once per pixel (sampler_start, THE COST OF A SOBOL NUMBER above), so each group's hash
   costs only the finaliser. */
static inline uint64_t key_hash(const PixelSample *ps, uint64_t b)
{
    return hash_mix(ps->key_mul ^ (b + ps->key_add));
}

/* ------------------------------------------------------------------ Sobol, Owen */

/* The digits of Sobol dimension 1 of point i, first digit in bit 0.  Column b
   of its generator matrix has digit r set iff C(b, r) is odd (Pascal's triangle
   mod 2), i.e. by Lucas' theorem iff the bits of r are a subset of those of b, so
   digit r = XOR of the i_b with b a superset of r: five butterfly steps over the
   bits of the digit position r, instead of a loop over the 32 columns (1). */
static uint32_t sobol1_digits(uint32_t i)
{
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0F0F0F0Fu;
    i ^= (i >> 8) & 0x00FF00FFu;
    i ^= (i >> 16) & 0x0000FFFFu;
    return i;
}

/* Sobol dimension 2 or 3 of point i by (1): the direction numbers m_k of the
   primitive polynomial x^s + a_1 x^(s-1) + ... + 1 follow (Bratley and Fox 1988)
       m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^s m_(k-s) ^ m_(k-s),
   and column b of the matrix is m_(b+1) / 2^(b+1) as a 32-bit fraction, i.e.
   m_(b+1) << (31 - b).  Dimension 2: x^2 + x + 1, m = 1, 3, so
   m_k = 2 m_(k-1) ^ 4 m_(k-2) ^ m_(k-2); dimension 3: x^3 + x + 1, m = 1, 3, 1, so
   m_k = 4 m_(k-2) ^ 8 m_(k-3) ^ m_(k-3).  The 32 columns of each, worked out from
   these recurrences once and written down here (the test sampler_sobol23_columns
   runs the recurrences again and compares): a render asks for these coordinates
   twice per camera sample when the camera sits in a medium, and rebuilding the
   columns each time cost some 600 instructions a call. */
static const uint32_t sobol2_columns[32] = {
    0x80000000u, 0xc0000000u, 0x60000000u, 0x90000000u, 0xe8000000u, 0x5c000000u, 0x8e000000u, 0xc5000000u,
    0x68800000u, 0x9cc00000u, 0xee600000u, 0x55900000u, 0x80680000u, 0xc09c0000u, 0x60ee0000u, 0x90550000u,
    0xe8808000u, 0x5cc0c000u, 0x8e606000u, 0xc5909000u, 0x6868e800u, 0x9c9c5c00u, 0xeeee8e00u, 0x5555c500u,
    0x8000e880u, 0xc0005cc0u, 0x60008e60u, 0x9000c590u, 0xe8006868u, 0x5c009c9cu, 0x8e00eeeeu, 0xc5005555u
};
static const uint32_t sobol3_columns[32] = {
    0x80000000u, 0xc0000000u, 0x20000000u, 0x50000000u, 0xf8000000u, 0x74000000u, 0xa2000000u, 0x93000000u,
    0xd8800000u, 0x25400000u, 0x59e00000u, 0xe6d00000u, 0x78080000u, 0xb40c0000u, 0x82020000u, 0xc3050000u,
    0x208f8000u, 0x51474000u, 0xfbea2000u, 0x75d93000u, 0xa0858800u, 0x914e5400u, 0xdbe79e00u, 0x25db6d00u,
    0x58800080u, 0xe54000c0u, 0x79e00020u, 0xb6d00050u, 0x800800f8u, 0xc00c0074u, 0x200200a2u, 0x50050093u
};

static uint32_t sobol23(uint32_t i, int dim)
{
    const uint32_t *col = dim == 2 ? sobol2_columns : sobol3_columns;
    uint32_t x = 0;
    for (; i; i >>= 1, col++)         /* (1): XOR the columns of the bits set in i */
        if (i & 1u) x ^= *col;
    return x;
}

uint32_t sobol_u32(uint32_t i, int dim)
{
    if (dim >= 2) return sobol23(i, dim);
    return reverse_bits32(dim == 0 ? i : sobol1_digits(i));   /* dim 0: van der Corput */
}

/* Burley's scramble works on the digits in reversed order (first digit in bit
   0): every step changes a bit only as a function of the bits below it, i.e.
   digit j as a function of digits < j (Vegdahl's constants). */
static inline uint32_t owen_reversed(uint32_t x, uint32_t seed)
{
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/* Owen scramble of the 32 digits of x (Burley 2020, section 4). */
uint32_t owen_scramble(uint32_t x, uint32_t seed)
{
    return reverse_bits32(owen_reversed(reverse_bits32(x), seed));
}

/* Coordinates 0 and 1 of the Owen-scrambled Sobol point i, as floats; seed is
   coordinate 0's scramble seed, coordinate 1 takes seed ^ 0x68bc21eb.  Both
   sobol_u32 and owen_scramble reverse the digits, so the reversals in between
   cancel: float(owen_scramble(sobol_u32(i, 0), seed)) is
   reversed_float(owen_reversed(i, seed)), as sobol_u32(i, 0) is i reversed, and
   coordinate 1's digits (first digit in bit 0) are sobol1_digits(i). */
static inline float sobol_owen0(uint32_t i, uint32_t seed)
{
    return reversed_float(owen_reversed(i, seed));
}
static inline float sobol_owen1(uint32_t i, uint32_t seed)
{
    return reversed_float(owen_reversed(sobol1_digits(i), seed ^ 0x68bc21ebu));
}

/* The tables of Sobol dimensions 2 and 3 by bytes (sampler_init): entry
   [d][b][v] is the XOR (1) of the columns 8 b + j of dimension d + 2 over the bits
   j set in the byte v, each column with its digits reversed.  The reversed
   coordinate of point i is then the XOR of four entries, one per byte of i,
   instead of a loop over its 32 bits (sobol23), and owen_reversed takes it as it
   is. */
static void sobol23_tables(Sampler *s)
{
    int d, b, v;
    for (d = 0; d < 2; d++)
        for (b = 0; b < 4; b++) {
            uint32_t *t = s->sobol23_rev[d][b];
            const uint32_t *col = (d == 0 ? sobol2_columns : sobol3_columns) + 8 * b;
            t[0] = 0u;
            for (v = 1; v < 256; v++) {   /* v's lowest set bit j, added to v without it */
                int j = 0;
                while (!(v >> j & 1)) j++;
                t[v] = t[v & (v - 1)] ^ reverse_bits32(col[j]);
            }
        }
}

/* Coordinate c (2 or 3) of the Owen-scrambled Sobol point i of the group whose
   hash is h (coordinates 0 and 1: sobol_owen0, sobol_owen1), with a scramble seed
   of its own: float(owen_scramble(sobol_u32(i, c), seed)), from the tables. */
static float sobol_coord(const Sampler *s, uint32_t i, uint64_t h, int c)
{
    const uint32_t (*t)[256] = s->sobol23_rev[c - 2];
    uint32_t rev = t[0][i & 0xffu] ^ t[1][(i >> 8) & 0xffu] ^ t[2][(i >> 16) & 0xffu] ^ t[3][i >> 24];
    return reversed_float(owen_reversed(rev, (uint32_t)hash_u64(h, (uint64_t)c)));
}

/* A hashed permutation of [0, n) evaluated at i: a 4-round Feistel network on
   the 2h bits of the smallest even-width power-of-two range holding n (each
   round swaps the halves and XORs one with a hash of the other: a bijection
   whatever the hash), repeated until the result lands below n (cycle walking,
   fewer than 4 rounds on average as 2^2h < 4n). */
static uint32_t permute_index(uint32_t i, uint32_t n, uint64_t seed)
{
    int h = 1, r;
    uint32_t hmask;
    while ((1ull << (2 * h)) < (uint64_t)n) h++;
    hmask = (1u << h) - 1u;
    do {
        uint32_t left = i >> h, right = i & hmask;
        for (r = 0; r < 4; r++) {
            uint32_t f = (uint32_t)hash_u64(seed + (uint64_t)r, (uint64_t)right) & hmask;
            uint32_t next = left ^ f;
            left = right;
            right = next;
        }
        i = (left << h) | right;
    } while (i >= n);
    return i;
}

/* ------------------------------------------------------------------ Halton */

/* The first primes: the base of coordinate j (the last one is the camera ray's
   first free flight). */
static const unsigned short halton_primes[HALTON_DIMS + 1] = {
    2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67,
    71, 73, 79, 83, 89, 97, 101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151, 157, 163
};

/* The Halton slot of specnee's dimension dim, -1 where a padded group serves it. */
static int halton_slot(int dim)
{
    if (dim >= 0 && dim < HALTON_DIMS) return dim;
    return dim == dim_medium(0, 0) ? HALTON_DIMS : -1;
}

/* The digit tables (sampler_init): for coordinate j of base p and each digit
   position i whose p^i < 2^24, a uniformly random permutation pi_ji of the digits
   0..p-1 (Fisher-Yates on hashes of the seed).  A position past the tables keeps
   the identity. */
static void halton_tables(Sampler *s)
{
    int j, i, off = 0;
    for (j = 0; j <= HALTON_DIMS; j++) {
        uint32_t p = halton_primes[j];
        double reach = 1.0;
        int nd = 0;
        while (reach < 16777216.0) { reach *= (double)p; nd++; }
        s->halton_off[j] = (unsigned short)off;
        s->halton_ndig[j] = (unsigned char)nd;
        for (i = 0; i < nd; i++) {
            unsigned char *t = s->halton_perm + off + i * (int)p;
            uint32_t a;
            for (a = 0; a < p; a++) t[a] = (unsigned char)a;
            for (a = p - 1u; a > 0u; a--) {     /* swap t[a] with t[r], r uniform in [0, a] */
                uint64_t h = hash_u64(hash_u64((uint64_t)s->seed ^ 0x9a17u, (uint64_t)(j * 64 + i)), a);
                uint32_t r = (uint32_t)((h >> 11) % (uint64_t)(a + 1u)), c = t[a];
                t[a] = t[r];
                t[r] = (unsigned char)c;
            }
            for (a = 0; a < p; a++) s->halton_inv[off + i * (int)p + t[a]] = (unsigned char)a;
        }
        off += nd * (int)p;
    }
}

/* (a + b) mod p for digits a, b < p: one subtraction instead of a division. */
static uint32_t add_mod(uint32_t a, uint32_t b, uint32_t p)
{
    uint32_t s = a + b;
    return s >= p ? s - p : s;
}

/* The float of a Halton coordinate v in [0, 1): its top 24 bits of 32. */
static float halton_float(double v)
{
    double t32 = v * 4294967296.0;
    return u32_to_float(t32 < 4294967295.0 ? (uint32_t)t32 : 4294967295u);
}

/* Coordinate `slot` of the scrambled Halton point k (2) of the pixel whose hash is
   key.  Digit a_i of k (base p, least significant first) becomes digit i of the
   result as pi_i((a_i + pi_i^-1(b_i)) mod p): b_i, the pixel's own, is the i-th
   base-p digit of a uniform number Z per (pixel, seed, coordinate); pi_i the
   film's random permutation (halton_tables).  For each pixel and position this is
   a bijection of the digits (so every elementary box of the Halton point keeps its
   one sample) that sends a = 0 to b_i, and over the pixels a digit that is uniform
   for every a (pi_i^-1(b_i) is uniform).  A shift alone (a + b_i) would make
   the first digit linear in k where k < p, so two coordinates of large bases
   would pair on a few lines; the permutation pairs them at random, as pbrt-v4's
   permuted digits do.  Past k's own digits (a = 0, hence b_i) the digits of Z are
   the rest of the number, w Z', so no digit is ever cut off.  Z, its first digit
   and pi_0^-1(b_0) are kept in ps for the pixel's later samples (KEPT PER PIXEL),
   and worked out in the same operations when they are not there yet. */
static float halton_coord(PixelSample *ps, int slot)
{
    const Sampler *s = ps->s;
    const double two53 = 9007199254740992.0;
    uint32_t p = halton_primes[slot], rest = ps->k;
    const unsigned char *t = s->halton_perm + s->halton_off[slot];
    const unsigned char *ti = s->halton_inv + s->halton_off[slot];
    int i = 1, nd = s->halton_ndig[slot];
    double z, v = 0.0, w = 1.0;
    uint32_t a, d;
    if (!(ps->halton_have >> slot & 1u)) {
        /* the pixel's Z and its first digit: the same for all the pixel's samples */
        uint64_t h = key_hash(ps, (uint64_t)slot + 0x4a17u);
        double z0 = (double)(h >> 11) / two53, zp = z0 * (double)p;
        uint32_t b0 = (uint32_t)zp;        /* the first digit of Z */
        ps->halton_z0[slot] = z0;
        ps->halton_z1[slot] = zp - (double)b0;   /* Z's rest after it */
        ps->halton_c0[slot] = ti[b0];      /* pi_0^-1(b_0): digit position 0 has a table */
        ps->halton_have |= (uint64_t)1 << slot;
    }
    if (rest == 0)                         /* k = 0: every digit is Z's */
        return halton_float(ps->halton_z0[slot]);
    a = rest % p;                          /* digit 0 of k */
    rest /= p;                             /* k's digits above it */
    w /= (double)p;                        /* p^-1 */
    d = t[add_mod(a, ps->halton_c0[slot], p)];
    v += (double)d * w;
    z = ps->halton_z1[slot];
    while (rest > 0) {                     /* digits 1, 2, ... of k */
        uint32_t b;
        a = rest % p;
        z *= (double)p;
        b = (uint32_t)z;                   /* the next digit of Z */
        z -= (double)b;
        rest /= p;
        w /= (double)p;
        if (i < nd)                        /* pi(a + pi^-1(b)): a = 0 keeps b */
            d = t[i * (int)p + (int)add_mod(a, ti[i * (int)p + (int)b], p)];
        else
            d = add_mod(a, b, p);
        v += (double)d * w;
        i++;
    }
    v += w * z;                            /* the zero digits above, shifted: Z's rest */
    return halton_float(v);
}

/* ------------------------------------------------------------------ the sampler */

void sampler_init(Sampler *s, SamplerType type, int seed, int spp, int xsamples, int ysamples, int jitter)
{
    memset(s, 0, sizeof *s);
    s->type = type;
    s->seed = (uint32_t)seed;
    s->spp = spp > 0 ? spp : 1;
    s->jitter = jitter;
    /* stratified: xsamples x ysamples = spp; when they do not multiply to spp,
       factor spp into the two most nearly equal factors (pbrt-v4 does the same
       with --spp) */
    if (xsamples > 0 && ysamples > 0 && xsamples * ysamples == s->spp) {
        s->xsamples = xsamples;
        s->ysamples = ysamples;
    } else {
        int d = 1;
        while ((d + 1) * (d + 1) <= s->spp) d++;
        while (s->spp % d) d--;
        s->ysamples = d;
        s->xsamples = s->spp / d;
    }
    while ((1L << s->log2_spp) < s->spp) s->log2_spp++;
    s->seed_mul = hash_a_mul((uint64_t)s->seed);   /* zsobol's group hash: the seed's share */
    s->seed_add = hash_a_add((uint64_t)s->seed);
    if (type == SAMPLER_HALTON) halton_tables(s);
    sobol23_tables(s);                     /* the camera group's (camera_medium is set later) */
}

void sampler_start(const Sampler *s, int x, int y, int k, PixelSample *ps)
{
    ps->s = s;
    ps->key = hash_u64(hash_u64((uint64_t)x, (uint64_t)y), (uint64_t)s->seed);
    ps->key_mul = hash_a_mul(ps->key);     /* key_hash's share of the key */
    ps->key_add = hash_a_add(ps->key);
    ps->halton_have = 0;                   /* a new pixel: nothing of it kept yet */
    if (s->type == SAMPLER_ZSOBOL)         /* the pixel's Morton code; k joins it below */
        ps->index = (spread_bits((uint32_t)y) << 1 | spread_bits((uint32_t)x)) << s->log2_spp;
    sampler_restart(ps, k);
}

void sampler_restart(PixelSample *ps, int k)
{
    const Sampler *s = ps->s;
    ps->k = (uint32_t)k;
    ps->k_reversed = reverse_bits32((uint32_t)k);
    memset(ps->used, 0, sizeof ps->used);
    ps->reused = 0;
    if (s->type == SAMPLER_INDEPENDENT) {
        rng_seed(&ps->rng, ps->key, (uint64_t)k);   /* sample k's stream: independent of spp */
    } else if (s->type == SAMPLER_ZSOBOL) {
        ps->index = (ps->index >> s->log2_spp << s->log2_spp) | (uint64_t)k;
        ps->low_reversed = reverse_bits32((uint32_t)ps->index);   /* sobol_index's start */
    }
}

/* Mark dimensions [dim, dim + n) as used by this sample (the table's promise:
   no two decisions share one); counts a second use. */
static void mark_used(PixelSample *ps, int dim, int n)
{
    for (; n > 0; n--, dim++)
        if (dim >= 0 && dim < SAMPLER_CHECKED_DIMS) {
            uint32_t bit = 1u << (dim & 31);
            if (ps->used[dim >> 5] & bit) ps->reused++;
            ps->used[dim >> 5] |= bit;
        }
}

/* The group that serves dimension dim, and *coord, the Sobol coordinate of its
   first number: dim itself and 0, except for the camera group (THE CAMERA GROUP
   above). */
static int group_of(const Sampler *s, int dim, int *coord)
{
    *coord = 0;
    if (!s->camera_medium) return dim;
    if (dim == dim_medium(0, 0)) { *coord = 2; return DIM_FILM; }
    if (dim == DIM_WAVELENGTH) { *coord = 3; return DIM_FILM; }
    return dim;
}

/* Dimension dim belongs to the camera group (THE CAMERA GROUP above): halton
   leaves these four to it, the 4-D Sobol net stratifying them jointly better than
   Halton bases 2, 3, 11 and 163 can at a few dozen samples. */
static int in_camera_group(const Sampler *s, int dim)
{
    return s->camera_medium && (dim == DIM_FILM || dim == DIM_FILM + 1 || dim == DIM_WAVELENGTH
                                || dim == dim_medium(0, 0));
}

/* The Sobol point i that group g gives this sample, and the group's hash *h
   (its scrambles' seeds); sampler_1d and sampler_2d then take coordinates of
   point i (sobol_owen0, sobol_owen1, sobol_coord).
   sobol (and halton's padded groups): h hashes (pixel, seed, group), and the
   group's own order of the pixel's samples is i = owen_scramble(k, h), k's
   reversal kept (sampler_restart).
   zsobol: h hashes (seed, group), one per film.  The film-wide index x (the
   Morton code x 2^L + k) is owen-scrambled on its 64 digits, nested: the high 32
   digits first with the seed h, then the low 32 with a seed hashed from h and
   the high half's digits, so that each low digit still depends on every digit
   above it.  Point i is the scrambled index's low 32 digits, so only the low
   half's scramble is worked out (the high half's value is never used); x's low
   half reversed is kept per sample (sampler_restart). */
static inline uint32_t sobol_index(const PixelSample *ps, int g, uint64_t *h)
{
    const Sampler *s = ps->s;
    if (s->type == SAMPLER_ZSOBOL) {
        *h = hash_mix(s->seed_mul ^ ((uint64_t)g + s->seed_add));  /* hash_u64(seed, g): per film */
        return reverse_bits32(owen_reversed(ps->low_reversed, (uint32_t)hash_u64(*h, ps->index >> 32)));
    }
    *h = key_hash(ps, (uint64_t)g);
    return reverse_bits32(owen_reversed(ps->k_reversed, (uint32_t)*h));
}

/* 1 if a Sobol group serves dimension dim: every dimension of sobol and zsobol,
   and halton's past its point or in the camera group.  Asked first for every
   number (sampler_1d, sampler_2d), as it is the common case of a deep path. */
static inline int sobol_group(const Sampler *s, int dim)
{
    if (s->type == SAMPLER_SOBOL || s->type == SAMPLER_ZSOBOL) return 1;
    return s->type == SAMPLER_HALTON && (halton_slot(dim) < 0 || in_camera_group(s, dim));
}

/* n = 1 or 2 numbers of the group that starts at dimension dim: stratified's
   and halton's point (sampler_1d and sampler_2d work the independent stream and
   the Sobol groups out themselves). */
static void group_sample(PixelSample *ps, int dim, int n, float *u)
{
    const Sampler *s = ps->s;
    int c;
    switch (s->type) {
    case SAMPLER_STRATIFIED: {
        uint64_t h = key_hash(ps, (uint64_t)dim);
        uint32_t cells = n == 2 ? (uint32_t)(s->xsamples * s->ysamples) : (uint32_t)s->spp;
        uint32_t cell = permute_index(ps->k, cells, h);
        uint64_t j = hash_u64(h, (uint64_t)ps->k);    /* the jitter of this sample */
        float jx = s->jitter ? u32_to_float((uint32_t)j) : 0.5f;
        float jy = s->jitter ? u32_to_float((uint32_t)(j >> 32)) : 0.5f;
        if (n == 1) {
            u[0] = ((float)cell + jx) / (float)cells;
        } else {
            u[0] = ((float)(cell % (uint32_t)s->xsamples) + jx) / (float)s->xsamples;
            u[1] = ((float)(cell / (uint32_t)s->xsamples) + jy) / (float)s->ysamples;
        }
        /* (cell + j) / cells can round up to 1 in float: keep [0, 1) */
        for (c = 0; c < n; c++) if (u[c] >= 1.0f) u[c] = 0.99999994f;
        break;
    }
    case SAMPLER_HALTON:   /* the Halton point's slots (the rest: sobol_group) */
        for (c = 0; c < n; c++) u[c] = halton_coord(ps, halton_slot(dim + c));
        break;
    default:
        for (c = 0; c < n; c++) u[c] = 0.5f;
    }
}

float sampler_1d(PixelSample *ps, int dim)
{
    const Sampler *s = ps->s;
    float u = 0.0f;
    mark_used(ps, dim, 1);
    if (s->type == SAMPLER_INDEPENDENT) return rng_float(&ps->rng);   /* the stream's next number */
    if (sobol_group(s, dim)) {
        int coord, g = group_of(s, dim, &coord);
        uint64_t h;
        uint32_t i = sobol_index(ps, g, &h);
        return coord ? sobol_coord(s, i, h, coord) : sobol_owen0(i, (uint32_t)(h >> 32));
    }
    group_sample(ps, dim, 1, &u);
    return u;
}

void sampler_2d(PixelSample *ps, int dim, float *u0, float *u1)
{
    const Sampler *s = ps->s;
    float u[2] = { 0.0f, 0.0f };
    int c;
    mark_used(ps, dim, 2);
    if (s->type == SAMPLER_INDEPENDENT) {  /* the stream's next two numbers, in this order */
        for (c = 0; c < 2; c++) u[c] = rng_float(&ps->rng);
        *u0 = u[0];
        *u1 = u[1];
        return;
    }
    if (sobol_group(s, dim)) {
        int coord, g = group_of(s, dim, &coord);
        uint64_t h;
        uint32_t i = sobol_index(ps, g, &h);
        if (coord) {                       /* a 1-D coordinate of the camera group: none second */
            *u0 = sobol_coord(s, i, h, coord);
            *u1 = 0.0f;
        } else {
            *u0 = sobol_owen0(i, (uint32_t)(h >> 32));
            *u1 = sobol_owen1(i, (uint32_t)(h >> 32));
        }
        return;
    }
    group_sample(ps, dim, 2, u);
    *u0 = u[0];
    *u1 = u[1];
}

Rng *sampler_stream(PixelSample *ps)
{
    return ps->s->type == SAMPLER_INDEPENDENT ? &ps->rng : NULL;
}
