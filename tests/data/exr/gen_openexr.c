/* tests/data/exr/gen_openexr.c - writes the OpenEXR fixtures of tests/test_exr.c
   with OpenEXR's own library (its C interface, ImfCRgbaFile.h, declared below), so
   that the reader is checked against files it did not write itself.  Not part of
   the build: specnee never depends on OpenEXR.  Made with the OpenEXR 3.1 that the
   pbrt-v4 oracle links (libOpenEXR-3_1.so.30):
     cc -o gen gen_openexr.c -L$LIB -l:libOpenEXR-3_1.so.30 && LD_LIBRARY_PATH=$LIB ./gen
   The pixel values are the ones test_exr.c computes (exr_value): all exact in half. */
#include <stdio.h>
#include <stdlib.h>
#include <stddef.h>

typedef unsigned short ImfHalf;
typedef struct { ImfHalf r, g, b, a; } ImfRgba;
typedef struct ImfHeader ImfHeader;
typedef struct ImfOutputFile ImfOutputFile;
typedef struct ImfTiledOutputFile ImfTiledOutputFile;
ImfHeader *ImfNewHeader(void);
void ImfDeleteHeader(ImfHeader *hdr);
void ImfHeaderSetDisplayWindow(ImfHeader *hdr, int xMin, int yMin, int xMax, int yMax);
void ImfHeaderSetDataWindow(ImfHeader *hdr, int xMin, int yMin, int xMax, int yMax);
void ImfHeaderSetLineOrder(ImfHeader *hdr, int lineOrder);
void ImfHeaderSetCompression(ImfHeader *hdr, int compression);
ImfOutputFile *ImfOpenOutputFile(const char name[], const ImfHeader *hdr, int channels);
int ImfOutputSetFrameBuffer(ImfOutputFile *out, const ImfRgba *base, size_t xStride, size_t yStride);
int ImfOutputWritePixels(ImfOutputFile *out, int numScanLines);
int ImfCloseOutputFile(ImfOutputFile *out);
ImfTiledOutputFile *ImfOpenTiledOutputFile(const char name[], const ImfHeader *hdr, int channels,
                                           int xSize, int ySize, int mode, int rmode);
int ImfTiledOutputSetFrameBuffer(ImfTiledOutputFile *out, const ImfRgba *base, size_t xStride,
                                 size_t yStride);
int ImfTiledOutputWriteTiles(ImfTiledOutputFile *out, int dxMin, int dxMax, int dyMin, int dyMax,
                             int lx, int ly);
int ImfCloseTiledOutputFile(ImfTiledOutputFile *out);
int ImfFloatToHalf(float f, ImfHalf *h);
const char *ImfErrorMessage(void);

#define WRITE_RGB 0x07
#define WRITE_RGBA 0x0f
#define WRITE_Y 0x10

/* The same pattern as test_exr.c's exr_value: channel c of pixel (x, y), in the
   coordinates of the data window. */
static float value(int x, int y, int c)
{
    if (c == 0) return (float)(x / 4) * 0.125f;                   /* runs of 4 */
    if (c == 1) return (float)y * 0.5f - 2.0f;                    /* negative too */
    if ((x + y) % 5 == 0) return 1.0f / 1048576.0f;               /* 2^-20: subnormal in half */
    if ((x + y) % 7 == 0) return 65504.0f;                        /* the largest half */
    return 1.0f + (float)(x % 3) * 0.25f;
}

static void write(const char *name, int comp, int order, int channels, int x0, int y0, int w, int h,
                  int grey)
{
    ImfHeader *hd = ImfNewHeader();
    ImfRgba *px = (ImfRgba *)malloc(sizeof *px * (size_t)w * (size_t)h);
    ImfOutputFile *f;
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            ImfRgba *p = px + (size_t)y * w + x;
            ImfFloatToHalf(grey ? value(x, y, 0) : value(x, y, 0), &p->r);
            ImfFloatToHalf(grey ? value(x, y, 0) : value(x, y, 1), &p->g);
            ImfFloatToHalf(grey ? value(x, y, 0) : value(x, y, 2), &p->b);
            ImfFloatToHalf(0.5f, &p->a);
        }
    ImfHeaderSetDisplayWindow(hd, 0, 0, 15, 15);
    ImfHeaderSetDataWindow(hd, x0, y0, x0 + w - 1, y0 + h - 1);
    ImfHeaderSetLineOrder(hd, order);
    ImfHeaderSetCompression(hd, comp);
    f = ImfOpenOutputFile(name, hd, channels);
    if (!f) { fprintf(stderr, "%s: %s\n", name, ImfErrorMessage()); exit(1); }
    ImfOutputSetFrameBuffer(f, px - x0 - (ptrdiff_t)y0 * w, 1, (size_t)w);
    if (!ImfOutputWritePixels(f, h)) { fprintf(stderr, "%s: %s\n", name, ImfErrorMessage()); exit(1); }
    ImfCloseOutputFile(f);
    ImfDeleteHeader(hd);
    free(px);
}

int main(void)
{
    ImfHeader *hd;
    ImfTiledOutputFile *t;
    ImfRgba px[16];
    int i;
    write("rgb-none.exr", 0, 0, WRITE_RGB, 0, 0, 13, 18, 0);
    write("rgb-rle.exr", 1, 0, WRITE_RGB, 0, 0, 13, 18, 0);
    write("rgb-zips-decreasing.exr", 2, 1, WRITE_RGB, 0, 0, 13, 18, 0);
    write("rgba-zip-window.exr", 3, 0, WRITE_RGBA, -3, 5, 13, 18, 0);
    write("y-zip.exr", 3, 0, WRITE_Y, 0, 0, 13, 18, 1);
    write("rgb-piz.exr", 4, 0, WRITE_RGB, 0, 0, 4, 4, 0);
    for (i = 0; i < 16; i++) px[i].r = px[i].g = px[i].b = px[i].a = 0x3c00;   /* 1.0 */
    hd = ImfNewHeader();
    ImfHeaderSetDisplayWindow(hd, 0, 0, 3, 3);
    ImfHeaderSetDataWindow(hd, 0, 0, 3, 3);
    ImfHeaderSetCompression(hd, 3);
    t = ImfOpenTiledOutputFile("rgb-tiled.exr", hd, WRITE_RGB, 4, 4, 0, 0);
    if (!t) { fprintf(stderr, "tiled: %s\n", ImfErrorMessage()); return 1; }
    ImfTiledOutputSetFrameBuffer(t, px, 1, 4);
    ImfTiledOutputWriteTiles(t, 0, 0, 0, 0, 0, 0);
    ImfCloseTiledOutputFile(t);
    ImfDeleteHeader(hd);
    return 0;
}
