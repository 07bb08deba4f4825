#pragma once
/// Tristimulus colours: CIE XYZ and linear sRGB (Rec. 709 primaries, D65 white).
#include "steradian/core/math.h"

namespace sr {

struct Rgb {
    Float r = 0, g = 0, b = 0;
    Float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    Rgb operator+(Rgb o) const { return {r + o.r, g + o.g, b + o.b}; }
    Rgb operator*(Float s) const { return {r * s, g * s, b * s}; }
    bool operator==(const Rgb&) const = default;
};

struct Xyz {
    Float x = 0, y = 0, z = 0;
    Xyz operator+(Xyz o) const { return {x + o.x, y + o.y, z + o.z}; }
    Xyz operator*(Float s) const { return {x * s, y * s, z * s}; }
};

/// Linear sRGB from XYZ (IEC 61966-2-1 matrix, D65 white point).
inline Rgb xyz_to_linear_srgb(Xyz c) {
    return {Float(3.2404542) * c.x - Float(1.5371385) * c.y - Float(0.4985314) * c.z,
            Float(-0.9692660) * c.x + Float(1.8760108) * c.y + Float(0.0415560) * c.z,
            Float(0.0556434) * c.x - Float(0.2040259) * c.y + Float(1.0572252) * c.z};
}
inline Xyz linear_srgb_to_xyz(Rgb c) {
    return {Float(0.4124564) * c.r + Float(0.3575761) * c.g + Float(0.1804375) * c.b,
            Float(0.2126729) * c.r + Float(0.7151522) * c.g + Float(0.0721750) * c.b,
            Float(0.0193339) * c.r + Float(0.1191920) * c.g + Float(0.9503041) * c.b};
}
/// sRGB transfer function (IEC 61966-2-1) for a linear value in [0, 1].
inline Float srgb_encode(Float v) {
    if (v <= Float(0.0031308)) return 12.92f * v;
    return Float(1.055) * std::pow(v, Float(1 / 2.4)) - Float(0.055);
}
inline Float srgb_decode(Float v) {
    if (v <= Float(0.04045)) return v / 12.92f;
    return std::pow((v + Float(0.055)) / Float(1.055), Float(2.4));
}

}  // namespace sr
