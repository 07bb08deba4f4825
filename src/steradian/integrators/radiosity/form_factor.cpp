#include "steradian/integrators/radiosity/form_factor.h"

#include <algorithm>

#include "steradian/sampling/hash.h"

namespace sr::radiosity {

double point_to_polygon(DVec3 x, DVec3 n, const DVec3* v, int count) {
    // Sutherland-Hodgman clip of the polygon to the receiver's front half-space.
    DVec3 clipped[9];
    int m = 0;
    for (int k = 0; k < count && m < 9; ++k) {
        const DVec3 a = v[k], b = v[(k + 1) % count];
        const double da = ddot(n, a - x), db = ddot(n, b - x);
        if (da >= 0) clipped[m++] = a;
        if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
            const double t = da / (da - db);
            if (m < 9) clipped[m++] = a + (b - a) * t;
        }
    }
    if (m < 3) return 0;
    double sum = 0;
    for (int k = 0; k < m; ++k) {
        const DVec3 r0 = clipped[k] - x, r1 = clipped[(k + 1) % m] - x;
        const DVec3 c = dcross(r0, r1);
        const double cl = dlength(c);
        if (!(cl > 0)) continue;  // x on the edge's line: the edge subtends no angle
        // The angle by the polynomial arctangent (relative error < 3e-7, core/math.h):
        // std::atan2 in double was half of the form factors' time.
        const double gamma = double(fast_atan2(Float(cl), Float(ddot(r0, r1))));
        sum += gamma * ddot(n, c) / cl;
    }
    return std::abs(sum) / (2 * std::numbers::pi);
}

const TriangleRule& triangle_rule(int degree) {
    static const TriangleRule centroid = [] {
        TriangleRule r;
        r.count = 1;
        r.b[0] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
        r.w[0] = 1;
        return r;
    }();
    static const TriangleRule three = [] {
        TriangleRule r;
        r.count = 3;
        for (int i = 0; i < 3; ++i) {
            r.b[i] = {1.0 / 6, 1.0 / 6, 1.0 / 6};
            r.b[i][i] = 2.0 / 3;
            r.w[i] = 1.0 / 3;
        }
        return r;
    }();
    static const TriangleRule seven = [] {
        // Radon's degree-5 rule: a1 = (9 - 2 sqrt 15) / 21, b1 = (6 + sqrt 15) / 21,
        // a2 = (9 + 2 sqrt 15) / 21, b2 = (6 - sqrt 15) / 21, weights 9/40 and
        // (155 +- sqrt 15) / 1200.
        TriangleRule r;
        r.count = 7;
        const double s = std::sqrt(15.0);
        const double a1 = (9 - 2 * s) / 21, b1 = (6 + s) / 21;
        const double a2 = (9 + 2 * s) / 21, b2 = (6 - s) / 21;
        const double w1 = (155 + s) / 1200, w2 = (155 - s) / 1200;
        r.b[0] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
        r.w[0] = 9.0 / 40;
        for (int i = 0; i < 3; ++i) {
            r.b[1 + i] = {b1, b1, b1};
            r.b[1 + i][i] = a1;
            r.w[1 + i] = w1;
            r.b[4 + i] = {b2, b2, b2};
            r.b[4 + i][i] = a2;
            r.w[4 + i] = w2;
        }
        return r;
    }();
    if (degree <= 1) return centroid;
    if (degree <= 2) return three;
    return seven;
}

Point2 r2(uint64_t i, uint64_t key) {
    constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
    const uint64_t h = hash(key);
    const double s1 = double(h >> 40) * 0x1p-24, s2 = double((h >> 16) & 0xffffff) * 0x1p-24;
    double x = s1 + a1 * double(i), y = s2 + a2 * double(i);
    x -= std::floor(x);
    y -= std::floor(y);
    return Point2(Float(std::min(x, double(kOneMinusEpsilon))),
                  Float(std::min(y, double(kOneMinusEpsilon))));
}

PatchGeom make_patch(DVec3 a, DVec3 b, DVec3 c, bool flip) {
    PatchGeom p;
    p.v = {a, b, c};
    p.c = (a + b + c) * (1.0 / 3);
    const DVec3 cr = dcross(b - a, c - a);
    const double l = dlength(cr);
    p.area = 0.5 * l;
    p.n = l > 0 ? cr * ((flip ? -1.0 : 1.0) / l) : DVec3(0, 0, 1);
    p.diam = std::max({dlength(b - a), dlength(c - b), dlength(a - c)});
    return p;
}

bool facing(const PatchGeom& a, const PatchGeom& b, double eps) {
    auto front = [&](const PatchGeom& of, const PatchGeom& q) {
        for (const DVec3& v : q.v)
            if (ddot(of.n, v - of.c) > eps) return true;
        return false;
    };
    return front(a, b) && front(b, a);
}

