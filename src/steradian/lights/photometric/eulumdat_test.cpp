#include "steradian/lights/photometric/eulumdat.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
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

struct Lamps {
    int count;
    std::string type;
    double flux;
    std::string colour, cri;
    double watts;
};

/// An EULUMDAT file assembled field by field (one per line, in the format's order).
struct LdtFile {
    std::string company = "Acme Lighting GmbH";
    int ityp = 1, isym = 1;
    int mc = 24;
    double dc = 15;
    int ng = 19;
    double dg = 10;
    std::string report = "R-42", name = "Downlight 2000", number = "DL-2000",
                file_name = "dl2000.ldt", date = "2024-05-01 / tester";
    double lum_length = 600, lum_width = 600, lum_height = 80;
    double area_length = 500, area_width = 0;
    double h_c0 = 0, h_c90 = 0, h_c180 = 0, h_c270 = 0;
    double dff = 100, lorl = 80, cfli = 1, tilt = 0;
    std::vector<Lamps> lamps = {{1, "LED 2000", 2000, "3000K", "80", 25}};
    std::vector<double> dr = {0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95};
    std::vector<double> c = range(0, 345, 15);
    std::vector<double> g = range(0, 180, 10);
    std::vector<std::vector<double>> planes;  // the stored planes, in file order

    /// Stored planes per the format's Mc1..Mc2 rule, values f(C, gamma) in cd/klm.
    void fill(const std::function<double(double, double)>& f) {
        mc = static_cast<int>(c.size());
        ng = static_cast<int>(g.size());
        int first = isym == 3 ? 3 * mc / 4 + 1 : 1;
        int count = isym == 0 ? mc : isym == 1 ? 1 : isym == 4 ? mc / 4 + 1 : mc / 2 + 1;
        planes.clear();
        for (int p = 0; p < count; ++p) {
            double cc = c[static_cast<size_t>((first - 1 + p) % mc)];
            std::vector<double> row;
            for (double gg : g) row.push_back(f(cc, gg));
            planes.push_back(row);
        }
    }

    int lamp_line() const { return 27; }
    int c_line(int k) const { return 27 + 6 * static_cast<int>(lamps.size()) + 10 + k; }
    int g_line(int k) const { return c_line(mc) + k; }
    int i_line(int plane, int k) const { return g_line(ng) + plane * ng + k; }

    std::string text() const {
        std::string s;
        auto add = [&](const auto& x) { s += fmt::format("{}\n", x); };
        add(company);
        add(ityp);
        add(isym);
        add(mc);
        add(dc);
        add(ng);
        add(dg);
        add(report);
        add(name);
        add(number);
        add(file_name);
        add(date);
        for (double x : {lum_length, lum_width, lum_height, area_length, area_width, h_c0, h_c90,
                         h_c180, h_c270, dff, lorl, cfli, tilt})
            add(x);
        add(lamps.size());
        for (const auto& l : lamps) add(l.count);
        for (const auto& l : lamps) add(l.type);
        for (const auto& l : lamps) add(l.flux);
        for (const auto& l : lamps) add(l.colour);
        for (const auto& l : lamps) add(l.cri);
        for (const auto& l : lamps) add(l.watts);
        for (double x : dr) add(x);
        for (double x : c) add(x);
        for (double x : g) add(x);
        for (const auto& row : planes)
            for (double x : row) add(x);
        return s;
    }
};

/// Replaces (1-based) line `line` of text.
std::string with_line(const std::string& text, int line, const std::string& replacement) {
    std::string out;
    size_t start = 0;
    int n = 1;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        out += (n == line ? replacement : text.substr(start, end - start)) + "\n";
        start = end + 1;
        ++n;
    }
    return out;
}

std::string first_lines(const std::string& text, int count) {
    size_t pos = 0;
    for (int i = 0; i < count && pos != std::string::npos; ++i) {
        pos = text.find('\n', pos);
        if (pos != std::string::npos) ++pos;
    }
    return pos == std::string::npos ? text : text.substr(0, pos);
}

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

// ---- scaling and flux ---------------------------------------------------------------------

