#include "scene_import.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <new>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "medspheres/error.h"
#include "medspheres/number_text.h"

namespace medspheres::detail {

namespace {

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return e;
}

// ---- OFF pre-scan -------------------------------------------------------------------
// It reads the file the way assimp 5.2's OFF reader does, so that "face f" is the line
// assimp takes as face f: the header's tokens, skipping blank space and '#' comment lines;
// then one vertex line per vertex and one face line per face, where a line ends at
// '\n', '\r' or '\f' and runs of line ends count as one.

bool is_digits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// The value of a string of digits, saturated at 2^62 (any count or index that large is
// out of range anyway). Each step is tested before it is taken, so that no digit string,
// however long, overflows: v * 10 + d <= 2^62 exactly when v <= (2^62 - d) / 10.
long long digits_value(std::string_view s) {
  constexpr long long kCap = 1ll << 62;
  long long v = 0;
  for (char c : s) {
    const int d = c - '0';
    if (v > (kCap - d) / 10) return kCap;
    v = v * 10 + d;
  }
  return v;
}

class OffScanner {
 public:
  explicit OffScanner(std::string_view text) : p_(text.data()), end_(text.data() + text.size()) {}

  // assimp's NextToken without the token: skips blanks, line ends and whole '#'
  // comment lines.
  void skip_blank() {
    for (;;) {
      while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || is_line_end(*p_))) ++p_;
      if (p_ >= end_ || *p_ != '#') return;
      while (p_ < end_ && !is_line_end(*p_)) ++p_;
    }
  }

  // The next header token.
  std::string_view token() {
    skip_blank();
    const char* s = p_;
    while (p_ < end_ && *p_ != ' ' && *p_ != '\t' && !is_line_end(*p_)) ++p_;
    return {s, static_cast<std::size_t>(p_ - s)};
  }

  // assimp's GetNextLine.
  bool line(std::string_view* out) {
    if (p_ >= end_) return false;
    const char* s = p_;
    while (p_ < end_ && !is_line_end(*p_)) ++p_;
    *out = {s, static_cast<std::size_t>(p_ - s)};
    while (p_ < end_ && is_line_end(*p_)) ++p_;
    return true;
  }

 private:
  static bool is_line_end(char c) { return c == '\n' || c == '\r' || c == '\f'; }
  const char* p_;
  const char* end_;
};

// Splits a line at blanks.
std::vector<std::string_view> split_blanks(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t s = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > s) out.push_back(line.substr(s, i - s));
  }
  return out;
}

// "ST", "C", "N", "4", "n" prefixes, in this order, then "OFF". *dimension set for "n".
bool is_off_keyword(std::string_view t, bool* dimension) {
  if (t.size() >= 2 && t.substr(0, 2) == "ST") t.remove_prefix(2);
  for (char c : {'C', 'N', '4'})
    if (!t.empty() && t.front() == c) t.remove_prefix(1);
  *dimension = !t.empty() && t.front() == 'n';
  if (*dimension) t.remove_prefix(1);
  return t == "OFF";
}

std::string plural(long long n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// A count as the file writes it (a count past 2^62 is not shown saturated).
std::string plural(std::string_view digits, long long n, const char* one, const char* many) {
  return std::string(digits) + " " + (n == 1 ? one : many);
}

}  // namespace

