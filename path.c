/* path.c - the path estimator: one camera sample's contributions to the film.

   Exported (render.h, for render.c): trace_path.

   THE ESTIMATOR.  docs/THEORY.md derives it; the numbers (2)-(9) below are its
   equation numbers, and the symbols are those of its section 0.  Each camera
   sample draws u and four wavelengths by rotation in the CDF P of the wavelength
   pdf p (HWSS, Wilkie et al. 2014, rotated in the CDF as in West et al. 2020):
   lambda_j = P^-1(frac(u + j/4))  (2), so every lambda_j has marginal density p.
   The path X is sampled with the hero lambda_0 only.  For a path ended by
   technique t (NEE or BSDF sampling) the film receives, for each wavelength j,

                      f(X, lambda_j) p_t(X | lambda_0)
        C_j = --------------------------------------------------        (4)
               p(lambda_j) * sum_{t', m} p_t'(X | lambda_m)^2

   the power heuristic over every (technique, hero) pair that could have made X
   (THEORY section 4).  Writing beta_j = f(prefix, lambda_j)/p(prefix | lambda_0)
   for the throughput and r_m = p(prefix | lambda_m)/p(prefix | lambda_0) for the
   pdf ratio of the path so far (r_0 = 1), and g_j = f_s Le_j |cos| for the last
   segment, a contribution at the last vertex with the technique densities
   q_nee = P(e | c) p_sigma (selection pmf x solid-angle pdf; one value for every m,
   THEORY section 6) and q_bsdf(m) (the BSDF pdf of the last direction with
   wavelength m's index) is

        C_j = beta_j g_j q_t(0) / (p(lambda_j) D),
        D   = sum_m r_m^2 (q_nee^2 + q_bsdf(m)^2)                          (6)

   In the code `w` = q_nee(0)/D multiplies an NEE contribution; a BSDF-sampled hit,
   whose beta already holds 1/q_bsdf(0), is multiplied by the MIS weight
   `W` = q_bsdf(0)^2/D (= q_bsdf(0) w); film_add divides by p(lambda_j) once (9).
   Special cases that make this readable:
   - No wavelength-dependent event so far: r_m = 1 and q_bsdf(m) = q_bsdf(0), so
     C_j is the usual power-heuristic NEE/BSDF weight times 1/(4 p(lambda_j)):
     pbrt-v4's film average.
   - Termination at a dispersive dielectric (thesis baseline, pbrt-v4
     TerminateSecondary; THEORY section 7): r = (1, 0, 0, 0) and beta_1..3 = 0, so
     the hero gets weight 1/p(lambda_0) - the "divide the hero pdf by 4"
     bookkeeping.
   - Single-wavelength mode: r = (1, 0, 0, 0) from the start.
   - Rough spectral MIS (beyond the baseline, --rough-dispersion mis): at a rough
     dispersive interface the secondaries survive; every later direction pdf is
     evaluated with each wavelength's own index and the ratios r_m carry them.
     Smooth dispersive interfaces still terminate: their pdf for any other
     wavelength is zero.
   Emission reached at depth 0 or after a specular bounce has q_nee = 0: no NEE
   could have produced it.

   PARTICIPATING MEDIA (THEORY section 12, docs/media.md).  In a medium the next
   vertex may be a collision: medium_flight draws the distance with the hero's
   sigma_t (16) and multiplies the ratios r_m by the other wavelengths' densities
   of the same collision or passage (17); medium_vertex adds the medium's emission
   (20) and scatters with the phase function; next_event multiplies NEE by the
   shadow ray's transmittance and every BSDF/phase density in D by T_m (19), as
   PrevVertex.T does for an emitter that a sampled direction finds.  Surfaces of
   Material "interface" only hand the ray from one medium to the next.

   Russian roulette (from depth RR_START_DEPTH) survives with probability
   q = min(1, 4 max_j beta_j / sum_m r_m)  (8).  beta_j / sum_m r_m =
   f_j / sum_m p(prefix | lambda_m) does not depend on which wavelength was the
   hero, so the roulette is the same for every technique and needs no place in (4).

   NEE picks one emitter with light_select (lights.c) in a context that is stored
   with the vertex, so that a BSDF-sampled hit on an emitter is weighted with the
   same selection probability (the consistency contract, item C1, THEORY section 5).

   The film averages C_j x (xbar, ybar, zbar)(lambda_j) per pixel: an estimate of
   the integrals of xbar L, ybar L, zbar L over the sampled range, not divided by
   the integral of ybar (emitters are normalised instead, as in pbrt-v4), then
   converted to linear sRGB with pbrt-v4's matrix.  Every (pixel, sample) owns its
   random stream, every pixel is written by one thread: the image is identical
   for any number of threads. */
#include "render.h"
#include <string.h>

/* ------------------------------------------------------------------ the path */

/* What the integrator remembers of the previous vertex for the MIS weight of an
   emitter found by BSDF sampling. */
typedef struct {
    int can_nee;                     /* NEE was possible there (non-delta, NEE on) */
    LightCtx ctx;                    /* the selection context used there */
    Vec3 p;                          /* its position */
    float q_bsdf[HERO_N];            /* pdf of the sampled direction per wavelength */
    float r[HERO_N];                 /* pdf ratios of the prefix before that vertex */
    double T[HERO_N];                /* transmittance of the media since that vertex, per
                                        wavelength (1 without media): the BSDF technique's
                                        pdf of the segment is q_bsdf(m) T_m (docs/media.md) */
    unsigned alive;                  /* wavelengths alive at that vertex */
} PrevVertex;

/* sum_m r_m^2 (q_nee^2 + (q_bsdf(m) T_m)^2) over the alive wavelengths */
static double mis_denominator(const float *r, const float *q_bsdf, const double *T, float q_nee,
                              unsigned alive)
{
    double d = 0.0;
    int m;
    for (m = 0; m < HERO_N; m++)
        if (alive & (1u << m)) {
            double qb = (double)q_bsdf[m] * T[m];
            d += (double)r[m] * r[m] * ((double)q_nee * q_nee + qb * qb);
        }
    return d;
}

