#include "visibility/AtomicFile.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "visibility/Error.h"

namespace sightline {

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes)
{
    namespace fs = std::filesystem;
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        throw Error(path.string() + ": folder '" + folder.string() + "' does not exist");

    std::random_device rd;
    std::string tempName = ".";
    tempName += path.filename().string();
    tempName += ".tmp-" + std::to_string(rd());
    const fs::path temp = folder / tempName;
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        throw Error(path.string() + ": cannot write (" + std::strerror(errno) + ")");

    auto fail = [&](const char* step) {
        const std::string reason = std::strerror(errno);
        ::close(fd);
        ::unlink(temp.c_str());
        throw Error(path.string() + ": " + step + " failed (" + reason + "); the old file is unchanged");
    };
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
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(temp.c_str());
        throw Error(path.string() + ": rename failed (" + reason + "); the old file is unchanged");
    }
}

} // namespace sightline
