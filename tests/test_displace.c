/* tests/test_displace.c - a plymesh's "texture displacement" and "float
   edgelength" (displace.c ply_displace; geometry.c's plymesh builder).

   Checked: a flat square with a constant displacement moves by exactly that
   value along its normal, in object space (under Scale 2 by twice it); every
   edge of the refined mesh is shorter than edgelength in world space, and one
   half as long is not (the bisection stops as soon as it may); the recomputed
   normals of the flat result are (0, 0, 1); no two vertices coincide (a midpoint
   is shared by the edge's two triangles); a quad is split as pbrt-v4 splits
   it; bad input (no uv, edgelength <= 0 or so small that the triangles would
   pass MAX_ELEMENTS, an unknown texture) at its file:line; Option
   "displacementedgescale" multiplies edgelength; pbrt-v4's images of a square displaced by a bilerp (a warped saddle) and of a
   UV sphere with its own normals, quads and a rotation, frozen. */
#include "test.h"
#include <string.h>

#define NEAR(a, b, tol) (fabs((double)(a) - (double)(b)) <= (tol))

static const char *const DS_PLY =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\n"
    "end_header\n-1 -1 0 0 0\n1 -1 0 1 0\n1 1 0 1 1\n-1 1 0 0 1\n4 0 1 2 3\n";

/* The longest and shortest world-space edge of the scene's triangles. */
static void edge_range(const Scene *s, double *lo, double *hi)
{
    int i, k;
    *lo = 1e30;
    *hi = 0.0;
    for (i = 0; i < s->n_tris; i++)
        for (k = 0; k < 3; k++) {
            Vec3 a = s->P[s->tris[i].v[k]], b = s->P[s->tris[i].v[(k + 1) % 3]];
            double d = v3_len(v3_sub(a, b));
            if (d > *hi) *hi = d;
            if (d < *lo) *lo = d;
        }
}

static void test_displace_flat_constant(T *t)
{
    static const struct { const char *xf; float edge, z; } c[] = {
        { "", 0.3f, 0.25f }, { "Scale 2 2 2\n", 0.3f, 0.5f }, { "", 5.0f, 0.25f },
    };
    const char *path = test_write_file(t, "square.ply", DS_PLY);
    char text[2048];
    Scene s;
    int i, j, bad;
    for (j = 0; j < 3; j++) {
        double lo, hi;
        snprintf(text, sizeof text, "WorldBegin\nTexture \"d\" \"float\" \"constant\" \"float value\" [ 0.25 ]\n"
                 "%sShape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
                 "\"float edgelength\" [ %g ]\n", c[j].xf, path, (double)c[j].edge);
        if (!test_load_scene(t, &s, text)) return;
        for (i = 0, bad = 0; i < s.n_verts; i++)
            bad += s.P[i].z != c[j].z || !s.N || s.N[i].x != 0.0f || s.N[i].y != 0.0f || s.N[i].z != 1.0f;
        for (i = 0; i < s.n_verts; i++) {          /* midpoints shared by both sides */
            int k;
            for (k = i + 1; k < s.n_verts; k++)
                bad += s.P[i].x == s.P[k].x && s.P[i].y == s.P[k].y && s.P[i].z == s.P[k].z;
        }
        edge_range(&s, &lo, &hi);
        CHECK(t, bad == 0, "case %d: %d of %d vertices not at z = %g with normal (0, 0, 1), or twice at one place", j, bad,
              s.n_verts, (double)c[j].z);
        CHECK(t, hi < c[j].edge && (c[j].edge > 4.0f || 2.0 * hi >= c[j].edge),
              "case %d: edges %g .. %g against edgelength %g", j, lo, hi, (double)c[j].edge);
        /* the square's 2 (or 2 x 2, scaled) units over edges below 0.3: at least
           (2 / 0.3)^2 = 44 (178) cells, 2 triangles each; edgelength 5: the two
           triangles of pbrt-v4's quad split, (0, 1, 2) and (0, 2, 3) of the face */
        if (j == 2)
            CHECK(t, s.n_tris == 2 && s.n_verts == 4 && s.tris[0].v[0] == 0 && s.tris[0].v[1] == 1 &&
                  s.tris[0].v[2] == 2 && s.tris[1].v[1] == 2 && s.tris[1].v[2] == 3,
                  "the quad: %d triangles (%d %d %d)", s.n_tris, s.tris[0].v[0], s.tris[0].v[1], s.tris[0].v[2]);
        else
            CHECK(t, s.n_tris >= (j ? 356 : 88), "case %d: only %d triangles", j, s.n_tris);
        scene_free(&s);
    }
}

