#pragma once
/// \file
/// A family of search scenes made from a seed (`builtin:suite/N`): what an exploration
/// planner is measured on beyond the paper's two settings. Each scene stands on the floor
/// slab of the built-in scenes (walls around it in some), in front of an arm base at
/// (0.2, 0, 0) facing +x, within the 1 m reach of the fvx arm, and mixes:
///   - crates open on top, with a hole in one side (any side, also the far one), or closed;
///   - shelves with two compartments, open towards the robot, away from it or to a side;
///   - a crate stacked on a closed crate; a crate leaning 10–25° on one bottom edge;
///   - clutter: solid blocks on the floor that occlude;
///   - in most scenes a target, a solid block 8–14 cm wide, on the floor of one container.
/// Every solid is a closed cuboid (walls are slabs that touch and do not overlap); the sidecar
/// gives the search space, the target, the containers' interiors (not those of leaning
/// crates, which are not axis-aligned) and where the arm's base may stand.
/// Generation uses its own integer mapping of a 64-bit Mersenne twister, so a scene is the
/// same on every standard library and machine.
#include "fvx/sim/scene.hpp"

namespace fvx::sim {

/// The default suite: scenes 1 to kSuiteScenes.
constexpr int kSuiteScenes = 24;

/// Scene `n` of the family (n >= 1; UsageError otherwise). Its mesh_path is "builtin:suite/N".
Scene suite_scene(int n);

/// Problems that make a scene unfit to measure a planner on (empty: none): a sidecar without
/// search space or base; a target not inside a container's interior, or not within the
/// search space; solids that overlap (their interiors intersect: ground truth's parity rule
/// then fails); a mesh triangle outside the floor's extent.
std::vector<std::string> check_scene_layout(const Scene& scene);

}  // namespace fvx::sim
