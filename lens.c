/* lens.c - pbrt-v4's RealisticCamera: a film behind a system of spherical lens
   elements, each camera ray traced through the glass (docs/THEORY.md §17).

   Implements (specnee.h section 8): lens_read (a lens file), lens_set_stop and
   lens_set_aperture (the Camera's stop), lens_focus (the
   thick-lens focus and the exit pupil's bounds), lens_trace (one ray through the
   elements) and lens_ray (a film point and a pupil sample to a camera-space ray
   and its weight).  options.c reads Camera "realistic" with lens_read, scene.c's
   finish() calls lens_focus once the film's size is known, camera.c calls lens_ray.

   THE LENS FILE (pbrt-v4's format): numbers, four per interface, from the front
   (scene side) to the rear (film side); '#' starts a comment.  Per interface, in mm:
   the radius of curvature R (> 0: the centre lies towards the film; 0: the
   aperture stop, a flat disk), the thickness (the distance along the axis to the
   next interface; the last one's is replaced by the focus), the index of
   refraction eta of the medium after the interface (0 or 1: air) and the
   aperture's diameter.  Everything is scaled to metres (scene units).

   COORDINATES.  Camera space (pbrt's, left-handed): the film is the plane z = 0,
   the lens lies towards +z, the rear interface at z = t_rear (the last
   thickness), the front one at z = sum of all thicknesses.  A film point of raster
   (x, y) on the xres x yres film of diagonal D sits at
     p_film = (W/2 - W x / xres,  -H/2 + H y / yres,  0),  W = D / sqrt(1 + a^2),
     H = a W,  a = yres / xres
   (mirrored in x, since the lens flips the image).

   TRACING (lens_trace).  Interface i is a sphere of radius R_i centred on the
   axis at z_i + R_i (z_i: where it crosses the axis); a ray meets it at the root
   t of |o + t d - c|^2 = R^2 that lies on the side the light comes from
   (the nearer one when d_z and R have the same orientation), is stopped outside
   the aperture radius, and refracts by Snell's law with the relative index
   eta_t / eta_i, dropped at total internal reflection.  The stop is the plane
   z = z_i; it only clips, unless "string aperture" names one of pbrt-v4's
   built-in shapes: then a ray from the film that crosses it at (x, y) weighs
   A(u, v), the bilinear lookup at u = (x/r + 1)/2, v = (y/r + 1)/2 of a
   256 x 256 raster of the shape (rows flipped, black outside), scaled so that
   its mean over the raster is pi/4, the circle's share of its square:
     gaussian  max(0, exp(-|s|^2) - exp(-1)),  s the pixel centre in [-1, 1]^2
     square    4 inside the central half of each axis (pixels 64..191)
     pentagon  1 inside the regular pentagon of circumradius 0.8, a vertex at +y
               before the flip
     star      1 inside the five-pointed star of outer radius 1 (inner
               cos 72 / cos 36), a point at -x
   (the polygons by their winding number at the pixel centres).

   FOCUS (pbrt-v4 FocusThickLens).  A ray parallel to the axis at height h =
   D/1000, traced through the system from either side, gives that side's focal
   point f_z (where the ray leaving crosses the axis) and principal plane p_z
   (where it reaches height h).  With f = f_z' - p_z' and the object at z = -d
   (lens coordinates, d = "focusdistance"), the Gaussian lens equation
   1/s + 1/s' = 1/f solved for the shift delta of the film gives
     delta = (p_z + d + p_z' - sqrt(c)) / 2,  c = (p_z + d - p_z')(p_z + d - 4f - p_z'),
   and the rear thickness grows by delta (refused when c <= 0: too close).

   THE EXIT PUPIL.  Rays leave a film point towards points of the plane of the
   rear interface; most are blocked.  For LENS_PUPIL_RINGS rings of film radius
   [r_i, r_(i+1)) (r up to D/2) lens_focus finds the box that holds every point of
   that plane through which a ray from a film point (r, 0, 0) of the ring passes:
   n points along the ring's segment, each towards a Halton point of the square
   of side 3 R_rear, grow the box; the box is then widened by two sample spacings.
   A film point at angle phi uses its ring's box rotated by phi, which holds its
   pupil because the system is round.  A shaped stop is not: its boxes are found
   with the circle that encloses the shape in its place (APERTURE_REACH), a
   superset at every angle.  pbrt-v4 finds them with the shape itself, so its
   turned boxes cut off part of the pupil away from the x axis and its image
   loses light (0.9 % with tests' pentagon, whose 2-D numeric integral specnee
   matches).

   THE WEIGHT (pbrt-v4 RealisticCamera::GenerateRay).  A pupil point p drawn
   uniformly in the box (pdf 1/A) gives the film point's irradiance estimate
     E = A L cos^4(theta) / (pdf t_rear^2),   cos theta = (p - p_film)_z / |p - p_film|,
   (A: a shaped stop's weight, else 1)
   since dA cos theta cos theta' / r^2 with theta' = theta and r = t_rear / cos
   theta is cos^4 theta dA / t_rear^2.  A blocked ray weighs 0 and the sample
   counts as black.  The lens glass itself neither absorbs nor reflects. */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

