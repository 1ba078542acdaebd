/* delta.c - delta lights: pbrt-v4's point, spot, distant, goniometric and
   projection lights.

   Exported (specnee.h section 11): delta_falloff, delta_sample, delta_power_area,
   delta_can_reach, delta_projection_Le, delta_free.  The last section builds a DeltaLight from a LightSource
   directive; lights.c treats it as one more emitter (a piece of its own) for every
   selection strategy; path.c's NEE gives its sample MIS weight 1 against BSDF
   sampling (THEORY §11 derives the estimator).

   1. What they emit (pbrt-v4 lights.cpp, the pbrt book 4th ed. section 12.1-12.4).
      A point light at x radiates the intensity I(lambda) (W/sr/nm) equally into
      every direction; the radiance it sends to a point p is a Dirac delta in the
      direction towards x, so it gives p the irradiance
          E(p) = I |cos theta_p| / |x - p|^2.
      A spot light is a point light whose intensity is scaled by a falloff of the
      angle theta between the cone's axis and the direction leaving the light:
          falloff = smoothstep(cos theta; cos_end, cos_start),
          smoothstep(c; a, b) = t^2 (3 - 2 t),  t = clamp((c - a) / (b - a), 0, 1),
      with cos_end = cos(coneangle) (nothing outside) and cos_start =
      cos(coneangle - conedeltaangle) (full intensity inside); when the two are
      equal the falloff is a step, 0 below a and 1 from a on (pbrt-v4's
      SmoothStep).  The angle is measured in the light's frame (the CTM at the
      LightSource): a CTM that stretches the cone makes it elliptic in the world,
      as in pbrt-v4.  A distant light sends the radiance L(lambda) from the one
      direction omega_d (towards the light; DeltaLight.w), as the sun does:
          E(p) = L |cos theta_p|.

   2. Sampling.  The light has no density over directions: for a shading point
      p, "sampling" it is taking the one direction it arrives from, with
      probability 1.  To keep one NEE code path for every emitter, delta_sample
      reports pdf_sa = 1 / G with G the geometric factor of its incident light,
          G = falloff / |x - p|^2   (point, spot),    G = 1   (distant),
      so that Le / pdf_sa = I G is the incident radiance's estimate, as Le /
      pdf_sa is for an area sample, and sets EmitterSample.delta: no BSDF sample
      can find a delta light, so its MIS weight against BSDF sampling is 1
      (path.c leaves the BSDF's pdfs out of its denominator).  The spatial
      selection tables (lights.c section 3) accumulate 1 / pdf_sa over receiver
      points: for a delta light that is G, its irradiance per unit intensity
      without the receiver's cosine - the same quantity they estimate for an
      area light.

   3. Power.  pbrt-v4's Phi: a point light 4 pi I, a spot light
      2 pi I ((1 - cos_start) + (cos_start - cos_end) / 2) (the falloff band
      counted at half weight, pbrt-v4's approximation, kept so that "power"
      means the same), a distant light pi R^2 L over the scene's bounding disc
      of radius R.  The selection tables write every emitter's power as
      pi A int Le (A: area, x 2 if two-sided), so a delta light gets the "power
      area" A = Phi / (pi int Le): 4, 2 ((1 - cos_start) + (cos_start -
      cos_end) / 2), and R^2.

   4. Image lights (pbrt-v4 lights.cpp GoniometricLight, ProjectionLight; the
      pbrt book 4th ed. section 12.2).  Both sit at CTM(0, 0, 0) and look up an
      image in the direction w leaving them, taken to the light's frame by the
      inverse CTM (not renormalised, as in pbrt-v4; a rigid CTM keeps it unit):
      v = CTM^-1 w.  The lookup is the nearest texel, x = floor(u W), y =
      floor(v H) clamped to the image (row 0 at the top).
      Goniometric: I(w) = I(lambda) g(u, v) with (u, v) pbrt-v4's equal-area
      octahedral square (infinite.c section 1) of (v_x, v_z, v_y): pbrt-v4 swaps
      y and z, so the light's +y is the map's pole.  g is the texel's mean of R,
      G and B (a one-channel image: its value); the image must be square.  I is
      normalised as a point light's; its power is 4 pi I mean(g), so "power" Phi
      multiplies scale by Phi / (4 pi mean(g)) and the power area is 4 mean(g).
      Projection: pbrt-v4 flips y first (v_y -> -v_y), then projects through a
      perspective of field of view fov onto the screen
          s = (v_x, v_y) / (v_z tan(fov/2)),   nothing where v_z < 1e-3,
      and lights only inside the window [-a, a] x [-1, 1] (aspect a = W/H >= 1)
      or [-1, 1] x [-1/a, 1/a] (a < 1), both edges inclusive; (u, v) is s's
      place in the window.  The intensity is the texel's RGB illuminant spectrum
      (pbrt-v4's RGBIlluminantSpectrum in sRGB: 2 max(rgb) sigmoid(...) D65,
      negative channels clamped to 0), divided by the luminance of D65 as an
      infinite light's map is, times scale; no cosine factor: a texel is an
      intensity, and the plane z = 1 of the light's frame gets the image
      stretched by dw = cos^3 theta dA.  Its power integrates that over the
      window: Phi = A mean_texels(S(rgb) cos^3 theta), A = 4 tan^2(fov/2) a'
      (a' = max(a, 1/a)), cos theta at each texel's centre; "power" multiplies
      scale by Phi / (A mean(Y(rgb) cos^3 theta)), Y sRGB's luminance row.  The
      selection tables get the power area A mean(cos^3) / pi and the spectrum
      of the mean of rgb cos^3 / mean(cos^3), the light tree a cone around
      CTM(0, 0, 1) out to the window's corner (pbrt-v4's bounds).

   The last section builds these lights from a scene's LightSource parameters
   for the scene builder (delta_light_from_params, parser.h). */
