// The textures' means (plugins/src/TextureMean.h): the mip chain, the largest level kept, and the
// decoded textures' budget. The means themselves are tested through both importers
// (tst_GltfImporter, tst_MeshFileImporter).

#include <gtest/gtest.h>

#include "TextureMean.h"
#include "base/Error.h"

using namespace sightline;

namespace {

RgbImage flat(int width, int height, glm::vec3 colour)
{
    RgbImage image;
    image.width = width, image.height = height;
    image.pixels.assign(std::size_t(width) * std::size_t(height), colour);
    return image;
}

TEST(TextureMean, TheChainHalvesToOneTexelAndKeepsNoLevelPastTheLargestSide)
{
    RgbImage image = flat(3, 2, glm::vec3(0.0f));
    image.pixels[0] = glm::vec3(1.0f);   // top left
    const std::vector<RgbImage> chain = texture::mipChain(image);
    ASSERT_EQ(chain.size(), 3u);   // 3 x 2, 2 x 1, 1 x 1
    EXPECT_EQ(chain[1].width, 2);
    EXPECT_EQ(chain[1].height, 1);
    EXPECT_FLOAT_EQ(chain[1].pixels[0].x, 0.25f);   // the 2 x 2 block holding the white texel
    EXPECT_FLOAT_EQ(chain[1].pixels[1].x, 0.0f);    // the last column, repeated
    EXPECT_FLOAT_EQ(chain[2].pixels[0].x, 0.125f);

    const std::vector<RgbImage> kept = texture::linearMips(flat(2 * texture::kMaxKeptSide + 1, 3, glm::vec3(1.0f)));
    EXPECT_LE(std::max(kept[0].width, kept[0].height), texture::kMaxKeptSide);
    EXPECT_GT(std::max(kept[0].width, kept[0].height), texture::kMaxKeptSide / 2);
    EXPECT_EQ(kept.back().width * kept.back().height, 1);
}

TEST(TextureMean, DecodedTexturesStayWithinTheirBudgetAndAreDecodedAgainWhenAskedFor)
{
    const std::size_t oneTexture = (4 + 1) * sizeof(glm::vec3);   // 2 x 2 and 1 x 1
    texture::DecodedTextures textures(oneTexture);
    int decodes = 0;
    const auto decode = [&](float value) {
        return [&decodes, value] { ++decodes; return flat(2, 2, glm::vec3(value)); };
    };
    std::vector<std::string> warnings;
    const std::vector<RgbImage>* a = textures.get("a", decode(0.25f), warnings);
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(textures.get("a", decode(0.25f), warnings), a);   // kept
    EXPECT_EQ(decodes, 1);
    const std::vector<RgbImage>* b = textures.get("b", decode(0.5f), warnings);   // over the budget: a dropped
    ASSERT_NE(b, nullptr);
    EXPECT_FLOAT_EQ(b->front().pixels[0].x, texture::srgbToLinear(0.5f));
    const std::vector<RgbImage>* again = textures.get("a", decode(0.25f), warnings);
    ASSERT_NE(again, nullptr);
    EXPECT_FLOAT_EQ(again->front().pixels[0].x, texture::srgbToLinear(0.25f));
    EXPECT_EQ(decodes, 3);
    // One that cannot be decoded: said once, not tried again.
    const auto broken = [&] { ++decodes; throw Error("broken.png: not a readable image"); return RgbImage(); };
    EXPECT_EQ(textures.get("broken", broken, warnings), nullptr);
    EXPECT_EQ(textures.get("broken", broken, warnings), nullptr);
    EXPECT_EQ(decodes, 4);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("broken.png: not a readable image"), std::string::npos);
}

} // namespace
