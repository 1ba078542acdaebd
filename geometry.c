/* geometry.c - the Shape directive: the scene's geometry built from its parameters.

   Implements (parser.h, "5. Each concept built from its parameters"): shape_directive,
   called by scene.c's directive loop for every `Shape`.  It reads the shape's
   "alpha" (every type), then the type's own parameters, and appends to the Scene
   what bvh.c intersects: triangles (trianglemesh, plymesh, loopsubdiv via subdiv.c,
   flat bilinear patches), bilinear patches (patch.c), whole spheres, the
   quadrics of shapes.c (disk, cylinder, cut or scaled spheres) and curves
   (curve.c builds them from their parameters); each as a Shape
   record of the current graphics state (material, area light, media, orientation,
   the object being defined), with its Emitter when an AreaLightSource is active.
   The parameters and their meaning are docs/conventions.md's Shape rows and §3.

   SHAPES AND ORIENTATION
     Vertices go to world space by the CTM, normals by its inverse transpose.
     A shape's orientation flag is
         flip = ReverseOrientation XOR swaps_handedness(CTM)
     (pbrt-v4 TriangleMesh/BilinearPatchMesh): the geometric normal
     n = normalize((p1 - p0) x (p2 - p0)) of a world-space triangle is negated
     when flip is set, which makes one-sided emitters face the side that the
     object-space winding (mapped by the normal transform) gives them.  Vertex
     normals N are negated by ReverseOrientation only, as in pbrt-v4.
     Bilinear patches (p00 p10 p01 p11: bilinearmesh, and a PLY file's quads) are
     patch.c's: a flat one is the two triangles (p00,p10,p11) and (p00,p11,p01)
     with the patch's (u, v), the others are patches of their own.

   EMISSION (pbrt-v4 DiffuseAreaLight::Create)
     Le(lambda) = scale * L(lambda) / sum_lambda ybar(lambda) L(lambda), so a
     light seen directly has luminance Y = scale; lights.c's emitter_radiance
     does the division (per render), its area_light_from_params records L, scale
     and twosided.  For "rgb L" pbrt-v4 divides by the colour space's illuminant
     (D65) instead of by L; we emulate that by multiplying scale by
     sum ybar L / sum ybar D65 (rgb_illuminant_scale, parser.c).

*/
#include "parser.h"
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* ===========================================================================
   1. Appending shapes to the Scene
   =========================================================================== */
/* Append a Shape record for the current graphics state, and its Emitter when an
   AreaLightSource is active.  Returns the shape index or -1. */
static int add_shape(Parser *P, ShapeType type, int tri_begin, int tri_count, double area,
                     int has_normals, const char *file, int line)
{
    Scene *s = P->s;
    Shape *sh;
    int mat;
    if (P->gs.area_light >= 0 && P->cur_object > 0) {
        fail(P, file, line, "Shape inside ObjectBegin \"%s\" under an AreaLightSource: area "
             "lights are not supported with object instancing (pbrt-v4 warns so and makes "
             "no light of it)", s->objects[P->cur_object - 1].name);
        return -1;
    }
    mat = P->gs.material != -1 ? P->gs.material : default_material(P, file, line);
    if (mat == -1) return -1;
    if (!grow((void **)&s->shapes, &P->cap_shapes, s->n_shapes + 1, sizeof(Shape))) {
        oom(P, file, line);
        return -1;
    }
    sh = &s->shapes[s->n_shapes];
    memset(sh, 0, sizeof *sh);
    sh->type = type;
    sh->material = mat;
    sh->emitter = -1;
    /* pbrt-v4: reverseOrientation ^ transformSwapsHandedness */
    sh->flip = (P->gs.reverse != 0) ^ (xf_swaps_handedness(&P->gs.ctm) != 0);
    sh->has_normals = has_normals;
    sh->tri_begin = tri_begin;
    sh->tri_count = tri_count;
    sh->area = area;
    sh->medium_inside = P->gs.medium_inside;
    sh->medium_outside = P->gs.medium_outside;
    sh->in_object = P->cur_object;      /* in an object's space (instance.c) */
    sh->alpha = P->shape_alpha;
    sh->alpha_tex = P->shape_alpha_tex;
    sh->alpha_on = sh->alpha_tex > 0 || sh->alpha < 1.0f;
    s->n_alpha += sh->alpha_on;
    sh->file = file;
    sh->line = line;
    if (P->gs.area_light >= 0) {
        const AreaLightDesc *al = &P->lights[P->gs.area_light];
        Emitter *em;
        if (!grow((void **)&s->emitters, &P->cap_emit, s->n_emitters + 1, sizeof(Emitter))) {
            oom(P, file, line);
            return -1;
        }
        em = &s->emitters[s->n_emitters];
        memset(em, 0, sizeof *em);
        em->shape = s->n_shapes;
        em->L = al->L;
        em->scale = al->scale;
        em->power = al->power;
        em->twosided = al->twosided;
        em->image = al->image;
        em->image_mean = al->image_mean;
        em->y_vis = al->y_vis;
        sh->emitter = s->n_emitters++;
    }
    return s->n_shapes++;
}

/* Same three corner positions, in any order. */
static int same_corners(const Scene *s, const Triangle *a, const Triangle *b)
{
    int i, j, found;
    for (i = 0; i < 3; i++) {
        Vec3 p = s->P[a->v[i]];
        for (found = 0, j = 0; j < 3 && !found; j++) {
            Vec3 q = s->P[b->v[j]];
            found = p.x == q.x && p.y == q.y && p.z == q.z;
        }
        if (!found) return 0;
    }
    return 1;
}

/* Do triangles a and b, of anti-parallel normals (na: a's), lie in one plane
   with interiors that overlap?  b's corners lie within 1e-5 of the triangles'
   size from a's plane; in that plane (the axis of na's largest component
   dropped) no edge of either triangle has the other wholly on its outer side
   (the separating-axis test of two convex polygons; a shared edge separates). */
