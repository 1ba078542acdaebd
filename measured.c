/* measured.c - measured BRDFs: pbrt-v4's "measured" material, a tabulated BRDF read
   from an RGL tensor file (.bsdf), in the adaptive parameterization of Dupuy and
   Jakob 2018 ("An Adaptive Parameterization for Efficient Material Acquisition and
   Rendering", SIGGRAPH Asia; docs/measured.md).

   Exported (specnee.h section 6): measured_read, measured_read_memory,
   measured_free, measured_eval, measured_sample and the 2-D warps warp2d_*.
   material.c's bsdf_sample and bsdf_eval call measured_sample and measured_eval in
   the shading frame (n = +z, directions pointing away, f without the cosine);
   material.c's measured_from_params reads the file.  tests/test_measured.c and the
   test-data generator tools/gen_measured.c use the warps directly.

   1. The tensor file (all numbers little-endian): the 12 bytes "tensor_file\0",
      the version (2 bytes, 1 0), the field count (uint32), then per field its
      name length (uint16), the name, its rank (uint16), its type (uint8: 1 uint8,
      2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64, 9 float16,
      10 float32, 11 float64), the offset of its data in the file (uint64) and its
      shape (rank uint64s), the data being rank-major (the last index contiguous).
      The BRDF needs: description (uint8, rank 1), jacobian (uint8, shape [1]),
      theta_i, phi_i, wavelengths (float32, rank 1), ndf and sigma (float32,
      [n_phi, n_theta]), vndf and luminance (float32, [phi_i, theta_i, n, m]),
      spectra (float32, [phi_i, theta_i, wavelengths, n, n]), luminance and
      spectra on the same n x n grid.  Every size is checked against the file
      before it is read; a malformed file is one line naming the file and the
      problem.  An isotropic BRDF has at most 2 values of phi_i; an anisotropic
      one must span 2 pi with them (pbrt-v4's "reduction" 1).

   2. The parameterization: a direction (theta, phi) is the point
      u = (sqrt(2 theta / pi), (phi + pi) / (2 pi)) of the unit square.  Its
      Jacobian: d omega = sin theta dtheta dphi = 2 pi^2 u_x sin theta du.
      The BRDF is stored as (docs/measured.md)
          f(wo, wi) = R(s; wo, lambda) D(wm) / (4 sigma(wo) cos theta_i),
      wm = normalize(wo + wi) the half vector, D the NDF (table ndf, over u of
      wm), sigma(wo) = integral of D(wm) max(0, wo.wm) dwm the projected area
      (table sigma, over u of wo), and R the spectral reflectance (table spectra)
      stored not over wm but over s = V^-1(u_wm), the uniform variable that the
      visible-NDF warp V of wo maps to u_wm.  That is the adaptive trick: R's
      grid is dense where the visible normals are.  An isotropic file stores
      u_wm's phi relative to wo's.

   3. The warps (Warp2D): a bilinear density on an nx x ny grid of [0,1]^2,
      optionally conditioned on up to 3 parameters (phi_i, theta_i, lambda),
      between whose grid values it is interpolated linearly (clamped at the
      ends).  Sampling inverts a marginal CDF over rows then a conditional CDF
      within the row, each piece a linear density, so a quadratic solves it;
      warp2d_invert maps a point back to its uniform pair; both report the
      density.  The CDFs are linear in the data, so interpolating a normalized
      slice's CDFs is exactly sampling the interpolated density.

   4. Sampling (as pbrt-v4's MeasuredBxDF): s = L(u) by the luminance warp (a
      density over s that follows R), u_wm = V(s) by the visible-NDF warp, wm from
      u_wm, wi = reflect(wo, wm); the pdf chain:
          p(wi) = p_L(s) p_V(u_wm) / (4 (wo.wm) 2 pi^2 u_x sin theta_m),
      the last factor the Jacobians of the reflection and of the
      parameterization (floored at 1e-6, as pbrt-v4).  measured_eval inverts V
      at wm = normalize(wo + wi) to find s, and gives the same pdf.  The
      direction does not depend on the wavelength: pdf_l[j] = pdf for all j.
      R is interpolated at each of the path's wavelengths (the spectra table's
      third parameter) and clamped at 0.  A wo below the surface is mirrored, a
      BRDF only (no transmission). */
