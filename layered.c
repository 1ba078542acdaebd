/* layered.c - pbrt-v4's "coateddiffuse" and "coatedconductor": a dielectric coat
   over a Lambertian or a conductor base, with an optional scattering medium between
   the two, evaluated by stochastic random walks between the interfaces.

   Exported: layered_sample, layered_eval, layered_pdf, layered_seed (specnee.h
   section 6), called by material.c's bsdf_sample / bsdf_eval in the shading frame
   (n = +z, directions pointing away from the surface, f without the cosine).  The coat's
   and the base's Fresnel terms and GGX come from the scattering room
   (microfacet.c), the phase function from medium.c; this room calls neither
   material.c nor conductor.c.

   1. The model (Guo, Hasan, Zhao 2018, "Position-free Monte Carlo simulation
      for arbitrary layered BSDFs", ACM TOG 37(6); pbrt 4th ed. section 14.3,
      LayeredBxDF<DielectricBxDF, DiffuseBxDF, twoSided = true>).  Two parallel
      interfaces at heights z = thickness (the coat: smooth or GGX dielectric of
      index eta, anisotropic when its alphas differ: alpha_x along the shading
      frame's s axis, dp/du, as conductor.c's) and z = 0 (the base: Lambert,
      f = R/pi, no transmission), with between them a medium of extinction
      sigma_t = 1 per unit height and single scattering albedo `albedo`
      (Henyey-Greenstein phase function, asymmetry g).
      With albedo 0 the slab only absorbs: a straight crossing along w keeps
      Tr = exp(-thickness / |w.z|).  "Position-free": only the height z of a
      vertex matters, never its (x, y), so a walk is a sequence of directions and
      heights.  Two-sided: a wo below the surface is handled by mirroring wo and
      wi (the coat faces both ways, as pbrt-v4's twoSided = true).  Thickness, g
      and albedo, like the roughnesses and the base's reflectance, may be textures:
      material.c's mat_point reads them at each hit (MatPoint), as pbrt-v4's
      GetBxDF does, and layer_init takes them from there.

   2. f(wo, wi) is an integral over all paths between the interfaces; one random
      walk gives an unbiased estimate (Guo et al. section 5):
        - the coat's reflection f_top(wo, wi) (GGX; 0 when smooth: a delta lobe);
        - a walk entering through the coat along wos (sampled transmission of
          wo), with throughput beta = f_t |cos| / p; at each vertex a
          next-event estimate connects towards wis, the inside direction of a
          sampled transmission of wi ("importance" mode: the adjoint; its weight
          f_t(wi -> wis) / p equals the radiance BTDF of the exit, Veach 1997
          section 5.2), combined by the power heuristic with the walk reaching
          the coat and leaving through it (the exit BTDF evaluated directly) when
          the coat is rough (both weights in the measure of the inside
          direction: the exit's competitor is p(v | wi), the density with which
          wi's transmission samples the inside direction v; pbrt-v4 (commit
          5f7a6068, LayeredBxDF::f) uses the exit's own p(wi | v) there, so its
          two weights do not sum to 1 and its f is biased high for rough coats:
          directional albedo 0.638 instead of 0.585 at alpha 0.4, R = 1, wo at
          34 deg (0.585: its Sample_f, specnee's f, and f without MIS all agree);
          a white rough-coated sphere under a distant light, where only f is
          seen, renders 8.5% brighter in pbrt-v4 than in specnee);  at the base: beta R/pi |cos wis| Tr(wis) f_t/p,
          in the medium: beta albedo p_HG Tr f_t/p;
        - the walk continues by sampling the base (cosine), the coat's internal
          reflection (total internal reflection included), or the medium
          (exponential free flight z += dz, dz = -ln(1 - u) |w.z|; a flight that
          ends beyond an interface reaches it with weight 1);
        - Russian roulette after depth 3 when max beta < 1/4, and at most
          `maxdepth` vertices (a truncation: pbrt-v4's bias, reproduced).
      The mean of `nsamples` walks is returned.
   3. Sampling: the coat is sampled at wo; a reflection is returned as it is (a
      delta lobe when smooth); a transmission starts a walk that multiplies f
      and pdf of every vertex until it leaves through the coat.  The walk's
      f/p is an unbiased estimate of the weight f cos / p, but its p is not the
      density of the returned direction (which has no closed form).
   4. pdf(wo, wi) is an approximation (pbrt-v4's LayeredBxDF::PDF): the coat's
      reflection pdf plus the TRT paths of one bounce at the base (exact for the
      smooth coat's refracted pair, MIS of the two one-bounce strategies when
      rough), mixed with the uniform sphere: pdf = 0.1/(4 pi) + 0.9 estimate.

   Integration with specnee's estimator (path.c): the MIS weights of a
   direction must come from ONE function whether NEE (bsdf_eval) or BSDF
   sampling found it.  That function is layered_pdf(wo, wi): a stochastic
   estimate made deterministic by seeding its random stream from (wo, wi) (as
   pbrt-v4 hashes its --seed, wo and wi).  bsdf_sample therefore reports pdf =
   pdf_l[j] = layered_pdf(wo, wi) and f[j] = f_walk[j] pdf / p_walk, so that
   path.c's update beta *= f cos / pdf multiplies by f_walk cos / p_walk, the
   walk's unbiased weight, while the emitter hit's MIS weight uses pdf, the
   same number NEE's bsdf_eval reports for that pair (pbrt-v4's path.cpp:
   p_b = pdfIsProportional ? bsdf.PDF(wo, wi) : pdf).  Any positive function
   used consistently by both strategies keeps the MIS weights summing to 1,
   so the estimate stays unbiased; pdf's quality only affects variance.
   bsdf_eval's f is a random-walk estimate seeded from (wo, wi) too: unbiased
   over the seeds, deterministic for a given pair, independent of threads.
   The coat's index is one number per path, the hero wavelength's (a spectral eta
   that varies makes path.c terminate the secondaries at the hit, as pbrt-v4's
   GetBxDF does), so every alive wavelength shares the directions: pdf_l[j] = pdf,
   and only the base's reflectance (R, or the conductor's Fresnel) and the albedo
   differ per wavelength.

   5. coatedconductor (pbrt-v4's CoatedConductorBxDF = LayeredBxDF<DielectricBxDF,
      ConductorBxDF, true>, CoatedConductorMaterial::GetBxDF): the same walks with
      conductor.c's BRDF as the base (complex Fresnel; smooth: a delta lobe, rough:
      GGX with visible-normal sampling).  The conductor sits under the coat, so its
      index is taken relative to the coat's: n / eta and k / eta ("reflectance" r
      first stands for n = 1, k = 2 sqrt(r) / sqrt(1 - r), r <= 0.9999, as for the
      bare conductor, then is divided too: r is NOT the reflectance under the
      coat).  Delta lobes change the MIS of section 2 as in pbrt-v4: a smooth base
      gets no next-event estimate (its f is 0) and its sampled exits weight 1; in
      the pdf estimate a smooth base's sampled direction adds the coat's pdf alone.
      A smooth coat over a smooth base without albedo is a purely specular BSDF:
      bsdf_eval gives 0 and every sample is a delta (a specular path). */
