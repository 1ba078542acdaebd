/* tests/test_patch.c - bilinear patches (patch.c, Shape "bilinearmesh") against
   closed forms computed here, and against pbrt-v4.

     patch_planar_hits       a planar trapezoid: a ray aimed at the point of known
                             (u, v) hits it at the known t with that (u, v); the
                             inversion at the point gives (u, v) back; loaded as a
                             bilinearmesh it is two triangles, and a hit through the
                             BVH gets the patch's (u, v) and "uv" interpolated
                             bilinearly (not per triangle), "N" likewise
     patch_twisted_hits      the hyperbolic paraboloid z = x y (corners (-1,-1,1),
                             (1,-1,-1), (-1,1,-1), (1,1,1)): vertical and oblique
                             rays hit at the root of the quadratic, the nearer of two
                             hits along a diagonal, from between them the farther;
                             the normal is (-y, -x, 1) / |.|, negated by
                             ReverseOrientation; rays beyond the edges miss
     patch_area              Shape.area of the twisted patch against the integral of
                             sqrt(1 + x^2 + y^2) over [-1,1]^2 (midpoint rule here),
                             and of a planar trapezoid against its closed form
     patch_sample_chi2       patch_sample on a strongly twisted patch: counts in
                             8 x 8 cells of (u, v) against each cell's share of the
                             area (chi-square)
     patch_checkerboard_pbrt a checkerboard on one bilinear patch (a planar
                             trapezoid with the unit square as "uv", where triangles
                             bend the checks) and on a twisted one: quadrant means
                             against pbrt-v4's, frozen below
     patch_lamp_strategies   a lamp of a twisted and a flat patch: every light
                             selection strategy, and BSDF sampling alone, render
                             the same tile means as uniform selection
     patch_lamp_solid_angle  E[1 / pdf_sa] of a twisted lamp's samples seen from
                             close by: the solid angle by ray casting
     patch_ply_uv            a PLY quad face (a planar trapezoid, its face starting
                             at another corner) is a flat patch: "u v" and "nx ny nz"
                             at a hit are the bilinear interpolation at the (u, v)
                             the map's inverse gives (closed form here)
     patch_ply_twisted       a twisted PLY quad (z = x y) is a patch: hits at
                             t = 5 - x y, its (u, v) from pbrt-v4's corner order
                             p00 p10 p01 p11 = the face's 0 1 3 2
     patch_ply_mixed         a PLY of a triangle and a quad makes a triangle mesh
                             and a patch mesh (two Shapes, each an emitter under
                             AreaLightSource), also inside ObjectBegin
     patch_ply_pbrt          the checkerboard scenes as PLY files (a trapezoid with
                             "u v", a saddle without, faces starting at other
                             corners): quadrant means against pbrt-v4's, frozen
     patch_ply_lamp          patch_lamp_strategies' lamp (a twisted and a flat
                             patch) as a PLY file renders the bilinearmesh's image
                             to the last bit (emission, sampling, light selection)
   Each was watched failing on a one-line mutant (tests/mutants.txt, patch.c). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static Ray ray_of(double ox, double oy, double oz, double dx, double dy, double dz)
{
    Ray r;
    r.o = v3((float)ox, (float)oy, (float)oz);
    r.d = v3((float)dx, (float)dy, (float)dz);
    r.tmax = INFINITY;
    return r;
}

/* The hit of r in scene s (BVH), its surface point in *sp; 0 on a miss. */
static int hit_point(const Scene *s, Ray r, float *t, SurfacePoint *sp)
{
    HitRecord h;
    if (!bvh_intersect(&s->bvh, s, &r, &h)) return 0;
    *t = h.t;
    scene_surface_point(s, &r, &h, sp);
    return 1;
}

#define TRAP "[ -1.4 -1.2 0  1.4 -1.2 0  -0.2 1.2 0  0.2 1.2 0 ]"

