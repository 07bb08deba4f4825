#include "steradian/film/image_io.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/input_file.h"
#include "steradian/core/output_file.h"
#include "steradian/film/image_formats.h"
#include "steradian/film/oiio_module.h"
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

/// sRGB-decodes the colour channels (the first three) of 8- and 16-bit images.
void decode_srgb(Image& img) {
    int color_channels = std::min(img.channels, 3);
    for (size_t i = 0; i < img.data.size(); ++i)
        if (int(i % img.channels) < color_channels) img.data[i] = sr::srgb_decode(img.data[i]);
}

// ---- OpenImageIO, loaded on first use ----------------------------------------------------

bool g_force_openimageio = false;

/// The module's file name; it is looked for in $STERADIAN_OIIO_MODULE (when set, only
/// there), beside the executable, then where the build put it.
constexpr const char* kModuleName = "steradian_oiio.so";

struct LoadedModule {
    const SrOiioModule* api = nullptr;
    std::string error;  ///< why it could not be loaded
};

LoadedModule load_module() {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("STERADIAN_OIIO_MODULE"); env && *env) {
        candidates.push_back(env);
    } else {
        std::error_code ec;
        std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
        if (!ec) candidates.push_back((exe.parent_path() / kModuleName).string());
#ifdef STERADIAN_OIIO_MODULE_PATH
        if (candidates.empty() || candidates.back() != STERADIAN_OIIO_MODULE_PATH)
            candidates.push_back(STERADIAN_OIIO_MODULE_PATH);
#endif
    }
    LoadedModule m;
    for (const std::string& c : candidates) {
        // Never unloaded: OpenImageIO keeps threads and static state.
        void* handle = ::dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = ::dlerror();
            m.error += fmt::format("{}{}", m.error.empty() ? "" : "; ", e ? e : c);
            continue;
        }
        auto entry = reinterpret_cast<SrOiioModuleEntry>(::dlsym(handle, SR_OIIO_MODULE_ENTRY));
        const SrOiioModule* api = entry ? entry() : nullptr;
        if (!api || api->abi_version != kSrOiioAbiVersion) {
            m.error += fmt::format("{}{}: not a steradian OpenImageIO module of this version",
                                   m.error.empty() ? "" : "; ", c);
            continue;
        }
        m.api = api;
        m.error.clear();
        return m;
    }
    if (candidates.empty()) m.error = "no place to look for it";
    return m;
}

/// The module, loaded on the first call (thread-safe); throws sr::Error naming `path` and
/// saying why the file needed it (`reading`: the file is not a PFM, nor an EXR or PNG of a
/// layout read directly; else: the extension is not .pfm, .exr or .png).
const SrOiioModule& openimageio(const std::string& path, bool reading) {
    static const LoadedModule module = load_module();
    if (!module.api)
        throw Error(fmt::format(
            "{}: {} through OpenImageIO, whose module ({}) could not be loaded: {}", path,
            reading ? "cannot read image: images other than PFM and plain EXR, PNG and JPEG are read"
                    : fmt::format("the image format \"{}\" is written", extension(path)),
            kModuleName, module.error));
    return *module.api;
}

void write_with_openimageio(const std::string& tmp, const std::string& path, const Image& img,
                            bool is_float, bool half, const void* pixels) {
    const SrOiioModule& oiio = openimageio(path, false);
    char err[1024] = "";
    if (!oiio.write(tmp.c_str(), img.width, img.height, img.channels, is_float, half, pixels,
                    err, sizeof err))
        throw Error(fmt::format("{}: {}", path, err));
}

Image read_with_openimageio(const std::string& path, bool srgb_decode) {
    const SrOiioModule& oiio = openimageio(path, true);
    char err[1024] = "";
    SrOiioHeader spec{};
    void* in = oiio.open(path.c_str(), &spec, err, sizeof err);
    if (!in) throw Error(fmt::format("{}: {}", path, err));
    struct Closer {
        const SrOiioModule& m;
        void* h;
        ~Closer() { m.close(h); }
    } closer{oiio, in};
    // The header's size is checked before a buffer of that size is allocated: a 68-byte PNG
    // can declare 16000 x 16000 pixels.
    const double values = double(spec.width) * spec.height * spec.channels;
    if (spec.width <= 0 || spec.height <= 0 || spec.channels <= 0 || values > kMaxImageValues)
        throw Error(fmt::format("{}: the image declares {} x {} pixels of {} channels, more than "
                                "the limit of {} values ({} GiB as floats)",
                                path, spec.width, spec.height, spec.channels, kMaxImageValues,
                                kMaxImageValues * 4 / (1 << 30)));
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.channels;
    img.data.resize(size_t(img.width) * img.height * img.channels);
    if (!oiio.read(in, img.data.data(), err, sizeof err))
        throw Error(fmt::format("{}: {}", path, err));
    if (srgb_decode && spec.integer && !spec.linear) decode_srgb(img);
    return img;
}

