/* bvh.c - the bounding volume hierarchy: answers ray queries with it (bvhbuild.c
   builds it).

   WHAT IT IMPLEMENTS (specnee.h section 5)
     (bvhbuild.c: bvh_build / bvh_free, a binned-SAH BVH over every triangle,
      sphere, quadric (disk, cylinder, cut sphere: shapes.c), bilinear patch
      (patch.c) and curve piece (curve.c) of a Scene, in 8-wide nodes)
     bvh_intersect          closest hit along a ray segment 0 < t < tmax
     bvh_occluded           any hit (shadow rays): stops at the first one found
     intersect_triangle     watertight ray/triangle test (Woop, Benthin, Wald 2013)
     intersect_sphere       ray/sphere in double (Haines et al. 2019)
     bvh_hit_floor          the distance below which no hit on a primitive is reported
   (hitpoint.c: scene_surface_point, the position, normals and (u, v) at a hit, and
    where a secondary ray starts)
   USE: scene_load calls bvh_build(&s->bvh, s) once.  The integrator calls
   bvh_intersect, then scene_surface_point, and bvh_occluded for the shadow rays of
   next event estimation (through media it follows them with bvh_intersect instead).
   Primitive id k < n_tris is triangle k, n_tris + j sphere j (s->sphere_shape[j]),
   n_tris + n_spheres + k quadric k (s->quadric_shape[k], intersected by shapes.c),
   n_tris + n_spheres + n_quadrics + k patch k (s->patches[k], a bilinear patch that
   is not flat, intersected by patch.c; flat ones are two triangles), that + n_patches
   + k curve piece k (s->curve_pieces[k], intersected by curve.c), and n_base + i
   instance i (n_base = n_tris + n_spheres + n_quadrics + n_patches + n_curve_pieces;
   instance.c: a second level); at most 2^28 - 1 of them (a leaf packs its first
   primitive into 28 bits).

   INSTANCES (the second level; instance.c has the transforms): bvh_build's tree
   holds the primitives in the world (Shape.in_object == 0) and one primitive per
   instance, boxed by its world box; bvh_build_object builds each object's tree over
   its primitives in the object's space.  A leaf that meets an instance traces the
   ray, carried into object space with the same t, through the object's tree with
   tmax = the closest hit so far (instance_hit), and a hit there counts as the
   instance's (floored by the instance's world box: THE HIT'S FLOOR): ties with it
   go by the instance's top-level id, ties inside the object by the object's ids,
   so the result stays independent of the order.  The
   hit record names the object's primitive and the instance (HitRecord.inst), and
   scene_surface_point computes the point in object space and carries it back.

   BUILD (bvh_build): a binary tree by the binned surface area heuristic (Wald 2007;
   pbrt-v4 section 7.3.2), then collapsed into 8-wide nodes (Wald, Benthin, Boulos
   2008): a wide node opens its inner child of largest area until it has 8.  A wide
   node replaces up to 7 binary ones and tests its 8 children's boxes without
   branches, four at a time in SSE2 where the compiler has it (node_hit_mask; the
   scalar loop it mirrors elsewhere), all eight at once where the processor has AVX2
   (node_hit8, in the AVX2 copy of the traversal); a ray visits about a third as
   many nodes.  The build is deterministic (no threads, no timing).

   LAYOUT (specnee.h: BvhNode, BvhPrim; 256-byte nodes aligned to 64 bytes)
         BvhNode          child 0   child 1   ...   child 7
         box[0]  lo x     [ f32 ]   [ f32 ]         [ f32 ]   one plane of all 8
           ...   lo y, lo z, hi x, hi y                       children: 32 bytes, so
         box[5]  hi z     [ f32 ]   [ f32 ]         [ f32 ]   the slab test reads 8 at once
         child[] >= 0: node index;  < 0: leaf ~(first << 3 | count - 1)
         pad[]   to 256 bytes: four whole cache lines
     An empty slot is the box lo = +inf, hi = -inf, which every ray misses.  A leaf is
     the records prims[first .. first + count), count <= BVH_WIDE_LEAF_MAX, each the
     primitive's id and its vertices (a sphere: centre, radius; a quadric: only the id),
     so a leaf is one contiguous run of memory; sorted by id (bvhbuild.c), so that
     triangles come first and a leaf whose last record is a triangle holds only
     triangles (traverse then tests them in a loop of their own).

   TRAVERSAL (traverse): iterative, with a stack of (child, entry distance).  The
   nearest child entered is visited first; shadow rays skip the ordering
   and return at the first hit.  Random rays make every data-dependent branch a coin
   toss, so the loop has as few as it can (the children by their set bits; two
   entered are ordered by one compare, more placed on the stack by rank; a shadow
   ray's one or two children take one path without a branch).  Where the
   processor has AVX2 (asked once a query), a second copy of the same loop compiled
   for AVX2 runs instead: the slab test in 8 lanes, and a 4-lane filter before each
   triangle test (tri_miss4), whose lanes the test then finishes from
   (tri_hit_rest); it computes the same floats in the same order, so
   every result is the same to the bit.  The closest
   hit does not depend on the order: it is exactly
   what brute force finds, the smallest reported t in (0, tmax), ties to the smallest
   id, where a hit's t is never reported nearer than its primitive's own box (the
   hit's floor: the proof opens the traversal section; tests/test_bvh.c checks it
   bit for bit).
   Speed: docs/bvh.md has the figures (Embree 3 at its fastest is as fast on all of
   tools/bench's incoherent rays and about 1.26 times faster on those that
   enter the mesh's box, closest hit, with the AVX2 copy on an AMD Zen 4; more with
   the SSE2 copy), what each choice gains and what was tried.

   ALPHA (pbrt-v4's "alpha" of a shape; alpha_keep): a hit on a shape with
   alpha_on counts only when u <= a, with a the shape's "float alpha" or its float
   texture at the hit's (u, v) (the SurfacePoint texture.c reads) and u in [0, 1) a
   hash of the bits of the ray's origin and direction: a deterministic stochastic
   test, the same for every thread count.  a <= 0 never counts, a >= 1 always.  A
   hit that does not count lets the ray go on: a sphere, quadric, patch or curve is
   intersected again beyond it, by the ray spawned there (its own hash).  The
   answer is a function of the ray and the primitive alone, so ORDER INDEPENDENCE
   still holds, and shadow rays (any hit) see exactly the hits that closest-hit
   rays see.  Without alpha shapes (Scene.n_alpha = 0) a hit costs one compare more.

   SELF-INTERSECTION: hitpoint.c states the policy by which a secondary ray does
   not hit the surface it leaves; this file's part is the triangle test's
   rejection of a t within its own rounding error (tri_hit, step 5) and the
   double-precision roots of spheres.
*/
#include "specnee.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* Traversal stack size.  The build switches from SAH to middle splits at depth
   SAH_DEPTH_MAX; a middle split halves the count, so no binary path is longer than
   SAH_DEPTH_MAX + 28 < 64 nodes for the at most 2^28 primitives, and no wide path
   either (a wide level takes at least one binary level).  A visit pops one entry and
   pushes at most BVH_WIDTH, so the stack never holds more than
   (BVH_WIDTH - 1) * 64 + 1 entries; one more slot, since a shadow ray's visit
   entering one child writes the slot above the top without keeping it. */
#define BVH_STACK ((BVH_WIDTH - 1) * 64 + 2)

/* The hot path (ray_prepare, node_hit, tri_hit) must be inlined into the traversal
   loop; gcc's size heuristics refuse without being told, costing about 30%. */
#if defined(__GNUC__) || defined(__clang__)
#define HOT_INLINE static inline __attribute__((always_inline))
#else
#define HOT_INLINE static inline
#endif

/* PREFETCH(p): a hint that the cache line holding *p will be read soon.  It changes no
   result, only when the memory arrives; gcc and clang have a builtin for it, other
   compilers (tcc) just skip it. */
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__TINYC__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif

/* UNLIKELY(c): c, with the hint that it is rarely true, so that the compiler lays
   the rare path out of the way.  It changes no result; tcc and other compilers
   just evaluate c. */
#if defined(__GNUC__) && !defined(__clang__) && !defined(__TINYC__) && __GNUC__ >= 9
#define UNLIKELY(c) __builtin_expect_with_probability(!!(c), 0, 0.99)   /* gcc 9 on */
#elif (defined(__GNUC__) || defined(__clang__)) && !defined(__TINYC__)
#define UNLIKELY(c) __builtin_expect(!!(c), 0)
#else
#define UNLIKELY(c) (c)
#endif

/* The slab test of a node's 8 children runs 4 at a time in SSE2 where the compiler
   offers it (every x86-64 gcc and clang); elsewhere (tcc, other processors, or
   -DSPECNEE_NO_SIMD) the scalar loop it mirrors runs.  Both do the same operations in
   the same order, so they agree to the bit (the test bvh_simd_matches_scalar). */
#if defined(__SSE2__) && !defined(__TINYC__) && !defined(SPECNEE_NO_SIMD)
#define BVH_SIMD 1
#include <emmintrin.h>
#else
#define BVH_SIMD 0
#endif

