#pragma once
/// The RGB film of pbrt-v4's "rgb" Film: samples are weighted by the filter's f/pdf,
/// converted to sensor values (the integral of L times the sensor's three sensitivities over
/// wavelength, times the imaging ratio: for the default "cie1931" sensor xbar, ybar, zbar, so
/// CIE XYZ; for a camera sensor its raw r, g, b), accumulated in double, and written as
/// linear sRGB through `rgb_from_sensor`.
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "steradian/core/transform.h"
#include "steradian/film/filter.h"
#include "steradian/film/image_io.h"
#include "steradian/spectrum/sampled.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

/// pbrt-v4's film types.
enum class FilmKind {
    Rgb,       ///< "rgb": the image
    GBuffer,   ///< "gbuffer": the image and the first visible surface's geometry and albedo
    Spectral,  ///< "spectral": the image and the radiance in wavelength buckets
};

struct FilmParams {
    FilmKind kind = FilmKind::Rgb;
    Vec2i resolution{1280, 720};
    int x0 = 0, x1 = 1280, y0 = 0, y1 = 720;  ///< pixel bounds [x0,x1) x [y0,y1) (crop window)
    std::string filename = "pbrt.exr";
    Float imaging_ratio = 1;  ///< exposuretime * iso / 100
    Float max_component = kInfinity;
    bool half_float = false;
    /// The sensor's sensitivities r, g, b (a camera of spectrum/camera_sensors.h); none: the
    /// CIE 1931 matching functions ("cie1931").
    std::optional<std::array<Spectrum, 3>> sensor_rgb;
    /// Linear sRGB from sensor values (includes any white balance; for a camera sensor, the
    /// fitted XYZ-from-sensor-RGB matrix of film/sensor.h).
    std::array<std::array<Float, 3>, 3> rgb_from_sensor{};
    /// Luminance Y from sensor values: (0, 1, 0) for the CIE sensor (its y is Y, before any
    /// white balance); the Y row of the fitted XYZ-from-sensor-RGB matrix for a camera.
    std::array<Float, 3> luminance_from_sensor{0, 1, 0};
    /// "gbuffer": positions, normals and depth slopes in camera space ("coordinatesystem"
    /// "camera", the default) or world space ("world"); the camera's camera-from-world.
    bool gbuffer_camera_space = true;
    Transform camera_from_world;
    /// "spectral": nbuckets buckets of equal width over [lambda_min, lambda_max] nm.
    int buckets = 16;
    Float lambda_min = kLambdaMin, lambda_max = kLambdaMax;
    /// Channels of the film's output image (Film::output_image).
    int output_channels() const {
        return kind == FilmKind::Rgb ? 3 : kind == FilmKind::GBuffer ? 25 : 3 + buckets;
    }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

/// Identity white balance: the IEC 61966-2-1 XYZ -> linear sRGB matrix.
std::array<std::array<Float, 3>, 3> srgb_from_xyz_matrix();
/// Bradford chromatic adaptation from a source white (xy) to D65 followed by XYZ -> sRGB.
std::array<std::array<Float, 3>, 3> srgb_from_xyz_white_balanced(Float src_x, Float src_y);

/// What a camera path records at the first surface it meets that scatters (pbrt-v4's
/// VisibleSurface), in world space, for the "gbuffer" film: position, geometric and shading
/// normals facing the ray's origin, uv, the BSDF's directional albedo, and the change of
/// position over one pixel in x and y on the surface's tangent plane.
struct VisibleSurface {
    bool set = false;
    Point3 p;
    Normal3 n, ns;
    Point2 uv;
    Vec3 dpdx, dpdy;
    SampledSpectrum albedo{0};
};

/// Per-pixel accumulators (weighted sums of the sensor values, named xyz after the default
/// CIE sensor, and the weight sum), in double.
struct PixelSum {
    double xyz[3] = {0, 0, 0};
    double weight = 0;
};

class Film {
public:
    explicit Film(const FilmParams& p);
    const FilmParams& params() const { return m_p; }

    /// Sensor values of a spectral radiance sample: imaging_ratio * average over wavelengths
    /// of sensitivity(l) L(l) / pdf(l), clamped to max_component.
    std::array<double, 3> to_sensor(const SampledSpectrum& L, const SampledWavelengths& lambda) const;

