// Ambient occlusion from the visibility matrix (Sattler et al. 2004): the light sphere,
// the closed forms (an open plane sees 1; beside an infinite wall of height H at distance d the
// uniform-sky cosine-weighted AO is 1 - (1 - 1/sqrt(1 + (H/d)^2)) / 2), the Monte-Carlo reference
// with a tolerance from its own variance, nested levels against direct ones, the exact CPU mode
// against Embree single rays, environments and relighting, texel points, and bad input.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "TestScenes.h"
#include "base/ImageFile.h"
#include "lighting/ao/AoBinnedCaster.h"
#include "lighting/ao/AoComputation.h"
#include "lighting/ao/AoEmbree.h"
#include "lighting/ao/AoEnvironment.h"
#include "lighting/ao/AoShading.h"
#include "lighting/ao/AoTexels.h"
#include "base/Error.h"

using namespace sightline;

namespace {

constexpr double kPi = std::numbers::pi;

/// One point at `p` with normal `n`, origins offset as the CLI does.
AoPoints onePoint(const glm::vec3& p, const glm::vec3& n, double offset)
{
    AoPoints points;
    points.positions = {p};
    points.normals = {glm::normalize(n)};
    points.status = {AoPointStatus::Ok};
    points.offsetOrigins(offset);
    return points;
}

std::vector<float> aoOf(const Scene& scene, AoPoints& points, int k, AoWeighting weighting = AoWeighting::SolidAngle)
{
    const AoOccluders occluders = aoOccluders(scene);
    AoBinnedCaster caster(occluders);
    AoComputation computation(caster, points, k);
    EXPECT_TRUE(computation.run());
    return ambientOcclusion(computation.matrix(), points, k, weighting);
}

double wallAo(double height, double distance) { return 1.0 - (1.0 - 1.0 / std::sqrt(1.0 + std::pow(height / distance, 2))) / 2.0; }

/// A floor (y = 0) and a wall at distance d of height H, both 2 km long: "infinite" to 5e-4 of
/// the AO for the heights tested (the missing solid angle beyond 1 km is below (H/1000)^2). The
/// wall is turned about +Y by `turn` radians (the AO does not change): at 0 its top edge would run
/// along a great circle of light directions for H = d (ties, half their cell blocked).
Scene wallScene(float height, float distance, float turn = 0.3f)
{
    const glm::vec3 across(std::cos(turn), 0.0f, std::sin(turn)), along(-std::sin(turn), 0.0f, std::cos(turn));
    return test::sceneOf({test::quad({-1000.0f, 0.0f, -1000.0f}, {0.0f, 0.0f, 2000.0f}, {2000.0f, 0.0f, 0.0f}, "floor"),
                          test::quad(distance * across - 1000.0f * along, {0.0f, height, 0.0f}, 2000.0f * along, "wall")});
}

} // namespace

TEST(AoDirections, LevelsNestAndCellsTileTheSphere)
{
    for (int k : kAoDirectionCounts) {
        const AoDirectionSet& set = aoDirections(k);
        ASSERT_EQ(int(set.directions.size()), k);
        double omega = 0.0;
        glm::dvec3 moment(0.0);
        for (int j = 0; j < k; ++j) {
            EXPECT_NEAR(glm::length(set.directions[std::size_t(j)]), 1.0f, 1e-6f);
            EXPECT_GT(set.solidAngle[std::size_t(j)], 0.0f);
            // The moment points along its direction (cells are symmetric about it, nearly).
            EXPECT_GT(glm::dot(glm::normalize(set.moment[std::size_t(j)]), set.directions[std::size_t(j)]), 0.998f);
            omega += set.solidAngle[std::size_t(j)];
            moment += glm::dvec3(set.moment[std::size_t(j)]);
        }
        EXPECT_NEAR(omega, 4.0 * kPi, 1e-6);
        EXPECT_NEAR(glm::length(moment), 0.0, 1e-5);   // the sphere is centrally symmetric
        // Nested: a finer level starts with the coarser level's directions.
        if (k > 6) {
            const AoDirectionSet& coarser = aoDirections(kAoDirectionCounts[std::size_t(aoLevelOf(k) - 1)]);
            for (int j = 0; j < coarser.k; ++j)
                EXPECT_EQ(coarser.directions[std::size_t(j)], set.directions[std::size_t(j)]);
        }
        // The cosine lobe over facing cells integrates to pi for any normal (up to horizon cells).
        const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.8f, -0.2f));
        double lobe = 0.0;
        for (int j = 0; j < k; ++j)
            lobe += aoWeight(set, j, n, AoWeighting::SolidAngle);
        EXPECT_NEAR(lobe, kPi, k >= 258 ? 0.02 : 0.6) << "k = " << k;
    }
}

