#include "steradian/integrators/radiosity/radiosity.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <tuple>
#include <cmath>
#include <mutex>
#include <thread>
#include <variant>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/bsdf/bsdf.h"
#include "steradian/core/error.h"
#include "steradian/core/output_file.h"
#include "steradian/integrators/radiosity/hierarchical.h"
#include "steradian/material/material.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/warp.h"
#include "steradian/scene/scene.h"
#include "steradian/spectrum/color.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

using radiosity::DVec3;
using radiosity::r2;
using radiosity::kBands;
constexpr int kGroups = kBands / kSpectrumSamples;

namespace {

/// The four band wavelengths of group g (their pdfs are unused: 1).
SampledWavelengths band_group(int g) {
    SampledWavelengths w;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        w.lambda[i] = radiosity::band_lambda(g * kSpectrumSamples + i);
        w.pdf[i] = 1;
    }
    return w;
}

SurfaceHit point_vertex(DVec3 p, DVec3 n) {
    SurfaceHit v;
    v.p = p.f();
    const Float err = (std::abs(v.p.x) + std::abs(v.p.y) + std::abs(v.p.z) + 1) * Float(4e-6);
    v.p_error = Vec3(err, err, err);
    v.ng = v.ns = v.wo = n.f();
    return v;
}

bool is_lambert(const std::optional<Bsdf>& b) {
    return b && std::holds_alternative<LambertLobe>(b->lobe());
}

struct Unknown {
    int patch = -1;
    int side = 0;
    DVec3 c, n;  ///< centroid, side normal
    std::array<DVec3, 3> v;
    double area = 0, diam = 0;
};

/// Direct irradiance arriving at point x (side normal n) from every light, one light sample
/// per light and sample point; `bands` receives it for the 48 bands (added, weighted by w).
class DirectLight {
public:
    DirectLight(const Scene& s) : m_scene(s) {
        for (int g = 0; g < kGroups; ++g) m_groups[g] = band_group(g);
    }
    /// Adds w * E(band) at x for light l with light sample u; returns the shadow rays cast.
    int add(int l, DVec3 x, DVec3 n, Point2 u, double w, double* bands, int groups = kGroups,
            int first_group = 0) const {
        const Light& light = m_scene.lights[size_t(l)];
        const SurfaceHit v = point_vertex(x, n);
        const LightSampleContext ctx{v.p, v.p_error, v.ng};
        // The first group whose sample exists (a spectrum may be zero in some bands, and a
        // light returns no sample then) gives the geometry and the one shadow ray.
        std::optional<LightLiSample> ls;
        int g0 = first_group;
        for (; g0 < first_group + groups; ++g0) {
            ls = sample_li(light, ctx, u, m_groups[size_t(g0)]);
            if (ls && ls->pdf_sa > 0) break;
        }
        if (!ls || !(ls->pdf_sa > 0)) return 0;
        const double cosv = double(dot(ls->wi, v.ng));
        if (!(cosv > 0)) return 0;
        Ray shadow = ls->at_infinity ? spawn_ray(v, ls->wi)
                     : ls->delta     ? spawn_ray_to(v, ls->p_light)
                                     : spawn_ray_between(v, ls->p_light, ls->p_error, ls->n_light);
        if (m_scene.occluded(shadow)) return 1;
        const double f = w * cosv / double(ls->pdf_sa);
        // An area light's sample is the same point for every wavelength: only its radiance
        // there is evaluated for the other groups (its direction's factor once).
        std::array<SampledSpectrum, kGroups> Lg;
        const int rest = first_group + groups - (g0 + 1);
        if (rest > 0 && std::holds_alternative<DiffuseAreaLight>(light))
            light_emitted(light, ls->p_light, ls->n_light, -ls->wi, &m_groups[size_t(g0 + 1)],
                          rest, &Lg[size_t(g0 + 1)]);
        for (int g = g0; g < first_group + groups; ++g) {
            SampledSpectrum L = ls->L;
            if (g != g0) {
                if (std::holds_alternative<DiffuseAreaLight>(light)) {
                    L = Lg[size_t(g)];
                } else {
                    auto lg = sample_li(light, ctx, u, m_groups[size_t(g)]);
                    L = lg ? lg->L : SampledSpectrum(0);
                }
            }
            for (int i = 0; i < kSpectrumSamples; ++i)
                bands[g * kSpectrumSamples + i] += f * double(L[i]);
        }
        return 1;
    }
    bool is_delta(int l) const {
        return std::visit([](const auto& x) { return x.is_delta(); }, m_scene.lights[size_t(l)]);
    }

private:
    const Scene& m_scene;
    std::array<SampledWavelengths, kGroups> m_groups;
};

/// Photopic weights of the bands (trapezoid rule, 10 nm).
std::array<double, kBands> band_ybar() {
    std::array<double, kBands> w{};
    for (int k = 0; k < kBands; ++k)
        w[size_t(k)] = double(cie_y()(radiosity::band_lambda(k))) * radiosity::kStepNm *
                       ((k == 0 || k == kBands - 1) ? 0.5 : 1.0);
    return w;
}

}  // namespace

bool radiosity_models_exactly(const Scene& scene, std::string* why) {
    auto no = [&](std::string s) {
        if (why) *why = std::move(s);
        return false;
    };
    if (!scene.media.empty()) return no("the scene has participating media");
    if (!scene.instances.empty()) return no("the scene has object instances");
    size_t triangles = 0;
    for (int si : scene.top_level_shapes)
        if (const auto* m = std::get_if<TriangleMesh>(&scene.shapes[size_t(si)].geometry))
            triangles += m->num_triangles();
    if (triangles > size_t(scene.integrator.radiosity.max_patches))
        return no(fmt::format("{} triangles, more than the radiosity mesh's {} patches",
                              triangles, scene.integrator.radiosity.max_patches));
    for (int si : scene.top_level_shapes) {
        const ShapeEntry& e = scene.shapes[size_t(si)];
        if (e.material < 0) continue;
        if (!std::holds_alternative<TriangleMesh>(e.geometry))
            return no(fmt::format("shape {} is not a triangle mesh", si));
        if (e.alpha) return no(fmt::format("shape {} has an alpha mask", si));
        const Material& mat = scene.materials[size_t(e.material)];
        if (!std::holds_alternative<DiffuseMaterial>(mat))
            return no(fmt::format("shape {} has a material other than \"diffuse\"", si));
        const auto& d = std::get<DiffuseMaterial>(mat);
        if (d.normal_map || d.displacement >= 0)
            return no(fmt::format("shape {} has a normal or bump map", si));
    }
    return true;
}

