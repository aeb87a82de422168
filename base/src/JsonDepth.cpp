#include "base/JsonDepth.h"

#include "base/Error.h"

namespace sightline {

void checkJsonDepth(std::string_view text, const std::string& what, std::size_t maxDepth)
{
    std::size_t depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i; // the escaped character, '"' or '\\' included, never ends the string
            else if (c == '"')
                inString = false;
            continue;
        }
        switch (c) {
        case '"':
            inString = true;
            break;
        case '[':
        case '{':
            if (++depth > maxDepth)
                throw Error(what + ": JSON nested deeper than " + std::to_string(maxDepth) + " levels, at byte " +
                            std::to_string(i) + "; refused");
            break;
        case ']':
        case '}':
            if (depth > 0) // an unbalanced close is the parser's to report
                --depth;
            break;
        default:
            break;
        }
    }
}

} // namespace sightline