TEST(AoDirections, EveryDirectionHasItsAntipodeInItsLevel)
{
    // The casters answer d and -d in one pass; the table must pair every direction exactly.
    for (int k : kAoDirectionCounts) {
        const AoDirectionSet& set = aoDirections(k);
        ASSERT_EQ(int(set.antipode.size()), k);
        for (int j = 0; j < k; ++j) {
            const int a = set.antipode[std::size_t(j)];
            ASSERT_GE(a, 0) << "k = " << k << ", j = " << j;
            ASSERT_LT(a, k);
            EXPECT_NE(a, j);
            EXPECT_EQ(set.antipode[std::size_t(a)], j);
            EXPECT_NEAR(glm::length(set.directions[std::size_t(a)] + set.directions[std::size_t(j)]), 0.0f, 1e-6f);
        }
    }
}

TEST(AoDirections, KOutsideTheSetIsRefused)
{
    for (int k : {0, 5, 7, 100, 257, 4098})
        EXPECT_THROW(aoLevelOf(k), Error);
    try {
        aoLevelOf(100);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("6, 18, 66, 258 or 1026"), std::string::npos) << e.what();
    }
}

TEST(AoClosedForm, OpenPlaneSeesEverything)
{
    const Scene plane = test::sceneOf({test::quad({-50.0f, 0.0f, -50.0f}, {0.0f, 0.0f, 100.0f}, {100.0f, 0.0f, 0.0f})});
    for (int k : kAoDirectionCounts)
        for (AoWeighting w : {AoWeighting::SolidAngle, AoWeighting::PlainCount}) {
            AoPoints points = onePoint({0.3f, 0.0f, -0.2f}, {0, 1, 0}, 1e-3);
            EXPECT_FLOAT_EQ(aoOf(plane, points, k, w)[0], 1.0f) << "k = " << k;
        }
}

TEST(AoClosedForm, BesideAnInfiniteWall)
{
    // Several heights and distances (H/d from 0.5 to 3), the point on the floor, normal up.
    for (const auto& [height, distance] : {std::pair{1.0f, 2.0f}, {1.0f, 1.0f}, {2.0f, 1.0f}, {3.0f, 1.0f}}) {
        const Scene scene = wallScene(height, distance);
        AoPoints points = onePoint({0.0f, 0.0f, 0.0f}, {0, 1, 0}, 1e-3);
        const double expected = wallAo(height, distance);
        const float weighted = aoOf(scene, points, 1026)[0];
        EXPECT_NEAR(weighted, expected, 2.5e-3) << "H = " << height << ", d = " << distance;
        // The paper's plain counting is reported beside it; coarser sets are further off.
        const float counted = aoOf(scene, points, 1026, AoWeighting::PlainCount)[0];
        EXPECT_NEAR(counted, expected, 0.02) << "H = " << height << ", d = " << distance;
    }
}

TEST(AoReference, MonteCarloAgreesWithTheClosedFormWithinItsVariance)
{
    const Scene scene = wallScene(1.0f, 1.0f);
    const AoOccluders occluders = aoOccluders(scene);
    const AoEmbreeScene embree(occluders);
    AoPoints points = onePoint({0.0f, 0.0f, 0.0f}, {0, 1, 0}, 1e-3);
    const int rays = 4096;
    const double a = wallAo(1.0, 1.0);
    const double sigma = std::sqrt(a * (1 - a) / rays);   // binomial bound; stratification only lowers it
    for (std::uint64_t seed : {1u, 2u, 3u})
        EXPECT_NEAR(monteCarloAo(embree, points, rays, seed)[0], a, 4.0 * sigma) << "seed " << seed;
}

