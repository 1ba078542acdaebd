/* patch.c - bilinear patches (Shape "bilinearmesh", a PLY file's quads; pbrt-v4's
   BilinearPatch, pbrt book 4th ed. section 6.6): the surface, its (u, v), ray hits,
   area and area sampling.

   WHAT IT IMPLEMENTS (specnee.h section 5)
     patch_corners        the four world corners of a Patch
     patch_is_flat        planar and not folded: the two triangles are the surface
     patch_intersect      closest hit of a ray, with the patch's (u, v)
     patch_uv_of_point    (u, v) of a point of a flat patch (the map inverted)
     patch_surface_point  position, oriented normals and texture (s, t) at (u, v)
     patch_shading        the shading normal and texture (s, t) at (u, v) alone
     patch_area           world area (Gauss-Legendre quadrature of |dp/du x dp/dv|)
     patch_sample         a (u, v) whose point is uniform by area

   THE SURFACE.  Corners p00 p10 p01 p11 (pbrt-v4's vertex order in "indices"):
       p(u, v) = (1-u)(1-v) p00 + u(1-v) p10 + (1-u) v p01 + u v p11,  (u, v) in [0,1]^2
               = p00 + u B + v C + u v D,
       B = p10 - p00,  C = p01 - p00,  D = p11 - p10 - p01 + p00  (the twist).
   dp/du = B + v D, dp/dv = C + u D, and their cross product
       n(u, v) = B x C + u (B x D) + v (D x C)          (the D x D term vanishes)
   is AFFINE in (u, v).  The geometric normal is n / |n|, negated when Shape.flip is
   set; "N" per vertex gives a shading normal, bilinear in (u, v) and authoritative
   for the side (as for triangles); "uv" per vertex gives the texture (s, t),
   bilinear in (u, v), else (s, t) = (u, v).  That is pbrt-v4's meaning; a triangle
   split would interpolate per triangle instead, which differs wherever the quad is
   not a parallelogram or its "uv" not an affine image of it.

   FLAT PATCHES.  A patch with D in the plane of B and C is planar; when n(u, v)
   also keeps one side at the four corners (so everywhere: n is affine) the map is
   one to one onto the convex quad p00 p10 p11 p01, which the triangles (p00, p10,
   p11) and (p00, p11, p01) tile exactly.  geometry.c keeps such a patch as those two
   triangles: the same surface, watertight with its neighbours, with the exact
   area and uniform area sampling of triangles (lights.c), and the light trees'
   bounds and cones.  Only its (u, v) is the patch's: bvh.c inverts the map at the
   hit point (patch_uv_of_point) and interpolates "uv" and "N" bilinearly
   (patch_shading).  Every other patch (twisted, or planar but folded) is a
   primitive of its own in the BVH (id n_tris + n_spheres + n_quadrics + k).
   Planar means |D . N| <= 1e-5 |N| (|p11 - p00| + |p01 - p10|) with N the cross
   product of the diagonals (D . N = 2 det(D, B, C)).

   INTERSECTION (in double; the method of Reshetov, "Cool patches", Ray Tracing
   Gems ch. 8, 2019, which pbrt-v4 uses).  The u-line from a(u) = p00 + u B to
   a(u) + e(u), e(u) = C + u D, meets the ray o + t d iff a(u) - o, d and e(u) are
   coplanar: with A = p00 - o,
       f(u) = (A + u B) . (d x (C + u D)) = c0 + c1 u + c2 u^2 = 0,
       c0 = A . (d x C),  c1 = B . (d x C) + A . (d x D),  c2 = B . (d x D),
   solved without cancellation (q = -(c1 + sign(c1) sqrt(disc)) / 2, roots q / c2,
   c0 / q; a linear f when c2 = 0).  For a root u in [0, 1], with w = a(u) - o,
   e = e(u) and m = d x e, the system w = t d - v e gives by Cramer's rule
       v = w . (d x m) / |m|^2,    t = w . (e x m) / |m|^2,
   kept when 0 <= v <= 1 and 0 < t <= tmax (t rounded to float, as for quadrics);
   the nearer of the two roots wins.  Self-intersection: hitpoint.c's policy holds, a
   secondary ray starts off the surface by 1e-5 (1 + max |p_i|).

   INVERSION of a flat patch at a point p (double): with h = p - p00, drop the axis
   of N's largest component; in the remaining two the point lies on the u-line when
       (h - u B) x2 (C + u D) = 0:  (h x2 C) + u ((h x2 D) - (B x2 C)) - u^2 (B x2 D) = 0
   (x2: the 2-D cross product), whose root nearest [0, 1] is u; then v = (h - u B) .
   e / |e|^2 with e = C + u D (3-D), both clamped to [0, 1].

   AREA.  A = integral over [0,1]^2 of |n(u, v)|, by 8 x 8 Gauss-Legendre points:
   exact for a flat patch (|n| is then affine), and for a twisted one the integrand
   is smooth (the square root of a positive quadratic) and converges geometrically.
   (pbrt-v4 sums a 3 x 3 triangle tessellation for non-rectangles; it uses the area
   only for the light's power, never in an estimate.)

   AREA SAMPLING by rejection.  |n| is the norm of an affine function, hence convex,
   so on each edge and then across it lies below the bilinear interpolation of its
   four corner values w_ij = |n(i, j)|:  |n(u, v)| <= W(u, v).  Proposals (u, v) are
   drawn with density W / integral(W) (a linear marginal in u, then a linear
   conditional in v, each inverted in closed form: x = xi (a + b) / (a + sqrt((1 - xi)
   a^2 + xi b^2)) for the density ~ (1 - x) a + x b), and kept with probability
   |n| / W: the kept points are uniform by area, density 1 / A (rejection sampling;
   on a flat patch W = |n| and the first proposal is always kept).  The first
   proposal uses the caller's (u1, u2); the acceptance tests and further proposals
   use numbers hashed from them (deterministic), at most PATCH_TRIES proposals (the
   acceptance rate is A / integral(W), above 1/2 for any patch whose corner
   Jacobians differ by less than a factor 3).  pbrt-v4 instead keeps the bilinear
   proposal with its pdf (and samples a rectangle by solid angle): the same
   expected image; specnee's lights need 1 / A (lights.c).

   USE.  geometry.c decides flat or not (patch_is_flat), stores twisted patches in
   Scene.patches, sums patch_area into Shape.area; bvh.c bounds them by their
   corners, intersects (patch_intersect; HitRecord b1, b2 hold (u, v)) and fills
   hit points (patch_surface_point, and patch_uv_of_point + patch_shading for the
   triangles of flat patches); lights.c samples an emitting bilinearmesh's
   triangles and twisted patches by one area cdf (patch_area, patch_sample), so
   its density stays 1 / A, and lighttree.c bounds the patches by their corners
   with a full normal cone. */
