#include "lighting/ao/AoDirections.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "base/Error.h"

namespace sightline {

namespace {

struct Face {
    int a, b, c;
};

/// Solid angle of the spherical triangle (a, b, c) of unit vectors (Van Oosterom & Strackee 1983).
double solidAngle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const double numerator = glm::dot(a, glm::cross(b, c));
    const double denominator = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
    return 2.0 * std::atan2(std::abs(numerator), denominator);
}

struct Sphere {
    std::vector<glm::dvec3> directions;
    std::vector<std::vector<Face>> faces;   ///< per level
};

/// Levels 0..4 of the subdivided octahedron: new vertices are appended, so levels nest.
Sphere buildSphere()
{
    Sphere s;
    s.directions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    std::vector<Face> faces;
    for (int sx : {0, 1})
        for (int sy : {2, 3})
            for (int sz : {4, 5}) {
                // Counter-clockwise seen from outside (orientation does not matter for the cells).
                faces.push_back({sx, sy, sz});
            }
    s.faces.push_back(faces);
    for (int level = 1; level < int(kAoDirectionCounts.size()); ++level) {
        std::map<std::pair<int, int>, int> midpoints;
        auto midpoint = [&](int i, int j) {
            const std::pair<int, int> key = std::minmax(i, j);
            const auto found = midpoints.find(key);
            if (found != midpoints.end())
                return found->second;
            s.directions.push_back(glm::normalize(s.directions[std::size_t(i)] + s.directions[std::size_t(j)]));
            const int index = int(s.directions.size()) - 1;
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<Face> finer;
        for (const Face& f : s.faces.back()) {
            const int ab = midpoint(f.a, f.b), bc = midpoint(f.b, f.c), ca = midpoint(f.c, f.a);
            finer.push_back({f.a, ab, ca});
            finer.push_back({ab, f.b, bc});
            finer.push_back({ca, bc, f.c});
            finer.push_back({ab, bc, ca});
        }
        s.faces.push_back(std::move(finer));
    }
    return s;
}

/// Cells of level `level`: each face is cut into n x n small spherical triangles, each given to
/// the face corner nearest its centroid (the Voronoi cell of the corner within the face; for these
/// well-shaped meshes the nearest direction of a face's point is one of its corners).
AoDirectionSet buildSet(const Sphere& sphere, int level)
{
    AoDirectionSet set;
    set.k = kAoDirectionCounts[std::size_t(level)];
    std::vector<double> omega(std::size_t(set.k), 0.0);
    std::vector<glm::dvec3> moment(std::size_t(set.k), glm::dvec3(0.0));
    const int n = std::max(8, 64 >> level);
    for (const Face& f : sphere.faces[std::size_t(level)]) {
        const glm::dvec3 A = sphere.directions[std::size_t(f.a)], B = sphere.directions[std::size_t(f.b)],
                         C = sphere.directions[std::size_t(f.c)];
        auto at = [&](int i, int j) {   // grid point i steps towards B, j towards C
            return glm::normalize(A + (B - A) * (double(i) / n) + (C - A) * (double(j) / n));
        };
        auto add = [&](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
            const double w = solidAngle(p, q, r);
            const glm::dvec3 centre = glm::normalize(p + q + r);
            const double da = glm::dot(centre, A), db = glm::dot(centre, B), dc = glm::dot(centre, C);
            const int owner = da >= db && da >= dc ? f.a : db >= dc ? f.b : f.c;
            omega[std::size_t(owner)] += w;
            moment[std::size_t(owner)] += w * centre;
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j) {
                add(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < n)
                    add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
    for (int j = 0; j < set.k; ++j) {
        set.directions.push_back(glm::vec3(sphere.directions[std::size_t(j)]));
        set.solidAngle.push_back(float(omega[std::size_t(j)]));
        set.moment.push_back(glm::vec3(moment[std::size_t(j)]));
        set.cellRadius.push_back(float(std::sqrt(omega[std::size_t(j)] / 3.14159265358979323846)));
    }
    set.antipode.assign(std::size_t(set.k), -1);
    for (int j = 0; j < set.k; ++j)
        for (int a = 0; a < set.k; ++a)
            if (glm::dot(sphere.directions[std::size_t(j)], sphere.directions[std::size_t(a)]) < -1.0 + 1e-9)
                set.antipode[std::size_t(j)] = a;
    return set;
}

} // namespace

float aoHorizonLobe(float c, float g, float r)
{
    if (!(g > 0.0f) || !(r > 0.0f))
        return std::max(0.0f, c) * 3.14159265f * r * r;
    // c + g x = g r (x' - t) with x' = x / r: integrate (x' - t) 2 sqrt(1 - x'^2) over x' in [t, 1].
    const double t = std::clamp(-double(c) / (double(g) * r), -1.0, 1.0);
    const double root = std::sqrt(1.0 - t * t);
    const double moment = 2.0 / 3.0 * root * root * root;
    const double chord = 3.14159265358979323846 / 2.0 - t * root - std::asin(t);
    return float(double(g) * r * r * r * (moment - t * chord));
}

int aoLevelOf(int k)
{
    for (std::size_t s = 0; s < kAoDirectionCounts.size(); ++s)
        if (kAoDirectionCounts[s] == k)
            return int(s);
    throw Error("k " + std::to_string(k) + ": the light sphere has 6, 18, 66, 258 or 1026 directions (subdivided octahedron)");
}

const AoDirectionSet& aoDirections(int k)
{
    const int level = aoLevelOf(k);
    static std::once_flag once;
    static std::vector<AoDirectionSet> sets;
    std::call_once(once, [] {
        const Sphere sphere = buildSphere();
        for (int s = 0; s < int(kAoDirectionCounts.size()); ++s)
            sets.push_back(buildSet(sphere, s));
    });
    return sets[std::size_t(level)];
}

} // namespace sightline
