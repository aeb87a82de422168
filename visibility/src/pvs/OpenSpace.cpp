#include "visibility/pvs/OpenSpace.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <utility>

#include <glm/geometric.hpp>

#include "base/UnionFind.h"
#include "visibility/bsp/PortalVis.h"
#include "visibility/pvs/PvsData.h"
#include "visibility/pvs/ShaftProof.h"

namespace sightline::pvs {

namespace {

using Box = OpenSpace::Box;

/// The portal vis's windings are in millimetres about the root's centre: its fixed margin
/// (bsp::kPortalOnPlane, a thousandth of a unit) is then a micrometre, and kilometre coordinates
/// keep their digits.
constexpr double kVisScale = 1000.0;

bool boxesMeet(const Box& a, const Box& b)
{
    for (int k = 0; k < 3; ++k)
        if (a.lo[k] > b.hi[k] || b.lo[k] > a.hi[k])
            return false;
    return true;
}

double overlapArea(const glm::dvec2& lo1, const glm::dvec2& hi1, const glm::dvec2& lo2, const glm::dvec2& hi2)
{
    const double w = std::min(hi1.x, hi2.x) - std::max(lo1.x, lo2.x);
    const double h = std::min(hi1.y, hi2.y) - std::max(lo1.y, lo2.y);
    return w > 0.0 && h > 0.0 ? w * h : 0.0;
}

glm::dvec2 crossSection(const glm::dvec3& p, int axis) { return {p[(axis + 1) % 3], p[(axis + 2) % 3]}; }

using Polygon = std::vector<glm::dvec2>;   // convex, counter-clockwise
using Triangle2 = std::array<glm::dvec2, 3>;

struct Passage {
    std::uint32_t low = 0, high = 0;   ///< leaves below and above the plane
    int axis = 0;
    double offset = 0.0;
    Polygon opening;                   ///< in the plane's coordinates
};

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

double polygonArea(const Polygon& p)
{
    double twice = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
        twice += cross2(p[i], p[(i + 1) % p.size()]);
    return 0.5 * twice;
}

/// `p` cut to the closed half-plane on the left of a -> b (sign +1) or on its right (sign -1).
Polygon clipToSide(const Polygon& p, const glm::dvec2& a, const glm::dvec2& b, double sign)
{
    Polygon out;
    const auto side = [&](const glm::dvec2& x) { return sign * cross2(b - a, x - a); };
    for (std::size_t i = 0; i < p.size(); ++i) {
        const glm::dvec2& u = p[i];
        const glm::dvec2& v = p[(i + 1) % p.size()];
        const double su = side(u), sv = side(v);
        if (su >= 0.0)
            out.push_back(u);
        if ((su > 0.0 && sv < 0.0) || (su < 0.0 && sv > 0.0))
            out.push_back(u + (su / (su - sv)) * (v - u));
    }
    return out;
}

/// The triangles on one plane (every region of it, either facing), counter-clockwise, and its regions.
struct PlaneTriangles {
    std::vector<Triangle2> triangles;
    std::vector<std::array<glm::dvec2, 2>> bounds;
    std::vector<std::uint32_t> regions;
    std::vector<std::array<glm::dvec2, 2>> regionBounds;
};

/// The pieces of the closed rectangle `rect` that the triangles `candidates` (those meeting it)
/// leave uncovered, each cut out in turn; a piece thinner than `thin` (area over its longest edge)
/// is dropped: what no closed triangle covers is open in the rectangle, so it has area, and
/// triangles that meet along an edge leave only rounding. False past kMaxPieces (the caller then
/// halves the rectangle).
bool cutOut(const PlaneTriangles& plane, const std::vector<std::uint32_t>& candidates, const Polygon& rect, double thin,
            std::vector<Polygon>& out)
{
    constexpr std::size_t kMaxPieces = 64;
    std::vector<Polygon> pieces{rect};
    for (std::uint32_t t : candidates) {
        const Triangle2& tri = plane.triangles[t];
        std::vector<Polygon> next;
        for (const Polygon& piece : pieces) {
            Polygon inside = piece;
            for (int e = 0; e < 3 && inside.size() >= 3; ++e) {
                const glm::dvec2& a = tri[std::size_t(e)];
                const glm::dvec2& b = tri[std::size_t((e + 1) % 3)];
                Polygon outside = clipToSide(inside, a, b, -1.0);
                inside = clipToSide(inside, a, b, 1.0);
                double longest = 0.0;
                for (std::size_t i = 0; i < outside.size(); ++i)
                    longest = std::max(longest, glm::length(outside[(i + 1) % outside.size()] - outside[i]));
                if (outside.size() >= 3 && polygonArea(outside) > thin * longest)
                    next.push_back(std::move(outside));
            }
        }
        pieces = std::move(next);
        if (pieces.size() > kMaxPieces)
            return false;
    }
    out.insert(out.end(), pieces.begin(), pieces.end());
    return true;
}

/// What of the closed rectangle lo..hi the plane's triangles leave uncovered, as pieces whose union
/// holds every such point: a rectangle one region covers whole (ShaftProver::regionCovers) is
/// covered; one that few triangles meet is cut exactly (cutOut); others are halved, down to
/// `depth` halvings or until `budget` calls are spent, past which the rectangle is kept whole
/// (open: still safe).
void uncovered(const ShaftProver& prover, const PlaneTriangles& plane, const std::vector<std::uint32_t>& meeting,
               const glm::dvec2& lo, const glm::dvec2& hi, double thin, int depth, std::size_t& budget,
               std::vector<Polygon>& out)
{
    constexpr std::size_t kCutTriangles = 12;
    const Polygon rect{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    std::vector<std::uint32_t> here;
    for (std::uint32_t t : meeting) {
        const auto& box = plane.bounds[t];
        if (box[1].x >= lo.x && box[0].x <= hi.x && box[1].y >= lo.y && box[0].y <= hi.y)
            here.push_back(t);
    }
    if (here.empty()) {
        out.push_back(rect);
        return;
    }
    for (std::size_t k = 0; k < plane.regions.size(); ++k) {
        const auto& box = plane.regionBounds[k];
        if (box[0].x <= lo.x && box[0].y <= lo.y && box[1].x >= hi.x && box[1].y >= hi.y &&
            prover.regionCovers(plane.regions[k], lo, hi))
            return;
    }
    if (here.size() <= kCutTriangles && cutOut(plane, here, rect, thin, out))
        return;
    if (depth == 0 || budget < 2) {
        out.push_back(rect);
        return;
    }
    budget -= 2;
    const int k = hi.x - lo.x >= hi.y - lo.y ? 0 : 1;
    glm::dvec2 midHi = hi, midLo = lo;
    midHi[k] = midLo[k] = 0.5 * (lo[k] + hi[k]);
    uncovered(prover, plane, here, lo, midHi, thin, depth - 1, budget, out);
    uncovered(prover, plane, here, midLo, hi, thin, depth - 1, budget, out);
}

/// What the plane leaves open of lo..hi (a wall's passage becomes its doorways): the convex hulls
/// of the groups of uncovered pieces that touch (at most kMaxOpenings, else one hull of all); empty
/// when all of it is covered.
std::vector<Polygon> openingsOf(const ShaftProver& prover, const PlaneTriangles& plane, const glm::dvec2& lo,
                                const glm::dvec2& hi, double thin)
{
    constexpr int kDepth = 16;
    constexpr std::size_t kMaxOpenings = 8, kMaxGrouped = 256;
    std::size_t budget = 4096;   // rectangles halved per passage
    std::vector<std::uint32_t> all(plane.triangles.size());
    std::iota(all.begin(), all.end(), std::uint32_t(0));
    std::vector<Polygon> pieces;
    uncovered(prover, plane, all, lo, hi, thin, kDepth, budget, pieces);
    std::vector<std::array<glm::dvec2, 2>> boxes;
    for (const Polygon& piece : pieces) {
        std::array<glm::dvec2, 2> box{piece[0], piece[0]};
        for (const glm::dvec2& p : piece)
            box = {glm::min(box[0], p), glm::max(box[1], p)};
        boxes.push_back(box);
    }
    UnionFind groups(pieces.size());
    const double touch = thin * 4.0;
    for (std::size_t i = 1; i < pieces.size(); ++i)
        for (std::size_t j = pieces.size() > kMaxGrouped ? i - 1 : 0; j < i; ++j)
            if (pieces.size() > kMaxGrouped || (boxes[i][0].x <= boxes[j][1].x + touch && boxes[j][0].x <= boxes[i][1].x + touch &&
                                                boxes[i][0].y <= boxes[j][1].y + touch && boxes[j][0].y <= boxes[i][1].y + touch))
                groups.join(std::uint32_t(i), std::uint32_t(j));
    std::map<std::uint32_t, std::vector<glm::dvec2>> points;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        auto& group = points[groups.find(std::uint32_t(i))];
        group.insert(group.end(), pieces[i].begin(), pieces[i].end());
    }
    std::vector<Polygon> out;
    if (points.size() > kMaxOpenings) {
        std::vector<glm::dvec2> every;
        for (const auto& [group, p] : points)
            every.insert(every.end(), p.begin(), p.end());
        points = {{0, every}};
    }
    for (const auto& [group, p] : points) {
        Polygon hull = convexHull(p);
        if (hull.size() >= 3)
            out.push_back(std::move(hull));
    }
    return out;
}

/// The triangles of every region, by plane (axis, offset).
std::map<std::pair<int, double>, PlaneTriangles> trianglesByPlane(const ShaftProver& prover)
{
    std::map<std::pair<int, double>, PlaneTriangles> onPlane;
    for (std::size_t r = 0; r < prover.regionCount(); ++r) {
        const auto p = prover.regionPlane(r);
        PlaneTriangles& plane = onPlane[{p.axis, p.offset}];
        plane.regions.push_back(std::uint32_t(r));
        plane.regionBounds.push_back({p.lo, p.hi});
        for (Triangle2 t : prover.regionTriangles(r)) {
            const double twice = cross2(t[1] - t[0], t[2] - t[0]);
            if (twice == 0.0)
                continue;
            if (twice < 0.0)
                std::swap(t[1], t[2]);
            plane.triangles.push_back(t);
            plane.bounds.push_back({glm::min(t[0], glm::min(t[1], t[2])), glm::max(t[0], glm::max(t[1], t[2]))});
        }
    }
    return onPlane;
}

/// The passages of the tree's leaves: under each split, the leaves on either side that touch its
/// plane, pairwise, each with what the plane's triangles leave open of it (none: sealed, counted);
/// the leaves an open one joins are joined in `parts`.
std::vector<Passage> openPassages(const std::vector<OpenSpace::Node>& nodes, const std::vector<std::uint32_t>& leafNode,
                                  const ShaftProver& prover, double thin, UnionFind& parts, OpenSpaceStats& stats)
{
    const auto onPlane = trianglesByPlane(prover);
    std::vector<Passage> open;
    using Node = OpenSpace::Node;
    for (const Node& node : nodes) {
        if (node.axis < 0)
            continue;
        const int axis = node.axis;
        std::vector<std::uint32_t> below, above;
        const auto touching = [&](std::uint32_t subtree, int side, std::vector<std::uint32_t>& out) {
            std::vector<std::uint32_t> stack{subtree};
            while (!stack.empty()) {
                const Node& m = nodes[stack.back()];
                stack.pop_back();
                if ((side == 0 ? m.box.hi[axis] : m.box.lo[axis]) != node.split)
                    continue;
                if (m.axis < 0)
                    out.push_back(std::uint32_t(m.leaf));
                else {
                    stack.push_back(m.child[0]);
                    stack.push_back(m.child[1]);
                }
            }
        };
        touching(node.child[0], 0, below);
        touching(node.child[1], 1, above);
        const auto plane = onPlane.find({axis, node.split});
        for (std::uint32_t l : below)
            for (std::uint32_t h : above) {
                const Box& a = nodes[leafNode[l]].box;
                const Box& b = nodes[leafNode[h]].box;
                const glm::dvec2 lo = glm::max(crossSection(a.lo, axis), crossSection(b.lo, axis));
                const glm::dvec2 hi = glm::min(crossSection(a.hi, axis), crossSection(b.hi, axis));
                if (!(hi.x > lo.x && hi.y > lo.y))
                    continue;
                ++stats.passages;
                std::vector<Polygon> openings{{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}};
                if (plane != onPlane.end()) {
                    openings = openingsOf(prover, plane->second, lo, hi, thin);
                    if (openings.empty()) {
                        ++stats.sealedPassages;
                        continue;
                    }
                }
                for (Polygon& opening : openings)
                    open.push_back({l, h, axis, node.split, std::move(opening)});
                parts.join(l, h);
            }
    }
    return open;
}

double elapsedMs(std::chrono::steady_clock::time_point since)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

} // namespace

bool triangleMeetsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const Box& box, double margin)
{
    const glm::dvec3 centre = 0.5 * (box.lo + box.hi);
    const glm::dvec3 half = 0.5 * (box.hi - box.lo) + glm::dvec3(margin);
    const glm::dvec3 v[3] = {a - centre, b - centre, c - centre};
    const auto separates = [&](const glm::dvec3& axis) {
        const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
        const double r = half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
        return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
    };
    for (int k = 0; k < 3; ++k) {
        glm::dvec3 axis(0.0);
        axis[k] = 1.0;
        if (separates(axis))
            return false;
    }
    const glm::dvec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    if (separates(glm::cross(edges[0], edges[1])))
        return false;
    for (const glm::dvec3& e : edges)
        for (int k = 0; k < 3; ++k) {
            glm::dvec3 unit(0.0);
            unit[k] = 1.0;
            if (separates(glm::cross(e, unit)))
                return false;
        }
    return true;
}

