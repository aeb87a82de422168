#include "demo/BenchScenes.h"

#include <string>

#include "demo/bench/SceneKinds.h"

namespace sightline::demo {

const char* benchKindName(BenchKind kind)
{
    switch (kind) {
    case BenchKind::ClutteredRooms: return "cluttered-rooms";
    case BenchKind::DenseMesh: return "dense-mesh";
    case BenchKind::ArchitecturalInterior: return "architectural-interior";
    case BenchKind::OpenHall: return "open-hall";
    }
    return "unknown";
}

BenchScene makeBenchScene(BenchKind kind, std::uint64_t seed)
{
    BenchScene out;
    switch (kind) {
    case BenchKind::ClutteredRooms: out = bench::clutteredRooms(seed); break;
    case BenchKind::DenseMesh: out = bench::denseMesh(seed); break;
    case BenchKind::ArchitecturalInterior: out = bench::architecturalInterior(seed); break;
    case BenchKind::OpenHall: out = bench::openHall(seed); break;
    }
    out.name = std::string(benchKindName(kind)) + "-" + std::to_string(seed);
    return out;
}

std::vector<BenchScene> benchScenes(BenchKind kind, int seeds)
{
    std::vector<BenchScene> out;
    for (int seed = 1; seed <= seeds; ++seed)
        out.push_back(makeBenchScene(kind, std::uint64_t(seed)));
    return out;
}

} // namespace sightline::demo
