#pragma once
/// The internal Builder behind build_scene(), its members defined across this folder (not public).
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "steradian/scene/build.h"

namespace sr::build_detail {

inline std::string resolve_path(const std::string& base_dir, const std::string& file) {
    std::filesystem::path p(file);
    if (p.is_absolute() || base_dir.empty()) return file;
    return (std::filesystem::path(base_dir) / p).string();
}

[[noreturn]] inline void unsupported(const EntityDesc& e, std::string_view what) {
    throw_unsupported(e.loc, "{} \"{}\" is not supported yet (see docs/pbrt-support.md)", what,
                      e.type);
}

/// The largest coordinate accepted for a camera, light or meter position: Embree 3 requires
/// ray origins and directions below 1.844e18 in magnitude (FLT_LARGE, kernels/common/ray.h)
/// and aborts otherwise; 1e17 leaves room for the differences rays are made of.
inline constexpr double kMaxCoordinate = 1e17;

/// Throws at `loc` unless `t` and its inverse are finite (a singular or overflowing
/// transformation: a zero scale, a matrix of huge values, a NaN from arithmetic).
inline void check_transform(const Transform& t, const SourceLoc& loc, std::string_view what) {
    if (!t.is_finite())
        throw_error(loc, "{}: the transformation (or its inverse) is not finite", what);
}

/// Throws at `loc` unless every coordinate of `p` is finite and within kMaxCoordinate.
inline void check_position(Point3 p, const SourceLoc& loc, std::string_view what) {
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(double(p[i])) <= kMaxCoordinate))
            throw_error(loc, "{} is at ({}, {}, {}): coordinates must be finite and within "
                        "+-{:g}", what, p.x, p.y, p.z, kMaxCoordinate);
}

class Builder {
  public:
    Builder(const SceneDesc& d, const BuildOptions& o) : m_d(d), m_o(o) {}

    Scene build();  // build.cpp

    /// Runs f(). An UnsupportedError it throws (an unsupported feature or an unknown
    /// parameter) is recorded instead and false returned: the caller leaves the entity out or
    /// puts a stand-in in its place, and the build goes on, so that one run lists them all.
    template <typename F>
    bool recorded(F&& f) {
        try {
            f();
            return true;
        } catch (const UnsupportedError& e) {
            m_unsupported.push_back(e);
            if (m_unsupported.size() >= m_o.max_unsupported) fail(nullptr);
            return false;
        }
    }
    /// Throws the recorded errors, if any, and `last` (an error that stopped the build).
    void fail_if_recorded() {
        if (!m_unsupported.empty()) fail(nullptr);
    }
    [[noreturn]] void fail(const Error* last);  // build.cpp
    bool failed() const { return m_failed; }    ///< fail() has thrown

  private:
    // ---- options block (options.cpp) ---------------------------------------------------
    void build_options_block();
    void build_film(const EntityDesc& f);
    void build_camera(const CameraDesc& c);
    void build_filter(const EntityDesc& f);
    void build_sampler(const EntityDesc& s);
    void build_integrator(const EntityDesc& e);

    // ---- textures (textures.cpp) -------------------------------------------------------
    std::shared_ptr<const TextureImage> load_image(const TextureDesc& t, const ParamSet& ps);
    void read_filter(const TextureDesc& t, const ParamSet& ps, TextureFilter& f, Float& max_aniso);
    /// The environment map of an image "infinite" light (errors located at `loc`).
    std::shared_ptr<const EnvironmentMap> environment_map(const std::string& path,
                                                          const SourceLoc& loc,
                                                          const std::string& what);
    UvMapping read_mapping(const TextureDesc& t, const ParamSet& ps);
    Vec3 mix_direction(const TextureDesc& t, const ParamSet& ps);
    void build_textures();
    void build_float_texture(const TextureDesc& t);
    void build_spectrum_texture(const TextureDesc& t);
    static void check_checkerboard_dimension(const TextureDesc& t, const ParamSet& ps);
    std::shared_ptr<const FloatTexture> float_tex_arg(const ParamSet& ps, std::string_view name,
                                                      Float def);
    std::shared_ptr<const SpectrumTexture> spectrum_tex_arg(const ParamSet& ps,
                                                            std::string_view name, Float def);
    int spectrum_texture_param(const ParamSet& ps, std::string_view name, Float def,
                               SpectrumKind kind = SpectrumKind::Albedo);
    int float_texture_param(const ParamSet& ps, std::string_view name, Float def);