TEST(Eulumdat, CdPerKlmTimesLampFluxOver1000) {
    LdtFile f;
    f.fill([](double, double g) { return 300 - g; });
    PhotometricData d = parse_eulumdat(f.text(), "a.ldt");
    EXPECT_EQ(d.format, PhotometricFormat::Eulumdat);
    EXPECT_EQ(d.version, "EULUMDAT");
    EXPECT_EQ(d.type, PhotometricType::C);
    EXPECT_EQ(d.candela_multiplier, 2);
    ASSERT_EQ(d.vertical_angles, f.g);
    for (const auto& row : d.candela) {
        ASSERT_EQ(row.size(), f.g.size());
        for (size_t j = 0; j < row.size(); ++j) EXPECT_EQ(row[j], 2 * (300 - f.g[j]));
    }
    // The conversion factor multiplies too.
    f.cfli = 1.5;
    d = parse_eulumdat(f.text(), "a.ldt");
    EXPECT_DOUBLE_EQ(d.candela[0][3], 3 * (300 - 30));
    EXPECT_DOUBLE_EQ(d.intensity(30, 77), 3 * (300 - 30));
}

TEST(Eulumdat, FluxIsLightOutputRatioTimesLampFlux) {
    // Isotropic cd/klm carrying LOR x 1000 lm per klm: total = LOR x lamp flux, exactly.
    LdtFile f;
    f.lorl = 80;
    f.fill([](double, double) { return 0.8 * 1000 / (4 * kPi); });
    PhotometricData d = parse_eulumdat(f.text(), "iso.ldt");
    EXPECT_DOUBLE_EQ(d.light_output_ratio, 0.8);
    EXPECT_NEAR(d.total_flux(), 0.8 * 2000, 1e-9 * 2000);
    EXPECT_EQ(d.nominal_flux(), 2000);

    // A cosine lobe downwards (1 deg steps) with a quadrant-symmetric table.
    LdtFile lobe;
    lobe.isym = 4;
    lobe.g = range(0, 90, 1);
    lobe.lamps = {{2, "T5", 2 * 2600, "4000K", "1B", 2 * 28}};
    lobe.fill([](double, double g) { return (0.7 * 1000 / kPi) * std::cos(g * kDeg); });
    d = parse_eulumdat(lobe.text(), "lobe.ldt");
    EXPECT_NEAR(d.total_flux(), 0.7 * 5200, 1e-4 * 0.7 * 5200);
    EXPECT_EQ(d.num_lamps, 2);
    EXPECT_EQ(d.lamp_lumens, 2600);
    EXPECT_EQ(d.input_watts, 56);
}

// ---- symmetry -----------------------------------------------------------------------------

TEST(Eulumdat, EverySymmetryExpandsToAllPlanes) {
    struct Case {
        int isym;
        std::function<double(double)> f;  // C dependence with the symmetry
    };
    const Case cases[] = {
        {0, [](double c) { return 100 + 30 * std::cos(c * kDeg) + 20 * std::sin(c * kDeg); }},
        {1, [](double) { return 100.0; }},
        {2, [](double c) { return 100 + 30 * std::cos(c * kDeg); }},
        {3, [](double c) { return 100 + 30 * std::sin(c * kDeg); }},
        {4, [](double c) { return 100 + 30 * std::cos(2 * c * kDeg); }},
    };
    for (const auto& cs : cases) {
        SCOPED_TRACE(cs.isym);
        LdtFile f;
        f.isym = cs.isym;
        f.ityp = cs.isym == 1 ? 1 : 3;
        auto full = [&](double c, double g) { return cs.f(c) * (1.5 + std::cos(g * kDeg)); };
        f.fill(full);
        PhotometricData d = parse_eulumdat(f.text(), "sym.ldt");
        // All Mc planes plus the 0 plane repeated at 360.
        std::vector<double> expected_c = f.c;
        expected_c.push_back(360);
        ASSERT_EQ(d.horizontal_angles, expected_c);
        ASSERT_EQ(d.candela.size(), expected_c.size());
        for (size_t i = 0; i < expected_c.size(); ++i) {
            for (size_t j = 0; j < f.g.size(); ++j) {
                const double want = 2 * full(expected_c[i], f.g[j]);
                EXPECT_NEAR(d.candela[i][j], want, 1e-9 * want);
                EXPECT_NEAR(d.intensity(f.g[j], expected_c[i]), want, 1e-9 * want);
            }
        }
        for (double g : {0.0, 35.0, 90.0, 145.0}) {
            for (double c : {0.0, 20.0, 45.0, 80.0, 100.0, 170.0}) {
                const double i = d.intensity(g, c);
                if (cs.isym == 1) {
                    EXPECT_NEAR(d.intensity(g, c + 77), i, 1e-9);
                }
                if (cs.isym == 2 || cs.isym == 4) {
                    EXPECT_NEAR(d.intensity(g, -c), i, 1e-9);
                }
                if (cs.isym == 3 || cs.isym == 4) {
                    EXPECT_NEAR(d.intensity(g, 180 - c), i, 1e-9);
                }
            }
        }
    }
}

