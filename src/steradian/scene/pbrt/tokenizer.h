#pragma once
/// Tokenizer for the pbrt-v4 scene format: quoted strings (with escapes), brackets, and
/// bare words (numbers, directive names, true/false); `#` starts a comment to end of line.
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/core/error.h"

namespace sr::pbrt {

enum class TokenKind {
    String,      ///< "..." ; Token::text is the contents without quotes, escapes decoded
    Number,      ///< a bare word starting with a digit, '+', '-' or '.' (not yet validated)
    Identifier,  ///< any other bare word: directive names, true, false, ActiveTransform args
    LBracket,    ///< [
    RBracket,    ///< ]
};
std::string_view to_string(TokenKind k);

/// One token. `text` views memory owned by the Tokenizer that produced it and stays valid
/// as long as that Tokenizer lives. Line and column are 1-based; the column counts bytes
/// (a tab is one column).
struct Token {
    TokenKind kind = TokenKind::Identifier;
    std::string_view text;
    int line = 0;
    int column = 0;
    const std::string* file = nullptr;  ///< the Tokenizer's file name (lives as long as it)
};

/// Streaming tokenizer over a whole file held in memory. Lexical errors (unterminated
/// string, newline in string, invalid escape) throw sr::Error at the offending position.
class Tokenizer {
public:
    /// Tokenizes `contents`; `filename` is used in source locations only.
    Tokenizer(std::string contents, std::string filename);
    /// Reads the file at `path`. Throws sr::Error if it cannot be read: at `where` if given
    /// (e.g. the Include directive), else without a location.
    static std::unique_ptr<Tokenizer> from_file(const std::string& path,
                                                const SourceLoc* where = nullptr);

    /// The next token into `t`; false at end of input. Comments are skipped.
    bool next(Token& t);

    const std::string& filename() const { return m_filename; }
    SourceLoc loc(const Token& t) const { return {m_filename, t.line, t.column}; }
    /// The position just past the last character (for "unexpected end of file").
    SourceLoc end_loc() const;

private:
    bool lex_string(Token& t, const char* start);
    SourceLoc loc_at(const char* p) const;

    std::string m_filename;
    std::string m_contents;
    const char* m_pos = nullptr;
    const char* m_end = nullptr;
    const char* m_line_start = nullptr;
    int m_line = 1;
    std::deque<std::string> m_unescaped;  ///< storage for strings that contained escapes
};

/// A self-contained token, for tests and tools.
struct TokenInfo {
    TokenKind kind = TokenKind::Identifier;
    std::string text;
    SourceLoc loc;
};

/// All tokens of `text` (comments skipped); `filename` only names the source in locations.
std::vector<TokenInfo> tokenize_string(std::string_view text, const std::string& filename);

}  // namespace sr::pbrt
