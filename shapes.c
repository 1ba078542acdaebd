/* shapes.c - the quadrics: disk, cylinder and partial sphere (pbrt-v4's Disk,
   Cylinder and Sphere; pbrt book 4th ed. sections 6.1-6.3), intersected in their
   own object space, bounded, measured and sampled by area.

   WHAT IT IMPLEMENTS (specnee.h section 5)
     quadric_set_transform     the CTM of a quadric, and whether it is a similarity
     quadric_intersect         closest hit of a world-space ray
     quadric_surface_point     position and oriented normal at a hit
     quadric_bounds            world-space box, for the BVH and the light tree
     quadric_area              world-space area (Shape.area, the emitter's area)
     quadric_uniform_sampling  whether quadric_sample is uniform by world area
     quadric_sample            a point uniform by area, with its oriented normal
   A full sphere under a rigid motion and a uniform scale keeps bvh.c's world-space
   test (SHAPE_SPHERE); a sphere cut by zmin/zmax/phimax, or under a non-uniform
   scale or shear, is a SHAPE_SPHERE_PART here.

   THE SHAPES, in object space (pbrt-v4's parameters and defaults; phi = atan2(y, x)
   taken in [0, 2 pi), and only 0 <= phi <= phimax is kept):
     disk       z = height, innerradius <= sqrt(x^2 + y^2) <= radius
                object normal +z
                area  phimax / 2 (radius^2 - innerradius^2)
     cylinder   x^2 + y^2 = radius^2, zmin <= z <= zmax, open (no caps)
                object normal (x, y, 0) / radius, outward
                area  phimax radius (zmax - zmin)
     sphere     x^2 + y^2 + z^2 = radius^2, zmin <= z <= zmax (clamped to
                [-radius, radius], as pbrt-v4 does)
                object normal (x, y, z) / radius, outward
                area  phimax radius (zmax - zmin)  (Archimedes: a zone's area
                grows linearly with its height)
   These are the directions of dp/du x dp/dv in pbrt-v4 (u = phi / phimax, v along
   z or the radius), so they match pbrt-v4's normals.  As for every shape, the
   world normal is then negated when Shape.flip (ReverseOrientation XOR a
   handedness-swapping CTM) is set (docs/conventions.md §3).

   TRANSFORMS.  Points go to the world by M (Quadric.world_from_obj.m), normals by
   M^-T (pbrt book section 3.10.3).  A world ray (o, d) becomes the object ray
   (M^-1 o, M^-1 d) with the SAME parameter t, because M is affine: no
   renormalisation, so the t found in object space is the world t.  Everything is
   computed in double from the float ray.

   INTERSECTION (pbrt book 6.1.3, 6.2.2, 6.3.2; the quadratic solved as bvh.c's
   sphere test does, Haines et al., Ray Tracing Gems ch. 7, 2019)
     disk      t = (height - o_z) / d_z (d_z = 0: the ray is parallel: no hit), then
               the radius and phi tests on o + t d.
     cylinder  (o_x + t d_x)^2 + (o_y + t d_y)^2 = r^2:  a t^2 + 2 b t + c = 0 with
               a = d_x^2 + d_y^2, b = o_x d_x + o_y d_y, c = o_x^2 + o_y^2 - r^2.
     sphere    |o + t d|^2 = r^2:  a = d.d, b = o.d, c = o.o - r^2.
     For both, the discriminant is a (r^2 - |o - (b / a) d|^2) (the squared distance
     of the line from the axis / centre: no catastrophic cancellation for a far
     shape), and the roots are q = -(b + sign(b) sqrt(disc)), t0 = q / a, t1 = c / q
     (no subtraction of nearly equal numbers).  The nearer root is tried first; if it
     lies behind the origin or outside the kept part (z range, phi), the farther
     one: a ray from inside a cylinder, or through the opening of a cut sphere, hits
     the far wall.
   SELF-INTERSECTION: hitpoint.c's policy holds as for spheres.  A secondary ray starts
   offset_ray_origin's 1e-5 (1 + max |p_i|) off the surface, on the side it leaves
   to; the root at that surface is then clearly negative in double (of the order of
   the offset over the cosine), so only t > 0 (in float) is asked of a root.

   SURFACE POINT.  p = o + t d in double, moved onto the surface (z = height for a
   disk; scaled to the radius from the axis / centre otherwise), then to the world.
   The shading normal is the geometric one (no per-vertex normals on quadrics).

   AREA.  An affine map L (M's 3x3 part) takes a surface element of area dA and unit
   normal n to one of area |det L| |L^-T n| dA (from cross(L a, L b) = det(L) L^-T
   (a x b)).  So the world area is the object area times the mean, by object area,
   of |det L| |L^-T n|:
     - a disk has one n: the factor is constant, exact under any affine CTM;
     - under a similarity L = s R the factor is s^2 everywhere;
     - otherwise (a cylinder or sphere under a non-uniform scale or shear: an
       ellipsoid, an elliptic cylinder) it is averaged by the midpoint rule over a
       64 x 64 grid in (phi, z), which is uniform by object area for both (the
       sphere by Archimedes); accurate to about 1e-4 relative for moderate
       anisotropy.
   SAMPLING (uniform by object area; pbrt book 6.2.4 for the disk):
     disk      r = sqrt(ri^2 + u1 (R^2 - ri^2)), phi = u2 phimax
     cylinder  z = zmin + u1 (zmax - zmin), phi = u2 phimax
     sphere    z = zmin + u1 (zmax - zmin), phi = u2 phimax (Archimedes again)
   This is uniform by WORLD area wherever the factor above is constant: a disk under
   any affine CTM, a cylinder or sphere under a similarity.  A cylinder or sphere
   under any other CTM (an ellipsoid, an elliptic cylinder) is sampled with a density
   that varies over it, 1 / (a_obj |det L| |L^-T n|) per world area at the point
   (quadric_area_at), which lights.c uses for such an area light instead of
   1 / area: still exact, only less even than uniform.  (pbrt-v4's Disk::Sample
   draws the whole disk whatever innerradius and phimax say, and its Sphere::Sample
   the whole sphere whatever zmin, zmax and phimax say, while their areas count
   only the part; specnee samples exactly the part that exists.)

   USE.  geometry.c fills Shape.q (quadric_set_transform and the parameters), Shape.area
   (quadric_area) and Scene.quadric_shape; bvh.c bounds (quadric_bounds) and
   intersects (quadric_intersect) quadric k as primitive n_tris + n_spheres + k,
   and scene_surface_point calls quadric_surface_point; lights.c samples an emitting
   quadric (quadric_sample, density 1 / quadric_area_at), gives a disk its plane for
   emitter_can_reach and the light tree a box and a normal cone.
*/
#include "specnee.h"
#include <float.h>

