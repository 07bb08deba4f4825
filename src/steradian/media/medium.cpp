#include "steradian/media/medium.h"

#include <string>

#include "steradian/core/noise.h"
#include "steradian/media/nanovdb.h"

namespace sr {

PhaseSample sample_hg(Vec3 wo, Float g, Point2 u) {
    // The usual inversion is for the cosine between the propagation directions, mu' =
    // dot(-wo, wi); its density is proportional to (1 + g^2 - 2 g mu')^(-3/2), whose CDF
    // inverts to mu' = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g).
    Float mu;
    if (std::abs(g) < Float(1e-3)) {
        mu = 1 - 2 * u.x;
    } else {
        Float q = (1 - g * g) / (1 - g + 2 * g * u.x);
        mu = (1 + g * g - q * q) / (2 * g);
    }
    mu = std::clamp(mu, Float(-1), Float(1));
    Float sin_theta = std::sqrt(std::max(Float(0), 1 - mu * mu));
    Float phi = 2 * kPi * u.y;
    Frame f = Frame::from_z(-wo);
    Vec3 wi = f.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), mu));
    return PhaseSample{wi, hg_phase(dot(wo, wi), g)};
}

namespace {

/// p in the grid's unit cube [0, 1]^3 (p0 -> 0, p1 -> 1).
Point3 unit_coords(Point3 p, Point3 p0, Point3 p1) {
    return Point3((p.x - p0.x) / (p1.x - p0.x), (p.y - p0.y) / (p1.y - p0.y),
                  (p.z - p0.z) / (p1.z - p0.z));
}

MediumProperties properties(const HomogeneousMedium& m, Point3, const SampledWavelengths& lambda) {
    MediumProperties mp;
    mp.sigma_a = m.sigma_a.sample(lambda) * m.scale;
    mp.sigma_s = m.sigma_s.sample(lambda) * m.scale;
    mp.le = m.le_scale > 0 ? m.le.sample(lambda) * m.le_scale : SampledSpectrum(0);
    mp.g = m.g;
    return mp;
}

MediumProperties properties(const GridMedium& m, Point3 p, const SampledWavelengths& lambda) {
    Point3 u = unit_coords(m.medium_from_world.point(p), m.p0, m.p1);
    Float d = m.density.lookup(u);
    MediumProperties mp;
    mp.sigma_a = m.sigma_a.sample(lambda) * (m.scale * d);
    mp.sigma_s = m.sigma_s.sample(lambda) * (m.scale * d);
    mp.le = SampledSpectrum(0);
    mp.g = m.g;
    if (m.emissive) {
        Float s = m.le_scale.lookup(u);
        if (s > 0) {
            if (m.temperature) {
                Float t = (m.temperature->lookup(u) - m.temperature_offset) * m.temperature_scale;
                if (t > 100) mp.le = Spectrum(BlackbodySpectrum(t)).sample(lambda) * s;
            } else {
                mp.le = m.le.sample(lambda) * s;
            }
        }
    }
    return mp;
}

MediumProperties properties(const RgbGridMedium& m, Point3 p, const SampledWavelengths& lambda) {
    Point3 u = unit_coords(m.medium_from_world.point(p), m.p0, m.p1);
    auto sample = [&](const RgbUnboundedSpectrum& s) {
        SampledSpectrum r;
        for (int i = 0; i < kSpectrumSamples; ++i) r[i] = s(lambda[i]);
        return r;
    };
    MediumProperties mp;
    mp.sigma_a = (m.sigma_a ? m.sigma_a->lookup(u, sample) : SampledSpectrum(1)) * m.scale;
    mp.sigma_s = (m.sigma_s ? m.sigma_s->lookup(u, sample) : SampledSpectrum(1)) * m.scale;
    mp.le = m.le && m.le_scale > 0
                ? m.le->lookup(u, sample) * m.illuminant.sample(lambda) * m.le_scale
                : SampledSpectrum(0);
    mp.g = m.g;
    return mp;
}

bool inside(Point3 p, Point3 p0, Point3 p1) {
    return p.x >= p0.x && p.y >= p0.y && p.z >= p0.z && p.x <= p1.x && p.y <= p1.y &&
           p.z <= p1.z;
}

MediumProperties properties(const CloudMedium& m, Point3 p, const SampledWavelengths& lambda) {
    Point3 pm = m.medium_from_world.point(p);
    // Nothing outside the bounds (pbrt-v4 never looks there: its majorant is 0 outside).
    Float d = inside(pm, m.p0, m.p1) ? cloud_density(m, pm) : 0;
    MediumProperties mp;
    mp.sigma_a = m.sigma_a.sample(lambda) * d;
    mp.sigma_s = m.sigma_s.sample(lambda) * d;
    mp.le = SampledSpectrum(0);
    mp.g = m.g;
    return mp;
}

MediumProperties properties(const NanoVdbMedium& m, Point3 p, const SampledWavelengths& lambda) {
    Point3 pm = m.medium_from_world.point(p);
    MediumProperties mp;
    mp.g = m.g;
    mp.le = SampledSpectrum(0);
    if (!inside(pm, m.p0, m.p1)) {
        mp.sigma_a = mp.sigma_s = SampledSpectrum(0);
        return mp;
    }
    // A negative density (not a fog volume's) counts as none.
    Float d = std::max(m.density->sample(pm), Float(0)) * m.scale;
    mp.sigma_a = m.sigma_a.sample(lambda) * d;
    mp.sigma_s = m.sigma_s.sample(lambda) * d;
    if (m.temperature && m.le_scale > 0) {
        Float t = (m.temperature->sample(pm) - m.temperature_offset) * m.temperature_scale;
        if (t > 100 && std::isfinite(t))
            mp.le = Spectrum(BlackbodySpectrum(t)).sample(lambda) * m.le_scale;
    }
    return mp;
}

template <typename F>
void fill_majorants(MajorantGrid& g, F&& max_in) {
    const int n = g.res;
    g.cells.assign(size_t(n) * n * n, 0);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                g.cells[(size_t(z) * n + y) * n + x] =
                    max_in(Point3(Float(x) / n, Float(y) / n, Float(z) / n),
                           Point3(Float(x + 1) / n, Float(y + 1) / n, Float(z + 1) / n));
}

}  // namespace

