/* scene.c - the scene builder: a strict subset of the pbrt-v4 scene format.

   Implements (specnee.h section 8): scene_load, scene_load_as, scene_load_string,
   scene_free.  The tokens, parameter lists and their typed getters and the
   file:line errors are parser.c's (parser.h); this file runs the directive loop
   over them, keeps pbrt's graphics state (transforms, attributes, named
   materials, textures and media) and assembles the Scene.
   Each concept reads its own parameters in its own room: the options block in
   options.c, materials in material.c, conductor.c and layered.c, textures in
   texture.c, lights in lights.c, delta.c and infinite.c, media in medium.c, the
   Shape directive (meshes, patches, PLY, loopsubdiv, quadrics) in geometry.c.
   scene_dump (--dump-scene) is dump.c's.

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

   ERRORS
     Every problem gives one line "file:line: problem" in the Error and a 0
     return; scene_load frees everything it allocated.  Nothing exits, and
     every loop advances through a finite buffer, so bad input cannot hang; the
     text budget (parser.h: READ_MAX_BYTES of text, each included file counted
     every time it runs) bounds the work of files that include each other
     repeatedly, MAX_INCLUDE_DEPTH a file that includes itself, MEM_BUDGET_MIB the
     instances' records.  Messages never carry raw
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
/* ===========================================================================
   2. Directives of the world block: materials, lights, shapes
   =========================================================================== */

/* ---------------------------------------------------------------------------
   Attribute "target" params (pbrt-v4 BasicSceneBuilder::Attribute)
   --------------------------------------------------------------------------- */
/* The targets, in the order of GState.attr. */
static const char *const attr_targets[5] = { "shape", "light", "material", "medium", "texture" };
enum { ATTR_SHAPE, ATTR_LIGHT, ATTR_MATERIAL, ATTR_MEDIUM, ATTR_TEXTURE };

/* Attribute: every parameter becomes a default of its target's directives in the
   current graphics state (so AttributeEnd drops it).  pbrt-v4's rule
   (ParameterDictionary with the attributes appended): a directive's own parameter
   wins, then the newest Attribute; a default the directive does not read is no
   error. */
static int attribute_directive(Parser *P, Lexer *L, const Token *t)
{
    Token ty;
    ParamList pl;
    int k, i, ok = 1;
    if (!expect_string(P, L, "Attribute", "target", &ty)) return 0;
    for (k = 0; k < 5; k++)
        if (!strcmp(ty.text, attr_targets[k])) break;
    if (k == 5)
        return fail(P, t->file, t->line, "Unknown attribute target \"%s\". Must be \"shape\", "
                    "\"light\", \"material\", \"medium\", or \"texture\".", ty.text);
    memset(&pl, 0, sizeof pl);
    if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
    for (i = 0; ok && i < pl.n; i++) {
        Param *c;
        int j;
        if (!grow((void **)&P->attrs, &P->cap_attrs, P->n_attrs + 1, sizeof(Param)) ||
            !grow((void **)&P->attr_prev, &P->cap_attr_prev, P->n_attrs + 1, sizeof(int))) {
            ok = oom(P, t->file, t->line);
            break;
        }
        c = &P->attrs[P->n_attrs];
        *c = pl.p[i];                               /* the values move to the copy */
        pl.p[i].num = NULL;
        pl.p[i].str = NULL;
        c->used = 0;
        c->attr = 1;
        for (j = 0; j < c->n_str; j++)              /* the lexer's buffer goes away */
            if (!(c->str[j] = intern(P, c->str[j]))) ok = oom(P, t->file, t->line);
        P->attr_prev[P->n_attrs] = P->gs.attr[k];
        P->gs.attr[k] = ++P->n_attrs;
    }
    params_free(&pl);
    return ok;
}

/* Put the defaults of `target` in front of a directive's own parameters, oldest
   first: the getters search from the end, so the directive's own parameters come
   first and then the newest default (pbrt-v4's order). */
static int attributes_apply(Parser *P, ParamList *pl, int target, const char *file, int line)
{
    int e, n = 0, i;
    for (e = P->gs.attr[target]; e > 0; e = P->attr_prev[e - 1]) n++;
    if (n == 0) return 1;
    if (!grow((void **)&pl->p, &pl->cap, pl->n + n, sizeof(Param))) return oom(P, file, line);
    memmove(pl->p + n, pl->p, (size_t)pl->n * sizeof(Param));
    memset(pl->p, 0, (size_t)n * sizeof(Param));
    pl->n += n;
    for (e = P->gs.attr[target], i = n - 1; e > 0; e = P->attr_prev[e - 1], i--) {
        const Param *a = &P->attrs[e - 1];
        Param *c = &pl->p[i];
        *c = *a;                                    /* owned copies: params_free frees them */
        c->num = NULL;
        c->str = NULL;
        if (a->n_num > 0) {
            c->num = (double *)malloc((size_t)a->n_num * sizeof(double));
            if (!c->num) { c->n_num = c->n_str = 0; return oom(P, file, line); }
            memcpy(c->num, a->num, (size_t)a->n_num * sizeof(double));
        }
        if (a->n_str > 0) {
            c->str = (const char **)malloc((size_t)a->n_str * sizeof(const char *));
            if (!c->str) { c->n_str = 0; return oom(P, file, line); }
            memcpy((void *)c->str, a->str, (size_t)a->n_str * sizeof(const char *));
        }
    }
    return 1;
}

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
    if (!parse_params(P, L, &pl) || !attributes_apply(P, &pl, ATTR_TEXTURE, t->file, t->line)) {
        params_free(&pl);
        return 0;
    }
    memset(&T, 0, sizeof T);
    T.file = t->file;
    T.line = t->line;
    T.amount_tex = T.scale_tex = -1;
    T.arg_tex[0] = T.arg_tex[1] = -1;
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
            NamedTexture *nt = &P->texnames[P->n_texnames];
            nt->name = keep_string(P, a[0].text);
            if (!nt->name) { ok = oom(P, t->file, t->line); goto done; }
            P->n_texnames++;
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
   (pbrt-v4's per-type Create): material.c, conductor.c, layered.c, hair.c,
   subsurface.c. */
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
    { "diffusetransmission", diffusetransmission_from_params },
    { "mix", mix_from_params }, { "hair", hair_from_params }, { "measured", measured_from_params },
    { "subsurface", subsurface_from_params }
};

