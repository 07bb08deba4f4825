#include "steradian/scene/pbrt/parser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "steradian/core/error_list.h"
#include "steradian/core/input_file.h"

namespace sr {
namespace {

namespace fs = std::filesystem;

class PbrtParser : public ::testing::Test {
protected:
    void SetUp() override { set_warnings_quiet(true); }
    void TearDown() override { set_warnings_quiet(false); }
};

SceneDesc parse(const std::string& text) { return parse_pbrt_string(text, "test.pbrt"); }

void expect_near(const Matrix4& a, const Matrix4& b, double eps = 1e-12) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            EXPECT_NEAR(a.m[size_t(i)][size_t(j)], b.m[size_t(i)][size_t(j)], eps)
                << "element " << i << "," << j;
}

void expect_near(Vec3d a, Vec3d b, double eps = 1e-12) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

/// Parses `text` as test.pbrt and expects an sr::Error containing `what` at line:column.
void expect_error(const std::string& text, const std::string& what, int line, int column,
                  const std::string& file = "test.pbrt") {
    SCOPED_TRACE(text);
    try {
        parse_pbrt_string(text, "test.pbrt");
        ADD_FAILURE() << "expected an error containing: " << what;
    } catch (const Error& e) {
        EXPECT_NE(e.message().find(what), std::string::npos) << "message: " << e.message();
        EXPECT_EQ(e.loc().file, file) << e.what();
        EXPECT_EQ(e.loc().line, line) << e.what();
        EXPECT_EQ(e.loc().column, column) << e.what();
    }
}

/// A scratch directory removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        std::random_device rd;
        path = fs::temp_directory_path() / ("sr_pbrt_test_" + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string write(const std::string& rel, const std::string& text) const {
        fs::path p = path / rel;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

// ---- well-formed input ------------------------------------------------------------------

TEST_F(PbrtParser, MinimalScene) {
    SceneDesc s = parse("WorldBegin\n");
    EXPECT_TRUE(s.shapes.empty());
    EXPECT_EQ(s.camera.type, "");
    EXPECT_EQ(s.base_dir, ".");
}

TEST_F(PbrtParser, OptionsBlock) {
    SceneDesc s = parse(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" [ 400 ] "integer yresolution" 300 "string filename" "out.exr"
Sampler "zsobol" "integer pixelsamples" 16
Integrator "path" "integer maxdepth" 5 "bool regularize" true
PixelFilter "gaussian"
Accelerator "bvh"
ColorSpace "srgb"
Option "disable-pixel-jitter" true
Option "seed" 7
Option "seed" 9
WorldBegin
)");
    EXPECT_EQ(s.camera.type, "perspective");
    EXPECT_EQ(s.camera.loc.line, 3);
    EXPECT_EQ(s.camera.loc.column, 1);
    EXPECT_EQ(s.camera.params.get_float("fov", 90), 45.0f);
    Transform look = Transform::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
    expect_near(s.camera.camera_from_world.matrix(), look.matrix());
    expect_near(s.camera.world_from_camera.matrix(), look.inverse_matrix());
    EXPECT_EQ(s.film.type, "rgb");
    EXPECT_EQ(s.film.params.get_int("xresolution", 0), 400);
    EXPECT_EQ(s.film.params.get_int("yresolution", 0), 300);
    EXPECT_EQ(s.film.params.get_string("filename", ""), "out.exr");
    EXPECT_EQ(s.sampler.type, "zsobol");
    EXPECT_EQ(s.integrator.type, "path");
    EXPECT_TRUE(s.integrator.params.get_bool("regularize", false));
    EXPECT_EQ(s.filter.type, "gaussian");
    EXPECT_EQ(s.accelerator.type, "bvh");
    ASSERT_EQ(s.color_spaces.size(), 1u);
    EXPECT_EQ(s.color_spaces[0].type, "srgb");
    EXPECT_TRUE(s.options.get_bool("disablepixeljitter", false));
    EXPECT_EQ(s.options.get_int("seed", 0), 9);  // a later Option replaces an earlier one
}

TEST_F(PbrtParser, TransformCompositionMatchesHandComputedMatrices) {
    SceneDesc s = parse(R"(WorldBegin
Translate 1 2 3
Scale 2 2 2
Rotate 90 0 0 1
Shape "sphere"
Identity
ConcatTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]
Translate 1 0 0
Shape "sphere"
Transform [ 2 0 0 0  0 3 0 0  0 0 4 0  0 0 0 1 ]
Shape "sphere"
)");
    ASSERT_EQ(s.shapes.size(), 3u);
    // T(1,2,3) * S(2) * Rz(90): x -> 2y + t, y -> -2x + t.
    Matrix4 expected = Matrix4::from_rows({0, -2, 0, 1,  //
                                           2, 0, 0, 2,   //
                                           0, 0, 2, 3,   //
                                           0, 0, 0, 1});
    expect_near(s.shapes[0].world_from_object.matrix(), expected);
    expect_near(s.shapes[0].world_from_object.point(Vec3d(1, 0, 0)), {1, 4, 3});
    // The 16 values are given column by column: translation is values 13-15.
    expect_near(s.shapes[1].world_from_object.matrix(),
                Transform::translate({6, 6, 7}).matrix());
    expect_near(s.shapes[2].world_from_object.matrix(), Transform::scale({2, 3, 4}).matrix());
    expect_near(s.shapes[2].world_from_object.inverse_matrix(),
                Transform::scale({0.5, 1.0 / 3.0, 0.25}).matrix());
}

TEST_F(PbrtParser, WorldBeginResetsTransformAndCameraSpaceIsNamed) {
    SceneDesc s = parse(R"(Scale -1 1 1
LookAt 1 2 3  0 0 0  0 0 1
Camera "perspective"
WorldBegin
Shape "sphere"
AttributeBegin
  CoordSysTransform "camera"
  Shape "disk"
AttributeEnd
Translate 0 0 1
CoordSysTransform "world"
Shape "sphere"
)");
    ASSERT_EQ(s.shapes.size(), 3u);
    Transform cam_from_world =
        Transform::scale({-1, 1, 1}) * Transform::look_at({1, 2, 3}, {0, 0, 0}, {0, 0, 1});
    expect_near(s.camera.camera_from_world.matrix(), cam_from_world.matrix());
    EXPECT_TRUE(s.shapes[0].world_from_object.is_identity());
    expect_near(s.shapes[1].world_from_object.matrix(), cam_from_world.inverse_matrix());
    EXPECT_TRUE(s.shapes[2].world_from_object.is_identity());
}

TEST_F(PbrtParser, NamedCoordinateSystemsAreGlobal) {
    SceneDesc s = parse(R"(WorldBegin
AttributeBegin
  Translate 0 5 0
  CoordinateSystem "up5"
AttributeEnd
Shape "sphere"
CoordSysTransform "up5"
Shape "sphere"
CoordSysTransform "nonexistent"
Shape "sphere"
)");
    ASSERT_EQ(s.shapes.size(), 3u);
    EXPECT_TRUE(s.shapes[0].world_from_object.is_identity());
    expect_near(s.shapes[1].world_from_object.matrix(),
                Transform::translate({0, 5, 0}).matrix());
    // An unknown name only warns (as pbrt-v4) and leaves the CTM alone.
    expect_near(s.shapes[2].world_from_object.matrix(),
                Transform::translate({0, 5, 0}).matrix());
}

TEST_F(PbrtParser, AttributeBlocksScopeTheGraphicsState) {
    SceneDesc s = parse(R"(WorldBegin
Material "diffuse"
AttributeBegin
  Translate 1 0 0
  ReverseOrientation
  Material "conductor"
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
  Shape "sphere"
  AttributeBegin
    ReverseOrientation
    Shape "sphere"
  AttributeEnd
AttributeEnd
Shape "sphere"
TransformBegin
  Translate 0 2 0
  Material "dielectric"
TransformEnd
Shape "sphere"
)");
    ASSERT_EQ(s.shapes.size(), 4u);
    ASSERT_EQ(s.materials.size(), 3u);
    const ShapeDesc& a = s.shapes[0];
    EXPECT_TRUE(a.reverse_orientation);
    EXPECT_EQ(a.material.index, 1);
    EXPECT_EQ(a.area_light, 0);
    expect_near(a.world_from_object.matrix(), Transform::translate({1, 0, 0}).matrix());
    EXPECT_FALSE(s.shapes[1].reverse_orientation);  // toggled twice
    EXPECT_EQ(s.shapes[1].area_light, 0);
    const ShapeDesc& c = s.shapes[2];
    EXPECT_FALSE(c.reverse_orientation);
    EXPECT_EQ(c.material.index, 0);
    EXPECT_EQ(c.material.loc.line, 2);
    EXPECT_EQ(c.area_light, -1);
    EXPECT_TRUE(c.world_from_object.is_identity());
    // TransformBegin/End behave like AttributeBegin/End in pbrt-v4 (material restored too).
    EXPECT_TRUE(s.shapes[3].world_from_object.is_identity());
    EXPECT_EQ(s.shapes[3].material.index, 0);
    ASSERT_EQ(s.area_lights.size(), 1u);
    EXPECT_EQ(s.area_lights[0].type, "diffuse");
}

TEST_F(PbrtParser, MaterialsNamedAndAnonymous) {
    SceneDesc s = parse(R"(WorldBegin
Shape "sphere"
NamedMaterial "gold"
Shape "sphere"
MakeNamedMaterial "gold" "string type" "conductor" "float roughness" 0.1
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "sphere"
Material ""
Material "interface"
)");
    ASSERT_EQ(s.shapes.size(), 3u);
    EXPECT_EQ(s.shapes[0].material.index, -1);  // pbrt-v4's default material
    EXPECT_EQ(s.shapes[0].material.name, "");
    EXPECT_EQ(s.shapes[1].material.index, -1);
    EXPECT_EQ(s.shapes[1].material.name, "gold");  // defined later: resolved by the builder
    EXPECT_EQ(s.shapes[1].material.loc.line, 3);
    ASSERT_EQ(s.materials.size(), 4u);
    const MaterialDesc& gold = s.materials[size_t(s.named_materials.at("gold"))];
    EXPECT_EQ(gold.name, "gold");
    EXPECT_EQ(gold.type, "conductor");
    EXPECT_EQ(gold.params.find("type"), nullptr);  // consumed by the reader
    EXPECT_EQ(gold.params.get_float("roughness", 0), 0.1f);
    EXPECT_EQ(s.shapes[2].material.index, 1);
    EXPECT_EQ(s.materials[1].name, "");
    EXPECT_NE(s.materials[1].params.find_spectrum("reflectance"), nullptr);
    EXPECT_EQ(s.materials[2].type, "");
    EXPECT_EQ(s.materials[3].type, "interface");
}

TEST_F(PbrtParser, TexturesHaveSeparateNameSpacesAndTransforms) {
    SceneDesc s = parse(R"(WorldBegin
Scale 2 2 2
Texture "checks" "spectrum" "checkerboard" "float uscale" 4 "rgb tex1" [1 0 0]
Texture "checks" "float" "imagemap" "string filename" "a.png"
)");
    ASSERT_EQ(s.spectrum_textures.size(), 1u);
    ASSERT_EQ(s.float_textures.size(), 1u);
    const TextureDesc& t = s.spectrum_textures[0];
    EXPECT_EQ(t.name, "checks");
    EXPECT_EQ(t.value_type, "spectrum");
    EXPECT_EQ(t.type, "checkerboard");
    EXPECT_EQ(t.loc.line, 3);
    expect_near(t.world_from_texture.matrix(), Transform::scale({2, 2, 2}).matrix());
    EXPECT_EQ(s.float_textures[0].type, "imagemap");
    EXPECT_EQ(s.float_textures[0].value_type, "float");
}

TEST_F(PbrtParser, LightsRecordTheirTransform) {
    SceneDesc s = parse(R"(WorldBegin
Translate 0 10 0
LightSource "point" "rgb I" [ 1 1 1 ] "blackbody L" 5500
LightSource "infinite" "spectrum L" "stdillum-D65"
)");
    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].type, "point");
    expect_near(s.lights[0].world_from_light.point(Vec3d(0, 0, 0)), {0, 10, 0});
    const Param* l = s.lights[1].params.find_spectrum("L");
    ASSERT_NE(l, nullptr);
    EXPECT_EQ(l->strings, std::vector<std::string>{"stdillum-D65"});
}