MediumProperties medium_properties(const Medium& m, Point3 p, const SampledWavelengths& lambda) {
    return std::visit([&](const auto& x) { return properties(x, p, lambda); }, m);
}

void build_majorants(GridMedium& m) {
    fill_majorants(m.majorant, [&](Point3 lo, Point3 hi) {
        return m.density.max_value(lo, hi, [](Float v) { return v; });
    });
}

Float cloud_density(const CloudMedium& m, Point3 p) {
    Point3 pp(p.x * m.frequency, p.y * m.frequency, p.z * m.frequency);
    if (m.wispiness > 0) {
        // Two octaves of displacement by the noise's differences.
        Float amplitude = Float(0.05) * m.wispiness, f = 10;
        for (int i = 0; i < 2; ++i) {
            pp = pp + perlin_noise_differences(Point3(pp.x * f, pp.y * f, pp.z * f)) * amplitude;
            amplitude *= Float(0.5);
            f *= Float(1.99);
        }
    }
    // Five octaves of noise, then a fall-off with the height y and a floor below y = 0.5.
    Float d = 0, omega = Float(0.5), f = 1;
    for (int i = 0; i < 5; ++i) {
        d += omega * perlin_noise(Point3(pp.x * f, pp.y * f, pp.z * f));
        omega *= Float(0.5);
        f *= Float(1.99);
    }
    d = std::clamp((1 - p.y) * Float(4.5) * m.density * d, Float(0), Float(1));
    d += 2 * std::max(Float(0), Float(0.5) - p.y);
    return std::clamp(d, Float(0), Float(1));
}

void build_majorants(CloudMedium& m) {
    // cloud_density() = clamp(clamp((1 - y) 4.5 density N, 0, 1) + 2 max(0, 0.5 - y), 0, 1)
    // with N the sum of five octaves of noise, weights 1/2 ... 1/32. Each noise value is a
    // convex combination of gradient terms +-a +-b with |a|, |b| <= 1 (offsets from the cell's
    // corners), so |noise| <= 2 and |N| <= 2 x 31/32: per cell, a true bound from its y range
    // (y may exceed 1: there the first term is positive where N < 0). pbrt-v4 bounds the
    // density by 1 everywhere; this is at most that.
    m.majorant.res = MajorantGrid::kDefaultRes;
    fill_majorants(m.majorant, [&](Point3 lo, Point3 hi) {
        // (A little wider: the DDA's float arithmetic may place a point a hair outside.)
        Float y0 = m.p0.y + (lo.y - Float(1e-4)) * (m.p1.y - m.p0.y);
        Float y1 = m.p0.y + (hi.y + Float(1e-4)) * (m.p1.y - m.p0.y);
        Float dy = std::max(std::abs(1 - y0), std::abs(1 - y1));
        Float a = std::min(Float(1), dy * Float(4.5) * std::abs(m.density) * 2 * Float(31.0 / 32));
        return std::min(Float(1), a + 2 * std::max(Float(0), Float(0.5) - y0));
    });
}

