#include "demo/bench/Planting.h"

#include "demo/Props.h"

namespace sightline::demo::bench {

std::uint32_t Planting::mesh(int which)
{
    if (meshes_.empty())
        meshes_.assign(6, -1);
    std::int64_t& id = meshes_[std::size_t(which)];
    if (id < 0) {
        Mesh m;
        switch (which) {
        case 0: m = plant(kFicus); break;
        case 1: m = plant(kFern); break;
        case 2: m = plant(kPalm); break;
        case 3: m = plant(kHanging); break;
        case 4: m = pot(); break;
        default: m = basket(); break;
        }
        id = stage_.add(std::move(m));
    }
    return std::uint32_t(id);
}

PlantKind Planting::anyKind()
{
    const float u = stage_.rng.unit();
    return u < 0.4f ? PlantKind::Ficus : u < 0.7f ? PlantKind::Fern : PlantKind::Palm;
}

void Planting::potted(vec2 at, PlantKind kind, float standHeight)
{
    Rng& rng = stage_.rng;
    const float turn = rng.unit(), size = rng.range(0.9f, 1.1f);
    stage_.put(mesh(4), place({at.x, standHeight, at.y}, turn));
    stage_.put(mesh(int(kind)), place({at.x, standHeight, at.y}, turn, size));
    if (standHeight == 0.0f)
        stage_.take(Rect::around(at, vec2(0.22f)));
    ++count_;
}

void Planting::hanging(vec3 hook)
{
    const float turn = stage_.rng.unit();
    stage_.put(mesh(5), place(hook, turn));
    stage_.put(mesh(3), place(hook, turn));
    ++count_;
}

} // namespace sightline::demo::bench