TEST_F(PbrtParser, ObjectInstancingTransforms) {
    // pbrt-v4: instanced shapes keep the full CTM of their Shape directive; the instance
    // adds the CTM of ObjectInstance in front (world = CTM_use * CTM_shape).
    SceneDesc s = parse(R"(WorldBegin
ObjectInstance "early"
Translate 1 0 0
ObjectBegin "obj"
  Translate 0 2 0
  Material "conductor"
  Shape "sphere"
ObjectEnd
Shape "sphere"
Translate 0 0 5
ObjectInstance "obj"
ObjectBegin "early"
ObjectEnd
)");
    ASSERT_EQ(s.shapes.size(), 1u);
    expect_near(s.shapes[0].world_from_object.matrix(),
                Transform::translate({1, 0, 0}).matrix());
    EXPECT_EQ(s.shapes[0].material.index, -1);  // Material inside the object is scoped
    ASSERT_EQ(s.instances.size(), 2u);
    const InstanceDefinition& def = s.instances.at("obj");
    EXPECT_EQ(def.name, "obj");
    EXPECT_EQ(def.loc.line, 4);
    ASSERT_EQ(def.shapes.size(), 1u);
    expect_near(def.shapes[0].world_from_object.matrix(),
                Transform::translate({1, 2, 0}).matrix());
    EXPECT_EQ(def.shapes[0].material.index, 0);
    EXPECT_TRUE(s.instances.at("early").shapes.empty());
    ASSERT_EQ(s.instance_uses.size(), 2u);
    EXPECT_EQ(s.instance_uses[0].name, "early");  // use before definition is fine
    EXPECT_TRUE(s.instance_uses[0].world_from_instance.is_identity());
    const InstanceUse& use = s.instance_uses[1];
    EXPECT_EQ(use.name, "obj");
    EXPECT_EQ(use.loc.line, 11);
    expect_near(use.world_from_instance.matrix(), Transform::translate({1, 0, 5}).matrix());
    Transform world = use.world_from_instance * def.shapes[0].world_from_object;
    expect_near(world.point(Vec3d(0, 0, 0)), {2, 2, 5});
}

