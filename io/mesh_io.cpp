#include "io/mesh_io.h"

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/atomic_output.h"
#include "core/color.h"
#include "core/error.h"
#include "core/mapped_file.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// Face groups by vertex class (majority of the three), for OBJ groups and GLB meshes.
std::map<int32_t, std::vector<size_t>> facesByClass(const TriangleMesh& mesh) {
  std::map<int32_t, std::vector<size_t>> out;
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    int32_t id = -1;
    if (mesh.hasClasses()) {
      const auto& t = mesh.triangles[f];
      const int32_t a = mesh.classes[t[0]], b = mesh.classes[t[1]], c = mesh.classes[t[2]];
      id = (b == c && a != b) ? b : a;
    }
    out[id].push_back(f);
  }
  return out;
}

std::string groupName(const ClassTable* classes, int32_t id) {
  const ClassInfo* c = classes ? classes->findId(id) : nullptr;
  std::string name = c ? c->name : (id < 0 ? std::string("surface") : "class_" + std::to_string(id));
  for (char& ch : name)
    if (std::isspace(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

// A group's material colour, linear: the class colour when the mesh is class-coloured or has no
// vertex colours (white without a class table), else the mean of the group's vertex colours
// (OBJ) or white (GLB, where COLOR_0 multiplies it).
Vec3f groupColor(const TriangleMesh& mesh, const std::vector<size_t>& faces, const MeshWriteOptions& options,
                 int32_t id, bool mean_of_vertices) {
  if (options.class_colors || !mesh.hasColors()) {
    const ClassInfo* c = options.classes ? options.classes->findId(id) : nullptr;
    return c ? srgb8ToLinear(c->color) : Vec3f{1, 1, 1};
  }
  if (!mean_of_vertices) return {1, 1, 1};
  Vec3f sum{0, 0, 0};
  for (size_t f : faces)
    for (int32_t v : mesh.triangles[f]) sum = sum + srgb8ToLinear(mesh.colors[size_t(v)]);
  return faces.empty() ? Vec3f{1, 1, 1} : sum * (1.f / float(3 * faces.size()));
}

void checkMesh(const TriangleMesh& mesh, const std::string& path) {
  const size_t n = mesh.positions.size();
  if ((mesh.hasNormals() && mesh.normals.size() != n) || (mesh.hasColors() && mesh.colors.size() != n) ||
      (mesh.hasClasses() && mesh.classes.size() != n) || (mesh.hasUvs() && mesh.uvs.size() != n))
    throw Error(path + ": mesh attribute arrays differ in length from the positions");
}

void checkTexture(const TriangleMesh& mesh, const MeshWriteOptions& options, const std::string& path) {
  if (!options.texture) return;
  if (!mesh.hasUvs()) throw Error(path + ": a texture needs texture coordinates (uvs) on the mesh");
  if (options.texture->extension != "jpg" && options.texture->extension != "png")
    throw Error(path + ": texture images are jpg or png, not '" + options.texture->extension + "'");
}

}  // namespace

MeshFormat meshFormatFromPath(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".ply") return MeshFormat::kPly;
  if (ext == ".obj") return MeshFormat::kObj;
  if (ext == ".glb") return MeshFormat::kGlb;
  throw Error(path + ": unknown mesh format '" + ext + "' (use .ply, .obj or .glb)");
}

void writeMesh(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options) {
  const MeshFormat format = meshFormatFromPath(path);
  if (mesh.triangles.empty() && format != MeshFormat::kPly)
    throw Error(path + ": a point cloud can only be written as .ply");
  if (options.texture && format == MeshFormat::kPly)
    throw Error(path + ": PLY carries no texture; write .glb or .obj for a textured mesh");
  switch (format) {
    case MeshFormat::kPly: return writePly(mesh, path, options.with_class_property, options.frame);
    case MeshFormat::kObj: return writeObj(mesh, path, options);
    case MeshFormat::kGlb: return writeGlb(mesh, path, options);
  }
}

namespace {

constexpr const char* kFrameComment = "vdbfuse frame";

// "comment vdbfuse frame z-up file_from_scene R00 R01 .. R22 TX TY TZ": full float precision, so
// that reading it back undoes the rotation exactly.
std::string frameComment(const MeshFrame& frame) {
  std::string line = std::string("comment ") + kFrameComment + " " + frame.axes + " file_from_scene";
  char number[32];
  const Rigid3f& T = frame.file_from_scene;
  for (float v : {T.r[0], T.r[1], T.r[2], T.r[3], T.r[4], T.r[5], T.r[6], T.r[7], T.r[8], T.t.x, T.t.y, T.t.z}) {
    std::snprintf(number, sizeof number, " %.9g", double(v));
    line += number;
  }
  return line + "\n";
}

// The rest of a "comment vdbfuse frame" line (after that prefix).
MeshFrame parseFrameComment(std::istringstream& in, const std::string& path) {
  MeshFrame frame;
  std::string key;
  float v[12];
  in >> frame.axes >> key;
  for (float& x : v) in >> x;
  bool finite = true;
  for (float x : v) finite = finite && std::isfinite(x);
  const bool known_axes = frame.axes == "camera" || frame.axes == "z-up" || frame.axes == "y-up";
  if (in.fail() || key != "file_from_scene" || !finite || !known_axes)
    throw Error(path + ": malformed '" + kFrameComment + "' header comment (expected axes camera, z-up or y-up, "
                "then file_from_scene and 12 numbers)");
  for (int i = 0; i < 9; ++i) frame.file_from_scene.r[i] = v[i];
  frame.file_from_scene.t = {v[9], v[10], v[11]};
  // Undoing it transposes the rotation: anything but a rotation would be undone wrongly.
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const float dot = v[3 * i] * v[3 * j] + v[3 * i + 1] * v[3 * j + 1] + v[3 * i + 2] * v[3 * j + 2];
      if (std::fabs(dot - (i == j ? 1.f : 0.f)) > 1e-4f)
        throw Error(path + ": the '" + kFrameComment + "' header comment holds no rotation (rows not orthonormal)");
    }
  return frame;
}

}  // namespace