#include "specnee.h"
#include <float.h>
#include <string.h>

/* ---------------------------------------------------------------- the coat */

typedef struct { float eta, ax, ay; } Coat;   /* GGX alphas along the frame's s, t */
typedef struct { Vec3 wi; float f, pdf; int reflect, specular; } Lobe;

/* pbrt-v4: index 1 or EffectivelySmooth (alpha < 1e-3) scatter in delta lobes. */
static int coat_smooth(const Coat *c) { return c->eta == 1.0f || tr_smooth(c->ax, c->ay); }

/* Sample the coat from w (either side), restricted to the lobes in `lobes`;
   radiance = 0 is the adjoint ("importance"): no 1/eta'^2 on transmission. */
static int coat_sample(const Coat *c, Vec3 w, float uc, float u1, float u2, int lobes,
                       int radiance, Lobe *s)
{
    float R, T, pr, pt, etap = 1.0f;
    if (w.z == 0.0f) return 0;
    if (coat_smooth(c)) {
        R = fresnel_dielectric(w.z, c->eta);
        T = 1.0f - R;
        pr = (lobes & LOBE_R) ? R : 0.0f;
        pt = (lobes & LOBE_T) ? T : 0.0f;
        if (!(pr + pt > 0.0f)) return 0;
        s->specular = 1;
        if (uc < pr / (pr + pt)) {
            s->wi = v3(-w.x, -w.y, w.z);
            s->reflect = 1;
            s->f = R / fabsf(s->wi.z);
            s->pdf = pr / (pr + pt);
        } else {
            if (!refract_dir(w, v3(0, 0, 1), c->eta, &etap, &s->wi) || s->wi.z == 0.0f) return 0;
            s->reflect = 0;
            s->f = T / fabsf(s->wi.z);
            if (radiance) s->f /= etap * etap;
            s->pdf = pt / (pr + pt);
        }
        return s->f > 0.0f && s->pdf > 0.0f;
    } else {
        float ax = c->ax, ay = c->ay;
        Vec3 wm = tr_sample_wm(ax, ay, w, u1, u2);
        float dwm = v3_dot(w, wm);
        R = fresnel_dielectric(dwm, c->eta);
        T = 1.0f - R;
        pr = (lobes & LOBE_R) ? R : 0.0f;
        pt = (lobes & LOBE_T) ? T : 0.0f;
        if (!(pr + pt > 0.0f) || dwm == 0.0f) return 0;
        s->specular = 0;
        if (uc < pr / (pr + pt)) {
            s->wi = reflect_dir(w, wm);
            if (s->wi.z * w.z <= 0.0f) return 0;
            s->reflect = 1;
            s->pdf = tr_pdf_reflect(ax, ay, w, wm) * pr / (pr + pt);
            s->f = tr_D(ax, ay, wm) * tr_G(ax, ay, w, s->wi) * R / fabsf(4.0f * s->wi.z * w.z);
        } else {
            float d, denom;
            if (!refract_dir(w, wm, c->eta, &etap, &s->wi)) return 0;
            if (s->wi.z * w.z >= 0.0f || s->wi.z == 0.0f) return 0;
            s->reflect = 0;
            d = v3_dot(s->wi, wm) + dwm / etap;
            denom = d * d;
            if (denom == 0.0f) return 0;
            s->pdf = tr_pdf_wm(ax, ay, w, wm) * fabsf(v3_dot(s->wi, wm)) / denom * pt / (pr + pt);
            s->f = T * tr_D(ax, ay, wm) * tr_G(ax, ay, w, s->wi) *
                   fabsf(v3_dot(s->wi, wm) * dwm / (s->wi.z * w.z * denom));
            if (radiance) s->f /= etap * etap;
        }
        return s->f > 0.0f && s->pdf > 0.0f && isfinite(s->f);
    }
}

/* The rough coat's value (radiance mode) and pdf for a pair; 0 when smooth. */
static void coat_pair(const Coat *c, Vec3 wo, Vec3 wi, int lobes, float *f, float *pdf)
{
    *f = 0.0f; *pdf = 0.0f;
    if (coat_smooth(c)) return;
    tr_dielectric_pair_xy(c->ax, c->ay, c->eta, wo, wi, lobes, f, pdf);
}

/* ---------------------------------------------------------------- base and medium */

/* The base at z = 0, seen from inside the slab (directions with z > 0): Lambert
   (coateddiffuse) or a conductor (coatedconductor, section 5). */
typedef struct {
    int cond;                  /* 0: Lambert of reflectance R; 1: conductor */
    float ax, ay;              /* conductor: GGX alphas along s, t (smooth below 1e-3) */
    float R[HERO_N];           /* Lambert: the reflectance */
    float ce[HERO_N], ck[HERO_N];   /* conductor: n and k relative to the coat's index */
} Base;

/* pbrt-v4's TrowbridgeReitzDistribution::EffectivelySmooth: a delta lobe. */
static int base_specular(const Base *b) { return b->cond && tr_smooth(b->ax, b->ay); }

