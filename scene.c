/* scene.c - the scene parser: a strict subset of the pbrt-v4 scene format.

   Implements (specnee.h section 8): scene_load, scene_load_as, scene_load_string,
   scene_free, scene_dump.

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
     does the division (per render), this file records L, scale and twosided.  For "rgb L"
     pbrt-v4 divides by the colour space's illuminant (D65) instead of by L;
     we emulate that by multiplying scale by  sum ybar L / sum ybar D65.

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
#include "specnee.h"
#include <ctype.h>
#include <float.h>
#include <limits.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------------
   Limits that keep hostile input finite.
   --------------------------------------------------------------------------- */
#define MAX_INCLUDE_DEPTH 32        /* Include/Import nesting (catches cycles) */
#define MAX_INCLUDES 10000          /* Include/Import directives run in one scene
                                       (with the byte budget below: catches fan-out,
                                       files that include the next one twice) */
#define MAX_RESOLUTION 16384        /* pixels per film axis */
#define MAX_SPP (1 << 24)           /* samples per pixel */
#define MAX_MAXDEPTH 10000          /* path length */
#define MAX_ELEMENTS (1 << 27)      /* vertices, indices, triangles of one scene */
#define MAX_WORD 255                /* longest unquoted token */
/* the scene text, all its included files together, is at most READ_MAX_BYTES */

/* ===========================================================================
   1. Tokens
   =========================================================================== */
typedef enum { TK_EOF, TK_WORD, TK_STRING, TK_LBRACKET, TK_RBRACKET } TokKind;

typedef struct {
    TokKind kind;
    const char *text;          /* word or (unescaped) string, NUL-terminated */
    const char *file; int line;/* where it was read */
} Token;

/* A file being read: its text and the cursor. */
typedef struct {
    const char *file;          /* interned name used in messages */
    char *buf; size_t len, pos;
    int line;
} Source;

/* The token stream of one file and the files it Includes.  As in pbrt-v4, Include
   is textual: the included file's tokens come next, and when it ends the stream
   goes on in the including file, so a statement may begin in one file and take
   parameters from the next.  Strings are unescaped in place inside the buffer,
   words are copied into `word` (their terminator is the next token's first
   character).  An included buffer that has been read to its end stays alive
   until the statement being read is done (parameters point into it). */
typedef struct {
    Source cur;                /* the file being read */
    Source parent[MAX_INCLUDE_DEPTH];  /* the files that included it, innermost last */
    int n_parent;
    char *finished[MAX_INCLUDE_DEPTH + 1]; int n_finished;  /* included, read to the end */
    const char *file;          /* = cur.file: the file of the last token read */
    char word[2][MAX_WORD + 1];/* two slots: a peeked word survives the next one */
    int word_slot;
    Token peeked; int has_peeked;
    const char *dir_file; int dir_line;  /* the directive being read */
} Lexer;

/* ===========================================================================
   2. Parameters:  "type name" value(s)
   =========================================================================== */
typedef enum {
    PT_FLOAT, PT_INTEGER, PT_BOOL, PT_STRING, PT_POINT2, PT_VECTOR2, PT_POINT3,
    PT_VECTOR3, PT_NORMAL, PT_SPECTRUM, PT_RGB, PT_BLACKBODY, PT_TEXTURE
} ParamType;

static const char *const param_type_names[] = {
    "float", "integer", "bool", "string", "point2", "vector2", "point3",
    "vector3", "normal", "spectrum", "rgb", "blackbody", "texture"
};

typedef enum { V_NONE, V_NUM, V_STR, V_BOOL } ValueKind;

typedef struct {
    ParamType type;
    char name[64];
    ValueKind kind;            /* what the values are (one kind per parameter) */
    double *num; int n_num;    /* numbers, or bools as 0/1 */
    const char **str; int n_str;  /* strings (point into the lexer's buffer) */
    const char *file; int line;
    int used;                  /* looked up by the directive (pbrt's lookedUp) */
} Param;

typedef struct { Param *p; int n, cap; } ParamList;

/* ===========================================================================
   3. The parser state: pbrt's graphics state and what the directives built
   =========================================================================== */
typedef struct {
    Spectrum L;
    float scale;
    int twosided;
} AreaLightDesc;

typedef struct {
    Xform ctm;                 /* current transformation matrix */
    int material;              /* index into Scene.materials, -1: the default,
                                  <= -2: named material -2 - material, not yet made */
    int reverse;               /* ReverseOrientation seen in this block */
    int area_light;            /* index into Parser.lights, -1: none */
    int medium_inside, medium_outside;   /* MediumInterface: Scene.media indices, -1: none */
    const char *file; int line;/* where the block was opened (for messages) */
} GState;

/* A medium named by MakeNamedMedium or MediumInterface.  As in pbrt-v4, which
   creates the media when the file has been read, a MediumInterface may name a
   medium defined further down: its Scene.media entry is made at the first
   mention and filled by the MakeNamedMedium; finish() fails at the first mention
   of a name that none defines. */
typedef struct { int defined; const char *file; int line; } MediumRef;

/* A named material.  As in pbrt-v4 a NamedMaterial may come before its
   MakeNamedMaterial (pbrt-v4 looks names up when it builds the scene): the name is
   then recorded with material -1 and the NamedMaterial's place, and shapes made
   under it carry the code -2 - (its index) until finish() resolves them. */
typedef struct { char name[64]; int material; const char *file; int line; } NamedMaterial;
/* A named texture: pbrt-v4 keeps float and spectrum textures in two namespaces. */
typedef struct { char name[64]; int is_float; int index; } NamedTexture;
typedef struct { char name[64]; Xform xf; } NamedCoordSys;

typedef struct {
    Scene *s;
    Error *err;
    char main_dir[1024];       /* directory of the top-level file (pbrt's search dir) */
    int in_world;              /* after WorldBegin */
    int world_seen, include_depth;   /* include_depth: Import nesting */
    int nest;                  /* files open now inside the top-level one (Include+Import) */
    long n_includes;           /* Include/Import directives run so far */
    size_t text_bytes;         /* scene text read so far, included files included */
    GState gs;
    GState *stack; int depth, stack_cap;
    AreaLightDesc *lights; int n_lights, cap_lights;
    NamedMaterial *named; int n_named, cap_named;
    NamedCoordSys *coords; int n_coords, cap_coords;
    NamedTexture *texnames; int n_texnames, cap_texnames;
    int cap_textures;
    int default_material;      /* -1 until a shape needs it */
    /* capacities of the growing Scene arrays */
    int cap_verts, cap_tris, cap_shapes, cap_mats, cap_emit, cap_spheres, cap_quadrics, cap_strings;
    int any_normals;
    int any_uv;                /* some mesh has "uv": Scene.UV is kept parallel to P */
    int inset_line[8];         /* where each inset comment was (for messages) */
    const char *inset_file[8];
    int end_line;              /* line of the top-level file's last token */
    const char *camera_file; int camera_line;   /* the Camera directive, if any */
    float iso, exposure_time;  /* Film "iso", Camera shutter interval: the imaging ratio */
    const char *output;        /* the command line's output file (-o), NULL: none */
    MediumRef *mrefs; int cap_media, cap_mrefs;   /* parallel to Scene.media */
    const char *integ_file; int integ_line; char integ_type[32];  /* the Integrator */
} Parser;

/* ===========================================================================
   4. Small helpers: errors, memory, strings, paths
   =========================================================================== */
static int fail(Parser *P, const char *file, int line, const char *fmt, ...)
{
    char buf[448];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    error_set(P->err, file, line, "%s", buf);
    return 0;
}

/* The same for a problem with the value of parameter `name`: the message points to
   that parameter's own file:line when the statement gives it (it may sit lines
   below the statement's first), else to the statement's (file, line). */
static int fail_param(Parser *P, const ParamList *pl, const char *name, const char *file,
                      int line, const char *fmt, ...)
{
    char buf[448];
    va_list ap;
    int i;
    for (i = pl->n - 1; i >= 0; i--)
        if (strcmp(pl->p[i].name, name) == 0) {
            file = pl->p[i].file;
            line = pl->p[i].line;
            break;
        }
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    error_set(P->err, file, line, "%s", buf);
    return 0;
}

/* Grow *arr so that it holds at least `need` elements of size elsz. */
static int grow(void **arr, int *cap, int need, size_t elsz)
{
    void *p;
    size_t ncap;
    if (need <= *cap) return 1;
    if (need > MAX_ELEMENTS) return 0;
    ncap = *cap > 0 ? (size_t)*cap : 16;
    while (ncap < (size_t)need) ncap *= 2;
    p = realloc(*arr, ncap * elsz);
    if (!p) return 0;
    *arr = p;
    *cap = (int)ncap;
    return 1;
}

static char *str_dup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = (char *)malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* Keep a copy of a file name in Scene.strings (Shape.file points there). */
static const char *intern(Parser *P, const char *name)
{
    Scene *s = P->s;
    int i;
    char *d;
    for (i = 0; i < s->n_strings; i++)
        if (strcmp(s->strings[i], name) == 0) return s->strings[i];
    if (!grow((void **)&s->strings, &P->cap_strings, s->n_strings + 1, sizeof(char *)))
        return NULL;
    d = str_dup(name);
    if (!d) return NULL;
    s->strings[s->n_strings++] = d;
    return d;
}

/* The directory part of path, with its trailing '/', or "" (the current dir). */
static void dir_of(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + 1 : 0;
    if (n >= cap) n = 0;
    memcpy(out, path, n);
    out[n] = '\0';
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    fclose(f);
    return 1;
}

/* Resolve a file name given in `from_file` as pbrt-v4 does (util/file.cpp
   ResolveFilename): relative to the directory of the top-level scene file, else as
   given (the working directory).  Only when neither exists, specnee also looks next
   to the file that names it.  When nothing exists, out gets pbrt-v4's candidate,
   the name in the top-level file's directory, for the message. */
static void resolve_path(const Parser *P, const char *from_file, const char *name,
                         char *out, size_t cap)
{
    char dir[1024];
    if (name[0] == '/') { snprintf(out, cap, "%s", name); return; }
    snprintf(out, cap, "%s%s", P->main_dir, name);
    if (file_exists(out)) return;
    snprintf(out, cap, "%s", name);
    if (file_exists(out)) return;
    dir_of(from_file, dir, sizeof dir);
    snprintf(out, cap, "%s%s", dir, name);
    if (file_exists(out)) return;
    snprintf(out, cap, "%s%s", P->main_dir, name);    /* pbrt-v4's candidate */
}

static int ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix), i;
    if (m > n) return 0;
    for (i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != tolower((unsigned char)suffix[i])) return 0;
    return 1;
}

/* ===========================================================================
   5. The tokenizer (pbrt-v4 parser.cpp Tokenizer::Next, in our own words)
   =========================================================================== */

/* A structured comment "# inset NAME x0 y0 x1 y1" names a region of the image
   (pixels from the top left, end exclusive) for crops and region metrics. */
static int inset_comment(Parser *P, Lexer *L, const char *c, size_t n, int line)
{
    char text[256], name[64];
    int x0, y0, x1, y1, used = 0;
    Scene *s = P->s;
    if (n >= sizeof text) n = sizeof text - 1;
    memcpy(text, c, n);
    text[n] = '\0';
    if (sscanf(text, " inset %63s %d %d %d %d %n", name, &x0, &y0, &x1, &y1, &used) != 5
        || text[used] != '\0')
        return fail(P, L->cur.file, line, "malformed structured comment, expected "
                    "\"# inset NAME x0 y0 x1 y1\"");
    if (strlen(name) > 15)
        return fail(P, L->cur.file, line, "inset name \"%s\" longer than 15 characters", name);
    if (x0 < 0 || y0 < 0 || x1 <= x0 || y1 <= y0)
        return fail(P, L->cur.file, line, "inset %s: need 0 <= x0 < x1 and 0 <= y0 < y1", name);
    if (s->n_insets >= 8)
        return fail(P, L->cur.file, line, "more than 8 insets");
    snprintf(s->inset_name[s->n_insets], sizeof s->inset_name[0], "%.15s", name); /* checked above */
    P->inset_line[s->n_insets] = line;
    P->inset_file[s->n_insets] = L->cur.file;
    s->inset[s->n_insets][0] = x0; s->inset[s->n_insets][1] = y0;
    s->inset[s->n_insets][2] = x1; s->inset[s->n_insets][3] = y1;
    s->n_insets++;
    return 1;
}

