/* tests/test_lighttree.c - the light tree of lighttree.c (--lights tree and
   spectral-tree), beyond what tests/test_lights.c checks for every strategy (there
   both trees are compared with `uniform` on one emitter, two identical emitters,
   64 small emitters of four spectra, complementary half spectra, a bright emitter
   facing away, an emitter seen only through glass, dispersive glass).

     lighttree_select_matches_pmf  light_select's pmf equals light_select_pmf
                  bit for bit, frequencies match the pmf (chi-square), the pmfs
                  sum to 1, pieces with pmf 0 are never chosen; random points,
                  normals, wavelengths and alive sets, with contexts where whole
                  subtrees have importance 0 (counted, so the case is exercised)
     lighttree_spectral_preference  hero alone at 450 nm: the spectral tree never
                  picks the emitter that is dark there, the total-power tree does
     lighttree_conservative  every piece with a point facing a random point has
                  P > 0 (one- and two-sided lamps facing every way, a split panel)
     lighttree_conservative_random  the same on 24 random scenes of quads in
                  groups facing random ways (equal, close or far-apart normals)
     lighttree_simd_matches_scalar  the four children's importances computed
                  side by side (SSE2) equal the scalar code's, bit for bit, at
                  random contexts on both trees
     lighttree_prefers_near  two identical emitters: the near one is preferred,
                  and an emitter facing away from the point is never chosen;
                  of two at one distance, the one facing the point about 4:1
                  over one seen at 80 degrees; inside a node's bounding sphere
                  the node whose centre is near wins
     lighttree_degenerate  all emitters at one point, all coplanar, one emitter,
                  10,000 emitters: the build works, pmfs sum to 1, no NaN
     lighttree_mesh_split_unbiased  a large emissive mesh split into clusters
                  converges to `uniform`'s image (and to the unsplit tree's)
     lighttree_mesh_split_pmf  the cluster hit by a ray is the one light_piece_of
                  names, with the pdf NEE sampled it with
     lighttree_per_render_radiance  the emitters' radiance for two wavelength
                  ranges from one const Scene (the render owns it)
     lighttree_behind_the_box  points just above a plane of down-facing lamps,
                  inside their bounding spheres: nothing is sampled (I = 0 at
                  the root); from below every lamp keeps P > 0; axis-aligned
                  and turned lamps
     lighttree_on_the_lamp  a point on a one-sided lamp: that lamp has P = 0
                  (its plane moved forward by the margin), with and without
                  "normal N"; normals that disagree keep the cone full
     lighttree_on_the_lamp_spot  a spot light whose cone reaches 90 degrees
                  keeps P > 0 within the margin in front of its plane */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static const char *camera16 =
    "LookAt 0 0 -3.2  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"t.pfm\"\n"
    "Integrator \"path\" \"integer maxdepth\" [ 5 ]\n"
    "WorldBegin\n";

#define SPIKY "[ 400 0 430 0 435 3 440 0 540 0 545 4 550 0 605 0 611 3 617 0 700 0 ]"
#define BLUEISH "[ 400 0.1 450 1.0 480 0.3 560 0.6 700 0.2 ]"
#define LOW_HALF "[ 400 1 550 1 551 0 700 0 ]"
#define HIGH_HALF "[ 400 0 549 0 550 1 700 1 ]"

/* Append a one-sided square emitter of half-size h centred at c, facing along
   +dir_axis (0: x, 1: y, 2: z) with sign sgn. */
static void add_quad(char *buf, size_t cap, const char *spectrum, float scale, Vec3 c, int axis,
                     int sgn, float h)
{
    size_t n = strlen(buf);
    float p[4][3];
    int k, u = (axis + 1) % 3, v = (axis + 2) % 3;
    static const float su[4] = { -1, 1, 1, -1 }, sv[4] = { -1, -1, 1, 1 };
    for (k = 0; k < 4; k++) {
        p[k][axis] = v3_get(c, axis);
        p[k][u] = v3_get(c, u) + h * su[k];
        p[k][v] = v3_get(c, v) + h * sv[k];
    }
    /* (u, v) counter-clockwise has normal +axis; flip the winding for -axis */
    snprintf(buf + n, cap - n,
             "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" %s \"float scale\" [ %g ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ %s ]\n"
             "  \"point3 P\" [ %g %g %g  %g %g %g  %g %g %g  %g %g %g ]\nAttributeEnd\n",
             spectrum, scale, sgn > 0 ? "0 1 2 0 2 3" : "0 2 1 0 3 2",
             p[0][0], p[0][1], p[0][2], p[1][0], p[1][1], p[1][2],
             p[2][0], p[2][1], p[2][2], p[3][0], p[3][1], p[3][2]);
}

/* One one-sided emissive mesh of n triangles tri[i][0..3), each wound so
   that its normal (pbrt-v4's cross(p0 - p2, p1 - p2)) points along facing[i],
   and turned (a cyclic turn keeps the winding) so that its highest vertex
   comes first. */
static void add_oriented(char *buf, size_t cap, Vec3 (*tri)[3], const Vec3 *facing, int n)
{
    size_t len = strlen(buf);
    int i, k;
    len += (size_t)snprintf(buf + len, cap - len,
                            "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" %s \"float scale\" [ 1 ]\n"
                            " Shape \"trianglemesh\" \"integer indices\" [", SPIKY);
    for (i = 0; i < 3 * n; i++) len += (size_t)snprintf(buf + len, cap - len, " %d", i);
    len += (size_t)snprintf(buf + len, cap - len, " ]\n  \"point3 P\" [");
    for (i = 0; i < n; i++) {
        Vec3 nrm = v3_cross(v3_sub(tri[i][0], tri[i][2]), v3_sub(tri[i][1], tri[i][2]));
        if (v3_dot(nrm, facing[i]) < 0.0f) { Vec3 x = tri[i][0]; tri[i][0] = tri[i][1]; tri[i][1] = x; }
        while (tri[i][1].y > tri[i][0].y || tri[i][2].y > tri[i][0].y) {
            Vec3 x = tri[i][0];
            tri[i][0] = tri[i][1]; tri[i][1] = tri[i][2]; tri[i][2] = x;
        }
        for (k = 0; k < 3; k++)
            len += (size_t)snprintf(buf + len, cap - len, " %g %g %g", tri[i][k].x, tri[i][k].y, tri[i][k].z);
    }
    snprintf(buf + len, cap - len, " ]\nAttributeEnd\n");
}

/* A one-sided "tent" lamp: one mesh of two quads of half-size h meeting at a
   right angle, one facing down (-y) centred on c, one facing +x standing on
   its +x edge.  Its normals span 90 degrees, so its cone (theta_o = 45,
   theta_e = 90) emits behind the plane that bounds its box on the side its
   axis points away from. */
static void add_tent(char *buf, size_t cap, Vec3 c, float h)
{
    Vec3 tri[4][3], facing[4];
    const Vec3 a = v3(c.x - h, c.y, c.z - h), b = v3(c.x + h, c.y, c.z - h), d = v3(c.x + h, c.y, c.z + h),
               e = v3(c.x - h, c.y, c.z + h), ta = v3(c.x + h, c.y + 2 * h, c.z - h),
               tb = v3(c.x + h, c.y + 2 * h, c.z + h);
    tri[0][0] = a; tri[0][1] = b; tri[0][2] = d;
    tri[1][0] = a; tri[1][1] = d; tri[1][2] = e;
    tri[2][0] = b; tri[2][1] = d; tri[2][2] = tb;
    tri[3][0] = b; tri[3][1] = tb; tri[3][2] = ta;
    facing[0] = facing[1] = v3(0, -1, 0);
    facing[2] = facing[3] = v3(1, 0, 0);
    add_oriented(buf, cap, tri, facing, 4);
}

/* A roof at c: two rectangles of half-size h leaning 40 degrees either way
   from a ridge along z, facing up and outwards (axis +y, theta_o = 40
   degrees).  The piece's lowest points, where the plane of node_behind must
   lie, are the eaves; every triangle lists a ridge vertex first. */
