#pragma once
// Saving never loses the user's data: bytes go to a temporary file beside the target, are flushed,
// and only then renamed over it (rename is atomic on POSIX within one file system). A failure at
// any point leaves the old file untouched and throws sightline::Error.
//
// What a save keeps: the old file's permission bits (a private 0600 file stays private; a new file
// gets the umask's default), and a symlink at the path (the link's final target is replaced, in
// the target's folder, and the link still points at it). A target that is a folder or other
// non-regular file is refused.
//
// The temporary is named ".NAME.tmp-PID-NONCE". A process killed mid-save leaves it behind; each
// later save of NAME removes such leftovers once their writer is gone (no process has that pid)
// and they are older than kDeadWriterTempAge. A live writer's temporary is never touched.

#include <chrono>
#include <filesystem>
#include <string_view>

namespace sightline {

/// How old a leftover temporary of a dead writer must be before a save removes it (a margin for
/// pids of other pid namespaces sharing the folder).
inline constexpr std::chrono::minutes kDeadWriterTempAge{10};
/// Leftovers without a pid in their name (older Sightline versions): age alone decides.
inline constexpr std::chrono::hours kUnknownWriterTempAge{1};

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

/// The temporary file name a writer with `pid` uses beside `target` (exposed for tests).
std::filesystem::path atomicTempName(const std::filesystem::path& target, unsigned long pid, unsigned long nonce);

} // namespace sightline