static int is_space(int c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/* Next token; comments are consumed here (structured ones are recorded). */
static int lex_next(Parser *P, Lexer *L, Token *t)
{
    Source *S = &L->cur;
    if (L->has_peeked) { *t = L->peeked; L->has_peeked = 0; return 1; }
    for (;;) {
        int c;
        if (S->pos >= S->len) {
            if (L->n_parent > 0) {                    /* an included file ends: go on */
                if (L->n_finished < MAX_INCLUDE_DEPTH + 1)   /* always (see Lexer) */
                    L->finished[L->n_finished++] = S->buf;
                else
                    free(S->buf);
                *S = L->parent[--L->n_parent];
                L->file = S->file;
                P->nest--;
                continue;
            }
            t->kind = TK_EOF; t->text = ""; t->file = S->file; t->line = S->line;
            return 1;
        }
        c = (unsigned char)S->buf[S->pos];
        if (c == '\n') { S->line++; S->pos++; continue; }
        if (is_space(c)) { S->pos++; continue; }
        t->file = S->file;
        t->line = S->line;
        if (c == '\0')
            return fail(P, S->file, S->line, "unexpected NUL byte (not a text file?)");
        if (c < 0x20 || c == 0x7F)
            return fail(P, S->file, S->line, "unexpected control byte 0x%02X (not a text "
                        "file?)", c);
        if (c == '#') {                               /* comment to end of line */
            size_t start = ++S->pos;
            while (S->pos < S->len && S->buf[S->pos] != '\n' && S->buf[S->pos] != '\r')
                S->pos++;
            if (S->pos - start >= 6 && strncmp(S->buf + start, " inset", 6) == 0
                && !inset_comment(P, L, S->buf + start, S->pos - start, t->line))
                return 0;
            continue;
        }
        if (c == '[' || c == ']') {
            S->pos++;
            t->kind = c == '[' ? TK_LBRACKET : TK_RBRACKET;
            t->text = c == '[' ? "[" : "]";
            return 1;
        }
        if (c == '"') {                               /* quoted string, escapes */
            char *w = S->buf + S->pos + 1;            /* write cursor (in place) */
            char *start = w;
            S->pos++;
            for (;;) {
                int ch;
                if (S->pos >= S->len)
                    return fail(P, S->file, t->line, "unterminated string (end of file)");
                ch = (unsigned char)S->buf[S->pos++];
                if (ch == '"') break;
                if (ch == '\n' || ch == '\r')
                    return fail(P, S->file, t->line, "unterminated string (end of line)");
                if (ch == '\\') {
                    int e;
                    if (S->pos >= S->len)
                        return fail(P, S->file, t->line, "unterminated string (end of file)");
                    e = (unsigned char)S->buf[S->pos++];
                    switch (e) {
                    case 'n': ch = '\n'; break;
                    case 't': ch = '\t'; break;
                    case 'r': ch = '\r'; break;
                    case 'b': ch = '\b'; break;
                    case 'f': ch = '\f'; break;
                    case '\\': case '\'': case '"': ch = e; break;
                    default:
                        return fail(P, S->file, t->line, "unexpected escaped character \"\\%c\"", e);
                    }
                }
                *w++ = (char)ch;
            }
            *w = '\0';                                /* w < closing quote + 1 */
            t->kind = TK_STRING;
            t->text = start;
            return 1;
        }
        {                                             /* word: up to space, quote, bracket */
            size_t start = S->pos, n;
            char *word = L->word[L->word_slot];
            L->word_slot ^= 1;
            while (S->pos < S->len) {
                c = (unsigned char)S->buf[S->pos];
                if (is_space(c) || c == '"' || c == '[' || c == ']' || c == '#' || c == '\0') break;
                S->pos++;
            }
            n = S->pos - start;
            if (n > MAX_WORD)
                return fail(P, S->file, t->line, "token longer than %d characters", MAX_WORD);
            memcpy(word, S->buf + start, n);
            word[n] = '\0';
            t->kind = TK_WORD;
            t->text = word;
            return 1;
        }
    }
}

static void lex_unget(Lexer *L, const Token *t) { L->peeked = *t; L->has_peeked = 1; }

static const char *tok_desc(const Token *t)
{
    switch (t->kind) {
    case TK_EOF: return "end of file";
    case TK_STRING: return "a quoted string";
    case TK_LBRACKET: return "'['";
    case TK_RBRACKET: return "']'";
    default: return t->text;
    }
}

/* A float literal: the whole token must be a finite number within float range. */
static int parse_number(const char *s, double *out)
{
    char *end;
    double v;
    if (!*s) return 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0') return 0;
    if (!(v == v) || v > FLT_MAX || v < -FLT_MAX) return 0;     /* NaN, inf, overflow */
    *out = v;
    return 1;
}

/* An integer literal (pbrt-v4 parseInt): optional sign, decimal digits, 32 bits. */
static int parse_integer(const char *s, double *out)
{
    long long v = 0;
    int neg = 0;
    if (*s == '+' || *s == '-') neg = *s++ == '-';
    if (!*s) return 0;
    for (; *s; s++) {
        if (*s < '0' || *s > '9') return 0;
        v = v * 10 + (*s - '0');
        if (v > (long long)INT_MAX + 1) return 0;
    }
    if (neg) v = -v;
    if (v > INT_MAX || v < INT_MIN) return 0;
    *out = (double)v;
    return 1;
}

/* A bare number where a directive expects one (LookAt, Translate, ...). */
static int expect_number(Parser *P, Lexer *L, const char *directive, int count, double *out)
{
    int i;
    for (i = 0; i < count; i++) {
        Token t;
        if (!lex_next(P, L, &t)) return 0;
        if (t.kind == TK_EOF)                     /* a truncated file: blame the directive */
            return fail(P, L->dir_file, L->dir_line, "%s expects %d numbers, found end of file",
                        directive, count);
        if (t.kind != TK_WORD)
            return fail(P, t.file, t.line, "%s expects %d numbers, found %s",
                        directive, count, tok_desc(&t));
        if (!parse_number(t.text, &out[i]))
            return fail(P, t.file, t.line, "%s: \"%s\" is not a finite number",
                        directive, t.text);
    }
    return 1;
}

/* '[' 16 numbers ']' for Transform / ConcatTransform (brackets required, as in pbrt-v4). */
static int expect_matrix(Parser *P, Lexer *L, const char *directive, double m[16])
{
    Token t;
    if (!lex_next(P, L, &t)) return 0;
    if (t.kind != TK_LBRACKET)
        return fail(P, t.file, t.line, "%s expects '[' and 16 numbers, found %s",
                    directive, tok_desc(&t));
    if (!expect_number(P, L, directive, 16, m)) return 0;
    if (!lex_next(P, L, &t)) return 0;
    if (t.kind != TK_RBRACKET)
        return fail(P, t.file, t.line, "%s expects exactly 16 numbers and ']', found %s",
                    directive, tok_desc(&t));
    return 1;
}

static int expect_string(Parser *P, Lexer *L, const char *directive, const char *what,
                         Token *t)
{
    if (!lex_next(P, L, t)) return 0;
    if (t->kind != TK_STRING)
        return fail(P, t->file, t->line, "%s expects a quoted %s, found %s",
                    directive, what, tok_desc(t));
    return 1;
}

/* ---------------------------------------------------------------------------
   Parameter lists (pbrt-v4 parseParameters + checkParameterTypes)
   --------------------------------------------------------------------------- */
static void params_free(ParamList *pl)
{
    int i;
    for (i = 0; i < pl->n; i++) { free(pl->p[i].num); free((void *)pl->p[i].str); }
    free(pl->p);
    pl->p = NULL; pl->n = pl->cap = 0;
}

static int param_add_value(Parser *P, Lexer *L, Param *p, const Token *v, int *cap_num,
                           int *cap_str)
{
    ValueKind k;
    double x = 0;
    (void)L;
    if (v->kind == TK_STRING) k = V_STR;
    else if (strcmp(v->text, "true") == 0) { k = V_BOOL; x = 1; }
    else if (strcmp(v->text, "false") == 0) { k = V_BOOL; x = 0; }
    else {
        k = V_NUM;
        if (p->type == PT_INTEGER) {
            if (!parse_integer(v->text, &x))
                return fail(P, v->file, v->line, "\"integer %s\": \"%s\" is not an integer",
                            p->name, v->text);
        } else if (!parse_number(v->text, &x))
            return fail(P, v->file, v->line, "\"%s %s\": \"%s\" is not a finite number",
                        param_type_names[p->type], p->name, v->text);
    }
    if (p->kind != V_NONE && p->kind != k)
        return fail(P, v->file, v->line, "\"%s %s\": mixed kinds of values in one list",
                    param_type_names[p->type], p->name);
    p->kind = k;
    if (k == V_STR) {
        if (!grow((void **)&p->str, cap_str, p->n_str + 1, sizeof(char *)))
            return fail(P, v->file, v->line, "out of memory");
        p->str[p->n_str++] = v->text;
    } else {
        if (!grow((void **)&p->num, cap_num, p->n_num + 1, sizeof(double)))
            return fail(P, v->file, v->line, "out of memory (or more than %d values)", MAX_ELEMENTS);
        p->num[p->n_num++] = x;
    }
    return 1;
}

/* Check that the values fit the declared type (pbrt-v4 checkParameterTypes). */
static int param_check_kind(Parser *P, const Param *p)
{
    const char *tn = param_type_names[p->type];
    switch (p->type) {
    case PT_BOOL:
        if (p->kind == V_STR)
            return fail(P, p->file, p->line, "\"bool %s\": write true or false without quotes "
                        "(pbrt-v4 rejects quoted Booleans)", p->name);
        if (p->kind != V_BOOL)
            return fail(P, p->file, p->line, "\"bool %s\": non-Boolean value", p->name);
        break;
    case PT_STRING: case PT_TEXTURE:
        if (p->kind != V_STR)
            return fail(P, p->file, p->line, "\"%s %s\": expected quoted string value(s)",
                        tn, p->name);
        break;
    case PT_SPECTRUM:
        if (p->kind != V_STR && p->kind != V_NUM)
            return fail(P, p->file, p->line, "\"spectrum %s\": expected numbers or a "
                        "quoted name", p->name);
        break;
    default:
        if (p->kind != V_NUM)
            return fail(P, p->file, p->line, "\"%s %s\": expected numeric value(s)",
                        tn, p->name);
    }
    return 1;
}

/* Read "type name" value(s) pairs until the next token is not a quoted string. */
static int parse_params(Parser *P, Lexer *L, ParamList *pl)
{
    for (;;) {
        Token t, v;
        Param *p;
        char type[64], name[64], extra[8];
        int i, nf, cap_num = 0, cap_str = 0;
        if (!lex_next(P, L, &t)) return 0;
        if (t.kind != TK_STRING) { lex_unget(L, &t); return 1; }
        extra[0] = '\0';
        nf = sscanf(t.text, "%63s %63s %7s", type, name, extra);
        if (nf < 2)
            return fail(P, t.file, t.line, "parameter \"%s\" needs a type and a name, "
                        "like \"float fov\"", t.text);
        if (nf > 2)
            return fail(P, t.file, t.line, "parameter \"%s\": more than a type and a name",
                        t.text);
        if (!grow((void **)&pl->p, &pl->cap, pl->n + 1, sizeof(Param)))
            return fail(P, t.file, t.line, "out of memory");
        p = &pl->p[pl->n];
        memset(p, 0, sizeof *p);
        for (i = 0; i < (int)(sizeof param_type_names / sizeof param_type_names[0]); i++)
            if (strcmp(type, param_type_names[i]) == 0) break;
        if (i == (int)(sizeof param_type_names / sizeof param_type_names[0])) {
            if (!strcmp(type, "point") || !strcmp(type, "vector") || !strcmp(type, "color")
                || !strcmp(type, "normal3"))
                return fail(P, t.file, t.line, "\"%s %s\": \"%s\" is pbrt-v3 syntax, not "
                            "pbrt-v4 (run pbrt --upgrade)", type, name, type);
            return fail(P, t.file, t.line, "\"%s %s\": \"%s\": unknown parameter type",
                        type, name, type);
        }
        p->type = (ParamType)i;
        snprintf(p->name, sizeof p->name, "%s", name);
        p->file = t.file;
        p->line = t.line;
        pl->n++;
        if (!lex_next(P, L, &v)) return 0;
        if (v.kind == TK_LBRACKET) {
            int open_line = v.line;
            const char *open_file = v.file;
            for (;;) {
                if (!lex_next(P, L, &v)) return 0;
                if (v.kind == TK_RBRACKET) break;
                if (v.kind == TK_EOF)
                    return fail(P, open_file, open_line, "\"%s %s\": unterminated '[' list "
                                "(end of file)", type, name);
                if (v.kind == TK_LBRACKET)
                    return fail(P, v.file, v.line, "\"%s %s\": '[' inside a list "
                                "(missing ']'?)", type, name);
                if (!param_add_value(P, L, p, &v, &cap_num, &cap_str)) return 0;
            }
        } else if (v.kind == TK_WORD || v.kind == TK_STRING) {
            if (!param_add_value(P, L, p, &v, &cap_num, &cap_str)) return 0;
        } else {
            return fail(P, v.file, v.line, "\"%s %s\": expected a value, found %s",
                        type, name, tok_desc(&v));
        }
        if (p->n_num == 0 && p->n_str == 0)
            return fail(P, p->file, p->line, "\"%s %s\": no values given", type, name);
        if (!param_check_kind(P, p)) return 0;
    }
}

/* Find a parameter by type and name.  As in pbrt-v4 the last one given wins and
   the earlier ones of the same type and name count as used (shadowed). */
static Param *param_find(ParamList *pl, ParamType type, const char *name)
{
    Param *found = NULL;
    int i;
    for (i = pl->n - 1; i >= 0; i--)
        if (pl->p[i].type == type && strcmp(pl->p[i].name, name) == 0) {
            if (!found) found = &pl->p[i];
            pl->p[i].used = 1;
        }
    return found;
}

/* The one number of parameter `TNAME name` (type `type`) in *v, and *found = 1;
   *found = 0 when absent.  Fails on any count but one. */
static int get_one(Parser *P, ParamList *pl, ParamType type, const char *tname, const char *name,
                   double *v, int *found)
{
    Param *p = param_find(pl, type, name);
    *found = p != NULL;
    if (!p) return 1;
    if (p->n_num == 1) { *v = p->num[0]; return 1; }
    return fail(P, p->file, p->line, "\"%s %s\": expected one value, got %d", tname, name, p->n_num);
}

static int get_float(Parser *P, ParamList *pl, const char *name, float def, float *out)
{
    double v = def;
    int found;
    if (!get_one(P, pl, PT_FLOAT, "float", name, &v, &found)) return 0;
    *out = found ? (float)v : def;
    return 1;
}

static int get_int(Parser *P, ParamList *pl, const char *name, int def, int *out, int *given)
{
    double v = def;
    int found;
    if (!get_one(P, pl, PT_INTEGER, "integer", name, &v, &found)) return 0;
    if (given) *given = found;
    *out = found ? (int)v : def;
    return 1;
}

static int get_bool(Parser *P, ParamList *pl, const char *name, int def, int *out)
{
    double v = def;
    int found;
    if (!get_one(P, pl, PT_BOOL, "bool", name, &v, &found)) return 0;
    *out = found ? v != 0 : def;
    return 1;
}

static int get_string(Parser *P, ParamList *pl, const char *name, const char **out)
{
    Param *p = param_find(pl, PT_STRING, name);
    *out = NULL;
    if (!p) return 1;
    if (p->n_str != 1)
        return fail(P, p->file, p->line, "\"string %s\": expected one value, got %d",
                    name, p->n_str);
    *out = p->str[0];
    return 1;
}

/* Is `name` one of the space-separated words of `list`? */
static int word_in(const char *list, const char *name)
{
    size_t n = strlen(name);
    const char *s = list;
    while (s && *s) {
        while (*s == ' ') s++;
        if (strncmp(s, name, n) == 0 && (s[n] == ' ' || s[n] == '\0')) return 1;
        s = strchr(s, ' ');
    }
    return 0;
}

/* After a directive has looked up what it understands: any parameter left over
   is an error, as in pbrt-v4 (ReportUnused).  `reads` lists what the directive
   reads ("integer xresolution, ..."), `pbrt_only` names the pbrt-v4 parameters
   of this directive that specnee does not support. */
static int params_check_unused_before(Parser *P, ParamList *pl, const char *what,
                                      const char *reads, const char *pbrt_only, int before)
{
    int i;
    for (i = 0; i < before && i < pl->n; i++) {
        const Param *p = &pl->p[i];
        const char *tn = param_type_names[p->type];
        char key[80];
        if (p->used) continue;
        if (p->type == PT_TEXTURE)
            return fail(P, p->file, p->line, "\"texture %s\": textures are valid pbrt-v4 "
                        "but not in the specnee subset", p->name);
        if (pbrt_only && word_in(pbrt_only, p->name))
            return fail(P, p->file, p->line, "%s: \"%s %s\" is valid pbrt-v4 but not in the "
                        "specnee subset", what, tn, p->name);
        {
            char padded[1024];
            snprintf(padded, sizeof padded, " %s,", reads);
            /* read with exactly this type: another parameter took precedence */
            snprintf(key, sizeof key, " %s %s,", tn, p->name);
            if (strstr(padded, key))
                return fail(P, p->file, p->line, "\"%s %s\": unused parameter (overridden "
                            "by another parameter of %s)", tn, p->name, what);
            /* the name is known with another type: a wrong type */
            snprintf(key, sizeof key, " %s,", p->name);
            if (strstr(padded, key))
                return fail(P, p->file, p->line, "\"%s %s\": wrong type for %s (it reads: %s)",
                            tn, p->name, what, reads);
        }
        return fail(P, p->file, p->line, "\"%s %s\": unused parameter (%s reads: %s)",
                    tn, p->name, what, reads[0] ? reads : "nothing");
    }
    return 1;
}

/* Every parameter, in the order of the file (the parameter list keeps it): the
   first one left over is named. */
static int params_check_unused(Parser *P, ParamList *pl, const char *what,
                               const char *reads, const char *pbrt_only)
{
    return params_check_unused_before(P, pl, what, reads, pbrt_only, pl->n);
}

/* A parameter p that was read but whose value specnee refuses: a statement's
   first problem in the file is the one named, so a parameter left over before p
   is reported instead; else msg, at p's own line (file:line when p is NULL).
   Call it after the directive has read all its parameters. */
static int refuse_param(Parser *P, ParamList *pl, const char *what, const char *reads,
                        const Param *p, const char *file, int line, const char *msg)
{
    if (p && !params_check_unused_before(P, pl, what, reads, NULL, (int)(p - pl->p))) return 0;
    return fail(P, p ? p->file : file, p ? p->line : line, "%s", msg);
}

/* ===========================================================================
   6. Spectrum-valued parameters
   =========================================================================== */
/* SPEC_COEFF: a medium's coefficients, pbrt-v4's "unbounded" spectra with rgb
   (RGBUnboundedSpectrum) and blackbody (peak 1) allowed */
typedef enum { SPEC_ALBEDO, SPEC_UNBOUNDED, SPEC_ILLUMINANT, SPEC_COEFF } SpecUse;

/* The last "spectrum/rgb/blackbody name" parameter (pbrt-v4 GetOneSpectrum). */
static Param *find_spectrum_param(ParamList *pl, const char *name)
{
    int i;
    for (i = pl->n - 1; i >= 0; i--) {
        Param *p = &pl->p[i];
        if ((p->type == PT_SPECTRUM || p->type == PT_RGB || p->type == PT_BLACKBODY)
            && strcmp(p->name, name) == 0) {
            param_find(pl, p->type, name);             /* mark it and its shadows */
            return p;
        }
    }
    return NULL;
}

/* Turn a spectrum parameter into a dense table.  *rgb_illum is set for an
   "rgb" illuminant (its scale needs pbrt's D65 normalisation, section 3). */
static int param_spectrum(Parser *P, Param *p, SpecUse use, Spectrum *out, int *rgb_illum)
{
    const char *tn = param_type_names[p->type];
    if (rgb_illum) *rgb_illum = 0;
    if (p->type == PT_RGB) {
        float rgb[3];
        int k;
        if (p->n_num != 3)
            return fail(P, p->file, p->line, "\"rgb %s\": expected 3 values, got %d",
                        p->name, p->n_num);
        for (k = 0; k < 3; k++) rgb[k] = (float)p->num[k];
        if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0)
            return fail(P, p->file, p->line, "\"rgb %s\": negative component", p->name);
        if (use == SPEC_ALBEDO && (rgb[0] > 1 || rgb[1] > 1 || rgb[2] > 1))
            return fail(P, p->file, p->line, "\"rgb %s\": a reflectance must be within "
                        "[0,1]", p->name);
        if (use == SPEC_UNBOUNDED)
            return fail(P, p->file, p->line, "\"rgb %s\": valid pbrt-v4 but not in the "
                        "specnee subset (give a spectrum)", p->name);
        if (!spec_from_rgb(out, rgb, use == SPEC_ILLUMINANT ? 1 : use == SPEC_COEFF ? 2 : 0,
                           P->err, p->file, p->line))
            return 0;
        if (rgb_illum) *rgb_illum = use == SPEC_ILLUMINANT;
        return 1;
    }
    if (p->type == PT_BLACKBODY) {
        if (p->n_num != 1)
            return fail(P, p->file, p->line, "\"blackbody %s\": expected one temperature "
                        "(K), got %d values", p->name, p->n_num);
        if (use != SPEC_ILLUMINANT && use != SPEC_COEFF)
            return fail(P, p->file, p->line, "\"blackbody %s\": valid pbrt-v4 but not in "
                        "the specnee subset here", p->name);
        if (!(p->num[0] > 0))
            return fail(P, p->file, p->line, "\"blackbody %s\": temperature must be > 0 K",
                        p->name);
        spec_blackbody(out, (float)p->num[0]);
        return 1;
    }
    if (p->kind == V_NUM) {                           /* inline [lambda value ...] */
        float *lambda, *value;
        int n = p->n_num / 2, k, ok;
        if (p->n_num % 2 != 0)
            return fail(P, p->file, p->line, "\"%s %s\": odd number of values (need "
                        "wavelength/value pairs)", tn, p->name);
        lambda = (float *)malloc(sizeof(float) * (size_t)n);
        value = (float *)malloc(sizeof(float) * (size_t)n);
        if (!lambda || !value) {
            free(lambda); free(value);
            return fail(P, p->file, p->line, "out of memory");
        }
        for (k = 0; k < n; k++) { lambda[k] = (float)p->num[2 * k]; value[k] = (float)p->num[2 * k + 1]; }
        ok = spec_from_pairs(out, lambda, value, n, P->err, p->file, p->line);
        free(lambda); free(value);
        return ok;
    }
    if (p->n_str != 1)                                /* a name or a file */
        return fail(P, p->file, p->line, "\"spectrum %s\": expected one name, got %d",
                    p->name, p->n_str);
    if (spec_named(out, p->str[0])) return 1;
    {
        char path[1024];
        Error e;
        resolve_path(P, p->file, p->str[0], path, sizeof path);
        if (!file_exists(path))
            return fail(P, p->file, p->line, "\"spectrum %s\": unknown named spectrum "
                        "\"%s\" and no file of that name", p->name, p->str[0]);
        if (!spec_from_file(out, path, &e))
            return fail(P, p->file, p->line, "\"spectrum %s\": %s", p->name, e.msg);
    }
    return 1;
}