#include "specnee.h"
#include <stdlib.h>

/* pbrt-v4's SmoothStep(x, a, b): 0 at x <= a, 1 at x >= b, the cubic between;
   a step at a when a == b. */
static float smoothstep(float x, float a, float b)
{
    float t;
    if (a == b) return x < a ? 0.0f : 1.0f;
    t = (x - a) / (b - a);
    if (t < 0.0f) t = 0.0f;
    if (t > 1.0f) t = 1.0f;
    return t * t * (3.0f - 2.0f * t);
}

/* A world direction w taken to the light's frame by the inverse CTM. */
static Vec3 to_light(const DeltaLight *d, Vec3 w)
{
    const float *m = d->obj_from_world;
    return v3(m[0] * w.x + m[1] * w.y + m[2] * w.z, m[3] * w.x + m[4] * w.y + m[5] * w.z,
              m[6] * w.x + m[7] * w.y + m[8] * w.z);
}

/* cos theta of the direction w (world, unit) leaving a spot light, measured in
   the light's frame (pbrt-v4's SpotLight works in light space): w taken back by
   the inverse CTM, against the cone's axis there. */
static float spot_cos(const DeltaLight *d, Vec3 w)
{
    Vec3 v = to_light(d, w);
    float len = v3_len(v);
    return len > 0.0f ? v3_dot(v, d->axis_obj) / len : 1.0f;
}

/* The nearest texel of (u, v) in [0, 1]^2, clamped to the image. */
static int nearest_texel(const DeltaLight *d, float u, float v)
{
    int x = (int)(u * d->img_w), y = (int)(v * d->img_h);
    x = x < 0 ? 0 : x >= d->img_w ? d->img_w - 1 : x;
    y = y < 0 ? 0 : y >= d->img_h ? d->img_h - 1 : y;
    return y * d->img_w + x;
}