static void add_roof(char *buf, size_t cap, Vec3 c, float h)
{
    Vec3 tri[4][3], facing[4];
    const float cs = (float)cos(40.0 * SPECNEE_PI / 180.0), sn = (float)sin(40.0 * SPECNEE_PI / 180.0);
    int side;
    for (side = 0; side < 2; side++) {
        float sx = side ? 1.0f : -1.0f;
        Vec3 r1 = v3(c.x, c.y, c.z - h), r2 = v3(c.x, c.y, c.z + h);
        Vec3 o1 = v3(c.x + sx * 2 * h * cs, c.y - 2 * h * sn, c.z - h), o2 = v3(o1.x, o1.y, c.z + h);
        tri[2 * side][0] = r1; tri[2 * side][1] = r2; tri[2 * side][2] = o2;
        tri[2 * side + 1][0] = r1; tri[2 * side + 1][1] = o2; tri[2 * side + 1][2] = o1;
        facing[2 * side] = facing[2 * side + 1] = v3(sx * sn, cs, 0.0f);
    }
    add_oriented(buf, cap, tri, facing, 4);
}

/* Three upright triangles at c facing the horizontal directions 0, 110 and 250
   degrees around y: a piece whose cone (theta_o = 110, theta_e = 90 degrees)
   spans more than 180 degrees, so that no plane bounds where its light goes. */
static void add_three_faced(char *buf, size_t cap, Vec3 c, float h)
{
    Vec3 tri[3][3], facing[3];
    int i;
    for (i = 0; i < 3; i++) {
        double phi = (i == 0 ? 0.0 : i == 1 ? 110.0 : 250.0) * SPECNEE_PI / 180.0;
        Vec3 n = v3((float)cos(phi), 0.0f, (float)sin(phi)), tg = v3(-(float)sin(phi), 0.0f, (float)cos(phi));
        Vec3 o = v3_add(c, v3_mul(n, h));
        tri[i][0] = v3_sub(o, v3_mul(tg, h));
        tri[i][1] = v3_add(o, v3_mul(tg, h));
        tri[i][2] = v3_add(o, v3(0.0f, 2.0f * h, 0.0f));
        facing[i] = n;
    }
    add_oriented(buf, cap, tri, facing, 3);
}

/* A tessellated emissive panel (k x k quads, 2 k^2 triangles) on the plane
   x = -0.98 facing +x, from y = -1 to 1 and z = -1 to 1: a large emitter next to
   the floor and the back wall. */
static void add_panel(char *buf, size_t cap, const char *spectrum, float scale, int k)
{
    size_t n = strlen(buf);
    int i, j;
    n += (size_t)snprintf(buf + n, cap - n,
                          "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" %s \"float scale\" [ %g ]\n"
                          " Shape \"trianglemesh\" \"integer indices\" [", spectrum, scale);
    for (i = 0; i < k; i++)
        for (j = 0; j < k; j++) {
            int a = i * (k + 1) + j, b = a + 1, c = a + k + 1, d = c + 1;
            /* vertex (i, j) at y = -1 + 2i/k, z = -1 + 2j/k: (a, c, d) winds to +x */
            n += (size_t)snprintf(buf + n, cap - n, " %d %d %d %d %d %d", a, c, d, a, d, b);
        }
    n += (size_t)snprintf(buf + n, cap - n, " ]\n  \"point3 P\" [");
    for (i = 0; i <= k; i++)
        for (j = 0; j <= k; j++)
            n += (size_t)snprintf(buf + n, cap - n, " -0.98 %g %g", -1.0 + 2.0 * i / k, -1.0 + 2.0 * j / k);
    snprintf(buf + n, cap - n, " ]\nAttributeEnd\n");
}

static LightSampler *build(T *t, const Scene *s, SelStrategy st, int tput, int no_split)
{
    SelOptions o;
    Error err;
    LightSampler *ls;
    memset(&o, 0, sizeof o);
    o.strategy = st;
    o.all_wavelengths = tput;
    o.throughput_weighted = tput;
    o.no_split = no_split;
    err.msg[0] = 0;
    ls = light_sampler_build(s, &o, &err);
    if (!ls) test_failf(t, __FILE__, __LINE__, "light_sampler_build: %s", err.msg);
    return ls;
}

/* A random context: a point in the scene's box (a quarter of them on an
   emitter's box face, inside the bounding spheres), a random normal or none,
   random wavelengths, the hero alone half of the time. */
static LightCtx random_ctx(const Scene *s, Rng *r)
{
    LightCtx c;
    int j;
    Vec3 ext = v3_sub(s->bmax, s->bmin);
    memset(&c, 0, sizeof c);
    {
        const Vec3 u = rng_vec3(r);
        c.p = v3_add(s->bmin, v3(ext.x * u.x, ext.y * u.y, ext.z * u.z));
    }
    if (rng_float(r) < 0.75f)
        c.n = v3_norm(v3_sub(v3_mul(rng_vec3(r), 2.0f), v3(1.0f, 1.0f, 1.0f)));
    c.voxel = -1;
    c.alive = rng_float(r) < 0.5f ? 1u : (1u | ((rng_u32(r) & 7u) << 1));
    c.hero_only = c.alive == 1u;
    for (j = 0; j < HERO_N; j++) {
        c.lambda[j] = 400.0f + 300.0f * rng_float(r);
        c.beta[j] = (c.alive & (1u << j)) ? 0.1f + rng_float(r) : 0.0f;
    }
    return c;
}

/* select == pmf, chi-square (with "none" as one more outcome; the significance
   level divided among the trials), the pmfs sum to at most 1, zero-pmf pieces
   never chosen.  Counts in *zero_seen the contexts where
   some piece had pmf 0, in *partial those where "none" had probability > 0.1. */
static int check_consistency(T *t, const Scene *s, LightSampler *ls, const char *what, int trials,
                             int draws, uint64_t seed, int *zero_seen, int *partial)
{
    int np = light_n_pieces(ls), trial;
    double *pmf = (double *)malloc(sizeof(double) * (size_t)np);
    double *count = (double *)malloc(sizeof(double) * (size_t)(np + 1));
    double *ex = (double *)malloc(sizeof(double) * (size_t)(np + 1));
    Rng r;
    int ok = 0;
    if (!pmf || !count || !ex) { test_failf(t, __FILE__, __LINE__, "out of memory"); goto done; }
    rng_seed(&r, seed, 3);
    for (trial = 0; trial < trials; trial++) {
        LightCtx c = random_ctx(s, &r);
        double sum = 0.0;
        int i, zeros = 0, none = 0;
        for (i = 0; i < np; i++) {
            float p = light_select_pmf(ls, &c, i);
            if (!(p >= 0.0f && p <= 1.0f)) {
                test_failf(t, __FILE__, __LINE__, "%s: pmf %g of piece %d", what, p, i);
                goto done;
            }
            pmf[i] = p;
            count[i] = 0.0;
            sum += p;
            zeros += p == 0.0f;
        }
        if (zeros) (*zero_seen)++;
        /* the pmfs sum to at most 1: the walk stops ("none") where both children of
           a node have importance 0 (a node's bound does not bound its children's) */
        if (!(sum < 1.0 + 1e-4)) {
            test_failf(t, __FILE__, __LINE__, "%s: pmfs sum to %.7g", what, sum);
            goto done;
        }
        if (sum > 0.0 && sum < 0.9) (*partial)++;
        for (i = 0; i < draws; i++) {
            float p;
            int e = light_select(ls, &c, rng_float(&r), &p, NULL);
            if (e < 0) { none++; continue; }
            if (e >= np || p != (float)pmf[e] || !(p > 0.0f)) {
                test_failf(t, __FILE__, __LINE__, "%s: light_select chose %d with %g, light_select_pmf %g",
                           what, e, p, e < np ? pmf[e] : -1.0);
                goto done;
            }
            count[e] += 1.0;
        }
        if (sum == 0.0) {
            if (none != draws) { test_failf(t, __FILE__, __LINE__, "%s: chose with pmf 0", what); goto done; }
            continue;
        }
        count[np] = none;                            /* i == np: "none", 1 - sum */
        for (i = 0; i <= np; i++) {
            ex[i] = (i < np ? pmf[i] : 1.0 - sum) * draws;
            if (ex[i] == 0.0 && count[i] > 0) {
                test_failf(t, __FILE__, __LINE__, "%s: %s chosen %g times with probability 0", what,
                           i < np ? "a piece" : "none", count[i]);
                goto done;
            }
        }
        if (!test_chi2_at(t, __FILE__, __LINE__, count, ex, np + 1, trials, NULL, "%s", what)) goto done;
    }
    ok = 1;
done:
    free(pmf);
    free(count);
    free(ex);
    return ok;
}