#include "specnee.h"
#include <string.h>

#define PATCH_TRIES 64

static void d3(Vec3 a, double o[3]) { o[0] = a.x; o[1] = a.y; o[2] = a.z; }
static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double a[3], const double b[3], double o[3])
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    o[0] = x; o[1] = y; o[2] = z;
}

/* B, C, D of the corners c = (p00, p10, p01, p11), in double. */
static void patch_bcd(const Vec3 c[4], double B[3], double C[3], double D[3])
{
    double p[4][3];
    int i, k;
    for (i = 0; i < 4; i++) d3(c[i], p[i]);
    for (k = 0; k < 3; k++) {
        B[k] = p[1][k] - p[0][k];
        C[k] = p[2][k] - p[0][k];
        D[k] = p[3][k] - p[1][k] - p[2][k] + p[0][k];
    }
}

/* n(u, v) = (B + v D) x (C + u D). */
static void patch_n(const double B[3], const double C[3], const double D[3], double u, double v,
                    double n[3])
{
    double du[3], dv[3];
    int k;
    for (k = 0; k < 3; k++) { du[k] = B[k] + v * D[k]; dv[k] = C[k] + u * D[k]; }
    cross3(du, dv, n);
}

void patch_corners(const Scene *s, const int32_t v[4], Vec3 c[4])
{
    int i;
    for (i = 0; i < 4; i++) c[i] = s->P[v[i]];
}

