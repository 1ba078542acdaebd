/* texture.c - pbrt-v4's textures: constant, checkerboard, scale, mix,
   directionmix, bilerp, imagemap, dots, marble, fbm, wrinkled, windy.

   Exported (specnee.h sections 6 and 10): tex_eval, tex_set_image, tex_free,
   tex_noise, tex_noise_diff, tex_fbm, tex_turbulence, tex_marble_init.
   scene.c's directive loop hands a Texture directive to texture_from_params (the
   last section), which fills Scene.textures; a material whose
   "reflectance" names a texture (diffuse) reads it through mat_albedo_at
   (material.c) at every hit, at each of the path's wavelengths; conductor and
   coateddiffuse read a textured reflectance and roughness through mat_point.

   1. Mapping (pbrt-v4 textures.h, the pbrt book 4th ed. section 10.2).  A 2-D
      texture maps the surface point to (s, t):
        uv           s = uscale u + udelta,  t = vscale v + vdelta, with (u, v) the
                     shape's parameters (SurfacePoint.u, .v)
        spherical    q = the point in the texture's frame (the inverse of the CTM at
                     the Texture directive), s = theta(q) / pi, t = phi(q) / (2 pi)
        cylindrical  s = (pi + atan2(q_y, q_x)) / (2 pi),  t = q_z
        planar       s = udelta + q . v1,  t = vdelta + q . v2
   2. The textures.
        constant      "value"
        checkerboard  tex1 where floor(s) + floor(t) is even, tex2 where it is odd
                      (pbrt-v4's 2-D Checkerboard); with "integer dimension" 3,
                      tex1 where floor(q_x) + floor(q_y) + floor(q_z) is even, q the
                      point in the texture's frame (pbrt-v4's TextureMapping3D,
                      which reads no parameters: the 2-D mapping's are then
                      unused, as in pbrt-v4).  pbrt-v4 also box-filters the edge
                      over the ray's footprint, which changes a pixel's mean only
                      in the pixels an edge crosses, and converges to the same
                      image as the footprint shrinks; specnee point-samples it and
                      the pixel filter averages)
        scale         tex x scale
        mix           (1 - amount) tex1 + amount tex2
        directionmix  a tex1 + (1 - a) tex2 with a = |ng . dir|: ng the geometric
                      normal at the hit (pbrt-v4's TextureEvalContext n, not the
                      shading normal), dir the "dir" parameter carried to world
                      space by the CTM at the directive (as a vector) and
                      normalised; a texture whose weight is 0 is not evaluated
        bilerp        (1 - s)(1 - t) v00 + s (1 - t) v10 + (1 - s) t v01 + s t v11:
                      v00 at (s, t) = (0, 0), v10 at (1, 0), v01 at (0, 1), v11 at
                      (1, 1) (pbrt-v4's FloatBilerpTexture and
                      SpectrumBilerpTexture); (s, t) is not clamped, so outside the
                      unit square the texture extrapolates, as pbrt-v4's does.  The
                      corners are constants (no textures), a spectrum corner held
                      as the other textures' constants are (a reflectance: an
                      "rgb" within [0, 1]); a material that reads the result as a
                      reflectance clamps it to [0, 1] (mat_albedo_at, mat_point),
                      as pbrt-v4's materials clamp theirs
        imagemap      the image at (s, 1 - t) (pbrt-v4 flips t: row 0 is the top),
                      the nearest texel for "filter" "point" (texel round(s w -
                      1/2), round((1 - t) h - 1/2), pbrt-v4's Point), else
                      bilinear between the four nearest texel centres (pbrt-v4's
                      default "bilinear" filter), wrapped by "repeat", "black" or
                      "clamp"; always at full resolution: pbrt-v4 reads the MIP
                      level of the ray footprint's width, full resolution where a
                      texel covers a pixel or more, and everywhere under Option
                      "disabletexturefiltering" (its footprint then is zero)
        dots          "outside" in a polka dot, "inside" elsewhere (sic, section 4)
        marble        a 3-D texture: a colour spline of a noise-perturbed sine
                      (section 4)
        fbm           (float, 3-D) FBm(q, roughness, octaves) (section 4)
        wrinkled      (float, 3-D) Turbulence(q, roughness, octaves)
        windy         (float, 3-D) |FBm(q / 10, 0.5, 3)| FBm(q, 0.5, 6)
                      (q: the point in the texture's frame; pbrt-v4 has these three
                      as float textures only)
   3. RGB to spectrum.  A spectrum image texture holds reflectances: each texel's
      RGB, after pbrt-v4's scale and invert, is clamped to [0, 1] and turned into
      the smooth spectrum of spec_from_rgb (Jakob and Hanika 2019's sigmoid of a
      quadratic; a grey texel exactly flat), stored as 4 floats (m, c0, c1, c2) so
      that the texel's value at lambda is m sigmoid(c(lambda)).  pbrt-v4 interpolates
      the RGB and fits the spectrum at each lookup (through its precomputed table);
      specnee fits each texel once at load time and interpolates the four texels'
      values at lambda.  Both reproduce a texel's RGB exactly under D65; between
      texel centres they differ by the fit's non-linearity, which the film's XYZ,
      linear in the spectrum, sees only in the second order.  Fitting is Newton's
      method from the previous texel's coefficients (spec_rgb_coeffs_from), with
      the full homotopy fit when that does not converge.  An area light's emission
      image (Texture.illuminant, lights.c) holds illuminant texels instead: not
      clamped to 1, m = 2 max(rgb) and the fit of rgb / m (pbrt-v4's
      RGBIlluminantSpectrum without its D65 factor, which the light applies),
      each fitted as an "rgb L" is (spec_rgb_coeffs: the table and its polish),
      so that a one-colour image is that light to float precision (about 10 us
      a texel).  The fit is in the image's colour space: sRGB for PNG and PFM,
      and for an EXR the space its "chromaticities" name (exr.c; pbrt-v4 gives
      each image its own space, whatever the ColorSpace directive says), whose
      matrix and white weight the fit (spec_rgb_fit_table, the space's table), so
      a texel of an ACES2065-1 file reproduces its RGB under ACES's white.
   4. Noise (pbrt-v4 util/noise.cpp, textures.cpp; the pbrt book 4th ed. section
      10.6, after Perlin 2002, "Improving Noise").  noise(p): p's lattice cell
      (ix, iy, iz) = floor(p) and offsets d = p - floor(p); each of the cell's 8
      corners c gets a gradient chosen by h = perm[perm[perm[cx] + cy] + cz] mod 16
      (indices mod 256) and contributes g_h . (d - c), with pbrt-v4's choice
      u = dx if h < 8 or h = 12, 13, else dy;  v = dy if h < 4 or h = 12, 13, else dz;
      g_h . x = (h & 1 ? -u : u) + (h & 2 ? -v : v); the 8 values are blended
      trilinearly with the weight w(t) = 6t^5 - 15t^4 + 10t^3 of each offset.
      Coordinates are first reduced mod 2^30 (pbrt-v4: no int overflow).
      tex_noise_diff returns noise at p and at p + h along each axis (the cloud's
      finite-difference gradient, medium.c): a shifted point in p's cell reuses
      its 8 corner hashes, so the four values cost little more than two.
        FBm(p) = sum_{i < octaves} omega^i noise(1.99^i p).  pbrt-v4 drops the
          octaves finer than the ray's footprint (n = clamp(-1 - log2(|dp|^2)/2,
          0, octaves), fading the last one in); specnee has no ray differentials
          and sums all of them, pbrt-v4's value for a footprint of zero.  The
          dropped octaves are finer than a pixel and weigh omega^i (0.5^i by
          default), so a pixel's mean moves little.
        Turbulence(p) = sum_{i < octaves} omega^i |noise(1.99^i p)| + 0.2 omega^octaves:
          pbrt-v4 fades the octave at the footprint from 0.2 (the mean of |noise|,
          its stand-in for unresolved octaves) to |noise| and adds 0.2 omega^i for
          each dropped octave; at a footprint of zero that leaves the octaves'
          sum and one 0.2 omega^octaves (pbrt-v4's Lerp(0, 0.2, .)).  As for FBm,
          pbrt-v4's value at a pixel's footprint differs in the octaves finer than
          the pixel: with the defaults at most 0.2 omega^n per dropped octave n.
        dots: the cell (sc, tc) = floor((s, t) + 1/2) has a dot when
          noise(sc + .5, tc + .5, .5) > 0, of radius 0.35 centred at
          (sc + 0.15 noise(sc + 1.5, tc + 2.8, .5), tc + 0.15 noise(sc + 4.5, tc + 9.8, .5));
          inside it the texture is the parameter "outside" (0 by default),
          elsewhere "inside" (1): pbrt-v4's DotsTexture::Create passes "inside" to
          the constructor's outsideDot and "outside" to its insideDot (as pbrt-v3
          did), so that is what pbrt-v4 files mean; with the defaults, black dots
          on white.
        marble: q = scale (the point in the texture's frame), m = q_y + variation
          FBm(q, roughness, octaves), x = 1/2 + sin(m)/2, and the RGB colour
          1.5 B(x) of pbrt-v4's spline: 9 colours c_0..c_8, segment k = min(floor(6x),
          5) is the cubic Bezier curve with control points c_k..c_{k+3} at 6x - k (the
          segments do not join: each starts at c_k and ends at c_{k+3}).  The
          colour is a reflectance (pbrt-v4's RGBAlbedoSpectrum); specnee fits the
          spline once, at MARBLE_KNOTS + 1 points of each segment (section 3), and
          interpolates the fitted spectra linearly between them: a colour within
          1e-3 of the spline's everywhere (tests/test_texture.c). */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

