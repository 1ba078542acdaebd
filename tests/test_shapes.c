/* tests/test_shapes.c - the quadrics of shapes.c (disk, cylinder, partial sphere)
   against closed forms computed here, not by shapes.c.

     shapes_disk_hits            rays at known points of a transformed annulus
                                 sector: hit point, t and pbrt-v4's (u, v), misses inside innerradius,
                                 outside radius and beyond phimax; normal +z under
                                 the CTM (a non-uniform scale tilts it as M^-T
                                 does), negated by ReverseOrientation and by a
                                 mirroring CTM, and both together cancel
     shapes_cylinder_hits        from outside: the near wall at the analytic t, outward
                                 normal; from inside: the wall ahead, normal still
                                 outward; misses past zmin/zmax; through the phimax
                                 gap: the far wall from its inside
     shapes_sphere_part_hits     a sphere cut by zmax and phimax: through the hole
                                 the inside of the far wall; below zmax the near
                                 wall; a whole sphere under a non-uniform scale is
                                 the ellipsoid; the defaults written out keep the
                                 world-space sphere (SHAPE_SPHERE)
     shapes_area                 Shape.area against the closed forms: annulus
                                 sector, ellipse (disk under Scale), cylinder
                                 patch, sphere zone, prolate spheroid (sphere under
                                 a non-uniform Scale: the quadrature)
     shapes_solid_angle          E[1 / pdf_sa] of emitter_sample (the solid angle
                                 the shape subtends) against 2 pi (1 - h / sqrt(h^2
                                 + R^2)) for a disk on its axis, and against the
                                 fraction of uniform directions that hit the shape
                                 (ray casting, independent of the sampling) for an
                                 annulus sector under a non-uniform scale and
                                 rotation, a cylinder, a sphere zone, an ellipsoid
                                 and an elliptic cylinder seen from inside (the
                                 last two sampled non-uniformly by world area); emitter_pdf_sa equals the sample's pdf; the
                                 sampled point lies on the shape with the normal a
                                 hit there gets
     shapes_disk_can_reach       a one-sided disk lights only its front half-space,
                                 a two-sided one both (not its own plane)
     shapes_disk_tree_cone       the light trees give a disk facing a point a positive
                                 probability and one facing away none (its cone is
                                 its one normal)
     shapes_disk_irradiance      a Lambertian disk of radiance L above a diffuse
                                 plane (albedo 1/2): the rendered radiance at the
                                 centre below it is (1/2) L R^2 / (h^2 + R^2)
                                 (E = pi L R^2 / (h^2 + R^2)), within 5 standard
                                 errors
     shapes_strategies_agree     disk, cylinder and sphere-zone lamps in a box: every
                                 selection strategy, and BSDF sampling alone (no
                                 NEE), render the same tile means as uniform
     shapes_reject_*             bad parameters: one-line file:line errors
   Each was watched failing on a one-line mutant of the code it guards
   (tests/mutants.txt, section shapes.c). */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ helpers */

/* Load text; returns 0 (and fails the test) on an error. */
static int load(T *t, Scene *s, const char *text)
{
    return test_load_scene(t, s, text);
}

/* Trace r through the scene: 1 and the surface point on a hit. */
static int trace(const Scene *s, Vec3 o, Vec3 d, float *t, SurfacePoint *sp)
{
    Ray r;
    HitRecord h;
    r.o = o; r.d = d; r.tmax = INFINITY;
    if (!bvh_intersect(&s->bvh, s, &r, &h)) return 0;
    *t = h.t;
    scene_surface_point(s, &r, &h, sp);
    return 1;
}

static int near3(Vec3 a, Vec3 b, float eps)
{
    return fabsf(a.x - b.x) <= eps && fabsf(a.y - b.y) <= eps && fabsf(a.z - b.z) <= eps;
}

#define V3F "(%.6g, %.6g, %.6g)"
#define V3A(v) (double)(v).x, (double)(v).y, (double)(v).z

/* ------------------------------------------------------------------ intersection */