void flat_patch_uv(const Scene *s, const Shape *sh, int prim, Vec3 p, int32_t q[4], float *u, float *v)
{
    const Triangle *t0 = &s->tris[sh->tri_begin + 2 * ((prim - sh->tri_begin) / 2)];
    Vec3 c[4];
    q[0] = t0[0].v[0]; q[1] = t0[0].v[1]; q[2] = t0[1].v[2]; q[3] = t0[0].v[2];
    patch_corners(s, q, c);
    patch_uv_of_point(c, p, u, v);
}

int patch_is_flat(const Vec3 c[4])
{
    double B[3], C[3], D[3], e1[3], e2[3], N[3], len, n[3], s0 = 0.0;
    int k, i, pos = 0, neg = 0;
    patch_bcd(c, B, C, D);
    for (k = 0; k < 3; k++) { e1[k] = B[k] + C[k] + D[k]; e2[k] = C[k] - B[k]; }   /* diagonals */
    cross3(e1, e2, N);
    len = sqrt(dot3(N, N));
    if (!(len > 0.0)) return 0;
    if (fabs(dot3(D, N)) > 1e-5 * len * (sqrt(dot3(e1, e1)) + sqrt(dot3(e2, e2)))) return 0;
    for (i = 0; i < 4; i++) {                      /* one side at the four corners */
        patch_n(B, C, D, (double)(i & 1), (double)(i >> 1), n);
        s0 = dot3(n, N);
        pos += s0 > 0.0;
        neg += s0 < 0.0;
    }
    return pos == 0 || neg == 0;
}

/* The root of c0 + c1 u + c2 u^2 = 0 (stable form); returns how many (0..2). */
static int quadratic(double c0, double c1, double c2, double r[2])
{
    double disc, q;
    if (c2 == 0.0) {
        if (c1 == 0.0) return 0;
        r[0] = -c0 / c1;
        return 1;
    }
    disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc < 0.0) return 0;
    q = -0.5 * (c1 + (c1 < 0.0 ? -sqrt(disc) : sqrt(disc)));
    r[0] = q / c2;
    if (q == 0.0) return 1;
    r[1] = c0 / q;
    return 2;
}

int patch_intersect(const Vec3 c[4], const Ray *r, float tmax, float *t_out, float *u_out,
                    float *v_out)
{
    double o[3], d[3], B[3], C[3], D[3], A[3], dC[3], dD[3], root[2];
    int n, i, k, hit = 0;
    float best = tmax;
    patch_bcd(c, B, C, D);
    d3(r->o, o);
    d3(r->d, d);
    for (k = 0; k < 3; k++) A[k] = (double)v3_get(c[0], k) - o[k];
    cross3(d, C, dC);
    cross3(d, D, dD);
    n = quadratic(dot3(A, dC), dot3(B, dC) + dot3(A, dD), dot3(B, dD), root);
    for (i = 0; i < n; i++) {
        const double u = root[i];
        double w[3], e[3], m[3], dm[3], em[3], m2, v, t;
        float tf;
        if (!(u >= 0.0 && u <= 1.0)) continue;
        for (k = 0; k < 3; k++) { w[k] = A[k] + u * B[k]; e[k] = C[k] + u * D[k]; }
        cross3(d, e, m);
        m2 = dot3(m, m);
        if (!(m2 > 0.0)) continue;                 /* the u-line is parallel to the ray */
        cross3(d, m, dm);
        cross3(e, m, em);
        v = dot3(w, dm) / m2;
        t = dot3(w, em) / m2;
        tf = (float)t;
        if (!(v >= 0.0 && v <= 1.0) || !(tf > 0.0f && tf <= best)) continue;
        if (hit && tf == best) continue;           /* a tie keeps the first root */
        best = tf;
        *t_out = tf;
        *u_out = (float)u;
        *v_out = (float)v;
        hit = 1;
    }
    return hit;
}

