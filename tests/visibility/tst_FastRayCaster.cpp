// The CPU sampler's fast ray casting (src/raycast/FastRayCaster.h): Embree's own float triangles,
// grown, with every hit proven or tested exactly, and the shaft's close triangles cast exactly.
// Its answer is not only exact by the contract: every candidate is decided by the reference's own
// test, so it must equal the reference's bit for bit, ties included. Any crossing the float pass
// failed to report, or any hit its float proof accepted wrongly, would show as a difference.

#include <random>

#include <gtest/gtest.h>

#include "ExactnessSuite.h"
#include "raycast/FastRayCaster.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;
using raycast::FastRayCaster;

namespace {

/// Both casters on one case; returns the number of rays they answer differently.
std::uint64_t differences(const AdversarialCase& c, const Question& question, std::size_t* close = nullptr)
{
    const WorldTriangles triangles = worldTriangles(c.scene);
    const RayCastOptions options{.jitter = question.jitter, .heights = question.heights};
    const HiddenSampleMap reference = RayCastScene(triangles).sample(c.source, c.receiver, options);
    const FastRayCaster fast(triangles);
    HiddenSampleMap map(c.source.sampleCount(), c.receiver.na, c.receiver.nb);
    fast.sampleUnblocked(c.source, c.receiver, map, options);
    if (close)
        *close += fast.prepare(c.source, c.receiver, options)->closeTriangles();
    return map.differenceCount(reference);
}

void expectIdentical(const std::vector<AdversarialCase>& cases, Variant variant)
{
    std::uint64_t total = 0, rays = 0;
    std::size_t close = 0;
    for (std::size_t n = 0; n < cases.size(); ++n) {
        const AdversarialCase& c = cases[n];
        Question question;
        ReceiverHeights heights;
        if (variant == Variant::Jittered)
            question.jitter.seed = std::uint32_t(n + 1);
        if (variant == Variant::Bumpy) {
            heights = randomHeights(c.receiver, unsigned(n + 1), 0.1 * glm::length(c.receiver.centre() - c.source.centre()));
            question.heights = &heights;
        }
        const std::uint64_t d = differences(c, question, &close);
        EXPECT_EQ(d, 0u) << c.name;
        total += d;
        rays += std::uint64_t(c.source.sampleCount()) * std::uint64_t(c.receiver.sampleCount());
    }
    std::printf("fast ray caster: %llu cases, %llu rays, %llu differences from the reference, %zu close triangles\n",
                (unsigned long long)cases.size(), (unsigned long long)rays, (unsigned long long)total, close);
}

} // namespace

TEST(FastRayCaster, AnswersAsTheReferenceBitForBitOnAdversarialScenes)
{
    expectIdentical(suite({0.0, 1e3, 1e4, 1e5}, seeds(2)), Variant::Plain);
}

TEST(FastRayCaster, AnswersAsTheReferenceBitForBitWithJitterAndBumps)
{
    expectIdentical(suite({0.0, 1e4}, seeds(1)), Variant::Jittered);
    expectIdentical(suite({0.0, 1e4}, seeds(1)), Variant::Bumpy);
}

