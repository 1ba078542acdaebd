/* material.c - the materials the scenes need: diffuse, (dispersive) glass, a
   diffuse fluorescent layer, pbrt-v4's thindielectric and diffusetransmission, and
   the dispatch to conductors (conductor.c), coateddiffuse and coatedconductor
   (layered.c), hair (hair.c) and subsurface (subsurface.c: its boundary is the
   dielectric below, its exit lobe Sw is subsurface.c's).

   Exported: mat_is_delta, mat_point, bsdf_sample, bsdf_eval, mat_albedo, fluor_*
   (specnee.h section 6).  Every sampler has its pdf beside it.  The Fresnel terms,
   reflect_dir, refract_dir, mat_eta and the GGX distribution come from the
   scattering room (microfacet.c); this room calls it, conductor.c and layered.c,
   and none of them calls back.

   Fluorescent (docs/FLUORESCENCE.md, F2-F4): f(li -> lo) = (1/pi) [rho(lo)(1 -
   A(lo)) delta(li - lo) + Phi A(li) e(lo) (li/lo) H(lo - li) / N(li)].  bsdf_sample
   and bsdf_eval give its reflect lobe, a Lambertian of albedo rho (1 - A); the
   re-radiate lobe is chosen and weighted by path.c with fluor_branch_pf,
   fluor_sample_li and fluor_weight, after which the vertex is a Lambertian of
   albedo 1 at the excitation wavelength li.

   Conventions.  wo and wi are unit world directions pointing AWAY from the
   surface; BSDF values f carry no cosine (the integrator multiplies |cos theta_i|
   with the shading normal).  Directions are sampled with the hero wavelength
   lambda[0]; f is returned for every alive wavelength.

   Diffuse (Lambert):  f = R(lambda)/pi,  wi ~ cos(theta)/pi on wo's side.

   Dielectric, index from Cauchy's law n(lambda) = A + B/lambda^2 (tabulated into
   Material.eta) or any eta spectrum, with the unpolarised Fresnel reflectance F
   of microfacet.c section 2 (fresnel_dielectric).
   Smooth (alpha = 0): reflect with probability F, else refract (Snell); the
   sample's weight f|cos|/p is 1 for reflection and 1/eta'^2 for transmission
   (radiance is compressed by eta'^2 entering a denser medium; eta' is the index
   ratio along the path).

   Rough (GGX / Trowbridge-Reitz, Walter et al. 2007, "Microfacet Models for
   Refraction through Rough Surfaces", EGSR), local frame n = +z, anisotropic
   when the alphas differ: alpha_x ("uroughness") along the shading frame's s
   axis, the surface's dp/du made tangent (mat_frame), alpha_y ("vroughness")
   along t, as pbrt-v4's DielectricBxDF over its TrowbridgeReitzDistribution.
   A visible normal m ~ D_wo (tr_sample_wm(alpha_x, alpha_y)), then reflection
   about m with probability F(wo.m), else refraction through it; f and pdf of
   the pair are microfacet.c's tr_dielectric_pair_xy (section 4: THEORY §10,
   (10)-(12), checked against pbrt-v4's DielectricBxDF).  Roughness textures
   give the alphas at each hit (dielectric_alphas, through mat_point); where
   both are below 1e-3 the hit is smooth (pbrt-v4's EffectivelySmooth), as
   numeric alphas that small are at load time; a rough hit keeps each alpha at
   least 1e-4 (pbrt-v4's distribution does, so that one smooth axis beside a
   rough one still has a finite D).

   Dispersion: with a wavelength-dependent index, the hero's index picks the
   direction.  For other wavelengths f and pdf are evaluated along the SAME
   directions with their own index (needed only by the rough spectral MIS of
   path.c; at smooth dispersive interfaces the other wavelengths have pdf 0).

   Mix (pbrt-v4's MixMaterial): no BSDF of its own; at each hit mat_choose picks
   one of its two materials, the second with probability "amount", by a hash of
   the hit point and wo, so the image is that of a surface whose material varies
   from point to point (and direction to direction) and is the same for any
   thread count.

   The last section builds these materials from a scene's parameters for the
   scene builder (*_from_params, parser.h). */
#include "specnee.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

float mat_albedo(const Material *m, float lambda_nm)
{
    float rho = albedo_eval(&m->reflectance, lambda_nm);
    if (m->type == MAT_FLUORESCENT) return rho * (1.0f - spec_eval(&m->fl->excitation, lambda_nm));
    return rho;
}

float mat_albedo_at(const Material *m, const SurfacePoint *sp, float lambda_nm)
{
    float rho;
    if (m->reflectance_tex <= 0 || !m->textures) return mat_albedo(m, lambda_nm);
    rho = tex_eval(m->textures, m->reflectance_tex - 1, sp, lambda_nm);   /* texture.c */
    return rho > 0.0f ? (rho < 1.0f ? rho : 1.0f) : 0.0f;               /* NaN: 0 */
}

int mat_reads_uv(const Material *m)
{
    int sss_tex = m->sss && (m->sss->tex[SSS_TEX_SIGMA_A] || m->sss->tex[SSS_TEX_SIGMA_S] ||
                             m->sss->tex[SSS_TEX_MFP]);
    if (m->extra && (m->extra->eta_tex > 0 || m->extra->k_tex > 0)) return 1;   /* conductors */
    if (m->thickness_tex > 0 || m->g_tex > 0 || m->albedo_tex > 0) return 1;   /* layered */
    if (m->alpha_t_tex > 0 || m->cond_alpha_t_tex > 0) return 1;   /* textured t-axis roughness */
    return m->reflectance_tex > 0 || m->alpha_tex > 0 || m->cond_alpha_tex > 0 || sss_tex ||
           m->type == MAT_MIX || m->bump || (m->extra && m->extra->transmittance_tex > 0);
}