/* The base's pdf of wi given wo (0 for a delta lobe). */
static float base_pdf(const Base *b, Vec3 wo, Vec3 wi)
{
    Vec3 wm;
    if (wo.z * wi.z <= 0.0f) return 0.0f;
    if (!b->cond) return fabsf(wi.z) / PI_F;
    if (base_specular(b)) return 0.0f;
    if (!tr_half_vector(wo, wi, &wm)) return 0.0f;
    return tr_pdf_reflect(b->ax, b->ay, wo, wm);
}

/* The base's f (without the cosine) for a pair, per wavelength (0 for a delta lobe). */
static void base_f(const Base *b, Vec3 wo, Vec3 wi, float f[HERO_N])
{
    int j;
    for (j = 0; j < HERO_N; j++) f[j] = 0.0f;
    if (wo.z * wi.z <= 0.0f) return;
    if (!b->cond) {
        for (j = 0; j < HERO_N; j++) f[j] = b->R[j] / PI_F;
    } else if (!base_specular(b)) {
        float ax = b->ax, ay = b->ay, c, dg;
        Vec3 wm;
        if (!tr_half_vector(wo, wi, &wm)) return;
        c = fabsf(v3_dot(wo, wm));
        dg = tr_D(ax, ay, wm) * tr_G(ax, ay, wo, wi) / (4.0f * fabsf(wo.z * wi.z));
        for (j = 0; j < HERO_N; j++) f[j] = dg * fresnel_conductor(c, b->ce[j], b->ck[j]);
    }
}

/* Sample the base from w (z > 0 side): the direction, f (without the cosine), the
   weight f |cos| / pdf per wavelength, the pdf (1 for the smooth conductor's delta
   lobe, whose f is F / |cos|).  0 when no direction (or all f = 0). */
static int base_sample(const Base *b, Vec3 w, float u1, float u2, Vec3 *wn, float f[HERO_N],
                       float wt[HERO_N], float *pdf, int *specular)
{
    int j, any = 0;
    *specular = 0;
    if (!b->cond) {                   /* cosine-weighted on w's side */
        float r = sqrtf(u1), phi = 2.0f * PI_F * u2;
        Vec3 d = v3(r * cosf(phi), r * sinf(phi), sqrtf(fmaxf(0.0f, 1.0f - u1)));
        if (w.z < 0.0f) d.z = -d.z;
        *wn = d;
        *pdf = base_pdf(b, w, d);
        for (j = 0; j < HERO_N; j++) {
            f[j] = b->R[j] / PI_F;
            wt[j] = b->R[j];          /* (R/pi) cos / (cos/pi) */
            if (f[j] > 0.0f) any = 1;
        }
        return *pdf > 0.0f && any;
    }
    if (base_specular(b)) {           /* the mirror direction, probability 1 */
        *wn = v3(-w.x, -w.y, w.z);
        *pdf = 1.0f;
        *specular = 1;
        for (j = 0; j < HERO_N; j++) {
            wt[j] = fresnel_conductor(fabsf(w.z), b->ce[j], b->ck[j]);
            f[j] = wt[j] / fabsf(w.z);
            if (f[j] > 0.0f) any = 1;
        }
        return any && w.z != 0.0f;
    } else {                          /* GGX visible normals, as conductor.c */
        Vec3 wm = tr_sample_wm(b->ax, b->ay, w, u1, u2);
        *wn = reflect_dir(w, wm);
        if (wn->z * w.z <= 0.0f) return 0;
        *wn = v3_norm(*wn);
        *pdf = base_pdf(b, w, *wn);
        if (!(*pdf > 0.0f)) return 0;
        base_f(b, w, *wn, f);
        for (j = 0; j < HERO_N; j++) {
            wt[j] = f[j] * fabsf(wn->z) / *pdf;
            if (f[j] > 0.0f) any = 1;
        }
        return any;
    }
}

/* Henyey-Greenstein: hg_phase and hg_sample (medium.c), whose cosine is
   measured from the direction the light travels: at a walk vertex reached along
   w, the phase of leaving along wn is hg_phase(g, w . wn). */

/* Transmittance of a vertical distance dz along w (sigma_t = 1). */
static float slab_tr(float dz, Vec3 w)
{
    if (fabsf(dz) <= FLT_MIN) return 1.0f;
    return expf(-fabsf(dz / w.z));
}

static float power_h(float a, float b)
{
    if (isinf(a)) return 1.0f;
    if (!(a * a + b * b > 0.0f)) return 0.0f;
    return a * a / (a * a + b * b);
}

/* ---------------------------------------------------------------- the layered BSDF */

typedef struct {
    Coat top;
    float thick, g;
    int maxdepth, nsamples, has_albedo;
    Base base;
    float A[HERO_N];
} Layer;

static void layer_init(const Material *m, const MatPoint *mp, const float *lambda, unsigned alive,
                       Layer *L)
{
    int j;
    L->top.eta = mat_eta(m, lambda[0]);
    L->top.ax = mp ? mp->alpha : m->alpha;
    L->top.ay = mp ? mp->alpha_t : m->alpha_t;
    L->thick = mp ? mp->thick : m->thickness;
    L->g = mp ? mp->g : m->hg_g;
    L->maxdepth = m->maxdepth;
    L->nsamples = m->nsamples;
    L->has_albedo = 0;
    L->base.cond = m->type == MAT_COATED_CONDUCTOR;
    L->base.ax = mp ? mp->cond_alpha : m->cond_alpha;
    L->base.ay = mp ? mp->cond_alpha_t : m->cond_alpha_t;
    tr_rough_floor(&L->top.ax, &L->top.ay);        /* pbrt-v4: a rough axis pair >= 1e-4 */
    tr_rough_floor(&L->base.ax, &L->base.ay);
    for (j = 0; j < HERO_N; j++) {
        int on = (alive & (1u << j)) != 0;
        L->A[j] = !on ? 0.0f : mp && mp->has_a ? mp->a[j] : spec_eval(&m->extra->albedo, lambda[j]);
        if (L->A[j] > 0.0f) L->has_albedo = 1;
        L->base.R[j] = 0.0f;
        L->base.ce[j] = 1.0f;                 /* n = 1, k = 0: F = 0 (dead wavelengths) */
        L->base.ck[j] = 0.0f;
        if (!on) continue;
        if (!L->base.cond) {
            L->base.R[j] = mp && mp->has_r ? mp->r[j] : albedo_eval(&m->reflectance, lambda[j]);
        } else {
            /* section 5: the conductor's index relative to the coat's */
            if (mp && mp->has_r) {
                double r = mp->r[j] < 0.9999f ? mp->r[j] : 0.9999;
                L->base.ck[j] = conductor_k_of_reflectance(r);
            } else if (mp && mp->has_ek) {                   /* textured (mat_point) */
                L->base.ce[j] = mp->eta[j];
                L->base.ck[j] = mp->k[j];
            } else {
                L->base.ce[j] = spec_eval(&m->extra->cond_eta, lambda[j]);
                L->base.ck[j] = spec_eval(&m->extra->k, lambda[j]);
            }
            L->base.ce[j] /= L->top.eta;
            L->base.ck[j] /= L->top.eta;
        }
    }
}

