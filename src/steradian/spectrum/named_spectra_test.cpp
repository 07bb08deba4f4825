#include <gtest/gtest.h>

#include <algorithm>

#include "steradian/spectrum/spectrum.h"

namespace sr {
namespace {

/// Normal-incidence reflectance of a conductor with complex index n + i k in air.
double normal_reflectance(double n, double k) {
    return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
}

Float eval_named(const char* name, Float lambda) {
    std::optional<Spectrum> s = named_spectrum(name);
    EXPECT_TRUE(s) << name;
    return s ? (*s)(lambda) : 0;
}

TEST(NamedSpectra, ListsPbrtNames) {
    std::vector<std::string> names = named_spectrum_names();
    const char* required[] = {
        "stdillum-D65",  "stdillum-D50",  "stdillum-A",   "stdillum-F1",    "stdillum-F12",
        "illum-acesD60", "glass-BK7",     "glass-BAF10",  "glass-FK51A",    "glass-LASF9",
        "glass-F5",      "glass-F10",     "glass-F11",    "glass-SF5",      "glass-SF10",
        "glass-SF11",    "metal-Ag-eta",  "metal-Ag-k",   "metal-Al-eta",   "metal-Al-k",
        "metal-Au-eta",  "metal-Au-k",    "metal-Cu-eta", "metal-Cu-k",     "metal-CuZn-eta",
        "metal-CuZn-k",  "metal-MgO-eta", "metal-MgO-k",  "metal-TiO2-eta", "metal-TiO2-k",
    };
    for (const char* r : required) {
        EXPECT_NE(std::find(names.begin(), names.end(), r), names.end()) << r;
        EXPECT_TRUE(named_spectrum(r)) << r;
    }
    EXPECT_FALSE(named_spectrum("metal-Unobtainium-eta"));
    for (const std::string& n : names) EXPECT_TRUE(named_spectrum(n)) << n;
}

TEST(NamedSpectra, ListsCieLedAndHighPressureIlluminants) {
    std::vector<std::string> names = named_spectrum_names();
    const char* required[] = {
        "stdillum-LED-B1", "stdillum-LED-B2",  "stdillum-LED-B3",   "stdillum-LED-B4",
        "stdillum-LED-B5", "stdillum-LED-BH1", "stdillum-LED-RGB1", "stdillum-LED-V1",
        "stdillum-LED-V2", "stdillum-HP1",     "stdillum-HP2",      "stdillum-HP3",
        "stdillum-HP4",    "stdillum-HP5",
    };
    for (const char* r : required) {
        EXPECT_NE(std::find(names.begin(), names.end(), r), names.end()) << r;
        EXPECT_TRUE(named_spectrum(r)) << r;
    }
    EXPECT_FALSE(named_spectrum("stdillum-LED-B6"));
    EXPECT_FALSE(named_spectrum("stdillum-HP6"));
}

TEST(NamedSpectra, CieLedAndHighPressureChromaticitiesMatchCie015) {
    struct Case {
        const char* name;
        double x, y;
    };
    // CIE 015:2018 "Colorimetry", 4th ed.: CIE 1931 (x, y) of the illuminants representing
    // typical LED lamps and high-pressure discharge lamps, as published (4 decimals). CIE
    // computes them from the 5 nm tables; here the table is interpolated linearly to 1 nm,
    // which moves (x, y) by up to ~3e-4 for the line spectra.
    const Case cases[] = {
        {"stdillum-LED-B1", 0.4560, 0.4078},   {"stdillum-LED-B2", 0.4357, 0.4012},
        {"stdillum-LED-B3", 0.3756, 0.3723},   {"stdillum-LED-B4", 0.3422, 0.3502},
        {"stdillum-LED-B5", 0.3118, 0.3236},   {"stdillum-LED-BH1", 0.4474, 0.4066},
        {"stdillum-LED-RGB1", 0.4557, 0.4211}, {"stdillum-LED-V1", 0.4548, 0.4044},
        {"stdillum-LED-V2", 0.3781, 0.3775},   {"stdillum-HP1", 0.5330, 0.4150},
        {"stdillum-HP2", 0.4778, 0.4158},      {"stdillum-HP3", 0.4302, 0.4075},
        {"stdillum-HP4", 0.3812, 0.3797},      {"stdillum-HP5", 0.3776, 0.3713},
    };
    for (const Case& c : cases) {
        std::optional<Spectrum> s = named_spectrum(c.name);
        ASSERT_TRUE(s) << c.name;
        Xyz xyz = spectrum_to_xyz(*s);
        EXPECT_NEAR(xyz.y, 1.0, 1e-4) << c.name;  // normalised like F1..F12
        double sum = double(xyz.x) + double(xyz.y) + double(xyz.z);
        EXPECT_NEAR(xyz.x / sum, c.x, 5e-4) << c.name;
        EXPECT_NEAR(xyz.y / sum, c.y, 5e-4) << c.name;
    }
}

TEST(NamedSpectra, HighPressureSodiumIsSodiumDominated) {
    // HP1 (standard high-pressure sodium, CIE 015:2018): its largest tabulated value is
    // 334.84 at 595 nm and the 590 nm self-reversal dip (142.55) lies between the broadened
    // sodium D wings at 585 nm (297.98) and 595 nm.
    Spectrum hp1 = *named_spectrum("stdillum-HP1");
    for (int l = 380; l <= 780; l += 5) {
        if (l != 595) {
            EXPECT_LT(hp1(Float(l)), hp1(595)) << l;
        }
    }
    EXPECT_NEAR(hp1(590) / hp1(595), 142.55 / 334.84, 1e-4);
    EXPECT_NEAR(hp1(585) / hp1(595), 297.98 / 334.84, 1e-4);
}

TEST(NamedSpectra, DefinedAndNonNegativeOverVisibleRange) {
    for (const std::string& n : named_spectrum_names()) {
        Spectrum s = *named_spectrum(n);
        for (Float l = kLambdaMin; l <= kLambdaMax; l += 0.5f) {
            Float v = s(l);
            ASSERT_TRUE(std::isfinite(v)) << n << " " << l;
            ASSERT_GE(v, 0) << n << " " << l;
        }
        if (n.find("-k") == std::string::npos) {
            EXPECT_GT(s(550), 0) << n;
        }
    }
}

TEST(NamedSpectra, IlluminantsHaveUnitLuminance) {
    for (const std::string& n : named_spectrum_names())
        if (n.rfind("stdillum-", 0) == 0 || n.rfind("illum-", 0) == 0) {
            EXPECT_NEAR(spectrum_to_xyz(*named_spectrum(n)).y, 1.0, 1e-4) << n;
        }
}

TEST(NamedSpectra, GlassIndicesMatchSchottCatalogue) {
    // n_d at the helium d line, 587.5618 nm, from the SCHOTT data sheets.
    constexpr Float d_line = 587.5618f;
    EXPECT_NEAR(eval_named("glass-BK7", d_line), 1.5168, 1e-4);
    EXPECT_NEAR(eval_named("glass-BAF10", d_line), 1.67003, 1e-4);
    EXPECT_NEAR(eval_named("glass-FK51A", d_line), 1.48656, 1e-4);
    EXPECT_NEAR(eval_named("glass-LASF9", d_line), 1.85025, 1e-4);
    EXPECT_NEAR(eval_named("glass-F5", d_line), 1.6727, 1e-4);
    EXPECT_NEAR(eval_named("glass-F10", d_line), 1.72828, 1e-4);
    EXPECT_NEAR(eval_named("glass-F11", d_line), 1.78472, 1e-4);
    EXPECT_EQ(eval_named("glass-SF11", d_line), eval_named("glass-F11", d_line));
    // Abbe number V_d = (n_d - 1) / (n_F - n_C) of N-BK7 is 64.17 (F: 486.1327 nm,
    // C: 656.2725 nm): normal dispersion of the right size.
    Float nd = eval_named("glass-BK7", d_line);
    Float vd = (nd - 1) / (eval_named("glass-BK7", 486.1327f) - eval_named("glass-BK7", 656.2725f));
    EXPECT_NEAR(vd, 64.17, 0.1);
}

TEST(NamedSpectra, GlassDispersionIsNormal) {
    for (const char* g : {"glass-BK7", "glass-BAF10", "glass-FK51A", "glass-LASF9", "glass-F5",
                          "glass-F10", "glass-F11"}) {
        for (Float l = 361; l <= 830; l += 1)
            EXPECT_LT(eval_named(g, l), eval_named(g, l - 1)) << g << " " << l;
    }
}

TEST(NamedSpectra, NobleMetalReflectanceIsPlausible) {
    // Consistency checks against well-known values of normal-incidence reflectance.
    auto r = [](const char* metal, Float l) {
        std::string m(metal);
        return normal_reflectance(eval_named((m + "-eta").c_str(), l),
                                  eval_named((m + "-k").c_str(), l));
    };
    EXPECT_NEAR(r("metal-Au", 600), 0.90, 0.04);  // gold: ~0.9 in the red
    EXPECT_LT(r("metal-Au", 450), 0.45);          // and low in the blue (its colour)
    EXPECT_GT(r("metal-Ag", 600), 0.95);          // silver: highest of all in the visible
    EXPECT_GT(r("metal-Ag", 450), 0.90);          // (pbrt-v4's data: 0.918 at 450 nm)
    EXPECT_NEAR(r("metal-Cu", 650), 0.95, 0.04);   // copper: high in the red
    EXPECT_LT(r("metal-Cu", 450), 0.65);           // low in the blue
    EXPECT_NEAR(r("metal-Al", 550), 0.915, 0.02);  // aluminium: ~0.91, dip near 800 nm
    EXPECT_LT(r("metal-Al", 820), r("metal-Al", 550));
    EXPECT_NEAR(r("metal-CuZn", 600), 0.85, 0.05);  // brass
}

TEST(NamedSpectra, MetalsMatchPbrtV4Tables) {
    // pbrt-v4's Au_eta/Au_k, Ag_eta/Ag_k, Cu_eta/Cu_k, Al_eta/Al_k (spectrum.cpp),
    // linearly interpolated to these wavelengths.
    EXPECT_NEAR(eval_named("metal-Au-eta", 450), 1.50846, 1e-4);
    EXPECT_NEAR(eval_named("metal-Au-k", 450), 1.87885, 1e-4);
    EXPECT_NEAR(eval_named("metal-Au-eta", 550), 0.35041, 1e-4);
    EXPECT_NEAR(eval_named("metal-Au-k", 550), 2.71406, 1e-4);
    EXPECT_NEAR(eval_named("metal-Au-eta", 650), 0.16779, 1e-4);
    EXPECT_NEAR(eval_named("metal-Au-k", 650), 3.13782, 1e-4);
    EXPECT_NEAR(eval_named("metal-Ag-eta", 450), 0.15169, 1e-4);
    EXPECT_NEAR(eval_named("metal-Ag-k", 450), 2.47042, 1e-4);
    EXPECT_NEAR(eval_named("metal-Ag-eta", 550), 0.12478, 1e-4);
    EXPECT_NEAR(eval_named("metal-Ag-k", 550), 3.33960, 1e-4);
    EXPECT_NEAR(eval_named("metal-Ag-eta", 650), 0.13941, 1e-4);
    EXPECT_NEAR(eval_named("metal-Ag-k", 650), 4.12877, 1e-4);
    EXPECT_NEAR(eval_named("metal-Cu-eta", 450), 1.16581, 1e-4);
    EXPECT_NEAR(eval_named("metal-Cu-k", 450), 2.39386, 1e-4);
    EXPECT_NEAR(eval_named("metal-Cu-eta", 550), 0.95816, 1e-4);
    EXPECT_NEAR(eval_named("metal-Cu-k", 550), 2.57706, 1e-4);
    EXPECT_NEAR(eval_named("metal-Cu-eta", 650), 0.21656, 1e-4);
    EXPECT_NEAR(eval_named("metal-Cu-k", 650), 3.63774, 1e-4);
    EXPECT_NEAR(eval_named("metal-Al-eta", 450), 0.61795, 1e-4);
    EXPECT_NEAR(eval_named("metal-Al-k", 450), 5.46942, 1e-4);
    EXPECT_NEAR(eval_named("metal-Al-eta", 550), 0.95857, 1e-4);
    EXPECT_NEAR(eval_named("metal-Al-k", 550), 6.68697, 1e-4);
    EXPECT_NEAR(eval_named("metal-Al-eta", 650), 1.47477, 1e-4);
    EXPECT_NEAR(eval_named("metal-Al-k", 650), 7.79411, 1e-4);
}

TEST(NamedSpectra, OxideIndices) {
    // MgO n_D = 1.7375 (Stephens & Malitson 1952); rutile n_e ~ 2.87 at 633 nm (Devore 1951).
    EXPECT_NEAR(eval_named("metal-MgO-eta", 589.3f), 1.7375, 1e-3);
    EXPECT_NEAR(eval_named("metal-TiO2-eta", 633), 2.87, 0.02);
    EXPECT_EQ(eval_named("metal-MgO-k", 500), 0);
    EXPECT_EQ(eval_named("metal-TiO2-k", 500), 0);
}

}  // namespace
}  // namespace sr
