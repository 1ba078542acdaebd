/* lighttree.c - the light tree: NEE's choice among many emitters in O(log n).

   Exported (specnee.h section 11, for lights.c only): light_tree_build/free,
   light_tree_select, light_tree_pmf, light_tree_simd_check, light_tree_bytes;
   and the build's helpers that lights.c shares: tri_area, sort_by_axis,
   longest_axis.

   Conty Estevez and Kulla, "Importance Sampling of Many Lights with Adaptive
   Tree Splitting", HPG 2018; pbrt-v4's BVHLightSampler and LightBounds (pbrt
   book 4th ed. section 12.6.3); written here from the equations.  Used by the
   strategies tree and spectral-tree: light_sampler_build (lights.c) makes the
   pieces (whole emitters, or clusters of a large emissive mesh) and builds
   this tree over them; light_select and light_select_pmf hand it the context.

   A binary tree over the pieces' boxes, built top-down by the surface-area-
   orientation cost, then collapsed into a 4-wide tree (a node's children are
   the binary node's grandchildren) that the walk reads.  Each child stores a
   bounding sphere (radius rho_k), an orientation cone (axis a_k, theta_o,
   theta_e), its power Phi and its power per 5 nm bin (from 300 nm up:
   fluorescence excites below the sampled range).  The importance (THEORY (5a))
   of child k at a shading point p with normal n:
       imp_k = Phi_c cos(theta') cos(theta_i') / d^2
   with Phi_c = Phi (tree) or the power in the alive wavelengths' bins
   (spectral-tree); inside the bounding sphere imp_k = Phi_c / max(d, rho_k/4)^2,
   and imp_k = 0 "behind the box" (node_behind).  The walk goes to child k with
   probability imp_k / sum_k' imp_k' (the code's arrays I[] hold imp_k, S their
   sum); the pmf of a piece follows its trail (the children
   taken, two bits a level) through the same function, so select and pmf cannot
   disagree.  Lights without a position (infinite, distant) stand beside the
   tree: each has probability 1 / (n_beside + 1), the tree the last share.

   The derivations (the importance bound and its square-root form, behind the
   box, the cone measure M_omega of the build cost, the 4-wide layout, the
   depth bound): docs/lighttree.md, "How it works"; the measurements behind
   each choice: the same file. */
#include "specnee.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>
/* The light tree evaluates a node's four children at once with SSE2 where the
   compiler offers it (every x86-64 gcc and clang); elsewhere (tcc, other
   processors, or -DSPECNEE_NO_SIMD) with the scalar code it mirrors, to the bit
   (the test lighttree_simd_matches_scalar). */
#if defined(__SSE2__) && !defined(__TINYC__) && !defined(SPECNEE_NO_SIMD)
#define TREE_SIMD 1
#include <emmintrin.h>
#else
#define TREE_SIMD 0
#endif

/* ------------------------------------------------------------------ nodes */

/* A node of the binary tree that the build makes before it is
   collapsed into 4-wide nodes.  Depth-first order: the first child of an
   interior node i is node i + 1, the second is nodes[i].second. */
typedef struct {
    float c[3], r;             /* centre and radius rho of the box's bounding sphere */
    float axis[3];             /* orientation cone: unit axis a ... */
    float cos_o, sin_o, cos_e; /* ... theta_o, cos theta_e (cos_o = -1: every direction) */
    float power;               /* radiant power over the sampled range */
    float behind, slack;       /* nothing below lights p when (p - c) . axis <=
                                  behind - slack L (p behind the plane that bounds the
                                  box on the side its light cannot reach); behind =
                                  -inf where there is no such plane (node_behind) */
    int32_t second;            /* interior: index of the second child; leaf: -1 - piece */
    int32_t twosided;
} TreeNode;

/* A node of the light tree that the walk reads: up to four
   children, each described in one lane of these arrays (structure of arrays,
   so that the four importances are computed side by side).  A lane that holds
   no child has power 0, so its importance is 0 and it is never taken. */
typedef struct {
    float cx[4], cy[4], cz[4], r[4];   /* each child's bounding sphere (r: rho_k) */
    float ax[4], ay[4], az[4];         /* its orientation cone: unit axis a_k ... */
    float cos_o[4], sin_o[4];          /* ... theta_o ... */
    float cos_e[4];                    /* ... and cos theta_e */
    float behind[4], slack[4];         /* TreeNode.behind and .slack */
    int32_t twosided[4];
    int32_t child[4];                  /* >= 0: a node; < 0: -1 - piece */
} TreeNode4;                           /* 224 bytes */

struct LightTree {
    int spectral;              /* spectral-tree: Phi_c from the bins of the context */
    int throughput_weighted;   /* ... weighted by the path throughput */
    float lo_nm;               /* the sampled range's lower end (the bins' origin) */
    int n_pieces;              /* all the sampler's pieces */
    uint64_t *trail;           /* per piece: lane taken at 4-wide depth d in bits 2d, 2d + 1 */
    int *depth;                /* per piece: levels from the root to its leaf (>= 1 in the
                                  tree, 0 beside it) */
    int n_inf;                 /* lights beside the tree (infinite, distant) */
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
                                  12 for 360-830 (fluorescence excitation) */
    float *leaf_power;         /* n_pieces: a piece's power over the sampled range, the
                                  sum of its bins b >= nb_uv (piece_bins; while building) */
    float *quad_bin;           /* nb x n_nodes4 x 4: for bin b and node i, the power of
                                  node i's four children side by side (bin-major: the
                                  entries of one bin, which a walk reads, lie together) */
    float *root_bin;           /* nb: the root's power per bin */
    float behind_margin;       /* 1e-5 (1 + the scene's largest |coordinate|): what
                                  TreeNode.behind gives away for round-off */
};

