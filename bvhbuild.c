/* bvhbuild.c - the BVH's construction: a binned-SAH binary tree over a scene's
   primitives, collapsed into the 8-wide nodes that bvh.c traverses.

   WHAT IT IMPLEMENTS (specnee.h section 5; docs/bvh.md "What each design choice gains")
     bvh_build          the world tree of a Scene: every primitive not inside an
                        ObjectBegin block, and one primitive per instance
     bvh_build_object   the tree of one object's primitives in its own space (instance.c)
     bvh_free           frees a tree
     bvh_prim_shape     the Shape of a primitive id (the id layout is in bvh.c's opening)
   The binary tree is built top-down: at each node the primitives' centroids are
   binned into BVH_BINS bins per axis and the split with the least surface-area cost
   (Goldsmith and Salmon 1987; MacDonald and Booth 1990) is taken; below depth
   SAH_DEPTH_MAX a middle split bounds the depth, which bvh.c's traversal stack relies
   on.  The binary tree is then collapsed into BVH_WIDTH-wide nodes.
   USE: scene_load calls bvh_build(&s->bvh, s) once; bvh.c answers ray queries with
   the result.  Nothing here runs per ray.
*/
#include "specnee.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>
/* ======================================================================
   Build
   ====================================================================== */
typedef struct { float lo[3], hi[3]; } Box;

static void box_empty(Box *b)
{
    int a;
    for (a = 0; a < 3; a++) { b->lo[a] = FLT_MAX; b->hi[a] = -FLT_MAX; }
}
static void box_grow(Box *b, const Box *c)
{
    int a;
    for (a = 0; a < 3; a++) {
        if (c->lo[a] < b->lo[a]) b->lo[a] = c->lo[a];
        if (c->hi[a] > b->hi[a]) b->hi[a] = c->hi[a];
    }
}
static void box_grow_point(Box *b, const float *p)
{
    int a;
    for (a = 0; a < 3; a++) {
        if (p[a] < b->lo[a]) b->lo[a] = p[a];
        if (p[a] > b->hi[a]) b->hi[a] = p[a];
    }
}
/* Half the surface area (the factor 2 cancels in the SAH); 0 for an empty box. */
static float box_half_area(const Box *b)
{
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    if (dx < 0.0f || dy < 0.0f || dz < 0.0f) return 0.0f;
    return dx * dy + dy * dz + dz * dx;
}

/* Everything the build needs about one primitive.  The build moves these records
   themselves as it partitions (not indices to them), so that each node reads its
   primitives in one run of memory: on the 3.2 million instances of a Menger sponge
   an index into 115 MB of records missed the cache at almost every read. */
typedef struct {
    Box box;
    float centroid[3];
    int32_t index;                 /* its position in the build's list of ids */
} PrimInfo;

/* A node of the binary tree the build makes first (then collapsed into wide nodes):
   its children are the next node and node first_or_right; a leaf (count > 0) holds
   prims[first_or_right .. + count). */
typedef struct {
    Box box;
    int32_t first_or_right, count;
    int32_t sub_first, sub_count;  /* all primitives below: prims[sub_first .. + sub_count) */
} BinNode;

/* A node waiting to be built: primitives prims[begin, end), at this depth; parent is
   the inner node whose right child it is (-1 for a left child or the root). */
typedef struct { int begin, end, parent, depth; } BuildTask;

/* The bin of centroid c along an axis whose centroid range starts at lo, with
   k = BVH_BINS / extent.  The same float expression is used for binning and for
   partitioning, so both agree on every primitive. */
static int bin_of(float c, float lo, float k)
{
    float f = (c - lo) * k;                        /* in [0, BVH_BINS] up to rounding */
    if (!(f > 0.0f)) return 0;                     /* clamp before converting to int */
    if (f >= (float)(BVH_BINS - 1)) return BVH_BINS - 1;
    return (int)f;
}

/* The Shape of primitive id < n_tris + n_spheres + n_quadrics + n_patches, -1 for
   an index out of range. */
