#pragma once
/// Pixel reconstruction filters, used by filter importance sampling as in pbrt-v4: each
/// camera sample's film offset is drawn from the filter and weighted by f / pdf, so a
/// sample contributes to exactly one pixel (no splatting; thread-count independent).
#include <string>
#include <vector>

#include "steradian/core/math.h"

namespace sr {

enum class FilterType { Box, Triangle, Gaussian };

struct FilterSample {
    Vec2 offset;   ///< from the pixel centre, in pixels
    Float weight;  ///< f(offset) / pdf(offset)
};

class Filter {
public:
    /// Box (default radius 0.5), triangle (2), gaussian (1.5, sigma 0.5): pbrt-v4 defaults.
    Filter(FilterType type, Vec2 radius, Float sigma = 0.5f);
    FilterType type() const { return m_type; }
    Vec2 radius() const { return m_radius; }
    /// Filter value at offset p (pixels).
    Float evaluate(Vec2 p) const;
    FilterSample sample(Point2 u) const;
    /// The filter's integral over its support (what sample()'s weight is for a positive
    /// filter), by which pbrt-v4 divides splatted values.
    Float integral() const { return m_integral[0] * m_integral[1]; }

private:
    Float eval_1d(Float x, int axis) const;
    Float sample_1d(Float u, int axis, Float& pdf) const;
    FilterType m_type;
    Vec2 m_radius;
    Float m_sigma;
    Float m_gauss_at_radius[2] = {0, 0};  ///< subtracted so the gaussian reaches 0 at r
    // Gaussian: per-axis piecewise-constant tabulation (value per cell, cdf).
    std::vector<Float> m_func[2], m_cdf[2];
    /// 1 / (cdf[i + 1] - cdf[i]) per cell (1 for an empty cell): a multiply, not a division,
    /// on every camera ray's chain.
    std::vector<Float> m_inv_width[2];
    /// guide[j]: first cell whose cdf end exceeds j / size. kGuidePerCell entries per cell,
    /// so that near the peak, where the cells are sampled most, the search from the guided
    /// cell almost never steps (with one entry per cell, a step taken or not was a coin toss
    /// at every camera sample, and its misprediction cost more than the table's load).
    static constexpr int kGuidePerCell = 8;
    std::vector<int> m_guide[2];
    Float m_integral[2] = {1, 1};
};

}  // namespace sr