static int overlap_in_plane(const Scene *s, const Triangle *a, const Triangle *b, Vec3 na)
{
    Vec3 p[2][3];
    float q[2][3][2], size = 0.0f, nl = v3_len(na);
    int ax = fabsf(na.x) > fabsf(na.y) ? (fabsf(na.x) > fabsf(na.z) ? 0 : 2)
                                         : (fabsf(na.y) > fabsf(na.z) ? 1 : 2);
    int k, i, j;
    for (i = 0; i < 3; i++) { p[0][i] = s->P[a->v[i]]; p[1][i] = s->P[b->v[i]]; }
    for (k = 0; k < 2; k++)
        for (i = 0; i < 3; i++) size = fmaxf(size, v3_len(v3_sub(p[k][(i + 1) % 3], p[k][i])));
    for (i = 0; i < 3; i++)
        if (fabsf(v3_dot(na, v3_sub(p[1][i], p[0][0]))) > 1e-5f * size * nl) return 0;
    for (k = 0; k < 2; k++)
        for (i = 0; i < 3; i++) {
            q[k][i][0] = ax == 0 ? p[k][i].y : p[k][i].x;
            q[k][i][1] = ax == 2 ? p[k][i].y : p[k][i].z;
        }
    for (k = 0; k < 2; k++) {
        float (*x)[2] = q[k], (*y)[2] = q[1 - k];
        float o = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[1][1] - x[0][1]) * (x[2][0] - x[0][0]);
        for (i = 0; i < 3; i++) {
            float ex = x[(i + 1) % 3][0] - x[i][0], ey = x[(i + 1) % 3][1] - x[i][1];
            float eps = 1e-5f * size * sqrtf(ex * ex + ey * ey), least = FLT_MAX;
            for (j = 0; j < 3; j++)                     /* > 0: outside edge i */
                least = fminf(least, (o > 0.0f ? -1.0f : 1.0f)
                                     * (ex * (y[j][1] - x[i][1]) - ey * (y[j][0] - x[i][0])));
            if (least >= -eps) return 0;                /* edge i of one separates them */
        }
    }
    return 1;
}

/* An emitting mesh with two triangles of opposite windings that lie on each other
   (an exporter's way to light both sides: the same three corners twice) or
   overlap in one plane (a quad's indices written wrong) gets a note: rays meet
   both at the same t, and which one is seen is a tie, broken in specnee by the
   smaller index (the earlier in the file) and in pbrt-v4 by the order its BVH
   build gives them or by the rounding of each t.  In both renderers next event
   estimation reaches the emitting side through its twin while BSDF sampling may
   stop at the twin's back, so the image means no definite surface there
   (docs/conventions.md §3).  Meshes of at most 4096 triangles are checked
   (pairs: at most 8.4 million comparisons). */
static void coincident_note(const Scene *s, int t0, int ntri, const char *file, int line)
{
    int i, j;
    if (ntri > 4096) return;
    for (i = t0; i < t0 + ntri; i++)
        for (j = i + 1; j < t0 + ntri; j++) {
            const Triangle *a = &s->tris[i], *b = &s->tris[j];
            Vec3 na, nb;
            int same;
            na = v3_cross(v3_sub(s->P[a->v[1]], s->P[a->v[0]]), v3_sub(s->P[a->v[2]], s->P[a->v[0]]));
            nb = v3_cross(v3_sub(s->P[b->v[1]], s->P[b->v[0]]), v3_sub(s->P[b->v[2]], s->P[b->v[0]]));
            if (!(v3_dot(na, nb) < -0.9999f * v3_len(na) * v3_len(nb))) continue;
            same = same_corners(s, a, b);
            if (!same && !overlap_in_plane(s, a, b, na)) continue;
            fprintf(stderr, "%s:%d: note: area light: triangles %d and %d of this mesh %s "
                    "with opposite windings; the earlier one is seen where both are hit "
                    "(pbrt-v4: the one its BVH tests first), so the light's two sides do not add up\n",
                    file, line, i - t0, j - t0, same ? "lie on each other" : "overlap in one plane");
            return;
        }
}

/* Append a triangle mesh given in object space (P: 3 floats a vertex, N: the
   same or NULL, idx: 3 ints a triangle, already range-checked). */