#include "specnee.h"
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- the warps */

/* The (up to 8) parameter slices a lookup mixes, with their weights. */
typedef struct { int n; unsigned off[8]; float w[8]; } WarpMix;

static void warp_mix(const Warp2D *w, const float *param, WarpMix *m)
{
    int d, k;
    m->n = 1; m->off[0] = 0; m->w[0] = 1.0f;
    for (d = 0; d < w->nparam; d++) {
        int n = w->psize[d], lo = 0, hi;
        const float *v = w->pval[d];
        float t;
        if (n == 1) continue;
        hi = n - 2;                               /* the last knot <= param, in [0, n-2] */
        while (lo < hi) {
            int mid = (lo + hi + 1) / 2;
            if (v[mid] <= param[d]) lo = mid; else hi = mid - 1;
        }
        t = (param[d] - v[lo]) / (v[lo + 1] - v[lo]);
        t = t > 0.0f ? (t < 1.0f ? t : 1.0f) : 0.0f;   /* NaN: 0 */
        for (k = 0; k < m->n; k++) {
            m->off[k + m->n] = m->off[k] + (unsigned)(lo + 1) * w->stride[d];
            m->w[k + m->n] = m->w[k] * t;
            m->off[k] += (unsigned)lo * w->stride[d];
            m->w[k] *= 1.0f - t;
        }
        m->n *= 2;
    }
}

/* Array a (slices of `slice` floats) at index i, mixed over the parameter slices. */
static float warp_at(const float *a, size_t i, size_t slice, const WarpMix *m)
{
    float v = 0.0f;
    int k;
    for (k = 0; k < m->n; k++)
        if (m->w[k] != 0.0f) v += m->w[k] * a[m->off[k] * slice + i];
    return v;
}

void warp2d_free(Warp2D *w)
{
    int d;
    free(w->data); free(w->marg); free(w->cond);
    for (d = 0; d < 3; d++) free(w->pval[d]);
    memset(w, 0, sizeof *w);
}

/* Per slice: running sums over rows (cond, unnormalized) and rows' totals (marg),
   then the data and both CDFs divided by the slice's integral. 0 when a slice
   integrates to zero. */
static int warp_build_cdfs(Warp2D *w, size_t slices)
{
    size_t nx = (size_t)w->nx, ny = (size_t)w->ny, s, x, y;
    for (s = 0; s < slices; s++) {
        float *d = w->data + s * nx * ny, *c = w->cond + s * nx * ny, *mg = w->marg + s * ny;
        double sum = 0.0, norm;
        for (y = 0; y < ny; y++) {
            double row = 0.0;
            c[y * nx] = 0.0f;
            for (x = 0; x + 1 < nx; x++) {
                row += 0.5 * ((double)d[y * nx + x] + d[y * nx + x + 1]);
                c[y * nx + x + 1] = (float)row;
            }
        }
        mg[0] = 0.0f;
        for (y = 0; y + 1 < ny; y++) {
            sum += 0.5 * ((double)c[y * nx + nx - 1] + c[(y + 1) * nx + nx - 1]);
            mg[y + 1] = (float)sum;
        }
        if (!(sum > 1e-30 && sum < 1e30)) return 0;  /* (also keeps the densities finite) */
        norm = 1.0 / mg[ny - 1];
        for (x = 0; x < nx * ny; x++) { c[x] = (float)(c[x] * norm); d[x] = (float)(d[x] * norm); }
        for (y = 0; y < ny; y++) mg[y] = (float)(mg[y] * norm);
    }
    return 1;
}

