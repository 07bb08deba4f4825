#include "steradian/sampling/distribution.h"

#include <algorithm>
#include <cmath>

#include "steradian/core/error.h"

namespace sr {
namespace {

/// Bin of x in n equal bins over [lo, hi], clamped to [0, n-1].
int bin_of(Float x, Float lo, Float hi, std::size_t n) {
    auto i = int(std::floor((x - lo) / (hi - lo) * Float(n)));
    return clamp(i, 0, int(n) - 1);
}

void check_finite(std::span<const Float> f, const char* what) {
    if (f.empty()) throw Error(fmt::format("{}: no values", what));
    for (std::size_t i = 0; i < f.size(); ++i) {
        if (!std::isfinite(f[i])) {
            throw Error(fmt::format("{}: value {} at index {} is not finite", what, f[i], i));
        }
    }
}

}  // namespace

// ---- Distribution1D ---------------------------------------------------------------------------

Distribution1D::Distribution1D(std::span<const Float> f, Float min, Float max)
    : m_func(f.size()), m_cdf(f.size() + 1), m_min(min), m_max(max) {
    check_finite(f, "Distribution1D");
    if (!(min < max)) throw Error(fmt::format("Distribution1D: empty range [{}, {}]", min, max));
    std::size_t n = f.size();
    for (std::size_t i = 0; i < n; ++i) m_func[i] = std::abs(f[i]);

    // Accumulate in double: environment maps have millions of bins.
    std::vector<double> partial(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) partial[i + 1] = partial[i] + double(m_func[i]);
    m_sum = partial[n];
    m_integral = Float(m_sum * double(max - min) / double(n));
    m_uniform = !(m_sum > 0) || !(m_integral > 0);
    for (std::size_t i = 0; i <= n; ++i) {
        m_cdf[i] = m_uniform ? Float(double(i) / double(n)) : Float(partial[i] / m_sum);
    }
    m_cdf[n] = 1;
    if (m_uniform) m_integral = 0;
    m_guide.resize(n);
    int i = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const Float u = Float(double(k) / double(n));
        while (i + 1 < int(n) && m_cdf[std::size_t(i) + 1] <= u) ++i;
        m_guide[k] = i;
    }
}

int Distribution1D::find_bin(Float u) const {
    // Largest i in [0, n-1] with cdf[i] <= u; bins of zero width are skipped because the
    // next cdf entry is equal and also <= u. From the guide table's bin for u's 1/n-th.
    const int n = int(m_func.size());
    if (!(u >= 0)) return u < 0 ? 0 : n - 1;  // (NaN: as a binary search would end)
    const int k = std::min(int(u * Float(n)), n - 1);
    int i = m_guide[std::size_t(k)];
    // The guide's u = k / n may round up past u in float: step back then.
    while (i > 0 && m_cdf[std::size_t(i)] > u) --i;
    while (i + 1 < n && m_cdf[std::size_t(i) + 1] <= u) ++i;
    return i;
}

Float Distribution1D::sample_continuous(Float u, Float* pdf_out, int* offset) const {
    int o = find_bin(u);
    Float du = u - m_cdf[std::size_t(o)];
    Float width = m_cdf[std::size_t(o) + 1] - m_cdf[std::size_t(o)];
    if (width > 0) du /= width;
    du = clamp(du, Float(0), kOneMinusEpsilon);
    Float t = (Float(o) + du) / Float(m_func.size());
    Float x = lerp(t, m_min, m_max);
    if (x >= m_max) x = std::nextafter(m_max, m_min);
    if (x < m_min) x = m_min;
    // Report the bin (and density) that pdf(x) would find, so the two always agree even when
    // rounding puts x on a neighbouring bin's boundary.
    int bin = bin_of(x, m_min, m_max, m_func.size());
    if (offset) *offset = bin;
    if (pdf_out) {
        *pdf_out = m_uniform ? 1 / (m_max - m_min) : m_func[std::size_t(bin)] / m_integral;
    }
    return x;
}

Float Distribution1D::pdf(Float x) const {
    if (!(x >= m_min && x <= m_max)) return 0;
    if (m_uniform) return 1 / (m_max - m_min);
    return m_func[std::size_t(bin_of(x, m_min, m_max, m_func.size()))] / m_integral;
}

int Distribution1D::sample_discrete(Float u, Float* pmf_out, Float* u_remapped) const {
    int o = find_bin(u);
    if (pmf_out) *pmf_out = pmf(o);
    if (u_remapped) {
        Float width = m_cdf[std::size_t(o) + 1] - m_cdf[std::size_t(o)];
        Float r = width > 0 ? (u - m_cdf[std::size_t(o)]) / width : Float(0);
        *u_remapped = clamp(r, Float(0), kOneMinusEpsilon);
    }
    return o;
}

Float Distribution1D::pmf(int i) const {
    if (m_uniform) return Float(1.0 / double(m_func.size()));
    return Float(double(m_func[std::size_t(i)]) / m_sum);
}