static int add_mesh(Parser *P, const float *Pobj, const float *Nobj, const float *UVobj, int nv,
                    const int32_t *idx, int ntri, const char *file, int line)
{
    Scene *s = P->s;
    int v0 = s->n_verts, t0 = s->n_tris, i;
    double area = 0.0;
    const Xform *ctm = &P->gs.ctm;
    if (nv > MAX_ELEMENTS - s->n_verts || ntri > MAX_ELEMENTS - s->n_tris)
        return oom(P, file, line);
    if (!grow((void **)&s->P, &P->cap_verts, s->n_verts + nv, sizeof(Vec3)))
        return oom(P, file, line);
    {   /* N stays parallel to P; it is allocated when the first normals appear */
        int cap = P->cap_verts;
        if (Nobj || P->any_normals) {
            if (!P->any_normals) {
                s->N = (Vec3 *)calloc((size_t)cap, sizeof(Vec3));
                if (!s->N) return oom(P, file, line);
                P->any_normals = 1;
            } else {
                Vec3 *nn = (Vec3 *)realloc(s->N, (size_t)cap * sizeof(Vec3));
                if (!nn) return oom(P, file, line);
                s->N = nn;
            }
        }
        /* UV likewise: 2 floats a vertex once the first mesh with "uv" appears */
        if (UVobj || P->any_uv) {
            if (!P->any_uv) {
                s->UV = (float *)calloc((size_t)cap * 2, sizeof(float));
                if (!s->UV) return oom(P, file, line);
                P->any_uv = 1;
            } else {
                float *nu = (float *)realloc(s->UV, (size_t)cap * 2 * sizeof(float));
                if (!nu) return oom(P, file, line);
                s->UV = nu;
            }
        }
    }
    if (!grow((void **)&s->tris, &P->cap_tris, s->n_tris + ntri, sizeof(Triangle)))
        return oom(P, file, line);
    for (i = 0; i < nv; i++) {
        Vec3 p = xf_point(ctm, v3(Pobj[3 * i], Pobj[3 * i + 1], Pobj[3 * i + 2]));
        if (!(fabsf(p.x) <= FLT_MAX && fabsf(p.y) <= FLT_MAX && fabsf(p.z) <= FLT_MAX))
            return fail(P, file, line, "vertex %d is not finite after the transform", i);
        s->P[v0 + i] = p;
        if (s->N) {
            Vec3 n = v3(0, 0, 0);
            if (Nobj) {
                n = xf_normal(ctm, v3(Nobj[3 * i], Nobj[3 * i + 1], Nobj[3 * i + 2]));
                if (!(v3_len(n) > 0.0f) || !(v3_len(n) <= FLT_MAX))
                    return fail(P, file, line, "normal %d has zero or non-finite length", i);
                n = v3_norm(n);
                if (P->gs.reverse) n = v3_neg(n);      /* pbrt-v4: RO flips N */
            }
            s->N[v0 + i] = n;
        }
        if (s->UV) {
            if (UVobj && !(isfinite(UVobj[2 * i]) && isfinite(UVobj[2 * i + 1])))
                return fail(P, file, line, "uv %d is not finite", i);
            s->UV[2 * (v0 + i)] = UVobj ? UVobj[2 * i] : 0.0f;
            s->UV[2 * (v0 + i) + 1] = UVobj ? UVobj[2 * i + 1] : 0.0f;
        }
    }
    for (i = 0; i < ntri; i++) {
        Triangle *t = &s->tris[t0 + i];
        Vec3 a, b, c;
        t->v[0] = v0 + idx[3 * i];
        t->v[1] = v0 + idx[3 * i + 1];
        t->v[2] = v0 + idx[3 * i + 2];
        t->shape = s->n_shapes;
        a = s->P[t->v[0]]; b = s->P[t->v[1]]; c = s->P[t->v[2]];
        area += 0.5 * (double)v3_len(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    }
    s->n_verts += nv;
    s->n_tris += ntri;
    {
        int sh = add_shape(P, SHAPE_MESH, t0, ntri, area, Nobj != NULL, file, line);
        if (sh < 0) return 0;
        s->shapes[sh].has_uv = UVobj != NULL;
        if (s->shapes[sh].emitter >= 0) coincident_note(s, t0, ntri, file, line);
    }
    return 1;
}

/* ===========================================================================
   2. The shapes, each from its parameters
   =========================================================================== */
/* Read vertex and index arrays common to the two mesh shapes. */
static int get_points(Parser *P, ParamList *pl, ParamType type, const char *name, int per,
                      const double **out, int *count)
{
    Param *p = param_find(pl, type, name);
    *out = NULL;
    *count = 0;
    if (!p) return 1;
    if (p->n_num % per != 0)
        return fail(P, p->file, p->line, "\"%s %s\": %d values, not a multiple of %d",
                    param_type_names[type], name, p->n_num, per);
    *out = p->num;
    *count = p->n_num / per;
    return 1;
}

/* Whether the patch q (4 indices into the object-space points Pf) is flat
   (patch.c), i.e. stored as two triangles. */
static int patch_flat_at(const float *Pf, const int32_t q[4])
{
    Vec3 c[4];
    int k;
    for (k = 0; k < 4; k++) c[k] = v3(Pf[3 * q[k]], Pf[3 * q[k] + 1], Pf[3 * q[k] + 2]);
    return patch_is_flat(c);
}

/* The patches q (4 indices each) of the bilinear mesh just added (its vertices from
   v0 on) that are not flat: Scene.patches of the last shape, their areas added to
   its area. */
static int bilinear_patches(Parser *P, const float *Pf, const int32_t *q, int n, int v0,
                            const char *file, int line)
{
    Scene *s = P->s;
    Shape *sh = &s->shapes[s->n_shapes - 1];
    int i, k;
    sh->bilinear = 1;
    sh->patch_begin = s->n_patches;
    for (i = 0; i < n; i++) {
        Patch *pa;
        Vec3 c[4];
        if (patch_flat_at(Pf, q + 4 * i)) continue;
        if (!grow((void **)&s->patches, &P->cap_patches, s->n_patches + 1, sizeof(Patch)))
            return oom(P, file, line);
        pa = &s->patches[s->n_patches++];
        for (k = 0; k < 4; k++) pa->v[k] = v0 + q[4 * i + k];
        pa->shape = s->n_shapes - 1;
        patch_corners(s, pa->v, c);
        sh->area += patch_area(c);
        sh->patch_count++;
    }
    return 1;
}

/* Append a bilinear patch mesh given in object space (P, N, UV as for add_mesh;
   q: 4 indices a patch in pbrt's order p00 p10 p01 p11, range-checked) as one
   Shape.  A flat patch (patch.c) is the two triangles (p00,p10,p11), (p00,p11,p01):
   the first edge pair (p10 - p00, p11 - p00) keeps the patch's dp/du x dp/dv side.
   The others follow the mesh as patches of their own (bilinear_patches). */
static int add_patch_mesh(Parser *P, const float *Pf, const float *Nf, const float *UVf, int nv,
                          const int32_t *q, int nq, const char *file, int line)
{
    const int v0 = P->s->n_verts;
    int32_t *idx = (int32_t *)calloc(6 * (size_t)nq + 1, sizeof(int32_t));
    int i, ntri = 0, ok;
    if (!idx) return oom(P, file, line);
    for (i = 0; i < nq; i++) {
        const int32_t *c = q + 4 * i;
        if (!patch_flat_at(Pf, c)) continue;
        idx[3 * ntri + 0] = c[0]; idx[3 * ntri + 1] = c[1]; idx[3 * ntri + 2] = c[3];
        idx[3 * ntri + 3] = c[0]; idx[3 * ntri + 4] = c[3]; idx[3 * ntri + 5] = c[2];
        ntri += 2;
    }
    ok = add_mesh(P, Pf, Nf, UVf, nv, idx, ntri, file, line) &&
         bilinear_patches(P, Pf, q, nq, v0, file, line);
    free(idx);
    return ok;
}

/* The "vector3 S" of the mesh just added (its nv vertices from v0 on): carried to
   the world by the CTM as vectors (pbrt-v4's TriangleMesh, not flipped by
   ReverseOrientation) into Scene.S, which grows to cover them. */
static int mesh_tangents(Parser *P, const double *Sd, int nv, int v0, const char *file, int line)
{
    Scene *s = P->s;
    int i;
    if (!grow((void **)&s->S, &P->cap_tangents, v0 + nv, sizeof(Vec3))) return oom(P, file, line);
    for (i = 0; i < nv; i++) {
        Vec3 v = xf_vector(&P->gs.ctm, v3((float)Sd[3 * i], (float)Sd[3 * i + 1], (float)Sd[3 * i + 2]));
        if (!(fabsf(v.x) <= FLT_MAX && fabsf(v.y) <= FLT_MAX && fabsf(v.z) <= FLT_MAX))
            return fail(P, file, line, "S vector %d is not finite after the transform", i);
        s->S[v0 + i] = v;
    }
    s->shapes[s->n_shapes - 1].has_tangents = 1;
    return 1;
}

/* A bilinearmesh's "string emissionfilename": pbrt-v4 reads the image (a missing
   or broken file stops it) and uses it only to sample points on the patches by
   the image's brightness when the mesh is an area light; the radiance stays the
   AreaLightSource's, and another density for the same points changes no
   expected value, so specnee reads and checks the file and samples by area (a
   note says so).  With "uv" pbrt-v4 ignores the file (an error message, and it
   renders on), and so does specnee, with a note. */
static int emission_file(Parser *P, const char *fn, int has_uv, const char *file, int line)
{
    Image im;
    if (has_uv) {
        fprintf(stderr, "%s:%d: note: Shape \"bilinearmesh\": \"emissionfilename\" is ignored with "
                "\"uv\", as pbrt-v4 does\n", file, line);
        return 1;
    }
    if (!emission_image_read(P, fn, "Shape \"bilinearmesh\"", file, line, &im)) return 0;
    img_free(&im);
    fprintf(stderr, "%s:%d: note: Shape \"bilinearmesh\": \"emissionfilename\" %s is read and "
            "ignored: pbrt-v4 samples light points by it, which changes no expected value "
            "(docs/coverage.md)\n", file, line, fn);
    return 1;
}

static int mesh_shape(Parser *P, int bilinear, ParamList *pl, const char *file, int line)
{
    const double *Pd, *Nd, *UV, *Id, *Fd, *Sd = NULL;
    int nv, nn, nuv, ni, nf, nsv = 0, per = bilinear ? 4 : 3, i, ok, v0 = P->s->n_verts;
    const char *what = bilinear ? "Shape \"bilinearmesh\"" : "Shape \"trianglemesh\"", *efn = NULL;
    float *Pf = NULL, *Nf = NULL, *UVf = NULL;
    int32_t *idx = NULL;
    int32_t deflt[4] = { 0, 1, 2, 3 };
    if (!get_points(P, pl, PT_INTEGER, "indices", 1, &Id, &ni)) return 0;
    if (!get_points(P, pl, PT_POINT3, "P", 3, &Pd, &nv)) return 0;
    if (!get_points(P, pl, PT_NORMAL, "N", 3, &Nd, &nn)) return 0;
    if (!get_points(P, pl, PT_POINT2, "uv", 2, &UV, &nuv)) return 0;
    /* "faceIndices": pbrt-v4 reads them only for Ptex lookups (a face's texture),
       which specnee refuses by name, so they are checked and not kept */
    if (!get_points(P, pl, PT_INTEGER, "faceIndices", 1, &Fd, &nf)) return 0;
    /* "S" (trianglemesh only): per-vertex tangents, the shading frame's dp/du */
    if (!bilinear && !get_points(P, pl, PT_VECTOR3, "S", 3, &Sd, &nsv)) return 0;
    if (bilinear && !get_string(P, pl, "emissionfilename", &efn)) return 0;
    if (!params_check_unused(P, pl, what, bilinear ? "integer indices, point3 P, normal N, "
                             "point2 uv, integer faceIndices, string emissionfilename"
                             : "integer indices, point3 P, normal N, point2 uv, "
                             "integer faceIndices, vector3 S",
                             bilinear ? "displacement" : "emissionfilename displacement"))
        return 0;
    if (nv == 0) return fail(P, file, line, "%s: \"point3 P\" is required", what);
    if (ni == 0 && nv != per)
        return fail(P, file, line, "%s: \"integer indices\" is required unless there are "
                    "exactly %d vertices", what, per);
    if (ni % per != 0)
        return fail(P, file, line, "%s: %d indices is not a multiple of %d", what, ni, per);
    if (nn && nn != nv)
        return fail(P, file, line, "%s: %d normals for %d vertices", what, nn, nv);
    if (nuv && nuv != nv)
        return fail(P, file, line, "%s: %d uv pairs for %d vertices", what, nuv, nv);
    if (nsv && nsv != nv)
        return fail(P, file, line, "%s: %d S vectors for %d vertices", what, nsv, nv);
    if (efn && efn[0] && !emission_file(P, efn, nuv > 0, file, line)) return 0;
    if (ni == 0) ni = per;
    if (nf && nf != ni / per)
        return fail(P, file, line, "%s: %d faceIndices for %d %s%s (one a face, as in "
                    "pbrt-v4)", what, nf, ni / per, bilinear ? "patch" : "triangle",
                    ni / per == 1 ? "" : bilinear ? "es" : "s");
    for (i = 0; i < ni; i++) {
        int k = Id ? (int)Id[i] : deflt[i];
        if (k < 0 || k >= nv)
            return fail(P, file, line, "%s: vertex index %d out of range [0, %d)", what, k, nv);
    }
    Pf = (float *)malloc(sizeof(float) * 3 * (size_t)nv);
    Nf = nn ? (float *)malloc(sizeof(float) * 3 * (size_t)nv) : NULL;
    idx = (int32_t *)malloc(sizeof(int32_t) * (size_t)ni);
    UVf = nuv ? (float *)malloc(sizeof(float) * 2 * (size_t)nv) : NULL;
    if (!Pf || !idx || (nn && !Nf) || (nuv && !UVf)) {
        free(Pf); free(Nf); free(UVf); free(idx);
        return oom(P, file, line);
    }
    for (i = 0; i < 3 * nv; i++) {
        Pf[i] = (float)Pd[i];
        if (Nf) Nf[i] = (float)Nd[i];
    }
    for (i = 0; i < 2 * nv && UVf; i++) UVf[i] = (float)UV[i];
    for (i = 0; i < ni; i++) idx[i] = Id ? (int32_t)Id[i] : deflt[i];
    ok = bilinear ? add_patch_mesh(P, Pf, Nf, UVf, nv, idx, ni / 4, file, line)
                  : add_mesh(P, Pf, Nf, UVf, nv, idx, ni / 3, file, line);
    free(Pf); free(Nf); free(UVf); free(idx);
    return ok && (!nsv || mesh_tangents(P, Sd, nv, v0, file, line));
}

/* A quadric (shapes.c) with the given object-space parameters under the CTM: a
   new Shape and an entry of Scene.quadric_shape.  what: "Shape \"disk\"" etc. */
static int add_quadric(Parser *P, ShapeType type, const Quadric *params, const char *what,
                       const char *file, int line)
{
    Scene *s = P->s;
    Shape *shp;
    float lo[3], hi[3];
    int sh, a;
    if (!grow((void **)&s->quadric_shape, &P->cap_quadrics, s->n_quadrics + 1, sizeof(int)))
        return oom(P, file, line);
    sh = add_shape(P, type, 0, 0, 0.0, 0, file, line);
    if (sh < 0) return 0;
    shp = &s->shapes[sh];
    shp->q = *params;
    if (!quadric_set_transform(&shp->q, &P->gs.ctm))
        return fail(P, file, line, "%s: projective transform not supported", what);
    shp->area = quadric_area(shp);
    quadric_bounds(shp, lo, hi);
    for (a = 0; a < 3; a++)
        if (!isfinite(lo[a]) || !isfinite(hi[a]) || !(hi[a] - lo[a] <= FLT_MAX))
            return fail(P, file, line, "%s: not finite after the transform", what);
    if (!(shp->area > 0.0) || !isfinite(shp->area))
        return fail(P, file, line, "%s: zero or non-finite area after the transform", what);
    s->quadric_shape[s->n_quadrics++] = sh;
    return 1;
}

/* Read "float NAME" (default def) into *out; fails on a value that is not finite
   as a float (the token was finite, but e.g. 1e300 is not a float). */
static int get_finite(Parser *P, ParamList *pl, const char *what, const char *name, float def,
                      double *out, const char *file, int line)
{
    float v;
    if (!get_float(P, pl, name, def, &v)) return 0;
    if (!isfinite(v)) return fail(P, file, line, "%s: \"float %s\" is not finite", what, name);
    *out = v;
    return 1;
}

/* phimax in degrees, as the file gives it, checked and turned into radians. */
static int check_phimax(Parser *P, const char *what, double deg, double *rad, const char *file, int line)
{
    if (!(deg > 0.0 && deg <= 360.0))
        return fail(P, file, line, "%s: phimax %g must lie in (0, 360] degrees", what, deg);
    *rad = deg >= 360.0 ? 2.0 * SPECNEE_PI : deg * (SPECNEE_PI / 180.0);
    return 1;
}

/* Shape "disk" (pbrt-v4 Disk::Create): float height 0, radius 1, innerradius 0,
   phimax 360. */
static int disk_shape(Parser *P, ParamList *pl, const char *file, int line)
{
    const char *what = "Shape \"disk\"";
    Quadric q;
    double deg = 360.0;
    memset(&q, 0, sizeof q);
    if (!get_finite(P, pl, what, "height", 0.0f, &q.height, file, line) ||
        !get_finite(P, pl, what, "radius", 1.0f, &q.radius, file, line) ||
        !get_finite(P, pl, what, "innerradius", 0.0f, &q.inner, file, line) ||
        !get_finite(P, pl, what, "phimax", 360.0f, &deg, file, line))
        return 0;
    if (!params_check_unused(P, pl, what, "float height, float radius, float innerradius, "
                             "float phimax", "emissionfilename"))
        return 0;
    if (!(q.radius > 0.0)) return fail_param(P, pl, "radius", file, line, "%s: radius %g must be > 0", what, q.radius);
    if (!(q.inner >= 0.0 && q.inner < q.radius))
        return fail_param(P, pl, "innerradius", file, line, "%s: innerradius %g must lie in [0, radius %g)", what, q.inner,
                    q.radius);
    if (!check_phimax(P, what, deg, &q.phimax, file, line)) return 0;
    return add_quadric(P, SHAPE_DISK, &q, what, file, line);
}

/* Shape "cylinder" (pbrt-v4 Cylinder::Create): float radius 1, zmin -1, zmax 1,
   phimax 360; open at both ends. */
static int cylinder_shape(Parser *P, ParamList *pl, const char *file, int line)
{
    const char *what = "Shape \"cylinder\"";
    Quadric q;
    double deg = 360.0;
    memset(&q, 0, sizeof q);
    if (!get_finite(P, pl, what, "radius", 1.0f, &q.radius, file, line) ||
        !get_finite(P, pl, what, "zmin", -1.0f, &q.zmin, file, line) ||
        !get_finite(P, pl, what, "zmax", 1.0f, &q.zmax, file, line) ||
        !get_finite(P, pl, what, "phimax", 360.0f, &deg, file, line))
        return 0;
    if (!params_check_unused(P, pl, what, "float radius, float zmin, float zmax, float phimax",
                             "emissionfilename"))
        return 0;
    if (!(q.radius > 0.0)) return fail_param(P, pl, "radius", file, line, "%s: radius %g must be > 0", what, q.radius);
    if (q.zmin > q.zmax) {                    /* pbrt-v4 Cylinder: min and max of the pair */
        double z = q.zmin;
        q.zmin = q.zmax;
        q.zmax = z;
    }
    if (!(q.zmin < q.zmax))
        return fail(P, file, line, "%s: zmin = zmax = %g: the cylinder has no height", what, q.zmin);
    if (!check_phimax(P, what, deg, &q.phimax, file, line)) return 0;
    return add_quadric(P, SHAPE_CYLINDER, &q, what, file, line);
}

static int sphere_shape(Parser *P, ParamList *pl, const char *file, int line)
{
    Scene *s = P->s;
    const double (*m)[4] = (const double (*)[4])P->gs.ctm.m;
    const char *what = "Shape \"sphere\"";
    float radius;
    double col[3][3], len[3], scale, zmin = 0.0, zmax = 0.0, deg = 360.0;
    int i, j, sh, uniform = 1;
    if (!get_float(P, pl, "radius", 1.0f, &radius)) return 0;
    if (!get_finite(P, pl, what, "zmin", -radius, &zmin, file, line) ||
        !get_finite(P, pl, what, "zmax", radius, &zmax, file, line) ||
        !get_finite(P, pl, what, "phimax", 360.0f, &deg, file, line))
        return 0;
    if (!params_check_unused(P, pl, what, "float radius, float zmin, float zmax, float phimax",
                             "emissionfilename"))
        return 0;
    if (!(radius > 0.0f) || !isfinite(radius))
        return fail_param(P, pl, "radius", file, line, "Shape \"sphere\": radius %g must be > 0", radius);
    /* The CTM's 3x3 part must be a uniform scale times a rotation (or mirror):
       its columns are orthogonal and equally long. */
    for (j = 0; j < 3; j++) {
        for (i = 0; i < 3; i++) col[j][i] = m[i][j];
        len[j] = sqrt(col[j][0] * col[j][0] + col[j][1] * col[j][1] + col[j][2] * col[j][2]);
    }
    scale = len[0];
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0)
        return fail(P, file, line, "Shape \"sphere\": projective transform not supported");
    for (j = 0; j < 3; j++) {
        int k = (j + 1) % 3;
        double dot = col[j][0] * col[k][0] + col[j][1] * col[k][1] + col[j][2] * col[k][2];
        if (fabs(len[j] - scale) > 1e-5 * scale || fabs(dot) > 1e-5 * scale * scale)
            uniform = 0;
    }
    if (zmin > zmax) {                        /* pbrt-v4 Sphere: min and max of the pair */
        double z = zmin;
        zmin = zmax;
        zmax = z;
    }
    if (!(zmin < zmax))
        return fail(P, file, line, "%s: zmin = zmax = %g: the sphere has no height", what, zmin);
    if (!(zmax > -radius && zmin < radius))
        return fail(P, file, line, "%s: zmin %g .. zmax %g misses the sphere of radius %g", what,
                    zmin, zmax, radius);
    {
        Quadric q;
        memset(&q, 0, sizeof q);
        if (!check_phimax(P, what, deg, &q.phimax, file, line)) return 0;
        if (zmin > -radius || zmax < radius || q.phimax < 2.0 * SPECNEE_PI || !uniform) {
            /* cut, or under a non-uniform scale: intersected in object space (shapes.c);
               pbrt-v4 clamps zmin and zmax to the sphere */
            q.radius = radius;
            q.zmin = zmin > -radius ? zmin : -(double)radius;
            q.zmax = zmax < radius ? zmax : (double)radius;
            return add_quadric(P, SHAPE_SPHERE_PART, &q, what, file, line);
        }
    }
    if (!grow((void **)&s->sphere_shape, &P->cap_spheres, s->n_spheres + 1, sizeof(int)))
        return oom(P, file, line);
    {
        double r = (double)radius * scale;
        sh = add_shape(P, SHAPE_SPHERE, 0, 0, 4.0 * SPECNEE_PI * r * r, 0, file, line);
        if (sh < 0) return 0;
        s->shapes[sh].center = xf_point(&P->gs.ctm, v3(0, 0, 0));
        s->shapes[sh].q.world_from_obj = P->gs.ctm;   /* bvh.c: (u, v) in object space */
        s->shapes[sh].radius = (float)r;
        if (!(s->shapes[sh].radius > 0.0f && s->shapes[sh].radius <= FLT_MAX))
            return fail(P, file, line, "Shape \"sphere\": radius not finite after the transform");
    }
    s->sphere_shape[s->n_spheres++] = sh;
    return 1;
}

