/* options.c - the options block of a pbrt-v4 scene: Camera, Film, PixelFilter,
   Sampler, Integrator and Accelerator, read into Scene.settings.

   Implements, for the scene builder (scene.c's directive loop calls them before
   WorldBegin, parser.h): camera_directive, film_directive, filter_directive,
   sampler_directive, integrator_directive, accelerator_directive,
   camera_transform_ok (also scene_load's last check); and, for the
   renderer and the commands (specnee.h section 8), film_bounds,
   scene_insets_rendered and camera_screen_window.  Each reads its statement's parameters with parser.h's
   typed getters, checks them (every problem is a "file:line: problem" line) and
   fills SceneSettings; pbrt-v4's parameters that specnee does not support are
   refused by name.  The subset and its defaults: docs/conventions.md.

   USE (scene.c)
     if (!strcmp(d, "Film")) ok = film_directive(P, type, &pl, t->file, t->line); */
#include "parser.h"
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* pbrt-v4 PerspectiveCamera's screen window: "screenwindow" (x0 x1 y0 y1) when
   given; else the shorter axis of a frame of aspect ratio `frame` spans [-1, 1]
   and the longer one [-frame, frame] (the fov belongs to the shorter axis). */
static void screen_window(int set, const float screen[4], float frame, float sw[4])
{
    if (set) memcpy(sw, screen, 4 * sizeof *sw);
    else if (frame > 1.0f) { sw[0] = -frame; sw[1] = frame; sw[2] = -1.0f; sw[3] = 1.0f; }
    else { sw[0] = -1.0f; sw[1] = 1.0f; sw[2] = -1.0f / frame; sw[3] = 1.0f / frame; }
}

void camera_screen_window(const SceneSettings *st, float sw[4])
{
    float frame = st->frame_aspect > 0.0f ? st->frame_aspect : (float)st->xres / (float)st->yres;
    screen_window(st->screen_set, st->screen, frame, sw);
}

/* The camera transform must give the renderer finite numbers, as mesh vertices
   must: the eye and the world-space directions through the screen window's
   corners and the screen's centre, in float, with a length that neither
   overflows nor underflows when squared (camera.c normalises them).  A transform
   such as `Scale 1e-30 ...` before Camera is invertible in double precision but
   fails here. */
int camera_transform_ok(const Xform *camera_from_world, float fov_deg, const float sw[4])
{
    Xform wfc;
    double t = tan(fov_deg * 0.5 * SPECNEE_PI / 180.0);
    Vec3 eye;
    int i;
    memcpy(wfc.m, camera_from_world->inv, sizeof wfc.m);     /* world_from_camera */
    memcpy(wfc.inv, camera_from_world->m, sizeof wfc.inv);
    eye = xf_point(&wfc, v3(0, 0, 0));
    if (!(fabsf(eye.x) <= FLT_MAX && fabsf(eye.y) <= FLT_MAX && fabsf(eye.z) <= FLT_MAX))
        return 0;
    for (i = 0; i < 5; i++) {
        double sx = i == 4 ? 0.0 : sw[i & 1], sy = i == 4 ? 0.0 : sw[2 + (i >> 1)];
        Vec3 d = xf_vector(&wfc, v3((float)(sx * t), (float)(sy * t), 1.0f));
        float l2 = v3_dot(d, d);
        if (!(l2 >= FLT_MIN && l2 <= FLT_MAX)) return 0;
    }
    return 1;
}

static int camera_place(Parser *P, float open, float close, const char *file, int line);

/* Camera "realistic" (pbrt-v4 RealisticCamera::Create): the lens file, resolved
   as other assets, read by lens.c; scene_load focuses it once the film is known.
   "string aperture": pbrt-v4's built-in shapes; an aperture image is refused. */
static int realistic_camera(Parser *P, ParamList *pl, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    float open, close, diameter, focus;
    const char *fn, *aperture;
    char path[PATH_CAP];
    Error e;
    Param *pf;
    if (!get_float(P, pl, "shutteropen", 0.0f, &open)) return 0;
    if (!get_float(P, pl, "shutterclose", 1.0f, &close)) return 0;
    if (!get_float(P, pl, "aperturediameter", 1.0f, &diameter)) return 0;
    if (!get_float(P, pl, "focusdistance", 10.0f, &focus)) return 0;
    if (!get_string(P, pl, "lensfile", &fn)) return 0;
    if (!get_string(P, pl, "aperture", &aperture)) return 0;
    pf = param_find(pl, PT_STRING, "lensfile");
    if (!params_check_unused(P, pl, "Camera \"realistic\"",
                             "float shutteropen, float shutterclose, string lensfile, "
                             "float aperturediameter, float focusdistance, string aperture", NULL))
        return 0;
    if (aperture && *aperture && !lens_set_aperture(&st->lens, aperture))
        return fail_param(P, pl, "aperture", file, line, "Camera \"realistic\": \"string aperture\" "
                          "\"%s\": an aperture image is valid pbrt-v4 but not in the specnee subset "
                          "(the built-in \"gaussian\", \"square\", \"pentagon\", \"star\" or the "
                          "circular stop)", aperture);
    if (!fn || !*fn)
        return fail(P, file, line, "Camera \"realistic\": \"string lensfile\" is required");
    if (!(diameter > 0.0f && diameter <= FLT_MAX) || !(focus > 0.0f && focus <= FLT_MAX))
        return fail_param(P, pl, diameter > 0.0f && diameter <= FLT_MAX ? "focusdistance" : "aperturediameter",
                          file, line, "Camera \"realistic\": \"float aperturediameter\" %g (mm) "
                          "and \"float focusdistance\" %g must be finite and > 0", diameter, focus);
    if (!(close - open > 0.0f))
        return fail_param(P, pl, "shutterclose", file, line, "Camera: shutterclose %g <= shutteropen %g: the shutter "
                    "never opens", close, open);
    {   /* as for the perspective camera, with its default window */
        static const float sw[4] = { -1.0f, 1.0f, -1.0f, 1.0f };
        if (!camera_transform_ok(&P->gs.ctm, 90.0f, sw))
            return fail(P, file, line, "Camera: degenerate camera transform: the eye or the "
                        "viewing directions are not finite, non-zero float vectors (look at "
                        "the Scale/Transform/LookAt before Camera)");
    }
    resolve_path(P, pf->file, fn, path, sizeof path);
    if (!lens_read(&st->lens, path, &e))
        return fail(P, file, line, "Camera \"realistic\": %s", e.msg);
    lens_set_aperture(&st->lens, aperture ? aperture : "");   /* checked above */
    if (!lens_set_stop(&st->lens, diameter * 1e-3))       /* pbrt-v4 warns and keeps the stop */
        fprintf(stderr, "%s:%d: note: Camera \"realistic\": \"float aperturediameter\" %g mm is "
                "wider than the lens's stop: the stop's own diameter is kept (as pbrt-v4 does)\n",
                file, line, diameter);
    st->focus_distance = focus;
    st->camera_type = CAMERA_PERSPECTIVE;       /* with its lens (lens.n > 0) */
    st->lens_radius = 0.0f;
    st->fov_deg = 90.0f;                        /* only for camera_transform_ok */
    st->screen_set = 0;
    st->frame_aspect = 0.0f;
    P->exposure_time = close - open;
    return camera_place(P, open, close, file, line);
}

