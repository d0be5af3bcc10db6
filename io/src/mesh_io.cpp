#include "treeskel/io/mesh_io.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "formats.h"

#include <assimp/Exporter.hpp>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <nlohmann/json.hpp>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <array>
#include <map>
#include <memory>
#include <ostream>
#include <system_error>

namespace treeskel::io {

namespace fs = std::filesystem;

namespace {

const std::map<std::string, std::string>& formats() {
  static const std::map<std::string, std::string> ids = {
      {"obj", "objnomtl"}, {"gltf", "gltf2"}, {"glb", "glb2"}, {"ply", "plyb"}, {"stl", "stlb"}};
  return ids;
}

/// The rotation that turns `up` to +Y, entries within 1e-12 of an integer made exact (so that an
/// axis-aligned turn is exact in 32-bit floats too).
Eigen::Matrix3d y_up_rotation(const Eigen::Vector3d& up) {
  Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (int i = 0; i < 9; ++i)
    if (std::abs(r(i) - std::round(r(i))) < 1e-12) r(i) = std::round(r(i));
  return r;
}

/// The scene assimp writes: the mesh's vertices plus `shift`, the skeleton's nodes plus
/// `skeleton_shift`, and the root node turned by `rotation`.
std::unique_ptr<aiScene> make_scene(const modeling::TreeMesh& mesh, const Eigen::Vector3d& shift,
                                    const Skeleton* skeleton, const Eigen::Vector3d& skeleton_shift,
                                    const Eigen::Matrix3d& rotation) {
  auto scene = std::make_unique<aiScene>();
  const unsigned mesh_count = skeleton ? 2u : 1u;
  scene->mRootNode = new aiNode("tree");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) scene->mRootNode->mTransformation[i][j] = static_cast<ai_real>(rotation(i, j));
  scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};
  scene->mNumMaterials = 1;
  {
    aiString name("bark");
    scene->mMaterials[0]->AddProperty(&name, AI_MATKEY_NAME);
    const aiColor4D bark(0.45f, 0.33f, 0.22f, 1.0f);
    scene->mMaterials[0]->AddProperty(&bark, 1, AI_MATKEY_COLOR_DIFFUSE);
    scene->mMaterials[0]->AddProperty(&bark, 1, AI_MATKEY_BASE_COLOR);
  }
  scene->mMeshes = new aiMesh*[mesh_count]();
  scene->mNumMeshes = mesh_count;
  scene->mRootNode->mMeshes = new unsigned[mesh_count];
  scene->mRootNode->mNumMeshes = mesh_count;
  for (unsigned i = 0; i < mesh_count; ++i) scene->mRootNode->mMeshes[i] = i;

  auto* m = scene->mMeshes[0] = new aiMesh();
  m->mName = "wood";
  m->mMaterialIndex = 0;
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mNumVertices = static_cast<unsigned>(mesh.n_vertices());
  m->mVertices = new aiVector3D[m->mNumVertices];
  m->mNormals = new aiVector3D[m->mNumVertices];
  modeling::TreeMesh with_normals = mesh;
  with_normals.request_face_normals();
  with_normals.request_vertex_normals();
  with_normals.update_normals();
  for (auto v : with_normals.vertices()) {
    const auto p = with_normals.point(v);
    auto nrm = with_normals.normal(v);
    if (nrm.norm() > 0.0) nrm.normalize();
    const auto i = static_cast<unsigned>(v.idx());
    m->mVertices[i] = aiVector3D(static_cast<ai_real>(p[0] + shift.x()), static_cast<ai_real>(p[1] + shift.y()),
                                 static_cast<ai_real>(p[2] + shift.z()));
    m->mNormals[i] = aiVector3D(static_cast<ai_real>(nrm[0]), static_cast<ai_real>(nrm[1]), static_cast<ai_real>(nrm[2]));
  }
  m->mNumFaces = static_cast<unsigned>(mesh.n_faces());
  m->mFaces = new aiFace[m->mNumFaces];
  for (auto f : mesh.faces()) {
    aiFace& face = m->mFaces[f.idx()];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3];
    unsigned k = 0;
    for (auto v : mesh.fv_range(f)) face.mIndices[k++] = static_cast<unsigned>(v.idx());
  }
  if (skeleton) {
    const auto& g = skeleton->graph;
    auto* l = scene->mMeshes[1] = new aiMesh();
    l->mName = "skeleton";
    l->mMaterialIndex = 0;
    l->mPrimitiveTypes = aiPrimitiveType_LINE;
    l->mNumVertices = static_cast<unsigned>(boost::num_vertices(g));
    l->mVertices = new aiVector3D[l->mNumVertices];
    for (NodeId v = 0; v < boost::num_vertices(g); ++v) {
      const Eigen::Vector3d p = g[v].position + skeleton_shift;
      l->mVertices[v] = aiVector3D(static_cast<ai_real>(p.x()), static_cast<ai_real>(p.y()), static_cast<ai_real>(p.z()));
    }
    l->mNumFaces = static_cast<unsigned>(boost::num_edges(g));
    l->mFaces = new aiFace[l->mNumFaces];
    unsigned k = 0;
    for (auto [it, end] = boost::edges(g); it != end; ++it, ++k) {
      l->mFaces[k].mNumIndices = 2;
      l->mFaces[k].mIndices = new unsigned[2]{static_cast<unsigned>(boost::source(*it, g)),
                                              static_cast<unsigned>(boost::target(*it, g))};
    }
  }
  return scene;
}