/* Material m of `type` (a Material or MakeNamedMaterial directive `dir`). */
static int material_from_params(Parser *P, const char *type, ParamList *pl, const char *file,
                                int line, Material *m, const char *dir)
{
    char what[192];
    int k;
    memset(m, 0, sizeof *m);
    if (!P->eta_one) {
        Spectrum one;
        spec_const(&one, 1.0f);
        if (!material_set_eta(P, m, &one, file, line)) return 0;
        P->eta_one = m->eta;
    }
    m->eta = P->eta_one;
    snprintf(what, sizeof what, "%s \"%s\"", dir, type);
    for (k = 0; k < (int)(sizeof material_types / sizeof material_types[0]); k++)
        if (!strcmp(type, material_types[k].type)) {
            int ok = material_types[k].build(P, pl, file, line, dir, what, m);
            if (!ok) material_release(m);       /* what a failed build had allocated */
            return ok;
        }
    return fail(P, file, line, "%s \"%s\": unknown material type", dir, type);
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
    Scene *s = P->s;
    Emitter em;
    int ok;
    if (!strcmp(type, "point") || !strcmp(type, "spot") || !strcmp(type, "distant") ||
        !strcmp(type, "goniometric") || !strcmp(type, "projection"))
        ok = delta_light_from_params(P, type, pl, file, line, &em);
    else if (!strcmp(type, "infinite"))
        ok = infinite_light_from_params(P, pl, file, line, &em);
    else
        return fail(P, file, line, "LightSource \"%s\": unknown light type", type);
    if (!ok) return 0;
    if (!grow((void **)&s->emitters, &P->cap_emit, s->n_emitters + 1, sizeof(Emitter))) {
        inf_free(em.inf);
        delta_free(&em.delta);
        return oom(P, file, line);
    }
    s->emitters[s->n_emitters++] = em;
    return 1;
}

/* ===========================================================================
   3. The directive loop
   =========================================================================== */
static int parse_text(Parser *P, const char *file, char *buf, size_t len);

/* The text of an included file, to be lexed (and unescaped in place) by the caller,
   who frees it; *name: the interned path.  A small file is read from the disk at
   its first Include only and kept (Parser.inc, at most INCLUDE_CACHE_FILES files
   of INCLUDE_CACHE_BYTES or less): files that place instances include the same few
   files over and over (the Menger sponge: six files, 168,420 times). */
#define INCLUDE_CACHE_FILES 64
#define INCLUDE_CACHE_BYTES ((size_t)1 << 16)
static char *include_text(Parser *P, const char *path, const char **name, size_t *len,
                          ReadStatus *rs)
{
    char *buf;
    int i;
    for (i = 0; i < P->n_inc; i++)
        if (!strcmp(P->inc[i].path, path)) {
            const IncludeCache *c = &P->inc[i];
            *rs = READ_NOMEM;
            if (!(buf = (char *)malloc(c->len + 1))) return NULL;
            memcpy(buf, c->text, c->len + 1);
            *name = c->path;
            *len = c->len;
            *rs = READ_OK;
            return buf;
        }
    buf = read_whole_file_gz(path, READ_TEXT, NULL, len, rs);
    if (!buf) return NULL;
    if (!(*name = intern(P, path))) { free(buf); *rs = READ_NOMEM; return NULL; }
    if (*len <= INCLUDE_CACHE_BYTES && P->n_inc < INCLUDE_CACHE_FILES
        && grow((void **)&P->inc, &P->cap_inc, P->n_inc + 1, sizeof(IncludeCache))) {
        IncludeCache *c = &P->inc[P->n_inc];
        if ((c->text = (char *)malloc(*len + 1)) != NULL) {
            memcpy(c->text, buf, *len + 1);
            c->path = *name;
            c->len = *len;
            P->n_inc++;
        }
    }
    return buf;
}

/* Include: the file's tokens come next in the same stream (pbrt-v4 pushes it on
   its file stack).  Import: parsed on its own into a copy of the graphics state.
   Both spend the text budget (parser.h): the file's length each time it runs, at
   least INCLUDE_MIN_BYTES, READ_MAX_BYTES in all, so that files which include the
   next one many times ("billion laughs") cost no more than one 1 GiB file; and
   MAX_INCLUDE_DEPTH stops a file that includes itself. */
static int include_directive(Parser *P, Lexer *L, const Token *dir, int is_import)
{
    Token t;
    char path[PATH_CAP];
    const char *name = NULL;
    char *buf;
    size_t len, cost;
    ReadStatus rs;
    int ok, depth = P->depth;
    GState saved = P->gs;
    const char *d = is_import ? "Import" : "Include";
    if (!expect_string(P, L, d, "file name", &t)) return 0;
    if (is_import && !P->in_world)
        return fail(P, dir->file, dir->line, "Import is only allowed after WorldBegin");
    if (P->nest >= MAX_INCLUDE_DEPTH)
        return fail(P, dir->file, dir->line, "%s \"%s\": nested deeper than %d (MAX_INCLUDE_DEPTH: "
                    "an include cycle?)", d, t.text, MAX_INCLUDE_DEPTH);
    resolve_path(P, t.file, t.text, path, sizeof path);
    buf = include_text(P, path, &name, &len, &rs);
    if (!buf) {
        if (rs == READ_OPEN)
            return fail(P, dir->file, dir->line, "%s \"%s\": cannot read \"%s\"", d, t.text, path);
        return fail(P, dir->file, dir->line, "%s \"%s\": \"%s\": %s", d, t.text, path,
                    read_status_text(rs));
    }
    cost = len > INCLUDE_MIN_BYTES ? len : INCLUDE_MIN_BYTES;
    if (cost > READ_MAX_BYTES - P->text_bytes) {
        free(buf);
        return fail(P, dir->file, dir->line, "%s \"%s\": the scene text, each included file "
                    "counted every time it is included (at least %d bytes), exceeds %lu MiB "
                    "(READ_MAX_BYTES: files that include each other many times?)", d, t.text,
                    INCLUDE_MIN_BYTES, (unsigned long)(READ_MAX_BYTES >> 20));
    }
    P->text_bytes += cost;
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
    parser_sync_colorspace(P);           /* the importer's space again */
    return 1;
}

