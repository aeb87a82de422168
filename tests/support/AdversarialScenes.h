#pragma once
// Randomised adversarial scenes for the exactness tests (docs/design.md §2, "Exact"): each category is
// an input kind that real levels contain and that broke a sampler once. Every case comes at
// production sample counts (32x32 sources, receivers up to 128x128) and can be moved far from the
// origin: the scene is built in local coordinates, moved by `offset` and only then rounded to
// float, so the float32 values a far-away level would have in its file are the input.
//
// Judge the samplers' answers with ExactJudge.h.

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/SourceJitter.h"

namespace sightline::test {

enum class Adversary {
    FlatEdges,          ///< edges parallel (or within 1e-7..1e-4 rad) to the source rows, parallel patches
    HugeTriangles,      ///< a 1e4-1e5 m floor or terrain through the shaft
    LongThinSource,     ///< a 10 m x 1 cm source with 32 x 1 samples
    StandingOnSource,   ///< walls through a source sample column, or 1 mm past it
    ClosedMeshes,       ///< watertight boxes; rays leaving through their shared edges and diagonals
    MirroredPlanes,     ///< plane occluders under mirroring transforms, patches centred on the diagonal
    KilometreCrossing,  ///< kilometre triangles crossing both patch planes, tilted receiver
    EdgeOnFins,         ///< triangles in planes that contain whole families of rays
    NearReceiver,       ///< occluders just short of, touching and crossing the receiver plane
    RandomSoup,         ///< tiny, medium and huge triangles in and around a tilted shaft
    SharedDiagonal,     ///< walls of two triangles with the patches centred on their diagonal
};

inline const std::vector<Adversary>& allAdversaries()
{
    static const std::vector<Adversary> all = {
        Adversary::FlatEdges,     Adversary::HugeTriangles, Adversary::LongThinSource,    Adversary::StandingOnSource,
        Adversary::ClosedMeshes,  Adversary::MirroredPlanes, Adversary::KilometreCrossing, Adversary::EdgeOnFins,
        Adversary::NearReceiver,  Adversary::RandomSoup,    Adversary::SharedDiagonal};
    return all;
}

inline const char* toString(Adversary a)
{
    switch (a) {
    case Adversary::FlatEdges: return "flat-edges";
    case Adversary::HugeTriangles: return "huge-triangles";
    case Adversary::LongThinSource: return "long-thin-source";
    case Adversary::StandingOnSource: return "standing-on-source";
    case Adversary::ClosedMeshes: return "closed-meshes";
    case Adversary::MirroredPlanes: return "mirrored-planes";
    case Adversary::KilometreCrossing: return "kilometre-crossing";
    case Adversary::EdgeOnFins: return "edge-on-fins";
    case Adversary::NearReceiver: return "near-receiver";
    case Adversary::RandomSoup: return "random-soup";
    case Adversary::SharedDiagonal: return "shared-diagonal";
    }
    return "?";
}

struct AdversarialCase {
    std::string name;   ///< category, seed and offset: for failure messages
    Scene scene;
    Patch source, receiver;
    glm::dvec3 offset{0.0};   ///< where the local origin went
};

namespace detail {

/// Builds one case in local coordinates (metres, double), then places it at `offset`.
class CaseBuilder {
public:
    CaseBuilder(unsigned seed, glm::dvec3 offset) : rng_(seed), offset_(offset) {}

    /// Turns the whole case (geometry and patches) about the local origin before it is moved:
    /// patch frames are then not axis-aligned, and coordinates that were exact are rounded.
    void rotateEverything(const glm::dmat3& rotation) { rotation_ = rotation; }

    double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
    int pick(int n) { return int(rng_() % std::uint32_t(n)); }
    bool coin(double p = 0.5) { return uniform(0.0, 1.0) < p; }
    glm::dvec3 jitter(double size) { return {uniform(-size, size), uniform(-size, size), uniform(-size, size)}; }

    /// A free triangle soup, each vertex placed at offset then rounded to float.
    void triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    {
        const auto base = std::uint32_t(soup_.positions.size());
        for (const glm::dvec3& p : {a, b, c})
            soup_.positions.emplace_back(rotation_ * p + offset_);
        soup_.indices.insert(soup_.indices.end(), {base, base + 1, base + 2});
    }
    void quad(const glm::dvec3& c, const glm::dvec3& u, const glm::dvec3& v)
    {
        triangle(c, c + u, c + u + v);
        triangle(c, c + u + v, c + v);
    }

