/* lights.c - emitters, and how next event estimation chooses one of them.

   Exported (specnee.h section 11): emitters_prepare, emitter_radiance,
   emitter_sample, emitter_pdf_sa, emitter_can_reach, light_sampler_build/free,
   light_Le, light_Le_at, emitter_point_at, light_spectrum, light_n_pieces, light_piece_emitter,
   light_piece_of, light_sample, light_pdf_sa, light_voxel, light_select,
   light_select_pmf, light_tree_simd_mismatches, light_sampler_bytes,
   light_sampler_lazy_seconds, sel_from_name, sel_name; what path.c's NEE asks
   ("what NEE asks", near the end): light_nee_count, light_nee_piece,
   light_nee_pmf, light_nee_source.  The AreaLightSource directive itself
   (area_light_from_params, emission_image_read) and its "float power"
   (emitter_apply_power) have their own file, arealight.c.
   The light tree of the strategies tree and spectral-tree has its own file,
   lighttree.c.  THEORY §5 derives everything below; this comment says where it
   lives.

   1. Emitters.  An emitter is one AreaLightSource shape (mesh, sphere, quadric), an
      infinite light (infinite.c) or a delta light (delta.c).  Its radiance is
      pbrt-v4's Le = scale L / sum_{1 nm over the film's range} ybar L, so a directly
      seen emitter has luminance scale; the range belongs to a render, so Le lives in
      the LightSampler (light_sampler_build), not in the Scene.  A mesh's point:
      a triangle by area, then on it by the solid angle it subtends from the
      receiver, the cosine at the receiver's normal warped in (sample_triangle,
      sphtri.c, THEORY §5.6), or, where that solid angle is out of range or with
      --light-shape-sampling area, uniformly on it, with the solid-angle density
      p_sigma(y) = |x - y|^2 / (A |cos theta_y|) (THEORY §4); other shapes by
      area; a sphere seen from outside in the cone it subtends (sphere_cone).  An area
      light with an emission image (pbrt-v4's "filename") has a radiance that
      depends on the point, Le(x) = scale I(u, 1 - v) D65 / sum ybar D65
      (light_Le_at): BSDF-found hits read it at the hit, NEE at the point it
      sampled (emitter_point_at), so both estimate the same integral; the
      selection weights and the power use the image's mean colour, which only
      changes how often the light is chosen, not what the estimate converges to
      (the pmf NEE samples with is the one MIS reads, THEORY §5.5).  pbrt-v4's
      "float power" gives each primitive of the shape that power (arealight.c,
      emitter_apply_power): a mesh's triangles of different areas then have
      different radiance, read at the point the same way (THEORY §11).

   2. Selection.  light_select picks a piece i (an emitter, or with the light trees
      a cluster of at most LIGHT_CLUSTER_TRIS triangles of a big emissive mesh:
      THEORY §5.1) with probability P(i | c) in the context c stored at the vertex;
      light_select_pmf(c, i) returns the same number for a piece that BSDF sampling
      hits (the contract C1-C4, THEORY §5.5).  The strategies and their pmfs are the
      table of THEORY §5.2: uniform, power, spatial, the thesis' spd and product,
      spectral-spatial, and the trees (lighttree.c, THEORY §5.4).  The spectral ones
      use the hero's bin on hero-only paths and the sum over the alive wavelengths'
      bins with --all-wavelengths or after a fluorescent shift, so P is the same
      whichever alive wavelength is the hero (C4, THEORY §6); no emitter in those
      bins falls back to spatial (counted).  Costs: uniform O(1), power and the
      trees O(log n), the table strategies O(n) per vertex.

   3. The spatial table (pbrt-v3's SpatialLightDistribution, THEORY §5.2): per voxel
      of a SPATIAL_RES grid, SPATIAL_SAMPLES Halton receivers and emitter points give
      each emitter e gamma_e = sum [faces the receiver] / p_sigma and s_e = Y_e
      gamma_e (THEORY's gamma_e(v), s_e(v)), floored at 1e-3 of the mean.  Voxels
      are built lazily (an OpenMP critical
      section) or all up front; both give the same tables.

   4. Which side an emitter lights (emitter_can_reach, THEORY §5.3): where the
      spatial table is used, emitter i's weight is multiplied by reach_i(x) in
      {0, 1}, 0 only where no point of i can light x (the planes of a one-sided mesh
      of at most REACH_MAX_TRIS triangles, a sphere's surface, a disk's plane, a
      spot's cone; others "may reach"), with the ray-offset margin of hitpoint.c.  It is
      part of context_weights, so light_select and light_select_pmf see the same
      zeros; if every weight is 0, NEE takes no sample (unbiased: nothing can
      light x). */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* ------------------------------------------------------------------ emitters */

/* The planes of a small emitter mesh, for emitter_can_reach (section 4): per
   triangle its unit normal with the orientation scene_surface_point gives it, and
   the offset d = n . v0.  With shading normals (which decide the orientation at a
   point) that disagree with a triangle's normal the mesh gets no planes. */
static int emitter_find_planes(const Scene *s, Emitter *em)
{
    const Shape *sh = &s->shapes[em->shape];
    double big = 0.0;
    int t, k, a;
    free(em->planes);
    em->planes = NULL;
    em->n_planes = 0;
    if (sh->type == SHAPE_SPHERE) {
        big = fabs(sh->center.x) + fabs(sh->center.y) + fabs(sh->center.z) + sh->radius;
        em->reach_eps = 1e-5 * (1.0 + big);
        return 1;
    }
    if (shape_is_quadric(sh->type)) {
        /* a disk is one plane: through a point of it, with its oriented normal (the
           same at every point); a cylinder or cut sphere gets no test */
        float lo[3], hi[3];
        Vec3 c, n;
        quadric_bounds(sh, lo, hi);
        for (a = 0; a < 3; a++) {
            if (fabs((double)lo[a]) > big) big = fabs((double)lo[a]);
            if (fabs((double)hi[a]) > big) big = fabs((double)hi[a]);
        }
        em->reach_eps = 1e-5 * (1.0 + big);
        if (sh->type != SHAPE_DISK) return 1;
        em->planes = (double *)malloc(sizeof(double) * 4);
        if (!em->planes) return 0;
        quadric_sample(sh, 0.0f, 0.0f, &c, &n);        /* a point of the disk, its normal */
        em->planes[0] = n.x; em->planes[1] = n.y; em->planes[2] = n.z;
        em->planes[3] = (double)n.x * c.x + (double)n.y * c.y + (double)n.z * c.z;
        em->n_planes = 1;
        return 1;
    }
    for (t = sh->tri_begin; t < sh->tri_begin + sh->tri_count; t++)
        for (k = 0; k < 3; k++)
            for (a = 0; a < 3; a++) {
                double q = fabs((double)v3_get(s->P[s->tris[t].v[k]], a));
                if (q > big) big = q;
            }
    for (t = sh->patch_begin; t < sh->patch_begin + sh->patch_count; t++)
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3; a++) {
                double q = fabs((double)v3_get(s->P[s->patches[t].v[k]], a));
                if (q > big) big = q;
            }
    em->reach_eps = 1e-5 * (1.0 + big);
    if (sh->tri_count > REACH_MAX_TRIS || sh->patch_count > 0) return 1;   /* (a twisted patch
                                                       has no plane: "may reach") */
    em->planes = (double *)malloc(sizeof(double) * 4 * (size_t)sh->tri_count);
    if (!em->planes) return 0;
    for (t = 0; t < sh->tri_count; t++) {
        const Triangle *tr = &s->tris[sh->tri_begin + t];
        Vec3 p0 = s->P[tr->v[0]], p1 = s->P[tr->v[1]], p2 = s->P[tr->v[2]];
        Vec3 c = v3_cross(v3_sub(p0, p2), v3_sub(p1, p2));   /* as scene_surface_point */
        double n[3], len;
        n[0] = c.x; n[1] = c.y; n[2] = c.z;
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (sh->flip) len = -len;
        if (!(fabs(len) > 0.0)) {                       /* degenerate: emits nothing */
            em->planes[4 * t + 0] = em->planes[4 * t + 1] = em->planes[4 * t + 2] = 0.0;
            em->planes[4 * t + 3] = 1.0;                /* 0 . p - 1 < 0: never reaches */
            continue;
        }
        for (a = 0; a < 3; a++) n[a] /= len;
        if (sh->has_normals && s->N)
            for (k = 0; k < 3; k++) {
                Vec3 m = s->N[tr->v[k]];
                if (!(n[0] * m.x + n[1] * m.y + n[2] * m.z > 0.0)) {
                    free(em->planes);
                    em->planes = NULL;
                    return 1;
                }
            }
        for (a = 0; a < 3; a++) em->planes[4 * t + a] = n[a];
        em->planes[4 * t + 3] = n[0] * p0.x + n[1] * p0.y + n[2] * p0.z;
    }
    em->n_planes = sh->tri_count;
    return 1;
}

int emitter_can_reach(const Scene *s, int e, Vec3 p)
{
    const Emitter *em = &s->emitters[e];
    const Shape *sh;
    int t;
    if (em->inf) return 1;                       /* light from every direction */
    if (em->delta.type != DELTA_NONE) return delta_can_reach(&em->delta, p);
    sh = &s->shapes[em->shape];
    if (sh->type == SHAPE_SPHERE) {
        double dx = (double)p.x - sh->center.x, dy = (double)p.y - sh->center.y;
        double dz = (double)p.z - sh->center.z, r = sqrt(dx * dx + dy * dy + dz * dz);
        if (em->twosided) return 1;
        /* convex outside: light leaves outwards, a point on the sphere sees none of
           it; flipped (emitting inwards): every point inside or on it is lit */
        return sh->flip ? r < sh->radius + em->reach_eps : r > sh->radius + em->reach_eps;
    }
    if (em->n_planes == 0) return 1;
    for (t = 0; t < em->n_planes; t++) {
        const double *q = em->planes + 4 * t;
        double dist = q[0] * p.x + q[1] * p.y + q[2] * p.z - q[3];
        if (em->twosided ? fabs(dist) > em->reach_eps : dist > em->reach_eps) return 1;
    }
    return 0;
}

