#pragma once
/// Participating media (pbrt-v4's "homogeneous", "uniformgrid", "rgbgrid", "cloud" and
/// "nanovdb"): their coefficients at a point, the Henyey-Greenstein phase function, and the
/// majorants that delta and ratio tracking sample free flights against (one for a
/// homogeneous medium, a coarse grid of upper bounds traversed by a 3D DDA for the others).
#include <array>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "steradian/core/math.h"
#include "steradian/spectrum/sampled.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

// ---- Henyey-Greenstein phase function --------------------------------------------------

/// The Henyey-Greenstein phase function (1941) in pbrt-v4's convention: wo and wi both point
/// away from the scattering point, so cos_theta = dot(wo, wi) = -1 is forward scattering.
/// p = (1 - g^2) / (4 pi (1 + g^2 + 2 g cos_theta)^(3/2)); integrates to 1 over the sphere.
inline Float hg_phase(Float cos_theta, Float g) {
    Float denom = 1 + g * g + 2 * g * cos_theta;
    return kInv4Pi * (1 - g * g) / (denom * std::sqrt(std::max(denom, Float(0))));
}

struct PhaseSample {
    Vec3 wi;      ///< unit, away from the scattering point
    Float p = 0;  ///< phase function value (= pdf: sampled exactly)
};

/// Samples wi with density hg_phase(dot(wo, wi), g) by inverting its CDF in cos_theta.
PhaseSample sample_hg(Vec3 wo, Float g, Point2 u);

// ---- media -----------------------------------------------------------------------------

/// An affine map stored as floats (3 x 4, row-major), for the per-sample point lookups.
struct Affine {
    std::array<Float, 12> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    Point3 point(Point3 p) const {
        return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
                m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
    }
    Vec3 vector(Vec3 v) const {
        return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
                m[8] * v.x + m[9] * v.y + m[10] * v.z};
    }
};

/// Values on the nodes of an nx x ny x nz grid over [0, 1]^3, sample (i, j, k) at
/// ((i + 0.5) / nx, ...), trilinearly interpolated, zero outside the nodes (pbrt-v4's
/// SampledGrid: the value falls to zero over the outer half cell).
template <typename T>
struct SampledGrid {
    int nx = 1, ny = 1, nz = 1;
    std::vector<T> values;
    T at(int x, int y, int z) const {
        if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return T{};
        return values[(size_t(z) * ny + y) * nx + x];
    }
    /// The trilinear interpolation at p of convert(value) (for spectral grids: the values
    /// sampled at the path's wavelengths, as pbrt-v4 interpolates them).
    template <typename F>
    auto lookup(Point3 p, F&& convert) const {
        Float sx = p.x * Float(nx) - 0.5f, sy = p.y * Float(ny) - 0.5f, sz = p.z * Float(nz) - 0.5f;
        Float fx = std::floor(sx), fy = std::floor(sy), fz = std::floor(sz);
        int ix = int(fx), iy = int(fy), iz = int(fz);
        Float dx = sx - fx, dy = sy - fy, dz = sz - fz;
        auto v = [&](int a, int b, int c) { return convert(at(ix + a, iy + b, iz + c)); };
        auto d00 = v(0, 0, 0) * (1 - dx) + v(1, 0, 0) * dx;
        auto d10 = v(0, 1, 0) * (1 - dx) + v(1, 1, 0) * dx;
        auto d01 = v(0, 0, 1) * (1 - dx) + v(1, 0, 1) * dx;
        auto d11 = v(0, 1, 1) * (1 - dx) + v(1, 1, 1) * dx;
        return (d00 * (1 - dy) + d10 * dy) * (1 - dz) + (d01 * (1 - dy) + d11 * dy) * dz;
    }
    T lookup(Point3 p) const {
        return lookup(p, [](const T& t) { return t; });
    }
    /// The largest convert(value) of the nodes that the interpolation in the box [lo, hi] of
    /// [0, 1]^3 reads (a bound of the interpolation there).
    template <typename F>
    Float max_value(Point3 lo, Point3 hi, F&& convert) const {
        int x0 = std::max(int(std::floor(lo.x * nx - 0.5f)), 0);
        int y0 = std::max(int(std::floor(lo.y * ny - 0.5f)), 0);
        int z0 = std::max(int(std::floor(lo.z * nz - 0.5f)), 0);
        int x1 = std::min(int(std::floor(hi.x * nx - 0.5f)) + 1, nx - 1);
        int y1 = std::min(int(std::floor(hi.y * ny - 0.5f)) + 1, ny - 1);
        int z1 = std::min(int(std::floor(hi.z * nz - 0.5f)) + 1, nz - 1);
        Float m = 0;
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) m = std::max(m, Float(convert(at(x, y, z))));
        return m;
    }
};

