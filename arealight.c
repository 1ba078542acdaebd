/* arealight.c - the AreaLightSource directive: what a diffuse area light's
   parameters mean, and its "float power".

   Exported: for the scene builder (parser.h) area_light_from_params and
   emission_image_read; for lights.c's emitters_prepare (specnee.h section 11)
   emitter_apply_power; luminance_sum and luminance_sum_t, the sum of ybar L over
   1 nm that normalises an emitter's L (pbrt-v4's SpectrumToPhotometric).  pbrt-v4's DiffuseAreaLight::Create is the reference for
   both halves: area_light_from_params reads L (spectrum, rgb as an RGB illuminant
   spectrum, blackbody), scale, twosided, an emission image ("filename") and power
   into an AreaLightDesc, which geometry.c attaches to each emitting shape;
   emitter_apply_power turns the power into the emitter's scale once the shape's
   primitives are known (section 1 below).  How an emitter is then sampled and
   selected is lights.c's (THEORY §5, §11). */
#include "specnee.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ 0. the luminance of L
   (lights.c normalises every emitter by it, render.c an emissive medium's Le) */

/* sum_{1 nm over [lo, hi]} ybar(lambda) L(lambda): the luminance that normalises
   an emitter's spectrum L (for an image map, L = D65). */
double luminance_sum(const Spectrum *L, float lo_nm, float hi_nm)
{
    double norm = 0.0;
    int lam;
    for (lam = (int)ceilf(lo_nm); lam <= (int)floorf(hi_nm); lam++) {
        /* cie_xyz's y (rounded to float) times spec_eval, which at a whole nm of
           the table is the knot itself */
        float y = (float)cie_ybar((double)lam);
        float v = lam >= SPEC_MIN && lam <= SPEC_MAX ? L->v[lam - SPEC_MIN] : spec_eval(L, (float)lam);
        norm += (double)y * v;
    }
    return norm;
}

/* luminance_sum with ybar read from T's knots (a load's area lights): the same
   floats (float)cie_ybar(lambda) and the same sum, without interpolating ybar. */
double luminance_sum_t(RgbTable *T, const Spectrum *L, float lo_nm, float hi_nm)
{
    const double *ybar;
    double norm = 0.0;
    int lam;
    if (!T || !(lo_nm >= (float)SPEC_MIN) || !(hi_nm <= (float)SPEC_MAX))
        return luminance_sum(L, lo_nm, hi_nm);
    ybar = spec_ybar_knots(T);
    for (lam = (int)ceilf(lo_nm); lam <= (int)floorf(hi_nm); lam++)
        norm += (double)(float)ybar[lam - SPEC_MIN] * L->v[lam - SPEC_MIN];
    return norm;
}

/* ------------------------------------------------------------------ 1. "float power"

   pbrt-v4's AreaLightSource "diffuse" "float power" Phi > 0 (DiffuseAreaLight::
   Create) makes one light per primitive of the shape - a triangle, a bilinear
   patch, a sphere, disk or cylinder - and scales each so that it alone emits Phi:
       scale_k = scale Phi / (pi s A_k k_e),   s = 2 if twosided else 1,
   on top of the normalisation that gives luminance scale (section 1), with k_e
   the emission image's mean luminance (1 without an image) and A_k pbrt-v4's
   Shape::Area() of primitive k: the world area of a triangle or patch (a patch
   not a rectangle: the sum over a 3 x 3 grid of its sub-quads of half their
   diagonals' cross product), and for a sphere, disk or cylinder the area of its
   OBJECT-space description (radius, zmin, zmax, phimax: the CTM's scale is not
   in it).  A mesh of n primitives thus emits n Phi, and triangles of different
   areas get different radiance.  The emitter keeps one scale,
       em->scale = scale Phi / (pi s Abar k_e),   Abar = (sum_k A_k) / n,
   and a mesh whose primitives differ in area gets em->prim_scale[k] = Abar / A_k
   per triangle and twisted patch (the two triangles of a flat patch share their
   patch's), which light_Le_at applies at the point it is given. */

/* pbrt-v4's area of the bilinear patch c = (p00, p10, p01, p11). */
static double pbrt_patch_area(const Vec3 c[4])
{
    Vec3 n, g[4][4];
    double d2[4], area = 0.0;
    int i, j, rect = 1;
    const Vec3 m = v3_mul(v3_add(v3_add(c[0], c[1]), v3_add(c[2], c[3])), 0.25f);
    n = v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0]));
    if (!(v3_len(n) > 0.0f) || !(v3_len(v3_sub(c[3], c[1])) > 0.0f) ||
        !(v3_len(v3_sub(c[3], c[2])) > 0.0f) ||
        fabs(v3_dot(v3_norm(v3_sub(c[3], c[0])), v3_norm(n))) > 1e-5)
        rect = 0;                                  /* degenerate, or not planar */
    for (i = 0; i < 4; i++) d2[i] = v3_dot(v3_sub(c[i], m), v3_sub(c[i], m));
    for (i = 1; i < 4 && rect; i++)
        if (fabs(d2[i] - d2[0]) / d2[0] > 1e-4) rect = 0;
    if (rect) return (double)v3_len(v3_sub(c[2], c[0])) * (double)v3_len(v3_sub(c[1], c[0]));
    for (i = 0; i <= 3; i++)
        for (j = 0; j <= 3; j++) {
            float u = (float)i / 3.0f, v = (float)j / 3.0f;
            Vec3 a = v3_add(c[0], v3_mul(v3_sub(c[2], c[0]), v));
            Vec3 b = v3_add(c[1], v3_mul(v3_sub(c[3], c[1]), v));
            g[i][j] = v3_add(a, v3_mul(v3_sub(b, a), u));
        }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            area += 0.5 * v3_len(v3_cross(v3_sub(g[i + 1][j + 1], g[i][j]),
                                          v3_sub(g[i + 1][j], g[i][j + 1])));
    return area;
}

