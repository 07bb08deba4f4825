// OpenEXR files through the OpenEXR library (see image_formats.h).
#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/film/image_formats.h"

namespace sr::image_formats {

bool is_exr_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    unsigned char magic[4] = {};
    if (!f.read(reinterpret_cast<char*>(magic), 4)) return false;
    return magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
}

namespace {

/// An output stream on a stdio file that remembers its first failure. The library writes
/// the line offset table from OutputFile's destructor, which swallows exceptions; the flag
/// makes that write checked too.
class CheckedOStream : public Imf::OStream {
public:
    explicit CheckedOStream(const std::string& file) : Imf::OStream(file.c_str()) {
        errno = 0;
        m_f = std::fopen(file.c_str(), "wb");
        if (!m_f) fail();
    }
    ~CheckedOStream() override {
        if (m_f) std::fclose(m_f);
    }
    void write(const char c[], int n) override {
        errno = 0;
        if (m_error.empty() && std::fwrite(c, 1, size_t(n), m_f) != size_t(n)) fail();
        if (!m_error.empty()) throw std::runtime_error(m_error);
    }
    uint64_t tellp() override {
        long pos = m_f ? std::ftell(m_f) : -1;
        if (pos < 0) fail();
        if (!m_error.empty()) throw std::runtime_error(m_error);
        return uint64_t(pos);
    }
    void seekp(uint64_t pos) override {
        if (m_error.empty() && std::fseek(m_f, long(pos), SEEK_SET) != 0) fail();
        if (!m_error.empty()) throw std::runtime_error(m_error);
    }
    const std::string& error() const { return m_error; }
    /// Flushes and closes the file; the first error of the whole write, or "".
    std::string finish() {
        if (m_f) {
            errno = 0;
            if (std::fflush(m_f) != 0 && m_error.empty()) fail();
            if (std::fclose(m_f) != 0 && m_error.empty()) fail();
            m_f = nullptr;
        }
        return m_error;
    }

private:
    void fail() {
        if (m_error.empty())
            m_error = errno != 0 ? std::strerror(errno) : std::string("write failed (disk full?)");
    }
    std::FILE* m_f = nullptr;
    std::string m_error;
};

/// Reads the channels `names` of an open file's data window as floats, interleaved in that
/// order (half channels are converted by the library), after checking the size against the
/// limit on image values.
Image read_exr_pixels(Imf::InputFile& in, std::vector<std::string> names, const std::string& path) {
    const Imath::Box2i dw = in.header().dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, ht = int64_t(dw.max.y) - dw.min.y + 1;
    const int count = int(names.size());
    if (w <= 0 || ht <= 0 || double(w) * double(ht) * count > double(kMaxImageValues))
        throw Error(fmt::format("{}: the image declares {} x {} pixels of {} channels, more "
                                "than the limit of {} values ({} GiB as floats)",
                                path, w, ht, count, kMaxImageValues,
                                kMaxImageValues * 4 / (1 << 30)));
    Image img;
    img.width = int(w);
    img.height = int(ht);
    img.channels = count;
    img.data.resize(size_t(w) * size_t(ht) * size_t(count));
    const size_t xs = sizeof(float) * size_t(count), ys = xs * size_t(w);
    // Slice::Make places the data window's first pixel at the start of our buffer.
    char* base = reinterpret_cast<char*>(img.data.data());
    Imf::FrameBuffer fb;
    for (int c = 0; c < count; ++c)
        fb.insert(names[size_t(c)],
                  Imf::Slice::Make(Imf::FLOAT, base + sizeof(float) * size_t(c), dw, xs, ys));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    img.channel_names = std::move(names);
    return img;
}

}  // namespace