/* Where the processor also has AVX2 (asked at run time: __builtin_cpu_supports), the
   whole traversal runs as a second copy compiled for it (traverse_avx2_*), whose slab
   test takes all 8 children in one 8-lane pass (node_hit8) and whose rank compares all
   8 slots at once, by integer keys (push_ranked8).  Only gcc and clang on x86 know the target attribute
   that compiles one function for an instruction set the rest of the file does not
   assume; tcc, -DSPECNEE_NO_SIMD and -DSPECNEE_NO_AVX keep the SSE2 (or scalar) code
   alone.  The AVX2 copy does the same operations in the same order (no fused
   multiply-add: the target is "avx2", not "fma", and the Makefile has
   -ffp-contract=off), so it agrees to the bit (the tests bvh_simd_matches_scalar and
   bvh_avx2_triangle_filter). */
#if BVH_SIMD && defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && \
    !defined(SPECNEE_NO_AVX)
#define BVH_AVX 1
#include <immintrin.h>
/* a function compiled for AVX2; not always_inline (gcc and clang refuse to force an
   AVX2 function into one compiled without it), but small, so both inline it into
   the AVX2 copies of the traversal (checked with objdump: no call) */
#define AVX2_FN static inline __attribute__((target("avx2")))
#define AVX2_STATIC static __attribute__((target("avx2")))
#define AVX2_NOINLINE static __attribute__((target("avx2"), noinline))
#else
#define BVH_AVX 0
#endif

/* gamma(n) = n u / (1 - n u) with u = 2^-24, the unit roundoff of float: a bound on the
   relative error of n chained roundings (Higham 2002; pbrt-v3 section 3.9.1). */
static inline float gamma_n(int n)
{
    const float u = FLT_EPSILON * 0.5f;
    return ((float)n * u) / (1.0f - (float)n * u);
}

/* ======================================================================
   Per-ray precomputation shared by the triangle test and the slab test
   ====================================================================== */
/* The slab test's and the triangle test's per-ray axis order depends only on the
   dominant axis kz and the signs of d: 3 x 8 cases, tabled once (ray_orders) so that
   preparing a ray copies its case instead of computing it.  For case (kz, n), bit a
   of n set when d_a < 0 (the sign bit):
     axis[s]   the slab test's axis order: the other two axes after kz, then kz
               (lane 3 = 3: the padding lane of a 4-float vector)
     plane     the planes of axis[s] that the ray enters (plane[s]) and leaves
               (plane[4 + s]) through, as offsets in floats from BvhNode.box[0]:
               row * BVH_WIDTH, the hi row for d < 0 and the lo row for d >= 0
     k         the triangle test's permutation kx, ky, kz: the two axes after kz,
               swapped when d_kz < 0 to keep the triangles' winding (Woop et al.),
               and (k[4..6]) each + 1, the AVX2 filter's lane choices (lane 3: 3,
               lane 7: 0) */
typedef struct {
    int32_t axis[4];
    int32_t plane[8];
    int32_t k[8];
} RayOrder;

#define RO_NEG(a, n) (((n) >> (a)) & 1)
#define RO_AX(kz, s) (((kz) + 1 + (s)) % 3)                     /* s = 2: kz itself */
#define RO_NEAR(kz, s, n) ((RO_AX(kz, s) + 3 * RO_NEG(RO_AX(kz, s), n)) * BVH_WIDTH)
#define RO_FAR(kz, s, n) ((RO_AX(kz, s) + 3 * (1 - RO_NEG(RO_AX(kz, s), n))) * BVH_WIDTH)
#define RO_KX(kz, n) (((kz) + 1 + RO_NEG(kz, n)) % 3)
#define RO_KY(kz, n) (((kz) + 2 - RO_NEG(kz, n)) % 3)
#define RO(kz, n) { { RO_AX(kz, 0), RO_AX(kz, 1), kz, 3 },                              \
    { RO_NEAR(kz, 0, n), RO_NEAR(kz, 1, n), RO_NEAR(kz, 2, n), 0,                       \
      RO_FAR(kz, 0, n), RO_FAR(kz, 1, n), RO_FAR(kz, 2, n), 0 },                        \
    { RO_KX(kz, n), RO_KY(kz, n), kz, 3, RO_KX(kz, n) + 1, RO_KY(kz, n) + 1, (kz) + 1, 0 } }
#define RO8(kz) RO(kz, 0), RO(kz, 1), RO(kz, 2), RO(kz, 3), RO(kz, 4), RO(kz, 5), RO(kz, 6), RO(kz, 7)
static const RayOrder ray_orders[3 * 8] = { RO8(0), RO8(1), RO8(2) };   /* [kz * 8 + n] */

/* the robust slab test's far factor 1 + 2 gamma(3) (THE SLAB TEST, below) */
#define FAR_SCALE (1.0f + 2.0f * gamma_n(3))

/* ======================================================================
   Per-ray precomputation shared by the triangle test and the slab test
   ====================================================================== */
typedef struct {
    float o[4], d[4];        /* lane 3: 0 */
    float inv_d[4];          /* 1/d; +-infinity where d is +-0 */
    int neg[3];              /* the sign bit of d: the slab the ray enters first */
    const RayOrder *ord;     /* the ray's case: the slab test's near plane of axis[s]
                                is ord->plane[s], its far plane ord->plane[4 + s]; the
                                triangle test's kx, ky, kz are ord->k[0], k[1], k[2] */
    float S[4];              /* shear constants of Woop et al.: Sx, Sy, Sz, 0 */
    float o_ax[4], ninv_ax[4];  /* o and -1/d of axis[s]: the slab test's operands */
#if BVH_SIMD
    __m128 o4[3], ninv4[3], far4;  /* o_ax, ninv_ax, FAR_SCALE in all four lanes */
#endif
#if BVH_AVX
    __m128 o_k, sx4, sy4;    /* (o_kx, o_ky, o_kz, 0); Sx and Sy in all four lanes */
    __m128 d_k, inv_k;       /* d and 1/d in the order kx, ky, kz (lane 3: 0, +inf):
                                tri_box_entry4's operands */
    __m256 o8[3], ninv8[3];  /* o_ax, ninv_ax in all eight lanes */
#endif
} RayPre;

/* The sign of d_a and 1/d_a (+-infinity for d_a = +-0); called once an axis, written
   out (as root_axis) */
HOT_INLINE void inv_axis(RayPre *rp, int a)
{
    rp->neg[a] = signbit(rp->d[a]) != 0;
    rp->inv_d[a] = rp->d[a] != 0.0f ? 1.0f / rp->d[a] : (rp->neg[a] ? -INFINITY : INFINITY);
}

/* The first part of the precomputation (o, d, 1/d, signs): all that the test of the
   root box needs.  Returns 0 for a ray that cannot hit anything (a non-finite origin
   or direction). */
HOT_INLINE int ray_prepare(const Ray *r, RayPre *rp)
{
    rp->o[0] = r->o.x; rp->o[1] = r->o.y; rp->o[2] = r->o.z; rp->o[3] = 0.0f;
    rp->d[0] = r->d.x; rp->d[1] = r->d.y; rp->d[2] = r->d.z; rp->d[3] = 0.0f;
    /* x - x is +0 for a finite x and NaN for an infinite or NaN one, so the sum of the
       six is 0 exactly when all six are finite: one test, not six branches */
    if (!((rp->o[0] - rp->o[0]) + (rp->o[1] - rp->o[1]) + (rp->o[2] - rp->o[2]) +
          (rp->d[0] - rp->d[0]) + (rp->d[1] - rp->d[1]) + (rp->d[2] - rp->d[2]) == 0.0f))
        return 0;
    inv_axis(rp, 0);
    inv_axis(rp, 1);
    inv_axis(rp, 2);
    rp->inv_d[3] = INFINITY;             /* 1 / d[3], as the 4-lane code makes it */
    return 1;
}

/* The rest: the dominant axis, the slab test's axis order and planes, and the
   triangle test's permutation and shear (Woop et al.).  Kept separate so that
   traversal computes it only for rays that hit the root box: most rays of an open
   scene miss everything.  Returns 0 for a direction too short to use. */
HOT_INLINE int ray_prepare_rest(RayPre *rp, int sse)
{
    const RayOrder *ord;
    int a, kz;
    /* kz: the dimension where |d| is largest, so the shear divides by the most */
    {   /* without branches: random directions would mispredict them (docs/bvh.md) */
        const float a0 = fabsf(rp->d[0]), a1 = fabsf(rp->d[1]), a2 = fabsf(rp->d[2]);
        const int k1 = a1 > a0;                     /* the first largest wins ties */
        const float m = a1 > a0 ? a1 : a0;
        kz = k1 + (a2 > m) * (2 - k1);
    }
    /* a direction too short for 1/d_kz to be finite hits nothing (the same for the
       brute-force tests intersect_triangle and intersect_sphere); this includes 0 */
    if (!(fabsf(rp->d[kz]) >= FLT_MIN)) return 0;
    ord = &ray_orders[kz * 8 + rp->neg[0] + 2 * rp->neg[1] + 4 * rp->neg[2]];
    rp->ord = ord;
    for (a = 0; a < 4; a++) {
        rp->o_ax[a] = rp->o[ord->axis[a]];
        rp->ninv_ax[a] = -rp->inv_d[ord->axis[a]];
    }
#if BVH_SIMD
    if (sse) {          /* node_hit4's operands (sse = 0: the AVX2 copy, or no slab test) */
        for (a = 0; a < 3; a++) {
            rp->o4[a] = _mm_set1_ps(rp->o_ax[a]);
            rp->ninv4[a] = _mm_set1_ps(rp->ninv_ax[a]);
        }
        rp->far4 = _mm_set1_ps(FAR_SCALE);
    }
#endif
    (void)sse;
    rp->S[0] = rp->d[rp->ord->k[0]] / rp->d[kz];
    rp->S[1] = rp->d[rp->ord->k[1]] / rp->d[kz];
    rp->S[2] = rp->inv_d[kz];        /* = 1 / d_kz, the very float the slab test uses */
    rp->S[3] = 0.0f;
    return 1;
}