int warp2d_init(Warp2D *w, const float *data, int nx, int ny, int nparam, const int *psize,
                const float *const *pval, int sampled)
{
    size_t slices = 1, n;
    int d;
    memset(w, 0, sizeof *w);
    if (nx < 2 || ny < 2 || nparam < 0 || nparam > 3) return 0;
    w->nx = nx; w->ny = ny; w->nparam = nparam; w->sampled = sampled;
    for (d = nparam - 1; d >= 0; d--) {
        if (psize[d] < 1) return 0;
        w->psize[d] = psize[d];
        w->stride[d] = psize[d] > 1 ? (unsigned)slices : 0u;
        slices *= (size_t)psize[d];
        w->pval[d] = (float *)malloc((size_t)psize[d] * sizeof(float));
        if (!w->pval[d]) { warp2d_free(w); return 0; }
        memcpy(w->pval[d], pval[d], (size_t)psize[d] * sizeof(float));
    }
    n = slices * (size_t)nx * (size_t)ny;
    w->data = (float *)malloc(n * sizeof(float));
    if (sampled) {
        w->marg = (float *)malloc(slices * (size_t)ny * sizeof(float));
        w->cond = (float *)malloc(n * sizeof(float));
    }
    if (!w->data || (sampled && (!w->marg || !w->cond))) { warp2d_free(w); return 0; }
    memcpy(w->data, data, n * sizeof(float));
    if (sampled && !warp_build_cdfs(w, slices)) { warp2d_free(w); return 0; }
    return 1;
}

float warp2d_eval(const Warp2D *w, const float *param, float ux, float uy)
{
    WarpMix m;
    size_t slice = (size_t)w->nx * w->ny, i;
    float x = ux * (float)(w->nx - 1), y = uy * (float)(w->ny - 1), s, t, v;
    int col = x > 0.0f ? (int)x : 0, row = y > 0.0f ? (int)y : 0;
    if (col > w->nx - 2) col = w->nx - 2;
    if (row > w->ny - 2) row = w->ny - 2;
    s = x - (float)col; t = y - (float)row;
    warp_mix(w, param, &m);
    i = (size_t)row * w->nx + (size_t)col;
    v = (1.0f - t) * ((1.0f - s) * warp_at(w->data, i, slice, &m) + s * warp_at(w->data, i + 1, slice, &m)) +
        t * ((1.0f - s) * warp_at(w->data, i + w->nx, slice, &m) + s * warp_at(w->data, i + w->nx + 1, slice, &m));
    return w->sampled ? v * (float)(w->nx - 1) * (float)(w->ny - 1) : v;
}

/* t in [0, 1] with integral_0^t (a + (b - a) x) dx = r: the inverse CDF of a linear
   density from a to b on [0, 1] (whose integral is (a + b) / 2). */
static float solve_linear(float a, float b, float r)
{
    float t;
    if (fabsf(a - b) < 1e-4f * (a + b)) t = 2.0f * r / (a + b);
    else t = (a - sqrtf(fmaxf(0.0f, a * a - 2.0f * r * (a - b)))) / (a - b);
    return t > 0.0f ? (t < 1.0f ? t : 1.0f) : 0.0f;          /* NaN (a = b = 0): 0 */
}

void warp2d_sample(const Warp2D *w, const float *param, float u[2], float *pdf)
{
    WarpMix m;
    size_t nx = (size_t)w->nx, slice = nx * w->ny, off;
    float ux = fminf(fmaxf(u[0], 1e-7f), 1.0f - 1e-7f), uy = fminf(fmaxf(u[1], 1e-7f), 1.0f - 1e-7f);
    float r0, r1, t, s, c0, c1;
    int row = 0, col = 0, hi;
    warp_mix(w, param, &m);
    for (hi = w->ny - 2; row < hi;) {                /* the row: marginal CDF */
        int mid = (row + hi + 1) / 2;
        if (warp_at(w->marg, (size_t)mid, (size_t)w->ny, &m) < uy) row = mid; else hi = mid - 1;
    }
    uy -= warp_at(w->marg, (size_t)row, (size_t)w->ny, &m);
    off = (size_t)row * nx;
    r0 = warp_at(w->cond, off + nx - 1, slice, &m);
    r1 = warp_at(w->cond, off + 2 * nx - 1, slice, &m);
    t = solve_linear(r0, r1, uy);
    ux *= (1.0f - t) * r0 + t * r1;                  /* the column: conditional CDF */
    for (hi = w->nx - 2; col < hi;) {
        int mid = (col + hi + 1) / 2;
        float c = (1.0f - t) * warp_at(w->cond, off + mid, slice, &m) + t * warp_at(w->cond, off + nx + mid, slice, &m);
        if (c < ux) col = mid; else hi = mid - 1;
    }
    ux -= (1.0f - t) * warp_at(w->cond, off + col, slice, &m) + t * warp_at(w->cond, off + nx + col, slice, &m);
    off += (size_t)col;
    c0 = (1.0f - t) * warp_at(w->data, off, slice, &m) + t * warp_at(w->data, off + nx, slice, &m);
    c1 = (1.0f - t) * warp_at(w->data, off + 1, slice, &m) + t * warp_at(w->data, off + nx + 1, slice, &m);
    s = solve_linear(c0, c1, ux);
    u[0] = ((float)col + s) / (float)(w->nx - 1);
    u[1] = ((float)row + t) / (float)(w->ny - 1);
    *pdf = ((1.0f - s) * c0 + s * c1) * (float)(w->nx - 1) * (float)(w->ny - 1);
}

