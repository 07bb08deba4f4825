#pragma once
/// The pbrt reader's Parser class, whose members are defined in parser.cpp (directives,
/// Include/Import), params.cpp (parameter lists, Option) and graphics_state.cpp (transformations
/// and the attribute stack) (internal to src/steradian/scene/pbrt/).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/transform.h"
#include "steradian/scene/desc.h"
#include "steradian/scene/pbrt/graphics_state.h"
#include "steradian/scene/pbrt/stream.h"
#include "steradian/scene/pbrt/tokenizer.h"

namespace sr::pbrt_detail {

/// Builds a ParamSet from an entity's own parameters (already free of duplicates) and the
/// Attribute defaults that apply to it; `skip` names a parameter to leave out.
ParamSet make_params(std::vector<Param>&& own, const std::vector<Param>* attrs,
                     std::string_view skip = {});

class Parser {
  public:
    explicit Parser(std::string base_dir) : m_base_dir(std::move(base_dir)) {
        m_scene.base_dir = m_base_dir;
    }

    void parse(Tokenizer& tz, const std::string& dir, int depth);
    SceneDesc finish(const SourceLoc& eof);

  private:
    enum class ValueKind { Number, Integer, Bool, String, Spectrum };

    /// As sr::pbrt_detail::make_params, counting the values of Attribute defaults copied
    /// into entities: every shape, light or material gets its own copy, so a large default
    /// over many entities would grow memory with the square of the file's size. Throws
    /// sr::Error at a default's declaration beyond kMaxAttributeValuesCopied.
    ParamSet make_params(std::vector<Param>&& own, const std::vector<Param>* attrs,
                         std::string_view skip = {});
    static constexpr uint64_t kMaxAttributeValuesCopied = uint64_t(1) << 26;
    uint64_t m_attribute_values_copied = 0;

    std::vector<Param> parse_params(Stream& s);
    Param parse_param(Stream& s, const Token& decl);
    std::pair<std::string, std::vector<Param>> parse_entity(Stream& s, std::string_view what);

    void require_world(std::string_view what, const SourceLoc& loc) const {
        if (!m_in_world) throw_error(loc, "{} is not allowed before WorldBegin", what);
    }
    void require_options(std::string_view what, const SourceLoc& loc) const {
        if (m_in_world)
            throw_error(loc, "{} is not allowed after WorldBegin (it belongs to the options block)",
                        what);
    }
    /// Applies `t` to the CTM: ctm = ctm * t (only the start-time transform is kept).
    void concat(const Transform& t) {
        if (m_gs.start_active) m_gs.ctm = m_gs.ctm * t;
    }
    void set_ctm(const Transform& t) {
        if (m_gs.start_active) m_gs.ctm = t;
    }
    Transform read_matrix(Stream& s, std::string_view what, const SourceLoc& loc);

    void attribute_begin(const char* what, const SourceLoc& loc);
    void attribute_end(std::string_view what, const SourceLoc& loc);
    void object_begin(Stream& s, const SourceLoc& loc);
    void object_end(const SourceLoc& loc);
    void attribute(Stream& s);
    void texture(Stream& s, const SourceLoc& loc);
    void make_named_material(Stream& s, const SourceLoc& loc);
    void shape(Stream& s, const SourceLoc& loc);
    void make_named_medium(Stream& s, const SourceLoc& loc);
    void option(Stream& s);
    void active_transform(Stream& s, const SourceLoc& loc);
    std::string resolve(const std::string& name, const std::string& dir, std::string_view what,
                        const SourceLoc& loc) const;
    void include(Stream& s, const SourceLoc& loc, bool import);

    SceneDesc m_scene;
    GraphicsState m_gs;
    std::vector<Pushed> m_stack;
    size_t m_stack_floor = 0;  ///< entries below this belong to the file that Imports
    std::unordered_map<std::string, Transform> m_coordsys;
    bool m_in_world = false;
    SourceLoc m_world_loc;
    InstanceDefinition* m_object = nullptr;  ///< the open ObjectBegin, if any
    std::unordered_map<std::string, SourceLoc> m_float_textures, m_spectrum_textures;
    std::vector<Param> m_options;
    bool m_warned_transform_begin = false;
    std::string m_base_dir;
};

}  // namespace sr::pbrt_detail
