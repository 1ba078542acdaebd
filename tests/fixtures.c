/* tests/fixtures.c - what the tests share: random numbers drawn in a fixed order;
   loading a scene from text and the checks of refused input; for the statistical
   image tests, rendering K seeds into per-tile means with standard errors, their
   luminance, comparing two such tile sets, the two comparisons with frozen
   pbrt-v4 luminances, the walls of a small test box and the emitting-cube
   furnace; for the tests of samplers, Pearson's chi-square of counts against
   expectations and of sampled directions against a density (test.h says how they
   judge). */
#include "test.h"
#include <stdlib.h>
#include <string.h>



void rng_fill(Rng *r, float *u, int n)
{
    int i;
    for (i = 0; i < n; i++) u[i] = rng_float(r);
}

Vec3 rng_vec3(Rng *r)
{
    float u[3];
    rng_fill(r, u, 3);
    return v3(u[0], u[1], u[2]);
}

int test_bsdf_sample(const Material *m, const SurfacePoint *sp, Vec3 wo, const float *lambda,
                     unsigned alive, Rng *r, BsdfSample *out)
{
    float u[3];
    rng_fill(r, u, 3);
    return bsdf_sample(m, sp, wo, lambda, alive, u[0], u[1], u[2], out);
}

/* Load a scene from text; fails the test on a parse error. */
int test_load_scene(T *t, Scene *s, const char *text)
{
    Error err;
    memset(s, 0, sizeof *s);
    err.msg[0] = 0;
    if (!scene_load_string(s, text, "test.pbrt", &err)) {
        test_failf(t, __FILE__, __LINE__, "scene did not load: %s", err.msg);
        return 0;
    }
    return 1;
}

/* Load head + body as the file `file`; the test fails unless the load is refused
   with a message containing `want`. */
void test_refused(T *t, const char *head, const char *body, const char *file, const char *want)
{
    static char buf[16384];
    Scene s;
    Error err;
    err.msg[0] = 0;
    snprintf(buf, sizeof buf, "%s%s", head, body);
    if (scene_load_string(&s, buf, file, &err)) {
        scene_free(&s);
        test_failf(t, __FILE__, __LINE__, "%s accepted; want \"%s\"", file, want);
        return;
    }
    if (!strstr(err.msg, want)) test_failf(t, __FILE__, __LINE__, "error \"%s\", want \"%s\"", err.msg, want);
}

/* A light statement in a small scene (the light on line 5 of "d.pbrt"): the test
   fails unless the load is refused with one line that starts with `prefix` and
   holds k1 (and k2 unless NULL). */
void test_light_refused(T *t, const char *light, const char *prefix, const char *k1, const char *k2)
{
    char text[2048];
    Scene s;
    Error e;
    int ok;
    snprintf(text, sizeof text,
             "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
             "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ] "
             "\"string filename\" \"d.pfm\"\n"
             "WorldBegin\n%s\n", light);
    e.msg[0] = '\0';
    ok = scene_load_string(&s, text, "d.pbrt", &e);
    if (ok) scene_free(&s);
    CHECK(t, !ok, "accepted \"%s\"", light);
    CHECK(t, strncmp(e.msg, prefix, strlen(prefix)) == 0, "message \"%s\" names no %s", e.msg, prefix);
    CHECK(t, strchr(e.msg, '\n') == NULL, "message \"%s\" is not one line", e.msg);
    CHECK(t, strstr(e.msg, k1) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k1);
    CHECK(t, !k2 || strstr(e.msg, k2) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k2);
}

/* The image's mean luminance over K renders of text (spp samples, NEE on or off,
   2 threads, seeds 1, 1001, 2001, ...) and its standard error. */