/* XYZ += sum_j cmf(lambda_j) value_j w / p(lambda_j) */
static void film_add(double xyz[3], float cmf[HERO_N][3], const Wavelengths *wl,
                     const double *value, double w, unsigned alive)
{
    int j;
    for (j = 0; j < HERO_N; j++) {
        double v;
        if (!(alive & (1u << j)) || value[j] == 0.0) continue;
        v = value[j] * w / wl->pdf[j];
        xyz[0] += cmf[j][0] * v;
        xyz[1] += cmf[j][1] * v;
        xyz[2] += cmf[j][2] * v;
    }
}

static void debug_vertex(FILE *dbg, int depth, const SurfacePoint *sp, const float *beta,
                         unsigned alive, const float *r)
{
    fprintf(dbg, "  vertex %d: p=(%.4g %.4g %.4g) shape=%d alive=%c%c%c%c beta=(%.4g %.4g %.4g %.4g) r=(%.3g %.3g %.3g %.3g)\n",
            depth, sp->p.x, sp->p.y, sp->p.z, sp->shape,
            alive & 1 ? 'h' : '-', alive & 2 ? '1' : '-', alive & 4 ? '2' : '-', alive & 8 ? '3' : '-',
            beta[0], beta[1], beta[2], beta[3], r[0], r[1], r[2], r[3]);
}

/* --debug-pixel: where P(e | c) came from (the rule of lights.c, section 2). */
static const char *debug_pmf_source(const SelOptions *sel, const LightCtx *c, int fell_back)
{
    SelStrategy st = sel->strategy;
    if (st == SEL_UNIFORM) return "uniform";
    if (st == SEL_POWER) return "power table";
    if (st == SEL_SPATIAL) return "spatial table of the voxel";
    if (st == SEL_TREE) return "light tree, total power";
    if (st == SEL_SPECTRAL_TREE) return "light tree, power in the alive wavelengths' bins";
    if (st == SEL_ALL) return "every emitter";
    if (fell_back) return "spatial table: no emitter emits in the bins of these wavelengths (fallback)";
    if (c->hero_only)
        return st == SEL_SPD ? "spectral table T_e(b) at the hero's bin"
             : st == SEL_PRODUCT ? "spectral table T_e(b) at the hero's bin x spatial table"
             : "spectral table T_e(b) at the hero's bin x unit-radiance spatial table";
    if (sel->all_wavelengths || c->shifted)
        return "spectral table summed over the alive wavelengths' bins";
    return "spatial table of the voxel: several wavelengths alive, spectral tables act on hero-only paths";
}

/* --debug-pixel: a contribution's MIS weight W = q_t(0)^2 / D (the film receives
   W / (q_t(0) p(lambda_j)) times the integrand, THEORY (6)) split into the share of
   the technique t, summed over every hero m, and the share of hero 0 within t:
       W = [sum_m r_m^2 q_t(m)^2 / D] x [q_t(0)^2 / sum_m r_m^2 q_t(m)^2]. */
static void debug_weight(FILE *dbg, const char *what, int e, double w, const float *r,
                         const float *q_bsdf, float q_nee, unsigned alive, int nee)
{
    double tech = 0.0, den = 0.0, q0;
    int m, n = 0;
    for (m = 0; m < HERO_N; m++)
        if (alive & (1u << m)) {
            double qn = (double)r[m] * r[m] * q_nee * q_nee;
            double qb = (double)r[m] * r[m] * q_bsdf[m] * q_bsdf[m];
            tech += nee ? qn : qb;
            den += qn + qb;
            n++;
        }
    q0 = nee ? (double)q_nee * q_nee : (double)q_bsdf[0] * q_bsdf[0];
    fprintf(dbg, "  %s %d: MIS weight %.4g = %s share %.4g x hero share %.4g (%d wavelength%s alive)\n",
            what, e, w, nee ? "NEE" : "BSDF", den > 0.0 ? tech / den : 0.0,
            tech > 0.0 ? q0 / tech : 0.0, n, n == 1 ? "" : "s");
}

/* --debug-pixel: the sum over every (technique, hero h) pair of the MIS weight that
   pair would give this path (docs/THEORY.md section 6).  Pair (t, h) evaluates its
   weight with its OWN selection probability P_h = P(e | c with lambda_h as the
   hero) for every term of its denominator:
       S = sum_h r_h^2 (a_h + q_bsdf(h)^2) / sum_m r_m^2 (a_h + q_bsdf(m)^2),
       a_h = (P_h p_sigma)^2.
   S = 1 whenever P_h is the same for every h (the reason the renderer may use one
   q_nee for every m); a hero-dependent P leaves S = 1 only while the densities do
   not depend on the wavelength (r_m = 1, equal q_bsdf).  The context for hero h is
   the stored one with the wavelengths (and their alive bits and throughputs)
   rotated so that lambda_h is in slot 0. */
static double debug_weight_sum(const Renderer *R, const LightCtx *c, int piece, float p_sigma,
                               const float *r, const float *q_bsdf, unsigned alive)
{
    double S = 0.0;
    int h, m, k;
    for (h = 0; h < HERO_N; h++) {
        LightCtx ch = *c;
        double a, num, den = 0.0;
        float P = 1.0f;
        if (!(alive & (1u << h))) continue;
        ch.alive = 0u;
        for (k = 0; k < HERO_N; k++) {
            int from = (h + k) % HERO_N;
            ch.lambda[k] = c->lambda[from];
            ch.beta[k] = c->beta[from];
            if (c->alive & (1u << from)) ch.alive |= 1u << k;
        }
        if (R->o->sel.strategy != SEL_ALL) P = light_select_pmf(R->ls, &ch, piece);
        a = (double)P * p_sigma * P * p_sigma;
        num = (double)r[h] * r[h] * (a + (double)q_bsdf[h] * q_bsdf[h]);
        for (m = 0; m < HERO_N; m++)
            if (alive & (1u << m)) den += (double)r[m] * r[m] * (a + (double)q_bsdf[m] * q_bsdf[m]);
        if (den > 0.0) S += num / den;
    }
    return S;
}

