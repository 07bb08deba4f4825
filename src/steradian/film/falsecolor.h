#pragma once
/// False-colour images of photometric quantities (luminance in cd/m², illuminance in lx)
/// with a labelled colour scale on the right, as lighting designers read them (in the
/// manner of Radiance's `falsecolor`).
///
/// The result is an ordinary linear-sRGB `Image`: the palette colours are defined in
/// sRGB-encoded 8-bit terms and decoded to linear when stored, so `write_image(path.png, ...)`
/// (which sRGB-encodes) writes exactly the palette's 8-bit colours. Write it with
/// `write_image`, with the default exposure of 0.
#include <string>
#include <string_view>
#include <vector>

#include "steradian/film/image_io.h"
#include "steradian/spectrum/color.h"

namespace sr {

struct FalseColorOptions {
    std::string unit = "cd/m2";  ///< label printed above the scale, e.g. "cd/m2" or "lx"
    bool log_scale = true;       ///< logarithmic (decades) or linear scale
    /// Range of the scale; a negative value means automatic. Log: max = the 99th percentile
    /// of the finite positive values rounded up to 1, 2 or 5 x 10^k, min = max / 1000 (three
    /// decades). Linear: min = 0, max = the 99th percentile of the finite values rounded up
    /// to a nice number. An explicit range must have max > min, and min > 0 on a log scale
    /// (else sr::Error).
    double min_value = -1, max_value = -1;
    /// Width of the legend panel in pixels; <= 0: automatic, max(60, image width / 6 rounded),
    /// widened if needed so that the labels fit. The legend's text scale is
    /// clamp(output height / 240, 1, 4); an explicit width too narrow for it lowers the scale,
    /// down to 1, where labels that still do not fit are clipped.
    int legend_width = 0;
    /// Nearest-neighbour upscaling factor of the values (e.g. an 8x8 illuminance grid shown as
    /// blocks); <= 0: automatic, the smallest factor that makes the image at least 256 px tall,
    /// limited so that the image stays at most 4096 px wide (and at least 1). An upscaled
    /// image larger than 65536 px on a side is an sr::Error.
    int upscale = 0;
};

/// Maps a single-channel image of values (W x H, row-major from the top; channels must be 1,
/// else sr::Error) to a 3-channel linear-sRGB image of size
///   (W*u + legend width) x max(H*u, 128),   u = the upscale factor,
/// the false-colour image at the top left, the legend panel on the right and, when H*u < 128,
/// legend background below the image. Values at or below the scale's minimum (and values
/// <= 0 on a log scale) get the lowest palette colour, values at or above the maximum the
/// highest; NaN and +-Inf pixels are shown in magenta (false_color_nan_srgb()).
/// Deterministic; throws sr::Error on an empty image or an invalid range.
Image false_color(const Image& values, const FalseColorOptions& opts = {});

// ---- building blocks (exposed for tests and for other annotated outputs) ------------------

/// The palette: a perceptually ordered ramp with monotonically increasing luminance, t in
/// [0, 1] (clamped; NaN -> 0), as sRGB-encoded components in [0, 1].
Rgb false_color_palette_srgb(double t);
/// The colour of NaN/Inf pixels (sRGB-encoded magenta), never produced by the palette.
Rgb false_color_nan_srgb();
/// The legend's background, text and tick-mark colours (sRGB-encoded).
Rgb false_color_background_srgb();
Rgb false_color_text_srgb();
Rgb false_color_tick_srgb();

/// The scale's range resolved from the options and the values (see FalseColorOptions).
struct FalseColorRange {
    double min = 0, max = 1;
};
FalseColorRange false_color_range(const Image& values, const FalseColorOptions& opts);

/// Position of a value on the scale in [0, 1] (clamped); NaN for NaN/Inf values. On a log
/// scale values <= 0 give 0.
double false_color_position(double value, FalseColorRange range, bool log_scale);

/// Tick values for a colour bar `bar_px` pixels long whose labels need centres at least
/// `min_spacing_px` apart: between 2 and 8 ticks inside [min, max] (fewer only if the bar is
/// too short). Log scale: the densest of {1,2,3,5,7}, {1,2,5}, {1,3} and {1} x 10^k (then every
/// 2nd, 3rd, 5th... decade) that fits; when fewer than two such values fall in the range,
/// linear nice ticks as below. Linear scale: multiples of the smallest step in
/// {1, 2, 2.5, 5} x 10^k that fits.
std::vector<double> false_color_ticks(double min, double max, bool log_scale, double bar_px,
                                      double min_spacing_px);

/// Compact label of a tick value: "0", "0.25", "3", "1000", "5000"; exponential form with a
/// two-digit exponent ("1e+04", "2.5e-05") for |v| >= 1e4 or |v| < 1e-3.
std::string format_tick(double v);

/// Geometry of a false_color output (all in output pixels; rows count from the top).
struct FalseColorLayout {
    int upscale = 1;
    int width = 0, height = 0;              ///< the whole output image
    int image_width = 0, image_height = 0;  ///< the false-colour area, W*u x H*u, at (0, 0)
    int legend_x = 0, legend_width = 0;     ///< legend panel: columns [legend_x, width)
    int text_scale = 1;                     ///< glyph magnification of all legend text
    int bar_x0 = 0, bar_x1 = 0;             ///< colour bar columns [bar_x0, bar_x1)
    int bar_top = 0, bar_bottom = 0;        ///< rows, inclusive: top = max, bottom = min
    int unit_x = 0, unit_y = 0;             ///< top-left of the unit label
    FalseColorRange range;
    struct Tick {
        double value = 0;
        int y = 0;                     ///< row of the tick mark's centre
        std::string label;             ///< format_tick(value)
        int label_x = 0, label_y = 0;  ///< top-left of the label
    };
    std::vector<Tick> ticks;
};
FalseColorLayout false_color_layout(const Image& values, const FalseColorOptions& opts);

// ---- a tiny bitmap font --------------------------------------------------------------------

/// 5x7 glyphs on a 6-pixel advance: digits, ". - + e /" and the letters
/// a c d E i k l m n o r s t u W x (enough for cd/m2, lx, lux, klx, W/m2, nits...) and space.
/// Any other character is drawn as a hollow box.
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;
/// Whether pixel (x, y) of the glyph for c is lit (x in [0, 5), y in [0, 7) from the top).
bool glyph_pixel(char c, int x, int y);
/// Whether c has a glyph of its own (rather than the hollow box).
bool has_glyph(char c);
/// Width in pixels of text drawn at the given scale (0 for empty text).
int text_width(std::string_view text, int scale);
/// Draws text with its top-left corner at (x, y), each glyph pixel as a scale x scale block
/// of the given linear colour; pixels outside the image are clipped. img needs 3 channels.
void draw_text(Image& img, int x, int y, std::string_view text, int scale, Rgb linear_color);

}  // namespace sr