void warp2d_invert(const Warp2D *w, const float *param, float u[2], float *pdf)
{
    WarpMix m;
    size_t nx = (size_t)w->nx, slice = nx * w->ny, i;
    float x = u[0] * (float)(w->nx - 1), y = u[1] * (float)(w->ny - 1), s, t;
    float v00, v10, v01, v11, c0, c1, r0, r1, ox;
    int col = x > 0.0f ? (int)x : 0, row = y > 0.0f ? (int)y : 0;
    if (col > w->nx - 2) col = w->nx - 2;
    if (row > w->ny - 2) row = w->ny - 2;
    s = x - (float)col; t = y - (float)row;
    warp_mix(w, param, &m);
    i = (size_t)row * nx + (size_t)col;
    v00 = warp_at(w->data, i, slice, &m); v10 = warp_at(w->data, i + 1, slice, &m);
    v01 = warp_at(w->data, i + nx, slice, &m); v11 = warp_at(w->data, i + nx + 1, slice, &m);
    c0 = (1.0f - t) * v00 + t * v01;
    c1 = (1.0f - t) * v10 + t * v11;
    *pdf = ((1.0f - s) * c0 + s * c1) * (float)(w->nx - 1) * (float)(w->ny - 1);
    ox = s * (c0 + 0.5f * s * (c1 - c0)) +
         (1.0f - t) * warp_at(w->cond, i, slice, &m) + t * warp_at(w->cond, i + nx, slice, &m);
    i = (size_t)row * nx;
    r0 = warp_at(w->cond, i + nx - 1, slice, &m);
    r1 = warp_at(w->cond, i + 2 * nx - 1, slice, &m);
    u[0] = ox / ((1.0f - t) * r0 + t * r1);
    u[1] = t * (r0 + 0.5f * t * (r1 - r0)) + warp_at(w->marg, (size_t)row, (size_t)w->ny, &m);
}

/* ---------------------------------------------------------------- the tensor file */

enum { T_UINT8 = 1, T_FLOAT32 = 10, T_FLOAT64 = 11 };
#define TENSOR_RANK_MAX 8
typedef struct {
    char name[64];
    int dtype, rank;
    uint64_t shape[TENSOR_RANK_MAX];
    const unsigned char *data;          /* into the file's bytes */
} TField;

static uint64_t get_le(const unsigned char *p, int n)
{
    uint64_t v = 0;
    while (n-- > 0) v = (v << 8) | p[n];
    return v;
}

static const int tensor_type_size[12] = { 0, 1, 1, 2, 2, 4, 4, 8, 8, 2, 4, 8 };

