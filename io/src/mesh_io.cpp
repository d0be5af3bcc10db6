#include "treeskel/io/mesh_io.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "formats.h"

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <ostream>
#include <system_error>
#include <unistd.h>

namespace treeskel::io {

namespace fs = std::filesystem;

namespace {

const std::map<std::string, std::string>& formats() {
  static const std::map<std::string, std::string> ids = {
      {"obj", "objnomtl"}, {"gltf", "gltf2"}, {"glb", "glb2"}, {"ply", "plyb"}, {"stl", "stlb"}};
  return ids;
}

std::unique_ptr<aiScene> make_scene(const modeling::TreeMesh& mesh, const Eigen::Vector3d& offset,
                                    const Skeleton* skeleton) {
  auto scene = std::make_unique<aiScene>();
  const unsigned mesh_count = skeleton ? 2u : 1u;
  scene->mRootNode = new aiNode("tree");
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
    m->mVertices[i] = aiVector3D(static_cast<ai_real>(p[0] + offset.x()), static_cast<ai_real>(p[1] + offset.y()),
                                 static_cast<ai_real>(p[2] + offset.z()));
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
      const Eigen::Vector3d p = g[v].position + skeleton->offset;
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

/// A folder beside `target` that is removed with whatever is left in it.
struct TempDir {
  fs::path path;
  explicit TempDir(const fs::path& target) {
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::string pattern = (dir / ("." + target.filename().string() + ".XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw Error("cannot write " + target.string() + ": cannot create a temporary folder in " + dir.string());
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

bool is_mesh_extension(const fs::path& path) { return formats().count(extension_of(path)) > 0; }

void write_mesh(const fs::path& path, const modeling::TreeMesh& mesh, const Eigen::Vector3d& offset,
                const Skeleton* skeleton) {
  const std::string ext = extension_of(path);
  const auto format = formats().find(ext);
  if (format == formats().end())
    throw OptionError(path.string() + ": unknown mesh extension '." + ext + "'; use .obj, .gltf, .glb, .ply or .stl");
  if (mesh.n_faces() == 0) throw InputError("the mesh is empty: nothing to write to " + path.string());
  const auto scene = make_scene(mesh, offset, skeleton);
  // assimp writes to a file name of its own choosing for side files (.bin of .gltf), so the export
  // goes into a private folder first and its files are moved beside the target when all is written.
  TempDir temp(path);
  Assimp::Exporter exporter;
  const fs::path staged = temp.path / path.filename();
  if (exporter.Export(scene.get(), format->second, staged.string()) != AI_SUCCESS)
    throw Error("cannot write " + path.string() + ": " + exporter.GetErrorString());
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  // The main file last, so that it never refers to a side file not there yet.
  for (const auto& entry : fs::directory_iterator(temp.path))
    if (entry.path().filename() != path.filename()) fs::rename(entry.path(), dir / entry.path().filename());
  fs::rename(staged, path);
}

modeling::TreeMesh read_mesh(const fs::path& path) {
  Assimp::Importer importer;
  // Normals (per face in STL) would keep copies of a position apart: drop them, then join.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TEXCOORDS | aiComponent_COLORS);
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_RemoveComponent | aiProcess_JoinIdenticalVertices);
  if (scene == nullptr) throw InputError(path.string() + ": " + importer.GetErrorString());
  modeling::TreeMesh mesh;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh* m = scene->mMeshes[i];
    if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    std::vector<modeling::TreeMesh::VertexHandle> handles;
    for (unsigned v = 0; v < m->mNumVertices; ++v)
      handles.push_back(mesh.add_vertex(modeling::TreeMesh::Point(m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z)));
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;
      if (!mesh.add_face(handles[face.mIndices[0]], handles[face.mIndices[1]], handles[face.mIndices[2]]).is_valid())
        throw InputError(path.string() + ": face " + std::to_string(f) + " makes the mesh non-manifold");
    }
  }
  return mesh;
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