#define LENS_MM_MAX 1e6          /* no radius, thickness or diameter beyond 1 km */
#define A3DOT(a, b) ((a)[0] * (b)[0] + (a)[1] * (b)[1] + (a)[2] * (b)[2])

/* One element from its four numbers (mm); "" when sane, else what is wrong. */
static const char *lens_element(LensElement *e, const double v[4])
{
    int k;
    for (k = 0; k < 4; k++)
        if (!(fabs(v[k]) <= LENS_MM_MAX)) return "a value is not finite or beyond 1e6 mm";
    if (v[1] < 0.0) return "negative thickness";
    if (!(v[3] > 0.0)) return "aperture diameter <= 0";
    if (v[0] != 0.0 && v[3] > 2.0 * fabs(v[0])) return "aperture wider than its sphere (diameter > 2 |radius|)";
    if (v[2] != 0.0 && !(v[2] >= 1.0 && v[2] <= 4.0)) return "eta outside [1, 4] (0 or 1: air)";
    if (v[0] != 0.0 && v[2] == 0.0) return "eta 0 on a curved interface (0 is written for the stop; air is 1)";
    e->radius = v[0] * 1e-3;
    e->thickness = v[1] * 1e-3;
    e->eta = v[2];
    e->aperture = v[3] * 0.5e-3;
    return "";
}

/* A lens file into L (metres); 0 with "path:line: problem" in err. */
int lens_read(Lens *L, const char *path, Error *err)
{
    FILE *f = fopen(path, "r");
    char buf[1024];
    double v[4];
    int line = 0, nv = 0, first = 0;
    memset(L, 0, sizeof *L);
    if (!f) { error_set(err, path, 0, "cannot open the lens file"); return 0; }
    while (fgets(buf, sizeof buf, f)) {
        char *p = buf, *hash = strchr(buf, '#');
        line++;
        if (!strchr(buf, '\n') && !feof(f)) {
            error_set(err, path, line, "line longer than %d characters", (int)sizeof buf - 2);
            fclose(f);
            return 0;
        }
        if (hash) *hash = 0;
        for (;;) {
            char *end;
            const char *why;
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
            if (!*p) break;
            v[nv] = strtod(p, &end);
            if (end == p || (*end && !strchr(" \t\r\n", *end))) {
                int len = (int)strcspn(p, " \t\r\n");
                error_set(err, path, line, "\"%.*s\" is not a number (a lens file holds radius, "
                          "thickness, eta and aperture diameter per interface, in mm)", len < 20 ? len : 20, p);
                fclose(f);
                return 0;
            }
            p = end;
            if (nv == 0) first = line;
            if (++nv < 4) continue;
            nv = 0;
            if (L->n == LENS_MAX) {
                error_set(err, path, first, "more than %d lens interfaces", LENS_MAX);
                fclose(f);
                return 0;
            }
            why = lens_element(&L->e[L->n], v);
            if (*why) {
                error_set(err, path, first, "lens interface %d: %s", L->n + 1, why);
                fclose(f);
                return 0;
            }
            L->n++;
        }
    }
    fclose(f);
    if (nv) {
        error_set(err, path, line, "%d values left over: a lens file holds four per interface "
                  "(radius, thickness, eta, aperture diameter, in mm)", nv);
        return 0;
    }
    if (L->n == 0) { error_set(err, path, line, "no lens interfaces"); return 0; }
    return 1;
}

/* pbrt-v4 "aperturediameter" (m): every stop narrows to it; 0 when one is wider
   (pbrt-v4 then keeps the stop's own, with a warning). */
int lens_set_stop(Lens *L, double diameter)
{
    int i, ok = 1;
    for (i = 0; i < L->n; i++)
        if (L->e[i].radius == 0.0) {
            if (diameter * 0.5 > L->e[i].aperture) ok = 0;
            else L->e[i].aperture = diameter * 0.5;
        }
    return ok;
}