static void test_select_matches_pmf(T *t)
{
    static char buf[1 << 16];
    const char *spectra[4] = { SPIKY, BLUEISH, LOW_HALF, HIGH_HALF };
    Scene s;
    int i, v, zero_seen = 0, partial = 0;
    /* 64 small emitters of four spectra facing every way, and a split panel */
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    for (i = 0; i < 64; i++)
        add_quad(buf, sizeof buf, spectra[i % 4], 0.5f + (float)(i % 3),
                 v3(-0.8f + 0.2f * (i % 8), -0.8f + 0.2f * (float)(i / 8), 0.3f * (float)(i % 5) - 0.6f),
                 i % 3, (i / 3) % 2 ? 1 : -1, 0.04f);
    add_panel(buf, sizeof buf, LOW_HALF, 1.0f, 4);
    if (!test_load_scene(t, &s, buf)) return;
    for (v = 0; v < 3; v++) {
        static const char *names[3] = { "tree", "spectral-tree", "spectral-tree throughput-weighted" };
        LightSampler *ls = build(t, &s, v == 0 ? SEL_TREE : SEL_SPECTRAL_TREE, v == 2, 0);
        int ok;
        if (!ls) break;
        CHECK(t, light_n_pieces(ls) > s.n_emitters, "%s: the 32-triangle panel was not split", names[v]);
        ok = check_consistency(t, &s, ls, names[v], 40, 20000, 11 + (uint64_t)v, &zero_seen, &partial);
        light_sampler_free(ls);
        if (!ok) break;
    }
    scene_free(&s);
    CHECK(t, zero_seen > 10, "only %d contexts had a piece of pmf 0: zero-importance subtrees untested",
          zero_seen);
}

static float pmf_of(LightSampler *ls, Vec3 p, Vec3 n, float lambda, unsigned alive, int piece)
{
    LightCtx c;
    int j;
    memset(&c, 0, sizeof c);
    c.p = p;
    c.n = n;
    c.voxel = -1;
    c.alive = alive;
    c.hero_only = alive == 1u;
    for (j = 0; j < HERO_N; j++) { c.lambda[j] = lambda + 75.0f * j; c.beta[j] = 1.0f; }
    for (j = 0; j < HERO_N; j++) if (c.lambda[j] > 700.0f) c.lambda[j] -= 300.0f;
    return light_select_pmf(ls, &c, piece);
}

static void test_spectral_preference(T *t)
{
    static char buf[1 << 14];
    Scene s;
    LightSampler *tree, *spec;
    Vec3 p = v3(0.0f, -0.9f, 0.0f), n = v3(0, 1, 0);
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_quad(buf, sizeof buf, LOW_HALF, 4, v3(-0.5f, 0.99f, 0.0f), 1, -1, 0.2f);
    add_quad(buf, sizeof buf, HIGH_HALF, 4, v3(0.5f, 0.99f, 0.0f), 1, -1, 0.2f);
    if (!test_load_scene(t, &s, buf)) return;
    tree = build(t, &s, SEL_TREE, 0, 0);
    spec = build(t, &s, SEL_SPECTRAL_TREE, 0, 0);
    if (tree && spec) {
        float a450 = pmf_of(spec, p, n, 450.0f, 1u, 0), b450 = pmf_of(spec, p, n, 450.0f, 1u, 1);
        float a650 = pmf_of(spec, p, n, 650.0f, 1u, 0), b650 = pmf_of(spec, p, n, 650.0f, 1u, 1);
        float t450 = pmf_of(tree, p, n, 450.0f, 1u, 1), all = pmf_of(spec, p, n, 450.0f, 15u, 1);
        CHECK(t, a450 == 1.0f && b450 == 0.0f, "spectral tree at 450 nm: P = %g, %g (want 1, 0)", a450, b450);
        CHECK(t, a650 == 0.0f && b650 == 1.0f, "spectral tree at 650 nm: P = %g, %g (want 0, 1)", a650, b650);
        CHECK(t, t450 > 0.4f && t450 < 0.6f, "total-power tree: the dark emitter still has P = %g", t450);
        /* four wavelengths 75 nm apart span both halves: both possible */
        CHECK(t, all > 0.2f && all < 0.8f, "spectral tree, all alive: P = %g", all);
    }
    light_sampler_free(tree);
    light_sampler_free(spec);
    scene_free(&s);
}

/* A pmf query: piece `piece` at point p with normal n (500 nm, all four
   wavelengths alive). */
typedef struct { Vec3 p, n; int piece; } PmfQuery;

/* The pmfs of the queries q[0..m) under tree (v = 0) or spectral-tree (v = 1);
   0 when the build fails. */
static int tree_pmfs(T *t, const Scene *s, int v, const PmfQuery *q, int m, float *out)
{
    LightSampler *ls = build(t, s, v ? SEL_SPECTRAL_TREE : SEL_TREE, 0, 0);
    int i;
    if (!ls) return 0;
    for (i = 0; i < m; i++) out[i] = pmf_of(ls, q[i].p, q[i].n, 500.0f, 15u, q[i].piece);
    light_sampler_free(ls);
    return 1;
}

static void test_prefers_near(T *t)
{
    static char buf[1 << 14];
    Scene s;
    int v;
    float P[3];
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_quad(buf, sizeof buf, BLUEISH, 4, v3(-0.7f, 0.99f, 0.0f), 1, -1, 0.1f);   /* faces down */
    add_quad(buf, sizeof buf, BLUEISH, 4, v3(0.7f, 0.99f, 0.0f), 1, -1, 0.1f);    /* faces down */
    add_quad(buf, sizeof buf, BLUEISH, 40, v3(0.0f, 0.0f, 0.9f), 2, 1, 0.1f);     /* faces the back wall */
    if (!test_load_scene(t, &s, buf)) return;
    {   /* near, far, facing away */
        const PmfQuery q[3] = { { { -0.7f, 0.5f, 0.0f }, { 0, 1, 0 }, 0 },
                                { { -0.7f, 0.5f, 0.0f }, { 0, 1, 0 }, 1 },
                                { { 0, 0, 0 }, { 0, 0, 0 }, 2 } };
        for (v = 0; v < 2 && tree_pmfs(t, &s, v, q, 3, P); v++) {
            CHECK(t, P[0] > 0.9f && P[1] > 0.0f && P[1] < 0.1f,
                  "%s: near emitter P = %g, far one %g", v ? "spectral-tree" : "tree", P[0], P[1]);
            CHECK(t, P[2] == 0.0f, "%s: an emitter facing away has P = %g", v ? "spectral-tree" : "tree", P[2]);
        }
    }
    scene_free(&s);
    /* two identical small lamps 0.6 from the origin, both facing down: the
       origin lies straight below the first and 80 degrees off the second's
       normal, so the orientation bound (cos 80 = 0.17, widened by the lamps'
       2.7-degree bounding spheres) must prefer the first about 4:1 */
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_quad(buf, sizeof buf, BLUEISH, 4, v3(0.0f, 0.6f, 0.0f), 1, -1, 0.02f);
    add_quad(buf, sizeof buf, BLUEISH, 4, v3(0.6f * (float)sin(80.0 * SPECNEE_PI / 180.0),
                                             0.6f * (float)cos(80.0 * SPECNEE_PI / 180.0), 0.0f), 1, -1, 0.02f);
    if (!test_load_scene(t, &s, buf)) return;
    {
        const PmfQuery q[2] = { { { 0, 0, 0 }, { 0, 0, 0 }, 0 }, { { 0, 0, 0 }, { 0, 0, 0 }, 1 } };
        for (v = 0; v < 2 && tree_pmfs(t, &s, v, q, 2, P); v++)
            CHECK(t, P[1] > 0.0f && P[0] > 3.0f * P[1] && P[0] < 6.0f * P[1],
                  "%s: the lamp above P = %g, the one seen at 80 degrees %g (want about 4:1)",
                  v ? "spectral-tree" : "tree", P[0], P[1]);
    }
    scene_free(&s);
    /* inside a bounding sphere: a 1.8 m panel under the ceiling facing down
       (A, rho = 1.27) and a 1 m panel on the left wall facing +x (B, rho = 0.71),
       of equal power.  4 cm below A's centre (inside A's sphere, 1.24 m from
       B's centre) A must win clearly (imp = Phi / max(d, rho/4)^2: P(A) = 0.94;
       Phi / rho^2 inside would give 0.49); 4 cm in front of B's
       centre (inside both spheres) B must (0.98; Phi / rho^2 would give 0.76) */
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_quad(buf, sizeof buf, BLUEISH, 1.0f, v3(0.0f, 0.99f, 0.0f), 1, -1, 0.9f);
    add_quad(buf, sizeof buf, BLUEISH, 3.24f, v3(-0.99f, 0.2f, 0.0f), 0, 1, 0.5f);
    if (!test_load_scene(t, &s, buf)) return;
    {
        const PmfQuery q[2] = { { { 0.0f, 0.95f, 0.0f }, { 0, 0, 0 }, 0 },
                                { { -0.95f, 0.2f, 0.0f }, { 0, 0, 0 }, 1 } };
        for (v = 0; v < 2 && tree_pmfs(t, &s, v, q, 2, P); v++)
            CHECK(t, P[0] > 0.85f && P[0] < 1.0f && P[1] > 0.9f && P[1] < 1.0f,
                  "%s: inside the bounding spheres: P(ceiling panel) = %g below its centre (want > 0.85), "
                  "P(wall panel) = %g in front of its centre (want > 0.9)", v ? "spectral-tree" : "tree", P[0], P[1]);
    }
    scene_free(&s);
}

