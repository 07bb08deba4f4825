#pragma once
/// Image files: EXR (linear float, through OpenEXR), PFM (our own writer/reader), PNG (8-bit
/// sRGB-encoded, through libpng), JPEG reading (libjpeg), and every other format OpenImageIO
/// knows (TIFF, HDR, ...) through OpenImageIO, which is loaded as a module on first use
/// (oiio_module.h).
#include <cstdint>
#include <string>
#include <vector>

#include "steradian/core/math.h"

namespace sr {

/// A float image, row-major from the top row, `channels` interleaved values per pixel.
struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> data;
    float at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
    float& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
};

struct WriteOptions {
    Float exposure = 0;      ///< stops, applied to 8-bit outputs only (scale 2^exposure)
    bool half_float = false; ///< EXR: 16-bit half instead of 32-bit float
};

/// Writes an RGB image (3 channels, linear) by the file extension: .exr (linear float),
/// .pfm (linear float), .png/.jpg/.tif... (8-bit sRGB, clamped); a single-channel image
/// (channel "Y") to .exr only. Throws sr::Error.
/// The file is written atomically (a temporary file in the same directory, checked, synced
/// and renamed into place), so a reader never sees a partial image.
void write_image(const std::string& path, const Image& rgb, const WriteOptions& opts = {});

/// Throws sr::Error unless an image of `channels` channels can be written to `path`: the
/// extension names a format we write (and .exr for one channel), and the directory exists
/// or can be created and is writable. For checking outputs before rendering.
void check_image_output(const std::string& path, int channels = 3);

/// The most values (pixels x channels) an image read may have: 2^28 (1 GiB as floats; e.g.
/// 8192 x 8192 x 4, or a 16384 x 8192 environment map of 2 channels). Larger images are
/// refused from their header, before any allocation.
inline constexpr int64_t kMaxImageValues = int64_t(1) << 28;

/// Reads an image. 8-bit (and 16-bit integer) images are sRGB-decoded to linear when
/// srgb_decode is true; float images are returned as stored. Throws sr::Error.
Image read_image(const std::string& path, bool srgb_decode = true);

}  // namespace sr
