#pragma once
/// The flat runtime scene: vectors of shapes, materials, textures and lights with integer
/// ids between them, one Embree acceleration structure, the camera and render settings.
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "steradian/camera/camera.h"
#include "steradian/film/film.h"
#include "steradian/film/filter.h"
#include "steradian/geometry/scene_geometry.h"
#include "steradian/lights/light.h"
#include "steradian/lights/light_sampler.h"
#include "steradian/material/material.h"
#include "steradian/media/medium.h"
#include "steradian/sensors/meter.h"

namespace sr {

class Accel;

/// The most samples per pixel accepted (from the scene or --spp): sample indices are ints,
/// and the zsobol sampler's index holds log2(spp) bits beside two 16-bit pixel coordinates.
inline constexpr int kMaxSamplesPerPixel = 1 << 26;
/// The largest film side, and the most pixels a film may have (its accumulators take 32
/// bytes a pixel: 8 GiB at the limit, a 16384 x 16384 image).
inline constexpr int kMaxFilmSide = 1 << 16;
inline constexpr int64_t kMaxFilmPixels = int64_t(1) << 28;

struct SamplerSettings {
    std::string type = "zsobol";
    int spp = 16;
    int x_samples = 4, y_samples = 4;
    bool jitter = true;
    uint64_t seed = 0;
};

/// Which strategies the path integrator combines.
enum class LightStrategy { Mis, BsdfOnly, LightOnly };

/// Integrator "radiosity" (a steradian extension; docs/radiosity.md): the meshing, solve and
/// final-gather parameters.
struct RadiosityParams {
    Float patch_size = 0;        ///< longest patch edge of the initial mesh; 0: from max_patches
    int max_patches = 2048;      ///< most patches (unknowns) after adaptive subdivision
    Float subdivide = 0.25f;     ///< split a patch whose direct irradiance varies more than this
    Float residual = 1e-6f;      ///< relative residual the solve stops at
    int direct_samples = 16;     ///< per patch and non-delta light
    int max_depth = 5;           ///< gather bounces through non-diffuse surfaces
    bool interpolate = false;    ///< read the solution interpolated from patch corners
    bool hierarchical = true;    ///< solver: hierarchical radiosity (false: dense matrix, CG)
    Float link_error = 2e-3f;    ///< hierarchical: a link's largest estimated error (fraction)
    /// Secondary gather: a gather ray whose diffuse hit is nearer than this many times the
    /// hit patch's size (the square root of its area) computes the light there (direct light
    /// and one more gather ray) instead of reading the patch's constant (0: never;
    /// docs/radiosity.md says what it gains and what it costs).
    Float gather_distance = 0;
};

/// pbrt-v4's "sppm" (SPPMIntegrator::Create): photons traced per iteration (<= 0: one per
/// pixel of the crop window), the initial search radius (world units), and the seed of the
/// photons' sample sequence (pbrt-v4's default is its --seed, ours 0 plus --seed).
struct SppmParams {
    int photons_per_iteration = -1;
    Float radius = 1;
    int seed = 0;
};

/// "vcm" (a steradian extension; docs/vcm.md): the initial merge radius (world units; <= 0:
/// 0.003 times the scene's bounding-sphere radius, SmallVCM's default), the radius reduction
/// exponent alpha (r_i = r_1 i^((alpha - 1) / 2)), the light paths per iteration (<= 0: one
/// per pixel of the crop window), their seed, and which of the two families of strategies
/// are used.
struct VcmParams {
    Float radius = 0;
    int light_paths = -1;
    Float alpha = 0.75f;
    int seed = 0;
    bool connect = true, merge = true;
};

struct IntegratorSettings {
    std::string type = "path";
    RadiosityParams radiosity;
    SppmParams sppm;
    VcmParams vcm;
    int max_depth = 5;
    LightStrategy strategy = LightStrategy::Mis;
    bool regularize = false;
    /// "bdpt": pbrt-v4's visualizestrategies / visualizeweights.
    bool visualize_strategies = false, visualize_weights = false;
    /// "mlt": pbrt-v4's MLTIntegrator parameters (integrators/mlt/mlt.h).
    struct Mlt {
        int bootstrap_samples = 100000, chains = 1000, mutations_per_pixel = 100;
        Float large_step_probability = 0.3f, sigma = 0.01f;
    } mlt;
    std::string light_sampler = "bvh";  ///< pbrt-v4's names: "bvh" (its default), "power", "uniform"
    /// "volpath" in a scene with media: paths are traced through them (integrators/path/
    /// volpath.cpp); otherwise media are ignored. Also set for the bidirectional integrators
    /// with media (which trace them themselves), so that the path kernel's other users
    /// (meters) do too.
    bool volumetric = false;
};

class Scene {
public:
    Scene();
    ~Scene();
    Scene(Scene&&) noexcept;
    Scene& operator=(Scene&&) noexcept;

