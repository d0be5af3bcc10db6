/// @file output_set.h
/// The files one run writes, committed together: whole or absent, all of them.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::io {

/// Stages the outputs of one run. `stage` checks a target before any work is done (its folder exists
/// and can be written, it is not a folder, not one of the inputs, not named twice) and returns the path
/// a writer should write to instead, in a private folder beside the target. `commit` moves every staged
/// file (with side files a writer put beside it, such as a .gltf's .bin) into place once all are
/// written. A set destroyed without `commit` — an error, an exception — leaves nothing behind, and
/// neither does SIGINT, SIGTERM or SIGHUP while a set is alive (the signal then ends the process as it
/// would have). A target that is a symbolic link stays one: the file it points to is replaced.
class OutputSet {
 public:
  /// `inputs`: files the run reads, which no output may overwrite.
  explicit OutputSet(std::vector<std::filesystem::path> inputs = {});
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  /// Checks `target` (what = how the user named it, e.g. "--report") and returns the staged path.
  /// @throws OptionError when the target cannot be an output (a usage error), Error when its folder
  /// cannot be written.
  std::filesystem::path stage(const std::filesystem::path& target, const std::string& what = "output");

  /// Moves every staged file into place. @throws Error if a move fails (the rest stay staged and are
  /// removed).
  void commit();

  /// `message` with each staged path replaced by the target the user named (for errors of writers).
  std::string explain(std::string message) const;

 private:
  struct Target {
    std::filesystem::path destination;  ///< where the file goes (a link's target resolved)
    std::filesystem::path staged;
    std::filesystem::path named;  ///< as the user named it
  };
  std::vector<std::filesystem::path> inputs_;
  std::vector<std::filesystem::path> folders_;  ///< staging folders, one per destination folder
  std::vector<Target> targets_;
  int slot_ = -1;  ///< this set's place in the signal handler's table
};

}  // namespace treeskel::io
