/* path.c - the path estimator: what one camera sample adds to the film.

   Exported (render.h, for render.c): trace_path.

   THE ESTIMATOR (THEORY §2-§9; the numbers below are THEORY's equations, the
   symbols those of its §0).  render.c draws four wavelengths lambda_j by rotation
   in the CDF of the wavelength pdf p (2).  The path X is sampled with the hero
   lambda_0 only.  For a path ended by technique tau (NEE or BSDF sampling) the film
   receives, for each wavelength j,

                      f(X, lambda_j) p_tau(X | lambda_0)
        C_j = ------------------------------------------------------    (4)
               p(lambda_j) * sum_{tau', m} p_tau'(X | lambda_m)^2

   the power heuristic over every (technique, hero) pair that could have made X
   (THEORY §4).  A path carries four lanes (PathState): the throughput
   beta_j = f(prefix, lambda_j)/p(prefix | lambda_0), the pdf ratio
   r_m = p(prefix | lambda_m)/p(prefix | lambda_0) (r_0 = 1), and an alive bit.
   With l_j = f_s Le_j |cos| the last segment's integrand (THEORY's ell_j) and the
   technique densities
   q_nee = P(e | c) p_sigma (selection pmf x solid-angle pdf; one value for every
   m, THEORY §6) and q_bsdf(m) (the BSDF pdf of the last direction with
   wavelength m's index), a contribution at the last vertex is

        C_j = beta_j l_j q_tau(0) / (p(lambda_j) D),
        D   = sum_m r_m^2 (q_nee^2 + q_bsdf(m)^2)                          (6)

   Each step returns its Contribution (beta_j l_j times its weight) and the caller
   adds it to the FilmSample; film_add divides by p(lambda_j) (9).  NEE's weight
   is q_nee/D (nee_sample); an emitter that the sampled direction finds, whose
   beta already holds 1/q_bsdf(0), gets W = q_bsdf(0)^2/D (emitter_found, for
   emitters hit and for infinite lights seen by escaped rays alike).
   Special cases that make this readable:
   - No wavelength-dependent event so far: r_m = 1 and q_bsdf(m) = q_bsdf(0), so
     C_j is the usual power-heuristic NEE/BSDF weight times 1/(4 p(lambda_j)):
     pbrt-v4's film average.
   - Termination at a dispersive dielectric (thesis baseline, pbrt-v4
     TerminateSecondary; THEORY §7): r = (1, 0, 0, 0) and beta_1..3 = 0, so the
     hero gets weight 1/p(lambda_0) - the "divide the hero pdf by 4" bookkeeping.
     A layered material whose coat index varies terminates them the same way.
   - Single-wavelength mode: r = (1, 0, 0, 0) from the start.
   - Rough spectral MIS (--rough-dispersion mis): at a rough dispersive interface
     the secondaries survive; every later direction pdf is evaluated with each
     wavelength's own index and the ratios r_m carry them.  Smooth dispersive
     interfaces still terminate: their pdf for any other wavelength is zero.
   Emission reached at depth 0 or after a specular bounce has q_nee = 0: no NEE
   could have produced it.  Every event that changes the lanes hands their new
   values to lanes_update, the one place of the rule "a secondary lane whose
   ratio is not positive and finite leaves the path" (its technique cannot make
   this path).

   THE LOOP.  trace_path alternates next_vertex (the closest surface, or a
   collision in the medium the ray is in) with surface_vertex or medium_vertex
   (emission found there, NEE, the next direction) and the roulette.  A surface
   vertex may first terminate the secondaries (dispersive glass) and take the
   fluorescent branch (fluor_vertex: reflect, or re-radiate at a sampled lambda_i,
   docs/FLUORESCENCE.md §3-§5).  The comments number these steps 1-6 as the
   walkthrough does.  C wants helpers first, so the file reads bottom-up:
   trace_path is its last function.

   PARTICIPATING MEDIA (THEORY §12; docs/media.md summarises).  medium_flight draws the
   distance with the hero's sigma_t (16) and multiplies the ratios r_m by the other
   wavelengths' densities of the same collision or passage (17); medium_vertex adds
   the medium's emission (20) and scatters with the phase function; nee_sample
   multiplies NEE by the shadow ray's transmittance and every BSDF/phase density in
   D by Tr_m (19), as PrevVertex.T (Tr) does for an emitter that a sampled direction
   finds.  Surfaces of Material "interface" only hand the ray from one medium to
   the next.  In a uniformgrid (THEORY §13) medium_flight hands the flight to
   grid_flight: medium.c's medium_track draws tentative collisions at the hero's
   majorant and grid_event estimates the emission at each (25) and makes it real
   or null, the lanes gaining the null or real densities of every hero (21), (22);
   shadow rays ratio-track (ratio_event, (23)), and NEE's own density of their
   null collisions, A_m, joins the MIS denominator (24) (PrevVertex.A for an
   emitter a sampled direction finds).

   Russian roulette (from depth RR_START_DEPTH) survives with probability
   P_survive = min(1, 4 max_j beta_j eta2_j / sum_m r_m)  (8), eta2_j the product of
   the refractions' etap_j^2 (radiance's 1/etap^2 taken back out of beta).
   beta_j eta2_j / sum_m r_m = f_j eta2_j / sum_m p(prefix | lambda_m) does not
   depend on which wavelength was the hero, so the roulette is the same for every
   technique and needs no place in (4).

   NEE asks lights.c which pieces to take (light_nee_count, light_nee_piece: one
   chosen piece, or every piece for the strategy "all") in a context stored with
   the vertex, so that an emitter that BSDF sampling finds is weighted with the
   same selection probability (light_nee_pmf; the consistency contract, item C1,
   THEORY §5).

   Every random number comes from the sample's PixelSample by its dimension
   (sampler.c), so a path is a pure function of (pixel, sample, seed): the image is
   identical for any number of threads. */
#include "render.h"
#include <string.h>

/* ------------------------------------------------------------------ the path's state */

/* Equiangular sampling's view of the segment that led to a collision in a
   homogeneous medium (THEORY §12.1): the technique drew a distance t' on the same
   segment towards a lamp and did NEE there, so it could have made any path whose
   last vertex is such a collision and whose light comes from one of the lamps
   (EquiLamps).  Its density for the collision at t and the point y on lamp i is
   r_m p_eq,i(t) P_E(i) p_sigma(y) for hero m (r_m: the ratios BEFORE the
   collision), which nee_sample and emitter_found add to D in the normalisation of
   free flight's density at the hero, p_ff,0(t) = sigma_t,0 Tr_0(t) (equi_e). */
typedef struct {
    int on;                          /* the technique ran on this segment */
    Vec3 o, d;                       /* the segment o + t d (d unit) ... */
    float tmax;                      /* ... for 0 <= t <= tmax (INFINITY: unbounded) */
    float t;                         /* the collision's distance along it */
    double pff0;                     /* free flight's density of t at the hero */
    float r[HERO_N];                 /* the ratios r_m before the collision */
    unsigned alive;                  /* the lanes alive before it */
} EquiTerm;

/* What the integrator remembers of the previous vertex for the MIS weight of an
   emitter found by BSDF (or phase function) sampling. */
typedef struct {
    int can_nee;                     /* NEE was possible there (non-delta, NEE on) */
    LightCtx ctx;                    /* the selection context used there */
    Vec3 p;                          /* its position */
    float q_bsdf[HERO_N];            /* pdf of the sampled direction per wavelength */
    float r[HERO_N];                 /* pdf ratios of the prefix before that vertex */
    double T[HERO_N];                /* Tr, the transmittance of the media since that
                                        vertex, per wavelength (1 without media): the BSDF
                                        technique's pdf of the segment is q_bsdf(m) Tr_m
                                        (THEORY (19)); through a uniformgrid the density
                                        of its null collisions, THEORY (24) */
    double A[HERO_N];                /* NEE's density of those null collisions, in the
                                        same normalisation (1 without grids: THEORY (24)) */
    unsigned alive;                  /* wavelengths alive at that vertex */
    EquiTerm eq;                     /* a collision: the equiangular technique (on 0: none) */
} PrevVertex;

/* One path: its four lanes and where it is. */
typedef struct {
    float lam[HERO_N];               /* the wavelengths light is transported at: the
                                        camera's until a fluorescent shift moves them to
                                        lambda_i; the film keeps the camera's
                                        (docs/FLUORESCENCE.md §4) */
    float beta[HERO_N];              /* throughput beta_j */
    float r[HERO_N];                 /* pdf ratios r_m (r_0 = 1) */
    float eta2[HERO_N];              /* the product of etap_j^2 over the refractions so far
                                        (BsdfSample.eta2): beta_j eta2_j is the throughput
                                        without radiance's 1/etap^2 (the roulette's, (8)) */
    unsigned alive;                  /* bit j: lane j is carried (bit 0, the hero, always) */
    float lobe_u;                    /* the last smooth dielectric's rescaled lobe number
                                        (BsdfSample.u_lobe), spent by the next smooth
                                        dielectric in place of its own (lobe_next) */
    double lobe_w;                   /* the product of the lobe probabilities it has passed
                                        through; 0: nothing to reuse */
    int shifted;                     /* a fluorescent vertex re-radiated (LightCtx.shifted) */
    int medium;                      /* the medium the ray is in (-1: none) */
    int any_nonspec;                 /* a bounce so far was not specular (a BSDF sample
                                        that is not delta, or a medium scattering):
                                        pbrt-v4's anyNonSpecularBounces, read by
                                        "regularize" (THEORY §15) */
    PrevVertex prev;
} PathState;

/* One medium's coefficients at the path's wavelengths.  They change only where the
   path enters another medium or a fluorescent vertex moves its wavelengths, so
   medium_lanes evaluates them there, not at every segment, shadow ray and
   collision. */
