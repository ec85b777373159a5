#include "fvx/io/visual.hpp"

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <ostream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "save_pcd.hpp"
#include "save_png.hpp"

namespace fvx::io {

void write_colored_cloud(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Rgb>& colors) {
  FVX_ASSERT(points.size() == colors.size(), "a colour per point");
  const std::string ext = lowercase_extension(path);
  if (ext == ".ply") {
    write_file_atomically(path, [&](std::ostream& out) {
      out << "ply\nformat binary_little_endian 1.0\ncomment written by fvx\nelement vertex " << points.size()
          << "\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
      for (std::size_t i = 0; i < points.size(); ++i) {
        out.write(reinterpret_cast<const char*>(points[i].data()), 3 * sizeof(float));
        out.write(reinterpret_cast<const char*>(colors[i].data()), 3);
      }
    });
  } else if (ext == ".pcd") {
    pcl::PointCloud<pcl::PointXYZRGB> cloud;
    for (std::size_t i = 0; i < points.size(); ++i) {
      pcl::PointXYZRGB p(colors[i][0], colors[i][1], colors[i][2]);
      p.x = points[i].x(), p.y = points[i].y(), p.z = points[i].z();
      cloud.push_back(p);
    }
    write_path_atomically(path, [&](const std::string& temp) {
      if (cloud.empty()) {  // PCL refuses to write an empty cloud; an empty result is valid
        write_file_atomically(temp, [](std::ostream& out) {
          out << "# .PCD v0.7 - written by fvx\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\n"
                 "COUNT 1 1 1 1\nWIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n";
        });
      } else {
        save_pcd_binary(temp, cloud, path);
      }
    });
  } else {
    throw FileError(path, "unknown cloud format '" + ext + "'; expected .ply or .pcd");
  }
}

void write_ply_mesh(const std::string& path, const std::vector<Eigen::Vector3f>& vertices,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<Rgb>& colors) {
  FVX_ASSERT(vertices.size() == colors.size(), "a colour per vertex");
  if (lowercase_extension(path) != ".ply") throw FileError(path, "meshes are written as .ply");
  write_file_atomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\ncomment written by fvx\nelement vertex " << vertices.size()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face "
        << triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      out.write(reinterpret_cast<const char*>(vertices[i].data()), 3 * sizeof(float));
      out.write(reinterpret_cast<const char*>(colors[i].data()), 3);
    }
    for (const auto& t : triangles) {
      const unsigned char three = 3;
      const std::int32_t index[3] = {std::int32_t(t[0]), std::int32_t(t[1]), std::int32_t(t[2])};
      out.write(reinterpret_cast<const char*>(&three), 1);
      out.write(reinterpret_cast<const char*>(index), sizeof index);
    }
  });
}

void write_top_view_png(const std::string& path, double cell_m, const std::vector<PictureLayer>& layers,
                        int width_px) {
  if (lowercase_extension(path) != ".png") throw FileError(path, "pictures are written as .png");
  Eigen::AlignedBox2d box;
  for (const auto& layer : layers)
    for (const auto& c : layer.centers_m) box.extend(c.head<2>());
  if (box.isEmpty()) box = Eigen::AlignedBox2d(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1));
  box.min().array() -= cell_m;
  box.max().array() += cell_m;
  const double scale = width_px / std::max(box.sizes().x(), 1e-9);  // pixels per metre
  const int legend_px = 24 * int(layers.size()) + 12;
  const int height_px = int(std::ceil(box.sizes().y() * scale)) + legend_px;
  cv::Mat image(height_px, width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  // Square edges from the cell's own bounds, so that neighbouring cells leave no gap.
  auto square = [&](const Eigen::Vector3d& c) {
    const int u0 = int(std::floor((c.x() - cell_m / 2 - box.min().x()) * scale));
    const int u1 = int(std::floor((c.x() + cell_m / 2 - box.min().x()) * scale));
    const int v0 = int(std::floor((box.max().y() - c.y() - cell_m / 2) * scale)) + legend_px;
    const int v1 = int(std::floor((box.max().y() - c.y() + cell_m / 2) * scale)) + legend_px;
    return cv::Rect(u0, v0, std::max(1, u1 - u0), std::max(1, v1 - v0));
  };
  for (const PictureLayer& layer : layers) {
    // Within a layer the highest cells on top.
    std::vector<const Eigen::Vector3d*> cells;
    for (const auto& c : layer.centers_m) cells.push_back(&c);
    std::stable_sort(cells.begin(), cells.end(), [](const auto* a, const auto* b) { return a->z() < b->z(); });
    double z_lo = INFINITY, z_hi = -INFINITY;
    for (const auto* c : cells) z_lo = std::min(z_lo, c->z()), z_hi = std::max(z_hi, c->z());
    cv::Mat target = layer.translucent ? image.clone() : image;
    for (const auto* c : cells) {
      double shade = 1.0;
      if (layer.shade_by_height && z_hi > z_lo) shade = 0.45 + 0.55 * (c->z() - z_lo) / (z_hi - z_lo);
      const Rgb& rgb = layer.color;
      cv::rectangle(target, square(*c), cv::Scalar(rgb[2] * shade, rgb[1] * shade, rgb[0] * shade), cv::FILLED);
    }
    if (layer.translucent) cv::addWeighted(target, 0.45, image, 0.55, 0.0, image);
  }
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const Rgb& rgb = layers[l].color;
    const int y = 8 + 24 * int(l);
    cv::rectangle(image, cv::Rect(10, y, 16, 16), cv::Scalar(rgb[2], rgb[1], rgb[0]), cv::FILLED);
    cv::putText(image, layers[l].name + " (" + std::to_string(layers[l].centers_m.size()) + " cells)",
                cv::Point(34, y + 14), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  }
  write_path_atomically(path, [&](const std::string& temp) {
    save_png(temp, image, path);
  });
}

