/// pbrt-v4's named spectra: CIE standard illuminants, optical glasses (Sellmeier equations)
/// and measured metal / oxide optical constants. Every table cites its source.
#include <cmath>
#include <functional>
#include <map>

#include "steradian/core/error.h"
#include "steradian/spectrum/camera_sensors.h"
#include "steradian/spectrum/cie_data.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

namespace {

// ---- illuminants ------------------------------------------------------------------------------

/// Relative SPD from a regularly spaced table, as interleaved (lambda, value) pairs.
std::vector<Float> regular_pairs(const float* values, int count, int first_nm, int step_nm) {
    std::vector<Float> pairs;
    pairs.reserve(2 * size_t(count));
    for (int i = 0; i < count; ++i) {
        pairs.push_back(Float(first_nm + i * step_nm));
        pairs.push_back(values[i]);
    }
    return pairs;
}

/// CIE daylight from the S0, S1, S2 basis with the given weights (CIE 015:2018 eq. for
/// S(l) = S0(l) + M1 S1(l) + M2 S2(l)), as (lambda, value) pairs at 10 nm, 300..830 nm.
std::vector<Float> daylight_pairs(double m1, double m2) {
    std::vector<Float> pairs;
    pairs.reserve(2 * cie::kDaylightCount);
    for (int i = 0; i < cie::kDaylightCount; ++i) {
        pairs.push_back(Float(cie::kDaylightFirstNm + i * cie::kDaylightStepNm));
        pairs.push_back(Float(cie::kS0[i] + m1 * cie::kS1[i] + m2 * cie::kS2[i]));
    }
    return pairs;
}

/// Chromaticity x of CIE daylight at correlated colour temperature cct (K), 4000..25000 K
/// (CIE 015:2018, eq. for x_D).
double daylight_x(double cct) {
    double t = cct, t2 = t * t, t3 = t2 * t;
    if (cct <= 7000) return -4.6070e9 / t3 + 2.9678e6 / t2 + 0.09911e3 / t + 0.244063;
    return -2.0064e9 / t3 + 1.9018e6 / t2 + 0.24748e3 / t + 0.23704;
}

/// The weights M1, M2 of S1, S2 for daylight of chromaticity (x, y) (CIE 015:2018).
void daylight_weights(double x, double y, double& m1, double& m2) {
    double m = 0.0241 + 0.2562 * x - 0.7341 * y;
    m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
}

/// CIE standard illuminant A by its defining formula (CIE 015:2018 / ISO/CIE 11664-2):
/// S_A(l) = 100 (560/l)^5 (exp(c2 / (T 560)) - 1) / (exp(c2 / (T l)) - 1), l in nm, with
/// c2 = 1.435e7 nm K and T = 2848 K (the historical 2856 K on the c2 = 1.438e-2 m K scale).
std::vector<Float> illuminant_a_pairs() {
    constexpr double c2 = 1.435e7, t = 2848;
    std::vector<Float> pairs;
    for (int l = 300; l <= 830; ++l) {
        double v =
            100 * std::pow(560.0 / l, 5) * std::expm1(c2 / (t * 560)) / std::expm1(c2 / (t * l));
        pairs.push_back(Float(l));
        pairs.push_back(Float(v));
    }
    return pairs;
}

Spectrum normalized_illuminant(const std::vector<Float>& pairs) {
    return densely_sampled(Spectrum(piecewise_linear_from_interleaved(pairs, true)));
}

// ---- glasses: Sellmeier equation ----------------------------------------------------------------

/// n^2(l) = 1 + sum_i B_i l^2 / (l^2 - C_i), l in micrometres (C_i in um^2).
struct Sellmeier {
    double b[3], c[3];
    double operator()(double lambda_nm) const {
        double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
        double n2 = 1;
        for (int i = 0; i < 3; ++i) n2 += b[i] * l2 / (l2 - c[i]);
        return std::sqrt(n2);
    }
};

// Sellmeier coefficients from the SCHOTT optical glass catalogue (Zemax AGF
// schott_2017-01-20b, as published by refractiveindex.info, CC0). pbrt-v4's "glass-F5",
// "-F10", "-F11" are the dense flints SF5, (N-)SF10 and (N-)SF11.
constexpr Sellmeier kNBk7{{1.03961212, 0.231792344, 1.01046945},
                          {0.00600069867, 0.0200179144, 103.560653}};  // nd = 1.5168
constexpr Sellmeier kNBaf10{{1.5851495, 0.143559385, 1.08521269},
                            {0.00926681282, 0.0424489805, 105.613573}};  // nd = 1.67003
constexpr Sellmeier kNFk51a{{0.971247817, 0.216901417, 0.904651666},
                            {0.00472301995, 0.0153575612, 168.68133}};  // nd = 1.48656
constexpr Sellmeier kNLasf9{{2.00029547, 0.298926886, 1.80691843},
                            {0.0121426017, 0.0538736236, 156.530829}};  // nd = 1.85025
constexpr Sellmeier kSf5{{1.46141885, 0.247713019, 0.949995832},
                         {0.0111826126, 0.0508594669, 112.041888}};  // nd = 1.6727
constexpr Sellmeier kNSf10{{1.62153902, 0.256287842, 1.64447552},
                           {0.0122241457, 0.0595736775, 147.468793}};  // nd = 1.72828
constexpr Sellmeier kNSf11{{1.73759695, 0.313747346, 1.89878101},
                           {0.013188707, 0.0623068142, 155.23629}};  // nd = 1.78472

/// Samples f at every nm of [kLambdaMin, kLambdaMax].
Spectrum dense_from_function(const std::function<double(double)>& f) {
    auto v = std::make_shared<std::vector<Float>>();
    for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l) v->push_back(Float(f(l)));
    return DenselySampledSpectrum{std::move(v)};
}

