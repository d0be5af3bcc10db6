// treeskel batch INPUT... -o OUTDIR: many trees, each converted by a treeskel process of its own (so a
// tree that fails, crashes or runs out of memory fails alone), N at a time, one summary row per tree.
#include "batch.h"
#include "batch_plan.h"
#include "commands.h"
#include "model_options.h"
#include "report.h"
#include "skeleton_options.h"
#include "view_options.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/view/html.h"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

extern char** environ;

namespace treeskel::cli {

namespace fs = std::filesystem;

namespace {

/// How often, at most, the summary files are rewritten while the batch runs (so that a batch killed
/// outright leaves a summary of nearly all it did).
constexpr double kSummaryInterval = 5.0;

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

/// The command line's options in `options` that were given, as arguments for the tree's command.
void append_given(const std::vector<const CLI::Option*>& options, std::vector<std::string>& args) {
  for (const CLI::Option* o : options) {
    if (o->count() == 0) continue;
    if (o->get_expected_min() == 0) {
      args.push_back(o->get_name());
      continue;
    }
    for (const auto& value : o->results()) {
      args.push_back(o->get_name());
      args.push_back(value);
    }
  }
}

fs::path output_path(const BatchSettings& s, const BatchInput& in, const std::string& suffix) {
  fs::path p = fs::path(s.out_dir) / in.name;
  p += suffix;
  return p;
}

/// The tree's outputs, its report last.
std::vector<fs::path> outputs_of(const BatchSettings& s, const BatchInput& in) {
  std::vector<fs::path> out;
  if (!s.model.empty()) out.push_back(output_path(s, in, s.model_suffix + "." + s.model));
  if (!s.skeleton.empty()) out.push_back(output_path(s, in, "_skeleton." + s.skeleton));
  if (s.html) out.push_back(output_path(s, in, ".html"));
  if (s.preview) out.push_back(output_path(s, in, ".png"));
  if (may_set_leaves_aside(s.method)) out.push_back(output_path(s, in, "_leaves.ply"));
  out.push_back(output_path(s, in, "_report.json"));
  return out;
}

std::vector<std::string> command_for(const BatchSettings& s, const BatchRow& row, unsigned threads) {
  std::vector<std::string> args{"treeskel", "--threads", std::to_string(threads)};
  if (!s.model.empty()) {
    args.insert(args.end(), {"model", row.input.path.string(), "-o", row.outputs[0].string()});
    if (!s.skeleton.empty()) args.insert(args.end(), {"--skeleton", row.outputs[1].string()});
  } else {
    args.insert(args.end(), {"skeletonize", row.input.path.string(), "-o", row.outputs[0].string()});
  }
  if (s.html) args.insert(args.end(), {"--html", output_path(s, row.input, ".html").string()});
  if (s.preview) args.insert(args.end(), {"--preview", output_path(s, row.input, ".png").string()});
  if (may_set_leaves_aside(s.method)) args.insert(args.end(), {"--leaves", output_path(s, row.input, "_leaves.ply").string()});
  args.insert(args.end(), {"--report", row.report.string(), "-q"});
  args.insert(args.end(), s.defaults.begin(), s.defaults.end());
  append_given(s.passed, args);
  return args;
}

/// A tree's process's stderr: a file with no name in the temporary folder, so that nothing is left
/// behind however the batch ends (a scheduler's SIGKILL too); closed with the object.
class Log {
 public:
  Log() {
    const std::string dir = fs::temp_directory_path().string();
    fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd_ < 0) {  // a file system without O_TMPFILE: a named file, unlinked at once
      std::string name = (fs::path(dir) / "treeskel-log-XXXXXX").string();
      fd_ = ::mkostemp(name.data(), O_CLOEXEC);
      if (fd_ >= 0) ::unlink(name.c_str());
    }
    if (fd_ < 0) throw Error("cannot make a temporary file in " + dir + ": " + std::string(std::strerror(errno)));
  }
  Log(Log&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  Log(const Log&) = delete;
  Log& operator=(const Log&) = delete;
  Log& operator=(Log&&) = delete;
  ~Log() {
    if (fd_ >= 0) ::close(fd_);
  }
  int fd() const { return fd_; }
  /// All the process wrote.
  std::string text() const {
    std::string out;
    char buffer[4096];
    for (off_t at = 0;;) {
      const ssize_t n = ::pread(fd_, buffer, sizeof buffer, at);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return out;
      out.append(buffer, static_cast<std::size_t>(n));
      at += n;
    }
  }

 private:
  int fd_ = -1;
};

/// Starts `args` as a child process of this executable, its output to nowhere, its errors to `log`.
pid_t spawn(const std::vector<std::string>& args, const Log& log) {
  static const fs::path self = fs::read_symlink("/proc/self/exe");
  posix_spawn_file_actions_t actions;
  ::posix_spawn_file_actions_init(&actions);
  ::posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  ::posix_spawn_file_actions_adddup2(&actions, log.fd(), STDERR_FILENO);  // the copy does not close on exec
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), environ);
  ::posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw Error("cannot start a treeskel process: " + std::string(std::strerror(rc)));
  return pid;
}

