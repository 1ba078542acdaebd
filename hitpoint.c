/* hitpoint.c - what a hit is: its point, normals and (u, v), and where a ray
   leaving it starts.

   WHAT IT IMPLEMENTS (specnee.h section 5)
     scene_surface_point    position, geometric and shading normals and (u, v) at a
                            hit of bvh_intersect (pbrt-v4 conventions), in object
                            space first for a hit inside an instance
     offset_ray_origin      where a secondary ray starts (the policy below)
     spawn_origin           the same from a hit, past a curve hit's error box
     offset_eps             the policy's distance for a point of largest
                            coordinate m
   USE: the integrator calls bvh_intersect (bvh.c), then scene_surface_point, and
   starts the next ray and the shadow rays at spawn_origin; bvh.c's alpha test
   calls both to go on past a hit that does not count.

   SELF-INTERSECTION POLICY (how secondary rays avoid hitting their own surface)
     1. scene_surface_point computes p from the barycentrics in double, so p lies within
        half an ulp of the triangle's plane (for spheres: reprojected onto the sphere).
     2. offset_ray_origin(p, ng, w) moves p along ng, to the side of w, by
            eps = 1e-5 (1 + max_i |p_i|)    (about 80 float ulps of the largest coordinate)
        so the new origin is certainly on w's side of the surface it left.
     3. The triangle test (bvh.c) rejects t below its error bound, so a ray leaving a triangle
        cannot re-hit it, even when that triangle's vertices are far larger than p; for
        spheres the double-precision roots do the same.
     4. A curve (curve.c) is a band that faces every ray, so a ray leaving it would
        meet it again at once; as in pbrt-v4 the hit carries an error box of about a
        width (SurfacePoint.err) and spawn_origin starts the ray |ng| . err further
        along ng (0 for every other shape: then it is offset_ray_origin).
     The shadow rays of next event estimation run from o = spawn_origin(sp, w)
     (in a medium: o = p) to q' = offset_ray_origin(q, n_q, -w), the emitter point q
     moved off the emitter towards p, with d = q' - o and tmax = 1: the segment ends
     short of the emitter, so the emitter does not occlude itself.
*/
#include "specnee.h"
#include <math.h>