/* Shape "plymesh" (pbrt-v4's plymesh): the file's triangles make a triangle mesh
   and its quads a bilinear patch mesh (ply.c gives them in the patch's order), two
   Shapes with the same material, light and media when the file has both. */
static int ply_shape(Parser *P, ParamList *pl, const char *file, int line)
{
    const char *fn;
    char path[PATH_CAP];
    PlyMesh mesh;
    Error e;
    int ok, i, tex = -1;
    float edge;
    const Param *pd = param_find(pl, PT_TEXTURE, "displacement");
    if (!get_string(P, pl, "filename", &fn) || !get_float(P, pl, "edgelength", 1.0f, &edge)) return 0;
    if (pd && (tex = texture_lookup(P, pd, 1)) < 0) return 0;
    if (!params_check_unused(P, pl, "Shape \"plymesh\"", "string filename, texture displacement, "
                             "float edgelength", "emissionfilename"))
        return 0;
    if (!fn) return fail(P, file, line, "Shape \"plymesh\": \"string filename\" is required");
    if (!(edge > 0.0f && edge <= FLT_MAX))
        return fail(P, file, line, "Shape \"plymesh\": \"float edgelength\" %g must be > 0 and finite",
                    (double)edge);
    resolve_path(P, file, fn, path, sizeof path);
    memset(&mesh, 0, sizeof mesh);
    if (!ply_read(path, &mesh, &e))
        return fail(P, file, line, "Shape \"plymesh\": %s", e.msg);
    for (i = 0; i < 3 * mesh.n_tris + 4 * mesh.n_quads; i++) {
        int32_t k = i < 3 * mesh.n_tris ? mesh.idx[i] : mesh.quads[i - 3 * mesh.n_tris];
        if (k < 0 || k >= mesh.n_verts) {
            ply_free(&mesh);
            return fail(P, file, line, "Shape \"plymesh\" \"%s\": vertex index out of range", fn);
        }
    }
    if (tex >= 0) {                /* displace.c: refined and displaced at load, as pbrt-v4 */
        if (!mesh.UV) {
            ply_free(&mesh);
            return fail(P, file, line, "Shape \"plymesh\" \"%s\": \"texture displacement\" needs "
                        "per-vertex uv in the file (pbrt-v4 refuses it too)", fn);
        }
        /* pbrt-v4 multiplies every displaced mesh's edgelength by the Option
           "displacementedgescale" (Options->displacementEdgeScale, 1 by default) */
        if (P->edge_scale_set) edge *= P->edge_scale;
        if (!(edge > 0.0f && edge <= FLT_MAX)) {
            ply_free(&mesh);
            return fail(P, file, line, "Shape \"plymesh\": \"float edgelength\" times Option "
                        "\"displacementedgescale\" %g is %g (must be > 0 and finite)",
                        (double)P->edge_scale, (double)edge);
        }
        if (!P->displaced_file) {
            P->displaced_file = file;
            P->displaced_line = line;
        }
        if (!ply_displace(&mesh, &P->gs.ctm, edge, P->s->textures, tex, &e)) {
            ply_free(&mesh);
            return fail(P, file, line, "Shape \"plymesh\" \"%s\": %s", fn, e.msg);
        }
    }
    ok = 1;
    if (mesh.n_tris > 0 || mesh.n_quads == 0)
        ok = add_mesh(P, mesh.P, mesh.N, mesh.UV, mesh.n_verts, mesh.idx, mesh.n_tris, file, line);
    if (ok && mesh.n_quads > 0)
        ok = add_patch_mesh(P, mesh.P, mesh.N, mesh.UV, mesh.n_verts, mesh.quads, mesh.n_quads,
                            file, line);
    ply_free(&mesh);
    return ok;
}

