#include "visibility/bsp/BspPortals.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

namespace sightline::bsp {

namespace {

/// A place in the tree: an internal node (plane >= 0) or one occurrence of a leaf. The shared
/// solid leaf 0 occurs under many nodes, each occurrence its own region.
struct TreePlace {
    int plane = -1;
    std::array<int, 2> children{-1, -1};
    int leaf = kOutside;
    std::vector<int> portals;
};

struct TreePortal {
    glm::dvec3 n{0.0};
    double d = 0.0;
    std::array<int, 2> places{};   ///< [0] in front
    Winding w;
};

struct PlaneD {
    glm::dvec3 n;
    double d;
};

PlaneD unitPlane(const BspPlane& p)
{
    const double length = glm::length(p.normal);
    return {p.normal / length, p.dist / length};
}

Winding baseWinding(const glm::dvec3& n, double d, double radius)
{
    int major = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(n[a]) > std::abs(n[major]))
            major = a;
    glm::dvec3 up = major == 2 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
    up = glm::normalize(up - n * glm::dot(up, n));
    const glm::dvec3 right = glm::cross(up, n);
    const glm::dvec3 origin = n * d;
    return {origin - right * radius + up * radius, origin + right * radius + up * radius,
            origin + right * radius - up * radius, origin - right * radius - up * radius};
}

/// Splits `w` by (n, d): points within onPlane of it go to both sides.
void split(const Winding& w, const glm::dvec3& n, double d, double onPlane, Winding& front, Winding& back)
{
    front.clear();
    back.clear();
    const std::size_t count = w.size();
    std::vector<double> dist(count);
    std::vector<int> side(count);
    for (std::size_t i = 0; i < count; ++i) {
        dist[i] = glm::dot(n, w[i]) - d;
        side[i] = dist[i] > onPlane ? 1 : dist[i] < -onPlane ? -1 : 0;
    }
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t j = (i + 1) % count;
        if (side[i] >= 0)
            front.push_back(w[i]);
        if (side[i] <= 0)
            back.push_back(w[i]);
        if (side[i] != 0 && side[j] != 0 && side[i] != side[j]) {
            const double t = dist[i] / (dist[i] - dist[j]);
            const glm::dvec3 mid = w[i] + (w[j] - w[i]) * t;
            front.push_back(mid);
            back.push_back(mid);
        }
    }
    if (front.size() < 3)
        front.clear();
    if (back.size() < 3)
        back.clear();
}

class PortalBuilder {
public:
    explicit PortalBuilder(const QuakeBsp& bsp) : bsp_(bsp) { buildPlaces(); }

    std::vector<LeafPortal> run()
    {
        headPortals();
        std::vector<int> todo{root_};
        while (!todo.empty()) {
            const int place = todo.back();
            todo.pop_back();
            if (places_[std::size_t(place)].plane < 0)
                continue;
            nodePortal(place);
            splitPortals(place);
            todo.push_back(places_[std::size_t(place)].children[1]);
            todo.push_back(places_[std::size_t(place)].children[0]);
        }
        return leafPortals();
    }

private:
    void buildPlaces()
    {
        places_.emplace_back();   // the outside, place 0
        // A place for every node and every leaf occurrence the tree reaches; the reader proved
        // that each node is reached once.
        root_ = addPlace(bsp_.headnode);
        std::vector<std::pair<int, int>> stack{{root_, bsp_.headnode}};   // (place, BSP node)
        while (!stack.empty()) {
            const auto [place, node] = stack.back();
            stack.pop_back();
            const BspNode& bn = bsp_.nodes[std::size_t(node)];
            places_[std::size_t(place)].plane = bn.plane;
            for (int s = 0; s < 2; ++s) {
                const int child = addPlace(bn.children[std::size_t(s)]);
                places_[std::size_t(place)].children[std::size_t(s)] = child;
                if (bn.children[std::size_t(s)] >= 0)
                    stack.emplace_back(child, bn.children[std::size_t(s)]);
            }
        }
    }

    int addPlace(int bspChild)
    {
        TreePlace place;
        if (bspChild < 0)
            place.leaf = QuakeBsp::leafOfChild(bspChild);
        places_.push_back(std::move(place));
        return int(places_.size()) - 1;
    }