static void test_disk_hits(T *t)
{
    Scene s;
    SurfacePoint sp;
    float th;
    /* an annulus sector 0.5 <= r <= 2, phi <= 90 degrees, at height 1, moved up by 3:
       the plane z = 4 in the world */
    if (!load(t, &s, "WorldBegin\nTranslate 0 0 3\nShape \"disk\" \"float height\" 1 "
                     "\"float radius\" 2 \"float innerradius\" 0.5 \"float phimax\" 90\n")) return;
    CHECK(t, s.n_quadrics == 1 && s.shapes[0].type == SHAPE_DISK, "one disk");
    CHECK(t, trace(&s, v3(1, 1, 10), v3(0, 0, -2), &th, &sp), "a ray down at (1, 1) misses the disk");
    CHECK(t, fabsf(th - 3.0f) < 1e-6f && near3(sp.p, v3(1, 1, 4), 1e-6f), "hit at t %g p " V3F
          ", expected t 3 at (1, 1, 4)", (double)th, V3A(sp.p));
    CHECK(t, near3(sp.ng, v3(0, 0, 1), 1e-6f) && near3(sp.ns, sp.ng, 0.0f), "normal " V3F
          " is not +z", V3A(sp.ng));
    /* pbrt-v4's (u, v): phi / phimax = 45 / 90, (radius - r) / (radius - innerradius) */
    CHECK(t, fabsf(sp.u - 0.5f) < 1e-6f && fabsf(sp.v - (2.0f - sqrtf(2.0f)) / 1.5f) < 1e-6f,
          "disk (u, v) = (%g, %g), expected (0.5, %g)", (double)sp.u, (double)sp.v,
          (2.0 - sqrt(2.0)) / 1.5);
    CHECK(t, trace(&s, v3(1.9f, 0.1f, 0), v3(0, 0, 1), &th, &sp) && fabsf(th - 4.0f) < 1e-6f,
          "a ray up at (1.9, 0.1) misses: both sides of a disk are hit");
    CHECK(t, !trace(&s, v3(0.3f, 0.3f, 10), v3(0, 0, -1), &th, &sp), "hit inside innerradius");
    CHECK(t, !trace(&s, v3(1.5f, 1.5f, 10), v3(0, 0, -1), &th, &sp), "hit outside radius");
    CHECK(t, !trace(&s, v3(-1, 1, 10), v3(0, 0, -1), &th, &sp), "hit beyond phimax (phi 135)");
    CHECK(t, !trace(&s, v3(1, -0.2f, 10), v3(0, 0, -1), &th, &sp), "hit beyond phimax (phi 349)");
    CHECK(t, !trace(&s, v3(1, 1, 5), v3(1, 0, 0), &th, &sp), "a ray parallel to the disk hit it");
    scene_free(&s);

    /* ReverseOrientation flips the normal; so does a mirroring CTM; both cancel */
    if (!load(t, &s, "WorldBegin\nReverseOrientation\nShape \"disk\"\n")) return;
    CHECK(t, trace(&s, v3(0.2f, 0.1f, 1), v3(0, 0, -1), &th, &sp) && near3(sp.ng, v3(0, 0, -1), 1e-6f),
          "ReverseOrientation: normal " V3F ", expected -z", V3A(sp.ng));
    scene_free(&s);
    if (!load(t, &s, "WorldBegin\nScale 1 1 -1\nShape \"disk\"\n")) return;
    CHECK(t, trace(&s, v3(0.2f, 0.1f, 1), v3(0, 0, -1), &th, &sp) && near3(sp.ng, v3(0, 0, 1), 1e-6f),
          "Scale 1 1 -1: normal " V3F ", expected +z (-z mapped by M^-T, then flipped)", V3A(sp.ng));
    scene_free(&s);
    if (!load(t, &s, "WorldBegin\nScale -1 1 1\nShape \"disk\"\n")) return;
    CHECK(t, trace(&s, v3(0.2f, 0.1f, 1), v3(0, 0, -1), &th, &sp) && near3(sp.ng, v3(0, 0, -1), 1e-6f),
          "Scale -1 1 1: normal " V3F ", expected -z (flip)", V3A(sp.ng));
    scene_free(&s);
    if (!load(t, &s, "WorldBegin\nScale -1 1 1\nReverseOrientation\nShape \"disk\"\n")) return;
    CHECK(t, trace(&s, v3(0.2f, 0.1f, 1), v3(0, 0, -1), &th, &sp) && near3(sp.ng, v3(0, 0, 1), 1e-6f),
          "mirror and ReverseOrientation: normal " V3F ", expected +z", V3A(sp.ng));
    scene_free(&s);

    /* a shear: the object's plane z = 0 becomes z = x / 2 (ConcatTransform is
       column-major: M[2][0] = m[2] = 0.5); normal by M^-T: (-0.5, 0, 1) / |.| */
    if (!load(t, &s, "WorldBegin\nConcatTransform [1 0 0.5 0  0 1 0 0  0 0 1 0  0 0 0 1]\n"
                     "Shape \"disk\" \"float radius\" 3\n")) return;
    CHECK(t, trace(&s, v3(2, 0, 5), v3(0, 0, -1), &th, &sp), "sheared disk missed");
    CHECK(t, fabsf(th - 4.0f) < 1e-5f && near3(sp.p, v3(2, 0, 1), 1e-5f), "sheared disk: t %g p " V3F
          ", expected t 4 at (2, 0, 1)", (double)th, V3A(sp.p));
    CHECK(t, near3(sp.ng, v3_norm(v3(-0.5f, 0, 1)), 1e-6f), "sheared disk: normal " V3F
          ", expected (-0.5, 0, 1) normalised", V3A(sp.ng));
    scene_free(&s);
}

