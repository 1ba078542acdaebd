/* tests/test_robust.c - regression tests for hostile and unusual input (issues #13
   section 2 and #20 section 2): every reader must answer with one printable line
   "file:line: problem" or with the right result, never crash, hang or allocate what
   a header merely claims.  The inputs that ever crashed a fuzz target live in
   fuzz/regress/ and are replayed by tests/run.sh (fuzz/replay); the cases here are
   the ones a review found, each checked by its message. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* The message is one printable line: no control bytes, no bytes that are not UTF-8
   (error_set escapes them as \xNN). */
static int printable(const char *m)
{
    const unsigned char *c;
    for (c = (const unsigned char *)m; *c; c++)
        if (*c < 0x20 || *c == 0x7F || *c >= 0x80) return 0;
    return 1;
}

/* Load path; must fail with a message containing k1 and k2 (k2 may be NULL). */
static int expect_fail(T *t, const char *path, const char *k1, const char *k2, Error *e)
{
    Scene s;
    int ok;
    e->msg[0] = '\0';
    ok = scene_load(&s, path, e);
    if (ok) scene_free(&s);
    if (ok) { test_failf(t, __FILE__, __LINE__, "%s: accepted, expected \"%s\"", path, k1); return 0; }
    if (!strstr(e->msg, k1) || (k2 && !strstr(e->msg, k2)) || !printable(e->msg)) {
        test_failf(t, __FILE__, __LINE__, "%s: message \"%s\" lacks \"%s\"/\"%s\" or is not "
                   "printable", path, e->msg, k1, k2 ? k2 : "");
        return 0;
    }
    return 1;
}

/* The scene at path loads (a case just inside a limit that expect_fail checks). */
static void expect_loads(T *t, const char *path, const char *what)
{
    Scene s;
    Error e;
    if (scene_load(&s, path, &e)) { scene_free(&s); return; }
    test_failf(t, __FILE__, __LINE__, "%s refused: %s", what, e.msg);
}

static const char *write_bin(T *t, const char *name, const unsigned char *b, size_t n)
{
    const char *p = test_path(t, name);
    FILE *f = fopen(p, "wb");
    if (f) { fwrite(b, 1, n, f); fclose(f); }
    return p;
}

/* "Billion laughs": each of 21 files includes the next one twice, 2^21 - 2 Include
   directives in all, of a few bytes each.  Neither the depth (21) nor the text
   itself (about 40 MB counted every time) stops it: the text budget does, because
   every Include costs at least INCLUDE_MIN_BYTES of it (2^19 directives), with a
   file:line error that names the budget, long before the tree's end. */
static void test_include_fanout(T *t)
{
    char name[64], text[256];
    const char *main_path;
    Error e;
    int i;
    for (i = 0; i < 21; i++) {
        snprintf(name, sizeof name, "fan%d.pbrt", i);
        snprintf(text, sizeof text, "Include \"fan%d.pbrt\"\nInclude \"fan%d.pbrt\"\n", i + 1, i + 1);
        test_write_file(t, name, text);
    }
    test_write_file(t, "fan21.pbrt", "# the leaf\n");
    main_path = test_write_file(t, "fan_main.pbrt", "WorldBegin\nInclude \"fan0.pbrt\"\n");
    if (!expect_fail(t, main_path, "READ_MAX_BYTES", "exceeds 1024 MiB", &e)) return;
    CHECK(t, strstr(e.msg, "fan") && strstr(e.msg, ".pbrt:"), "names no file: %s", e.msg);
}

/* A file that includes itself is stopped at MAX_INCLUDE_DEPTH (32) files open, and
   a chain of exactly that many distinct files loads. */