/* The index of refraction of the medium after interface i (the one before
   interface 0 is air). */
static double eta_after(const Lens *L, int i)
{
    return i < 0 || L->e[i].eta == 0.0 ? 1.0 : L->e[i].eta;
}

#define AP_RES 256               /* pbrt-v4's raster of a built-in aperture shape */
enum { TRACE_SCENE, TRACE_FILM, TRACE_BOUND };    /* lens_interface's modes */
/* Per LENS_APERTURE_*: the radius (in stop radii) of a circle that holds every
   point where the shape weighs more than 0, its raster's bilinear fringe (1.5
   pixels) included: the circle, the gaussian, the square's half diagonal, the
   pentagon's 0.8 and the star's 1. */
static const double APERTURE_REACH[5] = { 1.0, 1.02, 0.7272, 0.82, 1.02 };

/* Whether (x, y) lies inside the polygon v[0..n) (pbrt-v4's winding-number test). */
static int inside_polygon(const double (*v)[2], int n, double x, double y)
{
    int i, wn = 0;
    for (i = 0; i < n; i++) {
        const double *a = v[i], *b = v[(i + 1) % n];
        double e = (x - a[0]) * (b[1] - a[1]) - (y - a[1]) * (b[0] - a[0]);
        if (a[1] <= y) { if (b[1] > y && e > 0.0) wn++; }
        else if (b[1] <= y && e < 0.0) wn--;
    }
    return wn != 0;
}

/* Pixel (x, y) of the shape's raster before its rows are flipped, unscaled. */
static double aperture_pixel(int shape, int x, int y)
{
    double u = -1.0 + 2.0 * (x + 0.5) / AP_RES, v = -1.0 + 2.0 * (y + 0.5) / AP_RES, p[10][2];
    int i;
    if (shape == LENS_APERTURE_GAUSSIAN) return fmax(0.0, exp(-(u * u + v * v)) - exp(-1.0));
    if (shape == LENS_APERTURE_SQUARE)
        return x >= AP_RES / 4 && x < 3 * AP_RES / 4 && y >= AP_RES / 4 && y < 3 * AP_RES / 4 ? 4.0 : 0.0;
    if (shape == LENS_APERTURE_PENTAGON) {   /* clockwise from the top, circumradius 0.8 */
        double c1 = (sqrt(5.0) - 1.0) / 4.0, c2 = (sqrt(5.0) + 1.0) / 4.0;
        double s1 = sqrt(10.0 + 2.0 * sqrt(5.0)) / 4.0, s2 = sqrt(10.0 - 2.0 * sqrt(5.0)) / 4.0;
        double q[5][2];
        q[0][0] = 0.0; q[0][1] = 1.0; q[1][0] = s1; q[1][1] = c1; q[2][0] = s2; q[2][1] = -c2;
        q[3][0] = -s2; q[3][1] = -c2; q[4][0] = -s1; q[4][1] = c1;
        for (i = 0; i < 5; i++) { p[i][0] = 0.8 * q[i][0]; p[i][1] = 0.8 * q[i][1]; }
        return inside_polygon((const double (*)[2])p, 5, u, v);
    }
    for (i = 0; i < 10; i++) {               /* the star, its vertices in reverse order */
        double r = (i & 1) ? 1.0 : cos(72.0 * SPECNEE_PI / 180.0) / cos(36.0 * SPECNEE_PI / 180.0);
        p[9 - i][0] = r * cos(SPECNEE_PI * i / 5.0);
        p[9 - i][1] = r * sin(SPECNEE_PI * i / 5.0);
    }
    return inside_polygon((const double (*)[2])p, 10, u, v);
}

/* The shaped stop's weight at (x, y) in units of its radius: the bilinear lookup
   in the row-flipped raster, black outside it, times the scale (module comment). */
static double aperture_weight(const Lens *L, double x, double y)
{
    double fx = (x + 1.0) * 0.5 * AP_RES - 0.5, fy = (y + 1.0) * 0.5 * AP_RES - 0.5, dx, dy, v = 0.0;
    int x0, y0, i, j;
    if (!(fabs(x) <= 2.0 && fabs(y) <= 2.0)) return 0.0;
    x0 = (int)floor(fx);
    y0 = (int)floor(fy);
    dx = fx - x0;
    dy = fy - y0;
    for (j = 0; j < 2; j++)
        for (i = 0; i < 2; i++) {
            int px = x0 + i, py = y0 + j;
            if (px < 0 || px >= AP_RES || py < 0 || py >= AP_RES) continue;
            v += (i ? dx : 1.0 - dx) * (j ? dy : 1.0 - dy) * aperture_pixel(L->aperture, px, AP_RES - 1 - py);
        }
    return v * L->aperture_scale;
}

