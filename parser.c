/* parser.c - the pbrt-v4 front end: tokens, parameter lists, file:line errors.

   Implements parser.h (private to the scene builder; specnee.h section 8 is the
   public side): the tokenizer with textual Include streams and "# inset"
   structured comments, a statement's parameter list ("type name" value(s), as
   pbrt-v4's parseParameters and ParameterDictionary check them), the typed
   getters with pbrt-v4's rules (the last parameter of a name wins, one nobody
   reads is an error), spectrum-valued parameters, and the messages: every
   problem is one "file:line: problem" line in the Error.
   Sources: pbrt-v4's parser.cpp and paramdict.cpp (read, not copied).

   USE (scene.c's directive loop, and each concept's builder)
     Token t; ParamList pl = {0};
     if (!lex_next(P, L, &t)) return 0;            ... the directive's name
     if (!parse_params(P, L, &pl)) ...              its parameters
     if (!get_float(P, &pl, "radius", 1, &r)
         || !params_check_unused(P, &pl, "Shape \"sphere\"", "float radius", NULL)) ...
     params_free(&pl);                                                     */
#include "parser.h"
#include <ctype.h>
#include <float.h>
#include <limits.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

const char *const param_type_names[] = {
    "float", "integer", "bool", "string", "point2", "vector2", "point3",
    "vector3", "normal", "spectrum", "rgb", "blackbody", "texture"
};

/* ===========================================================================
   1. Small helpers: errors, memory, strings, paths
   =========================================================================== */
int fail(Parser *P, const char *file, int line, const char *fmt, ...)
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
int fail_param(Parser *P, const ParamList *pl, const char *name, const char *file,
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

/* The error for a failed allocation (or a grow past MAX_ELEMENTS). */
int oom(Parser *P, const char *file, int line)
{
    return fail(P, file, line, "out of memory (or more than %d elements)", MAX_ELEMENTS);
}

/* Grow *arr so that it holds at least `need` elements of size elsz. */
int grow(void **arr, int *cap, int need, size_t elsz)
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
const char *intern(Parser *P, const char *name)
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

const char *keep_string(Parser *P, const char *name)
{
    Scene *s = P->s;
    char *d;
    if (!grow((void **)&s->strings, &P->cap_strings, s->n_strings + 1, sizeof(char *)))
        return NULL;
    if ((d = str_dup(name)) != NULL) s->strings[s->n_strings++] = d;
    return d;
}

/* The directory part of path, with its trailing '/', or "" (the current dir). */
void dir_of(const char *path, char *out, size_t cap)
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
void resolve_path(const Parser *P, const char *from_file, const char *name,
                  char *out, size_t cap)
{
    char dir[PATH_CAP];
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

int ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix), i;
    if (m > n) return 0;
    for (i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != tolower((unsigned char)suffix[i])) return 0;
    return 1;
}

/* ===========================================================================
   2. The tokenizer (pbrt-v4 parser.cpp Tokenizer::Next, in our own words)
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
int lex_next(Parser *P, Lexer *L, Token *t)
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

void lex_unget(Lexer *L, const Token *t) { L->peeked = *t; L->has_peeked = 1; }

const char *tok_desc(const Token *t)
{
    switch (t->kind) {
    case TK_EOF: return "end of file";
    case TK_STRING: return "a quoted string";
    case TK_LBRACKET: return "'['";
    case TK_RBRACKET: return "']'";
    default: return t->text;
    }
}

/* A float literal: the whole token must be a finite number within float range.
   strtod is the slow part of reading a large file; files that place many instances
   write the same few numbers over and over (a Menger sponge: 54 million numbers,
   five distinct ones), so each short literal read is remembered in a small table
   (Parser.num_memo, by a hash of its text): the same text gives the same double. */
static int parse_number(Parser *P, const char *s, double *out)
{
    char *end;
    double v;
    size_t n = 0;
    unsigned h = 2166136261u;                  /* FNV-1a over the text */
    NumMemo *m;
    if (!*s) return 0;
    for (; s[n] && n < NUM_MEMO_TEXT; n++) h = (h ^ (unsigned char)s[n]) * 16777619u;
    m = &P->num_memo[h % NUM_MEMO_SIZE];
    if (n < NUM_MEMO_TEXT && !strcmp(m->text, s)) { *out = m->v; return 1; }
    v = strtod(s, &end);
    if (end == s || *end != '\0') return 0;
    if (!(v == v) || v > FLT_MAX || v < -FLT_MAX) return 0;     /* NaN, inf, overflow */
    if (n < NUM_MEMO_TEXT) { memcpy(m->text, s, n + 1); m->v = v; }
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
int expect_number(Parser *P, Lexer *L, const char *directive, int count, double *out)
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
        if (!parse_number(P, t.text, &out[i]))
            return fail(P, t.file, t.line, "%s: \"%s\" is not a finite number",
                        directive, t.text);
    }
    return 1;
}

