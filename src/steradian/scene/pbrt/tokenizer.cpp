#include "steradian/scene/pbrt/tokenizer.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "steradian/core/input_file.h"

namespace sr::pbrt {

std::string_view to_string(TokenKind k) {
    switch (k) {
        case TokenKind::String: return "string";
        case TokenKind::Number: return "number";
        case TokenKind::Identifier: return "identifier";
        case TokenKind::LBracket: return "'['";
        case TokenKind::RBracket: return "']'";
    }
    return "?";
}

namespace {

// Character classes: whitespace separates tokens; '"', '[' and ']' also end a bare word
// (as in pbrt-v4, '#' does not: "1#x" is one malformed word).
enum : unsigned char { kWord = 0, kSpace = 1, kDelim = 2 };

struct CharTable {
    unsigned char cls[256] = {};
    constexpr CharTable() {
        cls[unsigned(' ')] = cls[unsigned('\t')] = cls[unsigned('\r')] = kSpace;
        cls[unsigned('\n')] = cls[unsigned('\f')] = cls[unsigned('\v')] = kSpace;
        cls[unsigned('"')] = cls[unsigned('[')] = cls[unsigned(']')] = kDelim;
    }
};
constexpr CharTable kTable;

inline unsigned char char_class(char c) { return kTable.cls[static_cast<unsigned char>(c)]; }

bool decode_escape(char c, char& out) {
    switch (c) {
        case 'b': out = '\b'; return true;
        case 'f': out = '\f'; return true;
        case 'n': out = '\n'; return true;
        case 'r': out = '\r'; return true;
        case 't': out = '\t'; return true;
        case '\\': out = '\\'; return true;
        case '\'': out = '\''; return true;
        case '"': out = '"'; return true;
        default: return false;
    }
}

}  // namespace

Tokenizer::Tokenizer(std::string contents, std::string filename)
    : m_filename(std::move(filename)), m_contents(std::move(contents)) {
    m_pos = m_contents.data();
    m_end = m_pos + m_contents.size();
    m_line_start = m_pos;
    const auto* u = reinterpret_cast<const unsigned char*>(m_pos);
    size_t n = m_contents.size();
    if (n >= 2 && ((u[0] == 0xfe && u[1] == 0xff) || (u[0] == 0xff && u[1] == 0xfe)))
        throw_error(SourceLoc{m_filename, 1, 1},
                    "file is encoded in UTF-16; only UTF-8 (or ASCII) scene files are supported");
    if (n >= 3 && u[0] == 0xef && u[1] == 0xbb && u[2] == 0xbf) {  // UTF-8 byte order mark
        m_pos += 3;
        m_line_start = m_pos;
    }
}

std::unique_ptr<Tokenizer> Tokenizer::from_file(const std::string& path, const SourceLoc* where) {
    auto fail = [&](const std::string& why) -> std::unique_ptr<Tokenizer> {
        std::string msg = fmt::format("cannot read scene file \"{}\": {}", path, why);
        throw Error(where ? *where : SourceLoc{}, msg);  // an empty loc prints no prefix
    };
    // gzip data is decompressed in memory, whatever the name (pbrt-v4 goes by the name:
    // it decompresses a ".gz" file and rejects one that is not gzip data, as we do).
    std::string contents;
    bool gz = false;
    try {
        contents = read_input_file(path, kMaxSceneFileBytes, "scene file", &gz);
    } catch (const Error& e) {
        throw Error(where ? *where : SourceLoc{}, e.what());
    }
    if (!gz && path.size() >= 3 && path.compare(path.size() - 3, 3, ".gz") == 0)
        return fail(
            "the name ends in \".gz\" but the file is not gzip data (it does not "
            "start with the bytes 1f 8b)");
    return std::make_unique<Tokenizer>(std::move(contents), path);
}

SourceLoc Tokenizer::loc_at(const char* p) const {
    return {m_filename, m_line, int(p - m_line_start) + 1};
}

SourceLoc Tokenizer::end_loc() const {
    // Only meaningful once the input is exhausted; then m_pos == m_end.
    return loc_at(m_pos);
}

bool Tokenizer::next(Token& t) {
    for (;;) {
        while (m_pos < m_end && char_class(*m_pos) == kSpace) {
            if (*m_pos == '\n') {
                ++m_line;
                m_line_start = m_pos + 1;
            }
            ++m_pos;
        }
        if (m_pos == m_end) return false;

        const char* start = m_pos;
        char c = *start;
        t.file = &m_filename;
        t.line = m_line;
        t.column = int(start - m_line_start) + 1;
        switch (c) {
            case '#':
                while (m_pos < m_end && *m_pos != '\n') ++m_pos;
                continue;
            case '[':
            case ']':
                ++m_pos;
                t.kind = c == '[' ? TokenKind::LBracket : TokenKind::RBracket;
                t.text = std::string_view(start, 1);
                return true;
            case '"':
                return lex_string(t, start);
            default:
                break;
        }
        ++m_pos;
        while (m_pos < m_end && char_class(*m_pos) == kWord) ++m_pos;
        t.text = std::string_view(start, size_t(m_pos - start));
        bool numeric = (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
        t.kind = numeric ? TokenKind::Number : TokenKind::Identifier;
        return true;
    }
}

bool Tokenizer::lex_string(Token& t, const char* start) {
    const char* p = start + 1;
    bool escaped = false;
    for (;;) {
        if (p == m_end) throw_error(loc_at(start), "unterminated string");
        char c = *p;
        if (c == '"') break;
        if (c == '\n') throw_error(loc_at(start), "newline in string (missing closing quote?)");
        if (c == '\\') {
            escaped = true;
            if (p + 1 == m_end) throw_error(loc_at(start), "unterminated string");
            char out;
            if (p[1] == '\n')
                throw_error(loc_at(start), "newline in string (missing closing quote?)");
            if (!decode_escape(p[1], out))
                throw_error(loc_at(p), "invalid escape sequence '\\{}' in string", p[1]);
            p += 2;
            continue;
        }
        ++p;
    }
    std::string_view raw(start + 1, size_t(p - start - 1));
    m_pos = p + 1;
    t.kind = TokenKind::String;
    if (!escaped) {
        t.text = raw;
        return true;
    }
    std::string& s = m_unescaped.emplace_back();
    s.reserve(raw.size());
    for (size_t i = 0; i < raw.size(); ++i) {
        char out = raw[i];
        if (out == '\\') decode_escape(raw[++i], out);
        s.push_back(out);
    }
    t.text = s;
    return true;
}

std::vector<TokenInfo> tokenize_string(std::string_view text, const std::string& filename) {
    Tokenizer tz(std::string(text), filename);
    std::vector<TokenInfo> out;
    Token t;
    while (tz.next(t)) out.push_back({t.kind, std::string(t.text), tz.loc(t)});
    return out;
}

}  // namespace sr::pbrt