TEST(Eulumdat, NonEquidistantPlanesAreInterpolatedWhenMirrored) {
    LdtFile f;
    f.isym = 4;
    f.dc = 0;
    f.c = {0, 20, 90, 110, 180, 200, 270, 290};
    f.g = {0, 45, 90};
    f.fill([](double c, double g) { return 1000 + c + g; });  // planes 0, 20, 90 stored
    ASSERT_EQ(f.planes.size(), 3u);
    PhotometricData d = parse_eulumdat(f.text(), "ne.ldt");
    // C 110 mirrors to 70, between the stored 20 and 90 planes.
    const double t = 50.0 / 70.0;
    EXPECT_NEAR(d.candela[3][1], 2 * ((1 - t) * (1020 + 45) + t * (1090 + 45)), 1e-9);
    // C 200 mirrors to 20, C 290 to 70.
    EXPECT_NEAR(d.candela[5][0], 2 * 1020, 1e-9);
    EXPECT_NEAR(d.candela[7][2], d.candela[3][2], 1e-9);
}

TEST(Eulumdat, SinglePlaneFile) {
    LdtFile f;
    f.mc = 1;
    f.c = {0};
    f.fill([](double, double g) { return 50 + g; });
    PhotometricData d = parse_eulumdat(f.text(), "one.ldt");
    EXPECT_EQ(d.horizontal_angles, (std::vector<double>{0, 360}));
    EXPECT_EQ(d.intensity(20, 123), 2 * 70);
}

// ---- fields -------------------------------------------------------------------------------

TEST(Eulumdat, FieldsDimensionsAndLampSets) {
    LdtFile f;
    f.lamps = {{3, "TC-L 36W", 3 * 2900, "3000", "1B", 3 * 40},
               {3, "TC-L 36W/840", 3 * 3200, "4000", "1A", 3 * 40}};
    f.fill([](double, double) { return 100; });
    PhotometricData d = parse_eulumdat(f.text(), "f.ldt");
    EXPECT_EQ(d.keywords.at("COMPANY"), "Acme Lighting GmbH");
    EXPECT_EQ(d.keywords.at("LUMINAIRE"), "Downlight 2000");
    EXPECT_EQ(d.keywords.at("LUMINAIRE_NUMBER"), "DL-2000");
    EXPECT_EQ(d.keywords.at("REPORT"), "R-42");
    EXPECT_EQ(d.keywords.at("DATE_USER"), "2024-05-01 / tester");
    ASSERT_EQ(d.lamp_sets.size(), 2u);
    EXPECT_EQ(d.lamp_sets[1].type, "TC-L 36W/840");
    EXPECT_EQ(d.lamp_sets[1].total_flux_lm, 9600);
    EXPECT_EQ(d.lamp_sets[1].colour, "4000");
    EXPECT_EQ(d.lamp_sets[1].cri, "1A");
    // Lamp set 1 sets the scale.
    EXPECT_DOUBLE_EQ(d.candela[0][0], 100 * 8.7);
    EXPECT_EQ(d.num_lamps, 3);
    EXPECT_DOUBLE_EQ(d.lamp_lumens, 2900);
    EXPECT_EQ(d.direct_ratios, f.dr);
    EXPECT_DOUBLE_EQ(d.downward_flux_fraction, 1.0);
    // Circular luminous area of 500 mm diameter.
    EXPECT_EQ(d.shape, LuminousShape::Circular);
    EXPECT_DOUBLE_EQ(d.length, 0.5);
    EXPECT_DOUBLE_EQ(d.width, 0.5);

    f.area_width = 200;
    f.h_c90 = 30;
    d = parse_eulumdat(f.text(), "f.ldt");
    EXPECT_EQ(d.shape, LuminousShape::RectangularWithLuminousSides);
    EXPECT_DOUBLE_EQ(d.width, 0.2);
    EXPECT_DOUBLE_EQ(d.height, 0.03);
    f.area_length = 0;
    f.area_width = 0;
    f.h_c90 = 0;
    EXPECT_EQ(parse_eulumdat(f.text(), "f.ldt").shape, LuminousShape::Point);
}

