#include "steradian/film/film.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "steradian/core/error.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

namespace gbuffer {
// Layout of a "gbuffer" film's auxiliary sums, per pixel: the weight of the samples that
// found a surface, weighted sums of position, normal, shading normal, uv, dz/dx and dz/dy,
// and albedo (linear sRGB), and for each sensor channel a variance estimator (count, mean,
// sum of squared deviations).
constexpr int kWeight = 0, kP = 1, kN = 4, kNs = 7, kUv = 10, kDz = 12, kAlbedo = 14,
              kVariance = 17, kStride = 26;
/// pbrt-v4's GBufferFilm channels after R, G, B, in its order.
// clang-format off
constexpr const char* kChannels[] = {
    "Albedo.R", "Albedo.G", "Albedo.B", "P.X", "P.Y", "P.Z", "dzdx", "dzdy", "N.X", "N.Y",
    "N.Z", "Ns.X", "Ns.Y", "Ns.Z", "u", "v", "Variance.R", "Variance.G", "Variance.B",
    "RelativeVariance.R", "RelativeVariance.G", "RelativeVariance.B"};
// clang-format on
}  // namespace gbuffer

std::array<std::array<Float, 3>, 3> srgb_from_xyz_matrix() {
    // IEC 61966-2-1 (sRGB), D65 white.
    return {{{3.2404542f, -1.5371385f, -0.4985314f},
             {-0.9692660f, 1.8760108f, 0.0415560f},
             {0.0556434f, -0.2040259f, 1.0572252f}}};
}

std::array<std::array<Float, 3>, 3> srgb_from_xyz_white_balanced(Float sx, Float sy) {
    // Bradford cone response matrix (Lam 1985; as tabulated by Lindbloom).
    const double b[3][3] = {{0.8951, 0.2664, -0.1614},
                            {-0.7502, 1.7135, 0.0367},
                            {0.0389, -0.0685, 1.0296}};
    const double binv[3][3] = {{0.9869929, -0.1470543, 0.1599627},
                               {0.4323053, 0.5183603, 0.0492912},
                               {-0.0085287, 0.0400428, 0.9684867}};
    auto xyz_of = [](double x, double y) { return std::array<double, 3>{x / y, 1, (1 - x - y) / y}; };
    auto src = xyz_of(sx, sy), dst = xyz_of(0.3127, 0.3290);
    double ls[3], ld[3];
    for (int i = 0; i < 3; ++i) {
        ls[i] = b[i][0] * src[0] + b[i][1] * src[1] + b[i][2] * src[2];
        ld[i] = b[i][0] * dst[0] + b[i][1] * dst[1] + b[i][2] * dst[2];
    }
    double adapt[3][3];  // binv * diag(ld/ls) * b
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += binv[i][k] * (ld[k] / ls[k]) * b[k][j];
            adapt[i][j] = s;
        }
    auto m = srgb_from_xyz_matrix();
    std::array<std::array<Float, 3>, 3> r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += m[i][k] * adapt[k][j];
            r[i][j] = Float(s);
        }
    return r;
}

Film::Film(const FilmParams& p) : m_p(p), m_pixels(size_t(p.width()) * p.height()) {
    // The three sensitivities interleaved, so a sample costs one index computation.
    const std::array<Spectrum, 3> s =
        p.sensor_rgb ? *p.sensor_rgb : std::array<Spectrum, 3>{cie_x(), cie_y(), cie_z()};
    for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l)
        m_cmf.push_back(Float4{s[0](Float(l)), s[1](Float(l)), s[2](Float(l)), 0});
    m_cmf.push_back(Float4{0, 0, 0, 0});  // guard for interpolation at kLambdaMax
    if (p.kind == FilmKind::GBuffer) m_aux_stride = gbuffer::kStride;
    if (p.kind == FilmKind::Spectral) m_aux_stride = 2 * size_t(p.buckets);
    m_aux.assign(m_pixels.size() * m_aux_stride, 0.0);
}

void Film::set_aux_sums(std::vector<double> sums) {
    if (sums.size() != m_aux.size())
        throw Error(
            fmt::format("film: {} auxiliary sums for a film of {}", sums.size(), m_aux.size()));
    m_aux = std::move(sums);
}