/* ===========================================================================
   7. Growing the Scene
   =========================================================================== */
static int oom(Parser *P, const char *file, int line)
{
    return fail(P, file, line, "out of memory (or more than %d elements)", MAX_ELEMENTS);
}

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
   8. Directives of the options block
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
   9. Directives of the world block: materials, lights, shapes
   =========================================================================== */

/* A reflectance or absorptance must lie in [0, 1] at every nm, the UV extension
   included; 1e-4 of slack absorbs the rounding of an RGB upsampling of (1,1,1),
   and values in the slack are clamped to 1. */
static int check_unit_spectrum(Parser *P, const Param *p, Spectrum *sp)
{
    int k;
    for (k = 0; k < SPEC_N + SPEC_UV_N; k++) {
        /* 360..830 nm first (the first error names the visible value), then 300..359 */
        int nm = k < SPEC_N ? SPEC_MIN + k : SPEC_UV_MIN + (k - SPEC_N);
        float *v = spec_at(sp, nm);
        if (!(*v >= 0.0f && *v <= 1.0001f))
            return fail(P, p->file, p->line, "\"%s %s\": value %g at %d nm outside [0,1]",
                        param_type_names[p->type], p->name, *v, nm);
        if (*v > 1.0f) *v = 1.0f;
    }
    return 1;
}

/* A reflectance-like parameter p (may be NULL: the constant def): read, and
   checked to lie in [0, 1] (check_unit_spectrum). */
static int unit_spectrum_param(Parser *P, Param *p, Spectrum *out, float def)
{
    if (!p) { spec_const(out, def); return 1; }
    return param_spectrum(P, p, SPEC_ALBEDO, out, NULL) && check_unit_spectrum(P, p, out);
}

/* ====================================================================}

   Textures (texture.c): the Texture directive
   =========================================================================== */
/* The texture a "texture name" parameter names, in the float or spectrum
   namespace; -1 and an error when there is none. */
static int texture_lookup(Parser *P, const Param *p, int is_float)
{
    int i;
    if (p->n_str != 1)
        return fail(P, p->file, p->line, "\"texture %s\": expected one texture name", p->name) - 1;
    for (i = P->n_texnames - 1; i >= 0; i--)
        if (P->texnames[i].is_float == is_float && !strcmp(P->texnames[i].name, p->str[0]))
            return P->texnames[i].index;
    for (i = 0; i < P->n_texnames; i++)
        if (!strcmp(P->texnames[i].name, p->str[0]))
            return fail(P, p->file, p->line, "\"texture %s\": \"%s\" is a %s texture; a %s "
                        "one is needed here", p->name, p->str[0], is_float ? "spectrum" : "float",
                        is_float ? "float" : "spectrum") - 1;
    return fail(P, p->file, p->line, "\"texture %s\": no texture named \"%s\"", p->name,
                p->str[0]) - 1;
}

/* Argument k of texture T from parameter `name`: a texture, or a constant (def
   when absent). */
static int texture_arg(Parser *P, ParamList *pl, Texture *T, int k, const char *name, float def)
{
    Param *pt = param_find(pl, PT_TEXTURE, name);
    T->arg_tex[k] = -1;
    if (pt) {
        T->arg_tex[k] = texture_lookup(P, pt, T->is_float);
        return T->arg_tex[k] >= 0;
    }
    if (T->is_float) {
        if (!get_float(P, pl, name, def, &T->arg_f[k])) return 0;
        if (!isfinite(T->arg_f[k]))
            return fail(P, T->file, T->line, "Texture: \"float %s\" is not finite", name);
        return 1;
    } else {
        Param *p = find_spectrum_param(pl, name);
        if (!p) { spec_const(&T->arg_s[k], def); return 1; }
        return param_spectrum(P, p, SPEC_ALBEDO, &T->arg_s[k], NULL);
    }
}

/* The texture's frame: the inverse of the CTM at the directive (pbrt-v4's
   textureFromRender). */
static void texture_frame(Parser *P, Texture *T)
{
    int a, b;
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++) {
            T->tex_from_world.m[a][b] = P->gs.ctm.inv[a][b];
            T->tex_from_world.inv[a][b] = P->gs.ctm.m[a][b];
        }
}

