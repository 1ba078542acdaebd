/* spectrum.c - spectra, CIE colorimetry, named illuminants/lamps/glasses.

   WHAT IT IMPLEMENTS
     Every spectrum in specnee is a dense table at 1 nm over SPEC_MIN..SPEC_MAX
     (360..830 nm, pbrt-v4's range), evaluated by linear interpolation and zero
     outside.  Every source of a spectrum is resampled into that table once, at load
     time: inline (lambda, value) pairs, named spectra, .spd/.csv files, rgb values
     and blackbodies.

     1. CIE 1931 2-degree colour-matching functions xbar, ybar, zbar, tabulated every
        5 nm (360..830) and linearly interpolated in between:
            X = sum_{lambda, 1 nm} xbar(lambda) S(lambda) / sum_{lambda, 1 nm} ybar(lambda)
        (same for Y, Z), so that an equal-energy spectrum S = 1 gives Y = 1.
     2. XYZ -> linear sRGB with pbrt-v4's matrix (D65 white, xy = 0.312727, 0.329023).
     3. Correlated colour temperature (CCT) and Duv: the temperature T whose Planckian
        radiator has the CIE 1960 (u, v) chromaticity closest to the spectrum's,
            u = 4x / (-2x + 12y + 3),  v = 6y / (-2x + 12y + 3),
        Planck's law B(lambda, T) ~ lambda^-5 / (exp(c2 / (lambda T)) - 1),
        c2 = 1.438777e-2 m K; Duv = signed distance, > 0 above the locus.
     4. thesis eq. 6: sum_{w in W} Emm(w, e) = c, W = the 60 bins of 5 nm over
        400..700 nm.  A bin's value is the exact mean of the piecewise-linear table over
        the bin (never a point sample, so a 1 nm line is never lost).
     5. Cauchy's law n(lambda) = A + B / lambda^2 (lambda in um) and the Sellmeier
        formula n^2 = 1 + sum_i B_i lambda^2 / (lambda^2 - C_i) (SCHOTT catalogue).
     6. RGB -> spectrum (Jakob & Hanika 2019) is rgbfit.c: it fits and tabulates the
        sigmoid polynomials and fills this file's dense tables from them.

     The wavelength sampling that draws the four wavelengths of a path is in
     wavelengths.c; `specnee spectrum` is in cmd_spectrum.c.

   EXPORTS (specnee.h section 4)
     spec_eval spec_const spec_is_constant spec_from_pairs spec_named spec_named_list
     spec_from_file spec_blackbody blackbody_eval cie_xyz cie_cmf cie_ybar cie_y_integral
     spec_to_xyz spec_to_y xyz_to_linear_srgb spec_chromaticity cct_from_xy spec_bin_average
     spec_bin_sum cauchy_named spec_band_mean spec_band_average spec_store_add
     spec_store_free

   HOW IT IS USED
     parser.c turns "spectrum"/"blackbody" parameters into Spectrum tables with
     spec_from_pairs, spec_named, spec_from_file and spec_blackbody (and "rgb" ones
     through rgbfit.c);
     lights.c uses spec_bin_average for the emitter tables; path.c and render.c
     convert to colour with cie_xyz and xyz_to_linear_srgb; wavelengths.c weights its
     importance pdf with cie_cmf.  `specnee spectrum NAME|FILE` (cmd_spectrum.c)
     prints a spectrum, its colorimetry and the pbrt "scale" that realises thesis
     eq. 6 normalisation; `--svg` plots spectra (svg.c). */
#include "specnee.h"
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* ======================================================================
   1. Data tables
   ====================================================================== */

/* CIE 1931 2-degree colour-matching functions, 360..830 nm every 5 nm (95 rows).
   Source: CIE 015:2018 / ISO/CIE 11664-1 tables (via Debian colord-data,
   usr/share/colord/cmf/CIE1931-2deg-XYZ.cmf).  These 95 values equal the CIE 1 nm
   table at the same wavelengths; specnee interpolates linearly in between (the
   1 nm sum of the interpolated ybar is 106.8570, the 1 nm CIE table gives 106.8569). */
#define CIE_START 360
#define CIE_STEP 5
#define CIE_N5 95
/* CIE F1..F12 fluorescent illuminants cover 380..780 nm every 5 nm (81 rows). */
#define F_START 380
#define F_N5 81

static const float cie_xbar_5nm[CIE_N5] = {
    0.0001299f, 0.0002321f, 0.0004149f, 0.0007416f, 0.001368f, 0.002236f, 0.004243f, 0.00765f,
    0.01431f, 0.02319f, 0.04351f, 0.07763f, 0.13438f, 0.21477f, 0.2839f, 0.3285f,
    0.34828f, 0.34806f, 0.3362f, 0.3187f, 0.2908f, 0.2511f, 0.19536f, 0.1421f,
    0.09564f, 0.05795001f, 0.03201f, 0.0147f, 0.0049f, 0.0024f, 0.0093f, 0.0291f,
    0.06327f, 0.1096f, 0.1655f, 0.2257499f, 0.2904f, 0.3597f, 0.4334499f, 0.5120501f,
    0.5945f, 0.6784f, 0.7621f, 0.8425f, 0.9163f, 0.9786f, 1.0263f, 1.0567f,
    1.0622f, 1.0456f, 1.0026f, 0.9384f, 0.8544499f, 0.7514f, 0.6424f, 0.5419f,
    0.4479f, 0.3608f, 0.2835f, 0.2187f, 0.1649f, 0.1212f, 0.0874f, 0.0636f,
    0.04677f, 0.0329f, 0.0227f, 0.01584f, 0.01135916f, 0.008110916f, 0.005790346f, 0.004109457f,
    0.002899327f, 0.00204919f, 0.001439971f, 0.0009999493f, 0.0006900786f, 0.0004760213f, 0.0003323011f, 0.0002348261f,
    0.0001661505f, 0.000117413f, 0.00008307527f, 0.00005870652f, 0.00004150994f, 0.00002935326f, 0.00002067383f, 0.00001455977f,
    0.00001025398f, 0.000007221456f, 0.000005085868f, 0.000003581652f, 0.000002522525f, 0.000001776509f, 0.000001251141f,
};

static const float cie_ybar_5nm[CIE_N5] = {
    0.000003917f, 0.000006965f, 0.00001239f, 0.00002202f, 0.000039f, 0.000064f, 0.00012f, 0.000217f,
    0.000396f, 0.00064f, 0.00121f, 0.00218f, 0.004f, 0.0073f, 0.0116f, 0.01684f,
    0.023f, 0.0298f, 0.038f, 0.048f, 0.06f, 0.0739f, 0.09098f, 0.1126f,
    0.13902f, 0.1693f, 0.20802f, 0.2586f, 0.323f, 0.4073f, 0.503f, 0.6082f,
    0.71f, 0.7932f, 0.862f, 0.9148501f, 0.954f, 0.9803f, 0.9949501f, 1.0f,
    0.995f, 0.9786f, 0.952f, 0.9154f, 0.87f, 0.8163f, 0.757f, 0.6949f,
    0.631f, 0.5668f, 0.503f, 0.4412f, 0.381f, 0.321f, 0.265f, 0.217f,
    0.175f, 0.1382f, 0.107f, 0.0816f, 0.061f, 0.04458f, 0.032f, 0.0232f,
    0.017f, 0.01192f, 0.00821f, 0.005723f, 0.004102f, 0.002929f, 0.002091f, 0.001484f,
    0.001047f, 0.00074f, 0.00052f, 0.0003611f, 0.0002492f, 0.0001719f, 0.00012f, 0.0000848f,
    0.00006f, 0.0000424f, 0.00003f, 0.0000212f, 0.00001499f, 0.0000106f, 0.0000074657f, 0.0000052578f,
    0.0000037029f, 0.0000026078f, 0.0000018366f, 0.0000012934f, 0.00000091093f, 0.00000064153f, 0.00000045181f,
};

static const float cie_zbar_5nm[CIE_N5] = {
    0.0006061f, 0.001086f, 0.001946f, 0.003486f, 0.006450001f, 0.01054999f, 0.02005001f, 0.03621f,
    0.06785001f, 0.1102f, 0.2074f, 0.3713f, 0.6456f, 1.0390501f, 1.3856f, 1.62296f,
    1.74706f, 1.7826f, 1.77211f, 1.7441f, 1.6692f, 1.5281f, 1.28764f, 1.0419f,
    0.8129501f, 0.6162f, 0.46518f, 0.3533f, 0.272f, 0.2123f, 0.1582f, 0.1117f,
    0.07824999f, 0.05725001f, 0.04216f, 0.02984f, 0.0203f, 0.0134f, 0.008749999f, 0.005749999f,
    0.0039f, 0.002749999f, 0.0021f, 0.0018f, 0.001650001f, 0.0014f, 0.0011f, 0.001f,
    0.0008f, 0.0006f, 0.00034f, 0.00024f, 0.00019f, 0.0001f, 0.00004999999f, 0.00003f,
    0.00002f, 0.00001f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
    0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
    0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
    0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
    0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
};

static const float d65_5nm[CIE_N5] = {
    0.466383f, 0.493637f, 0.520891f, 0.510323f, 0.499755f, 0.523118f, 0.546482f, 0.687015f,
    0.827549f, 0.871204f, 0.91486f, 0.924589f, 0.934318f, 0.90057f, 0.866823f, 0.957736f,
    1.04865f, 1.10936f, 1.17008f, 1.1741f, 1.17812f, 1.16336f, 1.14861f, 1.15392f,
    1.15923f, 1.12367f, 1.08811f, 1.09082f, 1.09354f, 1.08578f, 1.07802f, 1.06296f,
    1.0479f, 1.06239f, 1.07689f, 1.06047f, 1.04405f, 1.04225f, 1.04046f, 1.02023f,
    1.0f, 0.981671f, 0.963342f, 0.960611f, 0.95788f, 0.922368f, 0.886856f, 0.893459f,
    0.900062f, 0.898026f, 0.895991f, 0.886489f, 0.876987f, 0.854936f, 0.832886f, 0.834939f,
    0.836992f, 0.81863f, 0.800268f, 0.801207f, 0.802146f, 0.812462f, 0.822778f, 0.80281f,
    0.782842f, 0.740027f, 0.697213f, 0.706652f, 0.716091f, 0.72979f, 0.74349f, 0.679765f,
    0.61604f, 0.657448f, 0.698856f, 0.724863f, 0.75087f, 0.693398f, 0.635927f, 0.550054f,
    0.464182f, 0.566118f, 0.668054f, 0.650941f, 0.633828f, 0.638434f, 0.64304f, 0.618779f,
    0.594519f, 0.557054f, 0.51959f, 0.546998f, 0.574406f, 0.588765f, 0.603125f,
};

