#pragma once
/// \file
/// Off-screen 3-D pictures of cells (the paper's Figures 2–4 look): a pinhole camera, a
/// z-buffered rasteriser of the cells' visible cube faces with flat Lambert shading, lines
/// that are dashed where a surface hides them, and layers blended through the surfaces in
/// front of them (voids inside boxes). No display and no GPU: pixels in memory, written as
/// PNG by io::write_png (which also draws the pictures' texts).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "fvx/io/visual.hpp"

namespace fvx::io {

/// The camera of a picture: at eye_m looking at target_m, world z up on the image.
struct PictureCamera {
  Eigen::Vector3d eye_m = Eigen::Vector3d(-1, -1, 1);
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();
  double fov_deg = 50.0;  ///< horizontal field of view
  int width_px = 960;
  int height_px = 720;
  /// Every violation, one line each (eye at the target, a field of view outside (1, 170)
  /// degrees, a side outside [16, 8192] pixels); empty when valid.
  std::vector<std::string> validate() const;
};

/// Points nearer to the camera than this are not drawn, metres.
constexpr double kPictureNear_m = 0.01;

/// T_world_camera: x right, y down, z along the viewing axis (the optical convention).
Eigen::Isometry3d camera_pose(const PictureCamera& camera);
/// Focal length in pixels: (width / 2) / tan(fov / 2).
double focal_px(const PictureCamera& camera);
/// (u, v, depth) of a world point: the pixel column and row (pixel x covers [x, x + 1)),
/// and the depth along the viewing axis, metres; empty when nearer than kPictureNear_m.
std::optional<Eigen::Vector3d> project(const PictureCamera& camera, const Eigen::Vector3d& p_world);

/// An image with a depth per pixel. Everything 3-D is depth-tested against what is drawn.
class Canvas {
 public:
  explicit Canvas(const PictureCamera& camera, Rgb background = {255, 255, 255});

  /// Cubes of edge `edge_m` around `centers_m`: the faces that look towards the camera,
  /// shaded by a light from over the camera's shoulder, edges a little darker where a face
  /// is large enough to show them. A cube under 3 pixels is a square of its size (at least
  /// one pixel) in the shade of its top face.
  void cells(const std::vector<Eigen::Vector3d>& centers_m, double edge_m, Rgb colour);
  /// Squares of `edge_m` (at their depth) facing the camera, one colour each.
  void dots(const std::vector<Eigen::Vector3d>& centers_m, const std::vector<Rgb>& colours, double edge_m);
  /// A segment `width_px` wide: solid where nothing drawn is in front of it, dashed and
  /// paler where something is. Lines do not hide what is drawn after them.
  void line(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, Rgb colour, int width_px = 1);
  /// `layer`'s pixels over this canvas: opaque where the layer is in front, blended at
  /// `alpha_hidden` where this canvas has a surface in front of them (seen through it).
  /// `take_depth` false: what is drawn later is not hidden by the layer (lines over a haze).
  void overlay(const Canvas& layer, double alpha_hidden, bool take_depth = true);

  /// Screen-space drawing for annotations (no depth): a filled rectangle, blended at
  /// `alpha`; a segment between pixel positions.
  void fill_rect(int x, int y, int w, int h, Rgb colour, double alpha = 1.0);
  void line_px(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Rgb colour, int width_px = 1);

  /// Whether a 3-D primitive covers pixel (x, y).
  bool covered(int x, int y) const;
  const PictureCamera& camera() const { return camera_; }
  RgbImage& image() { return image_; }
  const RgbImage& image() const { return image_; }

 private:
  struct Corner {
    Eigen::Vector2d px;
    double inv_depth;
  };
  void quad(const std::array<Corner, 4>& q, Rgb colour);
  void square(double u, double v, double half_px, float depth, Rgb colour);
  void put(int x, int y, float depth, Rgb colour);

  PictureCamera camera_;
  Eigen::Isometry3d T_camera_world_;
  double focal_px_;
  RgbImage image_;
  std::vector<float> depth_;
};

}  // namespace fvx::io