/* Camera "perspective", "orthographic" and "spherical": their names, the
   parameters each reads (pbrt-v4's Create(); the spherical camera reads the
   lens and the window as pbrt-v4's does, and ignores them: camera.c) */
static const char *const CAMERA_LABEL[3] = {
    "Camera \"perspective\"", "Camera \"orthographic\"", "Camera \"spherical\"" };
static const char *const CAMERA_READS[3] = {
    "float fov, float lensradius, float focaldistance, float shutteropen, float shutterclose, "
    "float frameaspectratio, float screenwindow",
    "float lensradius, float focaldistance, float shutteropen, float shutterclose, "
    "float frameaspectratio, float screenwindow",
    "float lensradius, float focaldistance, float shutteropen, float shutterclose, "
    "float frameaspectratio, float screenwindow, string mapping" };

/* "frameaspectratio" (pfr: given) and "screenwindow" (psw: given; its four
   numbers into scr), checked as pbrt-v4 reads them. */
static int camera_window_ok(Parser *P, const Param *pfr, float frame, const Param *psw, float scr[4])
{
    int k;
    if (pfr && !(frame > 0.0f && frame <= FLT_MAX))
        return fail(P, pfr->file, pfr->line, "Camera: \"float frameaspectratio\" %g must be "
                    "finite and > 0", frame);
    if (!psw) return 1;   /* pbrt-v4: x0 x1 y0 y1 of the screen, replacing the default */
    if (psw->n_num != 4)
        return fail(P, psw->file, psw->line, "Camera: \"float screenwindow\": %d values, "
                    "expected 4 (x0 x1 y0 y1 of the screen)", psw->n_num);
    for (k = 0; k < 4; k++) scr[k] = (float)psw->num[k];
    for (k = 0; k < 4; k++)
        if (!(fabsf(scr[k]) <= FLT_MAX) || (k & 1 && scr[k] == scr[k - 1]))
            return fail(P, psw->file, psw->line, "Camera: \"float screenwindow\" [%g %g %g %g] "
                        "must be finite with x0 != x1 and y0 != y1", scr[0], scr[1], scr[2], scr[3]);
    return 1;
}

int camera_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    float fov = 90.0f, lens, focus, open, close, frame = 0.0f, scr[4] = { 0, 0, 0, 0 }, sw[4];
    const char *mapping = NULL;
    Param *psw, *pfr;
    int kind;                                   /* 0 perspective, 1 orthographic, 2 spherical */
    if (!strcmp(type, "realistic")) return realistic_camera(P, pl, file, line);
    kind = !strcmp(type, "perspective") ? 0 : !strcmp(type, "orthographic") ? 1
         : !strcmp(type, "spherical") ? 2 : -1;
    if (kind < 0) return fail(P, file, line, "Camera \"%s\": unknown camera type", type);
    if (kind == 0 && !get_float(P, pl, "fov", 90.0f, &fov)) return 0;
    if (!get_float(P, pl, "lensradius", 0.0f, &lens)) return 0;
    if (!get_float(P, pl, "focaldistance", kind == 2 ? 1e30f : 1e6f, &focus)) return 0;
    if (!get_float(P, pl, "shutteropen", 0.0f, &open)) return 0;
    if (!get_float(P, pl, "shutterclose", 1.0f, &close)) return 0;
    if (kind == 2 && !get_string(P, pl, "mapping", &mapping)) return 0;
    pfr = param_find(pl, PT_FLOAT, "frameaspectratio");
    if (pfr && !get_float(P, pl, "frameaspectratio", 0.0f, &frame)) return 0;
    psw = param_find(pl, PT_FLOAT, "screenwindow");
    if (!params_check_unused(P, pl, CAMERA_LABEL[kind], CAMERA_READS[kind], NULL))
        return 0;
    if (!(fov > 0.0f && fov < 180.0f))
        return fail_param(P, pl, "fov", file, line, "Camera: \"float fov\" %g must be within (0, 180) degrees", fov);
    if (!camera_window_ok(P, pfr, frame, psw, scr)) return 0;
    if (mapping && strcmp(mapping, "equalarea") != 0 && strcmp(mapping, "equirectangular") != 0)
        return fail_param(P, pl, "mapping", file, line, "Camera \"spherical\": \"string mapping\" "
                          "\"%s\": unknown mapping (\"equalarea\" or \"equirectangular\")", mapping);
    /* the film may come later: checked with this window (the square frame's
       unless given) here and again with the film's own in finish() */
    screen_window(psw != NULL, scr, pfr ? frame : 1.0f, sw);
    if (!camera_transform_ok(&P->gs.ctm, fov, sw) || !camera_transform_ok(&P->gs.ctm_end, fov, sw))
        return fail(P, file, line, "Camera: degenerate camera transform: the eye or the "
                    "viewing directions are not finite, non-zero float vectors (look at "
                    "the Scale/Transform/LookAt before Camera)");
    /* pbrt-v4 (cameras.cpp) reads the focal distance only through a lens: with
       "lensradius" 0 any "focaldistance" (exporters write 0) means a pinhole */
    if (!(lens >= 0.0f) || (lens > 0.0f && !(focus > 0.0f)))
        return fail_param(P, pl, lens < 0.0f ? "lensradius" : "focaldistance", file, line, "Camera: \"float lensradius\" %g must be >= 0 and "
                    "\"float focaldistance\" %g > 0", lens, focus);
    /* pbrt-v4 (scene.cpp): the exposure time is the shutter interval; it scales the
       image (the imaging ratio, Film "iso"), and where something moves each camera
       sample's time is uniform in it (motion.c) */
    if (!(close - open > 0.0f))
        return fail_param(P, pl, "shutterclose", file, line, "Camera: shutterclose %g <= shutteropen %g: the shutter "
                    "never opens", close, open);
    st->camera_type = kind == 0 ? CAMERA_PERSPECTIVE : kind == 1 ? CAMERA_ORTHOGRAPHIC
                    : mapping && !strcmp(mapping, "equirectangular") ? CAMERA_EQUIRECT : CAMERA_EQUAL_AREA;
    st->fov_deg = fov;                          /* 90: only for camera_transform_ok */
    st->frame_aspect = kind == 2 ? 0.0f : frame;   /* the spherical camera ignores them */
    st->screen_set = kind != 2 && psw != NULL;
    memcpy(st->screen, scr, sizeof st->screen);
    st->lens_radius = kind == 2 ? 0.0f : lens;
    st->focal_distance = focus;
    st->lens.n = 0;                             /* a realistic camera before is replaced */
    P->exposure_time = close - open;
    return camera_place(P, open, close, file, line);
}

