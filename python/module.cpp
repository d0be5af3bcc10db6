// The Python package's native part: clouds, skeletons and meshes as numpy arrays, and the library's
// stages with the command line's options, given as keyword arguments (cell_points=3 for
// --cell-points 3, no_cpc=True for --no-cpc).
#include "batch_plan.h"
#include "model_warnings.h"
#include "model_options.h"
#include "skeleton_options.h"

#include "treeskel/error.h"
#include "treeskel/forest/ground.h"
#include "treeskel/forest/segment.h"
#include "treeskel/forest/wood.h"
#include "treeskel/forest/stems.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/output_set.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/pipeline.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace py = pybind11;

namespace treeskel::python {

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A cloud as the library holds it: local positions and the offset of the input's frame.
struct Cloud {
  PointCloud cloud;
  std::string source;  // the file it was read from, for messages ("" for an array)
};

/// A skeleton, the options it was made with (the up axis matters to the mesh file and the
/// measurements) and the cloud it stands for, when it was extracted from one.
struct PySkeleton {
  Skeleton skeleton;
  std::shared_ptr<const Cloud> cloud;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double cell_size = 0.0;  ///< the octree cell size it was extracted with (0: read from a file)
};

struct Mesh {
  modeling::TreeMesh mesh;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::shared_ptr<const PySkeleton> skeleton;  // for with_skeleton, and to sweep again for a file in other floats
  modeling::SweepOptions options;               // what it was swept with
  modeling::SweepStats stats;                   // what the sweep did (for the model's warnings)
};

/// The options of the command line named by `kwargs`, parsed by the command line's own parser: the same
/// names, defaults and checks. `function` names the caller in messages.
struct Options {
  cli::SkeletonSettings method;
  cli::ModelSettings model;
  std::vector<std::string> args;  ///< the keyword arguments as the command line's arguments
};

std::string flag_of(const std::string& key) {
  std::string name = key;
  for (char& c : name)
    if (c == '_') c = '-';
  return (name.size() == 1 ? "-" : "--") + name;
}

Options parse_options(const py::kwargs& kwargs, bool method, bool model, const std::string& function) {
  Options o;
  CLI::App app{function};
  if (method && model) cli::use_model_defaults(o.method);  // model(): the model's pruning
  if (method) cli::add_skeleton_options(app, o.method);
  if (model) cli::add_model_options(app, o.model);
  std::vector<std::string> args{function};
  for (const auto& [key_handle, value] : kwargs) {
    const std::string key = py::str(key_handle);
    const std::string flag = flag_of(key);
    const CLI::Option* option = app.get_option_no_throw(flag);
    if (!option) throw py::type_error(function + "() got an unexpected keyword argument '" + key + "'");
    if (option->get_expected_min() == 0) {
      if (!py::isinstance<py::bool_>(value))
        throw py::type_error(function + "(): " + key + " is a switch: pass True or False");
      if (value.cast<bool>()) args.push_back(flag);
      continue;
    }
    std::string text;
    if (py::isinstance<py::str>(value)) {
      text = value.cast<std::string>();
    } else if (py::isinstance<py::sequence>(value)) {  // root=(x, y, z)
      for (const auto& item : value.cast<py::sequence>()) text += (text.empty() ? "" : ",") + std::string(py::repr(item));
    } else {
      text = py::repr(value);  // floats as the shortest text that reads back the same
    }
    args.push_back(flag);
    args.push_back(text);
  }
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    throw py::value_error(function + "(): " + e.what());
  }
  if (method) cli::check_skeleton_settings(o.method);
  if (model) modeling::check_sweep_options(o.model.sweep);
  o.args.assign(args.begin() + 1, args.end());
  return o;
}