/* The bits of a float, for hashing (equal floats of equal sign hash alike). */
static uint64_t float_bits(float x)
{
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

/* pbrt-v4 hashes the bytes of (p, wo, the two material pointers); specnee hashes
   the same point and direction with the two materials' indices (hash_u64, util.c),
   so the choice is as deterministic, though not the same number as pbrt-v4's. */
int mat_choose(const Material *materials, int mi, const SurfacePoint *sp, Vec3 wo)
{
    while (materials[mi].type == MAT_MIX) {
        const Material *m = &materials[mi];
        float a = m->amount;
        uint64_t h;
        double u;
        if (m->amount_tex > 0) a = tex_eval(m->textures, m->amount_tex - 1, sp, 550.0f);
        if (a <= 0.0f) { mi = m->mix[0]; continue; }
        if (a >= 1.0f) { mi = m->mix[1]; continue; }
        h = hash_u64(float_bits(sp->p.x) << 32 | float_bits(sp->p.y),
                     float_bits(sp->p.z) << 32 | float_bits(wo.x));
        h = hash_u64(h, float_bits(wo.y) << 32 | float_bits(wo.z));
        h = hash_u64(h, (uint64_t)(uint32_t)m->mix[0] << 32 | (uint32_t)m->mix[1]);
        u = (double)(uint32_t)h * (1.0 / 4294967296.0);      /* in [0, 1) */
        mi = (double)a < u ? m->mix[0] : m->mix[1];
    }
    return mi;
}

/* A conductor's textured eta or k (coatedconductor: its base's) at the point, at
   each alive wavelength; the one not textured is the material's spectrum.  pbrt-v4
   reads them unbounded and unclamped; specnee keeps k >= 0 and eta >= 1e-3 (NaN:
   those bounds), where the Fresnel equations of a complex index stay finite. */
static void mat_point_ek(const Material *m, const SurfacePoint *sp, const float *lambda,
                         unsigned alive, MatPoint *mp)
{
    const Spectrum *n = m->type == MAT_COATED_CONDUCTOR ? &m->extra->cond_eta : m->eta;
    int j, te = m->extra->eta_tex, tk = m->extra->k_tex;
    mp->has_ek = 1;
    for (j = 0; j < HERO_N; j++) {
        float e = 1.0f, k = 0.0f;
        if (alive & (1u << j)) {
            e = te > 0 ? tex_eval(m->textures, te - 1, sp, lambda[j]) : spec_eval(n, lambda[j]);
            k = tk > 0 ? tex_eval(m->textures, tk - 1, sp, lambda[j]) : spec_eval(&m->extra->k, lambda[j]);
        }
        mp->eta[j] = e >= 1e-3f ? e : 1e-3f;
        mp->k[j] = k > 0.0f ? k : 0.0f;
    }
}

/* A texture's value at the point (at lambda), clamped to [lo, hi] (NaN: lo). */
static float tex_clamped(const Material *m, int tex, const SurfacePoint *sp, float lambda,
                         float lo, float hi)
{
    float v = tex_eval(m->textures, tex - 1, sp, lambda);
    return v > lo ? (v < hi ? v : hi) : lo;
}

/* A roughness texture's GGX alpha at sp (pbrt-v4, per axis): the texture's value,
   then RoughnessToAlpha (sqrt) when remapped; a negative value (or NaN) counts as 0,
   a smooth point; widened as mat_regularized widens the numbers. */
static float rough_alpha_at(const Material *m, int tex, const SurfacePoint *sp, const float *lambda)
{
    float v = tex_clamped(m, tex, sp, lambda[0], 0.0f, 1e4f);
    v = m->remap ? tr_alpha_of_roughness(v) : v;
    return m->regularized ? tr_regularize(v) : v;
}

/* A layered material's slab at the point, with pbrt-v4's bounds (GetBxDF and
   LayeredBxDF): a textured thickness at least FLT_MIN (and at most 1e30, as the
   float), g clamped to [-1, 1] and then to HenyeyGreenstein's [-0.99, 0.99], the
   albedo to [0, 1] at each wavelength. */
static void mat_point_slab(const Material *m, const SurfacePoint *sp, const float *lambda,
                           unsigned alive, MatPoint *mp)
{
    int j;
    mp->thick = m->thickness;
    mp->g = m->hg_g;
    mp->has_a = 0;
    if (!m->textures) return;
    if (m->thickness_tex > 0) mp->thick = tex_clamped(m, m->thickness_tex, sp, lambda[0], FLT_MIN, 1e30f);
    if (m->g_tex > 0) mp->g = tex_clamped(m, m->g_tex, sp, lambda[0], -0.99f, 0.99f);
    if (m->albedo_tex > 0) {
        mp->has_a = 1;
        for (j = 0; j < HERO_N; j++)
            mp->a[j] = (alive & (1u << j)) ? tex_clamped(m, m->albedo_tex, sp, lambda[j], 0.0f, 1.0f) : 0.0f;
    }
}

void mat_point(const Material *m, const SurfacePoint *sp, const float *lambda, unsigned alive,
               MatPoint *mp)
{
    int j;
    mp->alpha = m->alpha;
    mp->alpha_t = m->alpha_t;
    mp->has_r = 0;
    mp->cond_alpha = m->cond_alpha;
    mp->cond_alpha_t = m->cond_alpha_t;
    mp->has_ek = 0;
    mat_point_slab(m, sp, lambda, alive, mp);
    if (!m->textures) return;
    if (m->alpha_tex > 0) mp->alpha = rough_alpha_at(m, m->alpha_tex, sp, lambda);
    if (m->alpha_t_tex > 0)                      /* one texture for both axes: read once */
        mp->alpha_t = m->alpha_t_tex == m->alpha_tex ? mp->alpha
                                                     : rough_alpha_at(m, m->alpha_t_tex, sp, lambda);
    if (m->cond_alpha_tex > 0)                   /* coatedconductor's base, the same rule */
        mp->cond_alpha = rough_alpha_at(m, m->cond_alpha_tex, sp, lambda);
    if (m->cond_alpha_t_tex > 0)
        mp->cond_alpha_t = m->cond_alpha_t_tex == m->cond_alpha_tex
                               ? mp->cond_alpha : rough_alpha_at(m, m->cond_alpha_t_tex, sp, lambda);
    if (m->reflectance_tex > 0) {
        mp->has_r = 1;
        for (j = 0; j < HERO_N; j++) {
            float r = (alive & (1u << j)) ? tex_eval(m->textures, m->reflectance_tex - 1, sp, lambda[j]) : 0.0f;
            mp->r[j] = r > 0.0f ? (r < 1.0f ? r : 1.0f) : 0.0f;            /* NaN: 0 */
        }
    }
    if (m->extra && (m->extra->eta_tex > 0 || m->extra->k_tex > 0)) mat_point_ek(m, sp, lambda, alive, mp);
}

void material_release(Material *m)
{
    free(m->fl);
    m->fl = NULL;
    bump_free(m->bump);
    m->bump = NULL;
    free(m->hair);
    m->hair = NULL;
    if (m->type != MAT_SUBSURFACE_EXIT) free(m->sss);   /* an exit lobe borrows it */
    m->sss = NULL;
    free(m->extra);
    m->extra = NULL;
    if (m->measured && --m->measured->refs <= 0) {   /* the last material sharing it */
        measured_free(m->measured);
        free(m->measured);
    }
    m->measured = NULL;
}


/* ---- fluorescence: tables at the 1 nm knots 300..830 nm (k = nm - 300) ---- */

int fluor_prepare(Material *m)
{
    int k;
    double acc = 0.0;
    m->fl->cdf[0] = 0.0;
    for (k = 0; k + 1 < FL_N; k++) {      /* exact integral of the linear A per cell */
        acc += 0.5 * ((double)spec_get(&m->fl->excitation, SPEC_UV_MIN + k) +
                      spec_get(&m->fl->excitation, SPEC_UV_MIN + k + 1));
        m->fl->cdf[k + 1] = acc;
    }
    acc = 0.0;
    m->fl->tail[FL_N - 1] = 0.0;
    for (k = FL_N - 2; k >= 0; k--) {      /* N at the knots, from the top down */
        acc += 0.5 * ((double)spec_get(&m->fl->emission, SPEC_UV_MIN + k) +
                      spec_get(&m->fl->emission, SPEC_UV_MIN + k + 1));
        m->fl->tail[k] = acc;
    }
    return m->fl->tail[0] > 0.0;
}

/* The Stokes rule: light absorbed at li leaves at lo >= li only. */
static float stokes_limit(float lo) { return lo; }

/* The running integral of a density that is constant in each 1 nm cell (cdf[k] at
   the knot 300 + k), at x (clamped to the table). */
static double cdf_at(const double *cdf, float x)
{
    double t = (double)x - SPEC_UV_MIN;
    int k;
    if (!(t > 0.0)) return 0.0;
    if (t >= FL_N - 1) return cdf[FL_N - 1];
    k = (int)t;
    return cdf[k] + (t - k) * (cdf[k + 1] - cdf[k]);
}

/* C(x) = integral of A over [300, x] (x clamped to the table). */
static double fluor_cdf_at(const Material *m, float x)
{
    return cdf_at(m->fl->cdf, x);
}

/* N(li) = integral of e over [li, 830]: the tail at the next knot plus the exact
   integral of the linear e over [li, next knot]. */
static double fluor_tail_at(const Material *m, float li)
{
    double t = (double)li - SPEC_UV_MIN;
    int k;
    if (!(t >= 0.0)) return m->fl->tail[0];
    if (t >= FL_N - 1) return 0.0;
    k = (int)t;
    return m->fl->tail[k + 1] + (k + 1 - t) * 0.5 * ((double)spec_eval(&m->fl->emission, li) +
                                                    spec_get(&m->fl->emission, SPEC_UV_MIN + k + 1));
}

float fluor_branch_pf(const Material *m, float lo)
{
    /* Any P_f > 0 wherever re-radiation can contribute is unbiased; specnee uses 1/2
       where both lobes can contribute, else the one that can (docs/FLUORESCENCE.md §3). */
    int can_f = m->type == MAT_FLUORESCENT && fluor_cdf_at(m, stokes_limit(lo)) > 0.0 &&
                spec_eval(&m->fl->emission, lo) > 0.0f && m->fl->qyield > 0.0f;
    int can_r = mat_albedo(m, lo) > 0.0f;
    if (!can_f) return 0.0f;
    return can_r ? 0.5f : 1.0f;
}

float fluor_weight(const Material *m, float li, float lo)
{
    double n;
    if (!(li <= stokes_limit(lo)) || li < (float)SPEC_UV_MIN) return 0.0f;
    n = fluor_tail_at(m, li);
    if (!(n > 0.0)) return 0.0f;
    return (float)((double)m->fl->qyield * spec_eval(&m->fl->excitation, li) * spec_eval(&m->fl->emission, lo)
                   * ((double)li / lo) / n);
}

/* Sample li on [300, lo] from the cell-constant density whose running integral is
   cdf (F3's table, or fluor_power_cdf's); *pdf its density there, 0 if none. */
static float cdf_sample(const double *cdf, float lo, float u, float *pdf)
{
    double c = cdf_at(cdf, stokes_limit(lo)), target, w;
    int a = 0, b, k;
    float li;
    *pdf = 0.0f;
    if (!(c > 0.0)) return (float)SPEC_UV_MIN;
    target = (double)u * c;
    /* the first cell k with cdf[k + 1] > target (cells of zero weight are skipped) */
    b = FL_N - 1;
    while (a + 1 < b) {
        int mid = (a + b) / 2;
        if (cdf[mid] <= target) a = mid; else b = mid;
    }
    k = a;
    w = cdf[k + 1] - cdf[k];
    if (!(w > 0.0)) return (float)SPEC_UV_MIN;
    li = (float)(SPEC_UV_MIN + k + (target - cdf[k]) / w);
    if (li > stokes_limit(lo)) li = stokes_limit(lo);
    *pdf = (float)(w / c);
    return li;
}

static float cdf_pdf(const double *cdf, float lo, float li)
{
    double c = cdf_at(cdf, stokes_limit(lo));
    int k;
    if (!(c > 0.0) || !(li >= (float)SPEC_UV_MIN) || li > stokes_limit(lo)) return 0.0f;
    k = (int)(li - (float)SPEC_UV_MIN);
    if (k > FL_N - 2) k = FL_N - 2;
    return (float)((cdf[k + 1] - cdf[k]) / c);
}

float fluor_sample_li(const Material *m, float lo, float u, float *pdf)
{
    return cdf_sample(m->fl->cdf, lo, u, pdf);
}

float fluor_pdf_li(const Material *m, float lo, float li)
{
    return cdf_pdf(m->fl->cdf, lo, li);
}

/* ---- li in proportion to A x the scene's emitter power, with a defensive share
   of A alone (docs/FLUORESCENCE.md §3, "Excitation wavelength from A x power") ---- */

void fluor_power_cdf(const Material *m, const Spectrum *E, double *cdf)
{
    int k;
    double acc = 0.0;
    cdf[0] = 0.0;
    for (k = 0; k + 1 < FL_N; k++) {      /* the trapezoid of A E over each cell */
        acc += 0.5 * ((double)spec_get(&m->fl->excitation, SPEC_UV_MIN + k) * spec_get(E, SPEC_UV_MIN + k) +
                      (double)spec_get(&m->fl->excitation, SPEC_UV_MIN + k + 1) * spec_get(E, SPEC_UV_MIN + k + 1));
        cdf[k + 1] = acc;
    }
}

/* The share of A alone at lo: a, or 1 where A x power has no mass below lo. */
static float mix_share(const double *pcdf, float a, float lo)
{
    return pcdf && cdf_at(pcdf, stokes_limit(lo)) > 0.0 ? a : 1.0f;
}

float fluor_pdf_li_mix(const Material *m, const double *pcdf, float a, float lo, float li)
{
    float s = mix_share(pcdf, a, lo);
    float p = s * cdf_pdf(m->fl->cdf, lo, li);
    if (s < 1.0f) p += (1.0f - s) * cdf_pdf(pcdf, lo, li);
    return p;
}

float fluor_sample_li_mix(const Material *m, const double *pcdf, float a, float lo, float u, float *pdf)
{
    float s = mix_share(pcdf, a, lo), li, pc;
    /* one number picks the component and, rescaled, samples inside it */
    if (u < s) {
        li = cdf_sample(m->fl->cdf, lo, u / s, &pc);
    } else {
        float v = (u - s) / (1.0f - s);
        li = cdf_sample(pcdf, lo, v < 1.0f ? v : 0.99999994f, &pc);
    }
    *pdf = pc > 0.0f ? fluor_pdf_li_mix(m, pcdf, a, lo, li) : 0.0f;
    return li;
}

/* ---- li uniformly on [300, lo] (--fluor-li uniform; docs/FLUORESCENCE.md §3): blind to A,
   the reference the other two samplers must agree with ---- */

float fluor_sample_li_uniform(float lo, float u, float *pdf)
{
    float w = stokes_limit(lo) - (float)SPEC_UV_MIN, li;
    *pdf = 0.0f;
    if (!(w > 0.0f)) return (float)SPEC_UV_MIN;
    li = (float)SPEC_UV_MIN + u * w;
    if (li > stokes_limit(lo)) li = stokes_limit(lo);
    *pdf = 1.0f / w;
    return li;
}

float fluor_pdf_li_uniform(float lo, float li)
{
    float w = stokes_limit(lo) - (float)SPEC_UV_MIN;
    if (!(w > 0.0f) || !(li >= (float)SPEC_UV_MIN) || li > stokes_limit(lo)) return 0.0f;
    return 1.0f / w;
}

int mat_is_delta(const Material *m)
{
    if (m->type == MAT_CONDUCTOR)                            /* conductor.c */
        return m->alpha_tex <= 0 && m->alpha_t_tex <= 0 && tr_smooth(m->alpha, m->alpha_t);
    if (m->type == MAT_THIN_DIELECTRIC) return 1;
    return (m->type == MAT_DIELECTRIC || m->type == MAT_SUBSURFACE) && m->alpha_tex <= 0 &&
           m->alpha_t_tex <= 0 && m->alpha == 0.0f && m->alpha_t == 0.0f;
}

/* A dielectric's (or a subsurface boundary's) GGX alphas at sp, along the
   shading frame's s and t axes: its numbers, or its roughness textures' values
   (mat_point).  0: a smooth hit, both alphas below 1e-3 (pbrt-v4's
   EffectivelySmooth).  1: rough, each alpha raised to at least 1e-4 as pbrt-v4's
   TrowbridgeReitzDistribution does (one axis 0 beside a rough one would leave D
   the 0/0 of x/alpha_x along that axis). */
static int dielectric_alphas(const Material *m, const SurfacePoint *sp, const float *lambda,
                             float *ax, float *ay)
{
    *ax = m->alpha;
    *ay = m->alpha_t;
    if ((m->alpha_tex > 0 || m->alpha_t_tex > 0) && m->textures) {
        MatPoint mp;
        mat_point(m, sp, lambda, 1u, &mp);
        *ax = mp.alpha;
        *ay = mp.alpha_t;
    }
    if (tr_smooth(*ax, *ay)) return 0;
    *ax = fmaxf(*ax, 1e-4f);
    *ay = fmaxf(*ay, 1e-4f);
    return 1;
}

/* pbrt-v4's BxDF::Regularize: DielectricBxDF, ConductorBxDF and LayeredBxDF (its
   top and bottom) widen their Trowbridge-Reitz alphas; diffuse, thindielectric
   (a TODO in pbrt-v4), diffusetransmission keep theirs.  A dielectric of index 1
   everywhere stays specular, as pbrt-v4's (it passes light straight through
   whatever its alpha). */
int mat_regularized(const Material *m, Material *out)
{
    if (m->type != MAT_DIELECTRIC && m->type != MAT_CONDUCTOR && m->type != MAT_SUBSURFACE &&
        m->type != MAT_COATED_DIFFUSE && m->type != MAT_COATED_CONDUCTOR)
        return 0;
    if (m->type == MAT_DIELECTRIC && spec_is_constant(m->eta) && spec_get(m->eta, SPEC_MIN) == 1.0f)
        return 0;
    *out = *m;
    out->alpha = tr_regularize(m->alpha);
    out->alpha_t = tr_regularize(m->alpha_t);
    out->cond_alpha = tr_regularize(m->cond_alpha);
    out->cond_alpha_t = tr_regularize(m->cond_alpha_t);
    out->regularized = 1;
    return 1;
}

/* ---------------------------------------------------------------- thin dielectric */

/* pbrt-v4's ThinDielectricBxDF: a thin slab (a window pane, a soap film without
   interference) whose two parallel faces reflect F each.  Light bounces between
   the faces; summing the geometric series of the bounces (pbrt 4th ed. section
   9.5.1)
       R' = R + T^2 R (1 + R^2 + R^4 + ...) = R + T^2 R / (1 - R^2),  T = 1 - R,
       T' = 1 - R'                       (no absorption: nothing else is lost)
   with R = F(|cos o|, eta) of one face.  Everything leaves along two directions:
   the mirror direction (R') or straight on, wi = -wo (T': the two refractions
   cancel).  Both are delta lobes; the hero's R'/(R'+T') picks one, and every
   wavelength keeps its own R' or T' (its own probability of that lobe in pdf_l,
   so the spectral MIS ratios see the lobe choice; with a constant eta they are
   all equal).  No 1/eta^2: the light leaves into the medium it came from. */
static float thin_reflectance(float cos_o, float eta)
{
    float R = fresnel_dielectric(fabsf(cos_o), eta), T = 1.0f - R;
    if (R < 1.0f) R += T * T * R / (1.0f - R * R);
    return R;
}

static int thin_sample(const Material *m, Vec3 lo, const float *lambda, unsigned alive,
                       float u0, BsdfSample *out, Vec3 *li)
{
    float R0 = thin_reflectance(lo.z, mat_eta(m, lambda[0]));
    int reflect = u0 < R0, j;
    out->delta = 1;
    *li = reflect ? v3(-lo.x, -lo.y, lo.z) : v3_neg(lo);
    for (j = 0; j < HERO_N; j++) {
        float Rj = j == 0 ? R0 : thin_reflectance(lo.z, mat_eta(m, lambda[j]));
        float pj = reflect ? Rj : 1.0f - Rj;    /* lobe probability with hero j */
        out->pdf_l[j] = pj;
        if (alive & (1u << j)) out->f[j] = pj / fabsf(lo.z);   /* |cos i| = |cos o| */
    }
    out->pdf = out->pdf_l[0];
    return out->pdf > 0.0f;
}

/* ---------------------------------------------------------------- diffuse transmission */

/* pbrt-v4's DiffuseTransmissionBxDF: Lambertian reflection R/pi on wo's side and
   Lambertian transmission T/pi on the other (paper, leaves, lamp shades).
   Sampling picks the side with probability p_reflect, then a cosine direction on
   it:  p(wi) = p_side |cos i| / pi.  With constant R and T, p_reflect is max R over
   max R + max T, fixed at load time (pbrt-v4 takes the maxima over the four
   sampled wavelengths instead; any fixed choice is unbiased).  With a textured R
   or T (pbrt-v4's "texture reflectance"/"texture transmittance", times "scale",
   clamped to [0, 1]) it is pbrt-v4's rule at the point: the maxima over the alive
   wavelengths, the same for every hero, so sampling and evaluation agree.
   Reflection and transmission are told apart by the shading normal alone, as in
   pbrt-v4 (docs/conventions.md §6: no BSDF here looks at the geometric normal). */
typedef struct {
    float R[HERO_N], T[HERO_N];   /* at the four wavelengths (0 where not alive) */
    float p_reflect;              /* probability of sampling the reflect lobe */
} DtPoint;

static float dt_tex(const Material *m, int tex, const SurfacePoint *sp, float lambda)
{
    float v = m->extra->dt_scale * tex_eval(m->textures, tex - 1, sp, lambda);   /* texture.c */
    return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;                                /* NaN: 0 */
}

static void dt_point(const Material *m, const SurfacePoint *sp, const float *lambda,
                     unsigned alive, DtPoint *d)
{
    int j, textured = m->reflectance_tex > 0 || m->extra->transmittance_tex > 0;
    float maxr = 0.0f, maxt = 0.0f;
    for (j = 0; j < HERO_N; j++) {
        d->R[j] = d->T[j] = 0.0f;
        if (!(alive & (1u << j))) continue;
        d->R[j] = m->reflectance_tex > 0 ? dt_tex(m, m->reflectance_tex, sp, lambda[j])
                                         : albedo_eval(&m->reflectance, lambda[j]);
        d->T[j] = m->extra->transmittance_tex > 0 ? dt_tex(m, m->extra->transmittance_tex, sp, lambda[j])
                                                  : spec_eval(&m->extra->transmittance, lambda[j]);
        maxr = fmaxf(maxr, d->R[j]);
        maxt = fmaxf(maxt, d->T[j]);
    }
    d->p_reflect = !textured ? m->p_reflect : maxr + maxt > 0.0f ? maxr / (maxr + maxt) : 0.5f;
}

static int dt_pair(const DtPoint *d, Vec3 lo, Vec3 li, float f[HERO_N], float pdf_l[HERO_N])
{
    int reflect = lo.z * li.z > 0.0f, j;
    float pdf;
    for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
    if (lo.z * li.z == 0.0f) return 0;
    pdf = (reflect ? d->p_reflect : 1.0f - d->p_reflect) * fabsf(li.z) / PI_F;
    for (j = 0; j < HERO_N; j++) {
        pdf_l[j] = pdf;
        f[j] = (reflect ? d->R[j] : d->T[j]) / PI_F;
    }
    return pdf > 0.0f;
}

/* ---------------------------------------------------------------- sampling */

int mat_needs_tangent(const Material *m)
{
    if ((m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR) &&
        (m->alpha != m->alpha_t || m->cond_alpha != m->cond_alpha_t))
        return 1;                                  /* layered.c: an anisotropic layer */
    if ((m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR ||
         m->type == MAT_CONDUCTOR) &&
        (m->alpha_tex != m->alpha_t_tex || m->cond_alpha_tex != m->cond_alpha_t_tex))
        return 1;                                  /* textured axes that may differ */
    if ((m->type == MAT_DIELECTRIC || m->type == MAT_SUBSURFACE) &&
        (m->alpha != m->alpha_t || m->alpha_tex != m->alpha_t_tex))
        return 1;                                  /* an anisotropic rough interface */
    return (m->type == MAT_MEASURED && !m->measured->isotropic) ||
           (m->type == MAT_CONDUCTOR && m->alpha != m->alpha_t);
}

/* The shading frame: around ns; where the BSDF turns with dp/du (an anisotropic
   measured file, conductor, coat, dielectric or subsurface boundary) its s axis is dp/du made tangent (Gram-Schmidt), its
   t = ns x s, pbrt-v4's Frame::FromXZ(dpdu, ns). */
Frame mat_frame(const Material *m, const SurfacePoint *sp)
{
    if (mat_needs_tangent(m)) {
        Vec3 s = v3_sub(sp->dpdu, v3_mul(sp->ns, v3_dot(sp->dpdu, sp->ns)));
        if (v3_dot(s, s) > 0.0f) {
            Frame f;
            f.n = sp->ns;
            f.s = v3_norm(s);
            f.t = v3_cross(f.n, f.s);
            return f;
        }
    }
    return frame_from_normal(sp->ns);
}

/* BsdfSample.u_lobe: the lobe number rescaled into its lobe's interval, as a float
   in [0, 1).  Exactly, u0 < F gives u0 / F < 1, but rounding to float may reach 1
   (and 0 - F rounding may dip below 0): the ends are clamped. */
static float lobe_rescaled(double u)
{
    const float below_one = 1.0f - 1.0f / 16777216.0f;      /* the float next to 1 */
    if (!(u > 0.0)) return 0.0f;
    return u < (double)below_one ? (float)u : below_one;
}

int bsdf_sample(const Material *m, const SurfacePoint *sp, Vec3 wo, const float *lambda,
                unsigned alive, float u0, float u1, float u2, BsdfSample *out)
{
    Frame fr = mat_frame(m, sp);
    Vec3 lo = frame_to_local(&fr, wo), li;
    float ax, ay;
    int j;
    for (j = 0; j < HERO_N; j++) { out->f[j] = 0.0f; out->pdf_l[j] = 0.0f; out->eta2[j] = 1.0f; }
    out->delta = 0;
    out->u_lobe = -1.0f;
    if (lo.z == 0.0f) return 0;
    if (m->type == MAT_HAIR) return hair_sample(m, sp, wo, lambda, alive, u0, u1, u2, out);
    if (m->type == MAT_SUBSURFACE_EXIT) return sss_exit_sample(m, sp, alive, u1, u2, out);

    if (m->type == MAT_CONDUCTOR) {
        MatPoint mp;
        mat_point(m, sp, lambda, alive, &mp);
        if (!conductor_sample(m, &mp, lo, lambda, alive, u1, u2, out, &li)) return 0;
        out->wi = frame_to_world(&fr, li);
        return 1;
    }
    if (m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR) {   /* layered.c */
        MatPoint mp;
        mat_point(m, sp, lambda, alive, &mp);
        if (!layered_sample(m, &mp, &fr, wo, lambda, alive, u0, u1, u2, 0, out)) return 0;
        return 1;
    }
    if (m->type == MAT_MEASURED) {                                      /* measured.c */
        if (!measured_sample(m->measured, lo, lambda, alive, u1, u2, out, &li)) return 0;
        out->wi = frame_to_world(&fr, li);
        if (v3_dot(out->wi, sp->ng) * v3_dot(wo, sp->ng) <= 0.0f) return 0;   /* no leaks */
        return 1;
    }
    if (m->type == MAT_THIN_DIELECTRIC) {
        if (!thin_sample(m, lo, lambda, alive, u0, out, &li)) return 0;
        out->wi = frame_to_world(&fr, li);
        return 1;
    }
    if (m->type == MAT_DIFFUSE_TRANSMISSION) {
        DtPoint d;
        int reflect;
        float r = sqrtf(u1), phi = 2.0f * PI_F * u2;   /* cosine-weighted, as diffuse */
        dt_point(m, sp, lambda, alive, &d);
        reflect = u0 < d.p_reflect;
        li = v3(r * cosf(phi), r * sinf(phi), sqrtf(fmaxf(0.0f, 1.0f - u1)));
        if ((lo.z < 0.0f) == reflect) li.z = -li.z;     /* reflect: wo's side */
        out->wi = frame_to_world(&fr, li);
        if (!dt_pair(&d, lo, li, out->f, out->pdf_l)) return 0;
        out->pdf = out->pdf_l[0];
        return 1;
    }

    if (m->type != MAT_DIELECTRIC && m->type != MAT_SUBSURFACE) {
        /* diffuse, or the fluorescent reflect lobe: cosine-weighted hemisphere (Malley's method: a uniform disk lifted up) */
        float r = sqrtf(u1), phi = 2.0f * PI_F * u2;
        float z = sqrtf(fmaxf(0.0f, 1.0f - u1));
        (void)u0;
        li = v3(r * cosf(phi), r * sinf(phi), z);
        if (lo.z < 0.0f) li.z = -li.z;                 /* wo's side */
        out->wi = frame_to_world(&fr, li);
        out->pdf = z / PI_F;
        if (!(out->pdf > 0.0f)) return 0;
        for (j = 0; j < HERO_N; j++) {
            out->pdf_l[j] = out->pdf;
            if (alive & (1u << j)) out->f[j] = mat_albedo_at(m, sp, lambda[j]) / PI_F;
        }
        return 1;
    }

    /* dielectric (and the boundary of a subsurface material) */
    if (!dielectric_alphas(m, sp, lambda, &ax, &ay)) {
        float eta = mat_eta(m, lambda[0]);
        float F = fresnel_dielectric(lo.z, eta), etap = 1.0f;
        Vec3 n = v3(0, 0, 1);
        out->delta = 1;
        if (u0 < F) {
            li = reflect_dir(lo, n);
            out->pdf = F;
            out->u_lobe = lobe_rescaled((double)u0 / F);
            for (j = 0; j < HERO_N; j++)
                if (alive & (1u << j)) out->f[j] = F / fabsf(li.z);
        } else {
            if (!refract_dir(lo, n, eta, &etap, &li)) return 0;
            out->pdf = 1.0f - F;
            out->u_lobe = lobe_rescaled(((double)u0 - F) / (1.0 - F));
            for (j = 0; j < HERO_N; j++)
                if (alive & (1u << j)) {
                    out->f[j] = (1.0f - F) / fabsf(li.z) / (etap * etap);
                    out->eta2[j] = etap * etap;
                }
        }
        if (!(out->pdf > 0.0f) || li.z == 0.0f) return 0;
        out->wi = frame_to_world(&fr, li);
        /* Delta lobes: the other wavelengths have the same probability only if
           the index does not vary; a dispersive interface has terminated them. */
        for (j = 0; j < HERO_N; j++) out->pdf_l[j] = m->dispersive && j ? 0.0f : out->pdf;
        if (m->dispersive)
            for (j = 1; j < HERO_N; j++) out->f[j] = 0.0f;
        return 1;
    } else {
        float eta = mat_eta(m, lambda[0]);
        Vec3 wm = tr_sample_wm(ax, ay, lo, u1, u2);
        float F = fresnel_dielectric(v3_dot(lo, wm), eta), etap;
        if (u0 < F) {
            li = reflect_dir(lo, wm);
            if (li.z * lo.z <= 0.0f) return 0;
        } else {
            if (!refract_dir(lo, wm, eta, &etap, &li)) return 0;
            if (li.z * lo.z >= 0.0f || li.z == 0.0f) return 0;
        }
        li = v3_norm(li);
        out->wi = frame_to_world(&fr, li);
        /* f and pdf per wavelength along the hero's directions (pdf_l[0] is the
           hero's own pdf: evaluating it reproduces the sampling density) */
        for (j = 0; j < HERO_N; j++) {
            float etaj = j == 0 ? eta : mat_eta(m, lambda[j]), fj, pj;
            if (j > 0 && !(alive & (1u << j))) continue;
            tr_dielectric_pair_xy(ax, ay, etaj, lo, li, LOBE_R | LOBE_T, &fj, &pj);
            out->pdf_l[j] = pj;
            if (alive & (1u << j)) out->f[j] = fj;
            if (li.z * lo.z < 0.0f)            /* refracted: etap_j = eta_j entering */
                out->eta2[j] = lo.z > 0.0f ? etaj * etaj : 1.0f / (etaj * etaj);
        }
        out->pdf = out->pdf_l[0];
        return out->pdf > 0.0f;
    }
}

void bsdf_eval(const Material *m, const SurfacePoint *sp, Vec3 wo, Vec3 wi,
               const float *lambda, unsigned alive, float f[HERO_N], float pdf_l[HERO_N])
{
    Frame fr = mat_frame(m, sp);
    Vec3 lo = frame_to_local(&fr, wo), li = frame_to_local(&fr, wi);
    float ax, ay;
    int j;
    for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
    if (m->type == MAT_HAIR) { hair_eval(m, sp, wo, wi, lambda, alive, f, pdf_l); return; }
    if (m->type == MAT_SUBSURFACE_EXIT) { sss_exit_eval(m, sp, wi, alive, f, pdf_l); return; }
    if (m->type == MAT_CONDUCTOR || m->type == MAT_COATED_DIFFUSE ||
        m->type == MAT_COATED_CONDUCTOR) {
        MatPoint mp;
        mat_point(m, sp, lambda, alive, &mp);
        if (m->type == MAT_CONDUCTOR) conductor_eval(m, &mp, lo, li, lambda, alive, f, pdf_l);
        else layered_eval(m, &mp, lo, li, lambda, alive, layered_seed(wo, wi, 0), f, pdf_l);  /* layered.c */
        return;
    }
    if (m->type == MAT_MEASURED) {                                 /* measured.c */
        if (v3_dot(wi, sp->ng) * v3_dot(wo, sp->ng) <= 0.0f) return;   /* no leaks */
        measured_eval(m->measured, lo, li, lambda, alive, f, pdf_l);
        return;
    }
    if (m->type == MAT_THIN_DIELECTRIC) return;                    /* delta: f = 0 */
    if (m->type == MAT_DIFFUSE_TRANSMISSION) {
        DtPoint d;
        dt_point(m, sp, lambda, alive, &d);
        dt_pair(&d, lo, li, f, pdf_l);
        return;
    }
    if (m->type != MAT_DIELECTRIC && m->type != MAT_SUBSURFACE) {   /* diffuse, fluorescent */
        float pdf;
        if (lo.z * li.z <= 0.0f) return;                           /* other side */
        pdf = fabsf(li.z) / PI_F;
        for (j = 0; j < HERO_N; j++) {
            pdf_l[j] = pdf;
            if (alive & (1u << j)) f[j] = mat_albedo_at(m, sp, lambda[j]) / PI_F;
        }
        return;
    }
    if (!dielectric_alphas(m, sp, lambda, &ax, &ay)) return;       /* delta: f = 0 */
    for (j = 0; j < HERO_N; j++) {
        float fj, pj;
        if (j > 0 && !(alive & (1u << j))) continue;
        tr_dielectric_pair_xy(ax, ay, mat_eta(m, lambda[j]), lo, li, LOBE_R | LOBE_T, &fj, &pj);
        pdf_l[j] = pj;
        if (alive & (1u << j)) f[j] = fj;
    }
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   The scene builder (scene.c) calls these for a Material or MakeNamedMaterial
   of their type (pbrt-v4's per-type Create): each reads its parameters
   (parser.h), checks them and fills the Material.
   --------------------------------------------------------------------------- */
#include "parser.h"
#include <float.h>

/* pbrt-v4 (materials.cpp): no material, only the boundary between two media;
   "" and "none" are its deprecated spellings.  Rays cross it (path.c) */
int interface_from_params(Parser *P, ParamList *pl, const char *file, int line,
                          const char *dir, const char *what, Material *m)
{
    (void)dir; (void)file; (void)line;
    m->type = MAT_INTERFACE;
    if (!normalmap_ignored(P, pl, what, "an interface has no surface to shade (pbrt-v4 ignores it too)"))
        return 0;
    return params_check_unused(P, pl, what, "string normalmap", NULL);
}

/* pbrt-v4 DiffuseMaterial: "reflectance" (0.5 by default), a spectrum (clamped
   to [0, 1]) or a spectrum texture. */
int diffuse_from_params(Parser *P, ParamList *pl, const char *file, int line,
                        const char *dir, const char *what, Material *m)
{
    Param *p = find_spectrum_param(pl, "reflectance");
    Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
    Spectrum r;                                   /* the table of what is not a colour */
    (void)dir;
    m->type = MAT_DIFFUSE;
    if (pt) {
        /* "texture reflectance": evaluated at each hit (texture.c), clamped to [0, 1] */
        int ti = texture_lookup(P, pt, 0);
        if (ti < 0) return 0;
        m->reflectance_tex = ti + 1;
        spec_const(&r, 0.5f);                     /* (not read) */
    } else if (rgb_albedo_param(P, p, &m->reflectance)) {
        /* an "rgb" colour: its sigmoid, within [0, 1] (spec_from_rgb_t's knots) */
    } else if (p) {
        /* pbrt-v4 clamps a spectrum's values to [0, 1] where it uses them
           (DiffuseMaterial::GetBxDF, src/pbrt/materials.h:467): done once here,
           the spectrum being constant; past 1e-4 of slack (an RGB upsampling of
           (1,1,1) rounds) with a note.  An "rgb" above 1 stays refused, as there. */
        float lo = FLT_MAX, hi = -FLT_MAX;
        int nm;
        if (!param_spectrum(P, p, SPEC_ALBEDO, &r, NULL)) return 0;
        /* an "rgb" albedo is within [0, 1] already (spec_from_rgb_t): nothing to check */
        for (nm = p->type == PT_RGB ? SPEC_MAX + 1 : SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
            float *v = spec_at(&r, nm);
            if (!(fabsf(*v) <= FLT_MAX))
                return fail(P, p->file, p->line, "\"%s reflectance\": value %g at %d nm is "
                            "not finite", param_type_names[p->type], *v, nm);
            if (*v < lo) lo = *v;                 /* finite: as fminf, fmaxf, inline */
            if (*v > hi) hi = *v;
            *v = *v < 0.0f ? 0.0f : *v > 1.0f ? 1.0f : *v;
        }
        if (lo < 0.0f || hi > 1.0001f)
            fprintf(stderr, "%s:%d: note: \"%s reflectance\" goes from %g to %g: clamped "
                    "to [0, 1], as pbrt-v4's diffuse material does\n", p->file, p->line,
                    param_type_names[p->type], lo, hi);
    } else {
        spec_const(&r, 0.5f);                     /* pbrt-v4's default */
    }
    if (!m->reflectance.rgb && !albedo_set_table(P, &m->reflectance, &r, file, line)) return 0;
    return bump_from_params(P, pl, what, m) &&
           params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                               "texture reflectance", NULL);
}

/* specnee extension (docs/FLUORESCENCE.md, docs/conventions.md §6):
   a diffuse fluorescent layer, F2 */
int fluorescent_from_params(Parser *P, ParamList *pl, const char *file, int line,
                            const char *dir, const char *what, Material *m)
{
    Param *pr = find_spectrum_param(pl, "reflectance");
    Param *pa = find_spectrum_param(pl, "excitation"), *pe = find_spectrum_param(pl, "emission");
    Param *pq = param_find(pl, PT_FLOAT, "quantumyield");
    int nm;
    m->type = MAT_FLUORESCENT;
    m->fl = (Fluorescence *)calloc(1, sizeof *m->fl);   /* freed by material_release */
    if (!m->fl) return oom(P, file, line);
    if (!pa || !pe)
        return fail(P, file, line, "%s \"fluorescent\": needs \"spectrum excitation\" "
                    "and \"spectrum emission\"", dir);
    if (!unit_albedo_param(P, pr, &m->reflectance, 0.5f, file, line)) return 0;
    if (!param_spectrum(P, pa, SPEC_UNBOUNDED, &m->fl->excitation, NULL)) return 0;
    if (!check_unit_spectrum(P, pa, &m->fl->excitation)) return 0;
    if (!param_spectrum(P, pe, SPEC_UNBOUNDED, &m->fl->emission, NULL)) return 0;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
        if (!(spec_get(&m->fl->emission, nm) >= 0.0f))
            return fail(P, pe->file, pe->line, "\"spectrum emission\": negative (%g) at %d nm",
                        spec_get(&m->fl->emission, nm), nm);
    if (!get_float(P, pl, "quantumyield", 1.0f, &m->fl->qyield)) return 0;
    if (!(m->fl->qyield >= 0.0f && m->fl->qyield <= 1.0f))
        return fail(P, pq ? pq->file : file, pq ? pq->line : line,
                    "\"float quantumyield\": %g is outside [0,1] (photons re-emitted per "
                    "photon absorbed)", m->fl->qyield);
    if (!fluor_prepare(m))
        return fail(P, pe->file, pe->line, "\"spectrum emission\": zero everywhere in %d-%d nm",
                    SPEC_UV_MIN, SPEC_MAX);
    return params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                               "spectrum excitation, spectrum emission, float quantumyield", "");
}

/* pbrt-v4 DielectricMaterial: "float eta" (no dispersion), "spectrum eta" or
   "rgb eta", or specnee's Cauchy coefficients; roughness per axis (anisotropic
   when u and v differ). */
int dielectric_from_params(Parser *P, ParamList *pl, const char *file, int line,
                           const char *dir, const char *what, Material *m)
{
    Param *pf = param_find(pl, PT_FLOAT, "eta");
    Param *pa = param_find(pl, PT_FLOAT, "cauchyA"), *pb = param_find(pl, PT_FLOAT, "cauchyB");
    float A = 0, B = 0;
    int i;
    Spectrum ior;                   /* n(lambda), shared once built */
    spec_const(&ior, 1.0f);
    m->type = MAT_DIELECTRIC;
    if ((pa != NULL) != (pb != NULL))
        return fail(P, file, line, "%s \"dielectric\": \"float cauchyA\" and "
                    "\"float cauchyB\" must be given together", dir);
    if (pa) {
        /* specnee extension: n(lambda) = A + B / lambda^2, lambda in um */
        Param *ps = find_spectrum_param(pl, "eta");
        if (pf || ps)
            return fail(P, file, line, "%s \"dielectric\": give either eta or "
                        "cauchyA/cauchyB, not both", dir);
        if (!get_float(P, pl, "cauchyA", 0, &A) || !get_float(P, pl, "cauchyB", 0, &B))
            return 0;
        if (!(A > 0.0f) || !(B >= 0.0f) || !(B < 1.0f))
            return fail(P, file, line, "%s \"dielectric\": need cauchyA > 0 and "
                        "0 <= cauchyB < 1 um^2", dir);
        for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++) *spec_at(&ior, i) = cauchy_eta(A, B, (float)i);
        m->cauchy_a = A;
        m->cauchy_b = B;
    } else if (pf) {
        /* pbrt-v4: a float eta is a constant index (no dispersion) */
        float eta;
        if (!get_float(P, pl, "eta", 1.5f, &eta)) return 0;
        if (!(eta > 0.0f))
            return fail(P, pf->file, pf->line, "\"float eta\": must be > 0");
        spec_const(&ior, eta);
    } else {
        Param *ps = find_spectrum_param(pl, "eta");
        if (ps) {
            /* pbrt-v4 reads "rgb eta" as an RGBUnboundedSpectrum (SPEC_COEFF); it
               has no UV, which keeps the 360 nm value here */
            int rgb = ps->type == PT_RGB;
            if (!param_spectrum(P, ps, rgb ? SPEC_COEFF : SPEC_UNBOUNDED, &ior, NULL)) return 0;
            for (i = 0; rgb && i < SPEC_UV_N; i++) ior.uv[i] = ior.v[0];
            for (i = 0; i < SPEC_N; i++) {
                if (!(ior.v[i] >= 0.0f && ior.v[i] < 100.0f))
                    return fail(P, ps->file, ps->line, "\"spectrum eta\": value %g at %d "
                                "nm is not an index of refraction", ior.v[i], SPEC_MIN + i);
                if (ior.v[i] == 0.0f) ior.v[i] = 1.0f;   /* pbrt: eta 0 means 1 */
            }
            for (i = 0; i < SPEC_UV_N; i++) {          /* the UV extension, same rule */
                if (!(ior.uv[i] >= 0.0f && ior.uv[i] < 100.0f))
                    return fail(P, ps->file, ps->line, "\"spectrum eta\": value %g at %d "
                                "nm is not an index of refraction", ior.uv[i], SPEC_UV_MIN + i);
                if (ior.uv[i] == 0.0f) ior.uv[i] = 1.0f;
            }
        } else {
            spec_const(&ior, 1.5f);            /* pbrt-v4's default */
        }
    }
    /* pbrt-v4: u/vroughness default to "roughness", which defaults to 0; each
       axis is a number or a float texture read at each hit (parser.c
       microfacet_alphas: alpha along the shading frame's s axis from uroughness,
       along t from vroughness, each remapped unless remaproughness is false) */
    if (!microfacet_alphas(P, pl, file, line, what, m)) return 0;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "float eta, spectrum eta, rgb eta, "
                             "float roughness, float uroughness, float vroughness, "
                             "texture roughness, texture uroughness, texture vroughness, "
                             "bool remaproughness, float cauchyA, float cauchyB",
                             NULL))
        return 0;
    if (m->alpha_tex <= 0 && m->alpha_t_tex <= 0 && tr_smooth(m->alpha, m->alpha_t))
        m->alpha = m->alpha_t = 0.0f;                  /* pbrt-v4's EffectivelySmooth */
    m->dispersive = !spec_is_constant(&ior);
    return material_set_eta(P, m, &ior, file, line);
}