/* The CTMs that ActiveTransform names (pbrt-v4's ForActiveTransforms): x replaces
   them (Identity, Transform) or is appended, CTM <- CTM * x. */
static void ctm_apply(Parser *P, const Xform *x, int replace)
{
    if (P->gs.active & 1) P->gs.ctm = replace ? *x : xf_mul(&P->gs.ctm, x);
    if (P->gs.active & 2) P->gs.ctm_end = replace ? *x : xf_mul(&P->gs.ctm_end, x);
}

/* ActiveTransform StartTime | EndTime | All, and TransformTimes start end
   (motion.c): which CTMs the transform directives change, and when they hold. */
static int motion_directive(Parser *P, Lexer *L, const Token *t)
{
    Token w;
    if (!strcmp(t->text, "TransformTimes")) {
        double v[2];
        if (P->in_world)
            return fail(P, t->file, t->line, "Options cannot be set inside world block; "
                        "\"TransformTimes\" not allowed after WorldBegin");
        if (!expect_number(P, L, t->text, 2, v)) return 0;
        if (!(fabs(v[0]) <= FLT_MAX && fabs(v[1]) <= FLT_MAX && v[0] <= v[1]))
            return fail(P, t->file, t->line, "TransformTimes %g %g: the times must be finite, "
                        "start <= end", v[0], v[1]);
        P->t0 = v[0];
        P->t1 = v[1];
        return 1;
    }
    if (!lex_next(P, L, &w)) return 0;
    if (w.kind == TK_WORD && !strcmp(w.text, "All")) P->gs.active = 3;
    else if (w.kind == TK_WORD && !strcmp(w.text, "StartTime")) P->gs.active = 1;
    else if (w.kind == TK_WORD && !strcmp(w.text, "EndTime")) P->gs.active = 2;
    else return fail(P, t->file, t->line, "ActiveTransform: expected All, StartTime or EndTime");
    return 1;
}

/* A light, medium or texture made under two different CTMs takes the start one,
   as in pbrt-v4 (which warns so): a note says it. */
static void note_start_transform(const Parser *P, const Token *t)
{
    if (xf_differ(&P->gs.ctm, &P->gs.ctm_end))
        fprintf(stderr, "%s:%d: note: %s under a moving transform (ActiveTransform) takes its "
                "start transform, as in pbrt-v4\n", t->file, t->line, t->text);
}

static int transform_directive(Parser *P, Lexer *L, const Token *t, int *handled)
{
    const char *d = t->text;
    double v[16];
    Xform x;
    *handled = 1;
    if (!strcmp(d, "ActiveTransform") || !strcmp(d, "TransformTimes")) return motion_directive(P, L, t);
    if (!strcmp(d, "Identity")) { x = xf_identity(); ctm_apply(P, &x, 1); return 1; }
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
        if (d[0] == 'T') { ctm_apply(P, &x, 1); return 1; }   /* Transform replaces the CTM */
    } else if (!strcmp(d, "CoordinateSystem") || !strcmp(d, "CoordSysTransform")) {
        Token n;
        int i;
        if (!expect_string(P, L, d, "name", &n)) return 0;
        for (i = 0; i < P->n_coords; i++)
            if (!strcmp(P->coords[i].name, n.text)) break;
        if (d[5] == 'i') {                                 /* CoordinateSystem: record */
            if (i == P->n_coords) {
                if (!grow((void **)&P->coords, &P->cap_coords, P->n_coords + 1, sizeof(NamedCoordSys)) ||
                    !(P->coords[i].name = keep_string(P, n.text)))
                    return oom(P, t->file, t->line);
                P->n_coords++;
            }
            P->coords[i].xf = P->gs.ctm;
            P->coords[i].xf_end = P->gs.ctm_end;
            return 1;
        }
        if (i == P->n_coords)
            return fail(P, t->file, t->line, "CoordSysTransform: unknown coordinate system "
                        "\"%s\"", n.text);
        P->gs.ctm = P->coords[i].xf;                       /* pbrt-v4: both CTMs */
        P->gs.ctm_end = P->coords[i].xf_end;
        return 1;
    } else {
        *handled = 0;
        return 1;
    }
    ctm_apply(P, &x, 0);                                  /* CTM <- CTM * T */
    return 1;
}

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
    if (!grow((void **)&s->media, &P->cap_media, s->n_media + 1, sizeof(Medium))) {
        oom(P, file, line);
        return -2;
    }
    if (!grow((void **)&P->mrefs, &P->cap_mrefs, s->n_media + 1, sizeof(MediumRef))) {
        oom(P, file, line);
        return -2;
    }
    memset(&s->media[s->n_media], 0, sizeof(Medium));
    if (!(s->media[s->n_media].name = keep_string(P, name))) {
        oom(P, file, line);
        return -2;
    }
    P->mrefs[s->n_media].defined = P->mrefs[s->n_media].used = 0;
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
    if (!parse_params(P, L, &pl) || !attributes_apply(P, &pl, ATTR_MEDIUM, t->file, t->line)) {
        params_free(&pl);
        return 0;
    }
    snprintf(what, sizeof what, "MakeNamedMedium \"%.100s\"", nm.text);
    if (!medium_from_params(P, &pl, what, t->file, t->line, &m)) goto done;
    idx = medium_ref(P, nm.text, t->file, t->line);
    if (idx == -2) { medium_free(&m); goto done; }
    if (idx == -1) { fail(P, t->file, t->line, "MakeNamedMedium: the name \"\" is no medium"); medium_free(&m); goto done; }
    if (P->mrefs[idx].defined) {
        fail(P, t->file, t->line, "MakeNamedMedium: medium \"%s\" redefined (first at %s:%d)",
             nm.text, P->s->media[idx].file, P->s->media[idx].line);
        medium_free(&m);
        goto done;
    }
    m.name = P->s->media[idx].name;            /* kept by medium_ref */
    P->s->media[idx] = m;
    P->mrefs[idx].defined = 1;
    P->mrefs[idx].before_camera = P->camera_file == NULL;
    ok = 1;
