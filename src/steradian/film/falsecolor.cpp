#include "steradian/film/falsecolor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <span>

#include "steradian/core/error.h"

namespace sr {

namespace {

// ---- palette ----------------------------------------------------------------------------

/// matplotlib's "viridis" colormap (Stéfan van der Walt and Nathaniel Smith, 2015, CC0),
/// sampled at 10 equally spaced points (sRGB, 8 bit): #440154 #482878 #3e4a89 #31688e #26828e
/// #1f9e89 #35b779 #6ece58 #b5de2b #fde725. Its lightness increases monotonically and it is
/// readable by colour-blind viewers; we interpolate linearly in sRGB-encoded values between
/// these points.
constexpr std::array<std::array<int, 3>, 10> kViridis = {{{68, 1, 84},
                                                          {72, 40, 120},
                                                          {62, 74, 137},
                                                          {49, 104, 142},
                                                          {38, 130, 142},
                                                          {31, 158, 137},
                                                          {53, 183, 121},
                                                          {110, 206, 88},
                                                          {181, 222, 43},
                                                          {253, 231, 37}}};

Rgb from8(int r, int g, int b) { return {Float(r) / 255, Float(g) / 255, Float(b) / 255}; }

Rgb decode(Rgb c) { return {srgb_decode(c.r), srgb_decode(c.g), srgb_decode(c.b)}; }

// ---- numbers ----------------------------------------------------------------------------

/// 10^k, exact for |k| <= 22 (powers of ten up to 1e22 are representable doubles).
double pow10_exact(int k) {
    double p = 1;
    for (int i = 0; i < std::abs(k); ++i) p *= 10;
    return k >= 0 ? p : 1 / p;
}
/// m x 10^k with a single rounding when |k| <= 22 (3 x 10^-1 gives the double nearest 0.3).
double scaled(double m, int k) {
    if (std::abs(k) > 22) return m * std::pow(10.0, k);
    return k >= 0 ? m * pow10_exact(k) : m / pow10_exact(-k);
}

/// The smallest m x 10^k >= v (v > 0) with m from the given ascending mantissas ending in 10.
template <size_t N>
double nice_ceil(double v, const std::array<double, N>& mantissas) {
    int k = int(std::floor(std::log10(v)));
    for (int kk = k - 1; kk <= k + 1; ++kk)
        for (double m : mantissas) {
            double c = scaled(m, kk);
            if (c >= v * (1 - 1e-9)) return c;
        }
    return scaled(1, k + 2);
}
constexpr std::array<double, 4> kLogMaxMantissas = {1, 2, 5, 10};
constexpr std::array<double, 10> kLinMaxMantissas = {1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10};

/// The 99th percentile (nearest rank) of the finite values, only the positive ones if
/// positive_only; NaN when there are none.
double percentile99(const Image& values, bool positive_only) {
    std::vector<double> v;
    v.reserve(values.data.size());
    for (float x : values.data)
        if (std::isfinite(x) && (!positive_only || x > 0)) v.push_back(x);
    if (v.empty()) return std::nan("");
    size_t rank = size_t(std::ceil(0.99 * double(v.size())));
    size_t idx = rank > 0 ? rank - 1 : 0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(idx), v.end());
    return v[idx];
}

void check_values(const Image& values) {
    if (values.width <= 0 || values.height <= 0)
        throw Error("false colour: the image of values is empty");
    if (values.channels != 1)
        throw Error(fmt::format("false colour: expected a single-channel image, got {} channels",
                                values.channels));
    if (values.data.size() != size_t(values.width) * size_t(values.height))
        throw Error("false colour: the image's data size does not match its dimensions");
}

bool ticks_fit(const std::vector<double>& ticks, FalseColorRange range, bool log_scale,
               double bar_px, double min_spacing_px) {
    if (ticks.size() < 2 || ticks.size() > 8) return false;
    for (size_t i = 1; i < ticks.size(); ++i) {
        double d = false_color_position(ticks[i], range, log_scale) -
                   false_color_position(ticks[i - 1], range, log_scale);
        if (d * bar_px < min_spacing_px) return false;
    }
    return true;
}

std::vector<double> linear_ticks(double min, double max, double bar_px, double min_spacing_px,
                                 bool log_scale) {
    double span = max - min;
    if (!(span > 0)) return {max};
    FalseColorRange range{min, max};
    int k0 = int(std::floor(std::log10(span / 8))) - 1;
    for (int k = k0; k <= k0 + 4; ++k)
        for (double m : {1.0, 2.0, 2.5, 5.0}) {
            double step = scaled(m, k);
            if (std::max(std::abs(min), std::abs(max)) / step > 1e12) continue;  // no overflow
            long i0 = long(std::ceil(min / step - 1e-9));
            long i1 = long(std::floor(max / step + 1e-9));
            long count = i1 - i0 + 1;
            if (count > 8) continue;
            if (count < 2) return {};
            std::vector<double> t;
            for (long i = i0; i <= i1; ++i)
                // i x m x 10^k with one rounding, so that 3 x 0.1 is the double nearest 0.3
                t.push_back(std::clamp(scaled(double(i) * m, k), min, max));
            if (ticks_fit(t, range, log_scale, bar_px, min_spacing_px)) return t;
        }
    return {};
}

// ---- font -------------------------------------------------------------------------------

struct Glyph {
    char c;
    std::array<const char*, kGlyphHeight> rows;  ///< '#' lit, '.' unlit, kGlyphWidth each
};

// clang-format off
constexpr Glyph kFont[] = {
    {' ', {".....", ".....", ".....", ".....", ".....", ".....", "....."}},
    {'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
    {'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
    {'3', {"#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."}},
    {'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
    {'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
    {'6', {"..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."}},
    {'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
    {'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
    {'9', {".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."}},
    {'.', {".....", ".....", ".....", ".....", ".....", ".##..", ".##.."}},
    {'-', {".....", ".....", ".....", ".###.", ".....", ".....", "....."}},
    {'+', {".....", "..#..", "..#..", "#####", "..#..", "..#..", "....."}},
    {'/', {".....", "....#", "...#.", "..#..", ".#...", "#....", "....."}},
    {'a', {".....", ".....", ".###.", "....#", ".####", "#...#", ".####"}},
    {'c', {".....", ".....", ".###.", "#....", "#....", "#...#", ".###."}},
    {'d', {"....#", "....#", ".##.#", "#..##", "#...#", "#...#", ".####"}},
    {'e', {".....", ".....", ".###.", "#...#", "#####", "#....", ".###."}},
    {'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
    {'i', {"..#..", ".....", ".##..", "..#..", "..#..", "..#..", ".###."}},
    {'k', {"#....", "#....", "#..#.", "#.#..", "##...", "#.#..", "#..#."}},
    {'l', {".##..", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'m', {".....", ".....", "##.#.", "#.#.#", "#.#.#", "#...#", "#...#"}},
    {'n', {".....", ".....", "#.##.", "##..#", "#...#", "#...#", "#...#"}},
    {'o', {".....", ".....", ".###.", "#...#", "#...#", "#...#", ".###."}},
    {'r', {".....", ".....", "#.##.", "##..#", "#....", "#....", "#...."}},
    {'s', {".....", ".....", ".####", "#....", ".###.", "....#", "####."}},
    {'t', {".#...", ".#...", "###..", ".#...", ".#...", ".#..#", "..##."}},
    {'u', {".....", ".....", "#...#", "#...#", "#...#", "#..##", ".##.#"}},
    {'W', {"#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#."}},
    {'x', {".....", ".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#"}},
};
constexpr Glyph kBoxGlyph =
    {'?', {"#####", "#...#", "#...#", "#...#", "#...#", "#...#", "#####"}};
// clang-format on

constexpr bool row_ok(const char* r) {
    int n = 0;
    for (; r[n] != '\0'; ++n)
        if (r[n] != '#' && r[n] != '.') return false;
    return n == kGlyphWidth;
}
constexpr bool font_ok() {
    for (const Glyph& g : kFont)
        for (const char* r : g.rows)
            if (!row_ok(r)) return false;
    for (const char* r : kBoxGlyph.rows)
        if (!row_ok(r)) return false;
    return true;
}
static_assert(font_ok(), "every glyph row must be 5 characters of '#' and '.'");

const Glyph* find_glyph(char c) {
    for (const Glyph& g : kFont)
        if (g.c == c) return &g;
    return nullptr;
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, Rgb c) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, img.width);
    y1 = std::min(y1, img.height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            img.at(x, y, 0) = c.r;
            img.at(x, y, 1) = c.g;
            img.at(x, y, 2) = c.b;
        }
}

// ---- layout constants (in units of the text scale s) ---------------------------------------

constexpr int kMinHeight = 128;  ///< output images are at least this tall
constexpr int kMinLegendWidth = 60;
constexpr int kMargin = 4;  ///< around the legend's contents
constexpr int kBarWidth = 10;
constexpr int kTickLength = 3;
constexpr int kLabelGap = 2;  ///< between a tick mark and its label

struct LegendGeometry {
    int bar_top = 0, bar_bottom = 0;
    std::vector<double> ticks;
    std::vector<std::string> labels;
    int required_width = 0;  ///< legend width that holds the bar, the labels and the unit
};

LegendGeometry legend_geometry(int height, int s, FalseColorRange range, bool log_scale,
                               const std::string& unit) {
    LegendGeometry g;
    int m = kMargin * s, text_h = kGlyphHeight * s;
    g.bar_top = m + text_h + m + (text_h + 1) / 2;
    g.bar_bottom = height - 1 - m - text_h / 2;
    g.ticks =
        false_color_ticks(range.min, range.max, log_scale,
                          double(std::max(g.bar_bottom - g.bar_top, 1)), double(text_h + 2 * s));
    int label_w = 0;
    for (double t : g.ticks) {
        g.labels.push_back(format_tick(t));
        label_w = std::max(label_w, text_width(g.labels.back(), s));
    }
    g.required_width = std::max(m + (kBarWidth + kTickLength + kLabelGap) * s + label_w + m,
                                m + text_width(unit, s) + m);
    return g;
}

}  // namespace

// ---- palette and scale -----------------------------------------------------------------------

Rgb false_color_palette_srgb(double t) {
    if (!(t > 0)) t = 0;  // also NaN
    t = std::min(t, 1.0);
    constexpr int n = int(kViridis.size()) - 1;
    double x = t * n;
    int i = std::min(int(x), n - 1);
    double f = x - i;
    Rgb c;
    auto lerp8 = [&](int ch) {
        return Float((kViridis[i][ch] * (1 - f) + kViridis[i + 1][ch] * f) / 255);
    };
    c.r = lerp8(0);
    c.g = lerp8(1);
    c.b = lerp8(2);
    return c;
}
Rgb false_color_nan_srgb() { return {1, 0, 1}; }
Rgb false_color_background_srgb() { return from8(40, 40, 40); }
Rgb false_color_text_srgb() { return {1, 1, 1}; }
Rgb false_color_tick_srgb() { return from8(190, 190, 190); }

FalseColorRange false_color_range(const Image& values, const FalseColorOptions& opts) {
    check_values(values);
    double lo = opts.min_value, hi = opts.max_value;
    if (std::isnan(lo) || std::isnan(hi) || std::isinf(lo) || std::isinf(hi))
        throw Error("false colour: the scale's range must be finite");
    bool auto_lo = lo < 0, auto_hi = hi < 0;
    if (!auto_lo && !auto_hi && !(hi > lo))
        throw Error(fmt::format("false colour: max_value {} must exceed min_value {}", hi, lo));
    FalseColorRange r;
    if (opts.log_scale) {
        if (!auto_lo && lo == 0) throw Error("false colour: a log scale needs min_value > 0");
        if (!auto_hi && hi == 0) throw Error("false colour: a log scale needs max_value > 0");
        if (auto_hi) {
            double p = percentile99(values, true);
            hi = std::isnan(p) ? 1.0 : nice_ceil(p, kLogMaxMantissas);
            if (!auto_lo && hi <= lo) hi = lo * 1000;
        }
        if (auto_lo) lo = hi / 1000;
    } else {
        if (auto_lo) lo = 0;
        if (auto_hi) {
            double p = percentile99(values, false);
            hi = p > 0 ? nice_ceil(p, kLinMaxMantissas) : 1.0;
            if (hi <= lo) hi = nice_ceil(2 * lo, kLinMaxMantissas);
        }
        if (!(hi > lo))
            throw Error(fmt::format("false colour: max_value {} must exceed min_value {}", hi, lo));
    }
    r.min = lo;
    r.max = hi;
    return r;
}

double false_color_position(double value, FalseColorRange range, bool log_scale) {
    if (!std::isfinite(value)) return std::nan("");
    double t;
    if (log_scale) {
        if (value <= 0 || !(range.min > 0)) return 0;
        t = std::log(value / range.min) / std::log(range.max / range.min);
    } else {
        t = (value - range.min) / (range.max - range.min);
    }
    if (!(t > 0)) return 0;
    return std::min(t, 1.0);
}

std::vector<double> false_color_ticks(double min, double max, bool log_scale, double bar_px,
                                      double min_spacing_px) {
    std::vector<double> result;
    if (log_scale && min > 0 && max > min) {
        FalseColorRange range{min, max};
        int k0 = int(std::floor(std::log10(min))) - 1, k1 = int(std::ceil(std::log10(max))) + 1;
        auto in_range = [&](double v) { return v >= min * (1 - 1e-9) && v <= max * (1 + 1e-9); };
        auto make = [&](std::span<const double> mantissas, int every) {
            std::vector<double> t;
            for (int k = k0; k <= k1; ++k) {
                if (every > 1 && k % every != 0) continue;
                for (double m : mantissas) {
                    double v = scaled(m, k);
                    if (in_range(v)) t.push_back(std::clamp(v, min, max));
                }
            }
            return t;
        };
        // Densest first; a set that gives fewer than two ticks ends the search.
        static constexpr double kM12357[] = {1, 2, 3, 5, 7}, kM125[] = {1, 2, 5}, kM13[] = {1, 3},
                                kM1[] = {1};
        bool few = false;
        for (std::span<const double> mantissas :
             {std::span<const double>(kM12357), std::span<const double>(kM125),
              std::span<const double>(kM13), std::span<const double>(kM1)}) {
            std::vector<double> t = make(mantissas, 1);
            if (ticks_fit(t, range, true, bar_px, min_spacing_px)) return t;
            few = t.size() < 2;
        }
        if (!few) {
            for (int every : {2, 3, 5, 10, 20, 50, 100}) {
                std::vector<double> t = make(kM1, every);
                if (ticks_fit(t, range, true, bar_px, min_spacing_px)) return t;
                if (t.size() < 2) break;
            }
        }
        result = linear_ticks(min, max, bar_px, min_spacing_px, true);
    } else {
        result = linear_ticks(min, max, bar_px, min_spacing_px, log_scale);
    }
    if (result.empty()) {
        if (max > min && bar_px >= min_spacing_px) return {min, max};
        return {max};
    }
    return result;
}

std::string format_tick(double v) {
    if (v == 0) return "0";
    if (!std::isfinite(v)) return v != v ? "nan" : (v > 0 ? "inf" : "-inf");
    double a = std::abs(v);
    if (a >= 1e4 || a < 1e-3) {
        int e = int(std::floor(std::log10(a)));
        std::string mant = fmt::format("{:.3g}", v / std::pow(10.0, e));
        if (mant == "10" || mant == "-10") {  // 9.9996 rounded up
            ++e;
            mant = v < 0 ? "-1" : "1";
        }
        return fmt::format("{}e{}{:02d}", mant, e < 0 ? '-' : '+', std::abs(e));
    }
    return fmt::format("{:.4g}", v);
}

// ---- layout and image ------------------------------------------------------------------------

FalseColorLayout false_color_layout(const Image& values, const FalseColorOptions& opts) {
    check_values(values);
    FalseColorLayout L;
    L.range = false_color_range(values, opts);
    int w = values.width, h = values.height;
    int u = opts.upscale;
    if (u <= 0) {
        u = h >= 256 ? 1 : (256 + h - 1) / h;
        if (long(w) * u > 4096) u = std::max(1, 4096 / w);
    }
    if (long(w) * u > 65536 || long(h) * u > 65536)
        throw Error(
            fmt::format("false colour: upscaling {}x{} by {} gives too large an image", w, h, u));
    L.upscale = u;
    L.image_width = w * u;
    L.image_height = h * u;
    L.height = std::max(L.image_height, kMinHeight);

    // Text scale from the height; the automatic legend is made wide enough for it, an
    // explicit one lowers the scale until the labels fit (at scale 1 they may be clipped).
    int s = std::clamp(L.height / 240, 1, 4);
    LegendGeometry g = legend_geometry(L.height, s, L.range, opts.log_scale, opts.unit);
    if (opts.legend_width > 0) {
        L.legend_width = opts.legend_width;
        while (s > 1 && g.required_width > L.legend_width) {
            --s;
            g = legend_geometry(L.height, s, L.range, opts.log_scale, opts.unit);
        }
    } else {
        L.legend_width = std::max({kMinLegendWidth, (L.image_width + 3) / 6, g.required_width});
    }
    L.text_scale = s;
    L.legend_x = L.image_width;
    L.width = L.image_width + L.legend_width;

    int m = kMargin * s, text_h = kGlyphHeight * s;
    L.unit_x = L.legend_x + m;
    L.unit_y = m;
    L.bar_x0 = L.legend_x + m;
    L.bar_x1 = L.bar_x0 + kBarWidth * s;
    L.bar_top = g.bar_top;
    L.bar_bottom = g.bar_bottom;
    for (size_t i = 0; i < g.ticks.size(); ++i) {
        FalseColorLayout::Tick t;
        t.value = g.ticks[i];
        double pos = false_color_position(t.value, L.range, opts.log_scale);
        t.y = int(std::lround(L.bar_bottom - pos * (L.bar_bottom - L.bar_top)));
        t.label = g.labels[i];
        t.label_x = L.bar_x1 + (kTickLength + kLabelGap) * s;
        t.label_y = std::clamp(t.y - text_h / 2, 0, L.height - text_h);
        L.ticks.push_back(t);
    }
    return L;
}

Image false_color(const Image& values, const FalseColorOptions& opts) {
    FalseColorLayout L = false_color_layout(values, opts);
    Image out;
    out.width = L.width;
    out.height = L.height;
    out.channels = 3;
    out.data.resize(size_t(out.width) * out.height * 3);
    fill_rect(out, 0, 0, out.width, out.height, decode(false_color_background_srgb()));

    // The false-colour image, one colour per value, replicated over u x u blocks.
    const Rgb nan_color = decode(false_color_nan_srgb());
    const int u = L.upscale;
    for (int y = 0; y < values.height; ++y)
        for (int x = 0; x < values.width; ++x) {
            double t = false_color_position(values.data[size_t(y) * values.width + x], L.range,
                                            opts.log_scale);
            Rgb c = std::isnan(t) ? nan_color : decode(false_color_palette_srgb(t));
            fill_rect(out, x * u, y * u, (x + 1) * u, (y + 1) * u, c);
        }

    // The colour bar: the top row shows the maximum, the bottom row the minimum.
    const int s = L.text_scale;
    for (int y = L.bar_top; y <= L.bar_bottom; ++y) {
        double t = L.bar_bottom > L.bar_top
                       ? double(L.bar_bottom - y) / double(L.bar_bottom - L.bar_top)
                       : 1.0;
        fill_rect(out, L.bar_x0, y, L.bar_x1, y + 1, decode(false_color_palette_srgb(t)));
    }
    const Rgb tick_color = decode(false_color_tick_srgb());
    const Rgb text_color = decode(false_color_text_srgb());
    for (const FalseColorLayout::Tick& t : L.ticks) {
        int y0 = t.y - (s - 1) / 2;
        fill_rect(out, L.bar_x1, y0, L.bar_x1 + kTickLength * s, y0 + s, tick_color);
        draw_text(out, t.label_x, t.label_y, t.label, s, text_color);
    }
    draw_text(out, L.unit_x, L.unit_y, opts.unit, s, text_color);
    return out;
}

// ---- font ------------------------------------------------------------------------------------

bool glyph_pixel(char c, int x, int y) {
    if (x < 0 || x >= kGlyphWidth || y < 0 || y >= kGlyphHeight) return false;
    const Glyph* g = find_glyph(c);
    if (!g) g = &kBoxGlyph;
    return g->rows[size_t(y)][x] == '#';
}

bool has_glyph(char c) { return find_glyph(c) != nullptr; }

int text_width(std::string_view text, int scale) {
    if (text.empty()) return 0;
    return (int(text.size()) * kGlyphAdvance - (kGlyphAdvance - kGlyphWidth)) * scale;
}

void draw_text(Image& img, int x, int y, std::string_view text, int scale, Rgb linear_color) {
    SR_CHECK(img.channels == 3);
    for (size_t i = 0; i < text.size(); ++i) {
        int gx0 = x + int(i) * kGlyphAdvance * scale;
        for (int gy = 0; gy < kGlyphHeight; ++gy)
            for (int gx = 0; gx < kGlyphWidth; ++gx)
                if (glyph_pixel(text[i], gx, gy))
                    fill_rect(img, gx0 + gx * scale, y + gy * scale, gx0 + (gx + 1) * scale,
                              y + (gy + 1) * scale, linear_color);
    }
}

}  // namespace sr
