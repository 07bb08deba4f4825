#include "steradian/core/input_file.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <set>
#include <thread>
#include <utility>

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

namespace {

/// The last member's ISIZE (RFC 1952 2.3.1: its uncompressed size mod 2^32), or 0 when the
/// data are too short to have a trailer.
uint64_t gzip_trailer_size(std::string_view in) {
    if (in.size() < 18) return 0;
    const auto* t = reinterpret_cast<const unsigned char*>(in.data() + in.size() - 4);
    return uint32_t(t[0]) | uint32_t(t[1]) << 8 | uint32_t(t[2]) << 16 | uint32_t(t[3]) << 24;
}

/// zlib over all the members of gzip data, a piece of output at a time, into wherever the
/// caller points it. Throws sr::Error on corrupt or truncated data.
class GzipInflater {
  public:
    explicit GzipInflater(std::string_view in)
        : m_next(reinterpret_cast<const unsigned char*>(in.data())), m_left(in.size()) {
        if (!is_gzip(in)) throw Error("not gzip data (it does not start with the bytes 1f 8b)");
        if (inflateInit2(&m_z, 16 + MAX_WBITS) != Z_OK)  // 16+: gzip wrapper only
            throw Error("cannot initialise zlib");
    }
    ~GzipInflater() { inflateEnd(&m_z); }
    GzipInflater(const GzipInflater&) = delete;
    GzipInflater& operator=(const GzipInflater&) = delete;

    struct Step {
        uint64_t bytes = 0;  ///< written to dst
        bool end = false;    ///< the last member has ended
    };
    /// Writes at most n > 0 bytes to dst.
    Step step(char* dst, uint64_t n) {
        // zlib counts in uInt: feed and drain at most 1 GiB per call.
        const uInt in_chunk = uInt(std::min<uint64_t>(m_left, uint64_t(1) << 30));
        const uInt out_chunk = uInt(std::min<uint64_t>(n, uint64_t(1) << 30));
        m_z.next_in = const_cast<Bytef*>(m_next);
        m_z.avail_in = in_chunk;
        m_z.next_out = reinterpret_cast<Bytef*>(dst);
        m_z.avail_out = out_chunk;
        const int r = inflate(&m_z, Z_NO_FLUSH);
        m_next += in_chunk - m_z.avail_in;
        m_left -= in_chunk - m_z.avail_in;
        Step s;
        s.bytes = out_chunk - m_z.avail_out;
        m_produced += s.bytes;
        if (r == Z_STREAM_END) {
            // Another member may follow (gzip concatenates them); anything else is ignored,
            // as gzip -d does (garbage() says how much, for a warning).
            s.end = m_left == 0 ||
                    !is_gzip(std::string_view(reinterpret_cast<const char*>(m_next), m_left));
            if (s.end) {
                if (std::any_of(m_next, m_next + m_left, [](unsigned char c) { return c; }))
                    m_garbage = m_left;
            } else if (inflateReset(&m_z) != Z_OK) {
                throw Error("cannot reset zlib");
            }
            return s;
        }
        if (r == Z_DATA_ERROR)
            throw Error(fmt::format("corrupt gzip data ({})", m_z.msg ? m_z.msg : "invalid data"));
        if (r == Z_MEM_ERROR) throw Error("out of memory while decompressing");
        if (r != Z_BUF_ERROR && r != Z_OK)
            throw Error(fmt::format("zlib error {} while decompressing", r));
        if (m_left == 0 && m_z.avail_out > 0)
            throw Error(fmt::format("truncated gzip data (the compressed stream ends after {} "
                                    "decompressed bytes)",
                                    m_produced));
        return s;  // more output room or more input needed
    }
    /// Bytes of non-zero trailing garbage after the last member.
    uint64_t garbage() const { return m_garbage; }

  private:
    z_stream m_z{};
    const unsigned char* m_next;
    uint64_t m_left;
    uint64_t m_produced = 0;
    uint64_t m_garbage = 0;
};

void warn_garbage(uint64_t bytes) {
    if (bytes > 0)
        warning(SourceLoc{}, fmt::format("{} bytes of trailing garbage after gzip data ignored",
                                         bytes));
}

}  // namespace

