/* tests/test_spectrum.c - tests of spectrum.c (spectra, CIE colorimetry, named
   spectra, files, rgb upsampling, thesis eq. 6 bins, wavelength sampling) and svg.c.

   Reference values: CIE 015:2018 tables (ybar(555) = 1, xbar(600) = 1.0622,
   zbar(445) = 1.7826, integral of ybar = 106.857 nm); D65 white xy = (0.3127,
   0.3290), CCT 6504 K; CIE A = 2856 K; SCHOTT catalogue n_d of N-BK7 = 1.5168,
   SF10 = 1.72825; the thesis' lamp CCTs 4404 K, 5832 K, 7600 K (its Table 1).
   Statistical tests state their bound: chi-square by its p-value (CHECK_CHI2,
   tests/test.h). */
#include "test.h"
#include <string.h>
#include <stdlib.h>

/* ---------- helpers ---------- */

static double y_sum(const Spectrum *s)          /* sum_{360..830, 1 nm} ybar S */
{
    double xyz[3];
    spec_to_xyz(s, (float)SPEC_MIN, (float)SPEC_MAX, xyz);
    return xyz[1] * cie_y_integral((float)SPEC_MIN, (float)SPEC_MAX);
}

static double cct_of(const Spectrum *s, double *duv)
{
    double x, y;
    spec_chromaticity(s, &x, &y);
    return cct_from_xy(x, y, duv);
}

/* linear sRGB of a reflectance s lit by D65 (Y of the white = 1) */
static void reflectance_rgb(const Spectrum *s, double rgb[3])
{
    Spectrum d65, lit;
    double xyz[3];
    int i;
    spec_named(&d65, "stdillum-D65");
    for (i = 0; i < SPEC_N; i++) lit.v[i] = s->v[i] * d65.v[i];
    spec_to_xyz(&lit, (float)SPEC_MIN, (float)SPEC_MAX, xyz);
    xyz_to_linear_srgb(xyz, rgb);
}

/* the message starts with "path:line:" */
static int msg_at(const Error *e, const char *path, int line)
{
    char want[1100];
    snprintf(want, sizeof want, "%s:%d:", path, line);
    return strncmp(e->msg, want, strlen(want)) == 0;
}

/* ---------- CIE tables and colorimetry ---------- */

static void test_cie_values(T *t)
{
    float c[3];
    double s5 = 0.0;
    int l;
    cie_xyz(555.0f, c);
    CHECK(t, fabs(c[1] - 1.0) < 1e-6, "ybar(555) = %g, want 1", (double)c[1]);
    cie_xyz(600.0f, c);
    CHECK(t, fabs(c[0] - 1.0622) < 1e-6, "xbar(600) = %g, want 1.0622", (double)c[0]);
    cie_xyz(445.0f, c);
    CHECK(t, fabs(c[2] - 1.7826) < 1e-6, "zbar(445) = %g, want 1.7826", (double)c[2]);
    cie_xyz(557.5f, c);                           /* halfway between 555 and 560 */
    CHECK(t, fabs(c[1] - 0.5 * (1.0 + 0.995)) < 1e-6, "ybar(557.5) = %g is not linear", (double)c[1]);
    cie_xyz(359.0f, c);
    CHECK(t, c[0] == 0 && c[1] == 0 && c[2] == 0, "cmf outside 360..830 must be 0");
    cie_xyz(831.0f, c);
    CHECK(t, c[0] == 0 && c[1] == 0 && c[2] == 0, "cmf outside 360..830 must be 0");
    {   /* all three are linear between their 5 nm knots, with the knots' values */
        double x, d[3], a[3], b[3], worst = 0.0;
        for (x = 360.0; x < 830.0; x += 0.37) {
            double k = 360.0 + 5.0 * floor((x - 360.0) / 5.0), f = (x - k) / 5.0;
            int j;
            cie_cmf(x, d);
            cie_cmf(k, a);
            cie_cmf(k + 5.0, b);
            for (j = 0; j < 3; j++) worst = fmax(worst, fabs(d[j] - ((1.0 - f) * a[j] + f * b[j])));
        }
        CHECK(t, worst < 1e-9, "the CMFs are off the lines between their knots by up to %g", worst);
    }
    for (l = 360; l <= 830; l += 5) { cie_xyz((float)l, c); s5 += c[1]; }
    CHECK(t, fabs(5.0 * s5 - 106.857) < 0.01, "5 sum ybar = %.5f, want 106.857", 5.0 * s5);
    CHECK(t, fabs(cie_y_integral(360, 830) - 106.857) < 0.01, "cie_y_integral = %.5f",
          cie_y_integral(360, 830));
    CHECK(t, fabs(cie_y_integral(555, 555) - 1.0) < 1e-6, "one-sample integral");
    CHECK(t, cie_y_integral(700, 400) == 0.0, "empty range must give 0");
}

static void test_d65(T *t)
{
    Spectrum d65, e;
    double x, y, duv, cct, xyz[3], rgb[3];
    CHECK(t, spec_named(&d65, "stdillum-D65"), "stdillum-D65 unknown");
    spec_chromaticity(&d65, &x, &y);
    CHECK(t, fabs(x - 0.3127) < 5e-4 && fabs(y - 0.3290) < 5e-4, "D65 xy = (%.5f, %.5f)", x, y);
    cct = cct_from_xy(x, y, &duv);
    CHECK(t, fabs(cct - 6504.0) < 10.0, "D65 CCT = %.1f K, want 6504 +- 10", cct);
    CHECK(t, duv > 0.0 && duv < 0.005, "D65 lies slightly above the locus, Duv = %g", duv);
    spec_to_xyz(&d65, 360, 830, xyz);
    CHECK(t, fabs(xyz[1] - 1.0) < 1e-4, "named D65 has Y = %.6f, want 1 (pbrt scaling)", xyz[1]);
    xyz_to_linear_srgb(xyz, rgb);
    CHECK(t, fabs(rgb[0] - 1) < 1e-3 && fabs(rgb[1] - 1) < 1e-3 && fabs(rgb[2] - 1) < 1e-3,
          "D65 (Y = 1) -> sRGB (%.5f, %.5f, %.5f), want (1, 1, 1)", rgb[0], rgb[1], rgb[2]);
    spec_const(&e, 1.0f);                         /* equal energy: Y = 1 on any range */
    spec_to_xyz(&e, 400, 700, xyz);
    CHECK(t, fabs(xyz[1] - 1.0) < 1e-9, "equal-energy Y = %.12f on 400-700", xyz[1]);
    spec_to_xyz(&e, 360, 830, xyz);
    CHECK(t, fabs(xyz[1] - 1.0) < 1e-9 && fabs(xyz[0] - 1.0) < 2e-3 && fabs(xyz[2] - 1.0) < 2e-3,
          "equal-energy XYZ = (%.5f, %.5f, %.5f)", xyz[0], xyz[1], xyz[2]);
}

static void test_blackbody_and_cct(T *t)
{
    Spectrum s;
    double duv, cct, peak = 0.0;
    int i, i_peak = 0;
    spec_blackbody(&s, 5000.0f);                 /* Wien: peak at 2.8978e-3 / 5000 = 579.6 nm */
    for (i = 0; i < SPEC_N; i++) if (s.v[i] > peak) { peak = s.v[i]; i_peak = i; }
    CHECK(t, fabs(peak - 1.0) < 1e-4, "blackbody peak %.6f, want 1", peak);
    CHECK(t, abs(SPEC_MIN + i_peak - 580) <= 1, "blackbody 5000 K peaks at %d nm, want 580", SPEC_MIN + i_peak);
    cct = cct_of(&s, &duv);
    CHECK(t, fabs(cct - 5000.0) < 1.0 && fabs(duv) < 1e-5, "blackbody 5000 K: CCT %.2f, Duv %g", cct, duv);
    spec_blackbody(&s, 2700.0f);
    cct = cct_of(&s, &duv);
    CHECK(t, fabs(cct - 2700.0) < 1.0, "blackbody 2700 K: CCT %.2f", cct);
    spec_named(&s, "stdillum-A");
    cct = cct_of(&s, &duv);
    CHECK(t, fabs(cct - 2856.0) < 3.0 && fabs(duv) < 1e-4, "illuminant A: CCT %.1f, Duv %g", cct, duv);
    spec_blackbody(&s, -1.0f);
    CHECK(t, s.v[200] == 0.0f, "a negative temperature gives zero");
    cct = cct_from_xy(0.3, -0.2, &duv);
    CHECK(t, cct == 0.0 && duv == 0.0, "an invalid chromaticity gives 0");
    /* above/below the locus: move D65's chromaticity towards green / magenta */
    cct_from_xy(0.3127, 0.3400, &duv);
    CHECK(t, duv > 0.0, "greener than D65 must give Duv > 0 (got %g)", duv);
    cct_from_xy(0.3127, 0.3100, &duv);
    CHECK(t, duv < 0.0, "pinker than D65 must give Duv < 0 (got %g)", duv);
}