template <class Test>
void OpenSpace::leavesWhere(const Test& meets, std::vector<std::uint32_t>& out) const
{
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const Node& node = nodes_[stack.back()];
        stack.pop_back();
        if (!meets(node.box))
            continue;
        if (node.axis < 0)
            out.push_back(std::uint32_t(node.leaf));
        else {
            stack.push_back(node.child[1]);
            stack.push_back(node.child[0]);
        }
    }
}

void OpenSpace::leavesMeeting(const Box& box, std::vector<std::uint32_t>& out) const
{
    leavesWhere([&](const Box& b) { return boxesMeet(b, box); }, out);
}

/// The kd-tree: nodes split, in order of the region area their best plane holds, at that plane
/// (regions of bounds at least minSplitArea only) until no such plane crosses a node or the
/// leaves reach maxLeaves.
void OpenSpace::build(const ShaftProver& prover, const Box& root, const OpenSpaceLimits& limits)
{
    std::vector<ShaftProver::RegionPlane> planes(prover.regionCount());
    for (std::size_t r = 0; r < planes.size(); ++r)
        planes[r] = prover.regionPlane(r);
    struct Choice {
        double area = 0.0;
        int axis = -1;
        double offset = 0.0;
    };
    // The regions whose plane crosses the node's inside and whose bounds overlap its cross-section.
    const auto crossing = [&](const Box& box, const std::vector<std::uint32_t>& from) {
        std::vector<std::uint32_t> out;
        for (std::uint32_t r : from) {
            const auto& p = planes[r];
            if (p.offset > box.lo[p.axis] && p.offset < box.hi[p.axis] &&
                overlapArea(p.lo, p.hi, crossSection(box.lo, p.axis), crossSection(box.hi, p.axis)) > 0.0)
                out.push_back(r);
        }
        return out;
    };
    const auto choose = [&](const Box& box, const std::vector<std::uint32_t>& regions) {
        std::map<std::pair<int, double>, double> area;
        for (std::uint32_t r : regions) {
            const auto& p = planes[r];
            area[{p.axis, p.offset}] += overlapArea(p.lo, p.hi, crossSection(box.lo, p.axis), crossSection(box.hi, p.axis));
        }
        Choice best;
        for (const auto& [plane, a] : area)
            if (a > best.area)
                best = {a, plane.first, plane.second};
        return best;
    };
    std::vector<std::vector<std::uint32_t>> regionsOf;
    std::vector<Choice> choiceOf;
    nodes_.assign(1, Node{root});
    std::vector<std::uint32_t> all;
    for (std::size_t r = 0; r < planes.size(); ++r)
        if ((planes[r].hi.x - planes[r].lo.x) * (planes[r].hi.y - planes[r].lo.y) >= limits.minSplitArea)
            all.push_back(std::uint32_t(r));
    regionsOf.push_back(crossing(root, all));
    choiceOf.push_back(choose(root, regionsOf[0]));
    // Largest area first; ties by node index: deterministic.
    const auto later = [&](std::uint32_t a, std::uint32_t b) {
        return choiceOf[a].area != choiceOf[b].area ? choiceOf[a].area < choiceOf[b].area : a > b;
    };
    std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, decltype(later)> queue(later);
    if (choiceOf[0].axis >= 0)
        queue.push(0);
    std::size_t leaves = 1;
    while (!queue.empty() && leaves < limits.maxLeaves) {
        const std::uint32_t n = queue.top();
        queue.pop();
        const Choice choice = choiceOf[n];
        const std::vector<std::uint32_t> regions = std::move(regionsOf[n]);
        Box halves[2] = {nodes_[n].box, nodes_[n].box};
        halves[0].hi[choice.axis] = choice.offset;
        halves[1].lo[choice.axis] = choice.offset;
        nodes_[n].axis = choice.axis;
        nodes_[n].split = choice.offset;
        for (int side = 0; side < 2; ++side) {
            const std::uint32_t child = std::uint32_t(nodes_.size());
            nodes_[n].child[side] = child;
            nodes_.push_back(Node{halves[side]});
            regionsOf.push_back(crossing(halves[side], regions));
            choiceOf.push_back(choose(halves[side], regionsOf.back()));
            if (choiceOf.back().axis >= 0)
                queue.push(child);
        }
        ++leaves;
    }
    for (std::size_t n = 0; n < nodes_.size(); ++n)
        if (nodes_[n].axis < 0) {
            nodes_[n].leaf = std::int32_t(leafNode_.size());
            leafNode_.push_back(std::uint32_t(n));
        }
}

