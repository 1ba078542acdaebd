/* hair.c - pbrt-v4's "hair" material: the hair scattering model of Chiang,
   Bitterli, Tappan and Burley 2016, "A Practical and Controllable Hair and Fur
   Model for Production Path Tracing" (Computer Graphics Forum 35(2)), as pbrt-v4's
   HairBxDF uses it (pbrt 4th ed. section 9.9).  THEORY §16 has the equations.

   Exported (specnee.h section 6): hair_shade, hair_sample, hair_eval, and the
   colour helpers hair_sigma_a_from_reflectance and hair_melanin_rgb; hair_from_params
   (parser.h) builds the material.  material.c's bsdf_sample and bsdf_eval call
   hair_sample and hair_eval for a MAT_HAIR material; path.c calls hair_shade at
   a hair vertex, which adds the shape's dp/du (bump.c's shading_differentials)
   to the surface point.

   The fibre.  The hair is a dielectric cylinder of index eta whose interior
   absorbs sigma_a per unit radius.  Its axis is the shading frame's x axis, the
   direction of dp/du; z is the shading normal and y = z x x.  A direction w has
   the longitudinal angle theta (sin theta = w.x, from the normal plane of the
   axis) and the azimuth phi = atan2(w.z, w.y) around it.  The offset h across the
   fibre's width is pbrt-v4's h = -1 + 2 v of whatever surface carries the
   material (a curve's v runs across it; on a sphere v = 1 - theta / pi).

   f(wo, wi) |cos(wi, n)| = sum_{p<3} M_p(theta_i, theta_o) A_p N_p(phi)
                            + M_3(theta_i, theta_o) A_3 / (2 pi)
   p = 0 the light reflected at the surface (R), 1 once through (TT), 2 after
   one inner reflection (TRT), 3 all the rest.  Each M_p integrates to 1 against
   cos theta_i dtheta_i, each N_p to 1 over phi, so that
   integral f |cos| dw = sum A_p, which is 1 without absorption (the white
   furnace, tests/test_hair.c).  Sampling picks p in proportion to A_p (averaged
   over the path's alive wavelengths, so the density of a direction is the same
   whichever wavelength is the hero), theta_i from M_p exactly, phi from N_p
   exactly; the pdf is that mixture, the same sum with A_p / sum A replacing A_p.

   Every parameter may be a texture, evaluated at the hit (fibre_at).  A
   "displacement" is refused as unused (pbrt-v4's HairMaterial reads none, so it
   refuses it too); "string normalmap" is ignored, as pbrt-v4's HairMaterial
   ignores it, once the file is found (pbrt-v4 loads every material's normal map
   and stops when it cannot: bump.c normalmap_ignored). */
#include "specnee.h"
#include "parser.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

#define HAIR_PMAX 3            /* lobes R, TT, TRT and the remainder */

/* ------------------------------------------------------------------ 1. the terms */

/* The modified Bessel function I0(x) by its power series sum (x^2/4)^k / (k!)^2
   (every term positive: no cancellation); for x <= 40 here. */
static double bessel_i0(double x)
{
    double q = x * x / 4.0, term = 1.0, sum = 1.0;
    int k;
    for (k = 1; k < 200; k++) {
        term *= q / ((double)k * k);
        sum += term;
        if (term < 1e-17 * sum) break;
    }
    return sum;
}

/* log I0(x): the series below 12, beyond it the asymptotic expansion
   I0(x) = e^x / sqrt(2 pi x) (1 + 1/(8x) + 9/(128 x^2) + 225/(3072 x^3) + ...),
   whose next term is below 6e-6 there.  (pbrt-v4 keeps 1/(16 x) of the first
   correction, a relative error of up to 0.5 % in M_p near x = 12.) */
