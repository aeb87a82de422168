// A compiled Quake level opened as a scene: metres, Y up, every face wound counter-clockwise seen
// from the open space it faces. Checked against the BSP's own tree: a point just in front of each
// triangle lies in a leaf a player can stand in. Bad face data gets one line.

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "plugins/SceneFormats.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/bsp/QuakeBsp.h"

using namespace sightline;
namespace fs = std::filesystem;

namespace {

const std::string kLevel = SIGHTLINE_TEST_DATA "/levels/quake-dm4.bsp";

/// Back from metres, Y up, to Quake's units and axes.
glm::dvec3 quakeUnits(const glm::vec3& p) { return glm::dvec3(p.x, -p.z, p.y) / 0.0254; }

} // namespace

TEST(QuakeBspImporter, FacesAreWoundTowardsTheOpenSpaceTheyFace)
{
    std::vector<std::string> warnings;
    const Scene scene = loadScene(kLevel, &warnings);
    ASSERT_EQ(scene.meshes.size(), 1u);
    const Mesh& mesh = scene.meshes[0];
    EXPECT_EQ(mesh.name, "quake-dm4");
    ASSERT_GT(mesh.triangleCount(), 5000u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("liquid surfaces left out"), std::string::npos);

    const bsp::QuakeBsp level = bsp::readQuakeBsp(readInputFile(kLevel, "dm4"), "dm4");
    std::size_t checked = 0, open = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a = quakeUnits(mesh.positions[mesh.indices[3 * t]]);
        const glm::dvec3 b = quakeUnits(mesh.positions[mesh.indices[3 * t + 1]]);
        const glm::dvec3 c = quakeUnits(mesh.positions[mesh.indices[3 * t + 2]]);
        // The normal as the scene winds it, taken back to Quake's axes (a rotation keeps it).
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) < 1.0)
            continue;   // a sliver (collinear corners Quake keeps against cracks)
        const glm::dvec3 centre = (a + b + c) / 3.0, unit = glm::normalize(n);
        ++checked;
        const int front = level.leaves[std::size_t(bsp::leafAt(level, centre + unit * 0.25))].contents;
        open += front != bsp::kContentsSolid;
        // Behind is mostly solid, but not always: a floor over open space seen from below is a face
        // with air on both sides, so only the front is a rule.
    }
    EXPECT_GT(checked, 4000u);
    EXPECT_EQ(open, checked) << "every face's front is open space";

    // Y up: most of the level's floor area faces +Y, its ceilings -Y.
    double up = 0.0, down = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::vec3 n = glm::cross(mesh.positions[mesh.indices[3 * t + 1]] - mesh.positions[mesh.indices[3 * t]],
                                       mesh.positions[mesh.indices[3 * t + 2]] - mesh.positions[mesh.indices[3 * t]]);
        (n.y > 0.0f ? up : down) += std::abs(double(n.y));
    }
    EXPECT_GT(up, 0.2 * (up + down));
    EXPECT_GT(down, 0.2 * (up + down));
}

TEST(QuakeBspImporter, BadFaceDataGetsOneLine)
{
    const std::string good = readInputFile(kLevel, "dm4");
    auto lump = [&](int k) {
        std::uint32_t offset;
        std::memcpy(&offset, good.data() + 4 + 8 * k, 4);
        return std::size_t(offset);
    };
    const fs::path dir = fs::temp_directory_path() / ("sightline_bsp_import_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    auto refuses = [&](std::string bytes, const std::string& words) {
        const fs::path file = dir / "bad.bsp";
        std::ofstream(file, std::ios::binary) << bytes;
        try {
            loadScene(file);
            ADD_FAILURE() << "accepted; expected: " << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    };
    auto with = [&](std::size_t at, std::int32_t value, int bytes = 4) {
        std::string s = good;
        std::memcpy(s.data() + at, &value, std::size_t(bytes));
        return s;
    };
    const std::size_t model0 = lump(bsp::kModelLump), faces = lump(bsp::kFaceLump), surfedges = lump(bsp::kSurfedgeLump),
                      vertices = lump(bsp::kVertexLump);
    refuses(with(model0 + 60, 1 << 28), "world model's faces");
    refuses(with(faces + 8, 5000, 2), "edges from surfedge");
    refuses(with(surfedges, 1 << 30), "names edge");
    refuses(with(vertices, 0x7f800000), "not finite");
    fs::remove_all(dir);
}
