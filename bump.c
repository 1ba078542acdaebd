/* bump.c - shading-normal perturbation: bump and normal maps (pbrt-v4's BumpMap
   and NormalMap; pbrt book 4th ed. section 10.5.3; THEORY §14).

   WHAT IT IMPLEMENTS (specnee.h section 6)
     shading_differentials  pbrt-v4's shading dp/du, dp/dv, dn/du, dn/dv at a hit
     tangent_shade          the hit with its shading dp/du, for the BSDFs that turn
                            with it (an anisotropic conductor or measured file);
                            bump_shade sets the bumped dp/du itself (pbrt-v4's)
     bump_shade             the hit with the shading normal of its material's
                            "displacement" or "normalmap"
     bump_from_params       those two parameters of a Material (parser.h)
     normalmap_ignored      the "normalmap" of a material pbrt-v4 gives none
                            (interface, mix, hair): the file must open, then a note
   path.c calls bump_shade at a surface vertex whose material has a Bump, after a
   mix has chosen its material and before NEE and BSDF sampling, so that the BSDF
   frame, the |cos| of both estimators and the light tree's receiver cone all use
   the perturbed normal; the geometric normal (ray offsets, media, the BSDFs' leak
   tests) stays the shape's.

   THE DIFFERENTIAL GEOMETRY (pbrt-v4's InteractionFromIntersection of each shape).
     triangle   from its (u, v) ("uv", else (0,0), (1,0), (1,1)):
                  [dp/du; dp/dv] = [du02 dv02; du12 dv12]^-1 [p0 - p2; p1 - p2],
                an arbitrary frame around the normal when the uv determinant is
                below 1e-9 in size; with "N" or "S" the shading frame is ss made
                tangent to ns (ss = cross(ns x ss, ns)), ts = ns x ss, where ss is
                "S" interpolated at the hit (dp/du where that is 0, or without "S")
                and ns the shading normal (the geometric one without "N"); dn/du,
                dn/dv come from the vertex normals as dp/du, dp/dv from the
                positions (0 without "N").
     quadrics   in object space, then to the world by M (dn by M^-T): for
                phi = u phimax, dp/du = phimax (-y, x, 0); disk dp/dv = (x, y, 0)
                (ri - r) / |(x, y)|; cylinder (0, 0, zmax - zmin); sphere
                (thmax - thmin) (z cos phi, z sin phi, -r sin theta); dn/du, dn/dv
                by the Weingarten equations
                  dn/du = ((fF - eG) dp/du + (eF - fE) dp/dv) / (EG - F^2),
                  dn/dv = ((gF - fG) dp/du + (fF - gE) dp/dv) / (EG - F^2),
                with E, F, G = dp/du.dp/du, dp/du.dp/dv, dp/dv.dp/dv and e, f, g
                = n.d2p/du2, n.d2p/dudv, n.d2p/dv2 (n unoriented).
     patches    dp/du = lerp(v, p10, p11) - lerp(v, p00, p01), dp/dv likewise,
                re-expressed per (s, t) of "uv" as pbrt-v4 does it, with the
                reciprocals of the single partials (du/ds = 1 / (ds/du), 0 below
                1e-8), not the inverse of the 2 x 2 Jacobian: a "uv" that is not
                axis-aligned with the patch gives large tangents, in pbrt-v4 too;
                "N": the frame rotated from n to ns (pbrt-v4's RotateFromTo) and
                dn from the vertex normals.
     curves     curve.c's dp/du (along the segment) and dp/dv (across the band),
                dn/du = dn/dv = 0, as pbrt-v4.
     instances  computed in the object's space and carried to the world as above.

   BUMP MAP ("float displacement" or "texture displacement" d): the surface is
   moved to p' = p + d(p) ns, so
       dp'/du = dp/du + (dd/du) ns + d dn/du,   dp'/dv = dp/dv + (dd/dv) ns + d dn/dv,
   dd/du by a forward difference: (d(p + du dp/du, u + du) - d(p, u)) / du.  pbrt-v4
   takes du = (|du/dx| + |du/dy|) / 2 from ray differentials and 0.0005 when that is
   0; specnee has no ray differentials and always takes 0.0005 (the same for v).
   The derivative is the same to first order wherever d is smooth over the
   pixel's footprint (for textures that vary within a pixel pbrt-v4 smooths more).
   NORMAL MAP ("string normalmap", an RGB image read linearly, wrapped, bilinear,
   looked up at (u, 1 - v) as image textures are): n_t = normalize(2 rgb - 1) in
   the frame (x = normalize(dp/du), y = ns x x, z = ns), then
       dp'/du = normalize(dp/du - (dp/du.n) n) |dp/du|,  dp'/dv = normalize(n x dp'/du) |dp/dv|.
   Both: ns' = normalize(dp'/du x dp'/dv), turned to the geometric normal's side
   (pbrt-v4's SetShadingGeometry, orientation not authoritative).  A normal map
   wins over a displacement when a material has both, as in pbrt-v4. */
