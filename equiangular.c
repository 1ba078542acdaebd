/* equiangular.c - equiangular distance sampling towards a lamp in a homogeneous
   medium (Kulla and Fajardo 2012, "Importance Sampling Techniques for Path
   Tracing in Participating Media", EGSR; THEORY §12.1 derives the estimator that
   uses it, path.c's equi_nee and the MIS weights of nee_sample / emitter_found).

   Exported (specnee.h section 6b): equi_segment, equi_sample, equi_pdf,
   equi_lamps_build, equi_lamp_of.

   THE DENSITY.  Light scattered towards the camera along a ray o + t d (d unit)
   from a small lamp at c falls off as 1 / |x(t) - c|^2.  With
       Delta = (c - o) . d      the distance along the ray to the point nearest c,
       D     = |o + Delta d - c| the distance of the ray from c,
   the squared distance is D^2 + (t - Delta)^2, and the angle under which x(t) is
   seen from c, theta(t) = atan((t - Delta) / D), has d theta / dt = D / (D^2 +
   (t - Delta)^2).  Drawing theta uniformly between theta_a = theta(0) and
   theta_b = theta(tmax) (pi / 2 for an unbounded ray) therefore gives t the
   density
       p_eq(t) = D / ((theta_b - theta_a) (D^2 + (t - Delta)^2)),  0 <= t <= tmax,   (18c)
   proportional to the lamp's 1 / r^2, and the inverse of the CDF is
       t = Delta + D tan(theta_a + u (theta_b - theta_a)).                          (18d)
   The density does not depend on the wavelength and is positive on the whole
   segment: as one technique of the MIS of THEORY §12.1 it keeps the estimate
   unbiased whatever the lamp's shape (c only steers the samples).  A ray through
   c itself (D = 0) has no such density; equi_segment refuses it.

   THE LAMPS.  equi_lamps_build lists the emitters the technique aims at: point and
   spot lights and whole spheres (an emitter NEE samples as one piece), with their
   centres, when the scene has at least 1 and at most EQUI_LAMPS_MAX of them; each
   is chosen with probability 1 / n. */
#include "specnee.h"
#include <math.h>

int equi_segment(Vec3 o, Vec3 d, float tmax, Vec3 c, EquiSeg *seg)
{
    Vec3 oc = v3_sub(c, o), near;
    double delta = (double)v3_dot(oc, d), D, ta, tb;
    near = v3_sub(v3_add(o, v3_mul(d, (float)delta)), c);
    D = sqrt((double)v3_dot(near, near));
    if (!(D > 1e-6 * (fabs(delta) + 1e-3))) return 0;    /* through c: no density */
    ta = atan(-delta / D);
    tb = isinf(tmax) ? 0.5 * SPECNEE_PI : atan(((double)tmax - delta) / D);
    if (!(tb > ta)) return 0;
    seg->delta = delta;
    seg->D = D;
    seg->theta_a = ta;
    seg->theta_b = tb;
    seg->tmax = tmax;
    return 1;
}

double equi_pdf(const EquiSeg *seg, double t)
{
    double x = t - seg->delta;
    if (!(t >= 0.0) || t > (double)seg->tmax) return 0.0;
    return seg->D / ((seg->theta_b - seg->theta_a) * (seg->D * seg->D + x * x));
}

double equi_sample(const EquiSeg *seg, double u, double *pdf)
{
    double th = seg->theta_a + u * (seg->theta_b - seg->theta_a), t;
    t = seg->delta + seg->D * tan(th);
    if (t < 0.0) t = 0.0;                    /* rounding at theta_a */
    if (t > (double)seg->tmax) t = (double)seg->tmax;
    *pdf = equi_pdf(seg, t);
    return t;
}

void equi_lamps_build(const Scene *s, const int *emitter_piece, EquiLamps *out)
{
    int e;
    out->n = 0;
    for (e = 0; e < s->n_emitters; e++) {
        const Emitter *em = &s->emitters[e];
        Vec3 c;
        if (em->delta.type == DELTA_POINT || em->delta.type == DELTA_SPOT) c = em->delta.p;
        else if (em->shape >= 0 && s->shapes[em->shape].type == SHAPE_SPHERE &&
                 !s->shapes[em->shape].in_object && emitter_piece[e] >= 0)
            c = s->shapes[em->shape].center;
        else continue;
        if (out->n == EQUI_LAMPS_MAX) { out->n = 0; return; }   /* too many: the technique is off */
        out->emitter[out->n] = e;
        out->center[out->n] = c;
        out->n++;
    }
}

int equi_lamp_of(const EquiLamps *L, int e)
{
    int i;
    for (i = 0; i < L->n; i++)
        if (L->emitter[i] == e) return i;
    return -1;
}
