// treeskel synth OUTDIR  and  treeskel eval PREDICTED TRUTH
#include "commands.h"
#include "report.h"

#include "treeskel/error.h"
#include "treeskel/eval/hard_trees.h"
#include "treeskel/eval/metrics.h"
#include "treeskel/eval/paper_trees.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

namespace treeskel::cli {

namespace {

namespace fs = std::filesystem;

struct SynthSettings {
  std::string folder;
  std::uint64_t seed = 1;
  std::string format = "xyz";
  std::string set = "paper";
  bool quiet = false;
};

int run_synth(const SynthSettings& s) {
  Stopwatch clock;
  std::error_code ec;
  fs::create_directories(s.folder, ec);
  if (!fs::is_directory(s.folder)) throw Error(s.folder + ": cannot create the folder");
  Progress progress(s.quiet);
  std::size_t written = 0;
  if (s.set == "hard") {
    // Each harder cloud with its own truth: a sparse scan's truth is cut back to what it shows.
    progress("making the harder sets", 0.0);
    const std::vector<eval::HardCloud> clouds = eval::make_hard_clouds(s.seed);
    for (const auto& c : clouds) {
      progress("writing " + c.name, static_cast<double>(written) / clouds.size());
      io::write_point_cloud(fs::path(s.folder) / (c.name + "." + s.format), c.cloud);
      io::write_skeleton(fs::path(s.folder) / (c.name + "_truth.json"), c.truth.skeleton);
      ++written;
    }
    progress.clear();
    if (!s.quiet)
      std::cout << "wrote " << written << " clouds of the harder sets, each with its truth (<cloud>_truth.json), to "
                << s.folder << " in " << format_seconds(clock.seconds()) << '\n';
    return 0;
  }
  for (int t = 1; t <= 6; ++t) {
    progress("tree " + std::to_string(t), (t - 1) / 6.0);
    const eval::GroundTruth truth = eval::make_paper_tree(t, s.seed);
    const std::string stem = "tree" + std::to_string(t) + "_truth";
    io::write_skeleton(fs::path(s.folder) / (stem + ".json"), truth.skeleton);
    io::write_skeleton(fs::path(s.folder) / (stem + ".ply"), truth.skeleton);
    for (const auto& c : eval::make_paper_clouds(truth, t, s.seed)) {
      io::write_point_cloud(fs::path(s.folder) / (c.name + "." + s.format), c.cloud);
      ++written;
    }
  }
  progress.clear();
  if (!s.quiet)
    std::cout << "wrote " << written << " clouds and 6 ground truths (tree<N>_truth.json, .ply) to " << s.folder << " in "
              << format_seconds(clock.seconds()) << '\n';
  return 0;
}

struct EvalSettings {
  std::string predicted, truth;
  double tau = 0.05;
  bool json = false;
};

int run_eval(const EvalSettings& s) {
  const Skeleton predicted = io::read_skeleton(s.predicted);
  const Skeleton truth = io::read_skeleton(s.truth);
  eval::MetricOptions options;
  options.tau = s.tau;
  const eval::Metrics m = eval::evaluate(predicted, truth, options);
  if (s.json) {
    nlohmann::ordered_json j;
    j["predicted"] = s.predicted;
    j["truth"] = s.truth;
    j["tau"] = s.tau;
    j["spd"] = m.spd;
    j["reverse_spd"] = m.reverse_spd;
    j["bpc"] = m.bpc;
    j["epc"] = m.epc;
    j["bp_precision"] = m.bp_precision;
    j["ep_precision"] = m.ep_precision;
    j["branch_points"] = {{"truth", m.truth_branch_points}, {"predicted", m.predicted_branch_points}, {"matched", m.matched_branch_points}};
    j["endpoints"] = {{"truth", m.truth_endpoints}, {"predicted", m.predicted_endpoints}, {"matched", m.matched_endpoints}};
    j["cycles"] = m.cycles;
    j["components"] = m.components;
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("SPD %.4f  reverse SPD %.4f\n", m.spd, m.reverse_spd);
    std::printf("BPC %.3f  (%zu of %zu branch points matched within %.3g; precision %.3f of %zu predicted)\n", m.bpc,
                m.matched_branch_points, m.truth_branch_points, s.tau, m.bp_precision, m.predicted_branch_points);
    std::printf("EPC %.3f  (%zu of %zu endpoints matched; precision %.3f of %zu predicted)\n", m.epc, m.matched_endpoints,
                m.truth_endpoints, m.ep_precision, m.predicted_endpoints);
    std::printf("cycles %zu  components %zu\n", m.cycles, m.components);
  }
  return 0;
}

}  // namespace

Command add_synth(CLI::App& app) {
  auto s = std::make_shared<SynthSettings>();
  CLI::App* c = app.add_subcommand(
      "synth", "Write the paper's synthetic benchmark: 6 ground-truth trees (tree<N>_truth.json and .ply) and their 72 "
               "clouds named as in the paper's Table 1, normalised to a longest side of 1.");
  c->add_option("folder", s->folder, "Folder to write into (created if missing)")->required();
  c->add_option("--seed", s->seed, "Seed of the trees and clouds")->default_val(s->seed);
  c->add_option("--set", s->set,
                "paper: the paper's 72 clouds; hard: the harder sets of docs/accuracy.md (9 crowded crowns, 18 "
                "sparse virtual scans whose truth is cut back to what they show, 6 with every degradation at once), "
                "each cloud with its own <cloud>_truth.json")
      ->default_val(s->set)
      ->check(CLI::IsMember({"paper", "hard"}));
  c->add_option("--format", s->format, "Cloud file format")->default_val(s->format)
      ->check(CLI::IsMember({"xyz", "ply", "las", "txt", "csv"}));
  c->add_flag("-q,--quiet", s->quiet, "Print nothing but errors");
  return [s] { return run_synth(*s); };
}

Command add_eval(CLI::App& app) {
  auto s = std::make_shared<EvalSettings>();
  CLI::App* c = app.add_subcommand(
      "eval", "Score a skeleton against a ground truth: SPD, BPC, EPC (Fu et al. 2020), their precision, reverse SPD, "
              "cycles and components. Both files are .ply or .json skeletons in the same frame.");
  c->add_option("predicted", s->predicted, "Skeleton to score")->required();
  c->add_option("truth", s->truth, "Ground-truth skeleton")->required();
  c->add_option("--tau", s->tau, "Matching distance for branch points and endpoints")->default_val(s->tau)
      ->check(positive());
  c->add_flag("--json", s->json, "Print the measures as JSON");
  return [s] { return run_eval(*s); };
}

}  // namespace treeskel::cli