/// A coarse grid of majorants over a medium's bounds (res^3 cells: 16^3 for pbrt-v4's grid
/// media, 64^3 for "nanovdb", as pbrt-v4): each cell holds an upper bound of the density the
/// medium takes in it.
struct MajorantGrid {
    static constexpr int kDefaultRes = 16;
    int res = kDefaultRes;
    std::vector<Float> cells;  ///< res^3, x fastest
    Float at(int x, int y, int z) const { return cells[(size_t(z) * res + y) * res + x]; }
};

/// pbrt-v4's "homogeneous": constant coefficients everywhere (no bounds: the surfaces that
/// name it as a side of their MediumInterface bound it).
struct HomogeneousMedium {
    Spectrum sigma_a, sigma_s;  ///< per unit length, before `scale`
    Float scale = 1;
    Spectrum le;  ///< emitted radiance (normalised to 1 nit as pbrt-v4 does), before le_scale
    Float le_scale = 0;
    Float g = 0;
};

/// pbrt-v4's "uniformgrid": sigma_a, sigma_s times a density grid over the box [p0, p1] of
/// the medium's space; emission Le times a scale grid, or a blackbody of the temperature grid.
struct GridMedium {
    Point3 p0, p1;
    Affine medium_from_world;
    Spectrum sigma_a, sigma_s;
    Float scale = 1, g = 0;
    SampledGrid<Float> density;
    std::optional<SampledGrid<Float>> temperature;
    Float temperature_offset = 0, temperature_scale = 1;
    Spectrum le;
    SampledGrid<Float> le_scale;  ///< 1 x 1 x 1 of the normalisation when not a grid
    bool emissive = false;
    MajorantGrid majorant;  ///< of the density
};

/// pbrt-v4's "rgbgrid": RGB sigma_a and sigma_s grids (each optional: 1 where absent) and an
/// optional RGB emission grid, over [p0, p1].
struct RgbGridMedium {
    Point3 p0, p1;
    Affine medium_from_world;
    Float scale = 1, g = 0, le_scale = 1;
    std::optional<SampledGrid<RgbUnboundedSpectrum>> sigma_a, sigma_s;
    /// Emission: the sRGB illuminant times these (pbrt-v4's RGBIlluminantSpectrum grid).
    std::optional<SampledGrid<RgbUnboundedSpectrum>> le;
    Spectrum illuminant;
    MajorantGrid majorant;  ///< of max(sigma_a + sigma_s) over the wavelengths, times scale
};

/// pbrt-v4's "cloud": sigma_a, sigma_s times a procedural density (octaves of Perlin noise
/// at frequency x the point, the point first displaced by the noise's differences when
/// `wispiness` > 0, fading with the height y; cloud_density()) over the box [p0, p1] of the
/// medium's space. Not emissive.
struct CloudMedium {
    Point3 p0, p1;
    Affine medium_from_world;
    Spectrum sigma_a, sigma_s;
    Float g = 0, density = 1, wispiness = 1, frequency = 5;
    MajorantGrid majorant;  ///< of the density (at most 1: cloud_density() clamps it)
};

/// The density of a cloud medium at p, a point of the medium's space (pbrt-v4's
/// CloudMedium::Density): in [0, 1].
Float cloud_density(const CloudMedium& m, Point3 p);

class NanoVdbGrid;  // media/nanovdb.h

/// pbrt-v4's "nanovdb": sigma_a, sigma_s (times `scale`) times the trilinear interpolation
/// of a NanoVDB density grid, over the grid's bounds in the medium's space (the grid's world
/// space); emission Lescale x a blackbody (normalised to a peak of 1) of the optional
/// temperature grid's (value - offset) x scale, where that is above 100 K.
struct NanoVdbMedium {
    Point3 p0, p1;  ///< the density's bounds, with the temperature's
    Affine medium_from_world;
    Spectrum sigma_a, sigma_s;
    Float scale = 1, g = 0;
    std::shared_ptr<const NanoVdbGrid> density, temperature;
    Float le_scale = 1, temperature_offset = 0, temperature_scale = 1;
    MajorantGrid majorant;  ///< of the density (64^3)
};