/* Build, then check pmfs and selection at random points. */
static int degenerate_case(T *t, const char *text, const char *what, int trials)
{
    Scene s;
    int v, zero_seen = 0, partial = 0, ok = 1;
    if (!test_load_scene(t, &s, text)) return 0;
    for (v = 0; v < 2 && ok; v++) {
        LightSampler *ls = build(t, &s, v ? SEL_SPECTRAL_TREE : SEL_TREE, 0, 0);
        char name[96];
        if (!ls) { ok = 0; break; }
        snprintf(name, sizeof name, "%s, %s", what, v ? "spectral-tree" : "tree");
        ok = check_consistency(t, &s, ls, name, trials, 2000, 5, &zero_seen, &partial);
        light_sampler_free(ls);
    }
    scene_free(&s);
    return ok;
}

static void test_degenerate(T *t)
{
    size_t cap = (size_t)10000 * 400 + 4096;
    char *buf = (char *)malloc(cap);
    int i;
    CHECK(t, buf != NULL, "out of memory");
    /* all emitters at one point: 40 identical tiny triangles */
    snprintf(buf, cap, "%s", camera16);
    for (i = 0; i < 40; i++) add_quad(buf, cap, i % 2 ? SPIKY : BLUEISH, 1, v3(0, 0, 0), 1, -1, 1e-3f);
    strcat(buf, "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ -1 -1 -1  1 -1 -1  0 -1 1 ]\n");
    if (!degenerate_case(t, buf, "all at one point", 20)) goto done;
    /* all coplanar: a 10 x 10 grid of lamps in the plane y = 0.5, half facing up */
    snprintf(buf, cap, "%s", camera16);
    for (i = 0; i < 100; i++)
        add_quad(buf, cap, i % 3 ? SPIKY : HIGH_HALF, 1, v3(-0.9f + 0.2f * (i % 10), 0.5f, -0.9f + 0.2f * (float)(i / 10)),
                 1, i % 2 ? 1 : -1, 0.05f);
    if (!degenerate_case(t, buf, "coplanar", 20)) goto done;
    /* one emitter (a one-node tree: P = 1 wherever, as for every strategy) */
    snprintf(buf, cap, "%s", camera16);
    add_quad(buf, cap, SPIKY, 1, v3(0, 0.9f, 0), 1, -1, 0.2f);
    strcat(buf, "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ -1 -1 -1  1 -1 -1  0 -1 1 ]\n");
    if (!degenerate_case(t, buf, "one emitter", 10)) goto done;
    /* 10,000 emitters in a 100 x 100 x 1 ceiling grid */
    snprintf(buf, cap, "%s", camera16);
    for (i = 0; i < 10000; i++)
        add_quad(buf, cap, i % 2 ? SPIKY : BLUEISH, 1, v3(-1.0f + 0.02f * (i % 100), 1.0f, -1.0f + 0.02f * (float)(i / 100)),
                 1, -1, 0.005f);
    strcat(buf, "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ -1 -1 -1  1 -1 -1  0 -1 1 ]\n");
    degenerate_case(t, buf, "10,000 emitters", 3);
done:
    free(buf);
}

/* The large panel (128 triangles) split into clusters converges to uniform. */
static void test_mesh_split_unbiased(T *t)
{
    static char buf[1 << 15];
    static Tiles ref, m;
    Scene s;
    RenderOptions o;
    int v;
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_panel(buf, sizeof buf, SPIKY, 1.0f, 8);
    add_quad(buf, sizeof buf, BLUEISH, 3, v3(0.5f, 0.99f, 0.3f), 1, -1, 0.1f);
    strcat(buf, "AttributeBegin\n Translate 0 -0.6 0\n"
                " Material \"dielectric\" \"float cauchyA\" [ 1.5 ] \"float cauchyB\" [ 0.03 ] \"float roughness\" [ 0.04 ]\n"
                " Shape \"sphere\" \"float radius\" [ 0.3 ]\nAttributeEnd\n");
    if (!test_load_scene(t, &s, buf)) return;
    render_options_default(&o);
    o.spp = test_scaled(24, 4);
    o.seed = 3;
    o.sel.strategy = SEL_UNIFORM;
    if (!test_render_tiles(t, &s, &o, 8, 2, &ref)) goto done;
    for (v = 0; v < 3; v++) {
        static const char *names[3] = { "tree (split)", "spectral-tree (split)", "spectral-tree (one leaf)" };
        memset(&o.sel, 0, sizeof o.sel);
        o.sel.strategy = v ? SEL_SPECTRAL_TREE : SEL_TREE;
        o.sel.no_split = v == 2;
        if (!test_render_tiles(t, &s, &o, 8, 2, &m)) goto done;
        if (!test_tiles_agree(t, &m, &ref, 1e-4, names[v])) goto done;
    }
done:
    scene_free(&s);
}

/* light_piece_of names the cluster that holds a hit, and sampling a cluster
   stays on its triangles: the mean of 1/pdf over cluster samples is the
   cluster's solid angle estimate, consistent with light_pdf_sa. */
static void test_mesh_split_pmf(T *t)
{
    static char buf[1 << 15];
    Scene s;
    LightSampler *ls;
    Rng r;
    int np, i, k, checked = 0;
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_panel(buf, sizeof buf, SPIKY, 1.0f, 8);
    if (!test_load_scene(t, &s, buf)) return;
    ls = build(t, &s, SEL_SPECTRAL_TREE, 0, 0);
    if (!ls) { scene_free(&s); return; }
    np = light_n_pieces(ls);
    CHECK(t, np >= 128 / LIGHT_CLUSTER_TRIS && np <= 64, "128 triangles in %d clusters", np);
    rng_seed(&r, 9, 9);
    for (i = 0; i < np; i++)
        for (k = 0; k < 20; k++) {
            EmitterSample es;
            Ray ray;
            HitRecord h;
            SurfacePoint sp;
            Vec3 u = rng_vec3(&r), ref = v3(0.2f + 0.5f * u.x, -0.5f + u.y, -0.5f + u.z);
            float pdf;
            u = rng_vec3(&r);
            if (!light_sample(ls, i, ref, v3(0.0f, 0.0f, 0.0f), (const float[3]){ u.x, u.y, u.z }, &es)) continue;
            CHECK(t, light_piece_emitter(ls, i) == 0, "cluster %d belongs to emitter %d", i, light_piece_emitter(ls, i));
            ray.o = ref;
            ray.d = es.wi;
            ray.tmax = es.dist * 1.001f;
            if (!bvh_intersect(&s.bvh, &s, &ray, &h)) continue;
            scene_surface_point(&s, &ray, &h, &sp);
            if (s.shapes[sp.shape].emitter != 0) continue;
            CHECK(t, light_piece_of(ls, 0, sp.prim) == i || fabsf(h.t - es.dist) > 1e-3f,
                  "sample of cluster %d hit cluster %d", i, light_piece_of(ls, 0, sp.prim));
            pdf = light_pdf_sa(ls, i, ref, v3(0.0f, 0.0f, 0.0f), sp.p, sp.ng, sp.prim);
            CHECK(t, fabsf(pdf - es.pdf_sa) <= 1e-3f * es.pdf_sa, "pdf at the hit %g, sampled %g", pdf, es.pdf_sa);
            checked++;
        }
    CHECK(t, checked > np * 10, "only %d of %d samples were found again by a ray", checked, np * 20);
    light_sampler_free(ls);
    scene_free(&s);
}

/* The emitters' radiance belongs to the render: two samplers over one
   const Scene, for 400-700 and 360-830 nm, each normalise every emitter so that
   sum_{1 nm over its own range} ybar Le = scale (pbrt-v4), light_Le returns that
   radiance towards the front (0 behind a one-sided emitter), and the Scene's
   emitters are byte for byte what the file gave. */