/* CIE F-illuminants: documented CCTs (CIE 015:2018 table 10.3) and pbrt's scaling */
static void test_fluorescent_illuminants(T *t)
{
    static const double cct_cie[12] = { 6430, 4230, 3450, 2940, 6350, 4150, 6500, 5000, 4150,
                                        5000, 4000, 3000 };
    Spectrum s;
    char name[32];
    int k;
    for (k = 1; k <= 12; k++) {
        double duv, cct;
        snprintf(name, sizeof name, "stdillum-F%d", k);
        CHECK(t, spec_named(&s, name), "%s unknown", name);
        CHECK(t, fabs(y_sum(&s) - 106.856895) < 1e-3, "%s: sum ybar S = %.6f, want 106.856895",
              name, y_sum(&s));
        cct = cct_of(&s, &duv);
        CHECK(t, fabs(cct - cct_cie[k - 1]) < 0.01 * cct_cie[k - 1] + 10.0,
              "%s: CCT %.0f K, CIE lists %.0f K", name, cct, cct_cie[k - 1]);
        CHECK(t, spec_eval(&s, 370.0f) == 0.0f && spec_eval(&s, 790.0f) == 0.0f,
              "%s must be zero outside its 380-780 nm table", name);
    }
}

/* ---------- named spectra ---------- */

static void test_named(T *t)
{
    static const char *const required[] = {
        "stdillum-D65", "stdillum-A", "stdillum-F1", "stdillum-F12", "glass-BK7", "glass-BAF10",
        "glass-FK51A", "glass-LASF9", "glass-F5", "glass-F10", "glass-F11", "cauchy-BK7",
        "cauchy-fused-silica", "cauchy-SF10", "cauchy-SF11", "cauchy-diamond", "cauchy-teaching",
        "cauchy-teaching-strong", "lamp-CFL1", "lamp-LED1", "lamp-LED2", NULL };
    static const char *const unknown[] = {
        "", "stdillum-F0", "stdillum-F13", "stdillum-F1x", "stdillum-F", "glass-XYZ", "cauchy-",
        "cauchy-unobtainium", "lamp-LED3", "D65", NULL };
    const char *const *list = spec_named_list();
    Spectrum s;
    int i, j, n = 0;
    for (i = 0; list[i]; i++) {
        n++;
        CHECK(t, spec_named(&s, list[i]), "listed name '%s' does not resolve", list[i]);
        for (j = 0; j < SPEC_N; j++)
            CHECK(t, isfinite(s.v[j]) && s.v[j] >= 0.0f, "%s: bad value %g at %d nm", list[i],
                  (double)s.v[j], SPEC_MIN + j);
    }
    CHECK(t, n >= 31, "only %d names listed", n);
    for (i = 0; required[i]; i++) {
        int found = 0;
        for (j = 0; list[j]; j++) found |= strcmp(list[j], required[i]) == 0;
        CHECK(t, found, "'%s' missing from spec_named_list", required[i]);
    }
    for (i = 0; unknown[i]; i++)
        CHECK(t, !spec_named(&s, unknown[i]), "'%s' must be unknown", unknown[i]);
    CHECK(t, !spec_named(&s, NULL), "NULL name must fail");
    CHECK(t, spec_named(&s, "STDILLUM-d65"), "names are case-insensitive");
}

/* ---------- the thesis' lamps ---------- */

static void test_lamps(T *t)
{
    static const char *const names[3] = { "lamp-CFL1", "lamp-LED1", "lamp-LED2" };
    static const double target[3] = { 4404.0, 5832.0, 7600.0 };   /* thesis Table 1 */
    Spectrum s;
    int k;
    for (k = 0; k < 3; k++) {
        double duv, cct, sum;
        CHECK(t, spec_named(&s, names[k]), "%s unknown", names[k]);
        cct = cct_of(&s, &duv);
        CHECK(t, fabs(cct - target[k]) < 25.0, "%s: CCT %.1f K, want %.0f +- 25", names[k], cct, target[k]);
        /* |Duv| < 0.006: the ANSI C78.377 tolerance for "white" solid-state light */
        CHECK(t, fabs(duv) < 0.006, "%s: Duv %g is not white", names[k], duv);
        sum = spec_bin_sum(&s);
        CHECK(t, fabs(sum - 1.0) < 1e-5, "%s: thesis eq. 6 bin sum %.8f, want 1", names[k], sum);
    }
    /* the CFL's 435.8 nm mercury line: its 2 nm FWHM Gaussian, cell-averaged, keeps
       its area: sum of the 1 nm cells near the line ~ peak * 1.0645 * FWHM */
    spec_named(&s, "lamp-CFL1");
    CHECK(t, spec_eval(&s, 435.8f) > 5.0f * spec_eval(&s, 470.0f), "CFL1 must show the Hg 436 nm line");
    CHECK(t, spec_eval(&s, 611.0f) > spec_eval(&s, 640.0f) * 3.0f, "CFL1 must show the Eu 611 nm line");
}

/* ---------- glasses ---------- */

static void test_cauchy_and_glass(T *t)
{
    Spectrum glass, cauchy;
    float A = 0, B = 0, l;
    double n;
    CHECK(t, cauchy_named("BK7", &A, &B), "BK7 unknown");
    n = cauchy_eta(A, B, 587.6f);
    CHECK(t, fabs(n - 1.5168) < 1e-3, "Cauchy n_BK7(587.6) = %.5f, want 1.5168", n);
    CHECK(t, cauchy_named("bk7", &A, &B) && cauchy_named("cauchy-Fused-Silica", &A, &B),
          "cauchy_named must ignore case and accept the cauchy- prefix");
    CHECK(t, fabs(cauchy_eta(A, B, 587.6f) - 1.4585) < 1e-3, "fused silica n_d %.5f",
          (double)cauchy_eta(A, B, 587.6f));
    CHECK(t, cauchy_named("teaching-strong", &A, &B) && A == 1.50f && B == 0.04f, "teaching-strong");
    CHECK(t, !cauchy_named("glass", &A, &B) && !cauchy_named(NULL, &A, &B), "unknown Cauchy glass");
    spec_named(&glass, "glass-BK7");
    spec_named(&cauchy, "cauchy-BK7");
    for (l = 380.0f; l <= 780.0f; l += 1.0f) {
        double d = spec_eval(&glass, l) - spec_eval(&cauchy, l);
        CHECK(t, fabs(d) < 2e-3, "glass-BK7 vs Cauchy BK7 at %g nm: %.5f", (double)l, d);
    }
    /* Sellmeier tables reproduce the SCHOTT catalogue n_d (587.56 nm) */
    CHECK(t, fabs(spec_eval(&glass, 587.56f) - 1.51680) < 2e-5, "glass-BK7 n_d %.6f",
          (double)spec_eval(&glass, 587.56f));
    spec_named(&glass, "glass-F10");
    CHECK(t, fabs(spec_eval(&glass, 587.56f) - 1.72825) < 2e-5, "glass-F10 (SF10) n_d %.6f",
          (double)spec_eval(&glass, 587.56f));
    spec_named(&glass, "glass-LASF9");
    CHECK(t, fabs(spec_eval(&glass, 587.56f) - 1.85025) < 2e-5, "glass-LASF9 n_d %.6f",
          (double)spec_eval(&glass, 587.56f));
    CHECK(t, spec_eval(&glass, 400.0f) > spec_eval(&glass, 700.0f), "normal dispersion");
}

/* ---------- pairs and files ---------- */