static void test_cylinder_hits(T *t)
{
    Scene s;
    SurfacePoint sp;
    float th;
    /* radius 2, z in [-1, 3], phi <= 270 degrees (the gap: the quadrant x > 0, y < 0) */
    if (!load(t, &s, "WorldBegin\nShape \"cylinder\" \"float radius\" 2 \"float zmin\" -1 "
                     "\"float zmax\" 3 \"float phimax\" 270\n")) return;
    CHECK(t, s.n_quadrics == 1 && s.shapes[0].type == SHAPE_CYLINDER, "one cylinder");
    /* from outside along -y at x = 1: enters at y = sqrt(3) */
    CHECK(t, trace(&s, v3(1, 10, 0.5f), v3(0, -1, 0), &th, &sp), "missed from outside");
    CHECK(t, fabsf(th - (10.0f - sqrtf(3.0f))) < 1e-5f, "t %g, expected %g", (double)th,
          10.0 - sqrt(3.0));
    CHECK(t, near3(sp.p, v3(1, sqrtf(3.0f), 0.5f), 1e-5f) &&
          near3(sp.ng, v3(0.5f, sqrtf(3.0f) / 2, 0), 1e-6f), "outside hit p " V3F " n " V3F,
          V3A(sp.p), V3A(sp.ng));
    /* (u, v) = (60 / 270, (z - zmin) / (zmax - zmin)) */
    CHECK(t, fabsf(sp.u - 60.0f / 270.0f) < 1e-6f && fabsf(sp.v - 0.375f) < 1e-6f,
          "cylinder (u, v) = (%g, %g), expected (%g, 0.375)", (double)sp.u, (double)sp.v, 60.0 / 270.0);
    /* from inside (the axis) towards -x: the wall at x = -2, normal still outward (-x) */
    CHECK(t, trace(&s, v3(0, 0, 0), v3(-1, 0, 0), &th, &sp), "missed from inside");
    CHECK(t, fabsf(th - 2.0f) < 1e-6f && near3(sp.ng, v3(-1, 0, 0), 1e-6f),
          "inside hit t %g n " V3F ", expected t 2, n -x", (double)th, V3A(sp.ng));
    /* above zmax and below zmin: miss */
    CHECK(t, !trace(&s, v3(0, 10, 3.5f), v3(0, -1, 0), &th, &sp), "hit above zmax");
    CHECK(t, !trace(&s, v3(0, 10, -1.5f), v3(0, -1, 0), &th, &sp), "hit below zmin");
    /* down the axis: no hit (open, no caps) */
    CHECK(t, !trace(&s, v3(0.5f, 0.5f, 10), v3(0, 0, -1), &th, &sp), "a cylinder has no caps");
    /* into the gap from outside (x = 1, from -y): the near root (phi ~ 300) is cut away,
       the far wall at y = +sqrt(3) is hit from inside */
    CHECK(t, trace(&s, v3(1, -10, 0), v3(0, 1, 0), &th, &sp), "missed through the gap");
    CHECK(t, fabsf(th - (10.0f + sqrtf(3.0f))) < 1e-5f && near3(sp.ng, v3(0.5f, sqrtf(3.0f) / 2, 0), 1e-6f),
          "through the gap: t %g n " V3F ", expected the far wall at t %g", (double)th,
          V3A(sp.ng), 10.0 + sqrt(3.0));
    scene_free(&s);
    if (!load(t, &s, "WorldBegin\nReverseOrientation\nShape \"cylinder\"\n")) return;
    CHECK(t, trace(&s, v3(0, 0, 0), v3(1, 0, 0), &th, &sp) && near3(sp.ng, v3(-1, 0, 0), 1e-6f),
          "ReverseOrientation: normal " V3F ", expected inward -x", V3A(sp.ng));
    /* the defaults zmin -1, zmax 1 equal -radius, radius: still cut there (unlike a
       sphere, whose z range is the whole sphere then) */
    /* rays from inside leaving through the open ends (they meet the infinite
       cylinder at z = -1.5 and 1.5, inside the BVH box's x, y range) */
    CHECK(t, !trace(&s, v3(0, 0, 0.5f), v3(1, 0, -2), &th, &sp), "default cylinder hit below zmin");
    CHECK(t, !trace(&s, v3(0, 0, -0.5f), v3(1, 0, 2), &th, &sp), "default cylinder hit above zmax");
    scene_free(&s);
}

static void test_sphere_part_hits(T *t)
{
    Scene s;
    SurfacePoint sp;
    float th;
    /* radius 1 cut at z = 0.5 (the cap above is gone) and phi <= 180 (the half y < 0 gone) */
    if (!load(t, &s, "WorldBegin\nTranslate 0 0 1\nShape \"sphere\" \"float zmax\" 0.5 "
                     "\"float phimax\" 180\n")) return;
    CHECK(t, s.n_quadrics == 1 && s.n_spheres == 0 && s.shapes[0].type == SHAPE_SPHERE_PART,
          "one partial sphere");
    /* down the axis: through the hole, the bottom from inside, normal outward (-z) */
    CHECK(t, trace(&s, v3(0, 0.3f, 5), v3(0, 0, -1), &th, &sp), "missed down the hole");
    CHECK(t, fabsf(sp.p.z - (1.0f - sqrtf(1.0f - 0.09f))) < 1e-5f && sp.ng.z < -0.9f,
          "through the hole: p " V3F " n " V3F ", expected the bottom", V3A(sp.p), V3A(sp.ng));
    /* horizontal at z = 1 (object z = 0) from +y: the near wall at y = 1 */
    CHECK(t, trace(&s, v3(0, 5, 1), v3(0, -1, 0), &th, &sp) && fabsf(th - 4.0f) < 1e-5f &&
          near3(sp.ng, v3(0, 1, 0), 1e-5f), "near wall: t %g n " V3F, (double)th, V3A(sp.ng));
    /* (u, v) = (90 / 180, (theta - theta_zmin) / (theta_zmax - theta_zmin)) with theta 90,
       theta_zmin 180, theta_zmax 60 degrees */
    CHECK(t, fabsf(sp.u - 0.5f) < 1e-6f && fabsf(sp.v - 0.75f) < 1e-5f,
          "sphere (u, v) = (%g, %g), expected (0.5, 0.75)", (double)sp.u, (double)sp.v);
    /* from -y: the half y < 0 is gone, so the far wall from inside at y = 1 */
    CHECK(t, trace(&s, v3(0, -5, 1), v3(0, 1, 0), &th, &sp) && fabsf(th - 6.0f) < 1e-5f &&
          near3(sp.ng, v3(0, 1, 0), 1e-5f), "through the phi cut: t %g n " V3F ", expected t 6",
          (double)th, V3A(sp.ng));
    /* at object z = 0.7 > zmax: a ray along -y misses */
    CHECK(t, !trace(&s, v3(0, 5, 1.7f), v3(0, -1, 0), &th, &sp), "hit above zmax");
    scene_free(&s);
    /* the defaults written out (or a z range beyond the sphere, clamped): still the
       whole sphere of bvh.c's world-space test, so existing images do not move */
    if (!load(t, &s, "WorldBegin\nScale 2 2 2\nShape \"sphere\" \"float zmin\" -3 \"float zmax\" 1 "
                     "\"float phimax\" 360\n")) return;
    CHECK(t, s.n_spheres == 1 && s.n_quadrics == 0 && s.shapes[0].type == SHAPE_SPHERE,
          "a whole sphere became a quadric");
    scene_free(&s);
    /* a whole sphere under Scale 1 1 2: the ellipsoid; its top at z = 2, normal there +z;
       at (x, 0, z) the normal is proportional to (x, 0, z / 4) */
    if (!load(t, &s, "WorldBegin\nScale 1 1 2\nShape \"sphere\"\n")) return;
    CHECK(t, s.n_quadrics == 1 && s.shapes[0].type == SHAPE_SPHERE_PART, "ellipsoid is a quadric");
    CHECK(t, trace(&s, v3(0, 0, 5), v3(0, 0, -1), &th, &sp) && fabsf(th - 3.0f) < 1e-5f,
          "ellipsoid top: t %g, expected 3", (double)th);
    CHECK(t, trace(&s, v3(0.6f, 0, 5), v3(0, 0, -1), &th, &sp) && fabsf(sp.p.z - 1.6f) < 1e-5f &&
          near3(sp.ng, v3_norm(v3(0.6f, 0, 0.4f)), 1e-5f),
          "ellipsoid at x 0.6: p " V3F " n " V3F ", expected z 1.6, n ~ (0.6, 0, 0.4)",
          V3A(sp.p), V3A(sp.ng));
    scene_free(&s);
}

