// Batch runs lose nothing: a scheduler's SIGTERM, a closed terminal's SIGHUP, an output that cannot be written, a
// preparation that fails, a step count that is not a multiple of --every; and the command line's numbers read as the
// shell reads them. Each case is a reproducer run through the binary.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "shell/cli_fixtures.hpp"
#include "shell/shell_fixtures.hpp"

using silt::test::contains;
using silt::test::read_file;
using silt::test::Result;
using silt::test::scene_path;
using silt::test::sh;
using silt::test::silt_cli;
using silt::test::write_file;

namespace {

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(read_file(path)); }

// The rows of a stats CSV (header excluded), each as its text.
std::vector<std::string> csv_rows(const std::string& path) {
  std::vector<std::string> rows;
  std::istringstream in(read_file(path));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) rows.push_back(line);
  return rows;
}

// The second column (the step) of a stats row written with --observe t,step.
long long step_of(const std::string& row) { return std::stoll(row.substr(row.find(',') + 1)); }

// A shell command line that starts `command` in the background, waits until `file` holds `lines`
// lines (the run is under way), sends `signal` and prints the exit code as "code=N".
std::string signalled(const std::string& command, const std::string& file, int lines, const char* signal) {
  return command + " & p=$!; i=0; while [ \"$(cat " + file + " 2>/dev/null | wc -l)\" -lt " + std::to_string(lines) +
         " ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done; kill -" + signal + " $p; wait $p; echo code=$?";
}

}  // namespace

TEST_CASE("SIGTERM, SIGINT and SIGHUP stop a run at a step boundary, everything is written, exit 128 + signal") {
  for (const auto& signal_code : {std::pair<const char*, int>{"TERM", 143}, {"INT", 130}, {"HUP", 129}}) {
    const auto [signal, code] = signal_code;
    CAPTURE(signal_code.first);
    silt::test::TempDir dir;
    const std::string stats = dir / "st.csv", summary = dir / "s.json";
    // sh runs a background job with SIGINT ignored unless it is interactive: silt installs its own
    // handler, so both signals reach it.
    const Result r =
        sh(signalled(silt::test::silt_binary() + " run " + scene_path("chute") +
                         " --steps 1e9 --every 20 --observe t,step --quiet --stats " + stats + " --summary " + summary,
                     stats, 5, signal));
    CHECK(contains(r.out, "code=" + std::to_string(code)));
    const auto j = read_json(summary);
    CHECK(j["status"] == "interrupted");
    CHECK(j["exit_code"] == code);
    // The stats kept their rows (flushed at every sample), and the end is the last one. (The
    // signal is sent after the header and four rows: sent after three, it could stop the run at
    // the step of the third, already sampled, and leave three.)
    const auto rows = csv_rows(stats);
    REQUIRE(rows.size() >= 4);
    CHECK(step_of(rows.back()) == j["steps"].get<long long>());
    CHECK(j["steps_run"].get<long long>() == j["steps"].get<long long>());
  }
}

TEST_CASE("an ignored SIGHUP stays ignored (nohup): the run goes on until SIGTERM") {
  silt::test::TempDir dir;
  const std::string stats = dir / "st.csv", summary = dir / "s.json";
  const std::string run = "(trap '' HUP; exec " + silt::test::silt_binary() + " run " + scene_path("chute") +
                          " --steps 1e9 --every 20 --observe t,step --quiet --stats " + stats + " --summary " +
                          summary + ")";
  const Result r = sh(run + " & p=$!; i=0; while [ \"$(cat " + stats +
                      " 2>/dev/null | wc -l)\" -lt 4 ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done;"
                      " kill -HUP $p; sleep 0.3; kill -0 $p && echo alive; kill -TERM $p; wait $p; echo code=$?");
  CHECK(contains(r.out, "alive"));
  CHECK(contains(r.out, "code=143"));
  CHECK(read_json(summary)["status"] == "interrupted");
}

TEST_CASE("silt play stops on SIGTERM as silt run does") {
  silt::test::TempDir dir;
  const std::string script = silt::test::write_file(
      dir / "long.silt", "load " + scene_path("chute") + "\nwatch step every 50\nrun 1e9\nprint t\n");
  const Result r = sh(
      signalled(silt::test::silt_binary() + " play " + script + " > " + (dir / "out.txt"), dir / "out.txt", 6, "TERM"));
  CHECK(contains(r.out, "code=143"));
  CHECK(contains(r.out, "terminated (SIGTERM): the script stops here"));
  const std::string out = read_file(dir / "out.txt");
  CHECK(contains(out, "paused:"));
  CHECK_FALSE(contains(out, "> print t"));  // the script stopped where the signal came
}