/* The 2-D mapping parameters (pbrt-v4 TextureMapping2D::Create). */
static int texture_mapping(Parser *P, ParamList *pl, Texture *T)
{
    const char *map = NULL;
    double v1[3] = { 1, 0, 0 }, v2[3] = { 0, 1, 0 };
    Param *pv;
    int k;
    if (!get_string(P, pl, "mapping", &map)) return 0;
    if (!get_float(P, pl, "uscale", 1.0f, &T->su) || !get_float(P, pl, "vscale", 1.0f, &T->sv) ||
        !get_float(P, pl, "udelta", 0.0f, &T->du) || !get_float(P, pl, "vdelta", 0.0f, &T->dv))
        return 0;
    if (!isfinite(T->su) || !isfinite(T->sv) || !isfinite(T->du) || !isfinite(T->dv))
        return fail(P, T->file, T->line, "Texture: uscale, vscale, udelta, vdelta must be finite");
    if (!map || !strcmp(map, "uv")) T->map = TEXMAP_UV;
    else if (!strcmp(map, "spherical")) T->map = TEXMAP_SPHERICAL;
    else if (!strcmp(map, "cylindrical")) T->map = TEXMAP_CYLINDRICAL;
    else if (!strcmp(map, "planar")) T->map = TEXMAP_PLANAR;
    else return fail(P, T->file, T->line, "Texture: unknown mapping \"%s\" (pbrt-v4: uv, "
                     "spherical, cylindrical, planar)", map);
    for (k = 0; k < 2; k++) {
        double *v = k ? v2 : v1;
        pv = param_find(pl, PT_VECTOR3, k ? "v2" : "v1");
        if (pv) {
            int a;
            if (pv->n_num != 3)
                return fail(P, pv->file, pv->line, "\"vector3 %s\": expected 3 values", pv->name);
            for (a = 0; a < 3; a++) {
                if (!isfinite(pv->num[a]))
                    return fail(P, pv->file, pv->line, "\"vector3 %s\": not finite", pv->name);
                v[a] = pv->num[a];
            }
        }
    }
    T->vs = v3((float)v1[0], (float)v1[1], (float)v1[2]);
    T->vt = v3((float)v2[0], (float)v2[1], (float)v2[2]);
    texture_frame(P, T);
    return 1;
}

/* An imagemap's image: PNG, PFM, or EXR (the .pfm of the same name beside it, if any). */
static int texture_image(Parser *P, ParamList *pl, Texture *T, const char *name)
{
    const char *fn = NULL, *wrap = NULL, *filter = NULL, *enc = NULL;
    char path[1024], alt[1024];
    float scale;
    int invert, ok;
    Image im;
    Error ierr;
    FILE *f;
    if (!get_string(P, pl, "filename", &fn) || !get_string(P, pl, "wrap", &wrap) ||
        !get_string(P, pl, "filter", &filter) || !get_string(P, pl, "encoding", &enc) ||
        !get_float(P, pl, "scale", 1.0f, &scale) || !get_bool(P, pl, "invert", 0, &invert))
        return 0;
    (void)param_find(pl, PT_FLOAT, "maxanisotropy");   /* (only for the "ewa" filter) */
    if (!fn) return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": \"string filename\" is required", name);
    if (!isfinite(scale)) return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": scale is not finite", name);
    if (!wrap || !strcmp(wrap, "repeat")) T->wrap = TEXWRAP_REPEAT;
    else if (!strcmp(wrap, "black")) T->wrap = TEXWRAP_BLACK;
    else if (!strcmp(wrap, "clamp")) T->wrap = TEXWRAP_CLAMP;
    else return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": unknown wrap \"%s\" (repeat, "
                     "black, clamp)", name, wrap);
    if (filter && strcmp(filter, "bilinear") != 0 && strcmp(filter, "point") != 0)
        fprintf(stderr, "%s:%d: note: Texture \"imagemap\": filter \"%s\" is read as "
                "\"bilinear\" (specnee has no MIP maps)\n", T->file, T->line, filter);
    resolve_path(P, T->file, fn, path, sizeof path);
    if (ends_with_ci(fn, ".exr")) {
        snprintf(alt, sizeof alt, "%.*s.pfm", (int)strlen(path) - 4, path);
        f = fopen(alt, "rb");
        if (!f) {                              /* no .pfm beside it: the EXR (exr.c) */
            if (!exr_read(&im, path, &ierr))
                return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": %s", name, ierr.msg);
            ok = tex_set_image(T, &im, scale, invert, P->err);
            img_free(&im);
            return ok;
        }
        fclose(f);
        fprintf(stderr, "%s:%d: note: Texture \"imagemap\": reading %s for \"%s\"\n", T->file,
                T->line, alt, fn);
        snprintf(path, sizeof path, "%s", alt);
    } else if (ends_with_ci(fn, ".png")) {
        /* 8- and 16-bit PNG (png.c): sRGB-encoded unless "encoding" says "linear",
           as pbrt-v4 reads them; "gamma g" is refused by name */
        int linear = 0;
        if (enc && !strcmp(enc, "linear")) linear = 1;
        else if (enc && strcmp(enc, "sRGB") != 0)
            return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": encoding \"%s\" is valid "
                        "pbrt-v4 but not in the specnee subset (sRGB, linear)", name, enc);
        if (!png_read(&im, path, linear, &ierr))
            return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": %s", name, ierr.msg);
        ok = tex_set_image(T, &im, scale, invert, P->err);
        img_free(&im);
        return ok;
    } else if (!ends_with_ci(fn, ".pfm")) {
        return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": \"%s\": specnee reads image "
                    "textures as PNG or PFM (convert others with ImageMagick's `convert`)", name, fn);
    }
    (void)enc;                                 /* PFM holds linear values */
    if (!pfm_read(&im, path, &ierr))
        return fail(P, T->file, T->line, "Texture \"imagemap\" \"%s\": %s", name, ierr.msg);
    ok = tex_set_image(T, &im, scale, invert, P->err);
    img_free(&im);
    return ok;
}

/* Texture "name" "spectrum"|"float" "class" params (pbrt-v4's Texture). */
static int texture_directive(Parser *P, Lexer *L, const Token *t)
{
    static const char *const pbrt_classes[] = {
        "bilerp", "directionmix", "ptex", NULL
    };
    Scene *s = P->s;
    Token a[3];
    ParamList pl;
    Texture T;
    int k, ok = 0, dim = 2;
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
    if (!strcmp(a[2].text, "constant")) {
        T.type = TEX_CONSTANT;
        ok = texture_arg(P, &pl, &T, 0, "value", 1.0f);
    } else if (!strcmp(a[2].text, "checkerboard")) {
        T.type = TEX_CHECKERBOARD;
        ok = get_int(P, &pl, "dimension", 2, &dim, NULL);
        if (ok && dim != 2)
            ok = fail(P, t->file, t->line, "Texture \"checkerboard\": dimension %d: the 3-D "
                      "checkerboard is valid pbrt-v4 but not in the specnee subset", dim);
        ok = ok && texture_mapping(P, &pl, &T) && texture_arg(P, &pl, &T, 0, "tex1", 1.0f) &&
             texture_arg(P, &pl, &T, 1, "tex2", 0.0f);
    } else if (!strcmp(a[2].text, "scale")) {
        Param *ps = param_find(&pl, PT_TEXTURE, "scale");
        T.type = TEX_SCALE;
        ok = texture_arg(P, &pl, &T, 0, "tex", 1.0f);
        if (ok && ps) {
            T.scale_tex = texture_lookup(P, ps, 1);
            ok = T.scale_tex >= 0;
        } else if (ok) {
            ok = get_float(P, &pl, "scale", 1.0f, &T.arg_f[1]);
            if (ok && !isfinite(T.arg_f[1])) ok = fail(P, t->file, t->line, "Texture \"scale\": scale is not finite");
        }
    } else if (!strcmp(a[2].text, "mix")) {
        Param *pa = param_find(&pl, PT_TEXTURE, "amount");
        T.type = TEX_MIX;
        ok = texture_arg(P, &pl, &T, 0, "tex1", 0.0f) && texture_arg(P, &pl, &T, 1, "tex2", 1.0f);
        if (ok && pa) {
            T.amount_tex = texture_lookup(P, pa, 1);
            ok = T.amount_tex >= 0;
        } else if (ok) {
            ok = get_float(P, &pl, "amount", 0.5f, &T.amount);
            if (ok && !isfinite(T.amount)) ok = fail(P, t->file, t->line, "Texture \"mix\": amount is not finite");
        }
    } else if (!strcmp(a[2].text, "imagemap")) {
        T.type = TEX_IMAGEMAP;
        ok = texture_mapping(P, &pl, &T) && texture_image(P, &pl, &T, a[0].text);
    } else if (!strcmp(a[2].text, "dots")) {
        /* pbrt-v4 DotsTexture: "outside" (0) in a dot, "inside" (1) elsewhere (sic:
           pbrt-v4's Create passes "inside" as the constructor's outsideDot, since
           pbrt-v3; texture.c section 4) */
        T.type = TEX_DOTS;
        ok = texture_mapping(P, &pl, &T) && texture_arg(P, &pl, &T, 0, "inside", 1.0f) &&
             texture_arg(P, &pl, &T, 1, "outside", 0.0f);
    } else if (!strcmp(a[2].text, "marble")) {
        /* pbrt-v4 MarbleTexture (spectrum only): a 3-D texture in the frame of the
           CTM at the directive (TextureMapping3D, which reads no parameters) */
        T.type = TEX_MARBLE;
        if (T.is_float) {
            ok = fail(P, t->file, t->line, "Texture \"%s\": \"marble\" is a spectrum texture "
                      "(pbrt-v4 has no float marble)", a[0].text);
            goto done;
        }
        ok = get_int(P, &pl, "octaves", 8, &T.octaves, NULL) &&
             get_float(P, &pl, "roughness", 0.5f, &T.omega) &&
             get_float(P, &pl, "scale", 1.0f, &T.mscale) &&
             get_float(P, &pl, "variation", 0.2f, &T.variation);
        if (ok && !(isfinite(T.omega) && isfinite(T.mscale) && isfinite(T.variation)))
            ok = fail(P, t->file, t->line, "Texture \"marble\": roughness, scale and variation "
                      "must be finite");
        if (ok && !(T.octaves >= 0 && T.octaves <= 64))
            ok = fail(P, t->file, t->line, "Texture \"marble\": octaves %d must be within [0, 64]",
                      T.octaves);
        if (ok) {
            texture_frame(P, &T);   /* marble */
            ok = tex_marble_init(&T, P->err);
        }
    } else if (!strcmp(a[2].text, "fbm") || !strcmp(a[2].text, "wrinkled") ||
               !strcmp(a[2].text, "windy")) {
        /* pbrt-v4 FBmTexture, WrinkledTexture, WindyTexture (float only): 3-D noise
           in the frame of the CTM at the directive (texture.c section 4) */
        T.type = a[2].text[0] == 'f' ? TEX_FBM : a[2].text[1] == 'r' ? TEX_WRINKLED : TEX_WINDY;
        if (!T.is_float) {
            ok = fail(P, t->file, t->line, "Texture \"%s\": \"%s\" is a float texture "
                      "(pbrt-v4 has no spectrum %s)", a[0].text, a[2].text, a[2].text);
            goto done;
        }
        ok = 1;
        if (T.type != TEX_WINDY) {
            ok = get_int(P, &pl, "octaves", 8, &T.octaves, NULL) &&
                 get_float(P, &pl, "roughness", 0.5f, &T.omega);
            if (ok && !isfinite(T.omega))
                ok = fail(P, t->file, t->line, "Texture \"%s\": roughness must be finite", a[2].text);
            if (ok && !(T.octaves >= 0 && T.octaves <= 64))
                ok = fail(P, t->file, t->line, "Texture \"%s\": octaves %d must be within [0, 64]",
                          a[2].text, T.octaves);
        }
        if (ok) texture_frame(P, &T);
    } else {
        for (k = 0; pbrt_classes[k]; k++)
            if (!strcmp(a[2].text, pbrt_classes[k])) break;
        ok = fail(P, t->file, t->line, pbrt_classes[k] ? "Texture \"%s\": class \"%s\" is valid "
                  "pbrt-v4 but not in the specnee subset" : "Texture \"%s\": unknown class \"%s\"",
                  a[0].text, a[2].text);
    }
    if (ok) {
        static const char *const reads[] = {
            /* TEX_CONSTANT */ "spectrum value, rgb value, float value, texture value",
            /* TEX_CHECKERBOARD */ "integer dimension, string mapping, float uscale, float vscale, "
                "float udelta, float vdelta, vector3 v1, vector3 v2, spectrum tex1, rgb tex1, "
                "float tex1, texture tex1, spectrum tex2, rgb tex2, float tex2, texture tex2",
            /* TEX_SCALE */ "spectrum tex, rgb tex, float tex, texture tex, float scale, texture scale",
            /* TEX_MIX */ "spectrum tex1, rgb tex1, float tex1, texture tex1, spectrum tex2, rgb tex2, "
                "float tex2, texture tex2, float amount, texture amount",
            /* TEX_IMAGEMAP */ "string filename, string wrap, string filter, string encoding, "
                "float scale, bool invert, float maxanisotropy, string mapping, float uscale, "
                "float vscale, float udelta, float vdelta, vector3 v1, vector3 v2",
            /* TEX_DOTS */ "string mapping, float uscale, float vscale, float udelta, float vdelta, "
                "vector3 v1, vector3 v2, spectrum inside, rgb inside, float inside, texture inside, "
                "spectrum outside, rgb outside, float outside, texture outside",
            /* TEX_MARBLE */ "integer octaves, float roughness, float scale, float variation",
            /* TEX_FBM */ "integer octaves, float roughness",
            /* TEX_WRINKLED */ "integer octaves, float roughness",
            /* TEX_WINDY */ ""
        };
        char what[96];
        snprintf(what, sizeof what, "Texture \"%s\"", a[2].text);
        ok = params_check_unused(P, &pl, what, reads[T.type], NULL);
    }
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

/* One roughness parameter: a float texture (*tex its index, *have 1), a float
   (*v, *have 1), or absent (*have 0, *tex -1). */
static int rough_param(Parser *P, ParamList *pl, const char *name, int *have, float *v, int *tex)
{
    Param *pt = param_find(pl, PT_TEXTURE, name);
    *tex = -1;
    if (pt) {
        *have = 1;
        *tex = texture_lookup(P, pt, 1);
        return *tex >= 0;
    }
    *have = param_find(pl, PT_FLOAT, name) != NULL;
    return get_float(P, pl, name, 0, v);
}

/* pbrt-v4's roughness parameters of a microfacet material: u/vroughness default
   to "roughness", which defaults to 0; remaproughness (default true) maps them to
   alpha = sqrt(roughness) (TrowbridgeReitzDistribution::RoughnessToAlpha).  Each
   may be a float texture: then *alpha_tex = 1 + its index, the alphas are 0, and
   material.c's mat_point reads the texture at each hit (the same texture for u
   and v; anything else with a texture is anisotropic, refused by name).  prefix
   names a layer's parameters ("interface.", "conductor." of coatedconductor). */
static int microfacet_alphas_of(Parser *P, ParamList *pl, const char *file, int line,
                                const char *what, const char *prefix, float *alpha_u,
                                float *alpha_v, int *alpha_tex, int *remap_out)
{
    float u = 0, v = 0, r = 0;
    int remap, have_u, have_v, have_r, tu, tv, tr;
    char nu[48], nv[48], nr[48];
    snprintf(nu, sizeof nu, "%suroughness", prefix);
    snprintf(nv, sizeof nv, "%svroughness", prefix);
    snprintf(nr, sizeof nr, "%sroughness", prefix);
    if (!rough_param(P, pl, nu, &have_u, &u, &tu) || !rough_param(P, pl, nv, &have_v, &v, &tv))
        return 0;
    if (!have_u || !have_v) {
        if (!rough_param(P, pl, nr, &have_r, &r, &tr)) return 0;
        if (!have_u) { u = r; tu = tr; }
        if (!have_v) { v = r; tv = tr; }
    }
    if (!get_bool(P, pl, "remaproughness", 1, &remap)) return 0;
    *remap_out = remap;
    *alpha_tex = 0;
    if (tu >= 0 || tv >= 0) {
        if (tu != tv)
            return fail(P, file, line, "%s: u and v roughness from different sources (a texture "
                        "and a number, or two textures) is anisotropic roughness, valid pbrt-v4 "
                        "but not in the specnee subset", what);
        *alpha_tex = tu + 1;
        *alpha_u = *alpha_v = 0.0f;
        return 1;
    }
    if (!(u >= 0.0f && u <= 1e4f) || !(v >= 0.0f && v <= 1e4f))
        return fail(P, file, line, "%s: %s (%g, %g) must be within [0, 1e4]", what, nr, u, v);
    *alpha_u = remap ? sqrtf(u) : u;
    *alpha_v = remap ? sqrtf(v) : v;
    return 1;
}

/* The same for the unprefixed names ("roughness", "uroughness", "vroughness"). */
static int microfacet_alphas(Parser *P, ParamList *pl, const char *file, int line,
                             const char *what, float *alpha_u, float *alpha_v, int *alpha_tex,
                             int *remap_out)
{
    return microfacet_alphas_of(P, pl, file, line, what, "", alpha_u, alpha_v, alpha_tex,
                                remap_out);
}

/* Every value of a spectrum over 300-830 nm must satisfy lo < v (strict) or
   lo <= v (strict = 0), and be finite: else "file:line: ..." naming the first
   wavelength that fails.  p may be NULL (a default spectrum: the directive's line). */
static int check_spectrum_above(Parser *P, const Param *p, const char *file, int line,
                                const char *what, const Spectrum *sp, float lo, int strict)
{
    int nm;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
        float v = spec_get(sp, nm);
        if (!(strict ? v > lo : v >= lo) || !(v < 1e30f))
            return fail(P, p ? p->file : file, p ? p->line : line, "%s: value %g at %d nm "
                        "(need a finite value %s %g)", what, v, nm, strict ? ">" : ">=", lo);
    }
    return 1;
}

