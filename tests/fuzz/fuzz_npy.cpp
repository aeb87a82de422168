// libFuzzer harness for the .npy readers: float arrays (height fields) and hidden-sample masks
// (docs/design.md §4). Bad input must end in sightline::Error; anything else is a finding.

#include "FuzzInput.h"
#include "base/Error.h"
#include "visibility/MaskNpy.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto file = sightline::fuzz::inputFile("input.npy", data, size);
    try {
        (void)sightline::readFloatNpy(file);
    } catch (const sightline::Error&) {
    }
    try {
        (void)sightline::readMaskNpy(file, static_cast<int>(1 + size % 1024));
    } catch (const sightline::Error&) {
    }
    return 0;
}