/* Le = scale * L_shape / norm with norm = luminance_sum(L) and L_shape = L
   (L_shape = the mean colour's spectrum for an image map or emission image, whose
   L is D65), and k = scale / norm, which infinite.c applies to an image map's
   texels and light_Le_at to an emission image's.  A LightSampler keeps Le as
   this triple (LeSource) and evaluates it with spec_eval_scaled, not as a table. */
typedef struct {
    const Spectrum *shape;     /* the emitter's L (an image map: its mean colour's) */
    float scale;               /* the emitter's scale */
    double norm;
    Spectrum *table;           /* an infinite light's Le tabulated (inf_Le reads a
                                  Spectrum), else NULL */
} LeSource;

static int radiance_source(const Scene *s, int e, float lo_nm, float hi_nm, LeSource *q,
                           Error *err)
{
    const Emitter *em = &s->emitters[e];
    /* the luminance over 400-700 nm is computed once per emitter (Emitter.y_vis) */
    double norm = em->absolute ? 1.0 : lo_nm == LAMBDA_LO && hi_nm == LAMBDA_HI && em->y_vis > 0.0
                  ? em->y_vis : luminance_sum(em->L, lo_nm, hi_nm);
    q->shape = em->inf && em->inf->res > 0 ? &em->inf->mean :
               em->delta.type == DELTA_PROJECTION ? em->delta.mean :
               em->image ? em->image_mean : em->L;
    q->scale = em->scale;
    q->norm = norm;
    q->table = NULL;
    if (!(norm > 0.0)) {
        if (em->inf)
            error_set(err, em->inf->file, em->inf->line, "LightSource \"infinite\": spectrum L "
                      "emits nothing visible in %g-%g nm", lo_nm, hi_nm);
        else if (em->delta.type != DELTA_NONE)
            error_set(err, em->delta.file, em->delta.line, "LightSource: its spectrum "
                      "emits nothing visible in %g-%g nm", lo_nm, hi_nm);
        else
            error_set(err, s->shapes[em->shape].file, s->shapes[em->shape].line,
                      "AreaLightSource: spectrum L emits nothing visible in %g-%g nm", lo_nm, hi_nm);
        return 0;
    }
    return 1;
}

/* The table of Le = scale * shape / norm. */
static void le_tabulate(const LeSource *q, Spectrum *Le)
{
    int lam;
    for (lam = 0; lam < SPEC_N; lam++)
        Le->v[lam] = (float)(q->scale * q->shape->v[lam] / q->norm);
    for (lam = 0; lam < SPEC_UV_N; lam++)
        Le->uv[lam] = (float)(q->scale * q->shape->uv[lam] / q->norm);
}

/* LightTreeInput.le_knots: knots nm0 .. nm0 + n - 1 of radiance i of the LeSource
   array ctx, as le_tabulate makes them (the tree reads 300-700 nm of 300-830). */
static void le_knots_of(const void *ctx, int i, int nm0, int n, float *out)
{
    const LeSource *q = &((const LeSource *)ctx)[i];
    int k = 0;
    for (; k < n && nm0 + k < SPEC_MIN; k++)
        out[k] = (float)(q->scale * q->shape->uv[nm0 + k - SPEC_UV_MIN] / q->norm);
    for (; k < n; k++)
        out[k] = (float)(q->scale * q->shape->v[nm0 + k - SPEC_MIN] / q->norm);
}

static int radiance_and_k(const Scene *s, int e, float lo_nm, float hi_nm, Spectrum *Le,
                          double *k, Error *err)
{
    LeSource q;
    if (!radiance_source(s, e, lo_nm, hi_nm, &q, err)) return 0;
    le_tabulate(&q, Le);
    *k = q.scale / q.norm;
    return 1;
}

int emitter_radiance(const Scene *s, int e, float lo_nm, float hi_nm, Spectrum *Le, Error *err)
{
    double k;
    return radiance_and_k(s, e, lo_nm, hi_nm, Le, &k, err);
}


/* The factor of em->prim_scale at primitive prim (bvh.c's numbering) of em's shape. */
static float prim_factor(const Scene *s, const Emitter *em, int prim)
{
    const Shape *sh = &s->shapes[em->shape];
    int k = prim - sh->tri_begin;
    if (prim >= sh->tri_begin && k < sh->tri_count) return em->prim_scale[k];
    k = prim - (s->n_tris + s->n_spheres + s->n_quadrics) - sh->patch_begin;
    if (k >= 0 && k < sh->patch_count) return em->prim_scale[sh->tri_count + k];
    return 1.0f;
}

int emitters_prepare(Scene *s, Error *err)
{
    int e, t;
    for (e = 0; e < s->n_emitters; e++) {
        Emitter *em = &s->emitters[e];
        const Shape *sh;
        /* A UV lamp has no luminance: its L is absolute spectral radiance, and the
           decision is the emitter's own (made on 400-700 nm, whatever range the
           film integrates), so every range gives it the same meaning. */
        if (!(em->y_vis > 0.0)) em->y_vis = luminance_sum(em->L, LAMBDA_LO, LAMBDA_HI);
        em->absolute = !(em->y_vis > 0.0);
        /* so its radiance over 400-700 nm is defined: norm = 1 or that luminance */
        if (em->inf) {
            /* infinite.c has the rest; here the scene's bounding sphere, which gives
               NEE its far points and the light its "area" 4 pi R^2 (power) */
            InfiniteLight *inf = em->inf;
            inf->center = v3_mul(v3_add(s->bmin, s->bmax), 0.5f);
            inf->radius = 0.5 * v3_len(v3_sub(s->bmax, s->bmin));
            if (!(inf->radius > 0.0) || !isfinite(inf->radius)) inf->radius = 1.0;
            em->area = 4.0 * SPECNEE_PI * inf->radius * inf->radius;
            em->twosided = 0;
            continue;
        }
        if (em->delta.type != DELTA_NONE) {
            /* delta.c: a distant light's power needs the scene's bounding sphere,
               as an infinite light's does */
            DeltaLight *d = &em->delta;
            d->center = v3_mul(v3_add(s->bmin, s->bmax), 0.5f);
            d->radius = 0.5 * v3_len(v3_sub(s->bmax, s->bmin));
            if (!(d->radius > 0.0) || !isfinite(d->radius)) d->radius = 1.0;
            em->area = delta_power_area(d);
            em->twosided = 0;
            if (!(em->area > 0.0)) {
                error_set(err, d->file, d->line, "LightSource \"spot\": the cone is empty");
                return 0;
            }
            continue;
        }
        sh = &s->shapes[em->shape];
        /* area and the triangle CDF */
        free(em->tri_cdf);
        em->tri_cdf = NULL;
        if (sh->type == SHAPE_SPHERE) {
            em->area = 4.0 * SPECNEE_PI * sh->radius * sh->radius;
        } else if (shape_is_quadric(sh->type)) {
            em->area = sh->area;                    /* world area (shapes.c) */
        } else {
            /* triangles, then the twisted patches of a bilinearmesh (patch.c) */
            const int n = sh->tri_count + sh->patch_count;
            double acc = 0.0;
            em->tri_cdf = (float *)malloc(sizeof(float) * (size_t)(n + 1));
            if (!em->tri_cdf) { error_set(err, sh->file, sh->line, "out of memory"); return 0; }
            em->tri_cdf[0] = 0.0f;
            for (t = 0; t < n; t++) {
                if (t < sh->tri_count) acc += tri_area(s, sh->tri_begin + t);
                else {
                    Vec3 c[4];
                    patch_corners(s, s->patches[sh->patch_begin + t - sh->tri_count].v, c);
                    acc += patch_area(c);
                }
                em->tri_cdf[t + 1] = (float)acc;
            }
            em->area = acc;
            for (t = 1; t <= n; t++) em->tri_cdf[t] = acc > 0 ? (float)(em->tri_cdf[t] / acc) : 1.0f;
            em->tri_cdf[n] = 1.0f;
        }
        if (!(em->area > 0.0)) {
            error_set(err, sh->file, sh->line, "AreaLightSource: emitting shape has zero area");
            return 0;
        }
        if (em->power > 0.0f && !emitter_apply_power(s, em, sh)) {
            error_set(err, sh->file, sh->line, "out of memory");
            return 0;
        }
        if (!isfinite(em->scale)) {
            error_set(err, sh->file, sh->line, "AreaLightSource: scale x power / area is not a "
                      "finite number");
            return 0;
        }
        if (!emitter_find_planes(s, em)) {
            error_set(err, sh->file, sh->line, "out of memory");
            return 0;
        }
    }
    return 1;
}

/* The end of every area sample: direction, distance and solid-angle pdf of the
   point out->p (normal out->n) seen from ref, for a piece of area `area`. */
static int finish_sample(Vec3 ref, double area, EmitterSample *out)
{
    Vec3 d = v3_sub(out->p, ref);
    float dist2 = v3_dot(d, d), cos_y;
    if (!(dist2 > 0.0f)) return 0;
    out->dist = sqrtf(dist2);
    out->wi = v3_mul(d, 1.0f / out->dist);
    cos_y = fabsf(v3_dot(out->n, out->wi));
    if (!(cos_y > 0.0f)) return 0;
    out->pdf_sa = (float)(dist2 / (area * cos_y));
    return isfinite(out->pdf_sa) && out->pdf_sa > 0.0f;
}

/* The point of triangle tri at barycentrics (b1, b2) of v1, v2, with the oriented
   geometric normal the integrator sees at a hit there (as from a ray ref + s dir). */
static void surface_at(const Scene *s, int tri, Vec3 ref, Vec3 dir, float b1, float b2, EmitterSample *out)
{
    HitRecord h;
    SurfacePoint sp;
    Ray dummy;
    h.t = 0.0f;
    h.prim = tri;
    h.inst = -1;                       /* emitters are never inside instances */
    h.b1 = b1;
    h.b2 = b2;
    dummy.o = ref; dummy.d = dir; dummy.tmax = 0.0f;
    scene_surface_point(s, &dummy, &h, &sp);
    out->p = sp.p;
    out->n = sp.ng;
    out->prim = tri;
    out->b1 = b1;
    out->b2 = b2;
}