int bvh_prim_shape(const Scene *s, int id)
{
    int sh;
    if (id < s->n_tris) sh = s->tris[id].shape;
    else if (id < s->n_tris + s->n_spheres) sh = s->sphere_shape[id - s->n_tris];
    else if (id < s->n_tris + s->n_spheres + s->n_quadrics)
        sh = s->quadric_shape[id - s->n_tris - s->n_spheres];
    else if (id < s->n_tris + s->n_spheres + s->n_quadrics + s->n_patches)
        sh = s->patches[id - s->n_tris - s->n_spheres - s->n_quadrics].shape;
    else {
        const int k = id - s->n_tris - s->n_spheres - s->n_quadrics - s->n_patches;
        if (k >= s->n_curve_pieces) return -1;
        sh = s->curves[s->curve_pieces[k].curve].shape;
    }
    return sh >= 0 && sh < s->n_shapes ? sh : -1;
}

/* The bounds and centroid of primitive id (a triangle, sphere, quadric, patch, curve
   piece or instance); 0 on invalid geometry. */
static int prim_info(const Scene *s, int id, PrimInfo *info)
{
    const int n_quad_end = s->n_tris + s->n_spheres + s->n_quadrics;
    const int n_patch_end = n_quad_end + s->n_patches, n_base = n_patch_end + s->n_curve_pieces;
    Box *b = &info->box;
    int k, a;
    if (id < s->n_tris) {
        box_empty(b);
        for (k = 0; k < 3; k++) {
            int vi = s->tris[id].v[k];
            float p[3];
            if (vi < 0 || vi >= s->n_verts) return 0;
            p[0] = s->P[vi].x; p[1] = s->P[vi].y; p[2] = s->P[vi].z;
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) return 0;
            box_grow_point(b, p);
        }
    } else if (id < s->n_tris + s->n_spheres) {
        const int j = s->sphere_shape[id - s->n_tris];
        const Shape *sh;
        if (j < 0 || j >= s->n_shapes) return 0;
        sh = &s->shapes[j];
        {
            const float c[3] = { sh->center.x, sh->center.y, sh->center.z };
            bvh_sphere_box(c, sh->radius, b->lo, b->hi);
        }
    } else if (id < n_quad_end) {
        const int j = s->quadric_shape[id - s->n_tris - s->n_spheres];
        if (j < 0 || j >= s->n_shapes) return 0;
        quadric_bounds(&s->shapes[j], b->lo, b->hi);
    } else if (id >= n_patch_end && id < n_base) {   /* a curve piece (curve.c) */
        curve_piece_bounds(s, &s->curve_pieces[id - n_patch_end], b->lo, b->hi);
    } else if (id < n_base) {             /* a patch lies in its corners' box */
        box_empty(b);
        for (k = 0; k < 4; k++) {
            int vi = s->patches[id - n_quad_end].v[k];
            float p[3];
            if (vi < 0 || vi >= s->n_verts) return 0;
            p[0] = s->P[vi].x; p[1] = s->P[vi].y; p[2] = s->P[vi].z;
            box_grow_point(b, p);
        }
    } else {                              /* an instance: its world box (instance.c) */
        const Instance *in = &s->instances[id - n_base];
        for (a = 0; a < 3; a++) { b->lo[a] = in->lo[a]; b->hi[a] = in->hi[a]; }
    }
    for (a = 0; a < 3; a++) {
        if (!isfinite(b->lo[a]) || !isfinite(b->hi[a])) return 0;
        info->centroid[a] = 0.5f * b->lo[a] + 0.5f * b->hi[a];
    }
    return 1;
}

/* A sphere's box, rounded outwards so that it holds the sphere (also bvh.c's, for
   the hit's floor: the same floats) */
void bvh_sphere_box(const float c[3], float radius, float lo[3], float hi[3])
{
    int a;
    for (a = 0; a < 3; a++) {
        lo[a] = nextafterf(c[a] - radius, -FLT_MAX);
        hi[a] = nextafterf(c[a] + radius, FLT_MAX);
    }
}

int bvh_prim_box(const Scene *s, int id, float lo[3], float hi[3])
{
    PrimInfo info;
    int a;
    if (!prim_info(s, id, &info)) return 0;
    for (a = 0; a < 3; a++) { lo[a] = info.box.lo[a]; hi[a] = info.box.hi[a]; }
    return 1;
}