/// What the tree's process said went wrong: its last error line, else its last line.
std::string error_from_log(const Log& log) {
  std::istringstream in(log.text());
  std::string line, last, last_error;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    last = line;
    if (line.rfind("treeskel: ", 0) == 0) last_error = line.substr(10);
  }
  std::string e = last_error.empty() ? last : last_error;
  if (e.rfind("error: ", 0) == 0) e.erase(0, 7);
  return e;
}

/// Reads the tree's report into the row; false (with the error) when it cannot be read.
bool read_report(BatchRow& row) {
  try {
    row.facts = nlohmann::json::parse(io::read_whole_file(row.report));
    return row.facts.is_object();
  } catch (const std::exception& e) {
    row.error = "its report could not be read: " + std::string(e.what());
    return false;
  }
}

/// A complete earlier conversion: every output there and the report readable.
bool complete(BatchRow& row) {
  std::error_code ec;
  for (const auto& p : row.outputs)
    if (!fs::is_regular_file(p, ec)) return false;
  if (read_report(row)) return true;
  row.facts = nullptr;  // not complete after all: converted again
  row.error.clear();
  return false;
}

void finish(BatchRow& row, int status, const Log& log, bool stopping) {
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    std::error_code ec;
    for (const auto& p : row.outputs)
      if (!fs::is_regular_file(p, ec)) {
        row.status = "failed";
        row.error = "finished without writing " + p.string();
        return;
      }
    row.status = read_report(row) ? "ok" : "failed";
    return;
  }
  if (stopping && WIFSIGNALED(status)) {
    row.status = "not run";
    row.error = "stopped with the batch";
    return;
  }
  row.status = "failed";
  row.error = error_from_log(log);
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const std::string what = sig == SIGKILL ? "killed (signal 9: out of memory, or by a scheduler's limit?)"
                             : sig == SIGSEGV || sig == SIGABRT || sig == SIGBUS || sig == SIGFPE || sig == SIGILL
                                 ? "crashed (signal " + std::to_string(sig) + "; please report it with the input)"
                                 : "ended by signal " + std::to_string(sig);
    row.error = row.error.empty() ? what : what + " after: " + row.error;
  } else if (row.error.empty()) {
    row.error = "exit code " + std::to_string(WEXITSTATUS(status));
  }
}

// The summary: one row per tree, as CSV and as JSON, with the same fields.
const std::vector<std::string> kColumns{"input",  "name",      "status", "resumed", "seconds", "points", "leaf_points", "nodes",
                                        "height", "dbh",       "volume", "branch_points", "endpoints",
                                        "branches_by_order", "triangles", "components", "skeleton_coverage",
                                        "warnings", "outputs",  "error"};

