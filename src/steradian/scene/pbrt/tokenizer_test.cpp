#include "steradian/scene/pbrt/tokenizer.h"

#include <gtest/gtest.h>

namespace sr::pbrt {
namespace {

void expect_token(const TokenInfo& t, TokenKind kind, const std::string& text, int line,
                  int column) {
    EXPECT_EQ(t.kind, kind) << "token '" << t.text << "'";
    EXPECT_EQ(t.text, text);
    EXPECT_EQ(t.loc.line, line) << "token '" << t.text << "'";
    EXPECT_EQ(t.loc.column, column) << "token '" << t.text << "'";
}

void expect_lex_error(const std::string& text, const std::string& what, int line, int column) {
    SCOPED_TRACE(text);
    try {
        tokenize_string(text, "lex.pbrt");
        ADD_FAILURE() << "expected an error containing: " << what;
    } catch (const Error& e) {
        EXPECT_NE(e.message().find(what), std::string::npos) << "message: " << e.message();
        EXPECT_EQ(e.loc().file, "lex.pbrt");
        EXPECT_EQ(e.loc().line, line) << e.what();
        EXPECT_EQ(e.loc().column, column) << e.what();
    }
}

TEST(PbrtTokenizer, KindsTextAndLocations) {
    auto t = tokenize_string("Shape \"sphere\" [ 1 -2.5 ]\n  \"float r\"\t.5 true\n", "a.pbrt");
    ASSERT_EQ(t.size(), 9u);
    expect_token(t[0], TokenKind::Identifier, "Shape", 1, 1);
    expect_token(t[1], TokenKind::String, "sphere", 1, 7);
    expect_token(t[2], TokenKind::LBracket, "[", 1, 16);
    expect_token(t[3], TokenKind::Number, "1", 1, 18);
    expect_token(t[4], TokenKind::Number, "-2.5", 1, 20);
    expect_token(t[5], TokenKind::RBracket, "]", 1, 25);
    expect_token(t[6], TokenKind::String, "float r", 2, 3);
    expect_token(t[7], TokenKind::Number, ".5", 2, 13);  // a tab is one column
    expect_token(t[8], TokenKind::Identifier, "true", 2, 16);
    EXPECT_EQ(t[0].loc.file, "a.pbrt");
    EXPECT_EQ(t[0].loc.to_string(), "a.pbrt:1:1");
}

TEST(PbrtTokenizer, CommentsAreSkipped) {
    auto t = tokenize_string("# header \"not a string\n\nWorldBegin # trailing [ ]\n#\n  #x\nA#b",
                             "c.pbrt");
    ASSERT_EQ(t.size(), 2u);
    expect_token(t[0], TokenKind::Identifier, "WorldBegin", 3, 1);
    // As in pbrt-v4, '#' only starts a comment at the start of a token.
    expect_token(t[1], TokenKind::Identifier, "A#b", 6, 1);
    EXPECT_TRUE(tokenize_string("# only a comment", "c.pbrt").empty());
    EXPECT_TRUE(tokenize_string("", "c.pbrt").empty());
}

TEST(PbrtTokenizer, StringEscapes) {
    auto t = tokenize_string(R"("a\"b\\c\nd\te" "x\'y" "plain")", "e.pbrt");
    ASSERT_EQ(t.size(), 3u);
    expect_token(t[0], TokenKind::String, "a\"b\\c\nd\te", 1, 1);
    expect_token(t[1], TokenKind::String, "x'y", 1, 17);
    expect_token(t[2], TokenKind::String, "plain", 1, 24);
    auto empty = tokenize_string(R"("")", "e.pbrt");
    ASSERT_EQ(empty.size(), 1u);
    expect_token(empty[0], TokenKind::String, "", 1, 1);
}

TEST(PbrtTokenizer, DelimitersSplitWords) {
    auto t = tokenize_string("a\"b\"[c]1e3", "d.pbrt");
    ASSERT_EQ(t.size(), 6u);
    expect_token(t[0], TokenKind::Identifier, "a", 1, 1);
    expect_token(t[1], TokenKind::String, "b", 1, 2);
    expect_token(t[2], TokenKind::LBracket, "[", 1, 5);
    expect_token(t[3], TokenKind::Identifier, "c", 1, 6);
    expect_token(t[4], TokenKind::RBracket, "]", 1, 7);
    expect_token(t[5], TokenKind::Number, "1e3", 1, 8);
}

TEST(PbrtTokenizer, NumbersAndIdentifiers) {
    auto t = tokenize_string("-1 +2 .5 1e3 abc e5 nan", "n.pbrt");
    ASSERT_EQ(t.size(), 7u);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(t[size_t(i)].kind, TokenKind::Number) << i;
    for (int i = 4; i < 7; ++i) EXPECT_EQ(t[size_t(i)].kind, TokenKind::Identifier) << i;
}

TEST(PbrtTokenizer, LineEndingsAndByteOrderMark) {
    auto t = tokenize_string("A\r\n  B\r\n\r\nC", "r.pbrt");
    ASSERT_EQ(t.size(), 3u);
    expect_token(t[0], TokenKind::Identifier, "A", 1, 1);
    expect_token(t[1], TokenKind::Identifier, "B", 2, 3);
    expect_token(t[2], TokenKind::Identifier, "C", 4, 1);
    auto b = tokenize_string("\xEF\xBB\xBFWorldBegin", "b.pbrt");
    ASSERT_EQ(b.size(), 1u);
    expect_token(b[0], TokenKind::Identifier, "WorldBegin", 1, 1);
}

TEST(PbrtTokenizer, Errors) {
    expect_lex_error("WorldBegin\n\n  Shape \"sph", "unterminated string", 3, 9);
    expect_lex_error("Shape\n  \"abc\n\"", "newline in string", 2, 3);
    expect_lex_error("  \"ab\\qc\"", "invalid escape sequence '\\q' in string", 1, 6);
    expect_lex_error("\"abc\\", "unterminated string", 1, 1);
    expect_lex_error("\xFF\xFE" "A\0B", "UTF-16", 1, 1);
}

}  // namespace
}  // namespace sr::pbrt
