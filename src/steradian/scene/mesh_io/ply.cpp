#include "steradian/scene/mesh_io/ply.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <system_error>
#include <vector>

#if __has_include(<sys/mman.h>)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#define STERADIAN_PLY_MMAP 1
#endif

#include "steradian/core/input_file.h"

namespace sr {
namespace {

// ---- scalar types ----------------------------------------------------------------------------

enum class Type : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct TypeName {
    std::string_view name;
    Type type;
};
constexpr TypeName kTypeNames[] = {
    {"char", Type::Int8},      {"int8", Type::Int8},       {"uchar", Type::UInt8},
    {"uint8", Type::UInt8},    {"short", Type::Int16},     {"int16", Type::Int16},
    {"ushort", Type::UInt16},  {"uint16", Type::UInt16},   {"int", Type::Int32},
    {"int32", Type::Int32},    {"uint", Type::UInt32},     {"uint32", Type::UInt32},
    {"float", Type::Float32},  {"float32", Type::Float32}, {"double", Type::Float64},
    {"float64", Type::Float64}};

bool parse_type(std::string_view s, Type& t) {
    for (const TypeName& tn : kTypeNames) {
        if (tn.name == s) {
            t = tn.type;
            return true;
        }
    }
    return false;
}

constexpr std::size_t type_size(Type t) {
    switch (t) {
        case Type::Int8:
        case Type::UInt8:
            return 1;
        case Type::Int16:
        case Type::UInt16:
            return 2;
        case Type::Int32:
        case Type::UInt32:
        case Type::Float32:
            return 4;
        case Type::Float64:
            return 8;
    }
    return 1;
}

constexpr bool is_integer(Type t) { return t != Type::Float32 && t != Type::Float64; }

constexpr std::int64_t type_min(Type t) {
    switch (t) {
        case Type::Int8:
            return std::numeric_limits<std::int8_t>::min();
        case Type::Int16:
            return std::numeric_limits<std::int16_t>::min();
        case Type::Int32:
            return std::numeric_limits<std::int32_t>::min();
        default:
            return 0;
    }
}

constexpr std::int64_t type_max(Type t) {
    switch (t) {
        case Type::Int8:
            return std::numeric_limits<std::int8_t>::max();
        case Type::UInt8:
            return std::numeric_limits<std::uint8_t>::max();
        case Type::Int16:
            return std::numeric_limits<std::int16_t>::max();
        case Type::UInt16:
            return std::numeric_limits<std::uint16_t>::max();
        case Type::Int32:
            return std::numeric_limits<std::int32_t>::max();
        default:
            return std::numeric_limits<std::uint32_t>::max();
    }
}

std::string_view type_name(Type t) {
    for (const TypeName& tn : kTypeNames) {
        if (tn.type == t) return tn.name;
    }
    return "?";
}

// ---- header ----------------------------------------------------------------------------------

/// What a property feeds: a vertex attribute, the face's vertex list, its face index, or nothing.
enum Role : std::uint8_t {
    kX,
    kY,
    kZ,
    kNx,
    kNy,
    kNz,
    kU,
    kV,
    kNumVertexRoles,
    kVertexIndices = kNumVertexRoles,
    kFaceIndex,
    kSkip
};

struct Property {
    std::string name;
    bool is_list = false;
    Type count_type = Type::UInt8;  ///< lists only
    Type type = Type::Float32;      ///< the scalar type, or the list's item type
    Role role = kSkip;
    int line = 0;
};

struct Element {
    std::string name;
    std::int64_t count = 0;
    int line = 0;
    std::vector<Property> props;

    Property* find(std::string_view n) {
        for (Property& p : props) {
            if (p.name == n) return &p;
        }
        return nullptr;
    }
    bool all_scalar() const {
        return std::none_of(props.begin(), props.end(),
                            [](const Property& p) { return p.is_list; });
    }
};

enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::size_t data_offset = 0;  ///< first byte after the end_header line
    int data_line = 0;            ///< line number of the first data line (ascii)
    int vertex_element = -1;
    int face_element = -1;
    bool has_normals = false;
    bool has_uv = false;
    bool has_face_indices = false;
};

/// Shortens user text quoted in messages (it may be binary garbage).
std::string clip(std::string_view s) {
    constexpr std::size_t kMax = 40;
    if (s.size() <= kMax) return std::string(s);
    return std::string(s.substr(0, kMax)) + "...";
}

/// Throws sr::Error("name:line: msg"), or "name: msg" when line is 0.
template <typename... Args>
[[noreturn]] void fail(const std::string& name, int line, fmt::format_string<Args...> f,
                       Args&&... args) {
    std::string msg = fmt::format(f, std::forward<Args>(args)...);
    if (line > 0) throw Error(fmt::format("{}:{}: {}", name, line, msg));
    throw Error(fmt::format("{}: {}", name, msg));
}

void split_words(std::string_view line, std::vector<std::string_view>& words) {
    words.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
        if (j > i) words.push_back(line.substr(i, j - i));
        i = j;
    }
}