/* What every camera type sets: its frame (two ends where it moves), its shutter,
   its medium, the named coordinate system "camera" and where scene_load reports
   camera problems. */
static int camera_place(Parser *P, float open, float close, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    if (xf_differ(&P->gs.ctm, &P->gs.ctm_end)) {
        Motion m;
        if (!motion_init(&m, &P->gs.ctm, P->t0, &P->gs.ctm_end, P->t1))
            return fail(P, file, line, "Camera: its start and end transforms (ActiveTransform) "
                        "must be rotations, scales and translations without a mirror (pbrt-v4 "
                        "cannot interpolate a mirroring or projective transform)");
    }
    st->camera_from_world = P->gs.ctm;
    st->camera_from_world_end = P->gs.ctm_end;   /* a moving camera (camera.c) */
    st->camera_t0 = P->t0;
    st->camera_t1 = P->t1;
    st->shutter_open = open;
    st->shutter_close = close;
    st->camera_medium = P->gs.medium_outside;   /* pbrt-v4: the current outside medium */
    P->camera_file = file;
    P->camera_line = line;
    {   /* the named coordinate system "camera" is world_from_camera (pbrt-v4) */
        int i;
        for (i = 0; i < P->n_coords; i++)
            if (!strcmp(P->coords[i].name, "camera")) break;
        if (i == P->n_coords) {
            if (!grow((void **)&P->coords, &P->cap_coords, P->n_coords + 1, sizeof(NamedCoordSys)))
                return oom(P, file, line);
            P->coords[i].name = "camera";
            P->n_coords++;
        }
        memcpy(P->coords[i].xf.m, P->gs.ctm.inv, sizeof P->gs.ctm.inv);
        memcpy(P->coords[i].xf.inv, P->gs.ctm.m, sizeof P->gs.ctm.m);
        memcpy(P->coords[i].xf_end.m, P->gs.ctm_end.inv, sizeof P->gs.ctm_end.inv);
        memcpy(P->coords[i].xf_end.inv, P->gs.ctm_end.m, sizeof P->gs.ctm_end.m);
    }
    return 1;
}

int film_bounds(const SceneSettings *st, int b[4])
{
    b[0] = 0; b[1] = st->xres; b[2] = 0; b[3] = st->yres;
    if (st->crop_set) {
        /* pbrt-v4: ceil(resolution * fraction), the product in float (20 * 0.1f
           rounds to 2 in float, to 2.0000000298 in double) */
        float v[4];
        int a;
        v[0] = (float)st->xres * st->crop[0];
        v[1] = (float)st->xres * st->crop[1];
        v[2] = (float)st->yres * st->crop[2];
        v[3] = (float)st->yres * st->crop[3];
        for (a = 0; a < 4; a++) b[a] = (int)ceilf(v[a]);
    } else if (st->pixel_bounds_set) {   /* clipped to the film */
        b[0] = st->pixel_bounds[0] > 0 ? st->pixel_bounds[0] : 0;
        b[1] = st->pixel_bounds[1] < st->xres ? st->pixel_bounds[1] : st->xres;
        b[2] = st->pixel_bounds[2] > 0 ? st->pixel_bounds[2] : 0;
        b[3] = st->pixel_bounds[3] < st->yres ? st->pixel_bounds[3] : st->yres;
    }
    return b[1] > b[0] && b[3] > b[2];
}

int scene_insets_rendered(const Scene *s, int rect[8][4], const char *names[8])
{
    int b[4], i, n = 0;
    if (!film_bounds(&s->settings, b)) return 0;
    for (i = 0; i < s->n_insets; i++) {
        int x0 = s->inset[i][0] > b[0] ? s->inset[i][0] : b[0];
        int y0 = s->inset[i][1] > b[2] ? s->inset[i][1] : b[2];
        int x1 = s->inset[i][2] < b[1] ? s->inset[i][2] : b[1];
        int y1 = s->inset[i][3] < b[3] ? s->inset[i][3] : b[3];
        if (x1 <= x0 || y1 <= y0) continue;          /* outside the rendered part */
        rect[n][0] = x0 - b[0]; rect[n][1] = y0 - b[2];
        rect[n][2] = x1 - b[0]; rect[n][3] = y1 - b[2];
        names[n] = s->inset_name[i];
        n++;
    }
    return n;
}

