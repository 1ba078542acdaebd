/* lights.c - emitters, and how next event estimation chooses one of them.

   Exported (specnee.h section 11): emitters_prepare, emitter_Le, emitter_sample,
   emitter_pdf_sa, light_sampler_build/free, light_voxel, light_select,
   light_select_pmf, light_sampler_bytes, sel_from_name, sel_name.

   1. Emitters.  An emitter is one AreaLightSource shape: a whole mesh (or sphere).
      Its radiance follows pbrt-v4's normalisation (DiffuseAreaLight::Create):
          Le(lambda) = scale * L(lambda) / sum_{lambda = lo..hi, 1 nm} ybar(lambda) L(lambda)
      over the range the film integrates, so a directly seen emitter has Y = scale.
      A one-sided emitter emits only to the side its oriented normal points to.
      Points are sampled by area: a triangle with probability area_t / A, then a
      uniform point on it (u = 1 - sqrt(u1), v = u2 sqrt(u1)).  Converted to solid
      angle at the reference point x (pbrt-v3/v4 Shape::Sample):
          p_sigma(y) = |x - y|^2 / (A |cos theta_y|).

   2. Selection.  light_select picks emitter i with probability P(i | c), where the
      context c = (voxel, wavelengths, alive set, hero_only) is fixed at the vertex
      and stored by the integrator; light_select_pmf(c, i) returns the same number
      for an emitter hit by BSDF sampling (the consistency contract, items C1-C4 of
      docs/THEORY.md section 5).
      Strategies (T_i(b) = bin average of Le_i over bin b, times area x sides with
      the power metric):
        uniform           1/n
        power             proportional to pi * A_i * (2 if two-sided) * int_400^700 Le_i
        spatial           s_i(v): pbrt-v3's SpatialLightDistribution (see below)
        spd               thesis Sec. 2: T_i(b(lambda_h)) / sum_k T_k(b(lambda_h))
        product           thesis Sec. 2 ("combined PDF"): s_i(v) T_i(b) / sum_k s_k(v) T_k(b)
        spectral-spatial  beyond the thesis: g_i(v) T_i(b) / sum_k g_k(v) T_k(b), with
                          g_i(v) the spatial estimate for UNIT radiance, so brightness
                          is counted once (the thesis' argument for the unit
                          metric, thesis Sec. 2 "Combining PDFs")
      T_i(b) with the unit metric (the default) is the bin average of the emitted
      radiance Le_i, the thesis' "unit emission"; the power metric multiplies it by
      the area (x 2 if two-sided), the thesis' "power".
      The spectral strategies act only where the path carries the hero alone
      (after a wavelength-dependent event, LightCtx.hero_only); while several
      wavelengths are alive the thesis uses the spatial distribution.  Beyond the
      thesis (all_wavelengths), the weight of emitter i is sum over alive j of
      c_j * e_i(lambda_j), with e_i the strategy's unnormalised weight and c_j = 1
      or the path throughput at lambda_j.  Either way P(i | c) is the same whichever
      alive wavelength is the hero: item C4 of the contract, which the single
      q_nee of render.c's MIS weights needs (docs/THEORY.md section 6 derives why).  When every emitter has weight 0 for the hero's bin
      (or the hero lies outside 400-700 nm) the spatial distribution is used
      (counted as a fallback); the same rule runs in light_select_pmf.

   3. The spatial distribution (pbrt-v3 lightdistrib.cpp; docs/THEORY.md section 5): a grid
      over the scene bounds with SPATIAL_RES cells on the longest axis; per voxel,
      for k = 0..127, a receiver point at Halton(2,3,5)(k) in the voxel and an
      emitter sample at Halton(7,11,13)(k); each emitter j accumulates
          g_j += [emitter faces the receiver] / p_sigma,   s_j = Y_j g_j,
      an estimate of the unoccluded scalar irradiance (no cosine, no visibility).
      Y_j = scale_j is the emitter's luminance.  A floor of 1e-3 of the mean weight
      keeps every emitter possible.  Voxels are built lazily on first use (under an
      OpenMP critical section) or all up front; both give identical tables because
      the computation is deterministic. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* ------------------------------------------------------------------ emitters */

