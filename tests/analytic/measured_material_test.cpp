// Material "measured" end to end, with a stand-in .bsdf file (tests/support/
// measured_standin.h, a GGX conductor of F0 = 1 at every wavelength): in a white furnace a
// convex object's radiance is its directional albedo, at most 1 (energy conservation; the
// single-scattering GGX loses energy, so it is darker than the furnace but reflects most of
// it); the image is the same on 1 and 2 threads; and a missing "filename", a file that does
// not exist and a corrupt file are errors at the material's line naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/measured_standin.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4.5;

/// The stand-in written once to a temporary directory.
const std::string& standin_path() {
    static const std::string path = [] {
        auto dir = std::filesystem::temp_directory_path() / "steradian_measured_test";
        std::filesystem::create_directories(dir);
        StandinSpec s;
        s.f0 = {1, 1, 1, 1};
        std::string p = (dir / "white_ggx.bsdf").string();
        std::ofstream(p, std::ios::binary) << standin_bytes(s);
        return p;
    }();
    return path;
}

std::string measured(const std::string& file) {
    return fmt::format("Material \"measured\" \"string filename\" \"{}\"", file);
}

TEST(MeasuredMaterial, FurnaceRadianceIsAtMostOne) {
    Rendered r = render_string(furnace_scene(measured(standin_path()), 64, 1000));
    MeanSe m = mean_se(region(r, 4, 4, 12, 12));  // the sphere covers the centre
    std::printf("measured (GGX 0.3, F0 = 1): %.5f +- %.5f (<= 1)\n", m.mean, m.se);
    EXPECT_LE(m.mean, 1 + kZ * m.se);
    EXPECT_GT(m.mean, 0.8);
    EXPECT_EQ(r.stats.nonfinite, 0u);
}

TEST(MeasuredMaterial, ImageDoesNotDependOnThreadCount) {
    std::string scene = furnace_scene(measured(standin_path()), 16, 5);
    Rendered a = render_string(scene, 1), b = render_string(scene, 2);
    ASSERT_EQ(a.y.size(), b.y.size());
    for (size_t i = 0; i < a.y.size(); ++i) ASSERT_EQ(a.y[i], b.y[i]) << "pixel " << i;
}

/// The error message of building the furnace scene with `material` (line 10 of the scene).
std::string build_error(const std::string& material) {
    try {
        render_string(furnace_scene(material, 1, 1));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(MeasuredMaterial, BadFilesAreErrorsAtTheMaterialsLine) {
    std::string msg = build_error(R"(Material "measured")");
    EXPECT_NE(msg.find("<test>:10:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("\"filename\" must name a .bsdf file"), std::string::npos) << msg;

    msg = build_error(measured("/nonexistent/x.bsdf"));
    EXPECT_NE(msg.find("<test>:10:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("/nonexistent/x.bsdf"), std::string::npos) << msg;

    auto bad = std::filesystem::temp_directory_path() / "steradian_measured_test" / "bad.bsdf";
    std::filesystem::create_directories(bad.parent_path());
    std::ofstream(bad, std::ios::binary) << standin_bytes(StandinSpec{}).substr(0, 500);
    msg = build_error(measured(bad.string()));
    EXPECT_NE(msg.find("<test>:10:"), std::string::npos) << msg;
    // The headers fit in 500 bytes, the tables do not.
    EXPECT_NE(msg.find(bad.string() + ": field \""), std::string::npos) << msg;
    EXPECT_NE(msg.find("past the end of the file (500 bytes)"), std::string::npos) << msg;
}

}  // namespace
}  // namespace sr::test
