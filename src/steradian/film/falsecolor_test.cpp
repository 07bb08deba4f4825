#include "steradian/film/falsecolor.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/film/image_io.h"
#include "steradian/spectrum/color.h"

namespace sr {
namespace {

Image values_image(int w, int h, const std::vector<float>& v) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 1;
    img.data = v;
    img.data.resize(size_t(w) * h, 0.0f);
    return img;
}

Rgb linear(Rgb srgb) { return {srgb_decode(srgb.r), srgb_decode(srgb.g), srgb_decode(srgb.b)}; }
Rgb pixel(const Image& img, int x, int y) {
    return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)};
}
double luminance(Rgb lin) { return 0.2126 * lin.r + 0.7152 * lin.g + 0.0722 * lin.b; }

void expect_rgb_near(Rgb a, Rgb b, const char* what) {
    EXPECT_NEAR(a.r, b.r, 1e-6) << what;
    EXPECT_NEAR(a.g, b.g, 1e-6) << what;
    EXPECT_NEAR(a.b, b.b, 1e-6) << what;
}

/// Lit pixels of one glyph, counted from the font through glyph_pixel.
int glyph_bits(char c) {
    int n = 0;
    for (int y = 0; y < kGlyphHeight; ++y)
        for (int x = 0; x < kGlyphWidth; ++x) n += glyph_pixel(c, x, y);
    return n;
}
int text_bits(const std::string& s) {
    int n = 0;
    for (char c : s) n += glyph_bits(c);
    return n;
}

bool is_power_of_ten(double v) {
    double e = std::log10(v);
    return std::abs(e - std::round(e)) < 1e-9;
}

// ---- palette ---------------------------------------------------------------------------------

TEST(FalseColorPalette, LuminanceIncreasesStrictlyAlongTheRamp) {
    double prev = -1;
    for (int i = 0; i <= 2000; ++i) {
        double y = luminance(linear(false_color_palette_srgb(i / 2000.0)));
        EXPECT_GT(y, prev) << "t = " << i / 2000.0;
        prev = y;
    }
    // A real ramp: the top is many times brighter than the bottom.
    EXPECT_GT(luminance(linear(false_color_palette_srgb(1))),
              20 * luminance(linear(false_color_palette_srgb(0))));
}

TEST(FalseColorPalette, EndsAreViridisEndsAndClamped) {
    Rgb lo = false_color_palette_srgb(0), hi = false_color_palette_srgb(1);
    expect_rgb_near(lo, Rgb{68 / 255.f, 1 / 255.f, 84 / 255.f}, "bottom");
    expect_rgb_near(hi, Rgb{253 / 255.f, 231 / 255.f, 37 / 255.f}, "top");
    expect_rgb_near(false_color_palette_srgb(-3), lo, "below 0");
    expect_rgb_near(false_color_palette_srgb(7), hi, "above 1");
    expect_rgb_near(false_color_palette_srgb(std::nan("")), lo, "NaN position");
}

TEST(FalseColorPalette, NanColourIsFarFromEveryPaletteColour) {
    Rgb nan = false_color_nan_srgb();
    for (int i = 0; i <= 1000; ++i) {
        Rgb c = false_color_palette_srgb(i / 1000.0);
        double d = std::abs(c.r - nan.r) + std::abs(c.g - nan.g) + std::abs(c.b - nan.b);
        EXPECT_GT(d, 0.5) << "t = " << i / 1000.0;
    }
}

// ---- mapping ---------------------------------------------------------------------------------

TEST(FalseColor, MaxMapsToTopColourMinToBottomColour) {
    FalseColorOptions o;
    o.min_value = 1;
    o.max_value = 1000;
    o.upscale = 1;
    // 1000 (max), 5000 (above), 1 (min), 0.5 (below), 0, -5, 31.6 (middle of the log range)
    Image v = values_image(7, 1, {1000, 5000, 1, 0.5f, 0, -5, 31.6227766f});
    Image out = false_color(v, o);
    Rgb top = linear(false_color_palette_srgb(1)), bottom = linear(false_color_palette_srgb(0));
    expect_rgb_near(pixel(out, 0, 0), top, "value at max");
    expect_rgb_near(pixel(out, 1, 0), top, "value above max");
    expect_rgb_near(pixel(out, 2, 0), bottom, "value at min");
    expect_rgb_near(pixel(out, 3, 0), bottom, "value below min");
    expect_rgb_near(pixel(out, 4, 0), bottom, "zero");
    expect_rgb_near(pixel(out, 5, 0), bottom, "negative");
    expect_rgb_near(pixel(out, 6, 0), linear(false_color_palette_srgb(0.5)), "log middle");

    o.log_scale = false;
    o.min_value = 0;
    o.max_value = 400;
    Image lin = false_color(values_image(3, 1, {400, 0, 100}), o);
    expect_rgb_near(pixel(lin, 0, 0), top, "linear max");
    expect_rgb_near(pixel(lin, 1, 0), bottom, "linear min");
    expect_rgb_near(pixel(lin, 2, 0), linear(false_color_palette_srgb(0.25)), "linear quarter");
}

