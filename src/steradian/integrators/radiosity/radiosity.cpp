#include "steradian/integrators/radiosity/radiosity.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <numbers>
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

using Coarse = RadiositySolution::Coarse;

/// The (u, v) grid a curved shape is tessellated on (two coarse triangles per cell, or one
/// fan where a row of the grid ends at a pole): cells of at most 45 degrees, about square.
/// False for shapes that are not curved surfaces of revolution.
bool curved_grid(const ShapeGeometry& g, int& nu, int& nv, bool& pole0, bool& pole1) {
    const double step = std::numbers::pi / 4;
    auto around = [&](Float phi_max) { return std::max(3, int(std::ceil(double(phi_max) / step - 1e-4))); };
    pole0 = pole1 = false;
    if (const auto* s = std::get_if<Sphere>(&g)) {
        nu = around(s->phi_max);
        pole0 = s->z_min <= -s->radius || s->z_min >= s->radius;
        pole1 = s->z_max >= s->radius || s->z_max <= -s->radius;
        const double range = std::abs(double(s->theta_z_max) - double(s->theta_z_min));
        nv = std::max(pole0 && pole1 ? 2 : 1, int(std::ceil(range / step - 1e-4)));
        return true;
    }
    if (const auto* d = std::get_if<Disk>(&g)) {
        nu = around(d->phi_max);
        pole1 = !(d->inner_radius > 0);
        const double arc = double(d->radius) * double(d->phi_max) / nu;
        nv = std::clamp(int(std::lround(double(d->radius - d->inner_radius) / std::max(arc, 1e-30))), 1, 16);
        return true;
    }
    if (const auto* c = std::get_if<Cylinder>(&g)) {
        nu = around(c->phi_max);
        const double arc = double(c->radius) * double(c->phi_max) / nu;
        nv = std::clamp(int(std::lround(std::abs(double(c->z_max - c->z_min)) / std::max(arc, 1e-30))), 1, 64);
        return true;
    }
    return false;
}

/// The object-space point of a curved shape at (u, v), and the shape's world_from_object.
Vec3d curved_object_point(const ShapeGeometry& g, double u, double v, const Transform*& w) {
    if (const auto* s = std::get_if<Sphere>(&g)) {
        w = &s->world_from_object;
        const double phi = u * double(s->phi_max);
        const double th = (1 - v) * double(s->theta_z_min) + v * double(s->theta_z_max);
        double st = std::sin(th), ct = std::cos(th);
        if (std::abs(st) < 1e-7) st = 0, ct = ct < 0 ? -1 : 1;  // a pole: exactly on the axis
        const double r = double(s->radius);
        return Vec3d(r * st * std::cos(phi), r * st * std::sin(phi), r * ct);
    }
    if (const auto* d = std::get_if<Disk>(&g)) {
        w = &d->world_from_object;
        const double phi = u * double(d->phi_max);
        const double rho = (1 - v) * double(d->radius) + v * double(d->inner_radius);
        return Vec3d(rho * std::cos(phi), rho * std::sin(phi), double(d->height));
    }
    const auto& c = std::get<Cylinder>(g);
    w = &c.world_from_object;
    const double phi = u * double(c.phi_max), r = double(c.radius);
    return Vec3d(r * std::cos(phi), r * std::sin(phi), (1 - v) * double(c.z_min) + v * double(c.z_max));
}

/// The world-space point on the true surface of curved coarse triangle c at (b1, b2).
DVec3 curved_point(const Scene& scene, const Coarse& c, double b1, double b2) {
    double u = 0, v = 0;
    c.uv_of(b1, b2, u, v);
    const Transform* w = nullptr;
    const Vec3d q = curved_object_point(scene.shapes[size_t(c.shape)].geometry, u, v, w);
    Vec3d p = w->point(q);
    if (c.instance >= 0) p = scene.instances[size_t(c.instance)].world_from_instance.point(p);
    return DVec3(p.x, p.y, p.z);
}

/// A hit on coarse triangle c at (b1, b2), for its material (its position and uv).
SurfaceHit coarse_hit(const Scene& scene, const Coarse& c, double b1, double b2) {
    SurfaceHit h;
    const ShapeEntry& e = scene.shapes[size_t(c.shape)];
    if (!c.curved()) {
        std::get<TriangleMesh>(e.geometry).fill_hit(c.prim, Float(b1), Float(b2), h);
    } else {
        double u = 0, v = 0;
        c.uv_of(b1, b2, u, v);
        const Transform* w = nullptr;
        const Vec3d q = curved_object_point(e.geometry, u, v, w);
        const Point3 po(Float(q.x), Float(q.y), Float(q.z));
        std::visit([&](const auto& shape) {
            if constexpr (requires { shape.fill_hit(po, h); }) shape.fill_hit(po, h);
        }, e.geometry);
        h.uv = Point2(Float(u), Float(v));
    }
    if (c.instance >= 0) {
        const Transform& w = scene.instances[size_t(c.instance)].world_from_instance;
        h.p = w.point(h.p);
        h.ng = normalize(w.normal(h.ng));
        h.ns = normalize(w.normal(h.ns));
    }
    h.shape = c.shape;
    h.instance = c.instance;
    h.prim = c.prim;
    h.material = e.material;
    h.wo = h.ns;
    return h;
}

}  // namespace

