#include "report/PngFile.h"

#include <string_view>

#include <QBuffer>

#include "base/AtomicFile.h"
#include "base/Error.h"

namespace sightline {

std::string encodePng(const QImage& image)
{
    QByteArray bytes;
    QBuffer buffer(&bytes);
    buffer.open(QIODevice::WriteOnly);
    if (image.isNull() || !image.save(&buffer, "PNG"))
        throw Error("cannot encode the image as PNG");
    return std::string(bytes.constData(), std::size_t(bytes.size()));
}

void savePng(const QImage& image, const std::filesystem::path& file)
{
    std::string bytes;
    try {
        bytes = encodePng(image);
    } catch (const Error& e) {
        throw Error(file.string() + ": " + e.what());
    }
    writeFileAtomically(file, bytes);
}

void saveRgbPng(int width, int height, const std::vector<unsigned char>& rgb, const std::filesystem::path& file)
{
    if (width < 1 || height < 1 || rgb.size() != std::size_t(width) * std::size_t(height) * 3)
        throw Error(file.string() + ": " + std::to_string(rgb.size()) + " bytes are not a " + std::to_string(width) +
                    " x " + std::to_string(height) + " RGB image");
    // QImage reads the caller's buffer in place; savePng encodes it before this returns.
    const QImage image(rgb.data(), width, height, qsizetype(width) * 3, QImage::Format_RGB888);
    savePng(image, file);
}

} // namespace sightline