typedef struct {
    int medium;                      /* whose (-1: none yet) */
    float lam[HERO_N];               /* at which wavelengths */
    float sa[HERO_N], ss[HERO_N];    /* medium_sigma_a, medium_sigma_s */
    float st[HERO_N];                /* medium_sigma_t */
    float le[HERO_N];                /* its emitted radiance Le (spec_eval) */
} MediumLanes;

/* What every step of one camera sample works with besides its PathState. */
typedef struct {
    const Renderer *R;
    PixelSample *ps;                 /* the sample's random numbers (sampler.c) */
    FilmSample *fs;                  /* where its contributions go */
    Counters *cnt;                   /* its row's counters */
    FILE *dbg;                       /* --debug-pixel's stream; NULL: silent */
    float time;                      /* the camera ray's time: every ray of the path,
                                        shadow rays included, keeps it (motion.c) */
    MediumLanes media;               /* the last medium_lanes asked for */
} Tracer;

/* The coefficients of medium med at the wavelengths lam (MediumLanes): the cached
   ones while the medium and the wavelengths are those of the last call. */
static const MediumLanes *medium_lanes(Tracer *tr, int med, const float *lam)
{
    MediumLanes *c = &tr->media;
    if (c->medium != med || memcmp(c->lam, lam, sizeof c->lam) != 0) {
        const Medium *M = &tr->R->s->media[med];
        int j;
        c->medium = med;
        memcpy(c->lam, lam, sizeof c->lam);
        for (j = 0; j < HERO_N; j++) {
            c->sa[j] = medium_sigma_a(M, lam[j]);
            c->ss[j] = medium_sigma_s(M, lam[j]);
            c->st[j] = medium_sigma_t(M, lam[j]);
            c->le[j] = spec_eval(&M->Le, lam[j]);
        }
    }
    return c;
}

/* What one step adds to the film: per lane, beta_j l_j times its MIS weight, that
   is C_j p(lambda_j) of (6).  Lanes that are not alive hold 0. */
typedef struct {
    double c[HERO_N];
} Contribution;

/* fs->xyz += sum_j cmf(lambda_j) C_j, C_j = c_j / p(lambda_j)  (9); fs->lane[j] += c_j */
static void film_add(FilmSample *fs, Contribution k)
{
    int j;
    for (j = 0; j < HERO_N; j++) {
        double v;
        if (k.c[j] == 0.0) continue;
        fs->lane[j] += k.c[j];
        v = k.c[j] / fs->wl.pdf[j];
        fs->xyz[0] += fs->cmf[j][0] * v;
        fs->xyz[1] += fs->cmf[j][1] * v;
        fs->xyz[2] += fs->cmf[j][2] * v;
    }
}

/* c_j *= w where c_j is not 0 (a lane that carries nothing stays 0 whatever w). */
static Contribution weighted(Contribution k, double w)
{
    int j;
    for (j = 0; j < HERO_N; j++)
        if (k.c[j] != 0.0) k.c[j] *= w;
    return k;
}

/* The lanes after an event: beta_j and r_j take the new values the event computed
   (in double; rounded to float here).  A secondary lane whose ratio is then not
   positive and finite leaves the path: no technique with that hero can make it
   (beta_j = r_j = 0, its alive bit cleared).  The hero always stays; r[0] is not
   read.  Lanes that are not alive are not read either. */
static void lanes_update(PathState *p, const double *beta, const double *r)
{
    unsigned still = 1u;
    int j;
    for (j = 0; j < HERO_N; j++) {
        if (!(p->alive & (1u << j))) continue;
        p->beta[j] = (float)beta[j];
        if (j == 0) continue;
        p->r[j] = (float)r[j];
        if (p->r[j] > 0.0f && isfinite(p->r[j])) still |= 1u << j;
        else { p->r[j] = 0.0f; p->beta[j] = 0.0f; }
    }
    p->alive = still;
}

/* Only the hero goes on (pbrt-v4's TerminateSecondary, THEORY §7). */
static void lanes_hero_only(PathState *p)
{
    int j;
    p->alive = 1u;
    for (j = 1; j < HERO_N; j++) { p->beta[j] = 0.0f; p->r[j] = 0.0f; }
}

/* The selection context of a vertex at p with shading normal n (the zero vector
   in a medium: every strategy's pmf is exact without one). */
static void vertex_ctx(const Renderer *R, const PathState *path, Vec3 p, Vec3 n, LightCtx *ctx)
{
    int j;
    ctx->p = p;
    ctx->n = n;
    ctx->voxel = light_voxel(R->ls, p);
    for (j = 0; j < HERO_N; j++) { ctx->lambda[j] = path->lam[j]; ctx->beta[j] = path->beta[j]; }
    ctx->alive = path->alive;
    ctx->hero_only = path->alive == 1u;
    ctx->shifted = path->shifted;
}

/* The point lights are sampled from at a surface hit: pbrt-v4's SampleLd nudges its
   LightSampleContext past the hit's error bound, |ng| . err along ng, to wo's side
   when the BSDF only reflects, to the other side when it only transmits, and not
   when it does both.  Only a curve hit has a bound worth it (SurfacePoint.err,
   about a width; 0 elsewhere, where pbrt-v4's float-sized bound moves nothing). */
static Vec3 light_origin(const Material *m, const SurfacePoint *sp, Vec3 wo)
{
    const float d = fabsf(sp->ng.x) * sp->err.x + fabsf(sp->ng.y) * sp->err.y + fabsf(sp->ng.z) * sp->err.z;
    float side = 1.0f;                               /* the others only reflect */
    if (!(d > 0.0f) || m->type == MAT_DIELECTRIC || m->type == MAT_THIN_DIELECTRIC) return sp->p;
    if (m->type == MAT_DIFFUSE_TRANSMISSION) {
        if (m->p_reflect > 0.0f && m->p_reflect < 1.0f) return sp->p;        /* R and T */
        if (!(m->p_reflect > 0.0f)) side = -1.0f;                            /* T only */
    }
    side *= v3_dot(sp->ng, wo) < 0.0f ? -d : d;
    return v3_add(sp->p, v3_mul(sp->ng, side));
}

/* Remember the vertex at p that sampled the next direction with the densities
   q_bsdf (one per wavelength), before its lanes are updated. */
static void prev_set(PathState *path, int can_nee, const LightCtx *ctx, Vec3 p, const float *q_bsdf,
                     const EquiTerm *eq)
{
    int j;
    path->prev.can_nee = can_nee;
    path->prev.eq.on = 0;
    if (eq) path->prev.eq = *eq;
    path->prev.ctx = *ctx;
    path->prev.p = p;
    path->prev.alive = path->alive;
    for (j = 0; j < HERO_N; j++) {
        path->prev.r[j] = path->r[j];
        path->prev.q_bsdf[j] = q_bsdf[j];
        path->prev.T[j] = path->prev.A[j] = 1.0;
    }
}

/* sum_m r_m^2 ((q_nee A_m)^2 + (q_bsdf(m) Tr_m)^2) over the alive wavelengths
   (A_m = 1 unless the segment crossed a uniformgrid: THEORY (24)) */
static double mis_denominator(const float *r, const float *q_bsdf, const double *T, const double *A,
                              float q_nee, unsigned alive)
{
    double d = 0.0;
    int m;
    for (m = 0; m < HERO_N; m++)
        if (alive & (1u << m)) {
            double qb = (double)q_bsdf[m] * T[m], qn = (double)q_nee * A[m];
            d += (double)r[m] * r[m] * (qn * qn + qb * qb);
        }
    return d;
}

/* The equiangular technique's density (THEORY (18e)) for the point y on emitter em
   (solid-angle pdf p_sigma from the collision), over free flight's p_ff,0(t):
   e = p_eq,i(t) P_E(i) p_sigma / p_ff,0(t); 0 where the technique could not have
   made it (not on this segment, em not one of its lamps, a ray through the lamp's
   centre) or where p_ff,0 underflows (t beyond any light's reach). */
static double equi_e(const Renderer *R, const EquiTerm *q, int em, float pdf_sa)
{
    const EquiLamps *L;
    EquiSeg sg;
    double e;
    int i;
    if (!q || !q->on) return 0.0;
    L = light_equi(R->ls);
    i = equi_lamp_of(L, em);
    if (i < 0 || !equi_segment(q->o, q->d, q->tmax, L->center[i], &sg)) return 0.0;
    e = equi_pdf(&sg, (double)q->t) * ((double)pdf_sa / L->n) / q->pff0;
    return isfinite(e) ? e : 0.0;
}

/* Its terms of D: sum_m r_m^2 e^2 over the lanes alive before the collision. */
static double equi_den(const EquiTerm *q, double e)
{
    double d = 0.0;
    int m;
    if (!q || !q->on || e == 0.0) return 0.0;
    for (m = 0; m < HERO_N; m++)
        if (q->alive & (1u << m)) d += (double)q->r[m] * q->r[m] * e * e;
    return d;
}
/* ------------------------------------------------------------------ --debug-pixel */

static void debug_vertex(FILE *dbg, int depth, const SurfacePoint *sp, const float *beta,
                         unsigned alive, const float *r)
{
    fprintf(dbg, "  vertex %d: x=(%.4g %.4g %.4g) shape=%d alive=%c%c%c%c beta=(%.4g %.4g %.4g %.4g) r=(%.3g %.3g %.3g %.3g)\n",
            depth, sp->p.x, sp->p.y, sp->p.z, sp->shape,
            alive & 1 ? 'h' : '-', alive & 2 ? '1' : '-', alive & 4 ? '2' : '-', alive & 8 ? '3' : '-',
            beta[0], beta[1], beta[2], beta[3], r[0], r[1], r[2], r[3]);
}

