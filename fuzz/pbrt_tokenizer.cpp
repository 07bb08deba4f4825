// Feeds arbitrary bytes to the pbrt tokenizer (scene/pbrt/tokenizer.h) as a whole scene file
// and pulls every token, checking each token's kind, text and position.
#include "fuzz_target.h"
#include "steradian/scene/pbrt/tokenizer.h"

STERADIAN_FUZZ_TARGET(pbrt_tokenizer) {
    using namespace sr;
    using sr::fuzz::fuzz_check;
    const std::string name = "fuzz.pbrt";
    try {
        pbrt::Tokenizer tz{std::string(input), name};
        pbrt::Token t;
        int last_line = 1;
        while (tz.next(t)) {
            fuzz_check(t.line >= last_line && t.column >= 1, "token position goes backwards");
            last_line = t.line;
            switch (t.kind) {
                case pbrt::TokenKind::LBracket:
                    fuzz_check(t.text == "[", "'[' token");
                    break;
                case pbrt::TokenKind::RBracket:
                    fuzz_check(t.text == "]", "']' token");
                    break;
                case pbrt::TokenKind::Number:
                case pbrt::TokenKind::Identifier:
                    fuzz_check(!t.text.empty(), "empty bare word");
                    break;
                case pbrt::TokenKind::String:
                    break;
            }
        }
    } catch (const Error& e) {
        sr::fuzz::check_names_input(e, name);
    }
}