TEST_CASE("silt play stops on SIGINT as silt run does, exit 130") {
  silt::test::TempDir dir;
  const std::string script = silt::test::write_file(
      dir / "long.silt", "load " + scene_path("chute") + "\nwatch step every 50\nrun 1e9\nprint t\n");
  const Result r = sh(
      signalled(silt::test::silt_binary() + " play " + script + " > " + (dir / "out.txt"), dir / "out.txt", 6, "INT"));
  CHECK(contains(r.out, "code=130"));
  CHECK(contains(r.out, "interrupted: the script stops here"));
  const std::string out = read_file(dir / "out.txt");
  CHECK(contains(out, "paused:"));
  CHECK_FALSE(contains(out, "> print t"));
}

TEST_CASE("the shell fed by a pipe pauses its run and ends on SIGTERM (exit 143) or SIGHUP (exit 129)") {
  for (const auto& signal_code : {std::pair<const char*, int>{"TERM", 143}, {"HUP", 129}}) {
    const auto [signal, code] = signal_code;
    CAPTURE(signal_code.first);
    silt::test::TempDir dir;
    const std::string out = dir / "out.txt";
    // The commands come through a pipe that stays open (a fifo held by the test's shell), as from a
    // job's script.
    const std::string fifo = dir / "in";
    const Result r = sh("mkfifo " + fifo + "; " + silt::test::silt_binary() + " shell " + scene_path("chute") + " < " +
                        fifo + " > " + out + " & p=$!; exec 3> " + fifo +
                        "; printf 'watch step every 50\\nrun 1e9\\n' >&3; i=0; while [ \"$(cat " + out +
                        " | wc -l)\" -lt 4 ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done; kill -" + signal +
                        " $p; wait $p; echo code=$?");
    CHECK(contains(r.out, "code=" + std::to_string(code)));
    CHECK(contains(read_file(out), "paused:"));
  }
}

TEST_CASE("Ctrl-C while the shell's output waits on a full pipe loses none of it") {
  // 200 `help` (about 880 KB) into a pipe nobody reads for half a second: the shell blocks in a
  // write, and a signal then must not fail that write (std::cout would drop all later output).
  silt::test::TempDir dir;
  const std::string in = dir / "in.txt", fifo = dir / "o", out = dir / "out.txt";
  {
    std::ofstream f(in);
    for (int k = 0; k < 200; ++k) f << "help\n";
    f << "print step\n";
  }
  const std::string shell = silt::test::silt_binary() + " shell " + scene_path("collision_normal") + " < " + in;
  const Result quiet = sh(shell + " | wc -c");
  const Result r =
      sh("mkfifo " + fifo + "; " + shell + " > " + fifo + " & p=$!; exec 4< " + fifo +
         "; sleep 0.5; for k in 1 2 3; do kill -INT $p; sleep 0.1; done; cat <&4 > " + out + "; wait $p; echo code=$?");
  CHECK(contains(r.out, "code=0"));
  const std::string text = read_file(out);
  CHECK(std::to_string(text.size()) + "\n" == quiet.out);
  CHECK(contains(text.substr(text.size() - 20), "step = 0"));
}

TEST_CASE("every output is checked before the first step, and a failed write is exit 4 in the summary too") {
  silt::test::TempDir dir;
  const std::string run = "run " + scene_path("pack_2d") + " --steps 300 --quiet";
  // A full device: the summary cannot be written; the exit code says so.
  Result r = silt_cli(run + " --summary /dev/full");
  CHECK(r.code == 4);
  CHECK(contains(r.out, "cannot write summary '/dev/full': No space left on device"));
  // A checkpoint into a directory that does not exist, or over a device: refused before any step.
  for (const std::string& save : {(dir / "none/x.ckpt"), std::string("/dev/null")}) {
    r = silt_cli(run + " --save " + save + " --stats " + (dir / "st.csv"));
    CHECK(r.code == 4);
    CHECK(contains(r.out, "cannot write checkpoint"));
    CHECK_FALSE(contains(r.out, "status"));  // the run did not start
  }
  CHECK(std::filesystem::exists("/dev/null"));
  CHECK_FALSE(std::filesystem::is_regular_file("/dev/null"));
  // Stats that cannot be written: the run goes on, the summary records exit code 4 like the process.
  r = silt_cli(run + " --stats /dev/full --summary " + (dir / "s.json"));
  CHECK(r.code == 4);
  CHECK(contains(r.out, "cannot write stats file '/dev/full'"));
  const auto j = read_json(dir / "s.json");
  CHECK(j["exit_code"] == 4);
  CHECK(j["status"] == "ok");
  CHECK(j["warnings"].dump().find("/dev/full") != std::string::npos);
}

