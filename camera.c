/* camera.c - pbrt-v4's perspective, orthographic, spherical and realistic
   cameras: a raster point to a world-space ray.

   Exported (render.h, for render.c): camera_init, camera_ray, camera_has_lens.
   The realistic camera (Camera "realistic") traces its rays through the lens
   system of lens.c, which has its equations; camera_ray only moves its rays to
   the world.

   The screen window follows pbrt-v4 (camera_screen_window in options.c): by
   default the shorter image axis spans [-1, 1], and the field of view "fov"
   belongs to that axis; "screenwindow" [x0 x1 y0 y1] replaces it.  A raster point
   (x, y) (y down, pixel units of the full film) maps linearly onto the window,
   sx = x0 + (x / w)(x1 - x0), sy = y1 - (y / h)(y1 - y0).  The camera frame is
   left-handed, as pbrt's (docs/conventions.md).  Every call is a pure function
   of its arguments: the numbers for the lens come from the caller's sampler
   (render.c asks for them only when there is a lens), and the time (render.c
   draws it only when something moves, motion.c): a moving camera's
   world_from_camera is its motion at that time.  In camera space:

   PERSPECTIVE.  From the eye o = 0 along d = (sx tan(fov/2), sy tan(fov/2), 1).

   ORTHOGRAPHIC.  From o = (sx, sy, 0) along d = (0, 0, 1): the screen window is
   a rectangle of camera-space (world) units, and every pinhole ray is parallel
   to the camera's z axis.

   THIN LENS (both, "lensradius" rho_l > 0, "focaldistance" z_f; camera_ray).
   Every ray of a raster point passes through the point where its pinhole ray
   meets the plane of focus z = z_f, x_f = o + z_f d (d.z = 1), and leaves the
   lens point (rho_l e_l, 0), e_l uniform on the unit disk.  For the perspective
   camera a point at depth z blurs into a disk of radius rho_l |1/z_f - 1/z| in
   the screen's tan units (tested by render_thin_lens).  The orthographic one
   keeps pbrt-v4's choice: its lens sits at the camera's origin, not under the
   raster point, so its rays converge from near the origin onto x_f = (sx, sy,
   z_f); only the plane of focus keeps the orthographic image.

   SPHERICAL.  The whole sphere of directions on the film, from o = 0; the
   window, "fov" and the lens are not used (pbrt-v4 reads and ignores them).
   (u, v) = (x / w, y / h) in [0, 1]^2 (a filter's sample may fall just outside).
   "equirectangular": theta = pi v, phi = 2 pi u and
       d = (sin theta cos phi, cos theta, sin theta sin phi),
   so the top row looks along +y (up), the middle row's u = 1/4 along +z.
   "equalarea" (the default), Clarberg's octahedral map: a point outside the
   square is first folded back across the edge it crossed (u < 0: (u, v) ->
   (-u, 1 - v); u > 1: (2 - u, 1 - v); likewise v with u -> 1 - u), so the map
   stays continuous across the film's border.  Then a = 2u - 1, b = 2v - 1; the
   signed distance from the diamond |a| + |b| = 1 is s = 1 - |a| - |b|, the ring
   r = 1 - |s| in [0, 1] and
       z' = sign(s) (1 - r^2),   phi' = (pi/4) (1 + (|b| - |a|) / r)  (r = 0: pi/4),
       d' = (sign(a) cos(phi') r sqrt(2 - r^2), sign(b) sin(phi') r sqrt(2 - r^2), z'),
   and d = (d'x, d'z, d'y): the inner diamond (s > 0) is the upper hemisphere
   (the image's centre looks along +y), the four corners the lower one.  The
   ring between r and r + dr has area 4 r dr of [-1, 1]^2 and solid angle
   2 pi |dz'| = 4 pi r dr, and phi' is linear along the ring, so every pixel of a
   w x h film subtends the same 4 pi / (w h) sr (tested by spherical_equal_area). */
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
    c->type = st->camera_type;
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
    c->eye = xf_point(&c->world_from_camera, v3(0.0f, 0.0f, 0.0f));
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

