// All OpenGL of silt: an OSMesa (llvmpipe) core-profile 4.5 context drawing a RenderScene.
//
// Spheres (and the disks of 2D scenes) are impostors: one camera-facing quad per grain whose
// fragment shader intersects the view ray with the sphere, shades it and writes the true depth,
// so overlapping grains hide each other correctly. Force chains are capsule impostors likewise
// (lit in 3D, flat in 2D), the box outline lines of a constant width on screen, fields textured
// quads (shaders.hpp). Translucent grains are drawn last, back to front.
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <string>

#include "render/camera.hpp"
#include "render/occlusion.hpp"
#include "render/shaders.hpp"
#include "silt/render.hpp"

namespace silt::render {
namespace {

// A shader from the version line, a prefix of shared code and its own source.
GLuint compile_shader(GLenum type, const char* prefix, const char* src) {
  const GLuint s = glCreateShader(type);
  const char* parts[3] = {shaders::kVersion, prefix, src};
  glShaderSource(s, 3, parts, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw RenderError(std::string("shader compilation failed: ") + log);
  }
  return s;
}

GLuint link_program(const char* vs_prefix, const char* vs, const char* fs_prefix, const char* fs) {
  const GLuint p = glCreateProgram();
  const GLuint v = compile_shader(GL_VERTEX_SHADER, vs_prefix, vs),
               f = compile_shader(GL_FRAGMENT_SHADER, fs_prefix, fs);
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    throw RenderError(std::string("shader link failed: ") + log);
  }
  return p;
}

struct SphereVertex {
  float centre[3];
  float radius;
  uint8_t color[4];
};
struct SegmentVertex {
  float a[3], b[3];
  float width;
  uint8_t color[4];
};

}  // namespace

struct Rasterizer::Impl {
  OSMesaContext ctx = nullptr;
  std::vector<uint8_t> buffer;
  int width = 0, height = 0;
  GLuint sphere_prog = 0, capsule_prog = 0, line_prog = 0, field_prog = 0;
  GLuint vao = 0, vbo = 0, tex = 0;