void build_majorants(NanoVdbMedium& m) {
    m.majorant.res = 64;
    m.density->fill_majorants(m.majorant, m.p0, m.p1);
    for (Float& c : m.majorant.cells) c *= m.scale;
}

void build_majorants(RgbGridMedium& m) {
    auto mx = [](const RgbUnboundedSpectrum& s) { return s.max_value(); };
    fill_majorants(m.majorant, [&](Point3 lo, Point3 hi) {
        Float a = m.sigma_a ? m.sigma_a->max_value(lo, hi, mx) : 1;
        Float s = m.sigma_s ? m.sigma_s->max_value(lo, hi, mx) : 1;
        return m.scale * (a + s);
    });
}

bool is_emissive(const Medium& m) {
    if (auto* h = std::get_if<HomogeneousMedium>(&m)) return h->le_scale > 0;
    if (auto* g = std::get_if<GridMedium>(&m)) return g->emissive;
    if (std::holds_alternative<CloudMedium>(m)) return false;
    if (auto* v = std::get_if<NanoVdbMedium>(&m)) return v->temperature && v->le_scale > 0;
    const auto& r = std::get<RgbGridMedium>(m);
    return r.le && r.le_scale > 0;
}

MajorantIterator::MajorantIterator(const Medium& m, const Ray& ray, Float t_max,
                                   const SampledWavelengths& lambda) {
    if (auto* h = std::get_if<HomogeneousMedium>(&m)) {
        m_sigma_t = (h->sigma_a.sample(lambda) + h->sigma_s.sample(lambda)) * h->scale;
        m_t0 = 0;
        m_t1 = t_max;
        m_done = false;
        return;
    }
    // A grid medium: the ray in the unit cube of its bounds.
    Point3 p0, p1;
    const Affine* xf;
    if (auto* g = std::get_if<GridMedium>(&m)) {
        m_sigma_t = (g->sigma_a.sample(lambda) + g->sigma_s.sample(lambda)) * g->scale;
        m_grid = &g->majorant;
        p0 = g->p0, p1 = g->p1, xf = &g->medium_from_world;
    } else if (auto* c = std::get_if<CloudMedium>(&m)) {
        m_sigma_t = c->sigma_a.sample(lambda) + c->sigma_s.sample(lambda);
        m_grid = &c->majorant;
        p0 = c->p0, p1 = c->p1, xf = &c->medium_from_world;
    } else if (auto* v = std::get_if<NanoVdbMedium>(&m)) {
        // The majorant grid holds scale x density.
        m_sigma_t = v->sigma_a.sample(lambda) + v->sigma_s.sample(lambda);
        m_grid = &v->majorant;
        p0 = v->p0, p1 = v->p1, xf = &v->medium_from_world;
    } else {
        const auto& r = std::get<RgbGridMedium>(m);
        m_sigma_t = SampledSpectrum(1);
        m_grid = &r.majorant;
        p0 = r.p0, p1 = r.p1, xf = &r.medium_from_world;
    }
    Point3 o = unit_coords(xf->point(ray.o), p0, p1);
    Vec3 dm = xf->vector(ray.d);
    Vec3 d(dm.x / (p1.x - p0.x), dm.y / (p1.y - p0.y), dm.z / (p1.z - p0.z));
    // Slab test against [0, 1]^3.
    Float t0 = 0, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
        Float inv = 1 / d[a];
        Float tn = (0 - o[a]) * inv, tf = (1 - o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        if (std::isnan(tn) || std::isnan(tf)) {  // parallel, on a face
            if (o[a] < 0 || o[a] > 1) return;
            continue;
        }
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
        if (t0 > t1) return;
    }
    if (!(t0 < t1)) return;
    m_t0 = t0, m_t1 = t1, m_done = false;
    const int n = m_grid->res;
    Point3 pg = o + d * t0;
    for (int a = 0; a < 3; ++a) {
        m_cell[a] = std::clamp(int(pg[a] * n), 0, n - 1);
        if (d[a] == 0) {
            m_next_t[a] = kInfinity;
            m_delta_t[a] = kInfinity;
            m_step[a] = 0;
            m_out[a] = -2;
        } else if (d[a] > 0) {
            m_next_t[a] = t0 + (Float(m_cell[a] + 1) / n - pg[a]) / d[a];
            m_delta_t[a] = 1 / (n * d[a]);
            m_step[a] = 1;
            m_out[a] = n;
        } else {
            m_next_t[a] = t0 + (Float(m_cell[a]) / n - pg[a]) / d[a];
            m_delta_t[a] = -1 / (n * d[a]);
            m_step[a] = -1;
            m_out[a] = -1;
        }
    }
}