/* Ken Perlin's reference permutation of 0..255 ("Improving Noise", SIGGRAPH 2002,
   and its reference implementation), the table pbrt-v4's noise.cpp holds twice;
   section 4 indexes it mod 256. */
static const unsigned char PERM[256] = {
    151, 160, 137,  91,  90,  15, 131,  13, 201,  95,  96,  53, 194, 233,   7, 225,
    140,  36, 103,  30,  69, 142,   8,  99,  37, 240,  21,  10,  23, 190,   6, 148,
    247, 120, 234,  75,   0,  26, 197,  62,  94, 252, 219, 203, 117,  35,  11,  32,
     57, 177,  33,  88, 237, 149,  56,  87, 174,  20, 125, 136, 171, 168,  68, 175,
     74, 165,  71, 134, 139,  48,  27, 166,  77, 146, 158, 231,  83, 111, 229, 122,
     60, 211, 133, 230, 220, 105,  92,  41,  55,  46, 245,  40, 244, 102, 143,  54,
     65,  25,  63, 161,   1, 216,  80,  73, 209,  76, 132, 187, 208,  89,  18, 169,
    200, 196, 135, 130, 116, 188, 159,  86, 164, 100, 109, 198, 173, 186,   3,  64,
     52, 217, 226, 250, 124, 123,   5, 202,  38, 147, 118, 126, 255,  82,  85, 212,
    207, 206,  59, 227,  47,  16,  58,  17, 182, 189,  28,  42, 223, 183, 170, 213,
    119, 248, 152,   2,  44, 154, 163,  70, 221, 153, 101, 155, 167,  43, 172,   9,
    129,  22,  39, 253,  19,  98, 108, 110,  79, 113, 224, 232, 178, 185, 112, 104,
    218, 246,  97, 228, 251,  34, 242, 193, 238, 210, 144,  12, 191, 179, 162, 241,
     81,  51, 145, 235, 249,  14, 239, 107,  49, 192, 214,  31, 181, 199, 106, 157,
    184,  84, 204, 176, 115, 121,  50,  45, 127,   4, 150, 254, 138, 236, 205,  93,
    222, 114,  67,  29,  24,  72, 243, 141, 128, 195,  78,  66, 215,  61, 156, 180
};

/* perm[i mod 256] for i given as an unsigned int: an int converted to unsigned
   keeps its value mod 2^32, a multiple of 256, so the low 8 bits are i mod 256. */
static unsigned perm_u(unsigned i)
{
    return PERM[i & 255u];
}

/* The gradient of hash h (0..15) dotted with the offset d = (dx, dy, dz) (section 4),
   g_h . d = (h & 1 ? -u : u) + (h & 2 ? -v : v), by tables: u = d[NOISE_U[h]] (dx for
   h < 8 and h = 12, 13, else dy), v = d[NOISE_V[h]] (dy for h < 4 and h = 12, 13,
   else dz), and the signs as factors +-1 (a product by -1 is an exact negation). */
static const unsigned char NOISE_U[16] = { 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 1, 1 };
static const unsigned char NOISE_V[16] = { 1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 1, 1, 2, 2 };
static const float NOISE_SU[16] = { 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1 };
static const float NOISE_SV[16] = { 1, 1, -1, -1, 1, 1, -1, -1, 1, 1, -1, -1, 1, 1, -1, -1 };

static float grad(unsigned h, float dx, float dy, float dz)
{
    float d[3];
    d[0] = dx; d[1] = dy; d[2] = dz;
    return NOISE_SU[h] * d[NOISE_U[h]] + NOISE_SV[h] * d[NOISE_V[h]];
}

static float noise_weight(float t)
{
    return t * t * t * (t * (6.0f * t - 15.0f) + 10.0f);
}

static float lerpf(float t, float a, float b) { return (1.0f - t) * a + t * b; }

/* x mod 2^30 (pbrt-v4's reduction): fmodf returns x itself when |x| < 2^30. */
static float noise_reduce(float x)
{
    return fabsf(x) < 1073741824.0f ? x : fmodf(x, 1073741824.0f);
}

/* floor(x) as an int for |x| < 2^30: truncation, one less below zero when x has
   a fraction (the float of the truncation is exact there). */
