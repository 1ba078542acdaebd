/* curve.c - curves (pbrt-v4's Shape "curve"; pbrt book 4th ed. section 6.7): thin
   flat, cylindrical or ribbon strands along cubic Bezier splines, for hair and fur.

   WHAT IT IMPLEMENTS (specnee.h section 5; the builder in parser.h section 5)
     curve_shape             the Shape directive's "curve": parameters, conversion to
                             cubic Bezier segments, the pieces the BVH holds
     curve_bezier_eval       a cubic Bezier's point and derivative
     curve_bezier_piece      the control points of its part [u0, u1] (blossoms)
     curve_bspline_to_bezier, curve_quadratic_bspline_to_bezier,
     curve_elevate_quadratic the conversions of the other bases and degree 2
     curve_piece_bounds      a piece's world box
     curve_intersect         the closest (or any) hit of a ray with a piece
     curve_surface_point     position, normals, (u, v), dp/du, dp/dv at a hit
   geometry.c makes the Shape of `Shape "curve"` and calls curve_shape for its
   segments; bvh.c bounds and intersects piece k as primitive
   n_tris + n_spheres + n_quadrics + n_patches + k and calls
   curve_surface_point from scene_surface_point; bump.c takes dp/du, dp/dv from it
   (the hair material's frame).

   THE SHAPE.  "point3 P" are the control points in object space, "string basis"
   "bezier" (default) or "bspline", "integer degree" 3 (default) or 2.  A Bezier
   curve of degree k has k + 1 + n k points, n >= 0: segment s uses P[k s .. k s + k];
   a uniform b-spline has at least k + 1 points and segment s uses P[s .. s + k].
   Every segment becomes a cubic Bezier b0..b3 (pbrt-v4 does the same):
     cubic b-spline p0..p3:   b0 = (p0 + 4 p1 + p2) / 6,  b1 = (2 p1 + p2) / 3,
                              b2 = (p1 + 2 p2) / 3,       b3 = (p1 + 4 p2 + p3) / 6
     quadratic b-spline q0..q2 to a quadratic Bezier:  (q0 + q1) / 2, q1, (q1 + q2) / 2
     quadratic Bezier a0..a2 raised to degree 3:  a0, (a0 + 2 a1) / 3, (2 a1 + a2) / 3, a2
   (the same polynomial: tests/test_curve.c checks them against the bases' closed
   forms).  Each segment is its own curve with u in [0, 1] (a hit's u is the
   segment's, as in pbrt-v4), its width going linearly from
   lerp(s / n, width0, width1) to lerp((s + 1) / n, width0, width1) along it
   ("float width" 1 sets both ends; widths are in object space).  "integer
   splitdepth" d (3) cuts each segment into 2^d pieces [i / 2^d, (i + 1) / 2^d],
   the BVH's primitives (tighter boxes); a piece's control points are the blossoms
   B(u0, u0, u0), B(u0, u0, u1), B(u0, u1, u1), B(u1, u1, u1).
   "string type": "flat" (default) a band of the curve's width always facing the
   ray; "cylinder" the same band whose normal turns across it as a tube's would;
   "ribbon" a band turning along the curve, its normal interpolated between the
   "normal N" of the segment's ends (one per segment end: n + 1 for n segments) by
   spherical interpolation, n(u) = (sin((1 - u) th) n0 + sin(u th) n1) / sin th.

   INTERSECTION (Nakamaru and Ohno 2002, as pbrt-v4 uses it).  In object space (the
   ray carried there by M^-1, the same t), the piece is expressed in the RAY'S
   FRAME: the ray's origin at 0, its unit direction the z axis, x and y across it.
   A hit is then a point of the curve within half the width of the z axis, in
   front of the origin.  The piece is cut in halves (de Casteljau at 1/2) to a
   depth r = round(log2(sqrt(2) 6 L0 / (8 eps))) / 2 clamped to [0, 10], with L0
   the largest second difference |b_i - 2 b_(i+1) + b_(i+2)| of the ray-frame
   control points and eps = max(width0, width1) / 20: deep enough that each
   part is within eps of the chord b0 b3.  A part is skipped when its control
   points' box, widened by half its largest width, does not meet the ray's segment
   x = y = 0, 0 <= z <= |d| tmax.  At the bottom, a part is a line: the origin
   must lie between the perpendiculars to the curve at its ends
       (b1 - b0) . (0 - b0) >= 0   and   (b2 - b3) . (0 - b3) >= 0   (in x, y),
   w = the origin's projection on the chord b0 b3 (in x, y) gives
       u = clamp(lerp(w, u0, u1), u0, u1),  width  W = lerp(u, width0, width1),
   (a ribbon: W |n(u) . d| / |d|, the band seen at an angle), and the curve point
   pc = B(clamp(w, 0, 1)) must have pc_x^2 + pc_y^2 <= W^2 / 4 and pc_z >= 0.
   Then t = pc_z / |d| (the depth of the curve's centre line, as in pbrt-v4), and
       v = 1/2 +- sqrt(pc_x^2 + pc_y^2) / W,
   + when the ray passes on the side where (pc x B'(w))_z > 0: v runs across the
   band from 0 to 1 (the hair material's h = -1 + 2 v).  The closest of the parts'
   hits wins (any one for a shadow ray).  Computed in double; t is rounded to float
   and kept when 0 < t <= tmax in float (the boxes are culled at |d| tmax with a
   margin of 1e-6), so that a hit at the BVH's t_best is found whatever the order
   of the traversal.  The result is a function of the ray and the piece
   alone (ORDER INDEPENDENCE in bvh.c holds: the hit's ray point lies within half a
   width of the centre line, inside the piece's widened box).

   THE HIT (pbrt-v4's, in object space, then to the world by M, normals by M^-T):
       dp/du = B'(u) of the segment;
       flat:      dp/dv = W normalize(dir x dp/du)   (dir = the ray's unit direction)
       cylinder:  that vector turned about dp/du by -theta, theta = lerp(v, -90, 90)
                  degrees, so that the normal sweeps a half tube across the band;
       ribbon:    dp/dv = W normalize(n(u) x dp/du);
       n = normalize(dp/du x dp/dv), negated when Shape.flip; the shading normal is n.
   For a flat band n is dir made perpendicular to the curve: it points AWAY from the
   viewer (pbrt-v4's orientation; the BSDFs are two-sided).  p = o + t d (on the ray).
   SELF-INTERSECTION.  pbrt-v4 gives a curve hit the error bound W in each object
   axis (Point3fi pError), carried to the world as sum_j |M_ij| W, and starts a
   ray leaving it |n| . err along n; SurfacePoint.err holds that box and
   spawn_origin (hitpoint.c) adds it to the usual offset.  It matters: a ray leaving the
   band would otherwise meet the same band again (each ray sees it facing itself).

   NOT SUPPORTED (refused by name): an AreaLightSource on a curve (pbrt-v4 has no
   sampling of curves: its Curve::Sample stops the program), degree other than 2
   and 3, bases other than bezier and bspline, types other than the three above
   (pbrt-v4 makes an unknown type a cylinder after an error message), negative
   widths, splitdepth outside [0, 12], opposite ribbon normals at a segment's ends
   (no turn between them).  "N" on a flat or cylinder curve is read and ignored, as
   pbrt-v4 does (it warns).  Lights are sampled from the hit moved past its error
   box to the viewer's side, as pbrt-v4's SampleLd does (path.c light_origin). */