/// assimp's output kept in memory: every file an exporter opens for writing (the main file and side
/// files such as a .gltf's .bin) becomes a string, written to the disk by treeskel's own checked,
/// atomic writer afterwards (assimp's file streams do not report a full disk).
class MemoryFile : public Assimp::IOStream {
 public:
  explicit MemoryFile(std::string& data) : data_(data) {}
  size_t Read(void*, size_t, size_t) override { return 0; }
  size_t Write(const void* buffer, size_t size, size_t count) override {
    const std::size_t bytes = size * count;
    if (at_ + bytes > data_.size()) data_.resize(at_ + bytes);
    std::memcpy(data_.data() + at_, buffer, bytes);
    at_ += bytes;
    return count;
  }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    const std::size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? at_ : data_.size();
    at_ = base + offset;  // past the end too: the GLB exporter writes its chunks first, its header last
    if (at_ > data_.size()) data_.resize(at_);
    return aiReturn_SUCCESS;
  }
  size_t Tell() const override { return at_; }
  size_t FileSize() const override { return data_.size(); }
  void Flush() override {}

 private:
  std::string& data_;
  std::size_t at_ = 0;
};

class MemoryFiles : public Assimp::IOSystem {
 public:
  explicit MemoryFiles(std::map<std::string, std::string>& files) : files_(files) {}
  bool Exists(const char* path) const override { return files_.count(path) > 0; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* path, const char* mode) override {
    if (std::strchr(mode, 'w') == nullptr) return nullptr;
    auto& data = files_[path];
    data.clear();
    return new MemoryFile(data);
  }
  void Close(Assimp::IOStream* file) override { delete file; }

 private:
  std::map<std::string, std::string>& files_;
};

/// Writes OBJ text with every coordinate in double precision (shortest exact decimal), the mesh's
/// vertices plus `shift`, and the skeleton's edges as lines.
void write_obj(const fs::path& path, const modeling::TreeMesh& mesh, const Eigen::Vector3d& shift,
               const Skeleton* skeleton, const Eigen::Vector3d& skeleton_shift) {
  write_atomically(path, [&](std::ostream& out) {
    std::string line;
    auto vertex = [&](const Eigen::Vector3d& p) {
      line = "v";
      for (int a = 0; a < 3; ++a) {
        line += ' ';
        detail::append_number(line, p[a]);
      }
      line += '\n';
      out << line;
    };
    out << "# treeskel tree model\no wood\n";
    for (auto v : mesh.vertices()) {
      const auto p = mesh.point(v);
      vertex(Eigen::Vector3d(p[0], p[1], p[2]) + shift);
    }
    for (auto f : mesh.faces()) {
      line = "f";
      for (auto v : mesh.fv_range(f)) line += ' ' + std::to_string(v.idx() + 1);
      line += '\n';
      out << line;
    }
    if (!skeleton) return;
    const auto& g = skeleton->graph;
    out << "o skeleton\n";
    for (NodeId v = 0; v < boost::num_vertices(g); ++v) vertex(g[v].position + skeleton_shift);
    const std::size_t base = mesh.n_vertices() + 1;
    for (auto [it, end] = boost::edges(g); it != end; ++it)
      out << "l " << base + boost::source(*it, g) << ' ' << base + boost::target(*it, g) << '\n';
  });
}