/* Lights without a position - infinite and distant lights - stand beside the
   light tree, each with a share of its own. */
static int beside_tree(const Emitter *em) { return em->inf || em->delta.type == DELTA_DISTANT; }

/* ------------------------------------------------------------------ shared with lights.c */

/* The area of scene triangle t: lights.c weighs an emitter's triangles by it,
   the build here bounds the clusters' normals with it. */
double tri_area(const Scene *s, int t)
{
    const Triangle *tr = &s->tris[t];
    Vec3 e1 = v3_sub(s->P[tr->v[1]], s->P[tr->v[0]]);
    Vec3 e2 = v3_sub(s->P[tr->v[2]], s->P[tr->v[0]]);
    return 0.5 * (double)v3_len(v3_cross(e1, e2));
}

static int cmp_key(const void *pa, const void *pb)
{
    const KeyIdx *a = (const KeyIdx *)pa, *b = (const KeyIdx *)pb;
    if (a->key < b->key) return -1;
    if (a->key > b->key) return 1;
    return a->idx < b->idx ? -1 : a->idx > b->idx;   /* ties: a deterministic order */
}

/* Sort items[0..n) by coordinate `axis` of their points (pts[item]). */
void sort_by_axis(int *items, int n, const Vec3 *pts, int axis, KeyIdx *tmp)
{
    int i;
    for (i = 0; i < n; i++) { tmp[i].key = v3_get(pts[items[i]], axis); tmp[i].idx = items[i]; }
    qsort(tmp, (size_t)n, sizeof *tmp, cmp_key);
    for (i = 0; i < n; i++) items[i] = tmp[i].idx;
}

int longest_axis(Vec3 d)
{
    return d.x >= d.y && d.x >= d.z ? 0 : d.y >= d.z ? 1 : 2;
}

/* ------------------------------------------------------------------ bounds: cones, boxes, the split cost */

/* An orientation cone: unit axis a (the field w), cos theta_o, cos theta_e. */
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

/* Solid-angle measure of the directions a cone emits into, M_omega: 2 pi (1 -
   cos theta_o) for the cone itself, plus 2 pi times the integral of
   cos(theta - theta_o) sin theta from theta_o to t = min(theta_o + theta_e, pi)
   (our derivation; docs/lighttree.md, "Building"). */
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

/* The split cost of one side: Phi * area(box) * M_omega (docs/lighttree.md). */
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

/* The 5 nm bin means of the distinct radiances asked for last, direct-mapped on
   the radiance's index (LE_MEANS rows): the build reads them twice, for the
   leaves' power and for the leaf lanes of quad_bin, instead of holding a row
   for every radiance and every piece at once.  A radiance evicted and asked
   for again is tabulated again: the same means. */
#define LE_MEANS 64
typedef struct {
    int tag[LE_MEANS];         /* the radiance whose means row i holds, -1: none */
    double *avg;               /* LE_MEANS x nb */
    float *bins;               /* nb: piece_bins' output */
} LeMeans;

/* The row of radiance le's means: bin b is the mean of Le over the 5 nm from
   lo = lo_nm + 5 (b - nb_uv), in double: spec_band_mean's trapezoid rule, the
   same operations in the same order, on the knots laid out from 300 nm up. */
static const double *le_means(const LightTreeInput *in, const LightTree *lt, LeMeans *c, int le)
{
    const int w = (int)SPD_BIN_NM;
    int slot = le % LE_MEANS, b, k;
    double *row = c->avg + (size_t)slot * (size_t)lt->nb;
    if (c->tag[slot] != le) {
        float knot[SPEC_UV_N + SPEC_N];            /* Le at SPEC_UV_MIN + i nm */
        /* the knots the bins read: those of bins inside 300-830 nm */
        int nm0 = (int)in->opt->lo_nm - w * lt->nb_uv, nm1 = (int)in->opt->lo_nm + w * (lt->nb - lt->nb_uv);
        if (nm0 < SPEC_UV_MIN) nm0 = SPEC_UV_MIN;
        if (nm1 > SPEC_MAX) nm1 = SPEC_MAX;
        if (nm1 >= nm0) in->le_knots(in->le_ctx, le, nm0, nm1 - nm0 + 1, knot + (nm0 - SPEC_UV_MIN));
        for (b = 0; b < lt->nb; b++) {
            int lo = (int)in->opt->lo_nm + w * (b - lt->nb_uv);
            const float *kn = knot + (lo - SPEC_UV_MIN);
            double sum;
            if (lo < SPEC_UV_MIN || lo + w > SPEC_MAX) { row[b] = 0.0; continue; }
            sum = 0.5 * (kn[0] + kn[w]);
            for (k = 1; k < w; k++) sum += kn[k];
            row[b] = sum / w;
        }
        c->tag[slot] = le;
    }
    return row;
}

/* c->bins := the power per 5 nm bin of piece i: pi A (2 if two-sided) times the
   bin's mean of its Le. */
static void piece_bins(const LightTreeInput *in, const LightTree *lt, LeMeans *c, int i)
{
    const LightPiece *pc = &in->pieces[i];
    const double *avg = le_means(in, lt, c, in->le_of[pc->emitter]);
    double k = SPECNEE_PI * pc->area * (in->scene->emitters[pc->emitter].twosided ? 2.0 : 1.0);
    int b;
    for (b = 0; b < lt->nb; b++) c->bins[b] = (float)(k * avg[b]);
}

typedef struct {
    const LightTreeInput *in;
    LightTree *lt;
    const PieceBounds *pb;
    Vec3 *centroids;
    KeyIdx *tmp;
    MeasureMemo memo;
} Builder;

/* The scene triangle that is triangle j (0 <= j < piece_tri_count) of piece pc,
   a mesh piece whose emitter's shape is sh. */
