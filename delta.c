/* delta.c - delta lights: pbrt-v4's point, spot and distant lights.

   Exported (specnee.h section 11): delta_falloff, delta_sample, delta_power_area,
   delta_can_reach.  scene.c builds a DeltaLight from a LightSource directive;
   lights.c treats it as one more emitter (a piece of its own) for every
   selection strategy; render.c's NEE gives its sample MIS weight 1 against BSDF
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
      direction w (towards the light), as the sun does:
          E(p) = L |cos theta_p|.

   2. Sampling.  The light has no density over directions: for a shading point
      p, "sampling" it is taking the one direction it arrives from, with
      probability 1.  To keep one NEE code path for every emitter, delta_sample
      reports pdf_sa = 1 / G with G the geometric factor of its incident light,
          G = falloff / |x - p|^2   (point, spot),    G = 1   (distant),
      so that Le / pdf_sa = I G is the incident radiance's estimate, as Le /
      pdf_sa is for an area sample, and sets EmitterSample.delta: no BSDF sample
      can find a delta light, so its MIS weight against BSDF sampling is 1
      (render.c leaves the BSDF's pdfs out of its denominator).  The spatial
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
      cos_end) / 2), and R^2. */
#include "specnee.h"

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

/* cos theta of the direction w (world, unit) leaving a spot light, measured in
   the light's frame (pbrt-v4's SpotLight works in light space): w taken back by
   the inverse CTM, against the cone's axis there. */
static float spot_cos(const DeltaLight *d, Vec3 w)
{
    const float *m = d->obj_from_world;
    Vec3 v = v3(m[0] * w.x + m[1] * w.y + m[2] * w.z, m[3] * w.x + m[4] * w.y + m[5] * w.z,
                m[6] * w.x + m[7] * w.y + m[8] * w.z);
    float len = v3_len(v);
    return len > 0.0f ? v3_dot(v, d->axis_obj) / len : 1.0f;
}

float delta_falloff(const DeltaLight *d, Vec3 w)
{
    if (d->type != DELTA_SPOT) return 1.0f;
    return smoothstep(spot_cos(d, w), d->cos_end, d->cos_start);
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
    default: return 0.0;
    }
}

/* Exact up to a margin of 1e-5 in the cosine (round-off between this test and
   delta_sample's own cosine): 0 only well outside a spot's cone. */
int delta_can_reach(const DeltaLight *d, Vec3 p)
{
    Vec3 v;
    float len;
    if (d->type != DELTA_SPOT) return 1;
    v = v3_sub(p, d->p);
    len = v3_len(v);
    if (!(len > 0.0f)) return 1;
    return spot_cos(d, v3_mul(v, 1.0f / len)) >= d->cos_end - 1e-5f;
}