/// A cloud from an (N, 3) array (copied, moved to a local frame as the readers do), a file name or a
/// Cloud.
std::shared_ptr<const Cloud> cloud_from(const py::object& points) {
  if (py::isinstance<Cloud>(points)) return points.cast<std::shared_ptr<Cloud>>();
  if (py::isinstance<py::str>(points) || py::hasattr(points, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(points));
    auto c = std::make_shared<Cloud>();
    c->source = path;
    py::gil_scoped_release free;
    c->cloud = io::read_point_cloud(path);
    return c;
  }
  const Points a = Points::ensure(points);
  if (!a) throw py::value_error("points must be an (N, 3) array of numbers, a file name or a treeskel.Cloud");
  if (a.ndim() != 2 || a.shape(1) != 3) {
    std::ostringstream shape;
    for (py::ssize_t d = 0; d < a.ndim(); ++d) shape << (d ? ", " : "") << a.shape(d);
    throw py::value_error("points must be an (N, 3) array, one row x, y, z per point; got shape (" + shape.str() + ")");
  }
  auto c = std::make_shared<Cloud>();
  const auto r = a.unchecked<2>();
  c->cloud.positions.reserve(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    const Eigen::Vector3d p(r(i, 0), r(i, 1), r(i, 2));
    if (!p.allFinite())
      throw py::value_error("points: row " + std::to_string(i) + " is not finite (NaN or infinity): " + std::string(py::repr(py::make_tuple(p.x(), p.y(), p.z()))));
    c->cloud.positions.push_back(p);
  }
  recentre_offset(c->cloud);
  return c;
}

py::array_t<double> world_array(const std::vector<Eigen::Vector3d>& local, const Eigen::Vector3d& offset) {
  py::array_t<double> out({static_cast<py::ssize_t>(local.size()), py::ssize_t{3}});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < local.size(); ++i)
    for (int d = 0; d < 3; ++d) w(static_cast<py::ssize_t>(i), d) = local[i][d] + offset[d];
  return out;
}

py::object json_to_python(const nlohmann::ordered_json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

/// Writes through an output set: the file is whole or absent, and an existing one unchanged on failure.
template <class Write>
void save_whole(const std::filesystem::path& path, const std::string& what, Write write) {
  io::OutputSet outputs;
  const auto staged = outputs.stage(path, what);
  try {
    write(staged);
    outputs.commit();
  } catch (const Error& e) {
    throw Error(outputs.explain(e.what()));
  }
}

/// A UserWarning: `text` after the cloud's file name ("the points" for an array or no cloud).
void warn_user(const Cloud* cloud, const std::string& text) {
  const std::string message = (cloud && !cloud->source.empty() ? cloud->source : std::string("the points")) + ": " + text;
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) < 0) throw py::error_already_set();
}

PySkeleton extract(const py::object& points, const Options& o) {
  PySkeleton out;
  out.cloud = cloud_from(points);
  if (o.method.ground_aside) {  // the ground the tree stands on, set aside as `--set-ground-aside` does
    auto kept = std::make_shared<Cloud>(*out.cloud);
    std::size_t ground = 0;
    {
      py::gil_scoped_release free;
      ground = cli::set_ground_aside(o.method, kept->cloud, kept->source, true);
    }
    if (ground > 0) {
      out.cloud = std::move(kept);
      warn_user(out.cloud.get(), cli::ground_note(ground, "set_ground_aside=True"));
    }
  }
  if (cli::may_set_leaves_aside(o.method)) {  // the skeleton, the radii and the measurements of the wood alone
    auto wood = std::make_shared<Cloud>(*out.cloud);
    py::gil_scoped_release free;
    const cli::WoodSplit split =
        cli::keep_wood(o.method, wood->cloud, wood->source.empty() ? std::string("the points") : wood->source, true);
    if (split.run) out.cloud = std::move(wood);  // with wood_if_leafy, a cloud not leafy stays whole
  } else {
    std::string leafy;
    {
      py::gil_scoped_release free;
      leafy = cli::leafy_warning(out.cloud->cloud, "wood_only=True");
    }
    if (!leafy.empty()) warn_user(out.cloud.get(), leafy);
  }
  const SkeletonOptions options = cli::skeleton_options_for(o.method, out.cloud->cloud);
  out.up = options.root.up;
  {
    py::gil_scoped_release free;
    SkeletonStats stats;
    out.skeleton = out.cloud->source.empty() ? extract_skeleton(out.cloud->cloud, options, &stats)
                                             : cli::extract_skeleton_of(out.cloud->source, out.cloud->cloud, options, &stats);
    out.cell_size = stats.cell_size;
  }
  return out;
}