done:
    params_free(&pl);
    return ok;
}

/* A medium made before the Camera directive.  pbrt-v4 places every object by
   render_from_world * CTM, and its render_from_world is set only at Camera (the
   identity before it).  Its default render space ("cameraworld") is the world
   moved so that the camera sits at the origin: world = T(p_camera) render.  So a
   medium made before Camera lies at world_from_medium = T(p_camera) * CTM, offset
   by the camera's position; specnee does the same, which changes only the media
   that have a frame (the grids; a homogeneous medium is the same everywhere). */
static void media_before_camera(Parser *P)
{
    const Xform *cfw = &P->s->settings.camera_from_world;
    Xform back;
    int i;
    /* the camera's position in the world: world_from_camera applied to the origin */
    back = xf_translate(-cfw->inv[0][3], -cfw->inv[1][3], -cfw->inv[2][3]);
    for (i = 0; i < P->s->n_media; i++)
        if (P->mrefs[i].before_camera)
            P->s->media[i].medium_from_world = xf_mul(&P->s->media[i].medium_from_world, &back);
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

/* ===========================================================================
   Object instancing (instance.c): ObjectBegin, ObjectEnd, ObjectInstance
   =========================================================================== */
/* ObjectBegin "name": a new object definition, opened like AttributeBegin (pbrt-v4
   pushes the graphics state); the shapes up to ObjectEnd belong to it. */
static int object_begin(Parser *P, const Token *t, const char *name)
{
    Scene *s = P->s;
    Object *o;
    int i;
    if (P->cur_object > 0)
        return fail(P, t->file, t->line, "ObjectBegin \"%s\" called inside of instance "
                    "definition \"%s\"", name, s->objects[P->cur_object - 1].name);
    for (i = 0; i < s->n_objects; i++)
        if (!s->objects[i].unnamed && !strcmp(s->objects[i].name, name))
            return fail(P, t->file, t->line, "ObjectBegin \"%s\": trying to redefine an object "
                        "instance (first at %s:%d)", name, s->objects[i].file, s->objects[i].line);
    if (!grow((void **)&P->stack, &P->stack_cap, P->depth + 1, sizeof(GState)) ||
        !grow((void **)&s->objects, &P->cap_objects, s->n_objects + 1, sizeof(Object)))
        return oom(P, t->file, t->line);
    P->gs.file = t->file;
    P->gs.line = t->line;
    P->gs.by_object = 1;
    P->stack[P->depth++] = P->gs;
    o = &s->objects[s->n_objects];
    memset(o, 0, sizeof *o);
    if (!(o->name = keep_string(P, name))) return oom(P, t->file, t->line);
    o->file = t->file;
    o->line = t->line;
    P->cur_object = ++s->n_objects;
    return 1;
}

static int object_directive(Parser *P, Lexer *L, const Token *t)
{
    const char *d = t->text;
    Token n;
    if (!P->in_world)
        return fail(P, t->file, t->line, "Scene description must be inside world block; "
                    "\"%s\" not allowed before WorldBegin", d);
    if (!strcmp(d, "ObjectEnd")) {
        if (P->cur_object == 0)
            return fail(P, t->file, t->line, "ObjectEnd called outside of instance definition");
        if (!P->stack[P->depth - 1].by_object)
            return fail(P, t->file, t->line, "Mismatched nesting: open AttributeBegin from "
                        "%s:%d at ObjectEnd", P->stack[P->depth - 1].file,
                        P->stack[P->depth - 1].line);
        P->gs = P->stack[--P->depth];
        parser_sync_colorspace(P);       /* ObjectEnd */
        P->cur_object = 0;
        return 1;
    }
    if (!expect_string(P, L, d, "object name", &n)) return 0;
    if (!strcmp(d, "ObjectBegin")) return object_begin(P, t, n.text);
    {   /* ObjectInstance "name" */
        const double (*m)[4] = (const double (*)[4])P->gs.ctm.m;
        if (P->cur_object > 0)
            return fail(P, t->file, t->line, "ObjectInstance \"%s\" can't be called inside "
                        "instance definition \"%s\"", n.text, P->s->objects[P->cur_object - 1].name);
        if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0)
            return fail(P, t->file, t->line, "ObjectInstance \"%s\": projective transform not "
                        "supported", n.text);
        return add_instance(P, "ObjectInstance", n.text, -1, t->file, t->line);
    }
}

/* An Option as read: its name, whether it came typed ("integer seed") and as
   which type, and its value when that is one number. */
typedef struct {
    char name[64];
    int typed;
    ParamType type;
    int is_num;
    double num;
    int is_bool, b;      /* a bool: typed "bool", or the word true or false */
} OptionValue;

