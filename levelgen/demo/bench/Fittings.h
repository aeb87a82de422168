#pragma once
// Fittings the bench scenes need beyond the demo's props (internal): a light balustrade of square
// balusters, an open-riser stair, and office furniture (desk, desk screen, monitor, low cabinet).
// All closed and outward: each is a union of closed boxes that overlap and never share an edge.

#include "demo/LevelParts.h"

namespace sightline::demo::bench {

using namespace parts;

/// Along local +x from 0 to `length` (at least 0.5 m), 1.06 m high, centred on z = 0.
Mesh balustrade(const std::string& name, float length);
/// `steps` treads of `run` rising `rise` each along local +x, `width` wide in +z from z = 0, on two
/// stringers, with a handrail on the +z side; the top tread's surface is at steps * rise.
Mesh stair(const std::string& name, int steps, float rise, float run, float width);
/// 1.6 x 0.8 m desk, its top at 0.74 m, the user's side toward local +z.
Mesh desk();
/// A 1.25 m high screen of `length` m along local x, 4 cm thick.
Mesh deskScreen(float length);
/// A monitor on a foot, facing local +z.
Mesh monitor();
/// 0.8 x 0.75 x 0.45 m low cabinet (a planter stand), its top at 0.75 m.
Mesh cabinet();
/// Object -> world for the demo's pillar (built floor to kCeiling) standing at `at` and stretched
/// to `height`.
mat4 columnAt(vec2 at, float height);

} // namespace sightline::demo::bench
