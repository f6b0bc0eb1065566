#pragma once
// Face-level operations on a meshed scene: class filters, per-class split, small pieces.
#include <cstddef>
#include <map>
#include <set>
#include <vector>

#include "core/class_table.h"
#include "core/mesh.h"

namespace vf {

// A face's class: the class at least two of its vertices share, else its first vertex's.
// -1 for every face when the mesh has no classes.
std::vector<int32_t> faceClasses(const TriangleMesh& mesh);

// The faces with keep[f] true and the vertices they use (renumbered, order kept).
TriangleMesh selectFaces(const TriangleMesh& mesh, const std::vector<bool>& keep);

// Faces whose class is in `ids` (include) or not in `ids` (exclude). Throws vf::Error when the
// mesh has no classes or nothing is left.
TriangleMesh filterFacesByClass(const TriangleMesh& mesh, const std::set<int>& ids, bool include);

// One mesh per face class (key -1: unknown). Together they hold exactly the input's faces.
std::map<int32_t, TriangleMesh> splitByClass(const TriangleMesh& mesh);

// Connected pieces: faces sharing a vertex are in one piece. Per face, its piece's face count.
std::vector<size_t> faceComponentSizes(const TriangleMesh& mesh);

struct ComponentStats {
  size_t pieces = 0;           // connected pieces
  size_t small = 0;            // of them, with fewer than the threshold's triangles
  size_t small_triangles = 0;  // faces in those
  size_t largest = 0;          // faces of the largest piece
};
ComponentStats meshComponents(const TriangleMesh& mesh, size_t min_triangles);

// Drops connected pieces with fewer than `min_triangles` faces; returns how many faces went.
size_t removeSmallComponents(TriangleMesh& mesh, size_t min_triangles);

// A file-name-safe form of a class name ("dining table" -> "dining_table"; unknown -> "unknown").
std::string classFileStem(const ClassTable& table, int32_t id);

// classFileStem of each id, made unique: names that sanitise (or differ only in case) to the same
// stem ("a/b" and "a_b") get "_<id>" appended after the first (lowest id), so that one class's file
// never replaces another's.
std::map<int32_t, std::string> uniqueClassFileStems(const ClassTable& table, const std::vector<int32_t>& ids);

}  // namespace vf