/// Readers built on assimp 5.2 (Debian's) skip a line end right after a binary PLY's header
/// (assimp issue 5341): when the first byte of the data, the lowest byte of the first vertex's x,
/// is '\n', '\r', '\f' or '\0', every value is read one byte off (one of the 72 synthetic
/// trees' models; a chance of about 1 in 64). A
/// vertex whose first byte is safe is moved to the front (the faces follow it): the same mesh.
void put_a_safe_vertex_first(aiMesh& m) {
  auto first_byte = [&](unsigned v) {
    unsigned char bytes[sizeof(ai_real)];
    std::memcpy(bytes, &m.mVertices[v].x, sizeof(ai_real));
    return bytes[0];  // PLY binary little-endian, as assimp writes it on this platform
  };
  auto unsafe = [&](unsigned v) {
    const unsigned char b = first_byte(v);
    return b == '\n' || b == '\r' || b == '\f' || b == '\0';
  };
  if (m.mNumVertices == 0 || !unsafe(0)) return;
  unsigned k = 1;
  while (k < m.mNumVertices && unsafe(k)) ++k;
  if (k == m.mNumVertices) return;  // every vertex is unsafe: nothing to choose
  std::swap(m.mVertices[0], m.mVertices[k]);
  if (m.mNormals) std::swap(m.mNormals[0], m.mNormals[k]);
  for (unsigned f = 0; f < m.mNumFaces; ++f)
    for (unsigned i = 0; i < m.mFaces[f].mNumIndices; ++i) {
      unsigned& v = m.mFaces[f].mIndices[i];
      v = v == 0 ? k : v == k ? 0 : v;
    }
}

/// Sets the translation of the root node of a glTF document (JSON) to `t`, in double precision
/// (assimp holds node transforms in 32-bit floats, which would round a georeferenced offset).
void set_root_translation(nlohmann::json& doc, const Eigen::Vector3d& t) {
  const std::size_t root = doc.at("scenes").at(doc.value("scene", 0)).at("nodes").at(0).get<std::size_t>();
  auto& node = doc.at("nodes").at(root);
  std::vector<double> m(16, 0.0);
  if (node.contains("matrix")) m = node["matrix"].get<std::vector<double>>();
  else m[0] = m[5] = m[10] = m[15] = 1.0;
  for (int a = 0; a < 3; ++a) m[static_cast<std::size_t>(12 + a)] = t[a];  // column-major: the last column
  node["matrix"] = m;
}

/// The same in a .gltf (JSON text) or .glb (binary container: header, JSON chunk, BIN chunk) file.
std::string with_root_translation(const std::string& data, bool binary, const Eigen::Vector3d& t,
                                  const fs::path& file) {
  if (!binary) {
    nlohmann::json doc = nlohmann::json::parse(data);
    set_root_translation(doc, t);
    return doc.dump();
  }
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, data.data() + at, 4);
    return v;
  };
  if (data.size() < 20 || data.compare(0, 4, "glTF") != 0 || data.compare(16, 4, "JSON") != 0 ||
      u32(12) > data.size() - 20)
    throw Error("cannot write " + file.string() + ": assimp wrote no GLB JSON chunk");
  const std::size_t json_length = u32(12);
  nlohmann::json doc = nlohmann::json::parse(data.substr(20, json_length));
  set_root_translation(doc, t);
  std::string json = doc.dump();
  json.append((4 - json.size() % 4) % 4, ' ');  // chunks are 4-byte aligned, JSON padded with spaces
  const std::string rest = data.substr(20 + json_length);
  std::string out;
  auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  out = data.substr(0, 8);
  put(static_cast<std::uint32_t>(12 + 8 + json.size() + rest.size()));
  put(static_cast<std::uint32_t>(json.size()));
  out += "JSON";
  out += json;
  out += rest;
  return out;
}

}  // namespace

bool is_mesh_extension(const fs::path& path) { return formats().count(extension_of(path)) > 0; }

bool holds_local_floats(const fs::path& path) {
  const std::string ext = extension_of(path);
  return ext == "gltf" || ext == "glb";
}

MeshPlacement write_mesh(const fs::path& path, const modeling::TreeMesh& mesh, const Eigen::Vector3d& offset,
                         const Skeleton* skeleton) {
  MeshFrame frame;
  frame.offset = offset;
  return write_mesh(path, mesh, frame, skeleton);
}