/* pbrt-v4 "loopsubdiv": a control mesh of triangles ("integer indices", "point3 P")
   refined by "integer levels" (3) steps of Loop's scheme at load time (subdiv.c),
   then added as a triangle mesh with its limit normals.  "string scheme" is read
   and ignored, as pbrt-v4 does; a negative levels is 0, as there. */
static int loopsubdiv_shape(Parser *P, ParamList *pl, const char *file, int line)
{
    const char *what = "Shape \"loopsubdiv\"", *scheme;
    const double *Pd, *Id;
    int nv, ni, levels, i, ok;
    double ntri;
    int32_t *idx;
    SubdivMesh m;
    Error e;
    if (!get_points(P, pl, PT_INTEGER, "indices", 1, &Id, &ni)) return 0;
    if (!get_points(P, pl, PT_POINT3, "P", 3, &Pd, &nv)) return 0;
    if (!get_int(P, pl, "levels", 3, &levels, NULL) || !get_string(P, pl, "scheme", &scheme))
        return 0;
    {
        const Param *v3 = param_find(pl, PT_INTEGER, "nlevels");
        if (v3)
            return fail(P, v3->file, v3->line, "%s: \"integer nlevels\" is pbrt-v3's name; pbrt-v4 "
                        "reads \"integer levels\" (pbrt --upgrade renames it)", what);
    }
    if (!params_check_unused(P, pl, what, "integer levels, integer indices, point3 P, string scheme",
                             "emissionfilename"))
        return 0;
    if (ni == 0) return fail(P, file, line, "%s: \"integer indices\" is required", what);
    if (nv == 0) return fail(P, file, line, "%s: \"point3 P\" is required", what);
    if (ni % 3 != 0)
        return fail(P, file, line, "%s: %d indices is not a multiple of 3", what, ni);
    if (levels < 0) levels = 0;
    for (i = 0, ntri = ni / 3; i < levels; i++) ntri *= 4.0;
    if (ntri > MAX_ELEMENTS || ntri * SUBDIV_BYTES_PER_TRI > MEM_BUDGET_MIB * 1048576.0)
        return fail(P, file, line, "%s: %d levels make %.0f triangles (at most %d, and %.0f within "
                    "the memory budget MEM_BUDGET_MIB in specnee.h)", what, levels, ntri, MAX_ELEMENTS,
                    floor(MEM_BUDGET_MIB * 1048576.0 / SUBDIV_BYTES_PER_TRI));
    idx = (int32_t *)malloc(sizeof(int32_t) * (size_t)ni);
    if (!idx) return oom(P, file, line);
    for (i = 0; i < ni; i++) {
        if (!(Id[i] >= 0 && Id[i] < nv)) {
            free(idx);
            return fail(P, file, line, "%s: vertex index %.0f out of range [0, %d)", what, Id[i], nv);
        }
        idx[i] = (int32_t)Id[i];
    }
    ok = loop_subdivide(Pd, nv, idx, ni / 3, levels, &m, &e);
    free(idx);
    if (!ok) return fail(P, file, line, "%s: %s", what, e.msg);
    ok = add_mesh(P, m.P, m.N, NULL, m.n_verts, m.idx, m.n_tris, file, line);
    subdiv_free(&m);
    return ok;
}

