#pragma once
/// \file
/// Atomic file writes (ARCHITECTURE.md §2): the content goes to a temporary file in the same
/// folder, which is renamed over the target only when it is complete. A crash, a bad input or
/// an exception never leaves a half-written file or truncates an existing one.
#include <functional>
#include <iosfwd>
#include <string>

namespace fvx {

/// Calls `write` with a stream onto a temporary file beside `path`, then renames it onto
/// `path`. If `write` throws or the stream fails, the temporary is removed, `path` is left as
/// it was, and a FileError (or the original exception) propagates. A `path` that is a link
/// to a file gets the rename at the file it names (the link stays); one that is a stream
/// (is_stream_path) gets the finished content written into it, from a temporary file in the
/// temporary folder. "-" is standard output.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// write_file_atomically with `text` as the whole content.
void write_text_atomically(const std::string& path, const std::string& text);

/// Same, for writers that insist on a file name (e.g. PCL, OpenCV): `write` receives the
/// temporary path and must create that file. `extension` is kept on the temporary so that
/// writers that dispatch on it work.
void write_path_atomically(const std::string& path,
                           const std::function<void(const std::string& temp_path)>& write);

/// Why a write failed, from the errno it left: ": No space left on device" (ENOSPC), ": File
/// too large" (EFBIG, a file size limit), …; "" when errno is 0.
std::string write_failure(int errno_value);

/// Whether `path` is a stream, written into and never renamed onto: "-" (standard output), a
/// name for an open descriptor (/dev/stdout, /dev/stderr, /dev/fd/N, /proc/…), or an existing
/// path that is neither a regular file nor a folder after links (a device such as /dev/null, a
/// pipe, a socket). A rename onto a device would replace the node itself (as root, /dev/null
/// became a plain file); one onto a descriptor's file would leave the descriptor on the old one.
bool is_stream_path(const std::string& path);

/// The extension of `path` in lower case, with its dot (".pcd"), or "" when it has none.
std::string lowercase_extension(const std::string& path);

/// Throws FileError if `path` does not exist or is not a readable regular file.
void require_readable_file(const std::string& path);

/// Creates the folder `path` and its parents (nothing when it exists); FileError naming the
/// folder and the reason (a file in the way, no permission) otherwise.
void create_folder(const std::string& path);

}  // namespace fvx