#include "specnee.h"
#include "parser.h"
#include <stdlib.h>
#include <string.h>

#define BUMP_DELTA 0.0005f   /* pbrt-v4's du, dv without ray differentials */

/* ------------------------------------------------------------------ 1. geometry */

/* dn/du and dn/dv from the fundamental forms (the Weingarten equations above). */
static void weingarten(Vec3 dpdu, Vec3 dpdv, Vec3 d2uu, Vec3 d2uv, Vec3 d2vv, ShadingDiff *d)
{
    float E = v3_dot(dpdu, dpdu), F = v3_dot(dpdu, dpdv), G = v3_dot(dpdv, dpdv);
    Vec3 n = v3_norm(v3_cross(dpdu, dpdv));
    float e = v3_dot(n, d2uu), f = v3_dot(n, d2uv), g = v3_dot(n, d2vv);
    float egf2 = E * G - F * F, inv = egf2 == 0.0f ? 0.0f : 1.0f / egf2;
    d->dndu = v3_add(v3_mul(dpdu, (f * F - e * G) * inv), v3_mul(dpdv, (e * F - f * E) * inv));
    d->dndv = v3_add(v3_mul(dpdu, (g * F - f * G) * inv), v3_mul(dpdv, (f * F - g * E) * inv));
}

/* A quadric's (or a sphere's) derivatives at world point pw, in the world; the
   full sphere's (u, v) too (bvh.c leaves them 0 unless a texture reads them). */
static void quadric_diff(const Shape *sh, Vec3 pw, ShadingDiff *d, float *u, float *v)
{
    const Quadric *q = &sh->q;
    Xform inv;
    Vec3 p, z3 = v3(0, 0, 0);
    float phimax = sh->type == SHAPE_SPHERE ? 2.0f * PI_F : (float)q->phimax;
    float rxy;
    memcpy(inv.m, q->world_from_obj.inv, sizeof inv.m);
    memcpy(inv.inv, q->world_from_obj.m, sizeof inv.inv);
    p = xf_point(&inv, pw);
    rxy = sqrtf(p.x * p.x + p.y * p.y);
    d->dpdu = v3(-phimax * p.y, phimax * p.x, 0.0f);
    if (sh->type == SHAPE_DISK) {
        d->dpdv = rxy > 0.0f ? v3_mul(v3(p.x, p.y, 0.0f), (float)(q->inner - q->radius) / rxy) : z3;
        d->dndu = d->dndv = z3;
    } else if (sh->type == SHAPE_CYLINDER) {
        d->dpdv = v3(0.0f, 0.0f, (float)(q->zmax - q->zmin));
        weingarten(d->dpdu, d->dpdv, v3_mul(v3(p.x, p.y, 0.0f), -phimax * phimax), z3, z3, d);
    } else {                                       /* full or partial sphere */
        float r = sh->type == SHAPE_SPHERE ? v3_len(p) : (float)q->radius;
        float c0 = sh->type == SHAPE_SPHERE ? -1.0f : (float)(q->zmin / q->radius);
        float c1 = sh->type == SHAPE_SPHERE ? 1.0f : (float)(q->zmax / q->radius);
        float th0 = acosf(fminf(1.0f, fmaxf(-1.0f, c0))), th1 = acosf(fminf(1.0f, fmaxf(-1.0f, c1)));
        float ct = r > 0.0f ? fminf(1.0f, fmaxf(-1.0f, p.z / r)) : 1.0f, st = sqrtf(fmaxf(0.0f, 1.0f - ct * ct));
        float cp = rxy > 0.0f ? p.x / rxy : 1.0f, sp = rxy > 0.0f ? p.y / rxy : 0.0f, dth = th1 - th0;
        d->dpdv = v3_mul(v3(p.z * cp, p.z * sp, -r * st), dth);
        weingarten(d->dpdu, d->dpdv, v3_mul(v3(p.x, p.y, 0.0f), -phimax * phimax),
                   v3_mul(v3(-sp, cp, 0.0f), dth * p.z * phimax), v3_mul(p, -dth * dth), d);
        if (sh->type == SHAPE_SPHERE) {
            float phi = atan2f(p.y, p.x);
            if (phi < 0.0f) phi += 2.0f * PI_F;
            *u = phi / phimax;
            *v = (acosf(ct) - th0) / dth;
        }
    }
    d->dpdu = xf_vector(&q->world_from_obj, d->dpdu);
    d->dpdv = xf_vector(&q->world_from_obj, d->dpdv);
    d->dndu = xf_normal(&q->world_from_obj, d->dndu);
    d->dndv = xf_normal(&q->world_from_obj, d->dndv);
}