TEST_F(PbrtParser, AreaLightsAreNotInstanced) {
    SceneDesc s = parse(R"(WorldBegin
AreaLightSource "diffuse"
ObjectBegin "lamp"
  Shape "sphere"
ObjectEnd
Shape "sphere"
)");
    EXPECT_EQ(s.instances.at("lamp").shapes[0].area_light, -1);
    EXPECT_EQ(s.shapes[0].area_light, 0);
}

TEST_F(PbrtParser, ParameterTypesAndSynonyms) {
    SceneDesc s = parse(R"(WorldBegin
Shape "trianglemesh"
  "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
  "integer indices" [ 0 1 2 ]
  "normal N" [ 0 0 1  0 0 1  0 0 1 ]
  "point2 uv" [ 0 0 1 0 0 1 ]
  "vector3 S" [ 1 0 0 1 0 0 1 0 0 ]
  "float alpha" 1
  "texture tex" "checks"
  "bool b1" false "bool b2" "true" "bool bs" [ true false ]
  "string names" [ "a" "b" ]
  "spectrum sp" [ 300 .5 800 .5 ]
  "spectrum named" [ "metal-Cu-eta" ]
  "blackbody bb" 6500
  "point pt" [ 1 2 3 ] "vector v" [ 1 2 3 ] "normal3 n3" [ 0 1 0 ] "color c" [ .1 .2 .3 ]
  "vector2 v2" [ 1 2 ]
  "float empty" [ ]
)");
    const ParamSet& p = s.shapes[0].params;
    EXPECT_EQ(p.get_point3s("P").size(), 3u);
    EXPECT_EQ(p.get_ints("indices"), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(p.get_normals("N").size(), 3u);
    EXPECT_EQ(p.get_point2s("uv").size(), 3u);
    EXPECT_EQ(p.find("S")->type, ParamType::Vector3);
    EXPECT_EQ(*p.find_texture("tex"), "checks");
    EXPECT_FALSE(p.get_bool("b1", true));
    EXPECT_TRUE(p.get_bool("b2", false));
    EXPECT_EQ(p.find("bs")->bools, (std::vector<uint8_t>{1, 0}));
    EXPECT_EQ(p.get_strings("names"), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(p.find_spectrum("sp")->numbers.size(), 4u);
    EXPECT_EQ(p.find_spectrum("named")->strings[0], "metal-Cu-eta");
    EXPECT_EQ(p.find_spectrum("bb")->numbers, std::vector<double>{6500});
    EXPECT_EQ(p.find("pt")->type, ParamType::Point3);
    EXPECT_EQ(p.find("v")->type, ParamType::Vector3);
    EXPECT_EQ(p.find("n3")->type, ParamType::Normal3);
    EXPECT_EQ(p.find("c")->type, ParamType::Rgb);
    EXPECT_EQ(p.find("v2")->type, ParamType::Vector2);
    EXPECT_TRUE(p.get_floats("empty").empty());
    EXPECT_EQ(p.find("P")->loc.line, 3);
    EXPECT_EQ(p.find("P")->loc.column, 3);
}

TEST_F(PbrtParser, NumbersAreParsedExactly) {
    SceneDesc s = parse("WorldBegin Shape \"x\" \"float f\" [ 1e-3 -2.5E2 +.25 7 ]");
    EXPECT_EQ(s.shapes[0].params.find("f")->numbers, (std::vector<double>{1e-3, -250, 0.25, 7}));
}

TEST_F(PbrtParser, AttributeDirectiveSetsDefaults) {
    SceneDesc s = parse(R"(WorldBegin
AttributeBegin
  Attribute "shape" "float radius" 2 "float zmax" 0.5
  Attribute "shape" "float radius" 3
  Attribute "light" "float scale" 10
  Attribute "material" "string type" "diffuse"
  Shape "sphere"
  Shape "sphere" "float radius" 4
  LightSource "point"
  MakeNamedMaterial "m"
AttributeEnd
Shape "sphere"
)");
    ASSERT_EQ(s.shapes.size(), 3u);
    EXPECT_EQ(s.shapes[0].params.get_float("radius", 1), 3.0f);  // later Attribute wins
    EXPECT_EQ(s.shapes[1].params.get_float("radius", 1), 4.0f);  // entity's own wins
    // Attribute defaults may go unused (as in pbrt-v4): zmax was never read.
    EXPECT_NO_THROW(s.shapes[0].params.check_unused("shape"));
    EXPECT_TRUE(s.shapes[2].params.empty());  // scoped by AttributeEnd
    EXPECT_EQ(s.lights[0].params.get_float("scale", 1), 10.0f);
    EXPECT_EQ(s.materials[0].type, "diffuse");
}

TEST_F(PbrtParser, MediaAndMediumInterfacesAreRecorded) {
    SceneDesc s = parse(R"(Translate 1 2 3
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [1 1 1]
MediumInterface "" "fog"
Camera "perspective"
WorldBegin
AttributeBegin
MediumInterface "fog"
Shape "sphere"
MediumInterface "fog" ""
Shape "sphere"
AttributeEnd
Shape "sphere"
)");
    ASSERT_EQ(s.media.size(), 1u);
    EXPECT_EQ(s.media[0].name, "fog");
    EXPECT_EQ(s.media[0].type, "homogeneous");
    EXPECT_EQ(s.media[0].world_from_medium.point(Point3(0, 0, 0)), Point3(1, 2, 3));
    EXPECT_EQ(s.camera.medium, "fog");  // the outside medium at Camera
    ASSERT_EQ(s.shapes.size(), 3u);
    // One name: both sides (pbrt-v4).
    EXPECT_EQ(s.shapes[0].media.inside, "fog");
    EXPECT_EQ(s.shapes[0].media.outside, "fog");
    EXPECT_EQ(s.shapes[1].media.inside, "fog");
    EXPECT_EQ(s.shapes[1].media.outside, "");
    // AttributeEnd restores the interface in effect before it ("" "fog", from the options).
    EXPECT_EQ(s.shapes[2].media.inside, "");
    EXPECT_EQ(s.shapes[2].media.outside, "fog");
}

TEST_F(PbrtParser, MediumErrorsAreLocated) {
    expect_error(R"(WorldBegin
MakeNamedMedium "fog" "rgb sigma_a" [1 1 1]
)",
                 "missing \"string type\"", 2, 1);
    expect_error(R"(WorldBegin
MakeNamedMedium "fog" "string type" "homogeneous"
MakeNamedMedium "fog" "string type" "homogeneous"
)",
                 "redefined", 3, 1);
}