nlohmann::ordered_json row_json(const BatchRow& r) {
  const nlohmann::json& f = r.facts;
  auto fact = [&](const nlohmann::json::json_pointer& at) -> nlohmann::ordered_json {
    return f.is_object() && f.contains(at) ? nlohmann::ordered_json(f.at(at)) : nlohmann::ordered_json(nullptr);
  };
  using P = nlohmann::json::json_pointer;
  nlohmann::ordered_json j;
  j["input"] = r.input.path.string();
  j["name"] = r.input.name.string();
  j["status"] = r.status;
  j["resumed"] = r.resumed;
  // A converted tree's own time (its report's: `model` gives seconds.total, `skeletonize` seconds),
  // else the time its process ran.
  const auto own = f.is_object() && f.contains(P("/seconds/total")) ? fact(P("/seconds/total")) : fact(P("/seconds"));
  j["seconds"] = r.status == "ok" ? own : nlohmann::ordered_json(r.seconds);
  j["points"] = fact(P("/points"));  // with leaves set aside, the wood's
  j["leaf_points"] = leaf_points_of(f);
  j["nodes"] = fact(P("/nodes"));
  j["height"] = fact(P("/measurements/height"));
  j["dbh"] = fact(P("/measurements/dbh"));
  j["volume"] = fact(P("/measurements/volume"));
  j["branch_points"] = fact(P("/branch_points"));
  j["endpoints"] = fact(P("/endpoints"));
  j["branches_by_order"] = fact(P("/measurements/branches_by_order"));
  j["triangles"] = fact(P("/mesh/triangles"));
  j["components"] = fact(P("/mesh/components"));
  j["skeleton_coverage"] = fact(P("/mesh/skeleton_coverage"));
  j["warnings"] = f.is_object() && f.contains("warnings") ? nlohmann::ordered_json(f["warnings"]) : nlohmann::ordered_json::array();
  j["outputs"] = nlohmann::ordered_json::array();
  if (r.status == "ok")
    for (const auto& p : r.outputs) j["outputs"].push_back(p.string());
  j["error"] = r.error.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.error);
  return j;
}

/// A number of the summary as the index shows it ("" for none).
std::string index_number(const nlohmann::ordered_json& v, int digits = 3) {
  if (!v.is_number()) return "";
  std::ostringstream out;
  out.precision(digits);
  out << v.get<double>();
  return out.str();
}

/// The files a batch's summary is written to: summary.csv, summary.json and, with --html, index.html
/// (for a shard, summary-I-of-N.* and index-I-of-N.html).
struct SummaryFiles {
  fs::path csv, json, index;
};