/* --debug-pixel: a contribution's MIS weight W = q_tau(0)^2 / D (the film receives
   W / (q_tau(0) p(lambda_j)) times the integrand, THEORY (6)) split into the share
   of the technique tau, summed over every hero m, and the share of hero 0 within
   tau:
       W = [sum_m r_m^2 q_tau(m)^2 / D] x [q_tau(0)^2 / sum_m r_m^2 q_tau(m)^2]. */
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
   pair would give this path, W_sum of THEORY (7) (§6).  Pair (tau, h) evaluates its
   weight with its OWN selection probability P_h = P(e | c with lambda_h as the
   hero) for every term of its denominator, that is with q_nee(h) = P_h p_sigma:
       W_sum = sum_h r_h^2 (q_nee(h)^2 + q_bsdf(h)^2)
                     / sum_m r_m^2 (q_nee(h)^2 + q_bsdf(m)^2).
   W_sum = 1 whenever P_h is the same for every h (the reason the renderer may use
   one q_nee for every m); a hero-dependent P leaves W_sum = 1 only while the
   densities do not depend on the wavelength (r_m = 1, equal q_bsdf).  The context
   for hero h is the stored one with the wavelengths (and their alive bits and
   throughputs) rotated so that lambda_h is in slot 0. */
static double debug_weight_sum(const Renderer *R, const LightCtx *c, int piece, float p_sigma,
                               const float *r, const float *q_bsdf, unsigned alive)
{
    double w_sum = 0.0;
    int h, m, k;
    for (h = 0; h < HERO_N; h++) {
        LightCtx ch = *c;
        double qn2, num, den = 0.0;       /* qn2 = q_nee(h)^2 */
        float P;
        if (!(alive & (1u << h))) continue;
        ch.alive = 0u;
        for (k = 0; k < HERO_N; k++) {
            int from = (h + k) % HERO_N;
            ch.lambda[k] = c->lambda[from];
            ch.beta[k] = c->beta[from];
            if (c->alive & (1u << from)) ch.alive |= 1u << k;
        }
        P = light_nee_pmf(R->ls, &ch, piece);
        qn2 = (double)P * p_sigma * P * p_sigma;
        num = (double)r[h] * r[h] * (qn2 + (double)q_bsdf[h] * q_bsdf[h]);
        for (m = 0; m < HERO_N; m++)
            if (alive & (1u << m)) den += (double)r[m] * r[m] * (qn2 + (double)q_bsdf[m] * q_bsdf[m]);
        if (den > 0.0) w_sum += num / den;
    }
    return w_sum;
}

/* Silence means W_sum = 1 (to 1e-4): said once in docs/WALKTHROUGH.md. */
static void debug_check_sum(FILE *dbg, double w_sum)
{
    if (fabs(w_sum - 1.0) > 1e-4)
        fprintf(dbg, "  WARNING: the MIS weights of all (technique, hero) pairs sum to %.4g, not 1: "
                     "this contribution is weighted wrongly\n", w_sum);
}

/* lambda_i for a path at lo through fluorescent material mi (docs/FLUORESCENCE.md §3), by
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

/* A collision that medium_flight found: its distance along the ray and the
   extinctions sigma_t(lambda_j) of the alive lanes there.  In a uniformgrid
   (grid 1) also the scattering there and Tbar_j / Tbar_0 since the last
   tentative collision; its emission is already on the film (grid_event). */
typedef struct {
    float t;
    float st[HERO_N];
    int grid;
    double tm[HERO_N], ss[HERO_N];
    EquiTerm eq;               /* homogeneous: equiangular sampling on its segment */
} Collision;

/* The stream of a medium's further random numbers (delta and ratio tracking draw
   as many as they meet collisions): a PCG32 keyed by the camera sample and `tag`,
   so a path stays a pure function of (pixel, sample, seed). */
static void medium_rng(const Tracer *tr, uint64_t tag, Rng *rng)
{
    rng_seed(rng, hash_u64(tr->ps->key, tr->ps->k), tag);
}

/* Ratio tracking along a shadow ray in a uniformgrid (THEORY (23)): at each
   tentative collision Tr_j gains Tbar_j sigma_n,j / (Tbar_0 sigma_bar_0), A_m
   (NEE's own density of the collision, had lambda_m been the hero) Tbar_m
   sigma_bar_m / (Tbar_0 sigma_bar_0). */
typedef struct { unsigned alive; double *T, *A; } RatioWalk;

static int ratio_event(void *ctx, const MediumEvent *ev)
{
    RatioWalk *w = (RatioWalk *)ctx;
    double s0 = ev->smaj[0];
    int j, any = 0;
    for (j = 0; j < HERO_N; j++) {
        double sn;
        if (!(w->alive & (1u << j))) continue;
        sn = fmax(ev->smaj[j] - (ev->mp.sa[j] + ev->mp.ss[j]), 0.0);
        w->T[j] *= ev->tm[j] * sn / s0;
        w->A[j] *= ev->tm[j] * ev->smaj[j] / s0;
        if (w->T[j] != 0.0) any = 1;
    }
    return any;                  /* every Tr_j is 0: stop, the light is blocked */
}

/* The transmittance Tr_j along a shadow ray (tmax 1: it ends at its target) that
   starts in medium med: the product of exp(-sigma_t(lambda_j) t) over the lengths t
   of the media it crosses (THEORY (15)), passing surfaces of Material "interface" (pbrt-v4's
   volpath does the same); 0 when any other surface blocks it.  Tr_j is left alone
   for wavelengths that are not alive. */
static int shadow_transmittance(Tracer *tr, int depth, Ray sh, int med, const PathState *path,
                                double T[HERO_N], double A[HERO_N])
{
    const Scene *s = tr->R->s;
    int seg, j;
    for (seg = 0; seg < MEDIUM_SEGMENTS; seg++) {
        HitRecord hit;
        SurfacePoint sp;
        int found;
        double len;
        tr->cnt->rays++;
        /* without "interface" surfaces any surface before the target blocks the
           light: an any-hit query (bvh_occluded) answers that, and the ray stays
           in its medium all the way */
        if (!s->n_interface) {
            if (bvh_occluded(&s->bvh, s, &sh)) return 0;
            found = 0;
        } else found = bvh_intersect(&s->bvh, s, &sh, &hit);
        len = (double)(found ? hit.t : 1.0f) * v3_len(sh.d);
        if (med >= 0 && s->media[med].type != MEDIUM_HOMOGENEOUS) {
            RatioWalk w;
            Rng rng;
            double tm[HERO_N];
            w.alive = path->alive;
            w.T = T;
            w.A = A;
            medium_rng(tr, ((uint64_t)1 << 40) + (uint64_t)depth * MEDIUM_SEGMENTS + (uint64_t)seg, &rng);
            if (medium_track(&s->media[med], sh, found ? hit.t : 1.0f, path->lam, path->alive,
                             rng_float(&rng), &rng, ratio_event, &w, tm))
                return 0;
            for (j = 0; j < HERO_N; j++)
                if (path->alive & (1u << j)) { T[j] *= tm[j]; A[j] *= tm[j]; }
        } else if (med >= 0) {
            const MediumLanes *ml = medium_lanes(tr, med, path->lam);
            for (j = 0; j < HERO_N; j++)
                if (path->alive & (1u << j))
                    T[j] *= exp(-(double)ml->st[j] * len);
        }
        if (!found) return 1;
        scene_surface_point(s, &sh, &hit, &sp);
        if (s->materials[s->shapes[sp.shape].material].type != MAT_INTERFACE) return 0;
        med = medium_after(s, sp.shape, med, sh.d, sp.ng);
        {
            Vec3 target = v3_add(sh.o, sh.d);
            sh.o = spawn_origin(&sp, sh.d);
            sh.d = v3_sub(target, sh.o);
        }
    }
    return 0;                  /* more boundaries than MEDIUM_SEGMENTS: treated as blocked */
}

/* One straight stretch of the path through its medium, from the ray's origin to
   distance tmax (the next surface; INFINITY: none), with the hero's free-flight
   sampling (THEORY (16)): t = -ln(1 - u) / sigma_t(lambda_0).
   Collision (t < tmax): returns 1 with *c; the lanes are not updated yet.  Pass:
   returns 0 after multiplying each alive lane's throughput and ratio by Tr_j / Tr_0
   (the pass probability of the hero with lambda_j's coefficient over the hero's
   own), and prev.T (Tr) by Tr_j (the BSDF/phase technique's pdf for the segment, THEORY
   (19)).  With --chromatic-media terminate, an event in a medium whose sigma_t
   differs between the alive wavelengths first terminates the secondaries. */
static int grid_flight(Tracer *tr, int dim, int depth, const Ray *ray, float tmax, PathState *path,
                       Collision *c);
static void equi_nee(Tracer *tr, int depth, int seg, const EquiTerm *q, const PathState *path,
                     const float *st);

/* Whether the equiangular technique runs on a segment through a homogeneous
   medium at bounce depth (THEORY §12.1): NEE on, lamps to aim at, a collision
   there would scatter (below maxdepth and --equiangular N), and every alive lane has sigma_t > 0 (so
   free flight's density, which its weights divide by, is positive for every
   hero).  The rule reads nothing that depends on which wavelength is the hero. */
static int equi_applies(const Tracer *tr, int depth, const PathState *path, const float *st)
{
    const Renderer *R = tr->R;
    int j;
    if (!R->o->equiangular || !R->o->nee || depth >= R->o->maxdepth || light_equi(R->ls)->n == 0 ||
        (R->o->equi_depth > 0 && depth >= R->o->equi_depth))
        return 0;
    for (j = 0; j < HERO_N; j++)
        if ((path->alive & (1u << j)) && !(st[j] > 0.0f)) return 0;
    return 1;
}

