#pragma once
/// Spectral distributions as a std::variant of plain structs (see docs/architecture.md, "Dispatch").
/// Wavelengths in nm. Reflectances are unitless; emission spectra are in the scene's
/// radiance unit per nm (see docs/units.md).
#include <concepts>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "steradian/spectrum/color.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

struct ConstantSpectrum {
    Float c = 0;
    Float operator()(Float) const { return c; }
    Float max_value() const { return c; }
};

/// Values at every integer wavelength in [kLambdaMin, kLambdaMax], linearly interpolated.
/// Values are shared (immutable), so copies are cheap.
struct DenselySampledSpectrum {
    std::shared_ptr<const std::vector<Float>> values;  ///< size kLambdaMax - kLambdaMin + 1
    Float operator()(Float lambda) const;
    Float max_value() const;
};

/// Piecewise-linear through (lambda, value) pairs, zero outside the given range.
struct PiecewiseLinearSpectrum {
    std::shared_ptr<const std::vector<Float>> lambdas, values;
    Float operator()(Float lambda) const;
    Float max_value() const;
};

/// Planck's law at temperature T, normalised to a maximum of 1 (pbrt-v4 semantics).
struct BlackbodySpectrum {
    Float temperature = 6500;
    Float normalization = 1;  ///< 1 / B(lambda_max(T), T) by Wien's displacement law
    explicit BlackbodySpectrum(Float T = 6500);
    Float operator()(Float lambda) const;
    Float max_value() const { return 1; }
};

/// Reflectance uplifted from RGB: s(l) = sigmoid(c0 l^2 + c1 l + c2) (Jakob & Hanika 2019,
/// "A Low-Dimensional Function Space for Efficient Spectral Upsampling"), in [0, 1].
struct RgbAlbedoSpectrum {
    Float c0 = 0, c1 = 0, c2 = 0;
    Float operator()(Float lambda) const;
    Float max_value() const;
};

/// Unbounded RGB (e.g. scattering coefficients): scale * sigmoid polynomial.
struct RgbUnboundedSpectrum {
    Float scale = 1, c0 = 0, c1 = 0, c2 = 0;
    Float operator()(Float lambda) const;
    Float max_value() const;
};

/// Illuminant RGB: scale * sigmoid polynomial * the colour space's standard illuminant
/// (D65 for sRGB), as pbrt-v4's RGBIlluminantSpectrum.
struct RgbIlluminantSpectrum {
    Float scale = 1, c0 = 0, c1 = 0, c2 = 0;
    DenselySampledSpectrum illuminant;
    Float operator()(Float lambda) const;
    Float max_value() const;
};

template <typename S>
concept SpectrumLike = requires(const S& s, Float lambda) {
    { s(lambda) } -> std::convertible_to<Float>;
    { s.max_value() } -> std::convertible_to<Float>;
};
static_assert(SpectrumLike<ConstantSpectrum>);
static_assert(SpectrumLike<DenselySampledSpectrum>);
static_assert(SpectrumLike<PiecewiseLinearSpectrum>);
static_assert(SpectrumLike<BlackbodySpectrum>);
static_assert(SpectrumLike<RgbAlbedoSpectrum>);
static_assert(SpectrumLike<RgbUnboundedSpectrum>);
static_assert(SpectrumLike<RgbIlluminantSpectrum>);

class Spectrum {
public:
    using Variant = std::variant<ConstantSpectrum, DenselySampledSpectrum, PiecewiseLinearSpectrum,
                                 BlackbodySpectrum, RgbAlbedoSpectrum, RgbUnboundedSpectrum,
                                 RgbIlluminantSpectrum>;
    Spectrum() : m_v(ConstantSpectrum{0}) {}
    template <typename S>
        requires SpectrumLike<S>
    Spectrum(S s) : m_v(std::move(s)) {}

