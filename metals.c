/* metals.c - the optical constants of metals (and two oxides) that pbrt-v4 knows by
   name: metal-Ag-eta/-k, metal-Al-, metal-Au-, metal-Cu-, metal-CuZn-, metal-MgO-,
   metal-TiO2-.  Data only, read by spec_named (spectrum.c) through metal_named.

   A conductor's complex index of refraction is n + i k: n (the "eta" spectrum)
   bends the transmitted wave, the extinction coefficient k damps it within a
   fraction of a wavelength, so nothing is transmitted and the Fresnel reflectance
   (conductor.c) is all that matters.  At normal incidence from air
       R = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2)          (Born & Wolf, section 14.2)
   e.g. silver at 550 nm: n 0.124, k 3.35, R = 0.96.

   Sources.  The numbers are the tables pbrt-v4 ships (src/pbrt/util/spectrum.cpp,
   which names no source for them); they are published measurements:
     - Ag, Al, Au, Cu: on a grid of photon energies E = 4.15, 4.10, ..., 1.40 eV
       (lambda = hc / E, 298.8 - 885.6 nm), the grid of the tables in E. D. Palik
       (ed.), "Handbook of Optical Constants of Solids", Academic Press 1985
       (as distributed with the Mitsuba renderer's data/ior and pbrt-v3's
       scenes); every second row interpolated.  The attribution is by the grid
       and values; it was not checked against the handbook's pages here.
     - CuZn (brass): 290 - 890 nm every 10 nm, M. R. Querry, "Optical constants of
       minerals and other materials from the millimeter to the ultraviolet",
       CRDEC-CR-88009 (1987), as on refractiveindex.info (CC0).
     - MgO: at spectral lamp lines 310 - 768 nm (Hg, Cd, He, H, Na), R. E. Stephens
       and I. H. Malitson, "Index of refraction of magnesium oxide", J. Res. Natl.
       Bur. Stand. 49, 249 (1952); k = 0 (a transparent crystal: as a "conductor"
       it is a lossless Fresnel reflector, about 7% at normal incidence).
     - TiO2: 306 - 900 nm; pbrt-v4 names no source and none was identified here
       (k vanishes above 420 nm: a transparent crystal, n 2.8 - 3.4).
   Values are taken as given (7 significant digits).

   Resampling (pbrt-v4's PiecewiseLinearSpectrum::FromInterleaved meaning): linear
   between the tabulated wavelengths, and held at the first and last value beyond
   them (pbrt-v4 extends a table that does not cover 360-830 nm with its end
   values; here the extension also covers the UV table, 300-359 nm). */
#include "specnee.h"
#include <ctype.h>

#define EV_N 56                 /* 4.15 eV down to 1.40 eV in steps of 0.05 eV */
#define EV_FIRST 4.15
#define EV_STEP 0.05
#define HC_EV_NM 1239.84193     /* h c in eV nm (CODATA): lambda = HC_EV_NM / E */

