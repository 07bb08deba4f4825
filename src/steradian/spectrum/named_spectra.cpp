/// pbrt-v4's named spectra: CIE standard illuminants, optical glasses (Sellmeier equations)
/// and measured metal / oxide optical constants. Every table cites its source.
#include <cmath>
#include <functional>
#include <map>

#include "steradian/core/error.h"
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

// P. B. Johnson and R. W. Christy, "Optical constants of the noble metals", Phys. Rev. B 6,
// 4370-4379 (1972), room temperature; the rows from 0.29 to 0.98 um (data as tabulated by
// refractiveindex.info, CC0).
constexpr Nk kAgJohnsonChristy[] = {
    {0.2924, 1.39, 1.161}, {0.3009, 1.34, 0.964}, {0.3107, 1.13, 0.616}, {0.3204, 0.81, 0.392},
    {0.3315, 0.17, 0.829}, {0.3425, 0.14, 1.142}, {0.3542, 0.10, 1.419}, {0.3679, 0.07, 1.657},
    {0.3815, 0.05, 1.864}, {0.3974, 0.05, 2.070}, {0.4133, 0.05, 2.275}, {0.4305, 0.04, 2.462},
    {0.4509, 0.04, 2.657}, {0.4714, 0.05, 2.869}, {0.4959, 0.05, 3.093}, {0.5209, 0.05, 3.324},
    {0.5486, 0.06, 3.586}, {0.5821, 0.05, 3.858}, {0.6168, 0.06, 4.152}, {0.6595, 0.05, 4.483},
    {0.7045, 0.04, 4.838}, {0.7560, 0.03, 5.242}, {0.8211, 0.04, 5.727}, {0.8920, 0.04, 6.312},
    {0.9840, 0.04, 6.992},
};
constexpr Nk kAuJohnsonChristy[] = {
    {0.2924, 1.49, 1.878}, {0.3009, 1.53, 1.889}, {0.3107, 1.53, 1.893}, {0.3204, 1.54, 1.898},
    {0.3315, 1.48, 1.883}, {0.3425, 1.48, 1.871}, {0.3542, 1.50, 1.866}, {0.3679, 1.48, 1.895},
    {0.3815, 1.46, 1.933}, {0.3974, 1.47, 1.952}, {0.4133, 1.46, 1.958}, {0.4305, 1.45, 1.948},
    {0.4509, 1.38, 1.914}, {0.4714, 1.31, 1.849}, {0.4959, 1.04, 1.833}, {0.5209, 0.62, 2.081},
    {0.5486, 0.43, 2.455}, {0.5821, 0.29, 2.863}, {0.6168, 0.21, 3.272}, {0.6595, 0.14, 3.697},
    {0.7045, 0.13, 4.103}, {0.7560, 0.14, 4.542}, {0.8211, 0.16, 5.083}, {0.8920, 0.17, 5.663},
    {0.9840, 0.22, 6.350},
};
constexpr Nk kCuJohnsonChristy[] = {
    {0.2924, 1.42, 1.633}, {0.3009, 1.40, 1.679}, {0.3107, 1.38, 1.729}, {0.3204, 1.38, 1.783},
    {0.3315, 1.34, 1.821}, {0.3425, 1.36, 1.864}, {0.3542, 1.37, 1.916}, {0.3679, 1.36, 1.975},
    {0.3815, 1.33, 2.045}, {0.3974, 1.32, 2.116}, {0.4133, 1.28, 2.207}, {0.4305, 1.25, 2.305},
    {0.4509, 1.24, 2.397}, {0.4714, 1.25, 2.483}, {0.4959, 1.22, 2.564}, {0.5209, 1.18, 2.608},
    {0.5486, 1.02, 2.577}, {0.5821, 0.70, 2.704}, {0.6168, 0.30, 3.205}, {0.6595, 0.22, 3.747},
    {0.7045, 0.21, 4.205}, {0.7560, 0.24, 4.665}, {0.8211, 0.26, 5.180}, {0.8920, 0.30, 5.768},
    {0.9840, 0.32, 6.421},
};

// A. D. Rakic, "Algorithm for the determination of intrinsic optical constants of metal
// films: application to aluminum", Appl. Opt. 34, 4755-4767 (1995); rows 0.25..0.91 um
// (refractiveindex.info, CC0).
constexpr Nk kAlRakic[] = {
    {0.24797, 0.18137, 2.9029}, {0.30996, 0.28003, 3.7081}, {0.32628, 0.31474, 3.9165},
    {0.36466, 0.39877, 4.3957}, {0.41328, 0.52135, 5.0008}, {0.44280, 0.60790, 5.3676},
    {0.47687, 0.72780, 5.7781}, {0.51660, 0.87340, 6.2418}, {0.56357, 1.0728, 6.7839},
    {0.61993, 1.3660, 7.4052},  {0.65225, 1.5724, 7.7354},  {0.68881, 1.8301, 8.0601},
    {0.72932, 2.1606, 8.3565},  {0.77491, 2.6154, 8.4914},  {0.79478, 2.7675, 8.3866},
    {0.81569, 2.7668, 8.2573},  {0.83774, 2.6945, 8.1878},  {0.88561, 2.2802, 8.1134},
    {0.91166, 1.9739, 8.3058},
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
    m["metal-Ag-eta"] = nk_component(kAgJohnsonChristy, false);
    m["metal-Ag-k"] = nk_component(kAgJohnsonChristy, true);
    m["metal-Au-eta"] = nk_component(kAuJohnsonChristy, false);
    m["metal-Au-k"] = nk_component(kAuJohnsonChristy, true);
    m["metal-Cu-eta"] = nk_component(kCuJohnsonChristy, false);
    m["metal-Cu-k"] = nk_component(kCuJohnsonChristy, true);
    m["metal-Al-eta"] = nk_component(kAlRakic, false);
    m["metal-Al-k"] = nk_component(kAlRakic, true);
    m["metal-CuZn-eta"] = nk_component(kCuZnQuerry, false);
    m["metal-CuZn-k"] = nk_component(kCuZnQuerry, true);
    // Transparent oxides that pbrt-v4 lists among its metals: k = 0 in the visible.
    m["metal-MgO-eta"] = dense_from_function(mgo_index);
    m["metal-MgO-k"] = ConstantSpectrum{0};
    m["metal-TiO2-eta"] = dense_from_function(tio2_index);
    m["metal-TiO2-k"] = ConstantSpectrum{0};
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
