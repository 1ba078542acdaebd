/* sphtri.c - sampling a spherical triangle: the directions a triangle lamp
   subtends, uniformly by solid angle or following the cosine at the receiver.

   Seen from a point x, a triangle v0 v1 v2 covers the spherical triangle whose
   vertices are the unit directions A, B, C towards v0, v1, v2.  Its solid angle is
   its spherical excess (Girard)
       Omega = alpha + beta + gamma - pi,
   alpha, beta, gamma its angles at A, B, C (the angles between the great circles
   that meet there); computed here as Van Oosterom and Strackee's
   2 atan(|A . (B x C)| / (1 + A.B + B.C + C.A)), the same number with one
   arctangent, stable for small triangles.  Arvo's map (J. Arvo, "Stratified sampling of spherical
   triangles", SIGGRAPH 1995) takes the unit square onto it with the constant
   Jacobian 1 / Omega, so that a uniform (u0, u1) gives a direction with the
   density 1 / Omega:
     - u0 picks the sub-triangle A B C' of area A' = u0 Omega, C' on the arc AC;
       with s = sin(A' - alpha), t = cos(A' - alpha), u = t - cos alpha,
       v = s + sin alpha cos c (cos c = A . B),
           cos b' = ((v t - u s) cos alpha - v) / ((v s + u t) sin alpha),
       and C' = cos b' A + sin b' (C - (C . A) A) / |...|;
     - u1 picks a point on the arc from B to C', uniform in 1 - cos of its angle
       from B: z = 1 - u1 (1 - C' . B), w = z B + sqrt(1 - z^2) (C' - (C' . B) B) / |...|.
   The map is one to one, and sph_tri_invert undoes it: C' is where the great
   circle through B and w meets the arc AC, u0 = area(A B C') / Omega and
   u1 = (1 - w . B) / (1 - C' . B).

   The cosine warp (pbrt-v4's "warp product"): at a surface point with shading
   normal n the light arrives weighted by |n . w|, which uniform solid angle
   ignores.  The square is first warped by the bilinear density whose corner
   values are the cosines at the directions the corners map to, max(0.01, |n . .|):
   (0, 0) and (1, 0) map to B, (0, 1) to A, (1, 1) to C.  The direction's density
   is then bilinear_pdf(u) / Omega, u = sph_tri_invert(w) (THEORY §5.6).  In a
   medium (n the zero vector) there is no cosine and no warp.

   lights.c asks tri_sample_sa / tri_pdf_sa for a triangle lamp's direction and
   density; they answer 0 when the solid angle lies outside
   [SPH_TRI_MIN, SPH_TRI_MAX] sr, where the geometry is unstable (a far, tiny
   triangle; or one that covers nearly a hemisphere) and the caller samples the
   triangle by area instead.  Everything here is computed in double. */
#include "specnee.h"

typedef struct { double x, y, z; } D3;

static D3 d3(Vec3 a) { D3 r; r.x = a.x; r.y = a.y; r.z = a.z; return r; }
static D3 d3_sub(D3 a, D3 b) { D3 r; r.x = a.x - b.x; r.y = a.y - b.y; r.z = a.z - b.z; return r; }
static D3 d3_add(D3 a, D3 b) { D3 r; r.x = a.x + b.x; r.y = a.y + b.y; r.z = a.z + b.z; return r; }
static D3 d3_mul(D3 a, double k) { D3 r; r.x = a.x * k; r.y = a.y * k; r.z = a.z * k; return r; }
static double d3_dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static D3 d3_cross(D3 a, D3 b)
{
    D3 r;
    r.x = a.y * b.z - a.z * b.y;
    r.y = a.z * b.x - a.x * b.z;
    r.z = a.x * b.y - a.y * b.x;
    return r;
}
/* a / |a|; 0 when a is the zero vector */
static int d3_unit(D3 a, D3 *out)
{
    double l2 = d3_dot(a, a), k;
    if (!(l2 > 0.0) || !isfinite(l2)) return 0;
    k = 1.0 / sqrt(l2);
    *out = d3_mul(a, k);
    return 1;
}
/* The unit vector in the plane of a and b, perpendicular to a (unit), on b's side;
   0 when b is parallel to a. */
