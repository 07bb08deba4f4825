// Form factors of the radiosity pass against closed forms (Howell, "A Catalog of Radiation
// Heat Transfer Configuration Factors", 3rd ed., configurations B-13, C-11 and C-14), and the
// enclosure identities: reciprocity and row sums of 1.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "steradian/integrators/radiosity/form_factor.h"

namespace sr::radiosity {
namespace {

constexpr double kPiD = std::numbers::pi;

/// Howell C-11: identical, parallel, directly opposed a x b rectangles at distance c.
double parallel_rectangles(double a, double b, double c) {
    const double X = a / c, Y = b / c;
    const double x1 = 1 + X * X, y1 = 1 + Y * Y;
    return 2 / (kPiD * X * Y) *
           (0.5 * std::log(x1 * y1 / (x1 + Y * Y)) + X * std::sqrt(y1) * std::atan(X / std::sqrt(y1)) +
            Y * std::sqrt(x1) * std::atan(Y / std::sqrt(x1)) - X * std::atan(X) - Y * std::atan(Y));
}

/// Howell C-14: from a rectangle of width w to a perpendicular one of height h sharing its
/// edge of length l.
double perpendicular_rectangles(double w, double h, double l) {
    const double W = w / l, H = h / l, W2 = W * W, H2 = H * H, R = std::sqrt(H2 + W2);
    const double t1 = (1 + W2) * (1 + H2) / (1 + W2 + H2);
    const double t2 = std::pow(W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2)), W2);
    const double t3 = std::pow(H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2)), H2);
    return 1 / (kPiD * W) *
           (W * std::atan(1 / W) + H * std::atan(1 / H) - R * std::atan(1 / R) +
            0.25 * std::log(t1 * t2 * t3));
}

/// The patches of a parallelogram p0 + s u + t v, (s, t) in [0, 1]^2, n x n cells of two
/// triangles each; `flip` reverses the side.
std::vector<PatchGeom> grid(DVec3 p0, DVec3 u, DVec3 v, int n, bool flip) {
    std::vector<PatchGeom> out;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            auto at = [&](int a, int b) { return p0 + u * (double(a) / n) + v * (double(b) / n); };
            out.push_back(make_patch(at(i, j), at(i + 1, j), at(i + 1, j + 1), flip));
            out.push_back(make_patch(at(i, j), at(i + 1, j + 1), at(i, j + 1), flip));
        }
    return out;
}

double area_sum(const std::vector<PatchGeom>& p) {
    double a = 0;
    for (const auto& x : p) a += x.area;
    return a;
}

/// F from surface 1 to surface 2: sum of the patch exchanges over A_1.
double surface_factor(const std::vector<PatchGeom>& s1, const std::vector<PatchGeom>& s2) {
    double sum = 0;
    for (const auto& a : s1)
        for (const auto& b : s2)
            if (facing(a, b, 1e-12)) sum += exchange(a, b, 1e-9, nullptr);
    return sum / area_sum(s1);
}

TEST(RadiosityFormFactor, DifferentialAreaToCoaxialDisk) {
    // Howell B-13: F = r^2 / (h^2 + r^2). The disk as a fan of 720 triangles (the polygon's
    // area falls short of the disk's by (2 pi / n)^2 / 6 = 1.3e-5, far inside the bound).
    for (double h : {0.3, 1.0, 4.0}) {
        const double r = 1.0;
        const int n = 720;
        double F = 0;
        for (int k = 0; k < n; ++k) {
            const double a0 = 2 * kPiD * k / n, a1 = 2 * kPiD * (k + 1) / n;
            // The polygon is inscribed: scale its radius so its area equals the disk's.
            const double rr = r * std::sqrt(2 * kPiD / (n * std::sin(2 * kPiD / n)));
            const DVec3 tri[3] = {DVec3(0, 0, h), DVec3(rr * std::cos(a0), rr * std::sin(a0), h),
                                  DVec3(rr * std::cos(a1), rr * std::sin(a1), h)};
            F += point_to_polygon(DVec3(0, 0, 0), DVec3(0, 0, 1), tri, 3);
        }
        const double expect = r * r / (h * h + r * r);
        EXPECT_NEAR(F, expect, 1e-3 * expect) << "h " << h;
    }
}

TEST(RadiosityFormFactor, ClippedToTheHemisphere) {
    // A square straddling the receiver's plane counts only its upper half: a unit square
    // [-1, 1] x {1} x [-1, 1] seen from the origin with normal +z equals the half
    // [-1, 1] x {1} x [0, 1], which by symmetry is half of what the full square gives a
    // receiver facing +y: C-14-like check without a closed form, by two evaluations.
    const DVec3 sq[4] = {DVec3(-1, 1, -1), DVec3(1, 1, -1), DVec3(1, 1, 1), DVec3(-1, 1, 1)};
    const DVec3 half[4] = {DVec3(-1, 1, 0), DVec3(1, 1, 0), DVec3(1, 1, 1), DVec3(-1, 1, 1)};
    const DVec3 x(0, 0, 0), n(0, 0, 1);
    EXPECT_NEAR(point_to_polygon(x, n, sq, 4), point_to_polygon(x, n, half, 4), 1e-12);
    EXPECT_GT(point_to_polygon(x, n, half, 4), 0.0);
}