OpenSpace::OpenSpace(const ShaftProver& prover, const Bounds& sceneBounds, const std::vector<std::vector<glm::vec3>>& objects,
                     const std::vector<Bounds>& sources, const OpenSpaceLimits& limits)
    : objectCount_(objects.size())
{
    const auto start = std::chrono::steady_clock::now();
    Bounds around = sceneBounds;
    for (const Bounds& b : sources)
        around.extend(b);
    if (around.empty()) {
        nodes_.assign(1, Node{});
        return;
    }
    Box root{glm::dvec3(around.min), glm::dvec3(around.max)};
    const double grow = 0.01 * glm::length(root.hi - root.lo) + 1e-3;
    root.lo -= glm::dvec3(grow);
    root.hi += glm::dvec3(grow);
    build(prover, root, limits);
    const std::size_t leafCount = leafNode_.size();
    stats_.leaves = leafCount;

    // Rounding's scale: float vertices at the root's coordinates.
    const double thin = 1e-9 * (1.0 + std::max(glm::length(root.lo), glm::length(root.hi)));
    UnionFind parts(leafCount);
    const std::vector<Passage> open = openPassages(nodes_, leafNode_, prover, thin, parts, stats_);

    // The parts the sources touch, and their leaves numbered from 1 for the vis.
    std::vector<char> sourcePart(leafCount, 0);
    std::vector<std::uint32_t> meeting;
    for (const Bounds& s : sources) {
        if (s.empty())
            continue;
        meeting.clear();
        leavesMeeting({glm::dvec3(s.min), glm::dvec3(s.max)}, meeting);
        for (std::uint32_t l : meeting)
            sourcePart[parts.find(l)] = 1;
    }
    openIndex_.assign(leafCount, -1);
    std::vector<std::uint32_t> openLeaves;
    for (std::uint32_t l = 0; l < leafCount; ++l)
        if (sourcePart[parts.find(l)]) {
            openIndex_[l] = std::int32_t(openLeaves.size());
            openLeaves.push_back(l);
        }
    for (std::uint32_t l = 0; l < leafCount; ++l)
        stats_.parts += std::size_t(sourcePart[l] && parts.find(l) == l);
    std::vector<bsp::LeafPortal> portals;
    const glm::dvec3 centre = 0.5 * (root.lo + root.hi);
    for (const Passage& p : open) {
        if (openIndex_[p.low] < 0)
            continue;
        const int a = (p.axis + 1) % 3, b = (p.axis + 2) % 3;
        const auto corner = [&](double x, double y) {
            glm::dvec3 v(0.0);
            v[p.axis] = p.offset;
            v[a] = x;
            v[b] = y;
            return kVisScale * (v - centre);
        };
        bsp::LeafPortal portal;
        portal.leaves = {openIndex_[p.high] + 1, openIndex_[p.low] + 1};
        portal.plane.normal[p.axis] = 1.0;
        portal.plane.dist = kVisScale * (p.offset - centre[p.axis]);
        for (const glm::dvec2& q : p.opening)
            portal.winding.push_back(corner(q.x, q.y));
        portals.push_back(std::move(portal));
    }
    stats_.openLeaves = openLeaves.size();
    stats_.openPortals = portals.size();
    stats_.buildMs = elapsedMs(start);

    // Which objects each open leaf's closed box meets.
    const double margin = 1e-9 * (1.0 + glm::length(root.hi - root.lo) + glm::length(centre));
    std::vector<std::vector<std::uint32_t>> objectsIn(openLeaves.size());
    for (std::size_t o = 0; o < objects.size(); ++o) {
        const std::vector<glm::vec3>& soup = objects[o];
        meeting.clear();
        for (std::size_t t = 0; t + 2 < soup.size(); t += 3) {
            const glm::dvec3 a(soup[t]), b(soup[t + 1]), c(soup[t + 2]);
            leavesWhere([&](const Box& box) { return triangleMeetsBox(a, b, c, box, margin); }, meeting);
        }
        std::sort(meeting.begin(), meeting.end());
        meeting.erase(std::unique(meeting.begin(), meeting.end()), meeting.end());
        for (std::uint32_t l : meeting)
            if (openIndex_[l] >= 0)
                objectsIn[std::size_t(openIndex_[l])].push_back(std::uint32_t(o));
    }

    // Each open leaf's row: the leaves the vis says it reaches, or its whole part.
    const auto visStart = std::chrono::steady_clock::now();
    const std::size_t n = openLeaves.size(), rowBytes = (objectCount_ + 7) / 8;
    objectRows_.assign(n * rowBytes, 0);
    const auto addObjects = [&](std::size_t row, std::size_t leaf) {
        for (std::uint32_t o : objectsIn[leaf])
            objectRows_[row * rowBytes + o / 8] |= std::uint8_t(1u << (o % 8));
    };
    stats_.portalVis = n <= limits.maxVisLeaves && portals.size() <= limits.maxVisPortals;
    if (stats_.portalVis) {
        leafRows_ = bsp::portalVis(int(n), portals, {.stepsPerPortal = limits.stepsPerPortal, .threads = limits.threads});
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                if (leafRows_.visible(i, j))
                    addObjects(i, j);
    } else {
        for (std::uint32_t l : openLeaves)
            partOf_.push_back(parts.find(l));
        std::map<std::uint32_t, std::vector<std::uint8_t>> partRows;
        for (std::size_t i = 0; i < n; ++i) {
            auto& row = partRows[parts.find(openLeaves[i])];
            row.resize(rowBytes, 0);
            for (std::uint32_t o : objectsIn[i])
                row[o / 8] |= std::uint8_t(1u << (o % 8));
        }
        for (std::size_t i = 0; i < n; ++i) {
            const auto& row = partRows[parts.find(openLeaves[i])];
            std::copy(row.begin(), row.end(), objectRows_.begin() + std::ptrdiff_t(i * rowBytes));
        }
    }
    stats_.visMs = elapsedMs(visStart);
}