/* pbrt-v4's CoordinateSystem: two vectors completing the unit n to a frame. */
static void coordinate_system(Vec3 n, Vec3 *a, Vec3 *b)
{
    Frame f = frame_from_normal(n);
    *a = f.s;
    *b = f.t;
}

/* [x; y] = [a00 a01; a10 a11]^-1 [r0; r1] for 3-vectors r (0 when singular: *ok 0). */
static int solve2(float a00, float a01, float a10, float a11, Vec3 r0, Vec3 r1, Vec3 *x, Vec3 *y)
{
    float det = a00 * a11 - a01 * a10, inv;
    if (fabsf(det) < 1e-9f) return 0;
    inv = 1.0f / det;
    *x = v3_mul(v3_sub(v3_mul(r0, a11), v3_mul(r1, a01)), inv);
    *y = v3_mul(v3_sub(v3_mul(r1, a00), v3_mul(r0, a10)), inv);
    return 1;
}

/* The tangent "S" interpolated at the hit (barycentrics of h), or dpdu where it is 0
   (pbrt-v4's Triangle: the shading frame's ss before it is made tangent). */
static Vec3 triangle_tangent(const Scene *s, const Triangle *tri, const HitRecord *h, Vec3 dpdu)
{
    double b1 = h->b1, b2 = h->b2, b0 = 1.0 - b1 - b2;
    Vec3 s0 = s->S[tri->v[0]], s1 = s->S[tri->v[1]], s2 = s->S[tri->v[2]];
    Vec3 ss = v3((float)(b0 * s0.x + b1 * s1.x + b2 * s2.x), (float)(b0 * s0.y + b1 * s1.y + b2 * s2.y),
                 (float)(b0 * s0.z + b1 * s1.z + b2 * s2.z));
    return v3_dot(ss, ss) > 0.0f ? ss : dpdu;
}

