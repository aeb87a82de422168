#include "base/InputFile.h"

#include <fstream>
#include <iterator>
#include <system_error>

#include "base/Error.h"

namespace sightline {

namespace {

std::string describe(std::filesystem::file_type type)
{
    using std::filesystem::file_type;
    switch (type) {
    case file_type::directory: return "a folder";
    case file_type::fifo: return "a FIFO (named pipe)";
    case file_type::socket: return "a socket";
    case file_type::character: return "a character device";
    case file_type::block: return "a block device";
    default: return "not a regular file";
    }
}

std::string megabytes(std::uintmax_t bytes)
{
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB";
}

} // namespace

std::uintmax_t checkInputFile(const std::filesystem::path& path, const std::string& what, std::uintmax_t maxBytes)
{
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found)
        throw Error(path.string() + ": " + what + " file not found");
    if (ec)
        throw Error(path.string() + ": cannot read the " + what + " file: " + ec.message());
    if (status.type() != std::filesystem::file_type::regular)
        throw Error(path.string() + ": the " + what + " is " + describe(status.type()) + ", not a regular file");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec)
        throw Error(path.string() + ": cannot read the " + what + " file: " + ec.message());
    if (size > maxBytes)
        throw Error(path.string() + ": the " + what + " file is " + megabytes(size) + ", more than the limit of " +
                    megabytes(maxBytes));
    return size;
}

std::string readInputFile(const std::filesystem::path& path, const std::string& what, std::uintmax_t maxBytes)
{
    const std::uintmax_t size = checkInputFile(path, what, maxBytes);
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw Error(path.string() + ": cannot open the " + what + " file");
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    if (in.gcount() != static_cast<std::streamsize>(size))
        throw Error(path.string() + ": the " + what + " file changed or could not be read whole");
    return bytes;
}

} // namespace sightline
