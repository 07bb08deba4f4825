#include "steradian/lights/photometric/ies.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>

#include "steradian/core/error.h"
#include "steradian/lights/photometric/text_util.h"

namespace sr {
namespace {

using namespace photometric_detail;

constexpr double kFeetToMetres = 0.3048;

struct Token {
    std::string_view text;
    int line = 0;
    int column = 0;
};

/// Whitespace- and comma-separated tokens of lines[first..], with 1-based locations.
std::vector<Token> tokenize(const std::vector<std::string_view>& lines, size_t first) {
    std::vector<Token> out;
    for (size_t li = first; li < lines.size(); ++li) {
        std::string_view s = lines[li];
        size_t i = 0;
        while (i < s.size()) {
            char c = s[i];
            if (c == ' ' || c == '\t' || c == ',' || c == '\f' || c == '\v') {
                ++i;
                continue;
            }
            size_t start = i;
            while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != ',' && s[i] != '\f' &&
                   s[i] != '\v')
                ++i;
            out.push_back(Token{s.substr(start, i - start), static_cast<int>(li + 1),
                                static_cast<int>(start + 1)});
        }
    }
    return out;
}

/// Sequential reader of numeric tokens with located, explanatory errors.
class TokenStream {
  public:
    TokenStream(std::vector<Token> tokens, std::string file, int num_lines)
        : m_tokens(std::move(tokens)), m_file(std::move(file)), m_num_lines(num_lines) {}

    size_t remaining() const { return m_tokens.size() - m_pos; }
    bool done() const { return m_pos >= m_tokens.size(); }
    const Token& peek() const { return m_tokens[m_pos]; }
    const std::string& file() const { return m_file; }

    SourceLoc loc(const Token& t) const { return SourceLoc{m_file, t.line, t.column}; }
    /// Where the file ends: just after the last token (or the last line).
    SourceLoc end_loc() const {
        if (m_tokens.empty()) return SourceLoc{m_file, std::max(1, m_num_lines), 1};
        const Token& t = m_tokens.back();
        return SourceLoc{m_file, t.line, t.column + static_cast<int>(t.text.size())};
    }

    const Token& next(const std::string& what) {
        if (done()) throw_error(end_loc(), "unexpected end of file: expected {}", what);
        return m_tokens[m_pos++];
    }

    /// A finite number; `tok` receives its token for later range errors.
    double number(const std::string& what, const Token** tok = nullptr) {
        const Token& t = next(what);
        if (tok) *tok = &t;
        double v = 0;
        switch (parse_number(t.text, v)) {
            case NumberStatus::Ok:
                return v;
            case NumberStatus::NotFinite:
                throw_error(loc(t), "expected {} as a finite number, found {}", what,
                            quoted(t.text));
            case NumberStatus::NotANumber:
                break;
        }
        throw_error(loc(t), "expected {} (a number), found {}", what, quoted(t.text));
    }

    /// An integral number in [lo, hi] ("2" or "2.0").
    int integer(const std::string& what, long lo, long hi) {
        const Token* t = nullptr;
        double v = number(what, &t);
        if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
            throw_error(loc(*t), "expected {} as an integer between {} and {}, found {}", what, lo,
                        hi, quoted(t->text));
        }
        return static_cast<int>(v);
    }

  private:
    std::vector<Token> m_tokens;
    size_t m_pos = 0;
    std::string m_file;
    int m_num_lines = 0;
};

bool near(double a, double b) { return std::abs(a - b) <= 1e-6; }

/// Reads `n` strictly increasing finite angles; returns the tokens of the first and last.
std::vector<double> read_angles(TokenStream& ts, size_t n, const char* which,
                                const Token** first_tok, const Token** last_tok) {
    std::vector<double> angles;
    angles.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        const Token* t = nullptr;
        double a = ts.number(fmt::format("{} angle {} of {}", which, i + 1, n), &t);
        if (a < -360 || a > 360) {
            throw_error(ts.loc(*t),
                        "expected {} angle {} of {} in degrees between -360 and 360, "
                        "found {}",
                        which, i + 1, n, quoted(t->text));
        }
        if (!angles.empty() && !(a > angles.back())) {
            throw_error(ts.loc(*t),
                        "expected the {} angles to increase strictly, found {} after {}", which,
                        quoted(t->text), angles.back());
        }
        if (i == 0) *first_tok = t;
        *last_tok = t;
        angles.push_back(a);
    }
    return angles;
}