void Film::add_aux(std::vector<double>& aux, int x, int y, const SampledSpectrum& L,
                   const SampledWavelengths& lambda, const std::array<double, 3>& sensor,
                   double weight, const VisibleSurface* vs) const {
    double* a = aux.data() + (size_t(y - m_p.y0) * m_p.width() + (x - m_p.x0)) * m_aux_stride;
    if (m_p.kind == FilmKind::Spectral) {
        // pbrt-v4's SpectralFilm: the radiance of each wavelength (clamped as a whole to
        // maxcomponentvalue), weighted, summed in its bucket with the weight; the wavelengths
        // are uniform over the film's range, so a bucket's mean is the radiance averaged over
        // it. Scaled by kCieYIntegral, as pbrt-v4 does to undo the photometric normalisation
        // of lights. A wavelength of zero pdf (a secondary wavelength terminated at a
        // dispersive interface) carries no estimate of its own radiance and is left out.
        const Float m = L.max_value();
        const double clamp = m > m_p.max_component ? m_p.max_component / m : 1.0;
        const int n = m_p.buckets;
        for (int i = 0; i < kSpectrumSamples; ++i) {
            if (lambda.pdf[i] == 0) continue;
            int b =
                int(n * (lambda.lambda[i] - m_p.lambda_min) / (m_p.lambda_max - m_p.lambda_min));
            b = std::clamp(b, 0, n - 1);
            a[b] += weight * clamp * double(L[i]) * kCieYIntegral;
            a[n + b] += weight;
        }
        return;
    }
    // gbuffer: the variance of the sensor values of the samples that found a surface
    // (pbrt-v4's VarianceEstimator, unweighted, by Welford's update).
    using namespace gbuffer;
    if (!vs || !vs->set) return;
    for (int c = 0; c < 3; ++c) {
        double* v = a + kVariance + 3 * c;  // count, mean, sum of squared deviations
        v[0] += 1;
        const double d = sensor[size_t(c)] - v[1];
        v[1] += d / v[0];
        v[2] += d * (sensor[size_t(c)] - v[1]);
    }
    a[kWeight] += weight;
    const bool cam = m_p.gbuffer_camera_space;
    const Transform& t = m_p.camera_from_world;
    const Point3 p = cam ? t.point(vs->p) : vs->p;
    const Normal3 n = cam ? t.normal(vs->n) : vs->n, ns = cam ? t.normal(vs->ns) : vs->ns;
    const Vec3 dpdx = cam ? t.vector(vs->dpdx) : vs->dpdx,
               dpdy = cam ? t.vector(vs->dpdy) : vs->dpdy;
    for (int c = 0; c < 3; ++c) {
        a[kP + c] += weight * p[c];
        a[kN + c] += weight * n[c];
        a[kNs + c] += weight * ns[c];
    }
    a[kUv] += weight * vs->uv.x;
    a[kUv + 1] += weight * vs->uv.y;
    a[kDz] += weight * dpdx.z;
    a[kDz + 1] += weight * dpdy.z;
    // The albedo as the colour of a reflectance under the colour space's white (D65):
    // linear sRGB of the XYZ of albedo x D65 (Y of D65 = 1), estimated at the wavelengths.
    double xyz[3] = {0, 0, 0};
    for (int i = 0; i < kSpectrumSamples; ++i) {
        if (lambda.pdf[i] == 0) continue;
        const Float l = lambda.lambda[i];
        const double s = double(vs->albedo[i]) * srgb_illuminant()(l) / lambda.pdf[i] /
                         (kSpectrumSamples * double(kCieYIntegral));
        xyz[0] += s * cie_x()(l);
        xyz[1] += s * cie_y()(l);
        xyz[2] += s * cie_z()(l);
    }
    const auto rgb = srgb_from_xyz_matrix();
    for (int c = 0; c < 3; ++c)
        a[kAlbedo + c] += weight * (rgb[c][0] * xyz[0] + rgb[c][1] * xyz[1] + rgb[c][2] * xyz[2]);
}

