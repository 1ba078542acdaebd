/* tools/gen_measured.c - writes a small RGL tensor file (.bsdf, measured.c section 1)
   tabulated from an analytic BRDF, as test data for pbrt-v4's "measured" material.

       make tools/gen_measured && tools/gen_measured [ALPHA] > tests/data/measured/ggx.bsdf
       tools/gen_measured 0.3 small > fuzz/seeds/measured/small.bsdf    (2 KB: the fuzz seed)
       tools/gen_measured 0.3 aniso > tests/data/measured/ggx-aniso.bsdf (153 KB)

   The model (docs/measured.md): an isotropic Trowbridge-Reitz (GGX) microfacet
   conductor of roughness alpha (0.3 by default) with Schlick's Fresnel
   F = F0 + (1 - F0)(1 - c)^5, F0(lambda) = 0.25 + 0.65 (lambda - 360) / 470 (a
   reddish metal), and the height-correlated Smith G2 = 1 / (1 + L(wo) + L(wi)),
   L(w) = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2:
       f = D(wm) F(wo.wm) G2 / (4 cos_o cos_i).
   In the file's form f = R D / (4 sigma cos_i) (measured.c section 2) this is
       sigma(wo) = (cos_o + sqrt(cos_o^2 + alpha^2 sin_o^2)) / 2 = cos_o (1 + L(wo)),
       R = F(wo.wm) G2 (1 + L(wo)),
   R tabulated at the points s of the square that the visible-NDF warp maps to
   u_wm (warp2d_sample, the renderer's own).  R is linear in F0, hence in lambda:
   the spectral interpolation is exact.  tests/test_measured.c has the same model
   to compare with.  Not part of the renderer: it links the library for the warp. */
#include "../specnee.h"
#include <stdlib.h>
#include <string.h>

#define GPI 3.14159265358979323846
#define M_PI_ 6        /* at most: phi_i knots */
#define M_TI 10        /* theta_i knots */
#define M_WL 8
#define M_NDF 64
#define M_VNDF 32
#define M_S 16
/* The sizes: theta_i knots (degrees below), wavelengths (360 .. 830 nm), ndf and
   sigma (theta x phi), the vndf grid a side, the luminance and spectra grid a side;
   "small" takes fewer, "aniso" writes 6 uneven phi_i knots over [-pi, pi] (an anisotropic
   file of the same isotropic model: phi absolute). */
static int N_PI = 1, N_TI = 10, N_WL = 8, N_NDF_T = 64, N_NDF_P = 8, N_VNDF = 32, N_S = 16;
static const double theta_deg[M_TI] = { 0, 10, 20, 30, 40, 50, 60, 70, 80, 89 };
static const double theta_small[3] = { 0, 45, 80 };
static const double theta_aniso[6] = { 0, 18, 36, 54, 72, 85 };
/* uneven, so that no turn or mirror of the frame maps the knots onto themselves */
static const double phi_aniso[6] = { -GPI, -2.2, -0.9, 0.3, 1.6, GPI };
static double alpha = 0.3;

static double ggx_D(double cos_m)
{
    double c2 = cos_m * cos_m, a2 = alpha * alpha, d = c2 * (a2 - 1.0) + 1.0;
    return cos_m <= 0.0 ? 0.0 : a2 / (GPI * d * d);
}
static double ggx_L(double cos_t)
{
    double c2 = cos_t * cos_t;
    return cos_t <= 0.0 ? 1e30 : 0.5 * (sqrt(1.0 + alpha * alpha * (1.0 - c2) / c2) - 1.0);
}
static double schlick(double c, double lambda)
{
    double f0 = 0.25 + 0.65 * (lambda - 360.0) / 470.0, m = 1.0 - c;
    return f0 + (1.0 - f0) * m * m * m * m * m;
}
static double u2theta(double u) { return u * u * GPI / 2.0; }
static double u2phi(double u) { return (2.0 * u - 1.0) * GPI; }

/* ---- writing: fields of float32 (or uint8) data, little-endian */
typedef struct { const char *name; int dtype, rank; uint64_t shape[5]; const void *data; } Out;