static void test_pairs(T *t)
{
    static const float l3[3] = { 400.0f, 500.0f, 600.5f }, v3[3] = { 1.0f, 3.0f, 0.0f };
    static const float lbad[3] = { 400.0f, 500.0f, 500.0f };
    float lnan[2], vnan[2];
    Spectrum s;
    Error e;
    CHECK(t, spec_from_pairs(&s, l3, v3, 3, &e, "a.pbrt", 7), "valid pairs rejected: %s", e.msg);
    CHECK(t, spec_eval(&s, 399.0f) == 0.0f && spec_eval(&s, 601.0f) == 0.0f, "zero outside the pairs");
    CHECK(t, fabs(spec_eval(&s, 450.0f) - 2.0) < 1e-6, "linear inside: %g", (double)spec_eval(&s, 450.0f));
    CHECK(t, fabs(spec_eval(&s, 450.5f) - 2.01) < 1e-5, "interpolation between 1 nm samples");
    CHECK(t, fabs(spec_eval(&s, 600.0f) - 3.0 * 0.5 / 100.5) < 1e-6, "last segment");
    CHECK(t, !spec_is_constant(&s), "not constant");
    spec_const(&s, 0.25f);
    CHECK(t, spec_is_constant(&s) && spec_eval(&s, 777.7f) == 0.25f, "constant");
    CHECK(t, spec_eval(&s, 299.0f) == 0.0f && spec_eval(&s, 900.0f) == 0.0f && spec_eval(&s, NAN) == 0.0f,
          "spec_eval outside the table (300-830 nm with its UV extension) is 0");
    CHECK(t, spec_eval(&s, 300.0f) == 0.25f && spec_eval(&s, 359.5f) == 0.25f,
          "a constant reaches into the UV extension");
    CHECK(t, !spec_from_pairs(&s, lbad, v3, 3, &e, "a.pbrt", 7) && msg_at(&e, "a.pbrt", 7) &&
          strstr(e.msg, "increase"), "equal wavelengths must fail: '%s'", e.msg);
    CHECK(t, !spec_from_pairs(&s, l3, v3, 0, &e, "a.pbrt", 9) && msg_at(&e, "a.pbrt", 9),
          "no pairs must fail: '%s'", e.msg);
    lnan[0] = 400.0f; lnan[1] = 500.0f; vnan[0] = 1.0f; vnan[1] = NAN;
    CHECK(t, !spec_from_pairs(&s, lnan, vnan, 2, &e, "a.pbrt", 3) && msg_at(&e, "a.pbrt", 3),
          "NaN must fail: '%s'", e.msg);
}

static void test_file_formats(T *t)
{
    Spectrum s;
    Error e;
    const char *p;
    p = test_write_file(t, "spec_a.spd",
                        "# a pbrt .spd file\n400 1.0  450 2.0 # comment after pairs\n"
                        "500\n3.0\n\n   600 1e0\n# xy = 0.3, 0.3: commas in comments are fine\n");
    CHECK(t, spec_from_file(&s, p, &e), "spd rejected: %s", e.msg);
    CHECK(t, fabs(spec_eval(&s, 425.0f) - 1.5) < 1e-6 && fabs(spec_eval(&s, 550.0f) - 2.0) < 1e-6 &&
          spec_eval(&s, 650.0f) == 0.0f, "spd values wrong");
    p = test_write_file(t, "spec_b.csv", "Wavelength (nm),Relative intensity\r\n400,1\r\n500,3\r\n");
    CHECK(t, spec_from_file(&s, p, &e), "csv with header rejected: %s", e.msg);
    CHECK(t, fabs(spec_eval(&s, 450.0f) - 2.0) < 1e-6, "csv values wrong");
    p = test_write_file(t, "spec_c.csv", "400, 1\n\"500\",\"3\"\n# done\n");
    CHECK(t, spec_from_file(&s, p, &e), "csv without header rejected: %s", e.msg);
    CHECK(t, fabs(spec_eval(&s, 450.0f) - 2.0) < 1e-6, "csv (no header) values wrong");
}

static void test_file_errors(T *t)
{
    static const struct { const char *name, *text; int line; const char *what; } cases[] = {
        { "err_word.spd", "400 1\n450 2\n500 x3\n", 3, "not a number" },
        { "err_odd.spd", "400 1\n450 2\n500\n", 3, "odd" },
        { "err_order.spd", "400 1\n450 2\n# c\n440 2\n", 4, "increase" },
        { "err_empty.spd", "# nothing here\n\n", 2, "no (wavelength" },
        { "err_nan.spd", "400 1\n450 nan\n", 2, "finite" },
        { "err_inf.csv", "wavelength,value\n400,1\n450,inf\n", 3, "finite" },
        { "err_field.csv", "wavelength,value\n400,1\n450,abc\n", 3, "not a number" },
        { "err_three.csv", "400,1\n450,2,3\n", 2, "2 fields" },
        { "err_nocomma.csv", "400,1\n450\n", 2, "wavelength,value" },
        { "err_order.csv", "400,1\n400,2\n", 2, "increase" },
        { "err_big.spd", "400 1e300\n", 1, "finite" },
    };
    Spectrum s;
    Error e;
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *p = test_write_file(t, cases[k].name, cases[k].text);
        e.msg[0] = '\0';
        CHECK(t, !spec_from_file(&s, p, &e), "%s must be rejected", cases[k].name);
        CHECK(t, msg_at(&e, p, cases[k].line) && strstr(e.msg, cases[k].what) && !strchr(e.msg, '\n'),
              "%s: message '%s' should be '%s:%d: ...%s...'", cases[k].name, e.msg, p,
              cases[k].line, cases[k].what);
    }
    CHECK(t, !spec_from_file(&s, test_path(t, "no_such_file.spd"), &e) && strstr(e.msg, "no_such_file"),
          "a missing file must fail with its name: '%s'", e.msg);
}

/* ---------- thesis eq. 6 bins ---------- */

static void test_bins(T *t)
{
    static const float l_edge[3] = { 404.0f, 405.0f, 406.0f }, v_edge[3] = { 0.0f, 1.0f, 0.0f };
    static const float l_in[3] = { 411.0f, 412.0f, 413.0f };
    Spectrum s;
    Error e;
    int b;
    spec_const(&s, 1.0f);
    CHECK(t, fabs(spec_bin_sum(&s) - 60.0) < 1e-9, "constant 1: bin sum %g, want 60", spec_bin_sum(&s));
    /* a 1 nm wide line centred on the 405 nm bin edge: half its area in each bin
       (area 1 nm, so each bin mean is 0.5 / 5 = 0.1); a point sample at the bin
       centres (402.5, 407.5) would see nothing */
    CHECK(t, spec_from_pairs(&s, l_edge, v_edge, 3, &e, "t", 1), "%s", e.msg);
    CHECK(t, fabs(spec_bin_average(&s, 0) - 0.1) < 1e-6 && fabs(spec_bin_average(&s, 1) - 0.1) < 1e-6,
          "edge line: bins 0, 1 = %g, %g, want 0.1 each", (double)spec_bin_average(&s, 0),
          (double)spec_bin_average(&s, 1));
    CHECK(t, spec_eval(&s, 402.5f) == 0.0f && spec_eval(&s, 407.5f) == 0.0f, "point samples miss the line");
    for (b = 2; b < SPD_BINS; b++) CHECK(t, spec_bin_average(&s, b) == 0.0f, "bin %d must be 0", b);
    /* a line inside bin 2 (410-415 nm) lands there only */
    CHECK(t, spec_from_pairs(&s, l_in, v_edge, 3, &e, "t", 1), "%s", e.msg);
    CHECK(t, fabs(spec_bin_average(&s, 2) - 0.2) < 1e-6 && spec_bin_average(&s, 1) == 0.0f &&
          spec_bin_average(&s, 3) == 0.0f, "inner line: bin 2 = %g", (double)spec_bin_average(&s, 2));
    CHECK(t, spec_bin_average(&s, -1) == 0.0f && spec_bin_average(&s, SPD_BINS) == 0.0f, "bins out of range");
    /* a ramp: the bin mean equals the value at the bin centre exactly */
    for (b = 0; b < SPEC_N; b++) s.v[b] = (float)(SPEC_MIN + b);
    CHECK(t, fabs(spec_bin_average(&s, 10) - 452.5) < 1e-4, "ramp bin 10 mean %g, want 452.5",
          (double)spec_bin_average(&s, 10));
}

/* ---------- rgb upsampling ---------- */