std::optional<Float> Distribution1D::invert(Float x) const {
    if (!(x >= m_min && x <= m_max)) return std::nullopt;
    Float t = (x - m_min) / (m_max - m_min) * Float(m_func.size());
    int o = bin_of(x, m_min, m_max, m_func.size());
    Float frac = clamp(t - Float(o), Float(0), Float(1));
    Float u = lerp(frac, m_cdf[std::size_t(o)], m_cdf[std::size_t(o) + 1]);
    return std::min(u, kOneMinusEpsilon);
}

// ---- AliasTable -------------------------------------------------------------------------------

AliasTable::AliasTable(std::span<const Float> weights) : m_bins(weights.size()) {
    check_finite(weights, "AliasTable");
    std::size_t n = weights.size();
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (weights[i] < 0) {
            throw Error(fmt::format("AliasTable: negative weight {} at index {}", weights[i], i));
        }
        sum += double(weights[i]);
    }
    std::vector<double> p(n);
    for (std::size_t i = 0; i < n; ++i) {
        p[i] = sum > 0 ? double(weights[i]) / sum : 1.0 / double(n);
        m_bins[i].p = Float(p[i]);
    }

    // Vose: split bins into those below and above the average probability 1/n; repeatedly
    // fill a small bin up to 1/n with probability mass from a large one.
    std::vector<std::size_t> small, large;
    std::vector<double> scaled(n);
    for (std::size_t i = 0; i < n; ++i) {
        scaled[i] = p[i] * double(n);
        (scaled[i] < 1 ? small : large).push_back(i);
    }
    while (!small.empty() && !large.empty()) {
        std::size_t s = small.back(), l = large.back();
        small.pop_back();
        large.pop_back();
        m_bins[s].q = Float(scaled[s]);
        m_bins[s].alias = int(l);
        scaled[l] = (scaled[l] + scaled[s]) - 1;
        (scaled[l] < 1 ? small : large).push_back(l);
    }
    // Whatever remains is 1 up to rounding.
    for (std::size_t i : large) {
        m_bins[i].q = 1;
        m_bins[i].alias = int(i);
    }
    for (std::size_t i : small) {
        m_bins[i].q = 1;
        m_bins[i].alias = int(i);
    }
}

int AliasTable::sample(Float u, Float* pmf_out, Float* u_remapped) const {
    double up;
    std::size_t offset;
    int result = choose(u, up, offset);
    if (pmf_out) *pmf_out = m_bins[std::size_t(result)].p;
    if (u_remapped) {
        // Kept the bin: up was in [0, q); took the alias: up was in [q, 1).
        double q = double(m_bins[offset].q);
        double remapped = up < q ? up / q : (up - q) / (1 - q);
        *u_remapped = std::min(Float(remapped), kOneMinusEpsilon);
    }
    return result;
}

// ---- Distribution2D ---------------------------------------------------------------------------

Distribution2D::Distribution2D(std::span<const Float> f, int nu, int nv, Point2 lo, Point2 hi)
    : m_lo(lo), m_hi(hi) {
    if (nu < 1 || nv < 1 || f.size() != std::size_t(nu) * std::size_t(nv)) {
        throw Error(fmt::format("Distribution2D: {} values for a {} x {} grid", f.size(), nu, nv));
    }
    m_conditional.reserve(std::size_t(nv));
    std::vector<Float> marginal(static_cast<std::size_t>(nv));
    for (int v = 0; v < nv; ++v) {
        m_conditional.emplace_back(f.subspan(std::size_t(v) * std::size_t(nu), std::size_t(nu)),
                                   lo.x, hi.x);
        marginal[std::size_t(v)] = m_conditional.back().integral();
    }
    m_marginal = Distribution1D(marginal, lo.y, hi.y);
}

Point2 Distribution2D::sample(Point2 u, Float* pdf_out) const {
    Float pdf_y, pdf_x;
    int v;
    Float y = m_marginal.sample_continuous(u.y, &pdf_y, &v);
    Float x = m_conditional[std::size_t(v)].sample_continuous(u.x, &pdf_x);
    if (pdf_out) *pdf_out = pdf_x * pdf_y;
    return {x, y};
}

Float Distribution2D::pdf(Point2 p) const {
    if (!(p.x >= m_lo.x && p.x <= m_hi.x && p.y >= m_lo.y && p.y <= m_hi.y)) return 0;
    int v = bin_of(p.y, m_lo.y, m_hi.y, m_conditional.size());
    return m_marginal.pdf(p.y) * m_conditional[std::size_t(v)].pdf(p.x);
}

std::optional<Point2> Distribution2D::invert(Point2 p) const {
    auto uy = m_marginal.invert(p.y);
    if (!uy) return std::nullopt;
    int v = bin_of(p.y, m_lo.y, m_hi.y, m_conditional.size());
    auto ux = m_conditional[std::size_t(v)].invert(p.x);
    if (!ux) return std::nullopt;
    return Point2{*ux, *uy};
}

}  // namespace sr