#include "specnee.h"
#include "parser.h"
#include <float.h>
#include <string.h>

#define CURVE_MAX_DEPTH 10       /* pbrt-v4's largest refinement depth */
#define CURVE_MAX_SPLITDEPTH 12  /* 4096 pieces a segment at most */

/* ====================================================================
   1. Cubic Bezier arithmetic (double inside, Vec3 outside)
   ==================================================================== */
typedef struct { double x, y, z; } D3;

static D3 d3(double x, double y, double z) { D3 r; r.x = x; r.y = y; r.z = z; return r; }
static D3 d3_of(Vec3 v) { return d3(v.x, v.y, v.z); }
static Vec3 v3_of(D3 a) { return v3((float)a.x, (float)a.y, (float)a.z); }
static D3 d3_lerp(double t, D3 a, D3 b)
{ return d3((1 - t) * a.x + t * b.x, (1 - t) * a.y + t * b.y, (1 - t) * a.z + t * b.z); }
static D3 d3_sub(D3 a, D3 b) { return d3(a.x - b.x, a.y - b.y, a.z - b.z); }
static D3 d3_scale(D3 a, double s) { return d3(a.x * s, a.y * s, a.z * s); }
static double d3_dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static D3 d3_cross(D3 a, D3 b)
{ return d3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static D3 d3_norm(D3 a)
{ double l = sqrt(d3_dot(a, a)); return l > 0 ? d3_scale(a, 1.0 / l) : a; }

/* The point at u of the cubic Bezier cp (de Casteljau) and B'(u) in *deriv; where
   B'(u) vanishes (cp[0] = cp[1] at u = 0, say) the chord cp[3] - cp[0] stands in. */
static D3 bezier_eval(const D3 cp[4], double u, D3 *deriv)
{
    D3 a0 = d3_lerp(u, cp[0], cp[1]), a1 = d3_lerp(u, cp[1], cp[2]), a2 = d3_lerp(u, cp[2], cp[3]);
    D3 b0 = d3_lerp(u, a0, a1), b1 = d3_lerp(u, a1, a2);
    if (deriv) {
        D3 e = d3_sub(b1, b0);
        *deriv = d3_dot(e, e) > 0 ? d3_scale(e, 3.0) : d3_sub(cp[3], cp[0]);
    }
    return d3_lerp(u, b0, b1);
}

Vec3 curve_bezier_eval(const Vec3 cp[4], float u, Vec3 *deriv)
{
    D3 c[4], d;
    int i;
    for (i = 0; i < 4; i++) c[i] = d3_of(cp[i]);
    {
        D3 p = bezier_eval(c, u, &d);
        if (deriv) *deriv = v3_of(d);
        return v3_of(p);
    }
}

/* The blossom B(a, b, c) of the cubic cp: B(u, u, u) is the point at u. */
static D3 blossom(const D3 cp[4], double a, double b, double c)
{
    D3 p0 = d3_lerp(a, cp[0], cp[1]), p1 = d3_lerp(a, cp[1], cp[2]), p2 = d3_lerp(a, cp[2], cp[3]);
    D3 q0 = d3_lerp(b, p0, p1), q1 = d3_lerp(b, p1, p2);
    return d3_lerp(c, q0, q1);
}

static void piece_points(const D3 cp[4], double u0, double u1, D3 out[4])
{
    out[0] = blossom(cp, u0, u0, u0);
    out[1] = blossom(cp, u0, u0, u1);
    out[2] = blossom(cp, u0, u1, u1);
    out[3] = blossom(cp, u1, u1, u1);
}

void curve_bezier_piece(const Vec3 cp[4], float u0, float u1, Vec3 out[4])
{
    D3 c[4], o[4];
    int i;
    for (i = 0; i < 4; i++) c[i] = d3_of(cp[i]);
    piece_points(c, u0, u1, o);
    for (i = 0; i < 4; i++) out[i] = v3_of(o[i]);
}

/* The two halves of cp (de Casteljau at 1/2): out[0..3] and out[3..6]. */
static void bezier_halves(const D3 cp[4], D3 out[7])
{
    D3 a0 = d3_lerp(0.5, cp[0], cp[1]), a1 = d3_lerp(0.5, cp[1], cp[2]), a2 = d3_lerp(0.5, cp[2], cp[3]);
    D3 b0 = d3_lerp(0.5, a0, a1), b1 = d3_lerp(0.5, a1, a2);
    out[0] = cp[0]; out[1] = a0; out[2] = b0; out[3] = d3_lerp(0.5, b0, b1);
    out[4] = b1; out[5] = a2; out[6] = cp[3];
}

/* (a + 2 b) / 3 written as a lerp, so that a = b gives exactly a. */
static Vec3 third(Vec3 a, Vec3 b, double t)
{ return v3_of(d3_lerp(t, d3_of(a), d3_of(b))); }

void curve_bspline_to_bezier(const Vec3 p[4], Vec3 out[4])
{
    D3 q[4];
    int i;
    for (i = 0; i < 4; i++) q[i] = d3_of(p[i]);
    out[0] = v3_of(d3_scale(d3(q[0].x + 4 * q[1].x + q[2].x, q[0].y + 4 * q[1].y + q[2].y,
                               q[0].z + 4 * q[1].z + q[2].z), 1.0 / 6.0));
    out[1] = third(p[1], p[2], 1.0 / 3.0);
    out[2] = third(p[1], p[2], 2.0 / 3.0);
    out[3] = v3_of(d3_scale(d3(q[1].x + 4 * q[2].x + q[3].x, q[1].y + 4 * q[2].y + q[3].y,
                               q[1].z + 4 * q[2].z + q[3].z), 1.0 / 6.0));
}

void curve_quadratic_bspline_to_bezier(const Vec3 p[3], Vec3 out[3])
{
    out[0] = third(p[0], p[1], 0.5);
    out[1] = p[1];
    out[2] = third(p[1], p[2], 0.5);
}

void curve_elevate_quadratic(const Vec3 a[3], Vec3 out[4])
{
    out[0] = a[0];
    out[1] = third(a[0], a[1], 2.0 / 3.0);
    out[2] = third(a[1], a[2], 1.0 / 3.0);
    out[3] = a[2];
}

/* ====================================================================
   2. A piece and its shape: widths, ribbon normals, transforms
   ==================================================================== */
static double lerp1(double t, double a, double b) { return (1 - t) * a + t * b; }

static void seg_points(const Curve *c, D3 cp[4])
{
    int i;
    for (i = 0; i < 4; i++) cp[i] = d3_of(c->cp[i]);
}

/* A ribbon's unit normal at u (spherical interpolation of the ends'). */
static D3 ribbon_normal(const Curve *c, double u)
{
    double s0, s1;
    if (c->normal_angle == 0.0f) return d3_of(c->n[0]);
    s0 = sin((1 - u) * c->normal_angle) * c->inv_sin_angle;
    s1 = sin(u * c->normal_angle) * c->inv_sin_angle;
    return d3(s0 * c->n[0].x + s1 * c->n[1].x, s0 * c->n[0].y + s1 * c->n[1].y,
              s0 * c->n[0].z + s1 * c->n[1].z);
}

/* p by the 3 x 4 matrix m (w: 1 for a point, 0 for a vector). */
static D3 mat_apply(const double m[4][4], D3 p, double w)
{
    return d3(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3] * w,
              m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3] * w,
              m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3] * w);
}