double hair_log_i0(double x)
{
    if (x <= 12.0) return log(bessel_i0(x));
    {
        double r = 1.0 / x;
        return x - 0.5 * log(2.0 * SPECNEE_PI * x) +
               log(1.0 + r * (1.0 / 8.0 + r * (9.0 / 128.0 + r * (225.0 / 3072.0))));
    }
}

/* The longitudinal term (THEORY (30)): the von Mises-Fisher lobe of variance v
   around the mirror cone theta_i = -theta_o, integrated over the azimuth:
   M = exp(-sin_i sin_o / v) I0(cos_i cos_o / v) / (2 v sinh(1/v)).
   For v <= 0.1 in logarithms, 2 sinh(1/v) being e^(1/v) there (to e^(-20)). */
static double hair_mp(double cos_i, double cos_o, double sin_i, double sin_o, double v)
{
    double a = cos_i * cos_o / v, b = sin_i * sin_o / v;
    if (v <= 0.1) return exp(hair_log_i0(a) - b - 1.0 / v - log(v));
    return exp(-b) * bessel_i0(a) / (2.0 * v * sinh(1.0 / v));
}

/* The logistic distribution of scale s on [-pi, pi] (THEORY (31)): its density,
   its cumulative distribution, and a sample by inverting the latter. */
static double logistic_cdf(double x, double s) { return 1.0 / (1.0 + exp(-x / s)); }

static double trimmed_logistic(double x, double s)
{
    double e = exp(-fabs(x) / s);
    return e / (s * (1.0 + e) * (1.0 + e)) /
           (logistic_cdf(SPECNEE_PI, s) - logistic_cdf(-SPECNEE_PI, s));
}

static double sample_trimmed_logistic(double u, double s)
{
    double lo = logistic_cdf(-SPECNEE_PI, s), k = logistic_cdf(SPECNEE_PI, s) - lo;
    double x = -s * log(1.0 / (u * k + lo) - 1.0);
    return x < -SPECNEE_PI ? -SPECNEE_PI : x > SPECNEE_PI ? SPECNEE_PI : x;
}

/* An angle brought into [-pi, pi]. */
static double wrap_pi(double a)
{
    a = fmod(a + SPECNEE_PI, 2.0 * SPECNEE_PI);
    if (a < 0.0) a += 2.0 * SPECNEE_PI;
    return a - SPECNEE_PI;
}

/* ------------------------------------------------------------------ 2. one fibre */

/* The model at one hit: h, eta, the variances v_p, the logistic scale s, the
   tilt of each lobe's cone (THEORY (34)) and sigma_a at the path's wavelengths. */
typedef struct {
    double h, eta, s;
    double v[HAIR_PMAX + 1];
    double sin_tilt[HAIR_PMAX + 1], cos_tilt[HAIR_PMAX + 1];
    double sigma_a[HERO_N];
    unsigned alive;
} Fibre;

/* What depends on wo: its angles, the refracted ray's (gamma_t, cos theta_t), the
   attenuations A_p per wavelength and the lobe probabilities. */
typedef struct {
    double sin_o, cos_o, phi_o, gamma_o, gamma_t;
    double ap[HAIR_PMAX + 1][HERO_N];
    double ap_pdf[HAIR_PMAX + 1];
} FibreOut;

float hair_sigma_a_from_reflectance(float c, float beta_n)
{
    /* Chiang et al. 2016, eq. (9): the sigma_a whose multiply scattered colour
       (white furnace, many fibres) is c, for the azimuthal roughness beta_n */
    double b = beta_n, d = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b * b * b +
                           5.574 * b * b * b * b + 0.245 * b * b * b * b * b;
    double l = log(c > 0.0f ? (double)c : 1e-30) / d;
    return (float)(l * l);
}

