#pragma once
// Lights for the demo level (DemoLevel.h): an interior lit the way designers light one, for the
// lighting benchmark and the lit examples. 300 light samples in all:
//  - 10 ceiling panels (area lights 0.8 x 0.8 m, 4 x 4 samples, facing down, 10 cm under the
//    ceiling), two per room: 160 samples;
//  - 100 point lights (lamps and candles, 20 per room, 1.6-2.8 m up, 8 m range);
//  - 39 spot lights on the walls, aimed down and inwards (10 m range);
//  - one sun through the windows.
// Deterministic (splitmix64, fixed seed).

#include <vector>

#include "lighting/Light.h"
#include "visibility/Patch.h"

namespace sightline::demo {

std::vector<Light> demoLights();

/// The level's whole floor, 1 cm up, as a receiver of `side` x `side` samples facing up.
Patch demoFloor(int side);

} // namespace sightline::demo