/* Option "displacementedgescale" s: pbrt-v4 multiplies the "edgelength" of every
   displaced plymesh by s (Options->displacementEdgeScale, used when its scene
   creates the meshes, after the whole file is read).  specnee displaces a mesh
   as it reads it (geometry.c), so a scale that arrives after a displaced mesh
   and differs from the one it was refined with is refused by name. */
static int option_edge_scale(Parser *P, const Token *t, const OptionValue *o)
{
    float s = o->is_num ? (float)o->num : 0.0f;
    if ((o->typed && o->type != PT_FLOAT) || !o->is_num || !(s > 0.0f && s <= FLT_MAX))
        return fail(P, t->file, t->line, "Option \"displacementedgescale\": expected one number > 0");
    if (P->displaced_file && s != (P->edge_scale_set ? P->edge_scale : 1.0f))
        return fail(P, t->file, t->line, "Option \"displacementedgescale\" %g after the displaced "
                    "plymesh of %s:%d: pbrt-v4 scales every displaced mesh by it, and specnee "
                    "refines each as it reads it; put the Option before the first Shape",
                    (double)s, P->displaced_file, P->displaced_line);
    P->edge_scale = s;
    P->edge_scale_set = 1;
    return 1;
}

/* What an Option does (option_directive read it). */
static int option_apply(Parser *P, const Token *t, const OptionValue *o)
{
    static const char *const ignored[] = {          /* the image does not change */
        "msereferenceimage", "msereferenceout", "rendercoordsys", "pixelstats", "wavefront", NULL
    };
    static const char *const refused[] = {          /* the image (or its noise) changes */
        "forcediffuse", NULL
    };
    int i;
    if (!strcmp(o->name, "seed")) {
        if ((o->typed && o->type != PT_INTEGER) || !o->is_num || !(fabs(o->num) <= 2147483647.0) ||
            o->num != floor(o->num))
            return fail(P, t->file, t->line, "Option \"seed\": expected one \"integer seed\" value");
        P->option_seed = (int)o->num;
        P->option_seed_set = 1;
        return 1;
    }
    if (!strcmp(o->name, "displacementedgescale")) return option_edge_scale(P, t, o);
    /* render.c: rays through pixel centres; pbrt-v4's four fixed wavelengths.
       disabletexturefiltering: pbrt-v4 then zeroes every ray footprint, so each
       texture is read at its point (imagemap at full resolution, checkerboard
       unfiltered, noise with every octave, bump's du = 0.0005), as specnee
       always reads them: nothing to set */
    if (!strcmp(o->name, "disablepixeljitter") || !strcmp(o->name, "disablewavelengthjitter") ||
        !strcmp(o->name, "disabletexturefiltering")) {
        if (!o->is_bool)
            return fail(P, t->file, t->line, "Option \"%s\": expected true or false", o->name);
        if (!strcmp(o->name, "disablepixeljitter")) P->s->settings.no_pixel_jitter = o->b;
        else if (!strcmp(o->name, "disablewavelengthjitter")) P->s->settings.no_wavelength_jitter = o->b;
        return 1;
    }
    for (i = 0; ignored[i]; i++)
        if (!strcmp(o->name, ignored[i])) {
            fprintf(stderr, "%s:%d: note: Option \"%s\" is read and ignored: it steers pbrt-v4's "
                    "statistics or its own machinery, not the image\n", t->file, t->line, o->name);
            return 1;
        }
    for (i = 0; refused[i]; i++)
        if (!strcmp(o->name, refused[i])) {
            if (o->is_bool && !o->b) return 1;      /* false: pbrt-v4's default, no change */
            return fail(P, t->file, t->line, "Option \"%s\" is valid pbrt-v4 but not in the specnee "
                        "subset", refused[i]);
        }
    return fail(P, t->file, t->line, "Option \"%s\": unknown option (pbrt-v4 has none of that name)",
                o->name);
}

/* Option "name" value: pbrt-v4's global options (its Options struct, set from
   the file as from its command line).  pbrt-v4 (commit 5f7a6068) reads a quoted
   name and one value token (Option "seed" 7, Option "disablepixeljitter" true)
   and calls "integer seed" an unknown option; specnee reads that spelling and
   the typed one ("type name" value), which some files write.  Those that only
   steer pbrt-v4's statistics, its internal frame or its other integrator leave
   the image as it is: read and ignored with a note.  "seed" is the seed of the
   samplers that give no "integer seed" of their own (pbrt-v4's Options->seed,
   which the file sets after the command line): finish() makes it the scene's
   Sampler seed, so it changes only the noise, and specnee's --seed overrides it
   as it overrides the Sampler's (docs/conventions.md).  "displacementedgescale"
   scales displaced meshes' edgelength (option_edge_scale); "disablepixeljitter"
   sends every camera ray through its pixel's centre with filter weight 1 (pbrt-v4's
   GetCameraSample, render.c); "disablewavelengthjitter" renders every sample at
   pbrt-v4's four wavelengths of u = 1/2 (render.c); "disabletexturefiltering"
   is specnee's way of reading textures (at their point) and changes nothing.
   "forcediffuse" changes the image and is refused by name ("false", its
   default, changes nothing and is read);
   an option pbrt-v4 does not know is an error, as in pbrt-v4. */