std::optional<MajorantSegment> MajorantIterator::next() {
    if (m_done) return std::nullopt;
    if (!m_grid) {
        m_done = true;
        return MajorantSegment{m_t0, m_t1, m_sigma_t};
    }
    int a = m_next_t[0] < m_next_t[1] ? (m_next_t[0] < m_next_t[2] ? 0 : 2)
                                      : (m_next_t[1] < m_next_t[2] ? 1 : 2);
    Float t_exit = std::min(m_next_t[a], m_t1);
    MajorantSegment seg{m_t0, t_exit, m_sigma_t * m_grid->at(m_cell[0], m_cell[1], m_cell[2])};
    m_t0 = t_exit;
    if (t_exit >= m_t1) {
        m_done = true;
    } else {
        m_cell[a] += m_step[a];
        if (m_cell[a] == m_out[a]) m_done = true;
        m_next_t[a] += m_delta_t[a];
    }
    return seg;
}

bool measured_medium(const std::string& name, Rgb& sigma_s, Rgb& sigma_a) {
    struct Measured {
        const char* name;
        double sigma_prime_s[3], sigma_a[3];  // mm^-1
    };
    // Data as tabulated in pbrt-v4 (src/pbrt/media.cpp, GetMediumScatteringProperties).
    // The first twelve: H. W. Jensen, S. R. Marschner, M. Levoy, P. Hanrahan, "A Practical
    // Model for Subsurface Light Transport", Proc. SIGGRAPH 2001 (reduced scattering
    // coefficient sigma_s' and absorption coefficient, per mm). The others: S. G. Narasimhan,
    // M. Gupta, C. Donner, R. Ramamoorthi, S. K. Nayar, H. W. Jensen, "Acquiring Scattering
    // Properties of Participating Media by Dilution", Proc. SIGGRAPH 2006.
    static const Measured kTable[] = {
        // clang-format off
        {"Apple", {2.29, 2.39, 1.97}, {0.0030, 0.0034, 0.046}},
        {"Chicken1", {0.15, 0.21, 0.38}, {0.015, 0.077, 0.19}},
        {"Chicken2", {0.19, 0.25, 0.32}, {0.018, 0.088, 0.20}},
        {"Cream", {7.38, 5.47, 3.15}, {0.0002, 0.0028, 0.0163}},
        {"Ketchup", {0.18, 0.07, 0.03}, {0.061, 0.97, 1.45}},
        {"Marble", {2.19, 2.62, 3.00}, {0.0021, 0.0041, 0.0071}},
        {"Potato", {0.68, 0.70, 0.55}, {0.0024, 0.0090, 0.12}},
        {"Skimmilk", {0.70, 1.22, 1.90}, {0.0014, 0.0025, 0.0142}},
        {"Skin1", {0.74, 0.88, 1.01}, {0.032, 0.17, 0.48}},
        {"Skin2", {1.09, 1.59, 1.79}, {0.013, 0.070, 0.145}},
        {"Spectralon", {11.6, 20.4, 14.9}, {0.00, 0.00, 0.00}},
        {"Wholemilk", {2.55, 3.21, 3.77}, {0.0011, 0.0024, 0.014}},
        {"Lowfat Milk", {0.89187, 1.5136, 2.532}, {0.002875, 0.00575, 0.0115}},
        {"Reduced Milk", {2.4858, 3.1669, 4.5214}, {0.0025556, 0.0051111, 0.012778}},
        {"Regular Milk", {4.5513, 5.8294, 7.136}, {0.0015333, 0.0046, 0.019933}},
        {"Espresso", {0.72378, 0.84557, 1.0247}, {4.7984, 6.5751, 8.8493}},
        {"Mint Mocha Coffee", {0.31602, 0.38538, 0.48131}, {3.772, 5.8228, 7.82}},
        {"Lowfat Soy Milk", {0.30576, 0.34233, 0.61664}, {0.0014375, 0.0071875, 0.035937}},
        {"Regular Soy Milk", {0.59223, 0.73866, 1.4693}, {0.0019167, 0.0095833, 0.065167}},
        {"Lowfat Chocolate Milk", {0.64925, 0.83916, 1.1057}, {0.0115, 0.0368, 0.1564}},
        {"Regular Chocolate Milk", {1.4585, 2.1289, 2.9527}, {0.010063, 0.043125, 0.14375}},
        {"Coke", {8.9053e-05, 8.372e-05, 0}, {0.10014, 0.16503, 0.2468}},
        {"Pepsi", {6.1697e-05, 4.2564e-05, 0}, {0.091641, 0.14158, 0.20729}},
        {"Sprite", {6.0306e-06, 6.4139e-06, 6.5504e-06}, {0.001886, 0.0018308, 0.0020025}},
        {"Gatorade", {0.0024574, 0.003007, 0.0037325}, {0.024794, 0.019289, 0.008878}},
        {"Chardonnay", {1.7982e-05, 1.3758e-05, 1.2023e-05}, {0.010782, 0.011855, 0.023997}},
        {"White Zinfandel", {1.7501e-05, 1.9069e-05, 1.288e-05}, {0.012072, 0.016184, 0.019843}},
        {"Merlot", {2.1129e-05, 0, 0}, {0.11632, 0.25191, 0.29434}},
        {"Budweiser Beer", {2.4356e-05, 2.4079e-05, 1.0564e-05}, {0.011492, 0.024911, 0.057786}},
        {"Coors Light Beer", {5.0922e-05, 4.301e-05, 0}, {0.006164, 0.013984, 0.034983}},
        {"Clorox", {0.0024035, 0.0031373, 0.003991}, {0.0033542, 0.014892, 0.026297}},
        {"Apple Juice", {0.00013612, 0.00015836, 0.000227}, {0.012957, 0.023741, 0.052184}},
        {"Cranberry Juice", {0.00010402, 0.00011646, 7.8139e-05}, {0.039437, 0.094223, 0.12426}},
        {"Grape Juice", {5.382e-05, 0, 0}, {0.10404, 0.23958, 0.29325}},
        {"Ruby Grapefruit Juice", {0.011002, 0.010927, 0.011036}, {0.085867, 0.18314, 0.25262}},
        {"White Grapefruit Juice", {0.22826, 0.23998, 0.32748}, {0.0138, 0.018831, 0.056781}},
        {"Shampoo", {0.0007176, 0.0008303, 0.0009016}, {0.014107, 0.045693, 0.061717}},
        {"Strawberry Shampoo", {0.00015671, 0.00015947, 1.518e-05}, {0.01449, 0.05796, 0.075823}},
        {"Head & Shoulders Shampoo", {0.023805, 0.028804, 0.034306}, {0.084621, 0.15688, 0.20365}},
        {"Lemon Tea Powder", {0.040224, 0.045264, 0.051081}, {2.4288, 4.5757, 7.2127}},
        {"Orange Powder", {0.00015617, 0.00017482, 0.0001762}, {0.001449, 0.003441, 0.007863}},
        {"Pink Lemonade Powder", {0.00012103, 0.00013073, 0.00012528}, {0.001165, 0.002366, 0.003195}},
        {"Cappuccino Powder", {1.8436, 2.5851, 2.1662}, {35.844, 49.547, 61.084}},
        {"Salt Powder", {0.027333, 0.032451, 0.031979}, {0.28415, 0.3257, 0.34148}},
        {"Sugar Powder", {0.00022272, 0.00025513, 0.000271}, {0.012638, 0.031051, 0.050124}},
        {"Suisse Mocha Powder", {2.7979, 3.5452, 4.3365}, {17.502, 27.004, 35.433}},
        {"Pacific Ocean Surface Water", {0.0001764, 0.00032095, 0.00019617}, {0.031845, 0.031324, 0.030147}},
        // clang-format on
    };
    for (const Measured& m : kTable)
        if (name == m.name) {
            sigma_s = Rgb{Float(m.sigma_prime_s[0]), Float(m.sigma_prime_s[1]),
                          Float(m.sigma_prime_s[2])};
            sigma_a = Rgb{Float(m.sigma_a[0]), Float(m.sigma_a[1]), Float(m.sigma_a[2])};
            return true;
        }
    return false;
}

}  // namespace sr
