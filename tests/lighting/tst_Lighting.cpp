// Importance maps (§9) and soft shadows (§8) against closed forms: a half-plane occluder's
// penumbra, an infinite wall, a colour-textured light, a raised receiver, alternating frames.
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "lighting/AreaLight.h"
#include "lighting/SoftShadow.h"
#include "base/ColourMap.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/ImportanceMap.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ReceiverHeights.h"

using namespace sightline;

namespace {

// The penumbra set-up: source [0, 1]^2 at z = 0 (32 x 4 samples), receiver x in [-1, 2] at z = 2
// (64 x 2 samples), and at z = 1 a half-plane covering x < 0.5. A ray from x_s to x_r crosses
// z = 1 at (x_s + x_r) / 2, so it is blocked when x_s + x_r < 1 and the continuous visible
// fraction is clamp(x_r, 0, 1): a linear penumbra from x_r = 0 to 1. Sample positions are
// multiples of 1/128 whose sums never equal 1 exactly (no grazing rays).
struct Penumbra {
    Patch source = test::xyPatch(0.0, 32, 4);
    Patch receiver;
    Scene scene;

    Penumbra()
    {
        receiver.corner = {-1.0, 0.0, 2.0};
        receiver.u = {3.0, 0.0, 0.0};
        receiver.v = {0.0, 1.0, 0.0};
        receiver.na = 64;
        receiver.nb = 2;
        scene = test::sceneOf({test::quad({-10.0f, -10.0f, 1.0f}, {10.5f, 0.0f, 0.0f}, {0.0f, 20.0f, 0.0f}, "half-plane")});
    }

    double receiverX(int a) const { return receiver.sample(a, 0).x; }
    /// The light fraction the sampled closed form gives at receiver column a, counting source
    /// columns whose ray passes the edge; `crossing(x_s, x_r)` is where the ray meets z = 1.
    template <typename Crossing>
    double sampledFraction(int a, Crossing&& crossing) const
    {
        int seen = 0;
        for (int s = 0; s < source.na; ++s)
            seen += crossing(source.sample(s, 0).x, receiverX(a)) >= 0.5 ? 1 : 0;
        return double(seen) / source.na;
    }
    double sampledFraction(int a) const
    {
        return sampledFraction(a, [](double xs, double xr) { return 0.5 * (xs + xr); });
    }
    static double continuousFraction(double xr) { return std::clamp(xr, 0.0, 1.0); }
};

BitmaskOptions exactBitmask()
{
    BitmaskOptions options;
    options.strategy = CpuStrategy::Bitmask;
    return options;
}

} // namespace

TEST(ImportanceMap, ReceiverAndSourceFractionsOfAHandMadeMap)
{
    // 2x2 source samples, 3x1 receiver samples.
    HiddenSampleMap map(4, 3, 1);
    map.setBlocked(0, 0);
    map.setBlocked(0, 1);
    map.setBlocked(1, 1);
    for (int i = 0; i < 4; ++i)
        map.setBlocked(2, i);
    const ImportanceMap receiver = receiverImportance(map);
    ASSERT_EQ(receiver.na, 3);
    ASSERT_EQ(receiver.nb, 1);
    EXPECT_FLOAT_EQ(receiver.at(0, 0), 0.5f);
    EXPECT_FLOAT_EQ(receiver.at(1, 0), 0.75f);
    EXPECT_FLOAT_EQ(receiver.at(2, 0), 0.0f);
    const ImportanceMap source = sourceImportance(map, 2, 2);
    ASSERT_EQ(source.na, 2);
    ASSERT_EQ(source.nb, 2);
    EXPECT_FLOAT_EQ(source.at(0, 0), 1.0f / 3.0f);   // bit 0: blocked at receivers 0 and 2
    EXPECT_FLOAT_EQ(source.at(1, 0), 0.0f);          // bit 1: blocked everywhere
    EXPECT_FLOAT_EQ(source.at(0, 1), 2.0f / 3.0f);
    EXPECT_FLOAT_EQ(source.at(1, 1), 2.0f / 3.0f);
    EXPECT_THROW(sourceImportance(map, 3, 2), std::invalid_argument);
}

