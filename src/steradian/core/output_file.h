#pragma once
/// Output files that are never half-written: every output is written to a temporary file in
/// the destination's directory, flushed to the disk and checked, then renamed into place, so
/// a reader (or a second render writing the same path) sees the old file or the new one,
/// never a mix, and a full disk is an error instead of a truncated file (the temporary files a
/// killed writer left are removed by the next write of the same path). Also the check of
/// an output path before hours of rendering are spent on it.
#include <functional>
#include <string>

namespace sr {

/// Writes `path` atomically: `write` is called with a temporary path in the same directory
/// (with the same extension, so writers that choose a format by extension still do), must
/// create that file and throw on failure; the file is then fsync'ed and renamed over `path`.
/// The directory is created if missing. On any failure the temporary file is removed and an
/// sr::Error naming `path` is thrown.
void write_file_atomically(const std::string& path,
                           const std::function<void(const std::string& tmp_path)>& write);

/// Writes `text` to `path` atomically (write_file_atomically), checking every write.
void write_text_file(const std::string& path, const std::string& text);

/// Throws sr::Error (naming `path` and `what` it is for) unless `path` can be written: its
/// directory exists or can be created, is writable, and `path` is not a directory. Creates
/// the directory if missing. Meant for checking outputs before a long computation.
void check_output_path(const std::string& path, const std::string& what);

}  // namespace sr