void curve_piece_bounds(const Scene *s, const CurvePiece *pc, float lo[3], float hi[3])
{
    const Curve *c = &s->curves[pc->curve];
    const double (*m)[4] = (const double (*)[4])s->shapes[c->shape].q.world_from_obj.m;
    const double w = 0.5 * fmax(lerp1(pc->u0, c->width[0], c->width[1]),
                                lerp1(pc->u1, c->width[0], c->width[1]));
    D3 cp[4], pp[4];
    double blo[3], bhi[3], wlo[3], whi[3];
    int i, a, k;
    seg_points(c, cp);
    piece_points(cp, pc->u0, pc->u1, pp);
    for (a = 0; a < 3; a++) { blo[a] = wlo[a] = DBL_MAX; bhi[a] = whi[a] = -DBL_MAX; }
    for (i = 0; i < 4; i++) {
        const double q[3] = { pp[i].x, pp[i].y, pp[i].z };
        for (a = 0; a < 3; a++) { blo[a] = fmin(blo[a], q[a] - w); bhi[a] = fmax(bhi[a], q[a] + w); }
    }
    for (k = 0; k < 8; k++) {                  /* the object box's corners to the world */
        D3 q = mat_apply(m, d3((k & 1) ? bhi[0] : blo[0], (k & 2) ? bhi[1] : blo[1],
                               (k & 4) ? bhi[2] : blo[2]), 1.0);
        const double qa[3] = { q.x, q.y, q.z };
        for (a = 0; a < 3; a++) { wlo[a] = fmin(wlo[a], qa[a]); whi[a] = fmax(whi[a], qa[a]); }
    }
    for (a = 0; a < 3; a++) {                  /* rounded outwards, and a margin for */
        const double e = 1e-9 * (fabs(wlo[a]) + fabs(whi[a]));   /* the double solve */
        lo[a] = nextafterf((float)(wlo[a] - e), -FLT_MAX);
        hi[a] = nextafterf((float)(whi[a] + e), FLT_MAX);
    }
}

