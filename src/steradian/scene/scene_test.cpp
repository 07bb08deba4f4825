#include "steradian/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "steradian/core/error_list.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

// SurfaceHit is compared byte for byte below: it must have no padding.
static_assert(sizeof(SurfaceHit) == 48 * 4, "SurfaceHit: 48 four-byte fields, no padding");

// One shape of each kind the accelerator fills differently: a curved triangle mesh with vertex
// normals (its hits have normal derivatives), a flat mesh without, a sphere, a disk, an
// instanced sphere and a curve. The rays run along -z towards them.
const char* kScene = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [4] "integer yresolution" [4]
WorldBegin
Material "diffuse"
Shape "trianglemesh" "integer indices" [0 1 2]
    "point3 P" [-10 -1 0  -8 -1 0  -9 1 0.5]
    "normal N" [-0.3 0 1  0.3 0 1  0 0.4 1]
Shape "trianglemesh" "integer indices" [0 1 2] "point3 P" [-6 -1 0  -4 -1 0  -5 1 0]
Shape "sphere" "float radius" 1
AttributeBegin
  Translate 5 0 0
  Shape "disk" "float radius" 1
AttributeEnd
ObjectBegin "ball"
  Shape "sphere" "float radius" 0.8
ObjectEnd
AttributeBegin
  Translate 9 0 0
  ObjectInstance "ball"
AttributeEnd
Shape "curve" "string type" "cylinder" "point3 P" [13 -1 0  13 -0.3 0  13 0.3 0  13 1 0]
    "float width" 0.5
)";

Ray ray_at(Float x) { return Ray{Point3(x, 0.1f, 10), Vec3(0, 0, -1), kInfinity}; }

// Scene::intersect writes every field of the record, whatever it held: a record first filled
// with NaN bytes, or with a previous hit that had normal derivatives, ends byte for byte as a
// fresh one does. (The path integrator keeps one record per path and relies on this.)
TEST(SceneIntersect, WritesEveryFieldOfTheHit) {
    Scene s = build_scene(parse_pbrt_string(kScene, "<test>"));
    const std::vector<Float> xs = {-9, -5, 0, 5, 9, 13};
    SurfaceHit curved;
    ASSERT_TRUE(s.intersect(ray_at(-9), curved));
    ASSERT_NE(length_squared(curved.dndu) + length_squared(curved.dndv), 0)
        << "the curved mesh should give normal derivatives";
    for (Float x : xs) {
        SurfaceHit fresh;
        ASSERT_TRUE(s.intersect(ray_at(x), fresh)) << x;
        SurfaceHit garbage;
        std::memset(static_cast<void*>(&garbage), 0xff, sizeof garbage);
        ASSERT_TRUE(s.intersect(ray_at(x), garbage)) << x;
        EXPECT_EQ(std::memcmp(&fresh, &garbage, sizeof fresh), 0) << "after NaN bytes, x = " << x;
        SurfaceHit reused = curved;
        ASSERT_TRUE(s.intersect(ray_at(x), reused)) << x;
        EXPECT_EQ(std::memcmp(&fresh, &reused, sizeof fresh), 0) << "after a curved hit, x = " << x;
    }
}

