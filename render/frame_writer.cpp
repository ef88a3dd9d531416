#include <sys/stat.h>

#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <thread>

#include "silt/errors.hpp"
#include "silt/render.hpp"

namespace silt::render {

struct FrameWriter::Impl {
  std::string dir;
  int threads = 0;
  std::mutex mutex;
  std::condition_variable cv;
  std::optional<RenderScene> pending;
  bool busy = false, stop = false;
  int64_t next = 0, written = 0;
  std::string error;
  std::thread worker;

  void run() {
    std::optional<Rasterizer> raster;
    for (;;) {
      RenderScene scene;
      int64_t index;
      {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait(lock, [&] { return pending.has_value() || stop; });
        if (!pending) return;
        scene = std::move(*pending);
        pending.reset();
        busy = true;
        index = next++;
      }
      std::string err;
      try {
        if (!raster) raster.emplace(threads);
        Image img = raster->draw(scene);
        compose_overlays(scene, img);
        char name[32];
        std::snprintf(name, sizeof name, "/frame_%06lld.png", static_cast<long long>(index));
        write_png(dir + name, img);
      } catch (const std::exception& e) {
        err = e.what();
      }
      {
        std::lock_guard<std::mutex> lock(mutex);
        busy = false;
        if (err.empty()) ++written;
        else if (error.empty()) error = err;
      }
      cv.notify_all();
    }
  }
};

FrameWriter::FrameWriter(std::string dir, int threads) : impl_(std::make_unique<Impl>()) {
  if (::mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST)
    throw IoError("cannot create the frame directory '" + dir + "': " + std::strerror(errno));
  struct stat st{};
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw IoError("'" + dir + "' is not a directory");
  impl_->dir = std::move(dir);
  impl_->threads = threads;
  impl_->worker = std::thread([this] { impl_->run(); });
}

FrameWriter::~FrameWriter() {
  finish();
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stop = true;
  }
  impl_->cv.notify_all();
  impl_->worker.join();
}

void FrameWriter::submit(RenderScene scene) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  if (!impl_->error.empty()) return;
  impl_->cv.wait(lock, [&] { return !impl_->pending.has_value(); });
  impl_->pending = std::move(scene);
  lock.unlock();
  impl_->cv.notify_all();
}

void FrameWriter::finish() {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  impl_->cv.wait(lock, [&] { return !impl_->pending.has_value() && !impl_->busy; });
}

int64_t FrameWriter::written() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->written;
}

std::string FrameWriter::error() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->error;
}

}  // namespace silt::render
