/* fuzz/targets.c - the input readers of specnee as fuzz targets.

   Each target takes arbitrary bytes and must come back with either a result or a
   one-line error: no crash, no hang, no leak, no undefined behaviour, and no
   absurd allocation.  The same code serves two drivers:
     fuzz/libfuzzer.c  libFuzzer's entry point (clang -fsanitize=fuzzer, `make fuzz`)
     fuzz/replay.c     a plain C99 program that runs saved inputs through a target;
                       `make test` replays every input that ever crashed
                       (fuzz/regress/TARGET/) and the seeds (fuzz/seeds/TARGET/).

   Targets (name: what the bytes are):
     scene     pbrt-v4 scene text, parsed as if it were scenes/fuzz-input.pbrt (so
               relative names find scenes/meshes/...); a scene that loads is also
               rendered at no more than 8 x 8 pixels, 1 sample per pixel, and must
               give finite pixels (the camera and emitters are validated at load)
     ply       a PLY file
     pfm       a PFM image followed by its sidecar: the last byte b says that the
               last b bytes before it are the sidecar "<image>.txt"; the image is
               read, its sidecar spp is read, and `specnee merge` combines the image
               with itself
     spectrum  a spectrum file (.spd text or CSV)
     png       a PNG file, decoded from memory as sRGB and as linear, then once more
               with every chunk's CRC recomputed (so that mutations reach inflate);
               every value of a decoded image must lie in [0, 1]
     measured  an RGL tensor file (.bsdf, measured.c), read from memory; a BRDF that
               loads must give finite f >= 0 and pdf >= 0, evaluated and sampled
     exr       an OpenEXR file, decoded from memory; a decoded image must have the
               size its pixels were allocated for (values may be anything a float
               holds: the reader keeps them as stored)
     nvdb      a NanoVDB file, its "density" grid read from memory; a grid that
               loads must give finite lookups and a finite majorant over its bounds
     gzip      a gzip file (the container of .pbrt.gz and .ply.gz), inflated from
               memory with a 16 MiB limit; a result is NUL-terminated

   Files go to the directory tmpdir (the drivers give each process its own). */
#include "../specnee.h"
#include <stdlib.h>
#include <string.h>

int fuzz_run(const char *target, const unsigned char *data, size_t n, const char *tmpdir,
             Error *e);

static int write_bytes(const char *path, const unsigned char *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    int ok;
    if (!f) return 0;
    ok = fwrite(data, 1, n, f) == n;
    if (fclose(f) != 0) ok = 0;
    return ok;
}

/* Every error message must be one printable line: no control bytes. */
static void check_message(const Error *e)
{
    const unsigned char *c;
    for (c = (const unsigned char *)e->msg; *c; c++)
        if (*c < 0x20 || *c == 0x7F) abort();
}

static int fuzz_scene(const unsigned char *data, size_t n, Error *e)
{
    char *text = (char *)malloc(n + 1);
    Scene s;
    int loaded;
    if (!text) return 0;
    memcpy(text, data, n);
    text[n] = '\0';
    loaded = scene_load_string(&s, text, "scenes/fuzz-input.pbrt", e);
    if (loaded) {
        RenderOptions o;
        RenderStats st;
        Image img;
        Error re;
        render_options_default(&o);
        o.spp = 1;
        o.threads = 1;
        o.maxdepth = s.settings.maxdepth < 3 ? s.settings.maxdepth : 3;
        o.progress = 0;
        o.sel.strategy = (SelStrategy)(n % SEL_COUNT);
        o.sel.grid_res = 4;
        if (s.settings.xres > 8) s.settings.xres = 8;
        if (s.settings.yres > 8) s.settings.yres = 8;
        memset(&img, 0, sizeof img);
        if (render(&s, &o, &img, &st, &re)) {
            size_t i;
            if (st.nonfinite != 0) abort();
            for (i = 0; i < (size_t)img.w * (size_t)img.h * 3; i++)
                if (!(img.rgb[i] == img.rgb[i]) || img.rgb[i] > 3.0e38f || img.rgb[i] < -3.0e38f)
                    abort();
        } else {
            check_message(&re);
            *e = re;
            loaded = 0;
        }
        img_free(&img);
        scene_free(&s);
    } else {
        check_message(e);
    }
    free(text);
    return loaded;
}

static int fuzz_ply(const unsigned char *data, size_t n, const char *tmpdir, Error *e)
{
    char path[1024];
    PlyMesh m;
    int i;
    snprintf(path, sizeof path, "%s/fuzz-input.ply", tmpdir);
    if (!write_bytes(path, data, n)) return 0;
    if (ply_read(path, &m, e)) {
        for (i = 0; i < 3 * m.n_tris; i++)
            if (m.idx[i] < 0 || m.idx[i] >= m.n_verts) abort();
        for (i = 0; i < 4 * m.n_quads; i++)
            if (m.quads[i] < 0 || m.quads[i] >= m.n_verts) abort();
        ply_free(&m);
        return 1;
    }
    check_message(e);
    return 0;
}