TEST_F(PbrtParser, MotionBlurKeepsTheStartTransform) {
    SceneDesc s = parse(R"(TransformTimes 0 1
WorldBegin
ActiveTransform EndTime
Translate 5 0 0
ActiveTransform StartTime
Translate 0 1 0
ActiveTransform All
Shape "sphere"
WorldEnd
)");
    expect_near(s.shapes[0].world_from_object.matrix(), Transform::translate({0, 1, 0}).matrix());
}

TEST_F(PbrtParser, IncludeIsTextualAndResolvesAgainstTheSceneDirectory) {
    TempDir dir;
    dir.write("geometry/parts.pbrt",
              "Shape \"sphere\"\nMaterial \"conductor\"\nInclude \"geometry/more.pbrt\"\n");
    dir.write("geometry/more.pbrt", "Include \"leaf.pbrt\"\n");  // relative to its own dir
    dir.write("geometry/leaf.pbrt", "\n  Shape \"disk\"\n");
    std::string main = dir.write("scene.pbrt", R"(WorldBegin
AttributeBegin
  Translate 1 0 0
  Include "geometry/parts.pbrt"
  Shape "sphere"
AttributeEnd
)");
    SceneDesc s = parse_pbrt_file(main);
    EXPECT_EQ(s.base_dir, dir.path.string());
    ASSERT_EQ(s.shapes.size(), 3u);
    EXPECT_EQ(s.shapes[0].loc.file, (dir.path / "geometry/parts.pbrt").string());
    EXPECT_EQ(s.shapes[0].loc.line, 1);
    expect_near(s.shapes[0].world_from_object.matrix(), Transform::translate({1, 0, 0}).matrix());
    EXPECT_EQ(s.shapes[1].type, "disk");
    EXPECT_EQ(s.shapes[1].loc.file, (dir.path / "geometry/leaf.pbrt").string());
    EXPECT_EQ(s.shapes[1].loc.line, 2);
    EXPECT_EQ(s.shapes[1].loc.column, 3);
    EXPECT_EQ(s.shapes[2].material.index, 0);  // set inside the included file
}

