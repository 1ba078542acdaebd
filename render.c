/* render.c - a render: its options, its state, and the film the samples go to.

   Exported (specnee.h section 12): render_options_default, render_options_thesis,
   render, render_ladder, render_begin, render_advance, render_image, render_stats,
   render_end, render_spectral, img_write_spectral.  The camera is in camera.c, the path estimator in path.c; render.h
   holds what the three share (Renderer, FilmSample, Counters).

   A RENDER.  render_begin builds the Renderer: the emitters' radiance for the
   sampled wavelength range and their selection tables (lights.c), the wavelength
   pdf p (wavelengths.c, THEORY §2), the camera, the pixel filter, the samplers and
   the normalised emission of emissive media.  The Scene is only read.

   THE FILM (THEORY (9)).  For each sample of a pixel, render_pass picks the
   position in the pixel and its filter weight (filter.c), the wavelengths
   lambda_j (wl_sample) and the lens point, and path.c's trace_path fills a
   FilmSample with sum_j (xbar, ybar, zbar)(lambda_j) C_j: an estimate of the
   integrals of xbar L, ybar L, zbar L over the sampled range, not divided by the
   integral of ybar (emitters are normalised instead, as in pbrt-v4); with a
   camera sensor its curves replace xbar, ybar, zbar (sensor.c).  The sensor
   then scales it by the imaging ratio and clamps its largest component (pbrt-v4's
   RGBFilm::AddSample); a pixel is the mean of its samples (with mitchell or sinc,
   sum fw XYZ / sum fw), mapped to XYZ by the sensor's matrix (white balance,
   camera), converted to linear sRGB with pbrt-v4's
   matrix.  A sample whose XYZ is not finite is dropped (counted; it counts as 0).

   THE SPECTRAL FILM (pbrt-v4's Film "spectral", THEORY §9.1).  The camera samples
   its four wavelengths uniformly in [lambdamin, lambdamax] and the emitters are
   normalised over 360..830 nm, as pbrt-v4's; the RGB image is made as above.  Each
   of the four lanes also goes to the bucket (of nbuckets equal bands) its
   wavelength falls in, as each of pbrt-v4's four does: with the radiance estimate
   L_j = HERO_N c_j (path.c adds c_j = p(lambda_j) C_j to FilmSample.lane; without
   a wavelength-dependent event c_j is L(lambda_j) / HERO_N), the sample's lanes
   scaled together so that the largest is at most maxcomponentvalue, the bucket
   keeps sum fw L_j CIE_Y_INTEGRAL and sum fw, and its value is their ratio (0
   when no wavelength fell in it): the mean of L CIE_Y_INTEGRAL over the band.
   img_write_spectral writes it as OpenEXR (exr.c's exr_write): the channels R, G,
   B (linear sRGB) and one a bucket, named "S0.<centre>nm" with the band's centre
   printed "%.3f" and its '.' written ',' (the OpenEXR spectral layout of Fichet et
   al. 2021, JCGT 10(3), where '.' separates layers: "S0.560,000nm"), the strings
   spectralLayoutVersion "1.0" and emissiveUnits "W.m^-2.sr^-1"; HALF (values
   above 65504 clamped to 65504, as pbrt-v4 does) when savefp16, else FLOAT; the
   data window is the film's crop, the display window the whole film.

   DETERMINISM.  Every (pixel, sample) owns its random numbers (sampler.c) and
   every pixel is written by one thread (rows are handed out one at a time): the
   image is identical for any number of threads.

   PROGRESSIVE RENDERING.  render_ladder renders in passes up a ladder of sample
   counts (16, 32, ..., 512) and hands the image at each rung to a callback:
   sample k of a pixel uses the stream (pixel, seed, k) whatever the total, and the
   per-pixel sums are kept in double and added in sample order, so the image at a
   rung is bit-identical to a separate render with that spp (tested).  `specnee
   converge` uses it: one 512-spp render per seed gives the whole ladder, each rung
   timed as the render so far. */
#define _POSIX_C_SOURCE 200809L
#include "render.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