TiltData read_tilt_block(TokenStream& ts, const std::string& mode) {
    TiltData tilt;
    tilt.mode = mode;
    tilt.lamp_to_luminaire_geometry =
        ts.integer("the lamp-to-luminaire geometry of the tilt data (1, 2 or 3)", 1, 3);
    const Token* count_tok = nullptr;
    double count = ts.number("the number of tilt angles", &count_tok);
    if (count != std::floor(count) || count < 0) {
        throw_error(ts.loc(*count_tok),
                    "expected the number of tilt angles as a non-negative integer, found {}",
                    quoted(count_tok->text));
    }
    if (count * 2 > static_cast<double>(ts.remaining())) {
        throw_error(ts.end_loc(),
                    "unexpected end of file: expected {} tilt angles and {} multiplying factors "
                    "(only {} values remain)",
                    count, count, ts.remaining());
    }
    const auto n = static_cast<size_t>(count);
    for (size_t i = 0; i < n; ++i) {
        const Token* t = nullptr;
        double a = ts.number(fmt::format("tilt angle {} of {}", i + 1, n), &t);
        if (!tilt.angles.empty() && !(a > tilt.angles.back())) {
            throw_error(ts.loc(*t),
                        "expected the tilt angles to increase strictly, found {} after {}",
                        quoted(t->text), tilt.angles.back());
        }
        tilt.angles.push_back(a);
    }
    for (size_t i = 0; i < n; ++i) {
        const Token* t = nullptr;
        double f = ts.number(fmt::format("tilt multiplying factor {} of {}", i + 1, n), &t);
        if (f < 0) {
            throw_error(ts.loc(*t),
                        "expected tilt multiplying factor {} of {} to be "
                        "non-negative, found {}",
                        i + 1, n, quoted(t->text));
        }
        tilt.factors.push_back(f);
    }
    return tilt;
}

struct VersionInfo {
    std::string version;
    bool consumed_first_line = false;
};

VersionInfo detect_version(std::string_view first_line, const std::string& name) {
    std::string compact;
    for (char c : to_upper(trim(first_line))) {
        if (c != ' ' && c != '\t') compact += c;
    }
    struct Known {
        const char* tag;
        const char* version;
    };
    static const Known known[] = {
        {"IESNA:LM-63-1995", "LM-63-1995"}, {"IESNA:LM-63-2002", "LM-63-2002"},
        {"IES:LM-63-2019", "LM-63-2019"},   {"IESNA:LM-63-2019", "LM-63-2019"},
        {"IESNA:LM-63-1991", "LM-63-1991"}, {"IESNA91", "LM-63-1991"},
    };
    for (const auto& k : known) {
        if (compact == k.tag) return {k.version, true};
    }
    if (compact.rfind("IESNA", 0) == 0 || compact.rfind("IES:", 0) == 0) {
        throw_error(SourceLoc{name, 1, 1},
                    "unknown LM-63 version line {}: expected IESNA91, IESNA:LM-63-1995, "
                    "IESNA:LM-63-2002 or IES:LM-63-2019 (or no version line for LM-63-1986)",
                    quoted(trim(first_line)));
    }
    return {"LM-63-1986", false};
}

bool all_numeric(std::string_view line) {
    std::vector<std::string_view> one{line};
    auto toks = tokenize(one, 0);
    if (toks.empty()) return false;
    for (const auto& t : toks) {
        double v = 0;
        if (parse_number(t.text, v) != NumberStatus::Ok) return false;
    }
    return true;
}