static int medium_flight(Tracer *tr, int dim, int depth, const Ray *ray, float tmax, PathState *path,
                         Collision *c)
{
    const Medium *M = &tr->R->s->media[path->medium];
    const MediumLanes *ml = medium_lanes(tr, path->medium, path->lam);
    float *st = c->st;
    double s0, t, u, nb[HERO_N] = { 0 }, nr[HERO_N] = { 0 };
    int j, chromatic = 0;
    for (j = 0; j < HERO_N; j++) {
        st[j] = (path->alive & (1u << j)) ? ml->st[j] : 0.0f;
        if (j > 0 && (path->alive & (1u << j)) && (st[j] != st[0] || M->chromatic)) chromatic = 1;
    }
    if (chromatic && tr->R->o->media_terminate) {
        lanes_hero_only(path);
        path->prev.alive = 1u;
        if (tr->dbg) fprintf(tr->dbg, "  medium \"%s\": chromatic, secondaries terminated\n", M->name);
    }
    c->grid = 0;
    c->eq.on = 0;
    if (M->type != MEDIUM_HOMOGENEOUS) return grid_flight(tr, dim, depth, ray, tmax, path, c);
    s0 = st[0];
    if (equi_applies(tr, depth, path, st)) {
        /* the equiangular technique on this segment (THEORY §12.1): its own NEE now,
           its terms in the weights of free flight's collision on the segment */
        c->eq.on = 1;
        c->eq.o = ray->o;
        c->eq.d = ray->d;
        c->eq.tmax = tmax;
        memcpy(c->eq.r, path->r, sizeof c->eq.r);
        c->eq.alive = path->alive;
        equi_nee(tr, depth, dim - dim_medium(depth, 0), &c->eq, path, st);
    }
    u = sampler_1d(tr->ps, dim);
    t = s0 > 0.0 ? -log1p(-u) / s0 : INFINITY;
    if (t < (double)tmax) {
        c->t = (float)t;
        c->eq.t = c->t;
        c->eq.pff0 = s0 * exp(-s0 * (double)c->t);
        return 1;
    }
    for (j = 0; j < HERO_N; j++) {
        double ratio, Tj;
        if (!(path->alive & (1u << j))) continue;
        ratio = st[j] == st[0] ? 1.0 : exp(-((double)st[j] - s0) * tmax);
        Tj = st[j] == 0.0f ? 1.0 : exp(-(double)st[j] * tmax);
        path->prev.T[j] *= Tj;
        nb[j] = path->beta[j] * ratio;
        nr[j] = path->r[j] * ratio;
    }
    lanes_update(path, nb, nr);
    if (tr->dbg) fprintf(tr->dbg, "  medium \"%s\": passed %.4g, Tr=(%.4g %.4g %.4g %.4g)\n", M->name,
                         (double)tmax, path->prev.T[0], path->prev.T[1], path->prev.T[2], path->prev.T[3]);
    return 0;
}

/* ------------------------------------------------------------------ emitters */

/* What next event estimation needs to know of the vertex it starts from. */
typedef struct {
    const Material *mat;       /* the surface's material; NULL: a point in a medium */
    const SurfacePoint *sp;    /* the surface point (NULL in a medium) */
    Vec3 p, wo;                /* position; unit direction back along the path */
    float g;                   /* in a medium: its Henyey-Greenstein asymmetry */
    int medium;                /* the medium the path reached it through (-1: none) */
    const LightCtx *ctx;       /* the selection context there */
    const EquiTerm *eq;        /* a collision: the equiangular technique's terms (NULL: none) */
    int equi;                  /* 1: this is the equiangular technique's NEE (equi_nee) */
} Scatter;

/* One NEE sample from vertex v (THEORY (6)): a point on the piece that NEE took
   with probability P, drawn with the numbers u, weighted against the BSDF's (or
   phase function's) sampling of the same direction.  Along the shadow ray the
   light is attenuated by the media it crosses, Tr_j; the BSDF technique would have
   had to cross them too, so its pdf for wavelength m is q_bsdf(m) Tr_m in the
   denominator (THEORY (19)).  A delta light (point, spot, distant: delta.c) cannot
   be found by a BSDF direction: its weight against BSDF sampling is 1, so the
   BSDF's pdfs leave the denominator (es.pdf_sa = 1 / G there, and
   q_nee / den = 1 / (P (1/G) sum_m r_m^2): THEORY §11). */
static Contribution nee_sample(Tracer *tr, int depth, const Scatter *v, const PathState *path, int piece,
                               float P, const float u[3])
{
    const Renderer *R = tr->R;
    const Scene *s = R->s;
    FILE *dbg = tr->dbg;
    static const float no_bsdf[HERO_N] = { 0 };
    Contribution none = { { 0.0 } }, k;
    float f[HERO_N], pdf_l[HERO_N], cos_i, q_nee;
    const float *q_b;                 /* the BSDF's pdfs in the MIS weight */
    int em = light_piece_emitter(R->ls, piece), any = 0, j;
    EmitterSample es;
    double value[HERO_N], den, e_eq, T[HERO_N] = { 1.0, 1.0, 1.0, 1.0 }, A[HERO_N] = { 1.0, 1.0, 1.0, 1.0 };
    float alpha;                                   /* a shape's "alpha" at es (lights.c) */
    SurfacePoint at_sp;                            /* es's (u, v), for an emission image */
    const SurfacePoint *at;
    if (!light_sample(R->ls, piece, v->p, v->ctx->n, u, &es)) {
        if (dbg) fprintf(dbg, "  NEE: no usable point on emitter %d (seen edge-on or at distance 0)\n", em);
        return none;
    }
    alpha = emitter_alpha_at(s, em, v->p, &es);
    at = s->emitters[em].image || s->emitters[em].prim_scale ? emitter_point_at(s, em, v->p, &es, &at_sp)
                                                             : NULL;
    for (j = 0; j < HERO_N; j++) {
        value[j] = 0.0;
        if (path->alive & (1u << j))
            value[j] = light_Le_at(R->ls, em, es.n, v3_neg(es.wi), at, path->lam[j]) * alpha;
        if (value[j] != 0.0) any = 1;
    }
    if (!any) {
        if (dbg) fprintf(dbg, "  NEE: emitter %d sends nothing here (its back faces this point, or Le = 0 at the alive wavelengths)\n", em);
        return none;
    }
    if (v->mat) {
        bsdf_eval(v->mat, v->sp, v->wo, es.wi, path->lam, path->alive, f, pdf_l);
        cos_i = fabsf(v3_dot(es.wi, v->sp->ns));
    } else {                      /* in a medium: the phase function is f and pdf */
        float ph = hg_phase(v->g, v3_dot(v3_neg(v->wo), es.wi));
        for (j = 0; j < HERO_N; j++) f[j] = pdf_l[j] = (path->alive & (1u << j)) ? ph : 0.0f;
        cos_i = 1.0f;
    }
    any = 0;
    for (j = 0; j < HERO_N; j++) {
        value[j] *= (double)path->beta[j] * f[j] * cos_i;
        if (value[j] != 0.0) any = 1;
    }
    if (!any) {
        if (dbg) fprintf(dbg, "  NEE: emitter %d: f |cos| = 0 (the sampled point is below this surface, or the BSDF has no lobe there)\n", em);
        return none;
    }
    {
        Ray shadow;
        Vec3 target = offset_ray_origin(es.p, es.n, v3_neg(es.wi));
        shadow.o = v->mat ? spawn_origin(v->sp, es.wi) : v->p;
        shadow.d = v3_sub(target, shadow.o);
        shadow.tmax = 1.0f;
        shadow.time = tr->time;
        if (R->vol) {
            /* through media and "interface" surfaces (the medium it starts in:
               a surface's own MediumInterface decides by the side of es.wi) */
            int med = v->mat ? medium_after(s, v->sp->shape, v->medium, es.wi, v->sp->ng)
                             : v->medium;
            if (!shadow_transmittance(tr, depth, shadow, med, path, T, A)) {
                if (dbg) fprintf(dbg, "  NEE: occluded\n");
                return none;
            }
            for (j = 0; j < HERO_N; j++) value[j] *= T[j];
        } else {
            tr->cnt->rays++;
            if (bvh_occluded(&s->bvh, s, &shadow)) {
                if (dbg) fprintf(dbg, "  NEE: occluded\n");
                return none;
            }
        }
    }
    q_b = es.delta || emitter_invisible(s, em) ? no_bsdf : pdf_l;   /* lights.c: no BSDF finds it */
    /* free flight's NEE density (for the equiangular technique's own sample, the
       selection pmf free flight's NEE would have given this piece here) and the
       equiangular technique's, e (THEORY (18e)) */
    q_nee = (v->equi ? light_nee_pmf(R->ls, v->ctx, piece) : P) * es.pdf_sa;
    e_eq = v->eq ? equi_e(R, v->eq, em, es.pdf_sa) : 0.0;
    den = mis_denominator(path->r, q_b, T, A, q_nee, path->alive);
    if (e_eq != 0.0) den += equi_den(v->eq, e_eq);
    if (!(den > 0.0)) {
        if (dbg) fprintf(dbg, "  NEE: emitter %d: MIS denominator 0 (no technique has a density here)\n", em);
        return none;
    }
    if (dbg) {
        float qT[HERO_N];
        for (j = 0; j < HERO_N; j++) qT[j] = (float)(q_b[j] * T[j]);
        if (v->eq && v->eq->on)
            fprintf(dbg, "  NEE%s: equiangular density e %.4g (free flight's q_nee %.4g), weight %.4g\n",
                    v->equi ? " (equiangular)" : "", e_eq, q_nee, (v->equi ? e_eq * e_eq : (double)q_nee * q_nee) / den);
        else debug_weight(dbg, "NEE: visible emitter", em, (double)q_nee * q_nee / den,
                          path->r, qT, q_nee, path->alive, 1);
        if (path->alive != 1u && !(v->eq && v->eq->on))
            debug_check_sum(dbg, debug_weight_sum(R, v->ctx, piece, es.pdf_sa, path->r, qT, path->alive));
    }
    for (j = 0; j < HERO_N; j++) k.c[j] = value[j];
    return weighted(k, (v->equi ? e_eq : (double)q_nee) / den);
}

/* 4. Next event estimation at vertex v: the pieces lights.c offers (one chosen
   piece; every piece for the strategy "all"), one sample each, added to the film.
   The numbers for the point on the piece are drawn once for all of them (the
   order of these requests is the independent sampler's stream order), from the
   dimensions dim0 + BD_LIGHT .. BD_POINT (a bounce's, or a subsurface exit's). */