/* ====================================================================
   3. Intersection in the ray's frame
   ==================================================================== */
/* One ray-piece test: the ray in object space, the frame, the best hit so far. */
typedef struct {
    const Curve *c;
    D3 o, d;                   /* the object-space ray */
    double len;                /* |d| */
    double zmax;               /* |d| tmax, a little more: where the parts' boxes may end */
    float tmax;                /* the hits kept: t rounded to float <= tmax */
    int any_hit;
    int found;
    double t, u, v;            /* the closest hit so far */
} CurveQuery;

/* The ray frame of (o, d) for control points cp: right, up, dir as rows, and
   cp in it (x = right . (p - o), ...). */
static void ray_frame(const CurveQuery *q, const D3 cp[4], D3 rows[3], D3 out[4])
{
    D3 dir = d3_scale(q->d, 1.0 / q->len);
    D3 up = d3_cross(q->d, d3_sub(cp[3], cp[0])), right;
    int i;
    if (!(d3_dot(up, up) > 0)) {               /* the chord lies along the ray */
        up = fabs(dir.x) > fabs(dir.y) ? d3(-dir.z, 0, dir.x) : d3(0, dir.z, -dir.y);
    }
    right = d3_norm(d3_cross(d3_norm(up), dir));
    rows[0] = right;
    rows[1] = d3_cross(dir, right);
    rows[2] = dir;
    for (i = 0; i < 4; i++) {
        D3 p = d3_sub(cp[i], q->o);
        out[i] = d3(d3_dot(rows[0], p), d3_dot(rows[1], p), d3_dot(rows[2], p));
    }
}

/* Whether the box of cp, widened by half of width w, meets the ray's segment. */
static int box_meets_ray(const CurveQuery *q, const D3 cp[4], double w)
{
    double lo[3] = { DBL_MAX, DBL_MAX, DBL_MAX }, hi[3] = { -DBL_MAX, -DBL_MAX, -DBL_MAX };
    int i, a;
    for (i = 0; i < 4; i++) {
        const double p[3] = { cp[i].x, cp[i].y, cp[i].z };
        for (a = 0; a < 3; a++) { lo[a] = fmin(lo[a], p[a]); hi[a] = fmax(hi[a], p[a]); }
    }
    w *= 0.5;
    return lo[0] - w <= 0 && hi[0] + w >= 0 && lo[1] - w <= 0 && hi[1] + w >= 0 &&
           lo[2] - w <= q->zmax && hi[2] + w >= 0;
}