TEST(Eulumdat, AbsolutePhotometryAndDecimalComma) {
    LdtFile f;
    f.lamps = {{-1, "LED module", 1234, "3000K", "90", 15}};
    f.fill([](double, double) { return 100; });
    PhotometricData d = parse_eulumdat(f.text(), "abs.ldt");
    EXPECT_EQ(d.lamp_lumens, -1);
    EXPECT_EQ(d.nominal_flux(), -1);
    EXPECT_DOUBLE_EQ(d.candela[0][0], 123.4);

    std::string text = with_line(f.text(), 23, "72,5");  // LORL
    text = with_line(text, f.i_line(0, 0), "100,5");     // first intensity
    d = parse_eulumdat(text, "comma.ldt");
    EXPECT_DOUBLE_EQ(d.light_output_ratio, 0.725);
    EXPECT_DOUBLE_EQ(d.candela[0][0], 100.5 * 1.234);
    // Windows line ends.
    std::string crlf;
    for (char ch : f.text()) {
        if (ch == '\n') crlf += '\r';
        crlf += ch;
    }
    EXPECT_EQ(parse_eulumdat(crlf, "crlf.ldt").candela, parse_eulumdat(f.text(), "x").candela);
}

TEST(Eulumdat, ReadFromFile) {
    LdtFile f;
    f.fill([](double, double g) { return 10 + g; });
    auto dir = std::filesystem::path(::testing::TempDir()) /
               fmt::format("sr_ldt_test_{}", static_cast<long>(::getpid()));
    std::filesystem::create_directories(dir);
    const auto path = (dir / "x.ldt").string();
    {
        std::ofstream out(path, std::ios::binary);
        out << f.text();
    }
    PhotometricData d = read_eulumdat(path);
    EXPECT_EQ(d.source, path);
    EXPECT_EQ(d.candela[0][1], 2 * 20);
    EXPECT_THROW(read_eulumdat((dir / "missing.ldt").string()), Error);
}

// ---- malformed input ----------------------------------------------------------------------

LdtFile valid() {
    LdtFile f;
    f.isym = 2;
    f.fill([](double c, double g) { return 100 + 30 * std::cos(c * kDeg) + g; });
    return f;
}

TEST(EulumdatErrors, ValidBaseParses) { EXPECT_NO_THROW(parse_eulumdat(valid().text(), "b.ldt")); }

TEST(EulumdatErrors, HeaderFields) {
    const std::string t = valid().text();
    expect_error([&] { parse_eulumdat(with_line(t, 3, "5"), "b.ldt"); }, "b.ldt", 3,
                 "the symmetry indicator Isym (0-4) as an integer between 0 and 4");
    expect_error([&] { parse_eulumdat(with_line(t, 2, "x"), "b.ldt"); }, "b.ldt", 2,
                 "the type indicator Ityp (0-3) (one number on the line), found 'x'");
    expect_error([&] { parse_eulumdat(with_line(t, 4, "twenty-four"), "b.ldt"); }, "b.ldt", 4,
                 "the number of C planes Mc");
    expect_error([&] { parse_eulumdat(with_line(t, 4, "0"), "b.ldt"); }, "b.ldt", 4,
                 "as an integer between 1 and");
    expect_error([&] { parse_eulumdat(with_line(t, 6, ""), "b.ldt"); }, "b.ldt", 6,
                 "found an empty line");
    expect_error([&] { parse_eulumdat(with_line(t, 24, "0"), "b.ldt"); }, "b.ldt", 24,
                 "conversion factor for luminous intensities to be positive");
    expect_error([&] { parse_eulumdat(with_line(t, 13, "-600"), "b.ldt"); }, "b.ldt", 13,
                 "luminaire length/diameter (mm) to be non-negative");
    expect_error([&] { parse_eulumdat("", "b.ldt"); }, "b.ldt", 1, "empty file");
}

TEST(EulumdatErrors, BadSymmetry) {
    LdtFile f = valid();
    const std::string t = f.text();
    // Isym 4 needs Mc divisible by 4.
    std::string t4 = with_line(with_line(t, 3, "4"), 4, "22");
    expect_error([&] { parse_eulumdat(t4, "b.ldt"); }, "b.ldt", 4,
                 "Mc = 22 to be divisible by 4 for Isym 4");
    // Isym 2 stores C0..C180: the plane Mc/2+1 must be C180.
    LdtFile g = valid();
    g.c[12] = 170;
    expect_error([&] { parse_eulumdat(g.text(), "b.ldt"); }, "b.ldt", g.c_line(12),
                 "expected this C angle to be 180 for Isym 2");
}