/* pbrt-v4's "alpha" of every shape: "texture alpha" (a float texture) or "float
   alpha" (1); on an AreaLightSource shape NEE reads the texture at the points it
   samples (lights.c emitter_alpha_at).  A "constant" float texture is its value:
   pbrt-v4 tells a constant alpha of 0 apart whichever way it was written (shape,
   below).  Sets P->shape_alpha(_tex). */
static int shape_alpha(Parser *P, ParamList *pl)
{
    Param *pt = param_find(pl, PT_TEXTURE, "alpha");
    P->shape_alpha = 1.0f;
    P->shape_alpha_tex = 0;
    if (pt) {
        int k = texture_lookup(P, pt, 1);
        const Texture *t;
        if (k < 0) return 0;
        t = &P->s->textures[k];
        if (t->type == TEX_CONSTANT && t->arg_tex[0] < 0) P->shape_alpha = t->arg_f[0];
        else P->shape_alpha_tex = k + 1;
        return 1;
    }
    return get_float(P, pl, "alpha", 1.0f, &P->shape_alpha);
}

/* A shape pbrt-v4 can never hit (a constant alpha <= 0) that sends no light (not an
   area light, or alpha < 0, which DiffuseAreaLight's mask turns off) is read,
   checked, and then dropped with everything it appended, as if the file did not
   have it.  An area light of alpha exactly 0 stays (shape, below). */
