#pragma once
// Runs sightline-cli as a user does (a child process), and the scenes and projects the app tests share.
#include <array>
#include <cstdint>
#include <cstring>
#include <regex>
#include <vector>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "TestScenes.h"
#include "plugins/SceneFormats.h"

namespace sightline::test {

namespace fs = std::filesystem;

struct CliRun {
    int code = -1;
    std::string out, err;
};

/// ctest runs tests in parallel processes: each gets its own folder.
inline fs::path uniqueFolder()
{
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    return fs::temp_directory_path() / ("sightline_cli_" + std::string(test->name()) + "_" + std::to_string(getpid()));
}

/// Runs `program` (the CLI by default) with `arguments`. With `timeoutSeconds`, a run that hangs
/// is killed and returns code 124, so that a test of "never blocks" fails instead of hanging.
inline CliRun runProgram(const std::string& program, const std::string& arguments, int timeoutSeconds = 0)
{
    const fs::path errFile = uniqueFolder() / "stderr.txt";
    const std::string prefix = timeoutSeconds > 0 ? "timeout -k 5 " + std::to_string(timeoutSeconds) + " " : "";
    const std::string command = prefix + program + " " + arguments + " 2>" + errFile.string();
    CliRun run;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe)
        return run;
    std::array<char, 4096> buffer{};
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
        run.out.append(buffer.data(), n);
    const int status = pclose(pipe);
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::stringstream err;
    err << std::ifstream(errFile).rdbuf();
    run.err = err.str();
    return run;
}

inline CliRun runCli(const std::string& arguments, int timeoutSeconds = 0)
{
    return runProgram(SIGHTLINE_CLI, arguments, timeoutSeconds);
}

inline bool oneLine(const std::string& s) { return !s.empty() && s.find('\n') == s.size() - 1; }

/// A failed run that said why in one line holding `words`.
inline void expectOneLineError(const CliRun& run, const std::string& words)
{
    EXPECT_NE(run.code, 0);
    EXPECT_TRUE(oneLine(run.err)) << run.err;
    EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
}

/// A test with a fresh folder of its own (removed after it), and the CLI's JSON answers parsed.
class CliFolderTest : public ::testing::Test {
protected:
    fs::path folder;

    void SetUp() override
    {
        folder = uniqueFolder();
        fs::remove_all(folder);
        fs::create_directories(folder);
    }
    void TearDown() override { fs::remove_all(folder); }

    /// Runs the CLI, expects success, and parses its stdout (an empty object on failure).
    nlohmann::json runJson(const std::string& arguments)
    {
        const CliRun run = runCli(arguments);
        EXPECT_EQ(run.code, 0) << arguments << ": " << run.err;
        return run.code == 0 ? nlohmann::json::parse(run.out) : nlohmann::json::object();
    }
    std::string path(const std::string& name) const { return (folder / name).string(); }
};

/// The app tests' scene: a 3 x 2 m wall at z = 2 with a 1 m square hole over [0, 1]^2 (OBJ).
inline void writeWallWithHoleObj(const fs::path& file)
{
    std::ofstream(file) << "v -1 -0.5 2\nv 2 -0.5 2\nv 2 1.5 2\nv -1 1.5 2\n"
                           "v 0 0 2\nv 1 0 2\nv 1 1 2\nv 0 1 2\n"
                           "f 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
}

/// The app tests' project on that wall: a 16 x 8 source before it, a 24 x 20 receiver 4 m out and
/// a box occluder ("crate") in the hole's lower half.
inline nlohmann::json crateInWallProject()
{
    return {
        {"version", 1},
        {"scene", "wall.obj"},
        {"source", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}, {"samples", {16, 8}}}},
        {"receiver", {{"corner", {-0.5, -0.2, 4}}, {"u", {2, 0, 0.3}}, {"v", {0, 1.4, 0}}, {"samples", {24, 20}}}},
        {"occluders", {{{"name", "crate"}, {"mesh", "box"},
                        {"transform", {0.4, 0, 0, 0, 0, 0.3, 0, 0, 0, 0, 0.4, 0, 0.5, 0.15, 2.2, 1}}}}},
    };
}

/// A lumpy closed torus of 18,432 triangles standing across the view, 2 m from each patch
/// (`folder`/torus.glb), and the project `name` on it in `folder`: the coarse occluders' scene.
inline void writeTorusProject(const fs::path& folder, const std::string& name)
{
    Scene level;
    level.addMeshInstance(closedTorus({0.5, 0.5, 2.0}, 0.6, 0.25, 192, 48, 0.15));
    saveScene(level, folder / "torus.glb");
    const nlohmann::json project = {
        {"version", 1},
        {"scene", "torus.glb"},
        {"source", {{"corner", {-0.5, -0.5, 0}}, {"u", {2, 0, 0}}, {"v", {0, 2, 0}}, {"samples", {32, 32}}}},
        {"receiver", {{"corner", {-0.3, -0.4, 4}}, {"u", {1.8, 0, 0.2}}, {"v", {0, 1.8, 0}}, {"samples", {32, 32}}}}};
    std::ofstream(folder / name) << project.dump(2);
}

inline std::string readAll(const fs::path& file)
{
    std::stringstream s;
    s << std::ifstream(file, std::ios::binary).rdbuf();
    return s.str();
}

/// A float32 .npy's shape and values (the test's own small reader: header text, then data).
struct Npy {
    std::vector<std::size_t> shape;
    std::vector<float> values;
};

inline Npy readNpy(const fs::path& file)
{
    const std::string bytes = readAll(file);
    Npy npy;
    if (bytes.size() < 10 || bytes.compare(0, 6, "\x93NUMPY") != 0)
        return npy;
    const std::size_t headerLength = std::size_t(std::uint8_t(bytes[8])) | std::size_t(std::uint8_t(bytes[9])) << 8;
    const std::string header = bytes.substr(10, headerLength);
    EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
    std::smatch m;
    const std::regex shapeRe(R"('shape': \(([0-9, ]*)\))");
    if (!std::regex_search(header, m, shapeRe))
        return npy;
    std::stringstream dims(m[1].str());
    std::string dim;
    while (std::getline(dims, dim, ','))
        if (dim.find_first_of("0123456789") != std::string::npos)
            npy.shape.push_back(std::stoul(dim));
    npy.values.resize((bytes.size() - 10 - headerLength) / 4);
    std::memcpy(npy.values.data(), bytes.data() + 10 + headerLength, npy.values.size() * 4);
    return npy;
}

} // namespace sightline::test