std::array<double, 3> Film::to_sensor(const SampledSpectrum& L,
                                      const SampledWavelengths& lambda) const {
    // L / pdf for the four wavelengths in one vector division (four double divisions were
    // a tenth of this function's time); a lane of zero pdf is not read (`use` below).
    const Float4 pdf{lambda.pdf[0], lambda.pdf[1], lambda.pdf[2], lambda.pdf[3]};
    const Float4 l_over_pdf = L.v / pdf;
    // (x, y, z, 0) of the four wavelengths summed in one vector, each interpolated from two
    // row loads (in float: four non-negative terms, a relative rounding error near 1e-7).
    // Without branches: a wavelength outside the table or of zero pdf adds zero (whether L
    // is zero differs from sample to sample, and skipping was a mispredicted branch about
    // once per camera path).
    Float4 xyz{0, 0, 0, 0};
    for (int i = 0; i < kSpectrumSamples; ++i) {
        Float x = lambda.lambda[i] - kLambdaMin;
        const bool use = lambda.pdf[i] != 0 && x >= 0 && x <= kLambdaMax - kLambdaMin;
        x = use ? x : 0;
        int k = int(x);
        Float t = x - Float(k);
        Float l = use ? l_over_pdf[i] : 0;
        xyz += ((1 - t) * m_cmf[std::size_t(k)] + t * m_cmf[std::size_t(k) + 1]) * l;
    }
    double k = double(m_p.imaging_ratio) / kSpectrumSamples;
    std::array<double, 3> r{double(xyz[0]) * k, double(xyz[1]) * k, double(xyz[2]) * k};
    double m = std::max({r[0], r[1], r[2]});
    if (m > m_p.max_component) {
        double s = m_p.max_component / m;
        for (auto& v : r) v *= s;
    }
    return r;
}

void Film::add(std::vector<PixelSum>& buffer, int x, int y, const std::array<double, 3>& xyz,
               double weight) const {
    PixelSum& px = buffer[size_t(y - m_p.y0) * m_p.width() + (x - m_p.x0)];
    for (int c = 0; c < 3; ++c) px.xyz[c] += weight * xyz[c];
    px.weight += weight;
}

void Film::add_splat(std::vector<double>& buffer, Point2 p, const std::array<double, 3>& xyz,
                     const Filter& filter, int row_begin, int row_end) const {
    // The pixels whose centres lie within the filter's radius of p (pbrt-v4's splat bounds).
    const Vec2 r = filter.radius();
    const Float px = p.x + 0.5f, py = p.y + 0.5f;
    const int x0 = std::max(m_p.x0, int(std::floor(px - r.x)));
    const int x1 = std::min(m_p.x1, int(std::floor(px + r.x)) + 1);
    const int y0 = std::max({m_p.y0, int(std::floor(py - r.y)), row_begin});
    const int y1 = std::min({m_p.y1, int(std::floor(py + r.y)) + 1, row_end});
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const Float w = filter.evaluate(Vec2(p.x - Float(x) - 0.5f, p.y - Float(y) - 0.5f));
            if (w == 0) continue;
            double* b = buffer.data() + (size_t(y - m_p.y0) * m_p.width() + (x - m_p.x0)) * 3;
            for (int c = 0; c < 3; ++c) b[c] += double(w) * xyz[size_t(c)];
        }
}

void Film::set_splat_sums(std::vector<double> sums) {
    if (sums.size() != m_pixels.size() * 3)
        throw Error(fmt::format("film: {} splat sums for a film of {} pixels", sums.size(),
                                m_pixels.size()));
    m_splats = std::move(sums);
}

std::array<double, 3> Film::pixel_sensor(size_t i) const {
    const PixelSum& p = m_pixels[i];
    std::array<double, 3> xyz{0, 0, 0};
    if (p.weight != 0)
        for (int c = 0; c < 3; ++c) xyz[size_t(c)] = p.xyz[c] / p.weight;
    if (!m_splats.empty())
        for (int c = 0; c < 3; ++c) xyz[size_t(c)] += m_splat_scale * m_splats[i * 3 + size_t(c)];
    return xyz;
}

void Film::merge(const std::vector<PixelSum>& pass) {
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) m_pixels[i].xyz[c] += pass[i].xyz[c];
        m_pixels[i].weight += pass[i].weight;
    }
}