static const float cie_f_5nm[12][F_N5] = {
  { /* F1 */
    0.0187f, 0.0236f, 0.0294f, 0.0347f, 0.0517f, 0.1949f, 0.0613f, 0.0624f,
    0.0701f, 0.0779f, 0.0856f, 0.4367f, 0.1694f, 0.1072f, 0.1135f, 0.1189f,
    0.1237f, 0.1275f, 0.13f, 0.1315f, 0.1323f, 0.1317f, 0.1313f, 0.1285f,
    0.1252f, 0.122f, 0.1183f, 0.115f, 0.1122f, 0.1105f, 0.1103f, 0.1118f,
    0.1153f, 0.2774f, 0.1705f, 0.1355f, 0.1433f, 0.1501f, 0.1552f, 0.1829f,
    0.1955f, 0.1548f, 0.1491f, 0.1415f, 0.1322f, 0.1219f, 0.1112f, 0.1003f,
    0.0895f, 0.0796f, 0.0702f, 0.062f, 0.0542f, 0.0473f, 0.0415f, 0.0364f,
    0.032f, 0.0281f, 0.0247f, 0.0218f, 0.0193f, 0.0172f, 0.0167f, 0.0143f,
    0.0129f, 0.0119f, 0.0108f, 0.0096f, 0.0088f, 0.0081f, 0.0077f, 0.0075f,
    0.0073f, 0.0068f, 0.0069f, 0.0064f, 0.0068f, 0.0069f, 0.0061f, 0.0052f,
    0.0043f,
  },
  { /* F2 */
    0.0118f, 0.0148f, 0.0184f, 0.0215f, 0.0344f, 0.1569f, 0.0385f, 0.0374f,
    0.0419f, 0.0462f, 0.0506f, 0.3498f, 0.1181f, 0.0627f, 0.0663f, 0.0693f,
    0.0719f, 0.074f, 0.0754f, 0.0762f, 0.0765f, 0.0762f, 0.0762f, 0.0745f,
    0.0728f, 0.0715f, 0.0705f, 0.0704f, 0.0716f, 0.0747f, 0.0804f, 0.0888f,
    0.1001f, 0.2488f, 0.1664f, 0.1459f, 0.1616f, 0.1756f, 0.1862f, 0.2147f,
    0.2279f, 0.1929f, 0.1866f, 0.1773f, 0.1654f, 0.1521f, 0.138f, 0.1236f,
    0.1095f, 0.0965f, 0.084f, 0.0732f, 0.0631f, 0.0543f, 0.0468f, 0.0402f,
    0.0345f, 0.0296f, 0.0255f, 0.0219f, 0.0189f, 0.0164f, 0.0153f, 0.0127f,
    0.011f, 0.0099f, 0.0088f, 0.0076f, 0.0068f, 0.0061f, 0.0056f, 0.0054f,
    0.0051f, 0.0047f, 0.0047f, 0.0043f, 0.0046f, 0.0047f, 0.004f, 0.0033f,
    0.0027f,
  },
  { /* F3 */
    0.0082f, 0.0102f, 0.0126f, 0.0144f, 0.0257f, 0.1436f, 0.027f, 0.0245f,
    0.0273f, 0.03f, 0.0328f, 0.3185f, 0.0947f, 0.0402f, 0.0425f, 0.0444f,
    0.0459f, 0.0472f, 0.048f, 0.0486f, 0.0487f, 0.0485f, 0.0488f, 0.0477f,
    0.0467f, 0.0462f, 0.0462f, 0.0473f, 0.0499f, 0.0548f, 0.0625f, 0.0734f,
    0.0878f, 0.2382f, 0.1614f, 0.1459f, 0.1663f, 0.1849f, 0.1995f, 0.2311f,
    0.2469f, 0.2141f, 0.2085f, 0.1993f, 0.1867f, 0.1722f, 0.1565f, 0.1404f,
    0.1245f, 0.1095f, 0.0951f, 0.0827f, 0.0711f, 0.0609f, 0.0522f, 0.0445f,
    0.038f, 0.0323f, 0.0275f, 0.0233f, 0.0199f, 0.017f, 0.0155f, 0.0127f,
    0.0109f, 0.0096f, 0.0083f, 0.0071f, 0.0062f, 0.0054f, 0.0049f, 0.0046f,
    0.0043f, 0.0039f, 0.0039f, 0.0035f, 0.0038f, 0.0039f, 0.0033f, 0.0028f,
    0.0021f,
  },
  { /* F4 */
    0.0057f, 0.007f, 0.0087f, 0.0098f, 0.0201f, 0.1375f, 0.0195f, 0.0159f,
    0.0176f, 0.0193f, 0.021f, 0.3028f, 0.0803f, 0.0255f, 0.027f, 0.0282f,
    0.0291f, 0.0299f, 0.0304f, 0.0308f, 0.0309f, 0.0309f, 0.0314f, 0.0306f,
    0.03f, 0.0298f, 0.0301f, 0.0314f, 0.0341f, 0.039f, 0.0469f, 0.0581f,
    0.0732f, 0.2259f, 0.1511f, 0.1388f, 0.1633f, 0.1868f, 0.2064f, 0.2428f,
    0.2626f, 0.2328f, 0.2294f, 0.2214f, 0.2091f, 0.1943f, 0.1774f, 0.16f,
    0.1442f, 0.1256f, 0.1093f, 0.0952f, 0.0818f, 0.0701f, 0.06f, 0.0511f,
    0.0436f, 0.0369f, 0.0313f, 0.0264f, 0.0224f, 0.0191f, 0.017f, 0.0139f,
    0.0118f, 0.0103f, 0.0088f, 0.0074f, 0.0064f, 0.0054f, 0.0049f, 0.0046f,
    0.0042f, 0.0037f, 0.0037f, 0.0033f, 0.0035f, 0.0036f, 0.0031f, 0.0026f,
    0.0019f,
  },
  { /* F5 */
    0.0187f, 0.0235f, 0.0292f, 0.0345f, 0.051f, 0.1891f, 0.06f, 0.0611f,
    0.0685f, 0.0758f, 0.0831f, 0.4076f, 0.1606f, 0.1032f, 0.1091f, 0.114f,
    0.1183f, 0.1217f, 0.124f, 0.1254f, 0.1258f, 0.1252f, 0.1247f, 0.122f,
    0.1189f, 0.1161f, 0.1133f, 0.111f, 0.1096f, 0.1097f, 0.1116f, 0.1154f,
    0.1212f, 0.2778f, 0.1773f, 0.1447f, 0.152f, 0.1577f, 0.161f, 0.1854f,
    0.195f, 0.1539f, 0.1464f, 0.1372f, 0.1269f, 0.1157f, 0.1045f, 0.0935f,
    0.0829f, 0.0732f, 0.0641f, 0.0563f, 0.049f, 0.0426f, 0.0372f, 0.0325f,
    0.0283f, 0.0249f, 0.0219f, 0.0193f, 0.0171f, 0.0152f, 0.0143f, 0.0126f,
    0.0113f, 0.0105f, 0.0096f, 0.0085f, 0.0078f, 0.0072f, 0.0068f, 0.0067f,
    0.0065f, 0.0061f, 0.0062f, 0.0059f, 0.0062f, 0.0064f, 0.0055f, 0.0047f,
    0.004f,
  },
  { /* F6 */
    0.0105f, 0.0131f, 0.0163f, 0.019f, 0.0311f, 0.148f, 0.0343f, 0.033f,
    0.0368f, 0.0407f, 0.0445f, 0.3261f, 0.1074f, 0.0548f, 0.0578f, 0.0603f,
    0.0625f, 0.0641f, 0.0652f, 0.0658f, 0.0659f, 0.0656f, 0.0656f, 0.0642f,
    0.0628f, 0.062f, 0.0619f, 0.063f, 0.066f, 0.0712f, 0.0794f, 0.0907f,
    0.1049f, 0.2522f, 0.1746f, 0.1563f, 0.1722f, 0.1853f, 0.1943f, 0.2197f,
    0.2301f, 0.1941f, 0.1856f, 0.1742f, 0.1609f, 0.1464f, 0.1315f, 0.1168f,
    0.1025f, 0.0896f, 0.0774f, 0.0669f, 0.0571f, 0.0487f, 0.0416f, 0.0355f,
    0.0302f, 0.0257f, 0.022f, 0.0187f, 0.016f, 0.0137f, 0.0129f, 0.0105f,
    0.0091f, 0.0081f, 0.0071f, 0.0061f, 0.0054f, 0.0048f, 0.0044f, 0.0043f,
    0.004f, 0.0037f, 0.0038f, 0.0035f, 0.0039f, 0.0041f, 0.0033f, 0.0026f,
    0.0021f,
  },
  { /* F7 */
    0.0256f, 0.0318f, 0.0384f, 0.0453f, 0.0615f, 0.1937f, 0.0737f, 0.0705f,
    0.0771f, 0.0841f, 0.0915f, 0.4414f, 0.1752f, 0.1135f, 0.12f, 0.1258f,
    0.1308f, 0.1345f, 0.1371f, 0.1388f, 0.1395f, 0.1393f, 0.1382f, 0.1364f,
    0.1343f, 0.1325f, 0.1308f, 0.1293f, 0.1278f, 0.126f, 0.1244f, 0.1233f,
    0.1226f, 0.2952f, 0.1705f, 0.1244f, 0.1258f, 0.1272f, 0.1283f, 0.1546f,
    0.1675f, 0.1283f, 0.1267f, 0.1245f, 0.1219f, 0.1189f, 0.116f, 0.1135f,
    0.1112f, 0.1095f, 0.1076f, 0.1042f, 0.1011f, 0.1004f, 0.1002f, 0.1011f,
    0.0987f, 0.0865f, 0.0727f, 0.0644f, 0.0583f, 0.0541f, 0.0504f, 0.0457f,
    0.0412f, 0.0377f, 0.0346f, 0.0308f, 0.0273f, 0.0247f, 0.0225f, 0.0206f,
    0.019f, 0.0175f, 0.0162f, 0.0154f, 0.0145f, 0.0132f, 0.0117f, 0.0099f,
    0.0081f,
  },
  { /* F8 */
    0.0121f, 0.015f, 0.0181f, 0.0213f, 0.0317f, 0.1308f, 0.0383f, 0.0345f,
    0.0386f, 0.0442f, 0.0509f, 0.341f, 0.1242f, 0.0768f, 0.086f, 0.0946f,
    0.1024f, 0.1084f, 0.1133f, 0.1171f, 0.1198f, 0.1217f, 0.1228f, 0.1232f,
    0.1235f, 0.1244f, 0.1255f, 0.1268f, 0.1277f, 0.1272f, 0.126f, 0.1243f,
    0.1222f, 0.2896f, 0.1651f, 0.1179f, 0.1176f, 0.1177f, 0.1184f, 0.1461f,
    0.1611f, 0.1234f, 0.1253f, 0.1272f, 0.1292f, 0.1312f, 0.1334f, 0.1361f,
    0.1387f, 0.1407f, 0.142f, 0.1416f, 0.1413f, 0.1434f, 0.145f, 0.1446f,
    0.14f, 0.1258f, 0.1099f, 0.0998f, 0.0922f, 0.0862f, 0.0807f, 0.0739f,
    0.0671f, 0.0616f, 0.0563f, 0.0503f, 0.0446f, 0.0402f, 0.0366f, 0.0336f,
    0.0309f, 0.0285f, 0.0265f, 0.0251f, 0.0237f, 0.0215f, 0.0189f, 0.0161f,
    0.0132f,
  },
  { /* F9 */
    0.009f, 0.0112f, 0.0136f, 0.016f, 0.0259f, 0.128f, 0.0305f, 0.0256f,
    0.0286f, 0.033f, 0.0382f, 0.3262f, 0.1077f, 0.0584f, 0.0657f, 0.0725f,
    0.0786f, 0.0835f, 0.0875f, 0.0906f, 0.0931f, 0.0948f, 0.0961f, 0.0968f,
    0.0974f, 0.0988f, 0.1004f, 0.1026f, 0.1048f, 0.1063f, 0.1076f, 0.1096f,
    0.1118f, 0.2771f, 0.1629f, 0.1228f, 0.1274f, 0.1321f, 0.1365f, 0.1657f,
    0.1814f, 0.1455f, 0.1465f, 0.1466f, 0.1461f, 0.145f, 0.1439f, 0.144f,
    0.1447f, 0.1462f, 0.1472f, 0.1455f, 0.144f, 0.1458f, 0.1488f, 0.1551f,
    0.1547f, 0.132f, 0.1057f, 0.0918f, 0.0825f, 0.0757f, 0.0703f, 0.0635f,
    0.0572f, 0.0525f, 0.048f, 0.0429f, 0.038f, 0.0343f, 0.0312f, 0.0286f,
    0.0264f, 0.0243f, 0.0226f, 0.0214f, 0.0202f, 0.0183f, 0.0161f, 0.0138f,
    0.0112f,
  },
  { /* F10 */
    0.0111f, 0.0063f, 0.0062f, 0.0057f, 0.0148f, 0.1216f, 0.0212f, 0.027f,
    0.0374f, 0.0514f, 0.0675f, 0.3439f, 0.1486f, 0.104f, 0.1076f, 0.1067f,
    0.1011f, 0.0927f, 0.0829f, 0.0729f, 0.0791f, 0.1664f, 0.1673f, 0.1044f,
    0.0594f, 0.0334f, 0.0235f, 0.0188f, 0.0159f, 0.0147f, 0.018f, 0.0571f,
    0.4098f, 0.7369f, 0.3361f, 0.0824f, 0.0338f, 0.0247f, 0.0214f, 0.0486f,
    0.1145f, 0.1479f, 0.1216f, 0.0897f, 0.0652f, 0.0881f, 0.4412f, 0.3455f,
    0.1209f, 0.1215f, 0.1052f, 0.0443f, 0.0195f, 0.0219f, 0.0319f, 0.0277f,
    0.0229f, 0.02f, 0.0152f, 0.0135f, 0.0147f, 0.0179f, 0.0174f, 0.0102f,
    0.0114f, 0.0332f, 0.0449f, 0.0205f, 0.0049f, 0.0024f, 0.0021f, 0.0021f,
    0.0024f, 0.0024f, 0.0021f, 0.0017f, 0.0021f, 0.0022f, 0.0017f, 0.0012f,
    0.0009f,
  },
  { /* F11 */
    0.0091f, 0.0063f, 0.0046f, 0.0037f, 0.0129f, 0.1268f, 0.0159f, 0.0179f,
    0.0246f, 0.0333f, 0.0449f, 0.3394f, 0.1213f, 0.0695f, 0.0719f, 0.0712f,
    0.0672f, 0.0613f, 0.0546f, 0.0479f, 0.0566f, 0.1429f, 0.1496f, 0.0897f,
    0.0472f, 0.0233f, 0.0147f, 0.011f, 0.0089f, 0.0083f, 0.0118f, 0.049f,
    0.3959f, 0.7284f, 0.3261f, 0.0752f, 0.0283f, 0.0196f, 0.0167f, 0.0443f,
    0.1128f, 0.1476f, 0.1273f, 0.0974f, 0.0733f, 0.0972f, 0.5527f, 0.4258f,
    0.1318f, 0.1316f, 0.1226f, 0.0511f, 0.0207f, 0.0234f, 0.0358f, 0.0301f,
    0.0248f, 0.0214f, 0.0154f, 0.0133f, 0.0146f, 0.0194f, 0.02f, 0.012f,
    0.0135f, 0.041f, 0.0558f, 0.0251f, 0.0057f, 0.0027f, 0.0023f, 0.0021f,
    0.0024f, 0.0024f, 0.002f, 0.0024f, 0.0032f, 0.0026f, 0.0016f, 0.0012f,
    0.0009f,
  },
  { /* F12 */
    0.0096f, 0.0064f, 0.0045f, 0.0033f, 0.0119f, 0.1248f, 0.0112f, 0.0094f,
    0.0108f, 0.0137f, 0.0178f, 0.2905f, 0.079f, 0.0265f, 0.0271f, 0.0265f,
    0.0249f, 0.0233f, 0.021f, 0.0191f, 0.0301f, 0.1083f, 0.1188f, 0.0688f,
    0.0343f, 0.0149f, 0.0092f, 0.0071f, 0.006f, 0.0063f, 0.011f, 0.0456f,
    0.344f, 0.654f, 0.2948f, 0.0716f, 0.0308f, 0.0247f, 0.0227f, 0.0509f,
    0.1196f, 0.1532f, 0.1427f, 0.1186f, 0.0928f, 0.1231f, 0.6853f, 0.5302f,
    0.1467f, 0.1438f, 0.1471f, 0.0646f, 0.0257f, 0.0275f, 0.0418f, 0.0344f,
    0.0281f, 0.0242f, 0.0164f, 0.0136f, 0.0149f, 0.0214f, 0.0234f, 0.0142f,
    0.0161f, 0.0504f, 0.0698f, 0.0319f, 0.0071f, 0.003f, 0.0026f, 0.0023f,
    0.0028f, 0.0028f, 0.0021f, 0.0017f, 0.0021f, 0.0019f, 0.0015f, 0.001f,
    0.0005f,
  }
};