static int d3_perp(D3 b, D3 a, D3 *out)
{
    return d3_unit(d3_sub(b, d3_mul(a, d3_dot(b, a))), out);
}
static Vec3 d3_vec(D3 a) { return v3((float)a.x, (float)a.y, (float)a.z); }

/* The solid angle of the spherical triangle of unit vectors a, b, c (Van Oosterom
   and Strackee 1983, equal to Girard's excess and stable for small ones):
   tan(Omega / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a). */
static double solid_angle(D3 a, D3 b, D3 c)
{
    return 2.0 * atan2(fabs(d3_dot(a, d3_cross(b, c))), 1.0 + d3_dot(a, b) + d3_dot(b, c) + d3_dot(c, a));
}

/* The spherical triangle seen from ref; 0 when a vertex is at ref or it is
   degenerate (ref in its plane, or on the line of two vertices).  The angle alpha
   at A is that between the planes (A, B) and (A, C), whose normals' cross product
   is A (A . (B x C)) and dot product B.C - (A.B)(A.C), each over |A x B| |A x C|
   = sqrt((1 - (A.B)^2) (1 - (A.C)^2)): Arvo's map needs only its cosine and sine. */
int sph_tri_setup(Vec3 ref, Vec3 v0, Vec3 v1, Vec3 v2, SphTri *t)
{
    D3 r = d3(ref), A, B, C, E;
    double ab, ac, den;
    if (!d3_unit(d3_sub(d3(v0), r), &A) || !d3_unit(d3_sub(d3(v1), r), &B) ||
        !d3_unit(d3_sub(d3(v2), r), &C))
        return 0;
    ab = d3_dot(A, B);
    ac = d3_dot(A, C);
    den = (1.0 - ab * ab) * (1.0 - ac * ac);
    if (!(den > 0.0)) return 0;
    den = 1.0 / sqrt(den);
    t->a[0] = A.x; t->a[1] = A.y; t->a[2] = A.z;
    t->b[0] = B.x; t->b[1] = B.y; t->b[2] = B.z;
    t->c[0] = C.x; t->c[1] = C.y; t->c[2] = C.z;
    if (!d3_perp(C, A, &E)) return 0;        /* the arc AC's direction at A */
    t->e[0] = E.x; t->e[1] = E.y; t->e[2] = E.z;
    t->cos_alpha = (d3_dot(B, C) - ab * ac) * den;
    t->sin_alpha = fabs(d3_dot(A, d3_cross(B, C))) * den;
    t->area = solid_angle(A, B, C);
    return t->area > 0.0 && t->sin_alpha > 0.0;
}

static D3 tri_vertex(const double *v) { D3 r; r.x = v[0]; r.y = v[1]; r.z = v[2]; return r; }

/* Arvo's map: (u0, u1) in [0, 1]^2 -> a unit direction in the triangle.  With
   A' = u0 Omega: sin(A' - alpha) and cos(A' - alpha) by the angle difference. */
Vec3 sph_tri_sample(const SphTri *t, double u0, double u1)
{
    D3 A = tri_vertex(t->a), B = tri_vertex(t->b), Cp, e, w;
    double Ap = u0 * t->area, ca = t->cos_alpha, sa = t->sin_alpha;
    double sA = sin(Ap), cA = cos(Ap);
    double s = sA * ca - cA * sa, c = cA * ca + sA * sa;
    double u = c - ca, v = s + sa * d3_dot(A, B);
    double den = (v * s + u * c) * sa, q, z;
    q = den != 0.0 ? ((v * c - u * s) * ca - v) / den : 1.0;
    q = q > 1.0 ? 1.0 : (q < -1.0 ? -1.0 : q);                             /* cos b' */
    Cp = d3_add(d3_mul(A, q), d3_mul(tri_vertex(t->e), sqrt(1.0 - q * q)));
    z = 1.0 - u1 * (1.0 - d3_dot(Cp, B));
    z = z > 1.0 ? 1.0 : (z < -1.0 ? -1.0 : z);
    w = B;
    if (d3_perp(Cp, B, &e)) w = d3_add(d3_mul(B, z), d3_mul(e, sqrt(1.0 - z * z)));
    return d3_vec(w);
}

/* The (u0, u1) that sph_tri_sample maps to the unit direction w (w inside the
   triangle); both clamped to [0, 1].  0 when w lies along B (u0 is then free). */
