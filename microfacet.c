/* microfacet.c - the scattering room: the pieces every BSDF of specnee is built
   from, one copy each (pbrt-v4 keeps them in util/scattering.h, lajolla in
   microfacet.h).  Nothing here knows a material type; the rooms that do call in:

       material.c  (diffuse, dielectric, thin dielectric, diffuse transmission,
                    and the dispatch)  ->  conductor.c, layered.c, microfacet.c
       conductor.c (the conductor BRDF)                 ->  microfacet.c
       layered.c   (coateddiffuse, coatedconductor)     ->  microfacet.c, medium.c
       microfacet.c                                     ->  util.c, spectrum.c only

   so the material rooms form no cycle.  Everything works in the local shading
   frame (n = +z), with directions pointing AWAY from the surface.

   1. Directions.  reflect_dir(w, n) = 2 (w.n) n - w.  refract_dir: Snell's law,
      wt = -w/eta + (cos_i/eta - cos_t) n with n and eta flipped when w is
      inside, cos_t = sqrt(1 - sin^2 i / eta^2), none on total internal
      reflection; *etap receives the index ratio along the path.

   2. Fresnel for unpolarised light (Born & Wolf, "Principles of Optics", section
      1.5.2 and 14.2; pbrt 4th ed. section 9.3):
          sin^2 t = (1 - cos^2 i)/eta^2,  TIR if >= 1,
          r_par  = (eta cos i - cos t)/(eta cos i + cos t),
          r_perp = (cos i - eta cos t)/(cos i + eta cos t),  F = (|r_par|^2 + |r_perp|^2)/2.
      fresnel_dielectric takes a real eta (cos_i < 0: the ray is inside, eta is
      inverted).  fresnel_conductor takes the complex index eta_c = n + i k of a
      metal; the same formulas hold with complex numbers (cos t the principal
      root), and 1 - F is absorbed within a skin depth.  At normal incidence
      F = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).  The complex arithmetic is done
      in double with a small type of our own (C99's complex.h is optional and
      missing in some compilers).  pbrt-v4's conductor "reflectance" r stands
      for n = 1, k = 2 sqrt(r) / sqrt(1 - r), whose normal-incidence F is r
      (conductor_k_of_reflectance).  mat_eta is a material's real index at one
      wavelength (a sampled 0 means 1, as in pbrt-v4).

   3. The Trowbridge-Reitz (GGX) distribution, anisotropic with alpha_x along
      the frame's s axis and alpha_y along t; the isotropic case is
      alpha_x = alpha_y (Trowbridge & Reitz 1975; Walter et al. 2007,
      "Microfacet Models for Refraction through Rough Surfaces"; the
      anisotropic forms as in Heitz 2014, "Understanding the
      Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2)):
          D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)        (wm = (x, y, z))
          Lambda(w) = (sqrt(1 + (ax^2 w.x^2 + ay^2 w.y^2) / w.z^2) - 1) / 2
          G1(w) = 1 / (1 + Lambda(w)),  G(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi))
                                                    (height-correlated Smith)
          D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / |cos wo|   (the visible normals)
      tr_sample_wm draws wm from D_wo (Heitz 2018, "Sampling the GGX
      Distribution of Visible Normals", JCGT 7(4)); tr_pdf_wm is D_wo.  With
      ax = ay = alpha, D = alpha^2 / (pi (z^2 (alpha^2 - 1) + 1)^2) and
      Lambda = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2, THEORY §10's (10).
      A reflection wi = reflect_dir(wo, wm) has the density
      D_wo(wm) / (4 |wo.wm|) (tr_pdf_reflect; the half vector: tr_half_vector).
      Both alphas below 1e-3 count as a smooth surface (tr_smooth, pbrt-v4's
      EffectivelySmooth); a rough one keeps each alpha at least 1e-4
      (tr_rough_floor, as pbrt-v4's distribution does); the scene's "roughness" becomes alpha = sqrt(roughness)
      when remapped (tr_alpha_of_roughness, pbrt-v4's RoughnessToAlpha).

   4. The rough dielectric interface (Walter et al. 2007; THEORY §10, (11) and
      (12)), alphas alpha_x, alpha_y (tr_dielectric_pair: both alpha),
      index eta, for a pair (wo, wi): tr_dielectric_pair gives f in radiance mode and the pdf of sampling wi by a visible normal wm
      followed by the choice of reflection (probability F) or refraction (1 - F),
      restricted to the lobes asked for (LOBE_R, LOBE_T: the pdf of the chosen
      lobes renormalised to 1).  eta' is eta entering (cos o > 0), 1/eta leaving:
        reflection:   wm = normalize(wo + wi) turned to +z
          f = D G F / (4 |cos i cos o|),   p = D_wo(wm) / (4 |wo.wm|) * F
        transmission: wm = normalize(eta' wi + wo) turned to +z,
                      d = (wi.wm + wo.wm/eta')^2
          f = D G (1 - F) |wi.wm| |wo.wm| / (|cos i cos o| d) / eta'^2
          p = D_wo(wm) |wi.wm| / d * (1 - F)
      A microfacet seen from behind by wo or wi contributes nothing.  material.c's
      rough dielectric and layered.c's rough coat both call it. */
