#include "fvx/io/render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

#include "fvx/core/error.hpp"

namespace fvx::io {

namespace {

constexpr float kEmpty = std::numeric_limits<float>::infinity();
// Cells smaller than this in the picture are squares, not faces: their faces would be a pixel
// or two, and rasterising three of them per cell took most of a real map's picture.
constexpr double kSmallCell_px = 3.0;

Rgb scaled(Rgb c, double f) {
  return {std::uint8_t(std::clamp(c[0] * f, 0.0, 255.0)), std::uint8_t(std::clamp(c[1] * f, 0.0, 255.0)),
          std::uint8_t(std::clamp(c[2] * f, 0.0, 255.0))};
}

Rgb blend(Rgb over, Rgb under, double alpha) {
  Rgb out;
  for (int i = 0; i < 3; ++i) out[std::size_t(i)] = std::uint8_t(std::lround(alpha * over[std::size_t(i)] + (1 - alpha) * under[std::size_t(i)]));
  return out;
}

// Twice the signed area of (a, b, p): which side of a→b p lies on.
double edge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

/// The parameters [t0, t1] ⊆ [0, 1] of the part of segment a→b inside the box [lo, hi]
/// (Liang–Barsky), or none when it misses the box.
std::optional<std::pair<double, double>> clip_to_box(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                                     const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return std::nullopt;
      continue;
    }
    double enter = (lo[k] - a[k]) / d[k], leave = (hi[k] - a[k]) / d[k];
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
    if (t0 > t1) return std::nullopt;
  }
  return std::make_pair(t0, t1);
}

}  // namespace

int text_width_px(const std::string& text, double scale) {
  return int(std::ceil(double(text.size()) * 20.0 * scale));  // the simplex font's widest advance is ~20 at scale 1
}

std::vector<std::string> PictureCamera::validate() const {
  std::vector<std::string> problems;
  if (!eye_m.allFinite() || !target_m.allFinite() || (eye_m - target_m).norm() < 1e-6)
    problems.push_back("the picture's eye and target must be two different points");
  if (!(fov_deg > 1 && fov_deg < 170)) problems.push_back("the picture's field of view must be in (1, 170) degrees");
  if (width_px < 16 || width_px > 8192 || height_px < 16 || height_px > 8192)
    problems.push_back("a picture's sides must be 16 to 8192 pixels");
  return problems;
}

Eigen::Isometry3d camera_pose(const PictureCamera& camera) {
  const Eigen::Vector3d forward = (camera.target_m - camera.eye_m).normalized();
  // World z up on the image; looking straight down or up, world y is up instead.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  if (std::abs(forward.dot(up)) > 0.999) up = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d right = forward.cross(up).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = right;
  T.linear().col(1) = forward.cross(right);  // down
  T.linear().col(2) = forward;
  T.translation() = camera.eye_m;
  return T;
}

double focal_px(const PictureCamera& camera) {
  return 0.5 * camera.width_px / std::tan(0.5 * camera.fov_deg * M_PI / 180.0);
}

std::optional<Eigen::Vector3d> project(const PictureCamera& camera, const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d p = camera_pose(camera).inverse() * p_world;
  if (!(p.z() >= kPictureNear_m)) return std::nullopt;
  const double f = focal_px(camera);
  return Eigen::Vector3d(f * p.x() / p.z() + 0.5 * camera.width_px, f * p.y() / p.z() + 0.5 * camera.height_px, p.z());
}

Canvas::Canvas(const PictureCamera& camera, Rgb background)
    : camera_(camera), T_camera_world_(camera_pose(camera).inverse()), focal_px_(focal_px(camera)) {
  FVX_ASSERT(camera.validate().empty(), "a valid picture camera");
  image_.width = camera.width_px;
  image_.height = camera.height_px;
  image_.pixels.assign(std::size_t(image_.width) * std::size_t(image_.height), background);
  depth_.assign(image_.pixels.size(), kEmpty);
}

bool Canvas::covered(int x, int y) const {
  return x >= 0 && y >= 0 && x < image_.width && y < image_.height &&
         depth_[std::size_t(y) * std::size_t(image_.width) + std::size_t(x)] < kEmpty;
}

void Canvas::put(int x, int y, float depth, Rgb colour) {
  if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
  const std::size_t i = std::size_t(y) * std::size_t(image_.width) + std::size_t(x);
  if (!(depth < depth_[i])) return;
  depth_[i] = depth;
  image_.pixels[i] = colour;
}

