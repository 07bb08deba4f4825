#pragma once
/// Image files: EXR (linear float, through OpenEXR), PFM (our own writer/reader), PNG (8-bit
/// sRGB-encoded, through libpng), JPEG reading (libjpeg), and every other format OpenImageIO
/// knows (TIFF, HDR, ...) through OpenImageIO, which is loaded as a module on first use
/// (oiio_module.h).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "steradian/core/math.h"

namespace sr {

/// A float image, row-major from the top row, `channels` interleaved values per pixel.
struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> data;
    /// Channel names (EXR only): empty for R, G, B (3 channels) or Y (1 channel).
    std::vector<std::string> channel_names;
    /// String attributes of the file's header (EXR only), name and value.
    std::vector<std::pair<std::string, std::string>> attributes;
    float at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
    float& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
};

struct WriteOptions {
    Float exposure = 0;      ///< stops, applied to 8-bit outputs only (scale 2^exposure)
    bool half_float = false; ///< EXR: 16-bit half instead of 32-bit float
};

/// Writes an RGB image (3 channels, linear) by the file extension: .exr (linear float),
/// .pfm (linear float), .png/.jpg/.tif... (8-bit sRGB, clamped); a single-channel image
/// (channel "Y"), or one with channel_names (any number of channels), to .exr only. Throws
/// sr::Error.
/// The file is written atomically (a temporary file in the same directory, checked, synced
/// and renamed into place), so a reader never sees a partial image.
void write_image(const std::string& path, const Image& rgb, const WriteOptions& opts = {});

/// Throws sr::Error unless an image of `channels` channels can be written to `path`: the
/// extension names a format we write (and .exr for other than 3 channels), and the
/// directory exists or can be created and is writable. For checking outputs before rendering.
void check_image_output(const std::string& path, int channels = 3);

/// The most values (pixels x channels) an image read may have: 2^28 (1 GiB as floats; e.g.
/// 8192 x 8192 x 4, or a 16384 x 8192 environment map of 2 channels). Larger images are
/// refused from their header, before any allocation.
inline constexpr int64_t kMaxImageValues = int64_t(1) << 28;

/// Reads every channel of an EXR file (half or float, not subsampled) with its name, in the
/// file's order (alphabetical). Throws sr::Error.
Image read_exr_channels(const std::string& path);

/// Reads an image. 8-bit (and 16-bit integer) images are sRGB-decoded to linear when
/// srgb_decode is true; float images are returned as stored. Throws sr::Error.
Image read_image(const std::string& path, bool srgb_decode = true);

}  // namespace sr