/// The index of a batch's pages: one row per tree with its preview, its numbers and a link to its
/// page, and a link to the summary's CSV. Links are relative: the folder can be moved.
void write_index(const BatchSettings& s, const nlohmann::ordered_json& doc, const SummaryFiles& files) {
  const std::string csv_name = view::escape_html(files.csv.filename().string());
  auto relative = [&](const std::string& name, const std::string& suffix) {
    return view::escape_html(fs::path(name + suffix).generic_string());
  };
  io::write_atomically(files.index, [&](std::ostream& out) {
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>treeskel batch: "
        << view::escape_html(s.out_dir) << "</title>\n<style>\n"
        << "body { font: 14px/1.4 system-ui, sans-serif; margin: 20px; color: #222; }\n"
        << "table { border-collapse: collapse; } th, td { padding: 6px 10px; border-bottom: 1px solid #ddd; text-align: left; vertical-align: top; }\n"
        << "td.n { text-align: right; } img { width: 320px; display: block; } .failed { color: #b00; } .warn { color: #9a3412; font-size: 12px; }\n"
        << "</style>\n</head>\n<body>\n<h1>treeskel batch</h1>\n<p>" << doc["converted"].get<std::size_t>() << " of "
        << doc["inputs"].get<std::size_t>() << " trees converted, " << doc["failed"].get<std::size_t>() << " failed, "
        << doc["not_run"].get<std::size_t>() << " not run. Distances in the inputs' units. "
        << "<a href=\"" << csv_name << "\">" << csv_name << "</a></p>\n<table>\n<tr>" << (s.preview ? "<th>preview</th>" : "")
        << "<th>tree</th><th>status</th><th>points</th><th>height</th><th>DBH</th><th>volume</th><th>skeleton inside</th><th>warnings</th></tr>\n";
    for (const auto& t : doc["trees"]) {
      const std::string name = t["name"].get<std::string>();
      const bool ok = t["status"] == "ok";
      out << "<tr>";
      if (s.preview)
        out << "<td>" << (ok ? "<a href=\"" + relative(name, ".html") + "\"><img src=\"" + relative(name, ".png") + "\" alt=\"\"></a>" : "")
            << "</td>";
      out << "<td>" << (ok ? "<a href=\"" + relative(name, ".html") + "\">" + view::escape_html(name) + "</a>" : view::escape_html(name))
          << "<br><small>" << view::escape_html(t["input"].get<std::string>()) << "</small></td>";
      out << "<td" << (ok ? "" : " class=\"failed\"") << ">" << view::escape_html(t["status"].get<std::string>());
      if (!t["error"].is_null()) out << "<br><small>" << view::escape_html(t["error"].get<std::string>()) << "</small>";
      out << "</td><td class=\"n\">" << (t["points"].is_number() ? std::to_string(t["points"].get<std::size_t>()) : "")
          << "</td><td class=\"n\">" << index_number(t["height"]) << "</td><td class=\"n\">" << index_number(t["dbh"])
          << "</td><td class=\"n\">" << index_number(t["volume"]) << "</td><td class=\"n\">"
          << (t["skeleton_coverage"].is_number() ? index_number(100.0 * t["skeleton_coverage"].get<double>(), 3) + "%" : "")
          << "</td><td class=\"warn\">";
      for (const auto& w : t["warnings"]) out << view::escape_html(w.get<std::string>()) << "<br>";
      out << "</td></tr>\n";
    }
    out << "</table>\n</body>\n</html>\n";
  });
}

void write_summary(const BatchSettings& s, const std::vector<BatchRow>& rows, const SummaryFiles& files) {
  nlohmann::ordered_json all = nlohmann::ordered_json::array();
  for (const auto& r : rows) all.push_back(row_json(r));
  io::write_atomically(files.csv, [&](std::ostream& out) {
    for (std::size_t c = 0; c < kColumns.size(); ++c) out << (c ? "," : "") << kColumns[c];
    out << '\n';
    for (const auto& j : all) {
      for (std::size_t c = 0; c < kColumns.size(); ++c) out << (c ? "," : "") << csv_field(csv_text(j[kColumns[c]]));
      out << '\n';
    }
  });
  std::size_t ok = 0, failed = 0;
  for (const auto& r : rows) {
    ok += r.status == "ok";
    failed += r.status == "failed";
  }
  nlohmann::ordered_json doc;
  doc["treeskel"] = TREESKEL_VERSION;
  doc["output_folder"] = s.out_dir;
  doc["shard"] = s.shard.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.shard);
  doc["inputs"] = rows.size();
  doc["converted"] = ok;
  doc["failed"] = failed;
  doc["not_run"] = rows.size() - ok - failed;
  doc["trees"] = std::move(all);
  io::write_atomically(files.json, [&](std::ostream& out) { out << doc.dump(2) << '\n'; });
  if (s.html) write_index(s, doc, files);
}

