/* tests/test_scenes.c - the shipped scenes say what their headers claim.

   What it checks, for the files in scenes/ (run from the repository root, as
   tests/run.sh and `make test` do):
     - every scene parses and renders, at a reduced film and a few samples, to an
       image whose pixels are all finite (RenderStats.nonfinite == 0) and whose
       mean is not black;
     - the glass meshes are fit for a dielectric, which tells inside from outside
       by the normal: every interior edge is traversed in opposite directions by
       its two triangles (consistent winding), no directed edge occurs twice, and
       the signed volume  V = (1/6) sum_tri p0 . (p1 x p2)  is positive (outward
       normals; with the shape's flip flag the sign is reversed).  The Cornell
       glass boxes are closed (0 open edges); the Suzanne mesh has 3936 triangles,
       2012 vertices with normals and 84 open edges (around the eyes);
     - the lamps are normalised by thesis eq. 6 (Deshmukh et al. 2022, Section
       2): after scene_load (400-700 nm normalisation, pbrt-v4's rule Le = scale L /
       sum ybar L) the sum of the 60 bin averages of Le is c +- 1e-3, with c = 1 for
       every lamp except the Suzanne scene's LED1 (c = 2).  This holds only if the
       "float scale" in the file is the one `specnee spectrum` prints, so the test
       proves that each file says what it claims;
     - the insets "# inset A/B/C" parse and lie inside the film;
     - the geometric claims of the headers: cornell2's LEDs are larger than its
       CFL (so the unit and power metrics differ), the Suzanne scene's LED1 faces
       away from the glass head; many-lamps has 257 emitters of three lamp
       spectra, 32 facing up, 48 hidden above a panel, a strip the light trees
       split, and dispersive glass.
   No test here is statistical: every check is exact or a fixed tolerance. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* The shipped scenes (paths relative to the repository root). */
static const char *const scene_files[] = {
    "scenes/cornell.pbrt", "scenes/cornell1.pbrt", "scenes/cornell2.pbrt",
    "scenes/suzanne.pbrt", "scenes/many-lamps.pbrt", NULL
};

/* Load a scene file; fails the test (and returns 0) on a parse error. */
static int load_file(T *t, Scene *s, const char *path)
{
    Error err;
    memset(s, 0, sizeof *s);
    err.msg[0] = 0;
    if (!scene_load(s, path, &err)) {
        test_failf(t, __FILE__, __LINE__, "%s did not load: %s", path, err.msg);
        return 0;
    }
    return 1;
}

/* ---- 1. Each scene renders to a finite, non-black image ----------------- */
static void test_render_finite(T *t)
{
    int i;
    for (i = 0; scene_files[i]; i++) {
        Scene s;
        RenderOptions o;
        RenderStats st;
        Image img;
        Error err;
        double sum = 0.0;
        long k, bad = 0;
        int ok;
        if (!load_file(t, &s, scene_files[i])) return;
        /* A quarter-size film (the camera keeps its fov on the shorter axis, so
           the picture is the same, only coarser) and 8 samples a pixel. */
        s.settings.xres = s.settings.xres / 4;
        s.settings.yres = s.settings.yres / 4;
        render_options_default(&o);
        o.spp = 8;
        o.seed = 7;
        o.threads = 1;
        o.maxdepth = 6;
        o.progress = 0;
        o.sel.grid_res = 8;        /* keep the lazily built spatial grid cheap */
        ok = render(&s, &o, &img, &st, &err);
        scene_free(&s);
        CHECK(t, ok, "%s: render failed: %s", scene_files[i], err.msg);
        for (k = 0; k < 3L * img.w * img.h; k++) {
            if (!isfinite(img.rgb[k])) bad++;
            else sum += img.rgb[k];
        }
        img_free(&img);
        CHECK(t, st.nonfinite == 0, "%s: %ld non-finite samples reached the film",
              scene_files[i], st.nonfinite);
        CHECK(t, bad == 0, "%s: %ld non-finite pixel values", scene_files[i], bad);
        CHECK(t, sum > 1e-4 * 3.0 * (double)k, "%s: image is black (mean %g)",
              scene_files[i], sum / (double)k);
    }
}

/* ---- 2. Mesh topology: winding consistency, open edges, signed volume -------- */
typedef struct { int32_t a, b; } Edge;

