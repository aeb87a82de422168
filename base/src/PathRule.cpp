#include "base/PathRule.h"

#include <algorithm>
#include <system_error>

#include "base/Error.h"

namespace sightline {

namespace fs = std::filesystem;

bool resolvesInside(const fs::path& path, const fs::path& folder)
{
    std::error_code ec;
    const fs::path resolved = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec)
        return false;
    const fs::path root = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (ec)
        return false;
    // Compare whole components: /levels/a is not inside /level. A trailing separator on the folder
    // shows up as an empty last component; it must not count.
    auto rootEnd = root.end();
    if (rootEnd != root.begin() && std::prev(rootEnd)->empty())
        --rootEnd;
    return std::mismatch(root.begin(), rootEnd, resolved.begin(), resolved.end()).first == rootEnd;
}

fs::path resolveWrittenPath(const std::string& written, const fs::path& folder, bool allowOutside,
                            const std::string& what, const std::string& key)
{
    const fs::path p(written);
    if (p.is_absolute())
        return p;
    const fs::path full = (folder / p).lexically_normal();
    if (!allowOutside && !resolvesInside(full, folder))
        throw Error(what + ": " + key + " '" + written +
                    "' leaves the project's folder; pass --allow-outside-paths to allow it");
    return full;
}

} // namespace sightline