static double tri_area(const Scene *s, int t)
{
    const Triangle *tr = &s->tris[t];
    Vec3 e1 = v3_sub(s->P[tr->v[1]], s->P[tr->v[0]]);
    Vec3 e2 = v3_sub(s->P[tr->v[2]], s->P[tr->v[0]]);
    return 0.5 * (double)v3_len(v3_cross(e1, e2));
}

int emitters_prepare(Scene *s, float lo_nm, float hi_nm, Error *err)
{
    int e, b, t, lam;
    for (e = 0; e < s->n_emitters; e++) {
        Emitter *em = &s->emitters[e];
        const Shape *sh = &s->shapes[em->shape];
        double norm = 0.0, sum = 0.0;
        for (lam = (int)ceilf(lo_nm); lam <= (int)floorf(hi_nm); lam++) {
            float xyz[3];
            cie_xyz((float)lam, xyz);
            norm += (double)xyz[1] * spec_eval(&em->L, (float)lam);
        }
        /* A UV lamp has no luminance: its L is absolute spectral radiance, and the
           decision is the emitter's own (made on 400-700 nm, whatever range the
           film integrates now), so every range gives it the same meaning. */
        em->absolute = 0;
        {
            double vis = 0.0;
            for (lam = (int)LAMBDA_LO; lam <= (int)LAMBDA_HI; lam++) {
                float xyz[3];
                cie_xyz((float)lam, xyz);
                vis += (double)xyz[1] * spec_eval(&em->L, (float)lam);
            }
            if (!(vis > 0.0)) { em->absolute = 1; norm = 1.0; }
        }
        if (!(norm > 0.0)) {
            error_set(err, sh->file, sh->line,
                      "AreaLightSource: spectrum L emits nothing visible in %g-%g nm", lo_nm, hi_nm);
            return 0;
        }
        for (lam = 0; lam < SPEC_N; lam++)
            em->Le.v[lam] = (float)(em->scale * em->L.v[lam] / norm);
        for (lam = 0; lam < SPEC_UV_N; lam++)
            em->Le.uv[lam] = (float)(em->scale * em->L.uv[lam] / norm);
        /* area and the triangle CDF */
        free(em->tri_cdf);
        em->tri_cdf = NULL;
        if (sh->type == SHAPE_SPHERE) {
            em->area = 4.0 * SPECNEE_PI * sh->radius * sh->radius;
        } else {
            double acc = 0.0;
            em->tri_cdf = (float *)malloc(sizeof(float) * (size_t)(sh->tri_count + 1));
            if (!em->tri_cdf) { error_set(err, sh->file, sh->line, "out of memory"); return 0; }
            em->tri_cdf[0] = 0.0f;
            for (t = 0; t < sh->tri_count; t++) {
                acc += tri_area(s, sh->tri_begin + t);
                em->tri_cdf[t + 1] = (float)acc;
            }
            em->area = acc;
            for (t = 1; t <= sh->tri_count; t++) em->tri_cdf[t] = acc > 0 ? (float)(em->tri_cdf[t] / acc) : 1.0f;
            em->tri_cdf[sh->tri_count] = 1.0f;
        }
        if (!(em->area > 0.0)) {
            error_set(err, sh->file, sh->line, "AreaLightSource: emitting shape has zero area");
            return 0;
        }
        for (b = 0; b < SPD_BINS; b++) {
            em->bin[b] = spec_bin_average(&em->Le, b);
            sum += em->bin[b] * SPD_BIN_NM;
        }
        for (b = 0; b < SPD_UV_BINS; b++)
            em->bin_uv[b] = spec_band_average(&em->Le, SPEC_UV_MIN + (int)SPD_BIN_NM * b, (int)SPD_BIN_NM);
        em->power = SPECNEE_PI * em->area * (em->twosided ? 2.0 : 1.0) * sum;
    }
    return 1;
}

float emitter_Le(const Scene *s, int e, Vec3 n, Vec3 w, float lambda_nm)
{
    const Emitter *em = &s->emitters[e];
    if (!em->twosided && v3_dot(n, w) <= 0.0f) return 0.0f;
    return spec_eval(&em->Le, lambda_nm);
}