TEST(FalseColor, BrighterValueGivesBrighterColour) {
    std::vector<float> ramp;
    for (int i = 0; i < 64; ++i) ramp.push_back(0.5f * std::pow(1.2f, float(i)));
    for (bool log_scale : {true, false}) {
        FalseColorOptions o;
        o.log_scale = log_scale;
        o.min_value = 0.5;
        o.max_value = 0.5 * std::pow(1.2, 63);
        o.upscale = 1;
        Image out = false_color(values_image(64, 1, ramp), o);
        for (int x = 1; x < 64; ++x)
            EXPECT_GT(luminance(pixel(out, x, 0)), luminance(pixel(out, x - 1, 0)))
                << "x = " << x << (log_scale ? " log" : " linear");
    }
}

TEST(FalseColor, NanAndInfPixelsGetTheNanColour) {
    const float inf = std::numeric_limits<float>::infinity();
    Image v = values_image(4, 1, {std::nanf(""), inf, -inf, 10});
    FalseColorOptions one;
    one.upscale = 1;
    Image out = false_color(v, one);
    Rgb nan = linear(false_color_nan_srgb());
    for (int x = 0; x < 3; ++x) expect_rgb_near(pixel(out, x, 0), nan, "non-finite");
    // 10 is the only finite value: the automatic maximum, so the top colour.
    expect_rgb_near(pixel(out, 3, 0), linear(false_color_palette_srgb(1)), "finite");

    // Nothing usable at all: still an image with the default range.
    Image all_nan = values_image(2, 2, {std::nanf(""), std::nanf(""), inf, -inf});
    for (bool log_scale : {true, false}) {
        FalseColorOptions o;
        o.log_scale = log_scale;
        Image img;
        ASSERT_NO_THROW(img = false_color(all_nan, o));
        expect_rgb_near(pixel(img, 0, 0), nan, "all NaN");
        FalseColorRange r = false_color_range(all_nan, o);
        EXPECT_EQ(r.max, 1.0);
        EXPECT_EQ(r.min, log_scale ? 1e-3 : 0.0);
    }
}

// ---- range, ticks, labels ----------------------------------------------------------------------

TEST(FalseColor, AutomaticRangeUsesThe99thPercentileRoundedUp) {
    // 1..1000 plus ten wild outliers (1 % of 1010 is 10.1, so they are all above the 99th
    // percentile, which is 990 here) and non-finite/negative values that must be ignored.
    std::vector<float> v;
    for (int i = 1; i <= 1000; ++i) v.push_back(float(i));
    for (int i = 0; i < 10; ++i) v.push_back(1e9f);
    v.push_back(std::nanf(""));
    v.push_back(-1e12f);
    Image img = values_image(int(v.size()), 1, v);
    FalseColorOptions o;
    FalseColorRange r = false_color_range(img, o);
    EXPECT_EQ(r.max, 1000);  // 990 rounded up to 1, 2 or 5 x 10^k
    EXPECT_EQ(r.min, 1);     // three decades
    o.log_scale = false;
    r = false_color_range(img, o);
    EXPECT_EQ(r.max, 1000);
    EXPECT_EQ(r.min, 0);

    Image bright = values_image(1, 1, {3700});
    EXPECT_EQ(false_color_range(bright, {}).max, 5000);
    EXPECT_EQ(false_color_range(bright, {}).min, 5);
    o.log_scale = false;
    EXPECT_EQ(false_color_range(bright, o).max, 4000);

    // One bound given, the other automatic.
    FalseColorOptions only_max;
    only_max.max_value = 200;
    EXPECT_EQ(false_color_range(bright, only_max).min, 0.2);
    FalseColorOptions only_min;
    only_min.min_value = 10000;  // above the automatic maximum of 5000
    EXPECT_GT(false_color_range(bright, only_min).max, 10000);
}