void hair_melanin_rgb(float eumelanin, float pheomelanin, float rgb[3])
{
    /* sigma_a per unit concentration of the two melanins, linear sRGB: the values
       pbrt-v4 uses (HairBxDF::SigmaAFromConcentration), after d'Eon, Francois,
       Hill, Letteri and Aubry 2011, "An Energy-Conserving Hair Reflectance Model"
       (EGSR), as adopted by Chiang et al. 2016, section 4.1 */
    static const float eu[3] = { 0.419f, 0.697f, 1.37f }, ph[3] = { 0.187f, 0.4f, 1.05f };
    int k;
    for (k = 0; k < 3; k++) rgb[k] = eumelanin * eu[k] + pheomelanin * ph[k];
}

/* Parameter k at sp: its texture's value there, else the constant c. */
static float hair_param(const Material *m, int k, float c, const SurfacePoint *sp, float lambda)
{
    if (m->hair->tex[k] > 0 && m->textures) return tex_eval(m->textures, m->hair->tex[k] - 1, sp, lambda);
    return c;
}

/* pbrt-v4's RGBUnboundedSpectrum of the melanins' RGB at lambda: 2 max(rgb) times
   the sigmoid fitted to rgb / (2 max(rgb)), whose coefficients depend only on the
   pheomelanin share cp / (ce + cp): interpolated in H->mel_c (built at load). */
static double melanin_sigma_a(const Hair *H, float ce, float cp, float lambda)
{
    float rgb[3], c[3], x, w;
    int k, i;
    if (!(ce + cp > 0.0f)) return 0.0;
    hair_melanin_rgb(ce, cp, rgb);
    x = cp / (ce + cp) * (HAIR_MEL_N - 1);
    i = (int)x < HAIR_MEL_N - 2 ? (int)x : HAIR_MEL_N - 2;
    w = x - (float)i;
    for (k = 0; k < 3; k++) c[k] = (1.0f - w) * H->mel_c[i][k] + w * H->mel_c[i + 1][k];
    return 2.0 * fmax(rgb[0], fmax(rgb[1], rgb[2])) * spec_sigmoid_eval(c, lambda);
}

/* sigma_a at one wavelength (pbrt-v4's GetBxDF): given, from the reflectance, or
   from the melanins; negative values count as 0. */
static double hair_sigma_a(const Material *m, const SurfacePoint *sp, float lambda, float bn)
{
    const Hair *H = m->hair;
    if (H->from_color) {
        float c = hair_param(m, HAIR_COLOR, spec_eval(&H->color, lambda), sp, lambda);
        return hair_sigma_a_from_reflectance(fminf(1.0f, fmaxf(0.0f, c)), bn);
    }
    if (H->from_melanin)
        return melanin_sigma_a(H, fmaxf(0.0f, hair_param(m, HAIR_EU, H->eumelanin, sp, lambda)),
                               fmaxf(0.0f, hair_param(m, HAIR_PH, H->pheomelanin, sp, lambda)), lambda);
    return hair_param(m, HAIR_SIGMA_A, spec_eval(&H->sigma_a, lambda), sp, lambda);
}

/* The fibre at sp for the wavelengths lambda (THEORY (32)-(34)); the betas clamped
   to [0.01, 1] and eta kept positive, as pbrt-v4's GetBxDF reads textures. */
