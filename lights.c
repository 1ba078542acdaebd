/* lights.c - emitters, and how next event estimation chooses one of them.

   Exported (specnee.h section 11): emitters_prepare, emitter_radiance,
   emitter_sample, emitter_pdf_sa, emitter_can_reach, light_sampler_build/free,
   light_Le, light_spectrum, light_n_pieces, light_piece_emitter, light_piece_of,
   light_sample, light_pdf_sa, light_voxel, light_select, light_select_pmf,
   light_sampler_bytes, sel_from_name, sel_name.

   1. Emitters.  An emitter is one AreaLightSource shape: a whole mesh, a sphere, or
      another quadric (disk, cylinder, cut sphere: shapes.c, sampled uniformly by area).
      Its radiance follows pbrt-v4's normalisation (DiffuseAreaLight::Create):
          Le(lambda) = scale * L(lambda) / sum_{lambda = lo..hi, 1 nm} ybar(lambda) L(lambda)
      over the range the film integrates, so a directly seen emitter has Y = scale.
      The range belongs to a render (--wide samples 360-830 nm), so Le is computed
      by light_sampler_build and kept in the LightSampler, which the render owns
      (once per distinct (L, scale, kind): emitters of one lamp type share it);
      the Scene keeps only what the file says and the geometry (area, triangle CDF).
      A one-sided emitter emits only to the side its oriented normal points to.
      Points are sampled by area: a triangle with probability area_t / A, then a
      uniform point on it (u = 1 - sqrt(u1), v = u2 sqrt(u1)).  Converted to solid
      angle at the reference point x (pbrt-v3/v4 Shape::Sample):
          p_sigma(y) = |x - y|^2 / (A |cos theta_y|).

   2. Selection.  light_select picks a piece i (an emitter, or with the light trees
      a cluster of triangles of a large emissive mesh, section 4) with probability
      P(i | c), where the context c = (point, normal, voxel, wavelengths, alive set)
      is fixed at the vertex and stored by the integrator; light_select_pmf(c, i)
      returns the same number for a piece hit by BSDF sampling (the consistency
      contract, items C1-C4 of docs/THEORY.md section 5).
      Strategies (T_i(b) = bin average of Le_i over bin b, times area x sides with
      the power metric):
        uniform           1/n                                   (O(1): a lookup)
        power             proportional to pi * A_i * (2 if two-sided) * int_400^700 Le_i
                                      (O(log n): binary search in a CDF; pmf a lookup)
        spatial           s_i(v): pbrt-v3's SpatialLightDistribution (see below)
        spd               thesis Sec. 2: T_i(b(lambda_h)) / sum_k T_k(b(lambda_h))
        product           thesis Sec. 2 ("combined PDF"): s_i(v) T_i(b) / sum_k s_k(v) T_k(b)
        spectral-spatial  beyond the thesis: g_i(v) T_i(b) / sum_k g_k(v) T_k(b), with
                          g_i(v) the spatial estimate for UNIT radiance, so brightness
                          is counted once (the thesis' argument for the unit
                          metric, thesis Sec. 2 "Combining PDFs")
        tree              a light BVH (pbrt-v4's BVHLightSampler; Conty Estevez and
                          Kulla 2018), importance from total power (section 4)
        spectral-tree     the same tree, importance from the power in the bins of
                          the alive wavelengths (section 4)
      T_i(b) with the unit metric (the default) is the bin average of the emitted
      radiance Le_i, the thesis' "unit emission"; the power metric multiplies it by
      the area (x 2 if two-sided), the thesis' "power".
      The thesis' spectral strategies act only where the path carries the hero
      alone (LightCtx.hero_only, i.e. alive == 1: after a wavelength-dependent event
      terminated the secondaries, or with --single-wavelength); while several wavelengths are
      alive the thesis uses the spatial distribution.  Beyond the thesis
      (all_wavelengths, and after a fluorescent shift that kept several wavelengths,
      LightCtx.shifted: they are all absorbed ones then, and the spatial table,
      built from visible light, knows nothing of them), the weight of emitter i is sum over alive j of
      c_j * e_i(lambda_j), with e_i the strategy's unnormalised weight and c_j = 1
      or the path throughput at lambda_j.  Either way P(i | c) is the same whichever
      alive wavelength is the hero: item C4 of the contract, which the single
      q_nee of render.c's MIS weights needs (docs/THEORY.md section 6 derives why).
      When every emitter has weight 0 for the hero's bin (or the hero lies outside
      400-700 nm) the spatial distribution is used (counted as a fallback); the same
      rule runs in light_select_pmf.  spatial, spd, product and spectral-spatial
      cost O(n) per vertex; uniform O(1), power O(log n), the trees O(log n).

   3. The spatial distribution (pbrt-v3 lightdistrib.cpp; docs/THEORY.md section 5): a grid
      over the scene bounds with SPATIAL_RES cells on the longest axis; per voxel,
      for k = 0..127, a receiver point at Halton(2,3,5)(k) in the voxel and an
      emitter sample at Halton(7,11,13)(k); each emitter j accumulates
          g_j += [emitter faces the receiver] / p_sigma,   s_j = Y_j g_j,
      an estimate of the unoccluded scalar irradiance (no cosine, no visibility).
      Y_j = scale_j is the emitter's luminance.  An infinite light (infinite.c)
      fills the whole sphere: g_j = 4 pi per receiver, Y_j = the luminance of its
      (mean) radiance; its power is pbrt-v4's Phi = 4 pi^2 R^2 int Le (R: the
      scene's bounding-sphere radius) and its spectral table is its (mean) Le.  A floor of 1e-3 of the mean weight
      keeps every emitter possible.  Voxels are built lazily on first use (under an
      OpenMP critical section) or all up front; both give identical tables because
      the computation is deterministic.  Cost: 128 n evaluations per voxel touched
      and 2n floats per voxel.

   4. The light tree (Conty Estevez and Kulla, "Importance Sampling of Many Lights
      with Adaptive Tree Splitting", HPG 2018; pbrt-v4's BVHLightSampler and
      LightBounds, pbrt book 4th ed. section 12.6.3; written here from the
      equations).  A tree over the pieces, built once per render as a binary
      tree and collapsed into a 4-wide one for the walk (below).  Every binary
      node stores the box of its pieces, an orientation cone (axis w; theta_o,
      the spread of the emitting normals around w; theta_e = pi/2, how far past
      a normal a diffuse emitter still emits), a two-sided flag, its radiant power
      Phi = sum over pieces of pi A (2 if two-sided) int Le, and its power in each
      5 nm bin of the sampled range (60 bins over 400-700 nm, 94 over 360-830),
      preceded by the bins from 300 nm up to the sampled range (20 over 300-400,
      12 over 300-360): a fluorescent vertex moves the path to an excitation
      wavelength lambda_i < 400 nm (docs/FLUORESCENCE.md section 5), and the thesis'
      future work is that the spectral table "can be extended to store additional
      bins" there.  Phi itself stays the power over the sampled range.
      Importance of a node at a shading point p with normal n:
          I = Phi_c * cos(theta') * cos(theta_i') / d^2
      d = distance from p to the box centre; theta_b = the half-angle under
      which the box's bounding sphere (radius r) is seen from p.  Inside that
      sphere (theta_b = pi) no angle is bounded and I = Phi_c / max(d, r/4)^2:
      still 1/d^2, so that of two overlapping nodes the one whose centre is
      near p is preferred (equal to the outside's value at d = r; the clamp
      keeps it finite at the centre; before session 7 it was Phi_c / r^2
      everywhere inside, which on the 1024-lamp hall of tools/bench_lights
      cost 8% more MSE at equal spp, docs/lighttree.md); theta_w = angle
      between w and the direction from the centre to p (folded into [0, pi/2]
      when two-sided);
      theta' = max(0, theta_w - theta_o - theta_b), and I = 0 when theta' >= theta_e
      (no emitter below faces p); theta_i' = max(0, theta_i - theta_b) with
      theta_i the angle between n and the direction to the centre (|cos|: the
      surface may transmit).  Behind the box: a one-sided node with
      theta_t = theta_o + theta_e < pi emits only into directions within
      theta_t of w, so a point with w . p - h <= -sin(theta_t - pi/2)+ (|d| + r),
      h = min of w . x over its pieces' vertices (behind the plane that
      bounds them on the side their light cannot reach, by a slack that
      grows with the spread of their normals), gets I = 0 even inside the
      bounding sphere, where theta_b = pi bounds nothing (node_behind; a
      flat group of ceiling lamps seen from the ceiling just above them: on
      suzanne the MSE of spectral-tree against product at 64 spp went from
      +5.5% to -7.4%, docs/lighttree.md).  Each bound only overestimates, so a node that can
      light p never gets 0.  lane_importance computes it without normalising
      the direction or taking an angle: each cosine is a ratio of dot products
      and square roots of d, and I = Phi_c (1/d^2) (X/d^2) (Y/d^2) with
      X = d^2 cos theta', Y = d^2 cos theta_i' (its comment derives them): three
      square roots and one division.  node_importance4 computes the four
      children of a 4-wide node side by side with SSE2 (every x86-64 gcc and
      clang), the same operations in the same order, so the results are the
      same to the bit (tested); elsewhere (tcc, other processors) it calls
      lane_importance four times.  Phi_c is the power that counts in the context:
          tree           Phi (all wavelengths together: pbrt-v4's sampler)
          spectral-tree  sum over alive j of c_j Phi(bin(lambda_j)), c_j = 1 or the
                         throughput (--throughput-weighted): the hero's bin alone
                         after a wavelength-dependent event (a UV bin after a
                         fluorescent shift), the thesis' spectral preference; symmetric in the alive set, so the spectral MIS
                         weights stay intact (like --all-wavelengths above).
      The walk reads a 4-wide tree: the binary tree collapsed so that a node's
      children are the binary node's grandchildren (a binary child that is a
      leaf stays one child: 2 to 4 children), breadth first (the upper levels,
      which every walk reads, lie together), each node's children described in
      four lanes of one 224-byte record, their bin powers bin-major (the four
      children's powers in one bin side by side).  Selection walks from the
      root: at a node with children importances I_0..I_3 it goes to child k
      with probability I_k / sum I (the path stops when the sum is 0: nothing
      below can light p), narrows the interval of u that leads to the chosen
      child and multiplies the probabilities.  A walk makes half the levels
      of the binary tree's, each at about the cost of one scalar importance.
      The pmf of a given piece walks the same nodes along the piece's trail
      (digit d, two bits: the child taken at depth d), calling the same
      importance function: select and pmf cannot disagree.
      Build: top-down over the box centroids, LIGHT_TREE_BINS candidate planes per
      axis scored by the surface-area-orientation cost of both sides,
          M = Phi * area(box) * M_omega(theta_o, theta_e) * (longest extent / extent on the axis)
          M_omega = 2 pi (1 - cos theta_o) + pi/2 (2 t sin theta_o - cos(theta_o - 2 t)
                    - 2 theta_o sin theta_o + cos theta_o),   t = min(theta_o + theta_e, pi)
      (M_omega is the solid-angle measure of the cone of emitted directions: the
      integral of cos(theta - theta_o) sin theta from theta_o to t, our derivation).
      When all centroids coincide, or below depth 32, the middle of the list (in
      centroid order) is taken: binary depth <= 32 + log2 n <= 63, so the 4-wide
      depth is at most 32 and a 64-bit trail holds it.  O(n log n) time (n log^2 n
      for the median fallbacks), 2n - 1 binary nodes, at most n - 1 4-wide ones.
      Large emissive meshes (more than LIGHT_CLUSTER_TRIS triangles) are split into
      clusters of at most LIGHT_CLUSTER_TRIS nearby triangles (recursive median cuts
      of their centroids); each cluster is a leaf with its own box, cone and area,
      and the mesh's spectrum.  A point is then sampled by area inside the chosen
      cluster, so p_sigma uses the cluster's area.
      Infinite lights have no position, so they are not in the tree: as in
      pbrt-v4's BVHLightSampler, each of the n_inf infinite lights is chosen with
      probability 1 / (n_inf + 1) and the tree with the rest; the pmf of a tree
      piece is that share times its branch probabilities.  Where the tree cannot
      light p (no piece, or the root's importance is 0) the infinite lights share
      everything, 1 / n_inf each.

   5. Which side an emitter lights (emitter_can_reach).  The voxel table is an
      average over receivers spread through the whole voxel, so a voxel cut by a
      one-sided emitter credits it with the light its front receivers get - also
      at shading points behind it or on it (the emitter's own back face, lit by
      another lamp, was a band of noise: NEE chose the emitter that could not
      reach the point most of the time).  So where the spatial table is used
      (spatial, product, spectral-spatial, and spd while every wavelength is
      alive), emitter i's weight is multiplied by reach_i(p) in {0, 1}:
        mesh, one-sided    reach = [some triangle t has n_t . p - d_t > eps]
        mesh, two-sided    reach = [some triangle t has |n_t . p - d_t| > eps]
        sphere             outside of an outward one, inside of a flipped one
        disk               its plane, as a one-triangle mesh (shapes.c)
        cylinder, cut sphere  reach = 1 (not exact: "may reach")
        bigger meshes      reach = 1 (over REACH_MAX_TRIS triangles, or shading
                           normals against the geometry: a limit of the voxel
                           tables; the light tree's orientation cones cover it)
      eps = 1e-5 (1 + the largest coordinate), the ray-offset scale of bvh.c, so
      a point on the emitter (within round-off of its plane) is excluded.  The
      mask is exact for the shapes it tests, never 0 where light can arrive from
      more than eps away, and it is part of context_weights, so light_select and
      light_select_pmf agree; if it zeroes every emitter NEE is skipped, which is
      unbiased because no emitter can light the point. */