TEST_CASE("a run refused for its --vtk or --frames directory keeps the stats file it would have written") {
  silt::test::TempDir dir;
  const std::string stats = dir / "keep.csv", file = dir / "plain";
  write_file(file, "not a directory\n");
  for (const std::string& opt :
       {"--vtk " + file, "--frames " + file, std::string("--vtk /proc/none"), std::string("--frames /proc/none")}) {
    CAPTURE(opt);
    write_file(stats, "earlier,rows\n1,2\n");
    // (paste_iso: a refused --frames came after its whole preparation, which prints "prepared")
    const Result r = silt_cli("run " + scene_path("paste_iso") + " --steps 5 --stats " + stats + " " + opt);
    CHECK(r.code == 4);
    CHECK_FALSE(contains(r.out, "prepared"));
    CHECK(read_file(stats) == "earlier,rows\n1,2\n");
  }
  // A plain file named as the VTK directory was taken, and the run went on to lose every file.
  const Result r = silt_cli("run " + scene_path("pack_2d") + " --steps 5 --quiet --vtk " + file);
  CHECK(r.code == 4);
  CHECK(contains(r.out, "not a directory"));
  CHECK_FALSE(contains(r.out, "status"));
}

TEST_CASE("a checkpoint that cannot be written at the end of a run: exit 4, in the summary as for the process") {
  silt::test::TempDir dir;
  // A file size limit, as a full disk or a quota would stop a write: the checkpoint of pack_2d
  // (about 60 kB) fails at the end of the run, the summary (a few kB) is written. With SIGXFSZ
  // ignored, the write returns EFBIG instead of killing the process.
  const Result r =
      sh("bash -c 'trap \"\" XFSZ; ulimit -f 24; " + silt::test::silt_binary() + " run " + scene_path("pack_2d") +
         " --steps 20 --quiet --save " + (dir / "end.ckpt") + " --summary " + (dir / "s.json") + "; echo code=$?'");
  CHECK(contains(r.out, "cannot write checkpoint"));
  CHECK(contains(r.out, "File too large"));
  CHECK(contains(r.out, "code=4"));
  CHECK_FALSE(std::filesystem::exists(dir / "end.ckpt"));
  const auto j = read_json(dir / "s.json");
  CHECK(j["exit_code"] == 4);
  CHECK(j["status"] == "ok");
  CHECK(j["warnings"].dump().find("end.ckpt") != std::string::npos);
}

TEST_CASE("a preparation that fails writes a summary and its last good state") {
  silt::test::TempDir dir;
  // A pressure a thousand times the scene's, on contacts as soft: the compression overlaps the
  // grains beyond limits.max_overlap within a thousand steps. (A box a billion times lighter than
  // its grains, which blew up in the first step, is refused when the scene is read now.)
  const Result r = silt_cli("run " + scene_path("shear2d_dry") + " --set box.pressure=1e3 --quiet --summary " +
                            (dir / "p.json") + " --stats " + (dir / "p.csv"));
  CHECK(r.code == 3);
  CHECK(contains(r.out, "numerical failure during the preparation"));
  const auto j = read_json(dir / "p.json");
  CHECK(j["status"] == "failed");
  CHECK(j["exit_code"] == 3);
  CHECK(j["failure"]["during"] == "preparation");
  CHECK(j["failure"]["parameter"].get<std::string>().size() > 0);
  REQUIRE(std::filesystem::exists(dir / "p.last_good.ckpt"));
  // The last good state is a checkpoint of the same grains: it restores, and the compression goes
  // on from its step (it was run as the scene's shear from there); from grains already overlapped
  // by nearly 20 %, the next step overlaps them past the limit.
  const Result again =
      silt_cli("run " + scene_path("shear2d_dry") + " --quiet --steps 10 --restore " + (dir / "p.last_good.ckpt"));
  CHECK(again.code == 3);
  CHECK(contains(again.out, "numerical failure during the preparation: step 924,"));
  std::filesystem::remove("shear2d_dry.last_good.ckpt");  // (its own, beside the scene's name)
}

