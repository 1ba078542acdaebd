/* parser.h - the pbrt-v4 front end, private to the rooms that build a scene.

   Not part of specnee's public interface (that is specnee.h): only the files
   that build something from a scene file's parameters include it (scene.c,
   options.c, and the "building from scene parameters" sections at the end of
   the concept rooms).  It declares the tokens and the token stream (the Lexer),
   a statement's parameter list with its typed getters, the "file:line: problem"
   errors, and the builder's state (the Parser: pbrt's graphics state and what
   the directives built so far), which every builder receives.  parser.c
   implements sections 1-4; section 5 lists each concept's builder (pbrt-v4's
   per-concept Create), which scene.c's directive loop calls.

   Every getter and check returns 1 on success and 0 after it has set P->err to
   one "file:line: problem" line (fail); the caller returns 0 in turn. */
#ifndef SPECNEE_PARSER_H
#define SPECNEE_PARSER_H
#include "specnee.h"

/* ---------------------------------------------------------------------------
   Limits that keep hostile input finite.
   --------------------------------------------------------------------------- */
#define MAX_INCLUDE_DEPTH 32        /* Include/Import nesting (catches a file that
                                       includes itself, and cycles) */
#define INCLUDE_MIN_BYTES 2048      /* what one Include/Import costs of the text budget
                                       at least (READ_MAX_BYTES, below): a tree of tiny
                                       files that include each other ("billion laughs")
                                       stops after 2^19 directives */
#define MAX_RESOLUTION 16384        /* pixels per film axis */
#define MAX_SPP (1 << 24)           /* samples per pixel */
#define MAX_MAXDEPTH 10000          /* path length */
#define MAX_ELEMENTS (1 << 27)      /* vertices, indices, triangles of one scene */
#define MAX_WORD 255                /* longest unquoted token */
#define NAME_CAP 4096               /* longest type or name a directive copies (the
                                       MakeNamedMaterial name): far above what exporters
                                       write, a one-line error beyond */
#define PATH_CAP 4096               /* longest file path the builders form (Linux's PATH_MAX:
                                       longer ones no system call opens).  Names of
                                       textures, materials, media, objects and coordinate
                                       systems have no limit (kept in Scene.strings) */
/* The text budget: the scene text, each included file counted every time an
   Include or Import runs it (at least INCLUDE_MIN_BYTES), is at most
   READ_MAX_BYTES (1 GiB), so the work of files that include each other many times
   grows no further than that of one 1 GiB file. */

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

typedef enum { V_NONE, V_NUM, V_STR, V_BOOL } ValueKind;

typedef struct {
    ParamType type;
    char name[64];
    ValueKind kind;            /* what the values are (one kind per parameter) */
    double *num; int n_num;    /* numbers, or bools as 0/1 */
    const char **str; int n_str;  /* strings (point into the lexer's buffer) */
    const char *file; int line;
    int used;                  /* looked up by the directive (pbrt's lookedUp) */
    int attr;                  /* from an Attribute directive: a default that the
                                  directive may leave unread (pbrt's mayBeUnused) */
} Param;

typedef struct { Param *p; int n, cap; } ParamList;
/* the names of ParamType, in its order ("float", "integer", ...) */
extern const char *const param_type_names[];

/* ===========================================================================
   3. The parser state: pbrt's graphics state and what the directives built
   =========================================================================== */
typedef struct {
    const Spectrum *L;         /* in Scene.spectra (the Emitters of its shapes share it) */
    float scale;
    int twosided;
    int image;                 /* "filename": 1 + its emission image's index in Scene.textures */
    const Spectrum *image_mean;/* its mean colour's spectrum (in Scene.spectra) */
    float power;               /* "float power" / k_e (the image's mean luminance, else 1);
                                  <= 0: none (arealight.c emitter_apply_power) */

    double y_vis;              /* luminance_sum(L, LAMBDA_LO, LAMBDA_HI) (Emitter.y_vis) */
} AreaLightDesc;