/* With the file's normals (0.6, 0, 0.8) a constant 0.25 moves every vertex by
   (0.15, 0, 0.2), the file's normals unnormalised as pbrt-v4 uses them (here
   unit), the midpoints' their normalised sums; the result is flat again, its
   recomputed normals (0, 0, 1). */
static void test_displace_file_normals(T *t)
{
    const char *path = test_write_file(t, "tilted.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "-1 -1 0 0.6 0 0.8 0 0\n1 -1 0 0.6 0 0.8 1 0\n1 1 0 0.6 0 0.8 1 1\n-1 1 0 0.6 0 0.8 0 1\n"
        "3 0 1 2\n3 0 2 3\n");
    char text[2048];
    Scene s;
    double xlo = 1e30, xhi = -1e30;
    int i, bad = 0;
    snprintf(text, sizeof text, "WorldBegin\nTexture \"d\" \"float\" \"constant\" \"float value\" [ 0.25 ]\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
             "\"float edgelength\" [ 0.5 ]\n", path);
    if (!test_load_scene(t, &s, text)) return;
    for (i = 0; i < s.n_verts; i++) {
        bad += !NEAR(s.P[i].z, 0.2, 1e-6) || !s.N || !NEAR(s.N[i].z, 1.0, 1e-6);
        if (s.P[i].x < xlo) xlo = s.P[i].x;
        if (s.P[i].x > xhi) xhi = s.P[i].x;
    }
    CHECK(t, bad == 0 && s.n_verts > 9 && NEAR(xlo, -0.85, 1e-6) && NEAR(xhi, 1.15, 1e-6),
          "%d of %d vertices off z = 0.2 or normal (0, 0, 1); x from %g to %g (want -0.85, 1.15)",
          bad, s.n_verts, xlo, xhi);
    scene_free(&s);
}

static void test_displace_errors(T *t)
{
    const char *path = test_write_file(t, "square.ply", DS_PLY);
    const char *nouv = test_write_file(t, "nouv.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    char text[2048];
    snprintf(text, sizeof text, "WorldBegin\nTexture \"d\" \"float\" \"constant\"\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\"\n", nouv);
    test_rejected_at(t, text, 3, "\"texture displacement\" needs per-vertex uv", NULL);
    snprintf(text, sizeof text, "WorldBegin\nTexture \"d\" \"float\" \"constant\"\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
             "\"float edgelength\" 0\n", path);
    test_rejected_at(t, text, 3, "\"float edgelength\" 0 must be > 0", NULL);
    snprintf(text, sizeof text, "WorldBegin\nTexture \"d\" \"float\" \"constant\"\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
             "\"float edgelength\" 1e-5\n", path);
    test_rejected_at(t, text, 3, "edgelength 1e-05 makes at least 9.24e+10 triangles", NULL);
    snprintf(text, sizeof text, "WorldBegin\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"zz\"\n", path);
    test_rejected_at(t, text, 2, "no texture named \"zz\"", NULL);
}

/* The square (-1..1 in x and y, uv over it) displaced by a bilerp of 0, 0.5, 0.2,
   -0.2 (v00, v10, v01, v11), edgelength 0.15, diffuse (0.5), seen from (0, -3, 3)
   (fov 40, 48 x 48, box filter) under a distant light from (1, -0.5, 3), path
   maxdepth 1.  pbrt-v4 (commit 5f7a6068, `pbrt --seed S --spp 64`, S = 1..8, the
   independent sampler): image and quadrant luminances (top left, top right,
   bottom left, bottom right), mean and standard error over the seeds.  specnee
   at 4 x 64 spp: within 0.15 % of each; undisplaced the square gives 0.1469,
   0.1103, 0.1103, 0.1836, 0.1835. */
static const double PBRT_DISP_Y[5][2] = {
    { 0.12448, 0.00005 }, { 0.09462, 0.00008 }, { 0.13000, 0.00010 }, { 0.11983, 0.00008 },
    { 0.15348, 0.00006 },
};

static void test_displace_against_pbrt(T *t)
{
    const char *path = test_write_file(t, "square.ply", DS_PLY);
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 -3 3  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ]\n"
             "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
             "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 -0.5 3 ] "
             "\"point3 to\" [ 0 0 0 ]\n"
             "Texture \"d\" \"float\" \"bilerp\" \"float v00\" [ 0 ] \"float v10\" [ 0.5 ] "
             "\"float v01\" [ 0.2 ] \"float v11\" [ -0.2 ]\nMaterial \"diffuse\"\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
             "\"float edgelength\" [ 0.15 ]\n", path);
    test_against_pbrt_y(t, text, 1, PBRT_DISP_Y, 5e-3, "displaced square");
}