TEST(FalseColor, BadRangesAndImagesThrow) {
    Image v = values_image(2, 2, {1, 2, 3, 4});
    FalseColorOptions o;
    o.min_value = 10;
    o.max_value = 10;
    EXPECT_THROW(false_color(v, o), Error);
    o.min_value = 0;
    o.max_value = 10;
    EXPECT_THROW(false_color(v, o), Error);  // log scale needs min > 0
    o.log_scale = false;
    EXPECT_NO_THROW(false_color(v, o));
    Image rgb = v;
    rgb.channels = 3;
    rgb.data.resize(12);
    EXPECT_THROW(false_color(rgb, {}), Error);
    EXPECT_THROW(false_color(Image{}, {}), Error);
}

TEST(FalseColor, LogTicksArePowersOfTenWithinTheRange) {
    // Four or more decades: exactly the powers of ten in the range.
    struct Case {
        double min, max;
        int decades;
    };
    for (Case c : {Case{1, 1e5, 6}, Case{1e-3, 10, 5}, Case{0.5, 5e4, 5}, Case{2e-2, 1e5, 7}}) {
        std::vector<double> t = false_color_ticks(c.min, c.max, true, 400, 20);
        ASSERT_EQ(int(t.size()), c.decades) << c.min << ".." << c.max;
        for (size_t i = 0; i < t.size(); ++i) {
            EXPECT_TRUE(is_power_of_ten(t[i])) << t[i];
            EXPECT_GE(t[i], c.min);
            EXPECT_LE(t[i], c.max);
            if (i > 0) {
                EXPECT_NEAR(t[i] / t[i - 1], 10, 1e-9);
            }
        }
    }
    // The default three decades: every power of ten in the range, plus 3 x 10^k between them.
    std::vector<double> t = false_color_ticks(1, 1000, true, 230, 9);
    std::vector<double> expected = {1, 3, 10, 30, 100, 300, 1000};
    ASSERT_EQ(t.size(), expected.size());
    for (size_t i = 0; i < t.size(); ++i) EXPECT_DOUBLE_EQ(t[i], expected[i]);
    // Twelve decades: every other decade, at most eight ticks.
    t = false_color_ticks(1e-6, 1e6, true, 400, 20);
    ASSERT_GE(t.size(), 5u);
    ASSERT_LE(t.size(), 8u);
    for (size_t i = 0; i < t.size(); ++i) {
        EXPECT_TRUE(is_power_of_ten(t[i])) << t[i];
        if (i > 0) {
            EXPECT_NEAR(t[i] / t[i - 1], 100, 1e-6);
        }
    }
    // A short bar: fewer ticks, still at least min_spacing_px apart.
    t = false_color_ticks(1, 1e5, true, 60, 20);
    ASSERT_GE(t.size(), 2u);
    for (size_t i = 1; i < t.size(); ++i)
        EXPECT_GE(60 * std::log10(t[i] / t[i - 1]) / 5, 20 - 1e-9);
}

TEST(FalseColor, NarrowLogRangeFallsBackToNiceLinearTicks) {
    std::vector<double> t = false_color_ticks(100, 150, true, 300, 10);
    ASSERT_GE(t.size(), 2u);
    ASSERT_LE(t.size(), 8u);
    for (double v : t) {
        EXPECT_GE(v, 100);
        EXPECT_LE(v, 150);
        EXPECT_NEAR(v / 10, std::round(v / 10), 1e-9) << v;  // multiples of 10
    }
}

TEST(FalseColor, LinearTicksAreRoundNumbers) {
    std::vector<double> t = false_color_ticks(0, 400, false, 300, 10);
    std::vector<double> expected = {0, 100, 200, 300, 400};
    ASSERT_EQ(t.size(), expected.size());
    for (size_t i = 0; i < t.size(); ++i) EXPECT_DOUBLE_EQ(t[i], expected[i]);

    t = false_color_ticks(0, 1, false, 300, 10);
    ASSERT_EQ(t.size(), 6u);  // step 0.2
    EXPECT_EQ(format_tick(t[3]), "0.6");

    // Steps of 1 would be too many, steps of 2 too close (20 px): steps of 2.5.
    t = false_color_ticks(0, 10, false, 100, 21);
    ASSERT_EQ(t.size(), 5u);
    EXPECT_EQ(format_tick(t[1]), "2.5");
    EXPECT_EQ(format_tick(t[3]), "7.5");
}