int sph_tri_invert(const SphTri *t, Vec3 wv, double *u0, double *u1)
{
    D3 A = tri_vertex(t->a), B = tri_vertex(t->b), C = tri_vertex(t->c), w = d3(wv), Cp;
    double den, x, y;
    if (!d3_unit(w, &w)) return 0;
    /* C': on the great circle through B and w, and on the one through A and C */
    if (!d3_unit(d3_cross(d3_cross(B, w), d3_cross(C, A)), &Cp)) return 0;
    if (d3_dot(Cp, d3_add(A, C)) < 0.0) Cp = d3_mul(Cp, -1.0);
    x = solid_angle(A, B, Cp) / t->area;                    /* area(A B C') / Omega */
    den = 1.0 - d3_dot(Cp, B);
    y = den > 0.0 ? (1.0 - d3_dot(w, B)) / den : 0.0;
    *u0 = x > 1.0 ? 1.0 : (x > 0.0 ? x : 0.0);
    *u1 = y > 1.0 ? 1.0 : (y > 0.0 ? y : 0.0);
    return 1;
}

/* ------------------------------------------------------------------ the bilinear warp */

/* density 2 ((1 - x) a + x b) / (a + b) on [0, 1]: the x with CDF u,
   u (a + b) / (a + sqrt((1 - u) a^2 + u b^2)) (the root without cancellation) */
static double sample_linear(double u, double a, double b)
{
    double den = a + sqrt((1.0 - u) * a * a + u * b * b), x;
    if (!(den > 0.0)) return u;
    x = u * (a + b) / den;
    return x < 1.0 ? x : 1.0;
}

double bilinear_pdf(const double w[4], double x, double y)
{
    double sum = w[0] + w[1] + w[2] + w[3];
    if (x < 0.0 || x > 1.0 || y < 0.0 || y > 1.0) return 0.0;
    if (!(sum > 0.0)) return 1.0;
    return 4.0 * ((1.0 - x) * (1.0 - y) * w[0] + x * (1.0 - y) * w[1] +
                  (1.0 - x) * y * w[2] + x * y * w[3]) / sum;
}

void bilinear_sample(const double w[4], double u0, double u1, double *x, double *y)
{
    /* y by its marginal (linear in y), then x given y (linear in x) */
    *y = sample_linear(u1, w[0] + w[1], w[2] + w[3]);
    *x = sample_linear(u0, (1.0 - *y) * w[0] + *y * w[2], (1.0 - *y) * w[1] + *y * w[3]);
}

/* the warp's corner weights: max(0.01, |n . direction|) at B, B, A, C */
static void warp_weights(const SphTri *t, Vec3 n, double w[4])
{
    D3 N = d3(n);
    double cb = fabs(d3_dot(N, tri_vertex(t->b))), ca = fabs(d3_dot(N, tri_vertex(t->a)));
    double cc = fabs(d3_dot(N, tri_vertex(t->c)));
    w[0] = w[1] = cb > 0.01 ? cb : 0.01;
    w[2] = ca > 0.01 ? ca : 0.01;
    w[3] = cc > 0.01 ? cc : 0.01;
}

static int has_normal(Vec3 n) { return n.x != 0.0f || n.y != 0.0f || n.z != 0.0f; }

/* ------------------------------------------------------------------ a triangle lamp */

/* --light-shape-sampling auto: does the solid-angle map pay for this triangle?
   Sampled uniformly by area, the triangle gives the estimate f A cos_y / d^2 of
   the light arriving at ref; for a diffuse receiver f carries the receiver's
   cosine |n . w|, so the estimate is proportional to
       g = |n . w| cos_y / d^2 = |n . D| h / |D|^4      (D = p - ref, |D| = d),
   h = cos_y d the distance of ref to the triangle's plane, the same for every
   point p of it.  Where g hardly changes over the triangle, area sampling's
   estimate is nearly constant already, and the solid-angle map (whose warped
   estimate is nearly constant everywhere) buys little for its cost; where g
   spreads widely (a lamp close to the receiver, large in its sky, or low over its
   horizon) the map removes that spread.  The rule: g at the three vertices and
   the centroid (the centroid sees the near middle of a lamp right above ref),
   and the map where max g > SPH_TRI_SPREAD min g, which holds where one of
   them is 0 and another not (a vertex on ref's tangent plane: the lamp rises
   from the horizon); where all are 0 (ref in the lamp's own plane, as on the
   lamp's back: no light comes) the cheap area sample.  In a medium
   (n the zero vector) the phase function replaces the cosine: g = 1 / d^3.  No
   square root: some twenty multiplications and four divisions, against the map's
   arctangent, sine, cosine and ten square roots.  lights.c asks it at the sample and at the
   BSDF-hit pdf with the same (ref, n, v), so both see the same density. */