/* The bottom of the recursion: the part cp (ray frame) of u range [u0, u1] as a line. */
static void leaf_hit(CurveQuery *q, const D3 cp[4], double u0, double u1)
{
    const Curve *c = q->c;
    D3 chord, pc, dw;
    double denom, w, u, width, dist2, t, tf;
    /* the origin between the perpendiculars at the part's ends */
    if ((cp[1].y - cp[0].y) * -cp[0].y + cp[0].x * (cp[0].x - cp[1].x) < 0) return;
    if ((cp[2].y - cp[3].y) * -cp[3].y + cp[3].x * (cp[3].x - cp[2].x) < 0) return;
    chord = d3(cp[3].x - cp[0].x, cp[3].y - cp[0].y, 0);
    denom = chord.x * chord.x + chord.y * chord.y;
    if (denom == 0) return;
    w = -(cp[0].x * chord.x + cp[0].y * chord.y) / denom;
    u = lerp1(w, u0, u1);
    u = u < u0 ? u0 : u > u1 ? u1 : u;
    width = lerp1(u, c->width[0], c->width[1]);
    if (c->type == CURVE_RIBBON) width *= fabs(d3_dot(ribbon_normal(c, u), q->d)) / q->len;
    pc = bezier_eval(cp, w < 0 ? 0 : w > 1 ? 1 : w, &dw);
    dist2 = pc.x * pc.x + pc.y * pc.y;
    if (dist2 > 0.25 * width * width || pc.z < 0) return;
    t = pc.z / q->len;
    tf = (float)t;                        /* decided in float, as the BVH compares */
    if (!(tf > 0.0f) || !(tf <= q->tmax) || (q->found && tf >= (float)q->t)) return;
    q->found = 1;
    q->t = tf;
    q->u = u;
    q->v = dw.x * -pc.y + pc.x * dw.y > 0 ? 0.5 + sqrt(dist2) / width : 0.5 - sqrt(dist2) / width;
}

/* Nakamaru and Ohno's recursion: halves while depth > 0, skipping those whose
   widened box misses the ray. */
static void recurse(CurveQuery *q, const D3 cp[4], double u0, double u1, int depth)
{
    D3 half[7];
    double um = 0.5 * (u0 + u1), us[3];
    int k;
    if (depth == 0) { leaf_hit(q, cp, u0, u1); return; }
    bezier_halves(cp, half);
    us[0] = u0; us[1] = um; us[2] = u1;
    for (k = 0; k < 2 && !(q->any_hit && q->found); k++) {
        const double wmax = fmax(lerp1(us[k], q->c->width[0], q->c->width[1]),
                                 lerp1(us[k + 1], q->c->width[0], q->c->width[1]));
        if (box_meets_ray(q, half + 3 * k, wmax)) recurse(q, half + 3 * k, us[k], us[k + 1], depth - 1);
    }
}

/* The refinement depth for the ray-frame control points cp of a curve whose larger
   end width is wmax: round(log2(sqrt(2) 6 L0 / (8 eps))) / 2 in [0, 10]. */
static int refine_depth(const D3 cp[4], double wmax)
{
    double L0 = 0, eps = 0.05 * wmax, x, l;
    int i, r;
    for (i = 0; i < 2; i++) {
        L0 = fmax(L0, fabs(cp[i].x - 2 * cp[i + 1].x + cp[i + 2].x));
        L0 = fmax(L0, fabs(cp[i].y - 2 * cp[i + 1].y + cp[i + 2].y));
        L0 = fmax(L0, fabs(cp[i].z - 2 * cp[i + 1].z + cp[i + 2].z));
    }
    if (!(L0 > 0)) return 0;
    if (!(eps > 0)) return CURVE_MAX_DEPTH;
    x = 1.41421356237 * 6.0 * L0 / (8.0 * eps);
    l = log2(x);
    r = (int)(l >= 0 ? floor(l + 0.5) : -floor(-l + 0.5)) / 2;
    return r < 0 ? 0 : r > CURVE_MAX_DEPTH ? CURVE_MAX_DEPTH : r;
}

/* The world ray r in the object space of curve c's shape. */
static void object_ray(const Scene *s, const Curve *c, const Ray *r, D3 *o, D3 *d)
{
    const double (*inv)[4] = (const double (*)[4])s->shapes[c->shape].q.world_from_obj.inv;
    *o = mat_apply(inv, d3_of(r->o), 1.0);
    *d = mat_apply(inv, d3_of(r->d), 0.0);
}

