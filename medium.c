/* medium.c - participating media: homogeneous, uniformgrid, rgbgrid and cloud media, their
   coefficients, the Henyey-Greenstein phase function, pbrt-v4's named presets,
   which medium a ray is in after it leaves a surface, and the free flight through
   a grid (the majorant grid, its DDA, delta tracking).

   Exported (specnee.h section 6b): medium_sigma_t, medium_sigma_s, medium_sigma_a,
   hg_phase, hg_sample, medium_preset, medium_after, medium_grid_lookup,
   medium_point, medium_track, medium_free.

   THE MODEL (pbrt-v4 MakeNamedMedium "homogeneous"; THEORY §12 derives the
   estimator that uses it, docs/media.md summarises the format and the
   measurements).  Equation numbers are THEORY's.  Between surfaces a ray travels through at most one
   medium, with coefficients per unit length
       sigma_a(lambda)  absorption,   sigma_s(lambda)  scattering,
       sigma_t = sigma_a + sigma_s    extinction,
   the same at every point.  Over a distance t the light keeps the fraction
       Tr(t) = exp(-sigma_t t)                                        (15)
   (Beer-Lambert).  At a collision a fraction sigma_s / sigma_t of the light is
   scattered into the direction wi with the phase function p_HG(d, wi) (a density
   over the sphere of directions), and the medium itself emits sigma_a Le per unit
   length (pbrt-v4's volpath adds the emission weighted by sigma_a).

   HENYEY-GREENSTEIN (Henyey and Greenstein 1941).  With c the cosine between the
   direction d the light travelled and wi,
       p_HG(c) = (1 - g^2) / (4 pi (1 + g^2 - 2 g c)^(3/2)),          (18a)
   g in (-1, 1) the mean cosine: g > 0 scatters forward, g = 0 is isotropic.  Its
   CDF over c inverts in closed form (integrate (18a) times 2 pi over c): for a
   uniform u,
       c = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g),       (18b)
   c = 1 - 2u when g is 0; the azimuth is uniform.  So the sampled direction has
   exactly the density (18a), and the pdf the MIS weights need is (18a) itself.

   WHICH MEDIUM.  pbrt-v4's rule (Interaction::GetMedium): a shape whose
   MediumInterface has different inside and outside media is a transition; a ray
   that leaves it along w is in the outside medium when w points to the side of
   the shape's oriented normal ng (w . ng > 0), else in the inside one.  Any other
   surface leaves the ray in the medium it came through (a diffuse floor in fog
   sends its rays back into the fog).  The camera is in the outside medium of the
   MediumInterface in force at the Camera directive.  A surface with Material
   "interface" is no surface at all: rays cross it (path.c), shadow rays too.

   UNIFORMGRID (pbrt-v4's GridMedium; THEORY §13).  The spectra are scaled by a
   density d(x) interpolated trilinearly from nx ny nz samples at the centres of
   the cells of the bounds p0..p1 (0 beyond them), in the frame of the CTM at the
   MakeNamedMedium.  A majorant grid of MAJORANT_RES^3 cells holds each cell's
   largest reachable sample d_max, so sigma_bar(lambda) = d_max sigma_t(lambda)
   bounds sigma_t(x, lambda) in the cell.  medium_track walks a ray through the
   cells with a 3-D DDA and draws tentative collisions at the hero's majorant:
   an optical depth tau = -ln(1 - u) (at the previous collision: a fresh u) is
   spent cell by cell, sigma_bar_0 per unit length, and the collision lies where
   it runs out, t = t_cell + tau_left / sigma_bar_0 (THEORY §13), handing each to the caller (path.c decides real or null and weights the lanes,
   THEORY (21)-(25)) with the ratios Tbar_j / Tbar_0 = exp(-(sigma_bar_j -
   sigma_bar_0) t) since the previous one.  The emission there is sigma_a Le times
   the Lescale grid, or a blackbody of the temperature grid (medium_point).

   RGBGRID (pbrt-v4's RGBGridMedium; docs/media.md).  sigma_a, sigma_s and Le are
   grids of rgb triples; each sample is turned into a spectrum once, at load (four
   floats: 2 max(rgb) and the sigmoid coefficients of rgb / (2 max(rgb))), and a
   lookup blends the eight samples' values at each wavelength.  Its majorant grid
   holds sigma_bar itself, the same for every wavelength: scale (max sigma_a + max
   sigma_s) over the cell's samples and over lambda (THEORY §13).

   CLOUD (pbrt-v4's CloudMedium).  The uniformgrid's model with a procedural
   density d(x) in [0, 1] (medium_cloud_density, texture.c's Perlin noise) instead of
   a grid, and a majorant grid of 1 (pbrt-v4's one homogeneous majorant).

   The last section builds a medium from a MakeNamedMedium's parameters for the
   scene builder (medium_from_params, parser.h). */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

float medium_sigma_a(const Medium *m, float lambda_nm) { return spec_eval(&m->sigma_a, lambda_nm); }
float medium_sigma_s(const Medium *m, float lambda_nm) { return spec_eval(&m->sigma_s, lambda_nm); }
float medium_sigma_t(const Medium *m, float lambda_nm)
{
    return spec_eval(&m->sigma_a, lambda_nm) + spec_eval(&m->sigma_s, lambda_nm);
}

/* (18a), with the denominator kept away from 0 (g -> +-1) */
float hg_phase(float g, float cos_d_wi)
{
    float d = 1.0f + g * g - 2.0f * g * cos_d_wi;
    return (1.0f - g * g) / (4.0f * PI_F * d * sqrtf(fmaxf(d, 1e-12f)));
}

/* (18b), then wi = c d + sqrt(1 - c^2) (cos phi s + sin phi t) in a frame around d.
   (layered.c's coat medium samples with it too.) */
Vec3 hg_sample(float g, Vec3 d, float u1, float u2, float *pdf)
{
    float c, st, phi;
    Frame fr = frame_from_normal(d);
    Vec3 wi;
    if (fabsf(g) < 1e-3f) c = 1.0f - 2.0f * u1;
    else {
        float q = (1.0f - g * g) / (1.0f - g + 2.0f * g * u1);
        c = (1.0f + g * g - q * q) / (2.0f * g);
    }
    c = fminf(1.0f, fmaxf(-1.0f, c));
    st = sqrtf(fmaxf(0.0f, 1.0f - c * c));
    phi = 2.0f * PI_F * u2;
    wi = v3_norm(frame_to_world(&fr, v3(st * cosf(phi), st * sinf(phi), c)));
    *pdf = hg_phase(g, v3_dot(d, wi));
    return wi;
}

/* pbrt-v4's preset names (media.cpp, GetMediumScatteringProperties): measured
   reduced scattering sigma_s' and absorption sigma_a in mm^-1, as RGB.  Data from
   Jensen, Marschner, Levoy, Hanrahan, "A Practical Model for Subsurface Light
   Transport", SIGGRAPH 2001 (Table 2: Apple ... Wholemilk), and Narasimhan, Gupta,
   Donner, Ramamoorthi, Nayar, Jensen, "Acquiring Scattering Properties of
   Participating Media by Dilution", SIGGRAPH 2006 (Lowfat Milk ... Pacific Ocean
   Surface Water), with the numbers pbrt-v4 tabulates.  pbrt-v4 uses sigma_s' as
   sigma_s, and so does specnee (a file's "float g" still applies). */