    /// Adds a weighted sample to pixel (x, y) (absolute image coordinates) of `buffer`.
    void add(std::vector<PixelSum>& buffer, int x, int y, const std::array<double, 3>& xyz,
             double weight) const;
    std::vector<PixelSum> make_buffer() const {
        return std::vector<PixelSum>(size_t(m_p.width()) * m_p.height());
    }
    /// The wavelengths of a camera sample: importance-sampled over the visible range, or
    /// for the "spectral" film uniform over its [lambda_min, lambda_max] (pbrt-v4).
    SampledWavelengths sample_wavelengths(Float u) const {
        return m_p.kind == FilmKind::Spectral
                   ? SampledWavelengths::sample_uniform(u, m_p.lambda_min, m_p.lambda_max)
                   : SampledWavelengths::sample_visible(u);
    }
    /// Whether the film keeps channels besides the image ("gbuffer", "spectral"), whose
    /// per-pixel sums are aux_sums(), aux_stride() doubles a pixel.
    bool has_aux() const { return m_aux_stride > 0; }
    bool uses_visible_surface() const { return m_p.kind == FilmKind::GBuffer; }
    size_t aux_stride() const { return m_aux_stride; }
    /// Adds a sample's auxiliary values to pixel (x, y) of `aux` (a copy of aux_sums()):
    /// for "gbuffer" the visible surface (if set) and the variance of `sensor`, for
    /// "spectral" L in its wavelength buckets.
    void add_aux(std::vector<double>& aux, int x, int y, const SampledSpectrum& L,
                 const SampledWavelengths& lambda, const std::array<double, 3>& sensor,
                 double weight, const VisibleSurface* vs) const;
    const std::vector<double>& aux_sums() const { return m_aux; }
    /// Throws sr::Error unless `sums` has aux_stride() values per pixel.
    void set_aux_sums(std::vector<double> sums);
    /// Adds a completed pass into the film.
    void merge(const std::vector<PixelSum>& pass);
    /// The accumulated sums, pixel by pixel in rows of the crop window.
    const std::vector<PixelSum>& sums() const { return m_pixels; }
    /// Replaces the accumulated sums (a pass continued from sums(), or a checkpoint's).
    /// Throws sr::Error unless `sums` has one entry per pixel.
    void set_sums(std::vector<PixelSum> sums);
    /// Splats (pbrt-v4's Film::AddSplat): contributions of light paths that reach the camera
    /// at an arbitrary film position p (raster space), kept apart from the pixel sums as
    /// sensor values per pixel (3 doubles a pixel, rows of the crop window). add_splat adds
    /// `xyz` times the filter's value at each pixel centre within its radius of p into
    /// `buffer` (a splat_buffer(), or a copy of splat_sums()). The image is the pixel sums'
    /// weighted mean plus splat_sums() * splat_scale / filter integral, splat_scale being 1 /
    /// (samples per pixel) as pbrt-v4's. Only the pixel rows [row_begin, row_end) are
    /// touched (so that threads can add the same splats into disjoint bands of rows).
    void add_splat(std::vector<double>& buffer, Point2 p, const std::array<double, 3>& xyz,
                   const Filter& filter, int row_begin = std::numeric_limits<int>::min(),
                   int row_end = std::numeric_limits<int>::max()) const;
    std::vector<double> splat_buffer() const { return std::vector<double>(m_pixels.size() * 3); }
    bool has_splats() const { return !m_splats.empty(); }
    const std::vector<double>& splat_sums() const { return m_splats; }
    /// Replaces the splat sums (throws sr::Error unless 3 per pixel). A render reduces the
    /// splat buffers of its tiles in a fixed order and sets the result here; a distributed
    /// render would reduce these sums across processes in a fixed order the same way.
    void set_splat_sums(std::vector<double> sums);
    /// The factor splat_sums() are scaled by in the image: 1 / (spp x filter integral).
    void set_splat_scale(double scale) { m_splat_scale = scale; }
    double splat_scale() const { return m_splat_scale; }
    /// The image (crop-window size) as linear sRGB.
    Image rgb_image() const;
    /// The film's output: rgb_image(), or for "gbuffer" and "spectral" films that and their
    /// other channels, named as pbrt-v4 names them (EXR only).
    Image output_image() const;
    /// Luminance Y per pixel (cd/m^2 with the units of docs/units.md); for a camera sensor,
    /// the Y of its fitted XYZ.
    std::vector<double> luminance() const;

private:
    FilmParams m_p;
    std::vector<PixelSum> m_pixels;
    size_t m_aux_stride = 0;
    std::vector<double> m_aux;
    /// The sensitivities (and a zero) at each nm from kLambdaMin: one vector load per row.
    std::vector<Float4> m_cmf;
    std::vector<double> m_splats;  ///< empty: no splats
    double m_splat_scale = 0;
    /// A pixel's sensor values: weighted mean plus scaled splats.
    std::array<double, 3> pixel_sensor(size_t i) const;
};

}  // namespace sr