/* pbrt-v4 scales its named illuminants so that sum_{360..830, 1 nm} ybar S equals the
   integral of ybar, CIE_Y_integral = 106.856895 (pbrt-v4 src/pbrt/util/spectrum.h;
   CIE_Y_INTEGRAL, specnee.h); such a spectrum has luminance Y = 1 in spec_to_xyz's
   units. */

/* Planck's second radiation constant c2 = h c / k_B (CODATA 2018), in m K. */
#define PLANCK_C2 1.438777e-2
/* Wien's displacement constant b (CODATA 2018): the peak is at lambda = b / T. */
#define WIEN_B 2.897771955e-3

/* ======================================================================
   2. Small helpers
   ====================================================================== */

/* Linear interpolation in a table that starts at `start` nm with `step` nm spacing;
   zero outside the table (and for NaN). */
static double table_lerp(const float *tab, int n, double start, double step, double lambda_nm)
{
    double t = (lambda_nm - start) / step;
    int i;
    if (!(t >= 0.0) || t > (double)(n - 1)) return 0.0;
    i = (int)t;
    if (i >= n - 1) return tab[n - 1];
    t -= i;
    return (1.0 - t) * tab[i] + t * tab[i + 1];
}

/* The colour-matching functions at an exact wavelength, in double precision:
   table_lerp of each of the three tables.  They share their knots, so the cell i
   and the weight t are found once for all three (the film does this for every
   wavelength of every sample); the arithmetic per table is table_lerp's, written
   out for the three (a loop over a table of the tables cost the film some 20
   instructions a wavelength: docs/speed.md).  Static inline, so that cie_xyz, the
   film's call, has no second call. */
static inline void cmf_at(double lambda_nm, double xyz[3])
{
    double t = (lambda_nm - CIE_START) / CIE_STEP, s;
    int i;
    if (!(t >= 0.0) || t > (double)(CIE_N5 - 1)) {
        xyz[0] = xyz[1] = xyz[2] = 0.0;
        return;
    }
    i = (int)t;
    if (i >= CIE_N5 - 1) {
        xyz[0] = cie_xbar_5nm[CIE_N5 - 1];
        xyz[1] = cie_ybar_5nm[CIE_N5 - 1];
        xyz[2] = cie_zbar_5nm[CIE_N5 - 1];
        return;
    }
    t -= i;
    s = 1.0 - t;
    xyz[0] = s * cie_xbar_5nm[i] + t * cie_xbar_5nm[i + 1];
    xyz[1] = s * cie_ybar_5nm[i] + t * cie_ybar_5nm[i + 1];
    xyz[2] = s * cie_zbar_5nm[i] + t * cie_zbar_5nm[i + 1];
}

void cie_cmf(double lambda_nm, double xyz[3])
{
    cmf_at(lambda_nm, xyz);
}

/* ASCII case-insensitive string equality (strcasecmp is POSIX, not C99). */
static int name_eq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

/* ASCII case-insensitive prefix test; returns the rest of s after the prefix or NULL. */
static const char *skip_prefix(const char *s, const char *prefix)
{
    for (; *prefix; s++, prefix++)
        if (tolower((unsigned char)*s) != tolower((unsigned char)*prefix)) return NULL;
    return s;
}

/* Index of the first / last table entry inside [lo, hi] nm (1 nm grid). */
static void table_range(float lo_nm, float hi_nm, int *i0, int *i1)
{
    double lo = ceil((double)lo_nm), hi = floor((double)hi_nm);
    if (!(lo >= SPEC_MIN)) lo = SPEC_MIN;       /* also catches NaN */
    if (!(hi <= SPEC_MAX)) hi = SPEC_MAX;
    *i0 = (int)lo - SPEC_MIN;
    *i1 = (int)hi - SPEC_MIN;                   /* empty when *i1 < *i0 */
}

/* ======================================================================
   3. CIE colour-matching functions
   ====================================================================== */

void cie_xyz(float lambda_nm, float xyz[3])
{
    double d[3];
    cmf_at(lambda_nm, d);
    xyz[0] = (float)d[0];
    xyz[1] = (float)d[1];
    xyz[2] = (float)d[2];
}

/* ybar(lambda) alone: cie_cmf's xyz[1], the same arithmetic. */
double cie_ybar(double lambda_nm)
{
    return table_lerp(cie_ybar_5nm, CIE_N5, CIE_START, CIE_STEP, lambda_nm);
}