TEST_F(PbrtParser, IncludeIsTokenTransparent) {
    // pbrt-v4 pushes an included file on its token stream's file stack: a parameter list
    // left open at the end of the included file goes on after the Include, as in pbrt-v4's
    // smoke-plume scene ("Include density.pbrt" followed by "spectrum sigma_a" ...).
    TempDir dir;
    std::string inc = dir.write("geometry/head.pbrt", "Shape \"sphere\"\n  \"float radius\" 2\n");
    std::string main = dir.write("scene.pbrt", R"(WorldBegin
Include "geometry/head.pbrt"
    "float zmax" 0.5 "float phimax" [ 90 ]
Shape "disk"
)");
    SceneDesc s = parse_pbrt_file(main);
    ASSERT_EQ(s.shapes.size(), 2u);
    const ParamSet& p = s.shapes[0].params;
    EXPECT_EQ(p.get_float("radius", 1), 2.0f);
    EXPECT_EQ(p.get_float("zmax", 1), 0.5f);
    EXPECT_EQ(p.get_float("phimax", 360), 90.0f);
    EXPECT_EQ(s.shapes[0].loc.file, inc);
    EXPECT_EQ(p.find("radius")->loc.to_string(), inc + ":2:3");
    EXPECT_EQ(p.find("zmax")->loc.to_string(), main + ":3:5");
    EXPECT_EQ(s.shapes[1].type, "disk");
    // An error in the spliced part is located in the including file.
    dir.write("bad.pbrt", "WorldBegin\nInclude \"geometry/head.pbrt\"\n  \"float zmax\" \"x\"\n");
    try {
        parse_pbrt_file((dir.path / "bad.pbrt").string());
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.loc().to_string(), (dir.path / "bad.pbrt").string() + ":3:16") << e.what();
    }
}

TEST_F(PbrtParser, GzipCompressedIncludeAndSceneParseAsTheirText) {
    TempDir dir;
    const std::string inc_text = "Material \"conductor\"\nShape \"sphere\" \"float radius\" 3\n";
    dir.write("parts.pbrt", inc_text);
    const std::string gz_inc = dir.write("parts.pbrt.gz", gzip_compress(inc_text));
    const std::string main_text = "WorldBegin\nInclude \"parts.pbrt\"\nShape \"disk\"\n";
    std::string plain = dir.write("plain.pbrt", main_text);
    std::string gz = dir.write(
        "scene.pbrt.gz", gzip_compress("WorldBegin\nInclude \"parts.pbrt.gz\"\nShape \"disk\"\n"));
    SceneDesc a = parse_pbrt_file(plain), b = parse_pbrt_file(gz);
    ASSERT_EQ(b.shapes.size(), 2u);
    ASSERT_EQ(a.shapes.size(), 2u);
    EXPECT_EQ(b.shapes[0].params.get_float("radius", 1), 3.0f);
    EXPECT_EQ(b.shapes[0].material.index, 0);
    EXPECT_EQ(b.shapes[0].loc.to_string(), gz_inc + ":2:1");  // the .gz file, its text's line
    EXPECT_EQ(b.shapes[1].loc.to_string(), gz + ":3:1");
    EXPECT_EQ(a.shapes[1].loc.line, b.shapes[1].loc.line);
    // An error in the decompressed text names the .gz file, line and column.
    std::string bad =
        dir.write("bad.pbrt.gz", gzip_compress("WorldBegin\n\n  Shape \"sphere\" \"flot r\" 1\n"));
    try {
        parse_pbrt_file(bad);
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.loc().to_string(), bad + ":3:18") << e.what();
    }
}

