#include "silt/input_files.hpp"

#include <filesystem>

#include "core/machine.hpp"
#include "silt/errors.hpp"
#include "silt/text.hpp"

namespace silt {
namespace {

std::string size_text(std::uintmax_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= double(1 << 30)) return format_number(b / (1 << 30), 3) + " GiB";
  return format_number(b / (1 << 20), 3) + " MiB";
}

}  // namespace

std::uintmax_t max_checkpoint_bytes() { return static_cast<std::uintmax_t>(physical_memory_bytes()); }

void check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(path, ec);
  if (!fs::exists(st)) throw IoError("cannot read " + what + " '" + path + "': no such file");
  if (fs::is_directory(st)) throw IoError("'" + path + "' is a directory, not a " + what);
  if (!fs::is_regular_file(st)) throw IoError("'" + path + "' is not a regular file (a device, a pipe): not a " + what);
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw IoError("cannot read " + what + " '" + path + "': " + ec.message());
  if (size > max_bytes)
    throw IoError(what + " '" + path + "' has " + size_text(size) + ", more than any " + what + " can have here (" +
                  size_text(max_bytes) + "): not read");
}

}  // namespace silt
