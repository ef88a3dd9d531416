// The frame writer: numbered PNGs, at most one frame waiting, and errors that stop the frames only.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>

#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;

namespace {

// A sink that holds each frame until the test lets it go, and tells which frames it has begun.
struct Gate {
  std::mutex mutex;
  std::condition_variable cv;
  int64_t released = -1;  // frames up to this index may finish
  std::vector<int64_t> begun;

  void sink(int64_t index) {
    std::unique_lock<std::mutex> lock(mutex);
    begun.push_back(index);
    cv.notify_all();
    cv.wait(lock, [&] { return index <= released; });
  }
  void release(int64_t upto) {
    std::lock_guard<std::mutex> lock(mutex);
    released = upto;
    cv.notify_all();
  }
  // Waits (up to 10 s, against a hang) until frame `index` has begun.
  bool wait_begun(int64_t index) {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, std::chrono::seconds(10), [&] { return begun.size() > static_cast<size_t>(index); });
  }
};

bool done_soon(std::future<void>& f) { return f.wait_for(std::chrono::seconds(10)) == std::future_status::ready; }
bool still_blocked(std::future<void>& f) {
  return f.wait_for(std::chrono::milliseconds(200)) == std::future_status::timeout;
}

// `silt ARGS`, its exit code; its output in `out`.
int silt_run(const std::string& args, std::string& out) {
  const int status = std::system((test::silt_binary() + " " + args + " > render_cli.out 2>&1").c_str());
  {
    std::ifstream in("render_cli.out");
    out.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::filesystem::remove("render_cli.out");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("the frame writer numbers its PNGs, and a bad directory is refused") {
  auto sim = test::simulation_from(test::kRow);
  std::filesystem::remove_all("frame_writer_test");
  {
    FrameWriter w("frame_writer_test", 1);
    for (int k = 0; k < 3; ++k)
      w.submit(build_render_scene(sim->model(), sim->state(), test::plain_view(64, 32, {"grains"})));
    w.finish();
    CHECK(w.written() == 3);
    CHECK(w.error().empty());
  }
  for (const char* f : {"frame_writer_test/frame_000000.png", "frame_writer_test/frame_000002.png"})
    CHECK(read_png(f).width == 64);
  std::filesystem::remove_all("frame_writer_test");
  CHECK_THROWS_AS(FrameWriter("no_such_dir/sub"), IoError);
}

TEST_CASE("submit() blocks for at most one frame: only while one frame is drawn and another waits") {
  Gate gate;
  FrameWriter w([&](const RenderScene&, int64_t index) { gate.sink(index); });
  auto submit = [&] { return std::async(std::launch::async, [&] { w.submit(RenderScene{}); }); };
  // Frame 0 goes to the worker at once: the caller does not wait.
  auto s0 = submit();
  CHECK(done_soon(s0));
  CHECK(gate.wait_begun(0));
  // While frame 0 is drawn, frame 1 waits in the slot: the caller does not wait either.
  auto s1 = submit();
  CHECK(done_soon(s1));
  // Frame 2 finds frame 0 drawn and frame 1 waiting: its caller waits ...
  auto s2 = submit();
  CHECK(still_blocked(s2));
  // ... until frame 0 is done (not frame 1): one frame.
  gate.release(0);
  CHECK(done_soon(s2));
  CHECK(gate.wait_begun(1));
  CHECK(gate.begun == std::vector<int64_t>{0, 1});
  gate.release(2);
  w.finish();
  CHECK(w.written() == 3);
  CHECK(gate.begun == std::vector<int64_t>{0, 1, 2});
}

TEST_CASE("a frame that fails stops the frames, not the caller") {
  std::vector<int64_t> drawn;
  FrameWriter w([&](const RenderScene&, int64_t index) {
    if (index == 1) throw IoError("disk full");
    drawn.push_back(index);
  });
  for (int k = 0; k < 5; ++k) w.submit(RenderScene{});  // returns: never blocks on a stopped writer
  w.finish();
  CHECK(w.error() == "disk full");
  CHECK(w.written() == 1);
  CHECK(drawn == std::vector<int64_t>{0});
}

TEST_CASE("silt run: a frame that cannot be written stops the frames, the run goes on to its end, exit code 4") {
  const std::string dir = "render_cli_frames";
  std::filesystem::remove_all(dir);
  std::filesystem::remove("render_cli_end.ckpt");
  // The third frame's name is taken by a directory: writing it fails mid-run.
  std::filesystem::create_directories(dir + "/frame_000002.png/x");
  std::string out;
  const int code =
      silt_run("run " + test::scene_path("collision_normal") + " --quiet --steps 1000 --frames " + dir +
                   " --frame-every 100 --set render.width=64 --set render.height=32 --save render_cli_end.ckpt",
               out);
  CAPTURE(out);
  CHECK(code == 4);
  CHECK(out.find("frames stopped (the run went on)") != std::string::npos);
  CHECK(out.find(": 1000 steps") != std::string::npos);
  CHECK(std::filesystem::exists("render_cli_end.ckpt"));  // the end of the run is saved
  CHECK(std::filesystem::exists(dir + "/frame_000001.png"));
  CHECK_FALSE(std::filesystem::exists(dir + "/frame_000003.png"));
  // A frame directory that cannot be made: refused before the run, with the same exit code.
  CHECK(silt_run("run " + test::scene_path("collision_normal") + " --quiet --steps 10 --frames no_such_dir/sub", out) ==
        4);
  CHECK(out.find("cannot create the frame directory") != std::string::npos);
  std::filesystem::remove_all(dir);
  std::filesystem::remove("render_cli_end.ckpt");
}

TEST_CASE("silt run: frames and VTK files end with the run's last state, as the stats do") {
  // (--steps 250 with --every 100 drew steps 0, 100 and 200, where the stats end at 250)
  const std::string frames = "render_cli_last_frames", vtk = "render_cli_last_vtk";
  std::filesystem::remove_all(frames);
  std::filesystem::remove_all(vtk);
  std::string out;
  REQUIRE(silt_run("run " + test::scene_path("collision_normal") + " --quiet --steps 250 --every 100 --frames " +
                       frames + " --vtk " + vtk + " --set render.width=64 --set render.height=32",
                   out) == 0);
  CAPTURE(out);
  CHECK(std::filesystem::exists(frames + "/frame_000003.png"));
  CHECK_FALSE(std::filesystem::exists(frames + "/frame_000004.png"));
  CHECK(std::filesystem::exists(vtk + "/grains_000003.vtu"));
  CHECK_FALSE(std::filesystem::exists(vtk + "/grains_000004.vtu"));
  // A run ending on a multiple of the period draws its end once.
  REQUIRE(silt_run("run " + test::scene_path("collision_normal") + " --quiet --steps 200 --every 100 --frames " +
                       frames + " --set render.width=64 --set render.height=32",
                   out) == 0);
  CHECK(std::filesystem::exists(frames + "/frame_000002.png"));
  CHECK_FALSE(std::filesystem::exists(frames + "/frame_000003.png"));
  std::filesystem::remove_all(frames);
  std::filesystem::remove_all(vtk);
}
