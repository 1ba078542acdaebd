/* texture.c - pbrt-v4's textures: constant, checkerboard, scale, mix, imagemap.

   Exported (specnee.h sections 6 and 10): tex_eval, tex_set_image, tex_free.
   scene.c parses the Texture directive into Scene.textures; a material whose
   "reflectance" names a texture (today: diffuse) reads it through mat_albedo_at
   (material.c) at every hit, at each of the path's wavelengths.

   1. Mapping (pbrt-v4 textures.h, the pbrt book 4th ed. section 10.2).  A 2-D
      texture maps the surface point to (s, t):
        uv           s = uscale u + udelta,  t = vscale v + vdelta, with (u, v) the
                     shape's parameters (SurfacePoint.u, .v)
        spherical    q = the point in the texture's frame (the inverse of the CTM at
                     the Texture directive), s = theta(q) / pi, t = phi(q) / (2 pi)
        cylindrical  s = (pi + atan2(q_y, q_x)) / (2 pi),  t = q_z
        planar       s = udelta + q . v1,  t = vdelta + q . v2
   2. The textures.
        constant      "value"
        checkerboard  tex1 where floor(s) + floor(t) is even, tex2 where it is odd
                      (pbrt-v4's 2-D Checkerboard; pbrt-v4 also box-filters the edge
                      over the ray's footprint, which changes a pixel's mean only
                      in the pixels an edge crosses, and converges to the same
                      image as the footprint shrinks; specnee point-samples it and
                      the pixel filter averages)
        scale         tex x scale
        mix           (1 - amount) tex1 + amount tex2
        imagemap      the image at (s, 1 - t) (pbrt-v4 flips t: row 0 is the top),
                      bilinear between the four nearest texel centres (pbrt-v4's
                      default "bilinear" filter, which reads the full-resolution
                      level only), wrapped by "repeat", "black" or "clamp"
   3. RGB to spectrum.  A spectrum image texture holds reflectances: each texel's
      RGB, after pbrt-v4's scale and invert, is clamped to [0, 1] and turned into
      the smooth spectrum of spec_from_rgb (Jakob and Hanika 2019's sigmoid of a
      quadratic; a grey texel exactly flat), stored as 4 floats (m, c0, c1, c2) so
      that the texel's value at lambda is m sigmoid(c(lambda)).  pbrt-v4 interpolates
      the RGB and fits the spectrum at each lookup (through its precomputed table);
      specnee fits each texel once at load time and interpolates the four texels'
      values at lambda.  Both reproduce a texel's RGB exactly under D65; between
      texel centres they differ by the fit's non-linearity, which the film's XYZ,
      linear in the spectrum, sees only in the second order.  Fitting is Newton's
      method from the previous texel's coefficients (spec_rgb_coeffs_from), with
      the full homotopy fit when that does not converge. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

/* (s, t) of a 2-D texture at sp (section 1). */
static void tex_map(const Texture *t, const SurfacePoint *sp, float *s, float *tt)
{
    Vec3 q;
    if (t->map == TEXMAP_UV) {
        *s = t->su * sp->u + t->du;
        *tt = t->sv * sp->v + t->dv;
        return;
    }
    q = xf_point(&t->tex_from_world, sp->p);
    if (t->map == TEXMAP_SPHERICAL) {
        Vec3 d = v3_norm(q);
        float ct = d.z < -1.0f ? -1.0f : d.z > 1.0f ? 1.0f : d.z;
        float phi = atan2f(d.y, d.x);
        if (phi < 0.0f) phi += 2.0f * PI_F;
        *s = acosf(ct) / PI_F;
        *tt = phi / (2.0f * PI_F);
    } else if (t->map == TEXMAP_CYLINDRICAL) {
        *s = (PI_F + atan2f(q.y, q.x)) / (2.0f * PI_F);
        *tt = q.z;
    } else {
        *s = t->du + v3_dot(q, t->vs);
        *tt = t->dv + v3_dot(q, t->vt);
    }
}

/* Argument k: its texture, or its constant. */
static float tex_arg(const Texture *tex, const Texture *t, int k, const SurfacePoint *sp, float lambda)
{
    if (t->arg_tex[k] >= 0) return tex_eval(tex, t->arg_tex[k], sp, lambda);
    return t->is_float ? t->arg_f[k] : spec_eval(&t->arg_s[k], lambda);
}

/* The value of texel (x, y) at lambda, after the wrap mode; 0 outside with "black". */
static float texel_at(const Texture *t, int x, int y, float lambda)
{
    const float *q;
    if (t->wrap == TEXWRAP_BLACK && (x < 0 || y < 0 || x >= t->w || y >= t->h)) return 0.0f;
    if (t->wrap == TEXWRAP_REPEAT) {
        x %= t->w; if (x < 0) x += t->w;
        y %= t->h; if (y < 0) y += t->h;
    }
    x = x < 0 ? 0 : x >= t->w ? t->w - 1 : x;        /* "clamp" (and a guard for the others) */
    y = y < 0 ? 0 : y >= t->h ? t->h - 1 : y;
    if (t->is_float) return t->texel[(size_t)y * t->w + x];
    q = t->texel + 4 * ((size_t)y * t->w + x);
    return q[0] * spec_sigmoid_eval(q + 1, lambda);
}