/* One field's header at *pos; 0 and a message when it runs past the file. */
static int read_field(const unsigned char *d, size_t n, size_t *pos, TField *f, const char *name,
                      Error *e)
{
    size_t p = *pos, len, k;
    uint64_t off, bytes;
    if (n - p < 2) goto trunc;
    len = (size_t)get_le(d + p, 2); p += 2;
    if (n - p < len + 11) goto trunc;
    snprintf(f->name, sizeof f->name, "%.*s", (int)(len < 63 ? len : 63), (const char *)d + p);
    p += len;
    f->rank = (int)get_le(d + p, 2);
    f->dtype = d[p + 2];
    off = get_le(d + p + 3, 8);
    p += 11;
    if (f->dtype < 1 || f->dtype > T_FLOAT64) {
        error_set(e, name, 0, "tensor file: field \"%s\" has unknown type %d", f->name, f->dtype);
        return 0;
    }
    if (f->rank > TENSOR_RANK_MAX) {
        error_set(e, name, 0, "tensor file: field \"%s\" has rank %d (at most %d)", f->name, f->rank,
                  TENSOR_RANK_MAX);
        return 0;
    }
    if ((n - p) / 8 < (size_t)f->rank) goto trunc;
    bytes = (uint64_t)tensor_type_size[f->dtype];
    for (k = 0; k < (size_t)f->rank; k++, p += 8) {
        f->shape[k] = get_le(d + p, 8);
        if (f->shape[k] > n) bytes = (uint64_t)n + 1;   /* larger than the file, no overflow */
        else bytes *= f->shape[k];
        if (bytes > n) bytes = (uint64_t)n + 1;
    }
    if (off > n || bytes > n - off) {
        error_set(e, name, 0, "tensor file: the data of field \"%s\" lies beyond the end of the "
                  "file (truncated?)", f->name);
        return 0;
    }
    f->data = d + off;
    *pos = p;
    return 1;
trunc:
    error_set(e, name, 0, "tensor file: truncated in the header of field %s", f->name[0] ? f->name : "list");
    return 0;
}

/* The field `want` with its type and rank, or 0 and a message. */
static const TField *need(const TField *fs, int nf, const char *want, int dtype, int rank,
                          const char *name, Error *e)
{
    int i;
    for (i = 0; i < nf; i++)
        if (!strcmp(fs[i].name, want)) break;
    if (i == nf) {
        error_set(e, name, 0, "measured BRDF: no field \"%s\"", want);
        return NULL;
    }
    if (fs[i].dtype != dtype || fs[i].rank != rank) {
        error_set(e, name, 0, "measured BRDF: field \"%s\" must be %s of rank %d (type %d, rank %d "
                  "given)", want, dtype == T_UINT8 ? "uint8" : "float32", rank, fs[i].dtype, fs[i].rank);
        return NULL;
    }
    return &fs[i];
}

/* The floats of field f, copied (little-endian in the file); NULL when out of
   memory or a value is not finite.  clamp: a sampled density, whose negative
   values (measurement noise) are read as 0, so that its CDFs increase. */
static float *field_floats(const TField *f, int clamp, const char *name, Error *e)
{
    size_t n = 1, i;
    float *v;
    int k;
    for (k = 0; k < f->rank; k++) n *= (size_t)f->shape[k];
    v = (float *)malloc((n ? n : 1) * sizeof(float));
    if (!v) { error_set(e, name, 0, "measured BRDF: out of memory"); return NULL; }
    for (i = 0; i < n; i++) {
        uint32_t b = (uint32_t)get_le(f->data + 4 * i, 4);
        memcpy(&v[i], &b, 4);
        if (!(fabsf(v[i]) <= 3.4e38f)) {
            error_set(e, name, 0, "measured BRDF: field \"%s\": value %g at index %lu is not finite",
                      f->name, v[i], (unsigned long)i);
            free(v);
            return NULL;
        }
        if (clamp && v[i] < 0.0f) v[i] = 0.0f;
    }
    return v;
}

/* Strictly increasing knots of a parameter (the interval search needs them). */
static int increasing(const float *v, uint64_t n)
{
    uint64_t i;
    for (i = 1; i < n; i++)
        if (!(v[i] > v[i - 1])) return 0;
    return 1;
}

