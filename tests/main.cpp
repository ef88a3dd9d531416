// The test programs' main: doctest's, except that a run whose filters select no test case fails.
// ctest runs each case by name (doctest_discover_tests); a name the filter cannot match (a ';'
// splits it into two CMake list items) would otherwise pass having run nothing. The files the tests
// write (checkpoints, stats, frames, scripts, many through the command line into its working
// directory) go to a directory of the run's own, made empty in the system's temporary directory and
// removed when every test passed or it is empty (kept and named otherwise): not into the directory the program
// was started from (run from the source tree, they were left there), nor shared by the cases ctest
// runs at the same time.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

int g_selected = -1;  // test cases that passed the filters, once the run has ended

struct SelectedCount : doctest::IReporter {
  explicit SelectedCount(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats& stats) override {
    g_selected = static_cast<int>(stats.numTestCasesPassingFilters);
  }
  void test_case_start(const doctest::TestCaseData&) override {}
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats&) override {}
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}
};

}  // namespace

DOCTEST_REGISTER_LISTENER("selected_count", 0, SelectedCount);

int main(int argc, char** argv) {
  std::string dir = (std::filesystem::temp_directory_path() / "silt_tests.XXXXXX").string();
  if (!mkdtemp(dir.data()) || chdir(dir.c_str()) != 0) {
    std::perror("silt tests: a directory for the tests' files");
    return 1;
  }
  doctest::Context context(argc, argv);
  int result = context.run();
  if (!context.shouldExit() && result == 0 && g_selected == 0) {  // (not --list-test-cases, --help)
    std::fprintf(stderr, "no test case matches the filters given\n");
    result = 1;
  }
  std::error_code ec;
  if (result == 0 || std::filesystem::is_empty(dir, ec)) std::filesystem::remove_all(dir, ec);
  else std::fprintf(stderr, "the tests' files are kept in %s\n", dir.c_str());
  return result;
}