typedef struct { const char *name; float ss[3], sa[3]; } Preset;
static const Preset presets[] = {
    { "Apple", { 2.29f, 2.39f, 1.97f }, { 0.0030f, 0.0034f, 0.046f } },
    { "Chicken1", { 0.15f, 0.21f, 0.38f }, { 0.015f, 0.077f, 0.19f } },
    { "Chicken2", { 0.19f, 0.25f, 0.32f }, { 0.018f, 0.088f, 0.20f } },
    { "Cream", { 7.38f, 5.47f, 3.15f }, { 0.0002f, 0.0028f, 0.0163f } },
    { "Ketchup", { 0.18f, 0.07f, 0.03f }, { 0.061f, 0.97f, 1.45f } },
    { "Marble", { 2.19f, 2.62f, 3.00f }, { 0.0021f, 0.0041f, 0.0071f } },
    { "Potato", { 0.68f, 0.70f, 0.55f }, { 0.0024f, 0.0090f, 0.12f } },
    { "Skimmilk", { 0.70f, 1.22f, 1.90f }, { 0.0014f, 0.0025f, 0.0142f } },
    { "Skin1", { 0.74f, 0.88f, 1.01f }, { 0.032f, 0.17f, 0.48f } },
    { "Skin2", { 1.09f, 1.59f, 1.79f }, { 0.013f, 0.070f, 0.145f } },
    { "Spectralon", { 11.6f, 20.4f, 14.9f }, { 0.00f, 0.00f, 0.00f } },
    { "Wholemilk", { 2.55f, 3.21f, 3.77f }, { 0.0011f, 0.0024f, 0.014f } },
    { "Lowfat Milk", { 0.89187f, 1.5136f, 2.532f }, { 0.002875f, 0.00575f, 0.0115f } },
    { "Reduced Milk", { 2.4858f, 3.1669f, 4.5214f }, { 0.0025556f, 0.0051111f, 0.012778f } },
    { "Regular Milk", { 4.5513f, 5.8294f, 7.136f }, { 0.0015333f, 0.0046f, 0.019933f } },
    { "Espresso", { 0.72378f, 0.84557f, 1.0247f }, { 4.7984f, 6.5751f, 8.8493f } },
    { "Mint Mocha Coffee", { 0.31602f, 0.38538f, 0.48131f }, { 3.772f, 5.8228f, 7.82f } },
    { "Lowfat Soy Milk", { 0.30576f, 0.34233f, 0.61664f }, { 0.0014375f, 0.0071875f, 0.035937f } },
    { "Regular Soy Milk", { 0.59223f, 0.73866f, 1.4693f }, { 0.0019167f, 0.0095833f, 0.065167f } },
    { "Lowfat Chocolate Milk", { 0.64925f, 0.83916f, 1.1057f }, { 0.0115f, 0.0368f, 0.1564f } },
    { "Regular Chocolate Milk", { 1.4585f, 2.1289f, 2.9527f }, { 0.010063f, 0.043125f, 0.14375f } },
    { "Coke", { 8.9053e-05f, 8.372e-05f, 0.0f }, { 0.10014f, 0.16503f, 0.2468f } },
    { "Pepsi", { 6.1697e-05f, 4.2564e-05f, 0.0f }, { 0.091641f, 0.14158f, 0.20729f } },
    { "Sprite", { 6.0306e-06f, 6.4139e-06f, 6.5504e-06f }, { 0.001886f, 0.0018308f, 0.0020025f } },
    { "Gatorade", { 0.0024574f, 0.003007f, 0.0037325f }, { 0.024794f, 0.019289f, 0.008878f } },
    { "Chardonnay", { 1.7982e-05f, 1.3758e-05f, 1.2023e-05f }, { 0.010782f, 0.011855f, 0.023997f } },
    { "White Zinfandel", { 1.7501e-05f, 1.9069e-05f, 1.288e-05f }, { 0.012072f, 0.016184f, 0.019843f } },
    { "Merlot", { 2.1129e-05f, 0.0f, 0.0f }, { 0.11632f, 0.25191f, 0.29434f } },
    { "Budweiser Beer", { 2.4356e-05f, 2.4079e-05f, 1.0564e-05f }, { 0.011492f, 0.024911f, 0.057786f } },
    { "Coors Light Beer", { 5.0922e-05f, 4.301e-05f, 0.0f }, { 0.006164f, 0.013984f, 0.034983f } },
    { "Clorox", { 0.0024035f, 0.0031373f, 0.003991f }, { 0.0033542f, 0.014892f, 0.026297f } },
    { "Apple Juice", { 0.00013612f, 0.00015836f, 0.000227f }, { 0.012957f, 0.023741f, 0.052184f } },
    { "Cranberry Juice", { 0.00010402f, 0.00011646f, 7.8139e-05f }, { 0.039437f, 0.094223f, 0.12426f } },
    { "Grape Juice", { 5.382e-05f, 0.0f, 0.0f }, { 0.10404f, 0.23958f, 0.29325f } },
    { "Ruby Grapefruit Juice", { 0.011002f, 0.010927f, 0.011036f }, { 0.085867f, 0.18314f, 0.25262f } },
    { "White Grapefruit Juice", { 0.22826f, 0.23998f, 0.32748f }, { 0.0138f, 0.018831f, 0.056781f } },
    { "Shampoo", { 0.0007176f, 0.0008303f, 0.0009016f }, { 0.014107f, 0.045693f, 0.061717f } },
    { "Strawberry Shampoo", { 0.00015671f, 0.00015947f, 1.518e-05f }, { 0.01449f, 0.05796f, 0.075823f } },
    { "Head & Shoulders Shampoo", { 0.023805f, 0.028804f, 0.034306f }, { 0.084621f, 0.15688f, 0.20365f } },
    { "Lemon Tea Powder", { 0.040224f, 0.045264f, 0.051081f }, { 2.4288f, 4.5757f, 7.2127f } },
    { "Orange Powder", { 0.00015617f, 0.00017482f, 0.0001762f }, { 0.001449f, 0.003441f, 0.007863f } },
    { "Pink Lemonade Powder", { 0.00012103f, 0.00013073f, 0.00012528f }, { 0.001165f, 0.002366f, 0.003195f } },
    { "Cappuccino Powder", { 1.8436f, 2.5851f, 2.1662f }, { 35.844f, 49.547f, 61.084f } },
    { "Salt Powder", { 0.027333f, 0.032451f, 0.031979f }, { 0.28415f, 0.3257f, 0.34148f } },
    { "Sugar Powder", { 0.00022272f, 0.00025513f, 0.000271f }, { 0.012638f, 0.031051f, 0.050124f } },
    { "Suisse Mocha Powder", { 2.7979f, 3.5452f, 4.3365f }, { 17.502f, 27.004f, 35.433f } },
    { "Pacific Ocean Surface Water", { 0.0001764f, 0.00032095f, 0.00019617f }, { 0.031845f, 0.031324f, 0.030147f } }
};

int medium_preset(const char *name, float sigma_a[3], float sigma_s[3])
{
    size_t i;
    int k;
    for (i = 0; i < sizeof presets / sizeof presets[0]; i++)
        if (!strcmp(presets[i].name, name)) {
            for (k = 0; k < 3; k++) { sigma_a[k] = presets[i].sa[k]; sigma_s[k] = presets[i].ss[k]; }
            return 1;
        }
    return 0;
}

int medium_after(const Scene *s, int shape, int cur, Vec3 w, Vec3 ng)
{
    const Shape *sh = &s->shapes[shape];
    if (sh->medium_inside == sh->medium_outside) return cur;
    return v3_dot(w, ng) > 0.0f ? sh->medium_outside : sh->medium_inside;
}

/* ---------------------------------------------------------------------------
   ---- uniformgrid: lookups, the majorant grid, delta tracking (THEORY §13)
   --------------------------------------------------------------------------- */

/* Sample (x, y, z) of g; 0 beyond the outermost samples (pbrt-v4's SampledGrid). */
static double grid_at(const MediumGrid *g, int x, int y, int z)
{
    if (x < 0 || y < 0 || z < 0 || x >= g->nx || y >= g->ny || z >= g->nz) return 0.0;
    return g->v[((size_t)z * (size_t)g->ny + (size_t)y) * (size_t)g->nx + (size_t)x];
}

static double lerp_d(double f, double a, double b) { return (1.0 - f) * a + f * b; }

/* The corner sample i[] and the fractions f[] of a trilinear lookup at u in the
   unit cube: sample i sits at (i + 1/2) / n. */
static void grid_corner(const MediumGrid *g, Vec3 u, int i[3], double f[3])
{
    double s;
    int k;
    const int n[3] = { g->nx, g->ny, g->nz };
    const float uu[3] = { u.x, u.y, u.z };
    for (k = 0; k < 3; k++) {
        s = (double)uu[k] * n[k] - 0.5;
        if (!(s > -1.0)) s = -1.0;                /* beyond the grid: reads zeros */
        if (!(s < (double)n[k])) s = n[k];
        i[k] = (int)floor(s);
        f[k] = s - i[k];
    }
}

/* The trilinear blend of the eight values v[x + 2y + 4z] around a corner. */
static double blend8(const double v[8], const double f[3])
{
    return lerp_d(f[2], lerp_d(f[1], lerp_d(f[0], v[0], v[1]), lerp_d(f[0], v[2], v[3])),
                        lerp_d(f[1], lerp_d(f[0], v[4], v[5]), lerp_d(f[0], v[6], v[7])));
}

