// The .bsdf reader (tensor files, bsdf/tensor_file.h, and the measured BRDF's fields,
// bsdf/measured.h): a file written by write_tensor_file reads back; every truncation, every
// corrupt header and every table of the wrong type, shape or value is an sr::Error naming the
// file (and the field); random corruption never crashes. With constant tables the lobe is
// pbrt-v4's formula in closed form: f cos(theta_i) = fr D / (4 sigma) and, the (u, v) density
// of wm being uniform, pdf = 1 / (4 (wo . wm) 2 pi^2 u sin(theta_m)).
#include "steradian/bsdf/measured.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>

#include "steradian/bsdf/tensor_file.h"
#include "steradian/core/error.h"
#include "steradian/sampling/rng.h"

namespace sr {
namespace {

constexpr const char* kName = "test/constant.bsdf";
constexpr float kD = 0.8f, kSigma = 0.5f;
const float kFr[2] = {0.2f, 0.6f};  // at 400 and 700 nm

TensorField u8_field(std::vector<uint64_t> shape, std::string bytes) {
    TensorField f;
    f.dtype = TensorDtype::UInt8;
    f.shape = std::move(shape);
    f.bytes = std::move(bytes);
    return f;
}

/// A valid isotropic file with constant tables: 3 theta_i, 1 phi_i, 2 wavelengths, 3 x 3
/// grids (ndf and sigma 4 x 4).
TensorFile constant_file() {
    TensorFile f;
    f.fields["theta_i"] = float32_field({3}, {0, 0.5f, 1.0f});
    f.fields["phi_i"] = float32_field({1}, {0});
    f.fields["wavelengths"] = float32_field({2}, {400, 700});
    f.fields["ndf"] = float32_field({4, 4}, std::vector<float>(16, kD));
    f.fields["sigma"] = float32_field({4, 4}, std::vector<float>(16, kSigma));
    f.fields["vndf"] = float32_field({1, 3, 3, 3}, std::vector<float>(27, 2.0f));
    f.fields["luminance"] = float32_field({1, 3, 3, 3}, std::vector<float>(27, 0.4f));
    std::vector<float> spectra;
    for (int t = 0; t < 3; ++t)
        for (float v : kFr) spectra.insert(spectra.end(), 9, v);
    f.fields["spectra"] = float32_field({1, 3, 2, 3, 3}, spectra);
    f.fields["jacobian"] = u8_field({1}, std::string(1, '\1'));
    f.fields["description"] = u8_field({4}, "test");
    return f;
}

/// The error message of parsing `bytes`, or "" if it parses.
std::string parse_error(const std::string& bytes) {
    try {
        parse_measured_brdf(bytes, kName);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// Expects parsing the file changed by `change` to fail with a message containing `what`
/// and the file's name.
void expect_rejected(const std::function<void(TensorFile&)>& change, const std::string& what) {
    TensorFile f = constant_file();
    change(f);
    std::string msg = parse_error(write_tensor_file(f));
    EXPECT_NE(msg.find(kName), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << "expected \"" << what << "\" in: " << msg;
}

SampledWavelengths wavelengths(Float a, Float b, Float c, Float d) {
    SampledWavelengths w;
    w.lambda = {a, b, c, d};
    w.pdf = {1, 1, 1, 1};
    return w;
}

TEST(MeasuredBrdf, TensorFileRoundTrips) {
    TensorFile f = constant_file();
    TensorFile back = parse_tensor_file(write_tensor_file(f), kName);
    ASSERT_EQ(back.fields.size(), f.fields.size());
    for (const auto& [name, field] : f.fields) {
        const TensorField* b = back.find(name);
        ASSERT_NE(b, nullptr) << name;
        EXPECT_EQ(b->dtype, field.dtype);
        EXPECT_EQ(b->shape, field.shape);
        EXPECT_EQ(b->bytes, field.bytes);
    }
    EXPECT_EQ(parse_error(write_tensor_file(f)), "");
}

TEST(MeasuredBrdf, ConstantTablesGivePbrtFormula) {
    MeasuredBrdf b = parse_measured_brdf(write_tensor_file(constant_file()), kName);
    EXPECT_TRUE(b.isotropic);
    // 550 nm is halfway between the file's wavelengths; 300 and 800 nm are outside them.
    MeasuredLobe lobe{&b, wavelengths(400, 550, 300, 800)};
    const double expect[4] = {kFr[0], 0.5 * (kFr[0] + kFr[1]), kFr[0], kFr[1]};
    Pcg32 rng(3);
    int checked = 0;
    for (int k = 0; k < 200; ++k) {
        Vec3 wo = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 0.3f));
        Vec3 wi = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 0.4f));
        if (k % 2) {  // the lower side mirrors the upper one
            wo = -wo;
            wi = -wi;
        }
        SampledSpectrum f = lobe.f(wo, wi, TransportMode::Radiance);
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(f[i] * std::abs(wi.z), expect[i] * kD / (4 * kSigma), 1e-5);
        Vec3 wm = normalize(wo + wi) * (wo.z < 0 ? -1.0f : 1.0f);
        Float u = measured_theta_to_u(std::atan2(sin_theta(wm), wm.z));
        Float jac = 4 * std::abs(dot(wo, wm)) * 2 * kPi * kPi * u * sin_theta(wm);
        if (jac > 1e-3f) {
            EXPECT_NEAR(lobe.pdf(wo, wi, TransportMode::Radiance) * jac, 1, 1e-3);
            ++checked;
        }
        // Opposite sides never reflect.
        EXPECT_TRUE(lobe.f(wo, Vec3(wi.x, wi.y, -wi.z), TransportMode::Radiance).is_zero());
        EXPECT_EQ(lobe.pdf(wo, Vec3(wi.x, wi.y, -wi.z), TransportMode::Radiance), 0);
    }
    EXPECT_GT(checked, 150);
}

TEST(MeasuredBrdf, EveryTruncationIsAnErrorNamingTheFile) {
    std::string bytes = write_tensor_file(constant_file());
    for (size_t n = 0; n < bytes.size(); ++n) {
        std::string msg = parse_error(bytes.substr(0, n));
        ASSERT_NE(msg, "") << "a file truncated to " << n << " bytes was accepted";
        ASSERT_NE(msg.find(kName), std::string::npos) << msg;
    }
}

TEST(MeasuredBrdf, CorruptHeadersAreErrors) {
    std::string good = write_tensor_file(constant_file());
    auto with = [&](size_t at, std::string_view patch) {
        std::string b = good;
        b.replace(at, patch.size(), patch);
        return parse_error(b);
    };
    EXPECT_NE(with(0, "tensor_filf").find("not a tensor file"), std::string::npos);
    EXPECT_NE(with(12, std::string("\2\0", 2)).find("version 2.0"), std::string::npos);
    // The first field ("description", the map's order) : name length 11 at byte 18, then
    // the name, ndim (2 bytes), dtype (1), offset (8), shape (8 per dimension).
    const size_t ndim_at = 18 + 2 + 11, dtype_at = ndim_at + 2, offset_at = dtype_at + 1;
    EXPECT_NE(with(dtype_at, "\x0c").find("unknown type code 12"), std::string::npos);
    EXPECT_NE(with(ndim_at, "\x40").find("64 dimensions"), std::string::npos);
    EXPECT_NE(with(offset_at + 4, "\x01").find("past the end of the file"), std::string::npos);
    EXPECT_NE(with(offset_at + 8 + 7, "\x40").find("past the end of the file"),
              std::string::npos);  // a shape of 2^62
    // n_fields one more than there are: the next header is read from the data.
    std::string more = good;
    more[14] = char(more[14] + 1);
    EXPECT_NE(parse_error(more), "");
}

TEST(MeasuredBrdf, BadFieldsAreErrorsNamingTheField) {
    expect_rejected([](TensorFile& f) { f.fields.erase("vndf"); }, "no field \"vndf\"");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["rgb"] = f.fields["spectra"];
            f.fields.erase("spectra");
        },
        "RGB-only");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["ndf"] = u8_field({4, 4}, std::string(16, 'a'));
        },
        "field \"ndf\" is uint8 [4, 4]");
    expect_rejected(
        [](TensorFile& f) { f.fields["sigma"] = float32_field({16}, std::vector<float>(16, 1)); },
        "field \"sigma\" is float32 [16]");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["vndf"] = float32_field({1, 2, 3, 3}, std::vector<float>(18, 1));
        },
        "field \"vndf\" is float32 [1, 2, 3, 3]");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["luminance"] = float32_field({1, 3, 4, 4}, std::vector<float>(48, 1));
        },
        "their grids must agree");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["ndf"] = float32_field({1, 16}, std::vector<float>(16, 1));
        },
        "at least 2");
    expect_rejected(
        [](TensorFile& f) {
            std::vector<float> v = f.fields["spectra"].floats();
            v[7] = std::nanf("");
            f.fields["spectra"] = float32_field(f.fields["spectra"].shape, v);
        },
        "field \"spectra\": value 7 (nan) is not finite");
    expect_rejected(
        [](TensorFile& f) {
            std::vector<float> v(27, 2.0f);
            for (int i = 9; i < 18; ++i) v[i] = 0;
            f.fields["vndf"] = float32_field({1, 3, 3, 3}, v);
        },
        "field \"vndf\": slice 2 of 3 has no mass");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["theta_i"] = float32_field({3}, {0, 30, 60});
        },
        "not an angle in [0, pi/2] radians");
    expect_rejected(
        [](TensorFile& f) {
            f.fields["theta_i"] = float32_field({3}, {0, 1.0f, 0.5f});
        },
        "not increasing");
    expect_rejected(
        [](TensorFile& f) { f.fields["jacobian"] = u8_field({1}, std::string(1, '\0')); },
        "\"jacobian\" is 0");
    expect_rejected([](TensorFile& f) { f.fields.erase("jacobian"); }, "expected uint8 [1]");
    expect_rejected(
        [](TensorFile& f) {
            // Anisotropic over half the circle: a symmetry reduction pbrt-v4 refuses too.
            f.fields["phi_i"] = float32_field({3}, {0, 1.5f, 3.1f});
            f.fields["vndf"] = float32_field({3, 3, 3, 3}, std::vector<float>(81, 1));
            f.fields["luminance"] = float32_field({3, 3, 3, 3}, std::vector<float>(81, 1));
            f.fields["spectra"] = float32_field({3, 3, 2, 3, 3}, std::vector<float>(162, 1));
        },
        "less than the full circle");
}

TEST(MeasuredBrdf, RandomCorruptionNeverCrashes) {
    std::string good = write_tensor_file(constant_file());
    Pcg32 rng(23);
    int rejected = 0;
    for (int k = 0; k < 3000; ++k) {
        std::string b = good;
        int flips = 1 + int(rng.next_u32() % 4);
        for (int i = 0; i < flips; ++i) b[rng.next_u32() % b.size()] = char(rng.next_u32());
        std::string msg = parse_error(b);
        if (!msg.empty()) {
            ++rejected;
            ASSERT_NE(msg.find(kName), std::string::npos) << msg;
        }
    }
    EXPECT_GT(rejected, 0);
}

TEST(MeasuredBrdf, MissingFileIsAnErrorNamingIt) {
    try {
        read_measured_brdf("/nonexistent/dir/x.bsdf");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.bsdf"), std::string::npos);
    }
}

}  // namespace
}  // namespace sr