using Medium = std::variant<HomogeneousMedium, GridMedium, RgbGridMedium, CloudMedium,
                            NanoVdbMedium>;

/// The coefficients at a point.
struct MediumProperties {
    SampledSpectrum sigma_a, sigma_s, le;
    Float g = 0;
};

/// Medium properties at world point p.
MediumProperties medium_properties(const Medium& m, Point3 p, const SampledWavelengths& lambda);

/// Fills the majorant grid of a grid medium (call once its grids are final).
void build_majorants(GridMedium& m);
void build_majorants(RgbGridMedium& m);
void build_majorants(CloudMedium& m);
void build_majorants(NanoVdbMedium& m);

/// One segment [t0, t1) of a ray with a constant majorant.
struct MajorantSegment {
    Float t0 = 0, t1 = 0;
    SampledSpectrum sigma_maj{0};
};

/// The majorant segments along a ray (t in units of the ray's direction) up to t_max, in
/// order: one for a homogeneous medium; the cells the other media's bounds cut from the ray,
/// visited by a 3D DDA. Segments of zero majorant may be skipped.
class MajorantIterator {
  public:
    MajorantIterator(const Medium& m, const Ray& ray, Float t_max,
                     const SampledWavelengths& lambda);
    std::optional<MajorantSegment> next();

  private:
    const MajorantGrid* m_grid = nullptr;
    SampledSpectrum m_sigma_t{0};
    Float m_t0 = 0, m_t1 = 0;
    bool m_done = true;
    // DDA state (grid media)
    std::array<Float, 3> m_next_t{}, m_delta_t{};
    std::array<int, 3> m_step{}, m_out{}, m_cell{};
};

/// Majorant-based free-flight sampling along `ray` up to t_max (pbrt-v4's SampleT_maj):
/// tentative collisions are drawn with density sigma_maj[0] exp(-sigma_maj[0] t) (the hero
/// wavelength's majorant) from u and then rng; at each, callback(p, props, sigma_maj, T_maj)
/// is called with the majorant transmittance since the last collision, and tracking stops if
/// it returns false. Returns the majorant transmittance from the last collision to t_max
/// (1 if the callback stopped it).
template <typename Rng, typename F>
SampledSpectrum sample_t_maj(const Medium& medium, Ray ray, Float t_max, Float u, Rng& rng,
                             const SampledWavelengths& lambda, F&& callback) {
    // Unit direction, so that t is a distance.
    Float len = length(ray.d);
    t_max *= len;
    ray.d = ray.d / len;
    MajorantIterator iter(medium, ray, t_max, lambda);
    SampledSpectrum t_maj(1);
    while (auto seg = iter.next()) {
        if (seg->sigma_maj[0] == 0) {
            Float dt = std::min(seg->t1, std::numeric_limits<Float>::max()) - seg->t0;
            t_maj *= exp(seg->sigma_maj * -dt);
            continue;
        }
        Float t0 = seg->t0;
        while (true) {
            Float t = t0 - std::log1p(-std::min(u, Float(0x1.fffffep-1))) / seg->sigma_maj[0];
            u = rng.next_float();
            if (t < seg->t1) {
                t_maj *= exp(seg->sigma_maj * -(t - t0));
                Point3 p = ray.at(t);
                if (!callback(p, medium_properties(medium, p, lambda), seg->sigma_maj, t_maj))
                    return SampledSpectrum(1);
                t_maj = SampledSpectrum(1);
                t0 = t;
            } else {
                Float dt = std::min(seg->t1, std::numeric_limits<Float>::max()) - t0;
                t_maj *= exp(seg->sigma_maj * -dt);
                break;
            }
        }
    }
    return t_maj;
}

/// Whether the medium can emit (a non-zero Le or a temperature grid).
bool is_emissive(const Medium& m);

/// pbrt-v4's table of measured scattering coefficients (per mm): sigma_s (reduced, sigma_s')
/// and sigma_a as sRGB triples; false if `name` is not in it.
bool measured_medium(const std::string& name, Rgb& sigma_s, Rgb& sigma_a);

}  // namespace sr