int test_mean_y(T *t, const char *text, int spp, int nee, int K, double *mean, double *se)
{
    double sum = 0.0, sum2 = 0.0;
    int k;
    for (k = 0; k < K; k++) {
        RenderOptions o;
        Image im;
        double v;
        render_options_default(&o);
        o.spp = spp;
        o.seed = 1 + 1000 * k;
        o.threads = 2;
        o.nee = nee;
        if (!test_render_text(t, text, &o, &im)) return 0;
        v = test_image_y(&im);
        img_free(&im);
        sum += v;
        sum2 += v * v;
    }
    *mean = sum / K;
    *se = sqrt(fmax(0.0, (sum2 / K - *mean * *mean) * K / (K - 1)) / K);
    return 1;
}

int test_load_fails(T *t, const char *text, const char *k1, const char *k2)
{
    Scene s;
    Error e;
    e.msg[0] = 0;
    if (scene_load_string(&s, text, "m.pbrt", &e)) {
        scene_free(&s);
        test_failf(t, __FILE__, __LINE__, "accepted; expected \"%s\"", k1);
        return 0;
    }
    if (!strstr(e.msg, k1) || (k2 && !strstr(e.msg, k2))) {
        test_failf(t, __FILE__, __LINE__, "message \"%s\" lacks \"%s\" / \"%s\"", e.msg, k1, k2 ? k2 : "");
        return 0;
    }
    return 1;
}

void test_rejected_at(T *t, const char *text, int line, const char *k1, const char *k2)
{
    Scene s;
    Error e;
    char prefix[64];
    int ok;
    e.msg[0] = '\0';
    ok = scene_load_string(&s, text, "t.pbrt", &e);
    if (ok) scene_free(&s);
    CHECK(t, !ok, "accepted bad input, expected an error with \"%s\"", k1);
    snprintf(prefix, sizeof prefix, "t.pbrt:%d:", line);
    CHECK(t, strncmp(e.msg, prefix, strlen(prefix)) == 0, "message \"%s\" does not start with \"%s\"",
          e.msg, prefix);
    CHECK(t, strchr(e.msg, '\n') == NULL, "message \"%s\" is not one line", e.msg);
    CHECK(t, strstr(e.msg, k1) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k1);
    CHECK(t, !k2 || strstr(e.msg, k2) != NULL, "message \"%s\" lacks \"%s\"", e.msg, k2);
}

int test_render_text(T *t, const char *text, const RenderOptions *o, Image *im)
{
    Scene s;
    RenderStats st;
    Error err;
    int ok;
    if (!test_load_scene(t, &s, text)) return 0;
    ok = render(&s, o, im, &st, &err);
    if (!ok) test_failf(t, __FILE__, __LINE__, "render: %s", err.msg);
    scene_free(&s);
    return ok;
}

/* Render K seeds and gather tile statistics. */
int test_render_tiles(T *t, Scene *s, const RenderOptions *base, int K, int n, Tiles *out)
{
    int k, i, c;
    static double sum[MAX_TILES * MAX_TILES][3], sum2[MAX_TILES * MAX_TILES][3];
    memset(sum, 0, sizeof sum);
    memset(sum2, 0, sizeof sum2);
    out->n = n;
    for (k = 0; k < K; k++) {
        RenderOptions o = *base;
        Image img;
        RenderStats st;
        Error err;
        int x, y;
        o.seed = base->seed + 1000 * k;
        if (!render(s, &o, &img, &st, &err)) {
            test_failf(t, __FILE__, __LINE__, "render failed: %s", err.msg);
            return 0;
        }
        if (st.nonfinite) {
            test_failf(t, __FILE__, __LINE__, "%ld non-finite samples reached the film", st.nonfinite);
            img_free(&img);
            return 0;
        }
        for (i = 0; i < n * n; i++) {
            int tx = i % n, ty = i / n, cnt = 0;
            double acc[3] = { 0, 0, 0 };
            for (y = ty * img.h / n; y < (ty + 1) * img.h / n; y++)
                for (x = tx * img.w / n; x < (tx + 1) * img.w / n; x++) {
                    for (c = 0; c < 3; c++) acc[c] += img.rgb[3 * (y * img.w + x) + c];
                    cnt++;
                }
            for (c = 0; c < 3; c++) {
                double m = acc[c] / cnt;
                if (!isfinite(m)) {
                    test_failf(t, __FILE__, __LINE__, "non-finite pixel value");
                    img_free(&img);
                    return 0;
                }
                sum[i][c] += m;
                sum2[i][c] += m * m;
            }
        }
        img_free(&img);
    }
    for (i = 0; i < n * n; i++)
        for (c = 0; c < 3; c++) {
            double m = sum[i][c] / K, var = (sum2[i][c] / K - m * m) * K / (K - 1);
            out->mean[i][c] = m;
            out->se[i][c] = sqrt(var > 0 ? var / K : 0);
        }
    return 1;
}