static void test_per_render_radiance(T *t)
{
    static char buf[1 << 14];
    static Emitter before[5];
    Scene s;
    LightSampler *ls[2];
    int e, k, lam;
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    add_quad(buf, sizeof buf, SPIKY, 2, v3(-0.5f, 0.99f, 0.0f), 1, -1, 0.2f);
    add_quad(buf, sizeof buf, "[ 380 1 400 1 700 0.2 720 3 ]", 3, v3(0.5f, 0.99f, 0.0f), 1, -1, 0.2f);
    add_quad(buf, sizeof buf, LOW_HALF, 5, v3(0.0f, 0.99f, 0.5f), 1, -1, 0.2f);
    /* the same spectrum at another scale (its own radiance), then once more (the
       sampler may share that radiance between emitters 3 and 4) */
    add_quad(buf, sizeof buf, LOW_HALF, 9, v3(0.0f, 0.99f, -0.5f), 1, -1, 0.2f);
    add_quad(buf, sizeof buf, LOW_HALF, 9, v3(0.5f, 0.99f, -0.5f), 1, -1, 0.2f);
    if (!test_load_scene(t, &s, buf)) return;
    memcpy(before, s.emitters, sizeof before);
    for (k = 0; k < 2; k++) {
        SelOptions o;
        Error err;
        memset(&o, 0, sizeof o);
        o.strategy = k ? SEL_SPECTRAL_TREE : SEL_POWER;
        o.lo_nm = k ? (float)SPEC_MIN : LAMBDA_LO;
        o.hi_nm = k ? (float)SPEC_MAX : LAMBDA_HI;
        ls[k] = light_sampler_build(&s, &o, &err);
        CHECK(t, ls[k] != NULL, "%s", err.msg);
    }
    for (k = 0; k < 2; k++)
        for (e = 0; e < 5; e++) {
            int lo = k ? SPEC_MIN : (int)LAMBDA_LO, hi = k ? SPEC_MAX : (int)LAMBDA_HI;
            double Y = 0.0;
            Vec3 down = v3(0, -1, 0);
            for (lam = lo; lam <= hi; lam++) {
                float xyz[3];
                cie_xyz((float)lam, xyz);
                Y += (double)xyz[1] * light_Le(ls[k], e, down, down, (float)lam);
            }
            CHECK(t, fabs(Y - s.emitters[e].scale) < 1e-4 * s.emitters[e].scale,
                  "range %d-%d nm, emitter %d: sum ybar Le = %g, want scale %g", lo, hi, e, Y, s.emitters[e].scale);
            CHECK(t, light_Le(ls[k], e, down, v3(0, 1, 0), 500.0f) == 0.0f, "light from behind a one-sided emitter");
        }
    /* emitter 1 emits outside 400-700 nm: its wide-range radiance inside is lower */
    CHECK(t, light_Le(ls[1], 1, v3(0, -1, 0), v3(0, -1, 0), 550.0f) <
             light_Le(ls[0], 1, v3(0, -1, 0), v3(0, -1, 0), 550.0f), "the wide range changes nothing");
    light_sampler_free(ls[0]);
    light_sampler_free(ls[1]);
    CHECK(t, memcmp(before, s.emitters, sizeof before) == 0, "building a sampler changed the scene's emitters");
    scene_free(&s);
}

/* 48 small lamps facing every way, a third of them two-sided (16), and a
   4 x 4 panel that the trees split. */
static int load_mixed_lamps(T *t, Scene *s, char *buf, size_t cap)
{
    int i, k;
    snprintf(buf, cap, "%s%s", camera16, test_box_walls);
    for (i = 0; i < 48; i++) {
        size_t n;
        Vec3 c = v3(-0.8f + 0.3f * (i % 6), -0.7f + 0.2f * (float)(i / 6), 0.35f * (float)(i % 5) - 0.7f);
        add_quad(buf, cap, i % 2 ? SPIKY : BLUEISH, 1, c, i % 3, (i / 3) % 2 ? 1 : -1, 0.04f);
        if (i % 3 == 0) {                            /* make it two-sided */
            n = strlen(buf);
            while (n > 0 && strncmp(buf + n, "\"diffuse\"", 9) != 0) n--;
            memmove(buf + n + 9 + 25, buf + n + 9, strlen(buf + n + 9) + 1);
            memcpy(buf + n + 9, " \"bool twosided\" [ true ]", 25);
        }
    }
    add_panel(buf, cap, LOW_HALF, 1.0f, 4);
    if (!test_load_scene(t, s, buf)) return 0;
    for (i = 0, k = 0; i < s->n_emitters; i++) k += s->emitters[i].twosided;
    if (k != 16) {
        scene_free(s);
        test_failf(t, __FILE__, __LINE__, "%d two-sided lamps, want 16", k);
        return 0;
    }
    return 1;
}

/* Every piece with a point that faces the point (one-sided: on its front
   side; two-sided: either side) has P > 0 under the total-power tree, at 300
   random points in the box; adds to *checked the facing pieces seen. */
static void check_conservative(T *t, const Scene *s, uint64_t seed, int *checked)
{
    LightSampler *ls;
    Rng r;
    int k;
    ls = build(t, s, SEL_TREE, 0, 0);
    if (!ls) return;
    rng_seed(&r, seed, 4);
    for (k = 0; k < 300; k++) {
        LightCtx c;
        int piece, j;
        memset(&c, 0, sizeof c);
        c.p = v3_sub(v3_mul(rng_vec3(&r), 1.9f), v3(0.95f, 0.95f, 0.95f));
        c.voxel = -1;
        c.alive = 15u;
        for (j = 0; j < HERO_N; j++) { c.lambda[j] = 420.0f + 70.0f * j; c.beta[j] = 1.0f; }
        for (piece = 0; piece < light_n_pieces(ls); piece++) {
            int e = light_piece_emitter(ls, piece), faces = 0;
            for (j = 0; j < 8 && !faces; j++) {
                EmitterSample es;
                Vec3 to_p;
                float d;
                const Vec3 u = rng_vec3(&r);
                if (!light_sample(ls, piece, c.p, c.n, (const float[3]){ u.x, u.y, u.z }, &es)) continue;
                to_p = v3_mul(es.wi, -1.0f);
                d = v3_dot(es.n, to_p);
                faces = s->emitters[e].twosided ? fabsf(d) > 1e-3f : d > 1e-3f;
            }
            if (!faces) continue;
            (*checked)++;
            CHECK(t, light_select_pmf(ls, &c, piece) > 0.0f,
                  "piece %d (emitter %d%s) faces (%g %g %g) but has P = 0", piece, e,
                  s->emitters[e].twosided ? ", two-sided" : "", c.p.x, c.p.y, c.p.z);
        }
    }
    light_sampler_free(ls);
}

/* The bounds are conservative: no merged cone or box loses an emitter.  On
   the mixed lamps (facing every way, a third two-sided, a split panel), and
   on 36 lamps in a grid under the ceiling, all facing down, every other one
   two-sided: those light the points above them through their backs, so a
   node that merges one-sided and two-sided lamps must be two-sided; on 16
   tents (two faces at a right angle) whose light also goes behind the plane
   that bounds their box on their axis' far side; and on roofs and
   three-faced pieces (node_behind's plane from every vertex, and none for
   cones over 180 degrees). */
