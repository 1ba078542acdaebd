/* tests/test_overlap.c - an area light made of triangles that lie on each other
   with opposite windings (an exporter's way to light both sides).

     overlap_coincident_lamp  a square lamp of two triangles, each written twice
                              with opposite windings, seen from below (straight
                              on, nothing else in the scene): where a ray meets
                              both twins at the same t, specnee shows the earlier
                              in the file (the smaller primitive id wins a tie,
                              bvh.c), so the lamp is lit (luminance about 0.9: rays
                              whose two t round apart take the nearer) when the
                              down-facing twins come first and dark (about 0.1)
                              when the up-facing ones do.

   pbrt-v4 (commit 5f7a6068) breaks the tie by the order its BVH build puts the
   primitives in, which no rule of the file gives: it rendered this text (with
   "Sampler \"independent\"" added; pbrt --spp 64 --seed S, S = 1..4) as image
   luminance 0.0934 +- 0.0018 with the down-facing twins first, 0.8990 +- 0.0016
   with the up-facing ones first (the later twin wins in both), while inside a
   box (docs/conventions.md §3) the same four triangles in the same order show the
   earlier twin of one pair and the later of the other.  Where the back twin wins,
   both renderers lose light: next event estimation reaches the emitting twin
   through the other while BSDF sampling stops at its back.  The scene has no
   definite meaning, so specnee keeps its own deterministic rule and says so in a
   note at load time (scene.c). */
#include "test.h"
#include <string.h>

static void test_coincident_lamp(T *t)
{
    static const char *const order[2] = { "0 1 2  0 2 1  0 2 3  0 3 2", "0 2 1  0 1 2  0 3 2  0 2 3" };
    int c;
    for (c = 0; c < 2; c++) {
        char text[2048];
        Scene s;
        RenderOptions o;
        Tiles tl;
        double Y;
        snprintf(text, sizeof text,
                 "LookAt 0 0 0  0 1 0  0 0 1\nCamera \"perspective\" \"float fov\" [ 60 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" \"x.pfm\"\n"
                 "PixelFilter \"box\"\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
                 "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
                 "Shape \"trianglemesh\" \"point3 P\" [ -1 1 -1  1 1 -1  1 1 1  -1 1 1 ] \"integer indices\" [ %s ]\n"
                 "AttributeEnd\n", order[c]);
        if (!test_load_scene(t, &s, text)) return;
        CHECK(t, s.n_tris == 4 && s.n_emitters == 1, "one lamp of four triangles");
        render_options_default(&o);
        o.spp = test_scaled(16, 4);
        o.maxdepth = 1;
        if (!test_render_tiles(t, &s, &o, 2, 1, &tl)) { scene_free(&s); return; }
        scene_free(&s);
        Y = test_luminance(tl.mean[0]);
        CHECK(t, c == 0 ? Y > 0.8 : Y < 0.2, "%s twins first: lamp luminance %.4f, expected %s",
              c == 0 ? "down-facing" : "up-facing", Y, c == 0 ? "> 0.8" : "< 0.2");
    }
}

const TestCase tests_overlap[] = {
    { "overlap_coincident_lamp", test_coincident_lamp },
    { NULL, NULL }
};
