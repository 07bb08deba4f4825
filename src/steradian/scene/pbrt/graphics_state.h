#pragma once
/// The pbrt reader's graphics state and its saved copies on the attribute stack (internal to
/// src/steradian/scene/pbrt/).
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/transform.h"
#include "steradian/scene/desc.h"

namespace sr::pbrt_detail {

struct GraphicsState {
    Transform ctm;
    bool start_active = true;  ///< ActiveTransform includes StartTime (we keep only that one)
    bool reverse_orientation = false;
    MaterialRef material;
    int area_light = -1;
    MediumNames media;  ///< MediumInterface
    std::vector<Param> shape_attrs, light_attrs, material_attrs, medium_attrs, texture_attrs;
};

struct Pushed {
    const char* directive;  ///< "AttributeBegin", "TransformBegin" or "ObjectBegin"
    SourceLoc loc;
    GraphicsState state;
};

}  // namespace sr::pbrt_detail