static void fibre_at(const Material *m, const SurfacePoint *sp, const float *lambda,
                     unsigned alive, Fibre *F)
{
    const Hair *H = m->hair;
    double bm = fmin(1.0, fmax(0.01, hair_param(m, HAIR_BETA_M, H->beta_m, sp, 550.0f)));
    double bn = fmin(1.0, fmax(0.01, hair_param(m, HAIR_BETA_N, H->beta_n, sp, 550.0f)));
    double a = hair_param(m, HAIR_ALPHA, H->alpha, sp, 550.0f) * SPECNEE_PI / 180.0;
    double v0 = 0.726 * bm + 0.812 * bm * bm + 3.7 * pow(bm, 20.0);
    static const double tilt[HAIR_PMAX + 1] = { -2.0, 1.0, 4.0, 0.0 };   /* x alpha */
    int p, j;
    F->h = -1.0 + 2.0 * sp->v;
    F->h = F->h < -1.0 ? -1.0 : F->h > 1.0 ? 1.0 : F->h;
    F->eta = fmin(100.0, fmax(1e-3, hair_param(m, HAIR_ETA, H->eta, sp, 550.0f)));
    v0 *= v0;
    F->v[0] = v0;
    F->v[1] = 0.25 * v0;
    F->v[2] = F->v[3] = 4.0 * v0;
    F->s = sqrt(SPECNEE_PI / 8.0) * (0.265 * bn + 1.194 * bn * bn + 5.372 * pow(bn, 22.0));
    for (p = 0; p <= HAIR_PMAX; p++) {
        F->sin_tilt[p] = sin(tilt[p] * a);
        F->cos_tilt[p] = cos(tilt[p] * a);
    }
    F->alive = alive;
    for (j = 0; j < HERO_N; j++) {
        double sa = j == 0 || (alive & (1u << j)) ? hair_sigma_a(m, sp, lambda[j], (float)bn) : 0.0;
        F->sigma_a[j] = sa > 0.0 ? (sa < 1e30 ? sa : 1e30) : 0.0;   /* NaN: 0 */
    }
}

/* The wo terms: A_0 = F, A_1 = (1 - F)^2 T, A_2 = A_1 F T, A_3 = A_2 F T / (1 - F T)
   with F the Fresnel reflectance at cos theta_o cos gamma_o and T the
   transmittance of one chord, exp(-sigma_a 2 cos gamma_t / cos theta_t). */
static void fibre_out(const Fibre *F, Vec3 wo, FibreOut *o)
{
    double sin_o = wo.x < -1.0f ? -1.0 : wo.x > 1.0f ? 1.0 : wo.x;
    double cos_o = sqrt(fmax(0.0, 1.0 - sin_o * sin_o));
    double sin_t = sin_o / F->eta, cos_t = sqrt(fmax(0.0, 1.0 - sin_t * sin_t));
    double etap = sqrt(fmax(0.0, F->eta * F->eta - sin_o * sin_o)) / fmax(cos_o, 1e-12);
    double sin_gt = F->h / etap, cos_gt = sqrt(fmax(0.0, 1.0 - sin_gt * sin_gt));
    double fr = fresnel_dielectric((float)(cos_o * sqrt(fmax(0.0, 1.0 - F->h * F->h))), (float)F->eta);
    double sum = 0.0;
    int p, j;
    o->sin_o = sin_o;
    o->cos_o = cos_o;
    o->phi_o = atan2(wo.z, wo.y);
    o->gamma_o = asin(F->h);
    o->gamma_t = asin(sin_gt < -1.0 ? -1.0 : sin_gt > 1.0 ? 1.0 : sin_gt);
    for (j = 0; j < HERO_N; j++) {
        double T = exp(-F->sigma_a[j] * (2.0 * cos_gt / fmax(cos_t, 1e-12)));
        o->ap[0][j] = fr;
        o->ap[1][j] = (1.0 - fr) * (1.0 - fr) * T;
        o->ap[2][j] = o->ap[1][j] * fr * T;
        o->ap[3][j] = 1.0 - fr * T > 0.0 ? o->ap[2][j] * fr * T / (1.0 - fr * T) : 0.0;
    }
    for (p = 0; p <= HAIR_PMAX; p++) {
        o->ap_pdf[p] = 0.0;
        for (j = 0; j < HERO_N; j++)
            if (j == 0 || (F->alive & (1u << j))) o->ap_pdf[p] += o->ap[p][j];
        sum += o->ap_pdf[p];
    }
    for (p = 0; p <= HAIR_PMAX; p++) o->ap_pdf[p] = sum > 0.0 ? o->ap_pdf[p] / sum : 0.0;
}