namespace {

/// A small closed-and-open test object: a box on a floor beside a wall, vertices as points.
Scene clutter()
{
    Scene scene = test::sceneOf({test::quad({-3.0f, 0.0f, -3.0f}, {0.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 0.0f}, "floor"),
                                 test::quad({1.5f, 0.0f, -3.0f}, {0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 6.0f}, "wall")});
    Mesh box = test::closedBox();
    scene.addMeshInstance(box, glm::mat4(1.0f));
    return scene;
}

/// Points on a grid over the floor and the box top, normals up, plus a few on the wall.
AoPoints gridPoints(double offset)
{
    AoPoints points;
    for (int x = 0; x < 12; ++x)
        for (int z = 0; z < 12; ++z) {
            points.positions.push_back({-2.7f + 0.37f * x, 0.0f, -2.6f + 0.41f * z});
            points.normals.push_back({0, 1, 0});
            points.status.push_back(AoPointStatus::Ok);
        }
    for (int y = 0; y < 5; ++y) {
        points.positions.push_back({1.5f, 0.1f + 0.37f * y, 0.3f * y - 0.6f});
        points.normals.push_back({-1, 0, 0});
        points.status.push_back(AoPointStatus::Ok);
    }
    points.offsetOrigins(offset);
    return points;
}

} // namespace

TEST(AoReference, MatrixAoConvergesToMonteCarlo)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = gridPoints(1e-3);
    const AoEmbreeScene embree(occluders);
    const int rays = 4096;
    const std::vector<float> mc = monteCarloAo(embree, points, rays);
    const std::vector<float> ao = aoOf(scene, points, 1026);
    double sum = 0.0;
    for (std::size_t i = 0; i < mc.size(); ++i) {
        // Per point: MC's own 4 sigma, plus the light sphere's discretisation at k = 1026 (0.02
        // covers a box edge passing between directions).
        const double sigma = std::sqrt(std::max(1e-6, double(mc[i]) * (1.0 - mc[i]) / rays));
        EXPECT_NEAR(ao[i], mc[i], 4.0 * sigma + 0.02) << "point " << i;
        sum += (ao[i] - mc[i]) * (ao[i] - mc[i]);
    }
    EXPECT_LT(std::sqrt(sum / double(mc.size())), 0.008);
}

TEST(AoMatrix, NestedLevelsGiveTheSameBitsAsEachLevelDirectly)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = gridPoints(1e-3);
    AoBinnedCaster caster(occluders);
    AoComputation progressive(caster, points, 1026);
    for (int k : kAoDirectionCounts) {
        ASSERT_TRUE(progressive.refineLevel());
        ASSERT_EQ(progressive.completedK(), k);
        AoComputation direct(caster, points, k);
        ASSERT_TRUE(direct.step(k));
        for (std::size_t i = 0; i < points.size(); ++i)
            for (int j = 0; j < k; ++j)
                ASSERT_EQ(progressive.matrix().visible(i, j), direct.matrix().visible(i, j)) << "k " << k << " point " << i << " dir " << j;
    }
    // Chunks of any size give the same bits too (an editor's worker thread).
    AoComputation chunked(caster, points, 258);
    while (!chunked.finished())
        ASSERT_TRUE(chunked.step(7));
    for (std::size_t i = 0; i < points.size(); ++i)
        for (int j = 0; j < 258; ++j)
            ASSERT_EQ(chunked.matrix().visible(i, j), progressive.matrix().visible(i, j));
}

TEST(AoMatrix, CancelStopsAndIsRedone)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = gridPoints(1e-3);
    AoBinnedCaster caster(occluders);
    AoComputation computation(caster, points, 258);
    std::atomic<bool> cancel{true};
    std::atomic<int> done{0};
    EXPECT_FALSE(computation.refineLevel({&cancel, &done}));
    EXPECT_EQ(computation.directionsDone(), 0);
    cancel = false;
    EXPECT_TRUE(computation.run({&cancel, &done}));
    EXPECT_EQ(computation.completedK(), 258);
    EXPECT_EQ(done.load(), 258);
}

TEST(AoMatrix, ExactCpuModeAgreesWithEmbreeSingleRays)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = gridPoints(1e-3);
    AoBinnedCaster binned(occluders);
    AoEmbreeCaster embree(occluders);
    VisibilityMatrix a(points.size(), 1026), b(points.size(), 1026);
    binned.fill(points, aoDirections(1026), 0, 1026, a);
    embree.fill(points, aoDirections(1026), 0, 1026, b);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
        for (int j = 0; j < 1026; ++j)
            differ += a.visible(i, j) != b.visible(i, j);
    // Grazing rays along the box's faces may go either way (ties): well under 0.1%.
    EXPECT_LE(differ, a.visibleCount(1026) / 1000);
    EXPECT_GT(a.visibleCount(1026), 0u);
}