TEST(FalseColor, TickLabelsAreCompact) {
    EXPECT_EQ(format_tick(0), "0");
    EXPECT_EQ(format_tick(1), "1");
    EXPECT_EQ(format_tick(0.1), "0.1");
    EXPECT_EQ(format_tick(0.3), "0.3");
    EXPECT_EQ(format_tick(2.5), "2.5");
    EXPECT_EQ(format_tick(1000), "1000");
    EXPECT_EQ(format_tick(5000), "5000");
    EXPECT_EQ(format_tick(0.001), "0.001");
    EXPECT_EQ(format_tick(1e4), "1e+04");
    EXPECT_EQ(format_tick(2.5e5), "2.5e+05");
    EXPECT_EQ(format_tick(1e-4), "1e-04");
    EXPECT_EQ(format_tick(3e-5), "3e-05");
    EXPECT_EQ(format_tick(1e12), "1e+12");
    EXPECT_EQ(format_tick(-20), "-20");
    for (double v : {1e-4, 3e-5, 1e4, 2.5e5, 1e12, 0.001, 0.3})
        for (char c : format_tick(v)) EXPECT_TRUE(has_glyph(c)) << c;
}

// ---- output geometry -------------------------------------------------------------------------

TEST(FalseColor, OutputSizeIsAsDocumented) {
    // An 8 x 8 illuminance grid: automatically upscaled to 256 px, legend 60 px wide.
    std::vector<float> grid;
    for (int i = 0; i < 64; ++i) grid.push_back(float(10 + 7 * i));
    Image g = values_image(8, 8, grid);
    FalseColorOptions o;
    o.unit = "lx";
    Image out = false_color(g, o);
    EXPECT_EQ(out.channels, 3);
    EXPECT_EQ(out.width, 256 + 60);
    EXPECT_EQ(out.height, 256);
    EXPECT_EQ(out.data.size(), size_t(out.width) * out.height * 3);
    // Each value fills a 32 x 32 block.
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            Rgb block_corner = pixel(out, x / 32 * 32, y / 32 * 32);
            ASSERT_EQ(pixel(out, x, y), block_corner) << x << "," << y;
        }
    EXPECT_NE(pixel(out, 0, 0), pixel(out, 255, 255));

    // Explicit factors.
    o.upscale = 3;
    o.legend_width = 100;
    out = false_color(g, o);
    EXPECT_EQ(out.width, 24 + 100);
    EXPECT_EQ(out.height, 128);  // at least 128 tall: legend background below the image
    expect_rgb_near(pixel(out, 0, 127), linear(false_color_background_srgb()), "padding");

    // Large images: no upscaling, legend = width / 6, text scale from the height.
    Image big = values_image(600, 480, std::vector<float>(600 * 480, 500.0f));
    FalseColorLayout L = false_color_layout(big, {});
    EXPECT_EQ(L.upscale, 1);
    EXPECT_EQ(L.width, 600 + 100);
    EXPECT_EQ(L.height, 480);
    EXPECT_EQ(L.text_scale, 2);
    out = false_color(big, {});
    EXPECT_EQ(out.width, L.width);
    EXPECT_EQ(out.height, L.height);

    // Wide and flat: upscaling limited to 4096 px of width.
    L = false_color_layout(values_image(1000, 10, {}), {});
    EXPECT_EQ(L.upscale, 4);
    EXPECT_EQ(L.image_width, 4000);
    EXPECT_EQ(L.height, 128);
}

TEST(FalseColor, DeterministicOutput) {
    std::vector<float> v;
    for (int i = 0; i < 100; ++i) v.push_back(float(std::exp(0.1 * i)) - 2);
    Image img = values_image(10, 10, v);
    Image a = false_color(img, {}), b = false_color(img, {});
    EXPECT_EQ(a.data, b.data);
}

// ---- font and legend ---------------------------------------------------------------------------

TEST(FalseColorFont, GlyphsAreDefinedAndDistinct) {
    for (char c : std::string("0123456789.-+e/ cd/m2 lx lux klx W/m2 nits"))
        EXPECT_TRUE(has_glyph(c)) << "'" << c << "'";
    EXPECT_FALSE(has_glyph('#'));
    EXPECT_EQ(glyph_bits(' '), 0);
    // Every digit is lit and no two digits look alike.
    std::set<std::vector<bool>> shapes;
    for (char c = '0'; c <= '9'; ++c) {
        std::vector<bool> bits;
        for (int y = 0; y < kGlyphHeight; ++y)
            for (int x = 0; x < kGlyphWidth; ++x) bits.push_back(glyph_pixel(c, x, y));
        EXPECT_GT(glyph_bits(c), 5) << c;
        shapes.insert(bits);
    }
    EXPECT_EQ(shapes.size(), 10u);
    // Unknown characters are a hollow box.
    EXPECT_EQ(glyph_bits('#'), 2 * kGlyphWidth + 2 * (kGlyphHeight - 2));
    EXPECT_EQ(text_width("", 3), 0);
    EXPECT_EQ(text_width("lx", 1), 11);
    EXPECT_EQ(text_width("cd/m2", 3), 3 * (5 * kGlyphAdvance - 1));
}