TEST_F(PbrtParser, ErrorTruncatedOrMisnamedGzipInclude) {
    TempDir dir;
    const std::string gz = gzip_compress("WorldBegin\nShape \"sphere\"\n");
    dir.write("cut.pbrt.gz", gz.substr(0, gz.size() / 2));
    dir.write("plain.pbrt.gz", "Shape \"sphere\"\n");
    for (const char* name : {"cut.pbrt.gz", "plain.pbrt.gz"}) {
        try {
            parse_pbrt_string(fmt::format("WorldBegin\n  Include \"{}\"\n", name), "main.pbrt",
                              dir.path.string());
            ADD_FAILURE() << "expected an error for " << name;
        } catch (const Error& e) {
            EXPECT_EQ(e.loc().to_string(), "main.pbrt:2:3") << e.what();
            EXPECT_NE(e.message().find(name), std::string::npos) << e.what();
            EXPECT_NE(e.message().find(std::string(name) == "cut.pbrt.gz" ? "truncated gzip data"
                                                                          : "not gzip data"),
                      std::string::npos)
                << e.what();
        }
    }
}

TEST_F(PbrtParser, ImportDoesNotLeakGraphicsState) {
    TempDir dir;
    dir.write("imported.pbrt", R"(Material "conductor"
Translate 0 0 9
MakeNamedMaterial "shared" "string type" "diffuse"
Shape "sphere"
AttributeBegin
AttributeEnd
)");
    std::string text = R"(WorldBegin
Translate 1 0 0
Import "imported.pbrt"
NamedMaterial "shared"
Shape "disk"
)";
    SceneDesc s = parse_pbrt_string(text, "main.pbrt", dir.path.string());
    ASSERT_EQ(s.shapes.size(), 2u);
    expect_near(s.shapes[0].world_from_object.matrix(),
                Transform::translate({1, 0, 9}).matrix());
    EXPECT_EQ(s.shapes[0].material.index, 0);
    expect_near(s.shapes[1].world_from_object.matrix(), Transform::translate({1, 0, 0}).matrix());
    EXPECT_EQ(s.shapes[1].material.name, "shared");  // definitions are global
    EXPECT_EQ(s.named_materials.count("shared"), 1u);
}

// ---- malformed input: exact message and location ----------------------------------------

TEST_F(PbrtParser, ErrorUnterminatedString) {
    expect_error("WorldBegin\nShape \"sphere\"\n    \"float radius", "unterminated string", 3, 5);
}

TEST_F(PbrtParser, ErrorUnknownDirective) {
    expect_error("WorldBegin\n  Shape \"sphere\"\n  Foo 1 2", "unknown directive 'Foo'", 3, 3);
}

TEST_F(PbrtParser, ErrorBadNumber) {
    expect_error("Translate 1 x 3\nWorldBegin", "Translate: expected a number, got 'x'", 1, 13);
    expect_error("WorldBegin\nShape \"s\" \"float r\" [ 1 2.5.1 ]",
                 "parameter \"float r\": expected a number, got '2.5.1'", 2, 25);
}

TEST_F(PbrtParser, ErrorFloatGivenString) {
    expect_error("WorldBegin\nShape \"sphere\" \"float radius\" \"big\"",
                 "parameter \"float radius\": expected a number, got string \"big\"", 2, 31);
}

TEST_F(PbrtParser, ErrorIntegerGivenFloat) {
    expect_error("Film \"rgb\"\n  \"integer xresolution\" [ 640.5 ]\nWorldBegin",
                 "parameter \"integer xresolution\": expected an integer, got '640.5'", 2, 27);
}

TEST_F(PbrtParser, ErrorRgbNeedsThreeValues) {
    expect_error("WorldBegin\nMaterial \"diffuse\"\n  \"rgb reflectance\" [ 0.5 0.5 ]",
                 "parameter \"rgb reflectance\" needs 3 values (or a multiple of 3 for a grid), got 2",
                 3, 3);
}

TEST_F(PbrtParser, ErrorBlackbodyNeedsOneValue) {
    expect_error("WorldBegin\nLightSource \"point\" \"blackbody I\" [ 5500 1 ]",
                 "parameter \"blackbody I\" needs exactly 1 value (temperature in K), got 2", 2,
                 21);
}

TEST_F(PbrtParser, ErrorBoolNotTrueOrFalse) {
    expect_error("WorldBegin\nShape \"x\" \"bool flip\" \"yes\"",
                 "parameter \"bool flip\": expected true or false, got string \"yes\"", 2, 23);
    expect_error("WorldBegin\nShape \"x\" \"bool flip\" [ true 1 ]",
                 "expected true or false, got '1'", 2, 30);
}

TEST_F(PbrtParser, ErrorUnknownParameterType) {
    expect_error("WorldBegin\nShape \"x\" \"colour c\" [1 2 3]",
                 "unknown parameter type \"colour\" in \"colour c\"", 2, 11);
    expect_error("WorldBegin\nShape \"x\" \"float\" 1", "malformed parameter declaration", 2, 11);
}

