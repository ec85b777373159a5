// The 3-D pictures checked by what they show: the frontier's red pixels against the frontier
// cells' count and their size in the picture, voids violet only where voids were analysed, the
// best view's frustum where its pose projects, and a session's contact sheet with a tile
// per view and the chosen next view drawn in it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_support.hpp"
#include "fvx/io/render.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

cv::Mat read_png(const std::filesystem::path& path) {
  cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);  // BGR
  EXPECT_FALSE(image.empty()) << path;
  return image;
}

// The frontier red (220, 30, 30) under any shade; blends with violet or grey are not it.
bool frontier_red(const cv::Vec3b& bgr) { return bgr[2] >= 50 && 3 * bgr[1] < bgr[2] && 3 * bgr[0] < bgr[2]; }
// The void violet (140, 60, 200), shaded, or seen through a grey surface.
bool void_violet(const cv::Vec3b& bgr) { return bgr[0] > bgr[2] + 15 && bgr[2] > bgr[1] + 15; }
// The next view's blue (30, 90, 230), solid or in its pale dashes.
bool frustum_blue(const cv::Vec3b& bgr) { return bgr[0] >= 220 && bgr[2] <= 140 && bgr[0] - bgr[2] >= 90; }

std::size_t count(const cv::Mat& image, bool (*is)(const cv::Vec3b&), cv::Rect region = {}) {
  if (region.area() == 0) region = cv::Rect(0, 0, image.cols, image.rows);
  std::size_t n = 0;
  for (int y = region.y; y < region.y + region.height; ++y)
    for (int x = region.x; x < region.x + region.width; ++x) n += is(image.at<cv::Vec3b>(y, x));
  return n;
}

io::PictureCamera camera_of(const json& picture) {
  io::PictureCamera c;
  for (int i = 0; i < 3; ++i) {
    c.eye_m[i] = picture["eye_m"][std::size_t(i)].get<double>();
    c.target_m[i] = picture["target_m"][std::size_t(i)].get<double>();
  }
  c.fov_deg = picture["fov_deg"].get<double>();
  c.width_px = picture["width_px"].get<int>();
  c.height_px = picture["height_px"].get<int>();
  return c;
}

// A cell's face area in the picture at the target's distance, pixels.
double cell_area_px(const io::PictureCamera& c, double R) {
  const double side = io::focal_px(c) * R / (c.eye_m - c.target_m).norm();
  return side * side;
}

const std::string kBounds = " --bounds 0.4,-0.8,0.0,1.2,0.75,0.55";

TEST(CliPictures, TheFrontiersRedAndTheVoidsVioletMatchTheirCells) {
  const TempDir dir;
  make_crates_map(dir);
  RunResult r = run_fvx(dir, "voids map.ot" + kBounds + " --picture v.png --picture-top t.png");
  ASSERT_EQ(r.status, 0) << r.err;
  const json v = json::parse(r.out)["results"];
  ASSERT_EQ(v["picture"]["path"], "v.png");
  const io::PictureCamera camera = camera_of(v["picture"]);
  const cv::Mat picture = read_png(dir / "v.png");
  ASSERT_EQ(picture.cols, 960);
  ASSERT_EQ(picture.rows, 720);
  // Every frontier cell shows one to three faces unless something hides it: the red area is
  // of the order of the cells' count times a face's area (measured: 3023 cells, 78 px a
  // face; red 0.22 of that with voids tinting what lies behind them, 0.40 in fvx frontiers').
  const double frontier_area = double(v["frontier_cells"].get<int>()) * cell_area_px(camera, 0.025);
  const double red = double(count(picture, frontier_red));
  EXPECT_GT(red, 0.1 * frontier_area) << red << " red pixels for " << v["frontier_cells"] << " cells";
  EXPECT_LT(red, 3.0 * frontier_area) << red << " red pixels for " << v["frontier_cells"] << " cells";
  EXPECT_GT(count(picture, void_violet), 0.02 * double(v["void_cells"].get<int>()) * cell_area_px(camera, 0.025));
  EXPECT_EQ(read_png(dir / "t.png").cols, 900);  // the top view of earlier versions

  // fvx frontiers analyses no voids: not one violet pixel, and more red (no void in front
  // of a frontier tints it).
  r = run_fvx(dir, "frontiers map.ot" + kBounds + " --picture f.png");
  ASSERT_EQ(r.status, 0) << r.err;
  const cv::Mat frontiers = read_png(dir / "f.png");
  EXPECT_EQ(count(frontiers, void_violet), 0u);
  const double red_alone = double(count(frontiers, frontier_red));
  EXPECT_GE(red_alone, red);
  EXPECT_LT(red_alone, 3.0 * frontier_area);
}

