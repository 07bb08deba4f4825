#pragma once
/// The RGB film of pbrt-v4's "rgb" Film: samples are weighted by the filter's f/pdf,
/// converted to sensor values (for the default "cie1931" sensor, CIE XYZ: the integral of
/// L times xbar, ybar, zbar over wavelength, times the imaging ratio), accumulated in double,
/// and written as linear sRGB.
#include <array>
#include <string>
#include <vector>

#include "steradian/film/image_io.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

struct FilmParams {
    Vec2i resolution{1280, 720};
    int x0 = 0, x1 = 1280, y0 = 0, y1 = 720;  ///< pixel bounds [x0,x1) x [y0,y1) (crop window)
    std::string filename = "pbrt.exr";
    Float imaging_ratio = 1;  ///< exposuretime * iso / 100
    Float max_component = kInfinity;
    bool half_float = false;
    /// Linear sRGB from sensor XYZ (includes any white balance).
    std::array<std::array<Float, 3>, 3> rgb_from_sensor{};
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

/// Identity white balance: the IEC 61966-2-1 XYZ -> linear sRGB matrix.
std::array<std::array<Float, 3>, 3> srgb_from_xyz_matrix();
/// Bradford chromatic adaptation from a source white (xy) to D65 followed by XYZ -> sRGB.
std::array<std::array<Float, 3>, 3> srgb_from_xyz_white_balanced(Float src_x, Float src_y);

/// Per-pixel accumulators (sensor XYZ weighted sums and weight sum), in double.
struct PixelSum {
    double xyz[3] = {0, 0, 0};
    double weight = 0;
};

class Film {
public:
    explicit Film(const FilmParams& p);
    const FilmParams& params() const { return m_p; }

    /// Sensor XYZ of a spectral radiance sample: imaging_ratio * average over wavelengths of
    /// cmf(l) L(l) / pdf(l), clamped to max_component.
    std::array<double, 3> to_sensor(const SampledSpectrum& L, const SampledWavelengths& lambda) const;

    /// Adds a weighted sample to pixel (x, y) (absolute image coordinates) of `buffer`.
    void add(std::vector<PixelSum>& buffer, int x, int y, const std::array<double, 3>& xyz,
             double weight) const;
    std::vector<PixelSum> make_buffer() const {
        return std::vector<PixelSum>(size_t(m_p.width()) * m_p.height());
    }
    /// Adds a completed pass into the film.
    void merge(const std::vector<PixelSum>& pass);
    /// The accumulated sums, pixel by pixel in rows of the crop window.
    const std::vector<PixelSum>& sums() const { return m_pixels; }
    /// Replaces the accumulated sums (a pass continued from sums(), or a checkpoint's).
    /// Throws sr::Error unless `sums` has one entry per pixel.
    void set_sums(std::vector<PixelSum> sums);
    /// The image (crop-window size) as linear sRGB.
    Image rgb_image() const;
    /// Luminance Y per pixel (cd/m^2 with the units of docs/units.md).
    std::vector<double> luminance() const;

private:
    FilmParams m_p;
    std::vector<PixelSum> m_pixels;
    /// xbar, ybar, zbar (and a zero) at each nm from kLambdaMin: one vector load per row.
    std::vector<Float4> m_cmf;
};

}  // namespace sr