/* pbrt-v4's Area() of a sphere, disk, cylinder or cut sphere: object space. */
static double pbrt_quadric_area(const Shape *sh)
{
    const Quadric *q = &sh->q;
    if (sh->type == SHAPE_SPHERE) {                /* a whole sphere, stored in the world */
        const double (*m)[4] = (const double (*)[4])q->world_from_obj.m;
        double r = sh->radius / sqrt(m[0][0] * m[0][0] + m[1][0] * m[1][0] + m[2][0] * m[2][0]);
        return 4.0 * SPECNEE_PI * r * r;
    }
    if (sh->type == SHAPE_DISK) return q->phimax * 0.5 * (q->radius * q->radius - q->inner * q->inner);
    return q->phimax * q->radius * (q->zmax - q->zmin);   /* cylinder, sphere part */
}

/* pbrt-v4's area of the k-th primitive of mesh sh (flat patches: triangle pairs,
   then its twisted patches), for emitter_apply_power's per-primitive table. */
static double pbrt_prim_area(const Scene *s, const Shape *sh, int k)
{
    Vec3 c[4];
    if (k < sh->tri_count && !sh->bilinear) return tri_area(s, sh->tri_begin + k);
    if (k < sh->tri_count) {         /* (p00, p10, p11) and (p00, p11, p01) */
        const Triangle *a = &s->tris[sh->tri_begin + (k & ~1)], *b = a + 1;
        c[0] = s->P[a->v[0]]; c[1] = s->P[a->v[1]]; c[3] = s->P[a->v[2]]; c[2] = s->P[b->v[2]];
    } else {
        patch_corners(s, s->patches[sh->patch_begin + k - sh->tri_count].v, c);
    }
    return pbrt_patch_area(c);
}

/* Apply em->power (Phi / k_e) to emitter em of shape sh: em->scale and, for a mesh
   whose primitives differ in area, em->prim_scale.  0: out of memory. */
int emitter_apply_power(const Scene *s, Emitter *em, const Shape *sh)
{
    const int n = sh->tri_count + sh->patch_count;
    const int units = sh->bilinear ? sh->tri_count / 2 + sh->patch_count : n;
    double sum = 0.0, lo = HUGE_VAL, hi = 0.0, abar;
    int k;
    free(em->prim_scale);
    em->prim_scale = NULL;
    if (sh->type != SHAPE_MESH) {
        abar = pbrt_quadric_area(sh);
    } else {
        em->prim_scale = (float *)malloc(sizeof(float) * (size_t)(n > 0 ? n : 1));
        if (!em->prim_scale) return 0;
        for (k = 0; k < n; k++) {
            double a = pbrt_prim_area(s, sh, k);
            em->prim_scale[k] = (float)a;
            if (k >= sh->tri_count || !sh->bilinear || !(k & 1)) sum += a;   /* once a patch */
            if (a < lo) lo = a;
            if (a > hi) hi = a;
        }
        abar = sum / units;
        for (k = 0; k < n; k++)
            em->prim_scale[k] = em->prim_scale[k] > 0.0f ? (float)(abar / em->prim_scale[k]) : 0.0f;
        if (hi - lo <= 1e-6 * hi) {                /* all alike: one radiance */
            free(em->prim_scale);
            em->prim_scale = NULL;
        }
    }
    em->scale = (float)(em->scale * em->power / (SPECNEE_PI * (em->twosided ? 2.0 : 1.0) * abar));
    return 1;
}