    // ---- material parameters (material_params.cpp) -------------------------------------
    Roughness roughness_params(const ParamSet& ps);
    std::pair<Spectrum, bool> eta_param(const ParamSet& ps, Float def);
    Spectrum unbounded_param(const ParamSet& ps, std::string_view name, const char* def_named);
    int albedo_param(const ParamSet& ps, std::string_view name, Float def);
    std::optional<Float> constant_albedo_sum(int a, int b) const;
    Float energy_scale(int kd, int ks, const SourceLoc& loc, const std::string& what);
    HairMaterial hair_params(const ParamSet& ps, const std::string& what);
    int bounded_float_param(const ParamSet& ps, std::string_view name, Float def, bool positive);
    LafortuneMaterial lafortune_params(const ParamSet& ps, const SourceLoc& loc,
                                       const std::string& what);
    Roughness prefixed_roughness_params(const ParamSet& ps, const std::string& prefix);
    std::pair<Spectrum, bool> named_eta_param(const ParamSet& ps, const std::string& name,
                                              Float def);
    LayerParams layer_params(const ParamSet& ps, const std::string& what);
    SubsurfaceMaterial subsurface_params(const ParamSet& ps, const std::string& what);

    // ---- materials (materials.cpp) -----------------------------------------------------
    void resolve_mixes();
    Material make_material(const MaterialDesc& m);
    Material make_material_model(const MaterialDesc& m);
    /// The tables of a "measured" material's "filename", read once per file.
    std::shared_ptr<const MeasuredBrdf> measured_brdf(const ParamSet& ps, const MaterialDesc& m,
                                                      const std::string& what);
    void build_materials();
    int resolve_material(const MaterialRef& r);

    // ---- shapes and instances (shapes.cpp) ---------------------------------------------
    static std::shared_ptr<std::vector<Point3>> padded_positions(std::vector<Point3> p);
    TriangleMesh make_mesh(const ShapeDesc& s, std::vector<Point3> p, std::vector<Normal3> n,
                           std::vector<Point2> uv, std::vector<int> idx);
    /// make_mesh with Embree's index type: the arrays become the mesh's without a copy.
    TriangleMesh make_mesh_u32(const ShapeDesc& s, std::vector<Point3> p,
                               std::vector<Normal3> n, std::vector<Point2> uv,
                               std::vector<uint32_t> idx);
    std::optional<ShapeGeometry> make_geometry(const ShapeDesc& s);
    void check_alpha(const ShapeDesc& s);
    std::shared_ptr<const AlphaMask> alpha_mask(const ShapeDesc& s);
    ShapeGeometry make_bilinear(const ShapeDesc& s);
    ShapeGeometry make_curves(const ShapeDesc& s);
    void add_shape(const ShapeDesc& s, Prototype* proto);
    void build_instances();

    // ---- photometric luminaires (goniometric lights with an IES/LDT file; luminaires.cpp)
    // Read before the geometry is finalised: a luminous opening is a shape (with the
    // "interface" material, so it emits but does not block light).
    struct Luminaire {
        std::optional<GoniometricLight> point;          ///< the point form, or
        std::shared_ptr<GoniometricEmission> emission;  ///< the luminous opening
        int shape = -1;                                 ///< its shape
    };

    static std::string lower_extension(const std::string& f);
    void build_luminaires();
    Luminaire make_luminaire(const LightDesc& l);
    /// The triangle mesh of an LM-63 luminous shape in the luminaire frame (half-extents hx
    /// along the photometric horizontal, hy along C90, hz along z, centred on the
    /// photometric centre): a flat figure's triangles face flat_normal, a body's outwards,
    /// with the body's area vectors per face plane (GoniometricEmission::face_areas).
    struct LuminousMesh {
        std::vector<Point3> p;
        std::vector<int> idx;
        bool flat = false;
        Vec3 flat_normal{0, 0, 1};
        std::vector<Vec3> face_areas;
    };
    static constexpr int kEllipseSegments = 48, kEllipsoidRings = 24;
    static LuminousMesh luminous_mesh(LuminousShape shape, Float hx, Float hy, Float hz);
    Luminaire make_image_goniometric(const LightDesc& l, const std::string& path,
                                     const std::string& file);
    void add_luminaire(Scene& s, const Luminaire& lum);