static void test_include_depth(T *t)
{
    char name[64], text[256];
    const char *p;
    Error e;
    int i;
    test_write_file(t, "self.pbrt", "# itself\nInclude \"self.pbrt\"\n");
    p = test_write_file(t, "self_main.pbrt", "WorldBegin\nInclude \"self.pbrt\"\n");
    if (!expect_fail(t, p, "self.pbrt:2:", "nested deeper than 32 (MAX_INCLUDE_DEPTH", &e)) return;
    for (i = 1; i <= 32; i++) {       /* chain1 .. chain32: 32 files open at the end */
        snprintf(name, sizeof name, "chain%d.pbrt", i);
        if (i < 32) snprintf(text, sizeof text, "Include \"chain%d.pbrt\"\n", i + 1);
        else snprintf(text, sizeof text, "Shape \"sphere\"\n");
        test_write_file(t, name, text);
    }
    p = test_write_file(t, "chain0.pbrt", "WorldBegin\nInclude \"chain1.pbrt\"\n");
    expect_loads(t, p, "a chain of 32 nested Includes");
}

/* An included file is read once and each Include lexes a fresh copy of its text
   (the lexer unescapes strings in place): two files, each included twice in turn,
   give four spheres with the radii of the files, in order. */
static void test_include_cached(T *t)
{
    static const float want[4] = { 1.0f, 2.0f, 1.0f, 2.0f };
    Scene s;
    Error e;
    const char *p;
    int i;
    test_write_file(t, "cache_a.pbrt", "Shape \"sphere\" \"float radius\" 1 # a\n");
    test_write_file(t, "cache_b.pbrt", "Shape \"sphere\" \"float radius\" [ 2 ] # b\n");
    p = test_write_file(t, "cache_main.pbrt", "WorldBegin\nInclude \"cache_a.pbrt\"\n"
                        "Include \"cache_b.pbrt\"\nInclude \"cache_a.pbrt\"\nImport \"cache_b.pbrt\"\n");
    if (!scene_load(&s, p, &e)) { test_failf(t, __FILE__, __LINE__, "%s", e.msg); return; }
    CHECK(t, s.n_spheres == 4, "%d spheres", s.n_spheres);
    for (i = 0; i < 4 && i < s.n_spheres; i++)
        CHECK(t, s.shapes[s.sphere_shape[i]].radius == want[i], "sphere %d: radius %g, not %g",
              i, s.shapes[s.sphere_shape[i]].radius, want[i]);
    scene_free(&s);
}

/* The remembered number literals (parser.c parse_number) give each text its own
   value: 300 vertices of 300 distinct numbers, each read twice (x and y) and once
   more as the next vertex's z, equal strtod's values of their texts. */
static void test_number_memo(T *t)
{
    static char text[20000];
    char num[300][32];
    Scene s;
    size_t n;
    int i, bad = 0;
    for (i = 0; i < 300; i++) snprintf(num[i], sizeof num[i], "%.7g", 0.37 * i - 41.0 + 1e-4 * (i % 7));
    n = (size_t)snprintf(text, sizeof text, "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [");
    for (i = 0; i < 300; i++) n += (size_t)snprintf(text + n, sizeof text - n, " %d", i);
    n += (size_t)snprintf(text + n, sizeof text - n, " ] \"point3 P\" [");
    for (i = 0; i < 300; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, " %s %s %s", num[i], num[i], num[(i + 1) % 300]);
    snprintf(text + n, sizeof text - n, " ]\n");
    if (!test_load_scene(t, &s, text)) return;
    CHECK(t, s.n_verts == 300, "%d vertices", s.n_verts);
    for (i = 0; i < 300 && i < s.n_verts; i++) {
        const float x = (float)strtod(num[i], NULL), z = (float)strtod(num[(i + 1) % 300], NULL);
        if (s.P[i].x != x || s.P[i].y != x || s.P[i].z != z) bad++;
    }
    CHECK(t, bad == 0, "%d of 300 vertices differ from their numbers' values", bad);
    scene_free(&s);
}

/* #20: an Included file's last statement takes the parameters that follow the
   Include in the including file (pbrt-v4's token stream crosses files). */