int RadiositySolution::leaf_at(const SurfaceHit& h, double* ob1, double* ob2) const {
    if (h.shape < 0 || size_t(h.shape) >= m_shape_first.size()) return -1;
    const int first = m_shape_first[size_t(h.shape)];
    if (first < 0) return -1;
    const Coarse& c = m_coarse[size_t(first) + h.prim];
    if (c.root < 0) return -1;
    const DVec3 v = DVec3(h.p) - c.p0;
    const double d00 = ddot(c.e1, c.e1), d01 = ddot(c.e1, c.e2), d11 = ddot(c.e2, c.e2);
    const double d20 = ddot(v, c.e1), d21 = ddot(v, c.e2);
    const double den = d00 * d11 - d01 * d01;
    double b1 = den != 0 ? (d11 * d20 - d01 * d21) / den : 0;
    double b2 = den != 0 ? (d00 * d21 - d01 * d20) / den : 0;
    b1 = std::clamp(b1, 0.0, 1.0);
    b2 = std::clamp(b2, 0.0, 1.0);
    int node = c.root;
    while (m_nodes[size_t(node)].child >= 0) {
        const int ch = m_nodes[size_t(node)].child;
        if (b1 >= 0.5) {
            node = ch + 1;
            b1 = 2 * b1 - 1;
            b2 = 2 * b2;
        } else if (b2 >= 0.5) {
            node = ch + 2;
            b1 = 2 * b1;
            b2 = 2 * b2 - 1;
        } else if (b1 + b2 <= 0.5) {
            node = ch;
            b1 = 2 * b1;
            b2 = 2 * b2;
        } else {
            node = ch + 3;
            b1 = 1 - 2 * b1;
            b2 = 1 - 2 * b2;
        }
    }
    if (ob1) *ob1 = b1;
    if (ob2) *ob2 = b2;
    return m_nodes[size_t(node)].patch;
}

bool RadiositySolution::meshed(const SurfaceHit& h) const { return leaf_at(h) >= 0; }

bool RadiositySolution::side_at(const SurfaceHit& h, int& u, double& b1, double& b2,
                                double* area) const {
    const int leaf = leaf_at(h, &b1, &b2);
    if (leaf < 0) return false;
    const Patch& p = m_patches[size_t(leaf)];
    if (area) *area = p.area;
    u = p.unknown[ddot(DVec3(h.wo), p.n) >= 0 ? 0 : 1];
    return true;
}

bool RadiositySolution::weighted_exitance(const SurfaceHit& h, MeterWeighting w, double& Bw,
                                          double* area) const {
    double b1 = 0, b2 = 0;
    int u = -1;
    if (!side_at(h, u, b1, b2, area)) return false;
    Bw = 0;
    if (u < 0) return true;
    const size_t iw = size_t(w);
    if (m_Bv.empty()) {
        Bw = m_Bw[size_t(u) * 3 + iw];
    } else {
        const double* v = &m_Bw[size_t(u) * 9];
        Bw = std::max(0.0, 1 - b1 - b2) * v[iw] + b1 * v[3 + iw] + b2 * v[6 + iw];
    }
    return true;
}

void RadiositySolution::weigh_bands() {
    // Per weighting, the integral of the weight times each band's hat function (the linear
    // interpolation exitance() applies between band centres; constant beyond the first and
    // last), by the midpoint rule at 0.05 nm over the sampled range 360-830 nm.
    std::array<std::array<double, kBands>, 3> W{};
    const MeterWeighting kinds[3] = {MeterWeighting::Photopic, MeterWeighting::Scotopic,
                                     MeterWeighting::Radiometric};
    static_assert(int(MeterWeighting::Photopic) < 3 && int(MeterWeighting::Scotopic) < 3 &&
                  int(MeterWeighting::Radiometric) < 3);
    constexpr double dl = 0.05;
    for (const MeterWeighting kind : kinds) {
        Meter m;
        m.weighting = kind;
        auto& wk = W[size_t(kind)];
        for (double l = kLambdaMin + dl / 2; l < kLambdaMax; l += dl) {
            const double wl = double(m.spectral_weight(Float(l))) * dl;
            const double t = (l - radiosity::kFirstNm) / radiosity::kStepNm;
            const int k = std::clamp(int(std::floor(t)), 0, kBands - 2);
            const double f = std::clamp(t - k, 0.0, 1.0);
            wk[size_t(k)] += (1 - f) * wl;
            wk[size_t(k) + 1] += f * wl;
        }
    }
    const size_t N = m_B.size() / kBands, C = m_Bv.empty() ? 1 : 3;
    m_Bw.assign(N * C * 3, 0.0);
    for (size_t u = 0; u < N; ++u)
        for (size_t c = 0; c < C; ++c) {
            const float* b = m_Bv.empty() ? &m_B[u * kBands] : &m_Bv[(u * 3 + c) * kBands];
            for (size_t iw = 0; iw < 3; ++iw) {
                double sum = 0;
                for (int k = 0; k < kBands; ++k) sum += W[iw][size_t(k)] * double(b[k]);
                m_Bw[(u * C + c) * 3 + iw] = sum;
            }
        }
}

bool RadiositySolution::exitance(const SurfaceHit& h, const SampledWavelengths& lambda,
                                 SampledSpectrum& B, double* area) const {
    double b1 = 0, b2 = 0;
    int u = -1;
    if (!side_at(h, u, b1, b2, area)) return false;
    B = SampledSpectrum(0);
    if (u < 0) return true;
    // Linear in the patch from its corners' values (Gouraud's smooth shading of a radiosity
    // solution), or the patch's constant.
    const double b0 = std::max(0.0, 1 - b1 - b2);
    for (int i = 0; i < kSpectrumSamples; ++i) {
        const Float t = (lambda.lambda[i] - radiosity::kFirstNm) / radiosity::kStepNm;
        const int k = std::clamp(int(std::floor(t)), 0, kBands - 2);
        const Float f = std::clamp(t - Float(k), Float(0), Float(1));
        if (m_Bv.empty()) {
            const float* b = &m_B[size_t(u) * kBands];
            B[i] = (1 - f) * b[k] + f * b[k + 1];
        } else {
            const float* v = &m_Bv[size_t(u) * 3 * kBands];
            const double lo = b0 * v[k] + b1 * v[kBands + k] + b2 * v[2 * kBands + k];
            const double hi =
                b0 * v[k + 1] + b1 * v[kBands + k + 1] + b2 * v[2 * kBands + k + 1];
            B[i] = Float((1 - f) * lo + f * hi);
        }
    }
    return true;
}

