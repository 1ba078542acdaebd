/* render.h - what the render's three rooms share; not part of specnee's API
   (specnee.h section 12 is).

     camera.c   the camera: a raster point (and a lens sample) to a world ray
     path.c     the path estimator: one camera sample's contributions (THEORY (4)-(9))
     render.c   the options, a render's state (Renderer) and the film: passes over
                the pixels, the pixel filter, the sensor, the progressive ladder

   render.c builds one Renderer per render (render_begin); path.c and camera.c only
   read it. */
#ifndef SPECNEE_RENDER_H
#define SPECNEE_RENDER_H
#include "specnee.h"

/* ------------------------------------------------------------------ camera.c */

typedef struct {
    Xform world_from_camera;
    CameraType type;                 /* the projection (specnee.h) */
    float tan_half;                  /* tan(fov/2) of the shorter axis */
    float sx0, sx1, sy0, sy1;        /* screen window */
    int w, h;
    float lens_radius, focal_distance;   /* thin lens; lens_radius 0: pinhole */
    const Lens *lens;                /* the realistic camera (lens.c); NULL: perspective */
    double film_w, film_h;           /* its film's width and height (m) */
    int moving;                      /* its two CTMs differ: world_from_camera moves */
    Motion motion;                   /* then from the start to the end (motion.c) */
    Vec3 eye;                        /* xf_point(world_from_camera, 0): the origin of
                                        every ray that starts at the camera's own
                                        origin (pinholes that do not move), once */
} Camera;

void camera_init(Camera *c, const SceneSettings *st);
/* Raster (x, y), y down, to a world-space ray at `time`; (ul0, ul1) pick the
   point on the lens (unused for a pinhole).  *weight: the ray's weight (1; the
   realistic camera's lens.c weight, 0 when the lens blocks it). */
Ray  camera_ray(const Camera *c, float x, float y, float ul0, float ul1, float time, float *weight);
/* Whether camera_ray reads (ul0, ul1). */
int  camera_has_lens(const Camera *c);

/* ------------------------------------------------------------------ render.c */

/* A render's state: what render_begin builds and every pass reads. */
typedef struct {
    const Scene *s;
    const RenderOptions *o;
    LightSampler *ls;
    WavelengthPdf wl;
    Camera cam;
    int *inf; int n_inf;             /* the emitters that are infinite lights */
    Sampler sampler;                 /* the numbers (sampler.c); its spp is the pass's target */
    int moving;                      /* something moves: each sample draws its time (motion.c) */
    PixelFilter filter;              /* the pixel filter's sampler (filter.c) */
    Material white;                  /* Lambertian of albedo 1: a fluorescent vertex after a
                                        shift re-radiates like this at lambda_i
                                        (docs/FLUORESCENCE.md §3) */
    int vol;                         /* the media are rendered ("volpath", not "path") */
    double *med_le;                  /* per medium: Lescale / its Le's luminance over the
                                        sampled range (0: not emissive), as lights.c
                                        normalises an emitter */
    double *fl_power;                /* --fluor-li power: per material FL_N entries, the
                                        running integral of A x the emitters' power
                                        (fluor_power_cdf); NULL: lambda_i from A alone */
} Renderer;

/* What the samples of one row count (render.c sums them per pass: RenderStats). */
typedef struct {
    uint64_t rays;
    long nonfinite, fallbacks, dims_reused;
} Counters;

/* ------------------------------------------------------------------ path.c */

/* One camera sample on its way to the film: the wavelengths it carries and the
   XYZ the path estimator adds for them (THEORY (9)). */
typedef struct {
    Wavelengths wl;                  /* the camera's wavelengths and their pdf p(lambda_j):
                                        set by render.c; the film keeps them through a
                                        fluorescent shift */
    float cmf[HERO_N][3];            /* the sensor's curves at wl.lambda (xbar, ybar, zbar
                                        for cie1931; xyz then holds its RGB) */
    double xyz[3];                   /* sum_j cmf_j C_j over the path's contributions */
    double lane[HERO_N];             /* sum of c_j = p(lambda_j) C_j per wavelength: the
                                        spectral film's buckets (render.c) */
} FilmSample;

/* Trace one camera sample with the wavelengths fs->wl: fills fs->cmf and sets
   fs->xyz to the sample's XYZ estimate.  dbg: --debug-pixel's stream (NULL: silent). */
void trace_path(const Renderer *R, Ray ray, FilmSample *fs, PixelSample *ps, Counters *cnt, FILE *dbg);

#endif