static int noise_floor(float x)
{
    int i = (int)x;
    return (float)i > x ? i - 1 : i;
}

/* The noise's inner steps are inlined into its two callers below (gcc's size
   heuristics would keep them apart, costing a third of the noise's time). */
#if defined(__GNUC__) || defined(__clang__)
#define NOISE_INLINE static inline __attribute__((always_inline))
#else
#define NOISE_INLINE static inline
#endif

/* The hashes of a lattice cell's 8 corners (section 4), corner k = (k & 1,
   k >> 1 & 1, k >> 2): perm[perm[perm[x] + y] + z] & 15 shares its first two
   lookups among the corners of one x (hx) and of one (x, y) (hxy). */
NOISE_INLINE void noise_hashes(int ix, int iy, int iz, unsigned h[8])
{
    unsigned ux = (unsigned)ix, uy = (unsigned)iy, uz = (unsigned)iz, hx[2], hxy[4];
    hx[0] = perm_u(ux); hx[1] = perm_u(ux + 1u);
    hxy[0] = perm_u(hx[0] + uy); hxy[1] = perm_u(hx[1] + uy);
    hxy[2] = perm_u(hx[0] + uy + 1u); hxy[3] = perm_u(hx[1] + uy + 1u);
    h[0] = perm_u(hxy[0] + uz) & 15u; h[1] = perm_u(hxy[1] + uz) & 15u;
    h[2] = perm_u(hxy[2] + uz) & 15u; h[3] = perm_u(hxy[3] + uz) & 15u;
    h[4] = perm_u(hxy[0] + uz + 1u) & 15u; h[5] = perm_u(hxy[1] + uz + 1u) & 15u;
    h[6] = perm_u(hxy[2] + uz + 1u) & 15u; h[7] = perm_u(hxy[3] + uz + 1u) & 15u;
}

/* The noise from the corner hashes and the offset (dx, dy, dz) in [0, 1)^3 from
   the cell's lowest corner: the 8 gradients' dot products blended by the weights. */
NOISE_INLINE float noise_blend(const unsigned h[8], float dx, float dy, float dz)
{
    float wx, wy, wz, c[8], ex = dx - 1.0f, ey = dy - 1.0f, ez = dz - 1.0f;
    c[0] = grad(h[0], dx, dy, dz); c[1] = grad(h[1], ex, dy, dz);
    c[2] = grad(h[2], dx, ey, dz); c[3] = grad(h[3], ex, ey, dz);
    c[4] = grad(h[4], dx, dy, ez); c[5] = grad(h[5], ex, dy, ez);
    c[6] = grad(h[6], dx, ey, ez); c[7] = grad(h[7], ex, ey, ez);
    wx = noise_weight(dx); wy = noise_weight(dy); wz = noise_weight(dz);
    return lerpf(wz, lerpf(wy, lerpf(wx, c[0], c[1]), lerpf(wx, c[2], c[3])),
                 lerpf(wy, lerpf(wx, c[4], c[5]), lerpf(wx, c[6], c[7])));
}

/* Finite and below 1e30 (the noise is 0 at NaN, inf and huge points) */
#define NOISE_OK(v) (fabsf(v) < 1e30f)

float tex_noise(float x, float y, float z)
{
    unsigned h[8];
    int ix, iy, iz;
    if (!(NOISE_OK(x) && NOISE_OK(y) && NOISE_OK(z))) return 0.0f;
    x = noise_reduce(x); y = noise_reduce(y); z = noise_reduce(z);
    ix = noise_floor(x); iy = noise_floor(y); iz = noise_floor(z);
    noise_hashes(ix, iy, iz, h);
    return noise_blend(h, x - (float)ix, y - (float)iy, z - (float)iz);
}

/* The three shifted points differ from p in one coordinate each: where that
   coordinate stays in p's lattice cell, the shifted noise reuses p's hashes. */
void tex_noise_diff(Vec3 p, float h, float n[4])
{
    unsigned hp[8], hs[8];
    float x = p.x, y = p.y, z = p.z, sx = x + h, sy = y + h, sz = z + h, dx, dy, dz, e;
    int ix, iy, iz, is;
    if (!(NOISE_OK(x) && NOISE_OK(y) && NOISE_OK(z) && NOISE_OK(sx) && NOISE_OK(sy) && NOISE_OK(sz))) {
        n[0] = tex_noise(x, y, z); n[1] = tex_noise(sx, y, z);
        n[2] = tex_noise(x, sy, z); n[3] = tex_noise(x, y, sz);
        return;
    }
    x = noise_reduce(x); y = noise_reduce(y); z = noise_reduce(z);
    ix = noise_floor(x); iy = noise_floor(y); iz = noise_floor(z);
    dx = x - (float)ix; dy = y - (float)iy; dz = z - (float)iz;
    noise_hashes(ix, iy, iz, hp);
    n[0] = noise_blend(hp, dx, dy, dz);
    sx = noise_reduce(sx); is = noise_floor(sx); e = sx - (float)is;
    if (is != ix) noise_hashes(is, iy, iz, hs);
    n[1] = noise_blend(is == ix ? hp : hs, e, dy, dz);
    sy = noise_reduce(sy); is = noise_floor(sy); e = sy - (float)is;
    if (is != iy) noise_hashes(ix, is, iz, hs);
    n[2] = noise_blend(is == iy ? hp : hs, dx, e, dz);
    sz = noise_reduce(sz); is = noise_floor(sz); e = sz - (float)is;
    if (is != iz) noise_hashes(ix, iy, is, hs);
    n[3] = noise_blend(is == iz ? hp : hs, dx, dy, e);
}

/* pbrt-v4's octave frequency step (slightly off 2 so that octaves' lattices do not align) */
#define NOISE_LACUNARITY 1.99f

float tex_fbm(Vec3 p, float omega, int octaves)
{
    float sum = 0.0f, scale = 1.0f, o = 1.0f;
    int i;
    for (i = 0; i < octaves; i++) {
        sum += o * tex_noise(scale * p.x, scale * p.y, scale * p.z);
        scale *= NOISE_LACUNARITY;
        o *= omega;
    }
    return sum;
}

float tex_turbulence(Vec3 p, float omega, int octaves)
{
    float sum = 0.0f, scale = 1.0f, o = 1.0f;
    int i;
    for (i = 0; i < octaves; i++) {
        sum += o * fabsf(tex_noise(scale * p.x, scale * p.y, scale * p.z));
        scale *= NOISE_LACUNARITY;
        o *= omega;
    }
    return sum + o * 0.2f;
}

/* pbrt-v4's InsidePolkaDot (section 4). */
static int inside_dot(float s, float t)
{
    float sc = floorf(s + 0.5f), tc = floorf(t + 0.5f), cs, ct, ds, dt;
    if (!(tex_noise(sc + 0.5f, tc + 0.5f, 0.5f) > 0.0f)) return 0;
    cs = sc + 0.15f * tex_noise(sc + 1.5f, tc + 2.8f, 0.5f);
    ct = tc + 0.15f * tex_noise(sc + 4.5f, tc + 9.8f, 0.5f);
    ds = s - cs;
    dt = t - ct;
    return ds * ds + dt * dt < 0.35f * 0.35f;
}