double medium_grid_lookup(const MediumGrid *g, Vec3 u)
{
    double f[3], v[8];
    int i[3], c;
    grid_corner(g, u, i, f);
    for (c = 0; c < 8; c++) v[c] = grid_at(g, i[0] + (c & 1), i[1] + ((c >> 1) & 1), i[2] + (c >> 2));
    return blend8(v, f);
}

/* The eight rgbgrid samples around unit-cube point u (NULL: beyond the grid,
   which reads 0) and the fractions of their trilinear blend. */
typedef struct {
    const float *c[8];
    double f[3];
} RgbCorners;

static void rgb_corners(const MediumGrid *g, Vec3 u, RgbCorners *rc)
{
    int i[3], k;
    grid_corner(g, u, i, rc->f);
    for (k = 0; k < 8; k++) {
        int x = i[0] + (k & 1), y = i[1] + ((k >> 1) & 1), z = i[2] + (k >> 2);
        rc->c[k] = x < 0 || y < 0 || z < 0 || x >= g->nx || y >= g->ny || z >= g->nz ? NULL
                 : g->v + 4 * (((size_t)z * (size_t)g->ny + (size_t)y) * (size_t)g->nx + (size_t)x);
    }
}

/* The blend at lambda of the samples' spectra, 2 max(rgb) x sigmoid (pbrt-v4's
   SampledGrid::Lookup with a conversion).  A sample of 2 max(rgb) = 0 is that
   zero itself: the sigmoid lies in [0, 1], so the product is the same. */
static double rgb_blend(const RgbCorners *rc, float lambda)
{
    double v[8];
    int k;
    for (k = 0; k < 8; k++) {
        const float *c = rc->c[k];
        v[k] = !c ? 0.0 : c[0] == 0.0f ? (double)c[0] : (double)c[0] * spec_sigmoid_eval(c + 1, lambda);
    }
    return blend8(v, rc->f);
}

/* The samples a lookup in [lo, hi] (unit-cube coordinates, one axis, n samples)
   can read: floor(lo n - 1/2) .. floor(hi n - 1/2) + 1, clamped to the grid. */
static void cell_samples(double lo, double hi, int n, int *i0, int *i1)
{
    *i0 = (int)floor(lo * n - 0.5);
    *i1 = (int)floor(hi * n - 0.5) + 1;
    if (*i0 < 0) *i0 = 0;
    if (*i1 > n - 1) *i1 = n - 1;
}

/* The largest val(g, x, y, z) over the samples a lookup in majorant cell c can
   interpolate (an interpolation never exceeds its samples). */
static float cell_max(const MediumGrid *g, const int c[3], double (*val)(const MediumGrid *, int, int, int))
{
    int lo[3], hi[3], x, y, z;
    float mx = 0.0f;
    cell_samples((double)c[0] / MAJORANT_RES, (double)(c[0] + 1) / MAJORANT_RES, g->nx, &lo[0], &hi[0]);
    cell_samples((double)c[1] / MAJORANT_RES, (double)(c[1] + 1) / MAJORANT_RES, g->ny, &lo[1], &hi[1]);
    cell_samples((double)c[2] / MAJORANT_RES, (double)(c[2] + 1) / MAJORANT_RES, g->nz, &lo[2], &hi[2]);
    for (z = lo[2]; z <= hi[2]; z++)
        for (y = lo[1]; y <= hi[1]; y++)
            for (x = lo[0]; x <= hi[0]; x++)
                if (val(g, x, y, z) > mx) mx = (float)val(g, x, y, z);
    return mx;
}

/* An rgbgrid sample's largest value over SPEC_MIN..SPEC_MAX: the sigmoid is
   monotone, so at an end or at the quadratic's vertex (pbrt-v4's MaxValue). */
static double rgb_max(const MediumGrid *g, int x, int y, int z)
{
    const float *c = g->v + 4 * (((size_t)z * (size_t)g->ny + (size_t)y) * (size_t)g->nx + (size_t)x);
    double mx = fmax(spec_sigmoid_eval(c + 1, (float)SPEC_MIN), spec_sigmoid_eval(c + 1, (float)SPEC_MAX));
    if (c[1] != 0.0f) {
        double xv = -(double)c[2] / (2.0 * c[1]);
        if (xv > 0.0 && xv < 1.0)
            mx = fmax(mx, spec_sigmoid_eval(c + 1, (float)(SPEC_MIN + xv * (SPEC_N - 1))));
    }
    return c[0] * mx;
}

/* The majorant of every cell: dmax of the density (uniformgrid), or scale x
   (max sigma_a + max sigma_s) over wavelengths and the cell's samples (rgbgrid; an
   absent grid counts 1).  0: out of memory. */
static int build_majorant(Medium *m)
{
    int c[3];
    m->maj_res = m->type == MEDIUM_NANOVDB ? NANOVDB_MAJORANT_RES : MAJORANT_RES;
    m->majorant = (float *)malloc(sizeof(float) * m->maj_res * m->maj_res * m->maj_res);
    if (!m->majorant) return 0;
    if (m->type == MEDIUM_NANOVDB) {              /* the density grid's bound (nanovdb.c) */
        const double lo[3] = { m->p0.x, m->p0.y, m->p0.z }, hi[3] = { m->p1.x, m->p1.y, m->p1.z };
        nanovdb_majorant(&m->vdb[0], lo, hi, m->maj_res, m->majorant);
        return 1;
    }
    for (c[2] = 0; c[2] < MAJORANT_RES; c[2]++)
        for (c[1] = 0; c[1] < MAJORANT_RES; c[1]++)
            for (c[0] = 0; c[0] < MAJORANT_RES; c[0]++) {
                float mx;
                if (m->type == MEDIUM_RGBGRID)
                    mx = m->rgb_scale * ((m->rgb_sa.v ? cell_max(&m->rgb_sa, c, rgb_max) : 1.0f) +
                                         (m->rgb_ss.v ? cell_max(&m->rgb_ss, c, rgb_max) : 1.0f));
                else if (m->type == MEDIUM_CLOUD) mx = 1.0f;      /* d <= 1 */
                else mx = cell_max(&m->density, c, grid_at);
                m->majorant[(c[2] * MAJORANT_RES + c[1]) * MAJORANT_RES + c[0]] = mx;
            }
    return 1;
}

/* World point p in the unit cube of the medium's bounds. */
static Vec3 unit_coords(const Medium *m, Vec3 p)
{
    Vec3 q = xf_point(&m->medium_from_world, p);
    return v3((q.x - m->p0.x) / (m->p1.x - m->p0.x), (q.y - m->p0.y) / (m->p1.y - m->p0.y),
              (q.z - m->p0.z) / (m->p1.z - m->p0.z));
}

/* medium_point of an rgbgrid: each rgb grid at each alive wavelength, times scale;
   Le times D65 (m->Le) and Lescale. */
static void rgb_point(const Medium *m, Vec3 u, const float *lam, unsigned alive, MediumPoint *out)
{
    RgbCorners ca, cs, ce;
    int j;
    if (m->rgb_sa.v) rgb_corners(&m->rgb_sa, u, &ca);
    if (m->rgb_ss.v) rgb_corners(&m->rgb_ss, u, &cs);
    if (m->Le_scale > 0.0f) rgb_corners(&m->rgb_le, u, &ce);
    for (j = 0; j < HERO_N; j++) {
        out->sa[j] = out->ss[j] = out->le[j] = 0.0;
        if (!(alive & (1u << j))) continue;
        out->sa[j] = m->rgb_scale * (m->rgb_sa.v ? rgb_blend(&ca, lam[j]) : 1.0);
        out->ss[j] = m->rgb_scale * (m->rgb_ss.v ? rgb_blend(&cs, lam[j]) : 1.0);
        if (m->Le_scale > 0.0f) out->le[j] = rgb_blend(&ce, lam[j]) * spec_eval(&m->Le, lam[j]);
    }
}

/* pbrt-v4's CloudMedium::Density at q (medium space): the lookup point
   pp = frequency q is first pushed along the noise's finite-difference gradient
   (two octaves, the "wisps"), then five octaves of noise (weights 1/2, 1/4, ...,
   frequencies 1.99^i) are thinned with height; below y = 1/2 the cloud fills in. */