void check_off_faces(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;  // assimp reports it
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.resize(std::strlen(text.c_str()));  // assimp's reader stops at a NUL byte

  OffScanner scan(text);
  bool dimension = false;
  if (!is_off_keyword(scan.token(), &dimension)) return;  // assimp decides
  if (dimension && !is_digits(scan.token())) return;
  const std::string_view nv_token = scan.token();
  const std::string_view nf_token = scan.token();
  const std::string_view ne_token = scan.token();
  if (!is_digits(nv_token) || !is_digits(nf_token) || !is_digits(ne_token)) return;
  const long long nv = digits_value(nv_token), nf = digits_value(nf_token);
  if (nv == 0 || nf == 0) return;  // assimp's own error is clear
  scan.skip_blank();               // the data starts at the next token, as in assimp

  std::string_view line;
  for (long long v = 0; v < nv; ++v) {
    if (!scan.line(&line))
      throw InputError(
          path, "truncated: the header announces " + plural(nv_token, nv, "vertex", "vertices") +
                    ", but the file has only " + plural(v, "vertex line", "vertex lines"));
  }
  for (long long f = 0; f < nf; ++f) {
    if (!scan.line(&line))
      throw InputError(path, "truncated: the header announces " +
                                 plural(nf_token, nf, "face", "faces") +
                                 ", but the file has only " + plural(f, "face line", "face lines"));
    const std::vector<std::string_view> tokens = split_blanks(line);
    const std::string face = "face " + std::to_string(f) + " (counted from 0)";
    if (tokens.empty()) throw InputError(path, face + " is a blank line");
    if (!is_digits(tokens[0]))
      throw InputError(
          path, face + " does not start with a vertex count: '" + std::string(tokens[0]) + "'");
    const long long k = digits_value(tokens[0]);
    if (k < 1 || k > 9)
      throw InputError(path, face + " has " + std::to_string(k) +
                                 " vertices; the OFF reader takes 1 to 9 per face");
    if (static_cast<long long>(tokens.size()) < k + 1)
      throw InputError(path, face + " announces " + std::to_string(k) + " vertices but lists " +
                                 std::to_string(tokens.size() - 1));
    for (long long j = 1; j <= k; ++j) {
      std::string_view t = tokens[static_cast<std::size_t>(j)];
      const bool negative = t.size() > 1 && t.front() == '-';
      if (negative) t.remove_prefix(1);
      if (!is_digits(t))
        throw InputError(path, face + " has '" + std::string(tokens[static_cast<std::size_t>(j)]) +
                                   "' where a vertex index should be");
      const long long index = negative ? -digits_value(t) : digits_value(t);
      if (index < 0 || index >= nv)
        throw InputError(
            path, face + " refers to vertex " + std::string(tokens[static_cast<std::size_t>(j)]) +
                      ", out of range: the file has " + plural(nv_token, nv, "vertex", "vertices") +
                      " (0 to " + std::to_string(nv - 1) + ")");
    }
  }
}

namespace {

// The bytes one value of a PLY property type takes in binary ("char" ... "double", and
// the sized names); 0 for a name that is not a type.
int ply_type_bytes(std::string_view t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

}  // namespace

void check_ply_counts(const std::string& path, std::uintmax_t file_size) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return;  // assimp decides
  bool ascii = false;
  std::vector<std::pair<std::string, long long>> elements;  // name, count
  std::vector<long long> min_bytes;                         // per instance
  while (std::getline(in, line) && in.tellg() < (1 << 20)) {
    const std::vector<std::string_view> tok = split_blanks(line);
    if (tok.empty()) continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "format" && tok.size() > 1) ascii = tok[1] == "ascii";
    if (tok[0] == "element" && tok.size() > 2 && is_digits(tok[2])) {
      elements.emplace_back(std::string(tok[1]), digits_value(tok[2]));
      min_bytes.push_back(0);
    }
    // A value takes at least 2 bytes in ASCII (a digit and a separator); a list at least
    // its count (in binary, the count's type).
    if (tok[0] == "property" && !min_bytes.empty() && tok.size() > 1)
      min_bytes.back() +=
          ascii ? 2
                : std::max(1, ply_type_bytes(tok[1] == "list" && tok.size() > 2 ? tok[2] : tok[1]));
  }
  if (!in) return;  // no end_header: assimp reports it
  const long double after_header =
      static_cast<long double>(file_size) -
      static_cast<long double>(static_cast<std::streamoff>(in.tellg()));
  long double need = 0;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    need += static_cast<long double>(elements[e].second) * static_cast<long double>(min_bytes[e]);
    if (need > after_header)
      throw InputError(path, "truncated: the header announces " +
                                 std::to_string(elements[e].second) + " '" + elements[e].first +
                                 "' elements, which take more than the " +
                                 std::to_string(static_cast<long long>(after_header)) +
                                 " bytes that follow the header");
  }
}

void check_stl_counts(const std::string& path, std::uintmax_t file_size) {
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  if (file_size < 84 || !in.read(head, 84)) return;
  // ASCII (assimp skips blanks before the keyword), or assimp's own test decides.
  std::string_view start(head, 84);
  const std::size_t word = start.find_first_not_of(" \t\r\n");
  if (word == std::string_view::npos || start.substr(word, 5) == "solid") return;
  std::uint32_t count = 0;
  std::memcpy(&count, head + 80, 4);
  const std::uintmax_t need = 84 + 50 * static_cast<std::uintmax_t>(count);
  if (need != file_size)
    throw InputError(path,
                     "cannot parse the file (not ASCII STL: no 'solid' keyword; as "
                     "binary STL its header announces " +
                         std::to_string(count) + " triangles, " + std::to_string(need) +
                         " bytes, but the file has " + std::to_string(file_size) + ")");
}

