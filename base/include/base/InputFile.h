#pragma once
// Every file Sightline reads is checked before a byte is read: it must be a regular file
// (following symlinks: a FIFO would block forever, /dev/zero or /dev/urandom never end, a folder
// is not a file) and no larger than a limit, so a hostile or mistaken path costs an error message,
// not gigabytes of memory. Failures throw sightline::Error naming the file and what is wrong.

#include <cstdint>
#include <filesystem>
#include <string>

namespace sightline {

/// The largest file any reader accepts (1 GiB; a 1M-triangle binary glTF is about 40 MB).
inline constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t(1) << 30;

/// Checks that `path` names a regular file of at most `maxBytes` and returns its size. `what`
/// names the file's role in the message ("scene", "project", "occluder mesh").
std::uintmax_t checkInputFile(const std::filesystem::path& path, const std::string& what,
                              std::uintmax_t maxBytes = kMaxInputFileBytes);

/// checkInputFile, then the whole file's bytes.
std::string readInputFile(const std::filesystem::path& path, const std::string& what,
                          std::uintmax_t maxBytes = kMaxInputFileBytes);

} // namespace sightline