uint64_t RadiositySolution::digest() const {
    uint64_t h = 0xcbf29ce484222325ull;
    auto mix = [&h](const void* p, size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
    };
    const uint64_t sizes[3] = {m_patches.size(), m_B.size(), m_nodes.size()};
    mix(sizes, sizeof sizes);
    for (const Patch& p : m_patches) {
        for (const radiosity::DVec3& v : p.p) mix(&v, sizeof v);
        mix(p.unknown, sizeof p.unknown);
    }
    if (!m_B.empty()) mix(m_B.data(), m_B.size() * sizeof(float));
    if (!m_Bv.empty()) mix(m_Bv.data(), m_Bv.size() * sizeof(float));
    return h;
}

std::unique_ptr<RadiositySolution> solve_radiosity(const Scene& scene, const RadiosityParams& prm,
                                                  int threads) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (!scene.media.empty())
        throw Error("the radiosity method does not support participating media (use the path "
                    "tracer: Integrator \"volpath\", measure --method path)");
    auto sol = std::make_unique<RadiositySolution>();
    RadiositySolution& S = *sol;
    RadiosityStats& st = S.m_stats;
    if (threads <= 0) threads = int(std::thread::hardware_concurrency());
    tbb::task_arena arena(std::max(1, threads));
    const MaterialContext mctx = scene.material_context();
    const DirectLight direct(scene);
    const std::array<double, kBands> ybar = band_ybar();
    const double scene_diam = std::max(1e-6, double(length(scene.bounds.diagonal())));
    const double eps = 1e-6 * scene_diam;

    // ---- coarse triangles: the scene's diffuse triangles ------------------------------------
    S.m_shape_first.assign(scene.shapes.size(), -1);
    std::vector<char> is_top(scene.shapes.size(), 0);
    for (int si : scene.top_level_shapes) is_top[size_t(si)] = 1;
    for (size_t si = 0; si < scene.shapes.size(); ++si) {
        const ShapeEntry& e = scene.shapes[si];
        if (e.material < 0) continue;
        if (!is_top[si]) {
            st.notes.push_back(fmt::format("shape {} (in an object instance) is not meshed", si));
            continue;
        }
        const auto* mesh = std::get_if<TriangleMesh>(&e.geometry);
        if (!mesh) {
            const char* kind = std::holds_alternative<Sphere>(e.geometry)   ? "sphere"
                               : std::holds_alternative<Disk>(e.geometry)   ? "disk"
                               : std::holds_alternative<Cylinder>(e.geometry) ? "cylinder"
                                                                              : "curve";
            st.notes.push_back(fmt::format("shape {} (a {}) is not meshed: it reflects nothing "
                                           "in the radiosity pass", si, kind));
            continue;
        }
        S.m_shape_first[si] = int(S.m_coarse.size());
        const auto& P = *mesh->p;
        const auto& I = *mesh->indices;
        size_t non_diffuse = 0;
        for (size_t t = 0; t < mesh->num_triangles(); ++t) {
            RadiositySolution::Coarse c;
            c.shape = int(si);
            c.prim = uint32_t(t);
            const DVec3 p0(P[I[3 * t]]), p1(P[I[3 * t + 1]]), p2(P[I[3 * t + 2]]);
            c.p0 = p0;
            c.e1 = p1 - p0;
            c.e2 = p2 - p0;
            const DVec3 cr = dcross(c.e1, c.e2);
            const double len = dlength(cr);
            if (len > 0) {
                c.n = cr * (1 / len);
                SurfaceHit h;
                mesh->fill_hit(t, Float(1.0 / 3), Float(1.0 / 3), h);
                h.shape = int(si);
                h.prim = uint32_t(t);
                h.material = e.material;
                h.wo = h.ns;
                bool lambert = true, black = true;
                for (int g = 0; g < kGroups && lambert; ++g) {
                    SampledWavelengths lam = band_group(g);
                    auto b = make_bsdf(scene.materials[size_t(e.material)], mctx, h, lam);
                    lambert = is_lambert(b);
                    if (lambert) black = black && std::get<LambertLobe>(b->lobe()).r.is_zero();
                }
                if (lambert)
                    c.root = 0;  // diffuse: meshed below
                else
                    ++non_diffuse;
                c.black = lambert && black;
            }
            S.m_coarse.push_back(c);
        }
        if (non_diffuse > 0)
            st.notes.push_back(fmt::format("shape {}: {} non-diffuse triangles are black "
                                           "occluders in the radiosity pass", si, non_diffuse));
    }

    // ---- which sides can receive light --------------------------------------------------------
    // A side is active if a light or a point of another diffuse triangle lies strictly in
    // front of it (infinite and distant lights, and area lights on spheres and disks, count
    // as everywhere).
    std::vector<DVec3> light_points;
    bool light_everywhere = false;
    for (const Light& l : scene.lights) {
        if (const auto* pl = std::get_if<PointLight>(&l))
            light_points.push_back(DVec3(pl->p));
        else if (const auto* sl = std::get_if<SpotLight>(&l))
            light_points.push_back(DVec3(sl->p));
        else if (const auto* gl = std::get_if<GoniometricLight>(&l))
            light_points.push_back(DVec3(gl->p));
        else if (const auto* al = std::get_if<DiffuseAreaLight>(&l); al && al->triangle)
            for (Point3 q : {al->triangle->p0, al->triangle->p1, al->triangle->p2})
                light_points.push_back(DVec3(q));
        else
            light_everywhere = true;
    }
    const size_t nc = S.m_coarse.size();
    std::vector<std::array<char, 2>> active(nc, {0, 0});
    {
        std::vector<size_t> diffuse;
        for (size_t i = 0; i < nc; ++i)
            if (S.m_coarse[i].root >= 0 && !S.m_coarse[i].black) diffuse.push_back(i);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), diffuse.size(), [&](size_t a) {
                const auto& c = S.m_coarse[diffuse[a]];
                for (int side = 0; side < 2; ++side) {
                    const DVec3 n = side == 0 ? c.n : c.n * -1.0;
                    auto in_front = [&](DVec3 q) { return ddot(n, q - c.p0) > eps; };
                    bool act = light_everywhere;
                    for (size_t k = 0; k < light_points.size() && !act; ++k)
                        act = in_front(light_points[k]);
                    for (size_t b = 0; b < diffuse.size() && !act; ++b) {
                        if (b == a) continue;
                        const auto& o = S.m_coarse[diffuse[b]];
                        act = in_front(o.p0) || in_front(o.p0 + o.e1) || in_front(o.p0 + o.e2);
                    }
                    active[diffuse[a]][size_t(side)] = act;
                }
            });
        });
    }

    // ---- initial mesh: uniform midpoint subdivision to the patch size --------------------------
    auto tri_area = [](DVec3 e1, DVec3 e2) { return 0.5 * dlength(dcross(e1, e2)); };
    auto longest = [](DVec3 a, DVec3 b, DVec3 c) {
        return std::max({dlength(b - a), dlength(c - b), dlength(a - c)});
    };
    double active_area = 0;
    for (size_t i = 0; i < nc; ++i) {
        const auto& c = S.m_coarse[i];
        if (c.root < 0) continue;
        active_area += tri_area(c.e1, c.e2) * double(active[i][0] + active[i][1]);
    }
    auto level_for = [&](size_t i, double h) {
        const auto& c = S.m_coarse[i];
        const double L = longest(c.p0, c.p0 + c.e1, c.p0 + c.e2);
        int lv = 0;
        while (lv < 12 && L / double(1 << lv) > h) ++lv;
        return lv;
    };
    auto count_for = [&](double h) {
        double n = 0;
        for (size_t i = 0; i < nc; ++i)
            if (S.m_coarse[i].root >= 0 && (active[i][0] || active[i][1]))
                n += std::pow(4.0, level_for(i, h)) * double(active[i][0] + active[i][1]);
        return n;
    };
    {
        // At least one patch per side: a mesh finer than the budget is refused (the exchanges
        // are a dense matrix of 4 N^2 bytes).
        size_t sides = 0;
        for (size_t i = 0; i < nc; ++i)
            if (S.m_coarse[i].root >= 0) sides += size_t(active[i][0] + active[i][1]);
        if (sides > size_t(prm.max_patches))
            throw Error(fmt::format(
                "the radiosity method needs at least {} patches (one per lit side of each "
                "diffuse triangle), more than \"maxpatches\" {}: raise it{} or use the path "
                "tracer", sides, prm.max_patches,
                prm.hierarchical ? "" : " (the \"matrix\" solver's form factors take 4 "
                                        "maxpatches^2 bytes)"));
    }
    double h = prm.patch_size;
    if (h > 0 && count_for(h) > double(prm.max_patches)) {
        st.notes.push_back(fmt::format("\"patchsize\" {} would need more than \"maxpatches\" "
                                       "{} patches: coarsened", h, prm.max_patches));
        h = 0;
    }
    if (!(h > 0)) {
        const double target = std::max(1.0, double(prm.max_patches) / 3);
        h = std::sqrt(4 * std::max(active_area, 1e-12) / target / std::sqrt(3.0));
        for (int i = 0; i < 400 && count_for(h) > double(prm.max_patches) / 2; ++i) h *= 1.1;
    }
    // Nodes: for each coarse triangle a tree of midpoint splits.
    struct Tri {
        DVec3 a, b, c;
    };
    std::vector<Tri> node_tri;
    std::vector<int> node_coarse;
    std::vector<int> node_level;
    auto add_node = [&](Tri t, int coarse, int level) {
        S.m_nodes.push_back({});
        node_tri.push_back(t);
        node_coarse.push_back(coarse);
        node_level.push_back(level);
        return int(S.m_nodes.size()) - 1;
    };
    auto split = [&](int node) {
        const Tri t = node_tri[size_t(node)];
        const DVec3 m01 = (t.a + t.b) * 0.5, m12 = (t.b + t.c) * 0.5, m02 = (t.a + t.c) * 0.5;
        const int coarse = node_coarse[size_t(node)], lv = node_level[size_t(node)] + 1;
        const int first = add_node({t.a, m01, m02}, coarse, lv);
        add_node({m01, t.b, m12}, coarse, lv);
        add_node({m02, m12, t.c}, coarse, lv);
        add_node({m12, m02, m01}, coarse, lv);
        S.m_nodes[size_t(node)].child = first;
    };
    std::vector<int> leaves;  // nodes
    for (size_t i = 0; i < nc; ++i) {
        auto& c = S.m_coarse[i];
        if (c.root < 0) continue;
        ++st.diffuse_triangles;
        c.root = add_node({c.p0, c.p0 + c.e1, c.p0 + c.e2}, int(i), 0);
        const int lv = (active[i][0] || active[i][1]) ? level_for(i, h) : 0;
        std::vector<int> stack{c.root};
        while (!stack.empty()) {
            const int nd = stack.back();
            stack.pop_back();
            if (node_level[size_t(nd)] < lv) {
                split(nd);
                const int ch = S.m_nodes[size_t(nd)].child;
                for (int k = 3; k >= 0; --k) stack.push_back(ch + k);
            } else {
                leaves.push_back(nd);
            }
        }
    }
    auto unknowns_of = [&](const std::vector<int>& ls) {
        size_t n = 0;
        for (int nd : ls) {
            const auto& a = active[size_t(node_coarse[size_t(nd)])];
            n += size_t(a[0] + a[1]);
        }
        return n;
    };

    const auto t_mesh = Clock::now();
    // ---- adaptive subdivision where the direct irradiance varies -----------------------------
    // The photopic direct irradiance at the leaf's corners (pulled 2 % towards its centroid)
    // and centroid, per active side; a leaf whose spread exceeds `subdivide` times its mean
    // plus a fifth of the scene's mean is split, the largest spreads first, within
    // max_patches. Three rounds.
    std::atomic<uint64_t> rays{0};
    auto photopic_direct = [&](DVec3 x, DVec3 n, uint64_t key) {
        double bands[kBands] = {};
        uint64_t r = 0;
        for (int l = 0; l < int(scene.lights.size()); ++l) {
            const int ns = direct.is_delta(l) ? 1 : 4;
            for (int s = 0; s < ns; ++s)
                r += uint64_t(direct.add(l, x, n, r2(uint64_t(s), hash(key, uint64_t(l))),
                                         1.0 / ns, bands));
        }
        rays += r;
        double y = 0;
        for (int k = 0; k < kBands; ++k) y += ybar[size_t(k)] * bands[k];
        return y;
    };
    // Per node, once: the spread and mean of its samples (-1: not computed yet).
    std::vector<double> node_spread, node_mean;
    for (int round = 0; round < 3 && prm.subdivide > 0; ++round) {
        const size_t nl = leaves.size();
        node_spread.resize(S.m_nodes.size(), -1);
        node_mean.resize(S.m_nodes.size(), 0);
        std::vector<int> todo;
        for (int nd : leaves)
            if (node_spread[size_t(nd)] < 0) todo.push_back(nd);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), todo.size(), [&](size_t ti) {
                const int nd = todo[ti];
                const auto& a = active[size_t(node_coarse[size_t(nd)])];
                const Tri t = node_tri[size_t(nd)];
                const DVec3 g = (t.a + t.b + t.c) * (1.0 / 3);
                const DVec3 n = S.m_coarse[size_t(node_coarse[size_t(nd)])].n;
                double lo = kInfinity, hi = 0, sum = 0;
                int cnt = 0;
                for (int side = 0; side < 2; ++side) {
                    if (!a[size_t(side)]) continue;
                    const DVec3 ns = side == 0 ? n : n * -1.0;
                    const DVec3 pts[4] = {g, t.a + (g - t.a) * 0.02, t.b + (g - t.b) * 0.02,
                                          t.c + (g - t.c) * 0.02};
                    for (int k = 0; k < 4; ++k) {
                        const double y = photopic_direct(pts[k] + ns * eps, ns,
                                                         hash(uint64_t(nd), uint64_t(k), uint64_t(side)));
                        lo = std::min(lo, y);
                        hi = std::max(hi, y);
                        sum += y;
                        ++cnt;
                    }
                }
                node_spread[size_t(nd)] = cnt > 0 ? hi - lo : 0;
                node_mean[size_t(nd)] = cnt > 0 ? sum / cnt : 0;
            });
        });
        std::vector<double> spread(nl, 0), mean(nl, 0);
        for (size_t li = 0; li < nl; ++li) {
            spread[li] = node_spread[size_t(leaves[li])];
            mean[li] = node_mean[size_t(leaves[li])];
        }
        double global = 0, garea = 0;
        for (size_t li = 0; li < nl; ++li) {
            const Tri t = node_tri[size_t(leaves[li])];
            const double a = tri_area(t.b - t.a, t.c - t.a);
            global += mean[li] * a;
            garea += a;
        }
        global = garea > 0 ? global / garea : 0;
        std::vector<std::pair<double, size_t>> cand;
        for (size_t li = 0; li < nl; ++li) {
            const double ref = mean[li] + 0.2 * global;
            const double v = ref > 0 ? spread[li] / ref : 0;
            if (v > double(prm.subdivide) && node_level[size_t(leaves[li])] < 16)
                cand.push_back({v, li});
        }
        if (cand.empty()) break;
        std::stable_sort(cand.begin(), cand.end(),
                         [](const auto& x, const auto& y) { return x.first > y.first; });
        size_t have = unknowns_of(leaves);
        std::vector<char> do_split(nl, 0);
        for (const auto& [v, li] : cand) {
            const auto& a = active[size_t(node_coarse[size_t(leaves[li])])];
            const size_t add = 3 * size_t(a[0] + a[1]);
            if (have + add > size_t(prm.max_patches)) break;
            have += add;
            do_split[li] = 1;
        }
        std::vector<int> next;
        bool any = false;
        for (size_t li = 0; li < nl; ++li) {
            const int nd = leaves[li];
            if (!do_split[li]) {
                next.push_back(nd);
                continue;
            }
            any = true;
            split(nd);
            const int ch = S.m_nodes[size_t(nd)].child;
            for (int k = 0; k < 4; ++k) next.push_back(ch + k);
        }
        leaves = std::move(next);
        if (!any) break;
    }
    // Leaves in node order (deterministic, and the PLY's order).
    std::sort(leaves.begin(), leaves.end());

    const auto t_adaptive = Clock::now();
    // ---- patches and unknowns ------------------------------------------------------------------
    std::vector<Unknown> U;
    for (int nd : leaves) {
        const int ci = node_coarse[size_t(nd)];
        const Tri t = node_tri[size_t(nd)];
        RadiositySolution::Patch p;
        p.p = {t.a, t.b, t.c};
        p.n = S.m_coarse[size_t(ci)].n;
        p.area = tri_area(t.b - t.a, t.c - t.a);
        p.material = scene.shapes[size_t(S.m_coarse[size_t(ci)].shape)].material;
        const int pi = int(S.m_patches.size());
        S.m_nodes[size_t(nd)].patch = pi;
        for (int side = 0; side < 2; ++side) {
            if (!active[size_t(ci)][size_t(side)]) continue;
            Unknown u;
            u.patch = pi;
            u.side = side;
            u.v = p.p;
            u.c = (t.a + t.b + t.c) * (1.0 / 3);
            u.n = side == 0 ? p.n : p.n * -1.0;
            u.area = p.area;
            u.diam = longest(t.a, t.b, t.c);
            p.unknown[side] = int(U.size());
            U.push_back(u);
        }
        S.m_patches.push_back(p);
    }
    const size_t N = U.size();
    st.patches = S.m_patches.size();
    st.unknowns = N;

    const auto t_direct = Clock::now();
    // ---- reflectance and direct irradiance per unknown -----------------------------------------
    std::vector<double> rho(N * kBands, 0), E(N * kBands, 0);
    arena.execute([&] {
        tbb::parallel_for(size_t(0), N, [&](size_t ui) {
            const Unknown& u = U[ui];
            const RadiositySolution::Patch& p = S.m_patches[size_t(u.patch)];
            // Reflectance at the centroid, from the scene's material.
            const int ci = node_coarse[size_t(leaves[size_t(u.patch)])];
            const auto& c = S.m_coarse[size_t(ci)];
            const ShapeEntry& e = scene.shapes[size_t(c.shape)];
            const auto& mesh = std::get<TriangleMesh>(e.geometry);
            const DVec3 v = u.c - c.p0;
            const double d00 = ddot(c.e1, c.e1), d01 = ddot(c.e1, c.e2), d11 = ddot(c.e2, c.e2);
            const double d20 = ddot(v, c.e1), d21 = ddot(v, c.e2), den = d00 * d11 - d01 * d01;
            const Float b1 = Float((d11 * d20 - d01 * d21) / den);
            const Float b2 = Float((d00 * d21 - d01 * d20) / den);
            SurfaceHit hh;
            mesh.fill_hit(c.prim, b1, b2, hh);
            hh.shape = c.shape;
            hh.prim = c.prim;
            hh.material = e.material;
            hh.wo = u.n.f();
            for (int g = 0; g < kGroups; ++g) {
                SampledWavelengths lam = band_group(g);
                auto b = make_bsdf(scene.materials[size_t(e.material)], mctx, hh, lam);
                if (!is_lambert(b)) continue;
                const auto& r = std::get<LambertLobe>(b->lobe()).r;
                for (int i = 0; i < kSpectrumSamples; ++i)
                    rho[ui * kBands + size_t(g * kSpectrumSamples + i)] =
                        std::clamp(double(r[i]), 0.0, 0.9999);
            }
            // Direct irradiance averaged over the patch: delta lights at the degree-5 rule's
            // points, other lights by direct_samples points jointly stratified (R2) over the
            // patch and the light.
            double* Eu = &E[ui * kBands];
            uint64_t r = 0;
            const auto& rule = radiosity::triangle_rule(5);
            const int ns = std::max(1, prm.direct_samples);
            for (int l = 0; l < int(scene.lights.size()); ++l) {
                if (direct.is_delta(l)) {
                    for (int q = 0; q < rule.count; ++q) {
                        const auto& b = rule.b[size_t(q)];
                        const DVec3 x = p.p[0] * b[0] + p.p[1] * b[1] + p.p[2] * b[2];
                        r += uint64_t(direct.add(l, x + u.n * eps, u.n, Point2(0.5f, 0.5f),
                                                 rule.w[size_t(q)], Eu));
                    }
                } else {
                    for (int s = 0; s < ns; ++s) {
                        const Point2 up = r2(uint64_t(s), hash(uint64_t(ui), uint64_t(l), 1u));
                        const Point2 ul = r2(uint64_t(s), hash(uint64_t(ui), uint64_t(l), 2u));
                        const auto bt = sample_uniform_triangle(up);
                        const DVec3 x = p.p[0] * double(bt[0]) + p.p[1] * double(bt[1]) +
                                        p.p[2] * double(bt[2]);
                        r += uint64_t(direct.add(l, x + u.n * eps, u.n, ul, 1.0 / ns, Eu));
                    }
                }
            }
            rays += r;
        });
    });

    // Visibility as the gather and the path tracer's continued paths see it: through
    // "interface" surfaces (a luminous opening, a medium boundary), which scatter nothing.
    bool has_interface = false;
    for (int si : scene.top_level_shapes)
        has_interface = has_interface || scene.shapes[size_t(si)].material < 0;
    const radiosity::Visibility visible = [&](DVec3 o, DVec3 t) {
        const Ray ray{o.f(), (t - o).f(), 1 - Float(1e-4)};
        return has_interface ? !scene.occluded_by_surface(ray) : !scene.occluded(ray);
    };
    const radiosity::VisibilityBatch visible_batch = [&](const DVec3* o, const DVec3* t, int n) {
        Ray packet[Scene::kRayPacket];
        for (int i = 0; i < n; ++i) packet[i] = Ray{o[i].f(), (t[i] - o[i]).f(), 1 - Float(1e-4)};
        const unsigned bits = (1u << n) - 1;
        const unsigned blocked = has_interface ? scene.occluded_by_surface_packet(packet, bits)
                                               : scene.occluded_packet(packet, bits);
        return bits & ~blocked;
    };
    S.m_B.assign(N * kBands, 0.f);
    const auto t_links = Clock::now();
    if (prm.hierarchical) {
        // ---- hierarchical radiosity over the patch trees (hierarchical.cpp) --------------------
        // A tree per lit side of each coarse triangle, its nodes the mesh's (sub-)triangles.
        std::vector<radiosity::HierNode> hn;
        std::vector<int> roots;
        auto build = [&](auto&& self, int nd, int side, size_t at) -> void {
            const Tri t = node_tri[size_t(nd)];
            hn[at].g = radiosity::make_patch(t.a, t.b, t.c, side == 1);
            const int ch = S.m_nodes[size_t(nd)].child;
            if (ch < 0) {
                hn[at].unknown = S.m_patches[size_t(S.m_nodes[size_t(nd)].patch)].unknown[side];
                return;
            }
            const size_t first = hn.size();
            hn.resize(first + 4);
            hn[at].child = int(first);
            for (int c = 0; c < 4; ++c) self(self, ch + c, side, first + size_t(c));
        };
        for (size_t i = 0; i < nc; ++i) {
            const auto& c = S.m_coarse[i];
            if (c.root < 0) continue;
            for (int side = 0; side < 2; ++side) {
                if (!active[i][size_t(side)]) continue;
                roots.push_back(int(hn.size()));
                hn.emplace_back();
                build(build, c.root, side, hn.size() - 1);
            }
        }
        radiosity::HierParams hp;
        hp.link_error = double(prm.link_error);
        hp.residual = std::max(double(prm.residual), 1e-12);
        hp.eps = eps;
        radiosity::HierStats hs;
        const std::vector<double> yb(ybar.begin(), ybar.end());
        const std::vector<double> B =
            radiosity::solve_hierarchical(hn, roots, rho, E, yb, visible, hp, arena, hs,
                                          visible_batch);
        for (size_t i = 0; i < N * kBands; ++i) S.m_B[i] = float(std::max(0.0, B[i]));
        st.pairs = hs.links;
        st.seconds_sweeps = hs.seconds_sweeps;
        st.iterations = hs.sweeps;
        st.residual = hs.residual;
        st.solves = 1;
        rays += hs.rays;
    } else {
    // ---- form factors: S_ab = A_r F(r -> s), symmetric -------------------------------------------
    std::vector<float> Smat(N * N, 0.f);
    std::vector<radiosity::PatchGeom> G(N);
    for (size_t u = 0; u < N; ++u) {
        const auto& v = U[u].v;
        G[u] = radiosity::make_patch(v[0], v[1], v[2], U[u].side == 1);
    }
    std::atomic<uint64_t> pairs{0};
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, N, 1), [&](const tbb::blocked_range<size_t>& rg) {
            uint64_t my_rays = 0, my_pairs = 0;
            for (size_t a = rg.begin(); a < rg.end(); ++a) {
                for (size_t b = a + 1; b < N; ++b) {
                    if (!radiosity::facing(G[a], G[b], eps)) continue;
                    ++my_pairs;
                    const float sab = float(radiosity::exchange(G[a], G[b], eps, visible, &my_rays));
                    Smat[a * N + b] = sab;
                    Smat[b * N + a] = sab;
                }
            }
            rays += my_rays;
            pairs += my_pairs;
        });
    });
    st.pairs = pairs;

    // ---- solve: (A / rho - S) B = A E per band, by preconditioned conjugate gradients ----------
    // (A / rho - S is symmetric, and positive definite for rho < 1, as S = A F is and the
    // rows of F sum to at most 1.) Bands with the same reflectances share a matrix; their
    // right-hand sides are reduced to an orthonormal basis (modified Gram-Schmidt) that is
    // solved once and recombined: a single light over grey surfaces is one solve for all 48
    // bands. All the basis vectors of all the groups are solved together as the columns of
    // one block (the form factors read once per iteration for all of them).
    struct Column {
        std::vector<double> d, mask, q;
    };
    std::vector<Column> cols;
    struct BandPlan {
        std::vector<std::pair<int, double>> terms;  // (column, coefficient)
        int group_first_band = 0;
    };
    std::vector<BandPlan> plan(kBands);
    std::vector<char> done(kBands, 0);
    const double tol = std::max(double(prm.residual), 1e-12);
    for (int k0 = 0; k0 < kBands; ++k0) {
        if (done[size_t(k0)]) continue;
        std::vector<int> group;
        for (int k = k0; k < kBands; ++k) {
            bool same = true;
            for (size_t u = 0; u < N && same; ++u)
                same = rho[u * kBands + size_t(k)] == rho[u * kBands + size_t(k0)];
            if (same) {
                group.push_back(k);
                done[size_t(k)] = 1;
            }
        }
        std::vector<double> d(N), mask(N);
        for (size_t u = 0; u < N; ++u) {
            const double r = rho[u * kBands + size_t(k0)];
            mask[u] = r > 0 ? 1 : 0;
            d[u] = r > 0 ? U[u].area / r : 1;
        }
        const size_t first_col = cols.size();
        for (int k : group) {
            std::vector<double> b(N);
            for (size_t u = 0; u < N; ++u) b[u] = mask[u] * U[u].area * E[u * kBands + size_t(k)];
            double norm0 = 0;
            for (double x : b) norm0 += x * x;
            norm0 = std::sqrt(norm0);
            BandPlan& bp = plan[size_t(k)];
            for (size_t c = first_col; c < cols.size(); ++c) {
                double dp = 0;
                for (size_t u = 0; u < N; ++u) dp += cols[c].q[u] * b[u];
                for (size_t u = 0; u < N; ++u) b[u] -= dp * cols[c].q[u];
                bp.terms.push_back({int(c), dp});
            }
            double nb = 0;
            for (double x : b) nb += x * x;
            nb = std::sqrt(nb);
            if (nb > 1e-6 * norm0 && nb > 0) {
                for (double& x : b) x /= nb;
                bp.terms.push_back({int(cols.size()), nb});
                cols.push_back({d, mask, std::move(b)});
            }
        }
    }
    const size_t C = cols.size();
    st.solves = int(C);
    if (C > 0 && N > 0) {
        std::vector<double> X(N * C), R(N * C), Z(N * C), Pm(N * C), AP(N * C);
        auto matvec = [&](const std::vector<double>& x, std::vector<double>& y) {
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<size_t>(0, N, 8), [&](const auto& rg) {
                    std::vector<double> acc(C);
                    for (size_t i = rg.begin(); i < rg.end(); ++i) {
                        std::fill(acc.begin(), acc.end(), 0.0);
                        const float* row = &Smat[i * N];
                        for (size_t j = 0; j < N; ++j) {
                            const double sij = double(row[j]);
                            if (sij == 0) continue;
                            const double* xj = &x[j * C];
                            for (size_t c = 0; c < C; ++c) acc[c] += sij * xj[c];
                        }
                        for (size_t c = 0; c < C; ++c)
                            y[i * C + c] = cols[c].d[i] * x[i * C + c] - cols[c].mask[i] * acc[c];
                    }
                });
            });
        };
        for (size_t u = 0; u < N; ++u)
            for (size_t c = 0; c < C; ++c) X[u * C + c] = cols[c].q[u] / cols[c].d[u];
        matvec(X, AP);
        std::vector<double> rz(C, 0), qn(C, 0), res(C, 0);
        std::vector<char> conv(C, 0);
        for (size_t u = 0; u < N; ++u)
            for (size_t c = 0; c < C; ++c) {
                const size_t k = u * C + c;
                R[k] = cols[c].q[u] - AP[k];
                Z[k] = R[k] / cols[c].d[u];
                Pm[k] = Z[k];
                rz[c] += R[k] * Z[k];
                qn[c] += sqr(cols[c].q[u]);
            }
        for (int it = 0; it < 2000; ++it) {
            std::vector<double> rn(C, 0);
            for (size_t k = 0; k < N * C; ++k) rn[k % C] += R[k] * R[k];
            bool all = true;
            for (size_t c = 0; c < C; ++c) {
                res[c] = std::sqrt(rn[c] / qn[c]);
                conv[c] = conv[c] || res[c] <= tol;
                all = all && conv[c];
            }
            if (all) break;
            ++st.iterations;
            matvec(Pm, AP);
            std::vector<double> pAp(C, 0), alpha(C, 0), rz1(C, 0);
            for (size_t k = 0; k < N * C; ++k) pAp[k % C] += Pm[k] * AP[k];
            for (size_t c = 0; c < C; ++c) {
                if (!(pAp[c] > 0)) conv[c] = 1;  // broken down (rho = 1 enclosure): stop it
                alpha[c] = conv[c] ? 0 : rz[c] / pAp[c];
            }
            for (size_t u = 0; u < N; ++u)
                for (size_t c = 0; c < C; ++c) {
                    const size_t k = u * C + c;
                    X[k] += alpha[c] * Pm[k];
                    R[k] -= alpha[c] * AP[k];
                    Z[k] = R[k] / cols[c].d[u];
                    rz1[c] += R[k] * Z[k];
                }
            for (size_t c = 0; c < C; ++c) {
                const double beta = conv[c] || rz[c] == 0 ? 0 : rz1[c] / rz[c];
                rz[c] = rz1[c];
                for (size_t u = 0; u < N; ++u) Pm[u * C + c] = Z[u * C + c] + beta * Pm[u * C + c];
            }
        }
        for (size_t c = 0; c < C; ++c) st.residual = std::max(st.residual, res[c]);
        for (int k = 0; k < kBands; ++k)
            for (size_t u = 0; u < N; ++u) {
                double v = 0;
                for (const auto& [c, coef] : plan[size_t(k)].terms) v += coef * X[u * C + size_t(c)];
                S.m_B[u * kBands + size_t(k)] = float(std::max(0.0, v));
            }
    }
    }  // matrix solver

    // ---- corner values for the interpolated read-out ------------------------------------------
    // Each corner of each unknown takes the area-weighted mean of the unknowns of the same
    // surface (same material, same plane and side) that have a corner there. Summed in unknown
    // order on one thread: deterministic.
    if (prm.interpolate && N > 0) {
        const double q = 1e-7 * scene_diam;
        struct Key {
            int64_t x, y, z, nx, ny, nz, d;
            int material;
            bool operator<(const Key& o) const {
                return std::tie(x, y, z, nx, ny, nz, d, material) <
                       std::tie(o.x, o.y, o.z, o.nx, o.ny, o.nz, o.d, o.material);
            }
        };
        auto key_of = [&](size_t u, int c) {
            const DVec3 v = U[u].v[size_t(c)], n = U[u].n;
            const auto& co = S.m_coarse[size_t(node_coarse[size_t(leaves[size_t(U[u].patch)])])];
            return Key{std::llround(v.x / q), std::llround(v.y / q), std::llround(v.z / q),
                       std::llround(n.x * 1e6), std::llround(n.y * 1e6), std::llround(n.z * 1e6),
                       std::llround(ddot(n, v) / (1e3 * q)),
                       scene.shapes[size_t(co.shape)].material};
        };
        std::map<Key, int> index;
        std::vector<int> corner(N * 3);
        for (size_t u = 0; u < N; ++u)
            for (int c = 0; c < 3; ++c)
                corner[u * 3 + size_t(c)] =
                    index.emplace(key_of(u, c), int(index.size())).first->second;
        std::vector<double> sum(index.size() * kBands, 0), area(index.size(), 0);
        for (size_t u = 0; u < N; ++u)
            for (int c = 0; c < 3; ++c) {
                const size_t v = size_t(corner[u * 3 + size_t(c)]);
                area[v] += U[u].area;
                for (int k = 0; k < kBands; ++k)
                    sum[v * kBands + size_t(k)] += U[u].area * double(S.m_B[u * kBands + size_t(k)]);
            }
        S.m_Bv.assign(N * 3 * kBands, 0.f);
        for (size_t u = 0; u < N; ++u)
            for (int c = 0; c < 3; ++c) {
                const size_t v = size_t(corner[u * 3 + size_t(c)]);
                for (int k = 0; k < kBands; ++k)
                    S.m_Bv[(u * 3 + size_t(c)) * kBands + size_t(k)] =
                        float(sum[v * kBands + size_t(k)] / area[v]);
            }
    }
    S.weigh_bands();
    st.rays = rays;
    const auto t_end = Clock::now();
    auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    st.seconds = secs(t0, t_end);
    st.seconds_mesh = secs(t_mesh, t_adaptive);
    st.seconds_direct = secs(t_direct, t_links);
    st.seconds_exchange = secs(t_links, t_end) - st.seconds_sweeps;
    return sol;
}

