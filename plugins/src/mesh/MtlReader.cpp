#include "mesh/MeshReaders.h"

#include "mesh/MeshText.h"

namespace sightline::meshio {

std::unordered_map<std::string, glm::vec3> readMtl(std::string_view text, const std::string& what,
                                                   std::vector<std::string>& warnings)
{
    std::unordered_map<std::string, glm::vec3> albedo;
    glm::vec3* current = nullptr;   ///< the material being defined
    bool textured = false;
    std::size_t unread = 0;         ///< Kd statements not read
    std::string firstUnread;
    const auto finish = [&] {
        if (current && textured)
            *current = kUnknownAlbedo;
    };
    Lines lines(text);
    for (std::string_view line; lines.next(line);) {
        Tokens t(line.substr(0, line.find('#')));
        std::string_view keyword;
        if (!t.next(keyword))
            continue;
        if (keyword == "newmtl") {
            finish();
            current = &albedo.insert_or_assign(std::string(t.rest()), kUnknownAlbedo).first->second;
            textured = false;
        } else if (keyword == "map_Kd" && current) {
            textured = true;
        } else if (keyword == "Kd" && current) {
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
                *current = kUnknownAlbedo;
                continue;
            }
            *current = n == 1 ? glm::vec3(colour.x) : colour;
        }
    }
    finish();
    if (unread > 0)
        warnings.push_back(what + ": " + firstUnread + (unread > 1 ? " and " + std::to_string(unread - 1) + " more" : "") +
                           "; those materials' albedos are unknown");
    return albedo;
}

} // namespace sightline::meshio