static void test_rgb_reflectance(T *t)
{
    static const float levels[5] = { 0.1f, 0.3f, 0.5f, 0.7f, 0.9f };
    Spectrum s;
    Error e;
    double rgb[3], worst = 0.0, worst_grey = 0.0;
    float in[3];
    int a, b, c, i;
    /* round trip over a 5^3 grid of in-gamut colours: the measured worst error is
       documented in rgbfit.c */
    for (a = 0; a < 5; a++)
        for (b = 0; b < 5; b++)
            for (c = 0; c < 5; c++) {
                in[0] = levels[a]; in[1] = levels[b]; in[2] = levels[c];
                CHECK(t, spec_from_rgb(&s, in, 0, &e, "t", 1), "rgb rejected: %s", e.msg);
                for (i = 0; i < SPEC_N; i++)
                    CHECK(t, s.v[i] >= 0.0f && s.v[i] <= 1.0f, "reflectance outside [0, 1]");
                reflectance_rgb(&s, rgb);
                for (i = 0; i < 3; i++) {
                    double d = fabs(rgb[i] - in[i]);
                    if (a == b && b == c) { if (d > worst_grey) worst_grey = d; }
                    else if (d > worst) worst = d;
                }
            }
    /* measured: 1.3e-6 (the float table); greys are flat spectra, off by the
       difference between pbrt-v4's matrix white and D65 through these CMFs */
    CHECK(t, worst < 1e-5, "rgb -> spectrum -> rgb worst error %.2e over the grid", worst);
    CHECK(t, worst_grey < 2e-4, "grey round trip error %.2e", worst_grey);
    in[0] = in[1] = in[2] = 0.6f;                 /* grey: exactly constant */
    spec_from_rgb(&s, in, 0, &e, "t", 1);
    CHECK(t, spec_is_constant(&s) && s.v[0] == 0.6f, "grey must give a constant spectrum");
    in[0] = 2.0f; in[1] = -1.0f; in[2] = 0.5f;    /* clamped to (1, 0, 0.5) */
    CHECK(t, spec_from_rgb(&s, in, 0, &e, "t", 1), "out-of-range rgb must be clamped, not rejected");
    for (i = 0; i < SPEC_N; i++) CHECK(t, s.v[i] >= 0.0f && s.v[i] <= 1.0f, "clamped reflectance");
    reflectance_rgb(&s, rgb);
    /* (1, 0, 0.5) is on the sRGB gamut boundary; sharp sigmoids still reach it */
    CHECK(t, fabs(rgb[0] - 1.0) < 1e-3 && fabs(rgb[1]) < 1e-3 && fabs(rgb[2] - 0.5) < 1e-3,
          "boundary colour (1, 0, 0.5) -> (%.3f, %.3f, %.3f)", rgb[0], rgb[1], rgb[2]);
    in[1] = NAN;
    CHECK(t, !spec_from_rgb(&s, in, 0, &e, "scene.pbrt", 12) && msg_at(&e, "scene.pbrt", 12),
          "NaN rgb must fail with file:line: '%s'", e.msg);
}

/* An "rgb" albedo through the load's table is finite and within [0, 1] at every
   knot, the UV ones included (material.c's diffuse reflectance relies on it and
   does not check it again): an 11^3 grid of the unit cube, faces, edges and
   corners included. */
static void test_rgb_albedo_in_unit(T *t)
{
    RgbTable *tab = rgb_table_new();
    Spectrum s;
    Error e;
    float in[3];
    int a, b, c, i, bad = 0;
    if (!tab) { CHECK(t, 0, "rgb_table_new: out of memory"); return; }
    for (a = 0; a <= 10; a++)
        for (b = 0; b <= 10; b++)
            for (c = 0; c <= 10; c++) {
                in[0] = 0.1f * a; in[1] = 0.1f * b; in[2] = 0.1f * c;
                if (!spec_from_rgb_t(tab, &s, in, 0, &e, "t", 1)) { bad++; continue; }
                for (i = 0; i < SPEC_N; i++) bad += !(s.v[i] >= 0.0f && s.v[i] <= 1.0f);
                for (i = 0; i < SPEC_UV_N; i++) bad += !(s.uv[i] >= 0.0f && s.uv[i] <= 1.0f);
            }
    CHECK(t, bad == 0, "%d knots of rgb albedos outside [0, 1] (or refused)", bad);
    rgb_table_free(tab);
}

/* One colour: its Albedo against spec_eval of spec_from_rgb_t's table at the
   n wavelengths lam; the count of values that differ (bit for bit) or leave [0, 1]
   (n when the colour is not taken). */
static int albedo_mismatches(T *t, RgbTable *tab, const float rgb[3], const float *lam, int n)
{
    Spectrum s;
    Albedo a;
    Error e;
    int i, bad = 0;
    memset(&a, 0, sizeof a);
    if (!spec_from_rgb_t(tab, &s, rgb, 0, &e, "t", 1) || !albedo_from_rgb(tab, rgb, &a) || !a.rgb) {
        test_failf(t, __FILE__, __LINE__, "(%g, %g, %g) not taken as a colour", rgb[0], rgb[1], rgb[2]);
        return n;
    }
    for (i = 0; i < n; i++) {
        float v = albedo_eval(&a, lam[i]);
        bad += !(v == spec_eval(&s, lam[i]) && v >= 0.0f && v <= 1.0f);
    }
    return bad;
}

/* A material's "rgb" reflectance kept as its sigmoid's three coefficients (Albedo)
   evaluates exactly as the dense table it replaces: spec_eval of spec_from_rgb_t's
   table, bit for bit (the stated tolerance is 0), and within [0, 1].  Colours: a
   9^3 grid of [0, 1]^3 (0 and 1 included: the saturated faces and corners lie
   outside any spectrum's gamut, where the sigmoid reaches 0 or 1), 500 random
   ones, near-greys; wavelengths: 2,000 over 295-835 nm at an irrational step,
   every knot, and the edges (the UV ramp 359-360 nm, 830 nm and past it).  A grey,
   a component outside [0, 1] or NaN is not taken (the caller tabulates it: a grey's
   table is the grey in the UV too; the others are refused there). */
static void test_albedo_compact(T *t)
{
    static float lam[2000 + 541 + 12];
    static const float edge[12] = { 295.0f, 300.0f, 358.999f, 359.0f, 359.25f, 359.9999f,
                                    360.0f, 360.0001f, 829.9999f, 830.0f, 830.5f, 1000.0f };
    static const float near_grey[4][3] = { { 0.5f, 0.5f, 0.50001f }, { 1.0f, 1.0f, 0.999f },
                                           { 0.0f, 0.0f, 1e-4f }, { 1.0f, 1.0f, 0.0f } };
    RgbTable *tab = rgb_table_new();
    float rgb[3], nan = NAN;
    Albedo a;
    unsigned u = 12345u;
    int n = 0, i, r, g, b, bad = 0, taken = 0;
    if (!tab) { CHECK(t, 0, "rgb_table_new: out of memory"); return; }
    for (i = 0; i < 2000; i++) lam[n++] = 295.0f + (float)i * 0.2701f;
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++) lam[n++] = (float)i;
    for (i = 0; i < 12; i++) lam[n++] = edge[i];
    for (r = 0; r <= 8; r++)
        for (g = 0; g <= 8; g++)
            for (b = 0; b <= 8; b++) {
                rgb[0] = r / 8.0f; rgb[1] = g / 8.0f; rgb[2] = b / 8.0f;
                if (r == g && g == b) continue;
                bad += albedo_mismatches(t, tab, rgb, lam, n);
            }
    for (i = 0; i < 500; i++) {
        for (r = 0; r < 3; r++) { u = u * 1664525u + 1013904223u; rgb[r] = (float)(u >> 8) / 16777216.0f; }
        bad += albedo_mismatches(t, tab, rgb, lam, n);
    }
    for (i = 0; i < 4; i++) bad += albedo_mismatches(t, tab, near_grey[i], lam, n);
    CHECK(t, bad == 0, "%d values of compact albedos differ from the table's or leave [0, 1]", bad);
    /* not taken: greys, components outside [0, 1], NaN */
    for (i = 0; i < 6; i++) {
        static const float no[6][3] = { { 0, 0, 0 }, { 1, 1, 1 }, { 0.3f, 0.3f, 0.3f },
                                        { 1.5f, 0.2f, 0.3f }, { 0.2f, -0.1f, 0.3f }, { 0.2f, 0.3f, 0 } };
        memcpy(rgb, no[i], sizeof rgb);
        if (i == 5) rgb[2] = nan;
        memset(&a, 0, sizeof a);
        taken += albedo_from_rgb(tab, rgb, &a) || a.rgb;
    }
    CHECK(t, taken == 0, "%d greys or invalid colours taken as a compact albedo", taken);
    /* a zeroed Albedo is zero; a table is read as spec_eval reads it */
    {
        Spectrum s;
        memset(&a, 0, sizeof a);
        spec_named(&s, "stdillum-D65");
        CHECK(t, albedo_eval(&a, 550.0f) == 0.0f && albedo_eval(&a, 330.0f) == 0.0f, "a zeroed Albedo is not 0");
        a.tab = &s;
        CHECK(t, albedo_eval(&a, 551.3f) == spec_eval(&s, 551.3f), "a table is not read as spec_eval");
    }
    rgb_table_free(tab);
}

