#pragma once
/// \file
/// The scenes fvx ships (data/scenes/, written by scripts/make-scenes.sh) and tests with.
/// Coordinates: x forward from the robot base at the origin, y left, z up, floor at z = 0.
/// Everything is built from closed, non-overlapping axis-aligned slabs, as GroundTruth
/// assumes. Replicas of the paper's settings (§V-B) are sized for its 5-DOF arm, whose
/// workspace has a radius of 1 m, and stand in a lab (walls at the floor's edges) as the
/// paper's did.
#include <string>
#include <vector>

#include "fvx/sim/scene.hpp"

namespace fvx::sim {

/// "closed-box" (a box with one opening on top), "room" (a room with a closed crate),
/// "crates" (three crates, the victim in the one with a side opening), "paper-setting-1"
/// (a computer, two boxes open on top, two-by-fours), "paper-setting-2" (two larger closed
/// boxes, smaller boxes with small openings).
std::vector<std::string> builtin_scene_names();

/// The named scene (mesh and sidecar); throws UsageError for an unknown name.
Scene builtin_scene(const std::string& name);

/// A scene argument: "builtin:NAME" (with the sidecar `info_path` instead of its own when
/// not empty) or a mesh file (load_scene).
Scene scene_from(const std::string& source, const std::string& info_path);

/// How a face of a box is built.
struct Face {
  enum Kind { Solid, Open, Hole } kind = Solid;
  float hole_a_m = 0, hole_b_m = 0;  ///< centred hole size along the face's first and second axis
  Eigen::Vector2f hole_offset_m = Eigen::Vector2f::Zero();  ///< hole centre from the face centre
};

/// A hollow box of wall thickness `wall_m` with outer bounds `outer`. Faces in the order
/// x−, x+, y−, y+, z−, z+; the in-plane axes of a face are the other two axes in x, y, z order.
Mesh hollow_box(const Eigen::AlignedBox3f& outer, float wall_m, const Face (&faces)[6]);

}  // namespace fvx::sim
