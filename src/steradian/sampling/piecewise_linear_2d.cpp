#include "steradian/sampling/piecewise_linear_2d.h"

#include <algorithm>
#include <cmath>

#include "steradian/core/error.h"

namespace sr {

namespace {

/// The t in [0, 1] at which the integral from 0 to t of the linear density a + (b - a) x
/// equals s: a t + (b - a) t^2 / 2 = s, in the form 2 s / (a + sqrt(a^2 + 2 (b - a) s)),
/// which has no cancellation and no special case for a == b.
Float solve_linear_cdf(Float a, Float b, Float s) {
    Float den = a + safe_sqrt(a * a + 2 * (b - a) * s);
    if (!(den > 0)) return 0;
    return clamp(2 * s / den, Float(0), Float(1));
}

/// Clamps x to [0, 1], NaN to 0.
Float unit(Float x) { return x >= 0 ? std::min(x, Float(1)) : Float(0); }

/// The largest i in [0, n - 2] with value(i) <= x (0 if there is none); value non-decreasing.
template <typename F>
int find_interval(int n, Float x, F&& value) {
    int lo = 0, hi = n - 2;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (value(mid) <= x)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

}  // namespace

PiecewiseLinear2D::PiecewiseLinear2D(std::span<const float> data, int nx, int ny,
                                     std::span<const std::vector<float>> params, bool sampling)
    : m_nx(nx), m_ny(ny), m_sampling(sampling) {
    if (nx < 2 || ny < 2)
        throw Error(fmt::format("a {} x {} grid: at least 2 x 2 values are needed", ny, nx));
    if (params.size() > size_t(kMaxParams))
        throw Error(fmt::format("{} parameters, more than {}", params.size(), kMaxParams));
    size_t slices = 1;
    m_param_stride.resize(params.size());
    for (size_t d = params.size(); d-- > 0;) {
        const std::vector<float>& v = params[d];
        if (v.empty()) throw Error(fmt::format("parameter {} has no values", d + 1));
        for (size_t i = 0; i < v.size(); ++i) {
            if (!std::isfinite(v[i]))
                throw Error(fmt::format("parameter {} value {} is not finite", d + 1, i + 1));
            if (i > 0 && !(v[i] > v[i - 1]))
                throw Error(fmt::format("parameter {} values are not increasing ({} then {})",
                                        d + 1, v[i - 1], v[i]));
        }
        m_param_stride[d] = slices;
        slices *= v.size();
        m_params.emplace_back(v.begin(), v.end());
    }
    std::reverse(m_params.begin(), m_params.end());
    const size_t per_slice = size_t(nx) * size_t(ny);
    if (data.size() != slices * per_slice)
        throw Error(fmt::format("{} values, expected {} ({} slices of {} x {})", data.size(),
                                slices * per_slice, slices, ny, nx));
    for (size_t i = 0; i < data.size(); ++i)
        if (!std::isfinite(data[i]))
            throw Error(fmt::format("value {} ({}) is not finite", i, data[i]));
    m_data.assign(data.begin(), data.end());
    if (!sampling) return;

    m_conditional.resize(m_data.size());
    m_marginal.resize(slices * size_t(ny));
    for (size_t sl = 0; sl < slices; ++sl) {
        Float* d = m_data.data() + sl * per_slice;
        Float* cond = m_conditional.data() + sl * per_slice;
        Float* marg = m_marginal.data() + sl * size_t(ny);
        for (size_t i = 0; i < per_slice; ++i) d[i] = std::max(d[i], Float(0));
        // Integrals in cell units, in double: the trapezoid rule is exact for the bilinear
        // interpolant along each grid line.
        std::vector<double> row_cdf(per_slice), marg_cdf(static_cast<size_t>(ny));
        for (int y = 0; y < ny; ++y) {
            double sum = 0;
            row_cdf[size_t(y) * nx] = 0;
            for (int x = 0; x + 1 < nx; ++x) {
                sum += 0.5 * (double(d[y * nx + x]) + double(d[y * nx + x + 1]));
                row_cdf[size_t(y) * nx + x + 1] = sum;
            }
        }
        double total = 0;
        marg_cdf[0] = 0;
        for (int y = 0; y + 1 < ny; ++y) {
            total +=
                0.5 * (row_cdf[size_t(y) * nx + nx - 1] + row_cdf[size_t(y + 1) * nx + nx - 1]);
            marg_cdf[size_t(y) + 1] = total;
        }
        if (!(total > 0) || !std::isfinite(total))
            throw Error(fmt::format("slice {} of {} has no mass (all its values are 0 or less)",
                                    sl + 1, slices));
        for (size_t i = 0; i < per_slice; ++i) {
            d[i] = Float(double(d[i]) / total);
            cond[i] = Float(row_cdf[i] / total);
        }
        for (int y = 0; y < ny; ++y) marg[y] = Float(marg_cdf[size_t(y)] / total);
        marg[ny - 1] = 1;
    }
}

PiecewiseLinear2D::Corners PiecewiseLinear2D::corners(const Float* params) const {
    Corners c;
    c.slice[0] = 0;
    c.weight[0] = 1;
    for (size_t d = 0; d < m_params.size(); ++d) {
        const std::vector<Float>& v = m_params[d];
        if (v.size() == 1) continue;
        Float p = params[d];
        int i = int(std::upper_bound(v.begin() + 1, v.end() - 1, p) - v.begin()) - 1;
        Float t = (p - v[i]) / (v[i + 1] - v[i]);
        t = t > 0 ? std::min(t, Float(1)) : Float(0);  // NaN -> 0
        for (int k = c.count - 1; k >= 0; --k) {
            size_t base = c.slice[k] + size_t(i) * m_param_stride[d];
            Float w = c.weight[k];
            c.slice[2 * k] = base;
            c.weight[2 * k] = w * (1 - t);
            c.slice[2 * k + 1] = base + m_param_stride[d];
            c.weight[2 * k + 1] = w * t;
        }
        c.count *= 2;
    }
    return c;
}

void PiecewiseLinear2D::locate(Point2 p, int& col, int& row, Float& s, Float& t) const {
    Float x = unit(p.x) * Float(m_nx - 1), y = unit(p.y) * Float(m_ny - 1);
    col = std::min(int(x), m_nx - 2);
    row = std::min(int(y), m_ny - 2);
    s = x - Float(col);
    t = y - Float(row);
}

Float PiecewiseLinear2D::evaluate(Point2 p, const Float* params) const {
    int col, row;
    Float s, t;
    locate(p, col, row, s, t);
    Corners c = corners(params);
    const size_t n = size_t(m_nx) * size_t(m_ny), i = size_t(row) * m_nx + col;
    Float v00 = blend(m_data, c, n, i), v10 = blend(m_data, c, n, i + 1),
          v01 = blend(m_data, c, n, i + m_nx), v11 = blend(m_data, c, n, i + m_nx + 1);
    Float v = (1 - t) * ((1 - s) * v00 + s * v10) + t * ((1 - s) * v01 + s * v11);
    return m_sampling ? v * Float(m_nx - 1) * Float(m_ny - 1) : v;
}

PiecewiseLinear2D::Sample PiecewiseLinear2D::sample(Point2 u, const Float* params) const {
    constexpr Float kOneMinusEps = 0x1.fffffep-1f;
    u.x = std::min(unit(u.x), kOneMinusEps);
    u.y = std::min(unit(u.y), kOneMinusEps);
    Corners c = corners(params);
    const size_t n = size_t(m_nx) * size_t(m_ny);
    const size_t nx = size_t(m_nx);

    // The row band, then the position t within it, from the marginal distribution in y.
    int row = find_interval(m_ny, u.y, [&](int j) { return blend(m_marginal, c, m_ny, j); });
    Float r0 = blend(m_conditional, c, n, row * nx + nx - 1);
    Float r1 = blend(m_conditional, c, n, (row + 1) * nx + nx - 1);
    Float t = solve_linear_cdf(r0, r1, u.y - blend(m_marginal, c, m_ny, row));

    // The column, then s, from the conditional distribution in x at y = row + t.
    auto cond = [&](int i) {
        return (1 - t) * blend(m_conditional, c, n, row * nx + i) +
               t * blend(m_conditional, c, n, (row + 1) * nx + i);
    };
    Float target = u.x * ((1 - t) * r0 + t * r1);
    int col = find_interval(m_nx, target, cond);
    size_t i = row * nx + col;
    Float c0 = (1 - t) * blend(m_data, c, n, i) + t * blend(m_data, c, n, i + nx);
    Float c1 = (1 - t) * blend(m_data, c, n, i + 1) + t * blend(m_data, c, n, i + nx + 1);
    Float s = solve_linear_cdf(c0, c1, target - cond(col));

    Sample out;
    out.p = Point2{(Float(col) + s) / Float(m_nx - 1), (Float(row) + t) / Float(m_ny - 1)};
    out.pdf = ((1 - s) * c0 + s * c1) * Float(m_nx - 1) * Float(m_ny - 1);
    return out;
}

PiecewiseLinear2D::Sample PiecewiseLinear2D::invert(Point2 p, const Float* params) const {
    int col, row;
    Float s, t;
    locate(p, col, row, s, t);
    Corners c = corners(params);
    const size_t n = size_t(m_nx) * size_t(m_ny);
    const size_t nx = size_t(m_nx), i = row * nx + col;
    Float c0 = (1 - t) * blend(m_data, c, n, i) + t * blend(m_data, c, n, i + nx);
    Float c1 = (1 - t) * blend(m_data, c, n, i + 1) + t * blend(m_data, c, n, i + nx + 1);
    Float r0 = blend(m_conditional, c, n, row * nx + nx - 1);
    Float r1 = blend(m_conditional, c, n, (row + 1) * nx + nx - 1);
    Float cond = (1 - t) * blend(m_conditional, c, n, i) + t * blend(m_conditional, c, n, i + nx);
    Float row_total = (1 - t) * r0 + t * r1;
    Sample out;
    Float ux = cond + s * (c0 + Float(0.5) * s * (c1 - c0));
    out.p.x = row_total > 0 ? unit(ux / row_total) : 0;
    out.p.y = unit(blend(m_marginal, c, m_ny, row) + t * (r0 + Float(0.5) * t * (r1 - r0)));
    out.pdf = ((1 - s) * c0 + s * c1) * Float(m_nx - 1) * Float(m_ny - 1);
    return out;
}

}  // namespace sr