float medium_cloud_density(const Medium *m, Vec3 q)
{
    Vec3 pp = v3_mul(q, m->frequency);
    float d;
    if (m->wispiness > 0.0f) {
        float vomega = 0.05f * m->wispiness, vlambda = 10.0f;
        int i;
        for (i = 0; i < 2; i++) {
            float n[4], h = 0.01f;
            Vec3 dn;
            tex_noise_diff(v3_mul(pp, vlambda), h, n);
            dn = v3((n[1] - n[0]) / h, (n[2] - n[0]) / h, (n[3] - n[0]) / h);
            pp = v3_add(pp, v3_mul(dn, vomega));
            vomega *= 0.5f;
            vlambda *= 1.99f;
        }
    }
    d = 0.5f * tex_fbm(pp, 0.5f, 5);
    d = fminf(fmaxf((1.0f - q.y) * 4.5f * m->cloud_density * d, 0.0f), 1.0f);
    d += 2.0f * fmaxf(0.0f, 0.5f - q.y);
    return fminf(fmaxf(d, 0.0f), 1.0f);
}

/* A homogeneous, grid, cloud or nanovdb medium's sigma_a(lambda_j), sigma_s(lambda_j)
   at the lanes' wavelengths (lane_coeffs, below). */
typedef struct { float sa[HERO_N], ss[HERO_N]; } LaneCoeffs;

/* medium_point of a nanovdb medium (pbrt-v4's NanoVDBMedium::SamplePoint): d from
   the density grid (a negative blend reads 0), and where a temperature grid is,
   Lescale times the blackbody (peak 1) of (T - offset) scale above 100 K. */
static void vdb_point(const Medium *m, Vec3 p, const float *lam, unsigned alive, const LaneCoeffs *k,
                      MediumPoint *out)
{
    Vec3 q = xf_point(&m->medium_from_world, p);
    double d = fmax(0.0, nanovdb_sample(&m->vdb[0], q)), kelvin = 0.0;
    int j;
    if (m->vdb[1].buf && m->Le_scale > 0.0f)
        kelvin = (nanovdb_sample(&m->vdb[1], q) - m->temp_offset) * m->temp_scale;
    for (j = 0; j < HERO_N; j++) {
        out->sa[j] = out->ss[j] = out->le[j] = 0.0;
        if (!(alive & (1u << j))) continue;
        out->sa[j] = k->sa[j] * d;
        out->ss[j] = k->ss[j] * d;
        if (kelvin > 100.0) out->le[j] = m->Le_scale * blackbody_eval((float)kelvin, lam[j]);
    }
}

/* The coefficients sigma_a, sigma_s of a medium's spectra at the alive lanes'
   wavelengths (an rgbgrid's are in its grids: unused), computed once per track. */
static void lane_coeffs(const Medium *m, const float *lam, unsigned alive, LaneCoeffs *k)
{
    int j;
    for (j = 0; j < HERO_N; j++) {
        k->sa[j] = k->ss[j] = 0.0f;
        if (m->type == MEDIUM_RGBGRID || !(alive & (1u << j))) continue;
        k->sa[j] = medium_sigma_a(m, lam[j]);
        k->ss[j] = medium_sigma_s(m, lam[j]);
    }
}

/* medium_point with the lanes' coefficients k (lane_coeffs) */
static void point_at(const Medium *m, Vec3 p, const float *lam, unsigned alive, const LaneCoeffs *k,
                     MediumPoint *out)
{
    Vec3 u = unit_coords(m, p);
    double d, ls = 0.0, kelvin = 0.0;
    int j;
    if (m->type == MEDIUM_RGBGRID) { rgb_point(m, u, lam, alive, out); return; }
    if (m->type == MEDIUM_NANOVDB) { vdb_point(m, p, lam, alive, k, out); return; }
    d = m->type == MEDIUM_CLOUD ? medium_cloud_density(m, xf_point(&m->medium_from_world, p))
                                : medium_grid_lookup(&m->density, u);
    if (m->Le_scale > 0.0f) {
        ls = medium_grid_lookup(&m->lescale, u);
        if (m->temperature.v) {
            kelvin = (medium_grid_lookup(&m->temperature, u) - m->temp_offset) * m->temp_scale;
            if (!(kelvin > 100.0)) ls = 0.0;      /* pbrt-v4: no emission at or below 100 K */
        }
    }
    for (j = 0; j < HERO_N; j++) {
        out->sa[j] = out->ss[j] = out->le[j] = 0.0;
        if (!(alive & (1u << j))) continue;
        out->sa[j] = d * k->sa[j];
        out->ss[j] = d * k->ss[j];
        if (ls > 0.0)
            out->le[j] = ls * (m->temperature.v ? blackbody_eval((float)kelvin, lam[j])
                                                 : spec_eval(&m->Le, lam[j]));
    }
}

void medium_point(const Medium *m, Vec3 p, const float *lam, unsigned alive, MediumPoint *out)
{
    LaneCoeffs k;
    lane_coeffs(m, lam, alive, &k);
    point_at(m, p, lam, alive, &k, out);
}

void medium_free(Medium *m)
{
    free(m->density.v);
    free(m->lescale.v);
    free(m->temperature.v);
    free(m->majorant);
    free(m->rgb_sa.v);
    free(m->rgb_ss.v);
    free(m->rgb_le.v);
    nanovdb_free(&m->vdb[0]);
    nanovdb_free(&m->vdb[1]);
    m->density.v = m->lescale.v = m->temperature.v = m->majorant = NULL;
    m->rgb_sa.v = m->rgb_ss.v = m->rgb_le.v = NULL;
}

/* The ray o + t dn (dn unit, world) against the unit cube of the bounds, in the
   medium's grid coordinates g(t) = go + t gd: the overlap [*t0, *t1] of [0, tmax]. */
static int cube_overlap(const double go[3], const double gd[3], double tmax, double *t0, double *t1)
{
    int k;
    *t0 = 0.0;
    *t1 = tmax;
    for (k = 0; k < 3; k++) {
        double a, b;
        if (gd[k] == 0.0) {
            if (!(go[k] >= 0.0 && go[k] <= 1.0)) return 0;
            continue;
        }
        a = (0.0 - go[k]) / gd[k];
        b = (1.0 - go[k]) / gd[k];
        if (a > b) { double x = a; a = b; b = x; }
        if (a > *t0) *t0 = a;
        if (b < *t1) *t1 = b;
    }
    return *t0 < *t1;
}

/* A 3-D DDA over the res^3 majorant cells (Amanatides and Woo 1987): the cell the
   ray is in, and the distances at which it crosses into the next one per axis. */
typedef struct {
    int cell[3], step[3], res;
    double next[3], delta[3];
} Dda;

static void dda_start(Dda *w, int res, const double go[3], const double gd[3], double t0)
{
    int k;
    w->res = res;
    for (k = 0; k < 3; k++) {
        double pos = (go[k] + gd[k] * t0) * w->res;
        int c = (int)floor(pos);
        w->cell[k] = c < 0 ? 0 : c > w->res - 1 ? w->res - 1 : c;
        if (gd[k] > 0.0) {
            w->step[k] = 1;
            w->next[k] = ((double)(w->cell[k] + 1) / w->res - go[k]) / gd[k];
            w->delta[k] = 1.0 / (w->res * gd[k]);
        } else if (gd[k] < 0.0) {
            w->step[k] = -1;
            w->next[k] = ((double)w->cell[k] / w->res - go[k]) / gd[k];
            w->delta[k] = -1.0 / (w->res * gd[k]);
        } else {
            w->step[k] = 0;
            w->next[k] = w->delta[k] = INFINITY;
        }
    }
}

/* The exit distance of the current cell; steps into the next (0: left the grid). */
static int dda_step(Dda *w, double *t_exit)
{
    int a = w->next[0] < w->next[1] ? (w->next[0] < w->next[2] ? 0 : 2) : (w->next[1] < w->next[2] ? 1 : 2);
    *t_exit = w->next[a];
    w->cell[a] += w->step[a];
    w->next[a] += w->delta[a];
    return w->cell[a] >= 0 && w->cell[a] < w->res;
}

/* Tbar_j / Tbar_0 = exp(-(sigma_bar_j - sigma_bar_0) dt) over a length dt, with
   ds = sigma_bar_j - sigma_bar_0: exactly 1 where the majorants agree (the hero,
   grey media, every lane of an rgbgrid) without calling exp. */
static double maj_ratio(double ds, double dt)
{
    return ds == 0.0 ? 1.0 : exp(-ds * dt);
}

