/* conductor.c - metals: pbrt-v4's "conductor" material, the Fresnel reflectance of
   a complex index of refraction over a smooth (delta) or rough (anisotropic
   Trowbridge-Reitz / GGX) surface.

   Exported: fresnel_conductor, conductor_sample, conductor_eval, and the
   anisotropic microfacet distribution tr_D, tr_G, tr_sample_wm, tr_pdf_wm
   (specnee.h section 6).  material.c's bsdf_sample and bsdf_eval call
   conductor_sample / conductor_eval in the shading frame (n = +z, directions
   pointing away from the surface, f without the cosine, as everywhere).

   1. Fresnel for a conductor (Born & Wolf, "Principles of Optics", section 14.2;
      pbrt-v4 FrComplex, pbrt 4th ed. section 9.3.6).  The metal's index is complex,
      eta_c = n + i k (n: the "eta" spectrum, k: the extinction coefficient).
      Snell's law and the Fresnel amplitudes hold unchanged with complex numbers:
          sin^2 t = sin^2 i / eta_c^2,   cos t = sqrt(1 - sin^2 t)   (principal root)
          r_par  = (eta_c cos i - cos t) / (eta_c cos i + cos t)
          r_perp = (cos i - eta_c cos t) / (cos i + eta_c cos t)
          F = (|r_par|^2 + |r_perp|^2) / 2          (unpolarised light)
      At normal incidence F = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).  No light is
      transmitted (it is absorbed within a skin depth), so 1 - F is lost.  The
      arithmetic is done in double with a small complex type of our own (C99's
      complex.h is optional and missing in some compilers).

   2. Smooth (max(alpha_x, alpha_y) < 1e-3, pbrt-v4's EffectivelySmooth): the
      mirror direction wi = (-wo.x, -wo.y, wo.z) with probability 1; as a delta
      lobe its "f" is F(|cos i|) / |cos i| and its pdf 1, so the path weight
      f |cos| / pdf is F: each wavelength keeps F of its own.

   3. Rough: the Torrance-Sparrow microfacet BRDF with the anisotropic
      Trowbridge-Reitz distribution (Trowbridge & Reitz 1975; Walter et al. 2007
      for GGX; the anisotropic form as in Heitz 2014, "Understanding the
      Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2)), in the
      local frame, wm = normalize(wo + wi) turned to +z:
          D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)        (wm = (x, y, z))
          Lambda(w) = (sqrt(1 + (ax^2 w.x^2 + ay^2 w.y^2) / w.z^2) - 1) / 2
          G(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi))   (height-correlated Smith)
          f(wo, wi) = D(wm) F(|wo.wm|) G(wo, wi) / (4 |cos i| |cos o|)
      Directions: a visible normal wm ~ D_wo(wm) = G1(wo) |wo.wm| D(wm) / |cos o|
      (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4):
      stretch wo by (ax, ay), sample the projected hemisphere, unstretch), then
      wi = reflect(wo, wm); the Jacobian of the reflection, dwm/dwi = 1/(4 |wo.wm|),
      gives p(wi) = D_wo(wm) / (4 |wo.wm|).  The direction does not depend on the
      wavelength, so every wavelength has the same pdf (pdf_l[j] = pdf) and only F
      differs.  A wo below the surface (a back face) is handled by symmetry: the
      visible normals of -wo are sampled and wi stays on wo's side.

   4. Textures (pbrt-v4 evaluates a material's textures at the hit, in GetBxDF):
      the alphas and a "texture reflectance" come in a MatPoint (material.c's
      mat_point), so one conductor can be smooth at one point and rough at another.

   The anisotropy's axes are the shading frame's s and t; pbrt-v4 puts them on
   the surface's dp/du, which specnee does not have, so the parser accepts
   isotropic roughness only (the functions here take both alphas; the tests use
   anisotropic ones). */
#include "specnee.h"

/* ---------------------------------------------------------------- complex Fresnel */

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

/* ---------------------------------------------------------------- anisotropic GGX */

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
   and unstretch the normal.  wo below the surface is mirrored first. */
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

