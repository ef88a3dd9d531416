// The off-screen renderer: grains, force chains and scalar fields (vorticity) as PNG frames.
//
//   build_render_scene(Model, State, View [, field]) -> RenderScene   (plain data, no GL)
//   Rasterizer::draw(RenderScene) -> Image                            (all OSMesa/GL code)
//   compose_overlays(RenderScene, Image)                              (text, colour bar, scale bar)
//   write_png(path, Image)                                            (libpng)
//
// The renderer reads the engine only through its public headers and never changes a State.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "silt/io.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::render {

class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Rgba {
  uint8_t r = 0, g = 0, b = 0, a = 255;
  bool operator==(const Rgba&) const = default;
};

// A colormap: 256 colours read from assets/<name>.csv.
class Colormap {
 public:
  static const Colormap& get(const std::string& name);  // throws RenderError for unknown names
  Rgba at(double t) const;                              // t in [0, 1], clamped; NaN gives grey
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::vector<std::array<float, 3>> rgb_;
};
// Directory of the colormaps and the font (SILT_ASSETS overrides the built-in path).
std::string assets_dir();

// Fields on grids: silt::GridField (silt/io.hpp), a scalar or a 3-component vector at the cell
// centres. A scalar field is drawn with the diverging map, symmetric about zero; a vector field
// through View::slice_component: a component (diverging) or its magnitude (sequential, from 0).
//
// Analytic test fields, until the fluid module provides real ones: a Lamb-Oseen vortex
// (circulation gamma, core radius rc) and a Taylor-Green cell give the out-of-plane vorticity on
// an nx x ny grid; the 3D Taylor-Green vortex gives the vorticity vector on an n^3 grid.
GridField lamb_oseen_vorticity(int nx, int ny, std::array<double, 2> lo, std::array<double, 2> hi,
                               std::array<double, 2> centre, double gamma, double rc);
GridField taylor_green_vorticity(int nx, int ny, double length, double u0);
GridField taylor_green_vorticity_3d(int n, double length, double u0);
// One component ("x", "y", "z") or the "magnitude" of a vector field, as a scalar field on the
// same grid (a scalar field is returned as it is). Throws RenderError for other names.
GridField field_component(const GridField& f, const std::string& which);

// Camera: world -> clip, column-major 4x4 matrices, and whether it is orthographic.
struct Camera {
  std::array<float, 16> view{}, proj{};
  bool ortho = true;
  std::array<float, 3> eye{0, 0, 1};
  std::array<double, 3> target{0, 0, 0};     // the point looked at
  double pixels_per_unit = 0;                // ortho: everywhere; perspective: in the plane through
                                             // the target facing the camera
  std::array<int, 4> domain_px{0, 0, 0, 0};  // ortho only: the box in pixels (x, y from the bottom, w, h)
};

struct TextItem {
  std::string text;
  int x = 0, y = 0;  // pixel of the baseline start, origin top-left
  int size = 16;     // pixel height
  Rgba color;
};

struct ColorBar {
  bool on = false;
  int x = 0, y = 0, width = 0, height = 0;  // pixel rectangle, origin top-left
  std::string colormap;
  double lo = 0, hi = 1;
  std::string label;
  int label_above = 8;  // pixels from the bar's top up to its label's baseline
};

struct ScaleBar {
  bool on = false;
  int x = 0, y = 0, width_px = 0;
  std::string label;
};