#define TWO_PI (2.0 * SPECNEE_PI)

/* ------------------------------------------------------------------ transforms */

int quadric_set_transform(Quadric *q, const Xform *ctm)
{
    const double (*m)[4] = (const double (*)[4])ctm->m;
    double col[3][3], len[3];
    int i, j;
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0) return 0;
    q->world_from_obj = *ctm;
    /* a similarity: the 3x3 part's columns are orthogonal and equally long (the
       same tolerance as geometry.c's test for whole spheres) */
    for (j = 0; j < 3; j++) {
        for (i = 0; i < 3; i++) col[j][i] = m[i][j];
        len[j] = sqrt(col[j][0] * col[j][0] + col[j][1] * col[j][1] + col[j][2] * col[j][2]);
    }
    q->sim_scale = len[0];
    q->similarity = 1;
    for (j = 0; j < 3; j++) {
        int k = (j + 1) % 3;
        double dot = col[j][0] * col[k][0] + col[j][1] * col[k][1] + col[j][2] * col[k][2];
        if (fabs(len[j] - len[0]) > 1e-5 * len[0] || fabs(dot) > 1e-5 * len[0] * len[0])
            q->similarity = 0;
    }
    return 1;
}

/* The world ray (o, d) in object space, in double. */
static void ray_to_object(const Quadric *q, const Ray *r, double o[3], double d[3])
{
    const double (*inv)[4] = (const double (*)[4])q->world_from_obj.inv;
    int i;
    for (i = 0; i < 3; i++) {
        o[i] = inv[i][0] * r->o.x + inv[i][1] * r->o.y + inv[i][2] * r->o.z + inv[i][3];
        d[i] = inv[i][0] * r->d.x + inv[i][1] * r->d.y + inv[i][2] * r->d.z;
    }
}