static int edge_cmp(const void *pa, const void *pb)
{
    const Edge *x = (const Edge *)pa, *y = (const Edge *)pb;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    return 0;
}

/* Whether the directed edge (a, b) is in the sorted list. */
static int has_edge(const Edge *e, int n, int32_t a, int32_t b)
{
    Edge key;
    key.a = a; key.b = b;
    return bsearch(&key, e, (size_t)n, sizeof *e, edge_cmp) != NULL;
}

typedef struct {
    int duplicated;     /* directed edges traversed twice: inconsistent winding */
    int open;           /* directed edges whose reverse is missing: boundary edges */
    double volume;      /* signed volume, > 0 for outward normals (flip applied) */
    int normals_against;/* triangles whose vertex normals oppose the winding */
} Topology;

/* Analyse the triangles of one mesh shape.  0 on out of memory. */
static int mesh_topology(const Scene *s, const Shape *sh, Topology *out)
{
    int n = 3 * sh->tri_count, i, j;
    Edge *e = (Edge *)malloc((size_t)n * sizeof *e);
    if (!e) return 0;
    memset(out, 0, sizeof *out);
    for (i = 0; i < sh->tri_count; i++) {
        const Triangle *tr = &s->tris[sh->tri_begin + i];
        Vec3 p0 = s->P[tr->v[0]], p1 = s->P[tr->v[1]], p2 = s->P[tr->v[2]];
        Vec3 ng = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0));  /* right-hand normal */
        for (j = 0; j < 3; j++) {
            e[3 * i + j].a = tr->v[j];
            e[3 * i + j].b = tr->v[(j + 1) % 3];
        }
        out->volume += v3_dot(p0, v3_cross(p1, p2)) / 6.0;
        if (sh->has_normals && s->N) {  /* shading normals (already in world space) against the winding */
            Vec3 nsum = v3_add(v3_add(s->N[tr->v[0]], s->N[tr->v[1]]), s->N[tr->v[2]]);
            float side = v3_dot(nsum, ng);
            if (sh->flip) side = -side;          /* flip turns the geometric normal */
            if (side <= 0.0f) out->normals_against++;
        }
    }
    if (sh->flip) out->volume = -out->volume;
    qsort(e, (size_t)n, sizeof *e, edge_cmp);
    for (i = 0; i < n; i++) {
        if (i > 0 && edge_cmp(&e[i], &e[i - 1]) == 0) out->duplicated++;
        if (!has_edge(e, n, e[i].b, e[i].a)) out->open++;
    }
    free(e);
    return 1;
}

/* Every dielectric mesh of a scene: consistent, outward, with `open` open edges. */
static int check_glass(T *t, const char *path, int want_shapes, int want_open_each,
                       int want_tris_each)
{
    Scene s;
    int i, found = 0;
    if (!load_file(t, &s, path)) return 0;
    for (i = 0; i < s.n_shapes; i++) {
        const Shape *sh = &s.shapes[i];
        Topology tp;
        if (s.materials[sh->material].type != MAT_DIELECTRIC) continue;
        found++;
        if (sh->type != SHAPE_MESH) {
            test_failf(t, __FILE__, __LINE__, "%s: glass shape %d is not a mesh", path, i);
            break;
        }
        if (!mesh_topology(&s, sh, &tp)) {
            test_failf(t, __FILE__, __LINE__, "out of memory");
            break;
        }
        if (sh->tri_count != want_tris_each || tp.duplicated != 0 ||
            tp.open != want_open_each || !(tp.volume > 0.0) || tp.normals_against != 0) {
            test_failf(t, __FILE__, __LINE__,
                       "%s: glass shape %d (line %d): %d triangles (want %d), %d edges "
                       "traversed twice in one direction (want 0), %d open edges (want %d), "
                       "signed volume %g (want > 0: outward), %d triangles with vertex "
                       "normals against the winding (want 0)", path, i, sh->line,
                       sh->tri_count, want_tris_each, tp.duplicated, tp.open,
                       want_open_each, tp.volume, tp.normals_against);
            break;
        }
    }
    scene_free(&s);
    if (t->failed) return 0;
    if (found != want_shapes) {
        test_failf(t, __FILE__, __LINE__, "%s: %d glass shapes, want %d", path, found,
                   want_shapes);
        return 0;
    }
    return 1;
}

