/* tests/test_colorspace.c - the ColorSpace directive (rgbfit.c's colour spaces,
   docs/spectra.md): each space's matrix from its primaries and white, the rgb ->
   spectrum -> rgb round trip in each space, a small scene per space against
   frozen pbrt-v4 values, what the space leaves alone (images, the state after
   AttributeEnd), the default light of each space, and the refusals. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

/* The primaries of pbrt-v4's four spaces (src/pbrt/util/colorspace.cpp), in
   COLORSPACE_* order, written again here so that the test does not read
   rgbfit.c's table. */
static const double primaries[COLORSPACE_N][3][2] = {
    { { .64, .33 }, { .3, .6 }, { .15, .06 } },
    { { .68, .32 }, { .265, .69 }, { .15, .06 } },
    { { .708, .292 }, { .170, .797 }, { .131, .046 } },
    { { .7347, .2653 }, { 0., 1. }, { .0001, -.077 } } };
static const char *const space_names[COLORSPACE_N] = { "srgb", "dci-p3", "rec2020", "aces2065-1" };

/* The matrix maps each primary's XYZ to a multiple of its axis and the white's
   XYZ (integrated from the space's white spectrum) to (1, 1, 1).  sRGB keeps
   pbrt-v4's printed constants, whose white is D65 as pbrt-v4 integrates it:
   within 2e-4 of specnee's D65 (measured 1.4e-4); the others are built from
   specnee's own white: within 1e-9. */
static void test_colorspace_matrix(T *t)
{
    int cs, j, i;
    CHECK(t, colorspace_index("srgb") == 0 && colorspace_index("DCI-P3") == 1 &&
          colorspace_index("Rec2020") == 2 && colorspace_index("aces2065-1") == COLORSPACE_ACES &&
          colorspace_index("aces") < 0 && colorspace_index("srgbx") < 0 && colorspace_index("") < 0,
          "colorspace_index: pbrt-v4's four names, case-insensitive, nothing else");
    for (cs = 0; cs < COLORSPACE_N; cs++) {
        double m[3][3], xyz[3], rgb[3], wx, wy, tol = cs ? 1e-9 : 2e-4;
        Spectrum w;
        CHECK(t, !strcmp(colorspace_name(cs), space_names[cs]), "colorspace_name(%d)", cs);
        colorspace_from_xyz(cs, m);
        for (j = 0; j < 3; j++) {
            double x = primaries[cs][j][0], y = primaries[cs][j][1];
            xyz[0] = x / y; xyz[1] = 1.0; xyz[2] = (1.0 - x - y) / y;
            colorspace_rgb_from_xyz(cs, xyz, rgb);
            for (i = 0; i < 3; i++)
                if (i != j)
                    CHECK(t, fabs(rgb[i]) < 1e-9 * fabs(rgb[j]) + (cs ? 0.0 : 1e-4 * fabs(rgb[j])),
                          "%s: primary %d maps to (%g %g %g)", space_names[cs], j, rgb[0], rgb[1], rgb[2]);
        }
        colorspace_illuminant(cs, &w);
        spec_chromaticity(&w, &wx, &wy);
        xyz[0] = wx / wy; xyz[1] = 1.0; xyz[2] = (1.0 - wx - wy) / wy;
        colorspace_rgb_from_xyz(cs, xyz, rgb);
        for (i = 0; i < 3; i++)
            CHECK(t, fabs(rgb[i] - 1.0) < tol, "%s: its white maps to (%.9f %.9f %.9f)",
                  space_names[cs], rgb[0], rgb[1], rgb[2]);
    }
}

/* pbrt-v4's illum-acesD60: CIE daylight at 6000 K with M1 = -0.536, M2 = -0.519
   (its 5 nm table: 2.55 at 310 nm, 0.02928 at 300 nm, from S0 6.0, S1 4.5, S2
   2.0 at 310 nm), Y-normalised as stdillum-D65: the ratio to S0 + M1 S1 + M2 S2 is
   the same at 360, 560 and 830 nm, and its chromaticity is ACES's white
   (0.32168, 0.33767) within 3e-4 (the locus is 1.3e-4 off in y). */
