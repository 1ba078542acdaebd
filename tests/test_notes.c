/* tests/test_notes.c - what the loader reads and ignores is said in a note.

   A scene may hold what changes nothing: a medium that neither the camera nor a
   shape's transition leads into (scene.c's finish), a light's "float power" or
   "float illuminance" <= 0, which pbrt-v4 reads only when it is positive
   (delta.c, infinite.c, lights.c; parser.c's note_not_positive).  Each gets one
   "file:line: note: ..." line on stderr at the line that says it, and the scene
   is built as if it were not there.  The notes are written to stderr, so these
   tests send stderr to a file while the scene loads (POSIX dup/dup2). */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Load text as "n.pbrt" with stderr in a file; *out: what was written there. */
static int load_noting(T *t, Scene *s, const char *text, char *out, size_t cap)
{
    FILE *f = fopen(test_path(t, "notes_stderr.txt"), "w+");
    Error e;
    int saved, ok;
    size_t n;
    out[0] = '\0';
    if (!f) return 0;
    fflush(stderr);
    saved = dup(fileno(stderr));
    if (saved < 0 || dup2(fileno(f), fileno(stderr)) < 0) { fclose(f); return 0; }
    ok = scene_load_string(s, text, "n.pbrt", &e);
    fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    rewind(f);
    n = fread(out, 1, cap - 1, f);
    out[n] = '\0';
    fclose(f);
    if (!ok) fprintf(stderr, "test_notes: %s\n", e.msg);
    return ok;
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

/* "fog" is used by nothing; "mist" only by a shape that is no transition (the same
   medium on both sides: medium_after keeps the ray's medium); "haze" by a shape's
   inside, "air" by the camera: two notes, at the MakeNamedMedium lines. */
static void test_unused_medium(T *t)
{
    static const char *text =
        "MediumInterface \"\" \"air\"\n"
        "Camera \"perspective\"\n"
        "WorldBegin\n"
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n"
        "MakeNamedMedium \"mist\" \"string type\" \"homogeneous\"\n"
        "MakeNamedMedium \"haze\" \"string type\" \"homogeneous\"\n"
        "MakeNamedMedium \"air\" \"string type\" \"homogeneous\"\n"
        "AttributeBegin\n"
        "MediumInterface \"mist\" \"mist\"\n"
        "Shape \"sphere\" \"float radius\" 2\n"
        "MediumInterface \"haze\" \"\"\n"
        "Material \"interface\"\n"
        "Shape \"sphere\" \"float radius\" 1\n"
        "AttributeEnd\n"
        "LightSource \"point\"\n";
    Scene s;
    char out[2048];
    CHECK(t, load_noting(t, &s, text, out, sizeof out), "the scene did not load");
    CHECK(t, s.n_media == 4, "%d media, expected 4", s.n_media);
    CHECK(t, strstr(out, "n.pbrt:4: note: medium \"fog\" is defined but never used\n") != NULL,
          "no note for the unused \"fog\": \"%s\"", out);
    CHECK(t, strstr(out, "n.pbrt:5: note: medium \"mist\" is defined but never used\n") != NULL,
          "no note for \"mist\" (named by no transition): \"%s\"", out);
    CHECK(t, count_lines(out) == 2, "expected the two notes alone: \"%s\"", out);
    scene_free(&s);
}

/* A non-positive power or illuminance: a note at its own line, and the light
   keeps the scale of the same light without the parameter. */
static void test_power_ignored(T *t)
{
    static const char *lights[][3] = {   /* the light, its parameter, the value */
        { "LightSource \"point\"", "power", "-60" },
        { "LightSource \"spot\"", "power", "0" },
        { "LightSource \"distant\"", "illuminance", "-2" },
        { "LightSource \"infinite\"", "illuminance", "-1" },
    };
    char text[512], out[1024], want[256];
    float scale[2];
    int i, k;
    for (i = 0; i < 4; i++) {
        for (k = 0; k < 2; k++) {
            Scene s;
            if (k) snprintf(text, sizeof text, "WorldBegin\n%s\n    \"float %s\" [ %s ]\n",
                            lights[i][0], lights[i][1], lights[i][2]);
            else snprintf(text, sizeof text, "WorldBegin\n%s\n", lights[i][0]);
            CHECK(t, load_noting(t, &s, text, out, sizeof out), "%s did not load", lights[i][0]);
            CHECK(t, s.n_emitters == 1, "%s: %d emitters", lights[i][0], s.n_emitters);
            scale[k] = s.emitters[0].scale;
            scene_free(&s);
            if (!k) {
                CHECK(t, out[0] == '\0', "%s without power: \"%s\"", lights[i][0], out);
                continue;
            }
            snprintf(want, sizeof want, "n.pbrt:3: note: %s: \"float %s\" %s is not positive "
                     "and is ignored", lights[i][0], lights[i][1], lights[i][2]);
            CHECK(t, strstr(out, want) != NULL && count_lines(out) == 1, "%s: \"%s\", "
                  "expected \"%s...\"", lights[i][0], out, want);
        }
        CHECK(t, scale[0] == scale[1], "%s: scale %g with the parameter, %g without",
              lights[i][0], scale[1], scale[0]);
    }
    /* a positive power is read (no note) */
    {
        Scene s;
        CHECK(t, load_noting(t, &s, "WorldBegin\nLightSource \"point\" \"float power\" 10\n",
                             out, sizeof out), "point light of power 10 did not load");
        CHECK(t, out[0] == '\0', "a positive power noted: \"%s\"", out);
        scene_free(&s);
    }
}

/* An area light's "power": <= 0 (which pbrt-v4 ignores) is noted and the
   emitter keeps its scale; > 0 is read without a note (tests/test_lightpower.c
   checks its meaning). */
static void test_area_power(T *t)
{
    static const char *fmt = "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" %s\n"
                             "Shape \"sphere\"\nAttributeEnd\n";
    char text[256], out[1024];
    float scale[2];
    int k;
    for (k = 0; k < 2; k++) {
        Scene s;
        snprintf(text, sizeof text, fmt, k ? "\"float power\" 0" : "");
        CHECK(t, load_noting(t, &s, text, out, sizeof out), "area light did not load");
        CHECK(t, s.n_emitters == 1, "%d emitters", s.n_emitters);
        scale[k] = s.emitters[0].scale;
        scene_free(&s);
        CHECK(t, !k ? out[0] == '\0' :
              strstr(out, "n.pbrt:3: note: AreaLightSource \"diffuse\": \"float power\" 0 is "
                     "not positive and is ignored") != NULL && count_lines(out) == 1,
              "area light %s: \"%s\"", k ? "with power 0" : "alone", out);
    }
    CHECK(t, scale[0] == scale[1], "area light: scale %g with power 0, %g without", scale[1],
          scale[0]);
    {
        Scene s;
        snprintf(text, sizeof text, fmt, "\"float power\" 5");
        CHECK(t, load_noting(t, &s, text, out, sizeof out), "area light of power 5 did not load");
        CHECK(t, out[0] == '\0', "a positive area power noted: \"%s\"", out);
        CHECK(t, s.n_emitters == 1 && s.emitters[0].power == 5.0f, "power not kept");
        scene_free(&s);
    }
}

/* An area light of two triangles of opposite windings that share part of the
   plane: the square lamp of cuda-optix-pathtracing's scenes/cornell-box.pbrt
   (alexoz12v2, 576b447), whose indices 0 1 2  0 2 3 over the corners in row
   order give two triangles that overlap in a quarter of the square, and the same
   corners twice (an exporter's twins) each get a note naming the pair; a quad of
   two triangles of one winding, two of opposite windings that only share an
   edge, and two parallel ones 0.001 apart get none. */
static void test_overlapping_lamp(T *t)
{
    static const char *const fmt = "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -0.5 2 -0.5  0.5 2 -0.5  -0.5 2 0.5  0.5 2 0.5  %s ]\n"
        "  \"integer indices\" [ %s ]\nAttributeEnd\n";
    static const char *const c[6][3] = {   /* extra corners, indices, the note's words */
        { "", "0 1 2  0 2 3", "triangles 0 and 1 of this mesh overlap in one plane" },
        { "", "0 1 3  0 3 1", "triangles 0 and 1 of this mesh lie on each other" },
        { "", "0 1 3  0 3 2", NULL },
        { "", "0 1 2  1 2 3", NULL },
        { "", "0 1 3  0 3 2  1 2 3", "triangles 0 and 2 of this mesh overlap in one plane" },
        { "0.2 2.001 0.2", "0 1 2  4 1 0", NULL },
    };
    char text[1024], out[1024], want[256];
    int i;
    for (i = 0; i < 6; i++) {
        Scene s;
        snprintf(text, sizeof text, fmt, c[i][0], c[i][1]);
        CHECK(t, load_noting(t, &s, text, out, sizeof out), "lamp %d did not load", i);
        scene_free(&s);
        if (!c[i][2]) {
            CHECK(t, out[0] == '\0', "lamp %d (indices %s): \"%s\", expected no note", i, c[i][1], out);
            continue;
        }
        snprintf(want, sizeof want, "n.pbrt:4: note: area light: %s with opposite windings", c[i][2]);
        CHECK(t, strstr(out, want) != NULL && count_lines(out) == 1, "lamp %d (indices %s): \"%s\", "
              "expected \"%s...\"", i, c[i][1], out, want);
    }
}

const TestCase tests_notes[] = {
    {"notes_unused_medium", test_unused_medium},
    {"notes_power_ignored", test_power_ignored},
    {"notes_area_power", test_area_power},
    {"notes_overlapping_lamp", test_overlapping_lamp},
    {NULL, NULL}
};