/* A goniometric light's image factor towards w (section 4). */
static float gonio_factor(const DeltaLight *d, Vec3 w)
{
    Vec3 v = to_light(d, w);
    float u, t;
    equal_area_sphere_to_square(v3(v.x, v.z, v.y), &u, &t);     /* pbrt-v4's y <-> z */
    return d->img[nearest_texel(d, u, t)];
}

/* The texel a projection light sends w through, -1 outside its window. */
static int proj_texel(const DeltaLight *d, Vec3 w)
{
    Vec3 v = to_light(d, w);
    float x, y;
    v.y = -v.y;                                                  /* pbrt-v4's flip */
    if (!(v.z >= 1e-3f)) return -1;
    x = v.x / (v.z * d->tan_half);
    y = v.y / (v.z * d->tan_half);
    if (!(x >= -d->sx && x <= d->sx && y >= -d->sy && y <= d->sy)) return -1;
    return nearest_texel(d, (x + d->sx) / (2.0f * d->sx), (y + d->sy) / (2.0f * d->sy));
}

float delta_falloff(const DeltaLight *d, Vec3 w)
{
    if (d->type == DELTA_GONIO) return gonio_factor(d, w);
    if (d->type == DELTA_PROJECTION) {
        int t = proj_texel(d, w);
        return t >= 0 && d->img[4 * t] > 0.0f ? 1.0f : 0.0f;
    }
    if (d->type != DELTA_SPOT) return 1.0f;
    return smoothstep(spot_cos(d, w), d->cos_end, d->cos_start);
}

float delta_projection_Le(const Emitter *em, double k, Vec3 w, float lambda_nm)
{
    const DeltaLight *d = &em->delta;
    int t = proj_texel(d, w);
    const float *tx;
    if (t < 0) return 0.0f;
    tx = d->img + 4 * (size_t)t;
    if (!(tx[0] > 0.0f)) return 0.0f;
    return (float)(k * tx[0] * spec_sigmoid_eval(tx + 1, lambda_nm) * spec_eval(em->L, lambda_nm));
}

void delta_free(DeltaLight *d)
{
    free(d->img);
    d->img = NULL;
}

int delta_sample(const DeltaLight *d, Vec3 ref, EmitterSample *out)
{
    out->delta = 1;
    if (d->type == DELTA_DISTANT) {
        /* the direction towards the light; the "point" lies beyond the scene's
           bounding sphere, so that a shadow ray to it tests the whole way out */
        out->wi = d->w;
        out->dist = (float)(2.0 * d->radius + v3_len(v3_sub(ref, d->center)));
        out->p = v3_add(ref, v3_mul(out->wi, out->dist));
        out->n = v3_neg(out->wi);
        out->pdf_sa = 1.0f;
        return isfinite(out->dist);
    }
    {
        Vec3 v = v3_sub(d->p, ref);
        float dist2 = v3_dot(v, v), falloff;
        if (!(dist2 > 0.0f) || !(dist2 <= 3.0e38f)) return 0;   /* at the light, or inf/NaN */
        out->dist = sqrtf(dist2);
        out->wi = v3_mul(v, 1.0f / out->dist);
        falloff = delta_falloff(d, v3_neg(out->wi));             /* leaving the light */
        if (!(falloff > 0.0f)) return 0;                         /* outside the cone */
        out->p = d->p;
        out->n = v3_neg(out->wi);                                /* faces ref */
        out->pdf_sa = dist2 / falloff;                           /* 1 / G */
        return isfinite(out->pdf_sa) && out->pdf_sa > 0.0f;
    }
}

double delta_power_area(const DeltaLight *d)
{
    switch (d->type) {
    case DELTA_POINT: return 4.0;
    case DELTA_SPOT:
        return 2.0 * ((1.0 - (double)d->cos_start) + ((double)d->cos_start - d->cos_end) / 2.0);
    case DELTA_DISTANT: return d->radius * d->radius;
    case DELTA_GONIO: case DELTA_PROJECTION: return d->parea;
    default: return 0.0;
    }
}