/* Triangle h->prim (not of a bilinear mesh) with the shading normal sp->ns. */
static void triangle_diff(const Scene *s, const HitRecord *h, const SurfacePoint *sp, ShadingDiff *d)
{
    const Triangle *tri = &s->tris[h->prim];
    const Shape *sh = &s->shapes[tri->shape];
    Vec3 p0 = s->P[tri->v[0]], p1 = s->P[tri->v[1]], p2 = s->P[tri->v[2]];
    float uv[3][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 } };
    Vec3 dp02 = v3_sub(p0, p2), dp12 = v3_sub(p1, p2), z3 = v3(0, 0, 0);
    float du02, dv02, du12, dv12;
    int k, ok, normals = sh->has_normals && s->N, tangents = sh->has_tangents && s->S;
    if (sh->has_uv && s->UV)
        for (k = 0; k < 3; k++) { uv[k][0] = s->UV[2 * tri->v[k]]; uv[k][1] = s->UV[2 * tri->v[k] + 1]; }
    du02 = uv[0][0] - uv[2][0]; dv02 = uv[0][1] - uv[2][1];
    du12 = uv[1][0] - uv[2][0]; dv12 = uv[1][1] - uv[2][1];
    /* [du02 dv02; du12 dv12] [dpdu; dpdv] = [dp02; dp12] */
    ok = solve2(du02, dv02, du12, dv12, dp02, dp12, &d->dpdu, &d->dpdv);
    if (!ok || v3_dot(v3_cross(d->dpdu, d->dpdv), v3_cross(d->dpdu, d->dpdv)) == 0.0f)
        coordinate_system(v3_norm(v3_cross(v3_sub(p2, p0), v3_sub(p1, p0))), &d->dpdu, &d->dpdv);
    d->dndu = d->dndv = z3;
    if (!normals && !tangents) return;
    {   /* the shading frame around ns (from S when given), and dn from the vertex normals */
        Vec3 ns = sp->ns, ss = tangents ? triangle_tangent(s, tri, h, d->dpdu) : d->dpdu;
        Vec3 ts = v3_cross(ns, ss);
        if (v3_dot(ts, ts) > 0.0f) ss = v3_cross(ts, ns);
        else coordinate_system(ns, &ss, &ts);
        d->dpdu = ss;
        d->dpdv = ts;
    }
    if (normals) {
        Vec3 n0 = s->N[tri->v[0]], n1 = s->N[tri->v[1]], n2 = s->N[tri->v[2]];
        if (!solve2(du02, dv02, du12, dv12, v3_sub(n0, n2), v3_sub(n1, n2), &d->dndu, &d->dndv)) {
            Vec3 dn = v3_cross(v3_sub(n2, n0), v3_sub(n1, n0));
            d->dndu = d->dndv = z3;
            /* (pbrt-v4 hands CoordinateSystem the cross product unnormalised) */
            if (v3_dot(dn, dn) > 0.0f) coordinate_system(dn, &d->dndu, &d->dndv);
        }
    }
}

/* pbrt-v4's RotateFromTo(from, to) applied to w: two reflections, through the
   plane normal to refl - from and then to refl - to (refl the axis both are far from). */
static Vec3 rotate_from_to(Vec3 from, Vec3 to, Vec3 w)
{
    Vec3 refl, u, v, r;
    float uu, vv, uv, a[3], b[3], x[3] = { w.x, w.y, w.z }, out[3];
    int i, j;
    if (fabsf(from.x) < 0.72f && fabsf(to.x) < 0.72f) refl = v3(1, 0, 0);
    else if (fabsf(from.y) < 0.72f && fabsf(to.y) < 0.72f) refl = v3(0, 1, 0);
    else refl = v3(0, 0, 1);
    u = v3_sub(refl, from);
    v = v3_sub(refl, to);
    uu = v3_dot(u, u); vv = v3_dot(v, v); uv = v3_dot(u, v);
    a[0] = u.x; a[1] = u.y; a[2] = u.z;
    b[0] = v.x; b[1] = v.y; b[2] = v.z;
    for (i = 0; i < 3; i++) {
        out[i] = 0.0f;
        for (j = 0; j < 3; j++)
            out[i] += ((i == j ? 1.0f : 0.0f) - 2.0f / uu * a[i] * a[j] - 2.0f / vv * b[i] * b[j] +
                       4.0f * uv / (uu * vv) * b[i] * a[j]) * x[j];
    }
    r = v3(out[0], out[1], out[2]);
    return r;
}

/* The bilinear interpolation of four vectors at (u, v) (corner order 00 10 01 11). */
static Vec3 lerp4(const Vec3 c[4], float u, float v)
{
    return v3_add(v3_add(v3_mul(c[0], (1 - u) * (1 - v)), v3_mul(c[1], u * (1 - v))),
                  v3_add(v3_mul(c[2], (1 - u) * v), v3_mul(c[3], u * v)));
}