// A packet of rays finds what the rays find one by one: the same hits, filled byte for byte
// alike, and the same misses; inactive lanes are neither traced nor written. The rays run
// from above the scene down to every kind of shape (meshes, sphere, disk, instance) and past
// them. (Where two surfaces are hit at exactly the same distance, which one a ray reports
// depends on Embree's traversal order, and a packet's order differs from a single ray's; no
// two surfaces here coincide.)
TEST(SceneIntersect, PacketFindsWhatSingleRaysFind) {
    Scene s = build_scene(parse_pbrt_string(kScene, "<test>"));
    constexpr int kN = Scene::kRayPacket;
    for (int round = 0; round < 8; ++round) {
        Ray rays[kN];
        // At the five shapes and between and beyond them, moved a little each round.
        const Float targets[8] = {-9, -5, 0, 5, 9, -12, 12, 2.5f};
        static_assert(kN <= 8);
        for (int i = 0; i < kN; ++i) {
            Float x = targets[i] + 0.05f * Float(round);
            Point3 o(x * 0.5f, 0.02f * Float(round), 10);
            rays[i] = Ray{o, normalize(Point3(x, 0.1f, 0) - o), kInfinity};
        }
        const unsigned active = round == 0 ? (1u << kN) - 1 : 0x5du ^ (round * 37u);
        SurfaceHit packet[kN];
        std::memset(static_cast<void*>(packet), 0xab, sizeof packet);
        const unsigned found = s.intersect_packet(rays, active & ((1u << kN) - 1), packet);
        int hits = 0;
        for (int i = 0; i < kN; ++i) {
            SurfaceHit single;
            bool on = (active >> i) & 1;
            bool hit = s.intersect(rays[i], single);
            if (!on) {
                EXPECT_FALSE((found >> i) & 1) << "inactive lane " << i;
                unsigned char untouched[sizeof(SurfaceHit)];
                std::memset(untouched, 0xab, sizeof untouched);
                EXPECT_EQ(std::memcmp(&packet[i], untouched, sizeof untouched), 0) << i;
                continue;
            }
            ASSERT_EQ(bool((found >> i) & 1), hit) << "round " << round << " ray " << i;
            if (hit) {
                ++hits;
                EXPECT_EQ(std::memcmp(&packet[i], &single, sizeof single), 0)
                    << "round " << round << " ray " << i << " shape " << single.shape;
            }
        }
        if (round == 0) {
            EXPECT_EQ(hits, 5) << "the full packet should hit all five shapes";
        }
    }
}

// A packet of shadow rays finds blocked what occluded() finds blocked, for every kind of
// shape (meshes, sphere, disk, instance), for rays short of a shape and past it, in full and
// partial packets; inactive lanes are never reported blocked.
TEST(SceneIntersect, OccludedPacketAgreesWithOccluded) {
    Scene s = build_scene(parse_pbrt_string(kScene, "<test>"));
    constexpr int kN = Scene::kRayPacket;
    const Float targets[8] = {-9, -5, 0, 5, 9, -12, 12, 2.5f};
    for (int round = 0; round < 16; ++round) {
        Ray rays[kN];
        for (int i = 0; i < kN; ++i) {
            Float x = targets[i] + 0.05f * Float(round);
            Point3 o(x * 0.5f, 0.02f * Float(round), 10);
            Vec3 d = normalize(Point3(x, 0.1f, 0) - o);
            // Odd rounds stop 2 units above z = 0, short of every shape but the instanced
            // sphere's top (z up to 0.8) and the curved mesh's (z up to 0.5): free.
            Float t_max = (round & 1) ? (10 - 2) / -d.z : kInfinity;
            rays[i] = Ray{o, d, t_max};
        }
        const unsigned active = round < 2 ? (1u << kN) - 1 : (0xb7u * unsigned(round)) & 0xffu;
        const unsigned blocked = s.occluded_packet(rays, active);
        for (int i = 0; i < kN; ++i) {
            if (!((active >> i) & 1)) {
                EXPECT_FALSE((blocked >> i) & 1) << "inactive lane " << i;
                continue;
            }
            EXPECT_EQ(bool((blocked >> i) & 1), s.occluded(rays[i]))
                << "round " << round << " ray " << i;
        }
        // The geometry's own answer for the full packets: the five rays aimed at the five
        // shapes are blocked and the three aimed past them are not; the short ones all free.
        if (round == 0) {
            EXPECT_EQ(blocked, 0x1fu);
        }
        if (round == 1) {
            EXPECT_EQ(blocked, 0u);
        }
    }
}

/// The message of the error build_scene() throws for `text`, or "" if none.
std::string build_error(const std::string& text) {
    set_warnings_quiet(true);
    std::string msg;
    try {
        build_scene(parse_pbrt_string(text, "t.pbrt"));
    } catch (const Error& e) {
        msg = e.what();
    }
    set_warnings_quiet(false);
    return msg;
}

size_t count_of(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
    return n;
}