static void test_rgb_illuminant(T *t)
{
    Spectrum s, d65;
    Error e;
    double xyz[3], rgb[3];
    float in[3] = { 1.0f, 1.0f, 1.0f };
    int i;
    CHECK(t, spec_from_rgb(&s, in, 1, &e, "t", 1), "%s", e.msg);
    spec_named(&d65, "stdillum-D65");
    for (i = 0; i < SPEC_N; i++)
        CHECK(t, fabs(s.v[i] - d65.v[i]) < 1e-5 * (1.0 + d65.v[i]), "white illuminant must be D65 (Y = 1)");
    in[0] = 2.0f; in[1] = 1.0f; in[2] = 0.5f;
    CHECK(t, spec_from_rgb(&s, in, 1, &e, "t", 1), "%s", e.msg);
    spec_to_xyz(&s, 360, 830, xyz);
    xyz_to_linear_srgb(xyz, rgb);
    CHECK(t, fabs(rgb[0] - 2.0) < 1e-3 && fabs(rgb[1] - 1.0) < 1e-3 && fabs(rgb[2] - 0.5) < 1e-3,
          "illuminant (2, 1, 0.5) -> (%.5f, %.5f, %.5f)", rgb[0], rgb[1], rgb[2]);
    in[0] = in[1] = in[2] = 0.0f;
    CHECK(t, spec_from_rgb(&s, in, 1, &e, "t", 1) && spec_is_constant(&s) && s.v[0] == 0.0f, "black");
}

/* The load's path (rgbtable.c's table where trusted, else rgbfit.c's coefficient
   table polished by Newton) against the full fit, over a 9^3 grid of reflectances in
   [0.02, 0.98] and the illuminants (largest component 1/2) of a 9 x 9 grid: the
   spectra s(lambda) in [0, 1] over 360..830 nm at 1 nm and their rgb under D65.
   spectrum.c's table start alone must already be close (a wrong table would only be
   hidden by the polish; measured: max 0.040, mean 0.010).  The result is within
   1e-3 of the fit (measured: spectra within 3.5e-4, mean 9.0e-6; rgb round trips
   within 1.9e-4 of the fit's); spectrum_rgbtable checks
   the table over a denser set. */
static double sigmoid_rgb_err(const double c[3], const double target[3])
{
    Spectrum s;
    double rgb[3], d = 0.0;
    float cf[3];
    int i;
    for (i = 0; i < 3; i++) cf[i] = (float)c[i];
    for (i = 0; i < SPEC_N; i++) s.v[i] = spec_sigmoid_eval(cf, (float)(SPEC_MIN + i));
    reflectance_rgb(&s, rgb);
    for (i = 0; i < 3; i++) if (fabs(rgb[i] - target[i]) > d) d = fabs(rgb[i] - target[i]);
    return d;
}

static void rgb_table_target(int a, int b, int c, double target[3])
{
    if (c < 9) {                                  /* reflectance grid */
        target[0] = 0.02 + 0.12 * a; target[1] = 0.02 + 0.12 * b;
        target[2] = 0.02 + 0.12 * c;
    } else {                                      /* illuminant: max 1/2 */
        target[a % 3] = 0.5; target[(a + 1) % 3] = 0.06 * b;
        target[(a + 2) % 3] = 0.5 * (a / 3) / 2.0;
    }
}

static void test_rgb_table(T *t)
{
    static double first[9][9][10][6];             /* ct, cs of each colour, in grid order */
    double worst_s = 0.0, sum_s = 0.0, worst_rgb = 0.0, worst_start = 0.0, sum_start = 0.0;
    long n_s = 0, n_c = 0, n_differ = 0;
    int a, b, c, i, k;
    RgbTable *tab = rgb_table_new(), *rev = rgb_table_new();
    if (!tab || !rev) {
        rgb_table_free(tab);
        rgb_table_free(rev);
        CHECK(t, 0, "rgb_table_new: out of memory");
    }
    for (a = 0; a < 9; a++)
        for (b = 0; b < 9; b++)
            for (c = 0; c < 10; c++) {
                double target[3], ct[3], cf[3], cs[3], d;
                rgb_table_target(a, b, c, target);
                if (target[0] == target[1] && target[1] == target[2]) continue;
                spec_rgb_coeffs(tab, target, ct);
                spec_rgb_coeffs_fit(target, cf);
                spec_rgb_table_start(tab, target, cs);
                for (k = 0; k < 3; k++) { first[a][b][c][k] = ct[k]; first[a][b][c][3 + k] = cs[k]; }
                for (i = 0; i < SPEC_N; i++) {
                    float lam = (float)(SPEC_MIN + i), ft[3], ff[3];
                    for (k = 0; k < 3; k++) { ft[k] = (float)ct[k]; ff[k] = (float)cf[k]; }
                    d = fabs((double)spec_sigmoid_eval(ft, lam) - spec_sigmoid_eval(ff, lam));
                    if (d > worst_s) worst_s = d;
                    sum_s += d; n_s++;
                }
                d = fabs(sigmoid_rgb_err(ct, target) - sigmoid_rgb_err(cf, target));
                if (d > worst_rgb) worst_rgb = d;
                d = sigmoid_rgb_err(cs, target);
                if (d > worst_start) worst_start = d;
                sum_start += d; n_c++;
            }
    /* a second table asked in the reverse order fills its slices in another order:
       every colour gets the same coefficients and the same start, bit for bit */
    for (a = 8; a >= 0; a--)
        for (b = 8; b >= 0; b--)
            for (c = 9; c >= 0; c--) {
                double target[3], ct[3], cs[3];
                rgb_table_target(a, b, c, target);
                if (target[0] == target[1] && target[1] == target[2]) continue;
                spec_rgb_table_start(rev, target, cs);
                spec_rgb_coeffs(rev, target, ct);
                for (k = 0; k < 3; k++)
                    n_differ += (ct[k] != first[a][b][c][k]) + (cs[k] != first[a][b][c][3 + k]);
            }
    rgb_table_free(tab);
    rgb_table_free(rev);
    CHECK(t, n_differ == 0, "%ld coefficients depend on the order of the lookups", n_differ);
    printf("    rgb table vs fit over %ld colours: spectrum max %.2e mean %.2e, rgb error "
           "difference max %.2e; table start alone: rgb error max %.2e mean %.2e\n",
           n_c, worst_s, sum_s / (double)n_s, worst_rgb, worst_start, sum_start / (double)n_c);
    CHECK(t, worst_s < 1e-3, "table spectra differ from the fit by %.2e", worst_s);
    CHECK(t, worst_rgb < 1e-3, "table round trip differs from the fit's by %.2e", worst_rgb);
    CHECK(t, worst_start < 0.06 && sum_start / (double)n_c < 0.015,
          "the table's start is far from the colour: max %.2e, mean %.2e", worst_start,
          sum_start / (double)n_c);
}

/* rgbtable.c against the full fit (continuation from grey, no table) over a dense
   set: reflectances on a 17^3 grid of [0, 1]^3 and illuminants (largest component
   1/2, the two others on a 33 x 33 grid of [0, 1/2], each of the three largest).
   Where the table answers, its spectrum s(lambda), 360..830 nm at 1 nm, is within
   the tolerance 2e-3 of the fit's (measured here: max 1.02e-3, mean 2.4e-5;
   docs/loading.md: max 1.29e-3 over 140,400 colours); it answers for most colours
   (measured 82 % here), the rest go to the fit. */
static void test_rgbtable(T *t)
{
    enum { G = 16, GI = 32 };
    double worst = 0.0, sum = 0.0, at[3] = { 0, 0, 0 };
    long n = 0, n_tab = 0;
    int i, j, k, ill;
    for (ill = 0; ill < 2; ill++)
        for (i = 0; i <= (ill ? GI : G); i++)
            for (j = 0; j <= (ill ? GI : G); j++)
                for (k = 0; k <= (ill ? 2 : G); k++) {
                    double target[3], ct[3], cf[3], d = 0.0;
                    int l;
                    if (ill) {
                        target[k] = 0.5;
                        target[(k + 1) % 3] = 0.5 * i / GI;
                        target[(k + 2) % 3] = 0.5 * j / GI;
                    } else {
                        target[0] = (double)i / G; target[1] = (double)j / G;
                        target[2] = (double)k / G;
                    }
                    if (target[0] == target[1] && target[1] == target[2]) continue;
                    n++;
                    if (!rgbtable_coeffs(target, ct)) continue;
                    n_tab++;
                    spec_rgb_coeffs_fit(target, cf);
                    for (l = 0; l < SPEC_N; l++) {
                        float lam = (float)(SPEC_MIN + l), ft[3], ff[3];
                        int q;
                        for (q = 0; q < 3; q++) { ft[q] = (float)ct[q]; ff[q] = (float)cf[q]; }
                        d = fmax(d, fabs((double)spec_sigmoid_eval(ft, lam) - spec_sigmoid_eval(ff, lam)));
                    }
                    sum += d;
                    if (d > worst) { worst = d; at[0] = target[0]; at[1] = target[1]; at[2] = target[2]; }
                }
    printf("    rgbtable: %ld of %ld colours from the table; spectrum vs fit max %.2e at "
           "(%.3f, %.3f, %.3f), mean %.2e\n", n_tab, n, worst, at[0], at[1], at[2],
           sum / (double)(n_tab ? n_tab : 1));
    CHECK(t, worst <= 2e-3, "the table's spectrum differs from the fit's by %.2e at (%g, %g, %g)",
          worst, at[0], at[1], at[2]);
    CHECK(t, n_tab >= 0.75 * (double)n, "the table answers for %ld of %ld colours", n_tab, n);
}