static void test_glass_boxes_closed(T *t)
{
    /* two boxes of 12 triangles, closed: no open edge */
    if (!check_glass(t, "scenes/cornell1.pbrt", 2, 0, 12)) return;
    if (!check_glass(t, "scenes/cornell2.pbrt", 2, 0, 12)) return;
}

static void test_suzanne_mesh(T *t)
{
    PlyMesh m;
    Error err;
    int ok;
    memset(&m, 0, sizeof m);
    ok = ply_read("scenes/meshes/suzanne.ply", &m, &err);
    CHECK(t, ok, "suzanne.ply: %s", err.msg);
    ok = m.n_tris == 3936 && m.n_verts == 2012 && m.N != NULL;
    {
        int nt = m.n_tris, nv = m.n_verts, hn = m.N != NULL;
        ply_free(&m);
        CHECK(t, ok, "suzanne.ply: %d triangles, %d vertices, normals %d "
              "(want 3936, 2012, 1)", nt, nv, hn);
    }
    /* In the scene (world space, after Rotate/Scale): consistent and outward, with
       the 84 open edges of Suzanne's eye sockets. */
    check_glass(t, "scenes/suzanne.pbrt", 1, 84, 3936);
}

/* ---- 3. thesis eq. 6 normalisation of the lamps ----------------------------------- */
typedef struct { const char *scene, *lamp; double c; } LampClaim;
static const LampClaim lamp_claims[] = {
    { "scenes/cornell1.pbrt", "lamp-CFL1", 1.0 },
    { "scenes/cornell1.pbrt", "lamp-LED1", 1.0 },
    { "scenes/cornell2.pbrt", "lamp-CFL1", 1.0 },
    { "scenes/cornell2.pbrt", "lamp-LED1", 1.0 },
    { "scenes/cornell2.pbrt", "lamp-LED2", 1.0 },
    { "scenes/suzanne.pbrt",  "lamp-CFL1", 1.0 },
    { "scenes/suzanne.pbrt",  "lamp-LED1", 2.0 },   /* the bright occluded LED */
    { "scenes/suzanne.pbrt",  "lamp-LED2", 1.0 },
    { NULL, NULL, 0.0 }
};

/* Which named lamp an emitter's L is (its table equals the named one), or NULL. */
static const char *lamp_of(const Emitter *em)
{
    static const char *const lamps[] = { "lamp-CFL1", "lamp-LED1", "lamp-LED2", NULL };
    int i, k;
    for (i = 0; lamps[i]; i++) {
        Spectrum ref;
        float worst = 0.0f;
        if (!spec_named(&ref, lamps[i])) continue;
        for (k = 0; k < SPEC_N; k++) {
            float d = fabsf(ref.v[k] - em->L->v[k]);
            if (d > worst) worst = d;
        }
        if (worst <= 1e-6f) return lamps[i];
    }
    return NULL;
}

static void test_eq6_normalisation(T *t)
{
    const char *scenes[] = { "scenes/cornell1.pbrt", "scenes/cornell2.pbrt",
                             "scenes/suzanne.pbrt", NULL };
    int si;
    for (si = 0; scenes[si]; si++) {
        Scene s;
        int e, i, claimed = 0;
        if (!load_file(t, &s, scenes[si])) return;
        for (i = 0; lamp_claims[i].scene; i++)
            if (strcmp(lamp_claims[i].scene, scenes[si]) == 0) claimed++;
        if (s.n_emitters != claimed) {
            test_failf(t, __FILE__, __LINE__, "%s: %d emitters, the header claims %d",
                       scenes[si], s.n_emitters, claimed);
            scene_free(&s);
            return;
        }
        for (e = 0; e < s.n_emitters; e++) {
            const char *lamp = lamp_of(&s.emitters[e]);
            double c = -1.0, sum;
            Spectrum Le;
            Error err;
            if (!emitter_radiance(&s, e, LAMBDA_LO, LAMBDA_HI, &Le, &err)) spec_const(&Le, 0.0f);
            sum = spec_bin_sum(&Le);
            for (i = 0; lamp && lamp_claims[i].scene; i++)
                if (strcmp(lamp_claims[i].scene, scenes[si]) == 0 &&
                    strcmp(lamp_claims[i].lamp, lamp) == 0) c = lamp_claims[i].c;
            if (c < 0.0 || fabs(sum - c) > 1e-3) {
                test_failf(t, __FILE__, __LINE__,
                           "%s: emitter %d (%s): thesis eq. 6 bin sum %.6f, want c = %g +- 1e-3 "
                           "(use the scale `specnee spectrum` prints, times c)",
                           scenes[si], e, lamp ? lamp : "not a thesis lamp", sum, c);
                scene_free(&s);
                return;
            }
        }
        scene_free(&s);
    }
}

