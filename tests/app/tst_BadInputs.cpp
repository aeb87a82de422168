// Every bad input gets a clear one-line error naming the file and what is wrong; never a
// hang, a crash, a wrong answer, lost data or runaway memory. One case per category, run through
// the CLI (and the editor's headless front end) as a user would.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"

using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& words) { return text.find(words) != std::string::npos; }

class BadInputs : public ::testing::Test {
protected:
    fs::path folder;   // the test's scratch space; projects live in folder / "project"
    fs::path projectFolder;

    void SetUp() override
    {
        folder = uniqueFolder();
        fs::remove_all(folder);
        projectFolder = folder / "project";
        fs::create_directories(projectFolder);
        writeWallWithHoleObj(projectFolder / "wall.obj");
        writeWallWithHoleObj(folder / "outside.obj");
    }
    void TearDown() override { fs::remove_all(folder); }

    json project(const std::string& scene = "wall.obj") const
    {
        return {{"version", 1},
                {"scene", scene},
                {"source", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}, {"samples", {8, 4}}}},
                {"receiver", {{"corner", {-0.5, -0.2, 4}}, {"u", {2, 0, 0.3}}, {"v", {0, 1.4, 0}}, {"samples", {8, 8}}}}};
    }
    fs::path write(const json& document, const std::string& name = "p.json") const
    {
        const fs::path file = projectFolder / name;
        std::ofstream(file) << document.dump(2);
        return file;
    }
};

void expectRefused(const CliRun& run, const std::string& command, std::initializer_list<const char*> words)
{
    EXPECT_EQ(run.code, 1) << command << " -> " << run.err;
    EXPECT_TRUE(oneLine(run.err)) << command << " -> [" << run.err << "]";
    for (const char* w : words)
        EXPECT_TRUE(contains(run.err, w)) << command << ": expected '" << w << "' in: " << run.err;
}

} // namespace

// Category: only regular files are read (a FIFO blocks forever, a folder fails deep in iostreams).
TEST_F(BadInputs, AProjectThatIsNotARegularFileIsRefusedAtOnce)
{
    const fs::path fifo = projectFolder / "fifo.json";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string fifoCommand = "shaft " + fifo.string();
    expectRefused(runCli(fifoCommand, 30), fifoCommand, {"fifo.json", "FIFO"});

    const fs::path dir = projectFolder / "folder.json";
    fs::create_directories(dir);
    const std::string dirCommand = "info " + dir.string();
    const CliRun run = runCli(dirCommand, 30);
    expectRefused(run, dirCommand, {"folder.json", "a folder"});
    EXPECT_FALSE(contains(run.err, "basic_filebuf")) << run.err;
}

TEST_F(BadInputs, FilesAProjectNamesMustBeRegularFilesToo)
{
    // receiver heights from a FIFO (.npy) and a light texture that is a folder.
    ASSERT_EQ(::mkfifo((projectFolder / "heights.npy").c_str(), 0600), 0);
    json heights = project();
    heights["receiver_heights"] = {{"npy", "heights.npy"}};
    const std::string heightsCommand = "shaft " + write(heights).string();
    expectRefused(runCli(heightsCommand, 30), heightsCommand, {"heights.npy", "FIFO"});

    fs::create_directories(projectFolder / "light.png");
    json light = project();
    light["light"] = {{"texture", "light.png"}};
    const std::string lightCommand =
        "shadow " + write(light, "light.json").string() + " --out " + (folder / "shadow.png").string();
    expectRefused(runCli(lightCommand, 30), lightCommand, {"light.png", "a folder"});
}