static void test_conservative(T *t)
{
    static char buf[1 << 16];
    Scene s;
    int i, checked = 0;
    if (!load_mixed_lamps(t, &s, buf, sizeof buf)) return;
    check_conservative(t, &s, 21, &checked);
    scene_free(&s);
    CHECK(t, checked > 1000, "only %d facing pieces checked", checked);
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    for (i = 0; i < 36; i++) {
        size_t n;
        add_quad(buf, sizeof buf, SPIKY, 1, v3(-0.75f + 0.3f * (i % 6), 0.2f, -0.75f + 0.3f * (float)(i / 6)), 1, -1,
                 0.04f);
        if (i % 2 == 0) continue;                    /* one-sided and two-sided in turn */
        n = strlen(buf);
        while (n > 0 && strncmp(buf + n, "\"diffuse\"", 9) != 0) n--;
        memmove(buf + n + 9 + 25, buf + n + 9, strlen(buf + n + 9) + 1);
        memcpy(buf + n + 9, " \"bool twosided\" [ true ]", 25);
    }
    if (!test_load_scene(t, &s, buf)) return;
    checked = 0;
    check_conservative(t, &s, 22, &checked);
    scene_free(&s);
    CHECK(t, checked > 1000, "two-sided grid: only %d facing pieces checked", checked);
    /* 16 tents, whose cones are wider than 90 degrees: no plane bounds where
       their light goes, so "behind the box" must not apply to them */
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    for (i = 0; i < 16; i++) add_tent(buf, sizeof buf, v3(-0.7f + 0.4f * (i % 4), -0.5f + 0.3f * (float)(i / 4), -0.6f + 0.4f * (float)(i / 4)), 0.05f);
    if (!test_load_scene(t, &s, buf)) return;
    checked = 0;
    check_conservative(t, &s, 23, &checked);
    scene_free(&s);
    CHECK(t, checked > 1000, "tents: only %d facing pieces checked", checked);
    /* 8 roofs (the plane must come from every vertex) and 8 small
       three-faced pieces by the +x wall (cones over 180 degrees: no plane at
       all; points far along -x, which their 110 and 250 degree faces light,
       would be behind one) */
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    for (i = 0; i < 8; i++) {
        add_roof(buf, sizeof buf, v3(-0.6f + 0.4f * (float)(i % 4), -0.3f + 0.4f * (float)(i / 4), -0.5f + 0.3f * (float)(i % 3)), 0.05f);
        add_three_faced(buf, sizeof buf, v3(0.8f, -0.6f + 0.4f * (float)(i % 4), -0.5f + 0.3f * (float)(i / 2)), 0.005f);
    }
    if (!test_load_scene(t, &s, buf)) return;
    checked = 0;
    check_conservative(t, &s, 24, &checked);
    scene_free(&s);
    CHECK(t, checked > 1000, "roofs and three-faced pieces: only %d facing pieces checked", checked);
}

/* A context at p, no normal, four alive wavelengths. */
static LightCtx ctx_at(Vec3 p)
{
    LightCtx c;
    int j;
    memset(&c, 0, sizeof c);
    c.p = p;
    c.voxel = -1;
    c.alive = 15u;
    for (j = 0; j < HERO_N; j++) { c.lambda[j] = 430.0f + 70.0f * j; c.beta[j] = 1.0f; }
    return c;
}

/* The bounds stay conservative for lamps facing any way: 24 random scenes of
   4 to 63 one-sided quads in groups of four around a random direction (the
   normals of a group equal, 0.05 apart, or 0.8 apart; the quads spread
   through the box or crowded into a slab), 300 random points each in and
   around them: every piece with a point that faces the point has P > 0,
   under both trees (behind the box, with and without its slack, and the
   cone bound). */