/* An unknown Film "string sensor": the error names every sensor pbrt-v4 knows. */
static int film_unknown_sensor(Parser *P, const char *sensor, const char *file, int line)
{
    char names[512];
    int k;
    names[0] = 0;
    for (k = 1; k <= SENSOR_CAMERAS; k++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k > 1 ? ", " : "",
                 sensor_name(k));
    return fail(P, file, line, "Film: \"string sensor\" \"%s\": unknown sensor type "
                "(pbrt-v4 knows \"cie1931\" and 17 named cameras: %s)", sensor, names);
}

/* The output file: the command line's -o, else Film "string filename" fn (NULL:
   pbrt-v4's default), an .exr turned into a .pfm. */
static int film_output_name(Parser *P, SceneSettings *st, const char *fn, const char *file, int line)
{
    if (P->output) {
        /* pbrt-v4 (FilmBaseParameters): a file named on the command line wins over
           the scene's; the scene's name is then never used, so it is not checked
           (placeholders such as "__OUTPUT_PNG__" are common in shared scenes).
           pbrt-v4 warns whenever the scene names a file; specnee notes it only
           where the name is not one it writes as given (a placeholder, .exr, another
           format), so the shipped scenes' usual `-o` renders stay quiet */
        if (fn && !ends_with_ci(fn, ".pfm") && !ends_with_ci(fn, ".ppm") && !ends_with_ci(fn, ".png"))
            fprintf(stderr, "%s:%d: note: the output file \"%s\" of the command line "
                    "overrides Film \"string filename\" \"%s\" (as pbrt-v4 --outfile does)\n",
                    file, line, P->output, fn);
        snprintf(st->filename, sizeof st->filename, "%s", P->output);
        return 1;
    }
    if (!fn) fn = "pbrt.exr";                         /* pbrt-v4's default */
    if (strlen(fn) + 1 > sizeof st->filename)
        return fail(P, file, line, "Film: filename longer than %d characters",
                    (int)sizeof st->filename - 1);
    if (ends_with_ci(fn, ".exr")) {
        /* specnee has no EXR writer: the same name with .pfm (float32 too) */
        size_t n = strlen(fn);
        snprintf(st->filename, sizeof st->filename, "%.*s.pfm", (int)(n - 4), fn);
        fprintf(stderr, "%s:%d: note: specnee writes no EXR; \"%s\" becomes \"%s\"\n",
                file, line, fn, st->filename);
    } else if (ends_with_ci(fn, ".pfm") || ends_with_ci(fn, ".ppm") || ends_with_ci(fn, ".png")) {
        snprintf(st->filename, sizeof st->filename, "%s", fn);
    } else {
        return fail(P, file, line, "Film: \"string filename\" \"%s\": specnee writes .pfm, "
                    ".ppm or .png (.exr becomes .pfm)", fn);
    }
    return 1;
}

/* Film "spectral"'s own parameters (pbrt-v4 SpectralFilm::Create): read before
   the unused-parameter check (check 0) or checked after it (check 1), with its
   output file: the command line's -o, else "string filename" fn (NULL: pbrt-v4's
   default), which must be an .exr, as pbrt-v4 writes the spectral film as EXR
   only.  specnee's EXR writer (exr.c) takes 64 channels: R, G, B and 61 buckets. */
static int film_spectral(Parser *P, ParamList *pl, int check, const char *fn, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    const char *name = P->output ? P->output : fn ? fn : "pbrt.exr";
    if (!check)
        return get_int(P, pl, "nbuckets", 16, &st->nbuckets, NULL) &&
               get_float(P, pl, "lambdamin", (float)SPEC_MIN, &st->lambda_min) &&
               get_float(P, pl, "lambdamax", (float)SPEC_MAX, &st->lambda_max);
    if (st->nbuckets < 1 || st->nbuckets > 61)
        return fail_param(P, pl, "nbuckets", file, line, "Film \"spectral\": \"integer nbuckets\" "
                          "%d outside 1..61 (specnee's EXR writer takes 64 channels)", st->nbuckets);
    if (!(st->lambda_min >= (float)SPEC_MIN && st->lambda_max <= (float)SPEC_MAX &&
          st->lambda_min < st->lambda_max))
        return fail_param(P, pl, st->lambda_min >= (float)SPEC_MIN ? "lambdamax" : "lambdamin", file, line,
                          "Film \"spectral\": wavelengths %g..%g nm: \"float lambdamin\" < \"float "
                          "lambdamax\" within pbrt-v4's range %d..%d nm", st->lambda_min,
                          st->lambda_max, SPEC_MIN, SPEC_MAX);
    if (strlen(name) + 1 > sizeof st->filename)
        return fail(P, file, line, "Film: filename longer than %d characters",
                    (int)sizeof st->filename - 1);
    if (!ends_with_ci(name, ".exr"))
        return fail_param(P, pl, P->output ? "" : "filename", file, line, "Film \"spectral\": "
                          "\"%s\": pbrt-v4 writes the spectral film as .exr only", name);
    snprintf(st->filename, sizeof st->filename, "%s", name);
    return 1;
}