/* pbrt-v4 ThinDielectricMaterial: "float eta", "spectrum eta" or "rgb eta",
   1.5 by default; no roughness */
int thindielectric_from_params(Parser *P, ParamList *pl, const char *file, int line,
                               const char *dir, const char *what, Material *m)
{
    Param *pf = param_find(pl, PT_FLOAT, "eta"), *ps = find_spectrum_param(pl, "eta");
    Spectrum ior;                   /* n(lambda), shared once built */
    (void)dir;
    spec_const(&ior, 1.0f);
    m->type = MAT_THIN_DIELECTRIC;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "float eta, spectrum eta, rgb eta",
                             NULL))
        return 0;
    if (pf) {
        float eta;
        if (!get_float(P, pl, "eta", 1.5f, &eta)) return 0;
        spec_const(&ior, eta);
    } else if (ps) {
        int nm, is_rgb = ps->type == PT_RGB;    /* as the dielectric's */
        if (!param_spectrum(P, ps, is_rgb ? SPEC_COEFF : SPEC_UNBOUNDED, &ior, NULL)) return 0;
        for (nm = SPEC_UV_MIN; is_rgb && nm < SPEC_MIN; nm++) *spec_at(&ior, nm) = ior.v[0];
    } else {
        spec_const(&ior, 1.5f);                /* pbrt-v4's default */
    }
    /* pbrt-v4 reads an eta of 0 as 1 (no interface); negative is meaningless */
    if (!check_spectrum_above(P, pf ? pf : ps, file, line, "\"eta\" of a thindielectric",
                              &ior, 0.0f, 0))
        return 0;
    {
        int nm;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
            if (spec_get(&ior, nm) == 0.0f) *spec_at(&ior, nm) = 1.0f;
    }
    return material_set_eta(P, m, &ior, file, line);
}

