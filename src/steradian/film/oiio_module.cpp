// The OpenImageIO module (see oiio_module.h): built as a separate shared object
// (steradian_oiio.so), loaded by image_io.cpp on first use. Not part of steradian_core.
#include "steradian/film/oiio_module.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <string>

namespace {

void set_error(char* err, size_t err_size, const std::string& msg) {
    if (err_size == 0) return;
    std::snprintf(err, err_size, "%s", msg.c_str());
}

int can_write(const char* path) {
    // create() only looks the format up by the extension; it opens no file.
    return OIIO::ImageOutput::create(path) ? 1 : 0;
}

int write(const char* path, int width, int height, int channels, int is_float, int half,
          const void* pixels, char* err, size_t err_size) {
    try {
        auto out = OIIO::ImageOutput::create(path);
        if (!out) {
            std::string p(path);
            size_t dot = p.rfind('.');
            set_error(err, err_size, "unsupported image format '" +
                                         (dot == std::string::npos ? std::string() : p.substr(dot)) +
                                         "'");
            return 0;
        }
        OIIO::TypeDesc type = is_float ? (half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT)
                                       : OIIO::TypeDesc::UINT8;
        OIIO::ImageSpec spec(width, height, channels, type);
        if (channels == 1) spec.channelnames = {"Y"};
        spec.attribute("oiio:ColorSpace", is_float ? "Linear" : "sRGB");
        if (!out->open(path, spec)) {
            set_error(err, err_size, out->geterror());
            return 0;
        }
        bool ok = out->write_image(is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8,
                                   pixels);
        if (!ok || !out->close()) {
            set_error(err, err_size, out->geterror());
            return 0;
        }
        return 1;
    } catch (const std::exception& e) {
        set_error(err, err_size, e.what());
        return 0;
    }
}

void* open(const char* path, SrOiioHeader* header, char* err, size_t err_size) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) {
            set_error(err, err_size, "cannot read image: " + OIIO::geterror());
            return nullptr;
        }
        const OIIO::ImageSpec& spec = in->spec();
        header->width = spec.width;
        header->height = spec.height;
        header->channels = spec.nchannels;
        header->integer = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                          spec.format.basetype == OIIO::TypeDesc::UINT16;
        header->linear = spec.get_string_attribute("oiio:ColorSpace") == "Linear";
        return in.release();
    } catch (const std::exception& e) {
        set_error(err, err_size, std::string("cannot read image: ") + e.what());
        return nullptr;
    }
}

int read(void* handle, float* dst, char* err, size_t err_size) {
    auto* in = static_cast<OIIO::ImageInput*>(handle);
    try {
        if (!in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, dst)) {
            set_error(err, err_size, in->geterror());
            return 0;
        }
        return 1;
    } catch (const std::exception& e) {
        set_error(err, err_size, e.what());
        return 0;
    }
}

void close(void* handle) {
    std::unique_ptr<OIIO::ImageInput> in(static_cast<OIIO::ImageInput*>(handle));
    if (in) in->close();
}

const SrOiioModule kModule = {kSrOiioAbiVersion, can_write, write, open, read, close};

}  // namespace

extern "C" __attribute__((visibility("default"))) const SrOiioModule* steradian_oiio_module_v1() {
    return &kModule;
}