int emitter_sample(const Scene *s, int e, Vec3 ref, float u0, float u1, float u2,
                   EmitterSample *out)
{
    const Emitter *em = &s->emitters[e];
    const Shape *sh = &s->shapes[em->shape];
    Vec3 d;
    float dist2, cos_y;
    if (sh->type == SHAPE_SPHERE) {
        float z = 1.0f - 2.0f * u1, r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
        float phi = 2.0f * PI_F * u2;
        Vec3 dir = v3(r * cosf(phi), r * sinf(phi), z);
        (void)u0;
        out->p = v3_add(sh->center, v3_mul(dir, sh->radius));
        out->n = sh->flip ? v3_neg(dir) : dir;
    } else {
        /* pick a triangle by area: first cdf entry above u0 (binary search) */
        int lo = 0, hi = sh->tri_count - 1;
        HitRecord h;
        SurfacePoint sp;
        Ray dummy;
        float su;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (em->tri_cdf[mid + 1] <= u0) lo = mid + 1; else hi = mid;
        }
        su = sqrtf(u1);
        h.t = 0.0f;
        h.prim = sh->tri_begin + lo;
        h.b1 = u2 * su;                    /* barycentric of v1 */
        h.b2 = 1.0f - su;                  /* barycentric of v2 */
        dummy.o = ref; dummy.d = v3(0, 0, 1); dummy.tmax = 0.0f;
        scene_surface_point(s, &dummy, &h, &sp);
        out->p = sp.p;
        out->n = sp.ng;
    }
    d = v3_sub(out->p, ref);
    dist2 = v3_dot(d, d);
    if (!(dist2 > 0.0f)) return 0;
    out->dist = sqrtf(dist2);
    out->wi = v3_mul(d, 1.0f / out->dist);
    cos_y = fabsf(v3_dot(out->n, out->wi));
    if (!(cos_y > 0.0f)) return 0;
    out->pdf_sa = (float)(dist2 / (em->area * cos_y));
    return isfinite(out->pdf_sa) && out->pdf_sa > 0.0f;
}

float emitter_pdf_sa(const Scene *s, int e, Vec3 ref, Vec3 p, Vec3 n)
{
    Vec3 d = v3_sub(p, ref);
    float dist2 = v3_dot(d, d), cos_y;
    if (!(dist2 > 0.0f)) return 0.0f;
    cos_y = fabsf(v3_dot(n, d)) / sqrtf(dist2);
    if (!(cos_y > 0.0f)) return 0.0f;
    return (float)(dist2 / (s->emitters[e].area * cos_y));
}

/* ------------------------------------------------------------------ selection */

struct LightSampler {
    const Scene *scene;
    SelOptions opt;
    int n;                     /* number of emitters */
    float *power_pmf;          /* power strategy */
    float *T;                  /* (SPD_UV_BINS + SPD_BINS) x n spectral table (unit or power
                                  metric): rows 0..19 are 300-400 nm, rows 20..79 the
                                  thesis' 60 bins over 400-700 nm */
    float *Y;                  /* luminance (= scale) per emitter */
    /* spatial grid */
    int res[3];
    Vec3 bmin, bmax;
    long n_voxels;
    float **voxel;             /* per voxel: s[n] (spatial pmf) then g[n] (geometry) */
    double lazy_s;             /* seconds spent building voxels on first use (under the
                                  critical section, so the sum is time really spent) */
};

/* A clock for lazy_s: OpenMP's wall clock, else the CPU clock (one thread). */
static double lights_seconds(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    return (double)clock() / CLOCKS_PER_SEC;
#endif
}

static const char *const sel_names[SEL_COUNT] = {
    "uniform", "power", "spatial", "spd", "product", "spectral-spatial", "all"
};

const char *sel_name(SelStrategy st)
{
    return (st >= 0 && st < SEL_COUNT) ? sel_names[st] : "?";
}

SelStrategy sel_from_name(const char *name)
{
    int i;
    for (i = 0; i < SEL_COUNT; i++)
        if (strcmp(name, sel_names[i]) == 0) return (SelStrategy)i;
    return SEL_COUNT;
}

static int uses_grid(SelStrategy st)
{
    return st == SEL_SPATIAL || st == SEL_SPD || st == SEL_PRODUCT || st == SEL_SPECTRAL_SPATIAL;
}

