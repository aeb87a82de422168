// sightline-cli lights (docs/lights.md, a contract): its .npy shapes and --json keys, its values
// judged point by point by the independent brute force (LightsJudge.h), the fast path against
// --reference, bad lights and bad points refused in one line, and the "lights" key kept on save.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "LightsJudge.h"
#include "base/ImageFile.h"
#include "lighting/LightEmission.h"
#include "project/Project.h"
#include "project/ProjectLights.h"
#include "base/Error.h"
#include "base/NpyFile.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;

namespace {

class LightsCli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        // A 6 x 6 m floor, a table (a slab on nothing: its top 0.8 m up) and a wall with a doorway.
        std::ofstream(folder / "room.obj") << "v -3 0 -3\nv 3 0 -3\nv 3 0 3\nv -3 0 3\n"
                                              "v -0.6 0.8 -0.4\nv 0.6 0.8 -0.4\nv 0.6 0.8 0.4\nv -0.6 0.8 0.4\n"
                                              "v -3 0 1.5\nv -0.5 0 1.5\nv -0.5 2.5 1.5\nv -3 2.5 1.5\n"
                                              "v 0.5 0 1.5\nv 3 0 1.5\nv 3 2.5 1.5\nv 0.5 2.5 1.5\n"
                                              "f 1 3 2\nf 1 4 3\nf 5 7 6\nf 5 8 7\n"
                                              "f 9 10 11\nf 9 11 12\nf 13 14 15\nf 13 15 16\n";
    }

    json project(const json& lights) const
    {
        return {{"version", 1},
                {"scene", "room.obj"},
                {"source", {{"corner", {-1, 2, -1}}, {"u", {2, 0, 0}}, {"v", {0, 0, 2}}, {"samples", {8, 8}}}},
                {"receiver", {{"corner", {-2.5, 0.01, 2.5}}, {"u", {5, 0, 0}}, {"v", {0, 0, -5}}, {"samples", {20, 16}}}},
                {"lights", lights}};
    }
    fs::path write(const std::string& name, const json& document) const
    {
        std::ofstream(folder / name) << document.dump(2);
        return folder / name;
    }
    static json lights()
    {
        return json::array({
            {{"type", "area"}, {"name", "ceiling"}, {"corner", {-1, 2.4, -1}}, {"u", {2, 0, 0}}, {"v", {0, 0, 2}},
             {"samples", {6, 5}}, {"radiance", 4}, {"colour", {1, 0.9, 0.8}}},
            {{"type", "point"}, {"name", "lamp"}, {"position", {0.3, 1.5, -2}}, {"intensity", 6}, {"range", 8}},
            {{"type", "spot"}, {"position", {0, 2.2, 2.4}}, {"direction", {0, -1, -1}}, {"inner_angle", 0.2},
             {"outer_angle", 0.7}, {"intensity", 9}, {"colour", {0.2, 0.4, 1}}},
            {{"type", "directional"}, {"direction", {0.4, -1, -0.3}}, {"intensity", 2}},
        });
    }
    std::vector<Light> parsed() const { return parseLights(lights(), "test"); }
    Scene scene() const { return buildScene(loadProject(folder / "p.json")); }
};

} // namespace

