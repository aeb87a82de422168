#include "base/AtomicFile.h"

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/Error.h"

namespace sightline {

namespace fs = std::filesystem;

namespace {

/// Follows `path` through symlinks to the file they name (which need not exist yet), so that
/// saving through a link updates its target and keeps the link.
fs::path finalTarget(const fs::path& path)
{
    fs::path p = path;
    for (int hops = 0; hops < 40; ++hops) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(p, ec)))
            return p;
        const fs::path target = fs::read_symlink(p, ec);
        if (ec)
            throw Error(path.string() + ": cannot follow the symlink (" + ec.message() + ")");
        p = target.is_absolute() ? target : p.parent_path() / target;
    }
    throw Error(path.string() + ": too many levels of symlinks");
}

std::string tempPrefix(const fs::path& target)
{
    // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "." + name + ".tmp-".
    std::string prefix = ".";
    prefix += target.filename().string();
    prefix += ".tmp-";
    return prefix;
}

/// Whether a temporary file left beside the target by some writer is safe to delete: its writer
/// (the pid in its name) is gone and it has not been touched for a while. The age also covers
/// writers in another pid namespace sharing the folder, whose pids mean nothing here. Names from
/// before the pid was recorded (".NAME.tmp-RANDOM") have no writer to ask: only their age counts.
bool isStale(const fs::directory_entry& entry, const std::string& prefix, fs::file_time_type now)
{
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0)
        return false;
    std::error_code ec;
    if (!entry.is_regular_file(ec) || ec)
        return false;
    const auto modified = entry.last_write_time(ec);
    if (ec)
        return false;
    const auto age = now - modified;
    const std::string_view rest = std::string_view(name).substr(prefix.size());
    auto allDigits = [](std::string_view text) {
        return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    const std::size_t dash = rest.find('-');
    if (dash == std::string_view::npos)   // the old form's suffix was a decimal number only
        return allDigits(rest) && age > kUnknownWriterTempAge;
    if (!allDigits(rest.substr(dash + 1)))   // not a name this writer makes (".x.tmp-notes-1")
        return false;
    long pid = 0;
    const auto [end, err] = std::from_chars(rest.data(), rest.data() + dash, pid);
    if (err != std::errc() || end != rest.data() + dash || pid <= 0)
        return false;
    // EPERM means alive (another user's process); only ESRCH says nobody has that pid.
    const bool writerGone = ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
    return writerGone && age > kDeadWriterTempAge;
}

/// Removes stale temporaries of earlier, interrupted saves of `target` (a killed process leaves
/// its temporary behind; it would otherwise stay forever). Best effort: a failure here must not
/// stop the save.
void removeStaleTemps(const fs::path& folder, const fs::path& target)
{
    const std::string prefix = tempPrefix(target);
    const auto now = fs::file_time_type::clock::now();
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        if (isStale(*it, prefix, now)) {
            std::error_code ignored;
            fs::remove(it->path(), ignored);
        }
    }
}

/// The mode the new file gets: the old file's, so that a private (0600) file stays private, else
/// what a plain create would give under the process's umask.
mode_t modeFor(const fs::path& target, bool& keepExisting)
{
    struct stat st {};
    keepExisting = ::stat(target.c_str(), &st) == 0;
    return keepExisting ? st.st_mode & 07777 : 0666;
}

void syncFolder(const fs::path& folder)
{
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        ::fsync(fd);   // best effort: the rename reaches the disk with the folder's entry
        ::close(fd);
    }
}

} // namespace

fs::path atomicTempName(const fs::path& target, unsigned long pid, unsigned long nonce)
{
    return tempPrefix(target) + std::to_string(pid) + "-" + std::to_string(nonce);
}

void writeFileAtomically(const fs::path& path, std::string_view bytes)
{
    const fs::path target = finalTarget(path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        throw Error(path.string() + ": folder '" + folder.string() + "' does not exist");
    const fs::file_status existing = fs::status(target, ec);
    if (fs::exists(existing) && !fs::is_regular_file(existing))
        throw Error(path.string() + ": " + (fs::is_directory(existing) ? "is a folder" : "is not a regular file") +
                    "; not replaced");
    removeStaleTemps(folder, target);

    bool keepMode = false;
    const mode_t mode = modeFor(target, keepMode);
    // A nonce beside the pid; random_device may throw where no entropy source is available.
    unsigned long nonce = static_cast<unsigned long>(std::chrono::steady_clock::now().time_since_epoch().count());
    try {
        nonce = std::random_device{}();
    } catch (const std::exception&) {
    }
    const fs::path temp = folder / atomicTempName(target, static_cast<unsigned long>(::getpid()), nonce);
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
    if (fd < 0)
        throw Error(path.string() + ": cannot write (" + std::strerror(errno) + ")");

    auto fail = [&](const char* step) {
        const std::string reason = std::strerror(errno);
        ::close(fd);
        ::unlink(temp.c_str());
        throw Error(path.string() + ": " + step + " failed (" + reason + "); the old file is unchanged");
    };
    // open() applies the umask; an existing file's mode is restored exactly.
    if (keepMode && ::fchmod(fd, mode) != 0)
        fail("keeping the file's permissions");
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            fail("write");
        }
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0)
        fail("flush");
    if (::close(fd) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(temp.c_str());
        throw Error(path.string() + ": close failed (" + reason + "); the old file is unchanged");
    }
    if (std::rename(temp.c_str(), target.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(temp.c_str());
        throw Error(path.string() + ": rename failed (" + reason + "); the old file is unchanged");
    }
    syncFolder(folder);
}

} // namespace sightline