/* The slab between a layered material's coat and base (coateddiffuse,
   coatedconductor; layered.c): thickness, HG g, the walks' maxdepth and nsamples,
   each checked and reported at its own parameter's line, then stored in m. */
static int layer_slab(Parser *P, const char *what, const char *file, int line, float th,
                      const Param *pth, float g, const Param *pg, int md, const Param *pd,
                      int ns, const Param *pn, Material *m)
{
    if (!(th > 0.0f && th < 1e30f))
        return fail(P, pth ? pth->file : file, pth ? pth->line : line,
                    "%s: \"float thickness\" %g must be finite and > 0", what, th);
    if (!(g > -1.0f && g < 1.0f))
        return fail(P, pg ? pg->file : file, pg ? pg->line : line,
                    "%s: \"float g\" %g must be within (-1, 1)", what, g);
    if (md < 1)
        return fail(P, pd ? pd->file : file, pd ? pd->line : line,
                    "%s: \"integer maxdepth\" %d must be >= 1", what, md);
    if (ns < 1)
        return fail(P, pn ? pn->file : file, pn ? pn->line : line,
                    "%s: \"integer nsamples\" %d must be >= 1", what, ns);
    m->thickness = th;
    m->hg_g = g;
    m->maxdepth = md;
    m->nsamples = ns;
    return 1;
}

/* The slab's single-scattering albedo (0 by default), within [0, 1] at every nm. */
static int layer_albedo(Parser *P, Param *pa, const char *what, const char *file, int line,
                        Material *m)
{
    int nm;
    if (!unit_spectrum_param(P, pa, &m->albedo, 0.0f)) return 0;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
        if (!(spec_get(&m->albedo, nm) >= 0.0f && spec_get(&m->albedo, nm) <= 1.0f))
            return fail(P, pa ? pa->file : file, pa ? pa->line : line,
                        "%s: \"albedo\" %g at %d nm must be within [0, 1]", what,
                        spec_get(&m->albedo, nm), nm);
    return 1;
}