/* The colours in the cells rgbtable.c does not trust: rgbfit.c polishes the
   table's interpolation there by Newton (rgbtable_lookup's start).  Against the
   continuation fit from grey (spec_rgb_coeffs_fit), over reflectances on a 20^3
   grid of [0, 1]^3 (the gamut's faces and edges included: a component 0 or 1)
   and illuminants (largest component 1/2, the others on a 25 x 25 grid of
   [0, 1/2]): the polished spectrum is within 1e-4 of the fit's at every
   wavelength (measured here: max 1.1e-5; docs/loading.md: 2.4e-5 over 73,920
   colours; the two stop at the same squared rgb error, 1e-14, on either side of
   a steep sigmoid's root), and the rgb round trip within 1e-5 of the fit's
   (measured 1.1e-6, float coefficients and spectrum).  The
   interpolation alone is off by up to 0.77 in these cells: only the polish gets
   there. */
static void test_rgbtable_polish(T *t)
{
    enum { G = 20, GI = 24 };
    double worst = 0.0, worst_start = 0.0, worst_rgb = 0.0, at[3] = { 0, 0, 0 };
    long n = 0, n_pol = 0;
    int i, j, k, ill;
    RgbTable *tab = rgb_table_new();
    CHECK(t, tab != NULL, "rgb_table_new: out of memory");
    for (ill = 0; ill < 2; ill++)
        for (i = 0; i <= (ill ? GI : G); i++)
            for (j = 0; j <= (ill ? GI : G); j++)
                for (k = 0; k <= (ill ? 2 : G); k++) {
                    double target[3], cs[3], ct[3], cf[3], d = 0.0, ds = 0.0;
                    int l;
                    if (ill) {
                        target[k] = 0.5;
                        target[(k + 1) % 3] = 0.5 * i / GI;
                        target[(k + 2) % 3] = 0.5 * j / GI;
                    } else {
                        target[0] = (double)i / G; target[1] = (double)j / G;
                        target[2] = (double)k / G;
                    }
                    if (target[0] == target[1] && target[1] == target[2]) continue;
                    n++;
                    if (rgbtable_lookup(target, cs) != 1) continue;
                    n_pol++;
                    spec_rgb_coeffs(tab, target, ct);
                    spec_rgb_coeffs_fit(target, cf);
                    for (l = 0; l < SPEC_N; l++) {
                        float lam = (float)(SPEC_MIN + l), ft[3], ff[3], fs[3];
                        int q;
                        for (q = 0; q < 3; q++) {
                            ft[q] = (float)ct[q]; ff[q] = (float)cf[q]; fs[q] = (float)cs[q];
                        }
                        d = fmax(d, fabs((double)spec_sigmoid_eval(ft, lam) - spec_sigmoid_eval(ff, lam)));
                        ds = fmax(ds, fabs((double)spec_sigmoid_eval(fs, lam) - spec_sigmoid_eval(ff, lam)));
                    }
                    worst_start = fmax(worst_start, ds);
                    if (d > worst) { worst = d; at[0] = target[0]; at[1] = target[1]; at[2] = target[2]; }
                    worst_rgb = fmax(worst_rgb, fabs(sigmoid_rgb_err(ct, target) - sigmoid_rgb_err(cf, target)));
                }
    rgb_table_free(tab);
    printf("    rgbtable polish: %ld of %ld colours in untrusted cells; spectrum vs fit max %.2e "
           "at (%.3f, %.3f, %.3f) (the start alone: %.2e), rgb error difference max %.2e\n",
           n_pol, n, worst, at[0], at[1], at[2], worst_start, worst_rgb);
    CHECK(t, n_pol >= 0.1 * (double)n, "only %ld of %ld colours in untrusted cells", n_pol, n);
    CHECK(t, worst <= 1e-4, "the polished spectrum differs from the fit's by %.2e at (%g, %g, %g)",
          worst, at[0], at[1], at[2]);
    CHECK(t, worst_rgb <= 1e-5, "the polished rgb round trip differs from the fit's by %.2e",
          worst_rgb);
}

/* spec_to_y_t (a load's rgb lights: ybar read from the RgbTable's knots) equals
   spec_to_y (ybar interpolated per knot) bit for bit, for named spectra and rgb
   illuminants, and lights.c's luminance_sum_t equals luminance_sum over several
   ranges (one reaching into the UV, where it falls back); with no table each is
   its plain twin. */
static void test_to_y_table(T *t)
{
    static const char *const names[] = { "stdillum-D65", "stdillum-F2", "stdillum-A", "metal-Au-k" };
    RgbTable *tab = rgb_table_new();
    long n = 0, n_differ = 0;
    int i;
    CHECK(t, tab != NULL, "rgb_table_new: out of memory");
    for (i = 0; i < 4 + 20; i++) {
        Spectrum s;
        if (i < 4) spec_named(&s, names[i]);
        else {
            float rgb[3];
            rgb[0] = 0.05f * (float)i; rgb[1] = 1.0f - 0.04f * (float)i; rgb[2] = 0.3f;
            CHECK(t, spec_from_rgb_t(tab, &s, rgb, 1, NULL, "t", 1), "spec_from_rgb_t failed");
        }
        n += 2;
        n_differ += spec_to_y_t(tab, &s) != spec_to_y(&s);
        n_differ += spec_to_y_t(NULL, &s) != spec_to_y(&s);
        {
            static const float range[4][2] = { { 400, 700 }, { 360, 830 }, { 380.5f, 779.5f }, { 300, 700 } };
            int r;
            for (r = 0; r < 4; r++) {
                n += 2;
                n_differ += luminance_sum_t(tab, &s, range[r][0], range[r][1]) !=
                            luminance_sum(&s, range[r][0], range[r][1]);
                n_differ += luminance_sum_t(NULL, &s, range[r][0], range[r][1]) !=
                            luminance_sum(&s, range[r][0], range[r][1]);
            }
        }
    }
    rgb_table_free(tab);
    CHECK(t, n_differ == 0, "%ld of %ld luminances differ from spec_to_y's", n_differ, n);
}

/* spec_eval_scaled (lights.c's Le without a table) against spec_eval of the table
   (float)(num * s / den): bit for bit at every wavelength tried, UV part, knots,
   between knots and out of range included. */
static void test_eval_scaled(T *t)
{
    static const char *const names[] = { "stdillum-D65", "stdillum-F2", "metal-Au-k" };
    const float nums[3] = { 1.0f, 3.7f, 0.013f };
    const double dens[3] = { 1.0, 106.85673, 0.3 };
    long n = 0, n_differ = 0;
    int i, k;
    for (i = 0; i < 3; i++) {
        Spectrum s, tab;
        float lam;
        int l;
        spec_named(&s, names[i]);
        for (l = 0; l < SPEC_UV_N; l++) s.uv[l] = 0.01f * (float)(l % 7) * s.v[0];
        for (k = 0; k < 3; k++) {
            for (l = 0; l < SPEC_N; l++) tab.v[l] = (float)(nums[k] * s.v[l] / dens[k]);
            for (l = 0; l < SPEC_UV_N; l++) tab.uv[l] = (float)(nums[k] * s.uv[l] / dens[k]);
            for (lam = 250.0f; lam <= 880.0f; lam += 0.37f) {
                n++;
                n_differ += spec_eval_scaled(&s, nums[k], dens[k], lam) != spec_eval(&tab, lam);
            }
            for (l = SPEC_UV_MIN; l <= SPEC_MAX; l++) {
                n++;
                n_differ += spec_eval_scaled(&s, nums[k], dens[k], (float)l) != spec_eval(&tab, (float)l);
            }
        }
    }
    CHECK(t, n_differ == 0, "%ld of %ld values differ from the tabulated spectrum's", n_differ, n);
}