TEST(ImportanceMap, SourceImportanceCountsEveryWordOfA1024SampleSource)
{
    HiddenSampleMap map(1024, 4, 4);
    for (int j = 0; j < map.receiverCount(); ++j)
        for (int i = j; i < 1024; i += 7)
            map.setBlocked(j, i);
    const ImportanceMap source = sourceImportance(map, 32, 32);
    for (int i = 0; i < 1024; ++i) {
        int blocked = 0;
        for (int j = 0; j < map.receiverCount(); ++j)
            blocked += map.blocked(j, i) ? 1 : 0;
        ASSERT_FLOAT_EQ(source.values[std::size_t(i)], 1.0f - float(blocked) / 16.0f) << "source bit " << i;
    }
}

TEST(ImportanceAccumulator, TwoAlternatingFramesGiveTheirMeanMaximumAndEverVisible)
{
    ImportanceMap a(2, 1), b(2, 1);
    a.values = {1.0f, 0.0f};
    b.values = {0.5f, 0.0f};
    ImportanceAccumulator accumulator;
    EXPECT_TRUE(accumulator.result(ImportanceStatistic::Mean).values.empty());
    for (int k = 0; k < 6; ++k)
        accumulator.add(k % 2 ? b : a);
    EXPECT_EQ(accumulator.frames(), 6);
    EXPECT_FLOAT_EQ(accumulator.result(ImportanceStatistic::Mean).at(0, 0), 0.75f);
    EXPECT_FLOAT_EQ(accumulator.result(ImportanceStatistic::Mean).at(1, 0), 0.0f);
    EXPECT_FLOAT_EQ(accumulator.result(ImportanceStatistic::Maximum).at(0, 0), 1.0f);
    EXPECT_FLOAT_EQ(accumulator.result(ImportanceStatistic::EverVisible).at(0, 0), 1.0f);
    EXPECT_FLOAT_EQ(accumulator.result(ImportanceStatistic::EverVisible).at(1, 0), 0.0f);
    EXPECT_THROW(accumulator.add(ImportanceMap(3, 1)), std::invalid_argument);
    accumulator.reset();
    EXPECT_EQ(accumulator.frames(), 0);
    accumulator.add(ImportanceMap(3, 1, 0.25f));   // a new grid after a reset
    EXPECT_FLOAT_EQ(accumulator.result(ImportanceStatistic::Mean).at(2, 0), 0.25f);
    EXPECT_EQ(parseImportanceStatistic("ever"), ImportanceStatistic::EverVisible);
    EXPECT_THROW(parseImportanceStatistic("median"), Error);
}

TEST(ColourMap, ViridisAnchorsFromMatplotlib)
{
    // matplotlib's viridis at 0, 0.5 and 1: #440154, #21918c, #fde725.
    const Rgb8 expected[] = {{68, 1, 84}, {33, 145, 140}, {253, 231, 37}};
    const float at[] = {0.0f, 0.5f, 1.0f};
    for (int k = 0; k < 3; ++k) {
        const Rgb8 c = viridis8(at[k]);
        EXPECT_NEAR(c.r, expected[k].r, 4) << at[k];
        EXPECT_NEAR(c.g, expected[k].g, 4) << at[k];
        EXPECT_NEAR(c.b, expected[k].b, 4) << at[k];
    }
    EXPECT_EQ(viridis8(-1.0f), viridis8(0.0f));
    EXPECT_EQ(viridis8(2.0f), viridis8(1.0f));
    EXPECT_EQ(viridis8(std::nanf("")), viridis8(0.0f));
    // Perceptually ordered: lightness (here luma) rises monotonically.
    float last = -1.0f;
    for (int k = 0; k <= 100; ++k) {
        const glm::vec3 c = viridis(k / 100.0f);
        const float luma = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
        EXPECT_GT(luma, last) << k;
        last = luma;
    }
}

TEST(SoftShadow, HalfPlanePenumbraMatchesTheClosedForm)
{
    const Penumbra p;
    const RayCastScene reference(p.scene);
    const CpuBitmaskSampler cpu(p.scene);
    for (const auto& [name, fraction] :
         {std::pair{"raycast", lightFraction(reference.sample(p.source, p.receiver))},
          std::pair{"cpu", lightFraction(cpu.sample(p.source, p.receiver, exactBitmask()))}}) {
        double mae = 0.0;
        for (int b = 0; b < p.receiver.nb; ++b) {
            for (int a = 0; a < p.receiver.na; ++a) {
                // Exact against the sampled closed form, within a source cell of the continuous one.
                ASSERT_DOUBLE_EQ(fraction.at(a, b), p.sampledFraction(a)) << name << " column " << a;
                EXPECT_LE(std::abs(fraction.at(a, b) - Penumbra::continuousFraction(p.receiverX(a))), 1.0 / 32 + 1e-6);
                mae += std::abs(fraction.at(a, b) - Penumbra::continuousFraction(p.receiverX(a)));
            }
        }
        EXPECT_LT(mae / p.receiver.sampleCount(), 0.01) << name;
        // Fully lit beyond the penumbra, fully dark before it.
        EXPECT_FLOAT_EQ(fraction.at(0, 0), 0.0f);
        EXPECT_FLOAT_EQ(fraction.at(p.receiver.na - 1, 0), 1.0f);
    }
}