/* ------------------------------------------------------------------ area */

static void test_area(T *t)
{
    static const struct { const char *text; double area; const char *what; } c[] = {
        { "Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1 \"float phimax\" 90",
          0.25 * SPECNEE_PI * 3.0, "annulus sector" },
        { "Scale 3 0.5 7\nShape \"disk\" \"float radius\" 2", SPECNEE_PI * 6.0 * 1.0,
          "ellipse (disk under Scale 3 0.5 7)" },
        { "Rotate 30 1 1 0\nScale 2 2 2\nShape \"cylinder\" \"float radius\" 0.5 \"float zmin\" -1 "
          "\"float zmax\" 2 \"float phimax\" 120", (2.0 * SPECNEE_PI / 3.0) * 1.0 * 6.0,
          "cylinder patch (scaled by 2)" },
        { "Shape \"sphere\" \"float radius\" 2 \"float zmin\" -0.5 \"float zmax\" 1.5",
          2.0 * SPECNEE_PI * 2.0 * 2.0, "sphere zone" },
        { "Shape \"sphere\" \"float radius\" 2 \"float zmin\" -5 \"float zmax\" 0 \"float phimax\" 180",
          SPECNEE_PI * 2.0 * 2.0, "quarter sphere (zmin clamped)" },
        { NULL, 0.0, "prolate spheroid (Scale 1 1 2)" },
    };
    int i;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        char text[512];
        Scene s;
        double want = c[i].area, got;
        if (c[i].text) snprintf(text, sizeof text, "WorldBegin\n%s\n", c[i].text);
        else {
            /* a = b = 1, c = 2: S = 2 pi a^2 (1 + c / (a e) asin e), e^2 = 1 - a^2 / c^2 */
            double e = sqrt(1.0 - 0.25);
            snprintf(text, sizeof text, "WorldBegin\nScale 1 1 2\nShape \"sphere\"\n");
            want = 2.0 * SPECNEE_PI * (1.0 + 2.0 / e * asin(e));
        }
        if (!load(t, &s, text)) return;
        got = s.shapes[0].area;
        scene_free(&s);
        CHECK(t, fabs(got - want) <= 1e-4 * want, "%s: area %.7g, expected %.7g", c[i].what, got, want);
    }
}

/* ------------------------------------------------------------------ sampling */

/* E[1 / pdf_sa] over emitter_sample's points of emitter 0 seen from ref, and
   checks on each sample; the mean and its standard error. */
static int solid_angle_by_sampling(T *t, const Scene *s, Vec3 ref, int n, double *mean, double *se)
{
    Rng r;
    double sum = 0.0, sum2 = 0.0;
    int i;
    rng_seed(&r, 11, 0);
    for (i = 0; i < n; i++) {
        EmitterSample es;
        Vec3 u = rng_vec3(&r);
        double w = 0.0;
        if (emitter_sample(s, 0, ref, v3(0.0f, 0.0f, 0.0f), (const float[3]){ u.x, u.y, u.z }, &es)) {
            float pdf = emitter_pdf_sa(s, 0, ref, v3(0.0f, 0.0f, 0.0f), es.p, es.n, es.prim), th;
            SurfacePoint sp;
            if (!(fabsf(pdf - es.pdf_sa) <= 1e-5f * es.pdf_sa)) {
                test_failf(t, __FILE__, __LINE__, "emitter_pdf_sa %g differs from the sample's %g",
                           (double)pdf, (double)es.pdf_sa);
                return 0;
            }
            /* the point lies on the shape, and its normal is the one a hit there gets */
            if (!trace(s, ref, es.wi, &th, &sp) || fabsf(th - es.dist) > 1e-4f * (1.0f + es.dist) ||
                !near3(sp.ng, es.n, 1e-4f)) {
                test_failf(t, __FILE__, __LINE__, "sample " V3F " n " V3F ": the ray from the "
                           "reference point finds p " V3F " n " V3F, V3A(es.p), V3A(es.n),
                           V3A(sp.p), V3A(sp.ng));
                return 0;
            }
            w = 1.0 / es.pdf_sa;
        }
        sum += w;
        sum2 += w * w;
    }
    *mean = sum / n;
    *se = sqrt((sum2 / n - *mean * *mean) / n);
    return 1;
}

