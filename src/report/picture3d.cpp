#include "fvx/report/picture3d.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/report/analysis.hpp"
#include "fvx/report/nbv.hpp"
#include "fvx/session/recorder.hpp"

namespace fvx::report {

namespace {

const io::Rgb kEllipsoidViolet = {95, 25, 150};
const io::Rgb kNextViewBlue = {30, 90, 230};
const io::Rgb kTakenGrey = {90, 90, 90};
const io::Rgb kBoundsGrey = {175, 175, 175};
const io::Rgb kInk = {30, 30, 30};
constexpr double kElevation_deg = 35.0;
constexpr double kUtilityRankShown = 0.5;  ///< the utility field's cells drawn: rank at least this
constexpr int kTileWidth = 320, kTileHeight = 240, kFullWidth = 960, kFullHeight = 720;

std::optional<Eigen::Vector3d> read_point(const Args& args, const char* name) {
  if (!args.has(name)) return std::nullopt;
  const std::vector<double> v = parse_double_list(args.get(name), std::string("--") + name, 3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

std::string checked_png(const Args& args, const char* name) {
  if (!args.has(name)) return "";
  const std::string& path = args.get(name);
  if (lowercase_extension(path) != ".png") throw UsageError(std::string("--") + name + " " + path + ": expected a .png file");
  return path;
}

}  // namespace

std::vector<OptionSpec> picture_options(bool session, const char* picture_help, const char* top_help) {
  std::vector<OptionSpec> specs;
  if (session) {
    specs.push_back({"pictures", 0, nullptr, "a 3-D picture of every view as pictures/viewNNN.png (views.png, "
                                             "one small picture per view, is always written)", kNotASetting});
  } else {
    specs.push_back({"picture", 0, "FILE.png", picture_help, kNotASetting});
    specs.push_back({"picture-top", 0, "FILE.png", top_help, kNotASetting});
  }
  specs.push_back({"picture-eye", 0, "X,Y,Z", "where the 3-D picture's camera stands, metres (default: on the robot's "
                                               "side of the search space where the command knows one, else on its "
                                               "-x,-y side; 35 degrees above it)", kNotASetting});
  specs.push_back({"picture-target", 0, "X,Y,Z", "where the 3-D picture's camera looks, metres (default: the centre "
                                                  "of the search space)", kNotASetting});
  return specs;
}

PictureRequest read_picture_options(const Args& args) {
  PictureRequest r;
  r.path = checked_png(args, "picture");
  r.top_path = checked_png(args, "picture-top");
  r.per_view = args.has("pictures");
  r.eye_m = read_point(args, "picture-eye");
  r.target_m = read_point(args, "picture-target");
  for (const auto& p : {r.eye_m, r.target_m})
    if (p && !(p->allFinite() && p->cwiseAbs().maxCoeff() <= 1e6))
      throw UsageError("--picture-eye and --picture-target take three numbers within +-1e6 metres");
  if (r.eye_m && r.target_m && (*r.eye_m - *r.target_m).norm() < 1e-6)
    throw UsageError("--picture-eye and --picture-target are the same point");
  return r;
}

Eigen::Vector3d key_center(const map::VoxelKey& key, double resolution_m) {
  return {(double(key.x) - 32768 + 0.5) * resolution_m, (double(key.y) - 32768 + 0.5) * resolution_m,
          (double(key.z) - 32768 + 0.5) * resolution_m};
}

PictureScene picture_scene(const std::vector<Eigen::Vector3f>& occupied_m, double resolution_m,
                           const frontier_voids::Analysis& a) {
  PictureScene s;
  s.cell_m = resolution_m;
  s.bounds_m = a.bounds_m;
  for (const auto& c : occupied_m)
    if (a.bounds_m.contains(c.cast<double>())) s.occupied_m.push_back(c.cast<double>());
  for (const auto& k : a.frontier_cells) s.frontier_m.push_back(key_center(k, resolution_m));
  for (const auto& k : a.void_cells) s.void_m.push_back(key_center(k, resolution_m));
  s.clusters = a.void_clusters;
  return s;
}

void add_utility_field(PictureScene& scene, const nbv::Result& r) {
  const std::vector<double> rank = utility_ranks(r);
  for (std::size_t i = 0; i < r.utility_field.size(); ++i)
    if (r.utility_field[i].kept) {
      scene.utility_m.push_back(r.utility_field[i].center_m);
      scene.utility_rank.push_back(rank[i]);
    }
}

io::PictureCamera picture_camera(const PictureScene& scene, const PictureRequest& request, int width_px,
                                 int height_px) {
  io::PictureCamera camera;
  camera.width_px = width_px, camera.height_px = height_px;
  const Eigen::AlignedBox3d& S = scene.bounds_m;
  camera.target_m = request.target_m ? *request.target_m : S.isEmpty() ? Eigen::Vector3d(0, 0, 0) : Eigen::Vector3d(S.center());
  if (request.eye_m) {
    camera.eye_m = *request.eye_m;
    if ((camera.eye_m - camera.target_m).norm() < 1e-6)
      throw UsageError("--picture-eye is the point the picture looks at");
    return camera;
  }
  Eigen::Vector2d side(-1, -1);  // without a robot: from −x, −y
  if (scene.robot_m && (scene.robot_m->head<2>() - camera.target_m.head<2>()).norm() > 1e-3)
    side = scene.robot_m->head<2>() - camera.target_m.head<2>();
  side.normalize();
  const double el = kElevation_deg * M_PI / 180.0;
  const Eigen::Vector3d direction(side.x() * std::cos(el), side.y() * std::cos(el), std::sin(el));
  // S's bounding sphere inside the narrower of the two fields of view, grown to hold the
  // views drawn: a view may stand in the air beyond S (nbv --exterior view).
  double radius = S.isEmpty() ? 1.0 : std::max(0.5 * S.sizes().norm(), 0.05);
  for (const auto& view : {scene.taken, scene.chosen})
    if (view) radius = std::max(radius, (view->translation() - camera.target_m).norm() + scene.cell_m);
  const double half_h = 0.5 * camera.fov_deg * M_PI / 180.0;
  const double half_v = std::atan(std::tan(half_h) * height_px / width_px);
  camera.eye_m = camera.target_m + direction * (1.05 * radius / std::sin(std::min(half_h, half_v)));
  return camera;
}

namespace {

void draw_box(io::Canvas& canvas, const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return;
  for (int a = 0; a < 8; ++a)
    for (int axis = 0; axis < 3; ++axis)
      if (!(a & (1 << axis))) canvas.line(box.corner(Eigen::AlignedBox3d::CornerType(a)),
                                          box.corner(Eigen::AlignedBox3d::CornerType(a | (1 << axis))), kBoundsGrey);
}

// The three principal ellipses of μ + Σ a_j·e_j (the ellipsoid Algorithm 1 casts from).
void draw_ellipsoid(io::Canvas& canvas, const voids::VoidCluster& c) {
  constexpr int kSegments = 48;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const Eigen::Vector3d u = c.axes.col(i) * c.semi_axes_m[i], v = c.axes.col(j) * c.semi_axes_m[j];
    for (int s = 0; s < kSegments; ++s) {
      const double a0 = 2 * M_PI * s / kSegments, a1 = 2 * M_PI * (s + 1) / kSegments;
      canvas.line(c.mean_m + std::cos(a0) * u + std::sin(a0) * v, c.mean_m + std::cos(a1) * u + std::sin(a1) * v,
                  kEllipsoidViolet);
    }
  }
}

// The sensor's view cone to `depth_m`: the optical centre to the image's corners.
void draw_frustum(io::Canvas& canvas, const Eigen::Isometry3d& T_world_sensor, const io::Intrinsics& k,
                  double depth_m, io::Rgb colour, int width_px) {
  std::array<Eigen::Vector3d, 4> corners;
  const std::array<std::array<double, 2>, 4> uv = {{{0, 0}, {double(k.width), 0}, {double(k.width), double(k.height)},
                                                    {0, double(k.height)}}};
  for (std::size_t n = 0; n < 4; ++n)
    corners[n] = T_world_sensor * Eigen::Vector3d((uv[n][0] - k.cx) / k.fx * depth_m, (uv[n][1] - k.cy) / k.fy * depth_m,
                                                  depth_m);
  for (std::size_t n = 0; n < 4; ++n) {
    canvas.line(T_world_sensor.translation(), corners[n], colour, width_px);
    canvas.line(corners[n], corners[(n + 1) % 4], colour, width_px);
  }
}

double frustum_depth_m(const PictureScene& scene) {
  const double size = scene.bounds_m.isEmpty() ? 1.0 : scene.bounds_m.sizes().norm();
  return std::clamp(0.25 * size, 0.15, std::max(0.15, scene.sensor.depth_max_m));
}

void draw_scene(io::Canvas& canvas, const PictureScene& scene) {
  canvas.cells(scene.occupied_m, scene.cell_m, kOccupiedGrey);
  canvas.cells(scene.frontier_m, scene.cell_m, kFrontierRed);
  // Voids lie inside what hides them: drawn on their own, then seen through the surfaces.
  io::Canvas voids(canvas.camera());
  voids.cells(scene.void_m, scene.cell_m, kVoidViolet);
  canvas.overlay(voids, 0.4);
  // The utility field fills the free space around the frontier: its better half only, as
  // small squares that hide no line.
  std::vector<Eigen::Vector3d> better;
  std::vector<io::Rgb> colours;
  for (std::size_t i = 0; i < scene.utility_m.size(); ++i)
    if (scene.utility_rank[i] >= kUtilityRankShown)
      better.push_back(scene.utility_m[i]), colours.push_back(ramp(scene.utility_rank[i]));
  io::Canvas utility(canvas.camera());
  utility.dots(better, colours, 0.35 * scene.cell_m);
  canvas.overlay(utility, 0.25, false);
  draw_box(canvas, scene.bounds_m);
  for (const auto& c : scene.clusters)
    if (c.semi_axes_m.minCoeff() > 0) draw_ellipsoid(canvas, c);
  const double depth = frustum_depth_m(scene);
  if (scene.taken) draw_frustum(canvas, *scene.taken, scene.sensor.intrinsics, depth, kTakenGrey, 1);
  if (scene.chosen) draw_frustum(canvas, *scene.chosen, scene.sensor.intrinsics, depth, kNextViewBlue, 2);
}

struct LegendEntry {
  std::string text;
  std::vector<io::Rgb> swatch;  ///< one colour, or a ramp left to right
};

std::vector<LegendEntry> legend_of(const PictureScene& s) {
  std::vector<LegendEntry> e;
  e.push_back({"occupied: " + std::to_string(s.occupied_m.size()) + " cells", {kOccupiedGrey}});
  e.push_back({"frontier: " + std::to_string(s.frontier_m.size()) + " cells", {kFrontierRed}});
  if (s.voids_analysed) {
    e.push_back({"void: " + std::to_string(s.void_m.size()) + " cells (paler behind surfaces)", {kVoidViolet}});
    e.push_back({"void ellipsoids: " + std::to_string(s.clusters.size()), {kEllipsoidViolet}});
  }
  if (!s.utility_m.empty()) e.push_back({"utility field, upper half by rank (yellow to green)", {ramp(0.5), ramp(0.75), ramp(1)}});
  if (s.taken) e.push_back({"this view", {kTakenGrey}});
  if (s.chosen) e.push_back({"next view (frustum)", {kNextViewBlue}});
  e.push_back({"search space", {kBoundsGrey}});
  return e;
}

void draw_legend(io::Canvas& canvas, const PictureScene& scene) {
  const std::vector<LegendEntry> entries = legend_of(scene);
  int width = 0;
  for (const auto& e : entries) width = std::max(width, io::text_width_px(e.text, 0.45));
  canvas.fill_rect(6, 6, width + 44, 22 * int(entries.size()) + 10, {255, 255, 255}, 0.8);
  for (std::size_t n = 0; n < entries.size(); ++n) {
    const int y = 12 + 22 * int(n);
    const auto& sw = entries[n].swatch;
    for (std::size_t c = 0; c < sw.size(); ++c)
      canvas.fill_rect(12 + int(16 * c / sw.size()), y, int(16 / sw.size()) + 1, 16, sw[c]);
    canvas.image().texts.push_back({entries[n].text, 36, y + 13, 0.45, kInk});
  }
}

// A bar of a round length at the target's distance, and the world axes as seen.
void draw_scale_and_axes(io::Canvas& canvas) {
  const io::PictureCamera& cam = canvas.camera();
  const double px_per_m = io::focal_px(cam) / (cam.target_m - cam.eye_m).norm();
  double length = 0.01;
  for (const double l : {0.02, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0})
    if (l * px_per_m <= 0.25 * cam.width_px) length = l;
  const int bar = std::max(1, int(std::lround(length * px_per_m)));
  const int x0 = 16, y0 = cam.height_px - 22;
  canvas.fill_rect(x0, y0, bar, 4, kInk);
  canvas.fill_rect(x0, y0 - 6, 2, 10, kInk);
  canvas.fill_rect(x0 + bar - 2, y0 - 6, 2, 10, kInk);
  char label[48];
  std::snprintf(label, sizeof label, "%g m at the target", length);
  canvas.image().texts.push_back({label, x0, y0 - 10, 0.45, kInk});
  const Eigen::Matrix3d R_camera_world = io::camera_pose(cam).linear().transpose();
  const Eigen::Vector2d origin(cam.width_px - 50, cam.height_px - 40);
  const std::array<io::Rgb, 3> colours = {io::Rgb{210, 40, 40}, io::Rgb{40, 160, 40}, io::Rgb{40, 70, 210}};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = R_camera_world.col(k);
    const Eigen::Vector2d tip = origin + 28 * d.head<2>();
    canvas.line_px(origin, tip, colours[std::size_t(k)], 2);
    canvas.image().texts.push_back({std::string(1, char('x' + k)), int(tip.x()) + 2, int(tip.y()) + 4, 0.45,
                                    colours[std::size_t(k)]});
  }
}

}  // namespace

io::RgbImage render_picture(const PictureScene& scene, const io::PictureCamera& camera, bool annotated) {
  io::Canvas canvas(camera);
  draw_scene(canvas, scene);
  if (annotated) {
    draw_legend(canvas, scene);
    draw_scale_and_axes(canvas);
  }
  return canvas.image();
}

io::RgbImage contact_sheet(const std::vector<io::RgbImage>& tiles, const std::vector<std::string>& captions,
                           const std::string& title) {
  FVX_ASSERT(!tiles.empty() && tiles.size() == captions.size(), "a caption per tile");
  const int columns = std::clamp(int(std::ceil(std::sqrt(double(tiles.size())))), 1, 8);
  const int rows = (int(tiles.size()) + columns - 1) / columns;
  const int tw = tiles.front().width, th = tiles.front().height, head = 48, gap = 4;
  io::RgbImage sheet;
  sheet.width = std::max(columns * (tw + gap) + gap, 700);  // the key line fits
  sheet.height = head + rows * (th + gap) + gap;
  sheet.pixels.assign(std::size_t(sheet.width) * std::size_t(sheet.height), io::Rgb{235, 235, 235});
  sheet.texts.push_back({title, gap + 4, 18, 0.5, kInk});
  sheet.texts.push_back({"grey: the view taken; blue: the chosen next view; red: frontier; violet: void", gap + 4, 38,
                         0.42, kInk});
  for (std::size_t n = 0; n < tiles.size(); ++n) {
    FVX_ASSERT(tiles[n].width == tw && tiles[n].height == th, "tiles of one size");
    const int x0 = gap + int(n % std::size_t(columns)) * (tw + gap), y0 = head + int(n / std::size_t(columns)) * (th + gap);
    for (int y = 0; y < th; ++y)
      for (int x = 0; x < tw; ++x) sheet.at(x0 + x, y0 + y) = tiles[n].at(x, y);
    sheet.texts.push_back({captions[n], x0 + 6, y0 + 16, 0.45, kInk});
  }
  return sheet;
}

Json picture_json(const std::string& path, const io::PictureCamera& camera) {
  return {{"path", path},
          {"eye_m", {camera.eye_m.x(), camera.eye_m.y(), camera.eye_m.z()}},
          {"target_m", {camera.target_m.x(), camera.target_m.y(), camera.target_m.z()}},
          {"fov_deg", camera.fov_deg},
          {"width_px", camera.width_px},
          {"height_px", camera.height_px}};
}

namespace {

// The request's 3-D picture at full size, and the camera it was seen from.
Json write_full_picture(const PictureRequest& request, const PictureScene& scene) {
  const io::PictureCamera camera = picture_camera(scene, request, kFullWidth, kFullHeight);
  io::write_png(request.path, render_picture(scene, camera, true));
  return picture_json(request.path, camera);
}

}  // namespace

Json write_analysis_pictures(const PictureRequest& request, const map::OccupancyMap& map,
                             const frontier_voids::Analysis& a, bool with_voids) {
  if (!request.top_path.empty()) write_picture(request.top_path, map, a, with_voids);
  if (request.path.empty()) return nullptr;
  PictureScene scene = picture_scene(map.occupied_centers(), map.resolution_m(), a);
  scene.voids_analysed = with_voids;
  return write_full_picture(request, scene);
}

Json write_search_pictures(const PictureRequest& request, const map::OccupancyMap& map,
                           const frontier_voids::Analysis& a, const nbv::Result& r, const io::DepthCamera& sensor,
                           const std::optional<Eigen::Vector3d>& base_m) {
  if (!request.top_path.empty()) write_utility_picture(request.top_path, map, a, r);
  if (request.path.empty()) return nullptr;
  PictureScene scene = picture_scene(map.occupied_centers(), map.resolution_m(), a);
  add_utility_field(scene, r);
  scene.sensor = sensor;
  if (!r.views.empty()) scene.chosen = r.views.front().T_world_sensor;
  scene.robot_m = base_m ? base_m : scene.chosen ? std::optional<Eigen::Vector3d>(scene.chosen->translation()) : std::nullopt;
  return write_full_picture(request, scene);
}

PictureScene view_scene(const std::vector<Eigen::Vector3f>& occupied_m, double resolution_m,
                        const pipeline::StepResult& step, std::optional<std::size_t> chosen,
                        const io::DepthCamera& sensor, const std::optional<Eigen::Vector3d>& robot_m) {
  PictureScene scene = picture_scene(occupied_m, resolution_m, step.analysis);
  scene.taken = step.T_world_sensor;
  if (chosen) scene.chosen = step.nbv.views.at(*chosen).T_world_sensor;
  scene.sensor = sensor;
  scene.robot_m = robot_m;
  return scene;
}

SessionPictures::SessionPictures(std::string dir, PictureRequest request, const io::DepthCamera& sensor,
                                 const std::optional<Eigen::Isometry3d>& T_world_base)
    : dir_(std::move(dir)), request_(std::move(request)), sensor_(sensor) {
  if (T_world_base) robot_m_ = T_world_base->translation();
}

void SessionPictures::add(int view, const std::vector<Eigen::Vector3f>& occupied_m, double resolution_m,
                          const pipeline::StepResult& step, std::optional<std::size_t> chosen) {
  // Without an arm, the robot stood where the first view was taken: every view is seen from there.
  if (!robot_m_) robot_m_ = step.T_world_sensor.translation();
  const PictureScene scene = view_scene(occupied_m, resolution_m, step, chosen, sensor_, robot_m_);
  if (request_.per_view) {
    const std::filesystem::path folder = std::filesystem::path(dir_) / "pictures";
    create_folder(folder.string());
    io::write_png((folder / session::view_file_name(view, ".png")).string(),
                  render_picture(scene, picture_camera(scene, request_, kFullWidth, kFullHeight), true));
  }
  tiles_.push_back(render_picture(scene, picture_camera(scene, request_, kTileWidth, kTileHeight), false));
  captions_.push_back("view " + std::to_string(view + 1) + (scene.chosen || !step.searched ? "" : " (no next view)"));
}

void SessionPictures::finish(const std::string& title) const {
  if (tiles_.empty()) return;
  io::write_png((std::filesystem::path(dir_) / "views.png").string(),
                contact_sheet(tiles_, captions_, title));
}

}  // namespace fvx::report