// Category: relative paths in a project stay inside its folder unless the user allows otherwise.
TEST_F(BadInputs, RelativePathsThatLeaveTheProjectsFolderAreRefused)
{
    const std::string escape = "shaft " + write(project("../outside.obj")).string();
    expectRefused(runCli(escape), escape, {"p.json", "scene '../outside.obj'", "leaves the project's folder",
                                           "--allow-outside-paths"});
    EXPECT_EQ(runCli(escape + " --allow-outside-paths").code, 0) << "the explicit option allows it";
    const CliRun absolute = runCli("shaft " + write(project((folder / "outside.obj").string()), "absolute.json").string());
    EXPECT_EQ(absolute.code, 0) << "an absolute path is taken as written: " << absolute.err;

    // Through a symlink inside the folder that points out of it.
    fs::create_symlink(folder / "outside.obj", projectFolder / "linked.obj");
    const std::string linked = "info " + write(project("linked.obj"), "linked.json").string();
    expectRefused(runCli(linked), linked, {"scene 'linked.obj'", "leaves the project's folder"});

    // An occluder mesh, and a light texture (every path a project names goes through one rule).
    json occluder = project();
    occluder["occluders"] = {{{"name", "crate"}, {"mesh", "../outside.obj"}}};
    const std::string occluderCommand = "shaft " + write(occluder, "occluder.json").string();
    expectRefused(runCli(occluderCommand), occluderCommand, {"occluder 'crate' mesh '../outside.obj'", "leaves"});
    json light = project();
    light["light"] = {{"texture", "../../etc/light.png"}};
    const std::string lightCommand =
        "shadow " + write(light, "light.json").string() + " --out " + (folder / "shadow.png").string();
    expectRefused(runCli(lightCommand), lightCommand, {"light.texture '../../etc/light.png'", "leaves"});
}

// Category: options within their range whose cost cannot fit are refused before allocating,
// saying the cost.
TEST_F(BadInputs, AHoughTableTooLargeForTheSourceIsRefusedWithItsCost)
{
    json big = project();
    big["source"]["samples"] = {32, 32};
    const std::string command = "shaft " + write(big).string() + " --method cpu --mode table --table 8192 8192";
    expectRefused(runCli(command, 60), command, {"--table 8192 8192", "1024 source samples", "8.0 GiB", "limit"});
    // The same table for few samples fits.
    EXPECT_EQ(runCli("shaft " + write(project(), "small.json").string() + " --method cpu --mode table --table 512 256").code, 0);
}

TEST_F(BadInputs, AShadowImageTooLargeIsRefusedWithItsCost)
{
    json big = project();
    big["receiver"]["samples"] = {1024, 1024};
    const std::string command = "shadow " + write(big).string() + " --scale 64 --out " + (folder / "s.png").string();
    expectRefused(runCli(command, 60), command, {"--scale 64", "65536x65536", "GB"});
}

TEST_F(BadInputs, AScreenshotTooLargeIsRefusedWithItsCost)
{
    const fs::path editor = fs::path(SIGHTLINE_CLI).parent_path() / "sightline";
    if (!fs::exists(editor))
        GTEST_SKIP() << "the editor is not built: " << editor;
    const std::string command =
        "--screenshot " + (folder / "s.png").string() + " --size 16384x16384 " + write(project()).string();
    const CliRun run = runProgram(editor.string(), command, 60);
    EXPECT_EQ(run.code, 2) << run.err;
    EXPECT_TRUE(oneLine(run.err)) << run.err;
    EXPECT_TRUE(contains(run.err, "16384x16384") && contains(run.err, "GB") && contains(run.err, "8192"))
        << run.err;
    EXPECT_FALSE(fs::exists(folder / "s.png"));
}

// Category: messages quote what the user wrote, not what a conversion made of it.
TEST_F(BadInputs, SampleCountsBeyondSixtyFourBitsAreQuotedAsWritten)
{
    const fs::path file = projectFolder / "p.json";
    std::string text = project().dump();
    const std::string from = "\"samples\":[8,4]";
    ASSERT_NE(text.find(from), std::string::npos) << text;
    text.replace(text.find(from), from.size(), "\"samples\":[9223372036854775808,1]");
    std::ofstream(file) << text;
    const std::string command = "shaft " + file.string();
    const CliRun run = runCli(command);
    expectRefused(run, command, {"source.samples", "9223372036854775808"});
    EXPECT_FALSE(contains(run.err, "-9223372036854775808")) << run.err;
}

