#include "steradian/core/input_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>

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

}  // namespace sr