/* pbrt-v4 "string aperture": "" (the circle) or a built-in shape; 0 for any
   other name (an image file, which specnee does not read). */
int lens_set_aperture(Lens *L, const char *name)
{
    static const char *const names[] = { "", "gaussian", "square", "pentagon", "star" };
    double sum = 0.0;
    int k, x, y;
    for (k = 0; k < 5; k++)
        if (!strcmp(name, names[k])) break;
    if (k == 5) return 0;
    L->aperture = k;
    L->aperture_scale = 1.0;
    if (k == LENS_APERTURE_CIRCLE) return 1;
    for (y = 0; y < AP_RES; y++)
        for (x = 0; x < AP_RES; x++) sum += aperture_pixel(k, x, y);
    L->aperture_scale = (SPECNEE_PI / 4.0) / (sum / ((double)AP_RES * AP_RES));
    return 1;
}

/* Crossing interface i (at z = zi) in lens space, where the film-side is +z,
   from the film (mode TRACE_FILM or TRACE_BOUND) or from the scene: r->o moves
   to the hit, r->d turns by Snell's law from the medium before to the one after.
   Returns the weight (1; from the film a shaped stop's aperture_weight; for
   TRACE_BOUND the shape's enclosing circle clips instead), 0 when missed,
   clipped by the aperture or totally reflected. */
static double lens_interface(const Lens *L, int i, double zi, int mode, LensRay *r)
{
    int from_film = mode != TRACE_SCENE;
    const LensElement *e = &L->e[i];
    double t, p[3], n[3], w = 1.0;
    double eta_in = eta_after(L, from_film ? i : i - 1), eta_out = eta_after(L, from_film ? i - 1 : i);
    int k;
    if (e->radius == 0.0) {                  /* the stop: the plane z = zi */
        t = (zi - r->o[2]) / r->d[2];
        if (!(t >= 0.0)) return 0;
    } else {                                 /* the sphere of centre (0, 0, zi + R) */
        double o[3], A, B, C, disc, q, t0, t1;
        o[0] = r->o[0]; o[1] = r->o[1]; o[2] = r->o[2] - (zi + e->radius);
        A = r->d[0] * r->d[0] + r->d[1] * r->d[1] + r->d[2] * r->d[2];
        B = 2.0 * (r->d[0] * o[0] + r->d[1] * o[1] + r->d[2] * o[2]);
        C = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - e->radius * e->radius;
        disc = B * B - 4.0 * A * C;
        if (disc < 0.0) return 0;
        q = -0.5 * (B + (B < 0.0 ? -sqrt(disc) : sqrt(disc)));
        t0 = q / A;
        t1 = q != 0.0 ? C / q : t0;
        if (t0 > t1) { double s = t0; t0 = t1; t1 = s; }
        /* the nearer root when the ray runs towards the sphere's centre side */
        t = ((r->d[2] > 0.0) != (e->radius < 0.0)) ? t0 : t1;
        if (!(t >= 0.0)) return 0;
        for (k = 0; k < 3; k++) n[k] = o[k] + t * r->d[k];
    }
    for (k = 0; k < 3; k++) p[k] = r->o[k] + t * r->d[k];
    if (e->radius == 0.0 && L->aperture != LENS_APERTURE_CIRCLE && mode == TRACE_FILM) {
        /* a shaped stop weighs the ray instead (pbrt-v4 only from the film) */
        w = aperture_weight(L, p[0] / e->aperture, p[1] / e->aperture);
        if (w == 0.0) return 0;
    } else if (e->radius == 0.0 && mode == TRACE_BOUND) {
        double rho = APERTURE_REACH[L->aperture] * e->aperture;
        if (p[0] * p[0] + p[1] * p[1] > rho * rho) return 0;
    } else if (p[0] * p[0] + p[1] * p[1] > e->aperture * e->aperture) return 0;
    memcpy(r->o, p, sizeof p);
    if (e->radius != 0.0) {                  /* Snell: w_t = -w_i/eta + (cos_i/eta - cos_t) n */
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), dl, wi[3], ci, s2t, ct, eta;
        dl = sqrt(A3DOT(r->d, r->d));
        for (k = 0; k < 3; k++) { n[k] /= len; wi[k] = -r->d[k] / dl; }
        ci = A3DOT(n, wi);
        if (ci < 0.0) { ci = -ci; for (k = 0; k < 3; k++) n[k] = -n[k]; }   /* n faces wi */
        eta = eta_out / eta_in;
        s2t = (1.0 - ci * ci) / (eta * eta);
        if (s2t >= 1.0) return 0;            /* total internal reflection */
        ct = sqrt(1.0 - s2t);
        for (k = 0; k < 3; k++) r->d[k] = -wi[k] / eta + (ci / eta - ct) * n[k];
    }
    return w;
}

