/* scene.c - the scene builder: a strict subset of the pbrt-v4 scene format.

   Implements (specnee.h section 8): scene_load, scene_load_as, scene_load_string,
   scene_free, scene_dump.  The tokens, parameter lists and their typed getters
   and the file:line errors are parser.c's (parser.h); this file runs the
   directive loop over them, keeps pbrt's graphics state and assembles the Scene.

   WHAT IT READS
     A pbrt-v4 file is a stream of whitespace-separated tokens: words, quoted
     strings, '[' ']' and '#' comments.  A statement is
         Directive "type" "ptype pname" value(s) "ptype pname" value(s) ...
     where a value list is either one token or '[' tokens ']'.  The file has two
     blocks: the options block (camera, film, sampler, integrator, transforms)
     and, after WorldBegin, the world block (materials, lights, shapes).
     Sources: pbrt-v4's file-format documentation and its parser (parser.cpp),
     scene builder (scene.cpp) and parameter dictionary (paramdict.cpp).

     The subset and its defaults are listed in docs/conventions.md.  Everything
     a pbrt-v4 file may say that specnee does not support is an error that says
     so ("... is valid pbrt-v4 but not in the specnee subset"), and, like
     pbrt-v4, a parameter nobody reads is an error ("unused parameter"), so a
     typo never silently changes the picture.

   TRANSFORMS (pbrt-v4 semantics; points are column vectors, p' = M p)
     The current transformation matrix (CTM) is post-multiplied by each
     transform directive:   CTM <- CTM * T   (so the last directive acts first
     on the object).  `Transform m0..m15` replaces the CTM and
     `ConcatTransform m0..m15` post-multiplies it; pbrt-v4 reads the 16 numbers
     as the transpose of a row-major matrix, i.e. column by column:
         M[i][j] = m[4 j + i]      (the translation is m12 m13 m14).
     LookAt builds pbrt's left-handed camera frame (right = up x dir, see
     util.c).  At `Camera` the CTM becomes camera_from_world; `WorldBegin`
     resets the CTM to the identity.

   SHAPES AND ORIENTATION
     Vertices go to world space by the CTM, normals by its inverse transpose.
     A shape's orientation flag is
         flip = ReverseOrientation XOR swaps_handedness(CTM)
     (pbrt-v4 TriangleMesh/BilinearPatchMesh): the geometric normal
     n = normalize((p1 - p0) x (p2 - p0)) of a world-space triangle is negated
     when flip is set, which makes one-sided emitters face the side that the
     object-space winding (mapped by the normal transform) gives them.  Vertex
     normals N are negated by ReverseOrientation only, as in pbrt-v4.
     Bilinear patches (p00 p10 p01 p11) become two triangles (p00,p10,p11) and
     (p00,p11,p01): exact for planar patches, an approximation otherwise.

   EMISSION (pbrt-v4 DiffuseAreaLight::Create)
     Le(lambda) = scale * L(lambda) / sum_lambda ybar(lambda) L(lambda), so a
     light seen directly has luminance Y = scale; lights.c's emitter_radiance
     does the division (per render), its area_light_from_params records L, scale
     and twosided.  For "rgb L" pbrt-v4 divides by the colour space's illuminant
     (D65) instead of by L; we emulate that by multiplying scale by
     sum ybar L / sum ybar D65 (rgb_illuminant_scale, parser.c).

   ERRORS
     Every problem gives one line "file:line: problem" in the Error and a 0
     return; scene_load frees everything it allocated.  Nothing exits, and
     every loop advances through a finite buffer, so bad input cannot hang; the
     Include budget (MAX_INCLUDES directives, READ_MAX_BYTES of text) bounds the
     work of files that include each other repeatedly.  Messages never carry raw
     bytes of the input (error_set escapes them).

   USE
     Scene s; Error err;
     if (!scene_load(&s, "scenes/cornell.pbrt", &err)) { puts(err.msg); ... }
     ... render ...
     scene_free(&s);                                                        */
#include "parser.h"
#include <ctype.h>
#include <float.h>
#include <limits.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ===========================================================================
   1. Growing the Scene
   =========================================================================== */
static int add_material(Parser *P, const Material *m, const char *file, int line)
{
    Scene *s = P->s;
    if (!grow((void **)&s->materials, &P->cap_mats, s->n_materials + 1, sizeof(Material))) {
        oom(P, file, line);
        return -1;
    }
    s->materials[s->n_materials] = *m;
    return s->n_materials++;
}

/* pbrt-v4's default material: diffuse with reflectance 0.5. */
static int default_material(Parser *P, const char *file, int line)
{
    if (P->default_material < 0) {
        Material m;
        memset(&m, 0, sizeof m);
        m.type = MAT_DIFFUSE;
        spec_const(&m.reflectance, 0.5f);
        spec_const(&m.eta, 1.0f);
        P->default_material = add_material(P, &m, file, line);
    }
    return P->default_material;
}

/* Append a Shape record for the current graphics state, and its Emitter when an
   AreaLightSource is active.  Returns the shape index or -1. */
static int add_shape(Parser *P, ShapeType type, int tri_begin, int tri_count, double area,
                     int has_normals, const char *file, int line)
{
    Scene *s = P->s;
    Shape *sh;
    int mat = P->gs.material != -1 ? P->gs.material : default_material(P, file, line);
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
        em->twosided = al->twosided;
        sh->emitter = s->n_emitters++;
    }
    return s->n_shapes++;
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
    }
    return 1;
}

/* ===========================================================================
   2. Directives of the options block
   =========================================================================== */
/* The camera transform must give the renderer finite numbers, as mesh vertices
   must: the eye and the world-space directions through the image's corners and
   centre, in float, with a length that neither overflows nor underflows when
   squared (render.c normalises them).  A transform such as `Scale 1e-30 ...`
   before Camera is invertible in double precision but fails here. */
static int camera_transform_ok(const Xform *camera_from_world, float fov_deg, int xres, int yres)
{
    Xform wfc;
    double t = tan(fov_deg * 0.5 * SPECNEE_PI / 180.0);
    double ax = xres >= yres ? (double)xres / yres : 1.0, ay = xres >= yres ? 1.0 : (double)yres / xres;
    Vec3 eye;
    int i;
    memcpy(wfc.m, camera_from_world->inv, sizeof wfc.m);     /* world_from_camera */
    memcpy(wfc.inv, camera_from_world->m, sizeof wfc.inv);
    eye = xf_point(&wfc, v3(0, 0, 0));
    if (!(fabsf(eye.x) <= FLT_MAX && fabsf(eye.y) <= FLT_MAX && fabsf(eye.z) <= FLT_MAX))
        return 0;
    for (i = 0; i < 5; i++) {
        double sx = i == 4 ? 0.0 : (i & 1 ? ax : -ax), sy = i == 4 ? 0.0 : (i & 2 ? ay : -ay);
        Vec3 d = xf_vector(&wfc, v3((float)(sx * t), (float)(sy * t), 1.0f));
        float l2 = v3_dot(d, d);
        if (!(l2 >= FLT_MIN && l2 <= FLT_MAX)) return 0;
    }
    return 1;
}

static int camera_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    float fov, lens, focus, open, close;
    if (strcmp(type, "perspective") != 0) {
        if (!strcmp(type, "orthographic") || !strcmp(type, "realistic") || !strcmp(type, "spherical"))
            return fail(P, file, line, "Camera \"%s\" is valid pbrt-v4 but not in the specnee "
                        "subset (use \"perspective\")", type);
        return fail(P, file, line, "Camera \"%s\": unknown camera type", type);
    }
    if (!get_float(P, pl, "fov", 90.0f, &fov)) return 0;
    if (!get_float(P, pl, "lensradius", 0.0f, &lens)) return 0;
    if (!get_float(P, pl, "focaldistance", 1e6f, &focus)) return 0;
    if (!get_float(P, pl, "shutteropen", 0.0f, &open)) return 0;
    if (!get_float(P, pl, "shutterclose", 1.0f, &close)) return 0;
    if (!params_check_unused(P, pl, "Camera \"perspective\"",
                             "float fov, float lensradius, float focaldistance, "
                             "float shutteropen, float shutterclose",
                             "frameaspectratio screenwindow"))
        return 0;
    if (!(fov > 0.0f && fov < 180.0f))
        return fail_param(P, pl, "fov", file, line, "Camera: \"float fov\" %g must be within (0, 180) degrees", fov);
    /* the film may come later: checked with the largest aspect ratio allowed here
       and again with the film's own in finish() */
    if (!camera_transform_ok(&P->gs.ctm, fov, 1, 1))
        return fail(P, file, line, "Camera: degenerate camera transform: the eye or the "
                    "viewing directions are not finite, non-zero float vectors (look at "
                    "the Scale/Transform/LookAt before Camera)");
    if (!(lens >= 0.0f) || !(focus > 0.0f))
        return fail_param(P, pl, lens < 0.0f ? "lensradius" : "focaldistance", file, line, "Camera: \"float lensradius\" %g must be >= 0 and "
                    "\"float focaldistance\" %g > 0", lens, focus);
    /* pbrt-v4 (scene.cpp): the exposure time is the shutter interval; the scene is
       static, so it only scales the image (the imaging ratio, Film "iso") */
    if (!(close - open > 0.0f))
        return fail_param(P, pl, "shutterclose", file, line, "Camera: shutterclose %g <= shutteropen %g: the shutter "
                    "never opens", close, open);
    st->fov_deg = fov;
    st->lens_radius = lens;
    st->focal_distance = focus;
    P->exposure_time = close - open;
    st->camera_from_world = P->gs.ctm;
    st->camera_medium = P->gs.medium_outside;   /* pbrt-v4: the current outside medium */
    P->camera_file = file;
    P->camera_line = line;
    {   /* the named coordinate system "camera" is world_from_camera (pbrt-v4) */
        int i;
        for (i = 0; i < P->n_coords; i++)
            if (!strcmp(P->coords[i].name, "camera")) break;
        if (i == P->n_coords) {
            if (!grow((void **)&P->coords, &P->cap_coords, P->n_coords + 1, sizeof(NamedCoordSys)))
                return oom(P, file, line);
            snprintf(P->coords[i].name, sizeof P->coords[i].name, "camera");
            P->n_coords++;
        }
        memcpy(P->coords[i].xf.m, P->gs.ctm.inv, sizeof P->gs.ctm.inv);
        memcpy(P->coords[i].xf.inv, P->gs.ctm.m, sizeof P->gs.ctm.m);
    }
    return 1;
}

/* The chromaticity of the white of pbrt-v4's Film "whitebalance" temperature T:
   pbrt-v4 (Spectra::D) first turns T into a CCT with today's second radiation
   constant, T * 1.4388 / 1.4380, then takes the CIE daylight locus (CIE 015:2004,
   eq. 3.3 and 3.4: x_D as a cubic in 1/T, valid 4000..25000 K, and
   y_D = -3 x_D^2 + 2.870 x_D - 0.275) at 4000 K and above, and a Planckian
   (blackbody) radiator below.  pbrt-v4 rebuilds the daylight spectrum from the
   S0, S1, S2 basis and integrates it; the locus gives its chromaticity directly
   (the two agree to about 1e-4 in x and y). */
static void white_balance_xy(double kelvin, double *x, double *y)
{
    double cct = kelvin * 1.4388 / 1.4380, t = 1.0 / cct;
    if (cct < 4000.0) {
        Spectrum bb;
        spec_blackbody(&bb, (float)cct);
        spec_chromaticity(&bb, x, y);
        return;
    }
    if (cct <= 7000.0)
        *x = -4.6070e9 * t * t * t + 2.9678e6 * t * t + 0.09911e3 * t + 0.244063;
    else
        *x = -2.0064e9 * t * t * t + 1.9018e6 * t * t + 0.24748e3 * t + 0.237040;
    *y = -3.000 * *x * *x + 2.870 * *x - 0.275;
}