void writePly(const TriangleMesh& mesh, const std::string& path, bool with_class_property,
              const std::optional<MeshFrame>& frame) {
  checkMesh(mesh, path);
  if (with_class_property && !mesh.hasClasses())
    throw Error(path + ": --with-class-property needs a scene with classes");
  AtomicFile file(path);
  const fs::path tmp = file.tempPath();
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw Error(path + ": cannot create " + tmp.string());
    out << "ply\nformat binary_little_endian 1.0\ncomment written by vdbfuse\n";
    if (frame) out << frameComment(*frame);
    out << "element vertex " << mesh.positions.size() << "\n";
    out << "property float x\nproperty float y\nproperty float z\n";
    if (mesh.hasNormals()) out << "property float nx\nproperty float ny\nproperty float nz\n";
    if (mesh.hasColors()) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (with_class_property) out << "property int class\n";
    out << "element face " << mesh.triangles.size() << "\n";
    out << "property list uchar int vertex_indices\nend_header\n";
    // One record per vertex, assembled in a buffer (x86 is little endian, as the header says).
    const size_t stride = 12 + (mesh.hasNormals() ? 12 : 0) + (mesh.hasColors() ? 3 : 0) + (with_class_property ? 4 : 0);
    std::vector<char> buf(stride * mesh.positions.size());
    char* p = buf.data();
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      std::memcpy(p, &mesh.positions[v], 12), p += 12;
      if (mesh.hasNormals()) std::memcpy(p, &mesh.normals[v], 12), p += 12;
      if (mesh.hasColors()) {
        *p++ = char(mesh.colors[v].r);
        *p++ = char(mesh.colors[v].g);
        *p++ = char(mesh.colors[v].b);
      }
      if (with_class_property) std::memcpy(p, &mesh.classes[v], 4), p += 4;
    }
    out.write(buf.data(), std::streamsize(buf.size()));
    buf.assign(13 * mesh.triangles.size(), 0);
    p = buf.data();
    for (const auto& t : mesh.triangles) {
      *p++ = 3;
      std::memcpy(p, t.data(), 12), p += 12;
    }
    out.write(buf.data(), std::streamsize(buf.size()));
    out.close();
    if (!out) throw Error(path + ": write failed (disk full?)");
  }
  file.commit();
}

std::string objTexturePath(const std::string& obj_path, const MeshTexture& texture) {
  return fs::path(obj_path).replace_extension("." + texture.extension).string();
}