static void put(uint64_t v, int n)
{
    while (n-- > 0) { putchar((int)(v & 0xFF)); v >>= 8; }
}
static uint64_t bytes_of(const Out *o)
{
    uint64_t b = o->dtype == 1 ? 1 : 4;
    int k;
    for (k = 0; k < o->rank; k++) b *= o->shape[k];
    return b;
}
static void write_file(const Out *o, int n)
{
    uint64_t off = 18, at;
    int i, k;
    for (i = 0; i < n; i++) off += 2 + strlen(o[i].name) + 2 + 1 + 8 + 8 * (uint64_t)o[i].rank;
    fwrite("tensor_file", 1, 12, stdout);
    putchar(1); putchar(0);
    put((uint64_t)n, 4);
    for (i = 0, at = off; i < n; at += bytes_of(&o[i]), i++) {
        put(strlen(o[i].name), 2);
        fputs(o[i].name, stdout);
        put((uint64_t)o[i].rank, 2);
        put((uint64_t)o[i].dtype, 1);
        put(at, 8);
        for (k = 0; k < o[i].rank; k++) put(o[i].shape[k], 8);
    }
    for (i = 0; i < n; i++) {
        if (o[i].dtype == 1) { fwrite(o[i].data, 1, (size_t)bytes_of(&o[i]), stdout); continue; }
        for (k = 0; k < (int)(bytes_of(&o[i]) / 4); k++) {
            uint32_t b;
            memcpy(&b, (const float *)o[i].data + k, 4);
            put(b, 4);
        }
    }
}

/* The tables, sized for the largest mode. */
static float ti[M_TI], phi_i[M_PI_], wl[M_WL], ndf[M_NDF * M_NDF], sigma[M_NDF * M_NDF];
static float vndf[M_PI_ * M_TI * M_VNDF * M_VNDF], lum[M_PI_ * M_TI * M_S * M_S];
static float spec[M_PI_ * M_TI * M_WL * M_S * M_S];

/* wo at knot (p, t) of (phi_i, theta_i). */
static void wo_at(int p, int t, double *wo)
{
    wo[0] = sin(ti[t]) * cos(phi_i[p]); wo[1] = sin(ti[t]) * sin(phi_i[p]); wo[2] = cos(ti[t]);
}

/* The microfacet normal at u of the square (its phi absolute; for an isotropic
   file phi_i = 0, so relative and absolute agree). */
static void wm_at(double ux, double uy, double *wm)
{
    double th = u2theta(ux), ph = u2phi(uy);
    wm[0] = sin(th) * cos(ph); wm[1] = sin(th) * sin(ph); wm[2] = cos(th);
}

static void tabulate_vndf(void)
{
    int p, t, x, y;
    for (p = 0; p < N_PI; p++)
        for (t = 0; t < N_TI; t++)
            for (y = 0; y < N_VNDF; y++)
                for (x = 0; x < N_VNDF; x++) {
                    double ux = (double)x / (N_VNDF - 1), wo[3], wm[3], dot;
                    wo_at(p, t, wo);
                    wm_at(ux, (double)y / (N_VNDF - 1), wm);
                    dot = wo[0] * wm[0] + wo[1] * wm[1] + wo[2] * wm[2];
                    vndf[((p * N_TI + t) * N_VNDF + y) * N_VNDF + x] = (float)(ggx_D(wm[2]) *
                        (dot > 0.0 ? dot : 0.0) * 2.0 * GPI * GPI * ux * sqrt(1.0 - wm[2] * wm[2]));
                }
}

/* R and its luminance at the points s that the visible-normal warp of (p, t) maps
   to u_wm (the renderer's warp2d_sample). */
static int tabulate_r(void)
{
    Warp2D w;
    int psize[2], p, t, x, y, k;
    const float *pval[2];
    psize[0] = N_PI; psize[1] = N_TI; pval[0] = phi_i; pval[1] = ti;
    if (!warp2d_init(&w, vndf, N_VNDF, N_VNDF, 2, psize, pval, 1)) return 0;
    for (p = 0; p < N_PI; p++)
        for (t = 0; t < N_TI; t++) {
            double Lo = ggx_L(cos(ti[t])), wo[3];
            float par[2];
            par[0] = phi_i[p]; par[1] = ti[t];
            wo_at(p, t, wo);
            for (y = 0; y < N_S; y++)
                for (x = 0; x < N_S; x++) {
                    float u[2], pdf;
                    double wm[3], d, iz, sum = 0.0;
                    size_t at = (size_t)(p * N_TI + t);
                    u[0] = (float)x / (N_S - 1); u[1] = (float)y / (N_S - 1);
                    warp2d_sample(&w, par, u, &pdf);
                    wm_at(u[0], u[1], wm);
                    d = wo[0] * wm[0] + wo[1] * wm[1] + wo[2] * wm[2];
                    iz = 2.0 * d * wm[2] - wo[2];
                    for (k = 0; k < N_WL; k++) {
                        double R = iz > 0.0 && d > 0.0 ? schlick(d, wl[k]) * (1.0 + Lo) / (1.0 + Lo + ggx_L(iz)) : 0.0;
                        spec[((at * N_WL + k) * N_S + y) * N_S + x] = (float)R;
                        sum += R;
                    }
                    lum[(at * N_S + y) * N_S + x] = (float)(sum / N_WL + 1e-3);
                }
        }
    warp2d_free(&w);
    return 1;
}