/* ---------------------------------------------------------------- the BRDF */

/* pbrt-v4's TrowbridgeReitzDistribution::EffectivelySmooth. */
static int conductor_smooth(const MatPoint *mp)
{
    return fmaxf(mp->alpha, mp->alpha_t) < 1e-3f;
}

/* F of wavelength j (lambda) at the microfacet cosine c.  A textured reflectance r
   stands for eta = 1, k = 2 sqrt(r) / sqrt(1 - r), r clamped to [0, 0.9999]
   (pbrt-v4 ConductorMaterial::GetBxDF; scene.c does the same for a constant r). */
float conductor_k_of_reflectance(double r)
{
    return (float)(2.0 * sqrt(r) / sqrt(1.0 - r));
}

static float conductor_F(const Material *m, const MatPoint *mp, int j, float c, float lambda_nm)
{
    if (mp->has_r) {
        double r = mp->r[j] < 0.9999f ? mp->r[j] : 0.9999;
        return fresnel_conductor(c, 1.0f, conductor_k_of_reflectance(r));
    }
    return fresnel_conductor(c, spec_eval(&m->eta, lambda_nm), spec_eval(&m->k, lambda_nm));
}

/* f and pdf of the rough conductor for a pair of local directions (0 when they
   lie on different sides or the pair has no half vector). */
static void rough_pair(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                       unsigned alive, float f[HERO_N], float pdf_l[HERO_N])
{
    float ax = mp->alpha, ay = mp->alpha_t, cos_o = fabsf(wo.z), cos_i = fabsf(wi.z), D, G, pdf, c;
    Vec3 wm;
    int j;
    for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
    if (wo.z * wi.z <= 0.0f) return;         /* a BRDF: both on one side */
    wm = v3_add(wo, wi);
    if (v3_dot(wm, wm) == 0.0f) return;
    wm = v3_norm(wm);
    if (wm.z < 0.0f) wm = v3_neg(wm);        /* the microfacet normal faces +z */
    c = fabsf(v3_dot(wo, wm));
    if (c == 0.0f) return;
    D = tr_D(ax, ay, wm);
    G = tr_G(ax, ay, wo, wi);
    pdf = tr_pdf_wm(ax, ay, wo, wm) / (4.0f * c);
    for (j = 0; j < HERO_N; j++) {
        pdf_l[j] = pdf;                      /* the same direction for every wavelength */
        if (alive & (1u << j))
            f[j] = D * G * conductor_F(m, mp, j, c, lambda[j]) / (4.0f * cos_i * cos_o);
    }
}

int conductor_sample(const Material *m, const MatPoint *mp, Vec3 wo, const float *lambda,
                     unsigned alive, float u1, float u2, BsdfSample *out, Vec3 *wi_local)
{
    Vec3 wi, wm;
    int j;
    for (j = 0; j < HERO_N; j++) { out->f[j] = 0.0f; out->pdf_l[j] = 0.0f; }
    out->delta = 0;
    if (wo.z == 0.0f) return 0;
    if (conductor_smooth(mp)) {
        wi = v3(-wo.x, -wo.y, wo.z);         /* the mirror direction */
        out->delta = 1;
        out->pdf = 1.0f;
        for (j = 0; j < HERO_N; j++) {
            out->pdf_l[j] = 1.0f;
            if (alive & (1u << j))
                out->f[j] = conductor_F(m, mp, j, fabsf(wi.z), lambda[j]) / fabsf(wi.z);
        }
        *wi_local = wi;
        return 1;
    }
    wm = tr_sample_wm(mp->alpha, mp->alpha_t, wo, u1, u2);
    wi = v3_sub(v3_mul(wm, 2.0f * v3_dot(wo, wm)), wo);     /* reflect wo about wm */
    if (wi.z * wo.z <= 0.0f) return 0;       /* reflected below the surface: no sample */
    wi = v3_norm(wi);
    rough_pair(m, mp, wo, wi, lambda, alive, out->f, out->pdf_l);
    out->pdf = out->pdf_l[0];
    *wi_local = wi;
    return out->pdf > 0.0f;
}