TEST_CASE("the final state is sampled exactly once") {
  silt::test::TempDir dir;
  for (const auto& steps_rows : {std::pair<int, size_t>{1005, 12}, {1000, 11}}) {
    const auto [steps, rows_expected] = steps_rows;
    CAPTURE(steps_rows.first);
    const Result r = silt_cli("run " + scene_path("pack_2d") + " --steps " + std::to_string(steps) +
                              " --every 100 --observe t,step --quiet --stats " + (dir / "st.csv"));
    REQUIRE(r.code == 0);
    const auto rows = csv_rows(dir / "st.csv");
    CHECK(rows.size() == rows_expected);
    CHECK(step_of(rows.back()) == steps);
  }
  // Two runs in the shell (pack_2d samples every 5000 steps): the start, the end of the first run
  // and the end of the second, each once; the boundary between them is not sampled twice.
  auto samples = [](const std::string& runs) {
    silt::test::Fixture f;
    REQUIRE(f.run("load " + scene_path("pack_2d")));
    std::istringstream in(runs);
    std::string line;
    while (std::getline(in, line)) REQUIRE(f.run(line));
    f.take_out();
    REQUIRE(f.run("stats"));
    const std::string out = f.take_out();
    const auto at = out.find("\nt ");
    REQUIRE(at != std::string::npos);
    const std::string row = out.substr(at + 1, out.find('\n', at + 1) - at - 1);
    return std::stoi(row.substr(row.find_last_of(' ') + 1));
  };
  CHECK(samples("run 300") == 2);
  CHECK(samples("run 150\nrun 150") == 3);
  CHECK(samples("run 150\nrun 0\nrun 150") == 3);
}

TEST_CASE("the command line reads numbers as the shell does, with silt's messages") {
  silt::test::TempDir dir;
  const std::string run = "run " + scene_path("pack_2d") + " --quiet --summary " + (dir / "s.json");
  Result r = silt_cli(run + " --steps 1e3");
  REQUIRE(r.code == 0);
  CHECK(read_json(dir / "s.json")["steps"] == 1000);
  r = silt_cli(run + " --time 0.5s");
  REQUIRE(r.code == 0);
  CHECK(read_json(dir / "s.json")["sim_time"].get<double>() >= 0.5);
  for (const char* bad :
       {"--steps 1.5", "--steps -3", "--time -1", "--average-from nan", "--threads 0", "--threads 1e9", "--every 0",
        "--time 0x10", "--steps 0x10"}) {  // (strtod's hexadecimal: --time 0x10 ran 16 s)
    CAPTURE(bad);
    r = silt_cli(run + " " + bad);
    CHECK(r.code == 1);
    CHECK(r.out.size() < 200);  // no 300-digit bounds
    CHECK(contains(r.out, "is not a"));
  }
  // --average-from takes seconds as --time does, and one past the run's end says that nothing is
  // averaged (every mean was null without a word).
  r = silt_cli(run + " --steps 10 --average-from 1e6s");
  REQUIRE(r.code == 0);
  const auto late = read_json(dir / "s.json");
  CHECK(late["average_from"] == 1e6);
  bool said = false;
  for (const auto& w : late["warnings"]) said = said || contains(w.get<std::string>(), "after the run's end");
  CHECK(said);
  // A final checkpoint that replaces the one restored is allowed (a run continued in place), and said.
  REQUIRE(silt_cli(run + " --steps 10 --save " + (dir / "c.ckpt")).code == 0);
  r = silt_cli(run + " --steps 10 --restore " + (dir / "c.ckpt") + " --save " + (dir / "c.ckpt"));
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "replaces the checkpoint restored (a run continued in place)"));
  // More threads than cores: granted the cores, said in silt's words; the summary has the grant.
  r = silt_cli(run + " --steps 100 --threads 4096");
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "silt: --threads 4096: this process can use"));
  CHECK_FALSE(contains(r.out, "TBB Warning"));
  CHECK(read_json(dir / "s.json")["threads"].get<int>() < 4096);
}

TEST_CASE("a second --frames run into the same directory removes the first run's frames") {
  silt::test::TempDir dir;
  const std::string run = "run " + scene_path("collision_normal") + " --quiet --frame-every 10 --frames " + (dir / "f");
  REQUIRE(silt_cli(run + " --steps 30").code == 0);
  CHECK(std::filesystem::exists(dir / "f/frame_000003.png"));
  silt::test::write_file(dir / "f/notes.txt", "mine");
  const Result r = silt_cli(run + " --steps 10");
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "4 frame(s) of an earlier run removed"));
  CHECK_FALSE(std::filesystem::exists(dir / "f/frame_000003.png"));
  CHECK(std::filesystem::exists(dir / "f/frame_000001.png"));
  CHECK(std::filesystem::exists(dir / "f/notes.txt"));  // only silt's own frames go
}