#include "specnee.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif
/* The light tree evaluates a node's four children at once with SSE2 where the
   compiler offers it (every x86-64 gcc and clang); elsewhere (tcc, other
   processors, or -DSPECNEE_NO_SIMD) with the scalar code it mirrors, to the bit
   (section 4; the test lighttree_simd_matches_scalar). */
#if defined(__SSE2__) && !defined(__TINYC__) && !defined(SPECNEE_NO_SIMD)
#define TREE_SIMD 1
#include <emmintrin.h>
#else
#define TREE_SIMD 0
#endif

/* ------------------------------------------------------------------ emitters */

static double tri_area(const Scene *s, int t)
{
    const Triangle *tr = &s->tris[t];
    Vec3 e1 = v3_sub(s->P[tr->v[1]], s->P[tr->v[0]]);
    Vec3 e2 = v3_sub(s->P[tr->v[2]], s->P[tr->v[0]]);
    return 0.5 * (double)v3_len(v3_cross(e1, e2));
}

/* The planes of a small emitter mesh, for emitter_can_reach (section 5): per
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
    em->reach_eps = 1e-5 * (1.0 + big);
    if (sh->tri_count > REACH_MAX_TRIS) return 1;
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

/* sum_{1 nm over [lo, hi]} ybar(lambda) S(lambda): the luminance that normalises
   an emitter's spectrum S (for an image map, S = D65, held in L). */
static double luminance_sum(const Spectrum *S, float lo_nm, float hi_nm)
{
    double norm = 0.0;
    int lam;
    for (lam = (int)ceilf(lo_nm); lam <= (int)floorf(hi_nm); lam++) {
        float xyz[3];
        cie_xyz((float)lam, xyz);
        norm += (double)xyz[1] * spec_eval(S, (float)lam);
    }
    return norm;
}

/* Le = scale * S / luminance_sum(L) with S = L (S = the mean colour's spectrum
   for an image map), and k = scale / luminance_sum(L), which infinite.c applies
   to an image map's texels. */
static int radiance_and_k(const Scene *s, int e, float lo_nm, float hi_nm, Spectrum *Le,
                          double *k, Error *err)
{
    const Emitter *em = &s->emitters[e];
    const Spectrum *shape = em->inf && em->inf->res > 0 ? &em->inf->mean : &em->L;
    double norm = em->absolute ? 1.0 : luminance_sum(&em->L, lo_nm, hi_nm);
    int lam;
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
    for (lam = 0; lam < SPEC_N; lam++)
        Le->v[lam] = (float)(em->scale * shape->v[lam] / norm);
    for (lam = 0; lam < SPEC_UV_N; lam++)
        Le->uv[lam] = (float)(em->scale * shape->uv[lam] / norm);
    *k = em->scale / norm;
    return 1;
}

int emitter_radiance(const Scene *s, int e, float lo_nm, float hi_nm, Spectrum *Le, Error *err)
{
    double k;
    return radiance_and_k(s, e, lo_nm, hi_nm, Le, &k, err);
}