typedef struct {
    Xform ctm;                 /* current transformation matrix (at the start time) */
    Xform ctm_end;             /* the CTM at the end time (motion.c) */
    int active;                /* ActiveTransform: bit 0 start, bit 1 end (3: All) */
    int material;              /* index into Scene.materials, -1: the default,
                                  <= -2: named material -2 - material, not yet made */
    int reverse;               /* ReverseOrientation seen in this block */
    int area_light;            /* index into Parser.lights, -1: none */
    int medium_inside, medium_outside;   /* MediumInterface: Scene.media indices, -1: none */
    const char *file; int line;/* where the block was opened (for messages) */
    int by_object;             /* that block is an ObjectBegin's, not an AttributeBegin's */
    int attr[5];               /* Attribute "shape", "light", "material", "medium",
                                  "texture": 1 + the newest entry of Parser.attrs, 0: none */
    int colorspace;            /* ColorSpace: COLORSPACE_* (0: srgb, pbrt-v4's default) */
} GState;

/* A medium named by MakeNamedMedium or MediumInterface.  As in pbrt-v4, which
   creates the media when the file has been read, a MediumInterface may name a
   medium defined further down: its Scene.media entry is made at the first
   mention and filled by the MakeNamedMedium; finish() fails at the first mention
   of a name that none defines.  used: the camera starts in it or a shape's
   transition leads into it (finish() notes a medium that none does).
   before_camera: made before the Camera directive, where pbrt-v4's CTM maps to its
   render space, not to the world (finish() moves it; see media_before_camera). */
typedef struct { int defined, used, before_camera; const char *file; int line; } MediumRef;

/* An included file's text, kept after its first Include (scene.c include_text):
   a file included 160,000 times is read from the disk once. */
typedef struct { const char *path; char *text; size_t len; } IncludeCache;

/* A number literal read before (parser.c parse_number): its text and value. */
#define NUM_MEMO_TEXT 24           /* literals shorter than this are remembered */
#define NUM_MEMO_SIZE 64           /* slots, by a hash of the text */
typedef struct { char text[NUM_MEMO_TEXT]; double v; } NumMemo;

/* A named material.  As in pbrt-v4 a NamedMaterial may come before its
   MakeNamedMaterial (pbrt-v4 looks names up when it builds the scene): the name is
   then recorded with material -1 and the NamedMaterial's place, and shapes made
   under it carry the code -2 - (its index) until finish() resolves them. */
typedef struct { const char *name; int material; const char *file; int line; } NamedMaterial;
/* A named texture: pbrt-v4 keeps float and spectrum textures in two namespaces. */
typedef struct { const char *name; int is_float; int index; } NamedTexture;
typedef struct { const char *name; Xform xf, xf_end; } NamedCoordSys;   /* both CTMs */
/* An ObjectInstance whose object is not defined yet: as in pbrt-v4 the name is
   looked up when the file has been read (an instance may come before its
   ObjectBegin).  The placement itself is already Scene.instances[instance] (with
   object -1 until then); an instance of an object defined earlier, the usual
   case, never makes one of these (instance.c add_instance). */
typedef struct {
    const char *name; int instance;
    const char *file; int line;
} InstanceUse;

