#pragma once
// Options that several commands share, declared once: their table rows, their parsing and
// their report form.
#include <optional>
#include <vector>

#include "fvx/io/intrinsics.hpp"
#include "options.hpp"
#include "report.hpp"

namespace fvx::cli {

/// Concatenates option tables.
std::vector<OptionSpec> options(std::initializer_list<std::vector<OptionSpec>> tables);

/// --intrinsics, --fx, --fy, --cx, --cy, --depth-scale; with `with_size` also --width and
/// --height (for commands that render images).
std::vector<OptionSpec> intrinsics_options(bool with_size);

/// The intrinsics the user gave (file, then flags on top), or empty when none was given.
/// Throws UsageError naming `command` when the result is invalid.
std::optional<io::Intrinsics> parse_intrinsics(const Args& args, const std::string& command);

Json intrinsics_json(const io::Intrinsics& K);

/// --sensor FILE, --depth-min, --depth-max and the intrinsics options with the image size:
/// a depth camera for planning.
std::vector<OptionSpec> depth_camera_options();
/// The sensor file (default Kinect v1), then the flags on top. UsageError when invalid.
io::DepthCamera parse_depth_camera(const Args& args, const std::string& command);
Json depth_camera_json(const io::DepthCamera& camera);

}  // namespace fvx::cli