bool parse_int64(std::string_view s, std::int64_t& v) {
    if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && ptr == s.data() + s.size();
}

Header parse_header(std::string_view bytes, const std::string& name) {
    Header h;
    bool have_format = false;
    std::size_t pos = 0;
    int line_no = 0;
    std::vector<std::string_view> w;
    while (pos < bytes.size()) {
        const std::size_t eol = bytes.find('\n', pos);
        const std::size_t stop = eol == std::string_view::npos ? bytes.size() : eol;
        std::string_view line = bytes.substr(pos, stop - pos);
        pos = eol == std::string_view::npos ? bytes.size() : eol + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        split_words(line, w);
        if (line_no == 1) {
            if (w.size() != 1 || w[0] != "ply")
                fail(name, 0, "not a PLY file (the first line is not 'ply')");
            continue;
        }
        if (w.empty()) continue;
        const std::string_view key = w[0];
        if (key == "comment" || key == "obj_info") continue;
        if (key == "format") {
            if (have_format) fail(name, line_no, "duplicate 'format' line");
            if (w.size() != 3)
                fail(name, line_no,
                     "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
            if (w[1] == "ascii") {
                h.format = Format::Ascii;
            } else if (w[1] == "binary_little_endian") {
                h.format = Format::BinaryLittleEndian;
            } else if (w[1] == "binary_big_endian") {
                h.format = Format::BinaryBigEndian;
            } else {
                fail(name, line_no, "unsupported format '{}'", clip(w[1]));
            }
            if (w[2] != "1.0" && w[2] != "1")
                fail(name, line_no, "unsupported PLY version '{}' (only 1.0 is supported)",
                     clip(w[2]));
            have_format = true;
        } else if (key == "element") {
            if (!have_format) fail(name, line_no, "'element' before the 'format' line");
            if (w.size() != 3) fail(name, line_no, "expected 'element <name> <count>'");
            Element e;
            e.name = std::string(w[1]);
            e.line = line_no;
            if (!parse_int64(w[2], e.count))
                fail(name, line_no, "bad count '{}' for element '{}'", clip(w[2]), clip(e.name));
            if (e.count < 0)
                fail(name, line_no, "element '{}' has a negative count ({})", clip(e.name),
                     e.count);
            h.elements.push_back(std::move(e));
        } else if (key == "property") {
            if (h.elements.empty()) fail(name, line_no, "'property' before any 'element'");
            Element& e = h.elements.back();
            Property p;
            p.line = line_no;
            if (w.size() >= 2 && w[1] == "list") {
                if (w.size() != 5)
                    fail(name, line_no, "expected 'property list <count type> <item type> <name>'");
                if (!parse_type(w[2], p.count_type))
                    fail(name, line_no, "unknown property type '{}'", clip(w[2]));
                if (!is_integer(p.count_type))
                    fail(name, line_no, "list count type '{}' is not an integer type", clip(w[2]));
                if (!parse_type(w[3], p.type))
                    fail(name, line_no, "unknown property type '{}'", clip(w[3]));
                p.is_list = true;
                p.name = std::string(w[4]);
            } else {
                if (w.size() != 3) fail(name, line_no, "expected 'property <type> <name>'");
                if (!parse_type(w[1], p.type))
                    fail(name, line_no, "unknown property type '{}'", clip(w[1]));
                p.name = std::string(w[2]);
            }
            if (e.find(p.name))
                fail(name, line_no, "duplicate property '{}' in element '{}'", clip(p.name),
                     clip(e.name));
            e.props.push_back(std::move(p));
        } else if (key == "end_header") {
            if (w.size() != 1) fail(name, line_no, "unexpected text after 'end_header'");
            if (!have_format) fail(name, line_no, "no 'format' line before 'end_header'");
            h.data_offset = pos;
            h.data_line = line_no + 1;
            return h;
        } else {
            fail(name, line_no, "unknown header keyword '{}'", clip(key));
        }
    }
    if (line_no == 0) fail(name, 0, "not a PLY file (it is empty)");
    fail(name, 0, "unexpected end of file in the header (no 'end_header' line)");
}

/// Finds the vertex and face elements and gives their properties roles.
void resolve_roles(Header& h, const std::string& name) {
    for (std::size_t i = 0; i < h.elements.size(); ++i) {
        const Element& e = h.elements[i];
        if (e.name == "vertex") {
            if (h.vertex_element >= 0) fail(name, e.line, "duplicate element 'vertex'");
            h.vertex_element = static_cast<int>(i);
        } else if (e.name == "face") {
            if (h.face_element >= 0) fail(name, e.line, "duplicate element 'face'");
            h.face_element = static_cast<int>(i);
        }
    }
    if (h.vertex_element < 0) fail(name, 0, "no 'vertex' element in the header");
    if (h.face_element < 0) fail(name, 0, "no 'face' element in the header");

    Element& v = h.elements[h.vertex_element];
    if (v.count > std::numeric_limits<int>::max())
        fail(name, v.line, "too many vertices ({})", v.count);
    auto scalar = [&](Property* p, Role role) {
        if (p->is_list)
            fail(name, p->line, "property '{}' of element '{}' is a list, expected a scalar",
                 p->name, v.name);
        p->role = role;
    };
    const std::string_view xyz[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
        Property* p = v.find(xyz[k]);
        if (!p) fail(name, v.line, "element 'vertex' has no property '{}'", xyz[k]);
        scalar(p, static_cast<Role>(kX + k));
    }
    Property* nrm[] = {v.find("nx"), v.find("ny"), v.find("nz")};
    const int n_normals = (nrm[0] != nullptr) + (nrm[1] != nullptr) + (nrm[2] != nullptr);
    if (n_normals == 3) {
        for (int k = 0; k < 3; ++k) scalar(nrm[k], static_cast<Role>(kNx + k));
        h.has_normals = true;
    } else if (n_normals > 0) {
        fail(name, v.line, "element 'vertex' has only some of the properties nx, ny, nz");
    }
    const std::string_view uv_names[][2] = {
        {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
    const Property* partial = nullptr;
    std::string_view partial_missing;
    for (const auto& pair : uv_names) {
        Property* pu = v.find(pair[0]);
        Property* pv = v.find(pair[1]);
        if (pu && pv) {
            if (!h.has_uv) {
                scalar(pu, kU);
                scalar(pv, kV);
                h.has_uv = true;
            }
        } else if ((pu || pv) && !partial) {
            partial = pu ? pu : pv;
            partial_missing = pu ? pair[1] : pair[0];
        }
    }
    if (!h.has_uv && partial)
        fail(name, v.line, "element 'vertex' has property '{}' but no '{}'", partial->name,
             partial_missing);

    Element& f = h.elements[h.face_element];
    Property* vi = f.find("vertex_indices");
    if (!vi) vi = f.find("vertex_index");
    if (!vi) fail(name, f.line, "element 'face' has no property 'vertex_indices'");
    if (!vi->is_list)
        fail(name, vi->line, "property '{}' of element 'face' is not a list", vi->name);
    if (!is_integer(vi->type))
        fail(name, vi->line, "property '{}' of element 'face' has non-integer type '{}'", vi->name,
             type_name(vi->type));
    vi->role = kVertexIndices;
    if (Property* fi = f.find("face_indices")) {
        if (fi->is_list)
            fail(name, fi->line,
                 "property 'face_indices' of element 'face' is a list, "
                 "expected a scalar");
        if (!is_integer(fi->type))
            fail(name, fi->line,
                 "property 'face_indices' of element 'face' has non-integer "
                 "type '{}'",
                 type_name(fi->type));
        fi->role = kFaceIndex;
        h.has_face_indices = true;
    }
}

// ---- readers ---------------------------------------------------------------------------------

enum class Status { Ok, Eof, Bad };

template <typename T, bool Swap>
inline T load(const char* p) {
    T v;
    if constexpr (Swap && sizeof(T) > 1) {
        using U =
            std::conditional_t<sizeof(T) == 2, std::uint16_t,
                               std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
        U u;
        std::memcpy(&u, p, sizeof(U));
        if constexpr (sizeof(T) == 2) {
            u = __builtin_bswap16(u);
        } else if constexpr (sizeof(T) == 4) {
            u = __builtin_bswap32(u);
        } else {
            u = __builtin_bswap64(u);
        }
        std::memcpy(&v, &u, sizeof(T));
    } else {
        std::memcpy(&v, p, sizeof(T));
    }
    return v;
}

template <bool Swap>
inline double load_as_double(const char* p, Type t) {
    switch (t) {
        case Type::Int8:
            return load<std::int8_t, Swap>(p);
        case Type::UInt8:
            return load<std::uint8_t, Swap>(p);
        case Type::Int16:
            return load<std::int16_t, Swap>(p);
        case Type::UInt16:
            return load<std::uint16_t, Swap>(p);
        case Type::Int32:
            return load<std::int32_t, Swap>(p);
        case Type::UInt32:
            return load<std::uint32_t, Swap>(p);
        case Type::Float32:
            return load<float, Swap>(p);
        case Type::Float64:
            return load<double, Swap>(p);
    }
    return 0;
}

/// Integer types only (roles that need integers are checked in resolve_roles).
template <bool Swap>
inline std::int64_t load_as_int(const char* p, Type t) {
    switch (t) {
        case Type::Int8:
            return load<std::int8_t, Swap>(p);
        case Type::UInt8:
            return load<std::uint8_t, Swap>(p);
        case Type::Int16:
            return load<std::int16_t, Swap>(p);
        case Type::UInt16:
            return load<std::uint16_t, Swap>(p);
        case Type::Int32:
            return load<std::int32_t, Swap>(p);
        case Type::UInt32:
            return load<std::uint32_t, Swap>(p);
        default:
            return 0;
    }
}

/// Bounds-checked cursor over binary data; Swap when the file's byte order is not native.
template <bool Swap>
class BinaryReader {
  public:
    static constexpr bool kBinary = true;
    static constexpr bool kSwap = Swap;
    /// Over [begin, end). With a `stream`, the bytes are still being inflated into the
    /// buffer that starts at `base`: need_bytes() waits for them before they are read.
    BinaryReader(const char* begin, const char* end, ConcurrentGunzip* stream = nullptr,
                 const char* base = nullptr)
        : m_p(begin), m_end(end), m_ready(stream ? begin : end), m_stream(stream), m_base(base) {}

    /// Makes the n bytes from `from` (clipped to the end) readable; the bytes before `from`
    /// are never read again (a stream may reuse their memory).
    void need_bytes(const char* from, std::size_t n) {
        const char* upto = n >= static_cast<std::size_t>(m_end - from) ? m_end : from + n;
        if (upto > m_ready) {
            m_stream->release(static_cast<std::uint64_t>(from - m_base));
            m_stream->wait(static_cast<std::uint64_t>(upto - m_base));
            m_ready = upto;
        }
    }
    void need_all() { need_bytes(m_p, remaining()); }
    /// How far from `from` the bytes are readable without waiting.
    const char* ready() const { return m_ready; }
    const char* end() const { return m_end; }

    std::size_t remaining() const { return static_cast<std::size_t>(m_end - m_p); }
    const char* pos() const { return m_p; }
    void advance(std::size_t n) { m_p += n; }

    Status read_double(Type t, double& v) {
        const std::size_t s = type_size(t);
        if (remaining() < s) return Status::Eof;
        v = load_as_double<Swap>(m_p, t);
        m_p += s;
        return Status::Ok;
    }
    Status read_int(Type t, std::int64_t& v) {
        const std::size_t s = type_size(t);
        if (remaining() < s) return Status::Eof;
        v = load_as_int<Swap>(m_p, t);
        m_p += s;
        return Status::Ok;
    }
    Status skip(Type t, std::int64_t n = 1) {
        const std::size_t s = type_size(t);
        if (static_cast<std::uint64_t>(n) > remaining() / s) return Status::Eof;
        m_p += static_cast<std::size_t>(n) * s;
        return Status::Ok;
    }
    // Binary values are always well formed; these exist for the shared error path.
    int line() const { return 0; }
    std::string_view token() const { return {}; }
    std::string expected() const { return {}; }

  private:
    const char* m_p;
    const char* m_end;
    const char* m_ready;
    ConcurrentGunzip* m_stream;
    const char* m_base;
};

bool parse_float_token(std::string_view tok, Type t, double& v) {
    if (tok.size() > 1 && tok[0] == '+') tok.remove_prefix(1);
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (t == Type::Float32) {
        float f;
        auto [ptr, ec] = std::from_chars(b, e, f);
        if (ec == std::errc() && ptr == e) {
            v = f;
            return true;
        }
        // Out of float range (e.g. 1e-60 or 1e60): fall through to double and let the cast
        // to Float decide (validate() rejects infinities).
    }
    auto [ptr, ec] = std::from_chars(b, e, v);
    return ec == std::errc() && ptr == e;
}

bool parse_int_token(std::string_view tok, Type t, std::int64_t& v) {
    if (!parse_int64(tok, v)) {
        // Tolerate integral values written as reals ("3.0").
        double d;
        if (!parse_float_token(tok, Type::Float64, d) || !(std::floor(d) == d) ||
            std::abs(d) > 1e18)
            return false;
        v = static_cast<std::int64_t>(d);
    }
    return v >= type_min(t) && v <= type_max(t);
}

/// Whitespace-separated tokens; counts lines for messages.
class AsciiReader {
  public:
    static constexpr bool kBinary = false;
    AsciiReader(const char* begin, const char* end, int line)
        : m_p(begin), m_end(end), m_line(line), m_tok_line(line) {}

    std::size_t remaining() const { return static_cast<std::size_t>(m_end - m_p); }

    Status next_token() {
        while (m_p < m_end) {
            const char c = *m_p;
            if (c == '\n') {
                ++m_line;
            } else if (c != ' ' && c != '\t' && c != '\r' && c != '\v' && c != '\f') {
                break;
            }
            ++m_p;
        }
        if (m_p == m_end) return Status::Eof;
        const char* b = m_p;
        while (m_p < m_end && !is_space(*m_p)) ++m_p;
        m_tok = std::string_view(b, static_cast<std::size_t>(m_p - b));
        m_tok_line = m_line;
        return Status::Ok;
    }
    Status read_double(Type t, double& v) {
        if (next_token() != Status::Ok) return Status::Eof;
        if (is_integer(t)) {
            std::int64_t i;
            if (!parse_int_token(m_tok, t, i)) return bad(t);
            v = static_cast<double>(i);
        } else if (!parse_float_token(m_tok, t, v)) {
            return bad(t);
        }
        return Status::Ok;
    }
    Status read_int(Type t, std::int64_t& v) {
        if (next_token() != Status::Ok) return Status::Eof;
        if (is_integer(t)) {
            if (!parse_int_token(m_tok, t, v)) return bad(t);
        } else {
            double d;
            if (!parse_float_token(m_tok, t, d) || !(std::abs(d) <= 9e18)) return bad(t);
            v = static_cast<std::int64_t>(d);
        }
        return Status::Ok;
    }
    Status skip(Type t, std::int64_t n = 1) {
        double d;
        for (std::int64_t i = 0; i < n; ++i) {
            const Status st = read_double(t, d);
            if (st != Status::Ok) return st;
        }
        return Status::Ok;
    }
    int line() const { return m_tok_line; }
    std::string_view token() const { return m_tok; }
    std::string expected() const {
        if (is_integer(m_bad_type))
            return fmt::format("an integer of type '{}'", type_name(m_bad_type));
        return "a number";
    }

  private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    }
    Status bad(Type t) {
        m_bad_type = t;
        return Status::Bad;
    }

    const char* m_p;
    const char* m_end;
    int m_line;
    int m_tok_line;
    std::string_view m_tok;
    Type m_bad_type = Type::Float32;
};

// ---- element readers -------------------------------------------------------------------------

struct Context {
    const std::string& name;
    const Header& h;
    TriangleMeshData& mesh;
    std::int64_t num_vertices = 0;
};

template <class R>
[[noreturn]] void fail_read(const Context& c, const R& r, Status st, const Element& e,
                            std::int64_t i, const Property& p) {
    if (st == Status::Eof)
        fail(c.name, 0, "unexpected end of file in element '{}' (read {} of {})", clip(e.name), i,
             e.count);
    fail(c.name, r.line(), "element '{}' {}, property '{}': expected {}, got '{}'", clip(e.name), i,
         clip(p.name), r.expected(), clip(r.token()));
}

[[noreturn]] void fail_negative_list(const Context& c, const Element& e, std::int64_t i,
                                     const Property& p, std::int64_t n) {
    fail(c.name, 0, "element '{}' {}, property '{}': negative list length {}", clip(e.name), i,
         clip(p.name), n);
}

[[noreturn]] void fail_face_size(const Context& c, std::int64_t f, std::int64_t n) {
    fail(c.name, 0, "face {} has {} vertices; only triangles and quads are supported", f, n);
}

[[noreturn]] void fail_face_index(const Context& c, std::int64_t f, std::int64_t v) {
    fail(c.name, 0, "face {} references vertex {} but there are {} vertices", f, v, c.num_vertices);
}

/// Reads or skips any element, one property at a time.
template <class R>
void read_generic(R& r, const Element& e, Context& c) {
    if (e.props.empty()) return;  // nothing stored per item
    TriangleMeshData& m = c.mesh;
    const bool is_vertex = &e == &c.h.elements[c.h.vertex_element];
    const bool is_face = &e == &c.h.elements[c.h.face_element];
    if (is_vertex || is_face) {
        // Reserve for the items the remaining bytes can hold at most (counts may be lies).
        std::size_t min_item_bytes = 0;
        for (const Property& p : e.props) {
            if constexpr (R::kBinary) {
                min_item_bytes += type_size(p.is_list ? p.count_type : p.type);
            } else {
                min_item_bytes += 2;  // a digit and a separator
            }
        }
        const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(e.count),
                                                    r.remaining() / min_item_bytes + 1);
        if (is_vertex) {
            m.p.reserve(n + 1);  // the builder's padding (mesh.h)
            if (c.h.has_normals) m.n.reserve(n);
            if (c.h.has_uv) m.uv.reserve(n);
        } else {
            m.indices.reserve(m.indices.size() + 3 * n);
            if (c.h.has_face_indices) m.face_indices.reserve(m.face_indices.size() + n);
        }
    }
    double vals[kNumVertexRoles] = {};
    std::int64_t idx[4] = {};
    for (std::int64_t i = 0; i < e.count; ++i) {
        int nidx = 0;
        std::int64_t face_index = 0;
        for (const Property& p : e.props) {
            Status st = Status::Ok;
            if (p.is_list) {
                std::int64_t n = 0;
                st = r.read_int(p.count_type, n);
                if (st == Status::Ok) {
                    if (n < 0) fail_negative_list(c, e, i, p, n);
                    if (p.role == kVertexIndices) {
                        if (n < 3 || n > 4) fail_face_size(c, i, n);
                        for (int k = 0; k < n && st == Status::Ok; ++k) {
                            st = r.read_int(p.type, idx[k]);
                            if (st == Status::Ok && (idx[k] < 0 || idx[k] >= c.num_vertices))
                                fail_face_index(c, i, idx[k]);
                        }
                        nidx = static_cast<int>(n);
                    } else {
                        st = r.skip(p.type, n);
                    }
                }
            } else if (p.role < kNumVertexRoles) {
                st = r.read_double(p.type, vals[p.role]);
            } else if (p.role == kFaceIndex) {
                st = r.read_int(p.type, face_index);
                if (st == Status::Ok && (face_index < std::numeric_limits<int>::min() ||
                                         face_index > std::numeric_limits<int>::max()))
                    fail(c.name, 0, "face {} has face_indices {} outside the int range", i,
                         face_index);
            } else {
                st = r.skip(p.type);
            }
            if (st != Status::Ok) fail_read(c, r, st, e, i, p);
        }
        if (is_vertex) {
            m.p.emplace_back(Float(vals[kX]), Float(vals[kY]), Float(vals[kZ]));
            if (c.h.has_normals)
                m.n.emplace_back(Float(vals[kNx]), Float(vals[kNy]), Float(vals[kNz]));
            if (c.h.has_uv) m.uv.emplace_back(Float(vals[kU]), Float(vals[kV]));
        } else if (is_face) {
            // In [0, num_vertices): checked as read.
            const auto a = std::uint32_t(idx[0]), b = std::uint32_t(idx[1]),
                       d = std::uint32_t(idx[2]);
            m.indices.insert(m.indices.end(), {a, b, d});
            if (c.h.has_face_indices) m.face_indices.push_back(int(face_index));
            if (nidx == 4) {
                m.indices.insert(m.indices.end(), {a, d, std::uint32_t(idx[3])});
                if (c.h.has_face_indices) m.face_indices.push_back(int(face_index));
            }
        }
    }
}

/// Fixed-stride binary vertices (no list properties): one bounds check for the whole element.
template <bool Swap>
void read_vertices_fixed(BinaryReader<Swap>& r, const Element& e, Context& c) {
    std::size_t stride = 0;
    std::array<std::size_t, kNumVertexRoles> off{};
    std::array<Type, kNumVertexRoles> type{};
    bool all_float = true;
    for (const Property& p : e.props) {
        if (p.role < kNumVertexRoles) {
            off[p.role] = stride;
            type[p.role] = p.type;
            all_float = all_float && p.type == Type::Float32;
        }
        stride += type_size(p.type);
    }
    if (static_cast<std::uint64_t>(e.count) > r.remaining() / stride)
        fail(c.name, 0, "unexpected end of file in element '{}' (read {} of {})", e.name,
             r.remaining() / stride, e.count);
    const std::size_t n = static_cast<std::size_t>(e.count);
    const bool normals = c.h.has_normals;
    const bool uv = c.h.has_uv;
    TriangleMeshData& m = c.mesh;
    m.p.reserve(n + 1);  // the builder's padding (mesh.h)
    advise_huge_pages(m.p.data(), (n + 1) * sizeof(Point3));
    if (normals) {
        m.n.reserve(n);
        advise_huge_pages(m.n.data(), n * sizeof(Normal3));
    }
    if (uv) {
        m.uv.reserve(n);
        advise_huge_pages(m.uv.data(), n * sizeof(Point2));
    }
    m.p.resize(n);
    if (normals) m.n.resize(n);
    if (uv) m.uv.resize(n);
    auto fill = [&](auto get) {
        const char* rec = r.pos();
        // In blocks, each waited for when the file is still being inflated.
        constexpr std::size_t kBlock = std::size_t(1) << 16;
        for (std::size_t i0 = 0; i0 < n; i0 += kBlock) {
            const std::size_t i1 = std::min(n, i0 + kBlock);
            r.need_bytes(rec, (i1 - i0) * stride);
            for (std::size_t i = i0; i < i1; ++i, rec += stride) {
                m.p[i] = Point3(get(rec, kX), get(rec, kY), get(rec, kZ));
                if (normals) m.n[i] = Normal3(get(rec, kNx), get(rec, kNy), get(rec, kNz));
                if (uv) m.uv[i] = Point2(get(rec, kU), get(rec, kV));
            }
        }
    };
    if (all_float) {
        fill([&](const char* rec, Role role) { return load<float, Swap>(rec + off[role]); });
    } else {
        fill([&](const char* rec, Role role) {
            return static_cast<Float>(load_as_double<Swap>(rec + off[role], type[role]));
        });
    }
    r.advance(n * stride);
}

/// Binary faces whose only property is "list uchar int|uint vertex_indices".
template <bool Swap, typename Index>
void read_faces_fast(BinaryReader<Swap>& r, const Element& e, Context& c) {
    constexpr std::size_t kTri = 1 + 3 * sizeof(Index);
    const char* p = r.pos();
    const char* const end = p + r.remaining();
    const std::uint32_t nv = static_cast<std::uint32_t>(c.num_vertices);
    std::vector<std::uint32_t>& out = c.mesh.indices;
    out.reserve(out.size() +
                3 * std::min<std::size_t>(static_cast<std::size_t>(e.count), r.remaining() / kTri));
    advise_huge_pages(out.data() + out.size(), (out.capacity() - out.size()) * sizeof(out[0]));
    auto eof = [&](std::int64_t f) {
        fail(c.name, 0, "unexpected end of file in element 'face' (read {} of {})", f, e.count);
    };
    auto check = [&](std::int64_t f, const std::uint32_t* v, int k) {
        for (int j = 0; j < k; ++j) {
            if (v[j] >= nv) fail_face_index(c, f, static_cast<std::int64_t>(Index(v[j])));
        }
    };
    // Readable up to `ready` (the file may still be inflated): refreshed in 1 MiB steps.
    const char* ready = p;
    for (std::int64_t f = 0; f < e.count; ++f) {
        if (static_cast<std::size_t>(ready - p) < kTri + 4 && ready != end) {
            r.need_bytes(p, std::size_t(1) << 20);
            ready = r.ready();
        }
        if (p == end) eof(f);
        const unsigned k = static_cast<unsigned char>(*p);
        if (k == 3) {
            if (static_cast<std::size_t>(end - p) < kTri) eof(f);
            const std::uint32_t v[3] = {load<std::uint32_t, Swap>(p + 1),
                                        load<std::uint32_t, Swap>(p + 5),
                                        load<std::uint32_t, Swap>(p + 9)};
            if ((v[0] >= nv) | (v[1] >= nv) | (v[2] >= nv)) check(f, v, 3);
            out.push_back(v[0]);
            out.push_back(v[1]);
            out.push_back(v[2]);
            p += kTri;
        } else if (k == 4) {
            if (static_cast<std::size_t>(end - p) < kTri + 4) eof(f);
            const std::uint32_t v[4] = {
                load<std::uint32_t, Swap>(p + 1), load<std::uint32_t, Swap>(p + 5),
                load<std::uint32_t, Swap>(p + 9), load<std::uint32_t, Swap>(p + 13)};
            check(f, v, 4);
            out.insert(out.end(), {v[0], v[1], v[2], v[0], v[2], v[3]});
            p += kTri + 4;
        } else {
            fail_face_size(c, f, k);
        }
    }
    r.advance(static_cast<std::size_t>(p - r.pos()));
}

template <class R>
void read_element(R& r, const Element& e, Context& c) {
    if constexpr (R::kBinary) {
        const Element* vertex = &c.h.elements[c.h.vertex_element];
        const Element* face = &c.h.elements[c.h.face_element];
        if (&e == vertex && e.all_scalar()) {
            read_vertices_fixed(r, e, c);
            return;
        }
        if (&e == face && e.props.size() == 1 && e.props[0].count_type == Type::UInt8) {
            if (e.props[0].type == Type::Int32) {
                read_faces_fast<R::kSwap, std::int32_t>(r, e, c);
                return;
            }
            if (e.props[0].type == Type::UInt32) {
                read_faces_fast<R::kSwap, std::uint32_t>(r, e, c);
                return;
            }
        }
        r.need_all();
        if (&e != vertex && &e != face && e.all_scalar()) {
            std::size_t stride = 0;
            for (const Property& p : e.props) stride += type_size(p.type);
            if (stride > 0 && static_cast<std::uint64_t>(e.count) > r.remaining() / stride)
                fail(c.name, 0, "unexpected end of file in element '{}' (read {} of {})",
                     clip(e.name), r.remaining() / stride, e.count);
            r.advance(static_cast<std::size_t>(e.count) * stride);
            return;
        }
    }
    read_generic(r, e, c);
}

template <class R>
void read_body(R& r, Context& c) {
    for (const Element& e : c.h.elements) read_element(r, e, c);
}


/// parse_ply(), over bytes that a `stream` may still be inflating.
TriangleMeshData parse_ply_from(std::string_view bytes, const std::string& name,
                                ConcurrentGunzip* stream) {
    Header h;
    if (stream) {
        // The header is text at the front: parsed from the first 64 KiB, or from the whole
        // when it fails there (its end lies further, or it is malformed).
        constexpr std::size_t kHead = std::size_t(64) << 10;
        stream->wait(kHead);
        try {
            h = parse_header(bytes.substr(0, kHead), name);
        } catch (const Error&) {
            if (bytes.size() <= kHead) throw;
            stream->wait(bytes.size());
            h = parse_header(bytes, name);
        }
    } else {
        h = parse_header(bytes, name);
    }
    resolve_roles(h, name);
    TriangleMeshData mesh;
    Context c{name, h, mesh, h.elements[h.vertex_element].count};
    const char* begin = bytes.data() + h.data_offset;
    const char* end = bytes.data() + bytes.size();
    constexpr bool kLittle = std::endian::native == std::endian::little;
    if (h.format == Format::Ascii) {
        if (stream) stream->wait(bytes.size());
        AsciiReader r(begin, end, h.data_line);
        read_body(r, c);
        if (r.next_token() == Status::Ok)
            fail(name, r.line(), "unexpected data after the last element: '{}'", clip(r.token()));
    } else {
        std::size_t rest = 0;
        if (h.format == Format::BinaryLittleEndian) {
            BinaryReader<!kLittle> r(begin, end, stream, bytes.data());
            read_body(r, c);
            rest = r.remaining();
        } else {
            BinaryReader<kLittle> r(begin, end, stream, bytes.data());
            read_body(r, c);
            rest = r.remaining();
        }
        if (stream) stream->finish();
        if (rest > 0)
            warning(SourceLoc{},
                    fmt::format("{}: ignored {} bytes after the last element", name, rest));
    }
    validate(mesh, name);
    return mesh;
}

}  // namespace

