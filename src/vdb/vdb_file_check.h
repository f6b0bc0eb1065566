#pragma once
// A structural check of a .vdb file, run before libopenvdb reads it.
//
// libopenvdb trusts the sizes a file states: a blosc chunk header, a string length or a node count
// becomes an allocation or a loop before anything checks it against the file's length, so a
// damaged or hostile 30 kB file made it ask for 140 TB (found by tests/fuzz/fuzz_scene). This
// walks the same structure libopenvdb 10 reads (file format 222-224: header, file metadata, grid
// descriptors, and for each grid that will be read its metadata, transform, tree topology and leaf
// buffers) and checks every stated size against the bytes that are really there, so that what
// libopenvdb then allocates is bounded by the file size. It also refuses what libopenvdb would
// leak or read as undefined behaviour: internal-node values that do not decompress, two root
// children at one origin, bool bytes other than 0 and 1.
#include <string>
#include <vector>

namespace vf {

// Throws vf::Error naming `path`, the byte offset and the problem if the file is not a .vdb that
// libopenvdb can read safely. `grids_to_read` are the grid names the caller will read: each one
// present must be a float, vec3s or int32 grid (the scene's types), and is checked down to its
// last leaf; other grids are only checked as far as libopenvdb's File::open reads them.
// Returns what it walked, so that tests can tell the walk followed the format to the byte.
struct VdbFileWalk {
  int grids_checked = 0;
  int grids_ending_at_stated_end = 0;  // walks that ended exactly where the grid's descriptor says
};
VdbFileWalk checkVdbFileStructure(const std::string& path, const std::vector<std::string>& grids_to_read);
// The same walk for a reader of headers only (File::readGridMetadata, `vdbfuse info`): each grid
// in `grids_to_read` is checked as far as its metadata and transform, its tree is not visited
// (nor paged in: the file is mapped, so a 300 MB scene costs a few pages).
VdbFileWalk checkVdbFileHeaders(const std::string& path, const std::vector<std::string>& grids_to_read);

}  // namespace vf