/* "texture NAME" of a diffusetransmission: 1 + the texture's index, or 0 when the
   parameter is not a texture. */
static int dt_texture_param(Parser *P, ParamList *pl, const char *name, int *out)
{
    Param *pt = param_find(pl, PT_TEXTURE, name);
    int ti;
    *out = 0;
    if (!pt) return 1;
    ti = texture_lookup(P, pt, 0);
    if (ti < 0) return 0;
    *out = ti + 1;
    return 1;
}

/* pbrt-v4 DiffuseTransmissionMaterial: R and T (0.25 each by default; spectra or
   spectrum textures), both times "scale" and clamped to [0, 1] */
int diffusetransmission_from_params(Parser *P, ParamList *pl, const char *file, int line,
                                    const char *dir, const char *what, Material *m)
{
    Param *pr = find_spectrum_param(pl, "reflectance"), *pt = find_spectrum_param(pl, "transmittance");
    Param *psc = param_find(pl, PT_FLOAT, "scale");
    float scale, maxr = 0.0f, maxt = 0.0f;
    Spectrum R;                                   /* R, scaled, then shared */
    int nm;
    (void)dir;
    m->type = MAT_DIFFUSE_TRANSMISSION;
    if (!material_extra(m)) return oom(P, file, line);   /* transmittance */
    if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
    if (!dt_texture_param(P, pl, "reflectance", &m->reflectance_tex) ||
        !dt_texture_param(P, pl, "transmittance", &m->extra->transmittance_tex))
        return 0;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, texture reflectance, "
                             "spectrum transmittance, rgb transmittance, texture transmittance, "
                             "float scale", NULL))
        return 0;
    if (!unit_spectrum_param(P, m->reflectance_tex ? NULL : pr, &R, 0.25f)) return 0;
    if (!unit_spectrum_param(P, m->extra->transmittance_tex ? NULL : pt, &m->extra->transmittance, 0.25f))
        return 0;
    if (!(scale >= 0.0f))
        return fail(P, psc ? psc->file : file, psc ? psc->line : line,
                    "\"float scale\": %g must be >= 0", scale);
    m->extra->dt_scale = scale;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
        float *r = spec_at(&R, nm), *t = spec_at(&m->extra->transmittance, nm);
        *r = fminf(1.0f, scale * *r);
        *t = fminf(1.0f, scale * *t);
        if (*r > maxr) maxr = *r;
        if (*t > maxt) maxt = *t;
    }
    m->p_reflect = maxr + maxt > 0.0f ? maxr / (maxr + maxt) : 0.5f;
    return albedo_set_table(P, &m->reflectance, &R, file, line);
}

