#include "fvx/capmap/arm.hpp"

#include <console_bridge/console.h>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::capmap {

struct Arm::Impl {
  ArmConfig config;
  KDL::Chain chain;
  std::vector<std::string> joint_names;
  Eigen::VectorXd lower, upper;
  std::string urdf_hash, urdf_hash_short_basis;
  std::optional<FirstJointAxis> first_joint_axis;
  // KDL is not safe to share between threads: its solvers keep scratch state and
  // KDL::Joint caches its last pose in mutable members. fk() and jacobian() work on a copy
  // of the chain, so that one Arm serves many threads (a build found the race: maps
  // differed between 1 and 3 threads).
};

namespace {

KDL::Frame to_kdl(const urdf::Pose& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
                    KDL::Vector(p.position.x, p.position.y, p.position.z));
}

Eigen::Isometry3d to_eigen(const KDL::Frame& f) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = f.M(r, c);
    T.translation()[r] = f.p[r];
  }
  return T;
}

/// FNV-1a 64 of `text`, hex. `basis`: the standard offset basis, or the one a digit short that
/// maps written before it hold as their URDF hash.
std::string fnv1a_hex(const std::string& text, std::uint64_t basis = 14695981039346656037ull) {
  std::uint64_t h = basis;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

/// The first movable joint's axis line in the base frame, when it is revolute: the fixed
/// segments before it only move the line.
std::optional<FirstJointAxis> first_joint_axis_of(const KDL::Chain& chain) {
  KDL::Frame T_base_segment = KDL::Frame::Identity();
  for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
    const KDL::Segment& segment = chain.getSegment(i);
    const KDL::Joint& joint = segment.getJoint();
    if (joint.getType() == KDL::Joint::None) {
      T_base_segment = T_base_segment * segment.pose(0.0);
      continue;
    }
    if (joint.getType() != KDL::Joint::RotAxis) return std::nullopt;
    const KDL::Vector axis = T_base_segment.M * joint.JointAxis(), point = T_base_segment * joint.JointOrigin();
    return FirstJointAxis{Eigen::Vector3d(point.x(), point.y(), point.z()),
                          Eigen::Vector3d(axis.x(), axis.y(), axis.z()).normalized()};
  }
  return std::nullopt;
}

}  // namespace

Eigen::Isometry3d FirstJointAxis::turn(const Eigen::Isometry3d& T_base_sensor_at_zero, double q0_rad) const {
  Eigen::Isometry3d R = Eigen::Isometry3d::Identity();
  R.linear() = Eigen::AngleAxisd(q0_rad, direction_base).toRotationMatrix();
  R.translation() = point_base - R.linear() * point_base;
  return R * T_base_sensor_at_zero;
}

double FirstJointAxis::tilt_from_vertical_rad() const {
  return std::atan2(std::hypot(direction_base.x(), direction_base.y()), std::abs(direction_base.z()));
}

Arm Arm::from_urdf(const std::string& urdf_path, const ArmConfig& config) {
  require_readable_file(urdf_path);
  std::ifstream in(urdf_path);
  std::stringstream text;
  text << in.rdbuf();
  return from_urdf_string(text.str(), config, urdf_path);
}