/* ---------- wavelength sampling ---------- */

/* For a pdf w: draw n_draw sets of HERO_N wavelengths, and check with chi-square
   (CHECK_CHI2) that each lambda_j follows the pdf w claims (1 nm bins = the cells,
   expected counts from w->pdf), that pdf[j] = p(lambda_j),
   and that the set is stratified: the CDF positions are u + j/4 (mod 1). */
void check_wl_sampling(T *t, const WavelengthPdf *w, const char *what)
{
    enum { N_DRAW = 40000, BIN_NM = 1, MAX_BINS = 512 };
    int n_bins = (int)((w->hi - w->lo) / BIN_NM + 0.5), j, b, k, i;
    double expected[MAX_BINS], total = 0.0;
    double count[HERO_N][MAX_BINS];
    Rng rng;
    memset(count, 0, sizeof count);
    CHECK(t, n_bins > 1 && n_bins <= MAX_BINS, "%s: bad range", what);
    /* expected bin probabilities from the pdf (integrated in 1 nm steps, midpoint) */
    for (b = 0; b < n_bins; b++) {
        expected[b] = 0.0;
        for (k = 0; k < BIN_NM; k++) expected[b] += wl_pdf_eval(w, w->lo + b * BIN_NM + k + 0.5f);
        total += expected[b];
    }
    CHECK(t, fabs(total - 1.0) < 1e-4, "%s: pdf integrates to %.6f", what, total);
    rng_seed(&rng, 7, 0);
    for (i = 0; i < N_DRAW; i++) {
        Wavelengths wl;
        double P[HERO_N];
        int quarter_seen = 0, near_edge = 0;
        wl_sample(w, rng_float(&rng), &wl);
        for (j = 0; j < HERO_N; j++) {
            float l = wl.lambda[j];
            CHECK(t, l >= w->lo && l <= w->hi, "%s: lambda %g outside the range", what, (double)l);
            CHECK(t, wl.pdf[j] > 0.0f, "%s: pdf[%d] = %g at %g nm", what, j, (double)wl.pdf[j], (double)l);
            b = (int)((l - w->lo) / BIN_NM);
            if (b >= n_bins) b = n_bins - 1;
            count[j][b]++;
            P[j] = wl_cdf(w, l);                  /* CDF position of lambda_j */
        }
        /* the reported pdf is the sampler's own density: 1 / (d lambda / du), by
           one-sided differences (over about 0.25 nm) of wl_sample itself (not wl_pdf_eval, which
           wl_sample calls); one side may straddle a cell of the pdf, so either
           difference may match, within 2% (float wavelengths) */
        if (i < 4000) {
            float u = rng_float(&rng);
            Wavelengths a, b, c;
            wl_sample(w, u, &b);
            for (j = 0; j < HERO_N; j++) {
                float du = 0.25f * b.pdf[j];                /* a step of about 0.25 nm */
                double left, right, p = b.pdf[j];
                int ok_l, ok_r;
                if (du < 2e-5f) du = 2e-5f;
                if (!(u > 2 * du && u < 1 - 2 * du)) continue;
                wl_sample(w, u - du, &a);
                wl_sample(w, u + du, &c);
                left = b.lambda[j] - a.lambda[j];
                right = c.lambda[j] - b.lambda[j];
                if (left <= 0 || right <= 0) continue;             /* wrapped around 1 */
                ok_l = fabs(p * left / du - 1.0) < 0.02;
                ok_r = fabs(p * right / du - 1.0) < 0.02;
                CHECK(t, ok_l || ok_r, "%s: pdf[%d] = %g at %g nm, but the sampler's density is %g or %g",
                      what, j, p, (double)b.lambda[j], du / left, du / right);
            }
        }
        for (j = 1; j < HERO_N; j++) {
            double d = P[j] - P[0] - (double)j / HERO_N;
            d -= floor(d + 0.5);                  /* mod 1, into [-0.5, 0.5) */
            CHECK(t, fabs(d) < 2e-4, "%s: CDF positions not rotated by j/4 (%g)", what, d);
        }
        for (j = 0; j < HERO_N; j++) {
            double q = P[j] * HERO_N;
            if (fabs(q - floor(q + 0.5)) < 1e-4) near_edge = 1;
            quarter_seen |= 1 << ((int)q < HERO_N ? (int)q : HERO_N - 1);
        }
        CHECK(t, near_edge || quarter_seen == (1 << HERO_N) - 1, "%s: not one per quarter", what);
    }
    for (b = 0; b < n_bins; b++) expected[b] *= N_DRAW;
    for (j = 0; j < HERO_N; j++) {
        Chi2 c;
        CHECK_CHI2(t, count[j], expected, n_bins, HERO_N, &c, "%s: lambda_%d", what, j);
        CHECK(t, c.dof > 5, "%s: lambda_%d: only %d dof", what, j, c.dof);
    }
}

static void test_wl_uniform(T *t)
{
    WavelengthPdf w;
    Wavelengths wl;
    wl_pdf_uniform(&w, LAMBDA_LO, LAMBDA_HI);
    CHECK(t, fabs(wl_pdf_eval(&w, 550.0f) - 1.0 / 300.0) < 1e-9, "uniform pdf");
    CHECK(t, wl_pdf_eval(&w, 399.0f) == 0.0f && wl_pdf_eval(&w, 701.0f) == 0.0f, "pdf outside is 0");
    wl_sample(&w, 0.1f, &wl);
    CHECK(t, fabs(wl.lambda[0] - 430.0) < 1e-3 && fabs(wl.lambda[1] - 505.0) < 1e-3 &&
          fabs(wl.lambda[2] - 580.0) < 1e-3 && fabs(wl.lambda[3] - 655.0) < 1e-3,
          "uniform rotation: %g %g %g %g", (double)wl.lambda[0], (double)wl.lambda[1],
          (double)wl.lambda[2], (double)wl.lambda[3]);
    wl_sample(&w, 1.0f, &wl);                     /* u = 1 wraps to 0 */
    CHECK(t, wl.lambda[0] >= 400.0f && wl.lambda[0] < 400.001f, "u = 1 gives %g", (double)wl.lambda[0]);
    check_wl_sampling(t, &w, "uniform 400-700");
    wl_pdf_free(&w);
}

static void test_wl_importance(T *t)
{
    WavelengthPdf w;
    Spectrum f11, zero;
    double ratio_min = HUGE_VAL, ratio_max = 0.0;
    float l;
    spec_named(&f11, "stdillum-F11");
    CHECK(t, wl_pdf_importance(&w, LAMBDA_LO, LAMBDA_HI, &f11), "importance pdf failed");
    CHECK(t, w.n == 300 && w.cdf[0] == 0.0f && w.cdf[w.n] == 1.0f, "table layout");
    /* p is proportional to (xbar+ybar+zbar) * F11 where that is above the floor */
    for (l = 420.5f; l < 680.0f; l += 1.0f) {
        float c[3];
        double target, r;
        cie_xyz(l, c);
        target = (c[0] + c[1] + c[2]) * spec_eval(&f11, l);
        if (target < 0.05 * 30.0) continue;        /* skip the floor / near-floor cells */
        r = wl_pdf_eval(&w, l) / target;
        if (r < ratio_min) ratio_min = r;
        if (r > ratio_max) ratio_max = r;
    }
    CHECK(t, ratio_max / ratio_min < 1.02, "pdf / ((xbar+ybar+zbar) F11) varies %.4f..%.4g",
          ratio_min, ratio_max);
    for (l = 400.0f; l <= 700.0f; l += 0.5f)
        CHECK(t, wl_pdf_eval(&w, l) > 0.0f, "floor: p(%g) must be > 0", (double)l);
    check_wl_sampling(t, &w, "importance F11 400-700");
    wl_pdf_free(&w);
    CHECK(t, w.pdf == NULL && w.cdf == NULL && w.n == 0, "wl_pdf_free resets");
    /* a lamp with narrow lines on the wide range */
    spec_named(&f11, "lamp-CFL1");
    CHECK(t, wl_pdf_importance(&w, (float)SPEC_MIN, (float)SPEC_MAX, &f11), "wide pdf failed");
    check_wl_sampling(t, &w, "importance CFL1 360-830");
    wl_pdf_free(&w);
    /* an all-zero emission falls back to a uniform table */
    spec_const(&zero, 0.0f);
    CHECK(t, wl_pdf_importance(&w, LAMBDA_LO, LAMBDA_HI, &zero), "zero emission");
    CHECK(t, fabs(wl_pdf_eval(&w, 500.0f) - 1.0 / 300.0) < 1e-6, "zero emission must give uniform");
    wl_pdf_free(&w);
    CHECK(t, !wl_pdf_importance(&w, 700.0f, 400.0f, NULL), "empty range must fail");
}