/* Lobe p's cone: sin and |cos| of theta_o turned by the lobe's tilt. */
static void lobe_theta(const Fibre *F, const FibreOut *o, int p, double *sin_op, double *cos_op)
{
    *sin_op = o->sin_o * F->cos_tilt[p] + o->cos_o * F->sin_tilt[p];
    *cos_op = fabs(o->cos_o * F->cos_tilt[p] - o->sin_o * F->sin_tilt[p]);
}

/* f |cos(wi, n)| per wavelength (fc) and the sampling density (*pdf) of wi. */
static void fibre_eval(const Fibre *F, const FibreOut *o, Vec3 wi, double fc[HERO_N], double *pdf)
{
    double sin_i = wi.x < -1.0f ? -1.0 : wi.x > 1.0f ? 1.0 : wi.x;
    double cos_i = sqrt(fmax(0.0, 1.0 - sin_i * sin_i));
    double phi = atan2(wi.z, wi.y) - o->phi_o, mn[HAIR_PMAX + 1];
    int p, j;
    for (p = 0; p < HAIR_PMAX; p++) {
        double sop, cop, dphi;
        lobe_theta(F, o, p, &sop, &cop);
        dphi = wrap_pi(phi - (2.0 * p * o->gamma_t - 2.0 * o->gamma_o + p * SPECNEE_PI));
        mn[p] = hair_mp(cos_i, cop, sin_i, sop, F->v[p]) * trimmed_logistic(dphi, F->s);
    }
    mn[HAIR_PMAX] = hair_mp(cos_i, o->cos_o, sin_i, o->sin_o, F->v[HAIR_PMAX]) / (2.0 * SPECNEE_PI);
    *pdf = 0.0;
    for (j = 0; j < HERO_N; j++) fc[j] = 0.0;
    for (p = 0; p <= HAIR_PMAX; p++) {
        *pdf += o->ap_pdf[p] * mn[p];
        for (j = 0; j < HERO_N; j++) fc[j] += o->ap[p][j] * mn[p];
    }
}

/* ------------------------------------------------------------------ 3. the BSDF */

/* The hair frame at sp: x along dp/du made normal to ns, z = ns. */
static Frame hair_frame(const SurfacePoint *sp)
{
    Frame fr;
    Vec3 t = v3_sub(sp->dpdu, v3_mul(sp->ns, v3_dot(sp->dpdu, sp->ns)));
    if (!(v3_dot(t, t) > 1e-20f)) return frame_from_normal(sp->ns);  /* a pole: any axis */
    fr.n = sp->ns;
    fr.s = v3_norm(t);
    fr.t = v3_cross(fr.n, fr.s);
    return fr;
}

static void hair_out(double pdf, const double fc[HERO_N], float cos_n, unsigned alive,
                     float f[HERO_N], float pdf_l[HERO_N])
{
    int j;
    for (j = 0; j < HERO_N; j++) {
        pdf_l[j] = (float)pdf;
        f[j] = (alive & (1u << j)) ? (float)(fc[j] / cos_n) : 0.0f;
    }
}

void hair_eval(const Material *m, const SurfacePoint *sp, Vec3 wo, Vec3 wi, const float *lambda,
               unsigned alive, float f[HERO_N], float pdf_l[HERO_N])
{
    Frame fr = hair_frame(sp);
    Vec3 lo = frame_to_local(&fr, wo), li = frame_to_local(&fr, wi);
    Fibre F;
    FibreOut o;
    double fc[HERO_N], pdf;
    int j;
    for (j = 0; j < HERO_N; j++) f[j] = pdf_l[j] = 0.0f;
    if (lo.z == 0.0f || li.z == 0.0f) return;
    fibre_at(m, sp, lambda, alive, &F);
    fibre_out(&F, lo, &o);
    fibre_eval(&F, &o, li, fc, &pdf);
    hair_out(pdf, fc, fabsf(li.z), alive, f, pdf_l);
}