static int option_directive(Parser *P, Lexer *L, const Token *t)
{
    OptionValue o;
    Token n;
    memset(&o, 0, sizeof o);
    if (!lex_next(P, L, &n)) return 0;
    if (n.kind == TK_STRING && !strchr(n.text, ' ')) {     /* pbrt-v4's spelling */
        Token v;
        char *end;
        snprintf(o.name, sizeof o.name, "%s", n.text);
        if (!lex_next(P, L, &v)) return 0;
        if (v.kind != TK_WORD && v.kind != TK_STRING)
            return fail(P, t->file, t->line, "Option \"%s\": expected a value, found %s", o.name,
                        tok_desc(&v));
        if (v.kind == TK_WORD) {
            o.num = strtod(v.text, &end);
            o.is_num = end != v.text && *end == '\0';
            o.is_bool = !strcmp(v.text, "true") || !strcmp(v.text, "false");
            o.b = !strcmp(v.text, "true");
        }
    } else {                                               /* "type name" value */
        ParamList pl;
        const Param *p;
        lex_unget(L, &n);
        memset(&pl, 0, sizeof pl);
        if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
        if (pl.n != 1) {
            int k = pl.n;
            params_free(&pl);
            return fail(P, t->file, t->line, "Option: expected one \"type name\" value pair, found %d", k);
        }
        p = &pl.p[0];
        snprintf(o.name, sizeof o.name, "%s", p->name);
        o.typed = 1;
        o.type = p->type;
        o.is_num = p->n_num == 1 && (p->type == PT_FLOAT || p->type == PT_INTEGER);
        o.num = o.is_num ? p->num[0] : 0.0;
        o.is_bool = p->type == PT_BOOL && p->n_num == 1;
        o.b = o.is_bool && p->num[0] != 0.0;
        params_free(&pl);
    }
    return option_apply(P, t, &o);
}

/* Directives with a quoted type name and a parameter list. */
static int typed_directive(Parser *P, Lexer *L, const Token *t)
{
    const char *d = t->text;
    Token ty;
    ParamList pl;
    char type[NAME_CAP];
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
    if (strlen(ty.text) >= sizeof type)
        return fail(P, t->file, t->line, "%s: a name of %d characters (at most %d)", d,
                    (int)strlen(ty.text), NAME_CAP - 1);
    snprintf(type, sizeof type, "%s", ty.text);
    memset(&pl, 0, sizeof pl);
    if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
    {
        const int target = !strcmp(d, "Shape") ? ATTR_SHAPE
                         : !strcmp(d, "LightSource") || !strcmp(d, "AreaLightSource") ? ATTR_LIGHT
                         : !strcmp(d, "Material") || !strcmp(d, "MakeNamedMaterial") ? ATTR_MATERIAL
                         : -1;
        if (target >= 0 && !attributes_apply(P, &pl, target, t->file, t->line)) {
            params_free(&pl);
            return 0;
        }
    }
    if (!strcmp(d, "Camera")) ok = camera_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Film")) ok = film_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Sampler")) ok = sampler_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Integrator")) ok = integrator_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "PixelFilter")) ok = filter_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Accelerator")) ok = accelerator_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "Shape")) ok = shape_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "AreaLightSource")) ok = area_light_directive(P, type, &pl, t->file, t->line);
    else if (!strcmp(d, "LightSource")) {
        note_start_transform(P, t);
        ok = light_source_directive(P, type, &pl, t->file, t->line);
    }
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
                P->named[P->n_named].name = keep_string(P, type);
                if (!P->named[P->n_named].name) ok = oom(P, t->file, t->line);
            }
            if (ok) {
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
        P->gs.ctm = P->gs.ctm_end = xf_identity();
        P->gs.active = 3;                                  /* pbrt-v4: All again */
        for (i = 0; i < P->n_coords; i++)
            if (!strcmp(P->coords[i].name, "world")) break;
        if (i == P->n_coords) {
            if (!grow((void **)&P->coords, &P->cap_coords, P->n_coords + 1, sizeof(NamedCoordSys)))
                return oom(P, t->file, t->line);
            P->coords[i].name = "world";
            P->n_coords++;
        }
        P->coords[i].xf = P->coords[i].xf_end = xf_identity();
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
        P->gs.by_object = 0;
        P->stack[P->depth++] = P->gs;
        return 1;
    }
    if (!strcmp(d, "AttributeEnd") || !strcmp(d, "TransformEnd")) {
        if (!P->in_world)
            return fail(P, t->file, t->line, "Scene description must be inside world block; "
                        "\"%s\" not allowed before WorldBegin", d);
        if (P->depth == 0)
            return fail(P, t->file, t->line, "unmatched %s (no AttributeBegin open)", d);
        if (P->stack[P->depth - 1].by_object)
            return fail(P, t->file, t->line, "Mismatched nesting: open ObjectBegin from %s:%d "
                        "at %s", P->stack[P->depth - 1].file, P->stack[P->depth - 1].line, d);
        P->gs = P->stack[--P->depth];
        parser_sync_colorspace(P);       /* AttributeEnd */
        return 1;
    }
    if (!strcmp(d, "ObjectBegin") || !strcmp(d, "ObjectEnd") || !strcmp(d, "ObjectInstance"))
        return object_directive(P, L, t);
    if (!strcmp(d, "Attribute")) return attribute_directive(P, L, t);
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
        if (!grow((void **)&P->named, &P->cap_named, P->n_named + 1, sizeof(NamedMaterial)) ||
            !(P->named[i].name = keep_string(P, n.text)))
            return oom(P, t->file, t->line);
        P->named[i].material = -1;
        P->named[i].file = t->file;
        P->named[i].line = t->line;
        P->n_named++;
        P->gs.material = -2 - i;
        return 1;
    }
    if (!strcmp(d, "Texture") || !strcmp(d, "MakeNamedMedium")) note_start_transform(P, t);
    if (!strcmp(d, "Texture")) return texture_directive(P, L, t);
    if (!strcmp(d, "MakeNamedMedium")) return make_named_medium(P, L, t);
    if (!strcmp(d, "MediumInterface")) return medium_interface(P, L, t);
    if (!strcmp(d, "Include")) return include_directive(P, L, t, 0);
    if (!strcmp(d, "Import")) return include_directive(P, L, t, 1);
    if (!strcmp(d, "ColorSpace")) {
        Token n;
        int cs;
        if (!expect_string(P, L, d, "colour space name", &n)) return 0;
        cs = colorspace_index(n.text);              /* rgbfit.c: pbrt-v4's four */
        if (cs < 0)
            return fail(P, t->file, t->line, "ColorSpace \"%s\": unknown colour space (pbrt-v4 "
                        "knows \"srgb\", \"dci-p3\", \"rec2020\" and \"aces2065-1\")", n.text);
        return parser_set_colorspace(P, cs) || oom(P, t->file, t->line);
    }
    if (!strcmp(d, "Option")) return option_directive(P, L, t);
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
   4. Entry points
   =========================================================================== */
