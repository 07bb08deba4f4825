#pragma once
/// Typed parameter lists of scene entities ("float fov" [45]), with use tracking: every
/// lookup marks the parameter used, and check_unused() reports whatever nobody read.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/math.h"

namespace sr {

/// The parameter types of the pbrt-v4 format. Readers normalise synonyms
/// ("point" -> Point3, "vector" -> Vector3, "normal" -> Normal3, "color" -> Rgb).
// GCC's -Wshadow flags scoped enumerators that share a name with a type alias (Float,
// Point3, ...), although they cannot clash; silence that false positive here only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#endif
enum class ParamType {
    Integer, Float, Point2, Vector2, Point3, Vector3, Normal3, Bool, String, Texture,
    Spectrum, Rgb, Blackbody
};
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
std::string_view to_string(ParamType t);

struct Param {
    ParamType type = ParamType::Float;
    std::string name;
    SourceLoc loc;                     ///< where the parameter's declaration string starts
    std::vector<double> numbers;       ///< Integer, Float, Point*, Vector*, Normal3, Rgb,
                                       ///< Blackbody, and Spectrum given as (lambda, value) pairs
    std::vector<std::string> strings;  ///< String, Texture, and Spectrum given by name/file
    std::vector<uint8_t> bools;        ///< Bool
    mutable bool used = false;
};

/// Parameters of one entity. Getters return the default when the parameter is absent and
/// throw sr::Error (at the parameter's location) when it is present with the wrong type or
/// the wrong number of values.
class ParamSet {
public:
    /// Adds a parameter; throws if a parameter of that name is already present.
    void add(Param p);
    bool empty() const { return m_params.empty(); }
    const std::vector<Param>& params() const { return m_params; }

    /// The parameter named `name` of any type (marked used), or nullptr.
    const Param* find(std::string_view name) const;
    /// The parameter named `name` if its type is `type` (marked used); nullptr if absent;
    /// throws if present with another type.
    const Param* find(std::string_view name, ParamType type) const;

    Float get_float(std::string_view name, Float def) const;
    int get_int(std::string_view name, int def) const;
    bool get_bool(std::string_view name, bool def) const;
    std::string get_string(std::string_view name, const std::string& def) const;
    std::optional<Float> find_float(std::string_view name) const;
    std::optional<int> find_int(std::string_view name) const;
    std::optional<std::string> find_string(std::string_view name) const;
    std::optional<Point3> find_point3(std::string_view name) const;
    std::optional<Vec3> find_vector3(std::string_view name) const;
    std::optional<Normal3> find_normal3(std::string_view name) const;

    std::vector<Float> get_floats(std::string_view name) const;
    std::vector<int> get_ints(std::string_view name) const;
    std::vector<Point3> get_point3s(std::string_view name) const;
    std::vector<Vec3> get_normals(std::string_view name) const;
    std::vector<Point2> get_point2s(std::string_view name) const;
    std::vector<std::string> get_strings(std::string_view name) const;

    /// A spectrum-valued parameter (Spectrum, Rgb or Blackbody) or nullptr; throws if the
    /// name is present with a non-spectral type.
    const Param* find_spectrum(std::string_view name) const;
    /// The texture name of a "texture" parameter, if present. Empty (and the parameter not
    /// marked used) when it is absent or has another type, so callers may look for a texture
    /// first and then for a value of the same name; throws unless it has exactly one name.
    std::optional<std::string> find_texture(std::string_view name) const;

    /// Throws sr::Error at the first parameter nobody looked up:
    /// "unused parameter \"float foo\" for <what>".
    void check_unused(std::string_view what) const;

private:
    std::vector<Param> m_params;
};

}  // namespace sr