/* ---------------------------------------------------------------------------
   ---- 2. building from scene parameters
   area_light_from_params: the scene builder's (scene.c) AreaLightSource,
   read from its parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

int emission_image_read(Parser *P, const char *fn, const char *what, const char *file, int line,
                        Image *im)
{
    char path[PATH_CAP];
    Error ierr;
    int ok, space = COLORSPACE_SRGB;
    resolve_path(P, file, fn, path, sizeof path);
    if (ends_with_ci(fn, ".png")) ok = png_read(im, path, 0, &ierr);
    else if (ends_with_ci(fn, ".exr")) ok = read_exr_image(path, what, file, line, im, &space, &ierr);
    else if (ends_with_ci(fn, ".pfm")) ok = pfm_read(im, path, &ierr);
    else return fail(P, file, line, "%s: \"%s\": specnee reads emission images as PNG, PFM or "
                     "EXR", what, fn);
    if (!ok) return fail(P, file, line, "%s: %s", what, ierr.msg);
    if (space != COLORSPACE_SRGB) {
        /* pbrt-v4 would light it with RGBIlluminantSpectrum(that space) and normalise
           by the current space's white: not in the specnee subset */
        img_free(im);
        return fail(P, file, line, "%s: \"%s\": an emission image in colour space \"%s\" (its "
                    "\"chromaticities\") is valid pbrt-v4 but not in the specnee subset (sRGB "
                    "only; pbrt-v4's `imgtool convert` writes it as an sRGB .pfm)", what, fn, colorspace_name(space));
    }
    return 1;
}

/* sRGB's luminance row (pbrt-v4's RGBColorSpace::LuminanceVector of the colour
   space it gives PNG, PFM and EXR images). */
static const double srgb_y[3] = { 0.212639, 0.715169, 0.072192 };

/* An emission image: .png (sRGB-encoded, as pbrt-v4 reads 8- and 16-bit PNG),
   .pfm or .exr, read into an unnamed "clamp" imagemap texture of RGB illuminant
   texels (texture.c, Texture.illuminant) appended to Scene.textures; al->image is
   1 + its index, al->image_mean the RGB illuminant spectrum of its mean colour
   (pixels clamped at 0, as pbrt-v4's Phi clamps them).  pbrt-v4 refuses infinite
   and NaN pixels in a light's image; so does specnee. */
static int area_light_image(Parser *P, const char *fn, const char *file, int line, AreaLightDesc *al)
{
    Image im;
    Texture T;
    Spectrum mean;
    float mrgb[3];
    double sum[3] = { 0.0, 0.0, 0.0 }, ysum = 0.0;
    size_t i, n;
    int ok;
    if (!emission_image_read(P, fn, "AreaLightSource \"diffuse\"", file, line, &im)) return 0;
    n = (size_t)im.w * (size_t)im.h;
    for (i = 0; i < 3 * n; i++) {
        if (!isfinite(im.rgb[i])) {
            img_free(&im);
            return fail(P, file, line, "AreaLightSource \"diffuse\": \"%s\": image has infinite or "
                        "not-a-number pixel values and so is not suitable as a light (pbrt-v4)", fn);
        }
        if (im.rgb[i] > 0.0f) sum[i % 3] += im.rgb[i];
        ysum += srgb_y[i % 3] * im.rgb[i];    /* pbrt-v4's k_e: unclamped */
    }
    memset(&T, 0, sizeof T);
    T.type = TEX_IMAGEMAP;
    T.map = TEXMAP_UV;
    T.su = T.sv = 1.0f;
    T.wrap = TEXWRAP_CLAMP;                    /* pbrt-v4's Image::Bilerp default */
    T.illuminant = 1;
    T.amount_tex = T.scale_tex = -1;
    T.arg_tex[0] = T.arg_tex[1] = -1;
    T.file = file;
    T.line = line;
    ok = tex_set_image(&T, &im, 1.0f, 0, rgb_srgb_table(P), P->err);
    img_free(&im);
    if (!ok) return 0;
    if (!grow((void **)&P->s->textures, &P->cap_textures, P->s->n_textures + 1, sizeof(Texture))) {
        tex_free(&T);
        return oom(P, file, line);
    }
    P->s->textures[P->s->n_textures++] = T;
    al->image = P->s->n_textures;
    if (al->power > 0.0f) {                   /* "power": over k_e, the mean luminance */
        if (!(ysum > 0.0))
            return fail(P, file, line, "AreaLightSource \"diffuse\": \"float power\" with the "
                        "image \"%s\" of mean luminance %g: no scale gives it that power", fn,
                        ysum / (double)n);
        al->power = (float)(al->power / (ysum / (double)n));
    }
    for (i = 0; i < 3; i++) mrgb[i] = (float)(sum[i] / (double)n);
    if (!spec_from_rgb_t(rgb_srgb_table(P), &mean, mrgb, 1, P->err, file, line)) return 0;
    al->image_mean = spec_store_add(&P->s->spectra, &mean);
    if (!al->image_mean) return oom(P, file, line);
    return 1;
}

