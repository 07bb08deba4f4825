#pragma once
/// Integrator "radiosity" (a steradian extension; docs/radiosity.md): the scene's diffuse
/// triangles, spheres, disks and cylinders meshed into patches (split uniformly to a patch size, then adaptively where the
/// direct irradiance varies), form factors from the analytic point-to-polygon form factor
/// integrated over the receiving patch with ray-cast visibility, and the radiosity system
/// solved by preconditioned conjugate gradients on its symmetric form to a stated residual.
///
/// Spectral representation: 48 wavelengths 10 nm apart, 360..830 nm, read between them by
/// linear interpolation. Direct light is never in the mesh: the solution holds the exitance
/// *reflected* by each patch (each side of it), computed from the exact direct irradiance at
/// the patch's quadrature points; the final gather adds direct light at the receiving point
/// with the path tracer's light sampling, and reads the solution where its rays first meet a
/// diffuse surface.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "steradian/integrators/radiosity/form_factor.h"
#include "steradian/sensors/meter.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

class Scene;
class Sampler;
struct PathCounters;
struct RadiosityParams;
struct SurfaceHit;

namespace radiosity {
inline constexpr int kBands = 48;
inline constexpr Float kFirstNm = 360, kStepNm = 10;
inline Float band_lambda(int k) { return kFirstNm + kStepNm * Float(k); }
}  // namespace radiosity

struct RadiosityStats {
    size_t diffuse_triangles = 0;  ///< scene triangles meshed
    size_t patches = 0;            ///< leaf patches
    size_t unknowns = 0;           ///< patch sides in the system
    size_t pairs = 0;              ///< form factors computed (facing pairs, or links)
    uint64_t rays = 0;             ///< visibility and direct-light shadow rays
    int solves = 0;                ///< right-hand sides solved (after rank reduction)
    int iterations = 0;            ///< conjugate-gradient iterations, or hierarchical sweeps
    double residual = 0;           ///< largest relative residual reached
    double seconds = 0;            ///< wall, all of the pass
    double seconds_mesh = 0;       ///< wall: the adaptive subdivision
    double seconds_direct = 0;     ///< wall: reflectances and direct irradiance per patch
    double seconds_exchange = 0;   ///< wall: links / form factors (and the CG solve)
    double seconds_sweeps = 0;     ///< wall: the hierarchical solver's sweeps
    std::vector<std::string> notes;  ///< what the pass left out (unmeshed shapes, ...)
};

/// The solved mesh: per patch side its reflected exitance (scene units), and the lookup from
/// a scene hit to its patch.
class RadiositySolution {
public:
    struct Patch {
        std::array<radiosity::DVec3, 3> p;
        radiosity::DVec3 n;  ///< unit normal of the front side (the triangle's winding)
        /// The area of the surface it stands for: its triangle's, or on a curved shape the
        /// curved piece's (larger than the chord triangle's).
        double area = 0;
        int unknown[2] = {-1, -1};  ///< front and back side (-1: not in the system)
        int material = -1;          ///< the scene material of its triangle
        int surface = -1;           ///< on a curved shape: which one (per instance); else -1
    };
    /// Reflected exitance at a hit of the scene, at the wavelengths lambda; false if the hit
    /// is not on a meshed (diffuse) surface.
    /// `area`, if given, receives the area of the hit's patch.
    bool exitance(const SurfaceHit& h, const SampledWavelengths& lambda, SampledSpectrum& B,
                  double* area = nullptr) const;
    /// The exitance at a hit weighted by a meter's spectral weight (Meter::spectral_weight)
    /// and integrated over 360-830 nm exactly, the bands read linearly between them as
    /// exitance() reads them: what meter_weigh() of exitance() estimates from four sampled
    /// wavelengths, without their variance. False if the hit is not on a meshed surface.
    bool weighted_exitance(const SurfaceHit& h, MeterWeighting w, double& Bw,
                           double* area = nullptr) const;
    /// Whether a hit's surface is meshed (diffuse).
    bool meshed(const SurfaceHit& h) const;