/// One line for a finished tree.
std::string row_line(const BatchRow& r, std::size_t done, std::size_t total) {
  std::ostringstream out;
  out << "[" << done << "/" << total << "] ";
  if (r.status != "ok") {
    // Most errors name their file already.
    const std::string path = r.input.path.string();
    out << (r.status == "failed" ? "FAILED " : "not run ");
    if (r.error.rfind(path, 0) == 0) return out.str() + r.error;
    return out.str() + path + ": " + r.error;
  }
  out << "ok " << r.input.path.string();
  const auto& f = r.facts;
  if (r.resumed) out << " (done before)";
  else out << " (" << format_seconds(r.seconds) << ")";
  if (f.contains("points")) out << ": " << f["points"].get<std::size_t>() << " points";
  if (f.contains("wood_only")) out << " (" << f["wood_only"]["leaf_points"].get<std::size_t>() << " more set aside as leaves)";
  if (f.contains("measurements")) {
    const auto& m = f["measurements"];
    out << ", height " << m["height"].get<double>();
    if (!m["dbh"].is_null()) out << ", DBH " << m["dbh"].get<double>();
  } else if (f.contains("nodes")) {
    out << ", " << f["nodes"].get<std::size_t>() << " nodes";
  }
  if (f.contains("warnings") && !f["warnings"].empty()) out << ", " << f["warnings"].size() << " warning(s)";
  return out.str();
}

}  // namespace

nlohmann::ordered_json leaf_points_of(const nlohmann::json& report) {
  if (!report.is_object()) return nullptr;
  const nlohmann::json::json_pointer counted("/wood_only/leaf_points");
  if (report.contains(counted)) return report.at(counted);
  return report.contains("wood_if_leafy") ? nlohmann::ordered_json(0) : nlohmann::ordered_json(nullptr);
}

std::string csv_text(const nlohmann::ordered_json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::string out;
    for (const auto& e : v) out += (out.empty() ? "" : "; ") + csv_text(e);
    return out;
  }
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  return v.dump();
}