    /// A mesh instance placed by `transform` (local), the translation moved to offset. The
    /// transform is float (as in files); its translation carries the offset.
    void instance(Mesh mesh, glm::dmat4 transform)
    {
        transform = glm::dmat4(rotation_) * transform;
        transform[3] += glm::dvec4(offset_, 0.0);
        scene_.addMeshInstance(std::move(mesh), glm::mat4(transform));
    }

    static Mesh box(bool watertight)
    {
        Mesh m;
        m.name = "box";
        for (int i = 0; i < 8; ++i)
            m.positions.emplace_back((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
        m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                     2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
        m.watertight = watertight;
        return m;
    }
    static Mesh plane()
    {
        Mesh m;
        m.name = "plane";
        m.positions = {{-0.5f, 0.0f, -0.5f}, {0.5f, 0.0f, -0.5f}, {0.5f, 0.0f, 0.5f}, {-0.5f, 0.0f, 0.5f}};
        m.indices = {0, 2, 1, 0, 3, 2};
        return m;
    }

    static glm::dmat4 rotation(double angle, const glm::dvec3& axis)
    {
        return glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis));
    }

    AdversarialCase finish(std::string name, Patch source, Patch receiver)
    {
        AdversarialCase out;
        if (!soup_.positions.empty()) {
            soup_.name = "soup";
            scene_.addMeshInstance(std::move(soup_));
        }
        out.scene = std::move(scene_);
        for (Patch* p : {&source, &receiver}) {
            p->corner = rotation_ * p->corner + offset_;
            p->u = rotation_ * p->u;
            p->v = rotation_ * p->v;
        }
        out.source = source;
        out.receiver = receiver;
        out.offset = offset_;
        out.name = std::move(name);
        return out;
    }