void render_options_default(RenderOptions *o)
{
    memset(o, 0, sizeof *o);
    o->spp = DEFAULT_SPP;
    o->seed = 0;
    o->threads = 0;                  /* 0: all the cores OpenMP offers */
    o->maxdepth = DEFAULT_MAXDEPTH;
    /* The defaults are the best configuration of the factorial evaluation by the
       rule of docs/RESULTS.md ("What to use"): the best geometric mean of
       equal-time MSE over the evaluation scenes, never significantly worse than
       the thesis' baseline (--preset thesis) on any of them. */
    o->sel.strategy = SEL_SPECTRAL_TREE;  /* O(log n) per vertex, the thesis spectral preference */
    o->wl_mode = WL_MIXTURE;         /* importance + visible: 3-5x at equal time (docs/wavelengths.md) */
    o->rough_mis = 1;                /* secondaries live through rough glass (THEORY §7) */
    o->nee = 1;
    o->sampler = SAMPLER_SOBOL;      /* lowest equal-time error, progressive (docs/sampling.md) */
    o->fluor_keep = 1;               /* fluorescence: all four wavelengths through a shift, */
    o->fluor_li = FLUOR_LI_POWER;    /* lambda_i from A x power (docs/FLUORESCENCE.md sec. 9) */
    o->sel.area_sampling = SHAPE_AUTO;  /* a triangle lamp by solid angle where it pays (docs/sampling.md) */
    o->jitter = 1;
    o->debug_x = o->debug_y = -1;
}

void render_options_thesis(RenderOptions *o)
{
    render_options_default(o);
    o->wl_mode = WL_UNIFORM;
    o->sel.strategy = SEL_SPATIAL;
    o->sel.power_metric = 0;
    o->sel.all_wavelengths = o->sel.throughput_weighted = 0;
    o->rough_mis = 0;
    o->sampler = SAMPLER_INDEPENDENT;
    o->fluor_keep = 0;               /* a shift terminates the secondaries, as dispersion */
    o->fluor_li = FLUOR_LI_A;
    o->sel.area_sampling = 1;        /* triangle lamps by area, as pbrt-v3 */
}

/* Does any material of s fluoresce?  (Only then are --fluor-li power's tables built.) */
static int scene_has_fluorescence(const Scene *s)
{
    int mi;
    for (mi = 0; mi < s->n_materials; mi++)
        if (s->materials[mi].type == MAT_FLUORESCENT) return 1;
    return 0;
}

/* ------------------------------------------------------------------ the film and its passes */

static double wall_seconds(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
#endif
}

/* One pass of the progressive render: samples [k0, k1) of every pixel are added,
   in sample order, to acc (3 doubles per pixel, XYZ sums), and img receives
   acc / k1 in linear sRGB (with mitchell or sinc, acc holds sum fw XYZ and wsum
   sum fw, and img receives acc / wsum: filter.c).  Summing in sample order makes a render that stops at
   k1 after any sequence of passes bit-identical to one pass of k1 samples. */
typedef struct {
    const Renderer *R;
    double *acc;
    double *wsum;              /* per pixel sum of filter weights (mitchell, sinc), else NULL */
    double *bsum;              /* the spectral film: per pixel nbuckets sums of fw L_j
                                  CIE_Y_INTEGRAL, then nbuckets sums of fw; else NULL */
    Image *img;
    uint64_t *row_rays;
    long *row_nonfinite, *row_fallbacks, *row_dims_reused;
    int k0, k1, spp_final, rows_done;
    int x0, y0;                /* the image's first pixel on the film (crop window) */
} Pass;

/* A pixel of the image from its sums: the mean of its samples' XYZ (with mitchell
   or sinc, sum fw XYZ / sum fw), white-balanced, in linear sRGB. */
static void film_pixel(const Pass *P, const double *sum, const double *wsum, float *out)
{
    const SceneSettings *set = &P->R->s->settings;
    double avg[3], rgb[3];
    if (!wsum) {
        avg[0] = sum[0] / P->k1; avg[1] = sum[1] / P->k1; avg[2] = sum[2] / P->k1;
    } else if (*wsum != 0.0) {   /* pbrt-v4: sum fw L / sum fw, 0 when sum fw = 0 */
        avg[0] = sum[0] / *wsum; avg[1] = sum[1] / *wsum; avg[2] = sum[2] / *wsum;
    } else {
        avg[0] = avg[1] = avg[2] = 0.0;
    }
    if (set->white_balance > 0.0f) {
        /* pbrt-v4's white balance (Film "whitebalance") or a camera's XYZ
           from its RGB (sensor.c): a 3x3 map of the sensor's RGB after the
           clamp, linear, so applied to the mean */
        const double *m = set->white_balance_m;
        double a0 = avg[0], a1 = avg[1], a2 = avg[2];
        avg[0] = m[0] * a0 + m[1] * a1 + m[2] * a2;
        avg[1] = m[3] * a0 + m[4] * a1 + m[5] * a2;
        avg[2] = m[6] * a0 + m[7] * a1 + m[8] * a2;
    }
    xyz_to_linear_srgb(avg, rgb);
    out[0] = (float)rgb[0];
    out[1] = (float)rgb[1];
    out[2] = (float)rgb[2];
}

