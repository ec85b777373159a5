#pragma once
/// \file
/// What a PCD or PLY header declares, checked against the file before PCL reads it: PCL
/// allocates what the header claims (a WIDTH of 2e9, an uncompressed size of 4 GB) and parses
/// ascii tokens it cannot read as 0 and a VIEWPOINT of "nan" as the identity. Each check names
/// the field that is wrong; none reads past the file or allocates more than it holds.
#include <cstdint>
#include <string>

namespace fvx::io {

/// Throws FileError naming the field: FIELDS/SIZE/TYPE/COUNT that disagree or name a size
/// the type cannot have (TYPE F with SIZE 2), WIDTH/HEIGHT/POINTS that are not counts in
/// [0, 2^31) or whose product is not POINTS, a VIEWPOINT that is not seven finite numbers,
/// data shorter than the points promised (binary), a binary_compressed block whose sizes do
/// not fit the file or the points (or that claims more than 256× its compressed size, beyond
/// LZF), ascii lines with another number of values or a token that is not a number. Returns
/// whether the header states a VIEWPOINT (the scan's own pose).
bool check_pcd_header(const std::string& path);

/// Throws FileError for a PLY whose element counts are not counts in [0, 2^31), whose
/// property types are unknown, or whose data cannot hold what the header declares. Returns
/// whether the header declares one "camera" element (the pose PCL's PLY writer stores).
bool check_ply_header(const std::string& path);

}  // namespace fvx::io