    /// A receiver grid at production sizes, small ones more often (they are cheaper).
    int receiverSide()
    {
        static const int sides[] = {16, 16, 24, 32, 32, 48, 64, 128};
        return sides[pick(8)];
    }

private:
    std::mt19937 rng_;
    glm::dvec3 offset_;
    glm::dmat3 rotation_{1.0};
    Scene scene_;
    Mesh soup_;
};

inline Patch patch(const glm::dvec3& corner, const glm::dvec3& u, const glm::dvec3& v, int na, int nb)
{
    Patch p;
    p.corner = corner, p.u = u, p.v = v, p.na = na, p.nb = nb;
    return p;
}

} // namespace detail

/// One case of a category. `offset`: how far from the origin the level sits (0, 1e3, 1e4, 1e5 m
/// along a seeded direction).
inline AdversarialCase adversarialCase(Adversary kind, unsigned seed, double offsetMetres = 0.0)
{
    std::mt19937 directions(seed * 7919u + 17u);
    std::normal_distribution<double> gauss;
    glm::dvec3 direction(gauss(directions), gauss(directions), gauss(directions));
    direction = glm::normalize(direction);
    const glm::dvec3 offset = offsetMetres * direction;
    detail::CaseBuilder b(seed * 2654435761u + unsigned(kind), offset);
    using detail::patch;
    const std::string name = std::string(toString(kind)) + " seed " + std::to_string(seed) + " offset " +
                             std::to_string(int(offsetMetres)) + " m";
    const int side = b.receiverSide();
    // Half the cases are turned at random as a whole: the shapes stay, the frames do not line up.
    if (seed % 2 == 0) {
        std::normal_distribution<double> g;
        b.rotateEverything(glm::dmat3(detail::CaseBuilder::rotation(
            3.0 * std::abs(g(directions)), glm::dvec3(g(directions), g(directions), g(directions)))));
    }

    switch (kind) {
    case Adversary::FlatEdges: {
        // Parallel patches whose rows line up (receiver row b at the t of source row b): an edge
        // parallel to u at the height of row b backprojects, from every receiver sample of row
        // b, exactly onto source row b, and in float its two ends' t differ by a few ulps. Other
        // edges are tilted by 1e-7..1e-4 rad or sit at random heights.
        const double depth = b.uniform(3.0, 12.0);
        const Patch source = patch({0, 0, 0}, {b.uniform(0.5, 2.0), 0, 0}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({b.uniform(-1, 1), 0, depth}, {b.uniform(1, 3), 0, 0}, {0, 1, 0}, side, 32);
        for (int k = 0; k < 40; ++k) {
            const double z = b.uniform(0.2, depth - 0.2);
            double y = (b.pick(32) + 0.5) / 32.0;
            if (b.coin(0.3)) {   // lands on a row from the receiver's centre instead
                const glm::dvec3 rc = receiver.centre();
                y = rc.y + (y - rc.y) * (depth - z) / depth;
            }
            const double x0 = b.uniform(-2.0, 1.5), length = b.uniform(0.3, 3.0);
            const double tilt = b.coin(0.6) ? 0.0 : b.uniform(-1.0, 1.0) * std::pow(10.0, -b.uniform(4.0, 7.0));
            const glm::dvec3 a(x0, y, z), e(length * std::cos(tilt), length * std::sin(tilt), 0.0);
            const glm::dvec3 apex = a + glm::dvec3(b.uniform(0, length), (b.coin() ? 1 : -1) * b.uniform(0.01, 0.8),
                                                   b.uniform(-0.1, 0.1));
            b.triangle(a, a + e, apex);
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::HugeTriangles: {
        const double depth = b.uniform(4.0, 15.0);
        const Patch source = patch({0, 0, 0}, {1, 0, b.uniform(-0.2, 0.2)}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({b.uniform(-1, 1), b.uniform(-1, 1), depth}, {b.uniform(1, 3), 0, b.uniform(-0.5, 0.5)},
                                     {0, b.uniform(1, 3), 0}, side, side);
        const double size = b.coin() ? 1e4 : 1e5;
        // A floor through the shaft, tilted so it cuts some of the rays.
        const glm::dvec3 centre(0.5, b.uniform(-0.5, 1.5), depth * b.uniform(0.3, 0.7));
        const glm::dvec3 n = glm::normalize(glm::dvec3(b.uniform(-0.05, 0.05), 1.0, b.uniform(-0.3, 0.3)));
        const glm::dvec3 t1 = glm::normalize(glm::cross(n, glm::dvec3(0, 0, 1))), t2 = glm::cross(n, t1);
        b.triangle(centre - size * t1 - size * t2, centre + size * t1 - size * 0.3 * t2, centre + size * 0.2 * t1 + size * t2);
        // Huge triangles nearly parallel to the patches with an edge through the shaft: their
        // ends are far out, the edge is near, and they stay in the slab between the patches.
        for (int k = 0; k < 2; ++k) {
            const double z = depth * b.uniform(0.2, 0.8), tilt = 0.1 * std::min(z, depth - z) / size;
            const glm::dvec3 p(b.uniform(0, 1), b.uniform(0, 1), z);
            const double angle = b.uniform(0, 2 * M_PI);
            const glm::dvec3 along(std::cos(angle), std::sin(angle), b.uniform(-tilt, tilt));
            const glm::dvec3 across(-std::sin(angle), std::cos(angle), b.uniform(-tilt, tilt));
            b.triangle(p - size * along, p + size * along, p + (b.coin() ? 1.0 : -1.0) * size * across);
        }
        // Terrain: a few huge triangles with far vertices, crossing the shaft at random.
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p(b.uniform(-1, 2), b.uniform(-1, 2), b.uniform(0.5, depth - 0.5));
            b.triangle(p + b.jitter(size), p + b.jitter(size), p + b.jitter(size));
        }
        for (int k = 0; k < 20; ++k) {
            const glm::dvec3 p(b.uniform(-1, 2), b.uniform(-1, 2), b.uniform(0.3, depth - 0.3));
            b.triangle(p, p + b.jitter(0.5), p + b.jitter(0.5));
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::LongThinSource: {
        const double depth = b.uniform(4.0, 12.0);
        const Patch source = patch({0, 0, 0}, {10.0, 0, 0}, {0, 0.01, 0}, 32, 1);
        const Patch receiver = patch({b.uniform(2, 6), b.uniform(-1.5, 0), depth}, {b.uniform(1, 3), b.uniform(-0.3, 0.3), 0},
                                     {0, b.uniform(1, 3), b.uniform(-0.5, 0.5)}, side, side);
        for (int k = 0; k < 50; ++k) {
            const glm::dvec3 p(b.uniform(-1, 11), b.uniform(-1.5, 1.5), b.uniform(0.2, depth - 0.2));
            b.triangle(p, p + b.jitter(0.6), p + b.jitter(0.6));
        }
        for (int k = 0; k < 6; ++k) {   // posts along the source
            const double x = b.uniform(0, 10), z = b.uniform(0.5, depth - 0.5);
            b.quad({x, -2, z}, {0.05, 0, 0}, {0, 4, 0});
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::StandingOnSource: {
        const double depth = b.uniform(3.0, 8.0);
        const Patch source = patch({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({b.uniform(-1, 1), b.uniform(-1, 1), depth}, {b.uniform(1, 2.5), 0, b.uniform(-0.6, 0.6)},
                                     {0, b.uniform(1, 2.5), b.uniform(-0.4, 0.4)}, side, side);
        for (int k = 0; k < 3; ++k) {
            // A wall perpendicular to the source through the sample positions of one column (or
            // row), or 1 mm past them; it reaches below the source plane.
            const int column = b.pick(32);
            const double at = (column + 0.5) / 32.0 + (b.coin() ? 0.0 : (b.coin() ? 1e-3 : -1e-3));
            // Tall (up to 15/16 of the way to the receiver) and some very wide: their
            // backprojections reach far out on the source plane.
            const double height = depth * b.uniform(0.3, 0.94), below = b.coin() ? 0.5 : 0.0;
            const double width = b.coin() ? 2.0 : 100.0;
            if (b.coin())
                b.quad({at, 0.5 - 0.5 * width, -below}, {0, width, 0}, {0, 0, height + below});
            else
                b.quad({0.5 - 0.5 * width, at, -below}, {width, 0, 0}, {0, 0, height + below});
        }
        for (int k = 0; k < 10; ++k) {
            const glm::dvec3 p(b.uniform(-0.5, 1.5), b.uniform(-0.5, 1.5), b.uniform(0.3, depth - 0.3));
            b.triangle(p, p + b.jitter(0.4), p + b.jitter(0.4));
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::ClosedMeshes: {
        const double depth = b.uniform(4.0, 10.0);
        const Patch source = patch({-0.5, -0.5, 0}, {1, 0, 0}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({-1, -1, depth}, {2, 0, b.uniform(-0.3, 0.3)}, {0, 2, 0}, side, side);
        for (int k = 0; k < 6; ++k) {
            // Boxes centred on the shaft's axis (so rays leave through their diagonals and edges),
            // some axis-aligned, some turned, some touching each other.
            const double z = b.uniform(1.0, depth - 1.0);
            glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(b.coin() ? 0.0 : b.uniform(-0.4, 0.4),
                                                                       b.coin() ? 0.0 : b.uniform(-0.4, 0.4), z));
            if (b.coin())
                m = m * detail::CaseBuilder::rotation(b.coin() ? 0.25 * M_PI : b.uniform(0, M_PI), b.jitter(1.0) + glm::dvec3(0, 0, 0.1));
            glm::dvec3 scale(b.uniform(0.1, 0.8), b.uniform(0.1, 0.8), b.uniform(0.1, 0.8));
            if (b.coin(0.3))
                scale[b.pick(3)] *= -1.0;   // mirrored: the winding is flipped back by worldTriangles
            b.instance(detail::CaseBuilder::box(true), glm::scale(m, scale));
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::MirroredPlanes: {
        const double depth = b.uniform(4.0, 10.0);
        const Patch source = patch({-0.5, -0.5, 0}, {1, 0, 0}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({-1, -1, depth}, {2, 0, 0}, {0, 2, b.uniform(-0.3, 0.3)}, side, side);
        for (int k = 0; k < 4; ++k) {
            // The plane mesh (XZ, normal +Y) turned to face the source, mirrored on a random axis.
            glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, b.uniform(1.0, depth - 1.0)));
            m = m * detail::CaseBuilder::rotation(0.5 * M_PI, {1, 0, 0});
            if (b.coin())
                m = m * detail::CaseBuilder::rotation(b.uniform(0, 2 * M_PI), {0, 1, 0});
            glm::dvec3 scale(b.uniform(0.3, 1.2), 1.0, b.uniform(0.3, 1.2));
            scale[b.pick(3)] *= -1.0;
            b.instance(detail::CaseBuilder::plane(), glm::scale(m, scale));
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::KilometreCrossing: {
        const double depth = b.uniform(5.0, 15.0);
        const Patch source = patch({0, 0, 0}, {1, 0, 0}, {0, 1, b.uniform(-0.3, 0.3)}, 32, 32);
        const Patch receiver = patch({b.uniform(-1, 1), b.uniform(-1, 1), depth},
                                     {b.uniform(1.0, 2.5), b.uniform(-0.5, 0.5), b.uniform(-0.8, 0.8)},
                                     {b.uniform(-0.3, 0.3), b.uniform(1.0, 2.5), b.uniform(-0.8, 0.8)}, side, side);
        for (int k = 0; k < 4; ++k) {
            // Through the shaft, crossing both patch planes: vertices a kilometre out on either side.
            const glm::dvec3 p(b.uniform(0, 1), b.uniform(0, 1), b.uniform(1, depth - 1));
            const glm::dvec3 along = glm::normalize(glm::dvec3(b.uniform(-0.3, 0.3), b.uniform(-0.3, 0.3), 1.0));
            const glm::dvec3 across = glm::normalize(glm::cross(along, b.jitter(1.0)));
            const double km = b.uniform(1e3, 5e3);
            b.triangle(p - km * along + b.jitter(2.0), p + km * along + b.jitter(2.0), p + km * across);
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::EdgeOnFins: {
        // Aligned grids: source row b and receiver row b' share their y when the receiver's rows
        // line up with the source's, so the plane y = const holds every ray between those rows.
        const double depth = b.uniform(3.0, 10.0);
        const int rows = 32;
        const Patch source = patch({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 32, rows);
        const Patch receiver = patch({b.uniform(-0.5, 0.5), 0, depth}, {b.uniform(1, 2), 0, b.uniform(-0.5, 0.5)},
                                     {0, 1, 0}, side, rows);
        for (int k = 0; k < 8; ++k) {
            const double y = (b.pick(rows) + 0.5) / rows;
            const double z0 = b.uniform(0.3, depth - 1.0), z1 = z0 + b.uniform(0.2, 0.8);
            const double x0 = b.uniform(-0.5, 1.0), x1 = x0 + b.uniform(0.05, 0.6);
            if (b.coin())
                b.triangle({x0, y, z0}, {x1, y, z0 + b.uniform(-0.1, 0.1)}, {b.uniform(x0, x1), y, z1});
            else   // just off the plane
                b.triangle({x0, y, z0}, {x1, y + 1e-4, z0}, {b.uniform(x0, x1), y - 1e-4, z1});
        }
        // Fins in planes through source columns and receiver columns (x = const when the
        // columns line up): planes x = c that hold rays of equal x.
        for (int k = 0; k < 4; ++k) {
            const double x = (b.pick(32) + 0.5) / 32.0;
            const double z0 = b.uniform(0.3, depth - 1.0);
            b.triangle({x, b.uniform(-0.2, 0.5), z0}, {x, b.uniform(0.5, 1.2), z0 + 0.3}, {x, 0.5, z0 + b.uniform(0.3, 0.9)});
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::NearReceiver: {
        const double depth = b.uniform(3.0, 8.0);
        const Patch source = patch({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({-0.5, -0.5, depth}, {2, 0, b.uniform(-0.4, 0.4)}, {0, 2, 0}, side, side);
        const glm::dvec3 n = glm::normalize(glm::cross(receiver.u, receiver.v));
        for (int k = 0; k < 30; ++k) {
            // Points a hair above, on, or through the receiver plane.
            const glm::dvec3 on = receiver.corner + b.uniform(0, 1) * receiver.u + b.uniform(0, 1) * receiver.v;
            const double lift = b.coin(0.3) ? 0.0 : -std::pow(10.0, -b.uniform(1.0, 6.0));   // towards the source
            const glm::dvec3 p = on + lift * n;
            b.triangle(p, p + b.jitter(0.15) - 0.05 * n * b.uniform(0, 1), p + b.jitter(0.15) + 0.05 * n * b.uniform(-1, 1));
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::RandomSoup: {
        const Patch source = patch({b.uniform(-0.2, 0.2), b.uniform(-0.2, 0.2), 0.0},
                                   {b.uniform(0.6, 1.5), 0.0, b.uniform(-0.3, 0.3)},
                                   {b.uniform(-0.2, 0.2), b.uniform(0.6, 1.5), b.uniform(-0.3, 0.3)}, 32, 32);
        const double depth = b.uniform(3.0, 6.0);
        const Patch receiver = patch({b.uniform(-1, 1), b.uniform(-1, 1), depth},
                                     {b.uniform(0.8, 2.5), b.uniform(-0.4, 0.4), b.uniform(-0.5, 0.5)},
                                     {0.0, b.uniform(0.8, 2.5), b.uniform(-0.5, 0.5)}, side, side);
        const auto point = [&](double zLo, double zHi) { return glm::dvec3(b.uniform(-1, 2.5), b.uniform(-1, 2.5), b.uniform(zLo, zHi)); };
        for (int t = 0; t < 60; ++t) {
            const glm::dvec3 p = point(0.3, depth - 0.3);
            b.triangle(p, p + b.jitter(0.05), p + b.jitter(0.05));
        }
        for (int t = 0; t < 25; ++t) {
            const glm::dvec3 p = point(0.3, depth - 0.3);
            b.triangle(p, p + b.jitter(0.6), p + b.jitter(0.6));
        }
        for (int t = 0; t < 3; ++t) {
            const glm::dvec3 p = point(-1.0, depth + 1.0);
            b.triangle(p, p + b.jitter(6.0), p + b.jitter(6.0));
        }
        return b.finish(name, source, receiver);
    }
    case Adversary::SharedDiagonal: {
        const double depth = b.uniform(3.0, 10.0);
        const Patch source = patch({-0.5, -0.5, 0}, {1, 0, 0}, {0, 1, 0}, 32, 32);
        const Patch receiver = patch({-0.5, -0.5, depth}, {1, 0, 0}, {0, 1, b.coin() ? 0.0 : b.uniform(-0.3, 0.3)}, side, side);
        for (int k = 0; k < 3; ++k) {
            // A square wall centred on the axis, its diagonal through the patch centres' line,
            // with a hole pattern made by leaving some squares out.
            const double z = b.uniform(0.5, depth - 0.5), half = b.uniform(0.05, 0.6);
            const double angle = b.coin() ? 0.0 : b.uniform(0, M_PI);
            const glm::dvec3 e1(half * std::cos(angle), half * std::sin(angle), 0), e2(-e1.y, e1.x, 0);
            const glm::dvec3 c(0, 0, z);
            b.triangle(c - e1 - e2, c + e1 - e2, c + e1 + e2);
            b.triangle(c - e1 - e2, c + e1 + e2, c - e1 + e2);
        }
        return b.finish(name, source, receiver);
    }
    }
    return {};
}

/// World triangles of a case, with the receiver heights applied when given (for the judge).
inline std::vector<glm::dvec3> displacedSamples(const Patch& source, const Patch& receiver, const ReceiverHeights& heights)
{
    std::vector<glm::dvec3> out;
    for (int j = 0; j < receiver.sampleCount(); ++j)
        out.push_back(displacedReceiverSample(source, receiver, heights, j));
    return out;
}

/// Seeded bumps for a receiver: a few smooth hills up to `metres` towards the source.
inline ReceiverHeights randomHeights(const Patch& receiver, unsigned seed, double metres)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    ReceiverHeights h;
    h.metres.resize(std::size_t(receiver.sampleCount()));
    const double ax = unit(rng), ay = unit(rng), fx = 1 + 5 * unit(rng), fy = 1 + 5 * unit(rng);
    for (int b = 0; b < receiver.nb; ++b)
        for (int a = 0; a < receiver.na; ++a) {
            const double x = (a + 0.5) / receiver.na, y = (b + 0.5) / receiver.nb;
            h.metres[std::size_t(b * receiver.na + a)] =
                metres * 0.5 * (1.0 + std::sin(fx * x * 6.283 + ax * 6.283) * std::cos(fy * y * 6.283 + ay * 6.283));
        }
    return h;
}

} // namespace sightline::test