/* Exact up to a margin of 1e-5 in the cosine (round-off between this test and
   delta_sample's own cosine): 0 only well outside a spot's cone. */
int delta_can_reach(const DeltaLight *d, Vec3 p)
{
    Vec3 v;
    float len;
    if (d->type != DELTA_SPOT && d->type != DELTA_PROJECTION) return 1;
    v = v3_sub(p, d->p);
    len = v3_len(v);
    if (!(len > 0.0f)) return 1;
    return spot_cos(d, v3_mul(v, 1.0f / len)) >= d->cos_end - 1e-5f;
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   delta_light_from_params: the scene builder's (scene.c) LightSource "point",
   "spot" and "distant", read from their parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"
#include <string.h>

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

/* The light's frame: the inverse CTM's 3x3 part, and whether the CTM stretches
   or shears (not a rotation times a uniform scale: three axes equally long, at
   right angles), which makes a round cone elliptic in the world. */
static void keep_light_frame(const Xform *ctm, DeltaLight *d)
{
    Vec3 ax = xf_vector(ctm, v3(1, 0, 0)), ay = xf_vector(ctm, v3(0, 1, 0));
    Vec3 az = xf_vector(ctm, v3(0, 0, 1));
    float lx = v3_len(ax), ly = v3_len(ay), lz = v3_len(az), tol = 1e-4f * lx;
    int a, b;
    d->stretched = fabsf(lx - ly) > tol || fabsf(lx - lz) > tol || fabsf(v3_dot(ax, ay)) > tol * lx ||
                   fabsf(v3_dot(ax, az)) > tol * lx || fabsf(v3_dot(ay, az)) > tol * lx;
    for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) d->obj_from_world[3 * a + b] = (float)ctm->inv[a][b];
}

/* ---- goniometric and projection lights (section 4) */

/* An image light's "string filename": PFM, EXR or PNG (8/16-bit, sRGB-encoded as
   pbrt-v4 reads it), every value finite (pbrt-v4 refuses others as a light). */
static int read_light_image(Parser *P, const char *what, const char *fn, const char *file,
                            int line, Image *im)
{
    char path[1024];
    Error ierr;
    int ok;
    size_t i;
    int space = COLORSPACE_SRGB;
    resolve_path(P, file, fn, path, sizeof path);
    if (ends_with_ci(fn, ".exr")) ok = read_exr_image(path, what, file, line, im, &space, &ierr);
    else if (ends_with_ci(fn, ".png")) ok = png_read(im, path, 0, &ierr);
    else if (ends_with_ci(fn, ".pfm")) ok = pfm_read(im, path, &ierr);
    else return fail(P, file, line, "%s: \"%s\": specnee reads light images as PFM, EXR or PNG "
                     "(convert with pbrt-v4's `imgtool convert`)", what, fn);
    if (!ok) return fail(P, file, line, "%s: %s", what, ierr.msg);
    if (space != COLORSPACE_SRGB) {            /* pbrt-v4 fits it in that space */
        img_free(im);
        return fail(P, file, line, "%s: \"%s\": a light image in colour space \"%s\" (its "
                    "\"chromaticities\") is valid pbrt-v4 but not in the specnee subset (sRGB "
                    "only; pbrt-v4's `imgtool convert` writes it as an sRGB .pfm)", what, fn, colorspace_name(space));
    }
    for (i = 0; i < 3 * (size_t)im->w * im->h; i++)
        if (!isfinite(im->rgb[i])) {
            img_free(im);
            return fail(P, file, line, "%s: \"%s\": pixel (%d, %d) is not a finite number: pbrt-v4 "
                        "refuses such an image as a light", what, fn, (int)(i / 3) % im->w,
                        (int)(i / 3) / im->w);
        }
    return 1;
}