int run_batch(BatchSettings& s, std::vector<BatchRow>* finished) {
  Stopwatch clock;
  // What to write: a mesh unless only a skeleton is asked for.
  if (s.model.empty() && s.skeleton.empty()) s.model = "glb";
  if (!s.model.empty() && !io::is_mesh_extension("x." + s.model))
    throw OptionError("--model " + s.model + ": unknown mesh format; use obj, gltf, glb, ply or stl");
  if (!s.skeleton.empty()) require_skeleton_extension("x." + s.skeleton);
  check_skeleton_settings(s.method);
  if (s.model.empty())
    for (const CLI::Option* o : s.model_only)
      if (o->count() > 0) throw OptionError(o->get_name() + " shapes the model: add --model FORMAT, or leave it out");
  if (s.preview) require_chromium_for_preview();
  const Shard shard = s.shard.empty() ? Shard{} : parse_shard(s.shard);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const unsigned jobs = s.jobs > 0 ? s.jobs : cores;
  const unsigned threads = std::max(1u, cores / jobs);

  std::error_code ec;
  fs::create_directories(s.out_dir, ec);
  if (!fs::is_directory(s.out_dir)) throw OptionError("-o " + s.out_dir + ": cannot make this folder: " + ec.message());
  std::vector<std::string> extensions = io::point_cloud_extensions();
  std::vector<fs::path> passed_over;
  const std::vector<BatchInput> all = plan_inputs(s.inputs, extensions, s.out_dir, &passed_over);
  if (!passed_over.empty() && !s.quiet) {
    std::cerr << "note: " << passed_over.size() << " file(s) in the folders do not look like point clouds and are "
              << "passed over (name a file to convert it anyway):";
    for (std::size_t i = 0; i < std::min<std::size_t>(passed_over.size(), 5); ++i) std::cerr << ' ' << passed_over[i].string();
    std::cerr << (passed_over.size() > 5 ? " ...\n" : "\n");
  }
  if (all.empty()) throw OptionError("no input: name cloud files, folders holding them, or patterns");
  const std::vector<BatchInput> mine = take_shard(all, shard);
  const std::string shard_suffix =
      s.shard.empty() ? "" : "-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count);
  const fs::path out_dir(s.out_dir);
  const SummaryFiles summary{out_dir / ("summary" + shard_suffix + ".csv"), out_dir / ("summary" + shard_suffix + ".json"),
                             out_dir / ("index" + shard_suffix + ".html")};

  std::vector<BatchRow> rows;
  for (const auto& in : mine) {
    BatchRow r;
    r.input = in;
    r.outputs = outputs_of(s, in);
    r.report = r.outputs.back();
    if (!in.error.empty()) {
      r.status = "failed";
      r.error = in.error;
    } else if (s.resume && complete(r)) {
      r.status = "ok";
      r.resumed = true;
    }
    rows.push_back(std::move(r));
  }

  struct sigaction action {};
  action.sa_handler = on_stop_signal;  // no SA_RESTART: waitpid returns to look at the flag
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &action, nullptr);

  const std::size_t total = rows.size();
  std::size_t done = 0, failed = 0;
  for (auto& r : rows) {
    if (r.status == "not run") continue;
    ++done;
    failed += r.status == "failed";
    if (!s.quiet) std::cout << row_line(r, done, total) << '\n';
    else if (r.status == "failed") std::cerr << row_line(r, done, total) << '\n';
  }
  Progress progress(s.quiet);
  struct Running {
    std::size_t row;
    Stopwatch clock;
    Log log;  // its stderr
  };
  std::map<pid_t, Running> running;
  std::size_t next = 0, ran = 0;
  Stopwatch since_summary;
  bool stopping = false;
  auto draw = [&] {
    std::ostringstream line;
    line << done << " of " << total << " done, " << failed << " failed, " << running.size() << " running";
    if (ran > 0 && done < total) {
      const double per_tree = clock.seconds() / static_cast<double>(ran);
      line << ", about " << format_duration(per_tree * static_cast<double>(total - done)) << " left";
    }
    progress(line.str(), total ? static_cast<double>(done) / static_cast<double>(total) : 1.0);
  };
  // The largest files first: the long trees then overlap the rest instead of running last, alone.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].status == "not run") order.push_back(i);
  std::vector<std::uintmax_t> bytes(rows.size(), 0);
  for (std::size_t i : order) bytes[i] = fs::file_size(rows[i].input.path, ec);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return bytes[a] > bytes[b]; });
  while (true) {
    while (!stopping && running.size() < jobs && next < order.size()) {
      const std::size_t i = order[next++];
      BatchRow& r = rows[i];
      for (const auto& p : r.outputs) fs::create_directories(p.parent_path());
      Running job{i, Stopwatch(), Log()};
      const pid_t pid = spawn(command_for(s, r, threads), job.log);
      running.emplace(pid, std::move(job));
    }
    draw();
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno != EINTR) throw Error("waiting for a tree's process failed: " + std::string(std::strerror(errno)));
      if (g_stop_signal && !stopping) {
        stopping = true;
        for (const auto& [child, job] : running) ::kill(child, g_stop_signal);
      }
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    BatchRow& r = rows[it->second.row];
    r.seconds = it->second.clock.seconds();
    finish(r, status, it->second.log, stopping);
    running.erase(it);
    if (r.status != "not run") {
      ++done;
      ++ran;
      failed += r.status == "failed";
      progress.clear();
      if (!s.quiet) std::cout << row_line(r, done, total) << std::endl;
      else if (r.status == "failed") std::cerr << row_line(r, done, total) << std::endl;
    }
    if (since_summary.seconds() > kSummaryInterval) {
      write_summary(s, rows, summary);
      since_summary = Stopwatch();
    }
  }
  progress.clear();
  write_summary(s, rows, summary);
  std::size_t resumed = 0, not_run = 0;
  for (const auto& r : rows) {
    resumed += r.resumed;
    not_run += r.status == "not run";
  }
  if (!s.quiet || failed > 0 || stopping) {
    std::ostringstream line;
    line << total << (total == 1 ? " input" : " inputs") << (s.shard.empty() ? "" : " in shard " + s.shard) << ": "
         << done - failed << " converted";
    if (resumed) line << " (" << resumed << " before this run)";
    line << ", " << failed << " failed";
    if (not_run) line << ", " << not_run << " not run (stopped)";
    line << ", " << format_duration(clock.seconds()) << "; summary in " << summary.csv.string() << " and "
         << summary.json.filename().string();
    (failed > 0 || stopping ? std::cerr : std::cout) << line.str() << '\n';
  }
  if (finished) *finished = rows;
  if (stopping) return 128 + static_cast<int>(g_stop_signal);
  return failed > 0 ? 1 : 0;
}