MeshPlacement write_mesh(const fs::path& path, const modeling::TreeMesh& mesh, const MeshFrame& frame,
                         const Skeleton* skeleton) {
  const std::string ext = extension_of(path);
  const auto format = formats().find(ext);
  if (format == formats().end())
    throw OptionError(path.string() + ": unknown mesh extension '." + ext + "'; use .obj, .gltf, .glb, .ply or .stl");
  if (mesh.n_faces() == 0) throw InputError("the mesh is empty: nothing to write to " + path.string());
  if (!frame.offset.allFinite() || !frame.up.allFinite() || frame.up.norm() == 0.0)
    throw OptionError("cannot write " + path.string() + ": the offset and the up axis must be finite, the up axis not zero");
  MeshPlacement placed;
  const bool gltf = ext == "gltf" || ext == "glb";
  // The coordinates written are local + shift: the whole offset, or none of it.
  Eigen::Vector3d shift = frame.local ? Eigen::Vector3d::Zero() : frame.offset;
  if (frame.local) {
    placed.left_out = frame.offset;
    placed.note = "local coordinates, as asked";
  } else if (gltf) {
    shift.setZero();  // the offset goes into the root node instead
  } else if (ext == "ply" || ext == "stl") {
    Eigen::AlignedBox3d box;
    for (auto v : mesh.vertices()) {
      const auto p = mesh.point(v);
      box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
    }
    const double far = (box.min() + frame.offset).cwiseAbs().cwiseMax((box.max() + frame.offset).cwiseAbs()).maxCoeff();
    // A 32-bit float rounds by up to 2^-24 of the value.
    if (far * std::ldexp(1.0, -24) > 1e-5 * box.sizes().maxCoeff()) {
      shift.setZero();
      placed.left_out = frame.offset;
      placed.note = "local coordinates: 32-bit floats would round the input's frame by more than 1e-5 of the tree's size";
    }
  }
  const Eigen::Vector3d skeleton_shift = skeleton ? Eigen::Vector3d(skeleton->offset - frame.offset + shift) : shift;
  if (ext == "obj") {
    write_obj(path, mesh, shift, skeleton, skeleton_shift);
    return placed;
  }
  const Eigen::Matrix3d rotation = gltf ? y_up_rotation(frame.up) : Eigen::Matrix3d::Identity();
  placed.y_up_rotation = gltf && !rotation.isIdentity();
  const auto scene = make_scene(mesh, shift, skeleton, skeleton_shift, rotation);
  if (ext == "ply") put_a_safe_vertex_first(*scene->mMeshes[0]);
  // assimp names side files (the .bin of a .gltf) after the main file: all of them are exported into
  // memory, then written atomically beside the target, the main file last so that it never refers
  // to a side file not there yet.
  std::map<std::string, std::string> files;
  Assimp::Exporter exporter;
  exporter.SetIOHandler(new MemoryFiles(files));  // the exporter owns it
  const std::string main_name = path.filename().string();
  if (exporter.Export(scene.get(), format->second, main_name) != AI_SUCCESS || files.count(main_name) == 0)
    throw Error("cannot write " + path.string() + ": " + exporter.GetErrorString());
  if (gltf)
    files[main_name] = with_root_translation(files[main_name], ext == "glb",
                                             frame.local ? Eigen::Vector3d::Zero() : Eigen::Vector3d(rotation * frame.offset), path);
  const fs::path dir = folder_of(path);
  for (const auto& [name, data] : files)
    if (name != main_name)
      write_atomically(dir / fs::path(name).filename(), [&](std::ostream& out) { out.write(data.data(), std::streamsize(data.size())); });
  write_atomically(path, [&](std::ostream& out) {
    const std::string& data = files[main_name];
    out.write(data.data(), static_cast<std::streamsize>(data.size()));
  });
  return placed;
}

namespace {

/// Joins copies of a position (STL keeps one per face) by their exact coordinates, not by assimp's
/// JoinIdenticalVertices: that step (assimp 5.2) crashed on a valid binary PLY of ours.
class MeshBuilder {
 public:
  explicit MeshBuilder(const fs::path& path) : path_(path) {}
  modeling::TreeMesh::VertexHandle vertex(const Eigen::Vector3d& p) {
    auto [it, fresh] = at_.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, modeling::TreeMesh::VertexHandle());
    if (fresh) it->second = mesh_.add_vertex(modeling::TreeMesh::Point(p.x(), p.y(), p.z()));
    return it->second;
  }
  void face(modeling::TreeMesh::VertexHandle a, modeling::TreeMesh::VertexHandle b, modeling::TreeMesh::VertexHandle c,
            std::size_t number) {
    if (!mesh_.add_face(a, b, c).is_valid())
      throw InputError(path_.string() + ": face " + std::to_string(number) + " makes the mesh non-manifold");
  }
  modeling::TreeMesh take() { return std::move(mesh_); }

 private:
  fs::path path_;
  modeling::TreeMesh mesh_;
  std::map<std::array<double, 3>, modeling::TreeMesh::VertexHandle> at_;
};