static void next_event(Tracer *tr, int depth, int dim0, const Scatter *v, const PathState *path)
{
    const Renderer *R = tr->R;
    FILE *dbg = tr->dbg;
    float u[3];
    int k, n, needs_u;
    u[0] = sampler_1d(tr->ps, dim0 + BD_TRIANGLE);
    sampler_2d(tr->ps, dim0 + BD_POINT, &u[1], &u[2]);
    n = light_nee_count(R->ls, &needs_u);
    for (k = 0; k < n; k++) {
        float ul = needs_u ? sampler_1d(tr->ps, dim0 + BD_LIGHT) : 0.0f, P;
        int fb, piece = light_nee_piece(R->ls, v->ctx, k, ul, &P, &fb);
        if (fb) tr->cnt->fallbacks++;
        if (dbg) fprintf(dbg, "  NEE: chose emitter %d with P=%.4g (%s)\n",
                         piece >= 0 ? light_piece_emitter(R->ls, piece) : -1, P,
                         light_nee_source(R->ls, v->ctx, fb));
        if (piece < 0) {
            if (dbg) fprintf(dbg, "  NEE: no emitter can be chosen here (every P is 0)\n");
            break;
        }
        film_add(tr->fs, nee_sample(tr, depth, v, path, piece, P, u));
    }
}

/* Emitter e, found by the sampled direction dir (unit) from the previous vertex:
   at the surface point sp, or (sp NULL) an infinite light that the escaped ray
   sees.  Its radiance times beta, weighted against NEE from there:
   W = (q_bsdf(0) Tr_0)^2 / D, with q_nee = P(piece | prev's context) p_sigma
   (0 where NEE was not possible); beta already holds 1/q_bsdf(0) and Tr_m / Tr_0
   of the media on the way (THEORY (6), (19)). */
static Contribution emitter_found(Tracer *tr, const PathState *path, int e, const SurfacePoint *sp,
                                  Vec3 dir)
{
    const Renderer *R = tr->R;
    const PrevVertex *prev = &path->prev;
    Contribution k;
    Vec3 n = sp ? sp->ng : dir, wo = v3_neg(dir);
    double den, W;
    float q_nee = 0.0f, pdf_sa = 0.0f;
    int j, any = 0, piece;
    for (j = 0; j < HERO_N; j++) {
        k.c[j] = 0.0;
        if (!(path->alive & (1u << j))) continue;
        k.c[j] = (double)path->beta[j] * light_Le_at(R->ls, e, n, wo, sp, path->lam[j]);
        if (k.c[j] != 0.0) any = 1;
    }
    if (!any) return k;
    /* the piece NEE would have had to choose to sample this point */
    piece = light_piece_of(R->ls, e, sp ? sp->prim : -1);
    if (prev->can_nee) {
        pdf_sa = sp ? light_pdf_sa(R->ls, piece, prev->p, prev->ctx.n, sp->p, sp->ng, sp->prim)
                    : inf_pdf(&R->s->emitters[e], prev->p, dir);
        q_nee = light_nee_pmf(R->ls, &prev->ctx, piece) * pdf_sa;
    }
    den = mis_denominator(prev->r, prev->q_bsdf, prev->T, prev->A, q_nee, prev->alive);
    if (prev->eq.on && prev->can_nee && sp) den += equi_den(&prev->eq, equi_e(R, &prev->eq, e, pdf_sa));
    W = den > 0.0 ? ((double)prev->q_bsdf[0] * prev->T[0]) * ((double)prev->q_bsdf[0] * prev->T[0]) / den : 0.0;
    if (tr->dbg && !sp)
        fprintf(tr->dbg, "  escaped: infinite light %d, MIS weight %.4g (q_nee %.4g)\n", e, W, q_nee);
    if (tr->dbg && sp) {
        /* the printed shares use the densities of W's denominator: q_bsdf(m) Tr_m */
        float qT[HERO_N];
        for (j = 0; j < HERO_N; j++) qT[j] = (float)(prev->q_bsdf[j] * prev->T[j]);
        debug_weight(tr->dbg, "emission from emitter", e, W, prev->r, qT, q_nee, prev->alive, 0);
        if (prev->can_nee && prev->alive != 1u && !prev->eq.on)
            debug_check_sum(tr->dbg, debug_weight_sum(R, &prev->ctx, piece, pdf_sa, prev->r,
                                                      qT, prev->alive));
    }
    return weighted(k, W);
}

/* 6. Russian roulette on a hero-independent throughput: survival probability
   P_survive = min(1, 4 max_j beta_j eta2_j / sum_m r_m) (8), from RR_START_DEPTH on
   (q in the code below).  eta2_j takes out the 1/etap^2 of the refractions: inside
   glass of index 3 beta is 1/9 of what the path will carry out again, and a
   roulette on beta alone would end 8 of 9 paths there and send the rest out with
   9x the weight (fireflies).  Returns 0 when the path ends (also when only the
   hero is left and carries nothing). */
static int russian_roulette(Tracer *tr, int depth, PathState *path)
{
    int j;
    if (depth >= RR_START_DEPTH) {
        float sum_r = 0.0f, bmax = 0.0f, q;    /* q: P_survive */
        for (j = 0; j < HERO_N; j++)
            if (path->alive & (1u << j)) {
                float b = path->beta[j] * path->eta2[j];
                sum_r += path->r[j];
                if (b > bmax) bmax = b;
            }
        q = sum_r > 0.0f ? (float)HERO_N * bmax / sum_r : 0.0f;
        if (q < 1.0f) {
            int dies = sampler_1d(tr->ps, dim_bounce(depth, BD_ROULETTE)) >= q;
            if (tr->dbg) fprintf(tr->dbg, "  roulette: survival P_survive = min(1, %d max_j beta_j eta2_j / sum_m r_m) = %.4g: %s\n",
                                 HERO_N, q, dies ? "path ends" : "survives, beta /= P_survive");
            if (dies) return 0;
            for (j = 0; j < HERO_N; j++) path->beta[j] /= q;
        }
    }
    return !(!(path->beta[0] > 0.0f) && path->alive == 1u);
}
/* ------------------------------------------------------------------ vertices */

/* The emission of medium med along the ray, estimated at a collision (THEORY
   (20), (25)): its sigma_a Le (sa[j], le[j] at the point), with weight
   1 / sum_m r'_m^2 (no other technique makes this point); ratio[j] = Tr_j / Tr_0
   at the collision, rc the ratios r'_m after it. */
static Contribution medium_emission(Tracer *tr, const PathState *path, int med, const double *ratio,
                                    const double *sa, const double *le, const float *rc, double s0)
{
    const Renderer *R = tr->R;
    Contribution k;
    double den = 0.0;
    int j;
    for (j = 0; j < HERO_N; j++) {
        k.c[j] = 0.0;
        if (!(path->alive & (1u << j)) || !(rc[j] > 0.0f) || !isfinite(rc[j])) continue;
        k.c[j] = path->beta[j] * ratio[j] * sa[j] * (R->med_le[med] * le[j]) / s0;
        den += (double)rc[j] * rc[j];
    }
    if (tr->dbg) fprintf(tr->dbg, "  medium emission: weight 1 / sum_m r_m^2 = %.4g\n", den > 0.0 ? 1.0 / den : 0.0);
    if (!(den > 0.0)) { for (j = 0; j < HERO_N; j++) k.c[j] = 0.0; return k; }
    return weighted(k, 1.0 / den);
}

/* Delta tracking through a uniformgrid (THEORY §13): medium_track (medium.c)
   draws tentative collisions at the hero's majorant sigma_bar_0; grid_event
   decides each.  Every tentative collision first estimates the medium's emission
   (THEORY (25)); then with the hero's probability sigma_t,0 / sigma_bar_0 it is
   real (the collision medium_vertex continues from, THEORY (22)), else null:
       beta_j, r_j  *= Tbar_j sigma_n,j / (Tbar_0 sigma_n,0)             (21)
       T_m (PrevVertex) *= Tbar_m sigma_n,m / (Tbar_0 sigma_bar_0)
       A_m (PrevVertex) *= Tbar_m sigma_bar_m / (Tbar_0 sigma_bar_0)      (24)
   with sigma_n = sigma_bar - sigma_t >= 0. */
typedef struct {
    Tracer *tr;
    PathState *path;
    int depth, med;
    Rng rng;                   /* the real-or-null choices */
    Collision *c;
} GridWalk;

static int grid_event(void *ctx, const MediumEvent *ev)
{
    GridWalk *w = (GridWalk *)ctx;
    PathState *path = w->path;
    const Renderer *R = w->tr->R;
    double s0 = ev->smaj[0], st0 = ev->mp.sa[0] + ev->mp.ss[0], sn0, nb[HERO_N], nr[HERO_N];
    int j;
    if (w->depth < R->o->maxdepth && R->med_le[w->med] > 0.0) {
        float rc[HERO_N];
        for (j = 0; j < HERO_N; j++)
            rc[j] = (path->alive & (1u << j)) ? (j == 0 ? 1.0f : (float)(path->r[j] * ev->tm[j] * (ev->smaj[j] / s0)))
                                             : 0.0f;
        film_add(w->tr->fs, medium_emission(w->tr, path, w->med, ev->tm, ev->mp.sa, ev->mp.le, rc, s0));
    }
    if (rng_float(&w->rng) * s0 < st0) {          /* real: medium_vertex goes on */
        w->c->t = ev->t;
        w->c->grid = 1;
        for (j = 0; j < HERO_N; j++) {
            w->c->st[j] = (float)(ev->mp.sa[j] + ev->mp.ss[j]);
            w->c->ss[j] = ev->mp.ss[j];
            w->c->tm[j] = ev->tm[j];
        }
        return 0;
    }
    sn0 = s0 - st0;
    for (j = 0; j < HERO_N; j++) {
        double sn, f;
        nb[j] = nr[j] = 0.0;
        if (!(path->alive & (1u << j))) continue;
        sn = fmax(ev->smaj[j] - (ev->mp.sa[j] + ev->mp.ss[j]), 0.0);
        f = ev->tm[j] * sn / sn0;
        nb[j] = path->beta[j] * f;
        nr[j] = path->r[j] * f;
        path->prev.T[j] *= ev->tm[j] * sn / s0;
        path->prev.A[j] *= ev->tm[j] * ev->smaj[j] / s0;
    }
    lanes_update(path, nb, nr);
    return 1;
}

