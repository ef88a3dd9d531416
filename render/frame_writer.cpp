// FrameWriter: frames drawn and written on a worker thread, one waiting at most.
#include <sys/stat.h>

#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "silt/errors.hpp"
#include "silt/io.hpp"
#include "silt/render.hpp"

namespace silt::render {

namespace {
const NumberedSeries kFrames{{"frame_", ".png"}};  // frame_NNNNNN.png
}  // namespace

struct FrameWriter::Impl {
  std::string dir;
  int threads = 0;
  Sink sink;  // empty: draw, then write DIR/frame_NNNNNN.png
  std::mutex mutex;
  std::condition_variable cv;
  std::optional<RenderScene> pending;  // at most one frame waits
  bool busy = false, stop = false;
  int64_t next = 0, written = 0;
  std::string error;
  std::thread worker;
  std::optional<Rasterizer> raster;  // the worker's GL context, made at its first frame

  void deliver(const RenderScene& scene, int64_t index) {
    if (sink) return sink(scene, index);
    if (!raster) raster.emplace(threads);
    Image img = raster->draw(scene);
    compose_overlays(scene, img);
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%06lld.png", static_cast<long long>(index));
    write_png(dir + name, img);
  }

  void run() {
    for (;;) {
      RenderScene scene;
      int64_t index;
      bool stopped;
      {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait(lock, [&] { return pending.has_value() || stop; });
        if (!pending) break;
        scene = std::move(*pending);
        pending.reset();
        busy = true;
        index = next++;
        stopped = !error.empty();  // a frame queued before an error is dropped
      }
      cv.notify_all();  // a submit waiting for the slot may go on
      std::string err;
      try {
        if (!stopped) deliver(scene, index);
      } catch (const std::exception& e) {
        err = e.what();
      }
      {
        std::lock_guard<std::mutex> lock(mutex);
        busy = false;
        if (err.empty() && !stopped) ++written;
        else if (error.empty()) error = err;
      }
      cv.notify_all();
    }
    raster.reset();  // the GL context ends on the thread that used it
  }
};

bool FrameWriter::owns(const std::string& path, const std::string& dir) {
  return is_numbered_file(std::filesystem::path(path).filename().string(), kFrames) && is_in_directory(path, dir);
}

FrameWriter::FrameWriter(std::string dir, int threads) : impl_(std::make_unique<Impl>()) {
  make_output_directory(dir, "frame");
  // An earlier run's frames in the directory would mix with this run's in a film: remove them
  // (only silt's own names, frame_NNNNNN.png).
  removed_ = remove_numbered_files(dir, kFrames);
  impl_->dir = std::move(dir);
  impl_->threads = threads;
  impl_->worker = std::thread([this] { impl_->run(); });
}

FrameWriter::FrameWriter(Sink sink) : impl_(std::make_unique<Impl>()) {
  impl_->sink = std::move(sink);
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
  impl_->cv.wait(lock, [&] { return !impl_->pending.has_value() || !impl_->error.empty(); });
  if (!impl_->error.empty()) return;  // the frames have stopped
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
