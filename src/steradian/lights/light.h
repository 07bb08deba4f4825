#pragma once
/// Lights as a std::variant of plain structs (point, spot, distant, uniform and image
/// infinite, diffuse area, goniometric), each satisfying the LightLike concept. Radiometric values are spectral,
/// in the scene's radiance unit (docs/units.md); `scale` already includes pbrt-v4's
/// photometric normalisation and any power/illuminance parameter.
#include <concepts>
#include <memory>
#include <optional>
#include <variant>

#include "steradian/core/transform.h"
#include "steradian/geometry/scene_geometry.h"
#include "steradian/geometry/shapes.h"
#include "steradian/lights/photometric/photometric.h"
#include "steradian/sampling/distribution.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

/// The receiving point of a light sample.
struct LightSampleContext {
    Point3 p;
    Vec3 p_error;
    Normal3 ng;  ///< zero for points not on a surface
};

/// A sampled light direction: L arriving at the reference point along -wi (before
/// visibility), the solid-angle pdf (or the discrete probability 1 for delta lights), and
/// the light point for the shadow ray.
struct LightLiSample {
    SampledSpectrum L;
    Vec3 wi;            ///< unit, from the reference point towards the light
    Float pdf_sa = 0;
    Point3 p_light;     ///< point on the light (or far away for infinite/distant lights)
    Vec3 p_error{0, 0, 0};
    Normal3 n_light{0, 0, 0};
    bool delta = false;
    bool at_infinity = false;
};

struct PointLight {
    Point3 p;
    Spectrum intensity;
    Float scale = 1;
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda) const;
    Float pdf_li(const LightSampleContext&, Vec3) const { return 0; }
    /// Emitted power weighted by V(lambda) (for light selection), in scene units.
    Float phi_y() const;
    bool is_delta() const { return true; }
};

struct SpotLight {
    Transform light_from_world;
    Point3 p;
    Spectrum intensity;
    Float scale = 1;
    Float cos_falloff_start = 1, cos_falloff_end = 1;
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda) const;
    Float pdf_li(const LightSampleContext&, Vec3) const { return 0; }
    Float phi_y() const;
    bool is_delta() const { return true; }
};

struct DistantLight {
    Vec3 w_light;  ///< unit direction from the scene towards the light
    Spectrum radiance;
    Float scale = 1;
    Point3 scene_center;
    Float scene_radius = 1;
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda) const;
    Float pdf_li(const LightSampleContext&, Vec3) const { return 0; }
    Float phi_y() const;
    bool is_delta() const { return true; }
};

/// Constant radiance from every direction.
struct UniformInfiniteLight {
    Spectrum radiance;
    Float scale = 1;
    Point3 scene_center;
    Float scene_radius = 1;
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda) const;
    Float pdf_li(const LightSampleContext&, Vec3) const;
    Float phi_y() const;
    bool is_delta() const { return false; }
    /// Radiance arriving along a ray that escapes in direction dir.
    SampledSpectrum le(Vec3, const SampledWavelengths& lambda) const {
        return radiance.sample(lambda) * scale;
    }
};

/// An environment map in pbrt-v4's layout: a square RGB image in Clarberg's equal-area
/// octahedral parameterisation (sampling/warp.h; every texel covers 4 pi / res^2 sr),
/// looked up at the nearest texel as pbrt-v4's ImageInfiniteLight does, each texel's RGB an
/// RGB illuminant spectrum (sigmoid-polynomial uplift times the sRGB illuminant, D65).
struct EnvironmentMap {
    int res = 0;
    /// res * res texels, rows from the top of the image (v = 0).
    std::vector<RgbUnboundedSpectrum> texels;
    Spectrum illuminant;  ///< the colour space's white (D65), densely sampled
    /// Texel channel averages over [0,1]^2 (pbrt-v4's sampling distribution), and the same
    /// less their mean, clamped at 0: sampled where the map is brighter than average, for
    /// light samples combined by MIS with BSDF samples (pbrt-v4's "compensated" density,
    /// after Karlik et al. 2019), which find the dimmer rest.
    Distribution2D distribution, compensated;
    /// Average over texels of the texels' luminance (Y of linear sRGB) and of Y cos(theta)
    /// over the light's upper hemisphere (z > 0) times 4 pi: the map's illuminance on an
    /// upward patch in its own frame, per unit of scale.
    Float mean_y = 0, upper_illuminance = 0;
    /// The texels' luminance summed over coarse_res x coarse_res equal-area blocks (rows
    /// from the top), for fluxes through a portal (each texel spans 4 pi / res^2 sr).
    int coarse_res = 0;
    std::vector<float> coarse_y;