TEST_F(LightsCli, PointsGiveShapeNx3AndTheExactIrradiance)
{
    write("p.json", project(lights()));
    std::vector<float> rows;
    std::vector<ShadingPoint> points;
    for (int k = 0; k < 150; ++k) {
        const double x = -2.8 + 0.037 * k, z = -2.7 + 0.036 * k;
        const bool onTable = std::abs(x) < 0.55 && std::abs(z) < 0.35;
        const ShadingPoint p{{x, onTable ? 0.801 : 0.001, z}, {0.0, 2.0, 0.0}};   // a normal the tool normalises
        points.push_back({p.position, {0.0, 1.0, 0.0}});
        rows.insert(rows.end(), {float(p.position.x), float(p.position.y), float(p.position.z), 0.0f, 2.0f, 0.0f});
        points.back().position = glm::dvec3(glm::vec3(p.position));   // what the float32 file holds
    }
    writeFloatNpy(rows, 150, 6, folder / "points.npy");
    const CliRun run = runCli("lights " + (folder / "p.json").string() + " --points " + (folder / "points.npy").string() +
                              " --npy " + (folder / "e.npy").string() + " --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["lights"], 4);
    EXPECT_EQ(out["light_samples"], 33);
    EXPECT_EQ(out["points"], 150);
    EXPECT_TRUE(out["ms"].is_number());
    const Npy npy = readNpy(folder / "e.npy");
    ASSERT_EQ(npy.shape, (std::vector<std::size_t>{150, 3}));
    const LightsJudge judge(scene());
    const std::vector<Light> lightList = parsed();
    int lit = 0;
    for (std::size_t j = 0; j < points.size(); ++j) {
        const LitInterval exact = judge.at(lightList, points[j]);
        const glm::dvec3 value(npy.values[3 * j], npy.values[3 * j + 1], npy.values[3 * j + 2]);
        EXPECT_TRUE(LightsJudge::agrees(exact, value, 1e-6)) << "point " << j << ": " << value.x << " vs [" << exact.lit.x
                                                             << ", " << exact.lit.x + exact.ties.x << "]";
        lit += exact.lit.x > 0.0;
    }
    EXPECT_GT(lit, 100);
}

TEST_F(LightsCli, ReceiverSamplesGiveShapeNbNa3AndTheReferenceAgrees)
{
    write("p.json", project(lights()));
    const std::string base = "lights " + (folder / "p.json").string();
    const CliRun fast = runCli(base + " --bitmask-area --npy " + (folder / "f.npy").string() + " --json --compare");
    ASSERT_EQ(fast.code, 0) << fast.err;
    const CliRun reference = runCli(base + " --reference --npy " + (folder / "r.npy").string() + " --json");
    ASSERT_EQ(reference.code, 0) << reference.err;
    const json out = json::parse(fast.out);
    EXPECT_EQ(out["points"], 320);
    EXPECT_EQ(out["bitmask_lights"], 1);   // the ceiling panel faces the receiver: the bitmask
    EXPECT_EQ(json::parse(reference.out)["path"], "reference");
    const Npy f = readNpy(folder / "f.npy"), r = readNpy(folder / "r.npy");
    ASSERT_EQ(f.shape, (std::vector<std::size_t>{16, 20, 3}));
    ASSERT_EQ(f.values.size(), r.values.size());
    // Sample (a, b) at [b][a]. Both paths sum the same terms in the same order: they may differ
    // only where a shadow segment is a tie, and both lie in the exact interval everywhere.
    const Project p = loadProject(folder / "p.json");
    const LightsJudge judge(scene());
    const std::vector<Light> lightList = parsed();
    int tiedPoints = 0, differing = 0;
    for (int b = 0; b < 16; ++b)
        for (int a = 0; a < 20; ++a) {
            const LitInterval exact = judge.at(lightList, {p.receiver.sample(a, b), p.receiver.normal()});
            const std::size_t at = 3 * std::size_t(b * 20 + a);
            const glm::dvec3 byFast(f.values[at], f.values[at + 1], f.values[at + 2]);
            const glm::dvec3 byReference(r.values[at], r.values[at + 1], r.values[at + 2]);
            EXPECT_TRUE(LightsJudge::agrees(exact, byFast, 1e-6)) << a << ", " << b;
            EXPECT_TRUE(LightsJudge::agrees(exact, byReference, 1e-6)) << a << ", " << b;
            const bool tied = exact.ties != glm::dvec3(0.0);
            tiedPoints += tied;
            differing += byFast != byReference;
            if (!tied) {
                EXPECT_EQ(byFast, byReference) << a << ", " << b;
            }
        }
    EXPECT_EQ(out["compare"]["points_differing"], differing);
    EXPECT_LE(differing, tiedPoints);
    // The yardstick a user would write (Embree's float rays): timed, its ratio and its misses told.
    const json& compare = out["compare"];
    EXPECT_GT(compare["embree_float_ms"].get<double>(), 0.0);
    EXPECT_NEAR(compare["speedup_over_embree_float"].get<double>(),
                compare["embree_float_ms"].get<double>() / compare["fast_ms"].get<double>(), 1e-9);
    EXPECT_LE(compare["embree_float_points_differing"].get<std::size_t>(), 320u);
}

// The GL path (octahedral shadow maps) is not exact: --compare says how far it is, pair by pair
// and point by point. Its pairs are the exact count of non-zero terms, and on this room few differ.
TEST_F(LightsCli, GlPathReportsItsAgreementWithTheExactAnswer)
{
    write("p.json", project(lights()));
    const std::string base = "lights " + (folder / "p.json").string();
    const CliRun run = runCli(base + " --gl --gl-resolution 256 --compare --json --npy " + (folder / "g.npy").string());
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["path"], "gl");
    EXPECT_EQ(out["gl"]["pyramid"], true);
    EXPECT_LE(out["gl"]["maps"].get<int>(), 33);
    EXPECT_EQ(out["gl"]["resolution"], 256);
    const Npy g = readNpy(folder / "g.npy");
    ASSERT_EQ(g.shape, (std::vector<std::size_t>{16, 20, 3}));
    const Project p = loadProject(folder / "p.json");
    const std::vector<Light> lightList = parsed();
    std::uint64_t pairs = 0;
    for (int b = 0; b < 16; ++b)
        for (int a = 0; a < 20; ++a)
            for (const Emitter& e : lightEmitters(lightList))
                pairs += emitterTerm(lightList[e.light], e.position, p.receiver.sample(a, b), p.receiver.normal()) > 0.0;
    const json& compare = out["compare"];
    EXPECT_EQ(compare["pairs"], pairs);
    EXPECT_EQ(compare["pairs_differing"].get<std::uint64_t>(),
              compare["false_lit"].get<std::uint64_t>() + compare["false_shadowed"].get<std::uint64_t>());
    EXPECT_LT(compare["pairs_differing"].get<double>(), 0.03 * double(pairs));
    EXPECT_GT(compare["points_within_1pct"].get<double>(), 0.7);
    EXPECT_GT(compare["fast_ms"].get<double>(), 0.0);
    // Without the occlusion pyramid's classes every light sample gets a map, and no fewer pairs differ.
    const CliRun plain = runCli(base + " --gl --gl-resolution 256 --gl-no-pyramid --compare --json");
    ASSERT_EQ(plain.code, 0) << plain.err;
    const json plainOut = json::parse(plain.out);
    EXPECT_EQ(plainOut["gl"]["maps"], 33);
    EXPECT_EQ(plainOut["compare"]["pairs"], pairs);
    EXPECT_GE(plainOut["compare"]["pairs_differing"].get<std::uint64_t>(), compare["pairs_differing"].get<std::uint64_t>());
    // The GL answer is the one written.
    const CliRun again = runCli(base + " --gl --gl-resolution 256 --json");
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_NEAR(json::parse(again.out)["irradiance_mean"][0].get<double>(), out["irradiance_mean"][0].get<double>(), 1e-9);
    for (const char* bad : {" --gl --reference", " --gl --drag 3", " --gl-resolution 256", " --gl --gl-resolution 4", " --gl-no-pyramid"}) {
        const CliRun refused = runCli(base + bad);
        EXPECT_NE(refused.code, 0) << bad;
        EXPECT_TRUE(oneLine(refused.err)) << refused.err;
    }
}