/* medium_flight for a uniformgrid: the first distance from the sampler's
   dimension dim, the rest from a stream of its own (medium_rng).  Returns 1 with
   *c at a real collision; 0 after the pass factors Tbar_j / Tbar_0 of the rest. */
static int grid_flight(Tracer *tr, int dim, int depth, const Ray *ray, float tmax, PathState *path,
                       Collision *c)
{
    GridWalk w;
    double tm[HERO_N], nb[HERO_N] = { 0 }, nr[HERO_N] = { 0 };
    float u = sampler_1d(tr->ps, dim);
    int j;
    w.tr = tr;
    w.path = path;
    w.depth = depth;
    w.med = path->medium;
    w.c = c;
    medium_rng(tr, (uint64_t)dim, &w.rng);
    if (medium_track(&tr->R->s->media[path->medium], *ray, tmax, path->lam, path->alive, u, &w.rng,
                     grid_event, &w, tm))
        return 1;
    for (j = 0; j < HERO_N; j++) {
        if (!(path->alive & (1u << j))) continue;
        path->prev.T[j] *= tm[j];
        path->prev.A[j] *= tm[j];
        nb[j] = path->beta[j] * tm[j];
        nr[j] = path->r[j] * tm[j];
    }
    lanes_update(path, nb, nr);
    if (tr->dbg) fprintf(tr->dbg, "  medium \"%s\": passed %.4g\n", tr->R->s->media[path->medium].name,
                         (double)tmax);
    return 0;
}

/* A collision c along the ray in the path's medium (medium_flight found it).
   THEORY §12 derives each factor:
   - the collision's density for hero m is sigma_t(lambda_m) Tr_m(t), so every ratio
     r_m gains (sigma_t,m / sigma_t,0) Tr_m / Tr_0 (THEORY (17));
   - emission (an emissive medium, below maxdepth): medium_emission;
   - scattering: beta_j gains sigma_s,j Tr_j / (sigma_t,0 Tr_0): the path does not
     stop at an absorption (it goes on with the albedo as weight, and the
     roulette ends it), then NEE with the phase function, and the next direction
     from the phase function (f / pdf = 1, the same pdf for every wavelength).
   Returns 0 when the path ends; otherwise ray leaves the collision. */
/* The equiangular technique's sample on the segment q (THEORY §12.1): a lamp i
   with probability 1/n, a distance t by (18d) towards its centre, the lanes as
   free flight's collision at t would leave them (medium_vertex's (17)), and one
   NEE sample of lamp i from there, weighted by nee_sample against free flight's
   NEE and phase sampling at t (v.equi).  The lanes' throughput then holds
   1 / p_ff,0(t), which the weight e / D takes back out (e = p_eq P_E p_sigma /
   p_ff,0). */
static void equi_nee(Tracer *tr, int depth, int seg, const EquiTerm *q, const PathState *path,
                     const float *st)
{
    const Renderer *R = tr->R;
    const EquiLamps *L = light_equi(R->ls);
    const Medium *M = &R->s->media[path->medium];
    const MediumLanes *ml = medium_lanes(tr, path->medium, path->lam);
    EquiTerm at = *q;
    EquiSeg sg;
    PathState pc = *path;
    LightCtx ctx;
    Scatter v;
    double s0 = st[0], pe, nb[HERO_N], nr[HERO_N];
    float u[3];
    int i = 0, j, any = 0;
    if (L->n > 1) {
        i = (int)(sampler_1d(tr->ps, dim_equi(depth, seg, EQ_LAMP)) * (float)L->n);
        if (i >= L->n) i = L->n - 1;
    }
    if (!equi_segment(q->o, q->d, q->tmax, L->center[i], &sg)) return;
    at.t = (float)equi_sample(&sg, sampler_1d(tr->ps, dim_equi(depth, seg, EQ_T)), &pe);
    at.pff0 = s0 * exp(-s0 * (double)at.t);
    if (!(pe > 0.0) || !(at.pff0 > 0.0)) return;
    for (j = 0; j < HERO_N; j++) {
        double ratio;
        nb[j] = nr[j] = 0.0;
        if (!(path->alive & (1u << j))) continue;
        ratio = st[j] == st[0] ? 1.0 : exp(-((double)st[j] - s0) * at.t);
        nb[j] = path->beta[j] * (double)ml->ss[j] * ratio / s0;
        nr[j] = j == 0 ? 1.0 : path->r[j] * ((double)st[j] / s0) * ratio;
        if ((float)nb[j] > 0.0f) any = 1;
    }
    lanes_update(&pc, nb, nr);
    if (!any) return;
    v.mat = NULL;
    v.sp = NULL;
    v.p = v3_add(q->o, v3_mul(q->d, at.t));
    v.wo = v3_neg(q->d);
    v.g = M->g;
    v.medium = path->medium;
    vertex_ctx(R, &pc, v.p, v3(0.0f, 0.0f, 0.0f), &ctx);
    v.ctx = &ctx;
    v.eq = &at;
    v.equi = 1;
    if (tr->dbg) fprintf(tr->dbg, "  equiangular: lamp %d (emitter %d), t=%.4g, p_eq %.4g\n", i, L->emitter[i],
                         (double)at.t, pe);
    u[0] = 0.5f;                        /* a sphere's or a point's sample reads no triangle number */
    sampler_2d(tr->ps, dim_equi(depth, seg, EQ_POINT), &u[1], &u[2]);
    film_add(tr->fs, nee_sample(tr, depth, &v, &pc, light_piece_of(R->ls, L->emitter[i], -1), 1.0f / (float)L->n, u));
}

static int medium_vertex(Tracer *tr, int depth, Ray *ray, const Collision *c, PathState *path)
{
    const Renderer *R = tr->R;
    const Scene *s = R->s;
    const RenderOptions *o = R->o;
    int med = path->medium;
    const Medium *M = &s->media[med];
    const MediumLanes *ml = medium_lanes(tr, med, path->lam);
    const float *st = c->st;
    double s0 = st[0], ratio[HERO_N], nb[HERO_N], nr[HERO_N], sa[HERO_N], le[HERO_N];
    float rc[HERO_N], q[HERO_N], u1, u2, pdf;
    Vec3 p = v3_add(ray->o, v3_mul(ray->d, c->t)), d = ray->d, wi;
    LightCtx ctx;
    int j, any = 0;
    if (tr->dbg) fprintf(tr->dbg, "  vertex %d: in medium \"%s\" at x=(%.4g %.4g %.4g), t=%.4g, sigma_t(hero)=%.4g\n",
                         depth, M->name, p.x, p.y, p.z, (double)c->t, s0);
    if (depth >= o->maxdepth) return 0;   /* pbrt-v4: neither emission nor scattering there */
    for (j = 0; j < HERO_N; j++) {
        ratio[j] = rc[j] = 0.0f;
        sa[j] = le[j] = 0.0;
        if (!(path->alive & (1u << j))) continue;
        ratio[j] = c->grid ? c->tm[j] : st[j] == st[0] ? 1.0 : exp(-((double)st[j] - s0) * c->t);
        rc[j] = j == 0 ? 1.0f : (float)(path->r[j] * ((double)st[j] / s0) * ratio[j]);
        sa[j] = ml->sa[j];
        le[j] = ml->le[j];
    }
    if (R->med_le[med] > 0.0 && !c->grid)
        film_add(tr->fs, medium_emission(tr, path, med, ratio, sa, le, rc, s0));
    for (j = 0; j < HERO_N; j++) {
        nb[j] = nr[j] = 0.0;
        if (!(path->alive & (1u << j))) continue;
        nb[j] = path->beta[j] * (c->grid ? c->ss[j] : (double)ml->ss[j]) * ratio[j] / s0;
        nr[j] = rc[j];
        if ((float)nb[j] > 0.0f) any = 1;
    }
    lanes_update(path, nb, nr);
    if (!any) return 0;                   /* absorbed at every wavelength */
    vertex_ctx(R, path, p, v3(0.0f, 0.0f, 0.0f), &ctx);
    if (o->nee && s->n_emitters > 0) {
        Scatter v;
        v.mat = NULL;
        v.sp = NULL;
        v.p = p;
        v.wo = v3_neg(d);
        v.g = M->g;
        v.medium = med;
        v.ctx = &ctx;
        v.eq = c->eq.on ? &c->eq : NULL;
        v.equi = 0;
        next_event(tr, depth, dim_bounce(depth, 0), &v, path);
    }
    /* the phase function's direction */
    sampler_2d(tr->ps, dim_bounce(depth, BD_DIR), &u1, &u2);
    wi = hg_sample(M->g, d, u1, u2, &pdf);
    if (!(pdf > 0.0f)) return 0;
    for (j = 0; j < HERO_N; j++) q[j] = pdf;
    prev_set(path, o->nee && s->n_emitters > 0, &ctx, p, q, c->eq.on ? &c->eq : NULL);
    path->any_nonspec = 1;               /* (pbrt-v4's volpath: a real scattering) */
    ray->o = p;
    ray->d = wi;
    ray->tmax = INFINITY;
    return 1;
}

/* The fluorescent branch (surface_vertex, between steps 3 and 4): a fluorescent
   vertex reflects or re-radiates (docs/FLUORESCENCE.md §3-§5); mi is the
   material's index.  To re-radiate: sample lambda_i on [300, lambda_o] (from A,
   A x power or uniformly), weight by (F4), and from here on transport at lambda_i
   through a Lambertian of albedo 1: NEE, emitter selection (ctx.lambda) and every
   MIS pdf below use it.  The baseline terminates the secondaries (as at dispersive
   glass); --fluor-lanes keep shifts every alive wavelength with the SAME number ul
   through its own p(li | lo_j) and carries the branch probability in the ratios r
   (docs/FLUORESCENCE.md §4b).  To reflect: a Lambertian of albedo rho (1 - A); the choice
   depends on lambda_o, so the pdf ratios carry it (THEORY (5)).  Returns the
   material the vertex scatters with (R->white after a shift, mat after a
   reflection); NULL: the path ends. */
