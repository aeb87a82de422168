#pragma once
// The one PNG writer: every PNG Sightline writes (maps, charts, light maps, screenshots, the
// disagreement images) is encoded by Qt here and saved atomically, so an interrupted write leaves
// the old file whole.

#include <filesystem>
#include <string>
#include <vector>

#include <QImage>

namespace sightline {

/// The image as PNG bytes; throws sightline::Error when Qt cannot encode it (a null image).
std::string encodePng(const QImage& image);

/// Saves as PNG atomically; throws sightline::Error with the path on failure.
void savePng(const QImage& image, const std::filesystem::path& file);

/// Saves 8-bit RGB pixels (row-major, `width` * `height` * 3 bytes) as PNG atomically.
void saveRgbPng(int width, int height, const std::vector<unsigned char>& rgb, const std::filesystem::path& file);

} // namespace sightline
