#include "fvx/nbv/loaded_arm.hpp"

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"

namespace fvx::nbv {

void load_arm(const std::string& capmap_path, const std::string& urdf_path, const Eigen::Isometry3d& T_world_base,
              const std::string& command, LoadedArm& out) {
  out.T_world_base = T_world_base;
  out.capability_map = capmap::CapabilityMap::load(capmap_path);
  const capmap::CapabilityHeader& h = out.capability_map->header();
  if (h.shard_count != 1)
    throw UsageError(command + ": " + capmap_path + " is shard " + std::to_string(h.shard_index) + " of " +
                     std::to_string(h.shard_count) + "; merge the shards first (fvx capmap merge)");
  if (!urdf_path.empty()) {
    out.arm = capmap::Arm::from_urdf(urdf_path, capmap::arm_config_of(h));
    if (!out.arm->is_urdf_hash(h.urdf_hash))
      throw Error(command + ": " + capmap_path + " was built from another URDF than " + urdf_path + " (hash " +
                  h.urdf_hash + " vs " + out.arm->urdf_hash() + "); rebuild it with fvx capmap build");
  }
  out.reach = Reach{&*out.capability_map, out.T_world_base, out.arm ? &*out.arm : nullptr, {}};
  out.reach->ik.position_tolerance_m = h.position_tolerance_m;
  out.reach->ik.angle_tolerance_rad = h.angle_tolerance_rad;
}

std::vector<OptionSpec> arm_options() {
  return {
      {"capmap", 0, "FILE.fcm", "the arm's capability map (fvx capmap build)", "/inputs/capmap/file"},
      {"base", 0, "x,y,z,roll,pitch,yaw", "T_world_base: where the capability map's base stands, "
                                          "metres and degrees (default 0,0,0,0,0,0)", "/inputs/capmap/T_world_base"},
      {"no-capmap", 0, nullptr, "a free-flying sensor: no reachability constraint", "/inputs/capmap"},
      {"arm", 0, "URDF", "the arm the capability map was built for: each view then needs IK, "
                         "which gives its joint configuration", "/inputs/capmap/arm"},
  };
}

void check_arm_options(const Args& args, const std::string& command) {
  if (args.has("capmap") == args.has("no-capmap"))
    throw UsageError(command + ": give --capmap FILE.fcm (with --base) for an arm, or --no-capmap for a free-flying sensor");
  if (args.has("no-capmap") && (args.has("base") || args.has("arm")))
    throw UsageError(command + ": --base and --arm need --capmap");
}

void load_arm_inputs(const Args& args, const std::string& command, LoadedArm& out) {
  check_arm_options(args, command);
  out.T_world_base = args.has("base") ? parse_xyz_rpy_deg(args.get("base"), "--base") : Eigen::Isometry3d::Identity();
  if (!args.has("capmap")) return;
  load_arm(args.get("capmap"), args.has("arm") ? args.get("arm") : "", out.T_world_base, command, out);
}

}  // namespace fvx::nbv