/* A uniform point on triangle tri (u = 1 - sqrt(u1), v = u2 sqrt(u1)). */
static void point_on_triangle(const Scene *s, int tri, Vec3 ref, float u1, float u2, EmitterSample *out)
{
    float su = sqrtf(u1);
    surface_at(s, tri, ref, v3(0, 0, 1), u2 * su, 1.0f - su, out);   /* barycentrics of v1, v2 */
}

/* Where a lamp is seen from: the point, its shading normal (the zero vector in a
   medium) and how triangles are sampled (SHAPE_SA, SHAPE_AREA or SHAPE_AUTO,
   SelOptions.area_sampling). */
typedef struct { Vec3 p, ns; int shape; } Receiver;

static void tri_vertices(const Scene *s, int tri, Vec3 v[3])
{
    const Triangle *t = &s->tris[tri];
    v[0] = s->P[t->v[0]]; v[1] = s->P[t->v[1]]; v[2] = s->P[t->v[2]];
}

/* Is triangle v tried by solid angle from rx?  The one place that decides it, for
   the sample (sample_triangle) and for the pdf of a BSDF hit (pdf_triangle): were
   they to disagree, MIS would weigh a sample by another density than its own. */
static int try_solid_angle(const Receiver *rx, const Vec3 v[3])
{
    if (rx->shape == SHAPE_AREA) return 0;
    return rx->shape == SHAPE_SA || tri_sa_pays(rx->p, rx->ns, v);
}

/* A point on triangle tri of a piece of area `area`, which chose it with the
   probability tri_area / area: by solid angle from the receiver where its range
   allows (sphtri.c; density P_tri p_sigma, THEORY §5.6), else uniform by area
   (density dist^2 / (area cos), as for the whole piece). */
static int sample_triangle(const Scene *s, int tri, double area, const Receiver *rx, float u1, float u2,
                           EmitterSample *out)
{
    Vec3 v[3];
    SphTriSample ts;
    Vec3 d;
    float dist2;
    tri_vertices(s, tri, v);
    if (!try_solid_angle(rx, v) || !tri_sample_sa(rx->p, rx->ns, v, u1, u2, &ts)) {
        point_on_triangle(s, tri, rx->p, u1, u2, out);
        return finish_sample(rx->p, area, out);
    }
    surface_at(s, tri, rx->p, ts.dir, ts.b1, ts.b2, out);
    d = v3_sub(out->p, rx->p);
    dist2 = v3_dot(d, d);
    if (!(dist2 > 0.0f)) return 0;
    out->dist = sqrtf(dist2);
    out->wi = v3_mul(d, 1.0f / out->dist);
    out->pdf_sa = (float)(tri_area(s, tri) / area * ts.pdf);
    return isfinite(out->pdf_sa) && out->pdf_sa > 0.0f;
}

/* A point on a mesh: a triangle by area (the first of tri_count whose cdf entry
   tri_cdf[t + 1] lies above u0, binary search), then a point on it; area: the
   whole mesh's.  emitter_sample and light_sample share it. */
static int sample_mesh(const Scene *s, const float *tri_cdf, int tri_begin, int tri_count, double area,
                       const Receiver *rx, const float u[3], EmitterSample *out)
{
    int lo = 0, hi = tri_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (tri_cdf[mid + 1] <= u[0]) lo = mid + 1; else hi = mid;
    }
    return sample_triangle(s, tri_begin + lo, area, rx, u[1], u[2], out);
}

/* A point on a bilinearmesh with twisted patches by area: a triangle or patch by
   the cdf (triangles first), then a point uniform by area on it (patch_sample). */
static int sample_patch_mesh(const Scene *s, const Emitter *em, const Shape *sh, const Receiver *rx,
                             const float u[3], EmitterSample *out)
{
    int lo = 0, hi = sh->tri_count + sh->patch_count - 1;
    Vec3 ref = rx->p;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (em->tri_cdf[mid + 1] <= u[0]) lo = mid + 1; else hi = mid;
    }
    if (lo < sh->tri_count) return sample_triangle(s, sh->tri_begin + lo, em->area, rx, u[1], u[2], out);
    {
        const Patch *pa = &s->patches[sh->patch_begin + lo - sh->tri_count];
        Vec3 c[4];
        Ray dummy;
        SurfacePoint sp;
        float pu, pv;
        patch_corners(s, pa->v, c);
        patch_sample(c, u[1], u[2], &pu, &pv);
        dummy.o = ref; dummy.d = v3(0, 0, 1); dummy.tmax = 0.0f;
        patch_surface_point(s, sh, pa->v, pu, pv, &dummy, &sp);
        out->p = sp.p;
        out->n = sp.ng;
        out->prim = s->n_tris + s->n_spheres + s->n_quadrics + sh->patch_begin + lo - sh->tri_count;
        out->b1 = pu;
        out->b2 = pv;
    }
    return finish_sample(ref, em->area, out);
}

/* A sphere lamp seen from outside (not flipped, the reference point more than
   1e-3 of its radius beyond its surface) is sampled in the cone of directions it
   subtends, uniformly by solid angle (pbrt-v4's Sphere::Sample with a reference
   point): with d the distance to the centre and x = r^2 / d^2,
       cos theta_max = sqrt(1 - x),   p_sigma = 1 / (2 pi (1 - cos theta_max)),
   1 - cos theta_max = x / (1 + sqrt(1 - x)) without cancellation.  Every sample
   lies on the cap that faces the point, which uniform area sampling reaches only
   half the time, and p_sigma is constant: in a fog, where every medium vertex sees
   the lamp, that is what makes NEE to it cheap.  *omc = 1 - cos theta_max; 0 when
   area sampling applies (inside, flipped, or too close). */
static int sphere_cone(const Shape *sh, Vec3 ref, double *omc)
{
    double dx = (double)sh->center.x - ref.x, dy = (double)sh->center.y - ref.y;
    double dz = (double)sh->center.z - ref.z, d2 = dx * dx + dy * dy + dz * dz;
    double r = sh->radius, x;
    if (sh->flip || !(d2 > (r * 1.001) * (r * 1.001))) return 0;
    x = r * r / d2;
    *omc = x / (1.0 + sqrt(1.0 - x));
    return *omc > 0.0;
}

/* emitter_sample, by area only where rx says so (light_sample) */
static int sample_emitter(const Scene *s, int e, const Receiver *rx, const float uu[3], EmitterSample *out)
{
    const Emitter *em = &s->emitters[e];
    const Shape *sh;
    const Vec3 ref = rx->p;
    const float u0 = uu[0], u1 = uu[1], u2 = uu[2];
    out->delta = 0;
    if (em->delta.type != DELTA_NONE) return delta_sample(&em->delta, ref, out);
    if (em->inf) {
        /* a direction; the "point" lies beyond the scene's bounding sphere, so a
           shadow ray to it tests the whole way out */
        if (!inf_sample(em, ref, u1, u2, &out->wi, &out->pdf_sa)) return 0;
        (void)u0;
        out->dist = (float)(2.0 * em->inf->radius + v3_len(v3_sub(ref, em->inf->center)));
        out->p = v3_add(ref, v3_mul(out->wi, out->dist));
        out->n = v3_neg(out->wi);
        return 1;
    }
    sh = &s->shapes[em->shape];
    if (sh->type == SHAPE_SPHERE) {
        double omc;
        if (sphere_cone(sh, ref, &omc)) {
            /* a direction in the cone around the centre, then the sphere's near
               point along it (the ray ref + t w, w the sampled direction, enters
               the sphere of radius rho, r below, at
               t = d cos theta - sqrt(rho^2 - d^2 sin^2 theta)) */
            Vec3 wc = v3_sub(sh->center, ref);
            double d = v3_len(wc), om = (double)u1 * omc, cos_t = 1.0 - om;
            double sin2 = om * (2.0 - om), phi = 2.0 * SPECNEE_PI * u2, disc, t;
            double r = sh->radius, sin_t = sqrt(sin2 > 0.0 ? sin2 : 0.0);
            Frame fr = frame_from_normal(v3_mul(wc, (float)(1.0 / d)));
            Vec3 w = v3_norm(frame_to_world(&fr, v3((float)(sin_t * cos(phi)), (float)(sin_t * sin(phi)),
                                                    (float)cos_t)));
            (void)u0;
            disc = r * r - d * d * sin2;
            t = d * cos_t - sqrt(disc > 0.0 ? disc : 0.0);
            out->p = v3_add(ref, v3_mul(w, (float)t));
            out->n = v3_norm(v3_sub(out->p, sh->center));
            out->p = v3_add(sh->center, v3_mul(out->n, sh->radius));   /* on the sphere */
            {
                Vec3 dv = v3_sub(out->p, ref);
                float dist2 = v3_dot(dv, dv);
                if (!(dist2 > 0.0f)) return 0;
                out->dist = sqrtf(dist2);
                out->wi = v3_mul(dv, 1.0f / out->dist);
            }
            out->pdf_sa = (float)(1.0 / (2.0 * SPECNEE_PI * omc));
            return isfinite(out->pdf_sa) && out->pdf_sa > 0.0f && v3_dot(out->n, out->wi) < 0.0f;
        }
        {   /* inside, or a flipped sphere: uniformly by area */
            float z = 1.0f - 2.0f * u1, r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
            float phi = 2.0f * PI_F * u2;
            Vec3 dir = v3(r * cosf(phi), r * sinf(phi), z);
            (void)u0;
            out->p = v3_add(sh->center, v3_mul(dir, sh->radius));
            out->n = sh->flip ? v3_neg(dir) : dir;
        }
    } else if (shape_is_quadric(sh->type)) {
        /* uniform by object area: density 1 / quadric_area_at(p) per world area */
        (void)u0;
        quadric_sample(sh, u1, u2, &out->p, &out->n);
        return finish_sample(ref, quadric_area_at(sh, out->p), out);
    } else if (sh->patch_count > 0) {
        return sample_patch_mesh(s, em, sh, rx, uu, out);
    } else {
        return sample_mesh(s, em->tri_cdf, sh->tri_begin, sh->tri_count, em->area, rx, uu, out);
    }
    return finish_sample(ref, em->area, out);
}

