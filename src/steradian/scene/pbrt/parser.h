#pragma once
/// Reader for the pbrt-v4 scene format: syntax and graphics state (transformations,
/// attributes, named materials/textures/coordinate systems, object instancing, Include and
/// Import) into the format-neutral SceneDesc. Entity type names ("sphere", "diffuse", ...)
/// and their parameters are recorded, not validated: that is the builder's job.
/// docs/pbrt-support.md lists what is supported, warned about, or rejected.
#include <string>

#include "steradian/scene/desc.h"

namespace sr {

/// Parses the scene file at `path` and everything it Includes/Imports. Relative file
/// names resolve against the directory of `path` (pbrt-v4's search directory), which is
/// also returned as SceneDesc::base_dir. Throws sr::Error, located at file:line:col, at the
/// first error; warnings go to sr::warning().
SceneDesc parse_pbrt_file(const std::string& path);

/// Parses scene text; `filename` names it in source locations and `base_dir` plays the role
/// of the scene file's directory (for Include/Import and SceneDesc::base_dir).
SceneDesc parse_pbrt_string(const std::string& text, const std::string& filename = "<string>",
                            const std::string& base_dir = ".");

}  // namespace sr