// pbrt-v4's ParameterDictionary reverses each list before looking names up, so the last of
// two parameters with one name is the one used; the first is shadowed without an error.
TEST_F(PbrtParser, ParameterGivenTwiceTheLastIsUsedWithAWarning) {
    std::vector<ErrorEntry> warnings;
    SceneDesc s;
    {
        WarningCapture capture;
        s = parse("WorldBegin\nShape \"sphere\" \"float radius\" 1\n  \"float radius\" 2\n"
                  "Material \"diffuse\" \"rgb reflectance\" [1 0 0] \"spectrum reflectance\" "
                  "[400 0.5 700 0.5]\n");
        warnings = capture.take();
    }
    ASSERT_EQ(s.shapes.size(), 1u);
    const Param* r = s.shapes[0].params.find("radius");
    ASSERT_NE(r, nullptr);
    ASSERT_EQ(r->numbers.size(), 1u);
    EXPECT_EQ(r->numbers[0], 2.0);
    EXPECT_EQ(r->loc.line, 3);
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_EQ(warnings[0].loc.line, 3);
    EXPECT_NE(warnings[0].message.find("first at test.pbrt:2:16"), std::string::npos)
        << warnings[0].message;
    EXPECT_EQ(warnings[1].loc.line, 4);  // rgb then spectrum: both colours, the spectrum wins
}

TEST_F(PbrtParser, ErrorParameterGivenTwiceWithAnotherType) {
    expect_error("WorldBegin\nShape \"sphere\" \"float radius\" 1\n  \"string radius\" \"a\"",
                 "parameter \"radius\" given again with another type (first at test.pbrt:2:16)",
                 3, 3);
}

TEST_F(PbrtParser, ErrorUnbalancedAttributeEnd) {
    expect_error("WorldBegin\nAttributeBegin\nAttributeEnd\n AttributeEnd",
                 "AttributeEnd without matching AttributeBegin", 4, 2);
    expect_error("WorldBegin\nAttributeBegin\n  Shape \"x\"\n", 
                 "AttributeBegin without matching AttributeEnd", 2, 1);
}

TEST_F(PbrtParser, ErrorOptionsAfterWorldBegin) {
    expect_error("WorldBegin\n\nCamera \"perspective\"", "Camera is not allowed after WorldBegin",
                 3, 1);
    expect_error("WorldBegin\nSampler \"halton\"", "Sampler is not allowed after WorldBegin", 2,
                 1);
    expect_error("WorldBegin\nWorldBegin", "WorldBegin: the world block already began at", 2, 1);
}

TEST_F(PbrtParser, ErrorWorldDirectivesBeforeWorldBegin) {
    expect_error("Camera \"perspective\"\n  Shape \"sphere\"", "Shape is not allowed before WorldBegin",
                 2, 3);
    expect_error("AttributeBegin", "AttributeBegin is not allowed before WorldBegin", 1, 1);
    expect_error("Material \"diffuse\"", "Material is not allowed before WorldBegin", 1, 1);
    expect_error("Import \"x.pbrt\"", "Import is only allowed after WorldBegin", 1, 1);
    expect_error("Camera \"perspective\"\n", "end of file before WorldBegin", 2, 1);
}

TEST_F(PbrtParser, ErrorMissingIncludeFile) {
    expect_error("WorldBegin\n  Include \"nope/missing.pbrt\"",
                 "Include: cannot find file \"nope/missing.pbrt\"", 2, 3);
}

TEST_F(PbrtParser, ErrorInsideIncludedFileIsLocatedThere) {
    TempDir dir;
    std::string inc = dir.write("inc.pbrt", "Shape \"sphere\"\n\n  Shape \"disk\" \"rgb\" 1\n");
    try {
        parse_pbrt_string("WorldBegin\nInclude \"inc.pbrt\"\n", "main.pbrt", dir.path.string());
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.loc().file, inc);
        EXPECT_EQ(e.loc().line, 3);
        EXPECT_EQ(e.loc().column, 16);
        EXPECT_NE(e.message().find("malformed parameter declaration \"rgb\""), std::string::npos)
            << e.message();
    }
}

TEST_F(PbrtParser, ErrorEndOfFileInsideObjectBegin) {
    expect_error("WorldBegin\n  ObjectBegin \"tree\"\n  Shape \"sphere\"\n",
                 "ObjectBegin \"tree\" without matching ObjectEnd", 2, 3);
}

TEST_F(PbrtParser, ErrorObjectInstanceOfUnknownObject) {
    expect_error("WorldBegin\nObjectBegin \"a\"\nObjectEnd\n\n    ObjectInstance \"b\"",
                 "ObjectInstance: object \"b\" is not defined", 5, 5);
}

TEST_F(PbrtParser, ErrorObjectNesting) {
    expect_error("WorldBegin\nObjectBegin \"a\"\n ObjectBegin \"b\"",
                 "ObjectBegin \"b\" inside the definition of object \"a\"", 3, 2);
    expect_error("WorldBegin\nObjectBegin \"a\"\nAttributeEnd",
                 "AttributeEnd closes ObjectBegin \"a\"", 3, 1);
    expect_error("WorldBegin\nObjectBegin \"a\"\nAttributeBegin\nObjectEnd",
                 "ObjectEnd while AttributeBegin at test.pbrt:3:1 is still open", 4, 1);
    expect_error("WorldBegin\nObjectBegin \"a\"\nObjectEnd\nObjectBegin \"a\"",
                 "object \"a\" redefined (first defined at test.pbrt:2:1)", 4, 1);
    expect_error("WorldBegin\nObjectEnd", "ObjectEnd without matching ObjectBegin", 2, 1);
    expect_error("WorldBegin\nObjectBegin \"a\"\n  ObjectInstance \"a\"",
                 "instances cannot be nested", 3, 3);
}