/* The spectral film: the sample's four lanes into the pixel's buckets b (sums,
   then weight sums), each to the band its wavelength falls in (pbrt-v4's
   SpectralFilm::AddSample; the bucket index in float as there).  A sample that is
   not finite counts as 0, as for the RGB image. */
static void film_buckets(const Pass *P, const FilmSample *fs, float fw, double *b)
{
    const SceneSettings *set = &P->R->s->settings;
    int nb = set->nbuckets, j, ok = 1;
    double L[HERO_N], m = 0.0, f = CIE_Y_INTEGRAL;
    for (j = 0; j < HERO_N; j++) {
        L[j] = HERO_N * fs->lane[j];
        ok = ok && isfinite(L[j]);
        m = fmax(m, L[j]);
    }
    if (m > set->max_component) f *= set->max_component / m;
    for (j = 0; j < HERO_N; j++) {
        int k = (int)((float)nb * (fs->wl.lambda[j] - set->lambda_min) / (set->lambda_max - set->lambda_min));
        k = k < 0 ? 0 : k >= nb ? nb - 1 : k;
        if (ok) b[k] += fw * L[j] * f;
        b[nb + k] += fw;
    }
}

/* The progress bar after a row, over all passes (rows weighted by their samples). */
static void progress_row(Pass *P)
{
    int h = P->img->h;
#ifdef _OPENMP
#pragma omp critical(specnee_progress)
#endif
    {
        double done;
        int bar, i;
        P->rows_done++;
        done = ((double)P->k0 * h + (double)P->rows_done * (P->k1 - P->k0)) / ((double)P->spp_final * h);
        bar = (int)(40.0 * done);
        fprintf(stderr, "\r[");
        for (i = 0; i < 40; i++) fputc(i < bar ? '#' : ' ', stderr);
        fprintf(stderr, "] %3d%%", (int)(100.0 * done));
        if (P->rows_done == h && P->k1 == P->spp_final) fputc('\n', stderr);
        fflush(stderr);
    }
}