/* pbrt-v4 MeasuredMaterial: "string filename", an RGL tensor file (measured.c),
   found as pbrt-v4 finds files; read once per file (as pbrt-v4's BRDFDataFromFile),
   shared by the materials that name it (MeasuredBrdf.refs). */
int measured_from_params(Parser *P, ParamList *pl, const char *file, int line,
                         const char *dir, const char *what, Material *m)
{
    const char *fn = NULL;
    char path[4096];
    Error e;
    int i;
    m->type = MAT_MEASURED;
    if (!get_string(P, pl, "filename", &fn)) return 0;
    if (!fn || !fn[0])
        return fail(P, file, line, "%s \"measured\": \"string filename\" is required", dir);
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "string filename", NULL))
        return 0;
    resolve_path(P, file, fn, path, sizeof path);
    for (i = 0; i < P->s->n_materials; i++) {
        MeasuredBrdf *b = P->s->materials[i].measured;
        if (P->s->materials[i].type == MAT_MEASURED && b->path[0] && !strcmp(b->path, path)) {
            m->measured = b;
            b->refs++;
            return 1;
        }
    }
    m->measured = (MeasuredBrdf *)calloc(1, sizeof *m->measured);  /* freed by material_release */
    if (!m->measured) return oom(P, file, line);
    if (!measured_read(path, m->measured, &e))
        return fail(P, file, line, "%s \"measured\": %s", dir, e.msg);
    m->measured->refs = 1;
    if (strlen(path) < sizeof m->measured->path) memcpy(m->measured->path, path, strlen(path) + 1);
    return 1;
}