#include "specnee.h"

/* ---------------------------------------------------------------- directions */

Vec3 reflect_dir(Vec3 w, Vec3 n)
{
    return v3_sub(v3_mul(n, 2.0f * v3_dot(w, n)), w);
}

/* wt = -w/eta + (cos_i/eta - cos_t) n, with n and eta flipped when w is inside. */
int refract_dir(Vec3 w, Vec3 n, float eta, float *etap, Vec3 *wt)
{
    float cos_i = v3_dot(n, w), sin2_i, sin2_t, cos_t;
    if (cos_i < 0.0f) { eta = 1.0f / eta; cos_i = -cos_i; n = v3_neg(n); }
    sin2_i = 1.0f - cos_i * cos_i;
    if (sin2_i < 0.0f) sin2_i = 0.0f;
    sin2_t = sin2_i / (eta * eta);
    if (sin2_t >= 1.0f) return 0;
    cos_t = sqrtf(1.0f - sin2_t);
    *wt = v3_add(v3_mul(v3_neg(w), 1.0f / eta), v3_mul(n, cos_i / eta - cos_t));
    if (etap) *etap = eta;
    return 1;
}

/* ---------------------------------------------------------------- Fresnel */

float mat_eta(const Material *m, float lambda_nm)
{
    float eta = spec_eval(m->eta, lambda_nm);
    return eta > 0.0f ? eta : 1.0f;           /* pbrt-v4: a sampled eta of 0 means 1 */
}

float fresnel_dielectric(float cos_i, float eta)
{
    float sin2_t, cos_t, r_par, r_perp;
    if (cos_i < 0.0f) { eta = 1.0f / eta; cos_i = -cos_i; }   /* inside: swap media */
    if (cos_i > 1.0f) cos_i = 1.0f;
    sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;                          /* total internal reflection */
    cos_t = sqrtf(1.0f - sin2_t);
    r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_par * r_par + r_perp * r_perp);
}

typedef struct { double re, im; } Cplx;