static void test_include_params_continue(T *t)
{
    Scene s;
    Error e;
    const char *p;
    test_write_file(t, "cont_part.pbrt", "# ends with a statement\nMaterial \"diffuse\"\n");
    p = test_write_file(t, "cont_main.pbrt",
        "WorldBegin\nInclude \"cont_part.pbrt\"\n  \"spectrum reflectance\" [400 0.25 700 0.25]\n"
        "Shape \"sphere\"\n");
    CHECK(t, scene_load(&s, p, &e), "%s", e.msg);
    CHECK(t, s.n_materials == 1 && fabsf(albedo_eval(&s.materials[0].reflectance, 550.0f) - 0.25f) < 1e-6f,
          "the parameter after the Include did not reach the Material (%d materials)",
          s.n_materials);
    scene_free(&s);
    /* an error in a continued parameter names the file and line it is in */
    p = test_write_file(t, "cont_bad.pbrt",
        "WorldBegin\nInclude \"cont_part.pbrt\"\n\n  \"float frobnicate\" 1\n");
    if (!expect_fail(t, p, "cont_bad.pbrt:4:", "frobnicate", &e)) return;
}

/* #20: a name in an included file in a subdirectory resolves against the top-level
   file's directory (pbrt-v4), and a missing one is reported there, not as sub/sub/. */
