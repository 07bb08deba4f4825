#include "steradian/film/film.h"

#include <fmt/format.h>

#include "steradian/core/error.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

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
    // The three matching functions interleaved, so a sample costs one index computation.
    const auto &X = cie_x(), &Y = cie_y(), &Z = cie_z();
    for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l)
        m_cmf.push_back(Float4{X(Float(l)), Y(Float(l)), Z(Float(l)), 0});
    m_cmf.push_back(Float4{0, 0, 0, 0});  // guard for interpolation at kLambdaMax
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

Image Film::rgb_image() const {
    Image img;
    img.width = m_p.width();
    img.height = m_p.height();
    img.channels = 3;
    img.data.resize(size_t(img.width) * img.height * 3);
    const auto& m = m_p.rgb_from_sensor;
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const PixelSum& p = m_pixels[i];
        double xyz[3] = {0, 0, 0};
        if (p.weight != 0)
            for (int c = 0; c < 3; ++c) xyz[c] = p.xyz[c] / p.weight;
        for (int r = 0; r < 3; ++r)
            img.data[i * 3 + r] = float(m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2]);
    }
    return img;
}

std::vector<double> Film::luminance() const {
    std::vector<double> y(m_pixels.size());
    for (size_t i = 0; i < m_pixels.size(); ++i)
        y[i] = m_pixels[i].weight != 0 ? m_pixels[i].xyz[1] / m_pixels[i].weight : 0;
    return y;
}

}  // namespace sr