TEST(AoMatrix, EmbreePacketsOfDirectionsAnswerAsSingleRays)
{
    // The baseline's two traversals cast the same float rays against the same scene: the same
    // bits, at k = 6 (fewer directions than a packet) and 1026 (64 packets and a part).
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = gridPoints(1e-3);
    AoEmbreeCaster singles(occluders, 0, AoEmbreeTraversal::SingleRays);
    AoEmbreeCaster packets(occluders, 0, AoEmbreeTraversal::DirectionPackets);
    EXPECT_NE(singles.name(), packets.name());
    for (const int k : {6, 1026}) {
        VisibilityMatrix a(points.size(), k), b(points.size(), k);
        singles.fill(points, aoDirections(k), 0, k, a);
        packets.fill(points, aoDirections(k), 0, k, b);
        std::size_t differ = 0, blocked = 0;
        for (std::size_t i = 0; i < points.size(); ++i)
            for (int j = 0; j < k; ++j) {
                differ += a.visible(i, j) != b.visible(i, j);
                blocked += glm::dot(points.normals[i], aoDirections(k).directions[std::size_t(j)]) > 0.0f && !a.visible(i, j);
            }
        EXPECT_EQ(differ, 0u) << k;
        EXPECT_GT(a.visibleCount(k), 0u) << k;
        EXPECT_GT(blocked, 0u) << k;   // the clutter blocks some of the facing directions
    }
}

TEST(AoShading, RelightWithAUniformEnvironmentIsAoTimesItsRadiance)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = gridPoints(1e-3);
    AoBinnedCaster caster(occluders);
    AoComputation computation(caster, points, 258);
    computation.run();
    const std::vector<float> ao = ambientOcclusion(computation.matrix(), points, 258);
    const AoRelighter relighter(computation.matrix(), points, 258);
    const AoEnvironment sky = AoEnvironment::uniform({0.5f, 1.0f, 2.0f});
    const std::vector<glm::vec3> c = relighter.shade(sky.directionRadiance(aoDirections(258), 33.0, 1.0));
    for (std::size_t i = 0; i < points.size(); ++i) {
        EXPECT_NEAR(c[i].r, 2.0f * 0.5f * ao[i], 1e-5f);   // exposure +1 EV doubles
        EXPECT_NEAR(c[i].b, 2.0f * 2.0f * ao[i], 1e-5f);
    }
}