// ---- metals and oxides: measured optical constants ---------------------------------------------

/// One measurement: wavelength in micrometres, refractive index n and extinction k.
struct Nk {
    double lambda_um, n, k;
};

/// One measurement: wavelength in nanometres, refractive index n and extinction k.
struct NkNm {
    double lambda_nm, n, k;
};

// The tables pbrt-v4 ships as Ag_eta/Ag_k, Al_eta/Al_k, Au_eta/Au_k and Cu_eta/Cu_k
// (src/pbrt/util/spectrum.cpp, which cites no source for them), value for value: 56 samples
// on a 0.05 eV grid from 4.15 eV (298.76 nm) to 1.40 eV (885.60 nm), linearly interpolated
// in wavelength. Mitsuba's manual (conductor plugin) states that its metal data are
// identical to those distributed with PBRT and come from the Luxpop database
// (www.luxpop.com), based on E. D. Palik (ed.), "Handbook of Optical Constants of Solids"
// (Academic Press, 1998) and on atomic scattering factors measured by the Center for X-Ray
// Optics (CXRO, LBNL) and LLNL. Kept identical to pbrt-v4 so that scenes naming
// "metal-X-eta"/"metal-X-k" render as in pbrt-v4: Johnson & Christy (1972, Ag/Au/Cu) and
// Rakic (1995, Al), used here before, differ by -3.5 % (Au), +2.5 % (Ag), -2.5 % (Cu) and
// -0.6 % (Al) in luminance-weighted normal-incidence reflectance under a warm light.
constexpr NkNm kAgPbrt[] = {
    {298.757050, 1.519000, 1.080000}, {302.400421, 1.496000, 0.882000},
    {306.133759, 1.432500, 0.761063}, {309.960449, 1.323000, 0.647000},
    {313.884003, 1.142062, 0.550875}, {317.908142, 0.932000, 0.504000},
    {322.036835, 0.719062, 0.554375}, {326.274139, 0.526000, 0.663000},
    {330.624481, 0.388125, 0.818563}, {335.092377, 0.294000, 0.986000},
    {339.682678, 0.253313, 1.120687}, {344.400482, 0.238000, 1.240000},
    {349.251221, 0.221438, 1.345250}, {354.240509, 0.209000, 1.440000},
    {359.374420, 0.194813, 1.533750}, {364.659332, 0.186000, 1.610000},
    {370.102020, 0.192063, 1.641875}, {375.709625, 0.200000, 1.670000},
    {381.489777, 0.198063, 1.735000}, {387.450562, 0.192000, 1.810000},
    {393.600555, 0.182000, 1.878750}, {399.948975, 0.173000, 1.950000},
    {406.505493, 0.172625, 2.029375}, {413.280579, 0.173000, 2.110000},
    {420.285339, 0.166688, 2.186250}, {427.531647, 0.160000, 2.260000},
    {435.032196, 0.158500, 2.329375}, {442.800629, 0.157000, 2.400000},
    {450.851562, 0.151063, 2.478750}, {459.200653, 0.144000, 2.560000},
    {467.864838, 0.137313, 2.640000}, {476.862213, 0.132000, 2.720000},
    {486.212463, 0.130250, 2.798125}, {495.936707, 0.130000, 2.880000},
    {506.057861, 0.129938, 2.973750}, {516.600769, 0.130000, 3.070000},
    {527.592224, 0.130063, 3.159375}, {539.061646, 0.129000, 3.250000},
    {551.040771, 0.124375, 3.348125}, {563.564453, 0.120000, 3.450000},
    {576.670593, 0.119313, 3.553750}, {590.400818, 0.121000, 3.660000},
    {604.800842, 0.125500, 3.766250}, {619.920898, 0.131000, 3.880000},
    {635.816284, 0.136125, 4.010625}, {652.548279, 0.140000, 4.150000},
    {670.184753, 0.140063, 4.293125}, {688.800964, 0.140000, 4.440000},
    {708.481018, 0.144313, 4.586250}, {729.318665, 0.148000, 4.740000},
    {751.419250, 0.145875, 4.908125}, {774.901123, 0.143000, 5.090000},
    {799.897949, 0.142563, 5.288750}, {826.561157, 0.145000, 5.500000},
    {855.063293, 0.151938, 5.720624}, {885.601257, 0.163000, 5.950000},
};
constexpr NkNm kAlPbrt[] = {
    {298.757050, 0.273375, 3.593750}, {302.400421, 0.280000, 3.640000},
    {306.133759, 0.286813, 3.689375}, {309.960449, 0.294000, 3.740000},
    {313.884003, 0.301875, 3.789375}, {317.908142, 0.310000, 3.840000},
    {322.036835, 0.317875, 3.894375}, {326.274139, 0.326000, 3.950000},
    {330.624481, 0.334750, 4.005000}, {335.092377, 0.344000, 4.060000},
    {339.682678, 0.353813, 4.113750}, {344.400482, 0.364000, 4.170000},
    {349.251221, 0.374375, 4.233750}, {354.240509, 0.385000, 4.300000},
    {359.374420, 0.395750, 4.365000}, {364.659332, 0.407000, 4.430000},
    {370.102020, 0.419125, 4.493750}, {375.709625, 0.432000, 4.560000},
    {381.489777, 0.445688, 4.633750}, {387.450562, 0.460000, 4.710000},
    {393.600555, 0.474688, 4.784375}, {399.948975, 0.490000, 4.860000},
    {406.505493, 0.506188, 4.938125}, {413.280579, 0.523000, 5.020000},
    {420.285339, 0.540063, 5.108750}, {427.531647, 0.558000, 5.200000},
    {435.032196, 0.577313, 5.290000}, {442.800629, 0.598000, 5.380000},
    {450.851562, 0.620313, 5.480000}, {459.200653, 0.644000, 5.580000},
    {467.864838, 0.668625, 5.690000}, {476.862213, 0.695000, 5.800000},
    {486.212463, 0.723750, 5.915000}, {495.936707, 0.755000, 6.030000},
    {506.057861, 0.789000, 6.150000}, {516.600769, 0.826000, 6.280000},
    {527.592224, 0.867000, 6.420000}, {539.061646, 0.912000, 6.550000},
    {551.040771, 0.963000, 6.700000}, {563.564453, 1.020000, 6.850000},
    {576.670593, 1.080000, 7.000000}, {590.400818, 1.150000, 7.150000},
    {604.800842, 1.220000, 7.310000}, {619.920898, 1.300000, 7.480000},
    {635.816284, 1.390000, 7.650000}, {652.548279, 1.490000, 7.820000},
    {670.184753, 1.600000, 8.010000}, {688.800964, 1.740000, 8.210000},
    {708.481018, 1.910000, 8.390000}, {729.318665, 2.140000, 8.570000},
    {751.419250, 2.410000, 8.620000}, {774.901123, 2.630000, 8.600000},
    {799.897949, 2.800000, 8.450000}, {826.561157, 2.740000, 8.310000},
    {855.063293, 2.580000, 8.210000}, {885.601257, 2.240000, 8.210000},
};
constexpr NkNm kAuPbrt[] = {
    {298.757050, 1.795000, 1.920375}, {302.400421, 1.812000, 1.920000},
    {306.133759, 1.822625, 1.918875}, {309.960449, 1.830000, 1.916000},
    {313.884003, 1.837125, 1.911375}, {317.908142, 1.840000, 1.904000},
    {322.036835, 1.834250, 1.891375}, {326.274139, 1.824000, 1.878000},
    {330.624481, 1.812000, 1.868250}, {335.092377, 1.798000, 1.860000},
    {339.682678, 1.782000, 1.851750}, {344.400482, 1.766000, 1.846000},
    {349.251221, 1.752500, 1.845250}, {354.240509, 1.740000, 1.848000},
    {359.374420, 1.727625, 1.852375}, {364.659332, 1.716000, 1.862000},
    {370.102020, 1.705875, 1.883000}, {375.709625, 1.696000, 1.906000},
    {381.489777, 1.684750, 1.922500}, {387.450562, 1.674000, 1.936000},
    {393.600555, 1.666000, 1.947750}, {399.948975, 1.658000, 1.956000},
    {406.505493, 1.647250, 1.959375}, {413.280579, 1.636000, 1.958000},
    {420.285339, 1.628000, 1.951375}, {427.531647, 1.616000, 1.940000},
    {435.032196, 1.596250, 1.924500}, {442.800629, 1.562000, 1.904000},
    {450.851562, 1.502125, 1.875875}, {459.200653, 1.426000, 1.846000},
    {467.864838, 1.345875, 1.814625}, {476.862213, 1.242000, 1.796000},
    {486.212463, 1.086750, 1.797375}, {495.936707, 0.916000, 1.840000},
    {506.057861, 0.754500, 1.956500}, {516.600769, 0.608000, 2.120000},
    {527.592224, 0.491750, 2.326250}, {539.061646, 0.402000, 2.540000},
    {551.040771, 0.345500, 2.730625}, {563.564453, 0.306000, 2.880000},
    {576.670593, 0.267625, 2.940625}, {590.400818, 0.236000, 2.970000},
    {604.800842, 0.212375, 3.015000}, {619.920898, 0.194000, 3.060000},
    {635.816284, 0.177750, 3.070000}, {652.548279, 0.166000, 3.150000},
    {670.184753, 0.161000, 3.445812}, {688.800964, 0.160000, 3.800000},
    {708.481018, 0.160875, 4.087687}, {729.318665, 0.164000, 4.357000},
    {751.419250, 0.169500, 4.610188}, {774.901123, 0.176000, 4.860000},
    {799.897949, 0.181375, 5.125813}, {826.561157, 0.188000, 5.390000},
    {855.063293, 0.198125, 5.631250}, {885.601257, 0.210000, 5.880000},
};
constexpr NkNm kCuPbrt[] = {
    {298.757050, 1.400313, 1.662125}, {302.400421, 1.380000, 1.687000},
    {306.133759, 1.358438, 1.703313}, {309.960449, 1.340000, 1.720000},
    {313.884003, 1.329063, 1.744563}, {317.908142, 1.325000, 1.770000},
    {322.036835, 1.332500, 1.791625}, {326.274139, 1.340000, 1.810000},
    {330.624481, 1.334375, 1.822125}, {335.092377, 1.325000, 1.834000},
    {339.682678, 1.317812, 1.851750}, {344.400482, 1.310000, 1.872000},
    {349.251221, 1.300313, 1.894250}, {354.240509, 1.290000, 1.916000},
    {359.374420, 1.281563, 1.931688}, {364.659332, 1.270000, 1.950000},
    {370.102020, 1.249062, 1.972438}, {375.709625, 1.225000, 2.015000},
    {381.489777, 1.200000, 2.121562}, {387.450562, 1.180000, 2.210000},
    {393.600555, 1.174375, 2.177188}, {399.948975, 1.175000, 2.130000},
    {406.505493, 1.177500, 2.160063}, {413.280579, 1.180000, 2.210000},
    {420.285339, 1.178125, 2.249938}, {427.531647, 1.175000, 2.289000},
    {435.032196, 1.172812, 2.326000}, {442.800629, 1.170000, 2.362000},
    {450.851562, 1.165312, 2.397625}, {459.200653, 1.160000, 2.433000},
    {467.864838, 1.155312, 2.469187}, {476.862213, 1.150000, 2.504000},
    {486.212463, 1.142812, 2.535875}, {495.936707, 1.135000, 2.564000},
    {506.057861, 1.131562, 2.589625}, {516.600769, 1.120000, 2.605000},
    {527.592224, 1.092437, 2.595562}, {539.061646, 1.040000, 2.583000},
    {551.040771, 0.950375, 2.576500}, {563.564453, 0.826000, 2.599000},
    {576.670593, 0.645875, 2.678062}, {590.400818, 0.468000, 2.809000},
    {604.800842, 0.351250, 3.010750}, {619.920898, 0.272000, 3.240000},
    {635.816284, 0.230813, 3.458187}, {652.548279, 0.214000, 3.670000},
    {670.184753, 0.209250, 3.863125}, {688.800964, 0.213000, 4.050000},
    {708.481018, 0.216250, 4.239563}, {729.318665, 0.223000, 4.430000},
    {751.419250, 0.236500, 4.619563}, {774.901123, 0.250000, 4.817000},
    {799.897949, 0.254188, 5.034125}, {826.561157, 0.260000, 5.260000},
    {855.063293, 0.280000, 5.485625}, {885.601257, 0.300000, 5.717000},
};