static void mat3_mul(const double a[9], const double b[9], double out[9])
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            out[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

/* von Kries adaptation in the Bradford cone space (K. M. Lam, "Metamerism and
   colour constancy", PhD thesis, University of Bradford, 1985; the matrix as
   published by CIE 159:2004 and in pbrt-v4's WhiteBalance): XYZ -> LMS, each cone
   signal scaled by target white / source white, LMS -> XYZ (the inverse is
   computed here, not tabulated).  The source white is the temperature's
   (white_balance_xy), the target sRGB's own white: the xy of specnee's D65, as
   pbrt-v4 takes its colour space's white from its illuminant spectrum. */
static void white_balance_matrix(double kelvin, double m[9])
{
    static const double lms[9] = {  0.8951,  0.2664, -0.1614,
                                   -0.7502,  1.7135,  0.0367,
                                    0.0389, -0.0685,  1.0296 };
    double inv[9], det, src[3], dst[3], sx, sy, tx, ty, d[9], tmp[9];
    Spectrum d65;
    int i;
    white_balance_xy(kelvin, &sx, &sy);
    spec_named(&d65, "stdillum-D65");
    spec_chromaticity(&d65, &tx, &ty);
    /* inverse of lms by cofactors */
    det = lms[0] * (lms[4] * lms[8] - lms[5] * lms[7]) - lms[1] * (lms[3] * lms[8] - lms[5] * lms[6])
        + lms[2] * (lms[3] * lms[7] - lms[4] * lms[6]);
    inv[0] = (lms[4] * lms[8] - lms[5] * lms[7]) / det;
    inv[1] = (lms[2] * lms[7] - lms[1] * lms[8]) / det;
    inv[2] = (lms[1] * lms[5] - lms[2] * lms[4]) / det;
    inv[3] = (lms[5] * lms[6] - lms[3] * lms[8]) / det;
    inv[4] = (lms[0] * lms[8] - lms[2] * lms[6]) / det;
    inv[5] = (lms[2] * lms[3] - lms[0] * lms[5]) / det;
    inv[6] = (lms[3] * lms[7] - lms[4] * lms[6]) / det;
    inv[7] = (lms[1] * lms[6] - lms[0] * lms[7]) / det;
    inv[8] = (lms[0] * lms[4] - lms[1] * lms[3]) / det;
    for (i = 0; i < 3; i++) {   /* LMS of the whites at Y = 1: XYZ = (x/y, 1, (1-x-y)/y) */
        src[i] = lms[3 * i] * (sx / sy) + lms[3 * i + 1] + lms[3 * i + 2] * ((1.0 - sx - sy) / sy);
        dst[i] = lms[3 * i] * (tx / ty) + lms[3 * i + 1] + lms[3 * i + 2] * ((1.0 - tx - ty) / ty);
    }
    memset(d, 0, sizeof d);
    for (i = 0; i < 3; i++) d[4 * i] = dst[i] / src[i];
    mat3_mul(d, lms, tmp);
    mat3_mul(inv, tmp, m);
}

int film_bounds(const SceneSettings *st, int b[4])
{
    b[0] = 0; b[1] = st->xres; b[2] = 0; b[3] = st->yres;
    if (st->crop_set) {
        /* pbrt-v4: ceil(resolution * fraction), the product in float (20 * 0.1f
           rounds to 2 in float, to 2.0000000298 in double) */
        float v[4];
        int a;
        v[0] = (float)st->xres * st->crop[0];
        v[1] = (float)st->xres * st->crop[1];
        v[2] = (float)st->yres * st->crop[2];
        v[3] = (float)st->yres * st->crop[3];
        for (a = 0; a < 4; a++) b[a] = (int)ceilf(v[a]);
    } else if (st->pixel_bounds_set) {   /* clipped to the film */
        b[0] = st->pixel_bounds[0] > 0 ? st->pixel_bounds[0] : 0;
        b[1] = st->pixel_bounds[1] < st->xres ? st->pixel_bounds[1] : st->xres;
        b[2] = st->pixel_bounds[2] > 0 ? st->pixel_bounds[2] : 0;
        b[3] = st->pixel_bounds[3] < st->yres ? st->pixel_bounds[3] : st->yres;
    }
    return b[1] > b[0] && b[3] > b[2];
}

int scene_insets_rendered(const Scene *s, int rect[8][4], const char *names[8])
{
    int b[4], i, n = 0;
    if (!film_bounds(&s->settings, b)) return 0;
    for (i = 0; i < s->n_insets; i++) {
        int x0 = s->inset[i][0] > b[0] ? s->inset[i][0] : b[0];
        int y0 = s->inset[i][1] > b[2] ? s->inset[i][1] : b[2];
        int x1 = s->inset[i][2] < b[1] ? s->inset[i][2] : b[1];
        int y1 = s->inset[i][3] < b[3] ? s->inset[i][3] : b[3];
        if (x1 <= x0 || y1 <= y0) continue;          /* outside the rendered part */
        rect[n][0] = x0 - b[0]; rect[n][1] = y0 - b[2];
        rect[n][2] = x1 - b[0]; rect[n][3] = y1 - b[2];
        names[n] = s->inset_name[i];
        n++;
    }
    return n;
}

/* The named camera sensors of pbrt-v4 (their r, g, b curves are its named
   spectra "<name>_r/_g/_b"), which specnee does not have. */
static int pbrt_sensor_name(const char *n)
{
    static const char *const names[] = {
        "canon_eos_100d", "canon_eos_1dx_mkii", "canon_eos_200d", "canon_eos_200d_mkii",
        "canon_eos_5d", "canon_eos_5d_mkii", "canon_eos_5d_mkiii", "canon_eos_5d_mkiv",
        "canon_eos_5ds", "canon_eos_m", "hasselblad_l1d_20c", "nikon_d810", "nikon_d850",
        "sony_ilce_6400", "sony_ilce_7m3", "sony_ilce_7rm3", "sony_ilce_9", NULL
    };
    int i;
    for (i = 0; names[i]; i++)
        if (!strcmp(n, names[i])) return 1;
    return 0;
}

static int film_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    int xres, yres, fp16;
    const char *fn;
    int gbuffer = !strcmp(type, "gbuffer");
    float iso, maxcomp, scale, wb;
    const char *coordsys = NULL, *sensor;
    Param *crop, *pb;
    if (strcmp(type, "rgb") != 0 && !gbuffer) {
        if (!strcmp(type, "spectral"))
            return fail(P, file, line, "Film \"%s\" is valid pbrt-v4 but not in the specnee "
                        "subset (use \"rgb\")", type);
        return fail(P, file, line, "Film \"%s\": unknown film type", type);
    }
    if (!get_int(P, pl, "xresolution", 1280, &xres, NULL)) return 0;
    if (!get_int(P, pl, "yresolution", 720, &yres, NULL)) return 0;
    if (!get_string(P, pl, "filename", &fn)) return 0;
    if (!get_bool(P, pl, "savefp16", 1, &fp16)) return 0;    /* PFM is float32 anyway */
    if (!get_float(P, pl, "iso", 100.0f, &iso)) return 0;
    if (!get_float(P, pl, "maxcomponentvalue", INFINITY, &maxcomp)) return 0;
    if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
    if (!get_float(P, pl, "whitebalance", 0.0f, &wb)) return 0;
    if (!get_string(P, pl, "sensor", &sensor)) return 0;
    crop = param_find(pl, PT_FLOAT, "cropwindow");
    pb = param_find(pl, PT_INTEGER, "pixelbounds");
    if (gbuffer && !get_string(P, pl, "coordinatesystem", &coordsys)) return 0;
    if (!params_check_unused(P, pl, gbuffer ? "Film \"gbuffer\"" : "Film \"rgb\"",
                             gbuffer ? "integer xresolution, integer yresolution, string filename, "
                                       "bool savefp16, float iso, float maxcomponentvalue, "
                                       "float whitebalance, string sensor, float cropwindow, "
                                       "integer pixelbounds, float scale, "
                                       "string coordinatesystem"
                                     : "integer xresolution, integer yresolution, string filename, "
                                       "bool savefp16, float iso, float maxcomponentvalue, "
                                       "float whitebalance, string sensor, float cropwindow, "
                                       "integer pixelbounds, float scale",
                             "exposuretime diagonal writefp16"))
        return 0;
    /* pbrt-v4's sensor "cie1931" (the default) records XYZ, which is what specnee
       does; its named camera sensors need their measured r, g, b curves */
    if (sensor && strcmp(sensor, "cie1931") != 0) {
        if (pbrt_sensor_name(sensor))
            return fail(P, file, line, "Film: \"string sensor\" \"%s\" is valid pbrt-v4 but "
                        "not in the specnee subset (only \"cie1931\", the CIE 1931 observer; "
                        "specnee has no camera sensitivity curves)", sensor);
        return fail(P, file, line, "Film: \"string sensor\" \"%s\": unknown sensor type "
                    "(pbrt-v4 knows \"cie1931\" and 17 named cameras)", sensor);
    }
    if (!(wb == 0.0f || (wb >= 1000.0f && wb <= 100000.0f)))
        return fail_param(P, pl, "whitebalance", file, line, "Film: \"float whitebalance\" %g: a colour temperature "
                    "within 1000..100000 K, or 0 for none", wb);
    if (!(scale > 0.0f))
        return fail_param(P, pl, "scale", file, line, "Film: \"float scale\" %g must be > 0", scale);
    if (crop && crop->n_num != 4)
        return fail(P, crop->file, crop->line, "Film: \"float cropwindow\": %d values, "
                    "expected 4 (x0 x1 y0 y1, fractions of the film)", crop->n_num);
    if (pb && pb->n_num != 4)
        return fail(P, pb->file, pb->line, "Film: \"integer pixelbounds\": %d values, "
                    "expected 4 (x0 x1 y0 y1, pixels)", pb->n_num);
    if (xres < 1 || xres > MAX_RESOLUTION || yres < 1 || yres > MAX_RESOLUTION)
        return fail(P, file, line, "Film: resolution %d x %d outside 1..%d per axis",
                    xres, yres, MAX_RESOLUTION);
    {   /* what the render's buffers would take, against the stated budget */
        double need = (double)xres * yres * FILM_BYTES_PER_PIXEL;
        if (need > (double)MEM_BUDGET_MIB * 1048576.0)
            return fail(P, file, line, "Film: %d x %d pixels would need %.1f GiB for the "
                        "render's buffers, more than specnee's memory budget of %.0f GiB "
                        "(MEM_BUDGET_MIB in specnee.h)", xres, yres, need / 1073741824.0,
                        MEM_BUDGET_MIB / 1024.0);
    }
    if (!(iso > 0.0f) || !(maxcomp > 0.0f))
        return fail(P, file, line, "Film: \"float iso\" %g and \"float maxcomponentvalue\" %g "
                    "must be > 0", iso, maxcomp);
    if (gbuffer)
        fprintf(stderr, "%s:%d: note: Film \"gbuffer\" is read as \"rgb\": specnee writes "
                "the colour image only, without the geometry channels\n", file, line);
    P->iso = iso;
    if (scale != 1.0f) {
        /* pbrt-v3's film scale: current pbrt-v4 refuses it as unused, and its
           --upgrade rewrites it as "float iso" 100 * scale; specnee reads it so */
        fprintf(stderr, "%s:%d: note: Film \"float scale\" %g is pbrt-v3 syntax (pbrt-v4 "
                "reads \"float iso\" %g instead, as its --upgrade writes): the image is "
                "scaled by %g\n", file, line, scale, 100.0 * scale, scale);
        P->iso = iso * scale;
    }
    st->max_component = maxcomp;
    st->xres = xres;
    st->yres = yres;
    st->white_balance = wb;
    if (wb > 0.0f) white_balance_matrix(wb, st->white_balance_m);
    st->crop_set = crop != NULL;
    st->pixel_bounds_set = pb != NULL && !crop;   /* pbrt-v4: the crop window wins */
    if (crop) {
        /* pbrt-v4: each pair sorted, clamped to [0, 1] */
        int a;
        for (a = 0; a < 2; a++) {
            double lo = crop->num[2 * a] < crop->num[2 * a + 1] ? crop->num[2 * a] : crop->num[2 * a + 1];
            double hi = crop->num[2 * a] < crop->num[2 * a + 1] ? crop->num[2 * a + 1] : crop->num[2 * a];
            st->crop[2 * a] = (float)(lo < 0.0 ? 0.0 : lo > 1.0 ? 1.0 : lo);
            st->crop[2 * a + 1] = (float)(hi < 0.0 ? 0.0 : hi > 1.0 ? 1.0 : hi);
        }
    }
    if (pb) {
        int a;
        for (a = 0; a < 4; a++) st->pixel_bounds[a] = (int)pb->num[a];
    }
    {
        int b[4];
        if (!film_bounds(st, b))
            return fail(P, file, line, "Film: the %s selects no pixel of the %d x %d film "
                        "(x %d..%d, y %d..%d)", crop ? "cropwindow" : "pixelbounds",
                        xres, yres, b[0], b[1], b[2], b[3]);
    }
    if (P->output) {
        /* pbrt-v4 (FilmBaseParameters): a file named on the command line wins over
           the scene's; the scene's name is then never used, so it is not checked
           (placeholders such as "__OUTPUT_PNG__" are common in shared scenes).
           pbrt-v4 warns whenever the scene names a file; specnee notes it only
           where the name is not one it writes as given (a placeholder, .exr, another
           format), so the shipped scenes' usual `-o` renders stay quiet */
        if (fn && !ends_with_ci(fn, ".pfm") && !ends_with_ci(fn, ".ppm") && !ends_with_ci(fn, ".png"))
            fprintf(stderr, "%s:%d: note: the output file \"%s\" of the command line "
                    "overrides Film \"string filename\" \"%s\" (as pbrt-v4 --outfile does)\n",
                    file, line, P->output, fn);
        snprintf(st->filename, sizeof st->filename, "%s", P->output);
        return 1;
    }
    if (!fn) fn = "pbrt.exr";                         /* pbrt-v4's default */
    if (strlen(fn) + 1 > sizeof st->filename)
        return fail(P, file, line, "Film: filename longer than %d characters",
                    (int)sizeof st->filename - 1);
    if (ends_with_ci(fn, ".exr")) {
        /* specnee has no EXR writer: the same name with .pfm (float32 too) */
        size_t n = strlen(fn);
        snprintf(st->filename, sizeof st->filename, "%.*s.pfm", (int)(n - 4), fn);
        fprintf(stderr, "%s:%d: note: specnee writes no EXR; \"%s\" becomes \"%s\"\n",
                file, line, fn, st->filename);
    } else if (ends_with_ci(fn, ".pfm") || ends_with_ci(fn, ".ppm") || ends_with_ci(fn, ".png")) {
        snprintf(st->filename, sizeof st->filename, "%s", fn);
    } else {
        return fail(P, file, line, "Film: \"string filename\" \"%s\": specnee writes .pfm, "
                    ".ppm or .png (.exr becomes .pfm)", fn);
    }
    return 1;
}

