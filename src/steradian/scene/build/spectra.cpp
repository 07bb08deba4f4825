/// Spectra from parameters: rgb, blackbody, named spectra, inline pairs and spectrum files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "steradian/core/input_file.h"
#include "steradian/scene/build/builder.h"

namespace sr {

namespace {

using build_detail::resolve_path;

/// The largest magnitude of a tabulated spectrum value: interpolation computes
/// v1 + t (v2 - v1), and v2 - v1 must not overflow a float (FLT_MAX is 3.4e38).
constexpr double kMaxSpectrumValue = 1e38;

/// Reads a two-column (wavelength, value) text file.
std::vector<Float> read_spectrum_file(const std::string& path, const SourceLoc& loc) {
    std::string text;
    try {
        text = read_regular_file(path, kMaxSmallFileBytes, "spectrum file");
    } catch (const Error& e) {
        throw Error(loc, e.what());
    }
    return parse_spectrum_file(text, path, loc);
}

}  // namespace

std::vector<Float> parse_spectrum_file(std::string_view text, const std::string& path,
                                       const SourceLoc& loc) {
    std::istringstream f{std::string(text)};
    std::vector<Float> v;
    std::string line;
    int line_no = 0;
    while (std::getline(f, line)) {
        ++line_no;
        auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        if (line.find_first_not_of(" \t\r\f\v") == std::string::npos) continue;
        // Exactly two numbers: a line of text, a third number or a number beyond double range
        // was skipped or dropped silently before.
        std::istringstream ss(line);
        double a, b;
        std::string extra;
        if (!(ss >> a) || !(ss >> b) || (ss >> extra))
            throw_error(loc, "{}:{}: expected \"wavelength value\" (two numbers), got \"{}\"", path,
                        line_no, printable(line));
        if (!std::isfinite(Float(a)) || !std::isfinite(Float(b)))
            throw_error(loc, "{}:{}: the wavelength and value must be finite floats", path,
                        line_no);
        if (!(std::abs(b) <= kMaxSpectrumValue))
            throw_error(loc, "{}:{}: the value {:g} is outside +-{:g}", path, line_no, b,
                        kMaxSpectrumValue);
        if (!v.empty() && !(Float(a) > v[v.size() - 2]))
            throw_error(loc, "{}:{}: wavelengths must increase ({} nm after {} nm)", path, line_no,
                        a, v[v.size() - 2]);
        v.push_back(Float(a));
        v.push_back(Float(b));
    }
    if (v.size() < 4) throw_error(loc, "spectrum file \"{}\" has fewer than two samples", path);
    return v;
}

Spectrum spectrum_from_param(const Param& p, SpectrumKind kind, const std::string& base_dir) {
    switch (p.type) {
        case ParamType::Rgb: {
            if (p.numbers.size() != 3)
                throw_error(p.loc, "\"rgb {}\" needs 3 values, got {}", p.name, p.numbers.size());
            Rgb c{Float(p.numbers[0]), Float(p.numbers[1]), Float(p.numbers[2])};
            if (c.r < 0 || c.g < 0 || c.b < 0)
                throw_error(p.loc, "\"rgb {}\" has a negative component", p.name);
            switch (kind) {
                case SpectrumKind::Albedo:
                    if (c.r > 1 || c.g > 1 || c.b > 1)
                        throw_error(p.loc,
                                    "\"rgb {}\" is a reflectance and must be in [0, 1], got "
                                    "[{} {} {}]",
                                    p.name, c.r, c.g, c.b);
                    return rgb_albedo_spectrum(c);
                case SpectrumKind::Unbounded:
                    return rgb_unbounded_spectrum(c);
                case SpectrumKind::Illuminant:
                    return rgb_illuminant_spectrum(c);
            }
            break;
        }
        case ParamType::Blackbody: {
            if (p.numbers.size() != 1)
                throw_error(p.loc, "\"blackbody {}\" needs one temperature", p.name);
            if (!(p.numbers[0] > 0))
                throw_error(p.loc, "\"blackbody {}\": temperature must be positive", p.name);
            return BlackbodySpectrum(Float(p.numbers[0]));
        }
        case ParamType::Spectrum: {
            if (!p.strings.empty()) {
                if (p.strings.size() != 1)
                    throw_error(p.loc, "\"spectrum {}\" expects one name or file", p.name);
                if (auto s = named_spectrum(p.strings[0])) return *s;
                std::string path = resolve_path(base_dir, p.strings[0]);
                std::error_code ec;  // (a name too long for the system throws without it)
                if (!std::filesystem::exists(path, ec))
                    throw_error(p.loc, "\"{}\" is neither a named spectrum nor a file",
                                p.strings[0]);
                auto pairs = read_spectrum_file(path, p.loc);
                return densely_sampled(piecewise_linear_from_interleaved(pairs, false));
            }
            if (p.numbers.size() < 4 || p.numbers.size() % 2)
                throw_error(p.loc, "\"spectrum {}\" needs (wavelength, value) pairs, at least two",
                            p.name);
            std::vector<Float> pairs(p.numbers.begin(), p.numbers.end());
            for (Float x : pairs)
                if (!std::isfinite(x))
                    throw_error(p.loc, "\"spectrum {}\": every wavelength and value must be a "
                                "finite float, got {}", p.name, x);
            for (size_t i = 1; i < pairs.size(); i += 2)
                if (!(std::abs(pairs[i]) <= kMaxSpectrumValue))
                    throw_error(p.loc, "\"spectrum {}\": the value {:g} is outside +-{:g}", p.name,
                                pairs[i], kMaxSpectrumValue);
            for (size_t i = 2; i < pairs.size(); i += 2)
                if (!(pairs[i] > pairs[i - 2]))
                    throw_error(p.loc, "\"spectrum {}\": wavelengths must increase", p.name);
            return densely_sampled(piecewise_linear_from_interleaved(pairs, false));
        }
        default:
            break;
    }
    throw_error(p.loc, "parameter \"{} {}\" is not a spectrum", to_string(p.type), p.name);
}

}  // namespace sr