int hair_sample(const Material *m, const SurfacePoint *sp, Vec3 wo, const float *lambda,
                unsigned alive, float u0, float u1, float u2, BsdfSample *out)
{
    Frame fr = hair_frame(sp);
    Vec3 lo = frame_to_local(&fr, wo), li;
    Fibre F;
    FibreOut o;
    double u = u0, c = 0.0, sop, cop, cosT, sinT, sin_i, cos_i, dphi, phi_i, fc[HERO_N], pdf;
    int p;
    if (lo.z == 0.0f) return 0;
    fibre_at(m, sp, lambda, alive, &F);
    fibre_out(&F, lo, &o);
    /* the lobe, in proportion to A_p; u rescaled to [0, 1) within it */
    for (p = 0; p < HAIR_PMAX && u >= c + o.ap_pdf[p]; p++) c += o.ap_pdf[p];
    if (!(o.ap_pdf[p] > 0.0)) return 0;
    u = (u - c) / o.ap_pdf[p];
    u = u < 0.0 ? 0.0 : u < 1.0 ? u : 0x1.fffffffffffffp-1;
    /* theta_i from M_p: a vMF direction around the cone's axis (THEORY (35)) */
    lobe_theta(&F, &o, p, &sop, &cop);
    cosT = 1.0 + F.v[p] * log(fmax(1e-300, u1 + (1.0 - u1) * exp(-2.0 / F.v[p])));
    cosT = cosT < -1.0 ? -1.0 : cosT > 1.0 ? 1.0 : cosT;
    sinT = sqrt(fmax(0.0, 1.0 - cosT * cosT));
    sin_i = -cosT * sop + sinT * cos(2.0 * SPECNEE_PI * u2) * cop;
    sin_i = sin_i < -1.0 ? -1.0 : sin_i > 1.0 ? 1.0 : sin_i;
    cos_i = sqrt(fmax(0.0, 1.0 - sin_i * sin_i));
    /* phi from N_p, or uniformly for the remainder */
    dphi = p < HAIR_PMAX ? 2.0 * p * o.gamma_t - 2.0 * o.gamma_o + p * SPECNEE_PI +
                               sample_trimmed_logistic(u, F.s)
                         : 2.0 * SPECNEE_PI * u;
    phi_i = o.phi_o + dphi;
    li = v3((float)sin_i, (float)(cos_i * cos(phi_i)), (float)(cos_i * sin(phi_i)));
    if (li.z == 0.0f) return 0;
    fibre_eval(&F, &o, li, fc, &pdf);
    if (!(pdf > 0.0)) return 0;
    hair_out(pdf, fc, fabsf(li.z), alive, out->f, out->pdf_l);
    out->pdf = (float)pdf;
    out->wi = frame_to_world(&fr, li);
    out->delta = 0;
    return out->pdf > 0.0f;
}

const SurfacePoint *hair_shade(const Scene *s, const Ray *r, const HitRecord *h,
                               const SurfacePoint *sp, SurfacePoint *out)
{
    ShadingDiff d;
    *out = *sp;
    shading_differentials(s, r, h, out, &d);       /* bump.c: dp/du, and a sphere's (u, v) */
    out->dpdu = d.dpdu;
    return out;
}

/* ------------------------------------------------------------------ 4. the builder */

/* A float parameter k that may be a texture (pbrt-v4's GetFloatTexture). */
static int hair_float(Parser *P, ParamList *pl, const char *name, float def, int k, float *v, Hair *H)
{
    Param *pt = param_find(pl, PT_TEXTURE, name);
    if (pt) {
        int ti = texture_lookup(P, pt, 1);
        H->tex[k] = ti + 1;
        *v = def;
        return ti >= 0;
    }
    return get_float(P, pl, name, def, v);
}

/* A spectrum parameter k that may be a texture: its Param (value or texture), or
   NULL when absent; a texture's index goes to H->tex[k]. */