bool OpenSpace::inside(const Bounds& box) const
{
    if (box.empty() || leafNode_.empty())
        return false;
    const Box& root = nodes_[0].box;
    for (int k = 0; k < 3; ++k)
        if (double(box.min[k]) < root.lo[k] || double(box.max[k]) > root.hi[k])
            return false;
    return true;
}

std::vector<char> OpenSpace::reachableFrom(const Bounds& from) const
{
    if (!inside(from))
        return {};
    std::vector<std::uint32_t> meeting;
    leavesMeeting({glm::dvec3(from.min), glm::dvec3(from.max)}, meeting);
    const std::size_t n = stats_.openLeaves;
    std::vector<char> reach(std::max<std::size_t>(n, 1), 0);
    std::vector<std::uint32_t> seedParts;
    for (std::uint32_t l : meeting) {
        if (openIndex_[l] < 0)
            return {};
        const std::size_t i = std::size_t(openIndex_[l]);
        if (stats_.portalVis)
            for (std::size_t j = 0; j < n; ++j)
                reach[j] = char(reach[j] | leafRows_.visible(i, j));
        else
            seedParts.push_back(partOf_[i]);
    }
    if (!stats_.portalVis)
        for (std::size_t j = 0; j < n; ++j)
            reach[j] = char(std::find(seedParts.begin(), seedParts.end(), partOf_[j]) != seedParts.end());
    return reach;
}