/* 4 pi times the fraction of uniform directions from ref that hit the scene. */
static void solid_angle_by_rays(const Scene *s, Vec3 ref, int n, double *mean, double *se)
{
    Rng r;
    int i, hits = 0;
    double p;
    rng_seed(&r, 12, 0);
    for (i = 0; i < n; i++) {
        float u[2], z, rr, phi, th;
        SurfacePoint sp;
        rng_fill(&r, u, 2);
        z = 1.0f - 2.0f * u[0];
        rr = sqrtf(fmaxf(0.0f, 1.0f - z * z));
        phi = 2.0f * PI_F * u[1];
        hits += trace(s, ref, v3(rr * cosf(phi), rr * sinf(phi), z), &th, &sp);
    }
    p = (double)hits / n;
    *mean = 4.0 * SPECNEE_PI * p;
    *se = 4.0 * SPECNEE_PI * sqrt(p * (1.0 - p) / n);
}

static void test_solid_angle(T *t)
{
    static const struct { const char *shape; float ref[3]; const char *what; } c[] = {
        { "Translate 0.3 -0.2 0.5\nRotate 40 1 2 0\nScale 1.5 0.6 1\n"
          "Shape \"disk\" \"float radius\" 1.2 \"float innerradius\" 0.4 \"float phimax\" 250",
          { 0.5f, 0.2f, 2.0f }, "annulus sector under rotation and non-uniform scale" },
        { "Rotate 20 0 1 0\nShape \"cylinder\" \"float radius\" 1 \"float zmin\" -0.5 "
          "\"float zmax\" 1.5 \"float phimax\" 300", { 0.2f, 0.3f, 0.1f }, "cylinder from inside" },
        { "Scale 2 2 2\nShape \"sphere\" \"float zmin\" -0.6 \"float zmax\" 0.8 \"float phimax\" 200",
          { 0.3f, 0.5f, -0.2f }, "sphere zone from inside" },
        { "Rotate 30 1 1 0\nScale 1.8 0.5 1\nShape \"sphere\"",
          { 0.2f, 0.1f, 0.3f }, "ellipsoid (a sphere under a non-uniform scale) from inside" },
        { "Rotate 15 1 0 0\nScale 1 2.5 0.8\nShape \"cylinder\" \"float radius\" 1 \"float zmin\" -0.5 "
          "\"float zmax\" 1.5 \"float phimax\" 300", { 0.2f, 0.3f, 0.1f }, "elliptic cylinder from inside" },
    };
    const int n = test_scaled(200000, 20000);
    Scene s;
    double m, se, m2, se2, h = 1.5, R = 2.0, want;
    int i;
    /* a disk of radius 2 at z = 1.5, facing down, seen from the origin */
    if (!load(t, &s, "WorldBegin\nTranslate 0 0 1.5\nReverseOrientation\nAreaLightSource \"diffuse\"\n"
                     "Shape \"disk\" \"float radius\" 2\n")) return;
    if (!solid_angle_by_sampling(t, &s, v3(0, 0, 0), n, &m, &se)) { scene_free(&s); return; }
    scene_free(&s);
    want = 2.0 * SPECNEE_PI * (1.0 - h / sqrt(h * h + R * R));
    CHECK(t, fabs(m - want) < 5.0 * se + 1e-6, "disk on its axis: E[1/pdf] %.5f +- %.5f, solid "
          "angle %.5f", m, se, want);
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        char text[512];
        Vec3 ref = v3(c[i].ref[0], c[i].ref[1], c[i].ref[2]);
        snprintf(text, sizeof text, "WorldBegin\nAreaLightSource \"diffuse\" \"bool twosided\" true\n%s\n",
                 c[i].shape);
        if (!load(t, &s, text)) return;
        if (!solid_angle_by_sampling(t, &s, ref, n, &m, &se)) { scene_free(&s); return; }
        solid_angle_by_rays(&s, ref, n, &m2, &se2);
        scene_free(&s);
        CHECK(t, fabs(m - m2) < 5.0 * sqrt(se * se + se2 * se2), "%s: E[1/pdf] %.5f +- %.5f, "
              "by rays %.5f +- %.5f", c[i].what, m, se, m2, se2);
    }
}

static void test_disk_can_reach(T *t)
{
    Scene s;
    if (!load(t, &s, "WorldBegin\nTranslate 0 0 2\nRotate 90 1 0 0\nAreaLightSource \"diffuse\"\n"
                     "Shape \"disk\"\nAttributeBegin\nAreaLightSource \"diffuse\" \"bool twosided\" true\n"
                     "Shape \"disk\"\nAttributeEnd\n")) return;
    /* Rotate 90 about x takes +z to -y: the disks lie in the plane y = 0 (at z = 2),
       the first lights y < 0 only */
    CHECK(t, emitter_can_reach(&s, 0, v3(0.3f, -1.0f, 5.0f)), "one-sided: front point not reached");
    CHECK(t, !emitter_can_reach(&s, 0, v3(0.3f, 1.0f, 5.0f)), "one-sided: point behind reached");
    CHECK(t, !emitter_can_reach(&s, 0, v3(7.0f, 0.0f, -3.0f)), "one-sided: point in its plane reached");
    CHECK(t, emitter_can_reach(&s, 1, v3(0.3f, -1.0f, 5.0f)) && emitter_can_reach(&s, 1, v3(0.3f, 1.0f, 5.0f)),
          "two-sided: a side not reached");
    CHECK(t, !emitter_can_reach(&s, 1, v3(7.0f, 0.0f, -3.0f)), "two-sided: point in its plane reached");
    scene_free(&s);
}

/* The light tree's cone of a disk is its one normal: a disk facing the point gets
   a positive probability, one facing away (the point behind its plane, beyond the
   slack of its box) none. */
