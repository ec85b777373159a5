#pragma once
/// \file
/// The 3-D pictures of `fvx frontiers`, `voids`, `nbv`, and of each view of `explore` and
/// `replay` (the paper's Figures 2–6 look): the search space's occupied cells shaded grey,
/// frontier cells red, void cells violet (seen through the surfaces in front of them, paler),
/// the void clusters' ellipsoids as their three principal ellipses, the utility field by
/// rank, the view taken and the chosen next view as frusta; a legend, a scale bar and the
/// world axes. A session's views also go on one contact sheet (views.png).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "fvx/core/json.hpp"
#include "fvx/core/options.hpp"
#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/io/render.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/pipeline/pipeline.hpp"

namespace fvx::report {

/// What a command was asked to draw (--picture, --picture-top, --picture-eye,
/// --picture-target; explore and replay: --pictures).
struct PictureRequest {
  std::string path;      ///< the 3-D picture (empty: none)
  std::string top_path;  ///< the top view of earlier fvx versions (empty: none)
  bool per_view = false;  ///< sessions: DIR/pictures/viewNNN.png for every view
  std::optional<Eigen::Vector3d> eye_m, target_m;
};

/// --picture FILE.png and --picture-top FILE.png (or, for a session, --pictures), and
/// --picture-eye X,Y,Z / --picture-target X,Y,Z.
std::vector<OptionSpec> picture_options(bool session, const char* picture_help, const char* top_help);
/// The options' values; UsageError for a picture path that is not .png or a point that is
/// not three finite numbers, or for an eye equal to the target.
PictureRequest read_picture_options(const Args& args);

/// Everything a picture shows, in world coordinates.
struct PictureScene {
  double cell_m = 0.025;
  Eigen::AlignedBox3d bounds_m;  ///< S: what the camera looks at
  std::vector<Eigen::Vector3d> occupied_m, frontier_m, void_m;
  std::vector<voids::VoidCluster> clusters;    ///< drawn as ellipsoids
  bool voids_analysed = true;                  ///< false (fvx frontiers): the legend names no voids
  std::vector<Eigen::Vector3d> utility_m;      ///< the utility field's kept cells …
  std::vector<double> utility_rank;            ///< … and their rank in [0, 1]
  std::optional<Eigen::Isometry3d> taken;      ///< the view just taken (sessions), grey
  std::optional<Eigen::Isometry3d> chosen;     ///< the chosen next view, blue
  io::DepthCamera sensor;                      ///< the frusta's shape
  /// Where the robot stands (an arm's base, else the first view): the default camera looks
  /// at S from this side.
  std::optional<Eigen::Vector3d> robot_m;
};

/// The centre of a cell from its key (OctoMap's convention: (key − 32768 + ½)·R).
Eigen::Vector3d key_center(const map::VoxelKey& key, double resolution_m);
/// The occupied cells of `occupied_m` inside S, the frontier and void cells and the void
/// clusters of `a`.
PictureScene picture_scene(const std::vector<Eigen::Vector3f>& occupied_m, double resolution_m,
                           const frontier_voids::Analysis& a);
/// The utility field's kept cells and their ranks (nbv::Result::utility_field).
void add_utility_field(PictureScene& scene, const nbv::Result& r);

/// The camera: at the request's eye and target if given; by default it looks at the centre
/// of S from the robot's side (else from −x, −y), 35° above the horizontal, far enough that
/// S's bounding sphere, grown to hold the taken and chosen views' eyes, fits the narrower
/// field of view.
io::PictureCamera picture_camera(const PictureScene& scene, const PictureRequest& request, int width_px,
                                 int height_px);
/// The picture; `annotated`: with the legend, scale bar and axes (false: the bare scene, for
/// a contact sheet's tiles).
io::RgbImage render_picture(const PictureScene& scene, const io::PictureCamera& camera, bool annotated);
/// Tiles side by side in rows of `columns`, each with its caption, under a line of `title`.
io::RgbImage contact_sheet(const std::vector<io::RgbImage>& tiles, const std::vector<std::string>& captions,
                           const std::string& title);
/// {"path", "eye_m", "target_m", "fov_deg", "width_px", "height_px"}: how to find a point
/// of the world in the picture (io::project).
Json picture_json(const std::string& path, const io::PictureCamera& camera);

/// --picture and --picture-top of `fvx frontiers` and `fvx voids` (void cells and clusters
/// only `with_voids`, in the top view; the 3-D one draws what `a` holds): picture_json of
/// the 3-D picture, or null without one.
Json write_analysis_pictures(const PictureRequest& request, const map::OccupancyMap& map,
                             const frontier_voids::Analysis& a, bool with_voids);

/// --picture and --picture-top of `fvx nbv`: the analysis, the utility field and the best
/// view's frustum, seen from the arm's base (`base_m`) or else from the best view's side.
Json write_search_pictures(const PictureRequest& request, const map::OccupancyMap& map,
                           const frontier_voids::Analysis& a, const nbv::Result& r, const io::DepthCamera& sensor,
                           const std::optional<Eigen::Vector3d>& base_m);

/// A session's view: its analysis (occupied cells from `occupied_m`), the pose it was
/// integrated at (taken) and its search's chosen next view (an index into step.nbv.views).
PictureScene view_scene(const std::vector<Eigen::Vector3f>& occupied_m, double resolution_m,
                        const pipeline::StepResult& step, std::optional<std::size_t> chosen,
                        const io::DepthCamera& sensor, const std::optional<Eigen::Vector3d>& robot_m);

/// The pictures of a session (explore, replay): with --pictures, pictures/viewNNN.png per
/// view; always a small tile per view for views.png, written by finish(). Every view is seen
/// from the arm's base, or without an arm from where the first view was taken.
class SessionPictures {
 public:
  SessionPictures(std::string dir, PictureRequest request, const io::DepthCamera& sensor,
                  const std::optional<Eigen::Isometry3d>& T_world_base);
  /// View `view` (0-based; view_scene of its step): its picture when asked for, its tile.
  void add(int view, const std::vector<Eigen::Vector3f>& occupied_m, double resolution_m,
           const pipeline::StepResult& step, std::optional<std::size_t> chosen);
  /// views.png: every tile, the chosen next view marked in each; nothing without views.
  void finish(const std::string& title) const;

 private:
  std::string dir_;
  PictureRequest request_;
  io::DepthCamera sensor_;
  std::optional<Eigen::Vector3d> robot_m_;
  std::vector<io::RgbImage> tiles_;
  std::vector<std::string> captions_;
};

}  // namespace fvx::report