static void test_colorspace_aces_white(T *t)
{
    static const struct { int nm; double s0, s1, s2; } rows[3] = {
        { 360, 61.5, 38.0, 5.3 }, { 560, 100.0, 0.0, 0.0 }, { 830, 61.9, -9.8, 6.5 } };
    Spectrum w;
    double x, y, k = 0.0;
    int i;
    CHECK(t, spec_named(&w, "illum-acesD60") && spec_named(&w, "ILLUM-ACESd60"), "illum-acesD60 unknown");
    for (i = 0; i < 3; i++) {
        double d = rows[i].s0 - 0.536 * rows[i].s1 - 0.519 * rows[i].s2, r = spec_get(&w, rows[i].nm) / d;
        if (i == 0) k = r;
        CHECK(t, fabs(r - k) < 1e-5 * k, "illum-acesD60 at %d nm: %g, want %g", rows[i].nm,
              spec_get(&w, rows[i].nm), k * d);
    }
    spec_chromaticity(&w, &x, &y);
    CHECK(t, fabs(x - 0.32168) < 3e-4 && fabs(y - 0.33767) < 3e-4, "illum-acesD60 at xy (%.5f, %.5f)", x, y);
    CHECK(t, fabs(spec_to_y(&w) - 1.0) < 2e-3, "illum-acesD60: Y = %g, not about 1", spec_to_y(&w));
}

/* rgb -> spectrum -> rgb in each space: the spectrum's XYZ under the space's
   white (a reflectance) or as it is (an illuminant, over Y of the white), through
   the space's matrix.  The colours are sRGB's 5^3 grid 0.2..0.8 as the space
   writes them (the same real reflectances, inside every space's reach).
   Tolerance 2e-4 in sRGB (measured 1.3e-4: its matrix is pbrt-v4's constants,
   whose white is 1.5e-4 off specnee's D65), 2e-5 in the others (measured below
   1e-6: the matrix is built from specnee's own white). */
static double round_trip(T *t, RgbTable *tab, int cs, const float rgb[3], int illum)
{
    Spectrum s, w;
    Error e;
    double xyz[3], out[3], err = 0.0, yw;
    int k, i;
    if (!spec_from_rgb_t(tab, &s, rgb, illum, &e, "t", 1)) {
        test_failf(t, __FILE__, __LINE__, "%s", e.msg);
        return 1.0;
    }
    colorspace_illuminant(cs, &w);
    yw = spec_to_y(&w);
    if (!illum)
        for (i = 0; i < SPEC_N; i++) s.v[i] *= w.v[i];
    spec_to_xyz(&s, (float)SPEC_MIN, (float)SPEC_MAX, xyz);
    for (k = 0; k < 3; k++) xyz[k] /= yw;
    colorspace_rgb_from_xyz(cs, xyz, out);
    for (k = 0; k < 3; k++) err = fmax(err, fabs(out[k] - rgb[k]));
    return err;
}