/* Compare two tile sets; returns 1 if they agree. */
int test_tiles_agree(T *t, const Tiles *a, const Tiles *b, double slack, const char *what)
{
    int i, c;
    for (i = 0; i < a->n * a->n; i++)
        for (c = 0; c < 3; c++) {
            double d = fabs(a->mean[i][c] - b->mean[i][c]);
            double se = sqrt(a->se[i][c] * a->se[i][c] + b->se[i][c] * b->se[i][c]);
            if (d > TEST_K_SIGMA * se + slack) {
                test_failf(t, __FILE__, __LINE__,
                           "%s: tile %d channel %d differs: %.5g vs %.5g (%.1f standard errors of %.3g)",
                           what, i, c, a->mean[i][c], b->mean[i][c], se > 0 ? d / se : 1e9, se);
                return 0;
            }
        }
    return 1;
}

/* An open box [-1,1]^3 without its front: white floor, ceiling and back wall, a
   red-ish left wall and a green-ish right wall (diffuse, inline spectra). */
const char test_box_walls[] =
    "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.8 700 0.7 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3  4 5 6 4 6 7 ]\n"
    "  \"point3 P\" [ -1 -1 -1  1 -1 -1  1 -1 1  -1 -1 1   -1 1 -1  -1 1 1  1 1 1  1 1 -1 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -1 -1 1  1 -1 1  1 1 1  -1 1 1 ]\n"
    "AttributeBegin\n Material \"diffuse\" \"spectrum reflectance\" [ 400 0.05 550 0.1 600 0.6 700 0.7 ]\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -1 -1 -1  -1 -1 1  -1 1 1  -1 1 -1 ]\nAttributeEnd\n"
    "AttributeBegin\n Material \"diffuse\" \"spectrum reflectance\" [ 400 0.1 500 0.5 550 0.6 600 0.1 700 0.05 ]\n"
    " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ 1 -1 -1  1 1 -1  1 1 1  1 -1 1 ]\nAttributeEnd\n";

void test_glass(Material *m, float A, float B, float alpha)
{
    int k;
    memset(m, 0, sizeof *m);
    m->type = MAT_DIELECTRIC;
    {
        Spectrum *eta = test_material_eta();
        for (k = 0; k < SPEC_N; k++) eta->v[k] = cauchy_eta(A, B, (float)(SPEC_MIN + k));
        m->eta = eta;
    }
    m->cauchy_a = A;
    m->cauchy_b = B;
    m->dispersive = B != 0.0f;
    m->alpha = m->alpha_t = alpha;
}

int test_dir_cell(Vec3 w, int nt, int np)
{
    int ct = (int)((w.z + 1.0) * 0.5 * nt), cp;
    double phi = atan2(w.y, w.x);
    if (phi < 0) phi += 2 * SPECNEE_PI;
    cp = (int)(phi / (2 * SPECNEE_PI) * np);
    if (ct >= nt) ct = nt - 1;
    if (ct < 0) ct = 0;
    if (cp >= np) cp = np - 1;
    return ct * np + cp;
}

/* ---- chi-square tests (test.h) */