static void test_disk_tree_cone(T *t)
{
    static const SelStrategy st[] = { SEL_TREE, SEL_SPECTRAL_TREE };
    Scene s;
    int i;
    if (!load(t, &s, "WorldBegin\nAttributeBegin\nTranslate 0 0 2\nReverseOrientation\n"
                     "AreaLightSource \"diffuse\"\nShape \"disk\"\nAttributeEnd\n"
                     "AttributeBegin\nTranslate 3 0 2\nAreaLightSource \"diffuse\"\nShape \"disk\"\n"
                     "AttributeEnd\n")) return;
    for (i = 0; i < 2; i++) {
        SelOptions o;
        LightSampler *ls;
        LightCtx c;
        Error err;
        float p0, p1;
        memset(&o, 0, sizeof o);
        o.strategy = st[i];
        ls = light_sampler_build(&s, &o, &err);
        if (!ls) { scene_free(&s); CHECK(t, 0, "%s", err.msg); }
        memset(&c, 0, sizeof c);
        c.p = v3(0, 0, 0);
        c.n = v3(0, 0, 1);
        c.voxel = light_voxel(ls, c.p);
        c.alive = 1u;
        c.hero_only = 1;
        c.lambda[0] = 550.0f;
        c.beta[0] = 1.0f;
        p0 = light_select_pmf(ls, &c, light_piece_of(ls, 0, -1));
        p1 = light_select_pmf(ls, &c, light_piece_of(ls, 1, -1));
        light_sampler_free(ls);
        if (!(p0 > 0.0f && p1 == 0.0f)) scene_free(&s);
        CHECK(t, p0 > 0.0f && p1 == 0.0f, "%s: P(disk facing the point) %g, P(disk facing away) %g",
              sel_name(st[i]), (double)p0, (double)p1);
    }
    scene_free(&s);
}

/* ------------------------------------------------------------------ renders */

static void test_disk_irradiance(T *t)
{
    /* a disk of radius R = 1.5 at height h = 2, facing down (ReverseOrientation), over
       a large plane of albedo 1/2; the camera (not an object) looks straight down at
       the centre through a 1 degree field, so every pixel sees the plane within 1 cm
       of the centre, where E = pi L R^2 / (h^2 + R^2) varies by less than 1e-4.
       Direct light only (maxdepth 1).  Y of the film = (1/2) E / pi with L's Y = 1. */
    static const char text[] =
        "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n"
        "LookAt 0 0 1  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 1\n"
        "Integrator \"path\" \"integer maxdepth\" 1\n"
        "WorldBegin\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 300 0.5 900 0.5 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [-50 -50 0 50 -50 0 "
        "50 50 0 -50 50 0]\n"
        "AttributeBegin\nTranslate 0 0 2\nReverseOrientation\nAreaLightSource \"diffuse\"\n"
        "Shape \"disk\" \"float radius\" 1.5\nAttributeEnd\n";
    Scene s;
    RenderOptions o;
    Tiles tl;
    const double R = 1.5, h = 2.0, want = 0.5 * R * R / (h * h + R * R);
    double Y, se;
    if (!load(t, &s, text)) return;
    render_options_default(&o);
    o.spp = test_scaled(64, 16);
    o.seed = 5;
    o.maxdepth = 1;                    /* (the file's maxdepth is the command line's business) */
    if (!test_render_tiles(t, &s, &o, 8, 1, &tl)) { scene_free(&s); return; }
    scene_free(&s);
    /* luminance of linear sRGB; its standard error bounded by the sum of the parts' */
    Y = 0.2126 * tl.mean[0][0] + 0.7152 * tl.mean[0][1] + 0.0722 * tl.mean[0][2];
    se = 0.2126 * tl.se[0][0] + 0.7152 * tl.se[0][1] + 0.0722 * tl.se[0][2];
    CHECK(t, fabs(Y - want) < TEST_K_SIGMA * se + 1e-3 * want, "irradiance under a disk: rendered "
          "Y %.5f +- %.5f, expected (1/2) R^2 / (h^2 + R^2) = %.5f", Y, se, want);
}

static void test_strategies_agree(T *t)
{
    /* a box open at the front (camera side) with three lamps of different spectra:
       a tilted annulus sector under a non-uniform scale on the ceiling, a cylinder
       patch and a sphere zone */
    static const char text[] =
        "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n"
        "LookAt 0 -4 1  0 0 1  0 0 1\nCamera \"perspective\" \"float fov\" 50\n"
        "Integrator \"path\" \"integer maxdepth\" 3\n"
        "WorldBegin\n"
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7  8 9 10 8 10 11]\n"
        "  \"point3 P\" [-2 -2 0 2 -2 0 2 2 0 -2 2 0   -2 2 0 2 2 0 2 2 3 -2 2 3"
        "   -2 -2 0 -2 2 0 -2 2 3 -2 -2 3]\n"
        "AttributeBegin\nTranslate 0.2 0.3 2.6\nRotate 160 1 0.2 0\nScale 1 0.6 1\n"
        "AreaLightSource \"diffuse\" \"blackbody L\" 3000 \"float scale\" 2\n"
        "Shape \"disk\" \"float radius\" 0.7 \"float innerradius\" 0.2 \"float phimax\" 300\nAttributeEnd\n"
        "AttributeBegin\nTranslate 1.2 0.8 0.3\n"
        "AreaLightSource \"diffuse\" \"rgb L\" [0.2 0.5 1] \"bool twosided\" true\n"
        "Shape \"cylinder\" \"float radius\" 0.25 \"float zmin\" 0 \"float zmax\" 0.8 \"float phimax\" 270\n"
        "AttributeEnd\n"
        "AttributeBegin\nTranslate -1 0.5 0.6\nScale 1.3 0.7 1\n"
        "AreaLightSource \"diffuse\" \"rgb L\" [1 0.3 0.1]\n"
        "Shape \"sphere\" \"float radius\" 0.35 \"float zmin\" -0.2 \"float zmax\" 0.3\nAttributeEnd\n";
    static const SelStrategy st[] = { SEL_POWER, SEL_SPATIAL, SEL_SPD, SEL_PRODUCT,
                                      SEL_SPECTRAL_SPATIAL, SEL_TREE, SEL_SPECTRAL_TREE };
    static Tiles ref, m;
    Scene s;
    RenderOptions o;
    int i;
    const int K = 8;
    if (!load(t, &s, text)) return;
    render_options_default(&o);
    o.sel.grid_res = 8;
    o.spp = test_scaled(24, 4);
    o.seed = 1;
    o.sel.strategy = SEL_UNIFORM;
    if (!test_render_tiles(t, &s, &o, K, 2, &ref)) goto done;
    for (i = 0; i <= (int)(sizeof st / sizeof st[0]); i++) {
        char what[128];
        RenderOptions oi = o;
        if (i < (int)(sizeof st / sizeof st[0])) {
            oi.sel.strategy = st[i];
            snprintf(what, sizeof what, "quadric lamps, %s vs uniform", sel_name(st[i]));
        } else {
            /* BSDF sampling alone does not use the emitters' pdf: catches a pdf that
               differs from the sampling density, which biases every strategy alike */
            oi.nee = 0;
            oi.spp *= 4;
            snprintf(what, sizeof what, "quadric lamps, BSDF sampling only vs uniform NEE");
        }
        if (!test_render_tiles(t, &s, &oi, K, 2, &m)) goto done;
        if (!test_tiles_agree(t, &m, &ref, 1e-4, what)) goto done;
    }
