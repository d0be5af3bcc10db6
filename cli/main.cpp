// treeskel: tree skeletons and models from raw point clouds.
#include "commands.h"
#include "huge_pages.h"
#include "treeskel/error.h"

#include <tbb/global_control.h>

#include <csignal>
#include <iostream>
#include <memory>
#include <thread>

int main(int argc, char** argv) {
  treeskel::cli::restart_with_huge_pages(argv, treeskel::cli::memory_for(argc, argv));
  CLI::App app{"treeskel " TREESKEL_VERSION
               ": curve skeletons of trees from raw point clouds (Fu et al., IEEE Access 2020).\n"
               "Run 'treeskel COMMAND --help' for the options of a command."};
  app.set_version_flag("--version", std::string("treeskel ") + TREESKEL_VERSION);
  app.require_subcommand(1);
  unsigned threads = 0;
  app.add_option("--threads", threads, "Threads to use (0: all cores); results do not depend on it")
      ->default_val(0);
  const treeskel::cli::Command skeletonize = treeskel::cli::add_skeletonize(app);
  const treeskel::cli::Command model = treeskel::cli::add_model(app);
  const treeskel::cli::Command synth = treeskel::cli::add_synth(app);
  const treeskel::cli::Command evaluate = treeskel::cli::add_eval(app);
  const treeskel::cli::Command batch = treeskel::cli::add_batch(app);
  const treeskel::cli::Command plot = treeskel::cli::add_plot(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  // A file size limit (ulimit -f, a quota) then fails a write with EFBIG, reported like a full disk,
  // instead of killing the process mid-file.
  std::signal(SIGXFSZ, SIG_IGN);
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  try {
    if (app.got_subcommand("skeletonize")) return skeletonize();
    if (app.got_subcommand("model")) return model();
    if (app.got_subcommand("synth")) return synth();
    if (app.got_subcommand("eval")) return evaluate();
    if (app.got_subcommand("batch")) return batch();
    if (app.got_subcommand("plot")) return plot();
  } catch (const treeskel::OptionError& e) {
    std::cerr << "treeskel: error: " << e.what() << '\n';
    return 2;
  } catch (const treeskel::Error& e) {
    std::cerr << "treeskel: error: " << e.what() << '\n';
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "treeskel: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "treeskel: internal error: " << e.what() << '\n';
    return 3;
  }
  return 2;
}