typedef struct {
    Scene *s;
    Error *err;
    char main_dir[PATH_CAP];   /* directory of the top-level file (pbrt's search dir) */
    int in_world;              /* after WorldBegin */
    int world_seen, include_depth;   /* include_depth: Import nesting */
    int nest;                  /* files open now inside the top-level one (Include+Import) */
    size_t text_bytes;         /* the text budget spent (see READ_MAX_BYTES above) */
    IncludeCache *inc;         /* the small included files read so far (scene.c) */
    int n_inc, cap_inc;
    GState gs;
    GState *stack; int depth, stack_cap;
    AreaLightDesc *lights; int n_lights, cap_lights;
    NamedMaterial *named; int n_named, cap_named;
    NamedCoordSys *coords; int n_coords, cap_coords;
    NamedTexture *texnames; int n_texnames, cap_texnames;
    int cap_textures;
    int default_material;      /* -1 until a shape needs it */
    const Spectrum *eta_one;   /* Scene.spectra's record of the constant 1, every
                                  material's eta to start with (NULL until made) */
    /* capacities of the growing Scene arrays */
    int cap_verts, cap_tris, cap_shapes, cap_mats, cap_emit, cap_spheres, cap_quadrics, cap_strings,
        cap_patches, cap_curves, cap_pieces;
    int any_normals;
    int any_uv;                /* some mesh has "uv": Scene.UV is kept parallel to P */
    int cap_tangents;          /* Scene.S's capacity (it grows with the meshes that have S) */
    int inset_line[8];         /* where each inset comment was (for messages) */
    const char *inset_file[8];
    int end_line;              /* line of the top-level file's last token */
    const char *camera_file; int camera_line;   /* the Camera directive, if any */
    float iso, exposure_time;  /* Film "iso", Camera shutter interval: the imaging ratio */
    const char *output;        /* the command line's output file (-o), NULL: none */
    MediumRef *mrefs; int cap_media, cap_mrefs;   /* parallel to Scene.media */
    const char *integ_file; int integ_line; char integ_type[32];  /* the Integrator */
    RgbTable *rgb;             /* the current colour space's RGB -> spectrum coefficient
                                  table (rgbfit.c): rgb_cs[gs.colorspace] */
    RgbTable *rgb_cs[COLORSPACE_N];   /* one per colour space, made when it first becomes
                                  current; rgb_cs[0] (srgb) always: images' (rgb_image_table) */
    double white_y[COLORSPACE_N];     /* Y of each space's white (rgb_illuminant_scale), 0: not yet */
    int cur_object;            /* inside ObjectBegin: 1 + its Scene.objects index; else 0 */
    int option_seed, option_seed_set;   /* Option "integer seed" (scene.c finish) */
    float edge_scale; int edge_scale_set;   /* Option "float displacementedgescale" (1 unset) */
    const char *displaced_file; int displaced_line;   /* the first displaced plymesh, if any */
    float shape_alpha; int shape_alpha_tex;   /* the Shape being read: its "alpha" (Shape) */
    int cap_objects;
    InstanceUse *uses; int n_uses, cap_uses;   /* the ObjectInstances of an object
                                                  not defined yet (looked up at the end) */
    int cap_instances;         /* Scene.instances' capacity */
    NumMemo num_memo[NUM_MEMO_SIZE];   /* number literals read so far (parse_number) */
    int last_object;           /* the object the last ObjectInstance named (its index):
                                  looked at first, as files name one object many times */
    double t0, t1;             /* TransformTimes (0 1): when the two CTMs hold */
    int cap_motions;
    /* every parameter an Attribute directive gave, copied (strings interned); each
       entry's prev links to the older ones of its target (1 + index, 0: none), so a
       GState names its defaults by one index per target and AttributeEnd restores
       them by restoring the GState */
    Param *attrs; int *attr_prev; int n_attrs, cap_attrs, cap_attr_prev;
} Parser;

/* ===========================================================================
   4. The interface (parser.c)
   =========================================================================== */
/* Errors: set P->err to "file:line: message" (printf-style) and return 0.
   fail_param points at parameter `name`'s own line when the statement gives it. */
int fail(Parser *P, const char *file, int line, const char *fmt, ...);
int fail_param(Parser *P, const ParamList *pl, const char *name, const char *file,
               int line, const char *fmt, ...);

/* Memory, strings, paths.  grow: *arr holds at least `need` elements of elsz
   bytes (0: out of memory or more than MAX_ELEMENTS).  intern: a copy of `name`
   kept in Scene.strings (one per distinct string).  keep_string: the same without
   intern's search, for names of which a scene may hold many (textures, materials,
   media, objects, coordinate systems: as long as the file writes them; NULL: out
   of memory).  dir_of: the directory part of path, '/' included.
   resolve_path: a file named in from_file, found as pbrt-v4 finds it.  */