static void settings_default(SceneSettings *st)
{
    memset(st, 0, sizeof *st);
    st->camera_from_world = xf_identity();   /* pbrt-v4: no Camera -> identity */
    st->camera_from_world_end = st->camera_from_world;
    st->camera_t1 = 1.0;                     /* TransformTimes 0 1 */
    st->shutter_close = 1.0f;                /* shutteropen 0, shutterclose 1 */
    st->fov_deg = 90.0f;
    st->film_diagonal = 35.0f;               /* pbrt-v4 Film "diagonal", mm */
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
    free(P->uses);
    {
        int i;
        for (i = 0; i < P->n_inc; i++) free(P->inc[i].text);
        free(P->inc);
        for (i = 0; i < P->n_attrs; i++) { free(P->attrs[i].num); free((void *)P->attrs[i].str); }
    }
    free(P->attrs);
    free(P->attr_prev);
    {
        int i;
        for (i = 0; i < COLORSPACE_N; i++) rgb_table_free(P->rgb_cs[i]);
    }
}

/* Everything after the last token: checks, bounds, emitters, BVH. */
/* A Material "mix" that named a material made further down the file (mix_from_params,
   material.c): the name resolved now, as pbrt-v4 does after reading the file. */
static int resolve_mix_names(Parser *P)
{
    Scene *s = P->s;
    int i, k;
    for (i = 0; i < s->n_materials; i++)
        for (k = 0; k < 2 && s->materials[i].type == MAT_MIX; k++)
            if (s->materials[i].mix[k] <= -2) {
                const NamedMaterial *nm = &P->named[-2 - s->materials[i].mix[k]];
                if (nm->material < 0)
                    return fail(P, nm->file, nm->line, "Material \"mix\": named material "
                                "\"%s\" not found", nm->name);
                if (s->materials[nm->material].type == MAT_INTERFACE)
                    return fail(P, nm->file, nm->line, "Material \"mix\": \"%s\": an "
                                "\"interface\" material cannot be used as an element of the "
                                "\"mix\" material", nm->name);
                s->materials[i].mix[k] = nm->material;
            }
    return 1;
}

/* The world bounds of all geometry (vertices, spheres, quadrics, patches, curve
   pieces, instances), component by component (plain floats: tcc 0.9.27
   miscompiles a struct-returning call whose result is assigned to one of its own
   arguments inside such a loop); empty: the origin. */
static void world_bounds(Scene *s)
{
    int i;
    float lo[3] = { FLT_MAX, FLT_MAX, FLT_MAX }, hi[3] = { -FLT_MAX, -FLT_MAX, -FLT_MAX };
    for (i = 0; i < s->n_tris; i++) {
        int k, a;
        if (s->shapes[s->tris[i].shape].in_object) continue;   /* in object space */
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
        if (sh->in_object) continue;
        for (a = 0; a < 3; a++) {
            float c = v3_get(sh->center, a);
            if (c - sh->radius < lo[a]) lo[a] = c - sh->radius;
            if (c + sh->radius > hi[a]) hi[a] = c + sh->radius;
        }
    }
    for (i = 0; i < s->n_quadrics; i++) {
        float qlo[3], qhi[3];
        int a;
        if (s->shapes[s->quadric_shape[i]].in_object) continue;
        quadric_bounds(&s->shapes[s->quadric_shape[i]], qlo, qhi);
        for (a = 0; a < 3; a++) {
            if (qlo[a] < lo[a]) lo[a] = qlo[a];
            if (qhi[a] > hi[a]) hi[a] = qhi[a];
        }
    }
    for (i = 0; i < s->n_patches; i++) {
        int k, a;
        if (s->shapes[s->patches[i].shape].in_object) continue;
        for (k = 0; k < 4; k++) {
            Vec3 p = s->P[s->patches[i].v[k]];
            for (a = 0; a < 3; a++) {
                float x = v3_get(p, a);
                if (x < lo[a]) lo[a] = x;
                if (x > hi[a]) hi[a] = x;
            }
        }
    }
    for (i = 0; i < s->n_curve_pieces; i++) {
        float clo[3], chi[3];
        int a;
        if (s->shapes[s->curves[s->curve_pieces[i].curve].shape].in_object) continue;
        curve_piece_bounds(s, &s->curve_pieces[i], clo, chi);
        for (a = 0; a < 3; a++) {
            if (clo[a] < lo[a]) lo[a] = clo[a];
            if (chi[a] > hi[a]) hi[a] = chi[a];
        }
    }
    for (i = 0; i < s->n_instances; i++) {
        int a;
        for (a = 0; a < 3; a++) {
            if (s->instances[i].lo[a] < lo[a]) lo[a] = s->instances[i].lo[a];
            if (s->instances[i].hi[a] > hi[a]) hi[a] = s->instances[i].hi[a];
        }
    }
    s->bmin = v3(lo[0], lo[1], lo[2]);
    s->bmax = v3(hi[0], hi[1], hi[2]);
    if (s->bmin.x > s->bmax.x) s->bmin = s->bmax = v3(0, 0, 0);   /* nothing in the world */
}

