#pragma once
// A generated level for the PVS bake's benchmark and tests (the "4,096 cells x 2,000 objects"
// size the bake's speed target names): a square grid of 8 m rooms with 3 m walls (0.2 m slabs, one instance per room side),
// 1 m x 2.1 m doorways in about 60% of the inner walls (seeded), and box props scattered through
// the rooms (a unit box mesh placed many times) so that the instance count is `objects`.
// The view cells are listed: 4 x 4 boxes per room, inset 0.15 m from the walls, 0.1-1.9 m high.
// Deterministic: splitmix64 from `seed`.

#include <cstdint>
#include <vector>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::demo {

struct PvsLevel {
    Scene scene;
    std::vector<Bounds> cells;
    Patch source, receiver;   ///< a project needs patches; these look through the first doorway
};

/// `rooms` x `rooms` rooms; `objects` instances in all (at least the floor and walls: fewer props
/// when asked for fewer). Throws sightline::Error for rooms outside [1, 256].
PvsLevel makePvsLevel(int roomsX, int roomsZ, int objects, std::uint64_t seed);

} // namespace sightline::demo
