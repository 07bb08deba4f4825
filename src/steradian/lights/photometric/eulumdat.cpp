#include "steradian/lights/photometric/eulumdat.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "steradian/core/error.h"
#include "steradian/lights/photometric/text_util.h"

namespace sr {
namespace {

using namespace photometric_detail;

bool near(double a, double b) { return std::abs(a - b) <= 1e-6; }

/// Line-addressed access to an EULUMDAT file (1-based line numbers).
class LdtLines {
  public:
    LdtLines(std::string_view text, std::string name)
        : m_lines(split_lines(text)), m_name(std::move(name)) {}

    size_t count() const { return m_lines.size(); }
    SourceLoc loc(size_t line) const { return SourceLoc{m_name, static_cast<int>(line), 1}; }

    std::string_view text(size_t line, const std::string& what) const {
        if (line == 0 || line > m_lines.size()) {
            throw_error(loc(std::max<size_t>(1, m_lines.size())),
                        "unexpected end of file: expected {} on line {}", what, line);
        }
        return trim(m_lines[line - 1]);
    }

    double number(size_t line, const std::string& what) const {
        std::string_view s = text(line, what);
        if (s.empty()) throw_error(loc(line), "expected {} (a number), found an empty line", what);
        std::string buf(s);
        // A decimal comma ("12,5") as written by some European tools.
        if (buf.find(',') != std::string::npos && buf.find('.') == std::string::npos &&
            std::count(buf.begin(), buf.end(), ',') == 1) {
            std::replace(buf.begin(), buf.end(), ',', '.');
        }
        double v = 0;
        switch (parse_number(buf, v)) {
            case NumberStatus::Ok:
                return v;
            case NumberStatus::NotFinite:
                throw_error(loc(line), "expected {} as a finite number, found {}", what, quoted(s));
            case NumberStatus::NotANumber:
                break;
        }
        throw_error(loc(line), "expected {} (one number on the line), found {}", what, quoted(s));
    }

    long integer(size_t line, const std::string& what, long lo, long hi) const {
        double v = number(line, what);
        if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
            throw_error(loc(line), "expected {} as an integer between {} and {}, found {}", what,
                        lo, hi, quoted(text(line, what)));
        }
        return static_cast<long>(v);
    }

    double non_negative(size_t line, const std::string& what) const {
        double v = number(line, what);
        if (v < 0) {
            throw_error(loc(line), "expected {} to be non-negative, found {}", what,
                        quoted(text(line, what)));
        }
        return v;
    }

  private:
    std::vector<std::string_view> m_lines;
    std::string m_name;
};

const char* symmetry_name(long isym) {
    switch (isym) {
        case 0:
            return "no symmetry";
        case 1:
            return "symmetry about the vertical axis";
        case 2:
            return "symmetry about the C0-C180 plane";
        case 3:
            return "symmetry about the C90-C270 plane";
        case 4:
            return "symmetry about the C0-C180 and C90-C270 planes";
        default:
            return "?";
    }
}

}  // namespace

