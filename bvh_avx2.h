/* bvh_avx2.h - the AVX2 kernels of bvh.c's traversal: private to bvh.c, which
   includes it once, after the scalar and SSE2 kernels they mirror (RayPre, the slab
   test, child_rank, tri_hit: each AVX2 kernel does their operations in their order,
   so every result is the same to the bit, and the tests compare them).

     node_hit8          the slab test of all eight children in one 8-lane pass
     push_ranked8       three or more children entered, ranked by integer keys
     ray_prepare_avx2   the ray's precomputation and the root box's test, in 4 lanes
     tri_hit_avx2       the triangle test: a 4-lane filter (tri_lanes, tri_mixed),
                        then tri_hit_rest from the filter's own lanes
     bvh_cpu_avx2       whether the processor runs them (asked once per query)

   Without AVX2 (tcc, -DSPECNEE_NO_AVX, -DSPECNEE_NO_SIMD) the names fall back to
   the SSE2 or scalar kernels, and the AVX2 copy of the traversal is not compiled.
   docs/bvh.md has the figures of each. */
#ifndef SPECNEE_BVH_AVX2_H
#define SPECNEE_BVH_AVX2_H
#include "specnee.h"   /* its types (bvh.c has included it already; alone, a header
                          that names what it needs) */
#if BVH_AVX
/* node_hit_mask_scalar for all 8 children in one pass of 8-lane AVX: node_hit4's
   operations, lane for lane (_mm256_max_ps and _mm256_min_ps treat a NaN as
   _mm_max_ps and _mm_min_ps do; _CMP_LE_OS is _mm_cmple_ps's predicate).  A row of
   8 planes is 32 bytes, 32-byte aligned (nodes on 64 bytes), one aligned load.  The
   ray's operands come broadcast from RayPre (o8, ninv8: made once a ray, read from
   memory at each node, so no register holds them across the leaves). */
AVX2_FN unsigned node_hit8(const BvhNode *nd, const RayPre *rp, float t_best,
                           float *t_enter)
{
    const float *box = nd->box[0];
    const __m256 o0 = rp->o8[0], i0 = rp->ninv8[0];
    const __m256 o1 = rp->o8[1], i1 = rp->ninv8[1];
    const __m256 o2 = rp->o8[2], i2 = rp->ninv8[2];
    const __m256 tn0 = _mm256_mul_ps(_mm256_sub_ps(o0, _mm256_load_ps(box + rp->ord->plane[0])), i0);
    const __m256 tf0 = _mm256_mul_ps(_mm256_sub_ps(o0, _mm256_load_ps(box + rp->ord->plane[4])), i0);
    const __m256 tn1 = _mm256_mul_ps(_mm256_sub_ps(o1, _mm256_load_ps(box + rp->ord->plane[1])), i1);
    const __m256 tf1 = _mm256_mul_ps(_mm256_sub_ps(o1, _mm256_load_ps(box + rp->ord->plane[5])), i1);
    const __m256 tn2 = _mm256_mul_ps(_mm256_sub_ps(o2, _mm256_load_ps(box + rp->ord->plane[2])), i2);
    const __m256 tf2 = _mm256_mul_ps(_mm256_sub_ps(o2, _mm256_load_ps(box + rp->ord->plane[6])), i2);
    __m256 tn = _mm256_max_ps(tn0, _mm256_setzero_ps()), tf = _mm256_min_ps(tf0, _mm256_set1_ps(INFINITY));
    tn = _mm256_max_ps(tn1, tn);  tf = _mm256_min_ps(tf1, tf);
    tn = _mm256_max_ps(tn2, tn);  tf = _mm256_min_ps(tf2, tf);
    _mm256_storeu_ps(t_enter, tn);
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(
        tn, _mm256_min_ps(_mm256_mul_ps(tf, _mm256_set1_ps(FAR_SCALE)), _mm256_set1_ps(t_best)), _CMP_LE_OS));
}

/* The ranks of the AVX2 copy (closest-hit rays), by integer keys: a child's key is the bits of its
   entry distance with the lowest three replaced by its slot,
       key_j = (bits(t_enter[j]) & ~7) | j,
   and its rank the number of entered children of larger key.  An entry distance is
   never negative (folded from +0, NaNs skipped: node_hit8), and the bits of floats
   >= +0 order as the floats do, so a larger key never belongs to a nearer child
   except between two distances within 8 ulps, ordered by slot instead; the keys
   are distinct, so the ranks are 0 .. n-1.  Only speed depends on the order
   (ORDER INDEPENDENCE); the stack keeps the exact distance, which the pop culls
   by.  One integer compare a child, where child_rank's order (ties by slot) takes
   two float compares and the mask of the lower slots: 3 % of the closest hit's
   time (docs/bvh.md).  child_rank_key is the scalar definition (the test
   bvh_simd_matches_scalar compares the two). */