double chi2_tail(int k, double x)
{
    double a = 0.5 * k, y = 0.5 * x, front;
    int i;
    if (k < 1 || !(y > 0.0)) return 1.0;
    front = exp(a * log(y) - y - lgamma(a));      /* y^a e^-y / Gamma(a) */
    if (y < a + 1.0) {
        /* the lower function P(a, y) = front * sum_n y^n / (a (a+1) ... (a+n)) */
        double term = 1.0 / a, sum = term;
        for (i = 1; i < 100000 && term > 1e-17 * sum; i++) {
            term *= y / (a + i);
            sum += term;
        }
        return 1.0 - front * sum;
    } else {
        /* Q(a, y) = front / (y + 1 - a - 1 (1 - a) / (y + 3 - a - 2 (2 - a) / (y + 5 - a - ...))),
           the continued fraction evaluated forwards (modified Lentz) */
        double b = y + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
        for (i = 1; i < 100000; i++) {
            double an = -i * (i - a), del;
            b += 2.0;
            d = an * d + b;
            if (fabs(d) < 1e-300) d = 1e-300;
            c = b + an / c;
            if (fabs(c) < 1e-300) c = 1e-300;
            d = 1.0 / d;
            del = d * c;
            h *= del;
            if (fabs(del - 1.0) < 1e-15) break;
        }
        return front * h;
    }
}

/* The statistic with the low cells merged, and the verdict against the Sidak-
   corrected level; the message says what failed. */
static int chi2_judge(T *t, const char *file, int line, const double *obs, const double *ex, int n,
                      int n_tests, Chi2 *out, const char *what, va_list ap)
{
    double pool_o = 0.0, pool_e = 0.0, level;
    Chi2 c;
    int i, cells = 0;
    char msg[512];
    c.stat = 0.0;
    c.total = 0.0;
    for (i = 0; i < n; i++) {
        c.total += ex[i];
        if (ex[i] < TEST_CHI2_MIN_EXPECTED) { pool_o += obs[i]; pool_e += ex[i]; continue; }
        c.stat += (obs[i] - ex[i]) * (obs[i] - ex[i]) / ex[i];
        cells++;
    }
    if (pool_e >= TEST_CHI2_MIN_EXPECTED) {
        c.stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        cells++;
    }
    c.dof = cells > 1 ? cells - 1 : 0;
    c.p = c.dof ? chi2_tail(c.dof, c.stat) : 1.0;
    if (out) *out = c;
    level = -expm1(log1p(-TEST_CHI2_ALPHA) / (n_tests > 1 ? n_tests : 1));
    if (c.p >= level) return 1;
    vsnprintf(msg, sizeof msg, what, ap);
    test_failf(t, file, line, "%s: chi-square %.1f with %d dof, p = %.3g < %.3g (%g over %d checks)",
               msg, c.stat, c.dof, c.p, level, TEST_CHI2_ALPHA, n_tests);
    return 0;
}

int test_chi2_at(T *t, const char *file, int line, const double *obs, const double *ex, int n,
                 int n_tests, Chi2 *out, const char *what, ...)
{
    va_list ap;
    int ok;
    va_start(ap, what);
    ok = chi2_judge(t, file, line, obs, ex, n, n_tests, out, what, ap);
    va_end(ap);
    return ok;
}

/* The k-th of the 2 sub nodes in [0, 1) of the composite two-point Gauss-Legendre
   rule on sub equal intervals: (i + 1/2 -+ 1/(2 sqrt 3)) / sub for interval i = k / 2;
   exact for cubics on each interval, and never on an interval's edge. */
static double gauss2(int k, int sub)
{
    return (k / 2 + 0.5 + (k % 2 ? 0.5 : -0.5) / sqrt(3.0)) / sub;
}

