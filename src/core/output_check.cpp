#include "fvx/core/output_check.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx {
namespace fs = std::filesystem;
namespace {

struct Output {
  std::string option, path;
  bool folder = false;  ///< the command creates it (DIR); PATH: a file or a folder
  bool file = false;    ///< FILE…: must be a file in an existing folder
};

std::vector<Output> outputs_of(const CommandSpec& spec, const Args& args) {
  std::vector<Output> outputs;
  for (const OptionSpec& o : spec.options)
    for (const char* name : kOutputOptions)
      if (o.arg && std::string(o.name) == name && args.has(name) && !args.get(name).empty())
        outputs.push_back({"--" + std::string(name), args.get(name), std::string(o.arg) == "DIR",
                           std::string(o.arg).rfind("FILE", 0) == 0});
  return outputs;
}

bool is_output_option(const std::string& name) {
  for (const char* o : kOutputOptions)
    if (name == o) return true;
  return false;
}

/// Positional arguments and the values of the other options that are existing files.
std::vector<std::string> inputs_of(const CommandSpec& spec, const Args& args) {
  std::vector<std::string> inputs;
  std::error_code ec;
  for (const std::string& p : args.positional)
    if (fs::is_regular_file(p, ec)) inputs.push_back(p);
  for (const OptionSpec& o : spec.options)
    if (o.arg && !is_output_option(o.name) && args.has(o.name) && fs::is_regular_file(args.get(o.name), ec))
      inputs.push_back(args.get(o.name));
  return inputs;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (a == b) return true;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

/// The folder the output goes in must exist (for a folder output: its nearest existing
/// ancestor) and be writable.
void check_writable(const Output& out) {
  std::error_code ec;
  // A device or pipe (/dev/null, /dev/stdout) is written into, not replaced: it needs no
  // writable folder, only to be writable itself.
  if (!out.folder && is_stream_path(out.path)) {
    if (out.path == "-") return;  // standard output
    if (::access(out.path.c_str(), W_OK) != 0) throw FileError(out.path, std::string("cannot write: ") + std::strerror(errno));
    return;
  }
  fs::path target(out.path);
  if (out.folder && !target.has_filename()) target = target.parent_path();  // "out/" names the folder out
  fs::path folder = target.parent_path();
  if (out.folder)  // it creates its parents: up to the nearest that exists, or "." for a relative path
    while (!folder.empty() && !fs::exists(folder, ec) && folder.parent_path() != folder) folder = folder.parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::exists(folder, ec)) throw FileError(out.path, "cannot write: folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(folder, ec)) throw FileError(out.path, "cannot write: '" + folder.string() + "' is not a folder");
  if (::access(folder.c_str(), W_OK) != 0)
    throw FileError(out.path, "cannot write in '" + folder.string() + "': " + std::strerror(errno));
  if (out.file && fs::is_directory(out.path, ec)) throw FileError(out.path, "cannot write: it is a folder");
}

}  // namespace

void check_outputs(const CommandSpec& spec, const Args& args) {
  const std::vector<Output> outputs = outputs_of(spec, args);
  const std::vector<std::string> inputs = inputs_of(spec, args);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const Output& out = outputs[i];
    for (const std::string& input : inputs)
      if (same_file(out.path, input))
        throw UsageError(out.option + " " + out.path + " is also an input; fvx does not write over its inputs");
    for (std::size_t j = i + 1; j < outputs.size(); ++j)  // two outputs may share /dev/null
      if (!is_stream_path(out.path) && same_file(out.path, outputs[j].path))
        throw UsageError(out.option + " and " + outputs[j].option + " name the same file " + out.path);
    check_writable(out);
  }
}

}  // namespace fvx