static void test_planar_hits(T *t)
{
    static const double uv[3][2] = { { 0.25, 0.75 }, { 0.8, 0.1 }, { 0.5, 0.5 } };
    /* the trapezoid, and a convex quad with no parallel sides in the plane z = 0.1 x + 0.05 y */
    static const float quad[2][4][3] = {
        { { -1.4f, -1.2f, 0.0f }, { 1.4f, -1.2f, 0.0f }, { -0.2f, 1.2f, 0.0f }, { 0.2f, 1.2f, 0.0f } },
        { { -1.0f, -1.0f, -0.15f }, { 1.2f, -0.6f, 0.09f }, { -0.7f, 1.1f, -0.015f }, { 1.5f, 1.9f, 0.245f } },
    };
    Vec3 c[4];
    Scene s;
    int i, k, q;
    for (q = 0; q < 2; q++) {
        for (k = 0; k < 4; k++) c[k] = v3(quad[q][k][0], quad[q][k][1], quad[q][k][2]);
        CHECK(t, patch_is_flat(c), "quad %d is flat", q);
        for (i = 0; i < 3; i++) {
            const double u = uv[i][0], v = uv[i][1], d[3] = { 0.1, -0.2, -1.0 };
            double x[3];
            Ray r;
            float th, uh, vh, ui, vi;
            for (k = 0; k < 3; k++)        /* p(u, v) by hand */
                x[k] = (1 - u) * (1 - v) * quad[q][0][k] + u * (1 - v) * quad[q][1][k] +
                       (1 - u) * v * quad[q][2][k] + u * v * quad[q][3][k];
            r = ray_of(x[0] - 3 * d[0], x[1] - 3 * d[1], x[2] - 3 * d[2], d[0], d[1], d[2]);
            CHECK(t, patch_intersect(c, &r, INFINITY, &th, &uh, &vh), "quad %d: no hit at (%g, %g)", q, u, v);
            CHECK(t, fabs(th - 3.0) < 1e-5 && fabs(uh - u) < 1e-5 && fabs(vh - v) < 1e-5,
                  "quad %d: hit at t %.7g (u, v) (%.7g, %.7g), expected 3 (%g, %g)", q, th, uh, vh, u, v);
            patch_uv_of_point(c, v3((float)x[0], (float)x[1], (float)x[2]), &ui, &vi);
            CHECK(t, fabs(ui - u) < 1e-5 && fabs(vi - v) < 1e-5, "quad %d: inverted (%.7g, %.7g), "
                  "expected (%g, %g)", q, ui, vi, u, v);
        }
    }
    {   /* beside the trapezoid's slanted edge (inside its bounding box): a miss */
        Ray r = ray_of(-1.0, 1.0, 3.0, 0.0, 0.0, -1.0);
        float th, uh, vh;
        for (k = 0; k < 4; k++) c[k] = v3(quad[0][k][0], quad[0][k][1], quad[0][k][2]);
        CHECK(t, !patch_intersect(c, &r, INFINITY, &th, &uh, &vh), "hit outside the trapezoid");
    }
    /* through the scene: two triangles, the patch's (u, v) and a bilinear "uv" and "N" */
    CHECK(t, test_load_scene(t, &s, "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" " TRAP
                             " \"point2 uv\" [ 2 1  4 1  2 5  4 5 ]"
                             " \"normal N\" [ 0 0 1  0.6 0 0.8  0 0 1  0 0 1 ]\n"), "load");
    CHECK(t, s.n_tris == 2 && s.n_patches == 0 && s.shapes[0].bilinear, "stored as two triangles");
    CHECK(t, fabs(s.shapes[0].area - 3.84) < 1e-5, "trapezoid area %.7g, expected (2.8 + 0.4) / 2 x 2.4",
          s.shapes[0].area);
    for (i = 0; i < 3; i++) {
        const double u = uv[i][0], v = uv[i][1];
        const double x = (1 - v) * (-1.4 + 2.8 * u) + v * (-0.2 + 0.4 * u), y = -1.2 + 2.4 * v;
        /* N bilinear: (0.6 w, 0, 1 - 0.2 w), w = u (1 - v), normalised */
        const double nx = 0.6 * u * (1 - v), nz = 1 - 0.2 * u * (1 - v), nl = sqrt(nx * nx + nz * nz);
        SurfacePoint sp;
        float th;
        CHECK(t, hit_point(&s, ray_of(x, y, 2.0, 0.0, 0.0, -1.0), &th, &sp), "BVH miss at (%g, %g)", u, v);
        CHECK(t, fabs(sp.u - (2 + 2 * u)) < 1e-5 && fabs(sp.v - (1 + 4 * v)) < 1e-5,
              "uv at (%g, %g): (%.7g, %.7g), bilinear (%g, %g)", u, v, sp.u, sp.v, 2 + 2 * u, 1 + 4 * v);
        CHECK(t, fabs(sp.ns.x - nx / nl) < 1e-5 && fabs(sp.ns.z - nz / nl) < 1e-5 && sp.ng.z > 0.99f,
              "N at (%g, %g): (%g %g %g), expected (%g 0 %g)", u, v, sp.ns.x, sp.ns.y, sp.ns.z, nx / nl, nz / nl);
    }
    scene_free(&s);
}

#define SADDLE "[ -1 -1 1  1 -1 -1  -1 1 -1  1 1 1 ]"

/* The first hit t > 0 of o + t d with z = x y inside |x|, |y| <= 1 (by hand). */
static double saddle_t(const double o[3], const double d[3])
{
    double a = d[0] * d[1], b = o[0] * d[1] + o[1] * d[0] - d[2], c = o[0] * o[1] - o[2], r[2], best = -1;
    int i, n = 0;
    if (a == 0.0) r[n++] = -c / b;
    else if (b * b - 4 * a * c >= 0) {
        r[n++] = (-b - sqrt(b * b - 4 * a * c)) / (2 * a);
        r[n++] = (-b + sqrt(b * b - 4 * a * c)) / (2 * a);
    }
    for (i = 0; i < n; i++) {
        double x = o[0] + r[i] * d[0], y = o[1] + r[i] * d[1];
        if (r[i] > 0 && fabs(x) <= 1 && fabs(y) <= 1 && (best < 0 || r[i] < best)) best = r[i];
    }
    return best;
}