/* sum_{lambda = lo..hi, 1 nm} ybar(lambda), with ybar interpolated from the 5 nm
   table; over 360..830 this is 106.857 (the integral of ybar in nm). */
double cie_y_integral(float lo_nm, float hi_nm)
{
    int i, i0, i1;
    double sum = 0.0;
    table_range(lo_nm, hi_nm, &i0, &i1);
    for (i = i0; i <= i1; i++)
        sum += table_lerp(cie_ybar_5nm, CIE_N5, CIE_START, CIE_STEP, (double)(SPEC_MIN + i));
    return sum;
}

/* ======================================================================
   4. The Spectrum table: evaluation and construction
   ====================================================================== */

/* Linear interpolation between the 1 nm samples; 0 outside [SPEC_MIN, SPEC_MAX]. */
float spec_eval(const Spectrum *s, float lambda_nm)
{
    float t = lambda_nm - (float)SPEC_MIN;
    int i;
    if (lambda_nm < (float)SPEC_MIN && lambda_nm >= (float)SPEC_UV_MIN) {
        /* the UV extension, continuous with v[0] at SPEC_MIN */
        float a, b;
        t = lambda_nm - (float)SPEC_UV_MIN;
        i = (int)t;
        if (i > SPEC_UV_N - 1) i = SPEC_UV_N - 1;
        a = s->uv[i];
        b = i + 1 < SPEC_UV_N ? s->uv[i + 1] : s->v[0];
        t -= (float)i;
        return a + t * (b - a);
    }
    if (!(t >= 0.0f) || t > (float)(SPEC_N - 1)) return 0.0f;
    i = (int)t;
    if (i >= SPEC_N - 1) return s->v[SPEC_N - 1];
    t -= (float)i;
    return s->v[i] + t * (s->v[i + 1] - s->v[i]);
}

/* Knot i of the scaled table, (float)(num * s / den) (num * s a float product), of
   the UV part when uv is set. */
static float scaled_knot(const Spectrum *s, float num, double den, int uv, int i)
{
    return (float)(num * (uv ? s->uv[i] : s->v[i]) / den);
}

float spec_eval_scaled(const Spectrum *s, float num, double den, float lambda_nm)
{
    float t = lambda_nm - (float)SPEC_MIN;
    int i;
    if (lambda_nm < (float)SPEC_MIN && lambda_nm >= (float)SPEC_UV_MIN) {
        float a, b;
        t = lambda_nm - (float)SPEC_UV_MIN;
        i = (int)t;
        if (i > SPEC_UV_N - 1) i = SPEC_UV_N - 1;
        a = scaled_knot(s, num, den, 1, i);
        b = i + 1 < SPEC_UV_N ? scaled_knot(s, num, den, 1, i + 1) : scaled_knot(s, num, den, 0, 0);
        t -= (float)i;
        return a + t * (b - a);
    }
    if (!(t >= 0.0f) || t > (float)(SPEC_N - 1)) return 0.0f;
    i = (int)t;
    if (i >= SPEC_N - 1) return scaled_knot(s, num, den, 0, SPEC_N - 1);
    t -= (float)i;
    {
        float a = scaled_knot(s, num, den, 0, i), b = scaled_knot(s, num, den, 0, i + 1);
        return a + t * (b - a);
    }
}

void spec_const(Spectrum *s, float value)
{
    int i;
    for (i = 0; i < SPEC_N; i++) s->v[i] = value;
    for (i = 0; i < SPEC_UV_N; i++) s->uv[i] = value;
}

int spec_is_constant(const Spectrum *s)
{
    int i;
    for (i = 1; i < SPEC_N; i++)
        if (s->v[i] != s->v[0]) return 0;
    return 1;
}

/* FNV-1a (64-bit) over the table's 64-bit words (pairs of the floats' bit
   patterns; an odd last float alone) in four interleaved lanes (word i to lane
   i mod 4: four independent chains of multiplies, not one), folded to 32 bits. */
static unsigned spec_hash(const Spectrum *s)
{
    const unsigned char *b = (const unsigned char *)s;
    uint64_t h[4] = { 14695981039346656037u, 14695981039346656037u ^ 1u,
                      14695981039346656037u ^ 2u, 14695981039346656037u ^ 3u };
    size_t i;
    int k;
    for (i = 0; i + 32 <= sizeof *s; i += 32)
        for (k = 0; k < 4; k++) {
            uint64_t w;
            memcpy(&w, b + i + 8 * k, 8);
            h[k] = (h[k] ^ w) * 1099511628211u;
        }
    for (; i + 8 <= sizeof *s; i += 8) {
        uint64_t w;
        memcpy(&w, b + i, 8);
        h[0] = (h[0] ^ w) * 1099511628211u;
    }
    for (; i + 4 <= sizeof *s; i += 4) {
        uint32_t w;
        memcpy(&w, b + i, 4);
        h[0] = (h[0] ^ w) * 1099511628211u;
    }
    for (k = 1; k < 4; k++) h[0] = (h[0] ^ h[k]) * 1099511628211u;
    return (unsigned)(h[0] ^ (h[0] >> 32));
}

/* Put record i (hash h) in the first free slot of its probe sequence. */
static void spec_store_place(SpectrumStore *st, unsigned h, int i)
{
    int k = (int)(h & (unsigned)(st->n_slots - 1));
    while (st->slot[k]) k = (k + 1) & (st->n_slots - 1);
    st->slot[k] = i + 1;
}

const Spectrum *spec_store_add(SpectrumStore *st, const Spectrum *s)
{
    Spectrum *r;
    unsigned h = spec_hash(s);
    int k, i;
    if (st->n_slots > 0) {                  /* linear probing from the hash's slot */
        k = (int)(h & (unsigned)(st->n_slots - 1));
        for (; st->slot[k]; k = (k + 1) & (st->n_slots - 1))
            if (st->hash[st->slot[k] - 1] == h && memcmp(st->rec[st->slot[k] - 1], s, sizeof *s) == 0)
                return st->rec[st->slot[k] - 1];
    }
    if (st->n == st->cap) {
        int cap = st->cap ? 2 * st->cap : 16;
        Spectrum **rec = (Spectrum **)realloc(st->rec, sizeof *rec * (size_t)cap);
        unsigned *hash;
        if (!rec) return NULL;
        st->rec = rec;
        hash = (unsigned *)realloc(st->hash, sizeof *hash * (size_t)cap);
        if (!hash) return NULL;
        st->hash = hash;
        st->cap = cap;
    }
    if (2 * (st->n + 1) > st->n_slots) {    /* at most half full: grow and rehash */
        int n_slots = st->n_slots ? 2 * st->n_slots : 32;
        int *slot = (int *)calloc((size_t)n_slots, sizeof *slot);
        if (!slot) return NULL;
        free(st->slot);
        st->slot = slot;
        st->n_slots = n_slots;
        for (i = 0; i < st->n; i++) spec_store_place(st, st->hash[i], i);
    }
    r = (Spectrum *)malloc(sizeof *r);
    if (!r) return NULL;
    *r = *s;
    st->rec[st->n] = r;
    st->hash[st->n] = h;
    spec_store_place(st, h, st->n++);
    return r;
}

void spec_store_free(SpectrumStore *st)
{
    int i;
    for (i = 0; i < st->n; i++) free(st->rec[i]);
    free(st->rec);
    free(st->hash);
    free(st->slot);
    memset(st, 0, sizeof *st);
}

/* Scale s so that its luminance sum_{360..830, 1 nm} ybar S is CIE_Y_INTEGRAL, as
   pbrt-v4 does for its named illuminants (stdillum-*). */
static void scale_to_cie_y(Spectrum *s)
{
    double sum = 0.0, k;
    int i;
    for (i = 0; i < SPEC_N; i++)
        sum += table_lerp(cie_ybar_5nm, CIE_N5, CIE_START, CIE_STEP, (double)(SPEC_MIN + i)) * s->v[i];
    if (!(sum > 0.0)) return;
    k = CIE_Y_INTEGRAL / sum;
    for (i = 0; i < SPEC_N; i++) s->v[i] = (float)(s->v[i] * k);
    for (i = 0; i < SPEC_UV_N; i++) s->uv[i] = (float)(s->uv[i] * k);
}

/* Piecewise linear through the pairs, zero outside [lambda_0, lambda_{n-1}]
   (pbrt-v4's PiecewiseLinearSpectrum), sampled at every integer nm.  A single pair
   leaves a spike that survives only when its lambda is an integer (pbrt-v4 warns
   about one-pair spectra for the same reason). */
int spec_from_pairs(Spectrum *s, const float *lambda, const float *value, int n, Error *err,
                    const char *file, int line)
{
    int i, k;
    if (n < 1 || !lambda || !value) {
        error_set(err, file, line, "spectrum has no (wavelength, value) pairs");
        return 0;
    }
    for (k = 0; k < n; k++) {
        if (!isfinite(lambda[k]) || !isfinite(value[k])) {
            error_set(err, file, line, "spectrum pair %d (%g, %g) is not finite",
                      k + 1, (double)lambda[k], (double)value[k]);
            return 0;
        }
        if (k > 0 && !(lambda[k] > lambda[k - 1])) {
            error_set(err, file, line, "spectrum wavelengths must increase strictly "
                      "(%g nm after %g nm)", (double)lambda[k], (double)lambda[k - 1]);
            return 0;
        }
    }
    k = 0;                                        /* current segment [k, k + 1] */
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++) {   /* the UV extension too */
        double l = (double)i, t;
        float *v = spec_at(s, i);
        if (l < lambda[0] || l > lambda[n - 1]) { *v = 0.0f; continue; }
        while (k + 1 < n - 1 && l > lambda[k + 1]) k++;
        if (n == 1) { *v = value[0]; continue; }
        t = (l - lambda[k]) / ((double)lambda[k + 1] - lambda[k]);
        *v = (float)((1.0 - t) * value[k] + t * value[k + 1]);
    }
    return 1;
}

/* Planck's law without its constant factor: B(lambda, T) ~ lambda^-5 /
   (exp(c2 / (lambda T)) - 1), lambda in nm.  expm1 keeps precision at high T. */
static double planck_shape(double lambda_nm, double kelvin)
{
    double l = lambda_nm * 1e-9;                  /* metres */
    double x = PLANCK_C2 / (l * kelvin);
    if (x > 700.0) return 0.0;                    /* exp would overflow: B is ~0 */
    return 1.0 / (l * l * l * l * l * expm1(x));
}

/* Blackbody normalised to a peak of 1 (pbrt-v4's BlackbodySpectrum): the peak is at
   Wien's lambda_max = b / T, even if that lies outside 360..830 nm. */