/* Silence means S = 1 (to 1e-4): said once in docs/WALKTHROUGH.md. */
static void debug_check_sum(FILE *dbg, double S)
{
    if (fabs(S - 1.0) > 1e-4)
        fprintf(dbg, "  WARNING: the MIS weights of all (technique, hero) pairs sum to %.4g, not 1: "
                     "this contribution is weighted wrongly\n", S);
}

/* lambda_i for a path at lo through fluorescent material mi (FLUORESCENCE 3), by
   --fluor-li; *pdf the density it was drawn from (0: none). */
static float fluor_sample_lambda_i(const Renderer *R, const Material *mat, int mi, float lo,
                                   float u, float *pdf)
{
    if (R->o->fluor_li == FLUOR_LI_UNIFORM) return fluor_sample_li_uniform(lo, u, pdf);
    if (R->fl_power)
        return fluor_sample_li_mix(mat, R->fl_power + (size_t)mi * FL_N, FLUOR_LI_DEFENSIVE, lo, u, pdf);
    return fluor_sample_li(mat, lo, u, pdf);
}

/* ------------------------------------------------------------------ media */

/* What next event estimation needs to know of the vertex it starts from. */
typedef struct {
    const Material *mat;       /* the surface's material; NULL: a point in a medium */
    const SurfacePoint *sp;    /* the surface point (NULL in a medium) */
    Vec3 p, wo;                /* position; unit direction back along the path */
    float g;                   /* in a medium: its Henyey-Greenstein asymmetry */
    int medium;                /* the medium the path reached it through (-1: none) */
} Scatter;

/* The transmittance T_j along a shadow ray (tmax 1: it ends at its target) that
   starts in medium med: the product of exp(-sigma_t(lambda_j) l) over the media it
   crosses (medium.c, M1), passing surfaces of Material "interface" (pbrt-v4's
   volpath does the same); 0 when any other surface blocks it.  T_j is left alone
   for wavelengths that are not alive. */
static int shadow_transmittance(const Renderer *R, Ray sh, int med, const float *lam,
                                unsigned alive, double T[HERO_N], Counters *cnt)
{
    const Scene *s = R->s;
    int seg, j;
    for (seg = 0; seg < MEDIUM_SEGMENTS; seg++) {
        HitRecord hit;
        SurfacePoint sp;
        int found;
        double len;
        cnt->rays++;
        found = bvh_intersect(&s->bvh, s, &sh, &hit);
        len = (double)(found ? hit.t : 1.0f) * v3_len(sh.d);
        if (med >= 0)
            for (j = 0; j < HERO_N; j++)
                if (alive & (1u << j))
                    T[j] *= exp(-(double)medium_sigma_t(&s->media[med], lam[j]) * len);
        if (!found) return 1;
        scene_surface_point(s, &sh, &hit, &sp);
        if (s->materials[s->shapes[sp.shape].material].type != MAT_INTERFACE) return 0;
        med = medium_after(s, sp.shape, med, sh.d, sp.ng);
        {
            Vec3 target = v3_add(sh.o, sh.d);
            sh.o = offset_ray_origin(sp.p, sp.ng, sh.d);
            sh.d = v3_sub(target, sh.o);
        }
    }
    return 0;                  /* more boundaries than MEDIUM_SEGMENTS: treated as blocked */
}

/* One straight stretch of the path through medium med, from the ray's origin to
   distance tmax (the next surface; INFINITY: none), with the hero's free-flight
   sampling (THEORY (16)): t = -ln(1 - u) / sigma_t(lambda_0).
   Collision (t < tmax): returns 1 with *t and the extinctions st[] of the alive
   wavelengths; nothing is updated yet.  Pass: returns 0 after multiplying each
   alive lane's throughput and ratio by T_j / T_0 (the pass probability of the
   hero with lambda_j's coefficient over the hero's own), and prev->T by T_j
   (the BSDF/phase technique's pdf for the segment, THEORY (19)).  With --chromatic-media
   terminate, an event in a medium whose sigma_t differs between the alive
   wavelengths first terminates the secondaries. */
static int medium_flight(const Renderer *R, PixelSample *ps, int dim, int med, float tmax,
                         const float *lam, unsigned *alive, float *beta, float *r,
                         PrevVertex *prev, float *t_out, float st[HERO_N], FILE *dbg)
{
    const Medium *M = &R->s->media[med];
    double s0, t, u;
    int j, chromatic = 0;
    for (j = 0; j < HERO_N; j++) {
        st[j] = (*alive & (1u << j)) ? medium_sigma_t(M, lam[j]) : 0.0f;
        if (j > 0 && (*alive & (1u << j)) && st[j] != st[0]) chromatic = 1;
    }
    if (chromatic && R->o->media_terminate) {
        *alive = 1u;
        prev->alive = 1u;
        for (j = 1; j < HERO_N; j++) { beta[j] = 0.0f; r[j] = 0.0f; }
        if (dbg) fprintf(dbg, "  medium \"%s\": chromatic, secondaries terminated\n", M->name);
    }
    s0 = st[0];
    u = sampler_1d(ps, dim);
    t = s0 > 0.0 ? -log1p(-u) / s0 : INFINITY;
    if (t < (double)tmax) {
        *t_out = (float)t;
        return 1;
    }
    {
        unsigned still = 1u;
        for (j = 0; j < HERO_N; j++) {
            double ratio, Tj;
            if (!(*alive & (1u << j))) continue;
            ratio = st[j] == st[0] ? 1.0 : exp(-((double)st[j] - s0) * tmax);
            Tj = st[j] == 0.0f ? 1.0 : exp(-(double)st[j] * tmax);
            prev->T[j] *= Tj;
            beta[j] = (float)(beta[j] * ratio);
            if (j == 0) continue;
            r[j] = (float)(r[j] * ratio);
            if (r[j] > 0.0f && isfinite(r[j])) still |= 1u << j;
            else { r[j] = 0.0f; beta[j] = 0.0f; }
        }
        *alive = still;
        if (dbg) fprintf(dbg, "  medium \"%s\": passed %.4g, T=(%.4g %.4g %.4g %.4g)\n", M->name,
                         (double)tmax, prev->T[0], prev->T[1], prev->T[2], prev->T[3]);
    }
    return 0;
}