// Everything a frame shows, in world coordinates or pixels; no GL.
struct RenderScene {
  int width = 0, height = 0;
  Rgba background{255, 255, 255, 255};
  Camera camera;
  struct Sphere {
    std::array<float, 3> centre;
    float radius;
    Rgba color;
  };
  std::vector<Sphere> spheres;  // disks in 2D (z = 0)
  struct Segment {
    std::array<float, 3> a, b;
    float width;  // world units
    Rgba color;
  };
  std::vector<Segment> segments;  // force chains: capsules (round ends), lit in 3D, flat in 2D
  struct Line {
    std::array<float, 3> a, b;
    float width_px;
    Rgba color;
  };
  std::vector<Line> lines;  // the box outline: a constant width on screen, depth-tested
  struct FieldQuad {
    std::array<std::array<float, 3>, 4> corners;  // lo-lo, hi-lo, hi-hi, lo-hi of the texture
    int tex_w = 0, tex_h = 0;
    std::vector<Rgba> texels;  // tex_w * tex_h, row 0 at the first corner
  };
  std::vector<FieldQuad> fields;        // texels of alpha 0 (off the grid) are not drawn
  std::array<int, 4> clip{0, 0, 0, 0};  // pixel scissor x, y (from the bottom), w, h; w = 0: none
  std::vector<TextItem> texts;
  ColorBar colorbar;
  ColorBar lubrication_bar;  // the lubrication forces' own, left of the chains' bar where both are drawn
  ScaleBar scalebar;
  std::vector<std::string> warnings;  // e.g. NaN values in a field
  bool cull_hidden = true;            // 3D: skip the grains and chains that opaque grains hide wholly (same picture)
};

// What to draw and how (from Model::render, or set by hand).
using View = RenderSettings;

// Build a frame's content. `field` (optional) is drawn when the view asks for it.
RenderScene build_render_scene(const Model& m, const State& s, const View& v, const GridField* field = nullptr);

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // row 0 at the top
  Rgba pixel(int x, int y) const {
    const uint8_t* p = &rgba[(static_cast<size_t>(y) * width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
};

// All GL lives behind this: an OSMesa context (llvmpipe) drawing RenderScenes. One per thread.
class Rasterizer {
 public:
  // threads: llvmpipe rasterizer threads (0: its default); read when the first context is made.
  explicit Rasterizer(int threads = 0);
  ~Rasterizer();
  Rasterizer(const Rasterizer&) = delete;
  Rasterizer& operator=(const Rasterizer&) = delete;
  Image draw(const RenderScene& scene);  // throws RenderError

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Text (FreeType, DejaVu Sans), colour bar and scale bar, drawn into the image.
void compose_overlays(const RenderScene& scene, Image& image);
// Width in pixels of `text` in the overlays' font at `size` pixels.
int text_width(const std::string& text, int size);

// A complete frame: build, rasterize, overlays.
Image render_frame(Rasterizer& r, const Model& m, const State& s, const View& v, const GridField* field = nullptr);

// Writes frames DIR/frame_000000.png, ... on a worker thread (with its own Rasterizer), so the
// simulation goes on while a frame is drawn. At most one frame waits: submit() returns at once
// when the worker is free or busy with one frame, and otherwise blocks until that frame is done,
// so for at most the time of one frame. An error (no GL context, disk full) stops the frames
// (later submits return at once and drop theirs), not the caller.
class FrameWriter {
 public:
  // What the worker does with frame number `index`; throws to stop the frames.
  using Sink = std::function<void(const RenderScene& scene, int64_t index)>;
  // Creates dir, and removes the frames an earlier run left there (frame_NNNNNN.png, so that a
  // film is of one run); throws IoError.
  FrameWriter(std::string dir, int threads = 0);
  explicit FrameWriter(Sink sink);  // frames to `sink`, on the worker thread
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;
  void submit(RenderScene scene);
  void finish();  // waits for the pending frame
  int64_t written() const;
  std::string error() const;                    // "" while all is well
  int64_t removed() const { return removed_; }  // an earlier run's frames removed from dir
  // Whether `path` is a frame's name in `dir` (a file a FrameWriter on dir overwrites or removes).
  static bool owns(const std::string& path, const std::string& dir);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int64_t removed_ = 0;
};

void write_png(const std::string& path, const Image& image);  // RGB (frames are opaque); throws IoError
Image read_png(const std::string& path);                      // throws IoError

}  // namespace silt::render
