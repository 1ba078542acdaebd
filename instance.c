/* instance.c - object instancing: pbrt-v4's ObjectBegin / ObjectEnd / ObjectInstance
   as a second level of the BVH.

   WHAT IT IMPLEMENTS (specnee.h section 5)
     instances_prepare        one BVH per object definition, over its primitives in
                              the object's own space, and each instance's world box
     add_instance,            (parser.h) the Instance record of an ObjectInstance or
     instances_resolve        a moving shape, written where it is read; the names of
                              objects defined further down, looked up at the end
   USE: scene.c's ObjectBegin marks the shapes it makes (Shape.in_object) and
   ObjectInstance calls add_instance; scene_load calls instances_resolve and instances_prepare before
   bvh_build, whose top level then holds the world's primitives and one primitive
   per instance.  bvh.c's traversal meets an instance's primitive in a leaf and
   traces the ray, carried into object space (motion.c's instance_ray), through the
   object's BVH, and puts the hit point back into the world (instance_point); this
   room only prepares what those read.  No object's geometry is ever copied: a
   thousand instances of a mesh cost a thousand Instance records.

   THE TRANSFORMS (pbrt-v4 BasicSceneBuilder::Shape and ::ObjectInstance)
     A shape inside ObjectBegin is put into the object's space by the CTM at its own
     Shape directive, C_def, exactly as a shape in the world is put into the world
     (scene.c: vertices by C_def, normals by its inverse transpose, the orientation
     flag from ReverseOrientation and the handedness of C_def).  ObjectInstance
     records M = the CTM at that directive, so a point of the object lands at
         p_world = M C_def p_shape,
     which is pbrt-v4's renderFromInstance = RenderFromObject * worldFromRender
     composed with the shape's renderFromObject.  The object's primitives live in the
     space C_def maps to; only M is applied per ray.

   RAYS AND HITS
     The ray o + t d goes into object space as o' = M^-1 o, d' = M^-1 d (d' is not
     normalised), so a hit keeps its t: the closest hit of the whole scene is the
     smallest t among the world's primitives and the instances' closest hits, ties to
     the smallest top-level id (an instance's id is n_tris + n_spheres + n_quadrics + n_patches + n_curve_pieces +
     its index), as bvh.c's ORDER INDEPENDENCE says; inside an object the object's
     own ids break ties.  The hit point is computed in object space by
     scene_surface_point and carried back: p by M, the geometric and shading
     normals by M's inverse transpose, renormalised, and the shading normal turned to
     the geometric normal's side (pbrt-v4's Transform of a SurfaceInteraction).  The
     transformed normal has the orientation the same shape would get written out in
     the world: M^-T (a x b) = (M a x M b) / det M, so a mirroring M turns the normal
     exactly as the handedness term of geometry.c's flag does.  (u, v), the shape, its
     material and its media are those of the object's shape.

   THE INSTANCE'S BOX
     The eight corners of the object's box are mapped by M in double; their box is
     widened by offset_eps of its largest coordinate (the self-intersection policy's
     distance, bvh.c) on each side.  The culling of bvh.c compares the instance box's
     entry distance, computed from the world ray, with hits computed from the object
     ray: the margin keeps a hit on the object's boundary from being culled by the
     rounding of M^-1 o and M^-1 d.  A moving instance (Instance.motion: a shape or
     an ObjectInstance under two different CTMs, motion.c) has the box of the
     object's box over the whole motion, and each ray uses M(ray time).

   WHAT IS REFUSED (scene.c, with pbrt-v4's own reasons): an ObjectBegin inside an
   object definition, ObjectInstance inside one, ObjectEnd without ObjectBegin, an
   object defined twice, an instance of a name never defined, a projective CTM at
   ObjectInstance, and an area light inside an object definition (pbrt-v4 warns
   "Area lights not supported with object instancing" and makes no light of it).
   An instance of an object with no shapes is dropped, as pbrt-v4 does. */
#include "specnee.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* Each object's BVH over its primitives, gathered by a counting sort on
   Shape.in_object: object k holds ids[off[k] .. off[k + 1]), ascending. */