TEST(RadiosityFormFactor, ParallelRectangles) {
    // Unit squares 0.5 and 2 apart, meshed as the radiosity pass meshes them.
    for (double c : {0.5, 2.0}) {
        const auto s1 = grid(DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 1, 0), 6, false);
        const auto s2 = grid(DVec3(0, 0, c), DVec3(1, 0, 0), DVec3(0, 1, 0), 6, true);
        const double expect = parallel_rectangles(1, 1, c);
        EXPECT_NEAR(surface_factor(s1, s2), expect, 1e-3 * expect) << "c " << c;
    }
}

TEST(RadiosityFormFactor, PerpendicularRectanglesWithACommonEdge) {
    // Surface 1: width w along x, in the plane z = 0 (normal +z); surface 2: height h
    // along z in the plane x = 0 (normal +x); common edge of length l along y.
    struct Case {
        double w, h, l;
    };
    for (Case k : {Case{1, 1, 1}, Case{2, 1, 1}, Case{1, 3, 2}}) {
        const auto s1 = grid(DVec3(0, 0, 0), DVec3(k.w, 0, 0), DVec3(0, k.l, 0), 8, false);
        const auto s2 = grid(DVec3(0, 0, 0), DVec3(0, k.l, 0), DVec3(0, 0, k.h), 8, false);
        ASSERT_GT(s2[0].n.x, 0.5);
        const double expect = perpendicular_rectangles(k.w, k.h, k.l);
        EXPECT_NEAR(surface_factor(s1, s2), expect, 1e-3 * expect)
            << "w " << k.w << " h " << k.h << " l " << k.l;
    }
}

TEST(RadiosityFormFactor, EnclosureReciprocityAndRowSums) {
    // The six inward faces of a 1 x 1 x 1 cube, 4 x 4 cells of two triangles each: every
    // patch's form factors to all the others sum to 1, and the exchange computed with
    // either patch as the receiver agrees (reciprocity A_i F_ij = A_j F_ji).
    std::vector<PatchGeom> all;
    auto face = [&](DVec3 p0, DVec3 u, DVec3 v) {
        auto g = grid(p0, u, v, 4, false);
        all.insert(all.end(), g.begin(), g.end());
    };
    face(DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 1, 0));  // z = 0, +z
    face(DVec3(0, 0, 1), DVec3(0, 1, 0), DVec3(1, 0, 0));  // z = 1, -z
    face(DVec3(0, 0, 0), DVec3(0, 0, 1), DVec3(1, 0, 0));  // y = 0, +y
    face(DVec3(0, 1, 0), DVec3(1, 0, 0), DVec3(0, 0, 1));  // y = 1, -y
    face(DVec3(0, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1));  // x = 0, +x
    face(DVec3(1, 0, 0), DVec3(0, 0, 1), DVec3(0, 1, 0));  // x = 1, -x
    for (const auto& p : all) ASSERT_GT(ddot(p.n, DVec3(0.5, 0.5, 0.5) - p.c), 0);
    const size_t n = all.size();
    double worst_row = 0, worst_recip = 0;
    for (size_t i = 0; i < n; ++i) {
        double row = 0;
        for (size_t j = 0; j < n; ++j) {
            if (i == j || !facing(all[i], all[j], 1e-12)) continue;
            const double e = exchange(all[i], all[j], 1e-9, nullptr);
            row += e;
            // Reciprocity: the same exchange integrated over the other patch.
            const double e2 = exchange(all[i], all[j], 1e-9, nullptr, nullptr,
                                       all[i].area <= all[j].area ? 1 : 0);
            if (e > 0) worst_recip = std::max(worst_recip, std::abs(e - e2) / e);
        }
        worst_row = std::max(worst_row, std::abs(row / all[i].area - 1));
    }
    EXPECT_LT(worst_row, 1e-3);
    EXPECT_LT(worst_recip, 2e-3);
}

TEST(RadiosityFormFactor, ReciprocityOfTheQuadratureBothWays) {
    // The exchange integrated over one patch and over the other agree within the
    // quadrature's error: two perpendicular triangles sharing an edge, and two far apart.
    const PatchGeom a = make_patch(DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 1, 0));
    const PatchGeom b = make_patch(DVec3(0, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1.2));
    ASSERT_TRUE(facing(a, b, 1e-12));
    const double e1 = exchange(a, b, 1e-12, nullptr, nullptr, 0);  // a receives
    const double e2 = exchange(a, b, 1e-12, nullptr, nullptr, 1);  // b receives
    EXPECT_NEAR(e1, e2, 2e-3 * e1);
}

}  // namespace
}  // namespace sr::radiosity
