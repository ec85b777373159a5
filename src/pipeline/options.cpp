#include "fvx/pipeline/options.hpp"

#include <tuple>

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/io/camera_options.hpp"
#include "fvx/scan/load.hpp"

namespace fvx::pipeline {

OptionSpec resolution_option(const std::string& echo, const char* help, const std::string& note) {
  return {"resolution", 'r', "M", help, echo, dflt(kDefaultResolution_m) + note, in(0.001, 1)};
}

OptionSpec max_time_diff_option() {
  return {"max-time-diff", 0, "S", "largest stamp difference when matching by timestamp, seconds",
          "/config/max_time_diff_s", dflt(scan::LoadConfig{}.max_time_diff_s), in(0, 1e6)};
}

OptionSpec min_fit_score_option(const std::string& echo, const char* help) {
  return {"min-fit-score", 0, "S", help, echo, dflt(voids::ClusterConfig{}.min_fit_score), above(0, 1)};
}

double parse_resolution(const Args& args, double fallback) {
  return args.number("resolution", fallback);
}

std::vector<OptionSpec> near_voids_options(const std::string& echo) {
  return {{"far-voids-only", 0, nullptr, "only what the sensor can measure: U counts void cells from its minimum "
                                         "depth on, Algorithm 1 adds utility from that distance beyond the "
                                         "frontier (default: every void cell a ray crosses, utility from the "
                                         "frontier on)", echo + "/count_near_void_cells"},
          {"near-voids", 0, nullptr, "every void cell a ray crosses counts (the default; kept for scripts)",
           echo + "/count_near_void_cells"}};
}

bool parse_near_voids(const Args& args, bool fallback) {
  if (args.has("near-voids") && args.has("far-voids-only"))
    throw UsageError("--near-voids and --far-voids-only contradict each other: give one");
  if (args.has("near-voids")) return true;
  if (args.has("far-voids-only")) return false;
  return fallback;
}

OptionSpec void_hull_option(const std::string& echo) {
  return {"void-hull", 0, "MODE", "the voids' hull: map (default: of every occupied cell, the paper's accumulated "
                                  "cloud) or search-space (of the occupied cells in the search space only)", echo};
}

std::vector<OptionSpec> void_model_options(const std::string& pipeline_echo, const std::string& nbv_echo) {
  return {void_hull_option(pipeline_echo + "/hull_in_bounds"),
          {"unknown-depth", 0, "N", "U counts only the first N unknown cells of each ray, those a view reveals for "
                                    "sure (default 0: every void cell a ray crosses, the paper's)",
           nbv_echo + "/unknown_depth_cells", dflt(0), in(0, 1000)}};
}

bool parse_void_hull(const Args& args, bool fallback) {
  if (!args.has("void-hull")) return fallback;
  const std::string mode = args.get("void-hull");
  if (mode != "map" && mode != "search-space")
    throw UsageError("--void-hull '" + mode + "': expected map or search-space");
  return mode == "search-space";
}

std::vector<OptionSpec> search_model_options(const std::string& pipeline_echo, const std::string& nbv_echo) {
  return options({near_voids_options(nbv_echo), target_size_options(pipeline_echo), accumulation_options(nbv_echo),
                  void_model_options(pipeline_echo, nbv_echo), io::depth_camera_options(nbv_echo)});
}

std::vector<OptionSpec> target_size_options(const std::string& echo) {
  return {{"target-size", 0, "M", "the searched object's smallest extent, metres: only void cells in an all-unknown "
                                  "cube of floor(M/R)-1 cells count, as only those can hide it", echo + "/target_size_m",
           dflt(pipeline::Config{}.target_size_m) + ": every void cell, the paper's", in(0, 10)}};
}

std::vector<OptionSpec> accumulation_options(const std::string& echo) {
  return {{"accumulation", 0, "MODE", "Algorithm 1's accumulation: sampled (default: above --utility-vectors, "
                                      "a stratified sample of each frontier-void's frontier cells, weighted so "
                                      "that the expected field is the exact one) or exact (every utility vector, "
                                      "the paper's; minutes on large maps)", echo + "/accumulation"},
          {"utility-vectors", 0, "N", "sampled: trace about N utility vectors at most; under it the field is exact",
           echo + "/max_utility_vectors", dflt(nbv::Config{}.max_utility_vectors),
           in(7, double(std::numeric_limits<long long>::max()))},
          {"coarse-rays", 0, "COLSxROWS", "frontier-void: screen the poses with this coarser fan of "
                                          "field-of-view rays, then rank the best with the full fan (--rays); "
                                          "off: every pose with the full fan", echo + "/coarse_rays",
           dflt(nbv::Config{}.coarse_ray_cols) + "x" + dflt(nbv::Config{}.coarse_ray_rows)}};
}

std::pair<int, int> parse_cols_rows(const std::string& text, const std::string& option) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw UsageError(option + " '" + text + "': expected COLSxROWS, e.g. 80x60");
  return {int(parse_int_in(text.substr(0, x), option + " columns", 1, 4096)),
          int(parse_int_in(text.substr(x + 1), option + " rows", 1, 4096))};
}

void parse_accumulation(const Args& args, nbv::Config& config) {
  if (args.has("accumulation")) config.accumulation = utility::parse_accumulation(args.get("accumulation"));
  args.read("utility-vectors", config.max_utility_vectors);
  if (!args.has("coarse-rays")) return;
  if (args.get("coarse-rays") == "off")
    config.coarse_ray_cols = config.coarse_ray_rows = 0;
  else
    std::tie(config.coarse_ray_cols, config.coarse_ray_rows) = parse_cols_rows(args.get("coarse-rays"), "--coarse-rays");
}

double parse_target_size(const Args& args, double fallback) {
  return args.number("target-size", fallback);
}

}  // namespace fvx::pipeline