namespace {

// What assimp's validation guarantees of the meshes and what import_flat relies on, for a
// scene read without it: every mesh and array present, every face index in range (checked
// as faces are read).
void check_mesh_arrays(const std::string& path, const aiScene* scene) {
  if (scene->mNumMeshes > 0 && scene->mMeshes == nullptr)
    throw InputError(path, "cannot parse the file (the scene lists meshes but holds none)");
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    if (m == nullptr || (m->mNumVertices > 0 && m->mVertices == nullptr) ||
        (m->mNumFaces > 0 && m->mFaces == nullptr))
      throw InputError(path, "cannot parse the file (mesh " + std::to_string(mi) +
                                 " lacks its vertices or faces)");
    for (unsigned f = 0; f < m->mNumFaces; ++f)
      if (m->mFaces[f].mNumIndices > 0 && m->mFaces[f].mIndices == nullptr)
        throw InputError(path, "cannot parse the file (face " + std::to_string(f) + " of mesh " +
                                   std::to_string(mi) + " lacks its indices)");
  }
}

// The scene of path as assimp reads it (owned by importer), with assimp's structural
// validation; a scene that fails only the validation is read again without it and the
// failure kept in validation_failure (the rest of a scene, its cameras, lights and names,
// is no concern of a mesh, and the meshes are checked afterwards).
const aiScene* read_scene(Assimp::Importer& importer, const std::string& path,
                          std::string& validation_failure) {
  // Drop point and line primitives; triangulate polygons. No vertex joining: load_mesh
  // welds on positions only, so that split normals or UVs do not split vertices.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Keep COLLADA coordinates as written: no Z-up to Y-up rotation (robot description
  // formats place DAE meshes in the file's own axes).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const unsigned steps = aiProcess_Triangulate | aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(path, steps | aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    const std::string why = importer.GetErrorString();
    if (why.rfind("Validation failed", 0) == 0) {
      validation_failure = why;
      scene = importer.ReadFile(path, steps);
    }
  }
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    // assimp catches std::bad_alloc and keeps only its text.
    if (why.find("bad_alloc") != std::string::npos) throw std::bad_alloc();
    if (why.empty()) why = "unknown error";
    throw InputError(path, "cannot parse the file (assimp: " + why + ")");
  }
  return scene;
}

// The file's own coordinates, checked before any transform, so that the message can name
// the vertex as read.
void check_finite_vertices(const std::string& path, const aiScene* scene) {
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
      throw InputError(path, "vertex " + std::to_string(v) + " of mesh " + std::to_string(mi) +
                                 " (counted from 0, as assimp reads the file) has a "
                                 "non-finite coordinate (" +
                                 number_text(p.x) + ", " + number_text(p.y) + ", " +
                                 number_text(p.z) + ")");
    }
  }
}

// Mesh mesh_index of the scene, its vertices moved by X (the transform of `node`, null for
// a mesh no node references), its triangles' indices.
FlatMesh flat_mesh(const std::string& path, const aiScene* scene, unsigned mesh_index,
                   const Eigen::Matrix4d& X, const aiNode* node) {
  const aiMesh* m = scene->mMeshes[mesh_index];
  FlatMesh flat;
  flat.xyz.resize(3 * static_cast<std::size_t>(m->mNumVertices));
  const bool identity = X == Eigen::Matrix4d::Identity();
  for (unsigned v = 0; v < m->mNumVertices; ++v) {
    const aiVector3D& p = m->mVertices[v];
    Eigen::Vector3d q(p.x, p.y, p.z);
    if (!identity) {
      const Eigen::Vector4d h = X * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
      q = h.head<3>() / h.w();
      if (!q.allFinite())
        throw InputError(path, "vertex " + std::to_string(v) + " of mesh " +
                                   std::to_string(mesh_index) +
                                   " is finite in the file but not after the transform of "
                                   "scene node '" +
                                   std::string(node != nullptr ? node->mName.C_Str() : "") + "'");
    }
    for (int i = 0; i < 3; ++i) flat.xyz[3 * static_cast<std::size_t>(v) + i] = q[i];
  }
  flat.index.reserve(3 * static_cast<std::size_t>(m->mNumFaces));
  for (unsigned f = 0; f < m->mNumFaces; ++f) {
    const aiFace& face = m->mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines
    for (int k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= m->mNumVertices)  // ValidateDataStructure rules this out
        throw InputError(path, "face " + std::to_string(f) + " of mesh " +
                                   std::to_string(mesh_index) + " refers to vertex " +
                                   std::to_string(face.mIndices[k]) + ", out of range");
      flat.index.push_back(face.mIndices[k]);
    }
  }
  return flat;
}

}  // namespace