// Brass (70% Cu, 30% Zn): M. R. Querry, "Optical constants", Contractor Report
// CRDC-CR-85034 (1985); rows 0.34..0.85 um (refractiveindex.info, CC0).
constexpr Nk kCuZnQuerry[] = {
    {0.34, 1.494, 1.815}, {0.35, 1.504, 1.815}, {0.36, 1.503, 1.815}, {0.37, 1.497, 1.818},
    {0.38, 1.487, 1.818}, {0.39, 1.471, 1.813}, {0.40, 1.445, 1.805}, {0.41, 1.405, 1.794},
    {0.42, 1.350, 1.786}, {0.43, 1.278, 1.784}, {0.44, 1.191, 1.797}, {0.45, 1.094, 1.829},
    {0.46, 0.994, 1.883}, {0.47, 0.900, 1.957}, {0.48, 0.816, 2.046}, {0.49, 0.745, 2.145},
    {0.50, 0.686, 2.250}, {0.51, 0.639, 2.358}, {0.52, 0.602, 2.464}, {0.53, 0.573, 2.568},
    {0.54, 0.549, 2.668}, {0.55, 0.527, 2.765}, {0.56, 0.505, 2.860}, {0.57, 0.484, 2.958},
    {0.58, 0.468, 3.059}, {0.59, 0.460, 3.159}, {0.60, 0.450, 3.253}, {0.61, 0.452, 3.345},
    {0.62, 0.449, 3.434}, {0.63, 0.445, 3.522}, {0.64, 0.444, 3.609}, {0.65, 0.444, 3.695},
    {0.66, 0.445, 3.778}, {0.67, 0.444, 3.860}, {0.68, 0.444, 3.943}, {0.69, 0.445, 4.025},
    {0.70, 0.446, 4.106}, {0.71, 0.448, 4.186}, {0.72, 0.450, 4.266}, {0.73, 0.452, 4.346},
    {0.74, 0.455, 4.424}, {0.75, 0.457, 4.501}, {0.76, 0.458, 4.579}, {0.77, 0.460, 4.657},
    {0.78, 0.464, 4.737}, {0.79, 0.469, 4.814}, {0.80, 0.473, 4.890}, {0.81, 0.478, 4.965},
    {0.82, 0.481, 5.039}, {0.83, 0.483, 5.115}, {0.84, 0.486, 5.192}, {0.85, 0.490, 5.269},
};