static const float ag_eta[EV_N] = {
    1.519, 1.496, 1.4325, 1.323, 1.142062, 0.932, 0.719062, 0.526,
    0.388125, 0.294, 0.253313, 0.238, 0.221438, 0.209, 0.194813, 0.186,
    0.192063, 0.2, 0.198063, 0.192, 0.182, 0.173, 0.172625, 0.173,
    0.166688, 0.16, 0.1585, 0.157, 0.151063, 0.144, 0.137313, 0.132,
    0.13025, 0.13, 0.129938, 0.13, 0.130063, 0.129, 0.124375, 0.12,
    0.119313, 0.121, 0.1255, 0.131, 0.136125, 0.14, 0.140063, 0.14,
    0.144313, 0.148, 0.145875, 0.143, 0.142563, 0.145, 0.151938, 0.163,
};
static const float ag_k[EV_N] = {
    1.08, 0.882, 0.761063, 0.647, 0.550875, 0.504, 0.554375, 0.663,
    0.818563, 0.986, 1.120687, 1.24, 1.34525, 1.44, 1.53375, 1.61,
    1.641875, 1.67, 1.735, 1.81, 1.87875, 1.95, 2.029375, 2.11,
    2.18625, 2.26, 2.329375, 2.4, 2.47875, 2.56, 2.64, 2.72,
    2.798125, 2.88, 2.97375, 3.07, 3.159375, 3.25, 3.348125, 3.45,
    3.55375, 3.66, 3.76625, 3.88, 4.010625, 4.15, 4.293125, 4.44,
    4.58625, 4.74, 4.908125, 5.09, 5.28875, 5.5, 5.720624, 5.95,
};
static const float al_eta[EV_N] = {
    0.273375, 0.28, 0.286813, 0.294, 0.301875, 0.31, 0.317875, 0.326,
    0.33475, 0.344, 0.353813, 0.364, 0.374375, 0.385, 0.39575, 0.407,
    0.419125, 0.432, 0.445688, 0.46, 0.474688, 0.49, 0.506188, 0.523,
    0.540063, 0.558, 0.577313, 0.598, 0.620313, 0.644, 0.668625, 0.695,
    0.72375, 0.755, 0.789, 0.826, 0.867, 0.912, 0.963, 1.02,
    1.08, 1.15, 1.22, 1.3, 1.39, 1.49, 1.6, 1.74,
    1.91, 2.14, 2.41, 2.63, 2.8, 2.74, 2.58, 2.24,
};
static const float al_k[EV_N] = {
    3.59375, 3.64, 3.689375, 3.74, 3.789375, 3.84, 3.894375, 3.95,
    4.005, 4.06, 4.11375, 4.17, 4.23375, 4.3, 4.365, 4.43,
    4.49375, 4.56, 4.63375, 4.71, 4.784375, 4.86, 4.938125, 5.02,
    5.10875, 5.2, 5.29, 5.38, 5.48, 5.58, 5.69, 5.8,
    5.915, 6.03, 6.15, 6.28, 6.42, 6.55, 6.7, 6.85,
    7, 7.15, 7.31, 7.48, 7.65, 7.82, 8.01, 8.21,
    8.39, 8.57, 8.62, 8.6, 8.45, 8.31, 8.21, 8.21,
};
static const float au_eta[EV_N] = {
    1.795, 1.812, 1.822625, 1.83, 1.837125, 1.84, 1.83425, 1.824,
    1.812, 1.798, 1.782, 1.766, 1.7525, 1.74, 1.727625, 1.716,
    1.705875, 1.696, 1.68475, 1.674, 1.666, 1.658, 1.64725, 1.636,
    1.628, 1.616, 1.59625, 1.562, 1.502125, 1.426, 1.345875, 1.242,
    1.08675, 0.916, 0.7545, 0.608, 0.49175, 0.402, 0.3455, 0.306,
    0.267625, 0.236, 0.212375, 0.194, 0.17775, 0.166, 0.161, 0.16,
    0.160875, 0.164, 0.1695, 0.176, 0.181375, 0.188, 0.198125, 0.21,
};
static const float au_k[EV_N] = {
    1.920375, 1.92, 1.918875, 1.916, 1.911375, 1.904, 1.891375, 1.878,
    1.86825, 1.86, 1.85175, 1.846, 1.84525, 1.848, 1.852375, 1.862,
    1.883, 1.906, 1.9225, 1.936, 1.94775, 1.956, 1.959375, 1.958,
    1.951375, 1.94, 1.9245, 1.904, 1.875875, 1.846, 1.814625, 1.796,
    1.797375, 1.84, 1.9565, 2.12, 2.32625, 2.54, 2.730625, 2.88,
    2.940625, 2.97, 3.015, 3.06, 3.07, 3.15, 3.445812, 3.8,
    4.087687, 4.357, 4.610188, 4.86, 5.125813, 5.39, 5.63125, 5.88,
};
static const float cu_eta[EV_N] = {
    1.400313, 1.38, 1.358438, 1.34, 1.329063, 1.325, 1.3325, 1.34,
    1.334375, 1.325, 1.317812, 1.31, 1.300313, 1.29, 1.281563, 1.27,
    1.249062, 1.225, 1.2, 1.18, 1.174375, 1.175, 1.1775, 1.18,
    1.178125, 1.175, 1.172812, 1.17, 1.165312, 1.16, 1.155312, 1.15,
    1.142812, 1.135, 1.131562, 1.12, 1.092437, 1.04, 0.950375, 0.826,
    0.645875, 0.468, 0.35125, 0.272, 0.230813, 0.214, 0.20925, 0.213,
    0.21625, 0.223, 0.2365, 0.25, 0.254188, 0.26, 0.28, 0.3,
};
static const float cu_k[EV_N] = {
    1.662125, 1.687, 1.703313, 1.72, 1.744563, 1.77, 1.791625, 1.81,
    1.822125, 1.834, 1.85175, 1.872, 1.89425, 1.916, 1.931688, 1.95,
    1.972438, 2.015, 2.121562, 2.21, 2.177188, 2.13, 2.160063, 2.21,
    2.249938, 2.289, 2.326, 2.362, 2.397625, 2.433, 2.469187, 2.504,
    2.535875, 2.564, 2.589625, 2.605, 2.595562, 2.583, 2.5765, 2.599,
    2.678062, 2.809, 3.01075, 3.24, 3.458187, 3.67, 3.863125, 4.05,
    4.239563, 4.43, 4.619563, 4.817, 5.034125, 5.26, 5.485625, 5.717,
};
static const float cuzn_eta[61] = {
    1.358, 1.388, 1.419, 1.446, 1.473, 1.494, 1.504, 1.503, 1.497, 1.487,
    1.471, 1.445, 1.405, 1.35, 1.278, 1.191, 1.094, 0.994, 0.9, 0.816,
    0.745, 0.686, 0.639, 0.602, 0.573, 0.549, 0.527, 0.505, 0.484, 0.468,
    0.46, 0.45, 0.452, 0.449, 0.445, 0.444, 0.444, 0.445, 0.444, 0.444,
    0.445, 0.446, 0.448, 0.45, 0.452, 0.455, 0.457, 0.458, 0.46, 0.464,
    0.469, 0.473, 0.478, 0.481, 0.483, 0.486, 0.49, 0.494, 0.5, 0.507,
    0.515,
};
static const float cuzn_k[61] = {
    1.688, 1.731, 1.764, 1.789, 1.807, 1.815, 1.815, 1.815, 1.818, 1.818,
    1.813, 1.805, 1.794, 1.786, 1.784, 1.797, 1.829, 1.883, 1.957, 2.046,
    2.145, 2.25, 2.358, 2.464, 2.568, 2.668, 2.765, 2.86, 2.958, 3.059,
    3.159, 3.253, 3.345, 3.434, 3.522, 3.609, 3.695, 3.778, 3.86, 3.943,
    4.025, 4.106, 4.186, 4.266, 4.346, 4.424, 4.501, 4.579, 4.657, 4.737,
    4.814, 4.89, 4.965, 5.039, 5.115, 5.192, 5.269, 5.346, 5.423, 5.5,
    5.575,
};
static const float mgo_eta[60] = {   /* nm, value */
    309.95, 1.798,   330.613, 1.785,   351.119, 1.7768,   355.549, 1.7755,
    360.932, 1.7732,   361.142, 1.77318,   364.969, 1.77186,   382.065, 1.7668,
    386.712, 1.7655,   393.338, 1.7638,   404.634, 1.76104,   430.935, 1.7557,
    435.782, 1.75471,   457.829, 1.7512,   477.949, 1.7483,   486.005, 1.74711,
    487.918, 1.7469,   499.919, 1.7454,   502.35, 1.7453,   508.532, 1.74446,
    514.44, 1.7439,   546.167, 1.74077,   589.259, 1.73737,   632.874, 1.7346,
    643.718, 1.734,   656.326, 1.73335,   667.636, 1.73277,   690.696, 1.73191,
    706.439, 1.73101,   767.678, 1.72872,
};
static const float mgo_k[60] = {   /* nm, value */
    309.95, 0,   330.613, 0,   351.119, 0,   355.549, 1e-06,
    360.932, 1e-06,   361.142, 1e-06,   364.969, 0,   382.065, 0,
    386.712, 0,   393.338, 0,   404.634, 0,   430.935, 0,
    435.782, 0,   457.829, 0,   477.949, 0,   486.005, 0,
    487.918, 0,   499.919, 0,   502.35, 0,   508.532, 0,
    514.44, 0,   546.167, 0,   589.259, 0,   632.874, 0,
    643.718, 0,   656.326, 0,   667.636, 0,   690.696, 0,
    706.439, 0,   767.678, 0,
};
static const float tio2_eta[68] = {   /* nm, value */
    305.972, 3.84,   317.979, 5.38,   334.991, 4.22,   344.007, 4.36,
    359.988, 3.87,   388.044, 3.49,   399.935, 3.4,   412.031, 3.24,
    419.986, 3.29,   439.957, 3.2,   460.037, 3.13,   479.985, 3.08,
    499.919, 3.03,   520.05, 3,   539.044, 2.95,   539.983, 2.97,
    559.982, 2.94,   579.888, 2.92,   600.097, 2.9,   619.9, 2.88,
    640.062, 2.87,   659.819, 2.85,   680.088, 2.84,   700.056, 2.83,
    719.977, 2.82,   740.179, 2.81,   760.147, 2.81,   779.748, 2.8,
    799.871, 2.79,   819.9741, 2.79,   839.9731, 2.78,   859.778, 2.78,
    879.915, 2.77,   899.71, 2.77,
};
static const float tio2_k[68] = {   /* nm, value */
    305.972, 1.95,   317.979, 2.18,   334.991, 0.788,   344.007, 0,
    359.988, 0.251,   388.044, 0,   399.935, 0,   412.031, 0.022,
    419.986, 0,   439.957, 0,   460.037, 0,   479.985, 0,
    499.919, 0,   520.05, 0,   539.044, 0,   539.983, 0,
    559.982, 0,   579.888, 0,   600.097, 0,   619.9, 0,
    640.062, 0,   659.819, 0,   680.088, 0,   700.056, 0,
    719.977, 0,   740.179, 0,   760.147, 0,   779.748, 0,
    799.871, 0,   819.9741, 0,   839.9731, 0,   859.778, 0,
    879.915, 0,   899.71, 0,
};

