#pragma once
/// \file
/// Outputs people look at: coloured point clouds (PLY or PCD, for pcl_viewer, CloudCompare,
/// MeshLab), triangle meshes (PLY), orthographic top views of cells and the 3-D pictures of
/// io/render.hpp (PNG, like the paper's Figures 2–4). Every file is written atomically.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace fvx::io {

using Rgb = std::array<std::uint8_t, 3>;

/// Points with a colour each, as binary PLY (x y z red green blue) or PCD (x y z rgb),
/// chosen by extension; FileError for another extension.
void write_colored_cloud(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Rgb>& colors);

/// A triangle mesh with a colour per vertex, as binary PLY.
void write_ply_mesh(const std::string& path, const std::vector<Eigen::Vector3f>& vertices,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<Rgb>& colors);

/// Cells drawn as squares seen from above (looking down −z, x to the right, y up), scaled to
/// fit `width_px`: layers in order, each over the previous ones, within a layer the highest
/// cells on top. A legend names the layers and their cell counts.
struct PictureLayer {
  std::string name;
  Rgb color;
  std::vector<Eigen::Vector3d> centers_m;
  bool translucent = false;      ///< blended at 45 % over what is below (voids over boxes)
  bool shade_by_height = false;  ///< darker low, lighter high (shows the scene's shape)
};
void write_top_view_png(const std::string& path, double cell_m, const std::vector<PictureLayer>& layers,
                        int width_px = 900);

/// One line of a plot: a value per x = 1, 2, 3, …
struct PlotSeries {
  std::string name;
  Rgb color;
  std::vector<double> values;
};
/// Lines over x = 1..n on shared axes from 0 to the largest value, with a title, axis labels,
/// tick values and a legend naming each line and its last value; written atomically.
void write_line_plot_png(const std::string& path, const std::string& title, const std::string& x_label,
                         const std::string& y_label, const std::vector<PlotSeries>& series, int width_px = 900,
                         int height_px = 520);

/// Text drawn onto an image when it is written: the baseline's left end at (x_px, y_px).
struct PictureText {
  std::string text;
  int x_px = 0, y_px = 0;
  double scale = 0.45;  ///< OpenCV's Hershey simplex font scale (0.45: about 10 pixels high)
  Rgb colour = {30, 30, 30};
};
/// Pixels row by row (top first), and the texts io::write_png draws over them.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;
  std::vector<PictureText> texts;
  Rgb& at(int x, int y) { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
  const Rgb& at(int x, int y) const { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};
/// Text width in pixels at `scale`, as the Hershey simplex font draws it (an upper bound, for
/// laying out backgrounds without the font).
int text_width_px(const std::string& text, double scale);
/// The image as PNG with its texts drawn, atomically; FileError for another extension.
void write_png(const std::string& path, const RgbImage& image);

/// A colour per cluster id, distinct for neighbours, stable across runs.
Rgb cluster_color(int id);

}  // namespace fvx::io