/// MgO: R. E. Stephens and I. H. Malitson, "Index of refraction of magnesium oxide",
/// J. Res. Natl. Bur. Stand. 49, 249-252 (1952), 23.3 C, valid 0.36..5.4 um:
/// n^2 = 2.956362 + 0.02195770 / (l^2 - 0.01428322) - 0.01062387 l^2 - 2.04968e-5 l^4.
double mgo_index(double lambda_nm) {
    double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
    return std::sqrt(2.956362 + 0.02195770 / (l2 - 0.01428322) - 0.01062387 * l2 -
                     0.0000204968 * l2 * l2);
}

/// TiO2 (rutile), extraordinary ray: J. R. Devore, "Refractive indices of rutile and
/// sphalerite", J. Opt. Soc. Am. 41, 416-419 (1951), valid 0.43..1.53 um (extrapolated
/// below): n^2 = 7.197 + 0.3322 / (l^2 - 0.0843).
double tio2_index(double lambda_nm) {
    double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
    return std::sqrt(7.197 + 0.3322 / (l2 - 0.0843));
}

template <size_t N>
Spectrum nk_component(const Nk (&table)[N], bool extinction) {
    std::vector<Float> pairs;
    for (const Nk& m : table) {
        pairs.push_back(Float(m.lambda_um * 1000));
        pairs.push_back(Float(extinction ? m.k : m.n));
    }
    return densely_sampled(Spectrum(piecewise_linear_from_interleaved(pairs, false)));
}