void writeObj(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options) {
  const ClassTable* classes = options.classes;
  checkMesh(mesh, path);
  checkTexture(mesh, options, path);
  const MeshTexture* texture = options.texture;
  const fs::path target(path);
  fs::path mtl_target = target;
  mtl_target.replace_extension(".mtl");
  AtomicFile file(path), mtl_file(mtl_target.string());
  std::optional<AtomicFile> image_file;
  if (texture && texture->shared_file.empty()) {
    image_file.emplace(objTexturePath(path, *texture));
    image_file->write(texture->encoded.data(), texture->encoded.size());
  }
  const fs::path tmp = file.tempPath(), mtl_tmp = mtl_file.tempPath();
  const auto groups = facesByClass(mesh);
  {
    std::ofstream mtl(mtl_tmp);
    for (const auto& [id, faces] : groups) {
      if (texture) {  // the texture carries the colour; Kd white so that it is not tinted
        const std::string image = texture->shared_file.empty()
                                      ? fs::path(objTexturePath(path, *texture)).filename().string()
                                      : texture->shared_file;
        mtl << "newmtl " << groupName(classes, id) << "\nKd 1 1 1\nmap_Kd " << image << "\n\n";
        continue;
      }
      const Vec3f c = groupColor(mesh, faces, options, id, /*mean_of_vertices=*/true);
      mtl << "newmtl " << groupName(classes, id) << "\nKd " << c.x << " " << c.y << " " << c.z << "\n\n";
    }
    std::ofstream out(tmp);
    if (!out || !mtl) throw Error(path + ": cannot create " + tmp.string());
    out << "# written by vdbfuse\nmtllib " << mtl_target.filename().string() << "\n";
    char line[160];
    // Vertex colors as the common "v x y z r g b" extension (Assimp, MeshLab, Blender read it).
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3f& q = mesh.positions[v];
      if (mesh.hasColors() && !texture) {
        const Rgb8 c = mesh.colors[v];
        std::snprintf(line, sizeof line, "v %.6f %.6f %.6f %.4f %.4f %.4f\n", q.x, q.y, q.z, c.r / 255.f,
                      c.g / 255.f, c.b / 255.f);
      } else {
        std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", q.x, q.y, q.z);
      }
      out << line;
    }
    for (const Vec3f& n : mesh.normals) {
      std::snprintf(line, sizeof line, "vn %.5f %.5f %.5f\n", n.x, n.y, n.z);
      out << line;
    }
    if (texture)
      for (const Vec2f& uv : mesh.uvs) {
        std::snprintf(line, sizeof line, "vt %.7f %.7f\n", uv.x, uv.y);
        out << line;
      }
    for (const auto& [id, faces] : groups) {
      out << "g " << groupName(classes, id) << "\nusemtl " << groupName(classes, id) << "\n";
      for (size_t f : faces) {
        const auto& t = mesh.triangles[f];
        if (texture && mesh.hasNormals())  // uvs are per vertex: vt index = v index
          std::snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", t[0] + 1, t[0] + 1, t[0] + 1, t[1] + 1,
                        t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1, t[2] + 1);
        else if (texture)
          std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1,
                        t[2] + 1);
        else if (mesh.hasNormals())
          std::snprintf(line, sizeof line, "f %d//%d %d//%d %d//%d\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1,
                        t[2] + 1, t[2] + 1);
        else
          std::snprintf(line, sizeof line, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
        out << line;
      }
    }
    out.close();
    mtl.close();
    if (!out || !mtl) throw Error(path + ": write failed (disk full?)");
  }
  if (image_file) image_file->commit();
  mtl_file.commit();
  file.commit();
}