bool OpenSpace::hides(const std::vector<char>& reachable, const Bounds& target) const
{
    if (reachable.empty() || !inside(target))
        return false;
    std::vector<std::uint32_t> meeting;
    leavesMeeting({glm::dvec3(target.min), glm::dvec3(target.max)}, meeting);
    for (std::uint32_t l : meeting)
        if (openIndex_[l] >= 0 && reachable[std::size_t(openIndex_[l])])
            return false;
    return true;
}

std::vector<std::uint8_t> OpenSpace::hiddenFrom(const Bounds& box) const
{
    const std::size_t rowBytes = (objectCount_ + 7) / 8;
    std::vector<std::uint8_t> hidden(rowBytes, 0);
    if (!inside(box))
        return hidden;
    std::vector<std::uint32_t> meeting;
    leavesMeeting({glm::dvec3(box.min), glm::dvec3(box.max)}, meeting);
    std::vector<std::uint8_t> seen(rowBytes, 0);
    for (std::uint32_t l : meeting) {
        if (openIndex_[l] < 0)
            return hidden;
        const std::uint8_t* row = objectRows_.data() + std::size_t(openIndex_[l]) * rowBytes;
        for (std::size_t k = 0; k < rowBytes; ++k)
            seen[k] |= row[k];
    }
    for (std::size_t o = 0; o < objectCount_; ++o)
        if (!((seen[o / 8] >> (o % 8)) & 1u))
            hidden[o / 8] |= std::uint8_t(1u << (o % 8));
    return hidden;
}

} // namespace sightline::pvs
