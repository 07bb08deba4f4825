#include "steradian/sampling/stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "steradian/core/error.h"

namespace sr {
namespace {

constexpr int kMaxIterations = 1000;
constexpr double kEps = 1e-15;

/// exp(-x + a ln x - ln Gamma(a)): the common prefactor of both incomplete-gamma expansions.
double gamma_prefactor(double a, double x) {
    return std::exp(-x + a * std::log(x) - std::lgamma(a));
}

/// P(a, x) by its power series gamma(a, x) = e^-x x^a sum_n x^n / (a (a+1) ... (a+n))
/// (Abramowitz & Stegun 6.5.29); converges quickly for x < a + 1.
double gamma_p_series(double a, double x) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < kMaxIterations; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * kEps) break;
    }
    return sum * gamma_prefactor(a, x);
}

/// Q(a, x) by the continued fraction of Gamma(a, x) (A&S 6.5.31), evaluated with the modified
/// Lentz algorithm (Lentz 1976; Thompson & Barnett 1986); converges quickly for x >= a + 1.
double gamma_q_continued_fraction(double a, double x) {
    constexpr double tiny = 1e-300;
    double b = x + 1 - a;
    double c = 1 / tiny;
    double d = 1 / b;
    double h = d;
    for (int i = 1; i < kMaxIterations; ++i) {
        double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1) < kEps) break;
    }
    return h * gamma_prefactor(a, x);
}

}  // namespace

double gamma_p(double a, double x) {
    SR_CHECK(a > 0);
    if (!(x > 0)) return 0;
    if (std::isinf(x)) return 1;
    if (x < a + 1) return gamma_p_series(a, x);
    return 1 - gamma_q_continued_fraction(a, x);
}

double gamma_q(double a, double x) {
    SR_CHECK(a > 0);
    if (!(x > 0)) return 1;
    if (std::isinf(x)) return 0;
    if (x < a + 1) return 1 - gamma_p_series(a, x);
    return gamma_q_continued_fraction(a, x);
}

double chi2_sf(double x, double dof) { return gamma_q(dof / 2, x / 2); }

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normal_two_sided_p(double z) { return std::erfc(std::abs(z) / std::sqrt(2.0)); }

double z_test_p(double mean, double expected, double std_error) {
    double diff = mean - expected;
    if (diff == 0) return 1;
    if (std_error <= 0) return 0;
    return normal_two_sided_p(diff / std_error);
}

double sidak_alpha(double alpha, int num_tests) {
    // 1 - (1 - alpha)^(1/n) computed as -expm1(log1p(-alpha) / n) for accuracy at small alpha.
    return -std::expm1(std::log1p(-alpha) / num_tests);
}

Chi2Result chi2_test(std::span<const double> observed, std::span<const double> expected,
                     double min_expected) {
    SR_CHECK(observed.size() == expected.size());
    Chi2Result result;
    std::vector<std::size_t> order(expected.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });

    for (std::size_t i : order) {
        if (expected[i] == 0 && observed[i] > 0) {
            result.statistic = std::numeric_limits<double>::infinity();
            result.p_value = 0;
            return result;
        }
    }

    // Pool sparse cells (smallest expected first) into cells of at least min_expected.
    std::vector<double> obs, expc;
    double pool_o = 0, pool_e = 0;
    std::size_t k = 0;
    for (; k < order.size() && expected[order[k]] < min_expected; ++k) {
        pool_o += observed[order[k]];
        pool_e += expected[order[k]];
        ++result.pooled_cells;
        if (pool_e >= min_expected) {
            obs.push_back(pool_o);
            expc.push_back(pool_e);
            pool_o = pool_e = 0;
        }
    }
    std::size_t first_regular = obs.size();
    for (; k < order.size(); ++k) {
        obs.push_back(observed[order[k]]);
        expc.push_back(expected[order[k]]);
    }
    if (pool_e > 0 || pool_o > 0) {
        if (first_regular < obs.size()) {
            obs[first_regular] += pool_o;
            expc[first_regular] += pool_e;
        } else if (!obs.empty()) {
            obs.back() += pool_o;
            expc.back() += pool_e;
        } else {
            obs.push_back(pool_o);
            expc.push_back(pool_e);
        }
    }

    for (std::size_t i = 0; i < obs.size(); ++i) {
        if (expc[i] > 0) result.statistic += (obs[i] - expc[i]) * (obs[i] - expc[i]) / expc[i];
    }
    result.dof = int(obs.size()) - 1;
    result.p_value = result.dof > 0 ? chi2_sf(result.statistic, result.dof) : 1;
    return result;
}

}  // namespace sr