static float rng_u(Rng *r) { return rng_float(r); }

static uint64_t dir_key(Vec3 v)
{
    uint32_t x, y, z;
    memcpy(&x, &v.x, 4); memcpy(&y, &v.y, 4); memcpy(&z, &v.z, 4);
    return hash_u64(((uint64_t)x << 32) | y, z);
}

/* One estimate of f (section 2), mean of nsamples walks; wo.z > 0. */
static void walk_f(const Layer *L, Vec3 wo, Vec3 wi, Rng *rng, float f[HERO_N])
{
    int s, j, depth, smooth = coat_smooth(&L->top);
    float ftop, ptop;
    for (j = 0; j < HERO_N; j++) f[j] = 0.0f;
    if (wi.z <= 0.0f) return;                     /* the base transmits nothing */
    coat_pair(&L->top, wo, wi, LOBE_R | LOBE_T, &ftop, &ptop);
    for (j = 0; j < HERO_N; j++) f[j] = (float)L->nsamples * ftop;
    for (s = 0; s < L->nsamples; s++) {
        Lobe wos, wis;
        float beta[HERO_N], z, a, b, c;
        Vec3 w;
        a = rng_u(rng); b = rng_u(rng); c = rng_u(rng);
        if (!coat_sample(&L->top, wo, a, b, c, LOBE_T, 1, &wos)) continue;
        a = rng_u(rng); b = rng_u(rng); c = rng_u(rng);
        if (!coat_sample(&L->top, wi, a, b, c, LOBE_T, 0, &wis)) continue;   /* adjoint */
        for (j = 0; j < HERO_N; j++) beta[j] = wos.f * fabsf(wos.wi.z) / wos.pdf;
        z = L->thick;
        w = wos.wi;
        for (depth = 0; depth < L->maxdepth; depth++) {
            float bmax = 0.0f;
            for (j = 0; j < HERO_N; j++) bmax = fmaxf(bmax, beta[j]);
            if (depth > 3 && bmax < 0.25f) {
                float q = fmaxf(0.0f, 1.0f - bmax);
                if (rng_u(rng) < q) break;
                for (j = 0; j < HERO_N; j++) beta[j] /= 1.0f - q;
            }
            if (L->has_albedo) {
                float dz = -logf(1.0f - rng_u(rng)) * fabsf(w.z);
                float zp = w.z > 0.0f ? z + dz : z - dz;
                if (zp == z) continue;
                if (zp > 0.0f && zp < L->thick) {   /* scattering inside the slab */
                    float ph = hg_phase(L->g, v3_dot(w, v3_neg(wis.wi))), pp, wt;
                    float tr = slab_tr(zp - L->thick, wis.wi);
                    Vec3 wn;
                    wt = smooth ? 1.0f : power_h(wis.pdf, ph);
                    for (j = 0; j < HERO_N; j++)
                        f[j] += beta[j] * L->A[j] * ph * wt * tr * wis.f / wis.pdf;
                    a = rng_u(rng); b = rng_u(rng);
                    wn = hg_sample(L->g, w, a, b, &pp);
                    if (!(pp > 0.0f) || wn.z == 0.0f) continue;
                    for (j = 0; j < HERO_N; j++) beta[j] *= L->A[j];   /* p / pdf = 1 */
                    w = wn;
                    z = zp;
                    if (w.z > 0.0f && !smooth) {    /* towards the coat: leave through it */
                        float fe, pe;
                        coat_pair(&L->top, v3_neg(w), wi, LOBE_T, &fe, &pe);
                        coat_pair(&L->top, wi, v3_neg(w), LOBE_T, &pe, &pe);   /* p(-w | wi) */
                        if (fe > 0.0f) {
                            float wt2 = power_h(pp, pe), t2 = slab_tr(zp - L->thick, w);
                            for (j = 0; j < HERO_N; j++) f[j] += beta[j] * t2 * fe * wt2;
                        }
                    }
                    continue;
                }
                z = zp <= 0.0f ? 0.0f : L->thick;
            } else {
                z = z == L->thick ? 0.0f : L->thick;
                for (j = 0; j < HERO_N; j++) beta[j] *= slab_tr(L->thick, w);
            }
            if (z == L->thick) {                    /* the coat from inside: reflect */
                Lobe r;
                a = rng_u(rng); b = rng_u(rng); c = rng_u(rng);
                if (!coat_sample(&L->top, v3_neg(w), a, b, c, LOBE_R, 1, &r)) break;
                for (j = 0; j < HERO_N; j++) beta[j] *= r.f * fabsf(r.wi.z) / r.pdf;
                w = r.wi;
            } else {                                /* the base */
                float tr = slab_tr(L->thick, wis.wi), pb, bf[HERO_N], bw[HERO_N];
                int bspec;
                Vec3 wn;
                if (!base_specular(&L->base)) {
                    float wt = smooth ? 1.0f
                                      : power_h(wis.pdf, base_pdf(&L->base, v3_neg(w), v3_neg(wis.wi)));
                    base_f(&L->base, v3_neg(w), v3_neg(wis.wi), bf);
                    for (j = 0; j < HERO_N; j++)
                        f[j] += beta[j] * bf[j] * fabsf(wis.wi.z) * wt * tr * wis.f / wis.pdf;
                }
                a = rng_u(rng); b = rng_u(rng);
                if (!base_sample(&L->base, v3_neg(w), a, b, &wn, bf, bw, &pb, &bspec)) break;
                for (j = 0; j < HERO_N; j++) beta[j] *= bw[j];
                w = wn;
                if (!smooth) {
                    float fe, pe;
                    coat_pair(&L->top, v3_neg(w), wi, LOBE_T, &fe, &pe);
                    coat_pair(&L->top, wi, v3_neg(w), LOBE_T, &pe, &pe);       /* p(-w | wi) */
                    if (fe > 0.0f) {
                        float wt2 = bspec ? 1.0f : power_h(pb, pe), t2 = slab_tr(L->thick, w);
                        for (j = 0; j < HERO_N; j++) f[j] += beta[j] * t2 * fe * wt2;
                    }
                }
            }
        }
    }
    for (j = 0; j < HERO_N; j++) f[j] /= (float)L->nsamples;
}