int film_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    SceneSettings *st = &P->s->settings;
    int xres, yres, fp16;
    const char *fn;
    int gbuffer = !strcmp(type, "gbuffer");
    float iso, maxcomp, scale, wb, diagonal;
    const char *coordsys = NULL, *sensor;
    char what[24];
    Param *crop, *pb;
    st->spectral = !strcmp(type, "spectral");
    if (strcmp(type, "rgb") != 0 && !gbuffer && !st->spectral)
        return fail(P, file, line, "Film \"%s\": unknown film type", type);
    if (!get_int(P, pl, "xresolution", 1280, &xres, NULL)) return 0;
    if (!get_int(P, pl, "yresolution", 720, &yres, NULL)) return 0;
    if (!get_string(P, pl, "filename", &fn)) return 0;
    if (!get_bool(P, pl, "savefp16", 1, &fp16)) return 0;    /* PFM is float32 anyway */
    st->savefp16 = fp16;                                       /* the spectral film's EXR */
    if (!get_float(P, pl, "iso", 100.0f, &iso)) return 0;
    if (!get_float(P, pl, "maxcomponentvalue", INFINITY, &maxcomp)) return 0;
    if (!get_float(P, pl, "scale", 1.0f, &scale)) return 0;
    if (!get_float(P, pl, "whitebalance", 0.0f, &wb)) return 0;
    if (!get_string(P, pl, "sensor", &sensor)) return 0;
    if (!get_float(P, pl, "diagonal", 35.0f, &diagonal)) return 0;   /* mm: the realistic camera's */
    crop = param_find(pl, PT_FLOAT, "cropwindow");
    pb = param_find(pl, PT_INTEGER, "pixelbounds");
    if (gbuffer && !get_string(P, pl, "coordinatesystem", &coordsys)) return 0;
    if (st->spectral && !film_spectral(P, pl, 0, fn, file, line)) return 0;
    snprintf(what, sizeof what, "Film \"%s\"", type);
    if (!params_check_unused(P, pl, what,
                             gbuffer ? "integer xresolution, integer yresolution, string filename, "
                                       "bool savefp16, float iso, float maxcomponentvalue, "
                                       "float whitebalance, string sensor, float cropwindow, "
                                       "integer pixelbounds, float scale, float diagonal, "
                                       "string coordinatesystem"
                             : st->spectral ? "integer xresolution, integer yresolution, string filename, "
                                       "bool savefp16, float iso, float maxcomponentvalue, "
                                       "float whitebalance, string sensor, float cropwindow, "
                                       "integer pixelbounds, float scale, integer nbuckets, "
                                       "float lambdamin, float lambdamax"
                                     : "integer xresolution, integer yresolution, string filename, "
                                       "bool savefp16, float iso, float maxcomponentvalue, "
                                       "float whitebalance, string sensor, float cropwindow, "
                                       "integer pixelbounds, float scale, float diagonal",
                             "exposuretime writefp16"))
        return 0;
    if (st->spectral && !film_spectral(P, pl, 1, fn, file, line)) return 0;
    /* pbrt-v4's sensor: "cie1931" (the default) records XYZ, a named camera its
       measured RGB (sensor.c) */
    if (sensor && sensor_index(sensor) < 0) return film_unknown_sensor(P, sensor, file, line);
    if (!(wb == 0.0f || (wb >= 1000.0f && wb <= 100000.0f)))
        return fail_param(P, pl, "whitebalance", file, line, "Film: \"float whitebalance\" %g: a colour temperature "
                    "within 1000..100000 K, or 0 for none", wb);
    if (!(scale > 0.0f))
        return fail_param(P, pl, "scale", file, line, "Film: \"float scale\" %g must be > 0", scale);
    if (!(diagonal > 0.0f && diagonal <= FLT_MAX))
        return fail_param(P, pl, "diagonal", file, line, "Film: \"float diagonal\" %g (mm) must be "
                          "finite and > 0", diagonal);
    if (crop && crop->n_num != 4)
        return fail(P, crop->file, crop->line, "Film: \"float cropwindow\": %d values, "
                    "expected 4 (x0 x1 y0 y1, fractions of the film)", crop->n_num);
    if (pb && pb->n_num != 4)
        return fail(P, pb->file, pb->line, "Film: \"integer pixelbounds\": %d values, "
                    "expected 4 (x0 x1 y0 y1, pixels)", pb->n_num);
    if (xres < 1 || xres > MAX_RESOLUTION || yres < 1 || yres > MAX_RESOLUTION)
        return fail(P, file, line, "Film: resolution %d x %d outside 1..%d per axis",
                    xres, yres, MAX_RESOLUTION);
    {   /* what the render's buffers would take, against the stated budget (the
           spectral film: a sum and a weight sum in double, and a float, a bucket) */
        double need = (double)xres * yres * (FILM_BYTES_PER_PIXEL + (st->spectral ? 20.0 * st->nbuckets : 0.0));
        if (need > (double)MEM_BUDGET_MIB * 1048576.0)
            return fail(P, file, line, "Film: %d x %d pixels would need %.1f GiB for the "
                        "render's buffers, more than specnee's memory budget of %.0f GiB "
                        "(MEM_BUDGET_MIB in specnee.h)", xres, yres, need / 1073741824.0,
                        MEM_BUDGET_MIB / 1024.0);
    }
    if (!(iso > 0.0f) || !(maxcomp > 0.0f))
        return fail(P, file, line, "Film: \"float iso\" %g and \"float maxcomponentvalue\" %g "
                    "must be > 0", iso, maxcomp);
    if (gbuffer)
        fprintf(stderr, "%s:%d: note: Film \"gbuffer\" is read as \"rgb\": specnee writes "
                "the colour image only, without the geometry channels\n", file, line);
    P->iso = iso;
    if (scale != 1.0f) {
        /* pbrt-v3's film scale: current pbrt-v4 refuses it as unused, and its
           --upgrade rewrites it as "float iso" 100 * scale; specnee reads it so */
        fprintf(stderr, "%s:%d: note: Film \"float scale\" %g is pbrt-v3 syntax (pbrt-v4 "
                "reads \"float iso\" %g instead, as its --upgrade writes): the image is "
                "scaled by %g\n", file, line, scale, 100.0 * scale, scale);
        P->iso = iso * scale;
    }
    st->max_component = maxcomp;
    st->film_diagonal = diagonal;
    st->xres = xres;
    st->yres = yres;
    /* pbrt-v4's RGBFilm keeps its pixels in the colour space current here, and
       converts them to sRGB to write any file but an EXR: the same pixels as this
       sRGB film (specnee's EXR is sRGB too).  Only a camera sensor or a white
       balance depends on it: they aim at the space's white, which sensor.c takes
       to be D65's (srgb, dci-p3, rec2020), not ACES's */
    if (P->gs.colorspace == COLORSPACE_ACES && ((sensor && sensor_index(sensor) > 0) || wb != 0.0f))
        return fail(P, file, line, "Film: \"string sensor\" or \"float whitebalance\" with ColorSpace "
                    "\"aces2065-1\" is not in the specnee subset (sensor.c balances to D65)");
    /* pbrt-v4: a camera sensor is white-balanced for 6500 K unless told otherwise */
    st->sensor = sensor ? sensor_index(sensor) : 0;
    st->white_balance = st->sensor > 0 && wb == 0.0f ? 6500.0f : wb;
    if (st->white_balance > 0.0f && !sensor_xyz_matrix(st->sensor, st->white_balance, st->white_balance_m))
        return fail(P, file, line, "Film: sensor \"%s\": its XYZ-from-sensor-RGB matrix is singular",
                    sensor_name(st->sensor));
    st->crop_set = crop != NULL;
    st->pixel_bounds_set = pb != NULL && !crop;   /* pbrt-v4: the crop window wins */
    if (crop) {
        /* pbrt-v4: each pair sorted, clamped to [0, 1] */
        int a;
        for (a = 0; a < 2; a++) {
            double lo = crop->num[2 * a] < crop->num[2 * a + 1] ? crop->num[2 * a] : crop->num[2 * a + 1];
            double hi = crop->num[2 * a] < crop->num[2 * a + 1] ? crop->num[2 * a + 1] : crop->num[2 * a];
            st->crop[2 * a] = (float)(lo < 0.0 ? 0.0 : lo > 1.0 ? 1.0 : lo);
            st->crop[2 * a + 1] = (float)(hi < 0.0 ? 0.0 : hi > 1.0 ? 1.0 : hi);
        }
    }
    if (pb) {
        int a;
        for (a = 0; a < 4; a++) st->pixel_bounds[a] = (int)pb->num[a];
    }
    {
        int b[4];
        if (!film_bounds(st, b))
            return fail(P, file, line, "Film: the %s selects no pixel of the %d x %d film "
                        "(x %d..%d, y %d..%d)", crop ? "cropwindow" : "pixelbounds",
                        xres, yres, b[0], b[1], b[2], b[3]);
    }
    return st->spectral ? 1 : film_output_name(P, st, fn, file, line);
}

