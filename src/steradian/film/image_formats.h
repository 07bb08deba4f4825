#pragma once
/// The image formats that image_io.cpp reads and writes without OpenImageIO (internal to
/// film/): OpenEXR through the OpenEXR library, PNG through libpng, and JPEG reading through
/// libjpeg. Each reader returns
/// std::nullopt for a valid file whose layout it leaves to OpenImageIO (see the readers),
/// so that such files keep the values OpenImageIO has always given them. All throw
/// sr::Error naming the file.
#include <optional>
#include <string>

#include "steradian/film/image_io.h"

namespace sr::image_formats {

/// True if the file starts with the format's magic number (false if it cannot be read).
bool is_exr_file(const std::string& path);
bool is_png_file(const std::string& path);
bool is_jpeg_file(const std::string& path);

/// Writes `img` (3 channels R, G, B or 1 channel Y) to `file` as ZIP-compressed scan lines of
/// 32-bit floats, or 16-bit halves when `half_float` is set (rounded to nearest even).
/// `path` is the name used in error messages.
void write_exr(const std::string& file, const std::string& path, const Image& img,
               bool half_float);

/// Reads a single-part, flat EXR whose channels are R, G, B, optionally A, or just Y, all
/// half or float at full resolution; the data window's pixels, channels in the order R, G,
/// B, A. Other layouts (layers, other channel names, subsampled or integer channels, deep
/// data): std::nullopt.
std::optional<Image> read_exr(const std::string& path);

/// Writes 8-bit codes (width x height x 3, RGB) as a PNG marked sRGB (sRGB, gAMA and cHRM
/// chunks). `path` is the name used in error messages.
void write_png(const std::string& file, const std::string& path, int width, int height,
               const unsigned char* rgb);

/// Reads an 8- or 16-bit grey or RGB PNG, a grey of 1, 2 or 4 bits (expanded to 8 bits), or
/// a palette PNG without transparency, as floats (code / 255 or code / 65535), not yet
/// sRGB-decoded. PNGs with an alpha channel or transparency: std::nullopt.
std::optional<Image> read_png(const std::string& path);

/// Reads a grey or YCbCr/RGB JPEG (libjpeg's default decoding, as OpenImageIO's) as
/// code / 255, not yet sRGB-decoded. CMYK and YCCK files: std::nullopt.
std::optional<Image> read_jpeg(const std::string& path);

/// For tests: when set, every format but PFM goes through OpenImageIO as before.
void force_openimageio(bool on);
bool openimageio_forced();

}  // namespace sr::image_formats
