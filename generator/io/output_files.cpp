#include "io/output_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "model/inert_text.hpp"

namespace sweepgen::io {
namespace {

// An IoError naming `path` (escaped: a path may hold a line break or a terminal's escape), what
// failed and the system's reason.
IoError io_error(const std::string& path, const std::string& what, int error) {
  return IoError(path, what + " (" + std::strerror(error) + ")");
}

// Whether the open file `fd` holds exactly `text`: read block by block, never more than one block
// past `text`'s length, so that a file growing meanwhile cannot make the comparison endless.
bool reads_as(int fd, const std::string& text) {
  char block[1 << 16];
  std::size_t at = 0;
  for (;;) {
    const ssize_t n = ::read(fd, block, sizeof block);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n == 0 && at == text.size();
    const auto size = static_cast<std::size_t>(n);
    if (size > text.size() - at || text.compare(at, size, block, size) != 0) return false;
    at += size;
  }
}

// A suffix nobody can predict (16 letters and digits): a temporary's name must not be one that
// another user could have prepared, as a link or a file, before the run.
std::string unguessable_suffix() {
  static constexpr char kLetters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::random_device random;
  std::uniform_int_distribution<std::size_t> pick(0, sizeof kLetters - 2);
  std::string suffix(16, ' ');
  for (char& c : suffix) c = kLetters[pick(random)];
  return suffix;
}

struct Temporary {
  int fd;
  std::string path;
};

// A new file beside `path`: O_EXCL creates it or fails, so an existing name (a planted link
// above all) is never opened for writing; mode 0666 lets the umask and a default ACL decide the
// permissions, as for any file a program creates.
Temporary create_temporary(const std::string& path) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string temporary = path + ".tmp" + unguessable_suffix();
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_NOCTTY | O_CLOEXEC, 0666);
    if (fd >= 0) return {fd, std::move(temporary)};
    if (errno != EEXIST) throw io_error(path, "cannot write", errno);
  }
  throw io_error(path, "cannot write", EEXIST);
}

// Writes all of `text` to `fd` and flushes it to the disk, so that the rename that follows never
// puts an empty or partial file in place after a crash; false with errno set on failure.
bool write_durably(int fd, const std::string& text) {
  for (std::size_t at = 0; at < text.size();) {
    const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    at += static_cast<std::size_t>(n);
  }
  return ::fsync(fd) == 0;
}

// Flushes the renames in `directory` to the disk. A file system that cannot flush a directory
// (some refuse with EINVAL) keeps the renames all the same: its failure is not the run's.
void flush_directory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::string directory_of(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}


// Writes `file`'s text to a new temporary beside it and returns the temporary's name; on
// failure removes the temporary and throws.
std::string write_temporary(const OutputFile& file) {
  const Temporary temporary = create_temporary(file.path);
  const bool written = write_durably(temporary.fd, file.text);
  const int error = errno;
  if (::close(temporary.fd) == 0 && written) return temporary.path;
  const int reason = written ? errno : error;
  ::unlink(temporary.path.c_str());
  throw io_error(file.path, "cannot write", reason);
}

}  // namespace

bool holds(const std::string& path, const std::string& text) {
  struct stat named;
  if (::lstat(path.c_str(), &named) != 0 || !S_ISREG(named.st_mode) || static_cast<std::size_t>(named.st_size) != text.size())
    return false;
  // O_NOFOLLOW and O_NONBLOCK: should a link or a FIFO take the name after lstat, opening it
  // neither follows the link nor waits for a writer, and fstat sees it is no regular file.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat opened;
  const bool same = ::fstat(fd, &opened) == 0 && S_ISREG(opened.st_mode) && reads_as(fd, text);
  ::close(fd);
  return same;
}

void write_files_atomically(const std::vector<OutputFile>& files) {
  std::vector<std::string> temporaries;
  std::vector<const OutputFile*> changed;
  std::set<std::string> directories;
  try {
    for (const auto& file : files) {
      if (holds(file.path, file.text)) continue;
      temporaries.push_back(write_temporary(file));
      changed.push_back(&file);
    }
    for (std::size_t i = 0; i < changed.size(); ++i) {
      if (std::rename(temporaries[i].c_str(), changed[i]->path.c_str()) != 0)
        throw io_error(changed[i]->path, "cannot replace", errno);
      directories.insert(directory_of(changed[i]->path));
    }
  } catch (...) {
    for (const auto& t : temporaries) ::unlink(t.c_str());
    throw;
  }
  for (const std::string& directory : directories) flush_directory(directory);
}

std::string fnv1a64(const std::string& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace sweepgen::io