static void test_colorspace_round_trip(T *t)
{
    double to_xyz[3][3], m[3][3];
    int cs, a, b, c, k;
    {   /* sRGB -> XYZ: the inverse of sRGB's matrix, column by column */
        double e[3];
        colorspace_from_xyz(0, m);
        for (k = 0; k < 3; k++) {
            double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                       - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                       + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
            double A[3][3];
            int r, q;
            e[0] = e[1] = e[2] = 0.0;
            e[k] = 1.0;
            for (q = 0; q < 3; q++) {          /* Cramer: column q replaced by e */
                memcpy(A, m, sizeof A);
                for (r = 0; r < 3; r++) A[r][q] = e[r];
                to_xyz[q][k] = (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1])
                              - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0])
                              + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0])) / det;
            }
        }
    }
    for (cs = 0; cs < COLORSPACE_N; cs++) {
        RgbTable *tab = rgb_table_new_cs(cs);
        double worst[2] = { 0.0, 0.0 };
        CHECK(t, tab != NULL && rgb_table_space(tab) == cs, "rgb_table_new_cs(%d)", cs);
        if (!tab) return;
        colorspace_from_xyz(cs, m);
        for (a = 0; a < 5; a++)
            for (b = 0; b < 5; b++)
                for (c = 0; c < 5; c++) {
                    double s[3] = { 0.2 + 0.15 * a, 0.2 + 0.15 * b, 0.2 + 0.15 * c }, xyz[3];
                    float rgb[3], lit[3];
                    int ok = 1, r;
                    for (r = 0; r < 3; r++) xyz[r] = to_xyz[r][0] * s[0] + to_xyz[r][1] * s[1] + to_xyz[r][2] * s[2];
                    for (r = 0; r < 3; r++) {
                        rgb[r] = (float)(m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2]);
                        lit[r] = 3.0f * rgb[r];
                        ok &= rgb[r] > 0.0f && rgb[r] < 1.0f;
                    }
                    CHECK(t, ok, "%s: sRGB (%g %g %g) is (%g %g %g)", space_names[cs], s[0], s[1], s[2],
                          rgb[0], rgb[1], rgb[2]);
                    if (!ok) continue;
                    worst[0] = fmax(worst[0], round_trip(t, tab, cs, rgb, 0));
                    worst[1] = fmax(worst[1], round_trip(t, tab, cs, lit, 1) / 3.0);
                }
        if (getenv("DBG")) printf("%s: round trip %.3g (reflectance), %.3g (illuminant)\n",
                                  space_names[cs], worst[0], worst[1]);
        CHECK(t, worst[0] < (cs ? 2e-5 : 2e-4) && worst[1] < (cs ? 2e-5 : 2e-4), "%s: rgb round trip off by %g (reflectance), "
              "%g (illuminant, relative)", space_names[cs], worst[0], worst[1]);
        rgb_table_free(tab);
    }
}

/* A diffuse quad of "rgb reflectance" [0.6 0.4 0.3] lit by a two-sided quad of
   "rgb L" [1 0.6 0.3] (scale 4) in the top right, both read in the ColorSpace
   given before the Film (the fifth scene: rec2020 after the Film, which pbrt-v4
   renders as the fourth to 5 digits: its film keeps the space it was given, and
   converts to sRGB to write a PFM).  The frozen values are pbrt-v4's (5f7a6068)
   mean R, G, B of the image and its quadrants (top left, top right, bottom left,
   bottom right) at 16384 spp, Sampler "independent", from
       pbrt --spp 16384 --seed 1 --nthreads 2 --outfile cs.pfm cs.pbrt
   with cs.pbrt the scene below.  specnee: 6 seeds, each channel of each region
   within TEST_K_SIGMA standard errors + 1 % (the sRGB scene's own offset against
   pbrt-v4 is up to 0.4 %). */
static void cs_scene(char *buf, size_t cap, const char *before, const char *after)
{
    snprintf(buf, cap,
             "%s\n"
             "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32 \"string filename\" \"cs.pfm\"\n"
             "%s\n"
             "PixelFilter \"box\"\n"
             "Camera \"perspective\" \"float fov\" 40\n"
             "WorldBegin\n"
             "AttributeBegin\n"
             " AreaLightSource \"diffuse\" \"rgb L\" [ 1 0.6 0.3 ] \"float scale\" 4 \"bool twosided\" true\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ 1 0.5 2  3 0.5 2  3 2.5 2  1 2.5 2 ]\n"
             "AttributeEnd\n"
             "AttributeBegin\n"
             " Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.4 0.3 ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -3 -3 5  3 -3 5  3 3 5  -3 3 5 ]\n"
             "AttributeEnd\n", before, after);
}