int emitters_prepare(Scene *s, Error *err)
{
    int e, t;
    for (e = 0; e < s->n_emitters; e++) {
        Emitter *em = &s->emitters[e];
        const Shape *sh;
        Spectrum Le;
        /* A UV lamp has no luminance: its L is absolute spectral radiance, and the
           decision is the emitter's own (made on 400-700 nm, whatever range the
           film integrates), so every range gives it the same meaning. */
        em->absolute = !(luminance_sum(&em->L, LAMBDA_LO, LAMBDA_HI) > 0.0);
        if (!emitter_radiance(s, e, LAMBDA_LO, LAMBDA_HI, &Le, err)) return 0;
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
            double acc = 0.0;
            em->tri_cdf = (float *)malloc(sizeof(float) * (size_t)(sh->tri_count + 1));
            if (!em->tri_cdf) { error_set(err, sh->file, sh->line, "out of memory"); return 0; }
            em->tri_cdf[0] = 0.0f;
            for (t = 0; t < sh->tri_count; t++) {
                acc += tri_area(s, sh->tri_begin + t);
                em->tri_cdf[t + 1] = (float)acc;
            }
            em->area = acc;
            for (t = 1; t <= sh->tri_count; t++) em->tri_cdf[t] = acc > 0 ? (float)(em->tri_cdf[t] / acc) : 1.0f;
            em->tri_cdf[sh->tri_count] = 1.0f;
        }
        if (!(em->area > 0.0)) {
            error_set(err, sh->file, sh->line, "AreaLightSource: emitting shape has zero area");
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

/* A uniform point on triangle tri (u = 1 - sqrt(u1), v = u2 sqrt(u1)), with the
   oriented geometric normal the integrator sees at a hit there. */
static void point_on_triangle(const Scene *s, int tri, Vec3 ref, float u1, float u2, EmitterSample *out)
{
    HitRecord h;
    SurfacePoint sp;
    Ray dummy;
    float su = sqrtf(u1);
    h.t = 0.0f;
    h.prim = tri;
    h.b1 = u2 * su;                    /* barycentric of v1 */
    h.b2 = 1.0f - su;                  /* barycentric of v2 */
    dummy.o = ref; dummy.d = v3(0, 0, 1); dummy.tmax = 0.0f;
    scene_surface_point(s, &dummy, &h, &sp);
    out->p = sp.p;
    out->n = sp.ng;
}

/* A point on a mesh by area: a triangle (the first of tri_count whose cdf entry
   tri_cdf[t + 1] lies above u0, binary search), then a point on it; area: the
   whole mesh's.  emitter_sample and light_sample share it. */
static int sample_mesh(const Scene *s, const float *tri_cdf, int tri_begin, int tri_count, double area,
                       Vec3 ref, float u0, float u1, float u2, EmitterSample *out)
{
    int lo = 0, hi = tri_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (tri_cdf[mid + 1] <= u0) lo = mid + 1; else hi = mid;
    }
    point_on_triangle(s, tri_begin + lo, ref, u1, u2, out);
    return finish_sample(ref, area, out);
}

int emitter_sample(const Scene *s, int e, Vec3 ref, float u0, float u1, float u2,
                   EmitterSample *out)
{
    const Emitter *em = &s->emitters[e];
    const Shape *sh;
    out->delta = 0;
    if (em->delta.type != DELTA_NONE) return delta_sample(&em->delta, ref, out);
    if (em->inf) {
        /* a direction; the "point" lies beyond the scene's bounding sphere, so a
           shadow ray to it tests the whole way out */
        if (!inf_sample(em, u1, u2, &out->wi, &out->pdf_sa)) return 0;
        (void)u0;
        out->dist = (float)(2.0 * em->inf->radius + v3_len(v3_sub(ref, em->inf->center)));
        out->p = v3_add(ref, v3_mul(out->wi, out->dist));
        out->n = v3_neg(out->wi);
        return 1;
    }
    sh = &s->shapes[em->shape];
    if (sh->type == SHAPE_SPHERE) {
        float z = 1.0f - 2.0f * u1, r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
        float phi = 2.0f * PI_F * u2;
        Vec3 dir = v3(r * cosf(phi), r * sinf(phi), z);
        (void)u0;
        out->p = v3_add(sh->center, v3_mul(dir, sh->radius));
        out->n = sh->flip ? v3_neg(dir) : dir;
    } else if (shape_is_quadric(sh->type)) {
        /* uniform by world area (scene.c refuses an emitter where it would not be) */
        (void)u0;
        quadric_sample(sh, u1, u2, &out->p, &out->n);
    } else {
        return sample_mesh(s, em->tri_cdf, sh->tri_begin, sh->tri_count, em->area, ref, u0, u1, u2, out);
    }
    return finish_sample(ref, em->area, out);
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

float emitter_pdf_sa(const Scene *s, int e, Vec3 ref, Vec3 p, Vec3 n)
{
    if (s->emitters[e].delta.type != DELTA_NONE) return 0.0f;   /* no direction finds it */
    if (s->emitters[e].inf) {
        Vec3 d = v3_sub(p, ref);
        if (!(v3_dot(d, d) > 0.0f)) return 0.0f;
        return inf_pdf(&s->emitters[e], v3_norm(d));
    }
    return pdf_sa_area(s->emitters[e].area, ref, p, n);
}

/* ------------------------------------------------------------------ the sampler */

/* A piece: what NEE chooses.  A whole emitter (count == 0, sampled by
   emitter_sample), or a cluster of triangles of a split mesh. */
typedef struct {
    int emitter;
    int first, count;          /* triangles ls->piece_tri[first .. first + count) */
    double area;
    uint64_t trail;            /* light trees: bit d = 1 if the path to the leaf takes
                                  the second child at depth d */
    int depth;                 /* number of branches from the root to the leaf */
    /* a whole mesh emitter (count == 0): what sample_mesh reads, copied here so
       that NEE does not read the scene's Emitter (2 KB, mostly its spectrum) and
       Shape for every sample (a cache miss each with many emitters); NULL:
       spheres and infinite lights, sampled by emitter_sample */
    const float *tri_cdf;
    int tri_begin, tri_count;
} Piece;

/* Piece pc is the whole emitter e. */
static void piece_whole(const Scene *s, Piece *pc, int e)
{
    const Emitter *em = &s->emitters[e];
    pc->emitter = e;
    pc->area = em->area;
    if (em->shape >= 0 && s->shapes[em->shape].type == SHAPE_MESH) {
        pc->tri_cdf = em->tri_cdf;
        pc->tri_begin = s->shapes[em->shape].tri_begin;
        pc->tri_count = s->shapes[em->shape].tri_count;
    }
}

/* A node of the binary tree that the build makes (section 4), before it is
   collapsed into 4-wide nodes.  Depth-first order: the first child of an
   interior node i is node i + 1, the second is nodes[i].second. */
typedef struct {
    float c[3], r;             /* centre and radius of the box's bounding sphere */
    float axis[3];             /* orientation cone: unit axis w ... */
    float cos_o, sin_o, cos_e; /* ... theta_o, cos theta_e (cos_o = -1: every direction) */
    float power;               /* radiant power over the sampled range */
    float behind, slack;       /* nothing below lights p when (p - c) . axis <=
                                  behind - slack L (p behind the plane that bounds the
                                  box on the side its light cannot reach); behind =
                                  -inf where there is no such plane (node_behind) */
    int32_t second;            /* interior: index of the second child; leaf: -1 - piece */
    int32_t twosided;
} TreeNode;

/* A node of the light tree that the walk reads (section 4): up to four
   children, each described in one lane of these arrays (structure of arrays,
   so that the four importances are computed side by side).  A lane that holds
   no child has power 0, so its importance is 0 and it is never taken. */
typedef struct {
    float cx[4], cy[4], cz[4], r[4];   /* each child's bounding sphere */
    float ax[4], ay[4], az[4];         /* its orientation cone: unit axis w ... */
    float cos_o[4], sin_o[4];          /* ... theta_o ... */
    float cos_e[4];                    /* ... and cos theta_e */
    float behind[4], slack[4];         /* TreeNode.behind and .slack */
    int32_t twosided[4];
    int32_t child[4];                  /* >= 0: a node; < 0: -1 - piece */
} TreeNode4;                           /* 224 bytes */

/* Per emitter, the little that every emitter hit and NEE sample reads (light_Le):
   its radiance's index in LightSampler.Le, and how it emits. */
typedef struct { int le, twosided, inf, delta; } EmitterRef;

struct LightSampler {
    const Scene *scene;
    SelOptions opt;
    int n;                     /* number of emitters */
    Spectrum *Le;              /* the distinct radiances for the sampled range: emitters
                                  with the same L, scale and kind share one (a hall of
                                  1024 lamps of six spectra keeps 6, not 1024 x 2 KB,
                                  which NEE would read from all over memory) */
    int n_le;
    EmitterRef *ref;           /* per emitter: what light_Le reads, in one place */
    double *k;                 /* per emitter: scale / luminance_sum(L) (image maps' texels) */
    float *bin;                /* n x SPD_BINS: bin averages of Le over 400-700 nm */
    double *power;             /* per emitter: radiant power over 400-700 nm */
    double *power_cdf;         /* power strategy: n + 1 running sums of power_pmf */
    int power_last;            /* last emitter with positive power_pmf */
    float *power_pmf;          /* power strategy */
    float *T;                  /* (SPD_UV_BINS + SPD_BINS) x n spectral table (unit or power
                                  metric): rows 0..19 are 300-400 nm, rows 20..79 the
                                  thesis' 60 bins over 400-700 nm */
    float *Y;                  /* luminance (= scale) per emitter (T and Y: only the
                                  strategies of context_weights, uses_grid) */
    /* pieces (section 4): without splitting piece i is emitter i */
    int n_pieces;
    Piece *pieces;
    int *emitter_piece;        /* per emitter: its piece, -1 when split */
    int *piece_tri;            /* triangles of the split meshes' clusters */
    float *piece_cdf;          /* parallel: cumulative area fraction within the cluster */
    int *piece_of_tri;         /* per scene triangle: its cluster, -1 (NULL: no splits) */
    /* light tree */
    int n_inf;                 /* infinite lights: chosen beside the tree (section 4) */
    int *inf_piece;            /* their pieces */
    int n_tree_pieces;         /* pieces in the tree (0: no tree) */
    TreeNode *nodes;           /* the binary tree (while building) */
    int n_nodes;
    TreeNode4 *nodes4;         /* the 4-wide tree: node 0 is the root (64-byte aligned
                                  inside nodes4_mem) */
    void *nodes4_mem;
    int n_nodes4;
    float *quad_power;         /* n_nodes4 x 4: the radiant power of node i's children
                                  over the sampled range (tree) */
    TreeNode4 top;             /* lane 0: the bounds of everything (tree_live) */
    float top_power;           /* and their power */
    int nb;                    /* bins per node (5 nm each): nb_uv below the sampled
                                  range, from 300 nm, then those of the range */
    int nb_uv;                 /* bins over [lo_nm - 5 nb_uv, lo_nm): 20 for 400-700 nm,
                                  12 for 360-830 (fluorescence excitation, section 4) */
    float *node_bin;           /* n_nodes x nb: power per bin (while building) */
    float *quad_bin;           /* nb x n_nodes4 x 4: for bin b and node i, the power of
                                  node i's four children side by side (bin-major: the
                                  entries of one bin, which a walk reads, lie together) */
    float *root_bin;           /* nb: the root's power per bin */
    float behind_margin;       /* 1e-5 (1 + the scene's largest |coordinate|): what
                                  TreeNode.behind gives away for round-off */
    /* spatial grid */
    int res[3];
    Vec3 bmin, bmax;
    long n_voxels;
    float **voxel;             /* per voxel: s[n] (spatial pmf) then g[n] (geometry) */
    double lazy_s;             /* seconds spent building voxels on first use (under the
                                  critical section, so the sum is time really spent) */
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

/* Lights without a position - infinite and distant lights - stand beside the
   light tree, each with a share of its own (section 4). */
static int beside_tree(const Emitter *em) { return em->inf || em->delta.type == DELTA_DISTANT; }

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

/* The per-voxel estimate of section 3 above: fills s[n] (a pmf) and g[n].
   Returns 0 (out[] untouched) when out of memory. */
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
        float u2 = (float)radical_inverse(13, (uint64_t)k);
        for (j = 0; j < n; j++) {
            EmitterSample es;
            if (s->emitters[j].inf) { g[j] += 4.0 * SPECNEE_PI; continue; }  /* the whole sphere */
            if (!emitter_sample(s, j, p, u0, u1, u2, &es)) continue;
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


/* ------------------------------------------------------------------ light tree */

/* An orientation cone: unit axis w, cos theta_o, cos theta_e. */
typedef struct { Vec3 w; float cos_o, cos_e; } Cone;

static Cone cone_full(float cos_e)
{
    Cone c;
    c.w = v3(0.0f, 0.0f, 1.0f);
    c.cos_o = -1.0f;
    c.cos_e = cos_e;
    return c;
}

/* The smallest cone holding both a and b (the cone of normals; theta_e: the
   larger of the two).  Where the two axes are opposite, the whole sphere. */
static Cone cone_union(Cone a, Cone b)
{
    double ta, tb, td, to, rot, len, cd;
    Vec3 perp;
    Cone c;
    float cos_e = fminf(a.cos_e, b.cos_e);
    if (a.cos_o <= -1.0f || b.cos_o <= -1.0f) return cone_full(cos_e);
    ta = acos(a.cos_o);
    tb = acos(b.cos_o);
    cd = v3_dot(a.w, b.w);
    td = acos(cd > 1.0 ? 1.0 : cd < -1.0 ? -1.0 : cd);
    if (td + tb <= ta) { a.cos_e = cos_e; return a; }          /* b inside a */
    if (td + ta <= tb) { b.cos_e = cos_e; return b; }          /* a inside b */
    to = 0.5 * (ta + td + tb);
    if (to >= SPECNEE_PI) return cone_full(cos_e);
    /* turn a's axis towards b's by to - ta, in the plane of the two axes */
    perp = v3_sub(b.w, v3_mul(a.w, (float)cd));
    len = v3_len(perp);
    if (!(len > 1e-7)) return cone_full(cos_e);
    rot = to - ta;
    c.w = v3_norm(v3_add(v3_mul(a.w, (float)cos(rot)), v3_mul(perp, (float)(sin(rot) / len))));
    c.cos_o = (float)cos(to);
    c.cos_e = cos_e;
    return c;
}

/* Solid-angle measure of the directions a cone emits into (section 4). */
static double cone_measure(const Cone *c)
{
    double to = acos(c->cos_o < -1.0f ? -1.0 : c->cos_o > 1.0f ? 1.0 : c->cos_o);
    double te = acos(c->cos_e < -1.0f ? -1.0 : c->cos_e > 1.0f ? 1.0 : c->cos_e);
    double t = to + te < SPECNEE_PI ? to + te : SPECNEE_PI;
    double so = sin(to);
    return 2.0 * SPECNEE_PI * (1.0 - cos(to)) +
           0.5 * SPECNEE_PI * (2.0 * t * so - cos(to - 2.0 * t) - 2.0 * to * so + cos(to));
}

/* What the build knows of each piece. */
typedef struct {
    Vec3 bmin, bmax, centroid;
    Cone cone;
    int twosided;
    double power;
} PieceBounds;

/* The bounds of a set of pieces, accumulated one at a time. */
typedef struct {
    Vec3 bmin, bmax;
    Cone cone;
    int twosided, any;
    double power;
} Acc;

static void acc_init(Acc *a) { memset(a, 0, sizeof *a); }

static void acc_add(Acc *a, const PieceBounds *b)
{
    if (!a->any) {
        a->bmin = b->bmin; a->bmax = b->bmax; a->cone = b->cone;
        a->twosided = b->twosided; a->power = b->power; a->any = 1;
        return;
    }
    a->bmin = v3_min(a->bmin, b->bmin);
    a->bmax = v3_max(a->bmax, b->bmax);
    a->cone = cone_union(a->cone, b->cone);
    a->twosided |= b->twosided;
    a->power += b->power;
}

static void acc_merge(Acc *a, const Acc *b)
{
    PieceBounds pb;
    if (!b->any) return;
    pb.bmin = b->bmin; pb.bmax = b->bmax; pb.cone = b->cone;
    pb.twosided = b->twosided; pb.power = b->power;
    acc_add(a, &pb);
}

/* cone_measure of the last cone asked (a build evaluates the same cone over
   and over: lamps that face one way), so that its trigonometry runs once. */
typedef struct { float cos_o, cos_e; double m; int valid; } MeasureMemo;

/* The split cost of one side: Phi * area(box) * M_omega (section 4). */
static double acc_cost(const Acc *a, MeasureMemo *memo)
{
    Vec3 d;
    if (!a->any) return 0.0;
    d = v3_sub(a->bmax, a->bmin);
    if (!memo->valid || memo->cos_o != a->cone.cos_o || memo->cos_e != a->cone.cos_e) {
        memo->cos_o = a->cone.cos_o;
        memo->cos_e = a->cone.cos_e;
        memo->m = cone_measure(&a->cone);
        memo->valid = 1;
    }
    return a->power * 2.0 * ((double)d.x * d.y + (double)d.y * d.z + (double)d.z * d.x) * memo->m;
}

typedef struct { float key; int idx; } KeyIdx;

static int cmp_key(const void *pa, const void *pb)
{
    const KeyIdx *a = (const KeyIdx *)pa, *b = (const KeyIdx *)pb;
    if (a->key < b->key) return -1;
    if (a->key > b->key) return 1;
    return a->idx < b->idx ? -1 : a->idx > b->idx;   /* ties: a deterministic order */
}

/* Sort items[0..n) by coordinate `axis` of their points (pts[item]). */
static void sort_by_axis(int *items, int n, const Vec3 *pts, int axis, KeyIdx *tmp)
{
    int i;
    for (i = 0; i < n; i++) { tmp[i].key = v3_get(pts[items[i]], axis); tmp[i].idx = items[i]; }
    qsort(tmp, (size_t)n, sizeof *tmp, cmp_key);
    for (i = 0; i < n; i++) items[i] = tmp[i].idx;
}

typedef struct {
    LightSampler *ls;
    const PieceBounds *pb;
    Vec3 *centroids;
    KeyIdx *tmp;
    double *le_avg;            /* per distinct radiance (LightSampler.Le), its nb bin
                                  averages: computed once, not once per piece */
    MeasureMemo memo;
} Builder;

static int longest_axis(Vec3 d)
{
    return d.x >= d.y && d.x >= d.z ? 0 : d.y >= d.z ? 1 : 2;
}

/* The scene triangle that is triangle j (0 <= j < piece_tri_count) of piece pc,
   a mesh piece whose emitter's shape is sh. */
static int piece_tri_count(const Piece *pc, const Shape *sh) { return pc->count ? pc->count : sh->tri_count; }
static int piece_triangle(const LightSampler *ls, const Piece *pc, const Shape *sh, int j)
{
    return pc->count ? ls->piece_tri[pc->first + j] : sh->tri_begin + j;
}

/* TreeNode.behind and .slack of a node with bounds a (section 4, "behind the
   box").  Every emitted direction omega of the node lies within theta_t =
   theta_o + theta_e of its axis w.  Light from a point x of the box reaches p
   only along omega = (p - x) / |p - x|, so only if
       w . (p - x) > cos(theta_t) |p - x| = -sin(delta) |p - x|,
   delta = theta_t - pi/2 (slack = sin(delta), 0 where theta_t <= pi/2; no
   plane at all where theta_t >= pi, where sin(delta) would shrink again, or
   for two-sided nodes).  With h = min of w . x over the vertices of the
   pieces' triangles (every emitting point is a convex combination of them;
   the box's corners would put the plane far behind a tilted panel),
   w . (p - x) <= w . p - h, and |p - x| <= |d| + r (d = p - c), so nothing
   below lights p when
       w . p - h <= -slack (|d| + r),
   i.e. in the walk's terms d . w <= behind - slack L, behind = h - w . c,
   L = sqrt(|d|^2 - r^2) + 2 r >= |d| + r outside the bounding sphere and
   L = 2 r >= |d| + r inside it.  The margin (behind_margin, larger than the
   round-off of d . w for points in the scene) and rounding behind down and
   slack up keep the float test on the safe side. */
static float node_behind(const LightSampler *ls, const int *items, int n, const Acc *a, const TreeNode *nd,
                         float *slack)
{
    const Scene *s = ls->scene;
    double h = INFINITY, wc = 0.0, w[3], v, t;
    float f;
    int i, j, k;
    *slack = 0.0f;
    if (a->twosided || a->cone.cos_o <= -1.0f) return -INFINITY;
    t = acos((double)a->cone.cos_o) + acos((double)a->cone.cos_e);
    if (!(t < SPECNEE_PI)) return -INFINITY;
    if (t > 0.5 * SPECNEE_PI) {
        double sd = sin(t - 0.5 * SPECNEE_PI);
        *slack = (float)sd;
        if ((double)*slack < sd) *slack = nextafterf(*slack, INFINITY);
    }
    for (k = 0; k < 3; k++) {
        w[k] = nd->axis[k];
        wc += w[k] * nd->c[k];
    }
    for (i = 0; i < n; i++) {
        const Piece *pc = &ls->pieces[items[i]];
        const Emitter *em = &s->emitters[pc->emitter];
        const Shape *sh;
        if (em->shape < 0) {                            /* a spot light: its one point */
            const Vec3 x = em->delta.p;
            double d = w[0] * x.x + w[1] * x.y + w[2] * x.z;
            if (d < h) h = d;                           /* (its only "vertex") */
            continue;
        }
        sh = &s->shapes[em->shape];
        if (sh->type != SHAPE_MESH) return -INFINITY;   /* (a sphere's cone is full anyway) */
        for (j = 0; j < piece_tri_count(pc, sh); j++) {
            const Triangle *tr = &s->tris[piece_triangle(ls, pc, sh, j)];
            for (k = 0; k < 3; k++) {
                const Vec3 x = s->P[tr->v[k]];
                double d = w[0] * x.x + w[1] * x.y + w[2] * x.z;
                if (d < h) h = d;
            }
        }
    }
    v = h - wc - ls->behind_margin;
    f = (float)v;
    if ((double)f > v) f = nextafterf(f, -INFINITY);
    return f;
}

/* Build the binary subtree over items[0..n) at `depth`; returns its node
   index.  Recursion depth <= 64 (section 4). */
static int tree_build(Builder *B, int *items, int n, int depth)
{
    LightSampler *ls = B->ls;
    int node = ls->n_nodes++, i, b, mid = -1;
    TreeNode *nd = &ls->nodes[node];
    Acc all;
    Vec3 cmin, cmax, cext;
    acc_init(&all);
    for (i = 0; i < n; i++) acc_add(&all, &B->pb[items[i]]);
    {
        Vec3 c = v3_mul(v3_add(all.bmin, all.bmax), 0.5f), half = v3_mul(v3_sub(all.bmax, all.bmin), 0.5f);
        nd->c[0] = c.x; nd->c[1] = c.y; nd->c[2] = c.z;
        nd->r = v3_len(half);
    }
    nd->axis[0] = all.cone.w.x; nd->axis[1] = all.cone.w.y; nd->axis[2] = all.cone.w.z;
    nd->cos_o = all.cone.cos_o;
    nd->sin_o = sqrtf(fmaxf(0.0f, 1.0f - nd->cos_o * nd->cos_o));
    nd->cos_e = all.cone.cos_e;
    nd->twosided = all.twosided;
    nd->behind = node_behind(ls, items, n, &all, nd, &nd->slack);
    if (n == 1) {
        Piece *pc = &ls->pieces[items[0]];
        double sum = 0.0;
        nd->second = -1 - items[0];
        /* power per bin: pi A (2 if two-sided) times the bin average of Le; the
           power Phi sums the bins of the sampled range only (b >= nb_uv) */
        for (b = 0; b < ls->nb; b++) {
            double avg = B->le_avg[(size_t)ls->ref[pc->emitter].le * ls->nb + b];
            float v = (float)(SPECNEE_PI * pc->area * (ls->scene->emitters[pc->emitter].twosided ? 2.0 : 1.0) * avg);
            ls->node_bin[(size_t)node * ls->nb + b] = v;
            if (b >= ls->nb_uv) sum += (double)v * SPD_BIN_NM;
        }
        nd->power = (float)sum;
        return node;
    }
    cmin = cmax = B->centroids[items[0]];
    for (i = 1; i < n; i++) {
        cmin = v3_min(cmin, B->centroids[items[i]]);
        cmax = v3_max(cmax, B->centroids[items[i]]);
    }
    cext = v3_sub(cmax, cmin);
    if (depth < 32 && (cext.x > 0.0f || cext.y > 0.0f || cext.z > 0.0f)) {
        /* binned surface-area-orientation heuristic */
        double best = INFINITY;
        int best_axis = -1, best_plane = -1, a;
        Vec3 ext = v3_sub(all.bmax, all.bmin);
        float emax = fmaxf(ext.x, fmaxf(ext.y, ext.z));
        for (a = 0; a < 3; a++) {
            Acc bins[LIGHT_TREE_BINS], left[LIGHT_TREE_BINS];
            float lo = v3_get(cmin, a), w = v3_get(cext, a), ea = v3_get(ext, a);
            double kr;
            Acc right;
            if (!(w > 0.0f)) continue;
            kr = ea > 0.0f ? (double)emax / ea : 1.0;
            for (b = 0; b < LIGHT_TREE_BINS; b++) acc_init(&bins[b]);
            for (i = 0; i < n; i++) {
                int k = (int)((v3_get(B->centroids[items[i]], a) - lo) / w * LIGHT_TREE_BINS);
                if (k < 0) k = 0;
                if (k >= LIGHT_TREE_BINS) k = LIGHT_TREE_BINS - 1;
                acc_add(&bins[k], &B->pb[items[i]]);
            }
            acc_init(&left[0]);
            acc_merge(&left[0], &bins[0]);
            for (b = 1; b < LIGHT_TREE_BINS; b++) { left[b] = left[b - 1]; acc_merge(&left[b], &bins[b]); }
            acc_init(&right);
            for (b = LIGHT_TREE_BINS - 1; b >= 1; b--) {
                double cost;
                acc_merge(&right, &bins[b]);
                /* plane between bin b - 1 and bin b */
                if (!left[b - 1].any || !right.any) continue;
                cost = kr * (acc_cost(&left[b - 1], &B->memo) + acc_cost(&right, &B->memo));
                if (cost < best) { best = cost; best_axis = a; best_plane = b; }
            }
        }
        if (best_axis >= 0) {
            /* partition in place: bin < best_plane first */
            float lo = v3_get(cmin, best_axis), w = v3_get(cext, best_axis);
            int l = 0, r = n - 1;
            while (l <= r) {
                int k = (int)((v3_get(B->centroids[items[l]], best_axis) - lo) / w * LIGHT_TREE_BINS);
                if (k < 0) k = 0;
                if (k >= LIGHT_TREE_BINS) k = LIGHT_TREE_BINS - 1;
                if (k < best_plane) l++;
                else { int t = items[l]; items[l] = items[r]; items[r] = t; r--; }
            }
            if (l > 0 && l < n) mid = l;
        }
    }
    if (mid < 0) {
        /* all centroids coincide, or deep: the middle of the list in centroid order */
        if (cext.x > 0.0f || cext.y > 0.0f || cext.z > 0.0f)
            sort_by_axis(items, n, B->centroids, longest_axis(cext), B->tmp);
        mid = n / 2;
    }
    tree_build(B, items, mid, depth + 1);
    nd = &ls->nodes[node];
    nd->second = tree_build(B, items + mid, n - mid, depth + 1);
    {
        const TreeNode *c0 = &ls->nodes[node + 1], *c1 = &ls->nodes[nd->second];
        size_t o = (size_t)node * ls->nb, o0 = (size_t)(node + 1) * ls->nb, o1 = (size_t)nd->second * ls->nb;
        for (b = 0; b < ls->nb; b++) ls->node_bin[o + b] = ls->node_bin[o0 + b] + ls->node_bin[o1 + b];
        nd->power = c0->power + c1->power;
    }
    return node;
}

/* Lane k of the 4-wide node q describes the binary node b. */
static void lane_from(TreeNode4 *q, int k, const TreeNode *b)
{
    q->cx[k] = b->c[0]; q->cy[k] = b->c[1]; q->cz[k] = b->c[2]; q->r[k] = b->r;
    q->ax[k] = b->axis[0]; q->ay[k] = b->axis[1]; q->az[k] = b->axis[2];
    q->cos_o[k] = b->cos_o;
    q->sin_o[k] = b->sin_o;
    q->cos_e[k] = b->cos_e;
    q->behind[k] = b->behind;
    q->slack[k] = b->slack;
    q->twosided[k] = b->twosided;
}

/* The lanes of the 4-wide node that stands for the binary interior node i: its
   two children, each replaced by its own two children where it has them
   (2 to 4 lanes).  Returns how many. */
static int grandchildren(const TreeNode *bn, int i, int g[4])
{
    int kids[2], s, m = 0;
    kids[0] = i + 1;
    kids[1] = bn[i].second;
    for (s = 0; s < 2; s++) {
        if (bn[kids[s]].second < 0) g[m++] = kids[s];
        else { g[m++] = kids[s] + 1; g[m++] = bn[kids[s]].second; }
    }
    return m;
}

/* A 4-wide node still to be filled: its lanes are the binary nodes
   slots[0..m), at 4-wide depth `depth`, reached along `trail`. */
typedef struct {
    int slots[4], m, depth;
    uint64_t trail;
} Pending;

/* Collapse the binary tree into the 4-wide one (section 4), breadth first
   (the upper levels, which every walk reads, lie together in memory).  The
   root's lanes are root[0..m).  Each piece gets its trail (digit d, bits 2d
   and 2d + 1: the lane taken at depth d) and its depth.  Every level takes
   two binary levels (or ends at a leaf), so depth <= 32 and 64 bits hold the
   trail.  queue: room for every node (ls->n_nodes4, counted by count4). */
static void tree_collapse(LightSampler *ls, const int *root, int m, Pending *queue)
{
    const TreeNode *bn = ls->nodes;
    int head = 0, tail = 1, k, b;
    memcpy(queue[0].slots, root, sizeof(int) * (size_t)m);
    queue[0].m = m;
    queue[0].depth = 0;
    queue[0].trail = 0;
    for (head = 0; head < tail; head++) {
        const Pending *pd = &queue[head];
        TreeNode4 *nd = &ls->nodes4[head];
        float *col = ls->quad_bin + (size_t)head * 4;   /* bin b: col[4 n_nodes4 b] */
        for (k = 0; k < pd->m; k++) {                /* lanes m..3 stay 0: no power */
            const TreeNode *c = &bn[pd->slots[k]];
            uint64_t t = pd->trail | ((uint64_t)k << (2 * pd->depth));
            lane_from(nd, k, c);
            ls->quad_power[(size_t)head * 4 + k] = c->power;
            for (b = 0; b < ls->nb; b++)
                col[(size_t)4 * ls->n_nodes4 * b + k] = ls->node_bin[(size_t)pd->slots[k] * ls->nb + b];
            if (c->second < 0) {
                Piece *pc = &ls->pieces[-1 - c->second];
                pc->trail = t;
                pc->depth = pd->depth + 1;
                nd->child[k] = c->second;
            } else {
                Pending *q = &queue[tail];
                q->m = grandchildren(bn, pd->slots[k], q->slots);
                q->depth = pd->depth + 1;
                q->trail = t;
                nd->child[k] = tail++;
            }
        }
    }
}

/* How many 4-wide nodes the collapse makes of the binary subtree whose
   grandchildren g[0..m) are a 4-wide node's lanes. */
static int count4(const TreeNode *bn, const int *g, int m)
{
    int k, n = 1;
    for (k = 0; k < m; k++)
        if (bn[g[k]].second >= 0) {
            int gg[4], mm = grandchildren(bn, g[k], gg);
            n += count4(bn, gg, mm);
        }
    return n;
}

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
        Piece *pc = &ls->pieces[ls->n_pieces];
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

/* The oriented geometric normal of triangle t, as scene_surface_point sees it. */
static Vec3 tri_normal(const Scene *s, int t)
{
    const Triangle *tr = &s->tris[t];
    Vec3 p0 = s->P[tr->v[0]], p1 = s->P[tr->v[1]], p2 = s->P[tr->v[2]];
    Vec3 n = v3_norm(v3_cross(v3_sub(p0, p2), v3_sub(p1, p2)));
    return s->shapes[tr->shape].flip ? v3_neg(n) : n;
}

/* Box, cone and power of a piece. */
static void piece_bounds(const LightSampler *ls, const Piece *pc, PieceBounds *out)
{
    const Scene *s = ls->scene;
    const Emitter *em = &s->emitters[pc->emitter];
    const Shape *sh = em->shape >= 0 ? &s->shapes[em->shape] : NULL;
    double sum = 0.0;
    int b;
    out->twosided = em->twosided;
    if (!sh) {
        /* a point or spot light (delta.c): a box that is one point; a point light
           emits every way (theta_o = pi, theta_e = pi/2, as pbrt-v4's bounds), a
           spot light within theta_o = its full-intensity cone and theta_e = the
           falloff band beyond it (every direction when its CTM stretches the
           cone out of round).  A band of less than a milliradian is widened
           to one: "I = 0 when theta' >= theta_e" must not cut off a point just
           inside the cone by round-off (pbrt-v4 keeps a similar slop) */
        const DeltaLight *d = &em->delta;
        out->bmin = out->bmax = d->p;
        if (d->type == DELTA_SPOT && !d->stretched) {
            double to = acos(fmax(-1.0, fmin(1.0, (double)d->cos_start)));
            double te = acos(fmax(-1.0, fmin(1.0, (double)d->cos_end))) - to;
            out->cone.w = d->w;
            out->cone.cos_o = d->cos_start;
            out->cone.cos_e = (float)cos(te > 1e-3 ? te : 1e-3);
        } else {
            out->cone = cone_full(0.0f);
        }
    } else if (sh->type == SHAPE_SPHERE) {
        Vec3 r = v3(sh->radius, sh->radius, sh->radius);
        out->bmin = v3_sub(sh->center, r);
        out->bmax = v3_add(sh->center, r);
        out->cone = cone_full(0.0f);
    } else if (shape_is_quadric(sh->type)) {
        float lo[3], hi[3];
        quadric_bounds(sh, lo, hi);
        out->bmin = v3(lo[0], lo[1], lo[2]);
        out->bmax = v3(hi[0], hi[1], hi[2]);
        if (sh->type == SHAPE_DISK) {              /* one normal: a cone of angle 0 */
            Vec3 p;
            quadric_sample(sh, 0.0f, 0.0f, &p, &out->cone.w);
            out->cone.cos_o = 1.0f;
            out->cone.cos_e = 0.0f;
        } else {
            out->cone = cone_full(0.0f);           /* cylinder, cut sphere: every way */
        }
    } else {
        int count = piece_tri_count(pc, sh), i, k;
        Vec3 nsum = v3(0, 0, 0);
        float cos_o = 1.0f;
        for (i = 0; i < count; i++) {
            int t = piece_triangle(ls, pc, sh, i);
            const Triangle *tr = &s->tris[t];
            for (k = 0; k < 3; k++) {
                Vec3 p = s->P[tr->v[k]];
                if (i == 0 && k == 0) out->bmin = out->bmax = p;
                out->bmin = v3_min(out->bmin, p);
                out->bmax = v3_max(out->bmax, p);
            }
            nsum = v3_add(nsum, v3_mul(tri_normal(s, t), (float)tri_area(s, t)));
        }
        if (sh->has_normals || !(v3_len(nsum) > 0.0f)) {
            out->cone = cone_full(0.0f);   /* shading normals may flip a point's side */
        } else {
            out->cone.w = v3_norm(nsum);
            for (i = 0; i < count; i++) {
                int t = piece_triangle(ls, pc, sh, i);
                if (tri_area(s, t) > 0.0) cos_o = fminf(cos_o, v3_dot(out->cone.w, tri_normal(s, t)));
            }
            out->cone.cos_o = fmaxf(-1.0f, fminf(1.0f, cos_o));
            out->cone.cos_e = 0.0f;
        }
    }
    out->centroid = v3_mul(v3_add(out->bmin, out->bmax), 0.5f);
    for (b = 0; b < SPD_BINS; b++) sum += ls->bin[(size_t)pc->emitter * SPD_BINS + b];
    out->power = SPECNEE_PI * pc->area * (em->twosided ? 2.0 : 1.0) * sum;
}

/* The context as the tree reads it: point, normal, and the bins that count. */
typedef struct {
    Vec3 p, n;
    int has_n;
    int spectral, nbins;
    int bin[HERO_N];
    float c[HERO_N];
} TreeQuery;

static void tree_query(const LightSampler *ls, const LightCtx *c, TreeQuery *q)
{
    int j;
    q->p = c->p;
    q->n = c->n;
    q->has_n = v3_dot(c->n, c->n) > 0.0f;
    q->spectral = ls->opt.strategy == SEL_SPECTRAL_TREE;
    q->nbins = 0;
    if (!q->spectral) return;
    for (j = 0; j < HERO_N; j++) {
        float cj = ls->opt.throughput_weighted ? c->beta[j] : 1.0f;
        float x = (c->lambda[j] - ls->opt.lo_nm) / SPD_BIN_NM;
        int b;
        if (!(c->alive & (1u << j)) || !(cj > 0.0f)) continue;
        if (x >= 0.0f) {
            b = ls->nb_uv + (int)x;                  /* the sampled range */
        } else {                                     /* below it: a UV bin, from 300 nm */
            float xu = (c->lambda[j] - (ls->opt.lo_nm - SPD_BIN_NM * ls->nb_uv)) / SPD_BIN_NM;
            b = xu >= 0.0f ? (int)xu : 0;            /* also catches NaN */
            if (b >= ls->nb_uv) b = ls->nb_uv - 1;
        }
        if (b >= ls->nb) b = ls->nb - 1;
        q->bin[q->nbins] = b;
        q->c[q->nbins] = cj;
        q->nbins++;
    }
}

/* max(x, 0) without libm's fmaxf (a call per use in this, the hottest loop of the
   tree; a NaN gives 0 as fmaxf(0, NaN) does). */
static float pos_or_zero(float x) { return x > 0.0f ? x : 0.0f; }

/* The power that counts at the query (section 4): sum over the query's bins of
   c_j times the power in bin b_j, read from bins[stride * b_j]. */
static float query_power(const TreeQuery *q, const float *bins, int stride)
{
    float phi = 0.0f;
    int k;
    for (k = 0; k < q->nbins; k++) phi += q->c[k] * bins[stride * q->bin[k]];
    return phi;
}

/* Inside a node's bounding sphere the walk divides by |d|^2, but by no less
   than (r/4)^2 = TREE_INSIDE r^2 (section 4; 1/4 measured: 1/2 to 1/10 gave
   the same MSE within 0.5% on the hall and many-lamps, docs/lighttree.md). */
#define TREE_INSIDE 0.0625f

/* The importance of the child in lane k of node nd, whose power in the
   context is phi, at the query (section 4): the one function that both
   tree_select and tree_pmf call (through node_importance4, which computes
   four lanes at once exactly as this does one).  The walk waits for it at
   every level, and a core has one unit for square roots and divisions, so it
   is written with as few of them as the bound allows: with d = p - centre (not
   normalised) and
       S_b = sqrt(|d|^2 - r^2) = |d| cos theta_b,   r = |d| sin theta_b,
       dw = d . w (|d . w| when two-sided) = |d| cos theta_w,
       S_w = sqrt(|d|^2 - dw^2) = |d| sin theta_w,
       dn = |d . n| = |d| cos theta_i,   S_i = sqrt(|d|^2 - dn^2) = |d| sin theta_i,
   every cosine of section 4 is a ratio with |d| or |d|^2 below:
       theta_w <= theta_o  <=>  dw |dw| >= cos_o |cos_o| |d|^2   (x |x| increases),
       X = |d|^2 cos theta' = |d|^2, or (dw cos_o + S_w sin_o) S_b + (S_w cos_o - dw sin_o) r,
       Y = |d|^2 cos theta_i' = |d|^2, or dn S_b + S_i r,
   and I = Phi_c (1 / |d|^2) (X / |d|^2) (Y / |d|^2): three square roots and
   one division (by |d|^2, at least FLT_MIN).  Inside the bounding sphere
   I = Phi_c / max(|d|^2, TREE_INSIDE r^2), no angle.  The product is taken in
   double, where it can neither overflow nor round a positive importance to 0. */
static double lane_importance(const TreeNode4 *nd, int k, const TreeQuery *q, float phi)
{
    float dx, dy, dz, d2, r, r2, Sb, dw, X, Y, inv;
    double I;
    if (!(phi > 0.0f)) return 0.0;                   /* also an empty lane */
    dx = q->p.x - nd->cx[k];
    dy = q->p.y - nd->cy[k];
    dz = q->p.z - nd->cz[k];
    d2 = dx * dx + dy * dy + dz * dz;
    r = nd->r[k];
    r2 = r * r;
    dw = dx * nd->ax[k] + dy * nd->ay[k] + dz * nd->az[k];
    Sb = d2 > r2 ? sqrtf(d2 - r2) : 0.0f;
    if (dw <= nd->behind[k] - nd->slack[k] * (Sb + 2.0f * r))
        return 0.0;                                  /* p behind the box: I = 0 (node_behind) */
    if (!(d2 > r2)) { /* p inside the bounding sphere: no angle can be bounded; */
        float den = d2 > TREE_INSIDE * r2 ? d2 : TREE_INSIDE * r2;   /* I = Phi_c / max(|d|, r/4)^2 */
        return (double)phi * (double)(1.0f / (den > FLT_MIN ? den : FLT_MIN));
    }
    if (!(d2 <= FLT_MAX)) return 0.0;                /* p at infinity: I = 0 */
    if (nd->twosided[k]) dw = fabsf(dw);
    if (dw * fabsf(dw) >= nd->cos_o[k] * fabsf(nd->cos_o[k]) * d2) {
        X = d2;                                      /* p inside the normal cone */
    } else {
        /* theta_w - theta_o > 0, then minus theta_b, clamped at 0 */
        float Sw = sqrtf(pos_or_zero(d2 - dw * dw));
        float A = dw * nd->cos_o[k] + Sw * nd->sin_o[k];   /* |d| cos(theta_w - theta_o) */
        float B = Sw * nd->cos_o[k] - dw * nd->sin_o[k];   /* |d| sin(theta_w - theta_o) */
        X = A >= Sb ? d2 : A * Sb + B * r;
        if (X <= nd->cos_e[k] * d2) return 0.0;      /* theta' >= theta_e: I = 0 */
    }
    Y = d2;
    if (q->has_n) {
        float dn = fabsf(q->n.x * dx + q->n.y * dy + q->n.z * dz);
        if (dn < Sb) Y = dn * Sb + sqrtf(pos_or_zero(d2 - dn * dn)) * r;
    }
    inv = 1.0f / (d2 > FLT_MIN ? d2 : FLT_MIN);
    I = (double)phi * (double)inv * (double)(X * inv) * (double)(Y * inv);
    return I >= 0.0 ? I : 0.0;                       /* NaN: 0 */
}

/* The importances I[0..4) of the four lanes of nd, with powers phi[0..4):
   lane_importance four times.  With SSE2 the four are computed side by side,
   step for step the same operations in the same order (both sides of every
   test computed, the right one kept by a mask), so the results are the same
   to the bit; the test lighttree_simd_matches_scalar compares them. */
static void node_importance4(const TreeNode4 *nd, const TreeQuery *q, const float phi[4], double I[4])
{
#if TREE_SIMD
    const __m128 zero = _mm_setzero_ps();
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128d zero_d = _mm_setzero_pd();
    __m128 vphi = _mm_loadu_ps(phi);
    __m128 dx = _mm_sub_ps(_mm_set1_ps(q->p.x), _mm_loadu_ps(nd->cx));
    __m128 dy = _mm_sub_ps(_mm_set1_ps(q->p.y), _mm_loadu_ps(nd->cy));
    __m128 dz = _mm_sub_ps(_mm_set1_ps(q->p.z), _mm_loadu_ps(nd->cz));
    __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    __m128 r = _mm_loadu_ps(nd->r), r2 = _mm_mul_ps(r, r);
    __m128 cos_o = _mm_loadu_ps(nd->cos_o), sin_o = _mm_loadu_ps(nd->sin_o);
    /* one-sided lanes keep dw's sign: their mask is all ones */
    __m128 one_sided = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_loadu_si128((const __m128i *)nd->twosided),
                                                        _mm_setzero_si128()));
    __m128 dw = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, _mm_loadu_ps(nd->ax)), _mm_mul_ps(dy, _mm_loadu_ps(nd->ay))),
                           _mm_mul_ps(dz, _mm_loadu_ps(nd->az)));
    __m128 Sb, in_cone, X, Y, dead, inside, ok, inv, cX, cY;
    __m128d p_lo, p_hi, I_lo, I_hi, m_lo, m_hi;
    __m128 behind;
    inside = _mm_cmpngt_ps(d2, r2);
    Sb = _mm_sqrt_ps(_mm_sub_ps(d2, r2));
    /* p behind the box: I = 0, inside the bounding sphere too (L: Sb, 0 inside, + 2 r) */
    behind = _mm_cmple_ps(dw, _mm_sub_ps(_mm_loadu_ps(nd->behind),
                                         _mm_mul_ps(_mm_loadu_ps(nd->slack),
                                                    _mm_add_ps(_mm_andnot_ps(inside, Sb), _mm_add_ps(r, r)))));
    dw = _mm_and_ps(dw, _mm_or_ps(one_sided, abs_mask));
    in_cone = _mm_cmpge_ps(_mm_mul_ps(dw, _mm_and_ps(dw, abs_mask)),
                           _mm_mul_ps(_mm_mul_ps(cos_o, _mm_and_ps(cos_o, abs_mask)), d2));
    /* I = 0 where p is at infinity, or (below) where theta' >= theta_e */
    dead = _mm_cmpnle_ps(d2, _mm_set1_ps(FLT_MAX));
    X = d2;
    if (_mm_movemask_ps(in_cone) != 15) {            /* some lane outside its normal cone */
        __m128 Sw = _mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(d2, _mm_mul_ps(dw, dw)), zero));   /* max: NaN gives 0 */
        __m128 A = _mm_add_ps(_mm_mul_ps(dw, cos_o), _mm_mul_ps(Sw, sin_o));
        __m128 B = _mm_sub_ps(_mm_mul_ps(Sw, cos_o), _mm_mul_ps(dw, sin_o));
        __m128 Xc = _mm_add_ps(_mm_mul_ps(A, Sb), _mm_mul_ps(B, r));
        __m128 a_ge = _mm_cmpge_ps(A, Sb);
        Xc = _mm_or_ps(_mm_and_ps(a_ge, d2), _mm_andnot_ps(a_ge, Xc));
        X = _mm_or_ps(_mm_and_ps(in_cone, d2), _mm_andnot_ps(in_cone, Xc));
        dead = _mm_or_ps(dead, _mm_andnot_ps(in_cone, _mm_cmple_ps(Xc, _mm_mul_ps(_mm_loadu_ps(nd->cos_e), d2))));
    }
    Y = d2;
    if (q->has_n) {
        __m128 dn = _mm_and_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(q->n.x), dx),
                                                     _mm_mul_ps(_mm_set1_ps(q->n.y), dy)),
                                          _mm_mul_ps(_mm_set1_ps(q->n.z), dz)), abs_mask);
        __m128 Yc = _mm_add_ps(_mm_mul_ps(dn, Sb),
                               _mm_mul_ps(_mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(d2, _mm_mul_ps(dn, dn)), zero)), r));
        __m128 lt = _mm_cmplt_ps(dn, Sb);
        Y = _mm_or_ps(_mm_and_ps(lt, Yc), _mm_andnot_ps(lt, d2));
    }
    ok = _mm_andnot_ps(_mm_or_ps(_mm_andnot_ps(inside, dead), behind), _mm_cmpgt_ps(vphi, zero));
    {   /* one division: by max(|d|^2, r^2 / 16) inside the sphere, else by |d|^2,
           at least FLT_MIN */
        /* maxps is (d2 > rin ? d2 : rin), NaN included: the scalar test exactly */
        __m128 inner = _mm_max_ps(d2, _mm_mul_ps(_mm_set1_ps(TREE_INSIDE), r2));
        __m128 den = _mm_or_ps(_mm_and_ps(inside, inner), _mm_andnot_ps(inside, d2));
        __m128 flt_min = _mm_set1_ps(FLT_MIN), gt = _mm_cmpgt_ps(den, flt_min);
        inv = _mm_div_ps(_mm_set1_ps(1.0f), _mm_or_ps(_mm_and_ps(gt, den), _mm_andnot_ps(gt, flt_min)));
    }
    cX = _mm_mul_ps(X, inv);
    cY = _mm_mul_ps(Y, inv);
    /* the product in double, two lanes per register: Phi_c inv, times cX cY
       outside the sphere */