void Canvas::square(double u, double v, double half_px, float depth, Rgb colour) {
  // The pixels whose centres lie within half_px of (u, v); at least the one holding it.
  if (!(std::abs(u) < 1e7 && std::abs(v) < 1e7 && half_px < 1e7)) return;
  const int x0 = int(std::floor(u - half_px + 0.5)), x1 = std::max(x0, int(std::floor(u + half_px - 0.5)));
  const int y0 = int(std::floor(v - half_px + 0.5)), y1 = std::max(y0, int(std::floor(v + half_px - 0.5)));
  for (int y = std::max(0, y0); y <= std::min(image_.height - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(image_.width - 1, x1); ++x) put(x, y, depth, colour);
}

// A face's corners in order around it (c00, c10, c11, c01), as two triangles. Depth is
// interpolated as 1/z, which is affine in screen space under perspective. Pixels within
// 0.75 px of the face's border are darker when the face is at least 5 px across.
void Canvas::quad(const std::array<Corner, 4>& q, Rgb colour) {
  double u0 = q[0].px.x(), u1 = u0, v0 = q[0].px.y(), v1 = v0;
  for (const Corner& c : q) {
    u0 = std::min(u0, c.px.x()), u1 = std::max(u1, c.px.x());
    v0 = std::min(v0, c.px.y()), v1 = std::max(v1, c.px.y());
  }
  // Clamped before the conversion: a corner near the near plane projects far outside.
  const double W = image_.width, H = image_.height;
  const int x0 = int(std::floor(std::clamp(u0, 0.0, W))), x1 = int(std::ceil(std::clamp(u1, -1.0, W - 1)));
  const int y0 = int(std::floor(std::clamp(v0, 0.0, H))), y1 = int(std::ceil(std::clamp(v1, -1.0, H - 1)));
  const double side_s = (q[1].px - q[0].px).norm(), side_t = (q[3].px - q[0].px).norm();
  const bool outline = side_s >= 5 && side_t >= 5;
  const Rgb dark = scaled(colour, 0.72);
  // Triangles (0, 1, 2) and (0, 2, 3); (s, t) of a point from its barycentric weights.
  const std::array<std::array<int, 3>, 2> tris = {{{0, 1, 2}, {0, 2, 3}}};
  for (int t = 0; t < 2; ++t) {
    const Corner &a = q[std::size_t(tris[std::size_t(t)][0])], &b = q[std::size_t(tris[std::size_t(t)][1])],
                 &c = q[std::size_t(tris[std::size_t(t)][2])];
    const double area = edge(a.px, b.px, c.px);
    if (std::abs(area) < 1e-12) continue;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        const double wa = edge(b.px, c.px, p) / area, wb = edge(c.px, a.px, p) / area, wc = 1 - wa - wb;
        if (wa < -1e-9 || wb < -1e-9 || wc < -1e-9) continue;
        const double inv_z = wa * a.inv_depth + wb * b.inv_depth + wc * c.inv_depth;
        const double s = t == 0 ? wb + wc : wb, tt = t == 0 ? wc : wb + wc;
        const bool border = outline && (std::min(s, 1 - s) * side_s < 0.75 || std::min(tt, 1 - tt) * side_t < 0.75);
        put(x, y, float(1.0 / inv_z), border ? dark : colour);
      }
  }
}