static int shape_drop(Parser *P, const Scene *before)
{
    Scene *s = P->s;
    s->n_verts = before->n_verts;
    s->n_tris = before->n_tris;
    s->n_shapes = before->n_shapes;
    s->n_emitters = before->n_emitters;
    s->n_spheres = before->n_spheres;
    s->n_quadrics = before->n_quadrics;
    s->n_patches = before->n_patches;
    s->n_curves = before->n_curves;
    s->n_curve_pieces = before->n_curve_pieces;
    s->n_alpha = before->n_alpha;
    return 1;
}

static int shape_build(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    if (!strcmp(type, "trianglemesh")) return mesh_shape(P, 0, pl, file, line);
    if (!strcmp(type, "bilinearmesh")) return mesh_shape(P, 1, pl, file, line);
    if (!strcmp(type, "sphere")) return sphere_shape(P, pl, file, line);
    if (!strcmp(type, "disk")) return disk_shape(P, pl, file, line);
    if (!strcmp(type, "cylinder")) return cylinder_shape(P, pl, file, line);
    if (!strcmp(type, "plymesh")) return ply_shape(P, pl, file, line);
    if (!strcmp(type, "loopsubdiv")) return loopsubdiv_shape(P, pl, file, line);
    if (!strcmp(type, "curve")) {            /* the Shape, then curve.c's segments */
        int sh = add_shape(P, SHAPE_CURVE, 0, 0, 0.0, 0, file, line);
        return sh >= 0 && curve_shape(P, pl, sh, file, line);
    }
    return fail(P, file, line, "Shape \"%s\": unknown shape type", type);
}