/* ======================================================================
   Primitive tests on prepared rays
   ====================================================================== */

static inline float max3f(float a, float b, float c)
{
    float m = a > b ? a : b;
    return m > c ? m : c;
}

/* The edge functions again in double, for a ray exactly on an edge in float: the
   products of two floats are exact in double, so the signs are right. */
static void edge_functions_double(float Ax, float Ay, float Bx, float By, float Cx, float Cy,
                                  float *U, float *V, float *W)
{
    *U = (float)((double)Cx * (double)By - (double)Cy * (double)Bx);
    *V = (float)((double)Ax * (double)Cy - (double)Ay * (double)Cx);
    *W = (float)((double)Bx * (double)Ay - (double)By * (double)Ax);
}

/* A bound on the rounding error of t = T / det, from the sheared vertices and the
   edge functions (pbrt-v3 section 3.9.6, "Conservative ray-triangle intersection"):
   each delta is the error bound of the quantity it is named after. */
static float t_error_bound_max(float max_xt, float max_yt, float max_zt, float max_e,
                               float inv_det)
{
    const float delta_z = gamma_n(3) * max_zt;
    const float delta_x = gamma_n(5) * (max_xt + max_zt);
    const float delta_y = gamma_n(5) * (max_yt + max_zt);
    const float delta_e = 2.0f * (gamma_n(2) * max_xt * max_yt + delta_y * max_xt +
                                  delta_x * max_yt);
    return 3.0f * (gamma_n(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) *
           fabsf(inv_det);
}

/* The same from the sheared vertices and edge functions themselves: their largest
   magnitudes are all the bound reads. */
static float t_error_bound(float Ax, float Ay, float Az, float Bx, float By, float Bz,
                           float Cx, float Cy, float Cz, float U, float V, float W,
                           float inv_det)
{
    return t_error_bound_max(max3f(fabsf(Ax), fabsf(Bx), fabsf(Cx)),
                             max3f(fabsf(Ay), fabsf(By), fabsf(Cy)),
                             max3f(fabsf(Az), fabsf(Bz), fabsf(Cz)),
                             max3f(fabsf(U), fabsf(V), fabsf(W)), inv_det);
}

/* Watertight test of the triangle v[0..8] = (p0, p1, p2) (Woop, Benthin, Wald,
   "Watertight Ray/Triangle Intersection", JCGT 2013).  Translate the vertices to the
   ray origin, permute the axes so that the largest direction component is z, and
   shear so the ray becomes the +z axis:
       A' = (A_x - S_x A_z, A_y - S_y A_z, S_z A_z)   with S_x = d_x/d_z, S_y = d_y/d_z,
                                                           S_z = 1/d_z   (same for B, C)
   In that 2D frame the ray is the origin, and the scaled barycentrics are the edge
   functions  U = C'_x B'_y - C'_y B'_x,  V = A'_x C'_y - A'_y C'_x,
              W = B'_x A'_y - B'_y A'_x    (U is the weight of A, V of B, W of C).
   The ray hits iff U, V, W all have the same sign (both faces are hit).  When one of
   them is exactly 0 it is recomputed in double, where the products of two floats are
   exact, so the sign is right: a ray through a shared edge or vertex is accepted by at
   least one of the triangles around it - the mesh is watertight.  With
   det = U + V + W and T = U A'_z + V B'_z + W C'_z the hit is at
       t = T / det,  b1 = V / det,  b2 = W / det.
   Finally t must exceed a bound on its own rounding error (pbrt-v3 section 3.9.6): a
   ray starting on the triangle's plane never hits that triangle at a t that is only
   rounding noise (the self-intersection policy at the top of this file). */
/* THE HIT'S FLOOR (ORDER INDEPENDENCE, below): a primitive test reports a hit at
   t = max(t_test, box_entry(its own box)), where box_entry is the entry distance of
   the box lo..hi computed with the slab test's operations in the slab test's order
   (node_hit_mask_scalar's lane: the near plane of axis[s] by the ray's sign, then
   (o - plane) * (-1/d), folded with "x > acc ? x : acc" from 0). */
HOT_INLINE float box_entry(const RayPre *rp, const float *lo, const float *hi)
{
    float tn = 0.0f;
    int s;
    for (s = 0; s < 3; s++) {
        const int a = rp->ord->axis[s];
        const float plane = rp->ord->plane[s] >= 3 * BVH_WIDTH ? hi[a] : lo[a];   /* hi rows: d < 0 */
        const float x = (rp->o_ax[s] - plane) * rp->ninv_ax[s];
        tn = x > tn ? x : tn;
    }
    return tn;
}

/* A hit at t on a primitive whose box the ray enters at te is reported at this */
HOT_INLINE float floored(float t, float te)
{
    return te > t ? te : t;
}

/* box_entry of triangle v's box, the smallest and largest of its vertices'
   coordinates (the box bvhbuild.c gives it: the same floats) */
HOT_INLINE float tri_box_entry(const RayPre *rp, const float *v)
{
    float lo[3], hi[3];
    int a;
    for (a = 0; a < 3; a++) {
        const float p0 = v[a], p1 = v[3 + a], p2 = v[6 + a];
        lo[a] = p0 < p1 ? p0 : p1;  lo[a] = p2 < lo[a] ? p2 : lo[a];
        hi[a] = p0 > p1 ? p0 : p1;  hi[a] = p2 > hi[a] ? p2 : hi[a];
    }
    return box_entry(rp, lo, hi);
}

/* Steps 1 to 3 of tri_hit (below), for tri_hit and the test of its AVX2 filter:
   e[] = A'x A'y B'x B'y C'x C'y, z[] = A_z B_z C_z (before the scale by Sz), and
   uvw[] = U V W in float. */
HOT_INLINE void tri_edges(const RayPre *rp, const float *v, float *e, float *z, float *uvw)
{
    const int kx = rp->ord->k[0], ky = rp->ord->k[1], kz = rp->ord->k[2];
    const float ox = rp->o[kx], oy = rp->o[ky], oz = rp->o[kz];

    /* 1. Vertices relative to the ray origin, in the permuted axes (x, y, z) */
    const float A_x = v[kx] - ox, A_y = v[ky] - oy, A_z = v[kz] - oz;
    const float B_x = v[3 + kx] - ox, B_y = v[3 + ky] - oy, B_z = v[3 + kz] - oz;
    const float C_x = v[6 + kx] - ox, C_y = v[6 + ky] - oy, C_z = v[6 + kz] - oz;

    /* 2. Shear: the ray becomes the +z axis */
    const float Ax = A_x - rp->S[0] * A_z, Ay = A_y - rp->S[1] * A_z;
    const float Bx = B_x - rp->S[0] * B_z, By = B_y - rp->S[1] * B_z;
    const float Cx = C_x - rp->S[0] * C_z, Cy = C_y - rp->S[1] * C_z;

    /* 3. Scaled barycentrics = 2D edge functions of the origin */
    uvw[0] = Cx * By - Cy * Bx;
    uvw[1] = Ax * Cy - Ay * Cx;
    uvw[2] = Bx * Ay - By * Ax;
    e[0] = Ax; e[1] = Ay; e[2] = Bx; e[3] = By; e[4] = Cx; e[5] = Cy;
    z[0] = A_z; z[1] = B_z; z[2] = C_z;
}

HOT_INLINE int tri_hit(const RayPre *rp, const float *v, float tmax,
                       float *t_out, float *b1_out, float *b2_out)
{
    float e[6], z[3], uvw[3];
    float Ax, Ay, Bx, By, Cx, Cy, Az, Bz, Cz, U, V, W, det, T, inv_det, t;

    /* 1 to 3: the sheared vertices and the edge functions */
    tri_edges(rp, v, e, z, uvw);
    Ax = e[0]; Ay = e[1]; Bx = e[2]; By = e[3]; Cx = e[4]; Cy = e[5];
    U = uvw[0]; V = uvw[1]; W = uvw[2];
    /* (the conditions are combined with | and &, not || and &&: one branch, not six,
       each of which random rays would mispredict) */
    if ((U == 0.0f) | (V == 0.0f) | (W == 0.0f))  /* on an edge in float: ask double */
        edge_functions_double(Ax, Ay, Bx, By, Cx, Cy, &U, &V, &W);
    if (((U < 0.0f) | (V < 0.0f) | (W < 0.0f)) & ((U > 0.0f) | (V > 0.0f) | (W > 0.0f)))
        return 0;                                  /* mixed signs: outside */
    det = U + V + W;
    if (det == 0.0f) return 0;                     /* edge-on or degenerate triangle */

    /* 4. Scaled distance T = det * t */
    Az = rp->S[2] * z[0];  Bz = rp->S[2] * z[1];  Cz = rp->S[2] * z[2];
    T = U * Az + V * Bz + W * Cz;
    if (det < 0.0f ? T >= 0.0f : T <= 0.0f) return 0;   /* behind the origin */
    inv_det = 1.0f / det;
    t = T * inv_det;
    if (!(t > 0.0f && t <= tmax)) return 0;        /* tmax itself counts: ties */

    /* 5. Reject t within its rounding error of 0 (pbrt-v3 section 3.9.6) */
    if (t <= t_error_bound(Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz, U, V, W, inv_det)) return 0;

    /* 6. The hit's floor: never nearer than the triangle's own box (ORDER
       INDEPENDENCE); only then is t compared with tmax for good */
    {
        t = floored(t, tri_box_entry(rp, v));
        if (!(t <= tmax)) return 0;
    }

    *t_out = t;
    *b1_out = V * inv_det;
    *b2_out = W * inv_det;
    return 1;
}

/* Ray/sphere in double (Haines, Guenther, Akenine-Moller, "Precision Improvements for
   Ray/Sphere Intersection", Ray Tracing Gems ch. 7, 2019).  s[0..3] = (cx, cy, cz,
   radius).  With f = o - c, solve |f + t d|^2 = r^2, i.e. a t^2 + 2 b t + c = 0 with
   a = d.d, b = f.d, c = f.f - r^2.  The discriminant is formed as
   a (r^2 - |f - (b/a) d|^2), which does not cancel catastrophically for a far sphere,
   and the roots as  q = -(b + sign(b) sqrt(disc)),  t0 = q / a,  t1 = c / q,  which
   avoids subtracting nearly equal numbers.  Everything is in double (spheres are
   few).  The nearest root in (0, tmax] is returned. */
static int sphere_hit(const RayPre *rp, const float *s, float tmax, float *t_out)
{
    double f[3], d[3], l[3], a = 0, b = 0, c = 0, ll = 0, r = s[3], disc, q, t0, t1, tmp;
    float tf;
    int k;
    if (!(r > 0.0)) return 0;
    for (k = 0; k < 3; k++) {
        f[k] = (double)rp->o[k] - (double)s[k];
        d[k] = rp->d[k];
        a += d[k] * d[k];
        b += f[k] * d[k];
        c += f[k] * f[k];
    }
    c -= r * r;
    /* origin outside (c > 0) and the centre not ahead (b >= 0): both roots are
       negative (their product c / a > 0, their sum -2b / a <= 0), and the code below
       would compute q <= 0, t0 = q / a < 0, t1 = c / q < 0 and return 0; leave now,
       before the square root and the divisions (most spheres a ray meets behind it) */
    if (c > 0.0 && b >= 0.0) return 0;
    for (k = 0; k < 3; k++) {          /* l = f - (b/a) d: closest approach to the centre */
        l[k] = f[k] - (b / a) * d[k];
        ll += l[k] * l[k];
    }
    disc = a * (r * r - ll);
    if (disc < 0.0) return 0;
    q = -(b + (b < 0.0 ? -sqrt(disc) : sqrt(disc)));
    if (q == 0.0) return 0;                        /* tangent at the origin itself */
    t0 = q / a;
    t1 = c / q;
    if (t0 > t1) { tmp = t0; t0 = t1; t1 = tmp; }
    tf = (float)t0;
    if (!(tf > 0.0f)) tf = (float)t1;              /* origin inside or past the first root */
    if (!(tf > 0.0f && tf <= tmax)) return 0;
    {                                              /* the hit's floor, as tri_hit's */
        float lo[3], hi[3];
        bvh_sphere_box(s, s[3], lo, hi);
        tf = floored(tf, box_entry(rp, lo, hi));
        if (!(tf <= tmax)) return 0;
    }
    *t_out = tf;
    return 1;
}

int intersect_triangle(Vec3 p0, Vec3 p1, Vec3 p2, const Ray *r, float *t, float *b1, float *b2)
{
    RayPre rp;
    float v[9];
    v[0] = p0.x; v[1] = p0.y; v[2] = p0.z;
    v[3] = p1.x; v[4] = p1.y; v[5] = p1.z;
    v[6] = p2.x; v[7] = p2.y; v[8] = p2.z;
    if (!ray_prepare(r, &rp) || !ray_prepare_rest(&rp, 0)) return 0;
    return tri_hit(&rp, v, r->tmax, t, b1, b2) && *t < r->tmax;
}

int intersect_sphere(Vec3 c, float radius, const Ray *r, float *t)
{
    RayPre rp;
    float s[4];
    s[0] = c.x; s[1] = c.y; s[2] = c.z; s[3] = radius;
    if (!ray_prepare(r, &rp) || !ray_prepare_rest(&rp, 0)) return 0;
    return sphere_hit(&rp, s, r->tmax, t) && *t < r->tmax;
}


/* ======================================================================
   Traversal
   ====================================================================== */
/* ORDER INDEPENDENCE (the closest hit is a function of the ray, not of the traversal)
   The closest hit is defined as brute force over all primitives would find it: the
   smallest reported t with 0 < t < tmax, and among equal t the smallest primitive id.
   Whatever order the leaves are visited in, the traversal returns exactly that,
   because (1) a leaf accepts t <= t_best and breaks a tie by the id, and (2) a box is
   culled only when no primitive inside it can report a t <= t_best.
   (2) rests on one rule that every primitive test keeps, THE HIT'S FLOOR:
       reported t = max(t_test, entry distance of the primitive's own box)
   where t_test is the distance the test computed, the box is the one bvhbuild.c
   gives the primitive (bvh_prim_box: a triangle's is its vertices' smallest and
   largest coordinates), and its entry distance is computed by the slab test's own
   operations (box_entry; below).  Boxes nest: a box of the tree holds the box of
   every primitive under it, plane for plane (the build takes unions, which do not
   round).  On each axis the slab test computes (o - plane) * (-1/d), one
   subtraction and one multiplication by the same float, and rounding is monotonic,
   so the nearer plane of the outer box gives a distance no larger; the maximum over
   the axes keeps the order (a NaN, the origin on a plane with d = 0, is skipped by
   both).  So the tree's computed entry distance of a box is at most that of each
   primitive's box inside it, hence at most each reported t, and a box may be culled
   exactly when
       t_enter > t_best                          (no margin: a tie is visited)
   Without the floor no small margin would do: the computed t of a triangle and the
   computed entry distance of its box round differently, and for a grazing ray the
   barycentrics, hence t_test, can be off by far more than an ulp, below the box's
   entry.  The floor changes t_test only there, and by an ulp or so where a triangle
   lies in a plane of its box (an axis-aligned wall); it moves such a t towards the
   true one, which lies in the box.  It is applied before t is compared with tmax, so
   a hit whose floor passes tmax is no hit, for closest-hit and shadow rays alike.
   tests/test_bvh.c (bvh_exact_adversarial) checks the result against brute force bit
   for bit on rays through shared edges and vertices, along the normals of
   axis-aligned faces (where a triangle's box is flat and the floor moves t by an
   ulp), grazing, and on duplicated and coplanar triangles; bvh_hit_floor_holds
   checks the floor itself.  Culling on the full entry distance visits about 7 %
   fewer nodes than culling on the dominant axis alone, the one axis where a
   triangle's t is bounded by its box's distance without a floor (docs/bvh.md).

   THE SLAB TEST (Kay & Kajiya 1986) uses the precomputed inverse direction: on each
   axis the ray enters through the plane the sign of d points away from (lo for
   d >= 0, hi for d < 0), so near and far planes are picked once per ray
   (RayOrder.plane).  Each plane's distance is computed as (o - b) * (-1/d), the same
   float as (b - o) * (1/d) (above), because x86 folds a load only into the second
   operand of a subtraction: o - box[j] reads the box straight from memory.  A zero
   component of d gives 1/d = +-infinity; (o - b) * inf is
   then +-infinity, or NaN when the origin lies exactly on the plane, and the near/far
   distances are accumulated with "x > acc ? x : acc", which skips a NaN: a ray in the
   plane of a flat box (an axis-aligned wall seen edge-on) still enters it.  The far
   distance is enlarged by 1 + 2 gamma(3) (Ize 2013, "Robust BVH ray traversal";
   pbrt-v3 section 3.9.2) so that rounding never culls a box the ray really touches. */
/* The slab test of the root's box (as in node_hit_mask, but without the culling by
   tmax: for a ray that misses it, nothing else needs computing). */
/* One axis of root_hit: the entry and exit distances of the root box's slab, folded
   into *tn and *tf.  Called once an axis, written out: gcc keeps a loop of three
   here, whose counter and indexing cost about 15 instructions a ray. */
HOT_INLINE void root_axis(const Bvh *b, const RayPre *rp, int a, float *tn, float *tf)
{
    const float *lohi[2];
    float t_near, t_far;
    lohi[0] = b->bmin; lohi[1] = b->bmax;
    t_near = (lohi[rp->neg[a]][a] - rp->o[a]) * rp->inv_d[a];
    t_far = (lohi[1 - rp->neg[a]][a] - rp->o[a]) * rp->inv_d[a];
    *tn = t_near > *tn ? t_near : *tn;
    *tf = t_far < *tf ? t_far : *tf;
}

HOT_INLINE int root_hit(const Bvh *b, const RayPre *rp)
{
    float tn = 0.0f, tf = INFINITY;
    root_axis(b, rp, 0, &tn, &tf);
    root_axis(b, rp, 1, &tn, &tf);
    root_axis(b, rp, 2, &tn, &tf);
    return tn <= tf * (1.0f + 2.0f * gamma_n(3));
}

/* Ask for the memory of a child (a node, or a leaf's primitive records) before it is
   needed, so that loading it overlaps with the work on its siblings. */
HOT_INLINE void prefetch_ref(const Bvh *b, int32_t ref)
{
    if (ref >= 0) {
        const char *p = (const char *)&b->nodes[ref];
        PREFETCH(p); PREFETCH(p + 64); PREFETCH(p + 128); PREFETCH(p + 192);
    } else {
        const char *p = (const char *)&b->prims[(~ref) >> 3];
        PREFETCH(p); PREFETCH(p + 64); PREFETCH(p + 128);
    }
}

/* One stack entry: a child reference (node or leaf, as in BvhNode.child) and its
   entry distance (culls it when popped). */
typedef struct { int32_t ref; float t; } StackEntry;

/* The index of the lowest set bit of m (m != 0).  m & -m keeps only that bit, 2^k;
   multiplying it by the de Bruijn sequence 0x077CB531 (every 5-bit pattern occurs once
   in it) shifts a different pattern into the top 5 bits for each k, and the table
   turns the pattern back into k (Leiserson, Prokop, Randall 1998, "Using de Bruijn
   sequences to index a 1 in a computer word").  Portable C99, no branch: the loops
   over the children entered use it instead of testing all BVH_WIDTH bits one by one,
   a branch each that random rays mispredict. */
HOT_INLINE int lowest_bit_portable(unsigned m)
{
    static const unsigned char pos[32] = {0,  1,  28, 2,  29, 14, 24, 3,  30, 22, 20,
                                          15, 25, 17, 4,  8,  31, 27, 13, 23, 21, 19,
                                          16, 7,  26, 12, 18, 6,  11, 5,  10, 9};
    return pos[(uint32_t)((uint32_t)(m & (0u - m)) * 0x077CB531u) >> 27];
}

/* The index of the highest set bit of m (0 < m < 2^BVH_WIDTH), by halving. */
HOT_INLINE int highest_bit_portable(unsigned m)
{
    int k = 0;
    if (m >> 4) { k += 4; m >>= 4; }
    if (m >> 2) { k += 2; m >>= 2; }
    return k + (int)(m >> 1);
}

/* The same, in one instruction (count trailing or leading zeros) where the compiler
   has it. */
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__TINYC__)
#define lowest_bit(m) __builtin_ctz(m)
#define highest_bit(m) (31 - __builtin_clz(m))
#else
#define lowest_bit(m) lowest_bit_portable(m)
#define highest_bit(m) highest_bit_portable(m)
#endif