/* '[' 16 numbers ']' for Transform / ConcatTransform (brackets required, as in pbrt-v4). */
int expect_matrix(Parser *P, Lexer *L, const char *directive, double m[16])
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

int expect_string(Parser *P, Lexer *L, const char *directive, const char *what,
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
void params_free(ParamList *pl)
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
        } else if (!parse_number(P, v->text, &x))
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

/* The next whitespace-separated word of *s, at most max characters (what sscanf's
   "%<max>s" reads, without its cost per parameter), into out; 0 when none is left. */
static int scan_word(const char **s, char *out, int max)
{
    const char *p = *s;
    int n = 0;
    while (isspace((unsigned char)*p)) p++;
    if (!*p) { *s = p; return 0; }
    while (*p && !isspace((unsigned char)*p) && n < max) out[n++] = *p++;
    out[n] = '\0';
    *s = p;
    return 1;
}

/* Read "type name" value(s) pairs until the next token is not a quoted string. */
int parse_params(Parser *P, Lexer *L, ParamList *pl)
{
    for (;;) {
        Token t, v;
        Param *p;
        char type[64], name[64], extra[8];
        int i, nf, cap_num = 0, cap_str = 0;
        if (!lex_next(P, L, &t)) return 0;
        if (t.kind != TK_STRING) { lex_unget(L, &t); return 1; }
        {   /* sscanf(t.text, "%63s %63s %7s", type, name, extra) */
            const char *s = t.text;
            nf = !scan_word(&s, type, 63) ? 0 : !scan_word(&s, name, 63) ? 1 : !scan_word(&s, extra, 7) ? 2 : 3;
        }
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
        memcpy(p->name, name, strlen(name) + 1);   /* at most 63 characters */
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
Param *param_find(ParamList *pl, ParamType type, const char *name)
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

int get_float(Parser *P, ParamList *pl, const char *name, float def, float *out)
{
    double v = def;
    int found;
    if (!get_one(P, pl, PT_FLOAT, "float", name, &v, &found)) return 0;
    *out = found ? (float)v : def;
    return 1;
}

int get_int(Parser *P, ParamList *pl, const char *name, int def, int *out, int *given)
{
    double v = def;
    int found;
    if (!get_one(P, pl, PT_INTEGER, "integer", name, &v, &found)) return 0;
    if (given) *given = found;
    *out = found ? (int)v : def;
    return 1;
}

int get_bool(Parser *P, ParamList *pl, const char *name, int def, int *out)
{
    double v = def;
    int found;
    if (!get_one(P, pl, PT_BOOL, "bool", name, &v, &found)) return 0;
    *out = found ? v != 0 : def;
    return 1;
}

int get_string(Parser *P, ParamList *pl, const char *name, const char **out)
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
        /* an Attribute default nobody reads is fine (pbrt-v4), unless pbrt-v4 would
           read it and specnee cannot */
        if (p->attr && !(pbrt_only && word_in(pbrt_only, p->name))) continue;
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
int params_check_unused(Parser *P, ParamList *pl, const char *what,
                        const char *reads, const char *pbrt_only)
{
    return params_check_unused_before(P, pl, what, reads, pbrt_only, pl->n);
}

/* A parameter p that was read but whose value specnee refuses: a statement's
   first problem in the file is the one named, so a parameter left over before p
   is reported instead; else msg, at p's own line (file:line when p is NULL).
   Call it after the directive has read all its parameters. */
int refuse_param(Parser *P, ParamList *pl, const char *what, const char *reads,
                 const Param *p, const char *file, int line, const char *msg)
{
    if (p && !params_check_unused_before(P, pl, what, reads, NULL, (int)(p - pl->p))) return 0;
    return fail(P, p ? p->file : file, p ? p->line : line, "%s", msg);
}

/* ===========================================================================
   3. Spectrum-valued parameters
   =========================================================================== */

/* The last "spectrum/rgb/blackbody name" parameter (pbrt-v4 GetOneSpectrum). */
Param *find_spectrum_param(ParamList *pl, const char *name)
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
   "rgb" illuminant (its scale needs pbrt's D65 normalisation: scene.c's head, EMISSION). */
int param_spectrum(Parser *P, Param *p, SpecUse use, Spectrum *out, int *rgb_illum)
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
        if (!spec_from_rgb_t(P->rgb, out, rgb, use == SPEC_ILLUMINANT ? 1 : use == SPEC_COEFF ? 2 : 0,
                             P->err, p->file, p->line))
            return 0;
        if (rgb_illum) *rgb_illum = use == SPEC_ILLUMINANT;
        return 1;
    }
    if (p->type == PT_BLACKBODY) {
        if (p->n_num != 1)
            return fail(P, p->file, p->line, "\"blackbody %s\": expected one temperature "
                        "(K), got %d values", p->name, p->n_num);
        /* pbrt-v4's BlackbodySpectrum whatever the use (a reflectance, an unbounded
           spectrum, an illuminant): peak 1, so within [0, 1] as an albedo */
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
        char path[PATH_CAP];
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
   4. Parameters that several builders read (materials, textures, lights, media)
   =========================================================================== */
/* A reflectance or absorptance must lie in [0, 1] at every nm, the UV extension
   included; 1e-4 of slack absorbs the rounding of an RGB upsampling of (1,1,1),
   and values in the slack are clamped to 1. */
int check_unit_spectrum(Parser *P, const Param *p, Spectrum *sp)
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
int unit_spectrum_param(Parser *P, Param *p, Spectrum *out, float def)
{
    if (!p) { spec_const(out, def); return 1; }
    return param_spectrum(P, p, SPEC_ALBEDO, out, NULL) && check_unit_spectrum(P, p, out);
}

int rgb_albedo_param(Parser *P, const Param *p, Albedo *a)
{
    float rgb[3];
    int k;
    if (!p || p->type != PT_RGB || p->n_num != 3) return 0;
    if (P->s->spectra.n < ALBEDO_TABLES) return 0;   /* few tables yet: tabulated */
    for (k = 0; k < 3; k++) rgb[k] = (float)p->num[k];
    return albedo_from_rgb(P->rgb, rgb, a);      /* rgbfit.c */
}

int unit_albedo_param(Parser *P, Param *p, Albedo *a, float def, const char *file, int line)
{
    Spectrum s;
    if (rgb_albedo_param(P, p, a)) return 1;
    return unit_spectrum_param(P, p, &s, def) && albedo_set_table(P, a, &s, file, line);
}

/* The texture a "texture name" parameter names, in the float or spectrum
   namespace; -1 and an error when there is none. */
int texture_lookup(Parser *P, const Param *p, int is_float)
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
   axis (u along the shading frame's s, v along t) is a number or a float texture:
   then r->tex_u (tex_v) = 1 + its index, its alpha 0, and material.c's mat_point
   reads the texture at each hit and remaps that value, as pbrt-v4 does per axis
   (a number and a texture, or two textures, are anisotropic GGX there).  prefix
   names a layer's parameters ("interface.", "conductor." of coatedconductor). */
int microfacet_roughness(Parser *P, ParamList *pl, const char *file, int line,
                         const char *what, const char *prefix, Roughness *r)
{
    float u = 0, v = 0, rr = 0;
    int have_u, have_v, have_r, tu, tv, tr;
    char nu[48], nv[48], nr[48];
    snprintf(nu, sizeof nu, "%suroughness", prefix);
    snprintf(nv, sizeof nv, "%svroughness", prefix);
    snprintf(nr, sizeof nr, "%sroughness", prefix);
    if (!rough_param(P, pl, nu, &have_u, &u, &tu) || !rough_param(P, pl, nv, &have_v, &v, &tv))
        return 0;
    if (!have_u || !have_v) {
        if (!rough_param(P, pl, nr, &have_r, &rr, &tr)) return 0;
        if (!have_u) { u = rr; tu = tr; }
        if (!have_v) { v = rr; tv = tr; }
    }
    if (!get_bool(P, pl, "remaproughness", 1, &r->remap)) return 0;
    r->tex_u = tu + 1;                                  /* tu, tv: -1 for a number */
    r->tex_v = tv + 1;
    if (tu >= 0) u = 0.0f;
    if (tv >= 0) v = 0.0f;
    if (!(u >= 0.0f && u <= 1e4f) || !(v >= 0.0f && v <= 1e4f))
        return fail(P, file, line, "%s: %s (%g, %g) must be within [0, 1e4]", what, nr, u, v);
    r->alpha_u = r->remap ? tr_alpha_of_roughness(u) : u;
    r->alpha_v = r->remap ? tr_alpha_of_roughness(v) : v;
    return 1;
}

/* The unprefixed names ("roughness", "uroughness", "vroughness") into a
   conductor's or coateddiffuse's alpha, alpha_t, alpha_tex, alpha_t_tex, remap. */
int microfacet_alphas(Parser *P, ParamList *pl, const char *file, int line,
                      const char *what, Material *m)
{
    Roughness r;
    if (!microfacet_roughness(P, pl, file, line, what, "", &r)) return 0;
    m->alpha = r.alpha_u;
    m->alpha_t = r.alpha_v;
    m->alpha_tex = r.tex_u;
    m->alpha_t_tex = r.tex_v;
    m->remap = r.remap;
    return 1;
}

/* Every value of a spectrum over nm0-830 nm must satisfy lo < v (strict) or
   lo <= v (strict = 0), and be finite: else "file:line: ..." naming the first
   wavelength that fails.  p may be NULL (a default spectrum: the directive's line).
   check_spectrum_above checks from 300 nm, the UV extension included. */
int check_spectrum_above_from(Parser *P, const Param *p, const char *file, int line,
                              const char *what, const Spectrum *sp, float lo, int strict,
                              int nm0)
{
    int nm;
    for (nm = nm0; nm <= SPEC_MAX; nm++) {
        float v = spec_get(sp, nm);
        if (!(strict ? v > lo : v >= lo) || !(v < 1e30f))
            return fail(P, p ? p->file : file, p ? p->line : line, "%s: value %g at %d nm "
                        "(need a finite value %s %g)", what, v, nm, strict ? ">" : ">=", lo);
    }
    return 1;
}

int check_spectrum_above(Parser *P, const Param *p, const char *file, int line,
                         const char *what, const Spectrum *sp, float lo, int strict)
{
    return check_spectrum_above_from(P, p, file, line, what, sp, lo, strict, SPEC_UV_MIN);
}

/* pbrt-v4 normalises an RGB illuminant by its colour space's illuminant W:
   Le = scale * L / sum ybar W.  lights.c divides by sum ybar L, so every light
   with an rgb spectrum gets scale * Y(L) / Y(W) (area, infinite and delta
   lights alike); Y(W) is computed on the space's first rgb light and kept in
   the Parser (P->white_y), not rebuilt per light. */
float rgb_illuminant_scale(Parser *P, const Spectrum *L, float scale)
{
    int cs = P->gs.colorspace;
    if (!(P->white_y[cs] > 0.0)) {
        Spectrum w;
        colorspace_illuminant(cs, &w);
        P->white_y[cs] = spec_to_y(&w);
    }
    return P->white_y[cs] > 0.0 ? (float)(scale * (spec_to_y_t(P->rgb, L) / P->white_y[cs])) : scale;
}

/* ColorSpace: pbrt-v4 keeps the space in the graphics state (AttributeEnd restores
   it) and every directive's "rgb" parameters are read in the space current there. */
int parser_set_colorspace(Parser *P, int cs)
{
    if (!P->rgb_cs[cs] && !(P->rgb_cs[cs] = rgb_table_new_cs(cs))) return 0;
    P->gs.colorspace = cs;
    P->rgb = P->rgb_cs[cs];
    return 1;
}

void parser_sync_colorspace(Parser *P)
{
    P->rgb = P->rgb_cs[P->gs.colorspace];   /* made when that state was current */
}

void space_white(Parser *P, Spectrum *L)
{
    colorspace_illuminant(P->gs.colorspace, L);
}

RgbTable *rgb_srgb_table(Parser *P)
{
    return P->rgb_cs[COLORSPACE_SRGB];
}

RgbTable *rgb_space_table(Parser *P, int cs)
{
    if (!P->rgb_cs[cs]) P->rgb_cs[cs] = rgb_table_new_cs(cs);
    return P->rgb_cs[cs];
}

int read_exr_image(const char *path, const char *what, const char *file, int line, Image *im,
                   int *space, Error *err)
{
    if (!exr_read_space(im, path, space, err)) return 0;
    if (*space < 0) {                       /* pbrt-v4's ReadEXR: a warning, and sRGB */
        fprintf(stderr, "%s:%d: note: %s: %s: its \"chromaticities\" match none of pbrt-v4's "
                "colour spaces (srgb, dci-p3, rec2020, aces2065-1); read as sRGB, as pbrt-v4 "
                "does\n", file, line, what, path);
        *space = COLORSPACE_SRGB;
    }
    return 1;
}

/* pbrt-v4 reads a light's "power" or "illuminance" only when it is > 0 and
   leaves the light's scale alone otherwise: a given value <= 0 changes nothing,
   so it gets a note at its own line. */
void note_not_positive(ParamList *pl, const char *what, const char *name, float v)
{
    Param *p = param_find(pl, PT_FLOAT, name);
    if (p && v <= 0.0f)
        fprintf(stderr, "%s:%d: note: %s: \"float %s\" %g is not positive and is ignored, "
                "as in pbrt-v4 (the light keeps its scale)\n", p->file, p->line, what, name,
                (double)v);
}