static void test_colorspace_against_pbrt(T *t)
{
    static const char *const before[5] = { "ColorSpace \"srgb\"", "ColorSpace \"dci-p3\"",
        "ColorSpace \"rec2020\"", "ColorSpace \"aces2065-1\"", "" };
    static const double pbrt[5][5][3] = {
        { { 0.11543, 0.04744, 0.01671 }, { 0.08865, 0.03643, 0.01284 }, { 0.21161, 0.08696, 0.03064 },
          { 0.05371, 0.02207, 0.00778 }, { 0.10774, 0.04429, 0.01561 } },
        { { 0.13375, 0.04501, 0.01339 }, { 0.10272, 0.03457, 0.01028 }, { 0.24520, 0.08250, 0.02454 },
          { 0.06224, 0.02094, 0.00623 }, { 0.12485, 0.04202, 0.01250 } },
        { { 0.17737, 0.04052, 0.01249 }, { 0.13622, 0.03112, 0.00959 }, { 0.32517, 0.07428, 0.02289 },
          { 0.08254, 0.01885, 0.00581 }, { 0.16557, 0.03783, 0.01166 } },
        { { 0.29162, 0.03557, 0.00862 }, { 0.22395, 0.02732, 0.00662 }, { 0.53464, 0.06521, 0.01579 },
          { 0.13571, 0.01655, 0.00401 }, { 0.27219, 0.03321, 0.00805 } },
        { { 0.17738, 0.04052, 0.01249 }, { 0.13622, 0.03112, 0.00959 }, { 0.32518, 0.07428, 0.02289 },
          { 0.08254, 0.01885, 0.00581 }, { 0.16557, 0.03783, 0.01166 } } };
    static const char *const region[5] = { "image", "top left", "top right", "bottom left", "bottom right" };
    static char buf[4096];
    int i, q, c;
    for (i = 0; i < 5; i++) {
        RenderOptions o;
        Scene s;
        Tiles tl;
        cs_scene(buf, sizeof buf, before[i], i == 4 ? "ColorSpace \"rec2020\"" : "");
        if (!test_load_scene(t, &s, buf)) return;
        render_options_default(&o);
        o.spp = test_scaled(256, 64);
        o.seed = 3;
        o.threads = 2;
        if (!test_render_tiles(t, &s, &o, 6, 2, &tl)) { scene_free(&s); return; }
        for (c = 0; c < 3; c++) {
            double m = 0.0, se = 0.0;
            for (q = 0; q < 4; q++) { m += 0.25 * tl.mean[q][c]; se += 0.0625 * tl.se[q][c] * tl.se[q][c]; }
            se = sqrt(se);
            for (q = 0; q < 5; q++) {
                double v = q ? tl.mean[q - 1][c] : m, e = q ? tl.se[q - 1][c] : se;
                if (getenv("DBG")) printf("%s %s %c: %.5f +- %.5f, pbrt-v4 %.5f\n", before[i][0] ? before[i] : "late",
                                          region[q], "RGB"[c], v, e, pbrt[i][q][c]);
                CHECK(t, fabs(v - pbrt[i][q][c]) < TEST_K_SIGMA * e + 0.01 * pbrt[i][q][c],
                      "%s: %s %c = %.5f +- %.2g, pbrt-v4 %.5f", i < 4 ? before[i] : "rec2020 after Film",
                      region[q], "RGB"[c], v, e, pbrt[i][q][c]);
            }
        }
        scene_free(&s);
    }
}

/* Render text at 4 spp, seed 1 (for comparisons bit for bit). */
static int render4(T *t, const char *text, Image *im)
{
    RenderOptions o;
    render_options_default(&o);
    o.spp = 4;
    o.seed = 1;
    o.threads = 2;
    return test_render_text(t, text, &o, im);
}

