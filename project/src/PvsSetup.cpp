#include "project/PvsSetup.h"

#include <cmath>
#include <cstdint>

#include "base/Error.h"

namespace sightline {

namespace {

float number(const nlohmann::json& j, const std::string& key, const std::string& what)
{
    if (!j.is_number())
        throw Error(what + ": pvs." + key + " must be a number");
    return j.get<float>();
}

/// An integer in [lo, hi], its range checked on the JSON's own 64-bit value before it narrows to
/// int: 4294967296 must not bake as 0.
int integer(const nlohmann::json& j, const std::string& key, const std::string& what, int lo, int hi)
{
    bool inRange = false;
    if (j.is_number_unsigned()) {
        const std::uint64_t u = j.get<std::uint64_t>();
        inRange = u <= std::uint64_t(hi) && std::int64_t(u) >= lo;
    } else if (j.is_number_integer()) {
        const std::int64_t i = j.get<std::int64_t>();
        inRange = i >= lo && i <= hi;
    }
    if (!inRange)
        throw Error(what + ": pvs." + key + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "], got " + j.dump());
    return int(j.get<std::int64_t>());
}

glm::vec3 point(const nlohmann::json& j, const std::string& key, const std::string& what)
{
    if (!j.is_array() || j.size() != 3)
        throw Error(what + ": " + key + " must be three numbers [x, y, z]");
    glm::vec3 p;
    for (int k = 0; k < 3; ++k) {
        // JSON has no NaN; a null or a string where a number belongs is the usual stand-in.
        if (!j[std::size_t(k)].is_number())
            throw Error(what + ": " + key + " must be three finite numbers, got " + j.dump());
        p[k] = j[std::size_t(k)].get<float>();
    }
    return p;
}

} // namespace

PvsSetup parsePvsSetup(const Project& project, const std::string& what)
{
    PvsSetup setup;
    if (!project.extra.contains("pvs"))
        return setup;
    const nlohmann::json& p = project.extra.at("pvs");
    if (!p.is_object())
        throw Error(what + ": pvs must be an object");
    if (p.contains("cell_size"))
        setup.grid.cellSize = number(p["cell_size"], "cell_size", what);
    if (p.contains("cell_height"))
        setup.grid.height = number(p["cell_height"], "cell_height", what);
    if (p.contains("cell_lift"))
        setup.grid.lift = number(p["cell_lift"], "cell_lift", what);
    if (p.contains("cells")) {
        if (!p["cells"].is_array())
            throw Error(what + ": pvs.cells must be a list of {\"min\": [x,y,z], \"max\": [x,y,z]}");
        setup.gridCells = false;
        for (std::size_t c = 0; c < p["cells"].size(); ++c) {
            const nlohmann::json& cell = p["cells"][c];
            const std::string key = "pvs.cells[" + std::to_string(c) + "]";
            if (!cell.is_object() || !cell.contains("min") || !cell.contains("max"))
                throw Error(what + ": " + key + " must be {\"min\": [x,y,z], \"max\": [x,y,z]}");
            Bounds b;
            b.min = point(cell["min"], key + ".min", what);
            b.max = point(cell["max"], key + ".max", what);
            setup.cells.push_back(b);
        }
        pvs::validateCells(setup.cells, what + ": pvs.cells");
    }
    if (p.contains("group_by_name")) {
        if (!p["group_by_name"].is_boolean())
            throw Error(what + ": pvs.group_by_name must be true or false");
        setup.groupByName = p["group_by_name"].get<bool>();
    }
    for (const char* gone : {"coarse_samples", "fine_samples"})
        if (p.contains(gone))
            throw Error(what + ": pvs." + gone + " is gone: the bake now splits shafts adaptively; use coarse_shafts, "
                                              "fine_shafts and smallest_gap (docs/pvs.md)");
    if (p.contains("coarse_shafts"))
        setup.settings.coarseShafts = integer(p["coarse_shafts"], "coarse_shafts", what, 1, pvs::kMaxCoarseShafts);
    if (p.contains("fine_shafts"))
        setup.settings.fineShafts = integer(p["fine_shafts"], "fine_shafts", what, 1, pvs::kMaxFineShafts);
    if (p.contains("residue_rays"))
        setup.settings.residueRays = integer(p["residue_rays"], "residue_rays", what, 0, pvs::kMaxResidueRays);
    if (p.contains("smallest_gap"))
        setup.settings.smallestGap = number(p["smallest_gap"], "smallest_gap", what);
    if (p.contains("max_distance"))
        setup.settings.maxDistance = number(p["max_distance"], "max_distance", what);
    if (p.contains("cell_rows")) {
        if (!p["cell_rows"].is_boolean())
            throw Error(what + ": pvs.cell_rows must be true or false");
        setup.settings.cellRows = p["cell_rows"].get<bool>();
    }
    if (p.contains("safe")) {
        if (!p["safe"].is_boolean())
            throw Error(what + ": pvs.safe must be true or false");
        setup.settings.safe = p["safe"].get<bool>();
    }
    try {
        setup.settings.validate();
    } catch (const Error& e) {
        throw Error(what + ": " + e.what());
    }
    if (p.contains("overrides")) {
        if (!p["overrides"].is_array())
            throw Error(what + ": pvs.overrides must be a list");
        setup.overridesJson = p["overrides"];
    }
    return setup;
}

std::vector<PvsOverride> resolvePvsOverrides(const nlohmann::json& overrides, const std::vector<pvs::PvsObject>& objects,
                                             std::size_t cellCount, const std::string& what)
{
    std::vector<PvsOverride> out;
    for (std::size_t k = 0; k < overrides.size(); ++k) {
        const nlohmann::json& o = overrides[k];
        const std::string key = what + ": pvs.overrides[" + std::to_string(k) + "]";
        if (!o.is_object())
            throw Error(key + " must be an object like {\"object\": \"lamp\", \"visible\": \"always\"}");
        PvsOverride r;
        if (o.contains("object") == o.contains("instance"))
            throw Error(key + " must name exactly one of \"object\" (a name) or \"instance\" (an index)");
        bool found = false;
        if (o.contains("object")) {
            if (!o["object"].is_string())
                throw Error(key + ".object must be an object's name");
            const std::string name = o["object"].get<std::string>();
            for (std::size_t i = 0; i < objects.size() && !found; ++i)
                if (objects[i].name == name)
                    r.object = i, found = true;
            if (!found)
                throw Error(key + ": no object is named '" + name + "'");
        } else {
            if (!o["instance"].is_number_unsigned())
                throw Error(key + ".instance must be a non-negative integer");
            const auto instance = o["instance"].get<std::uint64_t>();
            for (std::size_t i = 0; i < objects.size() && !found; ++i)
                for (std::uint32_t in : objects[i].instances)
                    if (in == instance)
                        r.object = i, found = true;
            if (!found)
                throw Error(key + ": instance " + std::to_string(instance) + " is not in the scene (" +
                            std::to_string(objects.size()) + " objects)");
        }
        const std::string visible = o.contains("visible") && o["visible"].is_string() ? o["visible"].get<std::string>() : "";
        if (visible != "always" && visible != "never")
            throw Error(key + ".visible must be \"always\" or \"never\"");
        r.visible = visible == "always";
        if (o.contains("cells")) {
            if (!o["cells"].is_array())
                throw Error(key + ".cells must be a list of cell indices");
            for (const auto& c : o["cells"]) {
                if (!c.is_number_unsigned() || c.get<std::uint64_t>() >= cellCount)
                    throw Error(key + ".cells: " + c.dump() + " is not a cell index (there are " + std::to_string(cellCount) +
                                " cells)");
                r.cells.push_back(c.get<std::size_t>());
            }
        }
        out.push_back(r);
    }
    return out;
}

void applyPvsOverrides(const std::vector<PvsOverride>& overrides, pvs::VisibilityRows& rows)
{
    for (const PvsOverride& o : overrides) {
        if (o.cells.empty())
            for (std::size_t c = 0; c < rows.cellCount(); ++c)
                rows.set(c, o.object, o.visible);
        else
            for (std::size_t c : o.cells)
                rows.set(c, o.object, o.visible);
    }
}

} // namespace sightline