// A light cut (--light-cut) is an approximation: --compare says how far it is from the reference,
// point by point, as the written answers show.
TEST_F(LightsCli, LightCutReportsItsErrorAgainstTheReference)
{
    json lightList = lights();
    for (int k = 0; k < 200; ++k)
        lightList.push_back({{"type", "point"}, {"position", {-2.8 + 0.028 * k, 1.0 + 0.005 * k, -2.8 + 0.021 * (k % 100)}},
                             {"intensity", 0.2}, {"range", 3}});
    write("p.json", project(lightList));
    const std::string base = "lights " + (folder / "p.json").string();
    const CliRun cut = runCli(base + " --light-cut 0.05 --compare --json --npy " + (folder / "c.npy").string());
    ASSERT_EQ(cut.code, 0) << cut.err;
    const CliRun reference = runCli(base + " --reference --json --npy " + (folder / "r.npy").string());
    ASSERT_EQ(reference.code, 0) << reference.err;
    const json out = json::parse(cut.out);
    EXPECT_GT(out["cut_clusters"].get<std::uint64_t>(), 0u);
    EXPECT_GT(out["cut_lights"].get<std::uint64_t>(), out["cut_clusters"].get<std::uint64_t>());
    const json& error = out["compare"]["light_cut"];
    const Npy c = readNpy(folder / "c.npy"), r = readNpy(folder / "r.npy");
    ASSERT_EQ(c.shape, r.shape);
    // The mean of each point's largest relative difference over its channels, from the files.
    double peak = 0.0, mean = 0.0, worst = 0.0;
    for (const float v : r.values)
        peak = std::max(peak, double(v));
    const std::size_t points = r.values.size() / 3;
    for (std::size_t j = 0; j < points; ++j) {
        double here = 0.0;
        for (std::size_t k = 3 * j; k < 3 * j + 3; ++k)
            here = std::max(here, std::abs(double(c.values[k]) - double(r.values[k])) / std::max(double(r.values[k]), 1e-6 * peak));
        mean += here / double(points);
        worst = std::max(worst, here);
    }
    EXPECT_NEAR(error["mean_relative"].get<double>(), mean, 1e-4 + 1e-3 * mean);   // the files hold float32
    EXPECT_NEAR(error["max_relative"].get<double>(), worst, 1e-4 + 1e-3 * worst);
    EXPECT_GT(error["mean_relative"].get<double>(), 0.0);
    EXPECT_LE(error["p99_relative"].get<double>(), error["max_relative"].get<double>());
    EXPECT_LE(error["points_beyond_5pct"].get<double>(), error["points_beyond_1pct"].get<double>());
    for (const char* bad : {" --light-cut 0", " --light-cut 2", " --light-cut nan", " --light-cut 0.1 --reference", " --gl --light-cut 0.1"}) {
        const CliRun refused = runCli(base + bad);
        EXPECT_NE(refused.code, 0) << bad;
        EXPECT_TRUE(oneLine(refused.err)) << bad << ": " << refused.err;
    }
}