int medium_track(const Medium *m, Ray ray, float tmax, const float *lam, unsigned alive,
                 float u, Rng *rng, MediumEventFn fn, void *ctx, double tm_end[HERO_N])
{
    double len = v3_len(ray.d), go[3], gd[3], t, t1, st[HERO_N], tau;
    Vec3 dn = v3_mul(ray.d, 1.0f / (float)len), o = xf_point(&m->medium_from_world, ray.o),
         dm = xf_vector(&m->medium_from_world, dn);
    const float oo[3] = { o.x, o.y, o.z }, dd[3] = { dm.x, dm.y, dm.z },
                lo[3] = { m->p0.x, m->p0.y, m->p0.z }, hi[3] = { m->p1.x, m->p1.y, m->p1.z };
    MediumEvent ev;
    LaneCoeffs lc;
    Dda w;
    long events = 0;
    int j, k, inside = 1;
    lane_coeffs(m, lam, alive, &lc);
    for (j = 0; j < HERO_N; j++) {
        tm_end[j] = 1.0;
        st[j] = !(alive & (1u << j)) ? 0.0 : m->type == MEDIUM_RGBGRID ? 1.0 : lc.sa[j] + lc.ss[j];
    }
    for (k = 0; k < 3; k++) {
        go[k] = (oo[k] - lo[k]) / (hi[k] - lo[k]);
        gd[k] = dd[k] / (hi[k] - lo[k]);
    }
    if (!(len > 0.0) || !cube_overlap(go, gd, (double)tmax * len, &t, &t1)) return 0;
    dda_start(&w, m->maj_res, go, gd, t);
    tau = -log1p(-(double)u);
    while (inside && t < t1) {
        double t_exit, dmax = m->majorant[((size_t)w.cell[2] * w.res + w.cell[1]) * w.res + w.cell[0]];
        inside = dda_step(&w, &t_exit);
        if (t_exit > t1 || !inside) t_exit = t1;
        for (j = 0; j < HERO_N; j++) ev.smaj[j] = st[j] * dmax;
        while (ev.smaj[0] > 0.0) {          /* tentative collisions at the hero's majorant */
            double tc = t + tau / ev.smaj[0];
            if (!(tc < t_exit)) {           /* the cell's optical depth spent: carry the rest */
                tau = fmax(0.0, tau - ev.smaj[0] * (t_exit - t));
                break;
            }
            tau = -log1p(-(double)rng_float(rng));
            if (++events > MEDIUM_MAX_EVENTS || !isfinite(ev.smaj[0])) {
                for (j = 0; j < HERO_N; j++) tm_end[j] = 0.0;    /* opaque: nothing passes */
                return 0;
            }
            for (j = 0; j < HERO_N; j++) ev.tm[j] = tm_end[j] * maj_ratio(ev.smaj[j] - ev.smaj[0], tc - t);
            ev.t = (float)(tc / len);
            ev.p = v3_add(ray.o, v3_mul(dn, (float)tc));
            point_at(m, ev.p, lam, alive, &lc, &ev.mp);
            if (!fn(ctx, &ev)) return 1;
            for (j = 0; j < HERO_N; j++) tm_end[j] = 1.0;
            t = tc;
        }
        for (j = 0; j < HERO_N; j++) tm_end[j] *= maj_ratio(ev.smaj[j] - ev.smaj[0], t_exit - t);
        t = t_exit;
    }
    return 0;
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   medium_from_params: the scene builder's (scene.c) MakeNamedMedium, read from
   its parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* A medium coefficient (sigma_a, sigma_s): absent -> def (pbrt-v4: 1), else a
   spectrum with finite values >= 0 */
static int medium_coeff(Parser *P, ParamList *pl, const char *what, const char *name,
                        float def, Spectrum *out, const char *file, int line)
{
    Param *p = find_spectrum_param(pl, name);
    char w[192];
    if (!p) { spec_const(out, def); return 1; }
    snprintf(w, sizeof w, "%s: \"%s\"", what, name);
    return param_spectrum(P, p, SPEC_COEFF, out, NULL) &&
           check_spectrum_above(P, p, file, line, w, out, 0.0f, 0);
}

/* A float-array parameter of a uniformgrid as an nx ny nz grid (g->v NULL when
   absent and not required): count nx ny nz, every value finite and >= 0 unless
   `any_sign` (a temperature may have any offset). */
static int grid_param(Parser *P, ParamList *pl, const char *what, const char *name, const int n[3],
                      int required, int any_sign, const char *file, int line, MediumGrid *g)
{
    Param *p = param_find(pl, PT_FLOAT, name);
    size_t count = (size_t)n[0] * (size_t)n[1] * (size_t)n[2], i;
    g->nx = n[0]; g->ny = n[1]; g->nz = n[2];
    g->v = NULL;
    if (!p) return required ? fail(P, file, line, "%s: \"float %s\" is required (nx*ny*nz values)",
                                   what, name) : 1;
    if ((size_t)p->n_num != count)
        return fail(P, p->file, p->line, "%s: %d \"%s\" values; expected nx*ny*nz = %d*%d*%d = %lu",
                    what, p->n_num, name, n[0], n[1], n[2], (unsigned long)count);
    for (i = 0; i < count; i++)
        if (!isfinite(p->num[i]) || fabs(p->num[i]) > 1e30 || (!any_sign && p->num[i] < 0.0))
            return fail(P, p->file, p->line, "%s: \"%s\" value %lu is %g; need a finite value%s",
                        what, name, (unsigned long)i, p->num[i], any_sign ? "" : " >= 0");
    g->v = (float *)malloc(sizeof(float) * count);
    if (!g->v) return oom(P, p->file, p->line);
    for (i = 0; i < count; i++) g->v[i] = (float)p->num[i];
    return 1;
}

/* "point3 p0"/"p1" (defaults (0,0,0), (1,1,1)); p0 < p1 on every axis. */
static int grid_bounds(Parser *P, ParamList *pl, const char *what, const char *file, int line, Medium *m)
{
    Param *b[2];
    double v[2][3] = { { 0, 0, 0 }, { 1, 1, 1 } };
    int i, k;
    b[0] = param_find(pl, PT_POINT3, "p0");
    b[1] = param_find(pl, PT_POINT3, "p1");
    for (i = 0; i < 2; i++) {
        if (!b[i]) continue;
        if (b[i]->n_num != 3)
            return fail(P, b[i]->file, b[i]->line, "%s: \"point3 %s\" needs 3 values, got %d", what,
                        i ? "p1" : "p0", b[i]->n_num);
        for (k = 0; k < 3; k++) v[i][k] = b[i]->num[k];
    }
    for (k = 0; k < 3; k++)
        if (!isfinite(v[0][k]) || !isfinite(v[1][k]) || !(v[0][k] < v[1][k]) ||
            fabs(v[0][k]) > 1e30 || fabs(v[1][k]) > 1e30)
            return fail(P, b[1] ? b[1]->file : file, b[1] ? b[1]->line : line,
                        "%s: bounds \"point3 p0\" [ %g %g %g ] and \"point3 p1\" [ %g %g %g ] need "
                        "finite p0 < p1 on every axis", what, v[0][0], v[0][1], v[0][2],
                        v[1][0], v[1][1], v[1][2]);
    m->p0 = v3((float)v[0][0], (float)v[0][1], (float)v[0][2]);
    m->p1 = v3((float)v[1][0], (float)v[1][1], (float)v[1][2]);
    if (!(m->p0.x < m->p1.x && m->p0.y < m->p1.y && m->p0.z < m->p1.z))
        return fail(P, file, line, "%s: bounds p0 and p1 are too close for float precision", what);
    return 1;
}

/* A grid medium's frame: the inverse of the CTM at its MakeNamedMedium. */
static void medium_frame(const Parser *P, Medium *m)
{
    m->medium_from_world = P->gs.ctm;
    memcpy(m->medium_from_world.m, P->gs.ctm.inv, sizeof m->medium_from_world.m);
    memcpy(m->medium_from_world.inv, P->gs.ctm.m, sizeof m->medium_from_world.inv);
}

/* The grids of a uniformgrid: density, temperature, Lescale (pbrt-v4 GridMedium::Create). */
static int grid_arrays(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                       int has_le, Medium *m)
{
    int n[3], k;
    static const char *const axis[3] = { "nx", "ny", "nz" };
    static const int one[3] = { 1, 1, 1 };
    for (k = 0; k < 3; k++) {
        if (!get_int(P, pl, axis[k], 1, &n[k], NULL)) return 0;
        if (n[k] < 1 || n[k] > 4096) {
            Param *p = param_find(pl, PT_INTEGER, axis[k]);
            return fail(P, p->file, p->line, "%s: \"integer %s\" %d must lie in 1..4096", what,
                        axis[k], n[k]);
        }
    }
    if (!grid_param(P, pl, what, "density", n, 1, 0, file, line, &m->density) ||
        !grid_param(P, pl, what, "temperature", n, 0, 1, file, line, &m->temperature))
        return 0;
    if (m->temperature.v && has_le)
        return fail(P, file, line, "%s: both \"Le\" and \"temperature\" are given (pbrt-v4 "
                    "takes one of them)", what);
    if (param_find(pl, PT_FLOAT, "Lescale")) {
        if (!grid_param(P, pl, what, "Lescale", n, 1, 0, file, line, &m->lescale)) return 0;
    } else {
        if (!grid_param(P, pl, what, "Lescale", one, 0, 0, file, line, &m->lescale)) return 0;
        m->lescale.v = (float *)malloc(sizeof(float));
        if (!m->lescale.v) return oom(P, file, line);
        m->lescale.v[0] = 1.0f;                   /* pbrt-v4: a 1x1x1 grid of 1 */
    }
    if (!build_majorant(m)) return oom(P, file, line);
    return 1;
}

/* MakeNamedMedium ... "string type" "uniformgrid" with pbrt-v4's meaning
   (media.cpp, GridMedium::Create): sigma_a, sigma_s (1 each) times "float scale"
   (1) times the interpolated "float density" grid (nx ny nz values, x fastest,
   over the bounds "point3 p0" (0 0 0) .. "point3 p1" (1 1 1) in the frame of the
   CTM at the directive); "float g" (0); emission "spectrum Le" normalised as the
   homogeneous medium's, or a "float temperature" grid as a blackbody (peak 1) of
   (T - "float temperaturecutoff" (alias temperatureoffset, 0)) *
   "float temperaturescale" (1) kelvin; both times the "float Lescale" grid
   (default: one sample of 1). */
static int grid_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                            Medium *m)
{
    float scale, g, off, tscale;
    int i, rgb_illum = 0, ok;
    Param *ple;
    m->type = MEDIUM_UNIFORMGRID;
    medium_frame(P, m);
    if (!medium_coeff(P, pl, what, "sigma_a", 1.0f, &m->sigma_a, file, line) ||
        !medium_coeff(P, pl, what, "sigma_s", 1.0f, &m->sigma_s, file, line) ||
        !get_float(P, pl, "scale", 1.0f, &scale) || !get_float(P, pl, "g", 0.0f, &g) ||
        !get_float(P, pl, "temperatureoffset", 0.0f, &off) ||
        !get_float(P, pl, "temperaturecutoff", off, &off) ||
        !get_float(P, pl, "temperaturescale", 1.0f, &tscale))
        return 0;
    ple = find_spectrum_param(pl, "Le");
    if (ple) {
        char w[192];
        snprintf(w, sizeof w, "%s: \"Le\"", what);
        if (!param_spectrum(P, ple, SPEC_ILLUMINANT, &m->Le, &rgb_illum) ||
            !check_spectrum_above(P, ple, file, line, w, &m->Le, 0.0f, 0)) return 0;
    }
    ok = grid_arrays(P, pl, what, file, line, ple != NULL, m) && grid_bounds(P, pl, what, file, line, m) &&
         params_check_unused(P, pl, what, "string type, spectrum sigma_a, spectrum sigma_s, "
                             "float scale, float g, float density, integer nx, integer ny, "
                             "integer nz, point3 p0, point3 p1, spectrum Le, float Lescale, "
                             "float temperature, float temperaturecutoff, "
                             "float temperatureoffset, float temperaturescale", NULL);
    if (ok && (!(scale >= 0.0f) || !(scale < 1e30f)))
        ok = fail_param(P, pl, "scale", file, line, "%s: \"float scale\" %g must be a finite number >= 0",
                        what, scale);
    if (ok && (!(g > -1.0f) || !(g < 1.0f)))
        ok = fail_param(P, pl, "g", file, line, "%s: \"float g\" %g must lie in (-1, 1) (Henyey-Greenstein)",
                        what, g);
    if (ok && (!isfinite(off) || !isfinite(tscale)))
        ok = fail(P, file, line, "%s: \"float temperaturecutoff\" and \"float temperaturescale\" "
                  "must be finite", what);
    if (!ok) { medium_free(m); return 0; }
    for (i = 0; i < SPEC_N; i++) { m->sigma_a.v[i] *= scale; m->sigma_s.v[i] *= scale; }
    for (i = 0; i < SPEC_UV_N; i++) { m->sigma_a.uv[i] *= scale; m->sigma_s.uv[i] *= scale; }
    m->g = g;
    m->temp_offset = off;
    m->temp_scale = tscale;
    if (m->temperature.v) m->Le_scale = 1.0f;   /* absolute: render.c keeps it */
    else if (ple) {
        float mx = 0.0f;
        for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
            if (spec_get(&m->Le, i) > mx) mx = spec_get(&m->Le, i);
        if (mx > 0.0f) m->Le_scale = rgb_illum ? rgb_illuminant_scale(P, &m->Le, 1.0f) : 1.0f;
    }
    m->file = file;
    m->line = line;
    return 1;
}

