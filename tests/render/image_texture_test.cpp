// Generated textures (tileable, red, wet noise) and PNG files (round trip, clear errors).
#include <gtest/gtest.h>

#include <fstream>

#include "render/image.h"
#include "render/textures.h"
#include "test_support.h"

namespace hapticut::render {
namespace {

TEST(Textures, NoiseTilesAcrossBothEdges) {
    for (double t : {0.0, 0.13, 0.5, 0.77}) {
        EXPECT_NEAR(tiledNoise(0, t, 6, 2, 5, 3), tiledNoise(1, t, 6, 2, 5, 3), 1e-12);
        EXPECT_NEAR(tiledNoise(t, 0, 6, 2, 5, 3), tiledNoise(t, 1, 6, 2, 5, 3), 1e-12);
    }
    const double n = tiledNoise(0.3, 0.6, 6, 2, 5, 3);
    EXPECT_GE(n, 0);
    EXPECT_LE(n, 1);
}

TEST(Textures, TheDiffuseIsRedMuscleAndTheSpecularIsBlackAndWhiteNoise) {
    const OrganTextures t = makeOrganTextures(128);
    double r = 0, g = 0, b = 0;
    int shiny = 0, dull = 0;
    const int pixels = 128 * 128;
    for (int i = 0; i < pixels; ++i) {
        r += t.diffuse.rgba[4 * i];
        g += t.diffuse.rgba[4 * i + 1];
        b += t.diffuse.rgba[4 * i + 2];
        shiny += t.detail.rgba[4 * i] > 180;
        dull += t.detail.rgba[4 * i] < 80;
    }
    EXPECT_GT(r, 3 * g);
    EXPECT_GT(r, 3 * b);
    // Both wet and dry spots, neither dominating.
    EXPECT_GT(shiny, pixels / 10);
    EXPECT_GT(dull, pixels / 10);
}

TEST(Png, WritesAndReadsBackTheSamePixels) {
    test::ScratchDir dir;
    Image image(5, 3);
    for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = static_cast<std::uint8_t>(i * 7);
    ASSERT_FALSE(savePng(dir / "a.png", image));
    std::string error;
    const auto back = loadPng(dir / "a.png", error);
    ASSERT_TRUE(back) << error;
    EXPECT_EQ(back->width, 5);
    EXPECT_EQ(back->height, 3);
    EXPECT_EQ(back->rgba, image.rgba);
}

TEST(Png, NamesTheFileWhenItCannotReadOrWrite) {
    test::ScratchDir dir;
    std::string error;
    EXPECT_FALSE(loadPng(dir / "missing.png", error));
    EXPECT_NE(error.find("missing.png"), std::string::npos) << error;
    std::ofstream(dir / "text.png") << "not a png";
    EXPECT_FALSE(loadPng(dir / "text.png", error));
    EXPECT_NE(error.find("text.png"), std::string::npos) << error;
    const auto failed = savePng(dir / "no-such-folder" / "x.png", Image(4, 4));
    ASSERT_TRUE(failed);
    EXPECT_NE(failed->find("x.png"), std::string::npos) << *failed;
}

TEST(Png, FlipRowsTurnsTheImageUpsideDown) {
    Image image(1, 3);
    image.at(0, 0)[0] = 1;
    image.at(0, 2)[0] = 3;
    flipRows(image);
    EXPECT_EQ(image.at(0, 0)[0], 3);
    EXPECT_EQ(image.at(0, 2)[0], 1);
}

}  // namespace
}  // namespace hapticut::render