PySkeleton with_radii(const PySkeleton& in, const Options& o) {
  PySkeleton out = in;
  modeling::RadiusStats stats;
  {
    py::gil_scoped_release free;
    modeling::RadiusOptions radii = o.model.radii;
    radii.cell_size = in.cell_size;
    modeling::fit_radii(out.skeleton, out.cloud ? &out.cloud->cloud : nullptr, radii, &stats);
  }
  if (out.cloud)
    if (const std::string w = cli::bushes_left_out(stats.completion, out.cloud->cloud.size(), "complete_all", "wood_only=True");
        !w.empty())
      warn_user(out.cloud.get(), w);
  return out;
}

Mesh sweep(const std::shared_ptr<const PySkeleton>& s, const Options& o) {
  Mesh m;
  m.offset = s->skeleton.offset;
  m.up = s->up;
  m.skeleton = s;
  m.options = o.model.sweep;
  m.options.local_floats = o.model.local;
  py::gil_scoped_release free;
  m.mesh = modeling::sweep_mesh(s->skeleton, m.options, &m.stats);
  return m;
}

modeling::TreeMeasurements measure(const PySkeleton& s, const Options& o) {
  modeling::MeasureOptions mo;
  mo.up = s.up;
  mo.breast_height = o.model.breast_height;
  mo.dbh_from_points = !o.model.dbh_from_model;
  py::gil_scoped_release free;
  return modeling::measure_tree(s.skeleton, s.cloud ? &s.cloud->cloud : nullptr, mo);
}

py::object measurements(const PySkeleton& s, const Options& o) { return json_to_python(cli::measurements_json(measure(s, o))); }

/// What the front ends' warnings need of a mesh: its check and how much of the skeleton it holds.
struct MeshFacts {
  modeling::MeshCheck check;
  modeling::SkeletonCoverage coverage;
};

MeshFacts facts_of(const PySkeleton& s, const Mesh& mesh) {
  py::gil_scoped_release free;
  return {cli::check_swept(mesh.mesh, mesh.stats, mesh.options.repair), modeling::skeleton_coverage(s.skeleton, mesh.mesh)};
}

/// What `treeskel model` warns about a mesh alone (limbs apart or left out, crossings in floats,
/// little of the skeleton or of its wood inside), as Python UserWarnings (one each): `tree_mesh` has no measurements.
void warn_about_mesh(const PySkeleton& s, const Mesh& mesh) {
  const MeshFacts f = facts_of(s, mesh);
  for (const auto& w : cli::mesh_warnings(f.check, mesh.stats, f.coverage, mesh.options.unite_apart))
    warn_user(s.cloud.get(), w);
}

/// What `treeskel model` warns about for this model, as Python UserWarnings (one each).
void warn_about_model(const PySkeleton& s, const Mesh& mesh, const modeling::TreeMeasurements& m, const Options& o) {
  const MeshFacts f = facts_of(s, mesh);
  for (const auto& w : cli::model_warnings({s.skeleton, s.up, m, o.model.breast_height, f.check, mesh.stats, f.coverage,
                                            mesh.options.unite_apart}))
    warn_user(s.cloud.get(), w);
}

}  // namespace

}  // namespace treeskel::python