int emitter_sample(const Scene *s, int e, Vec3 ref, Vec3 ns, const float u[3], EmitterSample *out)
{
    Receiver rx;
    rx.p = ref; rx.ns = ns; rx.shape = SHAPE_SA;
    return sample_emitter(s, e, &rx, u, out);
}

/* pbrt-v4's invisible area light: an area light whose shape has the constant alpha
   0 (geometry.c keeps it).  No ray ever hits it (bvh.c ALPHA), yet pbrt-v4's
   DiffuseAreaLight drops the mask there and emits in full, and calls the light a
   DeltaPosition one so that its direct light is estimated by light sampling alone:
   NEE takes the whole MIS weight (path.c nee_sample), which keeps the estimate
   unbiased since no BSDF direction can find the light. */
int emitter_invisible(const Scene *s, int e)
{
    const Emitter *em = &s->emitters[e];
    const Shape *sh;
    if (em->inf || em->delta.type != DELTA_NONE || em->shape < 0) return 0;
    sh = &s->shapes[em->shape];
    return sh->alpha_tex == 0 && sh->alpha == 0.0f;
}

/* pbrt-v4 masks an area light's emission where its alpha test fails; a ray that
   finds the shape does so with probability alpha already (bvh.c ALPHA), so the
   points NEE samples, which no ray tests, carry the expected value alpha L.
   Both estimators then see alpha L, and MIS between them stays unbiased.  An
   invisible light (above) emits in full. */
float emitter_alpha(const Scene *s, int e)
{
    const Emitter *em = &s->emitters[e];
    float a;
    if (em->inf || em->delta.type != DELTA_NONE || em->shape < 0) return 1.0f;
    if (emitter_invisible(s, e)) return 1.0f;
    a = s->shapes[em->shape].alpha;
    return a < 1.0f ? (a > 0.0f ? a : 0.0f) : 1.0f;
}

/* A sphere's or quadric's primitive number (bvh.c's: triangles, spheres, quadrics,
   patches, curve pieces), -1 for the other shapes. */
static int quadric_prim(const Scene *s, int shape)
{
    int i;
    for (i = 0; i < s->n_spheres; i++)
        if (s->sphere_shape[i] == shape) return s->n_tris + i;
    for (i = 0; i < s->n_quadrics; i++)
        if (s->quadric_shape[i] == shape) return s->n_tris + s->n_spheres + i;
    return -1;
}

/* The sampled point as a hit of the ray from ref along es->wi at es->dist, on the
   primitive its sampler recorded (a sphere or quadric: the shape's own), so that
   the texture reads the (u, v) a ray finding it would have. */
const SurfacePoint *emitter_point_at(const Scene *s, int e, Vec3 ref, const EmitterSample *es,
                                     SurfacePoint *sp)
{
    const Emitter *em = &s->emitters[e];
    const Shape *sh;
    HitRecord h;
    Ray r;
    if (em->inf || em->delta.type != DELTA_NONE || em->shape < 0) return NULL;
    sh = &s->shapes[em->shape];
    h.prim = sh->type == SHAPE_SPHERE || shape_is_quadric(sh->type) ? quadric_prim(s, em->shape) : es->prim;
    if (h.prim < 0) return NULL;
    h.t = es->dist; h.b1 = es->b1; h.b2 = es->b2; h.inst = -1;
    r.o = ref; r.d = es->wi; r.tmax = es->dist;
    scene_surface_point(s, &r, &h, sp);
    return sp;
}

float emitter_alpha_at(const Scene *s, int e, Vec3 ref, const EmitterSample *es)
{
    const Emitter *em = &s->emitters[e];
    SurfacePoint sp;
    float a;
    if (em->inf || em->delta.type != DELTA_NONE || em->shape < 0) return 1.0f;
    if (s->shapes[em->shape].alpha_tex <= 0) return emitter_alpha(s, e);
    if (!emitter_point_at(s, e, ref, es, &sp)) return 1.0f;
    a = tex_eval(s->textures, s->shapes[em->shape].alpha_tex - 1, &sp, 550.0f);
    return a >= 1.0f ? 1.0f : (a > 0.0f ? a : 0.0f);                       /* NaN: 0 */
}

static float pdf_sa_area(double area, Vec3 ref, Vec3 p, Vec3 n)
{
    Vec3 d = v3_sub(p, ref);
    float dist2 = v3_dot(d, d), cos_y;
    if (!(dist2 > 0.0f) || !(area > 0.0)) return 0.0f;
    cos_y = fabsf(v3_dot(n, d)) / sqrtf(dist2);
    if (!(cos_y > 0.0f)) return 0.0f;
    return (float)(dist2 / (area * cos_y));
}

/* The pdf of a point p (normal n) on triangle prim of a piece of area `area` that
   chooses its triangles by area: sample_triangle's, by solid angle where it samples
   so, else by area; prim -1 (not known): by area. */
static float pdf_triangle(const Scene *s, int prim, double area, const Receiver *rx, Vec3 p, Vec3 n)
{
    Vec3 v[3], d = v3_sub(p, rx->p);
    double pdf;
    if (rx->shape != SHAPE_AREA && prim >= 0 && prim < s->n_tris && v3_dot(d, d) > 0.0f) {
        tri_vertices(s, prim, v);
        if (try_solid_angle(rx, v) && tri_pdf_sa(rx->p, rx->ns, v, v3_norm(d), &pdf))
            return (float)(tri_area(s, prim) / area * pdf);
    }
    return pdf_sa_area(area, rx->p, p, n);
}

/* emitter_pdf_sa, by area only where rx says so (light_pdf_sa) */
static float pdf_emitter(const Scene *s, int e, const Receiver *rx, Vec3 p, Vec3 n, int prim)
{
    const Vec3 ref = rx->p;
    const Shape *sh = s->emitters[e].shape >= 0 ? &s->shapes[s->emitters[e].shape] : NULL;
    if (s->emitters[e].delta.type != DELTA_NONE) return 0.0f;   /* no direction finds it */
    if (s->emitters[e].inf) {
        Vec3 d = v3_sub(p, ref);
        if (!(v3_dot(d, d) > 0.0f)) return 0.0f;
        return inf_pdf(&s->emitters[e], ref, v3_norm(d));
    }
    if (s->emitters[e].shape >= 0 && s->shapes[s->emitters[e].shape].type == SHAPE_SPHERE) {
        double omc;
        /* a direction from ref reaches the cap that faces it, where the cone
           sampler puts all its points, with this density */
        if (sphere_cone(&s->shapes[s->emitters[e].shape], ref, &omc))
            return v3_dot(n, v3_sub(p, ref)) < 0.0f ? (float)(1.0 / (2.0 * SPECNEE_PI * omc)) : 0.0f;
    }
    if (s->emitters[e].shape >= 0 && shape_is_quadric(s->shapes[s->emitters[e].shape].type))
        return pdf_sa_area(quadric_area_at(&s->shapes[s->emitters[e].shape], p), ref, p, n);
    if (sh && sh->type == SHAPE_MESH && prim >= sh->tri_begin && prim < sh->tri_begin + sh->tri_count)
        return pdf_triangle(s, prim, s->emitters[e].area, rx, p, n);
    return pdf_sa_area(s->emitters[e].area, ref, p, n);
}

float emitter_pdf_sa(const Scene *s, int e, Vec3 ref, Vec3 ns, Vec3 p, Vec3 n, int prim)
{
    Receiver rx;
    rx.p = ref; rx.ns = ns; rx.shape = SHAPE_SA;
    return pdf_emitter(s, e, &rx, p, n, prim);
}

/* ------------------------------------------------------------------ the sampler */

/* A piece (LightPiece, specnee.h section 11) is what NEE chooses: a whole emitter
   (count == 0, sampled by emitter_sample), or a cluster of triangles of a split mesh. */

/* Piece pc is the whole emitter e. */
static void piece_whole(const Scene *s, LightPiece *pc, int e)
{
    const Emitter *em = &s->emitters[e];
    pc->emitter = e;
    pc->area = em->area;
    if (em->shape >= 0 && s->shapes[em->shape].type == SHAPE_MESH &&
        s->shapes[em->shape].patch_count == 0) {   /* (with patches: emitter_sample) */
        pc->tri_cdf = em->tri_cdf;
        pc->tri_begin = s->shapes[em->shape].tri_begin;
        pc->tri_count = s->shapes[em->shape].tri_count;
    }
}

/* Per emitter, the little that every emitter hit and NEE sample reads (light_Le):
   its radiance's index in LightSampler.Le, and how it emits. */
typedef struct { int le, twosided, inf, delta; } EmitterRef;

struct LightSampler {
    const Scene *scene;
    SelOptions opt;
    int n;                     /* number of emitters */
    LeSource *Le;              /* the distinct radiances for the sampled range, each as
                                  (L, scale, norm), read through spec_eval_scaled, not a
                                  second 2 KB table per emitter: emitters with the same
                                  L, scale and kind share one */
    int n_le;
    EmitterRef *ref;           /* per emitter: what light_Le reads, in one place */
    double *k;                 /* per emitter: scale / luminance_sum(L) (image maps' texels) */
    float *bin;                /* n x SPD_BINS: bin averages of Le over 400-700 nm (freed,
                                  NULL, once the build has read them) */
    Spectrum le_sum;           /* the sum of every emitter's Le (360-830 nm knots; UV 0),
                                  added in emitter order as it is tabulated */
    double *power;             /* per emitter: radiant power over 400-700 nm */
    double *power_cdf;         /* power strategy: n + 1 running sums of power_pmf */
    int power_last;            /* last emitter with positive power_pmf */
    float *power_pmf;          /* power strategy */
    float *T;                  /* (SPD_UV_BINS + SPD_BINS) x n spectral table (unit or power
                                  metric): rows 0..19 are 300-400 nm, rows 20..79 the
                                  thesis' 60 bins over 400-700 nm */
    float *Y;                  /* luminance (= scale) per emitter (T and Y: only the
                                  strategies of context_weights, uses_grid) */
    /* pieces: without splitting piece i is emitter i */
    int n_pieces;
    LightPiece *pieces;
    int *emitter_piece;        /* per emitter: its piece, -1 when split */
    int *piece_tri;            /* triangles of the split meshes' clusters */
    float *piece_cdf;          /* parallel: cumulative area fraction within the cluster */
    int *piece_of_tri;         /* per scene triangle: its cluster, -1 (NULL: no splits) */
    LightTree *tree;           /* the tree strategies: the light tree (lighttree.c) */
    /* spatial grid */
    int res[3];
    Vec3 bmin, bmax;
    long n_voxels;
    float **voxel;             /* per voxel: s[n] (spatial pmf) then g[n] (geometry) */
    double lazy_s;             /* seconds spent building voxels on first use (under the
                                  critical section, so the sum is time really spent) */
    EquiLamps equi;            /* the lamps equiangular sampling aims at (equiangular.c) */
};