static int fuzz_pfm(const unsigned char *data, size_t n, const char *tmpdir, Error *e)
{
    char path[1024], side[1100], out[1024];
    size_t side_n = n > 0 ? data[n - 1] : 0;
    Image im;
    FILE *null;
    char *argv[6];
    int ok;
    if (n == 0) return 0;
    n--;                                         /* the length byte */
    if (side_n > n) side_n = n;
    snprintf(path, sizeof path, "%s/fuzz-input.pfm", tmpdir);
    snprintf(side, sizeof side, "%s.txt", path);
    snprintf(out, sizeof out, "%s/fuzz-merged.pfm", tmpdir);
    if (!write_bytes(path, data, n - side_n) || !write_bytes(side, data + n - side_n, side_n))
        return 0;
    ok = pfm_read(&im, path, e);
    if (ok) img_free(&im);
    else check_message(e);
    (void)img_read_sidecar_spp(path);
    null = fopen("/dev/null", "w");
    if (!null) return ok;
    argv[0] = (char *)"merge"; argv[1] = path; argv[2] = path;
    argv[3] = (char *)"-o"; argv[4] = out; argv[5] = NULL;
    (void)img_cmd_merge(5, argv, null, null);
    fclose(null);
    return ok;
}

static int fuzz_spectrum(const unsigned char *data, size_t n, const char *tmpdir, Error *e)
{
    char path[1024];
    Spectrum s;
    snprintf(path, sizeof path, "%s/fuzz-input.spd", tmpdir);
    if (!write_bytes(path, data, n)) return 0;
    if (spec_from_file(&s, path, e)) {
        int i;
        for (i = 0; i < SPEC_N; i++)
            if (!(s.v[i] == s.v[i]) || s.v[i] > 3.0e38f || s.v[i] < -3.0e38f) abort();
        return 1;
    }
    check_message(e);
    return 0;
}

/* The bytes with every chunk's CRC recomputed, so that mutated data reaches
   inflate and the filters instead of stopping at the CRC check. */
static void png_fix_crcs(unsigned char *d, size_t n)
{
    size_t pos = 8;
    while (n >= 12 && pos <= n - 12) {
        size_t len = (size_t)d[pos] << 24 | (size_t)d[pos + 1] << 16 | (size_t)d[pos + 2] << 8 | d[pos + 3];
        uint32_t c = 0xffffffffu;
        size_t i;
        int k;
        if (len > n - pos - 12) return;
        for (i = pos + 4; i < pos + 8 + len; i++) {
            c ^= d[i];
            for (k = 0; k < 8; k++) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
        }
        c ^= 0xffffffffu;
        d[pos + 8 + len] = (unsigned char)(c >> 24); d[pos + 9 + len] = (unsigned char)(c >> 16);
        d[pos + 10 + len] = (unsigned char)(c >> 8); d[pos + 11 + len] = (unsigned char)c;
        pos += len + 12;
    }
}

static int fuzz_png(const unsigned char *data, size_t n, Error *e)
{
    unsigned char *fixed = (unsigned char *)malloc(n > 0 ? n : 1);
    int pass, ok = 0;
    if (!fixed) return 0;
    memcpy(fixed, data, n);
    png_fix_crcs(fixed, n);
    for (pass = 0; pass < 3; pass++) {          /* as given (sRGB, linear), CRCs fixed */
        Image im;
        if (png_read_memory(pass < 2 ? data : fixed, n, "fuzz-input.png", pass == 1, &im, e)) {
            size_t i;
            for (i = 0; i < (size_t)im.w * (size_t)im.h * 3; i++)
                if (!(im.rgb[i] >= 0.0f && im.rgb[i] <= 1.0f)) abort();
            img_free(&im);
            if (pass < 2) ok = 1;
        } else {
            check_message(e);
            if (pass == 1 && ok) abort();        /* refused only as linear */
        }
    }
    free(fixed);
    return ok;
}

