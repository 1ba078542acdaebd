/* motion.c - motion blur: a transform that moves between two times (pbrt-v4's
   ActiveTransform, TransformTimes and AnimatedTransform).

   WHAT IT IMPLEMENTS (specnee.h section 5, "Motion")
     motion_init      the two ends taken apart into translation, rotation, the rest
     motion_at        the transform at a time
     motion_bounds    a box that holds a moving box over the whole motion
     xf_differ        whether two transforms differ (a shape moves or not)
     instance_xf      an instance's placement M for a ray: its own, or a moving
                      one's at the ray's time
     instance_ray,    the ray in the instance's object space, and a hit point found
     instance_point   there put back into the world (instance.c: RAYS AND HITS;
                      bvh.c's traversal and hitpoint.c's scene_surface_point call them)
   USE: scene.c keeps two CTMs, the start and the end one; `ActiveTransform
   StartTime`, `EndTime` and `All` choose which of them the transform directives
   change.  A shape whose two CTMs differ is made in its own space (CTM = identity;
   geometry.c moving_shape)
   as an unnamed object, placed by a moving Instance (instance.c; an ObjectInstance
   under two CTMs moves the same way), whose box is motion_bounds'.  bvh.c carries a
   ray into an instance's space with instance_xf (motion_at of the ray's time for a
   moving one) and instance_ray, both below.  The camera moves
   with its two CTMs the same way (camera.c).  render.c draws each camera sample's
   time from the sampler's own dimension DIM_TIME, uniform in [shutteropen,
   shutterclose], only when something moves; every ray of that path, shadow rays
   included, keeps the time (Ray.time).

   THE DECOMPOSITION (Shoemake and Duff 1992, pbrt-v4's Transform::Decompose)
     M = T R S: T is M's last column; A, the upper 3x3 block, is split by the polar
     decomposition A = R S with R orthogonal: R_0 = A, R_{k+1} = (R_k + R_k^-T) / 2
     converges to R (Newton's iteration, Higham 1986); S = R^T A.  R becomes a unit
     quaternion q.  A mirroring A (det < 0) has no rotation R with det R = +1 and
     pbrt-v4 leaves the case open: it is refused, as a projective M is.

   INTERPOLATION at time t, with u = (t - t0) / (t1 - t0) inside (t0, t1):
         T(u) = (1 - u) T0 + u T1,   S(u) = (1 - u) S0 + u S1,
         q(u) = slerp(q0, q1, u) = [sin((1 - u) theta) q0 + sin(u theta) q1] / sin theta,
     cos theta = q0 . q1 >= 0 (q1 negated otherwise: the shorter way round), and
     M(u) = T(u) R(q(u)) S(u).  Slerp is q0 (q0^-1 q1)^u: R(u) = R0 Rot(a, 2 theta u),
     the start rotation followed by a turn about one fixed axis a at a constant rate.
     For t <= t0 the start transform itself, for t >= t1 the end one.

   MOTION BOUNDS.  The box of an affinely mapped box is the box of its mapped
   corners, so it is enough to bound each corner's path p(u) = T(u) + R(u) S(u) c
   over u in [0, 1].  With w(u) = S(u) c (a line in u) and phi = 2 theta,
         p''(u) = R0 [phi^2 K^2 Rot w + 2 phi K Rot w'],  K = the cross product with a,
     so |p''| <= M = phi^2 max(|w(0)|, |w(1)|) + 2 phi |w(1) - w(0)| (|K v| <= |v|;
     T and S are linear: no second derivative).  A function f with |f''| <= M lies
     within M h^2 / 8 above the chord through its values at the ends of an interval
     of length h, so the corners at u = i / N, i = 0..N, widened by M / (8 N^2),
     bound the path: tight to that margin (N = 64), and exact for translation and scale.
     instance.c then rounds the box outwards as it does a fixed instance's. */
#include "specnee.h"
#include <float.h>
#include <string.h>

#define MOTION_BOUND_STEPS 64   /* @@ samples of each corner's path: load time vs. the margin M / 32768 */