    std::vector<ShapeEntry> shapes;
    std::vector<int> top_level_shapes;  ///< shapes in world space (not in prototypes)
    std::vector<Prototype> prototypes;
    std::vector<Instance> instances;
    std::vector<Material> materials;
    std::vector<SpectrumTexture> spectrum_textures;
    std::vector<FloatTexture> float_textures;
    std::vector<Light> lights;
    std::vector<int> infinite_lights;  ///< lights with radiance at infinity (escaping rays)
    LightSampler light_sampler;
    std::vector<Meter> meters;  ///< Meter directives (docs/photometry.md)
    std::vector<Medium> media;  ///< MakeNamedMedium, referred to by index
    int camera_medium = -1;     ///< the medium camera rays start in (-1: vacuum)
    /// The media on the two sides of each light (parallel to `lights`; -1: vacuum), where the
    /// bidirectional integrators' light paths start: the outside medium at a LightSource (both
    /// sides alike), an area light's shape's MediumInterface (emission in direction w leaves
    /// into `outside` where dot(w, n) > 0). Lights at infinity emit in vacuum, as in pbrt-v4.
    struct LightMedia {
        int inside = -1, outside = -1;
    };
    std::vector<LightMedia> light_media;

    std::unique_ptr<Camera> camera;
    /// Some texture filters by the footprint of a pixel (mip-mapped images, checkerboards,
    /// noise): the renderer then computes each camera path vertex's dpdx, dpdy, ... .
    bool texture_footprints = false;
    FilmParams film;
    std::unique_ptr<Filter> filter;
    SamplerSettings sampler;
    IntegratorSettings integrator;

    Bounds3 bounds;  ///< world bounds of all geometry

    /// Builds the acceleration structure and computes `bounds`; call once the shapes and
    /// instances are final. `expected_camera_paths`: the render's pixels x samples per
    /// pixel, or 0 if unknown (see GeometryView).
    void finalize_geometry(uint64_t expected_camera_paths = 0);
    /// Builds the light sampler; call once the lights are final.
    void finalize_lights();
    /// Closest hit along the ray in (0, ray.t_max); fills h (position, normals, uv, ids),
    /// writing every field of it whatever it held before (so one record may be reused).
    bool intersect(const Ray& ray, SurfaceHit& h) const;
    /// True if anything blocks the ray in (0, ray.t_max).
    bool occluded(const Ray& ray) const;
    /// Up to kRayPacket closest hits at once (rays[i] for the bits i of `active`), each
    /// filled as intersect() fills it; returns the bits of the rays that hit. For coherent
    /// rays, such as a pixel's camera rays, far cheaper per ray than intersect().
    static constexpr int kRayPacket = 8;
    unsigned intersect_packet(const Ray* rays, unsigned active, SurfaceHit* hits) const;
    /// occluded() for up to kRayPacket rays at once (the bits of `active`); returns the bits
    /// of the blocked ones.
    unsigned occluded_packet(const Ray* rays, unsigned active) const;
    /// Whether a surface that scatters light blocks the ray: interfaces (shapes without a
    /// material: luminous openings, medium boundaries) let it through. The radiosity pass's
    /// visibility between patches.
    bool occluded_by_surface(const Ray& ray) const;
    unsigned occluded_by_surface_packet(const Ray* rays, unsigned active) const;
    MaterialContext material_context() const {
        return {&spectrum_textures, &float_textures, &materials};
    }

private:
    std::unique_ptr<Accel> m_accel;
};

/// Occlusion by other geometry than a scene's, in an acceleration structure of its own: the
/// radiosity pass traces its form-factor rays against its patches' chords of curved shapes
/// (docs/radiosity.md). The vectors the view refers to must outlive it.
class Occluder {
public:
    explicit Occluder(const GeometryView& geometry);
    ~Occluder();
    Occluder(const Occluder&) = delete;
    Occluder& operator=(const Occluder&) = delete;
    /// As Scene's functions of the same names.
    bool occluded(const Ray& ray) const;
    unsigned occluded_packet(const Ray* rays, unsigned active) const;
    bool occluded_by_surface(const Ray& ray) const;
    unsigned occluded_by_surface_packet(const Ray* rays, unsigned active) const;

private:
    std::unique_ptr<Accel> m_accel;
};

}  // namespace sr