int test_chi2_dirs_at(T *t, const char *file, int line, const DirTest *d, Rng *r, int n_tests,
                      Chi2 *out, const char *what, ...)
{
    int cells = d->nt * d->np, i, it, ip, a, b, ok;
    double *obs = (double *)calloc((size_t)cells, sizeof(double));
    double *ex = (double *)calloc((size_t)cells, sizeof(double));
    va_list ap;
    if (!obs || !ex) {
        free(obs);
        free(ex);
        test_failf(t, file, line, "out of memory");
        return 0;
    }
    for (i = 0; i < d->n; i++) {
        Vec3 w;
        if (d->sample(d->ctx, r, &w)) obs[test_dir_cell(w, d->nt, d->np)] += 1.0;
    }
    for (it = 0; it < d->nt; it++)
        for (ip = 0; ip < d->np; ip++) {
            double acc = 0.0;
            for (a = 0; a < 2 * d->sub; a++)
                for (b = 0; b < 2 * d->sub; b++) {
                    double z = -1.0 + 2.0 * (it + gauss2(a, d->sub)) / d->nt;
                    double phi = 2.0 * SPECNEE_PI * (ip + gauss2(b, d->sub)) / d->np;
                    double s = sqrt(fmax(0.0, 1.0 - z * z)), w[3];
                    w[0] = s * cos(phi);
                    w[1] = s * sin(phi);
                    w[2] = z;
                    acc += d->pdf(d->ctx, w);
                }
            ex[it * d->np + ip] = acc / (4 * d->sub * d->sub) * (2.0 / d->nt) * (2.0 * SPECNEE_PI / d->np) * d->n;
        }
    va_start(ap, what);
    ok = chi2_judge(t, file, line, obs, ex, cells, n_tests, out, what, ap);
    va_end(ap);
    free(obs);
    free(ex);
    return ok;
}

int test_bsdf_dir_sample(void *ctx, Rng *r, Vec3 *w)
{
    const BsdfDirs *b = (const BsdfDirs *)ctx;
    BsdfSample bs;
    if (!test_bsdf_sample(b->m, &b->sp, b->wo, b->lambda, 1u, r, &bs)) return 0;
    *w = bs.wi;
    return 1;
}

double test_bsdf_dir_pdf(void *ctx, const double w[3])
{
    const BsdfDirs *b = (const BsdfDirs *)ctx;
    float f[HERO_N], p[HERO_N];
    bsdf_eval(b->m, &b->sp, b->wo, v3((float)w[0], (float)w[1], (float)w[2]), b->lambda, 1u, f, p);
    return p[0];
}

DirTest test_bsdf_dirs(BsdfDirs *b, int n)
{
    DirTest d;
    d.sample = test_bsdf_dir_sample;
    d.pdf = test_bsdf_dir_pdf;
    d.ctx = b;
    d.n = n;
    d.nt = 16;
    d.np = 32;
    d.sub = 8;
    return d;
}

MaterialSpectra *test_material_extra(void)
{
    static MaterialSpectra ring[64];
    static int next;
    MaterialSpectra *x = &ring[next];
    next = (next + 1) % 64;
    memset(x, 0, sizeof *x);
    return x;
}

Spectrum *test_material_eta(void)
{
    static Spectrum ring[64];
    static int next;
    Spectrum *x = &ring[next];
    next = (next + 1) % 64;
    memset(x, 0, sizeof *x);
    return x;
}

const Spectrum *test_eta_const(float eta)
{
    Spectrum *x = test_material_eta();
    spec_const(x, eta);
    return x;
}

const Spectrum *test_eta_named(const char *name)
{
    Spectrum *x = test_material_eta();
    spec_named(x, name);
    return x;
}

SurfacePoint test_flat_point(void)
{
    SurfacePoint sp;
    memset(&sp, 0, sizeof sp);
    sp.ng = sp.ns = v3(0, 0, 1);
    return sp;
}