/* By value, as pbrt-v4's Transform::operator!= (0 and -0 are equal). */
int xf_differ(const Xform *a, const Xform *b)
{
    int i, j;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            if (a->m[i][j] != b->m[i][j] || a->inv[i][j] != b->inv[i][j]) return 1;
    return 0;
}

static double det3(double a[3][3])
{
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
         - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
         + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* The inverse transpose of a (det != 0) by cofactors (no const: C99 cannot pass
   a const 2-D array). */
static void inv_transpose3(double a[3][3], double out[3][3])
{
    const double d = det3(a);
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            out[i][j] = (a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]) / d;
        }
}

/* Shoemake's rotation matrix to unit quaternion (w, x, y, z), p' = R p. */
static void quat_from_matrix(double r[3][3], double q[4])
{
    const double tr = r[0][0] + r[1][1] + r[2][2];
    double n;
    int k;
    if (tr > 0.0) {
        const double s = 2.0 * sqrt(tr + 1.0);
        q[0] = 0.25 * s;
        q[1] = (r[2][1] - r[1][2]) / s;
        q[2] = (r[0][2] - r[2][0]) / s;
        q[3] = (r[1][0] - r[0][1]) / s;
    } else {
        const int i = r[1][1] > r[0][0] ? (r[2][2] > r[1][1] ? 2 : 1) : (r[2][2] > r[0][0] ? 2 : 0);
        const int j = (i + 1) % 3, l = (i + 2) % 3;
        const double s = 2.0 * sqrt(1.0 + r[i][i] - r[j][j] - r[l][l]);
        q[1 + i] = 0.25 * s;
        q[1 + j] = (r[j][i] + r[i][j]) / s;
        q[1 + l] = (r[l][i] + r[i][l]) / s;
        q[0] = (r[l][j] - r[j][l]) / s;
    }
    n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (k = 0; k < 4; k++) q[k] /= n;
}

/* The rotation matrix of the unit quaternion q = (w, x, y, z). */
static void matrix_from_quat(const double q[4], double r[3][3])
{
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    r[0][0] = 1 - 2 * (y * y + z * z); r[0][1] = 2 * (x * y - w * z);     r[0][2] = 2 * (x * z + w * y);
    r[1][0] = 2 * (x * y + w * z);     r[1][1] = 1 - 2 * (x * x + z * z); r[1][2] = 2 * (y * z - w * x);
    r[2][0] = 2 * (x * z - w * y);     r[2][1] = 2 * (y * z + w * x);     r[2][2] = 1 - 2 * (x * x + y * y);
}

/* M = T R S (THE DECOMPOSITION); 0 for a projective or mirroring M. */
static int decompose(const Xform *x, double T[3], double q[4], double S[3][3])
{
    const double (*m)[4] = (const double (*)[4])x->m;
    double A[3][3], R[3][3], Rit[3][3];
    int i, j, k, it;
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0) return 0;
    for (i = 0; i < 3; i++) {
        T[i] = m[i][3];
        for (j = 0; j < 3; j++) A[i][j] = R[i][j] = m[i][j];
    }
    if (!(det3(A) > 0.0)) return 0;
    for (it = 0; it < 100; it++) {
        double norm = 0.0;
        inv_transpose3(R, Rit);
        for (i = 0; i < 3; i++) {
            double row = 0.0;
            for (j = 0; j < 3; j++) {
                const double next = 0.5 * (R[i][j] + Rit[i][j]);
                row += fabs(next - R[i][j]);
                R[i][j] = next;
            }
            if (row > norm) norm = row;
        }
        if (norm <= 1e-15) break;
    }
    for (i = 0; i < 3; i++)                               /* S = R^T A */
        for (j = 0; j < 3; j++) {
            S[i][j] = 0.0;
            for (k = 0; k < 3; k++) S[i][j] += R[k][i] * A[k][j];
        }
    quat_from_matrix(R, q);
    return 1;
}