/* ---- 4. Insets ------------------------------------------------------------- */
static void test_insets(T *t)
{
    const char *scenes[] = { "scenes/cornell1.pbrt", "scenes/cornell2.pbrt",
                             "scenes/suzanne.pbrt", NULL };
    int si, i;
    for (si = 0; scenes[si]; si++) {
        Scene s;
        const char *want = "ABC";
        if (!load_file(t, &s, scenes[si])) return;
        if (s.n_insets != 3) {
            test_failf(t, __FILE__, __LINE__, "%s: %d insets, want A, B, C", scenes[si],
                       s.n_insets);
            scene_free(&s);
            return;
        }
        for (i = 0; i < 3; i++) {
            const int *r = s.inset[i];
            if (s.inset_name[i][0] != want[i] || s.inset_name[i][1] != 0 ||
                !(0 <= r[0] && r[0] < r[2] && r[2] <= s.settings.xres &&
                  0 <= r[1] && r[1] < r[3] && r[3] <= s.settings.yres)) {
                test_failf(t, __FILE__, __LINE__, "%s: inset %d '%s' %d %d %d %d: want "
                           "'%c' inside the %dx%d film", scenes[si], i, s.inset_name[i],
                           r[0], r[1], r[2], r[3], want[i], s.settings.xres,
                           s.settings.yres);
                scene_free(&s);
                return;
            }
        }
        scene_free(&s);
    }
}

/* ---- 5. The geometric claims of the headers -------------------------------- */
/* Centre (vertex mean) and oriented normal of a 2-triangle emitter quad. */
static void emitter_frame(const Scene *s, int e, Vec3 *c, Vec3 *n)
{
    const Shape *sh = &s->shapes[s->emitters[e].shape];
    const Triangle *tr = &s->tris[sh->tri_begin];
    Vec3 p0 = s->P[tr->v[0]], p1 = s->P[tr->v[1]], p2 = s->P[tr->v[2]];
    *n = v3_norm(v3_cross(v3_sub(p0, p2), v3_sub(p1, p2)));   /* conventions.md 3 */
    if (sh->flip) *n = v3_neg(*n);
    *c = v3_mul(v3_add(v3_add(p0, p1), p2), 1.0f / 3.0f);
}

static void test_emitter_layout(T *t)
{
    Scene s;
    int e, glass = -1, i;
    double area_led = 0.0, area_cfl = 0.0;
    /* cornell2: both LEDs larger than the CFL, so unit and power metrics differ */
    if (!load_file(t, &s, "scenes/cornell2.pbrt")) return;
    for (e = 0; e < s.n_emitters; e++) {
        const char *lamp = lamp_of(&s.emitters[e]);
        double a = s.emitters[e].area;
        if (lamp && strcmp(lamp, "lamp-CFL1") == 0) area_cfl = a;
        else if (area_led == 0.0 || a < area_led) area_led = a;   /* smaller LED */
    }
    scene_free(&s);
    CHECK(t, area_cfl > 0.0 && area_led > 2.0 * area_cfl,
          "cornell2: CFL area %g, smaller LED area %g: want the LEDs > 2x the CFL",
          area_cfl, area_led);
    /* suzanne: LED1 faces away from the glass head (its normal points away from
       the head's centre), the other two face it */
    if (!load_file(t, &s, "scenes/suzanne.pbrt")) return;
    for (i = 0; i < s.n_shapes; i++)
        if (s.materials[s.shapes[i].material].type == MAT_DIELECTRIC) glass = i;
    if (glass < 0) { scene_free(&s); CHECK(t, 0, "suzanne: no glass shape"); }
    {
        const Shape *sh = &s.shapes[glass];
        Vec3 head = v3(0, 0, 0);
        for (i = 0; i < sh->tri_count; i++)
            head = v3_add(head, s.P[s.tris[sh->tri_begin + i].v[0]]);
        head = v3_mul(head, 1.0f / (float)sh->tri_count);
        for (e = 0; e < s.n_emitters; e++) {
            const char *lamp = lamp_of(&s.emitters[e]);
            Vec3 c, n;
            float facing;
            emitter_frame(&s, e, &c, &n);
            facing = v3_dot(n, v3_sub(head, c));
            if (lamp && strcmp(lamp, "lamp-LED1") == 0 ? facing >= 0.0f : facing <= 0.0f) {
                test_failf(t, __FILE__, __LINE__, "suzanne: emitter %d (%s) %s the head "
                           "(n . (head - centre) = %g)", e, lamp ? lamp : "?",
                           facing >= 0.0f ? "faces" : "faces away from", facing);
                break;
            }
        }
    }
    scene_free(&s);
}

