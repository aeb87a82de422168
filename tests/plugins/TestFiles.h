#pragma once
// Helpers shared by the plugin tests: the third-party test files (tests/data), a scratch folder, file writers and a
// check that an import fails with a one-line sightline::Error naming the file.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "base/Error.h"

namespace sightline::test {

/// The third-party files the tests read (tests/data, listed with sources and licences in its
/// SOURCES.md). They are part of the repository: a test that finds one missing fails, it never skips.
inline std::filesystem::path testData() { return SIGHTLINE_TEST_DATA; }

/// A fresh folder under the system temp folder, removed with everything in it.
class TempDir {
public:
    TempDir()
    {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() / ("sightline-test-" + std::to_string(rd()) + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

/// Little-endian bytes of a value, for building binary files (this machine is little-endian).
inline std::string binary(const void* data, std::size_t bytes) { return std::string(static_cast<const char*>(data), bytes); }
inline std::string f32(float v) { return binary(&v, 4); }
inline std::string i32(std::int32_t v) { return binary(&v, 4); }
inline std::string u32(std::uint32_t v) { return binary(&v, 4); }
inline std::string u8(std::uint8_t v) { return binary(&v, 1); }

inline std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& bytes)
{
    std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

/// Runs `load`, expecting a sightline::Error whose message is one non-empty line naming `file`.
/// Returns the message for further checks.
inline std::string expectOneLineError(const std::filesystem::path& file, const std::function<void()>& load)
{
    try {
        load();
    } catch (const sightline::Error& e) {
        const std::string message = e.what();
        EXPECT_FALSE(message.empty());
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.find('\r'), std::string::npos) << message;
        EXPECT_NE(message.find(file.filename().string()), std::string::npos) << message;
        return message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << file << ": threw a non-sightline exception: " << e.what();
        return {};
    }
    ADD_FAILURE() << file << ": loaded, but an error was expected";
    return {};
}

} // namespace sightline::test