int grow(void **arr, int *cap, int need, size_t elsz);
int oom(Parser *P, const char *file, int line);   /* "out of memory": fail, 0 */
const char *intern(Parser *P, const char *name);
const char *keep_string(Parser *P, const char *name);
void dir_of(const char *path, char *out, size_t cap);
void resolve_path(const Parser *P, const char *from_file, const char *name,
                  char *out, size_t cap);
int ends_with_ci(const char *s, const char *suffix);   /* case-insensitive suffix */
/* An Instance placed by the current CTMs (instance.c): of object `object` (>= 0: a
   moving shape's own object, geometry.c), else of the object named `name` (looked
   up now, or at the end of the file when it is not defined yet).  what: the
   directive, for messages ("ObjectInstance", or the moving shape's type). */
int add_instance(Parser *P, const char *what, const char *name, int object,
                 const char *file, int line);
/* The instances of objects defined after them, looked up at the end of the file. */
int instances_resolve(Parser *P);

/* The token stream.  lex_next: the next token (comments skipped, structured
   "# inset" comments recorded; an included file's end goes on in its parent);
   lex_unget: push one token back; tok_desc: a token for messages.
   expect_*: a directive's bare arguments (numbers, a bracketed 4x4 matrix, a
   quoted string), with the directive's name in the messages. */
int lex_next(Parser *P, Lexer *L, Token *t);
void lex_unget(Lexer *L, const Token *t);
const char *tok_desc(const Token *t);
int expect_number(Parser *P, Lexer *L, const char *directive, int count, double *out);
int expect_matrix(Parser *P, Lexer *L, const char *directive, double m[16]);
int expect_string(Parser *P, Lexer *L, const char *directive, const char *what,
                  Token *t);

/* Parameter lists.  parse_params reads "type name" value(s) pairs up to the next
   directive; params_free releases them.  param_find: the last parameter of that
   type and name (NULL: absent), marked used with its shadows.  get_*: one value,
   or `def` when absent (get_int's *given, when not NULL, says which). */
void params_free(ParamList *pl);
int parse_params(Parser *P, Lexer *L, ParamList *pl);
Param *param_find(ParamList *pl, ParamType type, const char *name);
int get_float(Parser *P, ParamList *pl, const char *name, float def, float *out);
int get_int(Parser *P, ParamList *pl, const char *name, int def, int *out, int *given);
int get_bool(Parser *P, ParamList *pl, const char *name, int def, int *out);
int get_string(Parser *P, ParamList *pl, const char *name, const char **out);

/* After a directive has read what it understands: a parameter left over is an
   error (pbrt-v4's ReportUnused).  `what` names the directive in messages,
   `reads` lists what it reads ("float radius, ..."), `pbrt_only` the pbrt-v4
   parameters specnee does not support (NULL: none).  refuse_param: a parameter p
   that was read but whose value is refused (msg), unless one left over comes
   first in the file. */
int params_check_unused(Parser *P, ParamList *pl, const char *what,
                        const char *reads, const char *pbrt_only);
int refuse_param(Parser *P, ParamList *pl, const char *what, const char *reads,
                 const Param *p, const char *file, int line, const char *msg);

/* Spectrum-valued parameters ("spectrum", "rgb", "blackbody").
   find_spectrum_param: the last one named `name` (NULL: absent), marked used;
   param_spectrum: its dense table, checked for `use`. */
/* SPEC_COEFF: a medium's coefficients, a dielectric's "rgb eta": pbrt-v4's
   "unbounded" spectra with rgb (RGBUnboundedSpectrum); a blackbody is pbrt-v4's
   BlackbodySpectrum (peak 1) for every use */
typedef enum { SPEC_ALBEDO, SPEC_UNBOUNDED, SPEC_ILLUMINANT, SPEC_COEFF } SpecUse;
Param *find_spectrum_param(ParamList *pl, const char *name);
int param_spectrum(Parser *P, Param *p, SpecUse use, Spectrum *out, int *rgb_illum);

