// The project's import settings (project/SceneImport.h, docs/design.md §3): every "scene_up" is a
// proper rotation taking the file's up to +Y, the scale multiplies, bad values are refused naming
// the key, the keys survive a save, a level is turned and scaled before the objects the project
// moved are placed, and the up-axis guess finds the floor of a furnished room whichever way up.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "project/Project.h"
#include "project/SceneImport.h"
#include "base/Error.h"

using namespace sightline;
using nlohmann::json;

namespace {

json documentWith(const json& extra)
{
    json document = {{"version", 1},
                     {"source", {{"corner", {0, 1, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}}},
                     {"receiver", {{"corner", {0, 1, 8}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}}}};
    document.update(extra);
    return document;
}

std::string errorOf(const json& extra)
{
    try {
        parseProject(documentWith(extra), "/tmp", "p.json");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(SceneImport, EveryUpIsAProperRotationTakingTheFilesUpToPlusY)
{
    const std::pair<const char*, glm::dvec3> ups[] = {{"+y", {0, 1, 0}}, {"-y", {0, -1, 0}}, {"+z", {0, 0, 1}},
                                                      {"-z", {0, 0, -1}}, {"+x", {1, 0, 0}}, {"-x", {-1, 0, 0}}};
    for (const auto& [up, axis] : ups) {
        const SceneImport settings{up, 0.0254};
        const glm::dmat4 m = settings.transform();
        const glm::dvec3 image(m * glm::dvec4(axis, 0.0));
        EXPECT_NEAR(image.x, 0.0, 1e-15) << up;
        EXPECT_NEAR(image.y, 0.0254, 1e-15) << up;
        EXPECT_NEAR(image.z, 0.0, 1e-15) << up;
        const glm::dmat3 r = glm::dmat3(m) / 0.0254;
        EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12) << up;   // no mirror
        const glm::dmat3 identity = glm::transpose(r) * r;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                EXPECT_NEAR(identity[i][j], i == j ? 1.0 : 0.0, 1e-12) << up;
        EXPECT_EQ(glm::dvec3(m[3]), glm::dvec3(0.0)) << up;   // no translation
    }
    // glTF's Z-up convention: (x, y, z) -> (x, z, -y).
    const glm::dvec3 p(SceneImport{"+z", 1.0}.transform() * glm::dvec4(1.0, 2.0, 3.0, 1.0));
    EXPECT_EQ(p, glm::dvec3(1.0, 3.0, -2.0));
    EXPECT_TRUE((SceneImport{}.identity()));
}

TEST(SceneImport, BadSettingsAreRefusedNamingTheKeyAndGoodOnesSurviveASave)
{
    EXPECT_NE(errorOf({{"scene_up", "up"}}).find("p.json: 'scene_up' must be one of +y, -y, +z, -z, +x, -x, not 'up'"), std::string::npos);
    EXPECT_NE(errorOf({{"scene_up", ""}}).find("'scene_up'"), std::string::npos);
    EXPECT_NE(errorOf({{"scene_up", 1}}).find("'scene_up'"), std::string::npos);
    EXPECT_NE(errorOf({{"scene_up", "Y"}}).find("'scene_up'"), std::string::npos);
    for (const json& scale : {json(0), json(-1.0), json(1e9), json("inches"), json(1e-9), json(nullptr)})
        EXPECT_NE(errorOf({{"scene_scale", scale}}).find("'scene_scale'"), std::string::npos) << scale.dump();
    EXPECT_EQ(errorOf({{"scene_up", "-z"}, {"scene_scale", 0.0254}}), "");

    Project project = parseProject(documentWith({{"scene_up", "+x"}, {"scene_scale", 0.01}}), "/tmp", "p.json");
    EXPECT_EQ(sceneImport(project).up, "+x");
    EXPECT_EQ(sceneImport(project).scale, 0.01);
    const json saved = toJson(project);
    EXPECT_EQ(saved.at("scene_up"), "+x");
    EXPECT_EQ(saved.at("scene_scale"), 0.01);
    setSceneImport(project, SceneImport{});   // the defaults write nothing
    EXPECT_FALSE(toJson(project).contains("scene_up"));
    EXPECT_FALSE(toJson(project).contains("scene_scale"));
}

TEST(SceneImport, TheLevelIsTurnedAndScaledBeforeMovedObjectsArePlaced)
{
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "sightline-scene-import";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    {   // Two z-up quads in inches: a 100 x 100 floor at z = 0 and a tile at z = 10.
        std::ofstream obj(folder / "level.obj");
        obj << "o floor\nv 0 0 0\nv 100 0 0\nv 100 100 0\nv 0 100 0\nf 1 2 3 4\n"
               "o tile\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\nf 5 6 7 8\n";
    }
    json document = documentWith({{"scene", "level.obj"}, {"scene_up", "+z"}, {"scene_scale", 0.0254}});
    const Project turned = parseProject(document, folder, "p.json");
    const Scene level = loadLevel(turned);
    ASSERT_EQ(level.instances.size(), 1u);   // OBJ objects are one mesh
    const Bounds bounds = level.bounds();
    EXPECT_NEAR(bounds.min.x, 0.0f, 1e-6f);
    EXPECT_NEAR(bounds.max.x, 2.54f, 1e-6f);
    EXPECT_NEAR(bounds.min.y, 0.0f, 1e-6f);     // the floor lies in y = 0
    EXPECT_NEAR(bounds.max.y, 0.254f, 1e-6f);   // the tile 10 inches above it
    EXPECT_NEAR(bounds.min.z, -2.54f, 1e-6f);
    EXPECT_NEAR(bounds.max.z, 0.0f, 1e-6f);
    EXPECT_EQ(buildScene(turned).bounds().max.y, bounds.max.y);
    // Moved by the designer: the transform is the object's world transform, not turned again.
    document["scene_transforms"] = json::array({{{"instance", 0}, {"transform", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}}});
    const Scene moved = buildScene(parseProject(document, folder, "p.json"));
    EXPECT_EQ(moved.instances[0].transform, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 5.0f, 0.0f)));
    std::filesystem::remove_all(folder);
}

TEST(SceneImport, TheUpGuessFindsTheFloorOfAFurnishedRoomWhicheverWayUp)
{
    // A room: floor and ceiling 10 x 8, walls 3 high, and three tables (tops, no undersides).
    std::vector<Mesh> parts = {test::quad({0, 0, 0}, {0, 0, 8}, {10, 0, 0}, "floor"),
                               test::quad({0, 3, 0}, {10, 0, 0}, {0, 0, 8}, "ceiling"),
                               test::quad({0, 0, 0}, {10, 0, 0}, {0, 3, 0}, "wall a"),
                               test::quad({0, 0, 8}, {0, 3, 0}, {10, 0, 0}, "wall b"),
                               test::quad({0, 0, 0}, {0, 3, 0}, {0, 0, 8}, "wall c"),
                               test::quad({10, 0, 0}, {0, 0, 8}, {0, 3, 0}, "wall d")};
    for (int k = 0; k < 3; ++k)
        parts.push_back(test::quad({1.0f + 3.0f * float(k), 0.8f, 2}, {0, 0, 1.5f}, {2, 0, 0}, "table"));
    const Scene room = test::sceneOf(parts);
    EXPECT_EQ(guessSceneUp(room), "+y");
    // Each way a file could be written: the guess undoes it.
    for (const char* up : {"-y", "+z", "-z", "+x", "-x"}) {
        Scene written = room;
        const glm::mat4 toFile(glm::inverse(SceneImport{up, 1.0}.transform()));
        for (Instance& instance : written.instances)
            instance.transform = toFile * instance.transform;
        EXPECT_EQ(guessSceneUp(written), up);
    }
    EXPECT_EQ(guessSceneUp(Scene{}), "+y");
}
