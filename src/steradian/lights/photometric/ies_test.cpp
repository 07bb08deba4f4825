#include "steradian/lights/photometric/ies.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "steradian/core/error.h"

namespace sr {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

std::vector<double> range(double first, double last, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::lround((last - first) / step));
    for (int i = 0; i <= n; ++i) out.push_back(first + step * i);
    return out;
}

std::string join(const std::vector<double>& v, const char* sep = " ") {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + fmt::format("{}", v[i]);
    return s;
}

/// An IES file assembled line by line: version line (if any), labels, TILT line, tilt block,
/// lamp line, ballast line, vertical angles, horizontal angles, one line per candela row.
struct IesFile {
    std::string header = "IESNA:LM-63-2002";
    std::vector<std::string> labels = {"[TEST] T-100", "[MANUFAC] Acme Lighting"};
    std::string tilt = "TILT=NONE";
    std::vector<std::string> tilt_block;
    double lamps = 1, lumens = 1000, multiplier = 1;
    int type = 1, units = 2;
    double width = 0, length = 0, height = 0;
    double ballast = 1, future = 1, watts = 60;
    std::vector<double> v = {0, 45, 90}, h = {0};
    std::vector<std::vector<double>> cd = {{100, 80, 20}};

    template <typename F>
    void fill(const F& f) {
        cd.clear();
        for (double hh : h) {
            std::vector<double> row;
            for (double vv : v) row.push_back(f(hh, vv));
            cd.push_back(row);
        }
    }

    std::string text(const char* eol = "\n") const {
        std::string s;
        if (!header.empty()) s += header + eol;
        for (const auto& l : labels) s += l + eol;
        s += tilt + eol;
        for (const auto& l : tilt_block) s += l + eol;
        s += fmt::format("{} {} {} {} {} {} {} {} {} {}{}", lamps, lumens, multiplier, v.size(),
                         h.size(), type, units, width, length, height, eol);
        s += fmt::format("{} {} {}{}", ballast, future, watts, eol);
        s += join(v) + eol;
        s += join(h) + eol;
        for (const auto& row : cd) s += join(row) + eol;
        return s;
    }
};