static int build_objects(Scene *s)
{
    const int n_base = s->n_tris + s->n_spheres + s->n_quadrics + s->n_patches + s->n_curve_pieces;
    int *off = (int *)calloc((size_t)s->n_objects + 1, sizeof(int));
    int *pos = (int *)calloc((size_t)s->n_objects + 1, sizeof(int));
    int32_t *ids = (int32_t *)malloc(((size_t)n_base + 1) * sizeof(int32_t));
    int i, k, ok = 1;
    if (!off || !pos || !ids) { free(off); free(pos); free(ids); return 0; }
    for (i = 0; i < n_base; i++) {
        const int sh = bvh_prim_shape(s, i);
        k = sh >= 0 ? s->shapes[sh].in_object : 0;
        if (k > 0 && k <= s->n_objects) off[k]++;        /* off[k + 1]: count of k */
    }
    for (k = 0; k < s->n_objects; k++) { off[k + 1] += off[k]; pos[k] = off[k]; }
    for (i = 0; i < n_base; i++) {
        const int sh = bvh_prim_shape(s, i);
        k = sh >= 0 ? s->shapes[sh].in_object : 0;
        if (k > 0 && k <= s->n_objects) ids[pos[k - 1]++] = i;
    }
    for (k = 0; ok && k < s->n_objects; k++)
        ok = bvh_build_object(&s->objects[k].bvh, s, ids + off[k], off[k + 1] - off[k]);
    free(off);
    free(pos);
    free(ids);
    return ok;
}

/* The world box of the object box [lo, hi] under M (a moving instance: under
   every M(t), motion.c's motion_bounds), widened (THE INSTANCE'S BOX). */
static int instance_box(const Scene *s, Instance *in, const float lo[3], const float hi[3])
{
    const double (*m)[4] = (const double (*)[4])in->world_from_obj.m;
    double wlo[3] = { DBL_MAX, DBL_MAX, DBL_MAX }, whi[3] = { -DBL_MAX, -DBL_MAX, -DBL_MAX };
    float big = 0.0f, eps;
    int c, a;
    if (in->motion > 0) {
        const double dlo[3] = { lo[0], lo[1], lo[2] }, dhi[3] = { hi[0], hi[1], hi[2] };
        motion_bounds(&s->motions[in->motion - 1], dlo, dhi, wlo, whi);
    } else for (c = 0; c < 8; c++) {
        const double p[3] = { (c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1],
                              (c & 4) ? hi[2] : lo[2] };
        for (a = 0; a < 3; a++) {
            const double w = m[a][0] * p[0] + m[a][1] * p[1] + m[a][2] * p[2] + m[a][3];
            if (w < wlo[a]) wlo[a] = w;
            if (w > whi[a]) whi[a] = w;
        }
    }
    for (a = 0; a < 3; a++) {
        if (!(fabs(wlo[a]) <= FLT_MAX && fabs(whi[a]) <= FLT_MAX)) return 0;
        in->lo[a] = nextafterf((float)wlo[a], -FLT_MAX);
        in->hi[a] = nextafterf((float)whi[a], FLT_MAX);
        if (fabsf(in->lo[a]) > big) big = fabsf(in->lo[a]);
        if (fabsf(in->hi[a]) > big) big = fabsf(in->hi[a]);
    }
    eps = offset_eps(big);
    for (a = 0; a < 3; a++) { in->lo[a] -= eps; in->hi[a] += eps; }
    for (a = 0; a < 3; a++)
        if (!isfinite(in->lo[a]) || !isfinite(in->hi[a])) return 0;
    return 1;
}

