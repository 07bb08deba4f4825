#pragma once
/// Reading input files whole, safely: only regular files are read (not devices, FIFOs or
/// directories: `Include "/dev/zero"` read until memory ran out), and only up to a size
/// limit that the error names, checked before anything is allocated.
#include <cstdint>
#include <string>
#include <string_view>

namespace sr {

/// Size limits of the inputs read whole: scene text and meshes (a 10-million-triangle
/// binary PLY is about 200 MB), and the small text formats (IES, EULUMDAT, spectra).
inline constexpr uint64_t kMaxSceneFileBytes = uint64_t(4) << 30;
inline constexpr uint64_t kMaxSmallFileBytes = uint64_t(64) << 20;

/// Why `path` cannot be read as a regular file of at most `limit` bytes (strerror(ENOENT),
/// "not a regular file ...", "N bytes, more than the limit of ..."), or "" if it can; its size
/// goes to *size.
std::string regular_file_problem(const std::string& path, uint64_t limit,
                                 uint64_t* size = nullptr);

/// Throws sr::Error("cannot read <what> \"<path>\": <why>") unless `path` is a regular file
/// of at most `limit` bytes; returns its size.
uint64_t check_regular_file(const std::string& path, uint64_t limit, std::string_view what);

/// The whole contents of `path`, after check_regular_file(). Throws sr::Error as it does,
/// or on a read error.
std::string read_regular_file(const std::string& path, uint64_t limit, std::string_view what);

}  // namespace sr
