// libFuzzer harness for the image readers (light textures, height images, and AO environments:
// Radiance HDR; stb_image behind base/ImageCheck.h). Bad input must end in
// sightline::Error; anything else (a hang, a crash, an allocation past the limit) is a finding.

#include "FuzzInput.h"
#include "base/ImageFile.h"
#include "lighting/ao/AoEnvironment.h"
#include "base/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto file = sightline::fuzz::inputFile("input.png", data, size);
    try {
        (void)sightline::loadRgbImage(file);
    } catch (const sightline::Error&) {
    }
    try {
        (void)sightline::AoEnvironment::load(file);
    } catch (const sightline::Error&) {
    }
    return 0;
}