static void render_pass(Pass *P)
{
    const Renderer *R = P->R;
    const RenderOptions *o = R->o;
    const SceneSettings *set = &R->s->settings;
    const int lens = camera_has_lens(&R->cam);   /* asked once per pass, not per sample */
    int w = P->img->w, h = P->img->h, y;
#ifdef _OPENMP
    /* rows are handed out one at a time; each pixel is written by one thread */
#pragma omp parallel for schedule(dynamic, 1) num_threads(o->threads > 0 ? o->threads : omp_get_max_threads())
#endif
    for (y = 0; y < h; y++) {
        int x;
        Counters cnt;
        memset(&cnt, 0, sizeof cnt);
        for (x = 0; x < w; x++) {
            double *sum = P->acc + 3 * ((size_t)y * w + x);
            double *wsum = P->wsum ? P->wsum + (size_t)y * w + x : NULL;  /* sum of weights */
            /* (fx0, fy0): this image pixel on the film (a crop window shifts it) */
            int fx0 = x + P->x0, fy0 = y + P->y0;
            FILE *dbg = (fx0 == o->debug_x && fy0 == o->debug_y) ? stderr : NULL;
            int k;
            PixelSample ps;      /* the pixel's samples in a row: what depends on the pixel is kept */
            for (k = P->k0; k < P->k1; k++) {
                Rng *stream;
                FilmSample fs;
                double *xyz = fs.xyz, m;
                float fx, fy, ul0 = 0.5f, ul1 = 0.5f, fw = 1.0f, cw, time = 0.0f;
                if (k == P->k0) sampler_start(&R->sampler, fx0, fy0, k, &ps);
                else sampler_restart(&ps, k);
                stream = sampler_stream(&ps);
                /* the position in the pixel and its filter weight fw (filter.c) */
                if (set->filter == FILTER_GAUSSIAN && stream) {
                    /* the independent sampler: the Gaussian exactly, from its stream (filter.c) */
                    fx = 0.5f + filter_gaussian_reject(&R->filter, stream);
                    fy = 0.5f + filter_gaussian_reject(&R->filter, stream);
                } else {
                    float u0, u1;
                    sampler_2d(&ps, DIM_FILM, &u0, &u1);
                    fw = filter_sample(&R->filter, u0, u1, &fx, &fy);
                }
                if (set->no_pixel_jitter) {   /* pbrt-v4: the filter's sample drawn, then unused */
                    fx = fy = 0.5f;
                    fw = 1.0f;
                }
                {   /* pbrt-v4's disablewavelengthjitter: the number drawn, then 1/2 */
                    float ulam = sampler_1d(&ps, DIM_WAVELENGTH);
                    wl_sample(&R->wl, set->no_wavelength_jitter ? 0.5f : ulam, &fs.wl);
                }
                /* the lens dimensions, requested only with a lens: the independent
                   sampler's stream then has them after the wavelength, and pinhole
                   images keep their random numbers */
                if (lens) sampler_2d(&ps, DIM_LENS, &ul0, &ul1);
                /* the time, only where something moves (motion.c): pbrt-v4's
                   lerp(u, shutteropen, shutterclose) */
                if (R->moving) {
                    const float ut = sampler_1d(&ps, DIM_TIME);
                    time = (1.0f - ut) * set->shutter_open + ut * set->shutter_close;
                }
                if (dbg) fprintf(dbg, "pixel (%d, %d) sample %d\n", fx0, fy0, k);
                {   /* a ray the realistic camera's lens blocks counts as black */
                    Ray cr = camera_ray(&R->cam, (float)fx0 + fx, (float)fy0 + fy, ul0, ul1, time, &cw);
                    int j;
                    if (cw > 0.0f) trace_path(R, cr, &fs, &ps, &cnt, dbg);
                    else xyz[0] = xyz[1] = xyz[2] = 0.0, memset(fs.lane, 0, sizeof fs.lane);
                    xyz[0] *= cw; xyz[1] *= cw; xyz[2] *= cw;
                    for (j = 0; j < HERO_N; j++) fs.lane[j] *= cw;   /* the spectral film's too */
                }
                cnt.dims_reused += ps.reused;
                if (isfinite(xyz[0]) && isfinite(xyz[1]) && isfinite(xyz[2])) {
                    /* pbrt-v4's sensor (RGBFilm::AddSample; the sensor's RGB, XYZ
                       for cie1931): times the imaging ratio, then the largest
                       component clamped to maxcomponentvalue, hue kept */
                    xyz[0] *= set->imaging_ratio; xyz[1] *= set->imaging_ratio; xyz[2] *= set->imaging_ratio;
                    m = xyz[1] > xyz[2] ? xyz[1] : xyz[2];   /* fmax of finite values, without */
                    m = xyz[0] > m ? xyz[0] : m;              /* two calls to libm */
                    if (m > set->max_component) {
                        double f = set->max_component / m;
                        xyz[0] *= f; xyz[1] *= f; xyz[2] *= f;
                    }
                    if (wsum) {          /* mitchell, sinc: sum fw L and sum fw */
                        sum[0] += fw * xyz[0]; sum[1] += fw * xyz[1]; sum[2] += fw * xyz[2];
                    } else {             /* constant weights: the mean */
                        sum[0] += xyz[0]; sum[1] += xyz[1]; sum[2] += xyz[2];
                    }
                } else {
                    cnt.nonfinite++;     /* dropped: it counts as L = 0 */
                }
                if (wsum) *wsum += fw;
                if (P->bsum) film_buckets(P, &fs, fw, P->bsum + 2 * (size_t)set->nbuckets * ((size_t)y * w + x));
            }
            film_pixel(P, sum, wsum, P->img->rgb + 3 * ((size_t)y * w + x));
        }
        P->row_rays[y] += cnt.rays;
        P->row_nonfinite[y] += cnt.nonfinite;
        P->row_fallbacks[y] += cnt.fallbacks;
        P->row_dims_reused[y] += cnt.dims_reused;
        if (o->progress) progress_row(P);
    }
}

/* A render in progress: what render_begin sets up and render_advance adds to. */
struct RenderJob {
    Renderer R;
    Pass P;
    Image img;
    SelOptions sel;            /* o->sel with the sampled wavelength range: the emitters'
                                  radiance for it lives in R.ls, not in the scene */
    RenderStats st;            /* cumulative: build + every pass, nothing in between */
    Spectrum white_r;          /* R.white's reflectance: 1 everywhere, the UV included */
};

/* The media (medium.c): rendered unless the integrator ignores them; an emissive
   one's Le normalised for this range as an emitter's is.  0 and a message on
   failure. */