/* The per-voxel estimate of section 3 above: fills s[n] (a pmf) and g[n]. */
static void build_voxel(const LightSampler *ls, long v, float *out)
{
    const Scene *s = ls->scene;
    int n = ls->n, j, k;
    long vx = v % ls->res[0], vy = (v / ls->res[0]) % ls->res[1], vz = v / ((long)ls->res[0] * ls->res[1]);
    double *g = (double *)calloc((size_t)n, sizeof(double));
    double sum_w = 0.0, sum_g = 0.0, floor_w, floor_g;
    Vec3 ext = v3_sub(ls->bmax, ls->bmin);
    if (!g) return;                                    /* caller checks out[] later */
    for (k = 0; k < SPATIAL_SAMPLES; k++) {
        Vec3 p = v3(ls->bmin.x + ext.x * (float)((vx + radical_inverse(2, (uint64_t)k)) / ls->res[0]),
                    ls->bmin.y + ext.y * (float)((vy + radical_inverse(3, (uint64_t)k)) / ls->res[1]),
                    ls->bmin.z + ext.z * (float)((vz + radical_inverse(5, (uint64_t)k)) / ls->res[2]));
        float u0 = (float)radical_inverse(7, (uint64_t)k), u1 = (float)radical_inverse(11, (uint64_t)k);
        float u2 = (float)radical_inverse(13, (uint64_t)k);
        for (j = 0; j < n; j++) {
            EmitterSample es;
            if (!emitter_sample(s, j, p, u0, u1, u2, &es)) continue;
            /* one-sided: no light towards a receiver behind the emitter */
            if (!s->emitters[j].twosided && v3_dot(es.n, v3_neg(es.wi)) <= 0.0f) continue;
            g[j] += 1.0 / es.pdf_sa;
        }
    }
    for (j = 0; j < n; j++) { sum_g += g[j]; sum_w += g[j] * ls->Y[j]; }
    /* pbrt-v3's floor: 1e-3 of the per-sample mean, or 1 when nothing is seen */
    floor_w = sum_w > 0 ? 1e-3 * sum_w / (SPATIAL_SAMPLES * (double)n) : 1.0;
    floor_g = sum_g > 0 ? 1e-3 * sum_g / (SPATIAL_SAMPLES * (double)n) : 1.0;
    sum_w = 0.0;
    for (j = 0; j < n; j++) {
        double w = g[j] * ls->Y[j];
        if (w < floor_w) w = floor_w;
        out[j] = (float)w;
        sum_w += w;
        out[n + j] = (float)(g[j] < floor_g ? floor_g : g[j]);
    }
    for (j = 0; j < n; j++) out[j] = (float)(out[j] / sum_w);
    free(g);
}

int light_voxel(const LightSampler *ls, Vec3 p)
{
    int a, c[3];
    float lo[3], hi[3], q[3];
    if (!ls->voxel) return -1;
    lo[0] = ls->bmin.x; lo[1] = ls->bmin.y; lo[2] = ls->bmin.z;
    hi[0] = ls->bmax.x; hi[1] = ls->bmax.y; hi[2] = ls->bmax.z;
    q[0] = p.x; q[1] = p.y; q[2] = p.z;
    for (a = 0; a < 3; a++) {
        float o = hi[a] > lo[a] ? (q[a] - lo[a]) / (hi[a] - lo[a]) : 0.0f;
        int i = (int)floorf(o * (float)ls->res[a]);
        if (!(i >= 0)) i = 0;                           /* also catches NaN */
        if (i >= ls->res[a]) i = ls->res[a] - 1;
        c[a] = i;
    }
    return (int)(c[0] + (long)ls->res[0] * (c[1] + (long)ls->res[1] * c[2]));
}

/* The voxel's table, built on first use.  Readers take the pointer atomically;
   a missing voxel is built inside a critical section, once. */
static const float *voxel_table(LightSampler *ls, int v)
{
    float *t;
#ifdef _OPENMP
#pragma omp atomic read
#endif
    t = ls->voxel[v];
    if (t) return t;
#ifdef _OPENMP
#pragma omp critical(specnee_voxel)
#endif
    {
        if (!ls->voxel[v]) {
            float *nt = (float *)malloc(sizeof(float) * 2 * (size_t)ls->n);
            if (nt) {
                double t0 = lights_seconds();
                build_voxel(ls, v, nt);
                ls->lazy_s += lights_seconds() - t0;
#ifdef _OPENMP
#pragma omp flush
#pragma omp atomic write
#endif
                ls->voxel[v] = nt;
            }
        }
        t = ls->voxel[v];
    }
    return t;
}