bool radiosity_models_exactly(const Scene& scene, std::string* why) {
    auto no = [&](std::string s) {
        if (why) *why = std::move(s);
        return false;
    };
    if (!scene.media.empty()) return no("the scene has participating media");
    // Every shape the pass meshes: the top-level ones, and the prototypes' once per instance.
    std::vector<size_t> uses(scene.shapes.size(), 0);
    for (int si : scene.top_level_shapes) ++uses[size_t(si)];
    for (const Instance& inst : scene.instances)
        for (int si : scene.prototypes[size_t(inst.prototype)].shapes) ++uses[size_t(si)];
    size_t triangles = 0;
    for (size_t si = 0; si < scene.shapes.size(); ++si) {
        const ShapeGeometry& g = scene.shapes[si].geometry;
        int nu = 0, nv = 0;
        bool p0 = false, p1 = false;
        if (const auto* m = std::get_if<TriangleMesh>(&g))
            triangles += uses[si] * m->num_triangles();
        else if (curved_grid(g, nu, nv, p0, p1))
            triangles += uses[si] * size_t(2 * nu * nv - nu * (int(p0) + int(p1)));
    }
    if (triangles > size_t(scene.integrator.radiosity.max_patches))
        return no(fmt::format("{} triangles, more than the radiosity mesh's {} patches",
                              triangles, scene.integrator.radiosity.max_patches));
    for (size_t si = 0; si < scene.shapes.size(); ++si) {
        const ShapeEntry& e = scene.shapes[si];
        if (e.material < 0 || uses[si] == 0) continue;
        if (std::holds_alternative<Curves>(e.geometry))
            return no(fmt::format("shape {} is a curve (the radiosity pass does not mesh curves)", si));
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

void RadiositySolution::Coarse::uv_of(double b1, double b2, double& u, double& v) const {
    double ls = 0, lt = 0;  // the point's place in the cell, 0..1 along u and v
    switch (kind) {
    case 0: ls = b1 + b2, lt = b2; break;
    case 1: ls = b1, lt = b1 + b2; break;
    case 2: lt = b1 + b2, ls = lt > 0 ? b1 / lt : 0.5; break;
    default: lt = b2, ls = b2 < 1 ? b1 / (1 - b2) : 0.5; break;
    }
    // Written so that a cell's corners come out exactly (neighbours share them bit for bit).
    u = (1 - ls) * u0 + ls * u1;
    v = (1 - lt) * v0 + lt * v1;
}

void RadiositySolution::Coarse::bary_of(double u, double v, double& b1, double& b2) const {
    const double ls = std::clamp((u - u0) / (u1 - u0), 0.0, 1.0);
    const double lt = std::clamp((v - v0) / (v1 - v0), 0.0, 1.0);
    switch (kind) {
    case 0: b1 = std::max(0.0, ls - lt), b2 = lt; break;
    case 1: b1 = ls, b2 = std::max(0.0, lt - ls); break;
    case 2: b1 = lt * ls, b2 = lt * (1 - ls); break;
    default: b1 = (1 - lt) * ls, b2 = lt; break;
    }
}

int RadiositySolution::coarse_at(const SurfaceHit& h, double& b1, double& b2) const {
    if (h.shape < 0) return -1;
    int sf = -1;
    if (h.instance < 0) {
        if (size_t(h.shape) < m_shape_surface.size()) sf = m_shape_surface[size_t(h.shape)];
    } else if (size_t(h.instance) < m_instance_base.size() &&
               size_t(h.shape) < m_proto_slot.size() && m_proto_slot[size_t(h.shape)] >= 0) {
        sf = m_instance_surface[size_t(m_instance_base[size_t(h.instance)] +
                                       m_proto_slot[size_t(h.shape)])];
    }
    if (sf < 0) return -1;
    const Surface& s = m_surfaces[size_t(sf)];
    if (s.nu == 0) {
        const int ci = s.first + int(h.prim);
        const Coarse& c = m_coarse[size_t(ci)];
        const DVec3 v = DVec3(h.p) - c.p0;
        const double d00 = ddot(c.e1, c.e1), d01 = ddot(c.e1, c.e2), d11 = ddot(c.e2, c.e2);
        const double d20 = ddot(v, c.e1), d21 = ddot(v, c.e2);
        const double den = d00 * d11 - d01 * d01;
        b1 = std::clamp(den != 0 ? (d11 * d20 - d01 * d21) / den : 0, 0.0, 1.0);
        b2 = std::clamp(den != 0 ? (d00 * d21 - d01 * d20) / den : 0, 0.0, 1.0);
        return ci;
    }
    // A curved shape: the cell of the hit's (u, v), then the triangle of the cell.
    if (!(h.uv[0] >= 0 && h.uv[0] <= 1 && h.uv[1] >= 0 && h.uv[1] <= 1)) return -1;  // NaN too
    const double u = double(h.uv[0]), v = double(h.uv[1]);
    const int iu = std::min(int(u * s.nu), s.nu - 1), iv = std::min(int(v * s.nv), s.nv - 1);
    int ci = s.first + 2 * (iv * s.nu + iu);
    const Coarse& c0 = m_coarse[size_t(ci)];
    if (c0.kind == 0 && (u - c0.u0) * (c0.v1 - c0.v0) < (v - c0.v0) * (c0.u1 - c0.u0)) ++ci;
    m_coarse[size_t(ci)].bary_of(u, v, b1, b2);
    return ci;
}

int RadiositySolution::leaf_at(const SurfaceHit& h, double* ob1, double* ob2) const {
    double b1 = 0, b2 = 0;
    const int ci = coarse_at(h, b1, b2);
    if (ci < 0) return -1;
    const Coarse& c = m_coarse[size_t(ci)];
    if (c.root < 0) return -1;
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
    // The side the ray came from; on a curved surface by the hit's own geometric normal (the
    // patch's chord is tilted against it), oriented as the patch's front.
    double side = ddot(DVec3(h.wo), p.n);
    if (p.surface >= 0) {
        const DVec3 ng(h.ng.x, h.ng.y, h.ng.z);
        side = ddot(DVec3(h.wo), ng) * (ddot(ng, p.n) >= 0 ? 1.0 : -1.0);
    }
    u = p.unknown[side >= 0 ? 0 : 1];
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

    // ---- coarse triangles: the scene's diffuse triangles and curved shapes' tessellations ----
    // Top-level shapes, then each object instance's prototype shapes (in world space).
    S.m_shape_surface.assign(scene.shapes.size(), -1);
    S.m_proto_slot.assign(scene.shapes.size(), -1);
    for (const Prototype& pr : scene.prototypes)
        for (size_t k = 0; k < pr.shapes.size(); ++k) S.m_proto_slot[size_t(pr.shapes[k])] = int(k);
    // Whether coarse triangle c is diffuse (and black), from its material at (b1, b2).
    auto classify = [&](RadiositySolution::Coarse& c, double b1, double b2) {
        const int material = scene.shapes[size_t(c.shape)].material;
        const SurfaceHit h = coarse_hit(scene, c, b1, b2);
        bool lambert = true, black = true;
        for (int g = 0; g < kGroups && lambert; ++g) {
            SampledWavelengths lam = band_group(g);
            auto b = make_bsdf(scene.materials[size_t(material)], mctx, h, lam);
            lambert = is_lambert(b);
            if (lambert) black = black && std::get<LambertLobe>(b->lobe()).r.is_zero();
        }
        if (lambert) c.root = 0;  // diffuse: meshed below
        c.black = lambert && black;
        return lambert;
    };
    auto set_chord = [](RadiositySolution::Coarse& c, DVec3 p0, DVec3 p1, DVec3 p2) {
        c.p0 = p0;
        c.e1 = p1 - p0;
        c.e2 = p2 - p0;
        const DVec3 cr = dcross(c.e1, c.e2);
        const double len = dlength(cr);
        if (len > 0) c.n = cr * (1 / len);
        return len > 0;
    };
    size_t non_diffuse_instanced = 0;
    std::vector<char> curve_noted(scene.shapes.size(), 0);
    // Meshes shape si (of instance inst, or -1) into coarse triangles; returns its surface.
    auto mesh_shape = [&](size_t si, int inst) -> int {
        const ShapeEntry& e = scene.shapes[si];
        if (e.material < 0) return -1;
        if (std::holds_alternative<Curves>(e.geometry)) {
            if (!curve_noted[si]++)
                st.notes.push_back(fmt::format("shape {} (a curve) is not meshed: it reflects "
                                               "nothing in the radiosity pass", si));
            return -1;
        }
        RadiositySolution::Surface sf;
        sf.first = int(S.m_coarse.size());
        size_t non_diffuse = 0;
        if (const auto* mesh = std::get_if<TriangleMesh>(&e.geometry)) {
            const auto& P = *mesh->p;
            const auto& I = *mesh->indices;
            const Transform* w = inst >= 0 ? &scene.instances[size_t(inst)].world_from_instance : nullptr;
            auto world = [&](uint32_t k) {
                if (!w) return DVec3(P[k]);
                const Vec3d q = w->point(Vec3d(P[k]));
                return DVec3(q.x, q.y, q.z);
            };
            for (size_t t = 0; t < mesh->num_triangles(); ++t) {
                RadiositySolution::Coarse c;
                c.shape = int(si);
                c.instance = inst;
                c.prim = uint32_t(t);
                if (set_chord(c, world(I[3 * t]), world(I[3 * t + 1]), world(I[3 * t + 2])) &&
                    !classify(c, 1.0 / 3, 1.0 / 3))
                    ++non_diffuse;
                S.m_coarse.push_back(c);
            }
        } else {
            bool pole0 = false, pole1 = false;
            if (!curved_grid(e.geometry, sf.nu, sf.nv, pole0, pole1)) return -1;
            for (int iv = 0; iv < sf.nv; ++iv)
                for (int iu = 0; iu < sf.nu; ++iu) {
                    const bool fan0 = pole0 && iv == 0, fan1 = pole1 && iv == sf.nv - 1;
                    for (int half = 0; half < 2; ++half) {
                        RadiositySolution::Coarse c;
                        c.shape = int(si);
                        c.instance = inst;
                        c.u0 = double(iu) / sf.nu;
                        c.u1 = double(iu + 1) / sf.nu;
                        c.v0 = double(iv) / sf.nv;
                        c.v1 = double(iv + 1) / sf.nv;
                        c.kind = fan0 ? 2 : fan1 ? 3 : half;
                        c.surface = int(S.m_surfaces.size());
                        // A fan covers its whole cell: the cell's second slot stays empty.
                        if (!((fan0 || fan1) && half == 1) &&
                            set_chord(c, curved_point(scene, c, 0, 0), curved_point(scene, c, 1, 0),
                                      curved_point(scene, c, 0, 1)) &&
                            !classify(c, 1.0 / 3, 1.0 / 3))
                            ++non_diffuse;
                        S.m_coarse.push_back(c);
                    }
                }
        }
        if (non_diffuse > 0) {
            if (inst >= 0)
                non_diffuse_instanced += non_diffuse;
            else
                st.notes.push_back(fmt::format("shape {}: {} non-diffuse triangles are black "
                                               "occluders in the radiosity pass", si, non_diffuse));
        }
        S.m_surfaces.push_back(sf);
        return int(S.m_surfaces.size()) - 1;
    };
    {
        std::vector<char> is_top(scene.shapes.size(), 0);
        for (int si : scene.top_level_shapes) is_top[size_t(si)] = 1;
        for (size_t si = 0; si < scene.shapes.size(); ++si)
            if (is_top[si]) S.m_shape_surface[si] = mesh_shape(si, -1);
        for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
            const Prototype& pr = scene.prototypes[size_t(scene.instances[ii].prototype)];
            S.m_instance_base.push_back(int(S.m_instance_surface.size()));
            for (int si : pr.shapes) S.m_instance_surface.push_back(mesh_shape(size_t(si), int(ii)));
        }
        if (non_diffuse_instanced > 0)
            st.notes.push_back(fmt::format("{} non-diffuse triangles of object instances are "
                                           "black occluders in the radiosity pass",
                                           non_diffuse_instanced));
    }

    // ---- which sides can receive light --------------------------------------------------------
    // A side is active if a light or a point of another diffuse triangle lies strictly in
    // front of it (infinite and distant lights count as everywhere; an emitting sphere or
    // disk if any of its bounding ball is in front).
    // The inside of a full sphere is closed: only a light or a surface inside it lights it.
    std::vector<DVec3> light_points;
    bool light_everywhere = false;
    // Emitting spheres and disks: their bounding balls' centres and radii, and their shapes
    // (what is inside a sphere).
    struct LightBall {
        DVec3 c;
        double r = 0;
        const void* shape = nullptr;
    };
    std::vector<LightBall> shape_lights;
    for (const Light& l : scene.lights) {
        if (const auto* al = std::get_if<DiffuseAreaLight>(&l); al && !al->triangle) {
            const Transform& w = al->sphere ? al->sphere->world_from_object : al->disk->world_from_object;
            const double r = al->sphere ? double(al->sphere->radius) : double(al->disk->radius);
            const double h = al->sphere ? 0.0 : double(al->disk->height);
            const Vec3d o = w.point(Vec3d(0, 0, h));
            LightBall b{DVec3(o.x, o.y, o.z), 0, al->sphere ? static_cast<const void*>(al->sphere) : al->disk};
            for (int k = 0; k < 8; ++k) {  // the object-space box's corners
                const Vec3d q = w.point(Vec3d(k & 1 ? r : -r, k & 2 ? r : -r, al->sphere ? (k & 4 ? r : -r) : h));
                b.r = std::max(b.r, dlength(DVec3(q.x, q.y, q.z) - b.c));
            }
            shape_lights.push_back(b);
            continue;
        }
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
                const auto* ball = c.curved() ? std::get_if<Sphere>(&scene.shapes[size_t(c.shape)].geometry)
                                              : nullptr;
                if (ball && !ball->full()) ball = nullptr;
                Transform object_from_world;
                if (ball) {
                    object_from_world = ball->world_from_object;
                    if (c.instance >= 0)
                        object_from_world =
                            scene.instances[size_t(c.instance)].world_from_instance * object_from_world;
                    object_from_world = object_from_world.inverse();
                }
                const Vec3d centre = ball ? object_from_world.inverse().point(Vec3d(0, 0, 0)) : Vec3d(0, 0, 0);
                // A curved coarse triangle's surface turns by up to 45 degrees: a point lies in
                // front of it if it lies in front of its tangent plane at a corner, an edge's
                // midpoint or the centroid (the chord's own plane would miss what sees only a
                // part of it, near a sphere's terminator).
                std::array<DVec3, 7> tx, tn;
                int nt = 0;
                if (c.curved()) {
                    constexpr double at[7][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}, {1.0 / 3, 1.0 / 3}};
                    constexpr double d = 1e-4;
                    for (const auto& b : at) {
                        const DVec3 x = curved_point(scene, c, b[0], b[1]);
                        const DVec3 cr = dcross(curved_point(scene, c, b[0] + d, b[1]) - x,
                                                curved_point(scene, c, b[0], b[1] + d) - x);
                        const double len = dlength(cr);
                        if (!(len > 0)) continue;
                        tx[size_t(nt)] = x;
                        tn[size_t(nt++)] = cr * ((ddot(cr, c.n) >= 0 ? 1.0 : -1.0) / len);
                    }
                }
                for (int side = 0; side < 2; ++side) {
                    const DVec3 n = side == 0 ? c.n : c.n * -1.0;
                    const double sgn = side == 0 ? 1.0 : -1.0;
                    auto in_front = [&](DVec3 q) {
                        if (ddot(n, q - c.p0) > eps) return true;
                        for (int k = 0; k < nt; ++k)
                            if (sgn * ddot(tn[size_t(k)], q - tx[size_t(k)]) > eps) return true;
                        return false;
                    };
                    if (ball && ddot(n, DVec3(centre.x, centre.y, centre.z) - c.p0) > 0) {
                        // The inside of a closed sphere.
                        auto inside = [&](DVec3 q) {
                            const Vec3d qo = object_from_world.point(Vec3d(q.x, q.y, q.z));
                            return std::sqrt(qo.x * qo.x + qo.y * qo.y + qo.z * qo.z) <
                                   double(ball->radius) * (1 - 1e-9);
                        };
                        bool act = false;
                        for (size_t k = 0; k < light_points.size() && !act; ++k)
                            act = inside(light_points[k]);
                        for (size_t k = 0; k < shape_lights.size() && !act; ++k)
                            act = shape_lights[k].shape != ball && inside(shape_lights[k].c);
                        for (size_t b = 0; b < diffuse.size() && !act; ++b) {
                            const auto& o2 = S.m_coarse[diffuse[b]];
                            if (o2.shape == c.shape && o2.instance == c.instance) continue;
                            act = inside(o2.p0) || inside(o2.p0 + o2.e1) || inside(o2.p0 + o2.e2);
                        }
                        active[diffuse[a]][size_t(side)] = act;
                        continue;
                    }
                    bool act = light_everywhere;
                    for (size_t k = 0; k < light_points.size() && !act; ++k)
                        act = in_front(light_points[k]);
                    // A ball is partly in front of a plane if its centre is less than its
                    // radius behind it.
                    for (size_t k = 0; k < shape_lights.size() && !act; ++k) {
                        const auto& lb = shape_lights[k];
                        act = ddot(n, lb.c - c.p0) > eps - lb.r;
                        for (int j = 0; j < nt && !act; ++j)
                            act = sgn * ddot(tn[size_t(j)], lb.c - tx[size_t(j)]) > eps - lb.r;
                    }
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
    // The length that sets a coarse triangle's depth of uniform splitting: its longest edge;
    // on a curved shape, the longest edge of any of the shape's coarse triangles. Their
    // children's corners lie on the true surface, so two neighbours split to different
    // depths would leave a crack between their chords, through which the solve would lose
    // light: split to one depth, the chords make one closed surface.
    std::vector<double> split_length(nc, 0);
    {
        std::vector<double> surface_max(S.m_surfaces.size(), 0);
        for (size_t i = 0; i < nc; ++i) {
            const auto& c = S.m_coarse[i];
            split_length[i] = longest(c.p0, c.p0 + c.e1, c.p0 + c.e2);
            if (c.curved() && c.root >= 0)
                surface_max[size_t(c.surface)] = std::max(surface_max[size_t(c.surface)], split_length[i]);
        }
        for (size_t i = 0; i < nc; ++i)
            if (S.m_coarse[i].curved()) split_length[i] = surface_max[size_t(S.m_coarse[i].surface)];
    }
    auto level_for = [&](size_t i, double h) {
        int lv = 0;
        while (lv < 12 && split_length[i] / double(1 << lv) > h) ++lv;
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
    // Nodes: for each coarse triangle a tree of midpoint splits. Each node keeps its corners'
    // barycentrics in its coarse triangle; on a curved shape its corners are the true
    // surface's points there (the children follow the surface, not the coarse chord).
    struct Tri {
        DVec3 a, b, c;
    };
    using Bary = std::array<std::array<double, 2>, 3>;
    // The coarse triangle's barycentrics (b1, b2) of a node's point at its own (l1, l2).
    auto in_coarse = [](const Bary& b, double l1, double l2) {
        const double l0 = 1 - l1 - l2;
        return std::array<double, 2>{l0 * b[0][0] + l1 * b[1][0] + l2 * b[2][0],
                                     l0 * b[0][1] + l1 * b[1][1] + l2 * b[2][1]};
    };
    std::vector<Tri> node_tri;
    std::vector<Bary> node_bary;
    std::vector<int> node_coarse;
    std::vector<int> node_level;
    // The normal of a node's chord (its front side: the coarse triangle's winding).
    auto tri_normal = [](const Tri& t) {
        const DVec3 cr = dcross(t.b - t.a, t.c - t.a);
        const double l = dlength(cr);
        return l > 0 ? cr * (1 / l) : DVec3(0, 0, 1);
    };
    auto add_node = [&](Tri t, const Bary& bary, int coarse, int level) {
        S.m_nodes.push_back({});
        node_tri.push_back(t);
        node_bary.push_back(bary);
        node_coarse.push_back(coarse);
        node_level.push_back(level);
        return int(S.m_nodes.size()) - 1;
    };
    auto split = [&](int node) {
        const Tri t = node_tri[size_t(node)];
        const Bary b = node_bary[size_t(node)];
        const int coarse = node_coarse[size_t(node)], lv = node_level[size_t(node)] + 1;
        auto mid = [](const std::array<double, 2>& x, const std::array<double, 2>& y) {
            return std::array<double, 2>{(x[0] + y[0]) * 0.5, (x[1] + y[1]) * 0.5};
        };
        const auto b01 = mid(b[0], b[1]), b12 = mid(b[1], b[2]), b02 = mid(b[0], b[2]);
        DVec3 m01 = (t.a + t.b) * 0.5, m12 = (t.b + t.c) * 0.5, m02 = (t.a + t.c) * 0.5;
        const auto& c = S.m_coarse[size_t(coarse)];
        if (c.curved()) {
            m01 = curved_point(scene, c, b01[0], b01[1]);
            m12 = curved_point(scene, c, b12[0], b12[1]);
            m02 = curved_point(scene, c, b02[0], b02[1]);
        }
        const int first = add_node({t.a, m01, m02}, {b[0], b01, b02}, coarse, lv);
        add_node({m01, t.b, m12}, {b01, b[1], b12}, coarse, lv);
        add_node({m02, m12, t.c}, {b02, b12, b[2]}, coarse, lv);
        add_node({m12, m02, m01}, {b12, b02, b01}, coarse, lv);
        S.m_nodes[size_t(node)].child = first;
    };
    std::vector<int> leaves;  // nodes
    for (size_t i = 0; i < nc; ++i) {
        auto& c = S.m_coarse[i];
        if (c.root < 0) continue;
        ++st.diffuse_triangles;
        const Tri root = c.curved() ? Tri{curved_point(scene, c, 0, 0), curved_point(scene, c, 1, 0),
                                          curved_point(scene, c, 0, 1)}
                                    : Tri{c.p0, c.p0 + c.e1, c.p0 + c.e2};
        c.root = add_node(root, Bary{{{0, 0}, {1, 0}, {0, 1}}}, int(i), 0);
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
        for (int nd : leaves) {
            if (node_spread[size_t(nd)] >= 0) continue;
            if (S.m_coarse[size_t(node_coarse[size_t(nd)])].curved())
                node_spread[size_t(nd)] = 0;  // not split (see split_length)
            else
                todo.push_back(nd);
        }
        arena.execute([&] {
            tbb::parallel_for(size_t(0), todo.size(), [&](size_t ti) {
                const int nd = todo[ti];
                const auto& a = active[size_t(node_coarse[size_t(nd)])];
                const Tri t = node_tri[size_t(nd)];
                const DVec3 g = (t.a + t.b + t.c) * (1.0 / 3);
                const DVec3 n = S.m_coarse[size_t(node_coarse[size_t(nd)])].n;  // flat only
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
            if (S.m_coarse[size_t(node_coarse[size_t(leaves[li])])].curved()) continue;  // not sampled
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
            // Curved shapes stay split uniformly (no cracks: see split_length).
            if (v > double(prm.subdivide) && node_level[size_t(leaves[li])] < 16 &&
                !S.m_coarse[size_t(node_coarse[size_t(leaves[li])])].curved())
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
        const auto& co = S.m_coarse[size_t(ci)];
        p.n = co.curved() ? tri_normal(t) : co.n;
        const double chord_area = tri_area(t.b - t.a, t.c - t.a);
        p.area = chord_area;
        if (co.curved()) {
            // The curved piece's area: the sum of the chords of an 8 x 8 subdivision of the
            // node in barycentrics (its error is 1/64 of the chord's own).
            constexpr int K = 8;
            const Bary& b = node_bary[size_t(nd)];
            auto at = [&](int i, int j) {
                const auto q = in_coarse(b, double(i) / K, double(j) / K);
                return curved_point(scene, co, q[0], q[1]);
            };
            std::vector<DVec3> grid;
            for (int j = 0; j <= K; ++j)
                for (int i = 0; i + j <= K; ++i) grid.push_back(at(i, j));
            auto idx = [&](int i, int j) { return size_t(j * (K + 1) - j * (j - 1) / 2 + i); };
            double area = 0;
            for (int j = 0; j < K; ++j)
                for (int i = 0; i + j < K; ++i) {
                    const DVec3 q = grid[idx(i, j)], r = grid[idx(i + 1, j)], w = grid[idx(i, j + 1)];
                    area += tri_area(r - q, w - q);
                    if (i + j + 1 < K) {
                        const DVec3 x = grid[idx(i + 1, j + 1)];
                        area += tri_area(x - r, w - r);
                    }
                }
            p.area = area;
        }
        p.material = scene.shapes[size_t(S.m_coarse[size_t(ci)].shape)].material;
        p.surface = co.curved() ? co.surface : -1;
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
            u.area = chord_area;  // the solve's: the chords' form factors' area
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
            const Bary& nb = node_bary[size_t(leaves[size_t(u.patch)])];
            SurfaceHit hh = coarse_hit(scene, c, (nb[0][0] + nb[1][0] + nb[2][0]) / 3,
                                       (nb[0][1] + nb[1][1] + nb[2][1]) / 3);
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
            // On a curved shape the points are the true surface's, with its normal there, each
            // weighted by the surface's area element over the chord's: the result is the flux
            // into the piece of surface the patch stands for, spread over the chord (the
            // solve's area; the reads spread it back over the piece). The chords of a convex
            // shape seen from outside would catch too little light.
            double* Eu = &E[ui * kBands];
            uint64_t r = 0;
            const auto& rule = radiosity::triangle_rule(5);
            const int ns = std::max(1, prm.direct_samples);
            const bool curved = c.curved();
            // The point at the patch's barycentrics (b0, b1, b2) and its normal: on the chord
            // (weight 1), or on the true surface, weighted by dA_surface / dA_chord there.
            auto point_at = [&](double b0, double b1, double b2, DVec3& x, DVec3& n) {
                if (!curved) {
                    x = p.p[0] * b0 + p.p[1] * b1 + p.p[2] * b2 + u.n * eps;
                    n = u.n;
                    return 1.0;
                }
                auto cb = [&](double l1, double l2) {
                    const auto q = in_coarse(nb, l1, l2);
                    return curved_point(scene, c, q[0], q[1]);
                };
                (void)b0;
                constexpr double d = 1e-5;
                const DVec3 s0 = cb(b1, b2), cr = dcross(cb(b1 + d, b2) - s0, cb(b1, b2 + d) - s0);
                const double len = dlength(cr);
                n = len > 0 ? cr * ((ddot(cr, u.n) >= 0 ? 1.0 : -1.0) / len) : u.n;
                x = s0 + n * eps;
                return len / (d * d) / (2 * u.area);
            };
            std::array<double, 7> wq{};
            std::array<DVec3, 7> xq, nq;
            for (int q = 0; q < rule.count; ++q) {
                const auto& b = rule.b[size_t(q)];
                wq[size_t(q)] = rule.w[size_t(q)] * point_at(b[0], b[1], b[2], xq[size_t(q)], nq[size_t(q)]);
            }
            for (int l = 0; l < int(scene.lights.size()); ++l) {
                if (direct.is_delta(l)) {
                    for (int q = 0; q < rule.count; ++q)
                        r += uint64_t(direct.add(l, xq[size_t(q)], nq[size_t(q)], Point2(0.5f, 0.5f),
                                                 wq[size_t(q)], Eu));
                } else {
                    for (int s = 0; s < ns; ++s) {
                        const Point2 up = r2(uint64_t(s), hash(uint64_t(ui), uint64_t(l), 1u));
                        const Point2 ul = r2(uint64_t(s), hash(uint64_t(ui), uint64_t(l), 2u));
                        const auto bt = sample_uniform_triangle(up);
                        DVec3 x, n;
                        const double jw = point_at(double(bt[0]), double(bt[1]), double(bt[2]), x, n);
                        r += uint64_t(direct.add(l, x, n, ul, jw / ns, Eu));
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
    for (const Instance& inst : scene.instances)
        for (int si : scene.prototypes[size_t(inst.prototype)].shapes)
            has_interface = has_interface || scene.shapes[size_t(si)].material < 0;
    // With curved shapes, the form factors' rays are traced against the patches' own chords
    // (an acceleration structure of the scene with each meshed curved shape replaced by its
    // patches' triangles, in world space), not against the true surfaces: the solve's world
    // is then one consistent polyhedron. Against the true surfaces, rays between other
    // patches were stopped by silhouettes larger than the chords' that the shapes exchange
    // light with, and that light was lost.
    std::vector<ShapeEntry> chord_shapes;
    std::vector<int> chord_top;
    std::vector<Prototype> chord_protos;
    std::vector<Instance> chord_instances;
    std::unique_ptr<Occluder> chord_occluder;
    {
        auto chords_of = [&](int sf_index) {
            const auto& sf = S.m_surfaces[size_t(sf_index)];
            std::vector<Point3> P;
            std::vector<uint32_t> I;
            for (int k = sf.first; k < sf.first + 2 * sf.nu * sf.nv; ++k) {
                const auto& c = S.m_coarse[size_t(k)];
                std::vector<int> stack;
                if (c.root >= 0) stack.push_back(c.root);
                else if (dlength(dcross(c.e1, c.e2)) > 0) {  // not meshed: its coarse chord
                    for (const DVec3& q : {c.p0, c.p0 + c.e1, c.p0 + c.e2}) {
                        I.push_back(uint32_t(P.size()));
                        P.push_back(Point3(q.f()));
                    }
                }
                while (!stack.empty()) {
                    const int nd = stack.back();
                    stack.pop_back();
                    if (S.m_nodes[size_t(nd)].child >= 0) {
                        for (int ch = 0; ch < 4; ++ch) stack.push_back(S.m_nodes[size_t(nd)].child + ch);
                        continue;
                    }
                    const Tri& t = node_tri[size_t(nd)];
                    for (const DVec3& q : {t.a, t.b, t.c}) {
                        I.push_back(uint32_t(P.size()));
                        P.push_back(Point3(q.f()));
                    }
                }
            }
            const auto& c0 = S.m_coarse[size_t(sf.first)];
            ShapeEntry e = scene.shapes[size_t(c0.shape)];
            e.alpha = nullptr;
            e.light_offset = -1;
            TriangleMesh mesh;
            P.push_back(Point3(0, 0, 0));  // Embree reads up to 16 bytes past the last vertex
            mesh.p = std::make_shared<std::vector<Point3>>(std::move(P));
            mesh.indices = std::make_shared<std::vector<uint32_t>>(std::move(I));
            e.geometry = std::move(mesh);
            chord_shapes.push_back(std::move(e));
            return int(chord_shapes.size()) - 1;
        };
        auto curved_surface = [&](int sf) { return sf >= 0 && S.m_surfaces[size_t(sf)].nu > 0; };
        bool any = false;
        for (size_t k = 0; k < S.m_surfaces.size() && !any; ++k) any = curved_surface(int(k));
        if (any) {
            chord_shapes = scene.shapes;
            for (int si : scene.top_level_shapes)
                chord_top.push_back(curved_surface(S.m_shape_surface[size_t(si)])
                                        ? chords_of(S.m_shape_surface[size_t(si)])
                                        : si);
            // Prototypes without their meshed curved shapes; those go to the top level, per
            // instance.
            std::vector<int> proto_index(scene.prototypes.size(), -1);
            for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
                const int pi = scene.instances[ii].prototype;
                const Prototype& pr = scene.prototypes[size_t(pi)];
                std::vector<int> kept;
                for (size_t k = 0; k < pr.shapes.size(); ++k) {
                    const int sf = S.m_instance_surface[size_t(S.m_instance_base[ii]) + k];
                    if (curved_surface(sf))
                        chord_top.push_back(chords_of(sf));
                    else
                        kept.push_back(pr.shapes[k]);
                }
                if (kept.empty()) continue;
                if (proto_index[size_t(pi)] < 0) {
                    proto_index[size_t(pi)] = int(chord_protos.size());
                    chord_protos.push_back(Prototype{pr.name, kept});
                }
                chord_instances.push_back(
                    Instance{proto_index[size_t(pi)], scene.instances[ii].world_from_instance});
            }
            chord_occluder = std::make_unique<Occluder>(
                GeometryView{chord_shapes, chord_top, chord_protos, chord_instances, 0});
        }
    }
    const radiosity::Visibility visible = [&](DVec3 o, DVec3 t) {
        const Ray ray{o.f(), (t - o).f(), 1 - Float(1e-4)};
        if (chord_occluder)
            return has_interface ? !chord_occluder->occluded_by_surface(ray) : !chord_occluder->occluded(ray);
        return has_interface ? !scene.occluded_by_surface(ray) : !scene.occluded(ray);
    };
    const radiosity::VisibilityBatch visible_batch = [&](const DVec3* o, const DVec3* t, int n) {
        Ray packet[Scene::kRayPacket];
        for (int i = 0; i < n; ++i) packet[i] = Ray{o[i].f(), (t[i] - o[i]).f(), 1 - Float(1e-4)};
        const unsigned bits = (1u << n) - 1;
        unsigned blocked = 0;
        if (chord_occluder)
            blocked = has_interface ? chord_occluder->occluded_by_surface_packet(packet, bits)
                                    : chord_occluder->occluded_packet(packet, bits);
        else
            blocked = has_interface ? scene.occluded_by_surface_packet(packet, bits)
                                    : scene.occluded_packet(packet, bits);
        return bits & ~blocked;
    };
    S.m_B.assign(N * kBands, 0.f);
    const auto t_links = Clock::now();
    if (prm.hierarchical) {
        // ---- hierarchical radiosity over the patch trees (hierarchical.cpp) --------------------
        // A tree per lit side of each coarse triangle, its nodes the mesh's (sub-)triangles.
        // On a curved shape every patch is a root of its own: a node's chord is not the union
        // of its children's (they bulge out to the surface), so a link between the chords of
        // inner nodes would see less of the other side than the patches it stands for do, and
        // light would be lost (2 % inside a sphere of 288 patches).
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
                std::vector<int> stack{c.root};
                while (!stack.empty()) {
                    const int nd = stack.back();
                    stack.pop_back();
                    const int ch = S.m_nodes[size_t(nd)].child;
                    if (c.curved() && ch >= 0) {
                        for (int k = 3; k >= 0; --k) stack.push_back(ch + k);
                        continue;
                    }
                    roots.push_back(int(hn.size()));
                    hn.emplace_back();
                    build(build, nd, side, hn.size() - 1);
                }
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

    // On a curved shape the solve's patches are chords, each standing for a piece of the
    // surface with a larger area: the flux it reflects is spread over that piece.
    for (size_t u = 0; u < N; ++u) {
        const double a = S.m_patches[size_t(U[u].patch)].area;
        if (a != U[u].area && a > 0)
            for (int k = 0; k < kBands; ++k)
                S.m_B[u * kBands + size_t(k)] = float(double(S.m_B[u * kBands + size_t(k)]) * U[u].area / a);
    }

    // ---- corner values for the interpolated read-out ------------------------------------------
    // Each corner of each unknown takes the area-weighted mean of the unknowns of the same
    // surface (same material, same plane and side; on a curved shape, the same shape and
    // side) that have a corner there. Summed in unknown order on one thread: deterministic.
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
            if (co.curved())
                return Key{std::llround(v.x / q), std::llround(v.y / q), std::llround(v.z / q),
                           U[u].side, co.shape, co.instance, std::numeric_limits<int64_t>::min(),
                           scene.shapes[size_t(co.shape)].material};
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
            // A curved shape's patches: the same shape (and instance) and side, not plane.
            const Key k =
                P[i].surface >= 0
                    ? Key{std::llround(v.x / qs), std::llround(v.y / qs), std::llround(v.z / qs),
                          P[i].unknown[0] >= 0 ? 0 : 1, P[i].surface, 0,
                          std::numeric_limits<int64_t>::min(), P[i].material}
                    : Key{std::llround(v.x / qs), std::llround(v.y / qs), std::llround(v.z / qs),
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