/* The shapes pbrt-v4 requires (bxdfs.cpp, MeasuredBxDFData::Create); 0 and a message. */
static int check_shapes(const TField *const *f, const char *name, Error *e)
{
    /* f: theta_i, phi_i, wavelengths, ndf, sigma, vndf, luminance, spectra, jacobian */
    uint64_t nt = f[0]->shape[0], np = f[1]->shape[0], nw = f[2]->shape[0];
    const uint64_t *v = f[5]->shape, *l = f[6]->shape, *s = f[7]->shape;
    const char *bad = NULL;
    int k;
    if (v[0] != np || v[1] != nt) bad = "vndf's first two sizes must be those of phi_i and theta_i";
    else if (l[0] != np || l[1] != nt) bad = "luminance's first two sizes must be those of phi_i and theta_i";
    else if (s[0] != np || s[1] != nt || s[2] != nw)
        bad = "spectra's first three sizes must be those of phi_i, theta_i and wavelengths";
    else if (l[2] != l[3] || s[3] != s[4] || l[2] != s[3])
        bad = "luminance and spectra must share one square grid";
    else if (f[8]->shape[0] != 1) bad = "jacobian must hold one byte";
    else if (nt < 1 || np < 1 || nw < 1) bad = "theta_i, phi_i and wavelengths need at least one value";
    for (k = 3; !bad && k < 8; k++) {
        int r = f[k]->rank;
        if (f[k]->shape[r - 1] < 2 || f[k]->shape[r - 2] < 2 || f[k]->shape[r - 1] > 4096 ||
            f[k]->shape[r - 2] > 4096)
            bad = "a grid (ndf, sigma, vndf, luminance, spectra) must be 2 to 4096 points a side";
    }
    if (bad) { error_set(e, name, 0, "measured BRDF: %s", bad); return 0; }
    return 1;
}

/* The five tables as warps; 0 and a message (a sampled table must integrate to
   more than 0 in every slice). */
static int build_tables(MeasuredBrdf *b, const TField *const *f, const char *name, Error *e)
{
    static const char *const what[5] = { "ndf", "sigma", "vndf", "luminance", "spectra" };
    int nt = (int)f[0]->shape[0], np = (int)f[1]->shape[0], nw = (int)f[2]->shape[0], k, ok = 1;
    Warp2D *w[5];
    w[0] = &b->ndf; w[1] = &b->sigma; w[2] = &b->vndf; w[3] = &b->lum; w[4] = &b->spectra;
    for (k = 0; k < 5 && ok; k++) {
        const TField *t = f[3 + k];
        int r = t->rank, sampled = k == 2 || k == 3, psize[3];
        const float *pval[3];
        float *data = field_floats(t, sampled, name, e);
        if (!data) return 0;
        psize[0] = np; psize[1] = nt; psize[2] = nw;
        pval[0] = b->phi_i; pval[1] = b->theta_i; pval[2] = b->wavelengths;
        ok = warp2d_init(w[k], data, (int)t->shape[r - 1], (int)t->shape[r - 2], r - 2, psize, pval,
                         sampled);
        free(data);
        if (!ok)
            error_set(e, name, 0, "measured BRDF: field \"%s\": %s", what[k], sampled ?
                      "a slice integrates to zero (or out of memory)" : "out of memory");
    }
    return ok;
}