#define TREE_LO(v) _mm_cvtps_pd(v)
#define TREE_HI(v) _mm_cvtps_pd(_mm_movehl_ps(v, v))
    p_lo = _mm_mul_pd(TREE_LO(vphi), TREE_LO(inv));
    p_hi = _mm_mul_pd(TREE_HI(vphi), TREE_HI(inv));
    I_lo = _mm_mul_pd(_mm_mul_pd(p_lo, TREE_LO(cX)), TREE_LO(cY));
    I_hi = _mm_mul_pd(_mm_mul_pd(p_hi, TREE_HI(cX)), TREE_HI(cY));
#undef TREE_LO
#undef TREE_HI
    /* the lane masks widened to two doubles each */
    m_lo = _mm_castps_pd(_mm_unpacklo_ps(inside, inside));
    m_hi = _mm_castps_pd(_mm_unpackhi_ps(inside, inside));
    I_lo = _mm_or_pd(_mm_and_pd(m_lo, p_lo), _mm_andnot_pd(m_lo, I_lo));
    I_hi = _mm_or_pd(_mm_and_pd(m_hi, p_hi), _mm_andnot_pd(m_hi, I_hi));
    I_lo = _mm_and_pd(I_lo, _mm_cmpge_pd(I_lo, zero_d));   /* NaN: 0 */
    I_hi = _mm_and_pd(I_hi, _mm_cmpge_pd(I_hi, zero_d));
    m_lo = _mm_castps_pd(_mm_unpacklo_ps(ok, ok));
    m_hi = _mm_castps_pd(_mm_unpackhi_ps(ok, ok));
    _mm_storeu_pd(I, _mm_and_pd(m_lo, I_lo));
    _mm_storeu_pd(I + 2, _mm_and_pd(m_hi, I_hi));