TEST_F(PbrtParser, ErrorUnterminatedValueList) {
    expect_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0\n 1 1 1\n",
                 "unterminated value list of parameter \"point3 P\": missing ']'", 2, 33);
}

TEST_F(PbrtParser, ErrorTransformNeedsBrackets) {
    expect_error("WorldBegin\nTransform 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1",
                 "Transform: expected '[' before the 16 matrix values, got '1'", 2, 11);
    expect_error("ConcatTransform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1 ]",
                 "ConcatTransform: expected ']' after 16 matrix values, got '1'", 1, 51);
    expect_error("WorldBegin\nTransform [ 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 ]",
                 "Transform: singular transformation matrix", 2, 1);
}

TEST_F(PbrtParser, ErrorMultipleValuesNeedBrackets) {
    expect_error("WorldBegin\nShape \"sphere\" \"float radius\" 1 2",
                 "expected a directive, got '2' (a parameter with several values needs brackets",
                 2, 33);
}

TEST_F(PbrtParser, ErrorNamedMaterials) {
    expect_error(
        "WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
        "MakeNamedMaterial \"m\" \"string type\" \"conductor\"",
        "named material \"m\" redefined (first defined at test.pbrt:2:1)", 3, 1);
    expect_error("WorldBegin\n MakeNamedMaterial \"m\" \"float roughness\" 0",
                 "MakeNamedMaterial \"m\": missing \"string type\" parameter", 2, 2);
    expect_error("WorldBegin\nMakeNamedMaterial \"m\" \"texture type\" \"t\"",
                 "\"type\" must be a single string", 2, 23);
}

TEST_F(PbrtParser, ErrorTextures) {
    expect_error("WorldBegin\nTexture \"t\" \"color\" \"imagemap\"",
                 "unknown texture type \"color\": must be \"float\" or \"spectrum\"", 2, 13);
    expect_error("WorldBegin\nTexture \"t\" \"float\" \"constant\"\nTexture \"t\" \"float\" "
                 "\"constant\"",
                 "float texture \"t\" redefined (first defined at test.pbrt:2:1)", 3, 1);
}

TEST_F(PbrtParser, ErrorMiscellaneousDirectiveArguments) {
    expect_error("WorldBegin\nAttribute \"camera\" \"float x\" 1",
                 "unknown Attribute target \"camera\"", 2, 11);
    expect_error("WorldBegin\nActiveTransform Later", "ActiveTransform: expected All, StartTime or "
                 "EndTime, got 'Later'", 2, 17);
    expect_error("WorldBegin\nShape sphere", "Shape: expected a quoted string, got 'sphere'", 2,
                 7);
    expect_error("WorldBegin\nShape", "Shape: unexpected end of file, expected a quoted string",
                 2, 6);
    expect_error("WorldBegin\nShape \"x\" \"float r\"", "parameter \"float r\" has no value", 2,
                 11);
    expect_error("WorldBegin\nRotate 30 0 0 0", "Rotate: the rotation axis is the zero vector",
                 2, 1);
    expect_error("Scale 1 0 1", "Scale: a zero scale factor", 1, 1);
    expect_error("WorldBegin\nNamedMaterial \"\"", "NamedMaterial: empty material name", 2, 1);
    expect_error("WorldBegin\n\"float x\" 1", "expected a directive, got string \"float x\"", 2, 1);
}

TEST_F(PbrtParser, ErrorUnusedParameterAndWrongGetterType) {
    SceneDesc s = parse("WorldBegin\nShape \"sphere\" \"float radius\" 1\n   \"float rdius\" 2");
    const ParamSet& p = s.shapes[0].params;
    EXPECT_EQ(p.get_float("radius", 1), 1.0f);
    try {
        p.check_unused("shape \"sphere\"");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.message(), "unused parameter \"float rdius\" for shape \"sphere\"");
        EXPECT_EQ(e.loc().to_string(), "test.pbrt:3:4");
    }
    try {
        p.get_int("radius", 0);
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.message(),
                  "parameter \"float radius\" has the wrong type: expected \"integer radius\"");
        EXPECT_EQ(e.loc().to_string(), "test.pbrt:2:16");
    }
}

TEST_F(PbrtParser, ErrorMissingSceneFile) {
    try {
        parse_pbrt_file("/nonexistent/dir/scene.pbrt");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.message(),
                  "cannot read scene file \"/nonexistent/dir/scene.pbrt\": No such file or "
                  "directory");
        EXPECT_TRUE(e.loc().file.empty());
    }
}

// ---- a larger input ----------------------------------------

TEST_F(PbrtParser, LargeMeshParsesAllValues) {
    std::string text = "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [\n";
    const int n = 30000;
    for (int i = 0; i < n; ++i) text += std::to_string(i) + ".5 -1e-2 3\n";
    text += "]\n";
    SceneDesc s = parse(text);
    auto p = s.shapes[0].params.get_point3s("P");
    ASSERT_EQ(p.size(), size_t(n));
    EXPECT_EQ(p[123], Point3(123.5f, -0.01f, 3));
}

}  // namespace
}  // namespace sr