/* Choose a split of info[begin, end) by the binned SAH (Wald 2007, "On fast
   construction of SAH-based bounding volume hierarchies").  Splitting a node of area A
   holding N primitives into (L, R) is estimated to cost
       C_split = C_trav + (A_L N_L + A_R N_R) / A
   against C_leaf = N for a leaf.  The centroids are sorted into BVH_BINS equal bins
   along each axis, and the BVH_BINS - 1 planes between bins are scored by two sweeps
   (one from each side).  A node with more than BVH_LEAF_MAX primitives is always
   split (bvh_build cuts it in the middle of its list when the SAH finds no plane); a
   smaller one only when C_split < C_leaf.  Returns 1 and sets *axis_out and *mid_out
   (after partitioning info) to split, 0 to make a leaf. */
static int sah_split(PrimInfo *info, int begin, int end,
                     const Box *node_box, const Box *cbox, int *axis_out, int *mid_out)
{
    /* pbrt-v4 uses C_trav = 1/2; here a visit tests both children's boxes.  With the
       slab test in SSE2 a box costs less than a triangle, and on tools/bench C_trav = 1
       tests 13% fewer triangles than 2 for the same wide nodes (docs/bvh.md) */
    const float C_trav = 1.0f;
    const int n = end - begin;
    float best_cost = FLT_MAX, k_best = 0.0f;
    int best_axis = -1, best_split = 0, axis, i, lo, hi;

    for (axis = 0; axis < 3; axis++) {
        Box bin_box[BVH_BINS], acc;
        int bin_n[BVH_BINS];
        float right_area[BVH_BINS], extent = cbox->hi[axis] - cbox->lo[axis], k;
        int right_n[BVH_BINS], left_n, b;
        if (!(extent > 0.0f)) continue;
        k = (float)BVH_BINS / extent;
        if (!isfinite(k)) continue;                /* extent so small that k overflows */
        for (b = 0; b < BVH_BINS; b++) { box_empty(&bin_box[b]); bin_n[b] = 0; }
        for (i = begin; i < end; i++) {
            const PrimInfo *p = &info[i];
            b = bin_of(p->centroid[axis], cbox->lo[axis], k);
            bin_n[b]++;
            box_grow(&bin_box[b], &p->box);
        }
        /* sweep from the right: area and count of bins [b, BVH_BINS) */
        box_empty(&acc);
        right_n[0] = 0;
        for (b = BVH_BINS - 1; b >= 1; b--) {
            box_grow(&acc, &bin_box[b]);
            right_area[b] = box_half_area(&acc);
            right_n[b] = bin_n[b] + (b + 1 < BVH_BINS ? right_n[b + 1] : 0);
        }
        /* sweep from the left; plane b lies between bins b-1 and b.  The cost is kept
           multiplied by the node's area A, so a flat node (A = 0) needs no division. */
        box_empty(&acc);
        left_n = 0;
        for (b = 1; b < BVH_BINS; b++) {
            float cost;
            box_grow(&acc, &bin_box[b - 1]);
            left_n += bin_n[b - 1];
            if (left_n == 0 || right_n[b] == 0) continue;
            cost = box_half_area(&acc) * (float)left_n + right_area[b] * (float)right_n[b];
            if (cost < best_cost) {
                best_cost = cost; best_axis = axis; best_split = b; k_best = k;
            }
        }
    }
    if (best_axis < 0) return 0;                   /* all centroids coincide */
    /* leaf versus split, both times A:  A N  versus  A C_trav + sum A_i N_i */
    if (n <= BVH_LEAF_MAX &&
        box_half_area(node_box) * (float)n <= box_half_area(node_box) * C_trav + best_cost)
        return 0;

    /* partition: bins below best_split to the front (two-pointer swap, deterministic) */
    lo = begin; hi = end - 1;
    while (lo <= hi) {
        if (bin_of(info[lo].centroid[best_axis], cbox->lo[best_axis], k_best) < best_split)
            lo++;
        else {
            PrimInfo tmp = info[lo]; info[lo] = info[hi]; info[hi] = tmp;
            hi--;
        }
    }
    if (lo == begin || lo == end) return 0;        /* cannot happen; be safe */
    *axis_out = best_axis;
    *mid_out = lo;
    return 1;
}