#else
    int k;
    for (k = 0; k < 4; k++) I[k] = lane_importance(nd, k, q, phi[k]);
#endif
}

/* The four children's powers in the context: their total power (tree), or
   query_power over their bins in quad_bin (spectral-tree). */
static void child_powers(const LightSampler *ls, const TreeQuery *q, int i, float phi[4])
{
    const float *col = ls->quad_bin + (size_t)i * 4;   /* bin b: col[stride b] */
    int k, stride = 4 * ls->n_nodes4;
    if (!q->spectral) { memcpy(phi, ls->quad_power + (size_t)i * 4, 4 * sizeof(float)); return; }
#if TREE_SIMD
    {   /* query_power of the four lanes side by side: the same sums, in the same order */
        __m128 acc = _mm_setzero_ps();
        for (k = 0; k < q->nbins; k++)
            acc = _mm_add_ps(acc, _mm_mul_ps(_mm_set1_ps(q->c[k]), _mm_loadu_ps(col + (size_t)stride * q->bin[k])));
        _mm_storeu_ps(phi, acc);
    }
#else
    for (k = 0; k < 4; k++) phi[k] = query_power(q, col + k, stride);
#endif
}

/* The branch at node i: the children's importances I[0..4) and their sum *S
   (in lane order, as the walk accumulates them); 0 when nothing below can
   light the point (or round-off overflowed). */