/* An "rgb NAME" grid of an rgbgrid (g->v NULL when absent): count 3 nx ny nz, each
   value finite and >= 0; each sample stored as 2 max(rgb) and the sigmoid fit of
   rgb / (2 max(rgb)) (pbrt-v4's RGBUnboundedSpectrum; an illuminant's D65 is
   applied at the lookup).  A run of equal samples is fitted once. */
static int rgb_grid_param(Parser *P, ParamList *pl, const char *what, const char *name, const int n[3],
                          Medium *m, MediumGrid *g)
{
    Param *p = param_find(pl, PT_RGB, name);
    size_t count = (size_t)n[0] * (size_t)n[1] * (size_t)n[2], i;
    int k;
    g->nx = n[0]; g->ny = n[1]; g->nz = n[2];
    g->v = NULL;
    if (!p) return 1;
    if ((size_t)p->n_num != 3 * count)
        return fail(P, p->file, p->line, "%s: %d \"rgb %s\" values; expected 3*nx*ny*nz = 3*%d*%d*%d = %lu",
                    what, p->n_num, name, n[0], n[1], n[2], (unsigned long)(3 * count));
    for (i = 0; i < 3 * count; i++)
        if (!isfinite(p->num[i]) || !(p->num[i] >= 0.0) || p->num[i] > 1e30)
            return fail(P, p->file, p->line, "%s: \"rgb %s\" value %lu is %g; need a finite value >= 0",
                        what, name, (unsigned long)i, p->num[i]);
    g->v = (float *)malloc(sizeof(float) * 4 * count);
    if (!g->v) return oom(P, p->file, p->line);
    for (i = 0; i < count; i++) {
        const double *rgb = p->num + 3 * i;
        double mx = fmax(rgb[0], fmax(rgb[1], rgb[2])), target[3], c[3] = { 0.0, 0.0, 0.0 };
        float *out = g->v + 4 * i;
        if (i > 0 && rgb[0] == rgb[-3] && rgb[1] == rgb[-2] && rgb[2] == rgb[-1]) {
            for (k = 0; k < 4; k++) out[k] = out[k - 4];
            continue;
        }
        if (mx > 0.0) {
            for (k = 0; k < 3; k++) target[k] = rgb[k] / (2.0 * mx);
            spec_rgb_coeffs(P->rgb, target, c);
        }
        out[0] = (float)(2.0 * mx);
        for (k = 0; k < 3; k++) out[k + 1] = (float)c[k];
        if (name[0] == 's' && (c[0] != 0.0 || c[1] != 0.0 || c[2] != 0.0)) m->chromatic = 1;
    }
    return 1;
}