/* PixelFilter: pbrt-v4's five filters with its parameter names and defaults
   (filters.cpp; their formulas and how samples are drawn: filter.c). */
static int filter_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const struct { const char *name; FilterType t; float radius; const char *reads; }
    kinds[] = {
        { "box", FILTER_BOX, 0.5f, "float xradius, float yradius" },
        { "gaussian", FILTER_GAUSSIAN, 1.5f, "float xradius, float yradius, float sigma" },
        { "triangle", FILTER_TRIANGLE, 2.0f, "float xradius, float yradius" },
        { "mitchell", FILTER_MITCHELL, 2.0f, "float xradius, float yradius, float B, float C" },
        { "sinc", FILTER_SINC, 4.0f, "float xradius, float yradius, float tau" },
    };
    SceneSettings *st = &P->s->settings;
    float xr, yr, sigma = 0.5f, B = 1.0f / 3.0f, C = 1.0f / 3.0f, tau = 3.0f;
    char what[160];
    int k;
    for (k = 0; k < 5 && strcmp(type, kinds[k].name) != 0; k++) {}
    if (k == 5)
        return fail(P, file, line, "PixelFilter \"%s\": unknown filter type (pbrt-v4 knows "
                    "box, gaussian, mitchell, sinc, triangle)", type);
    /* pbrt-v4 names the radii xradius/yradius */
    if (!get_float(P, pl, "xradius", kinds[k].radius, &xr)) return 0;
    if (!get_float(P, pl, "yradius", kinds[k].radius, &yr)) return 0;
    if (kinds[k].t == FILTER_GAUSSIAN && !get_float(P, pl, "sigma", 0.5f, &sigma)) return 0;
    if (kinds[k].t == FILTER_MITCHELL && (!get_float(P, pl, "B", B, &B) || !get_float(P, pl, "C", C, &C)))
        return 0;
    if (kinds[k].t == FILTER_SINC && !get_float(P, pl, "tau", 3.0f, &tau)) return 0;
    snprintf(what, sizeof what, "PixelFilter \"%s\"", type);
    if (!params_check_unused(P, pl, what, kinds[k].reads, NULL)) return 0;
    if (xr != yr)
        return fail(P, file, line, "PixelFilter: xradius %g != yradius %g is valid pbrt-v4 "
                    "but not in the specnee subset", xr, yr);
    if (!(xr > 0.0f && xr <= 16.0f) || !(sigma > 0.0f && sigma <= 16.0f))
        return fail(P, file, line, "PixelFilter: radius and sigma must be within (0, 16]");
    if (!(tau > 0.0f))
        return fail_param(P, pl, "tau", file, line, "PixelFilter \"sinc\": \"float tau\" %g must be > 0", tau);
    st->filter = kinds[k].t;
    st->filter_radius = xr;
    st->filter_sigma = sigma;
    st->filter_b = B;
    st->filter_c = C;
    st->filter_tau = tau;
    return 1;
}

/* Accelerator: pbrt-v4's choice of ray-intersection structure ("bvh" with
   splitmethod/maxnodeprims, or "kdtree").  It changes how fast rays are traced,
   never what they hit, so the image does not depend on it: specnee reads the
   parameters pbrt-v4 reads (an unknown one is an error, as there), ignores them
   and says so; its own BVH (bvh.c) is always built. */
static int accelerator_directive(Parser *P, const char *type, ParamList *pl, const char *file,
                                 int line)
{
    const char *split;
    int n;
    float f;
    if (!strcmp(type, "bvh")) {
        if (!get_string(P, pl, "splitmethod", &split)) return 0;
        if (!get_int(P, pl, "maxnodeprims", 4, &n, NULL)) return 0;
        if (!params_check_unused(P, pl, "Accelerator \"bvh\"",
                                 "string splitmethod, integer maxnodeprims", NULL))
            return 0;
    } else if (!strcmp(type, "kdtree")) {
        if (!get_int(P, pl, "intersectcost", 5, &n, NULL)) return 0;
        if (!get_int(P, pl, "traversalcost", 1, &n, NULL)) return 0;
        if (!get_float(P, pl, "emptybonus", 0.5f, &f)) return 0;
        if (!get_int(P, pl, "maxprims", 1, &n, NULL)) return 0;
        if (!get_int(P, pl, "maxdepth", -1, &n, NULL)) return 0;
        if (!params_check_unused(P, pl, "Accelerator \"kdtree\"",
                                 "integer intersectcost, integer traversalcost, float emptybonus, "
                                 "integer maxprims, integer maxdepth", NULL))
            return 0;
    } else {
        return fail(P, file, line, "Accelerator \"%s\": unknown accelerator type (pbrt-v4 "
                    "knows \"bvh\" and \"kdtree\")", type);
    }
    fprintf(stderr, "%s:%d: note: Accelerator \"%s\" is read and ignored: specnee always "
            "builds its own BVH, and the accelerator does not change the image\n", file, line, type);
    return 1;
}

static int sampler_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const char *const known[] = {
        "halton", "independent", "paddedsobol", "pmj02bn", "sobol", "stratified", "zsobol", NULL
    };
    SceneSettings *st = &P->s->settings;
    int i, spp, seed, given = 0, seed_given = 0, jitter = 1, xs = 0, ys = 0;
    const char *rnd;
    char what[48];
    for (i = 0; known[i]; i++)
        if (!strcmp(type, known[i])) break;
    if (!known[i]) return fail(P, file, line, "Sampler \"%s\": unknown sampler type", type);
    if (!strcmp(type, "stratified")) {
        /* pbrt-v4: xsamples * ysamples (4 x 4 by default), no pixelsamples */
        int gx, gy;
        if (!get_int(P, pl, "xsamples", 4, &xs, &gx)) return 0;
        if (!get_int(P, pl, "ysamples", 4, &ys, &gy)) return 0;
        if (!get_bool(P, pl, "jitter", 1, &jitter)) return 0;
        if (xs < 1 || ys < 1 || xs > 4096 || ys > 4096)
            return fail(P, file, line, "Sampler \"stratified\": xsamples/ysamples must be "
                        "within 1..4096");
        spp = xs * ys;
        given = gx || gy;
    } else {
        /* pbrt-v4 defaults: 4 for independent, 16 for the others */
        if (!get_int(P, pl, "pixelsamples", strcmp(type, "independent") ? 16 : 4, &spp, &given))
            return 0;
        /* pbrt-v4 reads "string randomization" for halton, paddedsobol, sobol and
           zsobol only (samplers.cpp, each Create) */
        if (strcmp(type, "independent") != 0 && strcmp(type, "pmj02bn") != 0 &&
            !get_string(P, pl, "randomization", &rnd))
            return 0;
    }
    if (!get_int(P, pl, "seed", 0, &seed, &seed_given)) return 0;
    /* specnee reads every parameter pbrt-v4's sampler of this type reads
       (samplers.cpp): any other is an unused parameter there too, e.g. "integer
       pixelsamples" of "stratified", which pbrt-v4 takes from --spp only */
    snprintf(what, sizeof what, "Sampler \"%s\"", type);
    if (!params_check_unused(P, pl, what,
                             !strcmp(type, "stratified") ? "integer xsamples, integer ysamples, bool jitter, integer seed"
                             : !strcmp(type, "independent") || !strcmp(type, "pmj02bn") ? "integer pixelsamples, integer seed"
                             : "integer pixelsamples, integer seed, string randomization", NULL))
        return 0;
    if (spp < 1 || spp > MAX_SPP)
        return fail_param(P, pl, "pixelsamples", file, line, "Sampler: %d samples per pixel outside 1..%d", spp, MAX_SPP);
    st->spp = spp;
    st->spp_set = given;
    st->seed = seed;
    st->seed_set = seed_given;
    st->xsamples = xs;
    st->ysamples = ys;
    st->jitter = jitter;
    /* pbrt-v4's samplers specnee does not have map to the nearest it has
       (docs/sampling.md): halton, pmj02bn and paddedsobol are per-pixel
       stratified low-discrepancy points like specnee's padded Owen-scrambled sobol */
    if (!strcmp(type, "halton") || !strcmp(type, "pmj02bn") || !strcmp(type, "paddedsobol")) {
        fprintf(stderr, "%s:%d: note: Sampler \"%s\": specnee uses its nearest, \"sobol\" "
                "(padded, Owen-scrambled), with the same sample count\n", file, line, type);
        type = "sobol";
    }
    snprintf(st->sampler, sizeof st->sampler, "%s", type);
    return 1;
}