int motion_init(Motion *m, const Xform *start, double t0, const Xform *end, double t1)
{
    double d = 0.0;
    int k;
    memset(m, 0, sizeof *m);
    m->t0 = t0;
    m->t1 = t1;
    m->start = *start;
    m->end = *end;
    if (!decompose(start, m->T[0], m->q[0], m->S[0]) || !decompose(end, m->T[1], m->q[1], m->S[1]))
        return 0;
    for (k = 0; k < 4; k++) d += m->q[0][k] * m->q[1][k];
    if (d < 0.0) {                                        /* the shorter way round */
        for (k = 0; k < 4; k++) m->q[1][k] = -m->q[1][k];
        d = -d;
    }
    m->theta = acos(d < 1.0 ? d : 1.0);
    return 1;
}

/* sin(x) / x, exact near 0 */
static double sinc(double x)
{
    return fabs(x) < 1e-4 ? 1.0 - x * x / 6.0 : sin(x) / x;
}

/* The parts at u in [0, 1]: T(u), R(q(u)) and S(u) as the 3x4 matrix T + R S. */
static void motion_matrix(const Motion *m, double u, double out[3][4])
{
    const double th = m->theta, s = sinc(th);
    const double w0 = (1.0 - u) * sinc((1.0 - u) * th) / s, w1 = u * sinc(u * th) / s;
    double q[4], n = 0.0, R[3][3];
    int i, j, k;
    for (k = 0; k < 4; k++) { q[k] = w0 * m->q[0][k] + w1 * m->q[1][k]; n += q[k] * q[k]; }
    n = sqrt(n);
    for (k = 0; k < 4; k++) q[k] /= n;
    matrix_from_quat(q, R);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double v = 0.0;
            for (k = 0; k < 3; k++) v += R[i][k] * ((1.0 - u) * m->S[0][k][j] + u * m->S[1][k][j]);
            out[i][j] = v;
        }
        out[i][3] = (1.0 - u) * m->T[0][i] + u * m->T[1][i];
    }
}

void motion_at(const Motion *m, double time, Xform *out)
{
    double a[3][4], A[3][3], Ait[3][3];
    int i, j;
    if (time <= m->t0) { *out = m->start; return; }
    if (time >= m->t1) { *out = m->end; return; }
    motion_matrix(m, (time - m->t0) / (m->t1 - m->t0), a);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) A[i][j] = a[i][j];
    inv_transpose3(A, Ait);                              /* (T A)^-1 = A^-1 (-T) */
    memset(out, 0, sizeof *out);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 4; j++) out->m[i][j] = a[i][j];
        for (j = 0; j < 3; j++) out->inv[i][j] = Ait[j][i];
        out->inv[i][3] = -(Ait[0][i] * a[0][3] + Ait[1][i] * a[1][3] + Ait[2][i] * a[2][3]);
    }
    out->m[3][3] = out->inv[3][3] = 1.0;
}

/* |v| of a 3-vector */
static double len3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

void motion_bounds(const Motion *m, const double lo[3], const double hi[3], double wlo[3], double whi[3])
{
    const double phi = 2.0 * m->theta;
    int c, i, a, b;
    for (a = 0; a < 3; a++) { wlo[a] = DBL_MAX; whi[a] = -DBL_MAX; }
    for (c = 0; c < 8; c++) {
        const double p[3] = { (c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2] };
        double w0[3], w1[3], dw[3], M, margin;
        for (a = 0; a < 3; a++) {
            w0[a] = m->S[0][a][0] * p[0] + m->S[0][a][1] * p[1] + m->S[0][a][2] * p[2];
            w1[a] = m->S[1][a][0] * p[0] + m->S[1][a][1] * p[1] + m->S[1][a][2] * p[2];
            dw[a] = w1[a] - w0[a];
        }
        M = phi * phi * fmax(len3(w0), len3(w1)) + 2.0 * phi * len3(dw);
        margin = M / (8.0 * MOTION_BOUND_STEPS * MOTION_BOUND_STEPS);
        for (i = 0; i <= MOTION_BOUND_STEPS + 2; i++) {
            double x[3][4];
            if (i <= MOTION_BOUND_STEPS) motion_matrix(m, (double)i / MOTION_BOUND_STEPS, x);
            else {                                    /* the two ends exactly as given */
                const Xform *e = i == MOTION_BOUND_STEPS + 1 ? &m->start : &m->end;
                for (a = 0; a < 3; a++) for (b = 0; b < 4; b++) x[a][b] = e->m[a][b];
            }
            for (a = 0; a < 3; a++) {
                const double v = x[a][0] * p[0] + x[a][1] * p[1] + x[a][2] * p[2] + x[a][3];
                const double r = 1e-12 * (fabs(v) + len3(p));     /* the rounding of x */
                if (v - margin - r < wlo[a]) wlo[a] = v - margin - r;
                if (v + margin + r > whi[a]) whi[a] = v + margin + r;
            }
        }
    }
}