/* Patch vi of shape sh (corners p00 p10 p01 p11) at its own (u, v). */
static void patch_diff(const Scene *s, const Shape *sh, const int32_t vi[4], float u, float v,
                       const SurfacePoint *sp, ShadingDiff *d)
{
    Vec3 c[4], z3 = v3(0, 0, 0);
    float duds = 1, dudt = 0, dvds = 0, dvdt = 1;
    int k;
    patch_corners(s, vi, c);
    d->dpdu = v3_sub(v3_add(v3_mul(c[1], 1 - v), v3_mul(c[3], v)), v3_add(v3_mul(c[0], 1 - v), v3_mul(c[2], v)));
    d->dpdv = v3_sub(v3_add(v3_mul(c[2], 1 - u), v3_mul(c[3], u)), v3_add(v3_mul(c[0], 1 - u), v3_mul(c[1], u)));
    if (sh->has_uv && s->UV) {       /* derivatives per the texture's (s, t) */
        float t[4][2], dsu, dtu, dsv, dtv;
        Vec3 dpds, dpdt;
        for (k = 0; k < 4; k++) { t[k][0] = s->UV[2 * vi[k]]; t[k][1] = s->UV[2 * vi[k] + 1]; }
        dsu = (1 - v) * (t[1][0] - t[0][0]) + v * (t[3][0] - t[2][0]);
        dtu = (1 - v) * (t[1][1] - t[0][1]) + v * (t[3][1] - t[2][1]);
        dsv = (1 - u) * (t[2][0] - t[0][0]) + u * (t[3][0] - t[1][0]);
        dtv = (1 - u) * (t[2][1] - t[0][1]) + u * (t[3][1] - t[1][1]);
        duds = fabsf(dsu) < 1e-8f ? 0 : 1 / dsu;
        dvds = fabsf(dsv) < 1e-8f ? 0 : 1 / dsv;
        dudt = fabsf(dtu) < 1e-8f ? 0 : 1 / dtu;
        dvdt = fabsf(dtv) < 1e-8f ? 0 : 1 / dtv;
        dpds = v3_add(v3_mul(d->dpdu, duds), v3_mul(d->dpdv, dvds));
        dpdt = v3_add(v3_mul(d->dpdu, dudt), v3_mul(d->dpdv, dvdt));
        if (v3_dot(v3_cross(dpds, dpdt), v3_cross(dpds, dpdt)) != 0.0f) {
            if (v3_dot(v3_cross(d->dpdu, d->dpdv), v3_cross(dpds, dpdt)) < 0.0f) dpdt = v3_neg(dpdt);
            d->dpdu = dpds;
            d->dpdv = dpdt;
        }
    }
    weingarten(d->dpdu, d->dpdv, z3, v3_add(v3_sub(c[0], c[2]), v3_sub(c[3], c[1])), z3, d);
    {
        Vec3 dnds = v3_add(v3_mul(d->dndu, duds), v3_mul(d->dndv, dvds));
        Vec3 dndt = v3_add(v3_mul(d->dndu, dudt), v3_mul(d->dndv, dvdt));
        d->dndu = dnds;
        d->dndv = dndt;
    }
    if (sh->has_normals && s->N) {
        Vec3 n[4], ns, n0;
        for (k = 0; k < 4; k++) n[k] = s->N[vi[k]];
        ns = lerp4(n, u, v);
        if (v3_dot(ns, ns) > 0.0f) {
            Vec3 dndu = v3_sub(v3_add(v3_mul(n[1], 1 - v), v3_mul(n[3], v)), v3_add(v3_mul(n[0], 1 - v), v3_mul(n[2], v)));
            Vec3 dndv = v3_sub(v3_add(v3_mul(n[2], 1 - u), v3_mul(n[3], u)), v3_add(v3_mul(n[0], 1 - u), v3_mul(n[1], u)));
            /* pbrt-v4 rotates from its geometric normal before orienting it: the
               unoriented normal dp/du x dp/dv, negated by Shape.flip */
            n0 = v3_norm(v3_cross(d->dpdu, d->dpdv));
            if (sh->flip) n0 = v3_neg(n0);
            d->dpdu = rotate_from_to(n0, sp->ns, d->dpdu);
            d->dpdv = rotate_from_to(n0, sp->ns, d->dpdv);
            d->dndu = v3_add(v3_mul(dndu, duds), v3_mul(dndv, dvds));
            d->dndv = v3_add(v3_mul(dndu, dudt), v3_mul(dndv, dvdt));
        }
    }
}

/* The world ray r in the object space of an instance placed by *x (the same t:
   bvh.c). */