/// An OBJ file's triangles (polygons as fans), its coordinates read as doubles: assimp reads them as
/// 32-bit floats, which at a georeferenced tree's UTM coordinates are centimetres apart and join
/// distinct vertices.
modeling::TreeMesh read_obj(const fs::path& path) {
  const std::string text = read_whole_file(path);
  MeshBuilder out(path);
  std::vector<Eigen::Vector3d> positions;
  std::vector<modeling::TreeMesh::VertexHandle> handles;
  std::size_t faces = 0, line_number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    auto bad = [&](const std::string& why) { return InputError(path.string() + ": line " + std::to_string(line_number) + ": " + why); };
    if (line.rfind("v ", 0) == 0) {
      const char* c = line.c_str() + 2;
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) {
        char* next = nullptr;
        p[k] = std::strtod(c, &next);
        if (next == c) throw bad("a vertex needs three numbers");
        c = next;
      }
      positions.push_back(p);
      handles.push_back(out.vertex(p));
    } else if (line.rfind("f ", 0) == 0) {
      std::vector<modeling::TreeMesh::VertexHandle> corners;
      const char* c = line.c_str() + 2;
      while (*c) {
        char* next = nullptr;
        const long index = std::strtol(c, &next, 10);
        if (next == c) break;
        const long at = index > 0 ? index - 1 : static_cast<long>(positions.size()) + index;
        if (index == 0 || at < 0 || at >= static_cast<long>(positions.size())) throw bad("a face names a vertex not given before it");
        corners.push_back(handles[static_cast<std::size_t>(at)]);
        c = next;
        while (*c && *c != ' ' && *c != '\t' && *c != '\r') ++c;  // /texture/normal
        while (*c == ' ' || *c == '\t' || *c == '\r') ++c;
      }
      if (corners.size() < 3) throw bad("a face needs three vertices");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) out.face(corners[0], corners[k], corners[k + 1], faces);
      ++faces;
    }
  }
  return out.take();
}

}  // namespace

modeling::TreeMesh read_mesh(const fs::path& path) {
  if (extension_of(path) == "obj") return read_obj(path);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  if (scene == nullptr || scene->mRootNode == nullptr) throw InputError(path.string() + ": " + importer.GetErrorString());
  // The nodes' transforms are applied in double precision to the positions as the file holds them:
  // assimp's own pre-transform rounds a georeferenced glTF's world coordinates to 32-bit floats,
  // centimetres apart, and joined distinct vertices.
  MeshBuilder out(path);
  std::function<void(const aiNode&, const Eigen::Matrix4d&)> visit = [&](const aiNode& node, const Eigen::Matrix4d& above) {
    Eigen::Matrix4d local;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) local(r, c) = node.mTransformation[static_cast<unsigned>(r)][static_cast<unsigned>(c)];
    const Eigen::Matrix4d to_world = above * local;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      const aiMesh* m = scene->mMeshes[node.mMeshes[i]];
      if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      std::vector<modeling::TreeMesh::VertexHandle> handles;
      for (unsigned v = 0; v < m->mNumVertices; ++v) {
        const aiVector3D& p = m->mVertices[v];
        const Eigen::Vector4d w = to_world * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
        handles.push_back(out.vertex(w.head<3>() / w.w()));
      }
      for (unsigned f = 0; f < m->mNumFaces; ++f) {
        const aiFace& face = m->mFaces[f];
        if (face.mNumIndices != 3) continue;
        out.face(handles[face.mIndices[0]], handles[face.mIndices[1]], handles[face.mIndices[2]], f);
      }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) visit(*node.mChildren[c], to_world);
  };
  visit(*scene->mRootNode, Eigen::Matrix4d::Identity());
  return out.take();
}

void write_qsm_csv(const fs::path& path, const modeling::TreeMeasurements& measurements) {
  write_atomically(path, [&](std::ostream& out) {
    out << "id,parent,branch,order,position_in_branch,start_x,start_y,start_z,axis_x,axis_y,axis_z,length,radius\n";
    std::string line;
    for (const auto& c : measurements.cylinders) {
      line.clear();
      line += std::to_string(c.id) + ',' + std::to_string(c.parent) + ',' + std::to_string(c.branch) + ',' +
              std::to_string(c.order) + ',' + std::to_string(c.position);
      for (double x : {c.start.x(), c.start.y(), c.start.z(), c.axis.x(), c.axis.y(), c.axis.z(), c.length, c.radius}) {
        line += ',';
        detail::append_number(line, x);
      }
      line += '\n';
      out << line;
    }
  });
}

}  // namespace treeskel::io
