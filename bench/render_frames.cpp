// Frame time of the renderer at 1920 x 1080: the chute (17,600 spheres and their force chains)
// and a 2D vorticity field of 512 x 512 cells under the 224 disks of pack_2d, with llvmpipe on 1
// and 2 threads. Target: under 0.5 s per frame.
//
//   build/bench/render_frames [--frames N] [--settled FILE]
//
// Each (case, threads) runs in a child process (llvmpipe fixes its thread count at the first GL
// context). Times: building the RenderScene, rasterizing, overlays, PNG encoding; mean over
// N frames after one warm-up frame. Appends to bench/results/render.csv.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "bench_util.hpp"
#include "silt/io.hpp"
#include "silt/render.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

struct Times {
  double build = 0, raster = 0, overlay = 0, png = 0;
};

Times time_frames(const Model& m, const State& s, const render::View& v, const render::ScalarGrid* field, int frames,
                  int threads) {
  render::Rasterizer r(threads);
  Times t;
  for (int k = 0; k <= frames; ++k) {
    const double t0 = bench::now_s();
    const render::RenderScene rs = render::build_render_scene(m, s, v, field);
    const double t1 = bench::now_s();
    render::Image img = r.draw(rs);
    const double t2 = bench::now_s();
    render::compose_overlays(rs, img);
    const double t3 = bench::now_s();
    render::write_png("render_bench_frame.png", img);
    const double t4 = bench::now_s();
    if (k == 0) continue;  // warm-up: context creation, shader compilation
    t.build += (t1 - t0) / frames;
    t.raster += (t2 - t1) / frames;
    t.overlay += (t3 - t2) / frames;
    t.png += (t4 - t3) / frames;
  }
  std::remove("render_bench_frame.png");
  return t;
}

int child(const std::string& which, int threads, int frames, const std::string& settled) {
  const std::string dir = std::string(SILT_SOURCE_DIR) + "/scenes/";
  Times t;
  if (which == "chute") {
    Model m = compile(load_scene_file(dir + "chute.toml"));
    Simulation sim(m, 2);
    if (!settled.empty() && std::ifstream(settled).good()) {
      sim.restore(read_checkpoint(settled, sim.model()));
    } else {
      for (int k = 0; k < 3000; ++k) sim.step();  // a bed with contacts
    }
    render::View v = sim.model().render;
    v.width = 1920;
    v.height = 1080;
    v.draw = {"grains", "chains", "colorbar", "time"};
    t = time_frames(sim.model(), sim.state(), v, nullptr, frames, threads);
  } else {
    Model m = compile(load_scene_file(dir + "pack_2d.toml"));
    Simulation sim(m, 2);
    sim.prepare();
    const render::ScalarGrid g = render::taylor_green_vorticity(512, 512, sim.state().box.len[0], 1.0);
    render::View v = sim.model().render;
    v.width = 1920;
    v.height = 1080;
    v.draw = {"field", "grains", "colorbar", "time", "scalebar"};
    t = time_frames(sim.model(), sim.state(), v, &g, frames, threads);
  }
  std::printf("%.6f %.6f %.6f %.6f\n", t.build, t.raster, t.overlay, t.png);
  return 0;
}

int run(int argc, char** argv) {
  int frames = 5;
  std::string settled;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--settled")) settled = argv[i + 1];
    else if (!std::strcmp(argv[i], "--child")) {
      const std::string spec = argv[i + 1];  // case:threads
      return child(spec.substr(0, spec.find(':')), std::atoi(spec.substr(spec.find(':') + 1).c_str()), frames, settled);
    }
  }
  std::printf("%-34s %8s %10s %10s %10s %10s %10s\n", "1920 x 1080 frame", "threads", "build ms", "raster ms",
              "overlay ms", "png ms", "total ms");
  for (const char* which : {"chute", "vorticity"}) {
    for (int threads : {1, 2}) {
      std::ostringstream cmd;
      cmd << argv[0] << " --frames " << frames << (settled.empty() ? "" : " --settled " + settled) << " --child " << which
          << ":" << threads;
      std::istringstream out(bench::capture(cmd.str()));
      Times t;
      if (!(out >> t.build >> t.raster >> t.overlay >> t.png)) {
        std::fprintf(stderr, "child %s:%d failed\n", which, threads);
        return 1;
      }
      const double total = t.build + t.raster + t.overlay + t.png;
      const char* label = std::strcmp(which, "chute") == 0 ? "chute: 17,600 spheres + chains" : "vorticity 512^2 + 224 disks";
      std::printf("%-34s %8d %10.1f %10.1f %10.1f %10.1f %10.1f\n", label, threads, 1e3 * t.build, 1e3 * t.raster,
                  1e3 * t.overlay, 1e3 * t.png, 1e3 * total);
      std::ostringstream row;
      row << bench::today() << "," << which << "," << threads << "," << t.build << "," << t.raster << "," << t.overlay
          << "," << t.png << "," << total;
      bench::append_csv(std::string(SILT_SOURCE_DIR) + "/bench/results/render.csv",
                        "date,case,threads,build_s,raster_s,overlay_s,png_s,total_s", row.str());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