/* The pdf approximation of section 4; wo.z > 0. */
static float walk_pdf(const Layer *L, Vec3 wo, Vec3 wi, Rng *rng)
{
    int s, j, smooth = coat_smooth(&L->top), base_on = L->base.cond;
    float sum = 0.0f, ftop, ptop;
    for (j = 0; j < HERO_N; j++) if (L->base.R[j] > 0.0f) base_on = 1;
    if (wi.z > 0.0f) {
        coat_pair(&L->top, wo, wi, LOBE_R | LOBE_T, &ftop, &ptop);
        sum += (float)L->nsamples * ptop;
        for (s = 0; s < L->nsamples; s++) {
            Lobe wos, wis;
            float a, b, c;
            a = rng_u(rng); b = rng_u(rng); c = rng_u(rng);
            if (!coat_sample(&L->top, wo, a, b, c, LOBE_T, 1, &wos)) continue;
            a = rng_u(rng); b = rng_u(rng); c = rng_u(rng);
            if (!coat_sample(&L->top, wi, a, b, c, LOBE_T, 0, &wis)) continue;
            if (smooth) sum += base_pdf(&L->base, v3_neg(wos.wi), v3_neg(wis.wi));
            else if (base_on) {
                Vec3 rs;
                float rp, rpdf, tf, tpdf, bf[HERO_N], bw[HERO_N];
                int bspec;
                a = rng_u(rng); b = rng_u(rng);
                if (!base_sample(&L->base, v3_neg(wos.wi), a, b, &rs, bf, bw, &rp, &bspec)) continue;
                coat_pair(&L->top, v3_neg(rs), wi, LOBE_R | LOBE_T, &tf, &tpdf);
                if (bspec) { sum += tpdf; continue; }  /* the base's delta lobe */
                rpdf = base_pdf(&L->base, v3_neg(wos.wi), v3_neg(wis.wi));
                sum += power_h(wis.pdf, rpdf) * rpdf;
                sum += power_h(rp, tpdf) * tpdf;
            }
        }
    }
    sum /= (float)L->nsamples;
    return 0.1f / (4.0f * PI_F) + 0.9f * sum;
}

uint64_t layered_seed(Vec3 wo, Vec3 wi, uint64_t key)
{
    return hash_u64(hash_u64(dir_key(wo), dir_key(wi)), key);
}

float layered_pdf(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                  unsigned alive, uint64_t seed)
{
    Layer L;
    Rng rng;
    if (wo.z == 0.0f) return 0.0f;
    if (wo.z < 0.0f) { wo = v3_neg(wo); wi = v3_neg(wi); }   /* two-sided */
    layer_init(m, mp, lambda, alive, &L);
    rng_seed(&rng, seed, 0x9dfULL);
    return walk_pdf(&L, wo, wi, &rng);
}

void layered_eval(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                  unsigned alive, uint64_t seed, float f[HERO_N], float pdf_l[HERO_N])
{
    Layer L;
    Rng rng;
    int j;
    float pdf;
    for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
    if (wo.z == 0.0f || wi.z == 0.0f) return;
    pdf = layered_pdf(m, mp, wo, wi, lambda, alive, seed);
    if (wo.z < 0.0f) { wo = v3_neg(wo); wi = v3_neg(wi); }   /* mirrored, as in the pdf */
    layer_init(m, mp, lambda, alive, &L);
    rng_seed(&rng, seed, 0xf1ULL);
    walk_f(&L, wo, wi, &rng, f);
    for (j = 0; j < HERO_N; j++) {
        pdf_l[j] = pdf;
        if (!(alive & (1u << j)) || !isfinite(f[j]) || f[j] < 0.0f) f[j] = 0.0f;
    }
}