/* The marble spline's colours (pbrt-v4 MarbleTexture::Evaluate). */
static const float MARBLE_RGB[9][3] = {
    { .58f, .58f, .6f }, { .58f, .58f, .6f }, { .58f, .58f, .6f },
    { .5f, .5f, .5f },   { .6f, .59f, .58f }, { .58f, .58f, .6f },
    { .58f, .58f, .6f }, { .2f, .2f, .33f },  { .58f, .58f, .6f },
};
#define MARBLE_SEGS 6
#define MARBLE_KNOTS 64          /* @@ fitted spectra per segment: memory vs. the spline's fidelity */

/* The spline's RGB in segment k at x in [0, 1] (1.5 times a cubic Bezier curve). */
static void marble_rgb(int k, float x, double rgb[3])
{
    float a = 1.0f - x, b0 = a * a * a, b1 = 3.0f * a * a * x, b2 = 3.0f * a * x * x, b3 = x * x * x;
    int c;
    for (c = 0; c < 3; c++)
        rgb[c] = 1.5 * (double)(b0 * MARBLE_RGB[k][c] + b1 * MARBLE_RGB[k + 1][c] +
                                b2 * MARBLE_RGB[k + 2][c] + b3 * MARBLE_RGB[k + 3][c]);
}

int tex_marble_init(Texture *t, RgbTable *rgb, Error *err)
{
    Image im;
    int k, i, ok;
    im.w = MARBLE_SEGS * (MARBLE_KNOTS + 1);
    im.h = 1;
    im.rgb = (float *)malloc(sizeof(float) * 3 * (size_t)im.w);
    if (!im.rgb) {
        error_set(err, t->file, t->line, "Texture \"marble\": out of memory");
        return 0;
    }
    for (k = 0; k < MARBLE_SEGS; k++)
        for (i = 0; i <= MARBLE_KNOTS; i++) {
            double rgb[3];
            int c;
            marble_rgb(k, (float)i / MARBLE_KNOTS, rgb);
            for (c = 0; c < 3; c++) im.rgb[3 * (k * (MARBLE_KNOTS + 1) + i) + c] = (float)rgb[c];
        }
    t->is_float = 0;
    ok = tex_set_image(t, &im, 1.0f, 0, rgb, err);
    free(im.rgb);
    return ok;
}

/* (s, t) of a 2-D texture at sp (section 1). */
static void tex_map(const Texture *t, const SurfacePoint *sp, float *s, float *tt)
{
    Vec3 q;
    if (t->map == TEXMAP_UV) {
        *s = t->su * sp->u + t->du;
        *tt = t->sv * sp->v + t->dv;
        return;
    }
    q = xf_point(&t->tex_from_world, sp->p);
    if (t->map == TEXMAP_SPHERICAL) {
        Vec3 d = v3_norm(q);
        float ct = d.z < -1.0f ? -1.0f : d.z > 1.0f ? 1.0f : d.z;
        float phi = atan2f(d.y, d.x);
        if (phi < 0.0f) phi += 2.0f * PI_F;
        *s = acosf(ct) / PI_F;
        *tt = phi / (2.0f * PI_F);
    } else if (t->map == TEXMAP_CYLINDRICAL) {
        *s = (PI_F + atan2f(q.y, q.x)) / (2.0f * PI_F);
        *tt = q.z;
    } else {
        *s = t->du + v3_dot(q, t->vs);
        *tt = t->dv + v3_dot(q, t->vt);
    }
}

/* Argument k: its texture, or its constant. */
static float tex_arg(const Texture *tex, const Texture *t, int k, const SurfacePoint *sp, float lambda)
{
    if (t->arg_tex[k] >= 0) return tex_eval(tex, t->arg_tex[k], sp, lambda);
    return t->is_float ? t->arg_f[k] : spec_eval(&t->arg_s[k], lambda);
}

/* The value of texel (x, y) at lambda, after the wrap mode; 0 outside with "black". */
static float texel_at(const Texture *t, int x, int y, float lambda)
{
    const float *q;
    if (t->wrap == TEXWRAP_BLACK && (x < 0 || y < 0 || x >= t->w || y >= t->h)) return 0.0f;
    if (t->wrap == TEXWRAP_REPEAT) {
        x %= t->w; if (x < 0) x += t->w;
        y %= t->h; if (y < 0) y += t->h;
    }
    x = x < 0 ? 0 : x >= t->w ? t->w - 1 : x;        /* "clamp" (and a guard for the others) */
    y = y < 0 ? 0 : y >= t->h ? t->h - 1 : y;
    if (t->is_float) return t->texel[(size_t)y * t->w + x];
    q = t->texel + 4 * ((size_t)y * t->w + x);
    return q[0] * spec_sigmoid_eval(q + 1, lambda);
}

/* Bilinear between the four texel centres around (s, 1 - t) (pbrt-v4 Image::Bilerp:
   texel (x, y) has its centre at ((x + 0.5) / w, (y + 0.5) / h)). */
static float image_lookup(const Texture *t, float s, float tt, float lambda)
{
    float x = s * t->w - 0.5f, y = (1.0f - tt) * t->h - 0.5f;
    float fx, fy;
    int x0, y0;
    if (!(x > -1e9f && x < 1e9f && y > -1e9f && y < 1e9f)) return 0.0f;   /* NaN, far away */
    if (t->nearest)                    /* pbrt-v4's Point: the texel round(x), round(y) */
        return texel_at(t, (int)roundf(x), (int)roundf(y), lambda);
    x0 = (int)floorf(x);
    y0 = (int)floorf(y);
    fx = x - (float)x0;
    fy = y - (float)y0;
    return (1.0f - fx) * (1.0f - fy) * texel_at(t, x0, y0, lambda) +
           fx * (1.0f - fy) * texel_at(t, x0 + 1, y0, lambda) +
           (1.0f - fx) * fy * texel_at(t, x0, y0 + 1, lambda) +
           fx * fy * texel_at(t, x0 + 1, y0 + 1, lambda);
}

/* A marble at p (section 4): the fitted spline at x, linear between knots. */
static float marble_eval(const Texture *t, Vec3 p, float lambda_nm)
{
    Vec3 q = v3_mul(xf_point(&t->tex_from_world, p), t->mscale);
    float m = q.y + t->variation * tex_fbm(q, t->omega, t->octaves);
    float x = 0.5f + 0.5f * sinf(m), f;
    int k, i;
    if (!(x >= 0.0f && x <= 1.0f)) x = 0.5f;         /* NaN (a point at infinity) */
    k = (int)floorf(x * MARBLE_SEGS);
    if (k > MARBLE_SEGS - 1) k = MARBLE_SEGS - 1;
    x = (x * MARBLE_SEGS - (float)k) * MARBLE_KNOTS;  /* in knots, 0..MARBLE_KNOTS */
    i = (int)floorf(x);
    if (i > MARBLE_KNOTS - 1) i = MARBLE_KNOTS - 1;
    f = x - (float)i;
    i += k * (MARBLE_KNOTS + 1);
    return (1.0f - f) * texel_at(t, i, 0, lambda_nm) + f * texel_at(t, i + 1, 0, lambda_nm);
}