void test_furnace_text(char *text, size_t n, const char *material)
{
    snprintf(text, n,
             "LookAt 0 0 -1.9  0.8 0.8 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 20 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ] \"string filename\" \"t.pfm\"\n"
             "WorldBegin\n"
             "AttributeBegin\n AreaLightSource \"diffuse\" \"spectrum L\" [ 360 1 830 1 ] \"bool twosided\" true\n"
             " Material \"diffuse\" \"spectrum reflectance\" [ 360 0 830 0 ]\n"
             " Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3  4 5 6 4 6 7  0 1 5 0 5 4  "
             "3 2 6 3 6 7  0 3 7 0 7 4  1 2 6 1 6 5 ]\n"
             "  \"point3 P\" [ -2 -2 -2  2 -2 -2  2 2 -2  -2 2 -2  -2 -2 2  2 -2 2  2 2 2  -2 2 2 ]\n"
             "AttributeEnd\n"
             "AttributeBegin\n Translate 0.8 0.8 0\n %s\n"
             " Shape \"sphere\" \"float radius\" [ 1 ]\nAttributeEnd\n", material);
}

/* K = 10 times: two renders of base->spp samples (seeds 3k+1, 3k+2) merged by
   sample count (img_merge), against one render of twice the samples (seed 3k+3).
   Per 4 x 4 tile and channel the means over k must agree within TEST_K_SIGMA
   standard errors; and the merge of equal counts is exactly the pixels' mean. */
void test_merge_agrees(T *t, const Scene *s, const RenderOptions *base, const char *what)
{
    enum { K = 10, NT = 4 };
    double sm[NT * NT][3], s2m[NT * NT][3], sf[NT * NT][3], s2f[NT * NT][3];
    RenderOptions o = *base;
    int k, i, c;
    memset(sm, 0, sizeof sm); memset(s2m, 0, sizeof s2m); memset(sf, 0, sizeof sf); memset(s2f, 0, sizeof s2f);
    for (k = 0; k < K; k++) {
        Image half[2], merged, full;
        RenderStats st;
        Error err;
        double w[2] = { 1, 1 };
        int x, y, tw, th;
        o.spp = base->spp;
        o.seed = 3 * k + 1;
        CHECK(t, render(s, &o, &half[0], &st, &err), "%s: %s", what, err.msg);
        o.seed = 3 * k + 2;
        CHECK(t, render(s, &o, &half[1], &st, &err), "%s: %s", what, err.msg);
        o.spp = 2 * base->spp;
        o.seed = 3 * k + 3;
        CHECK(t, render(s, &o, &full, &st, &err), "%s: %s", what, err.msg);
        CHECK(t, img_merge(half, w, 2, &merged), "%s: img_merge failed", what);
        tw = full.w / NT; th = full.h / NT;
        for (i = 0; i < NT * NT; i++) {
            double am[3] = { 0, 0, 0 }, af[3] = { 0, 0, 0 };
            int tx = i % NT, ty = i / NT;
            for (y = ty * th; y < (ty + 1) * th; y++)
                for (x = tx * tw; x < (tx + 1) * tw; x++)
                    for (c = 0; c < 3; c++) {
                        am[c] += merged.rgb[3 * (y * full.w + x) + c] / (tw * th);
                        af[c] += full.rgb[3 * (y * full.w + x) + c] / (tw * th);
                    }
            for (c = 0; c < 3; c++) {
                sm[i][c] += am[c]; s2m[i][c] += am[c] * am[c];
                sf[i][c] += af[c]; s2f[i][c] += af[c] * af[c];
            }
        }
        CHECK(t, fabsf(merged.rgb[0] - 0.5f * (half[0].rgb[0] + half[1].rgb[0])) <= 1e-6f * fabsf(merged.rgb[0]) + 1e-9f,
              "%s: the merge of equal counts is not the mean", what);
        img_free(&half[0]); img_free(&half[1]); img_free(&merged); img_free(&full);
    }
    for (i = 0; i < NT * NT; i++)
        for (c = 0; c < 3; c++) {
            double mm = sm[i][c] / K, mf = sf[i][c] / K;
            double vm = (s2m[i][c] / K - mm * mm) / (K - 1), vf = (s2f[i][c] / K - mf * mf) / (K - 1);
            double se = sqrt((vm > 0 ? vm : 0) + (vf > 0 ? vf : 0));
            CHECK(t, fabs(mm - mf) < TEST_K_SIGMA * se + 1e-5, "%s: tile %d ch %d: merged %.5g vs full %.5g (se %.2g)",
                  what, i, c, mm, mf, se);
        }
}

