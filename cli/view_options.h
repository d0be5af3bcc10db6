// --html and --preview, shared by skeletonize and model (and passed on by batch).
#pragma once

#include "treeskel/io/output_set.h"
#include "treeskel/view/html.h"

#include <CLI/CLI.hpp>

#include <cstddef>
#include <filesystem>
#include <string>

namespace treeskel::cli {

struct ViewSettings {
  std::string html;      ///< the page to write, or ""
  std::string preview;   ///< the PNG to render, or ""
  std::size_t html_points = view::HtmlOptions{}.max_points;
};

/// @throws OptionError (a usage error, before any work) when no Chromium can render --preview.
void require_chromium_for_preview();

/// Adds --html, --preview and --html-points to `command`.
void add_view_options(CLI::App* command, ViewSettings& s);

/// The page and the preview of one run: checked and staged before the work, written at its end.
class ViewOutputs {
 public:
  /// Checks the names (.html / .htm, .png) and stages them in `outputs`.
  ViewOutputs(const ViewSettings& settings, io::OutputSet& outputs);
  bool wanted() const { return !html_to_.empty() || !preview_to_.empty(); }
  /// Writes the page and renders the preview (into the staged paths). @throws Error naming the
  /// output as the user named it.
  void write(const view::Scene& scene) const;

 private:
  ViewSettings settings_;
  io::OutputSet& outputs_;
  std::filesystem::path html_to_, preview_to_;
};

}  // namespace treeskel::cli