/* A clock for lazy_s: OpenMP's wall clock, else the CPU clock (one thread). */
static double lights_seconds(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    return (double)clock() / CLOCKS_PER_SEC;
#endif
}

static const char *const sel_names[SEL_COUNT] = {
    "uniform", "power", "spatial", "spd", "product", "spectral-spatial", "all",
    "tree", "spectral-tree"
};

const char *sel_name(SelStrategy st)
{
    return (st >= 0 && st < SEL_COUNT) ? sel_names[st] : "?";
}

SelStrategy sel_from_name(const char *name)
{
    int i;
    for (i = 0; i < SEL_COUNT; i++)
        if (strcmp(name, sel_names[i]) == 0) return (SelStrategy)i;
    return SEL_COUNT;
}

static int is_tree(SelStrategy st) { return st == SEL_TREE || st == SEL_SPECTRAL_TREE; }

static int uses_grid(SelStrategy st)
{
    return st == SEL_SPATIAL || st == SEL_SPD || st == SEL_PRODUCT || st == SEL_SPECTRAL_SPATIAL;
}

/* A voxel whose table could not be built (out of memory) points here, for good:
   every later light_select and light_select_pmf in it then use the uniform pmf,
   so a selection and the pmf of the same context can never disagree.  Only its
   address matters; it is never written. */
static const float voxel_failed[1] = { 0.0f };
#define VOXEL_FAILED ((float *)voxel_failed)

/* The per-voxel estimate of section 3 above: fills out[0..n) with s_e and
   out[n..2n) with gamma_e (g[] accumulates gamma_e).  Returns 0 (out[] untouched)
   when out of memory. */
static int build_voxel(const LightSampler *ls, long v, float *out)
{
    const Scene *s = ls->scene;
    int n = ls->n, j, k;
    long vx = v % ls->res[0], vy = (v / ls->res[0]) % ls->res[1], vz = v / ((long)ls->res[0] * ls->res[1]);
    double *g = (double *)calloc((size_t)n, sizeof(double));
    double sum_w = 0.0, sum_g = 0.0, floor_w, floor_g;
    Vec3 ext = v3_sub(ls->bmax, ls->bmin);
    if (!g) return 0;
    for (k = 0; k < SPATIAL_SAMPLES; k++) {
        Vec3 p = v3(ls->bmin.x + ext.x * (float)((vx + radical_inverse(2, (uint64_t)k)) / ls->res[0]),
                    ls->bmin.y + ext.y * (float)((vy + radical_inverse(3, (uint64_t)k)) / ls->res[1]),
                    ls->bmin.z + ext.z * (float)((vz + radical_inverse(5, (uint64_t)k)) / ls->res[2]));
        float u0 = (float)radical_inverse(7, (uint64_t)k), u1 = (float)radical_inverse(11, (uint64_t)k);
        float uu[3];
        Receiver rx;                   /* by area: the estimate of the solid angle */
        uu[0] = u0; uu[1] = u1; uu[2] = (float)radical_inverse(13, (uint64_t)k);
        rx.p = p; rx.ns = v3(0.0f, 0.0f, 0.0f); rx.shape = SHAPE_AREA;
        for (j = 0; j < n; j++) {
            EmitterSample es;
            if (s->emitters[j].inf) { g[j] += 4.0 * SPECNEE_PI; continue; }  /* the whole sphere */
            if (!sample_emitter(s, j, &rx, uu, &es)) continue;
            /* one-sided: no light towards a receiver behind the emitter */
            if (!s->emitters[j].twosided && v3_dot(es.n, v3_neg(es.wi)) <= 0.0f) continue;
            g[j] += 1.0 / es.pdf_sa;
        }
    }
    for (j = 0; j < n; j++) { sum_g += g[j]; sum_w += g[j] * ls->Y[j]; }
    /* pbrt-v3's floor: 1e-3 of the per-sample mean, or 1 when nothing is seen */
    floor_w = sum_w > 0 ? 1e-3 * sum_w / (SPATIAL_SAMPLES * (double)n) : 1.0;
    floor_g = sum_g > 0 ? 1e-3 * sum_g / (SPATIAL_SAMPLES * (double)n) : 1.0;
    sum_w = 0.0;
    for (j = 0; j < n; j++) {
        double w = g[j] * ls->Y[j];
        if (w < floor_w) w = floor_w;
        out[j] = (float)w;
        sum_w += w;
        out[n + j] = (float)(g[j] < floor_g ? floor_g : g[j]);
    }
    for (j = 0; j < n; j++) out[j] = (float)(out[j] / sum_w);
    free(g);
    return 1;
}

int light_voxel(const LightSampler *ls, Vec3 p)
{
    int a, c[3];
    float lo[3], hi[3], q[3];
    if (!ls->voxel) return -1;
    lo[0] = ls->bmin.x; lo[1] = ls->bmin.y; lo[2] = ls->bmin.z;
    hi[0] = ls->bmax.x; hi[1] = ls->bmax.y; hi[2] = ls->bmax.z;
    q[0] = p.x; q[1] = p.y; q[2] = p.z;
    for (a = 0; a < 3; a++) {
        float o = hi[a] > lo[a] ? (q[a] - lo[a]) / (hi[a] - lo[a]) : 0.0f;
        int i = (int)floorf(o * (float)ls->res[a]);
        if (!(i >= 0)) i = 0;                           /* also catches NaN */
        if (i >= ls->res[a]) i = ls->res[a] - 1;
        c[a] = i;
    }
    return (int)(c[0] + (long)ls->res[0] * (c[1] + (long)ls->res[1] * c[2]));
}

/* The voxel's table, built on first use.  Readers take the pointer atomically;
   a missing voxel is built inside a critical section, once: what is published
   (the table, or VOXEL_FAILED when memory ran out) stays. */
static const float *voxel_table(LightSampler *ls, int v)
{
    float *t;
#ifdef _OPENMP
#pragma omp atomic read
#endif
    t = ls->voxel[v];
    if (t) return t;
#ifdef _OPENMP
#pragma omp critical(specnee_voxel)
#endif
    {
        if (!ls->voxel[v]) {
            float *nt = (float *)malloc(sizeof(float) * 2 * (size_t)ls->n);
            if (nt) {
                double t0 = lights_seconds();
                int built = build_voxel(ls, v, nt);
                ls->lazy_s += lights_seconds() - t0;
                if (!built) { free(nt); nt = NULL; }
            }
            if (!nt) nt = VOXEL_FAILED;
#ifdef _OPENMP
#pragma omp flush
#pragma omp atomic write
#endif
            ls->voxel[v] = nt;
        }
        t = ls->voxel[v];
    }
    return t;
}



/* ------------------------------------------------------------------ pieces of the tree strategies */

/* Split mesh emitter e's triangles tris[0..n) into clusters of at most
   LIGHT_CLUSTER_TRIS by median cuts along the longest axis of their centroids. */
static void cluster_mesh(LightSampler *ls, int e, int *tris, int n, const Vec3 *tri_c, KeyIdx *tmp,
                         int *next_tri)
{
    const Scene *s = ls->scene;
    if (n > LIGHT_CLUSTER_TRIS) {
        Vec3 cmin = tri_c[tris[0]], cmax = cmin;
        int i, mid = n / 2;
        for (i = 1; i < n; i++) { cmin = v3_min(cmin, tri_c[tris[i]]); cmax = v3_max(cmax, tri_c[tris[i]]); }
        sort_by_axis(tris, n, tri_c, longest_axis(v3_sub(cmax, cmin)), tmp);
        cluster_mesh(ls, e, tris, mid, tri_c, tmp, next_tri);
        cluster_mesh(ls, e, tris + mid, n - mid, tri_c, tmp, next_tri);
    } else {
        LightPiece *pc = &ls->pieces[ls->n_pieces];
        double acc = 0.0;
        int i;
        pc->emitter = e;
        pc->first = *next_tri;
        pc->count = n;
        for (i = 0; i < n; i++) {
            ls->piece_tri[pc->first + i] = tris[i];
            acc += tri_area(s, tris[i]);
            ls->piece_cdf[pc->first + i] = (float)acc;
            ls->piece_of_tri[tris[i]] = ls->n_pieces;
        }
        for (i = 0; i < n; i++)
            ls->piece_cdf[pc->first + i] = acc > 0.0 ? (float)(ls->piece_cdf[pc->first + i] / acc)
                                                     : (float)(i + 1) / (float)n;
        ls->piece_cdf[pc->first + n - 1] = 1.0f;
        pc->area = acc;
        *next_tri += n;
        ls->n_pieces++;
    }
}


/* The pieces - whole emitters, and clusters of the large emissive meshes - and
   the tree over them (called by light_sampler_build for the tree strategies). */
