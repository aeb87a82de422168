#pragma once
// What the mesh readers share (MeshReaders.h): text read line by line and token by token, numbers
// read strictly, and the messages' wording. The rules every reader follows are in MeshReaders.h.

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "visibility/Scene.h"

namespace sightline::meshio {

inline constexpr std::string_view::size_type npos = std::string_view::npos;

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

/// The lines of a text, one at a time; line ends and the BOM as MeshReaders.h says.
class Lines {
public:
    explicit Lines(std::string_view text, std::size_t firstNumber = 1) : text_(text), number_(firstNumber - 1)
    {
        if (text_.substr(0, 3) == "\xEF\xBB\xBF")
            pos_ = 3;
    }

    bool next(std::string_view& line)
    {
        if (pos_ >= text_.size())
            return false;
        const std::size_t end = text_.find_first_of("\r\n", pos_);
        line = text_.substr(pos_, end == npos ? npos : end - pos_);
        if (end == npos)
            pos_ = text_.size();
        else
            pos_ = end + (text_[end] == '\r' && end + 1 < text_.size() && text_[end + 1] == '\n' ? 2 : 1);
        ++number_;
        return true;
    }

    std::size_t number() const { return number_; } ///< of the line last returned
    std::size_t offset() const { return pos_; }    ///< just past the line last returned and its end

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t number_;
};

/// Whitespace-separated tokens of one line, one at a time (never collected: a line may be huge).
class Tokens {
public:
    explicit Tokens(std::string_view line = {}) : line_(line) {}

    bool next(std::string_view& token)
    {
        while (pos_ < line_.size() && isSpace(line_[pos_]))
            ++pos_;
        if (pos_ >= line_.size())
            return false;
        const std::size_t begin = pos_;
        while (pos_ < line_.size() && !isSpace(line_[pos_]))
            ++pos_;
        token = line_.substr(begin, pos_ - begin);
        return true;
    }

    /// What the line holds after the tokens read so far, spaces trimmed at both ends (a name that
    /// may hold spaces).
    std::string_view rest() const
    {
        std::string_view rest = line_.substr(std::min(pos_, line_.size()));
        while (!rest.empty() && isSpace(rest.front()))
            rest.remove_prefix(1);
        while (!rest.empty() && isSpace(rest.back()))
            rest.remove_suffix(1);
        return rest;
    }

private:
    std::string_view line_;
    std::size_t pos_ = 0;
};

/// Tokens across lines, for formats whose statements may span lines (ASCII STL).
class TextTokens {
public:
    explicit TextTokens(std::string_view text) : lines_(text) {}

    bool next(std::string_view& token)
    {
        for (std::string_view line; !tokens_.next(token);) {
            if (!lines_.next(line))
                return false;
            tokens_ = Tokens(line);
        }
        return true;
    }
    std::size_t line() const { return lines_.number(); }

private:
    Lines lines_;
    Tokens tokens_;
};

/// A token as an error message shows it: quoted, shortened, control bytes replaced.
std::string quote(std::string_view token);
/// C's "+1.5" is common in exported files; from_chars takes no sign but '-'.
std::string_view withoutPlus(std::string_view token);
/// Why `token` is not a finite decimal number of magnitude at most `limit`; empty when it is one.
std::string readReal(std::string_view token, double& value, double limit);
std::string readFloat(std::string_view token, float& value);
/// Why `token` is not a decimal integer fitting in a long long; empty when it is one.
std::string readInteger(std::string_view token, long long& value);
std::string plural(unsigned long long count, const std::string& noun);
/// Appends polygon `p` (3 or more vertex indices) as a fan: a quad gives 2 triangles.
void addFan(Mesh& mesh, const std::vector<std::uint32_t>& p);
std::string polygonTooSmall(std::size_t vertices);
/// An error at line `line` of a text file.
[[noreturn]] void failAt(const std::string& what, std::size_t line, const std::string& why);

} // namespace sightline::meshio