LightSampler *light_sampler_build(const Scene *s, const SelOptions *o, Error *err)
{
    LightSampler *ls = (LightSampler *)calloc(1, sizeof *ls);
    int n = s->n_emitters, i, b;
    double sum = 0.0;
    if (!ls) { error_set(err, NULL, 0, "out of memory"); return NULL; }
    ls->scene = s;
    ls->opt = *o;
    ls->n = n;
    if (n == 0) return ls;
    ls->power_pmf = (float *)malloc(sizeof(float) * (size_t)n);
    ls->T = (float *)malloc(sizeof(float) * (size_t)n * (SPD_UV_BINS + SPD_BINS));
    ls->Y = (float *)malloc(sizeof(float) * (size_t)n);
    if (!ls->power_pmf || !ls->T || !ls->Y) goto oom;
    for (i = 0; i < n; i++) sum += s->emitters[i].power;
    for (i = 0; i < n; i++)
        ls->power_pmf[i] = sum > 0 ? (float)(s->emitters[i].power / sum) : 1.0f / (float)n;
    for (i = 0; i < n; i++) {
        const Emitter *em = &s->emitters[i];
        float m = o->power_metric ? (float)(em->area * (em->twosided ? 2.0 : 1.0)) : 1.0f;
        ls->Y[i] = em->scale;
        for (b = 0; b < SPD_UV_BINS; b++) ls->T[b * n + i] = em->bin_uv[b] * m;
        for (b = 0; b < SPD_BINS; b++) ls->T[(SPD_UV_BINS + b) * n + i] = em->bin[b] * m;
    }
    if (uses_grid(o->strategy)) {
        Vec3 d = v3_sub(s->bmax, s->bmin);
        float dmax = fmaxf(d.x, fmaxf(d.y, d.z));
        int a;
        ls->bmin = s->bmin;
        ls->bmax = s->bmax;
        for (a = 0; a < 3; a++) {
            float da = v3_get(d, a);
            int res = o->grid_res > 0 ? o->grid_res : SPATIAL_RES;
            int r = dmax > 0 ? (int)lroundf((float)res * da / dmax) : 1;
            ls->res[a] = r < 1 ? 1 : r;
        }
        ls->n_voxels = (long)ls->res[0] * ls->res[1] * ls->res[2];
        ls->voxel = (float **)calloc((size_t)ls->n_voxels, sizeof(float *));
        if (!ls->voxel) goto oom;
        if (o->eager) {
            long v;
            for (v = 0; v < ls->n_voxels; v++)
                if (!voxel_table(ls, (int)v)) goto oom;
            ls->lazy_s = 0.0;          /* built up front: counted in the build time */
        }
    }
    return ls;
oom:
    light_sampler_free(ls);
    error_set(err, NULL, 0, "out of memory building the light sampler");
    return NULL;
}

void light_sampler_free(LightSampler *ls)
{
    long v;
    if (!ls) return;
    if (ls->voxel)
        for (v = 0; v < ls->n_voxels; v++) free(ls->voxel[v]);
    free(ls->voxel);
    free(ls->power_pmf);
    free(ls->T);
    free(ls->Y);
    free(ls);
}

double light_sampler_lazy_seconds(const LightSampler *ls)
{
    return ls->lazy_s;
}

size_t light_sampler_bytes(const LightSampler *ls)
{
    size_t bytes = sizeof *ls + sizeof(float) * (size_t)ls->n * (2 + SPD_UV_BINS + SPD_BINS);
    long v;
    if (ls->voxel) {
        bytes += sizeof(float *) * (size_t)ls->n_voxels;
        for (v = 0; v < ls->n_voxels; v++)
            if (ls->voxel[v]) bytes += sizeof(float) * 2 * (size_t)ls->n;
    }
    return bytes;
}

/* Row of a wavelength in the spectral table T: the thesis' 60 bins over 400-700 nm
   are rows SPD_UV_BINS.., the 20 UV bins over 300-400 nm (fluorescence excitation,
   docs/FLUORESCENCE.md section 5) rows 0..19; -1 outside 300-700 nm. */
static int spd_bin(float lambda)
{
    int b;
    if (lambda >= (float)SPEC_UV_MIN && lambda < LAMBDA_LO) {
        b = (int)((lambda - (float)SPEC_UV_MIN) / SPD_BIN_NM);
        return b >= SPD_UV_BINS ? SPD_UV_BINS - 1 : b;
    }
    if (!(lambda >= LAMBDA_LO && lambda <= LAMBDA_HI)) return -1;
    b = (int)((lambda - LAMBDA_LO) / SPD_BIN_NM);
    return SPD_UV_BINS + (b >= SPD_BINS ? SPD_BINS - 1 : b);
}

