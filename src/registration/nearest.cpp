#include "nearest.hpp"

#include <algorithm>

namespace fvx::registration {

void NanoflannSearch::setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices) {
  input_ = cloud;
  indices_ = indices;
  if (indices && !indices->empty()) {
    auto subset = std::make_shared<Cloud>();
    for (const auto i : *indices) subset->push_back((*cloud)[std::size_t(i)]);
    points_ = subset;
  } else {
    points_ = cloud;
  }
  adaptor_ = std::make_unique<CloudPoints>(CloudPoints{points_.get()});
  tree_ = std::make_unique<PointTree>(3, *adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
}

int NanoflannSearch::nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                                    std::vector<float>& k_sqr_distances) const {
  const std::size_t wanted = std::min<std::size_t>(std::size_t(std::max(k, 0)), points_->size());
  std::vector<std::uint32_t> found_index(wanted);
  k_sqr_distances.resize(wanted);
  const std::size_t found =
      wanted ? tree_->knnSearch(point.data, wanted, found_index.data(), k_sqr_distances.data()) : 0;
  k_indices.resize(found);
  k_sqr_distances.resize(found);
  for (std::size_t j = 0; j < found; ++j)
    k_indices[j] = indices_ && !indices_->empty() ? (*indices_)[found_index[j]] : pcl::index_t(found_index[j]);
  return int(found);
}

int NanoflannSearch::radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& k_indices,
                                  std::vector<float>& k_sqr_distances, unsigned int max_nn) const {
  std::vector<std::pair<std::uint32_t, float>> matches;
  nanoflann::SearchParams params;
  params.sorted = true;
  tree_->radiusSearch(point.data, float(radius * radius), matches, params);
  if (max_nn > 0 && matches.size() > max_nn) matches.resize(max_nn);
  k_indices.resize(matches.size());
  k_sqr_distances.resize(matches.size());
  for (std::size_t j = 0; j < matches.size(); ++j) {
    const std::uint32_t i = matches[j].first;
    k_indices[j] = indices_ && !indices_->empty() ? (*indices_)[i] : pcl::index_t(i);
    k_sqr_distances[j] = matches[j].second;
  }
  return int(matches.size());
}

}  // namespace fvx::registration