/* 4. Next event estimation at vertex v: choose an emitter (piece) with light_select
   in context ctx, sample a point on it, and add its contribution weighted against
   the BSDF's (or phase function's) sampling of the same direction (eq. 6).  Along
   the shadow ray the light is attenuated by the media it crosses, T_j; the BSDF
   technique would have had to cross them too, so its pdf for wavelength m is
   q_bsdf(m) T_m in the denominator (THEORY (19)). */
static void next_event(const Renderer *R, PixelSample *ps, int depth, const Scatter *v,
                       const LightCtx *ctx, const float *lam, const float *beta,
                       const float *r, unsigned alive, const Wavelengths *wl,
                       float cmf[HERO_N][3], double xyz[3], Counters *cnt, FILE *dbg)
{
    const Scene *s = R->s;
    const RenderOptions *o = R->o;
    int is_all = o->sel.strategy == SEL_ALL;
    int e, e_first = 0, e_end = 1, j;
    float u0, u1, u2;
    if (is_all) { e_first = 0; e_end = light_n_pieces(R->ls); }
    /* (the order of these requests is the independent sampler's stream order) */
    u0 = sampler_1d(ps, dim_bounce(depth, BD_TRIANGLE));
    sampler_2d(ps, dim_bounce(depth, BD_POINT), &u1, &u2);
    for (e = e_first; e < e_end; e++) {
        float P = 1.0f, f[HERO_N], pdf_l[HERO_N], cos_i, q_nee;
        const float *q_b;             /* the BSDF's pdfs in the MIS weight */
        static const float no_bsdf[HERO_N] = { 0 };
        int chosen = e, fb = 0, any = 0, em;
        EmitterSample es;
        double value[HERO_N], den, T[HERO_N] = { 1.0, 1.0, 1.0, 1.0 };
        if (!is_all) {
            chosen = light_select(R->ls, ctx, sampler_1d(ps, dim_bounce(depth, BD_LIGHT)), &P, &fb);
            if (fb) cnt->fallbacks++;
            if (dbg) fprintf(dbg, "  NEE: chose emitter %d with P=%.4g (%s)\n",
                             chosen >= 0 ? light_piece_emitter(R->ls, chosen) : -1, P,
                             debug_pmf_source(&o->sel, ctx, fb));
            if (chosen < 0) {
                if (dbg) fprintf(dbg, "  NEE: no emitter can be chosen here (every P is 0)\n");
                break;
            }
        }
        em = light_piece_emitter(R->ls, chosen);
        if (!light_sample(R->ls, chosen, v->p, u0, u1, u2, &es)) {
            if (dbg) fprintf(dbg, "  NEE: no usable point on emitter %d (seen edge-on or at distance 0)\n", em);
            continue;
        }
        for (j = 0; j < HERO_N; j++) {
            value[j] = 0.0;
            if (alive & (1u << j))
                value[j] = light_Le(R->ls, em, es.n, v3_neg(es.wi), lam[j]);
            if (value[j] != 0.0) any = 1;
        }
        if (!any) {
            if (dbg) fprintf(dbg, "  NEE: emitter %d sends nothing here (its back faces this point, or Le = 0 at the alive wavelengths)\n", em);
            continue;
        }
        if (v->mat) {
            bsdf_eval(v->mat, v->sp, v->wo, es.wi, lam, alive, f, pdf_l);
            cos_i = fabsf(v3_dot(es.wi, v->sp->ns));
        } else {                      /* in a medium: the phase function is f and pdf */
            float ph = hg_phase(v->g, v3_dot(v3_neg(v->wo), es.wi));
            for (j = 0; j < HERO_N; j++) f[j] = pdf_l[j] = (alive & (1u << j)) ? ph : 0.0f;
            cos_i = 1.0f;
        }
        any = 0;
        for (j = 0; j < HERO_N; j++) {
            value[j] *= (double)beta[j] * f[j] * cos_i;
            if (value[j] != 0.0) any = 1;
        }
        if (!any) {
            if (dbg) fprintf(dbg, "  NEE: emitter %d: f |cos| = 0 (the sampled point is below this surface, or the BSDF has no lobe there)\n", em);
            continue;
        }
        {
            Ray shadow;
            Vec3 target = offset_ray_origin(es.p, es.n, v3_neg(es.wi));
            shadow.o = v->mat ? offset_ray_origin(v->sp->p, v->sp->ng, es.wi) : v->p;
            shadow.d = v3_sub(target, shadow.o);
            shadow.tmax = 1.0f;
            if (R->vol) {
                /* through media and "interface" surfaces (the medium it starts in:
                   a surface's own MediumInterface decides by the side of es.wi) */
                int med = v->mat ? medium_after(s, v->sp->shape, v->medium, es.wi, v->sp->ng)
                                 : v->medium;
                if (!shadow_transmittance(R, shadow, med, lam, alive, T, cnt)) {
                    if (dbg) fprintf(dbg, "  NEE: occluded\n");
                    continue;
                }
                for (j = 0; j < HERO_N; j++) value[j] *= T[j];
            } else {
                cnt->rays++;
                if (bvh_occluded(&s->bvh, s, &shadow)) {
                    if (dbg) fprintf(dbg, "  NEE: occluded\n");
                    continue;
                }
            }
        }
        /* A delta light (point, spot, distant: delta.c) cannot be found
           by a BSDF direction: its weight against BSDF sampling is 1, so
           the BSDF's pdfs leave the denominator (es.pdf_sa = 1 / G there,
           and q_nee / den = 1 / (P (1/G) sum_m r_m^2): THEORY section 11) */
        q_b = es.delta ? no_bsdf : pdf_l;
        q_nee = P * es.pdf_sa;
        den = mis_denominator(r, q_b, T, q_nee, alive);
        if (den > 0.0) {
            film_add(xyz, cmf, wl, value, (double)q_nee / den, alive);
            if (dbg) {
                float qT[HERO_N];
                for (j = 0; j < HERO_N; j++) qT[j] = (float)(q_b[j] * T[j]);
                debug_weight(dbg, "NEE: visible emitter", em, (double)q_nee * q_nee / den,
                             r, qT, q_nee, alive, 1);
                if (alive != 1u)
                    debug_check_sum(dbg, debug_weight_sum(R, ctx, chosen, es.pdf_sa, r, qT, alive));
            }
        } else if (dbg) {
            fprintf(dbg, "  NEE: emitter %d: MIS denominator 0 (no technique has a density here)\n", em);
        }
    }
}