/* The rgb grids of an rgbgrid and their checks (pbrt-v4 RGBGridMedium::Create). */
static int rgb_grids(Parser *P, ParamList *pl, const char *what, const char *file, int line, Medium *m)
{
    int n[3], k;
    static const char *const axis[3] = { "nx", "ny", "nz" };
    for (k = 0; k < 3; k++) {
        if (!get_int(P, pl, axis[k], 1, &n[k], NULL)) return 0;
        if (n[k] < 1 || n[k] > 4096) {
            Param *p = param_find(pl, PT_INTEGER, axis[k]);
            return fail(P, p->file, p->line, "%s: \"integer %s\" %d must lie in 1..4096", what,
                        axis[k], n[k]);
        }
    }
    if (!param_find(pl, PT_RGB, "sigma_a") && !param_find(pl, PT_RGB, "sigma_s"))
        return fail(P, file, line, "%s: an rgbgrid needs \"rgb sigma_a\" and/or \"rgb sigma_s\" "
                    "(nx*ny*nz rgb triples)", what);
    if (param_find(pl, PT_RGB, "Le") && !param_find(pl, PT_RGB, "sigma_a"))
        return fail(P, file, line, "%s: an rgbgrid with \"rgb Le\" needs \"rgb sigma_a\" (it emits "
                    "sigma_a Le)", what);
    return rgb_grid_param(P, pl, what, "sigma_a", n, m, &m->rgb_sa) &&
           rgb_grid_param(P, pl, what, "sigma_s", n, m, &m->rgb_ss) &&
           rgb_grid_param(P, pl, what, "Le", n, m, &m->rgb_le);
}

/* MakeNamedMedium ... "string type" "rgbgrid" with pbrt-v4's meaning (media.cpp,
   RGBGridMedium::Create): "rgb sigma_a", "rgb sigma_s" (nx ny nz triples each,
   x fastest; an absent one is 1 everywhere; at least one is given) times
   "float scale" (1), over the bounds p0..p1 in the frame of the CTM; "float g"
   (0); emission sigma_a Le with an "rgb Le" grid (an RGB illuminant: times D65)
   times "float Lescale" (1).  pbrt-v4 does not divide this Le by its luminance
   (its homogeneous and uniformgrid media and its lights do): an "rgb Le" [ 1 1 1 ]
   is the integral of ybar (106.86) times as bright as an area light's "rgb L"
   [ 1 1 1 ], and specnee keeps that meaning (Le_scale). */
static int rgbgrid_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                               Medium *m)
{
    float g, lescale;
    int ok;
    m->type = MEDIUM_RGBGRID;
    medium_frame(P, m);
    if (!get_float(P, pl, "scale", 1.0f, &m->rgb_scale) || !get_float(P, pl, "g", 0.0f, &g) ||
        !get_float(P, pl, "Lescale", 1.0f, &lescale))
        return 0;
    ok = rgb_grids(P, pl, what, file, line, m) && grid_bounds(P, pl, what, file, line, m) &&
         params_check_unused(P, pl, what, "string type, rgb sigma_a, rgb sigma_s, rgb Le, "
                             "float scale, float g, float Lescale, integer nx, integer ny, "
                             "integer nz, point3 p0, point3 p1", NULL);
    if (ok && (!(m->rgb_scale >= 0.0f) || !(m->rgb_scale < 1e30f)))
        ok = fail_param(P, pl, "scale", file, line, "%s: \"float scale\" %g must be a finite number >= 0",
                        what, m->rgb_scale);
    if (ok && (!(g > -1.0f) || !(g < 1.0f)))
        ok = fail_param(P, pl, "g", file, line, "%s: \"float g\" %g must lie in (-1, 1) (Henyey-Greenstein)",
                        what, g);
    if (ok && (!(lescale >= 0.0f) || !(lescale < 1e30f)))
        ok = fail_param(P, pl, "Lescale", file, line, "%s: \"float Lescale\" %g must be a finite number >= 0",
                        what, lescale);
    if (ok && m->rgb_le.v && lescale > 0.0f) {
        space_white(P, &m->Le);                /* the colour space's illuminant */
        m->Le_scale = lescale * (float)cie_y_integral((float)SPEC_MIN, (float)SPEC_MAX);
    }
    if (ok && !build_majorant(m)) ok = oom(P, file, line);
    if (!ok) { medium_free(m); return 0; }
    m->g = g;
    m->file = file;
    m->line = line;
    return 1;
}

/* MakeNamedMedium ... "string type" "cloud" with pbrt-v4's meaning (media.cpp,
   CloudMedium::Create): "spectrum sigma_a", "sigma_s" (1 each, per scene unit;
   pbrt-v4 reads no "scale" here) times medium_cloud_density, with "float density"
   (1), "float wispiness" (1), "float frequency" (5), "float g" (0), inside the
   bounds p0..p1 (0 0 0, 1 1 1) in the frame of the CTM.  No emission. */
static int cloud_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                             Medium *m)
{
    float g;
    int ok;
    m->type = MEDIUM_CLOUD;
    medium_frame(P, m);
    if (!medium_coeff(P, pl, what, "sigma_a", 1.0f, &m->sigma_a, file, line) ||
        !medium_coeff(P, pl, what, "sigma_s", 1.0f, &m->sigma_s, file, line) ||
        !get_float(P, pl, "density", 1.0f, &m->cloud_density) || !get_float(P, pl, "g", 0.0f, &g) ||
        !get_float(P, pl, "wispiness", 1.0f, &m->wispiness) ||
        !get_float(P, pl, "frequency", 5.0f, &m->frequency))
        return 0;
    ok = grid_bounds(P, pl, what, file, line, m) &&
         params_check_unused(P, pl, what, "string type, spectrum sigma_a, spectrum sigma_s, "
                             "float density, float wispiness, float frequency, float g, "
                             "point3 p0, point3 p1", NULL);
    if (ok && (!isfinite(m->cloud_density) || !isfinite(m->wispiness) || !isfinite(m->frequency) ||
               fabsf(m->frequency) > 1e20f))
        ok = fail(P, file, line, "%s: \"float density\", \"wispiness\" and \"frequency\" must be "
                  "finite", what);
    if (ok && (!(g > -1.0f) || !(g < 1.0f)))
        ok = fail_param(P, pl, "g", file, line, "%s: \"float g\" %g must lie in (-1, 1) (Henyey-Greenstein)",
                        what, g);
    if (ok && !build_majorant(m)) ok = oom(P, file, line);
    if (!ok) { medium_free(m); return 0; }
    m->g = g;
    m->file = file;
    m->line = line;
    return 1;
}

/* The bounds of a nanovdb medium: the world bbox the file gives its density grid,
   joined with the temperature grid's (pbrt-v4 NanoVDBMedium). */
