#pragma once
// Image-based light for AO (Sattler et al. 2004 §5): a Radiance .hdr latitude-longitude
// environment, read with stb_image. As the paper pre-filters its map (a Gaussian blur in HDRShop),
// each light direction takes the mean radiance over a cone about as wide as its cell of the light
// sphere (half-angle 2 / sqrt(k)), so an environment with a small bright sun does not flicker as
// it rotates between directions.
//
// Convention: the image's top row is +Y (up), its centre column looks towards +Z, and the column
// angle phi = atan2(x, z) grows to the right. Rotation turns the environment about +Y by the given
// degrees; exposure multiplies radiance by 2^EV. Changing either only re-reads k values.

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/ao/AoDirections.h"

namespace sightline {

class AoEnvironment {
public:
    /// A uniform sky of one radiance (white: plain AO).
    static AoEnvironment uniform(const glm::vec3& radiance = glm::vec3(1.0f));
    /// Reads a Radiance .hdr (RGBE) file. Throws sightline::Error with the file name for a missing
    /// or unreadable file, an image that is not Radiance HDR (PNG, JPEG, ...), or one that is not
    /// 2:1 latitude-longitude within a factor of 1.5, larger than the image limits (16384 a side,
    /// 32 Mpixels: lighting/ImageFile.h), or whose data is truncated or corrupt (every byte is
    /// checked before decoding: lighting/src/ImageCheck.h).
    static AoEnvironment load(const std::filesystem::path& file);
    /// The same environment from pixels (row-major, top row first), for tests.
    static AoEnvironment fromPixels(int width, int height, std::vector<glm::vec3> pixels);

    /// Radiance of each of the set's k directions: pre-filtered for k, rotated, exposed.
    std::vector<glm::vec3> directionRadiance(const AoDirectionSet& set, double rotationDegrees = 0.0,
                                             double exposureEv = 0.0) const;
    /// The unfiltered radiance seen towards unit direction l (nearest pixel).
    glm::vec3 radiance(const glm::vec3& l) const;

    int width() const { return width_; }
    int height() const { return height_; }

private:
    int width_ = 0, height_ = 0;
    std::vector<glm::vec3> pixels_;
    int smallW_ = 0, smallH_ = 0;
    std::vector<glm::vec3> small_;   ///< area-averaged to at most 128 x 64
    struct Cache {
        std::mutex mutex;
        std::map<int, std::vector<glm::vec3>> filtered;   ///< per k: cone-filtered small map
    };
    std::shared_ptr<Cache> cache_ = std::make_shared<Cache>();

    const std::vector<glm::vec3>& filtered(int k) const;
};

} // namespace sightline