int instances_prepare(Scene *s, Error *err)
{
    int i, n = 0;
    if (!build_objects(s)) {
        error_set(err, s->n_objects > 0 ? s->objects[0].file : "", 0,
                  "out of memory building the objects' BVHs");
        return 0;
    }
    for (i = 0; i < s->n_instances; i++) {
        Instance *in = &s->instances[i];
        const Bvh *b = &s->objects[in->object].bvh;
        if (b->n_nodes == 0) continue;                   /* an empty object: dropped */
        s->instances[n] = *in;
        if (!instance_box(s, &s->instances[n], b->bmin, b->bmax)) {
            error_set(err, in->file, in->line, "ObjectInstance \"%s\": not finite after "
                      "the transform", s->objects[in->object].name);
            return 0;
        }
        n++;
    }
    s->n_instances = n;
    return 1;
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   add_instance: the record of an ObjectInstance (scene.c) or a moving shape
   (geometry.c), placed by the parser's CTMs; instances_resolve: the names not
   defined where they were used, looked up when the file has been read (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* The index of the named object defined so far, -1: none (yet). */
static int find_object(Parser *P, const char *name)
{
    const Scene *s = P->s;
    int k = P->last_object;
    if (k < s->n_objects && !s->objects[k].unnamed && !strcmp(s->objects[k].name, name))
        return k;
    for (k = 0; k < s->n_objects; k++)
        if (!s->objects[k].unnamed && !strcmp(s->objects[k].name, name))
            return P->last_object = k;
    return -1;
}

/* One Instance record per ObjectInstance (and per moving shape), written where the
   directive is read: a file that places millions of instances (a Menger sponge of
   3.2 million, docs/loading.md) holds each placement once, its CTM and nothing else.
   A name not defined yet is kept in Parser.uses and looked up by resolve_instances. */
int add_instance(Parser *P, const char *what, const char *name, int object,
                 const char *file, int line)
{
    Scene *s = P->s;
    Instance *in;
    if ((double)(s->n_instances + 1) * sizeof(Instance) > MEM_BUDGET_MIB * 1048576.0)
        return fail(P, file, line, "%s \"%s\": more than %d instances, whose records "
                    "exceed the memory budget MEM_BUDGET_MIB (%d MiB)", what, name,
                    s->n_instances, MEM_BUDGET_MIB);
    if (!grow((void **)&s->instances, &P->cap_instances, s->n_instances + 1, sizeof(Instance)))
        return oom(P, file, line);
    in = &s->instances[s->n_instances];
    memset(in, 0, sizeof *in);
    in->object = object >= 0 ? object : find_object(P, name);
    in->world_from_obj = P->gs.ctm;
    in->file = file;
    in->line = line;
    if (xf_differ(&P->gs.ctm, &P->gs.ctm_end)) {              /* it moves (motion.c) */
        if (!grow((void **)&s->motions, &P->cap_motions, s->n_motions + 1, sizeof(Motion)))
            return oom(P, file, line);
        if (!motion_init(&s->motions[s->n_motions], &P->gs.ctm, P->t0, &P->gs.ctm_end, P->t1))
            return fail(P, file, line, "%s \"%s\": its start and end transforms "
                        "(ActiveTransform) must be rotations, scales and translations "
                        "without a mirror (pbrt-v4 cannot interpolate a mirroring or "
                        "projective transform)", object >= 0 ? "Shape" : "ObjectInstance",
                        name);
        in->motion = ++s->n_motions;
    }
    if (in->object < 0) {                      /* defined further down, or never */
        InstanceUse *u;
        if (!grow((void **)&P->uses, &P->cap_uses, P->n_uses + 1, sizeof(InstanceUse)))
            return oom(P, file, line);
        u = &P->uses[P->n_uses];
        if (!(u->name = keep_string(P, name))) return oom(P, file, line);
        u->instance = s->n_instances;
        u->file = file;
        u->line = line;
        P->n_uses++;
    }
    s->n_instances++;
    return 1;
}

/* The instances whose names were not defined where they were placed, looked up now
   that every ObjectBegin has been read (pbrt-v4: "object instance not defined" at
   the ObjectInstance). */
int instances_resolve(Parser *P)
{
    Scene *s = P->s;
    int i, k;
    for (i = 0; i < P->n_uses; i++) {
        const InstanceUse *u = &P->uses[i];
        if ((k = find_object(P, u->name)) < 0)
            return fail(P, u->file, u->line, "ObjectInstance \"%s\": object instance not "
                        "defined", u->name);
        s->instances[u->instance].object = k;
    }
    return 1;
}