static int setup_media(RenderJob *j, Error *err)
{
    const Scene *s = j->R.s;
    int m;
    j->R.vol = s->n_media > 0 && !s->settings.media_ignored;
    j->R.med_le = (double *)calloc((size_t)s->n_media + 1, sizeof(double));
    if (!j->R.med_le) { error_set(err, NULL, 0, "out of memory"); return 0; }
    for (m = 0; m < s->n_media; m++) {
        const Medium *M = &s->media[m];
        double y;
        if (!(M->Le_scale > 0.0f)) continue;
        if (M->temperature.v || M->type == MEDIUM_NANOVDB) { j->R.med_le[m] = 1.0; continue; }  /* blackbody: absolute */
        y = luminance_sum(&M->Le, LAMBDA_LO, LAMBDA_HI) > 0.0
            ? luminance_sum(&M->Le, j->sel.lo_nm, j->sel.hi_nm) : 1.0;   /* UV: absolute */
        if (!(y > 0.0)) {
            error_set(err, M->file, M->line, "MakeNamedMedium \"%s\": Le emits nothing "
                      "visible in %g-%g nm", M->name, j->sel.lo_nm, j->sel.hi_nm);
            return 0;
        }
        j->R.med_le[m] = M->Le_scale / y;
    }
    return 1;
}

/* --fluor-li power (docs/FLUORESCENCE.md §3): E = the scene's emitter power per nm, pi A
   (2 if two-sided) Le (an infinite light's area is 4 pi r^2), for this render's
   Le; a table of A E for each fluorescent material.  render_begin calls it only
   for a scene with fluorescent materials (none to build, and no O(n) pass over the
   emitters, without them).  0 and a message when out of memory. */
static int setup_fluor_power(RenderJob *j, Error *err)
{
    const Scene *s = j->R.s;
    Spectrum E;
    int e, k, mi;
    spec_const(&E, 0.0f);
    for (e = 0; e < s->n_emitters; e++) {
        Spectrum Le;
        float f = (float)(SPECNEE_PI * s->emitters[e].area * (s->emitters[e].twosided ? 2.0 : 1.0));
        light_spectrum(j->R.ls, e, &Le);
        for (k = 0; k < SPEC_N; k++) E.v[k] += f * Le.v[k];
        for (k = 0; k < SPEC_UV_N; k++) E.uv[k] += f * Le.uv[k];
    }
    j->R.fl_power = (double *)calloc((size_t)s->n_materials * FL_N, sizeof(double));
    if (!j->R.fl_power) { error_set(err, NULL, 0, "out of memory"); return 0; }
    for (mi = 0; mi < s->n_materials; mi++)
        if (s->materials[mi].type == MAT_FLUORESCENT)
            fluor_power_cdf(&s->materials[mi], &E, j->R.fl_power + (size_t)mi * FL_N);
    return 1;
}