void writeGlb(const TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options) {
  const ClassTable* classes = options.classes;
  // Class colours go into the materials; COLOR_0 would multiply them by themselves.
  const MeshTexture* texture = options.texture;
  const bool vertex_colors = mesh.hasColors() && !options.class_colors && !texture;
  checkMesh(mesh, path);
  checkTexture(mesh, options, path);
  const auto groups = facesByClass(mesh);
  // Assimp's aiScene owns (and deletes) everything hung on it.
  aiScene scene;
  scene.mRootNode = new aiNode("vdbfuse_scene");
  scene.mNumMeshes = scene.mNumMaterials = unsigned(groups.size());
  scene.mMeshes = new aiMesh*[groups.size()];
  scene.mMaterials = new aiMaterial*[groups.size()];
  scene.mRootNode->mNumMeshes = unsigned(groups.size());
  scene.mRootNode->mMeshes = new unsigned[groups.size()];
  if (texture) {  // embedded ("*0"): the exporter stores it in the GLB's binary chunk
    scene.mNumTextures = 1;
    scene.mTextures = new aiTexture*[1];
    auto* tex = new aiTexture();
    tex->mWidth = unsigned(texture->encoded.size());  // compressed: width = bytes, height = 0
    tex->mHeight = 0;
    tex->pcData = new aiTexel[(texture->encoded.size() + sizeof(aiTexel) - 1) / sizeof(aiTexel)];
    std::memcpy(tex->pcData, texture->encoded.data(), texture->encoded.size());
    std::snprintf(tex->achFormatHint, sizeof tex->achFormatHint, "%s", texture->extension.c_str());
    tex->mFilename = aiString("texture." + texture->extension);
    scene.mTextures[0] = tex;
  }
  unsigned m = 0;
  for (const auto& [id, faces] : groups) {
    auto* material = new aiMaterial();
    const aiString name(groupName(classes, id));
    material->AddProperty(&name, AI_MATKEY_NAME);
    if (texture) {
      const aiString embedded("*0");
      material->AddProperty(&embedded, AI_MATKEY_TEXTURE(aiTextureType_BASE_COLOR, 0));
      material->AddProperty(&embedded, AI_MATKEY_TEXTURE(aiTextureType_DIFFUSE, 0));
    }
    const Vec3f c = texture ? Vec3f{1, 1, 1} : groupColor(mesh, faces, options, id, /*mean_of_vertices=*/false);
    const aiColor4D base(c.x, c.y, c.z, 1.f);
    material->AddProperty(&base, 1, AI_MATKEY_COLOR_DIFFUSE);
    material->AddProperty(&base, 1, AI_MATKEY_BASE_COLOR);
    // A scanned room is a matte dielectric (glTF's default metallicFactor is 1: a dark mirror).
    const float metallic = 0.f, roughness = 1.f;
    material->AddProperty(&metallic, 1, AI_MATKEY_METALLIC_FACTOR);
    material->AddProperty(&roughness, 1, AI_MATKEY_ROUGHNESS_FACTOR);
    scene.mMaterials[m] = material;

    // Each group gets its own compact vertex array (glTF primitives do not share vertices).
    std::vector<int32_t> remap(mesh.positions.size(), -1);
    std::vector<int32_t> used;
    for (size_t f : faces)
      for (int32_t v : mesh.triangles[f])
        if (remap[v] < 0) remap[v] = int32_t(used.size()), used.push_back(v);
    auto* am = new aiMesh();
    am->mName = name;
    am->mMaterialIndex = m;
    am->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    am->mNumVertices = unsigned(used.size());
    am->mVertices = new aiVector3D[used.size()];
    if (mesh.hasNormals()) am->mNormals = new aiVector3D[used.size()];
    if (vertex_colors) am->mColors[0] = new aiColor4D[used.size()];
    if (texture) {
      am->mTextureCoords[0] = new aiVector3D[used.size()];
      am->mNumUVComponents[0] = 2;
    }
    for (size_t i = 0; i < used.size(); ++i) {
      const Vec3f& p = mesh.positions[used[i]];
      am->mVertices[i] = aiVector3D(p.x, p.y, p.z);
      if (mesh.hasNormals()) {
        const Vec3f& n = mesh.normals[used[i]];
        am->mNormals[i] = aiVector3D(n.x, n.y, n.z);
      }
      if (texture) am->mTextureCoords[0][i] = aiVector3D(mesh.uvs[used[i]].x, mesh.uvs[used[i]].y, 0.f);
      if (vertex_colors) {  // glTF: COLOR_0 is linear
        const Vec3f col = srgb8ToLinear(mesh.colors[used[i]]);
        am->mColors[0][i] = aiColor4D(col.x, col.y, col.z, 1.f);
      }
    }
    am->mNumFaces = unsigned(faces.size());
    am->mFaces = new aiFace[faces.size()];
    for (size_t i = 0; i < faces.size(); ++i) {
      aiFace& face = am->mFaces[i];
      face.mNumIndices = 3;
      face.mIndices = new unsigned[3];
      for (int k = 0; k < 3; ++k) face.mIndices[k] = unsigned(remap[mesh.triangles[faces[i]][k]]);
    }
    scene.mMeshes[m] = am;
    scene.mRootNode->mMeshes[m] = m;
    ++m;
  }
  // To memory first: Assimp's file writer reports no write errors, ours does (disk full).
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "glb2");
  if (!blob) throw Error(path + ": GLB export failed: " + exporter.GetErrorString());
  AtomicFile file(path);
  file.write(blob->data, blob->size);
  file.commit();
}