// Category: JSON output never fails on names that are not UTF-8, and never after side files.
TEST_F(BadInputs, JsonOutputSurvivesFileNamesThatAreNotUtf8)
{
    const fs::path scene = projectFolder / "wall\xff.obj";
    fs::copy_file(projectFolder / "wall.obj", scene);
    const CliRun info = runCli("info '" + scene.string() + "' --json");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_TRUE(json::accept(info.out)) << info.out;

    const fs::path mask = folder / "mask\xff.npy";
    const CliRun shaft = runCli("shaft " + write(project()).string() + " --json --mask '" + mask.string() + "'");
    ASSERT_EQ(shaft.code, 0) << shaft.err;
    EXPECT_TRUE(json::accept(shaft.out)) << shaft.out;
    EXPECT_TRUE(fs::exists(mask));
}

// Category: lost data. An output naming an input of the same run (or another output) replaced it
// with a silent success: `shaft p.json --mask p.json` turned the project into a .npy, `importance
// --out wall.obj` the level into a PNG, `--out m.png --npy m.png` kept only the .npy.
TEST_F(BadInputs, AnOutputNeverReplacesAnInputOrAnotherOutput)
{
    const fs::path file = write(project());
    auto bytes = [](const fs::path& f) {
        std::stringstream text;
        text << std::ifstream(f, std::ios::binary).rdbuf();
        return text.str();
    };
    const std::string projectBytes = bytes(file), sceneBytes = bytes(projectFolder / "wall.obj");
    const std::string p = file.string(), wall = (projectFolder / "wall.obj").string();
    // Through another spelling and a symlink too: the same file, not the same string.
    fs::create_symlink(projectFolder / "wall.obj", folder / "link.obj");
    const std::string dotted = (projectFolder / "." / "p.json").string();
    const std::pair<std::string, std::vector<const char*>> cases[] = {
        {"shaft " + p + " --mask " + p, {"--mask", "would replace the project", "choose another file"}},
        {"shaft " + p + " --mask " + dotted, {"--mask", "the project"}},
        {"shaft " + p + " --mask " + wall, {"--mask", "the scene"}},
        {"importance " + p + " --out " + wall, {"--out", "the scene"}},
        {"importance " + p + " --out " + (folder / "link.obj").string(), {"--out", "the scene"}},
        {"shadow " + p + " --out " + p, {"--out", "the project"}},
        {"shadow " + p + " --out " + (folder / "s.png").string() + " --npy " + p, {"--npy", "the project"}},
        {"importance " + p + " --out " + (folder / "m.png").string() + " --npy " + (folder / "m.png").string(),
         {"--out and --npy both name", "m.png"}},
        {"ao " + wall + " --ply " + wall, {"--ply", "the mesh"}},
        {"ao " + p + " --npy " + wall, {"--npy", "the scene"}},
        {"bench " + p + " --methods raycast --sources 32 --receivers 32 --repeat 1 --csv " + p, {"--csv", "the project"}},
        {"pvs bake " + p + " --out " + p, {"--out", "the project"}},
        {"pvs bake " + p + " --out " + (folder / "r.pvs").string() + " --prt " + wall, {"--prt", "the scene"}},
        {"pvs bake " + p + " --out " + (folder / "r.pvs").string() + " --json " + (folder / "r.pvs").string(),
         {"--out and --json both name"}},
        {"pvs merge " + p + " --out " + p, {"--out", "the part file"}},
        {"pvs check " + p + " " + (folder / "r.pvs").string() + " --gaps " + p, {"--gaps", "the project"}},
    };
    for (const auto& [command, words] : cases) {
        const CliRun run = runCli(command, 120);
        EXPECT_EQ(run.code, 1) << command << " -> " << run.err;
        EXPECT_TRUE(oneLine(run.err)) << command << " -> [" << run.err << "]";
        for (const char* w : words)
            EXPECT_TRUE(contains(run.err, w)) << command << ": expected '" << w << "' in: " << run.err;
        EXPECT_EQ(bytes(file), projectBytes) << command;
        EXPECT_EQ(bytes(projectFolder / "wall.obj"), sceneBytes) << command;
    }
    EXPECT_FALSE(fs::exists(folder / "m.png"));
    EXPECT_FALSE(fs::exists(folder / "s.png"));
    EXPECT_FALSE(fs::exists(folder / "r.pvs"));

    // The editor's headless outputs too: `sightline --screenshot p.json p.json` replaced the project.
    const fs::path editor = fs::path(SIGHTLINE_CLI).parent_path() / "sightline";
    if (fs::exists(editor))
        for (const std::string& output : {p, dotted, wall}) {
            const std::string command = "--screenshot " + output + " " + p;
            const CliRun run = runProgram(editor.string(), command, 60);
            EXPECT_EQ(run.code, 1) << command << " -> " << run.err;
            EXPECT_TRUE(oneLine(run.err)) << command << " -> [" << run.err << "]";
            EXPECT_TRUE(contains(run.err, "--screenshot ") && contains(run.err, "would replace")) << run.err;
            EXPECT_EQ(bytes(file), projectBytes) << command;
            EXPECT_EQ(bytes(projectFolder / "wall.obj"), sceneBytes) << command;
        }

    // An empty file name is refused, not taken for "no mask".
    const CliRun empty = runCli("shaft " + p + " --mask ''");
    EXPECT_EQ(empty.code, 2) << empty.err;
    EXPECT_TRUE(contains(empty.err, "--mask") && contains(empty.err, "empty file name")) << empty.err;
}

