#include "batch_plan.h"

#include "treeskel/error.h"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

namespace treeskel::cli {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool hidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return name.size() > 1 && name[0] == '.' && name != "..";
}

/// Whether a file found in a folder looks like a cloud of its kind: PLY and LAS by their first bytes,
/// text by a line among the first ones that starts with three numbers (a README.txt or LICENSE.txt
/// beside the clouds does not). An empty file is taken: converting it fails with a clear error.
bool looks_like_cloud(const fs::path& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  std::string head(8192, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.empty()) return true;  // an empty scan is an input that fails, and says so
  if (ext == "ply") return head.rfind("ply", 0) == 0;
  if (ext == "las" || ext == "laz") return head.rfind("LASF", 0) == 0;
  std::istringstream lines(head);
  std::string line;
  bool first = true;
  while (std::getline(lines, line)) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
    std::istringstream fields(line);
    std::vector<std::string> words;
    for (std::string field; fields >> field;) words.push_back(field);
    if (words.empty()) continue;
    int numbers = 0;
    for (const auto& w : words) {
      char* end = nullptr;
      std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end != '\0') break;
      if (++numbers == 3) return true;
    }
    // A header line must name x, y and z (as the reader asks); a table of other columns (a QSM's
    // cylinders, say) is not a cloud.
    if (first && numbers == 0) {
      int named = 0;
      for (auto w : words) {
        std::transform(w.begin(), w.end(), w.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        named += w == "x" || w == "y" || w == "z";
      }
      if (named < 3) return false;
    }
    first = false;
  }
  return false;
}

/// A file found, with the name its outputs get before clashes are settled.
struct Found {
  fs::path path;
  fs::path name;
  std::string error;
};

void search_folder(const fs::path& folder, const std::vector<std::string>& extensions, const fs::path& skip,
                   std::vector<Found>& out, std::vector<fs::path>* passed_over) {
  std::error_code ec;
  const fs::path skip_canonical = skip.empty() ? fs::path() : fs::weakly_canonical(skip, ec);
  fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
  if (ec) {
    out.push_back({folder, folder.filename(), "cannot read the folder: " + ec.message()});
    return;
  }
  for (; it != end; it.increment(ec)) {
    if (ec) break;
    const fs::path& p = it->path();
    if (hidden(p) || (!skip_canonical.empty() && it->is_directory(ec) && fs::weakly_canonical(p, ec) == skip_canonical)) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file(ec)) continue;
    const std::string ext = lower_extension(p);
    if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) continue;
    if (!looks_like_cloud(p, ext)) {
      if (passed_over) passed_over->push_back(p);
      continue;
    }
    fs::path name = p.lexically_relative(folder);
    name.replace_extension();
    out.push_back({p, name, ""});
  }
}

void add_argument(const std::string& argument, const std::vector<std::string>& extensions, const fs::path& skip,
                  std::vector<Found>& out, std::vector<fs::path>* passed_over) {
  std::error_code ec;
  const fs::path path(argument);
  if (fs::is_directory(path, ec)) {
    search_folder(path, extensions, skip, out, passed_over);
    return;
  }
  if (fs::exists(path, ec)) {
    out.push_back({path, path.stem(), ""});
    return;
  }
  if (argument.find_first_of("*?[") != std::string::npos) {
    glob_t matches{};
    const int status = ::glob(argument.c_str(), 0, nullptr, &matches);
    std::vector<std::string> found;
    if (status == 0)
      for (std::size_t i = 0; i < matches.gl_pathc; ++i) found.emplace_back(matches.gl_pathv[i]);
    ::globfree(&matches);
    if (found.empty()) {
      out.push_back({path, path.stem(), "no file matches this pattern"});
      return;
    }
    for (const auto& f : found) add_argument(f, extensions, skip, out, passed_over);
    return;
  }
  out.push_back({path, path.stem(), "no such file or folder"});
}

}  // namespace

std::vector<BatchInput> plan_inputs(const std::vector<std::string>& arguments, const std::vector<std::string>& extensions,
                                    const fs::path& skip, std::vector<fs::path>* passed_over) {
  std::vector<Found> found;
  for (const auto& a : arguments) add_argument(a, extensions, skip, found, passed_over);
  // Each file once (the same file named twice, or found through a folder and a pattern).
  std::set<fs::path> seen;
  std::vector<Found> unique;
  for (auto& f : found) {
    std::error_code ec;
    const fs::path key = f.error.empty() ? fs::weakly_canonical(f.path, ec) : f.path;
    if (seen.insert(key).second) unique.push_back(std::move(f));
  }
  std::stable_sort(unique.begin(), unique.end(), [](const Found& a, const Found& b) { return a.path < b.path; });
  // Names that clash take their extension; what still clashes is refused, naming who has the name.
  std::map<fs::path, int> count;
  for (const auto& f : unique)
    if (f.error.empty()) ++count[f.name];
  std::map<fs::path, fs::path> holder;
  std::vector<BatchInput> out;
  for (auto& f : unique) {
    BatchInput in{f.path, f.name, f.error};
    if (in.error.empty()) {
      if (count[in.name] > 1) in.name += "_" + lower_extension(in.path);
      const auto [it, fresh] = holder.emplace(in.name, in.path);
      if (!fresh)
        in.error = "its outputs would have the name " + in.name.string() + ", which " + it->second.string() +
                   " has (convert the two in separate batches, or pass their folder)";
    }
    out.push_back(std::move(in));
  }
  return out;
}

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  std::size_t index = 0, count = 0;
  bool ok = slash != std::string::npos && slash > 0 && slash + 1 < text.size();
  if (ok) {
    try {
      std::size_t used_i = 0, used_n = 0;
      const std::string i = text.substr(0, slash), n = text.substr(slash + 1);
      ok = i.find_first_not_of("0123456789") == std::string::npos && n.find_first_not_of("0123456789") == std::string::npos;
      if (ok) {
        index = std::stoul(i, &used_i);
        count = std::stoul(n, &used_n);
      }
    } catch (const std::exception&) {
      ok = false;
    }
  }
  if (!ok) throw OptionError("--shard " + text + ": expected I/N, the shard's number I (from 0) of N, e.g. 3/10");
  if (count == 0) throw OptionError("--shard " + text + ": the number of shards N must be at least 1");
  if (index >= count)
    throw OptionError("--shard " + text + ": the shard's number counts from 0 to N-1 (with a Slurm array --array=0-" +
                      std::to_string(count - 1) + ", pass $SLURM_ARRAY_TASK_ID/" + std::to_string(count) + ")");
  return {index, count};
}

std::vector<BatchInput> take_shard(const std::vector<BatchInput>& inputs, const Shard& shard) {
  std::vector<BatchInput> out;
  for (std::size_t i = shard.index; i < inputs.size(); i += shard.count) out.push_back(inputs[i]);
  return out;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

}  // namespace treeskel::cli