static int fuzz_measured(const unsigned char *data, size_t n, Error *e)
{
    const float lambda[HERO_N] = { 380, 500, 620, 800 };
    MeasuredBrdf b;
    int i, j;
    if (!measured_read_memory(data, n, "fuzz-input.bsdf", &b, e)) {
        check_message(e);
        return 0;
    }
    for (i = 0; i < 16; i++) {
        float a = 0.1f * (float)i, f[HERO_N], p[HERO_N];
        Vec3 wo = v3(sinf(a) * cosf(3 * a), sinf(a) * sinf(3 * a), cosf(a)), wi;
        BsdfSample bs;
        measured_eval(&b, wo, v3_norm(v3(0.3f - a, 0.2f, 0.5f)), lambda, 15u, f, p);
        for (j = 0; j < HERO_N; j++)
            if (!(f[j] >= 0.0f && f[j] < 1e30f && p[j] >= 0.0f && p[j] < 1e30f)) abort();
        memset(&bs, 0, sizeof bs);
        if (measured_sample(&b, wo, lambda, 15u, 0.07f * (float)i, 0.93f - 0.05f * (float)i, &bs, &wi))
            for (j = 0; j < HERO_N; j++)
                if (!(bs.f[j] >= 0.0f && bs.f[j] < 1e30f && bs.pdf > 0.0f && bs.pdf < 1e30f)) abort();
    }
    measured_free(&b);
    return 1;
}

static int fuzz_exr(const unsigned char *data, size_t n, Error *e)
{
    Image im;
    if (exr_read_memory(data, n, "fuzz-input.exr", &im, e)) {
        volatile float sum = 0.0f;   /* touch every sample: ASan sees a short buffer */
        size_t i;
        if (im.w <= 0 || im.h <= 0 || (long long)im.w * im.h > IMG_MAX_PIXELS) abort();
        for (i = 0; i < (size_t)im.w * (size_t)im.h * 3; i++) sum += im.rgb[i];
        (void)sum;
        img_free(&im);
        return 1;
    }
    check_message(e);
    return 0;
}

static int fuzz_gzip(const unsigned char *data, size_t n, Error *e)
{
    unsigned char *out;
    size_t n_out;
    ReadStatus st = gzip_inflate(data, n, (size_t)1 << 24, &out, &n_out);
    if (st != READ_OK) {
        if (out) abort();
        error_set(e, "fuzz-input.gz", 0, "%s", read_status_text(st));
        check_message(e);
        return 0;
    }
    if (n_out > ((size_t)1 << 24) || out[n_out] != '\0') abort();
    free(out);
    return 1;
}

/* Returns 1 when the input was accepted, 0 when it was refused (e->msg says why),
   -1 for an unknown target. */
static int fuzz_nvdb(const unsigned char *data, size_t n, Error *e)
{
    NanoGrid g;
    float maj[4 * 4 * 4];
    int k, i;
    if (!nanovdb_read_memory(data, n, "fuzz-input.nvdb", "density", &g, e)) {
        check_message(e);
        return 0;
    }
    if (!g.buf) return 1;                       /* no grid of that name */
    for (i = 0; i < 27; i++) {                  /* the bbox's corners, centre, ... */
        double f[3];
        Vec3 p;
        f[0] = 0.5 * (i % 3); f[1] = 0.5 * ((i / 3) % 3); f[2] = 0.5 * (i / 9);
        p = v3((float)(g.wmin[0] + f[0] * (g.wmax[0] - g.wmin[0])), (float)(g.wmin[1] + f[1] * (g.wmax[1] - g.wmin[1])),
               (float)(g.wmin[2] + f[2] * (g.wmax[2] - g.wmin[2])));
        if (!isfinite(nanovdb_sample(&g, p))) abort();
    }
    for (k = 0; k < 3; k++)
        if (!(g.wmin[k] < g.wmax[k]) || !(fabs(g.wmin[k]) < 1e30) || !(fabs(g.wmax[k]) < 1e30)) break;
    if (k == 3) {
        nanovdb_majorant(&g, g.wmin, g.wmax, 4, maj);
        for (i = 0; i < 64; i++)
            if (!isfinite(maj[i]) || maj[i] < 0.0f) abort();
    }
    nanovdb_free(&g);
    return 1;
}

int fuzz_run(const char *target, const unsigned char *data, size_t n, const char *tmpdir,
             Error *e)
{
    e->msg[0] = '\0';
    if (!strcmp(target, "scene")) return fuzz_scene(data, n, e);
    if (!strcmp(target, "ply")) return fuzz_ply(data, n, tmpdir, e);
    if (!strcmp(target, "pfm")) return fuzz_pfm(data, n, tmpdir, e);
    if (!strcmp(target, "spectrum")) return fuzz_spectrum(data, n, tmpdir, e);
    if (!strcmp(target, "png")) return fuzz_png(data, n, e);
    if (!strcmp(target, "exr")) return fuzz_exr(data, n, e);
    if (!strcmp(target, "measured")) return fuzz_measured(data, n, e);
    if (!strcmp(target, "nvdb")) return fuzz_nvdb(data, n, e);
    if (!strcmp(target, "gzip")) return fuzz_gzip(data, n, e);
    return -1;
}