namespace {

/// Distance from p to the triangle abc (Ericson, "Real-Time Collision Detection", 5.1.5).
double distance_to_triangle(DVec3 p, DVec3 a, DVec3 b, DVec3 c) {
    const DVec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ddot(ab, ap), d2 = ddot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return dlength(ap);
    const DVec3 bp = p - b;
    const double d3 = ddot(ab, bp), d4 = ddot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return dlength(bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return dlength(p - (a + ab * (d1 / (d1 - d3))));
    const DVec3 cp = p - c;
    const double d5 = ddot(ab, cp), d6 = ddot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return dlength(cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return dlength(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return dlength(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double den = 1 / (va + vb + vc);
    return dlength(p - (a + ab * (vb * den) + ac * (vc * den)));
}

}  // namespace

double exchange(const PatchGeom& a, const PatchGeom& b, double eps, const Visibility& visible,
                uint64_t* rays, int receiver, int max_level) {
    const bool a_recv = receiver < 0 ? a.area <= b.area : receiver == 0;
    const PatchGeom& r = a_recv ? a : b;
    const PatchGeom& s = a_recv ? b : a;
    const TriangleRule& vis_rule = triangle_rule(5);
    // Adaptive quadrature over the receiver: a (sub-)triangle whose size exceeds its distance
    // to the source is split in four (midpoints), down to 6 levels; the others get the
    // degree-2 rule when far (size under 0.3 of the distance) and the degree-5 rule else.
    struct Item {
        std::array<DVec3, 3> t;
        int level;
    };
    // A receiver far from the source (size under 0.3 of the distance): the degree-2 rule, and
    // one visibility ray between the centroids for all its points.
    const double dist_rs = distance_to_triangle(r.c, s.v[0], s.v[1], s.v[2]);
    if (r.diam < 0.3 * dist_rs) {
        if (visible) {
            if (rays) ++*rays;
            if (!visible(r.c + r.n * eps, s.c + s.n * eps)) return 0;
        }
        const TriangleRule& rule = triangle_rule(2);
        // A source whose size is under a tenth of the distance: its form factor from each
        // point is the differential one to its centroid, A cos cos / (pi r^2), whose relative
        // error, second order in size / distance, is under about 1e-3 (the kernel's
        // curvature over the source); the contour integral costs ten times as much.
        const bool small_source = s.diam < 0.1 * dist_rs;
        double F = 0;
        for (int q = 0; q < rule.count; ++q) {
            const auto& bq = rule.b[size_t(q)];
            const DVec3 x = r.v[0] * bq[0] + r.v[1] * bq[1] + r.v[2] * bq[2];
            if (ddot(s.n, x - s.c) <= 0) continue;
            if (small_source) {
                const DVec3 d = s.c - x;
                const double d2 = ddot(d, d);
                const double cx = ddot(r.n, d), cy = -ddot(s.n, d);
                if (cx > 0 && cy > 0)
                    F += rule.w[size_t(q)] * s.area * cx * cy / (std::numbers::pi * d2 * d2);
            } else {
                F += rule.w[size_t(q)] * point_to_polygon(x, r.n, s.v.data(), 3);
            }
        }
        return r.area * F;
    }
    std::array<Item, 64> stack;
    int top = 0;
    stack[size_t(top++)] = {r.v, 0};
    double F = 0;
    int q_index = 0;
    while (top > 0) {
        const Item it = stack[size_t(--top)];
        const auto& t = it.t;
        const DVec3 g = (t[0] + t[1] + t[2]) * (1.0 / 3);
        const double diam = r.diam / double(1 << it.level);
        const double dist = distance_to_triangle(g, s.v[0], s.v[1], s.v[2]);
        const double ratio = diam / std::max(dist, 1e-300);
        if (ratio > 1 && it.level < max_level && top + 4 <= int(stack.size())) {
            const DVec3 m01 = (t[0] + t[1]) * 0.5, m12 = (t[1] + t[2]) * 0.5,
                        m02 = (t[0] + t[2]) * 0.5;
            stack[size_t(top++)] = {{t[0], m01, m02}, it.level + 1};
            stack[size_t(top++)] = {{m01, t[1], m12}, it.level + 1};
            stack[size_t(top++)] = {{m02, m12, t[2]}, it.level + 1};
            stack[size_t(top++)] = {{m12, m02, m01}, it.level + 1};
            continue;
        }
        const TriangleRule& rule = triangle_rule(ratio < 0.3 ? 2 : 5);
        const double sub_w = 1.0 / double(uint64_t(1) << (2 * it.level));
        for (int q = 0; q < rule.count; ++q, ++q_index) {
            const auto& bq = rule.b[size_t(q)];
            const DVec3 x = t[0] * bq[0] + t[1] * bq[1] + t[2] * bq[2];
            if (ddot(s.n, x - s.c) <= 0) continue;  // behind the other patch
            const double f = point_to_polygon(x, r.n, s.v.data(), 3);
            if (!(f > 0)) continue;
            if (visible) {
                const auto& bv = vis_rule.b[size_t(q_index % vis_rule.count)];
                const DVec3 y = s.v[0] * bv[0] + s.v[1] * bv[1] + s.v[2] * bv[2];
                if (rays) ++*rays;
                if (!visible(x + r.n * eps, y + s.n * eps)) continue;
            }
            F += rule.w[size_t(q)] * sub_w * f;
        }
    }
    return r.area * F;
}

}  // namespace sr::radiosity