TriangleMeshData parse_ply(std::string_view bytes, const std::string& name) {
    return parse_ply_from(bytes, name, nullptr);
}

namespace {

/// A file's bytes. Mapped where the system can (the page cache's pages, neither copied
/// nor freshly allocated: a 250 MB mesh read into a buffer costs 0.25 CPU-s of page
/// faults), else read into a buffer.
class FileBytes {
  public:
    FileBytes(const std::string& path, std::uint64_t size) : m_size(size) {
#ifdef STERADIAN_PLY_MMAP
        if (size > 0) {
            const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
            if (fd < 0) fail(path, 0, "cannot open file: {}", std::strerror(errno));
            // Mapped only at the size found before (a file since shortened is read, and its
            // read error reported, instead of faulting past its end).
            struct stat st {};
            void* map = MAP_FAILED;
            if (::fstat(fd, &st) == 0 && static_cast<std::uint64_t>(st.st_size) == size)
                map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
            ::close(fd);
            if (map != MAP_FAILED) {
                m_map = map;
                return;
            }
        }
#endif
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
        if (!file) fail(path, 0, "cannot open file: {}", std::strerror(errno));
        m_buffer = std::make_unique_for_overwrite<char[]>(size > 0 ? size : 1);
        const std::size_t got = std::fread(m_buffer.get(), 1, size, file.get());
        if (got != size) fail(path, 0, "read error after {} of {} bytes", got, size);
    }
    ~FileBytes() { release(); }
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;