static Ray object_ray(const Xform *x, const Ray *r)
{
    Xform inv;
    Ray ro;
    memcpy(inv.m, x->inv, sizeof inv.m);
    memcpy(inv.inv, x->m, sizeof inv.inv);
    ro.o = xf_point(&inv, r->o);
    ro.d = xf_vector(&inv, r->d);
    ro.tmax = r->tmax;
    ro.time = r->time;
    return ro;
}

void shading_differentials(const Scene *s, const Ray *r, const HitRecord *h, SurfacePoint *sp,
                           ShadingDiff *d)
{
    const Shape *sh = &s->shapes[sp->shape];
    if (h->inst >= 0 && h->inst < s->n_instances) {
        /* the object's own point and derivatives, then into the world */
        const Instance *in = &s->instances[h->inst];
        Xform x = in->world_from_obj;           /* a moving one's at the ray's time */
        Ray ro;
        if (in->motion > 0) motion_at(&s->motions[in->motion - 1], r->time, &x);
        ro = object_ray(&x, r);
        HitRecord ho = *h;
        SurfacePoint osp;
        ho.inst = -1;
        scene_surface_point(s, &ro, &ho, &osp);
        shading_differentials(s, &ro, &ho, &osp, d);
        sp->u = osp.u;
        sp->v = osp.v;
        d->dpdu = xf_vector(&x, d->dpdu);
        d->dpdv = xf_vector(&x, d->dpdv);
        d->dndu = xf_normal(&x, d->dndu);
        d->dndv = xf_normal(&x, d->dndv);
        return;
    }
    if (h->prim < s->n_tris && sh->bilinear) {
        /* a flat patch kept as two triangles (bvh.c): the patch at the point's (u, v) */
        int32_t q[4];
        float pu, pv;
        flat_patch_uv(s, sh, h->prim, sp->p, q, &pu, &pv);
        patch_diff(s, sh, q, pu, pv, sp, d);
    } else if (h->prim < s->n_tris) {
        triangle_diff(s, h, sp, d);
    } else if (h->prim >= s->n_tris + s->n_spheres + s->n_quadrics + s->n_patches) {
        SurfacePoint csp;                  /* a curve: its dp/du, dp/dv; dn = 0 (pbrt-v4) */
        curve_surface_point(s, &s->curve_pieces[h->prim - s->n_tris - s->n_spheres - s->n_quadrics - s->n_patches],
                            r, h, &csp, &d->dpdu, &d->dpdv);
        d->dndu = d->dndv = v3(0.0f, 0.0f, 0.0f);
    } else if (h->prim >= s->n_tris + s->n_spheres + s->n_quadrics) {
        const Patch *pa = &s->patches[h->prim - s->n_tris - s->n_spheres - s->n_quadrics];
        patch_diff(s, sh, pa->v, h->b1, h->b2, sp, d);
    } else {
        quadric_diff(sh, sp->p, d, &sp->u, &sp->v);
    }
}

const SurfacePoint *tangent_shade(const Scene *s, const Ray *r, const HitRecord *h,
                                  const SurfacePoint *sp, SurfacePoint *out)
{
    SurfacePoint tmp = *sp;
    ShadingDiff d;
    shading_differentials(s, r, h, &tmp, &d);
    *out = *sp;
    out->dpdu = d.dpdu;                             /* the shading frame's dp/du */
    return out;
}

/* ------------------------------------------------------------------ 2. the maps */

/* The displacement of material m's Bump at sp. */
static float displacement_at(const Material *m, const SurfacePoint *sp)
{
    const Bump *b = m->bump;
    if (b->disp_tex > 0 && m->textures) return tex_eval(m->textures, b->disp_tex - 1, sp, 550.0f);
    return b->disp;
}