/* Object point p to the world (M p). */
static Vec3 point_to_world(const Quadric *q, const double p[3])
{
    const double (*m)[4] = (const double (*)[4])q->world_from_obj.m;
    double w[3];
    int i;
    for (i = 0; i < 3; i++) w[i] = m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3];
    return v3((float)w[0], (float)w[1], (float)w[2]);
}

/* Object normal n to the world (M^-T n, i.e. n_i = sum_j inv[j][i] n_j), in double,
   with its length before normalising in *len (the |L^-T n| of the area factor). */
static void normal_to_world(const Quadric *q, const double n[3], double w[3], double *len)
{
    const double (*inv)[4] = (const double (*)[4])q->world_from_obj.inv;
    int i;
    for (i = 0; i < 3; i++) w[i] = inv[0][i] * n[0] + inv[1][i] * n[1] + inv[2][i] * n[2];
    *len = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
}

/* The unit object normal at object point p (on the surface), before flip. */
static void object_normal(const Shape *sh, const double p[3], double n[3])
{
    const double R = sh->q.radius;
    if (sh->type == SHAPE_DISK) { n[0] = 0.0; n[1] = 0.0; n[2] = 1.0; return; }
    n[0] = p[0] / R;
    n[1] = p[1] / R;
    n[2] = sh->type == SHAPE_CYLINDER ? 0.0 : p[2] / R;
}

/* The world position and oriented unit normal of object point p (on the surface). */
static void to_world(const Shape *sh, const double p[3], Vec3 *pw, Vec3 *nw)
{
    double n[3], w[3], len;
    object_normal(sh, p, n);
    normal_to_world(&sh->q, n, w, &len);
    *pw = point_to_world(&sh->q, p);
    if (len > 0.0) *nw = v3((float)(w[0] / len), (float)(w[1] / len), (float)(w[2] / len));
    else *nw = v3(0.0f, 0.0f, 1.0f);               /* (a singular CTM is refused by geometry.c) */
    if (sh->flip) *nw = v3_neg(*nw);
}

/* ------------------------------------------------------------------ intersection */

/* 1 if object point p (on the full surface) lies on the part that is kept. */
static int kept(const Shape *sh, const double p[3])
{
    const Quadric *q = &sh->q;
    if (sh->type == SHAPE_DISK) {
        double r2 = p[0] * p[0] + p[1] * p[1];
        if (r2 > q->radius * q->radius || r2 < q->inner * q->inner) return 0;
    } else {
        /* a sphere tests only the cuts it has (pbrt-v4): a root of a whole sphere
           may round a hair beyond +-radius */
        if ((sh->type == SHAPE_CYLINDER || q->zmin > -q->radius) && p[2] < q->zmin) return 0;
        if ((sh->type == SHAPE_CYLINDER || q->zmax < q->radius) && p[2] > q->zmax) return 0;
    }
    if (q->phimax < TWO_PI) {
        double phi = atan2(p[1], p[0]);
        if (phi < 0.0) phi += TWO_PI;
        if (phi > q->phimax) return 0;
    }
    return 1;
}

int quadric_intersect(const Shape *sh, const Ray *r, float tmax, float *t_out)
{
    const Quadric *q = &sh->q;
    double o[3], d[3], root[2], a, b, c, ll, disc, qq, R = q->radius;
    int dims, k, i;
    ray_to_object(q, r, o, d);
    if (sh->type == SHAPE_DISK) {
        double t, p[3];
        float tf;
        if (d[2] == 0.0) return 0;                 /* parallel to the disk's plane */
        t = (q->height - o[2]) / d[2];
        tf = (float)t;
        if (!(tf > 0.0f && tf <= tmax)) return 0;  /* tmax itself counts: ties, as bvh.c */
        p[0] = o[0] + t * d[0]; p[1] = o[1] + t * d[1]; p[2] = q->height;
        if (!kept(sh, p)) return 0;
        *t_out = tf;
        return 1;
    }
    /* the quadratic: over x, y for the cylinder, x, y, z for the sphere */
    dims = sh->type == SHAPE_CYLINDER ? 2 : 3;
    a = b = c = ll = 0.0;
    for (k = 0; k < dims; k++) {
        a += d[k] * d[k];
        b += o[k] * d[k];
        c += o[k] * o[k];
    }
    if (!(a > 0.0)) return 0;                      /* along the cylinder's axis */
    c -= R * R;
    for (k = 0; k < dims; k++) {                   /* o - (b/a) d: the closest approach */
        double l = o[k] - (b / a) * d[k];
        ll += l * l;
    }
    disc = a * (R * R - ll);
    if (disc < 0.0) return 0;
    qq = -(b + (b < 0.0 ? -sqrt(disc) : sqrt(disc)));
    if (qq == 0.0) return 0;                       /* tangent at the origin itself */
    root[0] = qq / a;
    root[1] = c / qq;
    if (root[0] > root[1]) { double tmp = root[0]; root[0] = root[1]; root[1] = tmp; }
    for (i = 0; i < 2; i++) {
        float tf = (float)root[i];
        double p[3];
        if (!(tf > 0.0f)) continue;                /* behind the origin */
        if (!(tf <= tmax)) return 0;               /* the farther root is farther still */
        for (k = 0; k < 3; k++) p[k] = o[k] + root[i] * d[k];
        if (!kept(sh, p)) continue;                /* cut away: try the far wall */
        *t_out = tf;
        return 1;
    }
    return 0;
}