static int tree_setup(LightSampler *ls)
{
    const Scene *s = ls->scene;
    int e, i, n_split_tris = 0, next_tri = 0, max_tris = 1, ok = 0;
    int *tris = NULL;
    Vec3 *tri_c = NULL;
    KeyIdx *tmp = NULL;
    size_t cap = (size_t)ls->n;
    for (e = 0; e < ls->n; e++) {
        const Shape *sh;
        if (s->emitters[e].shape < 0) continue;       /* infinite or delta light: one piece */
        sh = &s->shapes[s->emitters[e].shape];
        if (!ls->opt.no_split && sh->type == SHAPE_MESH && sh->tri_count > LIGHT_CLUSTER_TRIS &&
            sh->patch_count == 0) {
            n_split_tris += sh->tri_count;
            cap += (size_t)(sh->tri_count + LIGHT_CLUSTER_TRIS - 1) / LIGHT_CLUSTER_TRIS * 2;
            if (sh->tri_count > max_tris) max_tris = sh->tri_count;
        }
    }
    ls->pieces = (LightPiece *)calloc(cap, sizeof *ls->pieces);
    ls->emitter_piece = (int *)malloc(sizeof(int) * (size_t)ls->n);
    if (!ls->pieces || !ls->emitter_piece) goto done;
    if (n_split_tris > 0) {
        ls->piece_tri = (int *)malloc(sizeof(int) * (size_t)n_split_tris);
        ls->piece_cdf = (float *)malloc(sizeof(float) * (size_t)n_split_tris);
        ls->piece_of_tri = (int *)malloc(sizeof(int) * (size_t)s->n_tris);
        tris = (int *)malloc(sizeof(int) * (size_t)max_tris);
        tri_c = (Vec3 *)malloc(sizeof(Vec3) * (size_t)s->n_tris);
        tmp = (KeyIdx *)malloc(sizeof(KeyIdx) * (size_t)(max_tris > ls->n ? max_tris : ls->n));
        if (!ls->piece_tri || !ls->piece_cdf || !ls->piece_of_tri || !tris || !tri_c || !tmp) goto done;
        for (i = 0; i < s->n_tris; i++) ls->piece_of_tri[i] = -1;
    }
    ls->n_pieces = 0;
    for (e = 0; e < ls->n; e++) {
        const Shape *sh;
        sh = s->emitters[e].shape >= 0 ? &s->shapes[s->emitters[e].shape] : NULL;
        if (sh && ls->piece_of_tri && !ls->opt.no_split && sh->type == SHAPE_MESH &&
            sh->tri_count > LIGHT_CLUSTER_TRIS && sh->patch_count == 0) {
            for (i = 0; i < sh->tri_count; i++) {
                const Triangle *tr = &s->tris[sh->tri_begin + i];
                tris[i] = sh->tri_begin + i;
                tri_c[tris[i]] = v3_mul(v3_add(v3_add(s->P[tr->v[0]], s->P[tr->v[1]]), s->P[tr->v[2]]),
                                        1.0f / 3.0f);
            }
            ls->emitter_piece[e] = -1;
            cluster_mesh(ls, e, tris, sh->tri_count, tri_c, tmp, &next_tri);
        } else {
            piece_whole(s, &ls->pieces[ls->n_pieces], e);
            ls->emitter_piece[e] = ls->n_pieces++;
        }
    }
    free(tris); free(tri_c); free(tmp);        /* not held while the tree is built */
    tris = NULL; tri_c = NULL; tmp = NULL;
    /* the tree over the pieces (lighttree.c) */
    {
        LightTreeInput in;
        int *le_of = (int *)malloc(sizeof(int) * (size_t)ls->n);
        double *piece_power = (double *)malloc(sizeof(double) * (size_t)ls->n_pieces);
        if (!le_of || !piece_power) { free(le_of); free(piece_power); goto done; }
        for (e = 0; e < ls->n; e++) le_of[e] = ls->ref[e].le;
        /* each piece's power pi A (2 if two-sided) times the sum of its emitter's
           bins; the bins are not read again (context_tables ran), so they are freed
           before the tree's own tables are built */
        for (i = 0; i < ls->n_pieces; i++) {
            const LightPiece *pc = &ls->pieces[i];
            double sum = 0.0;
            int b;
            for (b = 0; b < SPD_BINS; b++) sum += ls->bin[(size_t)pc->emitter * SPD_BINS + b];
            piece_power[i] = SPECNEE_PI * pc->area * (s->emitters[pc->emitter].twosided ? 2.0 : 1.0) * sum;
        }
        free(ls->bin);
        ls->bin = NULL;
        in.scene = s;
        in.opt = &ls->opt;
        in.pieces = ls->pieces;
        in.n_pieces = ls->n_pieces;
        in.piece_tri = ls->piece_tri;
        in.le_knots = le_knots_of;
        in.le_ctx = ls->Le;
        in.n_le = ls->n_le;
        in.le_of = le_of;
        in.piece_power = piece_power;
        ls->tree = light_tree_build(&in);
        free(le_of);
        free(piece_power);
        if (!ls->tree) goto done;
    }
    ok = 1;
done:
    free(tris); free(tri_c); free(tmp);
    return ok;
}

/* ------------------------------------------------------------------ build */

/* An earlier area light with the same radiance (same L, image, scale, kind), or -1.
   The previous emitter is checked first, then a few before it: lamps of one kind
   are usually declared together (O(n), never O(n^2)).  radiance_source is a
   function of (L, scale, absolute, image) alone, so such lamps share it. */
static int same_radiance(const Scene *s, int i)
{
    const Emitter *em = &s->emitters[i];
    int j, tries = 0;
    if (em->inf || em->delta.type == DELTA_PROJECTION) return -1;   /* (its own stand-in) */
    for (j = i - 1; j >= 0 && tries < 8; j--, tries++) {
        const Emitter *ej = &s->emitters[j];
        if (!ej->inf && ej->scale == em->scale && ej->absolute == em->absolute &&
            ej->L == em->L && ej->image == em->image &&
            ej->delta.type != DELTA_PROJECTION) return j;
    }
    return -1;
}

/* The tables of context_weights (uses_grid strategies): Y and T of every emitter
   from the radiance sources and bins light_sampler_build made.  0: out of memory. */
static int context_tables(LightSampler *ls, const SelOptions *o)
{
    const Scene *s = ls->scene;
    int n = ls->n, i, b;
    /* the UV band averages once per distinct radiance, not per emitter */
    float *uv = (float *)malloc(sizeof(float) * (size_t)ls->n_le * SPD_UV_BINS);
    if (!uv) return 0;
    for (i = 0; i < ls->n_le; i++) {
        Spectrum Le;
        le_tabulate(&ls->Le[i], &Le);
        for (b = 0; b < SPD_UV_BINS; b++)
            uv[(size_t)i * SPD_UV_BINS + b] = spec_band_average(&Le, SPEC_UV_MIN + (int)SPD_BIN_NM * b,
                                                                (int)SPD_BIN_NM);
    }
    for (i = 0; i < n; i++) {
        const Emitter *em = &s->emitters[i];
        /* Y: luminance over the range, = scale for area lights (pbrt-v4's
           normalisation); an image map's stand-in spectrum has its own */
        ls->Y[i] = em->inf ? (float)luminance_sum(ls->Le[ls->ref[i].le].table, ls->opt.lo_nm, ls->opt.hi_nm)
                           : em->scale;
    }
    /* T rows 0..19: 300-400 nm (fluorescence excitation), rows 20..79: the
       thesis' 60 bins over 400-700 nm (spd_bin); row by row, so that the
       writes go in order */
    for (b = 0; b < SPD_UV_BINS + SPD_BINS; b++)
        for (i = 0; i < n; i++) {
            const Emitter *em = &s->emitters[i];
            float m = o->power_metric ? (float)(em->area * (em->twosided ? 2.0 : 1.0)) : 1.0f;
            ls->T[b * n + i] = (b < SPD_UV_BINS ? uv[(size_t)ls->ref[i].le * SPD_UV_BINS + b]
                                                : ls->bin[(size_t)i * SPD_BINS + (b - SPD_UV_BINS)]) * m;
        }
    free(uv);
    return 1;
}