static int integrator_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const char *const pbrt_types[] = {
        "ambientocclusion", "bdpt", "lightpath", "mlt", "randomwalk",
        "simplevolpath", "sppm", "volpath", NULL
    };
    SceneSettings *st = &P->s->settings;
    int i, maxdepth, given, regularize, dummy_i;
    float dummy_f;
    const char *ls = NULL, *reads;
    char what[64];
    /* volpath (pbrt-v4's default) is specnee's path tracer with its media
       (render.c, docs/media.md); bdpt converges to the same image (pbrt-v4's bdpt
       renders media too); sppm and simplepath (pbrt-v4's unidirectional path tracer
       without MIS: uniform light choice, lights and/or BSDF sampled, every variant
       unbiased) to the image of "path", which ignores media (settings.media_ignored) */
    int as_path = !strcmp(type, "volpath") || !strcmp(type, "bdpt") || !strcmp(type, "sppm") ||
                  !strcmp(type, "simplepath");
    if (strcmp(type, "path") != 0 && !as_path) {
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i]))
                return fail(P, file, line, "Integrator \"%s\" is valid pbrt-v4 but not in the "
                            "specnee subset (use \"path\")", type);
        return fail(P, file, line, "Integrator \"%s\": unknown integrator type", type);
    }
    snprintf(what, sizeof what, "Integrator \"%s\"", type);
    if (!get_int(P, pl, "maxdepth", DEFAULT_MAXDEPTH, &maxdepth, &given)) return 0;
    if (strcmp(type, "bdpt") != 0 && strcmp(type, "sppm") != 0 && strcmp(type, "simplepath") != 0 &&
        !get_string(P, pl, "lightsampler", &ls)) return 0;
    if (strcmp(type, "sppm") != 0 && strcmp(type, "simplepath") != 0 &&
        !get_bool(P, pl, "regularize", 0, &regularize)) return 0;
    if (!strcmp(type, "sppm") || !strcmp(type, "simplepath")) regularize = 0;
    if (!strcmp(type, "simplepath") &&
        (!get_bool(P, pl, "samplelights", 1, &dummy_i) || !get_bool(P, pl, "samplebsdf", 1, &dummy_i)))
        return 0;
    {   /* pbrt-v3's Russian-roulette threshold, which pbrt-v4 read only in 2020
           (until its commit 56ee5e8c): current pbrt-v4 starts the roulette when the
           throughput's largest component falls below 1 after the second bounce,
           its --upgrade drops the parameter and a plain pbrt-v4 refuses it as
           unused.  The roulette is unbiased, so ignoring it changes noise only,
           never the expected image */
        Param *rr = param_find(pl, PT_FLOAT, "rrthreshold");
        if (rr)
            fprintf(stderr, "%s:%d: note: Integrator \"float rrthreshold\" is pbrt-v3 syntax "
                    "that pbrt-v4 no longer reads (its --upgrade drops it): ignored\n",
                    rr->file, rr->line);
    }
    if (!strcmp(type, "bdpt")) {
        /* debugging images of bdpt's strategies: nothing to show for path */
        if (!get_bool(P, pl, "visualizestrategies", 0, &dummy_i)) return 0;
        if (dummy_i) return fail(P, file, line, "Integrator \"bdpt\": visualizestrategies is "
                                 "not in the specnee subset");
        if (!get_bool(P, pl, "visualizeweights", 0, &dummy_i)) return 0;
        if (dummy_i) return fail(P, file, line, "Integrator \"bdpt\": visualizeweights is "
                                 "not in the specnee subset");
    }
    if (!strcmp(type, "sppm")) {              /* photon-map settings: no meaning for path */
        if (!get_int(P, pl, "photonsperiteration", -1, &dummy_i, NULL)) return 0;
        if (!get_float(P, pl, "radius", 1.0f, &dummy_f)) return 0;
        if (!get_int(P, pl, "seed", 0, &dummy_i, NULL)) return 0;
    }
    reads = !strcmp(type, "bdpt") ? "integer maxdepth, bool regularize, "
                "bool visualizestrategies, bool visualizeweights"
            : !strcmp(type, "sppm") ? "integer maxdepth, integer "
                "photonsperiteration, float radius, integer seed"
            : !strcmp(type, "simplepath") ? "integer maxdepth, bool samplelights, bool samplebsdf"
            : "integer maxdepth, string lightsampler, bool regularize";
    /* the first problem in the file is named: a parameter left over before
       "bool regularize" true, else regularize, else one after it */
    if (regularize)
        return refuse_param(P, pl, what, reads, param_find(pl, PT_BOOL, "regularize"), file, line,
                            "Integrator: \"bool regularize\" true is valid pbrt-v4 but "
                            "not supported by specnee");
    if (!params_check_unused(P, pl, what, reads, NULL))
        return 0;
    if (as_path && strcmp(type, "volpath") != 0)
        fprintf(stderr, "%s:%d: note: Integrator \"%s\" is rendered by specnee's path tracer "
                "(the same expected image%s)\n", file, line, type,
                !strcmp(type, "bdpt") ? ", media included" : "; media are ignored, as by pbrt-v4's");
    st->media_ignored = !strcmp(type, "path") || !strcmp(type, "simplepath") || !strcmp(type, "sppm");
    P->integ_file = file;
    P->integ_line = line;
    snprintf(P->integ_type, sizeof P->integ_type, "%s", type);
    if (maxdepth < 0 || maxdepth > MAX_MAXDEPTH)
        return fail_param(P, pl, "maxdepth", file, line, "Integrator: maxdepth %d outside 0..%d", maxdepth, MAX_MAXDEPTH);
    st->maxdepth = maxdepth;
    st->maxdepth_set = given;
    if (ls) {
        if (strlen(ls) + 1 > sizeof st->lightsampler)
            return fail(P, file, line, "Integrator: lightsampler name \"%s\" too long", ls);
        snprintf(st->lightsampler, sizeof st->lightsampler, "%s", ls);
    }
    return 1;
}

/* ===========================================================================
   3. Directives of the world block: materials, lights, shapes
   =========================================================================== */

/* ---------------------------------------------------------------------------
   Textures: the Texture directive (texture.c builds each class)
   --------------------------------------------------------------------------- */
/* Texture "name" "spectrum"|"float" "class" params (pbrt-v4's Texture). */
static int texture_directive(Parser *P, Lexer *L, const Token *t)
{
    Scene *s = P->s;
    Token a[3];
    ParamList pl;
    Texture T;
    int ok = 0;
    if (!P->in_world)
        return fail(P, t->file, t->line, "Scene description must be inside world block; "
                    "\"Texture\" not allowed before WorldBegin");
    if (!expect_string(P, L, "Texture", "texture name", &a[0]) ||
        !expect_string(P, L, "Texture", "\"spectrum\" or \"float\"", &a[1]) ||
        !expect_string(P, L, "Texture", "texture class", &a[2]))
        return 0;
    memset(&pl, 0, sizeof pl);
    if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
    memset(&T, 0, sizeof T);
    T.file = t->file;
    T.line = t->line;
    T.amount_tex = T.scale_tex = -1;
    T.arg_tex[0] = T.arg_tex[1] = -1;
    if (strlen(a[0].text) >= sizeof P->texnames[0].name) {
        ok = fail(P, t->file, t->line, "Texture: name too long");
        goto done;
    }
    if (!strcmp(a[1].text, "float")) T.is_float = 1;
    else if (strcmp(a[1].text, "spectrum") != 0) {
        ok = fail(P, t->file, t->line, "Texture \"%s\": type \"%s\" must be \"spectrum\" or "
                  "\"float\"", a[0].text, a[1].text);
        goto done;
    }
    ok = texture_from_params(P, &pl, a[0].text, a[2].text, &T);
    if (ok) {
        if (!grow((void **)&s->textures, &P->cap_textures, s->n_textures + 1, sizeof(Texture)) ||
            !grow((void **)&P->texnames, &P->cap_texnames, P->n_texnames + 1, sizeof(NamedTexture))) {
            ok = oom(P, t->file, t->line);
        } else {
            NamedTexture *nt = &P->texnames[P->n_texnames++];
            snprintf(nt->name, sizeof nt->name, "%s", a[0].text);
            nt->is_float = T.is_float;
            nt->index = s->n_textures;
            s->textures[s->n_textures++] = T;
            T.texel = NULL;                    /* owned by the scene now */
        }
    }
done:
    tex_free(&T);
    params_free(&pl);
    return ok;
}

/* The material types and the rooms that build them from their parameters
   (pbrt-v4's per-type Create): material.c, conductor.c, layered.c. */
static const struct {
    const char *type;
    int (*build)(Parser *P, ParamList *pl, const char *file, int line, const char *dir,
                 const char *what, Material *m);
} material_types[] = {
    { "interface", interface_from_params }, { "", interface_from_params },
    { "none", interface_from_params },      /* pbrt-v4's deprecated spellings */
    { "diffuse", diffuse_from_params }, { "fluorescent", fluorescent_from_params },
    { "dielectric", dielectric_from_params }, { "conductor", conductor_from_params },
    { "coateddiffuse", coateddiffuse_from_params },
    { "coatedconductor", coatedconductor_from_params },
    { "thindielectric", thindielectric_from_params },
    { "diffusetransmission", diffusetransmission_from_params }
};

/* Material m of `type` (a Material or MakeNamedMaterial directive `dir`). */
static int material_from_params(Parser *P, const char *type, ParamList *pl, const char *file,
                                int line, Material *m, const char *dir)
{
    char what[192];
    int k;
    memset(m, 0, sizeof *m);
    spec_const(&m->eta, 1.0f);
    snprintf(what, sizeof what, "%s \"%s\"", dir, type);
    for (k = 0; k < (int)(sizeof material_types / sizeof material_types[0]); k++)
        if (!strcmp(type, material_types[k].type))
            return material_types[k].build(P, pl, file, line, dir, what, m);
    {
        static const char *const pbrt_types[] = {
            "hair", "measured", "mix", "subsurface", NULL
        };
        int i;
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i]))
                return fail(P, file, line, "%s \"%s\" is valid pbrt-v4 but not in the "
                            "specnee subset (use \"diffuse\", \"dielectric\", \"conductor\", "
                            "\"coateddiffuse\", \"coatedconductor\", \"thindielectric\" or "
                            "\"diffusetransmission\")", dir, type);
        return fail(P, file, line, "%s \"%s\": unknown material type", dir, type);
    }
}

static int area_light_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    AreaLightDesc al;
    if (!area_light_from_params(P, type, pl, file, line, &al)) return 0;
    if (!grow((void **)&P->lights, &P->cap_lights, P->n_lights + 1, sizeof(AreaLightDesc)))
        return oom(P, file, line);
    P->lights[P->n_lights] = al;
    P->gs.area_light = P->n_lights++;
    return 1;
}

/* LightSource: the delta lights (delta.c) and the infinite light (infinite.c)
   build the Emitter from the parameters; it joins Scene.emitters here. */
static int light_source_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const char *const pbrt_types[] = { "goniometric", "projection", NULL };
    Scene *s = P->s;
    Emitter em;
    int i, ok;
    if (!strcmp(type, "point") || !strcmp(type, "spot") || !strcmp(type, "distant"))
        ok = delta_light_from_params(P, type, pl, file, line, &em);
    else if (!strcmp(type, "infinite"))
        ok = infinite_light_from_params(P, pl, file, line, &em);
    else {
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i]))
                return fail(P, file, line, "LightSource \"%s\" is valid pbrt-v4 but not in the "
                            "specnee subset (infinite, point, spot, distant)", type);
        return fail(P, file, line, "LightSource \"%s\": unknown light type", type);
    }
    if (!ok) return 0;
    if (!grow((void **)&s->emitters, &P->cap_emit, s->n_emitters + 1, sizeof(Emitter))) {
        inf_free(em.inf);
        return oom(P, file, line);
    }
    s->emitters[s->n_emitters++] = em;
    return 1;
}

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

