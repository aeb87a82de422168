#pragma once
// What the command-line tools write: images of bounded size, and JSON that always prints.
//
// Every size option that allocates in proportion has a limit checked before anything is
// allocated, and a refusal says what the request would have cost, so "--size 16384x16384" is
// one line naming the size instead of a bare std::bad_alloc minutes later.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/Error.h"

namespace sightline::cli {

/// The largest image rendered or written: a side, and pixels in all (8K UHD fits).
inline constexpr int kMaxImageSide = 8192;
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t(1) << 25;

/// Throws sightline::Error unless a `width` x `height` image fits the limits above. `what` names
/// the request ("--size 16384x16384"); `bytesPerPixel` is what each pixel costs on the way
/// (render target, read-back, conversions), for the message.
inline void checkImageSize(int width, int height, const std::string& what, int bytesPerPixel)
{
    const std::uint64_t pixels = std::uint64_t(width > 0 ? width : 0) * std::uint64_t(height > 0 ? height : 0);
    if (width <= kMaxImageSide && height <= kMaxImageSide && pixels <= kMaxImagePixels)
        return;
    char cost[64];
    std::snprintf(cost, sizeof cost, "%.1f GB", double(pixels) * bytesPerPixel / 1e9);
    throw Error(what + ": a " + std::to_string(width) + "x" + std::to_string(height) + " image would take about " +
                cost + "; images are limited to " + std::to_string(kMaxImageSide) + " pixels a side and " +
                std::to_string(kMaxImagePixels / 1000000) + " million pixels");
}

/// JSON for stdout. Strings from file names or mesh files may hold bytes that are not UTF-8; they
/// print as U+FFFD instead of failing the whole command after its work is done.
inline std::string dumpJson(const nlohmann::json& value)
{
    return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// The importers' and builders' warnings, one "sightline-cli: warning: ..." line each on stderr.
inline void printWarnings(const std::vector<std::string>& warnings)
{
    for (const std::string& w : warnings)
        std::fprintf(stderr, "sightline-cli: warning: %s\n", w.c_str());
}

} // namespace sightline::cli