namespace {

/// XML is UTF-8 text. TinyXML (under urdfdom) steps over a multi-byte character by its lead
/// byte's length, so a lead byte cut short at the end made it read past the text (found by
/// fuzzing, under ASan): such text is refused before it is parsed.
void require_utf8_text(const std::string& text, const std::string& source) {
  for (std::size_t i = 0; i < text.size();) {
    const auto lead = static_cast<unsigned char>(text[i]);
    const std::size_t length = lead < 0x80 ? 1 : (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xe ? 3 : (lead >> 3) == 0x1e ? 4 : 0;
    bool valid = length != 0 && lead != 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (!valid) throw FileError(source, "not UTF-8 text (byte " + std::to_string(i) + "); a URDF is XML");
    i += length;
  }
}

/// urdfdom links each joint's child into its parent's child list (shared_ptr) before it checks
/// the tree: joints whose links form a cycle leave a model that is never freed, even when
/// urdfdom then refuses the file (LeakSanitizer, fuzzing). Such joints are refused first,
/// reading the same XML with the same parser (TinyXML).
void require_acyclic_joints(const std::string& urdf, const std::string& source) {
  TiXmlDocument document;
  document.Parse(urdf.c_str());
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (document.Error() || !robot) return;  // urdfdom refuses it without linking anything
  // Kahn's order over parent -> child links: a link whose parents are never all taken lies
  // on a cycle or below one.
  // (Iterative: a chain of many thousand joints must not deepen the stack.)
  std::map<std::string, std::vector<std::string>> children;
  std::map<std::string, int> parents;
  for (const TiXmlElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const TiXmlElement* parent = j->FirstChildElement("parent");
    const TiXmlElement* child = j->FirstChildElement("child");
    const char* p = parent ? parent->Attribute("link") : nullptr;
    const char* c = child ? child->Attribute("link") : nullptr;
    if (!p || !c) continue;
    children[p].push_back(c);
    ++parents[c];
    parents.emplace(p, 0);
  }
  std::vector<std::string> free_links;
  for (const auto& [link, count] : parents)
    if (count == 0) free_links.push_back(link);
  while (!free_links.empty()) {
    const std::string link = free_links.back();
    free_links.pop_back();
    for (const std::string& c : children[link])
      if (--parents[c] == 0) free_links.push_back(c);
  }
  for (const auto& [link, count] : parents)
    if (count > 0) throw FileError(source, "the joints' links form a cycle (through link '" + link + "')");
}

/// urdfdom's links own their children (shared_ptr): a model whose links form a cycle would
/// never be freed. Cutting every link's child lists when the model is no longer needed frees
/// it whatever its shape.
struct CutModelOnExit {
  const urdf::ModelInterfaceSharedPtr& model;
  ~CutModelOnExit() {
    if (!model) return;
    for (auto& [name, link] : model->links_) {
      link->child_links.clear();
      link->child_joints.clear();
    }
  }
};

}  // namespace

Arm Arm::from_urdf_string(const std::string& urdf, const ArmConfig& config, const std::string& source) {
  require_utf8_text(urdf, source);
  require_acyclic_joints(urdf, source);
  // urdfdom logs parse problems on stderr through console_bridge; fvx says it once, below.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf);
  const CutModelOnExit cut{model};
  if (!model) throw FileError(source, "not a valid URDF (it does not parse)");
  const auto base = model->getLink(config.base_link);
  const auto tip = model->getLink(config.tip_link);
  if (!base) throw UsageError("--base " + config.base_link + ": no such link in " + source);
  if (!tip) throw UsageError("--tip " + config.tip_link + ": no such link in " + source);

  // Walk from the tip up to the base; the joints on the way, base first.
  std::vector<urdf::JointConstSharedPtr> joints;
  for (urdf::LinkConstSharedPtr link = tip; link->name != config.base_link;) {
    const auto parent = link->getParent();
    if (!parent || !link->parent_joint)
      throw UsageError("--tip " + config.tip_link + " is not below --base " + config.base_link + " in " + source);
    // Parent links cannot loop: they follow joints backwards, and require_acyclic_joints refused
    // any cycle of joints.
    joints.insert(joints.begin(), link->parent_joint);
    link = parent;
  }

  auto impl = std::make_unique<Impl>();
  impl->config = config;
  impl->urdf_hash = fnv1a_hex(urdf);
  impl->urdf_hash_short_basis = fnv1a_hex(urdf, 1469598103934665603ull);
  std::vector<double> lower, upper;
  for (const auto& j : joints) {
    const KDL::Frame origin = to_kdl(j->parent_to_joint_origin_transform);
    const KDL::Vector axis = origin.M * KDL::Vector(j->axis.x, j->axis.y, j->axis.z);
    KDL::Joint joint;
    switch (j->type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        joint = KDL::Joint(j->name, origin.p, axis, KDL::Joint::RotAxis);
        break;
      case urdf::Joint::PRISMATIC:
        joint = KDL::Joint(j->name, origin.p, axis, KDL::Joint::TransAxis);
        break;
      case urdf::Joint::FIXED:
        joint = KDL::Joint(j->name, KDL::Joint::None);
        break;
      default:
        throw UsageError(source + ": joint " + j->name + " is floating or planar, which fvx does not support");
    }
    impl->chain.addSegment(KDL::Segment(j->child_link_name, joint, origin));
    if (j->type == urdf::Joint::FIXED) continue;
    impl->joint_names.push_back(j->name);
    if (j->type == urdf::Joint::CONTINUOUS || !j->limits) {
      lower.push_back(-M_PI);
      upper.push_back(M_PI);
    } else {
      lower.push_back(j->limits->lower);
      upper.push_back(j->limits->upper);
    }
  }
  if (impl->joint_names.empty()) throw UsageError(source + ": no movable joint between " + config.base_link + " and " + config.tip_link);
  impl->lower = Eigen::Map<Eigen::VectorXd>(lower.data(), Eigen::Index(lower.size()));
  impl->upper = Eigen::Map<Eigen::VectorXd>(upper.data(), Eigen::Index(upper.size()));
  impl->first_joint_axis = first_joint_axis_of(impl->chain);
  return Arm(std::move(impl));
}

Arm::Arm(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Arm::~Arm() = default;
Arm::Arm(Arm&&) noexcept = default;
Arm& Arm::operator=(Arm&&) noexcept = default;

int Arm::dof() const { return int(impl_->joint_names.size()); }
const std::vector<std::string>& Arm::joint_names() const { return impl_->joint_names; }
const Eigen::VectorXd& Arm::lower_rad() const { return impl_->lower; }
const Eigen::VectorXd& Arm::upper_rad() const { return impl_->upper; }
const ArmConfig& Arm::config() const { return impl_->config; }
const std::string& Arm::urdf_hash() const { return impl_->urdf_hash; }
bool Arm::is_urdf_hash(const std::string& hash) const {
  return hash == impl_->urdf_hash || hash == impl_->urdf_hash_short_basis;
}
const std::optional<FirstJointAxis>& Arm::first_joint_axis() const { return impl_->first_joint_axis; }

Eigen::Isometry3d Arm::fk(const Eigen::VectorXd& q) const {
  FVX_ASSERT(q.size() == dof(), "joint vector size");
  KDL::JntArray joints(unsigned(q.size()));
  joints.data = q;
  KDL::Frame tip;
  const KDL::Chain chain = impl_->chain;
  KDL::ChainFkSolverPos_recursive(chain).JntToCart(joints, tip);
  return to_eigen(tip) * impl_->config.T_tip_sensor;
}

Eigen::Vector3d Arm::viewing_direction(const Eigen::VectorXd& q) const {
  return fk(q).linear() * impl_->config.viewing_axis_sensor;
}

Eigen::VectorXd Arm::random_configuration(std::mt19937_64& rng) const {
  Eigen::VectorXd q(dof());
  for (int j = 0; j < dof(); ++j) q[j] = random_joint_rad(j, rng);
  return q;
}

double Arm::random_joint_rad(int joint, std::mt19937_64& rng) const {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return lower_rad()[joint] + unit(rng) * (upper_rad()[joint] - lower_rad()[joint]);
}

void Arm::jacobian(const Eigen::VectorXd& q, Eigen::Matrix3Xd& J_position, Eigen::Matrix3Xd& J_rotation) const {
  KDL::JntArray joints(unsigned(q.size()));
  joints.data = q;
  KDL::Jacobian J(unsigned(q.size()));
  const KDL::Chain chain = impl_->chain;
  KDL::ChainJntToJacSolver(chain).JntToJac(joints, J);  // reference: tip origin, base axes
  J_position = J.data.topRows<3>();
  J_rotation = J.data.bottomRows<3>();
  // Move the reference point to the sensor: v_sensor = v_tip + ω × r.
  const Eigen::Isometry3d T_base_sensor = fk(q);
  const Eigen::Vector3d r = T_base_sensor.translation() - (T_base_sensor * impl_->config.T_tip_sensor.inverse()).translation();
  for (int c = 0; c < J_position.cols(); ++c) J_position.col(c) += J_rotation.col(c).cross(r);
}

}  // namespace fvx::capmap