/* A goniometric light's factors (the mean of each texel's R, G, B) and power
   area 4 mean; *k_e = 4 pi mean, the power of a unit intensity. */
static int gonio_setup(Parser *P, DeltaLight *d, const Image *im, const char *file, int line,
                       double *k_e)
{
    double sum = 0.0;
    size_t i, n = (size_t)im->w * im->h;
    if (im->w != im->h)
        return fail(P, file, line, "LightSource \"goniometric\": image %d x %d is not square: "
                    "pbrt-v4 needs its equal-area octahedral layout", im->w, im->h);
    d->img = (float *)malloc(sizeof(float) * n);
    if (!d->img) return fail(P, file, line, "out of memory");
    d->img_w = d->img_h = im->w;
    for (i = 0; i < n; i++) {
        const float *px = im->rgb + 3 * i;
        d->img[i] = (px[0] + px[1] + px[2]) / 3.0f;
        if (d->img[i] < 0.0f)
            return fail(P, file, line, "LightSource \"goniometric\": texel (%d, %d) is negative: "
                        "an intensity cannot be", (int)(i % (size_t)im->w), (int)(i / (size_t)im->w));
        sum += d->img[i];
    }
    d->parea = 4.0 * sum / (double)n;
    *k_e = SPECNEE_PI * d->parea;
    if (!(sum > 0.0))
        return fail(P, file, line, "LightSource \"goniometric\": the image is black: the light "
                    "sends nothing");
    return 1;
}

/* sRGB's luminance row (pbrt-v4's RGBColorSpace::LuminanceVector). */
static const double srgb_y[3] = { 0.212639, 0.715169, 0.072192 };

/* A projection light's window, texels (m and the sigmoid's coefficients of each
   texel's RGB illuminant spectrum), power area and stand-in spectrum; *k_e =
   A mean(Y(rgb) cos^3), the luminous power of scale 1 (section 4). */
static int proj_setup(Parser *P, DeltaLight *d, const Image *im, float fov, const char *file,
                      int line, double *k_e)
{
    double aspect = (double)im->w / im->h, t = tan(0.5 * fov * SPECNEE_PI / 180.0), A;
    double ysum = 0.0, csum = 0.0, rgbc[3] = { 0, 0, 0 };
    float mrgb[3];
    Spectrum S;
    int x, y, c;
    d->img = (float *)malloc(sizeof(float) * 4 * (size_t)im->w * im->h);
    if (!d->img) return fail(P, file, line, "out of memory");
    d->img_w = im->w;
    d->img_h = im->h;
    d->sx = (float)(aspect > 1.0 ? aspect : 1.0);
    d->sy = (float)(aspect > 1.0 ? 1.0 : 1.0 / aspect);
    d->tan_half = (float)t;
    A = 4.0 * t * t * (aspect > 1.0 ? aspect : 1.0 / aspect);
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++) {
            const float *px = im->rgb + 3 * ((size_t)y * im->w + x);
            float *tx = d->img + 4 * ((size_t)y * im->w + x), rgb[3], mx = 0.0f;
            double sxp = d->sx * (2.0 * (x + 0.5) / im->w - 1.0) * t;
            double syp = d->sy * (2.0 * (y + 0.5) / im->h - 1.0) * t;
            double cos3 = pow(1.0 + sxp * sxp + syp * syp, -1.5);   /* dw/dA on z = 1 */
            for (c = 0; c < 3; c++) {
                rgb[c] = px[c] > 0.0f ? px[c] : 0.0f;               /* pbrt-v4 ClampZero */
                mx = rgb[c] > mx ? rgb[c] : mx;
                ysum += srgb_y[c] * px[c] * cos3;
                rgbc[c] += rgb[c] * cos3;
            }
            csum += cos3;
            tx[0] = 2.0f * mx;
            tx[1] = tx[2] = tx[3] = 0.0f;
            if (mx > 0.0f) {
                double target[3], co[3];
                for (c = 0; c < 3; c++) target[c] = rgb[c] / tx[0];
                spec_rgb_coeffs(rgb_srgb_table(P), target, co);
                for (c = 0; c < 3; c++) tx[1 + c] = (float)co[c];
            }
        }
    d->parea = A * csum / ((double)im->w * im->h) / SPECNEE_PI;
    *k_e = A * ysum / ((double)im->w * im->h);
    d->cos_start = 1.0f;                                             /* the corner's cosine */
    d->cos_end = (float)(1.0 / sqrt(1.0 + (double)d->sx * d->sx * t * t + (double)d->sy * d->sy * t * t));
    if (!(rgbc[0] + rgbc[1] + rgbc[2] > 0.0))
        return fail(P, file, line, "LightSource \"projection\": the image is black: the light "
                    "sends nothing");
    for (c = 0; c < 3; c++) mrgb[c] = (float)(rgbc[c] / csum);
    if (!spec_from_rgb_t(rgb_srgb_table(P), &S, mrgb, 1, P->err, file, line)) return 0;
    d->mean = spec_store_add(&P->s->spectra, &S);
    if (!d->mean) return fail(P, file, line, "out of memory");
    return 1;
}