void spec_blackbody(Spectrum *s, float kelvin)
{
    double peak;
    int i;
    if (!(kelvin > 0.0f) || !isfinite(kelvin)) { spec_const(s, 0.0f); return; }
    peak = planck_shape(WIEN_B / kelvin * 1e9, kelvin);
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
        *spec_at(s, i) = peak > 0.0 ? (float)(planck_shape(i, kelvin) / peak) : 0.0f;
}

/* The same normalised blackbody at one wavelength (a temperature grid's emission
   is evaluated at each collision, medium.c). */
float blackbody_eval(float kelvin, float lambda_nm)
{
    double peak;
    if (!(kelvin > 0.0f) || !isfinite(kelvin)) return 0.0f;
    peak = planck_shape(WIEN_B / kelvin * 1e9, kelvin);
    return peak > 0.0 ? (float)(planck_shape(lambda_nm, kelvin) / peak) : 0.0f;
}

/* ======================================================================
   5. Colorimetry
   ====================================================================== */

/* XYZ = sum_{1 nm} cmf S / sum_{1 nm} ybar over the same range [lo, hi]. */
void spec_to_xyz(const Spectrum *s, float lo_nm, float hi_nm, double xyz[3])
{
    int i, i0, i1;
    double c[3], norm = 0.0;
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    table_range(lo_nm, hi_nm, &i0, &i1);
    for (i = i0; i <= i1; i++) {
        cie_cmf((double)(SPEC_MIN + i), c);
        xyz[0] += c[0] * s->v[i];
        xyz[1] += c[1] * s->v[i];
        xyz[2] += c[2] * s->v[i];
        norm += c[1];
    }
    if (norm > 0.0) { xyz[0] /= norm; xyz[1] /= norm; xyz[2] /= norm; }
}

/* spec_to_xyz(s, SPEC_MIN, SPEC_MAX)'s Y alone: the same two sums in the same
   order, without X and Z (a third of the interpolations). */
double spec_to_y(const Spectrum *s)
{
    double y = 0.0, norm = 0.0;
    int i;
    for (i = 0; i < SPEC_N; i++) {
        double c = cie_ybar((double)(SPEC_MIN + i));
        y += c * s->v[i];
        norm += c;
    }
    return norm > 0.0 ? y / norm : 0.0;
}

/* pbrt-v4's XYZ -> linear sRGB matrix (its RGBColorSpace::sRGB, D65 white
   xy = (0.312727, 0.329023)), docs/conventions.md and THEORY §1. */
void xyz_to_linear_srgb(const double xyz[3], double rgb[3])
{
    static const double M[3][3] = {
        {  3.24044132, -1.53713238, -0.49852949 },
        { -0.96926785,  1.87601423,  0.04155612 },
        {  0.05564349, -0.20402624,  1.05722737 } };
    int r;
    for (r = 0; r < 3; r++)
        rgb[r] = M[r][0] * xyz[0] + M[r][1] * xyz[1] + M[r][2] * xyz[2];
}

void spec_chromaticity(const Spectrum *s, double *x, double *y)
{
    double xyz[3], sum;
    spec_to_xyz(s, (float)SPEC_MIN, (float)SPEC_MAX, xyz);
    sum = xyz[0] + xyz[1] + xyz[2];
    if (!(sum > 0.0)) { *x = *y = 0.0; return; }
    *x = xyz[0] / sum;
    *y = xyz[1] / sum;
}

/* CIE 1960 (u, v) of the Planckian radiator at temperature T (1 nm sums, 360..830). */
static void planck_uv(double kelvin, double *u, double *v)
{
    double xyz[3] = { 0.0, 0.0, 0.0 }, c[3], b, d;
    int l;
    for (l = SPEC_MIN; l <= SPEC_MAX; l++) {
        cie_cmf((double)l, c);
        b = planck_shape((double)l, kelvin);
        xyz[0] += c[0] * b; xyz[1] += c[1] * b; xyz[2] += c[2] * b;
    }
    d = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];   /* u = 4X/(X+15Y+3Z), v = 6Y/(...) */
    *u = 4.0 * xyz[0] / d;
    *v = 6.0 * xyz[1] / d;
}

static double uv_dist2(double kelvin, double u, double v)
{
    double pu, pv;
    planck_uv(kelvin, &pu, &pv);
    return (u - pu) * (u - pu) + (v - pv) * (v - pv);
}

/* Exact CCT: minimise the (u, v) distance to the Planckian locus over T in
   [1000 K, 100000 K].  A coarse scan in log T brackets the minimum, then a golden-
   section search refines it (the distance is unimodal near the locus).  Returns 0
   (and Duv 0) for an invalid chromaticity. */
double cct_from_xy(double x, double y, double *duv)
{
    const double log_lo = log(1000.0), log_hi = log(100000.0);
    const int n_scan = 64;
    const double golden = 0.6180339887498949;     /* (sqrt 5 - 1) / 2 */
    double d = -2.0 * x + 12.0 * y + 3.0, u, v, best = HUGE_VAL, a, b, c1, c2, f1, f2, t, pu, pv;
    int k, k_best = 0;
    if (duv) *duv = 0.0;
    if (!isfinite(x) || !isfinite(y) || !(d > 0.0) || !(y > 0.0)) return 0.0;
    u = 4.0 * x / d;
    v = 6.0 * y / d;
    for (k = 0; k <= n_scan; k++) {               /* 1. bracket */
        double dist = uv_dist2(exp(log_lo + (log_hi - log_lo) * k / n_scan), u, v);
        if (dist < best) { best = dist; k_best = k; }
    }
    a = log_lo + (log_hi - log_lo) * (k_best > 0 ? k_best - 1 : 0) / n_scan;
    b = log_lo + (log_hi - log_lo) * (k_best < n_scan ? k_best + 1 : n_scan) / n_scan;
    c1 = b - golden * (b - a);                    /* 2. golden-section search in log T */
    c2 = a + golden * (b - a);
    f1 = uv_dist2(exp(c1), u, v);
    f2 = uv_dist2(exp(c2), u, v);
    for (k = 0; k < 60; k++) {
        if (f1 < f2) { b = c2; c2 = c1; f2 = f1; c1 = b - golden * (b - a); f1 = uv_dist2(exp(c1), u, v); }
        else         { a = c1; c1 = c2; f1 = f2; c2 = a + golden * (b - a); f2 = uv_dist2(exp(c2), u, v); }
    }
    t = exp(0.5 * (a + b));
    if (duv) {                                    /* 3. signed distance: + above the locus */
        planck_uv(t, &pu, &pv);
        *duv = sqrt((u - pu) * (u - pu) + (v - pv) * (v - pv));
        if (v < pv) *duv = -*duv;
    }
    return t;
}

/* ======================================================================
   6. thesis eq. 6: bins of 5 nm over 400..700 nm
   ====================================================================== */

/* The exact mean of the piecewise-linear table over [lo, lo + width] nm, in
   double (0 outside the table): the trapezoid rule is exact for a
   piecewise-linear function with knots at integers; for a 5 nm bin
       mean = (v0/2 + v1 + v2 + v3 + v4 + v5/2) / 5. */
double spec_band_mean(const Spectrum *s, int lo_nm, int width_nm)
{
    int k;
    double sum;
    if (width_nm < 1 || lo_nm < SPEC_UV_MIN || lo_nm + width_nm > SPEC_MAX) return 0.0;
    sum = 0.5 * (spec_get(s, lo_nm) + spec_get(s, lo_nm + width_nm));
    for (k = 1; k < width_nm; k++) sum += spec_get(s, lo_nm + k);
    return sum / width_nm;
}

float spec_band_average(const Spectrum *s, int lo_nm, int width_nm)
{
    return (float)spec_band_mean(s, lo_nm, width_nm);
}

float spec_bin_average(const Spectrum *s, int bin)
{
    if (bin < 0 || bin >= SPD_BINS) return 0.0f;
    return spec_band_average(s, (int)LAMBDA_LO + (int)SPD_BIN_NM * bin, (int)SPD_BIN_NM);
}

double spec_bin_sum(const Spectrum *s)
{
    double sum = 0.0;
    int b;
    for (b = 0; b < SPD_BINS; b++) sum += spec_bin_average(s, b);
    return sum;
}

/* ======================================================================
   7. Glasses: Cauchy coefficients and Sellmeier tables
   ====================================================================== */

/* Cauchy's law n = A + B / lambda^2 (lambda in um).  Least-squares fits over
   380..780 nm to the published Sellmeier formulas: SCHOTT optical glass catalogue
   (N-BK7, N-SF10, N-SF11), Malitson 1965 (fused silica), Peter 1923 (diamond); the
   BK7 row is the classic textbook pair (1.5046, 0.00420).  The "teaching" glasses are
   exaggerated on purpose (Abbe number ~15) so that rainbows are easy to see. */
typedef struct { const char *name; float A, B; } CauchyGlass;
static const CauchyGlass cauchy_glasses[] = {
    { "BK7",             1.5046f, 0.00420f },   /* n_d 1.5168, V_d 64.2 */
    { "fused-silica",    1.4481f, 0.00354f },   /* n_d 1.4585, V_d 67.8 */
    { "SF10",            1.6877f, 0.01421f },   /* n_d 1.7283, V_d 28.5 */
    { "SF11",            1.7358f, 0.01715f },   /* n_d 1.7847, V_d 25.7 */
    { "diamond",         2.3781f, 0.01367f },   /* n_d 2.4175, V_d 55.3 */
    { "teaching",        1.50f,   0.02f    },   /* V_d ~ 15 */
    { "teaching-strong", 1.50f,   0.04f    },   /* V_d ~ 7.5 */
    { NULL, 0.0f, 0.0f }
};

/* name: "BK7", "fused-silica", ... (an optional "cauchy-" prefix is accepted),
   compared without regard to case. */
int cauchy_named(const char *name, float *A, float *B)
{
    const char *rest;
    int i;
    if (!name) return 0;
    if ((rest = skip_prefix(name, "cauchy-")) != NULL) name = rest;
    for (i = 0; cauchy_glasses[i].name; i++)
        if (name_eq(name, cauchy_glasses[i].name)) {
            *A = cauchy_glasses[i].A;
            *B = cauchy_glasses[i].B;
            return 1;
        }
    return 0;
}

/* Sellmeier coefficients of SCHOTT glasses (SCHOTT optical glass data sheets /
   catalogue; also listed by refractiveindex.info):
       n^2(lambda) = 1 + sum_{i=1..3} B_i lambda^2 / (lambda^2 - C_i),  lambda in um.
   pbrt-v4 names them glass-BK7 (N-BK7), glass-BAF10 (N-BAF10), glass-FK51A
   (N-FK51A), glass-LASF9 (N-LASF9), glass-F5 (SF5), glass-F10 (SF10), glass-F11
   (SF11).  Each set reproduces the catalogue n_d (587.56 nm) and Abbe number V_d. */