    /// The radiance of the texel at (u, v), before the light's scale.
    SampledSpectrum le(Point2 uv, const SampledWavelengths& lambda) const;
};

/// An environment map from linear RGB pixels (rows from the top): a square image is taken
/// as pbrt-v4's equal-area map; a 2:1 image as a latitude-longitude map (u = phi / 2 pi,
/// v = theta / pi, theta from +z, phi = atan2(y, x), as pbrt-v4's `imgtool makeequiarea`
/// reads it), resampled to an equal-area map as wide as the image (each texel the average
/// of 4x4 bilinear lookups spread over it). Throws sr::Error for other shapes, non-finite
/// pixels or a size beyond the image limits.
std::shared_ptr<const EnvironmentMap> make_environment_map(const std::vector<float>& rgb,
                                                           int width, int height);

/// Radiance from every direction given by an environment map, rotated by the light's
/// transformation (pbrt-v4's "infinite" light with "filename").
/// pbrt-v4's infinite-light portal ("point3 portal"): a world-space parallelogram p0, p1,
/// p2, p3 (a window) through which alone the light reaches the scene. Its normal n is
/// normalize((p3 - p0) x (p1 - p0)) (pbrt-v4's portal frame z); the light's radiance is zero
/// in directions w with w . n <= 0.
struct InfinitePortal {
    Point3 p0;
    Vec3 e1, e3;  ///< p1 - p0, p3 - p0
    Normal3 n;
    Float area = 0;
    /// Solid-angle density at `from` of a direction w (unit) aimed at a uniformly chosen
    /// point of the portal: dist^2 / (area |cos|) where the ray meets it, else 0.
    Float pdf_through(Point3 from, Vec3 w) const;
};

struct ImageInfiniteLight {
    std::shared_ptr<const EnvironmentMap> map;
    Transform light_from_world;  ///< directions only
    Transform world_from_light;
    Float scale = 1;
    Point3 scene_center;
    Float scene_radius = 1;
    /// With a portal, light samples are drawn half from the map's distribution and half
    /// uniformly over the portal's area (one-sample MIS over the two, the density the
    /// average of both), so a room lit through a small window finds it.
    std::optional<InfinitePortal> portal;
    Float portal_phi_y = 0;  ///< with a portal: the luminous flux through it (phi_y())
    /// allow_incomplete_pdf: sample the compensated density (only when the caller combines
    /// the light sample with a BSDF sample by MIS, which covers the rest), as pbrt-v4.
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda,
                                           bool allow_incomplete_pdf = false) const;
    Float pdf_li(const LightSampleContext& ctx, Vec3 w, bool allow_incomplete_pdf = false) const;
    Float phi_y() const;
    bool is_delta() const { return false; }
    /// Radiance arriving along a ray that escapes from `origin` in world direction dir;
    /// with `pdf`, also pdf_li at origin (one mapping of the direction for both).
    SampledSpectrum le(Point3 origin, Vec3 dir, const SampledWavelengths& lambda,
                       Float* pdf = nullptr, bool allow_incomplete_pdf = false) const;

private:
    Float map_pdf(Vec3 w, bool allow_incomplete_pdf) const;
};