/* The parameters of an image light: goniometric reads I (as a point light), both
   scale, power and filename, projection fov. */
static int image_light_params(Parser *P, const char *type, ParamList *pl, const char *file,
                              int line, Spectrum *L, int *rgb_illum, float *scale, float *power,
                              float *fov, const char **fn)
{
    int gonio = !strcmp(type, "goniometric");
    Param *p = gonio ? find_spectrum_param(pl, "I") : NULL;
    char what[64];
    int i;
    snprintf(what, sizeof what, "LightSource \"%s\"", type ? type : "");
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, L, rgb_illum)) return 0;
    } else {
        space_white(P, L);                     /* the colour space's illuminant */
    }
    *fn = NULL;
    if (!get_float(P, pl, "scale", 1.0f, scale) || !get_float(P, pl, "power", -1.0f, power) ||
        !get_float(P, pl, "fov", 90.0f, fov) || !get_string(P, pl, "filename", fn))
        return 0;
    if (!params_check_unused(P, pl, what, gonio ? "spectrum I, rgb I, blackbody I, float scale, "
                             "float power, string filename" : "float scale, float power, "
                             "float fov, string filename", NULL))
        return 0;
    if (!check_finite(P, pl, what, "scale", *scale, file, line) ||
        !check_finite(P, pl, what, "power", *power, file, line))
        return 0;
    if (!(*scale >= 0.0f)) return fail(P, file, line, "%s: \"float scale\" must be >= 0", what);
    if (!(*fov > 0.0f && *fov < 180.0f))
        return fail_param(P, pl, "fov", file, line, "%s: \"float fov\" %g must be in (0, 180) "
                          "degrees", what, *fov);
    if (!*fn || !**fn)
        return fail(P, file, line, "%s: \"string filename\" is required (pbrt-v4 has no image "
                    "without it)", what);
    note_not_positive(pl, what, "power", *power);
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
        if (!(spec_get(L, i) >= 0.0f))
            return fail(P, p ? p->file : file, p ? p->line : line, "%s: I is negative at %d nm",
                        what, i);
    return 1;
}

/* LightSource "goniometric" and "projection" (section 4): the light sits at
   CTM(0, 0, 0); L is I (goniometric) or D65 (projection: the texels' illuminant). */