static const Material *fluor_vertex(Tracer *tr, int depth, const Material *mat, int mi, PathState *path)
{
    const Renderer *R = tr->R;
    const RenderOptions *o = R->o;
    FILE *dbg = tr->dbg;
    float pf = fluor_branch_pf(mat, path->lam[0]), ub, ul;
    double nb[HERO_N], nr[HERO_N];
    int j;
    sampler_2d(tr->ps, dim_fluor(depth), &ub, &ul);
    if (ub >= pf) {
        for (j = 0; j < HERO_N; j++) {
            nb[j] = (double)path->beta[j] / (1.0f - pf);
            nr[j] = (double)path->r[j] * ((1.0f - fluor_branch_pf(mat, path->lam[j])) / (1.0f - pf));
        }
        lanes_update(path, nb, nr);
        if (dbg) fprintf(dbg, "  fluorescent: reflects (P_r %.3g)\n", 1.0f - pf);
        return mat;
    }
    {
        float li[HERO_N], pli[HERO_N], wgt[HERO_N];
        for (j = 0; j < HERO_N; j++) {
            li[j] = path->lam[j];
            pli[j] = wgt[j] = 0.0f;
            if (!(path->alive & (1u << j)) || (j > 0 && !o->fluor_keep)) continue;
            li[j] = fluor_sample_lambda_i(R, mat, mi, path->lam[j], ul, &pli[j]);
            wgt[j] = pli[j] > 0.0f ? fluor_weight(mat, li[j], path->lam[j]) : 0.0f;
        }
        if (dbg) fprintf(dbg, "  fluorescent: re-radiates, %.1f nm absorbed at %.1f nm "
                         "(P_f %.3g, p(li|lo) %.4g, weight %.4g); secondaries %s\n",
                         path->lam[0], li[0], pf, pli[0], wgt[0],
                         o->fluor_keep ? "shifted with the same number" : "terminated");
        if (!o->fluor_keep && (!(pli[0] > 0.0f) || !(wgt[0] > 0.0f))) return NULL;
        /* lane j: f_j / (P_f(lambda_0) p(li_j | lo_j)); the technique with hero j
           would have re-radiated with P_f(lo_j): r_j *= P_f(lo_j) / P_f(lo_0).
           A lane whose weight is 0 stays in the MIS sums while r_j > 0 (its
           technique could have made this path), with beta_j = 0.  Without
           --fluor-lanes keep the secondaries end here (r_j = 0). */
        for (j = 0; j < HERO_N; j++) {
            nb[j] = pli[j] > 0.0f ? path->beta[j] * (wgt[j] / (pf * pli[j])) : 0.0f;
            nr[j] = o->fluor_keep ? path->r[j] * (fluor_branch_pf(mat, path->lam[j]) / pf) : 0.0f;
        }
        lanes_update(path, nb, nr);
        path->shifted = 1;
        for (j = 0; j < HERO_N; j++) path->lam[j] = li[j];
        if (!(path->beta[0] > 0.0f) && path->alive == 1u) return NULL;
        return &R->white;
    }
}
/* The exit of a path that refracted into subsurface material mat (index mi, as
   its shapes name it) at sp (THEORY §18): sss_probe finds the exit point and
   its Sp and densities; the lanes gain (43); NEE there with the exit lobe Sw,
   and the next direction from Sw (44), on the numbers of dim_sss(depth).  The
   depth does not grow (pbrt-v4's volpath).  Returns 0 when the path ends. */
static int subsurface_exit(Tracer *tr, int depth, Ray *ray, const SurfacePoint *sp,
                           const Material *mat, int mi, PathState *path)
{
    const Renderer *R = tr->R;
    const Scene *s = R->s;
    int d0 = dim_sss(depth), j, can_nee = R->o->nee && s->n_emitters > 0;
    double nb[HERO_N], nr[HERO_N];
    float u[4], cos_i;
    SssExit ex;
    Material sw = *mat;
    LightCtx ctx;
    BsdfSample bs;
    u[0] = sampler_1d(tr->ps, d0 + SSS_AXIS);
    sampler_2d(tr->ps, d0 + SSS_RADIUS, &u[1], &u[2]);
    u[3] = sampler_1d(tr->ps, d0 + SSS_PICK);
    if (!sss_probe(s, mat, mi, sp, path->lam, path->alive, u, &ex)) {
        tr->cnt->rays += (uint64_t)ex.rays;
        if (tr->dbg) fprintf(tr->dbg, "  subsurface: no exit found by the probe\n");
        return 0;
    }
    tr->cnt->rays += (uint64_t)ex.rays;
    for (j = 0; j < HERO_N; j++) {                                  /* (43) */
        nb[j] = (double)path->beta[j] * ex.Sp[j] / ex.pdf[0];
        nr[j] = (double)path->r[j] * ex.pdf[j] / ex.pdf[0];
    }
    lanes_update(path, nb, nr);
    if (tr->dbg) fprintf(tr->dbg, "  subsurface: exit 1 of %d at x=(%.4g %.4g %.4g)\n", ex.n,
                         ex.sp.p.x, ex.sp.p.y, ex.sp.p.z);
    sw.type = MAT_SUBSURFACE_EXIT;
    sw.bump = NULL;
    vertex_ctx(R, path, ex.sp.p, ex.sp.ns, &ctx);
    if (can_nee) {
        Scatter v;
        v.mat = &sw;
        v.sp = &ex.sp;
        v.p = ex.sp.p;
        v.wo = ex.sp.ns;                     /* Sw's outgoing side: the exit's normal */
        v.g = 0.0f;
        v.medium = path->medium;
        v.ctx = &ctx;
        v.eq = NULL;
        v.equi = 0;
        next_event(tr, depth, d0, &v, path);
    }
    sampler_2d(tr->ps, d0 + BD_DIR, &u[0], &u[1]);
    if (!bsdf_sample(&sw, &ex.sp, ex.sp.ns, path->lam, path->alive, 0.0f, u[0], u[1], &bs)) return 0;
    prev_set(path, can_nee, &ctx, ex.sp.p, bs.pdf_l, NULL);
    path->any_nonspec = 1;
    cos_i = fabsf(v3_dot(bs.wi, ex.sp.ns));
    for (j = 0; j < HERO_N; j++) {
        nb[j] = (double)path->beta[j] * (bs.f[j] * cos_i / bs.pdf);
        nr[j] = path->r[j];
        path->eta2[j] /= mat->sss->eta * mat->sss->eta;   /* (44)'s eta^2 is back in beta */
    }
    lanes_update(path, nb, nr);
    if (R->vol) path->medium = medium_after(s, ex.sp.shape, path->medium, bs.wi, ex.sp.ng);
    ray->o = spawn_origin(&ex.sp, bs.wi);
    ray->d = bs.wi;
    ray->tmax = INFINITY;
    return 1;
}

/* 5. The lobe number of a smooth dielectric (THEORY §8.1).  Its choice between
   reflection (probability F) and refraction is the only random decision there,
   and a chain of them (into a glass sphere, back and forth inside it, out) picks
   one of many specular paths: the pixel's value is a sum over these chains, each
   with its probability.  Drawing every choice from its own dimension stratifies
   only the first one over the pixel's samples; the others pair at random.  Yet
   given the first choice, u0 / F (reflected) or (u0 - F) / (1 - F) (refracted) is
   again uniform on [0, 1) and independent of that choice, so it can make the next
   choice, and so on: the whole chain then comes from ONE stratified number, and
   the samples of a pixel visit the chains in proportion to their probabilities,
   instead of at random.  Unbiased: every choice still sees a uniform number
   independent of everything before it.  The number holds 24 bits; once the chosen
   probabilities multiply to less than LOBE_REUSE_MIN its steps would grow
   coarse, and the next choice takes its own dimension again.
   lobe_number returns the number the vertex uses (fresh, its own dimension, or
   the carried one) and the product *w it continues from; lobe_next keeps the
   rescaled number after a smooth dielectric's choice.  Other materials neither
   spend nor end it. */
static float lobe_number(const Material *mat, float fresh, PathState *path, double *w)
{
    *w = 1.0;
    if (mat->type != MAT_DIELECTRIC || !mat_is_delta(mat) || !(path->lobe_w > 0.0)) return fresh;
    *w = path->lobe_w;
    path->lobe_w = 0.0;                           /* spent */
    return path->lobe_u;
}

static void lobe_next(const Material *mat, const BsdfSample *bs, double w, PathState *path)
{
    if (mat->type != MAT_DIELECTRIC || !(bs->u_lobe >= 0.0f)) return;
    w *= bs->pdf;                                 /* the chosen lobe's probability */
    path->lobe_u = bs->u_lobe;
    path->lobe_w = w >= LOBE_REUSE_MIN ? w : 0.0;
}

/* A surface vertex at sp, reached along ray: the emission the path found there,
   then below maxdepth the termination of the secondaries at dispersive glass
   (3), the fluorescent branch (fluor_vertex), NEE (4) and the next direction
   from the BSDF with the hero's index (5).  Returns 0 when the path ends;
   otherwise ray leaves the vertex (the counterpart of medium_vertex). */