static int mesh_shape(Parser *P, int bilinear, ParamList *pl, const char *file, int line)
{
    const double *Pd, *Nd, *UV, *Id;
    int nv, nn, nuv, ni, per = bilinear ? 4 : 3, i, ok, ntri;
    const char *what = bilinear ? "Shape \"bilinearmesh\"" : "Shape \"trianglemesh\"";
    float *Pf = NULL, *Nf = NULL, *UVf = NULL;
    int32_t *idx = NULL;
    int32_t deflt[4] = { 0, 1, 2, 3 };
    if (!get_points(P, pl, PT_INTEGER, "indices", 1, &Id, &ni)) return 0;
    if (!get_points(P, pl, PT_POINT3, "P", 3, &Pd, &nv)) return 0;
    if (!get_points(P, pl, PT_NORMAL, "N", 3, &Nd, &nn)) return 0;
    if (!get_points(P, pl, PT_POINT2, "uv", 2, &UV, &nuv)) return 0;
    if (!params_check_unused(P, pl, what, "integer indices, point3 P, normal N, point2 uv",
                             "S faceIndices alpha emissionfilename displacement"))
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
    if (ni == 0) ni = per;
    for (i = 0; i < ni; i++) {
        int k = Id ? (int)Id[i] : deflt[i];
        if (k < 0 || k >= nv)
            return fail(P, file, line, "%s: vertex index %d out of range [0, %d)", what, k, nv);
    }
    ntri = bilinear ? ni / 2 : ni / 3;                /* a patch is two triangles */
    Pf = (float *)malloc(sizeof(float) * 3 * (size_t)nv);
    Nf = nn ? (float *)malloc(sizeof(float) * 3 * (size_t)nv) : NULL;
    idx = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)ntri);
    if (!Pf || !idx || (nn && !Nf)) { free(Pf); free(Nf); free(idx); return oom(P, file, line); }
    for (i = 0; i < 3 * nv; i++) {
        Pf[i] = (float)Pd[i];
        if (Nf) Nf[i] = (float)Nd[i];
    }
    if (!bilinear) {
        for (i = 0; i < ni; i++) idx[i] = Id ? (int32_t)Id[i] : deflt[i];
    } else {
        /* pbrt's patch order p00 p10 p01 p11 -> (p00,p10,p11), (p00,p11,p01): the
           first edge pair (p10 - p00, p11 - p00) keeps the patch's dp/du x dp/dv side */
        for (i = 0; i < ni / 4; i++) {
            int32_t q[4];
            int k;
            for (k = 0; k < 4; k++) q[k] = Id ? (int32_t)Id[4 * i + k] : deflt[k];
            idx[6 * i + 0] = q[0]; idx[6 * i + 1] = q[1]; idx[6 * i + 2] = q[3];
            idx[6 * i + 3] = q[0]; idx[6 * i + 4] = q[3]; idx[6 * i + 5] = q[2];
        }
    }
    ok = 1;
    if (nuv) {
        UVf = (float *)malloc(sizeof(float) * 2 * (size_t)nv);
        if (!UVf) { free(Pf); free(Nf); free(idx); return oom(P, file, line); }
        for (i = 0; i < 2 * nv; i++) UVf[i] = (float)UV[i];
    }
    ok = ok && add_mesh(P, Pf, Nf, UVf, nv, idx, ntri, file, line);
    free(Pf); free(Nf); free(UVf); free(idx);
    return ok;
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
    /* an area light is sampled uniformly by object area: that must be uniform by
       world area, or emitter_pdf_sa's 1 / area would not be its density (shapes.c) */
    if (shp->emitter >= 0 && !quadric_uniform_sampling(shp))
        return fail(P, file, line, "%s: an area light under a non-uniform scale or shear "
                    "is not in the specnee subset (its area sampling would not be uniform)", what);
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
                             "float phimax", "alpha emissionfilename"))
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
                             "alpha emissionfilename"))
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
                             "alpha emissionfilename"))
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

static int ply_shape(Parser *P, ParamList *pl, const char *file, int line)
{
    const char *fn;
    char path[1024];
    PlyMesh mesh;
    Error e;
    int ok, i;
    if (!get_string(P, pl, "filename", &fn)) return 0;
    if (!params_check_unused(P, pl, "Shape \"plymesh\"", "string filename",
                             "displacement edgelength alpha emissionfilename"))
        return 0;
    if (!fn) return fail(P, file, line, "Shape \"plymesh\": \"string filename\" is required");
    resolve_path(P, file, fn, path, sizeof path);
    memset(&mesh, 0, sizeof mesh);
    if (!ply_read(path, &mesh, &e))
        return fail(P, file, line, "Shape \"plymesh\": %s", e.msg);
    for (i = 0; i < 3 * mesh.n_tris; i++)
        if (mesh.idx[i] < 0 || mesh.idx[i] >= mesh.n_verts) {
            ply_free(&mesh);
            return fail(P, file, line, "Shape \"plymesh\" \"%s\": vertex index out of range", fn);
        }
    ok = add_mesh(P, mesh.P, mesh.N, mesh.UV, mesh.n_verts, mesh.idx, mesh.n_tris, file, line);
    ply_free(&mesh);
    return ok;
}

static int shape_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    if (!strcmp(type, "trianglemesh")) return mesh_shape(P, 0, pl, file, line);
    if (!strcmp(type, "bilinearmesh")) return mesh_shape(P, 1, pl, file, line);
    if (!strcmp(type, "sphere")) return sphere_shape(P, pl, file, line);
    if (!strcmp(type, "disk")) return disk_shape(P, pl, file, line);
    if (!strcmp(type, "cylinder")) return cylinder_shape(P, pl, file, line);
    if (!strcmp(type, "plymesh")) return ply_shape(P, pl, file, line);
    if (!strcmp(type, "curve") || !strcmp(type, "loopsubdiv"))
        return fail(P, file, line, "Shape \"%s\" is valid pbrt-v4 but not in the specnee subset",
                    type);
    return fail(P, file, line, "Shape \"%s\": unknown shape type", type);
}

/* ===========================================================================
   4. The directive loop
   =========================================================================== */
static int parse_text(Parser *P, const char *file, char *buf, size_t len);

/* Include: the file's tokens come next in the same stream (pbrt-v4 pushes it on
   its file stack).  Import: parsed on its own into a copy of the graphics state.
   Both count against the include budget: MAX_INCLUDES directives and
   READ_MAX_BYTES of text in all, so that files which include the next one twice
   cannot keep the parser busy for hours. */
static int include_directive(Parser *P, Lexer *L, const Token *dir, int is_import)
{
    Token t;
    char path[1024];
    const char *name;
    char *buf;
    size_t len;
    ReadStatus rs;
    int ok, depth = P->depth;
    GState saved = P->gs;
    const char *d = is_import ? "Import" : "Include";
    if (!expect_string(P, L, d, "file name", &t)) return 0;
    if (is_import && !P->in_world)
        return fail(P, dir->file, dir->line, "Import is only allowed after WorldBegin");
    if (P->nest >= MAX_INCLUDE_DEPTH)
        return fail(P, dir->file, dir->line, "%s \"%s\": nested deeper than %d (an include cycle?)",
                    d, t.text, MAX_INCLUDE_DEPTH);
    if (++P->n_includes > MAX_INCLUDES)
        return fail(P, dir->file, dir->line, "%s \"%s\": more than %d Include/Import directives "
                    "run in one scene (files that include each other repeatedly?)",
                    d, t.text, MAX_INCLUDES);
    resolve_path(P, t.file, t.text, path, sizeof path);
    buf = read_whole_file(path, 1, NULL, &len, &rs);
    if (!buf) {
        if (rs == READ_OPEN)
            return fail(P, dir->file, dir->line, "%s \"%s\": cannot read \"%s\"", d, t.text, path);
        return fail(P, dir->file, dir->line, "%s \"%s\": \"%s\": %s", d, t.text, path,
                    read_status_text(rs));
    }
    if (len > READ_MAX_BYTES - P->text_bytes) {
        free(buf);
        return fail(P, dir->file, dir->line, "%s \"%s\": the scene text with its included files "
                    "exceeds %lu MiB (files that include each other repeatedly?)", d, t.text,
                    (unsigned long)(READ_MAX_BYTES >> 20));
    }
    P->text_bytes += len;
    name = intern(P, path);
    if (!name) { free(buf); return oom(P, dir->file, dir->line); }
    if (!is_import) {                                  /* push: its tokens come next */
        L->parent[L->n_parent++] = L->cur;
        L->cur.file = name;
        L->cur.buf = buf;
        L->cur.len = len;
        L->cur.pos = 0;
        L->cur.line = 1;
        L->file = name;
        P->nest++;
        return 1;
    }
    P->include_depth++;
    P->nest++;
    ok = parse_text(P, name, buf, len);
    P->nest--;
    P->include_depth--;
    free(buf);
    if (!ok) return 0;
    /* pbrt-v4 parses an import into a copy of the graphics state */
    if (P->depth != depth)
        return fail(P, dir->file, dir->line, "Import \"%s\": unbalanced AttributeBegin/End "
                    "inside the imported file", t.text);
    P->gs = saved;
    return 1;
}

static int transform_directive(Parser *P, Lexer *L, const Token *t, int *handled)
{
    const char *d = t->text;
    double v[16];
    Xform x;
    *handled = 1;
    if (!strcmp(d, "Identity")) { P->gs.ctm = xf_identity(); return 1; }
    if (!strcmp(d, "Translate")) {
        if (!expect_number(P, L, d, 3, v)) return 0;
        x = xf_translate(v[0], v[1], v[2]);
    } else if (!strcmp(d, "Scale")) {
        if (!expect_number(P, L, d, 3, v)) return 0;
        if (v[0] == 0.0 || v[1] == 0.0 || v[2] == 0.0)
            return fail(P, t->file, t->line, "Scale %g %g %g: a zero factor flattens space "
                        "(singular transform)", v[0], v[1], v[2]);
        x = xf_scale(v[0], v[1], v[2]);
    } else if (!strcmp(d, "Rotate")) {
        if (!expect_number(P, L, d, 4, v)) return 0;
        if (v[1] == 0.0 && v[2] == 0.0 && v[3] == 0.0)
            return fail(P, t->file, t->line, "Rotate: the axis is the zero vector");
        x = xf_rotate(v[0], v[1], v[2], v[3]);
    } else if (!strcmp(d, "LookAt")) {
        if (!expect_number(P, L, d, 9, v)) return 0;
        if (!xf_lookat(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], &x))
            return fail(P, t->file, t->line, "LookAt: degenerate (eye == look, or up parallel "
                        "to the viewing direction)");
    } else if (!strcmp(d, "Transform") || !strcmp(d, "ConcatTransform")) {
        double m[4][4];
        int i, j;
        if (!expect_matrix(P, L, d, v)) return 0;
        for (i = 0; i < 4; i++)
            for (j = 0; j < 4; j++) m[i][j] = v[4 * j + i];   /* pbrt-v4: transposed */
        if (!xf_from_matrix(m, &x))
            return fail(P, t->file, t->line, "%s: singular matrix", d);
        if (d[0] == 'T') { P->gs.ctm = x; return 1; }     /* Transform replaces the CTM */
    } else if (!strcmp(d, "CoordinateSystem") || !strcmp(d, "CoordSysTransform")) {
        Token n;
        int i;
        if (!expect_string(P, L, d, "name", &n)) return 0;
        for (i = 0; i < P->n_coords; i++)
            if (!strcmp(P->coords[i].name, n.text)) break;
        if (d[5] == 'i') {                                 /* CoordinateSystem: record */
            if (strlen(n.text) >= sizeof P->coords[0].name)
                return fail(P, t->file, t->line, "CoordinateSystem: name too long");
            if (i == P->n_coords) {
                if (!grow((void **)&P->coords, &P->cap_coords, P->n_coords + 1, sizeof(NamedCoordSys)))
                    return oom(P, t->file, t->line);
                snprintf(P->coords[i].name, sizeof P->coords[i].name, "%s", n.text);
                P->n_coords++;
            }
            P->coords[i].xf = P->gs.ctm;
            return 1;
        }
        if (i == P->n_coords)
            return fail(P, t->file, t->line, "CoordSysTransform: unknown coordinate system "
                        "\"%s\"", n.text);
        P->gs.ctm = P->coords[i].xf;
        return 1;
    } else {
        *handled = 0;
        return 1;
    }
    P->gs.ctm = xf_mul(&P->gs.ctm, &x);                   /* CTM <- CTM * T */
    return 1;
}

/* Directives with a quoted type name and a parameter list. */
/* ===========================================================================
   Participating media (medium.c): MakeNamedMedium and MediumInterface
   =========================================================================== */
/* The Scene.media index of `name` ("" is no medium: -1), made at its first
   mention (MediumRef); -2 on out of memory. */
static int medium_ref(Parser *P, const char *name, const char *file, int line)
{
    Scene *s = P->s;
    int i;
    if (!name[0]) return -1;
    for (i = 0; i < s->n_media; i++)
        if (!strcmp(s->media[i].name, name)) return i;
    if (strlen(name) >= sizeof s->media[0].name) {
        fail(P, file, line, "medium name \"%.40s...\" too long", name);
        return -2;
    }
    if (!grow((void **)&s->media, &P->cap_media, s->n_media + 1, sizeof(Medium))) {
        oom(P, file, line);
        return -2;
    }
    if (!grow((void **)&P->mrefs, &P->cap_mrefs, s->n_media + 1, sizeof(MediumRef))) {
        oom(P, file, line);
        return -2;
    }
    memset(&s->media[s->n_media], 0, sizeof(Medium));
    snprintf(s->media[s->n_media].name, sizeof s->media[0].name, "%s", name);
    P->mrefs[s->n_media].defined = 0;
    P->mrefs[s->n_media].file = file;
    P->mrefs[s->n_media].line = line;
    return s->n_media++;
}