// Category: light-map densities and environment images are checked before any work.
TEST_F(BadInputs, TexelDensitiesOutsideTheirRangeAreRefused)
{
    const std::string p = write(project()).string();
    const std::string map = (folder / "map.png").string();
    for (const char* density : {"nan", "1e308", "inf", "1001", "0"}) {
        for (const std::string& command : {"lights " + p + " --texel " + density + " --lightmap " + map,
                                          "ao " + p + " --texel " + density + " --lightmap " + map}) {
            const CliRun run = runCli(command, 60);
            EXPECT_NE(run.code, 0) << command;
            EXPECT_TRUE(oneLine(run.err)) << command << " -> [" << run.err << "]";
            EXPECT_TRUE(contains(run.err, "(0, 1000]")) << command << ": " << run.err;
        }
    }
    EXPECT_FALSE(fs::exists(map));
}

TEST_F(BadInputs, AnEnvironmentThatWouldHangOrAllocateGigabytesIsRefused)
{
    const std::string p = write(project()).string();
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
    // A run-length count of 0 (stb's decoder never ends), a header alone, a header declaring 16384x8192.
    std::ofstream(folder / "zero.hdr", std::ios::binary) << header << "-Y 4 +X 8\n" << std::string{2, 2, 0, 8, 0} << std::string(60, '\0');
    std::ofstream(folder / "empty.hdr", std::ios::binary) << header << "-Y 4 +X 8\n";
    std::ofstream(folder / "huge.hdr", std::ios::binary) << header << "-Y 8192 +X 16384\n";
    const std::pair<const char*, const char*> cases[] = {{"zero.hdr", "run of 0"}, {"empty.hdr", "truncated"}, {"huge.hdr", "Mpixels"}};
    for (const auto& [file, says] : cases) {
        const std::string command = "ao " + p + " --env " + (folder / file).string();
        expectRefused(runCli(command, 60), command, {file, says});
    }
}

// Category: running out of memory while reading a project is one line, never an abort. nlohmann's
// destructor allocates as it frees a huge array; the reader frees such a DOM without allocating.
TEST_F(BadInputs, AProjectTooLargeForMemoryIsOneLineNotAnAbort)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the address sanitizer reserves more address space than the limit below";
#else
    std::string document = project().dump();
    document.pop_back();
    document += R"(,"recorded_path":{"fps":30,"frames":10,"edits":[)";
    const std::string key = R"({"frame":0,"object":"receiver","corner":[0,1,8],"u":[1,0,0],"v":[0,0,1]})";
    document.reserve(document.size() + 1'000'000 * (key.size() + 1) + 4);
    for (int k = 0; k < 1'000'000; ++k)
        document += (k ? "," : "") + key;
    document += "]}}";
    const fs::path file = projectFolder / "huge.json";
    std::ofstream(file) << document;
    document.clear();
    // 800 MB of address space: the program loads, the million keys' DOM (about 1 GB) does not fit.
    for (const std::string& arguments : {"shaft " + file.string(), "importance " + file.string() + " --path --out " +
                                                                      (folder / "i.png").string()}) {
        const CliRun run = runProgram("ulimit -v 800000; " + std::string(SIGHTLINE_CLI), arguments);
        expectRefused(run, arguments, {"out of memory while running"});
    }
#endif
}