/* Section 3: a walk from wo; *fw is its f (without the exit cosine), *pw its p. */
static int walk_sample(const Layer *L, Vec3 wo, float uc, float u1, float u2, Rng *rng,
                       Vec3 *wi, float fw[HERO_N], float *pw, int *specular)
{
    Lobe bs;
    Vec3 w;
    float pdf, z = L->thick;
    int j, depth, spec;
    if (!coat_sample(&L->top, wo, uc, u1, u2, LOBE_R | LOBE_T, 1, &bs)) return 0;
    if (bs.reflect) {
        *wi = bs.wi;
        for (j = 0; j < HERO_N; j++) fw[j] = bs.f;
        *pw = bs.pdf;
        *specular = bs.specular;
        return 1;
    }
    w = bs.wi;
    spec = bs.specular;
    for (j = 0; j < HERO_N; j++) fw[j] = bs.f * fabsf(w.z);
    pdf = bs.pdf;
    for (depth = 0; depth < L->maxdepth; depth++) {
        float fmax = 0.0f, a, b, c;
        for (j = 0; j < HERO_N; j++) fmax = fmaxf(fmax, fw[j]);
        if (depth > 3 && fmax / pdf < 0.25f) {
            float q = fmaxf(0.0f, 1.0f - fmax / pdf);
            if (rng_u(rng) < q) return 0;
            pdf *= 1.0f - q;
        }
        if (w.z == 0.0f) return 0;
        if (L->has_albedo) {
            float dz = -logf(1.0f - rng_u(rng)) * fabsf(w.z);
            float zp = w.z > 0.0f ? z + dz : z - dz;
            if (zp == z) return 0;
            if (zp > 0.0f && zp < L->thick) {
                float pp;
                Vec3 wn;
                a = rng_u(rng); b = rng_u(rng);
                wn = hg_sample(L->g, w, a, b, &pp);
                if (!(pp > 0.0f) || wn.z == 0.0f) return 0;
                for (j = 0; j < HERO_N; j++) fw[j] *= L->A[j] * pp;
                pdf *= pp;
                spec = 0;
                w = wn;
                z = zp;
                continue;
            }
            z = zp <= 0.0f ? 0.0f : L->thick;
        } else {
            z = z == L->thick ? 0.0f : L->thick;
            for (j = 0; j < HERO_N; j++) fw[j] *= slab_tr(L->thick, w);
        }
        if (z == 0.0f) {                            /* the base */
            Vec3 wn;
            float pb, bf[HERO_N], bw[HERO_N];
            int bspec;
            a = rng_u(rng); b = rng_u(rng);
            if (!base_sample(&L->base, v3_neg(w), a, b, &wn, bf, bw, &pb, &bspec)) return 0;
            for (j = 0; j < HERO_N; j++) fw[j] *= bf[j] * fabsf(wn.z);
            pdf *= pb;
            spec = spec && bspec;
            w = wn;
        } else {                                    /* the coat from inside */
            a = rng_u(rng); b = rng_u(rng); c = rng_u(rng);
            if (!coat_sample(&L->top, v3_neg(w), a, b, c, LOBE_R | LOBE_T, 1, &bs)) return 0;
            for (j = 0; j < HERO_N; j++) fw[j] *= bs.f;
            pdf *= bs.pdf;
            spec = spec && bs.specular;
            w = bs.wi;
            if (!bs.reflect) {
                *wi = w;
                *pw = pdf;
                *specular = spec;
                return pdf > 0.0f;
            }
            for (j = 0; j < HERO_N; j++) fw[j] *= fabsf(w.z);
        }
    }
    return 0;
}

int layered_sample(const Material *m, const MatPoint *mp, const Frame *fr, Vec3 wo_world,
                   const float *lambda, unsigned alive, float u0, float u1, float u2, uint64_t key,
                   BsdfSample *out)
{
    Layer L;
    Rng rng;
    Vec3 wo = frame_to_local(fr, wo_world), wi;
    int j, flip = wo.z < 0.0f, specular = 0;
    float fw[HERO_N], pw = 0.0f, pdf;
    uint32_t b0, b1, b2;
    for (j = 0; j < HERO_N; j++) { out->f[j] = 0.0f; out->pdf_l[j] = 0.0f; }
    out->delta = 0;
    if (wo.z == 0.0f) return 0;
    if (flip) wo = v3_neg(wo);
    layer_init(m, mp, lambda, alive, &L);
    memcpy(&b0, &u0, 4); memcpy(&b1, &u1, 4); memcpy(&b2, &u2, 4);
    rng_seed(&rng, hash_u64(((uint64_t)b0 << 32) | b1, b2), hash_u64(key, 0x5aULL));
    if (!walk_sample(&L, wo, u0, u1, u2, &rng, &wi, fw, &pw, &specular)) return 0;
    if (!(pw > 0.0f) || wi.z <= 0.0f) return 0;
    out->wi = frame_to_world(fr, flip ? v3_neg(wi) : wi);
    if (specular) {
        /* the smooth coat's mirror reflection: a delta lobe, f holds R/|cos| and
           pdf the lobe's probability, as a smooth dielectric's */
        out->delta = 1;
        pdf = pw;
    } else {
        /* MIS needs the deterministic pdf estimate, seeded from the WORLD
           directions exactly as bsdf_eval seeds it (see the top); f is scaled
           so that f cos / pdf is the walk's f_walk cos / p_walk */
        rng_seed(&rng, layered_seed(wo_world, out->wi, key), 0x9dfULL);
        pdf = walk_pdf(&L, wo, wi, &rng);
    }
    for (j = 0; j < HERO_N; j++) {
        float fj = specular ? fw[j] : fw[j] * pdf / pw;
        out->pdf_l[j] = pdf;
        out->f[j] = (alive & (1u << j)) && isfinite(fj) ? fj : 0.0f;
    }
    out->pdf = pdf;
    return pdf > 0.0f;
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   coateddiffuse_from_params, coatedconductor_from_params: the scene builder's
   (scene.c) layered materials, read from their parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* The slab between a layered material's coat and base (coateddiffuse,
   coatedconductor; layered.c): thickness, HG g, the walks' maxdepth and nsamples,
   each checked and reported at its own parameter's line, then stored in m. */
static int layer_slab(Parser *P, const char *what, const char *file, int line, float th,
                      const Param *pth, float g, const Param *pg, int md, const Param *pd,
                      int ns, const Param *pn, Material *m)
{
    if (!(th < 1e30f))                          /* <= 0: FLT_MIN below, as pbrt-v4 */
        return fail(P, pth ? pth->file : file, pth ? pth->line : line,
                    "%s: \"float thickness\" %g must be finite and > 0", what, th);
    if (!(g > -1.0f && g < 1.0f))
        return fail(P, pg ? pg->file : file, pg ? pg->line : line,
                    "%s: \"float g\" %g must be within (-1, 1)", what, g);
    if (md < 1)
        return fail(P, pd ? pd->file : file, pd ? pd->line : line,
                    "%s: \"integer maxdepth\" %d must be >= 1", what, md);
    if (ns < 1)
        return fail(P, pn ? pn->file : file, pn ? pn->line : line,
                    "%s: \"integer nsamples\" %d must be >= 1", what, ns);
    m->thickness = th > FLT_MIN ? th : FLT_MIN;     /* pbrt-v4 LayeredBxDF: max(th, FLT_MIN) */
    m->hg_g = g < -0.99f ? -0.99f : (g > 0.99f ? 0.99f : g);   /* pbrt-v4's HenyeyGreenstein */
    m->maxdepth = md;
    m->nsamples = ns;
    return 1;
}

