/* medium.c - homogeneous participating media: their coefficients, the
   Henyey-Greenstein phase function, pbrt-v4's named presets, and which medium a
   ray is in after it leaves a surface.

   Exported (specnee.h section 6b): medium_sigma_t, medium_sigma_s, medium_sigma_a,
   hg_phase, hg_sample, medium_preset, medium_after.

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

   The last section builds a medium from a MakeNamedMedium's parameters for the
   scene builder (medium_from_params, parser.h). */
#include "specnee.h"
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

/* MakeNamedMedium "name" "string type" "homogeneous" ... with pbrt-v4's meaning
   (media.cpp, HomogeneousMedium::Create): sigma_a, sigma_s (default 1 each, per
   scene unit), or a "string preset" of measured coefficients (medium.c; they are
   in mm^-1, used as they are, as pbrt-v4 does), both times "float scale" (1);
   "float g" (0) the Henyey-Greenstein asymmetry; emission "spectrum Le" (0)
   times "float Lescale" (1), normalised as an area light's L is (lights.c: an rgb
   Le through D65).  Only homogeneous media: the others are refused by name. */
int medium_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                       Medium *m)
{
    static const char *const pbrt_types[] = { "uniformgrid", "rgbgrid", "cloud", "nanovdb", NULL };
    const char *type = NULL, *preset = NULL;
    float scale, g, lescale;
    int i, rgb_illum = 0;
    Param *ple;
    memset(m, 0, sizeof *m);
    if (!get_string(P, pl, "type", &type)) return 0;
    if (!type) return fail(P, file, line, "%s: \"string type\" is required", what);
    if (strcmp(type, "homogeneous") != 0) {
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i]))
                return fail(P, file, line, "%s: medium type \"%s\" is valid pbrt-v4 but not in "
                            "the specnee subset (only \"homogeneous\")", what, type);
        return fail(P, file, line, "%s: unknown medium type \"%s\"", what, type);
    }
    if (!get_string(P, pl, "preset", &preset)) return 0;
    if (preset && preset[0]) {
        float sa[3], ss[3];
        Param *pp = param_find(pl, PT_STRING, "preset");
        if (!medium_preset(preset, sa, ss))
            return fail(P, pp->file, pp->line, "%s: unknown preset \"%s\" (pbrt-v4's names, e.g. "
                        "\"Wholemilk\", \"Skin1\", \"Ketchup\")", what, preset);
        if (!spec_from_rgb_t(P->rgb, &m->sigma_a, sa, 2, P->err, pp->file, pp->line) ||
            !spec_from_rgb_t(P->rgb, &m->sigma_s, ss, 2, P->err, pp->file, pp->line)) return 0;
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
        if (mx > 0.0f) m->Le_scale = rgb_illum ? rgb_illuminant_scale(&m->Le, lescale) : lescale;
    }
    m->file = file;
    m->line = line;
    return 1;
}