float tex_eval(const Texture *tex, int i, const SurfacePoint *sp, float lambda_nm)
{
    const Texture *t = &tex[i];
    float s, tt, a;
    switch (t->type) {
    case TEX_CONSTANT:
        return tex_arg(tex, t, 0, sp, lambda_nm);
    case TEX_CHECKERBOARD:
        if (t->map == TEXMAP_POINT3D) {                 /* the 3-D checkerboard */
            Vec3 q = xf_point(&t->tex_from_world, sp->p);
            if (!(fabsf(q.x) < 1e9f && fabsf(q.y) < 1e9f && fabsf(q.z) < 1e9f))
                return tex_arg(tex, t, 0, sp, lambda_nm);
            return (((long)floorf(q.x) + (long)floorf(q.y) + (long)floorf(q.z)) & 1) == 0
                       ? tex_arg(tex, t, 0, sp, lambda_nm) : tex_arg(tex, t, 1, sp, lambda_nm);
        }
        tex_map(t, sp, &s, &tt);
        if (!(s > -1e9f && s < 1e9f && tt > -1e9f && tt < 1e9f)) return tex_arg(tex, t, 0, sp, lambda_nm);
        return (((long)floorf(s) + (long)floorf(tt)) & 1) == 0 ? tex_arg(tex, t, 0, sp, lambda_nm)
                                                              : tex_arg(tex, t, 1, sp, lambda_nm);
    case TEX_SCALE:
        a = t->scale_tex >= 0 ? tex_eval(tex, t->scale_tex, sp, lambda_nm) : t->arg_f[1];
        if (a == 0.0f) return 0.0f;                      /* pbrt-v4: skips the texture */
        return tex_arg(tex, t, 0, sp, lambda_nm) * a;
    case TEX_MIX:
        a = t->amount_tex >= 0 ? tex_eval(tex, t->amount_tex, sp, lambda_nm) : t->amount;
        return (1.0f - a) * tex_arg(tex, t, 0, sp, lambda_nm) + a * tex_arg(tex, t, 1, sp, lambda_nm);
    case TEX_DIRECTIONMIX:
        a = fabsf(v3_dot(sp->ng, t->dir));
        s = a != 0.0f ? tex_arg(tex, t, 0, sp, lambda_nm) : 0.0f;   /* pbrt-v4 skips a */
        tt = a != 1.0f ? tex_arg(tex, t, 1, sp, lambda_nm) : 0.0f;  /* weight of 0 */
        return a * s + (1.0f - a) * tt;
    case TEX_BILERP:                                    /* arguments v00, v01, v10, v11 */
        tex_map(t, sp, &s, &tt);
        return (1.0f - s) * (1.0f - tt) * tex_arg(tex, t, 0, sp, lambda_nm) +
               s * (1.0f - tt) * tex_arg(tex, t, 2, sp, lambda_nm) +
               (1.0f - s) * tt * tex_arg(tex, t, 1, sp, lambda_nm) +
               s * tt * tex_arg(tex, t, 3, sp, lambda_nm);
    case TEX_IMAGEMAP:
        tex_map(t, sp, &s, &tt);
        return image_lookup(t, s, tt, lambda_nm);
    case TEX_DOTS:
        tex_map(t, sp, &s, &tt);
        return tex_arg(tex, t, inside_dot(s, tt) ? 1 : 0, sp, lambda_nm);
    case TEX_MARBLE:
        return marble_eval(t, sp->p, lambda_nm);
    case TEX_FBM:
        return tex_fbm(xf_point(&t->tex_from_world, sp->p), t->omega, t->octaves);
    case TEX_WRINKLED:
        return tex_turbulence(xf_point(&t->tex_from_world, sp->p), t->omega, t->octaves);
    case TEX_WINDY: {
        Vec3 q = xf_point(&t->tex_from_world, sp->p);
        return fabsf(tex_fbm(v3_mul(q, 0.1f), 0.5f, 3)) * tex_fbm(q, 0.5f, 6);
    }
    }
    return 0.0f;
}

int tex_set_image(Texture *t, const Image *im, float scale, int invert, RgbTable *rgbt, Error *err)
{
    size_t n = (size_t)im->w * (size_t)im->h, i;
    RgbFitTable *fit = NULL;
    double prev[3] = { 0.0, 0.0, 0.0 }, m;
    free(t->texel);
    t->texel = (float *)malloc(sizeof(float) * n * (t->is_float ? 1 : 4));
    if (!t->is_float) fit = (RgbFitTable *)malloc(sizeof *fit);
    if (!t->texel || (!t->is_float && !fit)) {
        free(fit);
        free(t->texel);
        t->texel = NULL;
        error_set(err, t->file, t->line, "Texture \"imagemap\": out of memory for %d x %d texels",
                  im->w, im->h);
        return 0;
    }
    t->w = im->w;
    t->h = im->h;
    if (fit) spec_rgb_fit_table(fit, rgb_table_space(rgbt));   /* the image's space */
    for (i = 0; i < n; i++) {
        double rgb[3], c[3];
        int k;
        for (k = 0; k < 3; k++) {
            double v = (double)scale * im->rgb[3 * i + k];
            if (invert) v = 1.0 - v;
            rgb[k] = v > 0.0 ? v : 0.0;                  /* pbrt-v4: ClampZero */
        }
        if (t->is_float) {
            t->texel[i] = (float)((rgb[0] + rgb[1] + rgb[2]) / 3.0);
            continue;
        }
        if (!t->illuminant)
            for (k = 0; k < 3; k++) if (rgb[k] > 1.0) rgb[k] = 1.0;   /* a reflectance */
        if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
            /* grey: exactly flat, m sigmoid(0) = m / 2 */
            t->texel[4 * i] = (float)(2.0 * rgb[0]);
            t->texel[4 * i + 1] = t->texel[4 * i + 2] = t->texel[4 * i + 3] = 0.0f;
            continue;
        }
        m = 1.0;
        if (t->illuminant) {
            /* an illuminant (pbrt-v4's RGBIlluminantSpectrum): m = 2 max(rgb) and
               the fit of rgb / m, whose largest component is 1/2 */
            m = 2.0 * (rgb[0] > rgb[1] ? (rgb[0] > rgb[2] ? rgb[0] : rgb[2])
                                       : (rgb[1] > rgb[2] ? rgb[1] : rgb[2]));
            for (k = 0; k < 3; k++) rgb[k] /= m;
        }
        if (t->illuminant || !spec_rgb_coeffs_from(fit, rgb, prev, c)) spec_rgb_coeffs(rgbt, rgb, c);
        for (k = 0; k < 3; k++) prev[k] = c[k];
        t->texel[4 * i] = (float)m;
        for (k = 0; k < 3; k++) t->texel[4 * i + 1 + k] = (float)c[k];
    }
    free(fit);
    return 1;
}

