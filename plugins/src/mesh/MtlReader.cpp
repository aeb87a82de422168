#include "mesh/MeshReaders.h"

#include "mesh/MeshText.h"

namespace sightline::meshio {

namespace {

/// Up to `most` numbers that follow an option; fewer where a token is not one (it is left unread).
std::vector<double> optionNumbers(Tokens& t, int most)
{
    std::vector<double> values;
    for (int k = 0; k < most; ++k) {
        Tokens before = t;
        std::string_view token;
        float value = 0.0f;
        if (!t.next(token) || !readFloat(token, value).empty()) {
            t = before;
            break;
        }
        values.push_back(value);
    }
    return values;
}

/// "map_Kd [options] file": the file is what the line holds after the options. -o and -s (u [v
/// [w]]) move and scale the texture, -clamp on clamps it; the other options are passed over with
/// their arguments (-mm: two numbers; -bm, -boost, -texres: one; the rest one word).
void readMapKd(Tokens t, MtlMaterial& material)
{
    material.offset = glm::dvec2(0.0), material.scale = glm::dvec2(1.0), material.clamp = false;
    for (;;) {
        Tokens before = t;
        std::string_view option;
        if (!t.next(option) || option.size() < 2 || option[0] != '-') {
            t = before;
            break;
        }
        if (option == "-o" || option == "-s" || option == "-t") {
            const std::vector<double> v = optionNumbers(t, 3);
            const double fallback = option == "-s" ? 1.0 : 0.0;
            const glm::dvec2 uv(v.empty() ? fallback : v[0], v.size() < 2 ? fallback : v[1]);
            if (option == "-o")
                material.offset = uv;
            else if (option == "-s")
                material.scale = uv;
        } else if (option == "-mm" || option == "-bm" || option == "-boost" || option == "-texres") {
            optionNumbers(t, option == "-mm" ? 2 : 1);
        } else {
            std::string_view word;
            if (t.next(word) && option == "-clamp")
                material.clamp = word == "on";
        }
    }
    material.texture = std::string(t.rest());
}

} // namespace

std::unordered_map<std::string, MtlMaterial> readMtl(std::string_view text, const std::string& what, std::vector<std::string>& warnings)
{
    std::unordered_map<std::string, MtlMaterial> materials;
    MtlMaterial* current = nullptr;   ///< the material being defined
    std::size_t unread = 0;           ///< Kd statements not read
    std::string firstUnread;
    Lines lines(text);
    for (std::string_view line; lines.next(line);) {
        Tokens t(line.substr(0, line.find('#')));
        std::string_view keyword;
        if (!t.next(keyword))
            continue;
        if (keyword == "newmtl") {
            current = &materials.insert_or_assign(std::string(t.rest()), MtlMaterial{}).first->second;
        } else if (keyword == "map_Kd" && current) {
            readMapKd(t, *current);
        } else if (keyword == "Kd" && current) {
            current->diffuseGiven = true;
            glm::vec3 colour(0.0f);
            int n = 0;
            std::string why;
            for (std::string_view token; why.empty() && t.next(token); ++n) {
                float value = 0.0f;
                why = readFloat(token, value);
                if (why.empty() && !(value >= 0.0f && value <= 1.0f))
                    why = quote(token) + " is outside [0, 1]";
                if (n < 3)
                    colour[n] = value;
            }
            if (why.empty() && n != 1 && n != 3)
                why = std::to_string(n) + " values (1 or 3 are read)";
            if (!why.empty()) {
                if (unread++ == 0)
                    firstUnread = "line " + std::to_string(lines.number()) + ": Kd not read (" + why + ")";
                current->diffuse = kUnknownAlbedo;
                continue;
            }
            current->diffuse = n == 1 ? glm::vec3(colour.x) : colour;
        }
    }
    if (unread > 0)
        warnings.push_back(what + ": " + firstUnread + (unread > 1 ? " and " + std::to_string(unread - 1) + " more" : "") +
                           "; those materials' albedos are unknown");
    return materials;
}

} // namespace sightline::meshio