/* ======================================================================
   An instance's placement applied to rays and hit points
   ====================================================================== */
/* Instance in's M for ray r: its own, or a moving one's at the ray's time
   (motion_at; *tmp holds it then). */
const Xform *instance_xf(const Scene *s, const Instance *in, const Ray *r, Xform *tmp)
{
    if (in->motion <= 0) return &in->world_from_obj;
    motion_at(&s->motions[in->motion - 1], r->time, tmp);
    return tmp;
}

/* The world ray r in the object space of an instance placed by M = *x: o' = M^-1 o,
   d' = M^-1 d, the same t (d' is not normalised), tmax and time kept (instance.c:
   RAYS AND HITS). */
Ray instance_ray(const Xform *x, const Ray *r)
{
    const double (*inv)[4] = (const double (*)[4])x->inv;
    const double o[3] = { r->o.x, r->o.y, r->o.z }, d[3] = { r->d.x, r->d.y, r->d.z };
    float oo[3], dd[3];
    Ray ro;
    int a;
    for (a = 0; a < 3; a++) {
        oo[a] = (float)(inv[a][0] * o[0] + inv[a][1] * o[1] + inv[a][2] * o[2] + inv[a][3]);
        dd[a] = (float)(inv[a][0] * d[0] + inv[a][1] * d[1] + inv[a][2] * d[2]);
    }
    ro.o = v3(oo[0], oo[1], oo[2]);
    ro.d = v3(dd[0], dd[1], dd[2]);
    ro.tmax = r->tmax;
    ro.time = r->time;
    return ro;
}

/* n by M's inverse transpose, normalised (n itself when the result has no length). */
static Vec3 normal_to_world(const Xform *m, Vec3 n)
{
    Vec3 w = xf_normal(m, n);
    return v3_dot(w, w) > 0.0f ? v3_norm(w) : n;
}

/* A hit point computed in instance in's object space, put into the world: p by M,
   the normals by M^-T, the shading normal turned to the geometric one's side
   (pbrt-v4's Transform of a SurfaceInteraction; instance.c: RAYS AND HITS). */
void instance_point(const Xform *x, SurfacePoint *sp)
{
    sp->p = xf_point(x, sp->p);
    sp->ng = normal_to_world(x, sp->ng);
    sp->ns = normal_to_world(x, sp->ns);
    if (v3_dot(sp->ns, sp->ng) < 0.0f) sp->ns = v3_neg(sp->ns);   /* pbrt-v4: FaceForward */
    if (sp->err.x > 0.0f || sp->err.y > 0.0f || sp->err.z > 0.0f) {   /* |M| err */
        const double (*m)[4] = (const double (*)[4])x->m;
        float e[3];
        int a;
        for (a = 0; a < 3; a++)
            e[a] = (float)(fabs(m[a][0]) * sp->err.x + fabs(m[a][1]) * sp->err.y + fabs(m[a][2]) * sp->err.z);
        sp->err = v3(e[0], e[1], e[2]);
    }
}
