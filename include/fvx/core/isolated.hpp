#pragma once
/// \file
/// Running a third-party parser where its crash cannot take fvx down: `work` runs in a child
/// process (fork) and hands back bytes through a pipe. librosbag_storage, for one, reads past
/// its buffers on some corrupt bags (5 of 150 byte-flipped bags crashed it with SIGSEGV).
#include <functional>
#include <string>

namespace fvx {

/// The bytes `work` returns, computed in a child process. An fvx::FileError, UsageError or
/// Error it throws comes back as the same kind with the same message; a child killed by a
/// signal (a crash inside the parser) is FileError(path, "corrupt <what>: the reader crashed
/// on it (signal N)"), and so is a child that runs out of the 2 GiB it may add to what the
/// process held (a parser that believes a corrupt length).
std::string run_isolated(const std::string& path, const std::string& what, const std::function<std::string()>& work);

}  // namespace fvx