GunzipBytes gunzip_bytes(std::string_view in, uint64_t limit) {
    GzipInflater z(in);
    // The last member's ISIZE is a first guess of the output size. The buffer is not
    // initialised: pages a wrong guess (a corrupt trailer) allocates in vain are never
    // touched.
    const uint64_t guess = std::max<uint64_t>(uint64_t(in.size()) * 4, gzip_trailer_size(in));
    // One byte more than the limit, to tell "exactly the limit" from "more".
    const uint64_t cap = limit + 1;
    GunzipBytes out;
    uint64_t room = std::max<uint64_t>(std::min<uint64_t>(guess, cap), 1);
    out.data = std::make_unique_for_overwrite<char[]>(room);
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
        const GzipInflater::Step s = z.step(out.data.get() + produced, room - produced);
        produced += s.bytes;
        if (s.end) break;
    }
    if (produced > limit)
        throw Error(fmt::format("decompresses to more than the limit of {} bytes ({} MiB)",
                                limit, limit >> 20));
    warn_garbage(z.garbage());
    out.size = produced;
    return out;
}

namespace {

/// The inflater's output pieces: 4 MiB, so that a reader waits at most one piece behind.
constexpr uint64_t kGunzipPiece = uint64_t(4) << 20;

/// The concurrent inflater's output: anonymous memory mapped on its own where the system
/// can (Linux), so that a piece the reader is done with can be moved, pages and all, to
/// where the inflater writes next (mremap): its pages are not zeroed by the kernel again.
/// Zeroing fresh pages cost 0.08-0.7 s per 250 MB on the project's 2-core machine (Nov
/// 2026, depending on the other load), on the inflater's thread, which is the critical
/// path of a large .ply.gz load. Elsewhere an ordinary allocation.
class GunzipBuffer {
  public:
    explicit GunzipBuffer(uint64_t size) {
#if defined(__linux__)
        // Aligned to 2 MiB (transparent huge pages); whole pieces.
        constexpr uint64_t kAlign = uint64_t(2) << 20;
        m_mapped = (size + kGunzipPiece - 1) / kGunzipPiece * kGunzipPiece + kAlign;
        void* p = ::mmap(nullptr, m_mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                         -1, 0);
        if (p != MAP_FAILED) {
            m_map = p;
            m_data = reinterpret_cast<char*>((reinterpret_cast<uintptr_t>(p) + kAlign - 1) &
                                             ~uintptr_t(kAlign - 1));
            advise_huge_pages(m_data, m_mapped - kAlign);
            return;
        }
        m_mapped = 0;
#endif
        m_owned = std::make_unique_for_overwrite<char[]>(size);
        m_data = m_owned.get();
    }
    ~GunzipBuffer() {
#if defined(__linux__)
        if (m_map) ::munmap(m_map, m_mapped);
#endif
    }
    GunzipBuffer(const GunzipBuffer&) = delete;
    GunzipBuffer& operator=(const GunzipBuffer&) = delete;
    char* data() const { return m_data; }
    bool movable() const { return m_map != nullptr; }
    /// Moves the pages of piece `from` to piece `to` (whose old pages are dropped); piece
    /// `from` is left unmapped. False if the system refused (nothing changed then).
    bool move_piece([[maybe_unused]] uint64_t from, [[maybe_unused]] uint64_t to) {
#if defined(__linux__)
        if (!m_map) return false;
        void* r = ::mremap(m_data + from * kGunzipPiece, kGunzipPiece, kGunzipPiece,
                           MREMAP_MAYMOVE | MREMAP_FIXED, m_data + to * kGunzipPiece);
        return r != MAP_FAILED;
#else
        return false;
#endif
    }

  private:
    char* m_data = nullptr;
    std::unique_ptr<char[]> m_owned;
    void* m_map = nullptr;
    uint64_t m_mapped = 0;
};

}  // namespace

struct ConcurrentGunzip::Shared {
    explicit Shared(uint64_t size) : buffer(size) {}
    GunzipBuffer buffer;
    std::mutex m;
    std::condition_variable cv;
    uint64_t ready = 0;
    enum class Status { running, done, failed, mismatch } status = Status::running;
    std::string failure;
    uint64_t garbage = 0;
    std::atomic<bool> cancel{false};
    uint64_t released = 0;         ///< pieces before this one are the reader's no more
    std::vector<uint64_t> spare;  ///< released pieces whose pages are not yet reused
    uint64_t moved = 0;            ///< pieces whose pages were reused (tests)
};

std::unique_ptr<ConcurrentGunzip> ConcurrentGunzip::start(std::string_view compressed,
                                                          uint64_t limit, uint64_t min_size) {
    const uint64_t size = gzip_trailer_size(compressed);
    if (!is_gzip(compressed) || size < std::max<uint64_t>(min_size, 1) || size > limit)
        return nullptr;
    return std::unique_ptr<ConcurrentGunzip>(new ConcurrentGunzip(compressed, size));
}

