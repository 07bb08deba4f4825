#include "steradian/core/output_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "steradian/core/error.h"

namespace sr {

namespace {

namespace fs = std::filesystem;

fs::path directory_of(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    return dir.empty() ? fs::path(".") : dir;
}

void make_directory(const std::string& path) {
    std::error_code ec;
    fs::path dir = directory_of(path);
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw Error(fmt::format("{}: cannot create the directory {}: {}", path, dir.string(),
                                ec ? ec.message() : "a file of that name is in the way"));
}

/// fsync of a written file, so that a full or failing disk shows here and not after the
/// rename has replaced the old file.
void sync_file(const std::string& tmp, const std::string& path) {
    int fd = ::open(tmp.c_str(), O_RDONLY);
    if (fd < 0 || ::fsync(fd) != 0) {
        int e = errno;
        if (fd >= 0) ::close(fd);
        throw Error(fmt::format("{}: cannot write: {}", path, std::strerror(e)));
    }
    if (::close(fd) != 0)
        throw Error(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
}

/// The temporary files of `path` that a writer killed mid-write (SIGKILL, power loss) left
/// behind: ".<stem>.tmp-<pid>-<n><ext>" in its directory, of a process that no longer runs.
void remove_stale_temporaries(const std::string& path) {
    const fs::path p(path);
    const std::string prefix = "." + p.stem().string() + ".tmp-";
    std::error_code ec;
    for (fs::directory_iterator it(directory_of(path), ec), end; !ec && it != end;
         it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        const char* digits = name.c_str() + prefix.size();
        char* stop = nullptr;
        const long pid = std::strtol(digits, &stop, 10);
        if (stop == digits || *stop != '-' || pid <= 0) continue;
        if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) {
            std::error_code ignored;
            fs::remove(it->path(), ignored);
        }
    }
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(const std::string& tmp_path)>& write) {
    make_directory(path);
    remove_stale_temporaries(path);
    static std::atomic<unsigned> counter{0};
    const fs::path p(path);
    // Hidden, unique per process and call, same directory (rename is atomic only within one
    // file system) and same extension.
    const std::string tmp =
        (directory_of(path) / fmt::format(".{}.tmp-{}-{}{}", p.stem().string(), ::getpid(),
                                          counter.fetch_add(1), p.extension().string()))
            .string();
    try {
        write(tmp);
        sync_file(tmp, path);
        std::error_code ec;
        fs::rename(tmp, path, ec);
        if (ec) throw Error(fmt::format("{}: cannot replace the file: {}", path, ec.message()));
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
}

void write_text_file(const std::string& path, const std::string& text) {
    write_file_atomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        if (!f) throw Error(fmt::format("{}: cannot open for writing", path));
        f.write(text.data(), std::streamsize(text.size()));
        f.flush();
        f.close();
        if (!f) throw Error(fmt::format("{}: cannot write (disk full?)", path));
    });
}

void check_output_path(const std::string& path, const std::string& what) {
    if (path.empty()) throw Error(fmt::format("empty file name for {}", what));
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw Error(fmt::format("{} ({}): is a directory", path, what));
    make_directory(path);
    if (::access(directory_of(path).c_str(), W_OK) != 0)
        throw Error(fmt::format("{} ({}): the directory {} is not writable: {}", path, what,
                                directory_of(path).string(), std::strerror(errno)));
}

}  // namespace sr