done:
    scene_free(&s);
}

/* ------------------------------------------------------------------ bad input */

static void expect_reject(T *t, const char *shape, int line, const char *k)
{
    char text[512];
    Scene s;
    Error e;
    char prefix[64];
    int ok;
    snprintf(text, sizeof text, "WorldBegin\n%s\n", shape);
    memset(&s, 0, sizeof s);
    e.msg[0] = '\0';
    ok = scene_load_string(&s, text, "bad.pbrt", &e);
    if (ok) scene_free(&s);
    CHECK(t, !ok, "accepted %s", shape);
    snprintf(prefix, sizeof prefix, "bad.pbrt:%d:", line);
    CHECK(t, strncmp(e.msg, prefix, strlen(prefix)) == 0 && strchr(e.msg, '\n') == NULL,
          "message \"%s\" is not one line starting with \"%s\"", e.msg, prefix);
    CHECK(t, strstr(e.msg, k) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k);
    scene_free(&s);
}

/* pbrt-v4 (shapes.h: Sphere and Cylinder keep min(zmin, zmax) and max(zmin, zmax))
   swaps a reversed pair: such a cylinder and cut sphere are the ordered ones, and
   a ray hits them where it hits those. */
static void test_swapped_z(T *t)
{
    static const char *const pairs[2][2] = {
        { "Shape \"cylinder\" \"float zmin\" 2", "Shape \"cylinder\" \"float zmin\" 1 \"float zmax\" 2" },
        { "Shape \"sphere\" \"float zmin\" 0.5 \"float zmax\" -0.2",
          "Shape \"sphere\" \"float zmin\" -0.2 \"float zmax\" 0.5" },
    };
    int k, i;
    for (k = 0; k < 2; k++) {
        Scene a, b;
        char text[512];
        snprintf(text, sizeof text, "WorldBegin\n%s\n", pairs[k][0]);
        if (!test_load_scene(t, &a, text)) return;
        snprintf(text, sizeof text, "WorldBegin\n%s\n", pairs[k][1]);
        if (!test_load_scene(t, &b, text)) { scene_free(&a); return; }
        CHECK(t, a.shapes[0].q.zmin == b.shapes[0].q.zmin && a.shapes[0].q.zmax == b.shapes[0].q.zmax &&
              a.shapes[0].q.zmin < a.shapes[0].q.zmax, "%s: z range [%g, %g], ordered [%g, %g]", pairs[k][0],
              a.shapes[0].q.zmin, a.shapes[0].q.zmax, b.shapes[0].q.zmin, b.shapes[0].q.zmax);
        for (i = 0; i < 16; i++) {
            Ray r;
            HitRecord ha, hb;
            int x, y;
            r.o = v3(3.0f, 0.1f * (float)i - 0.5f, 0.15f * (float)i - 0.6f);
            r.d = v3(-1, 0.05f, 0.02f);
            r.tmax = INFINITY;
            x = bvh_intersect(&a.bvh, &a, &r, &ha);
            y = bvh_intersect(&b.bvh, &b, &r, &hb);
            CHECK(t, x == y && (!x || ha.t == hb.t), "%s: ray %d: hit %d at %g, ordered %d at %g",
                  pairs[k][0], i, x, x ? ha.t : 0.0f, y, y ? hb.t : 0.0f);
        }
        scene_free(&a);
        scene_free(&b);
    }
}