RenderJob *render_begin(const Scene *s, const RenderOptions *o, Error *err)
{
    RenderJob *j;
    const SceneSettings *set = &s->settings;
    int w, h, b[4];
    double t0 = wall_seconds();
    clock_t c0 = clock();
    /* the part of the film to render and write (Film "cropwindow"/"pixelbounds") */
    if (!film_bounds(set, b)) {
        error_set(err, NULL, 0, "the film's crop window selects no pixel of the %d x %d film",
                  set->xres, set->yres);
        return NULL;
    }
    w = b[1] - b[0];
    h = b[3] - b[2];
    j = (RenderJob *)calloc(1, sizeof *j);
    if (!j) { error_set(err, NULL, 0, "out of memory"); return NULL; }
    j->P.x0 = b[0];
    j->P.y0 = b[2];
    j->sel = o->sel;
    /* the emitters' normalisation range (the spectral film: pbrt-v4's 360..830 nm) */
    /* pbrt-v4's range (360-830 nm) for --wide, the spectral film, and the
       fixed wavelengths of disablewavelengthjitter (pbrt-v4's own four) */
    j->sel.lo_nm = o->wl_wide || set->spectral || set->no_wavelength_jitter ? (float)SPEC_MIN : LAMBDA_LO;
    j->sel.hi_nm = o->wl_wide || set->spectral || set->no_wavelength_jitter ? (float)SPEC_MAX : LAMBDA_HI;
    j->R.s = s;
    j->R.o = o;
    j->R.white.type = MAT_DIFFUSE;
    spec_const(&j->white_r, 1.0f);
    j->R.white.reflectance.tab = &j->white_r;
    camera_init(&j->R.cam, set);
    j->R.moving = j->R.cam.moving || s->n_motions > 0;
    filter_init(&j->R.filter, set);
    sampler_init(&j->R.sampler, o->sampler, o->seed, o->spp, o->xsamples, o->ysamples, o->jitter);
    /* the emitters for this range and their selection tables */
    j->R.ls = light_sampler_build(s, &j->sel, err);
    if (!j->R.ls) { free(j); return NULL; }
    {
        /* the wavelength pdf (wavelengths.c); importance and mixture follow the
           emitters' summed spectrum (none: the importance part is flat) */
        const Spectrum *sum = light_spectrum_sum(j->R.ls);   /* summed as it was built */
        if (o->band_hi > o->band_lo)     /* a band of the film's spectrum (the tests) */
            wl_pdf_uniform(&j->R.wl, o->band_lo, o->band_hi);
        else if (set->spectral)          /* pbrt-v4 SpectralFilm: uniform in its range */
            wl_pdf_uniform(&j->R.wl, set->lambda_min, set->lambda_max);
        else if (set->no_wavelength_jitter) {
            /* pbrt-v4's RGB film samples its visible pdf over 360-830 nm
               (SampleVisible): with u fixed at 1/2, its four wavelengths exactly */
            if (!wl_pdf_visible(&j->R.wl, (float)SPEC_MIN, (float)SPEC_MAX)) {
                error_set(err, NULL, 0, "cannot build the visible wavelength pdf");
                light_sampler_free(j->R.ls);
                free(j);
                return NULL;
            }
        }
        else if (o->wl_mode == WL_IMPORTANCE && s->n_emitters == 0)
            wl_pdf_uniform(&j->R.wl, j->sel.lo_nm, j->sel.hi_nm);
        else if (!wl_pdf_build(&j->R.wl, o->wl_mode, j->sel.lo_nm, j->sel.hi_nm, sum, o->wl_mix)) {
            error_set(err, NULL, 0, "cannot build the %s wavelength pdf", wl_mode_name(o->wl_mode));
            light_sampler_free(j->R.ls);
            free(j);
            return NULL;
        }
    }
    if (!setup_media(j, err)) { render_end(j); return NULL; }
    {   /* the infinite lights, which rays that escape the scene see */
        int e;
        j->R.inf = (int *)malloc(sizeof(int) * (size_t)(s->n_emitters + 1));
        if (!j->R.inf) { error_set(err, NULL, 0, "out of memory"); render_end(j); return NULL; }
        for (e = 0; e < s->n_emitters; e++)
            if (s->emitters[e].inf) j->R.inf[j->R.n_inf++] = e;
    }
    if (o->fluor_li == FLUOR_LI_POWER && s->n_emitters > 0 && scene_has_fluorescence(s) &&
        !setup_fluor_power(j, err)) {
        render_end(j);
        return NULL;
    }
    j->P.R = &j->R;
    j->P.img = &j->img;
    j->P.acc = (double *)calloc(3 * (size_t)w * (size_t)h, sizeof *j->P.acc);
    if (filter_weighted(&j->R.filter)) {
        j->P.wsum = (double *)calloc((size_t)w * (size_t)h, sizeof *j->P.wsum);
        if (!j->P.wsum) { error_set(err, NULL, 0, "out of memory for a %dx%d image", w, h); render_end(j); return NULL; }
    }
    if (set->spectral) {
        j->P.bsum = (double *)calloc(2 * (size_t)set->nbuckets * (size_t)w * (size_t)h, sizeof *j->P.bsum);
        if (!j->P.bsum) { error_set(err, NULL, 0, "out of memory for a %dx%d image", w, h); render_end(j); return NULL; }
    }
    j->P.row_rays = (uint64_t *)calloc((size_t)h, sizeof *j->P.row_rays);
    j->P.row_nonfinite = (long *)calloc((size_t)h, sizeof *j->P.row_nonfinite);
    j->P.row_fallbacks = (long *)calloc((size_t)h, sizeof *j->P.row_fallbacks);
    j->P.row_dims_reused = (long *)calloc((size_t)h, sizeof *j->P.row_dims_reused);
    if (!img_alloc(&j->img, w, h) || !j->P.acc || !j->P.row_rays || !j->P.row_nonfinite || !j->P.row_fallbacks
        || !j->P.row_dims_reused) {
        error_set(err, NULL, 0, "out of memory for a %dx%d image", w, h);
        render_end(j);
        return NULL;
    }
    j->st.build_s = wall_seconds() - t0;
    j->st.wall_s = j->st.build_s;
    j->st.cpu_s = (double)(clock() - c0) / CLOCKS_PER_SEC;
    return j;
}