double test_luminance(const double rgb[3])
{
    return 0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2];
}

double test_image_y(const Image *im)
{
    double acc = 0.0;
    int i;
    for (i = 0; i < im->w * im->h; i++)
        acc += 0.212671 * im->rgb[3 * i] + 0.715160 * im->rgb[3 * i + 1] + 0.072169 * im->rgb[3 * i + 2];
    return acc / (im->w * im->h);
}

/* The channels' standard errors taken as independent: se(Y)^2 = sum_c w_c^2 se_c^2. */
double test_tile_y(const Tiles *tl, int i, double *se)
{
    *se = sqrt(0.212671 * 0.212671 * tl->se[i][0] * tl->se[i][0] +
               0.715160 * 0.715160 * tl->se[i][1] * tl->se[i][1] +
               0.072169 * 0.072169 * tl->se[i][2] * tl->se[i][2]);
    return test_luminance(tl->mean[i]);
}

/* The whole image is rendered once more as one tile (the same seeds, so the same
   images) for its own standard error over the seeds. */
void test_scene_against_pbrt_y(T *t, Scene *s, int spp, int seed, const double pbrt[5][2], double rel_slack,
                               const char *what)
{
    RenderOptions o;
    Tiles q, whole;
    int i;
    render_options_default(&o);
    o.spp = spp;
    o.seed = seed;
    if (s->settings.maxdepth_set) o.maxdepth = s->settings.maxdepth;   /* as pbrt-v4 rendered it */
    if (!test_render_tiles(t, s, &o, 4, 2, &q) || !test_render_tiles(t, s, &o, 4, 1, &whole)) return;
    for (i = 0; i < 5; i++) {
        const Tiles *tl = i == 0 ? &whole : &q;
        int k = i == 0 ? 0 : i - 1;
        double Y = test_luminance(tl->mean[k]);
        double se = tl->se[k][1], Yp = pbrt[i][0], sep = pbrt[i][1];
        if (getenv("DBG")) fprintf(stderr, "%s %d: specnee %.6f +- %.2g, pbrt %.6f\n", what, i, Y, se, Yp);
        CHECK(t, fabs(Y - Yp) < TEST_K_SIGMA * sqrt(se * se + sep * sep) + rel_slack * Yp,
              "%s: %s %d: specnee Y %.5f +- %.2g, pbrt-v4 %.5f +- %.2g", what, i ? "quadrant" : "image",
              k, Y, se, Yp, sep);
    }
}

void test_against_pbrt_y(T *t, const char *scene, int seed, const double pbrt[5][2], double rel_slack,
                         const char *what)
{
    Scene s;
    if (!test_load_scene(t, &s, scene)) return;
    test_scene_against_pbrt_y(t, &s, test_scaled(64, 16), seed, pbrt, rel_slack, what);
    scene_free(&s);
}

void test_quadrants_against_pbrt(T *t, Scene *s, const RenderOptions *o, const double pbrt[5], const char *what)
{
    static const char *const region[5] = { "image", "top left", "top right", "bottom left", "bottom right" };
    Tiles tl;
    double y[5], se[5];
    int q;
    if (!test_render_tiles(t, s, o, 6, 2, &tl)) return;
    y[0] = se[0] = 0.0;
    for (q = 0; q < 4; q++) {
        y[q + 1] = test_tile_y(&tl, q, &se[q + 1]);
        y[0] += 0.25 * y[q + 1];
        se[0] += 0.0625 * se[q + 1] * se[q + 1];
    }
    se[0] = sqrt(se[0]);
    for (q = 0; q < 5; q++)
        CHECK(t, fabs(y[q] - pbrt[q]) < TEST_K_SIGMA * se[q] + (q ? 0.02 : 0.01) * pbrt[q],
              "%s, %s: Y = %.6g +- %.2g, pbrt-v4 %.6g", what, region[q], y[q], se[q], pbrt[q]);
}