TEST(CliPictures, TheBestViewsFrustumIsDrawnWhereItsPoseProjects) {
  const TempDir dir;
  make_crates_map(dir);
  const RunResult r = run_fvx(dir, "nbv map.ot --no-capmap" + kBounds + " --top 1 --picture n.png");
  ASSERT_EQ(r.status, 0) << r.err;
  const json res = json::parse(r.out)["results"];
  ASSERT_EQ(res["views"].size(), 1u);
  const json& p = res["views"][0]["position_m"];
  const auto apex = io::project(camera_of(res["picture"]), Eigen::Vector3d(p[0], p[1], p[2]));
  ASSERT_TRUE(apex);
  const cv::Mat picture = read_png(dir / "n.png");
  const cv::Rect image(0, 0, picture.cols, picture.rows);
  const cv::Rect around = cv::Rect(int(apex->x()) - 3, int(apex->y()) - 3, 7, 7) & image;
  ASSERT_GT(around.area(), 0) << "the best view is outside the picture";
  // Four edges meet at the optical centre: blue there; elsewhere the lines' length.
  EXPECT_GE(count(picture, frustum_blue, around), 4u);
  EXPECT_GT(count(picture, frustum_blue), 200u);

  // The camera where the user puts it.
  const RunResult chosen = run_fvx(dir, "nbv map.ot --no-capmap" + kBounds +
                                            " --top 1 --picture m.png --picture-eye 3,2,2 --picture-target 0.8,0,0.2");
  ASSERT_EQ(chosen.status, 0) << chosen.err;
  const json placed = json::parse(chosen.out)["results"]["picture"];
  EXPECT_EQ(placed["eye_m"], json::parse("[3.0, 2.0, 2.0]"));
  EXPECT_EQ(placed["target_m"], json::parse("[0.8, 0.0, 0.2]"));
}

TEST(CliPictures, BadPictureOptionsAreRefusedBeforeAnyWork) {
  const TempDir dir;
  make_crates_map(dir);
  const std::vector<std::pair<std::string, int>> cases = {
      {"voids map.ot --picture v.jpg", 2},
      {"voids map.ot --picture-top v.bmp", 2},
      {"voids map.ot --picture v.png --picture-eye 1,2", 2},
      {"voids map.ot --picture v.png --picture-eye 1,2,nan", 2},
      {"voids map.ot --picture v.png --picture-eye 1e9,0,0", 2},
      {"voids map.ot --picture v.png --picture-eye 1,1,1 --picture-target 1,1,1", 2},
      {"nbv map.ot --no-capmap --picture no/such/folder/v.png", 1},
      {"frontiers map.ot --picture map.ot", 2},
  };
  for (const auto& [arguments, status] : cases) {
    const RunResult r = run_fvx(dir, arguments);
    EXPECT_EQ(r.status, status) << arguments << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << arguments << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "v.png"));
  EXPECT_FALSE(std::filesystem::exists(dir / "v.jpg"));
}

TEST(CliPictures, ASessionWritesAContactSheetWithTheNextViewInEachTile) {
  const TempDir dir;
  const std::string scene = " '" + source("data/scenes/paper-setting-1.ply") + "'";
  RunResult r = run_fvx(dir, "explore" + scene + " --no-capmap --max-views 2 --pictures --format json -o s");
  ASSERT_EQ(r.status, 0) << r.err;
  const json rows = json::parse(r.out)["results"]["rows"];
  ASSERT_EQ(rows.size(), 2u);
  for (const char* name : {"s/pictures/view000.png", "s/pictures/view001.png"})
    EXPECT_EQ(read_png(dir / name).cols, 960) << name;
  // Two tiles of 320 x 240 side by side under a 48-pixel head, 4 pixels apart.
  const cv::Mat sheet = read_png(dir / "s/views.png");
  EXPECT_EQ(sheet.rows, 48 + 240 + 8);
  for (int tile = 0; tile < 2; ++tile) {
    const cv::Rect region(4 + tile * 324, 48, 320, 240);
    EXPECT_GT(count(sheet, frustum_blue, region), 20u) << "tile " << tile;
    EXPECT_GT(count(sheet, frontier_red, region), 50u) << "tile " << tile;
  }

  // A replay of the session draws its own sheet, pictures only when asked.
  r = run_fvx(dir, "replay s -o r");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_png(dir / "r/views.png").rows, sheet.rows);
  EXPECT_FALSE(std::filesystem::exists(dir / "r/pictures"));
}

}  // namespace
}  // namespace fvx::test
