#pragma once
/// \file
/// The depth camera's options, declared with the configs they set (io::Intrinsics,
/// io::DepthCamera): their table rows and their parsing.
#include <optional>
#include <string>
#include <vector>

#include "fvx/core/options.hpp"
#include "fvx/io/intrinsics.hpp"

namespace fvx::io {

/// --intrinsics, --fx, --fy, --cx, --cy, --depth-scale; with `with_size` also --width and
/// --height (for commands that render images). `echo`: the report's pointer to the
/// intrinsics object.
std::vector<OptionSpec> intrinsics_options(bool with_size, const std::string& echo);
/// The intrinsics the user gave (file, then flags on top), or empty when none was given.
/// Throws UsageError naming `command` when the result is invalid.
std::optional<Intrinsics> parse_intrinsics(const Args& args, const std::string& command);

/// --sensor FILE, --depth-min, --depth-max and the intrinsics options with the image size:
/// a depth camera for planning; `echo` points at the config holding "sensor".
std::vector<OptionSpec> depth_camera_options(const std::string& echo);
/// The sensor file (default Kinect v1), then the flags on top. UsageError when invalid.
DepthCamera parse_depth_camera(const Args& args, const std::string& command);

}  // namespace fvx::io