/* Parameters that several builders read (parser.c section 4).
   check_unit_spectrum: every value of sp within [0, 1] (1e-4 of slack, clamped);
   unit_spectrum_param: p (NULL: the constant def) read and so checked.
   texture_lookup: the Scene.textures index a "texture name" parameter names in
   the float or spectrum namespace (-1 and an error when none).
   microfacet_roughness: pbrt-v4's roughness parameters (prefix: a layer's,
   "interface." or "conductor.") as a Roughness, each axis a GGX alpha or a float
   texture; microfacet_alphas: the unprefixed ones into a Material.
   check_spectrum_above: every value over
   300-830 nm finite and > lo (strict) or >= lo (p NULL: the statement's line);
   check_spectrum_above_from: the same from nm0 on.
   rgb_illuminant_scale: the scale that gives an "rgb L" illuminant pbrt-v4's
   D65 normalisation (D65's luminance computed once per load, in P). */
/* A microfacet material's roughness as read: per axis (u: the shading frame's s,
   v: its t) a GGX alpha (remapped unless remap is 0) or a float texture (tex_u,
   tex_v: 1 + its index, the alpha then 0; 0: the number). */
typedef struct { float alpha_u, alpha_v; int tex_u, tex_v, remap; } Roughness;
int check_unit_spectrum(Parser *P, const Param *p, Spectrum *sp);
int unit_spectrum_param(Parser *P, Param *p, Spectrum *out, float def);
/* A Material's reflectance (specnee.h Albedo).  rgb_albedo_param: an "rgb" of three
   values in [0, 1] that is not grey as its sigmoid's coefficients, once the Scene
   holds ALBEDO_TABLES spectrum records; 0 (nothing read, no error) for any other p,
   which the caller reads as a table and hands to albedo_set_table.  Both give the
   same values; a table is faster to shade (two loads where the sigmoid takes two
   square roots and divisions), so a scene's first colours get one, up to about
   2 MB, and a scene of many materials keeps 40 B per colour (docs/loading.md).
   unit_albedo_param: unit_spectrum_param into an Albedo, the colours by
   rgb_albedo_param (0: failed, at file:line when out of memory). */
#define ALBEDO_TABLES 1024
int rgb_albedo_param(Parser *P, const Param *p, Albedo *a);
int unit_albedo_param(Parser *P, Param *p, Albedo *a, float def, const char *file, int line);
int texture_lookup(Parser *P, const Param *p, int is_float);
int microfacet_roughness(Parser *P, ParamList *pl, const char *file, int line,
                         const char *what, const char *prefix, Roughness *r);
int microfacet_alphas(Parser *P, ParamList *pl, const char *file, int line,
                      const char *what, Material *m);
int check_spectrum_above(Parser *P, const Param *p, const char *file, int line,
                         const char *what, const Spectrum *sp, float lo, int strict);
int check_spectrum_above_from(Parser *P, const Param *p, const char *file, int line,
                              const char *what, const Spectrum *sp, float lo, int strict,
                              int nm0);
float rgb_illuminant_scale(Parser *P, const Spectrum *L, float scale);
/* The colour space (rgbfit.c): parser_set_colorspace makes cs current (its table made
   on first use; 0: out of memory), parser_sync_colorspace points P->rgb at the table of
   gs.colorspace after a graphics state is restored; space_white is the current space's
   white, the default L of every light; rgb_srgb_table the sRGB table, for what pbrt-v4
   reads in sRGB whatever the current space: an image's pixels (PNG, PFM: the
   file's own space, sRGB for these), the named media's and subsurface's preset
   coefficients, hair's melanin, marble's colours.  rgb_space_table is space cs's
   table (made on first use; NULL: out of memory), for an EXR image whose
   chromaticities name cs (read_exr_image: exr_read_space, with pbrt-v4's note and
   sRGB for chromaticities that match none of the four spaces). */