void bvh_free(Bvh *b)
{
    free(b->node_mem);
    free(b->prims);
    memset(b, 0, sizeof *b);
}

/* The empty slot of a wide node: a box with lo = +inf and hi = -inf, which every
   ray's slab test misses (entry +inf, exit -inf; no NaN, since o is finite). */
static void slot_empty(BvhNode *nd, int j)
{
    int a;
    for (a = 0; a < 3; a++) { nd->box[a][j] = INFINITY; nd->box[3 + a][j] = -INFINITY; }
    nd->child[j] = 0;
}

/* Slot k of a wide node holds the binary node c: its box, and for a leaf the packed
   (first, count), else the wide node index `wide`. */
static void slot_set(BvhNode *nd, int k, const BinNode *c, int32_t wide)
{
    int a;
    for (a = 0; a < 3; a++) { nd->box[a][k] = c->box.lo[a]; nd->box[3 + a][k] = c->box.hi[a]; }
    nd->child[k] = c->sub_count <= BVH_WIDE_LEAF_MAX
                       ? ~(int32_t)(((uint32_t)c->sub_first << 3) | (uint32_t)(c->sub_count - 1))
                       : wide;
}

/* The records of leaf ref (a child reference < 0) sorted by primitive id, by
   insertion (a leaf holds at most BVH_WIDE_LEAF_MAX of them). */
static void leaf_sort(Bvh *b, int32_t ref)
{
    BvhPrim *q = &b->prims[(~ref) >> 3];
    const int n = ((~ref) & 7) + 1;
    int i, j;
    for (i = 1; i < n; i++) {
        const BvhPrim x = q[i];
        for (j = i; j > 0 && q[j - 1].prim > x.prim; j--) q[j] = q[j - 1];
        q[j] = x;
    }
}

/* Collapse the binary tree bin[] (root bin[0], an inner node) into the wide nodes of
   b: each wide node starts from a binary node's two children and opens, while it has
   fewer than BVH_WIDTH children, the inner child of largest surface area (it is the
   one most rays enter), so one wide node replaces up to 7 binary levels.  Leaves stay
   as they are, and so does, as one leaf, an inner child left unopened that holds at
   most BVH_WIDE_LEAF_MAX primitives: without that, the bottom of the tree would be
   full of wide nodes with two or three leaves (on 1.3 M triangles 3.3 children a node
   and 30% more memory than the binary tree; with it 7.5 and less).  Wide nodes are numbered in depth-first order, which keeps a subtree
   close in memory. */
static void collapse(Bvh *b, const BinNode *bin, int32_t *todo_bin, int32_t *todo_wide)
{
    int sp = 0, k;
    todo_bin[sp] = 0; todo_wide[sp] = 0; sp++;
    b->n_nodes = 1;
    while (sp > 0) {
        const int bi = todo_bin[--sp], wi = todo_wide[sp];
        BvhNode *nd = &b->nodes[wi];
        int kids[BVH_WIDTH], n_kids = 2;
        kids[0] = bi + 1;
        kids[1] = bin[bi].first_or_right;
        while (n_kids < BVH_WIDTH) {
            int best = -1;
            float best_area = -1.0f;
            for (k = 0; k < n_kids; k++) {
                const BinNode *c = &bin[kids[k]];
                if (c->count == 0 && box_half_area(&c->box) > best_area) {
                    best = k;
                    best_area = box_half_area(&c->box);
                }
            }
            if (best < 0) break;                   /* only leaves left */
            kids[n_kids++] = bin[kids[best]].first_or_right;   /* open it */
            kids[best] = kids[best] + 1;
        }
        for (k = 0; k < BVH_WIDTH; k++) {
            if (k >= n_kids) { slot_empty(nd, k); continue; }
            slot_set(nd, k, &bin[kids[k]], b->n_nodes);
            if (bin[kids[k]].sub_count > BVH_WIDE_LEAF_MAX) {   /* a wide node to make */
                todo_bin[sp] = kids[k]; todo_wide[sp] = b->n_nodes++; sp++;
            }
        }
        for (k = 0; k < BVH_WIDTH; k++) nd->pad[k] = 0;
    }
}

/* The BVH over the primitives ids[0 .. n): the build works on their positions
   0 .. n - 1 in that list, and the leaves store the ids. */