void Canvas::cells(const std::vector<Eigen::Vector3d>& centers_m, double edge_m, Rgb colour) {
  const Eigen::Isometry3d T_world_camera = T_camera_world_.inverse();
  // The light comes from behind and above the camera, a little from its right.
  const Eigen::Vector3d light =
      (-T_world_camera.linear().col(2) - 0.9 * T_world_camera.linear().col(1) + 0.35 * T_world_camera.linear().col(0))
          .normalized();
  const double h = 0.5 * edge_m;
  const double top_shade = 0.35 + 0.65 * std::max(0.0, light.z());
  const Eigen::Vector3d& eye = camera_.eye_m;
  for (const Eigen::Vector3d& c : centers_m) {
    const Eigen::Vector3d pc = T_camera_world_ * c;
    if (pc.z() < kPictureNear_m + edge_m) continue;
    const double size_px = focal_px_ * edge_m / pc.z();
    if (size_px < kSmallCell_px) {  // a few pixels: a square in the shade of its top face
      square(focal_px_ * pc.x() / pc.z() + 0.5 * image_.width, focal_px_ * pc.y() / pc.z() + 0.5 * image_.height,
             0.5 * size_px, float(pc.z()), scaled(colour, top_shade));
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const double delta = eye[k] - c[k];
      if (std::abs(delta) <= h) continue;  // the camera is level with both faces on this axis
      const double sign = delta > 0 ? 1.0 : -1.0;
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      std::array<Corner, 4> q;
      const std::array<std::array<double, 2>, 4> offsets = {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
      bool behind = false;
      for (std::size_t n = 0; n < 4; ++n) {
        Eigen::Vector3d corner = c;
        corner[k] += sign * h, corner[i] += offsets[n][0] * h, corner[j] += offsets[n][1] * h;
        const Eigen::Vector3d p = T_camera_world_ * corner;
        if (p.z() < kPictureNear_m) behind = true;
        q[n] = {Eigen::Vector2d(focal_px_ * p.x() / p.z() + 0.5 * image_.width,
                                focal_px_ * p.y() / p.z() + 0.5 * image_.height),
                1.0 / p.z()};
      }
      if (behind) continue;
      quad(q, scaled(colour, 0.35 + 0.65 * std::max(0.0, sign * light[k])));
    }
  }
}

void Canvas::dots(const std::vector<Eigen::Vector3d>& centers_m, const std::vector<Rgb>& colours, double edge_m) {
  FVX_ASSERT(centers_m.size() == colours.size(), "a colour per dot");
  for (std::size_t n = 0; n < centers_m.size(); ++n) {
    const Eigen::Vector3d p = T_camera_world_ * centers_m[n];
    if (p.z() < kPictureNear_m) continue;
    square(focal_px_ * p.x() / p.z() + 0.5 * image_.width, focal_px_ * p.y() / p.z() + 0.5 * image_.height,
           std::max(0.5, 0.5 * focal_px_ * edge_m / p.z()), float(p.z()), colours[n]);
  }
}

void Canvas::line(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, Rgb colour, int width_px) {
  Eigen::Vector3d a = T_camera_world_ * a_m, b = T_camera_world_ * b_m;
  if (a.z() < kPictureNear_m && b.z() < kPictureNear_m) return;
  // Cut the part nearer than the near plane.
  if (a.z() < kPictureNear_m) a = a + (b - a) * ((kPictureNear_m - a.z()) / (b.z() - a.z()));
  if (b.z() < kPictureNear_m) b = b + (a - b) * ((kPictureNear_m - b.z()) / (a.z() - b.z()));
  const auto pixel = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector2d(focal_px_ * p.x() / p.z() + 0.5 * image_.width, focal_px_ * p.y() / p.z() + 0.5 * image_.height);
  };
  const Eigen::Vector2d pa = pixel(a), pb = pixel(b);
  const double length = (pb - pa).norm();
  if (!(length < 1e15)) return;  // not finite, or beyond what a sample index holds exactly
  // One sample per pixel of length, drawn only where the pen touches the image: a segment
  // from just past the near plane runs far off the image, and its samples there are skipped
  // without being visited (only its part on the image costs anything).
  const int lo = -(width_px - 1) / 2, hi = width_px / 2;
  const double margin = width_px + 1.0;  // a sample this far off the image draws nothing on it
  const auto on_image = clip_to_box(pa, pb, Eigen::Vector2d::Constant(-margin),
                                    Eigen::Vector2d(image_.width + margin, image_.height + margin));
  if (!on_image) return;
  const double steps = std::max(1.0, std::ceil(length));
  const Rgb pale = blend(colour, {255, 255, 255}, 0.55);
  const auto first = std::int64_t(std::floor(on_image->first * steps)), last = std::int64_t(std::ceil(on_image->second * steps));
  for (std::int64_t s = first; s <= last; ++s) {
    const double w = double(s) / steps;
    const Eigen::Vector2d p = pa + w * (pb - pa);
    const double depth = 1.0 / ((1 - w) / a.z() + w / b.z());
    for (int dy = lo; dy <= hi; ++dy)
      for (int dx = lo; dx <= hi; ++dx) {
        const int x = int(std::floor(p.x())) + dx, y = int(std::floor(p.y())) + dy;
        if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) continue;
        const std::size_t i = std::size_t(y) * std::size_t(image_.width) + std::size_t(x);
        const bool hidden = depth_[i] < kEmpty && depth > depth_[i] * 1.002 + 1e-3;
        if (!hidden) image_.pixels[i] = colour;
        else if ((s / 4) % 2 == 0) image_.pixels[i] = pale;  // dashed behind surfaces
      }
  }
}

void Canvas::overlay(const Canvas& layer, double alpha_hidden, bool take_depth) {
  FVX_ASSERT(layer.image_.width == image_.width && layer.image_.height == image_.height, "same-sized canvases");
  for (std::size_t i = 0; i < depth_.size(); ++i) {
    if (!(layer.depth_[i] < kEmpty)) continue;
    if (layer.depth_[i] <= depth_[i]) {
      image_.pixels[i] = layer.image_.pixels[i];
      if (take_depth) depth_[i] = layer.depth_[i];
    } else {
      image_.pixels[i] = blend(layer.image_.pixels[i], image_.pixels[i], alpha_hidden);
    }
  }
}

void Canvas::fill_rect(int x, int y, int w, int h, Rgb colour, double alpha) {
  for (int yy = std::max(0, y); yy < std::min(image_.height, y + h); ++yy)
    for (int xx = std::max(0, x); xx < std::min(image_.width, x + w); ++xx)
      image_.at(xx, yy) = alpha >= 1 ? colour : blend(colour, image_.at(xx, yy), alpha);
}

void Canvas::line_px(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Rgb colour, int width_px) {
  const int steps = std::max(1, int(std::ceil((b - a).norm())));
  const int lo = -(width_px - 1) / 2, hi = width_px / 2;
  for (int s = 0; s <= steps; ++s) {
    const Eigen::Vector2d p = a + (b - a) * (double(s) / steps);
    for (int dy = lo; dy <= hi; ++dy)
      for (int dx = lo; dx <= hi; ++dx) {
        const int x = int(std::floor(p.x())) + dx, y = int(std::floor(p.y())) + dy;
        if (x >= 0 && y >= 0 && x < image_.width && y < image_.height) image_.at(x, y) = colour;
      }
  }
}

}  // namespace fvx::io