int curve_intersect(const Scene *s, const CurvePiece *pc, const Ray *r, float tmax, int any_hit,
                    HitRecord *h)
{
    CurveQuery q;
    D3 cp[4], pp[4], rc[4], rows[3];
    memset(&q, 0, sizeof q);
    q.c = &s->curves[pc->curve];
    object_ray(s, q.c, r, &q.o, &q.d);
    q.len = sqrt(d3_dot(q.d, q.d));
    if (!(q.len > 0) || !(tmax > 0.0f)) return 0;
    q.zmax = q.len * (double)tmax * (1.0 + 1e-6);
    q.tmax = tmax;
    q.any_hit = any_hit;
    seg_points(q.c, cp);
    piece_points(cp, pc->u0, pc->u1, pp);
    ray_frame(&q, pp, rows, rc);
    if (!box_meets_ray(&q, rc, fmax(lerp1(pc->u0, q.c->width[0], q.c->width[1]),
                                    lerp1(pc->u1, q.c->width[0], q.c->width[1]))))
        return 0;
    recurse(&q, rc, pc->u0, pc->u1, refine_depth(rc, fmax(q.c->width[0], q.c->width[1])));
    if (!q.found) return 0;
    h->t = (float)q.t;
    h->b1 = (float)q.u;
    h->b2 = (float)q.v;
    return 1;
}

/* ====================================================================
   4. The hit point
   ==================================================================== */
/* v rotated by angle (radians) about the unit axis a (right-handed, Rodrigues). */
static D3 rotate_about(D3 v, D3 a, double angle)
{
    const double cs = cos(angle), sn = sin(angle), ad = d3_dot(a, v);
    D3 x = d3_cross(a, v);
    return d3(v.x * cs + x.x * sn + a.x * ad * (1 - cs), v.y * cs + x.y * sn + a.y * ad * (1 - cs),
              v.z * cs + x.z * sn + a.z * ad * (1 - cs));
}

void curve_surface_point(const Scene *s, const CurvePiece *pc, const Ray *r, const HitRecord *h,
                         SurfacePoint *sp, Vec3 *dpdu_w, Vec3 *dpdv_w)
{
    const double t = h->t, u = h->b1, v = h->b2;
    const Curve *c = &s->curves[pc->curve];
    const Shape *sh = &s->shapes[c->shape];
    const double (*m)[4] = (const double (*)[4])sh->q.world_from_obj.m;
    D3 o, d, cp[4], dpdu, dpdv, n;
    double width = lerp1(u, c->width[0], c->width[1]), len;
    int a;
    object_ray(s, c, r, &o, &d);
    len = sqrt(d3_dot(d, d));
    seg_points(c, cp);
    bezier_eval(cp, u, &dpdu);
    if (c->type == CURVE_RIBBON) {
        D3 nh = ribbon_normal(c, u);
        width *= len > 0 ? fabs(d3_dot(nh, d)) / len : 1.0;
        dpdv = d3_scale(d3_norm(d3_cross(nh, dpdu)), width);
    } else {
        dpdv = d3_scale(d3_norm(d3_cross(d3_norm(d), dpdu)), width);   /* in the ray's plane */
        if (c->type == CURVE_CYLINDER)
            dpdv = rotate_about(dpdv, d3_norm(dpdu), -lerp1(v, -0.5 * SPECNEE_PI, 0.5 * SPECNEE_PI));
    }
    n = d3_norm(d3_cross(dpdu, dpdv));
    sp->p = v3((float)(r->o.x + t * r->d.x), (float)(r->o.y + t * r->d.y), (float)(r->o.z + t * r->d.z));
    sp->ng = v3_norm(xf_normal(&sh->q.world_from_obj, v3_of(n)));
    if (sh->flip) sp->ng = v3_neg(sp->ng);
    sp->ns = sp->ng;
    sp->u = h->b1;
    sp->v = h->b2;
    {                                          /* pbrt-v4's error box W, to the world */
        float e[3];
        for (a = 0; a < 3; a++) e[a] = (float)((fabs(m[a][0]) + fabs(m[a][1]) + fabs(m[a][2])) * width);
        sp->err = v3(e[0], e[1], e[2]);
    }
    sp->shape = c->shape;
    if (dpdu_w) *dpdu_w = v3_of(mat_apply(m, dpdu, 0.0));
    if (dpdv_w) *dpdv_w = v3_of(mat_apply(m, dpdv, 0.0));
}

/* ====================================================================
   5. Building from the Shape directive's parameters
   ==================================================================== */
/* The cubic Bezier of segment k of the control points P (nP of them) in the basis
   and degree given. */
static void segment_bezier(const Vec3 *P, int k, int bspline, int degree, Vec3 out[4])
{
    if (!bspline) {
        if (degree == 2) curve_elevate_quadratic(P + 2 * k, out);
        else memcpy(out, P + 3 * k, 4 * sizeof(Vec3));
    } else if (degree == 2) {
        Vec3 a[3];
        curve_quadratic_bspline_to_bezier(P + k, a);
        curve_elevate_quadratic(a, out);
    } else
        curve_bspline_to_bezier(P + k, out);
}

