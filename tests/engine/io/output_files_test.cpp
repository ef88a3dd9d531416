// Output names: one path for every name of a file, the pairs of outputs that would overwrite one
// another (one file by two names), and the temporary files outputs are written to before a rename.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "silt/errors.hpp"
#include "silt/io.hpp"
#include "silt/run_job.hpp"
#include "support/files.hpp"
#include "support/scenes.hpp"

using namespace silt;
namespace fs = std::filesystem;

namespace {

struct Dir {
  // One per process: ctest runs each test case of this file in its own process, at the same time.
  fs::path path = fs::temp_directory_path() / ("silt_output_files_test_" + std::to_string(::getpid()));
  Dir() {
    fs::remove_all(path);
    fs::create_directories(path / "sub");
  }
  ~Dir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

}  // namespace

TEST_CASE("canonical_path gives one path for every name of a file, made or not") {
  const Dir d;
  CHECK(canonical_path(d / "sub/../a.csv") == canonical_path(d / "a.csv"));
  CHECK(canonical_path(d / "sub/") == canonical_path(d / "sub"));
  CHECK(canonical_path(d / "not_made/") == canonical_path(d / "not_made"));
  CHECK(canonical_path(d / "not_made/x/../y") == canonical_path(d / "not_made/y"));
  fs::create_directory_symlink(d.path / "sub", d.path / "link");
  CHECK(canonical_path(d / "link/a.csv") == canonical_path(d / "sub/a.csv"));
  CHECK(canonical_path("") == canonical_path("."));
  CHECK(canonical_path("").is_absolute());
  // A link to a file not made yet is that file (two outputs through it went to one file).
  fs::create_symlink("later.csv", d.path / "dangling");
  CHECK(canonical_path(d / "dangling") == canonical_path(d / "later.csv"));
  CHECK(output_clash(d / "dangling", d / "later.csv") == "the same file");
}

TEST_CASE("two outputs clash when they are one file, and a temporary file is new and unique") {
  const Dir d;
  CHECK(output_clash(d / "a.csv", d / "sub/../a.csv") == "the same file");
  CHECK(output_clash(d / "a.csv", d / "b.csv").empty());
  CHECK(output_clash(d / "a.csv", "").empty());
  CHECK(output_clash("/dev/null", "/dev/null").empty());  // a device takes several
  // A file is written to a temporary file made new beside it, never to a fixed NAME.tmp (which
  // emptied a file of that name, and failed every save when a directory had it): a.ckpt and
  // a.ckpt.tmp are two outputs apart.
  CHECK(output_clash(d / "a.ckpt", d / "a.ckpt.tmp").empty());
  CHECK_FALSE(overwrites(d / "x", d / "x.tmp"));
  std::ofstream(d / "x.tmp") << "kept\n";
  fs::create_directory(d.path / "y.tmp");
  write_text_file(d / "x", "x\n", "summary");
  write_text_file(d / "y", "y\n", "summary");
  CHECK(test::read_file(d / "x.tmp") == "kept\n");
  CHECK(test::read_file(d / "x") == "x\n");
  CHECK(test::read_file(d / "y") == "y\n");
  const TempFile a = make_temp_beside(d / "z"), b = make_temp_beside(d / "z");
  REQUIRE(a.fd >= 0);
  REQUIRE(b.fd >= 0);
  CHECK(a.name != b.name);
  CHECK(a.name.rfind(d / "z.tmp.", 0) == 0);
  // With the permissions open() gives a new file (mkstemp's are 0600).
  struct stat st {};
  REQUIRE(::fstat(a.fd, &st) == 0);
  const mode_t mask = ::umask(0);
  ::umask(mask);
  CHECK((st.st_mode & 0777) == (0666 & ~mask));
  ::close(a.fd);
  ::close(b.fd);
}

TEST_CASE("an output named as an input is refused with the reason") {
  const Dir d;
  std::ofstream(d / "scene.toml") << "# a scene\n";
  CHECK_THROWS_WITH_AS(check_not_input(d / "sub/../scene.toml", d / "scene.toml", "checkpoint"),
                       doctest::Contains("it is the scene file"), IoError);
  std::ofstream(d / "play.tmp") << "run 1\n";
  CHECK_NOTHROW(check_not_input(d / "play", d / "play.tmp", "checkpoint", "a script being played"));
  CHECK_NOTHROW(check_not_input(d / "scene.toml.tmp", d / "scene.toml", "checkpoint"));
}

TEST_CASE("a hard link is the same file, whatever its name: the scene behind one is refused") {
  // `--stats link.csv`, link.csv a hard link of the scene, emptied the scene.
  const Dir d;
  std::ofstream(d / "scene.toml") << "# a scene\n";
  std::filesystem::create_hard_link(d / "scene.toml", d / "link.csv");
  CHECK(output_clash(d / "link.csv", d / "scene.toml") == "the same file");
  CHECK_THROWS_WITH_AS(check_not_input(d / "link.csv", d / "scene.toml", "stats file"),
                       doctest::Contains("it is the scene file"), IoError);
  std::ofstream(d / "other.csv") << "t\n";
  CHECK(output_clash(d / "other.csv", d / "scene.toml").empty());
}

TEST_CASE("is_in_directory compares the file's directory with any name of the directory") {
  const Dir d;
  CHECK(is_in_directory(d / "sub/f.png", d / "sub/"));
  CHECK(is_in_directory(d / "sub/../sub/f.png", d / "sub"));
  CHECK_FALSE(is_in_directory(d / "f.png", d / "sub"));
  CHECK_FALSE(is_in_directory("", d / "sub"));
}

TEST_CASE("an output path is checked by making a file beside it, where writing is granted but refused") {
  // To root, /proc and /sys pass access(W_OK) and refuse a new file: a summary or a checkpoint
  // there was refused only after the run.
  // (Other users are refused by access: the directory.)
  CHECK_THROWS_WITH_AS(check_output_path("/proc/silt_output_test.ckpt", "checkpoint"), doctest::Contains("directory"),
                       IoError);
  Dir d;
  CHECK_NOTHROW(check_output_path(d / "new.json", "summary"));
  std::ofstream(d / "old.json") << "{}";
  CHECK_NOTHROW(check_output_path(d / "old.json", "summary"));
  CHECK_NOTHROW(check_output_path("/dev/null", "summary"));
  // A file where its directory should be is said to be one ("no directory 'old.json'").
  CHECK_THROWS_WITH_AS(check_output_path(d / "old.json/x.ckpt", "checkpoint"),
                       doctest::Contains("old.json' is not a directory"), IoError);
  // Nothing is left beside them.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d.path)) ++entries;
  CHECK(entries == 2);  // sub/ and old.json
}

TEST_CASE("a run job refuses two of its outputs on one file, or on a VTK file's name, as the command line does") {
  // (only `silt run` checked them: a caller of RunJob of its own lost one output to the other)
  auto sim = test::simulation_from(test::read_file(test::scene_path("collision_normal")), 1);
  Dir d;
  RunJobOptions same;
  same.stats = d / "out.csv";
  same.save = d / "sub/../out.csv";
  CHECK_THROWS_WITH_AS(RunJob(*sim, same), doctest::Contains("the same file"), IoError);
  RunJobOptions vtk;
  vtk.vtk = d / "v";
  vtk.summary = d / "v/index.pvd";
  CHECK_THROWS_WITH_AS(RunJob(*sim, vtk), doctest::Contains("is a VTK file's name in the VTK directory"), IoError);
  RunJobOptions apart;
  apart.stats = d / "a.csv";
  apart.summary = d / "a.json";
  CHECK_NOTHROW(RunJob(*sim, apart));
}

TEST_CASE("a final checkpoint whose directory went away during the run is written under its name here") {
  // (the run's end was lost: "cannot write checkpoint 'sub/x.ckpt': no directory 'sub'", exit 4)
  auto sim = test::simulation_from(test::read_file(test::scene_path("collision_normal")), 1);
  Dir d;
  const std::string name = "silt_output_files_test_" + std::to_string(::getpid()) + ".ckpt";
  RunJobOptions o;
  o.save = d / ("sub/" + name);
  RunJob job(*sim, o);
  RunOptions opt;
  opt.steps = 5;
  const RunReport rep = job.run(opt);
  fs::remove_all(d.path / "sub");
  CHECK(job.finish(rep) == 4);
  CHECK(state_hash(read_checkpoint(name, sim->model())) == state_hash(sim->state()));
  fs::remove(name);
}