typedef struct { const char *name; double B[3], C[3]; } SellmeierGlass;
static const SellmeierGlass sellmeier_glasses[] = {
    { "glass-BK7",   { 1.03961212, 0.231792344, 1.01046945 },      /* n_d 1.51680, V_d 64.17 */
                     { 0.00600069867, 0.0200179144, 103.560653 } },
    { "glass-BAF10", { 1.5851495, 0.143559385, 1.08521269 },       /* n_d 1.67003, V_d 47.11 */
                     { 0.00926681282, 0.0424489805, 105.613573 } },
    { "glass-FK51A", { 0.971247817, 0.216901417, 0.904651666 },    /* n_d 1.48656, V_d 84.47 */
                     { 0.00472301995, 0.0153575612, 168.68133 } },
    { "glass-LASF9", { 2.00029547, 0.298926886, 1.80691843 },      /* n_d 1.85025, V_d 32.17 */
                     { 0.0121426017, 0.0538736236, 156.530829 } },
    { "glass-F5",    { 1.46141885, 0.247713019, 0.949995832 },     /* SF5: n_d 1.67270, V_d 32.21 */
                     { 0.0111826126, 0.0508594669, 112.041888 } },
    { "glass-F10",   { 1.61625977, 0.259229334, 1.07762317 },      /* SF10: n_d 1.72825, V_d 28.41 */
                     { 0.0127534559, 0.0581983954, 116.60768 } },
    { "glass-F11",   { 1.73848403, 0.311168974, 1.17490871 },      /* SF11: n_d 1.78472, V_d 25.76 */
                     { 0.0136068604, 0.0615960463, 121.922711 } },
    { NULL, { 0, 0, 0 }, { 0, 0, 0 } }
};

static double sellmeier_eta(const SellmeierGlass *g, double lambda_nm)
{
    double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3), n2 = 1.0;
    int i;
    for (i = 0; i < 3; i++) n2 += g->B[i] * l2 / (l2 - g->C[i]);
    return sqrt(n2);
}

/* ======================================================================
   8. The thesis' three lamps, modeled (not measured)
   ----------------------------------------------------------------------
   The thesis used three measured spectra from the Lamp Spectral Power Distribution
   Database (LSPDD, indices 2488, 2470, 2489).  The LSPDD licence (CC BY-NC-ND) does
   not allow redistributing resampled tables, so specnee *models* each lamp from the
   physics of its light source and tunes one free parameter to the lamp's published
   correlated colour temperature (CCT).  These are look-alikes, not the measurements:
   load the real data with a CSV file (`"spectrum L" "lamp.csv"`) when you have it.

   g(lambda; mu, w) is a Gaussian with centre mu and full width at half maximum w
   (sigma = w / 2.3548) and peak 1.  Each table value is the Gaussian's MEAN over the
   1 nm cell [lambda - 1/2, lambda + 1/2] (an erf difference), not a point sample, so
   a 2 nm wide mercury line keeps its energy on the 1 nm grid.  Finally each lamp is
   scaled so that its thesis eq. 6 sum over the 60 bins is 1.
   ====================================================================== */

typedef struct { double mu, fwhm, peak; } GaussLine;

/* Add peak * mean_{cell} g(lambda; mu, fwhm) to every 1 nm cell:
   mean = peak sigma sqrt(pi/2) [erf((b - mu)/(sigma sqrt 2)) - erf((a - mu)/(sigma sqrt 2))]. */
static void add_gaussian(Spectrum *s, double mu, double fwhm, double peak)
{
    const double sigma = fwhm / 2.354820045;      /* 2 sqrt(2 ln 2) */
    const double k = 1.0 / (sigma * sqrt(2.0));
    int i;
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++) {      /* the UV extension too */
        double a = i - 0.5, b = a + 1.0;
        *spec_at(s, i) += (float)(peak * sigma * sqrt(0.5 * SPECNEE_PI) * (erf((b - mu) * k) - erf((a - mu) * k)));
    }
}

static void add_lines(Spectrum *s, const GaussLine *lines, int n, double scale)
{
    int i;
    for (i = 0; i < n; i++) add_gaussian(s, lines[i].mu, lines[i].fwhm, scale * lines[i].peak);
}

static void normalise_bin_sum(Spectrum *s)
{
    double sum = spec_bin_sum(s);
    int i;
    if (!(sum > 0.0)) return;
    for (i = 0; i < SPEC_N; i++) s->v[i] = (float)(s->v[i] / sum);
    for (i = 0; i < SPEC_UV_N; i++) s->uv[i] = (float)(s->uv[i] / sum);
}

/* CFL1, "Globe Twister" compact fluorescent, 4404 K (modeled after LSPDD 2488): a
   tri-phosphor lamp.  Mercury lines (FWHM 2 nm) with peaks relative to 435.8 nm;
   terbium (Tb3+) green bands (FWHM 9 nm) scaled by k_g; europium (Eu3+, Y2O3:Eu)
   red lines (FWHM 5 nm) scaled by k_r.  Line positions: NIST atomic spectra (Hg) and
   the phosphors' published emission peaks (docs/spectra.md). */
static const GaussLine cfl_mercury[] = {
    { 404.7, 2.0, 0.25 }, { 435.8, 2.0, 1.0 }, { 546.1, 2.0, 0.6 },
    { 577.0, 2.0, 0.08 }, { 579.1, 2.0, 0.08 } };
static const GaussLine cfl_terbium[] = {
    { 543.5, 9.0, 1.0 }, { 488.5, 9.0, 0.15 }, { 586.0, 9.0, 0.10 }, { 621.0, 9.0, 0.06 } };
static const GaussLine cfl_europium[] = {
    { 611.0, 5.0, 1.0 }, { 587.0, 5.0, 0.06 }, { 593.0, 5.0, 0.08 }, { 599.0, 5.0, 0.06 },
    { 626.0, 5.0, 0.12 }, { 650.0, 5.0, 0.03 }, { 707.0, 5.0, 0.03 } };

/* Tuned parameters (see docs/spectra.md for the resulting xy, CCT and Duv; the
   tests assert each CCT within 25 K of its target).  They were tuned with this
   file's own colorimetry (exact CCT, section 5) to within 5 K of the LSPDD CCTs. */
#define CFL1_K_G 0.2017    /* terbium (green) scale, tuned with k_r for CCT 4404 K, Duv 0 */
#define CFL1_K_R 0.3799    /* europium (red) scale */
#define LED1_R   1.694     /* blue die : phosphor peak ratio for CCT 5832 K */
#define LED2_R   2.253     /* blue die : phosphor peak ratio for CCT 7600 K */

static void lamp_cfl1(Spectrum *s, double k_g, double k_r)
{
    spec_const(s, 0.0f);
    add_lines(s, cfl_mercury, (int)(sizeof cfl_mercury / sizeof cfl_mercury[0]), 1.0);
    add_lines(s, cfl_terbium, (int)(sizeof cfl_terbium / sizeof cfl_terbium[0]), k_g);
    add_lines(s, cfl_europium, (int)(sizeof cfl_europium / sizeof cfl_europium[0]), k_r);
    normalise_bin_sum(s);
}

/* Phosphor-converted white LED: an InGaN blue die (peak 450 nm, FWHM 22 nm) plus a
   broad YAG:Ce phosphor band; r = blue peak / phosphor peak sets the CCT.
   LED1, "Ledtech PAR20", 5832 K (modeled after LSPDD 2470): phosphor 565 nm, FWHM 125.
   LED2, "Philips Blue-Golite", 7600 K (modeled after LSPDD 2489): phosphor 560 nm,
   FWHM 120.  (The product name suggests a blue light-therapy lamp; its listed 7600 K
   only fits a bluish *white* spectrum, so it is modeled as one.) */
static void lamp_led(Spectrum *s, double r, double phosphor_nm, double phosphor_fwhm)
{
    spec_const(s, 0.0f);
    add_gaussian(s, 450.0, 22.0, r);
    add_gaussian(s, phosphor_nm, phosphor_fwhm, 1.0);
    normalise_bin_sum(s);
}

/* ----------------------------------------------------------------------
   Ultraviolet lamps and fluorophores (fluorescence, docs/FLUORESCENCE.md §6).
   Modelled as Gaussian bands (the add_gaussian cell means above) from published
   peak positions and widths; they are not copied from measured tables.  Where a
   width is not given by the source it is marked "chosen".
   ---------------------------------------------------------------------- */

/* Peak 1 (the sample at the peak's nearest nm): the UV lamps have no luminance, so
   they cannot be scaled to thesis eq. 6 or to Y; scene files read them as absolute
   radiance times "scale" (docs/conventions.md §4). */
static void normalise_peak(Spectrum *s)
{
    float m = 0.0f;
    int nm;
    for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) if (spec_get(s, nm) > m) m = spec_get(s, nm);
    if (m > 0.0f)
        for (nm = SPEC_UV_MIN; nm <= SPEC_MAX; nm++) *spec_at(s, nm) /= m;
}

/* lamp-UVLED365: a 365 nm UV LED, peak 365 nm, spectrum half width (FWHM) 9 nm
   (Nichia NCSU033B specification: peak wavelength 365 nm, spectrum half width
   9 nm typ.). */
static void lamp_uvled365(Spectrum *s)
{
    spec_const(s, 0.0f);
    add_gaussian(s, 365.0, 9.0, 1.0);
    normalise_peak(s);
}

/* lamp-BLB: a blacklight-blue fluorescent tube (Philips TL-D BLB type): a UV-A
   phosphor band peaking at 365 nm behind a Wood's-glass envelope, about 350-400 nm
   (FWHM 25 nm, chosen to span that band), plus the mercury lines that leak through
   the glass, 404.66 and 435.84 nm (NIST Atomic Spectra Database), FWHM 2 nm as in
   CFL1, at 5 % and 2 % of the band's peak (chosen: "weak").  It has luminance (the
   lines), so a scene's "scale" sets the luminance of its visible leak, as for any
   visible lamp (pbrt-v4's rule). */
static void lamp_blb(Spectrum *s)
{
    spec_const(s, 0.0f);
    add_gaussian(s, 365.0, 25.0, 1.0);
    add_gaussian(s, 404.66, 2.0, 0.05);
    add_gaussian(s, 435.84, 2.0, 0.02);
    normalise_peak(s);
}

