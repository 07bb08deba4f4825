#include "steradian/film/filter.h"

#include <algorithm>

namespace sr {

namespace {
Float gaussian(Float x, Float sigma) {
    return 1 / std::sqrt(2 * kPi * sigma * sigma) * std::exp(-sqr(x) / (2 * sigma * sigma));
}
}  // namespace

Filter::Filter(FilterType type, Vec2 radius, Float sigma)
    : m_type(type), m_radius(radius), m_sigma(sigma) {
    for (int a = 0; a < 2; ++a)
        m_integral[a] = type == FilterType::Box ? 2 * m_radius[a] : sqr(m_radius[a]);
    if (type != FilterType::Gaussian) return;
    for (int a = 0; a < 2; ++a) m_gauss_at_radius[a] = gaussian(m_radius[a], m_sigma);
    for (int a = 0; a < 2; ++a) {
        int n = std::max(8, int(std::ceil(2 * 64 * m_radius[a])));  // 64 cells per pixel
        m_func[a].resize(n);
        m_cdf[a].resize(n + 1);
        m_cdf[a][0] = 0;
        Float dx = 2 * m_radius[a] / n;
        for (int i = 0; i < n; ++i) {
            // Cell average by Simpson's rule.
            Float x0 = -m_radius[a] + i * dx, x1 = x0 + dx;
            Float v = (eval_1d(x0, a) + 4 * eval_1d(0.5f * (x0 + x1), a) + eval_1d(x1, a)) / 6;
            m_func[a][i] = std::max(Float(0), v);
            m_cdf[a][i + 1] = m_cdf[a][i] + m_func[a][i] * dx;
        }
        m_integral[a] = m_cdf[a][n];
        for (auto& c : m_cdf[a]) c /= m_integral[a];
        m_inv_width[a].resize(n);
        for (int i = 0; i < n; ++i) {
            Float width = m_cdf[a][i + 1] - m_cdf[a][i];
            m_inv_width[a][i] = width > 0 ? 1 / width : 1;
        }
        // Guide table (Chen & Wu 1990's "cutpoint" method): O(1) expected inversion.
        const int m = kGuidePerCell * n;
        m_guide[a].resize(m);
        int cell = 0;
        for (int j = 0; j < m; ++j) {
            Float uj = Float(j) / m;
            while (cell < n - 1 && m_cdf[a][cell + 1] <= uj) ++cell;
            m_guide[a][j] = cell;
        }
    }
}

Float Filter::eval_1d(Float x, int a) const {
    Float r = m_radius[a];
    if (std::abs(x) > r) return 0;
    switch (m_type) {
        case FilterType::Box: return 1;
        case FilterType::Triangle: return std::max(Float(0), r - std::abs(x));
        case FilterType::Gaussian:
            return std::max(Float(0), gaussian(x, m_sigma) - m_gauss_at_radius[a]);
    }
    return 0;
}

Float Filter::evaluate(Vec2 p) const { return eval_1d(p.x, 0) * eval_1d(p.y, 1); }

Float Filter::sample_1d(Float u, int a, Float& pdf) const {
    Float r = m_radius[a];
    switch (m_type) {
        case FilterType::Box:
            pdf = 1 / (2 * r);
            return lerp(u, -r, r);
        case FilterType::Triangle: {
            // Inverse CDF of the tent on [-r, r].
            Float x;
            if (u < 0.5f)
                x = -r + r * std::sqrt(2 * u);
            else
                x = r - r * std::sqrt(2 * (1 - u));
            pdf = (r - std::abs(x)) / (r * r);
            return x;
        }
        case FilterType::Gaussian: {
            const auto& cdf = m_cdf[a];
            int n = int(m_func[a].size());
            const int m = int(m_guide[a].size());
            int i = m_guide[a][std::min(m - 1, int(u * m))];
            // The guide's cell is right or one short for nearly every u; that first step is
            // taken without a branch (whether it is needed is a coin toss per sample, and
            // as a loop branch it was mispredicted about once per camera ray). cdf has n + 1
            // entries and cdf[n] = 1 > u, so cdf[i + 1] exists and stops at the last cell.
            i += int(cdf[i + 1] <= u);
            while (i < n - 1 && cdf[i + 1] <= u) ++i;
            Float du = (u - cdf[i]) * m_inv_width[a][i];
            Float dx = 2 * r / n;
            pdf = m_func[a][i] / m_integral[a];
            return -r + (i + du) * dx;
        }
    }
    pdf = 0;
    return 0;
}

FilterSample Filter::sample(Point2 u) const {
    Float px, py;
    FilterSample s;
    s.offset = Vec2(sample_1d(u.x, 0, px), sample_1d(u.y, 1, py));
    // f / pdf is constant: exactly for box and triangle (sampled by their inverse CDFs), and
    // for the gaussian because it is sampled as its piecewise-constant approximation with 64
    // cells per pixel, which is the filter used: its cell averages equal the gaussian's, and
    // within a cell it deviates by under 1% of the peak. The constant is the integral.
    s.weight = m_integral[0] * m_integral[1];
    return s;
}

}  // namespace sr
