// The files silt reads whole (scenes, scripts, checkpoints): checked before a byte is read, so
// that a directory, a device that never ends (/dev/zero), a pipe or a file of gigabytes is refused
// with its reason instead of read into memory.
#pragma once

#include <cstdint>
#include <string>

namespace silt {

// The most bytes a scene file or a script may have: no text a user writes comes near it.
constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{64} << 20;

// The most bytes a checkpoint may have on this machine: its physical memory. A checkpoint holds
// one copy of a state, and compiling a scene refuses a system whose estimate (its state at least
// twice: the state and the restart point) exceeds the memory available, so no checkpoint of a
// system that runs here is larger; reading one also takes that much memory.
std::uintmax_t max_checkpoint_bytes();

// IoError unless `path` is a regular file of at most `max_bytes`; `what` names the kind of file
// ("scene file", "script", "checkpoint") in the message.
void check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes);

}  // namespace silt
