#include "mesh/MeshText.h"

#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>

#include "base/Error.h"

namespace sightline::meshio {

/// A token as an error message shows it: quoted, shortened, control bytes replaced.
std::string quote(std::string_view token)
{
    if (token.empty())
        return "an empty value";
    std::string out = "'";
    for (const char c : token.substr(0, 40))
        out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return out + (token.size() > 40 ? "...'" : "'");
}

/// C's "+1.5" is common in exported files; from_chars takes no sign but '-'.
std::string_view withoutPlus(std::string_view token)
{
    if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+')
        token.remove_prefix(1);
    return token;
}

/// Why `token` is not a finite decimal number of magnitude at most `limit`; empty when it is one.
std::string readReal(std::string_view token, double& value, double limit)
{
    const std::string_view digits = withoutPlus(token);
    double d = 0.0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), d);
    if (ec == std::errc::invalid_argument || end != digits.data() + digits.size()) {
        if (digits.size() > 2 && (digits[1] == 'x' || digits[1] == 'X' || digits[2] == 'x' || digits[2] == 'X'))
            return quote(token) + " is hexadecimal; only decimal numbers are accepted";
        return quote(token) + " is not a number";
    }
    if (ec == std::errc::result_out_of_range)
        return quote(token) + " is out of range";
    if (!std::isfinite(d))
        return quote(token) + " is not finite";
    if (std::abs(d) > limit)
        return quote(token) + " is beyond the float range";
    value = d;
    return {};
}

std::string readFloat(std::string_view token, float& value)
{
    double d = 0.0;
    std::string why = readReal(token, d, FLT_MAX);
    value = static_cast<float>(d);
    return why;
}

/// Why `token` is not a decimal integer fitting in a long long; empty when it is one.
std::string readInteger(std::string_view token, long long& value)
{
    const std::string_view digits = withoutPlus(token);
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc::invalid_argument || end != digits.data() + digits.size())
        return quote(token) + " is not an integer";
    if (ec == std::errc::result_out_of_range)
        return quote(token) + " is out of range";
    return {};
}

std::string plural(unsigned long long count, const std::string& noun)
{
    const std::string many = noun == "vertex" ? "vertices" : noun + "s";
    return std::to_string(count) + " " + (count == 1 ? noun : many);
}

/// Appends polygon `p` (3 or more vertex indices) as a fan: a quad gives 2 triangles.
void addFan(Mesh& mesh, const std::vector<std::uint32_t>& p)
{
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
        mesh.indices.insert(mesh.indices.end(), {p[0], p[k], p[k + 1]});
}

std::string polygonTooSmall(std::size_t vertices)
{
    return "has " + plural(vertices, "vertex") + "; 3 or more are needed";
}

void failAt(const std::string& what, std::size_t line, const std::string& why)
{
    throw Error(what + ": line " + std::to_string(line) + ": " + why);
}

} // namespace sightline::meshio
