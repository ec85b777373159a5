// The scene family of `builtin:suite/N`: seeded layouts of crates, shelves, stacks, leaning
// crates and clutter in front of the arm, each checked for what ground truth assumes.
#include "fvx/sim/scene_suite.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <tuple>

#include "fvx/core/error.hpp"
#include "fvx/sim/builtin_scenes.hpp"

namespace fvx::sim {
namespace {

using Box = Eigen::AlignedBox3f;
using V = Eigen::Vector3f;

/// Uniform numbers from the raw 64-bit stream (std::uniform_*_distribution differ between
/// standard libraries; the engine's output does not).
class Dice {
 public:
  explicit Dice(std::uint64_t seed) : engine_(seed) {}
  float uniform(float lo, float hi) { return lo + float((engine_() >> 11) * 0x1.0p-53) * (hi - lo); }
  int integer(int lo, int hi) { return lo + int(engine_() % std::uint64_t(hi - lo + 1)); }  // [lo, hi]
  bool chance(float p) { return uniform(0.0f, 1.0f) < p; }

 private:
  std::mt19937_64 engine_;
};

// Where objects stand: in front of the base at (0.2, 0, 0), within the fvx arm's reach.
const Eigen::AlignedBox2f kArea(Eigen::Vector2f(0.45f, -0.75f), Eigen::Vector2f(1.3f, 0.75f));
constexpr float kGap_m = 0.04f;  // between footprints: the sensor can look between objects

/// An interior a target may stand in, and where it is open: a face 0–5 (x−, x+, y−, y+, z−,
/// z+) or −1 when closed.
struct Home {
  std::string name;
  Box interior;
  int open_face;
  bool side_open;  ///< the whole face is open (a shelf), not a hole in it
};

struct Layout {
  Scene scene;
  std::vector<Eigen::AlignedBox2f> footprints;
  std::vector<Home> target_homes;
};

/// A free footprint of size `size` in the area, or none after 60 tries.
std::optional<Eigen::Vector2f> place(Layout& layout, const Eigen::Vector2f& size, Dice& dice) {
  for (int attempt = 0; attempt < 60; ++attempt) {
    const Eigen::Vector2f lo(dice.uniform(kArea.min().x(), kArea.max().x() - size.x()),
                             dice.uniform(kArea.min().y(), kArea.max().y() - size.y()));
    const Eigen::AlignedBox2f grown(lo - Eigen::Vector2f::Constant(kGap_m), lo + size + Eigen::Vector2f::Constant(kGap_m));
    if (std::none_of(layout.footprints.begin(), layout.footprints.end(),
                     [&](const Eigen::AlignedBox2f& f) { return f.intersects(grown); })) {
      layout.footprints.emplace_back(lo, lo + size);
      return lo;
    }
  }
  return std::nullopt;
}

Box interior_of(const Box& outer, float wall) {
  return Box(outer.min() + V::Constant(wall), outer.max() - V::Constant(wall));
}

/// One face of six: open top (0), a hole in one face (1: x−, towards the base, 2: x+, away,
/// 3: y−, 4: y+, 5: top), or closed (6).
int random_openings(Face (&faces)[6], const Box& outer, Dice& dice, int kind) {
  for (Face& f : faces) f = {};
  if (kind == 0) {
    faces[5] = {Face::Open};
    return 5;
  }
  if (kind == 6) return -1;
  const int face = kind == 1 ? 0 : kind == 2 ? 1 : kind == 3 ? 2 : kind == 4 ? 3 : 5;
  const int normal = face / 2;
  const int a = normal == 0 ? 1 : 0, b = normal == 2 ? 1 : 2;
  const V size = outer.sizes();
  const float hole_a = std::min(dice.uniform(0.1f, 0.18f), 0.6f * size[a]);
  const float hole_b = std::min(dice.uniform(0.08f, 0.14f), 0.6f * size[b]);
  faces[face] = {Face::Hole, hole_a, hole_b, Eigen::Vector2f::Zero()};
  return face;
}

std::string side_name(int kind) {
  static const char* names[] = {"open top", "hole towards the base", "hole away from the base", "hole on its right",
                                "hole on its left", "hole on top", "closed"};
  return names[kind];
}

void add_crate(Layout& l, Dice& dice, int index) {
  const V size(dice.uniform(0.22f, 0.42f), dice.uniform(0.22f, 0.42f), dice.uniform(0.18f, 0.38f));
  const auto lo = place(l, size.head<2>(), dice);
  if (!lo) return;
  const Box outer(V(lo->x(), lo->y(), 0.0f), V(lo->x(), lo->y(), 0.0f) + size);
  const float wall = dice.uniform(0.01f, 0.02f);
  Face faces[6];
  const int kind = dice.integer(0, 6);
  const int open_face = random_openings(faces, outer, dice, kind);
  l.scene.mesh.append(hollow_box(outer, wall, faces));
  const std::string name = "crate " + std::to_string(index) + " (" + side_name(kind) + ")";
  l.scene.info.containers.push_back({name, {outer.min().cast<double>() + Eigen::Vector3d::Constant(wall),
                                            outer.max().cast<double>() - Eigen::Vector3d::Constant(wall)}});
  l.target_homes.push_back({name, interior_of(outer, wall), open_face, false});
}

/// A shelf: a box open on one side with a board between two compartments.
void add_shelf(Layout& l, Dice& dice, int index) {
  const V size(dice.uniform(0.25f, 0.4f), dice.uniform(0.3f, 0.5f), dice.uniform(0.35f, 0.5f));
  const auto lo = place(l, size.head<2>(), dice);
  if (!lo) return;
  const Box outer(V(lo->x(), lo->y(), 0.0f), V(lo->x(), lo->y(), 0.0f) + size);
  const float wall = 0.015f;
  Face faces[6];
  const int open = dice.integer(0, 3);  // x− (towards the base), x+ (away), y−, y+
  faces[open] = {Face::Open};
  l.scene.mesh.append(hollow_box(outer, wall, faces));
  const Box inside = interior_of(outer, wall);
  const float board_z = inside.min().z() + dice.uniform(0.4f, 0.6f) * inside.sizes().z();
  Box board = inside;
  board.min().z() = board_z;
  board.max().z() = board_z + wall;
  if (open < 2) board.extend(V(open == 0 ? outer.min().x() : outer.max().x(), inside.min().y(), board_z));
  else board.extend(V(inside.min().x(), open == 2 ? outer.min().y() : outer.max().y(), board_z));
  l.scene.mesh.add_box(board);
  static const char* sides[] = {"open towards the base", "open away from the base", "open to its right",
                                "open to its left"};
  for (int level = 0; level < 2; ++level) {
    Box compartment = inside;
    if (level == 0) compartment.max().z() = board_z;
    else compartment.min().z() = board_z + wall;
    const std::string name = "shelf " + std::to_string(index) + " " + sides[open] + (level ? ", upper" : ", lower");
    l.scene.info.containers.push_back({name, {compartment.min().cast<double>(), compartment.max().cast<double>()}});
    l.target_homes.push_back({name, compartment, open, true});
  }
}

/// A crate on a closed crate of at least its footprint.
void add_stack(Layout& l, Dice& dice, int index) {
  const V lower_size(dice.uniform(0.3f, 0.42f), dice.uniform(0.3f, 0.42f), dice.uniform(0.15f, 0.25f));
  const auto lo = place(l, lower_size.head<2>(), dice);
  if (!lo) return;
  const Box lower(V(lo->x(), lo->y(), 0.0f), V(lo->x(), lo->y(), 0.0f) + lower_size);
  Face faces_lower[6];
  // Closed, or a hole in a side: the lid carries the upper crate.
  const int lower_open = dice.chance(0.5f) ? random_openings(faces_lower, lower, dice, 6)
                                           : random_openings(faces_lower, lower, dice, dice.integer(1, 4));
  l.scene.mesh.append(hollow_box(lower, 0.015f, faces_lower));
  const V upper_size(dice.uniform(0.2f, lower_size.x()), dice.uniform(0.2f, lower_size.y()), dice.uniform(0.15f, 0.25f));
  const V upper_lo(lower.min().x() + dice.uniform(0.0f, lower_size.x() - upper_size.x()),
                   lower.min().y() + dice.uniform(0.0f, lower_size.y() - upper_size.y()), lower.max().z());
  const Box upper(upper_lo, upper_lo + upper_size);
  Face faces[6];
  const int upper_open = random_openings(faces, upper, dice, dice.integer(0, 6));
  l.scene.mesh.append(hollow_box(upper, 0.015f, faces));
  const std::string name = "stack " + std::to_string(index);
  for (const auto& [box, part, open] : {std::tuple{lower, ", lower", lower_open}, std::tuple{upper, ", upper", upper_open}}) {
    const Box inside = interior_of(box, 0.015f);
    const std::string full = name + part + (open < 0 ? " (closed)" : "");
    l.scene.info.containers.push_back({full, {inside.min().cast<double>(), inside.max().cast<double>()}});
    l.target_homes.push_back({full, inside, open, false});
  }
}

/// A crate tilted 10–25° about one bottom edge, that edge on the floor.
void add_leaning(Layout& l, Dice& dice) {
  const V size(dice.uniform(0.22f, 0.35f), dice.uniform(0.22f, 0.35f), dice.uniform(0.2f, 0.3f));
  Face faces[6];
  random_openings(faces, Box(V::Zero(), size), dice, dice.integer(0, 6));
  Mesh crate = hollow_box(Box(V::Zero(), size), 0.015f, faces);
  const float angle = dice.uniform(10.0f, 25.0f) * float(M_PI / 180.0) * (dice.chance(0.5f) ? 1.0f : -1.0f);
  const Eigen::Vector3f axis = dice.chance(0.5f) ? V::UnitX() : V::UnitY();
  const Eigen::Matrix3f R = Eigen::AngleAxisf(angle, axis).toRotationMatrix();
  Box turned;
  for (V& v : crate.vertices) turned.extend(v = R * v);
  const auto lo = place(l, turned.sizes().head<2>(), dice);
  if (!lo) return;
  const V shift = V(lo->x(), lo->y(), 0.002f) - turned.min();  // 2 mm above the floor: no shared face
  for (V& v : crate.vertices) v += shift;
  l.scene.mesh.append(crate);
}

void add_clutter(Layout& l, Dice& dice) {
  const V size(dice.uniform(0.04f, 0.15f), dice.uniform(0.04f, 0.15f), dice.uniform(0.05f, 0.3f));
  const auto lo = place(l, size.head<2>(), dice);
  if (lo) l.scene.mesh.add_box(Box(V(lo->x(), lo->y(), 0.0f), V(lo->x(), lo->y(), 0.0f) + size));
}

/// The target: a block on the floor of one container, away from its walls. Where a sensor
/// outside could see it: behind a hole in a side (in the far half, where a look down through
/// the hole lands), in the front half of a compartment open on a side, anywhere under an open
/// or holed top; anywhere in a closed container (it cannot be seen there).
void add_target(Layout& l, Dice& dice) {
  std::vector<const Home*> fits;
  for (const Home& home : l.target_homes)
    if ((home.interior.sizes().array() > V(0.12f, 0.12f, 0.1f).array()).all()) fits.push_back(&home);
  if (fits.empty()) return;
  // Three in four targets go into a container with an opening, when the scene has one.
  std::vector<const Home*> open;
  for (const Home* h : fits)
    if (h->open_face >= 0) open.push_back(h);
  if (!open.empty() && dice.chance(0.75f)) fits = open;
  const Home& home = *fits[std::size_t(dice.integer(0, int(fits.size()) - 1))];
  const V room = home.interior.sizes();
  const float edge = std::min({dice.uniform(0.08f, 0.14f), room.x() - 0.03f, room.y() - 0.03f, (room.z() - 0.01f) / 0.8f});
  Box floor = home.interior;
  floor.min().array() += 0.01f;
  floor.max().array() -= 0.01f + edge;
  if (home.open_face >= 0 && home.open_face < 4) {
    const int axis = home.open_face / 2;
    const bool at_min = home.open_face % 2 == 0;
    const float middle = std::clamp(home.interior.center()[axis] - edge / 2, floor.min()[axis], floor.max()[axis]);
    // A hole: the half away from it; an open side: the half next to it (as far as the room allows).
    if (at_min != home.side_open) floor.min()[axis] = middle;
    else floor.max()[axis] = middle;
  }
  const V lo(dice.uniform(floor.min().x(), floor.max().x()), dice.uniform(floor.min().y(), floor.max().y()),
             home.interior.min().z());
  const Box block(lo, lo + V(edge, edge, edge * 0.8f));
  l.scene.mesh.add_box(block);
  l.scene.info.target = NamedBox{"target in " + home.name, {block.min().cast<double>(), block.max().cast<double>()}};
}

}  // namespace

Scene suite_scene(int n) {
  if (n < 1) throw UsageError("builtin:suite/" + std::to_string(n) + ": scenes are numbered from 1");
  Dice dice(0x5CE9E5u + std::uint64_t(n));
  Layout l;
  l.scene.mesh.add_box(Box(V(-0.6f, -1.6f, -0.05f), V(2.0f, 1.6f, 0.0f)));  // the floor of the built-in scenes
  const bool walls = dice.chance(0.5f);
  // Each scene leads with one kind in turn, so that the suite holds every kind; the rest is drawn.
  const int lead = (n - 1) % 4;
  const int containers = dice.integer(2, 3);
  for (int i = 0; i < containers; ++i) {
    const int kind = i == 0 ? lead : dice.integer(0, 3);
    if (kind == 0) add_crate(l, dice, i + 1);
    else if (kind == 1) add_shelf(l, dice, i + 1);
    else if (kind == 2) add_stack(l, dice, i + 1);
    else add_leaning(l, dice);
  }
  for (int i = dice.integer(0, 3); i > 0; --i) add_clutter(l, dice);
  if (n % 6 != 0) add_target(l, dice);  // one scene in six has nothing hidden
  if (walls) {
    const float t = 0.05f;
    l.scene.mesh.add_box(Box(V(-0.6f - t, -1.6f, -0.05f), V(-0.6f, 1.6f, 2.0f)));
    l.scene.mesh.add_box(Box(V(2.0f, -1.6f, -0.05f), V(2.0f + t, 1.6f, 2.0f)));
    l.scene.mesh.add_box(Box(V(-0.6f - t, -1.6f - t, -0.05f), V(2.0f + t, -1.6f, 2.0f)));
    l.scene.mesh.add_box(Box(V(-0.6f - t, 1.6f, -0.05f), V(2.0f + t, 1.6f + t, 2.0f)));
  }
  Eigen::AlignedBox3f objects;
  for (const V& v : l.scene.mesh.vertices)
    if (v.z() > 0.0f && v.z() < 1.0f) objects.extend(v);  // above the floor, below the walls' tops
  objects.extend(V(kArea.min().x(), kArea.min().y(), 0.0f));
  Scene& s = l.scene;
  s.mesh_path = "builtin:suite/" + std::to_string(n);
  s.info.name = "suite scene " + std::to_string(n) + (walls ? " (walls)" : "");
  const Eigen::Vector3d margin(0.1, 0.1, 0.0);
  s.info.search_space = Eigen::AlignedBox3d(
      Eigen::Vector3d(objects.min().x(), kArea.min().y(), 0.0) - margin,
      Eigen::Vector3d(objects.max().x(), kArea.max().y(), 0.0) + margin + Eigen::Vector3d(0, 0, std::max(0.55f, objects.max().z() + 0.1f)));
  s.info.bases = {{0.2, 0.0, 0.0, 0.0, 0.0, 0.0}};
  return s;
}

}  // namespace fvx::sim