TEST_F(LightsCli, BadLightsAndPointsGetOneLineErrors)
{
    const auto refused = [&](const json& lightList, const std::string& needle, const std::string& extra = "") {
        write("bad.json", project(lightList));
        const CliRun run = runCli("lights " + (folder / "bad.json").string() + extra);
        EXPECT_EQ(run.code, 1) << needle;
        EXPECT_TRUE(oneLine(run.err)) << run.err;
        EXPECT_NE(run.err.find(needle), std::string::npos) << run.err;
    };
    refused(json::array({{{"type", "point"}, {"position", {0, 1, 0}}, {"intensity", -1}}}), "'lights[0].intensity'");
    refused(json::array({{{"type", "point"}, {"position", {0, 1, 0}}, {"intensity", "bright"}}}), "'lights[0].intensity' must be a number");
    refused(json::array({{{"type", "candle"}, {"position", {0, 1, 0}}}}), "'lights[0].type'");
    refused(json::array({{{"type", "point"}}}), "'lights[0].position' is missing");
    refused(json::array({{{"type", "spot"}, {"position", {0, 1, 0}}, {"direction", {0, -1, 0}}, {"inner_angle", 0.9},
                          {"outer_angle", 0.5}}}),
            "'lights[0].inner_angle'");
    refused(json::array({{{"type", "area"}, {"corner", {0, 2, 0}}, {"u", {0, 0, 0}}, {"v", {1, 0, 0}}}}), "degenerate area light");
    refused(json::array({{{"type", "area"}, {"corner", {0, 2, 0}}, {"u", {1, 0, 0}}, {"v", {0, 0, 1}}, {"samples", {0, 4}}}}),
            "'lights[0].samples'");
    refused(json::array({{{"type", "point"}, {"position", {0, 1, 0}}, {"range", 0}}}), "'lights[0].range'");
    refused(json::object(), "'lights' must be an array");
    // Finite, but its irradiance does not fit the float32 outputs: refused, not written as inf.
    refused(json::array({{{"type", "point"}, {"position", {0, 1, 0}}, {"intensity", 1e300}}}), "beyond float32's range",
            " --npy " + (folder / "huge.npy").string());
    EXPECT_FALSE(fs::exists(folder / "huge.npy"));
    // Points: a zero normal, a wrong shape, NaN; outputs that would replace an input.
    write("p.json", project(lights()));
    writeFloatNpy({0, 1, 0, 0, 0, 0}, 1, 6, folder / "zero.npy");
    writeFloatNpy({0, 1, 0, 0, 1}, 1, 5, folder / "five.npy");
    writeFloatNpy({0, NAN, 0, 0, 1, 0}, 1, 6, folder / "nan.npy");
    refused(lights(), "has a zero normal", " --points " + (folder / "zero.npy").string());
    refused(lights(), "shape (N, 6)", " --points " + (folder / "five.npy").string());
    refused(lights(), "non-finite", " --points " + (folder / "nan.npy").string());
    const CliRun clobber = runCli("lights " + (folder / "p.json").string() + " --npy " + (folder / "p.json").string());
    EXPECT_EQ(clobber.code, 1);
    EXPECT_NE(clobber.err.find("would replace"), std::string::npos) << clobber.err;
    EXPECT_NO_THROW(loadProject(folder / "p.json"));
}

TEST_F(LightsCli, LightsRoundTripAndSurviveASave)
{
    const std::vector<Light> lightList = parsed();
    json written = json::array();
    for (const Light& light : lightList)
        written.push_back(lightJson(light));
    const std::vector<Light> again = parseLights(written, "again");
    ASSERT_EQ(again.size(), lightList.size());
    for (std::size_t k = 0; k < again.size(); ++k) {
        // The same light, but for a direction normalised twice (the last bit may differ).
        EXPECT_EQ(again[k].name, lightList[k].name);
        EXPECT_EQ(again[k].type, lightList[k].type);
        EXPECT_EQ(again[k].colour, lightList[k].colour);
        EXPECT_EQ(again[k].position, lightList[k].position);
        EXPECT_EQ(again[k].intensity, lightList[k].intensity);
        EXPECT_EQ(again[k].range, lightList[k].range);
        EXPECT_LT(glm::length(again[k].direction - lightList[k].direction), 1e-15);
        EXPECT_EQ(again[k].innerAngle, lightList[k].innerAngle);
        EXPECT_EQ(again[k].outerAngle, lightList[k].outerAngle);
        EXPECT_EQ(again[k].area.corner, lightList[k].area.corner);
        EXPECT_EQ(again[k].area.u, lightList[k].area.u);
        EXPECT_EQ(again[k].area.v, lightList[k].area.v);
        EXPECT_EQ(again[k].area.sampleCount(), lightList[k].area.sampleCount());
        EXPECT_EQ(again[k].radiance, lightList[k].radiance);
    }
    json document = project(lights());
    document["lights"][0]["editor_colour_temperature"] = 3200;   // a key we do not know is kept
    const Project p = parseProject(document, folder, "p.json");
    saveProject(p, folder / "saved.json");
    std::ifstream in(folder / "saved.json");
    const json saved = json::parse(in);
    EXPECT_EQ(saved["lights"], document["lights"]);
}