TEST(SoftShadow, DecorrelatedSamplingAnswersTheSameQuestionInEverySampler)
{
    const Penumbra p;
    const RayCastScene reference(p.scene);
    const CpuBitmaskSampler cpu(p.scene);
    RayCastOptions rayOptions;
    rayOptions.jitter.seed = 7;
    BitmaskOptions cpuOptions = exactBitmask();
    cpuOptions.jitter.seed = 7;
    const HiddenSampleMap expected = reference.sample(p.source, p.receiver, rayOptions);
    EXPECT_EQ(cpu.sample(p.source, p.receiver, cpuOptions).differenceCount(expected), 0u);
    // Jitter moves each receiver sample's source grid by under half a cell: at most one more or
    // one fewer source column is seen, and the regular grid's banding turns into noise.
    const ImportanceMap jittered = lightFraction(expected);
    const ImportanceMap regular = lightFraction(reference.sample(p.source, p.receiver));
    int differ = 0;
    for (std::size_t j = 0; j < jittered.values.size(); ++j) {
        EXPECT_LE(std::abs(jittered.values[j] - regular.values[j]), 1.0f / 32 + 1e-6f);
        differ += jittered.values[j] != regular.values[j];
    }
    EXPECT_GT(differ, 0);
}

TEST(SoftShadow, InfiniteWallGivesNoLight)
{
    const Penumbra p;
    const Scene wall = test::sceneOf({test::quad({-50.0f, -50.0f, 1.0f}, {100.0f, 0.0f, 0.0f}, {0.0f, 100.0f, 0.0f}, "wall")});
    const CpuBitmaskSampler cpu(wall);
    const RayCastScene reference(wall);
    const AreaLight light = AreaLight::white(p.source.sampleCount());
    for (const HiddenSampleMap& map : {cpu.sample(p.source, p.receiver, exactBitmask()), reference.sample(p.source, p.receiver)}) {
        const LightImage image = shadeReceiver(map, light);
        for (const glm::vec3& c : image.rgb)
            ASSERT_EQ(c, glm::vec3(0.0f));
    }
    // Without the wall every sample gets the full light.
    const LightImage open = shadeReceiver(HiddenSampleMap(p.source.sampleCount(), p.receiver.na, p.receiver.nb), light);
    for (const glm::vec3& c : open.rgb)
        ASSERT_EQ(c, glm::vec3(1.0f));
}

TEST(SoftShadow, ColourTexturedLightSumsItsGroupsUnderThePenumbra)
{
    const Penumbra p;
    // Left half of the source red, right half blue, the top row black (emits nothing).
    std::vector<glm::vec3> colours(std::size_t(p.source.sampleCount()));
    for (int b = 0; b < p.source.nb; ++b)
        for (int a = 0; a < p.source.na; ++a)
            colours[std::size_t(b * p.source.na + a)] =
                b == p.source.nb - 1 ? glm::vec3(0.0f) : a < 16 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    const AreaLight light = AreaLight::fromSampleColours(colours);
    ASSERT_EQ(light.groups.size(), 2u);
    EXPECT_EQ(light.groups[0].count + light.groups[1].count, 96);
    EXPECT_NEAR(light.unoccluded().r, 48.0f / 128.0f, 1e-6f);
    EXPECT_NEAR(light.unoccluded().b, 48.0f / 128.0f, 1e-6f);

    const LightImage image = shadeReceiver(CpuBitmaskSampler(p.scene).sample(p.source, p.receiver, exactBitmask()), light);
    for (int a = 0; a < p.receiver.na; ++a) {
        // Source column s is seen when x_s + x_r >= 1; red columns are s < 16, and 3 of 4 rows emit.
        int red = 0, blue = 0;
        for (int s = 0; s < p.source.na; ++s) {
            if (p.source.sample(s, 0).x + p.receiverX(a) >= 1.0)
                (s < 16 ? red : blue) += 3;
        }
        const glm::vec3 c = image.rgb[std::size_t(a)];
        EXPECT_FLOAT_EQ(c.r, float(red) / 128.0f) << a;
        EXPECT_FLOAT_EQ(c.g, 0.0f);
        EXPECT_FLOAT_EQ(c.b, float(blue) / 128.0f) << a;
    }
    EXPECT_THROW(AreaLight::fromSampleColours({glm::vec3(std::nanf(""), 0, 0)}), Error);
    std::vector<glm::vec3> rainbow(300);
    for (std::size_t k = 0; k < rainbow.size(); ++k)
        rainbow[k] = glm::vec3(float(k + 1) / 300.0f, 0.5f, 0.5f);
    EXPECT_THROW(AreaLight::fromSampleColours(rainbow), Error);   // more than kMaxLightGroups colours
    EXPECT_THROW(shadeReceiver(HiddenSampleMap(64, 2, 2), light), std::invalid_argument);
}