/* "texture thickness", "texture g" (float textures) and "texture albedo" (a
   spectrum texture): 1 + each one's index in m, read at each hit by mat_point
   (material.c); 0 where not a texture.  A texture and a number of the same name
   are refused together (pbrt-v4 reads the first and reports the other unused). */
static int layer_textures(Parser *P, ParamList *pl, Material *m)
{
    static const char *const name[3] = { "thickness", "g", "albedo" };
    int *out[3], k;
    out[0] = &m->thickness_tex;
    out[1] = &m->g_tex;
    out[2] = &m->albedo_tex;
    for (k = 0; k < 3; k++) {
        Param *pt = param_find(pl, PT_TEXTURE, name[k]);
        int ti;
        *out[k] = 0;
        if (!pt) continue;
        if (k < 2 ? param_find(pl, PT_FLOAT, name[k]) != NULL : find_spectrum_param(pl, name[k]) != NULL)
            return fail(P, pt->file, pt->line, "\"texture %s\": \"%s\" is given as a number too: give "
                        "one (pbrt-v4 reports the other as unused)", name[k], name[k]);
        ti = texture_lookup(P, pt, k < 2);
        if (ti < 0) return 0;
        *out[k] = ti + 1;
    }
    return 1;
}

/* The coat's index, "NAME": a "float" (1.5 by default; pbrt-v4's ConstantSpectrum)
   or a "spectrum" ("rgb": pbrt-v4's RGBUnboundedSpectrum, whose 360 nm value the
   UV extension keeps), >= 0 everywhere, 0 read as 1 as pbrt-v4 does.  A varying
   one sets m->dispersive: path.c then terminates the secondary wavelengths at the
   hit (pbrt-v4's GetBxDF: TerminateSecondary) and the walks take the hero's index
   (layer_init).  Given both, the float is read, as in pbrt-v4. */
static int layer_eta(Parser *P, ParamList *pl, const char *name, const char *what,
                     const char *file, int line, Material *m)
{
    Param *pf = param_find(pl, PT_FLOAT, name), *ps = find_spectrum_param(pl, name);
    Spectrum n;
    int nm;
    if (pf || !ps) {
        float eta;
        if (!get_float(P, pl, name, 1.5f, &eta)) return 0;
        if (!(eta > 0.0f && eta < 100.0f))
            return fail(P, pf ? pf->file : file, pf ? pf->line : line,
                        "%s: \"float %s\" %g is not an index of refraction", what, name, eta);
        spec_const(&n, eta);
    } else {
        if (!param_spectrum(P, ps, ps->type == PT_RGB ? SPEC_COEFF : SPEC_UNBOUNDED, &n, NULL)) return 0;
        for (nm = SPEC_UV_MIN; ps->type == PT_RGB && nm < SPEC_MIN; nm++) *spec_at(&n, nm) = n.v[0];
        if (!check_spectrum_above(P, ps, file, line, "the coat's \"eta\"", &n, 0.0f, 0)) return 0;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
            if (spec_get(&n, nm) == 0.0f) *spec_at(&n, nm) = 1.0f;
        m->dispersive = !spec_is_constant(&n);
    }
    return material_set_eta(P, m, &n, file, line);
}

/* The slab's single-scattering albedo (0 by default), within [0, 1] at every nm. */
static int layer_albedo(Parser *P, Param *pa, const char *what, const char *file, int line,
                        Material *m)
{
    int nm;
    if (!unit_spectrum_param(P, pa, &m->extra->albedo, 0.0f)) return 0;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
        if (!(spec_get(&m->extra->albedo, nm) >= 0.0f && spec_get(&m->extra->albedo, nm) <= 1.0f))
            return fail(P, pa ? pa->file : file, pa ? pa->line : line,
                        "%s: \"albedo\" %g at %d nm must be within [0, 1]", what,
                        spec_get(&m->extra->albedo, nm), nm);
    return 1;
}

/* pbrt-v4 CoatedDiffuseMaterial: a dielectric coat (float eta,
   roughness) over a Lambertian base (reflectance 0.5), a slab of thickness
   0.01 between them with a medium of albedo 0 and HG g 0; maxdepth 10 and
   nsamples 1 random walks */
int coateddiffuse_from_params(Parser *P, ParamList *pl, const char *file, int line,
                              const char *dir, const char *what, Material *m)
{
    Param *pr = find_spectrum_param(pl, "reflectance"), *pa = find_spectrum_param(pl, "albedo");
    Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
    Param *pth = param_find(pl, PT_FLOAT, "thickness"), *pg = param_find(pl, PT_FLOAT, "g");
    Param *pd = param_find(pl, PT_INTEGER, "maxdepth"), *pn = param_find(pl, PT_INTEGER, "nsamples");
    float th, g;
    int md, ns, given;
    (void)dir;
    m->type = MAT_COATED_DIFFUSE;
    if (!material_extra(m)) return oom(P, file, line);   /* albedo (freed by material_release) */
    find_spectrum_param(pl, "eta");                      /* read by layer_eta */
    param_find(pl, PT_FLOAT, "eta");
    if (!microfacet_alphas(P, pl, file, line, what, m) || !layer_textures(P, pl, m))
        return 0;
    if (pt) {
        /* "texture reflectance": the base's R read at each hit (mat_point) */
        int ti = texture_lookup(P, pt, 0);
        if (ti < 0) return 0;
        m->reflectance_tex = ti + 1;
    }
    if (!get_float(P, pl, "thickness", 0.01f, &th) ||
        !get_float(P, pl, "g", 0.0f, &g) || !get_int(P, pl, "maxdepth", 10, &md, &given) ||
        !get_int(P, pl, "nsamples", 1, &ns, &given))
        return 0;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                             "texture reflectance, float eta, spectrum eta, rgb eta, "
                             "float roughness, "
                             "float uroughness, float vroughness, texture roughness, "
                             "texture uroughness, texture vroughness, "
                             "bool remaproughness, float thickness, spectrum albedo, "
                             "rgb albedo, float g, integer maxdepth, integer nsamples, "
                             "texture thickness, texture g, texture albedo",
                             NULL))
        return 0;
    if (!layer_eta(P, pl, "eta", what, file, line, m)) return 0;
    if (!layer_slab(P, what, file, line, th, pth, g, pg, md, pd, ns, pn, m)) return 0;
    if (!unit_albedo_param(P, pt ? NULL : pr, &m->reflectance, 0.5f, file, line)) return 0;
    if (!layer_albedo(P, pa, what, file, line, m)) return 0;
    return 1;
}