    /// Value at wavelength lambda (nm).
    Float operator()(Float lambda) const;
    /// Values at the path's wavelengths.
    SampledSpectrum sample(const SampledWavelengths& lambda) const;
    /// An upper bound of the spectrum over [kLambdaMin, kLambdaMax].
    Float max_value() const;
    const Variant& variant() const { return m_v; }
    template <typename S>
    const S* get_if() const { return std::get_if<S>(&m_v); }

private:
    Variant m_v;
};

/// Resamples any spectrum at every nm in [kLambdaMin, kLambdaMax] for O(1) evaluation.
DenselySampledSpectrum densely_sampled(const Spectrum& s);
/// From interleaved (lambda, value) pairs; lambdas must increase strictly.
/// If normalize, scaled so that its CIE Y (integral of s * ybar / kCieYIntegral) is 1, as
/// pbrt-v4 normalises its named illuminants.
PiecewiseLinearSpectrum piecewise_linear_from_interleaved(const std::vector<Float>& pairs,
                                                          bool normalize);

// ---- CIE 1931 2-degree colour matching functions --------------------------------------
/// The integral of ybar over wavelength in nm (1 nm sums over 360..830).
inline constexpr Float kCieYIntegral = 106.856895f;
const DenselySampledSpectrum& cie_x();
const DenselySampledSpectrum& cie_y();
const DenselySampledSpectrum& cie_z();
/// CIE 1951 scotopic luminous efficiency function V'(lambda) (CIE 018:2019, ISO 23539 / CIE
/// S 010), 1 at 507 nm, tabulated at 1 nm over 380..780 nm. Zero at integer wavelengths
/// outside the table (the dense representation ramps linearly over the 1 nm next to each
/// end, as for the colour matching functions).
const DenselySampledSpectrum& cie_scotopic_v();
/// Maximum luminous efficacy for photopic vision, K_m in lm/W, applied to V(lambda) = ybar.
/// The SI defines the candela through K_cd = 683 lm/W for monochromatic radiation of
/// 540e12 Hz (555.016 nm in standard air), where V = 0.999998, so K_m = 683.002 lm/W, which
/// CIE S 017:2020 "ILV" and CIE 018:2019 "The basis of physical photometry" take as 683.
inline constexpr double kKmPhotopic = 683.0;
/// Maximum luminous efficacy for scotopic vision, K'_m in lm/W, applied to V'(lambda): from
/// the same SI definition, K'_m = 683 / V'(555.016 nm) = 683 / 0.40175 = 1700.06 lm/W,
/// which CIE S 017 / CIE 018 give as 1700 lm/W.
inline constexpr double kKmScotopic = 1700.0;

/// Integral of a(l) b(l) over the integer wavelengths 360..830 nm (1 nm steps).
Float inner_product(const Spectrum& a, const Spectrum& b);
/// XYZ of an emission spectrum: integral of s * {xbar, ybar, zbar} / kCieYIntegral.
Xyz spectrum_to_xyz(const Spectrum& s);
/// pbrt-v4's SpectrumToPhotometric: the inner product of s with ybar (for an
/// RgbIlluminantSpectrum, of its illuminant alone). Not divided by kCieYIntegral.
Float spectrum_to_photometric(const Spectrum& s);
/// XYZ of a reflectance r lit by an illuminant: integral of r * illum * {xbar, ybar, zbar}
/// divided by the integral of illum * ybar (so a perfect white reflector has Y = 1).
Xyz reflectance_to_xyz(const Spectrum& r, const Spectrum& illuminant);