LightSampler *light_sampler_build(const Scene *s, const SelOptions *o, Error *err)
{
    LightSampler *ls = (LightSampler *)calloc(1, sizeof *ls);
    int n = s->n_emitters, i, b;
    double sum = 0.0;
    if (!ls) { error_set(err, NULL, 0, "out of memory"); return NULL; }
    ls->scene = s;
    ls->opt = *o;
    if (!(ls->opt.hi_nm > ls->opt.lo_nm)) { ls->opt.lo_nm = LAMBDA_LO; ls->opt.hi_nm = LAMBDA_HI; }
    ls->n = n;
    if (n == 0) return ls;
    ls->Le = (LeSource *)calloc((size_t)n, sizeof(LeSource));
    ls->ref = (EmitterRef *)malloc(sizeof(EmitterRef) * (size_t)n);
    ls->k = (double *)malloc(sizeof(double) * (size_t)n);
    ls->bin = (float *)malloc(sizeof(float) * (size_t)n * SPD_BINS);
    ls->power = (double *)malloc(sizeof(double) * (size_t)n);
    ls->power_pmf = (float *)malloc(sizeof(float) * (size_t)n);
    ls->power_cdf = (double *)malloc(sizeof(double) * (size_t)(n + 1));
    if (uses_grid(o->strategy)) {              /* the tables of context_weights */
        ls->T = (float *)malloc(sizeof(float) * (size_t)n * (SPD_UV_BINS + SPD_BINS));
        ls->Y = (float *)malloc(sizeof(float) * (size_t)n);
        if (!ls->T || !ls->Y) goto oom;
    }
    if (!ls->Le || !ls->ref || !ls->k || !ls->bin || !ls->power || !ls->power_pmf || !ls->power_cdf)
        goto oom;
    /* the emitters' radiance for this render's range, bin table, power and sum */
    spec_const(&ls->le_sum, 0.0f);
    for (i = 0; i < n; i++) {
        const Emitter *em = &s->emitters[i];
        double bsum = 0.0;
        int same = same_radiance(s, i);
        Spectrum Le;
        ls->ref[i].twosided = em->twosided;
        ls->ref[i].inf = em->inf != NULL;
        ls->ref[i].delta = em->delta.type != DELTA_NONE;
        if (same < 0) {
            LeSource *q = &ls->Le[ls->n_le];
            ls->ref[i].le = ls->n_le++;
            if (!radiance_source(s, i, ls->opt.lo_nm, ls->opt.hi_nm, q, err)) {
                light_sampler_free(ls);
                return NULL;
            }
            ls->k[i] = q->scale / q->norm;
            le_tabulate(q, &Le);
            if (em->inf) {                         /* inf_Le reads a table */
                q->table = (Spectrum *)malloc(sizeof(Spectrum));
                if (!q->table) goto oom;
                *q->table = Le;
            }
            for (b = 0; b < SPD_BINS; b++)
                ls->bin[(size_t)i * SPD_BINS + b] = spec_bin_average(&Le, b);
        } else {
            /* radiance_source is a function of (L, scale, absolute, image) alone */
            ls->ref[i].le = ls->ref[same].le;
            ls->k[i] = ls->k[same];
            memcpy(ls->bin + (size_t)i * SPD_BINS, ls->bin + (size_t)same * SPD_BINS, sizeof(float) * SPD_BINS);
            le_tabulate(&ls->Le[ls->ref[i].le], &Le);
        }
        for (b = 0; b < SPEC_N; b++) ls->le_sum.v[b] += Le.v[b];
        for (b = 0; b < SPD_BINS; b++) bsum += ls->bin[(size_t)i * SPD_BINS + b] * SPD_BIN_NM;
        ls->power[i] = SPECNEE_PI * em->area * (em->twosided ? 2.0 : 1.0) * bsum;
    }
    for (i = 0; i < n; i++) sum += ls->power[i];
    for (i = 0; i < n; i++)
        ls->power_pmf[i] = sum > 0 ? (float)(ls->power[i] / sum) : 1.0f / (float)n;
    /* the power strategy's CDF: running sums in the order the old linear scan used */
    ls->power_cdf[0] = 0.0;
    ls->power_last = -1;
    for (i = 0; i < n; i++) {
        ls->power_cdf[i + 1] = ls->power_cdf[i] + ls->power_pmf[i];
        if (ls->power_pmf[i] > 0.0f) ls->power_last = i;
    }
    if (ls->T && !context_tables(ls, o)) goto oom;
    if (is_tree(o->strategy)) {
        if (!tree_setup(ls)) goto oom;
    } else {
        /* one piece per emitter */
        ls->n_pieces = n;
        ls->pieces = (LightPiece *)calloc((size_t)n, sizeof *ls->pieces);
        ls->emitter_piece = (int *)malloc(sizeof(int) * (size_t)n);
        if (!ls->pieces || !ls->emitter_piece) goto oom;
        for (i = 0; i < n; i++) {
            piece_whole(s, &ls->pieces[i], i);
            ls->emitter_piece[i] = i;
        }
    }
    if (uses_grid(o->strategy)) {
        Vec3 d = v3_sub(s->bmax, s->bmin);
        float dmax = fmaxf(d.x, fmaxf(d.y, d.z));
        int a;
        ls->bmin = s->bmin;
        ls->bmax = s->bmax;
        for (a = 0; a < 3; a++) {
            float da = v3_get(d, a);
            int res = o->grid_res > 0 ? o->grid_res : SPATIAL_RES;
            int r = dmax > 0 ? (int)lroundf((float)res * da / dmax) : 1;
            ls->res[a] = r < 1 ? 1 : r;
        }
        ls->n_voxels = (long)ls->res[0] * ls->res[1] * ls->res[2];
        ls->voxel = (float **)calloc((size_t)ls->n_voxels, sizeof(float *));
        if (!ls->voxel) goto oom;
        if (o->eager) {
            long v;
            for (v = 0; v < ls->n_voxels; v++)
                if (voxel_table(ls, (int)v) == VOXEL_FAILED) goto oom;
            ls->lazy_s = 0.0;          /* built up front: counted in the build time */
        }
    }
    equi_lamps_build(s, ls->emitter_piece, &ls->equi);
    return ls;
oom:
    light_sampler_free(ls);
    error_set(err, NULL, 0, "out of memory building the light sampler");
    return NULL;
}

const EquiLamps *light_equi(const LightSampler *ls) { return &ls->equi; }

void light_sampler_free(LightSampler *ls)
{
    long v;
    if (!ls) return;
    if (ls->voxel)
        for (v = 0; v < ls->n_voxels; v++)
            if (ls->voxel[v] != VOXEL_FAILED) free(ls->voxel[v]);
    free(ls->voxel);
    if (ls->Le)
        for (v = 0; v < ls->n_le; v++) free(ls->Le[v].table);
    free(ls->Le); free(ls->ref); free(ls->k); free(ls->bin); free(ls->power);
    free(ls->power_pmf); free(ls->power_cdf);
    free(ls->T);
    free(ls->Y);
    free(ls->pieces); free(ls->emitter_piece);
    free(ls->piece_tri); free(ls->piece_cdf); free(ls->piece_of_tri);
    light_tree_free(ls->tree);
    free(ls);
}

/* For the test lighttree_simd_matches_scalar (lighttree.c). */
int light_tree_simd_mismatches(const LightSampler *ls, const LightCtx *c, int *lanes)
{
    *lanes = 0;
    if (!is_tree(ls->opt.strategy) || !ls->tree) return 0;
    return light_tree_simd_check(ls->tree, c, lanes);
}

/* For the test lighttree_bins_sum (lighttree.c). */
int light_tree_bins_mismatches(const LightSampler *ls, int *lanes)
{
    *lanes = 0;
    if (!is_tree(ls->opt.strategy) || !ls->tree) return 0;
    return light_tree_bins_check(ls->tree, lanes);
}

int light_tree_root_bins(const LightSampler *ls, float *bins, int max)
{
    if (!is_tree(ls->opt.strategy) || !ls->tree) return 0;
    return light_tree_root_bins_copy(ls->tree, bins, max);
}

double light_sampler_lazy_seconds(const LightSampler *ls)
{
    return ls->lazy_s;
}

size_t light_sampler_bytes(const LightSampler *ls)
{
    size_t n = (size_t)ls->n, bytes = sizeof *ls;
    long v;
    bytes += (size_t)ls->n_le * sizeof(Spectrum);
    bytes += n * (sizeof(EmitterRef) + sizeof(float) * (SPD_BINS + 1) + sizeof(double) * 3 + sizeof(int));
    if (ls->T) bytes += n * sizeof(float) * (SPD_UV_BINS + SPD_BINS + 1);   /* T and Y */
    bytes += sizeof(LightPiece) * (size_t)ls->n_pieces;
    if (ls->piece_of_tri) bytes += sizeof(int) * (size_t)ls->scene->n_tris;
    if (ls->piece_tri) {
        size_t k = 0;
        int i;
        for (i = 0; i < ls->n_pieces; i++) k += (size_t)ls->pieces[i].count;
        bytes += k * (sizeof(int) + sizeof(float));
    }
    if (ls->tree) bytes += light_tree_bytes(ls->tree);
    if (ls->voxel) {
        bytes += sizeof(float *) * (size_t)ls->n_voxels;
        for (v = 0; v < ls->n_voxels; v++)
            if (ls->voxel[v] && ls->voxel[v] != VOXEL_FAILED)
                bytes += sizeof(float) * 2 * n;
    }
    return bytes;
}

/* ------------------------------------------------------------------ pieces */

/* An emission image (pbrt-v4's DiffuseAreaLight with "filename"):
     Le(x, lambda) = k  I(u, 1 - v; lambda)  D65(lambda),   k = scale / sum ybar D65,
   with I the image's RGB illuminant spectrum (m = 2 max(rgb) times the sigmoid of
   rgb / m) bilinear between texel centres and clamped at the edges (texture.c's
   imagemap lookup, "clamp"): a white texel has luminance scale, as an "rgb L" of
   the same colour does.  Without the point (at NULL) the image's mean colour,
   which is what selection and power use.  An emitter with "power" on a mesh of
   primitives of different areas multiplies by em->prim_scale at the point's
   primitive (emitter_apply_power); without the point, by 1 (their mean). */
float light_Le_at(const LightSampler *ls, int e, Vec3 n, Vec3 w, const SurfacePoint *at,
                  float lambda_nm)
{
    const EmitterRef *r = &ls->ref[e];
    const LeSource *q = &ls->Le[r->le];
    const Emitter *em;
    float f;
    if (r->inf)                                                    /* along w */
        return inf_Le(&ls->scene->emitters[e], q->table, ls->k[e], v3_neg(w), lambda_nm);
    if (r->delta && ls->scene->emitters[e].delta.type == DELTA_PROJECTION)   /* its texels */
        return delta_projection_Le(&ls->scene->emitters[e], ls->k[e], w, lambda_nm);
    if (r->delta) return spec_eval_scaled(q->shape, q->scale, q->norm, lambda_nm);  /* I or L */
    if (!r->twosided && v3_dot(n, w) <= 0.0f) return 0.0f;
    em = &ls->scene->emitters[e];
    f = em->prim_scale && at ? prim_factor(ls->scene, em, at->prim) : 1.0f;   /* "power" */
    if (em->image && at)
        return f * (float)(ls->k[e] * tex_eval(ls->scene->textures, em->image - 1, at, lambda_nm)
                           * spec_eval(em->L, lambda_nm));
    return f * spec_eval_scaled(q->shape, q->scale, q->norm, lambda_nm);
}

float light_Le(const LightSampler *ls, int e, Vec3 n, Vec3 w, float lambda_nm)
{
    return light_Le_at(ls, e, n, w, NULL, lambda_nm);
}

void light_spectrum(const LightSampler *ls, int e, Spectrum *Le) { le_tabulate(&ls->Le[ls->ref[e].le], Le); }
const Spectrum *light_spectrum_sum(const LightSampler *ls) { return &ls->le_sum; }
int light_n_pieces(const LightSampler *ls) { return ls->n_pieces; }
int light_piece_emitter(const LightSampler *ls, int piece) { return ls->pieces[piece].emitter; }