namespace {

struct PlyProperty {
  std::string name, type, count_type;  // count_type set for list properties
  bool is_list = false;
};
struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
};

size_t plyTypeSize(const std::string& t, const std::string& path) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  throw Error(path + ": unknown PLY property type '" + t + "'");
}

double plyRead(const char* p, const std::string& t) {
  auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return double(v);
  };
  if (t == "char" || t == "int8") return get(int8_t{});
  if (t == "uchar" || t == "uint8") return get(uint8_t{});
  if (t == "short" || t == "int16") return get(int16_t{});
  if (t == "ushort" || t == "uint16") return get(uint16_t{});
  if (t == "int" || t == "int32") return get(int32_t{});
  if (t == "uint" || t == "uint32") return get(uint32_t{});
  if (t == "float" || t == "float32") return get(float{});
  return get(double{});
}

// A value read for an integer field (a list's count, a vertex index, a class id): refused unless
// it is a whole number in [lo, hi], so that no conversion of NaN or of 1e30 to an integer occurs.
int64_t plyInteger(double d, double lo, double hi, const std::string& path, const char* what) {
  if (!(d >= lo && d <= hi && d == std::floor(d))) {
    std::ostringstream text;
    text << path << ": PLY " << what << " " << d << " is not a whole number in [" << int64_t(lo) << ", " << int64_t(hi)
         << "] (a damaged or crafted file)";
    throw Error(text.str());
  }
  return int64_t(d);
}

// A colour channel: clamped, NaN as 0 (colours only tint; no reason to refuse the mesh).
uint8_t plyByte(double d) { return d > 0 ? uint8_t(d < 255 ? d : 255) : uint8_t(0); }

}  // namespace