/// A luminous intensity distribution from a photometric file (IES LM-63 or EULUMDAT)
/// placed in the scene. The luminaire frame is PhotometricData's: photometric nadir
/// (gamma = 0) along local -z, C = 0 along local +x, C = 90 deg along local +y; local
/// directions are world directions mapped by `light_from_world` (rotation and any scale;
/// directions are normalised after mapping). intensity() is in candela as tabulated,
/// bilinear between the file's angles.
struct GoniometricProfile {
    std::shared_ptr<const PhotometricData> data;
    Transform light_from_world;
    /// Luminous intensity (cd, as tabulated) emitted in world direction w (any length).
    Float intensity(Vec3 w) const {
        Vec3 l = light_from_world.vector(w);
        return Float(data->intensity_direction(l.x, l.y, l.z));
    }
    Vec3 local(Vec3 w) const { return normalize(light_from_world.vector(w)); }
};

/// pbrt-v4's image goniometric distribution: a square single-channel image (RGB averaged)
/// in Clarberg's equal-area octahedral layout (sampling/warp.h), looked up at the nearest
/// pixel. As in pbrt-v4, the map's frame is the light's local frame with y and z swapped:
/// the image centre is the light's local +y, its corners local -y.
struct GoniometricImage {
    int res = 0;
    std::vector<float> y;  ///< res * res values, rows from the top
    Float lookup(Vec3 w_local) const;
    Float mean() const;
};

/// A goniometric point source: I_e(w, lambda) = scale * I_v(w) * S(lambda), where S is the
/// lamp spectrum normalised to unit photometric value (so one scene unit of intensity is
/// one candela, docs/units.md) and I_v the file's luminous intensity (or the image value).
struct GoniometricLight {
    Point3 p;
    GoniometricProfile profile;  ///< photometric file (profile.data set), or
    std::shared_ptr<const GoniometricImage> image;  ///< pbrt-v4 image
    Spectrum spectrum;  ///< normalised: integral of S(lambda) ybar(lambda) = 1
    Float scale = 1;
    Float flux_lm = 0;  ///< luminous flux of the tabulated distribution (lm, before scale)
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda) const;
    Float pdf_li(const LightSampleContext&, Vec3) const { return 0; }
    Float phi_y() const { return scale * flux_lm; }
    bool is_delta() const { return true; }
};

/// The shape of a photometric luminaire's emitting surface (LM-63 luminous opening).
/// Flat: a plane figure emitting from both faces; Sphere; Convex: a closed convex body (a
/// box with luminous sides, a cylinder, an ellipsoid: a triangle mesh) emitting outwards.
enum class LuminousBody { Flat, Sphere, Convex };

/// The luminous opening of a photometric luminaire as an emitting surface (LM-63 width,
/// length, height), whose radiance in direction w is I(w) / P(w), P(w) the shape's
/// projected area seen from w, so that the opening's intensity in every direction is the
/// file's: a flat opening (rectangle, disk or ellipse, emitting from both faces, unit
/// normal nf) has P = A |nf . w|, a sphere P = pi r^2, a convex body P = sum over its faces
/// of max(0, n_i . w) A_i = 1/2 sum |A_i n_i . w| (a closed surface's outward area vectors
/// sum to zero), computed from the mesh itself so that it is exact for the mesh.
struct GoniometricEmission {
    GoniometricProfile profile;
    Spectrum spectrum;  ///< normalised as in GoniometricLight
    Float scale = 1;
    LuminousBody body = LuminousBody::Flat;
    Float opening_area = 0;      ///< the whole emitting surface's area
    Vec3 flat_normal{0, 0, 1};   ///< Flat: the plane's normal in the luminaire frame
    Float sphere_radius = 0;     ///< Sphere: its radius
    /// Convex: A_i n_i of each distinct face plane, in the luminaire frame.
    std::vector<Vec3> face_areas;
    Float flux_lm = 0;           ///< of the whole distribution (before scale)
    /// P(w) for the unit direction l of the luminaire frame.
    Float projected_area(Vec3 l) const {
        switch (body) {
            case LuminousBody::Flat: return opening_area * std::abs(dot(flat_normal, l));
            case LuminousBody::Sphere: return kPi * sqr(sphere_radius);
            case LuminousBody::Convex: {
                Float s = 0;
                for (const Vec3& f : face_areas) s += std::abs(dot(f, l));
                return s / 2;
            }
        }
        return 0;
    }
    /// Radiance leaving a point of the opening with outward normal n in direction w; a
    /// sphere or a body emits only outwards (rays pass through the opening, which must not
    /// count the far side as well).
    SampledSpectrum radiance(Normal3 n, Vec3 w, const SampledWavelengths& lambda) const {
        if (body != LuminousBody::Flat && dot(n, w) <= 0) return SampledSpectrum(0);
        Vec3 l = profile.local(w);
        Float proj = projected_area(l);
        if (!(proj > 0)) return SampledSpectrum(0);
        Float i = Float(profile.data->intensity_direction(l.x, l.y, l.z));
        if (!(i > 0)) return SampledSpectrum(0);
        return spectrum.sample(lambda) * (scale * i / proj);
    }
};

