#pragma once
// Plants for the bench scenes (internal): the demo's plant meshes (1000 leaves each), stored once
// per scene on first use and placed in pots or hanging baskets, turned and sized at random.

#include <cstdint>
#include <vector>

#include "demo/bench/Stage.h"

namespace sightline::demo::bench {

enum class PlantKind { Ficus, Fern, Palm };

class Planting {
public:
    explicit Planting(Stage& stage) : stage_(stage) {}

    /// A pot with a plant standing at `at` on a surface `standHeight` high (0: the floor, whose
    /// spot is then taken).
    void potted(vec2 at, PlantKind kind, float standHeight = 0.0f);
    /// A hanging plant in its basket, hooked at `hook` (its crown about 1.2 m lower).
    void hanging(vec3 hook);
    /// A ficus, fern or palm, 40/30/30.
    PlantKind anyKind();
    /// Plants placed so far.
    int count() const { return count_; }

private:
    std::uint32_t mesh(int which);

    Stage& stage_;
    std::vector<std::int64_t> meshes_;
    int count_ = 0;
};

} // namespace sightline::demo::bench