/* Fluorophores: excitation = absorptance A (peak 1: the layer absorbs all light at
   its peak) and emission shape (peak 1; the material renormalises it).
   - brightener: stilbene-type fluorescent whitening agents in white paper absorb
     about 340-370 nm and emit about 420-470 nm (Wikipedia, "Optical brightener"):
     excitation 355 nm FWHM 35, emission 440 nm FWHM 50 (widths chosen to span the
     ranges).
   - fluorescein (dianion): absorption peak 490 nm, quantum yield 0.93 (Sjoeback,
     Nygren, Kubista 1995, Spectrochim. Acta A 51, L7); emission peak 515 nm (Martin,
     Lindqvist 1975, J. Luminescence 10, 381); FWHM 40 nm for both (chosen).  No
     near-UV band is modelled.
   - pyranine (the yellow highlighter dye): emission bands at 441 and 511 nm under
     350 nm excitation (Barnadas-Rodriguez, Estelrich 2008, J. Photochem. Photobiol.
     A 198, 262); excitation: the protonated and deprotonated bands at 405 and 455 nm
     and the 350 nm band the paper excites; relative heights and all widths chosen. */
static void fluor_band(Spectrum *s, const GaussLine *b, int n)
{
    spec_const(s, 0.0f);
    add_lines(s, b, n, 1.0);
    normalise_peak(s);
}
static const GaussLine fl_brightener_ex[] = { { 355.0, 35.0, 1.0 } };
static const GaussLine fl_brightener_em[] = { { 440.0, 50.0, 1.0 } };
static const GaussLine fl_fluorescein_ex[] = { { 490.0, 40.0, 1.0 } };
static const GaussLine fl_fluorescein_em[] = { { 515.0, 40.0, 1.0 } };
static const GaussLine fl_pyranine_ex[] = { { 350.0, 30.0, 0.5 }, { 405.0, 30.0, 0.7 }, { 455.0, 30.0, 1.0 } };
static const GaussLine fl_pyranine_em[] = { { 441.0, 35.0, 0.3 }, { 511.0, 40.0, 1.0 } };
#define FL_BANDS(a) (a), (int)(sizeof (a) / sizeof (a)[0])

/* ======================================================================
   9. Named spectra (pbrt-v4 names where pbrt-v4 has them)
   ====================================================================== */

static const char *const named_spectra[] = {
    "stdillum-D65", "stdillum-A", "illum-acesD60",
    "stdillum-F1", "stdillum-F2", "stdillum-F3", "stdillum-F4", "stdillum-F5", "stdillum-F6",
    "stdillum-F7", "stdillum-F8", "stdillum-F9", "stdillum-F10", "stdillum-F11", "stdillum-F12",
    "glass-BK7", "glass-BAF10", "glass-FK51A", "glass-LASF9", "glass-F5", "glass-F10", "glass-F11",
    "cauchy-BK7", "cauchy-fused-silica", "cauchy-SF10", "cauchy-SF11", "cauchy-diamond",
    "cauchy-teaching", "cauchy-teaching-strong",
    "lamp-CFL1", "lamp-LED1", "lamp-LED2", "lamp-UVLED365", "lamp-BLB",
    "fluor-brightener-ex", "fluor-brightener-em", "fluor-fluorescein-ex",
    "fluor-fluorescein-em", "fluor-pyranine-ex", "fluor-pyranine-em",
    "metal-Ag-eta", "metal-Ag-k", "metal-Al-eta", "metal-Al-k", "metal-Au-eta", "metal-Au-k",
    "metal-Cu-eta", "metal-Cu-k", "metal-CuZn-eta", "metal-CuZn-k", "metal-MgO-eta",
    "metal-MgO-k", "metal-TiO2-eta", "metal-TiO2-k",         /* metals.c */
    NULL
};

const char *const *spec_named_list(void) { return named_spectra; }

/* Resample a 5 nm table (start nm, n rows) onto the 1 nm grid; zero outside it. */
static void from_5nm_table(Spectrum *s, const float *tab, int n, int start)
{
    int i;
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++)
        *spec_at(s, i) = (float)table_lerp(tab, n, start, 5.0, (double)i);
}

/* CIE standard illuminant A by its definition (CIE 015:2018):
       S_A(lambda) = 100 (560/lambda)^5 (exp(1.435e7 / (2848 * 560)) - 1) /
                                        (exp(1.435e7 / (2848 * lambda)) - 1),
   i.e. Planck at 2848 K with the old c2 = 1.435e-2 m K, which is 2856 K with today's
   c2 = 1.438777e-2 m K. */
static void illuminant_a(Spectrum *s)
{
    const double c = 1.435e7 / 2848.0;            /* nm */
    int i;
    for (i = SPEC_UV_MIN; i <= SPEC_MAX; i++) {
        double l = i;
        *spec_at(s, i) = (float)(100.0 * pow(560.0 / l, 5.0) * expm1(c / 560.0) / expm1(c / l));
    }
}

/* ======================================================================
   CIE daylight (CIE 015:2004 section 3.1): the basis S0, S1, S2 of its Table T.2
   (10 nm, 360..830 nm; pbrt-v4 interpolates the same table at 5 nm, which is
   linear interpolation of these rows), the locus, and the spectrum.  sensor.c's
   white balance and illum-acesD60 below use them.
   ====================================================================== */
#define DAYLIGHT_N 48        /* daylight basis: 360..830 nm, 10 nm apart */
static const float daylight_basis[3][DAYLIGHT_N] = {
    {
        61.5, 68.8, 63.4, 65.8, 94.8, 104.8, 105.9, 96.8, 113.9, 125.6, 125.5, 121.3,
        121.3, 113.5, 113.1, 110.8, 106.5, 108.8, 105.3, 104.4, 100, 96, 95.1, 89.1,
        90.5, 90.3, 88.4, 84, 85.1, 81.9, 82.6, 84.9, 81.3, 71.9, 74.3, 76.4,
        63.3, 71.7, 77, 65.2, 47.7, 68.6, 65, 66, 61, 53.3, 58.9, 61.9 },
    {
        38, 42.4, 38.5, 35, 43.4, 46.3, 43.9, 37.1, 36.7, 35.9, 32.6, 27.9,
        24.3, 20.1, 16.2, 13.2, 8.6, 6.1, 4.2, 1.9, 0, -1.6, -3.5, -3.5,
        -5.8, -7.2, -8.6, -9.5, -10.9, -10.7, -12, -14, -13.6, -12, -13.3, -12.9,
        -10.6, -11.6, -12.2, -10.2, -7.8, -11.2, -10.4, -10.6, -9.7, -8.3, -9.3, -9.8 },
    {
        5.3, 6.1, 3, 1.2, -1.1, -0.5, -0.7, -1.2, -2.6, -2.9, -2.8, -2.6,
        -2.6, -1.8, -1.5, -1.3, -1.2, -1, -0.5, -0.3, 0, 0.2, 0.5, 2.1,
        3.2, 4.1, 4.7, 5.1, 6.7, 7.3, 8.6, 9.8, 10.2, 8.3, 9.6, 8.5,
        7, 7.6, 8, 6.7, 5.2, 7.4, 6.8, 7, 6.4, 5.5, 6.1, 6.5 }
};

/* Basis k at integer nm in 360..830: linear between the 10 nm rows. */
static double daylight_knot(int k, int nm)
{
    double x = (nm - 360.0) / 10.0;
    int i = (int)x;
    const float *v = daylight_basis[k];
    if (i >= DAYLIGHT_N - 1) return v[DAYLIGHT_N - 1];
    return v[i] + (x - i) * (v[i + 1] - v[i]);
}

/* The CIE daylight locus at correlated colour temperature cct (4000..25000 K;
   CIE 015:2004 eq. 3.3, 3.4). */
void cie_daylight_xy(double cct, double *x, double *y)
{
    double t = 1.0 / cct;
    if (cct <= 7000.0)
        *x = -4.6070e9 * t * t * t + 2.9678e6 * t * t + 0.09911e3 * t + 0.244063;
    else
        *x = -2.0064e9 * t * t * t + 1.9018e6 * t * t + 0.24748e3 * t + 0.237040;
    *y = -3.000 * *x * *x + 2.870 * *x - 0.275;
}

/* CIE daylight of locus chromaticity (x, y) at 360..830 nm, 1 nm apart (CIE
   015:2004 eq. 3.5-3.7): S0 + M1 S1 + M2 S2 with
       M = 0.0241 + 0.2562 x - 0.7341 y,
       M1 = (-1.3515 - 1.7703 x + 5.9114 y) / M,
       M2 = (0.0300 - 31.4424 x + 30.0717 y) / M,
   the basis linear between its 10 nm rows.  round3: M1 and M2 rounded to three
   decimals first, as CIE 015 tabulates its D illuminants (the ACES white,
   spectrum.c's illum-acesD60, is made so).  Unnormalised. */
void cie_daylight(double x, double y, int round3, double E[SPEC_N])
{
    double M = 0.0241 + 0.2562 * x - 0.7341 * y;
    double M1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / M;
    double M2 = (0.0300 - 31.4424 * x + 30.0717 * y) / M;
    int nm;
    if (round3) {
        M1 = floor(M1 * 1000.0 + 0.5) / 1000.0;
        M2 = floor(M2 * 1000.0 + 0.5) / 1000.0;
    }
    for (nm = SPEC_MIN; nm <= SPEC_MAX; nm++) {
        double s0 = daylight_knot(0, nm), s1 = daylight_knot(1, nm), s2 = daylight_knot(2, nm);
        E[nm - SPEC_MIN] = s0 + M1 * s1 + M2 * s2;
    }
}

/* pbrt-v4's illum-acesD60, the white of ACES (SMPTE ST 2065-1; Academy TB-2018-001,
   "Derivation of the ACES white point CIE chromaticity coordinates"): CIE daylight
   at a correlated colour temperature of 6000 K, its M1 and M2 rounded to three
   decimals (-0.536, -0.519), as the Academy's derivation (A. Forsythe's script,
   which pbrt-v4's table cites) tabulates it; x, y = (0.32169, 0.33780) on the
   locus.  The CIE daylight basis above starts at 360 nm, so the UV extension
   (300..359 nm) is zero. */
static void illuminant_aces_d60(Spectrum *s)
{
    double x, y, E[SPEC_N];
    int i;
    cie_daylight_xy(6000.0, &x, &y);
    cie_daylight(x, y, 1, E);
    for (i = 0; i < SPEC_N; i++) s->v[i] = (float)E[i];
    for (i = 0; i < SPEC_UV_N; i++) s->uv[i] = 0.0f;
}