int measured_read_memory(const unsigned char *d, size_t n, const char *name, MeasuredBrdf *b, Error *e)
{
    static const char *const names[9] = { "theta_i", "phi_i", "wavelengths", "ndf", "sigma", "vndf",
                                           "luminance", "spectra", "jacobian" };
    static const int ranks[9] = { 1, 1, 1, 2, 2, 4, 4, 5, 1 };
    const TField *f[9];
    TField *fs = NULL;
    size_t pos = 18;
    uint32_t nf, i;
    int ok = 0, k;
    memset(b, 0, sizeof *b);
    if (n < 18 || memcmp(d, "tensor_file", 12) != 0) {
        error_set(e, name, 0, "tensor file: %s", n < 18 && (n < 12 || !memcmp(d, "tensor_file", 12))
                  ? "truncated header" : "not a tensor file (no \"tensor_file\" header)");
        return 0;
    }
    if (d[12] != 1 || d[13] != 0) {
        error_set(e, name, 0, "tensor file: version %d.%d (only 1.0 is read)", d[12], d[13]);
        return 0;
    }
    nf = (uint32_t)get_le(d + 14, 4);
    if (nf > (n - 18) / 13) {             /* each field's header takes at least 13 bytes */
        error_set(e, name, 0, "tensor file: %lu fields do not fit in the file (truncated?)",
                  (unsigned long)nf);
        return 0;
    }
    fs = (TField *)calloc(nf ? nf : 1, sizeof *fs);
    if (!fs) { error_set(e, name, 0, "tensor file: out of memory"); return 0; }
    for (i = 0; i < nf; i++)
        if (!read_field(d, n, &pos, &fs[i], name, e)) goto done;
    for (k = 0; k < 9; k++)
        if (!(f[k] = need(fs, (int)nf, names[k], k == 8 ? T_UINT8 : T_FLOAT32, ranks[k], name, e)))
            goto done;
    if (!need(fs, (int)nf, "description", T_UINT8, 1, name, e) || !check_shapes(f, name, e)) goto done;
    if (!(b->theta_i = field_floats(f[0], 0, name, e)) || !(b->phi_i = field_floats(f[1], 0, name, e)) ||
        !(b->wavelengths = field_floats(f[2], 0, name, e)))
        goto done;
    for (k = 0; k < 3; k++)
        if (!increasing(k == 0 ? b->theta_i : k == 1 ? b->phi_i : b->wavelengths, f[k]->shape[0])) {
            error_set(e, name, 0, "measured BRDF: the values of \"%s\" must increase", names[k]);
            goto done;
        }
    b->isotropic = f[1]->shape[0] <= 2;
    if (!b->isotropic) {
        double span = b->phi_i[f[1]->shape[0] - 1] - b->phi_i[0];
        if (floor(6.283185307179586 / span + 0.5) != 1.0) {
            error_set(e, name, 0, "measured BRDF: phi_i spans %g rad; only a full turn (2 pi) is "
                      "read, as in pbrt-v4", span);
            goto done;
        }
    }
    b->n_wavelengths = (int)f[2]->shape[0];
    ok = build_tables(b, f, name, e);
done:
    free(fs);
    if (!ok) measured_free(b);
    return ok;
}

int measured_read(const char *path, MeasuredBrdf *b, Error *e)
{
    size_t len;
    ReadStatus rs;
    char *buf = read_whole_file(path, 0, NULL, &len, &rs);
    int ok;
    memset(b, 0, sizeof *b);
    if (!buf) {
        error_set(e, path, 0, "%s", rs == READ_OPEN ? "cannot read the measured BRDF file"
                  : read_status_text(rs));
        return 0;
    }
    ok = measured_read_memory((const unsigned char *)buf, len, path, b, e);
    free(buf);
    return ok;
}

void measured_free(MeasuredBrdf *b)
{
    warp2d_free(&b->ndf); warp2d_free(&b->sigma); warp2d_free(&b->vndf);
    warp2d_free(&b->lum); warp2d_free(&b->spectra);
    free(b->theta_i); free(b->phi_i); free(b->wavelengths);
    memset(b, 0, sizeof *b);
}

/* ---------------------------------------------------------------- f, pdf, sampling */

/* theta of a unit vector, accurate near the pole too (acos is not: at theta = 3e-3
   a float cos holds theta to 1 %). */
static float theta_of(Vec3 w) { return atan2f(sqrtf(w.x * w.x + w.y * w.y), w.z); }
static float theta_to_u(float theta) { return sqrtf(fmaxf(0.0f, theta) * (2.0f / PI_F)); }
static float phi_to_u(float phi) { return phi * (0.5f / PI_F) + 0.5f; }

/* The shared tail of eval and sample: f per wavelength at the warped point s (R),
   u_wm (D), wo (sigma) and cos theta_i. */
static void measured_f(const MeasuredBrdf *b, const float s[2], const float u_wm[2], float theta_o,
                       float phi_o, float cos_i, const float *lambda, unsigned alive, float f[HERO_N])
{
    float uo_x = theta_to_u(theta_o), uo_y = phi_to_u(phi_o), scale, par[3];
    int j;
    scale = warp2d_eval(&b->ndf, NULL, u_wm[0], u_wm[1]) /
            (4.0f * warp2d_eval(&b->sigma, NULL, uo_x, uo_y) * cos_i);
    if (!(scale < 1e30f)) scale = 0.0f;                  /* sigma 0 (a broken table) */
    par[0] = phi_o; par[1] = theta_o;
    for (j = 0; j < HERO_N; j++) {
        float r;
        f[j] = 0.0f;
        if (!(alive & (1u << j))) continue;
        par[2] = lambda[j];
        r = warp2d_eval(&b->spectra, par, s[0], s[1]) * scale;
        f[j] = r > 0.0f && r < 1e30f ? r : 0.0f;         /* NaN, overflow: 0 */
    }
}

