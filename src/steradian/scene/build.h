#pragma once
/// Turns a format-neutral SceneDesc into a runtime Scene: validates every entity's type and
/// parameters (unknown or unused parameters are errors at their file:line:col), resolves
/// named materials and textures, converts spectra (with pbrt-v4's photometric
/// normalisation of lights), reads meshes, and builds the acceleration structure. The
/// builder's stages are in scene/build/, one file for each kind of thing built.
#include <string>
#include <vector>

#include "steradian/scene/desc.h"
#include "steradian/scene/scene.h"

namespace sr {

struct BuildOptions {
    /// Overrides the Sampler's pixel samples when > 0 (so the camera sampler can size
    /// itself; the render options pass the same value).
    int spp_override = 0;
};

Scene build_scene(const SceneDesc& desc, const BuildOptions& options = {});

/// The spectrum of a parameter (rgb, spectrum pairs or name/file, blackbody) interpreted as
/// `kind` (albedo, unbounded or illuminant). Throws sr::Error at the parameter.
Spectrum spectrum_from_param(const Param& p, SpectrumKind kind, const std::string& base_dir);

/// Meters from the scene description, in the order of their directives. Every parameter
/// problem is an sr::Error at its file:line:col.
std::vector<Meter> build_meters(const std::vector<MeterDesc>& descs);

}  // namespace sr