void tex_free(Texture *t)
{
    free(t->texel);
    t->texel = NULL;
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   texture_from_params: the scene builder's (scene.c) Texture directive, one
   class read from its parameters (parser.h), with pbrt-v4's 2-D mappings.
   --------------------------------------------------------------------------- */
#include "parser.h"
#include <stdio.h>

/* Argument k of texture T from parameter `name` as a constant: a float, or a
   spectrum read as a reflectance (def when absent). */
static int texture_const(Parser *P, ParamList *pl, Texture *T, int k, const char *name, float def)
{
    T->arg_tex[k] = -1;
    if (T->is_float) {
        if (!get_float(P, pl, name, def, &T->arg_f[k])) return 0;
        if (!isfinite(T->arg_f[k]))
            return fail(P, T->file, T->line, "Texture: \"float %s\" is not finite", name);
        return 1;
    } else {
        Param *p = find_spectrum_param(pl, name);
        if (!p) { spec_const(&T->arg_s[k], def); return 1; }
        if (p->type == PT_RGB && p->n_num == 3 && (p->num[0] != p->num[1] || p->num[1] != p->num[2]))
            T->rgb_arg = 1;
        return param_spectrum(P, p, SPEC_ALBEDO, &T->arg_s[k], NULL);
    }
}

/* Argument k of texture T from parameter `name`: a texture, or a constant (def
   when absent). */
static int texture_arg(Parser *P, ParamList *pl, Texture *T, int k, const char *name, float def)
{
    Param *pt = param_find(pl, PT_TEXTURE, name);
    if (pt) {
        T->arg_tex[k] = texture_lookup(P, pt, T->is_float);
        return T->arg_tex[k] >= 0;
    }
    return texture_const(P, pl, T, k, name, def);
}

/* The texture's frame: the inverse of the CTM at the directive (pbrt-v4's
   textureFromRender). */
static void texture_frame(Parser *P, Texture *T)
{
    int a, b;
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++) {
            T->tex_from_world.m[a][b] = P->gs.ctm.inv[a][b];
            T->tex_from_world.inv[a][b] = P->gs.ctm.m[a][b];
        }
}

/* The 2-D mapping parameters (pbrt-v4 TextureMapping2D::Create). */
static int texture_mapping(Parser *P, ParamList *pl, Texture *T)
{
    const char *map = NULL;
    double v1[3] = { 1, 0, 0 }, v2[3] = { 0, 1, 0 };
    Param *pv;
    int k;
    if (!get_string(P, pl, "mapping", &map)) return 0;
    if (!get_float(P, pl, "uscale", 1.0f, &T->su) || !get_float(P, pl, "vscale", 1.0f, &T->sv) ||
        !get_float(P, pl, "udelta", 0.0f, &T->du) || !get_float(P, pl, "vdelta", 0.0f, &T->dv))
        return 0;
    if (!isfinite(T->su) || !isfinite(T->sv) || !isfinite(T->du) || !isfinite(T->dv))
        return fail(P, T->file, T->line, "Texture: uscale, vscale, udelta, vdelta must be finite");
    if (!map || !strcmp(map, "uv")) T->map = TEXMAP_UV;
    else if (!strcmp(map, "spherical")) T->map = TEXMAP_SPHERICAL;
    else if (!strcmp(map, "cylindrical")) T->map = TEXMAP_CYLINDRICAL;
    else if (!strcmp(map, "planar")) T->map = TEXMAP_PLANAR;
    else return fail(P, T->file, T->line, "Texture: unknown mapping \"%s\" (pbrt-v4: uv, "
                     "spherical, cylindrical, planar)", map);
    for (k = 0; k < 2; k++) {
        double *v = k ? v2 : v1;
        pv = param_find(pl, PT_VECTOR3, k ? "v2" : "v1");
        if (pv) {
            int a;
            if (pv->n_num != 3)
                return fail(P, pv->file, pv->line, "\"vector3 %s\": expected 3 values", pv->name);
            for (a = 0; a < 3; a++) {
                if (!isfinite(pv->num[a]))
                    return fail(P, pv->file, pv->line, "\"vector3 %s\": not finite", pv->name);
                v[a] = pv->num[a];
            }
        }
    }
    T->vs = v3((float)v1[0], (float)v1[1], (float)v1[2]);
    T->vt = v3((float)v2[0], (float)v2[1], (float)v2[2]);
    texture_frame(P, T);
    return 1;
}

/* An imagemap's image: PNG, PFM, or EXR (the .pfm of the same name beside it, if any). */
static int texture_image(Parser *P, ParamList *pl, Texture *T, const char *name)
{
    const char *fn = NULL, *wrap = NULL, *filter = NULL, *enc = NULL;
    char path[PATH_CAP], alt[PATH_CAP];
    float scale;
    int invert, ok;
    Image im;
    Error ierr;
    FILE *f;
    if (!get_string(P, pl, "filename", &fn) || !get_string(P, pl, "wrap", &wrap) ||
        !get_string(P, pl, "filter", &filter) || !get_string(P, pl, "encoding", &enc) ||
        !get_float(P, pl, "scale", 1.0f, &scale) || !get_bool(P, pl, "invert", 0, &invert))
        return 0;
    (void)param_find(pl, PT_FLOAT, "maxanisotropy");   /* (only for the "ewa" filter) */
    if (!fn) return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": \"string filename\" is required", name);
    if (!isfinite(scale)) return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": scale is not finite", name);
    if (!wrap || !strcmp(wrap, "repeat")) T->wrap = TEXWRAP_REPEAT;
    else if (!strcmp(wrap, "black")) T->wrap = TEXWRAP_BLACK;
    else if (!strcmp(wrap, "clamp")) T->wrap = TEXWRAP_CLAMP;
    else return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": unknown wrap \"%s\" (repeat, "
                     "black, clamp)", name, wrap);
    T->nearest = filter && !strcmp(filter, "point");
    if (filter && strcmp(filter, "bilinear") != 0 && strcmp(filter, "point") != 0)
        fprintf(stderr, "%s:%d: note: Texture \"imagemap\": filter \"%s\" is read as "
                "\"bilinear\" (specnee has no MIP maps)\n", T->file, T->line, filter);
    resolve_path(P, T->file, fn, path, sizeof path);
    if (ends_with_ci(fn, ".exr")) {
        snprintf(alt, sizeof alt, "%.*s.pfm", (int)strlen(path) - 4, path);
        f = fopen(alt, "rb");
        if (!f) {                              /* no .pfm beside it: the EXR (exr.c) */
            RgbTable *table;
            int space;
            if (!read_exr_image(path, "Texture \"imagemap\"", T->file, T->line, &im, &space, &ierr))
                return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": %s", name, ierr.msg);
            /* its RGB fitted in the space of its chromaticities (pbrt-v4's
               SpectrumImageTexture: RGBAlbedoSpectrum(*image colour space, rgb)) */
            if (!(table = rgb_space_table(P, space))) { img_free(&im); return oom(P, T->file, T->line); }
            ok = tex_set_image(T, &im, scale, invert, table, P->err);
            img_free(&im);
            return ok;
        }
        fclose(f);
        fprintf(stderr, "%s:%d: note: Texture \"imagemap\": reading %s for \"%s\"\n", T->file,
                T->line, alt, fn);
        snprintf(path, sizeof path, "%s", alt);
    } else if (ends_with_ci(fn, ".png")) {
        /* 8- and 16-bit PNG (png.c): sRGB-encoded unless "encoding" says "linear",
           as pbrt-v4 reads them; "gamma g" is refused by name */
        int linear = 0;
        if (enc && !strcmp(enc, "linear")) linear = 1;
        else if (enc && strcmp(enc, "sRGB") != 0)
            return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": encoding \"%s\" is valid "
                        "pbrt-v4 but not in the specnee subset (sRGB, linear)", name, enc);
        if (!png_read(&im, path, linear, &ierr))
            return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": %s", name, ierr.msg);
        ok = tex_set_image(T, &im, scale, invert, rgb_srgb_table(P), P->err);
        img_free(&im);
        return ok;
    } else if (!ends_with_ci(fn, ".pfm")) {
        return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": \"%s\": specnee reads image "
                    "textures as PNG or PFM (convert others with ImageMagick's `convert`)", name, fn);
    }
    (void)enc;                                 /* PFM holds linear values */
    if (!pfm_read(&im, path, &ierr))
        return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": %s", name, ierr.msg);
    ok = tex_set_image(T, &im, scale, invert, rgb_srgb_table(P), P->err);   /* a PFM's: sRGB */
    img_free(&im);
    return ok;
}

