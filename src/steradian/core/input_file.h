#pragma once
/// Reading input files whole, safely: only regular files are read (not devices, FIFOs or
/// directories: `Include "/dev/zero"` read until memory ran out), and only up to a size
/// limit that the error names, checked before anything is allocated.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace sr {

/// Size limits of the inputs read whole: scene text and meshes (a 10-million-triangle
/// binary PLY is about 200 MB), and the small text formats (IES, EULUMDAT, spectra).
inline constexpr uint64_t kMaxSceneFileBytes = uint64_t(4) << 30;
inline constexpr uint64_t kMaxSmallFileBytes = uint64_t(64) << 20;

/// Why `path` cannot be read as a regular file of at most `limit` bytes (strerror(ENOENT),
/// "not a regular file ...", "N bytes, more than the limit of ..."), or "" if it can; its size
/// goes to *size. A path that can be read is recorded as an input (input_files_read())
/// unless `record` is false (files that are not part of a scene: checkpoints).
std::string regular_file_problem(const std::string& path, uint64_t limit,
                                 uint64_t* size = nullptr, bool record = true);

/// Throws sr::Error("cannot read <what> \"<path>\": <why>") unless `path` is a regular file
/// of at most `limit` bytes; returns its size.
uint64_t check_regular_file(const std::string& path, uint64_t limit, std::string_view what,
                            bool record = true);

/// The whole contents of `path`, after check_regular_file(). Throws sr::Error as it does,
/// or on a read error.
std::string read_regular_file(const std::string& path, uint64_t limit, std::string_view what,
                              bool record = true);

/// True if `bytes` starts with the gzip magic number 1f 8b (RFC 1952, section 2.3.1). No
/// scene text or PLY file can start so (a PLY file starts with "ply").
bool is_gzip(std::string_view bytes);

/// The decompressed contents of gzip data (RFC 1952; several members are concatenated, as
/// gzip does). The output grows as it is produced and never beyond `limit` bytes: more is
/// an sr::Error naming the limit (a "gzip bomb" cannot exhaust memory). Truncated or corrupt
/// data (a bad header, deflate stream, CRC-32 or length) is an sr::Error too, whose message
/// says why ("truncated gzip data ..."): the caller names the file.
std::string gunzip(std::string_view compressed, uint64_t limit);

/// Asks the kernel for transparent huge pages (madvise MADV_HUGEPAGE; nothing where the
/// system has none) for the whole 2 MiB pages within [p, p + bytes) of a large buffer that
/// has not been written yet. Its page faults then cost a fraction: 0.03-0.04 CPU-s for
/// 250 MB against 0.16 with 4 KiB pages, measured on the project's 2-core machine (Nov
/// 2026). The PLY reader's arrays use it; gunzip_bytes' buffer does not (the 10M-triangle
/// .ply.gz load measured no better with it). Buffers under 8 MiB are left alone.
void advise_huge_pages(const void* p, uint64_t bytes);

/// gunzip() into a buffer of its own, without the copy into a std::string (large meshes).
struct GunzipBytes {
    std::unique_ptr<char[]> data;
    uint64_t size = 0;
    std::string_view view() const { return {data.get(), size_t(size)}; }
};
GunzipBytes gunzip_bytes(std::string_view compressed, uint64_t limit);

/// gzip data decompressed on a thread of its own while a reader consumes the front of the
/// output: a 250 MB mesh is parsed as it is inflated instead of after. The output buffer has
/// the size the last member's trailer states (ISIZE); data that turn out larger or smaller
/// (several members, over 4 GiB) make wait()/finish() throw SizeMismatch, and the caller
/// falls back to gunzip_bytes(). Errors are gunzip()'s, with the same messages.
class ConcurrentGunzip {
  public:
    struct SizeMismatch {};
    /// Starts when `compressed` (which must outlive the object) is gzip data whose trailer
    /// promises between `min_size` and `limit` bytes; null otherwise.
    static std::unique_ptr<ConcurrentGunzip> start(std::string_view compressed, uint64_t limit,
                                                   uint64_t min_size);
    ~ConcurrentGunzip();  ///< stops the inflater and joins it
    ConcurrentGunzip(const ConcurrentGunzip&) = delete;
    ConcurrentGunzip& operator=(const ConcurrentGunzip&) = delete;

    /// The promised extent; only its first bytes that wait() has returned for are valid.
    std::string_view view() const { return {m_data, size_t(m_size)}; }
    /// Blocks until the first min(n, size) bytes are there. Throws sr::Error if the data are
    /// corrupt or truncated before them, SizeMismatch if they are not the promised size.
    void wait(uint64_t n);
    /// Waits for the end and checks it: throws as wait(), warns about trailing garbage.
    void finish();
    /// After the reader's own error: waits for the inflater to end and says how it ended
    /// (its error first, as the serial path would have reported it).
    enum class Outcome { ok, failed, mismatch };
    Outcome outcome(std::string* why);
    /// The reader will never again read the bytes before `upto`: the inflater may reuse
    /// their memory for later bytes (where the system lets it move pages), so those bytes
    /// of view() become invalid, even unmapped.
    void release(uint64_t upto);
    /// How many pieces of memory were reused so far (for tests).
    uint64_t pieces_reused() const;

  private:
    ConcurrentGunzip(std::string_view compressed, uint64_t size);
    struct Shared;
    char* m_data = nullptr;
    uint64_t m_size;
    std::unique_ptr<Shared> m_shared;
    std::thread m_thread;
};

/// `data` compressed as one gzip member (zlib's deflate at `level` 1-9): what `gzip -c`
/// makes. For tests and benchmarks that make .gz inputs.
std::string gzip_compress(std::string_view data, int level = 6);

/// read_regular_file(), then gunzip() if the contents start with the gzip magic number (the
/// decompressed size has the same `limit`); *was_gzip tells which. The file is recorded by
/// its own (compressed) path.
std::string read_input_file(const std::string& path, uint64_t limit, std::string_view what,
                            bool* was_gzip = nullptr);

/// Every file accepted by regular_file_problem() (so by check_regular_file() and
/// read_regular_file(): every scene, mesh, luminaire, spectrum and image file a scene
/// loads) since the start of the process, sorted and without repeats. A checkpoint hashes
/// their contents, so that it is never resumed on a scene that has changed.
std::vector<std::string> input_files_read();

}  // namespace sr