void patch_uv_of_point(const Vec3 c[4], Vec3 p, float *u_out, float *v_out)
{
    double B[3], C[3], D[3], h[3], e1[3], e2[3], N[3], r[2], e[3], w[3], u = 0.5, v, ee;
    int k, ax = 0, x, y, n, i;
    patch_bcd(c, B, C, D);
    for (k = 0; k < 3; k++) {
        h[k] = (double)v3_get(p, k) - (double)v3_get(c[0], k);
        e1[k] = B[k] + C[k] + D[k];
        e2[k] = C[k] - B[k];
    }
    cross3(e1, e2, N);
    for (k = 1; k < 3; k++) if (fabs(N[k]) > fabs(N[ax])) ax = k;
    x = (ax + 1) % 3;
    y = (ax + 2) % 3;
    {
#define X2(a, b) ((a)[x] * (b)[y] - (a)[y] * (b)[x])
        n = quadratic(X2(h, C), X2(h, D) - X2(B, C), -X2(B, D), r);
#undef X2
    }
    {   /* the root nearest [0, 1] */
        double best = INFINITY;
        for (i = 0; i < n; i++) {
            double dist = r[i] < 0.0 ? -r[i] : r[i] > 1.0 ? r[i] - 1.0 : 0.0;
            if (dist < best) { best = dist; u = r[i]; }
        }
    }
    u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
    for (k = 0; k < 3; k++) { e[k] = C[k] + u * D[k]; w[k] = h[k] - u * B[k]; }
    ee = dot3(e, e);
    v = ee > 0.0 ? dot3(w, e) / ee : 0.0;
    *u_out = (float)u;
    *v_out = (float)(v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v);
}

/* Bilinear interpolation of per-vertex values a (stride `per`, component j). */
static double bilerp(const float *a, const int32_t vi[4], int per, int j, double u, double v)
{
    return (1.0 - u) * (1.0 - v) * a[per * vi[0] + j] + u * (1.0 - v) * a[per * vi[1] + j] +
           (1.0 - u) * v * a[per * vi[2] + j] + u * v * a[per * vi[3] + j];
}

void patch_shading(const Scene *s, const Shape *sh, const int32_t vi[4], double u, double v,
                   SurfacePoint *sp)
{
    if (sh->has_normals && s->N) {
        /* Vec3 is x, y, z first (tcc pads it to four floats: specnee.h) */
        const float *N = &s->N[0].x;
        const int per = (int)(sizeof(Vec3) / sizeof(float));
        Vec3 ns = v3((float)bilerp(N, vi, per, 0, u, v), (float)bilerp(N, vi, per, 1, u, v),
                     (float)bilerp(N, vi, per, 2, u, v));
        sp->ns = sp->ng;
        if (v3_dot(ns, ns) > 0.0f) {
            sp->ns = v3_norm(ns);                  /* authoritative for the side */
            if (v3_dot(sp->ng, sp->ns) < 0.0f) sp->ng = v3_neg(sp->ng);
        }
    } else
        sp->ns = sp->ng;
    if (sh->has_uv && s->UV) {
        sp->u = (float)bilerp(s->UV, vi, 2, 0, u, v);
        sp->v = (float)bilerp(s->UV, vi, 2, 1, u, v);
    } else {
        sp->u = (float)u;
        sp->v = (float)v;
    }
}