/* What each class reads (the parameters' "type name" list, by TexType). */
static const char *const texture_reads[] = {
    /* TEX_CONSTANT */ "spectrum value, rgb value, float value, texture value",
    /* TEX_CHECKERBOARD */ "integer dimension, string mapping, float uscale, float vscale, "
        "float udelta, float vdelta, vector3 v1, vector3 v2, spectrum tex1, rgb tex1, "
        "float tex1, texture tex1, spectrum tex2, rgb tex2, float tex2, texture tex2",
    /* TEX_SCALE */ "spectrum tex, rgb tex, float tex, texture tex, float scale, texture scale",
    /* TEX_MIX */ "spectrum tex1, rgb tex1, float tex1, texture tex1, spectrum tex2, rgb tex2, "
        "float tex2, texture tex2, float amount, texture amount",
    /* TEX_IMAGEMAP */ "string filename, string wrap, string filter, string encoding, "
        "float scale, bool invert, float maxanisotropy, string mapping, float uscale, "
        "float vscale, float udelta, float vdelta, vector3 v1, vector3 v2",
    /* TEX_DOTS */ "string mapping, float uscale, float vscale, float udelta, float vdelta, "
        "vector3 v1, vector3 v2, spectrum inside, rgb inside, float inside, texture inside, "
        "spectrum outside, rgb outside, float outside, texture outside",
    /* TEX_MARBLE */ "integer octaves, float roughness, float scale, float variation",
    /* TEX_FBM */ "integer octaves, float roughness",
    /* TEX_WRINKLED */ "integer octaves, float roughness",
    /* TEX_WINDY */ "",
    /* TEX_DIRECTIONMIX */ "spectrum tex1, rgb tex1, float tex1, texture tex1, spectrum tex2, "
        "rgb tex2, float tex2, texture tex2, vector3 dir",
    /* TEX_BILERP */ "string mapping, float uscale, float vscale, float udelta, float vdelta, "
        "vector3 v1, vector3 v2, spectrum v00, rgb v00, float v00, spectrum v01, rgb v01, "
        "float v01, spectrum v10, rgb v10, float v10, spectrum v11, rgb v11, float v11"
};

/* pbrt-v4 DirectionMixTexture, float and spectrum (section 2): tex1 (0), tex2
   (1) and "dir" (0 1 0), carried to world space by the CTM at the directive (a
   vector: pbrt-v4's renderFromTexture), then normalised. */
static int texture_directionmix(Parser *P, ParamList *pl, Texture *T)
{
    Param *pv = param_find(pl, PT_VECTOR3, "dir");
    Vec3 d = v3(0.0f, 1.0f, 0.0f);
    float len;
    T->type = TEX_DIRECTIONMIX;
    if (!texture_arg(P, pl, T, 0, "tex1", 0.0f) || !texture_arg(P, pl, T, 1, "tex2", 1.0f))
        return 0;
    if (pv) {
        if (pv->n_num != 3)
            return fail(P, pv->file, pv->line, "\"vector3 dir\": expected 3 values");
        d = v3((float)pv->num[0], (float)pv->num[1], (float)pv->num[2]);
    }
    d = xf_vector(&P->gs.ctm, d);
    len = v3_len(d);
    if (!(len > 0.0f && len < 1e30f))
        return fail(P, pv ? pv->file : T->file, pv ? pv->line : T->line, "Texture "
                    "\"directionmix\": \"vector3 dir\" (%g %g %g in world space) is not a "
                    "direction", d.x, d.y, d.z);
    T->dir = v3_mul(d, 1.0f / len);
    return 1;
}

/* pbrt-v4 FloatBilerpTexture, SpectrumBilerpTexture (section 2): the 2-D mapping
   and the corners v00 (0), v01 (1), v10 (0), v11 (1) as arguments 0..3, numbers
   or spectra; pbrt-v4 reads no texture there. */
static int texture_bilerp(Parser *P, ParamList *pl, Texture *T)
{
    static const char *const corner[4] = { "v00", "v01", "v10", "v11" };
    int k;
    T->type = TEX_BILERP;
    for (k = 0; k < 4; k++) {
        Param *pt = param_find(pl, PT_TEXTURE, corner[k]);
        if (pt != NULL)
            return fail(P, pt->file, pt->line, "Texture \"bilerp\": \"texture %s\": pbrt-v4's "
                        "bilerp corners are values, not textures", corner[k]);
    }
    if (!texture_mapping(P, pl, T)) return 0;
    for (k = 0; k < 4; k++)
        if (!texture_const(P, pl, T, k, corner[k], (float)(k & 1))) return 0;
    return 1;
}

/* Texture T of class `cls`, the texture named `name` (T's kind, float or
   spectrum, its file and line already set): pbrt-v4's per-class Create. */