static int material_from_params(Parser *P, const char *type, ParamList *pl, const char *file,
                                int line, Material *m, const char *dir)
{
    char what[192];
    memset(m, 0, sizeof *m);
    spec_const(&m->eta, 1.0f);
    snprintf(what, sizeof what, "%s \"%s\"", dir, type);
    if (!strcmp(type, "interface") || !type[0] || !strcmp(type, "none")) {
        /* pbrt-v4 (materials.cpp): no material, only the boundary between two media;
           "" and "none" are its deprecated spellings.  Rays cross it (render.c) */
        m->type = MAT_INTERFACE;
        return params_check_unused(P, pl, what, "", NULL);
    }
    if (!strcmp(type, "diffuse")) {
        Param *p = find_spectrum_param(pl, "reflectance");
        Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
        m->type = MAT_DIFFUSE;
        if (pt) {
            /* "texture reflectance": evaluated at each hit (texture.c), clamped to [0, 1] */
            int ti = texture_lookup(P, pt, 0);
            if (ti < 0) return 0;
            m->reflectance_tex = ti + 1;
            spec_const(&m->reflectance, 0.5f);        /* (not read) */
        } else if (p) {
            if (!param_spectrum(P, p, SPEC_ALBEDO, &m->reflectance, NULL)) return 0;
            /* a reflectance must lie in [0,1]; 1e-4 of slack absorbs the rounding of
               an RGB upsampling of (1,1,1) */
            if (!check_unit_spectrum(P, p, &m->reflectance)) return 0;
        } else {
            spec_const(&m->reflectance, 0.5f);        /* pbrt-v4's default */
        }
        return params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                                   "texture reflectance", "displacement normalmap");
    }
    if (!strcmp(type, "fluorescent")) {
        /* specnee extension (docs/FLUORESCENCE.md, docs/conventions.md section 6):
           a diffuse fluorescent layer, F2 */
        Param *pr = find_spectrum_param(pl, "reflectance");
        Param *pa = find_spectrum_param(pl, "excitation"), *pe = find_spectrum_param(pl, "emission");
        Param *pq = param_find(pl, PT_FLOAT, "quantumyield");
        int nm;
        m->type = MAT_FLUORESCENT;
        if (!pa || !pe)
            return fail(P, file, line, "%s \"fluorescent\": needs \"spectrum excitation\" "
                        "and \"spectrum emission\"", dir);
        if (!unit_spectrum_param(P, pr, &m->reflectance, 0.5f)) return 0;
        if (!param_spectrum(P, pa, SPEC_UNBOUNDED, &m->excitation, NULL)) return 0;
        if (!check_unit_spectrum(P, pa, &m->excitation)) return 0;
        if (!param_spectrum(P, pe, SPEC_UNBOUNDED, &m->emission, NULL)) return 0;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
            if (!(spec_get(&m->emission, nm) >= 0.0f))
                return fail(P, pe->file, pe->line, "\"spectrum emission\": negative (%g) at %d nm",
                            spec_get(&m->emission, nm), nm);
        if (!get_float(P, pl, "quantumyield", 1.0f, &m->qyield)) return 0;
        if (!(m->qyield >= 0.0f && m->qyield <= 1.0f))
            return fail(P, pq ? pq->file : file, pq ? pq->line : line,
                        "\"float quantumyield\": %g is outside [0,1] (photons re-emitted per "
                        "photon absorbed)", m->qyield);
        if (!fluor_prepare(m))
            return fail(P, pe->file, pe->line, "\"spectrum emission\": zero everywhere in %d-%d nm",
                        SPEC_UV_MIN, SPEC_MAX);
        return params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                                   "spectrum excitation, spectrum emission, float quantumyield", "");
    }
    if (!strcmp(type, "dielectric")) {
        Param *pf = param_find(pl, PT_FLOAT, "eta");
        Param *pa = param_find(pl, PT_FLOAT, "cauchyA"), *pb = param_find(pl, PT_FLOAT, "cauchyB");
        float u, v, r, A = 0, B = 0;
        int remap, i, have_u, have_v;
        m->type = MAT_DIELECTRIC;
        if ((pa != NULL) != (pb != NULL))
            return fail(P, file, line, "%s \"dielectric\": \"float cauchyA\" and "
                        "\"float cauchyB\" must be given together", dir);
        if (pa) {
            /* specnee extension: n(lambda) = A + B / lambda^2, lambda in um */
            Param *ps = find_spectrum_param(pl, "eta");
            if (pf || ps)
                return fail(P, file, line, "%s \"dielectric\": give either eta or "
                            "cauchyA/cauchyB, not both", dir);
            if (!get_float(P, pl, "cauchyA", 0, &A) || !get_float(P, pl, "cauchyB", 0, &B))
                return 0;
            if (!(A > 0.0f) || !(B >= 0.0f) || !(B < 1.0f))
                return fail(P, file, line, "%s \"dielectric\": need cauchyA > 0 and "
                            "0 <= cauchyB < 1 um^2", dir);
            for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++) *spec_at(&m->eta, i) = cauchy_eta(A, B, (float)i);
            m->cauchy_a = A;
            m->cauchy_b = B;
        } else if (pf) {
            /* pbrt-v4: a float eta is a constant index (no dispersion) */
            float eta;
            if (!get_float(P, pl, "eta", 1.5f, &eta)) return 0;
            if (!(eta > 0.0f))
                return fail(P, pf->file, pf->line, "\"float eta\": must be > 0");
            spec_const(&m->eta, eta);
        } else {
            Param *ps = find_spectrum_param(pl, "eta");
            if (ps) {
                if (!param_spectrum(P, ps, SPEC_UNBOUNDED, &m->eta, NULL)) return 0;
                for (i = 0; i < SPEC_N; i++) {
                    if (!(m->eta.v[i] >= 0.0f && m->eta.v[i] < 100.0f))
                        return fail(P, ps->file, ps->line, "\"spectrum eta\": value %g at %d "
                                    "nm is not an index of refraction", m->eta.v[i], SPEC_MIN + i);
                    if (m->eta.v[i] == 0.0f) m->eta.v[i] = 1.0f;   /* pbrt: eta 0 means 1 */
                }
                for (i = 0; i < SPEC_UV_N; i++) {          /* the UV extension, same rule */
                    if (!(m->eta.uv[i] >= 0.0f && m->eta.uv[i] < 100.0f))
                        return fail(P, ps->file, ps->line, "\"spectrum eta\": value %g at %d "
                                    "nm is not an index of refraction", m->eta.uv[i], SPEC_UV_MIN + i);
                    if (m->eta.uv[i] == 0.0f) m->eta.uv[i] = 1.0f;
                }
            } else {
                spec_const(&m->eta, 1.5f);            /* pbrt-v4's default */
            }
        }
        /* pbrt-v4: u/vroughness default to "roughness", which defaults to 0 */
        have_u = param_find(pl, PT_FLOAT, "uroughness") != NULL;
        have_v = param_find(pl, PT_FLOAT, "vroughness") != NULL;
        if (!get_float(P, pl, "uroughness", 0, &u) || !get_float(P, pl, "vroughness", 0, &v))
            return 0;
        if (!have_u || !have_v) {
            if (!get_float(P, pl, "roughness", 0, &r)) return 0;
            if (!have_u) u = r;
            if (!have_v) v = r;
        }
        if (!get_bool(P, pl, "remaproughness", 1, &remap)) return 0;
        if (!params_check_unused(P, pl, what, "float eta, spectrum eta, float roughness, "
                                 "float uroughness, float vroughness, bool remaproughness, "
                                 "float cauchyA, float cauchyB", "displacement normalmap"))
            return 0;
        if (u != v)
            return fail(P, file, line, "%s \"dielectric\": anisotropic roughness (%g, %g) "
                        "is valid pbrt-v4 but not in the specnee subset", dir, u, v);
        if (!(u >= 0.0f && u <= 1e4f))
            return fail(P, file, line, "%s \"dielectric\": roughness must be >= 0", dir);
        /* pbrt-v4 TrowbridgeReitzDistribution::RoughnessToAlpha: alpha = sqrt(roughness) */
        m->alpha = remap ? sqrtf(u) : u;
        m->dispersive = !spec_is_constant(&m->eta);
        return 1;
    }
    if (!strcmp(type, "conductor")) {
        /* pbrt-v4 ConductorMaterial (conductor.c): eta and k, or a reflectance that
           stands for them; Cu by default */
        Param *pe = find_spectrum_param(pl, "eta"), *pk = find_spectrum_param(pl, "k");
        Param *pr = find_spectrum_param(pl, "reflectance");
        Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
        int nm;
        m->type = MAT_CONDUCTOR;
        if (!microfacet_alphas(P, pl, file, line, what, &m->alpha, &m->alpha_t, &m->alpha_tex,
                               &m->remap))
            return 0;
        if (!params_check_unused(P, pl, what, "spectrum eta, spectrum k, spectrum reflectance, "
                                 "rgb reflectance, texture reflectance, float roughness, "
                                 "float uroughness, float vroughness, texture roughness, "
                                 "texture uroughness, texture vroughness, bool remaproughness",
                                 "displacement normalmap"))
            return 0;
        if ((pr || pt) && (pe || pk))
            return fail(P, file, line, "%s: give either \"reflectance\" or \"eta\" and \"k\", "
                        "not both (pbrt-v4 refuses it too)", what);
        if (pt) {
            /* "texture reflectance": r read at each hit (material.c mat_point), eta = 1
               and k from r there (conductor.c) */
            int ti = texture_lookup(P, pt, 0);
            if (ti < 0) return 0;
            m->reflectance_tex = ti + 1;
            spec_const(&m->eta, 1.0f);
            spec_const(&m->k, 0.0f);                  /* (not read) */
        } else if (pr) {
            /* pbrt-v4: r clamped to [0, 0.9999], eta = 1, k = 2 sqrt(r) / sqrt(1 - r),
               which makes the normal-incidence reflectance ((eta-1)^2 + k^2) /
               ((eta+1)^2 + k^2) = k^2 / (4 + k^2) exactly r */
            if (!param_spectrum(P, pr, SPEC_ALBEDO, &m->reflectance, NULL)) return 0;
            if (!check_unit_spectrum(P, pr, &m->reflectance)) return 0;
            spec_const(&m->eta, 1.0f);
            for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
                double r = spec_get(&m->reflectance, nm);
                if (r > 0.9999) r = 0.9999;
                *spec_at(&m->k, nm) = conductor_k_of_reflectance(r);
            }
        } else {
            if (pe) { if (!param_spectrum(P, pe, SPEC_UNBOUNDED, &m->eta, NULL)) return 0; }
            else spec_named(&m->eta, "metal-Cu-eta");
            if (pk) { if (!param_spectrum(P, pk, SPEC_UNBOUNDED, &m->k, NULL)) return 0; }
            else spec_named(&m->k, "metal-Cu-k");
            if (!check_spectrum_above(P, pe, file, line, "\"spectrum eta\" of a conductor",
                                      &m->eta, 0.0f, 1) ||
                !check_spectrum_above(P, pk, file, line, "\"spectrum k\" of a conductor",
                                      &m->k, 0.0f, 0))
                return 0;
        }
        if (m->alpha != m->alpha_t)
            return fail(P, file, line, "%s: anisotropic roughness (u %g, v %g after the remap) "
                        "is valid pbrt-v4 but not in the specnee subset (its axes follow the "
                        "surface's dp/du, which specnee does not have)", what, m->alpha,
                        m->alpha_t);
        return 1;
    }
    if (!strcmp(type, "coateddiffuse")) {
        /* pbrt-v4 CoatedDiffuseMaterial (layered.c): a dielectric coat (float eta,
           roughness) over a Lambertian base (reflectance 0.5), a slab of thickness
           0.01 between them with a medium of albedo 0 and HG g 0; maxdepth 10 and
           nsamples 1 random walks */
        Param *pr = find_spectrum_param(pl, "reflectance"), *pa = find_spectrum_param(pl, "albedo");
        Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
        Param *pe = find_spectrum_param(pl, "eta"), *pf = param_find(pl, PT_FLOAT, "eta");
        Param *pth = param_find(pl, PT_FLOAT, "thickness"), *pg = param_find(pl, PT_FLOAT, "g");
        Param *pd = param_find(pl, PT_INTEGER, "maxdepth"), *pn = param_find(pl, PT_INTEGER, "nsamples");
        float eta, th, g;
        int md, ns, given;
        m->type = MAT_COATED_DIFFUSE;
        if (pe && !pf)
            return fail(P, pe->file, pe->line, "%s: a spectral \"eta\" is valid pbrt-v4 (it "
                        "terminates the secondary wavelengths) but not in the specnee subset: "
                        "give \"float eta\"", what);
        if (!microfacet_alphas(P, pl, file, line, what, &m->alpha, &m->alpha_t, &m->alpha_tex,
                               &m->remap))
            return 0;
        if (pt) {
            /* "texture reflectance": the base's R read at each hit (mat_point) */
            int ti = texture_lookup(P, pt, 0);
            if (ti < 0) return 0;
            m->reflectance_tex = ti + 1;
        }
        if (!get_float(P, pl, "eta", 1.5f, &eta) || !get_float(P, pl, "thickness", 0.01f, &th) ||
            !get_float(P, pl, "g", 0.0f, &g) || !get_int(P, pl, "maxdepth", 10, &md, &given) ||
            !get_int(P, pl, "nsamples", 1, &ns, &given))
            return 0;
        if (!params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                                 "texture reflectance, float eta, float roughness, "
                                 "float uroughness, float vroughness, texture roughness, "
                                 "texture uroughness, texture vroughness, "
                                 "bool remaproughness, float thickness, spectrum albedo, "
                                 "rgb albedo, float g, integer maxdepth, integer nsamples",
                                 "displacement normalmap"))
            return 0;
        if (m->alpha != m->alpha_t)
            return fail(P, file, line, "%s: anisotropic roughness (u %g, v %g after the remap) "
                        "is valid pbrt-v4 but not in the specnee subset", what, m->alpha, m->alpha_t);
        if (!(eta > 0.0f && eta < 100.0f))
            return fail(P, pf ? pf->file : file, pf ? pf->line : line,
                        "%s: \"float eta\" %g is not an index of refraction", what, eta);
        spec_const(&m->eta, eta);
        if (!layer_slab(P, what, file, line, th, pth, g, pg, md, pd, ns, pn, m)) return 0;
        if (!unit_spectrum_param(P, pt ? NULL : pr, &m->reflectance, 0.5f)) return 0;
        if (!layer_albedo(P, pa, what, file, line, m)) return 0;
        return 1;
    }
    if (!strcmp(type, "coatedconductor")) {
        /* pbrt-v4 CoatedConductorMaterial (layered.c section 5): a dielectric coat
           ("interface." eta 1.5, roughness 0) over a conductor ("conductor." eta and
           k, Cu by default, or a "reflectance"; roughness 0), a slab of thickness
           0.01 with a medium of albedo 0 and HG g 0; maxdepth 10, nsamples 1 */
        Param *pe = find_spectrum_param(pl, "conductor.eta"), *pk = find_spectrum_param(pl, "conductor.k");
        Param *pr = find_spectrum_param(pl, "reflectance"), *pa = find_spectrum_param(pl, "albedo");
        Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
        Param *pie = find_spectrum_param(pl, "interface.eta");
        Param *pf = param_find(pl, PT_FLOAT, "interface.eta");
        Param *pth = param_find(pl, PT_FLOAT, "thickness"), *pg = param_find(pl, PT_FLOAT, "g");
        Param *pd = param_find(pl, PT_INTEGER, "maxdepth"), *pn = param_find(pl, PT_INTEGER, "nsamples");
        float eta, th, g, cat;
        int md, ns, given, nm, remap2;
        m->type = MAT_COATED_CONDUCTOR;
        if (pie && !pf)
            return fail(P, pie->file, pie->line, "%s: a spectral \"interface.eta\" is valid "
                        "pbrt-v4 (it terminates the secondary wavelengths) but not in the specnee "
                        "subset: give \"float interface.eta\"", what);
        if (!microfacet_alphas_of(P, pl, file, line, what, "interface.", &m->alpha, &m->alpha_t,
                                  &m->alpha_tex, &m->remap) ||
            !microfacet_alphas_of(P, pl, file, line, what, "conductor.", &m->cond_alpha, &cat,
                                  &m->cond_alpha_tex, &remap2))
            return 0;
        if (!get_float(P, pl, "interface.eta", 1.5f, &eta) ||
            !get_float(P, pl, "thickness", 0.01f, &th) || !get_float(P, pl, "g", 0.0f, &g) ||
            !get_int(P, pl, "maxdepth", 10, &md, &given) || !get_int(P, pl, "nsamples", 1, &ns, &given))
            return 0;
        if (!params_check_unused(P, pl, what, "float interface.eta, float interface.roughness, "
                                 "float interface.uroughness, float interface.vroughness, "
                                 "texture interface.roughness, texture interface.uroughness, "
                                 "texture interface.vroughness, spectrum conductor.eta, "
                                 "spectrum conductor.k, spectrum reflectance, rgb reflectance, "
                                 "texture reflectance, float conductor.roughness, "
                                 "float conductor.uroughness, float conductor.vroughness, "
                                 "texture conductor.roughness, texture conductor.uroughness, "
                                 "texture conductor.vroughness, bool remaproughness, "
                                 "float thickness, spectrum albedo, rgb albedo, float g, "
                                 "integer maxdepth, integer nsamples", "displacement normalmap"))
            return 0;
        if (m->alpha != m->alpha_t || m->cond_alpha != cat)
            return fail(P, file, line, "%s: anisotropic roughness (interface u %g v %g, conductor "
                        "u %g v %g after the remap) is valid pbrt-v4 but not in the specnee subset",
                        what, m->alpha, m->alpha_t, m->cond_alpha, cat);
        if ((pr || pt) && (pe || pk))
            return fail(P, file, line, "%s: give either \"reflectance\" or \"conductor.eta\" and "
                        "\"conductor.k\", not both (pbrt-v4 refuses it too)", what);
        if (!(eta > 0.0f && eta < 100.0f))
            return fail(P, pf ? pf->file : file, pf ? pf->line : line,
                        "%s: \"float interface.eta\" %g is not an index of refraction", what, eta);
        spec_const(&m->eta, eta);
        if (!layer_slab(P, what, file, line, th, pth, g, pg, md, pd, ns, pn, m)) return 0;
        if (!layer_albedo(P, pa, what, file, line, m)) return 0;
        if (pt) {
            /* "texture reflectance": r read at each hit (mat_point), n and k from it
               there (layered.c layer_init) */
            int ti = texture_lookup(P, pt, 0);
            if (ti < 0) return 0;
            m->reflectance_tex = ti + 1;
            spec_const(&m->cond_eta, 1.0f);
            spec_const(&m->k, 0.0f);                  /* (not read) */
        } else if (pr) {
            /* as the conductor's: r clamped to [0, 0.9999], n = 1, k = 2 sqrt(r) / sqrt(1 - r) */
            if (!param_spectrum(P, pr, SPEC_ALBEDO, &m->reflectance, NULL)) return 0;
            if (!check_unit_spectrum(P, pr, &m->reflectance)) return 0;
            spec_const(&m->cond_eta, 1.0f);
            for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
                double r = spec_get(&m->reflectance, nm);
                if (r > 0.9999) r = 0.9999;
                *spec_at(&m->k, nm) = conductor_k_of_reflectance(r);
            }
        } else {
            if (pe) { if (!param_spectrum(P, pe, SPEC_UNBOUNDED, &m->cond_eta, NULL)) return 0; }
            else spec_named(&m->cond_eta, "metal-Cu-eta");
            if (pk) { if (!param_spectrum(P, pk, SPEC_UNBOUNDED, &m->k, NULL)) return 0; }
            else spec_named(&m->k, "metal-Cu-k");
            if (!check_spectrum_above(P, pe, file, line, "\"spectrum conductor.eta\" of a "
                                      "coatedconductor", &m->cond_eta, 0.0f, 1) ||
                !check_spectrum_above(P, pk, file, line, "\"spectrum conductor.k\" of a "
                                      "coatedconductor", &m->k, 0.0f, 0))
                return 0;
        }
        return 1;
    }
    if (!strcmp(type, "thindielectric")) {
        /* pbrt-v4 ThinDielectricMaterial (material.c): "float eta" or "spectrum eta",
           1.5 by default; no roughness */
        Param *pf = param_find(pl, PT_FLOAT, "eta"), *ps = find_spectrum_param(pl, "eta");
        m->type = MAT_THIN_DIELECTRIC;
        if (!params_check_unused(P, pl, what, "float eta, spectrum eta", "displacement normalmap"))
            return 0;
        if (pf) {
            float eta;
            if (!get_float(P, pl, "eta", 1.5f, &eta)) return 0;
            spec_const(&m->eta, eta);
        } else if (ps) {
            if (!param_spectrum(P, ps, SPEC_UNBOUNDED, &m->eta, NULL)) return 0;
        } else {
            spec_const(&m->eta, 1.5f);                /* pbrt-v4's default */
        }
        /* pbrt-v4 reads an eta of 0 as 1 (no interface); negative is meaningless */
        if (!check_spectrum_above(P, pf ? pf : ps, file, line, "\"eta\" of a thindielectric",
                                  &m->eta, 0.0f, 0))
            return 0;
        {
            int nm;
            for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
                if (spec_get(&m->eta, nm) == 0.0f) *spec_at(&m->eta, nm) = 1.0f;
        }
        return 1;
    }
    if (!strcmp(type, "diffusetransmission")) {
        /* pbrt-v4 DiffuseTransmissionMaterial (material.c): R and T (0.25 each by
           default), both times "scale" and clamped to [0, 1] */
        Param *pr = find_spectrum_param(pl, "reflectance"), *pt = find_spectrum_param(pl, "transmittance");
        Param *psc = param_find(pl, PT_FLOAT, "scale");
        float scale, maxr = 0.0f, maxt = 0.0f;
        int nm;
        m->type = MAT_DIFFUSE_TRANSMISSION;
        if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
        if (!params_check_unused(P, pl, what, "spectrum reflectance, rgb reflectance, "
                                 "spectrum transmittance, rgb transmittance, float scale",
                                 "displacement normalmap"))
            return 0;
        if (!unit_spectrum_param(P, pr, &m->reflectance, 0.25f)) return 0;
        if (!unit_spectrum_param(P, pt, &m->transmittance, 0.25f)) return 0;
        if (!(scale >= 0.0f))
            return fail(P, psc ? psc->file : file, psc ? psc->line : line,
                        "\"float scale\": %g must be >= 0", scale);
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
            float *r = spec_at(&m->reflectance, nm), *t = spec_at(&m->transmittance, nm);
            *r = fminf(1.0f, scale * *r);
            *t = fminf(1.0f, scale * *t);
            if (*r > maxr) maxr = *r;
            if (*t > maxt) maxt = *t;
        }
        m->p_reflect = maxr + maxt > 0.0f ? maxr / (maxr + maxt) : 0.5f;
        return 1;
    }
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