static int build_ids(Bvh *b, const Scene *s, const int32_t *ids, int n)
{
    PrimInfo *info = NULL;
    BuildTask *stack = NULL;
    BinNode *bin = NULL;
    int32_t *prims = NULL, *todo = NULL;
    int sp = 0, n_bin = 0, n_inner, i, a;
    size_t n_wide;

    memset(b, 0, sizeof *b);
    if (n < 0) return 0;
    if (n == 0) return 1;                          /* empty scene: no nodes, no hits */
    if (n >= (1 << 28)) return 0;                  /* a leaf packs first << 3 in 31 bits */
    info = (PrimInfo *)malloc((size_t)n * sizeof *info);
    stack = (BuildTask *)malloc(((size_t)n + 1) * sizeof *stack);
    bin = (BinNode *)malloc(2 * (size_t)n * sizeof *bin);              /* <= 2n-1 nodes */
    prims = (int32_t *)malloc((size_t)n * sizeof *prims);
    if (!info || !stack || !bin || !prims) {
        free(info); free(stack); free(bin); free(prims);
        return 0;
    }
    for (i = 0; i < n; i++) {
        if (!prim_info(s, ids[i], &info[i])) {
            free(info); free(stack); free(bin); free(prims);
            return 0;
        }
        info[i].index = i;
    }

    /* 1. The binary SAH tree, depth first with an explicit stack (no recursion, so no
       C stack overflow on a degenerate tree): pushing the right task before the left
       one makes the left child the very next node. */
    stack[sp].begin = 0; stack[sp].end = n; stack[sp].parent = -1; stack[sp].depth = 0;
    sp++;
    while (sp > 0) {
        BuildTask task = stack[--sp];
        int node = n_bin++, count = task.end - task.begin, axis = 0, mid = 0, split;
        BinNode *nd = &bin[node];
        Box cbox;
        if (task.parent >= 0) bin[task.parent].first_or_right = node;

        box_empty(&nd->box); box_empty(&cbox);
        for (i = task.begin; i < task.end; i++) {
            box_grow(&nd->box, &info[i].box);
            box_grow_point(&cbox, info[i].centroid);
        }

        split = 0;
        if (count > 1 && task.depth < SAH_DEPTH_MAX)
            split = sah_split(info, task.begin, task.end, &nd->box, &cbox, &axis, &mid);
        if (!split && count > BVH_LEAF_MAX) {
            /* middle split: identical centroids, or too deep for the SAH */
            mid = task.begin + count / 2;
            split = 1;
        }
        if (!split) {                              /* leaf */
            nd->first_or_right = task.begin;
            nd->count = count;                     /* <= BVH_LEAF_MAX */
            continue;
        }
        nd->count = 0;
        nd->first_or_right = -1;                   /* set when the right child is made */
        stack[sp].begin = mid; stack[sp].end = task.end;
        stack[sp].parent = node; stack[sp].depth = task.depth + 1; sp++;
        stack[sp].begin = task.begin; stack[sp].end = mid;
        stack[sp].parent = -1; stack[sp].depth = task.depth + 1; sp++;
    }
    for (i = 0; i < n; i++) prims[i] = info[i].index;   /* the leaves' order */
    free(info);
    free(stack);
    /* every node's range of primitives, bottom up (children come after parents) */
    for (i = n_bin - 1; i >= 0; i--) {
        BinNode *nd = &bin[i];
        if (nd->count > 0) { nd->sub_first = nd->first_or_right; nd->sub_count = nd->count; }
        else {
            nd->sub_first = bin[i + 1].sub_first;
            nd->sub_count = bin[i + 1].sub_count + bin[nd->first_or_right].sub_count;
        }
    }

    /* 2. Collapse it into wide nodes.  Each wide node takes at least one binary inner
       node, so there are at most n_inner of them (one when the root is a leaf). */
    n_inner = (n_bin - 1) / 2;                     /* a binary tree: leaves = inner + 1 */
    n_wide = n_inner > 0 ? (size_t)n_inner : 1;
    b->node_mem = malloc(n_wide * sizeof(BvhNode) + 63);
    b->prims = (BvhPrim *)malloc((size_t)n * sizeof *b->prims);
    todo = (int32_t *)malloc(2 * (n_wide + 1) * sizeof *todo);
    if (!b->node_mem || !b->prims || !todo) {
        free(bin); free(prims); free(todo); bvh_free(b);
        return 0;
    }
    /* align the nodes to a cache line: a node is then exactly four lines */
    b->nodes = (BvhNode *)((char *)b->node_mem + ((64 - (size_t)((uintptr_t)b->node_mem & 63)) & 63));
    for (a = 0; a < 3; a++) { b->bmin[a] = bin[0].box.lo[a]; b->bmax[a] = bin[0].box.hi[a]; }
    if (bin[0].count > 0) {                        /* the root is a leaf: one slot */
        for (i = 1; i < BVH_WIDTH; i++) slot_empty(b->nodes, i);
        slot_set(b->nodes, 0, &bin[0], 0);
        for (i = 0; i < BVH_WIDTH; i++) b->nodes->pad[i] = 0;
        b->n_nodes = 1;
    } else
        collapse(b, bin, todo, todo + n_wide + 1);

    free(bin);                                     /* before b->prims is written */
    bin = NULL;
    /* 3. The primitives' data in leaf order: 9 floats a triangle, 4 a sphere, none
       a quadric or a patch. */
    for (i = 0; i < n; i++) {
        BvhPrim *q = &b->prims[i];
        int p = ids[prims[i]], k;
        q->prim = p;
        if (p < s->n_tris) {
            for (k = 0; k < 3; k++) {
                Vec3 v = s->P[s->tris[p].v[k]];
                q->v[3 * k] = v.x; q->v[3 * k + 1] = v.y; q->v[3 * k + 2] = v.z;
            }
        } else if (p >= s->n_tris + s->n_spheres) {     /* quadric, instance */
            for (k = 0; k < 9; k++) q->v[k] = 0.0f;
        } else {
            const Shape *sh = &s->shapes[s->sphere_shape[p - s->n_tris]];
            q->v[0] = sh->center.x; q->v[1] = sh->center.y; q->v[2] = sh->center.z;
            q->v[3] = sh->radius;
            for (k = 4; k < 9; k++) q->v[k] = 0.0f;
        }
    }
    b->n_prims = n;
    free(prims);
    free(todo);
    /* 4. Each leaf's records sorted by id: triangles (the smallest ids) first, so
       that bvh.c knows from a leaf's last record whether all are triangles */
    for (i = 0; i < b->n_nodes; i++)
        for (a = 0; a < BVH_WIDTH; a++)
            if (b->nodes[i].child[a] < 0) leaf_sort(b, b->nodes[i].child[a]);
    return 1;
}