/* Bilinear between the four texel centres around (s, 1 - t) (pbrt-v4 Image::Bilerp:
   texel (x, y) has its centre at ((x + 0.5) / w, (y + 0.5) / h)). */
static float image_lookup(const Texture *t, float s, float tt, float lambda)
{
    float x = s * t->w - 0.5f, y = (1.0f - tt) * t->h - 0.5f;
    float fx, fy;
    int x0, y0;
    if (!(x > -1e9f && x < 1e9f && y > -1e9f && y < 1e9f)) return 0.0f;   /* NaN, far away */
    x0 = (int)floorf(x);
    y0 = (int)floorf(y);
    fx = x - (float)x0;
    fy = y - (float)y0;
    return (1.0f - fx) * (1.0f - fy) * texel_at(t, x0, y0, lambda) +
           fx * (1.0f - fy) * texel_at(t, x0 + 1, y0, lambda) +
           (1.0f - fx) * fy * texel_at(t, x0, y0 + 1, lambda) +
           fx * fy * texel_at(t, x0 + 1, y0 + 1, lambda);
}

float tex_eval(const Texture *tex, int i, const SurfacePoint *sp, float lambda_nm)
{
    const Texture *t = &tex[i];
    float s, tt, a;
    switch (t->type) {
    case TEX_CONSTANT:
        return tex_arg(tex, t, 0, sp, lambda_nm);
    case TEX_CHECKERBOARD:
        tex_map(t, sp, &s, &tt);
        if (!(s > -1e9f && s < 1e9f && tt > -1e9f && tt < 1e9f)) return tex_arg(tex, t, 0, sp, lambda_nm);
        return (((long)floorf(s) + (long)floorf(tt)) & 1) == 0 ? tex_arg(tex, t, 0, sp, lambda_nm)
                                                              : tex_arg(tex, t, 1, sp, lambda_nm);
    case TEX_SCALE:
        a = t->scale_tex >= 0 ? tex_eval(tex, t->scale_tex, sp, lambda_nm) : t->arg_f[1];
        if (a == 0.0f) return 0.0f;                      /* pbrt-v4: skips the texture */
        return tex_arg(tex, t, 0, sp, lambda_nm) * a;
    case TEX_MIX:
        a = t->amount_tex >= 0 ? tex_eval(tex, t->amount_tex, sp, lambda_nm) : t->amount;
        return (1.0f - a) * tex_arg(tex, t, 0, sp, lambda_nm) + a * tex_arg(tex, t, 1, sp, lambda_nm);
    case TEX_IMAGEMAP:
        tex_map(t, sp, &s, &tt);
        return image_lookup(t, s, tt, lambda_nm);
    }
    return 0.0f;
}

int tex_set_image(Texture *t, const Image *im, float scale, int invert, Error *err)
{
    size_t n = (size_t)im->w * (size_t)im->h, i;
    RgbFitTable *fit = NULL;
    double prev[3] = { 0.0, 0.0, 0.0 };
    free(t->texel);
    t->texel = (float *)malloc(sizeof(float) * n * (t->is_float ? 1 : 4));
    if (!t->is_float) fit = (RgbFitTable *)malloc(sizeof *fit);
    if (!t->texel || (!t->is_float && !fit)) {
        free(fit);
        free(t->texel);
        t->texel = NULL;
        error_set(err, t->file, t->line, "Texture \"imagemap\": out of memory for %d x %d texels",
                  im->w, im->h);
        return 0;
    }
    t->w = im->w;
    t->h = im->h;
    if (fit) spec_rgb_fit_table(fit);
    for (i = 0; i < n; i++) {
        double rgb[3], c[3];
        int k;
        for (k = 0; k < 3; k++) {
            double v = (double)scale * im->rgb[3 * i + k];
            if (invert) v = 1.0 - v;
            rgb[k] = v > 0.0 ? v : 0.0;                  /* pbrt-v4: ClampZero */
        }
        if (t->is_float) {
            t->texel[i] = (float)((rgb[0] + rgb[1] + rgb[2]) / 3.0);
            continue;
        }
        for (k = 0; k < 3; k++) if (rgb[k] > 1.0) rgb[k] = 1.0;   /* a reflectance */
        if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
            /* grey: exactly flat, m sigmoid(0) = m / 2 */
            t->texel[4 * i] = (float)(2.0 * rgb[0]);
            t->texel[4 * i + 1] = t->texel[4 * i + 2] = t->texel[4 * i + 3] = 0.0f;
            continue;
        }
        if (!spec_rgb_coeffs_from(fit, rgb, prev, c)) spec_rgb_coeffs(rgb, c);
        for (k = 0; k < 3; k++) prev[k] = c[k];
        t->texel[4 * i] = 1.0f;
        for (k = 0; k < 3; k++) t->texel[4 * i + 1 + k] = (float)c[k];
    }
    free(fit);
    return 1;
}

void tex_free(Texture *t)
{
    free(t->texel);
    t->texel = NULL;
}