/* 6. Russian roulette on a hero-independent throughput: survival probability
   q = min(1, 4 max_j beta_j / sum_m r_m) (8), from RR_START_DEPTH on.  Returns 0
   when the path ends (also when only the hero is left and carries nothing). */
static int russian_roulette(PixelSample *ps, int depth, float *beta, const float *r,
                            unsigned alive, FILE *dbg)
{
    int j;
    if (depth >= RR_START_DEPTH) {
        float sum_r = 0.0f, bmax = 0.0f, q;
        for (j = 0; j < HERO_N; j++)
            if (alive & (1u << j)) {
                sum_r += r[j];
                if (beta[j] > bmax) bmax = beta[j];
            }
        q = sum_r > 0.0f ? (float)HERO_N * bmax / sum_r : 0.0f;
        if (q < 1.0f) {
            int dies = sampler_1d(ps, dim_bounce(depth, BD_ROULETTE)) >= q;
            if (dbg) fprintf(dbg, "  roulette: survival q = min(1, %d max_j beta_j / sum_m r_m) = %.4g: %s\n",
                             HERO_N, q, dies ? "path ends" : "survives, beta /= q");
            if (dies) return 0;
            for (j = 0; j < HERO_N; j++) beta[j] /= q;
        }
    }
    return !(!(beta[0] > 0.0f) && alive == 1u);
}

/* A collision at distance t along the ray in medium med (medium_flight gave t and
   the extinctions st).  docs/media.md derives each factor:
   - the collision's density for hero m is sigma_t(lambda_m) T_m(t), so every ratio
     r_m gains (sigma_t,m / sigma_t,0) T_m / T_0 (THEORY (17));
   - emission (an emissive medium, below maxdepth): the medium's sigma_a Le along
     the ray, estimated at this point with weight 1 / sum_m r_m^2 (no other
     technique makes this point);
   - scattering: beta_j gains sigma_s,j T_j / (sigma_t,0 T_0): the path does not
     stop at an absorption (it goes on with the albedo as weight, and the
     roulette ends it), then NEE with the phase function, and the next direction
     from the phase function (f / pdf = 1, the same pdf for every wavelength).
   Returns 0 when the path ends. */