/* MakeNamedMedium "name" params: medium.c builds the medium, named here. */
static int make_named_medium(Parser *P, Lexer *L, const Token *t)
{
    Token nm;
    ParamList pl;
    char what[160];
    Medium m;
    int ok = 0, idx;
    if (!expect_string(P, L, "MakeNamedMedium", "medium name", &nm)) return 0;
    memset(&pl, 0, sizeof pl);
    if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
    snprintf(what, sizeof what, "MakeNamedMedium \"%.100s\"", nm.text);
    if (!medium_from_params(P, &pl, what, t->file, t->line, &m)) goto done;
    idx = medium_ref(P, nm.text, t->file, t->line);
    if (idx == -2) goto done;
    if (idx == -1) { fail(P, t->file, t->line, "MakeNamedMedium: the name \"\" is no medium"); goto done; }
    if (P->mrefs[idx].defined) {
        fail(P, t->file, t->line, "MakeNamedMedium: medium \"%s\" redefined (first at %s:%d)",
             nm.text, P->s->media[idx].file, P->s->media[idx].line);
        goto done;
    }
    snprintf(m.name, sizeof m.name, "%s", nm.text);
    P->s->media[idx] = m;
    P->mrefs[idx].defined = 1;
    ok = 1;
done:
    params_free(&pl);
    return ok;
}

/* MediumInterface "inside" "outside" (one name: both); "" is no medium */
static int medium_interface(Parser *P, Lexer *L, const Token *t)
{
    Token a, b;
    int in, out;
    if (!expect_string(P, L, "MediumInterface", "inside medium name", &a)) return 0;
    if (!lex_next(P, L, &b)) return 0;
    if (b.kind != TK_STRING) { lex_unget(L, &b); b = a; }
    in = medium_ref(P, a.text, t->file, t->line);
    if (in == -2) return 0;
    out = medium_ref(P, b.text, t->file, t->line);
    if (out == -2) return 0;
    P->gs.medium_inside = in;
    P->gs.medium_outside = out;
    return 1;
}

static int typed_directive(Parser *P, Lexer *L, const Token *t)
{
    const char *d = t->text;
    Token ty;
    ParamList pl;
    char type[128];
    int ok = 0, world_only, options_only;
    options_only = !strcmp(d, "Camera") || !strcmp(d, "Film") || !strcmp(d, "Sampler")
                || !strcmp(d, "Integrator") || !strcmp(d, "PixelFilter")
                || !strcmp(d, "Accelerator");
    world_only = !strcmp(d, "Material") || !strcmp(d, "MakeNamedMaterial")
              || !strcmp(d, "AreaLightSource") || !strcmp(d, "Shape") || !strcmp(d, "LightSource");
    if (options_only && P->in_world)
        return fail(P, t->file, t->line, "Options cannot be set inside world block; \"%s\" "
                    "not allowed after WorldBegin", d);
    if (world_only && !P->in_world)
        return fail(P, t->file, t->line, "Scene description must be inside world block; "
                    "\"%s\" not allowed before WorldBegin", d);
    if (!expect_string(P, L, d, "type name", &ty)) return 0;
    snprintf(type, sizeof type, "%s", ty.text);
    memset(&pl, 0, sizeof pl);
    if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
    if (!strcmp(d, "Camera")) ok = camera_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Film")) ok = film_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Sampler")) ok = sampler_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Integrator")) ok = integrator_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "PixelFilter")) ok = filter_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Accelerator")) ok = accelerator_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Shape")) ok = shape_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "AreaLightSource")) ok = area_light_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "LightSource")) ok = light_source_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Material")) {
        Material m;
        int idx;
        ok = material_from_params(P, type, &pl, t->file, t->line, &m, "Material");
        if (ok) {
            idx = add_material(P, &m, t->file, t->line);
            ok = idx >= 0;
            if (ok) P->gs.material = idx;
        }
    } else if (!strcmp(d, "MakeNamedMaterial")) {
        /* MakeNamedMaterial "name" "string type" "diffuse" ... */
        const char *mtype;
        Material m;
        int i, idx;
        ok = get_string(P, &pl, "type", &mtype);
        if (ok && !mtype)
            ok = fail(P, t->file, t->line, "MakeNamedMaterial \"%s\": \"string type\" is "
                      "required", type);
        for (i = 0; ok && i < P->n_named; i++)
            if (!strcmp(P->named[i].name, type)) {
                if (P->named[i].material >= 0)
                    ok = fail(P, t->file, t->line, "MakeNamedMaterial: named material \"%s\" "
                              "redefined", type);
                break;                  /* else used before: made now */
            }
        if (ok && strlen(type) >= sizeof P->named[0].name)
            ok = fail(P, t->file, t->line, "MakeNamedMaterial: name too long");
        if (ok) {
            char what[128];
            snprintf(what, sizeof what, "MakeNamedMaterial \"%.100s\": type", type);
            ok = material_from_params(P, mtype, &pl, t->file, t->line, &m, what);
        }
        if (ok) {
            idx = add_material(P, &m, t->file, t->line);
            ok = idx >= 0;
        }
        if (ok && i < P->n_named) {
            P->named[i].material = idx;     /* a NamedMaterial before it: resolved in finish() */
        } else if (ok) {
            if (!grow((void **)&P->named, &P->cap_named, P->n_named + 1, sizeof(NamedMaterial)))
                ok = oom(P, t->file, t->line);
            else {
                snprintf(P->named[P->n_named].name, sizeof P->named[0].name, "%.63s", type); /* length checked above */
                P->named[P->n_named].file = t->file;
                P->named[P->n_named].line = t->line;
                P->named[P->n_named++].material = idx;
            }
        }
    }
    params_free(&pl);
    return ok;
}

static int directive(Parser *P, Lexer *L, const Token *t)
{
    const char *d = t->text;
    int handled;
    if (!transform_directive(P, L, t, &handled)) return 0;
    if (handled) return 1;
    if (!strcmp(d, "Camera") || !strcmp(d, "Film") || !strcmp(d, "Sampler")
        || !strcmp(d, "Integrator") || !strcmp(d, "PixelFilter") || !strcmp(d, "Shape")
        || !strcmp(d, "Accelerator") || !strcmp(d, "Material") || !strcmp(d, "MakeNamedMaterial")
        || !strcmp(d, "AreaLightSource") || !strcmp(d, "LightSource"))
        return typed_directive(P, L, t);
    if (!strcmp(d, "WorldBegin")) {
        int i;
        if (P->in_world)
            return fail(P, t->file, t->line, "Options cannot be set inside world block; "
                        "second \"WorldBegin\"");
        P->in_world = P->world_seen = 1;
        P->gs.ctm = xf_identity();
        for (i = 0; i < P->n_coords; i++)
            if (!strcmp(P->coords[i].name, "world")) break;
        if (i == P->n_coords) {
            if (!grow((void **)&P->coords, &P->cap_coords, P->n_coords + 1, sizeof(NamedCoordSys)))
                return oom(P, t->file, t->line);
            snprintf(P->coords[i].name, sizeof P->coords[i].name, "world");
            P->n_coords++;
        }
        P->coords[i].xf = xf_identity();
        return 1;
    }
    if (!strcmp(d, "WorldEnd"))
        return fail(P, t->file, t->line, "WorldEnd is pbrt-v3 syntax, not pbrt-v4 (delete it)");
    if (!strcmp(d, "AttributeBegin") || !strcmp(d, "TransformBegin")) {
        /* pbrt-v4 treats the deprecated TransformBegin as AttributeBegin */
        if (!P->in_world)
            return fail(P, t->file, t->line, "Scene description must be inside world block; "
                        "\"%s\" not allowed before WorldBegin", d);
        if (!grow((void **)&P->stack, &P->stack_cap, P->depth + 1, sizeof(GState)))
            return oom(P, t->file, t->line);
        P->gs.file = t->file;
        P->gs.line = t->line;
        P->stack[P->depth++] = P->gs;
        return 1;
    }
    if (!strcmp(d, "AttributeEnd") || !strcmp(d, "TransformEnd")) {
        if (!P->in_world)
            return fail(P, t->file, t->line, "Scene description must be inside world block; "
                        "\"%s\" not allowed before WorldBegin", d);
        if (P->depth == 0)
            return fail(P, t->file, t->line, "unmatched %s (no AttributeBegin open)", d);
        P->gs = P->stack[--P->depth];
        return 1;
    }
    if (!strcmp(d, "ReverseOrientation")) {
        if (!P->in_world)
            return fail(P, t->file, t->line, "Scene description must be inside world block; "
                        "\"ReverseOrientation\" not allowed before WorldBegin");
        P->gs.reverse = !P->gs.reverse;
        return 1;
    }
    if (!strcmp(d, "NamedMaterial")) {
        Token n;
        int i;
        if (!expect_string(P, L, d, "material name", &n)) return 0;
        if (!P->in_world)
            return fail(P, t->file, t->line, "Scene description must be inside world block; "
                        "\"NamedMaterial\" not allowed before WorldBegin");
        for (i = 0; i < P->n_named; i++)
            if (!strcmp(P->named[i].name, n.text)) {
                P->gs.material = P->named[i].material >= 0 ? P->named[i].material : -2 - i;
                return 1;
            }
        /* not made yet: pbrt-v4 looks the name up at the end of the file */
        if (strlen(n.text) >= sizeof P->named[0].name)
            return fail(P, t->file, t->line, "NamedMaterial: name too long");
        if (!grow((void **)&P->named, &P->cap_named, P->n_named + 1, sizeof(NamedMaterial)))
            return oom(P, t->file, t->line);
        snprintf(P->named[i].name, sizeof P->named[0].name, "%.63s", n.text);
        P->named[i].material = -1;
        P->named[i].file = t->file;
        P->named[i].line = t->line;
        P->n_named++;
        P->gs.material = -2 - i;
        return 1;
    }
    if (!strcmp(d, "Texture")) return texture_directive(P, L, t);
    if (!strcmp(d, "MakeNamedMedium")) return make_named_medium(P, L, t);
    if (!strcmp(d, "MediumInterface")) return medium_interface(P, L, t);
    if (!strcmp(d, "Include")) return include_directive(P, L, t, 0);
    if (!strcmp(d, "Import")) return include_directive(P, L, t, 1);
    if (!strcmp(d, "ColorSpace")) {
        Token n;
        if (!expect_string(P, L, d, "colour space name", &n)) return 0;
        if (strcmp(n.text, "srgb") != 0)
            return fail(P, t->file, t->line, "ColorSpace \"%s\" is valid pbrt-v4 but not in the "
                        "specnee subset (only \"srgb\", the default)", n.text);
        return 1;
    }
    {
        static const char *const pbrt_only[] = {
            "ActiveTransform", "Attribute", "ObjectBegin", "ObjectEnd", "ObjectInstance", "Option",
            "TransformTimes", NULL
        };
        int i;
        for (i = 0; pbrt_only[i]; i++)
            if (!strcmp(d, pbrt_only[i])) {
                /* name the type: LightSource "type" ..., Texture "name" "type" "class"
                   (the class says what it is), others their first string */
                Token a[3];
                int k, n = 0, want = !strcmp(d, "Texture") ? 3 : 1;
                for (k = 0; k < want; k++) {
                    if (!lex_next(P, L, &a[k])) return 0;
                    if (a[k].kind != TK_STRING) break;
                    n++;
                }
                if (n == 3)
                    return fail(P, t->file, t->line, "Texture \"%s\" (\"%s\" texture \"%s\") is "
                                "valid pbrt-v4 but not in the specnee subset", a[2].text,
                                a[1].text, a[0].text);
                if (n >= 1 && want == 1)
                    return fail(P, t->file, t->line, "%s \"%s\" is valid pbrt-v4 but not in the "
                                "specnee subset", d, a[0].text);
                return fail(P, t->file, t->line, "%s is valid pbrt-v4 but not in the specnee "
                            "subset", d);
            }
    }
    return fail(P, t->file, t->line, "Unknown directive: %s", d);
}