static int images_equal(const Image *a, const Image *b)
{
    return a->w == b->w && a->h == b->h &&
           !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

/* A 16 x 16 scene (film, camera, then `world` after WorldBegin) rendered without
   and with ColorSpace "rec2020" before WorldBegin: the same image bit for bit. */
static void cs_leaves_alone(T *t, const char *world, const char *what)
{
    static char a[4096], b[4096];
    Image ia, ib;
    int i;
    for (i = 0; i < 2; i++) {
        const int n = snprintf(i ? b : a, sizeof a,
                 "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"string filename\" \"cs.pfm\"\n"
                 "Camera \"perspective\" \"float fov\" 40\n"
                 "%s\n"
                 "WorldBegin\n"
                 "%s",
                 i ? "ColorSpace \"rec2020\"" : "", world);
        CHECK(t, n > 0 && n < (int)sizeof a, "%s: the scene text does not fit %d bytes", what, (int)sizeof a);
    }
    if (!render4(t, a, &ia)) return;
    if (!render4(t, b, &ib)) { img_free(&ia); return; }
    CHECK(t, images_equal(&ia, &ib), "ColorSpace \"rec2020\" changed %s", what);
    img_free(&ia); img_free(&ib);
}

/* What the space leaves alone: a ColorSpace inside AttributeBegin/End,
   ObjectBegin/End or an Import ends with it (pbrt-v4's graphics state); an
   imagemap texture's pixels stay sRGB (pbrt-v4 reads an image in the file's own
   space: sRGB for PFM), and so do an environment map's.  Each: the image bit for
   bit the same as with no ColorSpace at all.  (A reflectance texture's texels are
   fitted by Newton from the previous texel in sRGB, texture.c, and reach the
   table only where that fails: the environment map's texels, illuminants, are
   fitted from the table and show a wrong one.) */
static void test_colorspace_scope(T *t)
{
    static char a[4096], b[4096];
    Image ia, ib, px;
    const char *tex;
    int i;
    /* the state */
    static const char *const blocks[3] = { "AttributeBegin\nColorSpace \"rec2020\"\nAttributeEnd\n",
        "ObjectBegin \"o\"\nColorSpace \"rec2020\"\nObjectEnd\n", "Import \"%s\"\n" };
    char block[512];
    cs_scene(a, sizeof a, "", "");
    if (!render4(t, a, &ia)) return;
    for (i = 0; i < 3; i++) {
        const char *w = strstr(a, "WorldBegin\n") + 11;
        snprintf(block, sizeof block, blocks[i], test_write_file(t, "cs_import.pbrt", "ColorSpace \"aces2065-1\"\n"));
        snprintf(b, sizeof b, "%.*s%s%s", (int)(w - a), a, block, w);
        if (!render4(t, b, &ib)) { img_free(&ia); return; }
        CHECK(t, images_equal(&ia, &ib), "a ColorSpace inside %s outlives it", i == 0 ? "AttributeBegin/End" :
              i == 1 ? "ObjectBegin/End" : "an Import");
        img_free(&ib);
    }
    img_free(&ia);
    /* an image texture, under a spectrum light */
    if (!img_alloc(&px, 4, 4)) { CHECK(t, 0, "out of memory"); return; }
    for (i = 0; i < 48; i++) px.rgb[i] = 0.1f + 0.05f * (float)(i % 13);
    tex = test_path(t, "cs_tex.pfm");
    CHECK(t, pfm_write(&px, tex), "cannot write %s", tex);
    img_free(&px);
    snprintf(b, sizeof b,
             "LightSource \"infinite\" \"spectrum L\" \"stdillum-D65\"\n"
             "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\"\n"
             "Material \"diffuse\" \"texture reflectance\" \"t\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -3 -3 5  3 -3 5  3 3 5  -3 3 5 ]  \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n", tex);
    cs_leaves_alone(t, b, "an imagemap texture's colours");
    /* an environment map (an illuminant image: each texel fitted from the table) */
    snprintf(b, sizeof b,
             "LightSource \"infinite\" \"string filename\" \"%s\"\n"
             "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
             "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "  \"point3 P\" [ -3 -3 5  3 -3 5  3 3 5  -3 3 5 ]\n", tex);
    cs_leaves_alone(t, b, "an environment map's colours");
}

/* A light without L shines the space's white: in aces2065-1 it is illum-acesD60
   (pbrt-v4's colorSpace->illuminant), for an area, a point, a spot, an infinite
   and a goniometric light, within 1e-5 of the same light given
   "spectrum L" "illum-acesD60" in sRGB (not bit for bit: the rgb path rounds its
   Y once more).  And "rgb L" [1 1 1] in that space is the same white. */
static void test_colorspace_default_light(T *t)
{
    static const char *const lights[5][2] = {
        { "AttributeBegin\nAreaLightSource \"diffuse\" %s\nShape \"trianglemesh\" \"integer indices\" "
          "[ 0 1 2 0 2 3 ] \"point3 P\" [ 1 0.5 2  3 0.5 2  3 2.5 2  1 2.5 2 ]\nAttributeEnd\n", "area" },
        { "LightSource \"point\" \"point3 from\" [ 1 1 2 ] %s\n", "point" },
        { "LightSource \"spot\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ 0 0 1 ] %s\n", "spot" },
        { "LightSource \"infinite\" %s\n", "infinite" },
        { "AttributeBegin\nTranslate 1 1 2\nLightSource \"goniometric\" \"string filename\" \"%s\" %s\n"
          "AttributeEnd\n", "goniometric" } };
    static char text[3][4096], light[1024];
    Image px;
    int i, k, n;
    const char *gonio;
    if (!img_alloc(&px, 4, 4)) { CHECK(t, 0, "out of memory"); return; }
    for (n = 0; n < 48; n++) px.rgb[n] = 0.2f + 0.05f * (float)(n % 7);
    gonio = test_path(t, "cs_gonio.pfm");
    CHECK(t, pfm_write(&px, gonio), "cannot write %s", gonio);
    img_free(&px);
    for (i = 0; i < 5; i++) {
        Image im[3];
        double worst = 0.0;
        for (k = 0; k < 3; k++) {
            const char *L = k == 0 ? "" : k == 1 ? "\"spectrum L\" \"illum-acesD60\"" : "\"rgb L\" [ 1 1 1 ]";
            if (i == 1 || i == 2 || i == 4)   /* delta lights: I, not L */
                L = k == 0 ? "" : k == 1 ? "\"spectrum I\" \"illum-acesD60\"" : "\"rgb I\" [ 1 1 1 ]";
            if (i == 4) snprintf(light, sizeof light, lights[i][0], gonio, L);
            else snprintf(light, sizeof light, lights[i][0], L);
            snprintf(text[k], sizeof text[k],
                     "%s\nFilm \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"string filename\" \"cs.pfm\"\n"
                     "Camera \"perspective\" \"float fov\" 40\nWorldBegin\n%s"
                     "Material \"diffuse\" \"spectrum reflectance\" [ 360 0.5 830 0.5 ]\n"
                     "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                     "  \"point3 P\" [ -3 -3 5  3 -3 5  3 3 5  -3 3 5 ]\n",
                     k == 1 ? "" : "ColorSpace \"aces2065-1\"", light);
            if (!render4(t, text[k], &im[k])) { while (k-- > 0) img_free(&im[k]); return; }
        }
        for (k = 0; k < 3; k += 2)
            for (n = 0; n < 3 * 16 * 16; n++) {
                double ref = im[1].rgb[n], d = fabs(im[k].rgb[n] - ref);
                worst = fmax(worst, d / fmax(fabs(ref), 1e-3));
            }
        CHECK(t, worst < 1e-5, "%s light in aces2065-1: off illum-acesD60's image by %g (relative)",
              lights[i][1], worst);
        for (k = 0; k < 3; k++) img_free(&im[k]);
    }
}

/* An rgbgrid's "rgb Le" is an RGBIlluminantSpectrum of the space: times its white.
   A grey emitting slab (sigma_a [1 1 1], Le [1 1 1]: constant spectra in any space)
   in aces2065-1 and in srgb, the same seeds: the ratio of the two images' mean R, G,
   B is that of illum-acesD60's and stdillum-D65's sRGB over the film's range,
   within 0.5 % (measured 1e-4; D60 is 8 % less blue). */
static void test_colorspace_rgbgrid_le(T *t)
{
    static char text[4096];
    double mean[2][3], want[3], rgb[2][3];
    int k, c, n;
    for (k = 0; k < 2; k++) {
        Image im;
        snprintf(text, sizeof text,
                 "%s\nMediumInterface \"\" \"g\"\n"
                 "LookAt 0 0 5  0 0 0  0 1 0\n"
                 "Camera \"perspective\" \"float fov\" [ 10 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] \"string filename\" \"t.pfm\"\n"
                 "WorldBegin\n"
                 "MakeNamedMedium \"g\" \"string type\" \"rgbgrid\" \"integer nx\" 1 \"integer ny\" 1 "
                 "\"integer nz\" 1 \"rgb sigma_a\" [ 1 1 1 ] \"rgb sigma_s\" [ 0 0 0 ] \"rgb Le\" [ 1 1 1 ] "
                 "\"point3 p0\" [ -100 -100 0 ] \"point3 p1\" [ 100 100 1 ]\n",
                 k ? "ColorSpace \"aces2065-1\"" : "");
        {
            RenderOptions o;
            render_options_default(&o);
            o.spp = test_scaled(256, 64);
            o.seed = 2;
            o.threads = 2;
            if (!test_render_text(t, text, &o, &im)) return;
        }
        for (c = 0; c < 3; c++) {
            mean[k][c] = 0.0;
            for (n = 0; n < 16; n++) mean[k][c] += im.rgb[3 * n + c] / 16.0;
        }
        img_free(&im);
    }
    for (k = 0; k < 2; k++) {
        Spectrum w;
        double xyz[3];
        spec_named(&w, k ? "illum-acesD60" : "stdillum-D65");
        spec_to_xyz(&w, LAMBDA_LO, LAMBDA_HI, xyz);
        xyz_to_linear_srgb(xyz, rgb[k]);
    }
    for (c = 0; c < 3; c++) {
        want[c] = rgb[1][c] / rgb[0][c];
        if (getenv("DBG")) printf("rgbgrid Le %c: ratio %.4f, want %.4f\n", "RGB"[c], mean[1][c] / mean[0][c], want[c]);
        CHECK(t, mean[0][c] > 0.0 && fabs(mean[1][c] / mean[0][c] - want[c]) < 0.005 * want[c],
              "rgbgrid \"rgb Le\" in aces2065-1: %c ratio %.4f to srgb's, want %.4f", "RGB"[c],
              mean[1][c] / mean[0][c], want[c]);
    }
}

/* Refused by name at the directive's line: an unknown space; a camera sensor or a
   white balance on a Film read in aces2065-1 (they aim at the space's white,
   which sensor.c takes to be D65); a portal light with L in another space. */
static void test_colorspace_refused(T *t)
{
    test_refused(t, "Film \"rgb\" \"string filename\" \"cs.pfm\"\n", "ColorSpace \"adobe-rgb\"\nWorldBegin\n", "cs.pbrt",
                 "cs.pbrt:2: ColorSpace \"adobe-rgb\": unknown colour space (pbrt-v4 knows \"srgb\", "
                 "\"dci-p3\", \"rec2020\" and \"aces2065-1\")");
    test_refused(t, "ColorSpace \"aces2065-1\"\n", "Film \"rgb\" \"float whitebalance\" 5000 \"string filename\" \"cs.pfm\"\nWorldBegin\n",
                 "cs.pbrt", "cs.pbrt:2: Film: \"string sensor\" or \"float whitebalance\" with ColorSpace "
                 "\"aces2065-1\" is not in the specnee subset");
    test_refused(t, "ColorSpace \"aces2065-1\"\n", "Film \"rgb\" \"string sensor\" \"canon_eos_100d\" \"string filename\" \"cs.pfm\"\n"
                 "WorldBegin\n", "cs.pbrt", "cs.pbrt:2: Film: \"string sensor\" or \"float whitebalance\"");
    test_refused(t, "ColorSpace \"rec2020\"\nWorldBegin\n",
                 "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ] \"point3 portal\" [ 0 0 0  1 0 0  1 1 0  0 1 0 ]\n",
                 "cs.pbrt", "cs.pbrt:3: LightSource \"infinite\": a \"portal\" with \"L\" in ColorSpace "
                 "\"rec2020\" is not in the specnee subset");
}

const TestCase tests_colorspace[] = {
    { "colorspace_matrix", test_colorspace_matrix },
    { "colorspace_aces_white", test_colorspace_aces_white },
    { "colorspace_round_trip", test_colorspace_round_trip },
    { "colorspace_against_pbrt", test_colorspace_against_pbrt },
    { "colorspace_scope", test_colorspace_scope },
    { "colorspace_default_light", test_colorspace_default_light },
    { "colorspace_rgbgrid_le", test_colorspace_rgbgrid_le },
    { "colorspace_refused", test_colorspace_refused },
    { NULL, NULL }
};