static void test_conservative_random(T *t)
{
    static char buf[1 << 16];
    int trial, bad = 0, checked = 0;
    for (trial = 0; trial < 24; trial++) {
        Rng r;
        Scene s;
        size_t len;
        int i, nq, st;
        Vec3 base = v3(0, 1, 0);
        const float spread = trial % 3 == 0 ? 0.0f : trial % 3 == 1 ? 0.05f : 0.8f;
        rng_seed(&r, 4000 + (uint64_t)trial, 7);
        len = (size_t)snprintf(buf, sizeof buf, "%s", camera16);
        nq = 4 + (int)(rng_float(&r) * 60);
        for (i = 0; i < nq; i++) {
            Vec3 n, t1, t2, c, d;
            float h = 0.02f + 0.08f * rng_float(&r);
            int k;
            if (i % 4 == 0) {
                d = v3_sub(v3_mul(rng_vec3(&r), 2.0f), v3(1.0f, 1.0f, 1.0f));
                base = v3_dot(d, d) > 1e-4f ? v3_norm(d) : v3(0, 1, 0);
            }
            d = v3_sub(v3_mul(rng_vec3(&r), 2.0f), v3(1.0f, 1.0f, 1.0f));
            n = v3_norm(v3_add(base, v3_mul(d, spread)));
            t1 = v3_norm(v3_cross(n, fabsf(n.x) < 0.9f ? v3(1, 0, 0) : v3(0, 1, 0)));
            t2 = v3_cross(n, t1);
            c = v3_sub(v3_mul(rng_vec3(&r), 1.6f), v3(0.8f, 0.8f, 0.8f));
            if (trial % 2) c.x *= 0.2f;                  /* crowded into a slab */
            len += (size_t)snprintf(buf + len, sizeof buf - len,
                                    "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" %s \"float scale\" [ 1 ]\n"
                                    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [", SPIKY);
            for (k = 0; k < 4; k++) {                   /* counter-clockwise about n */
                Vec3 p = v3_add(c, v3_add(v3_mul(t1, k == 0 || k == 3 ? -h : h), v3_mul(t2, k < 2 ? -h : h)));
                len += (size_t)snprintf(buf + len, sizeof buf - len, " %.9g %.9g %.9g", p.x, p.y, p.z);
            }
            len += (size_t)snprintf(buf + len, sizeof buf - len, " ]\nAttributeEnd\n");
        }
        if (!test_load_scene(t, &s, buf)) return;
        for (st = 0; st < 2; st++) {
            LightSampler *ls = build(t, &s, st ? SEL_SPECTRAL_TREE : SEL_TREE, 0, 0);
            int k;
            if (!ls) break;
            for (k = 0; k < 300; k++) {
                LightCtx c = ctx_at(v3_sub(v3_mul(rng_vec3(&r), 2.4f), v3(1.2f, 1.2f, 1.2f)));
                int piece, j;
                for (piece = 0; piece < light_n_pieces(ls); piece++) {
                    int faces = 0;
                    for (j = 0; j < 8 && !faces; j++) {
                        EmitterSample es;
                        const Vec3 u = rng_vec3(&r);
                        if (!light_sample(ls, piece, c.p, c.n, (const float[3]){ u.x, u.y, u.z }, &es)) continue;
                        faces = v3_dot(es.n, v3_mul(es.wi, -1.0f)) > 1e-3f;
                    }
                    if (!faces) continue;
                    checked++;
                    if (!(light_select_pmf(ls, &c, piece) > 0.0f) && bad++ < 3)
                        test_failf(t, __FILE__, __LINE__, "scene %d, %s: piece %d faces (%g %g %g) but has P = 0",
                                   trial, st ? "spectral-tree" : "tree", piece, c.p.x, c.p.y, c.p.z);
                }
            }
            light_sampler_free(ls);
        }
        scene_free(&s);
    }
    CHECK(t, bad == 0 && checked > 100000, "%d of %d facing pieces had P = 0", bad, checked);
}

/* The four children of a node are evaluated side by side (SSE2) by code that
   mirrors the scalar importance step for step: at random contexts - points in
   and around the box, inside the nodes' bounding spheres and far outside, on
   a lamp's centre, with and without a normal, wavelengths from 300 to 700 nm
   (the UV bins too), one or four alive, throughput-weighted or not - both
   give the same bits for every child of every node, under both trees, on the
   mixed lamps (one- and two-sided, facing every way, a split panel) and on
   40 lamps at one point. */
static void test_simd_matches_scalar(T *t)
{
    static char buf[1 << 16];
    Scene s[2];
    int sc, v, k, lanes = 0, bad = 0, positive = 0;
    Rng r;
    if (!load_mixed_lamps(t, &s[0], buf, sizeof buf)) return;
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    for (k = 0; k < 40; k++) add_quad(buf, sizeof buf, k % 2 ? SPIKY : BLUEISH, 1, v3(0, 0, 0), k % 3, k % 2 ? 1 : -1, 1e-3f);
    if (!test_load_scene(t, &s[1], buf)) { scene_free(&s[0]); return; }
    rng_seed(&r, 77, 3);
    for (sc = 0; sc < 2; sc++)
        for (v = 0; v < 3; v++) {
            LightSampler *ls = build(t, &s[sc], v == 0 ? SEL_TREE : SEL_SPECTRAL_TREE, v == 2, 0);
            if (!ls) continue;
            for (k = 0; k < 400; k++) {
                LightCtx c = random_ctx(&s[sc], &r);
                int n, j, m;
                if (k % 4 == 1) c.p = v3_mul(c.p, 1e-4f);                /* near the centre */
                if (k % 8 == 2) c.p = v3_mul(c.p, 1e6f);                 /* far away */
                if (k % 8 == 3) c.p = v3(0.0f, 0.0f, 0.0f);              /* on a centre */
                for (j = 0; j < HERO_N; j++)
                    if (k % 3 == 0) c.lambda[j] = 300.0f + 400.0f * rng_float(&r);   /* UV bins */
                n = light_tree_simd_mismatches(ls, &c, &m);
                bad += n;
                lanes += m;
                if (light_select_pmf(ls, &c, 0) > 0.0f) positive++;
                if (n) {
                    test_failf(t, __FILE__, __LINE__, "scene %d, %s: %d of %d children differ at (%g %g %g)",
                               sc, v == 0 ? "tree" : "spectral-tree", n, m, c.p.x, c.p.y, c.p.z);
                    break;
                }
            }
            light_sampler_free(ls);
        }
    scene_free(&s[0]);
    scene_free(&s[1]);
    CHECK(t, bad == 0 && lanes > 10000 && positive > 100, "%d of %d children differ (%d contexts light piece 0)",
          bad, lanes, positive);
}

/* The 4-wide tree's power per 5 nm bin of an interior lane is summed from the
   lanes of its own node (lighttree.c quad_bins_up, the binary build's sums, with
   no per-node copy): every lane's bins and the root's equal the sum of the leaf
   lanes below them (relative 1e-5), on the mixed lamps and on 40 lamps of two
   spectra at one point, under both trees. */
static void test_bins_sum(T *t)
{
    static char buf[1 << 16];
    Scene s[2];
    int sc, v, lanes = 0, bad = 0;
    if (!load_mixed_lamps(t, &s[0], buf, sizeof buf)) return;
    snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
    for (v = 0; v < 40; v++) add_quad(buf, sizeof buf, v % 2 ? SPIKY : BLUEISH, 1, v3(0, 0, 0), v % 3, v % 2 ? 1 : -1, 1e-3f);
    if (!test_load_scene(t, &s[1], buf)) { scene_free(&s[0]); return; }
    for (sc = 0; sc < 2; sc++)
        for (v = 0; v < 2; v++) {
            LightSampler *ls = build(t, &s[sc], v == 0 ? SEL_TREE : SEL_SPECTRAL_TREE, 0, 0);
            int m;
            if (!ls) continue;
            bad += light_tree_bins_mismatches(ls, &m);
            lanes += m;
            light_sampler_free(ls);
        }
    scene_free(&s[0]);
    scene_free(&s[1]);
    CHECK(t, bad == 0 && lanes > 40, "%d of %d lanes' bins are not the sums of their leaves'", bad, lanes);
}

/* More distinct radiances than the build keeps bin means for (lighttree.c
   LE_MEANS, 64): 64 red lamps of distinct scales, then 6 blue ones, whose means
   take the red ones' rows.  Seen from the centre of their ring, every blue lamp
   is likelier at 450 nm than at 650 nm under the spectral tree and every red one
   the other way round. */
static void test_bins_many_radiances(T *t)
{
    static char buf[1 << 16];
    Scene s;
    LightSampler *ls;
    int i, w, wrong = 0;
    snprintf(buf, sizeof buf, "%s", camera16);
    for (i = 0; i < 70; i++) {
        size_t len = strlen(buf);
        double a = 2.0 * SPECNEE_PI * i / 70.0;
        snprintf(buf + len, sizeof buf - len, "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" %s "
                 "\"float scale\" %g\nTranslate %g %g 0\nShape \"sphere\" \"float radius\" 0.05\nAttributeEnd\n",
                 i < 64 ? "[ 1 0 0 ]" : "[ 0 0 1 ]", 1.0 + 0.01 * i, 2.0 * cos(a), 2.0 * sin(a));
    }
    if (!test_load_scene(t, &s, buf)) return;
    ls = build(t, &s, SEL_SPECTRAL_TREE, 0, 0);
    if (!ls) { scene_free(&s); return; }
    for (i = 0; i < s.n_emitters; i++) {
        float p[2];
        for (w = 0; w < 2; w++) {
            LightCtx c;
            memset(&c, 0, sizeof c);
            c.p = v3(0.0f, 0.0f, 0.0f);
            c.voxel = light_voxel(ls, c.p);
            c.alive = 1u;
            c.hero_only = 1;
            c.lambda[0] = w == 0 ? 450.0f : 650.0f;
            c.beta[0] = 1;
            p[w] = light_select_pmf(ls, &c, i);
        }
        if (i < 64 ? !(p[1] > p[0]) : !(p[0] > p[1])) wrong++;
    }
    CHECK(t, s.n_emitters == 70 && wrong == 0, "%d of 70 lamps have the other colour's bins", wrong);
    light_sampler_free(ls);
    scene_free(&s);
}

/* The spectral tree's root power per 5 nm bin from 300 nm up is the sum over
   the lamps of pi A times the bin's mean of each lamp's Le (spec_band_mean, the
   trapezoid rule over the table), relative 1e-5: four sphere lamps of spiky,
   bluish, rgb and UV-emitting spectra. */
static void test_root_bins_are_band_means(T *t)
{
    static char buf[1 << 14];
    /* the last one also emits in the UV (300-400 nm: the bins fluorescence reads) */
    static const char *const L[4] = { "\"spectrum L\" " SPIKY, "\"spectrum L\" " BLUEISH, "\"rgb L\" [ 2 0.3 0.1 ]",
                                      "\"spectrum L\" [ 300 0.5  350 2  400 1  700 1 ]" };
    Scene s;
    LightSampler *ls;
    float got[128];
    int i, b, nb, bad = 0;
    snprintf(buf, sizeof buf, "%s", camera16);
    for (i = 0; i < 4; i++) {
        size_t len = strlen(buf);
        snprintf(buf + len, sizeof buf - len, "AttributeBegin\nAreaLightSource \"diffuse\" %s\n"
                 "Translate %d 1 0\nShape \"sphere\" \"float radius\" 0.%d\nAttributeEnd\n", L[i], i - 1, i + 1);
    }
    if (!test_load_scene(t, &s, buf)) return;
    ls = build(t, &s, SEL_SPECTRAL_TREE, 0, 0);
    if (!ls) { scene_free(&s); return; }
    nb = light_tree_root_bins(ls, got, 128);
    CHECK(t, nb == 80, "%d bins, not 80 (300-700 nm)", nb);
    for (b = 0; b < nb && b < 128; b++) {
        double want = 0.0;
        for (i = 0; i < s.n_emitters; i++) {
            Spectrum Le;
            light_spectrum(ls, i, &Le);
            want += SPECNEE_PI * s.emitters[i].area * spec_band_mean(&Le, 300 + 5 * b, 5);
        }
        if (!(fabs(got[b] - want) <= 1e-5 * want + 1e-30)) {
            if (!bad) test_failf(t, __FILE__, __LINE__, "bin %d: %g, want %g", b, got[b], want);
            bad++;
        }
    }
    CHECK(t, bad == 0, "%d of %d root bins are not the lamps' band means", bad, nb);
    light_sampler_free(ls);
    scene_free(&s);
}

/* p rotated by 33 degrees about the axis (1, 2, 3) through the origin, as the
   scene directive "Rotate 33 1 2 3" turns a point (Rodrigues' formula); rot = 0:
   p itself. */
static Vec3 rotate33(Vec3 p, int rot)
{
    const double a = 33.0 * SPECNEE_PI / 180.0, c = cos(a), sn = sin(a), l = sqrt(14.0);
    const double k[3] = { 1.0 / l, 2.0 / l, 3.0 / l };
    double v[3], kv, x[3];
    int i;
    if (!rot) return p;
    v[0] = p.x; v[1] = p.y; v[2] = p.z;
    kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    x[0] = k[1] * v[2] - k[2] * v[1];                  /* k x v */
    x[1] = k[2] * v[0] - k[0] * v[2];
    x[2] = k[0] * v[1] - k[1] * v[0];
    for (i = 0; i < 3; i++) x[i] = v[i] * c + x[i] * sn + k[i] * kv * (1.0 - c);
    return v3((float)x[0], (float)x[1], (float)x[2]);
}

/* Behind the box: 16 small lamps in a plane, all facing down.  A point just
   above the plane is inside the bounding sphere of the lamps (and of most
   nodes), where no angle can be bounded, yet nothing can light it: the walk
   must find I = 0 at the root (light_select -1, every pmf 0) instead of
   sampling a lamp that sends nothing there.  Below the plane every lamp
   keeps P > 0.  Both trees; the lamps axis-aligned, and turned by 33 degrees
   about (1, 2, 3), where the normals of their triangles differ in the last
   bits (theta_o > 0, so the plane needs its slack, node_behind). */
static void test_behind(T *t)
{
    static char buf[1 << 15];
    Scene s;
    int i, st, rot, above = 0, below = 0;
    for (rot = 0; rot < 2; rot++) {
        snprintf(buf, sizeof buf, "%s%s%s", camera16, test_box_walls, rot ? "AttributeBegin\nRotate 33 1 2 3\n" : "");
        for (i = 0; i < 16; i++)
            add_quad(buf, sizeof buf, SPIKY, 1, v3(-0.45f + 0.3f * (i % 4), 0.2f, -0.45f + 0.3f * (float)(i / 4)), 1,
                     -1, 0.04f);
        if (rot) strncat(buf, "AttributeEnd\n", sizeof buf - strlen(buf) - 1);
        if (!test_load_scene(t, &s, buf)) return;
        for (st = 0; st < 2; st++) {
            LightSampler *ls = build(t, &s, st ? SEL_SPECTRAL_TREE : SEL_TREE, 0, 0);
            Rng r;
            int k;
            if (!ls) continue;
            rng_seed(&r, 31, (uint64_t)(2 * rot + st));
            for (k = 0; k < 200; k++) {
                const Vec3 u = rng_vec3(&r);
                Vec3 q = v3(-0.4f + 0.8f * u.x, 0.2f + (rot ? 0.01f : 0.0001f) + 0.1f * u.y, -0.4f + 0.8f * u.z);
                LightCtx c = ctx_at(rotate33(q, rot));
                float pmf = 1.0f, sum = 0.0f;
                int piece = light_select(ls, &c, rng_float(&r), &pmf, NULL), j;
                for (j = 0; j < light_n_pieces(ls); j++) sum += light_select_pmf(ls, &c, j);
                above += piece < 0 && pmf == 0.0f && sum == 0.0f;
                q.y = 0.2f - (q.y - 0.2f);               /* the mirror point below the lamps */
                c.p = rotate33(q, rot);
                for (j = 0, sum = 0.0f; j < light_n_pieces(ls); j++) {
                    float pj = light_select_pmf(ls, &c, j);
                    below += pj > 0.0f;
                    sum += pj;
                }
                CHECK(t, fabsf(sum - 1.0f) < 1e-4f, "%s%s: pmfs below the lamps sum to %g",
                      st ? "spectral-tree" : "tree", rot ? ", turned" : "", sum);
            }
            light_sampler_free(ls);
        }
        scene_free(&s);
    }
    CHECK(t, above == 800, "%d of 800 points above down-facing lamps found nothing to sample", above);
    CHECK(t, below == 800 * 16, "%d of %d lamps had P > 0 from below", below, 800 * 16);
}

/* Append "normal N" [ n n n n ] to the last quad of buf (add_quad's four vertices). */
static void quad_normals(char *buf, size_t cap, Vec3 n)
{
    char *at = strstr(buf + strlen(buf) - 160, "\"point3 P\""), tail[256];
    if (!at) return;
    snprintf(tail, sizeof tail, "%s", at);
    snprintf(at, cap - (size_t)(at - buf), "\"normal N\" [ %g %g %g %g %g %g %g %g %g %g %g %g ] %s",
             n.x, n.y, n.z, n.x, n.y, n.z, n.x, n.y, n.z, n.x, n.y, n.z, tail);
}

/* On the lamp: a point on a one-sided lamp A (facing down, half-size 0.2 at
   y = 0.2) with a lamp B below it facing up.  A cannot light a point of its own
   plane, so under both trees A's pieces have P = 0 there and B takes all of it
   (a point inside A's bounding sphere, where no angle is bounded: without the
   plane moved forward by the margin, node_behind, A took most of it).  The same
   when the lamps have "normal N" that agree with their winding (the cone of a
   lamp with normals, normals_agree); where A's normals point the other way its
   cone must stay full: from 0.05 above and below A, A keeps P > 0. */
static void test_on_the_lamp(T *t)
{
    static char buf[1 << 15];
    Scene s;
    int variant, st, k, on = 0, near = 0;
    for (variant = 0; variant < 3; variant++) {
        snprintf(buf, sizeof buf, "%s%s", camera16, test_box_walls);
        add_quad(buf, sizeof buf, SPIKY, 1, v3(0.0f, 0.2f, 0.0f), 1, -1, 0.2f);
        if (variant) quad_normals(buf, sizeof buf, v3(0.0f, variant == 1 ? -1.0f : 1.0f, 0.0f));
        add_quad(buf, sizeof buf, SPIKY, 1, v3(0.0f, -0.6f, 0.0f), 1, 1, 0.2f);
        if (variant) quad_normals(buf, sizeof buf, v3(0.0f, 1.0f, 0.0f));
        if (!test_load_scene(t, &s, buf)) return;
        for (st = 0; st < 2; st++) {
            LightSampler *ls = build(t, &s, st ? SEL_SPECTRAL_TREE : SEL_TREE, 0, 0);
            Rng r;
            if (!ls) continue;
            rng_seed(&r, 77, (uint64_t)(2 * variant + st));
            for (k = 0; k < 100; k++) {
                LightCtx c = ctx_at(v3(-0.19f + 0.38f * rng_float(&r), 0.2f, -0.19f + 0.38f * rng_float(&r)));
                float pa = 0.0f, pb = 0.0f;
                int j;
                c.n = v3(0.0f, -1.0f, 0.0f);
                if (variant == 2) c.p.y += k % 2 ? 0.05f : -0.05f;
                for (j = 0; j < light_n_pieces(ls); j++) {
                    float pj = light_select_pmf(ls, &c, j);
                    if (light_piece_emitter(ls, j) == 0) pa += pj;
                    else pb += pj;
                }
                if (variant < 2) on += pa == 0.0f && fabsf(pb - 1.0f) < 1e-5f;
                else near += pa > 0.0f;
            }
            light_sampler_free(ls);
        }
        scene_free(&s);
    }
    CHECK(t, on == 400, "%d of 400 points on a lamp gave it P = 0 and the other lamp P = 1", on);
    CHECK(t, near == 200, "%d of 200 points by a lamp whose normals disagree kept its P > 0", near);
}

/* A spot light keeps the margin behind its plane: its cone reaches 90 degrees
   (coneangle 90, conedelta 45: slack 0), and a point 1e-5 in front of the plane
   through it, within the margin, still gets a little of its light, which no
   BSDF sample can find: P > 0 there under both trees (node_behind moves the
   plane forward only for nodes of area lamps). */
static void test_spot_keeps_margin(T *t)
{
    static char buf[1 << 14];
    Scene s;
    int st, ok = 0;
    snprintf(buf, sizeof buf, "%s%sLightSource \"spot\" \"float scale\" [ 1 ] \"point3 from\" [ 0 0 0 ] "
             "\"point3 to\" [ 0 1 0 ] \"float coneangle\" [ 90 ] \"float conedeltaangle\" [ 45 ]\n", camera16, test_box_walls);
    add_quad(buf, sizeof buf, SPIKY, 1, v3(0.0f, -0.6f, 0.0f), 1, 1, 0.2f);
    if (!test_load_scene(t, &s, buf)) return;
    for (st = 0; st < 2; st++) {
        LightSampler *ls = build(t, &s, st ? SEL_SPECTRAL_TREE : SEL_TREE, 0, 0);
        LightCtx c = ctx_at(v3(0.5f, 1e-5f, 0.0f));
        int j;
        if (!ls) continue;
        for (j = 0; j < light_n_pieces(ls); j++)
            if (s.emitters[light_piece_emitter(ls, j)].shape < 0) ok += light_select_pmf(ls, &c, j) > 0.0f;
        light_sampler_free(ls);
    }
    scene_free(&s);
    CHECK(t, ok == 2, "the spot light had P > 0 by its plane under %d of 2 trees", ok);
}

const TestCase tests_lighttree[] = {
    { "lighttree_conservative", test_conservative },
    { "lighttree_conservative_random", test_conservative_random },
    { "lighttree_simd_matches_scalar", test_simd_matches_scalar },
    { "lighttree_bins_sum", test_bins_sum },
    { "lighttree_bins_many_radiances", test_bins_many_radiances },
    { "lighttree_root_bins_are_band_means", test_root_bins_are_band_means },
    { "lighttree_per_render_radiance", test_per_render_radiance },
    { "lighttree_select_matches_pmf", test_select_matches_pmf },
    { "lighttree_spectral_preference", test_spectral_preference },
    { "lighttree_prefers_near", test_prefers_near },
    { "lighttree_degenerate", test_degenerate },
    { "lighttree_mesh_split_pmf", test_mesh_split_pmf },
    { "lighttree_mesh_split_unbiased", test_mesh_split_unbiased },
    { "lighttree_behind_the_box", test_behind },
    { "lighttree_on_the_lamp", test_on_the_lamp },
    { "lighttree_on_the_lamp_spot", test_spot_keeps_margin },
    { NULL, NULL }
};