  void make_current(int w, int h) {
    if (!ctx) {
      const int attribs[] = {OSMESA_FORMAT,
                             OSMESA_RGBA,
                             OSMESA_DEPTH_BITS,
                             24,
                             OSMESA_PROFILE,
                             OSMESA_CORE_PROFILE,
                             OSMESA_CONTEXT_MAJOR_VERSION,
                             4,
                             OSMESA_CONTEXT_MINOR_VERSION,
                             5,
                             0};
      ctx = OSMesaCreateContextAttribs(attribs, nullptr);
      if (!ctx) throw RenderError("cannot create an OSMesa OpenGL 4.5 core context (is libosmesa6 installed?)");
    }
    if (w != width || h != height || buffer.empty()) {
      buffer.assign(static_cast<size_t>(w) * h * 4, 0);
      width = w;
      height = h;
    }
    if (!OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, w, h))
      throw RenderError("cannot bind the OSMesa context to a " + std::to_string(w) + " x " + std::to_string(h) +
                        " image");
    if (!sphere_prog) {
      using namespace shaders;
      sphere_prog = link_program("", kSphereVs, kImpostor, kSphereFs);
      capsule_prog = link_program(kSegmentInputs, kCapsuleVs, kImpostor, kCapsuleFs);
      line_prog = link_program(kSegmentInputs, kLineVs, "", kFlatFs);
      field_prog = link_program("", kFieldVs, "", kFieldFs);
      glGenVertexArrays(1, &vao);
      glGenBuffers(1, &vbo);
      glGenTextures(1, &tex);
    }
  }

  void set_camera(GLuint prog, const Camera& c) {
    glUseProgram(prog);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_view"), 1, GL_FALSE, c.view.data());
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_proj"), 1, GL_FALSE, c.proj.data());
    const GLint o = glGetUniformLocation(prog, "u_ortho");
    if (o >= 0) glUniform1i(o, c.ortho ? 1 : 0);
  }

  void draw_spheres(const std::vector<SphereVertex>& v) {
    if (v.empty()) return;
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, v.size() * sizeof(SphereVertex), v.data(), GL_STREAM_DRAW);
    const GLsizei st = sizeof(SphereVertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, st, reinterpret_cast<void*>(offsetof(SphereVertex, centre)));
    glVertexAttribDivisor(0, 1);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, st, reinterpret_cast<void*>(offsetof(SphereVertex, radius)));
    glVertexAttribDivisor(1, 1);
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, st, reinterpret_cast<void*>(offsetof(SphereVertex, color)));
    glVertexAttribDivisor(2, 1);
    glDisableVertexAttribArray(3);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(v.size()));
  }

  // Instances of `vertices` strip vertices each (a quad: 4).
  void draw_segments(const std::vector<SegmentVertex>& v, GLsizei vertices) {
    if (v.empty()) return;
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, v.size() * sizeof(SegmentVertex), v.data(), GL_STREAM_DRAW);
    const GLsizei st = sizeof(SegmentVertex);
    const GLint sizes[4] = {3, 3, 1, 4};
    const size_t offs[4] = {offsetof(SegmentVertex, a), offsetof(SegmentVertex, b), offsetof(SegmentVertex, width),
                            offsetof(SegmentVertex, color)};
    for (GLuint k = 0; k < 4; ++k) {
      glEnableVertexAttribArray(k);
      glVertexAttribPointer(k, sizes[k], k == 3 ? GL_UNSIGNED_BYTE : GL_FLOAT, k == 3 ? GL_TRUE : GL_FALSE, st,
                            reinterpret_cast<void*>(offs[k]));
      glVertexAttribDivisor(k, 1);
    }
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, vertices, static_cast<GLsizei>(v.size()));
  }

  void draw_field(const RenderScene::FieldQuad& q) {
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, q.tex_w, q.tex_h, 0, GL_RGBA, GL_UNSIGNED_BYTE, q.texels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const int order[4] = {0, 1, 3, 2};  // triangle strip
    float data[4][5];
    for (int k = 0; k < 4; ++k) {
      const int c = order[k];
      for (int a = 0; a < 3; ++a) data[k][a] = q.corners[c][a];
      data[k][3] = uv[c][0];
      data[k][4] = uv[c][1];
    }
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof data, data, GL_STREAM_DRAW);
    for (GLuint k = 0; k < 4; ++k) glVertexAttribDivisor(k, 0);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
    glDisableVertexAttribArray(2);
    glDisableVertexAttribArray(3);
    glUniform1i(glGetUniformLocation(field_prog, "u_tex"), 0);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  }

  ~Impl() {
    if (ctx) OSMesaDestroyContext(ctx);
  }
};

Rasterizer::Rasterizer(int threads) : impl_(std::make_unique<Impl>()) {
  // llvmpipe reads its thread count once, when the first context of the process is made.
  if (threads > 0) setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
}

Rasterizer::~Rasterizer() = default;