void quadric_surface_point(const Shape *sh, const Ray *r, float t, SurfacePoint *sp)
{
    const Quadric *q = &sh->q;
    double o[3], d[3], p[3], len, s;
    int k;
    ray_to_object(q, r, o, d);
    for (k = 0; k < 3; k++) p[k] = o[k] + (double)t * d[k];
    /* onto the surface, so that p is as exact as float allows */
    if (sh->type == SHAPE_DISK) {
        p[2] = q->height;
    } else {
        len = sh->type == SHAPE_CYLINDER ? sqrt(p[0] * p[0] + p[1] * p[1])
                                         : sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        s = len > 0.0 ? q->radius / len : 1.0;
        p[0] *= s; p[1] *= s;
        if (sh->type == SHAPE_SPHERE_PART) p[2] *= s;
    }
    to_world(sh, p, &sp->p, &sp->ng);
    sp->ns = sp->ng;
    /* pbrt-v4's (u, v) parameters (texture.c's "uv" mapping): u = phi / phimax;
       v: disk (radius - r) / (radius - innerradius), cylinder (z - zmin) / (zmax -
       zmin), sphere (theta - theta(zmin)) / (theta(zmax) - theta(zmin)) */
    {
        double phi = atan2(p[1], p[0]), v;
        if (phi < 0.0) phi += 2.0 * SPECNEE_PI;
        sp->u = (float)(phi / q->phimax);
        if (sh->type == SHAPE_DISK) {
            v = (q->radius - sqrt(p[0] * p[0] + p[1] * p[1])) / (q->radius - q->inner);
        } else if (sh->type == SHAPE_CYLINDER) {
            v = (p[2] - q->zmin) / (q->zmax - q->zmin);
        } else {
            double r = q->radius, c = p[2] / r, c0 = q->zmin / r, c1 = q->zmax / r;
            double t0 = acos(c0 < -1.0 ? -1.0 : c0 > 1.0 ? 1.0 : c0);
            double t1 = acos(c1 < -1.0 ? -1.0 : c1 > 1.0 ? 1.0 : c1);
            v = (acos(c < -1.0 ? -1.0 : c > 1.0 ? 1.0 : c) - t0) / (t1 - t0);
        }
        sp->v = (float)v;
    }
}

/* ------------------------------------------------------------------ bounds and area */

void quadric_bounds(const Shape *sh, float lo[3], float hi[3])
{
    const Quadric *q = &sh->q;
    double olo[3], ohi[3], wlo[3], whi[3];
    const double (*m)[4] = (const double (*)[4])q->world_from_obj.m;
    int c, a;
    /* the object box (ignoring phimax and innerradius: conservative) */
    olo[0] = olo[1] = -q->radius;
    ohi[0] = ohi[1] = q->radius;
    if (sh->type == SHAPE_DISK) olo[2] = ohi[2] = q->height;
    else { olo[2] = q->zmin; ohi[2] = q->zmax; }
    for (a = 0; a < 3; a++) { wlo[a] = INFINITY; whi[a] = -INFINITY; }
    for (c = 0; c < 8; c++) {                      /* its eight corners in the world */
        double p[3];
        p[0] = c & 1 ? ohi[0] : olo[0];
        p[1] = c & 2 ? ohi[1] : olo[1];
        p[2] = c & 4 ? ohi[2] : olo[2];
        for (a = 0; a < 3; a++) {
            double w = m[a][0] * p[0] + m[a][1] * p[1] + m[a][2] * p[2] + m[a][3];
            if (w < wlo[a]) wlo[a] = w;
            if (w > whi[a]) whi[a] = w;
        }
    }
    for (a = 0; a < 3; a++) {                      /* rounded outwards */
        lo[a] = nextafterf((float)wlo[a], -FLT_MAX);
        hi[a] = nextafterf((float)whi[a], FLT_MAX);
    }
}

