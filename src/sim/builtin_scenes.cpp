#include "fvx/sim/builtin_scenes.hpp"

#include "fvx/core/error.hpp"
#include "fvx/sim/scene_suite.hpp"

namespace fvx::sim {
namespace {

using Box = Eigen::AlignedBox3f;
using V = Eigen::Vector3f;

/// A slab spanning `lo`..`hi`, with a centred hole cut through its thinnest axis if asked.
void add_slab(Mesh& mesh, const Box& slab, const Face& face) {
  if (face.kind == Face::Open) return;
  if (face.kind == Face::Solid) {
    mesh.add_box(slab);
    return;
  }
  int normal_axis;
  (slab.max() - slab.min()).minCoeff(&normal_axis);
  const int a = normal_axis == 0 ? 1 : 0, b = normal_axis == 2 ? 1 : 2;
  const V c = slab.center();
  const float a0 = c[a] + face.hole_offset_m.x() - face.hole_a_m / 2, a1 = a0 + face.hole_a_m;
  const float b0 = c[b] + face.hole_offset_m.y() - face.hole_b_m / 2, b1 = b0 + face.hole_b_m;
  FVX_ASSERT(a0 > slab.min()[a] && a1 < slab.max()[a] && b0 > slab.min()[b] && b1 < slab.max()[b],
             "the hole must lie inside its face");
  auto piece = [&](float amin, float amax, float bmin, float bmax) {
    V lo = slab.min(), hi = slab.max();
    lo[a] = amin, hi[a] = amax, lo[b] = bmin, hi[b] = bmax;
    mesh.add_box(Box(lo, hi));
  };
  piece(slab.min()[a], a0, slab.min()[b], slab.max()[b]);  // the strips left and right of the hole
  piece(a1, slab.max()[a], slab.min()[b], slab.max()[b]);
  piece(a0, a1, slab.min()[b], b0);                        // below and above it
  piece(a0, a1, b1, slab.max()[b]);
}

Eigen::AlignedBox3d to_d(const Box& b) { return {b.min().cast<double>(), b.max().cast<double>()}; }

Eigen::AlignedBox3d interior(const Box& outer, float wall) {
  return to_d(Box(outer.min() + V::Constant(wall), outer.max() - V::Constant(wall)));
}

/// Four walls `t` thick around the rectangle (x0, y0)–(x1, y1), from z0 to z1: the x walls
/// span the rectangle's y, the y walls the whole outer x (corners are not doubled).
void add_walls(Mesh& m, float x0, float y0, float x1, float y1, float z0, float z1, float t) {
  m.add_box(Box(V(x0 - t, y0, z0), V(x0, y1, z1)));
  m.add_box(Box(V(x1, y0, z0), V(x1 + t, y1, z1)));
  m.add_box(Box(V(x0 - t, y0 - t, z0), V(x1 + t, y0, z1)));
  m.add_box(Box(V(x0 - t, y1, z0), V(x1 + t, y1 + t, z1)));
}

Mesh floor_slab() {
  Mesh m;
  m.add_box(Box(V(-0.6f, -1.6f, -0.05f), V(2.0f, 1.6f, 0.0f)));
  return m;
}

/// The floor slab inside four walls 2 m high, 5 cm thick, at its edges: the lab the paper's
/// settings stood in. A Kinect aimed over the boxes sees the far walls, so the air above them
/// becomes known free and an arm may move there; over a bare floor the rays above the
/// horizon return nothing and that air stays unknown.
Mesh lab() {
  Mesh m = floor_slab();
  add_walls(m, -0.6f, -1.6f, 2.0f, 1.6f, -0.05f, 2.0f, 0.05f);
  return m;
}

const Face kSolid[6] = {{}, {}, {}, {}, {}, {}};

Scene closed_box() {
  Scene s;
  s.mesh = floor_slab();
  const Box outer(V(0.52f, -0.27f, 0.0f), V(1.02f, 0.23f, 0.4f));
  Face faces[6] = {{}, {}, {}, {}, {}, {}};
  faces[5] = {Face::Hole, 0.16f, 0.16f, Eigen::Vector2f::Zero()};
  s.mesh.append(hollow_box(outer, 0.02f, faces));
  s.info.name = "closed box with one opening";
  s.info.search_space = Eigen::AlignedBox3d(Eigen::Vector3d(0.4, -0.4, 0.0), Eigen::Vector3d(1.15, 0.35, 0.55));
  s.info.containers.push_back({"box", interior(outer, 0.02f)});
  return s;
}

Scene room() {
  Scene s;
  const float t = 0.05f;
  s.mesh.add_box(Box(V(-2.0f, -1.5f, -t), V(2.0f, 1.5f, 0.0f)));             // floor
  s.mesh.add_box(Box(V(-2.0f, -1.5f, 2.5f), V(2.0f, 1.5f, 2.5f + t)));       // ceiling
  add_walls(s.mesh, -2.0f, -1.5f, 2.0f, 1.5f, -t, 2.5f + t, t);
  const Box crate(V(0.21f, -0.29f, 0.0f), V(0.81f, 0.31f, 0.6f));
  s.mesh.append(hollow_box(crate, 0.02f, kSolid));
  s.info.name = "room with a closed crate";
  s.info.search_space = Eigen::AlignedBox3d(Eigen::Vector3d(-1.9, -1.4, 0.0), Eigen::Vector3d(1.9, 1.4, 2.4));
  s.info.containers.push_back({"crate", interior(crate, 0.02f)});
  return s;
}

/// The victim: a small solid block standing inside a container.
NamedBox add_victim(Scene& s, const Box& block) {
  s.mesh.add_box(block);
  return {"victim", to_d(block)};
}

Scene crates() {
  Scene s;
  s.mesh = floor_slab();
  const float w = 0.015f;
  const Box closed(V(0.55f, 0.22f, 0.0f), V(0.95f, 0.58f, 0.35f));
  const Box side_open(V(0.62f, -0.23f, 0.0f), V(1.02f, 0.13f, 0.3f));
  const Box top_open(V(0.51f, -0.66f, 0.0f), V(0.83f, -0.34f, 0.25f));
  Face side[6] = {{}, {}, {}, {}, {}, {}};
  side[0] = {Face::Hole, 0.12f, 0.1f, Eigen::Vector2f(0.0f, 0.03f)};  // front (x−) face
  Face top[6] = {{}, {}, {}, {}, {}, {}};
  top[5] = {Face::Open};
  s.mesh.append(hollow_box(closed, w, kSolid));
  s.mesh.append(hollow_box(side_open, w, side));
  s.mesh.append(hollow_box(top_open, w, top));
  s.info.name = "three crates";
  s.info.target = add_victim(s, Box(V(0.8f, -0.1f, w), V(0.9f, 0.0f, w + 0.07f)));
  s.info.search_space = Eigen::AlignedBox3d(Eigen::Vector3d(0.4, -0.8, 0.0), Eigen::Vector3d(1.2, 0.75, 0.55));
  s.info.containers = {{"closed crate", interior(closed, w)}, {"crate with side opening", interior(side_open, w)},
                       {"open crate", interior(top_open, w)}};
  return s;
}

Scene paper_setting_1() {
  Scene s;
  s.mesh = lab();
  const float w = 0.01f;
  s.mesh.add_box(Box(V(0.52f, 0.27f, 0.0f), V(0.72f, 0.71f, 0.42f)));  // the computer (a tower)
  const Box box_a(V(0.63f, -0.47f, 0.0f), V(1.03f, -0.17f, 0.3f));
  const Box box_b(V(0.91f, 0.01f, 0.0f), V(1.26f, 0.36f, 0.27f));
  Face open_top[6] = {{}, {}, {}, {}, {}, {}};
  open_top[5] = {Face::Open};
  s.mesh.append(hollow_box(box_a, w, open_top));
  s.mesh.append(hollow_box(box_b, w, open_top));
  // Two-by-fours (38 × 89 mm): two on the floor, one across them.
  s.mesh.add_box(Box(V(0.37f, -0.12f, 0.0f), V(1.17f, -0.031f, 0.038f)));
  s.mesh.add_box(Box(V(0.37f, 0.59f + 0.15f, 0.0f), V(1.17f, 0.679f + 0.15f, 0.038f)));
  s.mesh.add_box(Box(V(1.3f, -0.5f, 0.0f), V(1.338f, 0.5f, 0.089f)));
  s.info.name = "paper setting 1: a computer, two boxes open on top, two-by-fours";
  s.info.target = add_victim(s, Box(V(1.0f, 0.1f, w), V(1.12f, 0.2f, w + 0.08f)));
  s.info.search_space = Eigen::AlignedBox3d(Eigen::Vector3d(0.3, -0.6, 0.0), Eigen::Vector3d(1.4, 0.9, 0.55));
  s.info.containers = {{"box A", interior(box_a, w)}, {"box B", interior(box_b, w)}};
  return s;
}

Scene paper_setting_2() {
  Scene s;
  s.mesh = lab();
  const float w = 0.01f;
  const Box large_1(V(0.71f, 0.13f, 0.0f), V(1.21f, 0.53f, 0.4f));
  const Box large_2(V(0.69f, -0.61f, 0.0f), V(1.14f, -0.16f, 0.35f));
  const Box small_1(V(0.45f, -0.11f, 0.0f), V(0.7f, 0.09f, 0.2f));
  const Box small_2(V(0.49f, 0.61f, 0.0f), V(0.69f, 0.81f, 0.2f));
  Face front_hole[6] = {{}, {}, {}, {}, {}, {}};
  front_hole[0] = {Face::Hole, 0.08f, 0.07f, Eigen::Vector2f::Zero()};
  Face top_hole[6] = {{}, {}, {}, {}, {}, {}};
  top_hole[5] = {Face::Hole, 0.07f, 0.07f, Eigen::Vector2f::Zero()};
  s.mesh.append(hollow_box(large_1, w, kSolid));
  s.mesh.append(hollow_box(large_2, w, kSolid));
  s.mesh.append(hollow_box(small_1, w, front_hole));
  s.mesh.append(hollow_box(small_2, w, top_hole));
  s.info.name = "paper setting 2: two larger closed boxes, smaller boxes with small openings";
  s.info.target = add_victim(s, Box(V(0.55f, -0.05f, w), V(0.64f, 0.03f, w + 0.06f)));
  s.info.search_space = Eigen::AlignedBox3d(Eigen::Vector3d(0.35, -0.75, 0.0), Eigen::Vector3d(1.3, 0.9, 0.55));
  s.info.containers = {{"large box 1", interior(large_1, w)}, {"large box 2", interior(large_2, w)},
                       {"small box with front opening", interior(small_1, w)},
                       {"small box with top opening", interior(small_2, w)}};
  return s;
}

}  // namespace

Mesh hollow_box(const Eigen::AlignedBox3f& outer, float wall_m, const Face (&faces)[6]) {
  const V lo = outer.min(), hi = outer.max();
  const float w = wall_m;
  FVX_ASSERT(((hi - lo).array() > 2 * w).all(), "walls thicker than the box");
  Mesh m;
  // z faces span the whole footprint, x faces fill between them, y faces between those.
  add_slab(m, Box(V(lo.x(), lo.y(), lo.z()), V(hi.x(), hi.y(), lo.z() + w)), faces[4]);
  add_slab(m, Box(V(lo.x(), lo.y(), hi.z() - w), V(hi.x(), hi.y(), hi.z())), faces[5]);
  add_slab(m, Box(V(lo.x(), lo.y(), lo.z() + w), V(lo.x() + w, hi.y(), hi.z() - w)), faces[0]);
  add_slab(m, Box(V(hi.x() - w, lo.y(), lo.z() + w), V(hi.x(), hi.y(), hi.z() - w)), faces[1]);
  add_slab(m, Box(V(lo.x() + w, lo.y(), lo.z() + w), V(hi.x() - w, lo.y() + w, hi.z() - w)), faces[2]);
  add_slab(m, Box(V(lo.x() + w, hi.y() - w, lo.z() + w), V(hi.x() - w, hi.y(), hi.z() - w)), faces[3]);
  return m;
}

namespace {

std::string names_text() {
  std::string text;
  for (const std::string& n : builtin_scene_names()) text += (text.empty() ? "" : ", ") + n;
  return text;
}

int parse_suite_number(const std::string& name) {
  const std::string digits = name.substr(6);
  if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos ||
      std::stoi(digits) < 1)
    throw UsageError("'" + name + "' is not a built-in scene: suite/N takes N from 1 to 999999");
  return std::stoi(digits);
}

}  // namespace

std::vector<std::string> builtin_scene_names() {
  return {"closed-box", "room", "crates", "paper-setting-1", "paper-setting-2"};
}

Scene builtin_scene(const std::string& name) {
  Scene s;
  if (name == "closed-box") s = closed_box();
  else if (name == "room") s = room();
  else if (name == "crates") s = crates();
  else if (name == "paper-setting-1") s = paper_setting_1();
  else if (name == "paper-setting-2") s = paper_setting_2();
  else if (name.rfind("suite/", 0) == 0) return suite_scene(parse_suite_number(name));
  else throw UsageError("'" + name + "' is not a built-in scene (" + names_text() + ", or suite/N)");
  s.mesh_path = "builtin:" + name;
  return s;
}

Scene scene_from(const std::string& source, const std::string& info_path) {
  const std::string prefix = "builtin:";
  if (source.rfind(prefix, 0) != 0) return load_scene(source, info_path);
  Scene s = builtin_scene(source.substr(prefix.size()));
  if (!info_path.empty()) {
    s.info = read_scene_info(info_path);
    s.info_path = info_path;
  }
  return s;
}

}  // namespace fvx::sim
