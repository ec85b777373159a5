#pragma once
// Private to the registration stage: nearest neighbours in a nanoflann k-d tree, for the fine
// pass and, behind PCL's search interface, for its GICP and ICP. PCL's FLANN tree opens an
// OpenMP region for every single-point query; on a 2-core machine that took 80 % of a 2.5 cm
// Kinect frame's registration (15 s of 18.5 s).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <nanoflann.hpp>

#include <cmath>
#include <cstdint>
#include <memory>

namespace fvx::registration {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// nanoflann's view of a cloud.
struct CloudPoints {
  const Cloud* cloud;
  std::size_t kdtree_get_point_count() const { return cloud->size(); }
  float kdtree_get_pt(std::size_t i, std::size_t axis) const { return cloud->points[i].data[axis]; }
  template <typename Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

using PointTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudPoints>, CloudPoints, 3,
                                                   std::uint32_t>;

/// The nearest point closer than a limit; among equally near ones the lowest index, so that
/// the result does not depend on the tree's layout.
class NearestWithin {
 public:
  explicit NearestWithin(float limit_sq) : worst_(std::nextafter(limit_sq, HUGE_VALF)) {}
  std::size_t size() const { return index_ >= 0 ? 1 : 0; }
  bool full() const { return true; }
  float worstDist() const { return worst_; }
  bool addPoint(float distance_sq, std::uint32_t index) {
    if (distance_sq < worst_ || (distance_sq == worst_ && std::int64_t(index) < index_)) {
      worst_ = distance_sq;
      index_ = index;
    }
    return true;
  }
  int index() const { return int(index_); }
  float distance_sq() const { return worst_; }

 private:
  float worst_;
  std::int64_t index_ = -1;
};

/// PCL's search interface over a nanoflann tree, for Registration::setSearchMethodTarget and
/// setSearchMethodSource. k-nearest and radius queries, sorted by distance.
class NanoflannSearch : public pcl::search::KdTree<pcl::PointXYZ> {
 public:
  NanoflannSearch() : pcl::search::KdTree<pcl::PointXYZ>(true) {}
  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override;
  int nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override;
  int radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override;

 private:
  Cloud::ConstPtr points_;  ///< the searched points (the indexed subset when indices are given)
  std::unique_ptr<CloudPoints> adaptor_;
  std::unique_ptr<PointTree> tree_;
};

}  // namespace fvx::registration