Image Rasterizer::draw(const RenderScene& scene) {
  Impl& g = *impl_;
  g.make_current(scene.width, scene.height);
  glViewport(0, 0, scene.width, scene.height);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(scene.background.r / 255.0f, scene.background.g / 255.0f, scene.background.b / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  if (scene.clip[2] > 0) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(scene.clip[0], scene.clip[1], scene.clip[2], scene.clip[3]);
  }
  // Fields first (opaque, behind), then chains and opaque grains, the box outline, and the
  // translucent grains over them.
  g.set_camera(g.field_prog, scene.camera);
  for (const auto& q : scene.fields) g.draw_field(q);
  const Hidden hidden = scene.cull_hidden ? find_hidden(scene) : Hidden{};
  auto shown = [](const std::vector<char>& flags, size_t k) { return flags.empty() || !flags[k]; };
  auto segments = [&](const auto& from, auto width, const std::vector<char>& skip) {
    std::vector<SegmentVertex> out;
    out.reserve(from.size());
    for (size_t k = 0; k < from.size(); ++k) {
      if (!shown(skip, k)) continue;
      const auto& s = from[k];
      SegmentVertex v;
      std::copy(s.a.begin(), s.a.end(), v.a);
      std::copy(s.b.begin(), s.b.end(), v.b);
      v.width = width(s);
      const uint8_t c[4] = {s.color.r, s.color.g, s.color.b, s.color.a};
      std::copy(c, c + 4, v.color);
      out.push_back(v);
    }
    return out;
  };
  g.set_camera(g.capsule_prog, scene.camera);
  glUniform1i(glGetUniformLocation(g.capsule_prog, "u_lit"), scene.camera.ortho ? 0 : 1);
  glUniform2f(glGetUniformLocation(g.capsule_prog, "u_viewport"), static_cast<float>(scene.width),
              static_cast<float>(scene.height));
  g.draw_segments(segments(
                      scene.segments, [](const RenderScene::Segment& s) { return s.width; }, hidden.segments),
                  4);
  std::vector<SphereVertex> opaque, clear;
  opaque.reserve(scene.spheres.size());
  std::vector<float> depth;
  for (size_t k = 0; k < scene.spheres.size(); ++k) {
    if (!shown(hidden.spheres, k)) continue;
    const auto& s = scene.spheres[k];
    SphereVertex v;
    std::copy(s.centre.begin(), s.centre.end(), v.centre);
    v.radius = s.radius;
    const uint8_t c[4] = {s.color.r, s.color.g, s.color.b, s.color.a};
    std::copy(c, c + 4, v.color);
    if (s.color.a == 255) {
      opaque.push_back(v);
    } else {
      clear.push_back(v);
      float d = 0;
      for (int a = 0; a < 3; ++a) d += (s.centre[a] - scene.camera.eye[a]) * (s.centre[a] - scene.camera.eye[a]);
      depth.push_back(d);
    }
  }
  g.set_camera(g.sphere_prog, scene.camera);
  g.draw_spheres(opaque);
  if (!scene.lines.empty()) {
    // The box outline lies on the clip rectangle of a 2D frame: drawn whole.
    glDisable(GL_SCISSOR_TEST);
    g.set_camera(g.line_prog, scene.camera);
    glUniform2f(glGetUniformLocation(g.line_prog, "u_viewport"), static_cast<float>(scene.width),
                static_cast<float>(scene.height));
    g.draw_segments(segments(scene.lines, [](const RenderScene::Line& l) { return l.width_px; }, {}), 4);
    if (scene.clip[2] > 0) glEnable(GL_SCISSOR_TEST);
  }
  if (!clear.empty()) {
    // Translucent grains back to front, without writing depth.
    std::vector<size_t> order(clear.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return depth[a] > depth[b]; });
    std::vector<SphereVertex> sorted;
    sorted.reserve(clear.size());
    for (size_t k : order) sorted.push_back(clear[k]);
    g.set_camera(g.sphere_prog, scene.camera);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    g.draw_spheres(sorted);
    glDepthMask(GL_TRUE);
  }
  glFinish();
  if (const GLenum err = glGetError(); err != GL_NO_ERROR) throw RenderError("OpenGL error " + std::to_string(err));
  Image img;
  img.width = scene.width;
  img.height = scene.height;
  img.rgba.resize(g.buffer.size());
  const size_t row = static_cast<size_t>(scene.width) * 4;
  for (int y = 0; y < scene.height; ++y)  // GL rows start at the bottom
    std::copy_n(&g.buffer[(scene.height - 1 - y) * row], row, &img.rgba[y * row]);
  for (size_t k = 3; k < img.rgba.size(); k += 4) img.rgba[k] = 255;
  return img;
}

}  // namespace silt::render