/* Through every interface, from the film (rear first) or from the scene (front
   first; mode as lens_interface's).  r is a camera-space ray; on success it
   becomes the ray that leaves the system (camera space) and its weight is
   returned; 0 when blocked. */
static double trace(const Lens *L, LensRay *r, int mode)
{
    int from_film = mode != TRACE_SCENE;
    double z = 0.0, w = 1.0;
    int i, k;
    r->o[2] = -r->o[2];                      /* camera to lens space: z mirrored */
    r->d[2] = -r->d[2];
    if (from_film) {
        for (i = L->n - 1; i >= 0 && w > 0.0; i--) {
            z -= L->e[i].thickness;
            w *= lens_interface(L, i, z, mode, r);
        }
    } else {
        for (i = 0; i < L->n; i++) z -= L->e[i].thickness;
        for (i = 0; i < L->n && w > 0.0; i++) {
            w *= lens_interface(L, i, z, mode, r);
            z += L->e[i].thickness;
        }
    }
    if (w == 0.0) return 0.0;
    r->o[2] = -r->o[2];
    r->d[2] = -r->d[2];
    for (k = 0; k < 3; k++) if (!isfinite(r->o[k]) || !isfinite(r->d[k])) return 0.0;
    return w;
}

double lens_trace(const Lens *L, LensRay *r, int from_film)
{
    return trace(L, r, from_film ? TRACE_FILM : TRACE_SCENE);
}

/* Sum of the thicknesses: the front interface's z (camera space). */
static double lens_front_z(const Lens *L)
{
    double z = 0.0;
    int i;
    for (i = 0; i < L->n; i++) z += L->e[i].thickness;
    return z;
}

/* One side's cardinal points (pbrt-v4 ComputeCardinalPoints): a ray `in`
   parallel to the axis at height in.o[0] left the system as `out`; *fz is
   where `out` crosses the axis, *pz where it reaches the height of `in` (lens
   coordinates: z mirrored). */
static void cardinal_points(const LensRay *in, const LensRay *out, double *pz, double *fz)
{
    double tf = -out->o[0] / out->d[0], tp = (in->o[0] - out->o[0]) / out->d[0];
    *fz = -(out->o[2] + tf * out->d[2]);
    *pz = -(out->o[2] + tp * out->d[2]);
}

/* The exit pupil's box for film points (r, 0, 0), r in [r0, r1]: n rays (module
   comment).  x0 > x1 when no ray passes. */
static void bound_pupil(const Lens *L, double r0, double r1, int n, double box[4])
{
    double rr = 1.5 * L->e[L->n - 1].aperture, zr = L->e[L->n - 1].thickness;
    int i;
    box[0] = box[1] = INFINITY;
    box[2] = box[3] = -INFINITY;
    for (i = 0; i < n; i++) {
        double fx = r0 + (r1 - r0) * ((i + 0.5) / n);
        double px = -rr + 2.0 * rr * radical_inverse(2, (uint64_t)i);
        double py = -rr + 2.0 * rr * radical_inverse(3, (uint64_t)i);
        LensRay r;
        if (px >= box[0] && px <= box[2] && py >= box[1] && py <= box[3]) continue;
        r.o[0] = fx; r.o[1] = 0.0; r.o[2] = 0.0;
        r.d[0] = px - fx; r.d[1] = py; r.d[2] = zr;
        if (trace(L, &r, TRACE_BOUND) == 0.0) continue;
        if (px < box[0]) box[0] = px;
        if (py < box[1]) box[1] = py;
        if (px > box[2]) box[2] = px;
        if (py > box[3]) box[3] = py;
    }
    if (box[0] <= box[2]) {                  /* widened by two sample spacings */
        double m = 2.0 * (2.0 * rr * sqrt(2.0)) / sqrt((double)n);
        box[0] -= m; box[1] -= m; box[2] += m; box[3] += m;
    }
}