FlatScene import_flat(const std::string& path) {
  Assimp::Importer importer;
  FlatScene out;
  const aiScene* scene = read_scene(importer, path, out.validation_failure);
  check_mesh_arrays(path, scene);
  check_finite_vertices(path, scene);
  std::vector<char> referenced(scene->mNumMeshes, 0);
  std::function<void(const aiNode*, const Eigen::Matrix4d&)> walk =
      [&](const aiNode* node, const Eigen::Matrix4d& parent) {
        const Eigen::Matrix4d X = parent * to_eigen(node->mTransformation);
        for (unsigned i = 0; node->mMeshes != nullptr && i < node->mNumMeshes; ++i) {
          const unsigned mi = node->mMeshes[i];
          if (mi >= scene->mNumMeshes) continue;
          referenced[mi] = 1;
          out.meshes.push_back(flat_mesh(path, scene, mi, X, node));
        }
        for (unsigned c = 0; node->mChildren != nullptr && c < node->mNumChildren; ++c)
          if (node->mChildren[c] != nullptr) walk(node->mChildren[c], X);
      };
  if (scene->mRootNode != nullptr) walk(scene->mRootNode, Eigen::Matrix4d::Identity());
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    if (referenced[i]) continue;
    out.meshes.push_back(flat_mesh(path, scene, i, Eigen::Matrix4d::Identity(), nullptr));
    ++out.orphans;
  }
  return out;
}

// ---- the child's answer --------------------------------------------------------------

namespace {

class Encoder {
 public:
  explicit Encoder(char tag, std::size_t reserve = 0) {
    out_.reserve(reserve);
    out_.push_back(tag);
  }
  void u64(std::uint64_t v) { bytes(&v, sizeof v); }
  template <typename T>
  void array(const std::vector<T>& v) {
    u64(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    u64(s.size());
    bytes(s.data(), s.size());
  }
  std::string take() { return std::move(out_); }

 private:
  void bytes(const void* p, std::size_t n) {
    if (n > 0) out_.append(static_cast<const char*>(p), n);
  }
  std::string out_;
};

class Decoder {
 public:
  Decoder(const char* begin, const char* end) : p_(begin), end_(end) {}
  bool u64(std::uint64_t* v) { return bytes(v, sizeof *v); }
  template <typename T>
  bool array(std::vector<T>* v) {
    std::uint64_t n = 0;
    if (!u64(&n) || n > static_cast<std::uint64_t>(end_ - p_) / sizeof(T)) return false;
    v->resize(static_cast<std::size_t>(n));
    return bytes(v->data(), v->size() * sizeof(T));
  }
  bool text(std::string* s) {
    std::uint64_t n = 0;
    if (!u64(&n) || n > static_cast<std::uint64_t>(end_ - p_)) return false;
    s->assign(p_, static_cast<std::size_t>(n));
    p_ += n;
    return true;
  }
  bool at_end() const { return p_ == end_; }

 private:
  bool bytes(void* out, std::size_t n) {
    if (n > static_cast<std::size_t>(end_ - p_)) return false;
    if (n > 0) std::memcpy(out, p_, n);
    p_ += n;
    return true;
  }
  const char* p_;
  const char* end_;
};

}  // namespace

std::string encode_scene(const FlatScene& scene) {
  std::size_t bytes = 25 + scene.validation_failure.size();
  for (const FlatMesh& m : scene.meshes)
    bytes += 16 + m.xyz.size() * sizeof(double) + m.index.size() * sizeof(std::uint32_t);
  Encoder e('R', bytes);
  e.u64(scene.orphans);
  e.text(scene.validation_failure);
  e.u64(scene.meshes.size());
  for (const FlatMesh& m : scene.meshes) {
    e.array(m.xyz);
    e.array(m.index);
  }
  return e.take();
}

std::string encode_message(char tag, const std::string& text) {
  Encoder e(tag);
  e.text(text);
  return e.take();
}

ImportAnswer decode_answer(const std::string& bytes) {
  ImportAnswer a;
  if (bytes.empty()) return a;
  a.tag = bytes[0];
  Decoder r(bytes.data() + 1, bytes.data() + bytes.size());
  if (a.tag == 'R') {
    std::uint64_t n = 0;
    if (!r.u64(&a.scene.orphans) || !r.text(&a.scene.validation_failure) || !r.u64(&n)) return a;
    for (std::uint64_t i = 0; i < n; ++i) {
      FlatMesh m;
      if (!r.array(&m.xyz) || !r.array(&m.index)) return a;
      if (m.xyz.size() % 3 != 0 || m.index.size() % 3 != 0) return a;
      for (std::uint32_t k : m.index)
        if (k >= m.xyz.size() / 3) return a;
      a.scene.meshes.push_back(std::move(m));
    }
  } else if (a.tag == 'E' || a.tag == 'M' || a.tag == 'X') {
    if (!r.text(&a.text)) return a;
  } else {
    return a;
  }
  a.ok = r.at_end();
  return a;
}

}  // namespace medspheres::detail
