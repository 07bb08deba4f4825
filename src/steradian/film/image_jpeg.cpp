// JPEG files read through libjpeg (see image_formats.h). Writing stays with OpenImageIO.
//
// libjpeg reports errors through error_exit, which must not return: it longjmps to the
// setjmp in jpeg_read_rows, whose locals are all trivially destructible.
#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <fstream>
#include <new>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/film/image_formats.h"

namespace sr::image_formats {

namespace {

struct JpegError {
    jpeg_error_mgr mgr;  // first: libjpeg's pointer to it is a pointer to this
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

extern "C" void on_jpeg_error(j_common_ptr cinfo) {
    auto* e = reinterpret_cast<JpegError*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, e->message);
    std::longjmp(e->jump, 1);
}

extern "C" void on_jpeg_message(j_common_ptr, int) {}  // warnings: not printed

struct JpegRead {
    JpegError error;
    std::FILE* file;
    JDIMENSION width, height;
    int channels;
    bool declined;   // CMYK / YCCK: left to OpenImageIO, which converts them to RGB
    bool too_large;
    std::vector<unsigned char>* pixels;
};

bool allocate(JpegRead* r) noexcept {
    try {
        r->pixels->resize(size_t(r->width) * r->height * size_t(r->channels));
        return true;
    } catch (const std::bad_alloc&) {
        return false;
    }
}

/// Decodes the file into r->pixels (8-bit RGB or grey); false with r->error.message on
/// failure, true with r->declined or r->too_large set when the file is left alone.
bool jpeg_read_rows(JpegRead* r) {
    jpeg_decompress_struct cinfo;
    std::memset(&cinfo, 0, sizeof cinfo);
    cinfo.err = jpeg_std_error(&r->error.mgr);
    r->error.mgr.error_exit = on_jpeg_error;
    r->error.mgr.emit_message = on_jpeg_message;
    if (setjmp(r->error.jump)) {
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_stdio_src(&cinfo, r->file);
    jpeg_read_header(&cinfo, TRUE);
    if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
        r->declined = true;
        jpeg_destroy_decompress(&cinfo);
        return true;
    }
    // libjpeg's default decoding (integer IDCT, smooth chroma upsampling), as OpenImageIO's.
    cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    r->width = cinfo.image_width;
    r->height = cinfo.image_height;
    r->channels = cinfo.num_components == 1 ? 1 : 3;
    if (double(r->width) * double(r->height) * r->channels > double(kMaxImageValues)) {
        r->too_large = true;
        jpeg_destroy_decompress(&cinfo);
        return true;
    }
    jpeg_start_decompress(&cinfo);
    if (int(cinfo.output_components) != r->channels || cinfo.output_width != r->width ||
        cinfo.output_height != r->height) {
        r->declined = true;
        jpeg_destroy_decompress(&cinfo);
        return true;
    }
    if (!allocate(r)) {
        std::snprintf(r->error.message, sizeof r->error.message, "out of memory");
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    const size_t stride = size_t(r->width) * size_t(r->channels);
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW row = r->pixels->data() + stride * cinfo.output_scanline;
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    return true;
}

}  // namespace

bool is_jpeg_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    unsigned char magic[3] = {};
    if (!f.read(reinterpret_cast<char*>(magic), 3)) return false;
    return magic[0] == 0xff && magic[1] == 0xd8 && magic[2] == 0xff;
}

std::optional<Image> read_jpeg(const std::string& path) {
    errno = 0;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw Error(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
    std::vector<unsigned char> pixels;
    JpegRead r{};
    r.file = f;
    r.pixels = &pixels;
    const bool ok = jpeg_read_rows(&r);
    std::fclose(f);
    if (!ok) throw Error(fmt::format("{}: cannot read image: {}", path, r.error.message));
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
    img.data.resize(pixels.size());
    const float k = 1.0f / 255.0f;  // as OpenImageIO converts (see read_png)
    for (size_t i = 0; i < pixels.size(); ++i) img.data[i] = float(pixels[i]) * k;
    return img;
}

}  // namespace sr::image_formats