static void branch_at(const LightSampler *ls, const TreeQuery *q, int i, double I[4], double *S)
{
    float phi[4];
    child_powers(ls, q, i, phi);
    node_importance4(&ls->nodes4[i], q, phi, I);
    *S = ((I[0] + I[1]) + I[2]) + I[3];
    if (!(*S > 0.0 && *S <= DBL_MAX)) *S = 0.0;
}

/* Does the tree get a share beside the infinite lights?  Only when it has pieces
   and its root can light the point (else every share goes to the infinite
   lights).  A function of the context alone, so select and pmf agree. */
static int tree_live(const LightSampler *ls, const TreeQuery *q)
{
    return ls->n_tree_pieces > 0 &&
           lane_importance(&ls->top, 0, q, q->spectral ? query_power(q, ls->root_bin, 1)
                                                        : ls->top_power) > 0.0;
}

static int tree_select(const LightSampler *ls, const LightCtx *c, float u, float *pmf)
{
    TreeQuery q;
    double uu = u, lo = 0.0, p = 1.0, w = 1.0;
    int i = 0;
    tree_query(ls, c, &q);
    if (ls->n_inf > 0) {
        /* one share for each infinite light, one for the tree (section 4) */
        int k = ls->n_inf + tree_live(ls, &q), slot;
        uu = (double)u * k;
        slot = (int)uu;
        if (slot >= k) slot = k - 1;
        p = 1.0 / k;
        if (slot < ls->n_inf) { *pmf = (float)p; return ls->inf_piece[slot]; }
        uu -= slot;
        if (!(uu < 1.0)) uu = 1.0 - DBL_EPSILON;
    }
    /* [lo, lo + w) is the part of [0, 1) that leads to node i (w = p / the
       tree's share); child k gets the piece of it from lo + w C_(k-1) / S to
       lo + w C_k / S, with C_k = I_0 + ... + I_k.  The test is uu - lo <
       w C_k / S times S, so that the walk need not wait for the division
       before it goes on; a child that cannot light p (I_k = 0) is never taken,
       whatever the round-off (at the top, the last child with I_k > 0). */
    for (;;) {
        double I[4], S, x, cum = 0.0, prev = 0.0, pa, invS;
        int k, pick = -1, child;
        branch_at(ls, &q, i, I, &S);
        if (!(S > 0.0)) { *pmf = 0.0f; return -1; }
        x = (uu - lo) * S;
        for (k = 0; k < 4; k++) {
            if (!(I[k] > 0.0)) continue;
            prev = cum;
            cum += I[k];
            pick = k;
            if (x < w * cum) break;
        }
        invS = 1.0 / S;
        pa = I[pick] * invS;
        p *= pa;
        lo += w * (prev * invS);
        w *= pa;
        child = ls->nodes4[i].child[pick];
        if (child < 0) { *pmf = (float)p; return -1 - child; }
        i = child;
    }
}