int bvh_build_object(Bvh *b, const Scene *s, const int32_t *ids, int n)
{
    return build_ids(b, s, ids, n);
}

/* The scene's BVH: every primitive in the world (Shape.in_object == 0) and one
   primitive per instance (instance.c). */
int bvh_build(Bvh *b, const Scene *s)
{
    const int n_base = s->n_tris + s->n_spheres + s->n_quadrics + s->n_patches + s->n_curve_pieces;
    int32_t *ids;
    int n = 0, i, ok;
    memset(b, 0, sizeof *b);
    if (s->n_tris < 0 || s->n_spheres < 0 || s->n_quadrics < 0 || s->n_patches < 0 ||
        s->n_curve_pieces < 0 || n_base < 0 ||
        s->n_instances < 0 || s->n_instances > INT32_MAX - n_base)
        return 0;
    if (n_base + s->n_instances >= (1 << 28)) return 0;   /* a leaf packs first << 3 in 31 bits */
    ids = (int32_t *)malloc(((size_t)n_base + (size_t)s->n_instances + 1) * sizeof *ids);
    if (!ids) return 0;
    for (i = 0; i < n_base; i++) {    /* (prim_info checks the shape indices) */
        const int sh = bvh_prim_shape(s, i);
        if (sh < 0 || s->shapes[sh].in_object == 0) ids[n++] = i;
    }
    for (i = 0; i < s->n_instances; i++) ids[n++] = n_base + i;
    ok = build_ids(b, s, ids, n);
    free(ids);
    return ok;
}
