// LAZ: decompressed by laz-perf (the LAZ library PDAL uses, built to WebAssembly and run by Node.js;
// tools/laz_to_las.js) into a private temporary LAS file, which the LAS reader then reads. Debian has
// no LAZ library (no LASzip, no PDAL); laz-perf comes from the npm registry, as the glTF validator does.
#include "formats.h"
#include "input_file.h"

#include "treeskel/error.h"
#include "treeskel/io/run_program.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

namespace treeskel::io::detail {

namespace fs = std::filesystem;

namespace {

/// The decoder script: $TREESKEL_LAZ_TOOL, else the one in the source tree's tools/.
fs::path laz_tool() {
  if (const char* tool = std::getenv("TREESKEL_LAZ_TOOL"); tool && *tool) return tool;
  return fs::path(TREESKEL_TOOLS_DIR) / "laz_to_las.js";
}

/// A private temporary folder, removed with what it holds.
struct TempFolder {
  fs::path path;
  TempFolder() {
    std::string name = (fs::temp_directory_path() / "treeskel-laz-XXXXXX").string();
    if (!::mkdtemp(name.data())) throw Error("cannot make a temporary folder to decompress LAZ: " + std::string(std::strerror(errno)));
    path = name;
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

PointCloud read_laz(const fs::path& path, std::string_view head, const std::string& name) {
  // An uncompressed file named .laz is read as the LAS it is.
  if (head.size() >= 227 && head.compare(0, 4, "LASF") == 0 && !(static_cast<unsigned char>(head[104]) & 0xC0))
    return read_las(head, name);
  if (head.size() < 4 || head.compare(0, 4, "LASF") != 0)
    throw InputError(name + ": not a LAZ file (it does not start with 'LASF')");
  if (head.size() < 227)
    throw InputError(name + ": truncated: " + std::to_string(head.size()) + " bytes, shorter than a LAS header (227)");
  const fs::path tool = laz_tool();
  const fs::path module = tool.parent_path() / "node_modules" / "laz-perf" / "package.json";
  if (!fs::exists(tool) || (!std::getenv("TREESKEL_LAZ_TOOL") && !fs::exists(module)))
    throw InputError(name + ": reading LAZ needs Node.js and laz-perf in " + tool.parent_path().string() +
                     " (scripts/setup.sh installs both), or decompress it first with 'laszip' or 'pdal translate'");
  const TempFolder temp;
  const fs::path las = temp.path / "decompressed.las", log = temp.path / "errors";
  const ProgramResult run = run_program({"node", tool.string(), fs::absolute(path).string(), las.string()}, log);
  if (!run.started)
    throw InputError(name + ": reading LAZ needs Node.js ('node' could not be started: " + run.error +
                     "; apt-get install nodejs), or decompress it first with 'laszip' or 'pdal translate'");
  if (!run.ok()) {
    std::string why = last_line_of(log);
    if (why.empty()) why = run.signal > 0 ? "the decoder ended by signal " + std::to_string(run.signal) : "the decoder failed";
    throw InputError(name + ": " + why);
  }
  const InputFile decoded(las);
  return read_las(decoded.bytes(), name);
}

}  // namespace treeskel::io::detail
