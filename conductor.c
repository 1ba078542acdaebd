/* conductor.c - metals: pbrt-v4's "conductor" material, the Fresnel reflectance of
   a complex index of refraction over a smooth (delta) or rough (anisotropic
   Trowbridge-Reitz / GGX) surface.

   Exported: conductor_sample, conductor_eval (specnee.h section 6).  material.c's
   bsdf_sample and bsdf_eval call them in the shading frame (n = +z, directions
   pointing away from the surface, f without the cosine, as everywhere).  The
   pieces come from the scattering room, microfacet.c: fresnel_conductor,
   conductor_k_of_reflectance, reflect_dir and the distribution tr_D, tr_G,
   tr_sample_wm, tr_pdf_wm; this room calls no other.

   1. Fresnel for a conductor (microfacet.c section 2): the metal's index is
      complex, eta_c = n + i k (n: the "eta" spectrum, k: the extinction
      coefficient), and F(cos) is the unpolarised Fresnel reflectance of it.  No
      light is transmitted (it is absorbed within a skin depth), so 1 - F is lost.

   2. Smooth (max(alpha_x, alpha_y) < 1e-3, pbrt-v4's EffectivelySmooth, tr_smooth): the
      mirror direction wi = (-wo.x, -wo.y, wo.z) with probability 1; as a delta
      lobe its "f" is F(|cos i|) / |cos i| and its pdf 1, so the path weight
      f |cos| / pdf is F: each wavelength keeps F of its own.

   3. Rough: the Torrance-Sparrow microfacet BRDF with the anisotropic
      Trowbridge-Reitz distribution D and the height-correlated Smith G
      (microfacet.c section 3), in the local frame, wm = normalize(wo + wi)
      turned to +z:
          f(wo, wi) = D(wm) F(|wo.wm|) G(wo, wi) / (4 |cos i| |cos o|)
      Directions: a visible normal wm ~ D_wo(wm) = G1(wo) |wo.wm| D(wm) / |cos o|
      (Heitz 2018: stretch wo by (ax, ay), sample the projected hemisphere,
      unstretch), then wi = reflect(wo, wm); the Jacobian of the reflection,
      dwm/dwi = 1/(4 |wo.wm|), gives p(wi) = D_wo(wm) / (4 |wo.wm|).  The
      direction does not depend on the wavelength, so every wavelength has the
      same pdf (pdf_l[j] = pdf) and only F differs.  A wo below the surface (a
      back face) is handled by symmetry: the visible normals of -wo are sampled
      and wi stays on wo's side.

   4. Textures (pbrt-v4 evaluates a material's textures at the hit, in GetBxDF):
      the alphas and a "texture reflectance" come in a MatPoint (material.c's
      mat_point), so one conductor can be smooth at one point and rough at another.

   5. Parameters (conductor_eta_k, also coatedconductor's "conductor." base): eta
      and k as spectra, or "rgb" as pbrt-v4's RGBUnboundedSpectrum; valid when
      eta > 0 and k >= 0 over pbrt-v4's 360-830 nm, continued below 360 nm (which
      only fluorescence traces) by their lowest value with data.

   The anisotropy's axes are the shading frame's s and t: alpha_x ("uroughness")
   along s, alpha_y ("vroughness") along t.  As in pbrt-v4, s is the surface's
   shading dp/du made tangent to ns (a triangle's "S" when it has them): path.c
   gives an anisotropic conductor's hit its dp/du (bump.c tangent_shade) and
   material.c's mat_frame builds the frame from it. */
#include "specnee.h"

/* F of wavelength j (lambda) at the microfacet cosine c.  A textured reflectance r
   stands for eta = 1, k = conductor_k_of_reflectance(r), r clamped to [0, 0.9999]
   (conductor_from_params does the same for a constant r). */
static float conductor_F(const Material *m, const MatPoint *mp, int j, float c, float lambda_nm)
{
    if (mp->has_ek) return fresnel_conductor(c, mp->eta[j], mp->k[j]);   /* textured */
    if (mp->has_r) {
        double r = mp->r[j] < 0.9999f ? mp->r[j] : 0.9999;
        return fresnel_conductor(c, 1.0f, conductor_k_of_reflectance(r));
    }
    return fresnel_conductor(c, spec_eval(m->eta, lambda_nm), spec_eval(&m->extra->k, lambda_nm));
}

