// GLSL sources of the rasterizer (GLSL 3.30 core); the GL calls themselves are all in rasterizer.cpp.
#pragma once

namespace silt::render::shaders {

// Every shader is compiled after this line and a prefix: kImpostor for the fragment shaders of
// spheres and capsules, kSegmentInputs for the vertex shaders of chains and lines.
inline const char* kVersion = "#version 330 core\n";

// Impostors: the shading, one light from the upper left front (view space), diffuse and a
// specular highlight (x^40 by squaring: pow is slow in llvmpipe) of weight `shine`; and the
// depth-buffer value of a view-space point.
inline const char* kImpostor = R"(
uniform mat4 u_proj;
vec3 lit(vec3 rgb, vec3 n, vec3 rd, float shine) {
  vec3 l = normalize(vec3(0.35, 0.45, 1.0));
  float diffuse = max(dot(n, l), 0.0);
  float x = max(dot(reflect(-l, n), -rd), 0.0);
  float x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
  return rgb * (0.38 + 0.62 * diffuse) + 0.22 * shine * x16 * x16 * x8;
}
float depth_of(vec3 p) {
  vec4 clip = u_proj * vec4(p, 1.0);
  return 0.5 * clip.z / clip.w + 0.5;
}
)";

// The vertex inputs of a segment (RenderScene::Segment or Line, one instance each) and the camera.
inline const char* kSegmentInputs = R"(
layout(location = 0) in vec3 a_a;
layout(location = 1) in vec3 a_b;
layout(location = 2) in float a_width;
layout(location = 3) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform vec2 u_viewport;
)";

// Spheres (and the disks of 2D scenes): one camera-facing quad per grain, whose fragments
// intersect the view ray with the sphere, shade it and write the true depth. (An octagon would
// shade a sixth fewer fragments, but llvmpipe's cost per triangle makes it slower.)
inline const char* kSphereVs = R"(
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

inline const char* kSphereFs = R"(
in vec3 v_centre;
in float v_radius;
in vec4 v_color;
in vec3 v_pos;
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
  frag = vec4(lit(v_color.rgb, n, rd, v_color.a), v_color.a);
  gl_FragDepth = depth_of(hit);
}
)";

// Force chains: capsules (a cylinder between two centres with round ends), ray-cast inside a quad
// that bounds their projection: a parallelogram across the view direction, through both centres,
// reaching past each end and to each side by the radius, grown as a sphere impostor's (the
// capsule is the convex hull of its two end spheres, so its projection is the hull of theirs).
inline const char* kCapsuleVs = R"(
uniform int u_ortho;
flat out vec3 v_a;
flat out vec3 v_b;
flat out float v_radius;
flat out vec4 v_color;
out vec3 v_pos;
void main() {
  vec3 a = (u_view * vec4(a_a, 1.0)).xyz;
  vec3 b = (u_view * vec4(a_b, 1.0)).xyz;
  // Never thinner than a pixel (a force far below the mean would break into dots otherwise).
  float pixel = 2.0 / (u_proj[1][1] * u_viewport.y) * (u_ortho == 1 ? 1.0 : max(-a.z, -b.z));
  float r = max(0.5 * a_width, 0.5 * pixel);
  bool end = (gl_VertexID & 1) != 0;
  vec3 c = end ? b : a;
  vec3 view = u_ortho == 1 ? vec3(0.0, 0.0, -1.0) : normalize(0.5 * (a + b));
  vec3 side = cross(b - a, view);
  side = length(side) > 1e-6 * length(b - a) ? normalize(side) : normalize(cross(abs(view.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), view));
  vec3 along = cross(view, side);
  if (dot(along, b - a) < 0.0) along = -along;
  float grow = u_ortho == 1 ? 1.02 : 1.05 * length(c) / max(-c.z, 1e-20) * max(length(c), 1e-20) / max(length(c) - r, 1e-20);
  float R = r * grow;
  vec3 p = c + R * ((gl_VertexID & 2) != 0 ? side : -side) + R * (end ? along : -along);
  v_a = a;
  v_b = b;
  v_radius = r;
  v_color = a_color;
  v_pos = p;
  gl_Position = u_proj * vec4(p, 1.0);
}
)";