TEST(FalseColorFont, DrawTextLightsExactlyTheGlyphPixels) {
    const std::string text = "cd/m2 1e+04 0.5";
    for (int scale : {1, 2, 3}) {
        Image img;
        img.width = text_width(text, scale) + 20;
        img.height = kGlyphHeight * scale + 20;
        img.channels = 3;
        img.data.assign(size_t(img.width) * img.height * 3, 0.0f);
        const int x0 = 7, y0 = 5;
        draw_text(img, x0, y0, text, scale, Rgb{1, 1, 1});
        int lit = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                bool on = img.at(x, y, 0) == 1.0f;
                lit += on;
                // Where the pixel falls in the text, and whether the font lights it there.
                int dx = x - x0, dy = y - y0;
                bool expected = false;
                if (dx >= 0 && dy >= 0) {
                    int cell = dx / (kGlyphAdvance * scale);
                    int gx = (dx % (kGlyphAdvance * scale)) / scale, gy = dy / scale;
                    if (cell < int(text.size())) expected = glyph_pixel(text[cell], gx, gy);
                }
                ASSERT_EQ(on, expected) << "scale " << scale << " at " << x << "," << y;
            }
        EXPECT_EQ(lit, scale * scale * text_bits(text));
        EXPECT_GT(lit, 0);
    }
    // Clipping at the image border does not crash and draws the visible part.
    Image small;
    small.width = small.height = 4;
    small.channels = 3;
    small.data.assign(48, 0.0f);
    draw_text(small, -3, -2, "8", 2, Rgb{1, 1, 1});
    draw_text(small, 100, 100, "8", 2, Rgb{1, 1, 1});
}

TEST(FalseColorLegend, LegendShowsTheUnitAndTickLabels) {
    for (bool log_scale : {true, false}) {
        for (int h : {8, 300, 700}) {
            std::vector<float> v;
            for (int i = 0; i < 8 * h; ++i) v.push_back(float(1 + i % 977));
            Image img = values_image(8, h, v);
            FalseColorOptions o;
            o.log_scale = log_scale;
            o.unit = log_scale ? "cd/m2" : "lx";
            FalseColorLayout L = false_color_layout(img, o);
            Image out = false_color(img, o);
            const int s = L.text_scale;
            SCOPED_TRACE(::testing::Message()
                         << (log_scale ? "log" : "linear") << " h " << h << " scale " << s);

            // Ticks: 2..8, inside the range, ordered bottom (min) to top (max), labelled.
            ASSERT_GE(L.ticks.size(), 2u);
            ASSERT_LE(L.ticks.size(), 8u);
            int expected_bits = text_bits(o.unit);
            for (size_t i = 0; i < L.ticks.size(); ++i) {
                const auto& t = L.ticks[i];
                EXPECT_GE(t.value, L.range.min);
                EXPECT_LE(t.value, L.range.max);
                EXPECT_GE(t.y, L.bar_top);
                EXPECT_LE(t.y, L.bar_bottom);
                if (i > 0) {
                    EXPECT_LT(t.y, L.ticks[i - 1].y);
                }
                EXPECT_EQ(t.label, format_tick(t.value));
                EXPECT_GE(t.label_x, L.legend_x);
                EXPECT_LE(t.label_x + text_width(t.label, s), L.width);
                expected_bits += text_bits(t.label);
            }

            // Text pixels (pure white, used nowhere else) are exactly the glyph pixels of the
            // unit and of every label: none missing, none overlapping, none in the image.
            Rgb white = linear(false_color_text_srgb());
            int lit = 0;
            for (int y = 0; y < out.height; ++y)
                for (int x = 0; x < out.width; ++x)
                    if (pixel(out, x, y) == white) {
                        ++lit;
                        EXPECT_GE(x, L.legend_x);
                    }
            EXPECT_EQ(lit, s * s * expected_bits);

            // The unit label is where the layout says: its first glyph's pixels are lit.
            for (int gy = 0; gy < kGlyphHeight; ++gy)
                for (int gx = 0; gx < kGlyphWidth; ++gx)
                    EXPECT_EQ(pixel(out, L.unit_x + gx * s, L.unit_y + gy * s) == white,
                              glyph_pixel(o.unit[0], gx, gy));

            // Each label is beside its tick, vertically centred on it, and drawn there.
            for (const auto& t : L.ticks) {
                EXPECT_LE(std::abs(t.label_y + kGlyphHeight * s / 2 - t.y), s) << t.label;
                for (int gy = 0; gy < kGlyphHeight; ++gy)
                    for (int gx = 0; gx < kGlyphWidth; ++gx)
                        EXPECT_EQ(pixel(out, t.label_x + gx * s, t.label_y + gy * s) == white,
                                  glyph_pixel(t.label[0], gx, gy))
                            << t.label;
            }

            // The colour bar runs from the top colour down to the bottom colour.
            int bx = (L.bar_x0 + L.bar_x1) / 2;
            expect_rgb_near(pixel(out, bx, L.bar_top), linear(false_color_palette_srgb(1)), "top");
            expect_rgb_near(pixel(out, bx, L.bar_bottom), linear(false_color_palette_srgb(0)),
                            "bottom");
            for (int y = L.bar_top + 1; y <= L.bar_bottom; ++y)
                EXPECT_LE(luminance(pixel(out, bx, y)), luminance(pixel(out, bx, y - 1)));
            // A tick mark beside the bar at each tick.
            Rgb tick = linear(false_color_tick_srgb());
            for (const auto& t : L.ticks) EXPECT_EQ(pixel(out, L.bar_x1, t.y), tick);
        }
    }
}