int render_advance(RenderJob *j, int spp, int spp_final, Error *err)
{
    int w = j->img.w, h = j->img.h, y;
    double t0;
    clock_t c0;
    if (spp <= j->P.k1) {
        error_set(err, NULL, 0, "the spp ladder must increase (%d after %d)", spp, j->P.k1);
        return 0;
    }
    if (j->P.k1 > 0 && !sampler_progressive(j->R.sampler.type)) {
        /* its samples depend on the total spp: adding to a render would mix two designs */
        error_set(err, NULL, 0, "the %s sampler is not progressive (its samples depend on the "
                  "total spp): render %d spp separately", sampler_name(j->R.sampler.type), spp);
        return 0;
    }
    t0 = wall_seconds();
    c0 = clock();
    j->P.k0 = j->P.k1;
    j->P.k1 = spp;
    j->P.spp_final = spp_final > spp ? spp_final : spp;
    j->P.rows_done = 0;
    {   /* the sampler's spp is this pass's target (only stratified and zsobol use it,
           and they allow one pass) */
        const RenderOptions *o = j->R.o;
        sampler_init(&j->R.sampler, o->sampler, o->seed, spp, o->xsamples, o->ysamples, o->jitter);
        j->R.sampler.camera_medium = j->R.vol && j->R.s->settings.camera_medium >= 0;
    }
    render_pass(&j->P);
    j->st.rays = 0;
    j->st.nonfinite = j->st.fallbacks = j->st.dims_reused = 0;
    for (y = 0; y < h; y++) {
        j->st.dims_reused += j->P.row_dims_reused[y];
        j->st.rays += j->P.row_rays[y];
        j->st.nonfinite += j->P.row_nonfinite[y];
        j->st.fallbacks += j->P.row_fallbacks[y];
    }
    j->st.samples = (uint64_t)w * (uint64_t)h * (uint64_t)spp;
    j->st.lazy_s = light_sampler_lazy_seconds(j->R.ls);
    j->st.wall_s += wall_seconds() - t0;
    j->st.cpu_s += (double)(clock() - c0) / CLOCKS_PER_SEC;
    return 1;
}

const Image *render_image(const RenderJob *j) { return &j->img; }
const RenderStats *render_stats(const RenderJob *j) { return &j->st; }

void render_end(RenderJob *j)
{
    if (!j) return;
    free(j->P.acc); free(j->P.wsum); free(j->P.bsum); free(j->P.row_rays); free(j->P.row_nonfinite); free(j->P.row_fallbacks);
    free(j->P.row_dims_reused);
    img_free(&j->img);
    if (j->R.ls) light_sampler_free(j->R.ls);
    free(j->R.inf);
    free(j->R.fl_power);
    free(j->R.med_le);
    wl_pdf_free(&j->R.wl);
    free(j);
}

int render(const Scene *s, const RenderOptions *o, Image *img, RenderStats *st, Error *err)
{
    if (o->spp <= 0) { memset(st, 0, sizeof *st); error_set(err, NULL, 0, "spp must be positive"); return 0; }
    return render_ladder(s, o, &o->spp, 1, NULL, NULL, img, st, err);
}

int render_spectral(const Scene *s, const RenderOptions *o, Image *img, float **buckets,
                    RenderStats *st, Error *err)
{
    RenderJob *j;
    int nb = s->settings.nbuckets;
    size_t i, k, n;
    memset(st, 0, sizeof *st);
    *buckets = NULL;
    if (!s->settings.spectral) { error_set(err, NULL, 0, "the film is not spectral"); return 0; }
    if (o->spp <= 0) { error_set(err, NULL, 0, "spp must be positive"); return 0; }
    if (!(j = render_begin(s, o, err))) return 0;
    if (!render_advance(j, o->spp, o->spp, err)) { render_end(j); return 0; }
    n = (size_t)j->img.w * (size_t)j->img.h;
    if (!(*buckets = (float *)malloc(sizeof(float) * (size_t)nb * n))) {
        error_set(err, NULL, 0, "out of memory for a %dx%d image", j->img.w, j->img.h);
        render_end(j);
        return 0;
    }
    for (i = 0; i < n; i++)         /* sum fw L / sum fw, 0 where no wavelength fell */
        for (k = 0; k < (size_t)nb; k++) {
            const double *b = j->P.bsum + 2 * (size_t)nb * i;
            (*buckets)[(size_t)nb * i + k] = b[nb + k] > 0.0 ? (float)(b[k] / b[nb + k]) : 0.0f;
        }
    *st = j->st;
    *img = j->img;                       /* the caller owns the image */
    memset(&j->img, 0, sizeof j->img);
    render_end(j);
    return 1;
}