/* Names are compared without regard to case ("stdillum-d65" works too). */
int spec_named(Spectrum *s, const char *name)
{
    const char *rest;
    float A, B;
    int i;
    if (!name || !s) return 0;
    if (name_eq(name, "stdillum-D65")) {
        from_5nm_table(s, d65_5nm, CIE_N5, CIE_START);
        scale_to_cie_y(s);
        return 1;
    }
    if (name_eq(name, "illum-acesD60")) {
        illuminant_aces_d60(s);
        scale_to_cie_y(s);
        return 1;
    }
    if (name_eq(name, "stdillum-A")) {
        illuminant_a(s);
        scale_to_cie_y(s);
        return 1;
    }
    if ((rest = skip_prefix(name, "stdillum-F")) != NULL) {
        char *end;
        long k = strtol(rest, &end, 10);
        if (end != rest && *end == '\0' && k >= 1 && k <= 12 && isdigit((unsigned char)rest[0])) {
            from_5nm_table(s, cie_f_5nm[k - 1], F_N5, F_START);
            scale_to_cie_y(s);
            return 1;
        }
        return 0;
    }
    for (i = 0; sellmeier_glasses[i].name; i++)
        if (name_eq(name, sellmeier_glasses[i].name)) {
            int l;
            for (l = SPEC_UV_MIN; l <= SPEC_MAX; l++)
                *spec_at(s, l) = (float)sellmeier_eta(&sellmeier_glasses[i], (double)l);
            return 1;
        }
    if (skip_prefix(name, "cauchy-") && cauchy_named(name, &A, &B)) {
        int l;
        for (l = SPEC_UV_MIN; l <= SPEC_MAX; l++) *spec_at(s, l) = cauchy_eta(A, B, (float)l);
        return 1;
    }
    if (name_eq(name, "lamp-CFL1")) { lamp_cfl1(s, CFL1_K_G, CFL1_K_R); return 1; }
    if (name_eq(name, "lamp-LED1")) { lamp_led(s, LED1_R, 565.0, 125.0); return 1; }
    if (name_eq(name, "lamp-LED2")) { lamp_led(s, LED2_R, 560.0, 120.0); return 1; }
    if (name_eq(name, "lamp-UVLED365")) { lamp_uvled365(s); return 1; }
    if (name_eq(name, "lamp-BLB")) { lamp_blb(s); return 1; }
    if (name_eq(name, "fluor-brightener-ex")) { fluor_band(s, FL_BANDS(fl_brightener_ex)); return 1; }
    if (name_eq(name, "fluor-brightener-em")) { fluor_band(s, FL_BANDS(fl_brightener_em)); return 1; }
    if (name_eq(name, "fluor-fluorescein-ex")) { fluor_band(s, FL_BANDS(fl_fluorescein_ex)); return 1; }
    if (name_eq(name, "fluor-fluorescein-em")) { fluor_band(s, FL_BANDS(fl_fluorescein_em)); return 1; }
    if (name_eq(name, "fluor-pyranine-ex")) { fluor_band(s, FL_BANDS(fl_pyranine_ex)); return 1; }
    if (name_eq(name, "fluor-pyranine-em")) { fluor_band(s, FL_BANDS(fl_pyranine_em)); return 1; }
    if (metal_named(s, name)) return 1;          /* metal-*-eta, metal-*-k (metals.c) */
    return 0;
}

/* ======================================================================
   10. Spectrum files: pbrt .spd and CSV
   ----------------------------------------------------------------------
   .spd (pbrt): whitespace-separated numbers "lambda value lambda value ...", any
   layout over lines, '#' starts a comment.
   CSV (e.g. an LSPDD export): one "wavelength,value" per line, optionally a header
   line first (recognised by a first field that is not a number), optional quotes
   around fields, '#' comments.  A file whose first data line (after comments and
   blank lines) contains a comma is read as CSV.
   Every problem is reported as "path:line: problem".
   ====================================================================== */

typedef struct { double *lambda, *value; int n, cap; } PairList;

static int pairs_push(PairList *p, double lambda, double value)
{
    if (p->n == p->cap) {
        int cap = p->cap ? 2 * p->cap : 256;
        double *l, *v;
        if (cap > (1 << 24)) return 0;            /* 16 M pairs: clearly not a spectrum */
        l = (double *)realloc(p->lambda, (size_t)cap * sizeof *l);
        if (!l) return 0;
        p->lambda = l;
        v = (double *)realloc(p->value, (size_t)cap * sizeof *v);
        if (!v) return 0;
        p->value = v;
        p->cap = cap;
    }
    p->lambda[p->n] = lambda;
    p->value[p->n] = value;
    p->n++;
    return 1;
}

/* A whole token as a number (strtod accepts "nan"/"inf": finiteness is checked by
   the caller so that it can say so). */
static int parse_number(const char *tok, double *out)
{
    char *end;
    if (!*tok) return 0;
    *out = strtod(tok, &end);
    return *end == '\0';
}

/* Trim blanks and one pair of surrounding double quotes, in place. */
static char *trim_field(char *f)
{
    char *e;
    while (*f == ' ' || *f == '\t') f++;
    e = f + strlen(f);
    while (e > f && (e[-1] == ' ' || e[-1] == '\t')) *--e = '\0';
    if (e - f >= 2 && f[0] == '"' && e[-1] == '"') { e[-1] = '\0'; f++; }
    return f;
}

/* Reject NaN, inf and numbers beyond the float range, naming the field. */
static int check_value(const char *path, int line, const char *tok, double x, Error *err)
{
    if (!isfinite(x) || fabs(x) > FLT_MAX) {
        error_set(err, path, line, "'%.40s' is not a finite number", tok);
        return 0;
    }
    return 1;
}

static int add_pair(PairList *p, const char *path, int line, double lambda, double value, Error *err)
{
    if (p->n > 0 && !(lambda > p->lambda[p->n - 1])) {
        error_set(err, path, line, "wavelengths must increase strictly (%g nm after %g nm)",
                  lambda, p->lambda[p->n - 1]);
        return 0;
    }
    if (!pairs_push(p, lambda, value)) {
        error_set(err, path, line, "out of memory");
        return 0;
    }
    return 1;
}

int spec_from_file(Spectrum *s, const char *path, Error *err)
{
    PairList p = { NULL, NULL, 0, 0 };
    size_t len = 0;
    ReadStatus rs;
    char *text, *line, *next;
    int line_no = 0, csv, seen_content = 0, have_lambda = 0, lambda_line = 0, ok = 0, i;
    double pending_lambda = 0.0;
    float *fl = NULL, *fv = NULL;

    if (!path) { error_set(err, "(null)", 0, "no spectrum file name"); return 0; }
    errno = 0;
    text = read_whole_file(path, 1, NULL, &len, &rs);
    if (!text) {
        if (rs == READ_OPEN)
            error_set(err, path, 0, "cannot read spectrum file (%s)", strerror(errno));
        else
            error_set(err, path, 0, "%s", read_status_text(rs));
        return 0;
    }
    line = text;
    if ((unsigned char)line[0] == 0xEF && (unsigned char)line[1] == 0xBB &&
        (unsigned char)line[2] == 0xBF) line += 3;   /* UTF-8 byte order mark */
    csv = -1;                                     /* decided by the first data line */

    for (; line && *line; line = next) {          /* *line == 0: after the last newline */
        char *hash;
        line_no++;
        /* a line ends at LF, CR LF or a lone CR (old Mac files) */
        next = line + strcspn(line, "\r\n");
        if (*next == '\0') next = NULL;
        else if (next[0] == '\r' && next[1] == '\n') { *next = '\0'; next += 2; }
        else *next++ = '\0';
        if ((hash = strchr(line, '#')) != NULL) *hash = '\0';
        if (csv < 0) {
            const char *c = line;
            while (isspace((unsigned char)*c)) c++;
            if (!*c) continue;                        /* blank or comment-only line */
            csv = strchr(c, ',') != NULL;
        }

        if (csv) {
            /* one "wavelength,value" record per line */
            char *f0, *f1, *comma;
            double l, v;
            f0 = line;
            while (*f0 == ' ' || *f0 == '\t') f0++;
            if (!*f0) continue;                       /* blank line */
            comma = strchr(f0, ',');
            if (!comma) {
                error_set(err, path, line_no, "expected 'wavelength,value', found '%.40s'", f0);
                goto done;
            }
            *comma = '\0';
            f1 = trim_field(comma + 1);
            f0 = trim_field(f0);
            if (!seen_content && !parse_number(f0, &l)) {  /* header line */
                seen_content = 1;
                continue;
            }
            seen_content = 1;
            if (strchr(f1, ',')) {
                error_set(err, path, line_no, "expected 2 fields 'wavelength,value', found more");
                goto done;
            }
            if (!parse_number(f0, &l)) {
                error_set(err, path, line_no, "'%.40s' is not a number", f0);
                goto done;
            }
            if (!parse_number(f1, &v)) {
                error_set(err, path, line_no, "'%.40s' is not a number", *f1 ? f1 : "(empty)");
                goto done;
            }
            if (!check_value(path, line_no, f0, l, err) || !check_value(path, line_no, f1, v, err) ||
                !add_pair(&p, path, line_no, l, v, err)) goto done;
        } else {
            /* a free stream of numbers: lambda, value, lambda, value, ... */
            char *tok = line;
            for (;;) {
                char *end;
                double x;
                while (*tok == ' ' || *tok == '\t' || *tok == '\f' || *tok == '\v') tok++;
                if (!*tok) break;
                end = tok;
                while (*end && *end != ' ' && *end != '\t' && *end != '\f' && *end != '\v') end++;
                if (*end) *end++ = '\0';
                else end = tok + strlen(tok);
                if (!parse_number(tok, &x)) {
                    error_set(err, path, line_no, "'%.40s' is not a number", tok);
                    goto done;
                }
                if (!check_value(path, line_no, tok, x, err)) goto done;
                if (!have_lambda) { pending_lambda = x; lambda_line = line_no; have_lambda = 1; }
                else {
                    if (!add_pair(&p, path, lambda_line, pending_lambda, x, err)) goto done;
                    have_lambda = 0;
                }
                tok = end;
            }
        }
    }
    if (have_lambda) {
        error_set(err, path, lambda_line, "odd number of values: wavelength %g has no value",
                  pending_lambda);
        goto done;
    }
    if (p.n == 0) {
        error_set(err, path, line_no > 0 ? line_no : 1, "no (wavelength, value) pairs in the file");
        goto done;
    }
    fl = (float *)malloc((size_t)p.n * sizeof *fl);
    fv = (float *)malloc((size_t)p.n * sizeof *fv);
    if (!fl || !fv) { error_set(err, path, 0, "out of memory"); goto done; }
    for (i = 0; i < p.n; i++) { fl[i] = (float)p.lambda[i]; fv[i] = (float)p.value[i]; }
    for (i = 1; i < p.n; i++)
        if (!(fl[i] > fl[i - 1])) {                 /* distinct doubles, equal floats */
            error_set(err, path, 0, "wavelengths %.9g and %.9g are too close", p.lambda[i - 1], p.lambda[i]);
            goto done;
        }
    ok = spec_from_pairs(s, fl, fv, p.n, err, path, 0);
done:
    free(fl); free(fv);
    free(p.lambda); free(p.value);
    free(text);
    return ok;
}
