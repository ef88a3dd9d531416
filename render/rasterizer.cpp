// All OpenGL of silt: an OSMesa (llvmpipe) core-profile 4.5 context drawing a RenderScene.
//
// Spheres (and the disks of 2D scenes) are impostors: one camera-facing quad per grain whose
// fragment shader intersects the view ray with the sphere, shades it and writes the true depth,
// so overlapping grains hide each other correctly. Force chains are quads along each contact.
// Fields are textured quads. Translucent grains are drawn last, back to front.
#define GL_GLEXT_PROTOTYPES
#include <GL/osmesa.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <string>

#include "render/camera.hpp"
#include "silt/render.hpp"

namespace silt::render {
namespace {

const char* kSphereVs = R"(#version 330 core
layout(location = 0) in vec3 a_centre;
layout(location = 1) in float a_radius;
layout(location = 2) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform int u_ortho;
out vec3 v_centre;
out float v_radius;
out vec4 v_color;
out vec3 v_pos;
void main() {
  vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
  vec4 c = u_view * vec4(a_centre, 1.0);
  // Perspective: the quad is moved along the ray to the front of the sphere (so that the near side
  // is never clipped), where the cone of rays grazing the sphere is narrower than the radius; off
  // the axis the silhouette stretches by 1/cos of the angle to the axis.
  float grow = u_ortho == 1 ? 1.0 : 1.05 * length(c.xyz) / max(-c.z, 1e-20);
  vec3 p = c.xyz + vec3(corner * a_radius * grow, 0.0);
  if (u_ortho == 0) p *= (length(c.xyz) - a_radius) / max(length(c.xyz), 1e-20);
  v_centre = c.xyz;
  v_radius = a_radius;
  v_color = a_color;
  v_pos = p;
  gl_Position = u_proj * vec4(p, 1.0);
}
)";

const char* kSphereFs = R"(#version 330 core
in vec3 v_centre;
in float v_radius;
in vec4 v_color;
in vec3 v_pos;
uniform mat4 u_proj;
uniform int u_ortho;
out vec4 frag;
void main() {
  vec3 ro, rd;
  if (u_ortho == 1) {
    ro = vec3(v_pos.xy, v_centre.z + 2.0 * v_radius);
    rd = vec3(0.0, 0.0, -1.0);
  } else {
    ro = vec3(0.0);
    rd = normalize(v_pos);
  }
  vec3 oc = ro - v_centre;
  float b = dot(oc, rd);
  float c = dot(oc, oc) - v_radius * v_radius;
  float disc = b * b - c;
  if (disc < 0.0) discard;
  float t = -b - sqrt(disc);
  vec3 hit = ro + t * rd;
  vec3 n = (hit - v_centre) / v_radius;
  vec3 l = normalize(vec3(0.35, 0.45, 1.0));
  float diffuse = max(dot(n, l), 0.0);
  float specular = pow(max(dot(reflect(-l, n), -rd), 0.0), 40.0);
  frag = vec4(v_color.rgb * (0.38 + 0.62 * diffuse) + 0.22 * specular * v_color.a, v_color.a);
  vec4 clip = u_proj * vec4(hit, 1.0);
  gl_FragDepth = 0.5 * clip.z / clip.w + 0.5;
}
)";

const char* kSegmentVs = R"(#version 330 core
layout(location = 0) in vec3 a_a;
layout(location = 1) in vec3 a_b;
layout(location = 2) in float a_width;
layout(location = 3) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_proj;
out vec4 v_color;
void main() {
  vec3 a = (u_view * vec4(a_a, 1.0)).xyz;
  vec3 b = (u_view * vec4(a_b, 1.0)).xyz;
  vec2 d = b.xy - a.xy;
  vec2 side = length(d) > 0.0 ? normalize(vec2(-d.y, d.x)) : vec2(1.0, 0.0);
  vec3 p = ((gl_VertexID & 1) == 0 ? a : b) + vec3(side * 0.5 * a_width * ((gl_VertexID & 2) == 0 ? -1.0 : 1.0), 0.0);
  v_color = a_color;
  gl_Position = u_proj * vec4(p, 1.0);
}
)";

const char* kFlatFs = R"(#version 330 core
in vec4 v_color;
out vec4 frag;
void main() { frag = v_color; }
)";

const char* kFieldVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec2 a_uv;
uniform mat4 u_view;
uniform mat4 u_proj;
out vec2 v_uv;
void main() {
  v_uv = a_uv;
  gl_Position = u_proj * u_view * vec4(a_pos, 1.0);
}
)";

const char* kFieldFs = R"(#version 330 core
in vec2 v_uv;
uniform sampler2D u_tex;
out vec4 frag;
void main() { frag = texture(u_tex, v_uv); }
)";

GLuint compile_shader(GLenum type, const char* src) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
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

GLuint link_program(const char* vs, const char* fs) {
  const GLuint p = glCreateProgram();
  const GLuint v = compile_shader(GL_VERTEX_SHADER, vs), f = compile_shader(GL_FRAGMENT_SHADER, fs);
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
  GLuint sphere_prog = 0, segment_prog = 0, field_prog = 0;
  GLuint vao = 0, vbo = 0, tex = 0;

  void make_current(int w, int h) {
    if (!ctx) {
      const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                             OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
      ctx = OSMesaCreateContextAttribs(attribs, nullptr);
      if (!ctx) throw RenderError("cannot create an OSMesa OpenGL 4.5 core context (is libosmesa6 installed?)");
    }
    if (w != width || h != height || buffer.empty()) {
      buffer.assign(static_cast<size_t>(w) * h * 4, 0);
      width = w;
      height = h;
    }
    if (!OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, w, h))
      throw RenderError("cannot bind the OSMesa context to a " + std::to_string(w) + " x " + std::to_string(h) + " image");
    if (!sphere_prog) {
      sphere_prog = link_program(kSphereVs, kSphereFs);
      segment_prog = link_program(kSegmentVs, kFlatFs);
      field_prog = link_program(kFieldVs, kFieldFs);
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

  void draw_segments(const std::vector<SegmentVertex>& v) {
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
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(v.size()));
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
  // Fields first (opaque, behind), then chains, then opaque grains.
  g.set_camera(g.field_prog, scene.camera);
  for (const auto& q : scene.fields) g.draw_field(q);
  g.set_camera(g.segment_prog, scene.camera);
  std::vector<SegmentVertex> seg(scene.segments.size());
  for (size_t k = 0; k < seg.size(); ++k) {
    const auto& s = scene.segments[k];
    std::copy(s.a.begin(), s.a.end(), seg[k].a);
    std::copy(s.b.begin(), s.b.end(), seg[k].b);
    seg[k].width = s.width;
    const uint8_t c[4] = {s.color.r, s.color.g, s.color.b, s.color.a};
    std::copy(c, c + 4, seg[k].color);
  }
  g.draw_segments(seg);
  std::vector<SphereVertex> opaque, clear;
  opaque.reserve(scene.spheres.size());
  std::vector<float> depth;
  for (const auto& s : scene.spheres) {
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
  if (!clear.empty()) {
    // Translucent grains back to front, without writing depth.
    std::vector<size_t> order(clear.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return depth[a] > depth[b]; });
    std::vector<SphereVertex> sorted;
    sorted.reserve(clear.size());
    for (size_t k : order) sorted.push_back(clear[k]);
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
