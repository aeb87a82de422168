// libFuzzer harness for the image reader (light textures, height images; stb_image). Bad input
// must end in sightline::Error; anything else is a finding.

#include "FuzzInput.h"
#include "lighting/ImageFile.h"
#include "visibility/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto file = sightline::fuzz::inputFile("input.png", data, size);
    try {
        (void)sightline::loadRgbImage(file);
    } catch (const sightline::Error&) {
    }
    return 0;
}
