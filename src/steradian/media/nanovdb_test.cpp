// pbrt-v4's "nanovdb" medium on .nvdb files written here with NanoVDB's own API: a box of
// constant density attenuates as exp(-sigma_t x optical depth) (the optical depth of
// NanoVDB's trilinear interpolation, falling to the background over the last voxel); a
// constant temperature emits Lescale x Planck's law normalised to its peak (pbrt-v4's
// BlackbodySpectrum); the majorants bound the density; every malformed file is an error
// naming the file and the MakeNamedMedium's location.
#include "steradian/media/nanovdb.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "steradian/core/error.h"
#include "steradian/media/medium.h"
#include "steradian/sampling/rng.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "support/majorant_check.h"
#include "support/nvdb_writer.h"

namespace sr {
namespace {

namespace fs = std::filesystem;
using test::nvdb_box;
using test::NvdbGridSpec;
using test::write_nvdb;

class NanoVdb : public ::testing::Test {
  protected:
    void SetUp() override {
        std::random_device rd;
        m_dir = fs::temp_directory_path() / ("sr_nvdb_test_" + std::to_string(rd()));
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    /// The media of a scene whose world is `world` (line 2 on: "WorldBegin" is line 1).
    std::vector<Medium> media(const std::string& world) const {
        SceneDesc d = parse_pbrt_string("WorldBegin\n" + world, "<test>", m_dir.string());
        return build_scene(d, BuildOptions{}).media;
    }
    /// The error message of building `world`.
    std::string error(const std::string& world) const {
        try {
            media(world);
        } catch (const Error& e) {
            return e.what();
        } catch (const std::exception& e) {
            return std::string("not an sr::Error: ") + e.what();
        }
        return "no error";
    }
    fs::path m_dir;
};

/// The transmittance along `ray` up to t_max at each wavelength, by ratio tracking (pbrt-v4's
/// estimator: at each tentative collision T *= T_maj sigma_n / (T_maj[0] sigma_maj[0]), and
/// T_maj / T_maj[0] at the end), averaged over n runs; with its standard errors.
struct Transmittance {
    SampledSpectrum mean{0}, se{0};
};
Transmittance ratio_tracking(const Medium& m, const Ray& ray, Float t_max,
                             const SampledWavelengths& lambda, int n) {
    std::array<double, kSpectrumSamples> s{}, s2{};
    for (int i = 0; i < n; ++i) {
        Pcg32 rng(uint64_t(i), 5);
        SampledSpectrum tr(1);
        SampledSpectrum end = sample_t_maj(
            m, ray, t_max, rng.next_float(), rng, lambda,
            [&](Point3, const MediumProperties& mp, SampledSpectrum sigma_maj, SampledSpectrum t_maj) {
                SampledSpectrum sigma_n = sigma_maj - mp.sigma_a - mp.sigma_s;
                tr *= t_maj * sigma_n / (t_maj[0] * sigma_maj[0]);
                return true;
            });
        tr *= end / end[0];
        for (int k = 0; k < kSpectrumSamples; ++k) {
            s[size_t(k)] += tr[k];
            s2[size_t(k)] += double(tr[k]) * tr[k];
        }
    }
    Transmittance t;
    for (int k = 0; k < kSpectrumSamples; ++k) {
        double mean = s[size_t(k)] / n;
        t.mean[k] = Float(mean);
        t.se[k] = Float(std::sqrt(std::max(0.0, s2[size_t(k)] / n - mean * mean) / (n - 1)));
    }
    return t;
}

TEST_F(NanoVdb, ConstantBoxAttenuatesAsBeerLambertPerWavelength) {
    // 8^3 voxels of density c = 2, voxel 0.25, index (0, 0, 0) at world (-1, -1, -1): the
    // bounds (active voxels [0, 7], NanoVDB's worldBBox [0, 8] in index space) are [-1, 1]^3.
    const double c = 2, h = 0.25, scale = 0.5;
    write_nvdb(path("box.nvdb"), {nvdb_box("density", 8, float(c), h, {-1, -1, -1})});
    auto ms = media(R"(MakeNamedMedium "vdb" "string type" "nanovdb" "string filename" "box.nvdb"
  "spectrum sigma_a" [ 300 0.2 900 0.8 ] "spectrum sigma_s" [ 300 0.3 900 0.3 ]
  "float scale" [ 0.5 ]
)");
    ASSERT_EQ(ms.size(), 1u);
    const Medium& m = ms[0];
    ASSERT_TRUE(std::holds_alternative<NanoVdbMedium>(m));
    EXPECT_FALSE(is_emissive(m));
    // Along x at y = z = 0 (index 4, inside): c from index 0 to 7, then linearly to the
    // background 0 at index 8: 7.5 voxels of c, i.e. an optical depth per unit sigma_t of
    // scale c h 7.5.
    const double depth = scale * c * h * 7.5;
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.37f);
    // From x = -3 through the box and beyond, a direction of length 2.
    Ray ray{Point3(-3, 0, 0), Vec3(2, 0, 0), kInfinity};
    Transmittance t = ratio_tracking(m, ray, Float(5), lambda, 20000);
    for (int k = 0; k < kSpectrumSamples; ++k) {
        double l = lambda[k];
        double sigma_t = 0.2 + 0.6 * (l - 300) / 600 + 0.3;
        double expected = std::exp(-sigma_t * depth);
        ASSERT_GT(expected, 0.1);  // a test that can fail: 0.13 to 0.39
        EXPECT_LT(t.se[k], 0.01);
        EXPECT_NEAR(t.mean[k], expected, 4.5 * t.se[k] + 1e-4)
            << "lambda " << l << " se " << t.se[k];
    }
    // Point values: c x scale x sigma inside; nothing outside the bounds.
    MediumProperties in = medium_properties(m, Point3(0.1f, -0.3f, 0.2f), lambda);
    EXPECT_NEAR(in.sigma_s[0], 0.3 * c * scale, 1e-5);
    MediumProperties out = medium_properties(m, Point3(1.2f, 0, 0), lambda);
    EXPECT_EQ(out.sigma_a[0] + out.sigma_s[0], 0);
    // ZIP-compressed, the same grid gives the same medium.
    write_nvdb(path("box_zip.nvdb"), {nvdb_box("density", 8, float(c), h, {-1, -1, -1})},
               nanovdb::io::Codec::ZIP);
    auto zm = media(R"(MakeNamedMedium "vdb" "string type" "nanovdb" "string filename" "box_zip.nvdb"
)");
    for (Point3 p : {Point3(0.1f, -0.3f, 0.2f), Point3(0.9f, 0.95f, -0.99f)})
        EXPECT_EQ(std::get<NanoVdbMedium>(zm[0]).density->sample(p),
                  std::get<NanoVdbMedium>(m).density->sample(p));
}

/// Planck's law (W sr^-1 m^-3), from the physical constants (CODATA 2018).
double planck(double lambda_nm, double t) {
    const double h = 6.62607015e-34, c = 299792458, kb = 1.380649e-23;
    double l = lambda_nm * 1e-9;
    return 2 * h * c * c / (std::pow(l, 5) * (std::exp(h * c / (l * kb * t)) - 1));
}

TEST_F(NanoVdb, ConstantTemperatureEmitsTheNormalisedBlackbodyTimesLescale) {
    // temperature grid value 25, offset ("temperaturecutoff") 5, scale 100: T = 2000 K.
    write_nvdb(path("fire.nvdb"), {nvdb_box("density", 4, 1, 1, {0, 0, 0}),
                                   nvdb_box("temperature", 4, 25, 1, {0, 0, 0})});
    auto ms = media(R"(MakeNamedMedium "fire" "string type" "nanovdb" "string filename" "fire.nvdb"
  "float Lescale" [ 3 ] "float temperaturecutoff" [ 5 ] "float temperaturescale" [ 100 ]
)");
    ASSERT_TRUE(is_emissive(ms[0]));
    const double t = 2000;
    // pbrt-v4's BlackbodySpectrum: B(lambda, T) / B(lambda_max, T), lambda_max by Wien's
    // displacement law (b = 2.897771955e-3 m K).
    const double peak = planck(2.897771955e-3 / t * 1e9, t);
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.61f);
    MediumProperties mp = medium_properties(ms[0], Point3(1.5f, 2.0f, 1.2f), lambda);
    for (int k = 0; k < kSpectrumSamples; ++k) {
        double expected = 3 * planck(lambda[k], t) / peak;
        EXPECT_NEAR(mp.le[k], expected, 2e-4 * expected) << "lambda " << lambda[k];
    }
    // At or below 100 K (here (25 - 24.5) x 100 = 50 K) nothing is emitted (pbrt-v4).
    auto cold = media(R"(MakeNamedMedium "fire" "string type" "nanovdb" "string filename" "fire.nvdb"
  "float temperatureoffset" [ 24.5 ] "float temperaturescale" [ 100 ]
)");
    EXPECT_EQ(medium_properties(cold[0], Point3(1.5f, 2.0f, 1.2f), lambda).le[0], 0);
    // "Lescale" 0: not emissive.
    auto off = media(R"(MakeNamedMedium "fire" "string type" "nanovdb" "string filename" "fire.nvdb"
  "float Lescale" [ 0 ]
)");
    EXPECT_FALSE(is_emissive(off[0]));
}

TEST_F(NanoVdb, MajorantsBoundTheDensityEverywhere) {
    // A sparse grid of varied values (a hash of the index; some voxels left at 0), voxel 0.3,
    // index 0 at world (0.4, -2, 1); 200000 random points of the bounds.
    NvdbGridSpec s;
    s.value = [](int i, int j, int k) {
        uint32_t x = uint32_t(i * 73856093) ^ uint32_t(j * 19349663) ^ uint32_t(k * 83492791);
        x = (x ^ (x >> 13)) * 0x5bd1e995u;
        return (x >> 24) % 5 == 0 ? 0.0f : float((x >> 8) % 1000) / 100;
    };
    s.lo = nanovdb::Coord(-9, -3, -20);
    s.hi = nanovdb::Coord(20, 11, 5);
    s.voxel = 0.3;
    s.origin = nanovdb::Vec3d(0.4, -2, 1);
    write_nvdb(path("noise.nvdb"), {s});
    auto ms = media(R"(MakeNamedMedium "m" "string type" "nanovdb" "string filename" "noise.nvdb"
  "spectrum sigma_a" [ 300 1 900 1 ] "spectrum sigma_s" [ 300 0 900 0 ] "float scale" [ 0.5 ]
)");
    const auto& m = std::get<NanoVdbMedium>(ms[0]);
    ASSERT_EQ(m.majorant.res, 64);
    test::MajorantCheck r = test::check_majorant(
        m.majorant, m.p0, m.p1,
        [&](Point3 p) { return std::max(0.0f, m.density->sample(p)) * m.scale; }, 200000, 3);
    EXPECT_EQ(r.violations, 0);
    EXPECT_GT(r.largest, 1);  // the grid is not empty where we looked
    // Bounds: the active voxels [lo, hi + 1] of index space in world space.
    EXPECT_NEAR(m.p0.x, 0.4 - 9 * 0.3, 1e-5);
    EXPECT_NEAR(m.p1.z, 1 + 6 * 0.3, 1e-5);
}

TEST_F(NanoVdb, TheGridNamedByGridnameIsRead) {
    write_nvdb(path("two.nvdb"),
               {nvdb_box("smoke", 4, 7, 1, {0, 0, 0}), nvdb_box("density", 4, 1, 1, {0, 0, 0})});
    auto ms = media(R"(MakeNamedMedium "m" "string type" "nanovdb" "string filename" "two.nvdb"
  "string gridname" "smoke"
)");
    EXPECT_FLOAT_EQ(std::get<NanoVdbMedium>(ms[0]).density->sample(Point3(1, 1, 1)), 7);
}

TEST_F(NanoVdb, MalformedFilesAreLocatedErrors) {
    auto make = [&](const std::string& file) {
        return "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"" + file +
               "\"\n";
    };
    auto expect = [&](const std::string& file, const std::string& what) {
        std::string e = error(make(file));
        EXPECT_NE(e.find(what), std::string::npos) << e;
        EXPECT_NE(e.find("<test>:2:1"), std::string::npos) << e;  // the MakeNamedMedium
        EXPECT_NE(e.find(file), std::string::npos) << e;
    };
    expect("missing.nvdb", "missing.nvdb");
    write_nvdb(path("smoke.nvdb"), {nvdb_box("smoke", 4, 1, 1, {0, 0, 0})});
    expect("smoke.nvdb", "no grid named \"density\"");
    // A level set is not a density.
    NvdbGridSpec ls = nvdb_box("density", 4, 1, 1, {0, 0, 0});
    ls.grid_class = nanovdb::GridClass::LevelSet;
    write_nvdb(path("ls.nvdb"), {ls});
    expect("ls.nvdb", "fog volume");
    // A grid of doubles.
    {
        nanovdb::GridBuilder<double> b(0.0);
        b.getAccessor().setValue(nanovdb::Coord(1, 2, 3), 1.0);
        nanovdb::io::writeGrid(path("double.nvdb"), b.getHandle<>(1.0, nanovdb::Vec3d(0), "density"));
    }
    expect("double.nvdb", "float grid is needed");
    // Not NanoVDB at all; empty.
    std::ofstream(path("text.nvdb")) << "hello, this is not a grid at all, but long enough";
    expect("text.nvdb", "not a NanoVDB file");
    std::ofstream(path("empty.nvdb")).flush();
    expect("empty.nvdb", "empty");
    // Truncated anywhere: in the header, the metadata, the name, the grid.
    write_nvdb(path("box.nvdb"), {nvdb_box("density", 8, 1, 1, {0, 0, 0})});
    std::string bytes;
    {
        std::ifstream f(path("box.nvdb"), std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(f), {});
    }
    for (size_t n : {size_t(10), size_t(100), size_t(16 + 176 + 3), bytes.size() / 2,
                     bytes.size() - 1}) {
        std::ofstream(path("cut.nvdb"), std::ios::binary).write(bytes.data(), std::streamsize(n));
        expect("cut.nvdb", "truncated");
    }
    // Bytes flipped in the grid's tree: an error or a valid grid, never a crash (the fuzz
    // harness fuzz/nanovdb.cpp does this at scale).
    Pcg32 rng(1, 2);
    for (int i = 0; i < 300; ++i) {
        std::string b = bytes;
        for (int k = 0; k < 4; ++k) {
            size_t at = 16 + 176 + rng.next_u32() % uint32_t(b.size() - 16 - 176);
            b[at] = char(rng.next_u32());
        }
        std::ofstream(path("flip.nvdb"), std::ios::binary).write(b.data(), std::streamsize(b.size()));
        try {
            media(make("flip.nvdb"));
        } catch (const Error&) {
        }
    }
}

// The "cloud" of a MakeNamedMedium without parameters has pbrt-v4's defaults
// (CloudMedium::Create): density 1, g 0, wispiness 1, frequency 5, sigma_a = sigma_s = 1,
// bounds [0, 1]^3, and the medium's transformation.
TEST(CloudMediumBuild, PbrtV4Defaults) {
    SceneDesc d = parse_pbrt_string(
        "WorldBegin\nTranslate 2 0 0\nMakeNamedMedium \"c\" \"string type\" \"cloud\"\n", "<test>", ".");
    auto ms = build_scene(d, BuildOptions{}).media;
    const auto& c = std::get<CloudMedium>(ms[0]);
    EXPECT_EQ(c.density, 1);
    EXPECT_EQ(c.g, 0);
    EXPECT_EQ(c.wispiness, 1);
    EXPECT_EQ(c.frequency, 5);
    EXPECT_EQ(c.p0, Point3(0, 0, 0));
    EXPECT_EQ(c.p1, Point3(1, 1, 1));
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.5f);
    EXPECT_EQ(c.sigma_a.sample(lambda)[0], 1);
    EXPECT_EQ(c.sigma_s.sample(lambda)[0], 1);
    EXPECT_EQ(c.medium_from_world.point(Point3(2.5f, 0.25f, 0.5f)), Point3(0.5f, 0.25f, 0.5f));
    EXPECT_FALSE(is_emissive(ms[0]));
}

}  // namespace
}  // namespace sr
