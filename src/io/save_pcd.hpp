#pragma once
/// \file
/// PCL's binary PCD writer with its failures as FileErrors: on a full disk or past a file
/// size limit it throws (posix_fallocate fails) instead of returning −1, which reached the
/// user as "unexpected error: [pcl::PCDWriter::writeBinary] Error during raw_fallocate ()!".
#include <pcl/console/print.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>

#include <string>

#include "fvx/core/error.hpp"

namespace fvx::io {

/// Writes `cloud` to `temp` (a write_path_atomically temporary) as binary PCD; a failure is
/// a FileError naming `path` and, where the system says, why.
template <typename Cloud>
void save_pcd_binary(const std::string& temp, const Cloud& cloud, const std::string& path) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // the FileError says it, in one line
  try {
    if (pcl::io::savePCDFileBinary(temp, cloud) == 0) return;
  } catch (const pcl::PCLException& e) {
    // PCL reserves the file's whole size first: a full disk or a size limit fails there.
    if (std::string(e.what()).find("fallocate") != std::string::npos)
      throw FileError(path, "cannot write PCD: no room for the file (disk full, or a file size limit)");
    throw FileError(path, std::string("cannot write PCD (PCL: ") + e.what() + ")");
  }
  throw FileError(path, "cannot write PCD");
}

}  // namespace fvx::io