// ---- Planck's law and CIE illuminants ------------------------------------------------------
/// Spectral radiance of a blackbody (Planck's law) in W m^-2 sr^-1 m^-1, at wavelength
/// lambda_nm (nm) and temperature_k (K); 0 for a non-positive temperature or wavelength.
/// Constants as pbrt-v4: c = 299792458 m/s, h = 6.62606957e-34 J s, kb = 1.3806488e-23 J/K.
double planck(double lambda_nm, double temperature_k);
/// Wien's displacement constant b (m K): the peak of Planck's law is at b / T.
inline constexpr double kWienDisplacement = 2.8977721e-3;
/// CIE daylight illuminant D for a correlated colour temperature in K (4000..25000), from
/// the S0, S1, S2 basis (CIE 015:2018), relative: 100 at 560 nm, 300..830 nm. Throws
/// sr::Error outside the range. (D65 is cct = 6500 * 1.4388 / 1.4380 = 6504 K; the
/// tabulated "stdillum-D65" is the official table.)
PiecewiseLinearSpectrum cie_daylight(Float cct);
/// pbrt-v4's Spectra::D(T) (used for "whitebalance"): CIE daylight for the nominal
/// temperature T in K, i.e. at cct = T * 1.4388 / 1.4380 (so 6500 gives D65 and 5000 gives
/// D50); a blackbody below 4000 K, where daylight is undefined; extrapolated above 25000 K.
/// Relative units (not normalised); zero for T <= 0.
Spectrum cie_d_illuminant(Float temperature);

// ---- RGB uplift (sRGB colour space, D65) ------------------------------------------------
// Solved per colour at load time (Gauss-Newton with continuation in CIELAB, Jakob & Hanika
// 2019) and cached (up to 65536 colours); thread-safe. About 0.1 ms per new colour (at most
// ~0.5 ms); behind a mutex, so meant for load time, not per shading point.
/// RGB reflectance in [0,1]^3 -> bounded spectrum. Throws sr::Error if out of range.
RgbAlbedoSpectrum rgb_albedo_spectrum(Rgb rgb);
/// Non-negative RGB -> scale * bounded spectrum with scale = 2 max(r, g, b) (pbrt-v4).
/// Throws sr::Error for a negative or non-finite component.
RgbUnboundedSpectrum rgb_unbounded_spectrum(Rgb rgb);
/// As rgb_unbounded_spectrum, times srgb_illuminant(): an emission spectrum whose colour
/// under the sRGB white is rgb.
RgbIlluminantSpectrum rgb_illuminant_spectrum(Rgb rgb);

// Table-based variants for colours that change per shading point (image textures): the
// Jakob & Hanika coefficient table (64^3 per largest channel, built by the same solver on
// first use, a few seconds once), trilinearly interpolated: O(1), lock-free,
// allocation-free. Round-trip error is larger than the exact path's (mean ~5e-4, max ~3e-3
// in linear sRGB, worst near white). Inputs are clamped (albedo to [0, 1], the others to
// >= 0) instead of throwing; NaN gives black.
/// Builds the table now (e.g. at scene load when image textures exist) rather than on the
/// first *_interpolated call. Idempotent and thread-safe.
void build_rgb_uplift_table();
RgbAlbedoSpectrum rgb_albedo_spectrum_interpolated(Rgb rgb);
RgbUnboundedSpectrum rgb_unbounded_spectrum_interpolated(Rgb rgb);
RgbIlluminantSpectrum rgb_illuminant_spectrum_interpolated(Rgb rgb);

// ---- named spectra ------------------------------------------------------------------------
/// pbrt-v4's named spectra ("stdillum-D65", "metal-Au-eta", "glass-BK7", ...), plus the
/// CIE 015:2018 LED and high-pressure lamp illuminants ("stdillum-LED-B1".."stdillum-LED-B5",
/// "stdillum-LED-BH1", "stdillum-LED-RGB1", "stdillum-LED-V1", "stdillum-LED-V2",
/// "stdillum-HP1".."stdillum-HP5"), or empty.
/// Returned as DenselySampledSpectrum (O(1) evaluation, zero outside 360..830 nm; the zero
/// k of the transparent oxides MgO and TiO2 as ConstantSpectrum);
/// illuminants are normalised to Y = 1, eta / k are not. Built once, thread-safe.
std::optional<Spectrum> named_spectrum(std::string_view name);
/// All names named_spectrum knows (for error messages and docs).
std::vector<std::string> named_spectrum_names();
/// The sRGB colour space's illuminant (CIE D65, normalised to Y = 1).
const DenselySampledSpectrum& srgb_illuminant();

}  // namespace sr