TriangleMesh readPly(const std::string& path, std::optional<MeshFrame>* frame) {
  if (frame) frame->reset();
  requireRegularFile(path, "PLY file");  // a FIFO would block, a device never end
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open PLY file");
  std::string line, format;
  std::getline(in, line);
  if (line != "ply" && line != "ply\r") throw Error(path + ": not a PLY file");
  std::vector<PlyElement> elements;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
    } else if (frame && line.rfind(std::string("comment ") + kFrameComment + " ", 0) == 0) {
      ls.seekg(std::streamoff(std::strlen("comment ") + std::strlen(kFrameComment)));
      *frame = parseFrameComment(ls, path);
    } else if (word == "element") {
      elements.emplace_back();
      ls >> elements.back().name >> elements.back().count;
    } else if (word == "property") {
      if (elements.empty()) throw Error(path + ": PLY property before any element");
      PlyProperty prop;
      ls >> prop.type;
      if (prop.type == "list") {
        prop.is_list = true;
        ls >> prop.count_type >> prop.type;
      }
      ls >> prop.name;
      elements.back().props.push_back(prop);
    } else if (word == "end_header") break;
  }
  if (format != "binary_little_endian" && format != "ascii")
    throw Error(path + ": PLY format '" + format + "' is not supported (binary_little_endian or ascii)");
  const bool ascii = format == "ascii";
  const uintmax_t file_bytes = fs::file_size(path);
  TriangleMesh mesh;
  for (const PlyElement& el : elements) {
    // Items without properties hold no data: nothing to read, however many the header states
    // (looping over 10^14 of them hung the reader).
    if (el.props.empty()) continue;
    // Every other item takes at least a byte (ASCII: a digit and a separator), so a count beyond
    // the file's size is a damaged or crafted header: refused before any loop or allocation.
    if (el.count > file_bytes)
      throw Error(path + ": PLY element '" + el.name + "' states " + std::to_string(el.count) + " items, more than the " +
                  std::to_string(file_bytes) + " bytes of the file hold");
    const bool is_vertex = el.name == "vertex", is_face = el.name == "face";
    for (size_t i = 0; i < el.count; ++i) {
      Vec3f pos{0, 0, 0}, nrm{0, 0, 0};
      Rgb8 col{0, 0, 0, 255};
      int32_t cls = -1;
      bool has_n = false, has_c = false, has_k = false;
      for (const PlyProperty& prop : el.props) {
        const auto truncated = [&] {
          return Error(path + ": PLY file is truncated: it ends in " + el.name + " " + std::to_string(i) + " of " +
                       std::to_string(el.count));
        };
        auto value = [&](const std::string& type) {
          if (ascii) {
            // A word, then the number: `in >> double` fails alike on the end of the file and on
            // "nan" or "inf", which were all reported as a truncated file.
            std::string word;
            if (!(in >> word)) throw truncated();
            char* end = nullptr;
            const double d = std::strtod(word.c_str(), &end);
            if (end != word.c_str() + word.size())
              throw Error(path + ": PLY " + el.name + " " + std::to_string(i) + ": property '" + prop.name + "' is '" +
                          word + "', not a number");
            return d;
          }
          char b[8];
          if (!in.read(b, std::streamsize(plyTypeSize(type, path)))) throw truncated();
          return plyRead(b, type);
        };
        if (prop.is_list) {
          const size_t n = size_t(plyInteger(value(prop.count_type), 0, double(file_bytes), path, "list length"));
          std::vector<int32_t> idx(n);
          for (size_t k = 0; k < n; ++k)
            idx[k] = int32_t(plyInteger(value(prop.type), INT32_MIN, INT32_MAX, path, "list entry"));
          if (is_face && (prop.name == "vertex_indices" || prop.name == "vertex_index"))
            for (size_t k = 1; k + 1 < n; ++k) mesh.triangles.push_back({idx[0], idx[k], idx[k + 1]});
          continue;
        }
        const double d = value(prop.type);
        if (!is_vertex) continue;
        const std::string& nm = prop.name;
        if (nm == "x") pos.x = float(d);
        else if (nm == "y") pos.y = float(d);
        else if (nm == "z") pos.z = float(d);
        else if (nm == "nx") nrm.x = float(d), has_n = true;
        else if (nm == "ny") nrm.y = float(d);
        else if (nm == "nz") nrm.z = float(d);
        else if (nm == "red") col.r = plyByte(d), has_c = true;
        else if (nm == "green") col.g = plyByte(d);
        else if (nm == "blue") col.b = plyByte(d);
        else if (nm == "class") cls = int32_t(plyInteger(d, INT32_MIN, INT32_MAX, path, "class")), has_k = true;
      }
      if (!is_vertex) continue;
      // NaN or inf has no place on a surface: the metrics and the writers would carry it on.
      if (!isFinite(pos)) {
        std::ostringstream text;
        text << path << ": PLY vertex " << mesh.positions.size() << " has a coordinate that is not a finite number ("
             << pos.x << ", " << pos.y << ", " << pos.z << ")";
        throw Error(text.str());
      }
      mesh.positions.push_back(pos);
      if (has_n) mesh.normals.push_back(nrm);
      if (has_c) mesh.colors.push_back(col);
      if (has_k) mesh.classes.push_back(cls);
    }
  }
  for (const auto& t : mesh.triangles)
    for (int32_t v : t)
      if (v < 0 || size_t(v) >= mesh.positions.size()) throw Error(path + ": PLY face index out of range");
  // Normals, colours and classes belong to every vertex or to none (two vertex elements with
  // different properties broke that, and the writers index them per vertex).
  const auto every_vertex = [&](size_t n, const char* what) {
    if (n != 0 && n != mesh.positions.size())
      throw Error(path + ": PLY vertices do not all carry " + what + " (a damaged or crafted file)");
  };
  every_vertex(mesh.normals.size(), "normals");
  every_vertex(mesh.colors.size(), "colours");
  every_vertex(mesh.classes.size(), "classes");
  return mesh;
}

TriangleMesh readPlyInSceneFrame(const std::string& path, std::string* note) {
  std::optional<MeshFrame> frame;
  TriangleMesh mesh = readPly(path, &frame);
  if (note) *note = "as written";
  if (!frame || frame->axes == "camera") return mesh;
  const Rigid3f T = frame->file_from_scene.inverse();
  for (Vec3f& p : mesh.positions) p = T * p;
  for (Vec3f& n : mesh.normals) n = T.rotate(n);
  if (note) *note = "written --axes " + frame->axes + ", brought back into the scene's frame";
  return mesh;
}

}  // namespace vf
