// Colormaps as data: assets/<name>.csv, 256 rows of r,g,b in [0, 1] (tools/make_colormaps.py).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "silt/render.hpp"

namespace silt::render {

std::string assets_dir() {
  if (const char* env = std::getenv("SILT_ASSETS")) return env;
  return SILT_ASSETS_DIR;
}

const Colormap& Colormap::get(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, Colormap> cache;
  std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(name); it != cache.end()) return it->second;
  const std::string path = assets_dir() + "/" + name + ".csv";
  std::ifstream in(path);
  if (!in) throw RenderError("unknown colormap '" + name + "' (no " + path + "); known: sequential, diverging");
  Colormap c;
  c.name_ = name;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::array<float, 3> rgb{};
    char comma;
    std::istringstream row(line);
    if (!(row >> rgb[0] >> comma >> rgb[1] >> comma >> rgb[2]))
      throw RenderError("bad colormap row in " + path + ": " + line);
    c.rgb_.push_back(rgb);
  }
  if (c.rgb_.size() < 2) throw RenderError("colormap " + path + " has fewer than 2 colours");
  return cache.emplace(name, std::move(c)).first->second;
}

Rgba Colormap::at(double t) const {
  if (std::isnan(t)) return {128, 128, 128, 255};
  t = std::min(1.0, std::max(0.0, t));
  const double x = t * (rgb_.size() - 1);
  const size_t i = std::min(rgb_.size() - 2, static_cast<size_t>(x));
  const double f = x - i;
  auto mix = [&](int k) {
    const double v = (1 - f) * rgb_[i][k] + f * rgb_[i + 1][k];
    return static_cast<uint8_t>(std::lround(255.0 * std::min(1.0, std::max(0.0, v))));
  };
  return {mix(0), mix(1), mix(2), 255};
}

}  // namespace silt::render