static int medium_vertex(const Renderer *R, PixelSample *ps, int depth, int med, Ray *ray,
                         float t, const float *st, const float *lam, const Wavelengths *wl,
                         float cmf[HERO_N][3], double xyz[3], float *beta, float *r,
                         unsigned *alive, PrevVertex *prev, int shifted, Counters *cnt, FILE *dbg)
{
    const Scene *s = R->s;
    const RenderOptions *o = R->o;
    const Medium *M = &s->media[med];
    double s0 = st[0], ratio[HERO_N];
    float rc[HERO_N], u1, u2, pdf;
    Vec3 p = v3_add(ray->o, v3_mul(ray->d, t)), d = ray->d, wi;
    LightCtx ctx;
    unsigned still = 1u;
    int j, any = 0;
    if (dbg) fprintf(dbg, "  vertex %d: in medium \"%s\" at p=(%.4g %.4g %.4g), t=%.4g, sigma_t(hero)=%.4g\n",
                     depth, M->name, p.x, p.y, p.z, (double)t, s0);
    if (depth >= o->maxdepth) return 0;   /* pbrt-v4: neither emission nor scattering there */
    for (j = 0; j < HERO_N; j++) {
        ratio[j] = rc[j] = 0.0f;
        if (!(*alive & (1u << j))) continue;
        ratio[j] = st[j] == st[0] ? 1.0 : exp(-((double)st[j] - s0) * t);
        rc[j] = j == 0 ? 1.0f : (float)(r[j] * ((double)st[j] / s0) * ratio[j]);
    }
    if (R->med_le[med] > 0.0) {
        double value[HERO_N], den = 0.0;
        for (j = 0; j < HERO_N; j++) {
            value[j] = 0.0;
            if (!(*alive & (1u << j)) || !(rc[j] > 0.0f) || !isfinite(rc[j])) continue;
            value[j] = beta[j] * ratio[j] * medium_sigma_a(M, lam[j]) *
                       (R->med_le[med] * spec_eval(&M->Le, lam[j])) / s0;
            den += (double)rc[j] * rc[j];
        }
        if (den > 0.0) film_add(xyz, cmf, wl, value, 1.0 / den, *alive);
        if (dbg) fprintf(dbg, "  medium emission: weight 1 / sum_m r_m^2 = %.4g\n", den > 0.0 ? 1.0 / den : 0.0);
    }
    for (j = 0; j < HERO_N; j++) {
        if (!(*alive & (1u << j))) continue;
        beta[j] = (float)(beta[j] * (double)medium_sigma_s(M, lam[j]) * ratio[j] / s0);
        if (beta[j] > 0.0f) any = 1;
        if (j == 0) continue;
        r[j] = rc[j];
        if (r[j] > 0.0f && isfinite(r[j])) still |= 1u << j;
        else { r[j] = 0.0f; beta[j] = 0.0f; }
    }
    *alive = still;
    if (!any) return 0;                   /* absorbed at every wavelength */
    /* NEE: the context has no normal (every strategy's pmf is exact without one) */
    ctx.p = p;
    ctx.n = v3(0.0f, 0.0f, 0.0f);
    ctx.voxel = light_voxel(R->ls, p);
    for (j = 0; j < HERO_N; j++) { ctx.lambda[j] = lam[j]; ctx.beta[j] = beta[j]; }
    ctx.alive = *alive;
    ctx.hero_only = *alive == 1u;
    ctx.shifted = shifted;
    if (o->nee && s->n_emitters > 0) {
        Scatter v;
        v.mat = NULL;
        v.sp = NULL;
        v.p = p;
        v.wo = v3_neg(d);
        v.g = M->g;
        v.medium = med;
        next_event(R, ps, depth, &v, &ctx, lam, beta, r, *alive, wl, cmf, xyz, cnt, dbg);
    }
    /* the phase function's direction */
    sampler_2d(ps, dim_bounce(depth, BD_DIR), &u1, &u2);
    wi = hg_sample(M->g, d, u1, u2, &pdf);
    if (!(pdf > 0.0f)) return 0;
    prev->can_nee = o->nee && s->n_emitters > 0;
    prev->ctx = ctx;
    prev->p = p;
    prev->alive = *alive;
    for (j = 0; j < HERO_N; j++) {
        prev->r[j] = r[j];
        prev->q_bsdf[j] = pdf;
        prev->T[j] = 1.0;
    }
    ray->o = p;
    ray->d = wi;
    ray->tmax = INFINITY;
    return 1;
}