static float tree_pmf(const LightSampler *ls, const LightCtx *c, int piece)
{
    const Piece *pc = &ls->pieces[piece];
    TreeQuery q;
    double p = 1.0;
    int i = 0, d;
    tree_query(ls, c, &q);
    if (ls->n_inf > 0) {
        int live = tree_live(ls, &q);
        p = 1.0 / (ls->n_inf + live);
        if (beside_tree(&ls->scene->emitters[pc->emitter])) return (float)p;
        if (!live) return 0.0f;
    }
    for (d = 0; d < pc->depth; d++) {
        double I[4], S;
        int k = (int)((pc->trail >> (2 * d)) & 3u), child;
        branch_at(ls, &q, i, I, &S);
        if (!(S > 0.0) || !(I[k] > 0.0)) return 0.0f;
        p *= I[k] * (1.0 / S);
        child = ls->nodes4[i].child[k];
        if (child < 0) return d == pc->depth - 1 && child == -1 - piece ? (float)p : 0.0f;
        i = child;
    }
    return 0.0f;                                     /* a trail shorter than the tree */
}

/* For the test lighttree_simd_matches_scalar: at context c, every child of
   every node evaluated both ways, power and importance compared bit for bit. */
int light_tree_simd_mismatches(const LightSampler *ls, const LightCtx *c, int *lanes)
{
    TreeQuery q;
    int i, k, bad = 0;
    *lanes = 0;
    if (!is_tree(ls->opt.strategy) || ls->n_tree_pieces == 0) return 0;
    tree_query(ls, c, &q);
    for (i = 0; i < ls->n_nodes4; i++) {
        float phi[4];
        double I[4], S;
        child_powers(ls, &q, i, phi);
        branch_at(ls, &q, i, I, &S);                 /* what the walk computes */
        for (k = 0; k < 4; k++) {
            float ps = q.spectral ? query_power(&q, ls->quad_bin + (size_t)i * 4 + k, 4 * ls->n_nodes4)
                                  : ls->quad_power[(size_t)i * 4 + k];
            double Is = lane_importance(&ls->nodes4[i], k, &q, ps);
            bad += memcmp(&ps, &phi[k], sizeof ps) != 0 || memcmp(&Is, &I[k], sizeof Is) != 0;
            (*lanes)++;
        }
    }
    return bad;
}

