#pragma once
/// Helpers shared by the sampling tests (header-only, no GoogleTest dependency): checks of
/// stratification and of the (0,m,2)- and (t,m,3)-net properties.
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "steradian/core/math.h"

namespace sr::testing {

/// Empty if the 2^m points form a (0,m,2)-net in base 2: for every split m = p + q, each of
/// the 2^m elementary intervals of size 2^-p by 2^-q contains exactly one point. Otherwise a
/// description of the first violation.
inline std::string check_02_net(const std::vector<Point2>& pts) {
    std::size_t n = pts.size();
    if (n == 0 || !std::has_single_bit(n)) return "point count is not a power of two";
    int m = std::countr_zero(n);
    for (int p = 0; p <= m; ++p) {
        int q = m - p;
        std::vector<int> count(n, 0);
        for (const Point2& pt : pts) {
            if (!(pt.x >= 0 && pt.x < 1 && pt.y >= 0 && pt.y < 1)) return "point outside [0,1)^2";
            // Multiplication by a power of two is exact, so floor() finds the true interval.
            auto ix = std::size_t(std::floor(double(pt.x) * double(std::size_t(1) << p)));
            auto iy = std::size_t(std::floor(double(pt.y) * double(std::size_t(1) << q)));
            ++count[(iy << p) | ix];
        }
        for (std::size_t c = 0; c < n; ++c) {
            if (count[c] != 1) {
                return "elementary interval " + std::to_string(c) + " of shape 2^-" +
                       std::to_string(p) + " x 2^-" + std::to_string(q) + " holds " +
                       std::to_string(count[c]) + " points";
            }
        }
    }
    return {};
}

/// Empty if the 2^m points form a (t,m,3)-net in base 2: for every split m - t = p + q + r,
/// each of the 2^(m-t) elementary boxes of size 2^-p by 2^-q by 2^-r contains exactly 2^t
/// points. Otherwise a description of the first violation.
inline std::string check_net_3d(const std::vector<Point3>& pts, int t) {
    std::size_t n = pts.size();
    if (n == 0 || !std::has_single_bit(n)) return "point count is not a power of two";
    int m = std::countr_zero(n);
    if (t > m) return "t exceeds m";
    int k = m - t;
    for (int p = 0; p <= k; ++p) {
        for (int q = 0; p + q <= k; ++q) {
            int r = k - p - q;
            std::vector<int> count(std::size_t(1) << k, 0);
            for (const Point3& pt : pts) {
                if (!(pt.x >= 0 && pt.x < 1 && pt.y >= 0 && pt.y < 1 && pt.z >= 0 && pt.z < 1))
                    return "point outside [0,1)^3";
                auto ix = std::size_t(std::floor(double(pt.x) * double(std::size_t(1) << p)));
                auto iy = std::size_t(std::floor(double(pt.y) * double(std::size_t(1) << q)));
                auto iz = std::size_t(std::floor(double(pt.z) * double(std::size_t(1) << r)));
                ++count[(((iz << q) | iy) << p) | ix];
            }
            for (std::size_t c = 0; c < count.size(); ++c) {
                if (count[c] != (1 << t)) {
                    return "elementary box " + std::to_string(c) + " of shape 2^-" +
                           std::to_string(p) + " x 2^-" + std::to_string(q) + " x 2^-" +
                           std::to_string(r) + " holds " + std::to_string(count[c]) + " points";
                }
            }
        }
    }
    return {};
}

/// True if each of the n = xs.size() strata [k/n, (k+1)/n) holds exactly one value.
inline bool is_stratified_1d(const std::vector<Float>& xs) {
    std::size_t n = xs.size();
    std::vector<int> count(n, 0);
    for (Float x : xs) {
        if (!(x >= 0 && x < 1)) return false;
        auto k = std::size_t(std::floor(double(x) * double(n)));
        if (k >= n || ++count[k] > 1) return false;
    }
    return true;
}

}  // namespace sr::testing