namespace fvx::sim {
namespace {

/// The mesh's solids: each run of 8 vertices and 12 triangles that Mesh::add_box wrote.
/// Empty when the mesh is not made that way.
std::vector<std::array<V, 8>> cuboids_of(const Mesh& mesh) {
  std::vector<std::array<V, 8>> solids;
  if (mesh.vertices.size() % 8 != 0 || mesh.triangles.size() != mesh.vertices.size() / 8 * 12) return {};
  for (std::size_t c = 0; c < mesh.vertices.size() / 8; ++c) {
    for (std::size_t t = 12 * c; t < 12 * c + 12; ++t)
      for (const std::uint32_t v : mesh.triangles[t])
        if (v / 8 != c) return {};
    std::array<V, 8> corners;
    std::copy_n(mesh.vertices.begin() + std::ptrdiff_t(8 * c), 8, corners.begin());
    solids.push_back(corners);
  }
  return solids;
}

/// A cuboid's three edge directions from corner 0 (corners 1, 2 and 4: add_box's order).
std::array<V, 3> edges_of(const std::array<V, 8>& c) { return {c[1] - c[0], c[2] - c[0], c[4] - c[0]}; }

/// Separating axis test: the interiors of two convex solids intersect by more than `tolerance_m`
/// along every candidate axis (face normals of both, and the cross products of their edges).
bool interiors_intersect(const std::array<V, 8>& a, const std::array<V, 8>& b, float tolerance_m) {
  std::vector<V> axes;
  const auto ea = edges_of(a), eb = edges_of(b);
  for (const V& e : ea) axes.push_back(e);
  for (const V& e : eb) axes.push_back(e);
  for (const V& x : ea)
    for (const V& y : eb) axes.push_back(x.cross(y));
  for (V axis : axes) {
    if (axis.norm() < 1e-6f) continue;
    axis.normalize();
    float a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
    for (const V& p : a) a0 = std::min(a0, p.dot(axis)), a1 = std::max(a1, p.dot(axis));
    for (const V& p : b) b0 = std::min(b0, p.dot(axis)), b1 = std::max(b1, p.dot(axis));
    if (std::min(a1, b1) - std::max(a0, b0) <= tolerance_m) return false;
  }
  return true;
}

bool is_cuboid(const std::array<V, 8>& c) {
  const auto e = edges_of(c);
  for (int i = 0; i < 3; ++i)
    if (e[i].norm() < 1e-5f || std::abs(e[i].normalized().dot(e[(i + 1) % 3].normalized())) > 1e-4f) return false;
  return (c[7] - (c[0] + e[0] + e[1] + e[2])).norm() < 1e-4f;
}

}  // namespace

std::vector<std::string> check_scene_layout(const Scene& scene) {
  std::vector<std::string> problems;
  const SceneInfo& info = scene.info;
  if (!info.search_space) problems.push_back("no search space");
  if (info.bases.empty()) problems.push_back("no base for the arm");
  const auto solids = cuboids_of(scene.mesh);
  if (solids.empty()) problems.push_back("the mesh is not made of closed cuboids");
  for (std::size_t i = 0; i < solids.size(); ++i) {
    if (!is_cuboid(solids[i])) problems.push_back("solid " + std::to_string(i) + " is not a cuboid");
    for (std::size_t j = i + 1; j < solids.size(); ++j)
      if (interiors_intersect(solids[i], solids[j], 1e-4f))
        problems.push_back("solids " + std::to_string(i) + " and " + std::to_string(j) + " overlap");
  }
  if (info.target) {
    const Eigen::AlignedBox3d& t = info.target->box;
    if (info.search_space && !info.search_space->contains(t)) problems.push_back("the target is outside the search space");
    const bool housed = std::any_of(info.containers.begin(), info.containers.end(), [&](const NamedBox& c) {
      return (c.box.min().array() <= t.min().array() + 1e-6).all() && (t.max().array() <= c.box.max().array() + 1e-6).all();
    });
    if (!housed) problems.push_back("the target is not inside a container");
  }
  return problems;
}

}  // namespace fvx::sim