/* PixelFilter: pbrt-v4's five filters with its parameter names and defaults
   (filters.cpp; their formulas and how samples are drawn: filter.c). */
int filter_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const struct { const char *name; FilterType t; float radius; const char *reads; }
    kinds[] = {
        { "box", FILTER_BOX, 0.5f, "float xradius, float yradius" },
        { "gaussian", FILTER_GAUSSIAN, 1.5f, "float xradius, float yradius, float sigma" },
        { "triangle", FILTER_TRIANGLE, 2.0f, "float xradius, float yradius" },
        { "mitchell", FILTER_MITCHELL, 2.0f, "float xradius, float yradius, float B, float C" },
        { "sinc", FILTER_SINC, 4.0f, "float xradius, float yradius, float tau" },
    };
    SceneSettings *st = &P->s->settings;
    float xr, yr, sigma = 0.5f, B = 1.0f / 3.0f, C = 1.0f / 3.0f, tau = 3.0f;
    char what[160];
    int k;
    for (k = 0; k < 5 && strcmp(type, kinds[k].name) != 0; k++) {}
    if (k == 5)
        return fail(P, file, line, "PixelFilter \"%s\": unknown filter type (pbrt-v4 knows "
                    "box, gaussian, mitchell, sinc, triangle)", type);
    /* pbrt-v4 names the radii xradius/yradius */
    if (!get_float(P, pl, "xradius", kinds[k].radius, &xr)) return 0;
    if (!get_float(P, pl, "yradius", kinds[k].radius, &yr)) return 0;
    if (kinds[k].t == FILTER_GAUSSIAN && !get_float(P, pl, "sigma", 0.5f, &sigma)) return 0;
    if (kinds[k].t == FILTER_MITCHELL && (!get_float(P, pl, "B", B, &B) || !get_float(P, pl, "C", C, &C)))
        return 0;
    if (kinds[k].t == FILTER_SINC && !get_float(P, pl, "tau", 3.0f, &tau)) return 0;
    snprintf(what, sizeof what, "PixelFilter \"%s\"", type);
    if (!params_check_unused(P, pl, what, kinds[k].reads, NULL)) return 0;
    if (xr != yr)
        return fail(P, file, line, "PixelFilter: xradius %g != yradius %g is valid pbrt-v4 "
                    "but not in the specnee subset", xr, yr);
    if (!(xr > 0.0f && xr <= 16.0f) || !(sigma > 0.0f && sigma <= 16.0f))
        return fail(P, file, line, "PixelFilter: radius and sigma must be within (0, 16]");
    if (!(tau > 0.0f))
        return fail_param(P, pl, "tau", file, line, "PixelFilter \"sinc\": \"float tau\" %g must be > 0", tau);
    st->filter = kinds[k].t;
    st->filter_radius = xr;
    st->filter_sigma = sigma;
    st->filter_b = B;
    st->filter_c = C;
    st->filter_tau = tau;
    return 1;
}

/* Accelerator: pbrt-v4's choice of ray-intersection structure ("bvh" with
   splitmethod/maxnodeprims, or "kdtree").  It changes how fast rays are traced,
   never what they hit, so the image does not depend on it: specnee reads the
   parameters pbrt-v4 reads (an unknown one is an error, as there), ignores them
   and says so; its own BVH (bvh.c) is always built. */