int light_piece_of(const LightSampler *ls, int e, int prim)
{
    if (ls->piece_of_tri && prim >= 0 && prim < ls->scene->n_tris && ls->piece_of_tri[prim] >= 0)
        return ls->piece_of_tri[prim];
    return ls->emitter_piece[e];
}

int light_sample(const LightSampler *ls, int piece, Vec3 ref, Vec3 ns, const float u[3],
                 EmitterSample *out)
{
    const LightPiece *pc = &ls->pieces[piece];
    int lo = 0, hi;
    Receiver rx;
    rx.p = ref; rx.ns = ns; rx.shape = ls->opt.area_sampling;
    out->delta = 0;
    if (pc->count == 0) {                        /* a whole emitter */
        if (pc->tri_cdf)
            return sample_mesh(ls->scene, pc->tri_cdf, pc->tri_begin, pc->tri_count, pc->area, &rx, u, out);
        return sample_emitter(ls->scene, pc->emitter, &rx, u, out);
    }
    /* a cluster: a triangle by area (first cdf entry above u[0]), then a point */
    hi = pc->count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (ls->piece_cdf[pc->first + mid] <= u[0]) lo = mid + 1; else hi = mid;
    }
    return sample_triangle(ls->scene, ls->piece_tri[pc->first + lo], pc->area, &rx, u[1], u[2], out);
}

float light_pdf_sa(const LightSampler *ls, int piece, Vec3 ref, Vec3 ns, Vec3 p, Vec3 n, int prim)
{
    Receiver rx;
    if (piece < 0 || piece >= ls->n_pieces) return 0.0f;
    rx.p = ref; rx.ns = ns; rx.shape = ls->opt.area_sampling;
    if (ls->pieces[piece].count == 0)             /* a whole emitter (also an infinite one) */
        return pdf_emitter(ls->scene, ls->pieces[piece].emitter, &rx, p, n, prim);
    return pdf_triangle(ls->scene, prim, ls->pieces[piece].area, &rx, p, n);
}

/* ------------------------------------------------------------------ selection */

/* Row of a wavelength in the spectral table T: the thesis' 60 bins over 400-700 nm
   are rows SPD_UV_BINS.., the 20 UV bins over 300-400 nm (fluorescence excitation,
   docs/FLUORESCENCE.md §5) rows 0..19; -1 outside 300-700 nm. */
static int spd_bin(float lambda)
{
    int b;
    if (lambda >= (float)SPEC_UV_MIN && lambda < LAMBDA_LO) {
        b = (int)((lambda - (float)SPEC_UV_MIN) / SPD_BIN_NM);
        return b >= SPD_UV_BINS ? SPD_UV_BINS - 1 : b;
    }
    if (!(lambda >= LAMBDA_LO && lambda <= LAMBDA_HI)) return -1;
    b = (int)((lambda - LAMBDA_LO) / SPD_BIN_NM);
    return SPD_UV_BINS + (b >= SPD_BINS ? SPD_BINS - 1 : b);
}

/* The unnormalised weights w[i] of the context for the O(n) strategies (spatial,
   spd, product, spectral-spatial); returns their sum.  Both light_select and
   light_select_pmf go through here, so they cannot disagree.  *fell_back = 1
   when a spectral strategy had to use the spatial weights. */
static double context_weights(LightSampler *ls, const LightCtx *c, double *w, int *fell_back)
{
    double *reach = w + ls->n;                   /* callers give 2n doubles */
    int n = ls->n, i, j;
    SelStrategy st = ls->opt.strategy;
    double sum = 0.0;
    const float *vt = NULL;
    *fell_back = 0;
    if (c->voxel >= 0 && c->voxel < ls->n_voxels) vt = voxel_table(ls, c->voxel);
    if (!vt || vt == VOXEL_FAILED) {             /* out of memory: uniform, for good */
        for (i = 0; i < n; i++) w[i] = 1.0;
        return n;
    }
    /* The voxel's table holds receivers on every side of an emitter; the shading
       point is on one.  An emitter that cannot reach p (p behind a flat one-sided
       emitter, or on it) gets weight 0 wherever the spatial table is used: the
       table would otherwise give it the share earned by the voxel's receivers in
       front of it (section 4). */
    for (i = 0; i < n; i++) reach[i] = emitter_can_reach(ls->scene, i, c->p) ? 1.0 : 0.0;
    if (st != SEL_SPATIAL && (c->hero_only || c->shifted || ls->opt.all_wavelengths)) {
        /* spectral weights, summed over the wavelengths that count here */
        for (i = 0; i < n; i++) w[i] = 0.0;
        for (j = 0; j < HERO_N; j++) {
            int b;
            double cj = 1.0;
            if (!(c->alive & (1u << j))) continue;
            if (c->hero_only && j > 0) continue;
            b = spd_bin(c->lambda[j]);
            if (b < 0) continue;
            if (ls->opt.throughput_weighted && ls->opt.all_wavelengths) cj = c->beta[j];
            if (!(cj > 0.0)) continue;
            for (i = 0; i < n; i++) {
                double e = ls->T[b * n + i];
                if (st == SEL_PRODUCT) e *= vt[i] * reach[i];
                else if (st == SEL_SPECTRAL_SPATIAL) e *= vt[n + i] * reach[i];
                w[i] += cj * e;
            }
        }
        for (i = 0; i < n; i++) sum += w[i];
        if (sum > 0.0 && isfinite(sum)) return sum;
        *fell_back = 1;                          /* no emitter for these bins */
    }
    sum = 0.0;
    for (i = 0; i < n; i++) { w[i] = vt[i] * reach[i]; sum += w[i]; }
    return sum;
}

/* Small scenes have a handful of emitters; 64 are tested.  Stack storage up to
   that many, heap beyond. */
#define SEL_STACK 128

int light_select(LightSampler *ls, const LightCtx *c, float u, float *pmf, int *fell_back)
{
    double wbuf[2 * SEL_STACK], *w = wbuf, sum, acc = 0.0, target;
    int n = ls->n, i, fb, chosen = -1;
    SelStrategy st = ls->opt.strategy;
    *pmf = 0.0f;
    if (fell_back) *fell_back = 0;
    if (n == 0) return -1;
    if (st == SEL_UNIFORM || st == SEL_ALL) {
        /* floor(u n): the same emitter as a scan of n weights 1 */
        i = (int)((double)u * n);
        if (i >= n) i = n - 1;
        *pmf = (float)(1.0 / n);
        return i;
    }
    if (st == SEL_POWER) {
        /* the first i with u < cdf[i + 1], by bisection */
        int lo = 0, hi = n;
        target = (double)u;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (target < ls->power_cdf[mid + 1]) hi = mid; else lo = mid + 1;
        }
        chosen = lo < n ? lo : ls->power_last;   /* round-off at u -> 1: last positive */
        if (chosen >= 0) *pmf = ls->power_pmf[chosen];
        return chosen;
    }
    if (is_tree(st)) return light_tree_select(ls->tree, c, u, pmf);
    if (n > SEL_STACK && !(w = (double *)malloc(sizeof(double) * 2 * (size_t)n))) return -1;
    sum = context_weights(ls, c, w, &fb);
    if (fell_back) *fell_back = fb;
    if (sum > 0.0) {
        target = (double)u * sum;
        for (i = 0; i < n; i++) {
            acc += w[i];
            if (target < acc && w[i] > 0.0) { chosen = i; break; }
        }
        if (chosen < 0)                          /* round-off at u -> 1: last positive */
            for (i = n - 1; i >= 0; i--)
                if (w[i] > 0.0) { chosen = i; break; }
        if (chosen >= 0) *pmf = (float)(w[chosen] / sum);
    }
    if (w != wbuf) free(w);
    return chosen;
}

float light_select_pmf(LightSampler *ls, const LightCtx *c, int piece)
{
    double wbuf[2 * SEL_STACK], *w = wbuf, sum;
    int n = ls->n, fb;
    SelStrategy st = ls->opt.strategy;
    float p = 0.0f;
    if (piece < 0 || piece >= ls->n_pieces) return 0.0f;
    if (st == SEL_UNIFORM || st == SEL_ALL) return (float)(1.0 / n);
    if (st == SEL_POWER) return ls->power_pmf[piece];
    if (is_tree(st)) return light_tree_pmf(ls->tree, c, piece);
    if (n > SEL_STACK && !(w = (double *)malloc(sizeof(double) * 2 * (size_t)n))) return 0.0f;
    sum = context_weights(ls, c, w, &fb);
    if (sum > 0.0) p = (float)(w[piece] / sum);
    if (w != wbuf) free(w);
    return p;
}

/* ------------------------------------------------------------------ what NEE asks */

/* The integrator (path.c) asks here, not of the strategy, how NEE takes its
   pieces: every strategy chooses one piece with one uniform number, while "all"
   takes every piece, each with probability 1 (a sum over the pieces, not a
   choice), and needs no number. */
int light_nee_count(const LightSampler *ls, int *needs_u)
{
    int all = ls->opt.strategy == SEL_ALL;
    *needs_u = !all;
    return all ? ls->n_pieces : 1;
}

int light_nee_piece(LightSampler *ls, const LightCtx *c, int k, float u, float *P, int *fell_back)
{
    if (ls->opt.strategy != SEL_ALL) return light_select(ls, c, u, P, fell_back);
    *P = 1.0f;
    if (fell_back) *fell_back = 0;
    return k;
}

float light_nee_pmf(LightSampler *ls, const LightCtx *c, int piece)
{
    return ls->opt.strategy == SEL_ALL ? 1.0f : light_select_pmf(ls, c, piece);
}

/* Where P(e | c) comes from, in words: the rule of context_weights (section 2). */
const char *light_nee_source(const LightSampler *ls, const LightCtx *c, int fell_back)
{
    SelStrategy st = ls->opt.strategy;
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
    if (ls->opt.all_wavelengths || c->shifted)
        return "spectral table summed over the alive wavelengths' bins";
    return "spatial table of the voxel: several wavelengths alive, spectral tables act on hero-only paths";
}