/* One of a mix's "string materials": the named material `name`, which must exist
   and not be an interface (pbrt-v4 resolves the names when it makes the mix).  A
   MakeNamedMaterial "mix" sees the named materials made before it; a Material
   "mix" is made, as in pbrt-v4, after them all, so a name made further down the
   file is recorded (-2 - its NamedMaterial entry) for finish() (scene.c). */
static int mix_member(Parser *P, const char *name, int anonymous, const char *file, int line,
                      const char *what, int *out)
{
    int i;
    for (i = 0; i < P->n_named; i++)
        if (!strcmp(P->named[i].name, name)) break;
    if (i < P->n_named && P->named[i].material >= 0) {
        if (P->s->materials[P->named[i].material].type == MAT_INTERFACE)
            return fail(P, file, line, "%s: \"%s\": an \"interface\" material cannot be used "
                        "as an element of the \"mix\" material", what, name);
        *out = P->named[i].material;
        return 1;
    }
    if (!anonymous)
        return fail(P, file, line, "%s: named material \"%s\" not found (a named \"mix\" can "
                    "only use materials made before it)", what, name);
    if (i == P->n_named) {
        if (!grow((void **)&P->named, &P->cap_named, P->n_named + 1, sizeof(NamedMaterial)) ||
            !(P->named[i].name = keep_string(P, name)))
            return oom(P, file, line);
        P->named[i].material = -1;
        P->named[i].file = file;
        P->named[i].line = line;
        P->n_named++;
    }
    *out = -2 - i;
    return 1;
}