int accelerator_directive(Parser *P, const char *type, ParamList *pl, const char *file,
                          int line)
{
    const char *split;
    int n;
    float f;
    if (!strcmp(type, "bvh")) {
        if (!get_string(P, pl, "splitmethod", &split)) return 0;
        if (!get_int(P, pl, "maxnodeprims", 4, &n, NULL)) return 0;
        if (!params_check_unused(P, pl, "Accelerator \"bvh\"",
                                 "string splitmethod, integer maxnodeprims", NULL))
            return 0;
    } else if (!strcmp(type, "kdtree")) {
        if (!get_int(P, pl, "intersectcost", 5, &n, NULL)) return 0;
        if (!get_int(P, pl, "traversalcost", 1, &n, NULL)) return 0;
        if (!get_float(P, pl, "emptybonus", 0.5f, &f)) return 0;
        if (!get_int(P, pl, "maxprims", 1, &n, NULL)) return 0;
        if (!get_int(P, pl, "maxdepth", -1, &n, NULL)) return 0;
        if (!params_check_unused(P, pl, "Accelerator \"kdtree\"",
                                 "integer intersectcost, integer traversalcost, float emptybonus, "
                                 "integer maxprims, integer maxdepth", NULL))
            return 0;
    } else {
        return fail(P, file, line, "Accelerator \"%s\": unknown accelerator type (pbrt-v4 "
                    "knows \"bvh\" and \"kdtree\")", type);
    }
    fprintf(stderr, "%s:%d: note: Accelerator \"%s\" is read and ignored: specnee always "
            "builds its own BVH, and the accelerator does not change the image\n", file, line, type);
    return 1;
}

int sampler_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const char *const known[] = {
        "halton", "independent", "paddedsobol", "pmj02bn", "sobol", "stratified", "zsobol", NULL
    };
    SceneSettings *st = &P->s->settings;
    int i, spp, seed, given = 0, seed_given = 0, jitter = 1, xs = 0, ys = 0;
    const char *rnd;
    char what[48];
    for (i = 0; known[i]; i++)
        if (!strcmp(type, known[i])) break;
    if (!known[i]) return fail(P, file, line, "Sampler \"%s\": unknown sampler type", type);
    if (!strcmp(type, "stratified")) {
        /* pbrt-v4: xsamples * ysamples (4 x 4 by default), no pixelsamples */
        int gx, gy;
        if (!get_int(P, pl, "xsamples", 4, &xs, &gx)) return 0;
        if (!get_int(P, pl, "ysamples", 4, &ys, &gy)) return 0;
        if (!get_bool(P, pl, "jitter", 1, &jitter)) return 0;
        if (xs < 1 || ys < 1 || xs > 4096 || ys > 4096)
            return fail(P, file, line, "Sampler \"stratified\": xsamples/ysamples must be "
                        "within 1..4096");
        spp = xs * ys;
        given = gx || gy;
    } else {
        /* pbrt-v4 defaults: 4 for independent, 16 for the others */
        if (!get_int(P, pl, "pixelsamples", strcmp(type, "independent") ? 16 : 4, &spp, &given))
            return 0;
        /* pbrt-v4 reads "string randomization" for halton, paddedsobol, sobol and
           zsobol only (samplers.cpp, each Create) */
        if (strcmp(type, "independent") != 0 && strcmp(type, "pmj02bn") != 0 &&
            !get_string(P, pl, "randomization", &rnd))
            return 0;
    }
    if (!get_int(P, pl, "seed", 0, &seed, &seed_given)) return 0;
    /* specnee reads every parameter pbrt-v4's sampler of this type reads
       (samplers.cpp): any other is an unused parameter there too, e.g. "integer
       pixelsamples" of "stratified", which pbrt-v4 takes from --spp only */
    snprintf(what, sizeof what, "Sampler \"%s\"", type ? type : "");
    if (!params_check_unused(P, pl, what,
                             !strcmp(type, "stratified") ? "integer xsamples, integer ysamples, bool jitter, integer seed"
                             : !strcmp(type, "independent") || !strcmp(type, "pmj02bn") ? "integer pixelsamples, integer seed"
                             : "integer pixelsamples, integer seed, string randomization", NULL))
        return 0;
    if (spp < 1 || spp > MAX_SPP)
        return fail_param(P, pl, "pixelsamples", file, line, "Sampler: %d samples per pixel outside 1..%d", spp, MAX_SPP);
    st->spp = spp;
    st->spp_set = given;
    st->seed = seed;
    st->seed_set = seed_given;
    st->xsamples = xs;
    st->ysamples = ys;
    st->jitter = jitter;
    /* pbrt-v4's samplers specnee does not have map to the nearest it has
       (docs/sampling.md): pmj02bn and paddedsobol are per-pixel stratified
       low-discrepancy points like specnee's padded Owen-scrambled sobol; halton is
       specnee's halton (one high-dimensional point per sample, sampler.c) */
    if (!strcmp(type, "pmj02bn") || !strcmp(type, "paddedsobol")) {
        fprintf(stderr, "%s:%d: note: Sampler \"%s\": specnee uses its nearest, \"sobol\" "
                "(padded, Owen-scrambled), with the same sample count\n", file, line, type);
        type = "sobol";
    }
    snprintf(st->sampler, sizeof st->sampler, "%s", type);
    return 1;
}