/* Free the buffers of included files that were read to their end. */
static void lex_release_finished(Lexer *L)
{
    while (L->n_finished > 0) free(L->finished[--L->n_finished]);
}

/* Parse one file's text (the top-level file or an imported one) with the files it
   Includes.  buf belongs to the caller; included buffers are freed here. */
static int parse_text(Parser *P, const char *file, char *buf, size_t len)
{
    Lexer L;
    int ok = 1;
    memset(&L, 0, sizeof L);
    L.cur.file = L.file = file;
    L.cur.buf = buf;
    L.cur.len = len;
    L.cur.line = 1;
    for (;;) {
        Token t;
        char name[MAX_WORD + 1];
        lex_release_finished(&L);       /* the last statement is done with them */
        if (!lex_next(P, &L, &t)) { ok = 0; break; }
        if (t.kind == TK_EOF) break;
        if (P->include_depth == 0 && t.file == file) P->end_line = t.line;
        if (t.kind == TK_STRING) {
            ok = fail(P, t.file, t.line, "expected a directive, found the string \"%s\"",
                      t.text);
            break;
        }
        if (t.kind != TK_WORD) {
            ok = fail(P, t.file, t.line, "expected a directive, found %s", tok_desc(&t));
            break;
        }
        /* keep the name: the lexer reuses its word buffers for the arguments */
        memcpy(name, t.text, strlen(t.text) + 1);
        t.text = name;
        L.dir_file = t.file;
        L.dir_line = t.line;
        if (!directive(P, &L, &t)) { ok = 0; break; }
    }
    lex_release_finished(&L);
    if (L.n_parent > 0) {               /* stopped inside included files: free them */
        free(L.cur.buf);
        while (L.n_parent > 1) free(L.parent[--L.n_parent].buf);
    }
    return ok;
}

/* ===========================================================================
   5. Entry points
   =========================================================================== */
static void settings_default(SceneSettings *st)
{
    memset(st, 0, sizeof *st);
    st->camera_from_world = xf_identity();   /* pbrt-v4: no Camera -> identity */
    st->fov_deg = 90.0f;
    st->camera_medium = -1;
    st->xres = 1280;
    st->yres = 720;
    snprintf(st->filename, sizeof st->filename, "pbrt.pfm");  /* pbrt.exr -> .pfm */
    st->filter = FILTER_GAUSSIAN;            /* pbrt-v4's default pixel filter */
    st->filter_radius = 1.5f;
    st->filter_sigma = 0.5f;
    st->filter_b = st->filter_c = 1.0f / 3.0f; /* mitchell's, sinc's defaults (unused here) */
    st->filter_tau = 3.0f;
    st->spp = DEFAULT_SPP;                   /* pbrt-v4's default zsobol: 16 */
    st->seed = 0;
    st->maxdepth = DEFAULT_MAXDEPTH;
    st->focal_distance = 1e6f;               /* pbrt-v4's default (no lens: unused) */
    st->imaging_ratio = 1.0f;
    st->max_component = INFINITY;
}

static void parser_free(Parser *P)
{
    free(P->stack);
    free(P->lights);
    free(P->named);
    free(P->texnames);
    free(P->coords);
    free(P->mrefs);
}

/* Everything after the last token: checks, bounds, emitters, BVH. */
static int finish(Parser *P, const char *file)
{
    Scene *s = P->s;
    int i;
    if (P->depth > 0) {
        const GState *g = &P->stack[P->depth - 1];
        return fail(P, g->file, g->line, "AttributeBegin without a matching AttributeEnd");
    }
    if (!P->world_seen)
        return fail(P, file, P->end_line, "no WorldBegin: the file describes no world");
    /* materials read their textures from the final table (it moved while growing) */
    for (i = 0; i < s->n_materials; i++) s->materials[i].textures = s->textures;
    /* shapes under a NamedMaterial that came before its MakeNamedMaterial (pbrt-v4
       looks every shape's name up now); a name never made is an error at the
       NamedMaterial that named it, as in pbrt-v4 only if a shape uses it */
    for (i = 0; i < s->n_shapes; i++)
        if (s->shapes[i].material <= -2) {
            const NamedMaterial *nm = &P->named[-2 - s->shapes[i].material];
            if (nm->material < 0)
                return fail(P, nm->file, nm->line, "NamedMaterial \"%s\": no "
                            "MakeNamedMaterial defines it", nm->name);
            s->shapes[i].material = nm->material;
        }
    /* media: every name mentioned is defined; emitters are real surfaces */
    for (i = 0; i < s->n_media; i++)
        if (!P->mrefs[i].defined)
            return fail(P, P->mrefs[i].file, P->mrefs[i].line, "MediumInterface: no "
                        "MakeNamedMedium defines the medium \"%s\"", s->media[i].name);
    for (i = 0; i < s->n_shapes; i++)
        if (s->shapes[i].emitter >= 0 && s->materials[s->shapes[i].material].type == MAT_INTERFACE)
            return fail(P, s->shapes[i].file, s->shapes[i].line, "AreaLightSource on a shape "
                        "with Material \"interface\" (no surface) is not in the specnee subset");
    if (s->n_media > 0 && s->settings.media_ignored)
        fprintf(stderr, "%s:%d: note: Integrator \"%s\" ignores the participating media, as "
                "pbrt-v4's does (\"volpath\" renders them)\n", P->integ_file, P->integ_line,
                P->integ_type);
    if (P->camera_file && !camera_transform_ok(&s->settings.camera_from_world,
                                               s->settings.fov_deg, s->settings.xres,
                                               s->settings.yres))
        return fail(P, P->camera_file, P->camera_line, "Camera: degenerate camera transform "
                    "for the %d x %d film: the viewing directions are not finite, non-zero "
                    "float vectors", s->settings.xres, s->settings.yres);
    /* pbrt-v4 PixelSensor::Create: imaging ratio = exposure time * ISO / 100 */
    s->settings.imaging_ratio = P->exposure_time * P->iso / 100.0f;
    for (i = 0; i < s->n_insets; i++)
        if (s->inset[i][2] > s->settings.xres || s->inset[i][3] > s->settings.yres)
            return fail(P, P->inset_file[i], P->inset_line[i], "inset %s (%d %d %d %d) lies outside the %d x %d film",
                        s->inset_name[i], s->inset[i][0], s->inset[i][1], s->inset[i][2],
                        s->inset[i][3], s->settings.xres, s->settings.yres);
    /* world bounds of all geometry (vertices, spheres), component by component
       (plain floats: tcc 0.9.27 miscompiles a struct-returning call whose result
       is assigned to one of its own arguments inside this loop) */
    {
        float lo[3] = { FLT_MAX, FLT_MAX, FLT_MAX }, hi[3] = { -FLT_MAX, -FLT_MAX, -FLT_MAX };
        for (i = 0; i < s->n_tris; i++) {
            int k, a;
            for (k = 0; k < 3; k++) {
                Vec3 p = s->P[s->tris[i].v[k]];
                for (a = 0; a < 3; a++) {
                    float x = v3_get(p, a);
                    if (x < lo[a]) lo[a] = x;
                    if (x > hi[a]) hi[a] = x;
                }
            }
        }
        for (i = 0; i < s->n_spheres; i++) {
            const Shape *sh = &s->shapes[s->sphere_shape[i]];
            int a;
            for (a = 0; a < 3; a++) {
                float c = v3_get(sh->center, a);
                if (c - sh->radius < lo[a]) lo[a] = c - sh->radius;
                if (c + sh->radius > hi[a]) hi[a] = c + sh->radius;
            }
        }
        for (i = 0; i < s->n_quadrics; i++) {
            float qlo[3], qhi[3];
            int a;
            quadric_bounds(&s->shapes[s->quadric_shape[i]], qlo, qhi);
            for (a = 0; a < 3; a++) {
                if (qlo[a] < lo[a]) lo[a] = qlo[a];
                if (qhi[a] > hi[a]) hi[a] = qhi[a];
            }
        }
        s->bmin = v3(lo[0], lo[1], lo[2]);
        s->bmax = v3(hi[0], hi[1], hi[2]);
    }
    if (s->n_tris == 0 && s->n_spheres == 0 && s->n_quadrics == 0) s->bmin = s->bmax = v3(0, 0, 0);
    if (!P->any_normals) { free(s->N); s->N = NULL; }
    if (!P->any_uv) { free(s->UV); s->UV = NULL; }
    if (s->n_emitters > 0 && !emitters_prepare(s, P->err)) return 0;
    if (!bvh_build(&s->bvh, s))
        return fail(P, file, P->end_line, "out of memory building the BVH");
    return 1;
}

static int load(Scene *s, char *buf, size_t len, const char *name, const char *output,
                Error *err)
{
    Parser P;
    const char *file;
    int ok;
    memset(&P, 0, sizeof P);
    P.s = s;
    P.err = err;
    P.default_material = -1;
    P.gs.ctm = xf_identity();
    P.gs.material = -1;
    P.gs.area_light = -1;
    P.gs.medium_inside = P.gs.medium_outside = -1;
    P.end_line = 1;
    P.iso = 100.0f;                          /* pbrt-v4: imaging ratio 1 by default */
    P.exposure_time = 1.0f;
    P.output = output;
    if (output) snprintf(s->settings.filename, sizeof s->settings.filename, "%s", output);
    dir_of(name, P.main_dir, sizeof P.main_dir);
    file = intern(&P, name);
    if (!file) { parser_free(&P); return fail(&P, name, 0, "out of memory"); }
    P.text_bytes = len;
    ok = parse_text(&P, file, buf, len) && finish(&P, file);
    parser_free(&P);
    return ok;
}

int scene_load_string(Scene *s, const char *text, const char *name, Error *err)
{
    size_t len = strlen(text);
    char *buf = (char *)malloc(len + 1);
    int ok;
    memset(s, 0, sizeof *s);
    settings_default(&s->settings);
    if (!name) name = "<string>";
    if (!buf) { error_set(err, name, 0, "out of memory"); return 0; }
    memcpy(buf, text, len + 1);
    ok = load(s, buf, len, name, NULL, err);
    free(buf);
    if (!ok) scene_free(s);
    return ok;
}

int scene_load_as(Scene *s, const char *path, const char *output, Error *err)
{
    size_t len;
    ReadStatus rs;
    char *buf;
    int ok;
    memset(s, 0, sizeof *s);
    settings_default(&s->settings);
    buf = read_whole_file(path, 1, NULL, &len, &rs);
    if (!buf) {
        error_set(err, path, 0, "%s", rs == READ_OPEN ? "cannot read the scene file"
                  : read_status_text(rs));
        return 0;
    }
    ok = load(s, buf, len, path, output, err);
    free(buf);
    if (!ok) scene_free(s);
    return ok;
}

int scene_load(Scene *s, const char *path, Error *err)
{
    return scene_load_as(s, path, NULL, err);
}

void scene_free(Scene *s)
{
    int i;
    if (!s) return;
    if (s->bvh.node_mem || s->bvh.prims) bvh_free(&s->bvh);
    for (i = 0; i < s->n_emitters; i++) {
        free(s->emitters[i].tri_cdf);
        free(s->emitters[i].planes);
        inf_free(s->emitters[i].inf);
    }
    for (i = 0; i < s->n_strings; i++) free(s->strings[i]);
    free(s->strings);
    free(s->P);
    free(s->N);
    free(s->tris);
    free(s->shapes);
    free(s->media);
    free(s->materials);
    free(s->emitters);
    free(s->sphere_shape);
    free(s->quadric_shape);
    for (i = 0; i < s->n_textures; i++) tex_free(&s->textures[i]);
    free(s->textures);
    free(s->UV);
    memset(s, 0, sizeof *s);
}

/* ===========================================================================
   6. --dump-scene: what the parser understood, in plain text
   =========================================================================== */