void write_radiosity_ply(const RadiositySolution& sol, const std::string& path) {
    const auto& P = sol.patches();
    const std::array<double, kBands> ybar = band_ybar();
    // Per patch: X, Y, Z of its exitance (Y in lm/m^2), from the side in the system.
    std::vector<std::array<double, 3>> xyz(P.size());
    double lo[3] = {kInfinity, kInfinity, kInfinity}, hi[3] = {-kInfinity, -kInfinity, -kInfinity};
    for (size_t i = 0; i < P.size(); ++i) {
        const int u = P[i].unknown[0] >= 0 ? P[i].unknown[0] : P[i].unknown[1];
        std::array<double, 3> c{0, 0, 0};
        if (u >= 0)
            for (int k = 0; k < kBands; ++k) {
                const Float l = radiosity::band_lambda(k);
                const double w = ybar[size_t(k)] / std::max(1e-30, double(cie_y()(l)));
                const double b = sol.band(u, k);
                c[0] += w * double(cie_x()(l)) * b;
                c[1] += ybar[size_t(k)] * b;
                c[2] += w * double(cie_z()(l)) * b;
            }
        xyz[i] = c;
        for (const auto& v : P[i].p) {
            const double q[3] = {v.x, v.y, v.z};
            for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], q[a]), hi[a] = std::max(hi[a], q[a]);
        }
    }
    // Corners of the same surface (material, plane, side) at the same place share a value:
    // the area-weighted mean of their patches'. In patch order: deterministic.
    const double diag = P.empty() ? 1
                                  : std::max(1e-12, std::sqrt(sqr(hi[0] - lo[0]) + sqr(hi[1] - lo[1]) +
                                                              sqr(hi[2] - lo[2])));
    const double qs = 1e-7 * diag;
    using Key = std::array<int64_t, 8>;
    std::map<Key, int> index;
    std::vector<int> corner(3 * P.size());
    for (size_t i = 0; i < P.size(); ++i) {
        const DVec3 n = P[i].unknown[0] >= 0 ? P[i].n : P[i].n * -1.0;
        for (int c = 0; c < 3; ++c) {
            const DVec3 v = P[i].p[size_t(c)];
            const Key k{std::llround(v.x / qs), std::llround(v.y / qs), std::llround(v.z / qs),
                        std::llround(n.x * 1e6), std::llround(n.y * 1e6), std::llround(n.z * 1e6),
                        std::llround(ddot(n, v) / (1e3 * qs)), P[i].material};
            corner[3 * i + size_t(c)] = index.emplace(k, int(index.size())).first->second;
        }
    }
    std::vector<std::array<double, 4>> acc(index.size(), {0, 0, 0, 0});  // A X, A Y, A Z, A
    for (size_t i = 0; i < P.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            auto& a = acc[size_t(corner[3 * i + size_t(c)])];
            for (int k = 0; k < 3; ++k) a[size_t(k)] += P[i].area * xyz[i][size_t(k)];
            a[3] += P[i].area;
        }
    double ymax = 0;
    for (auto& a : acc) {
        for (int k = 0; k < 3; ++k) a[size_t(k)] = a[3] > 0 ? a[size_t(k)] / a[3] : 0;
        ymax = std::max(ymax, a[1]);
    }
    std::string out = fmt::format(
        "ply\nformat binary_little_endian 1.0\ncomment steradian radiosity solution: per face "
        "the patch's reflected exitance in lm/m^2; per vertex the mean of the surface's patches "
        "there, as sRGB (brightest vertex white) and lm/m^2\n"
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float exitance\n"
        "element face {}\nproperty list uchar int vertex_indices\nproperty float exitance\n"
        "end_header\n",
        3 * P.size(), P.size());
    auto put = [&](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
    const double s = ymax > 0 ? 1 / ymax : 0;
    for (size_t i = 0; i < P.size(); ++i)
        for (int v = 0; v < 3; ++v) {
            const auto& a = acc[size_t(corner[3 * i + size_t(v)])];
            const Rgb rgb = xyz_to_linear_srgb(
                Xyz{Float(a[0] * s), Float(a[1] * s), Float(a[2] * s)});
            uint8_t c[3];
            for (int k = 0; k < 3; ++k)
                c[k] = uint8_t(std::lround(
                    255 * std::clamp(srgb_encode(std::max(Float(0), rgb[k])), Float(0), Float(1))));
            const float p3[3] = {float(P[i].p[size_t(v)].x), float(P[i].p[size_t(v)].y),
                                 float(P[i].p[size_t(v)].z)};
            const float e = float(a[1]);
            put(p3, sizeof p3);
            put(c, 3);
            put(&e, sizeof e);
        }
    for (size_t i = 0; i < P.size(); ++i) {
        const uint8_t three = 3;
        put(&three, 1);
        const int32_t idx[3] = {int32_t(3 * i), int32_t(3 * i + 1), int32_t(3 * i + 2)};
        put(idx, sizeof idx);
        const float e = float(xyz[i][1]);
        put(&e, sizeof e);
    }
    write_text_file(path, out);
}

}  // namespace sr
