#pragma once
/// The pbrt reader's token stream (one token of look-ahead) and number parsing (internal to
/// src/steradian/scene/pbrt/).
#include <string>
#include <string_view>

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

/// Tokens of one file with one token of look-ahead.
class Stream {
  public:
    explicit Stream(Tokenizer& tz) : m_tz(tz) {}
    bool next(Token& t) {
        if (m_has_unget) {
            t = m_unget;
            m_has_unget = false;
            return true;
        }
        return m_tz.next(t);
    }
    void unget(const Token& t) {
        m_unget = t;
        m_has_unget = true;
    }
    SourceLoc loc(const Token& t) const { return m_tz.loc(t); }
    SourceLoc end_loc() const { return m_tz.end_loc(); }

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
    Tokenizer& m_tz;
    Token m_unget;
    bool m_has_unget = false;
};

}  // namespace sr::pbrt_detail