TEST(FastRayCaster, AnswersAsTheReferenceBitForBitOnAThousandsOfTrianglesFoliage)
{
    // Production size: 32x32 sources, 64x64 receiver samples, 20,000 leaves of 1-10 cm at every
    // orientation between the patches (some seen edge-on, some slivers), 10 m apart, 1 km out.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const glm::dvec3 offset(1000.0, -250.0, 600.0);
    Scene scene;
    Mesh leaves;
    leaves.name = "leaves";
    for (int k = 0; k < 20000; ++k) {
        const glm::dvec3 centre(-1.5 + 3.0 * unit(random), -1.5 + 3.0 * unit(random), 1.0 + 8.0 * unit(random));
        const double size = 0.01 + 0.09 * unit(random), thin = k % 10 == 0 ? 1e-3 : 1.0;
        const auto direction = [&] {
            const double z = 2.0 * unit(random) - 1.0, phi = 6.283185307179586 * unit(random);
            return glm::dvec3(std::sqrt(1.0 - z * z) * std::cos(phi), std::sqrt(1.0 - z * z) * std::sin(phi), z);
        };
        const glm::dvec3 a = centre, u = direction(), v = glm::normalize(glm::cross(u, direction()));
        const glm::dvec3 b = a + size * u, c = a + 0.5 * size * u + thin * size * v;
        for (const glm::dvec3& p : {a, b, c}) {
            leaves.indices.push_back(std::uint32_t(leaves.positions.size()));
            leaves.positions.push_back(glm::vec3(p + offset));
        }
    }
    scene.meshes.push_back(leaves);
    scene.instances.push_back({"only", 0, glm::mat4(1.0f)});
    AdversarialCase c;
    c.name = "foliage";
    c.scene = scene;
    c.source.corner = offset + glm::dvec3(-1.0, -1.0, 0.0);
    c.source.u = {2.0, 0.0, 0.0}, c.source.v = {0.0, 2.0, 0.0};
    c.receiver.corner = offset + glm::dvec3(-1.2, -1.0, 10.0);
    c.receiver.u = {2.4, 0.0, 0.3}, c.receiver.v = {0.0, 2.0, 0.0};
    c.receiver.na = c.receiver.nb = 64;
    std::size_t close = 0;
    EXPECT_EQ(differences(c, {}, &close), 0u);
    // Some leaves are seen nearly edge-on from both patches: the close pass is exercised.
    EXPECT_GT(close, 0u);
}

TEST(FastRayCaster, LeavesFinsSeenEdgeOnAndSliversToTheClosePass)
{
    // A fin in a plane through both patches (beside the slab's shadow), a slab facing them, a
    // sliver 1 um wide.
    Scene scene;
    Mesh mesh;
    mesh.name = "parts";
    const auto add = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        for (const glm::vec3& p : {a, b, c}) {
            mesh.indices.push_back(std::uint32_t(mesh.positions.size()));
            mesh.positions.push_back(p);
        }
    };
    add({0.0f, 0.6f, 4.0f}, {0.0f, 0.95f, 4.0f}, {0.0f, 0.8f, 6.0f});       // fin: the plane x = 0
    add({-0.5f, -0.5f, 5.0f}, {0.5f, -0.5f, 5.0f}, {0.0f, 0.5f, 5.0f});    // facing the patches
    add({-0.5f, 0.3f, 3.0f}, {0.5f, 0.3f, 3.0f}, {0.0f, 0.300001f, 3.0f}); // sliver
    scene.meshes.push_back(mesh);
    scene.instances.push_back({"only", 0, glm::mat4(1.0f)});
    Patch source, receiver;
    source.corner = {-1.0, -1.0, 0.0}, source.u = {2.0, 0.0, 0.0}, source.v = {0.0, 2.0, 0.0};
    receiver.corner = {-1.0, -1.0, 10.0}, receiver.u = {2.0, 0.0, 0.0}, receiver.v = {0.0, 2.0, 0.0};
    const FastRayCaster fast(worldTriangles(scene));
    EXPECT_EQ(fast.floatTriangleCount(), 2u);   // the sliver is never in the float BVH
    const auto shaft = fast.prepare(source, receiver, {}, FastRayCaster::CloseTriangles::LeftToCaller);
    EXPECT_EQ(shaft->closeTriangleIndices(), (std::vector<std::uint32_t>{0, 2}));
    // Left to the caller, the float pass alone may miss what only the close triangles block, but
    // blocks nothing the reference leaves free (every hit it keeps is tested or proven).
    HiddenSampleMap floatOnly(source.sampleCount(), receiver.na, receiver.nb);
    fast.cast(*shaft, floatOnly);
    const HiddenSampleMap reference = RayCastScene(scene).sample(source, receiver);
    for (int j = 0; j < reference.receiverCount(); ++j) {
        for (int i = 0; i < reference.sourceCount(); ++i) {
            if (floatOnly.blocked(j, i)) {
                ASSERT_TRUE(reference.blocked(j, i)) << "receiver " << j << ", source " << i;
            }
        }
    }
    // Cast exactly, the close triangles give the reference's answer.
    HiddenSampleMap whole(source.sampleCount(), receiver.na, receiver.nb);
    fast.sampleUnblocked(source, receiver, whole);
    EXPECT_EQ(whole, reference);
}