/* pbrt-v4 MixMaterial: "string materials" (two named materials) and "amount"
   (0.5 by default), a float or a float texture: the probability of the second. */
int mix_from_params(Parser *P, ParamList *pl, const char *file, int line,
                    const char *dir, const char *what, Material *m)
{
    Param *pm = param_find(pl, PT_STRING, "materials"), *pt = param_find(pl, PT_TEXTURE, "amount");
    int k;
    m->type = MAT_MIX;
    if (!pm || pm->n_str != 2)
        return fail(P, pm ? pm->file : file, pm ? pm->line : line, "%s: \"string materials\" "
                    "must name two materials (%d given)", what, pm ? pm->n_str : 0);
    for (k = 0; k < 2; k++)
        if (!mix_member(P, pm->str[k], !strcmp(dir, "Material"), pm->file, pm->line, what, &m->mix[k]))
            return 0;
    if (pt) {
        int ti = texture_lookup(P, pt, 1);
        if (ti < 0) return 0;
        m->amount_tex = ti + 1;
        m->amount = 0.5f;                          /* (not read) */
    } else if (!get_float(P, pl, "amount", 0.5f, &m->amount)) {
        return 0;
    }
    if (!normalmap_ignored(P, pl, what, "pbrt-v4's mix has no normal map of its own; the material "
                           "it chooses shades with its own"))
        return 0;
    return params_check_unused(P, pl, what, "string materials, float amount, texture amount, "
                               "string normalmap", NULL);
}

/* ---- the Scene's material records */

int add_material(Parser *P, Material *m, const char *file, int line)
{
    Scene *s = P->s;
    if (!grow((void **)&s->materials, &P->cap_mats, s->n_materials + 1, sizeof(Material))) {
        material_release(m);           /* the Scene did not take what m owns */
        oom(P, file, line);
        return -1;
    }
    s->materials[s->n_materials] = *m;
    return s->n_materials++;
}

/* pbrt-v4's default material: diffuse with reflectance 0.5. */
int default_material(Parser *P, const char *file, int line)
{
    if (P->default_material < 0) {
        Material m;
        Spectrum one, half;
        memset(&m, 0, sizeof m);
        m.type = MAT_DIFFUSE;
        spec_const(&half, 0.5f);
        spec_const(&one, 1.0f);
        if (!albedo_set_table(P, &m.reflectance, &half, file, line) ||
            !material_set_eta(P, &m, &one, file, line))
            return -1;
        P->default_material = add_material(P, &m, file, line);
    }
    return P->default_material;
}