static int piece_tri_count(const LightPiece *pc, const Shape *sh) { return pc->count ? pc->count : sh->tri_count; }
static int piece_triangle(const LightTreeInput *in, const LightPiece *pc, const Shape *sh, int j)
{
    return pc->count ? in->piece_tri[pc->first + j] : sh->tri_begin + j;
}

/* TreeNode.behind and .slack of a node with bounds a ("behind the box",
   docs/lighttree.md).  Every emitted direction omega of the node lies within theta_t =
   theta_o + theta_e of its axis a.  Light from a point x of the box reaches p
   only along omega = (p - x) / |p - x|, so only if
       a . (p - x) > cos(theta_t) |p - x| = -sin(delta) |p - x|,
   delta = theta_t - pi/2 (slack = sin(delta), 0 where theta_t <= pi/2; no
   plane at all where theta_t >= pi, where sin(delta) would shrink again, or
   for two-sided nodes).  With h = min of a . x over the vertices of the
   pieces' triangles (every emitting point is a convex combination of them;
   the box's corners would put the plane far behind a tilted panel),
   a . (p - x) <= a . p - h, and |p - x| <= |d| + rho (d = p - c, rho the
   bounding sphere's radius), so nothing below lights p when
       a . p - h <= -slack (|d| + rho),
   i.e. in the walk's terms d . a <= behind - slack L, behind = h - a . c,
   L = sqrt(|d|^2 - rho^2) + 2 rho >= |d| + rho outside the bounding sphere and
   L = 2 rho >= |d| + rho inside it.  The margin (behind_margin, larger than the
   round-off of d . a for points in the scene) and rounding behind down and
   slack up keep the float test on the safe side where the node holds a spot
   light; a node of area lamps only moves the plane forward by the margin
   instead (below, and docs/lighttree.md). */
static float node_behind(const Builder *B, const int *items, int n, const Acc *a, const TreeNode *nd,
                         float *slack)
{
    const Scene *s = B->in->scene;
    double h = INFINITY, wc = 0.0, w[3], v, t;
    float f;
    int i, j, k, any_delta = 0;
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
        const LightPiece *pc = &B->in->pieces[items[i]];
        const Emitter *em = &s->emitters[pc->emitter];
        const Shape *sh;
        if (em->shape < 0) {                            /* a spot light: its one point */
            const Vec3 x = em->delta.p;
            double d = w[0] * x.x + w[1] * x.y + w[2] * x.z;
            if (d < h) h = d;                           /* (its only "vertex") */
            any_delta = 1;
            continue;
        }
        sh = &s->shapes[em->shape];
        if (sh->type != SHAPE_MESH || sh->patch_count > 0)   /* (their cones are full anyway) */
            return -INFINITY;
        for (j = 0; j < piece_tri_count(pc, sh); j++) {
            const Triangle *tr = &s->tris[piece_triangle(B->in, pc, sh, j)];
            for (k = 0; k < 3; k++) {
                const Vec3 x = s->P[tr->v[k]];
                double d = w[0] * x.x + w[1] * x.y + w[2] * x.z;
                if (d < h) h = d;
            }
        }
    }
    /* Only area lamps below: the plane moves the margin FORWARD, so that a point on
       the lamps' own plane (the lamp it lies on, seen from its back or its front)
       is behind it too.  Such a point gets light from them only at grazing angles,
       within the margin of their plane; NEE's pmf is 0 there for select and pmf
       alike, so a BSDF sample that finds one of them takes MIS weight 1 (as for
       emitter_can_reach's zeros, lights.c section 4): unbiased.  A spot light
       cannot be found by a BSDF sample, so a node that holds one keeps the
       margin behind its plane. */
    v = h - wc + (any_delta ? -B->lt->behind_margin : B->lt->behind_margin);
    f = (float)v;
    if ((double)f > v) f = nextafterf(f, -INFINITY);
    return f;
}

/* Build the binary subtree over items[0..n) at `depth`; returns its node
   index.  Recursion depth <= 64: below depth 32 every split
   is the median, which halves n. */
