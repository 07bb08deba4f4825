#pragma once
/// Tabulated distributions: piecewise-constant 1D densities (inverse-CDF sampling), Walker's
/// alias method for O(1) discrete sampling, and a 2D piecewise-constant density sampled as a
/// marginal in y times a conditional in x (e.g. environment maps).
///
/// All of them accept non-negative weights; an all-zero (or empty-integral) input falls back
/// to the uniform distribution so that sampling stays well defined, while integral() still
/// reports 0 so the caller can tell that there is nothing to sample.
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "steradian/core/math.h"

namespace sr {

/// Piecewise-constant density on [min, max] with n equal bins, proportional to f.
class Distribution1D {
  public:
    Distribution1D() = default;
    /// f: n >= 1 bin values, non-negative and finite (negative values are taken by absolute
    /// value; a non-finite value throws sr::Error). min < max.
    explicit Distribution1D(std::span<const Float> f, Float min = 0, Float max = 1);

    std::size_t size() const { return m_func.size(); }
    Float min() const { return m_min; }
    Float max() const { return m_max; }
    /// Value of bin i as given (absolute value).
    Float func(std::size_t i) const { return m_func[i]; }
    /// Integral of the piecewise-constant function over [min, max] (in units of f times units
    /// of x); 0 for an all-zero input (then sampling is uniform).
    Float integral() const { return m_integral; }

    /// Continuous sample x in [min, max) for u in [0, 1), by inverting the piecewise-linear CDF.
    /// pdf: density of x per unit of x (func(offset) / integral()). offset: the bin of x.
    Float sample_continuous(Float u, Float* pdf = nullptr, int* offset = nullptr) const;
    /// Density of sample_continuous at x per unit of x; 0 outside [min, max].
    Float pdf(Float x) const;
    /// Bin index i with probability pmf(i). u_remapped: the position of u inside the bin's CDF
    /// interval, again uniform in [0, 1) and independent of the choice (for reuse).
    int sample_discrete(Float u, Float* pmf = nullptr, Float* u_remapped = nullptr) const;
    /// Probability of choosing bin i by sample_discrete (func(i) / sum of all bins).
    Float pmf(int i) const;
    /// CDF at x: the u that sample_continuous maps to x; empty if x is outside [min, max].
    std::optional<Float> invert(Float x) const;

  private:
    int find_bin(Float u) const;

    std::vector<Float> m_func;
    std::vector<Float> m_cdf;  // n + 1 entries, m_cdf[0] = 0, m_cdf[n] = 1
    /// Guide table (the cutpoint method, Chen and Asau 1974): m_guide[k] is the bin of
    /// u = k / n, from which the bin of any u in [k / n, (k + 1) / n) is a short scan away
    /// (the same bin a binary search finds, in O(1) expected steps).
    std::vector<int> m_guide;
    Float m_min = 0, m_max = 1;
    Float m_integral = 0;
    double m_sum = 0;  // sum of m_func
    bool m_uniform = false;
};

/// Walker's alias method (Walker 1977, ACM TOMS 3(3)) built with Vose's numerically stable
/// O(n) construction (Vose 1991, IEEE TSE 17(9)): one uniform variate picks a bin and decides
/// between the bin and its alias, so sampling is O(1) regardless of n. Used for light
/// selection by power.
class AliasTable {
  public:
    AliasTable() = default;
    /// weights: n >= 1 non-negative finite values (a non-finite or negative value throws
    /// sr::Error); all-zero weights give the uniform distribution.
    explicit AliasTable(std::span<const Float> weights);

    std::size_t size() const { return m_bins.size(); }
    /// Index i with probability pmf(i) for u in [0, 1). u_remapped: a fresh uniform variate in
    /// [0, 1) recovered from the unused part of u (with about 24 - log2(n) bits of precision).
    int sample(Float u, Float* pmf = nullptr, Float* u_remapped = nullptr) const;
    /// As sample(u, &pmf) (the same index), inline and without the remapped variate: one
    /// multiply, one load and a select (light selection at every path vertex).
    int sample(Float u, Float& pmf) const {
        double up;
        std::size_t offset;
        int result = choose(u, up, offset);
        pmf = m_bins[std::size_t(result)].p;
        return result;
    }
    /// Probability of index i (normalized weight).
    Float pmf(int i) const { return m_bins[std::size_t(i)].p; }

  private:
    struct Bin {
        Float q = 1;    // probability of keeping the bin rather than jumping to its alias
        int alias = 0;  // the alias bin
        Float p = 0;    // normalized weight of this bin
    };
    std::vector<Bin> m_bins;

    /// The index for u. offset: the bin u falls in, whose q decides between it and its alias
    /// (by a select, not a branch); up: u's position in [0, 1) inside that bin.
    int choose(Float u, double& up, std::size_t& offset) const {
        std::size_t n = m_bins.size();
        double un = double(u) * double(n);
        offset = std::min(std::size_t(un), n - 1);
        up = std::min(un - double(offset), double(kOneMinusEpsilon));
        const Bin& bin = m_bins[offset];
        return up < double(bin.q) ? int(offset) : bin.alias;
    }
};

/// Piecewise-constant density on the rectangle [lo, hi] from an nu x nv grid of values
/// f[v * nu + u] (u along x, v along y): y is sampled from the marginal density of the rows
/// and x from the chosen row's conditional density (Pharr et al., "Physically Based
/// Rendering", 3rd ed., Sec. 13.6.7).
class Distribution2D {
  public:
    Distribution2D() = default;
    Distribution2D(std::span<const Float> f, int nu, int nv, Point2 lo = {0, 0},
                   Point2 hi = {1, 1});

    /// Point in [lo, hi) for u in [0,1)^2; pdf: density per unit area of the rectangle.
    Point2 sample(Point2 u, Float* pdf = nullptr) const;
    /// Density of sample() per unit area of the rectangle; 0 outside it.
    Float pdf(Point2 p) const;
    /// The u that sample() maps to p; empty if p is outside the rectangle.
    std::optional<Point2> invert(Point2 p) const;
    /// Integral of the piecewise-constant function over the rectangle; 0 for all-zero input.
    Float integral() const { return m_marginal.integral(); }
    int nu() const { return int(m_conditional.empty() ? 0 : m_conditional[0].size()); }
    int nv() const { return int(m_conditional.size()); }

  private:
    std::vector<Distribution1D> m_conditional;  // one per row v, over [lo.x, hi.x]
    Distribution1D m_marginal;                  // over [lo.y, hi.y]
    Point2 m_lo{0, 0}, m_hi{1, 1};
};

}  // namespace sr