PYBIND11_MODULE(_treeskel, m) {
  using namespace treeskel;
  using namespace treeskel::python;
  m.doc() = "treeskel: curve skeletons and tree models from raw point clouds (the native part; see treeskel)";
  m.attr("__version__") = TREESKEL_VERSION;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const OptionError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  py::class_<Cloud, std::shared_ptr<Cloud>>(m, "Cloud", "A point cloud: its points in the input's frame, computed in a local one")
      .def_property_readonly("points", [](const Cloud& c) { return world_array(c.cloud.positions, c.cloud.offset); },
                             "(N, 3) float64 array, in the input's frame")
      .def_property_readonly("offset", [](const Cloud& c) { return std::vector<double>{c.cloud.offset.x(), c.cloud.offset.y(), c.cloud.offset.z()}; },
                             "The local frame's origin in the input's frame")
      .def("__len__", [](const Cloud& c) { return c.cloud.size(); })
      .def("save", [](const Cloud& c, const std::filesystem::path& path) {
        save_whole(path, "path", [&](const std::filesystem::path& to) { io::write_point_cloud(to, c.cloud); });
      }, py::arg("path"), "Writes the cloud (.xyz .txt .asc .csv .pts .ply .las), whole or not at all")
      .def("__repr__", [](const Cloud& c) { return "<treeskel.Cloud of " + std::to_string(c.cloud.size()) + " points>"; });

  py::class_<PySkeleton, std::shared_ptr<PySkeleton>>(m, "Skeleton", "A curve skeleton: a tree of nodes with positions and radii")
      .def_property_readonly("positions", [](const PySkeleton& s) {
        std::vector<Eigen::Vector3d> p(s.skeleton.node_count());
        for (NodeId v = 0; v < p.size(); ++v) p[v] = s.skeleton[v].position;
        return world_array(p, s.skeleton.offset);
      }, "(M, 3) float64 array of node positions, in the input's frame")
      .def_property_readonly("radii", [](const PySkeleton& s) {
        py::array_t<double> r(static_cast<py::ssize_t>(s.skeleton.node_count()));
        auto w = r.mutable_unchecked<1>();
        for (NodeId v = 0; v < s.skeleton.node_count(); ++v) w(static_cast<py::ssize_t>(v)) = s.skeleton[v].radius;
        return r;
      }, "(M,) float64 array of node radii (0 where none was measured before fit_radii)")
      .def_property_readonly("edges", [](const PySkeleton& s) {
        py::array_t<std::int64_t> e({static_cast<py::ssize_t>(s.skeleton.edge_count()), py::ssize_t{2}});
        auto w = e.mutable_unchecked<2>();
        py::ssize_t i = 0;
        for (auto [it, end] = boost::edges(s.skeleton.graph); it != end; ++it, ++i) {
          w(i, 0) = static_cast<std::int64_t>(boost::source(*it, s.skeleton.graph));
          w(i, 1) = static_cast<std::int64_t>(boost::target(*it, s.skeleton.graph));
        }
        return e;
      }, "(E, 2) int64 array of node pairs")
      .def_property_readonly("root", [](const PySkeleton& s) { return s.skeleton.root; }, "The root node (the base of the trunk)")
      .def_property_readonly("labels", [](const PySkeleton& s) -> py::object {
        if (!s.cloud) return py::none();
        py::array_t<std::int64_t> l(static_cast<py::ssize_t>(s.cloud->cloud.size()));
        auto w = l.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < l.shape(0); ++i) w(i) = -1;
        for (NodeId v = 0; v < s.skeleton.node_count(); ++v)
          for (std::uint32_t p : s.skeleton[v].points) w(p) = static_cast<std::int64_t>(v);
        return l;
      }, "(N,) int64 array: the node each input point belongs to, -1 for points left out as noise (None for a skeleton read from a file)")
      .def_property_readonly("left_out", [](const PySkeleton& s) {
        py::dict d;
        d["small_clusters"] = s.skeleton.left_out.small_clusters;
        d["far_parts"] = s.skeleton.left_out.far_parts;
        d["outliers"] = s.skeleton.left_out.outliers;
        d["total"] = s.skeleton.left_out.total();
        return d;
      }, "How many points were left out, by reason")
      .def_property_readonly("cloud", [](const PySkeleton& s) -> py::object {
        return s.cloud ? py::cast(std::const_pointer_cast<Cloud>(s.cloud)) : py::none();
      }, "The cloud it was extracted from (None for a skeleton read from a file)")
      .def("__len__", [](const PySkeleton& s) { return s.skeleton.node_count(); })
      .def("save", [](const PySkeleton& s, const std::filesystem::path& path) {
        cli::require_skeleton_extension(path.string());
        save_whole(path, "path", [&](const std::filesystem::path& to) { io::write_skeleton(to, s.skeleton); });
      }, py::arg("path"), "Writes the skeleton (.ply .obj .json), whole or not at all")
      .def("__repr__", [](const PySkeleton& s) {
        return "<treeskel.Skeleton of " + std::to_string(s.skeleton.node_count()) + " nodes, " +
               std::to_string(count_branch_points(s.skeleton.graph)) + " branch points>";
      });

  py::class_<Mesh>(m, "Mesh", "One closed mesh of the wood")
      .def_property_readonly("vertices", [](const Mesh& t) {
        std::vector<Eigen::Vector3d> p;
        p.reserve(t.mesh.n_vertices());
        for (auto v : t.mesh.vertices()) {
          const auto& q = t.mesh.point(v);
          p.emplace_back(q[0], q[1], q[2]);
        }
        return world_array(p, t.offset);
      }, "(V, 3) float64 array, in the input's frame")
      .def_property_readonly("faces", [](const Mesh& t) {
        py::array_t<std::int64_t> f({static_cast<py::ssize_t>(t.mesh.n_faces()), py::ssize_t{3}});
        auto w = f.mutable_unchecked<2>();
        py::ssize_t i = 0;
        for (auto face : t.mesh.faces()) {
          int k = 0;
          for (auto v : t.mesh.fv_range(face)) w(i, k++) = v.idx();
          ++i;
        }
        return f;
      }, "(F, 3) int64 array of vertex indices, counter-clockwise seen from outside")
      .def("check", [](const Mesh& t) {
        modeling::MeshCheck c;
        {
          py::gil_scoped_release free;
          c = modeling::check_mesh(t.mesh);
        }
        py::dict d;
        d["vertices"] = c.vertices;
        d["triangles"] = c.faces;
        d["closed"] = c.boundary_edges == 0;
        d["manifold"] = c.non_manifold_vertices == 0;
        d["components"] = c.components;
        d["self_intersections"] = c.self_intersections;
        d["volume"] = c.volume;
        d["area"] = c.area;
        d["ok"] = c.ok();
        return d;
      }, "The mesh's checks: closed, manifold, components, self-intersections (CGAL), volume, area")
      .def("save", [](const Mesh& t, const std::filesystem::path& path, bool local, bool with_skeleton) {
        if (!io::is_mesh_extension(path))
          throw OptionError(path.string() + ": unknown mesh extension '." + io::extension_of(path) + "'; use .obj, .gltf, .glb, .ply or .stl");
        io::MeshFrame frame;
        frame.offset = t.offset;
        frame.up = t.up;
        frame.local = local;
        py::gil_scoped_release free;
        // The mesh was rounded to, and checked in, the floats of one frame; a file that holds the
        // other's gets the mesh swept again in those, as `treeskel model` would have swept it.
        const bool local_floats = local || io::holds_local_floats(path);
        modeling::TreeMesh again;
        if (local_floats != t.options.local_floats && !t.offset.isZero() && t.skeleton) {
          modeling::SweepOptions options = t.options;
          options.local_floats = local_floats;
          again = modeling::sweep_mesh(t.skeleton->skeleton, options);
        }
        const modeling::TreeMesh& mesh = again.n_faces() > 0 ? again : t.mesh;
        save_whole(path, "path", [&](const std::filesystem::path& to) {
          io::write_mesh(to, mesh, frame, with_skeleton && t.skeleton ? &t.skeleton->skeleton : nullptr);
        });
      }, py::arg("path"), py::arg("local") = false, py::arg("with_skeleton") = false,
         "Writes the mesh (.glb .gltf .obj .ply .stl) as `treeskel model` does, whole or not at all")
      .def("__repr__", [](const Mesh& t) { return "<treeskel.Mesh of " + std::to_string(t.mesh.n_faces()) + " triangles>"; });

  m.def("read_cloud", [](const std::filesystem::path& path) {
    auto c = std::make_shared<Cloud>();
    c->source = path.string();
    py::gil_scoped_release free;
    c->cloud = io::read_point_cloud(path);
    return c;
  }, py::arg("path"), "Reads a cloud (.xyz .txt .asc .csv .pts .ply .las .laz)");

  m.def("read_skeleton", [](const std::filesystem::path& path, const std::string& up) {
    auto s = std::make_shared<PySkeleton>();
    s->up = cli::parse_up(up);
    py::gil_scoped_release free;
    s->skeleton = io::read_skeleton(path);
    recentre_offset(s->skeleton);
    return s;
  }, py::arg("path"), py::arg("up") = "z", "Reads a skeleton (.json, or .ply with edges) written by treeskel");

  m.def("extract_skeleton", [](const py::object& points, const py::kwargs& kwargs) {
    return std::make_shared<PySkeleton>(extract(points, parse_options(kwargs, true, false, "extract_skeleton")));
  }, py::arg("points"),
        "The curve skeleton of a tree. `points`: an (N, 3) array, a file name or a Cloud; keyword "
        "arguments: the options of `treeskel skeletonize` (up='y', cell_points=3, no_cpc=True, ...)");

  m.def("fit_radii", [](const std::shared_ptr<PySkeleton>& s, const py::kwargs& kwargs) {
    const Options o = parse_options(kwargs, false, true, "fit_radii");
    return std::make_shared<PySkeleton>(with_radii(*s, o));
  }, py::arg("skeleton"),
        "A copy of the skeleton with radii by the pipe model, fitted to its cloud's points where it has "
        "one; keyword arguments: exponent, tip_weight, fit_points, complete (grow branches through the "
        "points the fitted tubes pass by, as `treeskel model --complete`), complete_all (the tufts and bushes "
        "too, as `--complete-all`), stem_share_bound (at the stem's "
        "forks no branch takes more than that many times its pipe-model share; 4 by default, 0 for none, "
        "as `treeskel model --stem-share-bound`), stub_length (tips shorter than that many radii of the branch "
        "they leave carry their own length only; 5 by default, 0 off, as `treeskel model --stub-length`), "
        "stiffness (each limb's path smoothed over that many times "
        "its radius; 2 by default, 0 keeps the skeleton's path, as `treeskel model --stiffness`)");

  m.def("tree_mesh", [](const std::shared_ptr<PySkeleton>& s, const py::kwargs& kwargs) {
    const Options o = parse_options(kwargs, false, true, "tree_mesh");
    Mesh mesh = sweep(s, o);
    warn_about_mesh(*s, mesh);
    return mesh;
  }, py::arg("skeleton"),
        "One closed mesh of a skeleton with radii (fit_radii first); keyword arguments: segments, "
        "min_segments, min_radius, no_unite, no_repair. What `treeskel model` warns about the mesh (limbs "
        "apart or left out, little of the skeleton or of its wood inside it) comes as UserWarnings");

  m.def("measure", [](const std::shared_ptr<PySkeleton>& s, const py::kwargs& kwargs) {
    const Options o = parse_options(kwargs, false, true, "measure");
    return measurements(*s, o);
  }, py::arg("skeleton"),
        "Height, DBH, volume, length, branches by order of a skeleton with radii, as `model --report` "
        "gives them; keyword arguments: breast_height, dbh_from_model");

  // For treeskel.dask: the options as the command's arguments (checked here, before any task runs),
  // the inputs as `treeskel batch` finds and names them, and where the command is.
  m.def("_command_args", [](bool with_model, const py::kwargs& kwargs) {
    return parse_options(kwargs, true, with_model, with_model ? "model" : "skeletonize").args;
  }, py::arg("with_model"));
  m.def("_plan_inputs", [](const std::vector<std::string>& arguments, const std::string& skip) {
    std::vector<std::filesystem::path> passed_over;
    const auto inputs = cli::plan_inputs(arguments, io::point_cloud_extensions(), skip, &passed_over);
    py::list out;
    for (const auto& in : inputs) out.append(py::make_tuple(in.path.string(), in.name.string(), in.error));
    py::list over;
    for (const auto& p : passed_over) over.append(p.string());
    return py::make_tuple(out, over);
  }, py::arg("arguments"), py::arg("skip") = "");
  m.attr("_built_executable") = TREESKEL_BUILT_EXE;
  m.attr("_built_package") = TREESKEL_BUILT_PACKAGE;
  m.attr("_installed_executable") = TREESKEL_INSTALLED_EXE;

  m.def("separate_wood", [](const py::object& points, const std::string& up) {
    const std::shared_ptr<const Cloud> c = cloud_from(points);
    forest::WoodOptions options;
    options.up = cli::parse_up(up);
    forest::WoodLeaf w;
    {
      py::gil_scoped_release free;
      w = forest::separate_wood(c->cloud, options);
    }
    py::array_t<bool> wood(static_cast<py::ssize_t>(w.is_wood.size()));
    py::array_t<float> score(static_cast<py::ssize_t>(w.score.size()));
    for (std::size_t p = 0; p < w.is_wood.size(); ++p) {
      wood.mutable_at(p) = w.is_wood[p] != 0;
      score.mutable_at(p) = w.score[p];
    }
    return py::make_tuple(wood, score);
  }, py::arg("points"), py::arg("up") = "z",
        "wood, score = separate_wood(points, up='z'): per point, whether it looks like wood (a bool array) and its "
        "score (wood above -0.4, and the few points that join cut-off wood back), as `wood_only=True` and `--wood-only` keep it. `points`: an (N, 3) array, a "
        "file name or a Cloud; `up`: the axis the tree grows along (x, y, z or a vector such as '0,0,1'): in a cloud in leaf, "
        "the ways from the tree's base through each point count too");

  m.def("segment_plot", [](const py::object& points, double voxel, double max_gap, std::pair<double, double> stem_slice,
                           double ground_cell, double ground_tolerance) {
    const std::shared_ptr<const Cloud> c = cloud_from(points);
    forest::GroundOptions go;
    go.cell = ground_cell;
    go.tolerance = ground_tolerance;
    forest::StemOptions so;
    so.slice_bottom = stem_slice.first;
    so.slice_top = stem_slice.second;
    forest::SegmentOptions seg_options;
    seg_options.voxel = voxel;
    seg_options.max_gap = max_gap;
    forest::Ground ground;
    std::vector<forest::Stem> stems;
    forest::Segmentation seg;
    std::vector<forest::TreeShape> shapes;
    {
      py::gil_scoped_release free;
      const bool classified = std::count(c->cloud.classes.begin(), c->cloud.classes.end(), std::uint8_t{2}) > 0;
      ground = forest::classify_ground(c->cloud, go, classified ? &c->cloud.classes : nullptr);
      stems = forest::find_stems(c->cloud, ground, so);
      seg = forest::segment_trees(c->cloud, ground, stems, so, seg_options);
      shapes = forest::describe_trees(c->cloud, stems, seg, so);
    }
    const std::size_t n = c->cloud.size();
    py::array_t<std::uint32_t> tree(static_cast<py::ssize_t>(n));
    py::array_t<bool> is_ground(static_cast<py::ssize_t>(n));
    py::array_t<float> height(static_cast<py::ssize_t>(n));
    for (std::size_t p = 0; p < n; ++p) {
      tree.mutable_at(p) = seg.tree[p];
      is_ground.mutable_at(p) = ground.is_ground[p] && seg.tree[p] == 0;
      height.mutable_at(p) = ground.height[p];
    }
    py::list trees;
    for (std::size_t t = 0; t < stems.size(); ++t) {
      py::dict d;
      d["id"] = t + 1;
      d["x"] = stems[t].centre.x() + c->cloud.offset.x();
      d["y"] = stems[t].centre.y() + c->cloud.offset.y();
      d["ground_z"] = stems[t].ground + c->cloud.offset.z();
      d["stem_dbh"] = 2 * stems[t].radius;
      d["points"] = shapes[t].points;
      d["height"] = shapes[t].height;
      d["crown_base"] = shapes[t].crown_base;
      trees.append(d);
    }
    py::dict out;
    out["tree"] = tree;
    out["ground"] = is_ground;
    out["height"] = height;
    out["trees"] = trees;
    return out;
  }, py::arg("points"), py::arg("voxel") = forest::SegmentOptions{}.voxel, py::arg("max_gap") = forest::SegmentOptions{}.max_gap,
     py::arg("stem_slice") = std::make_pair(forest::StemOptions{}.slice_bottom, forest::StemOptions{}.slice_top),
     py::arg("ground_cell") = forest::GroundOptions{}.cell, py::arg("ground_tolerance") = forest::GroundOptions{}.tolerance,
        "The trees of a plot scan, as `treeskel plot --segment-only` finds them: a dict with 'tree' (per "
        "point: 1 + the tree's index, 0 for none), 'ground' (per point: ground, and in no tree), 'height' (per "
        "point: above the ground) and 'trees' (per tree: id, x, y and ground_z of its stem in the input's frame, "
        "stem_dbh, points, height, crown_base). `points`: an (N, 3) array, a file name or a Cloud; a LAS "
        "file's ground class is its ground");

  m.def("model", [](const py::object& points, const py::kwargs& kwargs) {
    // The method's and the model's options together, as `treeskel model` takes them.
    const Options o = parse_options(kwargs, true, true, "model");
    auto s = std::make_shared<PySkeleton>(with_radii(extract(points, o), o));
    Mesh mesh = sweep(s, o);
    const modeling::TreeMeasurements m = measure(*s, o);
    warn_about_model(*s, mesh, m, o);
    return py::make_tuple(s, std::move(mesh), json_to_python(cli::measurements_json(m)));
  }, py::arg("points"),
        "skeleton, mesh, measurements = model(points, **options): what `treeskel model` does, with its options; what it "
        "warns about (limbs apart, little of the skeleton in the mesh, an unlikely height or DBH, a leafy cloud) comes as "
        "UserWarnings");
}