/* Trace one camera sample; adds its XYZ estimate to xyz. */
void trace_path(const Renderer *R, Ray ray, const Wavelengths *wl, PixelSample *ps,
                       double xyz[3], Counters *cnt, FILE *dbg)
{
    const Scene *s = R->s;
    const RenderOptions *o = R->o;
    int is_all = o->sel.strategy == SEL_ALL;
    float cmf[HERO_N][3], beta[HERO_N], r[HERO_N];
    float lam[HERO_N];         /* the wavelengths light is transported at: the camera's
                                  (wl) until a fluorescent shift moves the hero to
                                  lambda_i; the film keeps wl (FLUORESCENCE 4) */
    unsigned alive = o->single_wavelength ? 1u : (1u << HERO_N) - 1u;
    PrevVertex prev;
    int depth, j, shifted = 0; /* shifted: a fluorescent vertex re-radiated (LightCtx) */
    int med = R->vol ? s->settings.camera_medium : -1;   /* the medium the ray is in */

    for (j = 0; j < HERO_N; j++) {
        cie_xyz(wl->lambda[j], cmf[j]);
        lam[j] = wl->lambda[j];
        beta[j] = (alive & (1u << j)) ? 1.0f : 0.0f;
        r[j] = (alive & (1u << j)) ? 1.0f : 0.0f;
    }
    memset(&prev, 0, sizeof prev);
    for (j = 0; j < HERO_N; j++) { prev.q_bsdf[j] = 1.0f; prev.r[j] = r[j]; prev.T[j] = 1.0; }
    prev.alive = alive;
    if (dbg) fprintf(dbg, "sample: lambda=(%.1f %.1f %.1f %.1f) nm pdf=(%.4g %.4g %.4g %.4g)\n",
                     wl->lambda[0], wl->lambda[1], wl->lambda[2], wl->lambda[3],
                     wl->pdf[0], wl->pdf[1], wl->pdf[2], wl->pdf[3]);

    for (depth = 0;; depth++) {
        HitRecord hit;
        SurfacePoint sp;
        const Material *mat;
        const Shape *shape;
        Vec3 wo;
        LightCtx ctx;
        BsdfSample bs;
        float u0, u1, u2;
        int found, seg;

        /* 1. The next vertex: the closest surface, unless the ray collides in its
              medium first (docs/media.md); surfaces of Material "interface" only
              bound media: the ray crosses them (pbrt-v4's SkipIntersection), in
              "volpath" into the medium on their other side, in "path" as a
              specular bounce (no MIS weight at the emitter it may then find) */
        found = 0;
        for (seg = 0;; seg++) {
            float t_coll, st[HERO_N];
            cnt->rays++;
            found = bvh_intersect(&s->bvh, s, &ray, &hit);
            if (med >= 0 && medium_flight(R, ps, dim_medium(depth, seg),
                                          med, found ? hit.t : INFINITY, lam, &alive, beta, r,
                                          &prev, &t_coll, st, dbg)) {
                if (!medium_vertex(R, ps, depth, med, &ray, t_coll, st, lam, wl, cmf, xyz, beta,
                                   r, &alive, &prev, shifted, cnt, dbg) ||
                    !russian_roulette(ps, depth, beta, r, alive, dbg))
                    return;
                found = -1;            /* scattered: ray holds the new direction */
                break;
            }
            if (!found) break;
            scene_surface_point(s, &ray, &hit, &sp);
            if (s->materials[s->shapes[sp.shape].material].type != MAT_INTERFACE) break;
            if (seg + 1 >= MEDIUM_SEGMENTS) return;   /* (a path through too many boundaries) */
            if (med >= 0 || R->vol) med = medium_after(s, sp.shape, med, ray.d, sp.ng);
            else prev.can_nee = 0;
            if (dbg) fprintf(dbg, "  crossed a medium boundary (shape %d)%s\n", sp.shape,
                             R->vol ? "" : ": media are ignored by this integrator");
            ray.o = offset_ray_origin(sp.p, sp.ng, ray.d);
            ray.tmax = INFINITY;
        }
        if (found < 0) continue;
        if (!found) {
            Vec3 dir = v3_norm(ray.d);
            int i;
            for (i = 0; i < R->n_inf; i++) {
                int e = R->inf[i], any = 0;
                double value[HERO_N], W, den;
                float q_nee = 0.0f;
                for (j = 0; j < HERO_N; j++) {
                    value[j] = 0.0;
                    if (!(alive & (1u << j))) continue;
                    value[j] = (double)beta[j] * light_Le(R->ls, e, dir, v3_neg(dir), lam[j]);
                    if (value[j] != 0.0) any = 1;
                }
                if (!any) continue;
                if (prev.can_nee) {
                    float P = is_all ? 1.0f
                                     : light_select_pmf(R->ls, &prev.ctx, light_piece_of(R->ls, e, -1));
                    q_nee = P * inf_pdf(&s->emitters[e], dir);
                }
                den = mis_denominator(prev.r, prev.q_bsdf, prev.T, q_nee, prev.alive);
                W = den > 0.0 ? ((double)prev.q_bsdf[0] * prev.T[0]) * ((double)prev.q_bsdf[0] * prev.T[0]) / den : 0.0;
                film_add(xyz, cmf, wl, value, W, alive);
                if (dbg) fprintf(dbg, "  escaped: infinite light %d, MIS weight %.4g (q_nee %.4g)\n",
                                 e, W, q_nee);
            }
            if (dbg && R->n_inf == 0) fprintf(dbg, "  escaped\n");
            break;
        }
        shape = &s->shapes[sp.shape];
        mat = &s->materials[shape->material];
        wo = v3_neg(v3_norm(ray.d));
        if (dbg) debug_vertex(dbg, depth, &sp, beta, alive, r);

        /* 2. Emission found by the path, weighted against NEE from prev */
        if (shape->emitter >= 0) {
            double value[HERO_N], W, den;
            float q_nee = 0.0f;
            int any = 0;
            for (j = 0; j < HERO_N; j++) {
                value[j] = 0.0;
                if (!(alive & (1u << j))) continue;
                value[j] = (double)beta[j] * light_Le(R->ls, shape->emitter, sp.ng, wo, lam[j]);
                if (value[j] != 0.0) any = 1;
            }
            if (any) {
                /* the piece NEE would have had to choose to sample this point */
                int piece = light_piece_of(R->ls, shape->emitter, sp.prim);
                if (prev.can_nee) {
                    float P = is_all ? 1.0f : light_select_pmf(R->ls, &prev.ctx, piece);
                    q_nee = P * light_pdf_sa(R->ls, piece, prev.p, sp.p, sp.ng);
                }
                den = mis_denominator(prev.r, prev.q_bsdf, prev.T, q_nee, prev.alive);
                /* beta already holds 1/q_bsdf(0) and T_m / T_0 of the media on the way:
                   the MIS weight W = (q_bsdf(0) T_0)^2 / den (THEORY (19)) */
                W = den > 0.0 ? ((double)prev.q_bsdf[0] * prev.T[0]) * ((double)prev.q_bsdf[0] * prev.T[0]) / den : 0.0;
                film_add(xyz, cmf, wl, value, W, alive);
                if (dbg) {
                    debug_weight(dbg, "emission from emitter", shape->emitter, W, prev.r,
                                 prev.q_bsdf, q_nee, prev.alive, 0);
                    if (prev.can_nee && prev.alive != 1u)
                        debug_check_sum(dbg, debug_weight_sum(R, &prev.ctx, piece,
                                        light_pdf_sa(R->ls, piece, prev.p, sp.p, sp.ng),
                                        prev.r, prev.q_bsdf, prev.alive));
                }
            }
        }
        if (depth >= o->maxdepth) break;

        /* 3. Termination of the secondary wavelengths at a dispersive dielectric,
              before NEE at this vertex (pbrt-v4 TerminateSecondary; THEORY section 7) */
        if (mat->type == MAT_DIELECTRIC && mat->dispersive && alive != 1u &&
            (mat->alpha == 0.0f || !o->rough_mis)) {
            alive = 1u;
            for (j = 1; j < HERO_N; j++) { beta[j] = 0.0f; r[j] = 0.0f; }
            if (dbg) fprintf(dbg, "  dispersive: secondaries terminated, hero %.1f nm continues\n",
                             wl->lambda[0]);
        }

        /* 3b. A fluorescent vertex reflects or re-radiates (FLUORESCENCE 3-5).  To
              re-radiate: sample lambda_i on [300, lambda_o] (from A, A x power or
              uniformly), weight by (F4), and from here on transport at lambda_i
              through a Lambertian of albedo 1: NEE, emitter selection (ctx.lambda)
              and every MIS pdf below use it.  The baseline terminates the
              secondaries (as at dispersive glass); --fluor-lanes keep shifts every
              alive wavelength with the SAME number ul through its own p(li | lo_j)
              and carries the branch probability in the ratios r (FLUORESCENCE 4b). */
        if (mat->type == MAT_FLUORESCENT) {
            float pf = fluor_branch_pf(mat, lam[0]), ub, ul;
            sampler_2d(ps, dim_fluor(depth), &ub, &ul);
            if (ub < pf) {
                float li[HERO_N], pli[HERO_N], wgt[HERO_N];
                unsigned still = 1u;
                for (j = 0; j < HERO_N; j++) {
                    li[j] = lam[j];
                    pli[j] = wgt[j] = 0.0f;
                    if (!(alive & (1u << j)) || (j > 0 && !o->fluor_keep)) continue;
                    li[j] = fluor_sample_lambda_i(R, mat, shape->material, lam[j], ul, &pli[j]);
                    wgt[j] = pli[j] > 0.0f ? fluor_weight(mat, li[j], lam[j]) : 0.0f;
                }
                if (dbg) fprintf(dbg, "  fluorescent: re-radiates, %.1f nm absorbed at %.1f nm "
                                 "(P_f %.3g, p(li|lo) %.4g, weight %.4g); secondaries %s\n",
                                 lam[0], li[0], pf, pli[0], wgt[0],
                                 o->fluor_keep ? "shifted with the same number" : "terminated");
                if (!o->fluor_keep && (!(pli[0] > 0.0f) || !(wgt[0] > 0.0f))) break;
                /* lane j: f_j / (P_f(lambda_0) p(li_j | lo_j)); the technique with hero j
                   would have re-radiated with P_f(lo_j): r_j *= P_f(lo_j) / P_f(lo_0).
                   A lane whose weight is 0 stays in the MIS sums while r_j > 0 (its
                   technique could have made this path), with beta_j = 0. */
                beta[0] = pli[0] > 0.0f ? beta[0] * (wgt[0] / (pf * pli[0])) : 0.0f;
                for (j = 1; j < HERO_N; j++) {
                    if (o->fluor_keep && (alive & (1u << j))) {
                        r[j] *= fluor_branch_pf(mat, lam[j]) / pf;
                        beta[j] = pli[j] > 0.0f ? beta[j] * (wgt[j] / (pf * pli[j])) : 0.0f;
                        if (r[j] > 0.0f && isfinite(r[j])) { still |= 1u << j; continue; }
                    }
                    beta[j] = 0.0f;
                    r[j] = 0.0f;
                }
                alive = still;
                shifted = 1;
                for (j = 0; j < HERO_N; j++) lam[j] = li[j];
                if (!(beta[0] > 0.0f) && alive == 1u) break;
                mat = &R->white;
            } else {
                /* reflect: a Lambertian of albedo rho (1 - A); the choice depends on
                   lambda_o, so the pdf ratios carry it (THEORY (5)) */
                unsigned still = 1u;
                for (j = 1; j < HERO_N; j++) {
                    if (!(alive & (1u << j))) continue;
                    r[j] *= (1.0f - fluor_branch_pf(mat, lam[j])) / (1.0f - pf);
                    beta[j] /= 1.0f - pf;
                    if (r[j] > 0.0f) still |= 1u << j;
                    else { r[j] = 0.0f; beta[j] = 0.0f; }
                }
                beta[0] /= 1.0f - pf;
                alive = still;
                if (dbg) fprintf(dbg, "  fluorescent: reflects (P_r %.3g)\n", 1.0f - pf);
            }
        }

        /* 4. Next event estimation: choose an emitter, sample a point on it */
        ctx.p = sp.p;
        ctx.n = sp.ns;
        ctx.voxel = light_voxel(R->ls, sp.p);
        for (j = 0; j < HERO_N; j++) { ctx.lambda[j] = lam[j]; ctx.beta[j] = beta[j]; }
        ctx.alive = alive;
        ctx.hero_only = alive == 1u;
        ctx.shifted = shifted;
        if (o->nee && !mat_is_delta(mat) && s->n_emitters > 0) {
            Scatter v;
            v.mat = mat;
            v.sp = &sp;
            v.p = sp.p;
            v.wo = wo;
            v.g = 0.0f;
            v.medium = med;
            next_event(R, ps, depth, &v, &ctx, lam, beta, r, alive, wl, cmf, xyz, cnt, dbg);
        }

        /* 5. BSDF sampling: the next direction, with the hero's index */
        u0 = sampler_1d(ps, dim_bounce(depth, BD_LOBE));
        sampler_2d(ps, dim_bounce(depth, BD_DIR), &u1, &u2);
        if (!bsdf_sample(mat, &sp, wo, lam, alive, u0, u1, u2, &bs)) break;
        prev.can_nee = o->nee && !bs.delta && s->n_emitters > 0;
        prev.ctx = ctx;
        prev.p = sp.p;
        prev.alive = alive;
        for (j = 0; j < HERO_N; j++) {
            prev.r[j] = r[j];
            prev.q_bsdf[j] = bs.pdf_l[j];
            prev.T[j] = 1.0;
        }
        {
            float cos_i = fabsf(v3_dot(bs.wi, sp.ns));
            unsigned still = 0u;
            for (j = 0; j < HERO_N; j++) {
                if (!(alive & (1u << j))) continue;
                beta[j] *= bs.f[j] * cos_i / bs.pdf;   /* delta lobes: f holds 1/|cos| */
                if (j == 0) { still |= 1u; continue; }
                r[j] *= bs.pdf_l[j] / bs.pdf;       /* ratio p(X|lambda_j) / p(X|lambda_0) */
                if (r[j] > 0.0f && isfinite(r[j])) still |= 1u << j;
                else { r[j] = 0.0f; beta[j] = 0.0f; }
            }
            alive = still;
        }

        /* 6. Russian roulette on a hero-independent throughput */
        if (!russian_roulette(ps, depth, beta, r, alive, dbg)) break;

        if (R->vol) med = medium_after(s, sp.shape, med, bs.wi, sp.ng);
        ray.o = offset_ray_origin(sp.p, sp.ng, bs.wi);
        ray.d = bs.wi;
        ray.tmax = INFINITY;
    }
}
