#include "steradian/integrators/checkpoint.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdio>

#include "steradian/core/input_file.h"
#include "steradian/core/output_file.h"
#include "steradian/sampling/hash.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

// The layout:
//   steradian checkpoint\n
//   format 1\n
//   byte-order little|big\n
//   <key> <length>\n<length bytes>\n        (once per section, keys in order)
//   end <hash of everything before "end", 16 hex digits>\n
constexpr const char* kMagic = "steradian checkpoint\n";
constexpr int kFormat = 1;
constexpr const char* kByteOrder = std::endian::native == std::endian::little ? "little" : "big";
/// Checkpoints hold a film's sums (32 bytes a pixel, 2^28 pixels at most) and meter states.
constexpr uint64_t kMaxCheckpointBytes = uint64_t(16) << 30;

uint64_t hash_bytes(std::string_view s) {
    return murmur_hash64a(reinterpret_cast<const unsigned char*>(s.data()), s.size(),
                          0x636b7074);  // "ckpt"
}

std::string hex(uint64_t h) { return fmt::format("{:016x}", h); }

/// Reads one line (without its '\n') at `pos`, advancing it; false at the end of the data.
bool read_line(std::string_view data, size_t& pos, std::string_view& line) {
    const size_t nl = data.find('\n', pos);
    if (nl == std::string_view::npos) return false;
    line = data.substr(pos, nl - pos);
    pos = nl + 1;
    return true;
}

}  // namespace

void Checkpoint::set_number(const std::string& key, double v) {
    m_sections[key] = fmt::format("{}", v);  // shortest text that reads back to v
}

void Checkpoint::set_number(const std::string& key, uint64_t v) {
    m_sections[key] = fmt::format("{}", v);
}

const std::string& Checkpoint::get(const std::string& key) const {
    auto it = m_sections.find(key);
    if (it == m_sections.end())
        throw Error(fmt::format("checkpoint {}: no \"{}\" section (not a checkpoint of this kind)",
                                m_path, key));
    return it->second;
}

/// The whole of a section read as one number of type T (from_chars: the shortest text that
/// set_number wrote reads back exactly).
template <typename T>
T parse_number(const std::string& s, const std::string& path, const std::string& key) {
    T v{};
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size())
        throw Error(fmt::format("checkpoint {}: section \"{}\" is not a number", path, key));
    return v;
}

double Checkpoint::get_double(const std::string& key) const {
    return parse_number<double>(get(key), m_path, key);
}

uint64_t Checkpoint::get_u64(const std::string& key) const {
    return parse_number<uint64_t>(get(key), m_path, key);
}

Error Checkpoint::size_error(const std::string& key, size_t got, size_t want) const {
    return Error(fmt::format("checkpoint {}: section \"{}\" has {} bytes, expected {}", m_path, key,
                             got, want));
}

void Checkpoint::expect(const std::string& key, const std::string& value, const std::string& what,
                        const std::string& hint) const {
    const std::string& recorded = get(key);
    if (recorded == value) return;
    throw Error(fmt::format("checkpoint {} was written for {} {}; this run has {}{}{}", m_path,
                            what, recorded, value, hint.empty() ? "" : ": ", hint));
}

void Checkpoint::save(const std::string& path) const {
    std::string out = kMagic;
    out += fmt::format("format {}\nbyte-order {}\n", kFormat, kByteOrder);
    for (const auto& [key, value] : m_sections) {
        out += fmt::format("{} {}\n", key, value.size());
        out += value;
        out += '\n';
    }
    out += fmt::format("end {}\n", hex(hash_bytes(out)));
    write_text_file(path, out);
}

Checkpoint Checkpoint::load(const std::string& path) {
    const std::string data = read_regular_file(path, kMaxCheckpointBytes, "checkpoint", false);
    auto bad = [&](const std::string& why) {
        return Error(fmt::format("checkpoint {}: {}", path, why));
    };
    if (data.compare(0, std::strlen(kMagic), kMagic) != 0) throw bad("not a steradian checkpoint");
    // The hash first: whatever the damage (a truncated or altered file), it is reported as
    // such and nothing of it is parsed.
    const size_t end = data.rfind("end ");
    if (end == std::string::npos || data.size() != end + 4 + 16 + 1 || data.back() != '\n' ||
        data.compare(end + 4, 16, hex(hash_bytes(std::string_view(data).substr(0, end)))) != 0)
        throw bad("damaged or incomplete (its contents do not match its hash)");
    std::string_view body = std::string_view(data).substr(0, end);
    size_t pos = std::strlen(kMagic);
    std::string_view line;
    if (!read_line(body, pos, line) || line != fmt::format("format {}", kFormat))
        throw bad(fmt::format("format \"{}\", this build reads format {}", line, kFormat));
    if (!read_line(body, pos, line) || line != fmt::format("byte-order {}", kByteOrder))
        throw bad(fmt::format("written with {}, this machine is {}-endian", line, kByteOrder));
    Checkpoint c;
    c.m_path = path;
    while (pos < body.size()) {
        if (!read_line(body, pos, line)) throw bad("a section header without its end of line");
        const size_t sp = line.rfind(' ');
        uint64_t len = 0;
        if (sp == std::string_view::npos || sp == 0 ||
            std::from_chars(line.data() + sp + 1, line.data() + line.size(), len).ec !=
                std::errc() ||
            len > body.size() - pos || body.size() - pos - len < 1 || body[pos + len] != '\n')
            throw bad("a malformed section");
        c.m_sections[std::string(line.substr(0, sp))] = std::string(body.substr(pos, len));
        pos += len + 1;
    }
    return c;
}