ConcurrentGunzip::ConcurrentGunzip(std::string_view compressed, uint64_t size)
    : m_size(size), m_shared(std::make_unique<Shared>(size)) {
    m_data = m_shared->buffer.data();
    m_thread = std::thread([this, compressed] {
        Shared& sh = *m_shared;
        auto finish = [&](Shared::Status st, uint64_t produced) {
            std::lock_guard lock(sh.m);
            sh.ready = produced;
            sh.status = st;
            sh.cv.notify_all();
        };
        // At the start of a whole piece, the pages of one the reader released (if any).
        auto reuse_pages = [&](uint64_t produced) {
            if (!sh.buffer.movable() || produced % kGunzipPiece != 0 ||
                m_size - produced < kGunzipPiece)
                return;
            uint64_t from = 0;
            {
                std::lock_guard lock(sh.m);
                if (sh.spare.empty()) return;
                from = sh.spare.back();
                sh.spare.pop_back();
            }
            if (sh.buffer.move_piece(from, produced / kGunzipPiece)) {
                std::lock_guard lock(sh.m);
                ++sh.moved;
            }
        };
        uint64_t produced = 0;
        try {
            GzipInflater z(compressed);
            for (;;) {
                if (sh.cancel.load(std::memory_order_relaxed))
                    return finish(Shared::Status::failed, produced);
                if (produced == m_size) {
                    // Full: the data must end here. One byte more means they are larger
                    // than the trailer said (several members, or a size over 4 GiB).
                    char extra = 0;
                    const GzipInflater::Step s = z.step(&extra, 1);
                    if (s.bytes > 0) return finish(Shared::Status::mismatch, produced);
                    if (s.end) break;
                    continue;
                }
                reuse_pages(produced);
                const uint64_t piece_end =
                    std::min(m_size, (produced / kGunzipPiece + 1) * kGunzipPiece);
                const GzipInflater::Step s = z.step(m_data + produced, piece_end - produced);
                produced += s.bytes;
                if (s.end) {
                    if (produced != m_size) return finish(Shared::Status::mismatch, produced);
                    break;
                }
                std::lock_guard lock(sh.m);
                sh.ready = produced;
                sh.cv.notify_all();
            }
            sh.garbage = z.garbage();
            finish(Shared::Status::done, produced);
        } catch (const Error& e) {
            {
                std::lock_guard lock(sh.m);
                sh.failure = e.what();
            }
            finish(Shared::Status::failed, produced);
        } catch (const std::bad_alloc&) {
            {
                std::lock_guard lock(sh.m);
                sh.failure = "out of memory while decompressing";
            }
            finish(Shared::Status::failed, produced);
        } catch (const std::exception& e) {
            {
                std::lock_guard lock(sh.m);
                sh.failure = fmt::format("decompression failed ({})", e.what());
            }
            finish(Shared::Status::failed, produced);
        }
    });
}

void ConcurrentGunzip::release(uint64_t upto) {
    Shared& sh = *m_shared;
    std::lock_guard lock(sh.m);
    for (const uint64_t end = std::min(upto, sh.ready) / kGunzipPiece; sh.released < end;
         ++sh.released)
        sh.spare.push_back(sh.released);
}

uint64_t ConcurrentGunzip::pieces_reused() const {
    std::lock_guard lock(m_shared->m);
    return m_shared->moved;
}

ConcurrentGunzip::~ConcurrentGunzip() {
    m_shared->cancel = true;
    if (m_thread.joinable()) m_thread.join();
}

void ConcurrentGunzip::wait(uint64_t n) {
    Shared& sh = *m_shared;
    n = std::min(n, m_size);
    std::unique_lock lock(sh.m);
    sh.cv.wait(lock, [&] { return sh.ready >= n || sh.status != Shared::Status::running; });
    if (sh.ready >= n) return;
    if (sh.status == Shared::Status::mismatch) throw SizeMismatch{};
    throw Error(sh.failure.empty() ? std::string("decompression stopped") : sh.failure);
}

void ConcurrentGunzip::finish() {
    wait(m_size);
    if (m_thread.joinable()) m_thread.join();
    // Full but not yet known to end where the trailer said: the status decides.
    Shared& sh = *m_shared;
    if (sh.status == Shared::Status::mismatch) throw SizeMismatch{};
    if (sh.status == Shared::Status::failed) throw Error(sh.failure);
    warn_garbage(std::exchange(sh.garbage, 0));
}

ConcurrentGunzip::Outcome ConcurrentGunzip::outcome(std::string* why) {
    if (m_thread.joinable()) m_thread.join();
    Shared& sh = *m_shared;
    if (sh.status == Shared::Status::mismatch) return Outcome::mismatch;
    if (sh.status == Shared::Status::failed) {
        if (why) *why = sh.failure;
        return Outcome::failed;
    }
    return Outcome::ok;
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