static void test_reject(T *t)
{
    static const struct { const char *shape; int line; const char *k; } c[] = {
        { "Shape \"disk\" \"float radius\" 0", 2, "radius 0 must be > 0" },
        { "Shape \"disk\" \"float radius\" -1", 2, "radius -1 must be > 0" },
        { "Shape \"disk\" \"float innerradius\" 1.5", 2, "innerradius 1.5 must lie in [0, radius 1)" },
        { "Shape \"disk\" \"float innerradius\" -0.1", 2, "innerradius -0.1" },
        { "Shape \"disk\" \"float phimax\" 0", 2, "phimax 0 must lie in (0, 360]" },
        { "Shape \"disk\" \"float phimax\" 361", 2, "phimax 361" },
        { "Shape \"disk\" \"float height\" 1e300", 2, "finite" },
        { "Shape \"disk\"\n\"float radius\" nan", 3, "finite" },
        { "Shape \"disk\" \"texture alpha\" \"none\"", 2, "\"texture alpha\": no texture named \"none\"" },
        { "Shape \"cylinder\" \"float radius\" 0", 2, "radius 0 must be > 0" },
        { "Shape \"cylinder\" \"float zmin\" 1 \"float zmax\" 1", 2, "zmin = zmax = 1" },
        { "Shape \"cylinder\" \"float phimax\" -90", 2, "phimax -90" },
        { "Shape \"cylinder\" \"float zmax\" 1e39", 2, "finite" },
        { "Shape \"sphere\" \"float zmin\" 0.3 \"float zmax\" 0.3", 2, "zmin = zmax = 0.3" },
        { "Shape \"sphere\" \"float zmin\" 1.5 \"float zmax\" 2", 2, "misses the sphere" },
        { "Shape \"sphere\" \"float phimax\" 400", 2, "phimax 400" },
        { "ConcatTransform [1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1]\nShape \"disk\"", 3, "projective" },
    };
    int i;
    for (i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
        expect_reject(t, c[i].shape, c[i].line, c[i].k);
        if (t->failed) return;
    }
}

/* A whole sphere finds its (u, v) only for what reads them (mat_reads_uv): here a
   transmittance texture and a coated conductor's base roughness texture.  From +y
   the hit is at phi = 90 degrees, theta = 90 degrees: (u, v) = (0.25, 0.5). */
static void test_sphere_uv_when_read(T *t)
{
    static const char *const mats[2] = {
        "Material \"diffusetransmission\" \"texture transmittance\" \"c\"\n",
        "Material \"coatedconductor\" \"texture conductor.roughness\" \"f\"\n",
    };
    int i;
    for (i = 0; i < 2; i++) {
        Scene s;
        SurfacePoint sp;
        float th;
        char text[512];
        snprintf(text, sizeof text, "WorldBegin\nTexture \"c\" \"spectrum\" \"checkerboard\"\n"
                 "Texture \"f\" \"float\" \"checkerboard\"\n%sShape \"sphere\"\n", mats[i]);
        if (!load(t, &s, text)) return;
        CHECK(t, trace(&s, v3(0, 5, 0), v3(0, -1, 0), &th, &sp) &&
              fabsf(sp.u - 0.25f) < 1e-6f && fabsf(sp.v - 0.5f) < 1e-6f,
              "%s(u, v) = (%g, %g), expected (0.25, 0.5)", mats[i], (double)sp.u, (double)sp.v);
        scene_free(&s);
    }
}

/* "integer faceIndices" of trianglemesh and bilinearmesh: pbrt-v4 reads them only
   for Ptex lookups (the face a texture value belongs to), so a scene renders the
   same with them, bit for bit; one a face, else a one-line error at the Shape. */
static void test_face_indices(T *t)
{
    static const char *const head =
        "LookAt 0 -3 3  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
        "WorldBegin\nLightSource \"point\" \"point3 from\" [ 0 1 2 ] \"float scale\" [ 4 ]\n";
    static const char *const mesh[2] = {
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
        "\"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]%s\n"
        "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] "
        "\"point3 P\" [ -1 -1 1  1 -1 1  -1 1 1.5  1 1 1 ]%s\n",
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] "
        "\"point3 P\" [ -1 -1 0  1 -1 0  1 1 0 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] "
        "\"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] \"integer faceIndices\" [ 7 ]\n"
    };
    char text[2][2048];
    Image im[2];
    RenderOptions o;
    int k, i;
    render_options_default(&o);
    o.spp = 4;
    for (k = 0; k < 2; k++) {
        char body[1024];
        snprintf(body, sizeof body, mesh[0], k ? " \"integer faceIndices\" [ 5 9 ]" : "",
                 k ? " \"integer faceIndices\" [ 3 ]" : "");
        snprintf(text[k], sizeof text[k], "%s%s", head, body);
        if (!test_render_text(t, text[k], &o, &im[k])) {
            if (k) img_free(&im[0]);
            return;
        }
    }
    for (i = 0; i < 3 * im[0].w * im[0].h && im[0].rgb[i] == im[1].rgb[i]; i++) continue;
    k = i == 3 * im[0].w * im[0].h;
    img_free(&im[0]);
    img_free(&im[1]);
    CHECK(t, k, "faceIndices changed the image (value %d)", i);
    snprintf(text[0], sizeof text[0], "%s%s", head, mesh[1]);
    test_rejected_at(t, text[0], 7, "1 faceIndices for 2 triangles", NULL);
    snprintf(text[0], sizeof text[0], "%sShape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ] "
             "\"point3 P\" [ -1 -1 1  1 -1 1  -1 1 1  1 1 1 ] \"integer faceIndices\" [ 1 2 ]\n", head);
    test_rejected_at(t, text[0], 6, "2 faceIndices for 1 patch ", NULL);
}

const TestCase tests_shapes[] = {
    { "shapes_sphere_uv_when_read", test_sphere_uv_when_read },
    { "shapes_disk_hits", test_disk_hits },
    { "shapes_cylinder_hits", test_cylinder_hits },
    { "shapes_sphere_part_hits", test_sphere_part_hits },
    { "shapes_area", test_area },
    { "shapes_solid_angle", test_solid_angle },
    { "shapes_disk_can_reach", test_disk_can_reach },
    { "shapes_disk_tree_cone", test_disk_tree_cone },
    { "shapes_disk_irradiance", test_disk_irradiance },
    { "shapes_strategies_agree", test_strategies_agree },
    { "shapes_reject", test_reject },
    { "shapes_swapped_z", test_swapped_z },
    { "shapes_face_indices", test_face_indices },
    { NULL, NULL }
};