static int surface_vertex(Tracer *tr, int depth, Ray *ray, const SurfacePoint *sp,
                          const HitRecord *hit, PathState *path)
{
    const Renderer *R = tr->R;
    const Scene *s = R->s;
    const RenderOptions *o = R->o;
    const Shape *shape = &s->shapes[sp->shape];
    Vec3 dir = v3_norm(ray->d), wo = v3_neg(dir), lp;
    int mi = mat_choose(s->materials, shape->material, sp, wo);   /* a mix: one of its two */
    const Material *mat = &s->materials[mi];
    Material reg;
    double nb[HERO_N], nr[HERO_N];
    LightCtx ctx;
    BsdfSample bs;
    SurfacePoint bumped, framed;
    float u0, u1, u2, cos_i;
    double lobe_w;
    int j;
    if (tr->dbg) debug_vertex(tr->dbg, depth, sp, path->beta, path->alive, path->r);
    /* Integrator "bool regularize" (pbrt-v4's, biased by design; THEORY §15): after
       a non-specular bounce the BSDF's microfacet alphas are widened */
    if (s->settings.regularize && path->any_nonspec && mat_regularized(mat, &reg)) mat = &reg;

    /* 2. Emission found by the path, weighted against NEE from prev */
    if (shape->emitter >= 0) film_add(tr->fs, emitter_found(tr, path, shape->emitter, sp, dir));
    if (depth >= o->maxdepth) return 0;
    if (mat->bump) sp = bump_shade(s, mat, ray, hit, sp, &bumped);  /* bump.c: ns perturbed */
    if (mat->type == MAT_HAIR) sp = hair_shade(s, ray, hit, sp, &bumped);  /* the fibre's axis */
    if (mat_needs_tangent(mat) && !mat->bump)
        sp = tangent_shade(s, ray, hit, sp, &framed);        /* bump.c: dp/du (bump_shade's) */

    /* 3. Termination of the secondary wavelengths at a dispersive dielectric,
          before NEE at this vertex (pbrt-v4 TerminateSecondary; THEORY §7) */
    if (mat->type == MAT_DIELECTRIC && mat->dispersive && path->alive != 1u &&
        (mat->alpha == 0.0f || !o->rough_mis)) {
        lanes_hero_only(path);
        if (tr->dbg) fprintf(tr->dbg, "  dispersive: secondaries terminated, hero %.1f nm continues\n",
                             tr->fs->wl.lambda[0]);
    }
    if ((mat->type == MAT_COATED_DIFFUSE || mat->type == MAT_COATED_CONDUCTOR) && mat->dispersive &&
        path->alive != 1u)
        lanes_hero_only(path);                   /* layered.c: the coat's index at the hero's */
    if (mat->type == MAT_FLUORESCENT && !(mat = fluor_vertex(tr, depth, mat, mi, path)))
        return 0;

    /* 4. Next event estimation: choose an emitter, sample a point on it, from
          light_origin (the hit, or pbrt-v4's nudge of a curve hit) */
    lp = light_origin(mat, sp, wo);
    vertex_ctx(R, path, lp, sp->ns, &ctx);
    if (o->nee && !mat_is_delta(mat) && s->n_emitters > 0) {
        Scatter v;
        v.mat = mat;
        v.sp = sp;
        v.p = lp;
        v.wo = wo;
        v.g = 0.0f;
        v.medium = path->medium;
        v.ctx = &ctx;
        v.eq = NULL;
        v.equi = 0;
        next_event(tr, depth, dim_bounce(depth, 0), &v, path);
    }

    /* 5. BSDF sampling: the next direction, with the hero's index; every lane's
          throughput gains f_j |cos| / q_bsdf(0) (delta lobes: f holds 1/|cos|),
          its ratio q_bsdf(j) / q_bsdf(0) (THEORY (5)) */
    u0 = lobe_number(mat, sampler_1d(tr->ps, dim_bounce(depth, BD_LOBE)), path, &lobe_w);
    sampler_2d(tr->ps, dim_bounce(depth, BD_DIR), &u1, &u2);
    if (!bsdf_sample(mat, sp, wo, path->lam, path->alive, u0, u1, u2, &bs)) return 0;
    lobe_next(mat, &bs, lobe_w, path);
    prev_set(path, o->nee && !bs.delta && s->n_emitters > 0, &ctx, lp, bs.pdf_l, NULL);
    if (!bs.delta) path->any_nonspec = 1;
    cos_i = fabsf(v3_dot(bs.wi, sp->ns));
    for (j = 0; j < HERO_N; j++) {
        nb[j] = (double)path->beta[j] * (bs.f[j] * cos_i / bs.pdf);
        nr[j] = (double)path->r[j] * (bs.pdf_l[j] / bs.pdf);
        path->eta2[j] *= bs.eta2[j];
    }
    lanes_update(path, nb, nr);
    if (mat->type == MAT_SUBSURFACE && !s->settings.sss_ignored &&
        v3_dot(bs.wi, sp->ns) * v3_dot(wo, sp->ns) < 0.0f)
        return subsurface_exit(tr, depth, ray, sp, mat, shape->material, path);   /* refracted in */
    if (R->vol) path->medium = medium_after(s, sp->shape, path->medium, bs.wi, sp->ng);
    ray->o = spawn_origin(sp, bs.wi);
    ray->d = bs.wi;
    ray->tmax = INFINITY;
    return 1;
}

/* ------------------------------------------------------------------ the loop */

/* Where the next stretch of the path ends (next_vertex). */
enum { AT_SURFACE, AT_COLLISION, ESCAPED, LOST };

/* 1. The next vertex along ray: the closest surface (*sp), unless the ray collides
      in its medium first (*c; THEORY (16)).  Surfaces of Material "interface"
      only bound media: the ray crosses them (pbrt-v4's SkipIntersection), in
      "volpath" into the medium on their other side, in "path" as a specular
      bounce (no MIS weight at the emitter it may then find).  LOST: more
      boundaries than MEDIUM_SEGMENTS in a row. */
static int next_vertex(Tracer *tr, int depth, Ray *ray, PathState *path, SurfacePoint *sp,
                       HitRecord *hit, Collision *c)
{
    const Renderer *R = tr->R;
    const Scene *s = R->s;
    int seg;
    for (seg = 0;; seg++) {
        int found;
        tr->cnt->rays++;
        found = bvh_intersect(&s->bvh, s, ray, hit);
        if (path->medium >= 0 && medium_flight(tr, dim_medium(depth, seg), depth, ray, found ? hit->t : INFINITY, path, c))
            return AT_COLLISION;
        if (!found) return ESCAPED;
        scene_surface_point(s, ray, hit, sp);
        if (s->materials[s->shapes[sp->shape].material].type != MAT_INTERFACE) return AT_SURFACE;
        if (seg + 1 >= MEDIUM_SEGMENTS) return LOST;
        if (path->medium >= 0 || R->vol) path->medium = medium_after(s, sp->shape, path->medium, ray->d, sp->ng);
        else path->prev.can_nee = 0;
        if (tr->dbg) fprintf(tr->dbg, "  crossed a medium boundary (shape %d)%s\n", sp->shape,
                             R->vol ? "" : ": media are ignored by this integrator");
        ray->o = spawn_origin(sp, ray->d);
        ray->tmax = INFINITY;
    }
}

/* The lanes of a new camera path, and the film's colour matching at its
   wavelengths. */
static void path_start(const Renderer *R, FilmSample *fs, PathState *path)
{
    int j;
    memset(path, 0, sizeof *path);
    path->alive = R->o->single_wavelength ? 1u : (1u << HERO_N) - 1u;
    path->medium = R->vol ? R->s->settings.camera_medium : -1;
    for (j = 0; j < HERO_N; j++) {
        sensor_response(R->s->settings.sensor, fs->wl.lambda[j], fs->cmf[j]);
        path->lam[j] = fs->wl.lambda[j];
        path->beta[j] = (path->alive & (1u << j)) ? 1.0f : 0.0f;
        path->r[j] = (path->alive & (1u << j)) ? 1.0f : 0.0f;
        path->eta2[j] = 1.0f;
        path->prev.q_bsdf[j] = 1.0f;
        path->prev.r[j] = path->r[j];
        path->prev.T[j] = path->prev.A[j] = 1.0;
    }
    path->prev.alive = path->alive;
    fs->xyz[0] = fs->xyz[1] = fs->xyz[2] = 0.0;
    for (j = 0; j < HERO_N; j++) fs->lane[j] = 0.0;
}

void trace_path(const Renderer *R, Ray ray, FilmSample *fs, PixelSample *ps, Counters *cnt, FILE *dbg)
{
    Tracer tr;
    PathState path;
    int depth;
    tr.R = R;
    tr.ps = ps;
    tr.fs = fs;
    tr.cnt = cnt;
    tr.dbg = dbg;
    tr.time = ray.time;
    tr.media.medium = -1;
    path_start(R, fs, &path);
    if (dbg) fprintf(dbg, "sample: lambda=(%.1f %.1f %.1f %.1f) nm pdf=(%.4g %.4g %.4g %.4g)\n",
                     fs->wl.lambda[0], fs->wl.lambda[1], fs->wl.lambda[2], fs->wl.lambda[3],
                     fs->wl.pdf[0], fs->wl.pdf[1], fs->wl.pdf[2], fs->wl.pdf[3]);
    for (depth = 0;; depth++) {
        SurfacePoint sp;
        HitRecord hit;
        Collision c;
        int i, at = next_vertex(&tr, depth, &ray, &path, &sp, &hit, &c);
        if (at == ESCAPED) {          /* the infinite lights the ray sees (a portal light: through its portal) */
            Vec3 dir = v3_norm(ray.d);
            for (i = 0; i < R->n_inf; i++)
                if (inf_sees(&R->s->emitters[R->inf[i]], ray.o, dir))
                    film_add(fs, emitter_found(&tr, &path, R->inf[i], NULL, dir));
            if (dbg && R->n_inf == 0) fprintf(dbg, "  escaped\n");
            return;
        }
        if (at == LOST) return;
        if (at == AT_COLLISION ? !medium_vertex(&tr, depth, &ray, &c, &path)
                               : !surface_vertex(&tr, depth, &ray, &sp, &hit, &path))
            return;
        /* 6. Russian roulette on a hero-independent throughput */
        if (!russian_roulette(&tr, depth, &path)) return;
    }
}