/* A Shape under two different CTMs (motion.c): an unnamed object of its own, which
   the shape about to be made goes into (P->cur_object), and the moving instance
   that places it; the caller makes the shape under the identity CTM, as pbrt-v4
   makes an animated shape in its own space.  type: the shape's, for messages. */
static int moving_shape_object(Parser *P, const char *type, const char *file, int line)
{
    Scene *s = P->s;
    Object *o;
    if (P->cur_object > 0)
        return fail(P, file, line, "Shape \"%s\" inside ObjectBegin \"%s\" moves "
                    "(ActiveTransform): a moving shape inside an object definition is not "
                    "supported", type, s->objects[P->cur_object - 1].name);
    if (P->gs.area_light >= 0)
        return fail(P, file, line, "Shape \"%s\" under an AreaLightSource moves "
                    "(ActiveTransform): animated area lights are not supported (pbrt-v4 stops "
                    "there too)", type);
    if (!grow((void **)&s->objects, &P->cap_objects, s->n_objects + 1, sizeof(Object)))
        return oom(P, file, line);
    o = &s->objects[s->n_objects];
    memset(o, 0, sizeof *o);
    o->unnamed = 1;
    o->name = "";
    o->file = file;
    o->line = line;
    if (!add_instance(P, type, type, s->n_objects, file, line)) return 0;
    P->cur_object = ++s->n_objects;
    return 1;
}

/* A shape that moves (its two CTMs differ, motion.c): made in its own space, as
   pbrt-v4 does, inside an unnamed object that a moving instance places. */
static int moving_shape(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    const Xform start = P->gs.ctm;
    int ok;
    if (!moving_shape_object(P, type, file, line)) return 0;
    P->gs.ctm = xf_identity();
    ok = shape_build(P, type, pl, file, line);
    P->gs.ctm = start;
    P->cur_object = 0;
    return ok;
}

/* Shape: its "alpha" first (every type reads it), then the shape itself. */
int shape_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    Scene before = *P->s;
    int ok;
    if (!shape_alpha(P, pl)) return 0;
    if (xf_differ(&P->gs.ctm, &P->gs.ctm_end)) ok = moving_shape(P, type, pl, file, line);
    else ok = shape_build(P, type, pl, file, line);
    /* pbrt-v4's invisible area light: a constant alpha of exactly 0 on an area light
       makes the shape unhittable (the BVH's alpha test never keeps a hit of alpha 0)
       while the light emits in full and is found by NEE alone (lights.c
       emitter_invisible; path.c gives NEE the whole MIS weight there). */
    if (ok && P->shape_alpha_tex == 0 && P->shape_alpha <= 0.0f &&
        !(P->shape_alpha == 0.0f && P->s->n_emitters > before.n_emitters))
        return shape_drop(P, &before);
    return ok;
}