/* The ribbon normals of segment k's ends, unit length, and the angle between. */
static int ribbon_ends(Parser *P, Curve *c, const double *N, int k, const char *file, int line)
{
    D3 n0 = d3(N[3 * k], N[3 * k + 1], N[3 * k + 2]), n1 = d3(N[3 * k + 3], N[3 * k + 4], N[3 * k + 5]);
    double ang;
    if (!(d3_dot(n0, n0) > 0) || !(d3_dot(n1, n1) > 0) || !isfinite(d3_dot(n0, n0) + d3_dot(n1, n1)))
        return fail(P, file, line, "Shape \"curve\": \"normal N\" %d or %d has no direction", k, k + 1);
    n0 = d3_norm(n0);
    n1 = d3_norm(n1);
    /* the angle, accurate near 0 and pi: 2 asin(|n1 - n0| / 2), pi - 2 asin(|n1 + n0| / 2) */
    if (d3_dot(n0, n1) >= 0) ang = 2 * asin(fmin(1.0, sqrt(d3_dot(d3_sub(n1, n0), d3_sub(n1, n0))) / 2));
    else {
        D3 sum = d3(n0.x + n1.x, n0.y + n1.y, n0.z + n1.z);
        ang = SPECNEE_PI - 2 * asin(fmin(1.0, sqrt(d3_dot(sum, sum)) / 2));
    }
    if (!(sin(ang) > 1e-6) && ang > 1.0)
        return fail(P, file, line, "Shape \"curve\": \"normal N\" %d and %d are opposite: the ribbon's "
                    "turn between them has no direction", k, k + 1);
    c->n[0] = v3_of(n0);
    c->n[1] = v3_of(n1);
    c->normal_angle = (float)ang;
    c->inv_sin_angle = ang > 0 ? (float)(1.0 / sin(ang)) : 0.0f;
    return 1;
}

/* Append segment k (control points b, end widths w0 w1) and its 2^sd pieces. */
static int add_segment(Parser *P, const Vec3 b[4], double w0, double w1, int type, int sh,
                       int sd, const char *file, int line)
{
    Scene *s = P->s;
    const int np = 1 << sd;
    Curve *c;
    int i;
    if (!grow((void **)&s->curves, &P->cap_curves, s->n_curves + 1, sizeof(Curve)) ||
        !grow((void **)&s->curve_pieces, &P->cap_pieces, s->n_curve_pieces + np, sizeof(CurvePiece)))
        return oom(P, file, line);
    c = &s->curves[s->n_curves];
    memset(c, 0, sizeof *c);
    memcpy(c->cp, b, 4 * sizeof(Vec3));
    c->width[0] = (float)w0;
    c->width[1] = (float)w1;
    c->type = type;
    c->shape = sh;
    for (i = 0; i < np; i++) {
        CurvePiece *pc = &s->curve_pieces[s->n_curve_pieces++];
        D3 cp[4], pp[4];
        double len = 0;
        int k;
        pc->curve = s->n_curves;
        pc->u0 = (float)i / (float)np;
        pc->u1 = (float)(i + 1) / (float)np;
        seg_points(c, cp);                 /* Shape.area: pbrt-v4's estimate, the control */
        piece_points(cp, pc->u0, pc->u1, pp);   /* polygon's length x the mean width, in
                                                   object space (only --dump-scene shows it) */
        for (k = 0; k < 3; k++) len += sqrt(d3_dot(d3_sub(pp[k + 1], pp[k]), d3_sub(pp[k + 1], pp[k])));
        s->shapes[sh].area += len * 0.5 * (lerp1(pc->u0, w0, w1) + lerp1(pc->u1, w0, w1));
    }
    s->n_curves++;
    return 1;
}

/* The curve's type from "string type" (flat, cylinder, ribbon). */
static int curve_type(Parser *P, ParamList *pl, int *type, const char *file, int line)
{
    const char *ts;
    if (!get_string(P, pl, "type", &ts)) return 0;
    if (!ts) ts = "flat";
    if (!strcmp(ts, "flat")) *type = CURVE_FLAT;
    else if (!strcmp(ts, "cylinder")) *type = CURVE_CYLINDER;
    else if (!strcmp(ts, "ribbon")) *type = CURVE_RIBBON;
    else
        return fail_param(P, pl, "type", file, line, "Shape \"curve\": unknown \"string type\" \"%s\" "
                          "(flat, cylinder or ribbon)", ts);
    return 1;
}

/* How many segments the nP control points make; 0 and an error when they cannot. */
static int curve_segments(Parser *P, ParamList *pl, int nP, int bspline, int degree,
                          const char *file, int line)
{
    if (!bspline && (nP < degree + 1 || (nP - 1 - degree) % degree != 0))
        return fail_param(P, pl, "P", file, line, "Shape \"curve\": %d control points: a degree %d "
                          "Bezier curve needs %d + n * %d (n >= 0)", nP, degree, degree + 1, degree);
    if (bspline && nP < degree + 1)
        return fail_param(P, pl, "P", file, line, "Shape \"curve\": %d control points: a degree %d "
                          "b-spline needs at least %d", nP, degree, degree + 1);
    return bspline ? nP - degree : (nP - 1) / degree;
}