/* The unnormalised weights w[i] of the context; returns their sum.  Both
   light_select and light_select_pmf go through here, so they cannot disagree.
   *fell_back = 1 when a spectral strategy had to use the spatial weights. */
static double context_weights(LightSampler *ls, const LightCtx *c, double *w, int *fell_back)
{
    int n = ls->n, i, j;
    SelStrategy st = ls->opt.strategy;
    double sum = 0.0;
    const float *vt = NULL;
    *fell_back = 0;
    if (st == SEL_UNIFORM || st == SEL_ALL) {
        for (i = 0; i < n; i++) w[i] = 1.0;
        return n;
    }
    if (st == SEL_POWER) {
        for (i = 0; i < n; i++) w[i] = ls->power_pmf[i];
        return 1.0;
    }
    if (c->voxel >= 0 && c->voxel < ls->n_voxels) vt = voxel_table(ls, c->voxel);
    if (!vt) {                                   /* out of memory: degrade to uniform */
        for (i = 0; i < n; i++) w[i] = 1.0;
        return n;
    }
    if (st != SEL_SPATIAL && (c->hero_only || ls->opt.all_wavelengths)) {
        /* spectral weights, summed over the wavelengths that count here */
        for (i = 0; i < n; i++) w[i] = 0.0;
        for (j = 0; j < HERO_N; j++) {
            int b;
            double cj = 1.0;
            if (!(c->alive & (1u << j))) continue;
            if (c->hero_only && j > 0) continue;
            b = spd_bin(c->lambda[j]);
            if (b < 0) continue;
            if (ls->opt.throughput_weighted && ls->opt.all_wavelengths) cj = c->beta[j];
            if (!(cj > 0.0)) continue;
            for (i = 0; i < n; i++) {
                double e = ls->T[b * n + i];
                if (st == SEL_PRODUCT) e *= vt[i];
                else if (st == SEL_SPECTRAL_SPATIAL) e *= vt[n + i];
                w[i] += cj * e;
            }
        }
        for (i = 0; i < n; i++) sum += w[i];
        if (sum > 0.0 && isfinite(sum)) return sum;
        *fell_back = 1;                          /* no emitter for these bins */
    }
    sum = 0.0;
    for (i = 0; i < n; i++) { w[i] = vt[i]; sum += w[i]; }
    return sum;
}

/* Small scenes have a handful of emitters; 64 are tested.  Stack storage up to
   that many, heap beyond. */
#define SEL_STACK 128

int light_select(LightSampler *ls, const LightCtx *c, float u, float *pmf, int *fell_back)
{
    double wbuf[SEL_STACK], *w = wbuf, sum, acc = 0.0, target;
    int n = ls->n, i, fb, chosen = -1;
    *pmf = 0.0f;
    if (fell_back) *fell_back = 0;
    if (n == 0) return -1;
    if (n > SEL_STACK && !(w = (double *)malloc(sizeof(double) * (size_t)n))) return -1;
    sum = context_weights(ls, c, w, &fb);
    if (fell_back) *fell_back = fb;
    if (sum > 0.0) {
        target = (double)u * sum;
        for (i = 0; i < n; i++) {
            acc += w[i];
            if (target < acc && w[i] > 0.0) { chosen = i; break; }
        }
        if (chosen < 0)                          /* round-off at u -> 1: last positive */
            for (i = n - 1; i >= 0; i--)
                if (w[i] > 0.0) { chosen = i; break; }
        if (chosen >= 0) *pmf = (float)(w[chosen] / sum);
    }
    if (w != wbuf) free(w);
    return chosen;
}

float light_select_pmf(LightSampler *ls, const LightCtx *c, int e)
{
    double wbuf[SEL_STACK], *w = wbuf, sum;
    int n = ls->n, fb;
    float p = 0.0f;
    if (e < 0 || e >= n) return 0.0f;
    if (n > SEL_STACK && !(w = (double *)malloc(sizeof(double) * (size_t)n))) return 0.0f;
    sum = context_weights(ls, c, w, &fb);
    if (sum > 0.0) p = (float)(w[e] / sum);
    if (w != wbuf) free(w);
    return p;
}