/* The slab test of all BVH_WIDTH children of a node: returns the bitmask of those the
   ray enters and that may still hold a hit at t <= t_best (entry distance <= t_best:
   ORDER INDEPENDENCE above), with their entry distances.  The loop has no branches;
   the axes are taken in the ray's order and the planes by its signs. */
HOT_INLINE unsigned node_hit_mask_scalar(const BvhNode *nd, const RayPre *rp, float t_best,
                                         float *t_enter)
{
    const float *box = nd->box[0];
    const float *n0 = box + rp->ord->plane[0], *f0 = box + rp->ord->plane[4];
    const float *n1 = box + rp->ord->plane[1], *f1 = box + rp->ord->plane[5];
    const float *n2 = box + rp->ord->plane[2], *f2 = box + rp->ord->plane[6];
    const float o0 = rp->o_ax[0], o1 = rp->o_ax[1], o2 = rp->o_ax[2];
    const float i0 = rp->ninv_ax[0], i1 = rp->ninv_ax[1], i2 = rp->ninv_ax[2];
    const float far_scale = FAR_SCALE;
    int j;
    unsigned mask = 0;
    for (j = 0; j < BVH_WIDTH; j++) {
        const float tn0 = (o0 - n0[j]) * i0, tf0 = (o0 - f0[j]) * i0;
        const float tn1 = (o1 - n1[j]) * i1, tf1 = (o1 - f1[j]) * i1;
        const float tn2 = (o2 - n2[j]) * i2, tf2 = (o2 - f2[j]) * i2;
        /* "x > acc ? x : acc" skips a NaN x (d = 0 and the origin on the plane) */
        float tn = 0.0f, tf = INFINITY;
        tn = tn0 > tn ? tn0 : tn;  tf = tf0 < tf ? tf0 : tf;
        tn = tn1 > tn ? tn1 : tn;  tf = tf1 < tf ? tf1 : tf;
        tn = tn2 > tn ? tn2 : tn;  tf = tf2 < tf ? tf2 : tf;
        t_enter[j] = tn;
        mask |= (unsigned)((tn <= tf * far_scale) & (tn <= t_best)) << j;   /* bit j */
    }
    return mask;
}

