/* dump.c - --dump-scene: what the scene parser understood, in plain text.

   Implements scene_dump (specnee.h section 8): the settings, the camera, the
   materials, emitters (with their spectra sampled every 50 nm), media and
   shapes of a loaded Scene, printed to a FILE.  It reads only the Scene, so it
   shows what the renderer will see, after every default and normalisation.

   USE
     Scene s; Error err;
     if (scene_load(&s, "scenes/cornell.pbrt", &err)) scene_dump(&s, stdout); */
#include "specnee.h"
#include <string.h>

static void dump_spectrum(FILE *f, const char *label, const Spectrum *sp)
{
    int l;
    fprintf(f, "    %-12s", label);
    for (l = 400; l <= 700; l += 50) fprintf(f, " %3d:%-8.4g", l, spec_eval(sp, (float)l));
    fprintf(f, "\n");
}

/* A material's reflectance, as dump_spectrum prints a table */
static void dump_albedo(FILE *f, const char *label, const Albedo *a)
{
    int l;
    fprintf(f, "    %-12s", label);
    for (l = 400; l <= 700; l += 50) fprintf(f, " %3d:%-8.4g", l, albedo_eval(a, (float)l));
    fprintf(f, "\n");
}

/* Material i: its type, parameters and spectra. */
static void dump_material(FILE *f, int i, const Material *m)
{
    if (m->type == MAT_DIFFUSE) {
        fprintf(f, "  [%d] diffuse\n", i);
        dump_albedo(f, "reflectance", &m->reflectance);
    } else if (m->type == MAT_FLUORESCENT) {
        fprintf(f, "  [%d] fluorescent, quantum yield %g\n", i, m->fl->qyield);
        dump_albedo(f, "reflectance", &m->reflectance);
        dump_spectrum(f, "excitation", &m->fl->excitation);
        dump_spectrum(f, "emission", &m->fl->emission);
    } else if (m->type == MAT_CONDUCTOR) {
        fprintf(f, "  [%d] conductor, alpha %g\n", i, m->alpha);
        dump_spectrum(f, "eta", m->eta);
        dump_spectrum(f, "k", &m->extra->k);
    } else if (m->type == MAT_THIN_DIELECTRIC) {
        fprintf(f, "  [%d] thindielectric\n", i);
        dump_spectrum(f, "eta", m->eta);
    } else if (m->type == MAT_COATED_DIFFUSE) {
        fprintf(f, "  [%d] coateddiffuse, alpha %g, eta %g, thickness %g, g %g, maxdepth %d, "
                "nsamples %d\n", i, m->alpha, spec_eval(m->eta, 550.0f), m->thickness,
                m->hg_g, m->maxdepth, m->nsamples);
        dump_albedo(f, "reflectance", &m->reflectance);
        dump_spectrum(f, "albedo", &m->extra->albedo);
    } else if (m->type == MAT_INTERFACE) {
        fprintf(f, "  [%d] interface (no surface: the boundary of a medium)\n", i);
    } else if (m->type == MAT_COATED_CONDUCTOR) {
        fprintf(f, "  [%d] coatedconductor, interface alpha %g, eta %g, conductor alpha %g, "
                "thickness %g, g %g, maxdepth %d, nsamples %d\n", i, m->alpha,
                spec_eval(m->eta, 550.0f), m->cond_alpha, m->thickness, m->hg_g, m->maxdepth,
                m->nsamples);
        dump_spectrum(f, "conductor eta", &m->extra->cond_eta);
        dump_spectrum(f, "conductor k", &m->extra->k);
        dump_spectrum(f, "albedo", &m->extra->albedo);
    } else if (m->type == MAT_MIX) {
        fprintf(f, "  [%d] mix of [%d] and [%d], amount ", i, m->mix[0], m->mix[1]);
        if (m->amount_tex > 0) fprintf(f, "texture %d\n", m->amount_tex - 1);
        else fprintf(f, "%g\n", m->amount);
    } else if (m->type == MAT_HAIR) {
        fprintf(f, "  [%d] hair, eta %g, beta_m %g, beta_n %g, alpha %g degrees\n", i, m->hair->eta,
                m->hair->beta_m, m->hair->beta_n, m->hair->alpha);
        dump_spectrum(f, m->hair->from_color ? "reflectance" : "sigma_a",
                      m->hair->from_color ? &m->hair->color : &m->hair->sigma_a);
    } else if (m->type == MAT_DIFFUSE_TRANSMISSION) {
        fprintf(f, "  [%d] diffusetransmission, P(reflect lobe) %g\n", i, m->p_reflect);
        dump_albedo(f, "reflectance", &m->reflectance);
        dump_spectrum(f, "transmittance", &m->extra->transmittance);
    } else if (m->type == MAT_SUBSURFACE) {
        fprintf(f, "  [%d] subsurface, alpha %g, eta %g, g %g, scale %g, %s\n", i, m->alpha,
                m->sss->eta, m->sss->g, m->sss->scale,
                m->sss->from_albedo ? "from reflectance and mfp" : "sigma_a, sigma_s");
        if (!m->sss->from_albedo) {
            dump_spectrum(f, "sigma_a", &m->sss->sigma_a);
            dump_spectrum(f, "sigma_s", &m->sss->sigma_s);
        }
    } else if (m->type == MAT_MEASURED) {
        fprintf(f, "  [%d] measured, %s, %d x %d visible-normal grid, %d wavelengths\n", i,
                m->measured->isotropic ? "isotropic" : "anisotropic", m->measured->vndf.nx,
                m->measured->vndf.ny, m->measured->n_wavelengths);
    } else {
        fprintf(f, "  [%d] dielectric, alpha %g, %s", i, m->alpha,
                m->dispersive ? "dispersive" : "constant eta");
        if (m->cauchy_a > 0) fprintf(f, ", Cauchy A %g B %g um^2", m->cauchy_a, m->cauchy_b);
        fprintf(f, "\n    eta at F 486.1: %.5f  d 587.6: %.5f  C 656.3: %.5f\n",
                spec_eval(m->eta, 486.1f), spec_eval(m->eta, 587.6f),
                spec_eval(m->eta, 656.3f));
    }
}