TEST(FalseColorLegend, PngHoldsTheExactPaletteColours) {
    FalseColorOptions o;
    o.min_value = 1;
    o.max_value = 100;
    o.upscale = 1;
    Image out = false_color(values_image(3, 1, {100, 1, std::nanf("")}), o);
    std::string path = (std::filesystem::temp_directory_path() /
                        ("steradian_falsecolor_" + std::to_string(::getpid()) + ".png"))
                           .string();
    write_image(path, out);
    Image back = read_image(path, /*srgb_decode=*/false);
    std::filesystem::remove(path);
    ASSERT_EQ(back.width, out.width);
    ASSERT_EQ(back.height, out.height);
    auto byte = [&](int x, int c) { return int(std::lround(back.at(x, 0, c) * 255)); };
    EXPECT_EQ(byte(0, 0), 253);  // viridis top, #fde725
    EXPECT_EQ(byte(0, 1), 231);
    EXPECT_EQ(byte(0, 2), 37);
    EXPECT_EQ(byte(1, 0), 68);  // viridis bottom, #440154
    EXPECT_EQ(byte(1, 1), 1);
    EXPECT_EQ(byte(1, 2), 84);
    EXPECT_EQ(byte(2, 0), 255);  // magenta
    EXPECT_EQ(byte(2, 1), 0);
    EXPECT_EQ(byte(2, 2), 255);
}

/// Writes sample images for a visual check:
///   steradian_unit_tests --gtest_also_run_disabled_tests --gtest_filter='*WriteSample*'
/// into $SR_FALSECOLOR_SAMPLE (default /tmp/falsecolor_sample.png) and a linear-scale
/// illuminance grid beside it (..._grid.png).
TEST(FalseColorLegend, DISABLED_WriteSample) {
    const char* env = std::getenv("SR_FALSECOLOR_SAMPLE");
    std::string path = env ? env : "/tmp/falsecolor_sample.png";
    // A luminance-like field: a bright spot on a falling background, a NaN pixel.
    int w = 320, h = 240;
    std::vector<float> v;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double dx = x - 200.0, dy = y - 90.0;
            double spot = 4000 * std::exp(-(dx * dx + dy * dy) / 800);
            v.push_back(float(2 + 300 * std::exp(-x / 80.0) * (1 + y / 120.0) + spot));
        }
    v[size_t(h - 10) * w + 10] = std::nanf("");
    write_image(path, false_color(values_image(w, h, v), {}));

    std::vector<float> grid;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            grid.push_back(float(120 + 380 * std::exp(-0.1 * (x * x + y * y))));
    FalseColorOptions o;
    o.unit = "lx";
    o.log_scale = false;
    std::string grid_path = path.substr(0, path.size() - 4) + "_grid.png";
    write_image(grid_path, false_color(values_image(8, 8, grid), o));
}

}  // namespace
}  // namespace sr
