// Overlays drawn into the finished image on the CPU: text from a real font (FreeType with DejaVu
// Sans, Debian's fonts-dejavu-core), the colour bar and the scale bar.
#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "silt/render.hpp"

namespace silt::render {
namespace {

std::string font_path() {
  if (const char* env = std::getenv("SILT_FONT")) return env;
  return "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

class Font {
 public:
  static Font& get() {
    static Font font;
    return font;
  }
  std::mutex mutex;
  FT_Face face = nullptr;

 private:
  Font() {
    if (FT_Init_FreeType(&lib_)) throw RenderError("cannot initialise FreeType");
    if (FT_New_Face(lib_, font_path().c_str(), 0, &face))
      throw RenderError("cannot load the font " + font_path() + " (install fonts-dejavu-core, or set SILT_FONT)");
  }
  FT_Library lib_ = nullptr;
};

void blend(Image& img, int x, int y, Rgba c, double a) {
  if (x < 0 || y < 0 || x >= img.width || y >= img.height || a <= 0) return;
  uint8_t* p = &img.rgba[(static_cast<size_t>(y) * img.width + x) * 4];
  const double b = std::min(1.0, a * c.a / 255.0);
  p[0] = static_cast<uint8_t>(std::lround(p[0] * (1 - b) + c.r * b));
  p[1] = static_cast<uint8_t>(std::lround(p[1] * (1 - b) + c.g * b));
  p[2] = static_cast<uint8_t>(std::lround(p[2] * (1 - b) + c.b * b));
}

// The rectangle [x0, x0 + w) x [y0, y0 + h), clipped to the image first: its cost is bounded by
// the image's, whatever the rectangle.
void fill(Image& img, int x0, int y0, int w, int h, Rgba c) {
  const int64_t xa = std::max<int64_t>(x0, 0), xb = std::min<int64_t>(int64_t{x0} + w, img.width);
  const int64_t ya = std::max<int64_t>(y0, 0), yb = std::min<int64_t>(int64_t{y0} + h, img.height);
  for (int64_t y = ya; y < yb; ++y)
    for (int64_t x = xa; x < xb; ++x) blend(img, static_cast<int>(x), static_cast<int>(y), c, 1.0);
}

}  // namespace

int text_width(const std::string& text, int size) {
  Font& f = Font::get();
  std::lock_guard<std::mutex> lock(f.mutex);
  FT_Set_Pixel_Sizes(f.face, 0, static_cast<FT_UInt>(size));
  int w = 0;
  for (unsigned char ch : text)
    if (!FT_Load_Char(f.face, ch, FT_LOAD_DEFAULT)) w += static_cast<int>(f.face->glyph->advance.x >> 6);
  return w;
}

namespace {

void draw_text(Image& img, const TextItem& t) {
  Font& f = Font::get();
  std::lock_guard<std::mutex> lock(f.mutex);
  FT_Set_Pixel_Sizes(f.face, 0, static_cast<FT_UInt>(t.size));
  int pen = t.x;
  for (unsigned char ch : t.text) {
    if (FT_Load_Char(f.face, ch, FT_LOAD_RENDER)) continue;
    const FT_GlyphSlot g = f.face->glyph;
    const FT_Bitmap& bm = g->bitmap;
    for (unsigned r = 0; r < bm.rows; ++r)
      for (unsigned c = 0; c < bm.width; ++c)
        blend(img, pen + g->bitmap_left + static_cast<int>(c), t.y - g->bitmap_top + static_cast<int>(r), t.color,
              bm.buffer[r * bm.pitch + c] / 255.0);
    pen += static_cast<int>(g->advance.x >> 6);
  }
}

std::string label(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// A colour bar with its limits, its zero where it spans one, and its label above it.
void draw_bar(Image& image, const ColorBar& b, Rgba ink) {
  const Colormap& cm = Colormap::get(b.colormap);
  // Top row is hi, bottom row is lo.
  for (int y = 0; y < b.height; ++y) {
    const Rgba c = cm.at(1.0 - static_cast<double>(y) / std::max(1, b.height - 1));
    fill(image, b.x, b.y + y, b.width, 1, c);
  }
  fill(image, b.x - 1, b.y - 1, b.width + 2, 1, ink);
  fill(image, b.x - 1, b.y + b.height, b.width + 2, 1, ink);
  fill(image, b.x - 1, b.y - 1, 1, b.height + 2, ink);
  fill(image, b.x + b.width, b.y - 1, 1, b.height + 2, ink);
  const int tx = b.x + b.width + 5;
  draw_text(image, {label(b.hi), tx, b.y + 6, 12, ink});
  draw_text(image, {label(b.lo), tx, b.y + b.height + 4, 12, ink});
  if (b.lo < 0 && b.hi > 0)
    draw_text(image, {"0", tx, b.y + static_cast<int>(b.height * b.hi / (b.hi - b.lo)) + 4, 12, ink});
  const int w = text_width(b.label, 13);
  draw_text(image, {b.label, std::max(0, std::min(image.width - w - 2, b.x + b.width / 2 - w / 2)), b.y - b.label_above,
                    13, ink});
}

}  // namespace

void compose_overlays(const RenderScene& scene, Image& image) {
  const bool dark = scene.background.r + scene.background.g + scene.background.b < 384;
  const Rgba ink = dark ? Rgba{235, 235, 235, 255} : Rgba{20, 20, 20, 255};
  for (const ColorBar* b : {&scene.colorbar, &scene.lubrication_bar})
    if (b->on) draw_bar(image, *b, ink);
  if (scene.scalebar.on) {
    const ScaleBar& s = scene.scalebar;
    fill(image, s.x, s.y, s.width_px, 4, ink);
    fill(image, s.x, s.y - 4, 2, 12, ink);
    fill(image, s.x + s.width_px - 2, s.y - 4, 2, 12, ink);
    draw_text(image, {s.label, s.x + s.width_px + 8, s.y + 6, 13, ink});
  }
  for (const TextItem& t : scene.texts) draw_text(image, t);
}

}  // namespace silt::render