void write_png(const std::string& path, const RgbImage& image) {
  if (lowercase_extension(path) != ".png") throw FileError(path, "pictures are written as .png");
  FVX_ASSERT(image.pixels.size() == std::size_t(image.width) * std::size_t(image.height), "a pixel per position");
  cv::Mat bgr(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Rgb& c = image.at(x, y);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(c[2], c[1], c[0]);
    }
  for (const PictureText& t : image.texts)
    cv::putText(bgr, t.text, cv::Point(t.x_px, t.y_px), cv::FONT_HERSHEY_SIMPLEX, t.scale,
                cv::Scalar(t.colour[2], t.colour[1], t.colour[0]), 1, cv::LINE_AA);
  write_path_atomically(path, [&](const std::string& temp) {
    save_png(temp, bgr, path);
  });
}

void write_line_plot_png(const std::string& path, const std::string& title, const std::string& x_label,
                         const std::string& y_label, const std::vector<PlotSeries>& series, int width_px,
                         int height_px) {
  if (lowercase_extension(path) != ".png") throw FileError(path, "plots are written as .png");
  std::size_t n = 0;
  double top = 0.0;
  for (const auto& s : series) {
    n = std::max(n, s.values.size());
    for (const double v : s.values)
      if (std::isfinite(v)) top = std::max(top, v);
  }
  if (!(top > 0)) top = 1.0;
  // A round upper limit: 1, 2 or 5 times a power of ten, above the largest value.
  const double step10 = std::pow(10.0, std::floor(std::log10(top)));
  const double upper = top <= step10 ? step10 : top <= 2 * step10 ? 2 * step10 : top <= 5 * step10 ? 5 * step10 : 10 * step10;
  cv::Mat image(height_px, width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 80, right = 20, top_px = 56 + 20 * int(series.size()), bottom = 50;
  const int plot_w = width_px - left - right, plot_h = height_px - top_px - bottom;
  const cv::Scalar ink(30, 30, 30), grid(225, 225, 225);
  auto text = [&](const std::string& s, int x, int y, double scale = 0.45) {
    cv::putText(image, s, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, ink, 1, cv::LINE_AA);
  };
  auto px = [&](double x) { return left + (n > 1 ? int(std::lround((x - 1) * plot_w / double(n - 1))) : plot_w / 2); };
  auto py = [&](double y) { return top_px + plot_h - int(std::lround(y / upper * plot_h)); };
  text(title, left, 22, 0.55);
  for (int t = 0; t <= 5; ++t) {  // horizontal grid lines and their values
    const double y = upper * t / 5;
    cv::line(image, cv::Point(left, py(y)), cv::Point(left + plot_w, py(y)), grid, 1);
    char label[32];
    std::snprintf(label, sizeof label, "%g", y);
    text(label, 8, py(y) + 5, 0.4);
  }
  const std::size_t every = std::max<std::size_t>(1, (n + 14) / 15);  // at most ~15 x ticks
  for (std::size_t x = 1; x <= n; x += every) text(std::to_string(x), px(double(x)) - 4, top_px + plot_h + 18, 0.4);
  cv::rectangle(image, cv::Rect(left, top_px, plot_w, plot_h), ink, 1);
  text(x_label, left + plot_w / 2 - 20, height_px - 10);
  text(y_label, 8, top_px - 16, 0.4);
  for (std::size_t s = 0; s < series.size(); ++s) {
    const Rgb& c = series[s].color;
    const cv::Scalar colour(c[2], c[1], c[0]);
    const auto& v = series[s].values;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const cv::Point p(px(double(i + 1)), py(v[i]));
      if (i > 0) cv::line(image, cv::Point(px(double(i)), py(v[i - 1])), p, colour, 2, cv::LINE_AA);
      cv::circle(image, p, 3, colour, cv::FILLED, cv::LINE_AA);
    }
    const int y = 46 + 20 * int(s);
    cv::rectangle(image, cv::Rect(left + 8, y - 10, 14, 10), colour, cv::FILLED);
    char last[64] = "";
    if (!v.empty()) std::snprintf(last, sizeof last, " (last %.2f)", v.back());
    text(series[s].name + last, left + 28, y, 0.45);
  }
  write_path_atomically(path, [&](const std::string& temp) {
    save_png(temp, image, path);
  });
}

}  // namespace fvx::io