/* pbrt-v4's BumpMap: the displaced surface's dp/du and dp/dv. */
static void bump_map(const Material *m, const SurfacePoint *sp, const ShadingDiff *d,
                     Vec3 *dpdu, Vec3 *dpdv)
{
    SurfacePoint sh = *sp;
    float du = BUMP_DELTA, dv = BUMP_DELTA, ud, vd, disp;
    sh.p = v3_add(sp->p, v3_mul(d->dpdu, du));
    sh.u = sp->u + du;
    ud = displacement_at(m, &sh);
    sh.p = v3_add(sp->p, v3_mul(d->dpdv, dv));
    sh.u = sp->u;
    sh.v = sp->v + dv;
    vd = displacement_at(m, &sh);
    disp = displacement_at(m, sp);
    *dpdu = v3_add(v3_add(d->dpdu, v3_mul(sp->ns, (ud - disp) / du)), v3_mul(d->dndu, disp));
    *dpdv = v3_add(v3_add(d->dpdv, v3_mul(sp->ns, (vd - disp) / dv)), v3_mul(d->dndv, disp));
}

/* Channel c of the normal map, bilinear at (s, t) with wrap "repeat" (pbrt-v4's
   Image::BilerpChannel: texel (x, y) has its centre at ((x + 0.5) / w, (y + 0.5) / h)). */
static float nmap_channel(const Bump *b, float s, float t, int c)
{
    float x = s * b->nw - 0.5f, y = t * b->nh - 0.5f, fx, fy, v = 0.0f;
    int x0, y0, k;
    if (!(x > -1e9f && x < 1e9f && y > -1e9f && y < 1e9f)) return 0.5f;   /* NaN, far away */
    x0 = (int)floorf(x);
    y0 = (int)floorf(y);
    fx = x - (float)x0;
    fy = y - (float)y0;
    for (k = 0; k < 4; k++) {
        int xi = (x0 + (k & 1)) % b->nw, yi = (y0 + (k >> 1)) % b->nh;
        float w = ((k & 1) ? fx : 1.0f - fx) * ((k >> 1) ? fy : 1.0f - fy);
        if (xi < 0) xi += b->nw;
        if (yi < 0) yi += b->nh;
        v += w * b->nrgb[3 * ((size_t)yi * b->nw + xi) + c];
    }
    return v;
}

/* pbrt-v4's NormalMap: dp/du and dp/dv around the map's normal. */
static void normal_map(const Bump *b, const SurfacePoint *sp, const ShadingDiff *d,
                       Vec3 *dpdu, Vec3 *dpdv)
{
    float s = sp->u, t = 1.0f - sp->v;
    Vec3 nt = v3_norm(v3(2.0f * nmap_channel(b, s, t, 0) - 1.0f, 2.0f * nmap_channel(b, s, t, 1) - 1.0f,
                         2.0f * nmap_channel(b, s, t, 2) - 1.0f));
    Vec3 x = v3_norm(d->dpdu), y = v3_cross(sp->ns, x), n;
    float ulen = v3_len(d->dpdu), vlen = v3_len(d->dpdv);
    n = v3_add(v3_add(v3_mul(x, nt.x), v3_mul(y, nt.y)), v3_mul(sp->ns, nt.z));
    *dpdu = v3_mul(v3_norm(v3_sub(d->dpdu, v3_mul(n, v3_dot(d->dpdu, n)))), ulen);
    *dpdv = v3_mul(v3_norm(v3_cross(n, *dpdu)), vlen);
}

const SurfacePoint *bump_shade(const Scene *s, const Material *m, const Ray *r, const HitRecord *h,
                               const SurfacePoint *sp, SurfacePoint *out)
{
    ShadingDiff d;
    Vec3 dpdu, dpdv, ns;
    *out = *sp;
    shading_differentials(s, r, h, out, &d);
    out->dpdu = d.dpdu;                             /* (tangent_shade's, if unperturbed) */
    if (m->bump->nw > 0) normal_map(m->bump, out, &d, &dpdu, &dpdv);
    else bump_map(m, out, &d, &dpdu, &dpdv);
    ns = v3_norm(v3_cross(dpdu, dpdv));
    if (!(v3_dot(ns, ns) > 0.5f)) return out;       /* degenerate (or NaN): unperturbed */
    out->ns = v3_dot(ns, out->ng) < 0.0f ? v3_neg(ns) : ns;
    out->dpdu = dpdu;                   /* the frame's s axis, as pbrt-v4's bumped dp/du */
    return out;
}

/* ------------------------------------------------------------------ 3. parameters */

void bump_free(Bump *b)
{
    if (!b) return;
    free(b->nrgb);
    free(b);
}