/* The scalar parameters: widths, degree, basis, type, splitdepth. */
typedef struct { float w, w0, w1; int degree, bspline, type, sd; } CurveParams;

static int curve_params(Parser *P, ParamList *pl, CurveParams *cp, const char *file, int line)
{
    const char *basis;
    if (!get_float(P, pl, "width", 1.0f, &cp->w) || !get_float(P, pl, "width0", cp->w, &cp->w0) ||
        !get_float(P, pl, "width1", cp->w, &cp->w1) ||
        !get_int(P, pl, "degree", 3, &cp->degree, NULL) || !get_string(P, pl, "basis", &basis) ||
        !get_int(P, pl, "splitdepth", 3, &cp->sd, NULL) || !curve_type(P, pl, &cp->type, file, line))
        return 0;
    if (!(cp->w0 >= 0.0f && cp->w1 >= 0.0f && cp->w0 + cp->w1 < FLT_MAX))
        return fail(P, file, line, "Shape \"curve\": widths %g, %g must be finite and >= 0", cp->w0, cp->w1);
    if (!basis) basis = "bezier";
    if (cp->degree != 2 && cp->degree != 3)
        return fail_param(P, pl, "degree", file, line, "Shape \"curve\": \"integer degree\" %d: "
                          "only 2 and 3 (as in pbrt-v4)", cp->degree);
    if (strcmp(basis, "bezier") && strcmp(basis, "bspline"))
        return fail_param(P, pl, "basis", file, line, "Shape \"curve\": unknown \"string basis\" \"%s\" "
                          "(bezier or bspline)", basis);
    cp->bspline = !strcmp(basis, "bspline");
    if (cp->sd < 0 || cp->sd > CURVE_MAX_SPLITDEPTH)
        return fail_param(P, pl, "splitdepth", file, line, "Shape \"curve\": \"integer splitdepth\" %d "
                          "must lie in [0, %d]", cp->sd, CURVE_MAX_SPLITDEPTH);
    return 1;
}

int curve_shape(Parser *P, ParamList *pl, int sh, const char *file, int line)
{
    Param *pp = param_find(pl, PT_POINT3, "P"), *pn = param_find(pl, PT_NORMAL, "N");
    CurveParams cp;
    Vec3 *pts;
    int nP, nseg, k, ok = 1;
    if (!curve_params(P, pl, &cp, file, line)) return 0;
    if (!params_check_unused(P, pl, "Shape \"curve\"", "point3 P, string basis, integer degree, "
                             "string type, normal N, float width, float width0, float width1, "
                             "integer splitdepth", NULL))
        return 0;
    if (P->gs.area_light >= 0)
        return fail(P, file, line, "Shape \"curve\" under an AreaLightSource is valid pbrt-v4 but not in "
                    "the specnee subset (pbrt-v4 cannot sample a curve: its Curve::Sample stops)");
    if (!pp || pp->n_num % 3 != 0)
        return fail(P, file, line, "Shape \"curve\": \"point3 P\" is required (3 values a point)");
    nP = pp->n_num / 3;
    nseg = curve_segments(P, pl, nP, cp.bspline, cp.degree, file, line);
    if (nseg <= 0) return 0;
    if (cp.type == CURVE_RIBBON && (!pn || pn->n_num != 3 * (nseg + 1)))
        return fail(P, file, line, "Shape \"curve\": a ribbon needs \"normal N\" at its %d segment "
                    "ends (%d values), not %d", nseg + 1, 3 * (nseg + 1), pn ? pn->n_num : 0);
    pts = (Vec3 *)malloc((size_t)nP * sizeof(Vec3));
    if (!pts) return oom(P, file, line);
    for (k = 0; k < nP; k++) {
        pts[k] = v3((float)pp->num[3 * k], (float)pp->num[3 * k + 1], (float)pp->num[3 * k + 2]);
        if (!isfinite(pts[k].x) || !isfinite(pts[k].y) || !isfinite(pts[k].z)) {
            free(pts);
            return fail(P, pp->file, pp->line, "Shape \"curve\": control point %d is not finite", k);
        }
    }
    if (!quadric_set_transform(&P->s->shapes[sh].q, &P->gs.ctm)) {
        free(pts);
        return fail(P, file, line, "Shape \"curve\": projective transform not supported");
    }
    for (k = 0; ok && k < nseg; k++) {
        Vec3 b[4];
        segment_bezier(pts, k, cp.bspline, cp.degree, b);
        ok = add_segment(P, b, lerp1((double)k / nseg, cp.w0, cp.w1), lerp1((double)(k + 1) / nseg, cp.w0, cp.w1),
                         cp.type, sh, cp.sd, file, line) &&
             (cp.type != CURVE_RIBBON || ribbon_ends(P, &P->s->curves[P->s->n_curves - 1], pn->num, k, file, line));
    }
    free(pts);
    return ok;
}
