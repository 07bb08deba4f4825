// Hierarchical radiosity (hierarchical.cpp) in a closed cube: the "furnace" identity. In an
// enclosure every point sees the walls with form factors summing to 1, so with the same
// reflectance rho and direct irradiance E everywhere, B = rho (E + B) has the uniform
// solution B = rho E / (1 - rho) at every leaf: the links, their exchanges and the push and
// pull through the trees must neither lose nor create light, nor move it from one place to
// another. Also: two-band solves are independent, and the solution does not depend on the
// thread count.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/task_arena.h>

#include "steradian/integrators/radiosity/hierarchical.h"

namespace sr::radiosity {
namespace {

/// A tree of `levels` midpoint splits under triangle (a, b, c) seen from the side its
/// winding's normal points to; leaves numbered in order from `next_unknown`.
int add_tree(std::vector<HierNode>& nodes, DVec3 a, DVec3 b, DVec3 c, int levels,
             int& next_unknown) {
    const int at = int(nodes.size());
    nodes.emplace_back();
    auto fill = [&](auto&& self, int n, std::array<DVec3, 3> t, int level) -> void {
        nodes[size_t(n)].g = make_patch(t[0], t[1], t[2]);
        if (level == 0) {
            nodes[size_t(n)].unknown = next_unknown++;
            return;
        }
        const DVec3 m01 = (t[0] + t[1]) * 0.5, m12 = (t[1] + t[2]) * 0.5, m02 = (t[0] + t[2]) * 0.5;
        const int first = int(nodes.size());
        nodes.resize(nodes.size() + 4);
        nodes[size_t(n)].child = first;
        self(self, first, {t[0], m01, m02}, level - 1);
        self(self, first + 1, {m01, t[1], m12}, level - 1);
        self(self, first + 2, {m02, m12, t[2]}, level - 1);
        self(self, first + 3, {m12, m02, m01}, level - 1);
    };
    fill(fill, at, {a, b, c}, levels);
    return at;
}

/// The inside of the unit cube: 12 triangles with normals pointing inwards.
struct Cube {
    std::vector<HierNode> nodes;
    std::vector<int> roots;
    int unknowns = 0;
    explicit Cube(int levels) {
        const DVec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
        // Quads wound so that the normal (b - a) x (c - a) points into the cube.
        const int quads[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                                 {2, 6, 7, 3}, {0, 3, 7, 4}, {1, 5, 6, 2}};
        for (const auto& q : quads) {
            const DVec3 n = dcross(p[q[1]] - p[q[0]], p[q[2]] - p[q[0]]);
            if (ddot(n, DVec3(0.5, 0.5, 0.5) - p[q[0]]) <= 0) throw std::logic_error("winding");
            roots.push_back(add_tree(nodes, p[q[0]], p[q[1]], p[q[2]], levels, unknowns));
            roots.push_back(add_tree(nodes, p[q[0]], p[q[2]], p[q[3]], levels, unknowns));
        }
    }
};

std::vector<double> solve(const Cube& cube, const std::vector<double>& rho,
                          const std::vector<double>& E, const std::vector<double>& ybar,
                          int threads, double link_error, HierStats& st) {
    tbb::task_arena arena(threads);
    HierParams prm;
    prm.link_error = link_error;
    prm.residual = 1e-9;
    prm.eps = 1e-9;
    return solve_hierarchical(cube.nodes, cube.roots, rho, E, ybar, nullptr, prm, arena, st);
}

TEST(HierarchicalRadiosity, FurnaceCubeIsUniform) {
    const Cube cube(3);
    ASSERT_EQ(cube.unknowns, 12 * 64);
    // Facing pairs of leaves: each leaf faces the 5 * 128 leaves of the other faces.
    const size_t leaf_pairs = size_t(768) * 640 / 2;
    for (double rho : {0.5, 0.9}) {
        // Band 0: reflectance rho, E = 1; band 1: reflectance rho / 2, E = 2.
        std::vector<double> r, E;
        for (int u = 0; u < cube.unknowns; ++u) {
            r.insert(r.end(), {rho, rho / 2});
            E.insert(E.end(), {1, 2});
        }
        const double b[2] = {rho / (1 - rho), (rho / 2) * 2 / (1 - rho / 2)};
        const double rb[2] = {rho, rho / 2};
        // At the default link error: the light is conserved. A leaf's form factors sum to
        // 1 within the exchanges' quadrature error (0.1 %, form_factor_test.cpp), which the
        // solve multiplies by up to rho / (1 - rho) in the area mean of B.
        HierStats st;
        std::vector<double> B = solve(cube, r, E, {1, 1}, 2, HierParams{}.link_error, st);
        EXPECT_LE(st.residual, 1e-9);
        for (int k = 0; k < 2; ++k) {
            double mean = 0;
            for (int u = 0; u < cube.unknowns; ++u) mean += B[size_t(2 * u + k)] / cube.unknowns;
            EXPECT_NEAR(mean, b[k], 1e-3 * rb[k] / (1 - rb[k]) * b[k]) << "rho " << rho;
        }
        if (rho == 0.5) {
            EXPECT_LT(st.links, leaf_pairs * 3 / 4);
        }
        // Refined (link error 1e-4): every leaf's B within the same budget, 0.1 % of a row
        // sum times rho / (1 - rho), plus 0.1 %.
        B = solve(cube, r, E, {1, 1}, 2, 1e-4, st);
        for (int k = 0; k < 2; ++k) {
            double worst = 0;
            for (int u = 0; u < cube.unknowns; ++u)
                worst = std::max(worst, std::abs(B[size_t(2 * u + k)] / b[k] - 1));
            EXPECT_LT(worst, 1e-3 * rb[k] / (1 - rb[k]) + 1e-3) << "rho " << rho << " band " << k;
        }
    }
}

TEST(HierarchicalRadiosity, SolutionDoesNotDependOnTheThreadCount) {
    const Cube cube(3);
    std::vector<double> r, E;
    for (int u = 0; u < cube.unknowns; ++u) {
        r.push_back(0.7);
        // A hot spot in the floor's middle: E varies, and so does the refinement.
        E.push_back(u % 64 == 20 ? 50.0 : 1.0);
    }
    HierStats s1, s2;
    const auto a = solve(cube, r, E, {1}, 1, 1e-4, s1);
    const auto b = solve(cube, r, E, {1}, 2, 1e-4, s2);
    EXPECT_EQ(s1.links, s2.links);
    EXPECT_EQ(s1.sweeps, s2.sweeps);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << i;
}

}  // namespace
}  // namespace sr::radiosity
