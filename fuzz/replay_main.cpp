// steradian_fuzz_replay: runs every file of fuzz/regressions/<harness>/ (and any other
// directories given as DIR, laid out the same way) through the harness of that name, in
// the normal build (without libFuzzer). A reader bug shows as an abort, a sanitizer report
// in the asan build, or a ctest timeout.
//   steradian_fuzz_replay [DIR...]      (default: fuzz/regressions of the source tree)
//   steradian_fuzz_replay --list        (the harness names)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_target.h"

namespace sr::fuzz {

namespace {
std::map<std::string, TargetFn>& targets() {
    static std::map<std::string, TargetFn> t;
    return t;
}
}  // namespace

bool register_target(const char* name, TargetFn fn) {
    targets()[name] = fn;
    return true;
}

}  // namespace sr::fuzz

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    using sr::fuzz::targets;
    sr::set_warnings_quiet(true);
    std::vector<std::string> dirs(argv + 1, argv + argc);
    if (dirs.size() == 1 && dirs[0] == "--list") {
        for (const auto& [name, fn] : targets()) std::printf("%s\n", name.c_str());
        return 0;
    }
    if (dirs.empty()) dirs.push_back(STERADIAN_SOURCE_DIR "/fuzz/regressions");
    int files = 0, problems = 0;
    for (const std::string& dir : dirs) {
        if (!fs::is_directory(dir)) {
            std::fprintf(stderr, "steradian_fuzz_replay: %s is not a directory\n", dir.c_str());
            return 2;
        }
        std::vector<fs::path> subdirs;
        for (const auto& e : fs::directory_iterator(dir)) subdirs.push_back(e.path());
        std::sort(subdirs.begin(), subdirs.end());
        for (const fs::path& sub : subdirs) {
            if (!fs::is_directory(sub)) continue;
            auto it = targets().find(sub.filename().string());
            if (it == targets().end()) {
                // A misnamed folder would silently replay nothing.
                std::fprintf(stderr, "steradian_fuzz_replay: %s names no harness\n",
                             sub.string().c_str());
                ++problems;
                continue;
            }
            std::vector<fs::path> inputs;
            for (const auto& e : fs::directory_iterator(sub))
                if (e.is_regular_file()) inputs.push_back(e.path());
            std::sort(inputs.begin(), inputs.end());
            for (const fs::path& in : inputs) {
                std::ifstream f(in, std::ios::binary);
                std::string bytes((std::istreambuf_iterator<char>(f)),
                                  std::istreambuf_iterator<char>());
                std::fprintf(stderr, "%s %s\n", it->first.c_str(), in.string().c_str());
                it->second(bytes);
                ++files;
            }
        }
    }
    std::printf("steradian_fuzz_replay: %d inputs replayed without a crash\n", files);
    return problems ? 1 : 0;
}