void conductor_eval(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                    unsigned alive, float f[HERO_N], float pdf_l[HERO_N])
{
    int j;
    if (conductor_smooth(mp)) {               /* delta: f = 0 for any given pair */
        for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
        return;
    }
    rough_pair(m, mp, wo, wi, lambda, alive, f, pdf_l);
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   conductor_from_params: the scene builder's (scene.c) "conductor" material,
   read from its parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* pbrt-v4 ConductorMaterial: eta and k, or a reflectance that
   stands for them; Cu by default */
int conductor_from_params(Parser *P, ParamList *pl, const char *file, int line,
                          const char *dir, const char *what, Material *m)
{
    Param *pe = find_spectrum_param(pl, "eta"), *pk = find_spectrum_param(pl, "k");
    Param *pr = find_spectrum_param(pl, "reflectance");
    Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
    int nm;
    (void)dir;
    m->type = MAT_CONDUCTOR;
    if (!microfacet_alphas(P, pl, file, line, what, &m->alpha, &m->alpha_t, &m->alpha_tex,
                           &m->remap))
        return 0;
    if (!params_check_unused(P, pl, what, "spectrum eta, spectrum k, spectrum reflectance, "
                             "rgb reflectance, texture reflectance, float roughness, "
                             "float uroughness, float vroughness, texture roughness, "
                             "texture uroughness, texture vroughness, bool remaproughness",
                             "displacement normalmap"))
        return 0;
    if ((pr || pt) && (pe || pk))
        return fail(P, file, line, "%s: give either \"reflectance\" or \"eta\" and \"k\", "
                    "not both (pbrt-v4 refuses it too)", what);
    if (pt) {
        /* "texture reflectance": r read at each hit (material.c mat_point), eta = 1
           and k from r there (conductor_k_of_reflectance) */
        int ti = texture_lookup(P, pt, 0);
        if (ti < 0) return 0;
        m->reflectance_tex = ti + 1;
        spec_const(&m->eta, 1.0f);
        spec_const(&m->k, 0.0f);                  /* (not read) */
    } else if (pr) {
        /* pbrt-v4: r clamped to [0, 0.9999], eta = 1, k = 2 sqrt(r) / sqrt(1 - r),
           which makes the normal-incidence reflectance ((eta-1)^2 + k^2) /
           ((eta+1)^2 + k^2) = k^2 / (4 + k^2) exactly r */
        if (!param_spectrum(P, pr, SPEC_ALBEDO, &m->reflectance, NULL)) return 0;
        if (!check_unit_spectrum(P, pr, &m->reflectance)) return 0;
        spec_const(&m->eta, 1.0f);
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
            double r = spec_get(&m->reflectance, nm);
            if (r > 0.9999) r = 0.9999;
            *spec_at(&m->k, nm) = conductor_k_of_reflectance(r);
        }
    } else {
        if (pe) { if (!param_spectrum(P, pe, SPEC_UNBOUNDED, &m->eta, NULL)) return 0; }
        else spec_named(&m->eta, "metal-Cu-eta");
        if (pk) { if (!param_spectrum(P, pk, SPEC_UNBOUNDED, &m->k, NULL)) return 0; }
        else spec_named(&m->k, "metal-Cu-k");
        if (!check_spectrum_above(P, pe, file, line, "\"spectrum eta\" of a conductor",
                                  &m->eta, 0.0f, 1) ||
            !check_spectrum_above(P, pk, file, line, "\"spectrum k\" of a conductor",
                                  &m->k, 0.0f, 0))
            return 0;
    }
    if (m->alpha != m->alpha_t)
        return fail(P, file, line, "%s: anisotropic roughness (u %g, v %g after the remap) "
                    "is valid pbrt-v4 but not in the specnee subset (its axes follow the "
                    "surface's dp/du, which specnee does not have)", what, m->alpha,
                    m->alpha_t);
    return 1;
}