// ---- dispatch ----------------------------------------------------------------------------

/// The formats written without OpenImageIO.
bool written_directly(const std::string& ext) {
    return ext == ".pfm" || (!g_force_openimageio && (ext == ".exr" || ext == ".png"));
}

/// 8-bit sRGB codes: round(255 * srgb_encode(v * 2^exposure)), v clamped to [0, 1], NaN -> 0.
std::vector<uint8_t> to_srgb8(const Image& img, Float exposure) {
    Float k = std::exp2(exposure);
    std::vector<uint8_t> px(img.data.size());
    for (size_t i = 0; i < px.size(); ++i) {
        Float v = img.data[i] * k;
        if (!(v > 0)) v = 0;  // also maps NaN to 0
        v = srgb_encode(std::min(v, Float(1)));
        px[i] = uint8_t(std::lround(clamp(v, Float(0), Float(1)) * 255));
    }
    return px;
}

void write_image_file(const std::string& tmp, const std::string& path, const Image& img,
                      const WriteOptions& opts) {
    std::string ext = extension(path);
    if (ext == ".pfm") return write_pfm(tmp, img);
    if (written_directly(ext)) {
        if (ext == ".exr") return image_formats::write_exr(tmp, path, img, opts.half_float);
        std::vector<uint8_t> px = to_srgb8(img, opts.exposure);
        return image_formats::write_png(tmp, path, img.width, img.height, px.data());
    }
    bool is_float = ext == ".exr" || ext == ".hdr";
    if (is_float) return write_with_openimageio(tmp, path, img, true, opts.half_float, img.data.data());
    std::vector<uint8_t> px = to_srgb8(img, opts.exposure);
    write_with_openimageio(tmp, path, img, false, false, px.data());
}

}  // namespace

namespace image_formats {
void force_openimageio(bool on) { g_force_openimageio = on; }
bool openimageio_forced() { return g_force_openimageio; }
}  // namespace image_formats

void check_image_output(const std::string& path, int channels) {
    std::string ext = extension(path);
    if (channels != 3 && ext != ".exr")
        throw Error(fmt::format("{}: expected an RGB image (images of {} channels: .exr only)",
                                path, channels));
    if (!written_directly(ext) && !openimageio(path, false).can_write(path.c_str()))
        throw Error(fmt::format("{}: unknown image format \"{}\" (use .exr, .pfm or .png)", path,
                                ext));
    check_output_path(path, "image output");
}

void write_image(const std::string& path, const Image& img, const WriteOptions& opts) {
    check_image_output(path, img.channels);
    if (!img.channel_names.empty() && extension(path) != ".exr")
        throw Error(fmt::format("{}: named channels can be written to .exr only", path));
    write_file_atomically(path, [&](const std::string& tmp) { write_image_file(tmp, path, img, opts); });
}

Image read_image(const std::string& path, bool srgb_decode) {
    std::error_code ec;  // without it, a file name too long for the system throws
    if (!std::filesystem::exists(path, ec)) throw Error(fmt::format("{}: file not found", path));
    check_regular_file(path, kMaxSceneFileBytes, "image");
    if (extension(path) == ".pfm") return read_pfm(path);
    // EXR, PNG and JPEG by their content (as OpenImageIO, which also reads a PNG named .jpg);
    // layouts the direct readers leave alone and every other format go to OpenImageIO.
    if (!g_force_openimageio) {
        if (image_formats::is_exr_file(path)) {
            if (std::optional<Image> img = image_formats::read_exr(path)) return std::move(*img);
        } else if (image_formats::is_png_file(path)) {
            if (std::optional<Image> img = image_formats::read_png(path)) {
                // OpenImageIO 2.4 named a PNG of gamma 1.0 "linear" (lower case), which the
                // check for "Linear" never matched: every PNG was decoded. Kept so.
                if (srgb_decode) decode_srgb(*img);
                return std::move(*img);
            }
        } else if (image_formats::is_jpeg_file(path)) {
            if (std::optional<Image> img = image_formats::read_jpeg(path)) {
                if (srgb_decode) decode_srgb(*img);
                return std::move(*img);
            }
        }
    }
    return read_with_openimageio(path, srgb_decode);
}

}  // namespace sr