template <size_t N>
Spectrum nk_component(const NkNm (&table)[N], bool extinction) {
    std::vector<Float> pairs;
    for (const NkNm& m : table) {
        pairs.push_back(Float(m.lambda_nm));
        pairs.push_back(Float(extinction ? m.k : m.n));
    }
    return densely_sampled(Spectrum(piecewise_linear_from_interleaved(pairs, false)));
}

using NamedMap = std::map<std::string, Spectrum, std::less<>>;

NamedMap build_named_spectra() {
    NamedMap m;
    // Illuminants, normalised to Y = 1 as pbrt-v4 does.
    m["stdillum-D65"] = normalized_illuminant(
        regular_pairs(cie::kD65, cie::kDaylightCount, cie::kDaylightFirstNm, cie::kDaylightStepNm));
    // D50: CIE daylight at 5000 K on the current c2 scale, 5000 * 1.4388 / 1.4380 K.
    m["stdillum-D50"] = normalized_illuminant([] {
        const PiecewiseLinearSpectrum d50 = cie_daylight(Float(5000 * 1.4388 / 1.4380));
        std::vector<Float> pairs;
        for (size_t i = 0; i < d50.lambdas->size(); ++i) {
            pairs.push_back((*d50.lambdas)[i]);
            pairs.push_back((*d50.values)[i]);
        }
        return pairs;
    }());
    m["stdillum-A"] = normalized_illuminant(illuminant_a_pairs());
    for (int i = 0; i < 12; ++i)
        m[fmt::format("stdillum-F{}", i + 1)] = normalized_illuminant(regular_pairs(
            cie::kF[i], cie::kFluorescentCount, cie::kFluorescentFirstNm, cie::kFluorescentStepNm));
    // CIE 015:2018 illuminants representing high-pressure discharge lamps and LED lamps
    // (not in pbrt-v4), normalised like F1..F12.
    for (int i = 0; i < cie::kHpIlluminants; ++i)
        m[fmt::format("stdillum-HP{}", i + 1)] = normalized_illuminant(
            regular_pairs(cie::kHp[i], cie::kHpCount, cie::kHpFirstNm, cie::kHpStepNm));
    {
        const char* const led_names[cie::kLedIlluminants] = {"LED-B1",   "LED-B2", "LED-B3",
                                                             "LED-B4",   "LED-B5", "LED-BH1",
                                                             "LED-RGB1", "LED-V1", "LED-V2"};
        for (int i = 0; i < cie::kLedIlluminants; ++i)
            m[fmt::format("stdillum-{}", led_names[i])] = normalized_illuminant(
                regular_pairs(cie::kLed[i], cie::kLedCount, cie::kLedFirstNm, cie::kLedStepNm));
    }
    // ACES "D60" (Academy TB-2014-004): CIE daylight from the S basis at exactly 6000 K,
    // chromaticity (0.32169, 0.33780), close to the ACES white point (0.32168, 0.33767).
    {
        double m1 = 0, m2 = 0, x = daylight_x(6000);
        daylight_weights(x, -3 * x * x + 2.870 * x - 0.275, m1, m2);
        m["illum-acesD60"] = normalized_illuminant(daylight_pairs(m1, m2));
    }

    // Glasses (index of refraction; k = 0).
    const std::pair<const char*, const Sellmeier*> glasses[] = {
        {"glass-BK7", &kNBk7},     {"glass-BAF10", &kNBaf10}, {"glass-FK51A", &kNFk51a},
        {"glass-LASF9", &kNLasf9}, {"glass-F5", &kSf5},       {"glass-SF5", &kSf5},
        {"glass-F10", &kNSf10},    {"glass-SF10", &kNSf10},   {"glass-F11", &kNSf11},
        {"glass-SF11", &kNSf11},
    };
    for (const auto& [name, s] : glasses) {
        const Sellmeier glass = *s;
        m[name] = dense_from_function([glass](double l) { return glass(l); });
    }

    // Metals: complex index of refraction eta + i k, not normalised.
    m["metal-Ag-eta"] = nk_component(kAgPbrt, false);
    m["metal-Ag-k"] = nk_component(kAgPbrt, true);
    m["metal-Au-eta"] = nk_component(kAuPbrt, false);
    m["metal-Au-k"] = nk_component(kAuPbrt, true);
    m["metal-Cu-eta"] = nk_component(kCuPbrt, false);
    m["metal-Cu-k"] = nk_component(kCuPbrt, true);
    m["metal-Al-eta"] = nk_component(kAlPbrt, false);
    m["metal-Al-k"] = nk_component(kAlPbrt, true);
    m["metal-CuZn-eta"] = nk_component(kCuZnQuerry, false);
    m["metal-CuZn-k"] = nk_component(kCuZnQuerry, true);
    // Transparent oxides that pbrt-v4 lists among its metals: k = 0 in the visible.
    m["metal-MgO-eta"] = dense_from_function(mgo_index);
    m["metal-MgO-k"] = ConstantSpectrum{0};
    m["metal-TiO2-eta"] = dense_from_function(tio2_index);
    m["metal-TiO2-k"] = ConstantSpectrum{0};
    // Camera sensitivities ("canon_eos_100d_r", ...), as pbrt-v4 names them (camera_sensors.h).
    for (const std::string& cam : camera_sensor_names()) {
        const auto curves = *camera_sensor_curves(cam);
        for (int c = 0; c < 3; ++c)
            m[cam + "_" + "rgb"[c]] = densely_sampled(Spectrum(curves[size_t(c)]));
    }
    return m;
}