void scene_surface_point(const Scene *s, const Ray *r, const HitRecord *h, SurfacePoint *sp)
{
    if (h->inst >= 0 && h->inst < s->n_instances) {
        /* in an instance: the point in object space, then put into the world */
        Xform tmp;
        const Xform *x = instance_xf(s, &s->instances[h->inst], r, &tmp);
        const Ray ro = instance_ray(x, r);
        HitRecord ho = *h;
        ho.inst = -1;
        scene_surface_point(s, &ro, &ho, sp);
        instance_point(x, sp);
        return;
    }
    sp->prim = h->prim;
    sp->err = v3(0.0f, 0.0f, 0.0f);
    if (h->prim >= s->n_tris + s->n_spheres + s->n_quadrics + s->n_patches) {
        curve_surface_point(s, &s->curve_pieces[h->prim - s->n_tris - s->n_spheres - s->n_quadrics - s->n_patches],
                            r, h, sp, NULL, NULL);
    } else if (h->prim < s->n_tris) {
        const Triangle *tri = &s->tris[h->prim];
        const Shape *sh = &s->shapes[tri->shape];
        Vec3 p0 = s->P[tri->v[0]], p1 = s->P[tri->v[1]], p2 = s->P[tri->v[2]];
        double b1 = h->b1, b2 = h->b2, b0 = 1.0 - b1 - b2;
        /* p = b0 p0 + b1 p1 + b2 p2 in double: p lies within half an ulp of the plane */
        sp->p = v3((float)(b0 * p0.x + b1 * p1.x + b2 * p2.x),
                   (float)(b0 * p0.y + b1 * p1.y + b2 * p2.y),
                   (float)(b0 * p0.z + b1 * p1.z + b2 * p2.z));
        /* pbrt-v4: n = normalize(cross(p0 - p2, p1 - p2)), the right-hand normal of the
           counter-clockwise (p0, p1, p2) */
        sp->ng = v3_norm(v3_cross(v3_sub(p0, p2), v3_sub(p1, p2)));
        if (v3_dot(sp->ng, sp->ng) == 0.0f)        /* sliver too thin for float */
            sp->ng = v3_norm(v3_neg(r->d));
        if (sh->flip) sp->ng = v3_neg(sp->ng);
        sp->ns = sp->ng;
        if (sh->has_normals && s->N && !sh->bilinear) {     /* (a patch: patch_shading) */
            Vec3 n0 = s->N[tri->v[0]], n1 = s->N[tri->v[1]], n2 = s->N[tri->v[2]];
            Vec3 ns = v3((float)(b0 * n0.x + b1 * n1.x + b2 * n2.x),
                         (float)(b0 * n0.y + b1 * n1.y + b2 * n2.y),
                         (float)(b0 * n0.z + b1 * n1.z + b2 * n2.z));
            if (v3_dot(ns, ns) > 0.0f) {
                /* the shading normal is authoritative for orientation (pbrt-v4) */
                sp->ns = v3_norm(ns);
                if (v3_dot(sp->ng, sp->ns) < 0.0f) sp->ng = v3_neg(sp->ng);
            }
        }
        /* (u, v): the mesh's "uv" interpolated, else pbrt-v4's default corners
           (0,0), (1,0), (1,1), i.e. u = b1 + b2, v = b2; a flat bilinear patch's
           triangle: the patch's own (u, v) at p, "uv" and "N" bilinear (patch.c) */
        if (sh->bilinear) {
            int32_t q[4];
            float pu, pv;
            flat_patch_uv(s, sh, h->prim, sp->p, q, &pu, &pv);
            patch_shading(s, sh, q, pu, pv, sp);
        } else if (sh->has_uv && s->UV) {
            const float *t0 = s->UV + 2 * tri->v[0], *t1 = s->UV + 2 * tri->v[1], *t2 = s->UV + 2 * tri->v[2];
            sp->u = (float)(b0 * t0[0] + b1 * t1[0] + b2 * t2[0]);
            sp->v = (float)(b0 * t0[1] + b1 * t1[1] + b2 * t2[1]);
        } else {
            sp->u = (float)(b1 + b2);
            sp->v = (float)b2;
        }
        sp->shape = tri->shape;
    } else if (h->prim >= s->n_tris + s->n_spheres + s->n_quadrics) {
        const Patch *pa = &s->patches[h->prim - s->n_tris - s->n_spheres - s->n_quadrics];
        patch_surface_point(s, &s->shapes[pa->shape], pa->v, h->b1, h->b2, r, sp);
        sp->shape = pa->shape;
    } else if (h->prim >= s->n_tris + s->n_spheres) {
        int shape = s->quadric_shape[h->prim - s->n_tris - s->n_spheres];
        quadric_surface_point(&s->shapes[shape], r, h->t, sp);
        sp->shape = shape;
    } else {
        int shape = s->sphere_shape[h->prim - s->n_tris];
        const Shape *sh = &s->shapes[shape];
        double q[3], c[3], len = 0, scale;
        int a;
        c[0] = sh->center.x; c[1] = sh->center.y; c[2] = sh->center.z;
        q[0] = (double)r->o.x + (double)h->t * r->d.x - c[0];
        q[1] = (double)r->o.y + (double)h->t * r->d.y - c[1];
        q[2] = (double)r->o.z + (double)h->t * r->d.z - c[2];
        for (a = 0; a < 3; a++) len += q[a] * q[a];
        len = sqrt(len);
        /* reproject onto the sphere, so p is as exact as float allows */
        scale = len > 0.0 ? 1.0 / len : 0.0;
        sp->ng = v3((float)(q[0] * scale), (float)(q[1] * scale), (float)(q[2] * scale));
        if (len == 0.0) sp->ng = v3_norm(v3_neg(r->d));
        sp->p = v3((float)(c[0] + sh->radius * q[0] * scale),
                   (float)(c[1] + sh->radius * q[1] * scale),
                   (float)(c[2] + sh->radius * q[2] * scale));
        if (sh->flip) sp->ng = v3_neg(sp->ng);
        sp->ns = sp->ng;
        sp->shape = shape;
        /* pbrt-v4's sphere parameters in object space: u = phi / 2 pi, v = 1 -
           theta / pi of the direction o = (object from world) q, the CTM's 3x3 part
           being a rotation (or mirror) times a scale (scene.c); only an alpha
           texture or a material that reads them needs them (Shape.reads_uv; two
           inverse trigonometric calls) */
        sp->u = sp->v = 0.0f;
        if (sh->reads_uv) {
            const double (*oi)[4] = (const double (*)[4])sh->q.world_from_obj.inv;
            double o[3], olen = 0.0, phi, ct;
            for (a = 0; a < 3; a++) {
                o[a] = oi[a][0] * q[0] + oi[a][1] * q[1] + oi[a][2] * q[2];
                olen += o[a] * o[a];
            }
            olen = sqrt(olen);
            phi = atan2(o[1], o[0]);
            ct = olen > 0.0 ? o[2] / olen : 1.0;
            if (phi < 0.0) phi += 2.0 * SPECNEE_PI;
            ct = ct < -1.0 ? -1.0 : ct > 1.0 ? 1.0 : ct;
            sp->u = (float)(phi / (2.0 * SPECNEE_PI));
            sp->v = (float)(1.0 - acos(ct) / SPECNEE_PI);
        }
    }
}

float offset_eps(float m) { return 1e-5f * (1.0f + m); }   /* the policy above */

Vec3 offset_ray_origin(Vec3 p, Vec3 ng, Vec3 w)
{
    float m = fabsf(p.x), eps;
    if (fabsf(p.y) > m) m = fabsf(p.y);
    if (fabsf(p.z) > m) m = fabsf(p.z);
    eps = offset_eps(m);
    if (v3_dot(ng, w) < 0.0f) eps = -eps;          /* to w's side of the surface */
    return v3_add(p, v3_mul(ng, eps));
}

Vec3 spawn_origin(const SurfacePoint *sp, Vec3 w)
{
    const float d = fabsf(sp->ng.x) * sp->err.x + fabsf(sp->ng.y) * sp->err.y + fabsf(sp->ng.z) * sp->err.z;
    Vec3 o = offset_ray_origin(sp->p, sp->ng, w);
    if (d > 0.0f) o = v3_add(o, v3_mul(sp->ng, v3_dot(sp->ng, w) < 0.0f ? -d : d));
    return o;
}