TEST(AoShading, AnUpperHalfSkyLightsAnUpFacingPlaneAndRotationTurnsASun)
{
    // A lat-long map bright above the horizon only: an open plane facing up sees all of it.
    const int w = 64, h = 32;
    std::vector<glm::vec3> pixels(std::size_t(w * h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            pixels[std::size_t(y * w + x)] = glm::vec3(y < h / 2 ? 3.0f : 0.0f);
    const AoEnvironment upper = AoEnvironment::fromPixels(w, h, pixels);
    const Scene plane = test::sceneOf({test::quad({-50.0f, 0.0f, -50.0f}, {0.0f, 0.0f, 100.0f}, {100.0f, 0.0f, 0.0f})});
    AoPoints points = onePoint({0, 0, 0}, {0, 1, 0}, 1e-3);
    const AoOccluders occluders = aoOccluders(plane);
    AoBinnedCaster caster(occluders);
    AoComputation computation(caster, points, 258);
    computation.run();
    const AoRelighter relighter(computation.matrix(), points, 258);
    // The filter blurs the horizon a little: within 5%.
    EXPECT_NEAR(relighter.shade(upper.directionRadiance(aoDirections(258)))[0].g, 3.0f, 0.15f);
    // A bright region at +Z (image centre) moves to -Z after turning the environment by 180 degrees.
    std::vector<glm::vec3> sun(std::size_t(w * h), glm::vec3(0.0f));
    for (int y = 10; y < 22; ++y)
        for (int x = 26; x < 38; ++x)
            sun[std::size_t(y * w + x)] = glm::vec3(10.0f);
    const AoEnvironment env = AoEnvironment::fromPixels(w, h, sun);
    AoPoints facingZ = onePoint({0, 0.5f, 0}, {0, 0, 1}, 1e-3), facingMinusZ = onePoint({0, 0.5f, 0}, {0, 0, -1}, 1e-3);
    EXPECT_GT(env.radiance({0, 0, 1}).r, 5.0f);
    const std::vector<glm::vec3> r0 = env.directionRadiance(aoDirections(258), 0.0);
    const std::vector<glm::vec3> r180 = env.directionRadiance(aoDirections(258), 180.0);
    const AoDirectionSet& set = aoDirections(258);
    for (int j = 0; j < 258; ++j)
        if (set.directions[std::size_t(j)] == glm::vec3(0, 0, 1)) {
            EXPECT_GT(r0[std::size_t(j)].r, 3.0f);
            EXPECT_LT(r180[std::size_t(j)].r, 0.5f);
        } else if (set.directions[std::size_t(j)] == glm::vec3(0, 0, -1)) {
            EXPECT_LT(r0[std::size_t(j)].r, 0.5f);
            EXPECT_GT(r180[std::size_t(j)].r, 3.0f);
        }
}

TEST(AoBadInput, VerticesOfNoFaceAndZeroNormalsAreReportedNotShaded)
{
    Mesh mesh = test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    mesh.positions.push_back({5, 5, 5});          // belongs to no face
    mesh.positions.push_back({2, 0, 0});          // a degenerate face (all corners on a line) only
    mesh.positions.push_back({3, 0, 0});
    mesh.positions.push_back({4, 0, 0});
    const auto n = std::uint32_t(mesh.positions.size());
    mesh.indices.insert(mesh.indices.end(), {n - 3, n - 2, n - 1});
    mesh.normals.clear();
    Scene scene;
    scene.addMeshInstance(mesh);
    AoPoints points = aoVertexPoints(scene);
    ASSERT_EQ(points.size(), mesh.positions.size());
    EXPECT_EQ(points.count(AoPointStatus::NoFace), 1u);
    EXPECT_EQ(points.count(AoPointStatus::ZeroNormal), 3u);
    points.offsetOrigins(1e-3);
    const std::vector<float> ao = aoOf(scene, points, 66);
    for (std::size_t i = 0; i < 4; ++i)
        EXPECT_FLOAT_EQ(ao[i], 1.0f);
    for (std::size_t i = 4; i < ao.size(); ++i)
        EXPECT_TRUE(std::isnan(ao[i])) << i;
    // A file's zero normal falls back to the faces' normal.
    mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
    Scene withNormals;
    withNormals.addMeshInstance(mesh);
    EXPECT_EQ(aoVertexPoints(withNormals).count(AoPointStatus::Ok), 4u);
}

TEST(AoBadInput, EmptySceneHasNoPointsAndNoBits)
{
    const Scene empty;
    AoPoints points = aoVertexPoints(empty);
    EXPECT_EQ(points.size(), 0u);
    points.offsetOrigins(0.0);
    const AoOccluders occluders = aoOccluders(empty);
    AoBinnedCaster caster(occluders);
    AoComputation computation(caster, points, 18);
    EXPECT_TRUE(computation.run());
    EXPECT_TRUE(ambientOcclusion(computation.matrix(), points, 18).empty());
}

TEST(AoBadInput, EnvironmentFilesAreCheckedWithOneLineErrors)
{
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("sightline_ao_env_" + std::to_string(getpid()));
    std::filesystem::create_directories(folder);
    auto expectError = [](const std::filesystem::path& file, const std::string& words) {
        try {
            AoEnvironment::load(file);
            ADD_FAILURE() << file << " was accepted";
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(words), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    };
    expectError(folder / "missing.hdr", "missing.hdr");
    std::ofstream(folder / "garbage.hdr") << "not an image at all";
    expectError(folder / "garbage.hdr", "not a Radiance HDR");
    // A PNG is an image, but not high dynamic range.
    const unsigned char png[] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 0x0d, 'I', 'H', 'D', 'R', 0, 0, 0, 1,
                                 0, 0, 0, 1, 8, 2, 0, 0, 0, 0x90, 0x77, 0x53, 0xde};
    std::ofstream(folder / "photo.png", std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
    expectError(folder / "photo.png", "not a Radiance HDR");
    // A real (tiny) Radiance file of the wrong shape: 4 x 4 is not lat-long.
    {
        std::ofstream f(folder / "square.hdr", std::ios::binary);
        f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n";
        for (int i = 0; i < 16; ++i)
            f.write("\x80\x80\x80\x81", 4);
    }
    expectError(folder / "square.hdr", "latitude-longitude");
    {
        std::ofstream f(folder / "sky.hdr", std::ios::binary);
        f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n";
        for (int i = 0; i < 32; ++i)
            f.write("\x80\x80\x80\x81", 4);   // 0.5 * 2^(129-128) = 1.0... (RGBE)
    }
    const AoEnvironment sky = AoEnvironment::load(folder / "sky.hdr");
    EXPECT_EQ(sky.width(), 8);
    EXPECT_NEAR(sky.radiance({0, 1, 0}).g, 1.0f, 0.02f);
    std::filesystem::remove_all(folder);
}

namespace {

std::string hdrHeader(int width, int height)
{
    return "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) + "\n";
}

/// One run-length scanline of `width` pixels, every channel a single run of `value` (width <= 127).
std::string rleRow(int width, unsigned char value)
{
    std::string row = {2, 2, char(width >> 8), char(width & 0xff)};
    for (int c = 0; c < 4; ++c)
        row += {char(128 + width), char(value)};
    return row;
}

} // namespace

TEST(AoBadInput, EnvironmentDataIsCheckedBeforeDecoding)
{
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("sightline_ao_hdr_" + std::to_string(getpid()));
    std::filesystem::create_directories(folder);
    auto write = [&](const std::string& name, const std::string& bytes) {
        std::ofstream(folder / name, std::ios::binary) << bytes;
        return folder / name;
    };
    auto expectError = [](const std::filesystem::path& file, const std::string& words) {
        for (int reader = 0; reader < 2; ++reader)   // the environment and the 8-bit image reader
            try {
                if (reader == 0)
                    AoEnvironment::load(file);
                else
                    loadRgbImage(file);
                ADD_FAILURE() << file << " was accepted";
            } catch (const Error& e) {
                const std::string message = e.what();
                EXPECT_NE(message.find(words), std::string::npos) << message;
                EXPECT_EQ(message.find('\n'), std::string::npos) << message;
            }
    };
    // A run-length count of 0 made stb loop forever; padded so that the file is long enough.
    expectError(write("zero.hdr", hdrHeader(8, 4) + std::string{2, 2, 0, 8, 0} + std::string(60, '\0')), "run of 0");
    // A run past the end of the scanline, a row of the wrong length, a flat row among RLE ones.
    expectError(write("long.hdr", hdrHeader(8, 4) + std::string{2, 2, 0, 8, char(128 + 9), 1} + std::string(60, '\0')), "run of 9");
    expectError(write("width.hdr", hdrHeader(8, 4) + std::string{2, 2, 0, 9} + std::string(60, '\0')), "declares 9 pixels");
    expectError(write("mixed.hdr", hdrHeader(8, 4) + rleRow(8, 128) + std::string(64, '\x40')), "scanline 1 is flat");
    // Header only, or the data cut short: an error, not a black sky.
    expectError(write("header.hdr", hdrHeader(8, 4)), "truncated");
    expectError(write("short.hdr", hdrHeader(8, 4) + rleRow(8, 128) + rleRow(8, 128) + rleRow(8, 128) + rleRow(8, 128).substr(0, 6)),
                "truncated");
    expectError(write("flat.hdr", hdrHeader(4, 2) + std::string(31, '\x80')), "truncated");
    // Declared sizes are refused before anything is allocated.
    expectError(write("huge.hdr", hdrHeader(16384, 8192)), "Mpixels");
    expectError(write("wide.hdr", hdrHeader(16385, 1)), "outside 1..16384");
    expectError(write("flip.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 4 +X 8\n" + std::string(128, '\x80')), "only '-Y H +X W'");
    expectError(write("xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 4 +X 8\n" + std::string(128, '\x80')), "FORMAT");
    expectError(write("noend.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe"), "header");

    // Valid run-length and flat files read whole: RGBE 128, 128, 128, 129 is 1.0.
    std::string rle = hdrHeader(8, 4);
    for (int y = 0; y < 4; ++y) {
        std::string row = {2, 2, 0, 8};
        for (int c = 0; c < 3; ++c)
            row += {char(4), char(128), char(128), char(128), char(128), char(128 + 4), char(128)};   // a dump, then a run
        row += {char(128 + 8), char(129)};
        rle += row;
    }
    const AoEnvironment sky = AoEnvironment::load(write("rle.hdr", rle));
    EXPECT_EQ(sky.width(), 8);
    EXPECT_NEAR(sky.radiance({0, 1, 0}).g, 1.0f, 0.02f);
    std::string flat = hdrHeader(4, 2);
    for (int i = 0; i < 8; ++i)
        flat += "\x80\x80\x80\x81";
    const RgbImage image = loadRgbImage(write("flat-ok.hdr", flat));
    EXPECT_EQ(image.width, 4);
    EXPECT_NEAR(image.pixels[7].r, 1.0f, 0.01f);
    std::filesystem::remove_all(folder);
}

TEST(AoBadInput, TruncatedImagesAreErrorsNotBlack)
{
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("sightline_image_" + std::to_string(getpid()));
    std::filesystem::create_directories(folder);
    auto write = [&](const std::string& name, const std::string& bytes) {
        std::ofstream(folder / name, std::ios::binary) << bytes;
        return folder / name;
    };
    auto expectError = [](const std::filesystem::path& file, const std::string& words) {
        try {
            loadRgbImage(file);
            ADD_FAILURE() << file << " was accepted";
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(words), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    };
    // Binary PPM: 2x2 needs 12 pixel bytes.
    const std::string ppm = "P6\n2 2\n255\n" + std::string(12, '\x7f');
    EXPECT_EQ(loadRgbImage(write("ok.ppm", ppm)).width, 2);
    expectError(write("short.ppm", ppm.substr(0, ppm.size() - 1)), "truncated PNM");
    // 24-bit BMP, 2x2: rows padded to 8 bytes, pixels at offset 54.
    std::string bmp(54, '\0');
    auto put32 = [&](std::size_t at, std::uint32_t v) {
        for (int b = 0; b < 4; ++b)
            bmp[at + std::size_t(b)] = char(v >> (8 * b));
    };
    bmp[0] = 'B', bmp[1] = 'M';
    put32(2, 54 + 16), put32(10, 54), put32(14, 40), put32(18, 2), put32(22, 2);
    bmp[26] = 1, bmp[28] = 24;
    bmp += std::string(16, '\x40');
    EXPECT_EQ(loadRgbImage(write("ok.bmp", bmp)).height, 2);
    expectError(write("short.bmp", bmp.substr(0, bmp.size() - 3)), "truncated BMP");
    // A 1x1 RGB PNG cut before its IEND chunk.
    const unsigned char png[] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 0x0d, 'I', 'H', 'D', 'R', 0, 0, 0, 1,
                                 0, 0, 0, 1, 8, 2, 0, 0, 0, 0x90, 0x77, 0x53, 0xde, 0, 0, 0, 0x0c, 'I', 'D', 'A', 'T',
                                 0x08, 0xd7, 0x63, 0xf8, 0xcf, 0xc0, 0x00, 0x00, 0x03, 0x01, 0x01, 0x00};
    expectError(write("short.png", std::string(reinterpret_cast<const char*>(png), sizeof png)), "truncated PNG");
    // A GIF is not read at all (its data cannot be checked).
    expectError(write("a.gif", std::string("GIF89a\x01\x00\x01\x00\x00\x00\x00", 13) + std::string(20, '\0')), "GIF");
    std::filesystem::remove_all(folder);
}

TEST(AoTexels, DensitiesOutsideTheRangeAreRefused)
{
    const AoOccluders occluders = aoOccluders(clutter());
    for (const double density : {std::numeric_limits<double>::quiet_NaN(), 0.0, -1.0, 1001.0, 1e308,
                                 std::numeric_limits<double>::infinity()}) {
        AoPoints points;
        try {
            aoTexelPoints(occluders, density, points);
            ADD_FAILURE() << density << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("(0, 1000]"), std::string::npos) << e.what();
        }
        EXPECT_EQ(points.size(), 0u);
    }
    // The largest density is refused by the atlas limit, not by an overflowing tile size, naming
    // a density that fits (and is not far below what would).
    AoPoints points;
    std::string message;
    try {
        aoTexelPoints(occluders, kMaxTexelDensity, points, 1u << 20);
        ADD_FAILURE() << "the largest density fitted";
    } catch (const Error& e) {
        message = e.what();
    }
    const std::size_t at = message.find("try --texel ");
    ASSERT_NE(at, std::string::npos) << message;
    const double suggested = std::stod(message.substr(at + 12));
    AoPoints fitting;
    const AoTexelLayout layout = aoTexelPoints(occluders, suggested, fitting, 1u << 20);
    EXPECT_LE(std::uint64_t(layout.width) * std::uint64_t(layout.height), 1u << 20);
    AoPoints more;
    EXPECT_THROW(aoTexelPoints(occluders, suggested * 1.05, more, 1u << 20), Error);
}

TEST(AoTexels, GridsCoverEachTriangleAndMapToTheAtlas)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points;
    const AoTexelLayout layout = aoTexelPoints(occluders, 4.0, points);
    ASSERT_EQ(layout.tiles.size(), occluders.triangleCount());
    std::vector<std::uint8_t> used(std::size_t(layout.width) * std::size_t(layout.height), 0);
    for (std::uint32_t t = 0; t < layout.tiles.size(); ++t) {
        const AoTexelTile& tile = layout.tiles[t];
        ASSERT_GT(tile.width, 0);
        for (int q = 0; q < tile.height; ++q)
            for (int s = 0; s < tile.width; ++s) {
                auto& cell = used[std::size_t(tile.y + q) * std::size_t(layout.width) + std::size_t(tile.x + s)];
                EXPECT_EQ(cell, 0) << "tiles overlap";
                cell = 1;
            }
        // Each corner's uv lies in its tile (texel centres at +0.5).
        for (int c = 0; c < 3; ++c) {
            const glm::vec2 uv = layout.uv(occluders, t, c);
            EXPECT_GE(uv.x * layout.width, tile.x - 1e-3);
            EXPECT_LE(uv.x * layout.width, tile.x + tile.width + 1e-3);
            EXPECT_GE(uv.y * layout.height, tile.y - 1e-3);
            EXPECT_LE(uv.y * layout.height, tile.y + tile.height + 1e-3);
        }
    }
    // The floor's points see the wall's contact shadow: AO falls towards the wall's foot.
    points.offsetOrigins(1e-3);
    const std::vector<float> ao = aoOf(scene, points, 258);
    float lowest = 1.0f;
    for (float a : ao)
        lowest = std::min(lowest, a);
    EXPECT_LT(lowest, 0.7f);
    EXPECT_THROW(aoTexelPoints(occluders, 1e6, points), Error);   // far too many texels: refused
    EXPECT_THROW(aoTexelPoints(occluders, -1.0, points), Error);
}

// The editor's preview counts only occluders within reach (AoBinnedOptions::maxDistance). Under an
// infinite ceiling at height h, a ray at angle theta from the normal meets it at h / cos(theta), so
// the cosine-weighted visible fraction within reach R > h is P(cos(theta) < h / R) = (h / R)^2,
// and 1 for R <= h.
TEST(AoClosedForm, UnderACeilingWithinReach)
{
    // Turned off the light sphere's axes (the AO does not change): about +Y the cut-off cone
    // cos(theta) = h / R would run along a ring of directions (ties, as for the wall above).
    const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.4f, glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f))));
    const auto quadTurned = [&](glm::vec3 corner, glm::vec3 u, glm::vec3 v, const char* name) {
        return test::quad(turn * corner, turn * u, turn * v, name);
    };
    const Scene scene = test::sceneOf({quadTurned({-1000.0f, 0.0f, -1000.0f}, {0.0f, 0.0f, 2000.0f}, {2000.0f, 0.0f, 0.0f}, "floor"),
                                       quadTurned({-1000.0f, 1.0f, -1000.0f}, {2000.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 2000.0f}, "ceiling")});
    const AoOccluders occluders = aoOccluders(scene);
    for (const double reach : {0.9, 1.25, 2.0, 4.0, std::numeric_limits<double>::infinity()}) {
        AoPoints points = onePoint(turn * glm::vec3(0.2f, 0.0f, -0.1f), turn * glm::vec3(0, 1, 0), 1e-3);
        AoBinnedCaster caster(occluders, AoBinnedOptions{.maxDistance = reach});
        AoComputation computation(caster, points, 1026);
        ASSERT_TRUE(computation.run());
        const double expected = reach <= 1.0 ? 1.0 : std::pow(1.0 / reach, 2);
        // The cut-off cone crosses a ring of direction cells, each all in or all out (a cell's
        // weight is about 1/500 of the cosine lobe): 6.5e-3 off at most, measured.
        EXPECT_NEAR(ambientOcclusion(computation.matrix(), points, 1026)[0], expected, 1e-2) << "reach " << reach;
    }
}