/* pbrt-v4 CoatedConductorMaterial (section 5): a dielectric coat
   ("interface." eta 1.5, roughness 0) over a conductor ("conductor." eta and
   k, Cu by default, or a "reflectance"; roughness 0), a slab of thickness
   0.01 with a medium of albedo 0 and HG g 0; maxdepth 10, nsamples 1 */
int coatedconductor_from_params(Parser *P, ParamList *pl, const char *file, int line,
                                const char *dir, const char *what, Material *m)
{
    Param *pe = find_spectrum_param(pl, "conductor.eta"), *pk = find_spectrum_param(pl, "conductor.k");
    Param *pr = find_spectrum_param(pl, "reflectance"), *pa = find_spectrum_param(pl, "albedo");
    Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
    int ek_tex = (param_find(pl, PT_TEXTURE, "conductor.eta") != NULL) + (param_find(pl, PT_TEXTURE, "conductor.k") != NULL);
    Param *pth = param_find(pl, PT_FLOAT, "thickness"), *pg = param_find(pl, PT_FLOAT, "g");
    Param *pd = param_find(pl, PT_INTEGER, "maxdepth"), *pn = param_find(pl, PT_INTEGER, "nsamples");
    float th, g;
    int md, ns, given;
    Roughness top, base;
    (void)dir;
    m->type = MAT_COATED_CONDUCTOR;
    if (!material_extra(m)) return oom(P, file, line);   /* albedo, cond_eta, k (material_release) */
    find_spectrum_param(pl, "interface.eta");            /* read by layer_eta */
    param_find(pl, PT_FLOAT, "interface.eta");
    if (!microfacet_roughness(P, pl, file, line, what, "interface.", &top) ||
        !microfacet_roughness(P, pl, file, line, what, "conductor.", &base) ||
        !layer_textures(P, pl, m))
        return 0;
    m->alpha = top.alpha_u;                    /* the coat */
    m->alpha_t = top.alpha_v;
    m->alpha_tex = top.tex_u;
    m->alpha_t_tex = top.tex_v;
    m->remap = top.remap;                      /* one remaproughness for both layers */
    m->cond_alpha = base.alpha_u;              /* the conductor */
    m->cond_alpha_t = base.alpha_v;
    m->cond_alpha_tex = base.tex_u;
    m->cond_alpha_t_tex = base.tex_v;
    if (!get_float(P, pl, "thickness", 0.01f, &th) || !get_float(P, pl, "g", 0.0f, &g) ||
        !get_int(P, pl, "maxdepth", 10, &md, &given) || !get_int(P, pl, "nsamples", 1, &ns, &given))
        return 0;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "float interface.eta, spectrum interface.eta, "
                             "rgb interface.eta, float interface.roughness, "
                             "float interface.uroughness, float interface.vroughness, "
                             "texture interface.roughness, texture interface.uroughness, "
                             "texture interface.vroughness, spectrum conductor.eta, "
                             "spectrum conductor.k, rgb conductor.eta, rgb conductor.k, "
                             "texture conductor.eta, texture conductor.k, "
                             "spectrum reflectance, rgb reflectance, "
                             "texture reflectance, float conductor.roughness, "
                             "float conductor.uroughness, float conductor.vroughness, "
                             "texture conductor.roughness, texture conductor.uroughness, "
                             "texture conductor.vroughness, bool remaproughness, "
                             "float thickness, spectrum albedo, rgb albedo, float g, "
                             "integer maxdepth, integer nsamples, texture thickness, "
                             "texture g, texture albedo", NULL))
        return 0;
    if ((pr || pt) && (pe || pk || ek_tex))
        return fail(P, file, line, "%s: give either \"reflectance\" or \"conductor.eta\" and "
                    "\"conductor.k\", not both (pbrt-v4 refuses it too)", what);
    if (!layer_eta(P, pl, "interface.eta", what, file, line, m)) return 0;
    if (!layer_slab(P, what, file, line, th, pth, g, pg, md, pd, ns, pn, m)) return 0;
    if (!layer_albedo(P, pa, what, file, line, m)) return 0;
    if (pt) {
        /* "texture reflectance": r read at each hit (mat_point), n and k from it
           there (layered.c layer_init) */
        int ti = texture_lookup(P, pt, 0);
        if (ti < 0) return 0;
        m->reflectance_tex = ti + 1;
        spec_const(&m->extra->cond_eta, 1.0f);
        spec_const(&m->extra->k, 0.0f);                  /* (not read) */
    } else if (pr) {
        Spectrum r;                 /* r, shared (albedo_set_table) */
        if (!conductor_reflectance_param(P, pr, &r, &m->extra->cond_eta, &m->extra->k) ||
            !albedo_set_table(P, &m->reflectance, &r, file, line))
            return 0;
    } else {
        if (!conductor_eta_k_textures(P, pl, "conductor.", what, m->extra) ||
            !conductor_eta_k(P, pl, file, line, "conductor.", &m->extra->cond_eta, &m->extra->k))
            return 0;
    }
    return 1;
}