/// One emitting primitive (a triangle of a mesh, or a whole sphere or disk).
struct DiffuseAreaLight {
    /// Exactly one of triangle, sphere, disk is set. A mesh's triangle is kept by value
    /// (TriangleMesh::triangle()), with its normal and area computed once.
    std::optional<Triangle> triangle;
    const Sphere* sphere = nullptr;
    const Disk* disk = nullptr;
    Spectrum radiance;
    Float scale = 1;
    bool two_sided = false;
    Float area = 0;
    /// Set for the luminous opening of a photometric luminaire: the radiance then follows
    /// its intensity distribution (both faces of a flat opening emit) and `radiance`,
    /// `scale` and `two_sided` are unused.
    std::shared_ptr<const GoniometricEmission> goniometric;
    /// The emitting shape's "alpha" cut-out, if any, with what locates a point on it: the
    /// mesh and triangle (for meshes; sphere and disk are above).
    const AlphaMask* alpha = nullptr;
    const TriangleMesh* mesh = nullptr;
    uint32_t prim = 0;

    /// pbrt-v4's AlphaMasked for emission: whether the point p of this light's surface
    /// emits nothing because of its alpha: always where alpha <= 0, never where alpha >= 1,
    /// and in between where a hash of p, uniform in [0, 1), exceeds alpha. (pbrt-v4 tests
    /// this both where a light sample lands and where a ray hits the light.)
    bool masked(Point3 p) const;

    /// Emitted radiance leaving a point with geometric normal n in direction w.
    SampledSpectrum l(Normal3 n, Vec3 w, const SampledWavelengths& lambda) const {
        if (goniometric) return goniometric->radiance(n, w, lambda);
        if (!two_sided && dot(n, w) < 0) return SampledSpectrum(0);
        return radiance.sample(lambda) * scale;
    }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Point2 u,
                                           const SampledWavelengths& lambda) const;
    /// Solid-angle pdf that sample_li picks the point p_light (normal n_light) seen from ctx.
    Float pdf_li_point(const LightSampleContext& ctx, Point3 p_light, Normal3 n_light) const;
    Float pdf_li(const LightSampleContext&, Vec3) const { return 0; }
    Float phi_y() const;
    bool is_delta() const { return false; }
};

template <typename L>
concept LightLike = requires(const L& l, const LightSampleContext& c, Point2 u,
                             const SampledWavelengths& lambda, Vec3 w) {
    { l.sample_li(c, u, lambda) } -> std::same_as<std::optional<LightLiSample>>;
    { l.pdf_li(c, w) } -> std::same_as<Float>;
    { l.phi_y() } -> std::same_as<Float>;
    { l.is_delta() } -> std::same_as<bool>;
};

using Light = std::variant<PointLight, SpotLight, DistantLight, UniformInfiniteLight,
                           DiffuseAreaLight, GoniometricLight, ImageInfiniteLight>;
