#pragma once
// Small scenes with known answers, built in code.

#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::test {

/// A quad (two triangles) with corners c, c+u, c+u+v, c+v.
inline Mesh quad(const glm::vec3& c, const glm::vec3& u, const glm::vec3& v, const std::string& name = "quad")
{
    Mesh m;
    m.name = name;
    m.positions = {c, c + u, c + u + v, c + v};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

inline Scene sceneOf(std::vector<Mesh> meshes)
{
    Scene s;
    for (Mesh& m : meshes)
        s.addMeshInstance(std::move(m));
    return s;
}

/// Two parallel unit patches facing each other along +Z: source at z = 0, receiver at z = depth,
/// both spanning [0, 1]^2 in XY.
inline Patch xyPatch(double z, int na, int nb, double size = 1.0)
{
    Patch p;
    p.corner = {0.0, 0.0, z};
    p.u = {size, 0.0, 0.0};
    p.v = {0.0, size, 0.0};
    p.na = na;
    p.nb = nb;
    return p;
}

} // namespace sightline::test