int   parser_set_colorspace(Parser *P, int cs);
void  parser_sync_colorspace(Parser *P);
void  space_white(Parser *P, Spectrum *L);
RgbTable *rgb_srgb_table(Parser *P);
RgbTable *rgb_space_table(Parser *P, int cs);
int   read_exr_image(const char *path, const char *what, const char *file, int line, Image *im,
                     int *space, Error *err);
/* note_not_positive: a note at the line of "float name" when it is given and
   v <= 0 (a light's "power" or "illuminance", which pbrt-v4 then ignores); it
   marks the parameter read. */
void note_not_positive(ParamList *pl, const char *what, const char *name, float v);

/* ===========================================================================
   5. Each concept built from its parameters (the end of each concept's room)
   =========================================================================== */
/* The options block (options.c): a Camera, Film, PixelFilter, Accelerator,
   Sampler or Integrator statement of `type` at file:line into Scene.settings. */
int camera_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line);
/* 1 when the camera transform gives the renderer finite eye and corner rays for
   the screen window sw (x0 x1 y0 y1) */
int camera_transform_ok(const Xform *camera_from_world, float fov_deg, const float sw[4]);
int film_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line);
int filter_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line);
int accelerator_directive(Parser *P, const char *type, ParamList *pl, const char *file,
                          int line);
int sampler_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line);
int integrator_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line);

/* The Shape directive of `type` at file:line (geometry.c): the shape of the current
   graphics state appended to the Scene. */
int shape_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line);
/* Shape "curve": the Bezier segments and pieces of Shape sh, which geometry.c has
   just made (curve.c). */
int curve_shape(Parser *P, ParamList *pl, int sh, const char *file, int line);

/* The Scene's material records (material.c): m appended (the Scene takes what it
   owns; on failure it is released), its index or -1; pbrt-v4's default material
   (diffuse, reflectance 0.5), made once. */
int add_material(Parser *P, Material *m, const char *file, int line);
int default_material(Parser *P, const char *file, int line);
/* m->eta := the record of the Scene's SpectrumStore equal to *eta (added when new),
   so that materials of the same index share one table; 0 (out of memory, failed at
   file:line) or 1.  Inline: the builders of conductor.c and layered.c call it, and
   material.c calls them. */
static inline int material_set_eta(Parser *P, Material *m, const Spectrum *eta,
                                   const char *file, int line)
{
    m->eta = spec_store_add(&P->s->spectra, eta);
    return m->eta ? 1 : oom(P, file, line);
}

/* *a := the table *s, as the record of the Scene's SpectrumStore equal to it
   (material_set_eta's sharing); 0 (out of memory, failed at file:line) or 1. */
static inline int albedo_set_table(Parser *P, Albedo *a, const Spectrum *s,
                                   const char *file, int line)
{
    a->rgb = 0;
    a->tab = spec_store_add(&P->s->spectra, s);
    return a->tab ? 1 : oom(P, file, line);
}

/* Materials: m (zeroed, eta 1) of one type, from a Material or MakeNamedMaterial
   statement at file:line; dir names the directive, what the directive and type
   in messages.  material.c: */
int interface_from_params(Parser *P, ParamList *pl, const char *file, int line,
                          const char *dir, const char *what, Material *m);
int diffuse_from_params(Parser *P, ParamList *pl, const char *file, int line,
                        const char *dir, const char *what, Material *m);
int fluorescent_from_params(Parser *P, ParamList *pl, const char *file, int line,
                            const char *dir, const char *what, Material *m);
int dielectric_from_params(Parser *P, ParamList *pl, const char *file, int line,
                           const char *dir, const char *what, Material *m);
int thindielectric_from_params(Parser *P, ParamList *pl, const char *file, int line,
                               const char *dir, const char *what, Material *m);
int diffusetransmission_from_params(Parser *P, ParamList *pl, const char *file, int line,
                                    const char *dir, const char *what, Material *m);
/* A Material "mix" may name materials made further down the file: its mix[k] is then
   -2 - (the NamedMaterial entry), resolved by finish() (scene.c). */
int measured_from_params(Parser *P, ParamList *pl, const char *file, int line,
                         const char *dir, const char *what, Material *m);