TEST(SceneBuild, UnsupportedThingsAreAllReportedInFileOrder) {
    // One of each kind the builder goes on past, each with a stand-in or left out; what
    // refers to them (the material's texture, the shape's material) must not add errors.
    const std::string msg = build_error(R"(Camera "spherical"
Sampler "halton" "integer pixelsamples" 4 "string bogus" "x"
WorldBegin
Texture "t" "spectrum" "ptex"
Texture "c" "float" "checkerboard" "integer dimension" 3
MakeNamedMaterial "m" "string type" "diffuse" "texture reflectance" "t" "float sigma" 2
NamedMaterial "m"
Shape "heightfield"
Shape "sphere"
LightSource "spot" "float conedelta" 3
AreaLightSource "diffuse" "string filename" "e.exr"
Shape "disk"
)");
    EXPECT_EQ(msg.rfind("the scene cannot be rendered: 8 unsupported features or unknown "
                        "parameters",
                        0),
              0u)
        << msg;
    size_t at = 0;
    for (const char* want :
         {"\nt.pbrt:1:1: Camera \"spherical\" is not supported yet",
          "\nt.pbrt:2:43: unused parameter \"string bogus\" for Sampler \"halton\"",
          "\nt.pbrt:4:1: Texture \"ptex\" is not supported yet",
          "\nt.pbrt:5:36: Texture \"c\": 3D checkerboards are not supported yet",
          "\nt.pbrt:6:73: unused parameter \"float sigma\"",
          "\nt.pbrt:8:1: shape type \"heightfield\" is not supported yet",
          "\nt.pbrt:10:20: LightSource \"spot\": \"conedelta\" is not a pbrt-v4 parameter",
          "\nt.pbrt:11:1: image-textured area lights"}) {
        const size_t p = msg.find(want, at);
        EXPECT_NE(p, std::string::npos) << "missing or out of order: " << want << "\n" << msg;
        if (p != std::string::npos) at = p;
    }
    EXPECT_EQ(count_of(msg, "\nt.pbrt:"), 8u) << msg;
}

TEST(SceneBuild, OneUnsupportedThingIsReportedAsBeforeAndTheListStopsAt20) {
    EXPECT_EQ(build_error("WorldBegin\nShape \"heightfield\"\n"),
              "t.pbrt:2:1: shape type \"heightfield\" is not supported yet (see docs/pbrt-support.md)");
    std::string text = "WorldBegin\n";
    for (int i = 0; i < 30; ++i) text += "Shape \"heightfield\"\n";
    const std::string msg = build_error(text);
    EXPECT_NE(msg.find("20 unsupported features or unknown parameters (stopped at the first 20)"),
              std::string::npos)
        << msg;
    EXPECT_EQ(count_of(msg, "\nt.pbrt:"), 20u);
    // An error of another kind after unsupported ones ends the list.
    const std::string mixed =
        build_error("WorldBegin\nShape \"heightfield\"\nShape \"sphere\" \"float radius\" -1\n");
    EXPECT_NE(mixed.find("1 unsupported features or unknown parameters (see "
                         "docs/pbrt-support.md), then an error:\nt.pbrt:2:1: shape type "
                         "\"heightfield\""),
              std::string::npos)
        << mixed;
    EXPECT_NE(mixed.find("\nt.pbrt:3:1: Shape \"sphere\": radius must be positive"),
              std::string::npos)
        << mixed;
}

/// The ErrorList build_scene() throws for `desc` with `max_unsupported`, if it throws one.
std::optional<ErrorList> build_error_list(const SceneDesc& desc, size_t max_unsupported) {
    BuildOptions o;
    o.max_unsupported = max_unsupported;
    try {
        build_scene(desc, o);
    } catch (const ErrorList& e) {
        return e;
    }
    return std::nullopt;
}

TEST(SceneBuild, TheListIsAnErrorListOfLocatedEntriesAndItsLimitIsAnOption) {
    // steradian check reads the entries, not the message: each keeps its location, the
    // unsupported ones are marked, and an error that stops the build comes last.
    std::string text = "WorldBegin\n";
    for (int i = 0; i < 30; ++i) text += "Shape \"heightfield\"\n";
    text += "Shape \"sphere\" \"float radius\" -1\n";
    set_warnings_quiet(true);
    const SceneDesc desc = parse_pbrt_string(text, "t.pbrt");
    set_warnings_quiet(false);
    const std::optional<ErrorList> all = build_error_list(desc, 1000);
    ASSERT_TRUE(all);
    ASSERT_EQ(all->entries().size(), 31u);
    EXPECT_FALSE(all->truncated());
    for (int i = 0; i < 30; ++i) {
        EXPECT_EQ(all->entries()[i].loc.line, 2 + i);
        EXPECT_EQ(all->entries()[i].loc.column, 1);
        EXPECT_TRUE(all->entries()[i].unsupported);
        EXPECT_EQ(all->entries()[i].message,
                  "shape type \"heightfield\" is not supported yet (see docs/pbrt-support.md)");
    }
    EXPECT_EQ(all->entries()[30].loc.line, 32);
    EXPECT_FALSE(all->entries()[30].unsupported);
    const std::optional<ErrorList> five = build_error_list(desc, 5);
    ASSERT_TRUE(five);
    EXPECT_EQ(five->entries().size(), 5u);
    EXPECT_TRUE(five->truncated());
    // One problem is thrown as it was, and error_entries() still gives it as one entry.
    try {
        build_scene(parse_pbrt_string("WorldBegin\nShape \"heightfield\"\n", "t.pbrt"));
        ADD_FAILURE() << "the scene built";
    } catch (const Error& e) {
        EXPECT_EQ(dynamic_cast<const ErrorList*>(&e), nullptr);
        const std::vector<ErrorEntry> one = error_entries(e);
        ASSERT_EQ(one.size(), 1u);
        EXPECT_EQ(one[0].loc.line, 2);
        EXPECT_TRUE(one[0].unsupported);
    }
}

