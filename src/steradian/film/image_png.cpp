// PNG files through libpng (see image_formats.h).
//
// libpng reports errors by longjmp to the setjmp in the function that drives it. The two
// functions that call setjmp (png_write_rows, png_read_rows) hold only trivially
// destructible locals, so the jump skips no destructor; buffers live in the callers.
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/film/image_formats.h"

namespace sr::image_formats {

namespace {

/// libpng's error state: the first message, and errno of a failed write or read.
struct PngStatus {
    char message[256];
    int errno_value;
    std::FILE* file;
};

extern "C" void on_png_error(png_structp png, png_const_charp msg) {
    auto* st = static_cast<PngStatus*>(png_get_error_ptr(png));
    if (st->message[0] == 0) std::snprintf(st->message, sizeof st->message, "%s", msg);
    png_longjmp(png, 1);
}

extern "C" void on_png_warning(png_structp, png_const_charp) {}

extern "C" void on_png_write(png_structp png, png_bytep data, size_t n) {
    auto* st = static_cast<PngStatus*>(png_get_io_ptr(png));
    errno = 0;
    if (std::fwrite(data, 1, n, st->file) != n) {
        st->errno_value = errno;
        png_error(png, "write failed");
    }
}

extern "C" void on_png_flush(png_structp) {}

extern "C" void on_png_read(png_structp png, png_bytep data, size_t n) {
    auto* st = static_cast<PngStatus*>(png_get_io_ptr(png));
    errno = 0;
    if (std::fread(data, 1, n, st->file) != n) {
        st->errno_value = std::ferror(st->file) ? errno : 0;
        png_error(png, std::ferror(st->file) ? "read failed" : "file truncated");
    }
}

/// The message of a failed libpng call.
std::string describe(const PngStatus& st) {
    std::string msg = st.message[0] ? st.message : "unknown libpng error";
    if (st.errno_value != 0) msg += fmt::format(" ({})", std::strerror(st.errno_value));
    return msg;
}

/// Writes the PNG; false (with st->message) on failure.
bool png_write_rows(PngStatus* st, int width, int height, const unsigned char* rgb) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, st, on_png_error,
                                              on_png_warning);
    if (!png) {
        std::snprintf(st->message, sizeof st->message, "out of memory");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        std::snprintf(st->message, sizeof st->message, "out of memory");
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, st, on_png_write, on_png_flush);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    // The chunks OpenImageIO wrote for "sRGB" outputs: sRGB (absolute colorimetric intent)
    // with the matching gAMA and cHRM for readers that do not know sRGB.
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_ABSOLUTE);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y)
        png_write_row(png, const_cast<png_bytep>(rgb + size_t(y) * size_t(width) * 3));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

/// What png_read_rows learns and needs: the header, and the caller's buffers.
struct PngRead {
    PngStatus status;
    png_uint_32 width, height;
    int channels, bit_depth;  // after the transformations: 8 or 16 bits
    bool declined;            // alpha or transparency: left to OpenImageIO
    bool too_large;
    std::vector<unsigned char>* pixels;
    std::vector<png_bytep>* rows;
};

/// Sizes the caller's buffers; false if the memory is not there.
bool allocate(PngRead* r, size_t row_bytes) noexcept {
    try {
        r->pixels->resize(row_bytes * r->height);
        r->rows->resize(r->height);
        for (png_uint_32 y = 0; y < r->height; ++y)
            (*r->rows)[y] = r->pixels->data() + row_bytes * y;
        return true;
    } catch (const std::bad_alloc&) {
        return false;
    }
}

