// Registration against ground truth: a real Kinect frame placed at a known pose, started
// from priors offset by known transforms, forward and inverse (small_gicp-style).
#include <gtest/gtest.h>

#include "fvx/core/pose.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/registration/registration.hpp"
#include "test_support.hpp"

namespace fvx::registration {
namespace {

std::vector<Eigen::Vector3d> finite_points(const std::string& path) {
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : io::read_cloud(path).points)
    if (p.allFinite()) points.push_back(p);
  return points;
}

Eigen::Isometry3d ground_truth() {
  Eigen::Isometry3d T(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1.0, -0.3).normalized()));
  T.pretranslate(Eigen::Vector3d(3.0, -1.5, 0.8));
  return T;
}

Eigen::Isometry3d offset(double translation_m, double rotation_deg) {
  Eigen::Isometry3d T(Eigen::AngleAxisd(rotation_deg * M_PI / 180.0, Eigen::Vector3d(1, -2, 1).normalized()));
  T.pretranslate(translation_m * Eigen::Vector3d(1, 1, -1).normalized());
  return T;
}

struct Case {
  double translation_m, rotation_deg;
  bool inverse;
  Method method;
};

class RecoverKnownTransform : public ::testing::TestWithParam<Case> {};

TEST_P(RecoverKnownTransform, WithinFiveMillimetresAndHalfADegree) {
  FVX_REAL_DATA_OR_SKIP(path, "pcl-kinect-sequences/pairwise_tutorial/capture0001.pcd");
  const Case c = GetParam();
  const auto points_sensor = finite_points(path);
  const Eigen::Isometry3d T_world_sensor = ground_truth();
  std::vector<Eigen::Vector3f> target_world;
  for (const auto& p : points_sensor) target_world.push_back((T_world_sensor * p).cast<float>());

  const Eigen::Isometry3d delta = c.inverse ? offset(c.translation_m, c.rotation_deg).inverse()
                                            : offset(c.translation_m, c.rotation_deg);
  const Eigen::Isometry3d prior = T_world_sensor * delta;
  Config config;
  config.method = c.method;
  const Result r = align(points_sensor, prior, target_world, config);
  ASSERT_TRUE(r.converged) << r.problem;
  const Eigen::Isometry3d error = T_world_sensor.inverse() * r.T_world_sensor;
  EXPECT_LT(error.translation().norm(), 0.005);
  EXPECT_LT(rotation_angle_deg(error), 0.5);
  EXPECT_LT(r.fitness_rmse_m, 0.02);
  EXPECT_GT(r.inlier_fraction, 0.9);
  EXPECT_GT(r.iterations, 0);
  EXPECT_NEAR(r.correction_translation_m, (r.T_world_sensor.translation() - prior.translation()).norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(
    Offsets, RecoverKnownTransform,
    ::testing::Values(Case{0.02, 2, false, Method::Gicp}, Case{0.02, 2, true, Method::Gicp},
                      Case{0.10, 10, false, Method::Gicp}, Case{0.10, 10, true, Method::Gicp},
                      Case{0.02, 2, false, Method::Icp}, Case{0.02, 2, true, Method::Icp},
                      Case{0.10, 10, false, Method::Icp}, Case{0.10, 10, true, Method::Icp}),
    [](const auto& test_info) {
      const Case& c = test_info.param;
      return std::string(to_string(c.method)) + "_" + std::to_string(int(c.translation_m * 100)) + "cm_" +
             std::to_string(int(c.rotation_deg)) + "deg_" + (c.inverse ? "inverse" : "forward");
    });

TEST(RegistrationRealData, GrabberFramesRegisterToEachOther) {
  const std::string dir = "pcl-kinect-sequences/pcl_grabber_sequences/pcd/";
  FVX_REAL_DATA_OR_SKIP(first, dir + "frame_20121214T142255.814212.pcd");
  FVX_REAL_DATA_OR_SKIP(second, dir + "frame_20121214T142256.068683.pcd");
  FVX_REAL_DATA_OR_SKIP(third, dir + "frame_20121214T142256.332395.pcd");
  std::vector<Eigen::Vector3f> target;
  for (const auto& p : finite_points(first)) target.push_back(p.cast<float>());
  for (const auto& next : {second, third}) {
    const Result r = align(finite_points(next), Eigen::Isometry3d::Identity(), target, Config{});
    ASSERT_TRUE(r.converged) << next << ": " << r.problem;
    // Source and target are 5 cm voxel centroids of two noisy frames: even perfectly aligned
    // their nearest-neighbour RMS is about 1.5–2 cm. A misregistration is far above 3 cm.
    EXPECT_LT(r.fitness_rmse_m, 0.03) << next;
    EXPECT_GT(r.inlier_fraction, 0.9) << next;
    EXPECT_LT(r.correction_translation_m, 0.05) << next;
    EXPECT_LT(r.correction_rotation_deg, 3.0) << next;
  }
}

// The bundled box-room sample has exact poses and views that overlap by 40–70 %: parts of
// each new view were never seen. Registration must leave exact priors where they are.
TEST(Registration, ExactPriorsStayPutUnderPartialOverlap) {
  const char* source = std::getenv("FVX_SOURCE_DIR");
  ASSERT_NE(source, nullptr);
  const std::string dir = std::string(source) + "/data/sample/box-room/";
  const io::CloudFile first = io::read_cloud(dir + "view0.pcd");
  std::vector<Eigen::Vector3f> target;
  for (const auto& p : first.points) target.push_back((first.viewpoint * p).cast<float>());
  for (int view = 1; view < 4; ++view) {
    const io::CloudFile next = io::read_cloud(dir + "view" + std::to_string(view) + ".pcd");
    const Result r = align(next.points, next.viewpoint, target, Config{});
    ASSERT_TRUE(r.converged) << view << ": " << r.problem;
    const Eigen::Isometry3d error = next.viewpoint.inverse() * r.T_world_sensor;
    EXPECT_LT(error.translation().norm(), 0.005) << "view " << view;
    EXPECT_LT(rotation_angle_deg(error), 0.2) << "view " << view;
    EXPECT_LT(r.inlier_fraction, 0.8) << "view " << view << " overlaps only partly";
  }
}

TEST(Registration, HittingTheIterationCapKeepsThePrior) {
  FVX_REAL_DATA_OR_SKIP(path, "pcl-kinect-sequences/pairwise_tutorial/capture0001.pcd");
  const auto points = finite_points(path);
  std::vector<Eigen::Vector3f> target;
  for (const auto& p : points) target.push_back(p.cast<float>());
  Config config;
  config.max_iterations = 1;
  const Eigen::Isometry3d prior = offset(0.1, 10);
  const Result r = align(points, prior, target, config);
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.problem.empty());
  EXPECT_TRUE(r.T_world_sensor.isApprox(prior));
}

TEST(Registration, TooFewPointsIsReportedNotThrown) {
  const Result r = align({{0, 0, 1}, {0, 1, 1}}, Eigen::Isometry3d::Identity(), {Eigen::Vector3f(0, 0, 1)}, Config{});
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.problem.find("too few points"), std::string::npos);
}

TEST(Registration, ConfigValidationListsEveryViolation) {
  Config config;
  config.voxel_m = -1;
  config.max_correspondence_m = 0;
  config.max_iterations = 0;
  EXPECT_EQ(config.validate().size(), 3u);
  EXPECT_TRUE(Config{}.validate().empty());
}

}  // namespace
}  // namespace fvx::registration
