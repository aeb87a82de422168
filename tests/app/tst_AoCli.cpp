// sightline-cli ao (docs/design.md §4) run as a user does: the .npy contract (float32,
// shape (V,), NaN for vertices of no face), --json's keys, the engine files (glTF COLOR_0, PLY
// colours, texel-mode light map with TEXCOORD_1), environments, and one-line errors for bad input.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"

using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

class AoCli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        // A floor with an open box 5 cm above it (OBJ; no vertex lies on another surface, where
        // rays would be ties), and a vertex of no face (the last one).
        std::ofstream(folder / "room.obj") << "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"
                                              "v -0.5 0.05 -0.5\nv 0.5 0.05 -0.5\nv 0.5 1 -0.5\nv -0.5 1 -0.5\n"
                                              "v -0.5 0.05 0.5\nv 0.5 0.05 0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
                                              "v 9 9 9\n"
                                              "f 1 3 2\nf 1 4 3\n"
                                              "f 5 8 7\nf 5 7 6\nf 9 10 11\nf 9 11 12\nf 6 7 11\nf 6 11 10\n"
                                              "f 5 9 12\nf 5 12 8\nf 8 12 11\nf 8 11 7\n";
    }
    std::string room() const { return (folder / "room.obj").string(); }
};

} // namespace