    void addPortal(TreePortal portal)
    {
        const int id = int(portals_.size());
        places_[std::size_t(portal.places[0])].portals.push_back(id);
        places_[std::size_t(portal.places[1])].portals.push_back(id);
        portals_.push_back(std::move(portal));
    }

    void removeFrom(int place, int portal)
    {
        auto& list = places_[std::size_t(place)].portals;
        list.erase(std::find(list.begin(), list.end(), portal));
    }

    /// The level's box, enlarged, as six portals between the root and the outside, each facing in.
    void headPortals()
    {
        constexpr double kMargin = 32.0;
        const glm::dvec3 lo = bsp_.mins - kMargin, hi = bsp_.maxs + kMargin;
        radius_ = 2.0 * std::max(glm::length(lo), glm::length(hi)) + 1024.0;
        std::vector<PlaneD> planes;
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 n(0.0);
            n[a] = 1.0;
            planes.push_back({n, lo[a]});
            planes.push_back({-n, -hi[a]});
        }
        for (std::size_t i = 0; i < planes.size(); ++i) {
            Winding w = baseWinding(planes[i].n, planes[i].d, radius_);
            for (std::size_t j = 0; j < planes.size() && !w.empty(); ++j)
                if (j != i)
                    w = chopFront(w, planes[j].n, planes[j].d, kPortalOnPlane);
            addPortal({planes[i].n, planes[i].d, {root_, kOutsidePlace}, std::move(w)});
        }
    }

    /// The node's plane within its region: a base winding chopped by every portal bounding it.
    void nodePortal(int place)
    {
        TreePlace& node = places_[std::size_t(place)];
        const PlaneD plane = unitPlane(bsp_.planes[std::size_t(node.plane)]);
        Winding w = baseWinding(plane.n, plane.d, radius_);
        for (int id : node.portals) {
            const TreePortal& p = portals_[std::size_t(id)];
            w = p.places[0] == place ? chopFront(w, p.n, p.d, kPortalOnPlane) : chopFront(w, -p.n, -p.d, kPortalOnPlane);
            if (w.empty())
                return;
        }
        addPortal({plane.n, plane.d, node.children, std::move(w)});
    }

    /// Hands each portal bounding the node to the child (or both children) its winding lies in.
    void splitPortals(int place)
    {
        const PlaneD plane = unitPlane(bsp_.planes[std::size_t(places_[std::size_t(place)].plane)]);
        const auto children = places_[std::size_t(place)].children;
        const std::vector<int> list = places_[std::size_t(place)].portals;
        for (int id : list) {
            TreePortal& p = portals_[std::size_t(id)];
            const int side = p.places[0] == place ? 0 : 1;
            const int other = p.places[std::size_t(1 - side)];
            removeFrom(p.places[0], id);
            removeFrom(p.places[1], id);
            Winding front, back;
            split(p.w, plane.n, plane.d, kPortalOnPlane, front, back);
            auto attach = [&](TreePortal portal, int child) {
                portal.places[std::size_t(side)] = child;
                portal.places[std::size_t(1 - side)] = other;
                return portal;
            };
            if (!front.empty() && !back.empty()) {
                TreePortal behind = p;
                behind.w = std::move(back);
                p.w = std::move(front);
                TreePortal ahead = attach(std::move(p), children[0]);
                portals_[std::size_t(id)] = ahead;
                places_[std::size_t(ahead.places[0])].portals.push_back(id);
                places_[std::size_t(ahead.places[1])].portals.push_back(id);
                addPortal(attach(std::move(behind), children[1]));
            } else if (!front.empty() || !back.empty()) {
                const bool inFront = !front.empty();
                p.w = inFront ? std::move(front) : std::move(back);
                TreePortal moved = attach(std::move(p), children[inFront ? 0 : 1]);
                portals_[std::size_t(id)] = moved;
                places_[std::size_t(moved.places[0])].portals.push_back(id);
                places_[std::size_t(moved.places[1])].portals.push_back(id);
            } else {
                p.w.clear();   // nothing left of it on either side
            }
        }
        places_[std::size_t(place)].portals.clear();
    }

    std::vector<LeafPortal> leafPortals() const
    {
        std::vector<LeafPortal> out;
        for (const TreePortal& p : portals_) {
            if (p.w.empty())
                continue;
            const TreePlace& a = places_[std::size_t(p.places[0])];
            const TreePlace& b = places_[std::size_t(p.places[1])];
            if (a.plane >= 0 || b.plane >= 0)
                continue;   // still on a node: only possible for a winding lost to every side
            if (a.leaf == kOutside && b.leaf == kOutside)
                continue;
            out.push_back({{a.leaf, b.leaf}, {p.n, p.d}, p.w});
        }
        return out;
    }

    const QuakeBsp& bsp_;
    std::vector<TreePlace> places_;
    std::vector<TreePortal> portals_;
    static constexpr int kOutsidePlace = 0;
    int root_ = 1;
    double radius_ = 0.0;
};