/* Focus the lens at `distance` (m) for a film of diagonal `diagonal` (m), then
   bound its exit pupil with `samples` rays per ring (module comment).  0 with
   the problem in err (no file:line: the caller adds the Camera's). */
int lens_focus(Lens *L, double distance, double diagonal, int samples, Error *err)
{
    LensRay in, out;
    double pz[2], fz[2], f, z = -distance, c, delta, h = 1e-3 * diagonal;
    int i, open = 0;
    L->diagonal = diagonal;
    memset(&in, 0, sizeof in);
    in.o[0] = h; in.o[2] = lens_front_z(L) + 1.0; in.d[2] = -1.0;    /* from the scene */
    out = in;
    if (lens_trace(L, &out, 0) == 0.0) goto blocked;
    cardinal_points(&in, &out, &pz[0], &fz[0]);
    memset(&in, 0, sizeof in);
    in.o[0] = h; in.o[2] = L->e[L->n - 1].thickness - 1.0; in.d[2] = 1.0;   /* from the film */
    out = in;
    if (lens_trace(L, &out, 1) == 0.0) goto blocked;
    cardinal_points(&in, &out, &pz[1], &fz[1]);
    memcpy(L->pz, pz, sizeof pz);
    memcpy(L->fz, fz, sizeof fz);
    f = fz[0] - pz[0];
    c = (pz[1] - z - pz[0]) * (pz[1] - z - 4.0 * f - pz[0]);
    if (!(c > 0.0)) {
        error_set(err, NULL, 0, "Camera \"realistic\": \"float focusdistance\" %g is too short "
                  "for this lens (its focal length is %.4g mm)", distance, f * 1e3);
        return 0;
    }
    delta = (pz[1] - z + pz[0] - sqrt(c)) / 2.0;
    L->e[L->n - 1].thickness += delta;
    if (!(L->e[L->n - 1].thickness > 0.0) || !isfinite(L->e[L->n - 1].thickness)) {
        error_set(err, NULL, 0, "Camera \"realistic\": focused at %g the film would lie at "
                  "%.4g mm, not behind the lens", distance, L->e[L->n - 1].thickness * 1e3);
        return 0;
    }
    for (i = 0; i < LENS_PUPIL_RINGS; i++) {
        bound_pupil(L, diagonal * 0.5 * i / LENS_PUPIL_RINGS, diagonal * 0.5 * (i + 1) / LENS_PUPIL_RINGS,
                    samples, L->pupil[i]);
        open += L->pupil[i][0] <= L->pupil[i][2];
    }
    if (open) return 1;
    error_set(err, NULL, 0, "Camera \"realistic\": no ray from the film passes the lens");
    return 0;
blocked:
    error_set(err, NULL, 0, "Camera \"realistic\": the lens passes no ray parallel to its axis "
              "(is its aperture stop closed?)");
    return 0;
}

/* A camera ray from film point (fx, fy) (metres, camera space) through the exit
   pupil's point (u0, u1); its weight (module comment), 0 when blocked. */
double lens_ray(const Lens *L, double fx, double fy, float u0, float u1, LensRay *r)
{
    const double *b;
    double w, rf = sqrt(fx * fx + fy * fy), px, py, s, c, len, cosv, zr = L->e[L->n - 1].thickness;
    int i = (int)(rf / (0.5 * L->diagonal) * LENS_PUPIL_RINGS);
    if (i > LENS_PUPIL_RINGS - 1) i = LENS_PUPIL_RINGS - 1;
    b = L->pupil[i];
    if (!(b[0] <= b[2])) return 0.0;
    px = b[0] + u0 * (b[2] - b[0]);
    py = b[1] + u1 * (b[3] - b[1]);
    s = rf != 0.0 ? fy / rf : 0.0;           /* the box turned to the film point's angle */
    c = rf != 0.0 ? fx / rf : 1.0;
    r->o[0] = fx; r->o[1] = fy; r->o[2] = 0.0;
    r->d[0] = c * px - s * py - fx;
    r->d[1] = s * px + c * py - fy;
    r->d[2] = zr;
    len = sqrt(A3DOT(r->d, r->d));
    cosv = zr / len;
    w = lens_trace(L, r, 1);
    return w * cosv * cosv * cosv * cosv * (b[2] - b[0]) * (b[3] - b[1]) / (zr * zr);
}
