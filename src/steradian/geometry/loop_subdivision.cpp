#include "steradian/geometry/loop_subdivision.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "steradian/core/error.h"

namespace sr {

namespace {

using Face = std::array<int, 3>;

uint64_t edge_key(int a, int b) {
    const auto lo = uint64_t(std::min(a, b)), hi = uint64_t(std::max(a, b));
    return (hi << 32) | lo;
}

/// A mesh's connectivity: per vertex its one-ring in pbrt-v4's order and whether it is on a
/// boundary; per edge its faces' opposite vertices.
struct Topology {
    struct Edge {
        int opposite[2] = {-1, -1};
        int faces = 0;
    };
    std::unordered_map<uint64_t, Edge> edges;
    std::vector<std::vector<int>> ring;
    std::vector<uint8_t> boundary;

    Topology(size_t num_vertices, const std::vector<Face>& faces) {
        edges.reserve(faces.size() * 2);
        for (const Face& f : faces)
            for (int k = 0; k < 3; ++k) {
                Edge& e = edges[edge_key(f[size_t(k)], f[size_t(k + 1) % 3])];
                if (e.faces == 2)
                    throw Error(
                        fmt::format("loop subdivision: the edge ({}, {}) belongs to more "
                                    "than two triangles",
                                    f[size_t(k)], f[size_t(k + 1) % 3]));
                e.opposite[e.faces++] = f[size_t(k + 2) % 3];
            }
        // Per vertex, the (a, b) of its faces (v, a, b), v first in the face's winding.
        std::vector<std::vector<std::pair<int, int>>> fans(num_vertices);
        for (const Face& f : faces)
            for (int k = 0; k < 3; ++k)
                fans[size_t(f[size_t(k)])].push_back({f[size_t(k + 1) % 3], f[size_t(k + 2) % 3]});
        ring.resize(num_vertices);
        boundary.assign(num_vertices, 0);
        for (size_t v = 0; v < num_vertices; ++v) {
            const auto& fan = fans[v];
            if (fan.empty()) continue;
            bool on_boundary = false;
            for (const auto& [a, b] : fan)
                on_boundary = on_boundary || edges[edge_key(int(v), a)].faces == 1 ||
                              edges[edge_key(int(v), b)].faces == 1;
            boundary[v] = on_boundary;
            // pbrt-v4's SDVertex::oneRing: around an interior vertex the ring steps from a
            // face's b to its a; along a boundary, from the end whose edge is open, a to b.
            std::unordered_map<int, int> next;
            for (const auto& [a, b] : fan) {
                const int from = on_boundary ? a : b, to = on_boundary ? b : a;
                if (!next.emplace(from, to).second)
                    throw Error(
                        fmt::format("loop subdivision: the triangles around vertex {} "
                                    "do not form one fan (inconsistent winding?)",
                                    v));
            }
            int start = on_boundary ? -1 : fan.front().second;
            if (on_boundary) {
                std::unordered_map<int, int> has_prev;
                for (const auto& [from, to] : next) has_prev[to] = 1;
                for (const auto& [from, to] : next)
                    if (!has_prev.count(from)) start = from;
                if (start < 0)
                    throw Error(
                        fmt::format("loop subdivision: vertex {} has no open edge to "
                                    "start its ring from",
                                    v));
            }
            std::vector<int>& r = ring[v];
            for (int x = start;;) {
                r.push_back(x);
                auto it = next.find(x);
                if (it == next.end() || it->second == start) break;
                x = it->second;
                if (r.size() > fan.size() + 1) break;
            }
            const size_t want = on_boundary ? fan.size() + 1 : fan.size();
            if (r.size() != want)
                throw Error(
                    fmt::format("loop subdivision: the triangles around vertex {} do not "
                                "form one fan",
                                v));
        }
    }
};

Float beta(int valence) { return valence == 3 ? Float(3) / 16 : Float(3) / (8 * Float(valence)); }

Float gamma(int valence) { return 1 / (Float(valence) + 3 / (8 * beta(valence))); }

Point3 weight_one_ring(const std::vector<Point3>& p, int v, const std::vector<int>& ring, Float b) {
    const int n = int(ring.size());
    Vec3 sum = Vec3(p[size_t(v)]) * (1 - Float(n) * b);
    for (int r : ring) sum += Vec3(p[size_t(r)]) * b;
    return Point3(sum.x, sum.y, sum.z);
}

Point3 weight_boundary(const std::vector<Point3>& p, int v, const std::vector<int>& ring, Float b) {
    const Vec3 sum = Vec3(p[size_t(v)]) * (1 - 2 * b) +
                     (Vec3(p[size_t(ring.front())]) + Vec3(p[size_t(ring.back())])) * b;
    return Point3(sum.x, sum.y, sum.z);
}

}  // namespace

SubdividedMesh loop_subdivide(const std::vector<Point3>& p_in, const std::vector<int>& indices,
                              int levels) {
    if (indices.size() % 3 != 0 || indices.empty())
        throw Error("loop subdivision: \"indices\" must hold a positive multiple of 3 values");
    if (levels < 0) throw Error("loop subdivision: \"levels\" must not be negative");
    for (int i : indices)
        if (i < 0 || size_t(i) >= p_in.size())
            throw Error(
                fmt::format("loop subdivision: index {} out of range (0..{})", i, p_in.size() - 1));
    if (double(indices.size() / 3) * std::pow(4.0, levels) > double(kMaxSubdividedTriangles))
        throw Error(fmt::format("loop subdivision: {} triangles at {} levels make more than {}",
                                indices.size() / 3, levels, kMaxSubdividedTriangles));
    std::vector<Point3> p = p_in;
    std::vector<Face> faces(indices.size() / 3);
    for (size_t f = 0; f < faces.size(); ++f)
        faces[f] = {indices[3 * f], indices[3 * f + 1], indices[3 * f + 2]};

    for (int level = 0; level < levels; ++level) {
        const Topology topo(p.size(), faces);
        std::vector<Point3> next(p.size());
        // Even vertices.
        for (size_t v = 0; v < p.size(); ++v) {
            const auto& ring = topo.ring[v];
            if (ring.empty())
                next[v] = p[v];
            else if (topo.boundary[v])
                next[v] = weight_boundary(p, int(v), ring, Float(1) / 8);
            else
                next[v] = weight_one_ring(p, int(v), ring, beta(int(ring.size())));
        }
        // Odd vertices, one per edge.
        std::unordered_map<uint64_t, int> odd;
        odd.reserve(topo.edges.size());
        for (const auto& [key, e] : topo.edges) {
            const int a = int(key & 0xffffffffu), b = int(key >> 32);
            Vec3 q;
            if (e.faces == 1) {
                q = (Vec3(p[size_t(a)]) + Vec3(p[size_t(b)])) * Float(0.5);
            } else {
                q = (Vec3(p[size_t(a)]) + Vec3(p[size_t(b)])) * (Float(3) / 8) +
                    (Vec3(p[size_t(e.opposite[0])]) + Vec3(p[size_t(e.opposite[1])])) *
                        (Float(1) / 8);
            }
            odd[key] = int(next.size());
            next.push_back(Point3(q.x, q.y, q.z));
        }
        // Each face into four.
        std::vector<Face> split;
        split.reserve(faces.size() * 4);
        for (const Face& f : faces) {
            const int e01 = odd[edge_key(f[0], f[1])], e12 = odd[edge_key(f[1], f[2])],
                      e20 = odd[edge_key(f[2], f[0])];
            split.push_back({f[0], e01, e20});
            split.push_back({f[1], e12, e01});
            split.push_back({f[2], e20, e12});
            split.push_back({e01, e12, e20});
        }
        p = std::move(next);
        faces = std::move(split);
    }

    // Push the vertices to the limit surface, then the limit normals from the limit ring.
    const Topology topo(p.size(), faces);
    SubdividedMesh out;
    out.p.resize(p.size());
    for (size_t v = 0; v < p.size(); ++v) {
        const auto& ring = topo.ring[v];
        out.p[v] = ring.empty()       ? p[v]
                   : topo.boundary[v] ? weight_boundary(p, int(v), ring, Float(1) / 5)
                                      : weight_one_ring(p, int(v), ring, gamma(int(ring.size())));
    }
    out.n.resize(p.size());
    for (size_t v = 0; v < p.size(); ++v) {
        const auto& ring = topo.ring[v];
        const int n = int(ring.size());
        if (n == 0) continue;
        auto q = [&](int k) { return Vec3(out.p[size_t(ring[size_t(k)])]); };
        const Vec3 pv(out.p[v]);
        Vec3 s(0, 0, 0), t(0, 0, 0);
        if (!topo.boundary[v]) {
            for (int j = 0; j < n; ++j) {
                s += q(j) * std::cos(2 * kPi * Float(j) / Float(n));
                t += q(j) * std::sin(2 * kPi * Float(j) / Float(n));
            }
        } else {
            s = q(n - 1) - q(0);
            if (n == 2) {
                t = q(0) + q(1) - pv * 2;
            } else if (n == 3) {
                t = q(1) - pv;
            } else if (n == 4) {
                t = q(1) * 2 + q(2) * 2 - q(0) - q(3) - pv * 2;
            } else {
                const Float theta = kPi / Float(n - 1);
                t = (q(0) + q(n - 1)) * std::sin(theta);
                for (int k = 1; k < n - 1; ++k)
                    t += q(k) * ((2 * std::cos(theta) - 2) * std::sin(Float(k) * theta));
                t = -t;
            }
        }
        const Vec3 c = cross(s, t);
        out.n[v] = Normal3(c.x, c.y, c.z);
    }
    out.indices.reserve(faces.size() * 3);
    for (const Face& f : faces) out.indices.insert(out.indices.end(), f.begin(), f.end());
    return out;
}

}  // namespace sr