static void dump_spectrum(FILE *f, const char *label, const Spectrum *sp)
{
    int l;
    fprintf(f, "    %-12s", label);
    for (l = 400; l <= 700; l += 50) fprintf(f, " %3d:%-8.4g", l, spec_eval(sp, (float)l));
    fprintf(f, "\n");
}

void scene_dump(const Scene *s, FILE *f)
{
    const SceneSettings *st = &s->settings;
    Xform wfc;
    Vec3 eye, dir, up;
    int i;
    memcpy(wfc.m, st->camera_from_world.inv, sizeof wfc.m);   /* world_from_camera */
    memcpy(wfc.inv, st->camera_from_world.m, sizeof wfc.inv);
    eye = xf_point(&wfc, v3(0, 0, 0));
    dir = v3_norm(xf_vector(&wfc, v3(0, 0, 1)));
    up = v3_norm(xf_vector(&wfc, v3(0, 1, 0)));
    fprintf(f, "camera: perspective, fov %g deg (shorter image axis)", st->fov_deg);
    if (st->lens_radius > 0.0f)
        fprintf(f, ", thin lens: lensradius %g focaldistance %g", st->lens_radius,
                st->focal_distance);
    else
        fprintf(f, ", pinhole (lensradius 0)");
    fprintf(f, "\n");
    fprintf(f, "  eye (%g, %g, %g)  dir (%g, %g, %g)  up (%g, %g, %g)%s\n", eye.x, eye.y,
            eye.z, dir.x, dir.y, dir.z, up.x, up.y, up.z,
            xf_swaps_handedness(&st->camera_from_world) ? "  [mirrored: right-handed view]" : "");
    fprintf(f, "film: %d x %d -> %s, filter %s radius %g", st->xres, st->yres, st->filename,
            filter_name(st->filter), st->filter_radius);
    if (st->filter == FILTER_GAUSSIAN) fprintf(f, " sigma %g", st->filter_sigma);
    if (st->filter == FILTER_MITCHELL) fprintf(f, " B %g C %g", st->filter_b, st->filter_c);
    if (st->filter == FILTER_SINC) fprintf(f, " tau %g", st->filter_tau);
    {   /* the sensor: imaging ratio (iso, shutter, pbrt-v3 scale), clamp, white balance */
        int b[4];
        fprintf(f, "\n  sensor cie1931, imaging ratio %g (iso x exposure / 100), "
                "maxcomponentvalue %g, whitebalance ", st->imaging_ratio, st->max_component);
        if (st->white_balance > 0.0f) fprintf(f, "%g K", st->white_balance);
        else fprintf(f, "none");
        if (film_bounds(st, b) && (st->crop_set || st->pixel_bounds_set))
            fprintf(f, "\n  %s: renders and writes pixels x %d..%d, y %d..%d (%d x %d)",
                    st->crop_set ? "cropwindow" : "pixelbounds", b[0], b[1] - 1, b[2],
                    b[3] - 1, b[1] - b[0], b[3] - b[2]);
    }
    fprintf(f, "\nsettings: spp %d%s, seed %d%s, maxdepth %d%s, lightsampler \"%s\"\n",
            st->spp, st->spp_set ? "" : " (default)", st->seed, st->seed_set ? "" : " (default)",
            st->maxdepth, st->maxdepth_set ? "" : " (default)", st->lightsampler);
    for (i = 0; i < s->n_insets; i++)
        fprintf(f, "inset %s: x %d..%d, y %d..%d\n", s->inset_name[i], s->inset[i][0],
                s->inset[i][2], s->inset[i][1], s->inset[i][3]);
    fprintf(f, "materials: %d\n", s->n_materials);
    for (i = 0; i < s->n_materials; i++) {
        const Material *m = &s->materials[i];
        if (m->type == MAT_DIFFUSE) {
            fprintf(f, "  [%d] diffuse\n", i);
            dump_spectrum(f, "reflectance", &m->reflectance);
        } else if (m->type == MAT_FLUORESCENT) {
            fprintf(f, "  [%d] fluorescent, quantum yield %g\n", i, m->qyield);
            dump_spectrum(f, "reflectance", &m->reflectance);
            dump_spectrum(f, "excitation", &m->excitation);
            dump_spectrum(f, "emission", &m->emission);
        } else if (m->type == MAT_CONDUCTOR) {
            fprintf(f, "  [%d] conductor, alpha %g\n", i, m->alpha);
            dump_spectrum(f, "eta", &m->eta);
            dump_spectrum(f, "k", &m->k);
        } else if (m->type == MAT_THIN_DIELECTRIC) {
            fprintf(f, "  [%d] thindielectric\n", i);
            dump_spectrum(f, "eta", &m->eta);
        } else if (m->type == MAT_COATED_DIFFUSE) {
            fprintf(f, "  [%d] coateddiffuse, alpha %g, eta %g, thickness %g, g %g, maxdepth %d, "
                    "nsamples %d\n", i, m->alpha, spec_eval(&m->eta, 550.0f), m->thickness,
                    m->hg_g, m->maxdepth, m->nsamples);
            dump_spectrum(f, "reflectance", &m->reflectance);
            dump_spectrum(f, "albedo", &m->albedo);
        } else if (m->type == MAT_INTERFACE) {
            fprintf(f, "  [%d] interface (no surface: the boundary of a medium)\n", i);
        } else if (m->type == MAT_COATED_CONDUCTOR) {
            fprintf(f, "  [%d] coatedconductor, interface alpha %g, eta %g, conductor alpha %g, "
                    "thickness %g, g %g, maxdepth %d, nsamples %d\n", i, m->alpha,
                    spec_eval(&m->eta, 550.0f), m->cond_alpha, m->thickness, m->hg_g, m->maxdepth,
                    m->nsamples);
            dump_spectrum(f, "conductor eta", &m->cond_eta);
            dump_spectrum(f, "conductor k", &m->k);
            dump_spectrum(f, "albedo", &m->albedo);
        } else if (m->type == MAT_DIFFUSE_TRANSMISSION) {
            fprintf(f, "  [%d] diffusetransmission, P(reflect lobe) %g\n", i, m->p_reflect);
            dump_spectrum(f, "reflectance", &m->reflectance);
            dump_spectrum(f, "transmittance", &m->transmittance);
        } else {
            fprintf(f, "  [%d] dielectric, alpha %g, %s", i, m->alpha,
                    m->dispersive ? "dispersive" : "constant eta");
            if (m->cauchy_a > 0) fprintf(f, ", Cauchy A %g B %g um^2", m->cauchy_a, m->cauchy_b);
            fprintf(f, "\n    eta at F 486.1: %.5f  d 587.6: %.5f  C 656.3: %.5f\n",
                    spec_eval(&m->eta, 486.1f), spec_eval(&m->eta, 587.6f),
                    spec_eval(&m->eta, 656.3f));
        }
    }
    fprintf(f, "shapes: %d (%d triangles, %d vertices, %d spheres, %d other quadrics)\n",
            s->n_shapes, s->n_tris, s->n_verts, s->n_spheres, s->n_quadrics);
    for (i = 0; i < s->n_shapes; i++) {
        const Shape *sh = &s->shapes[i];
        if (sh->type == SHAPE_SPHERE)
            fprintf(f, "  [%d] sphere c (%g, %g, %g) r %g", i, sh->center.x, sh->center.y,
                    sh->center.z, sh->radius);
        else if (sh->type == SHAPE_DISK)
            fprintf(f, "  [%d] disk (object space) height %g radius %g innerradius %g phimax %g",
                    i, sh->q.height, sh->q.radius, sh->q.inner, sh->q.phimax * 180.0 / SPECNEE_PI);
        else if (shape_is_quadric(sh->type))
            fprintf(f, "  [%d] %s (object space) radius %g z %g..%g phimax %g", i,
                    sh->type == SHAPE_CYLINDER ? "cylinder" : "sphere", sh->q.radius, sh->q.zmin,
                    sh->q.zmax, sh->q.phimax * 180.0 / SPECNEE_PI);
        else
            fprintf(f, "  [%d] mesh %d triangles%s", i, sh->tri_count,
                    sh->has_normals ? " with normals" : "");
        fprintf(f, ", area %g, material %d, emitter %d%s", sh->area, sh->material,
                sh->emitter, sh->flip ? ", flipped" : "");
        if (sh->medium_inside != sh->medium_outside)
            fprintf(f, ", media inside %d outside %d", sh->medium_inside, sh->medium_outside);
        fprintf(f, "  (%s:%d)\n", sh->file ? sh->file : "?", sh->line);
    }
    fprintf(f, "media: %d, the camera in %d%s\n", s->n_media, st->camera_medium,
            s->n_media > 0 && st->media_ignored ? " (ignored by this Integrator)" : "");
    for (i = 0; i < s->n_media; i++) {
        const Medium *m = &s->media[i];
        fprintf(f, "  [%d] \"%s\" homogeneous, g %g, sigma_t at 450/550/650 nm: %g %g %g, "
                "albedo at 550 nm %g%s\n", i, m->name, m->g, medium_sigma_t(m, 450.0f),
                medium_sigma_t(m, 550.0f), medium_sigma_t(m, 650.0f),
                medium_sigma_t(m, 550.0f) > 0.0f ? medium_sigma_s(m, 550.0f) / medium_sigma_t(m, 550.0f) : 0.0f,
                m->Le_scale > 0.0f ? ", emissive" : "");
    }
    fprintf(f, "emitters: %d\n", s->n_emitters);
    for (i = 0; i < s->n_emitters; i++) {
        const Emitter *e = &s->emitters[i];
        double Y = 0.0, bins = 0.0;
        int lam, b;
        Spectrum Le;
        Error err;
        if (!emitter_radiance(s, i, LAMBDA_LO, LAMBDA_HI, &Le, &err)) spec_const(&Le, 0.0f);
        for (lam = (int)LAMBDA_LO; lam <= (int)LAMBDA_HI; lam++) {  /* Y = sum ybar Le, 1 nm */
            float xyz[3];
            cie_xyz((float)lam, xyz);
            Y += (double)xyz[1] * spec_eval(&Le, (float)lam);
        }
        for (b = 0; b < SPD_BINS; b++) bins += spec_bin_average(&Le, b) * SPD_BIN_NM;
        if (e->inf)
            fprintf(f, "  [%d] infinite light, %s, scale %g, Y(Le) %.4g over %g-%g nm (mean), "
                    "power %.4g\n", i, e->inf->res ? "image map" : "constant", e->scale, Y,
                    LAMBDA_LO, LAMBDA_HI, SPECNEE_PI * e->area * bins);
        else if (e->delta.type == DELTA_DISTANT)
            fprintf(f, "  [%d] distant light towards (%g, %g, %g), scale %g, Y(L) %.4g over %g-%g nm, "
                    "power %.4g\n", i, e->delta.w.x, e->delta.w.y, e->delta.w.z, e->scale, Y,
                    LAMBDA_LO, LAMBDA_HI, SPECNEE_PI * e->area * bins);
        else if (e->delta.type != DELTA_NONE)
            fprintf(f, "  [%d] %s light at (%g, %g, %g), scale %g, Y(I) %.4g over %g-%g nm, "
                    "power %.4g\n", i, e->delta.type == DELTA_SPOT ? "spot" : "point",
                    e->delta.p.x, e->delta.p.y, e->delta.p.z, e->scale, Y,
                    LAMBDA_LO, LAMBDA_HI, SPECNEE_PI * e->area * bins);
        else
        fprintf(f, "  [%d] shape %d, scale %g, %s, Y(Le) %.4g over %g-%g nm, area %g, power %.4g\n",
                i, e->shape, e->scale, e->twosided ? "two-sided" : "one-sided", Y,
                LAMBDA_LO, LAMBDA_HI, e->area, SPECNEE_PI * e->area * (e->twosided ? 2.0 : 1.0) * bins);
        dump_spectrum(f, "L (as given)", &e->L);
    }
    fprintf(f, "bounds: (%g, %g, %g) - (%g, %g, %g)\n", s->bmin.x, s->bmin.y, s->bmin.z,
            s->bmax.x, s->bmax.y, s->bmax.z);
}