/* A UV sphere of radius 1 (24 x 12 quads, uv = (i / 24, j / 12), the file's unit
   normals, the seam's and poles' vertices doubled as an exporter writes them). */
static const char *sphere_ply(T *t)
{
    static char buf[65536];
    size_t n = 0;
    int i, j;
    n += (size_t)snprintf(buf + n, sizeof buf - n, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\n"
                          "property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                          "property float nz\nproperty float u\nproperty float v\nelement face %d\n"
                          "property list uchar int vertex_indices\nend_header\n", 25 * 13, 24 * 12);
    for (j = 0; j <= 12; j++)
        for (i = 0; i <= 24; i++) {
            double th = SPECNEE_PI * j / 12, ph = 2.0 * SPECNEE_PI * i / 24;
            double x = sin(th) * cos(ph), y = sin(th) * sin(ph), z = cos(th);
            n += (size_t)snprintf(buf + n, sizeof buf - n, "%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n",
                                  x, y, z, x, y, z, i / 24.0, j / 12.0);
        }
    for (j = 0; j < 12; j++)
        for (i = 0; i < 24; i++) {
            int a = j * 25 + i;
            n += (size_t)snprintf(buf + n, sizeof buf - n, "4 %d %d %d %d\n", a, a + 25, a + 26, a + 1);
        }
    return test_write_file(t, "sphere.ply", buf);
}

/* That sphere under Rotate 30 0 0 1, displaced by a bilerp of 0, 0.3, 0.1, -0.2,
   edgelength 0.1, diffuse, seen from (0, -4, 1) (fov 40, 48 x 48, box filter)
   under a distant light from (1, -2, 3), path maxdepth 1; pbrt-v4 as above (8
   seeds x 64 spp).  specnee at 4 x 64 spp: within 0.08 % of each. */
static const double PBRT_DISP_SPHERE_Y[5][2] = {
    { 0.11762, 0.00002 }, { 0.21737, 0.00007 }, { 0.14597, 0.00006 }, { 0.06646, 0.00002 },
    { 0.04067, 0.00001 },
};

static void test_displace_sphere_against_pbrt(T *t)
{
    const char *path = sphere_ply(t);
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 -4 1  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ]\n"
             "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
             "LightSource \"distant\" \"float scale\" [ 3.14159265358979 ] \"point3 from\" [ 1 -2 3 ] "
             "\"point3 to\" [ 0 0 0 ]\n"
             "Texture \"d\" \"float\" \"bilerp\" \"float v00\" [ 0 ] \"float v10\" [ 0.3 ] "
             "\"float v01\" [ 0.1 ] \"float v11\" [ -0.2 ]\nMaterial \"diffuse\"\nRotate 30 0 0 1\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
             "\"float edgelength\" [ 0.1 ]\n", path);
    test_against_pbrt_y(t, text, 1, PBRT_DISP_SPHERE_Y, 5e-3, "displaced sphere");
}

