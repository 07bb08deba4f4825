#pragma once
/// The interface of the OpenImageIO module (oiio_module.cpp), a shared object that
/// image_io.cpp loads with dlopen the first time an image format it does not handle itself
/// is read or written. OpenImageIO depends on some 260 shared libraries whose loading costs
/// a process start 0.3 CPU-s and 130 MB; a process that reads and writes only EXR, PNG and
/// PFM (and reads JPEG) never loads it.
///
/// Plain C types only: the module and the program agree on nothing but this table.
/// Functions that can fail return 0 and put a message (without the file name) in `err`.
#include <cstddef>

extern "C" {

/// A header as the module reports it.
struct SrOiioHeader {
    int width, height, channels;
    int integer;  ///< stored as 8- or 16-bit integers (candidates for sRGB decoding)
    int linear;   ///< the file declares a linear encoding (OIIO's oiio:ColorSpace "Linear")
};

struct SrOiioModule {
    int abi_version;  ///< kSrOiioAbiVersion
    /// 1 if OpenImageIO has a writer for the path's extension (opens no file).
    int (*can_write)(const char* path);
    /// Writes `path` (its extension chooses the format): `pixels` is width x height x
    /// channels interleaved values, floats (stored as half when `half` is set) if `is_float`,
    /// else 8-bit codes.
    int (*write)(const char* path, int width, int height, int channels, int is_float, int half,
                 const void* pixels, char* err, size_t err_size);
    /// Opens `path` and fills `header`; the handle is closed by close().
    void* (*open)(const char* path, SrOiioHeader* header, char* err, size_t err_size);
    /// Reads the whole first subimage as floats (width x height x channels).
    int (*read)(void* handle, float* dst, char* err, size_t err_size);
    void (*close)(void* handle);
};

/// The module's one exported symbol.
typedef const SrOiioModule* (*SrOiioModuleEntry)(void);
#define SR_OIIO_MODULE_ENTRY "steradian_oiio_module_v1"

}  // extern "C"

inline constexpr int kSrOiioAbiVersion = 1;