static int tree_build(Builder *B, int *items, int n, int depth)
{
    LightTree *lt = B->lt;
    int node = lt->n_nodes++, i, b, mid = -1;
    TreeNode *nd = &lt->nodes[node];
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
    nd->behind = node_behind(B, items, n, &all, nd, &nd->slack);
    if (n == 1) {
        nd->second = -1 - items[0];
        nd->power = lt->leaf_power[items[0]];    /* (leaf_powers) */
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
    nd = &lt->nodes[node];
    nd->second = tree_build(B, items + mid, n - mid, depth + 1);
    nd->power = lt->nodes[node + 1].power + lt->nodes[nd->second].power;
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

/* Collapse the binary tree into the 4-wide one, breadth first
   (the upper levels, which every walk reads, lie together in memory).  The
   root's lanes are root[0..m).  Each piece gets its trail (digit d, bits 2d
   and 2d + 1: the lane taken at depth d) and its depth.  Every level takes
   two binary levels (or ends at a leaf), so depth <= 32 and 64 bits hold the
   trail.  queue: room for every node (lt->n_nodes4, counted by count4). */
static void tree_collapse(const LightTreeInput *in, LightTree *lt, LeMeans *lm, const int *root, int m,
                          Pending *queue)
{
    const TreeNode *bn = lt->nodes;
    int head = 0, tail = 1, k, b;
    memcpy(queue[0].slots, root, sizeof(int) * (size_t)m);
    queue[0].m = m;
    queue[0].depth = 0;
    queue[0].trail = 0;
    for (head = 0; head < tail; head++) {
        const Pending *pd = &queue[head];
        TreeNode4 *nd = &lt->nodes4[head];
        float *col = lt->quad_bin + (size_t)head * 4;   /* bin b: col[4 n_nodes4 b] */
        for (k = 0; k < pd->m; k++) {                /* lanes m..3 stay 0: no power */
            const TreeNode *c = &bn[pd->slots[k]];
            uint64_t t = pd->trail | ((uint64_t)k << (2 * pd->depth));
            lane_from(nd, k, c);
            lt->quad_power[(size_t)head * 4 + k] = c->power;
            if (c->second < 0) {                     /* a leaf: its piece's bins (others: quad_bins_up) */
                piece_bins(in, lt, lm, -1 - c->second);
                for (b = 0; b < lt->nb; b++) col[(size_t)4 * lt->n_nodes4 * b + k] = lm->bins[b];
            }
            if (c->second < 0) {
                lt->trail[-1 - c->second] = t;
                lt->depth[-1 - c->second] = pd->depth + 1;
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

/* The bins of binary node c, an interior node whose grandchildren are the lanes
   of 4-wide node j (grandchildren's order), into out[b * stride]: the sums of the
   binary build, each child the sum of its two children (or a leaf alone), then
   the two children. */
static void lanes_sum(const LightTree *lt, int c, int j, float *out, size_t stride)
{
    const TreeNode *bn = lt->nodes;
    const size_t bin_stride = (size_t)4 * lt->n_nodes4;
    const float *col = lt->quad_bin + (size_t)j * 4;
    int leaf0 = bn[c + 1].second < 0, leaf1 = bn[bn[c].second].second < 0;
    int k1 = leaf0 ? 1 : 2, b;                 /* the first lane of the second child */
    for (b = 0; b < lt->nb; b++, col += bin_stride) {
        float h0 = leaf0 ? col[0] : col[0] + col[1];
        float h1 = leaf1 ? col[k1] : col[k1] + col[k1 + 1];
        out[(size_t)b * stride] = h0 + h1;
    }
}

/* The bins of the lanes that hold interior binary nodes, from the lanes of their
   own 4-wide nodes, deepest first (a child has a higher index than its parent:
   breadth first), and the root's; queue: the collapse's nodes. */
static void quad_bins_up(LightTree *lt, const Pending *queue)
{
    const size_t bin_stride = (size_t)4 * lt->n_nodes4;
    int i, k, b;
    for (i = lt->n_nodes4 - 1; i >= 0; i--)
        for (k = 0; k < queue[i].m; k++) {
            int c = queue[i].slots[k];
            if (lt->nodes[c].second < 0) continue;   /* a leaf: its piece's bins */
            lanes_sum(lt, c, lt->nodes4[i].child[k], lt->quad_bin + (size_t)i * 4 + k, bin_stride);
        }
    if (lt->nodes[0].second >= 0) lanes_sum(lt, 0, 0, lt->root_bin, 1);
    else for (b = 0; b < lt->nb; b++) lt->root_bin[b] = lt->quad_bin[bin_stride * b];
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

/* The oriented geometric normal of triangle t, as scene_surface_point sees it. */
static Vec3 tri_normal(const Scene *s, int t)
{
    const Triangle *tr = &s->tris[t];
    Vec3 p0 = s->P[tr->v[0]], p1 = s->P[tr->v[1]], p2 = s->P[tr->v[2]];
    Vec3 n = v3_norm(v3_cross(v3_sub(p0, p2), v3_sub(p1, p2)));
    return s->shapes[tr->shape].flip ? v3_neg(n) : n;
}

/* Do the piece's shading normals leave every point on its triangle's side?  The
   shading normal decides which side a point of a lamp lights (lights.c,
   emitter_can_reach's planes); where the three vertex normals of a triangle lie
   on its oriented normal's side, so does every interpolation of them, and the
   triangle lights the side of its oriented normal, as without normals.  The
   same test as those planes' (a positive dot product); 1 without normals. */
static int normals_agree(const LightTreeInput *in, const LightPiece *pc, const Shape *sh)
{
    const Scene *s = in->scene;
    int i, k;
    if (!sh->has_normals) return 1;
    if (!s->N) return 0;
    for (i = 0; i < piece_tri_count(pc, sh); i++) {
        int t = piece_triangle(in, pc, sh, i);
        Vec3 n = tri_normal(s, t);
        for (k = 0; k < 3; k++)
            if (!(v3_dot(n, s->N[s->tris[t].v[k]]) > 0.0f)) return 0;
    }
    return 1;
}

/* Box, cone and power of a piece. */
static void piece_bounds(const LightTreeInput *in, const LightPiece *pc, PieceBounds *out)
{
    const Scene *s = in->scene;
    const Emitter *em = &s->emitters[pc->emitter];
    const Shape *sh = em->shape >= 0 ? &s->shapes[em->shape] : NULL;
    out->twosided = em->twosided;
    if (!sh) {
        /* a point or spot light (delta.c): a box that is one point; a point light
           emits every way (theta_o = pi, theta_e = pi/2, as pbrt-v4's bounds), a
           spot light within theta_o = its full-intensity cone and theta_e = the
           falloff band beyond it (every direction when its CTM stretches the
           cone out of round).  A band of less than a milliradian is widened
           to one: "imp_k = 0 when theta' >= theta_e" must not cut off a point just
           inside the cone by round-off (pbrt-v4 keeps a similar slop) */
        const DeltaLight *d = &em->delta;
        out->bmin = out->bmax = d->p;
        if ((d->type == DELTA_SPOT || d->type == DELTA_PROJECTION) && !d->stretched) {
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
            int t = piece_triangle(in, pc, sh, i);
            const Triangle *tr = &s->tris[t];
            for (k = 0; k < 3; k++) {
                Vec3 p = s->P[tr->v[k]];
                if (i == 0 && k == 0) out->bmin = out->bmax = p;
                out->bmin = v3_min(out->bmin, p);
                out->bmax = v3_max(out->bmax, p);
            }
            nsum = v3_add(nsum, v3_mul(tri_normal(s, t), (float)tri_area(s, t)));
        }
        for (i = 0; i < (pc->count ? 0 : sh->patch_count); i++) {
            const Patch *pa = &s->patches[sh->patch_begin + i];   /* in its corners' box */
            for (k = 0; k < 4; k++) {
                Vec3 p = s->P[pa->v[k]];
                if (count == 0 && i == 0 && k == 0) out->bmin = out->bmax = p;
                out->bmin = v3_min(out->bmin, p);
                out->bmax = v3_max(out->bmax, p);
            }
        }
        if (!normals_agree(in, pc, sh) || !(v3_len(nsum) > 0.0f) || (!pc->count && sh->patch_count > 0)) {
            out->cone = cone_full(0.0f);   /* shading normals may flip a point's side; a
                                              twisted patch faces many ways */
        } else {
            out->cone.w = v3_norm(nsum);
            for (i = 0; i < count; i++) {
                int t = piece_triangle(in, pc, sh, i);
                if (tri_area(s, t) > 0.0) cos_o = fminf(cos_o, v3_dot(out->cone.w, tri_normal(s, t)));
            }
            out->cone.cos_o = fmaxf(-1.0f, fminf(1.0f, cos_o));
            out->cone.cos_e = 0.0f;
        }
    }
    out->centroid = v3_mul(v3_add(out->bmin, out->bmax), 0.5f);
    out->power = in->piece_power[pc - in->pieces];
}

/* ------------------------------------------------------------------ the walk: importance, select, pmf */

/* The context as the tree reads it: point, normal, and the bins that count. */
typedef struct {
    Vec3 p, n;
    int has_n;
    int spectral, nbins;
    int bin[HERO_N];
    float c[HERO_N];
} TreeQuery;

static void tree_query(const LightTree *lt, const LightCtx *c, TreeQuery *q)
{
    int j;
    q->p = c->p;
    q->n = c->n;
    q->has_n = v3_dot(c->n, c->n) > 0.0f;
    q->spectral = lt->spectral;
    q->nbins = 0;
    if (!q->spectral) return;
    for (j = 0; j < HERO_N; j++) {
        float cj = lt->throughput_weighted ? c->beta[j] : 1.0f;
        float x = (c->lambda[j] - lt->lo_nm) / SPD_BIN_NM;
        int b;
        if (!(c->alive & (1u << j)) || !(cj > 0.0f)) continue;
        if (x >= 0.0f) {
            b = lt->nb_uv + (int)x;                  /* the sampled range */
        } else {                                     /* below it: a UV bin, from 300 nm */
            float xu = (c->lambda[j] - (lt->lo_nm - SPD_BIN_NM * lt->nb_uv)) / SPD_BIN_NM;
            b = xu >= 0.0f ? (int)xu : 0;            /* also catches NaN */
            if (b >= lt->nb_uv) b = lt->nb_uv - 1;
        }
        if (b >= lt->nb) b = lt->nb - 1;
        q->bin[q->nbins] = b;
        q->c[q->nbins] = cj;
        q->nbins++;
    }
}

/* max(x, 0) without libm's fmaxf (a call per use in this, the hottest loop of the
   tree; a NaN gives 0 as fmaxf(0, NaN) does). */
static float pos_or_zero(float x) { return x > 0.0f ? x : 0.0f; }

/* The power that counts at the query: sum over the query's bins of
   c_j times the power in bin b_j, read from bins[stride * b_j]. */
static float query_power(const TreeQuery *q, const float *bins, int stride)
{
    float phi = 0.0f;
    int k;
    for (k = 0; k < q->nbins; k++) phi += q->c[k] * bins[stride * q->bin[k]];
    return phi;
}

/* Inside a node's bounding sphere the walk divides by |d|^2, but by no less
   than (rho/4)^2 = TREE_INSIDE rho^2 (1/4 measured: 1/2 to 1/10 gave
   the same MSE within 0.5% on the hall and many-lamps, docs/lighttree.md). */
#define TREE_INSIDE 0.0625f

/* The importance of the child in lane k of node nd, whose power in the
   context is phi, at the query: the one function that both
   tree_select and tree_pmf call (through node_importance4, which computes
   four lanes at once exactly as this does one).  The walk waits for it at
   every level, and a core has one unit for square roots and divisions, so it
   is written with as few of them as the bound allows: with d = p - centre (not
   normalised), rho the bounding sphere's radius (r in the code), a the cone's
   axis, and
       S_b = sqrt(|d|^2 - rho^2) = |d| cos theta_b,   rho = |d| sin theta_b,
       dw = d . a (|d . a| when two-sided) = |d| cos theta_w,
       S_w = sqrt(|d|^2 - dw^2) = |d| sin theta_w,
       dn = |d . n| = |d| cos theta_i,   S_i = sqrt(|d|^2 - dn^2) = |d| sin theta_i,
   every cosine of the bound is a ratio with |d| or |d|^2 below:
       theta_w <= theta_o  <=>  dw |dw| >= cos_o |cos_o| |d|^2   (x |x| increases),
       X = |d|^2 cos theta' = |d|^2, or (dw cos_o + S_w sin_o) S_b + (S_w cos_o - dw sin_o) rho,
       Y = |d|^2 cos theta_i' = |d|^2, or dn S_b + S_i rho,
   and imp_k = Phi_c (1 / |d|^2) (X / |d|^2) (Y / |d|^2) (I below): three square
   roots and one division (by |d|^2, at least FLT_MIN).  Inside the bounding
   sphere imp_k = Phi_c / max(|d|^2, TREE_INSIDE rho^2), no angle.  The product is taken in
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
        return 0.0;                                  /* p behind the box: imp_k = 0 (node_behind) */
    if (!(d2 > r2)) { /* p inside the bounding sphere: no angle can be bounded; */
        float den = d2 > TREE_INSIDE * r2 ? d2 : TREE_INSIDE * r2;   /* imp_k = Phi_c / max(|d|, rho/4)^2 */
        return (double)phi * (double)(1.0f / (den > FLT_MIN ? den : FLT_MIN));
    }
    if (!(d2 <= FLT_MAX)) return 0.0;                /* p at infinity: imp_k = 0 */
    if (nd->twosided[k]) dw = fabsf(dw);
    if (dw * fabsf(dw) >= nd->cos_o[k] * fabsf(nd->cos_o[k]) * d2) {
        X = d2;                                      /* p inside the normal cone */
    } else {
        /* theta_w - theta_o > 0, then minus theta_b, clamped at 0 */
        float Sw = sqrtf(pos_or_zero(d2 - dw * dw));
        float A = dw * nd->cos_o[k] + Sw * nd->sin_o[k];   /* |d| cos(theta_w - theta_o) */
        float B = Sw * nd->cos_o[k] - dw * nd->sin_o[k];   /* |d| sin(theta_w - theta_o) */
        X = A >= Sb ? d2 : A * Sb + B * r;
        if (X <= nd->cos_e[k] * d2) return 0.0;      /* theta' >= theta_e: imp_k = 0 */
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

/* The importances imp_k of the four lanes of nd, into I[0..4), with powers phi[0..4):
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
    /* p behind the box: imp_k = 0, inside the bounding sphere too (L: Sb, 0 inside, + 2 rho) */
    behind = _mm_cmple_ps(dw, _mm_sub_ps(_mm_loadu_ps(nd->behind),
                                         _mm_mul_ps(_mm_loadu_ps(nd->slack),
                                                    _mm_add_ps(_mm_andnot_ps(inside, Sb), _mm_add_ps(r, r)))));
    dw = _mm_and_ps(dw, _mm_or_ps(one_sided, abs_mask));
    in_cone = _mm_cmpge_ps(_mm_mul_ps(dw, _mm_and_ps(dw, abs_mask)),
                           _mm_mul_ps(_mm_mul_ps(cos_o, _mm_and_ps(cos_o, abs_mask)), d2));
    /* imp_k = 0 where p is at infinity, or (below) where theta' >= theta_e */
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
static void child_powers(const LightTree *lt, const TreeQuery *q, int i, float phi[4])
{
    const float *col = lt->quad_bin + (size_t)i * 4;   /* bin b: col[stride b] */
    int k, stride = 4 * lt->n_nodes4;
    if (!q->spectral) { memcpy(phi, lt->quad_power + (size_t)i * 4, 4 * sizeof(float)); return; }
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

/* The branch at node i: the children's importances imp_k in I[0..4) and their sum *S
   (in lane order, as the walk accumulates them); 0 when nothing below can
   light the point (or round-off overflowed). */
static void branch_at(const LightTree *lt, const TreeQuery *q, int i, double I[4], double *S)
{
    float phi[4];
    child_powers(lt, q, i, phi);
    node_importance4(&lt->nodes4[i], q, phi, I);
    *S = ((I[0] + I[1]) + I[2]) + I[3];
    if (!(*S > 0.0 && *S <= DBL_MAX)) *S = 0.0;
}

/* Does the tree get a share beside the infinite lights?  Only when it has pieces
   and its root can light the point (else every share goes to the infinite
   lights).  A function of the context alone, so select and pmf agree. */
static int tree_live(const LightTree *lt, const TreeQuery *q)
{
    return lt->n_tree_pieces > 0 &&
           lane_importance(&lt->top, 0, q, q->spectral ? query_power(q, lt->root_bin, 1)
                                                        : lt->top_power) > 0.0;
}

int light_tree_select(const LightTree *lt, const LightCtx *c, float u, float *pmf)
{
    TreeQuery q;
    double uu = u, lo = 0.0, p = 1.0, w = 1.0;
    int i = 0;
    tree_query(lt, c, &q);
    if (lt->n_inf > 0) {
        /* one share for each infinite light, one for the tree */
        int k = lt->n_inf + tree_live(lt, &q), slot;
        uu = (double)u * k;
        slot = (int)uu;
        if (slot >= k) slot = k - 1;
        p = 1.0 / k;
        if (slot < lt->n_inf) { *pmf = (float)p; return lt->inf_piece[slot]; }
        uu -= slot;
        if (!(uu < 1.0)) uu = 1.0 - DBL_EPSILON;
    }
    /* [lo, lo + len) is the part of [0, 1) that leads to node i (len = p / the
       tree's share; the variable w); child k gets the piece of it from
       lo + len C_(k-1) / S to lo + len C_k / S, with C_k = imp_0 + ... + imp_k
       and S = C_3.  The test is uu - lo < len C_k / S times S, so that the walk
       need not wait for the division before it goes on; a child that cannot
       light p (imp_k = 0) is never taken, whatever the round-off (at the top,
       the last child with imp_k > 0). */
    for (;;) {
        double I[4], S, x, cum = 0.0, prev = 0.0, pa, invS;
        int k, pick = -1, child;
        branch_at(lt, &q, i, I, &S);
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
        child = lt->nodes4[i].child[pick];
        if (child < 0) { *pmf = (float)p; return -1 - child; }
        i = child;
    }
}

float light_tree_pmf(const LightTree *lt, const LightCtx *c, int piece)
{
    TreeQuery q;
    double p = 1.0;
    int i = 0, d;
    tree_query(lt, c, &q);
    if (lt->n_inf > 0) {
        int live = tree_live(lt, &q);
        p = 1.0 / (lt->n_inf + live);
        if (lt->depth[piece] == 0) return (float)p;       /* beside the tree */
        if (!live) return 0.0f;
    }
    for (d = 0; d < lt->depth[piece]; d++) {
        double I[4], S;
        int k = (int)((lt->trail[piece] >> (2 * d)) & 3u), child;
        branch_at(lt, &q, i, I, &S);
        if (!(S > 0.0) || !(I[k] > 0.0)) return 0.0f;
        p *= I[k] * (1.0 / S);
        child = lt->nodes4[i].child[k];
        if (child < 0) return d == lt->depth[piece] - 1 && child == -1 - piece ? (float)p : 0.0f;
        i = child;
    }
    return 0.0f;                                     /* a trail shorter than the tree */
}

/* For the test lighttree_simd_matches_scalar: at context c, every child of
   every node evaluated both ways, power and importance compared bit for bit. */
int light_tree_simd_check(const LightTree *lt, const LightCtx *c, int *lanes)
{
    TreeQuery q;
    int i, k, bad = 0;
    *lanes = 0;
    if (lt->n_tree_pieces == 0) return 0;
    tree_query(lt, c, &q);
    for (i = 0; i < lt->n_nodes4; i++) {
        float phi[4];
        double I[4], S;
        child_powers(lt, &q, i, phi);
        branch_at(lt, &q, i, I, &S);                 /* what the walk computes */
        for (k = 0; k < 4; k++) {
            float ps = q.spectral ? query_power(&q, lt->quad_bin + (size_t)i * 4 + k, 4 * lt->n_nodes4)
                                  : lt->quad_power[(size_t)i * 4 + k];
            double Is = lane_importance(&lt->nodes4[i], k, &q, ps);
            bad += memcmp(&ps, &phi[k], sizeof ps) != 0 || memcmp(&Is, &I[k], sizeof Is) != 0;
            (*lanes)++;
        }
    }
    return bad;
}

/* Bin b summed, in double, over the leaf lanes below lane k of 4-wide node i. */
static double leaves_sum(const LightTree *lt, int i, int k, int b)
{
    int j = lt->nodes4[i].child[k], kk;
    double sum = 0.0;
    if (j < 0) return lt->quad_bin[(size_t)4 * lt->n_nodes4 * b + (size_t)i * 4 + k];
    for (kk = 0; kk < 4; kk++)
        if (lt->nodes4[j].child[kk] != 0) sum += leaves_sum(lt, j, kk, b);   /* 0: no lane */
    return sum;
}

/* For the test lighttree_bins_sum: every lane's power per bin, and the root's,
   against the sum of the leaves' below it (relative 1e-5: float sums); the
   number of lanes (and root) that differ. */
int light_tree_bins_check(const LightTree *lt, int *lanes)
{
    int i, k, b, bad = 0;
    *lanes = 0;
    if (lt->n_tree_pieces == 0) return 0;
    for (i = 0; i < lt->n_nodes4; i++)
        for (k = 0; k < 4; k++) {
            if (lt->nodes4[i].child[k] == 0) continue;   /* an empty lane (node 0 is no child) */
            (*lanes)++;
            for (b = 0; b < lt->nb; b++) {
                double want = leaves_sum(lt, i, k, b);
                double got = lt->quad_bin[(size_t)4 * lt->n_nodes4 * b + (size_t)i * 4 + k];
                if (!(fabs(got - want) <= 1e-5 * fabs(want))) { bad++; break; }
            }
        }
    for (b = 0; b < lt->nb; b++) {
        double want = 0.0;
        for (k = 0; k < 4; k++)
            if (lt->nodes4[0].child[k] != 0) want += leaves_sum(lt, 0, k, b);
        if (!(fabs(lt->root_bin[b] - want) <= 1e-5 * fabs(want))) { bad++; break; }
    }
    return bad;
}

int light_tree_root_bins_copy(const LightTree *lt, float *bins, int max)
{
    int b;
    if (!lt->root_bin) return 0;
    for (b = 0; b < lt->nb && b < max; b++) bins[b] = lt->root_bin[b];
    return lt->nb;
}

/* ------------------------------------------------------------------ build, free, size */

/* lt->leaf_power: the power Phi of every piece in the tree, the sum of its bins
   (piece_bins) of the sampled range only (b >= nb_uv). */
static void leaf_powers(const LightTreeInput *in, LightTree *lt, LeMeans *lm)
{
    int i, b;
    for (i = 0; i < in->n_pieces; i++) {
        double sum = 0.0;
        if (beside_tree(&in->scene->emitters[in->pieces[i].emitter])) continue;
        piece_bins(in, lt, lm, i);
        for (b = lt->nb_uv; b < lt->nb; b++) sum += (double)lm->bins[b] * SPD_BIN_NM;
        lt->leaf_power[i] = (float)sum;
    }
}

LightTree *light_tree_build(const LightTreeInput *in)
{
    const Scene *s = in->scene;
    LightTree *lt = (LightTree *)calloc(1, sizeof *lt);
    int i, e, n = in->n_pieces, ok = 0;
    int *items = NULL;
    PieceBounds *pb = NULL;
    KeyIdx *tmp = NULL;
    Builder B;
    LeMeans lm;
    if (!lt) return NULL;
    lm.avg = NULL;
    lm.bins = NULL;
    lt->spectral = in->opt->strategy == SEL_SPECTRAL_TREE;
    lt->throughput_weighted = in->opt->throughput_weighted;
    lt->lo_nm = in->opt->lo_nm;
    lt->n_pieces = n;
    lt->trail = (uint64_t *)calloc((size_t)n + 1, sizeof *lt->trail);
    lt->depth = (int *)calloc((size_t)n + 1, sizeof *lt->depth);
    lt->inf_piece = (int *)malloc(sizeof(int) * (size_t)(n + 1));
    if (!lt->trail || !lt->depth || !lt->inf_piece) goto done;
    /* the lights beside the tree, in piece order */
    for (i = 0; i < n; i++)
        if (beside_tree(&s->emitters[in->pieces[i].emitter])) lt->inf_piece[lt->n_inf++] = i;
    /* the tree over the pieces that have a position (all but those beside it) */
    lt->n_tree_pieces = n - lt->n_inf;
    {   /* offset_ray_origin's policy at the scene's largest |coordinate| */
        float m = fmaxf(fmaxf(fabsf(s->bmin.x), fabsf(s->bmax.x)),
                        fmaxf(fmaxf(fabsf(s->bmin.y), fabsf(s->bmax.y)), fmaxf(fabsf(s->bmin.z), fabsf(s->bmax.z))));
        lt->behind_margin = offset_eps(m);
    }
    lt->nb_uv = (int)((in->opt->lo_nm - (float)SPEC_UV_MIN) / SPD_BIN_NM);
    if (lt->nb_uv < 0) lt->nb_uv = 0;
    lt->nb = lt->nb_uv + (int)((in->opt->hi_nm - in->opt->lo_nm) / SPD_BIN_NM + 0.5f);
    if (lt->n_tree_pieces == 0) { ok = 1; goto done; }
    pb = (PieceBounds *)malloc(sizeof *pb * (size_t)n);
    items = (int *)malloc(sizeof(int) * (size_t)n);
    tmp = (KeyIdx *)malloc(sizeof(KeyIdx) * (size_t)n);
    B.centroids = (Vec3 *)malloc(sizeof(Vec3) * (size_t)n);
    lt->nodes = (TreeNode *)calloc((size_t)(2 * lt->n_tree_pieces - 1), sizeof *lt->nodes);
    lt->leaf_power = (float *)malloc(sizeof(float) * (size_t)n);
    lm.avg = (double *)malloc(sizeof(double) * LE_MEANS * (size_t)lt->nb);
    lm.bins = (float *)malloc(sizeof(float) * (size_t)lt->nb);
    for (i = 0; i < LE_MEANS; i++) lm.tag[i] = -1;
    if (!pb || !items || !tmp || !B.centroids || !lt->nodes || !lt->leaf_power || !lm.avg || !lm.bins) {
        free(B.centroids);
        goto done;
    }
    for (i = 0, e = 0; i < n; i++) {
        if (beside_tree(&s->emitters[in->pieces[i].emitter])) continue;
        piece_bounds(in, &in->pieces[i], &pb[i]);
        B.centroids[i] = pb[i].centroid;
        items[e++] = i;
    }
    B.in = in;
    B.lt = lt;
    B.pb = pb;
    B.tmp = tmp;
    B.memo.valid = 0;
    leaf_powers(in, lt, &lm);
    lt->n_nodes = 0;
    tree_build(&B, items, lt->n_tree_pieces, 0);
    free(B.centroids);
    free(items); free(pb); free(tmp);          /* not held while the 4-wide tree is built */
    items = NULL; pb = NULL; tmp = NULL;
    /* collapse it into the 4-wide tree that the walk reads: count its nodes,
       then fill them breadth first */
    {
        int slots[4], m;
        Pending *queue;
        if (lt->nodes[0].second < 0) { slots[0] = 0; m = 1; }
        else m = grandchildren(lt->nodes, 0, slots);
        lt->n_nodes4 = count4(lt->nodes, slots, m);
        queue = (Pending *)malloc(sizeof *queue * (size_t)lt->n_nodes4);
        /* the nodes in 64-byte aligned memory (the root in its first cache lines) */
        lt->nodes4_mem = calloc(1, sizeof(TreeNode4) * (size_t)lt->n_nodes4 + 63);
        lt->quad_power = (float *)calloc((size_t)lt->n_nodes4 * 4, sizeof(float));
        lt->quad_bin = (float *)calloc((size_t)lt->n_nodes4 * 4 * (size_t)lt->nb, sizeof(float));
        lt->root_bin = (float *)malloc(sizeof(float) * (size_t)lt->nb);
        if (!queue || !lt->nodes4_mem || !lt->quad_power || !lt->quad_bin || !lt->root_bin) {
            free(queue);
            goto done;
        }
        lt->nodes4 = (TreeNode4 *)((char *)lt->nodes4_mem + (64 - (size_t)((uintptr_t)lt->nodes4_mem % 64)) % 64);
        lane_from(&lt->top, 0, &lt->nodes[0]);
        lt->top_power = lt->nodes[0].power;
        tree_collapse(in, lt, &lm, slots, m, queue);
        quad_bins_up(lt, queue);
        free(queue);
    }
    ok = 1;
done:
    free(items); free(pb); free(tmp);
    free(lt->nodes);
    lt->nodes = NULL;
    free(lt->leaf_power);
    lt->leaf_power = NULL;
    free(lm.avg); free(lm.bins);
    if (!ok) { light_tree_free(lt); return NULL; }
    return lt;
}

void light_tree_free(LightTree *lt)
{
    if (!lt) return;
    free(lt->trail); free(lt->depth); free(lt->inf_piece);
    free(lt->nodes); free(lt->leaf_power); free(lt->nodes4_mem); free(lt->quad_power); free(lt->quad_bin);
    free(lt->root_bin);
    free(lt);
}

size_t light_tree_bytes(const LightTree *lt)
{
    size_t bytes = sizeof *lt;
    bytes += (size_t)(lt->n_pieces + 1) * (sizeof(uint64_t) + 2 * sizeof(int));   /* trail, depth, inf_piece */
    bytes += (size_t)lt->n_nodes4 * (sizeof(TreeNode4) + 4 * sizeof(float) * (size_t)(lt->nb + 1));
    if (lt->root_bin) bytes += sizeof(float) * (size_t)lt->nb;
    return bytes;
}