static int hair_spectrum(Parser *P, ParamList *pl, const char *name, int k, Hair *H, Param **out)
{
    Param *pt = param_find(pl, PT_TEXTURE, name);
    *out = pt ? pt : find_spectrum_param(pl, name);
    if (pt) {
        int ti = texture_lookup(P, pt, 0);
        H->tex[k] = ti + 1;
        return ti >= 0;
    }
    return 1;
}

/* The melanins: a constant pair becomes sigma_a at load (pbrt-v4's
   SigmaAFromConcentration); with a texture the ratio table H->mel_c is built and
   sigma_a is made at each hit (melanin_sigma_a). */
static int hair_melanin(Parser *P, ParamList *pl, const char *file, int line, int given, Hair *H)
{
    float rgb[3];
    int k, nm;
    if (!hair_float(P, pl, "eumelanin", given ? 0.0f : 1.3f, HAIR_EU, &H->eumelanin, H) ||
        !hair_float(P, pl, "pheomelanin", 0.0f, HAIR_PH, &H->pheomelanin, H))
        return 0;
    if (H->tex[HAIR_EU] || H->tex[HAIR_PH]) {
        H->from_melanin = 1;
        for (k = 0; k < HAIR_MEL_N; k++) {
            double target[3], c[3], mx;
            float t = (float)k / (HAIR_MEL_N - 1);
            int i;
            hair_melanin_rgb(1.0f - t, t, rgb);
            mx = 2.0 * fmax(rgb[0], fmax(rgb[1], rgb[2]));
            for (i = 0; i < 3; i++) target[i] = rgb[i] / mx;
            spec_rgb_coeffs(rgb_srgb_table(P), target, c);
            for (i = 0; i < 3; i++) H->mel_c[k][i] = (float)c[i];
        }
        return 1;
    }
    hair_melanin_rgb(fmaxf(0.0f, H->eumelanin), fmaxf(0.0f, H->pheomelanin), rgb);
    if (!spec_from_rgb_t(rgb_srgb_table(P), &H->sigma_a, rgb, 2, P->err, file, line)) return 0;
    for (nm = 0; nm < SPEC_UV_N; nm++) H->sigma_a.uv[nm] = H->sigma_a.v[0];
    return 1;
}

/* pbrt-v4 HairMaterial::Create: the absorption from "sigma_a", else from
   "reflectance" (or its older name "color"), else from "eumelanin" and
   "pheomelanin", else eumelanin 1.3 (brown); the ones left aside are noted, as
   pbrt-v4 warns.  Each may be a texture. */