/* Option "displacementedgescale" s multiplies every displaced mesh's edgelength
   (pbrt-v4's Options->displacementEdgeScale; its image of the bilerp square of
   test_displace_against_pbrt with edgelength 15 and Option 0.01 is the image of
   edgelength 0.15 bit for bit, and with 0.15 and Option 4 another one):
   edgelength 15 under 0.01 (pbrt-v4's spelling, and the typed one) builds the
   mesh of 0.15, vertex for vertex; an undisplaced plymesh is not refined;
   a scale <= 0 or not a number, and one that arrives after a displaced mesh and differs from
   the one it was refined with, are refused at their file:line. */
static void test_displace_edge_scale(T *t)
{
    static const char *const opt[3] = { "", "Option \"displacementedgescale\" 0.01\n",
                                        "Option \"float displacementedgescale\" 0.01\n" };
    const char *path = test_write_file(t, "square.ply", DS_PLY);
    char text[2048];
    Scene s[3];
    int j, i, same = 1;
    for (j = 0; j < 3; j++) {
        snprintf(text, sizeof text, "%sWorldBegin\nTexture \"d\" \"float\" \"bilerp\" \"float v00\" [ 0 ] "
                 "\"float v10\" [ 0.5 ] \"float v01\" [ 0.2 ] \"float v11\" [ -0.2 ]\n"
                 "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\" "
                 "\"float edgelength\" [ %s ]\n", opt[j], path, j ? "15" : "0.15");
        if (!test_load_scene(t, &s[j], text)) {
            while (j-- > 0) scene_free(&s[j]);
            return;
        }
    }
    for (j = 1; j < 3; j++) {
        same = same && s[j].n_tris == s[0].n_tris && s[j].n_verts == s[0].n_verts;
        for (i = 0; same && i < s[0].n_verts; i++)
            same = !memcmp(&s[j].P[i], &s[0].P[i], sizeof(Vec3));
    }
    CHECK(t, same && s[0].n_tris > 100, "edgelength 15 under the Option 0.01: %d and %d triangles, "
          "edgelength 0.15: %d", s[1].n_tris, s[2].n_tris, s[0].n_tris);
    for (j = 0; j < 3; j++) scene_free(&s[j]);
    snprintf(text, sizeof text, "Option \"displacementedgescale\" 0.01\nWorldBegin\n"
             "Shape \"plymesh\" \"string filename\" \"%s\"\n", path);
    if (test_load_scene(t, &s[0], text)) {
        CHECK(t, s[0].n_tris == 0 || s[0].n_tris == 2, "an undisplaced plymesh refined: %d triangles", s[0].n_tris);
        scene_free(&s[0]);
    }
    test_rejected_at(t, "Option \"displacementedgescale\" 0\nWorldBegin\n", 1,
                     "Option \"displacementedgescale\": expected one number > 0", NULL);
    test_rejected_at(t, "Option \"displacementedgescale\" 2x\nWorldBegin\n", 1,
                     "Option \"displacementedgescale\": expected one number > 0", NULL);
    snprintf(text, sizeof text, "WorldBegin\nTexture \"d\" \"float\" \"constant\"\n"
             "Shape \"plymesh\" \"string filename\" \"%s\" \"texture displacement\" \"d\"\n"
             "Option \"displacementedgescale\" 1\nOption \"displacementedgescale\" 2\n", path);
    test_rejected_at(t, text, 5, "Option \"displacementedgescale\" 2 after the displaced plymesh of", NULL);
}

const TestCase tests_displace[] = {
    { "displace_flat_constant", test_displace_flat_constant },
    { "displace_file_normals", test_displace_file_normals },
    { "displace_errors", test_displace_errors },
    { "displace_edge_scale", test_displace_edge_scale },
    { "displace_against_pbrt", test_displace_against_pbrt },
    { "displace_sphere_against_pbrt", test_displace_sphere_against_pbrt },
    { NULL, NULL }
};
