// Does anything the map holds rank the search's candidates by what they reveal better than U?
// At each view of `fvx explore`'s own loop on the suite scenes (its defaults, the arm at the
// scene's base), every candidate the search ranked gets its true gain (the observable void
// cells still unknown in the map that it reveals, by the Kinect's rule on the mesh:
// reveal.hpp) and features of its view computed on the map with the search's 80 x 60 fan
// (Features). Each feature, and a ridge regression on all of them trained leave-one-scene-out,
// then picks one candidate per state; the table gives what the pick reveals against the
// capability map's best pose (as bench_regret). Issue 17, README "Exploration over a scene
// suite".
//
//   bench_rank_features CAPMAP.fcm URDF FIRST LAST [VIEWS] [CSV]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>

#include "rank_features.hpp"
#include "suite_loop.hpp"

namespace {

using namespace fvx;
using bench::CellSet;

class Scene : public bench::SuiteLoop {
 public:
  Scene(int n, const std::string& capmap, const std::string& urdf)
      : SuiteLoop(n, capmap, urdf, "bench_rank_features") {}

  /// Runs the loop for `views` views; one State per view whose search ranked views.
  void run(int n, int views, std::vector<bench::State>& out) {
    explore(views, [&](const session::ViewRecord& v, const pipeline::State& state, const session::ExploreConfig&) {
      if (!v.chosen) return;
      bench::State s{n, v.view + 1, clairvoyant(state.map), *v.chosen, {}};
      std::vector<Eigen::Isometry3d> poses;
      for (const nbv::View& r : v.step.nbv.views) poses.push_back(r.T_world_sensor);
      const std::vector<CellSet> truth = reveal_->sets(poses, dense_rays_);
      const bench::FeatureCaster caster(state, v.step.analysis, poses, S_, camera_);
      for (std::size_t p = 0; p < poses.size(); ++p)
        s.candidates.push_back({double(unknown_of(state.map, truth[p])), caster.features(poses[p], v.step.nbv.views[p])});
      out.push_back(std::move(s));
      std::fprintf(stderr, "\rsuite/%d, view %d", n, v.view + 1);
    });
  }
};

void write_csv(const std::string& path, const std::vector<bench::State>& states) {
  std::ofstream out(path);
  out << "scene,view,clair,candidate,chosen,gain";
  for (const char* name : bench::kFeatureNames) out << ',' << name;
  out << '\n';
  for (const bench::State& s : states)
    for (std::size_t c = 0; c < s.candidates.size(); ++c) {
      out << s.scene << ',' << s.view << ',' << s.clair << ',' << c << ',' << int(c == s.chosen) << ','
          << s.candidates[c].gain;
      for (const double x : s.candidates[c].features) out << ',' << x;
      out << '\n';
    }
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5 || argc > 7) {
    std::fprintf(stderr, "usage: bench_rank_features CAPMAP.fcm URDF FIRST LAST [VIEWS] [CSV]\n");
    return 2;
  }
  const int first = std::atoi(argv[3]), last = std::atoi(argv[4]), views = argc >= 6 ? std::atoi(argv[5]) : 8;
  if (first < 1 || last < first || views < 2) {
    std::fprintf(stderr, "bench_rank_features: FIRST >= 1, LAST >= FIRST, VIEWS >= 2\n");
    return 2;
  }
  std::vector<bench::State> states;
  try {
    for (int n = first; n <= last; ++n) {
      Scene scene(n, argv[1], argv[2]);
      if (!scene.empty()) scene.run(n, views, states);
    }
    std::fprintf(stderr, "\n");
    if (argc == 7) write_csv(argv[6], states);
  } catch (const std::exception& e) {  // a missing file, a scene the suite does not hold
    std::fprintf(stderr, "bench_rank_features: %s\n", e.what());
    return 1;
  }
  bench::print_evaluation(states);
  return 0;
}