int mix_from_params(Parser *P, ParamList *pl, const char *file, int line,
                    const char *dir, const char *what, Material *m);
/* conductor.c: */
/* A conductor's "reflectance" parameter pr as pbrt-v4's eta = 1 and k (conductor.c;
   also read by coatedconductor in layered.c). */
int conductor_reflectance_param(Parser *P, Param *pr, Spectrum *refl, Spectrum *eta, Spectrum *k);
/* A conductor's "eta" and "k" (prefix "" or "conductor." of coatedconductor), or
   Cu's when absent: pbrt-v4's meaning over 360-830 nm, continued below (conductor.c). */
int conductor_eta_k(Parser *P, ParamList *pl, const char *file, int line,
                    const char *prefix, Spectrum *eta, Spectrum *k);
/* Their "texture eta" and "texture k" (same prefixes): x->eta_tex, x->k_tex, or 0;
   a texture of RGB reflectances, which pbrt-v4 would read otherwise, is refused. */
int conductor_eta_k_textures(Parser *P, ParamList *pl, const char *prefix, const char *what,
                             MaterialSpectra *x);
int conductor_from_params(Parser *P, ParamList *pl, const char *file, int line,
                          const char *dir, const char *what, Material *m);
/* layered.c: */
int coateddiffuse_from_params(Parser *P, ParamList *pl, const char *file, int line,
                              const char *dir, const char *what, Material *m);
int coatedconductor_from_params(Parser *P, ParamList *pl, const char *file, int line,
                                const char *dir, const char *what, Material *m);
/* hair.c: */
int hair_from_params(Parser *P, ParamList *pl, const char *file, int line,
                     const char *dir, const char *what, Material *m);
int subsurface_from_params(Parser *P, ParamList *pl, const char *file, int line,
                           const char *dir, const char *what, Material *m);
/* bump.c: "float displacement" or "texture displacement" (a float texture) and
   "string normalmap" (an image) of every material but interface and mix, into
   m->bump (left NULL without them); each builder calls it before its
   params_check_unused. */
int bump_from_params(Parser *P, ParamList *pl, const char *what, Material *m);
/* bump.c: "string normalmap" on a material pbrt-v4 gives no normal map
   (interface, mix, hair): the file must open, as pbrt-v4 loads it and stops
   without it (a file:line error naming it), then a note that it is ignored, why. */
int normalmap_ignored(Parser *P, ParamList *pl, const char *what, const char *why);
/* Textures (texture.c): T (zeroed, its kind, file and line set, no texture
   arguments yet) of class `cls` for a Texture statement naming `name`. */
int texture_from_params(Parser *P, ParamList *pl, const char *name, const char *cls,
                        Texture *T);
/* Lights.  lights.c: an AreaLightSource of `type` (only "diffuse") into *out.
   delta.c: LightSource "point", "spot" or "distant" into *em, in the frame of
   the CTM.  infinite.c: LightSource "infinite" (constant or an image map) into
   *em, which then owns em->inf.  The caller adds *em to Scene.emitters. */
int area_light_from_params(Parser *P, const char *type, ParamList *pl, const char *file, int line,
                           AreaLightDesc *out);
/* lights.c: an emission image file fn (.png, .pfm, .exr) into *im, or a
   `file:line: what: problem` error (0).  A bilinearmesh's "emissionfilename"
   is read with it too (geometry.c). */
int emission_image_read(Parser *P, const char *fn, const char *what, const char *file, int line,
                        Image *im);
int delta_light_from_params(Parser *P, const char *type, ParamList *pl, const char *file,
                            int line, Emitter *em);
int infinite_light_from_params(Parser *P, ParamList *pl, const char *file, int line,
                               Emitter *em);

/* Media (medium.c): a MakeNamedMedium's medium (what: the statement, for
   messages) into *m; the caller names it and adds it to Scene.media. */
int medium_from_params(Parser *P, ParamList *pl, const char *what, const char *file, int line,
                       Medium *m);

#endif