    /// One DiffuseAreaLight per emitting primitive of shape `shape_index` (each triangle of
    /// a mesh, or the whole sphere or disk), made by make(primitive area), as pbrt-v4 does.
    template <typename Make>
    static void add_emitting_primitives(Scene& s, int shape_index, const Make& make) {
        ShapeEntry& e = s.shapes[shape_index];
        e.light_offset = int(s.lights.size());
        s.light_media.resize(s.lights.size());  // (lights before this shape's)
        if (auto* mesh = std::get_if<TriangleMesh>(&e.geometry)) {
            for (size_t i = 0; i < mesh->num_triangles(); ++i) {
                DiffuseAreaLight dl = make(mesh->triangle_area(i));
                dl.triangle = mesh->triangle(i);
                if (e.alpha) {
                    dl.alpha = e.alpha.get();
                    dl.mesh = mesh;
                    dl.prim = uint32_t(i);
                }
                s.lights.push_back(dl);
            }
        } else if (auto* sp = std::get_if<Sphere>(&e.geometry)) {
            DiffuseAreaLight dl = make(sp->area());
            dl.sphere = sp;
            dl.alpha = e.alpha.get();
            s.lights.push_back(dl);
        } else {
            auto* d = std::get_if<Disk>(&e.geometry);
            DiffuseAreaLight dl = make(d->area());
            dl.disk = d;
            dl.alpha = e.alpha.get();
            s.lights.push_back(dl);
        }
        s.light_media.resize(s.lights.size(), Scene::LightMedia{e.medium_inside, e.medium_outside});
    }

    // ---- media (media.cpp) -------------------------------------------------------------
    void build_media();
    /// Renders the scene with the volumetric kernel (integrators/path/volpath.cpp) because it
    /// has `what` ("participating media", "subsurface materials"), with "path" too (warning
    /// that pbrt-v4's `pbrt_path`); records as unsupported a strategy other than MIS.
    void use_volumetric_kernel(const std::string& what, const std::string& pbrt_path);

  public:
    /// The index of the named medium ("" = vacuum: -1); an error at `loc` if undefined.
    int medium_index(const std::string& name, const SourceLoc& loc) const;
    // ---- lights (lights.cpp) -----------------------------------------------------------
    void build_lights(Scene& s);

  private:
    Spectrum illum_param(const ParamSet& ps, std::string_view name);
    static Float photometric_or_fail(const Spectrum& s, const SourceLoc& loc);
    void add_light(Scene& s, const LightDesc& l, Point3 center, Float radius);
    void read_portal(ImageInfiniteLight& il, const Param& p, const ParamSet& ps,
                     const std::string& what);
    void add_area_light(Scene& s, int shape_index, const AreaLightDesc& a);

    const SceneDesc& m_d;
    BuildOptions m_o;
    std::vector<UnsupportedError> m_unsupported;  ///< recorded by recorded()
    bool m_failed = false;
    std::vector<bool> m_failed_light;  ///< by index into SceneDesc::lights: left out
    Scene m_s;
    Float m_exposure_iso = 1;
    std::map<std::string, std::shared_ptr<const TextureImage>> m_images;
    std::map<std::string, int> m_float_tex, m_spec_tex;
    std::map<std::string, std::shared_ptr<const MeasuredBrdf>> m_measured;  ///< by path
    std::vector<int> m_material_index;
    int m_default_material = -1;
    std::vector<std::pair<int, int>> m_pending_area;  ///< (shape, area light desc)
    std::map<size_t, Luminaire> m_luminaires;         ///< by index into SceneDesc::lights
    std::map<std::string, int> m_medium_index;        ///< MakeNamedMedium name -> Scene::media
    bool m_volpath = false;                           ///< Integrator "volpath" (the default)
};

}  // namespace sr::build_detail