/* f and pdf of the rough conductor for a pair of local directions (0 when they
   lie on different sides or the pair has no half vector). */
static void rough_pair(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                       unsigned alive, float f[HERO_N], float pdf_l[HERO_N])
{
    float ax = mp->alpha, ay = mp->alpha_t, cos_o = fabsf(wo.z), cos_i = fabsf(wi.z), D, G, pdf, c;
    Vec3 wm;
    int j;
    for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
    tr_rough_floor(&ax, &ay);                /* an axis of alpha 0 beside a rough one: 1e-4 */
    if (wo.z * wi.z <= 0.0f) return;         /* a BRDF: both on one side */
    if (!tr_half_vector(wo, wi, &wm)) return;
    c = fabsf(v3_dot(wo, wm));
    if (c == 0.0f) return;
    D = tr_D(ax, ay, wm);
    G = tr_G(ax, ay, wo, wi);
    pdf = tr_pdf_reflect(ax, ay, wo, wm);
    for (j = 0; j < HERO_N; j++) {
        pdf_l[j] = pdf;                      /* the same direction for every wavelength */
        if (alive & (1u << j))
            f[j] = D * G * conductor_F(m, mp, j, c, lambda[j]) / (4.0f * cos_i * cos_o);
    }
}

int conductor_sample(const Material *m, const MatPoint *mp, Vec3 wo, const float *lambda,
                     unsigned alive, float u1, float u2, BsdfSample *out, Vec3 *wi_local)
{
    Vec3 wi, wm;
    float ax = mp->alpha, ay = mp->alpha_t;
    int j;
    for (j = 0; j < HERO_N; j++) { out->f[j] = 0.0f; out->pdf_l[j] = 0.0f; }
    out->delta = 0;
    if (wo.z == 0.0f) return 0;
    if (tr_smooth(mp->alpha, mp->alpha_t)) {
        wi = v3(-wo.x, -wo.y, wo.z);         /* the mirror direction */
        out->delta = 1;
        out->pdf = 1.0f;
        for (j = 0; j < HERO_N; j++) {
            out->pdf_l[j] = 1.0f;
            if (alive & (1u << j))
                out->f[j] = conductor_F(m, mp, j, fabsf(wi.z), lambda[j]) / fabsf(wi.z);
        }
        *wi_local = wi;
        return 1;
    }
    tr_rough_floor(&ax, &ay);
    wm = tr_sample_wm(ax, ay, wo, u1, u2);
    wi = reflect_dir(wo, wm);
    if (wi.z * wo.z <= 0.0f) return 0;       /* reflected below the surface: no sample */
    wi = v3_norm(wi);
    rough_pair(m, mp, wo, wi, lambda, alive, out->f, out->pdf_l);
    out->pdf = out->pdf_l[0];
    *wi_local = wi;
    return out->pdf > 0.0f;
}

void conductor_eval(const Material *m, const MatPoint *mp, Vec3 wo, Vec3 wi, const float *lambda,
                    unsigned alive, float f[HERO_N], float pdf_l[HERO_N])
{
    int j;
    if (tr_smooth(mp->alpha, mp->alpha_t)) {               /* delta: f = 0 for any given pair */
        for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
        return;
    }
    rough_pair(m, mp, wo, wi, lambda, alive, f, pdf_l);
}

/* ---------------------------------------------------------------------------
   ---- building from scene parameters
   conductor_from_params: the scene builder's (scene.c) "conductor" material,
   read from its parameters (parser.h).
   --------------------------------------------------------------------------- */
#include "parser.h"

/* pbrt-v4's conductor "reflectance" r (conductor and coatedconductor): read as
   an albedo in [0, 1]; then eta = 1 and k = 2 sqrt(r) / sqrt(1 - r) with r
   clamped to 0.9999, which makes the normal-incidence reflectance
   ((eta-1)^2 + k^2) / ((eta+1)^2 + k^2) = k^2 / (4 + k^2) exactly r. */
int conductor_reflectance_param(Parser *P, Param *pr, Spectrum *refl, Spectrum *eta, Spectrum *k)
{
    int nm;
    if (!param_spectrum(P, pr, SPEC_ALBEDO, refl, NULL)) return 0;
    if (!check_unit_spectrum(P, pr, refl)) return 0;
    spec_const(eta, 1.0f);
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
        double r = spec_get(refl, nm);
        if (r > 0.9999) r = 0.9999;
        *spec_at(k, nm) = conductor_k_of_reflectance(r);
    }
    return 1;
}