static int vdb_bounds(Parser *P, const char *what, const char *file, int line, Medium *m)
{
    double lo[3], hi[3];
    int k, i;
    for (k = 0; k < 3; k++) { lo[k] = m->vdb[0].wmin[k]; hi[k] = m->vdb[0].wmax[k]; }
    for (i = 1; i < 2; i++)
        for (k = 0; k < 3 && m->vdb[i].buf; k++) {
            lo[k] = fmin(lo[k], m->vdb[i].wmin[k]);
            hi[k] = fmax(hi[k], m->vdb[i].wmax[k]);
        }
    for (k = 0; k < 3; k++)
        if (!(lo[k] < hi[k]) || !(fabs(lo[k]) < 1e30) || !(fabs(hi[k]) < 1e30) ||
            !((float)lo[k] < (float)hi[k]))
            return fail(P, file, line, "%s: the grids' world bounding box [ %g %g %g ] .. [ %g %g %g ] "
                        "is empty or not finite", what, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    m->p0 = v3((float)lo[0], (float)lo[1], (float)lo[2]);
    m->p1 = v3((float)hi[0], (float)hi[1], (float)hi[2]);
    return 1;
}

/* MakeNamedMedium ... "string type" "nanovdb" with pbrt-v4's meaning (media.cpp,
   NanoVDBMedium::Create): the grid "string gridname" ("density") of the NanoVDB
   file "string filename" (required; nanovdb.c reads it) scales sigma_a and sigma_s
   (1 each) times "float scale" (1); the grid "string temperaturename"
   ("temperature"), when the file has one, emits "float Lescale" (1) times the
   blackbody (peak 1) of (T - "float temperatureoffset" (default: "float
   temperaturecutoff", 0)) * "float temperaturescale" (1) kelvin; "float g" (0).
   The file's index-to-world map, then the CTM at the directive, place the grids. */
static int nanovdb_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                               Medium *m)
{
    const char *fn = NULL, *names[2] = { NULL, NULL };
    float scale, g, cut, off, tscale, lescale;
    char path[PATH_CAP];
    Error e;
    int i, ok;
    m->type = MEDIUM_NANOVDB;
    medium_frame(P, m);
    if (!get_string(P, pl, "filename", &fn) || !get_string(P, pl, "gridname", &names[0]) ||
        !get_string(P, pl, "temperaturename", &names[1]) ||
        !medium_coeff(P, pl, what, "sigma_a", 1.0f, &m->sigma_a, file, line) ||
        !medium_coeff(P, pl, what, "sigma_s", 1.0f, &m->sigma_s, file, line) ||
        !get_float(P, pl, "scale", 1.0f, &scale) || !get_float(P, pl, "g", 0.0f, &g) ||
        !get_float(P, pl, "Lescale", 1.0f, &lescale) ||
        !get_float(P, pl, "temperaturecutoff", 0.0f, &cut) ||
        !get_float(P, pl, "temperatureoffset", cut, &off) ||
        !get_float(P, pl, "temperaturescale", 1.0f, &tscale) ||
        !params_check_unused(P, pl, what, "string type, string filename, string gridname, "
                             "string temperaturename, spectrum sigma_a, spectrum sigma_s, float scale, "
                             "float g, float Lescale, float temperaturecutoff, float temperatureoffset, "
                             "float temperaturescale", NULL))
        return 0;
    if (!fn || !fn[0]) return fail(P, file, line, "%s: \"string filename\" is required", what);
    resolve_path(P, file, fn, path, sizeof path);
    ok = 1;
    for (i = 0; i < 2 && ok; i++)
        if (!nanovdb_read(path, names[i] ? names[i] : i ? "temperature" : "density", &m->vdb[i], &e))
            ok = fail(P, file, line, "%s: %s", what, e.msg);
    if (ok && !m->vdb[0].buf)
        ok = fail(P, file, line, "%s: %s: no grid named \"%s\"", what, fn, names[0] ? names[0] : "density");
    if (ok && (!(scale >= 0.0f) || !(scale < 1e30f)))
        ok = fail_param(P, pl, "scale", file, line, "%s: \"float scale\" %g must be a finite number >= 0",
                        what, scale);
    if (ok && (!(g > -1.0f) || !(g < 1.0f)))
        ok = fail_param(P, pl, "g", file, line, "%s: \"float g\" %g must lie in (-1, 1) (Henyey-Greenstein)",
                        what, g);
    if (ok && (!(lescale >= 0.0f) || !(lescale < 1e30f) || !isfinite(off) || !isfinite(tscale)))
        ok = fail(P, file, line, "%s: \"float Lescale\" must be finite and >= 0, \"temperatureoffset\" "
                  "and \"temperaturescale\" finite", what);
    ok = ok && vdb_bounds(P, what, file, line, m);
    if (ok && !build_majorant(m)) ok = oom(P, file, line);
    if (!ok) { medium_free(m); return 0; }
    for (i = 0; i < SPEC_N; i++) { m->sigma_a.v[i] *= scale; m->sigma_s.v[i] *= scale; }
    for (i = 0; i < SPEC_UV_N; i++) { m->sigma_a.uv[i] *= scale; m->sigma_s.uv[i] *= scale; }
    m->g = g;
    m->temp_offset = off;
    m->temp_scale = tscale;
    if (m->vdb[1].buf && lescale > 0.0f) m->Le_scale = lescale;   /* absolute (render.c) */
    m->file = file;
    m->line = line;
    return 1;
}

/* MakeNamedMedium "name" "string type" "homogeneous" ... with pbrt-v4's meaning
   (media.cpp, HomogeneousMedium::Create): sigma_a, sigma_s (default 1 each, per
   scene unit), or a "string preset" of measured coefficients (medium.c; they are
   in mm^-1, used as they are, as pbrt-v4 does), both times "float scale" (1);
   "float g" (0) the Henyey-Greenstein asymmetry; emission "spectrum Le" (0)
   times "float Lescale" (1), normalised as an area light's L is (lights.c: an rgb
   Le through D65).  "uniformgrid" and "rgbgrid" have builders of their own
   (above), and so have "cloud" and "nanovdb". */
int medium_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                       Medium *m)
{
    const char *type = NULL, *preset = NULL;
    float scale, g, lescale;
    int i, rgb_illum = 0;
    Param *ple;
    memset(m, 0, sizeof *m);
    if (!get_string(P, pl, "type", &type)) return 0;
    if (!type) return fail(P, file, line, "%s: \"string type\" is required", what);
    if (!strcmp(type, "uniformgrid")) return grid_from_params(P, pl, what, file, line, m);
    if (!strcmp(type, "rgbgrid")) return rgbgrid_from_params(P, pl, what, file, line, m);
    if (!strcmp(type, "cloud")) return cloud_from_params(P, pl, what, file, line, m);
    if (!strcmp(type, "nanovdb")) return nanovdb_from_params(P, pl, what, file, line, m);
    if (strcmp(type, "homogeneous") != 0)
        return fail(P, file, line, "%s: unknown medium type \"%s\"", what, type);
    if (!get_string(P, pl, "preset", &preset)) return 0;
    if (preset && preset[0]) {
        float sa[3], ss[3];
        Param *pp = param_find(pl, PT_STRING, "preset");
        if (!medium_preset(preset, sa, ss))
            return fail(P, pp->file, pp->line, "%s: unknown preset \"%s\" (pbrt-v4's names, e.g. "
                        "\"Wholemilk\", \"Skin1\", \"Ketchup\")", what, preset);
        if (!spec_from_rgb_t(rgb_srgb_table(P), &m->sigma_a, sa, 2, P->err, pp->file, pp->line) ||
            !spec_from_rgb_t(rgb_srgb_table(P), &m->sigma_s, ss, 2, P->err, pp->file, pp->line)) return 0;
    } else if (!medium_coeff(P, pl, what, "sigma_a", 1.0f, &m->sigma_a, file, line) ||
               !medium_coeff(P, pl, what, "sigma_s", 1.0f, &m->sigma_s, file, line))
        return 0;
    if (!get_float(P, pl, "scale", 1.0f, &scale) || !get_float(P, pl, "g", 0.0f, &g) ||
        !get_float(P, pl, "Lescale", 1.0f, &lescale)) return 0;
    ple = find_spectrum_param(pl, "Le");
    if (ple) {
        char w[192];
        snprintf(w, sizeof w, "%s: \"Le\"", what);
        if (!param_spectrum(P, ple, SPEC_ILLUMINANT, &m->Le, &rgb_illum) ||
            !check_spectrum_above(P, ple, file, line, w, &m->Le, 0.0f, 0)) return 0;
    }
    if (!params_check_unused(P, pl, what, "string type, string preset, spectrum sigma_a, "
                             "spectrum sigma_s, float scale, float g, spectrum Le, "
                             "float Lescale", NULL))
        return 0;
    if (!(scale >= 0.0f) || !(scale < 1e30f)) {
        Param *p = param_find(pl, PT_FLOAT, "scale");
        return fail(P, p->file, p->line, "%s: \"float scale\" %g must be a finite number >= 0", what, scale);
    }
    if (!(g > -1.0f) || !(g < 1.0f)) {
        Param *p = param_find(pl, PT_FLOAT, "g");
        return fail(P, p->file, p->line, "%s: \"float g\" %g must lie in (-1, 1) (Henyey-Greenstein)",
                    what, g);
    }
    if (!(lescale >= 0.0f) || !(lescale < 1e30f)) {
        Param *p = param_find(pl, PT_FLOAT, "Lescale");
        return fail(P, p->file, p->line, "%s: \"float Lescale\" %g must be a finite number >= 0", what,
                    lescale);
    }
    for (i = 0; i < SPEC_N; i++) {
        m->sigma_a.v[i] *= scale;
        m->sigma_s.v[i] *= scale;
    }
    for (i = 0; i < SPEC_UV_N; i++) {
        m->sigma_a.uv[i] *= scale;
        m->sigma_s.uv[i] *= scale;
    }
    m->g = g;
    m->Le_scale = 0.0f;
    if (ple) {
        float mx = 0.0f;
        for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
            if (spec_get(&m->Le, i) > mx) mx = spec_get(&m->Le, i);
        if (mx > 0.0f) m->Le_scale = rgb_illum ? rgb_illuminant_scale(P, &m->Le, lescale) : lescale;
    }
    m->file = file;
    m->line = line;
    return 1;
}
