#pragma once
/// Reader for the PLY polygon file format (Greg Turk, 1994): ascii 1.0,
/// binary_little_endian 1.0 and binary_big_endian 1.0.
///
/// Read: element "vertex" with x, y, z (required), nx, ny, nz (optional, all three), and a
/// texture coordinate pair u/v, s/t, texture_u/texture_v or texture_s/texture_t (optional);
/// element "face" with a list property "vertex_indices" (or "vertex_index") of 3 or 4
/// vertices (quads are split along the 0-2 diagonal) and an optional integer scalar
/// "face_indices". Every scalar type and its sized alias (char/int8 ... double/float64) is
/// accepted for every property; all other elements and properties are skipped.
#include <cstdint>
#include <string>
#include <string_view>

#include "steradian/scene/mesh_io/mesh.h"

namespace sr {

/// Reads the PLY file at `path`. Throws sr::Error whose message starts with "path: " (and
/// "path:line: " for header errors and ASCII data errors) on unreadable, malformed or
/// unsupported input; the result has passed validate().
/// gzip data ("name.ply.gz") are decompressed in memory; from `concurrent_gunzip_bytes` of
/// decompressed size on (by the gzip trailer), on a thread of their own while the front is
/// parsed.
inline constexpr std::uint64_t kPlyConcurrentGunzipBytes = std::uint64_t(16) << 20;
TriangleMeshData read_ply(const std::string& path,
                          std::uint64_t concurrent_gunzip_bytes = kPlyConcurrentGunzipBytes);

/// Parses a whole PLY file already in memory; `name` prefixes error messages.
TriangleMeshData parse_ply(std::string_view bytes, const std::string& name);

}  // namespace sr
