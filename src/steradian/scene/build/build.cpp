/// build_scene(): the Builder's stages in order, then lights and meters once geometry is final.
#include <algorithm>
#include <tuple>

#include "steradian/core/error_list.h"
#include "steradian/scene/build/builder.h"

namespace sr {

namespace build_detail {

Scene Builder::build() {
    build_options_block();
    build_media();
    build_textures();
    build_materials();
    for (const ShapeDesc& s : m_d.shapes) recorded([&] { add_shape(s, nullptr); });
    build_instances();
    build_luminaires();
    // Lights are created by build_lights() once the geometry's bounds are known.
    return std::move(m_s);
}

void Builder::fail(const Error* last) {
    m_failed = true;
    const size_t n = m_unsupported.size() + (last ? 1 : 0);
    if (n == 1) {  // as it was thrown (an UnsupportedError stays one)
        if (last) throw *last;
        throw m_unsupported.front();
    }
    const bool truncated = m_unsupported.size() >= m_o.max_unsupported;
    std::string msg = fmt::format(
        "the scene cannot be rendered: {} unsupported features or unknown parameters{} (see "
        "docs/pbrt-support.md){}:",
        m_unsupported.size(),
        truncated ? fmt::format(" (stopped at the first {})", m_o.max_unsupported) : "",
        last ? ", then an error" : "");
    // In the order of the files (the build's order is by kind: textures, materials, shapes...).
    std::stable_sort(m_unsupported.begin(), m_unsupported.end(),
                     [](const Error& a, const Error& b) {
                         return std::tie(a.loc().file, a.loc().line, a.loc().column) <
                                std::tie(b.loc().file, b.loc().line, b.loc().column);
                     });
    std::vector<ErrorEntry> entries;
    for (const UnsupportedError& e : m_unsupported) {
        msg += fmt::format("\n{}", e.what());
        entries.push_back({e.loc(), e.message(), true});
    }
    if (last) {
        msg += fmt::format("\n{}", last->what());
        std::vector<ErrorEntry> more = error_entries(*last);
        entries.insert(entries.end(), more.begin(), more.end());
    }
    throw ErrorList(msg, std::move(entries), truncated);
}

}  // namespace build_detail

using build_detail::Builder;

Scene build_scene(const SceneDesc& desc, const BuildOptions& options) {
    Builder b(desc, options);
    try {
        Scene s = b.build();
        // The camera paths a render traces choose Embree's build quality for very large
        // meshes (accel.cpp); unknown for a radiosity solve and for meters, whose rays are
        // not the film's.
        uint64_t paths = 0;
        if (desc.meters.empty() && s.integrator.type != "radiosity")
            paths = uint64_t(s.film.x1 - s.film.x0) * uint64_t(s.film.y1 - s.film.y0) *
                    uint64_t(s.sampler.spp);
        s.finalize_geometry(paths);
        b.build_lights(s);
        b.fail_if_recorded();
        s.finalize_lights();
        s.meters = build_meters(desc.meters);
        for (size_t i = 0; i < s.meters.size(); ++i)
            s.meters[i].medium = b.medium_index(desc.meters[i].medium, desc.meters[i].loc);
        return s;
    } catch (const Error& e) {
        if (b.failed()) throw;  // already the whole list
        b.fail(&e);             // the error that stopped the build, after those recorded
    }
}

}  // namespace sr
