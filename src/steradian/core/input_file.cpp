#include "steradian/core/input_file.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

#include "steradian/core/error.h"

namespace sr {

namespace {

std::mutex g_inputs_mutex;
std::set<std::string>& inputs() {
    static std::set<std::string> s;
    return s;
}

}  // namespace

std::vector<std::string> input_files_read() {
    std::lock_guard lock(g_inputs_mutex);
    return {inputs().begin(), inputs().end()};
}

std::string regular_file_problem(const std::string& path, uint64_t limit, uint64_t* size,
                                 bool record) {
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(st)) return std::generic_category().message(ENOENT);
    if (ec) return ec.message();
    if (std::filesystem::is_directory(st)) return "it is a directory";
    if (!std::filesystem::is_regular_file(st))
        return "not a regular file (a device, FIFO or socket)";
    const uint64_t n = std::filesystem::file_size(path, ec);
    if (ec) return ec.message();
    if (n > limit)
        return fmt::format("{} bytes, more than the limit of {} bytes ({} MiB)", n, limit,
                           limit >> 20);
    if (size) *size = n;
    if (record) {
        std::lock_guard lock(g_inputs_mutex);
        inputs().insert(path);
    }
    return "";
}

uint64_t check_regular_file(const std::string& path, uint64_t limit, std::string_view what,
                            bool record) {
    uint64_t size = 0;
    if (std::string why = regular_file_problem(path, limit, &size, record); !why.empty())
        throw Error(fmt::format("cannot read {} \"{}\": {}", what, path, why));
    return size;
}

std::string read_regular_file(const std::string& path, uint64_t limit, std::string_view what,
                              bool record) {
    const uint64_t size = check_regular_file(path, limit, what, record);
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw Error(fmt::format("cannot read {} \"{}\": {}", what, path, std::strerror(errno)));
    std::string contents(size, '\0');
    const size_t got = size > 0 ? std::fread(contents.data(), 1, size, f.get()) : 0;
    if (got != size || std::ferror(f.get()))
        throw Error(fmt::format("cannot read {} \"{}\": read error after {} of {} bytes", what,
                                path, got, size));
    return contents;
}