TEST(Warnings, ACaptureCollectsEveryWarningWithItsLocationInsteadOfPrintingIt) {
    std::vector<ErrorEntry> got;
    {
        WarningCapture capture;
        // Motion blur is not supported: a warning at each ActiveTransform, the same message
        // twice, both kept (the printed warnings show each distinct one once).
        parse_pbrt_string("ActiveTransform EndTime\nActiveTransform All\n"
                          "ActiveTransform EndTime\nWorldBegin\n",
                          "w.pbrt");
        got = capture.take();
        EXPECT_TRUE(capture.take().empty());
    }
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].loc.file, "w.pbrt");
    EXPECT_EQ(got[0].loc.line, 1);
    EXPECT_EQ(got[1].loc.line, 3);
    EXPECT_EQ(got[0].message, got[1].message);
    EXPECT_NE(got[0].message.find("motion blur"), std::string::npos) << got[0].message;
    EXPECT_FALSE(got[0].unsupported);
}

TEST(SceneBuild, SpotConeFalloffIsConedeltaangle) {
    // pbrt-v4 (lights.cpp, SpotLight::Create): cosFalloffEnd = cos(coneangle),
    // cosFalloffStart = cos(coneangle - conedeltaangle); defaults 30 and 5 degrees.
    set_warnings_quiet(true);
    const Scene s = build_scene(parse_pbrt_string(R"(WorldBegin
LightSource "spot" "float coneangle" 40 "float conedeltaangle" 15
LightSource "spot"
Shape "sphere"
)",
                                                  "t.pbrt"));
    set_warnings_quiet(false);
    ASSERT_EQ(s.lights.size(), 2u);
    const auto& a = std::get<SpotLight>(s.lights[0]);
    const auto& b = std::get<SpotLight>(s.lights[1]);
    const double deg = 3.14159265358979323846 / 180;
    EXPECT_NEAR(a.cos_falloff_end, std::cos(40 * deg), 1e-6);
    EXPECT_NEAR(a.cos_falloff_start, std::cos(25 * deg), 1e-6);
    EXPECT_NEAR(b.cos_falloff_end, std::cos(30 * deg), 1e-6);
    EXPECT_NEAR(b.cos_falloff_start, std::cos(25 * deg), 1e-6);
}

TEST(SceneBuild, FilmScaleIsReadAsPbrtUpgradeReadsIt) {
    // pbrt-v4's --upgrade (parser.cpp, FormattingParserTarget::Film) rewrites pbrt-v3's
    // "float scale" s as "float iso" 100 s; the imaging ratio is exposure time * iso / 100.
    auto ratio = [](const std::string& film) {
        set_warnings_quiet(true);
        const Scene s = build_scene(parse_pbrt_string(
            "Film \"rgb\" " + film + "\nWorldBegin\nShape \"sphere\"\n", "t.pbrt"));
        set_warnings_quiet(false);
        return s.film.imaging_ratio;
    };
    EXPECT_FLOAT_EQ(ratio("\"float scale\" 2.5"), ratio("\"float iso\" 250"));
    EXPECT_FLOAT_EQ(ratio("\"float scale\" 2.5"), 2.5f);
    EXPECT_FLOAT_EQ(ratio("\"float scale\" 2 \"float iso\" 50"), 1.0f);
}

}  // namespace
}  // namespace sr
