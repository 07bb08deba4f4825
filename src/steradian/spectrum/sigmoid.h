#pragma once
/// The sigmoid-polynomial spectra of Jakob & Hanika 2019, "A Low-Dimensional Function Space
/// for Efficient Spectral Upsampling" (Computer Graphics Forum 38(2)), eq. 3-4:
/// s(l) = S(c0 l^2 + c1 l + c2), S(x) = 1/2 + x / (2 sqrt(1 + x^2)). Internal to spectrum/.
#include <algorithm>
#include <cmath>
#include <limits>

#include "steradian/core/math.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

/// S(x) in [0, 1]; S(+inf) = 1, S(-inf) = 0 (a constant spectrum of 1 or 0).
template <typename T>
inline T sigmoid(T x) {
    // Beyond 1e18 the 1 + x^2 would overflow in float; the limit is exact there anyway.
    if (!(std::abs(x) < T(1e18))) return x > 0 ? T(1) : T(0);
    return T(0.5) + x / (2 * std::sqrt(1 + x * x));
}

/// The inverse of S for v in [0, 1]: +-infinity at 1 and 0.
inline double inverse_sigmoid(double v) {
    if (v <= 0) return -std::numeric_limits<double>::infinity();
    if (v >= 1) return std::numeric_limits<double>::infinity();
    double y = 2 * v - 1;  // = x / sqrt(1 + x^2)
    return y / std::sqrt((1 - y) * (1 + y));
}

/// S(c0 l^2 + c1 l + c2), lambda in nm.
inline Float sigmoid_polynomial(Float c0, Float c1, Float c2, Float lambda) {
    return sigmoid(std::fma(std::fma(c0, lambda, c1), lambda, c2));
}

/// The maximum of the sigmoid polynomial over [kLambdaMin, kLambdaMax]: S is monotonic, so
/// it is attained at an end or at the vertex of the parabola.
inline Float sigmoid_polynomial_max(Float c0, Float c1, Float c2) {
    Float m = std::max(sigmoid_polynomial(c0, c1, c2, kLambdaMin),
                       sigmoid_polynomial(c0, c1, c2, kLambdaMax));
    if (c0 != 0) {
        Float vertex = -c1 / (2 * c0);
        if (vertex >= kLambdaMin && vertex <= kLambdaMax)
            m = std::max(m, sigmoid_polynomial(c0, c1, c2, vertex));
    }
    return m;
}

}  // namespace sr