static void test_include_paths(T *t)
{
    char cmd[1200];
    Scene s;
    Error e;
    const char *p;
    snprintf(cmd, sizeof cmd, "mkdir -p %s/paths/sub", t->tmpdir);
    CHECK(t, system(cmd) == 0, "mkdir");
    remove(test_path(t, "paths/sub/m.ply"));        /* from an earlier run */
    test_write_file(t, "paths/sub/inc.pbrt", "Shape \"plymesh\" \"string filename\" \"sub/m.ply\"\n");
    p = test_write_file(t, "paths/main.pbrt", "WorldBegin\nInclude \"sub/inc.pbrt\"\n");
    if (!expect_fail(t, p, "paths/sub/m.ply", "cannot read", &e)) return;
    CHECK(t, !strstr(e.msg, "sub/sub/"), "reported the doubled path: %s", e.msg);
    CHECK(t, strstr(e.msg, "inc.pbrt:1:") != NULL, "names the including line: %s", e.msg);
    {   /* and with the mesh where pbrt-v4 looks, it loads */
        static const float P[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
        static const int32_t idx[3] = { 0, 1, 2 };
        CHECK(t, ply_write_binary(test_path(t, "paths/sub/m.ply"), P, 3, idx, 1), "write ply");
        CHECK(t, scene_load(&s, p, &e), "%s", e.msg);
        CHECK(t, s.n_tris == 1, "%d triangles", s.n_tris);
        scene_free(&s);
    }
}

/* #20: gzip data is decompressed where pbrt-v4 reads it (scene files, PLY meshes)
   and refused elsewhere (a spectrum file) with a message that says so; a damaged
   gzip file names the damage; nothing binary is echoed. */
static void test_gzip_refused(T *t)
{
    static const unsigned char gz[] = { 0x1F, 0x8B, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00,
                                        0x00, 0x03, 0x8B, 0xFF, 0x01, 0x1B, 0x00 };
    Error e;
    Spectrum sp;
    const char *p;
    write_bin(t, "zipped.pbrt.gz", gz, sizeof gz);
    write_bin(t, "zipped.ply.gz", gz, sizeof gz);
    p = test_write_file(t, "gz_inc.pbrt", "WorldBegin\nInclude \"zipped.pbrt.gz\"\n");
    if (!expect_fail(t, p, "gz_inc.pbrt:2:", "gzip: truncated compressed data", &e)) return;
    p = test_write_file(t, "gz_ply.pbrt",
                        "WorldBegin\nShape \"plymesh\" \"string filename\" \"zipped.ply.gz\"\n");
    if (!expect_fail(t, p, "gz_ply.pbrt:2:", "gzip: truncated compressed data", &e)) return;
    p = test_path(t, "zipped.pbrt.gz");
    if (!expect_fail(t, p, "zipped.pbrt.gz", "gzip: truncated", &e)) return;
    p = write_bin(t, "zipped.spd", gz, sizeof gz);
    CHECK(t, !spec_from_file(&sp, p, &e) && strstr(e.msg, "compressed files are not in the specnee subset"),
          "a gzip spectrum file: \"%s\"", e.msg);
}

/* #20: binary bytes in a scene give a printable message (escaped), not raw bytes. */
static void test_binary_scene_printable(T *t)
{
    static const unsigned char junk[] = { 'W', 'o', 'r', 'l', 'd', 0xC3, 0x28, 0xFF, 0x1B,
                                          '[', '2', 'J', '\n' };
    static const unsigned char ctl[] = { 'W', 'o', 'r', 'l', 'd', 'B', 'e', 'g', 'i', 'n', '\n',
                                         0x07, '\n' };
    Error e;
    if (!expect_fail(t, write_bin(t, "junk.pbrt", junk, sizeof junk), "Unknown directive",
                     "\\xC3(\\xFF", &e)) return;
    if (!expect_fail(t, write_bin(t, "bell.pbrt", ctl, sizeof ctl), "bell.pbrt:2:",
                     "control byte 0x07", &e)) return;
}

/* error_set itself: control bytes and broken UTF-8 escaped, UTF-8 kept. */
static void test_error_set_escapes(T *t)
{
    Error e;
    error_set(&e, "f\x01", 3, "%s", "a\nb\xff\xc3\xa9");
    CHECK(t, strcmp(e.msg, "f\\x01:3: a\\x0Ab\\xFF\xc3\xa9") == 0, "got \"%s\"", e.msg);
}

/* #20: a plymesh naming /dev/zero fails at once (no 'ply' magic), not after GiBs. */
static void test_ply_dev_zero(T *t)
{
    Error e;
    FILE *f = fopen("/dev/zero", "rb");
    const char *p;
    if (!f) return;                      /* no /dev/zero here: nothing to test */
    fclose(f);
    p = test_write_file(t, "zero.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"/dev/zero\"\n");
    if (!expect_fail(t, p, "zero.pbrt:2:", "not a PLY file", &e)) return;
    p = test_write_file(t, "zero_inc.pbrt", "WorldBegin\nInclude \"/dev/zero\"\n");
    if (!expect_fail(t, p, "zero_inc.pbrt:2:", "not a text file", &e)) return;
}

/* #13: `Scale 1e-30` (or 1e30) before Camera: invertible in double, degenerate in
   the float rays the renderer makes.  Refused like a non-finite vertex. */
static void test_camera_degenerate(T *t)
{
    Error e;
    const char *p;
    p = test_write_file(t, "cam_tiny.pbrt", "LookAt 0 0 -5 0 0 0 0 1 0\nScale 1e-30 1e-30 1e-30\n"
                        "Camera \"perspective\"\nWorldBegin\nShape \"sphere\"\n");
    if (!expect_fail(t, p, "cam_tiny.pbrt:3:", "degenerate camera transform", &e)) return;
    p = test_write_file(t, "cam_huge.pbrt", "Scale 1e30 1e30 1e30\nCamera \"perspective\"\n"
                        "WorldBegin\nShape \"sphere\"\n");
    if (!expect_fail(t, p, "cam_huge.pbrt:2:", "degenerate camera transform", &e)) return;
    p = test_write_file(t, "cam_ok.pbrt", "Scale 1e-3 1e-3 1e-3\nCamera \"perspective\"\n"
                        "WorldBegin\nShape \"sphere\"\n");
    expect_loads(t, p, "a small but sane scale");
}

/* #13: a film the render's buffers could not hold within the budget, with the need. */
static void test_film_budget(T *t)
{
    Error e;
    const char *p = test_write_file(t, "film_big.pbrt", "Film \"rgb\" \"integer xresolution\" 16384 "
                                    "\"integer yresolution\" 16384\nWorldBegin\n");
    if (!expect_fail(t, p, "film_big.pbrt:1:", "would need 12.0 GiB", &e)) return;
    CHECK(t, strstr(e.msg, "memory budget of 4 GiB") != NULL, "%s", e.msg);
    p = test_write_file(t, "film_ok.pbrt", "Film \"rgb\" \"integer xresolution\" 8192 "
                        "\"integer yresolution\" 8192\nWorldBegin\n");
    expect_loads(t, p, "8192 x 8192 (2.5 GiB)");
}

/* A parameter read as one number (float, integer, bool) given with two values or
   none is refused, naming its type and name and the count. */
static void test_param_count(T *t)
{
    Scene s;
    Error e;
    const char *p = test_write_file(t, "cnt_int.pbrt", "Film \"rgb\" \"integer xresolution\" [ 4 5 ]\nWorldBegin\n");
    if (!expect_fail(t, p, "cnt_int.pbrt:1:", "\"integer xresolution\": expected one value, got 2", &e)) return;
    p = test_write_file(t, "cnt_float.pbrt", "Camera \"perspective\" \"float fov\" [ 30 40 ]\nWorldBegin\n");
    if (!expect_fail(t, p, "cnt_float.pbrt:1:", "\"float fov\": expected one value, got 2", &e)) return;
    p = test_write_file(t, "cnt_bool.pbrt", "Integrator \"path\" \"bool regularize\" [ false true ]\nWorldBegin\n");
    if (!expect_fail(t, p, "cnt_bool.pbrt:1:", "\"bool regularize\": expected one value, got 2", &e)) return;
    p = test_write_file(t, "cnt_ok.pbrt", "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" 3\n"
                        "Camera \"perspective\" \"float fov\" 30\nWorldBegin\n");
    CHECK(t, scene_load(&s, p, &e), "one value each refused: %s", e.msg);
    CHECK(t, s.settings.xres == 4 && s.settings.yres == 3 && s.settings.fov_deg == 30.0f,
          "read %d x %d, fov %g: not the values given", s.settings.xres, s.settings.yres, s.settings.fov_deg);
    scene_free(&s);
}

/* #20: "" and "none" are pbrt-v4's deprecated names of "interface" (medium.c):
   they load as it, and take no parameters. */
static void test_material_none(T *t)
{
    Error e;
    const char *p = test_write_file(t, "mat_empty.pbrt", "WorldBegin\nMaterial \"\"\nShape \"sphere\"\n");
    expect_loads(t, p, "Material \"\"");
    if (t->failed) return;
    p = test_write_file(t, "mat_none.pbrt", "WorldBegin\n\nMaterial \"none\" \"float roughness\" 0\n");
    if (!expect_fail(t, p, "mat_none.pbrt:3:", "unused parameter", &e)) return;
    p = test_write_file(t, "mat_named_none.pbrt",
                        "WorldBegin\nMakeNamedMaterial \"x\" \"string type\" \"none\"\n");
    expect_loads(t, p, "MakeNamedMaterial \"none\"");
}

/* #20: the "valid pbrt-v4 but" messages name the type (the texture's class). */
static void test_unsupported_named(T *t)
{
    Error e;
    const char *p = test_write_file(t, "ls_inf.pbrt", "WorldBegin\nLightSource \"goniometric\" \"rgb I\" [1 1 1]\n");
    if (!expect_fail(t, p, "ls_inf.pbrt:2:", "LightSource \"goniometric\": \"string filename\" is required", &e)) return;
    p = test_write_file(t, "tex.pbrt", "WorldBegin\nTexture \"wood\" \"spectrum\" \"imagemap\" "
                        "\"string filename\" \"w.png\"\n");
    if (!expect_fail(t, p, "tex.pbrt:2:", "Texture \"imagemap\"", &e)) return;
    CHECK(t, strstr(e.msg, "\"wood\"") != NULL, "%s", e.msg);
    /* the other unsupported directives name their first string */
    p = test_write_file(t, "medium.pbrt", "WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"nanovdb\"\n");
    if (!expect_fail(t, p, "medium.pbrt:2:", "MakeNamedMedium \"fog\": \"string filename\" is required", &e)) return;
}

/* #20: a spectrum file with CR-only line endings is three lines, not one. */
static void test_spectrum_cr(T *t)
{
    Spectrum s;
    Error e;
    const char *p = test_write_file(t, "cr.spd", "400 1\r500 2\r600 3\r");
    CHECK(t, spec_from_file(&s, p, &e), "%s", e.msg);
    CHECK(t, fabsf(spec_eval(&s, 500.0f) - 2.0f) < 1e-6f && fabsf(spec_eval(&s, 550.0f) - 2.5f) < 1e-6f
          && spec_eval(&s, 650.0f) == 0.0f, "read as %g at 500 nm, %g at 550 nm",
          spec_eval(&s, 500.0f), spec_eval(&s, 550.0f));
    p = test_write_file(t, "cr.csv", "lambda,value\r400,1\r500,2\r\n600,3");
    CHECK(t, spec_from_file(&s, p, &e), "%s", e.msg);
    CHECK(t, fabsf(spec_eval(&s, 550.0f) - 2.5f) < 1e-6f, "csv read as %g at 550 nm",
          spec_eval(&s, 550.0f));
    p = test_write_file(t, "cr_bad.spd", "400 1\r500 x\r");
    CHECK(t, !spec_from_file(&s, p, &e) && strstr(e.msg, "cr_bad.spd:2:"), "bad value on line 2: %s",
          e.msg);
}

/* Run `merge a b -o out` capturing the error stream; returns the exit code. */
static int merge2(T *t, const char *a, const char *b, char *errbuf, size_t cap)
{
    char *argv[6];
    const char *ep = test_path(t, "merge_err.txt");
    FILE *out = fopen(test_path(t, "merge_out.txt"), "w+"), *err = fopen(ep, "w+");
    int rc;
    size_t n;
    argv[0] = (char *)"merge"; argv[1] = (char *)a; argv[2] = (char *)b;
    argv[3] = (char *)"-o"; argv[4] = (char *)test_path(t, "merge_res.pfm"); argv[5] = NULL;
    if (!out || !err) { if (out) fclose(out); if (err) fclose(err); return -1; }
    rc = img_cmd_merge(5, argv, out, err);
    rewind(err);
    n = fread(errbuf, 1, cap - 1, err);
    errbuf[n] = '\0';
    fclose(out); fclose(err);
    return rc;
}

/* #13: sidecars whose spp values overflow a long when summed (UB before). */
static void test_merge_spp_overflow(T *t)
{
    Image im;
    char a[1024], b[1024], msg[2048];
    int rc;
    CHECK(t, img_alloc(&im, 2, 1), "alloc");
    snprintf(a, sizeof a, "%s", test_path(t, "ovf_a.pfm"));
    snprintf(b, sizeof b, "%s", test_path(t, "ovf_b.pfm"));
    CHECK(t, pfm_write(&im, a) && pfm_write(&im, b), "write");
    img_free(&im);
    test_write_file(t, "ovf_a.pfm.txt", "spp 9223372036854775807\n");
    test_write_file(t, "ovf_b.pfm.txt", "spp 1\n");
    rc = merge2(t, a, b, msg, sizeof msg);
    CHECK(t, rc == 1 && strstr(msg, "would exceed"), "rc %d: %s", rc, msg);
    test_write_file(t, "ovf_b.pfm.txt", "spp 99999999999999999999\n");
    CHECK(t, img_read_sidecar_spp(b) == -1, "an out-of-range spp is not a valid line");
    rc = merge2(t, b, b, msg, sizeof msg);
    CHECK(t, rc == 1 && strstr(msg, "valid line 'spp N'"), "rc %d: %s", rc, msg);
    test_write_file(t, "ovf_a.pfm.txt", "spp 4611686018427387903\n");   /* 2^62 - 1: sums fine */
    rc = merge2(t, a, a, msg, sizeof msg);
    CHECK(t, rc == 0, "rc %d: %s", rc, msg);
}

/* #31: a bad value is reported at its parameter's line, which may lie below the
   statement's first line. */
static void test_error_at_param_line(T *t)
{
    Error e;
    const char *p = test_write_file(t, "pl_sphere.pbrt", "WorldBegin\nShape \"sphere\"\n  \"float radius\" [ -1 ]\n");
    if (!expect_fail(t, p, "pl_sphere.pbrt:3:", "radius -1 must be > 0", &e)) return;
    p = test_write_file(t, "pl_disk.pbrt", "WorldBegin\nShape \"disk\"\n \"float radius\" 1\n \"float innerradius\" 2\n");
    if (!expect_fail(t, p, "pl_disk.pbrt:4:", "innerradius 2", &e)) return;
    p = test_write_file(t, "pl_fov.pbrt", "Camera \"perspective\"\n\n \"float fov\" [ 200 ]\nWorldBegin\n");
    if (!expect_fail(t, p, "pl_fov.pbrt:3:", "\"float fov\" 200", &e)) return;
    p = test_write_file(t, "pl_depth.pbrt", "Integrator \"path\"\n \"integer maxdepth\" [ -3 ]\nWorldBegin\n");
    if (!expect_fail(t, p, "pl_depth.pbrt:2:", "maxdepth -3", &e)) return;
    p = test_write_file(t, "pl_same.pbrt", "Camera \"perspective\" \"float fov\" [ 0 ]\nWorldBegin\n");
    expect_fail(t, p, "pl_same.pbrt:1:", "\"float fov\" 0", &e);
}

/* A parameter's "type name" string is split into whitespace-separated words of
   at most 63 characters (parser.c scan_word, as sscanf's "%63s" did): spaces and
   tabs around and between the words are fine; one word, three words, or a type
   longer than 63 characters (its tail becomes a third word) are refused. */
static void test_param_words(T *t)
{
    Error e;
    Scene s;
    const char *p = test_write_file(t, "pw_ok.pbrt", "WorldBegin\nShape \"sphere\" \"  float\tradius  \" [ 0.5 ]\n");
    CHECK(t, scene_load(&s, p, &e), "%s", e.msg);
    CHECK(t, s.n_shapes == 1 && s.shapes[0].radius == 0.5f, "the radius was not read: %d shapes",
          s.n_shapes);
    scene_free(&s);
    p = test_write_file(t, "pw_one.pbrt", "WorldBegin\nShape \"sphere\" \"float\" [ 1 ]\n");
    if (!expect_fail(t, p, "pw_one.pbrt:2:", "needs a type and a name", &e)) return;
    p = test_write_file(t, "pw_three.pbrt", "WorldBegin\nShape \"sphere\" \"float radius 2\" [ 1 ]\n");
    if (!expect_fail(t, p, "pw_three.pbrt:2:", "more than a type and a name", &e)) return;
    p = test_write_file(t, "pw_long.pbrt", "WorldBegin\nShape \"sphere\" \"float"
                        "xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx radius\" [ 1 ]\n");
    expect_fail(t, p, "pw_long.pbrt:2:", "more than a type and a name", &e);
}

const TestCase tests_robust[] = {
    { "robust_error_at_param_line", test_error_at_param_line },
    { "robust_param_words", test_param_words },
    {"robust_include_fanout", test_include_fanout},
    {"robust_include_depth", test_include_depth},
    {"robust_include_cached", test_include_cached},
    {"robust_number_memo", test_number_memo},
    {"robust_include_params_continue", test_include_params_continue},
    {"robust_include_paths", test_include_paths},
    {"robust_gzip_refused", test_gzip_refused},
    {"robust_binary_scene_printable", test_binary_scene_printable},
    {"robust_error_set_escapes", test_error_set_escapes},
    {"robust_ply_dev_zero", test_ply_dev_zero},
    {"robust_camera_degenerate", test_camera_degenerate},
    {"robust_film_budget", test_film_budget},
    {"robust_param_count", test_param_count},
    {"robust_material_none", test_material_none},
    {"robust_unsupported_named", test_unsupported_named},
    {"robust_spectrum_cr", test_spectrum_cr},
    {"robust_merge_spp_overflow", test_merge_spp_overflow},
    {NULL, NULL}
};
