#include "steradian/film/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "steradian/core/error.h"
#include "steradian/core/input_file.h"
#include "steradian/core/output_file.h"
#include "steradian/spectrum/color.h"

namespace sr {

namespace {

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext;
}

void write_pfm(const std::string& path, const Image& img) {
    std::ofstream f(path, std::ios::binary);
    if (!f) throw Error(fmt::format("{}: cannot open for writing", path));
    f << "PF\n" << img.width << " " << img.height << "\n-1\n";
    // PFM rows go bottom to top, little-endian floats.
    std::vector<float> row(size_t(img.width) * 3);
    for (int y = img.height - 1; y >= 0; --y) {
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) row[size_t(x) * 3 + c] = img.at(x, y, c);
        f.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * 4));
    }
    f.flush();
    f.close();
    if (!f) throw Error(fmt::format("{}: write failed (disk full?)", path));
}

Image read_pfm(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error(fmt::format("{}: cannot open", path));
    std::string magic;
    int w = 0, h = 0;
    double scale = 0;
    f >> magic >> w >> h >> scale;
    f.get();
    if ((magic != "PF" && magic != "Pf") || w <= 0 || h <= 0 || scale == 0)
        throw Error(fmt::format("{}: not a valid PFM file", path));
    int ch = magic == "PF" ? 3 : 1;
    if (double(w) * h * ch > kMaxImageValues)
        throw Error(fmt::format("{}: the PFM declares {} x {} pixels, more than the limit of {} "
                                "values", path, w, h, kMaxImageValues));
    bool big_endian = scale > 0;
    Image img;
    img.width = w;
    img.height = h;
    img.channels = ch;
    img.data.resize(size_t(w) * h * ch);
    std::vector<float> row(size_t(w) * ch);
    for (int y = h - 1; y >= 0; --y) {
        if (!f.read(reinterpret_cast<char*>(row.data()), std::streamsize(row.size() * 4)))
            throw Error(fmt::format("{}: truncated PFM data", path));
        for (size_t i = 0; i < row.size(); ++i) {
            float v = row[i];
            if (big_endian) {
                uint32_t u;
                std::memcpy(&u, &v, 4);
                u = __builtin_bswap32(u);
                std::memcpy(&v, &u, 4);
            }
            img.data[size_t(y) * w * ch + i] = v;
        }
    }
    return img;
}

void write_image_file(const std::string& tmp, const std::string& path, const Image& img,
                      const WriteOptions& opts) {
    std::string ext = extension(path);
    if (ext == ".pfm") return write_pfm(tmp, img);
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error(fmt::format("{}: unsupported image format '{}'", path, ext));
    bool is_float = ext == ".exr" || ext == ".hdr";
    OIIO::TypeDesc type = is_float ? (opts.half_float ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT)
                                   : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(img.width, img.height, img.channels, type);
    if (img.channels == 1) spec.channelnames = {"Y"};
    spec.attribute("oiio:ColorSpace", is_float ? "Linear" : "sRGB");
    if (!out->open(tmp, spec)) throw Error(fmt::format("{}: {}", path, out->geterror()));
    bool ok;
    if (is_float) {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, img.data.data());
    } else {
        Float k = std::exp2(opts.exposure);
        std::vector<uint8_t> px(img.data.size());
        for (size_t i = 0; i < px.size(); ++i) {
            Float v = img.data[i] * k;
            if (!(v > 0)) v = 0;  // also maps NaN to 0
            v = srgb_encode(std::min(v, Float(1)));
            px[i] = uint8_t(std::lround(clamp(v, Float(0), Float(1)) * 255));
        }
        ok = out->write_image(OIIO::TypeDesc::UINT8, px.data());
    }
    if (!ok || !out->close()) throw Error(fmt::format("{}: {}", path, out->geterror()));
}

}  // namespace

void check_image_output(const std::string& path, int channels) {
    std::string ext = extension(path);
    if (channels != 3 && !(channels == 1 && ext == ".exr"))
        throw Error(fmt::format("{}: expected an RGB image{}", path,
                                channels == 1 ? " (single-channel images: .exr only)" : ""));
    if (ext != ".pfm") {
        // create() only looks the format up by the extension; it opens no file.
        auto out = OIIO::ImageOutput::create(path);
        if (!out)
            throw Error(fmt::format("{}: unknown image format \"{}\" (use .exr, .pfm or .png)",
                                    path, ext));
    }
    check_output_path(path, "image output");
}

void write_image(const std::string& path, const Image& img, const WriteOptions& opts) {
    check_image_output(path, img.channels);
    write_file_atomically(path, [&](const std::string& tmp) { write_image_file(tmp, path, img, opts); });
}

Image read_image(const std::string& path, bool srgb_decode) {
    std::error_code ec;  // without it, a file name too long for the system throws
    if (!std::filesystem::exists(path, ec)) throw Error(fmt::format("{}: file not found", path));
    check_regular_file(path, kMaxSceneFileBytes, "image");
    if (extension(path) == ".pfm") return read_pfm(path);
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error(fmt::format("{}: cannot read image: {}", path, OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    // The header's size is checked before a buffer of that size is allocated: a 68-byte PNG
    // can declare 16000 x 16000 pixels.
    const double values = double(spec.width) * spec.height * spec.nchannels;
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || values > kMaxImageValues)
        throw Error(fmt::format("{}: the image declares {} x {} pixels of {} channels, more than "
                                "the limit of {} values ({} GiB as floats)",
                                path, spec.width, spec.height, spec.nchannels, kMaxImageValues,
                                kMaxImageValues * 4 / (1 << 30)));
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.data.resize(size_t(img.width) * img.height * img.channels);
    if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.data.data()))
        throw Error(fmt::format("{}: {}", path, in->geterror()));
    bool integer = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                   spec.format.basetype == OIIO::TypeDesc::UINT16;
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    if (srgb_decode && integer && cs != "Linear") {
        int color_channels = std::min(img.channels, 3);
        for (size_t i = 0; i < img.data.size(); ++i)
            if (int(i % img.channels) < color_channels) img.data[i] = sr::srgb_decode(img.data[i]);
    }
    in->close();
    return img;
}

}  // namespace sr
