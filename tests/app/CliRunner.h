#pragma once
// Runs sightline-cli as a user does (a child process), for the CLI tests.
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

inline CliRun runCli(const std::string& arguments)
{
    const fs::path errFile = uniqueFolder() / "stderr.txt";
    const std::string command = std::string(SIGHTLINE_CLI) + " " + arguments + " 2>" + errFile.string();
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

inline bool oneLine(const std::string& s) { return !s.empty() && s.find('\n') == s.size() - 1; }

} // namespace sightline::test