void advise_huge_pages([[maybe_unused]] const void* p, [[maybe_unused]] uint64_t bytes) {
#if defined(MADV_HUGEPAGE)
    constexpr uint64_t kHuge = uint64_t(2) << 20;
    if (bytes < 4 * kHuge) return;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) & ~uintptr_t(kHuge - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~uintptr_t(kHuge - 1);
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

bool is_gzip(std::string_view bytes) {
    return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
           static_cast<unsigned char>(bytes[1]) == 0x8b;
}

GunzipBytes gunzip_bytes(std::string_view in, uint64_t limit) {
    auto fail = [](const std::string& why) -> void { throw Error(why); };
    if (!is_gzip(in)) fail("not gzip data (it does not start with the bytes 1f 8b)");
    // The last member's ISIZE (its size mod 2^32) is a first guess of the output size. The
    // buffer is not initialised: pages a wrong guess (a corrupt trailer) allocates in vain
    // are never touched.
    uint64_t guess = uint64_t(in.size()) * 4;
    if (in.size() >= 18) {
        const auto* t = reinterpret_cast<const unsigned char*>(in.data() + in.size() - 4);
        guess = std::max<uint64_t>(guess, uint32_t(t[0]) | uint32_t(t[1]) << 8 |
                                              uint32_t(t[2]) << 16 | uint32_t(t[3]) << 24);
    }
    // One byte more than the limit, to tell "exactly the limit" from "more".
    const uint64_t cap = limit + 1;
    GunzipBytes out;
    uint64_t room = std::max<uint64_t>(std::min<uint64_t>(guess, cap), 1);
    out.data = std::make_unique_for_overwrite<char[]>(room);

    z_stream z{};
    if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK)  // 16+: gzip wrapper only
        fail("cannot initialise zlib");
    std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, &inflateEnd);
    const auto* next_in = reinterpret_cast<const unsigned char*>(in.data());
    uint64_t left_in = in.size();
    uint64_t produced = 0;
    for (;;) {
        if (produced == room) {
            if (room >= cap) break;
            const uint64_t bigger = std::min<uint64_t>(cap, room * 2);
            auto grown = std::make_unique_for_overwrite<char[]>(bigger);
            std::memcpy(grown.get(), out.data.get(), produced);
            out.data = std::move(grown);
            room = bigger;
        }
        // zlib counts in uInt: feed and drain at most 1 GiB per call.
        const uInt in_chunk = uInt(std::min<uint64_t>(left_in, uint64_t(1) << 30));
        const uInt out_chunk = uInt(std::min<uint64_t>(room - produced, uint64_t(1) << 30));
        z.next_in = const_cast<Bytef*>(next_in);
        z.avail_in = in_chunk;
        z.next_out = reinterpret_cast<Bytef*>(out.data.get() + produced);
        z.avail_out = out_chunk;
        const int r = inflate(&z, Z_NO_FLUSH);
        next_in += in_chunk - z.avail_in;
        left_in -= in_chunk - z.avail_in;
        produced += out_chunk - z.avail_out;
        if (r == Z_STREAM_END) {
            // Another member may follow (gzip concatenates them); anything else is ignored,
            // as gzip -d does, with a warning.
            if (left_in == 0) break;
            if (!is_gzip(std::string_view(reinterpret_cast<const char*>(next_in), left_in))) {
                if (std::any_of(next_in, next_in + left_in, [](unsigned char c) { return c; }))
                    warning(SourceLoc{}, fmt::format("{} bytes of trailing garbage after "
                                                     "gzip data ignored",
                                                     left_in));
                break;
            }
            if (inflateReset(&z) != Z_OK) fail("cannot reset zlib");
            continue;
        }
        if (r == Z_DATA_ERROR)
            fail(fmt::format("corrupt gzip data ({})", z.msg ? z.msg : "invalid data"));
        if (r == Z_MEM_ERROR) fail("out of memory while decompressing");
        if (r == Z_BUF_ERROR || r == Z_OK) {
            if (left_in == 0 && z.avail_out > 0)
                fail(
                    fmt::format("truncated gzip data (the compressed stream ends after {} "
                                "decompressed bytes)",
                                produced));
            continue;  // more output room or more input needed
        }
        fail(fmt::format("zlib error {} while decompressing", r));
    }
    if (produced > limit)
        fail(fmt::format("decompresses to more than the limit of {} bytes ({} MiB)", limit,
                         limit >> 20));
    out.size = produced;
    return out;
}

std::string gunzip(std::string_view in, uint64_t limit) {
    return std::string(gunzip_bytes(in, limit).view());
}

std::string gzip_compress(std::string_view data, int level) {
    z_stream z{};
    if (deflateInit2(&z, level, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw Error("gzip_compress: cannot initialise zlib");
    std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, &deflateEnd);
    std::string out(deflateBound(&z, uLong(data.size())) + 64, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z.avail_in = uInt(data.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = uInt(out.size());
    if (data.size() > UINT_MAX / 2 || deflate(&z, Z_FINISH) != Z_STREAM_END)
        throw Error("gzip_compress: deflate failed");
    out.resize(z.total_out);
    return out;
}

std::string read_input_file(const std::string& path, uint64_t limit, std::string_view what,
                            bool* was_gzip) {
    std::string raw = read_regular_file(path, limit, what);
    const bool gz = is_gzip(raw);
    if (was_gzip) *was_gzip = gz;
    if (!gz) return raw;
    try {
        return gunzip(raw, limit);
    } catch (const Error& e) {
        throw Error(fmt::format("cannot read {} \"{}\": {}", what, path, e.what()));
    }
}

}  // namespace sr