Command add_batch(CLI::App& app) {
  auto s = std::make_shared<BatchSettings>();
  CLI::App* c = app.add_subcommand(
      "batch",
      "Convert many trees: every cloud named, found in a folder (recursively) or matching a pattern, each by a "
      "treeskel process of its own, several at a time; a tree that fails is one error row and the rest go on.\n"
      "Writes OUTDIR/NAME.glb (or --model FORMAT), NAME_skeleton.FORMAT with --skeleton, NAME_leaves.ply with "
      "--wood-only or --wood-if-leafy (the points set aside), NAME_report.json, and "
      "summary.csv and summary.json with one row per tree (input, status, seconds, points, points set aside as "
      "leaves, height, DBH, "
      "volume, branch counts, coverage, warnings, error). NAME is the input's file name without its "
      "extension, or for a file found in a folder its path below that folder. Exit code 0 when every tree "
      "converted, 1 when any failed.");
  c->add_option("inputs", s->inputs, "Cloud files, folders of them, or quoted patterns such as 'plot/*.las'")
      ->required();
  c->add_option("-o,--output", s->out_dir, "Folder to write into (made if missing)")->required();
  c->add_option("--model", s->model, "Mesh format of each tree's model: glb (the default), gltf, obj, ply or stl");
  c->add_option("--skeleton", s->skeleton,
                "Also write each tree's skeleton in this format: json, ply or obj (alone: skeletons only, "
                "no model, pruned as skeletonize prunes: the pruning defaults shown below are a model's)");
  c->add_flag("--html", s->html,
              "Also write each tree's page (NAME.html: cloud, skeleton, mesh and report, opens from disk) and "
              "index.html, a table of the trees linking to them");
  c->add_flag("--preview", s->preview, "Also render each tree's NAME.png (side and top views; needs Chromium), "
                                       "shown in index.html with --html");
  c->add_option("-j,--jobs", s->jobs, "Trees converted at once (0: as many as cores; each gets cores/jobs threads)")
      ->default_val(0)->check(CLI::Range(0u, 1024u));
  c->add_flag("--resume", s->resume,
              "Skip the trees whose outputs and report are all there from an earlier run (outputs are written "
              "whole or not at all, so a killed batch leaves none half-written)");
  c->add_option("--shard", s->shard,
                "I/N: convert only every N-th input from the I-th (from 0), for array jobs; e.g. with Slurm "
                "--array=0-9: --shard $SLURM_ARRAY_TASK_ID/10. The summary is then summary-I-of-N.csv/.json");
  c->add_flag("-q,--quiet", s->quiet, "Print only failures and the final count when some failed");
  add_tree_options(*c, *s);
  return [s] { return run_batch(*s); };
}

void add_tree_options(CLI::App& c, BatchSettings& s) {
  const auto before = c.get_options();
  add_model_options(c, s.model_settings);
  const auto with_model = c.get_options();
  use_model_defaults(s.method);  // each tree's own process takes its command's: skeletonize keeps 1.75
  add_skeleton_options(c, s.method);
  c.add_option("--html-points", s.html_points, "With --html or --preview: at most this many of a cloud's points in its page")
      ->check(CLI::PositiveNumber);
  for (const CLI::Option* o : c.get_options()) {
    if (std::find(before.begin(), before.end(), o) != before.end()) continue;
    s.passed.push_back(o);
    if (std::find(with_model.begin(), with_model.end(), o) != with_model.end()) s.model_only.push_back(o);
  }
}

}  // namespace treeskel::cli
