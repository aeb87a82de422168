#pragma once
// Saving never loses the user's data: bytes go to a temporary file beside the target, are flushed,
// and only then renamed over it (rename is atomic on POSIX within one file system). A failure at
// any point leaves the old file untouched and throws sightline::Error.

#include <filesystem>
#include <string_view>

namespace sightline {

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

} // namespace sightline
