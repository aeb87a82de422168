#pragma once
// Runs sightline-cli as a user does (a child process), and the scene file the app tests share.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

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

/// The app tests' scene: a 3 x 2 m wall at z = 2 with a 1 m square hole over [0, 1]^2 (OBJ).
inline void writeWallWithHoleObj(const fs::path& file)
{
    std::ofstream(file) << "v -1 -0.5 2\nv 2 -0.5 2\nv 2 1.5 2\nv -1 1.5 2\n"
                           "v 0 0 2\nv 1 0 2\nv 1 1 2\nv 0 1 2\n"
                           "f 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
}

} // namespace sightline::test