/* pbrt-v4's fold of a point just outside the unit square back across the edge
   it crossed (the module comment), so the equal-area map is continuous there. */
static void equal_area_fold(float *u, float *v)
{
    if (*u < 0.0f) { *u = -*u; *v = 1.0f - *v; }
    else if (*u > 1.0f) { *u = 2.0f - *u; *v = 1.0f - *v; }
    if (*v < 0.0f) { *u = 1.0f - *u; *v = -*v; }
    else if (*v > 1.0f) { *u = 1.0f - *u; *v = 2.0f - *v; }
}

/* The spherical camera's direction of film point (u, v) (the module comment),
   with pbrt-v4's exchange of y and z. */
static Vec3 spherical_dir(CameraType type, float u, float v)
{
    float a, b, s, r, phi, z, rho;
    if (type == CAMERA_EQUIRECT) {
        float theta = PI_F * v;
        phi = 2.0f * PI_F * u;
        return v3(sinf(theta) * cosf(phi), cosf(theta), sinf(theta) * sinf(phi));
    }
    equal_area_fold(&u, &v);
    a = 2.0f * u - 1.0f;
    b = 2.0f * v - 1.0f;
    s = 1.0f - (fabsf(a) + fabsf(b));          /* > 0 inside the diamond */
    r = 1.0f - fabsf(s);
    phi = (r == 0.0f ? 1.0f : (fabsf(b) - fabsf(a)) / r + 1.0f) * (PI_F / 4.0f);
    z = copysignf(1.0f - r * r, s);
    rho = r * sqrtf(2.0f - r * r);             /* r <= 1 */
    return v3(copysignf(cosf(phi), a) * rho, z, copysignf(sinf(phi), b) * rho);
}

/* Raster (x, y), y down, to a world-space ray.  (ul0, ul1) pick the point on the
   lens (unused for a pinhole); the thin lens's equations: the module comment. */
Ray camera_ray(const Camera *c, float x, float y, float ul0, float ul1, float time, float *weight)
{
    Ray r;
    Xform tmp;
    const Xform *wfc = &c->world_from_camera;
    float sx = c->sx0 + (x / (float)c->w) * (c->sx1 - c->sx0);
    float sy = c->sy1 - (y / (float)c->h) * (c->sy1 - c->sy0);
    Vec3 d = v3(sx * c->tan_half, sy * c->tan_half, 1.0f), o = v3(0, 0, 0);
    int at_eye = 1;                                    /* o is still the camera's origin */
    *weight = 1.0f;
    if (c->type == CAMERA_ORTHOGRAPHIC) {
        at_eye = 0;                                    /* orthographic: o on the window */
        o = v3(sx, sy, 0.0f);
        d = v3(0.0f, 0.0f, 1.0f);
    } else if (c->type != CAMERA_PERSPECTIVE) {
        d = spherical_dir(c->type, x / (float)c->w, y / (float)c->h);
    }
    if (c->lens) {
        at_eye = 0;                                    /* realistic: o on the rear lens */
        *weight = realistic_ray(c, x, y, ul0, ul1, &o, &d);
    } else if (c->lens_radius > 0.0f) {
        float lx, ly;
        at_eye = 0;                                    /* thin lens: o on the lens */
        Vec3 q = c->type == CAMERA_ORTHOGRAPHIC ? v3(sx, sy, c->focal_distance)
                                                : v3_mul(d, c->focal_distance);   /* x_f */
        concentric_disk(ul0, ul1, &lx, &ly);
        o = v3(c->lens_radius * lx, c->lens_radius * ly, 0.0f);
        d = v3_sub(q, o);
    }
    if (c->moving) {                                   /* a moving camera (motion.c) */
        motion_at(&c->motion, time, &tmp);
        wfc = &tmp;
        at_eye = 0;                                    /* the eye moves */
    }
    r.o = at_eye ? c->eye : xf_point(wfc, o);          /* a pinhole's eye: the same point, once */
    r.d = v3_norm(xf_vector(wfc, d));
    r.tmax = INFINITY;
    r.time = time;
    return r;
}