int tri_sa_pays(Vec3 ref, Vec3 n, const Vec3 v[3])
{
    int medium = !has_normal(n), i;
    double gmin = 0.0, gmax = 0.0;
    D3 p[4], N = d3(n);
    p[0] = d3(v[0]); p[1] = d3(v[1]); p[2] = d3(v[2]);
    p[3] = d3_mul(d3_add(d3_add(p[0], p[1]), p[2]), 1.0 / 3.0);
    for (i = 0; i < 4; i++) {
        D3 D = d3_sub(p[i], d3(ref));
        double d2 = d3_dot(D, D), c = medium ? 1.0 : fabs(d3_dot(N, D));
        /* medium: g d^3 = 1 compared as g^2 = 1 / d2^3 */
        double g = medium ? 1.0 / (d2 * d2 * d2) : c / (d2 * d2);
        if (!isfinite(g)) return 0;      /* ref on a vertex: the area sample refuses it */
        if (i == 0 || g < gmin) gmin = g;
        if (i == 0 || g > gmax) gmax = g;
    }
    if (!(gmax > 0.0)) return 0;         /* ref in the lamp's plane: no light from it */
    return gmax > (medium ? SPH_TRI_SPREAD * SPH_TRI_SPREAD : SPH_TRI_SPREAD) * gmin;
}


/* The solid angle of the triangle seen from ref when solid-angle sampling applies
   to it (in [SPH_TRI_MIN, SPH_TRI_MAX]); 0 (area sampling) otherwise. */
static int tri_setup_sa(Vec3 ref, const Vec3 v[3], SphTri *t)
{
    if (!sph_tri_setup(ref, v[0], v[1], v[2], t)) return 0;
    return t->area >= SPH_TRI_MIN && t->area <= SPH_TRI_MAX;
}

int tri_sample_sa(Vec3 ref, Vec3 n, const Vec3 v[3], float u1, float u2, SphTriSample *out)
{
    SphTri t;
    double x = u1, y = u2, q = 1.0, det;
    D3 w, e1, e2, pv, tv;
    if (!tri_setup_sa(ref, v, &t)) return 0;
    if (has_normal(n)) {
        double wt[4];
        warp_weights(&t, n, wt);
        bilinear_sample(wt, u1, u2, &x, &y);
        q = bilinear_pdf(wt, x, y);
    }
    out->dir = sph_tri_sample(&t, x, y);
    out->pdf = q / t.area;
    /* where the ray ref + s dir meets the triangle's plane: its barycentrics
       (Moller-Trumbore), clamped onto the triangle against rounding */
    w = d3(out->dir);
    e1 = d3_sub(d3(v[1]), d3(v[0]));
    e2 = d3_sub(d3(v[2]), d3(v[0]));
    pv = d3_cross(w, e2);
    det = d3_dot(e1, pv);
    if (!(fabs(det) > 0.0)) return 0;
    tv = d3_sub(d3(ref), d3(v[0]));
    x = d3_dot(tv, pv) / det;
    y = d3_dot(w, d3_cross(tv, e1)) / det;
    x = x > 0.0 ? x : 0.0;
    y = y > 0.0 ? y : 0.0;
    if (x + y > 1.0) { double k = 1.0 / (x + y); x *= k; y *= k; }
    out->b1 = (float)x;
    out->b2 = (float)y;
    return isfinite(out->pdf) && out->pdf > 0.0;
}

int tri_pdf_sa(Vec3 ref, Vec3 n, const Vec3 v[3], Vec3 dir, double *pdf)
{
    SphTri t;
    double x, y, w[4];
    if (!tri_setup_sa(ref, v, &t)) return 0;
    *pdf = 1.0 / t.area;
    if (!has_normal(n)) return 1;
    warp_weights(&t, n, w);
    if (!sph_tri_invert(&t, dir, &x, &y)) x = y = 0.0;     /* along B: u1 = 0, any u0 */
    *pdf *= bilinear_pdf(w, x, y);
    return 1;
}
