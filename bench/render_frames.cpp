// Frame time of the renderer at 1920 x 1080: the chute (17,600 spheres and their force chains) with
// opaque grains and with the 3D default (grains at opacity 0.25 over the chains), and a 2D
// vorticity field of 512 x 512 cells under the 224 disks of pack_2d, with llvmpipe on 1 and 2
// threads. Target: under 0.5 s per frame.
//
//   build/bench/render_frames [--frames N] [--settled FILE]
//
// FILE is a checkpoint of the settled chute, e.g. from
//   build/silt run scenes/chute.toml --steps 30000 --save /tmp/chute_settled.ckpt
// (a dense bed, about 40,000 contacts); without it the bed of 3,000 steps is drawn, and said so.
// Each (case, threads) runs in a child process (llvmpipe fixes its thread count at the first GL
// context). Times: building the RenderScene, rasterizing, overlays, PNG encoding; the median of
// each over N frames after one warm-up frame (the machine is shared: medians resist the frames
// that another job slowed). Appends to bench/results/render.csv with the number of chain
// segments drawn and the grains' opacity.
#include <algorithm>
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
  double build = 0, raster = 0, overlay = 0, png = 0, total = 0;
  size_t segments = 0;
  double opacity = 1;
  int64_t step = 0;  // of the state drawn
};

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

Times time_frames(const Model& m, const State& s, const render::View& v, const GridField* field, int frames,
                  int threads) {
  render::Rasterizer r(threads);
  std::vector<double> build, raster, overlay, png, total;
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
    t.segments = rs.segments.size();
    if (!rs.spheres.empty()) t.opacity = rs.spheres.back().color.a / 255.0;
    if (k == 0) continue;  // warm-up: context creation, shader compilation
    build.push_back(t1 - t0);
    raster.push_back(t2 - t1);
    overlay.push_back(t3 - t2);
    png.push_back(t4 - t3);
    total.push_back(t4 - t0);
  }
  std::remove("render_bench_frame.png");
  t.build = median(build);
  t.raster = median(raster);
  t.overlay = median(overlay);
  t.png = median(png);
  t.total = median(total);
  return t;
}

int child(const std::string& which, int threads, int frames, const std::string& settled) {
  const std::string dir = std::string(SILT_SOURCE_DIR) + "/scenes/";
  Times t;
  if (which != "vorticity") {
    Model m = compile(load_scene_file(dir + "chute.toml"));
    Simulation sim(m, 2);
    if (!settled.empty()) {
      sim.restore(read_checkpoint(settled, sim.model()));
    } else {
      for (int k = 0; k < 3000; ++k) sim.step();  // a loose bed with a few contacts
    }
    render::View v = sim.model().render;
    v.width = 1920;
    v.height = 1080;
    v.draw = {"grains", "chains", "colorbar", "time"};
    v.color_by = "";                                       // flat grains, the chains' colour bar
    v.grain_opacity = which == "chute_opaque" ? 1.0 : -1;  // -1: the 3D default with chains, 0.25
    t = time_frames(sim.model(), sim.state(), v, nullptr, frames, threads);
    t.step = sim.state().step;
  } else {
    Model m = compile(load_scene_file(dir + "pack_2d.toml"));
    Simulation sim(m, 2);
    sim.prepare();
    const GridField g = render::taylor_green_vorticity(512, 512, sim.state().box.len[0], 1.0);
    render::View v = sim.model().render;
    v.width = 1920;
    v.height = 1080;
    v.draw = {"field", "grains", "colorbar", "time", "scalebar"};
    t = time_frames(sim.model(), sim.state(), v, &g, frames, threads);
  }
  std::printf("%.6f %.6f %.6f %.6f %.6f %zu %.3f %lld\n", t.build, t.raster, t.overlay, t.png, t.total, t.segments,
              t.opacity, static_cast<long long>(t.step));
  return 0;
}

int run(int argc, char** argv) {
  int frames = 7;
  std::string settled;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::max(1, std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--settled")) settled = argv[i + 1];
    else if (!std::strcmp(argv[i], "--child")) {
      const std::string spec = argv[i + 1];  // case:threads
      return child(spec.substr(0, spec.find(':')), std::atoi(spec.substr(spec.find(':') + 1).c_str()), frames, settled);
    }
  }
  if (!settled.empty() && !std::ifstream(settled).good()) {
    std::fprintf(stderr, "render_frames: no checkpoint '%s'\n", settled.c_str());
    return 2;
  }
  if (settled.empty())
    std::fprintf(stderr, "render_frames: no --settled checkpoint: the chute after 3,000 steps, few contacts\n");
  std::printf("1920 x 1080, median of %d frames\n", frames);
  std::printf("%-30s %7s %8s %7s %9s %9s %9s %9s %9s\n", "frame", "threads", "segments", "opacity", "build ms",
              "raster ms", "overlay ms", "png ms", "total ms");
  for (const char* which : {"chute_opaque", "chute", "vorticity"}) {
    for (int threads : {1, 2}) {
      std::ostringstream cmd;
      cmd << argv[0] << " --frames " << frames << (settled.empty() ? "" : " --settled " + settled) << " --child "
          << which << ":" << threads;
      std::istringstream out(bench::capture(cmd.str()));
      Times t;
      if (!(out >> t.build >> t.raster >> t.overlay >> t.png >> t.total >> t.segments >> t.opacity >> t.step)) {
        std::fprintf(stderr, "child %s:%d failed\n", which, threads);
        return 1;
      }
      std::printf("%-30s %7d %8zu %7.2f %9.1f %9.1f %9.1f %9.1f %9.1f\n", which, threads, t.segments, t.opacity,
                  1e3 * t.build, 1e3 * t.raster, 1e3 * t.overlay, 1e3 * t.png, 1e3 * t.total);
      std::ostringstream row;
      row << bench::today() << "," << which << "," << threads << "," << t.build << "," << t.raster << "," << t.overlay
          << "," << t.png << "," << t.total << "," << t.segments << "," << t.opacity << ","
          << (std::strcmp(which, "vorticity") == 0 ? std::string("pack_2d prepared")
                                                   : "chute step " + std::to_string(t.step))
          << ",median of " << frames;
      bench::append_csv(std::string(SILT_SOURCE_DIR) + "/bench/results/render.csv",
                        "date,case,threads,build_s,raster_s,overlay_s,png_s,total_s,segments,grain_opacity,bed,stat",
                        row.str());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