int integrator_directive(Parser *P, const char *type, ParamList *pl, const char *file, int line)
{
    static const char *const pbrt_types[] = {
        "ambientocclusion", "bdpt", "function", "lightpath", "mlt", "randomwalk",
        "simplevolpath", "sppm", "volpath", NULL
    };
    SceneSettings *st = &P->s->settings;
    int i, maxdepth, given, regularize, dummy_i;
    float dummy_f;
    const char *ls = NULL, *reads;
    char what[64];
    /* volpath (pbrt-v4's default) is specnee's path tracer with its media
       (path.c, docs/media.md); bdpt converges to the same image (pbrt-v4's bdpt
       renders media too); sppm and simplepath (pbrt-v4's unidirectional path tracer
       without MIS: uniform light choice, lights and/or BSDF sampled, every variant
       unbiased) to the image of "path", which ignores media (settings.media_ignored) */
    int as_path = !strcmp(type, "volpath") || !strcmp(type, "bdpt") || !strcmp(type, "sppm") ||
                  !strcmp(type, "simplepath");
    if (strcmp(type, "path") != 0 && !as_path) {
        for (i = 0; pbrt_types[i]; i++)
            if (!strcmp(type, pbrt_types[i]))
                return fail(P, file, line, "Integrator \"%s\" is valid pbrt-v4 but not in the "
                            "specnee subset (use \"path\")", type);
        return fail(P, file, line, "Integrator \"%s\": unknown integrator type", type);
    }
    snprintf(what, sizeof what, "Integrator \"%s\"", type);
    if (!get_int(P, pl, "maxdepth", DEFAULT_MAXDEPTH, &maxdepth, &given)) return 0;
    if (strcmp(type, "bdpt") != 0 && strcmp(type, "sppm") != 0 && strcmp(type, "simplepath") != 0 &&
        !get_string(P, pl, "lightsampler", &ls)) return 0;
    if (strcmp(type, "sppm") != 0 && strcmp(type, "simplepath") != 0 &&
        !get_bool(P, pl, "regularize", 0, &regularize)) return 0;
    if (!strcmp(type, "sppm") || !strcmp(type, "simplepath")) regularize = 0;
    if (!strcmp(type, "simplepath") &&
        (!get_bool(P, pl, "samplelights", 1, &dummy_i) || !get_bool(P, pl, "samplebsdf", 1, &dummy_i)))
        return 0;
    {   /* pbrt-v3's Russian-roulette threshold, which pbrt-v4 read only in 2020
           (until its commit 56ee5e8c): current pbrt-v4 starts the roulette when the
           throughput's largest component falls below 1 after the second bounce,
           its --upgrade drops the parameter and a plain pbrt-v4 refuses it as
           unused.  The roulette is unbiased, so ignoring it changes noise only,
           never the expected image */
        Param *rr = param_find(pl, PT_FLOAT, "rrthreshold");
        if (rr)
            fprintf(stderr, "%s:%d: note: Integrator \"float rrthreshold\" is pbrt-v3 syntax "
                    "that pbrt-v4 no longer reads (its --upgrade drops it): ignored\n",
                    rr->file, rr->line);
    }
    if (!strcmp(type, "bdpt")) {
        /* debugging images of bdpt's strategies: nothing to show for path */
        if (!get_bool(P, pl, "visualizestrategies", 0, &dummy_i)) return 0;
        if (dummy_i) return fail(P, file, line, "Integrator \"bdpt\": visualizestrategies is "
                                 "not in the specnee subset");
        if (!get_bool(P, pl, "visualizeweights", 0, &dummy_i)) return 0;
        if (dummy_i) return fail(P, file, line, "Integrator \"bdpt\": visualizeweights is "
                                 "not in the specnee subset");
    }
    if (!strcmp(type, "sppm")) {              /* photon-map settings: no meaning for path */
        if (!get_int(P, pl, "photonsperiteration", -1, &dummy_i, NULL)) return 0;
        if (!get_float(P, pl, "radius", 1.0f, &dummy_f)) return 0;
        if (!get_int(P, pl, "seed", 0, &dummy_i, NULL)) return 0;
    }
    reads = !strcmp(type, "bdpt") ? "integer maxdepth, bool regularize, "
                "bool visualizestrategies, bool visualizeweights"
            : !strcmp(type, "sppm") ? "integer maxdepth, integer "
                "photonsperiteration, float radius, integer seed"
            : !strcmp(type, "simplepath") ? "integer maxdepth, bool samplelights, bool samplebsdf"
            : "integer maxdepth, string lightsampler, bool regularize";
    /* the first problem in the file is named: a parameter left over before
       "bool regularize" true, else regularize, else one after it.  path and volpath
       regularize as pbrt-v4's (path.c); bdpt, which regularizes its light subpaths
       too, is rendered by the path tracer: refused there */
    if (regularize && !strcmp(type, "bdpt"))
        return refuse_param(P, pl, what, reads, param_find(pl, PT_BOOL, "regularize"), file, line,
                            "Integrator: \"bool regularize\" true is valid pbrt-v4 but "
                            "not supported by specnee");
    if (!params_check_unused(P, pl, what, reads, NULL))
        return 0;
    if (as_path && strcmp(type, "volpath") != 0)
        fprintf(stderr, "%s:%d: note: Integrator \"%s\" is rendered by specnee's path tracer "
                "(the same expected image%s)\n", file, line, type,
                !strcmp(type, "bdpt") ? ", media included" : "; media are ignored, as by pbrt-v4's");
    st->media_ignored = !strcmp(type, "path") || !strcmp(type, "simplepath") || !strcmp(type, "sppm");
    st->sss_ignored = strcmp(type, "volpath") != 0;     /* only pbrt-v4's volpath has BSSRDFs */
    P->integ_file = file;
    P->integ_line = line;
    snprintf(P->integ_type, sizeof P->integ_type, "%s", type);
    if (maxdepth < 0 || maxdepth > MAX_MAXDEPTH)
        return fail_param(P, pl, "maxdepth", file, line, "Integrator: maxdepth %d outside 0..%d", maxdepth, MAX_MAXDEPTH);
    st->maxdepth = maxdepth;
    st->maxdepth_set = given;
    st->regularize = regularize;
    if (ls) {
        if (strlen(ls) + 1 > sizeof st->lightsampler)
            return fail(P, file, line, "Integrator: lightsampler name \"%s\" too long", ls);
        snprintf(st->lightsampler, sizeof st->lightsampler, "%s", ls);
    }
    return 1;
}