static_assert(LightLike<PointLight> && LightLike<SpotLight> && LightLike<DistantLight> &&
              LightLike<UniformInfiniteLight> && LightLike<DiffuseAreaLight> &&
              LightLike<GoniometricLight> && LightLike<ImageInfiniteLight>);

/// A light sample; allow_incomplete_pdf as for ImageInfiniteLight (other lights ignore it).
std::optional<LightLiSample> sample_li(const Light& light, const LightSampleContext& ctx,
                                       Point2 u, const SampledWavelengths& lambda,
                                       bool allow_incomplete_pdf = false);

/// Radiance at infinity along an escaping ray for the lights with radiance at infinity
/// (Scene::infinite_lights), zero for the others; with `pdf`, also the solid-angle density
/// of sample_li(..., allow_incomplete_pdf) at the ray's origin choosing its direction.
SampledSpectrum infinite_le(const Light& light, const Ray& ray, const SampledWavelengths& lambda,
                            Float* pdf = nullptr, bool allow_incomplete_pdf = false);
Float light_phi_y(const Light& light);

/// A ray of emitted light (pbrt-v4's LightLeSample), for paths traced from the lights
/// (integrators/bdpt/): it leaves ray.o in the unit direction ray.d carrying L (radiance of
/// an area or infinite light, intensity of a point-like one, radiance of a distant one), with
/// the densities of its origin (per unit area; 1 for a point) and of its direction (per unit
/// solid angle; 1 for a distant light's one direction). n is the surface normal at ray.o for
/// area lights and zero otherwise; an infinite or distant light's rays start on a disk of
/// the scene's bounding radius facing the scene, outside it.
struct LightLeSample {
    SampledSpectrum L;
    Ray ray;     ///< its origin offset off an area light's surface
    Point3 p;    ///< the point on the light (ray.o before the offset)
    Normal3 n{0, 0, 0};
    Vec3 p_error{0, 0, 0};
    Float pdf_pos = 0, pdf_dir = 0;
};

/// Whether sample_le() can emit from this light: every light but an environment map with a
/// portal. (Callers refuse scenes with lights that cannot.)
bool light_can_emit(const Light& light);
/// A point light's position is a delta (point, spot, goniometric point); a distant light's
/// direction is.
bool light_delta_position(const Light& light);
bool light_delta_direction(const Light& light);
/// Samples an emitted ray: u_pos chooses the origin, u_dir the direction. Area lights choose
/// the point uniformly by area and the direction cosine-weighted (a two-sided emitter, or a
/// flat luminous opening, chooses its face by u_dir.x first); point and goniometric lights
/// uniformly over the sphere; spot lights uniformly in their outer cone; infinite lights by
/// their direction density (sample_li's, complete), then a point on the disk.
std::optional<LightLeSample> sample_le(const Light& light, Point2 u_pos, Point2 u_dir,
                                       const SampledWavelengths& lambda);
/// What a light emits from its point p (an area light's face normal n) in the unit
/// direction w: an area light's radiance, a point, spot or goniometric light's intensity;
/// zero for distant and infinite lights (whose rays start nowhere a path can meet).
SampledSpectrum light_emitted(const Light& light, Point3 p, Normal3 n, Vec3 w,
                              const SampledWavelengths& lambda);
/// light_emitted at each of n sets of wavelengths (out[i] for lambdas[i]), the direction's
/// factor (a photometric table's lookup) evaluated once: what a light emits is that factor
/// times its spectrum.
void light_emitted(const Light& light, Point3 p, Normal3 n, Vec3 w,
                   const SampledWavelengths* lambdas, int count, SampledSpectrum* out);
/// The densities sample_le() has of emitting from p (normal n; ignored for lights without a
/// surface) in the unit direction w (for infinite and distant lights, w is the direction
/// light travels; pdf_pos is the disk's).
void pdf_le(const Light& light, Point3 p, Normal3 n, Vec3 w, Float& pdf_pos, Float& pdf_dir);

}  // namespace sr