int texture_from_params(Parser *P, ParamList *pl, const char *name, const char *cls,
                        Texture *T)
{
    static const char *const pbrt_classes[] = {
        "ptex", NULL
    };
    char what[96];
    int k, ok = 0, dim = 2;
    for (k = 0; k < TEX_ARGS; k++) T->arg_tex[k] = -1;     /* no texture arguments yet */
    if (!strcmp(cls, "constant")) {
        T->type = TEX_CONSTANT;
        ok = texture_arg(P, pl, T, 0, "value", 1.0f);
    } else if (!strcmp(cls, "checkerboard")) {
        T->type = TEX_CHECKERBOARD;
        ok = get_int(P, pl, "dimension", 2, &dim, NULL);
        if (ok && dim != 2 && dim != 3)
            ok = fail(P, T->file, T->line, "Texture \"checkerboard\": dimension %d: pbrt-v4 "
                      "has the 2-D and the 3-D checkerboard", dim);
        if (ok && dim == 3) {                  /* TextureMapping3D: the texture's frame */
            T->map = TEXMAP_POINT3D;
            texture_frame(P, T);   /* 3-D checkerboard */
        }
        ok = ok && (dim == 3 || texture_mapping(P, pl, T)) &&
             texture_arg(P, pl, T, 0, "tex1", 1.0f) && texture_arg(P, pl, T, 1, "tex2", 0.0f);
    } else if (!strcmp(cls, "scale")) {
        Param *ps = param_find(pl, PT_TEXTURE, "scale");
        T->type = TEX_SCALE;
        ok = texture_arg(P, pl, T, 0, "tex", 1.0f);
        if (ok && ps) {
            T->scale_tex = texture_lookup(P, ps, 1);
            ok = T->scale_tex >= 0;
        } else if (ok) {
            ok = get_float(P, pl, "scale", 1.0f, &T->arg_f[1]);
            if (ok && !isfinite(T->arg_f[1])) ok = fail(P, T->file, T->line, "Texture \"scale\": scale is not finite");
        }
    } else if (!strcmp(cls, "mix")) {
        Param *pa = param_find(pl, PT_TEXTURE, "amount");
        T->type = TEX_MIX;
        ok = texture_arg(P, pl, T, 0, "tex1", 0.0f) && texture_arg(P, pl, T, 1, "tex2", 1.0f);
        if (ok && pa) {
            T->amount_tex = texture_lookup(P, pa, 1);
            ok = T->amount_tex >= 0;
        } else if (ok) {
            ok = get_float(P, pl, "amount", 0.5f, &T->amount);
            if (ok && !isfinite(T->amount)) ok = fail(P, T->file, T->line, "Texture \"mix\": amount is not finite");
        }
    } else if (!strcmp(cls, "directionmix")) {
        ok = texture_directionmix(P, pl, T);
    } else if (!strcmp(cls, "bilerp")) {
        ok = texture_bilerp(P, pl, T);
    } else if (!strcmp(cls, "imagemap")) {
        T->type = TEX_IMAGEMAP;
        ok = texture_mapping(P, pl, T) && texture_image(P, pl, T, name);
    } else if (!strcmp(cls, "dots")) {
        /* pbrt-v4 DotsTexture: "outside" (0) in a dot, "inside" (1) elsewhere (sic:
           pbrt-v4's Create passes "inside" as the constructor's outsideDot, since
           pbrt-v3; section 4) */
        T->type = TEX_DOTS;
        ok = texture_mapping(P, pl, T) && texture_arg(P, pl, T, 0, "inside", 1.0f) &&
             texture_arg(P, pl, T, 1, "outside", 0.0f);
    } else if (!strcmp(cls, "marble")) {
        /* pbrt-v4 MarbleTexture (spectrum only): a 3-D texture in the frame of the
           CTM at the directive (TextureMapping3D, which reads no parameters) */
        T->type = TEX_MARBLE;
        if (T->is_float) {
            ok = fail(P, T->file, T->line, "Texture \"%s\": \"marble\" is a spectrum texture "
                      "(pbrt-v4 has no float marble)", name);
            return 0;
        }
        ok = get_int(P, pl, "octaves", 8, &T->octaves, NULL) &&
             get_float(P, pl, "roughness", 0.5f, &T->omega) &&
             get_float(P, pl, "scale", 1.0f, &T->mscale) &&
             get_float(P, pl, "variation", 0.2f, &T->variation);
        if (ok && !(isfinite(T->omega) && isfinite(T->mscale) && isfinite(T->variation)))
            ok = fail(P, T->file, T->line, "Texture \"marble\": roughness, scale and variation "
                      "must be finite");
        if (ok && !(T->octaves >= 0 && T->octaves <= 64))
            ok = fail(P, T->file, T->line, "Texture \"marble\": octaves %d must be within [0, 64]",
                      T->octaves);
        if (ok) {
            texture_frame(P, T);   /* marble */
            ok = tex_marble_init(T, rgb_srgb_table(P), P->err);
        }
    } else if (!strcmp(cls, "fbm") || !strcmp(cls, "wrinkled") ||
               !strcmp(cls, "windy")) {
        /* pbrt-v4 FBmTexture, WrinkledTexture, WindyTexture (float only): 3-D noise
           in the frame of the CTM at the directive (section 4) */
        T->type = cls[0] == 'f' ? TEX_FBM : cls[1] == 'r' ? TEX_WRINKLED : TEX_WINDY;
        if (!T->is_float) {
            ok = fail(P, T->file, T->line, "Texture \"%s\": \"%s\" is a float texture "
                      "(pbrt-v4 has no spectrum %s)", name, cls, cls);
            return 0;
        }
        ok = 1;
        if (T->type != TEX_WINDY) {
            ok = get_int(P, pl, "octaves", 8, &T->octaves, NULL) &&
                 get_float(P, pl, "roughness", 0.5f, &T->omega);
            if (ok && !isfinite(T->omega))
                ok = fail(P, T->file, T->line, "Texture \"%s\": roughness must be finite", cls);
            if (ok && !(T->octaves >= 0 && T->octaves <= 64))
                ok = fail(P, T->file, T->line, "Texture \"%s\": octaves %d must be within [0, 64]",
                          cls, T->octaves);
        }
        if (ok) texture_frame(P, T);
    } else {
        for (k = 0; pbrt_classes[k]; k++)
            if (!strcmp(cls, pbrt_classes[k])) break;
        ok = fail(P, T->file, T->line, pbrt_classes[k] ? "Texture \"%s\": class \"%s\" is valid "
                  "pbrt-v4 but not in the specnee subset" : "Texture \"%s\": unknown class \"%s\"",
                  name, cls);
    }
    if (!ok) return 0;
    snprintf(what, sizeof what, "Texture \"%s\"", cls);
    if (T->map == TEXMAP_POINT3D)              /* no 2-D mapping parameters */
        return params_check_unused(P, pl, what, "integer dimension, spectrum tex1, rgb tex1, "
                                   "float tex1, texture tex1, spectrum tex2, rgb tex2, "
                                   "float tex2, texture tex2", NULL);
    return params_check_unused(P, pl, what, texture_reads[T->type], NULL);
}