void patch_surface_point(const Scene *s, const Shape *sh, const int32_t vi[4], double u, double v,
                         const Ray *r, SurfacePoint *sp)
{
    Vec3 c[4];
    double B[3], C[3], D[3], n[3], p[3], len;
    int k;
    patch_corners(s, vi, c);
    patch_bcd(c, B, C, D);
    for (k = 0; k < 3; k++)
        p[k] = (double)v3_get(c[0], k) + u * B[k] + v * C[k] + u * v * D[k];
    sp->p = v3((float)p[0], (float)p[1], (float)p[2]);
    patch_n(B, C, D, u, v, n);
    len = sqrt(dot3(n, n));
    if (!(len > 0.0)) {                            /* a collapsed corner: the diagonals */
        double e1[3], e2[3];
        for (k = 0; k < 3; k++) { e1[k] = B[k] + C[k] + D[k]; e2[k] = C[k] - B[k]; }
        cross3(e1, e2, n);
        len = sqrt(dot3(n, n));
    }
    sp->ng = len > 0.0 ? v3((float)(n[0] / len), (float)(n[1] / len), (float)(n[2] / len))
                       : v3_norm(v3_neg(r->d));
    if (sh->flip) sp->ng = v3_neg(sp->ng);
    patch_shading(s, sh, vi, u, v, sp);
}

/* 8-point Gauss-Legendre on [0, 1]: nodes and weights. */
static const double GL_X[8] = { 0.01985507175123188, 0.10166676129318664, 0.23723379504183550,
                                0.40828267875217510, 0.59171732124782490, 0.76276620495816450,
                                0.89833323870681336, 0.98014492824876812 };
static const double GL_W[8] = { 0.05061426814518813, 0.11119051722668724, 0.15685332293894364,
                                0.18134189168918100, 0.18134189168918100, 0.15685332293894364,
                                0.11119051722668724, 0.05061426814518813 };

double patch_area(const Vec3 c[4])
{
    double B[3], C[3], D[3], n[3], a = 0.0;
    int i, j;
    patch_bcd(c, B, C, D);
    for (i = 0; i < 8; i++)
        for (j = 0; j < 8; j++) {
            patch_n(B, C, D, GL_X[i], GL_X[j], n);
            a += GL_W[i] * GL_W[j] * sqrt(dot3(n, n));
        }
    return a;
}

/* x in [0, 1] with density ~ (1 - x) a + x b (a, b >= 0), from xi in [0, 1). */
static double sample_linear(double xi, double a, double b)
{
    double den = a + sqrt((1.0 - xi) * a * a + xi * b * b);
    return den > 0.0 ? xi * (a + b) / den : xi;
}

/* A number in [0, 1) hashed from the bits of x and y and the round k (a 32-bit
   integer mix, Wellons' "lowbias32"). */
static float hash01(float x, float y, unsigned k)
{
    uint32_t a, b, h;
    memcpy(&a, &x, 4);
    memcpy(&b, &y, 4);
    h = a ^ (b * 0x9e3779b9u) ^ (k * 0x85ebca6bu);
    h ^= h >> 16; h *= 0x7feb352du;
    h ^= h >> 15; h *= 0x846ca68bu;
    h ^= h >> 16;
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

void patch_sample(const Vec3 c[4], float u1, float u2, float *u_out, float *v_out)
{
    double B[3], C[3], D[3], n[3], w[4], u = 0.0, v = 0.0;
    float x1 = u1, x2 = u2;
    int i;
    patch_bcd(c, B, C, D);
    for (i = 0; i < 4; i++) {                      /* w00, w10, w01, w11 */
        patch_n(B, C, D, (double)(i & 1), (double)(i >> 1), n);
        w[i] = sqrt(dot3(n, n));
    }
    for (i = 0; i < PATCH_TRIES; i++) {
        double W, J;
        if (i > 0) { x1 = hash01(u1, u2, 2u * (unsigned)i); x2 = hash01(u1, u2, 2u * (unsigned)i + 1u); }
        u = sample_linear(x1, w[0] + w[2], w[1] + w[3]);
        v = sample_linear(x2, (1.0 - u) * w[0] + u * w[1], (1.0 - u) * w[2] + u * w[3]);
        W = (1.0 - u) * (1.0 - v) * w[0] + u * (1.0 - v) * w[1] + (1.0 - u) * v * w[2] + u * v * w[3];
        patch_n(B, C, D, u, v, n);
        J = sqrt(dot3(n, n));
        if (J >= W * (1.0 - 1e-9) || (double)hash01(u1, u2, 1000u + (unsigned)i) * W < J) break;
    }
    *u_out = (float)u;
    *v_out = (float)v;
}
