// The off-screen renderer of fvx's 3-D pictures against pinhole geometry worked by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "fvx/io/render.hpp"

namespace fvx::test {
namespace {

// At the origin looking along +x, 90° wide: f = 200 px, the image centre (200, 150).
io::PictureCamera along_x() {
  io::PictureCamera c;
  c.eye_m = Eigen::Vector3d(0, 0, 0);
  c.target_m = Eigen::Vector3d(2, 0, 0);
  c.fov_deg = 90.0;
  c.width_px = 400;
  c.height_px = 300;
  return c;
}

std::size_t pixels_of(const io::RgbImage& image, io::Rgb colour) {
  std::size_t n = 0;
  for (const io::Rgb& p : image.pixels) n += p == colour;
  return n;
}

bool is_white(const io::Rgb& p) { return p == io::Rgb{255, 255, 255}; }

TEST(Render, ProjectIsThePinholeOfTheCamera) {
  const io::PictureCamera c = along_x();
  EXPECT_NEAR(io::focal_px(c), 200.0, 1e-9);
  const auto centre = io::project(c, {2, 0, 0});
  ASSERT_TRUE(centre);
  EXPECT_TRUE(centre->isApprox(Eigen::Vector3d(200, 150, 2)));
  // World z is up on the image, −y to the right (looking along +x).
  EXPECT_TRUE(io::project(c, {2, -1, 0})->isApprox(Eigen::Vector3d(300, 150, 2)));
  EXPECT_TRUE(io::project(c, {2, 0, 1})->isApprox(Eigen::Vector3d(200, 50, 2)));
  EXPECT_FALSE(io::project(c, {-1, 0, 0}));
  EXPECT_FALSE(io::project(c, {0.001, 0.5, 0}));  // nearer than the near plane
}

TEST(Render, ACubeSeenFaceOnCoversItsProjectedSquare) {
  // The cube's near face (x = 1.9) is 0.2 m wide at depth 1.9: 200 · 0.2 / 1.9 = 21.05 px.
  io::Canvas canvas(along_x());
  canvas.cells({Eigen::Vector3d(2, 0, 0)}, 0.2, {200, 0, 0});
  std::size_t covered = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) covered += canvas.covered(x, y);
  const double side = 200.0 * 0.2 / 1.9;
  EXPECT_NEAR(double(covered), side * side, 4 * side + 4);
  EXPECT_TRUE(canvas.covered(200, 150));
  EXPECT_FALSE(canvas.covered(200 + int(side), 150));
}

TEST(Render, TheNearerCellHidesTheFartherInEitherOrder) {
  const io::Rgb red = {200, 0, 0}, blue = {0, 0, 200};
  for (int order = 0; order < 2; ++order) {
    io::Canvas canvas(along_x());
    const std::vector<Eigen::Vector3d> near = {{2, 0, 0}}, far = {{3, 0, 0}};
    if (order == 0) canvas.cells(far, 0.2, blue), canvas.cells(near, 0.2, red);
    else canvas.cells(near, 0.2, red), canvas.cells(far, 0.2, blue);
    const io::Rgb centre = canvas.image().at(200, 150);
    EXPECT_GT(centre[0], 0) << order;
    EXPECT_EQ(centre[2], 0) << order;
    // The farther, smaller cube is wholly behind the nearer one.
    for (const io::Rgb& p : canvas.image().pixels) EXPECT_EQ(p[2], is_white(p) ? 255 : 0);
  }
}

TEST(Render, ALayerBehindASurfaceIsSeenThroughItPaler) {
  const io::Rgb grey = {100, 100, 100}, violet = {140, 60, 200};
  io::Canvas front(along_x());
  front.cells({Eigen::Vector3d(2, 0, 0)}, 0.2, grey);
  const io::Rgb surface = front.image().at(200, 150);
  io::Canvas behind(along_x());
  behind.cells({Eigen::Vector3d(3, 0, 0)}, 0.2, violet);
  const io::Rgb seen = behind.image().at(200, 150);
  front.overlay(behind, 0.4);
  const io::Rgb mixed = front.image().at(200, 150);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(mixed[std::size_t(i)], 0.4 * seen[std::size_t(i)] + 0.6 * surface[std::size_t(i)], 1.0) << i;
  // In front of the surface, the layer is drawn as it is.
  io::Canvas back(along_x());
  back.cells({Eigen::Vector3d(3, 0, 0)}, 0.2, grey);
  io::Canvas ahead(along_x());
  ahead.cells({Eigen::Vector3d(2, 0, 0)}, 0.2, violet);
  const io::Rgb drawn = ahead.image().at(200, 150);
  back.overlay(ahead, 0.4);
  EXPECT_EQ(back.image().at(200, 150), drawn);
}

TEST(Render, LinesAreSolidInFrontAndDashedBehindSurfaces) {
  const io::Rgb blue = {30, 90, 230};
  io::Canvas canvas(along_x());
  canvas.cells({Eigen::Vector3d(2, 0, 0)}, 0.4, {150, 150, 150});  // 42 px wide around the centre
  io::Canvas solid = canvas;
  solid.line({1.5, 0.6, 0}, {1.5, -0.6, 0}, blue);  // in front of the cube: every pixel
  canvas.line({3, 0.6, 0}, {3, -0.6, 0}, blue);     // behind it where it crosses it
  const int row = 150;
  std::size_t front_hidden_part = 0, behind_hidden_part = 0, behind_open_part = 0;
  for (int x = 181; x < 219; ++x) {
    front_hidden_part += solid.image().at(x, row) == blue;
    behind_hidden_part += canvas.image().at(x, row) == blue;
  }
  for (int x = 170; x < 178; ++x) behind_open_part += canvas.image().at(x, row) == blue;
  EXPECT_EQ(front_hidden_part, 38u);
  EXPECT_EQ(behind_hidden_part, 0u);   // behind the cube: pale dashes only
  EXPECT_EQ(behind_open_part, 8u);     // beside it: solid
  std::size_t dashes = 0;  // 55 % blue over white
  for (int x = 181; x < 219; ++x) dashes += canvas.image().at(x, row) == io::Rgb{131, 164, 241};
  EXPECT_GT(dashes, 10u);
  EXPECT_LT(dashes, 30u);
}

// A segment from just past the near plane projects millions of pixels off the image: its
// part on the image is drawn (it used to be dropped whole), and the part off it costs
// nothing (a segment 4·10¹⁰ px long is drawn at once).
TEST(Render, LinesRunningFarOffTheImageAreClippedNotDropped) {
  const io::Rgb blue = {30, 90, 230};
  io::Canvas canvas(along_x());
  canvas.line({0.011, -10, 0}, {2, 0, 0}, blue);  // from u ≈ 182 000 px to the centre, row 150
  EXPECT_EQ(canvas.image().at(200, 150), blue);
  EXPECT_EQ(canvas.image().at(399, 150), blue);
  EXPECT_TRUE(is_white(canvas.image().at(198, 150)));  // it ends at the centre
  io::Canvas across(along_x());
  across.line({0.0100001, 1000, -0.0000005}, {0.0100001, -1000, -0.0000005}, blue);  // row 150, far beyond both sides
  std::size_t row = 0;
  for (int x = 0; x < 400; ++x) row += across.image().at(x, 150) == blue;
  EXPECT_EQ(row, 400u);
  EXPECT_EQ(pixels_of(across.image(), blue), 400u);
  io::Canvas off(along_x());
  off.line({0.011, -10, 10}, {0.011, 10, 10}, blue);  // far above the image
  EXPECT_EQ(pixels_of(off.image(), blue), 0u);
}

TEST(Render, ACubeUnderAPixelIsOnePixelAndASmallOneASquare) {
  io::Canvas canvas(along_x());
  canvas.cells({Eigen::Vector3d(20, 0, 0)}, 0.05, {0, 200, 0});  // 0.5 px wide
  std::size_t covered = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) covered += canvas.covered(x, y);
  EXPECT_EQ(covered, 1u);
  EXPECT_EQ(pixels_of(canvas.image(), {255, 255, 255}), 400u * 300u - 1u);
  io::Canvas near(along_x());
  near.cells({Eigen::Vector3d(2.05, 0.0025, 0.0025)}, 0.025, {0, 200, 0});  // 200 * 0.025 / 2.05 = 2.44 px
  covered = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) covered += near.covered(x, y);
  EXPECT_EQ(covered, 4u);  // the pixels whose centres lie within 1.22 px of (199.76, 149.76)
}

TEST(Render, ACameraThatCannotBeIsRefused) {
  io::PictureCamera c = along_x();
  c.target_m = c.eye_m;
  EXPECT_FALSE(c.validate().empty());
  c = along_x();
  c.fov_deg = 180;
  EXPECT_FALSE(c.validate().empty());
  c = along_x();
  c.width_px = 100000;
  EXPECT_FALSE(c.validate().empty());
  EXPECT_TRUE(along_x().validate().empty());
}

}  // namespace
}  // namespace fvx::test