/// Reads the PNG into r->pixels (rows of 8-bit or native-endian 16-bit codes); false with
/// r->status.message on failure, true with r->declined or r->too_large set when the file
/// is left alone.
bool png_read_rows(PngRead* r) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r->status, on_png_error,
                                             on_png_warning);
    if (!png) {
        std::snprintf(r->status.message, sizeof r->status.message, "out of memory");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        std::snprintf(r->status.message, sizeof r->status.message, "out of memory");
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_set_read_fn(png, &r->status, on_png_read);
    png_read_info(png, info);
    const int color_type = png_get_color_type(png, info);
    const int depth = png_get_bit_depth(png, info);
    r->width = png_get_image_width(png, info);
    r->height = png_get_image_height(png, info);
    if ((color_type & PNG_COLOR_MASK_ALPHA) != 0 || png_get_valid(png, info, PNG_INFO_tRNS)) {
        r->declined = true;
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    r->channels = color_type == PNG_COLOR_TYPE_GRAY ? 1 : 3;
    if (double(r->width) * double(r->height) * r->channels > double(kMaxImageValues)) {
        r->too_large = true;
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color_type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (depth == 16) png_set_swap(png);  // little-endian machines: native 16-bit values
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    r->bit_depth = png_get_bit_depth(png, info);
    if (png_get_channels(png, info) != png_byte(r->channels) ||
        (r->bit_depth != 8 && r->bit_depth != 16)) {
        r->declined = true;
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    if (!allocate(r, png_get_rowbytes(png, info))) {
        std::snprintf(r->status.message, sizeof r->status.message, "out of memory");
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_read_image(png, r->rows->data());
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

}  // namespace

bool is_png_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    unsigned char magic[8] = {};
    if (!f.read(reinterpret_cast<char*>(magic), 8)) return false;
    return png_sig_cmp(magic, 0, 8) == 0;
}

void write_png(const std::string& file, const std::string& path, int width, int height,
               const unsigned char* rgb) {
    errno = 0;
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (!f)
        throw Error(fmt::format("{}: cannot open for writing: {}", path, std::strerror(errno)));
    PngStatus st{};
    st.file = f;
    bool ok = png_write_rows(&st, width, height, rgb);
    errno = 0;
    if (ok && std::fflush(f) != 0) {
        ok = false;
        st.errno_value = errno;
        std::snprintf(st.message, sizeof st.message, "write failed");
    }
    errno = 0;
    if (std::fclose(f) != 0 && ok) {
        ok = false;
        st.errno_value = errno;
        std::snprintf(st.message, sizeof st.message, "write failed");
    }
    if (!ok) throw Error(fmt::format("{}: cannot write PNG: {}", path, describe(st)));
}

std::optional<Image> read_png(const std::string& path) {
    errno = 0;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw Error(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
    std::vector<unsigned char> pixels;
    std::vector<png_bytep> rows;
    PngRead r{};
    r.status.file = f;
    r.pixels = &pixels;
    r.rows = &rows;
    const bool ok = png_read_rows(&r);
    std::fclose(f);
    if (!ok) throw Error(fmt::format("{}: cannot read image: {}", path, describe(r.status)));
    if (r.too_large)
        throw Error(fmt::format("{}: the image declares {} x {} pixels of {} channels, more than "
                                "the limit of {} values ({} GiB as floats)",
                                path, r.width, r.height, r.channels, kMaxImageValues,
                                kMaxImageValues * 4 / (1 << 30)));
    if (r.declined) return std::nullopt;
    Image img;
    img.width = int(r.width);
    img.height = int(r.height);
    img.channels = r.channels;
    const size_t n = size_t(r.width) * r.height * size_t(r.channels);
    img.data.resize(n);
    // Codes to [0, 1] by multiplying with the reciprocal of the largest code (as OpenImageIO
    // converts, so that the floats are the same bits).
    if (r.bit_depth == 8) {
        const float k = 1.0f / 255.0f;
        for (size_t i = 0; i < n; ++i) img.data[i] = float(pixels[i]) * k;
    } else {
        const float k = 1.0f / 65535.0f;
        for (size_t i = 0; i < n; ++i) {
            uint16_t v;
            std::memcpy(&v, pixels.data() + 2 * i, 2);
            img.data[i] = float(v) * k;
        }
    }
    return img;
}

}  // namespace sr::image_formats
