#pragma once
/// Turns a format-neutral SceneDesc into a runtime Scene: validates every entity's type and
/// parameters (unknown or unused parameters are errors at their file:line:col), resolves
/// named materials and textures, converts spectra (with pbrt-v4's photometric
/// normalisation of lights), reads meshes, and builds the acceleration structure. The
/// builder's stages are in scene/build/, one file for each kind of thing built.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/scene/desc.h"
#include "steradian/scene/scene.h"

namespace sr {

/// By default, at most this many unsupported features and unknown parameters are recorded
/// before the build stops; they are all reported together.
inline constexpr size_t kMaxReportedUnsupported = 20;

struct BuildOptions {
    /// Overrides the Sampler's pixel samples when > 0 (so the camera sampler can size
    /// itself; the render options pass the same value).
    int spp_override = 0;
    /// The most unsupported features and unknown parameters recorded before the build stops
    /// (`steradian check` raises it to list a scene's every one).
    size_t max_unsupported = kMaxReportedUnsupported;
};

/// Throws sr::Error at the first error that is not an unsupported feature; unsupported
/// features and unknown parameters are recorded and thrown together, as an sr::ErrorList
/// (core/error_list.h) when there are several.
Scene build_scene(const SceneDesc& desc, const BuildOptions& options = {});

/// The spectrum of a parameter (rgb, spectrum pairs or name/file, blackbody) interpreted as
/// `kind` (albedo, unbounded or illuminant). Throws sr::Error at the parameter.
Spectrum spectrum_from_param(const Param& p, SpectrumKind kind, const std::string& base_dir);

/// The samples of a spectrum file's text: one "wavelength value" pair per line (nm; `#`
/// starts a comment; blank lines are skipped, any other text is an error), wavelengths
/// increasing, at least two pairs; returned interleaved
/// (w0, v0, w1, v1, ...). Throws sr::Error at `loc` (the parameter naming the file) with
/// "path:line: " before the message.
std::vector<Float> parse_spectrum_file(std::string_view text, const std::string& path,
                                       const SourceLoc& loc);

/// Meters from the scene description, in the order of their directives. Every parameter
/// problem is an sr::Error at its file:line:col.
std::vector<Meter> build_meters(const std::vector<MeterDesc>& descs);

}  // namespace sr
