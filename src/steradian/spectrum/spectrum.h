#pragma once
/// Spectral distributions as a std::variant of plain structs (see ARCHITECTURE.md §2).
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

/// Integral of a(l) b(l) over the integer wavelengths 360..830 nm (1 nm steps).
Float inner_product(const Spectrum& a, const Spectrum& b);
/// XYZ of an emission spectrum: integral of s * {xbar, ybar, zbar} / kCieYIntegral.
Xyz spectrum_to_xyz(const Spectrum& s);
/// pbrt-v4's SpectrumToPhotometric: the inner product of s with ybar (for an
/// RgbIlluminantSpectrum, of its illuminant alone). Not divided by kCieYIntegral.
Float spectrum_to_photometric(const Spectrum& s);

// ---- RGB uplift (sRGB colour space, D65) ------------------------------------------------
/// RGB reflectance in [0,1]^3 -> bounded spectrum. Throws sr::Error if out of range.
RgbAlbedoSpectrum rgb_albedo_spectrum(Rgb rgb);
RgbUnboundedSpectrum rgb_unbounded_spectrum(Rgb rgb);
RgbIlluminantSpectrum rgb_illuminant_spectrum(Rgb rgb);

// ---- named spectra ------------------------------------------------------------------------
/// pbrt-v4's named spectra ("stdillum-D65", "metal-Au-eta", "glass-BK7", ...), or empty.
std::optional<Spectrum> named_spectrum(std::string_view name);
/// All names named_spectrum knows (for error messages and docs).
std::vector<std::string> named_spectrum_names();
/// The sRGB colour space's illuminant (CIE D65, normalised to Y = 1).
const DenselySampledSpectrum& srgb_illuminant();

}  // namespace sr
