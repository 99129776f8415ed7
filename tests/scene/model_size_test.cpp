// Models of an organ's size pass quietly; a millimetre file read as metres is named with the unit that
// fixes it; points that never come near the model are warned about.
#include <gtest/gtest.h>

#include <vector>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/scene/model_size.h"

namespace hapticut::scene {
namespace {

std::vector<Vec3> heartScaledBy(double factor) {
    std::vector<Vec3> p = mesh::procedural::makeHeart({}).positions;  // 12 cm long
    for (Vec3& v : p) v *= factor;
    return p;
}

TEST(ModelSize, AnOrgansSizePassesAndAMillimetreFileIsNamedWithItsUnit) {
    EXPECT_FALSE(sizeWarning(heartScaledBy(1), "heart.obj"));
    const auto mm = sizeWarning(heartScaledBy(1250), "liver.stl");  // 150 mm read as metres
    ASSERT_TRUE(mm);
    EXPECT_EQ(mm->file, "liver.stl");
    EXPECT_NE(mm->message.find("150 m across"), std::string::npos) << mm->message;
    EXPECT_NE(mm->message.find("give --units mm (it is then 15 cm across)"), std::string::npos) << mm->message;
    const auto cm = sizeWarning(heartScaledBy(100), "kidney.obj");  // 12 cm read as metres... from centimetres
    ASSERT_TRUE(cm);
    EXPECT_NE(cm->message.find("--units cm"), std::string::npos) << cm->message;
    const auto unitBox = sizeWarning(heartScaledBy(1 / 0.12), "thesis.txt");  // the thesis's unit box
    ASSERT_TRUE(unitBox);
    EXPECT_NE(unitBox->message.find("1 m across"), std::string::npos) << unitBox->message;
    const auto tiny = sizeWarning(heartScaledBy(0.01), "cell.obj");  // 1.2 mm: no unit makes it larger
    ASSERT_TRUE(tiny);
    EXPECT_NE(tiny->message.find("--scale"), std::string::npos) << tiny->message;
    EXPECT_EQ(unitScale("mm"), 0.001);
    EXPECT_EQ(unitScale("cm"), 0.01);
    EXPECT_EQ(unitScale("m"), 1.0);
    EXPECT_FALSE(unitScale("inch"));
}

TEST(ModelSize, PointsThatNeverComeNearTheModelAreWarnedAbout) {
    const std::vector<Vec3> heart = heartScaledBy(1);
    const std::vector<Vec3> near = {Vec3(0, -0.01, 0.09), Vec3(0, -0.01, 0.03)};  // the shipped press
    EXPECT_FALSE(farFromModelWarning(heart, near, "the device's path"));
    std::vector<Vec3> mm = near;
    for (Vec3& p : mm) p *= 1000;
    const auto far = farFromModelWarning(heart, mm, "the device's path", "press.csv");
    ASSERT_TRUE(far);
    EXPECT_EQ(far->file, "press.csv");
    EXPECT_NE(far->message.find("never comes near the model"), std::string::npos) << far->message;
    const std::vector<Vec3> corner = {Vec3(1, 1, 1)};
    EXPECT_TRUE(farFromModelWarning(heart, corner, "--force-at 1,1,1"));
}

}  // namespace
}  // namespace hapticut::scene
