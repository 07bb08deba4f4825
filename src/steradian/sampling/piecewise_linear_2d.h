#pragma once
/// A function on the unit square [0, 1]^2 that interpolates a grid of nx x ny values
/// bilinearly, optionally depending on up to kMaxParams further parameters, between whose
/// tabulated values it is interpolated linearly (a "slice" is the grid at one combination of
/// tabulated parameter values). It is the building block of the tabulated BRDFs of Dupuy and
/// Jakob 2018 ("An Adaptive Parameterization for Efficient Material Acquisition and
/// Rendering", ACM TOG 37(6)), which pbrt-v4 calls PiecewiseLinear2D; this is our own
/// implementation of the same mathematics.
///
/// Two kinds:
/// - an interpolant (sampling = false): evaluate() is the bilinear interpolation of the raw
///   values;
/// - a density (sampling = true): each slice is scaled so that the integral of its bilinear
///   interpolant over the unit square is 1 (negative values are taken as 0; a slice without
///   mass is an error), and sample() draws points with that density by inverting the
///   marginal cumulative distribution in y, then the conditional one in x (both piecewise
///   quadratic, inverted in closed form). Between parameter values the densities, and with
///   them the cumulative distributions, are blended linearly, so sample() draws from the
///   blended density exactly and evaluate() returns it. invert() is the inverse map of
///   sample().
///
/// Data layout: value (slice, y, x) at index (slice * ny + y) * nx + x; the slice index runs
/// over the parameters in row-major order (the first parameter varies slowest). Points and
/// parameters outside the tabulated ranges are clamped to them.
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "steradian/core/math.h"

namespace sr {

class PiecewiseLinear2D {
  public:
    static constexpr int kMaxParams = 3;

    struct Sample {
        Point2 p;       ///< a point of the unit square
        Float pdf = 0;  ///< density of p per unit area of the square
    };

    PiecewiseLinear2D() = default;
    /// nx, ny >= 2; params: the tabulated values of each parameter (at least one each,
    /// finite and strictly increasing); data: (product of the parameter counts) nx ny finite
    /// values. Throws sr::Error (without a file name: the caller adds it) on any violation.
    PiecewiseLinear2D(std::span<const float> data, int nx, int ny,
                      std::span<const std::vector<float>> params, bool sampling);

    int nx() const { return m_nx; }
    int ny() const { return m_ny; }
    int param_count() const { return int(m_params.size()); }

    /// The interpolated value at p (a density per unit area for sampling tables). `params`
    /// points to param_count() values.
    Float evaluate(Point2 p, const Float* params = nullptr) const;
    /// Sampling tables: the point with density evaluate(p) that u in [0, 1)^2 maps to.
    Sample sample(Point2 u, const Float* params = nullptr) const;
    /// Sampling tables: the u that sample() maps to p, with the density at p.
    Sample invert(Point2 p, const Float* params = nullptr) const;

  private:
    /// The slices around a parameter point and their weights (2^param_count() of them).
    struct Corners {
        int count = 1;
        std::array<size_t, 1 << kMaxParams> slice{};
        std::array<Float, 1 << kMaxParams> weight{};
    };
    Corners corners(const Float* params) const;
    /// sum over corners of weight * a[slice * per_slice + i]
    static Float blend(const std::vector<Float>& a, const Corners& c, size_t per_slice, size_t i) {
        Float v = 0;
        for (int k = 0; k < c.count; ++k) v += c.weight[k] * a[c.slice[k] * per_slice + i];
        return v;
    }
    /// The cell of p and p's position in it: index (col, row), fractions (s, t).
    void locate(Point2 p, int& col, int& row, Float& s, Float& t) const;

    int m_nx = 0, m_ny = 0;
    bool m_sampling = false;
    std::vector<std::vector<Float>> m_params;
    std::vector<size_t> m_param_stride;  ///< in slices
    /// Sampling tables: values divided by the slice's integral in cell units (so that a cell
    /// has area 1); interpolants: the raw values.
    std::vector<Float> m_data;
    /// Sampling tables: per row, the integral along x from 0 to x (cell units), and per
    /// slice the integral over y from 0 to each row (ends at 1).
    std::vector<Float> m_conditional, m_marginal;
};

}  // namespace sr