/// "TILT" followed by optional blanks and '='; returns the text after '=' in `value`.
bool tilt_line(std::string_view line, std::string_view& value) {
    std::string_view s = trim(line);
    if (s.size() < 5 || to_upper(s.substr(0, 4)) != "TILT") return false;
    s.remove_prefix(4);
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    if (s.empty() || s.front() != '=') return false;
    s.remove_prefix(1);
    value = trim(s);
    return true;
}

}  // namespace

PhotometricData parse_ies(std::string_view text, const std::string& name) {
    PhotometricData d;
    d.source = name;
    d.format = PhotometricFormat::Ies;
    const auto lines = split_lines(text);
    const int num_lines = static_cast<int>(lines.size());
    if (lines.empty()) {
        throw_error(SourceLoc{name, 1, 1},
                    "empty file: expected an LM-63 version line or a TILT= line");
    }

    VersionInfo vi = detect_version(lines[0], name);
    d.version = vi.version;
    const bool old_format = d.version == "LM-63-1986" || d.version == "LM-63-1991";

    // Header: keywords and labels up to the TILT= line.
    size_t li = vi.consumed_first_line ? 1 : 0;
    std::string last_keyword;
    std::string_view tilt_value;
    bool found_tilt = false;
    int first_numeric_line = 0;
    for (; li < lines.size(); ++li) {
        std::string_view line = trim(lines[li]);
        if (tilt_line(line, tilt_value)) {
            found_tilt = true;
            break;
        }
        if (!line.empty() && line.front() == '[') {
            size_t close = line.find(']');
            if (close != std::string_view::npos && close > 1) {
                std::string key = to_upper(trim(line.substr(1, close - 1)));
                std::string value(trim(line.substr(close + 1)));
                if (key == "MORE" && !last_keyword.empty()) {
                    d.keywords[last_keyword] += "\n" + value;
                    continue;
                }
                auto [it, inserted] = d.keywords.emplace(key, value);
                if (!inserted) it->second += "\n" + value;
                last_keyword = key;
                continue;
            }
        }
        if (first_numeric_line == 0 && all_numeric(line))
            first_numeric_line = static_cast<int>(li + 1);
        d.header_lines.emplace_back(line);
    }
    if (!found_tilt) {
        int at = first_numeric_line > 0 ? first_numeric_line : std::max(1, num_lines);
        throw_error(SourceLoc{name, at, 1},
                    "missing TILT line: expected 'TILT=NONE', 'TILT=INCLUDE' or 'TILT=<file>' "
                    "before the photometric data");
    }
    const int tilt_line_no = static_cast<int>(li + 1);
    if (tilt_value.empty()) {
        throw_error(SourceLoc{name, tilt_line_no, 1},
                    "expected NONE, INCLUDE or a file name after TILT=");
    }

    TokenStream ts(tokenize(lines, li + 1), name, num_lines);
    const std::string tilt_upper = to_upper(tilt_value);
    if (tilt_upper == "NONE") {
        d.tilt.mode = "NONE";
    } else if (tilt_upper == "INCLUDE") {
        d.tilt = read_tilt_block(ts, "INCLUDE");
    } else {
        std::filesystem::path tilt_path(std::string{tilt_value});
        if (tilt_path.is_relative()) {
            tilt_path = std::filesystem::path(name).parent_path() / tilt_path;
        }
        std::string tilt_text;
        try {
            tilt_text = read_file_text(tilt_path.string(), "tilt file");
        } catch (const Error& e) {
            throw_error(SourceLoc{name, tilt_line_no, 1},
                        "expected a readable tilt file {} (relative to the IES file): {}",
                        quoted(tilt_value), e.what());
        }
        const auto tilt_lines = split_lines(tilt_text);
        TokenStream tilt_ts(tokenize(tilt_lines, 0), tilt_path.string(),
                            static_cast<int>(tilt_lines.size()));
        d.tilt = read_tilt_block(tilt_ts, std::string(tilt_value));
        if (!tilt_ts.done()) {
            throw_error(tilt_ts.loc(tilt_ts.peek()),
                        "expected the end of the tilt file after {} tilt factors, found {}",
                        d.tilt.factors.size(), quoted(tilt_ts.peek().text));
        }
    }

    // Lamp and luminaire line.
    constexpr long kMaxCount = std::numeric_limits<int>::max();
    d.num_lamps = ts.integer("the number of lamps", 0, kMaxCount);
    const Token* t = nullptr;
    double lumens = ts.number("the lumens per lamp", &t);
    if (!(lumens > 0) && !near(lumens, -1)) {
        throw_error(ts.loc(*t),
                    "expected the lumens per lamp to be positive, or -1 for absolute "
                    "photometry, found {}",
                    quoted(t->text));
    }
    d.lamp_lumens = near(lumens, -1) ? -1.0 : lumens;
    d.candela_multiplier = ts.number("the candela multiplier", &t);
    if (!(d.candela_multiplier > 0)) {
        throw_error(ts.loc(*t), "expected the candela multiplier to be positive, found {}",
                    quoted(t->text));
    }
    const int nv = ts.integer("the number of vertical angles", 1, kMaxCount);
    const int nh = ts.integer("the number of horizontal angles", 1, kMaxCount);
    const int type_code = ts.integer("the photometric type (1 = C, 2 = B, 3 = A)", 1, 3);
    d.type = static_cast<PhotometricType>(type_code);
    d.units_type = ts.integer("the units type (1 = feet, 2 = metres)", 1, 2);
    const double w = ts.number("the luminous opening width");
    const double l = ts.number("the luminous opening length");
    const double h = ts.number("the luminous opening height");
    const double unit = d.units_type == 1 ? kFeetToMetres : 1.0;
    d.width = std::abs(w) * unit;
    d.length = std::abs(l) * unit;
    d.height = std::abs(h) * unit;
    d.shape = classify_luminous_shape(w, l, h);

    // Ballast line.
    d.ballast_factor = ts.number("the ballast factor", &t);
    if (!(d.ballast_factor > 0)) {
        throw_error(ts.loc(*t), "expected the ballast factor to be positive, found {}",
                    quoted(t->text));
    }
    const char* future_name = old_format                  ? "the ballast-lamp photometric factor"
                              : d.version == "LM-63-2019" ? "the file generation type"
                                                          : "the future-use value";
    d.future_use = ts.number(future_name, &t);
    if (old_format) {
        if (!(d.future_use > 0)) {
            throw_error(ts.loc(*t),
                        "expected the ballast-lamp photometric factor to be positive, found {}",
                        quoted(t->text));
        }
        d.ballast_lamp_factor = d.future_use;
    }
    d.input_watts = ts.number("the input watts", &t);
    if (d.input_watts < 0) {
        throw_error(ts.loc(*t), "expected the input watts to be non-negative, found {}",
                    quoted(t->text));
    }

    // Counts against what the file holds (caps every allocation below).
    const uint64_t needed = static_cast<uint64_t>(nv) + static_cast<uint64_t>(nh) +
                            static_cast<uint64_t>(nv) * static_cast<uint64_t>(nh);
    if (needed > ts.remaining()) {
        throw_error(ts.end_loc(),
                    "unexpected end of file: expected {} vertical angles, {} horizontal angles "
                    "and {} x {} candela values ({} numbers), but only {} remain",
                    nv, nh, nh, nv, needed, ts.remaining());
    }

    const Token *v_first = nullptr, *v_last = nullptr, *h_first = nullptr, *h_last = nullptr;
    d.vertical_angles = read_angles(ts, static_cast<size_t>(nv), "vertical", &v_first, &v_last);
    d.horizontal_angles = read_angles(ts, static_cast<size_t>(nh), "horizontal", &h_first, &h_last);
    const auto& V = d.vertical_angles;
    const auto& H = d.horizontal_angles;
    if (d.type == PhotometricType::C) {
        if (!near(V.front(), 0) && !near(V.front(), 90)) {
            throw_error(ts.loc(*v_first),
                        "expected the first vertical angle of a Type C file to be 0 or 90, "
                        "found {}",
                        quoted(v_first->text));
        }
        if (!near(V.back(), 90) && !near(V.back(), 180)) {
            throw_error(ts.loc(*v_last),
                        "expected the last vertical angle of a Type C file to be 90 or 180, "
                        "found {}",
                        quoted(v_last->text));
        }
        if (V.size() < 2) {
            throw_error(ts.loc(*v_first),
                        "expected at least 2 vertical angles (0-90, 90-180 or 0-180)");
        }
        if (near(H.front(), 0)) {
            const double last = H.back();
            if (!(near(last, 0) || near(last, 90) || near(last, 180) ||
                  (last > 180 && last <= 360 + 1e-6))) {
                throw_error(ts.loc(*h_last),
                            "expected the last horizontal angle of a Type C file to be 0, 90, "
                            "180 or 360 (or above 180 for no symmetry), found {}",
                            quoted(h_last->text));
            }
        } else if (near(H.front(), 90)) {
            if (!near(H.back(), 270)) {
                throw_error(ts.loc(*h_last),
                            "expected the last horizontal angle to be 270 when the first is 90 "
                            "(symmetry about the 90-270 plane), found {}",
                            quoted(h_last->text));
            }
        } else {
            throw_error(ts.loc(*h_first),
                        "expected the first horizontal angle of a Type C file to be 0 (or 90 "
                        "for symmetry about the 90-270 plane), found {}",
                        quoted(h_first->text));
        }
    } else {
        const char* tn = d.type == PhotometricType::B ? "B" : "A";
        if (!near(V.front(), -90) && !near(V.front(), 0)) {
            throw_error(ts.loc(*v_first),
                        "expected the first vertical angle of a Type {} file to be -90 or 0, "
                        "found {}",
                        tn, quoted(v_first->text));
        }
        if (!near(V.back(), 90)) {
            throw_error(ts.loc(*v_last),
                        "expected the last vertical angle of a Type {} file to be 90, found {}", tn,
                        quoted(v_last->text));
        }
        if (!near(H.front(), -90) && !near(H.front(), 0)) {
            throw_error(ts.loc(*h_first),
                        "expected the first horizontal angle of a Type {} file to be -90 or 0, "
                        "found {}",
                        tn, quoted(h_first->text));
        }
        if (!near(H.back(), 90)) {
            throw_error(ts.loc(*h_last),
                        "expected the last horizontal angle of a Type {} file to be 90, found "
                        "{}",
                        tn, quoted(h_last->text));
        }
    }

    const double scale = d.candela_multiplier * d.ballast_factor * d.ballast_lamp_factor;
    d.candela.assign(static_cast<size_t>(nh), std::vector<double>(static_cast<size_t>(nv)));
    for (int ih = 0; ih < nh; ++ih) {
        for (int iv = 0; iv < nv; ++iv) {
            const std::string what =
                fmt::format("the candela value for horizontal angle {} and vertical angle {}",
                            H[static_cast<size_t>(ih)], V[static_cast<size_t>(iv)]);
            double cd = ts.number(what, &t);
            if (cd < 0) {
                throw_error(ts.loc(*t), "expected {} to be non-negative, found {}", what,
                            quoted(t->text));
            }
            if (!(cd * scale <= kMaxCandela)) {
                throw_error(ts.loc(*t),
                            "{} times the candela multiplier and ballast factors is {:g} cd, "
                            "more than the {:g} cd accepted",
                            what, cd * scale, kMaxCandela);
            }
            d.candela[static_cast<size_t>(ih)][static_cast<size_t>(iv)] = cd * scale;
        }
    }
    if (!ts.done()) {
        throw_error(ts.loc(ts.peek()),
                    "expected the end of the file after {} x {} candela values, found {} "
                    "(do the angle counts match the data?)",
                    nh, nv, quoted(ts.peek().text));
    }

    d.lamp_sets.push_back(LampSet{d.num_lamps, "",
                                  d.lamp_lumens < 0 ? -1.0 : d.lamp_lumens * d.num_lamps, "", "",
                                  d.input_watts});
    return d;
}

PhotometricData read_ies(const std::string& path) {
    return parse_ies(read_file_text(path, "IES file"), path);
}

}  // namespace sr
