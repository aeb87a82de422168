// O'Rorke's light visibility sets (lighting/LightSets.h) on a scene with known answers: a light
// sealed in a box reaches the box alone, so nothing else is in its I; a pillar between a lamp and
// the floor is in the lamp's S though the camera does not see it; a crate off to the side is not.
#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "lighting/LightSets.h"

using namespace sightline;

namespace {

bool has(const std::vector<std::uint32_t>& set, std::uint32_t i) { return std::find(set.begin(), set.end(), i) != set.end(); }

Mesh boxMesh(const std::string& name)
{
    Mesh m = test::closedBox();
    m.name = name;
    m.watertight = false;
    return m;
}

} // namespace

TEST(LightSets, KnownAnswersForASealedBoxAPillarAndACrate)
{
    Scene scene = test::sceneOf({test::quad({-10, 0, -10}, {20, 0, 0}, {0, 0, 20}, "floor")});   // instance 0
    // 1: a closed 2 m box standing 5 cm above the floor around (-4, 1.05, 0).
    scene.addMeshInstance(boxMesh("sealed"), glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(-4.0f, 1.05f, 0.0f)), glm::vec3(2.0f)));
    // 2: a pillar under the lamp; 3: a crate far to the side.
    scene.addMeshInstance(boxMesh("pillar"), glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(4.0f, 1.0f, 0.0f)), glm::vec3(0.4f, 2.0f, 0.4f)));
    scene.addMeshInstance(boxMesh("crate"), glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(8.0f, 0.5f, 8.0f)), glm::vec3(1.0f)));
    const LightingScene lighting(scene);

    Light sealed;
    sealed.type = LightType::Point;
    sealed.position = {-4.0, 1.0, 0.0};
    sealed.name = "in the box";
    Light lamp;
    lamp.type = LightType::Spot;
    lamp.position = {4.0, 4.0, 0.0};
    lamp.direction = {0.0, -1.0, 0.0};
    lamp.outerAngle = 0.5;   // a cone onto the pillar and the floor round it, not the crate
    std::vector<Light> lights = {sealed, lamp};
    validateLights(lights, "test");
    const std::vector<std::uint32_t> visible = {0, 1, 3};   // the camera sees the floor, the box and the crate
    const std::vector<LightSets> sets = lightSets(lighting, scene, lights, visible);
    ASSERT_EQ(sets.size(), 2u);

    // Sealed in the box: it reaches the box's inside only.
    EXPECT_EQ(sets[0].V, (std::vector<std::uint32_t>{0, 1, 3}));
    EXPECT_EQ(sets[0].L, (std::vector<std::uint32_t>{1}));
    EXPECT_EQ(sets[0].I, (std::vector<std::uint32_t>{1}));
    EXPECT_TRUE(sets[0].S.empty());   // nothing stands between it and the box's inside

    // The lamp reaches the floor and the pillar; the crate is outside its cone.
    EXPECT_TRUE(has(sets[1].L, 0));
    EXPECT_TRUE(has(sets[1].L, 2));
    EXPECT_FALSE(has(sets[1].L, 1));
    EXPECT_FALSE(has(sets[1].L, 3));
    EXPECT_EQ(sets[1].I, (std::vector<std::uint32_t>{0}));   // the pillar is not visible
    EXPECT_TRUE(has(sets[1].S, 2));                           // but it shadows the floor
    EXPECT_FALSE(has(sets[1].S, 3));
    EXPECT_FALSE(has(sets[1].S, 1));
}