HOT_INLINE uint32_t child_key(const float *t_enter, int j)
{
    uint32_t bits;
    memcpy(&bits, &t_enter[j], sizeof bits);
    return (bits & ~7u) | (uint32_t)j;
}

HOT_INLINE int child_rank_key(const float *t_enter, unsigned mask, int jj)
{
    const uint32_t kj = child_key(t_enter, jj);
    int j, rank = 0;
    for (j = 0; j < BVH_WIDTH; j++)
        rank += (int)((mask >> j) & 1u) & (child_key(t_enter, j) > kj);
    return rank;
}

/* the keys of the eight slots, in AVX2 lanes */
AVX2_FN __m256i child_keys8(const float *t_enter)
{
    return _mm256_or_si256(
        _mm256_and_si256(_mm256_loadu_si256((const __m256i *)t_enter), _mm256_set1_epi32(~7)),
        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

/* the rank of the child of key kj: the entered lanes of larger key, counted by the
   population-count instruction (every AVX2 processor has it; the dispatch asks).
   AVX2 compares signed 32-bit lanes: a key's top bit is a float's sign bit, 0
   here, so signed and unsigned order agree. */
AVX2_FN int rank_by_keys8(__m256i keys, int32_t kj, unsigned mask)
{
    return __builtin_popcount((unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(
               _mm256_cmpgt_epi32(keys, _mm256_set1_epi32(kj)))) & mask);
}

/* traverse's three or more children entered, closest-hit rays, in the AVX2 copy:
   each child to top[rank] with its entry distance (and prefetched); returns their
   number */
AVX2_FN int push_ranked8(const Bvh *b, const BvhNode *nd, const float *t_enter,
                         unsigned mask, StackEntry *top)
{
    const __m256i keys = child_keys8(t_enter);
    int32_t key[BVH_WIDTH];
    unsigned m;
    int n = 0;
    _mm256_storeu_si256((__m256i *)key, keys);
    for (m = mask; m != 0; m &= m - 1, n++) {
        const int jj = lowest_bit(m), rank = rank_by_keys8(keys, key[jj], mask);
        top[rank].ref = nd->child[jj];
        top[rank].t = t_enter[jj];
        prefetch_ref(b, nd->child[jj]);
    }
    return n;
}

/* the rank push_ranked8 gives child jj (for the test) */
AVX2_FN int child_rank_key8(const float *t_enter, unsigned mask, int jj)
{
    const __m256i keys = child_keys8(t_enter);
    int32_t key[BVH_WIDTH];
    _mm256_storeu_si256((__m256i *)key, keys);
    return rank_by_keys8(keys, key[jj], mask);
}

/* The AVX2 copy's per-ray operands (tri_miss4's, node_hit8's) from the scalar
   precomputation (ray_prepare_avx2 makes them itself; the tests compare the two) */
AVX2_FN void ray_prepare4(RayPre *rp)
{
    int a;
    rp->o_k = _mm_setr_ps(rp->o[rp->ord->k[0]], rp->o[rp->ord->k[1]], rp->o[rp->ord->k[2]], 0.0f);
    rp->d_k = _mm_setr_ps(rp->d[rp->ord->k[0]], rp->d[rp->ord->k[1]], rp->d[rp->ord->k[2]], 0.0f);
    rp->inv_k = _mm_setr_ps(rp->inv_d[rp->ord->k[0]], rp->inv_d[rp->ord->k[1]],
                            rp->inv_d[rp->ord->k[2]], rp->inv_d[3]);
    rp->sx4 = _mm_set1_ps(rp->S[0]);
    rp->sy4 = _mm_set1_ps(rp->S[1]);
    for (a = 0; a < 3; a++) {
        rp->o8[a] = _mm256_set1_ps(rp->o_ax[a]);
        rp->ninv8[a] = _mm256_set1_ps(rp->ninv_ax[a]);
    }
}

/* ray_prepare, root_hit, ray_prepare_rest and ray_prepare4 in one, with o, d and 1/d
   as 4-lane vectors (lane 3: 0, 0, +inf): 0 for a ray that is not finite, misses
   the root box or has a direction too short to use, as the scalar three return
   (traverse); else RayPre filled with the same bits (the test
   bvh_simd_matches_scalar compares them).  Each lane does the scalar code's
   operation: 1 / d is +-infinity for d = +-0 as inv_axis makes it; the root box's
   near plane is picked by d's sign bit (blendv reads the sign bit, as signbit does);
   its distances are folded in the scalar order (_mm_max_ss(x, acc) is
   "x > acc ? x : acc"); kz is the lowest axis of largest |d| as in
   ray_prepare_rest (a2 > a0 and a2 > a1 gives 2, else a1 > a0 gives 1); the shear
   divides the same two floats. */
AVX2_FN int ray_prepare_avx2(const Bvh *b, const Ray *r, RayPre *rp)
{
    static const unsigned char kz_of[8] = {0, 1, 0, 1, 0, 1, 2, 2};  /* by (a1>a0, a2>a0, a2>a1) */
    const __m128 keep3 = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    const __m128 o = _mm_and_ps(_mm_loadu_ps(&r->o.x), keep3);     /* o.x o.y o.z (d.x) */
    const __m128 d = _mm_and_ps(_mm_loadu_ps(&r->d.x), keep3);     /* d.x d.y d.z (tmax) */
    const __m128 zero = _mm_setzero_ps();
    const __m128 bmin = _mm_loadu_ps(b->bmin);                          /* lane 3: bmax[0] */
    const __m128 bmax = _mm_permute_ps(_mm_loadu_ps(&b->bmin[2]), _MM_SHUFFLE(3, 3, 2, 1));
    __m128 inv, tn, tf, absd, dk, sh;
    __m128i kv;
    const RayOrder *ord;
    int negs, gts;
    /* all six finite: x - x is 0 for a finite x, NaN otherwise (ray_prepare) */
    if (_mm_movemask_ps(_mm_cmpeq_ps(_mm_add_ps(_mm_sub_ps(o, o), _mm_sub_ps(d, d)), zero)) != 15)
        return 0;
    inv = _mm_div_ps(_mm_set1_ps(1.0f), d);
    negs = _mm_movemask_ps(d);                    /* bit a: the sign bit of d_a */
    /* root_hit: near plane (lo for d >= 0, hi for d < 0) and far plane an axis */
    tn = _mm_mul_ps(_mm_sub_ps(_mm_blendv_ps(bmin, bmax, d), o), inv);
    tf = _mm_mul_ps(_mm_sub_ps(_mm_blendv_ps(bmax, bmin, d), o), inv);
    {
        __m128 n = _mm_max_ss(tn, zero), f = _mm_min_ss(tf, _mm_set_ss(INFINITY));
        n = _mm_max_ss(_mm_permute_ps(tn, 1), n);  f = _mm_min_ss(_mm_permute_ps(tf, 1), f);
        n = _mm_max_ss(_mm_permute_ps(tn, 2), n);  f = _mm_min_ss(_mm_permute_ps(tf, 2), f);
        if (!(_mm_cvtss_f32(n) <= _mm_cvtss_f32(f) * FAR_SCALE)) return 0;
    }
    /* ray_prepare_rest: kz, then the table of the ray's case */
    absd = _mm_andnot_ps(_mm_set1_ps(-0.0f), d);
    if (_mm_movemask_ps(_mm_cmpge_ps(absd, _mm_set1_ps(FLT_MIN))) == 0) return 0;
    gts = _mm_movemask_ps(_mm_cmpgt_ps(_mm_permute_ps(absd, _MM_SHUFFLE(3, 2, 2, 1)),
                                       _mm_permute_ps(absd, _MM_SHUFFLE(3, 1, 0, 0)))) & 7;
    ord = &ray_orders[kz_of[gts] * 8 + negs];
    _mm_storeu_ps(rp->o, o);
    _mm_storeu_ps(rp->d, d);
    _mm_storeu_ps(rp->inv_d, inv);
    rp->ord = ord;
    kv = _mm_loadu_si128((const __m128i *)ord->axis);
    _mm_storeu_ps(rp->o_ax, _mm_permutevar_ps(o, kv));
    _mm_storeu_ps(rp->ninv_ax, _mm_xor_ps(_mm_permutevar_ps(inv, kv), _mm_set1_ps(-0.0f)));
    rp->o8[0] = _mm256_set1_ps(rp->o_ax[0]); rp->ninv8[0] = _mm256_set1_ps(rp->ninv_ax[0]);
    rp->o8[1] = _mm256_set1_ps(rp->o_ax[1]); rp->ninv8[1] = _mm256_set1_ps(rp->ninv_ax[1]);
    rp->o8[2] = _mm256_set1_ps(rp->o_ax[2]); rp->ninv8[2] = _mm256_set1_ps(rp->ninv_ax[2]);
    kv = _mm_loadu_si128((const __m128i *)ord->k);
    rp->o_k = _mm_permutevar_ps(o, kv);                            /* o_kx o_ky o_kz 0 */
    dk = _mm_permutevar_ps(d, kv);                                  /* d_kx d_ky d_kz 0 */
    rp->d_k = dk;
    rp->inv_k = _mm_permutevar_ps(inv, kv);                        /* 1/d likewise, +inf */
    sh = _mm_div_ps(dk, _mm_permute_ps(dk, _MM_SHUFFLE(2, 2, 2, 2)));   /* Sx Sy 1 0 */
    rp->sx4 = _mm_permute_ps(sh, _MM_SHUFFLE(0, 0, 0, 0));
    rp->sy4 = _mm_permute_ps(sh, _MM_SHUFFLE(1, 1, 1, 1));
    _mm_storeu_ps(rp->S, _mm_blend_ps(_mm_blend_ps(sh, zero, 12), _mm_permutevar_ps(inv, kv), 4));  /* Sx Sy Sz 0 */
    return 1;
}

/* tri_hit's steps 1 to 3 with the three vertices side by side, as a filter: 1 where
   tri_hit returns 0 at its sign test (U, V, W of mixed signs, none 0 in float), else
   0 (then tri_hit decides).  A vertex is loaded as 4 floats (C from v + 5, so that no
   load passes v[8]) and put in the order (kx, ky, kz) by a variable permute; the
   three are then turned into X = (A_x, B_x, C_x), Y and Z alike, and every lane
   does tri_hit's operations in tri_hit's order:
       (A_x, A_y, A_z) = (v_kx - o_kx, v_ky - o_ky, v_kz - o_kz)  (B and C alike)
       (Ax, Bx, Cx)    = X - Sx Z,   (Ay, By, Cy) = Y - Sy Z
       (V, W, U)       = (Ax, Bx, Cx) (Cy, Ay, By) - (Ay, By, Cy) (Cx, Ax, Bx)
   so U, V and W are tri_hit's to the bit, and so is the filter's verdict (a NaN is
   neither < 0 nor > 0 in either).  Most triangles a ray is tested against end at
   the sign test (85 % on tools/bench_count's rays); the rest, and the rays on an
   edge in float, go through tri_hit itself. */
#define TRI_MIXED UINT64_C(0x2040e10325400)
typedef struct { __m128 X, Y, Z, UVW; } TriLanes;   /* tri_lanes' vectors, below */

AVX2_FN TriLanes tri_lanes(const RayPre *rp, const float *v)
{
    TriLanes l;
    const __m128 A_ = _mm_sub_ps(_mm_permutevar_ps(_mm_loadu_ps(v), _mm_loadu_si128((const __m128i *)rp->ord->k)), rp->o_k);
    const __m128 B_ = _mm_sub_ps(_mm_permutevar_ps(_mm_loadu_ps(v + 3), _mm_loadu_si128((const __m128i *)rp->ord->k)), rp->o_k);
    const __m128 C_ = _mm_sub_ps(_mm_permutevar_ps(_mm_loadu_ps(v + 5), _mm_loadu_si128((const __m128i *)(rp->ord->k + 4))), rp->o_k);
    /* side by side: X = (A_x, B_x, C_x), Y = (A_y, B_y, C_y), Z = (A_z, B_z, C_z) */
    const __m128 AB = _mm_unpacklo_ps(A_, B_);                            /* Ax Bx Ay By */
    const __m128 ABz = _mm_unpackhi_ps(A_, B_);                           /* Az Bz 0 0 */
    const __m128 X_ = _mm_shuffle_ps(AB, C_, _MM_SHUFFLE(0, 0, 1, 0));
    const __m128 Y_ = _mm_shuffle_ps(AB, C_, _MM_SHUFFLE(1, 1, 3, 2));
    l.Z = _mm_shuffle_ps(ABz, C_, _MM_SHUFFLE(2, 2, 1, 0));               /* lane 3: C_z */
    /* shear: x - Sx z, y - Sy z (lane 3: C's again) */
    l.X = _mm_sub_ps(X_, _mm_mul_ps(rp->sx4, l.Z));
    l.Y = _mm_sub_ps(Y_, _mm_mul_ps(rp->sy4, l.Z));
    /* (V, W, U) = (Ax, Bx, Cx) (Cy, Ay, By) - (Ay, By, Cy) (Cx, Ax, Bx): each tri_hit's
       products in tri_hit's order, only in other lanes (lane 3: Cx Cy - Cy Cx) */
    l.UVW = _mm_sub_ps(_mm_mul_ps(l.X, _mm_permute_ps(l.Y, _MM_SHUFFLE(3, 1, 0, 2))),
                       _mm_mul_ps(l.Y, _mm_permute_ps(l.X, _MM_SHUFFLE(3, 1, 0, 2))));
    return l;
}

/* The filter's verdict on tri_lanes' edge functions.  Mixed signs, none 0: with
   le = the lanes <= 0 and ge = the lanes >= 0 (a NaN in neither), the zeros are
   le & ge, and without them the lanes < 0 are le and those > 0 ge; MIXED has bit
   le | ge << 3 set where le & ge = 0, le != 0 and ge != 0 (its 18 such patterns), so
   one shift reads the verdict. */
AVX2_FN int tri_mixed(__m128 UVW)
{
    const __m128 zero = _mm_setzero_ps();
    const unsigned le = (unsigned)_mm_movemask_ps(_mm_cmple_ps(UVW, zero)) & 7u;
    const unsigned ge = (unsigned)_mm_movemask_ps(_mm_cmpge_ps(UVW, zero)) & 7u;
    return (int)((TRI_MIXED >> (le | ge << 3)) & 1u);   /* mixed signs: outside */
}

AVX2_FN int tri_miss4(const RayPre *rp, const float *v)
{
    return tri_mixed(tri_lanes(rp, v).UVW);
}

/* tri_box_entry in four lanes, from the vertices as tri_lanes reads them: the
   lanes (kx, ky, kz) of A_ = A - o, B_ and C_; their smallest and largest, the
   larger where d < 0 (blendv reads d's sign bit, as the slab test's choice of hi
   rows does); times 1/d; then the three folded from 0 with "x > acc ? x : acc"
   (_mm_max_ss).  The same float as tri_box_entry: rounding is monotonic, so the
   smallest of fl(v - o) is fl(smallest v - o); (plane - o) * (1/d) is the slab
   test's (o - plane) * (-1/d) (THE SLAB TEST); and a maximum folded from 0 that
   skips NaNs does not depend on the order of the axes. */
AVX2_FN float tri_box_entry4(const RayPre *rp, const float *v)
{
    const __m128i k = _mm_loadu_si128((const __m128i *)rp->ord->k);
    const __m128 A_ = _mm_sub_ps(_mm_permutevar_ps(_mm_loadu_ps(v), k), rp->o_k);
    const __m128 B_ = _mm_sub_ps(_mm_permutevar_ps(_mm_loadu_ps(v + 3), k), rp->o_k);
    const __m128 C_ = _mm_sub_ps(_mm_permutevar_ps(_mm_loadu_ps(v + 5),
                                 _mm_loadu_si128((const __m128i *)(rp->ord->k + 4))), rp->o_k);
    const __m128 lo = _mm_min_ps(A_, _mm_min_ps(B_, C_)), hi = _mm_max_ps(A_, _mm_max_ps(B_, C_));
    const __m128 tk = _mm_mul_ps(_mm_blendv_ps(lo, hi, rp->d_k), rp->inv_k);   /* lane 3 unused */
    __m128 te = _mm_max_ss(tk, _mm_setzero_ps());
    te = _mm_max_ss(_mm_permute_ps(tk, 1), te);
    te = _mm_max_ss(_mm_permute_ps(tk, 2), te);
    return _mm_cvtss_f32(te);
}

/* tri_hit for the triangles the filter lets through (15 %), from the filter's own
   lanes: steps 4 and 5 of tri_hit, each float as tri_hit computes it.  U, V, W are
   lanes 2, 0, 1 of UVW; det = (U + V) + W and T = (U Az + V Bz) + W Cz as C
   evaluates tri_hit's sums; the error bound reads only the largest magnitudes of
   the sheared x, y, z and of U, V, W, which the lanes give exactly (a maximum does
   not round, and lane 3 repeats C or is 0).  A lane of U, V, W that is 0 goes to
   tri_hit itself (its edge functions in double).  A call, not inlined: inlined, its
   operands would be kept ready at every leaf. */
AVX2_NOINLINE int tri_hit_rest(const RayPre *rp, const float *v, __m128 X, __m128 Y,
    __m128 Z, __m128 UVW, float tmax, float *t_out, float *b1_out, float *b2_out)
{
    const __m128 zero = _mm_setzero_ps(), sign = _mm_set1_ps(-0.0f);
    __m128 Zs, m_xy, m_ze, m;
    float U, V, W, Az, Bz, Cz, det, T, inv_det, t, mx[4];
    if ((_mm_movemask_ps(_mm_cmpeq_ps(UVW, zero)) & 7) != 0)
        return tri_hit(rp, v, tmax, t_out, b1_out, b2_out);   /* on an edge in float */
    V = _mm_cvtss_f32(UVW);
    W = _mm_cvtss_f32(_mm_permute_ps(UVW, 1));
    U = _mm_cvtss_f32(_mm_permute_ps(UVW, 2));
    det = (U + V) + W;                             /* as C evaluates U + V + W */
    if (det == 0.0f) return 0;                     /* edge-on or degenerate triangle */
    Zs = _mm_mul_ps(_mm_set1_ps(rp->S[2]), Z);   /* Az Bz Cz (Cz): S_z z */
    Az = _mm_cvtss_f32(Zs);
    Bz = _mm_cvtss_f32(_mm_permute_ps(Zs, 1));
    Cz = _mm_cvtss_f32(_mm_permute_ps(Zs, 2));
    T = (U * Az + V * Bz) + W * Cz;
    if (det < 0.0f ? T >= 0.0f : T <= 0.0f) return 0;   /* behind the origin */
    inv_det = 1.0f / det;
    t = T * inv_det;
    if (!(t > 0.0f && tmax >= t)) return 0;         /* a tie counts, as in tri_hit */
    /* the largest |x|, |y|, |z|, |e| of the three, four lanes at a time */
    m_xy = _mm_max_ps(_mm_unpacklo_ps(_mm_andnot_ps(sign, X), _mm_andnot_ps(sign, Y)),
                      _mm_unpackhi_ps(_mm_andnot_ps(sign, X), _mm_andnot_ps(sign, Y)));
    m_ze = _mm_max_ps(_mm_unpacklo_ps(_mm_andnot_ps(sign, Zs), _mm_andnot_ps(sign, UVW)),
                      _mm_unpackhi_ps(_mm_andnot_ps(sign, Zs), _mm_andnot_ps(sign, UVW)));
    m = _mm_max_ps(_mm_movelh_ps(m_xy, m_ze), _mm_movehl_ps(m_ze, m_xy));
    _mm_storeu_ps(mx, m);                          /* max x, max y, max z, max e */
    if (t <= t_error_bound_max(mx[0], mx[1], mx[2], mx[3], inv_det)) return 0;
    {                                              /* the hit's floor, as in tri_hit */
        t = floored(t, tri_box_entry4(rp, v));
        if (!(tmax >= t)) return 0;
    }
    *t_out = t;
    *b1_out = V * inv_det;
    *b2_out = W * inv_det;
    return 1;
}

/* tri_hit in the AVX2 copy: the filter, then tri_hit_rest */
AVX2_FN int tri_hit_avx2(const RayPre *rp, const float *v,
    float tmax, float *t_out, float *b1_out, float *b2_out)
{
    const TriLanes l = tri_lanes(rp, v);
    /* 15 % pass the filter: UNLIKELY keeps the call's register saves off the
       common path (920 -> 903 instructions a box-hitting ray, docs/bvh.md) */
    return UNLIKELY(!tri_mixed(l.UVW)) &&  /* the lanes go in registers, a struct would not */
           tri_hit_rest(rp, v, l.X, l.Y, l.Z, l.UVW, tmax, t_out, b1_out, b2_out);
}

/* whether this processor (and its operating system) runs the AVX2 copies */
static int bvh_cpu_avx2(void)
{
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
}
#else
#define node_hit8 node_hit_mask
#define tri_hit_avx2 tri_hit
#define ray_prepare4(rp) ((void)(rp))
#define ray_prepare_avx2(b, r, rp) 0
#define bvh_cpu_avx2() 0
#endif
#endif /* SPECNEE_BVH_AVX2_H */