bool isLiquid(int contents)
{
    return contents == kContentsWater || contents == kContentsSlime || contents == kContentsLava;
}

} // namespace

Winding chopFront(const Winding& w, const glm::dvec3& n, double d, double onPlane)
{
    Winding front, back;
    split(w, n, d, onPlane, front, back);
    return front;
}

std::vector<LeafPortal> treePortals(const QuakeBsp& bsp)
{
    return PortalBuilder(bsp).run();
}

bool seesThrough(const QuakeBsp& bsp, const LeafPortal& portal, bool clearLiquids)
{
    for (int leaf : portal.leaves)
        if (leaf < 1 || leaf > bsp.visleafs || bsp.leaves[std::size_t(leaf)].contents == kContentsSolid)
            return false;
    const int a = bsp.leaves[std::size_t(portal.leaves[0])].contents;
    const int b = bsp.leaves[std::size_t(portal.leaves[1])].contents;
    if (a == b)
        return true;
    return clearLiquids && (a == kContentsEmpty || isLiquid(a)) && (b == kContentsEmpty || isLiquid(b));
}

std::vector<LeafPortal> openPortals(const QuakeBsp& bsp, bool clearLiquids)
{
    std::vector<LeafPortal> open;
    for (LeafPortal& p : treePortals(bsp))
        if (seesThrough(bsp, p, clearLiquids))
            open.push_back(std::move(p));
    return open;
}

std::string prt1(const QuakeBsp& bsp, const std::vector<LeafPortal>& open)
{
    std::string out = "PRT1\n" + std::to_string(bsp.visleafs) + "\n" + std::to_string(open.size()) + "\n";
    char buffer[128];
    for (const LeafPortal& p : open) {
        // vis takes a winding's plane as (p0 - p1) x (p2 - p1) and its first leaf in front of it:
        // start at the corner where that cross product is largest, so the plane is well defined.
        const std::size_t n = p.winding.size();
        std::size_t start = 0;
        double largest = -1.0;
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3& a = p.winding[i];
            const glm::dvec3& b = p.winding[(i + 1) % n];
            const glm::dvec3& c = p.winding[(i + 2) % n];
            const double size = glm::length(glm::cross(a - b, c - b));
            if (size > largest)
                largest = size, start = i;
        }
        Winding w(n);
        for (std::size_t i = 0; i < n; ++i)
            w[i] = p.winding[(start + i) % n];
        const glm::dvec3 windingNormal = glm::cross(w[0] - w[1], w[2] - w[1]);
        const bool facesFirst = glm::dot(windingNormal, p.plane.normal) > 0.0;
        const int first = facesFirst ? p.leaves[0] : p.leaves[1], second = facesFirst ? p.leaves[1] : p.leaves[0];
        out += std::to_string(w.size()) + " " + std::to_string(first - 1) + " " + std::to_string(second - 1);
        for (const glm::dvec3& v : w) {
            std::snprintf(buffer, sizeof buffer, " (%.6f %.6f %.6f)", v.x, v.y, v.z);
            out += buffer;
        }
        out += "\n";
    }
    return out;
}

} // namespace sightline::bsp