/* AreaLightSource "diffuse" (pbrt-v4 DiffuseAreaLight::Create): L (D65 when
   absent), scale, twosided, checked; an "rgb L" gets pbrt-v4's D65 normalisation
   (rgb_illuminant_scale).  "filename": an emission image over the shape's (u, v)
   instead of L (area_light_image; both refused, as pbrt-v4 does), with L = D65
   for the normalisation (light_Le_at).  "float power" > 0 is kept, divided by
   the image's mean luminance k_e (area_light_image), for emitter_apply_power;
   <= 0 is noted and ignored, as pbrt-v4 ignores it.  The shapes that follow
   carry it (geometry.c). */
int area_light_from_params(Parser *P, const char *type, ParamList *pl, const char *file, int line,
                           AreaLightDesc *out)
{
    AreaLightDesc al;
    Spectrum L;
    Param *p;
    int rgb_illum = 0;
    const char *fn = NULL;
    if (strcmp(type, "diffuse") != 0)
        return fail(P, file, line, "AreaLightSource \"%s\": unknown area light type "
                    "(pbrt-v4 has only \"diffuse\")", type);
    memset(&al, 0, sizeof al);
    p = find_spectrum_param(pl, "L");
    if (!get_string(P, pl, "filename", &fn)) return 0;
    if (fn && !fn[0]) fn = NULL;               /* pbrt-v4: "" is no file */
    if (fn && p)
        return fail(P, file, line, "AreaLightSource \"diffuse\": both \"L\" and \"filename\" "
                    "given (pbrt-v4 refuses them together)");
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &L, &rgb_illum)) return 0;
    } else {
        space_white(P, &L);                    /* the colour space's illuminant */
    }
    if (!get_float(P, pl, "scale", 1.0f, &al.scale)) return 0;
    if (!get_bool(P, pl, "twosided", 0, &al.twosided)) return 0;
    if (!get_float(P, pl, "power", 0.0f, &al.power)) return 0;
    note_not_positive(pl, "AreaLightSource \"diffuse\"", "power", al.power);
    if (!params_check_unused(P, pl, "AreaLightSource \"diffuse\"",
                             "spectrum L, rgb L, blackbody L, float scale, bool twosided, "
                             "string filename, float power", "alpha"))
        return 0;
    if (!(al.scale >= 0.0f))
        return fail(P, file, line, "AreaLightSource: \"float scale\" must be >= 0");
    {
        /* A spectrum with no luminance in 400-700 nm (an ultraviolet lamp) cannot be
           normalised to Y = scale: lights.c reads it as absolute spectral radiance
           times scale (docs/conventions.md §4, docs/FLUORESCENCE.md §6).  One pass
           over the knots from 300 nm up: the first negative (or NaN) one is refused;
           with none negative, L is zero everywhere unless some knot is > 0. */
        double vis;
        int nm, any = 0;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
            float v = nm < SPEC_MIN ? L.uv[nm - SPEC_UV_MIN] : L.v[nm - SPEC_MIN];
            if (!(v >= 0.0f))
                return fail(P, p ? p->file : file, p ? p->line : line,
                            "AreaLightSource: L is negative at %d nm", nm);
            any |= v > 0.0f;
        }
        vis = luminance_sum_t(P->rgb, &L, LAMBDA_LO, LAMBDA_HI);
        if (!any)
            return fail(P, p ? p->file : file, p ? p->line : line,
                        "AreaLightSource: spectrum L is zero everywhere in %d-%d nm",
                        SPEC_UV_MIN, SPEC_MAX);
        if (!(vis > 0.0) && al.power > 0.0f)
            return fail(P, p ? p->file : file, p ? p->line : line, "AreaLightSource: \"float "
                        "power\" with an L that has no luminance in 400-700 nm (pbrt-v4 divides "
                        "by that luminance)");
        al.y_vis = vis;                        /* Emitter.y_vis: not summed again */
        if (!(vis > 0.0))
            fprintf(stderr, "%s:%d: note: AreaLightSource: L has no luminance in 400-700 nm; "
                    "read as absolute spectral radiance times scale (docs/conventions.md)\n",
                    p ? p->file : file, p ? p->line : line);
    }
    if (rgb_illum) al.scale = rgb_illuminant_scale(P, &L, al.scale);
    if (fn && !area_light_image(P, fn, file, line, &al)) return 0;
    al.L = spec_store_add(&P->s->spectra, &L);   /* shared with equal ones */
    if (!al.L) return fail(P, file, line, "out of memory");
    *out = al;
    return 1;
}