    const std::vector<Patch>& patches() const { return m_patches; }
    /// Exitance of unknown u at band k (the patch side's mean).
    float band(int u, int k) const { return m_B[size_t(u) * radiosity::kBands + size_t(k)]; }
    /// Whether the solution is read interpolated from its patches' corners.
    bool interpolated() const { return !m_Bv.empty(); }
    /// Exitance of unknown u at corner c (0..2, the patch's p[c]) and band k: the
    /// area-weighted mean of the unknowns of the same surface that share that corner (the
    /// patch's own mean if not interpolated).
    float corner_band(int u, int c, int k) const {
        return m_Bv.empty() ? band(u, k)
                            : m_Bv[(size_t(u) * 3 + size_t(c)) * radiosity::kBands + size_t(k)];
    }
    const RadiosityStats& stats() const { return m_stats; }
    /// A hash (64-bit FNV-1a) of the solution's patches and exitances: equal on two
    /// processes that solved the same system to the same bits (docs/distributed.md).
    uint64_t digest() const;

private:
    friend std::unique_ptr<RadiositySolution> solve_radiosity(const Scene&, const RadiosityParams&,
                                                             int threads);
    /// The leaf patch a hit lies on (-1: none), and the hit's barycentrics (b1, b2) in it.
    int leaf_at(const SurfaceHit& h, double* b1 = nullptr, double* b2 = nullptr) const;
    /// The patch side a hit sees (false: not on a meshed surface): its unknown u (-1: a side
    /// outside the system), the hit's barycentrics in the patch and, if asked, its area.
    bool side_at(const SurfaceHit& h, int& u, double& b1, double& b2, double* area) const;
    struct Node {
        int child = -1;  ///< first of four children, or -1 (leaf)
        int patch = -1;  ///< leaf: index into m_patches
    };
public:
    /// A coarse triangle: the root of a patch tree. A mesh's triangle, or a chord triangle of
    /// a curved shape's (sphere, disk, cylinder) tessellation in its (u, v) parameters, whose
    /// subdivisions take their corners on the true surface.
    struct Coarse {
        int shape = -1;
        int instance = -1;  ///< the object instance it belongs to (-1: a top-level shape)
        uint32_t prim = 0;
        radiosity::DVec3 p0, e1, e2;  ///< p0 and the edges to p1 and p2 (world space)
        radiosity::DVec3 n;
        int root = -1;
        bool black = false;  ///< reflects nothing (its sides are not in the system)
        /// Curved shapes: the cell [u0, u1] x [v0, v1] of the shape's (u, v) and the part of
        /// it the triangle covers: -1 none (a mesh triangle); 0 the lower triangle, corners
        /// (u0, v0) (u1, v0) (u1, v1); 1 the upper, (u0, v0) (u1, v1) (u0, v1); 2 the whole
        /// cell as a fan from a pole at v0 (corners the pole, (u1, v1), (u0, v1)); 3 the whole
        /// cell as a fan from a pole at v1 (corners (u0, v0), (u1, v0), the pole).
        int kind = -1;
        double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
        int surface = -1;  ///< curved: its entry in m_surfaces
        bool curved() const { return kind >= 0; }
        /// The (u, v) of the point at barycentrics (b1, b2) (b0 = 1 - b1 - b2).
        void uv_of(double b1, double b2, double& u, double& v) const;
        /// The barycentrics of the point at (u, v) (inside the cell).
        void bary_of(double u, double v, double& b1, double& b2) const;
    };
private:
    /// A meshed shape (per object instance when instanced): its coarse triangles.
    struct Surface {
        int first = -1;      ///< its first coarse triangle
        int nu = 0, nv = 0;  ///< curved: its (u, v) grid, two coarse triangles per cell; 0: a mesh
    };
    /// The coarse triangle a hit lies on (-1: none) and the hit's barycentrics in it.
    int coarse_at(const SurfaceHit& h, double& b1, double& b2) const;
    std::vector<Surface> m_surfaces;
    std::vector<int> m_shape_surface;     ///< per scene shape (top level): its surface, or -1
    std::vector<int> m_proto_slot;        ///< per scene shape: its index in its prototype
    std::vector<int> m_instance_base;     ///< per instance: its first m_instance_surface entry
    std::vector<int> m_instance_surface;  ///< per instance and prototype slot: surface, or -1
    std::vector<Coarse> m_coarse;
    std::vector<Node> m_nodes;
    std::vector<Patch> m_patches;
    std::vector<float> m_B;   ///< unknowns x kBands
    std::vector<float> m_Bv;  ///< unknowns x 3 corners x kBands (empty: not interpolated)
    /// Per unknown (x 3 corners when interpolated) x 3 weightings: the weighted exitance.
    std::vector<double> m_Bw;
    /// Fills m_Bw from m_B and m_Bv.
    void weigh_bands();
    RadiosityStats m_stats;
};

/// Meshes and solves the scene's diffuse surfaces. Deterministic: the same scene and
/// parameters give the same solution on any number of threads (0: all).
std::unique_ptr<RadiositySolution> solve_radiosity(const Scene& scene, const RadiosityParams& params,
                                                  int threads = 0);

/// Whether every surface of the scene is one the radiosity pass models exactly: diffuse
/// (Lambertian) or interface triangle meshes, spheres, disks and cylinders (top-level or in
/// object instances; not curves), and no media. `why` says what is not, when it returns false.
bool radiosity_models_exactly(const Scene& scene, std::string* why = nullptr);

/// Writes the solved mesh as a binary PLY: per face (patch) its photopic exitance in lm/m^2
/// ("exitance": the solution itself, the front side's, else the back's); per vertex, for a
/// smooth look, the area-weighted mean over the patches of the same surface (material, plane
/// and side) that have a corner there, as sRGB (XYZ to sRGB, the brightest vertex white) and
/// lm/m^2 ("exitance").
void write_radiosity_ply(const RadiositySolution& sol, const std::string& path);

/// Radiance arriving along `ray` as the final gather sees it: the solution's reflected
/// exitance / pi at the first diffuse surface, paths continuing through non-diffuse
/// surfaces by BSDF sampling (at most `max_depth` such bounces), with emission and light at
/// infinity counted only after such a bounce (the caller counts direct light).
SampledSpectrum radiosity_gather(const Scene& scene, const RadiositySolution& sol, Ray ray,
                                 SampledWavelengths& lambda, Sampler& sampler,
                                 PathCounters& counters, int max_depth);

/// One sample of value `point` of meter `m` by the radiosity method, counting `component` of
/// the light (a receiving meter's: direct light by the path tracer's first vertex, light and
/// BSDF sampling; indirect by one gather ray; measure() asks for the indirect part only
/// where it computes the direct part by direct_light.h).
double radiosity_meter_sample(const Scene& scene, const RadiositySolution& sol, const Meter& m,
                              size_t point, Sampler& sampler, PathCounters& counters,
                              MeterComponent component);

/// A camera sample's radiance by the radiosity integrator (the camera ray's first hit given).
SampledSpectrum radiosity_li_from(const Scene& scene, const RadiositySolution& sol,
                                  const Ray& ray, bool found, SurfaceHit& hit,
                                  SampledWavelengths& lambda, Sampler& sampler,
                                  PathCounters& counters);

}  // namespace sr