static void write_tables(void)
{
    static const char desc[] = "specnee test data: GGX conductor (tools/gen_measured.c)";
    static const unsigned char jac = 1;
    Out o[10];
    int i = 0;
    memset(o, 0, sizeof o);
    o[i].name = "description"; o[i].dtype = 1; o[i].rank = 1; o[i].shape[0] = sizeof desc - 1; o[i++].data = desc;
    o[i].name = "jacobian"; o[i].dtype = 1; o[i].rank = 1; o[i].shape[0] = 1; o[i++].data = &jac;
    o[i].name = "theta_i"; o[i].dtype = 10; o[i].rank = 1; o[i].shape[0] = N_TI; o[i++].data = ti;
    o[i].name = "phi_i"; o[i].dtype = 10; o[i].rank = 1; o[i].shape[0] = N_PI; o[i++].data = phi_i;
    o[i].name = "wavelengths"; o[i].dtype = 10; o[i].rank = 1; o[i].shape[0] = N_WL; o[i++].data = wl;
    o[i].name = "ndf"; o[i].dtype = 10; o[i].rank = 2; o[i].shape[0] = N_NDF_P; o[i].shape[1] = N_NDF_T; o[i++].data = ndf;
    o[i].name = "sigma"; o[i].dtype = 10; o[i].rank = 2; o[i].shape[0] = N_NDF_P; o[i].shape[1] = N_NDF_T; o[i++].data = sigma;
    o[i].name = "vndf"; o[i].dtype = 10; o[i].rank = 4; o[i].shape[0] = N_PI; o[i].shape[1] = N_TI;
    o[i].shape[2] = N_VNDF; o[i].shape[3] = N_VNDF; o[i++].data = vndf;
    o[i].name = "luminance"; o[i].dtype = 10; o[i].rank = 4; o[i].shape[0] = N_PI; o[i].shape[1] = N_TI;
    o[i].shape[2] = N_S; o[i].shape[3] = N_S; o[i++].data = lum;
    o[i].name = "spectra"; o[i].dtype = 10; o[i].rank = 5; o[i].shape[0] = N_PI; o[i].shape[1] = N_TI;
    o[i].shape[2] = N_WL; o[i].shape[3] = N_S; o[i].shape[4] = N_S; o[i++].data = spec;
    write_file(o, i);
}

int main(int argc, char **argv)
{
    int i, x, y, k;
    if (argc > 1) alpha = atof(argv[1]);
    if (argc > 2 && !strcmp(argv[2], "small")) {
        N_TI = 3; N_WL = 2; N_NDF_T = 8; N_NDF_P = 2; N_VNDF = 6; N_S = 4;
    } else if (argc > 2 && !strcmp(argv[2], "aniso")) {
        N_PI = 6; N_TI = 6; N_WL = 2; N_NDF_P = 16; N_VNDF = 24; N_S = 12;
    }
    for (i = 0; i < N_TI; i++)
        ti[i] = (float)((N_TI == 3 ? theta_small[i] : N_TI == 6 ? theta_aniso[i] : theta_deg[i]) * GPI / 180.0);
    for (i = 0; i < N_PI; i++) phi_i[i] = N_PI == 1 ? 0.0f : (float)phi_aniso[i];
    for (k = 0; k < N_WL; k++) wl[k] = (float)(360.0 + 470.0 * k / (N_WL - 1));
    for (y = 0; y < N_NDF_P; y++)
        for (x = 0; x < N_NDF_T; x++) {
            double th = u2theta((double)x / (N_NDF_T - 1)), c = cos(th), s = sin(th);
            ndf[y * N_NDF_T + x] = (float)ggx_D(c);
            sigma[y * N_NDF_T + x] = (float)(0.5 * (c + sqrt(c * c + alpha * alpha * s * s)));
        }
    tabulate_vndf();
    if (!tabulate_r()) return 1;
    write_tables();
    return 0;
}