#if BVH_SIMD
/* node_hit_mask_scalar for the four children h .. h + 3.  _mm_max_ps(x, acc) is
   exactly "x > acc ? x : acc" (NaN x: acc) and _mm_min_ps(x, acc) "x < acc ? x : acc",
   so every lane computes what the scalar loop computes, to the bit.  The two tests
   of the mask are one: tn <= min(tf * far, t_best), as none of the three is NaN (tn
   and tf are folded from 0 and infinity, skipping NaNs; t_best > 0).  The boxes'
   rows are 16-byte aligned (nodes on 64 bytes, rows of 32). */
HOT_INLINE unsigned node_hit4(const BvhNode *nd, const RayPre *rp, __m128 best, int h,
                              float *t_enter)
{
    const float *box = nd->box[0] + h;
    const __m128 tn0 = _mm_mul_ps(_mm_sub_ps(rp->o4[0], _mm_load_ps(box + rp->ord->plane[0])), rp->ninv4[0]);
    const __m128 tf0 = _mm_mul_ps(_mm_sub_ps(rp->o4[0], _mm_load_ps(box + rp->ord->plane[4])), rp->ninv4[0]);
    const __m128 tn1 = _mm_mul_ps(_mm_sub_ps(rp->o4[1], _mm_load_ps(box + rp->ord->plane[1])), rp->ninv4[1]);
    const __m128 tf1 = _mm_mul_ps(_mm_sub_ps(rp->o4[1], _mm_load_ps(box + rp->ord->plane[5])), rp->ninv4[1]);
    const __m128 tn2 = _mm_mul_ps(_mm_sub_ps(rp->o4[2], _mm_load_ps(box + rp->ord->plane[2])), rp->ninv4[2]);
    const __m128 tf2 = _mm_mul_ps(_mm_sub_ps(rp->o4[2], _mm_load_ps(box + rp->ord->plane[6])), rp->ninv4[2]);
    __m128 tn = _mm_max_ps(tn0, _mm_setzero_ps()), tf = _mm_min_ps(tf0, _mm_set1_ps(INFINITY));
    tn = _mm_max_ps(tn1, tn);  tf = _mm_min_ps(tf1, tf);
    tn = _mm_max_ps(tn2, tn);  tf = _mm_min_ps(tf2, tf);
    _mm_storeu_ps(t_enter + h, tn);
    return (unsigned)_mm_movemask_ps(_mm_cmple_ps(tn, _mm_min_ps(_mm_mul_ps(tf, rp->far4), best)));
}

/* node_hit_mask_scalar in two halves of four children */
HOT_INLINE unsigned node_hit_mask(const BvhNode *nd, const RayPre *rp, float t_best,
                                  float *t_enter)
{
    const __m128 best = _mm_set1_ps(t_best);
    return node_hit4(nd, rp, best, 0, t_enter) | node_hit4(nd, rp, best, 4, t_enter) << 4;
}
#else
#define node_hit_mask node_hit_mask_scalar
#endif

/* The rank of entered child jj among the entered children of a node (the bits of
   mask): how many of them are farther (t_enter larger; ties: lower slot first), so
   that the nearest gets rank 0.  A branch-free count over all slots. */
HOT_INLINE int child_rank_scalar(const float *t_enter, unsigned mask, int jj)
{
    const float te = t_enter[jj];
    int j, rank = 0;
    for (j = 0; j < BVH_WIDTH; j++)
        rank += (int)((mask >> j) & 1u) & ((t_enter[j] > te) | ((t_enter[j] == te) & (j < jj)));
    return rank;
}