/// Runs f expecting an sr::Error located at file:line whose message says what was expected
/// and contains `what`.
template <typename F>
void expect_error(F&& f, const std::string& file, int line, const std::string& what) {
    try {
        f();
        ADD_FAILURE() << "expected an error containing: " << what;
    } catch (const Error& e) {
        EXPECT_EQ(e.loc().file, file) << e.what();
        EXPECT_EQ(e.loc().line, line) << e.what();
        EXPECT_NE(std::string(e.what()).find(fmt::format("{}:{}:", file, line)), std::string::npos)
            << e.what();
        EXPECT_NE(e.message().find("expected"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find(what), std::string::npos) << e.what();
    }
}

std::filesystem::path temp_dir() {
    auto dir = std::filesystem::path(::testing::TempDir()) /
               fmt::format("sr_ies_test_{}", static_cast<long>(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

void write_file(const std::filesystem::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
}

// ---- versions, keywords, factors ----------------------------------------------------------

TEST(Ies, EveryVersionHeaderAndTheBallastLampFactor) {
    struct Case {
        const char* header;
        const char* version;
        bool blp_applied;
    };
    const Case cases[] = {{"", "LM-63-1986", true},
                          {"IESNA91", "LM-63-1991", true},
                          {"IESNA:LM-63-1995", "LM-63-1995", false},
                          {"IESNA:LM-63-2002", "LM-63-2002", false},
                          {"IES:LM-63-2019", "LM-63-2019", false}};
    for (const auto& c : cases) {
        IesFile f;
        f.header = c.header;
        if (f.header.empty()) f.labels = {"ACME 1986 DOWNLIGHT", "200W A19 LAMP"};
        f.multiplier = 2.5;
        f.ballast = 0.8;
        f.future = 0.5;
        PhotometricData d = parse_ies(f.text(), "v.ies");
        SCOPED_TRACE(c.version);
        EXPECT_EQ(d.version, c.version);
        EXPECT_EQ(d.format, PhotometricFormat::Ies);
        EXPECT_EQ(d.source, "v.ies");
        EXPECT_EQ(d.future_use, 0.5);
        EXPECT_EQ(d.ballast_lamp_factor, c.blp_applied ? 0.5 : 1.0);
        const double scale = 2.5 * 0.8 * (c.blp_applied ? 0.5 : 1.0);
        ASSERT_EQ(d.candela.size(), 1u);
        for (size_t j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(d.candela[0][j], f.cd[0][j] * scale);
        if (f.header.empty()) {
            EXPECT_TRUE(d.keywords.empty());
            ASSERT_EQ(d.header_lines.size(), 2u);
            EXPECT_EQ(d.header_lines[0], "ACME 1986 DOWNLIGHT");
        } else {
            EXPECT_EQ(d.keywords.at("TEST"), "T-100");
            EXPECT_EQ(d.keywords.at("MANUFAC"), "Acme Lighting");
        }
    }
}

TEST(Ies, KeywordsMoreAndRepeats) {
    IesFile f;
    f.labels = {"[TEST] 123",           "[LUMCAT] X-1",  "[LUMINAIRE] Long description",
                "[MORE] continued",     "[OTHER] first", "[OTHER] second",
                "[_USERKEY] user text", "[ISSUEDATE]"};
    PhotometricData d = parse_ies(f.text(), "k.ies");
    EXPECT_EQ(d.keywords.at("LUMINAIRE"), "Long description\ncontinued");
    EXPECT_EQ(d.keywords.at("OTHER"), "first\nsecond");
    EXPECT_EQ(d.keywords.at("_USERKEY"), "user text");
    EXPECT_EQ(d.keywords.at("ISSUEDATE"), "");
    EXPECT_EQ(d.keywords.count("MORE"), 0u);
}

TEST(Ies, FileGenerationType2019IsNotAMultiplier) {
    IesFile f;
    f.header = "IES:LM-63-2019";
    f.labels = {"[TEST] A", "[TESTLAB] Lab", "[ISSUEDATE] 2020-01-01", "[MANUFAC] M"};
    f.future = 1.0001;
    PhotometricData d = parse_ies(f.text(), "g.ies");
    EXPECT_DOUBLE_EQ(d.future_use, 1.0001);
    EXPECT_EQ(d.candela[0][0], 100);
}

TEST(Ies, CandelaMultiplierAndBallastFactorMultiplyExactly) {
    IesFile f;
    f.v = range(0, 180, 30);
    f.h = {0, 90};
    f.fill([](double h, double v) { return 17.25 + v * 3 + h; });
    PhotometricData one = parse_ies(f.text(), "a.ies");
    f.multiplier = 3;
    f.ballast = 0.75;
    PhotometricData scaled = parse_ies(f.text(), "a.ies");
    for (size_t i = 0; i < f.h.size(); ++i) {
        for (size_t j = 0; j < f.v.size(); ++j) {
            EXPECT_EQ(one.candela[i][j], f.cd[i][j]);
            EXPECT_DOUBLE_EQ(scaled.candela[i][j], f.cd[i][j] * 2.25);
        }
    }
    EXPECT_NEAR(scaled.total_flux(), 2.25 * one.total_flux(), 1e-12 * one.total_flux());
    EXPECT_EQ(scaled.candela_multiplier, 3);
    EXPECT_EQ(scaled.ballast_factor, 0.75);
}

// ---- absolute scale -----------------------------------------------------------------------

TEST(Ies, RelativePhotometryFluxMatchesLampLumens) {
    // A cosine lobe on the lower hemisphere carrying exactly lamps x lumens: I0 = F / pi.
    IesFile f;
    f.lamps = 2;
    f.lumens = 1500;
    const double flux = 3000;
    f.v = range(0, 90, 1);
    f.h = {0, 90};
    f.fill([&](double, double g) { return flux / kPi * std::cos(g * kDeg); });
    PhotometricData d = parse_ies(f.text(), "rel.ies");
    EXPECT_EQ(d.lamp_lumens, 1500);
    EXPECT_EQ(d.num_lamps, 2);
    EXPECT_EQ(d.nominal_flux(), flux);
    EXPECT_NEAR(d.total_flux(), flux, 1e-4 * flux);

    // The factors scale the flux: multiplier x ballast factor (x ballast-lamp factor in 1986).
    f.multiplier = 1.1;
    f.ballast = 0.9;
    EXPECT_NEAR(parse_ies(f.text(), "rel.ies").total_flux(), flux * 1.1 * 0.9, 1e-4 * flux);
    f.header = "";
    f.labels = {"OLD FILE"};
    f.future = 0.95;
    EXPECT_NEAR(parse_ies(f.text(), "rel.ies").total_flux(), flux * 1.1 * 0.9 * 0.95, 1e-4 * flux);

    // Isotropic over the sphere: I = F / (4 pi), exact for a constant.
    IesFile iso;
    iso.lumens = 800;
    iso.v = range(0, 180, 22.5);
    iso.h = {0};
    iso.fill([](double, double) { return 800 / (4 * kPi); });
    EXPECT_NEAR(parse_ies(iso.text(), "iso.ies").total_flux(), 800, 1e-9 * 800);
}

TEST(Ies, AbsolutePhotometry) {
    IesFile f;
    f.lumens = -1;
    PhotometricData d = parse_ies(f.text(), "abs.ies");
    EXPECT_EQ(d.lamp_lumens, -1);
    EXPECT_EQ(d.nominal_flux(), -1);
    EXPECT_EQ(d.candela[0][0], 100);
    EXPECT_GT(d.total_flux(), 0);
}

// ---- units and luminous opening -----------------------------------------------------------

TEST(Ies, FeetAndMetres) {
    IesFile f;
    f.units = 1;
    f.width = 2;
    f.length = 4;
    PhotometricData d = parse_ies(f.text(), "ft.ies");
    EXPECT_EQ(d.units_type, 1);
    EXPECT_DOUBLE_EQ(d.width, 0.6096);
    EXPECT_DOUBLE_EQ(d.length, 1.2192);
    EXPECT_EQ(d.height, 0);
    EXPECT_EQ(d.shape, LuminousShape::Rectangular);

    f.units = 2;
    d = parse_ies(f.text(), "m.ies");
    EXPECT_EQ(d.width, 2);
    EXPECT_EQ(d.length, 4);

    f.width = -0.5;
    f.length = -0.5;
    f.height = 0;
    d = parse_ies(f.text(), "m.ies");
    EXPECT_EQ(d.shape, LuminousShape::Circular);
    EXPECT_EQ(d.width, 0.5);

    f.units = 1;
    f.height = -0.5;
    d = parse_ies(f.text(), "ft.ies");
    EXPECT_EQ(d.shape, LuminousShape::Sphere);
    EXPECT_DOUBLE_EQ(d.height, 0.5 * 0.3048);

    f.width = -1;
    f.length = 3;
    f.height = -1;
    EXPECT_EQ(parse_ies(f.text(), "ft.ies").shape, LuminousShape::HorizontalCylinderAlong);
}

// ---- tilt ---------------------------------------------------------------------------------

TEST(Ies, TiltNoneIncludeAndFile) {
    IesFile f;
    EXPECT_EQ(parse_ies(f.text(), "n.ies").tilt.mode, "NONE");
    EXPECT_TRUE(parse_ies(f.text(), "n.ies").tilt.angles.empty());

    // Inline block spread over lines in an unusual way.
    f.tilt = "TILT=INCLUDE";
    f.tilt_block = {"1", "7", "0 15 30 45", "60 75 90", "1.0 .95 .94 .90 .88 .87 .98"};
    PhotometricData d = parse_ies(f.text(), "inc.ies");
    EXPECT_EQ(d.tilt.mode, "INCLUDE");
    EXPECT_EQ(d.tilt.lamp_to_luminaire_geometry, 1);
    EXPECT_EQ(d.tilt.angles, range(0, 90, 15));
    ASSERT_EQ(d.tilt.factors.size(), 7u);
    EXPECT_DOUBLE_EQ(d.tilt.factors[1], 0.95);
    EXPECT_DOUBLE_EQ(d.tilt.factor(7.5), 0.975);
    EXPECT_EQ(d.candela[0][0], 100);  // tilt factors are not applied to the table

    // TILT=<file>, relative to the IES file's directory.
    auto dir = temp_dir();
    write_file(dir / "lamp.tlt", "3\n3\n0 45 90\n1 0.9 0.8\n");
    f.tilt = "TILT=lamp.tlt";
    f.tilt_block.clear();
    write_file(dir / "fixture.ies", f.text());
    d = read_ies((dir / "fixture.ies").string());
    EXPECT_EQ(d.tilt.mode, "lamp.tlt");
    EXPECT_EQ(d.tilt.lamp_to_luminaire_geometry, 3);
    EXPECT_EQ(d.tilt.angles, (std::vector<double>{0, 45, 90}));
    EXPECT_EQ(d.tilt.factors, (std::vector<double>{1, 0.9, 0.8}));
    EXPECT_EQ(d.source, (dir / "fixture.ies").string());
    EXPECT_EQ(d.candela[0][1], 80);
}

// ---- photometric types and symmetry -------------------------------------------------------

TEST(Ies, TypeCSymmetries) {
    auto f_c = [](double c, double g) {
        return 100 + g + 20 * std::cos(c * kDeg) + 5 * std::sin(c * kDeg);
    };
    struct Case {
        std::vector<double> h;
        int mirrors;  // 0 rotational, 1 quadrant, 2 about 0-180, 3 about 90-270, 4 none
    };
    const Case cases[] = {{{0}, 0},
                          {range(0, 90, 22.5), 1},
                          {range(0, 180, 30), 2},
                          {range(90, 270, 30), 3},
                          {range(0, 360, 30), 4},
                          {range(0, 330, 30), 4}};
    for (const auto& c : cases) {
        IesFile f;
        f.v = range(0, 180, 10);
        f.h = c.h;
        f.fill(f_c);
        PhotometricData d = parse_ies(f.text(), "sym.ies");
        SCOPED_TRACE(c.mirrors);
        for (size_t i = 0; i < f.h.size(); ++i) {
            for (size_t j = 0; j < f.v.size(); ++j) {
                EXPECT_DOUBLE_EQ(d.intensity(f.v[j], f.h[i]), f.cd[i][j]);
            }
        }
        for (double g : {5.0, 50.0, 95.0, 170.0}) {
            for (double cc : {0.0, 12.0, 40.0, 77.0, 90.0}) {
                const double i = d.intensity(g, cc);
                if (c.mirrors == 0) {
                    EXPECT_DOUBLE_EQ(d.intensity(g, cc + 123), i);
                }
                if (c.mirrors == 1 || c.mirrors == 2) {
                    EXPECT_NEAR(d.intensity(g, -cc), i, 1e-9);
                }
                if (c.mirrors == 1) {
                    EXPECT_NEAR(d.intensity(g, 180 - cc), i, 1e-9);
                    EXPECT_NEAR(d.intensity(g, 180 + cc), i, 1e-9);
                }
                if (c.mirrors == 3) {
                    EXPECT_NEAR(d.intensity(g, 180 - cc), i, 1e-9);
                }
                EXPECT_NEAR(d.intensity(g, cc + 360), i, 1e-9);
            }
        }
    }
}

TEST(Ies, TypeCVerticalRanges) {
    for (auto v : {range(0, 90, 15), range(90, 180, 15), range(0, 180, 15)}) {
        IesFile f;
        f.v = v;
        f.h = {0};
        f.fill([](double, double g) { return 10 + g; });
        PhotometricData d = parse_ies(f.text(), "vr.ies");
        EXPECT_DOUBLE_EQ(d.intensity(v.front(), 0), 10 + v.front());
        EXPECT_DOUBLE_EQ(d.intensity(v.back(), 0), 10 + v.back());
        EXPECT_EQ(d.intensity(45, 0), v.front() > 45 ? 0 : 55);
        EXPECT_EQ(d.intensity(135, 0), v.back() < 135 ? 0 : 145);
    }
}

TEST(Ies, TypesBAndA) {
    for (int type : {2, 3}) {
        for (bool symmetric : {false, true}) {
            IesFile f;
            f.type = type;
            f.v = symmetric ? range(0, 90, 15) : range(-90, 90, 15);
            f.h = symmetric ? range(0, 90, 30) : range(-90, 90, 30);
            f.fill([](double, double) { return 50; });
            PhotometricData d = parse_ies(f.text(), "ab.ies");
            SCOPED_TRACE(type);
            EXPECT_EQ(d.type, type == 2 ? PhotometricType::B : PhotometricType::A);
            // Constant over the front hemisphere: 2 pi x 50 lm.
            EXPECT_NEAR(d.total_flux(), 2 * kPi * 50, 1e-9);
            // Front (nadir for B, +x for A) lit, back dark.
            if (type == 2) {
                EXPECT_EQ(d.intensity(0, 0), 50);
                EXPECT_EQ(d.intensity(180, 0), 0);
            } else {
                EXPECT_EQ(d.intensity(90, 0), 50);
                EXPECT_EQ(d.intensity(90, 180), 0);
            }
        }
    }
    // A Type B table that records its own angles: photometric horizontal is V = 90.
    IesFile f;
    f.type = 2;
    f.v = range(-90, 90, 30);
    f.h = range(-90, 90, 30);
    f.fill([](double h, double v) { return 1000 + v * std::cos(h * kDeg) + 3 * h; });
    PhotometricData d = parse_ies(f.text(), "b.ies");
    EXPECT_NEAR(d.intensity(90, 0), 1000 + 90, 1e-9);
    EXPECT_NEAR(d.intensity(30, 180), 1000 - 30, 1e-9);
}

// ---- free format --------------------------------------------------------------------------

TEST(Ies, NumbersMaySpanLinesAndUseCommas) {
    IesFile f;
    f.v = {0, 30, 60, 90};
    f.h = {0, 90};
    f.fill([](double h, double v) { return 5 + v + h; });
    PhotometricData ref = parse_ies(f.text(), "ref.ies");
    const std::string head = "IESNA:LM-63-2002\n[TEST] X\nTILT=NONE\n";
    const std::string one_line =
        head + "1,1000,1,4,2,1,2,0,0,0,1,1,60,0,30,60,90,0,90,5,35,65,95,95,125,155,185\n";
    const std::string one_per_line =
        head +
        "1\n1000\n1\n4\n2\n1\n2\n0\n0\n0\n1\n1\n60\n0\n30\n60\n90\n0\n90\n"
        "5\n35\n65\n95\n95\n125\n155\n185\n";
    const std::string ragged = head +
                               "1 1000 1 4\n2 1\t2 0 0 0 1 1 60 0\n30, 60 , 90\n0\n"
                               "90 5 35 65 95 95\n125 155\n185\n\n\n";
    for (const auto& text : {one_line, one_per_line, ragged}) {
        PhotometricData d = parse_ies(text, "free.ies");
        EXPECT_EQ(d.vertical_angles, ref.vertical_angles);
        EXPECT_EQ(d.horizontal_angles, ref.horizontal_angles);
        EXPECT_EQ(d.candela, ref.candela);
    }
}

TEST(Ies, LineEndingsAndByteOrderMark) {
    IesFile f;
    PhotometricData ref = parse_ies(f.text(), "x.ies");
    EXPECT_EQ(parse_ies(f.text("\r\n"), "x.ies").candela, ref.candela);
    EXPECT_EQ(parse_ies(f.text("\r"), "x.ies").candela, ref.candela);
    EXPECT_EQ(parse_ies("\xEF\xBB\xBF" + f.text(), "x.ies").version, "LM-63-2002");
    // Exponents, explicit signs and "2.0" as a count are numbers too.
    const std::string text =
        "IESNA:LM-63-1995\nTILT=NONE\n1 1.0E+03 +1 3.0 1 1 2 0 0 0 1 1 60\n0 45 9e1\n0\n"
        "1e2 8.0e+01 20.\n";
    PhotometricData d = parse_ies(text, "e.ies");
    EXPECT_EQ(d.lamp_lumens, 1000);
    EXPECT_EQ(d.candela, ref.candela);
}

// ---- malformed input ----------------------------------------------------------------------

/// A valid 9-line file; `line` (1-based) replaced by `text` (or removed when text is null).
std::string base(int line = 0, const char* text = nullptr) {
    const char* lines[] = {"IESNA:LM-63-2002",
                           "[TEST] BAD-1",
                           "[MANUFAC] Acme",
                           "TILT=NONE",
                           "1 1000 1 3 1 1 2 0 0 0",
                           "1 1 50",
                           "0 45 90",
                           "0",
                           "100 80 20"};
    std::string s;
    for (int i = 1; i <= 9; ++i) {
        if (i == line) {
            if (text) s += std::string(text) + "\n";
        } else {
            s += std::string(lines[i - 1]) + "\n";
        }
    }
    return s;
}

TEST(IesErrors, BaseFileIsValid) { EXPECT_NO_THROW(parse_ies(base(), "bad.ies")); }

TEST(IesErrors, Truncated) {
    expect_error([] { parse_ies(base(9, nullptr), "bad.ies"); }, "bad.ies", 8,
                 "unexpected end of file");
    expect_error([] { parse_ies(base(9, "100 80"), "bad.ies"); }, "bad.ies", 9,
                 "unexpected end of file");
    expect_error([] { parse_ies("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3\n", "bad.ies"); },
                 "bad.ies", 3, "the number of horizontal angles");
    expect_error([] { parse_ies("IESNA:LM-63-2002\nTILT=NONE\n", "bad.ies"); }, "bad.ies", 2,
                 "the number of lamps");
}

TEST(IesErrors, WrongCounts) {
    // Too few announced: values left over.
    expect_error([] { parse_ies(base(9, "100 80 20 5"), "bad.ies"); }, "bad.ies", 9,
                 "expected the end of the file after 1 x 3 candela values");
    // Too many announced: the file is too short for them.
    expect_error([] { parse_ies(base(5, "1 1000 1 4 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 9,
                 "expected 4 vertical angles");
    // Absurd counts are caught before any allocation.
    expect_error([] { parse_ies(base(5, "1 1000 1 1000000000 1000000000 1 2 0 0 0"), "bad.ies"); },
                 "bad.ies", 9, "unexpected end of file");
    expect_error([] { parse_ies(base(5, "1 1000 1 -3 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "the number of vertical angles as an integer between 1 and");
    expect_error([] { parse_ies(base(5, "1 1000 1 2.5 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "the number of vertical angles as an integer");
    expect_error([] { parse_ies(base(5, "-1 1000 1 3 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "the number of lamps as an integer");
}

TEST(IesErrors, NegativeCandela) {
    expect_error([] { parse_ies(base(9, "100 -80 20"), "bad.ies"); }, "bad.ies", 9,
                 "the candela value for horizontal angle 0 and vertical angle 45 to be "
                 "non-negative, found '-80'");
}

TEST(IesErrors, NonMonotonicAngles) {
    expect_error([] { parse_ies(base(7, "0 90 45"), "bad.ies"); }, "bad.ies", 7,
                 "expected the vertical angles to increase strictly, found '45' after 90");
    const std::string text =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 3 1 2 0 0 0\n1 1 0\n0 90\n0 90\n45\n"
        "1 2\n3 4\n5 6\n";
    expect_error([&] { parse_ies(text, "bad.ies"); }, "bad.ies", 7,
                 "expected the horizontal angles to increase strictly");
    expect_error([] { parse_ies(base(7, "0 45 45"), "bad.ies"); }, "bad.ies", 7,
                 "increase strictly");
}

TEST(IesErrors, NotFinite) {
    expect_error([] { parse_ies(base(9, "100 nan 20"), "bad.ies"); }, "bad.ies", 9,
                 "as a finite number, found 'nan'");
    expect_error([] { parse_ies(base(5, "1 1000 inf 3 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "the candela multiplier as a finite number");
    expect_error([] { parse_ies(base(7, "0 45 1e999"), "bad.ies"); }, "bad.ies", 7,
                 "finite number");
}

TEST(IesErrors, NonNumeric) {
    expect_error([] { parse_ies(base(9, "100 abc 20"), "bad.ies"); }, "bad.ies", 9,
                 "(a number), found 'abc'");
    expect_error([] { parse_ies(base(6, "1 1 50W"), "bad.ies"); }, "bad.ies", 6,
                 "expected the input watts (a number), found '50W'");
    expect_error([] { parse_ies(base(8, "0\x01"), "bad.ies"); }, "bad.ies", 8, "found '0\\x01'");
}

TEST(IesErrors, MissingOrBadTilt) {
    expect_error([] { parse_ies(base(4, nullptr), "bad.ies"); }, "bad.ies", 4,
                 "missing TILT line: expected 'TILT=NONE'");
    expect_error([] { parse_ies(base(4, "TILT="), "bad.ies"); }, "bad.ies", 4,
                 "expected NONE, INCLUDE or a file name after TILT=");
    expect_error([] { parse_ies(base(4, "TILT=INCLUDE\n7 2 0 90 1 1"), "bad.ies"); }, "bad.ies", 5,
                 "the lamp-to-luminaire geometry of the tilt data (1, 2 or 3)");
    expect_error([] { parse_ies(base(4, "TILT=INCLUDE\n1 3 0 90 45 1 1 1"), "bad.ies"); },
                 "bad.ies", 5, "tilt angles to increase strictly");
    expect_error([] { parse_ies(base(4, "TILT=INCLUDE\n1 2 0 90 1 -1"), "bad.ies"); }, "bad.ies", 5,
                 "tilt multiplying factor 2 of 2 to be non-negative");
    expect_error([] { parse_ies(base(4, "TILT=no_such_file.tlt"), "/nonexistent/bad.ies"); },
                 "/nonexistent/bad.ies", 4, "a readable tilt file 'no_such_file.tlt'");
    // Errors inside a tilt file name the tilt file and its line.
    auto dir = temp_dir();
    write_file(dir / "short.tlt", "1\n3\n0 45 90\n1 0.9\n");
    const std::string ies = (dir / "t.ies").string();
    expect_error([&] { parse_ies(base(4, "TILT=short.tlt"), ies); }, (dir / "short.tlt").string(),
                 4, "unexpected end of file: expected 3 tilt angles and 3 multiplying factors");
}

TEST(IesErrors, IllegalAngleSets) {
    expect_error([] { parse_ies(base(8, "45"), "bad.ies"); }, "bad.ies", 8,
                 "expected the first horizontal angle of a Type C file to be 0");
    const std::string last120 =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 2 1 2 0 0 0\n1 1 0\n0 90\n0 120\n1 2 3 4\n";
    expect_error([&] { parse_ies(last120, "bad.ies"); }, "bad.ies", 6,
                 "expected the last horizontal angle of a Type C file to be 0, 90, 180 or 360");
    const std::string from90 =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 2 1 2 0 0 0\n1 1 0\n0 90\n90 180\n1 2 3 4\n";
    expect_error([&] { parse_ies(from90, "bad.ies"); }, "bad.ies", 6,
                 "expected the last horizontal angle to be 270 when the first is 90");
    expect_error([] { parse_ies(base(7, "10 45 90"), "bad.ies"); }, "bad.ies", 7,
                 "expected the first vertical angle of a Type C file to be 0 or 90");
    expect_error([] { parse_ies(base(7, "0 45 80"), "bad.ies"); }, "bad.ies", 7,
                 "expected the last vertical angle of a Type C file to be 90 or 180");
    expect_error([] { parse_ies(base(7, "0 45 400"), "bad.ies"); }, "bad.ies", 7,
                 "between -360 and 360");
    // Type B: horizontal angles must start at -90 or 0 and end at 90.
    const std::string type_b =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 2 2 2 0 0 0\n1 1 0\n-90 90\n10 90\n1 2 3 4\n";
    expect_error([&] { parse_ies(type_b, "bad.ies"); }, "bad.ies", 6,
                 "expected the first horizontal angle of a Type B file to be -90 or 0");
    const std::string type_a =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 2 3 2 0 0 0\n1 1 0\n-90 80\n0 90\n1 2 3 4\n";
    expect_error([&] { parse_ies(type_a, "bad.ies"); }, "bad.ies", 5,
                 "expected the last vertical angle of a Type A file to be 90");
}

TEST(IesErrors, BadCodesAndFactors) {
    expect_error([] { parse_ies(base(5, "1 1000 1 3 1 4 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "the photometric type (1 = C, 2 = B, 3 = A) as an integer between 1 and 3");
    expect_error([] { parse_ies(base(5, "1 1000 1 3 1 1 3 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "the units type (1 = feet, 2 = metres)");
    expect_error([] { parse_ies(base(5, "1 -5 1 3 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "expected the lumens per lamp to be positive, or -1");
    expect_error([] { parse_ies(base(5, "1 1000 0 3 1 1 2 0 0 0"), "bad.ies"); }, "bad.ies", 5,
                 "expected the candela multiplier to be positive");
    expect_error([] { parse_ies(base(6, "-1 1 50"), "bad.ies"); }, "bad.ies", 6,
                 "expected the ballast factor to be positive");
    expect_error([] { parse_ies(base(6, "1 1 -50"), "bad.ies"); }, "bad.ies", 6,
                 "expected the input watts to be non-negative");
}

TEST(IesErrors, VersionAndEmpty) {
    expect_error([] { parse_ies(base(1, "IESNA:LM-63-2025"), "bad.ies"); }, "bad.ies", 1,
                 "unknown LM-63 version line 'IESNA:LM-63-2025'");
    expect_error([] { parse_ies("", "bad.ies"); }, "bad.ies", 1, "empty file");
    // In 1986/1991 files the ballast-lamp factor must be positive.
    const std::string v1991 =
        "IESNA91\n[TEST] X\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 0 50\n0 45 90\n0\n100 80 20\n";
    expect_error([&] { parse_ies(v1991, "bad.ies"); }, "bad.ies", 5,
                 "expected the ballast-lamp photometric factor to be positive");
}

TEST(IesErrors, MissingFile) {
    try {
        read_ies("/nonexistent/dir/x.ies");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.ies"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
    }
}

// ---- never crash --------------------------------------------------------------------------

/// Parses and returns normally or with an sr::Error; anything else fails the test.
void parse_or_error(const std::string& text) {
    try {
        PhotometricData d = parse_ies(text, "fuzz.ies");
        (void)d.total_flux();
        (void)d.intensity(33, 77);
    } catch (const Error&) {
    }
}

TEST(IesRobustness, EveryPrefixAndEveryByteChange) {
    IesFile f;
    f.tilt = "TILT=INCLUDE";
    f.tilt_block = {"2 3", "0 45 90", "1 .9 .8"};
    f.v = {0, 45, 90, 135, 180};
    f.h = {0, 90, 180};
    f.fill([](double h, double v) { return 10 + v + h; });
    const std::string text = f.text();
    for (size_t n = 0; n <= text.size(); ++n) parse_or_error(text.substr(0, n));
    for (size_t i = 0; i < text.size(); ++i) {
        for (char c : {'-', 'x', ',', '\n', '9', ' ', '\0', '.', '[', 'e'}) {
            std::string t = text;
            t[i] = c;
            parse_or_error(t);
        }
    }
    // Binary garbage.
    std::string junk;
    for (int i = 0; i < 4096; ++i) junk += static_cast<char>((i * 2654435761u) >> 13);
    parse_or_error(junk);
    parse_or_error("TILT=NONE\n" + junk);
    parse_or_error("TILT=INCLUDE\n" + junk);
}

}  // namespace
}  // namespace sr