    std::string_view view() const {
        return {m_map ? static_cast<const char*>(m_map) : m_buffer.get(),
                static_cast<std::size_t>(m_size)};
    }
    void release() {
#ifdef STERADIAN_PLY_MMAP
        if (m_map) ::munmap(m_map, m_size);
#endif
        m_map = nullptr;
        m_buffer.reset();
    }

  private:
    std::uint64_t m_size;
    void* m_map = nullptr;
    std::unique_ptr<char[]> m_buffer;
};

}  // namespace

TriangleMeshData read_ply(const std::string& path, std::uint64_t concurrent_gunzip_bytes) {
    uint64_t size = 0;
    if (std::string why = regular_file_problem(path, kMaxSceneFileBytes, &size); !why.empty())
        fail(path, 0, "cannot read file: {}", why);
    FileBytes file(path, size);
    const std::string_view bytes = file.view();
    // gzip data (".ply.gz", as pbrt-v4 reads through zlib) is decompressed in memory.
    if (is_gzip(bytes)) {
        // A large file is parsed while a thread of its own inflates it (wall time: the
        // inflate's alone, instead of the inflate's and the parse's).
        if (auto stream = ConcurrentGunzip::start(bytes, kMaxSceneFileBytes,
                                                  concurrent_gunzip_bytes)) {
            try {
                return parse_ply_from(stream->view(), path, stream.get());
            } catch (const ConcurrentGunzip::SizeMismatch&) {
                // Not the size its trailer states (several members): inflated whole below.
            } catch (const Error&) {
                // The data's own error comes first, as when inflated before parsing.
                std::string why;
                switch (stream->outcome(&why)) {
                    case ConcurrentGunzip::Outcome::ok:
                        throw;
                    case ConcurrentGunzip::Outcome::failed:
                        fail(path, 0, "{}", why);
                    case ConcurrentGunzip::Outcome::mismatch:
                        break;
                }
            }
        }
        GunzipBytes plain;
        try {
            plain = gunzip_bytes(bytes, kMaxSceneFileBytes);
        } catch (const Error& e) {
            fail(path, 0, "{}", e.what());
        }
        file.release();
        return parse_ply(plain.view(), path);
    }
    return parse_ply(bytes, path);
}

}  // namespace sr
