#pragma once
/// Reading input files whole, safely: only regular files are read (not devices, FIFOs or
/// directories: `Include "/dev/zero"` read until memory ran out), and only up to a size
/// limit that the error names, checked before anything is allocated.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sr {

/// Size limits of the inputs read whole: scene text and meshes (a 10-million-triangle
/// binary PLY is about 200 MB), and the small text formats (IES, EULUMDAT, spectra).
inline constexpr uint64_t kMaxSceneFileBytes = uint64_t(4) << 30;
inline constexpr uint64_t kMaxSmallFileBytes = uint64_t(64) << 20;

/// Why `path` cannot be read as a regular file of at most `limit` bytes (strerror(ENOENT),
/// "not a regular file ...", "N bytes, more than the limit of ..."), or "" if it can; its size
/// goes to *size. A path that can be read is recorded as an input (input_files_read())
/// unless `record` is false (files that are not part of a scene: checkpoints).
std::string regular_file_problem(const std::string& path, uint64_t limit,
                                 uint64_t* size = nullptr, bool record = true);

/// Throws sr::Error("cannot read <what> \"<path>\": <why>") unless `path` is a regular file
/// of at most `limit` bytes; returns its size.
uint64_t check_regular_file(const std::string& path, uint64_t limit, std::string_view what,
                            bool record = true);

/// The whole contents of `path`, after check_regular_file(). Throws sr::Error as it does,
/// or on a read error.
std::string read_regular_file(const std::string& path, uint64_t limit, std::string_view what,
                              bool record = true);

/// Every file accepted by regular_file_problem() (so by check_regular_file() and
/// read_regular_file(): every scene, mesh, luminaire, spectrum and image file a scene
/// loads) since the start of the process, sorted and without repeats. A checkpoint hashes
/// their contents, so that it is never resumed on a scene that has changed.
std::vector<std::string> input_files_read();

}  // namespace sr