/* The table (lambda[i], v[i]), i < n, with increasing lambda, resampled onto the
   1 nm grid: linear inside, held constant outside. */
static void resample(Spectrum *s, const double *lambda, const float *v, int n)
{
    int nm, i = 0;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) {
        double x = nm, t;
        float *out = spec_at(s, nm);
        if (x <= lambda[0]) { *out = v[0]; continue; }
        if (x >= lambda[n - 1]) { *out = v[n - 1]; continue; }
        while (lambda[i + 1] < x) i++;             /* lambda[i] < x <= lambda[i + 1] */
        t = (x - lambda[i]) / (lambda[i + 1] - lambda[i]);
        *out = (float)((1.0 - t) * v[i] + t * v[i + 1]);
    }
}

/* A table on the photon-energy grid: wavelengths increase as E falls. */
static void from_ev_grid(Spectrum *s, const float *v)
{
    double lambda[EV_N];
    int i;
    for (i = 0; i < EV_N; i++) lambda[i] = HC_EV_NM / (EV_FIRST - EV_STEP * i);
    resample(s, lambda, v, EV_N);
}

/* A table every step nm from first nm. */
static void from_even_grid(Spectrum *s, const float *v, int n, double first, double step)
{
    double lambda[64];
    int i;
    for (i = 0; i < n && i < 64; i++) lambda[i] = first + step * i;
    resample(s, lambda, v, n < 64 ? n : 64);
}

