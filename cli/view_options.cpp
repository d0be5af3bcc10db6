#include "view_options.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

namespace treeskel::cli {

namespace fs = std::filesystem;

void require_chromium_for_preview() {
  if (view::find_chromium().empty())
    throw OptionError("--preview needs Chromium: apt-get install chromium (or set TREESKEL_CHROMIUM to a Chrome or Chromium)");
}

void add_view_options(CLI::App* c, ViewSettings& s) {
  c->add_option("--html", s.html,
                "Also write a page that shows the cloud, the skeleton and the mesh with the report: one .html file that "
                "opens from disk in a browser, with no network");
  c->add_option("--preview", s.preview,
                "Also render a .png of the same scene from the side and from above (needs Chromium; no display)");
  c->add_option("--html-points", s.html_points, "At most this many of the cloud's points in the page and the preview")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

ViewOutputs::ViewOutputs(const ViewSettings& settings, io::OutputSet& outputs) : settings_(settings), outputs_(outputs) {
  if (!settings_.html.empty()) {
    const std::string e = io::extension_of(settings_.html);
    if (e != "html" && e != "htm") throw OptionError("--html must name a .html file");
    html_to_ = outputs.stage(settings_.html, "--html");
  }
  if (!settings_.preview.empty()) {
    if (io::extension_of(settings_.preview) != "png") throw OptionError("--preview must name a .png file");
    require_chromium_for_preview();
    preview_to_ = outputs.stage(settings_.preview, "--preview");
  }
}

void ViewOutputs::write(const view::Scene& scene) const {
  if (!wanted()) return;
  view::HtmlOptions options;
  options.max_points = settings_.html_points;
  try {
    // The preview is rendered from the page; without --html, from a page beside it that is not kept.
    const fs::path page = !html_to_.empty() ? html_to_ : fs::path(preview_to_.string() + ".html");
    view::write_html(page, scene, options);
    if (!preview_to_.empty()) {
      view::render_preview(page, preview_to_);
      if (html_to_.empty()) fs::remove(page);
    }
  } catch (const Error& e) {
    throw Error(outputs_.explain(e.what()));
  }
}

}  // namespace treeskel::cli