int img_write_spectral(const Image *im, const float *buckets, const SceneSettings *st,
                       const char *path, Error *err)
{
    static const char *const keys[2] = { "emissiveUnits", "spectralLayoutVersion" };
    static const char *const vals[2] = { "W.m^-2.sr^-1", "1.0" };
    char names[64][24];
    const char *np[64];
    int nb = st->nbuckets, nc = 3 + nb, b[4], k, ok;
    size_t i, n = (size_t)im->w * (size_t)im->h;
    float *v;
    ExrWrite x;
    if (!im->rgb || nb < 1 || nc > 64 || !film_bounds(st, b) || b[1] - b[0] != im->w ||
        b[3] - b[2] != im->h) {
        error_set(err, path, 0, "no image to write");
        return 0;
    }
    if (!(v = (float *)malloc(sizeof(float) * (size_t)nc * n))) {
        error_set(err, path, 0, "EXR: out of memory");
        return 0;
    }
    for (k = 0; k < nc; k++) {
        char *c;
        float t = ((float)(k - 3) + 0.5f) / (float)nb;   /* the band's centre, in float */
        if (k < 3) snprintf(names[k], sizeof names[k], "%c", "RGB"[k]);
        else snprintf(names[k], sizeof names[k], "S0.%.3fnm", (1.0f - t) * st->lambda_min + t * st->lambda_max);
        for (c = names[k]; *c; c++) if (*c == '.' && c > names[k] + 2) *c = ',';
        np[k] = names[k];
    }
    for (i = 0; i < n; i++)
        for (k = 0; k < nc; k++) {
            float c = k < 3 ? im->rgb[3 * i + (size_t)k] : buckets[(size_t)nb * i + (size_t)(k - 3)];
            v[(size_t)nc * i + (size_t)k] = st->savefp16 && c > 65504.0f ? 65504.0f : c;
        }
    x.w = im->w; x.h = im->h; x.x0 = b[0]; x.y0 = b[2]; x.full_w = st->xres; x.full_h = st->yres;
    x.n_ch = nc; x.names = np; x.v = v; x.half = st->savefp16;
    x.n_str = 2; x.str_key = keys; x.str_val = vals;
    ok = exr_write(path, &x, err);
    free(v);
    return ok;
}

int render_ladder(const Scene *s, const RenderOptions *o, const int *ladder, int n_rungs,
                  RenderRungFn on_rung, void *user, Image *img, RenderStats *st, Error *err)
{
    RenderJob *j;
    int i, ok = 1;
    memset(st, 0, sizeof *st);
    if (n_rungs < 1 || ladder[0] <= 0) { error_set(err, NULL, 0, "spp must be positive"); return 0; }
    for (i = 1; i < n_rungs; i++)
        if (ladder[i] <= ladder[i - 1]) {
            error_set(err, NULL, 0, "the spp ladder must increase (%d after %d)", ladder[i], ladder[i - 1]);
            return 0;
        }
    if (!sampler_progressive(o->sampler)) {
        /* stratified, zsobol: sample k depends on the total spp, so every rung is
           a render of its own (and st covers that render alone) */
        img->rgb = NULL;
        for (i = 0; i < n_rungs && ok; i++) {
            j = render_begin(s, o, err);
            if (!j) { img_free(img); return 0; }
            if (!render_advance(j, ladder[i], ladder[i], err)) { render_end(j); img_free(img); return 0; }
            *st = j->st;
            if (on_rung) ok = on_rung(user, i, &j->img, st);
            img_free(img);
            *img = j->img;               /* the caller owns the last image */
            memset(&j->img, 0, sizeof j->img);
            render_end(j);
        }
        return 1;
    }
    j = render_begin(s, o, err);
    if (!j) return 0;
    for (i = 0; i < n_rungs && ok; i++) {
        if (!render_advance(j, ladder[i], ladder[n_rungs - 1], err)) { render_end(j); return 0; }
        *st = j->st;
        if (on_rung) ok = on_rung(user, i, &j->img, st);
    }
    *img = j->img;                       /* the caller owns the last image */
    memset(&j->img, 0, sizeof j->img);
    render_end(j);
    return 1;
}