/* pbrt-v4 normalises an RGB illuminant by its colour space's illuminant:
   Le = scale * L / sum ybar D65.  lights.c divides by sum ybar L, so every light
   with an rgb spectrum gets scale * sum ybar L / sum ybar D65 (area, infinite
   and delta lights alike). */
static float rgb_illuminant_scale(const Spectrum *L, float scale)
{
    Spectrum d65;
    double xyz_l[3], xyz_d[3];
    if (!spec_named(&d65, "stdillum-D65")) return scale;
    spec_to_xyz(L, (float)SPEC_MIN, (float)SPEC_MAX, xyz_l);
    spec_to_xyz(&d65, (float)SPEC_MIN, (float)SPEC_MAX, xyz_d);
    return xyz_d[1] > 0.0 ? (float)(scale * (xyz_l[1] / xyz_d[1])) : scale;
}

static int area_light_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    AreaLightDesc al;
    Param *p;
    int rgb_illum = 0;
    if (strcmp(type, "diffuse") != 0)
        return fail(P, file, line, "AreaLightSource \"%s\": unknown area light type "
                    "(pbrt-v4 has only \"diffuse\")", type);
    memset(&al, 0, sizeof al);
    p = find_spectrum_param(pl, "L");
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &al.L, &rgb_illum)) return 0;
    } else if (!spec_named(&al.L, "stdillum-D65")) {  /* the colour space's illuminant */
        return fail(P, file, line, "AreaLightSource: the built-in spectrum stdillum-D65 is missing");
    }
    if (!get_float(P, pl, "scale", 1.0f, &al.scale)) return 0;
    if (!get_bool(P, pl, "twosided", 0, &al.twosided)) return 0;
    if (!params_check_unused(P, pl, "AreaLightSource \"diffuse\"",
                             "spectrum L, rgb L, blackbody L, float scale, bool twosided",
                             "power filename alpha"))
        return 0;
    if (!(al.scale >= 0.0f))
        return fail(P, file, line, "AreaLightSource: \"float scale\" must be >= 0");
    {
        int i;
        for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
            if (!(spec_get(&al.L, i) >= 0.0f))
                return fail(P, p ? p->file : file, p ? p->line : line,
                            "AreaLightSource: L is negative at %d nm", i);
    }
    {
        /* A spectrum with no luminance in 400-700 nm (an ultraviolet lamp) cannot be
           normalised to Y = scale: lights.c reads it as absolute spectral radiance
           times scale (docs/conventions.md section 4, docs/FLUORESCENCE.md section 6). */
        double vis = 0.0, any = 0.0;
        int nm;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
            float xyz[3];
            any += spec_get(&al.L, nm);
            if (nm < (int)LAMBDA_LO || nm > (int)LAMBDA_HI) continue;
            cie_xyz((float)nm, xyz);
            vis += (double)xyz[1] * spec_get(&al.L, nm);
        }
        if (!(any > 0.0))
            return fail(P, p ? p->file : file, p ? p->line : line,
                        "AreaLightSource: spectrum L is zero everywhere in %d-%d nm",
                        SPEC_UV_MIN, SPEC_MAX);
        if (!(vis > 0.0))
            fprintf(stderr, "%s:%d: note: AreaLightSource: L has no luminance in 400-700 nm; "
                    "read as absolute spectral radiance times scale (docs/conventions.md)\n",
                    p ? p->file : file, p ? p->line : line);
    }
    if (rgb_illum) al.scale = rgb_illuminant_scale(&al.L, al.scale);
    if (!grow((void **)&P->lights, &P->cap_lights, P->n_lights + 1, sizeof(AreaLightDesc)))
        return oom(P, file, line);
    P->lights[P->n_lights] = al;
    P->gs.area_light = P->n_lights++;
    return 1;
}

/* LightSource "infinite" (infinite.c): constant (L, scale, illuminance) or an
   image map (filename: a PFM in pbrt-v4's equal-area octahedral layout).  The
   CTM is the light's frame.  pbrt-v4's normalisation: L is divided by its
   luminance (an rgb L by D65's), a map's texels by D65's, so a constant light or
   a white texel has luminance scale; "illuminance" E_v (lux) then multiplies
   scale by E_v / k_e, k_e the illuminance the light would give an upward-facing
   point (+z of the light's frame) without it: pi for a constant light, and for a
   map pbrt-v4's sum over the upper hemisphere's texels of Y(rgb) cos(theta) 2 pi
   / res^2 (pbrt-v4 lights.cpp, reproduced as it is). */
/* The one point "point3 name" [x y z] (def when absent). */
static int get_point3(Parser *P, ParamList *pl, const char *name, const double def[3], double out[3])
{
    Param *p = param_find(pl, PT_POINT3, name);
    int k;
    for (k = 0; k < 3; k++) out[k] = def[k];
    if (!p) return 1;
    if (p->n_num != 3)
        return fail(P, p->file, p->line, "\"point3 %s\": expected 3 values, got %d", name, p->n_num);
    for (k = 0; k < 3; k++) {
        if (!isfinite(p->num[k]))
            return fail(P, p->file, p->line, "\"point3 %s\": not a finite number", name);
        out[k] = p->num[k];
    }
    return 1;
}

/* A number that must be finite: a file:line error naming it otherwise. */
static int check_finite(Parser *P, ParamList *pl, const char *what, const char *name, float v,
                        const char *file, int line)
{
    Param *p = param_find(pl, PT_FLOAT, name);
    if (isfinite(v)) return 1;
    return fail(P, p ? p->file : file, p ? p->line : line, "%s: \"float %s\" must be a finite "
                "number", what, name);
}

/* LightSource "point", "spot" and "distant" (delta.c), with pbrt-v4's meaning
   (lights.cpp, PointLight/SpotLight/DistantLight::Create).  The spectrum (I for
   point and spot, L for distant; D65 when absent) is normalised as an area
   light's is: lights.c divides it by its luminance (an rgb one by D65's), so that
   a point light of scale 1 has luminous intensity 1 and a distant light of scale
   1 gives illuminance 1 to a surface facing it.  Then
     point    "power" Phi (> 0): scale *= Phi / (4 pi)
     spot     "power" Phi: scale *= Phi / (2 pi ((1 - cos_start) + (cos_start - cos_end) / 2))
     distant  "illuminance" E (> 0): scale *= E
   (a power or illuminance <= 0 is pbrt-v4's "not given").  Positions and
   directions are in the light's frame, the CTM at the LightSource: a point light
   sits at CTM(from), a spot's axis is CTM(to - from), a distant light arrives
   from CTM(from - to).  A spot's cone is round in its own frame: under a CTM
   that stretches it, it is elliptic in the world, as in pbrt-v4. */
static int delta_light_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const double zero[3] = { 0, 0, 0 }, zplus[3] = { 0, 0, 1 };
    Scene *s = P->s;
    Emitter *em;
    DeltaLight d;
    Param *p;
    Spectrum L;
    double from[3], to[3];
    float scale, power = -1.0f, cone = 30.0f, cdelta = 5.0f;
    int rgb_illum = 0, i;
    const char *sname = !strcmp(type, "distant") ? "L" : "I";
    char what[64];
    snprintf(what, sizeof what, "LightSource \"%s\"", type);
    memset(&d, 0, sizeof d);
    d.type = !strcmp(type, "point") ? DELTA_POINT : !strcmp(type, "spot") ? DELTA_SPOT : DELTA_DISTANT;
    d.file = file;
    d.line = line;
    p = find_spectrum_param(pl, sname);
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &L, &rgb_illum)) return 0;
    } else if (!spec_named(&L, "stdillum-D65")) {
        return fail(P, file, line, "LightSource: the built-in spectrum stdillum-D65 is missing");
    }
    if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
    if (!get_point3(P, pl, "from", zero, from)) return 0;
    if (d.type != DELTA_POINT && !get_point3(P, pl, "to", zplus, to)) return 0;
    if (d.type == DELTA_DISTANT) {
        if (!get_float(P, pl, "illuminance", -1.0f, &power)) return 0;
        if (!params_check_unused(P, pl, what, "spectrum L, rgb L, blackbody L, float scale, "
                                 "float illuminance, point3 from, point3 to", NULL))
            return 0;
    } else {
        if (!get_float(P, pl, "power", -1.0f, &power)) return 0;
        if (d.type == DELTA_SPOT) {
            if (!get_float(P, pl, "coneangle", 30.0f, &cone)) return 0;
            if (!get_float(P, pl, "conedeltaangle", 5.0f, &cdelta)) return 0;
            if (!params_check_unused(P, pl, what, "spectrum I, rgb I, blackbody I, float scale, "
                                     "float power, float coneangle, float conedeltaangle, "
                                     "point3 from, point3 to", NULL))
                return 0;
        } else if (!params_check_unused(P, pl, what, "spectrum I, rgb I, blackbody I, float scale, "
                                        "float power, point3 from", NULL)) {
            return 0;
        }
    }
    if (!check_finite(P, pl, what, "scale", scale, file, line) ||
        !check_finite(P, pl, what, d.type == DELTA_DISTANT ? "illuminance" : "power", power, file, line) ||
        !check_finite(P, pl, what, "coneangle", cone, file, line) ||
        !check_finite(P, pl, what, "conedeltaangle", cdelta, file, line))
        return 0;
    if (!(scale >= 0.0f)) return fail(P, file, line, "%s: \"float scale\" must be >= 0", what);
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
        if (!(spec_get(&L, i) >= 0.0f))
            return fail(P, p ? p->file : file, p ? p->line : line, "%s: %s is negative at %d nm",
                        what, sname, i);
    if (rgb_illum) scale = rgb_illuminant_scale(&L, scale);
    d.p = xf_point(&P->gs.ctm, v3((float)from[0], (float)from[1], (float)from[2]));  /* point, spot */
    if (d.type == DELTA_POINT) {
        if (power > 0.0f) scale = (float)(scale * power / (4.0 * SPECNEE_PI));
    } else {
        Vec3 dir = v3((float)(to[0] - from[0]), (float)(to[1] - from[1]), (float)(to[2] - from[2]));
        if (!(v3_dot(dir, dir) > 0.0f))
            return fail(P, file, line, "%s: \"from\" and \"to\" are the same point: no direction", what);
        dir = v3_norm(xf_vector(&P->gs.ctm, dir));
        if (!(v3_dot(dir, dir) > 0.0f) || !isfinite(dir.x + dir.y + dir.z))
            return fail(P, file, line, "%s: the transform leaves no direction", what);
        if (d.type == DELTA_DISTANT) {
            d.w = v3_neg(dir);                           /* towards the light */
            if (power > 0.0f) scale *= power;
        } else {
            /* the cone is round in the light's frame (pbrt-v4): keep the inverse
               CTM for directions and the axis there; "stretched" unless the CTM is a
               rotation times a uniform scale (three axes equally long, at right angles) */
            Vec3 ax = xf_vector(&P->gs.ctm, v3(1, 0, 0)), ay = xf_vector(&P->gs.ctm, v3(0, 1, 0));
            Vec3 az = xf_vector(&P->gs.ctm, v3(0, 0, 1));
            float lx = v3_len(ax), ly = v3_len(ay), lz = v3_len(az), tol = 1e-4f * lx;
            double ts, tc;
            int a, b;
            d.stretched = fabsf(lx - ly) > tol || fabsf(lx - lz) > tol || fabsf(v3_dot(ax, ay)) > tol * lx ||
                          fabsf(v3_dot(ax, az)) > tol * lx || fabsf(v3_dot(ay, az)) > tol * lx;
            for (a = 0; a < 3; a++)
                for (b = 0; b < 3; b++) d.obj_from_world[3 * a + b] = (float)P->gs.ctm.inv[a][b];
            d.axis_obj = v3_norm(v3((float)(to[0] - from[0]), (float)(to[1] - from[1]),
                                    (float)(to[2] - from[2])));
            if (!(cone > 0.0f && cone <= 180.0f))
                return fail_param(P, pl, "coneangle", file, line, "%s: \"float coneangle\" %g must be in (0, 180] degrees",
                            what, cone);
            if (!(cdelta >= 0.0f))
                return fail_param(P, pl, "conedeltaangle", file, line, "%s: \"float conedeltaangle\" %g must be >= 0", what, cdelta);
            if (cdelta > cone)
                fprintf(stderr, "%s:%d: note: %s: conedeltaangle %g > coneangle %g; as in pbrt-v4 "
                        "the falloff starts at |coneangle - conedeltaangle| = %g degrees\n",
                        file, line, what, cdelta, cone, fabs((double)cone - cdelta));
            d.w = dir;
            tc = (double)cone * SPECNEE_PI / 180.0;
            ts = ((double)cone - cdelta) * SPECNEE_PI / 180.0;
            d.cos_end = (float)cos(tc);
            d.cos_start = (float)cos(ts);
            if (power > 0.0f)
                scale = (float)(scale * power / (2.0 * SPECNEE_PI * ((1.0 - d.cos_start) +
                                                                    (d.cos_start - d.cos_end) / 2.0)));
        }
    }
    if (!isfinite(scale))
        return fail(P, file, line, "%s: scale x power is not a finite number", what);
    if (!grow((void **)&s->emitters, &P->cap_emit, s->n_emitters + 1, sizeof(Emitter)))
        return oom(P, file, line);
    em = &s->emitters[s->n_emitters++];
    memset(em, 0, sizeof *em);
    em->shape = -1;
    em->delta = d;
    em->L = L;
    em->scale = scale;
    return 1;
}