TEST(SoftShadow, RaisedReceiverSamplesShiftThePenumbra)
{
    // The bumpy receiver of §8: odd receiver columns raised 0.4 m toward the light (z = 1.6). A ray
    // from x_s to such a sample meets z = 1 at x_s + (x_r - x_s) / 1.6; 12a + 30c never equals
    // 1131, so no ray grazes the edge.
    const Penumbra p;
    ReceiverHeights heights;
    heights.metres.resize(std::size_t(p.receiver.sampleCount()));
    for (int j = 0; j < p.receiver.sampleCount(); ++j)
        heights.metres[std::size_t(j)] = (j % p.receiver.na) % 2 ? 0.4 : 0.0;
    BitmaskOptions options = exactBitmask();
    options.heights = &heights;
    RayCastOptions rayOptions;
    rayOptions.heights = &heights;
    const ImportanceMap cpu = lightFraction(CpuBitmaskSampler(p.scene).sample(p.source, p.receiver, options));
    const ImportanceMap reference = lightFraction(RayCastScene(p.scene).sample(p.source, p.receiver, rayOptions));
    int raisedDiffers = 0;
    for (int a = 0; a < p.receiver.na; ++a) {
        const double depth = a % 2 ? 1.6 : 2.0;
        const double expected = p.sampledFraction(a, [&](double xs, double xr) { return xs + (xr - xs) / depth; });
        ASSERT_DOUBLE_EQ(cpu.at(a, 1), expected) << "column " << a;
        ASSERT_DOUBLE_EQ(reference.at(a, 1), expected) << "column " << a;
        raisedDiffers += a % 2 && expected != p.sampledFraction(a);
    }
    EXPECT_GT(raisedDiffers, 5);   // the raise is visible in the answer
}

TEST(SoftShadow, DenseReferenceConvergesToThePenumbraProfile)
{
    const Penumbra p;
    const RayCastScene reference(p.scene);
    double lastMae = 1.0;
    for (int side : {32, 64, 128}) {
        const ImportanceMap dense = denseLightFraction(reference, p.source, p.receiver, side);
        double mae = 0.0;
        for (int a = 0; a < p.receiver.na; ++a) {
            const double error = std::abs(dense.at(a, 0) - Penumbra::continuousFraction(p.receiverX(a)));
            EXPECT_LE(error, 1.0 / side + 1e-6) << side << " column " << a;
            mae += error;
        }
        mae /= p.receiver.na;
        EXPECT_LE(mae, lastMae) << side;
        lastMae = mae;
    }
    // The 32-per-side dense grid is the regular 32x32 grid itself.
    Patch square = p.source;
    square.na = square.nb = 32;
    EXPECT_EQ(denseLightFraction(reference, square, p.receiver, 32).values,
              lightFraction(reference.sample(square, p.receiver)).values);
    EXPECT_THROW(denseLightFraction(reference, p.source, p.receiver, 48), std::invalid_argument);
}

TEST(SoftShadow, MeanAbsoluteError)
{
    ImportanceMap a(2, 1), b(2, 1);
    a.values = {0.0f, 1.0f};
    b.values = {0.5f, 0.75f};
    EXPECT_DOUBLE_EQ(meanAbsoluteError(a, b), 0.375);
    EXPECT_THROW(meanAbsoluteError(a, ImportanceMap(1, 2)), std::invalid_argument);
}