// The ray o + t d (t > 0) against the capsule: the cylinder body, where the
// distance to the axis is r: with p = o - a, e = b - a, |p + t d|^2 - ((p + t d) . e)^2 / |e|^2
// = r^2, that is A t^2 + 2 B t + C = 0 with A = e.e - (e.d)^2, B = e.e (d.p) - (e.p)(e.d),
// C = e.e (p.p) - (e.p)^2 - r^2 e.e, valid where the hit projects inside the segment; and the
// spheres at both ends. The nearest hit wins.
inline const char* kCapsuleFs = R"(
flat in vec3 v_a;
flat in vec3 v_b;
flat in float v_radius;
flat in vec4 v_color;
in vec3 v_pos;
uniform int u_ortho;
uniform int u_lit;
out vec4 frag;
void main() {
  // From the eye, or in an orthographic view from the plane z = 0 in front of everything.
  vec3 ro = u_ortho == 1 ? vec3(v_pos.xy, 0.0) : vec3(0.0);
  vec3 rd = u_ortho == 1 ? vec3(0.0, 0.0, -1.0) : normalize(v_pos);
  float r2 = v_radius * v_radius;
  vec3 e = v_b - v_a, p = ro - v_a;
  float ee = dot(e, e), ed = dot(e, rd), ep = dot(e, p);
  float best = 1e30;
  vec3 n = vec3(0.0, 0.0, 1.0);
  float A = ee - ed * ed;
  if (A > 1e-9 * ee) {
    float B = ee * dot(rd, p) - ep * ed, C = ee * dot(p, p) - ep * ep - r2 * ee;
    float h = B * B - A * C;
    if (h >= 0.0) {
      float t = (-B - sqrt(h)) / A;
      float y = ep + t * ed;  // the hit's position along the axis, times |e|
      if (t > 0.0 && y >= 0.0 && y <= ee) {
        best = t;
        n = (p + t * rd - e * (y / ee)) / v_radius;
      }
    }
  }
  for (int end = 0; end < 2; ++end) {
    vec3 oc = ro - (end == 0 ? v_a : v_b);
    float b = dot(oc, rd), h = b * b - (dot(oc, oc) - r2);
    if (h < 0.0) continue;
    float t = -b - sqrt(h);
    if (t > 0.0 && t < best) {
      best = t;
      n = (oc + t * rd) / v_radius;
    }
  }
  if (best == 1e30) discard;
  vec3 hit = ro + best * rd;
  frag = vec4(u_lit == 1 ? lit(v_color.rgb, n, rd, 1.0) : v_color.rgb, 1.0);
  gl_FragDepth = depth_of(hit);
}
)";

// Lines of a constant width in pixels (the box outline): a quad around the projected segment,
// half a width longer at each end so that corners close, cut where it passes behind the eye.
inline const char* kLineVs = R"(
out vec4 v_color;
void main() {
  v_color = a_color;
  vec4 ca = u_proj * (u_view * vec4(a_a, 1.0));
  vec4 cb = u_proj * (u_view * vec4(a_b, 1.0));
  const float eps = 1e-6;
  if (ca.w < eps && cb.w < eps) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);  // wholly behind the eye: outside the clip volume
    return;
  }
  if (ca.w < eps) ca = mix(ca, cb, (eps - ca.w) / (cb.w - ca.w));
  if (cb.w < eps) cb = mix(cb, ca, (eps - cb.w) / (ca.w - cb.w));
  vec2 half_vp = 0.5 * u_viewport;
  vec2 sa = ca.xy / ca.w * half_vp, sb = cb.xy / cb.w * half_vp;  // pixels from the centre
  vec2 d = length(sb - sa) > 0.0 ? normalize(sb - sa) : vec2(1.0, 0.0);
  bool end = (gl_VertexID & 1) != 0;
  float side = (gl_VertexID & 2) != 0 ? 1.0 : -1.0;
  vec4 c = end ? cb : ca;
  vec2 offset = 0.5 * a_width * (side * vec2(-d.y, d.x) + (end ? d : -d));
  c.xy += offset / half_vp * c.w;
  gl_Position = c;
}
)";

inline const char* kFlatFs = R"(
in vec4 v_color;
out vec4 frag;
void main() { frag = v_color; }
)";

// Fields: textured quads; texels of alpha 0 lie off the grid (an oblique slice) and are not drawn.
inline const char* kFieldVs = R"(
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

inline const char* kFieldFs = R"(
in vec2 v_uv;
uniform sampler2D u_tex;
out vec4 frag;
void main() {
  vec4 c = texture(u_tex, v_uv);
  if (c.a < 0.5) discard;
  frag = vec4(c.rgb, 1.0);
}
)";

}  // namespace silt::render::shaders