/* The normal map's image at path (PNG read linearly, PFM, EXR or the PFM beside
   it), as pbrt-v4 reads it (ColorEncoding::Linear): 0 and a message in ierr. */
static int nmap_read(const char *path, Image *im, Error *ierr)
{
    char alt[PATH_CAP];
    FILE *f;
    if (ends_with_ci(path, ".png")) return png_read(im, path, 1, ierr);
    if (ends_with_ci(path, ".exr")) {
        snprintf(alt, sizeof alt, "%.*s.pfm", (int)strlen(path) - 4, path);
        f = fopen(alt, "rb");
        if (!f) return exr_read(im, path, ierr);
        fclose(f);
        return pfm_read(im, alt, ierr);
    }
    if (ends_with_ci(path, ".pfm")) return pfm_read(im, path, ierr);
    snprintf(ierr->msg, sizeof ierr->msg, "specnee reads normal maps as PNG, PFM or EXR "
             "(convert others with ImageMagick's `convert`)");
    return 0;
}

/* "string normalmap" on a material that has no normal map in pbrt-v4: its scene
   loads the image of every material's "normalmap" (a missing file stops it),
   but an interface has no BSDF to shade, MixMaterial::GetNormalMap returns
   none (the material it chooses shades with its own normal map), and so does
   HairMaterial's (hair.c), so the image is the one without it.  Read, the
   file's presence checked as pbrt-v4 stops without it, and ignored with a note. */
int normalmap_ignored(Parser *P, ParamList *pl, const char *what, const char *why)
{
    Param *pn = param_find(pl, PT_STRING, "normalmap");
    char path[PATH_CAP];
    FILE *f;
    if (!pn) return 1;
    if (pn->n_str != 1)
        return fail(P, pn->file, pn->line, "%s: \"string normalmap\" needs one file name", what);
    if (pn->str[0][0]) {                              /* "" is no map, as in pbrt-v4 */
        resolve_path(P, pn->file, pn->str[0], path, sizeof path);
        if (!(f = fopen(path, "rb")))
            return fail(P, pn->file, pn->line, "%s: \"string normalmap\" \"%s\": cannot open the "
                        "file (pbrt-v4 reads it here too, and stops)", what, pn->str[0]);
        fclose(f);
    }
    fprintf(stderr, "%s:%d: note: %s: \"string normalmap\" is ignored: %s\n", pn->file, pn->line,
            what, why);
    return 1;
}

int bump_from_params(Parser *P, ParamList *pl, const char *what, Material *m)
{
    Param *pt = param_find(pl, PT_TEXTURE, "displacement");
    Param *pf = param_find(pl, PT_FLOAT, "displacement");
    Param *pn = param_find(pl, PT_STRING, "normalmap");
    Bump b;
    memset(&b, 0, sizeof b);
    if (pt) {
        int ti = texture_lookup(P, pt, 1);
        if (ti < 0) return 0;
        b.disp_tex = ti + 1;
    } else if (pf) {
        if (!get_float(P, pl, "displacement", 0.0f, &b.disp)) return 0;
        if (!isfinite(b.disp))
            return fail(P, pf->file, pf->line, "%s: \"float displacement\" is not finite", what);
    }
    if (pn && pn->n_str == 1 && pn->str[0][0]) {       /* "" is no map, as in pbrt-v4 */
        char path[PATH_CAP];
        Image im;
        Error ierr;
        resolve_path(P, pn->file, pn->str[0], path, sizeof path);
        if (!nmap_read(path, &im, &ierr))
            return fail(P, pn->file, pn->line, "%s: \"string normalmap\" \"%s\": %s", what,
                        pn->str[0], ierr.msg);
        b.nw = im.w;
        b.nh = im.h;
        b.nrgb = im.rgb;
    } else if (pn && pn->n_str != 1) {
        return fail(P, pn->file, pn->line, "%s: \"string normalmap\" needs one file name", what);
    }
    if (!pt && !pf && !b.nw) return 1;
    m->bump = (Bump *)malloc(sizeof b);
    if (!m->bump) {
        free(b.nrgb);
        return fail(P, pn ? pn->file : pt ? pt->file : pf->file, pn ? pn->line : pt ? pt->line : pf->line,
                    "%s: out of memory", what);
    }
    *m->bump = b;
    return 1;
}
