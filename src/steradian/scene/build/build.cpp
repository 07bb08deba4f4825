/// build_scene(): the Builder's stages in order, then lights and meters once geometry is final.
#include "steradian/scene/build/builder.h"

namespace sr {

namespace build_detail {

Scene Builder::build() {
    build_options_block();
    build_textures();
    build_materials();
    for (const ShapeDesc& s : m_d.shapes) add_shape(s, nullptr);
    build_instances();
    build_luminaires();
    // Lights are created by build_lights() once the geometry's bounds are known.
    return std::move(m_s);
}

}  // namespace build_detail

using build_detail::Builder;

Scene build_scene(const SceneDesc& desc, const BuildOptions& options) {
    Builder b(desc, options);
    Scene s = b.build();
    s.finalize_geometry();
    b.build_lights(s);
    s.finalize_lights();
    s.meters = build_meters(desc.meters);
    return s;
}

}  // namespace sr