/* ---------- svg ---------- */

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    long n;
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = (char *)malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) { free(buf); buf = NULL; }
    if (buf) buf[n] = '\0';
    fclose(f);
    return buf;
}

static int count_of(const char *hay, const char *needle)
{
    int n = 0;
    for (; (hay = strstr(hay, needle)) != NULL; hay++) n++;
    return n;
}

static void test_svg(T *t)
{
    static const double x[6] = { 16, 32, 64, 128, 256, 512 };
    static const double y1[6] = { 1e-1, 5e-2, 2.4e-2, 1.3e-2, 6e-3, 3.1e-3 };
    static const double lo1[6] = { 8e-2, 4e-2, 2e-2, 1e-2, 5e-3, 2.5e-3 };
    static const double hi1[6] = { 1.2e-1, 6e-2, 3e-2, 1.5e-2, 7e-3, 3.6e-3 };
    double y2[6] = { 9e-2, 4e-2, NAN, 1e-2, -1.0, 2e-3 };   /* NaN and <= 0 break the line */
    SvgSeries s[3];
    SvgChart c;
    const char *path = test_path(t, "chart.svg");
    FILE *f;
    char *text;
    size_t len;
    int n_paths, n_moves;
    memset(s, 0, sizeof s);
    memset(&c, 0, sizeof c);
    s[0].name = "uniform & <power>"; s[0].n = 6; s[0].x = x; s[0].y = y1; s[0].ylo = lo1; s[0].yhi = hi1;
    s[1].name = "spd"; s[1].color = "#123456"; s[1].n = 6; s[1].x = x; s[1].y = y2; s[1].dashed = 1;
    s[2].name = "empty"; s[2].n = 0;
    c.title = "MSE vs spp"; c.xlabel = "spp"; c.ylabel = "MSE"; c.logx = c.logy = 1;
    f = fopen(path, "wb");
    CHECK(t, f != NULL, "cannot write %s", path);
    CHECK(t, svg_line_chart(f, &c, s, 3) == 1, "svg_line_chart failed");
    fclose(f);
    text = slurp(path);
    CHECK(t, text != NULL, "cannot read %s back", path);
    len = strlen(text);
    if (!(strncmp(text, "<svg", 4) == 0 && len > 8 && strcmp(text + len - 7, "</svg>\n") == 0)) {
        free(text);
        CHECK(t, 0, "SVG must start with <svg and end with </svg>");
    }
    if (!(strstr(text, "uniform &amp; &lt;power&gt;") && strstr(text, ">spd<") && strstr(text, ">empty<") &&
          strstr(text, "#123456") && strstr(text, "stroke-dasharray") && strstr(text, "fill-opacity") &&
          strstr(text, "MSE vs spp") && !strstr(text, "nan") && !strstr(text, "inf"))) {
        free(text);
        CHECK(t, 0, "SVG lacks a series, its escaping, style or has nan/inf");
    }
    /* log axes: x 16..512 rounds out to 10..1000 (ticks 10, 10^2, 10^3), y to 10^-3..1 */
    /* one band, one path per drawn series; the NaN and the negative value split the
       dashed series into 3 runs, i.e. 3 "M" commands in its path */
    n_paths = count_of(text, "<path");
    {
        const char *end = strstr(text, "stroke=\"#123456\" stroke-width"), *q = end;
        while (q && q > text && strncmp(q, "<path", 5) != 0) q--;
        for (n_moves = 0; q && q < end; q++) n_moves += *q == 'M';
    }
    if (!(strstr(text, ">10<") && strstr(text, ">10<tspan dy=\"-6\" font-size=\"9\">2</tspan>") &&
          strstr(text, ">-3</tspan>") && n_paths == 3 && n_moves == 3)) {
        free(text);
        CHECK(t, 0, "log ticks or paths wrong (paths: %d, want 3; runs: %d, want 3)", n_paths, n_moves);
    }
    free(text);
    CHECK(t, svg_line_chart(NULL, &c, s, 3) == 0 && svg_line_chart(stdout, NULL, s, 1) == 0,
          "NULL arguments must be rejected");
    f = fopen(path, "wb");
    CHECK(t, f != NULL, "cannot write %s", path);
    memset(&c, 0, sizeof c);                      /* no series at all, linear axes */
    CHECK(t, svg_line_chart(f, &c, NULL, 0) == 1, "an empty chart must still be written");
    fclose(f);
    text = slurp(path);
    CHECK(t, text && strncmp(text, "<svg", 4) == 0 && strstr(text, "</svg>"), "empty chart malformed");
    free(text);
}

static void test_cmd_errors(T *t)
{
    char a0[] = "spectrum", a1[] = "--bogus", a2[] = "no-such-spectrum-or-file", a3[] = "x", a4[] = "y";
    char *argv_bad[2], *argv_unknown[2], *argv_two[3];
    argv_bad[0] = a0; argv_bad[1] = a1;
    argv_unknown[0] = a0; argv_unknown[1] = a2;
    argv_two[0] = a0; argv_two[1] = a3; argv_two[2] = a4;
    fprintf(stderr, "(test_cmd_errors: the usage/error lines below are expected)\n");
    CHECK(t, cmd_spectrum(2, argv_bad) == 2, "unknown option must exit 2");
    CHECK(t, cmd_spectrum(3, argv_two) == 2, "two names without --svg must exit 2");
    CHECK(t, cmd_spectrum(2, argv_unknown) == 1, "unknown spectrum must exit 1");
}

/* spec_store_add: 2,000 spectra equal below 800 nm and distinct above (so the
   hashes collide in the probe sequences and the records must be told apart by
   their bytes), each added twice: 2,000 records, the second add returns the
   first's, every record equals what was given. */
static void test_spectrum_store(T *t)
{
    SpectrumStore st;
    Spectrum a;
    const Spectrum *first[2000];
    int i, pass, ok = 1;
    memset(&st, 0, sizeof st);
    spec_const(&a, 1.0f);
    for (pass = 0; pass < 2 && ok; pass++)
        for (i = 0; i < 2000 && ok; i++) {
            const Spectrum *r;
            a.v[SPEC_N - 1] = 2.0f + (float)i;
            r = spec_store_add(&st, &a);
            ok = r != NULL && memcmp(r, &a, sizeof a) == 0 && (pass == 0 || r == first[i]);
            if (pass == 0) first[i] = r;
        }
    CHECK(t, ok, "spectrum %d (pass %d): not its own record", i - 1, pass);
    CHECK(t, st.n == 2000, "%d records for 2000 distinct spectra", st.n);
    spec_store_free(&st);
}

const TestCase tests_spectrum[] = {
    { "spectrum_store", test_spectrum_store },
    { "spectrum_cie_values", test_cie_values },
    { "spectrum_d65", test_d65 },
    { "spectrum_blackbody_cct", test_blackbody_and_cct },
    { "spectrum_fluorescent_illuminants", test_fluorescent_illuminants },
    { "spectrum_named", test_named },
    { "spectrum_lamps", test_lamps },
    { "spectrum_cauchy_glass", test_cauchy_and_glass },
    { "spectrum_pairs", test_pairs },
    { "spectrum_file_formats", test_file_formats },
    { "spectrum_file_errors", test_file_errors },
    { "spectrum_bins", test_bins },
    { "spectrum_rgb_reflectance", test_rgb_reflectance },
    { "spectrum_rgb_albedo_in_unit", test_rgb_albedo_in_unit },
    { "spectrum_albedo_compact", test_albedo_compact },
    { "spectrum_rgb_illuminant", test_rgb_illuminant },
    { "spectrum_rgb_table", test_rgb_table },
    { "spectrum_rgbtable", test_rgbtable },
    { "spectrum_rgbtable_polish", test_rgbtable_polish },
    { "spectrum_to_y_table", test_to_y_table },
    { "spectrum_eval_scaled", test_eval_scaled },
    { "spectrum_wl_uniform", test_wl_uniform },
    { "spectrum_wl_importance", test_wl_importance },
    { "spectrum_svg", test_svg },
    { "spectrum_cmd_errors", test_cmd_errors },
    { NULL, NULL }
};
