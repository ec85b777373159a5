#pragma once
/// \file
/// An arm as the search reads it from files: its capability map, optionally its URDF (each
/// view then needs IK), where its base stands, and the Reach over them.
#include <optional>
#include <string>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/options.hpp"
#include "fvx/nbv/nbv.hpp"

namespace fvx::nbv {

/// `reach` points into the other members: keep the object where load_arm filled it.
struct LoadedArm {
  std::optional<capmap::CapabilityMap> capability_map;
  std::optional<capmap::Arm> arm;
  std::optional<Reach> reach;  ///< empty: a free-flying sensor
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
  /// The arm's joint names in chain order; empty without a URDF.
  std::vector<std::string> joint_names() const { return arm ? arm->joint_names() : std::vector<std::string>{}; }
};

/// Loads the capability map at `capmap_path` and, unless `urdf_path` is empty, the arm it was
/// built for, standing at T_world_base; IK tolerances from the map's header. FileError for a
/// bad file; UsageError (naming `command`) for a shard that was not merged; Error when the
/// URDF is not the one the map was built from.
void load_arm(const std::string& capmap_path, const std::string& urdf_path, const Eigen::Isometry3d& T_world_base,
              const std::string& command, LoadedArm& out);

/// --capmap, --base, --no-capmap, --arm: where the arm stands and what it reaches.
std::vector<OptionSpec> arm_options();
/// UsageError unless exactly one of --capmap and --no-capmap is given (--base and --arm
/// only with --capmap). Cheap: call it before reading other inputs.
void check_arm_options(const Args& args, const std::string& command);
/// check_arm_options(), then load_arm() from --capmap, --arm and --base (nothing with
/// --no-capmap). Call it before any long work.
void load_arm_inputs(const Args& args, const std::string& command, LoadedArm& out);

}  // namespace fvx::nbv
