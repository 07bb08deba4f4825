#include "steradian/scene/param_set.h"

#include <gtest/gtest.h>

namespace sr {
namespace {

Param make(ParamType type, const std::string& name, std::vector<double> numbers, int line = 1) {
    Param p;
    p.type = type;
    p.name = name;
    p.loc = SourceLoc{"p.pbrt", line, 3};
    p.numbers = std::move(numbers);
    return p;
}

Param make_strings(ParamType type, const std::string& name, std::vector<std::string> s,
                   int line = 1) {
    Param p = make(type, name, {}, line);
    p.strings = std::move(s);
    return p;
}

/// Runs f, expecting an sr::Error whose message contains `what`, located at line:3.
template <typename F>
void expect_error(F&& f, const std::string& what, int line) {
    try {
        f();
        ADD_FAILURE() << "expected an error containing: " << what;
    } catch (const Error& e) {
        EXPECT_NE(e.message().find(what), std::string::npos) << "message: " << e.message();
        EXPECT_EQ(e.loc().line, line) << e.what();
        EXPECT_EQ(e.loc().column, 3) << e.what();
    }
}

TEST(ParamSet, TypeNames) {
    EXPECT_EQ(to_string(ParamType::Integer), "integer");
    EXPECT_EQ(to_string(ParamType::Float), "float");
    EXPECT_EQ(to_string(ParamType::Point2), "point2");
    EXPECT_EQ(to_string(ParamType::Vector2), "vector2");
    EXPECT_EQ(to_string(ParamType::Point3), "point3");
    EXPECT_EQ(to_string(ParamType::Vector3), "vector3");
    EXPECT_EQ(to_string(ParamType::Normal3), "normal");
    EXPECT_EQ(to_string(ParamType::Bool), "bool");
    EXPECT_EQ(to_string(ParamType::String), "string");
    EXPECT_EQ(to_string(ParamType::Texture), "texture");
    EXPECT_EQ(to_string(ParamType::Spectrum), "spectrum");
    EXPECT_EQ(to_string(ParamType::Rgb), "rgb");
    EXPECT_EQ(to_string(ParamType::Blackbody), "blackbody");
}

TEST(ParamSet, GettersAndDefaults) {
    ParamSet ps;
    ps.add(make(ParamType::Float, "radius", {2.5}));
    ps.add(make(ParamType::Integer, "maxdepth", {7}));
    Param b = make(ParamType::Bool, "twosided", {});
    b.bools = {1};
    ps.add(b);
    ps.add(make_strings(ParamType::String, "filename", {"a.ply"}));
    ps.add(make(ParamType::Point3, "P", {0, 0, 0, 1, 0, 0, 0, 1, 0}));
    ps.add(make(ParamType::Normal3, "N", {0, 0, 1, 0, 0, 1, 0, 0, 1}));
    ps.add(make(ParamType::Point2, "uv", {0, 0, 1, 0, 0, 1}));
    ps.add(make(ParamType::Integer, "indices", {0, 1, 2}));
    ps.add(make(ParamType::Vector3, "up", {0, 1, 0}));
    ps.add(make_strings(ParamType::Texture, "reflectance", {"checks"}));
    ps.add(make(ParamType::Rgb, "L", {1, 2, 3}));

    EXPECT_EQ(ps.get_float("radius", 1), 2.5f);
    EXPECT_EQ(ps.get_float("absent", 1), 1.0f);
    EXPECT_EQ(ps.get_int("maxdepth", 5), 7);
    EXPECT_TRUE(ps.get_bool("twosided", false));
    EXPECT_EQ(ps.get_string("filename", ""), "a.ply");
    EXPECT_EQ(ps.get_point3s("P").size(), 3u);
    EXPECT_EQ(ps.get_point3s("P")[1], Point3(1, 0, 0));
    EXPECT_EQ(ps.get_normals("N").size(), 3u);
    EXPECT_EQ(ps.get_point2s("uv")[2], Point2(0, 1));
    EXPECT_EQ(ps.get_ints("indices"), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(*ps.find_vector3("up"), Vec3(0, 1, 0));
    EXPECT_FALSE(ps.find_point3("from").has_value());
    EXPECT_FALSE(ps.find_texture("L").has_value());  // another type: not a texture, not used
    EXPECT_EQ(*ps.find_texture("reflectance"), "checks");
    const Param* l = ps.find_spectrum("L");
    ASSERT_NE(l, nullptr);
    EXPECT_EQ(l->type, ParamType::Rgb);
    EXPECT_EQ(ps.find_spectrum("absent"), nullptr);
    EXPECT_NO_THROW(ps.check_unused("shape \"trianglemesh\""));
}

TEST(ParamSet, DuplicateIsAnError) {
    ParamSet ps;
    ps.add(make(ParamType::Float, "radius", {1}, 2));
    expect_error([&] { ps.add(make(ParamType::Integer, "radius", {1}, 4)); },
                 "duplicate parameter \"radius\" (first given at p.pbrt:2:3)", 4);
}

TEST(ParamSet, WrongTypeAndCountAreLocatedErrors) {
    ParamSet ps;
    ps.add(make(ParamType::Float, "radius", {1, 2}, 3));
    ps.add(make(ParamType::Float, "fov", {45}, 5));
    ps.add(make(ParamType::Point3, "P", {1, 2, 3, 4}, 6));
    ps.add(make(ParamType::Integer, "n", {1.5}, 7));
    ps.add(make(ParamType::Spectrum, "eta", {400, 1.5, 700}, 8));
    expect_error([&] { ps.get_float("radius", 0); },
                 "parameter \"float radius\" needs exactly 1 value, got 2", 3);
    expect_error([&] { ps.get_int("fov", 0); },
                 "parameter \"float fov\" has the wrong type: expected \"integer fov\"", 5);
    expect_error([&] { ps.get_point3s("P"); },
                 "parameter \"point3 P\" needs a multiple of 3 values, got 4", 6);
    expect_error([&] { ps.get_int("n", 0); }, "value 1.5 is not a 32-bit integer", 7);
    expect_error([&] { ps.find_spectrum("eta"); }, "needs (wavelength, value) pairs, got 3", 8);
    expect_error([&] { ps.find_spectrum("fov"); }, "expected a spectrum", 5);
}

TEST(ParamSet, CheckUnusedReportsFirstUnreadParameter) {
    ParamSet ps;
    ps.add(make(ParamType::Float, "radius", {1}, 2));
    ps.add(make(ParamType::Float, "zmin", {-1}, 3));
    ps.add(make(ParamType::Float, "zmax", {1}, 4));
    ps.get_float("radius", 1);
    expect_error([&] { ps.check_unused("shape \"sphere\""); },
                 "unused parameter \"float zmin\" for shape \"sphere\"", 3);
    ps.find("zmin");
    ps.find("zmax", ParamType::Float);
    EXPECT_NO_THROW(ps.check_unused("shape \"sphere\""));
}

}  // namespace
}  // namespace sr