static void test_twisted_hits(T *t)
{
    static const double ray[7][6] = {
        { 0.3, -0.6, 5, 0, 0, -1 },          /* vertical */
        { -0.9, 0.8, 5, 0, 0, -1 },
        { -2, 0.4, 3, 1, 0.1, -1.2 },        /* oblique */
        { 0.5, 2, -2, -0.2, -1, 0.9 },       /* from below */
        { -1.5, -1.5, 0.25, 1, 1, 0 },       /* along the diagonal: hits at x = y = -0.5 and 0.5 */
        { 0, 0, 0.25, 1, 1, 0 },             /* from between them: only the far one */
        { 1.5, 1.5, 0.25, -1, -1, 0 },       /* the diagonal the other way */
    };
    Scene s;
    int i;
    CHECK(t, test_load_scene(t, &s, "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" " SADDLE "\n"), "load");
    CHECK(t, s.n_tris == 0 && s.n_patches == 1 && s.shapes[0].patch_count == 1, "a twisted patch of its own");
    for (i = 0; i < 7; i++) {
        const double *o = ray[i], *d = ray[i] + 3, te = saddle_t(o, d);
        const double x = o[0] + te * d[0], y = o[1] + te * d[1], nl = sqrt(x * x + y * y + 1);
        SurfacePoint sp;
        float th;
        CHECK(t, te > 0, "ray %d: no hand-computed hit", i);
        CHECK(t, hit_point(&s, ray_of(o[0], o[1], o[2], d[0], d[1], d[2]), &th, &sp), "ray %d missed", i);
        CHECK(t, fabs(th - te) < 1e-5 * (1 + te), "ray %d: t %.7g, expected %.7g", i, th, te);
        CHECK(t, fabs(sp.p.x - x) < 1e-5 && fabs(sp.p.y - y) < 1e-5 && fabs(sp.p.z - x * y) < 1e-5,
              "ray %d: p (%g %g %g), expected (%g %g %g)", i, sp.p.x, sp.p.y, sp.p.z, x, y, x * y);
        CHECK(t, fabs(sp.u - (x + 1) / 2) < 1e-5 && fabs(sp.v - (y + 1) / 2) < 1e-5,
              "ray %d: (u, v) (%g, %g), expected (%g, %g)", i, sp.u, sp.v, (x + 1) / 2, (y + 1) / 2);
        CHECK(t, fabs(sp.ng.x + y / nl) < 1e-5 && fabs(sp.ng.y + x / nl) < 1e-5 && fabs(sp.ng.z - 1 / nl) < 1e-5,
              "ray %d: n (%g %g %g), expected (%g %g %g)", i, sp.ng.x, sp.ng.y, sp.ng.z, -y / nl, -x / nl, 1 / nl);
    }
    {   /* past the edges: misses */
        SurfacePoint sp;
        float th;
        CHECK(t, !hit_point(&s, ray_of(1.05, 0.2, 5, 0, 0, -1), &th, &sp), "hit beyond x = 1");
        CHECK(t, !hit_point(&s, ray_of(-3, 0.5, 0.1, 1, 0.6, 0), &th, &sp), "hit beyond y = 1");
    }
    scene_free(&s);
    {   /* ReverseOrientation: the other side */
        SurfacePoint sp;
        float th;
        CHECK(t, test_load_scene(t, &s, "WorldBegin\nReverseOrientation\nShape \"bilinearmesh\" \"point3 P\" "
                                 SADDLE "\n"), "load");
        CHECK(t, hit_point(&s, ray_of(0, 0, 5, 0, 0, -1), &th, &sp) && sp.ng.z < -0.99f,
              "reversed normal z %g", sp.ng.z);
        scene_free(&s);
    }
}

static void test_area(T *t)
{
    Scene s;
    double ref = 0.0;
    int i, j;
    const int N = 1000;
    /* z = x y over [-1,1]^2: dA = sqrt(1 + x^2 + y^2) dx dy */
    for (i = 0; i < N; i++)
        for (j = 0; j < N; j++) {
            double x = -1 + 2 * (i + 0.5) / N, y = -1 + 2 * (j + 0.5) / N;
            ref += sqrt(1 + x * x + y * y) * (4.0 / ((double)N * N));
        }
    CHECK(t, test_load_scene(t, &s, "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" " SADDLE "\n"), "load");
    CHECK(t, fabs(s.shapes[0].area - ref) < 1e-5 * ref, "saddle area %.9g, midpoint rule %.9g",
          s.shapes[0].area, ref);
    scene_free(&s);
}

static void test_sample_chi2(T *t)
{
    enum { G = 8, M = 24 };
    Vec3 c[4];
    double obs[G * G], ex[G * G], total = 0.0, B[3], C[3], D[3];
    const int n = test_scaled(400000, 100000);
    Rng r;
    int i, j, a, b, k;
    /* z = 3 x y: corner Jacobians differ by a factor sqrt(19), proposals are rejected */
    c[0] = v3(-1, -1, 3); c[1] = v3(1, -1, -3); c[2] = v3(-1, 1, -3); c[3] = v3(1, 1, 3);
    for (k = 0; k < 3; k++) {
        B[k] = v3_get(c[1], k) - v3_get(c[0], k);
        C[k] = v3_get(c[2], k) - v3_get(c[0], k);
        D[k] = v3_get(c[3], k) - v3_get(c[1], k) - v3_get(c[2], k) + v3_get(c[0], k);
    }
    for (i = 0; i < G; i++)                       /* each cell's area, midpoint rule */
        for (j = 0; j < G; j++) {
            double acc = 0.0;
            for (a = 0; a < M; a++)
                for (b = 0; b < M; b++) {
                    double u = (i + (a + 0.5) / M) / G, v = (j + (b + 0.5) / M) / G, du[3], dv[3], nn[3];
                    for (k = 0; k < 3; k++) { du[k] = B[k] + v * D[k]; dv[k] = C[k] + u * D[k]; }
                    nn[0] = du[1] * dv[2] - du[2] * dv[1];
                    nn[1] = du[2] * dv[0] - du[0] * dv[2];
                    nn[2] = du[0] * dv[1] - du[1] * dv[0];
                    acc += sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
                }
            ex[i * G + j] = acc;
            total += acc;
            obs[i * G + j] = 0.0;
        }
    for (i = 0; i < G * G; i++) ex[i] *= n / total;
    rng_seed(&r, 17, 0);
    for (k = 0; k < n; k++) {
        float uu[2], u, v;
        rng_fill(&r, uu, 2);
        patch_sample(c, uu[0], uu[1], &u, &v);
        i = (int)(u * G); j = (int)(v * G);
        if (i >= G) i = G - 1;
        if (j >= G) j = G - 1;
        obs[i * G + j] += 1.0;
    }
    CHECK_CHI2(t, obs, ex, G * G, 1, NULL, "patch_sample on z = 3 x y");
    CHECK(t, fabs(patch_area(c) - total / ((double)G * G * M * M)) <
                 1e-3 * patch_area(c), "area %.7g against the midpoint rule", patch_area(c));
}

/* pbrt-v4 (commit 5f7a6068) rendered each text below, with "Sampler \"independent\""
   added, 8 times: pbrt --spp 256 --seed S --outfile x_S.pfm x.pbrt, S = 1..8.
   Per quadrant (top left, top right, bottom left, bottom right) and for the image:
   the mean over the 8 images of the luminance 0.212671 R + 0.715160 G + 0.072169 B,
   and its standard error.  (The two triangles, as specnee drew a bilinearmesh
   before, give 0.333 0.217 0.089 0.536 for the trapezoid and 0.219 0.100 0.036
   0.315 for the saddle.)  pbrt-v4 filters its checkerboard over the pixel footprint
   (1.5 x the ray differentials, scaled by 1/8 at these sample counts), which moves
   up to 0.004 of luminance into the dark checks of a 32-pixel quadrant; specnee
   samples it at a point: hence the slack of 0.005 below (the triangle split is off
   by 0.17). */
static const char *const PBRT_PATCH[2] = {
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 27 ]\n%s"
    "Shape \"bilinearmesh\" \"point3 P\" " TRAP " \"point2 uv\" [ 0 0  1 0  0 1  1 1 ]\n",
    "LookAt 0.5 -1 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n%s"
    "Shape \"bilinearmesh\" \"point3 P\" [ -1 -1 0.8  1 -1 -0.8  -1 1 -0.8  1 1 0.8 ]\n",
};
static const double PBRT_PATCH_Y[2][5][2] = {
    { { 0.32909, 0.00006 }, { 0.04548, 0.00003 }, { 0.09337, 0.00004 }, { 0.70626, 0.00013 },
      { 0.29355, 0.00003 } },
    { { 0.41210, 0.00007 }, { 0.03331, 0.00003 }, { 0.04851, 0.00004 }, { 0.40557, 0.00008 },
      { 0.22487, 0.00003 } },
};

static const char *const CHECKER_WORLD =
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" \"x.pfm\"\n"
    "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
    "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
    "Texture \"ch\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 2 ] \"float vscale\" [ 2 ] "
    "\"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
    "Material \"diffuse\" \"texture reflectance\" \"ch\"\n";

/* Renders text (direct light only) and compares its quadrant and image luminance
   means with pbrt-v4's Yp (mean, standard error), with the slack explained above. */
static void checker_vs_pbrt(T *t, const char *text, const double Yp[5][2], const char *name)
{
    Scene s;
    RenderOptions o;
    Tiles tl;
    double all = 0.0;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(16, 4);
    o.maxdepth = 1;                                /* the text's Integrator (direct light only) */
    if (!test_render_tiles(t, &s, &o, 4, 2, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    for (i = 0; i < 4; i++) {
        double Y = test_luminance(tl.mean[i]);
        double se = tl.se[i][1];
        all += Y / 4;
        if (getenv("DBG")) fprintf(stderr, "%s %d %.5f %.5f\n", name, i, Y, Yp[i][0]);
        CHECK(t, fabs(Y - Yp[i][0]) < TEST_K_SIGMA * sqrt(se * se + Yp[i][1] * Yp[i][1]) + 5e-3,
              "%s: quadrant %d: specnee Y %.5f +- %.2g, pbrt-v4 %.5f", name, i, Y, se, Yp[i][0]);
    }
    CHECK(t, fabs(all - Yp[4][0]) < 2e-3 * Yp[4][0] + 1e-3, "%s: image Y %.5f, pbrt-v4 %.5f", name,
          all, Yp[4][0]);
}

static void test_checkerboard_pbrt(T *t)
{
    int c;
    for (c = 0; c < 2; c++) {
        char text[4096];
        snprintf(text, sizeof text, PBRT_PATCH[c], CHECKER_WORLD);
        checker_vs_pbrt(t, text, PBRT_PATCH_Y[c], c ? "saddle" : "trapezoid");
    }
}

/* A lamp of one twisted and one flat patch (one bilinearmesh, facing down) over a
   floor and a wall (pbrt-v4 renders it within 0.3 %, every quadrant within 0.7 %,
   tools/pbrt_compare.sh at 1024 samples): every selection strategy and BSDF sampling alone (which does not use the
   emitter's pdf) render the same tile means as uniform selection. */
/* The room and the lamp's attributes (a patch lamp facing down follows). */
#define LAMP_ROOM \
        "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n" \
        "LookAt 0 -4 1.2  0 0 1  0 0 1\nCamera \"perspective\" \"float fov\" 50\n" \
        "Integrator \"path\" \"integer maxdepth\" 3\nWorldBegin\n" \
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7]\n" \
        "  \"point3 P\" [-2 -2 0 2 -2 0 2 2 0 -2 2 0   -2 2 0 2 2 0 2 2 3 -2 2 3]\n"
#define LAMP_BEGIN \
        "AttributeBegin\nReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [1 0.6 0.3] \"float scale\" 3\n"

static void test_lamp_strategies(T *t)
{
    static const char text[] =
        LAMP_ROOM
        LAMP_BEGIN
        "Shape \"bilinearmesh\" \"integer indices\" [0 1 2 3  4 5 6 7]\n"
        "  \"point3 P\" [-1.2 -0.5 2.9  0.2 -0.5 1.5  -1.2 0.9 1.5  0.2 0.9 2.9"
        "   0.5 -0.3 2.2  1.5 -0.3 2.2  0.6 0.8 2.4  1.4 0.8 2.4]\n"
        "AttributeEnd\n";
    static const SelStrategy st[] = { SEL_POWER, SEL_SPATIAL, SEL_TREE, SEL_SPECTRAL_TREE };
    static Tiles ref, m;
    Scene s;
    RenderOptions o;
    int i;
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_patches == 1 && s.n_tris == 6 && s.n_emitters == 1, "one twisted patch, one flat");
    render_options_default(&o);
    o.sel.grid_res = 8;
    o.spp = test_scaled(24, 4);
    o.seed = 1;
    o.sel.strategy = SEL_UNIFORM;
    if (!test_render_tiles(t, &s, &o, 8, 2, &ref)) goto done;
    for (i = 0; i <= (int)(sizeof st / sizeof st[0]); i++) {
        char what[128];
        RenderOptions oi = o;
        if (i < (int)(sizeof st / sizeof st[0])) {
            oi.sel.strategy = st[i];
            snprintf(what, sizeof what, "patch lamp, %s vs uniform", sel_name(st[i]));
        } else {
            oi.nee = 0;
            oi.spp *= 4;
            snprintf(what, sizeof what, "patch lamp, BSDF sampling only vs uniform NEE");
        }
        if (!test_render_tiles(t, &s, &oi, 8, 2, &m)) goto done;
        if (!test_tiles_agree(t, &m, &ref, 1e-4, what)) goto done;
    }
done:
    scene_free(&s);
}

/* The number of points of z = 2 x y, |x|, |y| <= 1, on the ray o + t w, t > 0. */
static int saddle2_crossings(const double o[3], const double w[3])
{
    double a = 2 * w[0] * w[1], b = 2 * (o[0] * w[1] + o[1] * w[0]) - w[2], c = 2 * o[0] * o[1] - o[2];
    double r[2], disc = b * b - 4 * a * c;
    int i, m = 0, count = 0;
    if (a == 0.0) { if (b != 0.0) r[m++] = -c / b; }
    else if (disc >= 0.0) {
        r[m++] = (-b - sqrt(disc)) / (2 * a);
        r[m++] = (-b + sqrt(disc)) / (2 * a);
    }
    for (i = 0; i < m; i++)
        count += r[i] > 0 && fabs(o[0] + r[i] * w[0]) <= 1 && fabs(o[1] + r[i] * w[1]) <= 1;
    return count;
}

/* E[1 / pdf_sa] of emitter_sample on a twisted lamp (z = 2 x y, whose area
   density |dp/du x dp/dv| grows threefold from the centre to the corners) seen
   from a point close below it is the solid angle it subtends counted with
   multiplicity, integral of |cos| / d^2 dA; here by casting uniform directions
   and counting the crossings of each line by hand.  A sampler that is not uniform
   by area, which the pdf 1 / A assumes, is off. */
static void test_lamp_solid_angle(T *t)
{
    Scene s;
    Rng r;
    const int n = test_scaled(400000, 100000);
    const double o[3] = { 0.6, -0.6, -1.3 };
    const Vec3 ref = v3((float)o[0], (float)o[1], (float)o[2]);
    double sum = 0.0, sum2 = 0.0, cnt = 0.0, cnt2 = 0.0, mean, se, omega, se_o;
    int k;
    if (!test_load_scene(t, &s, "WorldBegin\nAreaLightSource \"diffuse\"\n"
                         "Shape \"bilinearmesh\" \"point3 P\" [ -1 -1 2  1 -1 -2  -1 1 -2  1 1 2 ]\n"))
        return;
    rng_seed(&r, 5, 0);
    for (k = 0; k < n; k++) {
        EmitterSample es;
        Vec3 u = rng_vec3(&r);
        double x = 0.0, w[3], z, rr, ph;
        int m;
        if (emitter_sample(&s, 0, ref, v3(0.0f, 0.0f, 0.0f), (const float[3]){ u.x, u.y, u.z }, &es)) x = 1.0 / es.pdf_sa;
        sum += x;
        sum2 += x * x;
        u = rng_vec3(&r);                          /* a uniform direction */
        z = 1.0 - 2.0 * u.x; rr = sqrt(fmax(0.0, 1.0 - z * z)); ph = 2.0 * SPECNEE_PI * u.y;
        w[0] = rr * cos(ph); w[1] = rr * sin(ph); w[2] = z;
        m = saddle2_crossings(o, w);
        cnt += m;
        cnt2 += (double)m * m;
    }
    scene_free(&s);
    mean = sum / n;
    se = sqrt((sum2 / n - mean * mean) / n);
    omega = 4.0 * SPECNEE_PI * cnt / n;
    se_o = 4.0 * SPECNEE_PI * sqrt((cnt2 / n - (cnt / n) * (cnt / n)) / n);
    if (getenv("DBG")) fprintf(stderr, "E[1/pdf] %.5f +- %.2g, omega %.5f +- %.2g\n", mean, se, omega, se_o);
    CHECK(t, fabs(mean - omega) < TEST_K_SIGMA * sqrt(se * se + se_o * se_o),
          "E[1/pdf] %.5f +- %.2g, solid angle by ray casting %.5f +- %.2g", mean, se, omega, se_o);
}

/* ---- PLY quads: pbrt-v4 makes each a bilinear patch ------------------------ */

/* An ascii PLY of the given vertex rows ("x y z [props]") and face rows; extra: the
   vertex properties after x y z (header lines). */
static const char *ply_file(T *t, const char *name, const char *extra, int nv, const char *verts,
                            int nf, const char *faces)
{
    char text[2048];
    snprintf(text, sizeof text, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\n"
             "property float y\nproperty float z\n%selement face %d\n"
             "property list uchar int vertex_indices\nend_header\n%s%s", nv, extra, nf, verts, faces);
    return test_write_file(t, name, text);
}

/* The trapezoid TRAP's corners in boundary order p00 p10 p11 p01, with "u v" (not an
   affine image of the trapezoid) and "nx ny nz" (tilted at p10). */
#define TRAP_PLY_VERTS "-1.4 -1.2 0  0 0  0 0 1\n1.4 -1.2 0  1 0  0.6 0 0.8\n" \
                       "0.2 1.2 0  1 1.5  0 0 1\n-0.2 1.2 0  0 1  0 0 1\n"
#define UVN_PROPS "property float u\nproperty float v\nproperty float nx\nproperty float ny\n" \
                  "property float nz\n"

static void test_ply_uv(T *t)
{
    /* a face may start at any corner and still go round the trapezoid */
    static const char *const faces[2] = { "4 0 1 2 3\n", "4 2 3 0 1\n" };
    static const double at[4][2] = { { 0.3, -0.5 }, { -0.9, -1.0 }, { 0.1, 1.0 }, { 0.9, -0.4 } };
    /* per corner p00 p10 p01 p11: "u v" and the normal's x, z */
    static const double tex[4][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 1, 1.5 } };
    static const double nrm[4][2] = { { 0, 1 }, { 0.6, 0.8 }, { 0, 1 }, { 0, 1 } };
    int f, i, k;
    for (f = 0; f < 2; f++) {
        char body[1200];
        Scene s;
        snprintf(body, sizeof body, "WorldBegin\nShape \"plymesh\" \"string filename\" \"%s\"\n",
                 ply_file(t, "trap_uv.ply", UVN_PROPS, 4, TRAP_PLY_VERTS, 1, faces[f]));
        if (!test_load_scene(t, &s, body)) return;
        CHECK(t, s.n_tris == 2 && s.n_patches == 0 && s.n_shapes == 1 && s.shapes[0].bilinear &&
                 fabs(s.shapes[0].area - 3.84) < 1e-5, "face %d: a flat patch of area 3.84 "
                 "(%d triangles, %d patches, area %g)", f, s.n_tris, s.n_patches, s.n_shapes ? s.shapes[0].area : 0.0);
        for (i = 0; i < 4; i++) {
            /* the inverse of the trapezoid's map: v from y, then u along the row */
            const double x = at[i][0], y = at[i][1], v = (y + 1.2) / 2.4;
            const double x0 = -1.4 + 1.2 * v, u = (x - x0) / (2.0 * -x0);
            const double w[4] = { (1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v };
            double su = 0, sv = 0, nx = 0, nz = 0, nl;
            SurfacePoint sp;
            float th;
            for (k = 0; k < 4; k++) {
                su += w[k] * tex[k][0]; sv += w[k] * tex[k][1];
                nx += w[k] * nrm[k][0]; nz += w[k] * nrm[k][1];
            }
            nl = sqrt(nx * nx + nz * nz);
            CHECK(t, hit_point(&s, ray_of(x, y, 2.0, 0.0, 0.0, -1.0), &th, &sp), "face %d: miss at (%g, %g)",
                  f, x, y);
            CHECK(t, fabs(sp.u - su) < 1e-5 && fabs(sp.v - sv) < 1e-5, "face %d at (%g, %g): uv (%.7g, %.7g), "
                  "bilinear (%.7g, %.7g)", f, x, y, sp.u, sp.v, su, sv);
            CHECK(t, fabs(sp.ns.x - nx / nl) < 1e-5 && fabs(sp.ns.z - nz / nl) < 1e-5,
                  "face %d at (%g, %g): N (%g %g %g), bilinear (%g 0 %g)", f, x, y, sp.ns.x, sp.ns.y,
                  sp.ns.z, nx / nl, nz / nl);
        }
        scene_free(&s);
    }
}

/* z = x y: corners (-1,-1,1) (1,-1,-1) (1,1,1) (-1,1,-1) round the boundary; the
   face "4 1 2 3 0" makes p00 = (1,-1,-1), p10 = (1,1,1), p01 = (-1,-1,1): the
   patch's u = (y + 1) / 2, v = (1 - x) / 2, which are the texture (s, t). */
static void test_ply_twisted(T *t)
{
    static const double at[4][2] = { { 0.5, 0.5 }, { -0.7, 0.2 }, { 0.9, -0.95 }, { -0.3, -0.6 } };
    char body[1200];
    Scene s;
    int i;
    snprintf(body, sizeof body, "WorldBegin\nShape \"plymesh\" \"string filename\" \"%s\"\n",
             ply_file(t, "saddle.ply", "", 4, "-1 -1 1\n1 -1 -1\n1 1 1\n-1 1 -1\n", 1, "4 1 2 3 0\n"));
    if (!test_load_scene(t, &s, body)) return;
    CHECK(t, s.n_tris == 0 && s.n_patches == 1 && s.shapes[0].bilinear, "a twisted patch "
          "(%d triangles, %d patches)", s.n_tris, s.n_patches);
    for (i = 0; i < 4; i++) {
        const double x = at[i][0], y = at[i][1];
        SurfacePoint sp;
        float th;
        CHECK(t, hit_point(&s, ray_of(x, y, 5.0, 0.0, 0.0, -1.0), &th, &sp), "miss at (%g, %g)", x, y);
        CHECK(t, fabs(th - (5.0 - x * y)) < 1e-5, "at (%g, %g): t %.7g, the saddle's %.7g", x, y, th,
              5.0 - x * y);
        CHECK(t, fabs(sp.u - (y + 1) / 2) < 1e-5 && fabs(sp.v - (1 - x) / 2) < 1e-5,
              "at (%g, %g): (u, v) (%.7g, %.7g), pbrt-v4's order gives (%.7g, %.7g)", x, y, sp.u, sp.v,
              (y + 1) / 2, (1 - x) / 2);
    }
    scene_free(&s);
}

/* One triangle (x in [2, 4]) and the trapezoid quad in one PLY file. */
static void test_ply_mixed(T *t)
{
    const char *ply = ply_file(t, "mixed.ply", "property float u\nproperty float v\n", 7,
                               "-1.4 -1.2 0 0 0\n1.4 -1.2 0 1 0\n0.2 1.2 0 1 1\n-0.2 1.2 0 0 1\n"
                               "2 0 0 0.5 0.5\n4 0 0 0.7 0.5\n2 2 0 0.5 0.9\n", 2, "3 4 5 6\n4 0 1 2 3\n");
    char body[1600];
    Scene s;
    SurfacePoint sp;
    float th = 0.0f;
    int inst;
    for (inst = 0; inst < 2; inst++) {
        if (inst)
            snprintf(body, sizeof body, "WorldBegin\nObjectBegin \"m\"\nShape \"plymesh\" \"string "
                     "filename\" \"%s\"\nObjectEnd\nTranslate 0 0 -1\nObjectInstance \"m\"\n", ply);
        else
            snprintf(body, sizeof body, "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
                     "Shape \"plymesh\" \"string filename\" \"%s\"\n", ply);
        if (!test_load_scene(t, &s, body)) return;
        CHECK(t, s.n_shapes == 2 && !s.shapes[0].bilinear && s.shapes[0].tri_count == 1 &&
                 s.shapes[1].bilinear && s.shapes[1].tri_count == 2 && fabs(s.shapes[0].area - 2.0) < 1e-6 &&
                 fabs(s.shapes[1].area - 3.84) < 1e-5, "%s: a triangle mesh and a patch mesh",
              inst ? "instanced" : "emitting");
        if (!inst)
            CHECK(t, s.n_emitters == 2 && s.shapes[0].emitter >= 0 && s.shapes[1].emitter >= 0,
                  "both meshes emit (%d emitters)", s.n_emitters);
        else
            CHECK(t, s.n_instances == 1 && s.shapes[0].in_object && s.shapes[1].in_object,
                  "both meshes in the object");
        /* the triangle's uv by barycentrics: (3, 0.5) = b1 (2,0) + b2 (0,2) at b1 = 0.5 */
        CHECK(t, hit_point(&s, ray_of(3.0, 0.5, 2.0, 0.0, 0.0, -1.0), &th, &sp) &&
                 fabs(sp.u - 0.6) < 1e-5 && fabs(sp.v - 0.6) < 1e-5 && fabs(th - 2.0 - inst) < 1e-5,
              "%s: triangle uv (%g, %g) at t %g", inst ? "instanced" : "emitting", sp.u, sp.v, th);
        /* the quad's: the patch's (u, v) at (0.3, -0.5): v = 0.7 / 2.4, u = (0.3 - x0) / (-2 x0) */
        {
            const double v = 0.7 / 2.4, x0 = -1.4 + 1.2 * v, u = (0.3 - x0) / (-2.0 * x0);
            CHECK(t, hit_point(&s, ray_of(0.3, -0.5, 2.0, 0.0, 0.0, -1.0), &th, &sp) &&
                     fabs(sp.u - u) < 1e-5 && fabs(sp.v - v) < 1e-5,
                  "%s: quad uv (%.7g, %.7g), bilinear (%.7g, %.7g)", inst ? "instanced" : "emitting",
                  sp.u, sp.v, u, v);
        }
        scene_free(&s);
    }
}

/* pbrt-v4 (commit 5f7a6068) rendered the checkerboard scenes above with the shape
   replaced by Shape "plymesh" "string filename" naming an ascii PLY of the vertex and
   face rows below (the trapezoid with "u v" (0,0) (1,0) (1,1) (0,1) round it, its
   face starting at p11; the saddle of PBRT_PATCH[1] without "u v", its face starting
   at p10, which turns the patch's (u, v) and so its checks by 90 degrees), as above:
   8 seeds, 256 spp, "Sampler \"independent\"", luminance means and standard errors
   per quadrant and image.  The trapezoid's equal the bilinearmesh's to the last
   digit.  (Two triangles a quad, as specnee read PLY quads before, give 0.334 0.217
   0.089 0.536 for the trapezoid and 0.048 0.118 0.264 0.201 for the saddle.) */
static const char *const PLY_ROWS[2][2] = {
    { "-1.4 -1.2 0 0 0\n1.4 -1.2 0 1 0\n0.2 1.2 0 1 1\n-0.2 1.2 0 0 1\n", "4 2 3 0 1\n" },
    { "-1 -1 0.8\n1 -1 -0.8\n1 1 0.8\n-1 1 -0.8\n", "4 1 2 3 0\n" },
};
static const double PBRT_PLY_Y[2][5][2] = {
    { { 0.32909, 0.00006 }, { 0.04548, 0.00003 }, { 0.09337, 0.00004 }, { 0.70626, 0.00013 },
      { 0.29355, 0.00003 } },
    { { 0.05828, 0.00006 }, { 0.24743, 0.00012 }, { 0.36448, 0.00006 }, { 0.05721, 0.00005 },
      { 0.18185, 0.00003 } },
};

static void test_ply_pbrt(T *t)
{
    static const char *const camera[2] = {
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 27 ]\n",
        "LookAt 0.5 -1 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n",
    };
    int c;
    for (c = 0; c < 2; c++) {
        char text[4096];
        const char *ply = ply_file(t, c ? "pbrt_saddle.ply" : "pbrt_trap.ply",
                                   c ? "" : "property float u\nproperty float v\n", 4, PLY_ROWS[c][0],
                                   1, PLY_ROWS[c][1]);
        snprintf(text, sizeof text, "%s%sShape \"plymesh\" \"string filename\" \"%s\"\n", camera[c],
                 CHECKER_WORLD, ply);
        checker_vs_pbrt(t, text, PBRT_PLY_Y[c], c ? "PLY saddle" : "PLY trapezoid");
    }
}

/* The lamp of patch_lamp_strategies as a PLY file (each face round its patch's
   boundary, p00 p10 p11 p01): the same scene, so the same image to the last bit. */
static void test_ply_lamp(T *t)
{
    static const char bilin[] =
        LAMP_ROOM LAMP_BEGIN
        "Shape \"bilinearmesh\" \"integer indices\" [0 1 2 3  4 5 6 7]\n"
        "  \"point3 P\" [-1.2 -0.5 2.9  0.2 -0.5 1.5  -1.2 0.9 1.5  0.2 0.9 2.9"
        "   0.5 -0.3 2.2  1.5 -0.3 2.2  0.6 0.8 2.4  1.4 0.8 2.4]\n"
        "AttributeEnd\n";
    static Tiles a, b;
    char text[2048];
    Scene s;
    RenderOptions o;
    int ok, c, i;
    snprintf(text, sizeof text, "%s%sShape \"plymesh\" \"string filename\" \"%s\"\nAttributeEnd\n",
             LAMP_ROOM, LAMP_BEGIN,
             ply_file(t, "lamp.ply", "", 8, "-1.2 -0.5 2.9\n0.2 -0.5 1.5\n-1.2 0.9 1.5\n0.2 0.9 2.9\n"
                      "0.5 -0.3 2.2\n1.5 -0.3 2.2\n0.6 0.8 2.4\n1.4 0.8 2.4\n", 2, "4 0 1 3 2\n4 4 5 7 6\n"));
    render_options_default(&o);
    o.spp = test_scaled(8, 4);
    o.seed = 1;
    o.sel.strategy = SEL_POWER;
    if (!test_load_scene(t, &s, bilin)) return;
    ok = test_render_tiles(t, &s, &o, 2, 2, &a);
    scene_free(&s);
    if (!ok || !test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_patches == 1 && s.n_tris == 6 && s.n_emitters == 1 && s.shapes[1].bilinear,
          "PLY lamp: one twisted patch, one flat (%d patches, %d triangles)", s.n_patches, s.n_tris);
    ok = test_render_tiles(t, &s, &o, 2, 2, &b);
    scene_free(&s);
    if (!ok) return;
    for (i = 0; i < 4; i++)
        for (c = 0; c < 3; c++)
            CHECK(t, a.mean[i][c] == b.mean[i][c], "tile %d channel %d: PLY %.9g, bilinearmesh %.9g", i, c,
                  b.mean[i][c], a.mean[i][c]);
}

const TestCase tests_patch[] = {
    { "patch_planar_hits", test_planar_hits },
    { "patch_twisted_hits", test_twisted_hits },
    { "patch_area", test_area },
    { "patch_sample_chi2", test_sample_chi2 },
    { "patch_checkerboard_pbrt", test_checkerboard_pbrt },
    { "patch_lamp_strategies", test_lamp_strategies },
    { "patch_lamp_solid_angle", test_lamp_solid_angle },
    { "patch_ply_uv", test_ply_uv },
    { "patch_ply_twisted", test_ply_twisted },
    { "patch_ply_mixed", test_ply_mixed },
    { "patch_ply_pbrt", test_ply_pbrt },
    { "patch_ply_lamp", test_ply_lamp },
    { NULL, NULL }
};