#if BVH_SIMD
/* child_rank_scalar with the comparisons four slots at a time: the slots farther, or
   as far and lower, as a bitmask; its entered bits counted by a table of the counts
   of 4-bit patterns (no population-count instruction in SSE2). */
HOT_INLINE int child_rank(const float *t_enter, unsigned mask, int jj)
{
    static const unsigned char bits4[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
    const __m128 te = _mm_set1_ps(t_enter[jj]);
    const __m128 lo = _mm_loadu_ps(t_enter), hi = _mm_loadu_ps(t_enter + 4);
    const unsigned gt = (unsigned)_mm_movemask_ps(_mm_cmpgt_ps(lo, te)) |
                        (unsigned)_mm_movemask_ps(_mm_cmpgt_ps(hi, te)) << 4;
    const unsigned eq = (unsigned)_mm_movemask_ps(_mm_cmpeq_ps(lo, te)) |
                        (unsigned)_mm_movemask_ps(_mm_cmpeq_ps(hi, te)) << 4;
    const unsigned m = (gt | (eq & ((1u << jj) - 1u))) & mask;
    return bits4[m & 15u] + bits4[m >> 4];
}
#else
#define child_rank child_rank_scalar
#endif

/* the AVX2 kernels, each the same operations as the kernel above it mirrors */
#include "bvh_avx2.h"

/* A number in [0, 1) hashed from the bits of r's origin and direction (ALPHA). */
static double ray_hash01(const Ray *r)
{
    uint32_t b[6];
    uint64_t h;
    memcpy(&b[0], &r->o.x, 4); memcpy(&b[1], &r->o.y, 4); memcpy(&b[2], &r->o.z, 4);
    memcpy(&b[3], &r->d.x, 4); memcpy(&b[4], &r->d.y, 4); memcpy(&b[5], &r->d.z, 4);
    h = hash_u64((uint64_t)b[0] << 32 | b[1], (uint64_t)b[2] << 32 | b[3]);
    h = hash_u64(h, (uint64_t)b[4] << 32 | b[5]);
    return (double)(uint32_t)(h >> 32) * (1.0 / 4294967296.0);
}

/* Primitive p (not an instance) along r again, for 0 < t < r->tmax: its further
   hit past one that alpha ignored; a triangle, being flat, has none. */
static int prim_hit_again(const Scene *s, int p, const Ray *r, float *t, float *b1, float *b2)
{
    const int n_sph = s->n_tris + s->n_spheres, n_quad = n_sph + s->n_quadrics;
    if (p < s->n_tris) return 0;
    if (p < n_sph) {
        const Shape *sh = &s->shapes[s->sphere_shape[p - s->n_tris]];
        *b1 = *b2 = 0.0f;
        return intersect_sphere(sh->center, sh->radius, r, t);
    }
    if (p < n_quad) {
        *b1 = *b2 = 0.0f;
        return quadric_intersect(&s->shapes[s->quadric_shape[p - n_sph]], r, r->tmax, t);
    } else if (p >= n_quad + s->n_patches) {
        HitRecord ch;
        if (!curve_intersect(s, &s->curve_pieces[p - n_quad - s->n_patches], r, r->tmax, 0, &ch)) return 0;
        *t = ch.t; *b1 = ch.b1; *b2 = ch.b2;
        return 1;
    } else {
        Vec3 c[4];
        patch_corners(s, s->patches[p - n_quad].v, c);
        return patch_intersect(c, r, r->tmax, t, b1, b2);
    }
}

/* ALPHA: whether the hit (t, b1, b2) of r with primitive p counts; when it does
   not, the ray spawned at the hit looks for a further hit on p before tmax, and
   (t, b1, b2) become the first one that counts.  0: none counts. */
static int alpha_keep(const Scene *s, const Ray *r, int p, float tmax, float *t, float *b1, float *b2)
{
    const Shape *sh = &s->shapes[bvh_prim_shape(s, p)];
    Ray ri = *r;
    float t0 = 0.0f;                           /* ri starts at r's t0 */
    int k;
    if (!sh->alpha_on) return 1;
    for (k = 0; k < 4; k++) {                  /* a quadric or patch meets a line at most twice */
        HitRecord h;
        SurfacePoint sp;
        float a = sh->alpha, ti;
        h.t = *t - t0; h.prim = p; h.b1 = *b1; h.b2 = *b2; h.inst = -1;
        if (sh->alpha_tex > 0 || p >= s->n_tris) scene_surface_point(s, &ri, &h, &sp);
        if (sh->alpha_tex > 0) a = tex_eval(s->textures, sh->alpha_tex - 1, &sp, 550.0f);
        if (a >= 1.0f || (a > 0.0f && ray_hash01(&ri) <= (double)a)) return *t <= tmax;
        if (p < s->n_tris) return 0;
        ri.o = spawn_origin(&sp, r->d);                /* pbrt-v4: SpawnRay(d) */
        t0 = *t;
        ri.tmax = tmax - t0;
        if (!(ri.tmax > 0.0f) || !prim_hit_again(s, p, &ri, &ti, b1, b2)) return 0;
        *t = t0 + ti;
    }
    return 0;
}

/* The first instance's id: the number of primitives of the other kinds (the
   numbering of the opening comment) */
HOT_INLINE int prim_base(const Scene *s)
{
    return s->n_tris + s->n_spheres + s->n_quadrics + s->n_patches + s->n_curve_pieces;
}

/* The closest hit (any_hit: any hit) of the world ray r with instance i's object,
   traced in object space with tmax = t_best; at_tmax: a hit at t_best itself counts
   (the caller breaks that tie by the instance's id).  Defined after traverse. */
static int instance_hit(const Scene *s, int i, const Ray *r, float t_best, int at_tmax,
                        int any_hit, int avx, HitRecord *h);

/* THE HIT'S FLOOR of a quadric, patch, curve piece or instance (triangles and
   spheres floor their own hits: tri_hit, sphere_hit): the entry distance of the
   box bvhbuild.c gives it */
static float prim_floor(const Scene *s, const RayPre *rp, int p)
{
    float lo[3], hi[3];
    return bvh_prim_box(s, p, lo, hi) ? box_entry(rp, lo, hi) : INFINITY;
}

/* A hit on quadric, patch or curve piece p (n_tris + n_spheres <= p < the
   instances) at t <= t_best, floored (THE HIT'S FLOOR); b1, b2: 0 for a quadric, a
   patch's or a curve piece's (u, v) */
static int shape_hit(const Scene *s, const RayPre *rp, const Ray *r, int p, float t_best,
                     int any_hit, float *t, float *b1, float *b2)
{
    const int n_quad_end = s->n_tris + s->n_spheres + s->n_quadrics;
    const int n_patch_end = n_quad_end + s->n_patches;
    int ok;
    if (p < n_quad_end) {
        ok = quadric_intersect(&s->shapes[s->quadric_shape[p - s->n_tris - s->n_spheres]], r, t_best, t);
        *b1 = *b2 = 0.0f;
    } else if (p < n_patch_end) {
        Vec3 c[4];
        patch_corners(s, s->patches[p - n_quad_end].v, c);
        ok = patch_intersect(c, r, t_best, t, b1, b2);
    } else {
        HitRecord hi;
        ok = curve_intersect(s, &s->curve_pieces[p - n_patch_end], r, t_best, any_hit, &hi);
        if (ok) { *t = hi.t; *b1 = hi.b1; *b2 = hi.b2; }
    }
    if (!ok) return 0;
    *t = floored(*t, prim_floor(s, rp, p));
    return *t <= t_best;
}

float bvh_hit_floor(const Scene *s, int id, const Ray *r)
{
    RayPre rp;
    float lo[3], hi[3];
    if (!ray_prepare(r, &rp) || !ray_prepare_rest(&rp, 0) || !bvh_prim_box(s, id, lo, hi))
        return INFINITY;
    return box_entry(&rp, lo, hi);
}

/* A hit closer than the best so far (or as close, with a smaller id) becomes the
   best: h records it, and boxes are culled against it from now on (an
   instance's hit then names its object's primitive: traverse) */
HOT_INLINE void take_closer(float t, float b1, float b2, int p, float *t_best,
                            int *best_p, HitRecord *h)
{
    *t_best = t;                         /* closer hits only from now on */
    *best_p = p;
    h->t = t; h->prim = p; h->b1 = b1; h->b2 = b2; h->inst = -1;
}

/* traverse's three or more children entered: each goes to top[rank] (with its entry
   distance, for closest-hit rays) and is prefetched; returns their number.  A
   child's rank is the number of children entered that are farther (ties: lower
   slot first), so the nearest ends on top.  The rank is a branch-free count over
   all slots, which costs less than the mispredicted branches of an insertion
   sort.  Shadow rays need no order: rank = arrival.  The AVX2 copy ranks by
   integer keys (push_ranked8): the same order but for entry distances within 8
   ulps. */
HOT_INLINE int push_children(const Bvh *b, const BvhNode *nd, const float *t_enter,
                             unsigned mask, StackEntry *top, int any_hit, int avx)
{
    unsigned m;
    int n = 0;
#if BVH_AVX
    if (avx && !any_hit) return push_ranked8(b, nd, t_enter, mask, top);
#endif
    (void)avx;
    for (m = mask; m != 0; m &= m - 1, n++) {
        const int jj = lowest_bit(m);
        const int rank = any_hit ? n : child_rank(t_enter, mask, jj);
        top[rank].ref = nd->child[jj];
        if (!any_hit) top[rank].t = t_enter[jj];
        prefetch_ref(b, nd->child[jj]);
    }
    return n;
}

/* Walk the tree; any_hit = 1 returns at the first hit (h may be NULL then).
   at_tmax = 1 (the trace of an instance's object, instance_hit) also accepts a hit
   at r->tmax itself, which the caller then weighs by the instance's id; the
   world's trace (at_tmax = 0) excludes the ray's own tmax.
   A stack holds the children still to visit.  At an inner node, the children the ray
   enters are pushed, the nearest last, so that it is popped next (the order only
   saves time: ORDER INDEPENDENCE; shadow rays take them in slot order); a child is
   dropped when popped if a hit closer than its entry distance has been found
   meanwhile.
   Random rays make every data-dependent branch a coin toss that the processor
   mispredicts about half the time, so the children entered are visited by their set
   bits (lowest_bit) and each is put straight into its place by its rank (how many of
   the others entered are farther, counted without branches):
       node_hit_mask:  mask = 0b00101100  t_enter = [ .  .  4.0  1.5  .  2.0  .  . ]
       children 2, 3, 5 entered; ranks (farther ones) 0, 2, 1:
       stack  ... | child 2 (4.0) | child 5 (2.0) | child 3 (1.5) | <- popped next */
HOT_INLINE int traverse(const Bvh *b, const Scene *s, const Ray *r, HitRecord *h, int any_hit,
                        int at_tmax, int avx)
{
    RayPre rp;
    StackEntry stack[BVH_STACK];
    float t_enter[BVH_WIDTH], t_best = r->tmax, t, b1, b2;
    const int no_hit = at_tmax ? INT32_MAX : -1;
    const int n_tris = s->n_tris;      /* the other kinds' bounds only where they are met */
    int sp = 0, best_p = no_hit, ref = 0;
    HitRecord hi;
    if (b->n_nodes == 0 || !(t_best > 0.0f)) return 0;
    if (avx ? !ray_prepare_avx2(b, r, &rp)           /* the same, in 4 lanes */
            : !ray_prepare(r, &rp) || !root_hit(b, &rp) ||
              !ray_prepare_rest(&rp, 1))           /* only now: most rays miss the root */
        return 0;

    for (;;) {
        if (ref >= 0) {
            /* inner node: test the children; one entered: go on with it; several:
               put them on the stack farthest first and go on with the nearest */
            const BvhNode *nd = &b->nodes[ref];
            const unsigned mask = avx ? node_hit8(nd, &rp, t_best, t_enter)
                                      : node_hit_mask(nd, &rp, t_best, t_enter);
            if (mask != 0) {
                const unsigned rest = mask & (mask - 1);
                if (any_hit && (rest & (rest - 1)) == 0) {
                    /* a shadow ray entering one child or two takes no order, so the
                       two cases need no branch between them: the highest bit is the
                       lowest when there is one, and then the slot written above the
                       top is not kept (and the one child is prefetched twice, which
                       costs less than the branch).  Closest-hit rays keep the branch:
                       their two-child case orders, and joined it ran slower
                       (docs/bvh.md) */
                    const int ja = lowest_bit(mask), jb = highest_bit(mask);
                    stack[sp].ref = nd->child[jb];
                    sp += rest != 0;
                    prefetch_ref(b, nd->child[jb]);
                    ref = nd->child[ja];
                    prefetch_ref(b, ref);
                    continue;
                }
                if (rest == 0) {                   /* one child: no stack */
                    ref = nd->child[lowest_bit(mask)];
                    prefetch_ref(b, ref);
                    continue;
                }
                if ((rest & (rest - 1)) == 0) {    /* two (the most common case): */
                    const int ja = lowest_bit(mask), jb = lowest_bit(rest);   /* ja < jb */
                    /* ties: the lower slot (only closest-hit rays come here); b_first
                       is all ones when jb is nearer, and the nearer is picked by XOR
                       through it: a coin toss for random rays, so no branch */
                    const unsigned b_first = 0u - (unsigned)(t_enter[jb] < t_enter[ja]);
                    const int jn = (int)((unsigned)ja ^ (((unsigned)ja ^ (unsigned)jb) & b_first)),
                              jf = ja ^ jb ^ jn;
                    stack[sp].ref = nd->child[jf];  /* the farther waits on the stack */
                    stack[sp].t = t_enter[jf];
                    sp++;
                    prefetch_ref(b, nd->child[jf]);
                    ref = nd->child[jn];
                    prefetch_ref(b, ref);
                    continue;
                }
                /* three or more: in their order on the stack (push_children),
                   the nearest on top */
                sp += push_children(b, nd, t_enter, mask, stack + sp, any_hit, avx);
                ref = stack[--sp].ref;             /* the nearest */
                continue;
            }
        } else {
            /* leaf: test its primitives; tri_hit accepts t <= t_best.  A leaf's
               records are sorted by id, triangles first: when its last is a
               triangle they all are, and (without alpha) a loop of triangle tests
               alone takes them, the general one below does the same for any kind */
            const BvhPrim *q = &b->prims[(~ref) >> 3], *end = q + ((~ref) & 7) + 1;
            if (end[-1].prim < n_tris && s->n_alpha == 0) {
                for (; q < end; q++) {
                    if (!(avx ? tri_hit_avx2(&rp, q->v, t_best, &t, &b1, &b2)   /* a filter first */
                              : tri_hit(&rp, q->v, t_best, &t, &b1, &b2)))
                        continue;
                    if (any_hit) {
                        if (r->tmax > t) return 1;          /* as below */
                        continue;
                    }
                    if (!(t < t_best || q->prim < best_p)) continue;
                    take_closer(t, b1, b2, q->prim, &t_best, &best_p, h);
                }
            } else for (; q < end; q++) {
                const int p = q->prim;
                int ok;
                if (p < n_tris)
                    ok = avx ? tri_hit_avx2(&rp, q->v, t_best, &t, &b1, &b2)   /* a filter first */
                             : tri_hit(&rp, q->v, t_best, &t, &b1, &b2);
                else {
                    const int n_sph_end = n_tris + s->n_spheres, n_base = prim_base(s);
                    if (p < n_sph_end) {
                        ok = sphere_hit(&rp, q->v, t_best, &t); b1 = b2 = 0.0f;
                    } else if (p < n_base) {
                        ok = shape_hit(s, &rp, r, p, t_best, any_hit, &t, &b1, &b2);
                    } else {
                        /* an instance: its object's closest hit, floored by the
                           instance's box; a shadow ray needs only to know that the
                           floor is below tmax and that the object has a hit there */
                        const float te = prim_floor(s, &rp, p);
                        if (!(te <= t_best)) continue;
                        if (any_hit) {
                            if (te < r->tmax && instance_hit(s, p - n_base, r, t_best, 0, 1, avx, &hi))
                                return 1;
                            continue;
                        }
                        if (!instance_hit(s, p - n_base, r, t_best, best_p != no_hit, 0, avx, &hi))
                            continue;
                        ok = 1; t = floored(hi.t, te); b1 = hi.b1; b2 = hi.b2;
                    }
                }
                if (!ok) continue;
                if (s->n_alpha > 0 && p < prim_base(s) && !alpha_keep(s, r, p, t_best, &t, &b1, &b2))
                    continue;                       /* ALPHA: the ray goes on */
                if (any_hit) {
                    if (t < r->tmax) return 1;
                    continue;
                }
                /* the ray's own tmax is excluded (best_p = -1 loses every tie);
                   a tie with the best so far goes to the smaller primitive id */
                if (!(t < t_best || p < best_p)) continue;
                take_closer(t, b1, b2, p, &t_best, &best_p, h);
                if (p >= n_tris && p >= prim_base(s)) { h->prim = hi.prim; h->inst = p - prim_base(s); }
            }
        }
        /* pop the next child that may still hold a hit at t <= t_best (a shadow ray's
           t_best never changes, as it returns at its first hit, and every child on
           its stack passed it when pushed: it neither stores the entry distance nor
           tests it) */
        do {
            if (sp == 0) return best_p != no_hit;
            sp--;
        } while (!any_hit && stack[sp].t > t_best);
        ref = stack[sp].ref;
    }
}

#if BVH_AVX
/* The AVX2 copies of the traversal: the same code (traverse is inlined), compiled for
   AVX2, so that node_hit8 and push_ranked8 inline into it. */
AVX2_STATIC int traverse_avx2_closest(const Bvh *b, const Scene *s,
                                                                 const Ray *r, HitRecord *h)
{
    return traverse(b, s, r, h, 0, 0, 1);
}

AVX2_STATIC int traverse_avx2_any(const Bvh *b, const Scene *s,
                                                             const Ray *r)
{
    return traverse(b, s, r, NULL, 1, 0, 1);
}

AVX2_STATIC int traverse_avx2(const Bvh *b, const Scene *s, const Ray *r,
                                                         HitRecord *h, int any_hit, int at_tmax)
{
    return traverse(b, s, r, h, any_hit, at_tmax, 1);
}
#endif

static int instance_hit(const Scene *s, int i, const Ray *r, float t_best, int at_tmax,
                        int any_hit, int avx, HitRecord *h)
{
    const Instance *in = &s->instances[i];
    Xform tmp;
    Ray ro = instance_ray(instance_xf(s, in, r, &tmp), r);
    ro.tmax = t_best;
#if BVH_AVX
    if (avx) return traverse_avx2(&s->objects[in->object].bvh, s, &ro, h, any_hit, at_tmax);
#endif
    (void)avx;
    return traverse(&s->objects[in->object].bvh, s, &ro, h, any_hit, at_tmax, 0);
}

/* The SSE2 (or scalar) copies, as functions of their own, so that the two queries
   below only choose: with a copy inlined into them, every query paid that copy's
   stack frame (24 instructions a ray) before choosing. */
#if BVH_AVX && (defined(__GNUC__) || defined(__clang__))
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE
#endif
static NOINLINE int traverse_sse_closest(const Bvh *b, const Scene *s, const Ray *r, HitRecord *h)
{
    return traverse(b, s, r, h, 0, 0, 0);
}

static NOINLINE int traverse_sse_any(const Bvh *b, const Scene *s, const Ray *r)
{
    return traverse(b, s, r, NULL, 1, 0, 0);
}

int bvh_intersect(const Bvh *b, const Scene *s, const Ray *r, HitRecord *h)
{
#if BVH_AVX
    if (bvh_cpu_avx2()) return traverse_avx2_closest(b, s, r, h);
#endif
    return traverse_sse_closest(b, s, r, h);
}

int bvh_occluded(const Bvh *b, const Scene *s, const Ray *r)
{
#if BVH_AVX
    if (bvh_cpu_avx2()) return traverse_avx2_any(b, s, r);
#endif
    return traverse_sse_any(b, s, r);
}

int bvh_avx2(void)
{
    return bvh_cpu_avx2();
}

/* The children of node nd that differ in any bit between the scalar slab test and
   rank (m0, te0) and those of the SIMD path (avx: the AVX2 one, else SSE2). */
HOT_INLINE int node_mismatches(const BvhNode *nd, const RayPre *rp, float t_best, int avx)
{
    float te[2][BVH_WIDTH];
    const unsigned m0 = node_hit_mask_scalar(nd, rp, t_best, te[0]);
    const unsigned m1 = avx ? node_hit8(nd, rp, t_best, te[1])
                            : node_hit_mask(nd, rp, t_best, te[1]);
    int j, bad = 0;
    for (j = 0; j < BVH_WIDTH; j++) {
        const int in0 = (m0 >> j) & 1u, in1 = (m1 >> j) & 1u;
        bad += in0 != in1 ||
               memcmp(&te[0][j], &te[1][j], sizeof(float)) != 0;
        if (in0 && in1) {                  /* the order of the children entered */
#if BVH_AVX
            if (avx) bad += child_rank_key(te[0], m0, j) != child_rank_key8(te[1], m1, j);
            else
#endif
            bad += child_rank_scalar(te[0], m0, j) != child_rank(te[1], m1, j);
        }
    }
    return bad;
}

#if BVH_AVX
AVX2_STATIC int node_mismatches_avx2(const BvhNode *nd, const RayPre *rp,
                                                                float t_best)
{
    return node_mismatches(nd, rp, t_best, 1);
}
#endif

/* tri_miss4 against the scalar sign test of tri_edges' U, V, W on the triangle v,
   and against tri_hit itself (a triangle the filter drops must be one tri_hit
   misses); then the whole AVX2 test (tri_hit_avx2: the filter and tri_hit_rest)
   against tri_hit, the verdict and t, b1, b2 bit for bit, with tmax = infinity, at
   the hit's t (a tie counts) and one float below it: 1 on a difference */
#if BVH_AVX
/* 1 when two values differ in any bit (the comparisons below, bit for bit) */
#define BITS_DIFFER(x, y) (memcmp(&(x), &(y), sizeof(x)) != 0)
AVX2_STATIC int tri_filter_mismatch(const RayPre *rp, const float *v)
{
    RayPre r4 = *rp;
    float e[6], z[3], uvw[3], t[2], b1[2], b2[2], tmax = INFINITY;
    int miss, hit[2], k, bad;
    ray_prepare4(&r4);
    tri_edges(rp, v, e, z, uvw);
    miss = ((uvw[0] != 0.0f) & (uvw[1] != 0.0f) & (uvw[2] != 0.0f)) &
           ((uvw[0] < 0.0f) | (uvw[1] < 0.0f) | (uvw[2] < 0.0f)) &
           ((uvw[0] > 0.0f) | (uvw[1] > 0.0f) | (uvw[2] > 0.0f));
    bad = tri_miss4(&r4, v) != miss;
    for (k = 0; k < 3; k++) {
        hit[0] = tri_hit(rp, v, tmax, &t[0], &b1[0], &b2[0]);
        hit[1] = tri_hit_avx2(&r4, v, tmax, &t[1], &b1[1], &b2[1]);
        bad |= (k == 0 && miss && hit[0]) ||      /* a dropped triangle tri_hit hits */
               hit[0] != hit[1] ||
               (hit[0] && (BITS_DIFFER(t[0], t[1]) || BITS_DIFFER(b1[0], b1[1]) ||
                           BITS_DIFFER(b2[0], b2[1])));
        if (!hit[0]) break;
        tmax = k == 0 ? t[0] : nextafterf(t[0], 0.0f);   /* at the hit, then just below */
    }
    return bad;
}
#endif

int bvh_tri_filter_mismatches(const Bvh *b, const Scene *s, const Ray *r, int *tested)
{
    RayPre rp;
    int i, bad = 0;
    if (!bvh_cpu_avx2() || !ray_prepare(r, &rp) || !ray_prepare_rest(&rp, 0)) return 0;
    for (i = 0; i < b->n_prims; i++) {
        if (b->prims[i].prim >= s->n_tris) continue;
#if BVH_AVX
        bad += tri_filter_mismatch(&rp, b->prims[i].v);
#endif
        ++*tested;
    }
    return bad;
}

/* ray_prepare_avx2 against the scalar ray_prepare, root_hit, ray_prepare_rest and
   ray_prepare4: the verdict, and every field the AVX2 traversal reads, bit for bit
   (1 on a difference) */
#if BVH_AVX
AVX2_STATIC int prepare_mismatch(const Bvh *b, const Ray *r)
{
    RayPre c, v;
    int ok_c, ok_v, a, bad;
    memset(&c, 0, sizeof c);
    memset(&v, 0, sizeof v);
    ok_c = ray_prepare(r, &c) && root_hit(b, &c) && ray_prepare_rest(&c, 0);
    ok_v = ray_prepare_avx2(b, r, &v);
    if (ok_c != ok_v) return 1;
    if (!ok_c) return 0;
    ray_prepare4(&c);
    bad = BITS_DIFFER(c.o, v.o) | BITS_DIFFER(c.d, v.d) | BITS_DIFFER(c.inv_d, v.inv_d) |
          (c.ord != v.ord) | BITS_DIFFER(c.S, v.S) | BITS_DIFFER(c.o_k, v.o_k) |
          BITS_DIFFER(c.sx4, v.sx4) | BITS_DIFFER(c.sy4, v.sy4) |
          BITS_DIFFER(c.d_k, v.d_k) | BITS_DIFFER(c.inv_k, v.inv_k);
    for (a = 0; a < 3; a++)
        bad |= BITS_DIFFER(c.o_ax[a], v.o_ax[a]) |
               BITS_DIFFER(c.ninv_ax[a], v.ninv_ax[a]) |
               BITS_DIFFER(c.o8[a], v.o8[a]) | BITS_DIFFER(c.ninv8[a], v.ninv8[a]);
    return bad;
}
#undef BITS_DIFFER
#endif

int bvh_simd_mismatches(const Bvh *b, const Ray *r, float t_best, int *lanes)
{
    RayPre rp;
    int i, bad = 0;
    const int avx = bvh_cpu_avx2();
    unsigned m;
    for (m = 1; m < 256; m++)
        bad += (lowest_bit(m) != lowest_bit_portable(m)) + (highest_bit(m) != highest_bit_portable(m)) +
               ((m >> highest_bit_portable(m)) != 1u);
#if BVH_AVX
    if (avx && b->n_nodes > 0) bad += prepare_mismatch(b, r);
#endif
    if (!ray_prepare(r, &rp) || !ray_prepare_rest(&rp, 1)) return bad;
#if BVH_AVX
    if (avx) ray_prepare4(&rp);
#endif
    for (i = 0; i < b->n_nodes; i++) {
        bad += node_mismatches(&b->nodes[i], &rp, t_best, 0);
        *lanes += BVH_WIDTH;
#if BVH_AVX
        if (avx) {
            bad += node_mismatches_avx2(&b->nodes[i], &rp, t_best);
            *lanes += BVH_WIDTH;
        }
#endif
    }
    (void)avx;
    return bad;
}
