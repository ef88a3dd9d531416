// Output files: a path checked before a run starts, and a text file written whole (a temporary
// file renamed over a regular file; a device or a pipe written directly), every write checked.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "silt/io.hpp"

namespace silt {

void check_output_path(const std::string& path, const std::string& what, bool regular_only) {
  if (path.empty()) return;
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(path, ec);
  if (fs::is_directory(st)) throw IoError("cannot write " + what + " '" + path + "': it is a directory");
  if (fs::exists(st)) {
    if (regular_only && !fs::is_regular_file(st))
      throw IoError("cannot write " + what + " '" + path + "': not a regular file (a device, a pipe)");
    if (::access(path.c_str(), W_OK) != 0)
      throw IoError("cannot write " + what + " '" + path + "': " + std::strerror(errno));
    if (!fs::is_regular_file(st)) return;  // a device or a pipe is written in place
  }
  std::string dir = fs::path(path).parent_path().string();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec))
    throw IoError("cannot write " + what + " '" + path +
                  "': " + (fs::exists(dir, ec) ? "'" + dir + "' is not a directory" : "no directory '" + dir + "'"));
  if (::access(dir.c_str(), W_OK) != 0)
    throw IoError("cannot write " + what + " '" + path + "': " + std::strerror(errno) + " (its directory)");
  // A file made there and removed: the directory may grant writing (to root, /proc and /sys do)
  // and refuse a new file, which a regular file's temporary file is before its rename (a summary or a
  // checkpoint was refused only after the run).
  const std::string probe = path + ".probe." + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return;  // (a file of that name: the directory takes new files)
    throw IoError("cannot write " + what + " '" + path + "': " + std::strerror(errno) +
                  " (a new file in its directory)");
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

std::filesystem::path canonical_path(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path abs = fs::absolute(path.empty() ? "." : path, ec).lexically_normal();
  // A symbolic link to a file not made yet names that file (weakly_canonical leaves a dangling
  // link as it is: --stats link --summary target, the link's target not there yet, wrote both to
  // one file). Followed a few times, as a chain of links may be.
  for (int k = 0; k < 8 && fs::is_symlink(fs::symlink_status(abs, ec)) && !fs::exists(abs, ec); ++k) {
    const fs::path target = fs::read_symlink(abs, ec);
    if (ec) break;
    abs = (target.is_absolute() ? target : abs.parent_path() / target).lexically_normal();
  }
  fs::path c = fs::weakly_canonical(abs, ec);
  if (ec) c = abs;
  // (a directory not made yet, given as "o2/", kept its slash and was not "o2")
  return c.has_filename() || !c.has_parent_path() ? c : c.parent_path();
}

namespace {

// Whether two names that exist are one file: a hard link, which no spelling of the paths shows.
bool same_inode(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec) && !ec;
}

// Whether writing `a` and `b` leaves only one: they name one file (by their names or as hard links
// of one file). A device or a pipe, written in place, meets nothing.
bool same_output(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  auto special = [](const std::string& path) {
    std::error_code ec;
    const auto st = fs::status(path, ec);
    return fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st);
  };
  if (a.empty() || b.empty() || special(a) || special(b)) return false;
  return canonical_path(a) == canonical_path(b) || same_inode(a, b);
}

}  // namespace

bool overwrites(const std::string& path, const std::string& file) { return same_output(path, file); }

std::string output_clash(const std::string& a, const std::string& b) {
  return same_output(a, b) ? "the same file" : "";
}

TempFile make_temp_beside(const std::string& path) {
  // The umask, read once (umask() sets it as it reads it).
  static const mode_t mask = [] {
    const mode_t m = ::umask(0);
    ::umask(m);
    return m;
  }();
  TempFile t{-1, path + ".tmp.XXXXXX"};
  t.fd = ::mkstemp(t.name.data());
  if (t.fd >= 0 && ::fchmod(t.fd, 0666 & ~mask) != 0) {
    const int error = errno;
    ::close(t.fd);
    ::unlink(t.name.c_str());
    t.fd = -1;
    errno = error;
  }
  return t;
}

std::string clashing_outputs(const std::vector<std::pair<std::string, std::string>>& outputs, const std::string& vtk) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const auto& [option, path] = outputs[i];
    if (path.empty()) continue;
    for (size_t j = 0; j < i; ++j)
      if (const std::string clash = output_clash(outputs[j].second, path); !clash.empty())
        return outputs[j].first + " and " + option + " name " + clash + ", " + path;
    if (VtkWriter::owns(path, vtk)) return option + " " + path + " is a VTK file's name in the VTK directory " + vtk;
  }
  return "";
}

void check_not_input(const std::string& path, const std::string& input, const std::string& what,
                     const std::string& input_what) {
  if (!same_output(path, input)) return;
  throw IoError("cannot write " + what + " '" + path + "': it is " + input_what + ", which it would overwrite");
}

bool is_numbered_file(const std::string& name, const NumberedSeries& series) {
  for (const auto& [prefix, ext] : series) {
    const size_t digits = prefix.size();
    if (name.size() == digits + 6 + ext.size() && name.rfind(prefix, 0) == 0 &&
        name.compare(digits + 6, ext.size(), ext) == 0 && name.find_first_not_of("0123456789", digits) == digits + 6)
      return true;
  }
  return false;
}

bool is_in_directory(const std::string& path, const std::string& dir) {
  if (path.empty() || dir.empty()) return false;
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return canonical_path(parent.empty() ? "." : parent) == canonical_path(dir);
}

int64_t remove_numbered_files(const std::string& dir, const NumberedSeries& series) {
  int64_t removed = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    if (!is_numbered_file(e.path().filename().string(), series) || !e.is_regular_file(ec)) continue;
    if (std::filesystem::remove(e.path(), ec)) ++removed;
  }
  return removed;
}

void make_output_directory(const std::string& dir, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec)) && ::mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST)
    throw IoError("cannot create the " + what + " directory '" + dir + "': " + std::strerror(errno));
  if (!fs::is_directory(dir, ec)) throw IoError("cannot write " + what + " files in '" + dir + "': not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw IoError("cannot write " + what + " files in '" + dir + "': " + std::strerror(errno));
}

void write_text_file(const std::string& path, const std::string& text, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(path, ec);
  // A regular file (or none yet) is replaced at once by a rename; anything else (/dev/stdout, a
  // pipe, a device) is written in place.
  const bool in_place = fs::exists(st) && !fs::is_regular_file(st);
  const TempFile temp = in_place ? TempFile{::open(path.c_str(), O_WRONLY), path} : make_temp_beside(path);
  const std::string& target = temp.name;
  const int fd = temp.fd;
  if (fd < 0) throw IoError("cannot write " + what + " '" + path + "': " + std::strerror(errno));
  size_t done = 0;
  int error = 0;
  while (done < text.size()) {
    const ssize_t k = ::write(fd, text.data() + done, text.size() - done);
    if (k < 0) {
      if (errno == EINTR) continue;
      error = errno;
      break;
    }
    done += static_cast<size_t>(k);
  }
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && !in_place && std::rename(target.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) {
    if (!in_place) ::unlink(target.c_str());
    throw IoError("cannot write " + what + " '" + path + "': " + std::strerror(error));
  }
}

}  // namespace silt