void put_render_state(Checkpoint& c, const Film& film, const RenderStats& st) {
    c.set_array("film", film.sums());
    c.set_number("film-pixels", uint64_t(film.sums().size()));
    if (film.has_aux()) c.set_array("film-aux", film.aux_sums());
    c.set_number("spp", uint64_t(st.spp));
    c.set_number("wall-seconds", st.wall_seconds);
    c.set_number("cpu-seconds", st.cpu_seconds);
    c.set_number("camera-paths", st.camera_paths);
    c.set_number("rays", st.rays);
    c.set_number("nonfinite", st.nonfinite);
}

RenderStats get_render_state(const Checkpoint& c, Film& film) {
    const size_t n = film.sums().size();
    if (c.get_u64("film-pixels") != n)
        throw Error(fmt::format("checkpoint {}: a film of {} pixels, this one has {}", c.path(),
                                c.get_u64("film-pixels"), n));
    film.set_sums(c.get_array<PixelSum>("film", n));
    if (film.has_aux()) film.set_aux_sums(c.get_array<double>("film-aux", film.aux_sums().size()));
    RenderStats st;
    const uint64_t spp = c.get_u64("spp");
    if (spp > uint64_t(kMaxSamplesPerPixel))
        throw Error(fmt::format("checkpoint {}: {} samples per pixel", c.path(), spp));
    st.spp = int(spp);
    st.wall_seconds = c.get_double("wall-seconds");
    st.cpu_seconds = c.get_double("cpu-seconds");
    st.camera_paths = c.get_u64("camera-paths");
    st.rays = c.get_u64("rays");
    st.nonfinite = c.get_u64("nonfinite");
    return st;
}

void put_measure_state(Checkpoint& c, const MeasureState& st) {
    c.set_number("round", uint64_t(st.round));
    c.set_number("values", uint64_t(st.values.size()));
    c.set_array("next-n", st.next_n);
    c.set_array("value", st.values);
    c.set_array("stderr", st.stderrs);
    c.set_array("samples", st.samples);
    c.set_array("converged", st.converged);
    c.set_number("items", uint64_t(st.item_done.size()));
    c.set_array("item-done", st.item_done);
    c.set_array("replica-mean", st.replica_mean);
    c.set_number("paths", st.paths);
    c.set_number("rays", st.rays);
    c.set_number("nonfinite", st.nonfinite);
    c.set_number("wall-seconds", st.wall_seconds);
    c.set_number("cpu-seconds", st.cpu_seconds);
}

MeasureState get_measure_state(const Checkpoint& c, size_t values) {
    if (c.get_u64("values") != values)
        throw Error(fmt::format("checkpoint {}: {} meter values, this scene has {}", c.path(),
                                c.get_u64("values"), values));
    MeasureState st;
    const uint64_t round = c.get_u64("round");
    if (round > 64) throw Error(fmt::format("checkpoint {}: round {}", c.path(), round));
    st.round = int(round);
    st.next_n = c.get_array<int64_t>("next-n", values);
    st.values = c.get_array<double>("value", values);
    st.stderrs = c.get_array<double>("stderr", values);
    st.samples = c.get_array<int64_t>("samples", values);
    st.converged = c.get_array<uint8_t>("converged", values);
    const uint64_t items = c.get_u64("items");
    if (items > uint64_t(values) * 4096)
        throw Error(fmt::format("checkpoint {}: {} items", c.path(), items));
    st.item_done = c.get_array<uint8_t>("item-done", items);
    st.replica_mean = c.get_array<double>("replica-mean", items);
    for (int64_t n : st.next_n)
        if (n < 0 || n > (int64_t(1) << 40))
            throw Error(fmt::format("checkpoint {}: a round of {} samples", c.path(), n));
    st.paths = c.get_u64("paths");
    st.rays = c.get_u64("rays");
    st.nonfinite = c.get_u64("nonfinite");
    st.wall_seconds = c.get_double("wall-seconds");
    st.cpu_seconds = c.get_double("cpu-seconds");
    return st;
}

std::string executable_id() {
    const std::string bytes =
        read_regular_file("/proc/self/exe", kMaxSceneFileBytes, "the running executable", false);
    return hex(hash_bytes(bytes));
}

std::string inputs_digest() {
    // Each file's contents hashed alone, the hashes sorted: independent of the order of
    // reading and of the files' names and places.
    std::vector<uint64_t> hashes;
    for (const std::string& path : input_files_read())
        hashes.push_back(hash_bytes(read_regular_file(path, kMaxSceneFileBytes, "input", false)));
    std::sort(hashes.begin(), hashes.end());
    std::string all;
    for (uint64_t h : hashes) all += hex(h);
    return fmt::format("{} files, {}", hashes.size(), hex(hash_bytes(all)));
}

}  // namespace sr
