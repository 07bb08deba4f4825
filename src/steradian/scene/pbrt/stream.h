#pragma once
/// The pbrt reader's token stream (one token of look-ahead) and number parsing (internal to
/// src/steradian/scene/pbrt/).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/scene/pbrt/tokenizer.h"

namespace sr::pbrt_detail {

using pbrt::Token;
using pbrt::Tokenizer;
using pbrt::TokenKind;

std::string describe(const Token& t);

bool parse_double(std::string_view s, double& v);

enum class IntParse { Ok, NotInteger, OutOfRange };

IntParse parse_int(std::string_view s, int& v);

/// The tokens of a file and of the files it Includes, as one stream with one token of
/// look-ahead. As in pbrt-v4, an Include pushes the included file on a stack of files and
/// its tokens are spliced into the stream: when it ends, the including file's tokens follow,
/// so a parameter list begun at the end of an included file continues after the Include.
class Stream {
  public:
    /// A stream over `root` (not owned), whose directory is `dir` and nesting depth `depth`.
    Stream(Tokenizer& root, std::string dir, int depth) : m_root(root) {
        m_files.push_back({&root, nullptr, std::move(dir), depth});
    }
    bool next(Token& t) {
        if (m_has_unget) {
            t = m_unget;
            m_has_unget = false;
            return true;
        }
        while (!m_files.empty()) {
            if (m_files.back().tz->next(t)) return true;
            // Tokens already read from the finished file may still be in use: it is freed
            // by release_finished().
            if (m_files.back().owned) m_finished.push_back(std::move(m_files.back().owned));
            m_files.pop_back();
        }
        return false;
    }
    void unget(const Token& t) {
        m_unget = t;
        m_has_unget = true;
    }
    /// Continues the stream with the tokens of `tz` (an Include), then those that follow.
    void push(std::unique_ptr<Tokenizer> tz, std::string dir, int depth) {
        Tokenizer* p = tz.get();
        m_files.push_back({p, std::move(tz), std::move(dir), depth});
    }
    /// The directory and nesting depth of the file the last token came from.
    const std::string& dir() const { return m_files.back().dir; }
    int depth() const { return m_files.back().depth; }
    /// Frees the included files that have ended; no token read before this call is used after.
    void release_finished() { m_finished.clear(); }

    SourceLoc loc(const Token& t) const {
        return t.file ? SourceLoc{*t.file, t.line, t.column} : SourceLoc{};
    }
    /// The end of the stream's first file (the stream ends there, after every included file).
    SourceLoc end_loc() const { return m_root.end_loc(); }

    /// The next token, or an "unexpected end of file" error mentioning `expected`.
    Token require(std::string_view what, std::string_view expected) {
        Token t;
        if (!next(t))
            throw_error(end_loc(), "{}: unexpected end of file, expected {}", what, expected);
        return t;
    }
    Token expect_string(std::string_view what) {
        Token t = require(what, "a quoted string");
        if (t.kind != TokenKind::String)
            throw_error(loc(t), "{}: expected a quoted string, got {}", what, describe(t));
        return t;
    }
    double expect_number(std::string_view what) {
        Token t = require(what, "a number");
        double v;
        if (t.kind != TokenKind::Number || !parse_double(t.text, v))
            throw_error(loc(t), "{}: expected a number, got {}", what, describe(t));
        return v;
    }

  private:
    struct File {
        Tokenizer* tz;
        std::unique_ptr<Tokenizer> owned;  ///< null for the root
        std::string dir;
        int depth;
    };
    Tokenizer& m_root;
    std::vector<File> m_files;
    std::vector<std::unique_ptr<Tokenizer>> m_finished;
    Token m_unget;
    bool m_has_unget = false;
};

}  // namespace sr::pbrt_detail
