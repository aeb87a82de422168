// libFuzzer harness for the PVS readers: .pvs and .pvs.json files, part files and merging (docs/pvs.md). Bad
// input must end in sightline::Error; anything else (a crash, a sanitizer report, a hang, memory
// beyond the limit) is a finding.
//
// A part carries the SHA-256 of its own bytes, so random mutations of a whole part stop at the
// hash. The input is therefore also read as a part's body with a fresh, correct header: the
// fuzzer then reaches everything behind the hash (counts, the cell list, the .pvs inside, merge).

#include <cstdint>
#include <string>
#include <string_view>

#include "base/Error.h"
#include "visibility/pvs/PvsFile.h"
#include "visibility/pvs/Sha256.h"

namespace {

std::string withPartHeader(std::string_view body)
{
    std::string out = "SLPVSPRT";
    for (int k = 0; k < 4; ++k)
        out += char((sightline::pvs::kPartFileVersion >> (8 * k)) & 0xff);
    return out + sightline::pvs::sha256Hex(body) + std::string(body);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace sightline;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        (void)pvs::decodePvs(bytes, "input.pvs");
    } catch (const Error&) {
    }
    try {
        (void)pvs::decodePvsJson(bytes, "input.pvs.json");
    } catch (const Error&) {
    }
    try {
        (void)pvs::decodePart(bytes, "input.part");
    } catch (const Error&) {
    }
    try {
        const pvs::PvsPart part = pvs::decodePart(withPartHeader(bytes), "input.part");
        (void)pvs::mergeParts({part}, {"input.part"});
    } catch (const Error&) {
    }
    return 0;
}