/* A table of (nm, value) pairs, n_pairs of them. */
static void from_pairs(Spectrum *s, const float *pairs, int n_pairs)
{
    double lambda[64];
    float v[64];
    int i;
    for (i = 0; i < n_pairs && i < 64; i++) { lambda[i] = pairs[2 * i]; v[i] = pairs[2 * i + 1]; }
    resample(s, lambda, v, n_pairs < 64 ? n_pairs : 64);
}

#define N_OF(a) ((int)(sizeof (a) / sizeof (a)[0]))

static const char *const metal_names[] = {
    "metal-Ag-eta", "metal-Ag-k", "metal-Al-eta", "metal-Al-k", "metal-Au-eta", "metal-Au-k",
    "metal-Cu-eta", "metal-Cu-k", "metal-CuZn-eta", "metal-CuZn-k", "metal-MgO-eta",
    "metal-MgO-k", "metal-TiO2-eta", "metal-TiO2-k", NULL
};

/* Names compare without regard to case, as spec_named's others do. */
static int same_name(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

int metal_named(Spectrum *s, const char *name)
{
    static const float *const ev[8] = { ag_eta, ag_k, al_eta, al_k, au_eta, au_k, cu_eta, cu_k };
    int i;
    for (i = 0; metal_names[i]; i++)
        if (same_name(name, metal_names[i])) break;
    if (!metal_names[i]) return 0;
    if (i < 8) from_ev_grid(s, ev[i]);
    else if (i == 8) from_even_grid(s, cuzn_eta, N_OF(cuzn_eta), 290.0, 10.0);
    else if (i == 9) from_even_grid(s, cuzn_k, N_OF(cuzn_k), 290.0, 10.0);
    else if (i == 10) from_pairs(s, mgo_eta, N_OF(mgo_eta) / 2);
    else if (i == 11) from_pairs(s, mgo_k, N_OF(mgo_k) / 2);
    else if (i == 12) from_pairs(s, tio2_eta, N_OF(tio2_eta) / 2);
    else from_pairs(s, tio2_k, N_OF(tio2_k) / 2);
    return 1;
}