TEST_F(AoCli, NpyAndJsonFollowTheContract)
{
    const CliRun run = runCli("ao " + room() + " --k 66 --npy " + (folder / "ao.npy").string() + " --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["k"], 66);
    EXPECT_EQ(out["vertices"], 13);
    EXPECT_TRUE(out["ms"].is_number());
    EXPECT_EQ(out["no_face"], 1);
    EXPECT_NE(run.err.find("1 vertices belong to no face"), std::string::npos) << run.err;
    const Npy npy = readNpy(folder / "ao.npy");
    ASSERT_EQ(npy.shape, std::vector<std::size_t>{13});
    ASSERT_EQ(npy.values.size(), 13u);
    EXPECT_TRUE(std::isnan(npy.values[12]));
    for (int i = 0; i < 12; ++i) {
        EXPECT_GE(npy.values[std::size_t(i)], 0.0f);
        EXPECT_LE(npy.values[std::size_t(i)], 1.0f);
    }
    // The floor's far corners see more sky than the box's foot.
    EXPECT_GT(npy.values[0], npy.values[4]);
    EXPECT_LT(npy.values[4], 0.9f);
    // The Embree baseline answers the same question.
    const CliRun embree = runCli("ao " + room() + " --k 66 --method embree --npy " + (folder / "e.npy").string());
    ASSERT_EQ(embree.code, 0) << embree.err;
    const Npy e = readNpy(folder / "e.npy");
    for (int i = 0; i < 12; ++i)
        EXPECT_NEAR(e.values[std::size_t(i)], npy.values[std::size_t(i)], 0.02f);
    // The GL mode says what its depth maps drew: the room's box and floor cannot be simplified
    // within a quarter texel without moving them, so every triangle.
    const CliRun gl = runCli("ao " + room() + " --k 18 --method gl --gl-resolution 256 --json");
    ASSERT_EQ(gl.code, 0) << gl.err;
    const json maps = json::parse(gl.out).at("gl");
    EXPECT_EQ(maps["resolution"], 256);
    EXPECT_GT(maps["texel_m"].get<double>(), 0.0);
    EXPECT_EQ(maps["drawn_triangles"], json::parse(gl.out)["triangles"]);
    EXPECT_LE(maps["simplification_m"].get<double>(), 0.25 * maps["texel_m"].get<double>());
}

TEST_F(AoCli, ProjectsGiveEveryInstanceInOrder)
{
    const json project = {{"version", 1},
                          {"scene", "room.obj"},
                          {"source", {{"corner", {0, 1, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}, {"samples", {4, 4}}}},
                          {"receiver", {{"corner", {0, 1, 8}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}, {"samples", {4, 4}}}},
                          {"occluders", {{{"name", "crate"}, {"mesh", "box"},
                                          {"transform", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1.2, 0.6, 1.2, 1}}}}}};
    std::ofstream(folder / "p.json") << project.dump();
    const CliRun run = runCli("ao " + (folder / "p.json").string() + " --k 18 --json --npy " + (folder / "p.npy").string());
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_EQ(json::parse(run.out)["vertices"], 13 + 8);   // the scene's vertices, then the crate's
    const Npy npy = readNpy(folder / "p.npy");
    ASSERT_EQ(npy.shape, std::vector<std::size_t>{21});
    EXPECT_TRUE(std::isnan(npy.values[12]));   // the room's vertex of no face keeps its place
    for (std::size_t i = 13; i < 21; ++i)
        EXPECT_FALSE(std::isnan(npy.values[i])) << i;
}

TEST_F(AoCli, BunnyHasNaNForItsVerticesOfNoFace)
{
    const fs::path bunny = fs::path(SIGHTLINE_TEST_DATA) / "meshes" / "bun_zipper.ply";
    const CliRun run = runCli("ao " + bunny.string() + " --k 18 --npy " + (folder / "b.npy").string() + " --json");
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_EQ(json::parse(run.out)["vertices"], 35947);
    const Npy npy = readNpy(folder / "b.npy");
    ASSERT_EQ(npy.shape, std::vector<std::size_t>{35947});
    std::size_t nan = 0;
    for (float v : npy.values)
        nan += std::isnan(v);
    EXPECT_EQ(nan, 1113u);
}

TEST_F(AoCli, WritesGltfWithColoursPlyAndATexelLightMap)
{
    const CliRun run = runCli("ao " + room() + " --k 18 --gltf " + (folder / "ao.glb").string() + " --ply " +
                              (folder / "ao.ply").string());
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_NE(readAll(folder / "ao.glb").find("COLOR_0"), std::string::npos);
    const std::string ply = readAll(folder / "ao.ply");
    EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    EXPECT_NE(ply.find("property uchar red"), std::string::npos);
    // The glTF reads back through Sightline's own importer: 13 vertices, 12 triangles.
    const CliRun info = runCli("info " + (folder / "ao.glb").string() + " --json");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_EQ(json::parse(info.out)["triangles"], 12);

    const CliRun texel = runCli("ao " + room() + " --k 18 --texel 8 --lightmap " + (folder / "lm.png").string() +
                                " --gltf " + (folder / "lm.glb").string() + " --npy " + (folder / "lm.npy").string() + " --json");
    ASSERT_EQ(texel.code, 0) << texel.err;
    const json out = json::parse(texel.out);
    EXPECT_EQ(out["mode"], "texel");
    const std::string png = readAll(folder / "lm.png");
    EXPECT_EQ(png.compare(0, 4, "\x89PNG"), 0);
    const std::string glb = readAll(folder / "lm.glb");
    EXPECT_NE(glb.find("TEXCOORD_1"), std::string::npos);
    EXPECT_NE(glb.find("occlusionTexture"), std::string::npos);
    EXPECT_NE(glb.find("lm.png"), std::string::npos);
    const Npy atlas = readNpy(folder / "lm.npy");
    ASSERT_EQ(atlas.shape.size(), 2u);
    EXPECT_EQ(atlas.shape[1], std::size_t(out["texel"]["atlas"][0]));
    // Texels in the floor's contact shadow beside the box are darker than open floor.
    float lo = 1.0f, hi = 0.0f;
    for (float v : atlas.values)
        if (!std::isnan(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    EXPECT_LT(lo, 0.7f);
    EXPECT_GT(hi, 0.9f);
}

TEST_F(AoCli, EnvironmentLightsTheColours)
{
    {
        std::ofstream f(folder / "sky.hdr", std::ios::binary);
        f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n";
        for (int i = 0; i < 128; ++i)
            f.write("\x80\x80\x80\x81", 4);   // radiance 1 everywhere
    }
    const CliRun run = runCli("ao " + room() + " --k 18 --env " + (folder / "sky.hdr").string() +
                              " --rotate 30 --exposure -1 --json --ply " + (folder / "e.ply").string());
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["env"]["rotate"], 30.0);
    EXPECT_TRUE(out["env"]["relight_ms"].is_number());
}

TEST_F(AoCli, BadInputGetsOneLineErrors)
{
    auto expectError = [](const CliRun& run, const std::string& words) {
        EXPECT_NE(run.code, 0);
        EXPECT_TRUE(oneLine(run.err)) << run.err;
        EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
    };
    expectError(runCli("ao " + room() + " --k 100"), "6, 18, 66, 258 or 1026");
    std::ofstream(folder / "empty.obj") << "# nothing\n";
    expectError(runCli("ao " + (folder / "empty.obj").string()), "no triangles");
    expectError(runCli("ao " + room() + " --env " + (folder / "missing.hdr").string()), "missing.hdr");
    std::ofstream(folder / "fake.hdr") << "P3\n1 1\n255\n0 0 0\n";
    expectError(runCli("ao " + room() + " --env " + (folder / "fake.hdr").string()), "not a Radiance HDR");
    expectError(runCli("ao " + room() + " --rotate 30"), "--env");
    expectError(runCli("ao " + room() + " --texel 4 --ply x.ply"), "--ply");
    expectError(runCli("ao " + room() + " --threads 2 --method gl"), "--threads");
    expectError(runCli("ao " + room() + " --gl-simplify 0.5"), "--gl-simplify");   // cpu, the default
    expectError(runCli("ao " + room() + " --method gl --gl-simplify 2"), "--gl-simplify");
    expectError(runCli("ao " + room() + " --texel 1000 --lightmap x.png"), "light map");   // the atlas limit
    expectError(runCli("ao " + room() + " --texel 100000 --lightmap x.png"), "(0, 1000]");   // the density range
}