// A level exported with KHR_lights_punctual lights itself: a point light at the root and a spot
// under a translated parent, rotated to shine down; the project has no "lights" key.
TEST_F(LightsCli, GltfPunctualLightsAreImportedWhenTheProjectHasNone)
{
    const json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_lights_punctual"}},
        {"extensions",
         {{"KHR_lights_punctual",
           {{"lights", {{{"type", "point"}, {"name", "bulb"}, {"intensity", 8.0}, {"color", {1.0, 0.5, 0.25}}},
                        {{"type", "spot"}, {"intensity", 20.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}}}}}}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0, 1, 2}}}}},
        {"nodes",
         {{{"mesh", 0}},
          {{"name", "bulb node"}, {"translation", {0.0, 2.0, 0.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
          {{"translation", {1.0, 0.0, 0.0}}, {"children", {3}}},
          {{"name", "spot node"}, {"translation", {0.0, 3.0, 0.0}}, {"rotation", {-0.7071067811865476, 0.0, 0.0, 0.7071067811865476}},
           {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"buffers", {{{"byteLength", 60},
                      {"uri", "data:application/octet-stream;base64,AACgwAAAAAAAAKDAAACgQAAAAAAAAKDAAACgQAAAAAAAAKBAAACgwAAAAAAAAKBAAAACAAEAAAADAAIA"}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {-5, 0, -5}}, {"max", {5, 0, 5}}},
          {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}}};
    write("lit.gltf", gltf);
    json document = project(json::array());
    document.erase("lights");
    document["scene"] = "lit.gltf";
    write("p.json", document);
    const Project p = loadProject(folder / "p.json");
    bool fromScene = false;
    const std::vector<Light> lights = lightsToUse(p, &fromScene);
    EXPECT_TRUE(fromScene);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_EQ(lights[0].type, LightType::Point);
    EXPECT_EQ(lights[0].name, "bulb");
    EXPECT_EQ(lights[0].colour, glm::dvec3(1.0, 0.5, 0.25));
    EXPECT_LT(glm::length(lights[0].position - glm::dvec3(0, 2, 0)), 1e-12);
    EXPECT_EQ(lights[1].type, LightType::Spot);
    EXPECT_EQ(lights[1].name, "spot node");
    EXPECT_LT(glm::length(lights[1].position - glm::dvec3(1, 3, 0)), 1e-12);
    EXPECT_LT(glm::length(lights[1].direction - glm::dvec3(0, -1, 0)), 1e-6);
    EXPECT_EQ(lights[1].outerAngle, 0.6);

    std::vector<float> rows;
    for (int k = 0; k < 5; ++k)
        rows.insert(rows.end(), {float(0.5 * k), 0.01f, 0.0f, 0.0f, 1.0f, 0.0f});
    writeFloatNpy(rows, 5, 6, folder / "pts.npy");
    const CliRun run = runCli("lights " + (folder / "p.json").string() + " --points " + (folder / "pts.npy").string() +
                              " --npy " + (folder / "e.npy").string() + " --json");
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_NE(run.err.find("KHR_lights_punctual"), std::string::npos) << run.err;
    EXPECT_EQ(json::parse(run.out)["lights"], 2);
    const Npy e = readNpy(folder / "e.npy");
    const LightsJudge judge(scene());
    for (int k = 0; k < 5; ++k) {
        const ShadingPoint point{glm::dvec3(glm::vec3(float(0.5 * k), 0.01f, 0.0f)), {0.0, 1.0, 0.0}};
        const std::size_t at = 3 * std::size_t(k);
        EXPECT_TRUE(LightsJudge::agrees(judge.at(lights, point), {e.values[at], e.values[at + 1], e.values[at + 2]}, 1e-6)) << k;
    }
    // A "lights" key, even empty, is the designer's list: the scene's lights are not added.
    write("p.json", project(json::array()));
    EXPECT_TRUE(lightsToUse(loadProject(folder / "p.json")).empty());
}

TEST_F(LightsCli, IndirectReadsTheSurfacesTexturesForTheirAlbedos)
{
    // The room with every face in one material whose diffuse texture is a red texel: the bounce
    // is red alone. Its texture missing, the material's albedo is unknown and --albedo's grey
    // applies.
    static const char kRedPng[] = "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00\x01"
                                  "\x08\x02\x00\x00\x00\x90\x77\x53\xde\x00\x00\x00\x0c\x49\x44\x41\x54\x78\x9c\x63\xf8\xcf\xc0\x00"
                                  "\x00\x03\x01\x01\x00\xc9\xfe\x92\xef\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82";
    std::ofstream(folder / "red.png", std::ios::binary).write(kRedPng, sizeof kRedPng - 1);
    std::ofstream(folder / "room.mtl") << "newmtl painted\nmap_Kd red.png\n";
    std::ifstream room(folder / "room.obj");
    std::string line;
    std::ofstream textured(folder / "textured.obj");
    textured << "mtllib room.mtl\nvt 0.5 0.5\nusemtl painted\n";
    while (std::getline(room, line))
        if (line.rfind("f ", 0) == 0) {   // every corner takes the one vt
            std::istringstream corners(line.substr(2));
            textured << "f";
            for (std::string corner; corners >> corner;)
                textured << ' ' << corner << "/1";
            textured << '\n';
        } else {
            textured << line << '\n';
        }
    textured.close();
    json document = project(lights());
    document["scene"] = "textured.obj";
    write("p.json", document);
    const std::string base = "lights " + (folder / "p.json").string() + " --indirect 2000 --albedo 0.4 --json";
    const CliRun red = runCli(base);
    ASSERT_EQ(red.code, 0) << red.err;
    const json bounce = json::parse(red.out).at("indirect");
    EXPECT_GT(bounce["mean"][0].get<double>(), 0.0);
    EXPECT_EQ(bounce["mean"][1].get<double>(), 0.0);
    EXPECT_EQ(bounce["mean"][2].get<double>(), 0.0);
    fs::remove(folder / "red.png");
    const CliRun grey = runCli(base);
    ASSERT_EQ(grey.code, 0) << grey.err;
    EXPECT_NE(grey.err.find("red.png"), std::string::npos) << grey.err;   // said
    const json greyBounce = json::parse(grey.out).at("indirect");
    EXPECT_GT(greyBounce["mean"][1].get<double>(), 0.0);
}

TEST_F(LightsCli, IndirectAddsOneBounceOfVplsAndReportsItsError)
{
    write("p.json", project(lights()));
    const std::string base = "lights " + (folder / "p.json").string();
    const CliRun direct = runCli(base + " --npy " + (folder / "d.npy").string());
    ASSERT_EQ(direct.code, 0) << direct.err;
    const CliRun lit = runCli(base + " --indirect 3000 --albedo 0.4 --indirect-reference 128 --json --npy " + (folder / "i.npy").string());
    ASSERT_EQ(lit.code, 0) << lit.err;
    const json indirect = json::parse(lit.out).at("indirect");
    EXPECT_EQ(indirect["photons"], 3000);
    EXPECT_GT(indirect["vpls"].get<int>(), 500);   // photons that meet the floor, the table or the wall (the rest leave)
    EXPECT_GE(indirect["clamp_loss"].get<double>(), 0.0);
    // Against the gathering reference: the same mean bounce (the VPLs' noise is in the RMSE).
    const json reference = indirect["reference"];
    const double vplMean = (indirect["mean"][0].get<double>() + indirect["mean"][1].get<double>() + indirect["mean"][2].get<double>()) / 3.0;
    EXPECT_GT(reference["mean"].get<double>(), 0.0);
    EXPECT_NEAR(vplMean, reference["mean"].get<double>(), 0.15 * reference["mean"].get<double>());
    EXPECT_LT(reference["relative_rmse"].get<double>(), 1.0);
    // Direct plus a bounce: never less than the direct light alone, and more somewhere.
    const Npy d = readNpy(folder / "d.npy"), i = readNpy(folder / "i.npy");
    ASSERT_EQ(d.values.size(), i.values.size());
    int brighter = 0;
    for (std::size_t k = 0; k < d.values.size(); ++k) {
        EXPECT_GE(i.values[k], d.values[k] * (1.0f - 1e-6f)) << k;
        brighter += i.values[k] > d.values[k] * 1.001f;
    }
    EXPECT_GT(brighter, 100);
    // The same VPLs by shadow maps (--gl): the same count, a mean bounce within a few percent of
    // the exact VPLs' (the maps' tolerance), no clamp loss claimed.
    const CliRun byMaps = runCli(base + " --gl --gl-resolution 256 --indirect 3000 --albedo 0.4 --json");
    ASSERT_EQ(byMaps.code, 0) << byMaps.err;
    const json indirectGl = json::parse(byMaps.out).at("indirect");
    EXPECT_EQ(indirectGl["vpls"], indirect["vpls"]);
    EXPECT_TRUE(indirectGl["clamp_loss"].is_null());
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(indirectGl["mean"][c].get<double>(), indirect["mean"][c].get<double>(), 0.05 * indirect["mean"][c].get<double>());
    // The same seed gives the same answer; options of the bounce need it.
    const CliRun again = runCli(base + " --indirect 3000 --albedo 0.4 --npy " + (folder / "j.npy").string());
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(readAll(folder / "j.npy"), readAll(folder / "i.npy"));
    for (const std::string bad : {" --albedo 0.5", " --indirect 10 --albedo 1.5", " --indirect 10 --clamp -1", " --indirect 0"}) {
        const CliRun run = runCli(base + bad);
        EXPECT_NE(run.code, 0) << bad;
        EXPECT_TRUE(oneLine(run.err)) << bad << ": " << run.err;
    }
}

// --sets --json (docs/design.md §4): V from the project's saved camera, looking down at the room's
// middle; a spot over a pillar that the camera sees; a crate out of view and out of the cone.
TEST_F(LightsCli, SetsFollowTheContract)
{
    json document = project(json::array({{{"type", "spot"}, {"name", "over the pillar"}, {"position", {1.5, 3.0, -1.0}},
                                          {"direction", {0, -1, 0}}, {"outer_angle", 0.6}, {"intensity", 5}},
                                         {{"type", "point"}, {"position", {0, 1.5, 0}}}}));
    document["occluders"] = {{{"name", "pillar"}, {"mesh", "box"}, {"transform", {0.3, 0, 0, 0, 0, 1.6, 0, 0, 0, 0, 0.3, 0, 1.5, 0.81, -1.0, 1}}},
                             {{"name", "crate"}, {"mesh", "box"}, {"transform", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 9, 0.5, 9, 1}}}};
    document["editor"] = {{"camera", {{"target", {0.5, 0, -0.5}}, {"distance", 4.0}, {"yaw", 0.0}, {"pitch", -1.4}}}};
    write("p.json", document);
    const CliRun run = runCli("lights " + (folder / "p.json").string() + " --sets --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const json sets = json::parse(run.out).at("sets");
    ASSERT_EQ(sets.size(), 2u);
    EXPECT_EQ(sets[0]["light"], "over the pillar");
    EXPECT_EQ(sets[1]["light"], "light 1");
    // Instances: 0 the room (one OBJ), 1 the pillar, 2 the crate (info --json's instance_list).
    const auto list = [](const json& value) { return value.get<std::vector<std::uint32_t>>(); };
    EXPECT_EQ(list(sets[0]["V"]), (std::vector<std::uint32_t>{0, 1}));
    EXPECT_EQ(list(sets[0]["L"]), (std::vector<std::uint32_t>{0, 1}));
    EXPECT_EQ(list(sets[0]["I"]), (std::vector<std::uint32_t>{0, 1}));
    // The pillar shadows the floor, the room's table its floor too; the crate, out of the cone, nothing.
    EXPECT_EQ(list(sets[0]["S"]), (std::vector<std::uint32_t>{0, 1}));
    for (const json& entry : sets) {
        std::vector<std::uint32_t> both;
        const auto V = list(entry["V"]), L = list(entry["L"]);
        std::set_intersection(V.begin(), V.end(), L.begin(), L.end(), std::back_inserter(both));
        EXPECT_EQ(list(entry["I"]), both);
    }
    const auto bulbReaches = list(sets[1]["L"]);
    // The bulb reaches the room and the pillar, not the crate behind the wall.
    EXPECT_EQ(bulbReaches, (std::vector<std::uint32_t>{0, 1}));
    const CliRun bad = runCli("lights " + (folder / "p.json").string() + " --sets --npy " + (folder / "x.npy").string());
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("--sets"), std::string::npos) << bad.err;
}

// --texel: a light map over the level's charts, as an atlas .npy, a PNG and a glTF using it.
// A baked PVS serves O'Rorke's V (the row of the camera's cell) and bounds each light's L by the
// rows of the cells it stands in: L is then the unbounded L within those rows.
TEST_F(LightsCli, SetsServedByABakedPvs)
{
    json document = project(json::array({{{"type", "spot"}, {"name", "over the pillar"}, {"position", {1.5, 3.0, -1.0}},
                                          {"direction", {0, -1, 0}}, {"outer_angle", 0.6}, {"intensity", 5}},
                                         {{"type", "point"}, {"position", {0, 1.5, 0}}},
                                         {{"type", "directional"}, {"direction", {0.2, -1, 0.1}}, {"intensity", 1}}}));
    document["occluders"] = {{{"name", "pillar"}, {"mesh", "box"}, {"transform", {0.3, 0, 0, 0, 0, 1.6, 0, 0, 0, 0, 0.3, 0, 1.5, 0.81, -1.0, 1}}},
                             {{"name", "crate"}, {"mesh", "box"}, {"transform", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 9, 0.5, 9, 1}}}};
    document["editor"] = {{"camera", {{"target", {0.5, 0, -0.5}}, {"distance", 4.0}, {"yaw", 0.0}, {"pitch", -1.4}}}};
    document["pvs"] = {{"cells", {{{"min", {-1, 3, -2}}, {"max", {2, 4.5, 1}}}, {{"min", {-0.5, 1, -0.5}}, {"max", {0.5, 2, 0.5}}}}}};
    write("p.json", document);
    const std::string p = (folder / "p.json").string();
    const CliRun bake = runCli("pvs bake " + p + " --out " + (folder / "p.pvs").string() + " --json " + (folder / "p.pvs.json").string());
    ASSERT_EQ(bake.code, 0) << bake.err;
    const json baked = json::parse(std::ifstream(folder / "p.pvs.json"));
    const auto row = [&](int cell) {
        std::vector<std::uint32_t> instances;
        for (const json& o : baked["visible"][std::size_t(cell)])
            instances.push_back(baked["objects"][o.get<std::size_t>()]["instance"].get<std::uint32_t>());
        std::sort(instances.begin(), instances.end());
        return instances;
    };
    const CliRun plain = runCli("lights " + p + " --sets --json");
    const CliRun served = runCli("lights " + p + " --sets --json --pvs " + (folder / "p.pvs").string());
    ASSERT_EQ(plain.code, 0) << plain.err;
    ASSERT_EQ(served.code, 0) << served.err;
    const json a = json::parse(plain.out), b = json::parse(served.out);
    EXPECT_EQ(b["pvs"]["camera_cell"], 0);
    EXPECT_EQ(b["pvs"]["lights_served"], 2);   // the sun stands in no cell
    const auto list = [](const json& value) { return value.get<std::vector<std::uint32_t>>(); };
    const int cellOf[2] = {0, 1};
    for (std::size_t l = 0; l < 3; ++l) {
        EXPECT_EQ(list(b["sets"][l]["V"]), row(0)) << l;
        std::vector<std::uint32_t> expected = list(a["sets"][l]["L"]);
        if (l < 2) {
            const std::vector<std::uint32_t> bound = row(cellOf[l]);
            std::vector<std::uint32_t> within;
            std::set_intersection(expected.begin(), expected.end(), bound.begin(), bound.end(), std::back_inserter(within));
            expected = within;
        }
        EXPECT_EQ(list(b["sets"][l]["L"]), expected) << l;
        EXPECT_FALSE(list(b["sets"][l]["L"]).empty()) << l;
    }
    const CliRun bad = runCli("lights " + p + " --pvs " + (folder / "p.pvs").string());
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("--pvs needs --sets"), std::string::npos) << bad.err;
}

// The baked level's glTF carries its point, spot and directional lights (KHR_lights_punctual; the
// area light has no counterpart and is named in a note): a project on that file with no "lights"
// reads them back, and lights the receiver as the original lights less the area light do.
TEST_F(LightsCli, TheBakedGltfCarriesThePunctualLightsBack)
{
    write("p.json", project(lights()));
    const CliRun bake = runCli("lights " + (folder / "p.json").string() + " --texel 4 --json --lightmap " +
                               (folder / "lm.png").string() + " --gltf " + (folder / "lit.glb").string());
    ASSERT_EQ(bake.code, 0) << bake.err;
    EXPECT_EQ(json::parse(bake.out)["texel"]["gltf_lights"], 3);
    EXPECT_NE(bake.err.find("1 area lights have no KHR_lights_punctual counterpart"), std::string::npos) << bake.err;
    json back = project(lights());
    back.erase("lights");
    back["scene"] = "lit.glb";
    write("back.json", back);
    json punctual = lights();
    punctual.erase(0);   // the area light
    write("punctual.json", project(punctual));
    const CliRun read = runCli("lights " + (folder / "back.json").string() + " --json --npy " + (folder / "back.npy").string());
    ASSERT_EQ(read.code, 0) << read.err;
    EXPECT_EQ(json::parse(read.out)["lights"], 3);
    const CliRun direct = runCli("lights " + (folder / "punctual.json").string() + " --npy " + (folder / "direct.npy").string());
    ASSERT_EQ(direct.code, 0) << direct.err;
    const Npy a = readNpy(folder / "back.npy"), b = readNpy(folder / "direct.npy");
    ASSERT_EQ(a.values.size(), b.values.size());
    std::size_t lit = 0;
    for (std::size_t k = 0; k < a.values.size(); ++k) {
        EXPECT_NEAR(a.values[k], b.values[k], 1e-4 * std::max(1.0f, std::abs(b.values[k]))) << k;
        lit += b.values[k] > 0.0f;
    }
    EXPECT_GT(lit, a.values.size() / 2);
}

TEST_F(LightsCli, TexelBakesALightMapOnCharts)
{
    write("p.json", project(lights()));
    const std::string base = "lights " + (folder / "p.json").string();
    const CliRun run = runCli(base + " --texel 8 --json --npy " + (folder / "atlas.npy").string() + " --lightmap " +
                              (folder / "lm.png").string() + " --gltf " + (folder / "lit.glb").string());
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    const json texel = out.at("texel");
    const int width = texel["atlas"][0], height = texel["atlas"][1];
    // The floor, the table's slab and the wall's two pieces (each two faces' worth of charts:
    // one chart per connected coplanar set, here one per rectangle).
    EXPECT_EQ(texel["charts"], 4);
    EXPECT_EQ(out["points"], texel["texels"]);
    const Npy atlas = readNpy(folder / "atlas.npy");
    ASSERT_EQ(atlas.shape, (std::vector<std::size_t>{std::size_t(height), std::size_t(width), 3}));
    std::size_t filled = 0, lit = 0;
    for (std::size_t px = 0; px < atlas.values.size() / 3; ++px)
        if (std::isfinite(atlas.values[3 * px])) {
            ++filled;
            EXPECT_GE(atlas.values[3 * px], 0.0f);
            lit += atlas.values[3 * px] > 0.0f;
        }
    EXPECT_EQ(filled, texel["texels"].get<std::size_t>());
    EXPECT_GT(lit, filled / 4);
    // The PNG's texels are dilated into the gutters: a pixel without a texel next to a lit texel
    // is not black (an engine's mip maps would darken the charts' edges).
    const RgbImage png = loadRgbImage(folder / "lm.png");
    ASSERT_EQ(png.width, width);
    ASSERT_EQ(png.height, height);
    std::size_t gutters = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t px = std::size_t(y) * std::size_t(width) + std::size_t(x);
            if (std::isfinite(atlas.values[3 * px]))
                continue;
            bool nextToLit = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    const std::size_t q = std::size_t(ny) * std::size_t(width) + std::size_t(nx);
                    nextToLit = nextToLit || (nx >= 0 && ny >= 0 && nx < width && ny < height && atlas.values[3 * q] > 0.01f);
                }
            if (nextToLit) {
                ++gutters;
                EXPECT_GT(png.pixels[px].r + png.pixels[px].g + png.pixels[px].b, 0.0f) << x << ", " << y;
            }
        }
    EXPECT_GT(gutters, 0u);
    const std::string glb = readAll(folder / "lit.glb");
    EXPECT_NE(glb.find("TEXCOORD_1"), std::string::npos);
    EXPECT_NE(glb.find("emissiveTexture"), std::string::npos);
    EXPECT_NE(glb.find("lm.png"), std::string::npos);
    for (const std::string bad : {" --lightmap x.png", " --texel 8 --points p.npy", " --texel 8 --gltf x.glb", " --texel 1e9",
                                  " --texel nan", " --texel 0"}) {
        const CliRun refused = runCli(base + bad);
        EXPECT_NE(refused.code, 0) << bad;
        EXPECT_TRUE(oneLine(refused.err)) << bad << ": " << refused.err;
    }
}

// --drag: frames of one light moving, each refreshing that light alone, exact at the end.
TEST_F(LightsCli, DragTimesOneLightMovingAndEndsExact)
{
    write("p.json", project(lights()));
    const CliRun run = runCli("lights " + (folder / "p.json").string() + " --drag 5 --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const json drag = json::parse(run.out).at("drag");
    EXPECT_EQ(drag["frames"], 5);
    EXPECT_EQ(drag["light"], "lamp");   // the first point or spot light
    EXPECT_TRUE(drag["exact"].get<bool>());
    EXPECT_LT(drag["max_relative_difference"].get<double>(), 1e-5);
    EXPECT_GT(drag["median_ms"].get<double>(), 0.0);
    write("sun.json", project(json::array({{{"type", "directional"}, {"direction", {0, -1, 0}}}})));
    const CliRun none = runCli("lights " + (folder / "sun.json").string() + " --drag 5");
    EXPECT_EQ(none.code, 1);
    EXPECT_NE(none.err.find("--drag needs a point or spot light"), std::string::npos) << none.err;
}