PhotometricData parse_eulumdat(std::string_view text, const std::string& name) {
    LdtLines f(text, name);
    PhotometricData d;
    d.source = name;
    d.format = PhotometricFormat::Eulumdat;
    d.version = "EULUMDAT";
    d.type = PhotometricType::C;
    d.units_type = 2;
    d.future_use = std::nan("");
    if (f.count() == 0) {
        throw_error(f.loc(1), "empty file: expected the EULUMDAT company identification line");
    }

    d.keywords["COMPANY"] = std::string(f.text(1, "the company identification"));
    const long ityp = f.integer(2, "the type indicator Ityp (0-3)", 0, 3);
    d.keywords["ITYP"] = std::to_string(ityp);
    const long isym = f.integer(3, "the symmetry indicator Isym (0-4)", 0, 4);
    constexpr long kMaxCount = 1000000;
    const long mc = f.integer(4, "the number of C planes Mc", 1, kMaxCount);
    f.number(5, "the distance between C planes Dc");
    const long ng = f.integer(6, "the number of gamma angles Ng", 1, kMaxCount);
    f.number(7, "the distance between gamma angles Dg");
    if ((isym == 2 && mc % 2 != 0) || ((isym == 3 || isym == 4) && mc % 4 != 0)) {
        throw_error(f.loc(4),
                    "expected the number of C planes Mc = {} to be divisible by {} "
                    "for Isym {} ({})",
                    mc, isym == 2 ? 2 : 4, isym, symmetry_name(isym));
    }
    d.keywords["REPORT"] = std::string(f.text(8, "the measurement report number"));
    d.keywords["LUMINAIRE"] = std::string(f.text(9, "the luminaire name"));
    d.keywords["LUMINAIRE_NUMBER"] = std::string(f.text(10, "the luminaire number"));
    d.keywords["FILE_NAME"] = std::string(f.text(11, "the file name"));
    d.keywords["DATE_USER"] = std::string(f.text(12, "the date/user"));
    f.non_negative(13, "the luminaire length/diameter (mm)");
    f.non_negative(14, "the luminaire width (mm)");
    f.non_negative(15, "the luminaire height (mm)");
    const double lum_length = f.non_negative(16, "the luminous area length/diameter (mm)");
    const double lum_width = f.non_negative(17, "the luminous area width (mm)");
    double lum_height = 0;
    static const char* kHeights[] = {"C0", "C90", "C180", "C270"};
    for (size_t k = 0; k < 4; ++k) {
        lum_height = std::max(
            lum_height, f.non_negative(18 + k, fmt::format("the luminous area height at {} (mm)",
                                                           kHeights[k])));
    }
    d.length = lum_length / 1000.0;
    d.width = (lum_width > 0 ? lum_width : lum_length) / 1000.0;
    d.height = lum_height / 1000.0;
    if (lum_length == 0 && lum_width == 0) {
        d.shape = lum_height > 0 ? LuminousShape::Unknown : LuminousShape::Point;
    } else if (lum_width == 0) {
        d.shape = lum_height > 0 ? LuminousShape::VerticalCylinder : LuminousShape::Circular;
    } else {
        d.shape = lum_height > 0 ? LuminousShape::RectangularWithLuminousSides
                                 : LuminousShape::Rectangular;
    }
    d.downward_flux_fraction = f.non_negative(22, "the downward flux fraction (%)") / 100.0;
    d.light_output_ratio = f.non_negative(23, "the light output ratio (%)") / 100.0;
    const double cfli = f.number(24, "the conversion factor for luminous intensities");
    if (!(cfli > 0)) {
        throw_error(f.loc(24),
                    "expected the conversion factor for luminous intensities to be "
                    "positive, found {}",
                    quoted(f.text(24, "")));
    }
    d.measurement_tilt_deg = f.number(25, "the tilt of the luminaire during measurement");
    const long n = f.integer(26, "the number of lamp sets n", 1, kMaxCount);

    // All remaining sizes are known: check them against the file before allocating.
    const uint64_t planes = isym == 0   ? static_cast<uint64_t>(mc)
                            : isym == 1 ? 1
                            : isym == 4 ? static_cast<uint64_t>(mc / 4 + 1)
                                        : static_cast<uint64_t>(mc / 2 + 1);
    const uint64_t lamp_first = 27;
    const uint64_t dr_first = lamp_first + 6 * static_cast<uint64_t>(n);
    const uint64_t c_first = dr_first + 10;
    const uint64_t g_first = c_first + static_cast<uint64_t>(mc);
    const uint64_t i_first = g_first + static_cast<uint64_t>(ng);
    const uint64_t end = i_first + planes * static_cast<uint64_t>(ng);  // one past the last
    if (end - 1 > f.count()) {
        throw_error(f.loc(std::max<size_t>(1, f.count())),
                    "unexpected end of file: expected {} lines for n = {} lamp sets, Mc = {}, "
                    "Ng = {} and Isym = {} ({} intensity planes), but the file has {}",
                    end - 1, n, mc, ng, isym, planes, f.count());
    }

    for (long k = 0; k < n; ++k) {
        const auto ku = static_cast<uint64_t>(k);
        LampSet s;
        const size_t count_line = lamp_first + ku;
        s.count = static_cast<int>(f.integer(count_line,
                                             fmt::format("the number of lamps of set {}", k + 1),
                                             -kMaxCount, kMaxCount));
        s.type = std::string(f.text(lamp_first + n + ku, "the lamp type"));
        const size_t flux_line = lamp_first + 2 * n + ku;
        s.total_flux_lm =
            f.non_negative(flux_line, fmt::format("the total luminous flux of lamp set {}", k + 1));
        s.colour = std::string(f.text(lamp_first + 3 * n + ku, "the colour temperature"));
        s.cri = std::string(f.text(lamp_first + 4 * n + ku, "the colour rendering index"));
        s.watts = f.non_negative(lamp_first + 5 * n + ku,
                                 fmt::format("the wattage of lamp set {}", k + 1));
        if (k == 0) {
            if (s.count == 0) {
                throw_error(f.loc(count_line),
                            "expected a non-zero number of lamps in lamp set "
                            "1 (negative for absolute photometry), found 0");
            }
            if (!(s.total_flux_lm > 0)) {
                throw_error(f.loc(flux_line),
                            "expected a positive total luminous flux for lamp set 1 (the "
                            "intensities are in cd per 1000 lm of it), found {}",
                            quoted(f.text(flux_line, "")));
            }
        }
        d.lamp_sets.push_back(s);
    }
    const LampSet& set1 = d.lamp_sets.front();
    d.num_lamps = std::abs(set1.count);
    d.lamp_lumens = set1.count < 0 ? -1.0 : set1.total_flux_lm / d.num_lamps;
    d.input_watts = set1.watts;

    for (uint64_t k = 0; k < 10; ++k) {
        d.direct_ratios.push_back(
            f.number(dr_first + k, fmt::format("direct ratio {} of 10", k + 1)));
    }

    // C angles (all Mc of them, whatever the symmetry) and gamma angles.
    std::vector<double> c_angles;
    for (long k = 0; k < mc; ++k) {
        const size_t line = c_first + static_cast<uint64_t>(k);
        double c = f.number(line, fmt::format("C angle {} of {}", k + 1, mc));
        if (k == 0 && !near(c, 0)) {
            throw_error(f.loc(line), "expected the first C angle to be 0, found {}",
                        quoted(f.text(line, "")));
        }
        if (k > 0 && !(c > c_angles.back())) {
            throw_error(f.loc(line),
                        "expected the C angles to increase strictly, found {} after {}",
                        quoted(f.text(line, "")), c_angles.back());
        }
        if (c > 360 + 1e-6 || (c >= 360 - 1e-6 && k + 1 < mc)) {
            throw_error(f.loc(line), "expected C angle {} of {} to be below 360, found {}", k + 1,
                        mc, quoted(f.text(line, "")));
        }
        c_angles.push_back(c);
    }
    for (long k = 0; k < ng; ++k) {
        const size_t line = g_first + static_cast<uint64_t>(k);
        double g = f.number(line, fmt::format("gamma angle {} of {}", k + 1, ng));
        if (g < 0 || g > 180) {
            throw_error(f.loc(line), "expected gamma angle {} of {} between 0 and 180, found {}",
                        k + 1, ng, quoted(f.text(line, "")));
        }
        if (k > 0 && !(g > d.vertical_angles.back())) {
            throw_error(f.loc(line),
                        "expected the gamma angles to increase strictly, found {} after {}",
                        quoted(f.text(line, "")), d.vertical_angles.back());
        }
        d.vertical_angles.push_back(g);
    }

    // Stored planes: 1-based indices Mc1..Mc2 (wrapping past Mc), their angles in a
    // coordinate where they increase (Isym 3: C270..C345 become -90..-15).
    const uint64_t mc1 = isym == 3 ? static_cast<uint64_t>(3 * mc / 4 + 1) : 1;
    std::vector<double> stored_angle;
    std::vector<size_t> stored_angle_line;
    for (uint64_t p = 0; p < planes; ++p) {
        const uint64_t idx = (mc1 - 1 + p) % static_cast<uint64_t>(mc);
        double a = c_angles[idx];
        if (isym == 3 && a > 180) a -= 360;
        stored_angle.push_back(a);
        stored_angle_line.push_back(c_first + idx);
    }
    auto require_angle = [&](size_t which, double expected) {
        if (!near(stored_angle[which], expected)) {
            const size_t line = stored_angle_line[which];
            throw_error(f.loc(line),
                        "expected this C angle to be {} for Isym {} ({}) with Mc = {}, found {}",
                        expected < 0 ? expected + 360 : expected, isym, symmetry_name(isym), mc,
                        quoted(f.text(line, "")));
        }
    };
    if (isym == 2) {
        require_angle(stored_angle.size() - 1, 180);
    } else if (isym == 3) {
        require_angle(0, -90);
        require_angle(stored_angle.size() - 1, 90);
    } else if (isym == 4) {
        require_angle(stored_angle.size() - 1, 90);
    }
    for (size_t p = 1; p < stored_angle.size(); ++p) {
        if (!(stored_angle[p] > stored_angle[p - 1])) {
            throw_error(f.loc(stored_angle_line[p]),
                        "expected the stored C planes to increase strictly for Isym {} ({})", isym,
                        symmetry_name(isym));
        }
    }

    // Intensities (cd/klm) of the stored planes.
    d.candela_multiplier = cfli * set1.total_flux_lm / 1000.0;
    std::vector<std::vector<double>> stored(planes, std::vector<double>(static_cast<size_t>(ng)));
    for (uint64_t p = 0; p < planes; ++p) {
        for (long k = 0; k < ng; ++k) {
            const size_t line = i_first + p * static_cast<uint64_t>(ng) + static_cast<uint64_t>(k);
            double a = stored_angle[p] < 0 ? stored_angle[p] + 360 : stored_angle[p];
            const std::string what = fmt::format("the luminous intensity (cd/klm) at C {} gamma {}",
                                                 a, d.vertical_angles[static_cast<size_t>(k)]);
            const double v = f.non_negative(line, what);
            if (!(v * d.candela_multiplier <= kMaxCandela)) {
                throw_error(f.loc(line),
                            "{} times the conversion factor and the lamp flux / 1000 is {:g} "
                            "cd, more than the {:g} cd accepted",
                            what, v * d.candela_multiplier, kMaxCandela);
            }
            stored[p][static_cast<size_t>(k)] = v;
        }
    }
    for (size_t line = end; line <= f.count(); ++line) {
        if (!f.text(line, "").empty()) {
            throw_error(f.loc(line),
                        "expected the end of the file after {} intensity planes of {} values "
                        "(do Mc, Ng and Isym match the data?), found {}",
                        planes, ng, quoted(f.text(line, "")));
        }
    }

    // Expand to all C planes 0..360 (the 0 plane repeated at 360).
    d.horizontal_angles = c_angles;
    if (d.horizontal_angles.back() < 360 - 1e-6) d.horizontal_angles.push_back(360);
    for (double c : d.horizontal_angles) {
        double x = c;
        if (isym == 2) {
            if (x > 180) x = 360 - x;
        } else if (isym == 3) {
            if (x > 180) x -= 360;
            if (x > 90)
                x = 180 - x;
            else if (x < -90)
                x = -180 - x;
        } else if (isym == 4) {
            if (x > 180) x = 360 - x;
            if (x > 90) x = 180 - x;
        } else if (isym == 0) {
            if (x >= 360 - 1e-6 && stored_angle.back() < 360 - 1e-6) x = 0;
        }
        std::vector<double> row(static_cast<size_t>(ng));
        if (stored.size() == 1) {
            row = stored[0];
        } else {
            auto it = std::upper_bound(stored_angle.begin(), stored_angle.end(), x);
            size_t hi = std::clamp<size_t>(static_cast<size_t>(it - stored_angle.begin()), 1,
                                           stored_angle.size() - 1);
            size_t lo = hi - 1;
            double t = std::clamp((x - stored_angle[lo]) / (stored_angle[hi] - stored_angle[lo]),
                                  0.0, 1.0);
            for (size_t k = 0; k < row.size(); ++k) {
                row[k] = (1 - t) * stored[lo][k] + t * stored[hi][k];
            }
        }
        for (double& v : row) v *= d.candela_multiplier;
        d.candela.push_back(std::move(row));
    }
    return d;
}

PhotometricData read_eulumdat(const std::string& path) {
    return parse_eulumdat(read_file_text(path, "EULUMDAT file"), path);
}

}  // namespace sr