static int light_source_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const char *const pbrt_types[] = { "goniometric", "projection", NULL };
    Scene *s = P->s;
    Emitter *em;
    InfiniteLight *inf;
    Param *p, *portal;
    const char *fn = NULL;
    float scale, ev;
    int rgb_illum = 0, i;
    Spectrum L;
    if (!strcmp(type, "point") || !strcmp(type, "spot") || !strcmp(type, "distant"))
        return delta_light_directive(P, type, pl, file, line);
    if (strcmp(type, "infinite") != 0) {
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i]))
                return fail(P, file, line, "LightSource \"%s\" is valid pbrt-v4 but not in the "
                            "specnee subset (infinite, point, spot, distant)", type);
        return fail(P, file, line, "LightSource \"%s\": unknown light type", type);
    }
    p = find_spectrum_param(pl, "L");
    if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
    if (!get_float(P, pl, "illuminance", -1.0f, &ev)) return 0;
    if (!get_string(P, pl, "filename", &fn)) return 0;
    portal = param_find(pl, PT_POINT3, "portal");
    if (portal)
        return fail(P, portal->file, portal->line, "LightSource \"infinite\": \"point3 portal\" "
                    "is valid pbrt-v4 but not in the specnee subset");
    if (p && fn)
        return fail(P, file, line, "LightSource \"infinite\": cannot have both \"L\" and "
                    "\"filename\" (pbrt-v4)");
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &L, &rgb_illum)) return 0;
    } else if (!spec_named(&L, "stdillum-D65")) {
        return fail(P, file, line, "LightSource: the built-in spectrum stdillum-D65 is missing");
    }
    if (!params_check_unused(P, pl, "LightSource \"infinite\"",
                             "spectrum L, rgb L, blackbody L, float scale, float illuminance, "
                             "string filename", "portal"))
        return 0;
    if (!(scale >= 0.0f))
        return fail(P, file, line, "LightSource \"infinite\": \"float scale\" must be >= 0");
    for (i = 0; i < SPEC_N; i++)
        if (!(L.v[i] >= 0.0f))
            return fail(P, p ? p->file : file, p ? p->line : line,
                        "LightSource \"infinite\": L is negative at %d nm", SPEC_MIN + i);
    if (rgb_illum) scale = rgb_illuminant_scale(&L, scale);
    inf = (InfiniteLight *)calloc(1, sizeof *inf);
    if (!inf) return oom(P, file, line);
    inf->world_from_light = P->gs.ctm;
    inf->file = file;
    inf->line = line;
    if (fn) {
        char path[1024];
        Image im;
        Error ierr;
        double mean[3] = { 0, 0, 0 }, k_e = 0.0;
        float mrgb[3];
        int x, y, c;
        if (!ends_with_ci(fn, ".pfm") && !ends_with_ci(fn, ".exr")) {
            free(inf);
            return fail(P, file, line, "LightSource \"infinite\": \"%s\": specnee reads image "
                        "maps only as PFM or EXR (convert with pbrt-v4's `imgtool convert`)", fn);
        }
        resolve_path(P, file, fn, path, sizeof path);
        if (ends_with_ci(fn, ".exr") ? !exr_read(&im, path, &ierr) : !pfm_read(&im, path, &ierr)) {
            free(inf);
            return fail(P, file, line, "LightSource \"infinite\": %s", ierr.msg);
        }
        if (!inf_set_image(inf, &im, file, line, P->err)) {
            img_free(&im);
            inf_free(inf);
            return 0;
        }
        for (y = 0; y < im.h; y++)
            for (x = 0; x < im.w; x++) {
                const float *px = im.rgb + 3 * ((size_t)y * im.w + x);
                for (c = 0; c < 3; c++) mean[c] += px[c] > 0.0f ? px[c] : 0.0f;
                if (ev > 0.0f) {
                    Vec3 w = equal_area_square_to_sphere((x + 0.5f) / im.w, (y + 0.5f) / im.h);
                    if (w.z > 0.0f)                      /* sRGB's luminance row */
                        k_e += (0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]) * w.z;
                }
            }
        for (c = 0; c < 3; c++) mrgb[c] = (float)(mean[c] / ((double)im.w * im.h));
        k_e *= 2.0 * SPECNEE_PI / ((double)im.w * im.h);
        img_free(&im);
        if (!spec_from_rgb(&inf->mean, mrgb, 1, P->err, file, line)) { inf_free(inf); return 0; }
        if (ev > 0.0f) {
            if (!(k_e > 0.0)) {
                inf_free(inf);
                return fail(P, file, line, "LightSource \"infinite\": \"illuminance\" given, but "
                            "the map sends no light to the upper hemisphere");
            }
            scale = (float)(scale * ev / k_e);
        }
    } else if (ev > 0.0f) {
        scale = (float)(scale * ev / SPECNEE_PI);
    }
    if (!grow((void **)&s->emitters, &P->cap_emit, s->n_emitters + 1, sizeof(Emitter))) {
        inf_free(inf);
        return oom(P, file, line);
    }
    em = &s->emitters[s->n_emitters++];
    memset(em, 0, sizeof *em);
    em->shape = -1;
    em->inf = inf;
    em->L = L;                   /* an image map: D65, the texels' illuminant */
    em->scale = scale;
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
   10. The directive loop
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

/* A medium coefficient (sigma_a, sigma_s): absent -> def (pbrt-v4: 1), else a
   spectrum with finite values >= 0 */
static int medium_coeff(Parser *P, ParamList *pl, const char *what, const char *name,
                        float def, Spectrum *out, const char *file, int line)
{
    Param *p = find_spectrum_param(pl, name);
    char w[192];
    if (!p) { spec_const(out, def); return 1; }
    snprintf(w, sizeof w, "%s: \"%s\"", what, name);
    return param_spectrum(P, p, SPEC_COEFF, out, NULL) &&
           check_spectrum_above(P, p, file, line, w, out, 0.0f, 0);
}

/* MakeNamedMedium "name" "string type" "homogeneous" ... with pbrt-v4's meaning
   (media.cpp, HomogeneousMedium::Create): sigma_a, sigma_s (default 1 each, per
   scene unit), or a "string preset" of measured coefficients (medium.c; they are
   in mm^-1, used as they are, as pbrt-v4 does), both times "float scale" (1);
   "float g" (0) the Henyey-Greenstein asymmetry; emission "spectrum Le" (0)
   times "float Lescale" (1), normalised as an area light's L is (lights.c: an rgb
   Le through D65).  Only homogeneous media: the others are refused by name. */
static int make_named_medium(Parser *P, Lexer *L, const Token *t)
{
    static const char *const pbrt_types[] = { "grid", "rgbgrid", "cloud", "nanovdb", NULL };
    Token nm;
    ParamList pl;
    const char *type = NULL, *preset = NULL;
    char what[160];
    Medium m;
    float scale, g, lescale;
    int ok = 0, idx, i, rgb_illum = 0;
    Param *ple;
    if (!expect_string(P, L, "MakeNamedMedium", "medium name", &nm)) return 0;
    memset(&pl, 0, sizeof pl);
    if (!parse_params(P, L, &pl)) { params_free(&pl); return 0; }
    memset(&m, 0, sizeof m);
    snprintf(what, sizeof what, "MakeNamedMedium \"%.100s\"", nm.text);
    if (!get_string(P, &pl, "type", &type)) goto done;
    if (!type) { fail(P, t->file, t->line, "%s: \"string type\" is required", what); goto done; }
    if (strcmp(type, "homogeneous") != 0) {
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i])) {
                fail(P, t->file, t->line, "%s: medium type \"%s\" is valid pbrt-v4 but not in "
                     "the specnee subset (only \"homogeneous\")", what, type);
                goto done;
            }
        fail(P, t->file, t->line, "%s: unknown medium type \"%s\"", what, type);
        goto done;
    }
    if (!get_string(P, &pl, "preset", &preset)) goto done;
    if (preset && preset[0]) {
        float sa[3], ss[3];
        Param *pp = param_find(&pl, PT_STRING, "preset");
        if (!medium_preset(preset, sa, ss)) {
            fail(P, pp->file, pp->line, "%s: unknown preset \"%s\" (pbrt-v4's names, e.g. "
                 "\"Wholemilk\", \"Skin1\", \"Ketchup\")", what, preset);
            goto done;
        }
        if (!spec_from_rgb(&m.sigma_a, sa, 2, P->err, pp->file, pp->line) ||
            !spec_from_rgb(&m.sigma_s, ss, 2, P->err, pp->file, pp->line)) goto done;
    } else if (!medium_coeff(P, &pl, what, "sigma_a", 1.0f, &m.sigma_a, t->file, t->line) ||
               !medium_coeff(P, &pl, what, "sigma_s", 1.0f, &m.sigma_s, t->file, t->line))
        goto done;
    if (!get_float(P, &pl, "scale", 1.0f, &scale) || !get_float(P, &pl, "g", 0.0f, &g) ||
        !get_float(P, &pl, "Lescale", 1.0f, &lescale)) goto done;
    ple = find_spectrum_param(&pl, "Le");
    if (ple) {
        char w[192];
        snprintf(w, sizeof w, "%s: \"Le\"", what);
        if (!param_spectrum(P, ple, SPEC_ILLUMINANT, &m.Le, &rgb_illum) ||
            !check_spectrum_above(P, ple, t->file, t->line, w, &m.Le, 0.0f, 0)) goto done;
    }
    if (!params_check_unused(P, &pl, what, "string type, string preset, spectrum sigma_a, "
                             "spectrum sigma_s, float scale, float g, spectrum Le, "
                             "float Lescale", NULL))
        goto done;
    if (!(scale >= 0.0f) || !(scale < 1e30f)) {
        Param *p = param_find(&pl, PT_FLOAT, "scale");
        fail(P, p->file, p->line, "%s: \"float scale\" %g must be a finite number >= 0", what, scale);
        goto done;
    }
    if (!(g > -1.0f) || !(g < 1.0f)) {
        Param *p = param_find(&pl, PT_FLOAT, "g");
        fail(P, p->file, p->line, "%s: \"float g\" %g must lie in (-1, 1) (Henyey-Greenstein)",
             what, g);
        goto done;
    }
    if (!(lescale >= 0.0f) || !(lescale < 1e30f)) {
        Param *p = param_find(&pl, PT_FLOAT, "Lescale");
        fail(P, p->file, p->line, "%s: \"float Lescale\" %g must be a finite number >= 0", what,
             lescale);
        goto done;
    }
    for (i = 0; i < SPEC_N; i++) {
        m.sigma_a.v[i] *= scale;
        m.sigma_s.v[i] *= scale;
    }
    for (i = 0; i < SPEC_UV_N; i++) {
        m.sigma_a.uv[i] *= scale;
        m.sigma_s.uv[i] *= scale;
    }
    m.g = g;
    m.Le_scale = 0.0f;
    if (ple) {
        float mx = 0.0f;
        for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
            if (spec_get(&m.Le, i) > mx) mx = spec_get(&m.Le, i);
        if (mx > 0.0f) m.Le_scale = rgb_illum ? rgb_illuminant_scale(&m.Le, lescale) : lescale;
    }
    m.file = t->file;
    m.line = t->line;
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
   11. Entry points
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
   12. --dump-scene: what the parser understood, in plain text
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