void write_exr(const std::string& file, const std::string& path, const Image& img,
               bool half_float) {
    const bool named = !img.channel_names.empty();
    if (named ? img.channel_names.size() != size_t(img.channels)
              : img.channels != 3 && img.channels != 1)
        throw Error(fmt::format("{}: cannot write {} channels to EXR", path, img.channels));
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const auto& [name, value] : img.attributes)
            header.insert(name, Imf::StringAttribute(value));
        const Imf::PixelType type = half_float ? Imf::HALF : Imf::FLOAT;
        static const char* const rgb[] = {"R", "G", "B"};
        const char* const* names = img.channels == 3 ? rgb : nullptr;
        // The library converts half to float on reading but not float to half on writing:
        // halves are converted here (Imath's conversion, rounding to nearest even).
        std::vector<Imath::half> halves;
        if (half_float) halves.assign(img.data.begin(), img.data.end());
        const size_t value_size = half_float ? sizeof(Imath::half) : sizeof(float);
        const char* pixels = half_float ? reinterpret_cast<const char*>(halves.data())
                                        : reinterpret_cast<const char*>(img.data.data());
        const size_t xs = value_size * size_t(img.channels);
        const size_t ys = xs * size_t(img.width);
        Imf::FrameBuffer fb;
        for (int c = 0; c < img.channels; ++c) {
            const char* name = named   ? img.channel_names[size_t(c)].c_str()
                               : names ? names[c]
                                       : "Y";
            header.channels().insert(name, Imf::Channel(type));
            fb.insert(name, Imf::Slice(type, const_cast<char*>(pixels + value_size * size_t(c)),
                                       xs, ys));
        }
        CheckedOStream os(file);
        if (!os.error().empty())
            throw Error(fmt::format("{}: cannot open for writing: {}", path, os.error()));
        {
            Imf::OutputFile out(os, header, 1);
            out.setFrameBuffer(fb);
            out.writePixels(img.height);
        }
        if (std::string e = os.finish(); !e.empty())
            throw Error(fmt::format("{}: cannot write EXR: {}", path, e));
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(fmt::format("{}: cannot write EXR: {}", path, e.what()));
    }
}

std::optional<Image> read_exr(const std::string& path) {
    try {
        Imf::InputFile in(path.c_str(), 1);
        const Imf::Header& h = in.header();
        if (h.hasType() && h.type() != Imf::SCANLINEIMAGE && h.type() != Imf::TILEDIMAGE)
            return std::nullopt;  // deep data
        // The channels we read ourselves: R, G, B (and A), or Y alone, every one half or
        // float with no subsampling. OpenImageIO orders R, G, B, A (the file lists them
        // alphabetically); other layouts are left to it.
        static const char* const order[] = {"R", "G", "B", "A"};
        std::array<bool, 4> has{};
        bool y = false;
        int count = 0;
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
            const Imf::Channel& ch = it.channel();
            if ((ch.type != Imf::HALF && ch.type != Imf::FLOAT) || ch.xSampling != 1 ||
                ch.ySampling != 1)
                return std::nullopt;
            const char* name = it.name();
            bool known = false;
            for (int k = 0; k < 4; ++k)
                if (std::strcmp(name, order[k]) == 0) has[size_t(k)] = known = true;
            if (std::strcmp(name, "Y") == 0) y = known = true;
            if (!known) return std::nullopt;
            ++count;
        }
        const bool rgb = has[0] && has[1] && has[2];
        if (!(rgb && !y) && !(y && count == 1)) return std::nullopt;

        std::vector<std::string> names;
        if (y)
            names.emplace_back("Y");
        else
            for (int k = 0; k < 4; ++k)
                if (has[size_t(k)]) names.emplace_back(order[k]);
        Image img = read_exr_pixels(in, std::move(names), path);
        img.channel_names.clear();  // the usual layouts go unnamed
        return img;
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(fmt::format("{}: cannot read image: {}", path, e.what()));
    }
}

}  // namespace sr::image_formats

namespace sr {

Image read_exr_channels(const std::string& path) {
    try {
        Imf::InputFile in(path.c_str(), 1);
        const Imf::Header& h = in.header();
        std::vector<std::string> names;
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
            const Imf::Channel& ch = it.channel();
            if ((ch.type != Imf::HALF && ch.type != Imf::FLOAT) || ch.xSampling != 1 ||
                ch.ySampling != 1)
                throw Error(
                    fmt::format("{}: channel {} is not of half or float pixels", path, it.name()));
            names.emplace_back(it.name());
        }
        Image img = image_formats::read_exr_pixels(in, std::move(names), path);
        for (auto it = h.begin(); it != h.end(); ++it)
            if (const auto* a = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                img.attributes.emplace_back(it.name(), a->value());
        return img;
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(fmt::format("{}: cannot read EXR: {}", path, e.what()));
    }
}

}  // namespace sr