/* The UV extension (300-359 nm) of a conductor's eta or k, where its data does
   not reach: pbrt-v4 samples 360-830 nm only, so a spectrum is valid for it when
   it is valid there; below, specnee (whose fluorescence may trace a UV
   wavelength) continues the lowest value it has.  A run of zeros at the bottom of
   the extension is read as "no data" (spec_from_pairs' zero outside the pairs;
   an rgb spectrum has no UV at all) and takes the value of the first nm above it
   that is not zero, or of 360 nm. */
static void conductor_uv_continue(Spectrum *s)
{
    int n0 = SPEC_UV_MIN, nm;
    while (n0 < SPEC_MIN && spec_get(s, n0) == 0.0f) n0++;
    for (nm = SPEC_UV_MIN; nm < n0; nm++) *spec_at(s, nm) = spec_get(s, n0);
}

/* One of eta, k: pbrt-v4 reads "rgb" as an RGBUnboundedSpectrum (SPEC_COEFF),
   a spectrum as it is; Cu's named spectrum when absent. */
static int conductor_spectrum(Parser *P, Param *p, const char *cu, Spectrum *out)
{
    if (!p) return spec_named(out, cu);
    return param_spectrum(P, p, p->type == PT_RGB ? SPEC_COEFF : SPEC_UNBOUNDED, out, NULL);
}

/* pbrt-v4 ConductorMaterial's (and CoatedConductorMaterial's "conductor.")
   eta and k.  Checked over pbrt-v4's 360-830 nm (eta > 0: eta = k = 0 gives
   pbrt-v4's Fresnel term 0/0; k >= 0), then continued into the UV extension
   (conductor_uv_continue) and checked there too. */
int conductor_eta_k(Parser *P, ParamList *pl, const char *file, int line,
                    const char *prefix, Spectrum *eta, Spectrum *k)
{
    char ne[32], nk[32], we[96], wk[96];
    const char *owner = prefix[0] ? "coatedconductor" : "conductor";
    Param *pe, *pk;
    snprintf(ne, sizeof ne, "%seta", prefix);
    snprintf(nk, sizeof nk, "%sk", prefix);
    pe = find_spectrum_param(pl, ne);
    pk = find_spectrum_param(pl, nk);
    if (!conductor_spectrum(P, pe, "metal-Cu-eta", eta) ||
        !conductor_spectrum(P, pk, "metal-Cu-k", k))
        return 0;
    snprintf(we, sizeof we, "\"%s %s\" of a %s", pe && pe->type == PT_RGB ? "rgb" : "spectrum",
             ne, owner);
    snprintf(wk, sizeof wk, "\"%s %s\" of a %s", pk && pk->type == PT_RGB ? "rgb" : "spectrum",
             nk, owner);
    if (!check_spectrum_above_from(P, pe, file, line, we, eta, 0.0f, 1, SPEC_MIN) ||
        !check_spectrum_above_from(P, pk, file, line, wk, k, 0.0f, 0, SPEC_MIN))
        return 0;
    conductor_uv_continue(eta);
    conductor_uv_continue(k);
    return check_spectrum_above(P, pe, file, line, we, eta, 0.0f, 1) &&
           check_spectrum_above(P, pk, file, line, wk, k, 0.0f, 0);
}

/* Whether spectrum texture t (and the textures it reads) means what pbrt-v4's
   unbounded version of it means: specnee's spectrum textures are pbrt-v4's albedo
   ones, the same numbers for spectra, constants and grey RGB; an imagemap or a
   marble (texels fitted as reflectances, clamped to [0, 1]) or a non-grey "rgb"
   argument (RGBAlbedoSpectrum where pbrt-v4 reads RGBUnboundedSpectrum) differs.
   Returns the first one that differs, or -1. */
static int texture_not_unbounded(const Scene *s, int t)
{
    const Texture *T = &s->textures[t];
    int a;
    if (T->is_float) return -1;
    if (T->type == TEX_IMAGEMAP || T->type == TEX_MARBLE || T->rgb_arg) return t;
    for (a = 0; a < TEX_ARGS; a++)
        if (T->arg_tex[a] >= 0 && T->arg_tex[a] < t) {
            int b = texture_not_unbounded(s, T->arg_tex[a]);
            if (b >= 0) return b;
        }
    return -1;
}