static Cplx cx(double re, double im) { Cplx z; z.re = re; z.im = im; return z; }
static Cplx cx_add(Cplx a, Cplx b) { return cx(a.re + b.re, a.im + b.im); }
static Cplx cx_sub(Cplx a, Cplx b) { return cx(a.re - b.re, a.im - b.im); }
static Cplx cx_mul(Cplx a, Cplx b) { return cx(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re); }
static double cx_norm2(Cplx a) { return a.re * a.re + a.im * a.im; }   /* |a|^2 */
static Cplx cx_div(Cplx a, Cplx b)
{
    double d = cx_norm2(b);
    return cx((a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d);
}
/* The principal square root (real part >= 0):
   sqrt(z) = sqrt((|z| + re)/2) + i sign(im) sqrt((|z| - re)/2). */
static Cplx cx_sqrt(Cplx z)
{
    double r = sqrt(cx_norm2(z));
    double a = sqrt(fmax(0.0, 0.5 * (r + z.re))), b = sqrt(fmax(0.0, 0.5 * (r - z.re)));
    return cx(a, z.im < 0.0 ? -b : b);
}

float fresnel_conductor(float cos_i_f, float eta, float k)
{
    double cos_i = cos_i_f < 0.0f ? 0.0 : cos_i_f > 1.0f ? 1.0 : (double)cos_i_f;
    Cplx n = cx(eta, k), ci = cx(cos_i, 0.0);
    Cplx sin2_t = cx_div(cx(1.0 - cos_i * cos_i, 0.0), cx_mul(n, n));
    Cplx cos_t = cx_sqrt(cx_sub(cx(1.0, 0.0), sin2_t));
    Cplx r_par = cx_div(cx_sub(cx_mul(n, ci), cos_t), cx_add(cx_mul(n, ci), cos_t));
    Cplx r_perp = cx_div(cx_sub(ci, cx_mul(n, cos_t)), cx_add(ci, cx_mul(n, cos_t)));
    return (float)(0.5 * (cx_norm2(r_par) + cx_norm2(r_perp)));
}

/* A textured reflectance r stands for eta = 1, k = 2 sqrt(r) / sqrt(1 - r), r
   clamped to [0, 0.9999] by the caller (pbrt-v4 ConductorMaterial::GetBxDF). */
float conductor_k_of_reflectance(double r)
{
    return (float)(2.0 * sqrt(r) / sqrt(1.0 - r));
}

/* ---------------------------------------------------------------- Trowbridge-Reitz */

float tr_D(float ax, float ay, Vec3 wm)
{
    double x = wm.x / ax, y = wm.y / ay, z = wm.z, e = x * x + y * y + z * z;
    if (wm.z <= 0.0f) return 0.0f;           /* grazing or back-facing microfacet */
    return (float)(1.0 / (SPECNEE_PI * ax * ay * e * e));
}

/* Smith's Lambda: the projected area of the microfacets wo cannot see, per unit
   projected area of the macrosurface. */
static float tr_lambda(float ax, float ay, Vec3 w)
{
    double z2 = (double)w.z * w.z, a2t2;
    if (z2 == 0.0) return 1e30f;             /* grazing: everything masked */
    a2t2 = ((double)ax * ax * w.x * w.x + (double)ay * ay * w.y * w.y) / z2;
    return (float)(0.5 * (sqrt(1.0 + a2t2) - 1.0));
}

static float tr_G1(float ax, float ay, Vec3 w) { return 1.0f / (1.0f + tr_lambda(ax, ay, w)); }

float tr_G(float ax, float ay, Vec3 wo, Vec3 wi)
{
    return 1.0f / (1.0f + tr_lambda(ax, ay, wo) + tr_lambda(ax, ay, wi));
}

float tr_pdf_wm(float ax, float ay, Vec3 wo, Vec3 wm)
{
    float c = fabsf(wo.z);
    if (c == 0.0f) return 0.0f;
    return tr_G1(ax, ay, wo) * fabsf(v3_dot(wo, wm)) * tr_D(ax, ay, wm) / c;
}

/* Heitz 2018: (1) stretch wo into the configuration where the roughness is 1,
   (2) sample a point on the projection of the hemisphere seen from there (a disk
   whose lower half is squashed by (1 + cos)/2), (3) lift it onto the hemisphere
   and unstretch the normal.  wo below the surface is mirrored first (the
   visible normals of the macrosurface face up). */
Vec3 tr_sample_wm(float ax, float ay, Vec3 wo, float u1, float u2)
{
    Vec3 vh = v3_norm(v3(ax * wo.x, ay * wo.y, wo.z)), t1, t2, nh;
    float lensq, r, phi, p1, p2, s;
    if (vh.z < 0.0f) vh = v3_neg(vh);
    lensq = vh.x * vh.x + vh.y * vh.y;
    t1 = lensq > 1e-14f ? v3_mul(v3(-vh.y, vh.x, 0.0f), 1.0f / sqrtf(lensq)) : v3(1, 0, 0);
    t2 = v3_cross(vh, t1);
    r = sqrtf(u1);                           /* a uniform point on the unit disk */
    phi = 2.0f * PI_F * u2;
    p1 = r * cosf(phi);
    p2 = r * sinf(phi);
    s = 0.5f * (1.0f + vh.z);                /* the visible part of the disk's lower half */
    p2 = (1.0f - s) * sqrtf(fmaxf(0.0f, 1.0f - p1 * p1)) + s * p2;
    nh = v3_add(v3_add(v3_mul(t1, p1), v3_mul(t2, p2)),
                v3_mul(vh, sqrtf(fmaxf(0.0f, 1.0f - p1 * p1 - p2 * p2))));
    return v3_norm(v3(ax * nh.x, ay * nh.y, fmaxf(1e-6f, nh.z)));
}

/* pbrt-v4's TrowbridgeReitzDistribution::EffectivelySmooth: with both alphas
   below 1e-3 the surface scatters into a delta lobe. */
int tr_smooth(float ax, float ay)
{
    return fmaxf(ax, ay) < 1e-3f;
}

/* pbrt-v4's TrowbridgeReitzDistribution keeps each alpha of a rough surface
   (tr_smooth false) at least 1e-4: one axis of alpha 0 beside a rough one would
   leave D the 0/0 of x/alpha_x.  A smooth pair is left as it is. */
void tr_rough_floor(float *ax, float *ay)
{
    if (tr_smooth(*ax, *ay)) return;
    if (*ax < 1e-4f) *ax = 1e-4f;
    if (*ay < 1e-4f) *ay = 1e-4f;
}

/* pbrt-v4's RoughnessToAlpha ("remaproughness"): alpha = sqrt(roughness). */
float tr_alpha_of_roughness(float roughness)
{
    return sqrtf(roughness);
}

/* pbrt-v4's TrowbridgeReitzDistribution::Regularize (the Integrator's "bool
   regularize", THEORY §15): an alpha below 0.3 becomes clamp(2 alpha, 0.1, 0.3),
   so a smooth surface turns glossy (alpha 0.1); 0.3 and above stay. */
float tr_regularize(float alpha)
{
    if (!(alpha < 0.3f)) return alpha;
    alpha *= 2.0f;
    return alpha < 0.1f ? 0.1f : alpha > 0.3f ? 0.3f : alpha;
}

/* The reflection half vector wm = normalize(wo + wi), turned to +z (the
   microfacet normals face up); 0 when wo = -wi, where it has none. */
int tr_half_vector(Vec3 wo, Vec3 wi, Vec3 *wm)
{
    Vec3 h = v3_add(wo, wi);
    if (v3_dot(h, h) == 0.0f) return 0;
    h = v3_norm(h);
    *wm = h.z < 0.0f ? v3_neg(h) : h;
    return 1;
}

/* The density of wi = reflect_dir(wo, wm) for wm ~ D_wo: the Jacobian of the
   reflection, dwm/dwi = 1 / (4 |wo.wm|), times D_wo(wm). */
float tr_pdf_reflect(float ax, float ay, Vec3 wo, Vec3 wm)
{
    return tr_pdf_wm(ax, ay, wo, wm) / (4.0f * fabsf(v3_dot(wo, wm)));
}

/* ---------------------------------------------------------------- the rough dielectric */

void tr_dielectric_pair(float alpha, float eta, Vec3 wo, Vec3 wi, int lobes, float *f, float *pdf)
{
    tr_dielectric_pair_xy(alpha, alpha, eta, wo, wi, lobes, f, pdf);
}

void tr_dielectric_pair_xy(float ax, float ay, float eta, Vec3 wo, Vec3 wi, int lobes, float *f,
                           float *pdf)
{
    float co = wo.z, ci = wi.z, etap = 1.0f, F, pr, pt;
    int reflect = ci * co > 0.0f;
    Vec3 wm;
    *f = 0.0f; *pdf = 0.0f;
    if (ci == 0.0f || co == 0.0f) return;
    if (!reflect) etap = co > 0.0f ? eta : 1.0f / eta;
    wm = v3_add(v3_mul(wi, etap), wo);                 /* generalised half vector */
    if (v3_dot(wm, wm) == 0.0f) return;
    wm = v3_norm(wm);
    if (wm.z < 0.0f) wm = v3_neg(wm);
    if (v3_dot(wm, wi) * ci < 0.0f || v3_dot(wm, wo) * co < 0.0f) return;   /* back-facing */
    F = fresnel_dielectric(v3_dot(wo, wm), eta);
    pr = (lobes & LOBE_R) ? F : 0.0f;
    pt = (lobes & LOBE_T) ? 1.0f - F : 0.0f;
    if (reflect) {
        *f = tr_D(ax, ay, wm) * tr_G(ax, ay, wo, wi) * F / fabsf(4.0f * ci * co);
        if (pr + pt > 0.0f)
            *pdf = tr_pdf_reflect(ax, ay, wo, wm) * pr / (pr + pt);
    } else {
        float d = v3_dot(wi, wm) + v3_dot(wo, wm) / etap, denom = d * d;
        if (denom == 0.0f) return;
        *f = tr_D(ax, ay, wm) * tr_G(ax, ay, wo, wi) * (1.0f - F) *
             fabsf(v3_dot(wi, wm) * v3_dot(wo, wm) / (ci * co * denom)) / (etap * etap);
        if (pr + pt > 0.0f)
            *pdf = tr_pdf_wm(ax, ay, wo, wm) * fabsf(v3_dot(wi, wm)) / denom * pt / (pr + pt);
    }
    if (!isfinite(*f) || !isfinite(*pdf)) { *f = 0.0f; *pdf = 0.0f; }
}
