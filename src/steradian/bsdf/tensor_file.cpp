#include "steradian/bsdf/tensor_file.h"

#include <bit>
#include <cstring>

#include "steradian/core/error.h"

namespace sr {

namespace {

constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
constexpr size_t kMaxDims = 16;

/// Little-endian unsigned integer of N bytes at p.
template <typename T>
T load_le(const char* p) {
    T v = 0;
    for (size_t i = 0; i < sizeof(T); ++i) v |= T(uint8_t(p[i])) << (8 * i);
    return v;
}

template <typename T>
void store_le(std::string& out, T v) {
    for (size_t i = 0; i < sizeof(T); ++i) out.push_back(char(uint8_t(uint64_t(v) >> (8 * i))));
}

/// Reads the header fields in order, each checked against the end of the file.
class Cursor {
  public:
    Cursor(std::string_view bytes, std::string_view name) : m_bytes(bytes), m_name(name) {}
    template <typename T>
    T read(const char* what) {
        need(sizeof(T), what);
        T v = load_le<T>(m_bytes.data() + m_pos);
        m_pos += sizeof(T);
        return v;
    }
    std::string_view read_bytes(size_t n, const char* what) {
        need(n, what);
        std::string_view v = m_bytes.substr(m_pos, n);
        m_pos += n;
        return v;
    }
    [[noreturn]] void fail(const std::string& why) const {
        throw Error(fmt::format("{}: {}", m_name, why));
    }

  private:
    void need(size_t n, const char* what) const {
        if (m_bytes.size() - m_pos < n)
            fail(
                fmt::format("truncated tensor file: {} at byte {} needs {} bytes, the file has "
                            "{}",
                            what, m_pos, n, m_bytes.size()));
    }
    std::string_view m_bytes;
    std::string_view m_name;
    size_t m_pos = 0;
};

}  // namespace

size_t tensor_dtype_size(TensorDtype t) {
    switch (t) {
        case TensorDtype::UInt8:
        case TensorDtype::Int8:
            return 1;
        case TensorDtype::UInt16:
        case TensorDtype::Int16:
        case TensorDtype::Float16:
            return 2;
        case TensorDtype::UInt32:
        case TensorDtype::Int32:
        case TensorDtype::Float32:
            return 4;
        case TensorDtype::UInt64:
        case TensorDtype::Int64:
        case TensorDtype::Float64:
            return 8;
        default:
            return 0;
    }
}

const char* to_string(TensorDtype t) {
    switch (t) {
        case TensorDtype::UInt8:
            return "uint8";
        case TensorDtype::Int8:
            return "int8";
        case TensorDtype::UInt16:
            return "uint16";
        case TensorDtype::Int16:
            return "int16";
        case TensorDtype::UInt32:
            return "uint32";
        case TensorDtype::Int32:
            return "int32";
        case TensorDtype::UInt64:
            return "uint64";
        case TensorDtype::Int64:
            return "int64";
        case TensorDtype::Float16:
            return "float16";
        case TensorDtype::Float32:
            return "float32";
        case TensorDtype::Float64:
            return "float64";
        default:
            return "invalid";
    }
}

uint64_t TensorField::count() const {
    uint64_t n = 1;
    for (uint64_t s : shape) n *= s;  // bounded by the file size when read
    return n;
}

std::vector<float> TensorField::floats() const {
    std::vector<float> v(bytes.size() / 4);
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = std::bit_cast<float>(load_le<uint32_t>(bytes.data() + 4 * i));
    return v;
}

std::string TensorField::describe() const {
    std::string s = fmt::format("{} [", to_string(dtype));
    for (size_t i = 0; i < shape.size(); ++i) s += fmt::format("{}{}", i ? ", " : "", shape[i]);
    return s + "]";
}

TensorFile parse_tensor_file(std::string_view bytes, std::string_view name) {
    Cursor in(bytes, name);
    std::string_view magic = in.read_bytes(sizeof kMagic, "the header");
    if (std::memcmp(magic.data(), kMagic, sizeof kMagic) != 0)
        in.fail("not a tensor file (it does not start with \"tensor_file\")");
    uint8_t major = in.read<uint8_t>("the version"), minor = in.read<uint8_t>("the version");
    if (major != 1 || minor != 0)
        in.fail(fmt::format("tensor file version {}.{}; only version 1.0 is known", major, minor));
    uint32_t n_fields = in.read<uint32_t>("the number of fields");
    TensorFile file;
    for (uint32_t f = 0; f < n_fields; ++f) {
        std::string what = fmt::format("field {} of {}", f + 1, n_fields);
        uint16_t name_length = in.read<uint16_t>("a field's name length");
        std::string field_name(in.read_bytes(name_length, "a field's name"));
        what = fmt::format("field \"{}\"", printable(field_name));
        uint16_t ndim = in.read<uint16_t>("a field's dimension count");
        auto dtype = TensorDtype(in.read<uint8_t>("a field's type"));
        uint64_t offset = in.read<uint64_t>("a field's offset");
        if (ndim > kMaxDims)
            in.fail(fmt::format("{} has {} dimensions, more than {}", what, ndim, kMaxDims));
        size_t value_size = tensor_dtype_size(dtype);
        if (value_size == 0)
            in.fail(fmt::format("{} has an unknown type code {}", what, int(dtype)));
        TensorField field;
        field.dtype = dtype;
        uint64_t size = value_size;
        bool too_big = false;
        for (uint16_t d = 0; d < ndim; ++d) {
            uint64_t extent = in.read<uint64_t>("a field's shape");
            field.shape.push_back(extent);
            if (extent != 0 && size > bytes.size() / extent) too_big = true;
            size *= too_big ? 1 : extent;
        }
        if (too_big || offset > bytes.size() || size > bytes.size() - offset) {
            std::string need =
                too_big ? fmt::format("more than {}", bytes.size()) : std::to_string(size);
            in.fail(
                fmt::format("{} ({}) needs {} bytes at byte {}, past the end of the file ({} "
                            "bytes)",
                            what, field.describe(), need, offset, bytes.size()));
        }
        field.bytes.assign(bytes.substr(size_t(offset), size_t(size)));
        if (!file.fields.emplace(std::move(field_name), std::move(field)).second)
            in.fail(fmt::format("{} appears twice", what));
    }
    return file;
}

std::string write_tensor_file(const TensorFile& file) {
    size_t header = sizeof kMagic + 2 + 4;
    for (const auto& [name, field] : file.fields)
        header += 2 + name.size() + 2 + 1 + 8 + 8 * field.shape.size();
    std::string out(kMagic, sizeof kMagic);
    out.push_back(1);
    out.push_back(0);
    store_le<uint32_t>(out, uint32_t(file.fields.size()));
    uint64_t offset = header;
    for (const auto& [name, field] : file.fields) {
        store_le<uint16_t>(out, uint16_t(name.size()));
        out += name;
        store_le<uint16_t>(out, uint16_t(field.shape.size()));
        out.push_back(char(field.dtype));
        store_le<uint64_t>(out, offset);
        for (uint64_t s : field.shape) store_le<uint64_t>(out, s);
        offset += field.bytes.size();
    }
    for (const auto& [name, field] : file.fields) out += field.bytes;
    return out;
}

TensorField float32_field(std::vector<uint64_t> shape, const std::vector<float>& values) {
    TensorField f;
    f.dtype = TensorDtype::Float32;
    f.shape = std::move(shape);
    f.bytes.reserve(values.size() * 4);
    for (float v : values) store_le<uint32_t>(f.bytes, std::bit_cast<uint32_t>(v));
    return f;
}

}  // namespace sr