void measured_eval(const MeasuredBrdf *b, Vec3 wo, Vec3 wi, const float *lambda, unsigned alive,
                   float f[HERO_N], float pdf_l[HERO_N])
{
    float theta_o, phi_o, theta_m, phi_m, par[2], u[2], s[2], pv, pl, jac, sin_m, pdf;
    Vec3 wm;
    int j;
    for (j = 0; j < HERO_N; j++) { f[j] = 0.0f; pdf_l[j] = 0.0f; }
    if (wo.z * wi.z <= 0.0f) return;                  /* a BRDF: both on one side */
    if (wo.z < 0.0f) { wo = v3_neg(wo); wi = v3_neg(wi); }
    wm = v3_add(wo, wi);
    if (v3_dot(wm, wm) == 0.0f) return;
    wm = v3_norm(wm);
    theta_o = theta_of(wo); phi_o = atan2f(wo.y, wo.x);
    theta_m = theta_of(wm); phi_m = atan2f(wm.y, wm.x);
    u[0] = theta_to_u(theta_m);
    u[1] = phi_to_u(b->isotropic ? phi_m - phi_o : phi_m);
    u[1] -= floorf(u[1]);
    par[0] = phi_o; par[1] = theta_o;
    s[0] = u[0]; s[1] = u[1];
    warp2d_invert(&b->vndf, par, s, &pv);             /* s = V^-1(u_wm) */
    pl = warp2d_eval(&b->lum, par, s[0], s[1]);
    measured_f(b, s, u, theta_o, phi_o, wi.z, lambda, alive, f);
    sin_m = sqrtf(wm.x * wm.x + wm.y * wm.y);
    jac = 4.0f * v3_dot(wo, wm) * fmaxf(2.0f * PI_F * PI_F * u[0] * sin_m, 1e-6f);
    pdf = pv * pl / jac;
    if (!(pdf < 1e30f)) pdf = 0.0f;                    /* as measured_sample refuses it */
    for (j = 0; j < HERO_N; j++) pdf_l[j] = pdf;
}

int measured_sample(const MeasuredBrdf *b, Vec3 wo, const float *lambda, unsigned alive, float u1,
                    float u2, BsdfSample *out, Vec3 *wi_local)
{
    float theta_o, phi_o, theta_m, phi_m, par[2], s[2], u[2], pl, pv, pdf;
    int flip = wo.z <= 0.0f, j;
    Vec3 wm, wi;
    if (flip) wo = v3_neg(wo);
    theta_o = theta_of(wo); phi_o = atan2f(wo.y, wo.x);
    par[0] = phi_o; par[1] = theta_o;
    s[0] = u1; s[1] = u2;
    warp2d_sample(&b->lum, par, s, &pl);              /* s ~ the luminance of R */
    u[0] = s[0]; u[1] = s[1];
    warp2d_sample(&b->vndf, par, u, &pv);             /* u_wm = V(s) */
    phi_m = (2.0f * u[1] - 1.0f) * PI_F;
    theta_m = u[0] * u[0] * (0.5f * PI_F);
    if (b->isotropic) phi_m += phi_o;
    wm = v3(sinf(theta_m) * cosf(phi_m), sinf(theta_m) * sinf(phi_m), cosf(theta_m));
    wi = reflect_dir(wo, wm);
    if (wi.z <= 0.0f) return 0;
    measured_f(b, s, u, theta_o, phi_o, wi.z, lambda, alive, out->f);
    pdf = pv * pl / (4.0f * v3_dot(wo, wm) * fmaxf(2.0f * PI_F * PI_F * u[0] * sinf(theta_m), 1e-6f));
    if (!(pdf > 0.0f) || !(pdf < 1e30f)) return 0;
    out->pdf = pdf;
    for (j = 0; j < HERO_N; j++) out->pdf_l[j] = pdf;
    out->delta = 0;
    *wi_local = flip ? v3_neg(wi) : wi;
    return 1;
}