static int finish(Parser *P, const char *file)
{
    Scene *s = P->s;
    float sw[4];
    int i;
    if (P->depth > 0) {
        const GState *g = &P->stack[P->depth - 1];
        if (g->by_object)
            return fail(P, g->file, g->line, "ObjectBegin without a matching ObjectEnd");
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
    if (!resolve_mix_names(P)) return 0;
    for (i = 0; i < s->n_shapes; i++) {
        Shape *sh = &s->shapes[i];
        sh->reads_uv = sh->alpha_tex > 0 || (sh->material >= 0 && sh->material < s->n_materials &&
                                             mat_reads_uv(&s->materials[sh->material])) ||
                       (sh->emitter >= 0 && s->emitters[sh->emitter].image);   /* lights.c */
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
    /* a medium that neither the camera nor a shape's transition (medium_after)
       leads into changes nothing: a note at its MakeNamedMedium */
    if (s->settings.camera_medium >= 0) P->mrefs[s->settings.camera_medium].used = 1;
    for (i = 0; i < s->n_shapes; i++) {
        const Shape *sh = &s->shapes[i];
        if (sh->medium_inside == sh->medium_outside) continue;
        if (sh->medium_inside >= 0) P->mrefs[sh->medium_inside].used = 1;
        if (sh->medium_outside >= 0) P->mrefs[sh->medium_outside].used = 1;
    }
    for (i = 0; i < s->n_media; i++)
        if (!P->mrefs[i].used)
            fprintf(stderr, "%s:%d: note: medium \"%s\" is defined but never used\n",
                    s->media[i].file, s->media[i].line, s->media[i].name);
    if (s->n_media > 0 && s->settings.media_ignored)
        fprintf(stderr, "%s:%d: note: Integrator \"%s\" ignores the participating media, as "
                "pbrt-v4's does (\"volpath\" renders them)\n", P->integ_file, P->integ_line,
                P->integ_type);
    for (i = 0; s->settings.sss_ignored && i < s->n_materials; i++)
        if (s->materials[i].type == MAT_SUBSURFACE) {
            fprintf(stderr, "%s:%d: note: Integrator \"%s\" renders a \"subsurface\" material as "
                    "its dielectric boundary alone, as pbrt-v4's does (\"volpath\" renders the "
                    "subsurface scattering)\n", P->integ_file, P->integ_line, P->integ_type);
            break;
        }
    media_before_camera(P);
    camera_screen_window(&s->settings, sw);
    if (P->camera_file && !camera_transform_ok(&s->settings.camera_from_world,
                                               s->settings.fov_deg, sw))
        return fail(P, P->camera_file, P->camera_line, "Camera: degenerate camera transform "
                    "for the %d x %d film: the viewing directions are not finite, non-zero "
                    "float vectors", s->settings.xres, s->settings.yres);
    if (s->settings.lens.n) {   /* the realistic camera, focused for this film (lens.c) */
        Error e;
        if (!lens_focus(&s->settings.lens, s->settings.focus_distance,
                        1e-3 * s->settings.film_diagonal, LENS_PUPIL_SAMPLES, &e))
            return fail(P, P->camera_file, P->camera_line, "%s", e.msg);
    }
    /* pbrt-v4: a Sampler's "integer seed", else Option "seed" (option_directive) */
    if (P->option_seed_set && !s->settings.seed_set) {
        s->settings.seed = P->option_seed;
        s->settings.seed_set = 1;
    }
    /* pbrt-v4 PixelSensor::Create: imaging ratio = exposure time * ISO / 100 */
    s->settings.imaging_ratio = P->exposure_time * P->iso / 100.0f;
    for (i = 0; i < s->n_insets; i++)
        if (s->inset[i][2] > s->settings.xres || s->inset[i][3] > s->settings.yres)
            return fail(P, P->inset_file[i], P->inset_line[i], "inset %s (%d %d %d %d) lies outside the %d x %d film",
                        s->inset_name[i], s->inset[i][0], s->inset[i][1], s->inset[i][2],
                        s->inset[i][3], s->settings.xres, s->settings.yres);
    if (!instances_resolve(P) || !instances_prepare(s, P->err)) return 0;
    world_bounds(s);
    if (!P->any_normals) { free(s->N); s->N = NULL; }
    if (!P->any_uv) { free(s->UV); s->UV = NULL; }
    if (s->n_emitters > 0 && !emitters_prepare(s, P->err)) return 0;
    for (i = 0; i < s->n_shapes; i++)
        if (s->materials[s->shapes[i].material].type == MAT_INTERFACE) s->n_interface++;
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
    P.gs.ctm = P.gs.ctm_end = xf_identity();
    P.gs.active = 3;                         /* ActiveTransform All */
    P.t1 = 1.0;                              /* TransformTimes 0 1 */
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
    if (!file || !parser_set_colorspace(&P, COLORSPACE_SRGB)) { parser_free(&P); return fail(&P, name, 0, "out of memory"); }
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
    buf = read_whole_file_gz(path, READ_TEXT, NULL, &len, &rs);
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
        free(s->emitters[i].prim_scale);
        free(s->emitters[i].planes);
        inf_free(s->emitters[i].inf);
        delta_free(&s->emitters[i].delta);
    }
    for (i = 0; i < s->n_strings; i++) free(s->strings[i]);
    free(s->strings);
    free(s->P);
    free(s->N);
    free(s->S);
    free(s->tris);
    free(s->shapes);
    for (i = 0; i < s->n_media; i++) medium_free(&s->media[i]);
    free(s->media);
    for (i = 0; i < s->n_materials; i++) material_release(&s->materials[i]);
    free(s->materials);
    free(s->emitters);
    spec_store_free(&s->spectra);
    free(s->sphere_shape);
    free(s->quadric_shape);
    free(s->patches);
    free(s->curves);
    free(s->curve_pieces);
    for (i = 0; i < s->n_objects; i++) bvh_free(&s->objects[i].bvh);
    free(s->objects);
    free(s->instances);
    free(s->motions);
    for (i = 0; i < s->n_textures; i++) tex_free(&s->textures[i]);
    free(s->textures);
    free(s->UV);
    memset(s, 0, sizeof *s);
}
