#pragma once
// Helpers shared by the tests that compare integrators on whole images (bidir_test.cpp,
// mlt_test.cpp, sppm_test.cpp): scene text edited in place, seeded renders, block means and
// their standard errors over independent replicas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/render_util.h"

namespace sr::test {

inline std::string read_text(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/// Replaces the first occurrence of `from` in s (a test failure if there is none).
inline void replace_once(std::string& s, const std::string& from, const std::string& to) {
    const size_t i = s.find(from);
    ASSERT_NE(i, std::string::npos) << from;
    s.replace(i, from.size(), to);
}

/// The bundled Cornell box at res x res with the given Integrator directive, with independent
/// samples (the replicas' spread is then an honest standard error of each block) unless
/// `independent` is false (the scene's own zsobol sampler).
inline std::string cornell_box(const std::string& integrator, int res, bool independent = true) {
    std::string s = read_text(std::string(STERADIAN_SOURCE_DIR) + "/scenes/cornell-box.pbrt");
    replace_once(s, "\"integer xresolution\" [ 512 ] \"integer yresolution\" [ 512 ]",
                 "\"integer xresolution\" [ " + std::to_string(res) +
                     " ] \"integer yresolution\" [ " + std::to_string(res) + " ]");
    replace_once(s, "Integrator \"path\" \"integer maxdepth\" [ 16 ]", integrator);
    if (independent) replace_once(s, "Sampler \"zsobol\"", "Sampler \"independent\"");
    return s;
}

/// The glass-and-metal Cornell box (tests/data/reference/cornell-box-glass-metal) at
/// res x res with independent samples and `integrator` in place of its Integrator line.
inline std::string glass_metal_box(const std::string& integrator, int res) {
    std::string s = read_text(std::string(STERADIAN_SOURCE_DIR) +
                              "/tests/data/reference/cornell-box-glass-metal/scene.pbrt");
    replace_once(s, "\"integer xresolution\" [ 512 ] \"integer yresolution\" [ 512 ]",
                 "\"integer xresolution\" [ " + std::to_string(res) +
                     " ] \"integer yresolution\" [ " + std::to_string(res) + " ]");
    replace_once(s, "Sampler \"zsobol\"", "Sampler \"independent\"");
    const size_t i = s.find("Integrator \"path\"");
    if (i == std::string::npos) {
        ADD_FAILURE() << "the glass-and-metal box has no path Integrator line";
        return s;
    }
    return s.substr(0, i) + integrator + s.substr(s.find('\n', i));
}

/// A render of scene text with the seed `seed` (files named in it resolve against scenes/).
inline Rendered render_seeded(const std::string& text, int spp, uint64_t seed, int threads = 2,
                              RenderOptions ro = {},
                              const std::string& base = std::string(STERADIAN_SOURCE_DIR) +
                                                        "/scenes") {
    ro.seed = seed;
    return render_string(text, threads, spp, base, ro);
}

/// Means of the b x b-pixel blocks of a res x res image.
inline std::vector<double> block_means(const std::vector<double>& y, int res, int b) {
    const int n = res / b;
    std::vector<double> m(size_t(n * n), 0);
    for (int yy = 0; yy < res; ++yy)
        for (int x = 0; x < res; ++x) m[size_t((yy / b) * n + x / b)] += y[size_t(yy * res + x)];
    for (double& v : m) v /= double(b * b);
    return m;
}

/// Mean and standard error of each entry over replicas.
struct BlockStats {
    std::vector<double> mean, se;
};
inline BlockStats stats_of(const std::vector<std::vector<double>>& reps) {
    const size_t n = reps[0].size(), r = reps.size();
    BlockStats s;
    s.mean.assign(n, 0);
    s.se.assign(n, 0);
    for (const auto& v : reps)
        for (size_t i = 0; i < n; ++i) s.mean[i] += v[i] / double(r);
    for (const auto& v : reps)
        for (size_t i = 0; i < n; ++i) s.se[i] += (v[i] - s.mean[i]) * (v[i] - s.mean[i]);
    for (size_t i = 0; i < n; ++i) s.se[i] = std::sqrt(s.se[i] / double(r - 1) / double(r));
    return s;
}

}  // namespace sr::test