TEST(EulumdatErrors, Truncated) {
    const LdtFile f = valid();
    const std::string t = f.text();
    const int total = f.i_line(static_cast<int>(f.planes.size()) - 1, f.ng - 1);
    expect_error([&] { parse_eulumdat(first_lines(t, total - 1), "b.ldt"); }, "b.ldt", total - 1,
                 fmt::format("expected {} lines", total));
    expect_error([&] { parse_eulumdat(first_lines(t, 10), "b.ldt"); }, "b.ldt", 10,
                 "expected the file name on line 11");
    expect_error([&] { parse_eulumdat(first_lines(t, 30), "b.ldt"); }, "b.ldt", 30,
                 "unexpected end of file");
    // Counts larger than the file: refused before allocating.
    expect_error([&] { parse_eulumdat(with_line(t, 6, "1000000"), "b.ldt"); }, "b.ldt", total,
                 "unexpected end of file");
    // Counts smaller than the data: lines left over.
    // (Ng = 18 instead of 19: 1 + 13 lines of the 13 planes are left over.)
    expect_error([&] { parse_eulumdat(with_line(t, 6, "18"), "b.ldt"); }, "b.ldt", total - 13,
                 "expected the end of the file");
}

TEST(EulumdatErrors, BadValues) {
    const LdtFile f = valid();
    const std::string t = f.text();
    expect_error([&] { parse_eulumdat(with_line(t, f.i_line(2, 5), "-3"), "b.ldt"); }, "b.ldt",
                 f.i_line(2, 5),
                 "the luminous intensity (cd/klm) at C 30 gamma 50 to be "
                 "non-negative");
    expect_error([&] { parse_eulumdat(with_line(t, f.i_line(0, 0), "NaN"), "b.ldt"); }, "b.ldt",
                 f.i_line(0, 0), "as a finite number");
    expect_error([&] { parse_eulumdat(with_line(t, f.g_line(4), "25"), "b.ldt"); }, "b.ldt",
                 f.g_line(4), "expected the gamma angles to increase strictly, found '25'");
    expect_error([&] { parse_eulumdat(with_line(t, f.g_line(18), "190"), "b.ldt"); }, "b.ldt",
                 f.g_line(18), "between 0 and 180");
    expect_error([&] { parse_eulumdat(with_line(t, f.c_line(0), "5"), "b.ldt"); }, "b.ldt",
                 f.c_line(0), "expected the first C angle to be 0");
    expect_error([&] { parse_eulumdat(with_line(t, f.c_line(3), "15"), "b.ldt"); }, "b.ldt",
                 f.c_line(3), "expected the C angles to increase strictly");
    expect_error([&] { parse_eulumdat(with_line(t, f.lamp_line() + 2, "0"), "b.ldt"); }, "b.ldt",
                 f.lamp_line() + 2, "positive total luminous flux for lamp set 1");
    expect_error([&] { parse_eulumdat(with_line(t, f.lamp_line(), "0"), "b.ldt"); }, "b.ldt",
                 f.lamp_line(), "a non-zero number of lamps");
    expect_error([&] { parse_eulumdat(with_line(t, 26, "0"), "b.ldt"); }, "b.ldt", 26,
                 "the number of lamp sets n as an integer between 1 and");
}

TEST(EulumdatRobustness, EveryPrefixAndLineChange) {
    LdtFile f = valid();
    f.g = range(0, 180, 30);
    f.c = range(0, 330, 30);
    f.fill([](double c, double g) { return 100 + 30 * std::cos(c * kDeg) + g; });
    const std::string t = f.text();
    auto attempt = [](const std::string& text) {
        try {
            PhotometricData d = parse_eulumdat(text, "fuzz.ldt");
            (void)d.total_flux();
            (void)d.intensity(12, 34);
        } catch (const Error&) {
        }
    };
    for (size_t n = 0; n <= t.size(); ++n) attempt(t.substr(0, n));
    const int lines = f.i_line(static_cast<int>(f.planes.size()) - 1, f.ng - 1);
    for (int line = 1; line <= lines; ++line) {
        for (const char* r : {"", "-1", "0", "4", "1e9", "abc", "360", "2147483648"}) {
            attempt(with_line(t, line, r));
        }
    }
}

}  // namespace
}  // namespace sr