static int hair_colour(Parser *P, ParamList *pl, const char *file, int line, const char *what,
                       Hair *H)
{
    Param *ps, *pr, *pe, *pp;
    int nm;
    if (!hair_spectrum(P, pl, "sigma_a", HAIR_SIGMA_A, H, &ps) ||
        !hair_spectrum(P, pl, "reflectance", HAIR_COLOR, H, &pr))
        return 0;
    if (!pr && !hair_spectrum(P, pl, "color", HAIR_COLOR, H, &pr)) return 0;
    pe = param_find(pl, PT_TEXTURE, "eumelanin");
    pp = param_find(pl, PT_TEXTURE, "pheomelanin");
    if (!pe) pe = param_find(pl, PT_FLOAT, "eumelanin");
    if (!pp) pp = param_find(pl, PT_FLOAT, "pheomelanin");
    if ((ps && (pr || pe || pp)) || (pr && (pe || pp)))
        fprintf(stderr, "%s:%d: note: %s: \"%s\" given: %s ignored, as pbrt-v4 does\n",
                (ps ? ps : pr)->file, (ps ? ps : pr)->line, what, ps ? "sigma_a" : pr->name,
                ps ? "\"reflectance\", \"eumelanin\" and \"pheomelanin\" are" : "the melanins are");
    if (ps && ps->type == PT_TEXTURE) {
        H->tex[HAIR_COLOR] = 0;
        return 1;
    }
    if (ps) {
        H->tex[HAIR_COLOR] = 0;
        if (!param_spectrum(P, ps, SPEC_COEFF, &H->sigma_a, NULL)) return 0;
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++)
            if (!(spec_get(&H->sigma_a, nm) >= 0.0f) || !(spec_get(&H->sigma_a, nm) <= FLT_MAX))
                return fail(P, ps->file, ps->line, "\"%s sigma_a\": value %g at %d nm is not "
                            "an absorption coefficient (>= 0, finite)", param_type_names[ps->type],
                            spec_get(&H->sigma_a, nm), nm);
        if (ps->type == PT_RGB)          /* no UV in an rgb spectrum: its 360 nm value */
            for (nm = 0; nm < SPEC_UV_N; nm++) H->sigma_a.uv[nm] = H->sigma_a.v[0];
        return 1;
    }
    if (pr) {
        H->from_color = 1;                 /* clamped to [0, 1] where it is used */
        return pr->type == PT_TEXTURE || param_spectrum(P, pr, SPEC_ALBEDO, &H->color, NULL);
    }
    return hair_melanin(P, pl, file, line, pe || pp, H);
}

int hair_from_params(Parser *P, ParamList *pl, const char *file, int line,
                     const char *dir, const char *what, Material *m)
{
    Hair *H;
    (void)dir;
    m->type = MAT_HAIR;
    m->hair = H = (Hair *)calloc(1, sizeof *H);         /* freed by material_release */
    if (!H) return oom(P, file, line);
    if (!normalmap_ignored(P, pl, what, "pbrt-v4's hair material has no normal map "
                           "(HairMaterial::GetNormalMap returns none)"))
        return 0;
    if (!hair_colour(P, pl, file, line, what, H)) return 0;
    if (!hair_float(P, pl, "eta", 1.55f, HAIR_ETA, &H->eta, H) ||
        !hair_float(P, pl, "beta_m", 0.3f, HAIR_BETA_M, &H->beta_m, H) ||
        !hair_float(P, pl, "beta_n", 0.3f, HAIR_BETA_N, &H->beta_n, H) ||
        !hair_float(P, pl, "alpha", 2.0f, HAIR_ALPHA, &H->alpha, H))
        return 0;
    if (!params_check_unused(P, pl, what, "spectrum sigma_a, rgb sigma_a, texture sigma_a, "
                             "spectrum reflectance, rgb reflectance, texture reflectance, "
                             "spectrum color, rgb color, texture color, float eumelanin, "
                             "texture eumelanin, float pheomelanin, texture pheomelanin, "
                             "float eta, texture eta, float beta_m, texture beta_m, float beta_n, "
                             "texture beta_n, float alpha, texture alpha, string normalmap", NULL))
        return 0;
    if (!(H->eta > 0.0f && H->eta <= 100.0f))
        return fail_param(P, pl, "eta", file, line, "%s: \"float eta\" %g is not an index of "
                          "refraction (0 < eta <= 100)", what, H->eta);
    if (!(fabsf(H->alpha) <= 90.0f))
        return fail_param(P, pl, "alpha", file, line, "%s: \"float alpha\" %g is not a scale "
                          "tilt in degrees (-90 to 90)", what, H->alpha);
    if (!(fabsf(H->beta_m) <= FLT_MAX) || !(fabsf(H->beta_n) <= FLT_MAX))
        return fail(P, file, line, "%s: \"beta_m\" and \"beta_n\" must be finite", what);
    H->beta_m = fminf(1.0f, fmaxf(0.01f, H->beta_m));   /* pbrt-v4's GetBxDF clamps them */
    H->beta_n = fminf(1.0f, fmaxf(0.01f, H->beta_n));
    return 1;
}