static int image_light_from_params(Parser *P, const char *type, ParamList *pl, const char *file,
                                   int line, Emitter *em)
{
    DeltaLight d;
    Spectrum L;
    Image im;
    const char *fn;
    float scale, power, fov;
    double k_e = 0.0;
    int rgb_illum = 0, ok;
    char what[64];
    snprintf(what, sizeof what, "LightSource \"%s\"", type ? type : "");
    if (!image_light_params(P, type, pl, file, line, &L, &rgb_illum, &scale, &power, &fov, &fn))
        return 0;
    if (!read_light_image(P, what, fn, file, line, &im)) return 0;
    memset(&d, 0, sizeof d);
    d.type = !strcmp(type, "goniometric") ? DELTA_GONIO : DELTA_PROJECTION;
    d.file = file;
    d.line = line;
    d.p = xf_point(&P->gs.ctm, v3(0, 0, 0));
    keep_light_frame(&P->gs.ctm, &d);
    d.axis_obj = v3(0, 0, 1);
    d.w = v3_norm(xf_vector(&P->gs.ctm, v3(0, 0, 1)));
    ok = d.type == DELTA_GONIO ? gonio_setup(P, &d, &im, file, line, &k_e)
                               : proj_setup(P, &d, &im, fov, file, line, &k_e);
    img_free(&im);
    if (!ok) { delta_free(&d); return 0; }
    if (rgb_illum) scale = rgb_illuminant_scale(P, &L, scale);      /* goniometric's rgb I */
    if (power > 0.0f) {
        if (!(k_e > 0.0)) {
            delta_free(&d);
            return fail(P, file, line, "%s: \"power\" given, but the image has no luminance", what);
        }
        scale = (float)(scale * power / k_e);
    }
    memset(em, 0, sizeof *em);
    em->shape = -1;
    em->delta = d;
    em->L = spec_store_add(&P->s->spectra, &L);
    em->scale = scale;
    if (!em->L) { delta_free(&em->delta); return fail(P, file, line, "out of memory"); }
    if (!isfinite(scale)) {
        delta_free(&em->delta);
        return fail(P, file, line, "%s: scale x power is not a finite number", what);
    }
    return 1;
}

/* LightSource "point", "spot" and "distant", with pbrt-v4's meaning
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
int delta_light_from_params(Parser *P, const char *type, ParamList *pl, const char *file,
                            int line, Emitter *em)
{
    static const double zero[3] = { 0, 0, 0 }, zplus[3] = { 0, 0, 1 };
    DeltaLight d;
    Param *p;
    Spectrum L;
    double from[3], to[3];
    float scale, power = -1.0f, cone = 30.0f, cdelta = 5.0f;
    int rgb_illum = 0, i;
    const char *sname = !strcmp(type, "distant") ? "L" : "I";
    char what[64];
    if (!strcmp(type, "goniometric") || !strcmp(type, "projection"))
        return image_light_from_params(P, type, pl, file, line, em);
    snprintf(what, sizeof what, "LightSource \"%s\"", type ? type : "");
    memset(&d, 0, sizeof d);
    d.type = !strcmp(type, "point") ? DELTA_POINT : !strcmp(type, "spot") ? DELTA_SPOT : DELTA_DISTANT;
    d.file = file;
    d.line = line;
    p = find_spectrum_param(pl, sname);
    if (p) {
        if (!param_spectrum(P, p, SPEC_ILLUMINANT, &L, &rgb_illum)) return 0;
    } else {
        space_white(P, &L);                    /* the colour space's illuminant */
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
    note_not_positive(pl, what, d.type == DELTA_DISTANT ? "illuminance" : "power", power);
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
        if (!(spec_get(&L, i) >= 0.0f))
            return fail(P, p ? p->file : file, p ? p->line : line, "%s: %s is negative at %d nm",
                        what, sname, i);
    if (rgb_illum) scale = rgb_illuminant_scale(P, &L, scale);
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
            double ts, tc;
            keep_light_frame(&P->gs.ctm, &d);
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
    memset(em, 0, sizeof *em);
    em->shape = -1;
    em->delta = d;
    em->L = spec_store_add(&P->s->spectra, &L);
    if (!em->L) return fail(P, file, line, "out of memory");
    em->scale = scale;
    return 1;
}