/* Pieces and the tree (called by light_sampler_build for the tree strategies). */
static int tree_setup(LightSampler *ls)
{
    const Scene *s = ls->scene;
    int e, i, n_split_tris = 0, next_tri = 0, max_tris = 1, ok = 0;
    int *items = NULL, *tris = NULL;
    Vec3 *tri_c = NULL;
    PieceBounds *pb = NULL;
    KeyIdx *tmp = NULL;
    Builder B;
    size_t cap = (size_t)ls->n;
    for (e = 0; e < ls->n; e++) {
        const Shape *sh;
        if (beside_tree(&s->emitters[e])) { ls->n_inf++; continue; }
        if (s->emitters[e].shape < 0) continue;       /* a point or spot light: one piece */
        sh = &s->shapes[s->emitters[e].shape];
        if (!ls->opt.no_split && sh->type == SHAPE_MESH && sh->tri_count > LIGHT_CLUSTER_TRIS) {
            n_split_tris += sh->tri_count;
            cap += (size_t)(sh->tri_count + LIGHT_CLUSTER_TRIS - 1) / LIGHT_CLUSTER_TRIS * 2;
            if (sh->tri_count > max_tris) max_tris = sh->tri_count;
        }
    }
    ls->pieces = (Piece *)calloc(cap, sizeof *ls->pieces);
    ls->emitter_piece = (int *)malloc(sizeof(int) * (size_t)ls->n);
    ls->inf_piece = (int *)malloc(sizeof(int) * (size_t)(ls->n_inf + 1));
    if (!ls->pieces || !ls->emitter_piece || !ls->inf_piece) goto done;
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
    ls->n_inf = 0;
    for (e = 0; e < ls->n; e++) {
        const Shape *sh;
        if (beside_tree(&s->emitters[e])) {          /* beside the tree (section 4) */
            Piece *pc = &ls->pieces[ls->n_pieces];
            pc->emitter = e;
            pc->area = s->emitters[e].area;
            ls->inf_piece[ls->n_inf++] = ls->n_pieces;
            ls->emitter_piece[e] = ls->n_pieces++;
            continue;
        }
        sh = s->emitters[e].shape >= 0 ? &s->shapes[s->emitters[e].shape] : NULL;
        if (sh && ls->piece_of_tri && !ls->opt.no_split && sh->type == SHAPE_MESH &&
            sh->tri_count > LIGHT_CLUSTER_TRIS) {
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
    /* the tree over the pieces that have a position (all but the infinite lights) */
    free(tmp);
    tmp = NULL;
    ls->n_tree_pieces = ls->n_pieces - ls->n_inf;
    {   /* offset_ray_origin's policy at the scene's largest |coordinate| */
        float m = fmaxf(fmaxf(fabsf(s->bmin.x), fabsf(s->bmax.x)),
                        fmaxf(fmaxf(fabsf(s->bmin.y), fabsf(s->bmax.y)), fmaxf(fabsf(s->bmin.z), fabsf(s->bmax.z))));
        ls->behind_margin = offset_eps(m);
    }
    ls->nb_uv = (int)((ls->opt.lo_nm - (float)SPEC_UV_MIN) / SPD_BIN_NM);
    if (ls->nb_uv < 0) ls->nb_uv = 0;
    ls->nb = ls->nb_uv + (int)((ls->opt.hi_nm - ls->opt.lo_nm) / SPD_BIN_NM + 0.5f);
    if (ls->n_tree_pieces == 0) { ok = 1; goto done; }
    pb = (PieceBounds *)malloc(sizeof *pb * (size_t)ls->n_pieces);
    items = (int *)malloc(sizeof(int) * (size_t)ls->n_pieces);
    tmp = (KeyIdx *)malloc(sizeof(KeyIdx) * (size_t)ls->n_pieces);
    B.centroids = (Vec3 *)malloc(sizeof(Vec3) * (size_t)ls->n_pieces);
    ls->nodes = (TreeNode *)calloc((size_t)(2 * ls->n_tree_pieces - 1), sizeof *ls->nodes);
    ls->node_bin = (float *)malloc(sizeof(float) * (size_t)(2 * ls->n_tree_pieces - 1) * (size_t)ls->nb);
    if (!pb || !items || !tmp || !B.centroids || !ls->nodes || !ls->node_bin) { free(B.centroids); goto done; }
    for (i = 0, e = 0; i < ls->n_pieces; i++) {
        if (beside_tree(&ls->scene->emitters[ls->pieces[i].emitter])) continue;
        piece_bounds(ls, &ls->pieces[i], &pb[i]);
        B.centroids[i] = pb[i].centroid;
        items[e++] = i;
    }
    B.ls = ls;
    B.pb = pb;
    B.tmp = tmp;
    B.memo.valid = 0;
    B.le_avg = (double *)malloc(sizeof(double) * (size_t)ls->n_le * (size_t)ls->nb);
    if (!B.le_avg) { free(B.centroids); goto done; }
    for (i = 0; i < ls->n_le; i++) {
        int b;
        for (b = 0; b < ls->nb; b++)               /* the 5 nm bin's mean of Le, in double */
            B.le_avg[(size_t)i * ls->nb + b] =
                spec_band_mean(&ls->Le[i], (int)ls->opt.lo_nm + (int)SPD_BIN_NM * (b - ls->nb_uv), (int)SPD_BIN_NM);
    }
    ls->n_nodes = 0;
    tree_build(&B, items, ls->n_tree_pieces, 0);
    free(B.centroids);
    free(B.le_avg);
    /* collapse it into the 4-wide tree that the walk reads: count its nodes,
       then fill them breadth first */
    {
        int slots[4], m;
        Pending *queue;
        if (ls->nodes[0].second < 0) { slots[0] = 0; m = 1; }
        else m = grandchildren(ls->nodes, 0, slots);
        ls->n_nodes4 = count4(ls->nodes, slots, m);
        queue = (Pending *)malloc(sizeof *queue * (size_t)ls->n_nodes4);
        /* the nodes in 64-byte aligned memory (the root in its first cache lines) */
        ls->nodes4_mem = calloc(1, sizeof(TreeNode4) * (size_t)ls->n_nodes4 + 63);
        ls->quad_power = (float *)calloc((size_t)ls->n_nodes4 * 4, sizeof(float));
        ls->quad_bin = (float *)calloc((size_t)ls->n_nodes4 * 4 * (size_t)ls->nb, sizeof(float));
        ls->root_bin = (float *)malloc(sizeof(float) * (size_t)ls->nb);
        if (!queue || !ls->nodes4_mem || !ls->quad_power || !ls->quad_bin || !ls->root_bin) {
            free(queue);
            goto done;
        }
        ls->nodes4 = (TreeNode4 *)((char *)ls->nodes4_mem + (64 - (size_t)((uintptr_t)ls->nodes4_mem % 64)) % 64);
        memcpy(ls->root_bin, ls->node_bin, sizeof(float) * (size_t)ls->nb);
        lane_from(&ls->top, 0, &ls->nodes[0]);
        ls->top_power = ls->nodes[0].power;
        tree_collapse(ls, slots, m, queue);
        free(queue);
    }
    free(ls->nodes);
    ls->nodes = NULL;
    free(ls->node_bin);
    ls->node_bin = NULL;
    ok = 1;
done:
    free(items); free(tris); free(tri_c); free(pb); free(tmp);
    return ok;
}

/* ------------------------------------------------------------------ build */

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
    ls->Le = (Spectrum *)malloc(sizeof(Spectrum) * (size_t)n);
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
    /* the emitters' radiance for this render's range, bin table and power */
    for (i = 0; i < n; i++) {
        const Emitter *em = &s->emitters[i];
        double bsum = 0.0;
        int same = -1;
        ls->ref[i].twosided = em->twosided;
        ls->ref[i].inf = em->inf != NULL;
        ls->ref[i].delta = em->delta.type != DELTA_NONE;
        /* the same radiance as an earlier area light (same L, scale, kind)?  The
           previous emitter is checked first, then a few before it: lamps of one
           kind are usually declared together (O(n), never O(n^2)) */
        if (!em->inf) {
            int j, tries = 0;
            for (j = i - 1; j >= 0 && tries < 8; j--, tries++) {
                const Emitter *ej = &s->emitters[j];
                if (!ej->inf && ej->scale == em->scale && ej->absolute == em->absolute &&
                    memcmp(&ej->L, &em->L, sizeof em->L) == 0) { same = j; break; }
            }
        }
        if (same >= 0) {
            /* radiance_and_k is a function of (L, scale, absolute) alone */
            ls->ref[i].le = ls->ref[same].le;
            ls->k[i] = ls->k[same];
            memcpy(ls->bin + (size_t)i * SPD_BINS, ls->bin + (size_t)same * SPD_BINS, sizeof(float) * SPD_BINS);
        } else {
            ls->ref[i].le = ls->n_le++;
            if (!radiance_and_k(s, i, ls->opt.lo_nm, ls->opt.hi_nm, &ls->Le[ls->ref[i].le], &ls->k[i], err)) {
                light_sampler_free(ls);
                return NULL;
            }
            for (b = 0; b < SPD_BINS; b++)
                ls->bin[(size_t)i * SPD_BINS + b] = spec_bin_average(&ls->Le[ls->ref[i].le], b);
        }
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
    if (ls->T) {
        /* the UV band averages once per distinct radiance, not per emitter */
        float *uv = (float *)malloc(sizeof(float) * (size_t)ls->n_le * SPD_UV_BINS);
        if (!uv) goto oom;
        for (i = 0; i < ls->n_le; i++)
            for (b = 0; b < SPD_UV_BINS; b++)
                uv[(size_t)i * SPD_UV_BINS + b] = spec_band_average(&ls->Le[i], SPEC_UV_MIN + (int)SPD_BIN_NM * b,
                                                                    (int)SPD_BIN_NM);
        for (i = 0; i < n; i++) {
            const Emitter *em = &s->emitters[i];
            /* Y: luminance over the range, = scale for area lights (pbrt-v4's
               normalisation); an image map's stand-in spectrum has its own */
            ls->Y[i] = em->inf ? (float)luminance_sum(&ls->Le[ls->ref[i].le], ls->opt.lo_nm, ls->opt.hi_nm)
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
    }
    if (is_tree(o->strategy)) {
        if (!tree_setup(ls)) goto oom;
    } else {
        /* one piece per emitter */
        ls->n_pieces = n;
        ls->pieces = (Piece *)calloc((size_t)n, sizeof *ls->pieces);
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
    return ls;
oom:
    light_sampler_free(ls);
    error_set(err, NULL, 0, "out of memory building the light sampler");
    return NULL;
}

void light_sampler_free(LightSampler *ls)
{
    long v;
    if (!ls) return;
    if (ls->voxel)
        for (v = 0; v < ls->n_voxels; v++)
            if (ls->voxel[v] != VOXEL_FAILED) free(ls->voxel[v]);
    free(ls->voxel);
    free(ls->Le); free(ls->ref); free(ls->k); free(ls->bin); free(ls->inf_piece); free(ls->power);
    free(ls->power_pmf); free(ls->power_cdf);
    free(ls->T);
    free(ls->Y);
    free(ls->pieces); free(ls->emitter_piece);
    free(ls->piece_tri); free(ls->piece_cdf); free(ls->piece_of_tri);
    free(ls->nodes); free(ls->node_bin); free(ls->nodes4_mem); free(ls->quad_power); free(ls->quad_bin); free(ls->root_bin);
    free(ls);
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
    bytes += sizeof(Piece) * (size_t)ls->n_pieces;
    if (ls->piece_of_tri) bytes += sizeof(int) * (size_t)ls->scene->n_tris;
    if (ls->piece_tri) {
        size_t k = 0;
        int i;
        for (i = 0; i < ls->n_pieces; i++) k += (size_t)ls->pieces[i].count;
        bytes += k * (sizeof(int) + sizeof(float));
    }
    bytes += (size_t)ls->n_nodes4 * (sizeof(TreeNode4) + 4 * sizeof(float) * (size_t)(ls->nb + 1));
    if (ls->root_bin) bytes += sizeof(float) * (size_t)ls->nb;
    if (ls->voxel) {
        bytes += sizeof(float *) * (size_t)ls->n_voxels;
        for (v = 0; v < ls->n_voxels; v++)
            if (ls->voxel[v] && ls->voxel[v] != VOXEL_FAILED)
                bytes += sizeof(float) * 2 * n;
    }
    return bytes;
}

/* ------------------------------------------------------------------ pieces */

float light_Le(const LightSampler *ls, int e, Vec3 n, Vec3 w, float lambda_nm)
{
    const EmitterRef *r = &ls->ref[e];
    if (r->inf)                                                    /* along w */
        return inf_Le(&ls->scene->emitters[e], &ls->Le[r->le], ls->k[e], v3_neg(w), lambda_nm);
    if (r->delta) return spec_eval(&ls->Le[r->le], lambda_nm);    /* I or L: G is in pdf_sa */
    if (!r->twosided && v3_dot(n, w) <= 0.0f) return 0.0f;
    return spec_eval(&ls->Le[r->le], lambda_nm);
}

const Spectrum *light_spectrum(const LightSampler *ls, int e) { return &ls->Le[ls->ref[e].le]; }
int light_n_pieces(const LightSampler *ls) { return ls->n_pieces; }
int light_piece_emitter(const LightSampler *ls, int piece) { return ls->pieces[piece].emitter; }

int light_piece_of(const LightSampler *ls, int e, int prim)
{
    if (ls->piece_of_tri && prim >= 0 && prim < ls->scene->n_tris && ls->piece_of_tri[prim] >= 0)
        return ls->piece_of_tri[prim];
    return ls->emitter_piece[e];
}

int light_sample(const LightSampler *ls, int piece, Vec3 ref, float u0, float u1, float u2,
                 EmitterSample *out)
{
    const Piece *pc = &ls->pieces[piece];
    int lo = 0, hi;
    out->delta = 0;
    if (pc->count == 0) {                        /* a whole emitter */
        if (pc->tri_cdf)
            return sample_mesh(ls->scene, pc->tri_cdf, pc->tri_begin, pc->tri_count, pc->area, ref, u0, u1, u2, out);
        return emitter_sample(ls->scene, pc->emitter, ref, u0, u1, u2, out);
    }
    /* a cluster: a triangle by area (first cdf entry above u0), then a point */
    hi = pc->count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (ls->piece_cdf[pc->first + mid] <= u0) lo = mid + 1; else hi = mid;
    }
    point_on_triangle(ls->scene, ls->piece_tri[pc->first + lo], ref, u1, u2, out);
    return finish_sample(ref, pc->area, out);
}

float light_pdf_sa(const LightSampler *ls, int piece, Vec3 ref, Vec3 p, Vec3 n)
{
    if (piece < 0 || piece >= ls->n_pieces) return 0.0f;
    if (ls->pieces[piece].count == 0)             /* a whole emitter (also an infinite one) */
        return emitter_pdf_sa(ls->scene, ls->pieces[piece].emitter, ref, p, n);
    return pdf_sa_area(ls->pieces[piece].area, ref, p, n);
}

/* ------------------------------------------------------------------ selection */

/* Row of a wavelength in the spectral table T: the thesis' 60 bins over 400-700 nm
   are rows SPD_UV_BINS.., the 20 UV bins over 300-400 nm (fluorescence excitation,
   docs/FLUORESCENCE.md section 5) rows 0..19; -1 outside 300-700 nm. */
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
       front of it (section 5). */
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
    if (is_tree(st)) return tree_select(ls, c, u, pmf);
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
    if (is_tree(st)) return tree_pmf(ls, c, piece);
    if (n > SEL_STACK && !(w = (double *)malloc(sizeof(double) * 2 * (size_t)n))) return 0.0f;
    sum = context_weights(ls, c, w, &fb);
    if (sum > 0.0) p = (float)(w[piece] / sum);
    if (w != wbuf) free(w);
    return p;
}
