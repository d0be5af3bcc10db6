#include "support/synthetic.h"
#include "treeskel/io/run_program.h"

#include <gtest/gtest.h>

namespace treeskel::io {
namespace {

TEST(RunProgram, ReportsHowTheProgramEnded) {
  test::TempDir dir;
  const std::filesystem::path log = dir.path("log");
  EXPECT_TRUE(run_program({"true"}, log).ok());

  const ProgramResult failed = run_program({"sh", "-c", "echo first >&2; echo; echo 'the last words' >&2; exit 3"}, log);
  EXPECT_TRUE(failed.started);
  EXPECT_FALSE(failed.ok());
  EXPECT_EQ(failed.exit_code, 3);
  EXPECT_EQ(last_line_of(log), "the last words");

  const ProgramResult killed = run_program({"sh", "-c", "kill -TERM $$"}, log);
  EXPECT_FALSE(killed.ok());
  EXPECT_EQ(killed.signal, 15);

  const ProgramResult missing = run_program({"/nonexistent/program"}, log);
  EXPECT_FALSE(missing.started);
  EXPECT_FALSE(missing.error.empty());
  EXPECT_FALSE(run_program({}, log).started);
  EXPECT_EQ(last_line_of(dir.path("no such file")), "");
}

}  // namespace
}  // namespace treeskel::io