/* "texture eta" and "texture k" (prefix "conductor." for coatedconductor): spectrum
   textures read at each hit as unbounded spectra (pbrt-v4's GetSpectrumTextureOrNull
   with SpectrumType::Unbounded), into x->eta_tex, x->k_tex; the other of the two,
   when not textured, keeps its spectrum (Cu's by default). */
int conductor_eta_k_textures(Parser *P, ParamList *pl, const char *prefix, const char *what,
                             MaterialSpectra *x)
{
    static const char *const names[2] = { "eta", "k" };
    int i;
    for (i = 0; i < 2; i++) {
        char nm[32];
        Param *pt;
        int t, bad;
        snprintf(nm, sizeof nm, "%s%s", prefix, names[i]);
        pt = param_find(pl, PT_TEXTURE, nm);
        if (!pt) continue;
        if (find_spectrum_param(pl, nm))
            return fail(P, pt->file, pt->line, "%s: give either a spectrum or a texture "
                        "\"%s\", not both", what, nm);
        t = texture_lookup(P, pt, 0);
        if (t < 0) return 0;
        bad = texture_not_unbounded(P->s, t);
        if (bad >= 0)
            return fail(P, pt->file, pt->line, "%s: \"texture %s\" reads a texture of RGB "
                        "reflectances (%s:%d: an imagemap, a marble or a non-grey \"rgb\"), "
                        "which pbrt-v4 reads as unbounded spectra here: valid pbrt-v4 but "
                        "not in the specnee subset (give spectra or grey values)", what, nm,
                        P->s->textures[bad].file, P->s->textures[bad].line);
        if (i == 0) x->eta_tex = t + 1; else x->k_tex = t + 1;
    }
    return 1;
}

/* pbrt-v4 ConductorMaterial: eta and k, or a reflectance that
   stands for them; Cu by default */
int conductor_from_params(Parser *P, ParamList *pl, const char *file, int line,
                          const char *dir, const char *what, Material *m)
{
    Param *pe = find_spectrum_param(pl, "eta"), *pk = find_spectrum_param(pl, "k");
    Param *pr = find_spectrum_param(pl, "reflectance");
    Param *pt = param_find(pl, PT_TEXTURE, "reflectance");
    int ek_tex = (param_find(pl, PT_TEXTURE, "eta") != NULL) + (param_find(pl, PT_TEXTURE, "k") != NULL);
    Spectrum n;                     /* eta, shared once built (material_set_eta) */
    (void)dir;
    spec_const(&n, 1.0f);
    m->type = MAT_CONDUCTOR;
    if (!material_extra(m)) return oom(P, file, line);   /* k (freed by material_release) */
    if (!microfacet_alphas(P, pl, file, line, what, m)) return 0;
    if (!bump_from_params(P, pl, what, m) ||
        !params_check_unused(P, pl, what, "spectrum eta, spectrum k, rgb eta, rgb k, "
                             "texture eta, texture k, spectrum reflectance, rgb reflectance, texture reflectance, float roughness, "
                             "float uroughness, float vroughness, texture roughness, "
                             "texture uroughness, texture vroughness, bool remaproughness",
                             NULL))
        return 0;
    if ((pr || pt) && (pe || pk || ek_tex))
        return fail(P, file, line, "%s: give either \"reflectance\" or \"eta\" and \"k\", "
                    "not both (pbrt-v4 refuses it too)", what);
    if (pt) {
        /* "texture reflectance": r read at each hit (material.c mat_point), eta = 1
           and k from r there (conductor_k_of_reflectance) */
        int ti = texture_lookup(P, pt, 0);
        if (ti < 0) return 0;
        m->reflectance_tex = ti + 1;
        spec_const(&n, 1.0f);
        spec_const(&m->extra->k, 0.0f);                  /* (not read) */
    } else if (pr) {
        Spectrum r;                 /* r, shared (albedo_set_table) */
        if (!conductor_reflectance_param(P, pr, &r, &n, &m->extra->k) ||
            !albedo_set_table(P, &m->reflectance, &r, file, line))
            return 0;
    } else {
        if (!conductor_eta_k_textures(P, pl, "", what, m->extra) ||
            !conductor_eta_k(P, pl, file, line, "", &n, &m->extra->k))
            return 0;
    }
    return material_set_eta(P, m, &n, file, line);
}