/* scenes/many-lamps.pbrt has what its header claims: 257 emitters, three lamp
   spectra, 32 lamps facing up, the 48 lamps above the dropped panel (x > 0.5,
   z > 4) hidden from the floor, a 192-triangle strip that the light trees split,
   dispersive glass. */
static void test_many_lamps(T *t)
{
    Scene s;
    SelOptions o;
    LightSampler *ls;
    Error err;
    int e, up = 0, hidden = 0, big = -1, lamps[3] = { 0, 0, 0 }, i, glass = 0;
    static const char *const names[3] = { "lamp-CFL1", "lamp-LED1", "lamp-LED2" };
    if (!load_file(t, &s, "scenes/many-lamps.pbrt")) return;
    for (e = 0; e < s.n_emitters; e++) {
        const Shape *sh = &s.shapes[s.emitters[e].shape];
        const Triangle *tr = &s.tris[sh->tri_begin];
        Vec3 p0 = s.P[tr->v[0]], p1 = s.P[tr->v[1]], p2 = s.P[tr->v[2]];
        Vec3 n = v3_cross(v3_sub(p0, p2), v3_sub(p1, p2));
        const char *lamp = lamp_of(&s.emitters[e]);
        if (sh->flip) n = v3_neg(n);
        for (i = 0; i < 3; i++) if (lamp && !strcmp(lamp, names[i])) lamps[i]++;
        if (sh->tri_count > 2) { big = e; continue; }
        if (n.y > 0.0f) up++;
        if (p0.x > 0.5f && p0.z > 4.0f) {
            /* above the panel at y = 2.7: a ray from the floor below is blocked */
            Ray r;
            HitRecord h;
            r.o = v3(p0.x + 0.03f, 0.01f, p0.z + 0.03f);
            r.d = v3(0.0f, 1.0f, 0.0f);
            r.tmax = 2.97f;
            if (bvh_occluded(&s.bvh, &s, &r) && bvh_intersect(&s.bvh, &s, &r, &h) && h.t < 2.75f) hidden++;
        }
    }
    for (i = 0; i < s.n_materials; i++) glass += s.materials[i].type == MAT_DIELECTRIC && s.materials[i].dispersive;
    CHECK(t, s.n_emitters == 257, "%d emitters, the header claims 257", s.n_emitters);
    CHECK(t, lamps[0] >= 85 && lamps[1] >= 85 && lamps[2] >= 86, "lamp spectra %d %d %d", lamps[0], lamps[1], lamps[2]);
    CHECK(t, up == 32 && hidden == 48, "%d lamps face up (want 32), %d hidden above the panel (want 48)", up, hidden);
    CHECK(t, big >= 0 && s.shapes[s.emitters[big].shape].tri_count == 192, "no 192-triangle strip");
    CHECK(t, glass == 1, "%d dispersive glasses", glass);
    memset(&o, 0, sizeof o);
    o.strategy = SEL_SPECTRAL_TREE;
    ls = light_sampler_build(&s, &o, &err);
    CHECK(t, ls != NULL, "%s", err.msg);
    i = light_n_pieces(ls);
    light_sampler_free(ls);
    scene_free(&s);
    CHECK(t, i >= 256 + 192 / LIGHT_CLUSTER_TRIS, "the strip was not split: %d pieces", i);
}

const TestCase tests_scenes[] = {
    { "scenes_many_lamps", test_many_lamps },
    { "scenes_render_finite", test_render_finite },
    { "scenes_glass_boxes_closed", test_glass_boxes_closed },
    { "scenes_suzanne_mesh", test_suzanne_mesh },
    { "scenes_eq6_normalisation", test_eq6_normalisation },
    { "scenes_insets", test_insets },
    { "scenes_emitter_layout", test_emitter_layout },
    { NULL, NULL }
};
