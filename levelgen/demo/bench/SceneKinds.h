#pragma once
// One generator per bench scene kind (BenchScenes.h describes what each promises). Internal: the
// public entry is makeBenchScene, which also names the scene.

#include <cstdint>

#include "demo/BenchScenes.h"

namespace sightline::demo::bench {

BenchScene clutteredRooms(std::uint64_t seed);
BenchScene denseMesh(std::uint64_t seed);
BenchScene architecturalInterior(std::uint64_t seed);
BenchScene openHall(std::uint64_t seed);

} // namespace sightline::demo::bench
