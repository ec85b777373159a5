// A map as large as a building's, for scripts/bench-large-map.sh: one scan from 1 m above the
// centre of a square hall of side 2·HALF m to two of its walls (2 m high), at RESOLUTION m.
// The walls' hull holds the whole unseen hall: on a 60 m hall at 5 cm, 59 M cells in the
// known box and 25 M void cells, the kind of map a user loads whole and searches in part.
//
//   make_large_map RESOLUTION HALF OUT.bt
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fvx/core/error.hpp"
#include "fvx/map/occupancy_map.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: make_large_map RESOLUTION HALF OUT.bt\n");
    return 2;
  }
  const double R = std::atof(argv[1]), half = std::atof(argv[2]);
  if (!(R > 0.0 && R <= 1.0 && half > 0.0 && half / R < 30000.0)) {
    std::fprintf(stderr, "make_large_map: RESOLUTION in (0, 1] m and HALF / RESOLUTION < 30000\n");
    return 2;
  }
  try {
    fvx::map::OccupancyMap map(R);
    std::vector<Eigen::Vector3f> wall_points;  // a point every 4 cells on the walls y = half and x = half
    for (double a = -half; a <= half; a += 4 * R)
      for (double z = 0.0; z <= 2.0; z += 4 * R) {
        wall_points.emplace_back(float(a), float(half), float(z));
        wall_points.emplace_back(float(half), float(a), float(z));
      }
    map.integrate(wall_points, Eigen::Vector3f(0, 0, 1));
    map.save(argv[3]);
  } catch (const fvx::Error& e) {
    std::fprintf(stderr, "make_large_map: %s\n", e.what());
    return 1;
  }
  return 0;
}
