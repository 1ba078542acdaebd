/* camera.c - pbrt-v4's perspective and realistic cameras: a raster point to a
   world-space ray.

   Exported (render.h, for render.c): camera_init, camera_ray, camera_has_lens.
   The realistic camera (Camera "realistic") traces its rays through the lens
   system of lens.c, which has its equations; camera_ray only moves its rays to
   the world.

   The screen window follows pbrt-v4 (camera_screen_window in options.c): by
   default the shorter image axis spans [-1, 1], and the field of view "fov"
   belongs to that axis; "screenwindow" [x0 x1 y0 y1] replaces it.  A raster point
   (x, y) (y down, pixel units of the full film) maps linearly onto the window,
   sx = x0 + (x / w)(x1 - x0), sy = y1 - (y / h)(y1 - y0), and then to the
   camera-space direction (sx tan(fov/2), sy tan(fov/2), 1).  The camera frame is left-handed, as pbrt's
   (docs/conventions.md).  With "lensradius" > 0 the camera is a thin lens focused
   at "focaldistance" (camera_ray says how); otherwise a pinhole.  Every call is a
   pure function of its arguments: the numbers for the lens come from the caller's
   sampler (render.c asks for them only when there is a lens), and the time
   (render.c draws it only when something moves, motion.c): a moving camera's
   world_from_camera is its motion at that time. */
#include "render.h"
#include <string.h>

void camera_init(Camera *c, const SceneSettings *st)
{
    float sw[4];
    {
        Xform t = st->camera_from_world;
        memcpy(c->world_from_camera.m, t.inv, sizeof t.inv);
        memcpy(c->world_from_camera.inv, t.m, sizeof t.m);
    }
    c->tan_half = tanf(st->fov_deg * 0.5f * PI_F / 180.0f);
    camera_screen_window(st, sw);            /* options.c: pbrt-v4's screen window */
    c->sx0 = sw[0]; c->sx1 = sw[1]; c->sy0 = sw[2]; c->sy1 = sw[3];
    c->w = st->xres;
    c->h = st->yres;
    c->lens_radius = st->lens_radius;
    c->focal_distance = st->focal_distance;
    c->lens = st->lens.n ? &st->lens : NULL;
    if (c->lens) {   /* pbrt-v4: the film's width and height from its diagonal and shape */
        double a = (double)st->yres / (double)st->xres;
        c->film_w = st->lens.diagonal / sqrt(1.0 + a * a);
        c->film_h = a * c->film_w;
    }
    c->moving = xf_differ(&st->camera_from_world, &st->camera_from_world_end);
    if (c->moving) {   /* pbrt-v4: world_from_camera's two ends, interpolated (motion.c) */
        Xform w1;
        memcpy(w1.m, st->camera_from_world_end.inv, sizeof w1.m);
        memcpy(w1.inv, st->camera_from_world_end.m, sizeof w1.inv);
        c->moving = motion_init(&c->motion, &c->world_from_camera, st->camera_t0, &w1, st->camera_t1);
    }
}

int camera_has_lens(const Camera *c)
{
    return c->lens_radius > 0.0f || c->lens != NULL;
}

/* The realistic camera's ray in camera space (lens.c): raster (x, y) to the film
   point of the module comment of lens.c, mirrored in x; returns the ray's weight
   (0 when the lens blocks it). */
static float realistic_ray(const Camera *c, float x, float y, float ul0, float ul1, Vec3 *o, Vec3 *d)
{
    LensRay lr;
    double fx = 0.5 * c->film_w - c->film_w * ((double)x / c->w);
    double fy = -0.5 * c->film_h + c->film_h * ((double)y / c->h);
    float weight = (float)lens_ray(c->lens, fx, fy, ul0, ul1, &lr);
    *o = v3((float)lr.o[0], (float)lr.o[1], (float)lr.o[2]);
    *d = v3((float)lr.d[0], (float)lr.d[1], (float)lr.d[2]);
    return weight;
}

/* Shirley and Chiu's concentric map from the unit square to the unit disk (1997):
   squares around the centre go to circles, so strata stay compact and the map
   keeps area ratios (uniform in, uniform out). */
static void concentric_disk(float u0, float u1, float *dx, float *dy)
{
    float a = 2.0f * u0 - 1.0f, b = 2.0f * u1 - 1.0f, r, phi;
    if (a == 0.0f && b == 0.0f) { *dx = *dy = 0.0f; return; }
    if (fabsf(a) > fabsf(b)) { r = a; phi = (PI_F / 4.0f) * (b / a); }
    else { r = b; phi = PI_F / 2.0f - (PI_F / 4.0f) * (a / b); }
    *dx = r * cosf(phi);
    *dy = r * sinf(phi);
}

/* Raster (x, y), y down, to a world-space ray.  (ul0, ul1) pick the point on the
   lens (unused for a pinhole).

   THIN LENS (pbrt-v4 PerspectiveCamera).  The pinhole ray of the raster point has
   the camera-space direction d = (sx tan, sy tan, 1).  A lens of radius rho_l at
   z = 0 focused at distance z_f sends every ray of that raster point through the
   point where the pinhole ray meets the plane of focus, x_f = z_f d (z = z_f), from
   a point (rho_l e_l, 0) with e_l uniform on the unit disk.  Points on that plane
   are sharp; a point at depth z spreads into a disk of radius rho_l |1/z_f - 1/z|
   in the screen's tan units (the circle of confusion; tested by render_thin_lens). */
Ray camera_ray(const Camera *c, float x, float y, float ul0, float ul1, float time, float *weight)
{
    Ray r;
    Xform tmp;
    const Xform *wfc = &c->world_from_camera;
    float sx = c->sx0 + (x / (float)c->w) * (c->sx1 - c->sx0);
    float sy = c->sy1 - (y / (float)c->h) * (c->sy1 - c->sy0);
    Vec3 d = v3(sx * c->tan_half, sy * c->tan_half, 1.0f), o = v3(0, 0, 0);
    *weight = 1.0f;
    if (c->lens) {
        *weight = realistic_ray(c, x, y, ul0, ul1, &o, &d);
    } else if (c->lens_radius > 0.0f) {
        float lx, ly;
        Vec3 q = v3_mul(d, c->focal_distance);     /* x_f, the point of focus */
        concentric_disk(ul0, ul1, &lx, &ly);
        o = v3(c->lens_radius * lx, c->lens_radius * ly, 0.0f);
        d = v3_sub(q, o);
    }
    if (c->moving) {                                   /* a moving camera (motion.c) */
        motion_at(&c->motion, time, &tmp);
        wfc = &tmp;
    }
    r.o = xf_point(wfc, o);
    r.d = v3_norm(xf_vector(wfc, d));
    r.tmax = INFINITY;
    r.time = time;
    return r;
}