/* Emitter i: its kind, scale, luminance and power over the sampled range. */
static void dump_emitter(FILE *f, const Scene *s, int i)
{
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
                "power %.4g\n", i, e->delta.type == DELTA_SPOT ? "spot" :
                e->delta.type == DELTA_GONIO ? "goniometric" :
                e->delta.type == DELTA_PROJECTION ? "projection" : "point",
                e->delta.p.x, e->delta.p.y, e->delta.p.z, e->scale, Y,
                LAMBDA_LO, LAMBDA_HI, SPECNEE_PI * e->area * bins);
    else
        fprintf(f, "  [%d] shape %d, scale %g, %s, Y(Le) %.4g over %g-%g nm, area %g, power "
                "%.4g\n", i, e->shape, e->scale, e->twosided ? "two-sided" : "one-sided", Y,
                LAMBDA_LO, LAMBDA_HI, e->area,
                SPECNEE_PI * e->area * (e->twosided ? 2.0 : 1.0) * bins);
    dump_spectrum(f, "L (as given)", e->L);
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
    if (st->lens.n) {   /* the realistic camera (lens.c) */
        fprintf(f, "camera: realistic, %d lens interfaces, focused at %g, film %g mm behind "
                "the rear one, diagonal %g mm", st->lens.n, st->focus_distance,
                st->lens.e[st->lens.n - 1].thickness * 1e3, st->film_diagonal);
    } else if (st->camera_type == CAMERA_EQUAL_AREA || st->camera_type == CAMERA_EQUIRECT) {
        fprintf(f, "camera: spherical, mapping %s",
                st->camera_type == CAMERA_EQUAL_AREA ? "equalarea" : "equirectangular");
    } else {
        if (st->camera_type == CAMERA_ORTHOGRAPHIC) fprintf(f, "camera: orthographic");
        else fprintf(f, "camera: perspective, fov %g deg (shorter image axis)", st->fov_deg);
        if (st->screen_set || st->frame_aspect > 0.0f || st->camera_type == CAMERA_ORTHOGRAPHIC) {
            /* pbrt-v4's window, as camera.c uses it */
            float sw[4];
            camera_screen_window(st, sw);
            fprintf(f, ", screen window [%g %g %g %g]", sw[0], sw[1], sw[2], sw[3]);
        }
        if (st->lens_radius > 0.0f)
            fprintf(f, ", thin lens: lensradius %g focaldistance %g", st->lens_radius,
                    st->focal_distance);
        else
            fprintf(f, ", pinhole (lensradius 0)");
    }
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
        fprintf(f, "\n  sensor %s, imaging ratio %g (iso x exposure / 100), "
                "maxcomponentvalue %g, whitebalance ", sensor_name(st->sensor), st->imaging_ratio,
                st->max_component);
        if (st->white_balance > 0.0f) fprintf(f, "%g K", st->white_balance);
        else fprintf(f, "none");
        if (film_bounds(st, b) && (st->crop_set || st->pixel_bounds_set))
            fprintf(f, "\n  %s: renders and writes pixels x %d..%d, y %d..%d (%d x %d)",
                    st->crop_set ? "cropwindow" : "pixelbounds", b[0], b[1] - 1, b[2],
                    b[3] - 1, b[1] - b[0], b[3] - b[2]);
        if (st->spectral)
            fprintf(f, "\n  spectral: %d buckets over %g..%g nm (wavelengths uniform there), EXR %s",
                    st->nbuckets, st->lambda_min, st->lambda_max, st->savefp16 ? "half" : "float");
    }
    fprintf(f, "\nsettings: spp %d%s, seed %d%s, maxdepth %d%s, lightsampler \"%s\"\n",
            st->spp, st->spp_set ? "" : " (default)", st->seed, st->seed_set ? "" : " (default)",
            st->maxdepth, st->maxdepth_set ? "" : " (default)", st->lightsampler);
    for (i = 0; i < s->n_insets; i++)
        fprintf(f, "inset %s: x %d..%d, y %d..%d\n", s->inset_name[i], s->inset[i][0],
                s->inset[i][2], s->inset[i][1], s->inset[i][3]);
    fprintf(f, "materials: %d\n", s->n_materials);
    for (i = 0; i < s->n_materials; i++) dump_material(f, i, &s->materials[i]);
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
        else if (sh->type == SHAPE_CURVE)
            fprintf(f, "  [%d] curve (object space)", i);
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
        fprintf(f, "  [%d] \"%s\" %s, g %g, sigma_t at 450/550/650 nm: %g %g %g, "
                "albedo at 550 nm %g%s\n", i, m->name,
                m->type == MEDIUM_UNIFORMGRID ? "uniformgrid (times its density)"
                : m->type == MEDIUM_RGBGRID ? "rgbgrid (sigma from its rgb grids)"
                : m->type == MEDIUM_CLOUD ? "cloud (times its density)"
                : m->type == MEDIUM_NANOVDB ? "nanovdb (times its density grid)" : "homogeneous",
                m->g, medium_sigma_t(m, 450.0f),
                medium_sigma_t(m, 550.0f), medium_sigma_t(m, 650.0f),
                medium_sigma_t(m, 550.0f) > 0.0f ? medium_sigma_s(m, 550.0f) / medium_sigma_t(m, 550.0f) : 0.0f,
                m->Le_scale > 0.0f ? ", emissive" : "");
    }
    fprintf(f, "emitters: %d\n", s->n_emitters);
    for (i = 0; i < s->n_emitters; i++) dump_emitter(f, s, i);
    fprintf(f, "bounds: (%g, %g, %g) - (%g, %g, %g)\n", s->bmin.x, s->bmin.y, s->bmin.z,
            s->bmax.x, s->bmax.y, s->bmax.z);
}