const NamedMap& named_spectra() {
    static const NamedMap m = build_named_spectra();
    return m;
}

}  // namespace

namespace {

/// CIE daylight at correlated colour temperature cct (K), M1 and M2 rounded to three
/// decimals as CIE 015 does (this reproduces the official D65 table).
PiecewiseLinearSpectrum daylight(double cct) {
    double x = daylight_x(cct);
    double y = -3 * x * x + 2.870 * x - 0.275;
    double m1 = 0, m2 = 0;
    daylight_weights(x, y, m1, m2);
    m1 = std::round(m1 * 1000) / 1000;
    m2 = std::round(m2 * 1000) / 1000;
    return piecewise_linear_from_interleaved(daylight_pairs(m1, m2), false);
}

}  // namespace

PiecewiseLinearSpectrum cie_daylight(Float cct) {
    if (!(cct >= 4000 && cct <= 25000))
        throw Error(fmt::format(
            "CIE daylight is defined for correlated colour temperatures 4000..25000 K, not {} K",
            cct));
    return daylight(cct);
}

Spectrum cie_d_illuminant(Float temperature) {
    if (!(temperature > 0)) return ConstantSpectrum{0};
    // pbrt-v4's Spectra::D: the nominal temperature on the c2 = 1.4380e-2 m K scale of the
    // D-series names, converted to CCT on the current c2 = 1.4388e-2 m K scale (CIE 015).
    double cct = double(temperature) * 1.4388 / 1.4380;
    if (cct < 4000) return BlackbodySpectrum(Float(cct));  // daylight is undefined there
    return daylight(cct);
}

std::optional<Spectrum> named_spectrum(std::string_view name) {
    const NamedMap& m = named_spectra();
    auto it = m.find(name);
    if (it == m.end()) return std::nullopt;
    return it->second;
}

std::vector<std::string> named_spectrum_names() {
    std::vector<std::string> names;
    for (const auto& [name, s] : named_spectra()) names.push_back(name);
    return names;
}

const DenselySampledSpectrum& srgb_illuminant() {
    static const DenselySampledSpectrum d65 =
        densely_sampled(Spectrum(piecewise_linear_from_interleaved(
            regular_pairs(cie::kD65, cie::kDaylightCount, cie::kDaylightFirstNm,
                          cie::kDaylightStepNm),
            true)));
    return d65;
}

}  // namespace sr