/* |det L|, L the CTM's 3x3 part. */
static double det3(const Quadric *q)
{
    const double (*m)[4] = (const double (*)[4])q->world_from_obj.m;
    return fabs(m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]));
}

int quadric_uniform_sampling(const Shape *sh)
{
    return sh->type == SHAPE_DISK || sh->q.similarity;
}

/* The object point of the (u1, u2) parameterisation that quadric_sample draws
   from (uniform by object area). */
static void object_point(const Shape *sh, double u1, double u2, double p[3])
{
    const Quadric *q = &sh->q;
    const double phi = u2 * q->phimax;
    double rho, z;
    if (sh->type == SHAPE_DISK) {
        rho = sqrt(q->inner * q->inner + u1 * (q->radius * q->radius - q->inner * q->inner));
        z = q->height;
    } else {
        z = q->zmin + u1 * (q->zmax - q->zmin);
        rho = sh->type == SHAPE_CYLINDER ? q->radius
                                         : sqrt(fmax(0.0, q->radius * q->radius - z * z));
    }
    p[0] = rho * cos(phi);
    p[1] = rho * sin(phi);
    p[2] = z;
}

/* The object-space area of the part kept. */
static double object_area(const Shape *sh)
{
    const Quadric *q = &sh->q;
    const double R = q->radius;
    if (sh->type == SHAPE_DISK) return 0.5 * q->phimax * (R * R - q->inner * q->inner);
    return q->phimax * R * (q->zmax - q->zmin);
}

double quadric_area(const Shape *sh)
{
    const Quadric *q = &sh->q;
    double a_obj = object_area(sh), det = det3(q), n[3], w[3], len, sum = 0.0;
    int i, j;
    const int N = 64;
    if (q->similarity) return a_obj * q->sim_scale * q->sim_scale;
    if (sh->type == SHAPE_DISK) {                  /* one normal: a constant factor */
        n[0] = 0.0; n[1] = 0.0; n[2] = 1.0;
        normal_to_world(q, n, w, &len);
        return a_obj * det * len;
    }
    /* the mean factor |det L| |L^-T n| by the midpoint rule, uniform by object area */
    for (i = 0; i < N; i++)
        for (j = 0; j < N; j++) {
            double p[3];
            object_point(sh, (i + 0.5) / N, (j + 0.5) / N, p);
            object_normal(sh, p, n);
            normal_to_world(q, n, w, &len);
            sum += len;
        }
    return a_obj * det * sum / ((double)N * N);
}

/* quadric_sample draws object points with density 1 / a_obj per object area; a
   world element is |det L| |L^-T n| times its object element (AREA above), so the
   density per world area at p is 1 / (a_obj |det L| |L^-T n(p)|).  This returns
   that denominator: Shape.area where the factor is constant (the same double as
   before any sampling), and at the object point under p otherwise (an ellipsoid,
   an elliptic cylinder). */
double quadric_area_at(const Shape *sh, Vec3 p)
{
    const Quadric *q = &sh->q;
    const double (*inv)[4] = (const double (*)[4])q->world_from_obj.inv;
    double po[3], n[3], w[3], len, nn;
    int i;
    if (quadric_uniform_sampling(sh)) return sh->area;
    for (i = 0; i < 3; i++)
        po[i] = inv[i][0] * p.x + inv[i][1] * p.y + inv[i][2] * p.z + inv[i][3];
    object_normal(sh, po, n);
    nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);   /* p may sit a rounding off */
    if (!(nn > 0.0)) return sh->area;
    for (i = 0; i < 3; i++) n[i] /= nn;
    normal_to_world(q, n, w, &len);
    return object_area(sh) * det3(q) * len;
}

void quadric_sample(const Shape *sh, float u1, float u2, Vec3 *p, Vec3 *n)
{
    double po[3];
    object_point(sh, u1, u2, po);
    to_world(sh, po, p, n);
}
