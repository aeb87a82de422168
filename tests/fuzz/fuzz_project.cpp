// libFuzzer harness for the project file reader (docs/design.md §3). Bad input must end in
// sightline::Error; anything else is a finding.

#include "FuzzInput.h"
#include "project/Project.h"
#include "base/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto file = sightline::fuzz::inputFile("project.json", data, size);
    try {
        (void)sightline::loadProject(file);
    } catch (const sightline::Error&) {
    }
    return 0;
}