void Film::set_sums(std::vector<PixelSum> sums) {
    if (sums.size() != m_pixels.size())
        throw Error(fmt::format("film: {} pixel sums for a film of {} pixels", sums.size(),
                                m_pixels.size()));
    m_pixels = std::move(sums);
}

Image Film::output_image() const {
    Image img = rgb_image();
    if (m_p.kind == FilmKind::Rgb) return img;
    std::vector<std::string> names = {"R", "G", "B"};
    if (m_p.kind == FilmKind::GBuffer) {
        for (const char* n : gbuffer::kChannels) names.emplace_back(n);
    } else {
        // pbrt-v4 names a bucket by its centre in nm, to three decimals, with ',' for the
        // decimal point ('.' separates the layers of an EXR file's channel names).
        for (int b = 0; b < m_p.buckets; ++b) {
            std::string l = fmt::format(
                "{:.3f}nm", lerp((b + 0.5f) / m_p.buckets, m_p.lambda_min, m_p.lambda_max));
            std::replace(l.begin(), l.end(), '.', ',');
            names.push_back("S0." + l);
        }
        img.attributes = {{"spectralLayoutVersion", "1.0"}, {"emissiveUnits", "W.m^-2.sr^-1"}};
    }
    const int nc = int(names.size());
    std::vector<float> data(size_t(img.width) * img.height * nc);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        float* out = data.data() + i * nc;
        for (int c = 0; c < 3; ++c) out[c] = img.data[i * 3 + c];
        const double* a = m_aux.data() + i * m_aux_stride;
        if (m_p.kind == FilmKind::Spectral) {
            for (int b = 0; b < m_p.buckets; ++b)
                out[3 + b] = a[m_p.buckets + b] > 0 ? float(a[b] / a[m_p.buckets + b]) : 0.f;
            continue;
        }
        using namespace gbuffer;
        // As pbrt-v4's GBufferFilm: the albedo over all samples' weight, the geometry over
        // the weight of the samples that found a surface, normals normalised, depth slopes
        // as magnitudes.
        const double w = m_pixels[i].weight, wg = a[kWeight];
        const double kw = w != 0 ? 1 / w : 0, kg = wg != 0 ? 1 / wg : 0;
        for (int c = 0; c < 3; ++c) out[3 + c] = float(a[kAlbedo + c] * kw);
        for (int c = 0; c < 3; ++c) out[6 + c] = float(a[kP + c] * kg);
        out[9] = float(std::abs(a[kDz] * kg));
        out[10] = float(std::abs(a[kDz + 1] * kg));
        for (int k : {0, 1}) {
            const double* v = a + (k ? kNs : kN);
            const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            for (int c = 0; c < 3; ++c) out[11 + 3 * k + c] = len > 0 ? float(v[c] / len) : 0.f;
        }
        out[17] = float(a[kUv] * kg);
        out[18] = float(a[kUv + 1] * kg);
        for (int c = 0; c < 3; ++c) {
            const double* v = a + kVariance + 3 * c;
            const double var = v[0] > 1 ? v[2] / (v[0] - 1) : 0;
            out[19 + c] = float(var);
            out[22 + c] = v[0] >= 1 && v[1] != 0 ? float(var / v[1]) : 0.f;
        }
    }
    img.channels = nc;
    img.data = std::move(data);
    img.channel_names = std::move(names);
    return img;
}

Image Film::rgb_image() const {
    Image img;
    img.width = m_p.width();
    img.height = m_p.height();
    img.channels = 3;
    img.data.resize(size_t(img.width) * img.height * 3);
    const auto& m = m_p.rgb_from_sensor;
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const std::array<double, 3> xyz = pixel_sensor(i);
        for (int r = 0; r < 3; ++r)
            img.data[i * 3 + r] = float(m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2]);
    }
    return img;
}

std::vector<double> Film::luminance() const {
    std::vector<double> y(m_pixels.size());
    const auto& w = m_p.luminance_from_sensor;
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const std::array<double, 3> xyz = pixel_sensor(i);
        y[i] = w[0] * xyz[0] + w[1] * xyz[1] + w[2] * xyz[2];
    }
    return y;
}

}  // namespace sr
